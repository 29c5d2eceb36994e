// setbound — saved states of estimators (save_state / restore_state).
//
// Every estimator and observer can write its full mutable state (current set, step counter,
// last β/gain, working sets, counters, the buffers that influence the next step) as a flat
// vector of doubles, and read it back into an estimator constructed from the same design; it
// then continues bit-for-bit as the saved one would have. The blob is
//
//   [tag, version, fingerprint_hi, fingerprint_lo, items...]
//
// tag = kStateTagBase + the estimator kind, version = kStateVersion, and the fingerprint is a
// 64-bit FNV-1a hash of the design's bytes (gains, shapes, system matrices, dimensions), split
// into two 32-bit halves (exact in a double). Each item is a scalar, or a length followed by
// that many entries (vectors; matrices are rows, cols, then column-major entries), so that a
// size that does not match the estimator is reported by name. restore_state checks the tag,
// the version, the fingerprint, the sizes and that every entry is finite, and throws an
// InvalidArgumentError whose message starts with "state" before anything is changed.
//
// Restores are transactions (issue 26): every field is validated against what this estimator
// can hold (no count read from a blob sizes an allocation beyond the data the blob carries or
// the design implies), the new state is built in temporaries, and only then committed with
// moves, swaps and copies into buffers of the right size, none of which can throw. Memory
// exhaustion while building (std::bad_alloc) is refused like a corrupted state
// (guard_state_memory): the estimator is unchanged either way.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"

namespace setbound {

/// Estimator kinds (the blob's tag is kStateTagBase + kind).
enum class StateKind : int {
  EllipsoidalPredictor = 1,
  ImprovedEstimator = 2,
  DescriptorEstimator = 3,
  KalmanFilter = 4,
  ZonotopicEstimator = 5,
  EllipsoidalSMObserver = 6,
  LPVEllipsoidalSMObserver = 7,
  IntervalLuenbergerObserver = 8,
  NonlinearIntervalObserver = 9,
  IntervalInvariantObserver = 10,
};

inline constexpr double kStateTagBase = 5342000.0;  // "SB" 0x53 0x42
inline constexpr double kStateVersion = 1.0;
inline constexpr std::size_t kStateHeader = 4;

inline const char* state_kind_name(StateKind k) {
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
  }
  return "unknown estimator";
}

/// FNV-1a over the bytes of the design data (cheap; not cryptographic: it only refuses a state
/// restored into an estimator made from another design).
class StateFingerprint {
 public:
  StateFingerprint& add(double v) {
    if (v == 0.0) v = 0.0;  // -0 and +0 hash alike
    unsigned char b[sizeof(double)];
    std::memcpy(b, &v, sizeof v);
    for (unsigned char c : b) h_ = (h_ ^ c) * 1099511628211ull;
    return *this;
  }
  StateFingerprint& add_int(long long v) { return add(static_cast<double>(v)); }
  template <class Derived>
  StateFingerprint& add(const Eigen::DenseBase<Derived>& m) {
    add_int(m.rows());
    add_int(m.cols());
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      for (Eigen::Index i = 0; i < m.rows(); ++i) add(static_cast<double>(m(i, j)));
    return *this;
  }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 1469598103934665603ull;
};

/// Builds a blob: header, then items.
class StateWriter {
 public:
  StateWriter(StateKind kind, const StateFingerprint& fp) {
    buf_.push_back(kStateTagBase + static_cast<int>(kind));
    buf_.push_back(kStateVersion);
    buf_.push_back(static_cast<double>(fp.value() >> 32));
    buf_.push_back(static_cast<double>(fp.value() & 0xffffffffull));
  }
  StateWriter& scalar(double v) {
    buf_.push_back(v);
    return *this;
  }
  StateWriter& count(long long v) { return scalar(static_cast<double>(v)); }
  StateWriter& flag(bool v) { return scalar(v ? 1.0 : 0.0); }
  template <class Derived>
  StateWriter& vec(const Eigen::DenseBase<Derived>& v) {
    buf_.push_back(static_cast<double>(v.size()));
    for (Eigen::Index i = 0; i < v.size(); ++i) buf_.push_back(v(i));
    return *this;
  }
  template <class Derived>
  StateWriter& mat(const Eigen::DenseBase<Derived>& m) {
    buf_.push_back(static_cast<double>(m.rows()));
    buf_.push_back(static_cast<double>(m.cols()));
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      for (Eigen::Index i = 0; i < m.rows(); ++i) buf_.push_back(m(i, j));
    return *this;
  }
  StateWriter& text(const std::string& s) {
    buf_.push_back(static_cast<double>(s.size()));
    for (char c : s) buf_.push_back(static_cast<double>(static_cast<unsigned char>(c)));
    return *this;
  }
  StateWriter& blob(const std::vector<double>& b) {
    buf_.push_back(static_cast<double>(b.size()));
    buf_.insert(buf_.end(), b.begin(), b.end());
    return *this;
  }
  std::vector<double> finish() { return std::move(buf_); }

 private:
  std::vector<double> buf_;
};

/// Reads a blob, validating everything; throws InvalidArgumentError("state: ...").
class StateReader {
 public:
  StateReader(const std::vector<double>& b, StateKind kind, const StateFingerprint& fp) : b_(b), kind_(kind) {
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
      if (k >= 1 && k <= 10 && k == std::floor(k))
        what = std::string("a saved ") + state_kind_name(static_cast<StateKind>(static_cast<int>(k)));
      fail("tag " + num(b[0]) + " is " + what + ", expected a saved " + who);
    }
    if (b[1] != kStateVersion) fail("format version " + num(b[1]) + " is not supported (expected " + num(kStateVersion) + ")");
    if (b[2] != static_cast<double>(fp.value() >> 32) || b[3] != static_cast<double>(fp.value() & 0xffffffffull))
      fail("it was saved from a " + who + " with another design (gains, shapes, system or options differ); restore it "
           "into an estimator constructed from the same design");
    pos_ = kStateHeader;
  }

  double scalar(const char* name) {
    need(1, name);
    return b_[pos_++];
  }
  long long count(const char* name, long long lo = 0, long long hi = (1ll << 52)) {
    const double v = scalar(name);
    if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi))
      fail(std::string(name) + " is " + num(v) + ", expected an integer in [" + std::to_string(lo) + ", " +
           std::to_string(hi) + "]");
    return static_cast<long long>(v);
  }
  bool flag(const char* name) { return count(name, 0, 1) != 0; }
  /// A vector of exactly n entries (n < 0: any length).
  Eigen::VectorXd vec(Eigen::Index n, const char* name) {
    const long long len = count(name);
    if (n >= 0 && len != n)
      fail(std::string(name) + " has " + std::to_string(len) + " entries, expected " + std::to_string(n));
    need(static_cast<std::size_t>(len), name);
    Eigen::VectorXd v(static_cast<Eigen::Index>(len));
    for (Eigen::Index i = 0; i < v.size(); ++i) v(i) = b_[pos_++];
    return v;
  }
  /// A rows × cols matrix (negative: any size).
  Eigen::MatrixXd mat(Eigen::Index rows, Eigen::Index cols, const char* name) {
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
  std::string text(const char* name) {
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
  std::vector<double> blob(const char* name) {
    const long long len = count(name);
    need(static_cast<std::size_t>(len), name);
    std::vector<double> out(b_.begin() + static_cast<std::ptrdiff_t>(pos_),
                            b_.begin() + static_cast<std::ptrdiff_t>(pos_ + static_cast<std::size_t>(len)));
    pos_ += static_cast<std::size_t>(len);
    return out;
  }
  /// The blob must end here.
  void finish() const {
    if (pos_ != b_.size())
      fail(std::to_string(b_.size() - pos_) + " values left over after the saved " + state_kind_name(kind_) +
           " (corrupted or of another format)");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InvalidArgumentError(std::string("state: ") + what);
  }

 private:
  static std::string num(double v) {
    std::string s = std::to_string(v);
    return s;
  }
  void need(std::size_t k, const char* name) const {
    if (k > b_.size() - pos_)
      fail(std::string("truncated: ") + name + " needs " + std::to_string(k) + " values, " +
           std::to_string(b_.size() - pos_) + " left");
  }
  const std::vector<double>& b_;
  StateKind kind_;
  std::size_t pos_ = 0;
};

/// Runs the validate-and-build half of a restore_state (which changes nothing) and returns its
/// result. std::bad_alloc there is reported as a refused state (InvalidArgumentError "state:
/// ..."), not as the C ABI's internal "out of memory": the estimator is unchanged, and the
/// caller can go on with it (the message says so).
template <class Build>
auto guard_state_memory(StateKind kind, Build&& build) -> decltype(build()) {
  try {
    return build();
  } catch (const std::bad_alloc&) {
    throw InvalidArgumentError(std::string("state: out of memory while reading the saved ") + state_kind_name(kind) +
                               "; nothing was changed");
  }
}

}  // namespace setbound
