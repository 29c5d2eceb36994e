// setbound — definitions of the functions declared in setbound/estimators/ellipsoidal/improved_estimator.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/ellipsoidal/improved_estimator.hpp"
#include "setbound/core/config.hpp"

#include <sstream>

namespace setbound {

SETBOUND_INLINE Ellipsoid ImprovedEstimator::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  const LinearSystem& sys = pred_.design().system;
  const Eigen::Index ny = sys.ny();
  if (y.size() != ny)
    throw DimensionError("y: expected length " + std::to_string(ny) + ", got " + std::to_string(y.size()));
  if (u.size() != sys.nu())
    throw DimensionError("u: expected length " + std::to_string(sys.nu()) + ", got " + std::to_string(u.size()));
  require_no_infinity(y, "y");
  require_finite(u, "u");
  const OnInconsistency policy = pred_.inconsistency_policy();
  Ellipsoid predicted = pred_.current();
  MeasurementCheck report = pred_.screen(predicted, y, u);
  MeasurementCheck use = report;  // the outputs used
  if (report.flagged()) {
    if (policy == OnInconsistency::Raise) pred_.raise_if_inconsistent(report, predicted, y, u);
    if (policy == OnInconsistency::Reset) {
      predicted = pred_.reset_set();
      use = pred_.screen(predicted, y, u);
      report.reset = true;
    }
  }
  CorrectionResult r = correct_with(predicted, y, u, use);
  Eigen::VectorXd lo, hi;
  for (int attempt = 0;; ++attempt) {
    // The set fed back to the prediction (shape P, contains x_k): r.fixed_shape is rule (ii),
    // or the better of (ii) and (iii) when the corrector solves the fixed-shape problem too
    // (FixedShape feedback); it is the prediction when nothing helps.
    const Ellipsoid& back = feedback_ == ImprovedFeedback::None ? predicted : r.fixed_shape;
    const BoundingBox hp = predicted.bounding_box(), hc = r.improved.bounding_box(), hb = back.bounding_box();
    lo = hp.lo.cwiseMax(hc.lo).cwiseMax(hb.lo);
    hi = hp.hi.cwiseMin(hc.hi).cwiseMin(hb.hi);
    // Three outer bounds of the consistent set that do not meet: the readings used are jointly
    // impossible (each was possible alone). Beyond a few ulps this is a certificate.
    bool apart = false;
    for (Eigen::Index i = 0; i < lo.size(); ++i) {
      if (!(lo(i) > hi(i))) continue;
      const double slack = 8.0 * ell_rounding::kEps * (std::abs(lo(i)) + std::abs(hi(i)));
      if (lo(i) > hi(i) + slack) apart = true;
      else std::swap(lo(i), hi(i));  // touching within rounding: keep an interval that covers both
    }
    if (!apart || attempt > 0) {
      if (apart) {  // even the reset set: report and predict without the outputs
        for (auto& st : use.status)
          if (st == OutputStatus::Used) st = OutputStatus::Inconsistent;
        r = correct_with(predicted, y, u, use);
        lo = predicted.bounding_box().lo;
        hi = predicted.bounding_box().hi;
      }
      break;
    }
    // Jointly inconsistent: every used output is reported, then the policy decides.
    for (std::size_t i = 0; i < use.status.size(); ++i)
      if (use.status[i] == OutputStatus::Used) report.status[i] = OutputStatus::Inconsistent;
    if (policy == OnInconsistency::Raise) {
      std::ostringstream s;
      s << "step " << k_ << ": outputs";
      for (std::size_t i = 0; i < use.status.size(); ++i)
        if (use.status[i] == OutputStatus::Used) s << ' ' << i;
      s << ": each reading is possible alone, but no state of the predicted set produces them together (a fault, "
           "a glitch or a wrong model)";
      throw InconsistentMeasurementError(s.str());
    }
    if (policy == OnInconsistency::Reset && !report.reset) {
      predicted = pred_.reset_set();
      use = pred_.screen(predicted, y, u);
      report.reset = true;
    } else {
      for (auto& st : use.status)
        if (st == OutputStatus::Used) st = OutputStatus::Inconsistent;
    }
    r = correct_with(predicted, y, u, use);
  }
  const Ellipsoid& back = feedback_ == ImprovedFeedback::None ? predicted : r.fixed_shape;
  const EllipsoidalPredictor before = pred_;
  try {
    pred_.reset(back);
    pred_.advance(y, u, use);
  } catch (...) {
    pred_ = before;
    throw;
  }
  current_ = std::move(r.improved);
  lower_ = std::move(lo);
  upper_ = std::move(hi);
  last_failed_ = !r.improved_solved;
  last_check_ = std::move(report);
  ++k_;
  return current_;
}

SETBOUND_INLINE CorrectionResult ImprovedEstimator::correct_with(const Ellipsoid& predicted,
                                                                 const Eigen::Ref<const Eigen::VectorXd>& y,
                                                                 const Eigen::Ref<const Eigen::VectorXd>& u,
                                                                 const MeasurementCheck& use) {
  const LinearSystem& sys = pred_.design().system;
  std::string key;
  std::vector<Eigen::Index> rows;
  for (std::size_t i = 0; i < use.status.size(); ++i) {
    const bool used = use.status[i] == OutputStatus::Used;
    key.push_back(used ? '1' : '0');
    if (used) rows.push_back(static_cast<Eigen::Index>(i));
  }
  if (static_cast<Eigen::Index>(rows.size()) == sys.ny()) return corrector_.correct(predicted, y, u);
  if (rows.empty()) {  // nothing to correct with: the prediction, with its trivial certificate
    CorrectionResult r{predicted, predicted, 1.0, Eigen::MatrixXd::Zero(0, 0), Eigen::VectorXd::Zero(sys.nw()), true};
    return r;
  }
  auto it = subset_correctors_.find(key);
  if (it == subset_correctors_.end()) {
    if (subset_correctors_.size() >= 64) subset_correctors_.clear();  // bounded memory
    const Eigen::Index m = static_cast<Eigen::Index>(rows.size());
    Eigen::MatrixXd C(m, sys.nx()), F(m, sys.nw()), D(m, sys.nu());
    for (Eigen::Index j = 0; j < m; ++j) {
      C.row(j) = sys.C().row(rows[static_cast<std::size_t>(j)]);
      F.row(j) = sys.F().row(rows[static_cast<std::size_t>(j)]);
      if (sys.nu() > 0) D.row(j) = sys.D().row(rows[static_cast<std::size_t>(j)]);
    }
    LinearSystem sub(sys.A(), C, sys.E(), F, sys.B(), sys.nu() > 0 ? D : Eigen::MatrixXd(), sys.A_rad());
    it = subset_correctors_.emplace(key, ImprovedCorrector(sub, corrector_.option(), corrector_.options())).first;
  }
  Eigen::VectorXd ys(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t j = 0; j < rows.size(); ++j) ys(static_cast<Eigen::Index>(j)) = y(rows[j]);
  return it->second.correct(predicted, ys, u);
}

SETBOUND_INLINE void ImprovedEstimator::reset() {
  pred_.reset();
  current_ = pred_.current();
  const BoundingBox b = current_.bounding_box();
  lower_ = b.lo;
  upper_ = b.hi;
  k_ = 0;
  last_failed_ = false;
  last_check_.clear(pred_.design().system.ny());
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
