// setbound — definitions of the functions declared in setbound/estimators/zonotopic/designs.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/zonotopic/designs.hpp"
#include "setbound/core/config.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <optional>

#include "setbound/estimators/pradius.hpp"
#include "setbound/lmi/model.hpp"
#include "setbound/lmi/solver.hpp"

namespace setbound {

SETBOUND_INLINE ZonotopicGainDesign design_zonotopic_gain(const LinearSystem& sys, ZonotopicGainMethod method) {
  using lmi::AffineExpr;
  if (method != ZonotopicGainMethod::PRadE && method != ZonotopicGainMethod::NomG)
    throw InvalidArgumentError("method: unknown zonotopic gain design " + std::to_string(static_cast<int>(method)));
  if (sys.uncertain_A()) throw InvalidArgumentError("system: the gain designs need a known A");
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
  lmi::InteriorPointSolver solver(problem);
  struct Found {
    double s;
    Eigen::VectorXd x;
  };
  bool unbounded = false;
  auto feasible = [&](double s) -> std::optional<Found> {
    build(s);
    model.update(problem);
    const lmi::SolveResult& res = solver.solve();
    if (res.status == lmi::SolveStatus::Unbounded) unbounded = true;
    if (res.status != lmi::SolveStatus::Optimal && res.status != lmi::SolveStatus::Inaccurate) return std::nullopt;
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
    if (!best)
      throw InfeasibleError(std::string("design PRad-E: the LMI is infeasible for every beta in (0, 1)") +
                            (unbounded ? " (trace P unbounded)" : ""));
  } else {
    // Nom-G: μ = 1 is CORA's condition; the smallest feasible μ on (0, 1] to 1e-3.
    best = feasible(1.0);
    if (!best)
      throw InfeasibleError("design Nom-G: no gain L with (A − LC)ᵀP(A − LC) ⪯ P, P ⪰ I (is (C, A) detectable?)");
    double lo = 0.0, up = 1.0;
    while (up - lo > 1e-3) {
      const double mu = 0.5 * (lo + up);
      if (auto f = feasible(mu)) {
        best = f;
        up = mu;
      } else {
        lo = mu;
      }
    }
  }
  ZonotopicGainDesign d;
  d.beta = best->s;
  d.P = model.value(P, best->x);
  d.P = 0.5 * (d.P + d.P.transpose());
  d.Y = model.value(Y, best->x);
  Eigen::LLT<Eigen::MatrixXd> llt(d.P);
  if (llt.info() != Eigen::Success || !d.P.allFinite())
    throw NumericalError(std::string("design ") + who + ": P is not positive definite at the solution");
  d.gain = llt.solve(d.Y);
  if (!d.gain.allFinite()) throw NumericalError(std::string("design ") + who + ": the gain is not finite");
  d.objective = d.P.trace();
  d.lmi = main_lmi(d.beta).evaluate(best->x);
  return d;
}

}  // namespace setbound
