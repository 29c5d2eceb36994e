// setbound — the projection of a constrained zonotope onto two coordinates, as a polygon (for
// plots; issue 21 point 4).
//
// Why a separate concept: the queries of ConstrainedZonotope are certified outer bounds; a plot
// wants the shape itself. The projection P = {(x_i, x_j) : x ∈ Z} is a convex polygon whose
// vertices are support points of Z (LP maximisers). Starting from the four axis directions, each
// edge (p, q) of the current inner polygon is tested with its outward normal d: when the support
// point s in d is beyond the edge (dᵀs > dᵀp + tol), s is a new vertex between p and q; else the
// edge is a facet of P. With an exact LP this ends with P's vertices; here it is exact up to the
// simplex's rounding (tol = 1e-9 of the set's size), not certified.
#pragma once

#include <Eigen/Core>

#include "setbound/sets/constrained_zonotope.hpp"

namespace setbound {

/// Vertices (k × 2, counter-clockwise) of the projection of Z onto coordinates (i, j), i ≠ j
/// ("i", "j"). 0 rows when Z is certified empty, 1 for a point, 2 for a segment. At most
/// `max_vertices` vertices are found (then the polygon is an inner approximation whose missing
/// corners are below the tolerance of the plot); max_vertices >= 4 ("max_vertices").
Eigen::MatrixXd projection_polygon(const ConstrainedZonotope& Z, Eigen::Index i, Eigen::Index j,
                                   Eigen::Index max_vertices = 4096);

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/polygon_projection.ipp"
#endif
