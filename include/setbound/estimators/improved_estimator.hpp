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
#pragma once

#include <Eigen/Core>
#include <memory>
#include <utility>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/ellipsoidal.hpp"
#include "setbound/estimators/improved_correction.hpp"

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
        upper_(pred_.current().bounding_box().hi) {}

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

  /// Uses y_k and u_k: returns the corrected set for x_k, then predicts x_{k+1}. Unchanged on error.
  Ellipsoid step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
    const LinearSystem& sys = pred_.design().system;
    if (y.size() != sys.ny())
      throw DimensionError("y: expected length " + std::to_string(sys.ny()) + ", got " + std::to_string(y.size()));
    if (u.size() != sys.nu())
      throw DimensionError("u: expected length " + std::to_string(sys.nu()) + ", got " + std::to_string(u.size()));
    require_finite(y, "y");
    require_finite(u, "u");
    const Ellipsoid predicted = pred_.current();
    CorrectionResult r = corrector_.correct(predicted, y, u);
    // The set fed back to the prediction (shape P, contains x_k).
    // r.fixed_shape is rule (ii), or the better of (ii) and (iii) when the corrector solves the
    // fixed-shape problem too (FixedShape feedback); it is the prediction when nothing helps.
    const Ellipsoid& back = feedback_ == ImprovedFeedback::None ? predicted : r.fixed_shape;
    const BoundingBox hp = predicted.bounding_box(), hc = r.improved.bounding_box(), hb = back.bounding_box();
    Eigen::VectorXd lo = hp.lo.cwiseMax(hc.lo).cwiseMax(hb.lo);
    Eigen::VectorXd hi = hp.hi.cwiseMin(hc.hi).cwiseMin(hb.hi);
    pred_.reset(back);
    pred_.step(y, u);
    current_ = std::move(r.improved);
    lower_ = std::move(lo);
    upper_ = std::move(hi);
    last_failed_ = !r.improved_solved;
    ++k_;
    return current_;
  }

  /// Full mutable state (core/state.hpp): the predictor's state, the corrected set, the
  /// reported bounds, the step counter and the last correction's status.
  std::vector<double> save_state() const {
    StateWriter w(StateKind::ImprovedEstimator, fingerprint());
    w.blob(pred_.save_state()).count(k_).flag(last_failed_);
    w.mat(current_.shape()).vec(current_.center()).scalar(current_.level()).vec(lower_).vec(upper_);
    return w.finish();
  }
  /// Restores a state from save_state() (same design, option, feedback and predictor); throws
  /// InvalidArgumentError ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state) {
    struct Parsed {
      EllipsoidalPredictor::ParsedState ps;
      long long k;
      bool failed;
      std::unique_ptr<Ellipsoid> cur;
      Eigen::VectorXd lo, hi;
    };
    Parsed q = guard_state_memory(StateKind::ImprovedEstimator, [&] {
      const Eigen::Index n = pred_.design().system.nx();
      StateReader r(state, StateKind::ImprovedEstimator, fingerprint());
      const std::vector<double> pstate = r.blob("predictor");
      Parsed t{pred_.parse_state(pstate), 0, false, nullptr, {}, {}};  // validates, changes nothing
      t.k = r.count("steps");
      t.failed = r.flag("last_correction_failed");
      Eigen::MatrixXd P = r.mat(n, n, "shape");
      Eigen::VectorXd c = r.vec(n, "center");
      const double rho = r.scalar("level");
      t.lo = r.vec(n, "lower");
      t.hi = r.vec(n, "upper");
      r.finish();
      try {
        t.cur = std::make_unique<Ellipsoid>(std::move(P), std::move(c), rho);
      } catch (const Error& e) {
        r.fail(std::string("the saved corrected set is invalid (") + e.what() + ")");
      }
      return t;
    });
    // Commit (moves only: nothing throws).
    pred_.apply_state(std::move(q.ps));
    current_ = std::move(*q.cur);
    lower_.swap(q.lo);
    upper_.swap(q.hi);
    k_ = static_cast<Eigen::Index>(q.k);
    last_failed_ = q.failed;
  }
  StateFingerprint fingerprint() const {
    StateFingerprint f = pred_.fingerprint();
    f.add_int(static_cast<int>(corrector_.option())).add_int(static_cast<int>(feedback_));
    return f;
  }

 private:
  static ImprovedCorrectionOptions corrector_options(ImprovedFeedback feedback) {
    ImprovedCorrectionOptions o;
    o.fixed_shape_by_lmi = feedback == ImprovedFeedback::FixedShape;
    return o;
  }

  EllipsoidalPredictor pred_;
  ImprovedCorrector corrector_;
  ImprovedFeedback feedback_;
  Ellipsoid current_;
  Eigen::VectorXd lower_, upper_;
  Eigen::Index k_ = 0;
  bool last_failed_ = false;
};

}  // namespace setbound
