// setbound — definitions of setbound/estimators/ellipsoidal/bounding_ellipsoid.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/ellipsoidal/bounding_ellipsoid.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace detail {

/// 2 γ_k rounded up: the relative slack of an elementwise rounding bound computed in floating point.
SETBOUND_INLINE double be_slack(Eigen::Index k) { return ell_rounding::round_up(2.0 * ell_rounding::gamma(k)); }

SETBOUND_INLINE double be_round_down(double x) { return x >= 0 ? x * (1.0 - 4.0 * ell_rounding::kEps)
                                                              : x * (1.0 + 4.0 * ell_rounding::kEps); }

/// X = M⁻¹ (symmetrised, positive definite) and a bound r ≥ ‖I − X M‖∞ (the residual with its own
/// rounding bound). Every eigenvalue of X M lies in [1 − r, 1 + r], so X ⪯ (1 + r) M⁻¹ and,
/// when r < 1, X⁻¹ ⪯ M / (1 − r). Throws NumericalError naming `what` when M or X is not
/// numerically positive definite.
SETBOUND_INLINE double be_certified_inverse(const Eigen::MatrixXd& M, Eigen::MatrixXd& X, const char* what) {
  const Eigen::Index n = M.rows();
  Eigen::LLT<Eigen::MatrixXd> llt(M);
  if (llt.info() != Eigen::Success || !M.allFinite())
    throw NumericalError(std::string(what) + ": the ellipsoid's shape is not numerically positive definite");
  Eigen::MatrixXd Xi = llt.solve(Eigen::MatrixXd::Identity(n, n));
  X = 0.5 * (Xi + Xi.transpose());
  Eigen::LLT<Eigen::MatrixXd> lx(X);
  if (lx.info() != Eigen::Success || !X.allFinite())
    throw NumericalError(std::string(what) + ": the inverse of the ellipsoid's shape is not positive definite");
  Eigen::MatrixXd R = Eigen::MatrixXd::Identity(n, n) - X * M;
  Eigen::MatrixXd bound = R.cwiseAbs() + be_slack(n + 2) * (X.cwiseAbs() * M.cwiseAbs() +
                                                           Eigen::MatrixXd::Identity(n, n));
  return ell_rounding::round_up(bound.rowwise().sum().maxCoeff());
}

/// Largest eigenvalue of a symmetric PSD matrix, certified from above (φ² of ESO-A).
SETBOUND_INLINE double be_lambda_max_certified(const Eigen::MatrixXd& M) {
  const Eigen::Index n = M.rows();
  if (n == 0) return 0.0;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (M + M.transpose()), Eigen::EigenvaluesOnly);
  double lam = std::max(es.eigenvalues().maxCoeff(), 0.0);
  const double scale = std::max(M.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  for (double slack = 1e-12; slack < 1.0; slack *= 16.0) {
    const double cand = ell_rounding::round_up(lam * (1.0 + slack) + slack * scale);
    Eigen::MatrixXd T = -M;
    T.diagonal().array() += cand;
    if (certify_psd(T)) return cand;
  }
  return ell_rounding::lambda_max_upper(M);
}

SETBOUND_INLINE void be_require_psd(const Eigen::MatrixXd& M, Eigen::Index n, const std::string& name) {
  require_shape(M, n, n, name);
  require_finite(M, name);
  require_symmetric(M, name);
  if (n == 0) return;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (M + M.transpose()), Eigen::EigenvaluesOnly);
  const double scale = std::max(1.0, M.cwiseAbs().maxCoeff());
  if (es.eigenvalues().minCoeff() < -1e-12 * scale)
    throw NotPositiveDefiniteError(name + ": matrix is not positive semidefinite (smallest eigenvalue " +
                                   std::to_string(es.eigenvalues().minCoeff()) + ")");
}

}  // namespace detail

SETBOUND_INLINE Eigen::MatrixXd enclosing_ellipsoid_shape(const Eigen::MatrixXd& G) {
  require_finite(G, "G");
  const Eigen::Index n = G.rows();
  Eigen::Index m = 0;
  for (Eigen::Index j = 0; j < G.cols(); ++j)
    if ((G.col(j).array() != 0.0).any()) ++m;
  Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(n, n);
  if (m == 0) return Q;
  const double md = static_cast<double>(m);
  Q = md * (G * G.transpose());
  symmetrize(Q);
  // Elementwise rounding of m G Gᵀ; its row sums on the diagonal make the result ⪰ the exact shape.
  const Eigen::MatrixXd err = detail::be_slack(G.cols() + 4) * md * (G.cwiseAbs() * G.cwiseAbs().transpose());
  for (Eigen::Index i = 0; i < n; ++i) {
    const double add = ell_rounding::round_up(err.row(i).sum() + 4.0 * ell_rounding::kEps * std::abs(Q(i, i)));
    Q(i, i) = ell_rounding::round_up(Q(i, i) + add);
  }
  if (!Q.allFinite()) throw NumericalError("G: the enclosing ellipsoid's shape m G Gᵀ overflows");
  return Q;
}

SETBOUND_INLINE BoundingEllipsoidEstimator::BoundingEllipsoidEstimator(LinearSystem sys, Eigen::MatrixXd QW,
                                                                       Eigen::MatrixXd QV, Eigen::VectorXd q0,
                                                                       Eigen::MatrixXd Q0, double rho0,
                                                                       BoundingEllipsoidOptions opt)
    : sys_(std::move(sys)), QW_(std::move(QW)), QV_(std::move(QV)), opt_(opt), q0_(std::move(q0)),
      Q0_(std::move(Q0)), rho0_(rho0) {
  const Eigen::Index n = sys_.nx();
  if (sys_.uncertain_A())
    throw InvalidArgumentError("system: an interval A is not supported by the bounding-ellipsoid estimator");
  if (opt_.rule != BoundingRule::Gollamudi && opt_.rule != BoundingRule::Liu)
    throw InvalidArgumentError("rule: expected Gollamudi (ESO-A) or Liu (ESO-B)");
  if (opt_.convention != Convention::Setbound && opt_.convention != Convention::Cora)
    throw InvalidArgumentError("convention: expected Setbound or Cora");
  if (!(opt_.step_cap > 0.0 && opt_.step_cap < 1.0))
    throw InvalidArgumentError("step_cap: expected a value in (0, 1), got " + std::to_string(opt_.step_cap));
  detail::require_length(q0_.size(), n, "x0");
  require_finite(q0_, "x0");
  require_shape(Q0_, n, n, "Q0");
  require_positive_definite(Q0_, "Q0");
  symmetrize(Q0_);  // symmetric within tolerance is accepted; the saved shapes must be exactly so
  require_finite(rho0_, "rho0");
  require_positive(rho0_, "rho0");
  init_noise();
  reset();
}

SETBOUND_INLINE BoundingEllipsoidEstimator::BoundingEllipsoidEstimator(LinearSystem sys, Eigen::MatrixXd QW,
                                                                       Eigen::MatrixXd QV, const Ellipsoid& x0,
                                                                       BoundingEllipsoidOptions opt)
    : sys_(std::move(sys)), QW_(std::move(QW)), QV_(std::move(QV)), opt_(opt) {
  const Eigen::Index n = sys_.nx();
  detail::require_length(x0.dimension(), n, "x0");
  if (x0.level() <= 0.0)
    throw InvalidArgumentError("x0: the initial ellipsoid must have a positive level");
  Eigen::MatrixXd Q;
  const double r = detail::be_certified_inverse(x0.shape(), Q, "x0");
  if (!(r < 0.5)) throw NumericalError("x0: the initial ellipsoid's shape is too ill-conditioned to invert");
  // Q⁻¹ ⪯ P/(1 − r): the level absorbs the inverse's rounding.
  const double rho = ell_rounding::round_up(x0.level() / detail::be_round_down(1.0 - r));
  *this = BoundingEllipsoidEstimator(sys_, QW_, QV_, x0.center(), Q, rho, opt);
}

SETBOUND_INLINE void BoundingEllipsoidEstimator::init_noise() {
  const Eigen::Index n = sys_.nx(), p = sys_.ny();
  if (QW_.size() == 0) {
    QW_ = enclosing_ellipsoid_shape(sys_.E());
  } else {
    detail::be_require_psd(QW_, n, "QW");
    symmetrize(QW_);
  }
  if (QV_.size() == 0 && p > 0) {
    QV_ = enclosing_ellipsoid_shape(sys_.F());
  } else {
    detail::be_require_psd(QV_, p, "QV");
    symmetrize(QV_);
  }
  wbar_ = std::sqrt(std::max(QW_.trace(), 0.0));
  if (opt_.rule == BoundingRule::Gollamudi) {
    if (opt_.convention == Convention::Cora) {
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(QV_, Eigen::EigenvaluesOnly);
      phi2_ = p > 0 ? std::max(es.eigenvalues().maxCoeff(), 0.0) : 0.0;  // φ = √λ_max = CORA's norm(V)
    } else {
      phi2_ = detail::be_lambda_max_certified(QV_);
    }
    r0_ = phi2_;
  } else {
    Eigen::LLT<Eigen::MatrixXd> llt(QV_);
    if (p > 0 && llt.info() != Eigen::Success)
      throw NotPositiveDefiniteError("QV: ESO-B (Liu 2016) needs a positive definite output noise shape");
    if (opt_.convention == Convention::Cora) {
      R_ = QV_.inverse();
      r0_ = 1.0;
    } else {
      const double r = detail::be_certified_inverse(QV_, R_, "QV");
      r0_ = ell_rounding::round_up(1.0 + r);  // R̂ ⪯ (1 + r) Q_V⁻¹
    }
    Eigen::LLT<Eigen::MatrixXd> lr(0.5 * (R_ + R_.transpose()));
    if (lr.info() != Eigen::Success) throw NumericalError("QV: its inverse is not numerically positive definite");
    Vbar_ = lr.matrixU();  // V̄ᵀV̄ = Q_V⁻¹ (CORA's chol(inv(V.Q)))
    rmax_ = ell_rounding::lambda_max_upper(R_);
  }
}

SETBOUND_INLINE void BoundingEllipsoidEstimator::reset() {
  q_ = q0_;
  q_out_ = q0_;
  k_ = 0;
  last_lambda_ = 0;
  last_inconsistent_ = false;
  out_inverse_ = false;
  W_out_.resize(0, 0);
  if (opt_.convention == Convention::Cora) {
    S_ = rho0_ == 1.0 ? Q0_ : Eigen::MatrixXd(rho0_ * Q0_);
    s_ = 0.3;  // CORA's initial σ² (spec §2.13)
    Q_out_ = S_;
    s_out_ = 1.0;
  } else {
    S_ = Q0_;
    s_ = rho0_;
    Q_out_ = Q0_;
    s_out_ = rho0_;
  }
}

SETBOUND_INLINE double BoundingEllipsoidEstimator::optimal_lambda(double s, double dd, double r0, double g,
                                                                  double cap) {
  // Gollamudi et al. 1996, Thm. 2: ν minimises the next σ²; no update when σ² + δᵀδ ≤ γ².
  if (!(s + dd > r0)) return 0.0;
  double nu;
  if (!(dd > 0.0)) {
    nu = cap;
  } else {
    const double beta = (r0 - s) / dd;
    if (std::abs(g - 1.0) <= 1e-8) {
      nu = 0.5 * (1.0 - beta);
    } else {
      const double omega = 1.0 + beta * (g - 1.0);
      nu = omega > 0.0 ? (1.0 - std::sqrt(g / omega)) / (1.0 - g) : cap;
    }
  }
  double lam = std::min(cap, nu);
  if (!std::isfinite(lam)) lam = std::min(cap, 0.5);
  if (lam <= 0.0) return 0.0;
  if (lam >= 1.0) lam = 0.5;  // any λ in (0, 1) is valid; ν ≥ 1 only arises from rounding
  return lam;
}

SETBOUND_INLINE void BoundingEllipsoidEstimator::step(const Eigen::Ref<const Eigen::VectorXd>& y,
                                                      const Eigen::Ref<const Eigen::VectorXd>& u) {
  detail::require_length(y.size(), sys_.ny(), "y");
  for (Eigen::Index i = 0; i < y.size(); ++i)
    if (!std::isfinite(y(i)))
      throw NotFiniteError("y: entry " + std::to_string(i) + " is " + std::to_string(y(i)) +
                           "; the bounding-ellipsoid estimator needs every output (no missing readings)");
  Eigen::VectorXd uu = u;
  if (sys_.nu() == 0 && uu.size() == 0) uu.resize(0);
  detail::require_length(uu.size(), sys_.nu(), "u");
  require_finite(uu, "u");
  // Work on a copy so that an error leaves the estimator unchanged.
  BoundingEllipsoidEstimator next = *this;
  if (opt_.convention == Convention::Cora) {
    next.step_cora(y, uu);
    // CORA's recursion has no guards: a level s <= 0 (ESO-B) makes the next prediction's step NaN.
    // Say so instead of carrying NaN into the state (which could then not be saved and restored).
    if (!next.S_.allFinite() || !next.q_.allFinite() || !std::isfinite(next.s_) || !std::isfinite(next.last_lambda_))
      throw NumericalError("convention cora: CORA's recursion broke down (a non-finite prediction or step; "
                           "e.g. ESO-B's level s <= 0)");
  } else {
    next.step_setbound(y, uu);
  }
  next.k_ = k_ + 1;
  *this = std::move(next);
}

SETBOUND_INLINE void BoundingEllipsoidEstimator::step_cora(const Eigen::VectorXd& y, const Eigen::VectorXd& u) {
  // CORA's ellipsoid/intersectStrip ('Gollamudi1996' / 'Liu2016') and priv_observe_ESO_A/B as
  // they are (spec §2.13, §2.14; file comment). Q = S_, σ² = s_.
  const Eigen::Index n = sys_.nx(), p = sys_.ny();
  const Eigen::MatrixXd& C = sys_.C();
  Eigen::MatrixXd Q = S_;
  Eigen::VectorXd c = q_;
  Eigen::VectorXd yt = y;
  if (sys_.nu() > 0) yt -= sys_.D() * u;
  const Eigen::VectorXd delta = yt - C * c;
  const double dd = delta.squaredNorm();
  double lambda = 0.0;
  if (opt_.rule == BoundingRule::Gollamudi) {
    const double phi = std::sqrt(phi2_);
    if (s_ + dd > phi) {  // sic: φ, not φ²
      const double alpha = opt_.step_cap;
      const Eigen::MatrixXd G = C * Q * C.transpose();
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(G);
      const double g = p > 0 ? svd.singularValues()(0) : 0.0;
      double nu;
      if ((delta.array().abs() <= 1e-8).all()) {
        nu = alpha;
      } else {
        const double beta = (phi - s_) / dd;
        if (std::abs(g - 1.0) <= 1e-8 || std::abs(g - 1.0) <= 1e-8 * std::min(std::abs(g), 1.0)) {
          nu = (1.0 - beta) / 2.0;
        } else {
          const double omega = 1.0 + beta * (g - 1.0);
          nu = omega > 0.0 ? 1.0 / (1.0 - g) * (1.0 - std::sqrt(g / omega)) : alpha;
        }
      }
      lambda = std::min(alpha, nu);
      c = c + lambda * Q * C.transpose() * delta;  // sic: the old shape
      const Eigen::MatrixXd Qtmp = (1.0 - lambda) * Eigen::MatrixXd::Identity(p, p) + lambda * G;
      const double s_new = 1.0 - lambda + lambda * phi * phi -
                           lambda * (1.0 - lambda) * delta.dot(Qtmp.inverse() * delta);
      const Eigen::MatrixXd invQ = (1.0 - lambda) * Q.inverse() + lambda * (C.transpose() * C);
      Q = invQ.inverse() / s_new;  // sic: divided by σ²
      s_ = s_new;
    }
  } else {
    if (s_ + dd > 1.0) {  // sic: the unweighted δᵀδ
      const Eigen::MatrixXd G = Vbar_ * C * Q * C.transpose() * Vbar_.transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (G + G.transpose()), Eigen::EigenvaluesOnly);
      const double g = p > 0 ? es.eigenvalues()(p - 1) : 0.0;
      const double beta = (1.0 - s_) / dd;
      if (std::abs(g - 1.0) <= 1e-8 || std::abs(g - 1.0) <= 1e-8 * std::min(std::abs(g), 1.0)) {
        lambda = (1.0 - beta) / 2.0;
      } else {
        const double omega = 1.0 + beta * (g - 1.0);
        lambda = 1.0 / (1.0 - g) * (1.0 - std::sqrt(g / omega));  // sic: no guard, no cap
      }
      const Eigen::MatrixXd Qtmp = 1.0 / lambda * QV_ + 1.0 / (1.0 - lambda) * (C * Q * C.transpose());
      const Eigen::MatrixXd Qti = Qtmp.inverse();
      const Eigen::MatrixXd K = 1.0 / (1.0 - lambda) * Q * C.transpose() * Qti;
      s_ = (1.0 - lambda) * s_ + lambda - delta.dot(Qti * delta);
      Q = (1.0 - lambda) * (Eigen::MatrixXd::Identity(n, n) - K * C) * Q;  // sic: (1 − λ), eq. (24) as coded
      c = c + K * delta;
    }
  }
  if (!Q.allFinite() || !c.allFinite() || !std::isfinite(s_))
    throw NumericalError("convention cora: CORA's recursion broke down (non-finite shape; e.g. ESO-B's ω ≤ 0)");
  last_lambda_ = lambda;
  last_inconsistent_ = false;
  Q_out_ = Q;
  q_out_ = c;
  s_out_ = 1.0;
  // Prediction with u_k (post: A E + B u + c; then eq. (48) of Liu 2016).
  Eigen::MatrixXd Qh = sys_.A() * Q * sys_.A().transpose();
  symmetrize(Qh);
  Eigen::VectorXd qh = sys_.A() * c;
  if (sys_.nu() > 0) qh += sys_.B() * u;
  if (wbar_ > 0.0) {
    const double pp = wbar_ / (std::sqrt((s_ * Qh).trace()) + wbar_);
    S_ = std::pow(1.0 - pp, -1.0) * Qh + std::pow(s_ * pp, -1.0) * QW_;
  } else {
    S_ = Qh;
  }
  q_ = qh;
}

SETBOUND_INLINE void BoundingEllipsoidEstimator::step_setbound(const Eigen::VectorXd& y, const Eigen::VectorXd& u) {
  using ell_rounding::round_up;
  using detail::be_slack;
  using detail::be_round_down;
  const Eigen::Index n = sys_.nx(), p = sys_.ny(), nu = sys_.nu();
  const Eigen::MatrixXd& C = sys_.C();
  const Eigen::MatrixXd aC = C.cwiseAbs();
  const double u_eps = ell_rounding::kEps;

  // 1. The prediction {zᵀ S⁻¹ z ≤ s} in inverse form: W ⪯ (1 + r1) S⁻¹.
  Eigen::MatrixXd W;
  const double r1 = detail::be_certified_inverse(S_, W, "prediction");
  const double s1 = round_up(s_ * round_up(1.0 + r1));

  // 2. The measurement y − D u and its rounding; the noise level r₀ widened by it.
  Eigen::VectorXd yt = y, ey = Eigen::VectorXd::Zero(p);
  if (nu > 0) {
    yt -= sys_.D() * u;
    ey = be_slack(nu + 2) * (y.cwiseAbs() + sys_.D().cwiseAbs() * u.cwiseAbs());
  }
  const bool liu = opt_.rule == BoundingRule::Liu;
  const double eyn = round_up(ey.norm());
  double r0;
  if (liu)
    r0 = round_up(std::sqrt(r0_)) + round_up(eyn * round_up(std::sqrt(rmax_)));
  else
    r0 = round_up(std::sqrt(r0_)) + eyn;
  r0 = round_up(round_up(r0) * round_up(r0));

  // 3. λ (Gollamudi's ν; for Liu the same rule in the whitened outputs V̄ y).
  const Eigen::VectorXd delta = yt - C * q_;
  double lambda = 0.0;
  if (p > 0) {
    const Eigen::MatrixXd CS = C * S_;
    Eigen::MatrixXd G = CS * C.transpose();
    Eigen::VectorXd db = delta;
    if (liu) {
      G = Vbar_ * G * Vbar_.transpose();
      db = Vbar_ * delta;
    }
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (G + G.transpose()), Eigen::EigenvaluesOnly);
    const double g = std::max(es.eigenvalues()(p - 1), 0.0);
    lambda = optimal_lambda(s_, db.squaredNorm(), liu ? r0_ : phi2_, g, liu ? 1.0 : opt_.step_cap);
  }

  Eigen::MatrixXd Pp;  // shape used by the prediction, with level sp
  double sp;
  last_inconsistent_ = false;
  last_lambda_ = 0.0;
  if (lambda > 0.0) {
    // 4. W_t = a1 W + a2 Cᵀ R C, reduced by its rounding bound so that W_out ⪯ W_t exactly.
    const double a1 = 1.0 - lambda, a2 = lambda;
    const Eigen::MatrixXd Rm = liu ? R_ : Eigen::MatrixXd::Identity(p, p);
    const Eigen::MatrixXd aR = Rm.cwiseAbs();
    Eigen::MatrixXd Wt = a1 * W + a2 * (C.transpose() * (Rm * C));
    symmetrize(Wt);
    const Eigen::MatrixXd aCRC = aC.transpose() * (aR * aC);
    const Eigen::MatrixXd E = be_slack(2 * p + 8) * (a1 * W.cwiseAbs() + a2 * aCRC);
    Eigen::MatrixXd Wo = Wt;
    for (Eigen::Index i = 0; i < n; ++i)
      Wo(i, i) = be_round_down(Wt(i, i) - round_up(E.row(i).sum() + 4.0 * u_eps * std::abs(Wt(i, i))));
    Eigen::LLT<Eigen::MatrixXd> lo(Wo);
    if (lo.info() != Eigen::Success)
      throw NumericalError("correction: the corrected ellipsoid is numerically degenerate");
    // 5. The centre (any q̂ is valid: the level below accounts for it).
    const Eigen::VectorXd qh = q_ + lo.solve(a2 * (C.transpose() * (Rm * delta)));
    // 6. g = ∇f(q̂)/2 and f(q̂), each with a rounding bound.
    const Eigen::VectorXd d = qh - q_;
    const Eigen::VectorXd e = yt - C * qh;
    const Eigen::VectorXd ed = round_up(2.0 * u_eps) * d.cwiseAbs();
    const Eigen::VectorXd ee = be_slack(n + 2) * (yt.cwiseAbs() + aC * qh.cwiseAbs());
    const Eigen::MatrixXd aW = W.cwiseAbs();
    const Eigen::VectorXd gv = a1 * (W * d) - a2 * (C.transpose() * (Rm * e));
    const Eigen::VectorXd dm = d.cwiseAbs() + ed, em = e.cwiseAbs() + ee;
    const Eigen::VectorXd eg = be_slack(n + 2 * p + 8) * (a1 * (aW * dm) + a2 * (aC.transpose() * (aR * em))) +
                               a1 * (aW * ed) + a2 * (aC.transpose() * (aR * ee));
    const double fhat = a1 * d.dot(W * d) + a2 * e.dot(Rm * e);
    const double ferr = a1 * (be_slack(n + 4) * d.cwiseAbs().dot(aW * d.cwiseAbs()) +
                              2.0 * d.cwiseAbs().dot(aW * ed) + ed.dot(aW * ed)) +
                        a2 * (be_slack(p + 4) * e.cwiseAbs().dot(aR * e.cwiseAbs()) +
                              2.0 * e.cwiseAbs().dot(aR * ee) + ee.dot(aR * ee)) +
                        be_slack(4) * std::abs(fhat);
    const double f_lo = be_round_down(fhat - round_up(ferr));
    const double h = round_up(round_up(round_up(a1 * s1) * (1.0 + u_eps)) + round_up(a2 * r0));
    // 7. ‖g‖_{W_t⁻¹} ≤ ‖g‖₂ √λ_max(W_out⁻¹) and W_out⁻¹ ⪯ P̂ / (1 − r2).
    Eigen::MatrixXd Ph;
    const double r2 = detail::be_certified_inverse(Wo, Ph, "correction");
    if (!(r2 < 0.5)) throw NumericalError("correction: the corrected shape is too ill-conditioned to invert");
    const double inv_margin = be_round_down(1.0 - r2);
    const double lmax_inv = round_up(ell_rounding::lambda_max_upper(Ph) / inv_margin);
    const double a = round_up(round_up((gv.cwiseAbs() + eg).norm()) * round_up(std::sqrt(lmax_inv)));
    const double b = round_up(h - f_lo);
    const double disc = round_up(round_up(a * a) + b);
    if (!(disc > 0.0)) {
      // The measurement is inconsistent with the prediction (the intersection is empty): keep the
      // predicted set and say so.
      last_inconsistent_ = true;
      W_out_ = W;
      s_out_ = s1;
      q_out_ = q_;
      Pp = S_;
      sp = s_;
    } else {
      const double rl = round_up(a + round_up(std::sqrt(disc)));
      W_out_ = Wo;
      s_out_ = round_up(rl * rl);
      q_out_ = qh;
      last_lambda_ = lambda;
      Pp = Ph;
      sp = round_up(s_out_ / inv_margin);  // P̂⁻¹ ⪯ W_out/(1 − r2)
    }
  } else {
    W_out_ = W;
    s_out_ = s1;
    q_out_ = q_;
    Pp = S_;
    sp = s_;
  }
  out_inverse_ = true;

  // 8. Prediction: A E(q, sp P̂) ⊕ E(0, Q_W) ⊕ (the centre's rounding box) ⊆ E(q⁺, t S⁺),
  //    S⁺ = (sp/t) A P̂ Aᵀ/b1 + Q_W/(t b2) + n diag(d²)/(t b3), b1 + b2 + b3 ≤ 1, b2 = Liu's
  //    trace-optimal p. t = sp (the papers: σ² unchanged by the prediction) while σ² stays within
  //    [1e-6, 1e6]; outside, σ² is folded into the shape (t = 1; the set is the same): left alone,
  //    σ² can drift to 0 while P grows, the step λ ~ 1/λ_max(C P Cᵀ) vanishes and the numbers
  //    overflow (an 8-state campaign case after 1284 steps). CORA renormalises at every step, but
  //    divides the shape by σ² instead of multiplying it (spec §2.13).
  const Eigen::MatrixXd& A = sys_.A();
  const Eigen::MatrixXd aA = A.cwiseAbs();
  const double t = (sp >= 1e-6 && sp <= 1e6) ? sp : 1.0;
  const double st = t == sp ? 1.0 : sp;  // sp / t, exact in both cases
  Eigen::MatrixXd Ah = A * (st * Pp) * A.transpose();
  symmetrize(Ah);
  Eigen::VectorXd qn = A * q_out_;
  Eigen::VectorXd dc = aA * q_out_.cwiseAbs();
  if (nu > 0) {
    qn += sys_.B() * u;
    dc += sys_.B().cwiseAbs() * u.cwiseAbs();
  }
  dc = be_slack(n + nu + 2) * dc;
  const double pw = wbar_ > 0.0 ? wbar_ / (std::sqrt(t * std::max(Ah.trace(), 0.0)) + wbar_) : 0.0;
  const double b3 = dc.maxCoeff() > 0.0 ? 1e-12 : 0.0;
  const double b1 = (1.0 - pw - b3) * (1.0 - 4.0 * u_eps);
  Eigen::MatrixXd Sn = Ah / b1;
  Eigen::MatrixXd Eb = be_slack(2 * n + 8) * ((aA * (st * Pp.cwiseAbs()) * aA.transpose()) / b1);
  if (pw > 0.0) {
    const double f = 1.0 / (t * pw);
    Sn += f * QW_;
    Eb += be_slack(8) * f * QW_.cwiseAbs();
  }
  if (b3 > 0.0) {
    const double f = static_cast<double>(n) / (t * b3);
    const Eigen::VectorXd d2 = (f * dc.cwiseProduct(dc)).eval();
    Sn.diagonal() += d2;
    Eb.diagonal() += be_slack(8) * d2;
  }
  symmetrize(Sn);
  for (Eigen::Index i = 0; i < n; ++i)
    Sn(i, i) = round_up(Sn(i, i) + round_up(Eb.row(i).sum() + 4.0 * u_eps * std::abs(Sn(i, i))));
  if (!Sn.allFinite())
    throw NumericalError("prediction: the predicted ellipsoid is not finite");
  Eigen::LLT<Eigen::MatrixXd> ls(Sn);
  if (ls.info() != Eigen::Success)
    throw NumericalError("prediction: the predicted ellipsoid is degenerate (A singular with Q_W singular?)");
  S_ = Sn;
  q_ = qn;
  s_ = t;
}

SETBOUND_INLINE Eigen::MatrixXd BoundingEllipsoidEstimator::shape() const {
  if (!out_inverse_) return Q_out_ * s_out_;
  Eigen::MatrixXd X;
  const double r = detail::be_certified_inverse(W_out_, X, "shape");
  // X⁻¹ ⪯ W/(1 − r): shape s X/(1 − r) contains the set.
  return X * ell_rounding::round_up(s_out_ / detail::be_round_down(1.0 - std::min(r, 0.5)));
}

SETBOUND_INLINE Ellipsoid BoundingEllipsoidEstimator::ellipsoid() const {
  if (out_inverse_) return Ellipsoid(W_out_, q_out_, s_out_);
  // Shape form (the initial set, or CORA's convention): W ⪯ (1 + r) Q⁻¹.
  Eigen::MatrixXd W;
  const double r = detail::be_certified_inverse(Q_out_, W, "shape");
  const double level = opt_.convention == Convention::Cora
                           ? s_out_
                           : ell_rounding::round_up(s_out_ * ell_rounding::round_up(1.0 + r));
  return Ellipsoid(W, q_out_, level);
}

SETBOUND_INLINE BoundingBox BoundingEllipsoidEstimator::bounding_box() const {
  if (opt_.convention == Convention::Cora) {
    // CORA's interval(E): q ± √diag Q (spec §1.5).
    const Eigen::VectorXd r = (Q_out_.diagonal() * s_out_).cwiseMax(0.0).cwiseSqrt();
    return {q_out_ - r, q_out_ + r};
  }
  return ellipsoid().bounding_box();
}

SETBOUND_INLINE StateFingerprint BoundingEllipsoidEstimator::fingerprint() const {
  StateFingerprint f;
  f.add(sys_.A()).add(sys_.B()).add(sys_.C()).add(sys_.D()).add(QW_).add(QV_).add(q0_).add(Q0_).add(rho0_);
  f.add_int(static_cast<int>(opt_.rule)).add_int(static_cast<int>(opt_.convention)).add(opt_.step_cap);
  return f;
}

SETBOUND_INLINE std::vector<double> BoundingEllipsoidEstimator::save_state() const {
  StateWriter w(StateKind::BoundingEllipsoid, fingerprint());
  w.count(k_).mat(S_).vec(q_).scalar(s_).flag(out_inverse_).mat(out_inverse_ ? W_out_ : Q_out_).vec(q_out_)
      .scalar(s_out_).scalar(last_lambda_).flag(last_inconsistent_);
  return w.finish();
}

SETBOUND_INLINE void BoundingEllipsoidEstimator::restore_state(const std::vector<double>& state) {
  struct Parsed {
    long long k;
    Eigen::MatrixXd S, M;
    Eigen::VectorXd q, qo;
    double s, so, lam;
    bool inv, inc;
  };
  Parsed t = guard_state_memory(StateKind::BoundingEllipsoid, [&] {
    const Eigen::Index n = sys_.nx();
    StateReader r(state, StateKind::BoundingEllipsoid, fingerprint());
    Parsed x;
    x.k = r.count("steps");
    x.S = r.mat(n, n, "prediction shape");
    x.q = r.vec(n, "prediction centre");
    x.s = r.scalar("prediction level");
    x.inv = r.flag("inverse form");
    x.M = r.mat(n, n, "set shape");
    x.qo = r.vec(n, "set centre");
    x.so = r.scalar("set level");
    x.lam = r.scalar("last lambda");
    x.inc = r.flag("last inconsistent");
    r.finish();
    // Symmetric to rounding, not bit for bit: CORA's convention keeps CORA's unsymmetrised products
    // (Q = (1 − λ)(I − K C) Q, inverses), and a saved state must restore exactly as it was.
    const auto symmetric = [](const Eigen::MatrixXd& X) {
      return (X - X.transpose()).cwiseAbs().maxCoeff() <= 1e-10 * X.cwiseAbs().maxCoeff();
    };
    if (!symmetric(x.S) || !symmetric(x.M)) r.fail("a shape is not symmetric");
    // CORA's recursion may drive its levels to 0 or below (ESO-B's s = (1 − λ)s + λ − δᵀQ⁻¹δ, no guard)
    // and go on stepping, so only setbound's convention can insist on positive levels.
    if (opt_.convention == Convention::Setbound && (!(x.s > 0) || !(x.so > 0))) r.fail("a level is not positive");
    return x;
  });
  k_ = static_cast<long>(t.k);
  S_.swap(t.S);
  q_.swap(t.q);
  s_ = t.s;
  out_inverse_ = t.inv;
  if (out_inverse_) {
    W_out_.swap(t.M);
    Q_out_ = Q0_;
  } else {
    Q_out_.swap(t.M);
    W_out_.resize(0, 0);
  }
  q_out_.swap(t.qo);
  s_out_ = t.so;
  last_lambda_ = t.lam;
  last_inconsistent_ = t.inc;
}

}  // namespace setbound
