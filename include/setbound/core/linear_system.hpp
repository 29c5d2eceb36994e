// setbound — the discrete-time linear model shared by the estimators.
//
//   x_{k+1} = A x_k + B u_k + E ω_k,     y_k = C x_k + D u_k + F ω_k,     ω_k ∈ B^{n_ω}
//
// (papers.md §0.3; the unit-box disturbance ω may drive state and output together, and any
// n_ω is accepted). A may be uncertain, A ∈ [A] = [A_mid − A_rad, A_mid + A_rad] (papers.md
// §0.1, §6.7, [Le2013] §3.4): then A() is mid[A] and A_rad() the entrywise radius.
//
// The zonotopic family writes the same model as x⁺ = A x + F_w ω, y = C x + Φ v; it is this
// class with E = [F_w, 0] and F = [0, Φ].
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <complex>
#include <sstream>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"

namespace setbound {

/// Largest number of uncertain entries of A for which vertex enumeration (2^q matrices) is
/// accepted; the offline LMI designs impose one block per vertex.
inline constexpr int kMaxUncertainEntries = 16;

class LinearSystem {
 public:
  /// Empty B or D mean "no input" (n_u = 0, or D = 0 when B has columns). An empty A_rad
  /// means A is known exactly. Every argument is validated; messages name it.
  LinearSystem(Eigen::MatrixXd A, Eigen::MatrixXd C, Eigen::MatrixXd E, Eigen::MatrixXd F,
               Eigen::MatrixXd B = Eigen::MatrixXd(), Eigen::MatrixXd D = Eigen::MatrixXd(),
               Eigen::MatrixXd A_rad = Eigen::MatrixXd());

  Eigen::Index nx() const { return A_.rows(); }
  Eigen::Index ny() const { return C_.rows(); }
  Eigen::Index nu() const { return B_.cols(); }
  Eigen::Index nw() const { return E_.cols(); }

  /// A, or mid[A] when A is uncertain.
  const Eigen::MatrixXd& A() const { return A_; }
  const Eigen::MatrixXd& A_rad() const { return A_rad_; }
  const Eigen::MatrixXd& B() const { return B_; }
  const Eigen::MatrixXd& C() const { return C_; }
  const Eigen::MatrixXd& D() const { return D_; }
  const Eigen::MatrixXd& E() const { return E_; }
  const Eigen::MatrixXd& F() const { return F_; }

  bool uncertain_A() const;
  int uncertain_entries() const;

  /// vert[A] (papers §0.1): every uncertain entry at one of its two ends, 2^q matrices.
  std::vector<Eigen::MatrixXd> A_vertices() const;

  /// Radius of the output noise on output i: |F_i ω| <= Σ_j |F_ij| for ω in the unit box.
  double output_noise_bound(Eigen::Index i) const;

 private:
  Eigen::MatrixXd A_, B_, C_, D_, E_, F_, A_rad_;
};

/// Result of the PBH detectability test.
struct DetectabilityReport {
  bool detectable = true;
  std::complex<double> mode{0.0, 0.0};  ///< an unstable mode that C does not see (if any)
};

/// PBH test: (C, A) is detectable iff rank [λI − A; C] = n for every eigenvalue λ of A with
/// |λ| >= 1. The rank is judged with a relative tolerance on the smallest singular value.
DetectabilityReport check_detectability(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C,
                                               double rel_tol = 1e-9);

/// Throws NotDetectableError naming the unobservable unstable mode.
void require_detectable(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C,
                               const std::string& what = "(C, A)");

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/core/impl/linear_system.ipp"
#endif
