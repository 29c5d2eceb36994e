// setbound — definitions of the functions declared in setbound/lmi/l1.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/lmi/l1.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace lmi {

SETBOUND_INLINE WeightedL1Result minimize_weighted_l1(const Eigen::MatrixXd& G, const Eigen::VectorXd& h,
                                              const Eigen::VectorXd& gamma, double tol,
                                              int max_iterations) {
  const Eigen::Index T0 = G.rows(), n = G.cols();
  if (h.size() != T0 || gamma.size() != T0)
    throw DimensionError("minimize_weighted_l1: G has " + std::to_string(T0) + " rows, h " +
                         std::to_string(h.size()) + " and gamma " + std::to_string(gamma.size()) + " entries");
  if (!G.allFinite() || !h.allFinite() || !gamma.allFinite() || (gamma.array() < 0).any())
    throw InvalidArgumentError("minimize_weighted_l1: G, h must be finite and gamma finite and >= 0");
  WeightedL1Result out;
  out.x = Eigen::VectorXd::Zero(n);
  // Keep the rows that matter, scaled so that max_i |g_ti| = 1 (γ_t carries the scale).
  Eigen::Index T = 0;
  for (Eigen::Index t = 0; t < T0; ++t)
    if (gamma(t) > 0 && G.row(t).cwiseAbs().maxCoeff() > 0) ++T;
  auto objective_at = [&](const Eigen::VectorXd& x) {
    return (gamma.array() * (G * x - h).array().abs()).sum();
  };
  if (T == 0 || n == 0) {
    out.converged = true;
    out.objective = objective_at(out.x);
    out.lower_bound = out.objective;
    return out;
  }
  Eigen::MatrixXd A(T, n);
  Eigen::VectorXd b(T), w(T);
  for (Eigen::Index t = 0, k = 0; t < T0; ++t) {
    const double s = G.row(t).cwiseAbs().maxCoeff();
    if (!(gamma(t) > 0 && s > 0)) continue;
    A.row(k) = G.row(t) / s;
    b(k) = h(t) / s;
    w(k) = gamma(t) * s;
    ++k;
  }
  // Weights of order one (the minimiser does not depend on a common factor).
  const double wscale = w.maxCoeff();
  w /= wscale;

  // Start: x = 0, p, q from the residual plus one, u = 0 (z_p = z_q = w).
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n), u = Eigen::VectorXd::Zero(T);
  Eigen::VectorXd p = (-b).cwiseMax(0.0).array() + 1.0, q = b.cwiseMax(0.0).array() + 1.0;
  Eigen::VectorXd zp(T), zq(T), r1(T), r2(n), r3(T), r4(T), D(T), rt(T), dx(n), du(T), dp(T), dq(T);
  Eigen::VectorXd dxa(n), dua(T), dpa(T), dqa(T);
  Eigen::MatrixXd K(n, n);
  Eigen::LLT<Eigen::MatrixXd> llt(n);
  double best = std::numeric_limits<double>::infinity();

  auto solve = [&](Eigen::VectorXd& ox, Eigen::VectorXd& ou, Eigen::VectorXd& op, Eigen::VectorXd& oq) {
    rt = r1.array() + r3.array() / zp.array() - r4.array() / zq.array();
    const Eigen::VectorXd Dinv = D.cwiseInverse();
    ox.noalias() = A.transpose() * Dinv.cwiseProduct(rt);
    ox -= r2;
    ox = llt.solve(ox);
    ou = (rt - A * ox).cwiseQuotient(D);
    op = (r3.array() - p.array() * ou.array()) / zp.array();
    oq = (r4.array() + q.array() * ou.array()) / zq.array();
  };
  auto max_step = [&](const Eigen::VectorXd& v, const Eigen::VectorXd& dv) {
    double a = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < v.size(); ++i)
      if (dv(i) < 0) a = std::min(a, -v(i) / dv(i));
    return a;
  };
  auto step_limit = [&](const Eigen::VectorXd& dpv, const Eigen::VectorXd& dqv, const Eigen::VectorXd& duv) {
    double a = std::min(max_step(p, dpv), max_step(q, dqv));
    a = std::min(a, max_step(zp, duv));
    a = std::min(a, max_step(zq, -duv));
    return a;
  };

  for (int it = 0; it < max_iterations; ++it) {
    zp = w + u;
    zq = w - u;
    r1 = b - (A * x - p + q);
    r2 = -(A.transpose() * u);
    const double gap = p.dot(zp) + q.dot(zq);
    const double mu = gap / static_cast<double>(2 * T);
    out.iterations = it;
    // Track the best x by its true objective (any x is a valid answer; this one is the best).
    const double fx = (w.array() * (A * x - b).array().abs()).sum();
    if (fx < best) {
      best = fx;
      out.x = x;
    }
    // Termination on the true objective: for |u| ≤ w (kept strictly by z_p, z_q > 0),
    // Σ w|Ax − b| ≥ bᵀu − (Aᵀu)ᵀx for every x (weak duality), so the gap below is certified up to
    // the dual residual r2 = −Aᵀu. The primal residual r1 is not used: rows with small weights let
    // p and q grow together, and their difference loses digits, while x stays exact.
    const double lower = b.dot(u) + r2.dot(x);
    if (r2.cwiseAbs().maxCoeff() <= 1e-9) {
      // relative to the objective itself (the weights were scaled to max 1, so an objective well
      // below 1 is common; max(1, ·) would make the test absolute there)
      out.relative_gap = std::max(0.0, best - lower) / std::max(std::abs(best), 1e-12);
      out.lower_bound = wscale * lower;
    }
    if (out.relative_gap <= tol) {
      out.converged = true;
      break;
    }
    if (!std::isfinite(gap)) break;
    D = p.cwiseQuotient(zp) + q.cwiseQuotient(zq);
    K.noalias() = A.transpose() * D.cwiseInverse().asDiagonal() * A;
    K.diagonal().array() += 1e-13 * std::max(1.0, K.diagonal().maxCoeff());
    llt.compute(K);
    if (llt.info() != Eigen::Success) break;
    // Predictor.
    r3 = -p.cwiseProduct(zp);
    r4 = -q.cwiseProduct(zq);
    solve(dxa, dua, dpa, dqa);
    const double aa = std::min(1.0, step_limit(dpa, dqa, dua));
    const double mu_aff = ((p + aa * dpa).dot(zp + aa * dua) + (q + aa * dqa).dot(zq - aa * dua)) / static_cast<double>(2 * T);
    const double sigma = std::pow(std::max(0.0, mu_aff) / mu, 3);
    // Corrector.
    r3 = (sigma * mu - p.array() * zp.array() - dpa.array() * dua.array()).matrix();
    r4 = (sigma * mu - q.array() * zq.array() + dqa.array() * dua.array()).matrix();
    solve(dx, du, dp, dq);
    const double alpha = std::min(1.0, 0.99 * step_limit(dp, dq, du));
    if (!(alpha > 0) || !dx.allFinite()) break;
    x += alpha * dx;
    u += alpha * du;
    p += alpha * dp;
    q += alpha * dq;
  }
  {
    const double fx = (w.array() * (A * x - b).array().abs()).sum();
    if (fx < best) {
      best = fx;
      out.x = x;
    }
  }
  out.objective = objective_at(out.x);
  return out;
}

}  // namespace lmi
}  // namespace setbound
