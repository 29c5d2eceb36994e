// setbound — Chapter 3 of the thesis (thesis.md §5): polytopic LPV plant, barycentric weights,
// vertex H∞ gains with a common P (3.13), Algorithm 3 and the online LPV observer (3.63–3.74).
//
//   x⁺ = A(ρ)x + B(ρ)u + F(ρ)d,  y = Cx + Zv,  M(ρ) = Σ α_i(ρ) M_i,  ρ ∈ conv{θ_1..θ_N}.
//
// The vertex list θ is explicit (rows of `theta`, in the order of the vertex matrices): the
// thesis's examples order their vertices differently. When the vertices are exactly the 2^L
// corners of a box (in any order) the weights are the closed-form multilinear ones; otherwise
// an LP finds a convex combination. A ρ outside the polytope (beyond a relative 1e-9) is an
// error naming rho.
#pragma once

#include <Eigen/Core>
#include <sstream>
#include <string>
#include <vector>

#include "setbound/lmi/lp.hpp"
#include "setbound/thesis/hinf_observer.hpp"

namespace setbound::thesis {

/// Barycentric weights α(ρ) of the polytope conv{θ_i} (thesis.md §5.1). Box polytopes use the
/// closed form (no allocation); general polytopes an LP.
class PolytopicWeights {
 public:
  PolytopicWeights() = default;
  explicit PolytopicWeights(Eigen::MatrixXd theta);

  Eigen::Index num_vertices() const { return theta_.rows(); }
  Eigen::Index dim() const { return theta_.cols(); }
  bool is_box() const { return is_box_; }
  const Eigen::MatrixXd& theta() const { return theta_; }

  /// α (size N) with α ≥ 0, Σα = 1, Σ α_i θ_i = ρ. Throws for ρ outside the polytope.
  void compute(const Eigen::Ref<const Eigen::VectorXd>& rho, Eigen::Ref<Eigen::VectorXd> alpha) const;

  Eigen::VectorXd operator()(const Eigen::Ref<const Eigen::VectorXd>& rho) const;

 private:
  [[noreturn]] void outside(const Eigen::Ref<const Eigen::VectorXd>& rho, Eigen::Index j) const;

  Eigen::MatrixXd theta_;
  Eigen::VectorXd lo_, hi_;
  Eigen::MatrixXi at_hi_;
  bool is_box_ = false;
  double scale_ = 1.0;
};

/// Barycentric weights of ρ in conv{rows of theta} (3.2): closed form for a box, LP otherwise.
inline Eigen::VectorXd polytopic_weights(const Eigen::MatrixXd& theta, const Eigen::VectorXd& rho) {
  return PolytopicWeights(theta)(rho);
}

/// Polytopic LPV plant (3.5): vertex matrices A_i, B_i, F_i (one per row θ_i of theta), common C, Z.
struct LpvSystem {
  std::vector<Eigen::MatrixXd> A, B, F;
  Eigen::MatrixXd C, Z, theta;
  PolytopicWeights weights;

  LpvSystem(std::vector<Eigen::MatrixXd> A_, std::vector<Eigen::MatrixXd> B_, std::vector<Eigen::MatrixXd> F_,
            Eigen::MatrixXd C_, Eigen::MatrixXd Z_, Eigen::MatrixXd theta_);

  Eigen::Index nx() const { return A[0].rows(); }
  Eigen::Index nu() const { return B[0].cols(); }
  Eigen::Index ny() const { return C.rows(); }
  Eigen::Index nd() const { return F[0].cols(); }
  Eigen::Index nv() const { return Z.cols(); }
  Eigen::Index m() const { return nd() + nv(); }
  Eigen::Index num_vertices() const;
  Eigen::Index rho_dim() const { return theta.cols(); }
  Plant vertex_plant(size_t i) const;
};

struct HinfGainLpv {
  Eigen::MatrixXd P, Q;
  std::vector<Eigen::MatrixXd> U, L;  // L_i = P⁻¹U_i
  double gamma = 0, g = 0, g_solver = 0, solve_time = 0, spectral_radius = 0;  // max over vertices
  lmi::SolveStatus status = lmi::SolveStatus::NumericalError;
};

/// Theorem 3.1 (3.13): common P, per-vertex U_i, minimise g. Certified at every vertex.
HinfGainLpv hinf_observer_gain_lpv(const LpvSystem& sys, const Eigen::MatrixXd& Q = {}, const HinfOptions& opt = {});

/// Algorithm 3: as Algorithm 2 with the vertex LMIs (3.13), the vertex refinement (3.20) and
/// V = mean V_i (3.60). λ: by default the larger of λ_min(Q_input, P) and λ_min(Q_ref, P) (§5.8).
EllipsoidalSMOptions default_lpv_options();

EllipsoidalSMDesign design_ellipsoidal_sm_observer_lpv(const LpvSystem& sys, const Eigen::VectorXd& wbar,
                                                              const EllipsoidalSMOptions& opt = default_lpv_options());

/// Online LPV observer (3.63–3.66): α(ρ_k), L(ρ_k) = Σα_iL_i, x̂⁺ = (A(ρ) − L(ρ)C)x̂ + B(ρ)u + L(ρ)y,
/// μ⁺ = (1 − λ)μ + λ, box x̂ ± ē∞√μ. step() does not allocate for box polytopes.
class LPVEllipsoidalSMObserver {
 public:
  LPVEllipsoidalSMObserver(const LpvSystem& sys, EllipsoidalSMDesign design, const Eigen::VectorXd& xhat0, double mu0);

  /// Missing and impossible readings as EllipsoidalSMObserver::step (the fallback uses A(ρ_k),
  /// B(ρ_k), F(ρ_k), widened by the rounding of their combination).
  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u,
            const Eigen::Ref<const Eigen::VectorXd>& rho);

  /// As EllipsoidalSMObserver.
  void set_inconsistency_policy(OnInconsistency policy, const Box& reset_box = Box()) {
    rd_.screen.set_policy(policy, reset_box, sys_.nx());
  }
  OnInconsistency inconsistency_policy() const { return rd_.screen.policy; }
  const MeasurementCheck& last_check() const { return rd_.screen.check; }

  /// Full mutable state (core/state.hpp): x̂_k, μ_k, k and the weights α of the last step.
  std::vector<double> save_state() const;
  /// Restores a state from save_state() (same LPV system and design); throws
  /// InvalidArgumentError ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

  void reset(const Eigen::VectorXd& xhat0, double mu0) {
    st_.init(design_, xhat0, mu0);
    rd_.screen.check.clear(sys_.ny(), OutputStatus::Used);
  }

  const Eigen::VectorXd& center() const { return st_.xhat; }
  const Eigen::VectorXd& lower() const { return st_.lower; }
  const Eigen::VectorXd& upper() const { return st_.upper; }
  const Eigen::VectorXd& weights() const { return alpha_; }  // α of the last step
  double mu() const { return st_.mu; }
  long steps() const { return st_.k; }
  const EllipsoidalSMDesign& design() const { return design_; }

 private:
  EllipsoidalSMDesign design_;
  LpvSystem sys_;
  Eigen::VectorXd alpha_, tmp_, tmpu_, tmpy_, tmpn_;
  Eigen::MatrixXd Aa_, Ba_, La_, Ao_, absAo_, absA_, absB_, absL_, absC_, Fa_, absF_;
  hinf_detail::SMState st_;
  hinf_detail::SMReadings rd_;
};

}  // namespace setbound::thesis

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/thesis/impl/lpv.ipp"
#endif
