// setbound — missing and impossible readings in the thesis observers (issue 24; the screening
// itself is estimators/measurement_check.hpp, shared with every other family).
//
// The thesis observers (H∞ set-membership LTI/LPV, interval Luenberger, nonlinear, invariant)
// are one-step predictors with a FIXED gain: their set of x_k is x̂_k plus an error bound that
// is tabulated (interval observers) or recursive (μ_k of the SM observers) for the full
// innovation L(y_k − C x̂_k). A step that lacks some output (NaN: missing; or a reading outside
// the predicted output set, skipped under the flag policy) has no such bound. It is made in
// interval arithmetic instead (outward rounded, so guaranteed):
//   1. the box [x_k] is narrowed by the strips of the outputs present, C_i x ∈ y_i − Z_i[v]
//      (one pass of interval constraint propagation per output);
//   2. it is propagated, [x_{k+1}] = A[x_k] + B u_k + F[d] (for the nonlinear observer
//      A[x_k] + [h]_k + B u_k);
//   3. the observer restarts from that box at k+1 (x̂ = its midpoint, the error bound of its
//      radius: the construction's tables with k counted from the restart).
// The SM observers test a reading against the support of their ellipsoid
// {(x − x̂)ᵀP(x − x̂) ≤ μc̄} in ±C_i (a certified upper bound of C_i P⁻¹ C_iᵀ); the interval
// observers against their box. Readings are then as in every other family: policy Flag (skip
// the impossible outputs, mark the step), Raise (InconsistentMeasurementError naming step and
// output, observer unchanged) or Reset (restart from the reset box — by default the initial box
// — and correct from there).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "setbound/estimators/measurement_check.hpp"
#include "setbound/sets/box.hpp"

namespace setbound::thesis {

/// The reading policy of a thesis observer and the screening of its last step.
struct ReadingScreen {
  OnInconsistency policy = OnInconsistency::Flag;
  Box reset_box;           ///< the set Reset restarts from (the observer's initial box)
  MeasurementCheck check;  ///< of the last step (all Used before any step)
  // Predicted output sets of the last screening: center_i ± (radius_i + phi_i); magnitude_i
  // bounds the terms that entered them (test_output's rounding allowance).
  Eigen::VectorXd center, radius, phi, magnitude;

  void init(Eigen::Index ny, const Box& initial);
  /// Sets the policy; `reset` (size n_x, bounded, non-empty) replaces the reset box when its
  /// size is not 0. Throws naming on_inconsistency / reset_set.
  void set_policy(OnInconsistency p, const Box& reset, Eigen::Index nx);
  /// Tests every present reading against the output sets in center/radius/phi/magnitude
  /// (filled by the caller); NaN entries are Missing. Returns true when every output is Used.
  bool screen(const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Index terms);
  /// Policy Raise: throws InconsistentMeasurementError for the first inconsistent output.
  void raise_first(long step, const Eigen::Ref<const Eigen::VectorXd>& y) const;
};

namespace screen_detail {

/// Entrywise half-widths of the model matrices (see fallback_prediction).
struct ModelWidening {
  Eigen::MatrixXd A, B, F;
};

/// Output sets of the box [lo, hi] with output noise v ∈ [vlo, vhi]: center_i = C_i mid + Z_i
/// mid_v, radius_i = |C_i| rad, phi_i = |Z_i| rad_v (plain floating point; the test's rounding
/// allowance covers them through magnitude).
void box_output_sets(const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Eigen::VectorXd& vlo,
                     const Eigen::VectorXd& vhi, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                     ReadingScreen& s);

/// Steps 1–2 above: narrows [lo, hi] by the Used outputs of `check`, then returns
/// A[x] + B u + F[d] (+ [h] when h.size() > 0), all outward rounded. `widen` (optional) holds
/// entrywise half-widths ≥ 0 of A, B and F (the LPV observer's matrices are rounded
/// combinations of the vertices: A(ρ) ∈ A ± widen->A).
Box fallback_prediction(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& F,
                        const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Eigen::VectorXd& lo,
                        const Eigen::VectorXd& hi, const Eigen::Ref<const Eigen::VectorXd>& y,
                        const Eigen::Ref<const Eigen::VectorXd>& u, const Box& d, const Box& v,
                        const MeasurementCheck& check, const Box& h = Box(),
                        const ModelWidening* widen = nullptr);

/// The screening of an observer whose set of x_k is the box [lo, hi]: output sets, test,
/// policy Raise (throws, nothing changed). True: every output is used.
bool screen_box_step(ReadingScreen& s, const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Box& v,
                     const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, const Eigen::Ref<const Eigen::VectorXd>& y,
                     long step);

/// Policy Reset with a flagged step: [lo, hi] becomes the reset box, y is screened against it,
/// s.check keeps the test that triggered the reset (reset = true) and the outputs to use
/// (those consistent with the reset box) are returned. Otherwise returns s.check unchanged.
MeasurementCheck apply_reset(ReadingScreen& s, const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Box& v,
                             const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::VectorXd& lo, Eigen::VectorXd& hi);

/// Narrowing only (step 1): the box [lo, hi] with the strips of the Used outputs.
Box narrow_by_outputs(const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Eigen::VectorXd& lo,
                      const Eigen::VectorXd& hi, const Eigen::Ref<const Eigen::VectorXd>& y, const Box& v,
                      const MeasurementCheck& check);

}  // namespace screen_detail

}  // namespace setbound::thesis

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/thesis/impl/reading_screen.ipp"
#endif
