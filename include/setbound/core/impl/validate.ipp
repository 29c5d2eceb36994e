// setbound — definitions of the functions declared in setbound/core/validate.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/core/validate.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace detail {

SETBOUND_INLINE std::string shape_string(Eigen::Index r, Eigen::Index c) {
  std::ostringstream s;
  s << r << "x" << c;
  return s.str();
}

}  // namespace detail
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE void require_finite(double v, const std::string& name) {
  if (!std::isfinite(v)) {
    std::ostringstream s;
    s << name << ": value is " << v << "; it must be finite";
    throw NotFiniteError(s.str());
  }
}

SETBOUND_INLINE void require_positive(double v, const std::string& name) {
  require_finite(v, name);
  if (!(v > 0)) {
    std::ostringstream s;
    s << name << ": must be > 0, got " << v;
    throw InvalidArgumentError(s.str());
  }
}

SETBOUND_INLINE void require_nonnegative(double v, const std::string& name) {
  require_finite(v, name);
  if (!(v >= 0)) {
    std::ostringstream s;
    s << name << ": must be >= 0, got " << v;
    throw InvalidArgumentError(s.str());
  }
}

}  // namespace setbound
