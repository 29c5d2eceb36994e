// setbound — [Alamo2005] volume minimisation (papers.md §5.2): the strip gain λ that minimises
// the exact volume of p̂(λ) ⊕ Ĥ(λ) B^(m+1), as a linear program on the bundled solver.
//
//   vol(λ)/2^n = |1 − cᵀλ| Σ_{|S|=n} |det H_S| + φ Σ_{|T|=n−1} |w_Tᵀλ|
//
// (det((I − λcᵀ)H_S) = (1 − cᵀλ) det H_S; a subset with the new column φλ gives
// φ det[H_T, λ] = φ w_Tᵀλ, w_T the cofactor vector of H_T, orthogonal to its columns with
// norm the (n−1)-volume they span.) Convex piecewise linear in λ, hence the LP
//   min a r + φ Σ_T s_T   s.t.  r ≥ ±(1 − cᵀλ),  s_T ≥ ±w_Tᵀλ.
// Any λ is guaranteed; if the LP cannot be solved to optimality the segment-minimising λ
// is used instead (documented fallback, still guaranteed).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/estimators/zonotopic.hpp"
#include "setbound/lmi/lp.hpp"
#include "setbound/sets/zonotope.hpp"

namespace setbound {

/// Largest number of (n−1)-subsets the LP accepts (its dense Schur complement grows with it).
inline constexpr double kVolumeMinMaxSubsets = 2000;

namespace detail {
/// Cofactor vector of the n×(n−1) matrix M: w_i = (−1)^i det(M without row i).
inline Eigen::VectorXd cofactor_vector(const Eigen::MatrixXd& M) {
  const Eigen::Index n = M.rows();
  Eigen::VectorXd w(n);
  if (n == 1) {
    w(0) = 1.0;
    return w;
  }
  Eigen::MatrixXd minor(n - 1, n - 1);
  for (Eigen::Index i = 0; i < n; ++i) {
    minor.topRows(i) = M.topRows(i);
    minor.bottomRows(n - 1 - i) = M.bottomRows(n - 1 - i);
    w(i) = ((i % 2) ? -1.0 : 1.0) * minor.determinant();
  }
  return w;
}
}  // namespace detail

/// The volume-minimising λ for one strip (papers.md §5.2).
inline Eigen::VectorXd volume_min_gain(const Zonotope& Z, const StripMeasurement& meas) {
  const Eigen::Index n = Z.dimension(), m = Z.num_generators();
  const Eigen::MatrixXd& H = Z.generators();
  const Eigen::VectorXd& c = meas.strip.normal();
  const double phi = meas.strip.half_width();
  if (detail::binomial(m, n - 1) > kVolumeMinMaxSubsets)
    throw InvalidArgumentError("volume_min_gain: C(" + std::to_string(m) + ", " + std::to_string(n - 1) +
                               ") generator subsets exceed the LP limit of " +
                               std::to_string(static_cast<long>(kVolumeMinMaxSubsets)) +
                               "; reduce the zonotope order or use segment minimisation");
  double a = 0.0;
  if (m >= n) {
    Eigen::MatrixXd HS(n, n);
    detail::for_each_subset(m, n, [&](const std::vector<Eigen::Index>& idx) {
      for (Eigen::Index j = 0; j < n; ++j) HS.col(j) = H.col(idx[static_cast<std::size_t>(j)]);
      a += std::abs(HS.determinant());
    });
  }
  std::vector<Eigen::VectorXd> w;
  {
    Eigen::MatrixXd HT(n, n - 1);
    detail::for_each_subset(m, n - 1, [&](const std::vector<Eigen::Index>& idx) {
      for (Eigen::Index j = 0; j + 1 < n; ++j) HT.col(j) = H.col(idx[static_cast<std::size_t>(j)]);
      Eigen::VectorXd wt = detail::cofactor_vector(HT);
      if (wt.cwiseAbs().maxCoeff() > 0) w.push_back(std::move(wt));
    });
  }
  if (w.empty() || phi == 0.0) return segment_min_gain(Z, meas);
  // Variables: λ (0..n−1), r (n), s_T (n+1 …). Scale the objective to order one.
  const int N = static_cast<int>(n) + 1 + static_cast<int>(w.size());
  double scale = a;
  for (const auto& wt : w) scale = std::max(scale, phi * wt.cwiseAbs().sum());
  if (!(scale > 0)) return segment_min_gain(Z, meas);
  lmi::LinearProgram lp(N);
  Eigen::VectorXd obj = Eigen::VectorXd::Zero(N);
  obj(n) = a / scale;
  const int r = static_cast<int>(n);
  for (std::size_t t = 0; t < w.size(); ++t) obj(r + 1 + static_cast<int>(t)) = phi / scale;
  lp.set_objective(obj);
  // r ≥ 1 − cᵀλ  ⇔  −r − cᵀλ ≤ −1 ;  r ≥ cᵀλ − 1  ⇔  −r + cᵀλ ≤ 1
  lmi::LpRow lo{{r, -1.0}}, hi{{r, -1.0}};
  for (Eigen::Index i = 0; i < n; ++i) lo.emplace_back(static_cast<int>(i), -c(i)), hi.emplace_back(static_cast<int>(i), c(i));
  lp.add_le(lo, -1.0);
  lp.add_le(hi, 1.0);
  for (std::size_t t = 0; t < w.size(); ++t) {
    const int s = r + 1 + static_cast<int>(t);
    lmi::LpRow p{{s, -1.0}}, q{{s, -1.0}};
    for (Eigen::Index i = 0; i < n; ++i) {
      if (w[t](i) == 0.0) continue;
      p.emplace_back(static_cast<int>(i), w[t](i));
      q.emplace_back(static_cast<int>(i), -w[t](i));
    }
    lp.add_le(p, 0.0);
    lp.add_le(q, 0.0);
  }
  const lmi::SolveResult res = lp.solve();
  if (res.status != lmi::SolveStatus::Optimal && res.status != lmi::SolveStatus::Inaccurate)
    return segment_min_gain(Z, meas);
  Eigen::VectorXd lambda = res.x.head(n);
  if (!lambda.allFinite()) return segment_min_gain(Z, meas);
  return lambda;
}

}  // namespace setbound
