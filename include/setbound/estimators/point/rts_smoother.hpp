// setbound — the Rauch–Tung–Striebel smoother (CORA's "Rauch-Tung-Striebel"; spec
// cora_observers.md §2.20). Point estimates, NOT guaranteed sets.
//
// Model x_{k+1} = A x_k + B u_k + w_k, y_k = C x_k + D u_k + v_k with w_k ~ N(0, Σ_w),
// v_k ~ N(0, Σ_v) white and independent, x_0 ~ N(x0, P0) (CORA: x₀ = the centre of R0 and
// P₁ = 0.33² G_R0 G_R0ᵀ, Σ_w = 0.33² G_W G_Wᵀ, Σ_v = 0.33² G_V G_Vᵀ: a zonotope's generators read
// as 3-sigma, "5-sigma" in CORA's comment). The system's E and F are not used.
//
// Forward pass: the library's KalmanFilter (estimators/point/kalman.hpp) on the model with ω = [w; v]
// (E = [I 0], F = [0 I], W = diag(Σ_w, Σ_v)), which is this textbook filter:
//     x̄_k = A x̂_{k−1} + B u_{k−1},  M_k = A P_{k−1} Aᵀ + Σ_w,
//     K_k = M_k Cᵀ (C M_k Cᵀ + Σ_v)⁻¹,  x̂_k = x̄_k + K_k (y_k − C x̄_k − D u_k),  P_k = (I − K_kC) M_k
// (P_k in Joseph form, the same matrix in exact arithmetic). Backward pass, per step:
//     J_k = P_k Aᵀ M_{k+1}⁺,  x^s_k = x̂_k + J_k (x^s_{k+1} − x̄_{k+1}),
//     P^s_k = P_k + J_k (P^s_{k+1} − M_{k+1}) J_kᵀ,   x^s_{N−1} = x̂_{N−1}.
//
// Time indexing: row k is x_k. use_first_measurement = true (the textbook, setbound's filters):
// x0, P0 is the prior of x_0 and y_0 corrects it. false (CORA's file): x̂_0 = x0, P_0 = P0 and y_0
// is not used (the forward loop starts at the second sample).
//
// Deviations from CORA's priv_observe_RauchTungStriebel.m (2023), which cannot run:
//   * it reads a non-existent `initialState` and the undefined n, q, timeSteps, B, D: here x0 and
//     P0 are arguments (the Python runner takes R0's centre and 0.33² G_R0 G_R0ᵀ; CORA's P₁ = 0);
//   * its backward pass uses the LAST forward M for every J_k (sic); here M_{k+1} of each step;
//   * it forms Σ = 0.33² (G G)ᵀ, equal to G Gᵀ only for a symmetric G: here the given Σ_w, Σ_v
//     (the runner forms 0.33² G Gᵀ);
//   * it never stores R{N}: here the last row is x̂_{N−1};
//   * K uses pinv(C M Cᵀ + Σ_v): here Σ_v must be positive definite (the Kalman filter's
//     requirement), so C M Cᵀ + Σ_v is positive definite and its pseudo-inverse is its inverse;
//     M_{k+1} may be singular (Σ_w and P_k singular), so J_k keeps the pseudo-inverse (MATLAB's
//     tolerance max(size)·eps(‖M‖₂));
//   * missing outputs (NaN entries of y) are allowed: the forward step corrects with the rows
//     present.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "setbound/core/linear_system.hpp"

namespace setbound {

struct RtsOptions {
  /// Correct x0 with y_0 (the textbook). false: CORA's indexing, x̂_0 = x0 and y_0 unused.
  bool use_first_measurement = true;
};

struct RtsResult {
  Eigen::MatrixXd smoothed;   ///< N × n_x, row k = x^s_k
  Eigen::MatrixXd filtered;   ///< N × n_x, row k = x̂_k (forward Kalman filter)
  Eigen::MatrixXd predicted;  ///< N × n_x, row k = x̄_k (row 0: x0)
  std::vector<Eigen::MatrixXd> smoothed_cov, filtered_cov;  ///< P^s_k, P_k (n_x × n_x each)
};

/// Smooths the record Y (N × n_y; NaN entries: missing outputs), U (N × n_u; empty when n_u = 0)
/// with the model A, B, C, D of `system` (a known A), x0 (n_x), P0 (n_x × n_x, positive
/// semidefinite), Σ_w (n_x × n_x, positive semidefinite) and Σ_v (n_y × n_y, positive definite).
/// Throws DimensionError / NotFiniteError / NotSymmetricError / NotPositiveDefiniteError naming
/// the argument.
RtsResult rts_smooth(const LinearSystem& system, const Eigen::VectorXd& x0, const Eigen::MatrixXd& P0,
                     const Eigen::MatrixXd& Sigma_w, const Eigen::MatrixXd& Sigma_v, const Eigen::MatrixXd& Y,
                     const Eigen::MatrixXd& U = Eigen::MatrixXd(), RtsOptions options = {});

namespace detail {
/// Pseudo-inverse of a symmetric positive semidefinite matrix (eigenvalues below
/// max(size)·eps(λ_max) are zero, MATLAB's pinv tolerance).
Eigen::MatrixXd psd_pinv(const Eigen::MatrixXd& M);
}  // namespace detail

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/point/impl/rts_smoother.ipp"
#endif
