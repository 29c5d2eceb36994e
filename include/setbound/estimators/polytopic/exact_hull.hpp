// setbound — the exact reference: interval hull of the exact consistent state set.
//
// For known A, x_k is affine in the unknowns (x_0 = p0 + H0 ξ, ω_0 … ω_k):
//   x_k = A^k p0 + A^k H0 ξ + Σ_{j<k} A^{k−1−j} (B u_j + E ω_j),
// with |ξ| ≤ 1, |ω_j| ≤ 1 and the measurements y_j = C x_j + D u_j + F ω_j (the same ω_j as
// in the state equation, as the model says). The set of x_k consistent with y_0 … y_k is a
// polytope; its interval hull is found by 2 n_x linear programs per step (min and max of each
// coordinate) on the bundled solver. Slow by nature (the LPs grow with k): it is the accuracy
// reference every guaranteed estimator's hull must contain, not an estimator.
// Time indexing as the estimators: row k uses y_0 … y_k (y_1 … y_k without the first one).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <string>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/lmi/lp.hpp"
#include "setbound/sets/zonotope.hpp"

namespace setbound {

struct ExactHull {
  Eigen::MatrixXd lower, upper;  ///< N × n_x
};

ExactHull exact_hull(const LinearSystem& sys, const Zonotope& x0, const Eigen::MatrixXd& Y,
                            const Eigen::MatrixXd& U = Eigen::MatrixXd(), bool use_first_measurement = true);

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/polytopic/impl/exact_hull.ipp"
#endif
