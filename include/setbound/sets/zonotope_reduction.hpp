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

#include "setbound/sets/generator_kernels.hpp"

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
  Eigen::MatrixXd Q, Qt, QtG, QtQ, W;  ///< PCA basis, its transpose, Qᵀ Gred, QᵀQ, the box generators
  Eigen::MatrixXd absQ, bound;
  Eigen::VectorXd s, wred, tmp;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;
  Eigen::Index reduced_count = 0;  ///< |R| of the last call (0: nothing reduced)
};

/// Sizes the workspace for reductions of up to `capacity` columns of n rows, so that reductions
/// never allocate afterwards (they otherwise grow the buffers on first need; an estimator's
/// allocation-free steady state must not depend on the largest column count seen so far).
void reserve_reduction_workspace(ReductionWorkspace& ws, Eigen::Index n, Eigen::Index capacity);

/// Reduction keys of columns [from, m) of H into key(from) … key(m − 1) (key grows to m when
/// shorter): larger = more worth keeping.
void reduction_keys(ZonotopeReduction method, const Eigen::MatrixXd& H, Eigen::Index m, Eigen::VectorXd& key,
                    Eigen::Index from = 0);

/// compact_and_sum (generator_kernels.hpp: drop exactly-zero columns of the first m of W, w =
/// rs|W| rounded up) that also writes the reduction key of every kept column, in the same pass
/// over the columns. key grows to m when shorter. Returns the kept column count.
Eigen::Index compact_sum_keys(ZonotopeReduction method, Eigen::MatrixXd& W, Eigen::Index m, Eigen::VectorXd& w,
                              Eigen::VectorXd& key);

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
/// With keys_ready, ws.key holds the keys of the m columns already (compact_sum_keys). With w,
/// *w = rs|H| of the result rounded up, as compact_and_sum would give it (the pass that moves
/// the kept columns sums them), when something was reduced.
Eigen::Index reduce_in_place(ZonotopeReduction method, Eigen::MatrixXd& H, Eigen::Index m, Eigen::Index limit,
                             const Eigen::VectorXd* r, ReductionWorkspace& ws, bool want_gram = false,
                             bool keys_ready = false, Eigen::VectorXd* w = nullptr);

/// The end of every step of the zonotopic estimators, on the first m columns of W (room for
/// m + n more): drop exactly-zero columns (CORA never counts them, order kept); a pending
/// rounding box r above box_threshold × the largest row sum becomes n axis generators (counted);
/// above `limit` (when `reduce`) the reduction absorbs what is left of the box (r = 0 after).
/// w = rs|W| of the result rounded up. With S (n × n, the Gram matrix of the m columns before),
/// S follows the box columns and the reduction by rank updates. Returns the column count;
/// ws.reduced_count says whether the reduction ran. With negligible > 0, the columns that are
/// below `negligible` times the row sum in every row join the box first (absorb_negligible: an
/// outer bound that the order limit no longer counts).
Eigen::Index finish_generators(ZonotopeReduction method, Eigen::MatrixXd& W, Eigen::Index m, Eigen::Index limit,
                               bool reduce, double box_threshold, Eigen::VectorXd& r, Eigen::VectorXd& w,
                               ReductionWorkspace& ws, Eigen::MatrixXd* S, double negligible = 0.0);

// ---- fixed-size kernels (n <= 8: a column lives in registers) ----------------------------------

/// The key of one column g (|g| in a): ‖g‖₂ (Combastel) or ‖g‖₁ − ‖g‖∞ (Girard, PCA;
/// MATLAB's vecnorm(G,1,1) − vecnorm(G,Inf,1)), summed in row order. The one definition both key
/// passes use, so keys computed in different passes compare exactly. Plain loops over a
/// compile-time N: the compiler keeps the column in registers (Eigen's fixed-size reductions
/// went through memory and an out-of-line call here).
template <int N, bool Euclidean>
inline double column_key(const double* g, const double* a, double& abs_sum) {
  double s = 0.0, mx = 0.0, q = 0.0;
  for (int i = 0; i < N; ++i) {
    s += a[i];
    if constexpr (Euclidean) q += g[i] * g[i];
    else mx = a[i] > mx ? a[i] : mx;
  }
  abs_sum = s;
  if constexpr (Euclidean) return std::sqrt(q);
  else return s - mx;
}

template <int N>
void reduction_keys_fixed(bool euclidean, const Eigen::MatrixXd& H, Eigen::Index from, Eigen::Index m, double* key) {
  const double* const base = H.data();
  double a[N], s;
  for (Eigen::Index j = from; j < m; ++j) {
    const double* g = base + j * N;
    for (int i = 0; i < N; ++i) a[i] = std::abs(g[i]);
    key[j] = euclidean ? column_key<N, true>(g, a, s) : column_key<N, false>(g, a, s);
  }
}

template <int N, bool Euclidean>
Eigen::Index compact_sum_keys_impl(Eigen::MatrixXd& W, Eigen::Index m, Eigen::VectorXd& w, double* key) {
  double acc[N];
  for (int i = 0; i < N; ++i) acc[i] = 0.0;
  double* const base = W.data();
  Eigen::Index k = 0;
  for (Eigen::Index j = 0; j < m; ++j) {
    const double* g = base + j * N;
    double a[N], s;
    for (int i = 0; i < N; ++i) a[i] = std::abs(g[i]);
    for (int i = 0; i < N; ++i) acc[i] += a[i];
    const double kj = column_key<N, Euclidean>(g, a, s);
    // Σ|g_i| is 0 exactly when every entry is (no cancellation among non-negative terms; a NaN
    // column is kept).
    if (s == 0.0) continue;
    key[k] = kj;
    if (k != j)
      for (int i = 0; i < N; ++i) base[k * N + i] = g[i];  // k < j: no overlap
    ++k;
  }
  const double infl = 1.0 + static_cast<double>(k + 2) * std::numeric_limits<double>::epsilon();
  w.resize(N);
  for (int i = 0; i < N; ++i) w(i) = acc[i] * infl;
  return k;
}

template <int N>
Eigen::Index compact_sum_keys_fixed(bool euclidean, Eigen::MatrixXd& W, Eigen::Index m, Eigen::VectorXd& w, double* key) {
  return euclidean ? compact_sum_keys_impl<N, true>(W, m, w, key) : compact_sum_keys_impl<N, false>(W, m, w, key);
}

/// The reduction's compaction: columns listed in `reduced` (ascending) go to gred in that order,
/// the others close the gaps in place; returns their count and adds their |·| to acc in column
/// order (as compact_and_sum sums them).
template <int N>
Eigen::Index gather_and_sum_fixed(double* base, Eigen::Index m, const Eigen::Index* reduced, Eigen::Index nred,
                                  double* gred, double* acc) {
  double sum[N];  // local: stays in registers (acc might alias the columns)
  for (int i = 0; i < N; ++i) sum[i] = acc[i];
  Eigen::Index kk = 0, from = 0;
  auto keep_run = [&](Eigen::Index a, Eigen::Index b) {  // kept columns a … b − 1 move to kk …
    const Eigen::Index shift = a - kk;
    for (Eigen::Index j = a; j < b; ++j) {
      const double* g = base + j * N;
      for (int i = 0; i < N; ++i) sum[i] += std::abs(g[i]);
      if (shift != 0)
        for (int i = 0; i < N; ++i) base[(j - shift) * N + i] = g[i];
    }
    kk += b - a;
  };
  for (Eigen::Index t = 0; t < nred; ++t) {
    const Eigen::Index j = reduced[t];
    keep_run(from, j);
    for (int i = 0; i < N; ++i) gred[t * N + i] = base[j * N + i];
    from = j + 1;
  }
  keep_run(from, m);
  for (int i = 0; i < N; ++i) acc[i] = sum[i];
  return kk;
}

}  // namespace detail
}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/zonotope_reduction.ipp"
#endif
