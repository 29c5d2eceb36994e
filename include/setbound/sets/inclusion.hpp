// setbound — inclusion functions (thesis §1.2.8; spec thesis.md §1 "Inclusion functions", §3.2).
//
// [f] is an inclusion function of f when f([x]) ⊆ [f]([x]) for every box [x]. Three forms:
//   natural     [f]([x])                                  (f evaluated in interval arithmetic)
//   centered    f(m) + [J]([x])·([x] − m)                 (mean-value form, m = mid [x])
//   Taylor-2    f(m) + J(m)·([x] − m) + ½([x] − m)ᵀ[H]([x])([x] − m)
// Every callable takes intervals (Interval for scalar functions, Box for vector functions) and
// returns intervals: the point values f(m) and J(m) are evaluated on the degenerate interval [m, m],
// so the forms stay guaranteed enclosures under rounding (the interval arithmetic of
// sets/interval.hpp rounds outward). The elementary functions are setbound::ia::{sqr, sqrt, exp,
// sin, cos, abs, pow, reciprocal}; sqr([x]) is [0, max²] when 0 ∈ [x], and sin/cos return ±1 at
// interior extrema.
//
// Shapes for vector functions f : ℝⁿ → ℝᵖ:
//   f(Box n) → Box p;  J(Box n) → IntervalMatrix p×n;  H(Box n) → std::vector<IntervalMatrix>, p
//   matrices n×n (the Hessian of each output component).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/sets/box.hpp"
#include "setbound/sets/interval.hpp"
#include "setbound/sets/interval_matrix.hpp"

namespace setbound {

namespace detail {
void require_bounded_nonempty(const Interval& x, const std::string& name);
void require_bounded_nonempty(const Box& x, const std::string& name);
void require_result_size(Eigen::Index got, Eigen::Index want, const std::string& what);
}  // namespace detail

// ---------------------------------------------------------------- scalar functions ℝ → ℝ

/// Natural inclusion: f evaluated on [x].
template <class F>
Interval natural_inclusion(F&& f, const Interval& x) {
  if (x.is_empty()) throw InvalidArgumentError("x: the interval is empty");
  return f(x);
}

/// Centered (mean-value) form f(m) + [f′]([x])·([x] − m), m = mid [x]; df is an inclusion of f′.
template <class F, class DF>
Interval centered_inclusion(F&& f, DF&& df, const Interval& x) {
  detail::require_bounded_nonempty(x, "x");
  const double m = x.mid();
  const Interval M(m);
  return f(M) + df(x) * (x - M);
}

/// Order-2 Taylor form f(m) + f′(m)([x] − m) + ½·sqr([x] − m)·[f″]([x]).
template <class F, class DF, class D2F>
Interval taylor2_inclusion(F&& f, DF&& df, D2F&& d2f, const Interval& x) {
  detail::require_bounded_nonempty(x, "x");
  const double m = x.mid();
  const Interval M(m);
  const Interval d = x - M;
  return f(M) + df(M) * d + Interval(0.5) * ia::sqr(d) * d2f(x);
}

// ---------------------------------------------------------------- vector functions ℝⁿ → ℝᵖ

/// Natural inclusion: f evaluated on the box.
template <class F>
Box natural_inclusion(F&& f, const Box& x) {
  if (x.is_empty()) throw InvalidArgumentError("x: the box is empty");
  return f(x);
}

/// Centered form f(m) + [J]([x])·([x] − m).
template <class F, class JF>
Box centered_inclusion(F&& f, JF&& jac, const Box& x) {
  detail::require_bounded_nonempty(x, "x");
  const Eigen::VectorXd m = x.mid();
  const Box M = Box::point(m);
  const Box fm = f(M);
  const IntervalMatrix J = jac(x);
  detail::require_result_size(J.rows(), fm.size(), "jacobian rows");
  detail::require_result_size(J.cols(), x.size(), "jacobian columns");
  return fm + J * (x - M);
}

/// Order-2 Taylor form f(m) + J(m)([x] − m) + ½([x] − m)ᵀ[H_i]([x])([x] − m) per output i. The
/// quadratic form is evaluated as Σ_j [H_jj]·sqr([d_j]) + Σ_{j<k} ([H_jk] + [H_kj])·[d_j][d_k]
/// (sqr on the diagonal avoids the dependency effect of [d_j]·[d_j]).
template <class F, class JF, class HF>
Box taylor2_inclusion(F&& f, JF&& jac, HF&& hess, const Box& x) {
  detail::require_bounded_nonempty(x, "x");
  const Eigen::Index n = x.size();
  const Eigen::VectorXd m = x.mid();
  const Box M = Box::point(m);
  const Box fm = f(M);
  const IntervalMatrix Jm = jac(M);
  detail::require_result_size(Jm.rows(), fm.size(), "jacobian rows");
  detail::require_result_size(Jm.cols(), n, "jacobian columns");
  const Box d = x - M;
  const Box lin = fm + Jm * d;
  const std::vector<IntervalMatrix> H = hess(x);
  detail::require_result_size(static_cast<Eigen::Index>(H.size()), fm.size(), "hessian count");
  std::vector<Interval> out(static_cast<std::size_t>(fm.size()));
  for (Eigen::Index i = 0; i < fm.size(); ++i) {
    const IntervalMatrix& Hi = H[static_cast<std::size_t>(i)];
    detail::require_result_size(Hi.rows(), n, "hessian rows");
    detail::require_result_size(Hi.cols(), n, "hessian columns");
    Interval q(0.0);
    for (Eigen::Index j = 0; j < n; ++j) {
      q += Hi(j, j) * ia::sqr(d[j]);
      for (Eigen::Index k = j + 1; k < n; ++k) q += (Hi(j, k) + Hi(k, j)) * (d[j] * d[k]);
    }
    out[static_cast<std::size_t>(i)] = lin[i] + Interval(0.5) * q;
  }
  return Box::from_intervals(out);
}

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/inclusion.ipp"
#endif
