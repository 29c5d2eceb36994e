// setbound — C ABI: thesis Chapter 4 interval observers (thesis.md §6).
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "c_api_common.hpp"
#include "setbound/thesis/interval_observer.hpp"

using namespace setbound;
using namespace setbound::thesis;
using namespace setbound::capi;

struct sb_interval_luenberger {
  std::optional<IntervalLuenbergerObserver> obs;
  Eigen::MatrixXd P;
  double gamma = std::numeric_limits<double>::quiet_NaN();
};

struct sb_interval_invariant_design {
  InvariantObserverDesign design;
};

struct sb_interval_invariant {
  IntervalInvariantObserver obs;
};

struct sb_interval_nonlinear {
  std::optional<NonlinearIntervalObserver> obs;
  Eigen::MatrixXd P;
  double gamma = std::numeric_limits<double>::quiet_NaN();
};

namespace {


ErrorRecursion variant_arg(int v, bool allow_naive) {
  switch (v) {
    case SB_IOBS_TIGHT: return ErrorRecursion::Tight;
    case SB_IOBS_WRAPPED: return ErrorRecursion::Wrapped;
    case SB_IOBS_NAIVE:
      if (allow_naive) return ErrorRecursion::Naive;
      throw InvalidArgumentError("variant: the online observers support SB_IOBS_TIGHT and SB_IOBS_WRAPPED only");
    default: throw InvalidArgumentError("variant: unknown value " + std::to_string(v));
  }
}

Plant plant_arg(int nx, int nu, int ny, int nd, int nv, const double* A, const double* B, const double* C,
                const double* F, const double* Z) {
  require_dimension(nx, "nx");
  require_dimension(ny, "ny");
  require_dimension(nu, "nu", true);
  require_dimension(nd, "nd", true);
  require_dimension(nv, "nv", true);
  return Plant(matrix_arg(A, nx, nx, "A"), matrix_arg(B, nx, nu, "B"), matrix_arg(C, ny, nx, "C"),
               matrix_arg(F, nx, nd, "F"), matrix_arg(Z, ny, nv, "Z"));
}

Eigen::VectorXd opt_vector(const double* p, int n, const char* name) {
  if (n == 0) return Eigen::VectorXd(0);
  return vector_arg(p, n, name);
}

}  // namespace

extern "C" {

int sb_interval_error_recursion(int n, int m, const double* Ao, const double* E, const double* e0_lo,
                                const double* e0_hi, const double* w_lo, const double* w_hi, int steps, int variant,
                                double* lo, double* hi) {
  return guard("sb_interval_error_recursion", [&] {
    require_dimension(n, "n");
    require_dimension(m, "m", true);
    if (steps < 0) throw InvalidArgumentError("steps: must be >= 0, got " + std::to_string(steps));
    require_pointer(lo, "lo");
    require_pointer(hi, "hi");
    const auto boxes = interval_error_recursion(matrix_arg(Ao, n, n, "Ao"), matrix_arg(E, n, m, "E"),
                                                box_arg(e0_lo, e0_hi, n, "e0"), box_arg(w_lo, w_hi, m, "w"), steps,
                                                variant_arg(variant, true));
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      VecMap(lo + k * std::size_t(n), n) = boxes[k].lo();
      VecMap(hi + k * std::size_t(n), n) = boxes[k].hi();
    }
  });
}

int sb_interval_error_limit(int n, int m, const double* Ao, const double* E, const double* w_lo, const double* w_hi,
                            int variant, double* lo, double* hi) {
  return guard("sb_interval_error_limit", [&] {
    require_dimension(n, "n");
    require_dimension(m, "m", true);
    require_pointer(lo, "lo");
    require_pointer(hi, "hi");
    const Box g = interval_error_limit(matrix_arg(Ao, n, n, "Ao"), matrix_arg(E, n, m, "E"),
                                       box_arg(w_lo, w_hi, m, "w"), variant_arg(variant, true));
    VecMap(lo, n) = g.lo();
    VecMap(hi, n) = g.hi();
  });
}

int sb_interval_luenberger_create(int nx, int nu, int ny, int nd, int nv, const double* A, const double* B,
                                  const double* C, const double* F, const double* Z, const double* L,
                                  const double* x0_lo, const double* x0_hi, const double* xhat0, const double* d_lo,
                                  const double* d_hi, const double* v_lo, const double* v_hi, int variant,
                                  sb_interval_luenberger** out) {
  return guard("sb_interval_luenberger_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    const Plant plant = plant_arg(nx, nu, ny, nd, nv, A, B, C, F, Z);
    auto h = std::make_unique<sb_interval_luenberger>();
    Eigen::MatrixXd gain;
    IntervalObserverOptions opt;
    opt.variant = variant_arg(variant, false);
    const Box x0 = box_arg(x0_lo, x0_hi, nx, "x0"), d = box_arg(d_lo, d_hi, nd, "d"), v = box_arg(v_lo, v_hi, nv, "v");
    const Eigen::VectorXd xh = vector_arg(xhat0, nx, "xhat0");
    if (L != nullptr) {
      gain = matrix_arg(L, nx, ny, "L");
    } else {
      const HinfGain g = hinf_observer_gain(plant);
      gain = g.L;
      h->P = g.P;
      h->gamma = g.gamma;
    }
    h->obs.emplace(plant, gain, x0, xh, d, v, opt);
    *out = h.release();
  });
}

int sb_interval_luenberger_free(sb_interval_luenberger* observer) {
  delete observer;
  return SB_OK;
}

int sb_interval_luenberger_info(const sb_interval_luenberger* observer, int* steps, int* freeze_index,
                                double* contraction, double* gamma) {
  return guard("sb_interval_luenberger_info", [&] {
    require_pointer(observer, "observer");
    const auto& o = *observer->obs;
    if (steps) *steps = static_cast<int>(std::min<long>(o.steps(), std::numeric_limits<int>::max()));
    if (freeze_index) *freeze_index = o.freeze_index();
    if (contraction) *contraction = o.contraction();
    if (gamma) *gamma = observer->gamma;
  });
}

int sb_interval_luenberger_gain(const sb_interval_luenberger* observer, double* L, double* P) {
  return guard("sb_interval_luenberger_gain", [&] {
    require_pointer(observer, "observer");
    write_matrix(observer->obs->gain(), L);
    if (observer->P.size() > 0) write_matrix(observer->P, P);
  });
}

int sb_interval_luenberger_current(const sb_interval_luenberger* observer, double* xhat, double* lo, double* hi) {
  return guard("sb_interval_luenberger_current", [&] {
    require_pointer(observer, "observer");
    write_vector(observer->obs->xhat(), xhat);
    write_vector(observer->obs->lower(), lo);
    write_vector(observer->obs->upper(), hi);
  });
}

int sb_interval_luenberger_step(sb_interval_luenberger* observer, const double* y, const double* u, double* xhat,
                                double* lo, double* hi) {
  return guard("sb_interval_luenberger_step", [&] {
    require_pointer(observer, "observer");
    auto& o = *observer->obs;
    o.step(vector_arg(y, int(o.ny()), "y"), opt_vector(u, int(o.nu()), "u"));
    write_vector(o.xhat(), xhat);
    write_vector(o.lower(), lo);
    write_vector(o.upper(), hi);
  });
}

int sb_interval_nonlinear_create(int nx, int nu, int ny, int nv, const double* A, const double* B, const double* C,
                                 const double* Z, const double* L, const double* x0_lo, const double* x0_hi,
                                 const double* xhat0, const double* v_lo, const double* v_hi, int window,
                                 sb_interval_nonlinear** out) {
  return guard("sb_interval_nonlinear_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    require_dimension(nx, "nx");
    // Check the caller's A before allocating the nx x nx identity: a huge nx with a NULL A must be
    // refused, not exhaust the memory (fuzz finding).
    matrix_arg(A, nx, nx, "A");
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(nx, nx);
    const Plant plant = plant_arg(nx, nu, ny, nx, nv, A, B, C, I.data(), Z);
    auto h = std::make_unique<sb_interval_nonlinear>();
    Eigen::MatrixXd gain;
    if (L != nullptr) {
      gain = matrix_arg(L, nx, ny, "L");
    } else {
      const HinfGain g = hinf_observer_gain(plant);
      gain = g.L;
      h->P = g.P;
      h->gamma = g.gamma;
    }
    NonlinearObserverOptions opt;
    if (window > SB_INTERVAL_MAX_WINDOW)  // the work per step grows with the window
      throw InvalidArgumentError("window: at most " + std::to_string(SB_INTERVAL_MAX_WINDOW) + ", got " +
                                 std::to_string(window));
    if (window > 0) opt.window = window;
    h->obs.emplace(plant, gain, box_arg(x0_lo, x0_hi, nx, "x0"), vector_arg(xhat0, nx, "xhat0"),
                   box_arg(v_lo, v_hi, nv, "v"), NonlinearityBox{}, opt);
    *out = h.release();
  });
}

int sb_interval_nonlinear_free(sb_interval_nonlinear* observer) {
  delete observer;
  return SB_OK;
}

int sb_interval_nonlinear_info(const sb_interval_nonlinear* observer, int* steps, int* window, double* gamma) {
  return guard("sb_interval_nonlinear_info", [&] {
    require_pointer(observer, "observer");
    const auto& o = *observer->obs;
    if (steps) *steps = static_cast<int>(std::min<long>(o.steps(), std::numeric_limits<int>::max()));
    if (window) *window = o.window();
    if (gamma) *gamma = observer->gamma;
  });
}

int sb_interval_nonlinear_gain(const sb_interval_nonlinear* observer, double* L, double* P) {
  return guard("sb_interval_nonlinear_gain", [&] {
    require_pointer(observer, "observer");
    write_matrix(observer->obs->gain(), L);
    if (observer->P.size() > 0) write_matrix(observer->P, P);
  });
}

int sb_interval_nonlinear_current(const sb_interval_nonlinear* observer, double* xhat, double* lo, double* hi) {
  return guard("sb_interval_nonlinear_current", [&] {
    require_pointer(observer, "observer");
    write_vector(observer->obs->xhat(), xhat);
    write_vector(observer->obs->lower(), lo);
    write_vector(observer->obs->upper(), hi);
  });
}

int sb_interval_nonlinear_step(sb_interval_nonlinear* observer, const double* y, const double* u, const double* h_lo,
                               const double* h_hi, double* xhat, double* lo, double* hi) {
  return guard("sb_interval_nonlinear_step", [&] {
    require_pointer(observer, "observer");
    auto& o = *observer->obs;
    const int n = int(o.nx());
    require_pointer(h_lo, "h (lo)");
    require_pointer(h_hi, "h (hi)");
    // validate the h box here too so that the message names h (Box itself would say "h")
    const Box hb = box_arg(h_lo, h_hi, n, "h");
    o.step(vector_arg(y, int(o.ny()), "y"), opt_vector(u, int(o.nu()), "u"), hb);
    write_vector(o.xhat(), xhat);
    write_vector(o.lower(), lo);
    write_vector(o.upper(), hi);
  });
}

int sb_interval_invariant_design_create(int nx, int nu, int ny, int nd, int nv, const double* A, const double* B,
                                        const double* C, const double* F, const double* Z, const double* L,
                                        const double* P, double gamma, const double* x0_lo, const double* x0_hi,
                                        const double* xhat0, const double* d_lo, const double* d_hi,
                                        const double* v_lo, const double* v_hi, double mu, double inflation,
                                        double epsilon, int variant, sb_interval_invariant_design** out) {
  return guard("sb_interval_invariant_design_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    const Plant plant = plant_arg(nx, nu, ny, nd, nv, A, B, C, F, Z);
    InvariantObserverOptions opt;
    opt.mu = mu;
    opt.inflation = inflation;
    opt.epsilon = epsilon;
    opt.variant = variant_arg(variant, false);
    const Box x0 = box_arg(x0_lo, x0_hi, nx, "x0"), d = box_arg(d_lo, d_hi, nd, "d"), v = box_arg(v_lo, v_hi, nv, "v");
    const Eigen::VectorXd xh = vector_arg(xhat0, nx, "xhat0");
    HinfGain g;
    if (L != nullptr) {
      g.L = matrix_arg(L, nx, ny, "L");
      g.P = matrix_arg(P, nx, nx, "P");
      require_finite(gamma, "gamma");
      g.gamma = gamma;
    } else {
      g = hinf_observer_gain(plant);
    }
    *out = new sb_interval_invariant_design{offline_error_sequence(plant, g, x0, xh, d, v, opt)};
  });
}

int sb_interval_invariant_design_free(sb_interval_invariant_design* design) {
  delete design;
  return SB_OK;
}

int sb_interval_invariant_design_info(const sb_interval_invariant_design* design, int* k_star, int* phi0_vertices,
                                      int* phi0_facets, double* gamma, double* beta, double* mu, double* inflation,
                                      double* inflation_min, double* epsilon, double* c_in, double* c_out) {
  return guard("sb_interval_invariant_design_info", [&] {
    require_pointer(design, "design");
    const auto& D = design->design;
    if (k_star) *k_star = D.k_star;
    if (phi0_vertices) *phi0_vertices = int(D.phi0.num_vertices());
    if (phi0_facets) *phi0_facets = int(D.phi0.H().rows());
    if (gamma) *gamma = D.gamma;
    if (beta) *beta = D.beta;
    if (mu) *mu = D.mu;
    if (inflation) *inflation = D.inflation;
    if (inflation_min) *inflation_min = D.inflation_min;
    if (epsilon) *epsilon = D.epsilon;
    if (c_in) *c_in = D.c_in;
    if (c_out) *c_out = D.c_out;
  });
}

int sb_interval_invariant_design_matrices(const sb_interval_invariant_design* design, double* L, double* P,
                                          double* E) {
  return guard("sb_interval_invariant_design_matrices", [&] {
    require_pointer(design, "design");
    write_matrix(design->design.L, L);
    write_matrix(design->design.P, P);
    write_matrix(design->design.E, E);
  });
}

int sb_interval_invariant_design_sequence(const sb_interval_invariant_design* design, double* lo, double* hi,
                                          double* shrinking) {
  return guard("sb_interval_invariant_design_sequence", [&] {
    require_pointer(design, "design");
    const auto& D = design->design;
    const std::size_t n = std::size_t(D.plant.nx());
    for (std::size_t k = 0; k < D.sequence.size(); ++k) {
      if (lo) VecMap(lo + k * n, Eigen::Index(n)) = D.sequence[k].lo();
      if (hi) VecMap(hi + k * n, Eigen::Index(n)) = D.sequence[k].hi();
      if (shrinking) shrinking[k] = D.shrinking_index[k];
    }
  });
}

int sb_interval_invariant_design_phi0(const sb_interval_invariant_design* design, double* vertices, double* H,
                                      double* b) {
  return guard("sb_interval_invariant_design_phi0", [&] {
    require_pointer(design, "design");
    const auto& D = design->design;
    write_matrix(D.phi0.vertices(), vertices);
    write_matrix(D.phi0.H(), H);
    write_vector(D.phi0.b(), b);
  });
}

int sb_interval_invariant_create(const sb_interval_invariant_design* design, sb_interval_invariant** out) {
  return guard("sb_interval_invariant_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    require_pointer(design, "design");
    *out = new sb_interval_invariant{IntervalInvariantObserver(design->design)};
  });
}

int sb_interval_invariant_free(sb_interval_invariant* observer) {
  delete observer;
  return SB_OK;
}

int sb_interval_invariant_info(const sb_interval_invariant* observer, int* steps) {
  return guard("sb_interval_invariant_info", [&] {
    require_pointer(observer, "observer");
    if (steps) *steps = static_cast<int>(std::min<long>(observer->obs.steps(), std::numeric_limits<int>::max()));
  });
}

int sb_interval_invariant_current(const sb_interval_invariant* observer, double* xhat, double* lo, double* hi) {
  return guard("sb_interval_invariant_current", [&] {
    require_pointer(observer, "observer");
    write_vector(observer->obs.xhat(), xhat);
    write_vector(observer->obs.lower(), lo);
    write_vector(observer->obs.upper(), hi);
  });
}

int sb_interval_invariant_step(sb_interval_invariant* observer, const double* y, const double* u, double* xhat,
                               double* lo, double* hi) {
  return guard("sb_interval_invariant_step", [&] {
    require_pointer(observer, "observer");
    auto& o = observer->obs;
    o.step(vector_arg(y, int(o.ny()), "y"), opt_vector(u, int(o.nu()), "u"));
    write_vector(o.xhat(), xhat);
    write_vector(o.lower(), lo);
    write_vector(o.upper(), hi);
  });
}

#define SB_STATE_FUNCTIONS(name, deref)                                                \
  int sb_##name##_state_size(const sb_##name* observer, int* n) {                     \
    return guard("sb_" #name "_state_size", [&] {                                     \
      require_pointer(observer, "observer");                                          \
      state_size_out((deref observer->obs).save_state(), n);                               \
    });                                                                               \
  }                                                                                   \
  int sb_##name##_save_state(const sb_##name* observer, double* state, int n) {       \
    return guard("sb_" #name "_save_state", [&] {                                     \
      require_pointer(observer, "observer");                                          \
      state_copy_out((deref observer->obs).save_state(), state, n);                        \
    });                                                                               \
  }                                                                                   \
  int sb_##name##_restore_state(sb_##name* observer, const double* state, int n) {    \
    return guard("sb_" #name "_restore_state", [&] {                                  \
      require_pointer(observer, "observer");                                          \
      (deref observer->obs).restore_state(state_arg(state, n));                            \
    });                                                                               \
  }

SB_STATE_FUNCTIONS(interval_luenberger, *)
SB_STATE_FUNCTIONS(interval_nonlinear, *)
SB_STATE_FUNCTIONS(interval_invariant, )
#undef SB_STATE_FUNCTIONS

// Missing and impossible readings (thesis/reading_screen.hpp).
#define SB_READING_FUNCTIONS(name, deref)                                                              \
  int sb_##name##_set_inconsistency_policy(sb_##name* observer, int policy, const double* reset_lo,     \
                                           const double* reset_hi) {                                    \
    return guard("sb_" #name "_set_inconsistency_policy", [&] {                                        \
      require_pointer(observer, "observer");                                                           \
      auto& o = deref observer->obs;                                                                    \
      const OnInconsistency pol = inconsistency_policy_arg(policy);                                     \
      if ((reset_lo == nullptr) != (reset_hi == nullptr))                                               \
        throw InvalidArgumentError("reset_lo, reset_hi: give both ends of the reset box or neither");   \
      o.set_inconsistency_policy(pol, reset_lo ? box_arg(reset_lo, reset_hi, int(o.nx()), "reset_set")  \
                                               : Box());                                               \
    });                                                                                                 \
  }                                                                                                     \
  int sb_##name##_last_check(const sb_##name* observer, int* status, double* margin, int* reset) {      \
    return guard("sb_" #name "_last_check", [&] {                                                      \
      require_pointer(observer, "observer");                                                           \
      check_out((deref observer->obs).last_check(), status, margin, reset);                             \
    });                                                                                                 \
  }

SB_READING_FUNCTIONS(interval_luenberger, *)
SB_READING_FUNCTIONS(interval_nonlinear, *)
SB_READING_FUNCTIONS(interval_invariant, )
#undef SB_READING_FUNCTIONS

}  // extern "C"
