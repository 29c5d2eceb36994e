// setbound — linear programs on the bundled solver: an LP is an LMI with 1×1 blocks.
//
//   minimise cᵀx  s.t.  G x ≤ h (row by row),  Aeq x = beq.
//
// Rows are given sparsely (only the variables they touch), so the solver's structure analysis
// sees which variables touch which 1×1 block.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "setbound/lmi/problem.hpp"
#include "setbound/lmi/solver.hpp"

namespace setbound::lmi {

/// A sparse LP row: Σ_k coef_k x_{var_k} (≤ or = a right-hand side).
using LpRow = std::vector<std::pair<int, double>>;

class LinearProgram {
 public:
  explicit LinearProgram(int num_vars) : n_(num_vars), c_(Eigen::VectorXd::Zero(num_vars)) {}
  int num_vars() const { return n_; }
  void set_objective(const Eigen::Ref<const Eigen::VectorXd>& c) { c_ = c; }
  /// row·x ≤ rhs
  void add_le(LpRow row, double rhs);
  /// row·x = rhs
  void add_eq(LpRow row, double rhs);
  /// lo ≤ x_i ≤ hi
  void add_bounds(int i, double lo, double hi);

  /// The LMI form: one 1×1 block rhs − row·x ⪰ 0 per inequality.
  LmiProblem to_lmi() const;

  SolveResult solve(const SolverOptions& options = {}) const { return solve_linear(to_lmi(), options); }

 private:
  int n_;
  Eigen::VectorXd c_;
  std::vector<std::pair<LpRow, double>> le_, eq_;
};

}  // namespace setbound::lmi

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/lmi/impl/lp.ipp"
#endif
