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
  ConstrainedZonotopicEstimator = 11,
  // issue 22, the CORA catalogue's ellipsoidal / interval part (numbers from 21 on)
  BoundingEllipsoid = 21,
  IntervalHinfObserver = 22,
  ZonotopicObserver = 23,  ///< estimators/zonotopic/observer.hpp (CORA's zonotopic catalogue)
  ParallelotopeEstimator = 24,  ///< estimators/zonotopic/parallelotope.hpp (CORA's ROPO)
};

inline constexpr double kStateTagBase = 5342000.0;  // "SB" 0x53 0x42
inline constexpr double kStateVersion = 1.0;
inline constexpr std::size_t kStateHeader = 4;

const char* state_kind_name(StateKind k);

/// FNV-1a over the bytes of the design data (cheap; not cryptographic: it only refuses a state
/// restored into an estimator made from another design).
class StateFingerprint {
 public:
  StateFingerprint& add(double v);
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
  StateWriter(StateKind kind, const StateFingerprint& fp);
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
  StateWriter& text(const std::string& s);
  StateWriter& blob(const std::vector<double>& b);
  std::vector<double> finish() { return std::move(buf_); }

 private:
  std::vector<double> buf_;
};

/// Reads a blob, validating everything; throws InvalidArgumentError("state: ...").
class StateReader {
 public:
  StateReader(const std::vector<double>& b, StateKind kind, const StateFingerprint& fp);

  double scalar(const char* name);
  long long count(const char* name, long long lo = 0, long long hi = (1ll << 52));
  bool flag(const char* name) { return count(name, 0, 1) != 0; }
  /// A vector of exactly n entries (n < 0: any length).
  Eigen::VectorXd vec(Eigen::Index n, const char* name);
  /// A rows × cols matrix (negative: any size).
  Eigen::MatrixXd mat(Eigen::Index rows, Eigen::Index cols, const char* name);
  std::string text(const char* name);
  std::vector<double> blob(const char* name);
  /// The blob must end here.
  void finish() const;
  [[noreturn]] void fail(const std::string& what) const;

 private:
  static std::string num(double v);
  void need(std::size_t k, const char* name) const;
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

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/core/impl/state.ipp"
#endif
