// setbound — the Kalman filter used as the accuracy / cost baseline of [Merhy2017] (papers.md
// §2.3), on the library's system model
//
//     x_{k+1} = A x_k + B u_k + E ω_k,     y_k = C x_k + D u_k + F ω_k,     ω_k ~ N(0, W) white,
//     x_0 ~ N(x̂_{0|−1}, G_{0|−1}).
//
// [Merhy2017] writes the special case ω = [w; v], E = [E_w 0], F = [0 F_v], W = diag(G_w, G_v).
// Here one ω may drive state and output together, so the process noise E ω_k and the
// measurement noise F ω_k are correlated (cross-covariance E W Fᵀ) whenever E W Fᵀ ≠ 0.
//
// Correction with y_k (Joseph form, which keeps G symmetric positive semidefinite in floating
// point, §2.3 "Library: prefer Joseph form"):
//     S_k = C G_{k|k−1} Cᵀ + R,   R = F W Fᵀ,   K_k = G_{k|k−1} Cᵀ S_k⁻¹,
//     x̂_{k|k} = x̂_{k|k−1} + K_k (y_k − C x̂_{k|k−1} − D u_k),
//     G_{k|k} = (I − K_k C) G_{k|k−1} (I − K_k C)ᵀ + K_k R K_kᵀ.
// Prediction to k+1 with the decorrelated model: adding J (y_k − C x_k − D u_k − F ω_k) = 0 with
// J = E W Fᵀ R⁻¹,
//     x_{k+1} = (A − J C) x_k + (B − J D) u_k + J y_k + (E − J F) ω_k,
// where (E − J F) ω_k is uncorrelated with F ω_k (E W Fᵀ − J R = 0) and independent of x_k,
// hence of y_0..y_k (jointly Gaussian). So
//     x̂_{k+1|k} = (A − J C) x̂_{k|k} + (B − J D) u_k + J y_k,
//     G_{k+1|k} = (A − J C) G_{k|k} (A − J C)ᵀ + (E − J F) W (E − J F)ᵀ.
// With uncorrelated noise J = 0 and these are the usual equations of §2.3. R must be positive
// definite (every output noisy); a singular R is rejected (the filter would need a reduced-order
// form). When A is uncertain (A_rad ≠ 0) the filter uses mid[A]; it has no guarantee anyway.
//
// Time indexing (same as the set-membership filters): step(y_k, u_k) corrects with y_k — mean()
// and covariance() are then x̂_{k|k}, G_{k|k}, the estimate of x_k from y_0..y_k — and predicts
// to k+1 with u_k (predicted_mean() / predicted_covariance()). Before the first step mean() and
// covariance() are the prior x̂_{0|−1}, G_{0|−1}.
//
// Missing outputs (NaN entries of y, issue 24): the correction uses the rows present (C_S,
// R_SS) and the prediction decorrelates with those rows only (J_S = E W F_Sᵀ R_SS⁻¹); with no
// output the step is a pure prediction. ±inf is an error.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/state.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/measurement_check.hpp"
#include "setbound/sets/ellipsoid.hpp"

namespace setbound {

namespace detail {

/// (M + Mᵀ)/2 into a new matrix (exactly symmetric, no aliasing).
Eigen::MatrixXd kalman_symmetrized(const Eigen::MatrixXd& M);

/// Finite, symmetric, positive semidefinite (smallest eigenvalue ≥ −1e-12·max(1, ‖M‖_max)).
void require_covariance(const Eigen::MatrixXd& M, Eigen::Index n, const std::string& name);

}  // namespace detail

class KalmanFilter {
 public:
  /// mean0, cov0: x̂_{0|−1}, G_{0|−1} (cov0 positive semidefinite). omega_cov: W (n_ω × n_ω,
  /// positive semidefinite); empty means the identity. Throws NotPositiveDefiniteError naming
  /// "F" when F W Fᵀ is singular.
  KalmanFilter(LinearSystem sys, Eigen::VectorXd mean0, Eigen::MatrixXd cov0,
               Eigen::MatrixXd omega_cov = Eigen::MatrixXd());

  /// Restarts from x̂_{0|−1} = mean0, G_{0|−1} = cov0 (validated; on error nothing changes).
  void reset(Eigen::VectorXd mean0, Eigen::MatrixXd cov0);

  /// Correction with y_k (NaN entries: missing outputs), then prediction to k+1 with u_k (see
  /// the file comment). On error the filter is unchanged.
  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);

  /// x̂_{k|k} and G_{k|k} after step(y_k, u_k) (the prior before the first step).
  const Eigen::VectorXd& mean() const { return x_; }
  const Eigen::MatrixXd& covariance() const { return G_; }
  /// x̂_{k+1|k} and G_{k+1|k}.
  const Eigen::VectorXd& predicted_mean() const { return xp_; }
  const Eigen::MatrixXd& predicted_covariance() const { return Gp_; }
  /// K_k of the last correction (zero before the first step).
  const Eigen::MatrixXd& gain() const { return K_; }
  /// Decorrelation gain J = E W Fᵀ (F W Fᵀ)⁻¹ (zero when process and output noise are uncorrelated).
  const Eigen::MatrixXd& decorrelation_gain() const { return J_; }
  bool correlated_noise() const { return correlated_; }
  const Eigen::MatrixXd& omega_covariance() const { return W_; }
  const LinearSystem& system() const { return sys_; }
  long steps() const { return steps_; }

  /// mean ± nsigma·sqrt(diag G_{k|k}). NOT a guaranteed set: a Gaussian confidence box.
  BoundingBox box(double nsigma = 3.0) const;

  /// Full mutable state (core/state.hpp): x̂_{k|k}, G_{k|k}, x̂_{k+1|k}, G_{k+1|k}, K_k, k.
  std::vector<double> save_state() const;
  /// Restores a state from save_state() (same system and omega_cov); throws
  /// InvalidArgumentError ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

 private:
  LinearSystem sys_;
  Eigen::MatrixXd W_, R_, J_, Abar_, Bbar_, Qbar_;
  Eigen::LLT<Eigen::MatrixXd> Rllt_;
  bool correlated_ = false;
  Eigen::VectorXd x_, xp_;
  Eigen::MatrixXd G_, Gp_, K_;
  long steps_ = 0;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/point/impl/kalman.ipp"
#endif
