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
inline double binomial(Eigen::Index m, Eigen::Index k) {
  if (k < 0 || k > m) return 0.0;
  k = std::min(k, m - k);
  double r = 1.0;
  for (Eigen::Index i = 1; i <= k; ++i) r = r * static_cast<double>(m - k + i) / static_cast<double>(i);
  return std::round(r);
}

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
inline double sum_inflation(Eigen::Index terms) {
  return 1.0 + static_cast<double>(terms + 2) * std::numeric_limits<double>::epsilon();
}

/// rs(M) of papers §0.1 as a vector: the row sums of |M|, rounded outward.
inline Eigen::VectorXd abs_row_sums(const Eigen::Ref<const Eigen::MatrixXd>& M) {
  return M.cwiseAbs().rowwise().sum() * sum_inflation(M.cols());
}

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
  Zonotope(Eigen::VectorXd p, Eigen::MatrixXd H) : p_(std::move(p)), H_(std::move(H)) {
    if (p_.size() == 0) throw DimensionError("p: the zonotope must have dimension >= 1");
    require_finite(p_, "p");
    if (H_.rows() != p_.size())
      throw DimensionError("H: expected " + std::to_string(p_.size()) + " rows (the length of p), got " +
                           std::to_string(H_.rows()));
    require_finite(H_, "H");
  }

  Eigen::Index dimension() const { return p_.size(); }
  Eigen::Index num_generators() const { return H_.cols(); }
  /// Order m / n (Girard 2005).
  double order() const { return static_cast<double>(H_.cols()) / static_cast<double>(p_.size()); }
  const Eigen::VectorXd& center() const { return p_; }
  const Eigen::MatrixXd& generators() const { return H_; }

  /// (p1 ⊕ H1 B) ⊕ (p2 ⊕ H2 B) = (p1 + p2) ⊕ [H1 H2] B (exact).
  Zonotope minkowski_sum(const Zonotope& other) const {
    detail::require_length(other.dimension(), dimension(), "other");
    Eigen::MatrixXd H(dimension(), H_.cols() + other.H_.cols());
    H << H_, other.H_;
    return Zonotope(p_ + other.p_, std::move(H));
  }
  Zonotope operator+(const Zonotope& other) const { return minkowski_sum(other); }

  /// K Z = K p ⊕ K H B (exact). K may be any k×n matrix (k >= 1).
  Zonotope linear_map(const Eigen::Ref<const Eigen::MatrixXd>& K) const {
    if (K.cols() != dimension() || K.rows() == 0)
      throw DimensionError("M: expected a k x " + std::to_string(dimension()) + " matrix with k >= 1, got " +
                           detail::shape_string(K.rows(), K.cols()));
    require_finite(K, "M");
    return Zonotope(K * p_, K * H_);
  }

  Zonotope translate(const Eigen::Ref<const Eigen::VectorXd>& b) const {
    detail::require_length(b.size(), dimension(), "b");
    require_finite(b, "b");
    return Zonotope(p_ + b, H_);
  }

  /// Interval hull p_i ± sum_j |H_ij| (papers §0.1), radii rounded outward.
  BoundingBox interval_hull() const {
    const Eigen::VectorXd r = detail::abs_row_sums(H_);
    return {p_ - r, p_ + r};
  }

  /// Support function h(d) = max_{x in Z} d^T x = d^T p + ||H^T d||_1.
  double support(const Eigen::Ref<const Eigen::VectorXd>& d) const {
    detail::require_length(d.size(), dimension(), "d");
    require_finite(d, "d");
    const double h = d.dot(p_) + (H_.transpose() * d).cwiseAbs().sum();
    // Finite data whose products overflow (|d| |p| ~ 1e600) gave inf - inf = NaN (fuzz finding).
    if (std::isnan(h))
      throw NumericalError("d: the support value overflows double precision (|d| times the zonotope's size "
                           "exceeds 1.8e308)");
    return h;
  }

  /// Exact volume 2^n sum_{|S| = n} |det H_S| (papers §0.1; the zonotope is tiled by the
  /// parallelotopes of its n-column subsets). Zero when m < n. Refused (InvalidArgumentError)
  /// when C(m, n) exceeds kZonotopeEnumerationLimit.
  double volume() const {
    const Eigen::Index n = dimension(), m = num_generators();
    if (m < n) return 0.0;
    const double count = detail::binomial(m, n);
    if (count > kZonotopeEnumerationLimit)
      throw InvalidArgumentError("H: exact volume needs C(" + std::to_string(m) + ", " + std::to_string(n) +
                                 ") determinants, above the limit of 5e6; reduce the zonotope first");
    double sum = 0.0;
    Eigen::MatrixXd HS(n, n);
    detail::for_each_subset(m, n, [&](const std::vector<Eigen::Index>& idx) {
      for (Eigen::Index j = 0; j < n; ++j) HS.col(j) = H_.col(idx[static_cast<size_t>(j)]);
      sum += std::abs(HS.partialPivLu().determinant());
    });
    return std::ldexp(sum, static_cast<int>(n));
  }

  struct PRadius {
    double value;            ///< max_{s in B^m} s^T H^T P H s
    Eigen::VectorXd vertex;  ///< a maximising vertex s in {-1, 1}^m
  };

  /// Exact P-radius L = max_{z in Z} ||z - p||_P^2 = max_{s in {-1,1}^m} s^T H^T P H s
  /// (papers §0.1: a convex quadratic attains its max over a box at a vertex). Enumerates
  /// the 2^(m-1) vertices modulo the sign symmetry s ~ -s in Gray-code order, O(m) per
  /// vertex; refused above kPRadiusMaxGenerators generators.
  PRadius pradius_with_vertex(const Eigen::Ref<const Eigen::MatrixXd>& P) const {
    const Eigen::Index n = dimension(), m = num_generators();
    require_shape(P, n, n, "P");
    require_positive_definite(P, "P");
    if (m > kPRadiusMaxGenerators)
      throw InvalidArgumentError("H: exact P-radius enumerates 2^(m-1) vertices; m = " + std::to_string(m) +
                                 " is above the limit of " + std::to_string(kPRadiusMaxGenerators));
    if (m == 0) return {0.0, Eigen::VectorXd()};
    Eigen::MatrixXd G = H_.transpose() * (0.5 * (P + P.transpose())) * H_;
    G = (0.5 * (G + G.transpose())).eval();
    Eigen::VectorXd s = Eigen::VectorXd::Ones(m);
    Eigen::VectorXd g = G * s;
    double v = s.dot(g);
    double best = v;
    Eigen::VectorXd best_s = s;
    const std::uint64_t count = std::uint64_t{1} << static_cast<unsigned>(m - 1);
    for (std::uint64_t i = 1; i < count; ++i) {
      // Gray code: step i flips bit ctz(i); s_{m-1} stays +1 (the ±s symmetry).
      int k = 0;
      while (((i >> k) & 1u) == 0) ++k;
      const double sk = s(k);
      v += -4.0 * sk * g(k) + 4.0 * G(k, k);
      g -= 2.0 * sk * G.col(k);
      s(k) = -sk;
      if ((i & 4095u) == 0) {  // bound the drift of the incremental updates
        g = G * s;
        v = s.dot(g);
      }
      if (v > best) {
        best = v;
        best_s = s;
      }
    }
    return {best_s.dot(G * best_s), best_s};
  }
  double pradius(const Eigen::Ref<const Eigen::MatrixXd>& P) const { return pradius_with_vertex(P).value; }

  /// Reduction of [Le2013] Property 3 (Combastel 2003 / [Alamo2005]), papers §0.1: when
  /// m > s, keep the s - n longest columns (Euclidean norm) and replace the rest H_Q by the
  /// n×n diagonal rs(H_Q). The result has at most s generators (a zero row of rs(H_Q) gives
  /// no column) and contains Z (H_Q B ⊆ rs(H_Q) B^n, the interval hull). Unchanged when
  /// m <= s. s must be >= n ("s").
  Zonotope reduce_combastel(Eigen::Index s) const {
    const Eigen::Index n = dimension();
    if (s < n)
      throw InvalidArgumentError("s: the generator limit must be >= n = " + std::to_string(n) + ", got " +
                                 std::to_string(s));
    return reduced(ZonotopeReduction::Combastel, s);
  }

  /// Girard 2005 reduction to at most `max_generators` (>= n) generators: keep the
  /// max_generators - n largest ||g||_1 - ||g||_inf (how much boxing a generator costs: zero
  /// for an axis-aligned one), replace the rest by their interval hull. Ties are reduced
  /// lower index first, as CORA's pickedGenerators (MATLAB mink).
  Zonotope reduce_girard_to(Eigen::Index max_generators) const {
    const Eigen::Index n = dimension();
    if (max_generators < n)
      throw InvalidArgumentError("limit: the generator limit must be >= n = " + std::to_string(n) +
                                 ", got " + std::to_string(max_generators));
    return reduced(ZonotopeReduction::Girard, max_generators);
  }

  /// CORA's PCA reduction (reduce(Z,'pca',order), priv_reducePCA) to at most
  /// `max_generators` (>= n): Girard's choice of the columns to reduce, which are then boxed
  /// in the eigenbasis of their Gram matrix H_R H_Rᵀ instead of the axes. Guaranteed in
  /// floating point (see sets/zonotope_reduction.hpp).
  Zonotope reduce_pca(Eigen::Index max_generators) const {
    const Eigen::Index n = dimension();
    if (max_generators < n)
      throw InvalidArgumentError("limit: the generator limit must be >= n = " + std::to_string(n) +
                                 ", got " + std::to_string(max_generators));
    return reduced(ZonotopeReduction::Pca, max_generators);
  }

  /// Girard 2005 with an order bound: result has at most floor(order * n) generators.
  Zonotope reduce_girard(double order) const {
    require_finite(order, "order");
    if (order < 1.0) throw InvalidArgumentError("order: must be >= 1, got " + std::to_string(order));
    const double k = std::floor(order * static_cast<double>(dimension()) * (1.0 + 1e-12));
    if (k > 1e9) return *this;
    return reduce_girard_to(static_cast<Eigen::Index>(k));
  }

  /// Zonotope/strip family of [Le2013] Property 6 (papers §0.1): for any lambda in R^n,
  /// Z ∩ S ⊆ p̂ ⊕ Ĥ B^(m+1), p̂ = p + lambda (y - c^T p), Ĥ = [(I - lambda c^T) H, phi lambda].
  /// (For x = p + H z with |c^T x - y| <= phi, write c^T x - y = phi t, |t| <= 1; then
  /// x = p̂ + (I - lambda c^T) H z + phi lambda t.)
  Zonotope intersect_strip_family(const Strip& strip, const Eigen::Ref<const Eigen::VectorXd>& lambda) const {
    const Eigen::Index n = dimension(), m = num_generators();
    detail::require_length(strip.dimension(), n, "c");
    detail::require_length(lambda.size(), n, "lambda");
    require_finite(lambda, "lambda");
    const Eigen::VectorXd& c = strip.normal();
    Eigen::MatrixXd Hn(n, m + 1);
    Hn.leftCols(m) = H_ - lambda * (c.transpose() * H_);
    Hn.col(m) = strip.half_width() * lambda;
    return Zonotope(p_ + lambda * (strip.measurement() - c.dot(p_)), std::move(Hn));
  }

  /// Drops the columns whose largest |entry| is <= tol (exactly zero ones by default).
  Zonotope remove_zero_generators(double tol = 0.0) const {
    require_nonnegative(tol, "tol");
    std::vector<Eigen::Index> keep;
    for (Eigen::Index j = 0; j < H_.cols(); ++j)
      if (H_.col(j).cwiseAbs().maxCoeff() > tol) keep.push_back(j);
    Eigen::MatrixXd H(dimension(), static_cast<Eigen::Index>(keep.size()));
    for (size_t j = 0; j < keep.size(); ++j) H.col(static_cast<Eigen::Index>(j)) = H_.col(keep[j]);
    return Zonotope(p_, std::move(H));
  }

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
  bool contains(const Eigen::Ref<const Eigen::VectorXd>& x, double rel_tol = 1e-9) const {
    const Eigen::Index n = dimension();
    detail::require_length(x.size(), n, "x");
    require_finite(x, "x");
    require_nonnegative(rel_tol, "rel_tol");
    Eigen::VectorXd d = x - p_;
    // Rounding of x - p and of p + H z is relative to these magnitudes (no absolute floor, so
    // tiny zonotopes are tested at their own scale).
    const double scale = std::max({p_.cwiseAbs().maxCoeff(), x.cwiseAbs().maxCoeff(),
                                   H_.size() ? H_.cwiseAbs().rowwise().sum().maxCoeff() : 0.0});
    Eigen::MatrixXd G = remove_zero_generators().H_;
    if (G.cols() == 0) return d.cwiseAbs().maxCoeff() <= rel_tol * scale;
    // Membership is invariant under scaling d and G together; normalising to max |G_ij| = 1
    // keeps the QR's squared column norms (and the tolerance) from underflowing for tiny
    // generators. scale / gmax >= 1 because scale includes the largest row sum of |H|.
    const double gmax = G.cwiseAbs().maxCoeff();
    G /= gmax;
    d /= gmax;
    const double abs_tol = rel_tol * (scale / gmax);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(G);
    qr.setThreshold(1e-10);
    const Eigen::Index r = qr.rank();
    if (r == 0) throw NumericalError("H: rank determination failed in the membership test");
    if (r < n) {
      const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(n, r);
      const Eigen::VectorXd dr = Q.transpose() * d;
      if ((d - Q * dr).norm() > abs_tol) return false;
      d = dr;
      G = Q.transpose() * G;
    }
    const Eigen::Index m = G.cols();
    if (detail::binomial(m, r - 1) > kZonotopeEnumerationLimit)
      throw InvalidArgumentError("H: exact membership needs C(" + std::to_string(m) + ", " +
                                 std::to_string(r - 1) + ") facet normals, above the limit of 5e6");
    if (r == 1) return std::abs(d(0)) <= G.cwiseAbs().sum() * (1.0 + rel_tol) + abs_tol;
    const Eigen::VectorXd colnorm = G.colwise().norm().transpose();
    bool inside = true;
    Eigen::MatrixXd GS(r, r - 1), minor(r - 1, r - 1);
    Eigen::VectorXd c(r);
    detail::for_each_subset(m, r - 1, [&](const std::vector<Eigen::Index>& idx) {
      if (!inside) return;
      // Unit columns, so |c| is the (r-1)-volume they span: near 0 means degenerate.
      for (Eigen::Index j = 0; j < r - 1; ++j)
        GS.col(j) = G.col(idx[static_cast<size_t>(j)]) / colnorm(idx[static_cast<size_t>(j)]);
      // c_i = (-1)^i det(GS without row i): orthogonal to every column of GS.
      for (Eigen::Index i = 0; i < r; ++i) {
        minor.topRows(i) = GS.topRows(i);
        minor.bottomRows(r - 1 - i) = GS.bottomRows(r - 1 - i);
        c(i) = ((i % 2) ? -1.0 : 1.0) * minor.determinant();
      }
      const double cn = c.norm();
      if (cn <= 1e-10) return;  // the subset does not span a hyperplane
      c /= cn;
      const double h = (G.transpose() * c).cwiseAbs().sum();
      if (std::abs(c.dot(d)) > h * (1.0 + rel_tol) + abs_tol) inside = false;
    });
    return inside;
  }

 private:
  /// The non-zero columns (CORA counts only those), reduced in place by `method`.
  Zonotope reduced(ZonotopeReduction method, Eigen::Index limit) const {
    Eigen::MatrixXd H = remove_zero_generators().H_;
    detail::ReductionWorkspace ws;
    const Eigen::Index m = detail::reduce_in_place(method, H, H.cols(), limit, nullptr, ws);
    if (m == H.cols()) return Zonotope(p_, std::move(H));
    return Zonotope(p_, H.leftCols(m));
  }

  Eigen::VectorXd p_;
  Eigen::MatrixXd H_;
};

/// [Le2013] Property 4 (papers §0.1): for an interval matrix [M] (n×m) given by mid/rad,
/// the family p ⊕ [M] B^m (every M ∈ [M]) is contained in p ⊕ [mid[M], rs(rad[M])] B^(m+n).
/// (M z = mid z + (M - mid) z and |(M - mid) z|_i <= sum_j rad_ij for z ∈ B^m.)
inline Zonotope interval_generator_inclusion(const Eigen::Ref<const Eigen::VectorXd>& p,
                                             const Eigen::Ref<const Eigen::MatrixXd>& mid,
                                             const Eigen::Ref<const Eigen::MatrixXd>& rad) {
  const Eigen::Index n = p.size();
  if (mid.rows() != n)
    throw DimensionError("mid: expected " + std::to_string(n) + " rows (the length of p), got " +
                         std::to_string(mid.rows()));
  require_shape(rad, mid.rows(), mid.cols(), "rad");
  require_finite(mid, "mid");
  require_finite(rad, "rad");
  if (rad.size() > 0 && rad.minCoeff() < 0) throw InvalidArgumentError("rad: entries must be >= 0");
  Eigen::MatrixXd H(n, mid.cols() + n);
  H << mid, Eigen::MatrixXd(detail::abs_row_sums(rad).asDiagonal());
  return Zonotope(Eigen::VectorXd(p), std::move(H));
}

/// Prediction through an interval matrix, papers §3.1: for every A ∈ [A] (k×n, given by
/// mid/rad) and z ∈ Z = p ⊕ H B^m,
///   A z ∈ mid p ⊕ [mid H, rs(rad |H|), diag(rad |p|)] B^(m + 2k).
/// (A z = mid p + mid H s + (A - mid) H s + (A - mid) p; the last two terms are bounded
/// componentwise by the row sums of rad |H| and by rad |p|.) The two box blocks are
/// rounded outward; the products mid p and mid H are the usual floating-point linear image.
inline Zonotope interval_linear_map(const Eigen::Ref<const Eigen::MatrixXd>& mid,
                                    const Eigen::Ref<const Eigen::MatrixXd>& rad, const Zonotope& Z) {
  const Eigen::Index n = Z.dimension(), m = Z.num_generators(), k = mid.rows();
  if (k == 0 || mid.cols() != n)
    throw DimensionError("mid: expected a k x " + std::to_string(n) + " matrix with k >= 1, got " +
                         detail::shape_string(mid.rows(), mid.cols()));
  require_shape(rad, k, n, "rad");
  require_finite(mid, "mid");
  require_finite(rad, "rad");
  if (rad.minCoeff() < 0) throw InvalidArgumentError("rad: entries must be >= 0");
  const Eigen::MatrixXd absH = Z.generators().cwiseAbs();
  const Eigen::VectorXd box_H =
      m > 0 ? Eigen::VectorXd((rad * absH).rowwise().sum() * detail::sum_inflation(n * m))
            : Eigen::VectorXd::Zero(k);
  const Eigen::VectorXd box_p = rad * Z.center().cwiseAbs() * detail::sum_inflation(n);
  Eigen::MatrixXd H(k, m + 2 * k);
  H << mid * Z.generators(), Eigen::MatrixXd(box_H.asDiagonal()), Eigen::MatrixXd(box_p.asDiagonal());
  return Zonotope(mid * Z.center(), std::move(H));
}

}  // namespace setbound
