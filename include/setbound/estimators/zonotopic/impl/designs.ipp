// setbound — definitions of the functions declared in setbound/estimators/zonotopic/designs.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/zonotopic/designs.hpp"
#include "setbound/core/config.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "setbound/core/symmetric.hpp"
#include "setbound/estimators/zonotopic/pradius.hpp"
#include "setbound/lmi/classes.hpp"
#include "setbound/lmi/model.hpp"
#include "setbound/lmi/scalar_search.hpp"
#include "setbound/lmi/solver.hpp"
#include "setbound/sets/zonotope.hpp"

namespace setbound {

namespace detail {

/// The P-radius LMI of a strip weight Λ = P⁻¹Y applied to all strips at once (designs.hpp;
/// spec §2.7–§2.9), with the multipliers Dw, Dv of the disturbance and noise coordinates:
///   [ sP          0            0      ·  ]
///   [ 0           Dw           0      ·  ]  ⪰ 0   ⇔   ‖(I − ΛC)(Ae + E_w w) − ΛF_v v‖²_P
///   [ 0           0            Dv     ·  ]             ≤ s‖e‖²_P + wᵀDw w + vᵀDv v  for all e, w, v.
///   [ (P − YC)A   (P − YC)E_w  YF_v   P  ]
/// PRad-B: Dw = E_wᵀE_w, Dv = F_vᵀF_v; PRad-C: diagonal variables Γ, Ω; PRad-D: multiples of I.
/// Empty E_w or F_v drop their block row.
SETBOUND_INLINE lmi::AffineExpr strip_weight_lmi(const lmi::Var& P, const lmi::Var& Y, const Eigen::MatrixXd& A,
                                                 const Eigen::MatrixXd& Cs, const Eigen::MatrixXd& Ew,
                                                 const lmi::AffineExpr& Dw, const Eigen::MatrixXd& Fv,
                                                 const lmi::AffineExpr& Dv, double s) {
  using lmi::AffineExpr;
  const Eigen::Index n = A.rows();
  const AffineExpr K = P - Y * Cs;  // P(I − ΛC)
  std::vector<std::vector<AffineExpr>> rows;
  rows.push_back({s * P});
  std::vector<AffineExpr> last{K * A};
  if (Ew.cols() > 0) {
    rows.push_back({AffineExpr::zero(Ew.cols(), n), Dw});
    last.push_back(K * Ew);
  }
  if (Fv.cols() > 0) {
    std::vector<AffineExpr> r{AffineExpr::zero(Fv.cols(), n)};
    if (Ew.cols() > 0) r.push_back(AffineExpr::zero(Fv.cols(), Ew.cols()));
    r.push_back(Dv);
    rows.push_back(r);
    last.push_back(Y * Fv);
  }
  last.push_back(P);
  rows.push_back(last);
  return lmi::sym_block(rows);
}

/// d.P (symmetrised), d.Y and d.gain = P⁻¹Y of a design's solution x; the reason when that fails
/// (P not positive definite, a gain that is not finite), nullptr when it does not.
SETBOUND_INLINE const char* read_gain(const lmi::Model& model, const lmi::Var& P, const lmi::Var& Y,
                                      const Eigen::VectorXd& x, ZonotopicGainDesign& d) {
  d.P = model.value(P, x);
  symmetrize(d.P);
  d.Y = model.value(Y, x);
  Eigen::LLT<Eigen::MatrixXd> llt(d.P);
  if (llt.info() != Eigen::Success || !d.P.allFinite()) return "P is not positive definite at the solution";
  d.gain = llt.solve(d.Y);
  if (!d.gain.allFinite()) return "the gain is not finite";
  return nullptr;
}

/// CORA's PRad-B LMI (designs.hpp) for the outputs rows Cs (q × n), output noise Fv (q × r) and
/// ε; β by bisection on (0, 1) to 0.01, the last feasible solve kept.
SETBOUND_INLINE ZonotopicGainDesign prad_b_design(const LinearSystem& sys, const Eigen::MatrixXd& Cs,
                                                  const Eigen::MatrixXd& Fv, double eps, const std::string& who,
                                                  bool least_norm, const lmi::SolverOptions& solver_options) {
  using lmi::AffineExpr;
  const Eigen::Index n = sys.nx(), q = Cs.rows();
  const Eigen::MatrixXd& A = sys.A();
  const Eigen::MatrixXd Ew = compress_disturbance(sys.E());
  if (!(eps > 0))
    throw InvalidArgumentError("system: " + who + " needs a non-zero disturbance or noise bound (epsilon = 0)");
  lmi::Model model;
  const lmi::Var P = model.symmetric(static_cast<int>(n));
  const lmi::Var Y = model.full(static_cast<int>(n), static_cast<int>(q));
  const lmi::Var tau = model.scalar();
  const AffineExpr EwEw(Eigen::MatrixXd(Ew.transpose() * Ew)), FvFv(Eigen::MatrixXd(Fv.transpose() * Fv));
  auto main_lmi = [&](double beta) { return strip_weight_lmi(P, Y, A, Cs, Ew, EwEw, Fv, FvFv, beta); };
  auto build = [&](double beta) {
    model.clear_constraints();
    model.add_lmi(main_lmi(beta));
    model.add_lmi(P);
    model.add_lmi(((1.0 - beta) / eps) * P - tau * Eigen::MatrixXd::Identity(n, n));
    model.add_lmi(tau);
    model.maximize(tau);
  };
  build(0.5);
  lmi::LmiProblem problem = model.build();
  lmi::InteriorPointSolver solver(problem, solver_options);
  double lo = 0.0, up = 1.0, best_beta = -1.0;
  Eigen::VectorXd best_x;
  SolveTally tally;
  while (up - lo > 0.01) {
    const double beta = 0.5 * (lo + up);
    build(beta);
    model.update(problem);
    const lmi::SolveResult& res = solver.solve();
    if (tally.count(res, solver_options)) {
      best_beta = beta;
      best_x = res.x;
      lo = beta;
    } else {
      up = beta;  // infeasible or undecided (CORA counts undecided as feasible, spec §1.7; there is no point to keep)
    }
  }
  if (best_beta < 0) tally.fail("design " + who, "beta");
  if (least_norm) {
    // Only τ (a bound on λ_min(P)) is maximised, so the optimum is a face, and the gain components
    // of states the outputs cannot see are whatever the solver's end point says (spec §2.6: SDPT3
    // and our interior point disagree there). Second solve at the kept β: within 0.1 % of the
    // best τ, the Y of least norm (‖Y‖₂ ≤ t as [[t I, Y], [Yᵀ, t I]] ⪰ 0).
    const double tau_best = model.scalar_value(tau, best_x);
    lmi::Model second;
    const lmi::Var P2 = second.symmetric(static_cast<int>(n));
    const lmi::Var Y2 = second.full(static_cast<int>(n), static_cast<int>(q));
    const lmi::Var tau2 = second.scalar();
    const lmi::Var t = second.scalar();
    const AffineExpr second_lmi = strip_weight_lmi(P2, Y2, A, Cs, Ew, EwEw, Fv, FvFv, best_beta);
    second.add_lmi(second_lmi);
    second.add_lmi(P2);
    second.add_lmi(((1.0 - best_beta) / eps) * P2 - tau2 * Eigen::MatrixXd::Identity(n, n));
    second.add_lmi(tau2 - AffineExpr(Eigen::MatrixXd::Constant(1, 1, (1.0 - 1e-3) * tau_best)));
    second.add_lmi(lmi::sym_block({{t * Eigen::MatrixXd::Identity(n, n)},
                                   {AffineExpr(Y2).transpose(), t * Eigen::MatrixXd::Identity(q, q)}}));
    second.minimize(t);
    lmi::LmiProblem p2 = second.build();
    lmi::InteriorPointSolver s2(p2, solver_options);
    const lmi::SolveResult& r2 = s2.solve();
    if (r2.status == lmi::SolveStatus::Optimal || r2.status == lmi::SolveStatus::Inaccurate) {
      ZonotopicGainDesign d;
      d.beta = best_beta;
      d.objective = second.scalar_value(tau2, r2.x);
      if (read_gain(second, P2, Y2, r2.x, d) == nullptr) {
        d.lmi = second_lmi.evaluate(r2.x);
        return d;
      }
    }
    // the second solve failed: keep the first one's end point (below)
  }
  ZonotopicGainDesign d;
  d.beta = best_beta;
  d.objective = model.scalar_value(tau, best_x);
  if (const char* why = read_gain(model, P, Y, best_x, d)) throw NumericalError("design " + who + ": " + why);
  d.lmi = main_lmi(best_beta).evaluate(best_x);
  return d;
}

/// The spectral radius of the error map (I − ΛC)A of a weight applied to all strips at once. The
/// non-strict LMIs admit a P singular along a direction no output sees, with λ_min(P) ≈ 0 and a
/// gain that cannot make that direction contract; a strict certificate implies ρ ≤ √β < 1.
SETBOUND_INLINE void require_contracting_error_map(const LinearSystem& sys, const Eigen::MatrixXd& gain,
                                                   const std::string& who) {
  const Eigen::MatrixXd M = sys.A() - gain * (sys.C() * sys.A());
  const double rho = M.eigenvalues().cwiseAbs().maxCoeff();
  if (!(rho < 1.0))
    throw InfeasibleError("design " + who + ": the best weight leaves the error map (I - Lambda C) A with spectral radius " +
                          std::to_string(rho) + " >= 1, so no weight makes the error contract (is (C, A) detectable?)");
}

/// PRad-C and PRad-D (designs.hpp): the weight of largest λ_min(P) under strip_weight_lmi with
/// the invariance budget of the unit P-ball, the contraction s chosen by a scalar search.
SETBOUND_INLINE ZonotopicGainDesign wang_strip_weight_design(const LinearSystem& sys, bool prad_d,
                                                             const lmi::SolverOptions& solver_options) {
  using lmi::AffineExpr;
  const std::string who = prad_d ? "PRad-D" : "PRad-C";
  const Eigen::Index n = sys.nx(), p = sys.ny();
  const Eigen::MatrixXd& A = sys.A();
  // The non-zero columns of E and F themselves: the unit-box coordinates the diagonal multipliers
  // weigh one by one (compress_disturbance would mix them, and wᵀΓw ≤ trace Γ holds only in the
  // coordinates of the box).
  const Eigen::MatrixXd Ew = Zonotope(Eigen::VectorXd::Zero(sys.nx()), sys.E()).remove_zero_generators().generators();
  const Eigen::MatrixXd Fv = Zonotope(Eigen::VectorXd::Zero(sys.ny()), sys.F()).remove_zero_generators().generators();
  const Eigen::Index k = Ew.cols(), q = Fv.cols();
  if (k + q == 0)
    throw InvalidArgumentError("system: " + who + " needs a non-zero disturbance or noise bound (E = 0 and F = 0)");
  lmi::Model model;
  const lmi::Var P = model.symmetric(static_cast<int>(n));
  const lmi::Var Y = model.full(static_cast<int>(n), static_cast<int>(p));
  const lmi::Var tau = model.scalar();
  // PRad-C: Γ (k × k), Ω (q × q) diagonal, the paper's multipliers (CORA's G, O).
  const lmi::Var Gamma = !prad_d && k > 0 ? model.diagonal(static_cast<int>(k)) : lmi::Var();
  const lmi::Var Omega = !prad_d && q > 0 ? model.diagonal(static_cast<int>(q)) : lmi::Var();
  AffineExpr budget_used(0.0);
  for (Eigen::Index i = 0; i < k && !prad_d; ++i) budget_used += Gamma.block(i, i, 1, 1);
  for (Eigen::Index i = 0; i < q && !prad_d; ++i) budget_used += Omega.block(i, i, 1, 1);
  constexpr double kNoiseShare = 0.5;  // PRad-D: CORA's (and the paper's example) β = 1/2
  auto main_lmi = [&](double s) {
    if (!prad_d) return strip_weight_lmi(P, Y, A, sys.C(), Ew, Gamma, Fv, Omega, s);
    const AffineExpr Dw((1.0 - s) * kNoiseShare * Eigen::MatrixXd::Identity(k, k));
    const AffineExpr Dv((1.0 - s) * (1.0 - kNoiseShare) * Eigen::MatrixXd::Identity(q, q));
    return strip_weight_lmi(P, Y, A, sys.C(), Ew, Dw, Fv, Dv, s);
  };
  auto build = [&](double s) {
    model.clear_constraints();
    model.add_lmi(main_lmi(s));
    model.add_lmi(P - tau * Eigen::MatrixXd::Identity(n, n));
    // PRad-C: ‖e⁺‖²_P ≤ s‖e‖²_P + trace Γ + trace Ω ≤ 1 on the unit P-ball (|w_i|, |v_i| ≤ 1).
    if (!prad_d) model.add_lmi(AffineExpr(1.0 - s) - budget_used);
    model.maximize(tau);
  };
  build(0.5);
  lmi::LmiProblem problem = model.build();
  lmi::InteriorPointSolver solver(problem, solver_options);
  SolveTally tally;
  auto solve_at = [&](double s) -> std::optional<Eigen::VectorXd> {
    build(s);
    model.update(problem);
    const lmi::SolveResult& res = solver.solve();
    if (!tally.count(res, solver_options)) return std::nullopt;
    return res.x;
  };
  // The criterion is not monotone in s (papers.md §0.4): a larger s relaxes the decay but leaves
  // less budget (PRad-C) or noise weight (PRad-D) — CORA's bisection on feasibility would end
  // where λ_min(P) vanishes. Coarse grid on (0, 1), then NLopt in the best cell.
  lmi::ScalarSearchOptions search;
  search.grid_points = 9;
  search.max_evaluations = 16;
  search.xtol_rel = 1e-3;
  search.ftol_rel = 1e-6;
  // The solution of the best τ seen is kept (minimize_scalar's argmin is that point), so the
  // chosen contraction is not solved a second time.
  double best_tau = 0;
  Eigen::VectorXd best_x;
  const lmi::ScalarSearchResult found = lmi::minimize_scalar(
      [&](double s) {
        const std::optional<Eigen::VectorXd> x = solve_at(s);
        if (!x) return std::numeric_limits<double>::infinity();
        const double t = model.scalar_value(tau, *x);
        if (!(t > 0 && std::isfinite(t))) return std::numeric_limits<double>::infinity();
        if (t > best_tau) best_tau = t, best_x = *x;
        return -t;
      },
      0.0, 1.0, search);
  if (!found.found()) {
    if (tally.solved == 0) tally.fail("design " + who, "contraction");
    throw InfeasibleError("design " + who + ": the LMI has no solution with lambda_min(P) > 0 for any contraction in "
                          "(0, 1) (is (C, A) detectable?)");
  }
  ZonotopicGainDesign d;
  d.beta = found.argmin;
  d.objective = best_tau;
  if (const char* why = read_gain(model, P, Y, best_x, d)) throw NumericalError("design " + who + ": " + why);
  require_contracting_error_map(sys, d.gain, who);
  d.lmi = main_lmi(d.beta).evaluate(best_x);
  return d;
}

}  // namespace detail

SETBOUND_INLINE ZonotopicGainDesign design_zonotopic_gain(const LinearSystem& sys, ZonotopicGainMethod method,
                                                          const lmi::SolverOptions& solver_options) {
  using lmi::AffineExpr;
  const int m = static_cast<int>(method);
  if (m < 1 || m > 6) throw InvalidArgumentError("method: unknown zonotopic gain design " + std::to_string(m));
  solver_options.validate();
  if (sys.uncertain_A()) throw InvalidArgumentError("system: the gain designs need a known A");
  if (method == ZonotopicGainMethod::PRadC || method == ZonotopicGainMethod::PRadD)
    return detail::wang_strip_weight_design(sys, method == ZonotopicGainMethod::PRadD, solver_options);
  if (method == ZonotopicGainMethod::PRadB || method == ZonotopicGainMethod::PRadA) {
    // ε = ‖rs|E|‖₂ + σᵀσ with σ_i = Σ_j |F_ij| (spec §2.7: W's interval radius, not squared).
    const Eigen::VectorXd radW = sys.nw() > 0 ? Eigen::VectorXd(sys.E().cwiseAbs().rowwise().sum())
                                              : Eigen::VectorXd(Eigen::VectorXd::Zero(sys.nx()));
    const Eigen::VectorXd sigma = sys.nw() > 0 ? Eigen::VectorXd(sys.F().cwiseAbs().rowwise().sum())
                                               : Eigen::VectorXd(Eigen::VectorXd::Zero(sys.ny()));
    if (method == ZonotopicGainMethod::PRadB) {
      ZonotopicGainDesign d = detail::prad_b_design(sys, sys.C(), detail::compress_disturbance(sys.F()),
                                                    radW.norm() + sigma.squaredNorm(), "PRad-B", false, solver_options);
      detail::require_contracting_error_map(sys, d.gain, "PRad-B");
      return d;
    }
    // Each output's design alone (spec §2.6). The strips are applied one after the other, so the
    // error map of a step is Π_i (I − λ_i c_iᵀ) A; the single-output LMIs bound each factor's
    // P_i-radius but not the product. When the solver's end points compose to a map with a
    // spectral radius ≥ 1 (vehicle6: 263, the set overflows at step 126), every output is
    // designed again with the least-norm tie-break of prad_b_design (vehicle6: ρ = 0.993).
    auto design_all = [&](bool least_norm) {
      ZonotopicGainDesign all;
      all.gain = Eigen::MatrixXd::Zero(sys.nx(), sys.ny());
      for (Eigen::Index i = 0; i < sys.ny(); ++i) {
        // Output i alone, its noise the 1-D box of half-width σ_i (spec §2.6).
        const Eigen::MatrixXd Fi = Eigen::MatrixXd::Constant(1, sigma(i) > 0 ? 1 : 0, sigma(i));
        ZonotopicGainDesign d = detail::prad_b_design(sys, sys.C().row(i), Fi, radW.norm() + sigma(i) * sigma(i),
                                                      "PRad-A (output " + std::to_string(i) + ")", least_norm,
                                                      solver_options);
        all.gain.col(i) = d.gain;
        all.P = d.P;
        all.Y = d.Y;
        all.beta = d.beta;
        all.objective = d.objective;
        all.lmi = d.lmi;
      }
      return all;
    };
    auto composed_radius = [&](const Eigen::MatrixXd& gain) {
      Eigen::MatrixXd M = sys.A();
      for (Eigen::Index i = 0; i < sys.ny(); ++i) M -= gain.col(i) * (sys.C().row(i) * M);
      return M.eigenvalues().cwiseAbs().maxCoeff();
    };
    ZonotopicGainDesign all = design_all(false);
    if (sys.ny() > 1 && !(composed_radius(all.gain) < 1.0)) {
      ZonotopicGainDesign tied = design_all(true);
      if (composed_radius(tied.gain) < composed_radius(all.gain)) all = std::move(tied);
    }
    return all;
  }
  const Eigen::Index n = sys.nx(), ny = sys.ny();
  const Eigen::MatrixXd& A = sys.A();
  const Eigen::MatrixXd& C = sys.C();
  const bool prad_e = method == ZonotopicGainMethod::PRadE;
  const char* who = prad_e ? "PRad-E" : "Nom-G";

  lmi::Model model;
  const lmi::Var P = model.symmetric(static_cast<int>(n));
  const lmi::Var Y = model.full(static_cast<int>(n), static_cast<int>(ny));
  const AffineExpr PAYC = P * A - Y * C;
  const Eigen::MatrixXd Ew = detail::compress_disturbance(sys.E());
  const Eigen::MatrixXd Fv = detail::compress_disturbance(sys.F());
  if (prad_e && Ew.cols() < n)
    throw InfeasibleError("design PRad-E: trace P is unbounded unless the state disturbance spans the state space "
                          "(E has rank " + std::to_string(Ew.cols()) + " < n_x = " + std::to_string(n) + ")");

  auto main_lmi = [&](double s) -> AffineExpr {
    if (!prad_e) return lmi::sym_block({{s * P}, {PAYC, P}});
    std::vector<std::vector<AffineExpr>> rows;
    rows.push_back({s * P});
    rows.push_back({AffineExpr::zero(Ew.cols(), n), AffineExpr(Eigen::MatrixXd(Ew.transpose() * Ew))});
    std::vector<AffineExpr> last{PAYC, P * Ew};
    if (Fv.cols() > 0) {
      rows.push_back({AffineExpr::zero(Fv.cols(), n), AffineExpr::zero(Fv.cols(), Ew.cols()),
                      AffineExpr(Eigen::MatrixXd(Fv.transpose() * Fv))});
      last.push_back(Y * Fv);
    }
    last.push_back(P);
    rows.push_back(last);
    return lmi::sym_block(rows);
  };
  AffineExpr traceP = P.block(0, 0, 1, 1);
  for (Eigen::Index i = 1; i < n; ++i) traceP += P.block(i, i, 1, 1);
  auto build = [&](double s) {
    model.clear_constraints();
    model.add_lmi(main_lmi(s));
    if (prad_e) {
      model.add_lmi(P);
      model.maximize(traceP);
    } else {
      model.add_lmi(P - AffineExpr::identity(n));
      model.minimize(traceP);
    }
  };
  build(0.5);
  lmi::LmiProblem problem = model.build();
  lmi::InteriorPointSolver solver(problem, solver_options);
  struct Found {
    double s;
    Eigen::VectorXd x;
  };
  bool unbounded = false;
  detail::SolveTally tally;
  auto feasible = [&](double s) -> std::optional<Found> {
    build(s);
    model.update(problem);
    const lmi::SolveResult& res = solver.solve();
    if (res.status == lmi::SolveStatus::Unbounded) unbounded = true;
    if (!tally.count(res, solver_options)) return std::nullopt;
    return Found{s, res.x};
  };
  std::optional<Found> best;
  if (prad_e) {
    // CORA's bisection (spec §2.10): lo = 0, up = 1, halve while up − lo > 0.01; a larger β
    // relaxes the LMI. setbound keeps the last feasible solve.
    double lo = 0.0, up = 1.0;
    while (up - lo > 0.01) {
      const double beta = 0.5 * (lo + up);
      if (auto f = feasible(beta)) {
        best = f;
        lo = beta;
      } else {
        up = beta;
      }
    }
    if (!best && unbounded)
      throw InfeasibleError("design PRad-E: the LMI has no bounded solution for any beta in (0, 1) (trace P unbounded)");
    if (!best) tally.fail("design PRad-E", "beta");
  } else {
    // Nom-G: CORA's condition (μ = 1) defines a cone containing P = 0 (spec §2.11). setbound takes
    // the analytic centre of its slice P ⪰ I, trace P ≤ 10 t* (t* the least trace P in the slice,
    // found first): the maximiser of log det N + log det(P − I) + log(10 t* − trace P), a
    // deterministic point strictly inside.
    const std::optional<Found> least = feasible(1.0);  // build(): min trace P, P ⪰ I
    if (!least && tally.undecided > 0)
      throw NumericalError("design Nom-G: the least-trace LMI was not solved (" + tally.undecided_reason() + ")");
    if (!least)
      throw InfeasibleError("design Nom-G: no gain L with (A − LC)ᵀP(A − LC) ⪯ P, P ⪰ I (is (C, A) detectable?)");
    const double cap = 10.0 * model.value(P, least->x).trace();
    model.clear_constraints();
    const AffineExpr N = main_lmi(1.0);
    const AffineExpr PI = P - AffineExpr::identity(n);
    const AffineExpr room = AffineExpr(cap) - traceP;
    model.add_lmi(N);
    model.add_lmi(PI);
    model.add_lmi(room);
    model.add_logdet(
        lmi::sym_block({{N}, {AffineExpr::zero(n, 2 * n), PI}, {AffineExpr::zero(1, 2 * n), AffineExpr::zero(1, n), room}}));
    lmi::LmiProblem centre = model.build();
    const lmi::SolveResult res = lmi::solve_maxdet(centre, solver_options);
    if (res.status != lmi::SolveStatus::Optimal && res.status != lmi::SolveStatus::Inaccurate)
      throw NumericalError(std::string("design Nom-G: the analytic centre could not be computed (") +
                           lmi::status_name(res.status) + ", " + std::to_string(res.iterations) + " iterations: " +
                           (res.status == lmi::SolveStatus::MaxIterations
                                ? (res.solve_time >= solver_options.time_limit ? "it reached " + detail::SolveTally::limit_reached(res, solver_options)
                                                                               : std::string("the solver's iteration limit"))
                                : std::string("numerical trouble")) +
                           "; the solver options of design_zonotopic_gain (max_iterations, time_limit) raise the limits)");
    best = Found{1.0, res.x};
  }
  ZonotopicGainDesign d;
  d.beta = best->s;
  if (const char* why = detail::read_gain(model, P, Y, best->x, d))
    throw NumericalError(std::string("design ") + who + ": " + why);
  d.objective = d.P.trace();
  d.lmi = main_lmi(d.beta).evaluate(best->x);
  return d;
}

}  // namespace setbound
