// setbound — definitions of the functions declared in setbound/sets/polygon_projection.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "setbound/core/config.hpp"
#include "setbound/core/error.hpp"
#include "setbound/sets/box_lp.hpp"
#include "setbound/sets/polygon_projection.hpp"

namespace setbound {

SETBOUND_INLINE Eigen::MatrixXd projection_polygon(const ConstrainedZonotope& Z, Eigen::Index i, Eigen::Index j,
                                                   Eigen::Index max_vertices) {
  const Eigen::Index n = Z.dimension();
  if (i < 0 || i >= n) throw InvalidArgumentError("i: coordinate " + std::to_string(i) + " outside 0.." + std::to_string(n - 1));
  if (j < 0 || j >= n) throw InvalidArgumentError("j: coordinate " + std::to_string(j) + " outside 0.." + std::to_string(n - 1));
  if (i == j) throw InvalidArgumentError("j: must differ from i (" + std::to_string(i) + ")");
  if (max_vertices < 4) throw InvalidArgumentError("max_vertices: must be >= 4, got " + std::to_string(max_vertices));
  // The rounding box enters as two unconstrained generators (its projection is a box).
  const Eigen::Index m = Z.num_generators(), q = Z.num_constraints();
  Eigen::MatrixXd G2(2, m + 2);
  G2.leftCols(m) << Z.generators().row(i), Z.generators().row(j);
  G2.rightCols(2) = Eigen::Vector2d(Z.rounding_radius()(i), Z.rounding_radius()(j)).asDiagonal();
  Eigen::MatrixXd A(q, m + 2);
  A << Z.constraint_matrix(), Eigen::MatrixXd::Zero(q, 2);
  const Eigen::Vector2d c(Z.center()(i), Z.center()(j));
  if (m == 0 && q == 0) return c.transpose();
  BoxLP lp(A, Z.constraint_vector());
  if (lp.feasibility() == BoxLP::Feasibility::empty) return Eigen::MatrixXd(0, 2);
  auto support_point = [&](const Eigen::Vector2d& d) -> Eigen::Vector2d {
    const BoxLP::Bound bnd = lp.maximize(G2.transpose() * d);
    if (bnd.point.size() != G2.cols())
      throw NumericalError("projection_polygon: the LP found no support point (set almost empty)");
    return c + G2 * bnd.point;
  };
  // The scale of the set for the tolerance: its extent along the axes.
  std::vector<Eigen::Vector2d> poly;
  for (const Eigen::Vector2d& d : {Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1), Eigen::Vector2d(-1, 0),
                                  Eigen::Vector2d(0, -1)})
    poly.push_back(support_point(d));
  const double scale = std::max({(poly[0] - poly[2]).cwiseAbs().maxCoeff(), (poly[1] - poly[3]).cwiseAbs().maxCoeff(),
                                 c.cwiseAbs().maxCoeff(), 1e-300});
  const double tol = 1e-9 * scale;
  auto dedupe = [&](std::vector<Eigen::Vector2d>& v) {
    std::vector<Eigen::Vector2d> out;
    for (const auto& p : v)
      if (out.empty() || (p - out.back()).cwiseAbs().maxCoeff() > tol) out.push_back(p);
    while (out.size() > 1 && (out.front() - out.back()).cwiseAbs().maxCoeff() <= tol) out.pop_back();
    v.swap(out);
  };
  dedupe(poly);  // the axis points are in counter-clockwise order already (right, top, left, bottom)
  // Refine edge by edge: poly[k] → poly[k+1]; a new vertex is inserted after k and tested again.
  std::size_t k = 0;
  while (poly.size() >= 2 && k < poly.size() && static_cast<Eigen::Index>(poly.size()) < max_vertices) {
    const Eigen::Vector2d p = poly[k], r = poly[(k + 1) % poly.size()];
    const Eigen::Vector2d e = r - p;
    if (e.cwiseAbs().maxCoeff() <= tol) {
      ++k;
      continue;
    }
    Eigen::Vector2d d(e(1), -e(0));  // outward normal of a counter-clockwise edge
    d /= d.norm();
    const Eigen::Vector2d s = support_point(d);
    if (d.dot(s) > d.dot(p) + tol && (s - p).cwiseAbs().maxCoeff() > tol && (s - r).cwiseAbs().maxCoeff() > tol) {
      poly.insert(poly.begin() + static_cast<std::ptrdiff_t>(k + 1), s);
    } else {
      ++k;
    }
    if (poly.size() == 2 && k >= 2) break;  // a segment: both directions of its one edge tested
  }
  // Drop vertices on the line through their neighbours (the axis points may lie inside an edge).
  std::vector<Eigen::Vector2d> out;
  for (std::size_t a = 0; a < poly.size(); ++a) {
    const Eigen::Vector2d& prev = poly[(a + poly.size() - 1) % poly.size()];
    const Eigen::Vector2d& next = poly[(a + 1) % poly.size()];
    const Eigen::Vector2d u = poly[a] - prev, w = next - poly[a];
    if (poly.size() <= 2 || std::abs(u(0) * w(1) - u(1) * w(0)) > tol * (u.norm() + w.norm())) out.push_back(poly[a]);
  }
  Eigen::MatrixXd V(static_cast<Eigen::Index>(out.size()), 2);
  for (std::size_t a = 0; a < out.size(); ++a) V.row(static_cast<Eigen::Index>(a)) = out[a].transpose();
  return V;
}

}  // namespace setbound
