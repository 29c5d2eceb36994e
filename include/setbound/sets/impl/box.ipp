// setbound — definitions of the functions declared in setbound/sets/box.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/sets/box.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE Box::Box(const Eigen::Ref<const Eigen::VectorXd>& lo, const Eigen::Ref<const Eigen::VectorXd>& hi,
      const std::string& name)
    : lo_(lo), hi_(hi) {
  if (lo.size() != hi.size()) {
    std::ostringstream s;
    s << name << ": lower corner has " << lo.size() << " entries but upper corner has "
      << hi.size();
    throw DimensionError(s.str());
  }
  for (Eigen::Index i = 0; i < lo.size(); ++i)
    Interval::validate(lo(i), hi(i), name + " component " + std::to_string(i));
  if (is_empty()) *this = empty(size());
}

SETBOUND_INLINE Box Box::from_center_radius(const Eigen::Ref<const Eigen::VectorXd>& center,
                                const Eigen::Ref<const Eigen::VectorXd>& radius,
                                const std::string& name) {
  if (center.size() != radius.size()) {
    std::ostringstream s;
    s << name << ": centre has " << center.size() << " entries but radius has "
      << radius.size();
    throw DimensionError(s.str());
  }
  Box b;
  b.lo_.resize(center.size());
  b.hi_.resize(center.size());
  for (Eigen::Index i = 0; i < center.size(); ++i) {
    if (std::isnan(center(i)) || std::isnan(radius(i)))
      throw NotFiniteError(name + ": centre or radius entry " + std::to_string(i) + " is NaN");
    if (!std::isfinite(center(i)))
      throw NotFiniteError(name + ": centre entry " + std::to_string(i) + " is infinite");
    if (!(radius(i) >= 0)) {
      std::ostringstream s;
      s << name << ": radius entry " << i << " is " << radius(i) << "; it must be >= 0";
      throw InvalidArgumentError(s.str());
    }
    b.lo_(i) = rounding::sub_down(center(i), radius(i));
    b.hi_(i) = rounding::add_up(center(i), radius(i));
  }
  return b;
}

SETBOUND_INLINE Box Box::empty(Eigen::Index n) {
  Box b;
  b.lo_ = Eigen::VectorXd::Constant(n, rounding::kInf);
  b.hi_ = Eigen::VectorXd::Constant(n, -rounding::kInf);
  return b;
}

SETBOUND_INLINE Box Box::from_intervals(const std::vector<Interval>& xs) {
  Box b;
  b.lo_.resize(Eigen::Index(xs.size()));
  b.hi_.resize(Eigen::Index(xs.size()));
  for (std::size_t i = 0; i < xs.size(); ++i) {
    b.lo_(Eigen::Index(i)) = xs[i].lo();
    b.hi_(Eigen::Index(i)) = xs[i].hi();
  }
  if (b.is_empty()) return empty(b.size());
  return b;
}

SETBOUND_INLINE Interval Box::operator[](Eigen::Index i) const { return Interval::unchecked(lo_(i), hi_(i)); }

SETBOUND_INLINE bool Box::is_empty() const { return (lo_.array() > hi_.array()).any(); }

SETBOUND_INLINE Eigen::VectorXd Box::mid() const { return map([](const Interval& x) { return x.mid(); }); }

SETBOUND_INLINE Eigen::VectorXd Box::rad() const { return map([](const Interval& x) { return x.rad(); }); }

SETBOUND_INLINE Eigen::VectorXd Box::width() const { return map([](const Interval& x) { return x.width(); }); }

SETBOUND_INLINE double Box::max_width() const { return size() == 0 ? 0.0 : width().maxCoeff(); }

SETBOUND_INLINE double Box::max_radius() const { return size() == 0 ? 0.0 : rad().maxCoeff(); }

SETBOUND_INLINE double Box::volume() const {
  if (is_empty()) return 0.0;
  double v = 1.0;
  for (Eigen::Index i = 0; i < size(); ++i) v = rounding::mul_up(v, (*this)[i].width());
  return v;
}

SETBOUND_INLINE double Box::norm() const {
  if (size() == 0) return 0.0;
  return map([](const Interval& x) { return x.mag(); }).maxCoeff();
}

SETBOUND_INLINE std::pair<Eigen::VectorXd, Box> Box::split() const {
  const Eigen::VectorXd r = rad();
  Box d;
  d.lo_ = -r;
  d.hi_ = r;
  return {mid(), d};
}

SETBOUND_INLINE bool Box::contains(const Eigen::Ref<const Eigen::VectorXd>& p) const {
  return p.size() == size() && (lo_.array() <= p.array()).all() &&
         (p.array() <= hi_.array()).all();
}

SETBOUND_INLINE bool Box::subset(const Box& other) const {
  require_same_size(other, "other");
  return is_empty() ||
         ((other.lo_.array() <= lo_.array()).all() && (hi_.array() <= other.hi_.array()).all());
}

SETBOUND_INLINE Box Box::intersect(const Box& other) const {
  require_same_size(other, "other");
  return combine(other, [](const Interval& a, const Interval& b) { return a.intersect(b); });
}

SETBOUND_INLINE Box Box::hull(const Box& other) const {
  require_same_size(other, "other");
  if (is_empty()) return other;
  if (other.is_empty()) return *this;
  return combine(other, [](const Interval& a, const Interval& b) { return a.hull(b); });
}

SETBOUND_INLINE Box Box::operator+(const Box& o) const {
  require_same_size(o, "rhs");
  return combine(o, [](const Interval& a, const Interval& b) { return a + b; });
}

SETBOUND_INLINE Box Box::operator-(const Box& o) const {
  require_same_size(o, "rhs");
  return combine(o, [](const Interval& a, const Interval& b) { return a - b; });
}

SETBOUND_INLINE Box Box::operator-() const {
  Box b;
  b.lo_ = -hi_;
  b.hi_ = -lo_;
  return is_empty() ? empty(size()) : b;
}

SETBOUND_INLINE Box Box::operator*(double a) const {
  const Interval ia(a);  // validates a (NaN/inf rejected)
  std::vector<Interval> out;
  for (Eigen::Index i = 0; i < size(); ++i) out.push_back((*this)[i] * ia);
  return from_intervals(out);
}

SETBOUND_INLINE void Box::require_same_size(const Box& other, const std::string& name) const {
  if (other.size() != size()) {
    std::ostringstream s;
    s << name << ": box has " << other.size() << " components, expected " << size();
    throw DimensionError(s.str());
  }
}

SETBOUND_INLINE std::ostream& operator<<(std::ostream& os, const Box& x) {
  os << "[";
  for (Eigen::Index i = 0; i < x.size(); ++i) os << (i ? " x " : "") << x[i];
  return os << "]";
}

SETBOUND_INLINE Box multiply(const Eigen::Ref<const Eigen::MatrixXd>& M, const Box& x,
                    const std::string& name) {
  if (M.cols() != x.size()) {
    std::ostringstream s;
    s << name << ": matrix has " << M.cols() << " columns but the box has " << x.size()
      << " components";
    throw DimensionError(s.str());
  }
  for (Eigen::Index j = 0; j < M.cols(); ++j)
    for (Eigen::Index i = 0; i < M.rows(); ++i)
      if (!std::isfinite(M(i, j))) {
        std::ostringstream s;
        s << name << ": entry (" << i << ", " << j << ") is " << M(i, j)
          << "; all entries must be finite";
        throw NotFiniteError(s.str());
      }
  if (x.is_empty()) return Box::empty(M.rows());
  std::vector<Interval> y(std::size_t(M.rows()), Interval(0.0));
  for (Eigen::Index i = 0; i < M.rows(); ++i)
    for (Eigen::Index j = 0; j < M.cols(); ++j) y[std::size_t(i)] += M(i, j) * x[j];
  return Box::from_intervals(y);
}

}  // namespace setbound
