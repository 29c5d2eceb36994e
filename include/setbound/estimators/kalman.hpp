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
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>
#include <utility>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/state.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/ellipsoid.hpp"

namespace setbound {

namespace detail {

/// (M + Mᵀ)/2 into a new matrix (exactly symmetric, no aliasing).
inline Eigen::MatrixXd kalman_symmetrized(const Eigen::MatrixXd& M) {
  Eigen::MatrixXd S(M.rows(), M.cols());
  for (Eigen::Index j = 0; j < M.cols(); ++j)
    for (Eigen::Index i = j; i < M.rows(); ++i) S(i, j) = S(j, i) = 0.5 * (M(i, j) + M(j, i));
  return S;
}

/// Finite, symmetric, positive semidefinite (smallest eigenvalue ≥ −1e-12·max(1, ‖M‖_max)).
inline void require_covariance(const Eigen::MatrixXd& M, Eigen::Index n, const std::string& name) {
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

class KalmanFilter {
 public:
  /// mean0, cov0: x̂_{0|−1}, G_{0|−1} (cov0 positive semidefinite). omega_cov: W (n_ω × n_ω,
  /// positive semidefinite); empty means the identity. Throws NotPositiveDefiniteError naming
  /// "F" when F W Fᵀ is singular.
  KalmanFilter(LinearSystem sys, Eigen::VectorXd mean0, Eigen::MatrixXd cov0,
               Eigen::MatrixXd omega_cov = Eigen::MatrixXd())
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

  /// Restarts from x̂_{0|−1} = mean0, G_{0|−1} = cov0 (validated; on error nothing changes).
  void reset(Eigen::VectorXd mean0, Eigen::MatrixXd cov0) {
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

  /// Correction with y_k, then prediction to k+1 with u_k (see the file comment). On error the
  /// filter is unchanged.
  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
    const Eigen::Index n = sys_.nx();
    detail::require_length(y.size(), sys_.ny(), "y");
    require_finite(y, "y");
    detail::require_length(u.size(), sys_.nu(), "u");
    require_finite(u, "u");
    const Eigen::MatrixXd& C = sys_.C();
    // Correction.
    const Eigen::MatrixXd GCt = Gp_ * C.transpose();
    const Eigen::MatrixXd S = detail::kalman_symmetrized(C * GCt + R_);
    Eigen::LLT<Eigen::MatrixXd> sllt(S);
    if (sllt.info() != Eigen::Success)
      throw NumericalError("y: the innovation covariance C G C^T + F W F^T lost positive definiteness");
    Eigen::MatrixXd K = sllt.solve(GCt.transpose()).transpose();  // G Cᵀ S⁻¹
    Eigen::VectorXd innov = y - C * xp_;
    if (sys_.nu() > 0) innov -= sys_.D() * u;
    Eigen::VectorXd x = xp_ + K * innov;
    const Eigen::MatrixXd IKC = Eigen::MatrixXd::Identity(n, n) - K * C;
    Eigen::MatrixXd G = detail::kalman_symmetrized(IKC * Gp_ * IKC.transpose() + K * R_ * K.transpose());
    // Prediction.
    Eigen::VectorXd xp = Abar_ * x + J_ * y;
    if (sys_.nu() > 0) xp += Bbar_ * u;
    Eigen::MatrixXd Gp = detail::kalman_symmetrized(Abar_ * G * Abar_.transpose() + Qbar_);
    if (!x.allFinite() || !G.allFinite() || !xp.allFinite() || !Gp.allFinite())
      throw NumericalError("y: the Kalman recursion produced a non-finite value (overflow)");
    x_ = std::move(x);
    G_ = std::move(G);
    xp_ = std::move(xp);
    Gp_ = std::move(Gp);
    K_ = std::move(K);
    ++steps_;
  }

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
  BoundingBox box(double nsigma = 3.0) const {
    require_positive(nsigma, "nsigma");
    const Eigen::VectorXd half = nsigma * G_.diagonal().cwiseMax(0.0).cwiseSqrt();
    return {x_ - half, x_ + half};
  }

  /// Full mutable state (core/state.hpp): x̂_{k|k}, G_{k|k}, x̂_{k+1|k}, G_{k+1|k}, K_k, k.
  std::vector<double> save_state() const {
    StateWriter w(StateKind::KalmanFilter, fingerprint());
    w.count(steps_).vec(x_).mat(G_).vec(xp_).mat(Gp_).mat(K_);
    return w.finish();
  }
  /// Restores a state from save_state() (same system and omega_cov); throws
  /// InvalidArgumentError ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state) {
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
  StateFingerprint fingerprint() const {
    StateFingerprint f;
    f.add(sys_.A()).add(sys_.B()).add(sys_.C()).add(sys_.D()).add(sys_.E()).add(sys_.F()).add(W_);
    return f;
  }

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
