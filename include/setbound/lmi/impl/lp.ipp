// setbound — definitions of the functions declared in setbound/lmi/lp.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/lmi/lp.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace lmi {

SETBOUND_INLINE void LinearProgram::add_le(LpRow row, double rhs) { le_.push_back({std::move(row), rhs}); }

SETBOUND_INLINE void LinearProgram::add_eq(LpRow row, double rhs) { eq_.push_back({std::move(row), rhs}); }

SETBOUND_INLINE void LinearProgram::add_bounds(int i, double lo, double hi) {
  add_le({{i, 1.0}}, hi);
  add_le({{i, -1.0}}, -lo);
}

SETBOUND_INLINE LmiProblem LinearProgram::to_lmi() const {
  LmiProblem p(n_);
  p.set_objective(c_);
  for (const auto& [row, rhs] : le_) {
    BlockTerms terms;
    for (const auto& [v, a] : row)
      if (a != 0.0) terms.emplace_back(v, Eigen::MatrixXd::Constant(1, 1, -a));
    p.add_block_terms(Eigen::MatrixXd::Constant(1, 1, rhs), terms);
  }
  if (!eq_.empty()) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(eq_.size()), n_);
    Eigen::VectorXd b(static_cast<Eigen::Index>(eq_.size()));
    for (std::size_t r = 0; r < eq_.size(); ++r) {
      for (const auto& [v, a] : eq_[r].first) A(static_cast<Eigen::Index>(r), v) += a;
      b(static_cast<Eigen::Index>(r)) = eq_[r].second;
    }
    p.set_equalities(A, b);
  }
  return p;
}

}  // namespace lmi
}  // namespace setbound
