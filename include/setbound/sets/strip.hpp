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
  Strip(Eigen::VectorXd c, double y, double phi) : c_(std::move(c)), y_(y), phi_(phi) {
    if (c_.size() == 0) throw DimensionError("c: the strip normal must have at least one entry");
    require_finite(c_, "c");
    if (c_.cwiseAbs().maxCoeff() == 0.0)
      throw InvalidArgumentError("c: the strip normal must not be the zero vector");
    require_finite(y_, "y");
    require_nonnegative(phi_, "phi");
  }

  Eigen::Index dimension() const { return c_.size(); }
  const Eigen::VectorXd& normal() const { return c_; }
  double measurement() const { return y_; }
  double half_width() const { return phi_; }  ///< phi, in measurement units

  /// Euclidean distance between the two bounding hyperplanes: 2 phi / ||c||_2.
  double width() const { return 2.0 * phi_ / c_.norm(); }

  /// |c^T x - y| <= phi (1 + rel_tol) + rel_tol * |y|: the relative slack absorbs the
  /// rounding of the inner product when a sample sits on the boundary.
  bool contains(const Eigen::Ref<const Eigen::VectorXd>& x, double rel_tol = 1e-12) const {
    if (x.size() != c_.size())
      throw DimensionError("x: expected length " + std::to_string(c_.size()) + ", got " +
                           std::to_string(x.size()));
    const double r = c_.dot(x) - y_;
    const double scale = c_.cwiseAbs().dot(x.cwiseAbs()) + std::abs(y_) + phi_;
    return std::abs(r) <= phi_ + rel_tol * scale;
  }

  /// The strip as { c^T x <= y + phi } ∩ { -c^T x <= phi - y }.
  std::pair<HalfSpace, HalfSpace> half_spaces() const {
    return {HalfSpace{c_, y_ + phi_}, HalfSpace{-c_, phi_ - y_}};
  }

 private:
  Eigen::VectorXd c_;
  double y_;
  double phi_;
};

}  // namespace setbound
