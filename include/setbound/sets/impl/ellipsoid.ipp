// setbound — definitions of the functions declared in setbound/sets/ellipsoid.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/sets/ellipsoid.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace detail {

SETBOUND_INLINE void require_length(Eigen::Index size, Eigen::Index n, const std::string& name) {
  if (size != n)
    throw DimensionError(name + ": expected length " + std::to_string(n) + ", got " +
                         std::to_string(size));
}

SETBOUND_INLINE double log_unit_ball_volume(Eigen::Index n) {
  const double h = 0.5 * static_cast<double>(n);
  return h * std::log(3.14159265358979323846) - std::lgamma(h + 1.0);
}

}  // namespace detail
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE double Ellipsoid::box_inflation(Eigen::Index n) {
  return 64.0 * static_cast<double>(n + 1) * std::numeric_limits<double>::epsilon();
}

SETBOUND_INLINE Ellipsoid::Ellipsoid(Eigen::MatrixXd P, Eigen::VectorXd c, double rho)
    : P_(std::move(P)), c_(std::move(c)), rho_(rho) {
  if (P_.rows() == 0) throw DimensionError("P: the ellipsoid must have dimension >= 1");
  require_square(P_, "P");
  require_positive_definite(P_, "P");
  P_ = (0.5 * (P_ + P_.transpose())).eval();  // exact symmetry from here on (eval: no aliasing)
  detail::require_length(c_.size(), P_.rows(), "c");
  require_finite(c_, "c");
  require_nonnegative(rho_, "rho");
  llt_.compute(P_);
  if (llt_.info() != Eigen::Success)
    throw NotPositiveDefiniteError("P: matrix is not positive definite");
}

SETBOUND_INLINE Eigen::MatrixXd Ellipsoid::shape_inverse() const {
  return llt_.solve(Eigen::MatrixXd::Identity(dimension(), dimension()));
}

SETBOUND_INLINE double Ellipsoid::dual_quadratic(const Eigen::Ref<const Eigen::VectorXd>& a) const {
  detail::require_length(a.size(), dimension(), "a");
  return llt_.matrixL().solve(Eigen::VectorXd(a)).squaredNorm();
}

SETBOUND_INLINE BoundingBox Ellipsoid::bounding_box() const {
  const Eigen::Index n = dimension();
  const Eigen::MatrixXd Linv =
      llt_.matrixL().solve(Eigen::MatrixXd::Identity(n, n));  // P^-1 = L^-T L^-1
  Eigen::VectorXd half(n);
  for (Eigen::Index i = 0; i < n; ++i)
    half(i) = std::sqrt(rho_ * Linv.col(i).squaredNorm()) * (1.0 + box_inflation(n));
  return {c_ - half, c_ + half};
}

SETBOUND_INLINE double Ellipsoid::log_volume() const {
  if (rho_ == 0.0) return -std::numeric_limits<double>::infinity();
  const double n = static_cast<double>(dimension());
  const double log_det_P = 2.0 * llt_.matrixLLT().diagonal().array().log().sum();
  return detail::log_unit_ball_volume(dimension()) + 0.5 * n * std::log(rho_) - 0.5 * log_det_P;
}

SETBOUND_INLINE bool Ellipsoid::contains(const Eigen::Ref<const Eigen::VectorXd>& x, double rel_tol) const {
  detail::require_length(x.size(), dimension(), "x");
  require_finite(x, "x");
  require_finite(rel_tol, "rel_tol");
  const double q = (llt_.matrixU() * (x - c_)).squaredNorm();
  return q <= rho_ * (1.0 + rel_tol);
}

SETBOUND_INLINE double Ellipsoid::support(const Eigen::Ref<const Eigen::VectorXd>& a) const {
  detail::require_length(a.size(), dimension(), "a");
  require_finite(a, "a");
  return a.dot(c_) + std::sqrt(rho_ * dual_quadratic(a));
}

SETBOUND_INLINE Eigen::VectorXd Ellipsoid::support_point(const Eigen::Ref<const Eigen::VectorXd>& a) const {
  const double q = dual_quadratic(a);
  if (!(q > 0)) throw InvalidArgumentError("a: direction must be nonzero");
  return c_ + std::sqrt(rho_ / q) * llt_.solve(Eigen::VectorXd(a));
}

SETBOUND_INLINE Eigen::VectorXd Ellipsoid::boundary_point(const Eigen::Ref<const Eigen::VectorXd>& d) const {
  detail::require_length(d.size(), dimension(), "d");
  const double q = (llt_.matrixU() * d).squaredNorm();
  if (!(q > 0)) throw InvalidArgumentError("d: direction must be nonzero");
  return c_ + std::sqrt(rho_ / q) * d;
}

SETBOUND_INLINE Ellipsoid Ellipsoid::affine_map(const Eigen::Ref<const Eigen::MatrixXd>& M,
                       const Eigen::Ref<const Eigen::VectorXd>& b) const {
  const Eigen::Index n = dimension();
  require_shape(M, n, n, "M");
  require_finite(M, "M");
  detail::require_length(b.size(), n, "b");
  require_finite(b, "b");
  Eigen::FullPivLU<Eigen::MatrixXd> lu(M);
  if (!lu.isInvertible() || lu.rcond() < 1e3 * std::numeric_limits<double>::epsilon())
    throw InvalidArgumentError("M: matrix must be invertible (it is singular or numerically singular)");
  // M^-T P M^-1 = (L^T M^-1)^T (L^T M^-1): a Gram matrix, symmetric PSD by construction.
  const Eigen::MatrixXd W = Eigen::MatrixXd(llt_.matrixU()) * lu.inverse();  // L^T M^-1
  Eigen::MatrixXd Pn = W.transpose() * W;
  Pn = (0.5 * (Pn + Pn.transpose())).eval();
  Eigen::LLT<Eigen::MatrixXd> check(Pn);
  if (check.info() != Eigen::Success)
    throw NumericalError("M: the image ellipsoid's shape matrix lost positive definiteness "
                         "(M is too ill-conditioned)");
  return Ellipsoid(std::move(Pn), M * c_ + b, rho_);
}

SETBOUND_INLINE double Ellipsoid::level_for_shape(const Eigen::Ref<const Eigen::MatrixXd>& P_new) const {
  const Eigen::Index n = dimension();
  require_shape(P_new, n, n, "P_new");
  require_positive_definite(P_new, "P_new");
  if (rho_ == 0.0) return 0.0;
  const Eigen::MatrixXd Pn = 0.5 * (P_new + P_new.transpose());
  const auto L = llt_.matrixL();
  Eigen::MatrixXd C = L.solve(Pn);                           // L^-1 P_new
  C = L.solve(Eigen::MatrixXd(C.transpose())).transpose();  // L^-1 P_new L^-T
  C = (0.5 * (C + C.transpose())).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(C, Eigen::EigenvaluesOnly);
  if (eig.info() != Eigen::Success)
    throw NumericalError("P_new: generalised eigenvalue computation did not converge");
  const double lmax = eig.eigenvalues().maxCoeff();
  double delta = 16.0 * static_cast<double>(n) * std::numeric_limits<double>::epsilon();
  for (; delta <= 1e-6; delta *= 4.0) {
    const double mu = lmax * (1.0 + delta);
    Eigen::LLT<Eigen::MatrixXd> cert(mu * P_ - Pn);
    if (cert.info() == Eigen::Success) return rho_ * mu;
  }
  throw NumericalError("P_new: the change of shape could not be certified (the pair (P, P_new) "
                       "is too ill-conditioned)");
}

SETBOUND_INLINE Ellipsoid Ellipsoid::with_shape(const Eigen::Ref<const Eigen::MatrixXd>& P_new) const {
  const double r = level_for_shape(P_new);
  return Ellipsoid(Eigen::MatrixXd(P_new), c_, r);
}

}  // namespace setbound
