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
inline double two_sum_error(double a, double b, double s) {
  const double bb = s - a;
  const double aa = s - bb;
  return (a - aa) + (b - bb);
}

/// Lower bound of a + b. Overflow from finite operands gives DBL_MAX (the exact sum exceeds it).
inline double add_down(double a, double b) {
  const double s = a + b;
  if (std::isnan(s)) return -kInf;  // inf − inf: nothing is known
  if (std::isinf(s)) return (std::isfinite(a) && std::isfinite(b) && s > 0) ? kMax : s;
  const double e = two_sum_error(a, b, s);
  if (!std::isfinite(e)) return next_down(s);
  return e < 0 ? next_down(s) : s;
}

/// Upper bound of a + b.
inline double add_up(double a, double b) {
  const double s = a + b;
  if (std::isnan(s)) return kInf;
  if (std::isinf(s)) return (std::isfinite(a) && std::isfinite(b) && s < 0) ? -kMax : s;
  const double e = two_sum_error(a, b, s);
  if (!std::isfinite(e)) return next_up(s);
  return e > 0 ? next_up(s) : s;
}

inline double sub_down(double a, double b) { return add_down(a, -b); }
inline double sub_up(double a, double b) { return add_up(a, -b); }

/// Lower bound of a·b. Endpoint convention of interval arithmetic: 0·(±inf) = 0, because an
/// infinite end stands for "unbounded", and 0 times any real is 0.
inline double mul_down(double a, double b) {
  if (a == 0 || b == 0) return 0.0;
  const double p = a * b;
  if (std::isinf(p)) return (std::isfinite(a) && std::isfinite(b) && p > 0) ? kMax : p;
  if (std::fabs(p) < kTiny) return next_down(p);
  const double e = std::fma(a, b, -p);
  return e < 0 ? next_down(p) : p;
}

inline double mul_up(double a, double b) {
  if (a == 0 || b == 0) return 0.0;
  const double p = a * b;
  if (std::isinf(p)) return (std::isfinite(a) && std::isfinite(b) && p < 0) ? -kMax : p;
  if (std::fabs(p) < kTiny) return next_up(p);
  const double e = std::fma(a, b, -p);
  return e > 0 ? next_up(p) : p;
}

namespace detail {
/// Sign of (a/b − q) for q = fl(a/b): the remainder a − q·b is exact (fma) and has the sign of
/// the error times sign(b). Returns 0 when q is exact, +1/−1 otherwise, 2 when unknown.
inline int quotient_error_sign(double a, double b, double q) {
  if (std::fabs(q) < kTiny || std::fabs(a) < kTiny) return 2;
  const double r = std::fma(-q, b, a);
  if (r == 0) return 0;
  return ((r > 0) == (b > 0)) ? 1 : -1;
}
}  // namespace detail

/// Lower bound of a/b for b != 0. Infinite operands give exact results (inf/finite = inf,
/// finite/inf = 0); inf/inf is NaN and must be excluded by the caller.
inline double div_down(double a, double b) {
  const double q = a / b;
  if (a == 0 || std::isinf(a) || std::isinf(b)) return q;
  if (std::isinf(q)) return q > 0 ? kMax : q;
  const int s = detail::quotient_error_sign(a, b, q);
  return (s < 0 || s == 2) ? next_down(q) : q;
}

inline double div_up(double a, double b) {
  const double q = a / b;
  if (a == 0 || std::isinf(a) || std::isinf(b)) return q;
  if (std::isinf(q)) return q < 0 ? -kMax : q;
  const int s = detail::quotient_error_sign(a, b, q);
  return (s > 0 || s == 2) ? next_up(q) : q;
}

/// Bounds of sqrt(x), x >= 0.
inline double sqrt_down(double x) {
  const double s = std::sqrt(x);
  if (x == 0 || std::isinf(x)) return s;
  if (x < kTiny) return std::max(0.0, next_down(s));
  const double r = std::fma(-s, s, x);  // x − s², exact
  return r < 0 ? next_down(s) : s;
}

inline double sqrt_up(double x) {
  const double s = std::sqrt(x);
  if (x == 0 || std::isinf(x)) return s;
  if (x < kTiny) return next_up(s);
  const double r = std::fma(-s, s, x);
  return r > 0 ? next_up(s) : s;
}

/// x^n for x >= 0 and n >= 0 by binary powering; every partial product is rounded in the same
/// direction, which is valid because all factors are non-negative (monotone). Lower bounds are
/// clamped at 0 (the true partial products are >= 0): an underflowing step may otherwise return
/// a negative lower bound, and a product of two negative lower bounds would break monotonicity.
inline double pow_down(double x, unsigned n) {
  double result = 1.0, base = x;
  while (n > 0) {
    if (n & 1u) result = std::max(0.0, mul_down(result, base));
    n >>= 1u;
    if (n > 0) base = std::max(0.0, mul_down(base, base));
  }
  return result;
}

inline double pow_up(double x, unsigned n) {
  double result = 1.0, base = x;
  while (n > 0) {
    if (n & 1u) result = mul_up(result, base);
    n >>= 1u;
    if (n > 0) base = mul_up(base, base);
  }
  return result;
}

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
  static Interval entire() { return unchecked(-rounding::kInf, rounding::kInf); }
  /// No validation: for endpoints produced by this library's own directed-rounding code.
  static Interval unchecked(double lo, double hi) {
    Interval r;
    r.lo_ = lo;
    r.hi_ = hi;
    return r;
  }

  /// Throws unless (lo, hi) is a valid interval or the empty encoding.
  static void validate(double lo, double hi, const std::string& name) {
    if (std::isnan(lo) || std::isnan(hi)) {
      std::ostringstream s;
      s << name << ": interval end is NaN ([" << lo << ", " << hi << "])";
      throw NotFiniteError(s.str());
    }
    if (is_empty_encoding(lo, hi)) return;
    if (lo > hi) {
      std::ostringstream s;
      s << name << ": lower end " << lo << " is greater than upper end " << hi;
      throw InvalidArgumentError(s.str());
    }
    if (lo == rounding::kInf || hi == -rounding::kInf) {
      std::ostringstream s;
      s << name << ": [" << lo << ", " << hi << "] contains no real number";
      throw InvalidArgumentError(s.str());
    }
  }
  static bool is_empty_encoding(double lo, double hi) {
    return lo == rounding::kInf && hi == -rounding::kInf;
  }

  double lo() const { return lo_; }
  double hi() const { return hi_; }
  /// inf and sup of thesis eqs. 1.2–1.3.
  double inf() const { return lo_; }
  double sup() const { return hi_; }

  bool is_empty() const { return lo_ > hi_; }
  bool is_entire() const { return lo_ == -rounding::kInf && hi_ == rounding::kInf; }
  bool is_degenerate() const { return lo_ == hi_; }
  bool is_bounded() const { return std::isfinite(lo_) && std::isfinite(hi_); }

  /// Midpoint (eq. 1.4), computed without overflow. Unbounded intervals follow IEEE 1788:
  /// mid(entire) = 0, mid([−inf, b]) = −DBL_MAX, mid([a, +inf]) = DBL_MAX. NaN when empty.
  double mid() const {
    if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
    if (lo_ == -rounding::kInf) return hi_ == rounding::kInf ? 0.0 : -rounding::kMax;
    if (hi_ == rounding::kInf) return rounding::kMax;
    const double m = 0.5 * lo_ + 0.5 * hi_;  // no overflow, unlike (lo + hi)/2
    // Exact midpoints of tiny intervals can be lost by the halving; keep m inside [lo, hi].
    return std::min(std::max(m, lo_), hi_);
  }
  /// Radius (eq. 1.6), rounded up so that [mid − rad, mid + rad] ⊇ [x] always holds.
  double rad() const {
    if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
    const double m = mid();
    return std::max(rounding::sub_up(m, lo_), rounding::sub_up(hi_, m));
  }
  /// Width (eq. 1.5), rounded up.
  double width() const {
    if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
    return rounding::sub_up(hi_, lo_);
  }
  /// Magnitude |[x]| = max(|lo|, |hi|) (eq. 1.7). NaN when empty.
  double mag() const {
    if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
    return std::max(std::fabs(lo_), std::fabs(hi_));
  }
  /// Mignitude: min |x| over [x] (0 when 0 ∈ [x]). NaN when empty.
  double mig() const {
    if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
    if (lo_ <= 0 && hi_ >= 0) return 0.0;
    return std::min(std::fabs(lo_), std::fabs(hi_));
  }

  bool contains(double x) const { return lo_ <= x && x <= hi_; }
  /// [this] ⊆ [other]; the empty set is a subset of everything.
  bool subset(const Interval& other) const {
    return is_empty() || (other.lo_ <= lo_ && hi_ <= other.hi_);
  }
  /// Intersection (eq. 1.31); empty when disjoint.
  Interval intersect(const Interval& other) const {
    const double l = std::max(lo_, other.lo_), h = std::min(hi_, other.hi_);
    return l <= h ? unchecked(l, h) : empty();
  }
  /// Convex-hull union ⊔ (eqs. 1.33–1.34); the empty interval is its neutral element.
  Interval hull(const Interval& other) const {
    if (is_empty()) return other;
    if (other.is_empty()) return *this;
    return unchecked(std::min(lo_, other.lo_), std::max(hi_, other.hi_));
  }

  bool operator==(const Interval& o) const {
    return (is_empty() && o.is_empty()) || (lo_ == o.lo_ && hi_ == o.hi_);
  }
  bool operator!=(const Interval& o) const { return !(*this == o); }

  Interval operator-() const { return is_empty() ? empty() : unchecked(-hi_, -lo_); }

 private:
  double lo_, hi_;
};

inline std::ostream& operator<<(std::ostream& os, const Interval& x) {
  if (x.is_empty()) return os << "[empty]";
  return os << "[" << x.lo() << ", " << x.hi() << "]";
}

// ---- arithmetic (thesis §1.2.4) ------------------------------------------------------------

/// [x] + [y] = [x̲ + y̲, x̄ + ȳ] (eq. 1.24).
inline Interval operator+(const Interval& x, const Interval& y) {
  if (x.is_empty() || y.is_empty()) return Interval::empty();
  return Interval::unchecked(rounding::add_down(x.lo(), y.lo()), rounding::add_up(x.hi(), y.hi()));
}

/// [x] − [y] = [x̲ − ȳ, x̄ − y̲] (eq. 1.25).
inline Interval operator-(const Interval& x, const Interval& y) {
  if (x.is_empty() || y.is_empty()) return Interval::empty();
  return Interval::unchecked(rounding::sub_down(x.lo(), y.hi()), rounding::sub_up(x.hi(), y.lo()));
}

/// [x]·[y] = [min S, max S], S = the four endpoint products (eq. 1.26), each rounded outward.
inline Interval operator*(const Interval& x, const Interval& y) {
  if (x.is_empty() || y.is_empty()) return Interval::empty();
  const double a[2] = {x.lo(), x.hi()}, b[2] = {y.lo(), y.hi()};
  double lo = rounding::kInf, hi = -rounding::kInf;
  for (double u : a)
    for (double v : b) {
      lo = std::min(lo, rounding::mul_down(u, v));
      hi = std::max(hi, rounding::mul_up(u, v));
    }
  return Interval::unchecked(lo, hi);
}

/// [x]/[y] = hull{a/b : a ∈ [x], b ∈ [y], b ≠ 0} (eq. 1.29 with the extended reciprocal 1.28).
/// Computed directly from the endpoints (not as [x]·(1/[y])) so exact quotients stay exact.
/// Division by [0, 0] gives the empty set; [0, 0]/[y] = [0, 0] for any other [y].
inline Interval operator/(const Interval& x, const Interval& y) {
  using namespace rounding;
  if (x.is_empty() || y.is_empty()) return Interval::empty();
  const double xl = x.lo(), xh = x.hi(), yl = y.lo(), yh = y.hi();
  if (yl == 0 && yh == 0) return Interval::empty();
  if (yl > 0 || yh < 0) {
    // 0 ∉ [y]: the quotient is continuous and monotone in each argument on the box, so its
    // extremes are among the endpoint quotients. inf/inf is skipped: the candidates a/inf = 0 and
    // inf/b = ±inf of the same box already span everything inf/inf could stand for.
    double lo = kInf, hi = -kInf;
    for (double u : {xl, xh})
      for (double v : {yl, yh}) {
        if (std::isinf(u) && std::isinf(v)) continue;
        lo = std::min(lo, div_down(u, v));
        hi = std::max(hi, div_up(u, v));
      }
    if (lo == 0) lo = 0.0;  // normalise −0
    if (hi == 0) hi = 0.0;
    return Interval::unchecked(lo, hi);
  }
  if (xl == 0 && xh == 0) return Interval::unchecked(0.0, 0.0);
  if (yl == 0) {  // [y] = [0, ȳ], ȳ > 0: b ranges over (0, ȳ]
    if (xl >= 0) return Interval::unchecked(div_down(xl, yh) + 0.0, kInf);
    if (xh <= 0) return Interval::unchecked(-kInf, div_up(xh, yh) + 0.0);
    return Interval::entire();
  }
  if (yh == 0) {  // [y] = [y̲, 0], y̲ < 0: b ranges over [y̲, 0)
    if (xl >= 0) return Interval::unchecked(-kInf, div_up(xl, yl) + 0.0);
    if (xh <= 0) return Interval::unchecked(div_down(xh, yl) + 0.0, kInf);
    return Interval::entire();
  }
  return Interval::entire();  // 0 strictly inside [y] and [x] ≠ [0, 0]
}

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
inline Interval sqr(const Interval& x) {
  using namespace rounding;
  if (x.is_empty()) return x;
  const double a = x.mig(), b = x.mag();
  return Interval::unchecked(std::max(0.0, mul_down(a, a)), mul_up(b, b));
}

/// sqrt over [x] ∩ [0, +inf); empty when [x] < 0.
inline Interval sqrt(const Interval& x) {
  using namespace rounding;
  if (x.is_empty() || x.hi() < 0) return Interval::empty();
  const double l = std::max(x.lo(), 0.0);
  return Interval::unchecked(sqrt_down(l), sqrt_up(x.hi()));
}

/// Exact: |x| is monotone on each sign part.
inline Interval abs(const Interval& x) {
  if (x.is_empty()) return x;
  return Interval::unchecked(x.mig(), x.mag());
}

/// Integer power {t^n : t ∈ [x]} (t ≠ 0 when n < 0), by binary powering with directed rounding.
/// n = 0 gives [1, 1]; a negative n is the reciprocal of the positive power (so [x]^(−2) over an
/// interval containing 0 is [1/mag², +inf] and [0,0]^(−n) is empty).
inline Interval pow(const Interval& x, int n) {
  using namespace rounding;
  if (x.is_empty()) return x;
  if (n == 0) return Interval(1.0);
  if (n < 0) {
    const unsigned m = n == std::numeric_limits<int>::min() ? 0x80000000u : unsigned(-n);
    // Compute the positive power first, then take the reciprocal: both steps enclose.
    Interval p;
    if (m % 2 == 0) {
      p = Interval::unchecked(pow_down(x.mig(), m), pow_up(x.mag(), m));
    } else {
      const double l = x.lo() >= 0 ? pow_down(x.lo(), m) : -pow_up(-x.lo(), m);
      const double h = x.hi() >= 0 ? pow_up(x.hi(), m) : -pow_down(-x.hi(), m);
      p = Interval::unchecked(l, h);
    }
    // 1/t^m over the *set* t^m, t ∈ [x], t ≠ 0: for odd m, t^m keeps the sign of t, so the
    // reciprocal of the power interval is the exact answer; for even m, t^m ≥ 0.
    return reciprocal(p);
  }
  const unsigned m = unsigned(n);
  if (m % 2 == 0) return Interval::unchecked(pow_down(x.mig(), m), pow_up(x.mag(), m));
  // Odd powers are increasing.
  const double l = x.lo() >= 0 ? pow_down(x.lo(), m) : -pow_up(-x.lo(), m);
  const double h = x.hi() >= 0 ? pow_up(x.hi(), m) : -pow_down(-x.hi(), m);
  return Interval::unchecked(l, h);
}

/// exp is increasing; libm's exp is widened by one ulp each side (see the file comment) and the
/// lower end is clamped at 0. exp(0) = 1 and exp(±inf) are exact.
inline Interval exp(const Interval& x) {
  using namespace rounding;
  if (x.is_empty()) return x;
  auto lower = [](double t) {
    if (t == 0) return 1.0;
    if (std::isinf(t)) return t > 0 ? kInf : 0.0;
    return std::max(0.0, next_down(std::exp(t)));
  };
  auto upper = [](double t) {
    if (t == 0) return 1.0;
    if (std::isinf(t)) return t > 0 ? kInf : 0.0;
    return next_up(std::exp(t));
  };
  return Interval::unchecked(lower(x.lo()), upper(x.hi()));
}

namespace detail {
inline constexpr double kPi = 3.14159265358979323846264338327950288;
inline constexpr double kTwoPi = 2 * kPi;
/// Whether [lo, hi] may contain a point offset + 2kπ for an integer k. Decided in floating point
/// with a generous relative slack, so that it errs only towards "yes": a wrong "yes" makes the
/// result use the extremal value ±1 (still an enclosure), a wrong "no" would lose guarantee.
inline bool may_contain_periodic_point(double lo, double hi, double offset) {
  const double kl = (lo - offset) / kTwoPi, kh = (hi - offset) / kTwoPi;
  const double slack_l = 1e-9 * std::max(1.0, std::fabs(kl));
  const double slack_h = 1e-9 * std::max(1.0, std::fabs(kh));
  return std::ceil(kl - slack_l) <= std::floor(kh + slack_h);
}

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
inline Interval sin(const Interval& x) {
  return detail::periodic_range(x, [](double t) { return std::sin(t); }, 0.5 * detail::kPi, -0.5 * detail::kPi);
}

/// cos over [x]; maxima at 2kπ and minima at π + 2kπ inside [x] give ±1.
inline Interval cos(const Interval& x) {
  return detail::periodic_range(x, [](double t) { return std::cos(t); }, 0.0, detail::kPi);
}

}  // namespace ia
}  // namespace setbound
