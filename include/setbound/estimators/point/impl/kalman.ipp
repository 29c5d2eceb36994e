// setbound — definitions of the functions declared in setbound/estimators/point/kalman.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/point/kalman.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace detail {

SETBOUND_INLINE Eigen::MatrixXd kalman_symmetrized(const Eigen::MatrixXd& M) {
  Eigen::MatrixXd S(M.rows(), M.cols());
  for (Eigen::Index j = 0; j < M.cols(); ++j)
    for (Eigen::Index i = j; i < M.rows(); ++i) S(i, j) = S(j, i) = 0.5 * (M(i, j) + M(j, i));
  return S;
}

SETBOUND_INLINE void require_covariance(const Eigen::MatrixXd& M, Eigen::Index n, const std::string& name) {
  require_shape(M, n, n, name);
  require_finite(M, name);
  require_symmetric(M, name);
  if (n == 0) return;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(kalman_symmetrized(M), Eigen::EigenvaluesOnly);
  if (eig.info() != Eigen::Success) throw NumericalError(name + ": eigenvalue computation did not converge");
  const double lmin = eig.eigenvalues()(0);
  if (lmin < -1e-12 * std::max(1.0, M.cwiseAbs().maxCoeff()))
    throw NotPositiveDefiniteError(name + ": a covariance must be positive semidefinite (smallest eigenvalue " +
                                   std::to_string(lmin) + ")");
}

}  // namespace detail
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE KalmanFilter::KalmanFilter(LinearSystem sys, Eigen::VectorXd mean0, Eigen::MatrixXd cov0,
               Eigen::MatrixXd omega_cov)
    : sys_(std::move(sys)) {
  const Eigen::Index nw = sys_.nw();
  if (omega_cov.size() == 0) omega_cov = Eigen::MatrixXd::Identity(nw, nw);
  detail::require_covariance(omega_cov, nw, "omega_cov");
  W_ = detail::kalman_symmetrized(omega_cov);
  const Eigen::MatrixXd& C = sys_.C();
  const Eigen::MatrixXd& E = sys_.E();
  const Eigen::MatrixXd& F = sys_.F();
  R_ = detail::kalman_symmetrized(F * W_ * F.transpose());
  // R must be safely positive definite: Cholesky, and a condition check on its diagonal.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(R_, Eigen::EigenvaluesOnly);
  const double rmax = std::max(eig.eigenvalues().cwiseAbs().maxCoeff(), 0.0);
  if (!(eig.eigenvalues()(0) > 1e-12 * rmax) || !(rmax > 0))
    throw NotPositiveDefiniteError(
        "F: the output noise covariance F W F^T is singular (an output without noise, or outputs "
        "driven by fewer independent noises than there are outputs); the Kalman filter needs it "
        "positive definite");
  Rllt_.compute(R_);
  if (Rllt_.info() != Eigen::Success)
    throw NotPositiveDefiniteError("F: the output noise covariance F W F^T is not positive definite");
  // J = E W Fᵀ R⁻¹ (decorrelation gain), Ā = A − J C, B̄ = B − J D, Q̄ = (E − J F) W (E − J F)ᵀ.
  const Eigen::MatrixXd S_cross = E * W_ * F.transpose();  // n × ny
  J_ = Rllt_.solve(S_cross.transpose()).transpose();
  correlated_ = S_cross.cwiseAbs().maxCoeff() > 0.0;
  Abar_ = sys_.A() - J_ * C;
  Bbar_ = sys_.B() - J_ * sys_.D();
  const Eigen::MatrixXd Ebar = E - J_ * F;
  Qbar_ = detail::kalman_symmetrized(Ebar * W_ * Ebar.transpose());
  reset(std::move(mean0), std::move(cov0));
}

SETBOUND_INLINE void KalmanFilter::reset(Eigen::VectorXd mean0, Eigen::MatrixXd cov0) {
  const Eigen::Index n = sys_.nx();
  detail::require_length(mean0.size(), n, "mean0");
  require_finite(mean0, "mean0");
  detail::require_covariance(cov0, n, "cov0");
  xp_ = std::move(mean0);
  Gp_ = detail::kalman_symmetrized(cov0);
  x_ = xp_;
  G_ = Gp_;
  K_ = Eigen::MatrixXd::Zero(n, sys_.ny());
  steps_ = 0;
}

SETBOUND_INLINE void KalmanFilter::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  const Eigen::Index n = sys_.nx(), ny = sys_.ny();
  detail::require_length(y.size(), ny, "y");
  require_no_infinity(y, "y");
  detail::require_length(u.size(), sys_.nu(), "u");
  require_finite(u, "u");
  // Missing outputs (NaN): the textbook answer, the correction with the rows present, and the
  // decorrelation of the prediction (J) with those rows only (J_S = E W F_Sᵀ R_SS⁻¹).
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < ny; ++i)
    if (!std::isnan(y(i))) rows.push_back(i);
  const Eigen::Index m = static_cast<Eigen::Index>(rows.size());
  const bool all = m == ny;
  auto pick_rows = [&](const Eigen::MatrixXd& M) {
    Eigen::MatrixXd out(m, M.cols());
    for (Eigen::Index j = 0; j < m; ++j) out.row(j) = M.row(rows[static_cast<std::size_t>(j)]);
    return out;
  };
  const Eigen::MatrixXd C = all ? sys_.C() : pick_rows(sys_.C());
  Eigen::MatrixXd R = R_;
  if (!all) {
    const Eigen::MatrixXd Rt = pick_rows(R_).transpose();
    R = pick_rows(Rt);  // R_SS (R is symmetric)
  }
  Eigen::VectorXd ys(m);
  for (Eigen::Index j = 0; j < m; ++j) ys(j) = y(rows[static_cast<std::size_t>(j)]);
  const Eigen::MatrixXd D = sys_.nu() > 0 ? (all ? sys_.D() : pick_rows(sys_.D())) : Eigen::MatrixXd(m, 0);
  // Correction.
  Eigen::VectorXd x = xp_;
  Eigen::MatrixXd G = Gp_, K = Eigen::MatrixXd::Zero(n, ny);
  if (m > 0) {
    const Eigen::MatrixXd GCt = Gp_ * C.transpose();
    const Eigen::MatrixXd S = detail::kalman_symmetrized(C * GCt + R);
    Eigen::LLT<Eigen::MatrixXd> sllt(S);
    if (sllt.info() != Eigen::Success)
      throw NumericalError("y: the innovation covariance C G C^T + F W F^T lost positive definiteness");
    const Eigen::MatrixXd Ks = sllt.solve(GCt.transpose()).transpose();  // G Cᵀ S⁻¹
    Eigen::VectorXd innov = ys - C * xp_;
    if (sys_.nu() > 0) innov -= D * u;
    x = xp_ + Ks * innov;
    const Eigen::MatrixXd IKC = Eigen::MatrixXd::Identity(n, n) - Ks * C;
    G = detail::kalman_symmetrized(IKC * Gp_ * IKC.transpose() + Ks * R * Ks.transpose());
    for (Eigen::Index j = 0; j < m; ++j) K.col(rows[static_cast<std::size_t>(j)]) = Ks.col(j);
  }
  // Prediction.
  Eigen::VectorXd xp;
  Eigen::MatrixXd Gp;
  if (all) {
    xp = Abar_ * x + J_ * y;
    if (sys_.nu() > 0) xp += Bbar_ * u;
    Gp = detail::kalman_symmetrized(Abar_ * G * Abar_.transpose() + Qbar_);
  } else {
    const Eigen::MatrixXd Fs = pick_rows(sys_.F());
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, m);
    if (correlated_ && m > 0) J = R.llt().solve((sys_.E() * W_ * Fs.transpose()).transpose()).transpose();
    const Eigen::MatrixXd Abar = sys_.A() - J * C;
    const Eigen::MatrixXd Ebar = sys_.E() - J * Fs;
    xp = Abar * x + J * ys;
    if (sys_.nu() > 0) xp += (sys_.B() - J * D) * u;
    Gp = detail::kalman_symmetrized(Abar * G * Abar.transpose() + detail::kalman_symmetrized(Ebar * W_ * Ebar.transpose()));
  }
  if (!x.allFinite() || !G.allFinite() || !xp.allFinite() || !Gp.allFinite())
    throw NumericalError("y: the Kalman recursion produced a non-finite value (overflow)");
  x_ = std::move(x);
  G_ = std::move(G);
  xp_ = std::move(xp);
  Gp_ = std::move(Gp);
  K_ = std::move(K);
  ++steps_;
}

SETBOUND_INLINE BoundingBox KalmanFilter::box(double nsigma) const {
  require_positive(nsigma, "nsigma");
  const Eigen::VectorXd half = nsigma * G_.diagonal().cwiseMax(0.0).cwiseSqrt();
  return {x_ - half, x_ + half};
}

SETBOUND_INLINE std::vector<double> KalmanFilter::save_state() const {
  StateWriter w(StateKind::KalmanFilter, fingerprint());
  w.count(steps_).vec(x_).mat(G_).vec(xp_).mat(Gp_).mat(K_);
  return w.finish();
}

SETBOUND_INLINE void KalmanFilter::restore_state(const std::vector<double>& state) {
  struct Parsed {
    long long k;
    Eigen::VectorXd x, xp;
    Eigen::MatrixXd G, Gp, K;
  };
  Parsed q = guard_state_memory(StateKind::KalmanFilter, [&] {
    const Eigen::Index n = sys_.nx();
    StateReader r(state, StateKind::KalmanFilter, fingerprint());
    Parsed t;
    t.k = r.count("steps");
    t.x = r.vec(n, "mean");
    t.G = r.mat(n, n, "covariance");
    t.xp = r.vec(n, "predicted_mean");
    t.Gp = r.mat(n, n, "predicted_covariance");
    t.K = r.mat(n, sys_.ny(), "gain");
    r.finish();
    if (t.G != t.G.transpose() || t.Gp != t.Gp.transpose()) r.fail("covariance is not symmetric");
    // A covariance has a non-negative diagonal (a full PSD test would refuse states that
    // rounding left barely indefinite; the filter's own updates keep them symmetric only).
    if ((t.G.diagonal().array() < 0).any() || (t.Gp.diagonal().array() < 0).any())
      r.fail("a covariance has a negative variance on its diagonal");
    return t;
  });
  // Commit (swaps: nothing throws).
  x_.swap(q.x);
  G_.swap(q.G);
  xp_.swap(q.xp);
  Gp_.swap(q.Gp);
  K_.swap(q.K);
  steps_ = static_cast<long>(q.k);
}

SETBOUND_INLINE StateFingerprint KalmanFilter::fingerprint() const {
  StateFingerprint f;
  f.add(sys_.A()).add(sys_.B()).add(sys_.C()).add(sys_.D()).add(sys_.E()).add(sys_.F()).add(W_);
  return f;
}

}  // namespace setbound
