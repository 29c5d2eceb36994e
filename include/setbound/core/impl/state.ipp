// setbound — definitions of the functions declared in setbound/core/state.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/core/state.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE const char* state_kind_name(StateKind k) {
  switch (k) {
    case StateKind::EllipsoidalPredictor: return "EllipsoidalPredictor";
    case StateKind::ImprovedEstimator: return "ImprovedEstimator";
    case StateKind::DescriptorEstimator: return "DescriptorEstimator";
    case StateKind::KalmanFilter: return "KalmanFilter";
    case StateKind::ZonotopicEstimator: return "ZonotopicEstimator";
    case StateKind::EllipsoidalSMObserver: return "EllipsoidalSMObserver";
    case StateKind::LPVEllipsoidalSMObserver: return "LPVEllipsoidalSMObserver";
    case StateKind::IntervalLuenbergerObserver: return "IntervalLuenbergerObserver";
    case StateKind::NonlinearIntervalObserver: return "NonlinearIntervalObserver";
    case StateKind::IntervalInvariantObserver: return "IntervalInvariantObserver";
    case StateKind::ConstrainedZonotopicEstimator: return "ConstrainedZonotopicEstimator";
    case StateKind::BoundingEllipsoid: return "BoundingEllipsoidEstimator";
    case StateKind::IntervalHinfObserver: return "IntervalHinfObserver";
    case StateKind::ZonotopicObserver: return "ZonotopicObserver";
    case StateKind::ParallelotopeEstimator: return "ParallelotopeEstimator";
  }
  return "unknown estimator";
}

SETBOUND_INLINE StateFingerprint& StateFingerprint::add(double v) {
  if (v == 0.0) v = 0.0;  // -0 and +0 hash alike
  unsigned char b[sizeof(double)];
  std::memcpy(b, &v, sizeof v);
  for (unsigned char c : b) h_ = (h_ ^ c) * 1099511628211ull;
  return *this;
}

SETBOUND_INLINE StateWriter::StateWriter(StateKind kind, const StateFingerprint& fp) {
  buf_.push_back(kStateTagBase + static_cast<int>(kind));
  buf_.push_back(kStateVersion);
  buf_.push_back(static_cast<double>(fp.value() >> 32));
  buf_.push_back(static_cast<double>(fp.value() & 0xffffffffull));
}

SETBOUND_INLINE StateWriter& StateWriter::text(const std::string& s) {
  buf_.push_back(static_cast<double>(s.size()));
  for (char c : s) buf_.push_back(static_cast<double>(static_cast<unsigned char>(c)));
  return *this;
}

SETBOUND_INLINE StateWriter& StateWriter::blob(const std::vector<double>& b) {
  buf_.push_back(static_cast<double>(b.size()));
  buf_.insert(buf_.end(), b.begin(), b.end());
  return *this;
}

SETBOUND_INLINE StateReader::StateReader(const std::vector<double>& b, StateKind kind, const StateFingerprint& fp)
    : b_(b), kind_(kind) {
  const std::string who = state_kind_name(kind);
  if (b.size() < kStateHeader)
    fail("truncated: " + std::to_string(b.size()) + " values, a saved state has at least " +
         std::to_string(kStateHeader));
  for (std::size_t i = 0; i < b.size(); ++i)
    if (!std::isfinite(b[i])) fail("entry " + std::to_string(i) + " is not finite (corrupted)");
  const double tag = kStateTagBase + static_cast<int>(kind);
  if (b[0] != tag) {
    const double k = b[0] - kStateTagBase;
    std::string what = "not a saved state of setbound";
    if (((k >= 1 && k <= 10) || k == 21) && k == std::floor(k))
      what = std::string("a saved ") + state_kind_name(static_cast<StateKind>(static_cast<int>(k)));
    fail("tag " + num(b[0]) + " is " + what + ", expected a saved " + who);
  }
  if (b[1] != kStateVersion) fail("format version " + num(b[1]) + " is not supported (expected " + num(kStateVersion) + ")");
  if (b[2] != static_cast<double>(fp.value() >> 32) || b[3] != static_cast<double>(fp.value() & 0xffffffffull))
    fail("it was saved from a " + who + " with another design (gains, shapes, system or options differ); restore it "
         "into an estimator constructed from the same design");
  pos_ = kStateHeader;
}

SETBOUND_INLINE double StateReader::scalar(const char* name) {
  need(1, name);
  return b_[pos_++];
}

SETBOUND_INLINE long long StateReader::count(const char* name, long long lo, long long hi) {
  const double v = scalar(name);
  if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi))
    fail(std::string(name) + " is " + num(v) + ", expected an integer in [" + std::to_string(lo) + ", " +
         std::to_string(hi) + "]");
  return static_cast<long long>(v);
}

SETBOUND_INLINE Eigen::VectorXd StateReader::vec(Eigen::Index n, const char* name) {
  const long long len = count(name);
  if (n >= 0 && len != n)
    fail(std::string(name) + " has " + std::to_string(len) + " entries, expected " + std::to_string(n));
  need(static_cast<std::size_t>(len), name);
  Eigen::VectorXd v(static_cast<Eigen::Index>(len));
  for (Eigen::Index i = 0; i < v.size(); ++i) v(i) = b_[pos_++];
  return v;
}

SETBOUND_INLINE Eigen::MatrixXd StateReader::mat(Eigen::Index rows, Eigen::Index cols, const char* name) {
  const long long r = count(name), c = count(name);
  if ((rows >= 0 && r != rows) || (cols >= 0 && c != cols))
    fail(std::string(name) + " is " + std::to_string(r) + "x" + std::to_string(c) + ", expected " +
         (rows >= 0 ? std::to_string(rows) : std::string("any")) + "x" +
         (cols >= 0 ? std::to_string(cols) : std::string("any")));
  if (r > 0 && c > (1ll << 40) / r) fail(std::string(name) + " is too large");
  need(static_cast<std::size_t>(r * c), name);
  Eigen::MatrixXd m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c));
  for (Eigen::Index j = 0; j < m.cols(); ++j)
    for (Eigen::Index i = 0; i < m.rows(); ++i) m(i, j) = b_[pos_++];
  return m;
}

SETBOUND_INLINE std::string StateReader::text(const char* name) {
  const long long len = count(name);
  need(static_cast<std::size_t>(len), name);
  std::string s;
  for (long long i = 0; i < len; ++i) {
    const double v = b_[pos_++];
    if (v != std::floor(v) || v < 0 || v > 255) fail(std::string(name) + " is not a character string");
    s.push_back(static_cast<char>(static_cast<unsigned char>(v)));
  }
  return s;
}

SETBOUND_INLINE std::vector<double> StateReader::blob(const char* name) {
  const long long len = count(name);
  need(static_cast<std::size_t>(len), name);
  std::vector<double> out(b_.begin() + static_cast<std::ptrdiff_t>(pos_),
                          b_.begin() + static_cast<std::ptrdiff_t>(pos_ + static_cast<std::size_t>(len)));
  pos_ += static_cast<std::size_t>(len);
  return out;
}

SETBOUND_INLINE void StateReader::finish() const {
  if (pos_ != b_.size())
    fail(std::to_string(b_.size() - pos_) + " values left over after the saved " + state_kind_name(kind_) +
         " (corrupted or of another format)");
}

SETBOUND_INLINE void StateReader::fail(const std::string& what) const {
  throw InvalidArgumentError(std::string("state: ") + what);
}

SETBOUND_INLINE std::string StateReader::num(double v) {
  std::string s = std::to_string(v);
  return s;
}

SETBOUND_INLINE void StateReader::need(std::size_t k, const char* name) const {
  if (k > b_.size() - pos_)
    fail(std::string("truncated: ") + name + " needs " + std::to_string(k) + " values, " +
         std::to_string(b_.size() - pos_) + " left");
}

}  // namespace setbound
