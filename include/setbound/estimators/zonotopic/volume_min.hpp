// setbound — [Alamo2005] volume minimisation (papers.md §5.2): the strip gain λ that minimises
// the exact volume of p̂(λ) ⊕ Ĥ(λ) B^(m+1), as a linear program on the bundled solver.
//
//   vol(λ)/2^n = |1 − cᵀλ| Σ_{|S|=n} |det H_S| + φ Σ_{|T|=n−1} |w_Tᵀλ|
//
// (det((I − λcᵀ)H_S) = (1 − cᵀλ) det H_S; a subset with the new column φλ gives
// φ det[H_T, λ] = φ w_Tᵀλ, w_T the cofactor vector of H_T, orthogonal to its columns with
// norm the (n−1)-volume they span.) Convex piecewise linear in λ: the weighted least absolute
// deviations problem  min a |cᵀλ − 1| + φ Σ_T |w_Tᵀλ|, the LP
//   min a r + φ Σ_T s_T   s.t.  r ≥ ±(1 − cᵀλ),  s_T ≥ ±w_Tᵀλ,
// solved by lmi::minimize_weighted_l1 (an interior-point method whose Newton systems are n×n;
// on the general LMI solver the LP's dense Schur complement had one row per subset T, which made
// a step cost seconds at a few hundred subsets). Any λ is guaranteed; if the minimisation stops
// short of a relative gap of 1e-6 the segment-minimising λ is used instead (documented
// fallback, still guaranteed).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/estimators/zonotopic/gain_estimator.hpp"
#include "setbound/lmi/l1.hpp"
#include "setbound/sets/zonotope.hpp"

namespace setbound {

/// Largest number of (n−1)-subsets the volume minimisation accepts: the subsets are enumerated
/// (n cofactors each) and each is a row of the L1 problem at every step, whose iterations cost
/// rows·n² (at the limit and n = 8: about 20 ms per strip).
inline constexpr double kVolumeMinMaxSubsets = 20000;

namespace detail {
/// Cofactor vector of the n×(n−1) matrix M: w_i = (−1)^i det(M without row i).
Eigen::VectorXd cofactor_vector(const Eigen::MatrixXd& M);
}  // namespace detail

/// The volume-minimising λ for one strip (papers.md §5.2).
Eigen::VectorXd volume_min_gain(const Zonotope& Z, const StripMeasurement& meas);

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/zonotopic/impl/volume_min.ipp"
#endif
