// setbound — argument validation with messages that name the offending argument.
//
// Used by constructors of sets, models and estimators, and by the C ABI. Each check
// throws the matching setbound::Error subclass; the message always starts with the
// argument name so that a Python user sees e.g. "P: matrix is not positive definite".
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <sstream>
#include <string>

#include "setbound/core/error.hpp"

namespace setbound {

/// Relative tolerance used to accept a matrix as symmetric: |M - M^T| <= tol * max(1, |M|).
inline constexpr double kSymmetryTolerance = 1e-10;

namespace detail {
std::string shape_string(Eigen::Index r, Eigen::Index c);
}  // namespace detail

template <class Derived>
void require_finite(const Eigen::DenseBase<Derived>& m, const std::string& name) {
  for (Eigen::Index j = 0; j < m.cols(); ++j)
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      if (!std::isfinite(m(i, j))) {
        std::ostringstream s;
        s << name << ": entry (" << i << ", " << j << ") is " << m(i, j)
          << "; all entries must be finite";
        throw NotFiniteError(s.str());
      }
}

void require_finite(double v, const std::string& name);

template <class Derived>
void require_shape(const Eigen::DenseBase<Derived>& m, Eigen::Index rows, Eigen::Index cols,
                   const std::string& name) {
  if (m.rows() != rows || m.cols() != cols)
    throw DimensionError(name + ": expected shape " + detail::shape_string(rows, cols) +
                         ", got " + detail::shape_string(m.rows(), m.cols()));
}

template <class Derived>
void require_square(const Eigen::DenseBase<Derived>& m, const std::string& name) {
  if (m.rows() != m.cols())
    throw DimensionError(name + ": matrix must be square, got shape " +
                         detail::shape_string(m.rows(), m.cols()));
}

template <class Derived>
void require_symmetric(const Eigen::MatrixBase<Derived>& m, const std::string& name) {
  require_square(m, name);
  const double scale = std::max(1.0, m.cwiseAbs().maxCoeff());
  const double asym = (m - m.transpose()).cwiseAbs().maxCoeff();
  if (asym > kSymmetryTolerance * scale) {
    std::ostringstream s;
    s << name << ": matrix is not symmetric (max |M - M^T| = " << asym << ")";
    throw NotSymmetricError(s.str());
  }
}

/// Finite, symmetric and positive definite (checked by a Cholesky factorisation).
template <class Derived>
void require_positive_definite(const Eigen::MatrixBase<Derived>& m, const std::string& name) {
  require_finite(m, name);
  require_symmetric(m, name);
  Eigen::MatrixXd sym = 0.5 * (m + m.transpose());
  Eigen::LLT<Eigen::MatrixXd> llt(sym);
  if (llt.info() != Eigen::Success)
    throw NotPositiveDefiniteError(name + ": matrix is not positive definite");
}

void require_positive(double v, const std::string& name);

void require_nonnegative(double v, const std::string& name);

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/core/impl/validate.ipp"
#endif
