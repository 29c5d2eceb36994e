// Second translation unit of the header-only consumer (see header_only_a.cpp).
#include <setbound/sets/ellipsoid.hpp>
#include <setbound/sets/zonotope.hpp>

double zonotope_hull_width(const setbound::Zonotope& Z) {
  const auto hull = Z.interval_hull();
  return hull.hi(0) - hull.lo(0);
}
