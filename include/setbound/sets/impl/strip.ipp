// setbound — definitions of the functions declared in setbound/sets/strip.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/sets/strip.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE Strip::Strip(Eigen::VectorXd c, double y, double phi)
    : c_(std::move(c)), y_(y), phi_(phi) {
  if (c_.size() == 0) throw DimensionError("c: the strip normal must have at least one entry");
  require_finite(c_, "c");
  if (c_.cwiseAbs().maxCoeff() == 0.0)
    throw InvalidArgumentError("c: the strip normal must not be the zero vector");
  require_finite(y_, "y");
  require_nonnegative(phi_, "phi");
}

SETBOUND_INLINE bool Strip::contains(const Eigen::Ref<const Eigen::VectorXd>& x, double rel_tol) const {
  if (x.size() != c_.size())
    throw DimensionError("x: expected length " + std::to_string(c_.size()) + ", got " +
                         std::to_string(x.size()));
  const double r = c_.dot(x) - y_;
  const double scale = c_.cwiseAbs().dot(x.cwiseAbs()) + std::abs(y_) + phi_;
  return std::abs(r) <= phi_ + rel_tol * scale;
}

SETBOUND_INLINE std::pair<HalfSpace, HalfSpace> Strip::half_spaces() const {
  return {HalfSpace{c_, y_ + phi_}, HalfSpace{-c_, phi_ - y_}};
}

}  // namespace setbound
