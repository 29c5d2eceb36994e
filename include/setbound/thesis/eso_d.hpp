// setbound — CORA's ESO-D design: the H∞ set-membership observer of Martinez, Loukkas, Meslem,
// "H∞ set-membership observer design for discrete-time LPV systems", Int. J. Control 93(10),
// 2020 (Alg. 1, LTI case; CORA's priv_observe_gain_ESO_D, spec cora_observers.md §2.16).
//
// The online observer is the thesis's (hinf_observer.hpp, EllipsoidalSMObserver: x̂⁺ = A_o x̂ +
// Bu + Ly, μ⁺ = (1 − λ)μ + λ, box x̂ ± ē∞√μ, ē∞ = sqrt(diag(c̄P⁻¹)), c̄ = γ²w̄ᵀw̄/λ) — CORA's skeleton
// P (eqs. 65–68) is that recursion. Only the offline design differs from Algorithm 2:
//
//  (a) Q = I: LMI (2.35) at the first γ of a grid (CORA: linspace(1, 50, 100)) with a
//      feasibility solution → P, Y, L = P⁻¹Y; A_o = A − LC, E = [F, −LZ];
//  (b) the Lyapunov LMI V ⪰ 0, A_o V A_oᵀ − V ⪯ −E W Eᵀ with W = diag(w̄²/3) (CORA: I/3, the
//      covariance of the uniform w on the unit box); Q = V⁻¹;
//  (c) LMI (2.35) with that Q, γ restarting at the grid's start → γ, P, Y, L;
//      λ = λ_min(Q, P), the smallest generalized eigenvalue.
//
// Choices where CORA's result is solver-dependent (and so not reproducible):
//  * (a), (c): each γ is a feasibility problem (no objective, in CORA and here). Ours is
//    lmi::find_feasible: a γ counts as infeasible only with a certificate of infeasibility; a γ
//    the solver does not decide (iteration limit, numerical trouble) is recorded as "not
//    solved" and the search goes on (CORA counts every YALMIP code but 1 as feasible, spec
//    §1.7). The point is the solver's first certified strictly feasible iterate (deterministic).
//  * (b): CORA gives no objective and uses YALMIP's default solver, so its V is whatever that
//    solver stops at. We take min trace V: every feasible V satisfies V ⪰ V* with V* the solution
//    of the Lyapunov equation A_o V* A_oᵀ − V* = −E W Eᵀ (D = V − V* has D − A_o D A_oᵀ ⪰ 0, so
//    D = Σ_k A_oᵏ(D − A_o D A_oᵀ)A_oᵀᵏ ⪰ 0), so the minimiser of the trace (of any monotone
//    objective) is V* itself: well defined, unique, computed in closed form
//    (hinf_detail::discrete_lyapunov, the thesis's covariance step (2.43)), and it gives the
//    largest Q = V⁻¹ of the feasible set in the Loewner order. When V* is singular or nearly so
//    ((A_o, E W^½) not controllable), V solves the equation with E W Eᵀ + δI, δ = 1e-6 ·
//    max(tr(E W Eᵀ)/n, ‖…‖ floor): still feasible (strictly), Q finite; δ is reported.
//  * λ: CORA takes the minimum of MATLAB's eigs(Q, P), which returns the 6 largest-magnitude
//    generalized eigenvalues — for n > 6 not the smallest. We take the true minimum (certified:
//    Q − λP ⪰ 0 and the dissipation inequality with Q := λP pass a Cholesky test); it is the value
//    the guarantee needs.
//  * The disturbance model is the plant's (F, Z, w̄: in setbound's CORA runner the generators of
//    W and V, |w_i| ≤ 1), not CORA's ellipsoid shape matrices used as generators (sic, §2.15).
//
// Everything the observer relies on is certified as in Algorithm 2 (hinf_observer.hpp): the
// dissipation LMI at the returned (P, L, g) and with Q := λP, c̄ and ē∞ rounded up.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "setbound/thesis/hinf_gain.hpp"
#include "setbound/thesis/hinf_observer.hpp"

namespace setbound::thesis {

struct EsoDOptions {
  HinfOptions hinf{};
  /// The γ grid of both searches (strictly increasing, > 0); empty: CORA's linspace(1, 50, 100).
  std::vector<double> gammas;
  /// Covariance of w in step (b) (m×m); empty: diag(w̄²/3) (uniform on [−w̄, w̄]; CORA: I/3).
  Eigen::MatrixXd w_covariance;
  void validate() const;
};

struct EsoDDesign {
  /// What EllipsoidalSMObserver takes. passes[0] = step (a) (Q_input = I), passes[1] = step (c)
  /// (Q_input = V⁻¹); no log-det refinement (Q_refined = Q_input); V = step (b)'s V.
  EllipsoidalSMDesign sm;
  std::vector<GammaTrial> trials_a, trials_c;  // every γ tried by searches (a) and (c)
  Eigen::MatrixXd Y;        // P L of step (c) (the LMI's variable)
  Eigen::MatrixXd W;        // the covariance used in step (b)
  double lyapunov_shift = 0;  // δ of step (b) (0: V is the Lyapunov solution itself)
};

/// The ESO-D design (steps (a)–(c) above) for `plant` and the 2-norm bound w̄ of w = (d, v).
/// Errors: NotDetectableError ((A, C) not detectable), InfeasibleError (LMI (2.35) infeasible
/// for every γ of the grid, at step (a) or (c), said which), NumericalError (some γ not solved:
/// iteration limit / numerical trouble, or a certificate failed), DimensionError /
/// NotFiniteError / InvalidArgumentError for bad w̄, W or γ grid.
EsoDDesign design_eso_d(const Plant& plant, const Eigen::VectorXd& wbar, const EsoDOptions& opt = {});

}  // namespace setbound::thesis

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/thesis/impl/eso_d.ipp"
#endif
