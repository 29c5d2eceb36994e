// setbound — definitions of the functions declared in setbound/estimators/improved_estimator.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/improved_estimator.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE Ellipsoid ImprovedEstimator::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
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

SETBOUND_INLINE std::vector<double> ImprovedEstimator::save_state() const {
  StateWriter w(StateKind::ImprovedEstimator, fingerprint());
  w.blob(pred_.save_state()).count(k_).flag(last_failed_);
  w.mat(current_.shape()).vec(current_.center()).scalar(current_.level()).vec(lower_).vec(upper_);
  return w.finish();
}

SETBOUND_INLINE void ImprovedEstimator::restore_state(const std::vector<double>& state) {
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

SETBOUND_INLINE StateFingerprint ImprovedEstimator::fingerprint() const {
  StateFingerprint f = pred_.fingerprint();
  f.add_int(static_cast<int>(corrector_.option())).add_int(static_cast<int>(feedback_));
  return f;
}

SETBOUND_INLINE ImprovedCorrectionOptions ImprovedEstimator::corrector_options(ImprovedFeedback feedback) {
  ImprovedCorrectionOptions o;
  o.fixed_shape_by_lmi = feedback == ImprovedFeedback::FixedShape;
  return o;
}

}  // namespace setbound
