// setbound — ellipsoids E(P, c, rho) = { x : (x - c)^T P (x - c) <= rho }.
//
// Convention of spec papers.md §0.1 and thesis.md §1 (1.39): rho is a *level* that
// multiplies, not a squared radius written rho^2, so (P, rho) and (tP, t rho) describe the
// same set. Everything below is computed from a Cholesky factor P = L L^T, which is both
// the positive-definiteness check and the cheapest stable way to apply P^-1.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"

namespace setbound {

/// Axis-aligned box [lo, hi] (componentwise), the interval hull of a set.
struct BoundingBox {
  Eigen::VectorXd lo;
  Eigen::VectorXd hi;
};

namespace detail {
/// Throws DimensionError unless v has length n; the message names the argument.
inline void require_length(Eigen::Index size, Eigen::Index n, const std::string& name) {
  if (size != n)
    throw DimensionError(name + ": expected length " + std::to_string(n) + ", got " +
                         std::to_string(size));
}
/// log V_n, the log-volume of the Euclidean unit ball in R^n: V_n = pi^(n/2) / Gamma(n/2 + 1).
inline double log_unit_ball_volume(Eigen::Index n) {
  const double h = 0.5 * static_cast<double>(n);
  return h * std::log(3.14159265358979323846) - std::lgamma(h + 1.0);
}
}  // namespace detail

class Ellipsoid {
 public:
  /// Relative outward rounding of the bounding-box half-widths: sqrt(rho (P^-1)_ii) is
  /// computed with a relative error of a few ulps times n (triangular solves, a sum of n
  /// squares, a sqrt); 64 n eps covers that so the box stays an outer bound (ARCHITECTURE.md
  /// "Guarantees").
  static double box_inflation(Eigen::Index n) {
    return 64.0 * static_cast<double>(n + 1) * std::numeric_limits<double>::epsilon();
  }

  /// Validates P symmetric positive definite ("P"), c of length n and finite ("c"),
  /// rho >= 0 and finite ("rho"). rho = 0 is the single point {c}.
  Ellipsoid(Eigen::MatrixXd P, Eigen::VectorXd c, double rho)
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

  Eigen::Index dimension() const { return P_.rows(); }
  const Eigen::MatrixXd& shape() const { return P_; }
  const Eigen::VectorXd& center() const { return c_; }
  double level() const { return rho_; }

  /// P^-1, via the Cholesky factor.
  Eigen::MatrixXd shape_inverse() const {
    return llt_.solve(Eigen::MatrixXd::Identity(dimension(), dimension()));
  }

  /// a^T P^-1 a = ||L^-1 a||^2 (never negative, unlike a^T (P^-1 a) in floating point).
  double dual_quadratic(const Eigen::Ref<const Eigen::VectorXd>& a) const {
    detail::require_length(a.size(), dimension(), "a");
    return llt_.matrixL().solve(Eigen::VectorXd(a)).squaredNorm();
  }

  /// Interval hull c ± sqrt(rho (P^-1)_ii), thesis (1.40) / papers §0.1. The thesis prints a
  /// box computed from diag(P) for Example 1.3/1.4; that is wrong (thesis.md §3.3, §8), the
  /// projection needs diag(P^-1). Half-widths are rounded outward by box_inflation(n).
  BoundingBox bounding_box() const {
    const Eigen::Index n = dimension();
    const Eigen::MatrixXd Linv =
        llt_.matrixL().solve(Eigen::MatrixXd::Identity(n, n));  // P^-1 = L^-T L^-1
    Eigen::VectorXd half(n);
    for (Eigen::Index i = 0; i < n; ++i)
      half(i) = std::sqrt(rho_ * Linv.col(i).squaredNorm()) * (1.0 + box_inflation(n));
    return {c_ - half, c_ + half};
  }

  /// log vol = log V_n + (n/2) log rho - (1/2) log det P (papers §0.1), with log det P from
  /// the Cholesky diagonal so large or small determinants do not overflow. -inf when rho = 0.
  double log_volume() const {
    if (rho_ == 0.0) return -std::numeric_limits<double>::infinity();
    const double n = static_cast<double>(dimension());
    const double log_det_P = 2.0 * llt_.matrixLLT().diagonal().array().log().sum();
    return detail::log_unit_ball_volume(dimension()) + 0.5 * n * std::log(rho_) - 0.5 * log_det_P;
  }
  double volume() const { return std::exp(log_volume()); }

  /// (x - c)^T P (x - c) <= rho (1 + rel_tol). The tolerance only absorbs the rounding of
  /// the quadratic form for points on the boundary; it is relative to rho.
  bool contains(const Eigen::Ref<const Eigen::VectorXd>& x, double rel_tol = 1e-12) const {
    detail::require_length(x.size(), dimension(), "x");
    require_finite(x, "x");
    require_finite(rel_tol, "rel_tol");
    const double q = (llt_.matrixU() * (x - c_)).squaredNorm();
    return q <= rho_ * (1.0 + rel_tol);
  }

  /// Support function h(a) = max_{x in E} a^T x = a^T c + sqrt(rho a^T P^-1 a)
  /// (thesis §1 "containment tests": E ⊆ {a^T x <= b} iff h(a) <= b).
  double support(const Eigen::Ref<const Eigen::VectorXd>& a) const {
    detail::require_length(a.size(), dimension(), "a");
    require_finite(a, "a");
    return a.dot(c_) + std::sqrt(rho_ * dual_quadratic(a));
  }

  /// The maximiser of a^T x over E: c + sqrt(rho) P^-1 a / sqrt(a^T P^-1 a). For a = e_i it is
  /// the point where the bounding box's upper bound i is attained (thesis.md §3.3).
  Eigen::VectorXd support_point(const Eigen::Ref<const Eigen::VectorXd>& a) const {
    const double q = dual_quadratic(a);
    if (!(q > 0)) throw InvalidArgumentError("a: direction must be nonzero");
    return c_ + std::sqrt(rho_ / q) * llt_.solve(Eigen::VectorXd(a));
  }

  /// The point of the boundary on the ray c + t d, t >= 0: t = sqrt(rho / d^T P d).
  Eigen::VectorXd boundary_point(const Eigen::Ref<const Eigen::VectorXd>& d) const {
    detail::require_length(d.size(), dimension(), "d");
    const double q = (llt_.matrixU() * d).squaredNorm();
    if (!(q > 0)) throw InvalidArgumentError("d: direction must be nonzero");
    return c_ + std::sqrt(rho_ / q) * d;
  }

  /// Image under x -> M x + b with M square invertible: E(M^-T P M^-1, M c + b, rho).
  /// (y = Mx + b gives x - c = M^-1 (y - Mc - b).) A singular M would flatten the
  /// ellipsoid, which this representation (P positive definite) cannot hold.
  Ellipsoid affine_map(const Eigen::Ref<const Eigen::MatrixXd>& M,
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

  /// Smallest level rho' with E(P, c, rho) ⊆ E(P_new, c, rho'), papers §0.1 "change of shape":
  /// rho' = rho * lambda_max(P^-1/2 P_new P^-1/2), the largest generalised eigenvalue of
  /// (P_new, P). It is computed as lambda_max(L^-1 P_new L^-T) (same spectrum, P = L L^T) and
  /// then rounded UP: rho' = rho * lambda_max * (1 + delta), where delta starts at 16 n eps and
  /// is multiplied by 4 until the inclusion certificate  (rho'/rho) P - P_new > 0  passes a
  /// Cholesky factorisation (the "verified margin" rule of ARCHITECTURE.md). delta never
  /// exceeds 1e-6; beyond that the pair is too ill-conditioned and NumericalError is thrown.
  double level_for_shape(const Eigen::Ref<const Eigen::MatrixXd>& P_new) const {
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

  /// E(P_new, c, level_for_shape(P_new)): the smallest ellipsoid of shape P_new and the same
  /// centre that contains this one (how an initial set given with P0 enters a recursion run
  /// with the designed P; papers §0.1 and §8 item 8).
  Ellipsoid with_shape(const Eigen::Ref<const Eigen::MatrixXd>& P_new) const {
    const double r = level_for_shape(P_new);
    return Ellipsoid(Eigen::MatrixXd(P_new), c_, r);
  }

 private:
  Eigen::MatrixXd P_;
  Eigen::VectorXd c_;
  double rho_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace setbound
