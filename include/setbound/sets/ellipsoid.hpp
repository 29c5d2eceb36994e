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
void require_length(Eigen::Index size, Eigen::Index n, const std::string& name);
/// log V_n, the log-volume of the Euclidean unit ball in R^n: V_n = pi^(n/2) / Gamma(n/2 + 1).
double log_unit_ball_volume(Eigen::Index n);
}  // namespace detail

class Ellipsoid {
 public:
  /// Relative outward rounding of the bounding-box half-widths: sqrt(rho (P^-1)_ii) is
  /// computed with a relative error of a few ulps times n (triangular solves, a sum of n
  /// squares, a sqrt); 64 n eps covers that so the box stays an outer bound (ARCHITECTURE.md
  /// "Guarantees").
  static double box_inflation(Eigen::Index n);

  /// Validates P symmetric positive definite ("P"), c of length n and finite ("c"),
  /// rho >= 0 and finite ("rho"). rho = 0 is the single point {c}.
  Ellipsoid(Eigen::MatrixXd P, Eigen::VectorXd c, double rho);

  Eigen::Index dimension() const { return P_.rows(); }
  const Eigen::MatrixXd& shape() const { return P_; }
  const Eigen::VectorXd& center() const { return c_; }
  double level() const { return rho_; }

  /// P^-1, via the Cholesky factor.
  Eigen::MatrixXd shape_inverse() const;

  /// a^T P^-1 a = ||L^-1 a||^2 (never negative, unlike a^T (P^-1 a) in floating point).
  double dual_quadratic(const Eigen::Ref<const Eigen::VectorXd>& a) const;

  /// Interval hull c ± sqrt(rho (P^-1)_ii), thesis (1.40) / papers §0.1. The thesis prints a
  /// box computed from diag(P) for Example 1.3/1.4; that is wrong (thesis.md §3.3, §8), the
  /// projection needs diag(P^-1). Half-widths are rounded outward by box_inflation(n).
  BoundingBox bounding_box() const;

  /// log vol = log V_n + (n/2) log rho - (1/2) log det P (papers §0.1), with log det P from
  /// the Cholesky diagonal so large or small determinants do not overflow. -inf when rho = 0.
  double log_volume() const;
  double volume() const { return std::exp(log_volume()); }

  /// (x - c)^T P (x - c) <= rho (1 + rel_tol). The tolerance only absorbs the rounding of
  /// the quadratic form for points on the boundary; it is relative to rho.
  bool contains(const Eigen::Ref<const Eigen::VectorXd>& x, double rel_tol = 1e-12) const;

  /// Support function h(a) = max_{x in E} a^T x = a^T c + sqrt(rho a^T P^-1 a)
  /// (thesis §1 "containment tests": E ⊆ {a^T x <= b} iff h(a) <= b).
  double support(const Eigen::Ref<const Eigen::VectorXd>& a) const;

  /// The maximiser of a^T x over E: c + sqrt(rho) P^-1 a / sqrt(a^T P^-1 a). For a = e_i it is
  /// the point where the bounding box's upper bound i is attained (thesis.md §3.3).
  Eigen::VectorXd support_point(const Eigen::Ref<const Eigen::VectorXd>& a) const;

  /// The point of the boundary on the ray c + t d, t >= 0: t = sqrt(rho / d^T P d).
  Eigen::VectorXd boundary_point(const Eigen::Ref<const Eigen::VectorXd>& d) const;

  /// Image under x -> M x + b with M square invertible: E(M^-T P M^-1, M c + b, rho).
  /// (y = Mx + b gives x - c = M^-1 (y - Mc - b).) A singular M would flatten the
  /// ellipsoid, which this representation (P positive definite) cannot hold.
  Ellipsoid affine_map(const Eigen::Ref<const Eigen::MatrixXd>& M,
                       const Eigen::Ref<const Eigen::VectorXd>& b) const;

  /// Smallest level rho' with E(P, c, rho) ⊆ E(P_new, c, rho'), papers §0.1 "change of shape":
  /// rho' = rho * lambda_max(P^-1/2 P_new P^-1/2), the largest generalised eigenvalue of
  /// (P_new, P). It is computed as lambda_max(L^-1 P_new L^-T) (same spectrum, P = L L^T) and
  /// then rounded UP: rho' = rho * lambda_max * (1 + delta), where delta starts at 16 n eps and
  /// is multiplied by 4 until the inclusion certificate  (rho'/rho) P - P_new > 0  passes a
  /// Cholesky factorisation (the "verified margin" rule of ARCHITECTURE.md). delta never
  /// exceeds 1e-6; beyond that the pair is too ill-conditioned and NumericalError is thrown.
  double level_for_shape(const Eigen::Ref<const Eigen::MatrixXd>& P_new) const;

  /// E(P_new, c, level_for_shape(P_new)): the smallest ellipsoid of shape P_new and the same
  /// centre that contains this one (how an initial set given with P0 enters a recursion run
  /// with the designed P; papers §0.1 and §8 item 8).
  Ellipsoid with_shape(const Eigen::Ref<const Eigen::MatrixXd>& P_new) const;

 private:
  Eigen::MatrixXd P_;
  Eigen::VectorXd c_;
  double rho_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/ellipsoid.ipp"
#endif
