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
inline double gamma(Eigen::Index k) {
  const double ku = static_cast<double>(k + 2) * (kEps / 2);
  return 2.0 * ku / (1.0 - ku);
}

/// x (1 + 4 eps): an upper bound of a quantity computed with a few roundings from x.
inline double round_up(double x) { return x >= 0 ? x * (1.0 + 4.0 * kEps) + std::numeric_limits<double>::denorm_min()
                                                 : x * (1.0 - 4.0 * kEps); }

/// A cheap guaranteed upper bound of λ_max(P) for P symmetric: the largest absolute row sum
/// (≥ the spectral radius), rounded up.
inline double lambda_max_upper(const Eigen::MatrixXd& P) {
  return round_up(P.cwiseAbs().rowwise().sum().maxCoeff() * (1.0 + gamma(P.cols())));
}

}  // namespace ell_rounding

/// True when the symmetric matrix M is certified positive semidefinite in exact arithmetic:
/// the Cholesky factorisation of M − δI succeeds with δ = γ_{n+1} tr|M|·(1 + relative_slack)
/// + absolute_slack. `relative_slack` covers the rounding made when M was formed from products
/// (pass a bound on that error relative to tr|M| if it is larger than a few γ_k); M must be
/// finite. A NaN anywhere gives false.
inline bool certify_psd(const Eigen::MatrixXd& M, double absolute_slack = 0.0, double relative_slack = 1e-12) {
  const Eigen::Index n = M.rows();
  if (n == 0) return true;
  if (M.cols() != n || !M.allFinite()) return false;
  const double tr = M.diagonal().cwiseAbs().sum();
  const double delta = ell_rounding::gamma(n + 1) * tr * 4.0 + relative_slack * tr + absolute_slack;
  Eigen::MatrixXd S = 0.5 * (M + M.transpose());
  S.diagonal().array() -= delta;
  Eigen::LLT<Eigen::MatrixXd> llt(S);
  return llt.info() == Eigen::Success;
}

/// Componentwise bound d on |fl(c⁺) − c⁺| for c⁺ = A c + B u + L (y − C c − D u) computed the
/// obvious way (each product a dot product, then the sums).
inline Eigen::VectorXd center_rounding_bound(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                             const Eigen::MatrixXd& L, const Eigen::MatrixXd& C,
                                             const Eigen::MatrixXd& D, const Eigen::VectorXd& c,
                                             const Eigen::VectorXd& y, const Eigen::VectorXd& u) {
  using ell_rounding::gamma;
  const Eigen::VectorXd ac = c.cwiseAbs(), au = u.cwiseAbs();
  // innovation e = y − C c − D u and its magnitude bound
  Eigen::VectorXd e_mag = y.cwiseAbs() + C.cwiseAbs() * ac;
  if (D.size() > 0 && u.size() > 0) e_mag += D.cwiseAbs() * au;
  const Eigen::Index k = A.cols() + (B.size() > 0 ? B.cols() : 0) + L.cols() + 4;
  Eigen::VectorXd mag = A.cwiseAbs() * ac + L.cwiseAbs() * e_mag;
  if (B.size() > 0 && u.size() > 0) mag += B.cwiseAbs() * au;
  return ell_rounding::round_up(2.0 * gamma(k)) * mag;
}

/// The level ρ' such that E(P, ĉ, ρ') ⊇ E(P, c, ρ) whenever |c − ĉ| ≤ d componentwise:
/// ρ' = (√ρ + √λ_max(P) ‖d‖₂)², rounded up. lambda_max_upper must bound λ_max(P) from above
/// (ell_rounding::lambda_max_upper(P) does).
inline double level_with_center_error(double rho, double lambda_max_upper, const Eigen::VectorXd& d) {
  using ell_rounding::round_up;
  const double dn = round_up(d.norm());
  const double s = round_up(std::sqrt(round_up(rho))) + round_up(std::sqrt(lambda_max_upper) * dn);
  return round_up(round_up(s) * round_up(s));
}

}  // namespace setbound
