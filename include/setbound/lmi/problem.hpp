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

  void reset(int num_vars);

  int num_vars() const { return m_; }
  int num_blocks() const;
  const LmiBlock& block(int b) const;
  const std::vector<LmiBlock>& blocks() const { return blocks_; }
  const Eigen::VectorXd& objective() const { return c_; }
  const Eigen::MatrixXd& eq_matrix() const { return Aeq_; }
  const Eigen::VectorXd& eq_rhs() const { return beq_; }
  int num_equalities() const;
  bool has_logdet() const { return has_logdet_; }
  const LmiBlock& logdet_block() const { return logdet_; }
  /// Barrier degree Σ_b n_b (the conic "ν").
  int degree() const;
  /// Incremented whenever the structure changes; solvers re-run their setup when it moves.
  std::uint64_t structure_version() const { return version_; }
  /// Incremented whenever a block, the log-det term or the equalities change (structure or
  /// values; not the objective): a solver re-reads and re-equilibrates the data only then, so
  /// that problems re-solved with a new objective (the online estimators) skip that work.
  std::uint64_t values_version() const { return values_version_; }

  void set_objective(const Eigen::Ref<const Eigen::VectorXd>& c);

  /// Adds F0 + Σ_i x_i Fs[i] ⪰ 0 with one dense coefficient per variable (Fs.size() == m).
  int add_block(const Eigen::Ref<const Eigen::MatrixXd>& F0, const std::vector<Eigen::MatrixXd>& Fs);

  /// Adds F0 + Σ_(i,F) x_i F ⪰ 0 listing only the variables that touch the block.
  int add_block_terms(const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms);

  /// Replaces the values of block b. No re-analysis unless a variable that did not touch
  /// the block now does (then the structure version moves and solvers re-run setup).
  void update_block_terms(int b, const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms);

  void update_block(int b, const Eigen::Ref<const Eigen::MatrixXd>& F0, const std::vector<Eigen::MatrixXd>& Fs);

  /// Objective term −log det(G0 + Σ x_i G_i) (maxdet class); G must be ≻ 0 at the solution.
  void set_logdet_terms(const Eigen::Ref<const Eigen::MatrixXd>& G0, const BlockTerms& terms);
  void set_logdet(const Eigen::Ref<const Eigen::MatrixXd>& G0, const std::vector<Eigen::MatrixXd>& Gs);
  void clear_logdet();

  /// Aeq x = beq (replaces earlier equalities; 0 rows removes them).
  void set_equalities(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::VectorXd>& b);

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
  void require_solvable() const;

 private:
  void require_configured() const {
    if (m_ <= 0) throw InvalidArgumentError("problem: empty problem (no variables)");
  }

  static void check_matrix(const Eigen::Ref<const Eigen::MatrixXd>& M, int n, const std::string& name);

  // Sparse when the upper triangle has at most n non-zeros: the scaled product QᵀFQ is then
  // cheaper as a sum of rank-one terms than as two dense n³ products.
  static void classify(Coefficient& co, int n);

  LmiBlock analyse(const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms,
                   const std::string& f0name, const std::string& fsname) const;

  void update_values(LmiBlock& blk, const Eigen::Ref<const Eigen::MatrixXd>& F0, const BlockTerms& terms,
                     const std::string& f0name, const std::string& fsname);

  static Coefficient* find(LmiBlock& blk, int var);

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

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/lmi/impl/problem.ipp"
#endif
