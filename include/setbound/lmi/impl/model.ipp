// setbound — definitions of the functions declared in setbound/lmi/model.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/lmi/model.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace lmi {

SETBOUND_INLINE AffineExpr AffineExpr::zero(Eigen::Index rows, Eigen::Index cols) { return AffineExpr(Eigen::MatrixXd::Zero(rows, cols)); }

SETBOUND_INLINE AffineExpr AffineExpr::identity(Eigen::Index n) { return AffineExpr(Eigen::MatrixXd::Identity(n, n)); }

SETBOUND_INLINE Eigen::MatrixXd AffineExpr::evaluate(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  Eigen::MatrixXd v = c_;
  for (const auto& [var, M] : t_) v.noalias() += x(var) * M;
  return v;
}

SETBOUND_INLINE AffineExpr AffineExpr::transpose() const {
  AffineExpr r(Eigen::MatrixXd(c_.transpose()));
  r.t_.reserve(t_.size());
  for (const auto& [v, M] : t_) r.t_.emplace_back(v, M.transpose());
  return r;
}

SETBOUND_INLINE AffineExpr AffineExpr::block(Eigen::Index i0, Eigen::Index j0, Eigen::Index r, Eigen::Index c) const {
  AffineExpr out(Eigen::MatrixXd(c_.block(i0, j0, r, c)));
  for (const auto& [v, M] : t_) {
    Eigen::MatrixXd B = M.block(i0, j0, r, c);
    if ((B.array() != 0.0).any()) out.t_.emplace_back(v, std::move(B));
  }
  return out;
}

SETBOUND_INLINE bool AffineExpr::is_symmetric(double tol) const {
  if (rows() != cols()) return false;
  auto sym = [&](const Eigen::MatrixXd& M) {
    const double s = std::max(1.0, M.cwiseAbs().maxCoeff());
    return (M - M.transpose()).cwiseAbs().maxCoeff() <= tol * s;
  };
  if (!sym(c_)) return false;
  for (const auto& [v, M] : t_)
    if (!sym(M)) return false;
  return true;
}

SETBOUND_INLINE AffineExpr AffineExpr::from_terms(Eigen::MatrixXd c, std::vector<std::pair<int, Eigen::MatrixXd>> t) {
  AffineExpr r(std::move(c));
  r.t_ = std::move(t);
  return r;
}

SETBOUND_INLINE std::string AffineExpr::shape(Eigen::Index r, Eigen::Index c) { return std::to_string(r) + "x" + std::to_string(c); }

SETBOUND_INLINE AffineExpr AffineExpr::scalar_times(const AffineExpr& s, const Eigen::MatrixXd& M) {
  AffineExpr r(Eigen::MatrixXd(s.c_(0, 0) * M));
  r.t_.reserve(s.t_.size());
  for (const auto& [v, C] : s.t_) r.t_.emplace_back(v, C(0, 0) * M);
  return r;
}

SETBOUND_INLINE AffineExpr AffineExpr::combine(const AffineExpr& a, const AffineExpr& b, double sb) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    throw DimensionError("expression: cannot add a " + shape(a.rows(), a.cols()) + " and a " +
                         shape(b.rows(), b.cols()) + " expression");
  AffineExpr r(Eigen::MatrixXd(a.c_ + sb * b.c_));
  r.t_.reserve(a.t_.size() + b.t_.size());
  size_t i = 0, j = 0;
  while (i < a.t_.size() || j < b.t_.size()) {
    if (j == b.t_.size() || (i < a.t_.size() && a.t_[i].first < b.t_[j].first)) {
      r.t_.push_back(a.t_[i++]);
    } else if (i == a.t_.size() || b.t_[j].first < a.t_[i].first) {
      r.t_.emplace_back(b.t_[j].first, sb * b.t_[j].second);
      ++j;
    } else {
      r.t_.emplace_back(a.t_[i].first, a.t_[i].second + sb * b.t_[j].second);
      ++i;
      ++j;
    }
  }
  return r;
}

SETBOUND_INLINE AffineExpr block_matrix(const std::vector<std::vector<AffineExpr>>& rows_in) {
  const size_t R = rows_in.size();
  if (R == 0) throw DimensionError("blocks: empty block matrix");
  const size_t C = rows_in[0].size();
  std::vector<Eigen::Index> rh(R, -1), cw(C, -1);
  for (size_t i = 0; i < R; ++i) {
    if (rows_in[i].size() != C)
      throw DimensionError("blocks: row " + std::to_string(i) + " has " + std::to_string(rows_in[i].size()) +
                           " blocks, expected " + std::to_string(C));
    for (size_t j = 0; j < C; ++j) {
      const AffineExpr& e = rows_in[i][j];
      if (e.is_placeholder()) continue;
      if ((rh[i] >= 0 && rh[i] != e.rows()) || (cw[j] >= 0 && cw[j] != e.cols()))
        throw DimensionError("blocks: block (" + std::to_string(i) + ", " + std::to_string(j) + ") has shape " +
                             AffineExpr::shape(e.rows(), e.cols()) + " which does not fit its row/column");
      rh[i] = e.rows();
      cw[j] = e.cols();
    }
  }
  for (size_t i = 0; i < R; ++i)
    if (rh[i] < 0) throw DimensionError("blocks: the height of block row " + std::to_string(i) + " is unknown");
  for (size_t j = 0; j < C; ++j)
    if (cw[j] < 0) throw DimensionError("blocks: the width of block column " + std::to_string(j) + " is unknown");
  Eigen::Index H = 0, W = 0;
  std::vector<Eigen::Index> r0(R), c0(C);
  for (size_t i = 0; i < R; ++i) r0[i] = H, H += rh[i];
  for (size_t j = 0; j < C; ++j) c0[j] = W, W += cw[j];
  Eigen::MatrixXd constant = Eigen::MatrixXd::Zero(H, W);
  // Gather coefficients per variable (sorted map via vector of pairs after sort).
  std::vector<std::pair<int, Eigen::MatrixXd>> acc;
  std::vector<int> pos;  // var → position in acc (grown on demand)
  for (size_t i = 0; i < R; ++i)
    for (size_t j = 0; j < C; ++j) {
      const AffineExpr& e = rows_in[i][j];
      if (e.is_placeholder()) continue;
      constant.block(r0[i], c0[j], rh[i], cw[j]) = e.constant();
      for (const auto& [v, M] : e.terms()) {
        if (static_cast<size_t>(v) >= pos.size()) pos.resize(static_cast<size_t>(v) + 1, -1);
        if (pos[static_cast<size_t>(v)] < 0) {
          pos[static_cast<size_t>(v)] = static_cast<int>(acc.size());
          acc.emplace_back(v, Eigen::MatrixXd::Zero(H, W));
        }
        acc[static_cast<size_t>(pos[static_cast<size_t>(v)])].second.block(r0[i], c0[j], rh[i], cw[j]) += M;
      }
    }
  std::sort(acc.begin(), acc.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return AffineExpr::from_terms(std::move(constant), std::move(acc));
}

SETBOUND_INLINE AffineExpr sym_block(const std::vector<std::vector<AffineExpr>>& lower) {
  const size_t R = lower.size();
  std::vector<std::vector<AffineExpr>> full(R, std::vector<AffineExpr>(R));
  for (size_t i = 0; i < R; ++i) {
    if (lower[i].size() != i + 1)
      throw DimensionError("blocks: row " + std::to_string(i) + " of a lower triangle must have " +
                           std::to_string(i + 1) + " blocks, got " + std::to_string(lower[i].size()));
    for (size_t j = 0; j <= i; ++j) {
      full[i][j] = lower[i][j];
      if (j < i && !lower[i][j].is_placeholder()) full[j][i] = lower[i][j].transpose();
    }
  }
  AffineExpr out = block_matrix(full);
  // Diagonal blocks must be symmetric themselves.
  if (!out.is_symmetric()) throw NotSymmetricError("blocks: a diagonal block is not symmetric");
  return out;
}

SETBOUND_INLINE Var Model::symmetric(int n) {
  if (n <= 0) throw DimensionError("n: matrix variable size must be > 0");
  Eigen::MatrixXi idx(n, n);
  std::vector<std::pair<int, Eigen::MatrixXd>> t;
  for (int j = 0; j < n; ++j)
    for (int i = j; i < n; ++i) {
      const int v = m_++;
      idx(i, j) = idx(j, i) = v;
      Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, n);
      E(i, j) = E(j, i) = 1.0;
      t.emplace_back(v, std::move(E));
    }
  return Var(AffineExpr::from_terms(Eigen::MatrixXd::Zero(n, n), std::move(t)), idx);
}

SETBOUND_INLINE Var Model::full(int r, int c) {
  if (r <= 0 || c <= 0) throw DimensionError("shape: matrix variable dimensions must be > 0");
  Eigen::MatrixXi idx(r, c);
  std::vector<std::pair<int, Eigen::MatrixXd>> t;
  for (int j = 0; j < c; ++j)
    for (int i = 0; i < r; ++i) {
      const int v = m_++;
      idx(i, j) = v;
      Eigen::MatrixXd E = Eigen::MatrixXd::Zero(r, c);
      E(i, j) = 1.0;
      t.emplace_back(v, std::move(E));
    }
  return Var(AffineExpr::from_terms(Eigen::MatrixXd::Zero(r, c), std::move(t)), idx);
}

SETBOUND_INLINE Var Model::diagonal(int n) {
  if (n <= 0) throw DimensionError("n: matrix variable size must be > 0");
  Eigen::MatrixXi idx = Eigen::MatrixXi::Constant(n, n, -1);
  std::vector<std::pair<int, Eigen::MatrixXd>> t;
  for (int i = 0; i < n; ++i) {
    const int v = m_++;
    idx(i, i) = v;
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, n);
    E(i, i) = 1.0;
    t.emplace_back(v, std::move(E));
  }
  return Var(AffineExpr::from_terms(Eigen::MatrixXd::Zero(n, n), std::move(t)), idx);
}

SETBOUND_INLINE int Model::add_lmi(const AffineExpr& expr, double margin) {
  require_finite(margin, "margin");
  if (expr.rows() != expr.cols() || expr.rows() == 0)
    throw DimensionError("lmi: expression must be square and non-empty, got " +
                         AffineExpr::shape(expr.rows(), expr.cols()));
  if (!expr.is_symmetric())
    throw NotSymmetricError("lmi: expression is not symmetric (build it with sym_block or symmetrise it)");
  Eigen::MatrixXd c = expr.constant();
  c.diagonal().array() -= margin;
  lmis_.push_back(AffineExpr::from_terms(std::move(c), expr.terms()));
  return static_cast<int>(lmis_.size()) - 1;
}

SETBOUND_INLINE void Model::add_equality(const AffineExpr& expr, const Eigen::MatrixXd& rhs) {
  if (rhs.rows() != expr.rows() || rhs.cols() != expr.cols())
    throw DimensionError("rhs: expected shape " + AffineExpr::shape(expr.rows(), expr.cols()) + ", got " +
                         AffineExpr::shape(rhs.rows(), rhs.cols()));
  require_finite(rhs, "rhs");
  const bool sym = expr.is_symmetric() && rhs.rows() == rhs.cols() &&
                   (rhs - rhs.transpose()).cwiseAbs().maxCoeff() <= kSymmetryTolerance * std::max(1.0, rhs.cwiseAbs().maxCoeff());
  for (Eigen::Index j = 0; j < expr.cols(); ++j)
    for (Eigen::Index i = sym ? j : 0; i < expr.rows(); ++i) {
      std::vector<std::pair<int, double>> coefs;
      for (const auto& [v, M] : expr.terms())
        if (M(i, j) != 0.0) coefs.emplace_back(v, M(i, j));
      const double b = rhs(i, j) - expr.constant()(i, j);
      if (coefs.empty()) {
        if (std::abs(b) > 1e-12 * std::max(1.0, std::abs(rhs(i, j))))
          throw InfeasibleError("equality: entry (" + std::to_string(i) + ", " + std::to_string(j) +
                                ") is a constant that differs from rhs");
        continue;
      }
      eq_rows_.push_back({std::move(coefs), b});
    }
}

SETBOUND_INLINE void Model::add_equality(const AffineExpr& expr) { add_equality(expr, Eigen::MatrixXd::Zero(expr.rows(), expr.cols())); }

SETBOUND_INLINE void Model::minimize(const AffineExpr& expr) {
  if (expr.rows() != 1 || expr.cols() != 1)
    throw DimensionError("objective: must be a 1x1 expression, got " + AffineExpr::shape(expr.rows(), expr.cols()));
  objective_ = expr;
}

SETBOUND_INLINE void Model::add_logdet(const AffineExpr& expr) {
  if (expr.rows() != expr.cols() || expr.rows() == 0 || !expr.is_symmetric())
    throw NotSymmetricError("logdet: expression must be square and symmetric");
  logdet_ = expr;
  has_logdet_ = true;
}

SETBOUND_INLINE void Model::clear_constraints() {
  lmis_.clear();
  eq_rows_.clear();
  objective_ = AffineExpr();
  has_logdet_ = false;
  logdet_ = AffineExpr();
}

SETBOUND_INLINE LmiProblem Model::build() const {
  if (m_ == 0) throw InvalidArgumentError("model: no variables");
  LmiProblem p(m_);
  for (const auto& e : lmis_) p.add_block_terms(e.constant(), e.terms());
  write_common(p);
  return p;
}

SETBOUND_INLINE void Model::update(LmiProblem& p) const {
  if (p.num_vars() != m_ || p.num_blocks() != static_cast<int>(lmis_.size()))
    throw DimensionError("problem: was not built from this model (variables/blocks differ)");
  for (size_t b = 0; b < lmis_.size(); ++b) {
    if (p.block(static_cast<int>(b)).size != lmis_[b].rows())
      throw DimensionError("problem: block " + std::to_string(b) + " changed size");
    p.update_block_terms(static_cast<int>(b), lmis_[b].constant(), lmis_[b].terms());
  }
  write_common(p);
}

SETBOUND_INLINE double Model::objective_constant() const { return objective_.is_placeholder() ? 0.0 : objective_.constant()(0, 0); }

SETBOUND_INLINE Eigen::MatrixXd Model::value(const Var& v, const Eigen::Ref<const Eigen::VectorXd>& x) const {
  if (x.size() != m_) throw DimensionError("x: expected " + std::to_string(m_) + " entries");
  Eigen::MatrixXd out(v.index().rows(), v.index().cols());
  for (Eigen::Index j = 0; j < out.cols(); ++j)
    for (Eigen::Index i = 0; i < out.rows(); ++i) out(i, j) = v.index()(i, j) < 0 ? 0.0 : x(v.index()(i, j));
  return out;
}

SETBOUND_INLINE double Model::scalar_value(const Var& v, const Eigen::Ref<const Eigen::VectorXd>& x) const { return value(v, x)(0, 0); }

SETBOUND_INLINE void Model::write_common(LmiProblem& p) const {
  Eigen::VectorXd c = Eigen::VectorXd::Zero(m_);
  if (!objective_.is_placeholder())
    for (const auto& [v, M] : objective_.terms()) c(v) += M(0, 0);
  p.set_objective(c);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(eq_rows_.size()), m_);
  Eigen::VectorXd b(static_cast<Eigen::Index>(eq_rows_.size()));
  for (size_t r = 0; r < eq_rows_.size(); ++r) {
    for (const auto& [v, a] : eq_rows_[r].coefs) A(static_cast<Eigen::Index>(r), v) += a;
    b(static_cast<Eigen::Index>(r)) = eq_rows_[r].rhs;
  }
  p.set_equalities(A, b);
  if (has_logdet_) p.set_logdet_terms(logdet_.constant(), logdet_.terms());
  else if (p.has_logdet()) p.clear_logdet();
}

}  // namespace lmi
}  // namespace setbound
