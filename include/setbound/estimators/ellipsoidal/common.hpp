// setbound — what every ellipsoidal estimator shares: the interface types and the rules that
// keep a floating-point recursion guaranteed.
//
// The ellipsoidal family (papers.md §1, §2, §4, §6) propagates E(P, c, ρ) = { x : (x − c)ᵀ P
// (x − c) ≤ ρ }. Two things can break the guarantee in floating point, and both are handled
// here once:
//
//  1. The LMI certificate. A solver returns a point that satisfies its LMIs up to its
//     tolerance, usually on the boundary at the optimum. An estimator imposes its LMIs with a
//     small margin and then *certifies* the matrices built from the values it actually uses
//     (the rounded gain L, the rounded ρ): `certify_psd(M)` succeeds only when a Cholesky
//     factorisation of M − δI succeeds for a δ that covers the rounding of the factorisation
//     itself (Demmel's bound: floating-point Cholesky of M succeeds ⇒ M + ΔM ⪰ 0 with
//     ‖ΔM‖₂ ≤ γ_{n+1} tr M) and the rounding of forming M from products of small matrices.
//  2. The centre. c⁺ = A c + B u + L (y − C c − D u) is computed with a rounding error bounded
//     componentwise by `center_rounding_bound`; the true centre lies within that box of the
//     computed one, so the level is enlarged by `level_with_center_error` to keep the set an
//     outer bound: ‖x − ĉ‖_P ≤ ‖x − c‖_P + ‖c − ĉ‖_P ≤ √ρ + √λ_max(P) ‖d‖₂.
//
// Every level update is rounded upwards with `round_up`.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/sets/ellipsoid.hpp"

namespace setbound {

/// Normalisation of the homogeneous offline LMI (papers.md §1.1): LogDet (log det P ≥ 0, the
/// minimum steady-state volume; default), Ball (P ⪰ I), PaperTrace (tr P ≤ 1 as printed: an
/// *upper* bound, degenerate — kept only so the paper's behaviour can be reproduced).
enum class EllNormalization { LogDet = 0, Ball = 1, PaperTrace = 2 };

namespace ell_rounding {

inline constexpr double kEps = std::numeric_limits<double>::epsilon();

/// γ_k = k u / (1 − k u) with u = eps/2 (Higham), with a safety factor 2.
double gamma(Eigen::Index k);

/// x (1 + 4 eps): an upper bound of a quantity computed with a few roundings from x.
double round_up(double x);

/// A cheap guaranteed upper bound of λ_max(P) for P symmetric: the largest absolute row sum
/// (≥ the spectral radius), rounded up.
double lambda_max_upper(const Eigen::MatrixXd& P);

}  // namespace ell_rounding

/// True when the symmetric matrix M is certified positive semidefinite in exact arithmetic:
/// the Cholesky factorisation of M − δI succeeds with δ = γ_{n+1} tr|M|·(1 + relative_slack)
/// + absolute_slack. `relative_slack` covers the rounding made when M was formed from products
/// (pass a bound on that error relative to tr|M| if it is larger than a few γ_k); M must be
/// finite. A NaN anywhere gives false.
bool certify_psd(const Eigen::MatrixXd& M, double absolute_slack = 0.0, double relative_slack = 1e-12);

/// Componentwise bound d on |fl(c⁺) − c⁺| for c⁺ = A c + B u + L (y − C c − D u) computed the
/// obvious way (each product a dot product, then the sums).
Eigen::VectorXd center_rounding_bound(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                             const Eigen::MatrixXd& L, const Eigen::MatrixXd& C,
                                             const Eigen::MatrixXd& D, const Eigen::VectorXd& c,
                                             const Eigen::VectorXd& y, const Eigen::VectorXd& u);

/// The level ρ' such that E(P, ĉ, ρ') ⊇ E(P, c, ρ) whenever |c − ĉ| ≤ d componentwise:
/// ρ' = (√ρ + √λ_max(P) ‖d‖₂)², rounded up. lambda_max_upper must bound λ_max(P) from above
/// (ell_rounding::lambda_max_upper(P) does).
double level_with_center_error(double rho, double lambda_max_upper, const Eigen::VectorXd& d);

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/ellipsoidal/impl/common.ipp"
#endif
