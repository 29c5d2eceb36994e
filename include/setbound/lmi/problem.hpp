// setbound — the LMI problem form and its structure analysis.
//
//   minimise cᵀx  subject to  F_b(x) = F_b0 + Σ_i x_i F_bi ⪰ 0   for every block b,
//                             Aeq x = beq,
//   optionally with the objective cᵀx − log det G(x), G(x) = G0 + Σ_i x_i G_i ≻ 0 (maxdet).
//
// 1×1 blocks are plain linear inequalities. This is the "dual standard form" of an SDP
// (papers.md §0.2 LMIs are all of this shape once β is fixed, §0.4). The structure (which
// variables touch which block, and whether a coefficient is sparse or dense) is analysed
// when a block is added; values can be replaced later without re-analysis as long as no new
// variable starts touching a block (β searches and online estimators only change values).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"

namespace setbound::lmi {

/// One non-zero of a sparse coefficient, upper triangle only (row <= col).
struct SparseEntry {
  int row;
  int col;
  double value;
};

enum class CoefficientKind { Sparse, Dense };

/// The coefficient F_bi of one variable in one block (only non-zero coefficients are kept).
struct Coefficient {
  int var = 0;
  CoefficientKind kind = CoefficientKind::Dense;
  Eigen::MatrixXd dense;              // always held (n×n), used by dense kernels and updates
  std::vector<SparseEntry> entries;   // upper-triangle non-zeros when kind == Sparse
};

/// One LMI block F0 + Σ x_i F_i ⪰ 0 of size n.
struct LmiBlock {
  int size = 0;
  Eigen::MatrixXd constant;
  std::vector<Coefficient> coefficients;  // sorted by variable index
};

/// Sparse coefficient list of a block: (variable index, n×n symmetric matrix).
using BlockTerms = std::vector<std::pair<int, Eigen::MatrixXd>>;

class LmiProblem {
 public:
  LmiProblem() = default;
  explicit LmiProblem(int num_vars) { reset(num_vars); }

  void reset(int num_vars) {
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

  int num_vars() const { return m_; }
  int num_blocks() const { return static_cast<int>(blocks_.size()); }
  const LmiBlock& block(int b) const { return blocks_.at(static_cast<size_t>(b)); }
  const std::vector<LmiBlock>& blocks() const { return blocks_; }
  const Eigen::VectorXd& objective() const { return c_; }
  const Eigen::MatrixXd& eq_matrix() const { return Aeq_; }
  const Eigen::VectorXd& eq_rhs() const { return beq_; }
  int num_equalities() const { return static_cast<int>(Aeq_.rows()); }
  bool has_logdet() const { return has_logdet_; }
  const LmiBlock& logdet_block() const { return logdet_; }
  /// Barrier degree Σ_b n_b (the conic "ν").
  int degree() const {
    int d = 0;
    for (const auto& b : blocks_) d += b.size;
    return d;
  }
  /// Incremented whenever the structure changes; solvers re-run their setup when it moves.
  std::uint64_t structure_version() const { return version_; }
  /// Incremented whenever a block, the log-det term or the equalities change (structure or
  /// values; not the objective): a solver re-reads and re-equilibrates the data only then, so
  /// that problems re-solved with a new objective (the online estimators) skip that work.
  std::uint64_t values_version() const { return values_version_; }

  void set_objective(const Eigen::Ref<const Eigen::VectorXd>& c) {
    require_configured();
    if (c.size() != m_)
      throw DimensionError("c: expected " + std::to_string(m_) + " entries, got " +
                           std::to_string(c.size()));
    require_finite(c, "c");
    c_ = c;
  }

  /// Adds F0 + Σ_i x_i Fs[i] ⪰ 0 with one dense coefficient per variable (Fs.size() == m).
  int add_block(const Eigen::Ref<const Eigen::MatrixXd>& F0, const std::vector<Eigen::MatrixXd>& Fs) {
    require_configured();
    if (static_cast<int>(Fs.size()) != m_)
      throw DimensionError("Fs: expected " + std::to_string(m_) + " coefficient matrices, got " +
                           std::to_string(Fs.size()));
    BlockTerms terms;
    for (int i = 0; i < m_; ++i) terms.emplace_back(i, Fs[static_cast<size_t>(i)]);
    return add_block_terms(F0, terms);
  }

  /// Adds F0 + Σ_(i,F) x_i F ⪰ 0 listing only the variables that touch the block.
  int add_block_terms(const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms) {
    require_configured();
    LmiBlock blk = analyse(F0, terms, "F0", "Fs");
    blocks_.push_back(std::move(blk));
    ++version_;
    ++values_version_;
    return num_blocks() - 1;
  }

  /// Replaces the values of block b. No re-analysis unless a variable that did not touch
  /// the block now does (then the structure version moves and solvers re-run setup).
  void update_block_terms(int b, const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms) {
    require_configured();
    if (b < 0 || b >= num_blocks())
      throw InvalidArgumentError("block: index " + std::to_string(b) + " out of range [0, " +
                                 std::to_string(num_blocks()) + ")");
    update_values(blocks_[static_cast<size_t>(b)], F0, terms, "F0", "Fs");
    ++values_version_;
  }

  void update_block(int b, const Eigen::Ref<const Eigen::MatrixXd>& F0, const std::vector<Eigen::MatrixXd>& Fs) {
    if (static_cast<int>(Fs.size()) != m_)
      throw DimensionError("Fs: expected " + std::to_string(m_) + " coefficient matrices, got " +
                           std::to_string(Fs.size()));
    BlockTerms terms;
    for (int i = 0; i < m_; ++i) terms.emplace_back(i, Fs[static_cast<size_t>(i)]);
    update_block_terms(b, F0, terms);
  }

  /// Objective term −log det(G0 + Σ x_i G_i) (maxdet class); G must be ≻ 0 at the solution.
  void set_logdet_terms(const Eigen::Ref<const Eigen::MatrixXd>& G0, const BlockTerms& terms) {
    require_configured();
    logdet_ = analyse(G0, terms, "G0", "Gs");
    has_logdet_ = true;
    ++version_;
    ++values_version_;
  }
  void set_logdet(const Eigen::Ref<const Eigen::MatrixXd>& G0, const std::vector<Eigen::MatrixXd>& Gs) {
    require_configured();
    if (static_cast<int>(Gs.size()) != m_)
      throw DimensionError("Gs: expected " + std::to_string(m_) + " coefficient matrices, got " +
                           std::to_string(Gs.size()));
    BlockTerms terms;
    for (int i = 0; i < m_; ++i) terms.emplace_back(i, Gs[static_cast<size_t>(i)]);
    set_logdet_terms(G0, terms);
  }
  void clear_logdet() {
    has_logdet_ = false;
    logdet_ = LmiBlock{};
    ++version_;
    ++values_version_;
  }

  /// Aeq x = beq (replaces earlier equalities; 0 rows removes them).
  void set_equalities(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::VectorXd>& b) {
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

  /// F_b(x) (without any margin) into `out` (resized only if needed).
  template <class Vec>
  void evaluate_block(const LmiBlock& blk, const Vec& x, Eigen::MatrixXd& out) const {
    out = blk.constant;
    for (const auto& co : blk.coefficients) {
      const double xi = x[co.var];
      if (xi == 0.0) continue;
      if (co.kind == CoefficientKind::Sparse) {
        for (const auto& e : co.entries) {
          out(e.row, e.col) += xi * e.value;
          if (e.row != e.col) out(e.col, e.row) += xi * e.value;
        }
      } else {
        out.noalias() += xi * co.dense;
      }
    }
  }

  /// Throws unless the problem can be solved (at least one block or a logdet term).
  void require_solvable() const {
    require_configured();
    if (blocks_.empty() && !has_logdet_)
      throw InvalidArgumentError("blocks: the problem has no LMI block (add at least one)");
  }

 private:
  void require_configured() const {
    if (m_ <= 0) throw InvalidArgumentError("problem: empty problem (no variables)");
  }

  static void check_matrix(const Eigen::Ref<const Eigen::MatrixXd>& M, int n, const std::string& name) {
    require_shape(M, n, n, name);
    require_finite(M, name);
    require_symmetric(M, name);
  }

  // Sparse when the upper triangle has at most n non-zeros: the scaled product QᵀFQ is then
  // cheaper as a sum of rank-one terms than as two dense n³ products.
  static void classify(Coefficient& co, int n) {
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

  LmiBlock analyse(const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms,
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

  void update_values(LmiBlock& blk, const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms,
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

  static Coefficient* find(LmiBlock& blk, int var) {
    for (auto& co : blk.coefficients)
      if (co.var == var) return &co;
    return nullptr;
  }

  int m_ = 0;
  Eigen::VectorXd c_;
  std::vector<LmiBlock> blocks_;
  Eigen::MatrixXd Aeq_;
  Eigen::VectorXd beq_;
  bool has_logdet_ = false;
  LmiBlock logdet_;
  std::uint64_t version_ = 0;
  std::uint64_t values_version_ = 0;
};

}  // namespace setbound::lmi
