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
                 const Eigen::Ref<const Eigen::MatrixXd>& hi, const std::string& name = "M")
      : lo_(lo), hi_(hi) {
    if (lo.rows() != hi.rows() || lo.cols() != hi.cols()) {
      std::ostringstream s;
      s << name << ": lower bound is " << lo.rows() << "x" << lo.cols() << " but upper bound is "
        << hi.rows() << "x" << hi.cols();
      throw DimensionError(s.str());
    }
    for (Eigen::Index i = 0; i < lo.rows(); ++i)
      for (Eigen::Index j = 0; j < lo.cols(); ++j) {
        const std::string entry =
            name + " entry (" + std::to_string(i) + ", " + std::to_string(j) + ")";
        Interval::validate(lo(i, j), hi(i, j), entry);
        if (Interval::is_empty_encoding(lo(i, j), hi(i, j)))
          throw InvalidArgumentError(entry + ": empty interval in a matrix");
      }
  }

  /// mid ± rad (rad >= 0), corners rounded outward so the matrix contains the exact set.
  static IntervalMatrix from_mid_rad(const Eigen::Ref<const Eigen::MatrixXd>& mid,
                                     const Eigen::Ref<const Eigen::MatrixXd>& rad,
                                     const std::string& name = "M") {
    if (mid.rows() != rad.rows() || mid.cols() != rad.cols()) {
      std::ostringstream s;
      s << name << ": midpoint is " << mid.rows() << "x" << mid.cols() << " but radius is "
        << rad.rows() << "x" << rad.cols();
      throw DimensionError(s.str());
    }
    Eigen::MatrixXd lo(mid.rows(), mid.cols()), hi(mid.rows(), mid.cols());
    for (Eigen::Index i = 0; i < mid.rows(); ++i)
      for (Eigen::Index j = 0; j < mid.cols(); ++j) {
        const std::string entry = " entry (" + std::to_string(i) + ", " + std::to_string(j) + ")";
        if (!std::isfinite(mid(i, j)) || std::isnan(rad(i, j)))
          throw NotFiniteError(name + ": midpoint or radius" + entry + " is not finite");
        if (!(rad(i, j) >= 0))
          throw InvalidArgumentError(name + ": radius" + entry + " must be >= 0");
        lo(i, j) = rounding::sub_down(mid(i, j), rad(i, j));
        hi(i, j) = rounding::add_up(mid(i, j), rad(i, j));
      }
    return IntervalMatrix(lo, hi, name);
  }

  /// The degenerate interval matrix [N, N].
  static IntervalMatrix point(const Eigen::Ref<const Eigen::MatrixXd>& N,
                              const std::string& name = "M") {
    return IntervalMatrix(N, N, name);
  }

  Eigen::Index rows() const { return lo_.rows(); }
  Eigen::Index cols() const { return lo_.cols(); }
  const Eigen::MatrixXd& lo() const { return lo_; }
  const Eigen::MatrixXd& hi() const { return hi_; }
  Interval operator()(Eigen::Index i, Eigen::Index j) const {
    return Interval::unchecked(lo_(i, j), hi_(i, j));
  }

  /// mid[M] = (M̲ + M̄)/2 (eq. 1.20 as corrected in thesis §8), overflow-safe.
  Eigen::MatrixXd mid() const { return map([](const Interval& x) { return x.mid(); }); }
  /// rad[M], rounded up so that mid ± rad ⊇ [M].
  Eigen::MatrixXd rad() const { return map([](const Interval& x) { return x.rad(); }); }
  /// M̄ − M̲, rounded up.
  Eigen::MatrixXd width() const { return map([](const Interval& x) { return x.width(); }); }

  bool contains(const Eigen::Ref<const Eigen::MatrixXd>& N) const {
    return N.rows() == rows() && N.cols() == cols() && (lo_.array() <= N.array()).all() &&
           (N.array() <= hi_.array()).all();
  }

  /// q: the number of uncertain entries (lo < hi); vert[M] has 2^q elements (papers.md §0.1).
  int uncertain_count() const { return int((lo_.array() < hi_.array()).count()); }

  /// vert[M]: every matrix whose uncertain entries sit at one of their ends and whose certain
  /// entries keep their value. Uncertain entries are numbered in row-major order; in vertex v,
  /// uncertain entry k is at its upper end iff bit k of v is set. Throws InvalidArgumentError when
  /// q > kMaxVertexEntries and NotFiniteError when an uncertain entry has an infinite end.
  std::vector<Eigen::MatrixXd> vertices(const std::string& name = "M") const {
    const int q = uncertain_count();
    if (q > kMaxVertexEntries) {
      std::ostringstream s;
      s << name << ": " << q << " uncertain entries give 2^" << q
        << " vertices; vertex enumeration is limited to kMaxVertexEntries = "
        << kMaxVertexEntries << " uncertain entries";
      throw InvalidArgumentError(s.str());
    }
    std::vector<std::pair<Eigen::Index, Eigen::Index>> uncertain;
    for (Eigen::Index i = 0; i < rows(); ++i)
      for (Eigen::Index j = 0; j < cols(); ++j)
        if (lo_(i, j) < hi_(i, j)) {
          if (!std::isfinite(lo_(i, j)) || !std::isfinite(hi_(i, j))) {
            std::ostringstream s;
            s << name << ": entry (" << i << ", " << j << ") = " << (*this)(i, j)
              << " is unbounded, so it has no vertices";
            throw NotFiniteError(s.str());
          }
          uncertain.emplace_back(i, j);
        }
    std::vector<Eigen::MatrixXd> out;
    out.reserve(std::size_t(1) << q);
    for (unsigned long v = 0; v < (1ul << q); ++v) {
      Eigen::MatrixXd V = lo_;
      for (int k = 0; k < q; ++k)
        if (v & (1ul << k)) V(uncertain[std::size_t(k)].first, uncertain[std::size_t(k)].second) =
                              hi_(uncertain[std::size_t(k)].first, uncertain[std::size_t(k)].second);
      out.push_back(std::move(V));
    }
    return out;
  }

  /// [M]·v for a real vector: y_i = Σ_j [M_ij]·v_j. (Plain VectorXd/MatrixXd parameters rather
  /// than Eigen::Ref: a Ref<const VectorXd> also binds to a matrix, making the overloads ambiguous.)
  Box operator*(const Eigen::VectorXd& v) const {
    require_inner(v.size(), "v");
    for (Eigen::Index j = 0; j < v.size(); ++j)
      if (!std::isfinite(v(j)))
        throw NotFiniteError("v: entry " + std::to_string(j) + " is not finite");
    std::vector<Interval> y(std::size_t(rows()), Interval(0.0));
    for (Eigen::Index i = 0; i < rows(); ++i)
      for (Eigen::Index j = 0; j < cols(); ++j) y[std::size_t(i)] += (*this)(i, j) * v(j);
    return Box::from_intervals(y);
  }

  /// [M]·[x] = ([c_i]) with [c_i] = Σ_k [m_ik]·[x_k] (thesis Remark 1.2). It encloses
  /// {Mx : M ∈ [M], x ∈ [x]}; it is the hull when every entry of [x] appears once per row,
  /// which is the case here.
  Box operator*(const Box& x) const {
    require_inner(x.size(), "x");
    if (x.is_empty()) return Box::empty(rows());
    std::vector<Interval> y(std::size_t(rows()), Interval(0.0));
    for (Eigen::Index i = 0; i < rows(); ++i)
      for (Eigen::Index j = 0; j < cols(); ++j) y[std::size_t(i)] += (*this)(i, j) * x[j];
    return Box::from_intervals(y);
  }

  /// [M]·N for a real matrix N: centre mid[M]·N and radius rad[M]·|N| ([Le2013] Property 5,
  /// papers.md §0.1). Evaluated as Σ_k [M_ik]·N_kj in interval arithmetic, which equals that
  /// centre/radius form in exact arithmetic and encloses it under rounding.
  IntervalMatrix operator*(const Eigen::MatrixXd& N) const {
    require_inner(N.rows(), "N");
    for (Eigen::Index i = 0; i < N.rows(); ++i)
      for (Eigen::Index j = 0; j < N.cols(); ++j)
        if (!std::isfinite(N(i, j)))
          throw NotFiniteError("N: entry (" + std::to_string(i) + ", " + std::to_string(j) +
                               ") is not finite");
    IntervalMatrix R;
    R.lo_.resize(rows(), N.cols());
    R.hi_.resize(rows(), N.cols());
    for (Eigen::Index i = 0; i < rows(); ++i)
      for (Eigen::Index j = 0; j < N.cols(); ++j) {
        Interval s(0.0);
        for (Eigen::Index k = 0; k < cols(); ++k) s += (*this)(i, k) * N(k, j);
        R.lo_(i, j) = s.lo();
        R.hi_(i, j) = s.hi();
      }
    return R;
  }

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
  double norm() const {
    double best = 0.0;
    for (Eigen::Index i = 0; i < rows(); ++i) {
      double s = 0.0;
      for (Eigen::Index j = 0; j < cols(); ++j) s = rounding::add_up(s, (*this)(i, j).mag());
      best = std::max(best, s);
    }
    return best;
  }

 private:
  void require_inner(Eigen::Index n, const std::string& name) const {
    if (n != cols()) {
      std::ostringstream s;
      s << name << ": has " << n << " rows/entries but the interval matrix has " << cols()
        << " columns";
      throw DimensionError(s.str());
    }
  }
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
