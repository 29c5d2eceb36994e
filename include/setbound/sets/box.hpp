// setbound — boxes (interval vectors), thesis §1 "Boxes" (eqs. 1.9–1.17, 1.30, 1.32–1.34) and
// the real-matrix × box product that Chapter 4 relies on.
//
// A Box stores its lower and upper corners as Eigen vectors. Components may be unbounded. A box
// with an empty component is the empty set; operations that can produce the empty set
// (intersection) return the canonical empty box, all of whose components are (+inf, −inf).
// Every operation encloses the exact set under floating-point rounding: endpoints come from the
// directed-rounding primitives of interval.hpp.
#pragma once

#include <Eigen/Core>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/sets/interval.hpp"

namespace setbound {

class Box {
 public:
  /// The 0-dimensional box.
  Box() = default;

  /// Box with corners lo and hi. Throws DimensionError when the sizes differ, NotFiniteError on
  /// NaN and InvalidArgumentError when lo_i > hi_i (messages start with `name`). A component
  /// given as the empty encoding (+inf, −inf) makes the whole box empty.
  Box(const Eigen::Ref<const Eigen::VectorXd>& lo, const Eigen::Ref<const Eigen::VectorXd>& hi,
      const std::string& name = "box")
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

  /// centre ± radius (midpoint–radius form, eqs. 1.15–1.16). The radius must be >= 0 and nothing
  /// may be NaN. The corners are rounded outward, so the box contains the exact set.
  static Box from_center_radius(const Eigen::Ref<const Eigen::VectorXd>& center,
                                const Eigen::Ref<const Eigen::VectorXd>& radius,
                                const std::string& name = "box") {
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

  static Box empty(Eigen::Index n) {
    Box b;
    b.lo_ = Eigen::VectorXd::Constant(n, rounding::kInf);
    b.hi_ = Eigen::VectorXd::Constant(n, -rounding::kInf);
    return b;
  }
  /// The degenerate box {p}.
  static Box point(const Eigen::Ref<const Eigen::VectorXd>& p, const std::string& name = "point") {
    return Box(p, p, name);
  }
  static Box from_intervals(const std::vector<Interval>& xs) {
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

  Eigen::Index size() const { return lo_.size(); }
  const Eigen::VectorXd& lo() const { return lo_; }
  const Eigen::VectorXd& hi() const { return hi_; }
  /// Component i as an Interval.
  Interval operator[](Eigen::Index i) const { return Interval::unchecked(lo_(i), hi_(i)); }

  bool is_empty() const { return (lo_.array() > hi_.array()).any(); }

  /// Midpoint vector (eq. 1.11).
  Eigen::VectorXd mid() const { return map([](const Interval& x) { return x.mid(); }); }
  /// Radius vector, rounded up so that mid ± rad ⊇ box.
  Eigen::VectorXd rad() const { return map([](const Interval& x) { return x.rad(); }); }
  /// Width vector 𝕎 (eq. 1.13), rounded up.
  Eigen::VectorXd width() const { return map([](const Interval& x) { return x.width(); }); }
  /// w = max_i width_i (eq. 1.12); 0 for the 0-dimensional box.
  double max_width() const { return size() == 0 ? 0.0 : width().maxCoeff(); }
  /// r = max_i rad_i (eq. 1.14).
  double max_radius() const { return size() == 0 ? 0.0 : rad().maxCoeff(); }
  /// vol = Π_i width_i (eq. 1.17), an upper bound under rounding; 0 for the empty box.
  double volume() const {
    if (is_empty()) return 0.0;
    double v = 1.0;
    for (Eigen::Index i = 0; i < size(); ++i) v = rounding::mul_up(v, (*this)[i].width());
    return v;
  }
  /// ‖[x]‖ = max_i |[x_i]| (§1.2.6, max of magnitudes).
  double norm() const {
    if (size() == 0) return 0.0;
    return map([](const Interval& x) { return x.mag(); }).maxCoeff();
  }

  /// Midpoint–radius split [x] ⊆ m + [Δx] with [Δx] = [−rad, rad] (eqs. 1.15–1.16).
  std::pair<Eigen::VectorXd, Box> split() const {
    const Eigen::VectorXd r = rad();
    Box d;
    d.lo_ = -r;
    d.hi_ = r;
    return {mid(), d};
  }

  bool contains(const Eigen::Ref<const Eigen::VectorXd>& p) const {
    return p.size() == size() && (lo_.array() <= p.array()).all() &&
           (p.array() <= hi_.array()).all();
  }
  /// [this] ⊆ [other] (sizes must agree).
  bool subset(const Box& other) const {
    require_same_size(other, "other");
    return is_empty() ||
           ((other.lo_.array() <= lo_.array()).all() && (hi_.array() <= other.hi_.array()).all());
  }
  /// Intersection (eq. 1.32): componentwise, empty when any component is.
  Box intersect(const Box& other) const {
    require_same_size(other, "other");
    return combine(other, [](const Interval& a, const Interval& b) { return a.intersect(b); });
  }
  /// Convex-hull union ⊔ (eq. 1.34).
  Box hull(const Box& other) const {
    require_same_size(other, "other");
    if (is_empty()) return other;
    if (other.is_empty()) return *this;
    return combine(other, [](const Interval& a, const Interval& b) { return a.hull(b); });
  }

  Box operator+(const Box& o) const {
    require_same_size(o, "rhs");
    return combine(o, [](const Interval& a, const Interval& b) { return a + b; });
  }
  Box operator-(const Box& o) const {
    require_same_size(o, "rhs");
    return combine(o, [](const Interval& a, const Interval& b) { return a - b; });
  }
  Box operator-() const {
    Box b;
    b.lo_ = -hi_;
    b.hi_ = -lo_;
    return is_empty() ? empty(size()) : b;
  }
  Box operator*(double a) const {
    const Interval ia(a);  // validates a (NaN/inf rejected)
    std::vector<Interval> out;
    for (Eigen::Index i = 0; i < size(); ++i) out.push_back((*this)[i] * ia);
    return from_intervals(out);
  }

  /// Throws DimensionError naming `name` unless `other` has this box's size.
  void require_same_size(const Box& other, const std::string& name) const {
    if (other.size() != size()) {
      std::ostringstream s;
      s << name << ": box has " << other.size() << " components, expected " << size();
      throw DimensionError(s.str());
    }
  }

 private:
  template <class F>
  Eigen::VectorXd map(F f) const {
    Eigen::VectorXd v(size());
    for (Eigen::Index i = 0; i < size(); ++i) v(i) = f((*this)[i]);
    return v;
  }
  template <class F>
  Box combine(const Box& o, F f) const {
    std::vector<Interval> out;
    out.reserve(std::size_t(size()));
    for (Eigen::Index i = 0; i < size(); ++i) out.push_back(f((*this)[i], o[i]));
    return from_intervals(out);
  }

  Eigen::VectorXd lo_, hi_;
};

inline Box operator*(double a, const Box& x) { return x * a; }

inline std::ostream& operator<<(std::ostream& os, const Box& x) {
  os << "[";
  for (Eigen::Index i = 0; i < x.size(); ++i) os << (i ? " x " : "") << x[i];
  return os << "]";
}

/// M[x] for a real matrix M (p×n) and a box [x] (thesis §1, "real matrix × box"): the exact hull
/// [Mc − |M|r, Mc + |M|r] of {Mx : x ∈ [x]}.
///
/// Choice for rounding: it is evaluated row by row in interval arithmetic, y_i = Σ_j M_ij·[x_j].
/// Each x_j occurs once per row, so in exact arithmetic this *is* the hull above (no dependency
/// effect), and with directed rounding every partial sum encloses the exact one. Evaluating
/// Mc ± |M|r in floating point instead would need a separate bound on the rounding of c and r
/// (which are themselves rounded from lo/hi); the interval form needs none and stays exact when
/// all products and sums are exact. Unbounded components are fine: 0·[−inf, inf] = 0.
inline Box multiply(const Eigen::Ref<const Eigen::MatrixXd>& M, const Box& x,
                    const std::string& name = "M") {
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

inline Box operator*(const Eigen::MatrixXd& M, const Box& x) { return multiply(M, x); }

}  // namespace setbound
