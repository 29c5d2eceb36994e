// setbound — definitions of the functions declared in setbound/estimators/polytopic/exact_hull.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/polytopic/exact_hull.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE ExactHull exact_hull(const LinearSystem& sys, const Zonotope& x0, const Eigen::MatrixXd& Y,
                            const Eigen::MatrixXd& U, bool use_first_measurement) {
  if (sys.uncertain_A())
    throw InvalidArgumentError("exact_hull: needs a known A (with an interval A the consistent set is not a polytope)");
  const Eigen::Index n = sys.nx(), nw = sys.nw(), ny = sys.ny(), nu = sys.nu();
  if (x0.dimension() != n) throw DimensionError("x0: expected dimension " + std::to_string(n));
  if (Y.cols() != ny) throw DimensionError("y: expected " + std::to_string(ny) + " columns");
  // NaN entries are missing outputs (no constraint); ±inf is an error.
  for (Eigen::Index k = 0; k < Y.rows(); ++k)
    if (Y.row(k).array().isInf().any())
      throw NotFiniteError("y: row " + std::to_string(k) + " has an infinite entry; a reading must be finite "
                           "(NaN marks a missing one)");
  const Eigen::Index N = Y.rows();
  if (nu > 0) {
    require_shape(U, N, nu, "u");
    require_finite(U, "u");
  }
  const Eigen::Index m0 = x0.num_generators();
  const Eigen::Index nvar_max = m0 + N * nw;
  // x_k = const + Coef · v, v = [ξ, ω_0, …, ω_{N−1}].
  Eigen::VectorXd xc = x0.center();
  Eigen::MatrixXd xv = Eigen::MatrixXd::Zero(n, nvar_max);
  xv.leftCols(m0) = x0.generators();
  ExactHull out{Eigen::MatrixXd(N, n), Eigen::MatrixXd(N, n)};
  // Measurement rows collected so far: Cx_j + F ω_j = y_j − D u_j.
  std::vector<std::pair<lmi::LpRow, double>> eqs;
  for (Eigen::Index k = 0; k < N; ++k) {
    const Eigen::Index wk = m0 + k * nw;  // index of ω_k
    if (k > 0 || use_first_measurement) {
      const Eigen::VectorXd du = nu > 0 ? Eigen::VectorXd(sys.D() * U.row(k).transpose()) : Eigen::VectorXd::Zero(ny);
      const Eigen::MatrixXd Cx = sys.C() * xv;
      const Eigen::VectorXd rhs = Y.row(k).transpose() - du - sys.C() * xc;
      for (Eigen::Index i = 0; i < ny; ++i) {
        if (std::isnan(Y(k, i))) continue;  // missing: no constraint
        lmi::LpRow row;
        for (Eigen::Index v = 0; v < wk; ++v)
          if (Cx(i, v) != 0.0) row.emplace_back(static_cast<int>(v), Cx(i, v));
        for (Eigen::Index j = 0; j < nw; ++j)
          if (sys.F()(i, j) != 0.0) row.emplace_back(static_cast<int>(wk + j), sys.F()(i, j));
        if (row.empty()) continue;  // this output carries no information on the unknowns
        eqs.emplace_back(std::move(row), rhs(i));
      }
    }
    const int nvar = static_cast<int>(wk + nw);
    for (Eigen::Index i = 0; i < n; ++i)
      for (int sign : {-1, 1}) {
        lmi::LinearProgram lp(nvar);
        for (int v = 0; v < nvar; ++v) lp.add_bounds(v, -1.0, 1.0);
        for (const auto& [row, rhs] : eqs) lp.add_eq(row, rhs);
        Eigen::VectorXd obj = Eigen::VectorXd::Zero(nvar);
        obj.head(wk) = sign * xv.row(i).head(wk).transpose();  // x_k does not depend on ω_k
        lp.set_objective(obj);
        const lmi::SolveResult r = lp.solve();
        if (r.status == lmi::SolveStatus::Infeasible)
          throw InfeasibleError("exact_hull: the measurements up to step " + std::to_string(k) +
                                " are inconsistent with the model and the bounds");
        if (r.status != lmi::SolveStatus::Optimal && r.status != lmi::SolveStatus::Inaccurate)
          throw NumericalError("exact_hull: LP at step " + std::to_string(k) + " ended with status " +
                               lmi::status_name(r.status));
        const double value = xc(i) + sign * r.objective;
        (sign > 0 ? out.lower : out.upper)(k, i) = value;  // min x_i: lower; min −x_i: upper
      }
    // Propagate to x_{k+1}.
    if (k + 1 < N) {
      xc = sys.A() * xc;
      if (nu > 0) xc += sys.B() * U.row(k).transpose();
      xv = sys.A() * xv;
      xv.block(0, wk, n, nw) += sys.E();
    }
  }
  return out;
}

}  // namespace setbound
