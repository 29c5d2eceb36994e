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
      const std::string& name = "box");

  /// centre ± radius (midpoint–radius form, eqs. 1.15–1.16). The radius must be >= 0 and nothing
  /// may be NaN. The corners are rounded outward, so the box contains the exact set.
  static Box from_center_radius(const Eigen::Ref<const Eigen::VectorXd>& center,
                                const Eigen::Ref<const Eigen::VectorXd>& radius,
                                const std::string& name = "box");

  static Box empty(Eigen::Index n);
  /// The degenerate box {p}.
  static Box point(const Eigen::Ref<const Eigen::VectorXd>& p, const std::string& name = "point") {
    return Box(p, p, name);
  }
  static Box from_intervals(const std::vector<Interval>& xs);

  Eigen::Index size() const { return lo_.size(); }
  const Eigen::VectorXd& lo() const { return lo_; }
  const Eigen::VectorXd& hi() const { return hi_; }
  /// Component i as an Interval.
  Interval operator[](Eigen::Index i) const;

  bool is_empty() const;

  /// Midpoint vector (eq. 1.11).
  Eigen::VectorXd mid() const;
  /// Radius vector, rounded up so that mid ± rad ⊇ box.
  Eigen::VectorXd rad() const;
  /// Width vector 𝕎 (eq. 1.13), rounded up.
  Eigen::VectorXd width() const;
  /// w = max_i width_i (eq. 1.12); 0 for the 0-dimensional box.
  double max_width() const;
  /// r = max_i rad_i (eq. 1.14).
  double max_radius() const;
  /// vol = Π_i width_i (eq. 1.17), an upper bound under rounding; 0 for the empty box.
  double volume() const;
  /// ‖[x]‖ = max_i |[x_i]| (§1.2.6, max of magnitudes).
  double norm() const;

  /// Midpoint–radius split [x] ⊆ m + [Δx] with [Δx] = [−rad, rad] (eqs. 1.15–1.16).
  std::pair<Eigen::VectorXd, Box> split() const;

  bool contains(const Eigen::Ref<const Eigen::VectorXd>& p) const;
  /// [this] ⊆ [other] (sizes must agree).
  bool subset(const Box& other) const;
  /// Intersection (eq. 1.32): componentwise, empty when any component is.
  Box intersect(const Box& other) const;
  /// Convex-hull union ⊔ (eq. 1.34).
  Box hull(const Box& other) const;

  Box operator+(const Box& o) const;
  Box operator-(const Box& o) const;
  Box operator-() const;
  Box operator*(double a) const;

  /// Throws DimensionError naming `name` unless `other` has this box's size.
  void require_same_size(const Box& other, const std::string& name) const;

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

std::ostream& operator<<(std::ostream& os, const Box& x);

/// M[x] for a real matrix M (p×n) and a box [x] (thesis §1, "real matrix × box"): the exact hull
/// [Mc − |M|r, Mc + |M|r] of {Mx : x ∈ [x]}.
///
/// Choice for rounding: it is evaluated row by row in interval arithmetic, y_i = Σ_j M_ij·[x_j].
/// Each x_j occurs once per row, so in exact arithmetic this *is* the hull above (no dependency
/// effect), and with directed rounding every partial sum encloses the exact one. Evaluating
/// Mc ± |M|r in floating point instead would need a separate bound on the rounding of c and r
/// (which are themselves rounded from lo/hi); the interval form needs none and stays exact when
/// all products and sums are exact. Unbounded components are fine: 0·[−inf, inf] = 0.
Box multiply(const Eigen::Ref<const Eigen::MatrixXd>& M, const Box& x,
                    const std::string& name = "M");

inline Box operator*(const Eigen::MatrixXd& M, const Box& x) { return multiply(M, x); }

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/box.ipp"
#endif
