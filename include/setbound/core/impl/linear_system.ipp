// setbound — definitions of the functions declared in setbound/core/linear_system.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/core/linear_system.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE LinearSystem::LinearSystem(Eigen::MatrixXd A, Eigen::MatrixXd C, Eigen::MatrixXd E, Eigen::MatrixXd F,
               Eigen::MatrixXd B, Eigen::MatrixXd D,
               Eigen::MatrixXd A_rad)
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

SETBOUND_INLINE bool LinearSystem::uncertain_A() const { return (A_rad_.array() > 0).any(); }

SETBOUND_INLINE int LinearSystem::uncertain_entries() const { return static_cast<int>((A_rad_.array() > 0).count()); }

SETBOUND_INLINE std::vector<Eigen::MatrixXd> LinearSystem::A_vertices() const {
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

SETBOUND_INLINE double LinearSystem::output_noise_bound(Eigen::Index i) const { return F_.row(i).cwiseAbs().sum(); }

SETBOUND_INLINE DetectabilityReport check_detectability(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C,
                                               double rel_tol) {
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

SETBOUND_INLINE void require_detectable(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C,
                               const std::string& what) {
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
