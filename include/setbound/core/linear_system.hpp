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
               Eigen::MatrixXd A_rad = Eigen::MatrixXd())
      : A_(std::move(A)), B_(std::move(B)), C_(std::move(C)), D_(std::move(D)), E_(std::move(E)),
        F_(std::move(F)), A_rad_(std::move(A_rad)) {
    if (A_.rows() == 0) throw DimensionError("A: the state dimension must be >= 1");
    require_square(A_, "A");
    require_finite(A_, "A");
    const Eigen::Index n = A_.rows();
    if (C_.cols() != n || C_.rows() == 0)
      throw DimensionError("C: expected shape (n_y, " + std::to_string(n) + ") with n_y >= 1, got " +
                           detail::shape_string(C_.rows(), C_.cols()));
    require_finite(C_, "C");
    const Eigen::Index ny = C_.rows();
    if (E_.rows() != n)
      throw DimensionError("E: expected " + std::to_string(n) + " rows (the state dimension), got " +
                           std::to_string(E_.rows()));
    require_shape(F_, ny, E_.cols(), "F");
    require_finite(E_, "E");
    require_finite(F_, "F");
    if (B_.size() == 0) B_ = Eigen::MatrixXd::Zero(n, D_.cols());  // no input, or B = 0
    if (B_.rows() != n)
      throw DimensionError("B: expected " + std::to_string(n) + " rows (the state dimension), got " +
                           std::to_string(B_.rows()));
    if (D_.size() == 0) D_ = Eigen::MatrixXd::Zero(ny, B_.cols());
    require_shape(D_, ny, B_.cols(), "D");
    require_finite(B_, "B");
    require_finite(D_, "D");
    if (A_rad_.size() == 0) A_rad_ = Eigen::MatrixXd::Zero(n, n);
    require_shape(A_rad_, n, n, "A_rad");
    require_finite(A_rad_, "A_rad");
    if (A_rad_.minCoeff() < 0) throw InvalidArgumentError("A_rad: radii must be >= 0");
  }

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

  bool uncertain_A() const { return (A_rad_.array() > 0).any(); }
  int uncertain_entries() const { return static_cast<int>((A_rad_.array() > 0).count()); }

  /// vert[A] (papers §0.1): every uncertain entry at one of its two ends, 2^q matrices.
  std::vector<Eigen::MatrixXd> A_vertices() const {
    const int q = uncertain_entries();
    if (q > kMaxUncertainEntries)
      throw InvalidArgumentError("A_rad: " + std::to_string(q) + " uncertain entries give 2^" +
                                 std::to_string(q) + " vertices; at most " +
                                 std::to_string(kMaxUncertainEntries) + " are supported");
    std::vector<std::pair<Eigen::Index, Eigen::Index>> idx;
    for (Eigen::Index j = 0; j < A_.cols(); ++j)
      for (Eigen::Index i = 0; i < A_.rows(); ++i)
        if (A_rad_(i, j) > 0) idx.emplace_back(i, j);
    std::vector<Eigen::MatrixXd> out;
    out.reserve(std::size_t(1) << q);
    for (unsigned long s = 0; s < (1ul << q); ++s) {
      Eigen::MatrixXd V = A_;
      for (int b = 0; b < q; ++b) {
        const auto [i, j] = idx[static_cast<std::size_t>(b)];
        V(i, j) += ((s >> b) & 1ul) ? A_rad_(i, j) : -A_rad_(i, j);
      }
      out.push_back(std::move(V));
    }
    return out;
  }

  /// Radius of the output noise on output i: |F_i ω| <= Σ_j |F_ij| for ω in the unit box.
  double output_noise_bound(Eigen::Index i) const { return F_.row(i).cwiseAbs().sum(); }

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
inline DetectabilityReport check_detectability(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C,
                                               double rel_tol = 1e-9) {
  require_square(A, "A");
  require_finite(A, "A");
  if (C.cols() != A.rows()) throw DimensionError("C: must have as many columns as A");
  require_finite(C, "C");
  const Eigen::Index n = A.rows();
  Eigen::EigenSolver<Eigen::MatrixXd> eig(A, false);
  if (eig.info() != Eigen::Success) throw NumericalError("A: eigenvalue computation failed");
  const double scale = std::max({1.0, A.norm(), C.norm()});
  for (Eigen::Index k = 0; k < n; ++k) {
    const std::complex<double> lambda = eig.eigenvalues()(k);
    if (std::abs(lambda) < 1.0 - 1e-12) continue;
    Eigen::MatrixXcd M(n + C.rows(), n);
    M.topRows(n) = lambda * Eigen::MatrixXcd::Identity(n, n) - A.cast<std::complex<double>>();
    M.bottomRows(C.rows()) = C.cast<std::complex<double>>();
    Eigen::JacobiSVD<Eigen::MatrixXcd> svd(M);
    if (svd.singularValues()(n - 1) <= rel_tol * scale) return {false, lambda};
  }
  return {};
}

/// Throws NotDetectableError naming the unobservable unstable mode.
inline void require_detectable(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C,
                               const std::string& what = "(C, A)") {
  const DetectabilityReport r = check_detectability(A, C);
  if (!r.detectable) {
    std::ostringstream s;
    s << what << ": the pair is not detectable: the mode at eigenvalue " << r.mode.real();
    if (r.mode.imag() != 0) s << (r.mode.imag() > 0 ? " + " : " - ") << std::abs(r.mode.imag()) << "i";
    s << " (|lambda| = " << std::abs(r.mode) << " >= 1) is not seen by C";
    throw NotDetectableError(s.str());
  }
}

}  // namespace setbound
