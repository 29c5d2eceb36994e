// setbound — definitions of the functions declared in setbound/lmi/scalar_search.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/lmi/scalar_search.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace lmi {

SETBOUND_INLINE ScalarSearchResult minimize_scalar(const std::function<double(double)>& f, double lo, double hi,
                                          const ScalarSearchOptions& o) {
  require_finite(lo, "lo");
  require_finite(hi, "hi");
  if (!(lo < hi)) throw InvalidArgumentError("lo: must be < hi");
  if (o.grid_points < 3) throw InvalidArgumentError("grid_points: must be >= 3");
  ScalarSearchResult r;
  const int N = o.grid_points;
  const double h = (hi - lo) / (o.open_interval ? N + 1 : N - 1);
  auto grid = [&](int k) { return o.open_interval ? lo + (k + 1) * h : lo + k * h; };
  int best = -1;
  for (int k = 0; k < N; ++k) {
    const double b = grid(k);
    double v = f(b);
    ++r.evaluations;
    if (std::isnan(v)) v = std::numeric_limits<double>::infinity();
    if (v < r.value) {
      r.value = v;
      r.argmin = b;
      best = k;
    }
  }
  if (best < 0) return r;  // infeasible everywhere on the grid

  // Refinement in the cell [β_{k−1}, β_{k+1}] around the best grid point.
  struct Ctx {
    const std::function<double(double)>* f;
    ScalarSearchResult* r;
    std::exception_ptr error;
    nlopt_opt opt;
  } ctx{&f, &r, nullptr, nullptr};
  const double a = std::max(lo, grid(best) - h), b = std::min(hi, grid(best) + h);
  const double la = o.open_interval && a <= lo ? lo + 1e-3 * h : a;
  const double lb = o.open_interval && b >= hi ? hi - 1e-3 * h : b;
  nlopt_opt opt = nlopt_create(NLOPT_LN_SBPLX, 1);
  if (opt == nullptr) throw NumericalError("scalar search: NLopt could not create an optimiser");
  ctx.opt = opt;
  nlopt_set_lower_bounds1(opt, la);
  nlopt_set_upper_bounds1(opt, lb);
  nlopt_set_xtol_rel(opt, o.xtol_rel);
  nlopt_set_ftol_rel(opt, o.ftol_rel);
  nlopt_set_maxeval(opt, o.max_evaluations);
  double step = 0.25 * (lb - la);
  nlopt_set_initial_step(opt, &step);
  nlopt_set_min_objective(
      opt,
      [](unsigned, const double* x, double*, void* data) -> double {
        auto* c = static_cast<Ctx*>(data);
        try {
          double v = (*c->f)(x[0]);
          ++c->r->evaluations;
          if (std::isnan(v)) v = std::numeric_limits<double>::infinity();
          if (v < c->r->value) {
            c->r->value = v;
            c->r->argmin = x[0];
          }
          // NLopt compares values; a huge finite number keeps it away from infeasible β.
          return std::isfinite(v) ? v : std::numeric_limits<double>::max() / 4;
        } catch (...) {
          c->error = std::current_exception();
          nlopt_force_stop(c->opt);
          return std::numeric_limits<double>::max() / 4;
        }
      },
      &ctx);
  double x0 = std::min(lb, std::max(la, r.argmin)), fx = 0;
  nlopt_optimize(opt, &x0, &fx);  // the best point is tracked in the callback
  nlopt_destroy(opt);
  if (ctx.error) std::rethrow_exception(ctx.error);
  return r;
}

}  // namespace lmi
}  // namespace setbound
