// setbound — definitions of the functions declared in setbound/sets/box_lp.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "setbound/core/config.hpp"
#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/box_lp.hpp"
#include "setbound/sets/interval.hpp"

namespace setbound {

namespace box_lp_detail {

/// γ_k = k u / (1 − k u), u = 2⁻⁵³ (Higham's constant for k rounded operations).
SETBOUND_INLINE double gamma_k(Eigen::Index k) {
  const double ku = static_cast<double>(k) * std::ldexp(1.0, -53);
  return rounding::div_up(ku, rounding::sub_down(1.0, ku));
}

SETBOUND_INLINE double upper_bound_q_plus_l1(const Eigen::Ref<const Eigen::MatrixXd>& M,
                                            const Eigen::Ref<const Eigen::VectorXd>& q,
                                            const Eigen::Ref<const Eigen::VectorXd>& w) {
  const Eigen::Index k = M.rows(), m = M.cols();
  // Computed values and the sums of the absolute terms that bound their errors.
  const Eigen::VectorXd r = M.transpose() * w;                          // Mᵀw
  const Eigen::VectorXd a = M.cwiseAbs().transpose() * w.cwiseAbs();    // |M|ᵀ|w|
  const double t = q.dot(w);
  const double tb = q.cwiseAbs().dot(w.cwiseAbs());
  const double R = r.cwiseAbs().sum();
  const double Aa = a.sum();
  if (!std::isfinite(t) || !std::isfinite(R) || !std::isfinite(Aa) || !std::isfinite(tb))
    return rounding::kInf;
  // One constant for every inner product and sum here (none has more than k + m + 4 terms).
  // Exact Σ|r_j| <= Σ|r̂_j| + γ Σ a_j, exact a_j <= â_j / (1 − γ), exact qᵀw <= t̂ + γ |q|ᵀ|w|
  // (the latter again computed with relative error γ), and a sum of m non-negative computed
  // terms is below its computed value times (1 + γ). The factor 2 on the error terms covers the
  // (1 + γ)/(1 − γ) products of these second-order corrections (γ <= 1e-12 for any size used).
  const double g = gamma_k(k + m + 4);
  const double one_plus = rounding::add_up(1.0, g);
  const double err = rounding::mul_up(rounding::mul_up(2.0, g), rounding::add_up(Aa, tb));
  double total = rounding::add_up(t, rounding::mul_up(R, one_plus));
  total = rounding::add_up(total, rounding::mul_up(err, one_plus));
  // Products that underflow are rounded absolutely (at most half the smallest subnormal each).
  const double underflow = std::numeric_limits<double>::denorm_min() * static_cast<double>(k * m + k + m + 4);
  return rounding::add_up(total, underflow);
}

/// ‖g‖₁ rounded upward (the bound with μ = 0).
SETBOUND_INLINE double l1_upper(const Eigen::Ref<const Eigen::VectorXd>& g) {
  const double s = g.cwiseAbs().sum();
  if (!std::isfinite(s)) return rounding::kInf;
  return rounding::mul_up(s, rounding::add_up(1.0, gamma_k(g.size() + 1)));
}

}  // namespace box_lp_detail


SETBOUND_INLINE BoxLP::BoxLP(Eigen::MatrixXd A, Eigen::VectorXd b) : A_(std::move(A)), b_(std::move(b)) {
  require_finite(A_, "A");
  if (b_.size() != A_.rows())
    throw DimensionError("b: expected length " + std::to_string(A_.rows()) + " (the rows of A), got " +
                         std::to_string(b_.size()));
  require_finite(b_, "b");
  const Eigen::Index r = A_.rows();
  row_scale_ = Eigen::VectorXd::Ones(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    const double mx = box_lp_detail::max_abs(A_.row(i));
    if (mx > 0.0) row_scale_(i) = 1.0 / mx;
  }
  As_ = row_scale_.asDiagonal() * A_;
  bs_ = row_scale_.cwiseProduct(b_);
}

SETBOUND_INLINE double BoxLP::value_of(int var) const {
  const int m = static_cast<int>(A_.cols());
  if (state_[static_cast<size_t>(var)] == 0) {
    for (size_t i = 0; i < basis_.size(); ++i)
      if (basis_[i] == var) return beta_(static_cast<Eigen::Index>(i));
  }
  if (var >= m) return 0.0;  // a non-basic artificial sits at 0
  return state_[static_cast<size_t>(var)] > 0 ? 1.0 : -1.0;
}

SETBOUND_INLINE void BoxLP::refactor() {
  const Eigen::Index r = A_.rows(), m = A_.cols();
  since_refactor_ = 0;
  if (r == 0) {
    T_.resize(0, m);
    beta_.resize(0);
    return;
  }
  Eigen::MatrixXd full(r, m + r);
  full.leftCols(m) = As_;
  full.rightCols(r) = art_sign_.asDiagonal();
  Eigen::MatrixXd B(r, r);
  for (Eigen::Index i = 0; i < r; ++i) B.col(i) = full.col(basis_[static_cast<size_t>(i)]);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(B);
  T_ = lu.solve(full);
  Eigen::VectorXd rhs = bs_;
  for (Eigen::Index j = 0; j < m; ++j)
    if (state_[static_cast<size_t>(j)] != 0) rhs -= As_.col(j) * (state_[static_cast<size_t>(j)] > 0 ? 1.0 : -1.0);
  beta_ = lu.solve(rhs);
}

SETBOUND_INLINE Eigen::VectorXd BoxLP::duals(const Eigen::VectorXd& cost_basic) const {
  const Eigen::Index r = A_.rows(), m = A_.cols();
  if (r == 0) return Eigen::VectorXd();
  Eigen::MatrixXd B(r, r);
  for (Eigen::Index i = 0; i < r; ++i) {
    const int v = basis_[static_cast<size_t>(i)];
    if (v < m) B.col(i) = As_.col(v);
    else {
      B.col(i).setZero();
      B(v - m, i) = art_sign_(v - m);
    }
  }
  // Bᵀ μ_s = c_B in the scaled rows; μ = D μ_s in the original ones (μ_sᵀ D A = (D μ_s)ᵀ A).
  const Eigen::VectorXd mu_s = B.transpose().partialPivLu().solve(cost_basic);
  return row_scale_.cwiseProduct(mu_s);
}

SETBOUND_INLINE bool BoxLP::run_simplex(const Eigen::VectorXd& cost, long max_pivots) {
  const Eigen::Index r = A_.rows(), m = A_.cols();
  const bool phase1 = !phase1_done_;
  auto cost_basic = [&] {
    Eigen::VectorXd cB(r);
    for (Eigen::Index i = 0; i < r; ++i) cB(i) = cost(basis_[static_cast<size_t>(i)]);
    return cB;
  };
  Eigen::VectorXd d = cost - T_.transpose() * cost_basic();
  const double dscale = std::max(1.0, box_lp_detail::max_abs(cost));
  long done = 0;
  int degenerate = 0;
  while (true) {
    // Pricing: Dantzig's largest violation; after many degenerate pivots, Bland's first index
    // (which cannot cycle).
    const bool bland = degenerate > 50;
    int enter = -1;
    double best = box_lp_detail::kReducedCostTol * dscale;
    for (Eigen::Index j = 0; j < m; ++j) {  // artificials never (re-)enter
      const signed char s = state_[static_cast<size_t>(j)];
      if (s == 0) continue;
      const double viol = (s < 0) ? -d(j) : d(j);
      if (viol > best) {
        enter = static_cast<int>(j);
        if (bland) break;
        best = viol;
      }
    }
    if (enter < 0) return true;
    if (done >= max_pivots) return false;
    const double delta = state_[static_cast<size_t>(enter)] < 0 ? 1.0 : -1.0;  // direction of x_enter
    const Eigen::VectorXd t = T_.col(enter);
    const double tmax = box_lp_detail::max_abs(t);
    double theta = 2.0;  // the entering variable's own range (bound flip)
    Eigen::Index row = -1;
    for (Eigen::Index i = 0; i < r; ++i) {
      if (std::abs(t(i)) <= box_lp_detail::kPivotTol * tmax) continue;
      const double rate = -delta * t(i);  // d x_basic(i) / d theta
      const int k = basis_[static_cast<size_t>(i)];
      const double lo = k < m ? -1.0 : 0.0;
      const double hi = k < m ? 1.0 : (phase1 ? rounding::kInf : 0.0);
      double lim;
      if (rate < 0.0) lim = (beta_(i) - lo) / -rate;
      else if (std::isfinite(hi)) lim = (hi - beta_(i)) / rate;
      else continue;
      lim = std::max(lim, 0.0);
      if (lim < theta - 1e-12 || (row >= 0 && lim <= theta + 1e-12 && std::abs(t(i)) > std::abs(t(row)))) {
        theta = lim;
        row = i;
      }
    }
    ++done;
    ++pivots_;
    degenerate = theta <= 1e-12 ? degenerate + 1 : 0;
    if (row < 0) {  // bound flip: no basis change
      beta_ -= (delta * theta) * t;
      state_[static_cast<size_t>(enter)] = static_cast<signed char>(-state_[static_cast<size_t>(enter)]);
      continue;
    }
    const int leave = basis_[static_cast<size_t>(row)];
    const double enter_value = (delta > 0 ? -1.0 + theta : 1.0 - theta);
    const bool leave_at_lower = (-delta * t(row)) < 0.0;
    beta_ -= (delta * theta) * t;
    beta_(row) = enter_value;
    state_[static_cast<size_t>(leave)] = static_cast<signed char>(leave_at_lower ? -1 : 1);
    if (leave >= m) state_[static_cast<size_t>(leave)] = -1;  // artificials leave at 0
    state_[static_cast<size_t>(enter)] = 0;
    basis_[static_cast<size_t>(row)] = enter;
    T_.row(row) /= t(row);
    for (Eigen::Index i = 0; i < r; ++i)
      if (i != row && t(i) != 0.0) T_.row(i) -= t(i) * T_.row(row);
    d -= d(enter) * T_.row(row).transpose();
    if (++since_refactor_ >= box_lp_detail::kRefactorEvery) {
      refactor();
      d = cost - T_.transpose() * cost_basic();
    }
  }
}

SETBOUND_INLINE void BoxLP::phase1() {
  phase1_done_ = false;
  const Eigen::Index r = A_.rows(), m = A_.cols();
  state_.assign(static_cast<size_t>(m + r), -1);
  basis_.resize(static_cast<size_t>(r));
  // Every ξ_j starts at its lower bound −1; artificial i absorbs the residual of row i.
  const Eigen::VectorXd res = bs_ + As_.rowwise().sum();
  art_sign_ = Eigen::VectorXd::Ones(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    if (res(i) < 0.0) art_sign_(i) = -1.0;
    basis_[static_cast<size_t>(i)] = static_cast<int>(m + i);
    state_[static_cast<size_t>(m + i)] = 0;
  }
  refactor();
  Eigen::VectorXd cost = Eigen::VectorXd::Zero(m + r);
  cost.tail(r).setOnes();
  const bool converged = run_simplex(cost, 50 * (m + r) + 1000);
  double infeasibility = 0.0;
  Eigen::VectorXd cB(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    const int v = basis_[static_cast<size_t>(i)];
    cB(i) = cost(v);
    if (v >= m) infeasibility += std::abs(beta_(i));
  }
  phase1_done_ = true;
  if (converged && infeasibility <= box_lp_detail::kFeasibilityTol * std::max(1.0, box_lp_detail::max_abs(bs_))) {
    feasibility_ = Feasibility::feasible;
    // Drive the artificials out of the basis where a structural column can replace them; the
    // rest belong to redundant rows and stay basic, fixed at 0 from now on.
    for (Eigen::Index i = 0; i < r; ++i) {
      if (basis_[static_cast<size_t>(i)] < m) continue;
      Eigen::Index best = -1;
      double bmax = 0.0;
      const double rowmax = box_lp_detail::max_abs(T_.row(i).head(m));
      for (Eigen::Index j = 0; j < m; ++j)
        if (state_[static_cast<size_t>(j)] != 0 && std::abs(T_(i, j)) > bmax) { bmax = std::abs(T_(i, j)); best = j; }
      if (best < 0 || bmax <= 1e-9 * std::max(1.0, rowmax)) continue;
      const int leave = basis_[static_cast<size_t>(i)];
      state_[static_cast<size_t>(leave)] = -1;
      state_[static_cast<size_t>(best)] = 0;
      basis_[static_cast<size_t>(i)] = static_cast<int>(best);
    }
    refactor();
    return;
  }
  // Phase 1 ended above zero: its dual is the candidate certificate (at the optimum
  // w = yᵀb − ‖Aᵀy‖₁, see the header). It is believed only if the certified margin is positive.
  const Eigen::VectorXd y = duals(cB);
  const double margin = -box_lp_detail::upper_bound_q_plus_l1(A_, -b_, y);
  if (y.size() && margin > 0.0) {
    feasibility_ = Feasibility::empty;
    certificate_ = y;
    certificate_margin_ = margin;
  } else {
    feasibility_ = Feasibility::inconclusive;
  }
}

SETBOUND_INLINE BoxLP::Feasibility BoxLP::feasibility() {
  if (!phase1_done_) phase1();
  return feasibility_;
}

SETBOUND_INLINE BoxLP::Bound BoxLP::maximize(const Eigen::Ref<const Eigen::VectorXd>& g) {
  const Eigen::Index r = A_.rows(), m = A_.cols();
  if (g.size() != m)
    throw DimensionError("g: expected length " + std::to_string(m) + " (the columns of A), got " +
                         std::to_string(g.size()));
  require_finite(g, "g");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  switch (feasibility()) {
    case Feasibility::empty:
      return {-rounding::kInf, nan, Eigen::VectorXd::Zero(r), Eigen::VectorXd(), true};
    case Feasibility::inconclusive:
      return {box_lp_detail::l1_upper(g), nan, Eigen::VectorXd::Zero(r), Eigen::VectorXd(), false};
    case Feasibility::feasible:
      break;
  }
  Eigen::VectorXd cost = Eigen::VectorXd::Zero(m + r);
  cost.head(m) = -g;  // the simplex minimises
  const bool optimal = run_simplex(cost, 50 * (m + r) + 1000);
  if (since_refactor_ > 0) refactor();  // fresh β for the reported point
  Eigen::VectorXd cB(r);
  for (Eigen::Index i = 0; i < r; ++i) cB(i) = cost(basis_[static_cast<size_t>(i)]);
  const Eigen::VectorXd mu = -duals(cB);  // dual of the maximisation
  Eigen::MatrixXd M(r + 1, m);
  M.row(0) = g.transpose();
  M.bottomRows(r) = A_;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(r + 1), w(r + 1);
  q.tail(r) = -b_;
  w(0) = 1.0;
  w.tail(r) = -mu;
  double value = box_lp_detail::upper_bound_q_plus_l1(M, q, w);  // μᵀb + ‖g − Aᵀμ‖₁
  Eigen::VectorXd mu_used = mu;
  const double plain = box_lp_detail::l1_upper(g);
  if (!(value <= plain)) {  // a poor dual (or NaN from a breakdown): μ = 0 is valid and better
    value = plain;
    mu_used.setZero();
  }
  Eigen::VectorXd xi(m);
  for (Eigen::Index j = 0; j < m; ++j) xi(j) = value_of(static_cast<int>(j));
  return {value, g.dot(xi), mu_used, xi, optimal};
}

}  // namespace setbound
