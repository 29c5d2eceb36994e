// setbound — convex polytopes in small dimension (thesis §1.3, Def 1.6–1.7), held in both
// representations: H-rep {x : Hx ≤ b} and V-rep conv{v_1, …, v_p}.
//
// Convex hulls and vertex enumeration use Qhull (reentrant C library libqhull_r, Debian package
// libqhull-dev): a hull of the candidate points gives the vertices and the facets; vertex
// enumeration of an H-rep is the hull of the polar points h_i/(b_i − h_iᵀc) around an interior
// point c. The polytope must be full-dimensional (n ≥ 1; meant for n ≤ 6 — the cost of a hull
// grows quickly with n and with the number of points).
//
// Guarantee kept in floating point: every point a polytope was built from satisfies the stored
// H-rep exactly as evaluated (each b_i is raised to max_j h_iᵀp_j after the hull), so operations
// whose result is the hull of computed points (linear map, Minkowski sums) never lose a computed
// point. The rows of H have unit Euclidean norm, so `contains(x, tol)` tolerates a distance tol.
//
// Note: this header includes <libqhull_r/libqhull_r.h>, which defines a few plain macros
// (True, False, boolT, coordT, pointT, realT). Link Qhull::qhull_r (setbound::headers does).
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/box.hpp"
#include "setbound/sets/zonotope.hpp"

extern "C" {
#include <libqhull_r/libqhull_r.h>
#include <libqhull_r/poly_r.h>
#include <libqhull_r/qset_r.h>
}

namespace setbound {

namespace detail {

/// Result of one Qhull run on points (columns of an n×p matrix).
struct QhullFacets {
  std::vector<int> vertex_ids;              // indices of the input points that are hull vertices
  Eigen::MatrixXd normals;                  // m×n outward unit normals
  Eigen::VectorXd offsets;                  // m: normal·x + offset = 0 on the facet
  std::vector<std::vector<int>> facet_vertices;  // input-point indices on each facet
};

/// Runs Qhull ("qhull", merged facets) on the columns of pts. Throws InvalidArgumentError
/// (message starting with `name`) when the points do not span ℝⁿ, NumericalError on any other
/// Qhull failure (with Qhull's own message).
QhullFacets qhull_facets(const Eigen::MatrixXd& pts, const std::string& name);

void require_polytope_dim(Eigen::Index got, Eigen::Index want, const std::string& name);

}  // namespace detail

/// A bounded, full-dimensional convex polytope with both representations.
///   V-rep: vertices() is n×p, one vertex per column;
///   H-rep: {x : H x ≤ b}, H is m×n with unit-norm rows, no redundant rows (up to Qhull merging).
class Polytope {
 public:
  Polytope() = default;

  /// conv(points), points given as the columns of an n×p matrix (n ≥ 1). Throws
  /// InvalidArgumentError when the points do not span ℝⁿ, NotFiniteError on NaN/Inf.
  static Polytope from_vertices(const Eigen::MatrixXd& points, const std::string& name = "points");

  /// {x : H x ≤ b} (bounded, full-dimensional) with a point `interior` strictly inside
  /// (H·interior < b). Vertex enumeration by the polar hull. Throws InvalidArgumentError when the
  /// set is unbounded, when `interior` is not strictly inside, or on bad shapes.
  static Polytope from_halfspaces(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                                  const Eigen::VectorXd& interior,
                                  const std::string& name = "halfspaces");

  /// The box as a polytope (2ⁿ vertices). The box must be bounded and non-degenerate.
  static Polytope from_box(const Box& box, const std::string& name = "box");

  Eigen::Index dimension() const { return V_.rows(); }
  Eigen::Index num_vertices() const { return V_.cols(); }
  Eigen::Index num_facets() const { return H_.rows(); }
  const Eigen::MatrixXd& vertices() const { return V_; }
  const Eigen::MatrixXd& H() const { return H_; }
  const Eigen::VectorXd& b() const { return b_; }

  /// H x ≤ b + tol (tol ≥ 0 is a distance, since the rows of H have unit norm).
  bool contains(const Eigen::Ref<const Eigen::VectorXd>& x, double tol = 1e-9) const;
  /// other ⊆ this (every vertex of other satisfies this H-rep up to tol).
  bool contains(const Polytope& other, double tol = 1e-9) const;
  /// Largest violation max_i (h_iᵀx − b_i) (≤ 0 inside).
  double violation(const Eigen::Ref<const Eigen::VectorXd>& x) const;

  /// h(d) = max_{x ∈ P} dᵀx (over the vertices).
  double support(const Eigen::Ref<const Eigen::VectorXd>& d) const;

  /// The exact interval hull (componentwise min/max over the vertices).
  Box bounding_box() const;
  /// max_i ‖v_i‖₂ (the radius of the smallest origin-centred ball containing the polytope).
  double max_vertex_norm() const;

  /// M·P for a k×n matrix M whose image is full-dimensional in ℝᵏ (e.g. M square nonsingular).
  Polytope linear_map(const Eigen::MatrixXd& M, const std::string& name = "M") const;
  /// conv{v_i + w_j}: Minkowski sum with another polytope (pairwise vertex sums, then hull).
  Polytope minkowski_sum(const Polytope& other) const;
  /// P ⊕ conv(points) for arbitrary points (columns, dimension n); the points need not span ℝⁿ.
  Polytope minkowski_sum_points(const Eigen::MatrixXd& points, const std::string& name = "points") const;
  /// P ⊕ box (a degenerate box — zero widths — is allowed; it must be bounded and non-empty).
  Polytope minkowski_sum(const Box& box) const;
  /// P ⊕ Z (Z a zonotope p ⊕ H·[−1,1]^q: q segment sums, each followed by a hull).
  Polytope minkowski_sum(const Zonotope& Z) const;
  /// a·P about the origin (a > 0).
  Polytope scaled(double a) const;
  /// P + t.
  Polytope translated(const Eigen::Ref<const Eigen::VectorXd>& t) const;

 private:
  static Eigen::MatrixXd pairwise_sums(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);
  Polytope add_segments(const Eigen::VectorXd& c, const Eigen::MatrixXd& G) const;
  static void check_box(const Box& box, const std::string& name, bool full);

  Eigen::MatrixXd V_;
  Eigen::MatrixXd H_;
  Eigen::VectorXd b_;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/polytope.ipp"
#endif
