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

/// The certified total of qᵀw + ‖Mᵀw‖₁ from its computed parts: t = fl(qᵀw), tb = fl(|q|ᵀ|w|),
/// R = fl(Σ_j |(Mᵀw)_j|), Aa = fl(Σ_j (|M|ᵀ|w|)_j), for a k×m matrix M.
SETBOUND_INLINE double certified_total(double t, double tb, double R, double Aa, Eigen::Index k, Eigen::Index m) {
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

SETBOUND_INLINE double upper_bound_q_plus_l1(const Eigen::Ref<const Eigen::MatrixXd>& M,
                                            const Eigen::Ref<const Eigen::VectorXd>& q,
                                            const Eigen::Ref<const Eigen::VectorXd>& w) {
  // Computed values and the sums of the absolute terms that bound their errors.
  const Eigen::VectorXd r = M.transpose() * w;                          // Mᵀw
  const Eigen::VectorXd a = M.cwiseAbs().transpose() * w.cwiseAbs();    // |M|ᵀ|w|
  return certified_total(q.dot(w), q.cwiseAbs().dot(w.cwiseAbs()), r.cwiseAbs().sum(), a.sum(), M.rows(), M.cols());
}

/// A pivot on T (row-major, rows × cols) at row p: row p divided by the pivot t_p, then
/// T_i −= t_i T_p for every other row with t_i ≠ 0 (t: the pivot column before the pivot, not
/// part of T). A quarter of a CZN step on vehicle6 is this loop: on CPUs with AVX2 it runs on
/// 4-wide vectors (SETBOUND_AVX2_CLONES: the same operations, quotient, product then difference,
/// so the same bits as the baseline's 2-wide ones).
SETBOUND_INLINE SETBOUND_AVX2_CLONES void pivot_tableau(double* T, Eigen::Index rows, Eigen::Index cols, Eigen::Index p,
                                                       const double* t) {
  double* __restrict tp = T + p * cols;
  const double piv = t[p];
  for (Eigen::Index j = 0; j < cols; ++j) tp[j] /= piv;
  for (Eigen::Index i = 0; i < rows; ++i) {
    if (i == p || t[i] == 0.0) continue;
    double* __restrict ti = T + i * cols;
    const double f = t[i];
    for (Eigen::Index j = 0; j < cols; ++j) ti[j] -= f * tp[j];
  }
}

/// The dual ratio test's pass over a row of T (the row of the leaving variable): w_j = σ s_j t_j
/// (s_j the state of column j: −1/+1 at a bound, 0 basic) and the ratio |d_j| / w_j, for every
/// column; the candidates are the j with w_j above the pivot tolerance. Separate from the test
/// on w so that the divisions run on vectors and the selection needs no branch per column.
SETBOUND_INLINE SETBOUND_AVX2_CLONES void dual_ratios(const double* t, const signed char* state, const double* d,
                                                     double sigma, Eigen::Index m, double* w, double* ratio) {
  for (Eigen::Index j = 0; j < m; ++j) {
    w[j] = sigma * static_cast<double>(state[j]) * t[j];
    ratio[j] = std::abs(d[j]) / w[j];  // inf or NaN where w_j = 0: never a candidate
  }
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
  scale_rows();
}

SETBOUND_INLINE void BoxLP::scale_rows() {
  const Eigen::Index r = A_.rows();
  row_scale_ = Eigen::VectorXd::Ones(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    const double mx = box_lp_detail::max_abs(A_.row(i));
    if (mx > 0.0) row_scale_(i) = 1.0 / mx;
  }
  As_ = row_scale_.asDiagonal() * A_;
  bs_ = row_scale_.cwiseProduct(b_);
  absA_ = A_.cwiseAbs();
}

SETBOUND_INLINE double BoxLP::dual_bound(const Eigen::Ref<const Eigen::VectorXd>& g, const Eigen::VectorXd& mu) const {
  // upper_bound_q_plus_l1 with M = [gᵀ; A], q = [0; −b], w = [1; −μ] (μᵀb + ‖g − Aᵀμ‖₁), its
  // parts computed from A and the cached |A| instead of a stacked copy.
  const Eigen::Index r = A_.rows(), m = A_.cols();
  if (r == 0) return box_lp_detail::certified_total(0.0, 0.0, g.cwiseAbs().sum(), g.cwiseAbs().sum(), 1, m);
  const Eigen::VectorXd res = g - A_.transpose() * mu;
  const Eigen::VectorXd a = g.cwiseAbs() + absA_.transpose() * mu.cwiseAbs();
  return box_lp_detail::certified_total(b_.dot(mu), b_.cwiseAbs().dot(mu.cwiseAbs()), res.cwiseAbs().sum(), a.sum(),
                                        r + 1, m);
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

SETBOUND_INLINE Eigen::VectorXd BoxLP::duals(const Eigen::VectorXd& cost) const {
  const Eigen::Index r = A_.rows();
  if (r == 0) return Eigen::VectorXd();
  // Bᵀ μ_s = c_B in the scaled rows; μ = D μ_s in the original ones (μ_sᵀ D A = (D μ_s)ᵀ A).
  // T's artificial columns are B⁻¹S (S = diag(s), s_i = ±1), so B⁻¹ = T_art S and
  // μ_s = S T_artᵀ c_B: no factorisation per query. T is refreshed every kRefactorEvery pivots;
  // a μ spoilt by drift would only loosen the bound, which duality certifies whatever μ is.
  const Eigen::VectorXd mu_s = art_sign_.cwiseProduct(T_.rightCols(r).transpose() * basic_costs(cost));
  return row_scale_.cwiseProduct(mu_s);
}

SETBOUND_INLINE bool BoxLP::run_simplex(const Eigen::VectorXd& cost, long max_pivots) {
  const Eigen::Index r = A_.rows(), m = A_.cols();
  const bool phase1 = !phase1_done_;
  Eigen::VectorXd d = reduced_costs(cost);
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
    col_ = T_.col(enter);
    const Eigen::VectorXd& t = col_;
    const double tmax = box_lp_detail::max_abs(t);
    double theta = 2.0;  // the entering variable's own range (bound flip)
    Eigen::Index row = -1;
    for (Eigen::Index i = 0; i < r; ++i) {
      if (std::abs(t(i)) <= box_lp_detail::kPivotTol * tmax) continue;
      const double rate = -delta * t(i);  // d x_basic(i) / d theta
      const int k = basis_[static_cast<size_t>(i)];
      const double lo = lower_of(k);
      const double hi = (phase1 && k >= m) ? rounding::kInf : upper_of(k);  // phase 1: artificials >= 0
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
    pivot(row, enter, cost, d);
  }
}

SETBOUND_INLINE Eigen::VectorXd BoxLP::basic_costs(const Eigen::VectorXd& cost) const {
  Eigen::VectorXd cB(A_.rows());
  for (Eigen::Index i = 0; i < cB.size(); ++i) cB(i) = cost(basis_[static_cast<size_t>(i)]);
  return cB;
}

SETBOUND_INLINE Eigen::VectorXd BoxLP::reduced_costs(const Eigen::VectorXd& cost) const {
  return cost - T_.transpose() * basic_costs(cost);
}

SETBOUND_INLINE void BoxLP::pivot(Eigen::Index row, int enter, const Eigen::VectorXd& cost, Eigen::VectorXd& d) {
  const Eigen::VectorXd& t = col_;  // T's column `enter` before the pivot
  // Rows are contiguous (T_ is row-major); col_ is a copy, not a view of T_.
  box_lp_detail::pivot_tableau(T_.data(), T_.rows(), T_.cols(), row, t.data());
  d -= d(enter) * T_.row(row).transpose();
  // A fresh factorisation every so often bounds the drift of the product-form updates; it costs
  // about 2r pivots, hence an interval of at least r.
  if (++since_refactor_ >= std::max<Eigen::Index>(box_lp_detail::kRefactorEvery, T_.rows())) {
    refactor();
    d = reduced_costs(cost);
  }
}

SETBOUND_INLINE bool BoxLP::run_dual_simplex(const Eigen::VectorXd& cost, long max_pivots) {
  const Eigen::Index r = A_.rows(), m = A_.cols();
  Eigen::VectorXd pc = cost;  // the perturbed costs (below)
  Eigen::VectorXd d = reduced_costs(pc);
  const double dscale = std::max(1.0, box_lp_detail::max_abs(cost));
  // Dual feasibility for free: each non-basic ξ_j at the bound its reduced cost prefers (the
  // artificials are fixed at 0 in phase 2). The basic values follow: β −= Δx_j T_j. Then the
  // costs of the non-basic columns are perturbed away from zero in the direction their bound
  // keeps dual feasible (the hull objectives have many zero entries — the noise and slack columns
  // — whose zero reduced costs make every dual step degenerate and the method stall); the
  // caller's primal simplex finishes with the true costs. The perturbation is a fixed function of
  // j, so runs stay bit-identical (computed once per column count: fmod cost ~4 % of a step).
  if (perturb_frac_.size() != m) {
    perturb_frac_.resize(m);
    for (Eigen::Index j = 0; j < m; ++j)
      perturb_frac_(j) = 0.5 + 0.5 * std::fmod(0.6180339887498949 * static_cast<double>(j + 1), 1.0);
  }
  for (Eigen::Index j = 0; j < m; ++j) {
    const signed char s = state_[static_cast<size_t>(j)];
    if (s == 0) continue;
    const signed char want = d(j) < 0.0 ? 1 : (d(j) > 0.0 ? -1 : s);
    if (want != s) {
      beta_ -= (2.0 * want) * T_.col(j);
      state_[static_cast<size_t>(j)] = want;
    }
    const double eps = (want < 0 ? 1.0 : -1.0) * box_lp_detail::kDualPerturbation * dscale * perturb_frac_(j);
    pc(j) += eps;  // a non-basic cost enters its own reduced cost only
    d(j) += eps;
  }
  long done = 0;
  while (true) {
    // Leaving: the basic variable furthest outside its bounds. A basic artificial whose row has
    // no structural entry belongs to a redundant row: its value is rounding noise, it stays.
    Eigen::Index row = -1;
    double worst = box_lp_detail::kFeasibilityTol;
    bool below = false;
    for (Eigen::Index i = 0; i < r; ++i) {
      const int k = basis_[static_cast<size_t>(i)];
      const double lo = lower_of(k), hi = upper_of(k);
      const double v = std::max(lo - beta_(i), beta_(i) - hi);
      if (v <= worst) continue;
      if (k >= m && box_lp_detail::max_abs(T_.row(i).head(m)) <= 1e-9) continue;
      worst = v;
      row = i;
      below = beta_(i) < lo;
    }
    if (row < 0) return true;  // primal feasible and dual feasible: optimal
    if (done >= max_pivots) return false;
    // Entering, by the bound-flipping ratio test (the "long-step" rule of the dual simplex for
    // boxed variables, Maros 2003 §10.4; Koberstein 2005 §3.3): the candidates are the non-basic
    // structural variables whose move from their bound pushes β_row towards its violated bound;
    // taken in order of the dual ratio |d_j| / |T_rj|, each one that the row's infeasibility can
    // absorb whole (it moves β_row by 2|T_rj| when it crosses its box) is flipped to its other
    // bound instead of entering, and the first one that cannot enters. Without this, the entering
    // variable often lands outside its own box and leaves again at the next pivot.
    const auto Trow = T_.row(row);
    const double rowmax = box_lp_detail::max_abs(Trow.head(m));
    // β_row changes by −a Δx_j; Δx_j > 0 from the lower bound (s = −1), < 0 from the upper one
    // (s = +1): column j helps when w = σ s a > 0 (σ = +1 below the box, −1 above), and w = |a|
    // then (basic columns, s = 0, never): one compare per column instead of a tree of branches.
    const double sigma = below ? 1.0 : -1.0, threshold = box_lp_detail::kPivotTol * rowmax;
    // Candidates in increasing j, as (ratio, j). The w_j > threshold test is as good as random
    // (about 40 % pass), so the indices are compacted without a branch.
    scan_w_.resize(m);
    scan_ratio_.resize(m);
    cand_index_.resize(static_cast<size_t>(m));
    box_lp_detail::dual_ratios(Trow.data(), state_.data(), d.data(), sigma, m, scan_w_.data(), scan_ratio_.data());
    std::size_t count = 0;
    for (Eigen::Index j = 0; j < m; ++j) {
      cand_index_[count] = static_cast<int>(j);
      count += scan_w_(j) > threshold ? 1 : 0;
    }
    cand_.resize(count);
    for (std::size_t c = 0; c < count; ++c) cand_[c] = {scan_ratio_(cand_index_[c]), cand_index_[c]};
    // The candidates are taken in increasing ratio (ties by index); usually only the first few
    // are looked at (vehicle6: ~8 of ~60 per pivot), and a full sort cost ~6 % of a step. The
    // first kLinearPops come from linear scans for the least one (predictable branches), the rest
    // from a min-heap (its sift-downs mispredict, but it does not rescan). Either way each popped
    // one lands at the back of cand_, so the i-th popped sits at cand_[size − 1 − i].
    constexpr int kLinearPops = 8;
    const auto later = [](const std::pair<double, int>& x, const std::pair<double, int>& y) { return x > y; };
    auto heap_end = cand_.end();
    int linear_pops = 0;
    const auto least_unpopped = [&] {
      auto best = cand_.begin();
      for (auto it = cand_.begin() + 1; it < heap_end; ++it)
        if (*it < *best) best = it;
      return best;
    };
    const auto pop = [&] {
      if (linear_pops <= kLinearPops && ++linear_pops > kLinearPops) std::make_heap(cand_.begin(), heap_end, later);
      if (linear_pops > kLinearPops) std::pop_heap(cand_.begin(), heap_end, later);
      else std::iter_swap(least_unpopped(), heap_end - 1);
      return *--heap_end;
    };
    const auto least = [&]() -> const std::pair<double, int>& {
      return linear_pops > kLinearPops ? cand_.front() : *least_unpopped();
    };
    int enter = -1;
    double slope = worst, ratio = 0.0;  // the row's remaining infeasibility; the entering ratio
    std::size_t flips = 0;  // the first `flips` popped candidates flip, the next one enters
    while (heap_end != cand_.begin()) {
      const auto c = pop();
      const double step = 2.0 * std::abs(Trow(c.second));
      if (heap_end != cand_.begin() && slope - step > box_lp_detail::kFeasibilityTol) {
        slope -= step;
        ++flips;
        continue;
      }
      enter = c.second;
      ratio = c.first;
      break;
    }
    // Among candidates whose ratio ties the entering one's, the largest pivot (stability).
    if (enter >= 0) {
      const double tol = box_lp_detail::kReducedCostTol * dscale;
      double piv = std::abs(Trow(enter));
      while (heap_end != cand_.begin() && least().first <= ratio + tol / piv) {
        const int l = pop().second;
        if (std::abs(Trow(l)) > piv) {
          enter = l;
          piv = std::abs(Trow(enter));
        }
      }
      for (std::size_t l = 0; l < flips; ++l) {
        const int f = cand_[cand_.size() - 1 - l].second;
        const signed char s = state_[static_cast<size_t>(f)];
        beta_ -= (-2.0 * s) * T_.col(f);  // Δx = −2 s
        state_[static_cast<size_t>(f)] = static_cast<signed char>(-s);
      }
    }
    if (enter < 0) return false;  // no column can repair the row: infeasible, or numerically stuck
    ++done;
    ++pivots_;
    const int leave = basis_[static_cast<size_t>(row)];
    const double bound = below ? lower_of(leave) : upper_of(leave);
    col_ = T_.col(enter);
    const double dx = (beta_(row) - bound) / col_(row);  // Δx_enter that puts β_row on its bound
    const double x_enter = (state_[static_cast<size_t>(enter)] > 0 ? 1.0 : -1.0) + dx;
    beta_ -= dx * col_;
    beta_(row) = x_enter;
    state_[static_cast<size_t>(leave)] = static_cast<signed char>(leave >= m ? -1 : (below ? -1 : 1));
    state_[static_cast<size_t>(enter)] = 0;
    basis_[static_cast<size_t>(row)] = enter;
    pivot(row, enter, pc, d);
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
  // The artificial basis B = S = diag(s) (s_i = ±1) is its own inverse: T = [S As | I] and
  // β = S res = |res| without a factorisation (which costs 2r²(m + r) flops: on tank30's LPs,
  // r ≈ 120, as much as a few hundred pivots).
  since_refactor_ = 0;
  T_.resize(r, m + r);
  T_.leftCols(m) = art_sign_.asDiagonal() * As_;
  T_.rightCols(r).setIdentity();
  beta_ = res.cwiseAbs();
  phase1_run();
}

SETBOUND_INLINE void BoxLP::phase1_run() {
  const Eigen::Index r = A_.rows(), m = A_.cols();
  warm_ = false;
  Eigen::VectorXd cost = Eigen::VectorXd::Zero(m + r);
  cost.tail(r).setOnes();
  const bool converged = run_simplex(cost, 50 * (m + r) + 1000);
  double infeasibility = 0.0;
  for (Eigen::Index i = 0; i < r; ++i)
    if (basis_[static_cast<size_t>(i)] >= m) infeasibility += std::abs(beta_(i));
  phase1_done_ = true;
  if (converged && infeasibility <= box_lp_detail::kFeasibilityTol * std::max(1.0, box_lp_detail::max_abs(bs_))) {
    feasibility_ = Feasibility::feasible;
    // Drive the artificials out of the basis where a structural column can replace them; the
    // rest belong to redundant rows and stay basic, fixed at 0 from now on. A fresh factorisation
    // only when the basis changed here.
    bool swapped = false;
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
      swapped = true;
    }
    if (swapped) refactor();
    return;
  }
  // Phase 1 ended above zero: its dual is the candidate certificate (at the optimum
  // w = yᵀb − ‖Aᵀy‖₁, see the header). It is believed only if the certified margin is positive.
  refactor();
  const Eigen::VectorXd y = duals(cost);
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
  if (!phase1_done_) {
    if (warm_) phase1_run();
    else phase1();
  }
  return feasibility_;
}

SETBOUND_INLINE void BoxLP::extend(Eigen::MatrixXd A_new, Eigen::VectorXd b_new) {
  const Eigen::Index r0 = A_.rows(), m0 = A_.cols();
  require_finite(A_new, "A");
  if (A_new.rows() < r0 || A_new.cols() < m0)
    throw DimensionError("A: expected at least the " + detail::shape_string(r0, m0) + " of the LP it extends, got " +
                         detail::shape_string(A_new.rows(), A_new.cols()));
  if (b_new.size() != A_new.rows())
    throw DimensionError("b: expected length " + std::to_string(A_new.rows()) + " (the rows of A), got " +
                         std::to_string(b_new.size()));
  require_finite(b_new, "b");
  const Eigen::Index r = A_new.rows(), m = A_new.cols();
  if (A_new.topLeftCorner(r0, m0) != A_ || b_new.head(r0) != b_ ||
      (r0 > 0 && m > m0 && box_lp_detail::max_abs(A_new.topRightCorner(r0, m - m0)) > 0.0))
    throw InvalidArgumentError("A: the rows of the LP it extends must stay unchanged and zero in the new columns");
  const bool keep = phase1_done_ && feasibility_ == Feasibility::feasible;
  Eigen::VectorXd x = Eigen::VectorXd::Constant(m, -1.0);  // the current point, new columns at −1
  std::vector<signed char> old_state;
  std::vector<int> old_basis;
  Eigen::VectorXd old_sign, old_beta;
  decltype(T_) old_T;
  if (keep) {
    for (Eigen::Index j = 0; j < m0; ++j) x(j) = state_[static_cast<size_t>(j)] > 0 ? 1.0 : -1.0;
    for (Eigen::Index i = 0; i < r0; ++i)
      if (basis_[static_cast<size_t>(i)] < m0) x(basis_[static_cast<size_t>(i)]) = beta_(i);
    old_state = std::move(state_);
    old_basis = std::move(basis_);
    old_sign = std::move(art_sign_);
    old_T = std::move(T_);
    old_beta = std::move(beta_);
  }
  A_ = std::move(A_new);
  b_ = std::move(b_new);
  scale_rows();
  certificate_.resize(0);
  certificate_margin_ = 0.0;
  feasibility_ = Feasibility::inconclusive;
  phase1_done_ = false;
  warm_ = false;
  if (!keep) return;  // the next query runs phase 1 from the start
  // Old variables keep their state (artificial i moves from m0 + i to m + i); new columns sit at
  // −1; each new row gets a basic artificial that absorbs its residual. B = [B0 0; * S_new] is
  // block triangular, hence regular.
  state_.assign(static_cast<size_t>(m + r), -1);
  for (Eigen::Index j = 0; j < m0; ++j) state_[static_cast<size_t>(j)] = old_state[static_cast<size_t>(j)];
  for (Eigen::Index i = 0; i < r0; ++i) state_[static_cast<size_t>(m + i)] = old_state[static_cast<size_t>(m0 + i)];
  basis_.resize(static_cast<size_t>(r));
  art_sign_.resize(r);
  for (Eigen::Index i = 0; i < r0; ++i) {
    const int v = old_basis[static_cast<size_t>(i)];
    basis_[static_cast<size_t>(i)] = v < m0 ? v : static_cast<int>(v - m0 + m);
    art_sign_(i) = old_sign(i);
  }
  const Eigen::Index p = r - r0;
  Eigen::VectorXd res(p);
  for (Eigen::Index i = r0; i < r; ++i) {
    res(i - r0) = bs_(i) - As_.row(i).dot(x);
    art_sign_(i) = res(i - r0) < 0.0 ? -1.0 : 1.0;
    basis_[static_cast<size_t>(i)] = static_cast<int>(m + i);
    state_[static_cast<size_t>(m + i)] = 0;
  }
  // The new tableau from the old one instead of a factorisation (2r²(m + r) flops):
  // B⁻¹ = [B0⁻¹ 0; −S_n R B0⁻¹ S_n] with R the new rows' entries in the old basic columns, so
  // T = [T0 (old columns in place, zero in the new ones); S_n ([A_r A_c 0 S_n] − R [T0 0])].
  // β keeps the old basic values and the new artificials take |residual| (as in phase 1).
  T_.setZero(r, m + r);
  T_.topLeftCorner(r0, m0) = old_T.leftCols(m0);
  T_.block(0, m, r0, r0) = old_T.rightCols(r0);
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(p, r0);
  for (Eigen::Index i = 0; i < r0; ++i) {
    const int v = basis_[static_cast<size_t>(i)];
    if (v < m) R.col(i) = As_.col(v).tail(p);
  }
  auto bottom = T_.bottomRows(p);
  bottom.leftCols(m) = As_.bottomRows(p);
  bottom.leftCols(m0).noalias() -= R * old_T.leftCols(m0);
  bottom.block(0, m, p, r0).noalias() -= R * old_T.rightCols(r0);
  bottom = art_sign_.tail(p).asDiagonal() * bottom;
  bottom.rightCols(p).setIdentity();  // S_n S_n
  beta_.resize(r);
  beta_.head(r0) = old_beta;
  beta_.tail(p) = res.cwiseAbs();
  warm_ = true;
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
  // The dual simplex first: the previous optimum is primal feasible but, for a new objective,
  // usually far from optimal — most of its non-basic variables belong at their other bound, which
  // the primal simplex reaches one bound flip (a pass over every column) at a time, the dual
  // simplex in one sweep (measured: ~80 % of the primal iterations were flips). Should it stop
  // (iteration limit, or a row it cannot repair through rounding), the primal simplex takes over
  // from the saved feasible basis.
  saved_basis_ = basis_;  // member buffers: no allocation per query once they have grown
  saved_state_ = state_;
  bool optimal = run_dual_simplex(cost, 10 * (m + r) + 100);
  if (!optimal) {
    basis_ = saved_basis_;
    state_ = saved_state_;
    refactor();
  }
  // The primal simplex finishes (or, after a fallback, does) the job with the true costs: the
  // dual simplex ran on perturbed ones and its Harris-style ties may leave reduced costs a hair
  // on the wrong side. From its primal-feasible basis this is usually a few pivots or none.
  const long primal_limit = 50 * (m + r) + 1000;
  optimal = run_simplex(cost, primal_limit);
  Eigen::VectorXd mu = -duals(cost);  // dual of the maximisation
  double value = dual_bound(g, mu);  // μᵀb + ‖g − Aᵀμ‖₁, certified
  Eigen::VectorXd xi = point();
  // The tableau is updated in product form between factorisations; on a nearly degenerate set
  // (a consistent set shrunk to almost a point) its drift can leave the simplex "optimal" on a
  // basis whose multipliers certify a loose bound (seen: 0.02 where the maximum is −0.32). A gap
  // between the certified bound and the simplex's own value is that symptom: factorise afresh,
  // let the primal simplex repair the basis, and keep the better certified bound.
  const double scale = 1.0 + box_lp_detail::max_abs(g);
  if (optimal && since_refactor_ > 0 && value - g.dot(xi) > 1e-7 * scale) {
    refactor();
    optimal = run_simplex(cost, primal_limit);
    const Eigen::VectorXd mu2 = -duals(cost);
    const double value2 = dual_bound(g, mu2);
    if (value2 < value) {
      value = value2;
      mu = mu2;
    }
    xi = point();
  }
  Eigen::VectorXd mu_used = mu;
  const double plain = box_lp_detail::l1_upper(g);
  if (!(value <= plain)) {  // a poor dual (or NaN from a breakdown): μ = 0 is valid and better
    value = plain;
    mu_used.setZero();
  }
  return {value, g.dot(xi), mu_used, xi, optimal};
}

SETBOUND_INLINE Eigen::VectorXd BoxLP::point() const {
  // Not certified: β as updated by the pivots, refreshed every kRefactorEvery of them.
  const Eigen::Index r = A_.rows(), m = A_.cols();
  Eigen::VectorXd xi(m);
  for (Eigen::Index j = 0; j < m; ++j) xi(j) = state_[static_cast<size_t>(j)] > 0 ? 1.0 : -1.0;
  for (Eigen::Index i = 0; i < r; ++i)
    if (basis_[static_cast<size_t>(i)] < m) xi(basis_[static_cast<size_t>(i)]) = beta_(i);
  return xi;
}

}  // namespace setbound
