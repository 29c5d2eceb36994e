// setbound — bounded scalar minimisation for the bilinear scalars of the spec (β).
//
// papers.md §0.4: every design with β·P is an LMI only for fixed β, and the criterion is not
// monotone in β, so bisection on feasibility is wrong. We minimise the actual criterion
// f(β) over [lo, hi]: a coarse grid first (f may be +inf where the LMI is infeasible), then
// local refinement with NLopt (derivative-free, bounded to the grid cell around the best
// point). The callback usually re-solves one LmiProblem whose values it updates.
#pragma once

#include <nlopt.h>

#include <cmath>
#include <exception>
#include <functional>
#include <limits>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"

namespace setbound::lmi {

struct ScalarSearchOptions {
  int grid_points = 12;     // coarse grid size (interior points of [lo, hi] when open)
  bool open_interval = true;  // evaluate only strictly inside (lo, hi) (e.g. β ∈ (0, 1))
  double xtol_rel = 1e-6;   // NLopt relative tolerance on β
  double ftol_rel = 1e-9;
  int max_evaluations = 80; // for the refinement stage
};

struct ScalarSearchResult {
  double argmin = std::numeric_limits<double>::quiet_NaN();
  double value = std::numeric_limits<double>::infinity();  // +inf: nowhere finite
  int evaluations = 0;
  bool found() const { return std::isfinite(value); }
};

ScalarSearchResult minimize_scalar(const std::function<double(double)>& f, double lo, double hi,
                                          const ScalarSearchOptions& o = {});

}  // namespace setbound::lmi

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/lmi/impl/scalar_search.ipp"
#endif
