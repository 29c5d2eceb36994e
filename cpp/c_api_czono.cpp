// setbound — C ABI: constrained zonotopes (sets/constrained_zonotope.hpp, polygon_projection.hpp) and
// the estimators CZN-A / CZN-B (estimators/constrained_zonotopic/estimator.hpp). Sets cross as arrays
// (c, G, A, b, r); the estimator is an opaque handle.
#include <algorithm>
#include <limits>
#include <memory>
#include <string>

#include "c_api_handles.hpp"
#include "setbound/estimators/constrained_zonotopic/estimator.hpp"
#include "setbound/sets/constrained_zonotope.hpp"
#include "setbound/sets/polygon_projection.hpp"

using namespace setbound;
using namespace setbound::capi;

struct sb_czonotopic {
  ConstrainedZonotopicEstimator estimator;
};

namespace setbound::capi {
namespace {

/// The caller's arrays as a constrained zonotope; `which` prefixes the argument names ("", "1", "2").
ConstrainedZonotope czono_arg(int n, int ng, int nc, const double* c, const double* G, const double* A,
                              const double* b, const double* r, const std::string& which = "") {
  const std::string sc = "c" + which, sG = "G" + which, sA = "A" + which, sb = "b" + which, sr = "r" + which;
  require_dimension(n, "n");
  require_dimension(ng, ("ng" + which).c_str(), true);
  require_dimension(nc, ("nc" + which).c_str(), true);
  Eigen::VectorXd cv = vector_arg(c, n, sc.c_str());
  Eigen::MatrixXd Gm = ng > 0 ? Eigen::MatrixXd(matrix_arg(G, n, ng, sG.c_str())) : Eigen::MatrixXd(n, 0);
  Eigen::MatrixXd Am = (nc > 0 && ng > 0) ? Eigen::MatrixXd(matrix_arg(A, nc, ng, sA.c_str())) : Eigen::MatrixXd::Zero(nc, ng);
  Eigen::VectorXd bv = nc > 0 ? Eigen::VectorXd(vector_arg(b, nc, sb.c_str())) : Eigen::VectorXd(0);
  Eigen::VectorXd rv = r != nullptr ? Eigen::VectorXd(ConstVecMap(r, n)) : Eigen::VectorXd::Zero(n);
  try {
    return ConstrainedZonotope::from_parts(std::move(cv), std::move(Gm), std::move(Am), std::move(bv), std::move(rv));
  } catch (const Error& e) {
    if (which.empty()) throw;
    // Name the operand: "c2: ..." instead of "c: ...".
    const std::string msg = e.what();
    const std::size_t colon = msg.find(':');
    const std::string head = colon == std::string::npos ? std::string() : msg.substr(0, colon);
    const std::string text = (head.size() == 1) ? head + which + msg.substr(colon) : msg;
    if (e.code() == SB_ERR_DIMENSION) throw DimensionError(text);
    if (e.code() == SB_ERR_NOT_FINITE) throw NotFiniteError(text);
    throw InvalidArgumentError(text);
  }
}

/// Writes a set into the caller's buffers after checking their capacities (in/out ng_out, nc_out).
void czono_out(const ConstrainedZonotope& Z, int* ng_out, int* nc_out, double* c_out, double* G_out, double* A_out,
               double* b_out, double* r_out) {
  require_pointer(ng_out, "ng_out");
  require_pointer(nc_out, "nc_out");
  const int cap_g = *ng_out, cap_c = *nc_out;
  const int ng = static_cast<int>(Z.num_generators()), nc = static_cast<int>(Z.num_constraints());
  if (cap_g < ng || cap_c < nc) {
    *ng_out = ng;
    *nc_out = nc;
    throw BufferTooSmallError("ng_out: the buffers hold " + std::to_string(cap_g) + " generators and " +
                              std::to_string(cap_c) + " constraints, the result has " + std::to_string(ng) + " and " +
                              std::to_string(nc));
  }
  require_pointer(c_out, "c_out");
  require_pointer(r_out, "r_out");
  if (ng > 0) require_pointer(G_out, "G_out");
  if (nc > 0) require_pointer(b_out, "b_out");
  if (nc > 0 && ng > 0) require_pointer(A_out, "A_out");
  write_vector(Z.center(), c_out);
  write_matrix(Z.generators(), G_out);
  write_matrix(Z.constraint_matrix(), A_out);
  write_vector(Z.constraint_vector(), b_out);
  write_vector(Z.rounding_radius(), r_out);
  *ng_out = ng;
  *nc_out = nc;
}

ZonotopeReduction czono_technique_arg(int technique) {
  if (technique == SB_REDUCE_GIRARD) return ZonotopeReduction::Girard;
  if (technique == SB_REDUCE_PCA) return ZonotopeReduction::Pca;
  throw InvalidArgumentError("technique: expected SB_REDUCE_GIRARD (2) or SB_REDUCE_PCA (3), got " +
                             std::to_string(technique));
}

/// A limit argument: -1 (the default) or 0 .. SB_CZN_MAX_SIZE.
Eigen::Index czono_limit_arg(int v, const char* name) {
  if (v < -1 || v > SB_CZN_MAX_SIZE)
    throw InvalidArgumentError(std::string(name) + ": expected -1 (default) or 0.." + std::to_string(SB_CZN_MAX_SIZE) +
                               ", got " + std::to_string(v));
  return v;
}

ConstrainedZonotopicEstimator& czn_arg(sb_czonotopic* e) {
  require_pointer(e, "estimator");
  return e->estimator;
}
const ConstrainedZonotopicEstimator& czn_arg(const sb_czonotopic* e) {
  require_pointer(e, "estimator");
  return e->estimator;
}

}  // namespace
}  // namespace setbound::capi

extern "C" {

int sb_czono_validate(int n, int ng, int nc, const double* c, const double* G, const double* A, const double* b,
                      const double* r) {
  return guard("sb_czono_validate", [&] { czono_arg(n, ng, nc, c, G, A, b, r); });
}

int sb_czono_interval_hull(int n, int ng, int nc, const double* c, const double* G, const double* A, const double* b,
                           const double* r, double* lo, double* hi, int* empty) {
  return guard("sb_czono_interval_hull", [&] {
    const ConstrainedZonotope Z = czono_arg(n, ng, nc, c, G, A, b, r);
    require_pointer(lo, "lo");
    require_pointer(hi, "hi");
    const BoundingBox box = Z.interval_hull();
    VecMap(lo, n) = box.lo;
    VecMap(hi, n) = box.hi;
    if (empty != nullptr) *empty = (n > 0 && !(box.lo(0) <= box.hi(0))) ? 1 : 0;
  });
}

int sb_czono_support(int n, int ng, int nc, const double* c, const double* G, const double* A, const double* b,
                     const double* r, int ndir, const double* directions, double* values) {
  return guard("sb_czono_support", [&] {
    const ConstrainedZonotope Z = czono_arg(n, ng, nc, c, G, A, b, r);
    require_dimension(ndir, "ndir", true);
    if (ndir == 0) return;
    const Eigen::MatrixXd D = matrix_arg(directions, ndir, n, "directions");
    require_finite(D, "directions");
    require_pointer(values, "values");
    const BoundingBox box = Z.image_bounds(D);  // one LP basis for every direction
    VecMap(values, ndir) = box.hi;
  });
}

int sb_czono_contains(int n, int ng, int nc, const double* c, const double* G, const double* A, const double* b,
                      const double* r, int npoints, const double* points, int* inside) {
  return guard("sb_czono_contains", [&] {
    const ConstrainedZonotope Z = czono_arg(n, ng, nc, c, G, A, b, r);
    require_dimension(npoints, "npoints", true);
    if (npoints == 0) return;
    const Eigen::MatrixXd X = matrix_arg(points, npoints, n, "points");
    require_finite(X, "points");
    require_pointer(inside, "inside");
    for (int k = 0; k < npoints; ++k) inside[k] = Z.contains(X.row(k).transpose()) ? 1 : 0;
  });
}

int sb_czono_emptiness(int n, int ng, int nc, const double* c, const double* G, const double* A, const double* b,
                       const double* r, int* empty, int* conclusive, double* certificate, double* margin) {
  return guard("sb_czono_emptiness", [&] {
    const ConstrainedZonotope Z = czono_arg(n, ng, nc, c, G, A, b, r);
    require_pointer(empty, "empty");
    const ConstrainedZonotope::Emptiness e = Z.emptiness();
    *empty = e.empty ? 1 : 0;
    if (conclusive != nullptr) *conclusive = e.conclusive ? 1 : 0;
    if (margin != nullptr) *margin = e.empty ? e.margin : 0.0;
    if (certificate != nullptr && nc > 0) {
      if (e.empty) VecMap(certificate, nc) = e.certificate;
      else VecMap(certificate, nc).setZero();
    }
  });
}

int sb_czono_linear_map(int n, int ng, int nc, const double* c, const double* G, const double* A, const double* b,
                        const double* r, int k, const double* K, double* c_out, double* G_out, double* r_out) {
  return guard("sb_czono_linear_map", [&] {
    const ConstrainedZonotope Z = czono_arg(n, ng, nc, c, G, A, b, r);
    require_dimension(k, "k");
    const ConstrainedZonotope R = Z.linear_map(matrix_arg(K, k, n, "K"));
    require_pointer(c_out, "c_out");
    require_pointer(r_out, "r_out");
    if (ng > 0) require_pointer(G_out, "G_out");
    write_vector(R.center(), c_out);
    write_matrix(R.generators(), G_out);
    write_vector(R.rounding_radius(), r_out);
  });
}

int sb_czono_minkowski_sum(int n, int ng1, int nc1, const double* c1, const double* G1, const double* A1,
                           const double* b1, const double* r1, int ng2, int nc2, const double* c2, const double* G2,
                           const double* A2, const double* b2, const double* r2, int* ng_out, int* nc_out,
                           double* c_out, double* G_out, double* A_out, double* b_out, double* r_out) {
  return guard("sb_czono_minkowski_sum", [&] {
    const ConstrainedZonotope Z1 = czono_arg(n, ng1, nc1, c1, G1, A1, b1, r1, "1");
    const ConstrainedZonotope Z2 = czono_arg(n, ng2, nc2, c2, G2, A2, b2, r2, "2");
    czono_out(Z1.minkowski_sum(Z2), ng_out, nc_out, c_out, G_out, A_out, b_out, r_out);
  });
}

int sb_czono_intersect(int n, int ng1, int nc1, const double* c1, const double* G1, const double* A1,
                       const double* b1, const double* r1, int k, int ng2, int nc2, const double* c2,
                       const double* G2, const double* A2, const double* b2, const double* r2, const double* R,
                       int* ng_out, int* nc_out, double* c_out, double* G_out, double* A_out, double* b_out,
                       double* r_out) {
  return guard("sb_czono_intersect", [&] {
    const ConstrainedZonotope Z1 = czono_arg(n, ng1, nc1, c1, G1, A1, b1, r1, "1");
    require_dimension(k, "k");
    const ConstrainedZonotope Z2 = czono_arg(k, ng2, nc2, c2, G2, A2, b2, r2, "2");
    if (R == nullptr && k != n)
      throw DimensionError("R: NULL means the identity, which needs k = n = " + std::to_string(n) + ", got k = " +
                           std::to_string(k));
    const ConstrainedZonotope out = R == nullptr ? Z1.intersect(Z2) : Z1.intersect(Z2, matrix_arg(R, k, n, "R"));
    czono_out(out, ng_out, nc_out, c_out, G_out, A_out, b_out, r_out);
  });
}

int sb_czono_intersect_strip(int n, int ng, int nc, const double* c, const double* G, const double* A, const double* b,
                             const double* r, const double* h, double y, double sigma, int* ng_out, int* nc_out,
                             double* c_out, double* G_out, double* A_out, double* b_out, double* r_out) {
  return guard("sb_czono_intersect_strip", [&] {
    const ConstrainedZonotope Z = czono_arg(n, ng, nc, c, G, A, b, r);
    const Strip s(Eigen::VectorXd(vector_arg(h, n, "h")), y, sigma);
    czono_out(Z.intersect_strip(s), ng_out, nc_out, c_out, G_out, A_out, b_out, r_out);
  });
}

int sb_czono_intersect_halfspace(int n, int ng, int nc, const double* c, const double* G, const double* A,
                                 const double* b, const double* r, const double* h, double d, int* ng_out,
                                 int* nc_out, double* c_out, double* G_out, double* A_out, double* b_out,
                                 double* r_out) {
  return guard("sb_czono_intersect_halfspace", [&] {
    const ConstrainedZonotope Z = czono_arg(n, ng, nc, c, G, A, b, r);
    HalfSpace hs{Eigen::VectorXd(vector_arg(h, n, "h")), d};
    require_finite(hs.a, "h");
    require_finite(d, "d");
    czono_out(Z.intersect_halfspace(hs), ng_out, nc_out, c_out, G_out, A_out, b_out, r_out);
  });
}

int sb_czono_reduce(int n, int ng, int nc, const double* c, const double* G, const double* A, const double* b,
                    const double* r, int method, int technique, double order, int max_generators, int max_constraints,
                    int* ng_out, int* nc_out, double* c_out, double* G_out, double* A_out, double* b_out,
                    double* r_out) {
  return guard("sb_czono_reduce", [&] {
    const ConstrainedZonotope Z = czono_arg(n, ng, nc, c, G, A, b, r);
    switch (method) {
      case SB_CZONO_REDUCE_CORA:
        czono_out(Z.reduce_cora(czono_technique_arg(technique), order), ng_out, nc_out, c_out, G_out, A_out, b_out, r_out);
        return;
      case SB_CZONO_REDUCE_LIMITS: {
        if (max_generators < 0 || max_generators > SB_CZN_MAX_SIZE)
          throw InvalidArgumentError("max_generators: expected 0.." + std::to_string(SB_CZN_MAX_SIZE) + ", got " +
                                     std::to_string(max_generators));
        if (max_constraints < 0 || max_constraints > SB_CZN_MAX_SIZE)
          throw InvalidArgumentError("max_constraints: expected 0.." + std::to_string(SB_CZN_MAX_SIZE) + ", got " +
                                     std::to_string(max_constraints));
        czono_out(Z.reduce_limits(max_generators, max_constraints, czono_technique_arg(technique)), ng_out, nc_out, c_out,
                  G_out, A_out, b_out, r_out);
        return;
      }
      case SB_CZONO_REMOVE_ZERO:
        czono_out(Z.remove_zero_constraints(), ng_out, nc_out, c_out, G_out, A_out, b_out, r_out);
        return;
      case SB_CZONO_ELIMINATE:
        if (max_constraints < 0 || max_constraints > SB_CZN_MAX_SIZE)
          throw InvalidArgumentError("max_constraints: expected 0.." + std::to_string(SB_CZN_MAX_SIZE) + ", got " +
                                     std::to_string(max_constraints));
        czono_out(Z.eliminate_constraints(max_constraints), ng_out, nc_out, c_out, G_out, A_out, b_out, r_out);
        return;
      case SB_CZONO_RESCALE:
        czono_out(Z.rescale(), ng_out, nc_out, c_out, G_out, A_out, b_out, r_out);
        return;
      default:
        throw InvalidArgumentError("method: unknown reduction " + std::to_string(method) +
                                   " (SB_CZONO_REDUCE_CORA = 1, _LIMITS = 2, SB_CZONO_REMOVE_ZERO = 3, "
                                   "SB_CZONO_ELIMINATE = 4, SB_CZONO_RESCALE = 5)");
    }
  });
}

int sb_czono_projection_polygon(int n, int ng, int nc, const double* c, const double* G, const double* A,
                                const double* b, const double* r, int i, int j, int* nv, double* vertices) {
  return guard("sb_czono_projection_polygon", [&] {
    const ConstrainedZonotope Z = czono_arg(n, ng, nc, c, G, A, b, r);
    require_pointer(nv, "nv");
    const int capacity = *nv;
    if (capacity < 4) throw InvalidArgumentError("nv: the capacity must be >= 4 vertices, got " + std::to_string(capacity));
    const Eigen::MatrixXd V = projection_polygon(Z, i, j, capacity);
    if (V.rows() > 0) require_pointer(vertices, "vertices");
    write_matrix(V, vertices);
    *nv = static_cast<int>(V.rows());
  });
}

int sb_czonotopic_create(const sb_linear_system* system, int correction, int reduction, int technique, double order,
                         int max_constraints, int max_generators, int use_first_measurement, int ng0, int nc0,
                         const double* c0, const double* G0, const double* A0, const double* b0, const double* r0,
                         sb_czonotopic** out) {
  return guard("sb_czonotopic_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    const LinearSystem& sys = system_arg(system);
    CZOptions opt;
    if (correction != SB_CZN_EXACT_OUTPUT && correction != SB_CZN_WANG_STRIPS)
      throw InvalidArgumentError("correction: expected SB_CZN_EXACT_OUTPUT (0) or SB_CZN_WANG_STRIPS (1), got " +
                                 std::to_string(correction));
    opt.correction = static_cast<CZCorrection>(correction);
    if (reduction != SB_CZN_REDUCE_NONE && reduction != SB_CZN_REDUCE_CORA && reduction != SB_CZN_REDUCE_LIMITS)
      throw InvalidArgumentError("reduction: expected SB_CZN_REDUCE_NONE (0), _CORA (1) or _LIMITS (2), got " +
                                 std::to_string(reduction));
    opt.reduction = static_cast<CZReduction>(reduction);
    opt.technique = czono_technique_arg(technique);
    opt.order = order;
    opt.max_constraints = czono_limit_arg(max_constraints, "max_constraints");
    opt.max_generators = czono_limit_arg(max_generators, "max_generators");
    opt.use_first_measurement = use_first_measurement != 0;
    ConstrainedZonotope x0 = czono_arg(static_cast<int>(sys.nx()), ng0, nc0, c0, G0, A0, b0, r0, "0");
    auto est = std::make_unique<sb_czonotopic>(sb_czonotopic{ConstrainedZonotopicEstimator(sys, std::move(x0), opt)});
    *out = est.release();
  });
}

int sb_czonotopic_free(sb_czonotopic* estimator) {
  delete estimator;
  return SB_OK;
}

int sb_czonotopic_options(const sb_czonotopic* estimator, int* correction, int* reduction, int* technique,
                          double* order, int* max_constraints, int* max_generators) {
  return guard("sb_czonotopic_options", [&] {
    const CZOptions& o = czn_arg(estimator).options();
    if (correction) *correction = static_cast<int>(o.correction);
    if (reduction) *reduction = static_cast<int>(o.reduction);
    if (technique) *technique = static_cast<int>(o.technique);
    if (order) *order = o.order;
    if (max_constraints) *max_constraints = static_cast<int>(o.max_constraints);
    if (max_generators) *max_generators = static_cast<int>(o.max_generators);
  });
}

int sb_czonotopic_step(sb_czonotopic* estimator, const double* y, const double* u, double* lower, double* upper,
                       int* ng, int* nc) {
  return guard("sb_czonotopic_step", [&] {
    ConstrainedZonotopicEstimator& est = czn_arg(estimator);
    const LinearSystem& sys = est.system();
    const int nx = static_cast<int>(sys.nx()), nu = static_cast<int>(sys.nu());
    require_pointer(lower, "lower");
    require_pointer(upper, "upper");
    if (nu > 0) require_pointer(u, "u");
    if (nu > 0) est.update(vector_arg(y, static_cast<int>(sys.ny()), "y"), vector_arg(u, nu, "u"));
    else est.update(vector_arg(y, static_cast<int>(sys.ny()), "y"), Eigen::VectorXd(0));
    VecMap(lower, nx) = est.current_lower();
    VecMap(upper, nx) = est.current_upper();
    if (ng) *ng = static_cast<int>(est.current_set().num_generators());
    if (nc) *nc = static_cast<int>(est.current_set().num_constraints());
  });
}

int sb_czonotopic_last_set(const sb_czonotopic* estimator, int* ng_out, int* nc_out, double* c, double* G, double* A,
                           double* b, double* r) {
  return guard("sb_czonotopic_last_set", [&] {
    const ConstrainedZonotopicEstimator& est = czn_arg(estimator);
    if (!est.has_current()) throw InvalidArgumentError("estimator: no step has been taken yet");
    czono_out(est.current_set(), ng_out, nc_out, c, G, A, b, r);
  });
}

int sb_czonotopic_prediction(const sb_czonotopic* estimator, int* ng_out, int* nc_out, double* c, double* G,
                             double* A, double* b, double* r) {
  return guard("sb_czonotopic_prediction",
               [&] { czono_out(czn_arg(estimator).prediction(), ng_out, nc_out, c, G, A, b, r); });
}

int sb_czonotopic_set_inconsistency_policy(sb_czonotopic* estimator, int policy, int ng, int nc, const double* c,
                                           const double* G, const double* A, const double* b, const double* r) {
  return guard("sb_czonotopic_set_inconsistency_policy", [&] {
    ConstrainedZonotopicEstimator& est = czn_arg(estimator);
    const OnInconsistency pol = inconsistency_policy_arg(policy);
    if (c == nullptr) {
      est.set_inconsistency_policy(pol);
      return;
    }
    est.set_inconsistency_policy(pol, czono_arg(static_cast<int>(est.system().nx()), ng, nc, c, G, A, b, r));
  });
}

int sb_czonotopic_last_check(const sb_czonotopic* estimator, int* status, double* margin, int* reset) {
  return guard("sb_czonotopic_last_check", [&] { check_out(czn_arg(estimator).last_check(), status, margin, reset); });
}

int sb_czonotopic_reset(sb_czonotopic* estimator) {
  return guard("sb_czonotopic_reset", [&] { czn_arg(estimator).reset(); });
}

int sb_czonotopic_steps(const sb_czonotopic* estimator, int* steps) {
  return guard("sb_czonotopic_steps", [&] {
    const ConstrainedZonotopicEstimator& est = czn_arg(estimator);
    require_pointer(steps, "steps");
    *steps = static_cast<int>(std::min<Eigen::Index>(est.steps_taken(), std::numeric_limits<int>::max()));
  });
}

int sb_czonotopic_state_size(const sb_czonotopic* estimator, int* n) {
  return guard("sb_czonotopic_state_size", [&] { state_size_out(czn_arg(estimator).save_state(), n); });
}

int sb_czonotopic_save_state(const sb_czonotopic* estimator, double* state, int n) {
  return guard("sb_czonotopic_save_state", [&] { state_copy_out(czn_arg(estimator).save_state(), state, n); });
}

int sb_czonotopic_restore_state(sb_czonotopic* estimator, const double* state, int n) {
  return guard("sb_czonotopic_restore_state", [&] {
    ConstrainedZonotopicEstimator& est = czn_arg(estimator);
    est.restore_state(state_arg(state, n));
  });
}

}  // extern "C"
