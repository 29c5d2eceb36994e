// setbound — order reduction of a zonotope's generator matrix, in place (papers.md §0.1).
//
// All three methods keep the generators that are costly to box and replace the others, H_R,
// by n generators W with W B^n ⊇ H_R B^{|R|} (⊕ an extra box B_r, see below):
//
//   Combastel ([Le2013] Property 3): keep the s − n longest columns (Euclidean norm), W the
//             diagonal rs(H_R) (the interval hull of H_R B).
//   Girard (2005): keep the s − n columns with the largest ‖g‖₁ − ‖g‖∞ (the cost of boxing a
//             generator; zero for an axis-aligned one), W = rs(H_R).
//   Pca (CORA's reduce 'pca', Althoff's priv_reducePCA): select as Girard, then box H_R in the
//             eigenbasis Q of H_R H_Rᵀ (its principal components): W = Q diag(rs(Qᵀ H_R)).
//
// "s − n kept" is CORA's rule with order s/n: reduce only when the number of non-zero columns
// m exceeds s, keep floor(n·(order − 1)) = s − n, box the m − s + n others. The reduced set is
// chosen as MATLAB's mink does: the smallest keys, ties to the lower column index. Kept columns
// stay in their original order, the n box columns follow (CORA's [Gunred, Gbox]).
//
// An extra axis box B_r (the estimators' pending rounding box, r >= 0 componentwise) can be
// absorbed into W without counting as generators.
//
// Guarantee in floating point. For Combastel/Girard, W = diag(s) with s the absolute row sums
// of [H_R, diag(r)] rounded up, an exact enclosure. For PCA the computed Q is only nearly
// orthogonal and W = fl(Q diag(s)) is rounded, so s is made large enough for the stored W:
// with Q̂ = W diag(s)⁻¹ (= Q up to one rounding per entry, |Q̂ − Q| ≤ u|Q|) and
// F̂ = Q̂ᵀQ̂ − I, ‖F̂‖₂ ≤ f < 1/2 (bounded from the computed QᵀQ),
//   Q̂⁻¹ = (I + F̂)⁻¹ Q̂ᵀ,   ‖Q̂⁻¹ − Q̂ᵀ‖₂ ≤ η = f √(1 + f) / (1 − f),
// so every x = H_R z + diag(r) t (|z|, |t| ≤ 1) is x = Q̂ d with
//   |d_i| ≤ rs(|fl(Qᵀ H_R)|)_i + (γ_n + u)(|Q|ᵀ rs|H_R|)_i + (1 + u)(|Q|ᵀ r)_i + η (Σ‖g_j‖₂ + ‖r‖₂) = s_i
// (after outward rounding of the sums), i.e. x ∈ W B^n. If f is not small (a failed
// eigen-decomposition), the method falls back to the axis box, which is exact.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

namespace setbound {

/// Order-reduction method of a zonotope (see sets/zonotope_reduction.hpp).
enum class ZonotopeReduction { Combastel = 1, Girard = 2, Pca = 3 };

namespace rounding_bounds {
inline constexpr double kUnitRoundoff = std::numeric_limits<double>::epsilon() / 2;
/// γ_k = k u / (1 − k u) (Higham), for k + 2 operations and doubled as a safety factor for
/// the additions around it.
double gamma(Eigen::Index k);
}  // namespace rounding_bounds

namespace detail {

/// Buffers of the in-place reduction, reused between calls (no allocation once grown).
struct ReductionWorkspace {
  Eigen::VectorXd key;
  std::vector<Eigen::Index> order;
  Eigen::MatrixXd Gred;            ///< n × capacity; the first |R| columns are the reduced ones
  Eigen::MatrixXd gram;            ///< n × n, Gred Gredᵀ (PCA, or when requested)
  Eigen::MatrixXd Q, QtG, QtQ, W;  ///< PCA basis, Qᵀ Gred, QᵀQ, the box generators
  Eigen::MatrixXd absQ, bound;
  Eigen::VectorXd s, wred, tmp;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;
  Eigen::Index reduced_count = 0;  ///< |R| of the last call (0: nothing reduced)
};

/// Sizes the workspace for reductions of up to `capacity` columns of n rows, so that reductions
/// never allocate afterwards (they otherwise grow the buffers on first need; an estimator's
/// allocation-free steady state must not depend on the largest column count seen so far).
void reserve_reduction_workspace(ReductionWorkspace& ws, Eigen::Index n, Eigen::Index capacity);

/// Reduction keys of the first m columns of H: larger = more worth keeping.
void reduction_keys(ZonotopeReduction method, const Eigen::MatrixXd& H, Eigen::Index m, Eigen::VectorXd& key);

/// The axis box: s = rs(|Gred|) + r, rounded up (exact enclosure of Gred B ⊕ B_r).
void axis_box(const Eigen::VectorXd& wred, const Eigen::VectorXd* r, Eigen::Index count, Eigen::VectorXd& s);

/// PCA box of ws.Gred (⊕ B_r) into ws.W (n × n); returns false (W untouched) when the
/// computed basis is not safely orthogonal, so the caller uses the axis box.
bool pca_box(const Eigen::VectorXd* r, Eigen::Index k, ReductionWorkspace& ws);

/// Reduces the first m columns of H in place to at most `limit` (>= n) columns when m > limit,
/// absorbing the box B_r (r may be null) into the replacement generators. Returns the new
/// column count. When nothing is reduced (m <= limit) H is untouched, r is NOT absorbed and
/// ws.reduced_count = 0. H must have room for m columns; the result never needs more.
/// With want_gram, ws.gram = Gred Gredᵀ of the reduced columns afterwards (for the estimators'
/// Gram matrix); the reduced columns are ws.Gred.leftCols(ws.reduced_count).
Eigen::Index reduce_in_place(ZonotopeReduction method, Eigen::MatrixXd& H, Eigen::Index m, Eigen::Index limit,
                                    const Eigen::VectorXd* r, ReductionWorkspace& ws, bool want_gram = false);

}  // namespace detail
}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/zonotope_reduction.ipp"
#endif
