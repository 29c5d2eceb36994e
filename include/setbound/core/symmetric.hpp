#pragma once
// Exact symmetrisation of a matrix in place.

#include <Eigen/Core>

namespace setbound {

/// M ← (M + Mᵀ)/2, exactly symmetric ((a + b)/2 = (b + a)/2 in floating point).
/// Why a function: `M = 0.5 * (M + M.transpose())` is wrong in Eigen — the assignment overwrites
/// entries that the transpose reads later (aliasing; no check without assertions), so M(i, j)
/// became ¾M(i, j) + ¼M(j, i) below the diagonal and the result was not symmetric: a saved
/// ellipsoid state then failed restore_state's symmetry check (found 2026-11-27).
template <class Derived>
void symmetrize(Eigen::PlainObjectBase<Derived>& M) {
  M = (0.5 * (M + M.transpose())).eval();
}

}  // namespace setbound
