// setbound — definitions of the functions declared in setbound/estimators/point/rts_smoother.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/point/rts_smoother.hpp"
#include "setbound/core/config.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <string>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/point/kalman.hpp"

namespace setbound {

namespace detail {

SETBOUND_INLINE Eigen::MatrixXd psd_pinv(const Eigen::MatrixXd& M) {
  const Eigen::Index n = M.rows();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(kalman_symmetrized(M));
  if (eig.info() != Eigen::Success) throw NumericalError("pinv: eigenvalue computation did not converge");
  const Eigen::VectorXd& l = eig.eigenvalues();
  const double lmax = n > 0 ? l.cwiseAbs().maxCoeff() : 0.0;
  const double tol = static_cast<double>(n) * lmax * std::numeric_limits<double>::epsilon();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (l(i) > tol) out.noalias() += (eig.eigenvectors().col(i) / l(i)) * eig.eigenvectors().col(i).transpose();
  return kalman_symmetrized(out);
}

}  // namespace detail

SETBOUND_INLINE RtsResult rts_smooth(const LinearSystem& system, const Eigen::VectorXd& x0, const Eigen::MatrixXd& P0,
                                     const Eigen::MatrixXd& Sigma_w, const Eigen::MatrixXd& Sigma_v,
                                     const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U, RtsOptions options) {
  using Mat = Eigen::MatrixXd;
  using Vec = Eigen::VectorXd;
  if (system.uncertain_A())
    throw InvalidArgumentError("system: the RTS smoother needs a known A (an interval [A] is not supported)");
  const Eigen::Index n = system.nx(), ny = system.ny(), nu = system.nu(), N = Y.rows();
  if (x0.size() != n)
    throw DimensionError("x0: expected length " + std::to_string(n) + ", got " + std::to_string(x0.size()));
  require_finite(x0, "x0");
  detail::require_covariance(P0, n, "P0");
  detail::require_covariance(Sigma_w, n, "Sigma_w");
  require_shape(Sigma_v, ny, ny, "Sigma_v");
  require_positive_definite(Sigma_v, "Sigma_v");
  if (ny > 0) {
    // The Kalman filter's own test (kalman.ipp), reported under this argument's name.
    Eigen::SelfAdjointEigenSolver<Mat> eig(detail::kalman_symmetrized(Sigma_v), Eigen::EigenvaluesOnly);
    const double rmax = eig.eigenvalues().cwiseAbs().maxCoeff();
    if (!(eig.eigenvalues()(0) > 1e-12 * rmax))
      throw NotPositiveDefiniteError("Sigma_v: the measurement noise covariance is singular to working precision "
                                     "(condition number above 1e12)");
  }
  if (Y.cols() != ny)
    throw DimensionError("y: expected " + std::to_string(ny) + " columns, got " + std::to_string(Y.cols()));
  if (nu > 0) {
    require_shape(U, N, nu, "u");
    require_finite(U, "u");
  }
  for (Eigen::Index k = 0; k < N; ++k) require_no_infinity(Y.row(k).transpose(), "y");
  RtsResult res{Mat(N, n), Mat(N, n), Mat(N, n), {}, {}};
  if (N == 0) return res;
  // The forward pass is the library's Kalman filter with ω = [w; v] (see the header).
  Mat E = Mat::Zero(n, n + ny), F = Mat::Zero(ny, n + ny), W = Mat::Zero(n + ny, n + ny);
  E.leftCols(n).setIdentity();
  F.rightCols(ny).setIdentity();
  W.topLeftCorner(n, n) = detail::kalman_symmetrized(Sigma_w);
  W.bottomRightCorner(ny, ny) = detail::kalman_symmetrized(Sigma_v);
  LinearSystem ks(system.A(), system.C(), E, F, nu > 0 ? system.B() : Mat(), nu > 0 ? system.D() : Mat());
  KalmanFilter kf(std::move(ks), x0, P0, W);
  std::vector<Mat> M(static_cast<std::size_t>(N));  // M[k] = M_{k+1} = predicted covariance after step k
  Mat xbar_next(N, n);                              // row k = x̄_{k+1}
  res.filtered_cov.resize(static_cast<std::size_t>(N));
  res.smoothed_cov.resize(static_cast<std::size_t>(N));
  const Vec no_input(0);
  const Vec missing = Vec::Constant(ny, std::numeric_limits<double>::quiet_NaN());
  for (Eigen::Index k = 0; k < N; ++k) {
    const Vec yk = (k == 0 && !options.use_first_measurement) ? missing : Vec(Y.row(k).transpose());
    if (nu > 0) kf.step(yk, U.row(k).transpose());
    else kf.step(yk, no_input);
    res.filtered.row(k) = kf.mean().transpose();
    res.filtered_cov[static_cast<std::size_t>(k)] = kf.covariance();
    xbar_next.row(k) = kf.predicted_mean().transpose();
    M[static_cast<std::size_t>(k)] = kf.predicted_covariance();
  }
  res.predicted.row(0) = x0.transpose();
  if (N > 1) res.predicted.bottomRows(N - 1) = xbar_next.topRows(N - 1);
  // Backward pass with M_{k+1} of each step (CORA uses the last one for every k, sic).
  res.smoothed.row(N - 1) = res.filtered.row(N - 1);
  res.smoothed_cov[static_cast<std::size_t>(N - 1)] = res.filtered_cov[static_cast<std::size_t>(N - 1)];
  const Mat At = system.A().transpose();
  for (Eigen::Index k = N - 2; k >= 0; --k) {
    const std::size_t ks_ = static_cast<std::size_t>(k);
    const Mat& P = res.filtered_cov[ks_];
    const Mat& Mk1 = M[ks_];
    const Mat J = P * At * detail::psd_pinv(Mk1);
    const Vec d = (res.smoothed.row(k + 1) - xbar_next.row(k)).transpose();
    res.smoothed.row(k) = res.filtered.row(k) + (J * d).transpose();
    res.smoothed_cov[ks_] =
        detail::kalman_symmetrized(P + J * (res.smoothed_cov[ks_ + 1] - Mk1) * J.transpose());
  }
  if (!res.smoothed.allFinite())
    throw NumericalError("the RTS smoother produced a non-finite value (overflow)");
  return res;
}

}  // namespace setbound
