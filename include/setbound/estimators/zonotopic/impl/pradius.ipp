// setbound — definitions of the functions declared in setbound/estimators/zonotopic/pradius.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/zonotopic/pradius.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace detail {

SETBOUND_INLINE double disturbance_psi(const Eigen::MatrixXd& E) {
  const Eigen::Index nw = E.cols();
  if (nw == 0) return 0.0;
  if (nw > 24) throw InvalidArgumentError("E: more than 24 disturbance columns; psi needs 2^(n_w-1) vertices");
  double best = 0.0;
  Eigen::VectorXd g(nw);
  for (unsigned long s = 0; s < (1ul << (nw - 1)); ++s) {
    for (Eigen::Index i = 0; i < nw; ++i) g(i) = (i + 1 < nw && ((s >> i) & 1ul)) ? -1.0 : 1.0;
    best = std::max(best, (E * g).squaredNorm());
  }
  return best;
}

SETBOUND_INLINE Eigen::MatrixXd compress_disturbance(const Eigen::MatrixXd& E) {
  if (E.cols() == 0) return E;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(E, Eigen::ComputeThinU);
  const Eigen::VectorXd& s = svd.singularValues();
  const double tol = 1e-12 * std::max(1.0, s.size() ? s(0) : 0.0);
  Eigen::Index r = 0;
  while (r < s.size() && s(r) > tol) ++r;
  return svd.matrixU().leftCols(r) * s.head(r).asDiagonal();
}

SETBOUND_INLINE PRadiusDesign design_pradius_best_order(const LinearSystem& sys, PRadiusOptions opt) {
  if (sys.ny() > 7) throw InvalidArgumentError("try_all_orders: n_y! orders are too many for n_y > 7");
  std::vector<Eigen::Index> order(static_cast<std::size_t>(sys.ny()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  opt.try_all_orders = false;
  PRadiusDesign best;
  bool found = false;
  std::string last_error;
  do {
    opt.strip_order = order;
    try {
      PRadiusDesign d = design_pradius(sys, opt);
      const double t = d.tau(order.back());
      if (!found || t > best.tau(best.strip_order.back())) best = std::move(d), found = true;
    } catch (const InfeasibleError& e) {
      last_error = e.what();
    }
  } while (std::next_permutation(order.begin(), order.end()));
  if (!found) throw InfeasibleError("design_pradius: infeasible for every strip order (" + last_error + ")");
  return best;
}

}  // namespace detail
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE PRadiusDesign design_pradius(const LinearSystem& sys, const PRadiusOptions& opt) {
  if (opt.try_all_orders && opt.approach == PRadiusApproach::Coupled) return detail::design_pradius_best_order(sys, opt);
  using lmi::AffineExpr;
  const Eigen::Index n = sys.nx(), ny = sys.ny();
  if (!(opt.beta_lo > 0 && opt.beta_lo < opt.beta_hi && opt.beta_hi < 1))
    throw InvalidArgumentError("beta_lo, beta_hi: need 0 < beta_lo < beta_hi < 1");
  std::vector<Eigen::Index> order = opt.strip_order;
  if (order.empty()) {
    order.resize(static_cast<std::size_t>(ny));
    std::iota(order.begin(), order.end(), Eigen::Index{0});
  }
  {
    std::vector<Eigen::Index> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (Eigen::Index i = 0; i < ny; ++i)
      if (static_cast<Eigen::Index>(sorted.size()) != ny || sorted[static_cast<std::size_t>(i)] != i)
        throw InvalidArgumentError("strip_order: must be a permutation of 0..n_y-1");
  }
  const std::vector<Eigen::MatrixXd> vertices = sys.A_vertices();
  const Eigen::MatrixXd Fw = detail::compress_disturbance(sys.E());
  const Eigen::Index r = Fw.cols();
  const double psi = detail::disturbance_psi(sys.E());

  PRadiusDesign d;
  d.approach = opt.approach;
  d.strip_order = order;
  d.lambdas = Eigen::MatrixXd::Zero(ny, n);
  d.P.assign(static_cast<std::size_t>(ny), Eigen::MatrixXd());
  d.beta = Eigen::VectorXd::Zero(ny);
  d.tau = Eigen::VectorXd::Zero(ny);
  d.psi = psi;

  for (std::size_t t = 0; t < order.size(); ++t) {
    const Eigen::Index o = order[t];
    const Eigen::VectorXd c = sys.C().row(o).transpose();
    // Earlier strips taken into account (approach 2), with K_{l+1..t−1} products.
    std::vector<Eigen::Index> prev;
    if (opt.approach == PRadiusApproach::Coupled) prev.assign(order.begin(), order.begin() + t);
    Eigen::MatrixXd K = Eigen::MatrixXd::Identity(n, n);  // κ_{t−1} ⋯ κ_0
    for (Eigen::Index l : prev)
      K = (Eigen::MatrixXd::Identity(n, n) - d.lambdas.row(l).transpose() * sys.C().row(l)) * K;
    // v_l = K_{l+1..t−1} φ_l λ_l for each earlier strip l.
    std::vector<Eigen::VectorXd> v;
    for (std::size_t a = 0; a < prev.size(); ++a) {
      Eigen::VectorXd vl = sys.output_noise_bound(prev[a]) * d.lambdas.row(prev[a]).transpose();
      for (std::size_t b = a + 1; b < prev.size(); ++b)
        vl = vl - d.lambdas.row(prev[b]).transpose() * sys.C().row(prev[b]).dot(vl);
      v.push_back(vl);
    }
    double normaliser = psi + std::pow(sys.output_noise_bound(o), 2);
    for (Eigen::Index l : prev) normaliser += std::pow(sys.output_noise_bound(l), 2);
    if (!(normaliser > 0))
      throw InvalidArgumentError("E, F: no disturbance and no noise on output " + std::to_string(o) +
                                 "; the P-radius design needs a bounded, non-zero uncertainty");
    const double phi = sys.output_noise_bound(o);

    lmi::Model model;
    const lmi::Var P = model.symmetric(static_cast<int>(n));
    const lmi::Var Y = model.full(static_cast<int>(n), 1);
    const lmi::Var tau = model.scalar();
    auto build = [&](double beta) {
      model.clear_constraints();
      const AffineExpr M = P - Eigen::MatrixXd(c) * Y.transpose();  // P − c Yᵀ
      const AffineExpr Mt = M.transpose();                            // P − Y cᵀ
      for (const Eigen::MatrixXd& G : vertices) {
        // Lower triangle, block rows: βP | F_wᵀF_w | φ_l² … | φ_j² | last row.
        std::vector<std::vector<AffineExpr>> rows;
        rows.push_back({beta * P});
        if (r > 0) rows.push_back({AffineExpr::zero(r, n), AffineExpr(Eigen::MatrixXd(Fw.transpose() * Fw))});
        auto zeros_before = [&](Eigen::Index rows_here) {
          std::vector<AffineExpr> z{AffineExpr::zero(rows_here, n)};
          if (r > 0) z.push_back(AffineExpr::zero(rows_here, r));
          return z;
        };
        for (std::size_t a = 0; a < prev.size(); ++a) {
          std::vector<AffineExpr> row = zeros_before(1);
          for (std::size_t b = 0; b < a; ++b) row.push_back(AffineExpr::zero(1, 1));
          row.push_back(AffineExpr(std::pow(sys.output_noise_bound(prev[a]), 2)));
          rows.push_back(row);
        }
        {
          std::vector<AffineExpr> row = zeros_before(1);
          for (std::size_t b = 0; b < prev.size(); ++b) row.push_back(AffineExpr::zero(1, 1));
          row.push_back(AffineExpr(phi * phi));
          rows.push_back(row);
        }
        std::vector<AffineExpr> last{Mt * Eigen::MatrixXd(K * G)};
        if (r > 0) last.push_back(Mt * Eigen::MatrixXd(K * Fw));
        for (const Eigen::VectorXd& vl : v) last.push_back(Mt * Eigen::MatrixXd(vl));
        last.push_back(phi * Y);
        last.push_back(P);
        rows.push_back(last);
        model.add_lmi(lmi::sym_block(rows));
      }
      model.add_lmi(((1.0 - beta) / normaliser) * P - tau * Eigen::MatrixXd::Identity(n, n));
      model.add_lmi(tau);
      model.maximize(tau);
    };
    build(0.5);
    lmi::LmiProblem problem = model.build();
    lmi::InteriorPointSolver solver(problem);
    Eigen::VectorXd last_x;
    auto neg_tau = [&](double beta) {
      build(beta);
      model.update(problem);
      const lmi::SolveResult& res = solver.solve();
      if (res.status != lmi::SolveStatus::Optimal && res.status != lmi::SolveStatus::Inaccurate)
        return std::numeric_limits<double>::infinity();
      last_x = res.x;
      return -model.scalar_value(tau, res.x);
    };
    const lmi::ScalarSearchResult best = lmi::minimize_scalar(neg_tau, opt.beta_lo, opt.beta_hi, opt.search);
    if (!best.found() || !(-best.value > 0))
      throw InfeasibleError("design_pradius: the P-radius LMI of output " + std::to_string(o) +
                            " is infeasible for every beta in (" + std::to_string(opt.beta_lo) + ", " +
                            std::to_string(opt.beta_hi) + ")");
    // Re-solve at the chosen β and read the design back.
    if (!std::isfinite(neg_tau(best.argmin)))
      throw NumericalError("design_pradius: the LMI of output " + std::to_string(o) +
                           " could not be re-solved at the chosen beta");
    const Eigen::VectorXd x = last_x;
    const Eigen::MatrixXd Pv = model.value(P, x);
    const Eigen::VectorXd Yv = model.value(Y, x);
    Eigen::LLT<Eigen::MatrixXd> llt(Pv);
    if (llt.info() != Eigen::Success) throw NumericalError("design_pradius: P is not positive definite");
    d.lambdas.row(o) = llt.solve(Yv).transpose();
    // The LMI's supremum can be τ = 0, approached with a singular P that ignores a mode no
    // gain of this strip can contract; the solver then returns a tiny positive τ. What the
    // design must deliver is a contracting closed loop κ_t K G for every vertex: check it.
    const Eigen::MatrixXd kappa = Eigen::MatrixXd::Identity(n, n) - d.lambdas.row(o).transpose() * c.transpose();
    for (const Eigen::MatrixXd& G : vertices) {
      const double rho = Eigen::EigenSolver<Eigen::MatrixXd>(kappa * K * G, false).eigenvalues().cwiseAbs().maxCoeff();
      if (!(rho < 1.0))
        throw InfeasibleError("design_pradius: no beta in (" + std::to_string(opt.beta_lo) + ", " +
                              std::to_string(opt.beta_hi) + ") gives a contracting gain for output " +
                              std::to_string(o) + " (the LMI optimum is tau = 0; closed-loop spectral radius " +
                              std::to_string(rho) + "). With approach 1 every output must detect the " +
                              "unstable modes on its own: try approach 2 or another strip order");
    }
    d.P[static_cast<std::size_t>(o)] = Pv;
    d.beta(o) = best.argmin;
    d.tau(o) = model.scalar_value(tau, x);
  }
  return d;
}

}  // namespace setbound
