// setbound — definitions of the functions declared in setbound/sets/interval.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/sets/interval.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace rounding {

SETBOUND_INLINE double two_sum_error(double a, double b, double s) {
  const double bb = s - a;
  const double aa = s - bb;
  return (a - aa) + (b - bb);
}

SETBOUND_INLINE double add_down(double a, double b) {
  const double s = a + b;
  if (std::isnan(s)) return -kInf;  // inf − inf: nothing is known
  if (std::isinf(s)) return (std::isfinite(a) && std::isfinite(b) && s > 0) ? kMax : s;
  const double e = two_sum_error(a, b, s);
  if (!std::isfinite(e)) return next_down(s);
  return e < 0 ? next_down(s) : s;
}

SETBOUND_INLINE double add_up(double a, double b) {
  const double s = a + b;
  if (std::isnan(s)) return kInf;
  if (std::isinf(s)) return (std::isfinite(a) && std::isfinite(b) && s < 0) ? -kMax : s;
  const double e = two_sum_error(a, b, s);
  if (!std::isfinite(e)) return next_up(s);
  return e > 0 ? next_up(s) : s;
}

SETBOUND_INLINE double mul_down(double a, double b) {
  if (a == 0 || b == 0) return 0.0;
  const double p = a * b;
  if (std::isinf(p)) return (std::isfinite(a) && std::isfinite(b) && p > 0) ? kMax : p;
  if (std::fabs(p) < kTiny) return next_down(p);
  const double e = std::fma(a, b, -p);
  return e < 0 ? next_down(p) : p;
}

SETBOUND_INLINE double mul_up(double a, double b) {
  if (a == 0 || b == 0) return 0.0;
  const double p = a * b;
  if (std::isinf(p)) return (std::isfinite(a) && std::isfinite(b) && p < 0) ? -kMax : p;
  if (std::fabs(p) < kTiny) return next_up(p);
  const double e = std::fma(a, b, -p);
  return e > 0 ? next_up(p) : p;
}

}  // namespace rounding
}  // namespace setbound

namespace setbound {
namespace rounding {
namespace detail {

SETBOUND_INLINE int quotient_error_sign(double a, double b, double q) {
  if (std::fabs(q) < kTiny || std::fabs(a) < kTiny) return 2;
  const double r = std::fma(-q, b, a);
  if (r == 0) return 0;
  return ((r > 0) == (b > 0)) ? 1 : -1;
}

}  // namespace detail
}  // namespace rounding
}  // namespace setbound

namespace setbound {
namespace rounding {

SETBOUND_INLINE double div_down(double a, double b) {
  const double q = a / b;
  if (a == 0 || std::isinf(a) || std::isinf(b)) return q;
  if (std::isinf(q)) return q > 0 ? kMax : q;
  const int s = detail::quotient_error_sign(a, b, q);
  return (s < 0 || s == 2) ? next_down(q) : q;
}

SETBOUND_INLINE double div_up(double a, double b) {
  const double q = a / b;
  if (a == 0 || std::isinf(a) || std::isinf(b)) return q;
  if (std::isinf(q)) return q < 0 ? -kMax : q;
  const int s = detail::quotient_error_sign(a, b, q);
  return (s > 0 || s == 2) ? next_up(q) : q;
}

SETBOUND_INLINE double sqrt_down(double x) {
  const double s = std::sqrt(x);
  if (x == 0 || std::isinf(x)) return s;
  if (x < kTiny) return std::max(0.0, next_down(s));
  const double r = std::fma(-s, s, x);  // x − s², exact
  return r < 0 ? next_down(s) : s;
}

SETBOUND_INLINE double sqrt_up(double x) {
  const double s = std::sqrt(x);
  if (x == 0 || std::isinf(x)) return s;
  if (x < kTiny) return next_up(s);
  const double r = std::fma(-s, s, x);
  return r > 0 ? next_up(s) : s;
}

SETBOUND_INLINE double pow_down(double x, unsigned n) {
  double result = 1.0, base = x;
  while (n > 0) {
    if (n & 1u) result = std::max(0.0, mul_down(result, base));
    n >>= 1u;
    if (n > 0) base = std::max(0.0, mul_down(base, base));
  }
  return result;
}

SETBOUND_INLINE double pow_up(double x, unsigned n) {
  double result = 1.0, base = x;
  while (n > 0) {
    if (n & 1u) result = mul_up(result, base);
    n >>= 1u;
    if (n > 0) base = mul_up(base, base);
  }
  return result;
}

}  // namespace rounding
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE Interval Interval::entire() { return unchecked(-rounding::kInf, rounding::kInf); }

SETBOUND_INLINE Interval Interval::unchecked(double lo, double hi) {
  Interval r;
  r.lo_ = lo;
  r.hi_ = hi;
  return r;
}

SETBOUND_INLINE void Interval::validate(double lo, double hi, const std::string& name) {
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

SETBOUND_INLINE bool Interval::is_empty_encoding(double lo, double hi) {
  return lo == rounding::kInf && hi == -rounding::kInf;
}

SETBOUND_INLINE bool Interval::is_entire() const { return lo_ == -rounding::kInf && hi_ == rounding::kInf; }

SETBOUND_INLINE bool Interval::is_bounded() const { return std::isfinite(lo_) && std::isfinite(hi_); }

SETBOUND_INLINE double Interval::mid() const {
  if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
  if (lo_ == -rounding::kInf) return hi_ == rounding::kInf ? 0.0 : -rounding::kMax;
  if (hi_ == rounding::kInf) return rounding::kMax;
  const double m = 0.5 * lo_ + 0.5 * hi_;  // no overflow, unlike (lo + hi)/2
  // Exact midpoints of tiny intervals can be lost by the halving; keep m inside [lo, hi].
  return std::min(std::max(m, lo_), hi_);
}

SETBOUND_INLINE double Interval::rad() const {
  if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
  const double m = mid();
  return std::max(rounding::sub_up(m, lo_), rounding::sub_up(hi_, m));
}

SETBOUND_INLINE double Interval::width() const {
  if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
  return rounding::sub_up(hi_, lo_);
}

SETBOUND_INLINE double Interval::mag() const {
  if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
  return std::max(std::fabs(lo_), std::fabs(hi_));
}

SETBOUND_INLINE double Interval::mig() const {
  if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
  if (lo_ <= 0 && hi_ >= 0) return 0.0;
  return std::min(std::fabs(lo_), std::fabs(hi_));
}

SETBOUND_INLINE bool Interval::subset(const Interval& other) const {
  return is_empty() || (other.lo_ <= lo_ && hi_ <= other.hi_);
}

SETBOUND_INLINE Interval Interval::intersect(const Interval& other) const {
  const double l = std::max(lo_, other.lo_), h = std::min(hi_, other.hi_);
  return l <= h ? unchecked(l, h) : empty();
}

SETBOUND_INLINE Interval Interval::hull(const Interval& other) const {
  if (is_empty()) return other;
  if (other.is_empty()) return *this;
  return unchecked(std::min(lo_, other.lo_), std::max(hi_, other.hi_));
}

SETBOUND_INLINE bool Interval::operator==(const Interval& o) const {
  return (is_empty() && o.is_empty()) || (lo_ == o.lo_ && hi_ == o.hi_);
}

SETBOUND_INLINE Interval Interval::operator-() const { return is_empty() ? empty() : unchecked(-hi_, -lo_); }

SETBOUND_INLINE std::ostream& operator<<(std::ostream& os, const Interval& x) {
  if (x.is_empty()) return os << "[empty]";
  return os << "[" << x.lo() << ", " << x.hi() << "]";
}

SETBOUND_INLINE Interval operator+(const Interval& x, const Interval& y) {
  if (x.is_empty() || y.is_empty()) return Interval::empty();
  return Interval::unchecked(rounding::add_down(x.lo(), y.lo()), rounding::add_up(x.hi(), y.hi()));
}

SETBOUND_INLINE Interval operator-(const Interval& x, const Interval& y) {
  if (x.is_empty() || y.is_empty()) return Interval::empty();
  return Interval::unchecked(rounding::sub_down(x.lo(), y.hi()), rounding::sub_up(x.hi(), y.lo()));
}

SETBOUND_INLINE Interval operator*(const Interval& x, const Interval& y) {
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

SETBOUND_INLINE Interval operator/(const Interval& x, const Interval& y) {
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

}  // namespace setbound

namespace setbound {
namespace ia {

SETBOUND_INLINE Interval sqr(const Interval& x) {
  using namespace rounding;
  if (x.is_empty()) return x;
  const double a = x.mig(), b = x.mag();
  return Interval::unchecked(std::max(0.0, mul_down(a, a)), mul_up(b, b));
}

SETBOUND_INLINE Interval sqrt(const Interval& x) {
  using namespace rounding;
  if (x.is_empty() || x.hi() < 0) return Interval::empty();
  const double l = std::max(x.lo(), 0.0);
  return Interval::unchecked(sqrt_down(l), sqrt_up(x.hi()));
}

SETBOUND_INLINE Interval abs(const Interval& x) {
  if (x.is_empty()) return x;
  return Interval::unchecked(x.mig(), x.mag());
}

SETBOUND_INLINE Interval pow(const Interval& x, int n) {
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

SETBOUND_INLINE Interval exp(const Interval& x) {
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

}  // namespace ia
}  // namespace setbound

namespace setbound {
namespace ia {
namespace detail {

SETBOUND_INLINE bool may_contain_periodic_point(double lo, double hi, double offset) {
  const double kl = (lo - offset) / kTwoPi, kh = (hi - offset) / kTwoPi;
  const double slack_l = 1e-9 * std::max(1.0, std::fabs(kl));
  const double slack_h = 1e-9 * std::max(1.0, std::fabs(kh));
  return std::ceil(kl - slack_l) <= std::floor(kh + slack_h);
}

}  // namespace detail
}  // namespace ia
}  // namespace setbound

namespace setbound {
namespace ia {

SETBOUND_INLINE Interval sin(const Interval& x) {
  return detail::periodic_range(x, [](double t) { return std::sin(t); }, 0.5 * detail::kPi, -0.5 * detail::kPi);
}

SETBOUND_INLINE Interval cos(const Interval& x) {
  return detail::periodic_range(x, [](double t) { return std::cos(t); }, 0.0, detail::kPi);
}

}  // namespace ia
}  // namespace setbound
