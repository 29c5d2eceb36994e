// setbound — definitions of the functions declared in setbound/thesis/reading_screen.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/thesis/reading_screen.hpp"
#include "setbound/core/config.hpp"

#include <cmath>
#include <string>

#include "setbound/core/error.hpp"
#include "setbound/sets/interval.hpp"

namespace setbound {
namespace thesis {

SETBOUND_INLINE void ReadingScreen::init(Eigen::Index ny, const Box& initial) {
  reset_box = initial;
  check.clear(ny, OutputStatus::Used);
  check.margin.setConstant(ny, std::numeric_limits<double>::quiet_NaN());
  center.setZero(ny);
  radius.setZero(ny);
  phi.setZero(ny);
  magnitude.setZero(ny);
}

SETBOUND_INLINE void ReadingScreen::set_policy(OnInconsistency p, const Box& reset, Eigen::Index nx) {
  if (p != OnInconsistency::Flag && p != OnInconsistency::Raise && p != OnInconsistency::Reset)
    throw InvalidArgumentError("on_inconsistency: must be Flag, Raise or Reset");
  if (reset.size() != 0) {
    if (reset.size() != nx)
      throw DimensionError("reset_set: expected a box with " + std::to_string(nx) + " components, got " +
                           std::to_string(reset.size()));
    if (reset.is_empty()) throw InvalidArgumentError("reset_set: the box is empty");
    for (Eigen::Index i = 0; i < nx; ++i)
      if (!std::isfinite(reset.lo()(i)) || !std::isfinite(reset.hi()(i)))
        throw NotFiniteError("reset_set: component " + std::to_string(i) + " is unbounded; a bounded box is required");
    reset_box = reset;
  }
  policy = p;
}

SETBOUND_INLINE bool ReadingScreen::screen(const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Index terms) {
  const Eigen::Index ny = y.size();
  check.clear(ny, OutputStatus::Used);
  bool all = true;
  for (Eigen::Index i = 0; i < ny; ++i) {
    if (std::isnan(y(i))) {
      check.status[std::size_t(i)] = OutputStatus::Missing;
      all = false;
      continue;
    }
    const OutputTest t = test_output(y(i), center(i), radius(i), phi(i), magnitude(i), terms);
    check.margin(i) = t.margin;
    if (t.inconsistent) {
      check.status[std::size_t(i)] = OutputStatus::Inconsistent;
      all = false;
    }
  }
  return all;
}

SETBOUND_INLINE void ReadingScreen::raise_first(long step, const Eigen::Ref<const Eigen::VectorXd>& y) const {
  const Eigen::Index i = check.first_inconsistent();
  if (i >= 0) throw_inconsistent(step, i, y(i), center(i), radius(i), phi(i), check.margin(i));
}

namespace screen_detail {

SETBOUND_INLINE void box_output_sets(const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Eigen::VectorXd& vlo,
                                     const Eigen::VectorXd& vhi, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                                     ReadingScreen& s) {
  const Eigen::Index ny = C.rows(), n = C.cols(), nv = Z.cols();
  for (Eigen::Index i = 0; i < ny; ++i) {
    double c = 0, r = 0, p = 0, mag = 0;
    for (Eigen::Index j = 0; j < n; ++j) {
      const double m = 0.5 * (lo(j) + hi(j)), h = 0.5 * (hi(j) - lo(j));
      c += C(i, j) * m;
      r += std::abs(C(i, j)) * h;
      mag += std::abs(C(i, j)) * (std::abs(m) + h);
    }
    for (Eigen::Index j = 0; j < nv; ++j) {
      const double m = 0.5 * (vlo(j) + vhi(j)), h = 0.5 * (vhi(j) - vlo(j));
      c += Z(i, j) * m;
      p += std::abs(Z(i, j)) * h;
      mag += std::abs(Z(i, j)) * (std::abs(m) + h);
    }
    // the midpoints and half-widths are themselves rounded: a relative eps of each term, inside
    // the allowance through the extra terms counted by the caller
    s.center(i) = c;
    s.radius(i) = r;
    s.phi(i) = p;
    s.magnitude(i) = mag + r + p;
  }
}

SETBOUND_INLINE bool screen_box_step(ReadingScreen& s, const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Box& v,
                                     const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                                     const Eigen::Ref<const Eigen::VectorXd>& y, long step) {
  box_output_sets(C, Z, v.lo(), v.hi(), lo, hi, s);
  const bool all = s.screen(y, C.cols() + Z.cols() + 4);
  if (!all && s.policy == OnInconsistency::Raise) s.raise_first(step, y);
  return all;
}

SETBOUND_INLINE MeasurementCheck apply_reset(ReadingScreen& s, const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z,
                                             const Box& v, const Eigen::Ref<const Eigen::VectorXd>& y,
                                             Eigen::VectorXd& lo, Eigen::VectorXd& hi) {
  if (s.policy != OnInconsistency::Reset || !s.check.flagged()) return s.check;
  const MeasurementCheck trigger = s.check;
  lo = s.reset_box.lo();
  hi = s.reset_box.hi();
  box_output_sets(C, Z, v.lo(), v.hi(), lo, hi, s);
  s.screen(y, C.cols() + Z.cols() + 4);
  MeasurementCheck use = s.check;
  s.check = trigger;
  s.check.reset = true;
  return use;
}

SETBOUND_INLINE Box narrow_by_outputs(const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Eigen::VectorXd& lo,
                                      const Eigen::VectorXd& hi, const Eigen::Ref<const Eigen::VectorXd>& y, const Box& v,
                                      const MeasurementCheck& check) {
  const Eigen::Index n = lo.size(), ny = C.rows(), nv = Z.cols();
  std::vector<Interval> x;
  x.reserve(std::size_t(n));
  for (Eigen::Index j = 0; j < n; ++j) x.push_back(Interval::unchecked(lo(j), hi(j)));
  for (Eigen::Index i = 0; i < ny; ++i) {
    if (check.status[std::size_t(i)] != OutputStatus::Used) continue;
    // C_i x ∈ t := y_i − Z_i [v]
    Interval t(y(i));
    for (Eigen::Index j = 0; j < nv; ++j)
      if (Z(i, j) != 0.0) t = t - Interval(Z(i, j)) * v[j];
    for (Eigen::Index j = 0; j < n; ++j) {
      if (C(i, j) == 0.0) continue;
      Interval s = t;
      for (Eigen::Index l = 0; l < n; ++l)
        if (l != j && C(i, l) != 0.0) s = s - Interval(C(i, l)) * x[std::size_t(l)];
      const Interval xj = x[std::size_t(j)].intersect(s / Interval(C(i, j)));
      // Empty only when the reading lies within the test's rounding allowance outside the box:
      // keep the box (it contains every consistent state) rather than an empty set.
      if (!xj.is_empty()) x[std::size_t(j)] = xj;
    }
  }
  return Box::from_intervals(x);
}

SETBOUND_INLINE Box fallback_prediction(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& F,
                                        const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Eigen::VectorXd& lo,
                                        const Eigen::VectorXd& hi, const Eigen::Ref<const Eigen::VectorXd>& y,
                                        const Eigen::Ref<const Eigen::VectorXd>& u, const Box& d, const Box& v,
                                        const MeasurementCheck& check, const Box& h, const ModelWidening* widen) {
  const Eigen::Index n = lo.size(), nu = B.cols(), nd = F.cols();
  const Box xb = narrow_by_outputs(C, Z, lo, hi, y, v, check);
  // a coefficient a ± w (w = 0 unless the matrix is a rounded combination)
  auto coef = [](double a, double w) {
    if (w == 0.0) return Interval(a);
    return Interval(rounding::sub_down(a, w), rounding::add_up(a, w));
  };
  const Eigen::MatrixXd* wA = widen ? &widen->A : nullptr;
  const Eigen::MatrixXd* wB = widen ? &widen->B : nullptr;
  const Eigen::MatrixXd* wF = widen ? &widen->F : nullptr;
  std::vector<Interval> out;
  out.reserve(std::size_t(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    Interval s(0.0);
    for (Eigen::Index j = 0; j < n; ++j) {
      const double w = wA ? (*wA)(i, j) : 0.0;
      if (A(i, j) != 0.0 || w != 0.0) s = s + coef(A(i, j), w) * xb[j];
    }
    for (Eigen::Index j = 0; j < nu; ++j) {
      const double w = wB ? (*wB)(i, j) : 0.0;
      if (B(i, j) != 0.0 || w != 0.0) s = s + coef(B(i, j), w) * Interval(u(j));
    }
    for (Eigen::Index j = 0; j < nd; ++j) {
      const double w = wF ? (*wF)(i, j) : 0.0;
      if (F(i, j) != 0.0 || w != 0.0) s = s + coef(F(i, j), w) * d[j];
    }
    if (h.size() > 0) s = s + h[i];
    if (!std::isfinite(s.lo()) || !std::isfinite(s.hi()))
      throw NumericalError("y: the predicted box overflowed (component " + std::to_string(i) + ")");
    out.push_back(s);
  }
  return Box::from_intervals(out);
}

}  // namespace screen_detail
}  // namespace thesis
}  // namespace setbound
