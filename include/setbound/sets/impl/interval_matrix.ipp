// setbound — definitions of the functions declared in setbound/sets/interval_matrix.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/sets/interval_matrix.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE IntervalMatrix::IntervalMatrix(const Eigen::Ref<const Eigen::MatrixXd>& lo,
                 const Eigen::Ref<const Eigen::MatrixXd>& hi, const std::string& name)
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

SETBOUND_INLINE IntervalMatrix IntervalMatrix::from_mid_rad(const Eigen::Ref<const Eigen::MatrixXd>& mid,
                                     const Eigen::Ref<const Eigen::MatrixXd>& rad,
                                     const std::string& name) {
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

SETBOUND_INLINE Interval IntervalMatrix::operator()(Eigen::Index i, Eigen::Index j) const {
  return Interval::unchecked(lo_(i, j), hi_(i, j));
}

SETBOUND_INLINE Eigen::MatrixXd IntervalMatrix::mid() const { return map([](const Interval& x) { return x.mid(); }); }

SETBOUND_INLINE Eigen::MatrixXd IntervalMatrix::rad() const { return map([](const Interval& x) { return x.rad(); }); }

SETBOUND_INLINE Eigen::MatrixXd IntervalMatrix::width() const { return map([](const Interval& x) { return x.width(); }); }

SETBOUND_INLINE bool IntervalMatrix::contains(const Eigen::Ref<const Eigen::MatrixXd>& N) const {
  return N.rows() == rows() && N.cols() == cols() && (lo_.array() <= N.array()).all() &&
         (N.array() <= hi_.array()).all();
}

SETBOUND_INLINE int IntervalMatrix::uncertain_count() const { return int((lo_.array() < hi_.array()).count()); }

SETBOUND_INLINE std::vector<Eigen::MatrixXd> IntervalMatrix::vertices(const std::string& name) const {
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

SETBOUND_INLINE Box IntervalMatrix::operator*(const Eigen::VectorXd& v) const {
  require_inner(v.size(), "v");
  for (Eigen::Index j = 0; j < v.size(); ++j)
    if (!std::isfinite(v(j)))
      throw NotFiniteError("v: entry " + std::to_string(j) + " is not finite");
  std::vector<Interval> y(std::size_t(rows()), Interval(0.0));
  for (Eigen::Index i = 0; i < rows(); ++i)
    for (Eigen::Index j = 0; j < cols(); ++j) y[std::size_t(i)] += (*this)(i, j) * v(j);
  return Box::from_intervals(y);
}

SETBOUND_INLINE Box IntervalMatrix::operator*(const Box& x) const {
  require_inner(x.size(), "x");
  if (x.is_empty()) return Box::empty(rows());
  std::vector<Interval> y(std::size_t(rows()), Interval(0.0));
  for (Eigen::Index i = 0; i < rows(); ++i)
    for (Eigen::Index j = 0; j < cols(); ++j) y[std::size_t(i)] += (*this)(i, j) * x[j];
  return Box::from_intervals(y);
}

SETBOUND_INLINE IntervalMatrix IntervalMatrix::operator*(const Eigen::MatrixXd& N) const {
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

SETBOUND_INLINE double IntervalMatrix::norm() const {
  double best = 0.0;
  for (Eigen::Index i = 0; i < rows(); ++i) {
    double s = 0.0;
    for (Eigen::Index j = 0; j < cols(); ++j) s = rounding::add_up(s, (*this)(i, j).mag());
    best = std::max(best, s);
  }
  return best;
}

SETBOUND_INLINE void IntervalMatrix::require_inner(Eigen::Index n, const std::string& name) const {
  if (n != cols()) {
    std::ostringstream s;
    s << name << ": has " << n << " rows/entries but the interval matrix has " << cols()
      << " columns";
    throw DimensionError(s.str());
  }
}

}  // namespace setbound
