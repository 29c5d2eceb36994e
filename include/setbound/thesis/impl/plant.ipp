// setbound — definitions of the functions declared in setbound/thesis/plant.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/thesis/plant.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace thesis {

SETBOUND_INLINE Plant::Plant(Eigen::MatrixXd A_, Eigen::MatrixXd B_, Eigen::MatrixXd C_, Eigen::MatrixXd F_,
        Eigen::MatrixXd Z_)
    : A(std::move(A_)), B(std::move(B_)), C(std::move(C_)), F(std::move(F_)), Z(std::move(Z_)) {
  if (A.rows() == 0) throw DimensionError("A: the state dimension must be >= 1");
  require_square(A, "A");
  require_finite(A, "A");
  const Eigen::Index n = A.rows();
  if (C.cols() != n || C.rows() == 0)
    throw DimensionError("C: expected shape (n_y, " + std::to_string(n) + ") with n_y >= 1, got " +
                         setbound::detail::shape_string(C.rows(), C.cols()));
  require_finite(C, "C");
  if (B.size() == 0) B.resize(n, 0);
  if (B.rows() != n)
    throw DimensionError("B: expected " + std::to_string(n) + " rows (the state dimension), got " +
                         std::to_string(B.rows()));
  require_finite(B, "B");
  if (F.size() == 0) F.resize(n, 0);
  if (F.rows() != n)
    throw DimensionError("F: expected " + std::to_string(n) + " rows (the state dimension), got " +
                         std::to_string(F.rows()));
  require_finite(F, "F");
  if (Z.size() == 0) Z.resize(C.rows(), 0);
  if (Z.rows() != C.rows())
    throw DimensionError("Z: expected " + std::to_string(C.rows()) + " rows (the output dimension), got " +
                         std::to_string(Z.rows()));
  require_finite(Z, "Z");
  if (F.cols() + Z.cols() == 0)
    throw DimensionError("F, Z: the plant has no disturbance (n_d + n_v = 0)");
}

SETBOUND_INLINE Eigen::Index Plant::m() const { return F.cols() + Z.cols(); }

SETBOUND_INLINE Eigen::MatrixXd Plant::error_input(const Eigen::MatrixXd& L) const {
  require_shape(L, nx(), ny(), "L");
  Eigen::MatrixXd E(nx(), m());
  E.leftCols(nd()) = F;
  E.rightCols(nv()) = -L * Z;
  return E;
}

}  // namespace thesis
}  // namespace setbound
