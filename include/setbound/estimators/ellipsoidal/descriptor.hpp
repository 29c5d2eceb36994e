// setbound — ellipsoidal estimation for descriptor systems ([Merhy2019], papers.md §4).
//
//   E x_{k+1} = A x_k + B u_k + D w_k,     y_k = C x_k + F w_k,     w_k ∈ B^{n_w},
//
// with E possibly singular (here E is the descriptor matrix and D the disturbance matrix).
// When rank [E; C] = n_x there are T, N with T E + N C = I; [T N] = pinv([E; C]) (§4.0). Then
//
//   x_{k+1} = T A x_k + T B u_k + N y_{k+1} + T D w_k − N F w_{k+1},
//
// an explicit system driven by ω_k = [w_k; w_{k+1}] ∈ B^{2 n_w}: w_k and w_{k+1} are the
// disturbance at two different times and must be *independent* vertices (§4.1 warning). The
// LMI of §4.1 is the §1.1 LMI of the equivalent system (T A, C, [T D, −N F], [F, 0], T B),
// so the design is design_ellipsoidal_offline on it (± halving and zero-column dropping
// included). The estimator
//
//   x̄_{k+1} = T A x̄_k + T B u_k + N y_{k+1} + L (y_k − C x̄_k),   ρ_{k+1} = β ρ_k + σ
//
// is a filter (x̄_{k+1} uses y_{k+1}), so step(y_k, u_k) returns the set for x_k.
//
// Floating point: besides the centre rounding (which includes the N y_{k+1} term), the
// stored T, N and the stored products T A, T B, T D, N F are not exact, so the true error
// obeys z⁺ = (Ã − L C) z + Ẽ ω + e with e = R x⁺ + ΔA x + ΔB u + ΔD w − ΔNF w⁺, R = I − T E − N C
// (all of order eps). Each step bounds e (‖R‖ from a rounding bound of T E + N C − I, x from the
// current set's box, x⁺ through the new level itself, see step()) and enlarges the level.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <complex>
#include <memory>
#include <sstream>
#include <string>
#include <utility>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/state.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/ellipsoidal/lmi_estimators.hpp"
#include "setbound/estimators/ellipsoidal/common.hpp"
#include "setbound/sets/ellipsoid.hpp"

namespace setbound {

class DescriptorSystem {  // E x⁺ = A x + B u + D w,  y = C x + F w,  w ∈ B^{n_w}
 public:
  /// Validates shapes and finiteness (messages name the argument) and the two rank
  /// conditions of §4.0 (NotDetectableError naming the condition):
  ///  * infinite observability  rank [E; C] = n_x;
  ///  * finite observability    rank [λE − A; C] = n_x for every complex λ. If [λE − A; C] v = 0
  ///    with v ≠ 0 then C v = 0 and T A v = T (λ E v) = λ (I − N C) v = λ v: λ is an eigenvalue of
  ///    T A. So checking the rank at the n_x eigenvalues of T A is complete (also for a singular
  ///    pencil, where every λ is a generalised eigenvalue), and each check is one SVD.
  DescriptorSystem(Eigen::MatrixXd E, Eigen::MatrixXd A, Eigen::MatrixXd C, Eigen::MatrixXd D, Eigen::MatrixXd F,
                   Eigen::MatrixXd B = Eigen::MatrixXd());

  const Eigen::MatrixXd& E() const { return E_; }
  const Eigen::MatrixXd& A() const { return A_; }
  const Eigen::MatrixXd& B() const { return B_; }
  const Eigen::MatrixXd& C() const { return C_; }
  const Eigen::MatrixXd& D() const { return D_; }
  const Eigen::MatrixXd& F() const { return F_; }
  Eigen::Index nx() const { return A_.rows(); }
  Eigen::Index ny() const { return C_.rows(); }
  Eigen::Index nu() const { return B_.cols(); }
  Eigen::Index nw() const { return D_.cols(); }

  /// [T N] = pinv([E; C]), so that T E + N C = I.
  const Eigen::MatrixXd& T() const { return T_; }
  const Eigen::MatrixXd& N() const { return N_; }

  /// x⁺ = (T A) x + (T B) u + [T D, −N F] [w_k; w_{k+1}] (+ N y_{k+1}, known data),
  /// y = C x + [F, 0] [w_k; w_{k+1}]: the §4.1 LMI is the §1.1 LMI of this system.
  LinearSystem equivalent() const;

 private:
  Eigen::MatrixXd E_, A_, B_, C_, D_, F_, T_, N_, TA_;
};

/// The offline design of §4.1: design_ellipsoidal_offline on the equivalent system. The
/// detectability needed is that of (C, T A) (the error dynamics is T A − L C).
EllDesign design_descriptor_offline(const DescriptorSystem& sys, const EllDesignOptions& opt = {});

class DescriptorEstimator {
 public:
  DescriptorEstimator(EllDesign design, DescriptorSystem sys, const Ellipsoid& x0);

  const EllDesign& design() const { return d_; }
  const DescriptorSystem& system() const { return sys_; }
  /// The set for x_k, k = steps_taken(); before the first step, x0 converted to shape P.
  const Ellipsoid& current() const { return cur_; }
  Eigen::Index steps_taken() const { return k_; }

  /// step(y_k, u_k) returns the set for x_k using y_0..y_k: the first call returns x0
  /// converted to shape P (and remembers y_0, u_0); later calls apply the recursion of §4.1
  /// with the remembered y_{k−1}, u_{k−1}. Unchanged on error.
  Ellipsoid step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);

  /// Full mutable state (core/state.hpp): the current set, the step counter and the remembered
  /// y_{k-1}, u_{k-1} (empty before the first step).
  std::vector<double> save_state() const;
  /// Restores a state from save_state() (same design and descriptor system); throws
  /// InvalidArgumentError ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

 private:
  static Ellipsoid check(const EllDesign& d, const DescriptorSystem& sys, const Ellipsoid& x0);

  EllDesign d_;
  DescriptorSystem sys_;
  LinearSystem eq_;
  Ellipsoid cur_;
  Eigen::Index k_ = 0;
  bool started_ = false;
  Eigen::VectorXd y_prev_, u_prev_;
  double lmax_up_ = 0, lmin_low_ = 0, r_ = 0, den_ = 1;
  Eigen::MatrixXd dA_, dB_;
  Eigen::VectorXd dw_;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/ellipsoidal/impl/descriptor.ipp"
#endif
