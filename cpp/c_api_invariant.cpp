// setbound C ABI — thesis Chapter 1: polytopes, ellipsoid box, polyhedral RPI set, Algorithm 1
// (include/setbound/thesis/invariant.hpp).
#include <memory>
#include <optional>

#include "c_api_common.hpp"
#include "setbound/sets/polytope.hpp"
#include "setbound/thesis/invariant.hpp"

struct sb_polytope {
  setbound::Polytope polytope;
};

struct sb_mrpi {
  setbound::thesis::MrpiShrinking result;
  setbound::Polytope phi0;
  std::optional<setbound::thesis::MrpiDesign> design;  // Algorithm 1 only (its shrinking is `result`)
  int n = 0;
  bool has_sets = false;
};

namespace {

using namespace setbound;
using namespace setbound::capi;

const Polytope& polytope_arg(const sb_polytope* p, const char* name = "polytope") {
  require_pointer(p, name);
  return p->polytope;
}

void emit(Polytope P, sb_polytope** out) {
  auto h = std::make_unique<sb_polytope>();
  h->polytope = std::move(P);
  *out = h.release();
}

Eigen::MatrixXd points_arg(const double* data, int npoints, int n, const char* name) {
  require_dimension(n, name);
  require_dimension(npoints, name);
  return matrix_arg(data, npoints, n, name).transpose();  // columns = points
}

Eigen::MatrixXd square_arg(const double* data, int n, const char* name) {
  require_dimension(n, name);
  return matrix_arg(data, n, n, name);
}

thesis::MrpiOptions mrpi_options(int stop_rule, double mu, int max_iterations) {
  thesis::MrpiOptions o;
  switch (stop_rule) {
    case SB_MRPI_STOP_RADIUS: o.stop = thesis::MrpiStopRule::Radius; break;
    case SB_MRPI_STOP_SHRINKING_INDEX: o.stop = thesis::MrpiStopRule::ShrinkingIndex; break;
    case SB_MRPI_STOP_VERTEX_NORM: o.stop = thesis::MrpiStopRule::VertexNorm; break;
    default: throw InvalidArgumentError("stop_rule: unknown stop rule " + std::to_string(stop_rule));
  }
  o.mu = mu;
  if (max_iterations > 0) o.max_iterations = max_iterations;
  return o;
}

const sb_mrpi& mrpi_arg(const sb_mrpi* m) {
  require_pointer(m, "mrpi");
  return *m;
}

}  // namespace

extern "C" {

int sb_polytope_from_vertices(int n, int npoints, const double* points, sb_polytope** out) {
  return guard(__func__, [&] {
    require_pointer(out, "out");
    emit(Polytope::from_vertices(points_arg(points, npoints, n, "points"), "points"), out);
  });
}

int sb_polytope_from_halfspaces(int n, int m, const double* H, const double* b, const double* interior,
                                sb_polytope** out) {
  return guard(__func__, [&] {
    require_pointer(out, "out");
    require_dimension(n, "H");
    require_dimension(m, "H");
    emit(Polytope::from_halfspaces(matrix_arg(H, m, n, "H"), vector_arg(b, m, "b"), vector_arg(interior, n, "interior"),
                                   "halfspaces"),
         out);
  });
}

int sb_polytope_free(sb_polytope* polytope) {
  delete polytope;
  return SB_OK;
}

int sb_polytope_sizes(const sb_polytope* polytope, int* n, int* nvertices, int* nfacets) {
  return guard(__func__, [&] {
    const Polytope& P = polytope_arg(polytope);
    if (n) *n = int(P.dimension());
    if (nvertices) *nvertices = int(P.num_vertices());
    if (nfacets) *nfacets = int(P.num_facets());
  });
}

int sb_polytope_get(const sb_polytope* polytope, double* vertices, double* H, double* b) {
  return guard(__func__, [&] {
    const Polytope& P = polytope_arg(polytope);
    const int n = int(P.dimension());
    if (vertices) RowMap(vertices, P.num_vertices(), n) = P.vertices().transpose();
    if (H) RowMap(H, P.num_facets(), n) = P.H();
    if (b) VecMap(b, P.num_facets()) = P.b();
  });
}

int sb_polytope_contains(const sb_polytope* polytope, int npoints, const double* points, double tol, int* inside) {
  return guard(__func__, [&] {
    const Polytope& P = polytope_arg(polytope);
    require_dimension(npoints, "points", true);
    require_finite(tol, "tol");
    if (!(tol >= 0)) throw InvalidArgumentError("tol: must be >= 0");
    if (npoints == 0) return;
    require_pointer(inside, "inside");
    const Eigen::MatrixXd X = points_arg(points, npoints, int(P.dimension()), "points");
    require_finite(X, "points");
    for (int i = 0; i < npoints; ++i) inside[i] = P.contains(X.col(i), tol) ? 1 : 0;
  });
}

int sb_polytope_linear_map(const sb_polytope* polytope, int rows, const double* M, sb_polytope** out) {
  return guard(__func__, [&] {
    const Polytope& P = polytope_arg(polytope);
    require_pointer(out, "out");
    require_dimension(rows, "M");
    emit(P.linear_map(matrix_arg(M, rows, int(P.dimension()), "M")), out);
  });
}

int sb_polytope_minkowski_sum(const sb_polytope* a, const sb_polytope* b, sb_polytope** out) {
  return guard(__func__, [&] {
    require_pointer(out, "out");
    emit(polytope_arg(a, "a").minkowski_sum(polytope_arg(b, "b")), out);
  });
}

int sb_polytope_minkowski_box(const sb_polytope* polytope, const double* lo, const double* hi, sb_polytope** out) {
  return guard(__func__, [&] {
    const Polytope& P = polytope_arg(polytope);
    require_pointer(out, "out");
    const int n = int(P.dimension());
    emit(P.minkowski_sum(Box(vector_arg(lo, n, "lo"), vector_arg(hi, n, "hi"), "box")), out);
  });
}

int sb_polytope_scale(const sb_polytope* polytope, double a, sb_polytope** out) {
  return guard(__func__, [&] {
    const Polytope& P = polytope_arg(polytope);
    require_pointer(out, "out");
    emit(P.scaled(a), out);
  });
}

int sb_polytope_bounding_box(const sb_polytope* polytope, double* lo, double* hi) {
  return guard(__func__, [&] {
    const Polytope& P = polytope_arg(polytope);
    require_pointer(lo, "lo");
    require_pointer(hi, "hi");
    const Box b = P.bounding_box();
    VecMap(lo, P.dimension()) = b.lo();
    VecMap(hi, P.dimension()) = b.hi();
  });
}

int sb_polytope_max_vertex_norm(const sb_polytope* polytope, double* radius) {
  return guard(__func__, [&] {
    const Polytope& P = polytope_arg(polytope);
    require_pointer(radius, "radius");
    *radius = P.max_vertex_norm();
  });
}

int sb_expanded_ellipsoid_levels(int n, const double* P, double gamma, double wbar_sq, double mu, double* c_in,
                                 double* c_out) {
  return guard(__func__, [&] {
    require_pointer(c_in, "c_in");
    require_pointer(c_out, "c_out");
    const auto L = thesis::expanded_ellipsoid_levels(square_arg(P, n, "P"), gamma, wbar_sq, mu);
    *c_in = L.c_in;
    *c_out = L.c_out;
  });
}

int sb_polyhedral_rpi(int n, const double* P, double c_in, double c_out, int max_vertices, sb_polytope** out) {
  return guard(__func__, [&] {
    require_pointer(out, "out");
    thesis::PolyhedralRpiOptions o;
    if (max_vertices > 0) o.max_vertices = max_vertices;
    emit(thesis::polyhedral_rpi_between_ellipsoids(square_arg(P, n, "P"), c_in, c_out, o), out);
  });
}

int sb_contraction_rate(int n, const double* A, const double* P, double* beta) {
  return guard(__func__, [&] {
    require_pointer(beta, "beta");
    *beta = thesis::contraction_rate(square_arg(A, n, "A"), square_arg(P, n, "P"));
  });
}

int sb_mrpi_shrinking(int n, int m, const double* A, const double* E, const double* dlo, const double* dhi,
                      const sb_polytope* phi0, const double* P, double c_out, double eps, int stop_rule, double mu,
                      int max_iterations, int boxes_only, sb_mrpi** out) {
  return guard(__func__, [&] {
    require_pointer(out, "out");
    require_dimension(m, "E");
    const Polytope& Phi0 = polytope_arg(phi0, "phi0");
    const Eigen::MatrixXd Am = square_arg(A, n, "A");
    const Eigen::MatrixXd Em = matrix_arg(E, n, m, "E");
    const Box delta(vector_arg(dlo, m, "dlo"), vector_arg(dhi, m, "dhi"), "delta");
    const Eigen::MatrixXd Pm = square_arg(P, n, "P");
    const auto o = mrpi_options(stop_rule, mu, max_iterations);
    auto h = std::make_unique<sb_mrpi>();
    h->result = boxes_only ? thesis::mrpi_outer_shrinking_boxes(Am, Em, delta, Phi0, Pm, c_out, eps, o)
                           : thesis::mrpi_outer_shrinking(Am, Em, delta, Phi0, Pm, c_out, eps, o);
    h->phi0 = Phi0;
    h->n = n;
    h->has_sets = !boxes_only;
    *out = h.release();
  });
}

int sb_mrpi_algorithm1(int n, int m, const double* A, const double* E, const double* wbar, double mu, double eps,
                       int stop_rule, int max_iterations, int boxes_only, sb_mrpi** out) {
  return guard(__func__, [&] {
    require_pointer(out, "out");
    require_dimension(m, "E");
    const Eigen::MatrixXd Am = square_arg(A, n, "A");
    const Eigen::MatrixXd Em = matrix_arg(E, n, m, "E");
    const Eigen::VectorXd w = vector_arg(wbar, m, "wbar");
    const auto o = mrpi_options(stop_rule, 1.0, max_iterations);
    auto h = std::make_unique<sb_mrpi>();
    thesis::MrpiDesign d = thesis::mrpi_outer_shrinking(Am, Em, w, mu, eps, o, boxes_only != 0);
    h->result = std::move(d.shrinking);
    d.shrinking = {};
    h->phi0 = d.phi_v;
    h->design = std::move(d);
    h->n = n;
    h->has_sets = !boxes_only;
    *out = h.release();
  });
}

int sb_mrpi_free(sb_mrpi* mrpi) {
  delete mrpi;
  return SB_OK;
}

int sb_mrpi_info(const sb_mrpi* mrpi, int* n, int* k_star, double* beta, int* has_sets, int* has_design) {
  return guard(__func__, [&] {
    const sb_mrpi& h = mrpi_arg(mrpi);
    if (n) *n = h.n;
    if (k_star) *k_star = h.result.k_star;
    if (beta) *beta = h.result.beta;
    if (has_sets) *has_sets = h.has_sets ? 1 : 0;
    if (has_design) *has_design = h.design ? 1 : 0;
  });
}

int sb_mrpi_sequences(const sb_mrpi* mrpi, double* radius_bound, double* vertex_radius, double* shrinking_index) {
  return guard(__func__, [&] {
    const auto& r = mrpi_arg(mrpi).result;
    const std::size_t K = std::size_t(r.k_star) + 1;
    for (std::size_t k = 0; k < K; ++k) {
      if (radius_bound) radius_bound[k] = r.radius_bound[k];
      if (vertex_radius) vertex_radius[k] = r.vertex_radius[k];
      if (shrinking_index) shrinking_index[k] = r.shrinking_index[k];
    }
  });
}

int sb_mrpi_boxes(const sb_mrpi* mrpi, double* lo, double* hi) {
  return guard(__func__, [&] {
    const sb_mrpi& h = mrpi_arg(mrpi);
    require_pointer(lo, "lo");
    require_pointer(hi, "hi");
    const auto& r = h.result;
    for (std::size_t k = 0; k < r.boxes.size(); ++k) {
      VecMap(lo + k * std::size_t(h.n), h.n) = r.boxes[k].lo();
      VecMap(hi + k * std::size_t(h.n), h.n) = r.boxes[k].hi();
    }
  });
}

int sb_mrpi_set(const sb_mrpi* mrpi, int k, sb_polytope** out) {
  return guard(__func__, [&] {
    const sb_mrpi& h = mrpi_arg(mrpi);
    require_pointer(out, "out");
    if (k < 0 || k > h.result.k_star)
      throw InvalidArgumentError("k: must be in [0, " + std::to_string(h.result.k_star) + "], got " + std::to_string(k));
    if (k == 0) return emit(h.phi0, out);
    if (!h.has_sets)
      throw InvalidArgumentError("k: this result was computed with boxes_only, only Phi_0 is available");
    emit(h.result.sets[std::size_t(k)], out);
  });
}

int sb_mrpi_design(const sb_mrpi* mrpi, double* P, double* gamma, double* c_in, double* c_out) {
  return guard(__func__, [&] {
    const sb_mrpi& h = mrpi_arg(mrpi);
    if (!h.design) throw InvalidArgumentError("mrpi: not an Algorithm 1 result (made by sb_mrpi_shrinking)");
    if (P) RowMap(P, h.n, h.n) = h.design->brl.P;
    if (gamma) *gamma = h.design->brl.gamma;
    if (c_in) *c_in = h.design->levels.c_in;
    if (c_out) *c_out = h.design->levels.c_out;
  });
}

}  // extern "C"
