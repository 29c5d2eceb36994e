// setbound — screening of a measurement before a correction: missing outputs and readings that
// no state of the model can produce (issue 24, "real measurement data").
//
// Every guaranteed estimator holds a set X that contains every state consistent with the model,
// the bounds and the data used so far. Output i then lies in its predicted output set
//     c_iᵀX + D_i u + [−φ_i, φ_i],     φ_i = Σ_j |F_ij|  (papers.md §0.3),
// an interval given by the support function of X in the directions ±c_i. A reading outside it is
// impossible: no state of X, hence no consistent state, produces it. Intersecting X with that
// strip would "correct" with an empty set and return a set that need not contain the true state,
// so the reading is not used and is reported. Because X is an OUTER bound of the consistent set,
// the test is one-sided exact: an inconsistency reported here is a certificate that the model,
// the bounds or the data are wrong (a fault): zero false alarms while they hold. Rounding is
// accounted for (inconsistency is declared only beyond a bound of the rounding error of the
// support computation), so a consistent reading is never declared inconsistent.
//
// A missing output is a NaN entry of y: the estimator predicts, and corrects with the outputs
// that are present.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace setbound {

/// What an estimator does with a reading outside its predicted output set.
enum class OnInconsistency : int {
  Flag = 0,   ///< skip the impossible outputs, keep the rest of the step, mark it (the default)
  Raise = 1,  ///< throw InconsistentMeasurementError naming the step and the output; unchanged
  Reset = 2,  ///< restart from the reset set (default: the initial set) and correct from there
};

/// What happened to one output at one step (the C ABI's SB_OUTPUT_* values).
enum class OutputStatus : std::int8_t {
  Used = 0,          ///< present, consistent, used in the correction
  Missing = 1,       ///< NaN: not measured
  Inconsistent = 2,  ///< outside the predicted output set: not used, reported
  Unused = 3,        ///< present but not used by design (e.g. the first step with
                     ///< use_first_measurement = false)
};

/// The screening of one step: per output its status and its margin, the distance of the reading
/// from the predicted output set in units of the output's noise bound φ_i (absolute when φ_i = 0):
/// > 0 outside (inconsistent when beyond the rounding bound), <= 0 inside (−1 at the centre of
/// a point prediction), NaN when the output was missing or not tested.
struct MeasurementCheck {
  std::vector<OutputStatus> status;
  Eigen::VectorXd margin;
  bool reset = false;  ///< the estimator restarted from its reset set at this step

  void clear(Eigen::Index ny, OutputStatus s = OutputStatus::Unused) {
    status.assign(static_cast<std::size_t>(ny), s);
    margin.setConstant(ny, std::numeric_limits<double>::quiet_NaN());
    reset = false;
  }
  /// Whether some output was inconsistent (the step is flagged).
  bool flagged() const;
  /// The first inconsistent output, or −1.
  Eigen::Index first_inconsistent() const;
};

/// Relative slack of the consistency test beyond the rounding of its own computation: a reading
/// is declared impossible only when it lies outside the predicted output set by more than
/// 1e-12 of the magnitudes involved (faults that small are far below any sensor's resolution).
inline constexpr double kReadingSlack = 1e-12;

/// Result of testing one reading against a predicted output interval.
struct OutputTest {
  double margin;      ///< see MeasurementCheck
  bool inconsistent;  ///< beyond the rounding bound
};

/// Reading y (already shifted by D_i u) against the output set center ± (radius + φ).
/// `magnitude` bounds the sum of the absolute values of every term that entered center and
/// radius (|c|ᵀ|p| + |c|ᵀ rs|H| + …); `terms` the number of rounded operations along the
/// longest chain (n + m + …). Inconsistent only if the gap exceeds
/// (2γ_terms + kReadingSlack)(magnitude + |y| + φ).
OutputTest test_output(double y, double center, double radius, double phi, double magnitude, Eigen::Index terms);

/// A lower bound of Σ_j |tᵀg_j| (the part of an output set's radius from generators g_j) from a
/// Gram matrix S ≈ G Gᵀ kept by rank updates: Σ_j |tᵀg_j| >= ‖Gᵀt‖₂ = (tᵀ S t)^½. `tSt` is tᵀ S t
/// computed with the kept S, minus the squares of projections it also holds but the radius
/// counts exactly elsewhere; `S_max` = max |S_ij|, `t2` = ‖t‖². The kept S drifts from G Gᵀ by
/// rounding: 0.9 and 1e-10 S_max t2 leave room for it (both screens that use this only decide
/// "consistent" with it; a wrong decision would lose a flag, never the guarantee).
double gram_radius_lower_bound(double tSt, double S_max, double t2);

/// The ±inf check of a measurement vector: NaN means missing and is accepted, ±inf is an error
/// naming the entry ("y: entry 3 is inf; ...").
void require_no_infinity(const Eigen::Ref<const Eigen::VectorXd>& y, const std::string& name);

/// The InconsistentMeasurementError of policy Raise: "step k: output i: reading … lies … noise
/// bounds outside the predicted output set [lo, hi]".
[[noreturn]] void throw_inconsistent(Eigen::Index step, Eigen::Index output, double y, double center, double radius,
                                     double phi, double margin);

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/impl/measurement_check.ipp"
#endif
