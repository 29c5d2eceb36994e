// setbound — definitions of the functions declared in setbound/lmi/problem.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/lmi/problem.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace lmi {

SETBOUND_INLINE void LmiProblem::reset(int num_vars) {
  if (num_vars <= 0)
    throw DimensionError("num_vars: the problem needs at least one variable, got " +
                         std::to_string(num_vars));
  m_ = num_vars;
  c_ = Eigen::VectorXd::Zero(m_);
  blocks_.clear();
  Aeq_.resize(0, m_);
  beq_.resize(0);
  has_logdet_ = false;
  logdet_ = LmiBlock{};
  ++version_;
  ++values_version_;
}

SETBOUND_INLINE int LmiProblem::num_blocks() const { return static_cast<int>(blocks_.size()); }

SETBOUND_INLINE const LmiBlock& LmiProblem::block(int b) const { return blocks_.at(static_cast<size_t>(b)); }

SETBOUND_INLINE int LmiProblem::num_equalities() const { return static_cast<int>(Aeq_.rows()); }

SETBOUND_INLINE int LmiProblem::degree() const {
  int d = 0;
  for (const auto& b : blocks_) d += b.size;
  return d;
}

SETBOUND_INLINE void LmiProblem::set_objective(const Eigen::Ref<const Eigen::VectorXd>& c) {
  require_configured();
  if (c.size() != m_)
    throw DimensionError("c: expected " + std::to_string(m_) + " entries, got " +
                         std::to_string(c.size()));
  require_finite(c, "c");
  c_ = c;
}

SETBOUND_INLINE int LmiProblem::add_block(const Eigen::Ref<const Eigen::MatrixXd>& F0, const std::vector<Eigen::MatrixXd>& Fs) {
  require_configured();
  if (static_cast<int>(Fs.size()) != m_)
    throw DimensionError("Fs: expected " + std::to_string(m_) + " coefficient matrices, got " +
                         std::to_string(Fs.size()));
  BlockTerms terms;
  for (int i = 0; i < m_; ++i) terms.emplace_back(i, Fs[static_cast<size_t>(i)]);
  return add_block_terms(F0, terms);
}

SETBOUND_INLINE int LmiProblem::add_block_terms(const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms) {
  require_configured();
  LmiBlock blk = analyse(F0, terms, "F0", "Fs");
  blocks_.push_back(std::move(blk));
  ++version_;
  ++values_version_;
  return num_blocks() - 1;
}

SETBOUND_INLINE void LmiProblem::update_block_terms(int b, const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms) {
  require_configured();
  if (b < 0 || b >= num_blocks())
    throw InvalidArgumentError("block: index " + std::to_string(b) + " out of range [0, " +
                               std::to_string(num_blocks()) + ")");
  update_values(blocks_[static_cast<size_t>(b)], F0, terms, "F0", "Fs");
  ++values_version_;
}

SETBOUND_INLINE void LmiProblem::update_block(int b, const Eigen::Ref<const Eigen::MatrixXd>& F0, const std::vector<Eigen::MatrixXd>& Fs) {
  if (static_cast<int>(Fs.size()) != m_)
    throw DimensionError("Fs: expected " + std::to_string(m_) + " coefficient matrices, got " +
                         std::to_string(Fs.size()));
  BlockTerms terms;
  for (int i = 0; i < m_; ++i) terms.emplace_back(i, Fs[static_cast<size_t>(i)]);
  update_block_terms(b, F0, terms);
}

SETBOUND_INLINE void LmiProblem::set_logdet_terms(const Eigen::Ref<const Eigen::MatrixXd>& G0, const BlockTerms& terms) {
  require_configured();
  logdet_ = analyse(G0, terms, "G0", "Gs");
  has_logdet_ = true;
  ++version_;
  ++values_version_;
}

SETBOUND_INLINE void LmiProblem::set_logdet(const Eigen::Ref<const Eigen::MatrixXd>& G0, const std::vector<Eigen::MatrixXd>& Gs) {
  require_configured();
  if (static_cast<int>(Gs.size()) != m_)
    throw DimensionError("Gs: expected " + std::to_string(m_) + " coefficient matrices, got " +
                         std::to_string(Gs.size()));
  BlockTerms terms;
  for (int i = 0; i < m_; ++i) terms.emplace_back(i, Gs[static_cast<size_t>(i)]);
  set_logdet_terms(G0, terms);
}

SETBOUND_INLINE void LmiProblem::clear_logdet() {
  has_logdet_ = false;
  logdet_ = LmiBlock{};
  ++version_;
  ++values_version_;
}

SETBOUND_INLINE void LmiProblem::set_equalities(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::VectorXd>& b) {
  require_configured();
  if (A.cols() != m_)
    throw DimensionError("Aeq: expected " + std::to_string(m_) + " columns, got " +
                         std::to_string(A.cols()));
  if (b.size() != A.rows())
    throw DimensionError("beq: expected " + std::to_string(A.rows()) + " entries, got " +
                         std::to_string(b.size()));
  require_finite(A, "Aeq");
  require_finite(b, "beq");
  const bool same_shape = A.rows() == Aeq_.rows();
  Aeq_ = A;
  beq_ = b;
  if (!same_shape) ++version_;
  ++values_version_;
}

SETBOUND_INLINE void LmiProblem::require_solvable() const {
  require_configured();
  if (blocks_.empty() && !has_logdet_)
    throw InvalidArgumentError("blocks: the problem has no LMI block (add at least one)");
}

SETBOUND_INLINE void LmiProblem::check_matrix(const Eigen::Ref<const Eigen::MatrixXd>& M, int n, const std::string& name) {
  require_shape(M, n, n, name);
  require_finite(M, name);
  require_symmetric(M, name);
}

SETBOUND_INLINE void LmiProblem::classify(Coefficient& co, int n) {
  co.entries.clear();
  int nnz = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i <= j; ++i)
      if (co.dense(i, j) != 0.0) ++nnz;
  if (nnz <= n) {
    co.kind = CoefficientKind::Sparse;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i <= j; ++i)
        if (co.dense(i, j) != 0.0) co.entries.push_back({i, j, co.dense(i, j)});
  } else {
    co.kind = CoefficientKind::Dense;
  }
}

SETBOUND_INLINE LmiBlock LmiProblem::analyse(const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms,
                   const std::string& f0name, const std::string& fsname) const {
  if (F0.rows() <= 0 || F0.rows() != F0.cols())
    throw DimensionError(f0name + ": must be a non-empty square matrix, got shape " +
                         std::to_string(F0.rows()) + "x" + std::to_string(F0.cols()));
  const int n = static_cast<int>(F0.rows());
  check_matrix(F0, n, f0name);
  LmiBlock blk;
  blk.size = n;
  blk.constant = 0.5 * (F0 + F0.transpose());
  std::vector<int> seen(static_cast<size_t>(m_), -1);
  for (const auto& [var, Fi] : terms) {
    const std::string name = fsname + "[" + std::to_string(var) + "]";
    if (var < 0 || var >= m_)
      throw InvalidArgumentError(name + ": variable index out of range [0, " + std::to_string(m_) + ")");
    check_matrix(Fi, n, name);
    if (!(Fi.array() != 0.0).any()) continue;
    if (seen[static_cast<size_t>(var)] >= 0) {
      blk.coefficients[static_cast<size_t>(seen[static_cast<size_t>(var)])].dense += 0.5 * (Fi + Fi.transpose());
      continue;
    }
    Coefficient co;
    co.var = var;
    co.dense = 0.5 * (Fi + Fi.transpose());
    seen[static_cast<size_t>(var)] = static_cast<int>(blk.coefficients.size());
    blk.coefficients.push_back(std::move(co));
  }
  for (auto& co : blk.coefficients) classify(co, n);
  std::sort(blk.coefficients.begin(), blk.coefficients.end(),
            [](const Coefficient& a, const Coefficient& b) { return a.var < b.var; });
  return blk;
}

SETBOUND_INLINE void LmiProblem::update_values(LmiBlock& blk, const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms,
                     const std::string& f0name, const std::string& fsname) {
  const int n = blk.size;
  check_matrix(F0, n, f0name);
  // Validate everything before touching the stored values (strong exception guarantee).
  bool new_var = false;
  for (const auto& [var, Fi] : terms) {
    const std::string name = fsname + "[" + std::to_string(var) + "]";
    if (var < 0 || var >= m_)
      throw InvalidArgumentError(name + ": variable index out of range [0, " + std::to_string(m_) + ")");
    check_matrix(Fi, n, name);
    if ((Fi.array() != 0.0).any() && find(blk, var) == nullptr) new_var = true;
  }
  if (new_var) {
    blk = analyse(F0, terms, f0name, fsname);
    ++version_;
    return;
  }
  blk.constant = 0.5 * (F0 + F0.transpose());
  for (auto& co : blk.coefficients) co.dense.setZero();
  for (const auto& [var, Fi] : terms) {
    Coefficient* co = find(blk, var);
    if (co != nullptr) co->dense += 0.5 * (Fi + Fi.transpose());
  }
  // The kind (sparse/dense) may change with the values; the solver handles both per
  // coefficient, so this is not a structural change.
  for (auto& co : blk.coefficients) classify(co, n);
}

SETBOUND_INLINE Coefficient* LmiProblem::find(LmiBlock& blk, int var) {
  for (auto& co : blk.coefficients)
    if (co.var == var) return &co;
  return nullptr;
}

}  // namespace lmi
}  // namespace setbound
