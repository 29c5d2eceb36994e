// setbound — modelling helpers: write LMIs the way the spec prints them.
//
//   lmi::Model model;
//   auto P = model.symmetric(3);   auto Y = model.full(3, 2);   auto sigma = model.scalar();
//   model.add_lmi(lmi::sym_block({{beta * P},
//                                 {lmi::AffineExpr::zero(1, 3), sigma},
//                                 {P * A - Y * C, (P * E - Y * F) * w, P}}), 1e-9);
//   model.add_lmi(P - I);          // P ⪰ I
//   model.minimize(sigma);
//   lmi::LmiProblem prob = model.build();  ...  Eigen::MatrixXd Pv = model.value(P, x);
//
// An AffineExpr is Const + Σ_v x_v Coef_v (a matrix affine in the scalar variables x_v).
// Online estimators rebuild the constraints every step with new data: call
// clear_constraints(), add them again, then update(problem) writes the new values into an
// already-built LmiProblem without re-analysis (papers.md §1.2, §0.4).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/lmi/problem.hpp"

namespace setbound::lmi {

class AffineExpr {
 public:
  /// 0×0 placeholder: a zero block whose size is taken from its neighbours in sym_block.
  AffineExpr() = default;
  AffineExpr(const Eigen::MatrixXd& constant) : c_(constant) {}  // NOLINT: implicit on purpose
  AffineExpr(double v) : c_(Eigen::MatrixXd::Constant(1, 1, v)) {}  // NOLINT

  static AffineExpr zero(Eigen::Index rows, Eigen::Index cols);
  static AffineExpr identity(Eigen::Index n);

  Eigen::Index rows() const { return c_.rows(); }
  Eigen::Index cols() const { return c_.cols(); }
  bool is_placeholder() const { return c_.size() == 0; }
  const Eigen::MatrixXd& constant() const { return c_; }
  /// (variable, coefficient) pairs, sorted by variable, unique.
  const std::vector<std::pair<int, Eigen::MatrixXd>>& terms() const { return t_; }

  Eigen::MatrixXd evaluate(const Eigen::Ref<const Eigen::VectorXd>& x) const;

  AffineExpr transpose() const;

  AffineExpr operator-() const { return (*this) * -1.0; }

  friend AffineExpr operator+(const AffineExpr& a, const AffineExpr& b) { return combine(a, b, 1.0); }
  friend AffineExpr operator-(const AffineExpr& a, const AffineExpr& b) { return combine(a, b, -1.0); }

  friend AffineExpr operator*(const AffineExpr& a, double s) {
    AffineExpr r(Eigen::MatrixXd(a.c_ * s));
    r.t_.reserve(a.t_.size());
    for (const auto& [v, M] : a.t_) r.t_.emplace_back(v, M * s);
    return r;
  }
  friend AffineExpr operator*(double s, const AffineExpr& a) { return a * s; }

  /// Constant · expression. A 1×1 expression times a matrix is a scalar multiple.
  friend AffineExpr operator*(const Eigen::MatrixXd& L, const AffineExpr& a) {
    if (a.rows() == 1 && a.cols() == 1 && L.cols() != 1) return scalar_times(a, L);
    if (L.cols() != a.rows())
      throw DimensionError("expression: cannot multiply a " + shape(L.rows(), L.cols()) + " constant by a " +
                           shape(a.rows(), a.cols()) + " expression");
    AffineExpr r(Eigen::MatrixXd(L * a.c_));
    r.t_.reserve(a.t_.size());
    for (const auto& [v, M] : a.t_) r.t_.emplace_back(v, L * M);
    return r;
  }
  friend AffineExpr operator*(const AffineExpr& a, const Eigen::MatrixXd& R) {
    if (a.rows() == 1 && a.cols() == 1 && R.rows() != 1) return scalar_times(a, R);
    if (a.cols() != R.rows())
      throw DimensionError("expression: cannot multiply a " + shape(a.rows(), a.cols()) + " expression by a " +
                           shape(R.rows(), R.cols()) + " constant");
    AffineExpr r(Eigen::MatrixXd(a.c_ * R));
    r.t_.reserve(a.t_.size());
    for (const auto& [v, M] : a.t_) r.t_.emplace_back(v, M * R);
    return r;
  }
  /// Product of two expressions: allowed when one of them is constant (affine result).
  friend AffineExpr operator*(const AffineExpr& a, const AffineExpr& b) {
    if (a.t_.empty()) return a.c_ * b;
    if (b.t_.empty()) return a * b.c_;
    throw InvalidArgumentError("expression: product of two non-constant expressions is not affine");
  }

  AffineExpr& operator+=(const AffineExpr& b) { return *this = *this + b; }
  AffineExpr& operator-=(const AffineExpr& b) { return *this = *this - b; }

  /// Sub-block (rows i0.., cols j0..) of the expression.
  AffineExpr block(Eigen::Index i0, Eigen::Index j0, Eigen::Index r, Eigen::Index c) const;

  /// True when the constant and every coefficient are symmetric (relative tolerance).
  bool is_symmetric(double tol = kSymmetryTolerance) const;

  // Used by Model and block assembly.
  static AffineExpr from_terms(Eigen::MatrixXd c, std::vector<std::pair<int, Eigen::MatrixXd>> t);

  static std::string shape(Eigen::Index r, Eigen::Index c);

 private:
  static AffineExpr scalar_times(const AffineExpr& s, const Eigen::MatrixXd& M);
  static AffineExpr combine(const AffineExpr& a, const AffineExpr& b, double sb);

  Eigen::MatrixXd c_;
  std::vector<std::pair<int, Eigen::MatrixXd>> t_;
};

// Mixed arithmetic with Eigen expressions (e.g. P − MatrixXd::Identity(n, n)): one
// conversion to a plain matrix, then the AffineExpr operators.
template <class D>
AffineExpr operator+(const AffineExpr& a, const Eigen::MatrixBase<D>& b) { return a + AffineExpr(Eigen::MatrixXd(b)); }
template <class D>
AffineExpr operator+(const Eigen::MatrixBase<D>& a, const AffineExpr& b) { return AffineExpr(Eigen::MatrixXd(a)) + b; }
template <class D>
AffineExpr operator-(const AffineExpr& a, const Eigen::MatrixBase<D>& b) { return a - AffineExpr(Eigen::MatrixXd(b)); }
template <class D>
AffineExpr operator-(const Eigen::MatrixBase<D>& a, const AffineExpr& b) { return AffineExpr(Eigen::MatrixXd(a)) - b; }

/// A matrix variable: an AffineExpr whose entries are the scalar variables in `index`.
class Var : public AffineExpr {
 public:
  Var() = default;
  Var(AffineExpr e, Eigen::MatrixXi index) : AffineExpr(std::move(e)), index_(std::move(index)) {}
  const Eigen::MatrixXi& index() const { return index_; }

 private:
  Eigen::MatrixXi index_;
};

/// General block matrix from rows of expressions ({} placeholders are zero blocks sized by
/// their row and column neighbours).
AffineExpr block_matrix(const std::vector<std::vector<AffineExpr>>& rows_in);

/// Symmetric block matrix from its lower triangle: row i lists blocks (i,0)..(i,i); the
/// upper triangle is the transpose, so the result is symmetric by construction.
AffineExpr sym_block(const std::vector<std::vector<AffineExpr>>& lower);

class Model {
 public:
  /// Symmetric n×n matrix variable (n(n+1)/2 scalars).
  Var symmetric(int n);
  /// Full r×c matrix variable.
  Var full(int r, int c);
  Var scalar() { return full(1, 1); }
  /// Diagonal n×n matrix variable (n scalars).
  Var diagonal(int n);

  int num_vars() const { return m_; }

  /// expr ⪰ margin·I (margin > 0 turns a strict inequality of the spec into a margin).
  int add_lmi(const AffineExpr& expr, double margin = 0.0);
  /// expr ⪯ other  ⇔  other − expr ⪰ 0.
  int add_lmi_le(const AffineExpr& expr, const AffineExpr& other, double margin = 0.0) {
    return add_lmi(other - expr, margin);
  }

  /// expr == rhs entrywise (lower triangle only when both sides are symmetric).
  void add_equality(const AffineExpr& expr, const Eigen::MatrixXd& rhs);
  void add_equality(const AffineExpr& expr);

  /// Objective: minimise the 1×1 expression (replaces any previous one).
  void minimize(const AffineExpr& expr);
  void maximize(const AffineExpr& expr) { minimize(-expr); }
  /// Adds −log det(expr) to the objective (maximise log det expr); one such term.
  void add_logdet(const AffineExpr& expr);

  /// Removes constraints, objective and logdet term but keeps the variables, so that the
  /// same building code can run again with new data and update() an existing problem.
  void clear_constraints();

  LmiProblem build() const;

  /// Writes the current values into a problem built from the same model code; no
  /// re-analysis as long as the same variables touch the same blocks.
  void update(LmiProblem& p) const;

  /// Constant added to the objective (the LmiProblem objective is linear without offset).
  double objective_constant() const;

  Eigen::MatrixXd value(const Var& v, const Eigen::Ref<const Eigen::VectorXd>& x) const;
  double scalar_value(const Var& v, const Eigen::Ref<const Eigen::VectorXd>& x) const;

 private:
  struct EqRow {
    std::vector<std::pair<int, double>> coefs;
    double rhs;
  };
  void write_common(LmiProblem& p) const;

  int m_ = 0;
  std::vector<AffineExpr> lmis_;
  std::vector<EqRow> eq_rows_;
  AffineExpr objective_;
  bool has_logdet_ = false;
  AffineExpr logdet_;
};

}  // namespace setbound::lmi

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/lmi/impl/model.ipp"
#endif
