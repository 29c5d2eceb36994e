// setbound — guaranteed scalar interval arithmetic (thesis §1, "Interval-arithmetic primitives").
//
// An Interval [lo, hi] is a closed, possibly unbounded set of reals (lo <= hi, infinite ends
// allowed, NaN never). The empty interval is encoded as (+inf, -inf), as in setbound.h.
//
// Guarantee: every operation returns an interval that contains the exact real result of the
// set operation (thesis eq. 1.23: [x]∘[y] = {a∘b : a ∈ [x], b ∈ [y]}), also after floating-point
// rounding. We do not switch the FPU rounding mode (that is global state, fragile under
// optimising compilers and other threads). Instead each endpoint is computed in
// round-to-nearest together with its *exact* rounding error, obtained by an error-free
// transformation:
//   + and −  TwoSum (Knuth):            a + b = s + e exactly,
//   ×        fused multiply-add:         a·b − p = fma(a, b, −p) exactly,
//   ÷        fma remainder:              a − q·b = fma(−q, b, a) exactly,
//   √        fma remainder:              x − s² = fma(−s, s, x) exactly.
// The endpoint is moved one ulp outward (std::nextafter) only when the sign of the error says the
// rounded value lies on the wrong side. Exact operations therefore stay exact ([−2,4]+[1,3] is
// exactly [−1,7], [6,12]/[2,3] exactly [2,6]), and inexact ones are enclosed by one ulp.
// The transformations are exact only away from underflow and overflow; in those ranges the code
// falls back to an unconditional outward step (or to ±DBL_MAX / ±inf on overflow).
//
// exp, sin and cos come from libm, which is not correctly rounded. Their results are widened
// by one ulp on each side, which encloses the true value as long as libm's error is below one
// ulp: glibc's table of known maximum errors lists at most 1 ulp for double exp, sin and cos on
// x86-64 (and the tests check the bounds against 200-bit mpmath values). A libm with larger
// errors would need a wider step here. sqr, integer powers, abs and sqrt do not use libm's
// approximations: they are computed with the error-free transformations above (abs is exact).
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <ostream>
#include <sstream>
#include <string>

#include "setbound/core/error.hpp"

// The error-free transformations need IEEE-754 double arithmetic evaluated as written: no
// value-changing optimisations and no excess precision (x87). Refuse to build otherwise rather
// than silently lose the enclosure guarantee.
#if defined(__FAST_MATH__)
#error "setbound/sets/interval.hpp: -ffast-math breaks the guaranteed outward rounding"
#endif
static_assert(std::numeric_limits<double>::is_iec559, "IEEE-754 doubles are required");
#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD != 0
#error "setbound/sets/interval.hpp: needs FLT_EVAL_METHOD == 0 (no excess precision)"
#endif

namespace setbound {

namespace rounding {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kMax = DBL_MAX;
// Below this magnitude the error terms of ×, ÷ and √ may fall into the subnormal range and be
// rounded themselves (exactness needs e_a + e_b >= emin + p − 1 = −970); stay well clear of it.
inline constexpr double kTiny = 0x1p-960;

inline double next_down(double x) { return std::nextafter(x, -kInf); }
inline double next_up(double x) { return std::nextafter(x, kInf); }

/// Exact error of s = fl(a + b) (Knuth's TwoSum, branch free): a + b = s + error.
double two_sum_error(double a, double b, double s);

/// Lower bound of a + b. Overflow from finite operands gives DBL_MAX (the exact sum exceeds it).
double add_down(double a, double b);

/// Upper bound of a + b.
double add_up(double a, double b);

inline double sub_down(double a, double b) { return add_down(a, -b); }
inline double sub_up(double a, double b) { return add_up(a, -b); }

/// Lower bound of a·b. Endpoint convention of interval arithmetic: 0·(±inf) = 0, because an
/// infinite end stands for "unbounded", and 0 times any real is 0.
double mul_down(double a, double b);

double mul_up(double a, double b);

namespace detail {
/// Sign of (a/b − q) for q = fl(a/b): the remainder a − q·b is exact (fma) and has the sign of
/// the error times sign(b). Returns 0 when q is exact, +1/−1 otherwise, 2 when unknown.
int quotient_error_sign(double a, double b, double q);
}  // namespace detail

/// Lower bound of a/b for b != 0. Infinite operands give exact results (inf/finite = inf,
/// finite/inf = 0); inf/inf is NaN and must be excluded by the caller.
double div_down(double a, double b);

double div_up(double a, double b);

/// Bounds of sqrt(x), x >= 0.
double sqrt_down(double x);

double sqrt_up(double x);

/// x^n for x >= 0 and n >= 0 by binary powering; every partial product is rounded in the same
/// direction, which is valid because all factors are non-negative (monotone). Lower bounds are
/// clamped at 0 (the true partial products are >= 0): an underflowing step may otherwise return
/// a negative lower bound, and a product of two negative lower bounds would break monotonicity.
double pow_down(double x, unsigned n);

double pow_up(double x, unsigned n);

}  // namespace rounding

class Interval {
 public:
  /// The empty interval (the default, as in IEEE 1788).
  Interval() : lo_(rounding::kInf), hi_(-rounding::kInf) {}

  /// The degenerate interval [x, x]; x must be a finite number.
  explicit Interval(double x) : Interval(x, x, "x") {}

  /// [lo, hi]. Throws NotFiniteError on NaN and InvalidArgumentError when lo > hi or when the
  /// interval holds no real number ([+inf, +inf], [−inf, −inf]); messages start with `name`.
  /// The empty encoding (+inf, −inf) is accepted and gives the empty interval.
  Interval(double lo, double hi, const std::string& name = "interval") : lo_(lo), hi_(hi) {
    validate(lo, hi, name);
  }

  static Interval empty() { return Interval(); }
  static Interval entire();
  /// No validation: for endpoints produced by this library's own directed-rounding code.
  static Interval unchecked(double lo, double hi);

  /// Throws unless (lo, hi) is a valid interval or the empty encoding.
  static void validate(double lo, double hi, const std::string& name);
  static bool is_empty_encoding(double lo, double hi);

  double lo() const { return lo_; }
  double hi() const { return hi_; }
  /// inf and sup of thesis eqs. 1.2–1.3.
  double inf() const { return lo_; }
  double sup() const { return hi_; }

  bool is_empty() const { return lo_ > hi_; }
  bool is_entire() const;
  bool is_degenerate() const { return lo_ == hi_; }
  bool is_bounded() const;

  /// Midpoint (eq. 1.4), computed without overflow. Unbounded intervals follow IEEE 1788:
  /// mid(entire) = 0, mid([−inf, b]) = −DBL_MAX, mid([a, +inf]) = DBL_MAX. NaN when empty.
  double mid() const;
  /// Radius (eq. 1.6), rounded up so that [mid − rad, mid + rad] ⊇ [x] always holds.
  double rad() const;
  /// Width (eq. 1.5), rounded up.
  double width() const;
  /// Magnitude |[x]| = max(|lo|, |hi|) (eq. 1.7). NaN when empty.
  double mag() const;
  /// Mignitude: min |x| over [x] (0 when 0 ∈ [x]). NaN when empty.
  double mig() const;

  bool contains(double x) const { return lo_ <= x && x <= hi_; }
  /// [this] ⊆ [other]; the empty set is a subset of everything.
  bool subset(const Interval& other) const;
  /// Intersection (eq. 1.31); empty when disjoint.
  Interval intersect(const Interval& other) const;
  /// Convex-hull union ⊔ (eqs. 1.33–1.34); the empty interval is its neutral element.
  Interval hull(const Interval& other) const;

  bool operator==(const Interval& o) const;
  bool operator!=(const Interval& o) const { return !(*this == o); }

  Interval operator-() const;

 private:
  double lo_, hi_;
};

std::ostream& operator<<(std::ostream& os, const Interval& x);

// ---- arithmetic (thesis §1.2.4) ------------------------------------------------------------

/// [x] + [y] = [x̲ + y̲, x̄ + ȳ] (eq. 1.24).
Interval operator+(const Interval& x, const Interval& y);

/// [x] − [y] = [x̲ − ȳ, x̄ − y̲] (eq. 1.25).
Interval operator-(const Interval& x, const Interval& y);

/// [x]·[y] = [min S, max S], S = the four endpoint products (eq. 1.26), each rounded outward.
Interval operator*(const Interval& x, const Interval& y);

/// [x]/[y] = hull{a/b : a ∈ [x], b ∈ [y], b ≠ 0} (eq. 1.29 with the extended reciprocal 1.28).
/// Computed directly from the endpoints (not as [x]·(1/[y])) so exact quotients stay exact.
/// Division by [0, 0] gives the empty set; [0, 0]/[y] = [0, 0] for any other [y].
Interval operator/(const Interval& x, const Interval& y);

inline Interval operator+(const Interval& x, double a) { return x + Interval(a); }
inline Interval operator+(double a, const Interval& x) { return Interval(a) + x; }
inline Interval operator-(const Interval& x, double a) { return x - Interval(a); }
inline Interval operator-(double a, const Interval& x) { return Interval(a) - x; }
/// α[x] (eq. 1.27).
inline Interval operator*(const Interval& x, double a) { return x * Interval(a); }
inline Interval operator*(double a, const Interval& x) { return Interval(a) * x; }
inline Interval operator/(const Interval& x, double a) { return x / Interval(a); }
inline Interval operator/(double a, const Interval& x) { return Interval(a) / x; }

inline Interval& operator+=(Interval& x, const Interval& y) { return x = x + y; }
inline Interval& operator-=(Interval& x, const Interval& y) { return x = x - y; }
inline Interval& operator*=(Interval& x, const Interval& y) { return x = x * y; }
inline Interval& operator/=(Interval& x, const Interval& y) { return x = x / y; }

// ---- elementary functions ------------------------------------------------------------------
// In namespace setbound::ia (interval analysis) rather than setbound itself, so that an
// unqualified sqrt(double) elsewhere in namespace setbound is never hidden by these overloads.
namespace ia {

/// 1/[x] with the extended cases of thesis eq. 1.28 (reading of §8): ∅ for [0,0], [1/x̄, 1/x̲] when
/// 0 ∉ [x], [1/x̄, +inf] when x̲ = 0 < x̄, [−inf, 1/x̲] when x̲ < 0 = x̄, entire when x̲ < 0 < x̄.
inline Interval reciprocal(const Interval& x) { return Interval(1.0) / x; }

/// {t² : t ∈ [x]} = [0, max(x̲², x̄²)] when 0 ∈ [x] (thesis §1.2.8: NOT [x]·[x], which would give
/// [x̲x̄, …] < 0).
Interval sqr(const Interval& x);

/// sqrt over [x] ∩ [0, +inf); empty when [x] < 0.
Interval sqrt(const Interval& x);

/// Exact: |x| is monotone on each sign part.
Interval abs(const Interval& x);

/// Integer power {t^n : t ∈ [x]} (t ≠ 0 when n < 0), by binary powering with directed rounding.
/// n = 0 gives [1, 1]; a negative n is the reciprocal of the positive power (so [x]^(−2) over an
/// interval containing 0 is [1/mag², +inf] and [0,0]^(−n) is empty).
Interval pow(const Interval& x, int n);

/// exp is increasing; libm's exp is widened by one ulp each side (see the file comment) and the
/// lower end is clamped at 0. exp(0) = 1 and exp(±inf) are exact.
Interval exp(const Interval& x);

namespace detail {
inline constexpr double kPi = 3.14159265358979323846264338327950288;
inline constexpr double kTwoPi = 2 * kPi;
/// Whether [lo, hi] may contain a point offset + 2kπ for an integer k. Decided in floating point
/// with a generous relative slack, so that it errs only towards "yes": a wrong "yes" makes the
/// result use the extremal value ±1 (still an enclosure), a wrong "no" would lose guarantee.
bool may_contain_periodic_point(double lo, double hi, double offset);

/// Range of a 2π-periodic function f with maximum at offset_max + 2kπ and minimum at
/// offset_min + 2kπ, monotone between them (sin, cos). Values at the ends come from libm and are
/// widened by one ulp; interior extrema found by the period test give exactly ±1.
template <class F>
Interval periodic_range(const Interval& x, F f, double offset_max, double offset_min) {
  using namespace rounding;
  if (x.is_empty()) return x;
  if (!x.is_bounded() || x.hi() - x.lo() >= kTwoPi) return Interval::unchecked(-1.0, 1.0);
  const double fl = f(x.lo()), fh = f(x.hi());
  double lo = std::max(-1.0, next_down(std::min(fl, fh)));
  double hi = std::min(1.0, next_up(std::max(fl, fh)));
  if (may_contain_periodic_point(x.lo(), x.hi(), offset_max)) hi = 1.0;
  if (may_contain_periodic_point(x.lo(), x.hi(), offset_min)) lo = -1.0;
  return Interval::unchecked(lo, hi);
}
}  // namespace detail

/// sin over [x]; maxima at π/2 + 2kπ and minima at −π/2 + 2kπ inside [x] give ±1 (thesis §1.2.8).
Interval sin(const Interval& x);

/// cos over [x]; maxima at 2kπ and minima at π + 2kπ inside [x] give ±1.
Interval cos(const Interval& x);

}  // namespace ia
}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/interval.ipp"
#endif
