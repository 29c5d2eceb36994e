// setbound — definitions of the functions declared in setbound/estimators/constrained_zonotopic/estimator.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "setbound/core/config.hpp"
#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/constrained_zonotopic/estimator.hpp"
#include "setbound/sets/interval.hpp"
#include "setbound/sets/zonotope_reduction.hpp"

namespace setbound {

namespace czn_detail {

/// D u, or zeros when the system has no feed-through.
SETBOUND_INLINE Eigen::VectorXd feedthrough(const LinearSystem& s, const Eigen::Ref<const Eigen::VectorXd>& u) {
  if (s.D().size() == 0 || s.nu() == 0) return Eigen::VectorXd::Zero(s.ny());
  return s.D() * u;
}

}  // namespace czn_detail

SETBOUND_INLINE ConstrainedZonotopicEstimator::ConstrainedZonotopicEstimator(LinearSystem system, ConstrainedZonotope x0,
                                                                            CZOptions options)
    : sys_(std::move(system)), x0_(std::move(x0)), opt_(options), reset_set_(x0_), prior_(x0_), current_(x0_) {
  if (sys_.uncertain_A())
    throw InvalidArgumentError("system: the constrained-zonotope estimators need a known A (no interval A)");
  if (x0_.dimension() != sys_.nx())
    throw DimensionError("x0: expected a set in R^" + std::to_string(sys_.nx()) + ", got R^" +
                         std::to_string(x0_.dimension()));
  require_finite(opt_.order, "order");
  if (!(opt_.order >= 1.0)) throw InvalidArgumentError("order: must be >= 1, got " + std::to_string(opt_.order));
  if (opt_.correction != CZCorrection::ExactOutput && opt_.correction != CZCorrection::WangStrips)
    throw InvalidArgumentError("correction: unknown method " + std::to_string(static_cast<int>(opt_.correction)));
  if (opt_.reduction != CZReduction::None && opt_.reduction != CZReduction::Cora && opt_.reduction != CZReduction::Limits)
    throw InvalidArgumentError("reduction: unknown method " + std::to_string(static_cast<int>(opt_.reduction)));
  const Eigen::Index n = sys_.nx();
  // Defaults from a first accuracy measurement (8 random systems, n_x 2–4: mean width 1.02–1.29×
  // the exact hull, against 1.05–1.84× with 2 n_x rows and 12 n_x generators).
  if (opt_.max_constraints == -1) opt_.max_constraints = 4 * n;
  if (opt_.max_constraints < 0)
    throw InvalidArgumentError("max_constraints: must be >= 0 (or -1 for 4 n_x), got " + std::to_string(opt_.max_constraints));
  if (opt_.max_generators == -1) opt_.max_generators = 20 * n + opt_.max_constraints;
  if (opt_.max_generators < n + opt_.max_constraints)
    throw InvalidArgumentError("max_generators: must be >= n_x + max_constraints = " +
                               std::to_string(n + opt_.max_constraints) + " (or -1 for the default), got " +
                               std::to_string(opt_.max_generators));
  sigma_.resize(sys_.ny());
  for (Eigen::Index i = 0; i < sys_.ny(); ++i) {
    const double s = sys_.F().row(i).cwiseAbs().sum();
    sigma_(i) = s * (1.0 + 2.0 * rounding_bounds::gamma(sys_.F().cols()));
  }
  reset();
}

SETBOUND_INLINE void ConstrainedZonotopicEstimator::reset() {
  prior_ = x0_;
  current_ = x0_;
  has_current_ = false;
  k_ = 0;
  lo_.resize(0);
  hi_.resize(0);
  check_.clear(sys_.ny());
}

SETBOUND_INLINE void ConstrainedZonotopicEstimator::set_inconsistency_policy(OnInconsistency policy) {
  set_inconsistency_policy(policy, x0_);
}

SETBOUND_INLINE void ConstrainedZonotopicEstimator::set_inconsistency_policy(OnInconsistency policy,
                                                                            const ConstrainedZonotope& reset_set) {
  if (policy != OnInconsistency::Flag && policy != OnInconsistency::Raise && policy != OnInconsistency::Reset)
    throw InvalidArgumentError("on_inconsistency: unknown policy " + std::to_string(static_cast<int>(policy)));
  if (reset_set.dimension() != sys_.nx())
    throw DimensionError("reset_set: expected a set in R^" + std::to_string(sys_.nx()) + ", got R^" +
                         std::to_string(reset_set.dimension()));
  opt_.on_inconsistency = policy;
  reset_set_ = reset_set;
}

SETBOUND_INLINE const ConstrainedZonotope& ConstrainedZonotopicEstimator::current_set() const {
  if (!has_current_) throw InvalidArgumentError("current_set: no step has been taken yet");
  return current_;
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotopicEstimator::predict(const ConstrainedZonotope& X,
                                                                          const Eigen::Ref<const Eigen::VectorXd>& u) const {
  // Long runs (bounded mode, no reduction) keep the rounding box from wrapping through A by turning
  // it into columns once it is no longer negligible (absorb_rounding). CORA's mode keeps CORA's
  // generator count instead: its reduction folds the box in (reduce_cora), and its runs are short
  // (its constraints are never removed).
  ConstrainedZonotope P = (opt_.reduction == CZReduction::Cora ? X : X.absorb_rounding()).linear_map(sys_.A());
  if (sys_.nu() > 0) P = P.translate(sys_.B() * u);  // B u's own rounding: P.translate adds γ|c'|
  if (sys_.nw() > 0) {
    Eigen::MatrixXd E = sys_.E();
    // Columns of E that are zero (pure output noise) add nothing.
    std::vector<Eigen::Index> keep;
    for (Eigen::Index j = 0; j < E.cols(); ++j)
      if (box_lp_detail::max_abs(E.col(j)) > 0.0) keep.push_back(j);
    Eigen::MatrixXd Ek(E.rows(), static_cast<Eigen::Index>(keep.size()));
    for (size_t j = 0; j < keep.size(); ++j) Ek.col(static_cast<Eigen::Index>(j)) = E.col(keep[j]);
    if (Ek.cols() > 0) P = P.minkowski_sum(Zonotope(Eigen::VectorXd::Zero(sys_.nx()), Ek));
  }
  return P;
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotopicEstimator::correct(const ConstrainedZonotope& X,
                                                                          const Eigen::Ref<const Eigen::VectorXd>& y,
                                                                          const Eigen::Ref<const Eigen::VectorXd>& u,
                                                                          const std::vector<Eigen::Index>& used) const {
  if (used.empty()) return X;
  const Eigen::Index p = static_cast<Eigen::Index>(used.size()), n = sys_.nx();
  const Eigen::VectorXd Du = czn_detail::feedthrough(sys_, u);
  Eigen::MatrixXd C(p, n), FS(p, sys_.F().cols());
  Eigen::VectorXd ys(p), du_err = Eigen::VectorXd::Zero(p);
  // |fl(D u) − D u| <= γ |D||u| per row (zero without feed-through).
  const Eigen::VectorXd du_bound = (sys_.nu() > 0 && sys_.D().size() > 0)
      ? Eigen::VectorXd(rounding_bounds::gamma(sys_.nu()) * (sys_.D().cwiseAbs() * u.cwiseAbs()) * 2.0)
      : Eigen::VectorXd::Zero(sys_.ny());
  for (Eigen::Index k = 0; k < p; ++k) {
    const Eigen::Index i = used[static_cast<size_t>(k)];
    C.row(k) = sys_.C().row(i);
    FS.row(k) = sys_.F().row(i);
    ys(k) = y(i) - Du(i);
    du_err(k) = du_bound(i);
  }
  if (opt_.correction == CZCorrection::ExactOutput) {
    // y − D u − C x ∈ F_S B: the noise rows of the used outputs, zero columns dropped. The
    // rounding of y − D u (and of D u) is absorbed by intersect_output's rounding box of the
    // output set's centre only for the subtraction; D u's own product error is added below.
    std::vector<Eigen::Index> keep;
    for (Eigen::Index j = 0; j < FS.cols(); ++j)
      if (box_lp_detail::max_abs(FS.col(j)) > 0.0) keep.push_back(j);
    Eigen::MatrixXd V(p, static_cast<Eigen::Index>(keep.size()));
    for (size_t j = 0; j < keep.size(); ++j) V.col(static_cast<Eigen::Index>(j)) = FS.col(keep[j]);
    if (du_err.maxCoeff() > 0.0) {  // a private noise column per row covers D u's rounding
      Eigen::MatrixXd Vx(p, V.cols() + p);
      Vx << V, Eigen::MatrixXd::Zero(p, p);
      Vx.rightCols(p).diagonal() = du_err;
      V = std::move(Vx);
    }
    ConstrainedZonotope Xc = X.intersect_output(C, ys, Zonotope(Eigen::VectorXd::Zero(p), V));
    if (opt_.reduction != CZReduction::Limits) return Xc;
    // The bounded mode writes the new rows with a gain (substitute_rows: the same set, another
    // parametrisation). The rows say C G ξ − V ζ = ys − C c; with Λ, x = c + Λ(ys − C c) +
    // (I − ΛC) G ξ + Λ V ζ on them. Λ = P Cᵀ (C P Cᵀ + V Vᵀ)⁻¹, P = G Gᵀ of the predicted set,
    // minimises the Frobenius norm of those generators (segment minimisation's rule, all outputs
    // at once). Why: the reduction that follows boxes generators and eliminates rows, and what
    // it loses grows with the generators' size. Without the gain the generators keep the
    // prediction's full size and the measurement sits only in the rows; once rows are
    // eliminated, directions the outputs see only through the dynamics lose their correlation
    // step after step: on vehicle6 CZN-A's width grew without bound (x6 from 5.8 at step 25 to
    // 46 at step 325, where segment minimisation stays at 9.4); with the gain it stays bounded
    // (docs/theory/constrained_zonotopes.md). Any Λ gives the same set, so a singular C P Cᵀ + V Vᵀ
    // (no gain) keeps the intersection as it is.
    const Eigen::MatrixXd& G = X.generators();
    const Eigen::MatrixXd CG = C * G;
    const Eigen::MatrixXd S = CG * CG.transpose() + V * V.transpose();
    const Eigen::LLT<Eigen::MatrixXd> llt(S);
    if (llt.info() != Eigen::Success) return Xc;
    const Eigen::MatrixXd Lambda = llt.solve(CG * G.transpose()).transpose();
    if (!Lambda.allFinite()) return Xc;
    return Xc.substitute_rows(Lambda, Xc.num_constraints() - p);
  }
  // CZN-B (WangStrips): strips |C_i x − ys_i| <= σ_i as one generalized intersection (the
  // strip variable t_i private to its row, so the rounding slack widens σ_i), then CORA's
  // representation x = c + Λ(b_S − M ξ + σ ∘ t) + G ξ on the stored rows M ξ − σ t = b_S.
  Eigen::VectorXd sig(p);
  for (Eigen::Index k = 0; k < p; ++k) sig(k) = rounding::add_up(sigma_(used[static_cast<size_t>(k)]), du_err(k));
  const ConstrainedZonotope strips(ys, sig.asDiagonal().toDenseMatrix(), Eigen::MatrixXd(0, p), Eigen::VectorXd(0));
  const ConstrainedZonotope Xs = X.intersect(strips, C);
  // The gain from the set entering the correction: P = G Gᵀ, R̄ = A P Aᵀ + E Eᵀ, S = C R̄ Cᵀ + F Fᵀ.
  const Eigen::MatrixXd& G = X.generators();
  const Eigen::MatrixXd P = G * G.transpose();
  const Eigen::MatrixXd Rbar = sys_.A() * P * sys_.A().transpose() + sys_.E() * sys_.E().transpose();
  const Eigen::MatrixXd S = C * Rbar * C.transpose() + FS * FS.transpose();
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(S);
  if (!lu.isInvertible()) return Xs;  // no gain: the intersection's own representation (same set)
  const Eigen::MatrixXd Lambda = Rbar * C.transpose() * lu.inverse();
  if (!Lambda.allFinite()) return Xs;
  return Xs.substitute_rows(Lambda, Xs.num_constraints() - p);
}

SETBOUND_INLINE std::vector<Eigen::Index> ConstrainedZonotopicEstimator::screen(const ConstrainedZonotope& X, BoxLP& lp,
                                                                               const Eigen::Ref<const Eigen::VectorXd>& y,
                                                                               const Eigen::Ref<const Eigen::VectorXd>& u,
                                                                               MeasurementCheck& chk) const {
  chk.clear(sys_.ny(), OutputStatus::Missing);
  const Eigen::VectorXd Du = czn_detail::feedthrough(sys_, u);
  std::vector<Eigen::Index> present;
  for (Eigen::Index i = 0; i < sys_.ny(); ++i)
    if (!std::isnan(y(i))) present.push_back(i);
  // [lo_i, hi_i] ⊇ {C_i x : x ∈ X} (certified support values, one LP basis for every output).
  Eigen::MatrixXd Cp(static_cast<Eigen::Index>(present.size()), sys_.nx());
  for (size_t k = 0; k < present.size(); ++k) Cp.row(static_cast<Eigen::Index>(k)) = sys_.C().row(present[k]);
  const BoundingBox out = present.empty() ? BoundingBox{} : X.image_bounds(Cp, lp);
  std::vector<Eigen::Index> used;
  for (size_t k = 0; k < present.size(); ++k) {
    const Eigen::Index i = present[k];
    const double hi = out.hi(static_cast<Eigen::Index>(k)), lo = out.lo(static_cast<Eigen::Index>(k));
    if (!(lo <= hi)) {  // X itself is certified empty: nothing is consistent with it
      chk.status[static_cast<size_t>(i)] = OutputStatus::Inconsistent;
      continue;
    }
    const double center = 0.5 * lo + 0.5 * hi;
    const double radius = std::max(rounding::sub_up(hi, center), rounding::sub_up(center, lo));
    const double magnitude = std::abs(lo) + std::abs(hi) + std::abs(Du(i));
    const OutputTest t = test_output(y(i) - Du(i), center, radius, sigma_(i), magnitude, sys_.nu() + 2);
    chk.margin(i) = t.margin;
    if (t.inconsistent) {
      chk.status[static_cast<size_t>(i)] = OutputStatus::Inconsistent;
      if (opt_.on_inconsistency == OnInconsistency::Raise)
        throw_inconsistent(k_, i, y(i) - Du(i), center, radius, sigma_(i), t.margin);
      continue;
    }
    chk.status[static_cast<size_t>(i)] = OutputStatus::Used;
    used.push_back(i);
  }
  return used;
}

SETBOUND_INLINE void ConstrainedZonotopicEstimator::optimistic_margins(const Eigen::MatrixXd& points,
                                                                        const Eigen::Ref<const Eigen::VectorXd>& y,
                                                                        const Eigen::Ref<const Eigen::VectorXd>& u,
                                                                        MeasurementCheck& chk) const {
  // Every point of X ∩ strips is a point of X, so [min, max] of C_i x over the points lies inside
  // C_i X: the margin against it is >= the margin against C_i X (up to the simplex's tolerance).
  const Eigen::VectorXd Du = czn_detail::feedthrough(sys_, u);
  for (Eigen::Index i = 0; i < sys_.ny(); ++i) {
    if (chk.status[static_cast<size_t>(i)] != OutputStatus::Used) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (Eigen::Index k = 0; k < points.cols(); ++k) {
      if (std::isnan(points(0, k))) continue;
      const double v = sys_.C().row(i).dot(points.col(k));
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    if (!(lo <= hi)) continue;  // no point: the margin stays NaN (not tested)
    // (Only the margin is read: the rounding tolerance, hence `magnitude`, decides nothing here.)
    const double magnitude = std::abs(lo) + std::abs(hi) + std::abs(Du(i));
    chk.margin(i) = test_output(y(i) - Du(i), 0.5 * lo + 0.5 * hi, 0.5 * hi - 0.5 * lo, sigma_(i), magnitude,
                                sys_.nu() + 2).margin;
  }
}

SETBOUND_INLINE void ConstrainedZonotopicEstimator::update(const Eigen::Ref<const Eigen::VectorXd>& y,
                                                          const Eigen::Ref<const Eigen::VectorXd>& u) {
  if (y.size() != sys_.ny())
    throw DimensionError("y: expected length " + std::to_string(sys_.ny()) + ", got " + std::to_string(y.size()));
  require_no_infinity(y, "y");
  if (u.size() != sys_.nu())
    throw DimensionError("u: expected length " + std::to_string(sys_.nu()) + ", got " + std::to_string(u.size()));
  require_finite(u, "u");
  MeasurementCheck chk;
  ConstrainedZonotope X = prior_;
  ConstrainedZonotope corrected = X;
  const bool correct_now = k_ > 0 || opt_.use_first_measurement;
  // The optimistic path (Limits and None): every present reading is used at once and the LP of
  // the corrected set decides. When phase 1 finds a point of X ∩ strips, each reading is
  // consistent with X (that point produces it) and the 2 n_y screening LPs per step are not
  // needed (on vehicle6 they were 36 % of a step); the margins of those readings then come from
  // the hull LPs' points (below). Only when the corrected set is not found feasible (certified
  // empty, or undecided) does the step screen each reading against X with certified support
  // values, as CORA's mode always does. A reading outside X's output set by less than the
  // simplex's feasibility tolerance (1e-9 of its row's scale) can thus count as consistent,
  // where the screen's certified test would flag it beyond 1e-12 of the magnitudes.
  bool optimistic = correct_now && opt_.reduction != CZReduction::Cora;
  std::vector<Eigen::Index> used;
  BoxLP lp = [&] {
    if (!optimistic) return BoxLP(X.constraint_matrix(), X.constraint_vector());
    chk.clear(sys_.ny(), OutputStatus::Missing);
    for (Eigen::Index i = 0; i < sys_.ny(); ++i)
      if (!std::isnan(y(i))) {
        chk.status[static_cast<size_t>(i)] = OutputStatus::Used;
        used.push_back(i);
      }
    corrected = correct(X, y, u, used);
    BoxLP joint(corrected.constraint_matrix(), corrected.constraint_vector());
    if (joint.feasibility() == BoxLP::Feasibility::feasible) return joint;
    optimistic = false;  // screen each reading against X (the step's LP on X's rows)
    corrected = X;
    used.clear();
    return BoxLP(X.constraint_matrix(), X.constraint_vector());
  }();
  if (!correct_now) {
    chk.clear(sys_.ny(), OutputStatus::Unused);
  } else if (!optimistic) {
    used = screen(X, lp, y, u, chk);
    if (chk.flagged() && opt_.on_inconsistency == OnInconsistency::Reset) {
      X = reset_set_;
      lp = BoxLP(X.constraint_matrix(), X.constraint_vector());
      MeasurementCheck again;
      used = screen(X, lp, y, u, again);
      again.reset = true;
      for (size_t i = 0; i < again.status.size(); ++i)  // keep what the first screening found
        if (chk.status[i] == OutputStatus::Inconsistent) again.status[i] = OutputStatus::Inconsistent;
      chk = again;
    }
    corrected = correct(X, y, u, used);
    // The correction appended rows and columns (and kept X's rows): phase 1 goes on from the
    // screening's basis.
    if (!used.empty()) lp.extend(corrected.constraint_matrix(), corrected.constraint_vector());
    if (!used.empty() && corrected.emptiness(lp).empty) {
      // Each reading was possible, together they are not: report the step, keep the prediction
      // (or restart, or raise), never an empty "estimate".
      for (Eigen::Index i : used) {
        chk.status[static_cast<size_t>(i)] = OutputStatus::Inconsistent;
        chk.margin(i) = std::numeric_limits<double>::quiet_NaN();
      }
      if (opt_.on_inconsistency == OnInconsistency::Raise)
        throw InconsistentMeasurementError("step " + std::to_string(k_) + ": outputs jointly inconsistent: each reading "
                                           "is possible alone, but no state of the predicted set produces them all "
                                           "(a fault, a glitch or a wrong model)");
      corrected = (opt_.on_inconsistency == OnInconsistency::Reset) ? reset_set_ : X;
      if (opt_.on_inconsistency == OnInconsistency::Reset) chk.reset = true;
      lp = BoxLP(corrected.constraint_matrix(), corrected.constraint_vector());
    }
  }
  BoundingBox hull;
  Eigen::MatrixXd points;  // the hull LPs' points of the corrected set (the optimistic margins)
  if (opt_.reduction == CZReduction::Cora) {
    // CORA's hull is that of the reduced set (conZonotope/reduce.m, then interval()).
    if (correct_now && k_ > 0) corrected = corrected.reduce_cora(opt_.technique, opt_.order);
    hull = corrected.interval_hull();
  } else {
    // The hull LPs' multipliers guide the reduction: the generators whose box costs the hull least
    // are boxed, the rows it leans on least are eliminated first (measured on the §3.5 example:
    // row order alone took the mean width from 1.61 to 1.26 times the exact hull). The hull is
    // taken before the reduction (see the header); its sensitivity only when a reduction follows.
    const bool reduce = correct_now && opt_.reduction == CZReduction::Limits;
    ConstrainedZonotope::HullSensitivity sensitivity;
    hull = corrected.interval_hull(lp, reduce ? &sensitivity : nullptr, points);
    if (optimistic) optimistic_margins(points, y, u, chk);
    if (reduce) corrected = corrected.reduce_limits(opt_.max_generators, opt_.max_constraints, opt_.technique, sensitivity);
  }
  ConstrainedZonotope next = predict(corrected, u);
  // Commit (everything above may throw; nothing was changed before this point).
  current_ = std::move(corrected);
  prior_ = std::move(next);
  lo_ = hull.lo;
  hi_ = hull.hi;
  check_ = std::move(chk);
  has_current_ = true;
  ++k_;
}

SETBOUND_INLINE CZTrajectory ConstrainedZonotopicEstimator::run(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U) {
  if (Y.cols() != sys_.ny())
    throw DimensionError("Y: expected " + std::to_string(sys_.ny()) + " columns (one per output), got shape " +
                         detail::shape_string(Y.rows(), Y.cols()));
  const bool no_input = sys_.nu() == 0;
  if (!no_input && (U.rows() != Y.rows() || U.cols() != sys_.nu()))
    throw DimensionError("U: expected shape " + detail::shape_string(Y.rows(), sys_.nu()) + ", got " +
                         detail::shape_string(U.rows(), U.cols()));
  for (Eigen::Index k = 0; k < Y.rows(); ++k)
    for (Eigen::Index i = 0; i < Y.cols(); ++i)
      if (std::isinf(Y(k, i)))
        throw NotFiniteError("Y: row " + std::to_string(k) + ", output " + std::to_string(i) +
                             " is inf; a reading must be finite (NaN marks a missing one)");
  if (!no_input) require_finite(U, "U");
  reset();
  CZTrajectory t;
  t.lower.resize(Y.rows(), sys_.nx());
  t.upper.resize(Y.rows(), sys_.nx());
  const Eigen::VectorXd none(0);
  for (Eigen::Index k = 0; k < Y.rows(); ++k) {
    if (no_input) update(Y.row(k).transpose(), none);
    else update(Y.row(k).transpose(), U.row(k).transpose());
    t.lower.row(k) = lo_.transpose();
    t.upper.row(k) = hi_.transpose();
    t.sets.push_back(current_);
    t.checks.push_back(check_);
  }
  return t;
}

SETBOUND_INLINE StateFingerprint ConstrainedZonotopicEstimator::fingerprint() const {
  StateFingerprint f;
  f.add(sys_.A()).add(sys_.B()).add(sys_.C()).add(sys_.D()).add(sys_.E()).add(sys_.F());
  f.add_int(static_cast<int>(opt_.correction)).add_int(static_cast<int>(opt_.reduction));
  f.add_int(static_cast<int>(opt_.technique)).add(opt_.order);
  f.add_int(opt_.max_constraints).add_int(opt_.max_generators).add_int(opt_.use_first_measurement ? 1 : 0);
  return f;
}

namespace czn_detail {

SETBOUND_INLINE void write_set(StateWriter& w, const ConstrainedZonotope& Z) {
  w.vec(Z.center()).mat(Z.generators()).mat(Z.constraint_matrix()).vec(Z.constraint_vector()).vec(Z.rounding_radius());
}

/// A saved set of dimension n: the counts are read from the blob (the reader checks that the
/// blob carries that many entries), the parts validated by ConstrainedZonotope::from_parts.
SETBOUND_INLINE ConstrainedZonotope read_set(StateReader& r, Eigen::Index n, const std::string& name) {
  Eigen::VectorXd c = r.vec(n, (name + " centre").c_str());
  Eigen::MatrixXd G = r.mat(n, -1, (name + " generators").c_str());
  Eigen::MatrixXd A = r.mat(-1, G.cols(), (name + " constraints").c_str());
  Eigen::VectorXd b = r.vec(A.rows(), (name + " constraint vector").c_str());
  Eigen::VectorXd rr = r.vec(n, (name + " rounding radius").c_str());
  try {
    return ConstrainedZonotope::from_parts(std::move(c), std::move(G), std::move(A), std::move(b), std::move(rr));
  } catch (const Error& e) {
    r.fail(name + ": " + e.what());
  }
}

}  // namespace czn_detail

SETBOUND_INLINE std::vector<double> ConstrainedZonotopicEstimator::save_state() const {
  StateWriter w(StateKind::ConstrainedZonotopicEstimator, fingerprint());
  w.count(k_).flag(has_current_);
  czn_detail::write_set(w, prior_);
  czn_detail::write_set(w, current_);
  w.vec(lo_).vec(hi_);
  // The last screening: statuses, then margins with a presence flag each (a margin may be NaN,
  // and saved entries must be finite).
  const Eigen::Index ny = static_cast<Eigen::Index>(check_.status.size());
  w.count(ny);
  for (Eigen::Index i = 0; i < ny; ++i) {
    const double m = check_.margin(i);
    w.count(static_cast<int>(check_.status[static_cast<std::size_t>(i)])).flag(!std::isnan(m)).scalar(std::isnan(m) ? 0.0 : m);
  }
  w.flag(check_.reset);
  return w.finish();
}

SETBOUND_INLINE void ConstrainedZonotopicEstimator::restore_state(const std::vector<double>& state) {
  struct Parsed {
    long long k = 0;
    bool has_cur = false;
    ConstrainedZonotope prior, current;
    Eigen::VectorXd lo, hi;
    MeasurementCheck check;
  };
  const Eigen::Index n = sys_.nx(), ny = sys_.ny();
  Parsed q = guard_state_memory(StateKind::ConstrainedZonotopicEstimator, [&] {
    StateReader r(state, StateKind::ConstrainedZonotopicEstimator, fingerprint());
    Parsed t{0, false, x0_, x0_, {}, {}, {}};
    t.k = r.count("steps");
    t.has_cur = r.flag("has_current");
    t.prior = czn_detail::read_set(r, n, "prior");
    t.current = czn_detail::read_set(r, n, "current set");
    const Eigen::Index nh = t.has_cur ? n : 0;
    t.lo = r.vec(nh, "lower bounds");
    t.hi = r.vec(nh, "upper bounds");
    const long long nys = r.count("outputs", ny, ny);
    t.check.clear(ny);
    for (long long i = 0; i < nys; ++i) {
      t.check.status[static_cast<std::size_t>(i)] = static_cast<OutputStatus>(r.count("output status", 0, 3));
      const bool has_margin = r.flag("margin present");
      const double m = r.scalar("margin");
      t.check.margin(static_cast<Eigen::Index>(i)) = has_margin ? m : std::numeric_limits<double>::quiet_NaN();
    }
    t.check.reset = r.flag("reset");
    r.finish();
    if (t.has_cur != (t.k > 0)) r.fail("has_current must be set exactly when a step was taken");
    return t;
  });
  // Commit (moves and swaps only).
  k_ = static_cast<Eigen::Index>(q.k);
  has_current_ = q.has_cur;
  prior_ = std::move(q.prior);
  current_ = std::move(q.current);
  lo_.swap(q.lo);
  hi_.swap(q.hi);
  check_ = std::move(q.check);
}

}  // namespace setbound
