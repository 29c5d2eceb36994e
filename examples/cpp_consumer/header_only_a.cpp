// The header-only way (setbound::headers, no SETBOUND_SEPARATE_COMPILATION): the same headers
// in two translation units of one program, which links only if every definition they pull in
// is inline (include/setbound/core/config.hpp). Compiling these two files is the cost the
// compiled library (setbound::setbound) saves a consumer: docs/cpp_usage.md.
#include <setbound/sets/ellipsoid.hpp>
#include <setbound/sets/zonotope.hpp>

#include <cmath>
#include <cstdio>

double zonotope_hull_width(const setbound::Zonotope& Z);  // header_only_b.cpp

int main() {
  const setbound::Ellipsoid E(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(), 4.0);
  const setbound::Zonotope Z(Eigen::Vector2d::Zero(), 2.0 * Eigen::Matrix2d::Identity());
  // The box of the disc of radius 2 and the square [-2, 2]^2 have the same first width, 4.
  const double w_e = E.bounding_box().hi(0) - E.bounding_box().lo(0);
  const double w_z = zonotope_hull_width(Z);
  std::printf("header-only: widths %.6f %.6f\n", w_e, w_z);
  if (std::abs(w_e - 4.0) > 1e-9 || std::abs(w_z - 4.0) > 1e-9) return 1;
  std::printf("header-only consumer ok\n");
  return 0;
}
