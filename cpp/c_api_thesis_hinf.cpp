// setbound — C ABI of the thesis Ch. 1–3 H∞ set-membership observers (thesis.md §3.4, §4, §5).
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "c_api_common.hpp"
#include "setbound/thesis/eso_d.hpp"
#include "setbound/thesis/lpv.hpp"

using namespace setbound;
using namespace setbound::capi;
using namespace setbound::thesis;

static_assert(SB_HINF_MAX_GAMMAS == setbound::thesis::hinf_detail::kMaxGammas, "setbound.h and hinf_gain.hpp disagree");

struct sb_hinf_design {
  std::optional<Plant> plant;     // LTI (Algorithm 2)
  std::optional<LpvSystem> lpv;   // LPV (Algorithm 3)
  EllipsoidalSMDesign design;
  int nvert = 1, nx = 0, nu = 0, ny = 0, nd = 0, nv = 0, nrho = 0;
  // ESO-D designs (sb_eso_d_design_create): the γ searches of steps (a) and (c), step (b)'s shift.
  bool eso_d = false;
  std::vector<GammaTrial> trials[2];
  double lyapunov_shift = 0;
};

struct sb_hinf_observer {
  std::optional<EllipsoidalSMObserver> lti;
  std::optional<LPVEllipsoidalSMObserver> lpv;
  int nx = 0, nu = 0, ny = 0, nrho = 0;
};

namespace {

void write_blocks(const std::vector<Eigen::MatrixXd>& Ms, double* out) {
  if (out == nullptr) return;
  for (const auto& M : Ms) {
    RowMap(out, M.rows(), M.cols()) = M;
    out += M.size();
  }
}
void write_scalar(double v, double* out) {
  if (out != nullptr) *out = v;
}

std::vector<Eigen::MatrixXd> blocks_arg(const double* data, int nvert, int rows, int cols, const char* name) {
  require_dimension(nvert, "nvert");
  require_dimension(rows, name, true);
  require_dimension(cols, name, true);
  std::vector<Eigen::MatrixXd> out;
  if (rows > 0 && cols > 0) require_pointer(data, name);
  for (int i = 0; i < nvert; ++i)
    out.emplace_back(rows > 0 && cols > 0 ? Eigen::MatrixXd(ConstRowMap(data + static_cast<size_t>(i) * rows * cols, rows, cols))
                                          : Eigen::MatrixXd(rows, cols));
  return out;
}

LambdaRoute route_arg(int r, bool lpv) {
  switch (r) {
    case SB_LAMBDA_DEFAULT: return lpv ? LambdaRoute::InputOrLogDet : LambdaRoute::LogDet;
    case SB_LAMBDA_LOGDET: return LambdaRoute::LogDet;
    case SB_LAMBDA_DIRECT: return LambdaRoute::Direct;
    case SB_LAMBDA_INPUT_OR_LOGDET: return LambdaRoute::InputOrLogDet;
    case SB_LAMBDA_LARGEST: return LambdaRoute::Largest;
  }
  throw InvalidArgumentError("lambda_route: unknown value " + std::to_string(r) + " (expected -1..3)");
}

/// An LpvSystem for the vertex routines (theta unused by them: a dummy 1-D list when absent).
LpvSystem vertex_system(int nvert, int nx, int ny, int nd, int nv, const double* A, const double* C, const double* F,
                        const double* Z) {
  require_dimension(nx, "nx");
  require_dimension(ny, "ny");
  require_dimension(nd, "nd", true);
  require_dimension(nv, "nv", true);
  // Every pointer and dimension is checked before anything of size nvert is allocated: a huge
  // nvert with a NULL pointer must be refused, not exhaust the memory (fuzz finding).
  require_dimension(nvert, "nvert");
  require_pointer(A, "A");
  if (nd > 0) require_pointer(F, "F");
  std::vector<Eigen::MatrixXd> As = blocks_arg(A, nvert, nx, nx, "A");
  std::vector<Eigen::MatrixXd> Fs = blocks_arg(F, nvert, nx, nd, "F");
  Eigen::MatrixXd Cm(matrix_arg(C, ny, nx, "C")), Zm(matrix_arg(Z, ny, nv, "Z"));
  Eigen::MatrixXd theta(nvert, 1);
  for (int i = 0; i < nvert; ++i) theta(i) = i;
  return LpvSystem(std::move(As), {}, std::move(Fs), std::move(Cm), std::move(Zm), theta);
}

}  // namespace

namespace {

template <class Obs>
void write_current(const Obs& o, double* center, double* lower, double* upper, double* mu) {
  write_vector(o.center(), center);
  write_vector(o.lower(), lower);
  write_vector(o.upper(), upper);
  write_scalar(o.mu(), mu);
}

void current(const sb_hinf_observer* o, double* center, double* lower, double* upper, double* mu) {
  if (o->lti) write_current(*o->lti, center, lower, upper, mu);
  else write_current(*o->lpv, center, lower, upper, mu);
}

void one_step(sb_hinf_observer* o, const double* y, const double* u, const double* rho) {
  const ConstVecMap yv = vector_arg(y, o->ny, "y");
  const ConstVecMap uv = vector_arg(u, o->nu, "u");
  if (o->lti) {
    o->lti->step(yv, uv);
  } else {
    const ConstVecMap rv = vector_arg(rho, o->nrho, "rho");
    o->lpv->step(yv, uv, rv);
  }
}

}  // namespace

extern "C" {

int sb_hinf_observer_gain(int nvert, int nx, int ny, int nd, int nv, const double* A, const double* C,
                          const double* F, const double* Z, const double* Q, double* P, double* U, double* L,
                          double* gamma, double* g) {
  return guard("sb_hinf_observer_gain", [&] {
    const LpvSystem sys = vertex_system(nvert, nx, ny, nd, nv, A, C, F, Z);
    const Eigen::MatrixXd Qm = Q ? Eigen::MatrixXd(ConstRowMap(Q, nx, nx)) : Eigen::MatrixXd();
    if (nvert == 1) {
      const HinfGain h = hinf_observer_gain(sys.vertex_plant(0), Qm);
      write_matrix(h.P, P);
      write_matrix(h.U, U);
      write_matrix(h.L, L);
      write_scalar(h.gamma, gamma);
      write_scalar(h.g, g);
    } else {
      const HinfGainLpv h = hinf_observer_gain_lpv(sys, Qm);
      write_matrix(h.P, P);
      write_blocks(h.U, U);
      write_blocks(h.L, L);
      write_scalar(h.gamma, gamma);
      write_scalar(h.g, g);
    }
  });
}

int sb_brl_ellipsoidal_rpi(int nx, int m, const double* A, const double* E, const double* wbar, double* P,
                           double* gamma, double* g, double* level) {
  return guard("sb_brl_ellipsoidal_rpi", [&] {
    require_dimension(nx, "nx");
    require_dimension(m, "m");
    const BrlRpi b = brl_ellipsoidal_rpi(Eigen::MatrixXd(matrix_arg(A, nx, nx, "A")), Eigen::MatrixXd(matrix_arg(E, nx, m, "E")),
                                         Eigen::VectorXd(vector_arg(wbar, m, "wbar")));
    write_matrix(b.P, P);
    write_scalar(b.gamma, gamma);
    write_scalar(b.g, g);
    write_scalar(b.level, level);
  });
}

int sb_ellipsoidal_error_rpi(int nx, const double* P, const double* Q, double g, int m, const double* wbar,
                             double* lambda, double* cbar, double* e_inf) {
  return guard("sb_ellipsoidal_error_rpi", [&] {
    require_dimension(nx, "nx");
    require_dimension(m, "m");
    const ErrorRpi r = ellipsoidal_error_rpi(Eigen::MatrixXd(matrix_arg(P, nx, nx, "P")),
                                             Eigen::MatrixXd(matrix_arg(Q, nx, nx, "Q")), g,
                                             Eigen::VectorXd(vector_arg(wbar, m, "wbar")));
    write_scalar(r.lambda, lambda);
    write_scalar(r.cbar, cbar);
    write_vector(r.e_inf, e_inf);
  });
}

int sb_refine_dissipation_matrix(int nvert, int nx, int ny, int nd, int nv, const double* A, const double* C,
                                 const double* F, const double* Z, const double* P, const double* L, double g,
                                 int route, double* Q_ref, double* lambda) {
  return guard("sb_refine_dissipation_matrix", [&] {
    const LpvSystem sys = vertex_system(nvert, nx, ny, nd, nv, A, C, F, Z);
    const Eigen::MatrixXd Pm = matrix_arg(P, nx, nx, "P");
    require_positive_definite(Pm, "P");
    require_positive(g, "g");
    const std::vector<Eigen::MatrixXd> Ls = blocks_arg(L, nvert, nx, ny, "L");
    std::vector<Eigen::MatrixXd> Aos, Es;
    for (int i = 0; i < nvert; ++i) {
      require_finite(Ls[static_cast<size_t>(i)], "L");
      Aos.push_back(sys.A[static_cast<size_t>(i)] - Ls[static_cast<size_t>(i)] * sys.C);
      Es.push_back(sys.vertex_plant(static_cast<size_t>(i)).error_input(Ls[static_cast<size_t>(i)]));
    }
    HinfOptions opt;
    if (route == SB_LAMBDA_LOGDET) {
      const Eigen::MatrixXd Qr = hinf_detail::refine_q(Pm, Aos, Es, g, opt);
      write_matrix(Qr, Q_ref);
      write_scalar(hinf_detail::lambda_min_certified(Qr, Pm), lambda);
    } else if (route == SB_LAMBDA_DIRECT) {
      const double lam = hinf_detail::direct_lambda(Pm, Aos, Es, g, opt);
      write_matrix(lam * Pm, Q_ref);
      write_scalar(lam, lambda);
    } else {
      throw InvalidArgumentError("route: expected SB_LAMBDA_LOGDET (0) or SB_LAMBDA_DIRECT (1), got " +
                                 std::to_string(route));
    }
  });
}

int sb_covariance_dissipation_matrix(int nvert, int nx, int m, const double* Ao, const double* E, const double* W,
                                     double* V, double* Q) {
  return guard("sb_covariance_dissipation_matrix", [&] {
    require_dimension(nx, "nx");
    require_dimension(m, "m");
    const auto Aos = blocks_arg(Ao, nvert, nx, nx, "Ao");
    const auto Es = blocks_arg(E, nvert, nx, m, "E");
    for (const auto& M : Aos) require_finite(M, "Ao");
    for (const auto& M : Es) require_finite(M, "E");
    const CovarianceDissipation c = covariance_dissipation_matrix(Aos, Es, Eigen::MatrixXd(matrix_arg(W, m, m, "W")));
    write_matrix(c.V, V);
    write_matrix(c.Q, Q);
  });
}

int sb_chebyshev_error_ellipsoid(int nx, const double* V, double t, double* shape, double* level, double* probability) {
  return guard("sb_chebyshev_error_ellipsoid", [&] {
    require_dimension(nx, "nx");
    const ChebyshevEllipsoid c = chebyshev_error_ellipsoid(Eigen::MatrixXd(matrix_arg(V, nx, nx, "V")), t);
    write_matrix(c.shape, shape);
    write_scalar(c.level, level);
    write_scalar(c.probability_lower, probability);
  });
}

int sb_polytopic_weights(int nvert, int nrho, const double* theta, const double* rho, double* alpha) {
  return guard("sb_polytopic_weights", [&] {
    require_dimension(nvert, "nvert");
    require_dimension(nrho, "nrho");
    require_pointer(alpha, "alpha");
    const Eigen::VectorXd a = polytopic_weights(Eigen::MatrixXd(matrix_arg(theta, nvert, nrho, "theta")),
                                                Eigen::VectorXd(vector_arg(rho, nrho, "rho")));
    write_vector(a, alpha);
  });
}

int sb_hinf_design_create(int nvert, int nx, int nu, int ny, int nd, int nv, int nrho, const double* A,
                          const double* B, const double* C, const double* F, const double* Z, const double* theta,
                          const double* wbar, const double* W, int lambda_route, int passes, sb_hinf_design** out) {
  return guard("sb_hinf_design_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    require_dimension(nx, "nx");
    require_dimension(nu, "nu", true);
    require_dimension(ny, "ny");
    require_dimension(nd, "nd", true);
    require_dimension(nv, "nv", true);
    require_dimension(nrho, "nrho", true);
    const bool is_lpv = nrho > 0;
    if (!is_lpv && nvert != 1) throw DimensionError("nrho: an LTI design has one vertex; give theta (nvert x nrho) for LPV");
    const int m = nd + nv;
    auto d = std::make_unique<sb_hinf_design>();
    d->nvert = nvert, d->nx = nx, d->nu = nu, d->ny = ny, d->nd = nd, d->nv = nv, d->nrho = nrho;
    EllipsoidalSMOptions opt;
    opt.lambda_route = route_arg(lambda_route, is_lpv);
    // every pass solves the design LMIs again (about a second each): a huge count would run for years
    if (passes > SB_HINF_MAX_PASSES)
      throw InvalidArgumentError("passes: at most " + std::to_string(SB_HINF_MAX_PASSES) + ", got " +
                                 std::to_string(passes));
    opt.passes = passes <= 0 ? 2 : passes;
    if (W) opt.w_covariance = ConstRowMap(W, m, m);
    const Eigen::VectorXd wb = vector_arg(wbar, m, "wbar");
    const Eigen::MatrixXd Cm = matrix_arg(C, ny, nx, "C"), Zm = matrix_arg(Z, ny, nv, "Z");
    if (!is_lpv) {
      d->plant.emplace(Eigen::MatrixXd(matrix_arg(A, nx, nx, "A")), Eigen::MatrixXd(matrix_arg(B, nx, nu, "B")), Cm,
                       Eigen::MatrixXd(matrix_arg(F, nx, nd, "F")), Zm);
      d->design = design_ellipsoidal_sm_observer(*d->plant, wb, opt);
    } else {
      d->lpv.emplace(blocks_arg(A, nvert, nx, nx, "A"), blocks_arg(B, nvert, nx, nu, "B"), blocks_arg(F, nvert, nx, nd, "F"),
                     Cm, Zm, Eigen::MatrixXd(matrix_arg(theta, nvert, nrho, "theta")));
      d->design = design_ellipsoidal_sm_observer_lpv(*d->lpv, wb, opt);
    }
    *out = d.release();
  });
}

/* ==== ESO-D (CORA's name; Martinez, Loukkas, Meslem 2020): a grid design for sb_hinf_observer ==== */

int sb_eso_d_design_create(int nx, int nu, int ny, int nd, int nv, const double* A, const double* B, const double* C,
                           const double* F, const double* Z, const double* wbar, const double* W, int ngammas,
                           const double* gammas, sb_hinf_design** out) {
  return guard("sb_eso_d_design_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    require_dimension(nx, "nx");
    require_dimension(nu, "nu", true);
    require_dimension(ny, "ny");
    require_dimension(nd, "nd", true);
    require_dimension(nv, "nv", true);
    require_dimension(ngammas, "ngammas", true);
    if (ngammas > SB_HINF_MAX_GAMMAS)
      throw InvalidArgumentError("ngammas: at most " + std::to_string(SB_HINF_MAX_GAMMAS) + " (each gamma is an SDP), got " +
                                 std::to_string(ngammas));
    if (ngammas > 0) require_pointer(gammas, "gammas");
    const int m = nd + nv;
    EsoDOptions opt;
    if (ngammas > 0) opt.gammas.assign(gammas, gammas + ngammas);
    if (W) opt.w_covariance = ConstRowMap(W, m, m);
    const Eigen::VectorXd wb = vector_arg(wbar, m, "wbar");
    auto d = std::make_unique<sb_hinf_design>();
    d->nvert = 1, d->nx = nx, d->nu = nu, d->ny = ny, d->nd = nd, d->nv = nv, d->nrho = 0;
    d->plant.emplace(Eigen::MatrixXd(matrix_arg(A, nx, nx, "A")), Eigen::MatrixXd(matrix_arg(B, nx, nu, "B")),
                     Eigen::MatrixXd(matrix_arg(C, ny, nx, "C")), Eigen::MatrixXd(matrix_arg(F, nx, nd, "F")),
                     Eigen::MatrixXd(matrix_arg(Z, ny, nv, "Z")));
    EsoDDesign e = design_eso_d(*d->plant, wb, opt);
    d->design = std::move(e.sm);
    d->eso_d = true;
    d->trials[0] = std::move(e.trials_a);
    d->trials[1] = std::move(e.trials_c);
    d->lyapunov_shift = e.lyapunov_shift;
    *out = d.release();
  });
}

int sb_hinf_design_gammas(const sb_hinf_design* design, int search, int* count, double* gammas, int* status) {
  return guard("sb_hinf_design_gammas", [&] {
    require_pointer(design, "design");
    require_pointer(count, "count");
    if (!design->eso_d)
      throw InvalidArgumentError("design: not a gamma-grid design (sb_hinf_design_create minimises gamma; only "
                                 "sb_eso_d_design_create searches a grid)");
    if (search != 0 && search != 1)
      throw InvalidArgumentError("search: expected 0 (step (a), Q = I) or 1 (step (c), Q = V^-1), got " +
                                 std::to_string(search));
    const std::vector<GammaTrial>& t = design->trials[search];
    const int n = static_cast<int>(t.size());
    const int capacity = *count;
    if ((gammas != nullptr || status != nullptr) && capacity < n) {
      *count = n;
      throw BufferTooSmallError("count: " + std::to_string(n) + " gamma values were tried, capacity " +
                                std::to_string(capacity));
    }
    *count = n;
    for (int i = 0; i < n; ++i) {
      if (gammas) gammas[i] = t[static_cast<size_t>(i)].gamma;
      if (status) status[i] = static_cast<int>(t[static_cast<size_t>(i)].status);
    }
  });
}

int sb_eso_d_design_lyapunov_shift(const sb_hinf_design* design, double* shift) {
  return guard("sb_eso_d_design_lyapunov_shift", [&] {
    require_pointer(design, "design");
    require_pointer(shift, "shift");
    if (!design->eso_d) throw InvalidArgumentError("design: not an ESO-D design (sb_eso_d_design_create)");
    *shift = design->lyapunov_shift;
  });
}

/* ==== end ESO-D ==== */

int sb_hinf_design_free(sb_hinf_design* design) {
  delete design;
  return SB_OK;
}

int sb_hinf_design_dims(const sb_hinf_design* design, int* nvert, int* nx, int* nu, int* ny, int* nd, int* nv,
                        int* nrho, int* npasses) {
  return guard("sb_hinf_design_dims", [&] {
    require_pointer(design, "design");
    if (nvert) *nvert = design->nvert;
    if (nx) *nx = design->nx;
    if (nu) *nu = design->nu;
    if (ny) *ny = design->ny;
    if (nd) *nd = design->nd;
    if (nv) *nv = design->nv;
    if (nrho) *nrho = design->nrho;
    if (npasses) *npasses = static_cast<int>(design->design.passes.size());
  });
}

int sb_hinf_design_get(const sb_hinf_design* design, double* P, double* L, double* Q_input, double* Q_refined,
                       double* V, double* e_inf, double* scalars) {
  return guard("sb_hinf_design_get", [&] {
    require_pointer(design, "design");
    const EllipsoidalSMDesign& d = design->design;
    write_matrix(d.P, P);
    write_blocks(d.L_vertices, L);
    write_matrix(d.Q_input, Q_input);
    write_matrix(d.Q_refined, Q_refined);
    if (V) {
      if (d.V.size() > 0) write_matrix(d.V, V);
      else RowMap(V, design->nx, design->nx).setConstant(std::numeric_limits<double>::quiet_NaN());
    }
    write_vector(d.e_inf, e_inf);
    if (scalars) {
      const double s[9] = {d.gamma, d.g, d.lambda, d.lambda_input, d.lambda_refined, d.cbar, d.wtw, d.lambda_max_P,
                           d.design_time};
      for (int i = 0; i < 9; ++i) scalars[i] = s[i];
    }
  });
}

int sb_hinf_design_pass(const sb_hinf_design* design, int pass, double* P, double* L, double* Q_input, double* Q_refined,
                        double* scalars) {
  return guard("sb_hinf_design_pass", [&] {
    require_pointer(design, "design");
    const auto& ps = design->design.passes;
    if (pass < 0 || pass >= static_cast<int>(ps.size()))
      throw InvalidArgumentError("pass: expected 0.." + std::to_string(ps.size() - 1) + ", got " + std::to_string(pass));
    const EllipsoidalSMPass& p = ps[static_cast<size_t>(pass)];
    write_matrix(p.P, P);
    write_blocks(p.L, L);
    write_matrix(p.Q_input, Q_input);
    write_matrix(p.Q_refined, Q_refined);
    if (scalars) {
      const double s[7] = {p.g, p.gamma, p.lambda_input, p.lambda_refined, p.lambda_direct, p.lambda,
                           p.refinement_failed ? 1.0 : 0.0};
      for (int i = 0; i < 7; ++i) scalars[i] = s[i];
    }
  });
}

int sb_hinf_design_mu0_ball(const sb_hinf_design* design, double radius, double* mu0) {
  return guard("sb_hinf_design_mu0_ball", [&] {
    require_pointer(design, "design");
    require_pointer(mu0, "mu0");
    require_finite(radius, "radius");
    *mu0 = mu0_from_ball(design->design, radius);
  });
}

int sb_hinf_design_mu0_vertices(const sb_hinf_design* design, int npoints, const double* vertices, double* mu0) {
  return guard("sb_hinf_design_mu0_vertices", [&] {
    require_pointer(design, "design");
    require_pointer(mu0, "mu0");
    require_dimension(npoints, "npoints");
    const Eigen::MatrixXd V = matrix_arg(vertices, npoints, design->nx, "vertices");
    *mu0 = mu0_from_vertices(design->design, Eigen::MatrixXd(V.transpose()));
  });
}

int sb_hinf_design_mu0_box(const sb_hinf_design* design, const double* lo, const double* hi, double* mu0) {
  return guard("sb_hinf_design_mu0_box", [&] {
    require_pointer(design, "design");
    require_pointer(mu0, "mu0");
    *mu0 = mu0_from_box(design->design, Eigen::VectorXd(vector_arg(lo, design->nx, "lo")),
                        Eigen::VectorXd(vector_arg(hi, design->nx, "hi")));
  });
}

int sb_hinf_observer_create(const sb_hinf_design* design, const double* xhat0, double mu0, sb_hinf_observer** out) {
  return guard("sb_hinf_observer_create", [&] {
    require_pointer(out, "out");
    *out = nullptr;
    require_pointer(design, "design");
    const Eigen::VectorXd x0 = vector_arg(xhat0, design->nx, "xhat0");
    require_finite(mu0, "mu0");
    auto o = std::make_unique<sb_hinf_observer>();
    o->nx = design->nx, o->nu = design->nu, o->ny = design->ny, o->nrho = design->nrho;
    if (design->plant) o->lti.emplace(*design->plant, design->design, x0, mu0);
    else o->lpv.emplace(*design->lpv, design->design, x0, mu0);
    *out = o.release();
  });
}

int sb_hinf_observer_free(sb_hinf_observer* observer) {
  delete observer;
  return SB_OK;
}


int sb_hinf_observer_current(const sb_hinf_observer* observer, double* center, double* lower, double* upper, double* mu,
                             int* steps) {
  return guard("sb_hinf_observer_current", [&] {
    require_pointer(observer, "observer");
    current(observer, center, lower, upper, mu);
    if (steps) *steps = static_cast<int>(observer->lti ? observer->lti->steps() : observer->lpv->steps());
  });
}

int sb_hinf_observer_step(sb_hinf_observer* observer, const double* y, const double* u, const double* rho,
                          double* center, double* lower, double* upper, double* mu) {
  return guard("sb_hinf_observer_step", [&] {
    require_pointer(observer, "observer");
    one_step(observer, y, u, rho);  // the observers validate before changing anything
    current(observer, center, lower, upper, mu);
  });
}

int sb_hinf_observer_run(sb_hinf_observer* observer, int T, const double* Y, const double* U, const double* R,
                         double* centers, double* lowers, double* uppers, double* mus) {
  return guard("sb_hinf_observer_run", [&] {
    require_pointer(observer, "observer");
    require_dimension(T, "T", true);
    const int nx = observer->nx, ny = observer->ny, nu = observer->nu, nr = observer->lpv ? observer->nrho : 0;
    if (T > 0) {
      require_pointer(Y, "Y");
      if (nu > 0) require_pointer(U, "U");
      if (nr > 0) require_pointer(R, "R");
    }
    sb_hinf_observer backup = *observer;  // restored on error: the observer is unchanged
    try {
      auto row = [&](double* p, int k, int w) { return p ? p + static_cast<size_t>(k) * w : nullptr; };
      current(observer, row(centers, 0, nx), row(lowers, 0, nx), row(uppers, 0, nx), row(mus, 0, 1));
      for (int k = 0; k < T; ++k) {
        one_step(observer, Y + static_cast<size_t>(k) * ny, nu > 0 ? U + static_cast<size_t>(k) * nu : nullptr,
                 nr > 0 ? R + static_cast<size_t>(k) * nr : nullptr);
        current(observer, row(centers, k + 1, nx), row(lowers, k + 1, nx), row(uppers, k + 1, nx), row(mus, k + 1, 1));
      }
    } catch (...) {
      *observer = std::move(backup);
      throw;
    }
  });
}

int sb_hinf_observer_set_inconsistency_policy(sb_hinf_observer* observer, int policy, const double* reset_lo,
                                              const double* reset_hi) {
  return guard("sb_hinf_observer_set_inconsistency_policy", [&] {
    require_pointer(observer, "observer");
    const OnInconsistency pol = inconsistency_policy_arg(policy);
    if ((reset_lo == nullptr) != (reset_hi == nullptr))
      throw InvalidArgumentError("reset_lo, reset_hi: give both ends of the reset box or neither");
    const Box rb = reset_lo ? box_arg(reset_lo, reset_hi, observer->nx, "reset_set") : Box();
    if (observer->lti) observer->lti->set_inconsistency_policy(pol, rb);
    else observer->lpv->set_inconsistency_policy(pol, rb);
  });
}

int sb_hinf_observer_last_check(const sb_hinf_observer* observer, int* status, double* margin, int* reset) {
  return guard("sb_hinf_observer_last_check", [&] {
    require_pointer(observer, "observer");
    check_out(observer->lti ? observer->lti->last_check() : observer->lpv->last_check(), status, margin, reset);
  });
}

int sb_hinf_observer_state_size(const sb_hinf_observer* observer, int* n) {
  return guard("sb_hinf_observer_state_size", [&] {
    require_pointer(observer, "observer");
    state_size_out(observer->lti ? observer->lti->save_state() : observer->lpv->save_state(), n);
  });
}

int sb_hinf_observer_save_state(const sb_hinf_observer* observer, double* state, int n) {
  return guard("sb_hinf_observer_save_state", [&] {
    require_pointer(observer, "observer");
    state_copy_out(observer->lti ? observer->lti->save_state() : observer->lpv->save_state(), state, n);
  });
}

int sb_hinf_observer_restore_state(sb_hinf_observer* observer, const double* state, int n) {
  return guard("sb_hinf_observer_restore_state", [&] {
    require_pointer(observer, "observer");
    const std::vector<double> s = state_arg(state, n);
    if (observer->lti) observer->lti->restore_state(s);
    else observer->lpv->restore_state(s);
  });
}

}  // extern "C"
