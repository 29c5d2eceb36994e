// Scalar interval arithmetic (thesis §1, reference checks §3.1 and §3.2, guarantees §7 item 1):
// exact table values, extended reciprocal/division, outward rounding checked against exact
// arithmetic, enclosure of sampled point evaluations (also with infinite ends), inclusion
// isotonicity, and the C ABI sb_interval_* with its error paths.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "c_api_common.hpp"
#include "setbound/sets/interval.hpp"

using setbound::Interval;
namespace ia = setbound::ia;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

Interval I(double lo, double hi) { return Interval(lo, hi); }

::testing::AssertionResult same(const Interval& got, const Interval& want) {
  if (got == want) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "got " << got << ", want " << want;
}

::testing::AssertionResult near(const Interval& got, double lo, double hi, double tol) {
  if (std::fabs(got.lo() - lo) <= tol && std::fabs(got.hi() - hi) <= tol)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "got " << got << ", want [" << lo << ", " << hi
                                       << "] within " << tol;
}

// ---- random generation --------------------------------------------------------------------

struct Gen {
  std::mt19937_64 rng{20240521};
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); }

  /// Random non-empty interval: bounded, degenerate, touching 0, or with infinite ends.
  Interval interval() {
    const double a = uniform(-10, 10), b = uniform(-10, 10);
    switch (pick(8)) {
      case 0: return Interval(a);
      case 1: return I(-kInf, std::max(a, b));
      case 2: return I(std::min(a, b), kInf);
      case 3: return I(0.0, std::fabs(a));
      case 4: return I(-std::fabs(a), 0.0);
      case 5: return Interval::entire();
      default: return I(std::min(a, b), std::max(a, b));
    }
  }
  /// A finite point of a non-empty interval (unbounded ends sampled out to ±1e6, and the
  /// finite ends themselves with some probability since extremes often sit there).
  double point(const Interval& x) {
    const double lo = std::isfinite(x.lo()) ? x.lo() : std::min(x.hi(), 0.0) - 1e6;
    const double hi = std::isfinite(x.hi()) ? x.hi() : std::max(x.lo(), 0.0) + 1e6;
    switch (pick(6)) {
      case 0: return lo;
      case 1: return hi;
      default: return lo + (hi - lo) * uniform(0, 1);
    }
  }
  /// A random sub-interval of x (for isotonicity).
  Interval sub(const Interval& x) {
    double a = point(x), b = point(x);
    if (a > b) std::swap(a, b);
    if (pick(4) == 0) a = x.lo();  // keep infinite ends sometimes
    if (pick(4) == 0) b = x.hi();
    return I(a, b);
  }
};

using BinaryOp = std::function<Interval(const Interval&, const Interval&)>;
using PointBinary = std::function<double(double, double)>;

struct NamedBinary {
  const char* name;
  BinaryOp op;
  PointBinary f;
};

std::vector<NamedBinary> binary_ops() {
  return {
      {"add", [](const Interval& a, const Interval& b) { return a + b; },
       [](double a, double b) { return a + b; }},
      {"sub", [](const Interval& a, const Interval& b) { return a - b; },
       [](double a, double b) { return a - b; }},
      {"mul", [](const Interval& a, const Interval& b) { return a * b; },
       [](double a, double b) { return a * b; }},
      {"div", [](const Interval& a, const Interval& b) { return a / b; },
       [](double a, double b) { return a / b; }},
  };
}

struct NamedUnary {
  const char* name;
  std::function<Interval(const Interval&)> op;
  std::function<long double(long double)> f;  // long double reference (more accurate than libm)
  bool in_domain(double) const { return true; }
};

std::vector<NamedUnary> unary_ops() {
  return {
      {"neg", [](const Interval& x) { return -x; }, [](long double t) { return -t; }},
      {"recip", [](const Interval& x) { return ia::reciprocal(x); },
       [](long double t) { return 1.0L / t; }},
      {"sqr", [](const Interval& x) { return ia::sqr(x); }, [](long double t) { return t * t; }},
      {"sqrt", [](const Interval& x) { return ia::sqrt(x); },
       [](long double t) { return std::sqrt(t); }},
      {"exp", [](const Interval& x) { return ia::exp(x); },
       [](long double t) { return std::exp(t); }},
      {"sin", [](const Interval& x) { return ia::sin(x); },
       [](long double t) { return std::sin(t); }},
      {"cos", [](const Interval& x) { return ia::cos(x); },
       [](long double t) { return std::cos(t); }},
      {"abs", [](const Interval& x) { return ia::abs(x); },
       [](long double t) { return std::fabs(t); }},
      {"pow3", [](const Interval& x) { return ia::pow(x, 3); },
       [](long double t) { return t * t * t; }},
      {"pow4", [](const Interval& x) { return ia::pow(x, 4); },
       [](long double t) { return t * t * t * t; }},
      {"pow-2", [](const Interval& x) { return ia::pow(x, -2); },
       [](long double t) { return 1.0L / (t * t); }},
  };
}

}  // namespace

// ---- thesis §3.1: every scalar row is exact -------------------------------------------------

TEST(IntervalReference, Table31ScalarRowsAreExact) {
  EXPECT_TRUE(same(I(-2, 4) + I(1, 3), I(-1, 7)));
  EXPECT_TRUE(same(I(0, 7) - I(1, 2), I(-2, 6)));
  EXPECT_TRUE(same(I(-2, 1) * I(3, 4), I(-8, 4)));
  EXPECT_TRUE(same(I(6, 12) / I(2, 3), I(2, 6)));
  EXPECT_TRUE(same(I(-1, 2).intersect(I(0, 4)), I(0, 2)));
  EXPECT_TRUE(same(I(-2, 1).hull(I(2, 6)), I(-2, 6)));
  // Dependency effect (§1.2.7): [x] − [x] ≠ 0 and [x]/[x] ≠ 1.
  const Interval x = I(3, 8);
  EXPECT_TRUE(same(x - x, I(-5, 5)));
  const Interval y = I(1, 2);
  EXPECT_TRUE(same(y / y, I(0.5, 2)));
}

TEST(IntervalReference, ScalarMultiplicationEq127) {
  EXPECT_TRUE(same(2.0 * I(-1, 3), I(-2, 6)));
  EXPECT_TRUE(same(-2.0 * I(-1, 3), I(-6, 2)));
  EXPECT_TRUE(same(I(-1, 3) * 0.0, I(0, 0)));
}

TEST(IntervalReference, ReciprocalExtendedCasesEq128) {
  EXPECT_TRUE(ia::reciprocal(I(0, 0)).is_empty());
  EXPECT_TRUE(same(ia::reciprocal(I(2, 4)), I(0.25, 0.5)));
  EXPECT_TRUE(same(ia::reciprocal(I(-4, -2)), I(-0.5, -0.25)));
  EXPECT_TRUE(same(ia::reciprocal(I(0, 2)), I(0.5, kInf)));
  EXPECT_TRUE(same(ia::reciprocal(I(-4, 0)), I(-kInf, -0.25)));
  EXPECT_TRUE(ia::reciprocal(I(-1, 1)).is_entire());
  EXPECT_TRUE(same(ia::reciprocal(I(2, kInf)), I(0, 0.5)));
  EXPECT_TRUE(same(ia::reciprocal(I(-kInf, -4)), I(-0.25, 0)));
  EXPECT_TRUE(same(ia::reciprocal(I(0, kInf)), I(0, kInf)));
  EXPECT_TRUE(ia::reciprocal(Interval::entire()).is_entire());
}

TEST(IntervalReference, DivisionByIntervalsContainingZero) {
  EXPECT_TRUE((I(1, 2) / I(0, 0)).is_empty());
  EXPECT_TRUE(same(I(0, 0) / I(-1, 1), I(0, 0)));
  EXPECT_TRUE(same(I(1, 2) / I(0, 4), I(0.25, kInf)));
  EXPECT_TRUE(same(I(-2, -1) / I(0, 4), I(-kInf, -0.25)));
  EXPECT_TRUE(same(I(1, 2) / I(-4, 0), I(-kInf, -0.25)));
  EXPECT_TRUE(same(I(-2, -1) / I(-4, 0), I(0.25, kInf)));
  EXPECT_TRUE(same(I(0, 2) / I(0, 4), I(0, kInf)));  // a ≥ 0, b > 0: never negative
  EXPECT_TRUE((I(-1, 2) / I(0, 4)).is_entire());
  EXPECT_TRUE((I(1, 2) / I(-1, 1)).is_entire());
  EXPECT_TRUE(same(I(1, kInf) / I(1, kInf), I(0, kInf)));
}

TEST(IntervalReference, EmptyPropagatesAndIsNeutralForHull) {
  const Interval e = Interval::empty();
  EXPECT_TRUE(e.is_empty());
  EXPECT_TRUE((e + I(1, 2)).is_empty());
  EXPECT_TRUE((I(1, 2) * e).is_empty());
  EXPECT_TRUE(ia::sin(e).is_empty());
  EXPECT_TRUE(same(e.hull(I(1, 2)), I(1, 2)));
  EXPECT_TRUE(I(0, 1).intersect(I(2, 3)).is_empty());
  EXPECT_TRUE(e.subset(I(0, 0)));
  EXPECT_FALSE(e.contains(0.0));
  EXPECT_TRUE(std::isnan(e.mid()));
}

TEST(IntervalReference, MeasuresEq14To17) {
  const Interval x = I(2, 6);
  EXPECT_EQ(x.inf(), 2);
  EXPECT_EQ(x.sup(), 6);
  EXPECT_EQ(x.mid(), 4);
  EXPECT_EQ(x.rad(), 2);
  EXPECT_EQ(x.width(), 4);
  EXPECT_EQ(I(-7, 3).mag(), 7);
  EXPECT_EQ(I(-7, 3).mig(), 0);
  EXPECT_EQ(I(-7, -3).mig(), 3);
  // Overflow-safe midpoint: (lo + hi)/2 would be inf here.
  EXPECT_EQ(I(0.5 * DBL_MAX, DBL_MAX).mid(), 0.75 * DBL_MAX);
  EXPECT_EQ(I(-DBL_MAX, DBL_MAX).mid(), 0);
  EXPECT_EQ(Interval::entire().mid(), 0);
  EXPECT_EQ(I(1, kInf).mid(), DBL_MAX);
  EXPECT_EQ(Interval::entire().rad(), kInf);
  // mid ± rad always encloses, even where the halving rounds.
  const Interval z = I(0.1, 0.7);
  EXPECT_LE(z.mid() - z.rad(), z.lo());
  EXPECT_GE(z.mid() + z.rad(), z.hi());
}

TEST(IntervalReference, SetPredicates) {
  EXPECT_TRUE(I(1, 2).subset(I(0, 3)));
  EXPECT_FALSE(I(-1, 2).subset(I(0, 3)));
  EXPECT_TRUE(I(1, 2).contains(2.0));
  EXPECT_FALSE(I(1, 2).contains(2.0000001));
  EXPECT_TRUE(I(-kInf, 0).contains(-1e308));
}

// ---- thesis §3.2: inclusion functions -------------------------------------------------------

TEST(InclusionFunctions, XSquaredMinusXOnTwoFour) {
  const Interval x = I(2, 4);
  EXPECT_TRUE(same(ia::sqr(x) - x, I(0, 14)));         // natural form
  EXPECT_TRUE(same(x * (x - 1.0), I(2, 12)));          // factored form
}

TEST(InclusionFunctions, FourFormsOfXSquaredPlusTwoX) {
  const Interval x = I(-1, 1);
  EXPECT_TRUE(same(ia::sqr(x), I(0, 1)));              // sqr is not [x]·[x]
  EXPECT_TRUE(same(x * x, I(-1, 1)));
  EXPECT_TRUE(same(ia::sqr(x) + 2.0 * x, I(-2, 3)));   // f1
  EXPECT_TRUE(same(x * (x + 2.0), I(-3, 3)));          // f2
  EXPECT_TRUE(same(x * x + 2.0 * x, I(-3, 3)));        // f3
  EXPECT_TRUE(same(ia::sqr(x + 1.0) - 1.0, I(-1, 3))); // f4, minimal
}

TEST(InclusionFunctions, XSquaredPlusSinXAllFourForms) {
  const Interval x = I(2 * kPi / 3, 4 * kPi / 3);
  const double c = kPi;
  // natural
  EXPECT_TRUE(near(ia::sqr(x) + ia::sin(x), 3.52046, 18.41199, 1e-5));
  // centered: f(c) + [f']([x])([x] − c), [f'] = 2[x] + cos[x]
  const Interval fc = ia::sqr(Interval(c)) + ia::sin(Interval(c));
  const Interval dfx = 2.0 * x + ia::cos(x);
  EXPECT_TRUE(near(dfx, 3.18879, 7.87758, 1e-5));
  EXPECT_TRUE(near(fc + dfx * (x - c), 1.62022, 18.11899, 1e-5));
  // Taylor-2: f(c) + f'(c)([x] − c) + ½ sqr([x] − c)[f''], [f''] = 2 − sin[x]
  const Interval dfc = 2.0 * Interval(c) + ia::cos(Interval(c));
  const Interval d2f = 2.0 - ia::sin(x);
  EXPECT_TRUE(near(d2f, 1.13397, 2.86603, 1e-5));
  EXPECT_TRUE(near(fc + dfc * (x - c) + 0.5 * ia::sqr(x - c) * d2f, 4.33706, 16.97362, 1e-5));
  // minimal: f increasing on [x]
  const Interval xl(x.lo()), xh(x.hi());
  EXPECT_TRUE(near(Interval((ia::sqr(xl) + ia::sin(xl)).lo(), (ia::sqr(xh) + ia::sin(xh)).hi()),
                   5.25251, 16.67994, 1e-5));
}

// ---- elementary functions -------------------------------------------------------------------

TEST(ElementaryFunctions, KnownRanges) {
  EXPECT_TRUE(same(ia::sqrt(I(4, 9)), I(2, 3)));
  EXPECT_TRUE(same(ia::sqrt(I(-1, 4)), I(0, 2)));
  EXPECT_TRUE(ia::sqrt(I(-4, -1)).is_empty());
  EXPECT_TRUE(same(ia::sqrt(I(0, kInf)), I(0, kInf)));
  EXPECT_TRUE(same(ia::abs(I(-3, 2)), I(0, 3)));
  EXPECT_TRUE(same(ia::abs(I(-3, -2)), I(2, 3)));
  EXPECT_TRUE(same(ia::pow(I(-2, 3), 2), I(0, 9)));
  EXPECT_TRUE(same(ia::pow(I(-2, 3), 3), I(-8, 27)));
  EXPECT_TRUE(same(ia::pow(I(-3, -2), 3), I(-27, -8)));
  EXPECT_TRUE(same(ia::pow(I(2, 4), -1), I(0.25, 0.5)));
  EXPECT_TRUE(same(ia::pow(I(-2, 4), -2), I(1.0 / 16, kInf)));
  EXPECT_TRUE(same(ia::pow(I(-2, 4), 0), I(1, 1)));
  EXPECT_TRUE(ia::pow(I(0, 0), -1).is_empty());
  EXPECT_TRUE(same(ia::exp(I(0, 0)), I(1, 1)));
  EXPECT_TRUE(same(ia::exp(I(-kInf, 0)), I(0, 1)));
  EXPECT_TRUE(same(ia::exp(Interval::entire()), I(0, kInf)));
  // Interior extrema of sin/cos come from the periods, exactly ±1.
  EXPECT_EQ(ia::sin(I(0, 3)).hi(), 1.0);
  EXPECT_LE(ia::sin(I(0, 3)).lo(), 0.0);
  EXPECT_EQ(ia::cos(I(-1, 1)).hi(), 1.0);
  EXPECT_EQ(ia::cos(I(3, 3.5)).lo(), -1.0);
  EXPECT_EQ(ia::sin(I(4, 5)).lo(), -1.0);           // 3π/2 ≈ 4.712
  EXPECT_EQ(ia::sin(I(2 * kPi + 1, 2 * kPi + 2)).hi(), 1.0);  // next period
  EXPECT_TRUE(same(ia::sin(I(0, 7)), I(-1, 1)));    // width ≥ 2π
  EXPECT_TRUE(same(ia::cos(I(-kInf, 0)), I(-1, 1)));
  // Monotone pieces: no extremum inside, result is a one-ulp widening of the end values.
  const Interval s = ia::sin(I(-1, 1));
  EXPECT_LT(s.hi(), 1.0);
  EXPECT_LE(s.hi(), std::nextafter(std::nextafter(std::sin(1.0), 2.0), 2.0));
  EXPECT_GE(s.hi(), std::sin(1.0));
}

// ---- outward rounding: exact results stay exact, inexact ones enclose the real value ---------

TEST(OutwardRounding, PointOperationsEncloseTheExactRealResult) {
  // 0.1 + 0.2: the double sum rounds; the interval must contain the exact sum of the two
  // doubles (exactly representable in 80-bit long double, whose 64-bit significand holds it).
  static_assert(std::numeric_limits<long double>::digits >= 64, "needs x87 long double");
  const Interval s = Interval(0.1) + Interval(0.2);
  const long double exact = (long double)0.1 + (long double)0.2;
  EXPECT_LE((long double)s.lo(), exact);
  EXPECT_GE((long double)s.hi(), exact);
  EXPECT_LT(s.lo(), s.hi());  // inexact, so not degenerate
  EXPECT_EQ(std::nextafter(s.lo(), 1.0), s.hi());  // and only one ulp wide

  Gen g;
  for (int k = 0; k < 20000; ++k) {
    // Operands with close exponents so that their exact sum fits a long double.
    const double a = std::ldexp(g.uniform(1, 2), g.pick(8) - 4) * (g.pick(2) ? 1 : -1);
    const double b = std::ldexp(g.uniform(1, 2), g.pick(8) - 4) * (g.pick(2) ? 1 : -1);
    const Interval A(a), B(b);
    const long double sum = (long double)a + (long double)b;
    const Interval add = A + B;
    ASSERT_LE((long double)add.lo(), sum);
    ASSERT_GE((long double)add.hi(), sum);
    ASSERT_LE(add.hi(), std::nextafter(add.lo(), kInf)) << "wider than one ulp";
    const long double diff = (long double)a - (long double)b;
    const Interval sub = A - B;
    ASSERT_LE((long double)sub.lo(), diff);
    ASSERT_GE((long double)sub.hi(), diff);
    // Product: the sign of fma(a, b, −t) = a·b − t is exact.
    const Interval mul = A * B;
    ASSERT_GE(std::fma(a, b, -mul.lo()), 0.0);
    ASSERT_LE(std::fma(a, b, -mul.hi()), 0.0);
    ASSERT_EQ(mul.is_degenerate(), std::fma(a, b, -(a * b)) == 0);
    // Quotient: lo ≤ a/b ⇔ lo·b ≤ a for b > 0 (reversed for b < 0); fma gives exact signs.
    const Interval q = A / B;
    const double sb = b > 0 ? 1.0 : -1.0;
    ASSERT_LE(sb * std::fma(q.lo(), b, -a), 0.0);
    ASSERT_GE(sb * std::fma(q.hi(), b, -a), 0.0);
    ASSERT_LE(q.hi(), std::nextafter(q.lo(), kInf));
    // Square root: lo² ≤ |a| ≤ hi².
    const Interval r = ia::sqrt(Interval(std::fabs(a)));
    ASSERT_LE(std::fma(r.lo(), r.lo(), -std::fabs(a)), 0.0);
    ASSERT_GE(std::fma(r.hi(), r.hi(), -std::fabs(a)), 0.0);
  }
}

TEST(OutwardRounding, OverflowAndUnderflowStayEnclosing) {
  const Interval big = Interval(DBL_MAX) + Interval(DBL_MAX);
  EXPECT_EQ(big.lo(), DBL_MAX);
  EXPECT_EQ(big.hi(), kInf);
  const Interval tiny = Interval(1e-200) * Interval(1e-200);  // underflows to 0
  EXPECT_LT(tiny.lo(), 0.0);
  EXPECT_GT(tiny.hi(), 0.0);
  const Interval q = Interval(1.0) / Interval(3.0);
  EXPECT_LT(q.lo(), q.hi());
  EXPECT_LE(std::fma(q.lo(), 3.0, -1.0), 0.0);
  EXPECT_GE(std::fma(q.hi(), 3.0, -1.0), 0.0);
}

// ---- enclosure of sampled point evaluations and inclusion isotonicity (§7 item 1) ----------

TEST(IntervalProperties, SampledPointsOfBinaryOpsLieInTheResult) {
  Gen g;
  for (const auto& op : binary_ops()) {
    for (int k = 0; k < 3000; ++k) {
      const Interval x = g.interval(), y = g.interval();
      const Interval z = op.op(x, y);
      for (int s = 0; s < 10; ++s) {
        const double a = g.point(x), b = g.point(y);
        if (std::string(op.name) == "div" && b == 0) continue;
        const double v = op.f(a, b);  // the rounded value of a real in z is in z as well
        ASSERT_TRUE(z.contains(v)) << op.name << " " << x << " " << y << " a=" << a
                                   << " b=" << b << " value " << v << " not in " << z;
      }
    }
  }
  // The set operations: every point of both is in the hull, every common point in the meet.
  for (int k = 0; k < 3000; ++k) {
    const Interval x = g.interval(), y = g.interval();
    const Interval h = x.hull(y), m = x.intersect(y);
    EXPECT_TRUE(x.subset(h) && y.subset(h));
    EXPECT_TRUE(m.subset(x) && m.subset(y));
    const double a = g.point(x);
    EXPECT_EQ(m.contains(a), y.contains(a));
  }
}

TEST(IntervalProperties, SampledPointsOfFunctionsLieInTheResult) {
  Gen g;
  for (const auto& op : unary_ops()) {
    for (int k = 0; k < 3000; ++k) {
      const Interval x = g.interval();
      const Interval z = op.op(x);
      for (int s = 0; s < 10; ++s) {
        const double a = g.point(x);
        const std::string name = op.name;
        if ((name == "recip" || name == "pow-2") && a == 0) continue;
        if (name == "sqrt" && a < 0) continue;
        const long double v = op.f(a);
        if (std::isinf(v)) {
          ASSERT_TRUE(v > 0 ? z.hi() == kInf : z.lo() == -kInf) << name << " " << x;
          continue;
        }
        ASSERT_TRUE((long double)z.lo() <= v && v <= (long double)z.hi())
            << name << " of " << x << " at " << a << " = " << (double)v << " not in " << z;
      }
    }
  }
}

TEST(IntervalProperties, InclusionIsotonicity) {
  Gen g;
  for (int k = 0; k < 5000; ++k) {
    const Interval X = g.interval(), Y = g.interval();
    const Interval x = g.sub(X), y = g.sub(Y);
    ASSERT_TRUE(x.subset(X) && y.subset(Y));
    for (const auto& op : binary_ops())
      ASSERT_TRUE(op.op(x, y).subset(op.op(X, Y)))
          << op.name << ": " << x << " ⊆ " << X << ", " << y << " ⊆ " << Y;
    for (const auto& op : unary_ops())
      ASSERT_TRUE(op.op(x).subset(op.op(X))) << op.name << ": " << x << " ⊆ " << X;
    ASSERT_TRUE(x.hull(y).subset(X.hull(Y)));
    ASSERT_TRUE(x.intersect(y).subset(X.intersect(Y)));
  }
}

// ---- validation ----------------------------------------------------------------------------

TEST(IntervalValidation, BadEndsThrowNamedErrors) {
  try {
    Interval(2.0, 1.0, "d");
    FAIL() << "expected InvalidArgumentError";
  } catch (const setbound::InvalidArgumentError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("d:", 0), 0u) << e.what();
  }
  EXPECT_THROW(Interval(std::nan(""), 1.0), setbound::NotFiniteError);
  EXPECT_THROW(Interval(0.0, std::nan("")), setbound::NotFiniteError);
  EXPECT_THROW(Interval(kInf, kInf), setbound::InvalidArgumentError);
  EXPECT_THROW(Interval(-kInf, -kInf), setbound::InvalidArgumentError);
  EXPECT_THROW(Interval{kInf}, setbound::InvalidArgumentError);
  EXPECT_THROW(I(0, 1) + std::nan(""), setbound::NotFiniteError);
  EXPECT_TRUE(Interval(kInf, -kInf).is_empty());  // the empty encoding is accepted
}

// ---- C ABI ---------------------------------------------------------------------------------

TEST(IntervalCApi, BinaryAndUnaryAreVectorised) {
  const double alo[] = {-2, 0, -2, 6, -1, -2}, ahi[] = {4, 7, 1, 12, 2, 1};
  const double blo[] = {1, 1, 3, 2, 0, 2}, bhi[] = {3, 2, 4, 3, 4, 6};
  const int ops[] = {SB_IV_ADD, SB_IV_SUB, SB_IV_MUL, SB_IV_DIV, SB_IV_INTERSECT, SB_IV_HULL};
  const double want_lo[] = {-1, -2, -8, 2, 0, -2}, want_hi[] = {7, 6, 4, 6, 2, 6};
  for (int k = 0; k < 6; ++k) {
    double lo[6], hi[6];
    ASSERT_EQ(sb_interval_binary(ops[k], 6, alo, ahi, blo, bhi, lo, hi), SB_OK) << sb_last_error();
    EXPECT_EQ(lo[k], want_lo[k]) << "op " << ops[k];
    EXPECT_EQ(hi[k], want_hi[k]) << "op " << ops[k];
  }
  // Division by [0, 0] and a disjoint intersection give the empty encoding.
  double lo, hi;
  const double z = 0, one = 1, two = 2, three = 3;
  ASSERT_EQ(sb_interval_binary(SB_IV_DIV, 1, &one, &two, &z, &z, &lo, &hi), SB_OK);
  EXPECT_EQ(lo, kInf);
  EXPECT_EQ(hi, -kInf);
  ASSERT_EQ(sb_interval_binary(SB_IV_INTERSECT, 1, &z, &one, &two, &three, &lo, &hi), SB_OK);
  EXPECT_TRUE(lo > hi);
  // and the empty encoding is accepted back as input.
  ASSERT_EQ(sb_interval_binary(SB_IV_HULL, 1, &lo, &hi, &two, &three, &lo, &hi), SB_OK);
  EXPECT_EQ(lo, 2);
  EXPECT_EQ(hi, 3);

  const double xlo[] = {-1, 0, -1, 4, 0, -1, -1, -3};
  const double xhi[] = {3, 0, 1, 9, 0, 3, 1, 2};
  const int uops[] = {SB_IV_NEG, SB_IV_RECIP, SB_IV_SQR, SB_IV_SQRT,
                      SB_IV_EXP, SB_IV_SIN,   SB_IV_COS, SB_IV_ABS};
  std::vector<Interval> expect = {I(-3, 1),
                                  Interval::empty(),
                                  I(0, 1),
                                  I(2, 3),
                                  I(1, 1),
                                  ia::sin(I(-1, 3)),
                                  ia::cos(I(-1, 1)),
                                  I(0, 3)};
  for (int k = 0; k < 8; ++k) {
    double ol[8], oh[8];
    ASSERT_EQ(sb_interval_unary(uops[k], 8, xlo, xhi, ol, oh), SB_OK) << sb_last_error();
    EXPECT_TRUE(same(Interval::unchecked(ol[k], oh[k]), expect[std::size_t(k)])) << uops[k];
  }
  double pl[2], ph[2];
  const double plo[] = {-2, 2}, phi[] = {3, 4};
  ASSERT_EQ(sb_interval_pow(2, plo, phi, 3, pl, ph), SB_OK);
  EXPECT_EQ(pl[0], -8);
  EXPECT_EQ(ph[0], 27);
  EXPECT_EQ(pl[1], 8);
  EXPECT_EQ(ph[1], 64);
  ASSERT_EQ(sb_interval_pow(2, plo, phi, -1, pl, ph), SB_OK);
  EXPECT_EQ(pl[0], -kInf);
  EXPECT_EQ(ph[0], kInf);
  EXPECT_EQ(pl[1], 0.25);
  EXPECT_EQ(ph[1], 0.5);
  // n = 0 with null pointers is fine.
  EXPECT_EQ(sb_interval_unary(SB_IV_SIN, 0, nullptr, nullptr, nullptr, nullptr), SB_OK);
}

TEST(IntervalCApi, ErrorPathsNameTheArgument) {
  const double lo[] = {0, 1}, hi[] = {1, 2}, bad_hi[] = {1, 0.5};
  const double nan_lo[] = {0, std::nan("")};
  double ol[2], oh[2];
  auto starts = [](const char* prefix) {
    return std::string(sb_last_error()).rfind(prefix, 0) == 0;
  };
  EXPECT_EQ(sb_interval_binary(99, 2, lo, hi, lo, hi, ol, oh), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_interval_binary: op:")) << sb_last_error();
  EXPECT_EQ(sb_interval_unary(SB_IV_ADD, 2, lo, hi, ol, oh), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_interval_unary: op:")) << sb_last_error();
  EXPECT_EQ(sb_interval_binary(SB_IV_ADD, 2, lo, hi, lo, bad_hi, ol, oh),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_interval_binary: b entry 1:")) << sb_last_error();
  EXPECT_EQ(sb_interval_binary(SB_IV_MUL, 2, nan_lo, hi, lo, hi, ol, oh), SB_ERR_NOT_FINITE);
  EXPECT_TRUE(starts("sb_interval_binary: a entry 1:")) << sb_last_error();
  EXPECT_EQ(sb_interval_binary(SB_IV_ADD, 2, nullptr, hi, lo, hi, ol, oh),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_interval_binary: a")) << sb_last_error();
  EXPECT_EQ(sb_interval_binary(SB_IV_ADD, 2, lo, hi, lo, hi, nullptr, oh),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_interval_binary: lo:")) << sb_last_error();
  EXPECT_EQ(sb_interval_binary(SB_IV_ADD, -1, lo, hi, lo, hi, ol, oh), SB_ERR_DIMENSION);
  EXPECT_EQ(sb_interval_unary(SB_IV_SQRT, 2, lo, bad_hi, ol, oh), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_interval_unary: x entry 1:")) << sb_last_error();
  EXPECT_EQ(sb_interval_pow(2, nan_lo, hi, 2, ol, oh), SB_ERR_NOT_FINITE);
  EXPECT_TRUE(starts("sb_interval_pow: x entry 1:")) << sb_last_error();
  EXPECT_EQ(sb_interval_pow(2, lo, hi, 2, ol, nullptr), SB_ERR_INVALID_ARGUMENT);
  const double pinf = kInf;
  EXPECT_EQ(sb_interval_unary(SB_IV_EXP, 1, &pinf, &pinf, ol, oh), SB_ERR_INVALID_ARGUMENT);
}

TEST(OutwardRounding, PowersOfTinyNumbersStayNonNegativeAndEnclosing) {
  // x^4 of a tiny x underflows; the lower end must be 0 (not negative) and the upper end > 0.
  const Interval p = ia::pow(Interval(1e-200), 4);
  EXPECT_EQ(p.lo(), 0.0);
  EXPECT_GT(p.hi(), 0.0);
  EXPECT_EQ(ia::sqr(Interval(1e-200)).lo(), 0.0);
  EXPECT_GT(ia::sqr(Interval(1e-200)).hi(), 0.0);
  const Interval q = ia::pow(Interval(-1e-200), 3);  // odd power of a negative tiny number
  EXPECT_LT(q.lo(), 0.0);
  EXPECT_GE(q.hi(), -0.0);
  // Exact powers stay exact.
  EXPECT_TRUE(same(ia::pow(Interval(3.0), 5), Interval(243.0)));
  EXPECT_TRUE(same(ia::pow(I(-0.5, 2), 4), I(0, 16)));
}
