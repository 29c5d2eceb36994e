// setbound — definitions of the functions declared in setbound/thesis/eso_d.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/thesis/eso_d.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace thesis {

SETBOUND_INLINE void EsoDOptions::validate() const {
  hinf.validate();
  if (!gammas.empty()) hinf_detail::require_gamma_grid(gammas);
}

namespace eso_d_detail {

/// One pass of the ESO-D design from a γ search: the pass record and (A_o, E) of its gain.
SETBOUND_INLINE EllipsoidalSMPass make_pass(const Plant& plant, const Eigen::MatrixXd& Q,
                                            const hinf_detail::VertexGainResult& r, const HinfOptions& opt,
                                            Eigen::MatrixXd& Ao, Eigen::MatrixXd& E) {
  Ao = plant.A - r.L.front() * plant.C;
  E = plant.error_input(r.L.front());
  EllipsoidalSMPass p;
  p.Q_input = Q;
  p.Q_refined = Q;  // no log-det refinement in ESO-D
  p.P = r.P;
  p.L = r.L;
  p.g = r.g;
  p.gamma = ell_rounding::round_up(std::sqrt(r.g));
  // λ = λ_min(Q, P): the true smallest generalized eigenvalue (not eigs' 6 largest), rounded
  // down until Q − λP ⪰ 0 is certified, then until the dissipation LMI with Q := λP is.
  p.lambda_input = hinf_detail::lambda_min_certified(Q, r.P);
  p.lambda_refined = p.lambda_input;
  p.lambda = hinf_detail::certify_lambda(r.P, {Ao}, {E}, r.g, p.lambda_input, opt.certificate_slack);
  return p;
}

}  // namespace eso_d_detail

SETBOUND_INLINE EsoDDesign design_eso_d(const Plant& plant, const Eigen::VectorXd& wbar, const EsoDOptions& opt) {
  opt.validate();
  const Eigen::Index n = plant.nx(), m = plant.m();
  hinf_detail::require_wbar(wbar, m);
  EsoDDesign d;
  d.W = opt.w_covariance;
  if (d.W.size() == 0) d.W = uniform_covariance(-wbar, wbar);  // diag((2w̄)²/12) = diag(w̄²/3)
  require_shape(d.W, m, m, "w_covariance");
  require_finite(d.W, "w_covariance");
  require_symmetric(d.W, "w_covariance");
  hinf_detail::require_detectable(plant.A, plant.C, opt.hinf.detectability_tol, "A, C");
  const std::vector<double> grid = opt.gammas.empty() ? cora_gamma_grid() : opt.gammas;
  EllipsoidalSMDesign& sm = d.sm;
  sm.wbar = wbar;
  sm.wtw = ell_rounding::round_up(wbar.squaredNorm());

  // (a) Q = I: the first feasible γ of the grid.
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  hinf_detail::GammaSearch a = hinf_detail::first_feasible_gamma({plant.A}, {plant.F}, plant.C, plant.Z, I, grid,
                                                                 opt.hinf, "design_eso_d, step (a) (Q = I)");
  d.trials_a = a.trials;
  sm.design_time += a.gain.solve_time;
  Eigen::MatrixXd Ao, E;
  sm.passes.push_back(eso_d_detail::make_pass(plant, I, a.gain, opt.hinf, Ao, E));

  // (b) V ⪰ 0, A_o V A_oᵀ − V ⪯ −E W Eᵀ: the least-trace V is the Lyapunov solution (eso_d.hpp).
  const Eigen::MatrixXd EWE = E * d.W * E.transpose();
  Eigen::MatrixXd V = hinf_detail::discrete_lyapunov(Ao, EWE);
  const auto well_conditioned = [](const Eigen::MatrixXd& M) {
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M, Eigen::EigenvaluesOnly).eigenvalues();
    return ev.allFinite() && ev(0) > 1e-10 * std::max(ev(ev.size() - 1), 0.0) && ev(0) > 0;
  };
  if (!well_conditioned(V)) {
    // (A_o, E W^½) not controllable: the least-trace V is singular. Shift the right-hand side by
    // δI (V stays strictly feasible, Q = V⁻¹ finite); reported as lyapunov_shift.
    const double scale = std::max(EWE.trace() / static_cast<double>(n), EWE.cwiseAbs().maxCoeff());
    d.lyapunov_shift = 1e-6 * (scale > 0 ? scale : 1.0);
    V = hinf_detail::discrete_lyapunov(Ao, EWE + d.lyapunov_shift * I);
    if (!well_conditioned(V))
      throw NumericalError("design_eso_d, step (b): the Lyapunov LMI gave no positive definite V (A - LC of step (a) "
                           "is too close to instability); Q = V^-1 does not exist");
  }
  Eigen::LLT<Eigen::MatrixXd> llt(V);
  if (llt.info() != Eigen::Success)
    throw NumericalError("design_eso_d, step (b): V is not positive definite in floating point");
  Eigen::MatrixXd Q = llt.solve(I);
  symmetrize(Q);
  sm.V = V;

  // (c) LMI (2.35) with Q = V⁻¹, γ from the grid's start again.
  hinf_detail::GammaSearch c = hinf_detail::first_feasible_gamma({plant.A}, {plant.F}, plant.C, plant.Z, Q, grid,
                                                                 opt.hinf, "design_eso_d, step (c) (Q = V^-1)");
  d.trials_c = c.trials;
  sm.design_time += c.gain.solve_time;
  sm.passes.push_back(eso_d_detail::make_pass(plant, Q, c.gain, opt.hinf, Ao, E));
  d.Y = c.gain.U.front();
  if (!(sm.passes.back().lambda > 0 && sm.passes.back().lambda <= 1.0))
    throw NumericalError("design_eso_d: lambda = " + std::to_string(sm.passes.back().lambda) + " is outside (0, 1]");
  hinf_detail::finish_design(sm);
  return d;
}

}  // namespace thesis
}  // namespace setbound
