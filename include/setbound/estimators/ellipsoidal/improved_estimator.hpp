// setbound — the improved ellipsoidal estimator ([Merhy2017], papers.md §2, §6): a prediction
// with a fixed shape P (offline, online-vertex or online-scaled, §1) followed at every step by
// the measurement-based correction (§6.3) of the predicted set with the new measurement.
//
// Time indexing (a filter): step(y_k, u_k) corrects the prediction for x_k with y_k and returns
// the corrected set for x_k; then it predicts x_{k+1} with y_k and u_k (the predictors of §1
// use y_k in their centre update, as [Merhy2017] runs LMI (3) then LMI (4) every step).
//
// What is fed back to the prediction (§6.6 is silent in the source; the options are guaranteed
// by the change of shape of §0.1):
//   None        (i)   nothing: the corrected set is only reported;
//   OuterBound  (ii)  the P-shaped outer bound E(P, c', ρ' λ_max(P'^{-1/2} P P'^{-1/2})) of the
//                     corrected set, when its level is below the prediction's;
//   FixedShape  (iii) the fixed-shape correction (option A, P' = P) solved in addition, or (ii)
//                     when that is smaller (default: the P-shaped bound of a thin minimum-volume
//                     set is rarely below the prediction, the fixed-shape optimum often is; it
//                     costs a second, linear, LMI solve per step).
// The reported bounds are the intersection of the interval hulls of the corrected and the
// predicted sets (both contain x_k).
//
// Real measurement data (issue 24): the readings are screened against the predicted set (the
// predictor's test, measurement_check.hpp); the correction uses the outputs present and
// consistent (a corrector per subset of outputs met, built on the sub-system of those rows), and
// so does the prediction (EllipsoidalPredictor::advance). Readings that are each possible can
// still be jointly impossible: then the corrected and predicted hulls do not meet, and the step
// is treated as inconsistent in all its used outputs (never a row with lower > upper).
#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/ellipsoidal/lmi_estimators.hpp"
#include "setbound/estimators/ellipsoidal/improved_correction.hpp"

namespace setbound {

enum class ImprovedFeedback { None = 0, OuterBound = 1, FixedShape = 2 };

class ImprovedEstimator {
 public:
  ImprovedEstimator(EllDesign design, const Ellipsoid& x0,
                    CorrectionOption option = CorrectionOption::DetNormalized,
                    ImprovedFeedback feedback = ImprovedFeedback::FixedShape,
                    EllPredictorMode predictor = EllPredictorMode::OnlineVertex)
      : pred_(design, x0, predictor),
        corrector_(design.system, option, corrector_options(feedback)),
        feedback_(feedback),
        current_(pred_.current()),
        lower_(pred_.current().bounding_box().lo),
        upper_(pred_.current().bounding_box().hi) {
    last_check_.clear(design.system.ny());
  }

  const EllDesign& design() const { return pred_.design(); }
  /// The corrected set for x_k returned by the last step (before the first step: x0 in shape P).
  const Ellipsoid& current() const { return current_; }
  /// Guaranteed bounds of x_k: the intersection of the hulls of the corrected and predicted sets.
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }
  /// The prediction for the next state x_{k+1} (shape P).
  const Ellipsoid& prediction() const { return pred_.current(); }
  Eigen::Index steps_taken() const { return k_; }
  const EllipsoidalPredictor& predictor() const { return pred_; }
  /// True when the last correction could not be solved and certified (the prediction was kept).
  bool last_correction_failed() const { return last_failed_; }

  /// Uses y_k and u_k: returns the corrected set for x_k, then predicts x_{k+1}. NaN entries of
  /// y are missing outputs; impossible readings follow the inconsistency policy. Unchanged on
  /// error.
  Ellipsoid step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);

  /// The inconsistency policy (kept by the predictor; reset set converted to shape P).
  void set_inconsistency_policy(OnInconsistency policy) { pred_.set_inconsistency_policy(policy); }
  void set_inconsistency_policy(OnInconsistency policy, const Ellipsoid& reset_set) {
    pred_.set_inconsistency_policy(policy, reset_set);
  }
  OnInconsistency inconsistency_policy() const { return pred_.inconsistency_policy(); }
  /// The screening of the last step (the test that triggered a reset, with reset = true).
  const MeasurementCheck& last_check() const { return last_check_; }
  /// Back to the initial set and the state right after construction; options are kept.
  void reset();

  /// Full mutable state (core/state.hpp): the predictor's state, the corrected set, the
  /// reported bounds, the step counter and the last correction's status.
  std::vector<double> save_state() const;
  /// Restores a state from save_state() (same design, option, feedback and predictor); throws
  /// InvalidArgumentError ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

 private:
  static ImprovedCorrectionOptions corrector_options(ImprovedFeedback feedback);
  /// The correction of `predicted` with the outputs `use` marks Used.
  CorrectionResult correct_with(const Ellipsoid& predicted, const Eigen::Ref<const Eigen::VectorXd>& y,
                                const Eigen::Ref<const Eigen::VectorXd>& u, const MeasurementCheck& use);

  EllipsoidalPredictor pred_;
  ImprovedCorrector corrector_;
  ImprovedFeedback feedback_;
  Ellipsoid current_;
  Eigen::VectorXd lower_, upper_;
  Eigen::Index k_ = 0;
  bool last_failed_ = false;
  MeasurementCheck last_check_;
  std::map<std::string, ImprovedCorrector> subset_correctors_;  // key: '1' per output used
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/ellipsoidal/impl/improved_estimator.ipp"
#endif
