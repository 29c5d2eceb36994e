// setbound — zonotopes Z = p ⊕ H B^m = { p + H z : z in [-1, 1]^m } (spec papers.md §0.1).
//
// The set representation of the zonotopic estimators ([Le2013], [Alamo2005]): prediction is
// a linear image plus a Minkowski sum, correction is the zonotope/strip family (Property
// 6), and the generator count is kept bounded by reduction (Property 3 / Girard 2005).
// Every over-approximating operation here contains its exact counterpart; where a sum of
// absolute values is rounded, it is inflated by a documented few ulps (ARCHITECTURE.md,
// "Guarantees").
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/ellipsoid.hpp"  // BoundingBox, detail::require_length
#include "setbound/sets/strip.hpp"
#include "setbound/sets/zonotope_reduction.hpp"

namespace setbound {

namespace detail {

/// C(m, k) as a double (exact up to 2^53, then a close over-estimate is all we need: it
/// is only compared against enumeration limits).
double binomial(Eigen::Index m, Eigen::Index k);

/// Calls f(idx) for every k-subset idx (increasing indices) of {0..m-1}, in lexicographic order.
template <class F>
void for_each_subset(Eigen::Index m, Eigen::Index k, F&& f) {
  if (k < 0 || k > m) return;
  std::vector<Eigen::Index> idx(static_cast<size_t>(k));
  std::iota(idx.begin(), idx.end(), Eigen::Index{0});
  while (true) {
    f(idx);
    Eigen::Index i = k - 1;
    while (i >= 0 && idx[static_cast<size_t>(i)] == m - k + i) --i;
    if (i < 0) return;
    ++idx[static_cast<size_t>(i)];
    for (Eigen::Index j = i + 1; j < k; ++j) idx[static_cast<size_t>(j)] = idx[static_cast<size_t>(j - 1)] + 1;
  }
}

/// Relative outward rounding for a floating-point sum of `terms` non-negative numbers: the
/// computed sum is within (terms - 1) eps of the exact one (Higham, recursive summation), so
/// (terms + 2) eps keeps an outer bound.
double sum_inflation(Eigen::Index terms);

/// rs(M) of papers §0.1 as a vector: the row sums of |M|, rounded outward.
Eigen::VectorXd abs_row_sums(const Eigen::Ref<const Eigen::MatrixXd>& M);

}  // namespace detail

/// The limit on enumerations (n-column subsets for the exact volume, (n-1)-subsets for the
/// exact membership test). Above it the exact answer is refused with InvalidArgumentError
/// instead of silently running for hours.
inline constexpr double kZonotopeEnumerationLimit = 5e6;
/// Exact P-radius enumerates 2^(m-1) sign vectors; above this many generators it is refused.
inline constexpr Eigen::Index kPRadiusMaxGenerators = 24;

class Zonotope {
 public:
  /// Validates: p non-empty and finite ("p"), H with n rows ("H") and finite entries.
  /// H may have zero columns (the single point {p}).
  Zonotope(Eigen::VectorXd p, Eigen::MatrixXd H);

  Eigen::Index dimension() const { return p_.size(); }
  Eigen::Index num_generators() const { return H_.cols(); }
  /// Order m / n (Girard 2005).
  double order() const;
  const Eigen::VectorXd& center() const { return p_; }
  const Eigen::MatrixXd& generators() const { return H_; }

  /// (p1 ⊕ H1 B) ⊕ (p2 ⊕ H2 B) = (p1 + p2) ⊕ [H1 H2] B (exact).
  Zonotope minkowski_sum(const Zonotope& other) const;
  Zonotope operator+(const Zonotope& other) const { return minkowski_sum(other); }

  /// K Z = K p ⊕ K H B (exact). K may be any k×n matrix (k >= 1).
  Zonotope linear_map(const Eigen::Ref<const Eigen::MatrixXd>& K) const;

  Zonotope translate(const Eigen::Ref<const Eigen::VectorXd>& b) const;

  /// Interval hull p_i ± sum_j |H_ij| (papers §0.1), radii rounded outward.
  BoundingBox interval_hull() const;

  /// Support function h(d) = max_{x in Z} d^T x = d^T p + ||H^T d||_1.
  double support(const Eigen::Ref<const Eigen::VectorXd>& d) const;

  /// Exact volume 2^n sum_{|S| = n} |det H_S| (papers §0.1; the zonotope is tiled by the
  /// parallelotopes of its n-column subsets). Zero when m < n. Refused (InvalidArgumentError)
  /// when C(m, n) exceeds kZonotopeEnumerationLimit.
  double volume() const;

  struct PRadius {
    double value;            ///< max_{s in B^m} s^T H^T P H s
    Eigen::VectorXd vertex;  ///< a maximising vertex s in {-1, 1}^m
  };

  /// Exact P-radius L = max_{z in Z} ||z - p||_P^2 = max_{s in {-1,1}^m} s^T H^T P H s
  /// (papers §0.1: a convex quadratic attains its max over a box at a vertex). Enumerates
  /// the 2^(m-1) vertices modulo the sign symmetry s ~ -s in Gray-code order, O(m) per
  /// vertex; refused above kPRadiusMaxGenerators generators.
  PRadius pradius_with_vertex(const Eigen::Ref<const Eigen::MatrixXd>& P) const;
  double pradius(const Eigen::Ref<const Eigen::MatrixXd>& P) const { return pradius_with_vertex(P).value; }

  /// Reduction of [Le2013] Property 3 (Combastel 2003 / [Alamo2005]), papers §0.1: when
  /// m > s, keep the s - n longest columns (Euclidean norm) and replace the rest H_Q by the
  /// n×n diagonal rs(H_Q). The result has at most s generators (a zero row of rs(H_Q) gives
  /// no column) and contains Z (H_Q B ⊆ rs(H_Q) B^n, the interval hull). Unchanged when
  /// m <= s. s must be >= n ("s").
  Zonotope reduce_combastel(Eigen::Index s) const;

  /// Girard 2005 reduction to at most `max_generators` (>= n) generators: keep the
  /// max_generators - n largest ||g||_1 - ||g||_inf (how much boxing a generator costs: zero
  /// for an axis-aligned one), replace the rest by their interval hull. Ties are reduced
  /// lower index first, as CORA's pickedGenerators (MATLAB mink).
  Zonotope reduce_girard_to(Eigen::Index max_generators) const;

  /// CORA's PCA reduction (reduce(Z,'pca',order), priv_reducePCA) to at most
  /// `max_generators` (>= n): Girard's choice of the columns to reduce, which are then boxed
  /// in the eigenbasis of their Gram matrix H_R H_Rᵀ instead of the axes. Guaranteed in
  /// floating point (see sets/zonotope_reduction.hpp).
  Zonotope reduce_pca(Eigen::Index max_generators) const;

  /// Girard 2005 with an order bound: result has at most floor(order * n) generators.
  Zonotope reduce_girard(double order) const;

  /// Zonotope/strip family of [Le2013] Property 6 (papers §0.1): for any lambda in R^n,
  /// Z ∩ S ⊆ p̂ ⊕ Ĥ B^(m+1), p̂ = p + lambda (y - c^T p), Ĥ = [(I - lambda c^T) H, phi lambda].
  /// (For x = p + H z with |c^T x - y| <= phi, write c^T x - y = phi t, |t| <= 1; then
  /// x = p̂ + (I - lambda c^T) H z + phi lambda t.)
  Zonotope intersect_strip_family(const Strip& strip, const Eigen::Ref<const Eigen::VectorXd>& lambda) const;

  /// Drops the columns whose largest |entry| is <= tol (exactly zero ones by default).
  Zonotope remove_zero_generators(double tol = 0.0) const;

  /// Exact membership test (up to a relative tolerance `rel_tol` for boundary points).
  ///
  /// A full-dimensional zonotope in R^r is the intersection of the slabs |c^T (x - p)| <=
  /// ||H^T c||_1 over the normals c of its facets, and every facet normal is orthogonal to
  /// r - 1 generators. So we enumerate the (r-1)-column subsets, take their normal (the
  /// generalised cross product: cofactors), skip degenerate subsets, and test every slab
  /// (extra, non-facet normals are valid inequalities too, so they do no harm). A flat
  /// zonotope (rank H = r < n) is first checked for x - p ∈ range(H) and then tested in
  /// coordinates of range(H). Cost C(m, r-1) normals; refused (InvalidArgumentError) above
  /// kZonotopeEnumerationLimit. Rank decisions use a relative threshold of 1e-10.
  bool contains(const Eigen::Ref<const Eigen::VectorXd>& x, double rel_tol = 1e-9) const;

 private:
  /// The non-zero columns (CORA counts only those), reduced in place by `method`.
  Zonotope reduced(ZonotopeReduction method, Eigen::Index limit) const;

  Eigen::VectorXd p_;
  Eigen::MatrixXd H_;
};

/// [Le2013] Property 4 (papers §0.1): for an interval matrix [M] (n×m) given by mid/rad,
/// the family p ⊕ [M] B^m (every M ∈ [M]) is contained in p ⊕ [mid[M], rs(rad[M])] B^(m+n).
/// (M z = mid z + (M - mid) z and |(M - mid) z|_i <= sum_j rad_ij for z ∈ B^m.)
Zonotope interval_generator_inclusion(const Eigen::Ref<const Eigen::VectorXd>& p,
                                             const Eigen::Ref<const Eigen::MatrixXd>& mid,
                                             const Eigen::Ref<const Eigen::MatrixXd>& rad);

/// Prediction through an interval matrix, papers §3.1: for every A ∈ [A] (k×n, given by
/// mid/rad) and z ∈ Z = p ⊕ H B^m,
///   A z ∈ mid p ⊕ [mid H, rs(rad |H|), diag(rad |p|)] B^(m + 2k).
/// (A z = mid p + mid H s + (A - mid) H s + (A - mid) p; the last two terms are bounded
/// componentwise by the row sums of rad |H| and by rad |p|.) The two box blocks are
/// rounded outward; the products mid p and mid H are the usual floating-point linear image.
Zonotope interval_linear_map(const Eigen::Ref<const Eigen::MatrixXd>& mid,
                                    const Eigen::Ref<const Eigen::MatrixXd>& rad, const Zonotope& Z);

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/zonotope.ipp"
#endif
