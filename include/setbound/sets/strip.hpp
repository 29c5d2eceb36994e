// setbound — strips S = { x : |c^T x - y| <= phi } (spec papers.md §0.1).
//
// A strip is the set of states consistent with one scalar measurement y = c^T x + v,
// |v| <= phi ([Le2013] §3.0: a multi-output measurement is n_y strips). It is the
// intersection of two half-spaces, which is how polytope code consumes it.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"

namespace setbound {

/// Closed half-space { x : a^T x <= b }.
struct HalfSpace {
  Eigen::VectorXd a;
  double b = 0.0;
};

class Strip {
 public:
  /// Validates: c finite and not identically zero ("c"), y finite ("y"), phi >= 0 finite
  /// ("phi"). A zero c would make the strip either all of R^n or empty, which is never
  /// what a measurement model means, so it is rejected.
  Strip(Eigen::VectorXd c, double y, double phi);

  Eigen::Index dimension() const { return c_.size(); }
  const Eigen::VectorXd& normal() const { return c_; }
  double measurement() const { return y_; }
  double half_width() const { return phi_; }  ///< phi, in measurement units

  /// Euclidean distance between the two bounding hyperplanes: 2 phi / ||c||_2.
  double width() const { return 2.0 * phi_ / c_.norm(); }

  /// |c^T x - y| <= phi (1 + rel_tol) + rel_tol * |y|: the relative slack absorbs the
  /// rounding of the inner product when a sample sits on the boundary.
  bool contains(const Eigen::Ref<const Eigen::VectorXd>& x, double rel_tol = 1e-12) const;

  /// The strip as { c^T x <= y + phi } ∩ { -c^T x <= phi - y }.
  std::pair<HalfSpace, HalfSpace> half_spaces() const;

 private:
  Eigen::VectorXd c_;
  double y_;
  double phi_;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/strip.ipp"
#endif
