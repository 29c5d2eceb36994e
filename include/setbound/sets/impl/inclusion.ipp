// setbound — definitions of the functions declared in setbound/sets/inclusion.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/sets/inclusion.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace detail {

SETBOUND_INLINE void require_bounded_nonempty(const Interval& x, const std::string& name) {
  if (x.is_empty()) throw InvalidArgumentError(name + ": the interval is empty");
  if (!x.is_bounded()) throw InvalidArgumentError(name + ": the interval must be bounded");
}

SETBOUND_INLINE void require_bounded_nonempty(const Box& x, const std::string& name) {
  if (x.size() == 0) throw DimensionError(name + ": the box has dimension 0");
  if (x.is_empty()) throw InvalidArgumentError(name + ": the box is empty");
  if (!x.lo().allFinite() || !x.hi().allFinite())
    throw InvalidArgumentError(name + ": the box must be bounded");
}

SETBOUND_INLINE void require_result_size(Eigen::Index got, Eigen::Index want, const std::string& what) {
  if (got != want)
    throw DimensionError(what + ": expected size " + std::to_string(want) + ", got " + std::to_string(got));
}

}  // namespace detail
}  // namespace setbound
