// setbound — CORA's interval observer skeleton (priv_observe_interval), used by its Hinf-G
// (Tang, Wang, Wang, Raïssi, Shen, "Interval estimation methods for discrete-time linear
// time-invariant systems", IEEE TAC 64(11), 2019; spec cora_observers.md §2.12), as CORA runs it.
//
//   x̂⁺ = A x̂ + B u + L (y − C x̂),   X⁺ = (A − LC) X,   S⁺ = S + □D,   D⁺ = (A − LC) D,
//
// X starts as the whole initial zonotope R0 (centre included), D = (−L)V ⊕ W, S = 0, and the set
// of step i+1 is x̂ + □X + S (□: the interval hull, centre kept). CORA's quirks are kept (this is
// the `convention="cora"` of issue 22): the set of row k ≥ 1 is computed *before* the update with
// y_{k−1}, a one-step lag (row k encloses the state of time k − 1 in exact arithmetic; the
// non-lagged variant misses CORA's vehicle2 value by 2.1e-2), and R0's centre is counted twice
// (row 1 = c_R0 + □R0). The constant c is not part of the recursion, so a model whose constant
// input column is not zero is refused (the sets would be wrong, not merely loose). No rounding
// control: not a guaranteed estimator. setbound's guaranteed interval observer with the same
// error recursion is thesis::IntervalLuenbergerObserver (variant Tight).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/state.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/ellipsoid.hpp"

namespace setbound {

class CoraIntervalObserver {
 public:
  /// sys: A, B, C, E, F (D must be zero: CORA's model has no feedthrough); the disturbance
  /// ω ∈ B^{n_ω} gives W = E ω and V = F ω. R0 = (c0, G0) a zonotope. L: n_x × n_y, finite.
  CoraIntervalObserver(LinearSystem sys, Eigen::VectorXd c0, Eigen::MatrixXd G0, Eigen::MatrixXd L);

  /// Row k of CORA's result (k = steps() before the call): row 0 is □R0; row k ≥ 1 is
  /// x̂ + □X + S before the update with (y_{k−1}, u_{k−1}), which this call then makes.
  /// y (n_y) and u (n_u) must be finite. On error the observer is unchanged.
  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);

  /// The interval hull of the last row (□R0 before the first step).
  const BoundingBox& box() const { return box_; }
  const Eigen::MatrixXd& gain() const { return L_; }
  const LinearSystem& system() const { return sys_; }
  long steps() const { return k_; }
  void reset();
  std::vector<double> save_state() const;
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

 private:
  LinearSystem sys_;
  Eigen::VectorXd c0_;
  Eigen::MatrixXd G0_, L_, Ao_;
  // x̂; X = (cx, GX); D = (cd, GD); S = (cs, rs); the previous reading.
  Eigen::VectorXd xh_, cx_, cd_, cs_, rs_, yprev_, uprev_;
  Eigen::MatrixXd GX_, GD_;
  BoundingBox box_;
  long k_ = 0;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/interval/impl/cora_interval_observer.ipp"
#endif
