// setbound — C ABI: ellipsoids, zonotopes and strips (setbound.h section "ellipsoids,
// zonotopes, strips"). Sets cross as arrays; every entry point rebuilds the C++ object,
// which validates its arguments, so the C, C++ and Python users see the same messages.
#include <algorithm>
#include <string>

#include "c_api_common.hpp"
#include "setbound/sets/ellipsoid.hpp"
#include "setbound/sets/strip.hpp"
#include "setbound/sets/zonotope.hpp"

namespace setbound::capi {
namespace {

Ellipsoid ellipsoid_arg(int n, const double* P, const double* c, double rho) {
  require_dimension(n, "n");
  return Ellipsoid(Eigen::MatrixXd(matrix_arg(P, n, n, "P")), Eigen::VectorXd(vector_arg(c, n, "c")), rho);
}

Zonotope zonotope_arg(int n, int m, const double* p, const double* H) {
  require_dimension(n, "n");
  require_dimension(m, "m", /*allow_zero=*/true);
  return Zonotope(Eigen::VectorXd(vector_arg(p, n, "p")), Eigen::MatrixXd(matrix_arg(H, n, m, "H")));
}

/// A batch of `count` row vectors of length n (row-major count x n); count may be 0.
ConstRowMap batch_arg(const double* data, int count, int n, const char* count_name, const char* name) {
  require_dimension(count, count_name, /*allow_zero=*/true);
  return matrix_arg(data, count, n, name);
}

template <class Out>
void require_output(Out* p, const char* name) {
  require_pointer(static_cast<const void*>(p), name);
}


}  // namespace
}  // namespace setbound::capi

using namespace setbound;
using namespace setbound::capi;

extern "C" {

int sb_ellipsoid_validate(int n, const double* P, const double* c, double rho) {
  return guard("sb_ellipsoid_validate", [&] { (void)ellipsoid_arg(n, P, c, rho); });
}

int sb_ellipsoid_bounding_box(int n, const double* P, const double* c, double rho, double* lo, double* hi) {
  return guard("sb_ellipsoid_bounding_box", [&] {
    const Ellipsoid E = ellipsoid_arg(n, P, c, rho);
    require_output(lo, "lo");
    require_output(hi, "hi");
    const BoundingBox box = E.bounding_box();
    VecMap(lo, n) = box.lo;
    VecMap(hi, n) = box.hi;
  });
}

int sb_ellipsoid_volume(int n, const double* P, const double* c, double rho, double* volume,
                        double* log_volume) {
  return guard("sb_ellipsoid_volume", [&] {
    const Ellipsoid E = ellipsoid_arg(n, P, c, rho);
    require_output(volume, "volume");
    const double lv = E.log_volume();
    *volume = std::exp(lv);
    if (log_volume) *log_volume = lv;
  });
}

int sb_ellipsoid_contains(int n, const double* P, const double* c, double rho, int npoints,
                          const double* points, double rel_tol, int* inside) {
  return guard("sb_ellipsoid_contains", [&] {
    const Ellipsoid E = ellipsoid_arg(n, P, c, rho);
    const ConstRowMap X = batch_arg(points, npoints, n, "npoints", "points");
    require_finite(X, "points");
    require_nonnegative(rel_tol, "rel_tol");
    if (npoints > 0) require_output(inside, "inside");
    for (int k = 0; k < npoints; ++k) inside[k] = E.contains(X.row(k).transpose(), rel_tol) ? 1 : 0;
  });
}

int sb_ellipsoid_support(int n, const double* P, const double* c, double rho, int ndir,
                         const double* directions, double* values) {
  return guard("sb_ellipsoid_support", [&] {
    const Ellipsoid E = ellipsoid_arg(n, P, c, rho);
    const ConstRowMap D = batch_arg(directions, ndir, n, "ndir", "directions");
    require_finite(D, "directions");
    if (ndir > 0) require_output(values, "values");
    for (int k = 0; k < ndir; ++k) values[k] = E.support(D.row(k).transpose());
  });
}

int sb_ellipsoid_affine_map(int n, const double* P, const double* c, double rho, const double* M,
                            const double* b, double* P_out, double* c_out, double* rho_out) {
  return guard("sb_ellipsoid_affine_map", [&] {
    const Ellipsoid E = ellipsoid_arg(n, P, c, rho);
    const Eigen::MatrixXd Mm = matrix_arg(M, n, n, "M");
    const Eigen::VectorXd bv = vector_arg(b, n, "b");
    require_output(P_out, "P_out");
    require_output(c_out, "c_out");
    require_output(rho_out, "rho_out");
    const Ellipsoid F = E.affine_map(Mm, bv);
    write_matrix(F.shape(), P_out);
    VecMap(c_out, n) = F.center();
    *rho_out = F.level();
  });
}

int sb_ellipsoid_level_for_shape(int n, const double* P, const double* c, double rho, const double* P_new,
                                 double* rho_out) {
  return guard("sb_ellipsoid_level_for_shape", [&] {
    const Ellipsoid E = ellipsoid_arg(n, P, c, rho);
    const Eigen::MatrixXd Pn = matrix_arg(P_new, n, n, "P_new");
    require_output(rho_out, "rho_out");
    *rho_out = E.level_for_shape(Pn);
  });
}

int sb_zonotope_validate(int n, int m, const double* p, const double* H) {
  return guard("sb_zonotope_validate", [&] { (void)zonotope_arg(n, m, p, H); });
}

int sb_zonotope_interval_hull(int n, int m, const double* p, const double* H, double* lo, double* hi) {
  return guard("sb_zonotope_interval_hull", [&] {
    const Zonotope Z = zonotope_arg(n, m, p, H);
    require_output(lo, "lo");
    require_output(hi, "hi");
    const BoundingBox box = Z.interval_hull();
    VecMap(lo, n) = box.lo;
    VecMap(hi, n) = box.hi;
  });
}

int sb_zonotope_volume(int n, int m, const double* p, const double* H, double* volume) {
  return guard("sb_zonotope_volume", [&] {
    const Zonotope Z = zonotope_arg(n, m, p, H);
    require_output(volume, "volume");
    *volume = Z.volume();
  });
}

int sb_zonotope_pradius(int n, int m, const double* p, const double* H, const double* P, double* radius,
                        double* vertex) {
  return guard("sb_zonotope_pradius", [&] {
    const Zonotope Z = zonotope_arg(n, m, p, H);
    const Eigen::MatrixXd Pm = matrix_arg(P, n, n, "P");
    require_output(radius, "radius");
    const Zonotope::PRadius r = Z.pradius_with_vertex(Pm);
    *radius = r.value;
    if (vertex && m > 0) VecMap(vertex, m) = r.vertex;
  });
}

int sb_zonotope_support(int n, int m, const double* p, const double* H, int ndir, const double* directions,
                        double* values) {
  return guard("sb_zonotope_support", [&] {
    const Zonotope Z = zonotope_arg(n, m, p, H);
    const ConstRowMap D = batch_arg(directions, ndir, n, "ndir", "directions");
    require_finite(D, "directions");
    if (ndir > 0) require_output(values, "values");
    for (int k = 0; k < ndir; ++k) values[k] = Z.support(D.row(k).transpose());
  });
}

int sb_zonotope_contains(int n, int m, const double* p, const double* H, int npoints, const double* points,
                         double rel_tol, int* inside) {
  return guard("sb_zonotope_contains", [&] {
    const Zonotope Z = zonotope_arg(n, m, p, H);
    const ConstRowMap X = batch_arg(points, npoints, n, "npoints", "points");
    require_finite(X, "points");
    require_nonnegative(rel_tol, "rel_tol");
    if (npoints > 0) require_output(inside, "inside");
    for (int k = 0; k < npoints; ++k) inside[k] = Z.contains(X.row(k).transpose(), rel_tol) ? 1 : 0;
  });
}

int sb_zonotope_reduce(int n, int m, const double* p, const double* H, int method, int limit, int* m_out,
                       double* H_out) {
  return guard("sb_zonotope_reduce", [&] {
    const Zonotope Z = zonotope_arg(n, m, p, H);
    require_output(m_out, "m_out");
    if (method != SB_REDUCE_COMBASTEL && method != SB_REDUCE_GIRARD && method != SB_REDUCE_PCA)
      throw InvalidArgumentError("method: unknown reduction method " + std::to_string(method) +
                                 " (SB_REDUCE_COMBASTEL = 1, SB_REDUCE_GIRARD = 2, SB_REDUCE_PCA = 3)");
    if (limit < n)
      throw InvalidArgumentError("limit: the generator limit must be >= n = " + std::to_string(n) +
                                 ", got " + std::to_string(limit));
    const int capacity = *m_out;
    const int needed = std::min(m, limit);
    if (capacity < needed) {
      *m_out = needed;
      throw BufferTooSmallError("m_out: H_out has room for " + std::to_string(capacity) +
                                " generators, the result has " + std::to_string(needed));
    }
    const Zonotope R = method == SB_REDUCE_COMBASTEL ? Z.reduce_combastel(limit)
                       : method == SB_REDUCE_GIRARD  ? Z.reduce_girard_to(limit)
                                                     : Z.reduce_pca(limit);
    if (R.num_generators() > capacity) throw InternalError("sb_zonotope_reduce: result larger than predicted");
    if (R.num_generators() > 0) require_output(H_out, "H_out");
    write_matrix(R.generators(), H_out);
    *m_out = static_cast<int>(R.num_generators());
  });
}

int sb_zonotope_intersect_strip(int n, int m, const double* p, const double* H, const double* c, double y,
                                double phi, const double* lambda, double* p_out, double* H_out) {
  return guard("sb_zonotope_intersect_strip", [&] {
    const Zonotope Z = zonotope_arg(n, m, p, H);
    const Strip S(Eigen::VectorXd(vector_arg(c, n, "c")), y, phi);
    const Eigen::VectorXd lam = vector_arg(lambda, n, "lambda");
    require_output(p_out, "p_out");
    require_output(H_out, "H_out");
    const Zonotope R = Z.intersect_strip_family(S, lam);
    VecMap(p_out, n) = R.center();
    write_matrix(R.generators(), H_out);
  });
}

int sb_zonotope_interval_linear_map(int k, int n, int m, const double* mid, const double* rad, const double* p,
                                    const double* H, double* p_out, double* H_out) {
  return guard("sb_zonotope_interval_linear_map", [&] {
    require_dimension(k, "k");
    const Zonotope Z = zonotope_arg(n, m, p, H);
    const Eigen::MatrixXd Mm = matrix_arg(mid, k, n, "mid");
    const Eigen::MatrixXd Rm = matrix_arg(rad, k, n, "rad");
    require_output(p_out, "p_out");
    require_output(H_out, "H_out");
    const Zonotope R = interval_linear_map(Mm, Rm, Z);
    VecMap(p_out, k) = R.center();
    write_matrix(R.generators(), H_out);
  });
}

int sb_strip_contains(int n, const double* c, double y, double phi, int npoints, const double* points,
                      double rel_tol, int* inside) {
  return guard("sb_strip_contains", [&] {
    require_dimension(n, "n");
    const Strip S(Eigen::VectorXd(vector_arg(c, n, "c")), y, phi);
    const ConstRowMap X = batch_arg(points, npoints, n, "npoints", "points");
    require_finite(X, "points");
    require_nonnegative(rel_tol, "rel_tol");
    if (npoints > 0) require_output(inside, "inside");
    for (int k = 0; k < npoints; ++k) inside[k] = S.contains(X.row(k).transpose(), rel_tol) ? 1 : 0;
  });
}

}  // extern "C"
