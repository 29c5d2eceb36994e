// setbound — weighted least absolute deviations by a primal-dual interior-point method:
//
//   minimise  Σ_t γ_t |g_tᵀx − h_t|   over x ∈ ℝⁿ   (G = [g_tᵀ] is T×n, γ_t > 0).
//
// This is the linear program of [Alamo2005]'s volume minimisation (papers.md §5.2; the
// (n−1)-subsets of the generators give T up to a few thousand rows, n ≤ 8). Written as the LP
// min γᵀ(p + q) s.t. Gx − p + q = h, p, q ≥ 0 (dual: max hᵀu s.t. Gᵀu = 0, |u_t| ≤ γ_t), its
// Newton systems reduce to the n×n matrix Gᵀ diag(1/D) G, D = p/(γ + u) + q/(γ − u): the cost per
// iteration is T·n², where the general LMI solver, which sees T + n + 1 variables and 2T + 2
// scalar blocks, factorises a dense (T + n + 1)² Schur complement. Mehrotra predictor–corrector,
// rows pre-scaled to unit largest entry. The problem is always feasible and bounded below.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "setbound/core/error.hpp"

namespace setbound::lmi {

struct WeightedL1Result {
  bool converged = false;    // relative gap and residuals below the tolerance
  int iterations = 0;
  double relative_gap = std::numeric_limits<double>::infinity();  // of the last iterate
  Eigen::VectorXd x;         // the minimiser (best point met if not converged)
  double objective = std::numeric_limits<double>::quiet_NaN();  // Σ γ_t |g_tᵀx − h_t| at x
  double lower_bound = -std::numeric_limits<double>::infinity();  // bᵀu − (Gᵀu)ᵀx: weak duality
};

/// Minimises Σ_t γ_t |g_tᵀx − h_t| (rows with γ_t = 0 or g_t = 0 are constant terms and
/// ignored). tol: relative duality gap at termination. The returned x is the best iterate by
/// the true objective, so it is usable even when the iteration stops early (converged = false,
/// relative_gap says how far it got).
WeightedL1Result minimize_weighted_l1(const Eigen::MatrixXd& G, const Eigen::VectorXd& h,
                                              const Eigen::VectorXd& gamma, double tol = 1e-9,
                                              int max_iterations = 80);

}  // namespace setbound::lmi

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/lmi/impl/l1.ipp"
#endif
