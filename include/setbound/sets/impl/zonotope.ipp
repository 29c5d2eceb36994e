// setbound — definitions of the functions declared in setbound/sets/zonotope.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/sets/zonotope.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace detail {

SETBOUND_INLINE double binomial(Eigen::Index m, Eigen::Index k) {
  if (k < 0 || k > m) return 0.0;
  k = std::min(k, m - k);
  double r = 1.0;
  for (Eigen::Index i = 1; i <= k; ++i) r = r * static_cast<double>(m - k + i) / static_cast<double>(i);
  return std::round(r);
}

SETBOUND_INLINE double sum_inflation(Eigen::Index terms) {
  return 1.0 + static_cast<double>(terms + 2) * std::numeric_limits<double>::epsilon();
}

SETBOUND_INLINE Eigen::VectorXd abs_row_sums(const Eigen::Ref<const Eigen::MatrixXd>& M) {
  return M.cwiseAbs().rowwise().sum() * sum_inflation(M.cols());
}

}  // namespace detail
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE Zonotope::Zonotope(Eigen::VectorXd p, Eigen::MatrixXd H)
    : p_(std::move(p)), H_(std::move(H)) {
  if (p_.size() == 0) throw DimensionError("p: the zonotope must have dimension >= 1");
  require_finite(p_, "p");
  if (H_.rows() != p_.size())
    throw DimensionError("H: expected " + std::to_string(p_.size()) + " rows (the length of p), got " +
                         std::to_string(H_.rows()));
  require_finite(H_, "H");
}

SETBOUND_INLINE double Zonotope::order() const { return static_cast<double>(H_.cols()) / static_cast<double>(p_.size()); }

SETBOUND_INLINE Zonotope Zonotope::minkowski_sum(const Zonotope& other) const {
  detail::require_length(other.dimension(), dimension(), "other");
  Eigen::MatrixXd H(dimension(), H_.cols() + other.H_.cols());
  H << H_, other.H_;
  return Zonotope(p_ + other.p_, std::move(H));
}

SETBOUND_INLINE Zonotope Zonotope::linear_map(const Eigen::Ref<const Eigen::MatrixXd>& K) const {
  if (K.cols() != dimension() || K.rows() == 0)
    throw DimensionError("M: expected a k x " + std::to_string(dimension()) + " matrix with k >= 1, got " +
                         detail::shape_string(K.rows(), K.cols()));
  require_finite(K, "M");
  return Zonotope(K * p_, K * H_);
}

SETBOUND_INLINE Zonotope Zonotope::translate(const Eigen::Ref<const Eigen::VectorXd>& b) const {
  detail::require_length(b.size(), dimension(), "b");
  require_finite(b, "b");
  return Zonotope(p_ + b, H_);
}

SETBOUND_INLINE BoundingBox Zonotope::interval_hull() const {
  const Eigen::VectorXd r = detail::abs_row_sums(H_);
  return {p_ - r, p_ + r};
}

SETBOUND_INLINE double Zonotope::support(const Eigen::Ref<const Eigen::VectorXd>& d) const {
  detail::require_length(d.size(), dimension(), "d");
  require_finite(d, "d");
  const double h = d.dot(p_) + (H_.transpose() * d).cwiseAbs().sum();
  // Finite data whose products overflow (|d| |p| ~ 1e600) gave inf - inf = NaN (fuzz finding).
  if (std::isnan(h))
    throw NumericalError("d: the support value overflows double precision (|d| times the zonotope's size "
                         "exceeds 1.8e308)");
  return h;
}

SETBOUND_INLINE double Zonotope::volume() const {
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

SETBOUND_INLINE auto Zonotope::pradius_with_vertex(const Eigen::Ref<const Eigen::MatrixXd>& P) const -> PRadius {
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

SETBOUND_INLINE Zonotope Zonotope::reduce_combastel(Eigen::Index s) const {
  const Eigen::Index n = dimension();
  if (s < n)
    throw InvalidArgumentError("s: the generator limit must be >= n = " + std::to_string(n) + ", got " +
                               std::to_string(s));
  return reduced(ZonotopeReduction::Combastel, s);
}

SETBOUND_INLINE Zonotope Zonotope::reduce_girard_to(Eigen::Index max_generators) const {
  const Eigen::Index n = dimension();
  if (max_generators < n)
    throw InvalidArgumentError("limit: the generator limit must be >= n = " + std::to_string(n) +
                               ", got " + std::to_string(max_generators));
  return reduced(ZonotopeReduction::Girard, max_generators);
}

SETBOUND_INLINE Zonotope Zonotope::reduce_pca(Eigen::Index max_generators) const {
  const Eigen::Index n = dimension();
  if (max_generators < n)
    throw InvalidArgumentError("limit: the generator limit must be >= n = " + std::to_string(n) +
                               ", got " + std::to_string(max_generators));
  return reduced(ZonotopeReduction::Pca, max_generators);
}

SETBOUND_INLINE Zonotope Zonotope::reduce_girard(double order) const {
  require_finite(order, "order");
  if (order < 1.0) throw InvalidArgumentError("order: must be >= 1, got " + std::to_string(order));
  const double k = std::floor(order * static_cast<double>(dimension()) * (1.0 + 1e-12));
  if (k > 1e9) return *this;
  return reduce_girard_to(static_cast<Eigen::Index>(k));
}

SETBOUND_INLINE Zonotope Zonotope::intersect_strip_family(const Strip& strip, const Eigen::Ref<const Eigen::VectorXd>& lambda) const {
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

SETBOUND_INLINE Zonotope Zonotope::remove_zero_generators(double tol) const {
  require_nonnegative(tol, "tol");
  std::vector<Eigen::Index> keep;
  for (Eigen::Index j = 0; j < H_.cols(); ++j)
    if (H_.col(j).cwiseAbs().maxCoeff() > tol) keep.push_back(j);
  Eigen::MatrixXd H(dimension(), static_cast<Eigen::Index>(keep.size()));
  for (size_t j = 0; j < keep.size(); ++j) H.col(static_cast<Eigen::Index>(j)) = H_.col(keep[j]);
  return Zonotope(p_, std::move(H));
}

SETBOUND_INLINE bool Zonotope::contains(const Eigen::Ref<const Eigen::VectorXd>& x, double rel_tol) const {
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

SETBOUND_INLINE Zonotope Zonotope::reduced(ZonotopeReduction method, Eigen::Index limit) const {
  Eigen::MatrixXd H = remove_zero_generators().H_;
  detail::ReductionWorkspace ws;
  const Eigen::Index m = detail::reduce_in_place(method, H, H.cols(), limit, nullptr, ws);
  if (m == H.cols()) return Zonotope(p_, std::move(H));
  return Zonotope(p_, H.leftCols(m));
}

SETBOUND_INLINE Zonotope interval_generator_inclusion(const Eigen::Ref<const Eigen::VectorXd>& p,
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

SETBOUND_INLINE Zonotope interval_linear_map(const Eigen::Ref<const Eigen::MatrixXd>& mid,
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
