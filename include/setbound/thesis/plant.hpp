// setbound — the plant of the thesis methods (thesis.md §2), in the thesis's own letters:
//
//   x_{k+1} = A x_k + B u_k + F d_k,     y_k = C x_k + Z v_k,     w_k = (d_k, v_k) ∈ ℝ^m,
//
// m = n_d + n_v. The disturbances are bounded by boxes d ∈ [d_lo, d_hi], v ∈ [v_lo, v_hi]
// (Ch. 4 uses the boxes; Ch. 1–3 only the 2-norm bound wᵀw ≤ w̄ᵀw̄ with w̄ the vector of box
// half-widths of a centred box, thesis.md §2). The error of a Luenberger observer with gain
// L obeys e⁺ = (A − LC) e + E w with E = [F, −LZ] (error_input).
//
// This is not LinearSystem (papers' letters, ω in the unit box shared by state and output):
// the thesis designs (γ, L, P) are defined for unscaled, independent d and v, and the
// acceptance checks compare them with reference values, so the thesis methods keep its model.
#pragma once

#include <Eigen/Core>
#include <string>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"

namespace setbound::thesis {

struct Plant {
  Eigen::MatrixXd A, B, C, F, Z;

  /// Validates every matrix (finite, shapes consistent); messages name the argument.
  /// An empty B means no input (n_u = 0); an empty F or Z means no d or no v.
  Plant(Eigen::MatrixXd A_, Eigen::MatrixXd B_, Eigen::MatrixXd C_, Eigen::MatrixXd F_,
        Eigen::MatrixXd Z_);

  Eigen::Index nx() const { return A.rows(); }
  Eigen::Index nu() const { return B.cols(); }
  Eigen::Index ny() const { return C.rows(); }
  Eigen::Index nd() const { return F.cols(); }
  Eigen::Index nv() const { return Z.cols(); }
  Eigen::Index m() const;

  /// E = [F, −L Z] (thesis.md §2), n_x × m.
  Eigen::MatrixXd error_input(const Eigen::MatrixXd& L) const;
};

}  // namespace setbound::thesis

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/thesis/impl/plant.ipp"
#endif
