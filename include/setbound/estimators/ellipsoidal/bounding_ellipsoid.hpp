// setbound — optimal bounding ellipsoids with ellipsoidal noise: CORA's ESO-A and ESO-B
// (spec cora_observers.md §2.13, §2.14).
//
//   x_{k+1} = A x_k + B u_k + w_k,  w_k ∈ E(0, Q_W);   y_k = C x_k + D u_k + v_k,  v_k ∈ E(0, Q_V)
//
// with E(q, Q) = {q + Q^{1/2} b : ‖b‖₂ ≤ 1} (shape form; Q_W may be singular). The state set is
// kept as Gollamudi's pair (P, σ²): X = {x : (x − q)ᵀ P⁻¹ (x − q) ≤ σ²}.
//
//  * Prediction (Liu, Zhao, Wu, IET CTA 10(4), 2016, eqs. 21, 48): the Minkowski sum A X ⊕ E(Q_W)
//    is enclosed by P⁺ = A P Aᵀ/(1 − p) + Q_W/(σ² p) at level σ², with the trace-optimal
//    p = w̄/(√(σ² tr A P Aᵀ) + w̄), w̄ = √tr Q_W. The default convention folds σ² into the shape
//    (P⁺ ← σ² P⁺, σ² ← 1; the same set) only when σ² leaves [1e-6, 1e6]: left alone, σ² can drift
//    to 0 while P grows, until the step λ vanishes and the numbers overflow.
//  * Correction: for any λ ∈ [0, 1) the convex combination of the two quadratic constraints
//        (1 − λ)(x − q)ᵀP⁻¹(x − q) + λ (y − Cx)ᵀ R (y − Cx) ≤ (1 − λ)σ² + λ r₀
//    is an ellipsoid that contains X ∩ {measurement set}; λ only changes its size.
//    ESO-A (Gollamudi, Nagaraj, Kapoor, Huang, ISITA 1996, Thms. 1–2) bounds the noise by a ball,
//    ‖v‖ ≤ φ = √λ_max(Q_V): R = I, r₀ = φ²; λ = min(α, ν) with the σ²-minimising ν of Thm. 2.
//    ESO-B (Liu 2016, Thm. 3) uses the noise ellipsoid itself: R = Q_V⁻¹, r₀ = 1, λ = ν in the
//    whitened outputs V̄(y − Cx) (V̄ᵀV̄ = Q_V⁻¹), no cap.
//
// Time indexing (as every estimator of the library, and CORA's skeleton E of spec §1.3):
// step(y_k, u_k) corrects the prediction for x_k with y_k (the first step corrects X_0 with y_0),
// returns that set, then predicts x_{k+1} with u_k.
//
// Conventions (issue 22):
//  * Setbound (default): the papers' algorithm with the guarantee kept in floating point. Each
//    conversion between P and P⁻¹ is an inverse whose rounding is covered by a residual bound
//    (λ_max(Ŵ S) ≤ 1 + ‖I − Ŵ S‖∞, the residual evaluated with its own error bound); the
//    prediction shape is enlarged by the diagonal of its elementwise rounding bound (a
//    diagonally dominant, hence PSD, correction) and the centre's rounding enters as a third
//    Minkowski term; the corrected shape is reduced by its rounding bound, and the level is
//    taken from the exact quadratic at the computed centre: with z = x − q̂ and
//    f(x) = zᵀ W_t z + 2 zᵀ g + f(q̂) ≤ h,  ‖z‖_{W_t} ≤ a + √(a² + h − f(q̂)), a ≥ ‖g‖_{W_t⁻¹}
//    (g, f(q̂) and h evaluated with their rounding bounds). Reported sets are outer bounds.
//  * Cora: CORA's priv_observe_ESO_A/B and ellipsoid/intersectStrip as they are (spec §2.13,
//    §2.14: σ² starts at 0.3; ESO-A tests s + δᵀδ > φ (not φ²), caps the step at α = 1e-4, moves
//    the centre with the old shape and divides the new shape by σ²; ESO-B multiplies the new shape
//    by (1 − λ) and tests the unweighted δᵀδ). The reported set is E(q, Q) without σ². Not
//    guaranteed (spec §2.13: "containment is not established"); it reproduces CORA's numbers.
//
// Cost per step: O(n³ + n²p + p³) (two n × n inverses in the default convention, one in CORA's).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <string>
#include <vector>

#include "setbound/core/convention.hpp"
#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/state.hpp"
#include "setbound/core/symmetric.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/ellipsoidal/common.hpp"
#include "setbound/sets/ellipsoid.hpp"

namespace setbound {

/// Which correction: ESO-A (Gollamudi 1996, ball noise bound, capped step) or ESO-B (Liu 2016).
enum class BoundingRule { Gollamudi = 0, Liu = 1 };

struct BoundingEllipsoidOptions {
  BoundingRule rule = BoundingRule::Gollamudi;
  Convention convention = Convention::Setbound;
  /// Gollamudi's cap α on λ (ESO-A only; CORA uses 1e-4). In (0, 1).
  double step_cap = 1e-4;
};

/// Shape m G Gᵀ of an ellipsoid that encloses the zonotope {G b : ‖b‖∞ ≤ 1} (m = the number of
/// non-zero columns: ‖b‖₂² ≤ m), enlarged by the diagonal of its rounding bound so that it stays
/// an outer bound. This is CORA's `ellipsoid(Z)` with the norm bound λ = 1 (spec §1.6).
Eigen::MatrixXd enclosing_ellipsoid_shape(const Eigen::MatrixXd& G);

class BoundingEllipsoidEstimator {
 public:
  /// sys: A, B, C, D (E, F are used only when Q_W / Q_V are empty: then the disturbances E ω and
  /// F ω, ω ∈ B^{n_ω}, are enclosed separately by enclosing_ellipsoid_shape). Q_W: n_x × n_x
  /// symmetric PSD; Q_V: n_y × n_y symmetric, PSD for Gollamudi, PD for Liu. The initial set is
  /// {x : (x − q0)ᵀ Q0⁻¹ (x − q0) ≤ rho0} with Q0 PD (shape form). Messages name the argument.
  BoundingEllipsoidEstimator(LinearSystem sys, Eigen::MatrixXd QW, Eigen::MatrixXd QV, Eigen::VectorXd q0,
                             Eigen::MatrixXd Q0, double rho0, BoundingEllipsoidOptions opt = {});
  /// The initial set as a setbound ellipsoid E(P, c, ρ) = {(x − c)ᵀ P (x − c) ≤ ρ}; converted to
  /// shape form with a certified inverse (the level absorbs its rounding).
  BoundingEllipsoidEstimator(LinearSystem sys, Eigen::MatrixXd QW, Eigen::MatrixXd QV, const Ellipsoid& x0,
                             BoundingEllipsoidOptions opt = {});

  /// Corrects with y_k (finite, length n_y), returns through current(), then predicts with u_k.
  /// On error the estimator is unchanged.
  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);

  /// The set of the last step (the initial set before the first step), centre and shape form
  /// {(x − q)ᵀ Q⁻¹ (x − q) ≤ 1}.
  const Eigen::VectorXd& center() const { return q_out_; }
  Eigen::MatrixXd shape() const;
  /// The same set as a setbound Ellipsoid (default convention: exactly the guaranteed set).
  Ellipsoid ellipsoid() const;
  /// Interval hull q ± √diag Q (default convention: rounded outward).
  BoundingBox bounding_box() const;

  /// λ of the last correction (0: the measurement did not change the set), and whether the last
  /// measurement was found inconsistent with the predicted set (the set was then kept).
  double last_lambda() const { return last_lambda_; }
  bool last_inconsistent() const { return last_inconsistent_; }
  long steps() const { return k_; }
  const BoundingEllipsoidOptions& options() const { return opt_; }
  const LinearSystem& system() const { return sys_; }
  const Eigen::MatrixXd& QW() const { return QW_; }
  const Eigen::MatrixXd& QV() const { return QV_; }

  /// Back to the initial set, no step taken.
  void reset();
  std::vector<double> save_state() const;
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

 private:
  void init_noise();
  void step_setbound(const Eigen::VectorXd& y, const Eigen::VectorXd& u);
  void step_cora(const Eigen::VectorXd& y, const Eigen::VectorXd& u);
  /// Gollamudi's ν (Thm. 2) from σ², the innovation's squared norm, the noise level r₀ and g.
  static double optimal_lambda(double s, double dd, double r0, double g, double cap);

  LinearSystem sys_;
  Eigen::MatrixXd QW_, QV_;
  BoundingEllipsoidOptions opt_;
  // Noise data: φ² (Gollamudi) or R̂ = Q_V⁻¹ with its factor V̄ (Liu); r₀ before the measurement's
  // rounding; λ_max(R̂) bound; w̄ = √tr Q_W.
  double phi2_ = 0, r0_ = 1, rmax_ = 0, wbar_ = 0;
  Eigen::MatrixXd R_, Vbar_;
  // Initial set (shape form, level) and the state: the prediction (S, q, s) for the next step
  // and the set of the last step in shape form (Q_out, q_out; CORA: E.Q) or inverse form (W_out,
  // level s_out; default convention).
  Eigen::VectorXd q0_;
  Eigen::MatrixXd Q0_;
  double rho0_ = 1;
  Eigen::MatrixXd S_;
  Eigen::VectorXd q_;
  double s_ = 1;
  Eigen::MatrixXd Q_out_, W_out_;
  Eigen::VectorXd q_out_;
  double s_out_ = 1;
  bool out_inverse_ = false;  // the output is held as (W_out, s_out) (default convention, after a step)
  long k_ = 0;
  double last_lambda_ = 0;
  bool last_inconsistent_ = false;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/ellipsoidal/impl/bounding_ellipsoid.ipp"
#endif
