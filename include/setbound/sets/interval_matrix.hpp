// setbound — interval matrices [M] = [M̲, M̄] (thesis §1.2.3, Remark 1.2, §1.2.6; papers.md §0.1).
//
// Entries are (bounded or unbounded) non-empty intervals. Products with vectors, boxes and real
// matrices are evaluated in the directed-rounding interval arithmetic of interval.hpp, so they
// enclose the exact sets under floating-point rounding.
#pragma once

#include <Eigen/Core>
#include <sstream>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/sets/box.hpp"
#include "setbound/sets/interval.hpp"

namespace setbound {

class IntervalMatrix {
 public:
  /// Vertex enumeration refuses matrices with more uncertain entries than this (2^20 matrices).
  static constexpr int kMaxVertexEntries = 20;

  IntervalMatrix() = default;

  /// [lo, hi] entrywise. DimensionError when the shapes differ, NotFiniteError on NaN,
  /// InvalidArgumentError when lo_ij > hi_ij (empty entries are not allowed in a matrix).
  IntervalMatrix(const Eigen::Ref<const Eigen::MatrixXd>& lo,
                 const Eigen::Ref<const Eigen::MatrixXd>& hi, const std::string& name = "M");

  /// mid ± rad (rad >= 0), corners rounded outward so the matrix contains the exact set.
  static IntervalMatrix from_mid_rad(const Eigen::Ref<const Eigen::MatrixXd>& mid,
                                     const Eigen::Ref<const Eigen::MatrixXd>& rad,
                                     const std::string& name = "M");

  /// The degenerate interval matrix [N, N].
  static IntervalMatrix point(const Eigen::Ref<const Eigen::MatrixXd>& N,
                              const std::string& name = "M") {
    return IntervalMatrix(N, N, name);
  }

  Eigen::Index rows() const { return lo_.rows(); }
  Eigen::Index cols() const { return lo_.cols(); }
  const Eigen::MatrixXd& lo() const { return lo_; }
  const Eigen::MatrixXd& hi() const { return hi_; }
  Interval operator()(Eigen::Index i, Eigen::Index j) const;

  /// mid[M] = (M̲ + M̄)/2 (eq. 1.20 as corrected in thesis §8), overflow-safe.
  Eigen::MatrixXd mid() const;
  /// rad[M], rounded up so that mid ± rad ⊇ [M].
  Eigen::MatrixXd rad() const;
  /// M̄ − M̲, rounded up.
  Eigen::MatrixXd width() const;

  bool contains(const Eigen::Ref<const Eigen::MatrixXd>& N) const;

  /// q: the number of uncertain entries (lo < hi); vert[M] has 2^q elements (papers.md §0.1).
  int uncertain_count() const;

  /// vert[M]: every matrix whose uncertain entries sit at one of their ends and whose certain
  /// entries keep their value. Uncertain entries are numbered in row-major order; in vertex v,
  /// uncertain entry k is at its upper end iff bit k of v is set. Throws InvalidArgumentError when
  /// q > kMaxVertexEntries and NotFiniteError when an uncertain entry has an infinite end.
  std::vector<Eigen::MatrixXd> vertices(const std::string& name = "M") const;

  /// [M]·v for a real vector: y_i = Σ_j [M_ij]·v_j. (Plain VectorXd/MatrixXd parameters rather
  /// than Eigen::Ref: a Ref<const VectorXd> also binds to a matrix, making the overloads ambiguous.)
  Box operator*(const Eigen::VectorXd& v) const;

  /// [M]·[x] = ([c_i]) with [c_i] = Σ_k [m_ik]·[x_k] (thesis Remark 1.2). It encloses
  /// {Mx : M ∈ [M], x ∈ [x]}; it is the hull when every entry of [x] appears once per row,
  /// which is the case here.
  Box operator*(const Box& x) const;

  /// [M]·N for a real matrix N: centre mid[M]·N and radius rad[M]·|N| ([Le2013] Property 5,
  /// papers.md §0.1). Evaluated as Σ_k [M_ik]·N_kj in interval arithmetic, which equals that
  /// centre/radius form in exact arithmetic and encloses it under rounding.
  IntervalMatrix operator*(const Eigen::MatrixXd& N) const;

  /// Eigen expressions: a compile-time column vector goes to [M]·v (a Box), anything else to
  /// [M]·N (an IntervalMatrix).
  template <class Derived>
  auto operator*(const Eigen::MatrixBase<Derived>& e) const {
    if constexpr (Derived::ColsAtCompileTime == 1)
      return (*this) * Eigen::VectorXd(e);
    else
      return (*this) * Eigen::MatrixXd(e);
  }

  /// ‖[M]‖ = max_i Σ_j |[m_ij]| (§1.2.6, max row sum of magnitudes), rounded up.
  double norm() const;

 private:
  void require_inner(Eigen::Index n, const std::string& name) const;
  template <class F>
  Eigen::MatrixXd map(F f) const {
    Eigen::MatrixXd m(rows(), cols());
    for (Eigen::Index i = 0; i < rows(); ++i)
      for (Eigen::Index j = 0; j < cols(); ++j) m(i, j) = f((*this)(i, j));
    return m;
  }

  Eigen::MatrixXd lo_, hi_;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/interval_matrix.ipp"
#endif
