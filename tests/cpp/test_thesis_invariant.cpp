// Thesis Chapter 1 (spec thesis.md §3): inclusion functions, polytopes, the polyhedral RPI set
// between two ellipsoids, the mRPI outer shrinking (Algorithm 1) and their C ABI.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "setbound/sets/inclusion.hpp"
#include "setbound/sets/polytope.hpp"
extern "C" {
#include "setbound/setbound.h"
}
#include "setbound/thesis/invariant.hpp"
#include "test_helpers.hpp"

using namespace setbound;
using setbound::testing::expect_error_naming;

namespace {

const double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------- helpers

void expect_interval(const Interval& x, double lo, double hi, double tol) {
  EXPECT_NEAR(x.lo(), lo, tol) << x;
  EXPECT_NEAR(x.hi(), hi, tol) << x;
}

/// Random SPD matrix with condition number ≤ ~cond.
Eigen::MatrixXd random_spd(int n, std::mt19937& rng, double cond = 20.0) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) M(i, j) = u(rng);
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(M);
  const Eigen::MatrixXd Q = qr.householderQ();
  Eigen::VectorXd ev(n);
  std::uniform_real_distribution<double> ue(0, std::log(cond));
  for (int i = 0; i < n; ++i) ev(i) = std::exp(ue(rng));
  return Q * ev.asDiagonal() * Q.transpose();
}

/// Random Schur-stable A with spectral radius ≈ rho.
Eigen::MatrixXd random_schur(int n, std::mt19937& rng, double rho = 0.8) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = u(rng);
  const double r = Eigen::EigenSolver<Eigen::MatrixXd>(A).eigenvalues().cwiseAbs().maxCoeff();
  return A * (rho / r);
}

/// Random point of conv(V): a random convex combination of a few vertices.
Eigen::VectorXd random_point(const Eigen::MatrixXd& V, std::mt19937& rng) {
  std::uniform_int_distribution<int> pick(0, int(V.cols()) - 1);
  std::exponential_distribution<double> ex(1.0);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(V.rows());
  double s = 0;
  for (int t = 0; t < 4; ++t) {
    const double w = ex(rng);
    x += w * V.col(pick(rng));
    s += w;
  }
  return x / s;
}

/// H∞ norm of (A, E, I, 0) by frequency gridding (independent of the LMI), refined around the
/// best grid point.
double hinf_norm_grid(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E) {
  const int n = int(A.rows());
  auto sigma = [&](double w) {
    const std::complex<double> z = std::polar(1.0, w);
    Eigen::MatrixXcd M = z * Eigen::MatrixXcd::Identity(n, n) - A.cast<std::complex<double>>();
    Eigen::MatrixXcd G = M.partialPivLu().solve(E.cast<std::complex<double>>());
    return Eigen::JacobiSVD<Eigen::MatrixXcd>(G).singularValues()(0);
  };
  double best = 0, wbest = 0;
  const int N = 20000;
  for (int k = 0; k <= N; ++k) {
    const double w = kPi * k / N;
    const double s = sigma(w);
    if (s > best) best = s, wbest = w;
  }
  double lo = std::max(0.0, wbest - kPi / N), hi = std::min(kPi, wbest + kPi / N);
  for (int it = 0; it < 100; ++it) {  // golden-section on the bracket
    const double a = lo + 0.382 * (hi - lo), b = lo + 0.618 * (hi - lo);
    if (sigma(a) > sigma(b)) hi = b; else lo = a;
  }
  return std::max(best, sigma(0.5 * (lo + hi)));
}

/// A valid (not optimal) BRL pair for tests: P from A'PA − P = −2I, then the smallest γ² with
/// LMI (1.48) for that P (Schur complement in closed form).
std::pair<Eigen::MatrixXd, double> brl_pair_closed_form(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E) {
  const int n = int(A.rows());
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(n, n), Ak = Eigen::MatrixXd::Identity(n, n);
  for (int i = 0; i < 2000; ++i) {
    P += 2.0 * Ak.transpose() * Ak;
    Ak = Ak * A;
  }
  const Eigen::MatrixXd S = P - Eigen::MatrixXd::Identity(n, n) - A.transpose() * P * A;  // ≻ 0
  const Eigen::MatrixXd G = E.transpose() * P * E + E.transpose() * P * A * S.llt().solve(A.transpose() * P * E);
  const double g = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(G).eigenvalues().maxCoeff() * (1 + 1e-9);
  return {P, g};
}

Eigen::MatrixXd ex15_A() { return (Eigen::MatrixXd(2, 2) << 0.2, 0.2, -0.2, 0.5).finished(); }
Eigen::MatrixXd ex15_E() { return (Eigen::MatrixXd(2, 1) << 0, 1).finished(); }

/// All corners of the box [−w̄, w̄] (columns).
Eigen::MatrixXd corners(const Eigen::VectorXd& wbar) {
  const int m = int(wbar.size());
  Eigen::MatrixXd D(m, 1 << m);
  for (int k = 0; k < (1 << m); ++k)
    for (int i = 0; i < m; ++i) D(i, k) = ((k >> i) & 1) ? wbar(i) : -wbar(i);
  return D;
}

// ---------------------------------------------------------------- §3.1 and §3.2 tables

TEST(ThesisInclusion, Section31TableExact) {
  const Interval a(-2, 4), b(1, 3);
  EXPECT_EQ(a + b, Interval(-1, 7));
  EXPECT_EQ(Interval(0, 7) - Interval(1, 2), Interval(-2, 6));
  EXPECT_EQ(Interval(-2, 1) * Interval(3, 4), Interval(-8, 4));
  EXPECT_EQ(Interval(6, 12) / Interval(2, 3), Interval(2, 6));
  EXPECT_EQ(Interval(-1, 2).intersect(Interval(0, 4)), Interval(0, 2));
  EXPECT_EQ(Interval(-2, 1).hull(Interval(2, 6)), Interval(-2, 6));
  EXPECT_EQ(Interval(3, 8) - Interval(3, 8), Interval(-5, 5));
  EXPECT_EQ(Interval(1, 2) / Interval(1, 2), Interval(0.5, 2));
  const Box s = Box(Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 3)) + Box(Eigen::Vector2d(-2, 5), Eigen::Vector2d(4, 6));
  EXPECT_EQ(s.lo(), Eigen::Vector2d(-2, 6));
  EXPECT_EQ(s.hi(), Eigen::Vector2d(5, 9));
  const IntervalMatrix M((Eigen::MatrixXd(2, 2) << 0, 2, 1, -1).finished(),
                         (Eigen::MatrixXd(2, 2) << 1, 3, 2, 4).finished());
  const Box y = M * Box(Eigen::Vector2d(1, 0), Eigen::Vector2d(2, 3));
  EXPECT_EQ(y.lo(), Eigen::Vector2d(0, -2));
  EXPECT_EQ(y.hi(), Eigen::Vector2d(11, 16));
}

TEST(ThesisInclusion, Section32PolynomialForms) {
  auto nat = [](const Interval& x) { return ia::sqr(x) - x; };
  EXPECT_EQ(natural_inclusion(nat, Interval(2, 4)), Interval(0, 14));
  EXPECT_EQ(natural_inclusion([](const Interval& x) { return x * (x - Interval(1.0)); }, Interval(2, 4)),
            Interval(2, 12));
  const Interval x(-1, 1);
  EXPECT_EQ(natural_inclusion([](const Interval& t) { return ia::sqr(t) + Interval(2.0) * t; }, x), Interval(-2, 3));
  EXPECT_EQ(natural_inclusion([](const Interval& t) { return t * (t + Interval(2.0)); }, x), Interval(-3, 3));
  EXPECT_EQ(natural_inclusion([](const Interval& t) { return t * t + Interval(2.0) * t; }, x), Interval(-3, 3));
  EXPECT_EQ(natural_inclusion([](const Interval& t) { return ia::sqr(t + Interval(1.0)) - Interval(1.0); }, x),
            Interval(-1, 3));
  EXPECT_EQ(ia::sqr(x), Interval(0, 1));
}

TEST(ThesisInclusion, Section32SquarePlusSine) {
  const Interval pi3(2 * kPi / 3), pi43(4 * kPi / 3);
  const Interval x(2 * kPi / 3, 4 * kPi / 3);
  auto f = [](const Interval& t) { return ia::sqr(t) + ia::sin(t); };
  auto df = [](const Interval& t) { return Interval(2.0) * t + ia::cos(t); };
  auto d2f = [](const Interval& t) { return Interval(2.0) - ia::sin(t); };
  const double tol = 1e-5;  // printed to 5 decimals (rounded or truncated: 3.520465 is printed 3.52046)
  expect_interval(natural_inclusion(f, x), 3.52046, 18.41199, tol);
  expect_interval(df(x), 3.18879, 7.87758, tol);
  expect_interval(centered_inclusion(f, df, x), 1.62022, 18.11899, tol);
  expect_interval(d2f(x), 1.13397, 2.86603, tol);
  expect_interval(taylor2_inclusion(f, df, d2f, x), 4.33706, 16.97362, tol);
  // minimal: f increasing on [x]
  const Interval fmin = f(Interval(x.lo())).hull(f(Interval(x.hi())));
  expect_interval(fmin, 5.25251, 16.67994, tol);
  // every form contains the minimal one
  for (const Interval& r : {natural_inclusion(f, x), centered_inclusion(f, df, x), taylor2_inclusion(f, df, d2f, x)})
    EXPECT_TRUE(Interval(std::nextafter(fmin.lo(), 1e9), std::nextafter(fmin.hi(), -1e9)).subset(r)) << r;
}

TEST(ThesisInclusion, ElementaryFunctionsInteriorExtrema) {
  EXPECT_EQ(ia::sin(Interval(1, 2)).hi(), 1.0);          // π/2 inside
  EXPECT_EQ(ia::sin(Interval(4, 5)).lo(), -1.0);         // 3π/2 inside
  EXPECT_EQ(ia::cos(Interval(3, 3.5)).lo(), -1.0);       // π inside
  EXPECT_EQ(ia::cos(Interval(-0.5, 0.25)).hi(), 1.0);    // 0 inside
  EXPECT_LT(ia::sin(Interval(0.1, 0.2)).hi(), 0.2);      // monotone piece: no spurious extremum
  EXPECT_EQ(ia::sqr(Interval(-1, 2)), Interval(0, 4));
  EXPECT_EQ(ia::sqrt(Interval(4, 9)), Interval(2, 3));
  EXPECT_TRUE(ia::exp(Interval(0, 1)).contains(std::exp(1.0)));
}

// ------------------------------------------- randomized inclusion with random expression trees

/// f, f′, f″ carried together (forward mode, second order), over T = double or Interval.
template <class T>
struct D2 {
  T v, d, dd;
};
double lit(double c, double) { return c; }
Interval lit(double c, const Interval&) { return Interval(c); }
double fsqr(double x) { return x * x; }
Interval fsqr(const Interval& x) { return ia::sqr(x); }
double fsin(double x) { return std::sin(x); }
Interval fsin(const Interval& x) { return ia::sin(x); }
double fcos(double x) { return std::cos(x); }
Interval fcos(const Interval& x) { return ia::cos(x); }
double fexp(double x) { return std::exp(x); }
Interval fexp(const Interval& x) { return ia::exp(x); }
double fsqrt(double x) { return std::sqrt(x); }
Interval fsqrt(const Interval& x) { return ia::sqrt(x); }

template <class T> D2<T> operator+(const D2<T>& a, const D2<T>& b) { return {a.v + b.v, a.d + b.d, a.dd + b.dd}; }
template <class T> D2<T> operator-(const D2<T>& a, const D2<T>& b) { return {a.v - b.v, a.d - b.d, a.dd - b.dd}; }
template <class T> D2<T> operator*(const D2<T>& a, const D2<T>& b) {
  return {a.v * b.v, a.d * b.v + a.v * b.d, a.dd * b.v + lit(2.0, a.v) * a.d * b.d + a.v * b.dd};
}
template <class T> D2<T> chain(const D2<T>& a, const T& g, const T& g1, const T& g2) {
  return {g, g1 * a.d, g2 * fsqr(a.d) + g1 * a.dd};
}
template <class T> D2<T> dsqr(const D2<T>& a) { return chain(a, fsqr(a.v), lit(2.0, a.v) * a.v, lit(2.0, a.v)); }
template <class T> D2<T> dsin(const D2<T>& a) { return chain(a, fsin(a.v), fcos(a.v), lit(0.0, a.v) - fsin(a.v)); }
template <class T> D2<T> dcos(const D2<T>& a) { return chain(a, fcos(a.v), lit(0.0, a.v) - fsin(a.v), lit(0.0, a.v) - fcos(a.v)); }
template <class T> D2<T> dexp(const D2<T>& a) { const T e = fexp(a.v); return chain(a, e, e, e); }
/// sqrt(a² + 1) (domain-safe square root)
template <class T> D2<T> dsqrt1(const D2<T>& a) {
  const D2<T> s = dsqr(a) + D2<T>{lit(1.0, a.v), lit(0.0, a.v), lit(0.0, a.v)};
  const T r = fsqrt(s.v);
  return chain(s, r, lit(0.5, a.v) / r, lit(-0.25, a.v) / (r * s.v));
}
/// a / (b² + 1) (domain-safe division)
template <class T> D2<T> ddiv1(const D2<T>& a, const D2<T>& b) {
  const D2<T> q = dsqr(b) + D2<T>{lit(1.0, a.v), lit(0.0, a.v), lit(0.0, a.v)};
  const T r = lit(1.0, a.v) / q.v;  // 1/q: derivatives −q′/q², 2q′²/q³ − q″/q²
  const D2<T> inv{r, lit(0.0, a.v) - q.d * fsqr(r), lit(2.0, a.v) * fsqr(q.d) * fsqr(r) * r - q.dd * fsqr(r)};
  return a * inv;
}

struct Node {
  int op;  // 0 var, 1 const, 2 +, 3 −, 4 ×, 5 ÷, 6 sqr, 7 sin, 8 cos, 9 exp, 10 sqrt
  double c = 0;
  std::unique_ptr<Node> a, b;
};

std::unique_ptr<Node> random_tree(std::mt19937& rng, int depth) {
  auto n = std::make_unique<Node>();
  std::uniform_int_distribution<int> leaf(0, 1), op(2, 10);
  std::uniform_real_distribution<double> c(-2, 2);
  if (depth == 0) {
    n->op = leaf(rng);
    n->c = c(rng);
    return n;
  }
  n->op = op(rng);
  n->a = random_tree(rng, depth - 1);
  if (n->op <= 5) n->b = random_tree(rng, depth - 1);
  if (n->op == 9) n->a = random_tree(rng, 0);  // keep exp of a small argument
  return n;
}

template <class T>
D2<T> eval(const Node& n, const D2<T>& x) {
  const T z = lit(0.0, x.v);
  switch (n.op) {
    case 0: return x;
    case 1: return {lit(n.c, x.v), z, z};
    case 2: return eval(*n.a, x) + eval(*n.b, x);
    case 3: return eval(*n.a, x) - eval(*n.b, x);
    case 4: return eval(*n.a, x) * eval(*n.b, x);
    case 5: return ddiv1(eval(*n.a, x), eval(*n.b, x));
    case 6: return dsqr(eval(*n.a, x));
    case 7: return dsin(eval(*n.a, x));
    case 8: return dcos(eval(*n.a, x));
    case 9: return dexp(eval(*n.a, x));
    default: return dsqrt1(eval(*n.a, x));
  }
}

TEST(ThesisInclusion, RandomTreesScalarFormsEnclose) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uc(-3, 3), uw(0.0, 1.5), ut(0, 1);
  int checked = 0;
  for (int t = 0; t < 300; ++t) {
    const auto tree = random_tree(rng, 1 + t % 3);
    const double c = uc(rng), w = uw(rng);
    const Interval x(c - w, c + w);
    auto f = [&](const Interval& s) { return eval<Interval>(*tree, {s, Interval(1.0), Interval(0.0)}).v; };
    auto df = [&](const Interval& s) { return eval<Interval>(*tree, {s, Interval(1.0), Interval(0.0)}).d; };
    auto d2f = [&](const Interval& s) { return eval<Interval>(*tree, {s, Interval(1.0), Interval(0.0)}).dd; };
    const Interval nat = natural_inclusion(f, x), cen = centered_inclusion(f, df, x),
                   tay = taylor2_inclusion(f, df, d2f, x);
    for (int s = 0; s <= 40; ++s) {
      const double p = s == 0 ? x.lo() : s == 40 ? x.hi() : x.lo() + ut(rng) * (x.hi() - x.lo());
      const double v = eval<double>(*tree, {p, 1.0, 0.0}).v;
      if (!std::isfinite(v)) continue;
      ASSERT_TRUE(nat.contains(v)) << "natural " << nat << " misses f(" << p << ") = " << v;
      ASSERT_TRUE(cen.contains(v)) << "centered " << cen << " misses f(" << p << ") = " << v;
      ASSERT_TRUE(tay.contains(v)) << "taylor2 " << tay << " misses f(" << p << ") = " << v;
      ++checked;
    }
    // a derivative check of the test's own forward mode (so the forms get correct inputs)
    const double p0 = c, h = 1e-5;
    const auto e0 = eval<double>(*tree, {p0, 1.0, 0.0});
    const double fd = (eval<double>(*tree, {p0 + h, 1.0, 0.0}).v - eval<double>(*tree, {p0 - h, 1.0, 0.0}).v) / (2 * h);
    ASSERT_NEAR(e0.d, fd, 1e-4 * std::max(1.0, std::abs(fd)));
  }
  EXPECT_GT(checked, 10000);
}

// vector function f: ℝ² → ℝ³ with hand-written Jacobian and Hessians
Box vf(const Box& x) {
  const Interval a = x[0], b = x[1];
  return Box::from_intervals({a * b + ia::sin(a), ia::exp(Interval(0.5) * b) - ia::sqr(a),
                              ia::sqrt(ia::sqr(a) + Interval(1.0)) * ia::cos(b)});
}
Eigen::Vector3d vf_point(double a, double b) {
  return {a * b + std::sin(a), std::exp(0.5 * b) - a * a, std::sqrt(a * a + 1) * std::cos(b)};
}
IntervalMatrix imat(const std::vector<std::vector<Interval>>& rows) {
  const Eigen::Index r = Eigen::Index(rows.size()), c = Eigen::Index(rows[0].size());
  Eigen::MatrixXd lo(r, c), hi(r, c);
  for (Eigen::Index i = 0; i < r; ++i)
    for (Eigen::Index j = 0; j < c; ++j) lo(i, j) = rows[i][j].lo(), hi(i, j) = rows[i][j].hi();
  return IntervalMatrix(lo, hi);
}
IntervalMatrix vjac(const Box& x) {
  const Interval a = x[0], b = x[1];
  const Interval s = ia::sqrt(ia::sqr(a) + Interval(1.0));
  return imat({{b + ia::cos(a), a},
               {Interval(-2.0) * a, Interval(0.5) * ia::exp(Interval(0.5) * b)},
               {a / s * ia::cos(b), Interval(0.0) - s * ia::sin(b)}});
}
std::vector<IntervalMatrix> vhess(const Box& x) {
  const Interval a = x[0], b = x[1];
  const Interval s = ia::sqrt(ia::sqr(a) + Interval(1.0));
  const Interval z(0.0);
  return {imat({{z - ia::sin(a), Interval(1.0)}, {Interval(1.0), z}}),
          imat({{Interval(-2.0), z}, {z, Interval(0.25) * ia::exp(Interval(0.5) * b)}}),
          imat({{ia::cos(b) / (s * ia::sqr(s)), z - a / s * ia::sin(b)}, {z - a / s * ia::sin(b), z - s * ia::cos(b)}})};
}

TEST(ThesisInclusion, RandomBoxesVectorFormsEnclose) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uc(-2, 2), uw(0.0, 0.8), ut(0, 1);
  for (int t = 0; t < 200; ++t) {
    const Eigen::Vector2d c(uc(rng), uc(rng)), r(uw(rng), uw(rng));
    const Box x = Box::from_center_radius(c, r);
    const Box nat = natural_inclusion(vf, x), cen = centered_inclusion(vf, vjac, x),
              tay = taylor2_inclusion(vf, vjac, vhess, x);
    for (int s = 0; s < 60; ++s) {
      const double a = x.lo()(0) + ut(rng) * (x.hi()(0) - x.lo()(0));
      const double b = x.lo()(1) + ut(rng) * (x.hi()(1) - x.lo()(1));
      const Eigen::VectorXd v = vf_point(a, b);
      ASSERT_TRUE(nat.contains(v)) << nat << " " << v.transpose();
      ASSERT_TRUE(cen.contains(v)) << cen << " " << v.transpose();
      ASSERT_TRUE(tay.contains(v)) << tay << " " << v.transpose();
    }
  }
  // on a small box the centered and Taylor forms are tighter than the natural one
  const Box small(Eigen::Vector2d(0.4, -0.3), Eigen::Vector2d(0.42, -0.28));
  const double wn = natural_inclusion(vf, small).width().sum();
  EXPECT_LT(centered_inclusion(vf, vjac, small).width().sum(), wn);
  EXPECT_LT(taylor2_inclusion(vf, vjac, vhess, small).width().sum(), wn);
}

TEST(ThesisInclusion, BadInput) {
  auto f = [](const Interval& t) { return t; };
  expect_error_naming<InvalidArgumentError>([&] { centered_inclusion(f, f, Interval(0, rounding::kInf)); }, "x");
  expect_error_naming<InvalidArgumentError>([&] { taylor2_inclusion(f, f, f, Interval::empty()); }, "x");
  expect_error_naming<InvalidArgumentError>([&] { centered_inclusion(vf, vjac, Box::empty(2)); }, "x");
  auto badjac = [](const Box&) { return IntervalMatrix::point(Eigen::MatrixXd::Zero(2, 2)); };
  expect_error_naming<DimensionError>(
      [&] { centered_inclusion(vf, badjac, Box(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1))); }, "jacobian rows");
}

// ---------------------------------------------------------------- ellipsoid box (1.40)

TEST(ThesisInvariant, EllipsoidBoundingBoxAttained) {
  const Eigen::MatrixXd P = (Eigen::MatrixXd(2, 2) << 1, 1, 1, 4).finished();  // Ex 1.3/1.4
  std::mt19937 rng(3);
  for (int t = 0; t < 20; ++t) {
    const Eigen::MatrixXd Pt = t == 0 ? P : random_spd(2 + t % 3, rng, 50);
    const int n = int(Pt.rows());
    const Eigen::VectorXd c = t == 0 ? Eigen::VectorXd(Eigen::VectorXd::Zero(2)) : Eigen::VectorXd(Eigen::VectorXd::Random(n));
    const double rho = t == 0 ? 1.0 : 0.5 + t;
    const Box b = thesis::ellipsoid_bounding_box(Pt, c, rho);
    const Eigen::MatrixXd Pinv = Pt.inverse();
    for (int i = 0; i < n; ++i) {
      const double h = std::sqrt(rho * Pinv(i, i));
      EXPECT_NEAR(b.hi()(i), c(i) + h, 1e-12 * (1 + h));
      EXPECT_NEAR(b.lo()(i), c(i) - h, 1e-12 * (1 + h));
      // the bound is attained at x* = c ± √ρ P⁻¹e_i / √(P⁻¹)_ii, a boundary point
      const Eigen::VectorXd xs = c + std::sqrt(rho) * Pinv.col(i) / std::sqrt(Pinv(i, i));
      EXPECT_NEAR((xs - c).dot(Pt * (xs - c)), rho, 1e-10 * rho);
      EXPECT_NEAR(xs(i), c(i) + h, 1e-10 * (1 + h));
      EXPECT_LE(xs(i), b.hi()(i));
    }
    // random boundary points stay inside the box
    for (int s = 0; s < 50; ++s) {
      Eigen::VectorXd d = Eigen::VectorXd::Random(n);
      d *= std::sqrt(rho / d.dot(Pt * d));
      EXPECT_TRUE(b.contains(c + d));
    }
  }
  if (true) {  // Ex 1.3: half-widths sqrt(4/3), sqrt(1/3) (diag of P⁻¹ = [[4,−1],[−1,1]]/3)
    const Box b = thesis::ellipsoid_bounding_box(P, Eigen::Vector2d::Zero(), 1.0);
    EXPECT_NEAR(b.hi()(0), std::sqrt(4.0 / 3.0), 1e-12);
    EXPECT_NEAR(b.hi()(1), std::sqrt(1.0 / 3.0), 1e-12);
  }
  expect_error_naming<NotPositiveDefiniteError>(
      [] { thesis::ellipsoid_bounding_box((Eigen::MatrixXd(2, 2) << 1, 2, 2, 1).finished(), Eigen::Vector2d::Zero(), 1); }, "P");
  expect_error_naming<InvalidArgumentError>(
      [&] { thesis::ellipsoid_bounding_box(P, Eigen::Vector2d::Zero(), 0.0); }, "rho");
}

// ---------------------------------------------------------------- polytopes

TEST(Polytope, RepresentationsAgree) {
  std::mt19937 rng(7);
  for (int n = 1; n <= 4; ++n) {
    const Eigen::MatrixXd pts = Eigen::MatrixXd::Random(n, 12 + 6 * n);
    const Polytope P = Polytope::from_vertices(pts);
    // every input point is inside; every vertex is an input point and lies on ≥ n facets
    for (Eigen::Index j = 0; j < pts.cols(); ++j) EXPECT_TRUE(P.contains(pts.col(j), 0.0));
    for (Eigen::Index j = 0; j < P.num_vertices(); ++j) {
      const Eigen::VectorXd s = P.b() - P.H() * P.vertices().col(j);
      EXPECT_GE((s.array() < 1e-9).count(), n);
    }
    EXPECT_NEAR((P.H().rowwise().norm().array() - 1.0).abs().maxCoeff(), 0.0, 1e-12);
    // H-rep → V-rep round trip
    const Polytope Q = Polytope::from_halfspaces(P.H(), P.b(), pts.rowwise().mean());
    EXPECT_EQ(Q.num_vertices(), P.num_vertices());
    EXPECT_TRUE(P.contains(Q, 1e-9));
    EXPECT_TRUE(Q.contains(P, 1e-9));
    // support function of a Minkowski sum is the sum of the support functions
    const Polytope R = Polytope::from_vertices(Eigen::MatrixXd::Random(n, 2 * n + 4));
    const Polytope S = P.minkowski_sum(R);
    const Box bx(-Eigen::VectorXd::Ones(n) * 0.3, Eigen::VectorXd::Ones(n) * 0.5);
    const Polytope T = P.minkowski_sum(bx);
    Eigen::MatrixXd G = Eigen::MatrixXd::Random(n, 3);
    const Zonotope Z(Eigen::VectorXd::Random(n), G);
    const Polytope U = P.minkowski_sum(Z);
    for (int t = 0; t < 30; ++t) {
      const Eigen::VectorXd d = Eigen::VectorXd::Random(n);
      EXPECT_NEAR(S.support(d), P.support(d) + R.support(d), 1e-12);
      EXPECT_NEAR(T.support(d), P.support(d) + (d.array().max(0) * 0.5 - d.array().min(0) * 0.3).sum(), 1e-12);
      EXPECT_NEAR(U.support(d), P.support(d) + d.dot(Z.center()) + (G.transpose() * d).cwiseAbs().sum(), 1e-12);
    }
    // linear map, scaling, box, max vertex norm
    const Eigen::MatrixXd M = Eigen::MatrixXd::Random(n, n) + 2 * Eigen::MatrixXd::Identity(n, n);
    const Polytope L = P.linear_map(M);
    for (int t = 0; t < 20; ++t) {
      const Eigen::VectorXd d = Eigen::VectorXd::Random(n);
      EXPECT_NEAR(L.support(d), P.support(M.transpose() * d), 1e-12);
      EXPECT_NEAR(P.scaled(2.5).support(d), 2.5 * P.support(d), 1e-12);
    }
    const Box bb = P.bounding_box();
    EXPECT_EIGEN_NEAR(bb.lo(), pts.rowwise().minCoeff(), 0.0);
    EXPECT_EIGEN_NEAR(bb.hi(), pts.rowwise().maxCoeff(), 0.0);
    EXPECT_NEAR(P.max_vertex_norm(), pts.colwise().norm().maxCoeff(), 1e-15);
    const Eigen::VectorXd far = 2.0 * Eigen::VectorXd::Ones(n);
    EXPECT_FALSE(P.contains(far));
  }
}

TEST(Polytope, BadInput) {
  expect_error_naming<InvalidArgumentError>(
      [] { Polytope::from_vertices((Eigen::MatrixXd(2, 3) << 0, 1, 2, 0, 1, 2).finished()); }, "points");
  Eigen::MatrixXd nanpts = Eigen::MatrixXd::Random(2, 4);
  nanpts(1, 2) = NAN;
  expect_error_naming<NotFiniteError>([&] { Polytope::from_vertices(nanpts); }, "points");
  // unbounded H-rep
  expect_error_naming<InvalidArgumentError>(
      [] {
        Polytope::from_halfspaces((Eigen::MatrixXd(3, 2) << 1, 0, 0, 1, -1, 0).finished(), Eigen::Vector3d(1, 1, 1),
                                  Eigen::Vector2d::Zero());
      },
      "halfspaces");
  const Polytope sq = Polytope::from_box(Box(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1)));
  expect_error_naming<InvalidArgumentError>([&] { sq.minkowski_sum(Box::empty(2)); }, "box");
  expect_error_naming<DimensionError>([&] { sq.contains(Eigen::Vector3d(0, 0, 0)); }, "x");
  expect_error_naming<InvalidArgumentError>([&] { sq.scaled(-1.0); }, "a");
  expect_error_naming<InvalidArgumentError>([&] { sq.linear_map(Eigen::MatrixXd::Zero(2, 2)); }, "M (image not full-dimensional: is the matrix singular?)");
}

// ---------------------------------------------------------------- §3.5 Φ_v

void check_between(const Polytope& Phi, const Eigen::MatrixXd& P, double c_in, double c_out) {
  const Eigen::MatrixXd Pinv = P.inverse();
  for (Eigen::Index j = 0; j < Phi.num_vertices(); ++j) {
    const Eigen::VectorXd v = Phi.vertices().col(j);
    ASSERT_LE(v.dot(P * v), c_out) << "vertex " << j << " outside the outer ellipsoid";
  }
  for (Eigen::Index i = 0; i < Phi.num_facets(); ++i) {
    const Eigen::VectorXd h = Phi.H().row(i).transpose();
    ASSERT_LE(std::sqrt(c_in * h.dot(Pinv * h)), Phi.b()(i)) << "facet " << i << " cuts the inner ellipsoid";
  }
}

TEST(ThesisInvariant, PolyhedralRpiBetweenEllipsoidsRandom) {
  std::mt19937 rng(21);
  for (int n = 1; n <= 5; ++n)
    for (double ratio : {1.5, 1.15}) {
      if (n == 5 && ratio < 1.2) continue;
      const Eigen::MatrixXd P = random_spd(n, rng, 30);
      const double c_in = 0.7, c_out = c_in * ratio;
      const Polytope Phi = thesis::polyhedral_rpi_between_ellipsoids(P, c_in, c_out);
      SCOPED_TRACE("n = " + std::to_string(n) + ", ratio " + std::to_string(ratio));
      check_between(Phi, P, c_in, c_out);
      // sampled boundary points of the inner ellipsoid are inside; of the outer one mostly outside
      for (int s = 0; s < 200; ++s) {
        Eigen::VectorXd d = Eigen::VectorXd::Random(n);
        const double q = d.dot(P * d);
        ASSERT_TRUE(Phi.contains(d * std::sqrt(c_in / q), 0.0));
        ASSERT_FALSE(Phi.contains(d * std::sqrt(c_out / q) * 1.0000001, 0.0));
      }
      // symmetric about the origin
      for (Eigen::Index j = 0; j < Phi.num_vertices(); ++j)
        ASSERT_TRUE(Phi.contains(-Phi.vertices().col(j), 1e-12));
    }
}

TEST(ThesisInvariant, PolyhedralRpiIsRpiForBrl) {
  // Ex 1.5 with the BRL P (and a random 3-D and 4-D system): A v + E d ∈ Φ_v for every vertex v
  // and every disturbance corner d.
  std::mt19937 rng(8);
  struct Case { Eigen::MatrixXd A, E; Eigen::VectorXd wbar; double mu; };
  std::vector<Case> cases = {{ex15_A(), ex15_E(), Eigen::VectorXd::Ones(1), 2.0},
                             {ex15_A(), ex15_E(), Eigen::VectorXd::Ones(1), 1.2}};
  cases.push_back({random_schur(3, rng, 0.7), Eigen::MatrixXd::Random(3, 2), Eigen::Vector2d(1, 0.5), 2.0});
  cases.push_back({random_schur(4, rng, 0.6), Eigen::MatrixXd::Random(4, 2), Eigen::Vector2d(0.3, 1), 3.0});
  for (const auto& c : cases) {
    const thesis::BrlRpi brl = thesis::brl_ellipsoidal_rpi(c.A, c.E, c.wbar);
    const auto lv = thesis::expanded_ellipsoid_levels(brl.P, std::sqrt(brl.g), c.wbar.squaredNorm(), c.mu);
    EXPECT_LT(lv.c_in, lv.c_out);
    const Polytope Phi = thesis::polyhedral_rpi_between_ellipsoids(brl.P, lv.c_in, lv.c_out);
    check_between(Phi, brl.P, lv.c_in, lv.c_out);
    const Eigen::MatrixXd D = corners(c.wbar);
    for (Eigen::Index j = 0; j < Phi.num_vertices(); ++j)
      for (Eigen::Index k = 0; k < D.cols(); ++k)
        ASSERT_TRUE(Phi.contains(c.A * Phi.vertices().col(j) + c.E * D.col(k), 1e-12))
            << "n = " << c.A.rows() << ": A v + E d leaves Phi_v";
  }
}

TEST(ThesisInvariant, Example15GammaIsHinfNorm) {
  const thesis::BrlRpi brl = thesis::brl_ellipsoidal_rpi(ex15_A(), ex15_E(), Eigen::VectorXd::Ones(1));
  const double hinf = hinf_norm_grid(ex15_A(), ex15_E());
  EXPECT_GE(brl.gamma, hinf * (1 - 1e-9));
  EXPECT_LE(brl.gamma, hinf * (1 + 1e-4));
}

// ---------------------------------------------------------------- Algorithm 1

struct MrpiCase {
  Eigen::MatrixXd A, E;
  Eigen::VectorXd wbar;
  double mu, eps;
};

void check_algorithm1(const MrpiCase& c, std::mt19937& rng, thesis::MrpiStopRule rule) {
  thesis::MrpiOptions opt;
  opt.stop = rule;
  const thesis::MrpiDesign d = thesis::mrpi_outer_shrinking(c.A, c.E, c.wbar, c.mu, c.eps, opt);
  const auto& r = d.shrinking;
  const int K = r.k_star;
  const int n = int(c.A.rows());
  SCOPED_TRACE("n = " + std::to_string(n) + ", k* = " + std::to_string(K));
  ASSERT_GE(K, 1);
  ASSERT_EQ(int(r.sets.size()), K + 1);
  ASSERT_EQ(int(r.boxes.size()), K + 1);
  EXPECT_GT(r.beta, 0.0);
  EXPECT_LT(r.beta, 1.0);
  // β is the P-norm contraction: AᵀPA ≼ β²P
  const Eigen::MatrixXd Mb = r.beta * r.beta * d.brl.P - c.A.transpose() * d.brl.P * c.A;
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Mb).eigenvalues().minCoeff(), -1e-10);
  // stop rule
  if (rule == thesis::MrpiStopRule::Radius) {
    EXPECT_LE(r.radius_bound[K], c.eps);
    EXPECT_GT(r.radius_bound[K - 1], c.eps);
  }
  if (rule == thesis::MrpiStopRule::ShrinkingIndex) {
    EXPECT_LE(r.shrinking_index[K], c.eps);
    EXPECT_GT(r.shrinking_index[K - 1], c.eps);
  }
  Eigen::MatrixXd AkV = d.phi_v.vertices();
  for (int k = 0; k < K; ++k) AkV = c.A * AkV;
  if (rule != thesis::MrpiStopRule::ShrinkingIndex)  // A^{k*}Φ_0 ⊆ 𝔹(ε)
    EXPECT_LE(AkV.colwise().norm().maxCoeff(), c.eps * (1 + 1e-12));
  EXPECT_NEAR(AkV.colwise().norm().maxCoeff(), r.vertex_radius[K], 1e-12);
  for (int k = 0; k <= K; ++k) EXPECT_LE(r.vertex_radius[k], r.radius_bound[k] * (1 + 1e-12));
  const Eigen::MatrixXd D = corners(c.wbar);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd Ai = Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd omega_rad = Eigen::VectorXd::Zero(n);  // Σ_{i<k} |A^iE| w̄
  for (int k = 0; k <= K; ++k) {
    const Polytope& Phi = r.sets[k];
    if (k >= 1) ASSERT_TRUE(r.sets[k - 1].contains(Phi, 1e-9)) << "not nested at k = " << k;
    // RPI: vertices mapped with every disturbance corner, and sampled points with random w
    for (Eigen::Index j = 0; j < Phi.num_vertices(); ++j)
      for (Eigen::Index q = 0; q < D.cols(); ++q)
        ASSERT_TRUE(Phi.contains(c.A * Phi.vertices().col(j) + c.E * D.col(q), 1e-9)) << "k = " << k;
    for (int s = 0; s < 100; ++s) {
      const Eigen::VectorXd x = random_point(Phi.vertices(), rng);
      Eigen::VectorXd w(c.wbar.size());
      for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = u(rng) * c.wbar(i);
      ASSERT_TRUE(Phi.contains(c.A * x + c.E * w, 1e-9));
    }
    // the rigorous box contains the polytope's own box; and ⊇ Σ_{i<k}|A^iE|w̄ (hull of Ω_k)
    const Box pb = Phi.bounding_box();
    ASSERT_TRUE((r.boxes[k].lo().array() <= pb.lo().array() + 1e-12).all());
    ASSERT_TRUE((r.boxes[k].hi().array() >= pb.hi().array() - 1e-12).all());
    EXPECT_NEAR((r.boxes[k].hi() - pb.hi()).cwiseAbs().maxCoeff(), 0.0, 1e-9);  // exact box
    ASSERT_TRUE((r.boxes[k].hi().array() >= omega_rad.array()).all());
    ASSERT_TRUE((r.boxes[k].lo().array() <= -omega_rad.array()).all());
    // Ω_k ⊆ Φ_k: random sums Σ_{i<k} A^iE w_i with corner and random w
    for (int s = 0; s < 50; ++s) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
      Eigen::MatrixXd Ap = Eigen::MatrixXd::Identity(n, n);
      for (int i = 0; i < k; ++i) {
        Eigen::VectorXd w(c.wbar.size());
        for (Eigen::Index t = 0; t < w.size(); ++t) w(t) = (s % 2 ? (u(rng) > 0 ? 1 : -1) : u(rng)) * c.wbar(t);
        x += Ap * c.E * w;
        Ap = Ap * c.A;
      }
      ASSERT_TRUE(Phi.contains(x, 1e-9)) << "Omega_k not in Phi_k at k = " << k;
    }
    omega_rad += (Ai * c.E).cwiseAbs() * c.wbar;
    Ai = Ai * c.A;
  }
  // containment in simulation: x_0 at a vertex or random in Φ_0, w random or bang-bang; x_k ∈ Φ_k
  // for k ≤ k* and x_k ∈ Φ_{k*} afterwards
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd x = trial % 2 ? random_point(d.phi_v.vertices(), rng)
                                  : Eigen::VectorXd(d.phi_v.vertices().col(trial % d.phi_v.num_vertices()));
    for (int k = 0; k <= K + 30; ++k) {
      const Polytope& Phi = r.sets[std::min(k, K)];
      ASSERT_TRUE(Phi.contains(x, 1e-9)) << "trial " << trial << " step " << k;
      ASSERT_TRUE(r.boxes[std::min(k, K)].contains(x));
      Eigen::VectorXd w(c.wbar.size());
      for (Eigen::Index t = 0; t < w.size(); ++t)
        w(t) = (trial % 4 < 2 ? (u(rng) > 0 ? 1.0 : -1.0) : u(rng)) * c.wbar(t);
      x = c.A * x + c.E * w;
    }
  }
  // the box-only variant gives the same boxes and k*
  const auto rb = thesis::mrpi_outer_shrinking_boxes(c.A, c.E, Box(-c.wbar, c.wbar), d.phi_v, d.brl.P, d.levels.c_out,
                                                     c.eps, [&] { auto o = opt; o.mu = c.mu; return o; }());
  ASSERT_EQ(rb.k_star, K);
  EXPECT_TRUE(rb.sets.empty());
  for (int k = 0; k <= K; ++k) {
    EXPECT_EQ(rb.boxes[k].lo(), r.boxes[k].lo());
    EXPECT_EQ(rb.boxes[k].hi(), r.boxes[k].hi());
  }
}

TEST(ThesisInvariant, Algorithm1Example15) {
  std::mt19937 rng(15);
  // Ex 1.5 data; ε = 4.4e-3 with the thesis's shrinking-index rule, and the rigorous radius rule
  check_algorithm1({ex15_A(), ex15_E(), Eigen::VectorXd::Ones(1), 1.2, 4.4e-3}, rng, thesis::MrpiStopRule::ShrinkingIndex);
  check_algorithm1({ex15_A(), ex15_E(), Eigen::VectorXd::Ones(1), 2.0, 1e-3}, rng, thesis::MrpiStopRule::Radius);
  check_algorithm1({ex15_A(), ex15_E(), Eigen::VectorXd::Ones(1), 2.0, 1e-3}, rng, thesis::MrpiStopRule::VertexNorm);
}

TEST(ThesisInvariant, Algorithm1Random3D4D) {
  std::mt19937 rng(34);
  check_algorithm1({random_schur(3, rng, 0.5), Eigen::MatrixXd::Random(3, 2), Eigen::Vector2d(1, 0.4), 2.0, 0.05},
                   rng, thesis::MrpiStopRule::Radius);
  check_algorithm1({random_schur(4, rng, 0.4), Eigen::MatrixXd::Random(4, 1), Eigen::VectorXd::Ones(1), 3.0, 0.05},
                   rng, thesis::MrpiStopRule::VertexNorm);
}

TEST(ThesisInvariant, ShrinkingFromClosedFormBrlPair) {
  // a non-optimal but valid BRL pair (P, γ) also gives an RPI Φ_v and a valid shrinking
  std::mt19937 rng(2);
  for (int n = 2; n <= 3; ++n) {
    const Eigen::MatrixXd A = random_schur(n, rng, 0.6), E = Eigen::MatrixXd::Random(n, 1);
    const auto [P, g] = brl_pair_closed_form(A, E);
    const auto lv = thesis::expanded_ellipsoid_levels(P, std::sqrt(g), 1.0, 2.0);
    const Polytope Phi = thesis::polyhedral_rpi_between_ellipsoids(P, lv.c_in, lv.c_out);
    const auto r = thesis::mrpi_outer_shrinking(A, E, Box(-Eigen::VectorXd::Ones(1), Eigen::VectorXd::Ones(1)), Phi, P,
                                                lv.c_out, 1e-2);
    for (int k = 1; k <= r.k_star; ++k) ASSERT_TRUE(r.sets[k - 1].contains(r.sets[k], 1e-9));
    for (Eigen::Index j = 0; j < Phi.num_vertices(); ++j)
      for (double w : {-1.0, 1.0}) ASSERT_TRUE(Phi.contains(A * Phi.vertices().col(j) + E * w, 1e-12));
  }
}

TEST(ThesisInvariant, BadInput) {
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(2, 2);
  expect_error_naming<InvalidArgumentError>([&] { thesis::polyhedral_rpi_between_ellipsoids(P, 2.0, 1.0); }, "c_out");
  expect_error_naming<InvalidArgumentError>([&] { thesis::polyhedral_rpi_between_ellipsoids(P, 1.0, 1.0); }, "c_out");
  expect_error_naming<InvalidArgumentError>([&] { thesis::polyhedral_rpi_between_ellipsoids(P, 0.0, 1.0); }, "c_in");
  expect_error_naming<NotFiniteError>([&] { thesis::polyhedral_rpi_between_ellipsoids(P, NAN, 1.0); }, "c_in");
  expect_error_naming<NotPositiveDefiniteError>(
      [&] { thesis::polyhedral_rpi_between_ellipsoids((Eigen::MatrixXd(2, 2) << 1, 0, 0, -1).finished(), 1, 2); }, "P");
  expect_error_naming<NotSymmetricError>(
      [&] { thesis::polyhedral_rpi_between_ellipsoids((Eigen::MatrixXd(2, 2) << 1, 0.5, 0, 1).finished(), 1, 2); }, "P");
  expect_error_naming<InfeasibleError>(
      [&] {
        thesis::PolyhedralRpiOptions o;
        o.max_vertices = 50;
        thesis::polyhedral_rpi_between_ellipsoids(Eigen::MatrixXd::Identity(3, 3), 1.0, 1.001, o);
      },
      "c_out");
  const Polytope Phi = thesis::polyhedral_rpi_between_ellipsoids(P, 1.0, 2.0);
  const Box d(-Eigen::VectorXd::Ones(1), Eigen::VectorXd::Ones(1));
  const Eigen::MatrixXd E = ex15_E();
  const Eigen::MatrixXd unstable = (Eigen::MatrixXd(2, 2) << 1.1, 0, 0, 0.5).finished();
  expect_error_naming<InvalidArgumentError>([&] { thesis::mrpi_outer_shrinking(unstable, E, d, Phi, P, 2.0, 0.1); }, "A");
  expect_error_naming<InvalidArgumentError>([&] { thesis::mrpi_outer_shrinking(ex15_A(), E, d, Phi, P, 2.0, 0.0); }, "eps");
  expect_error_naming<InvalidArgumentError>([&] { thesis::mrpi_outer_shrinking(ex15_A(), E, d, Phi, P, 2.0, -1.0); }, "eps");
  expect_error_naming<InvalidArgumentError>(
      [&] { thesis::mrpi_outer_shrinking(ex15_A(), E, Box::empty(1), Phi, P, 2.0, 0.1); }, "delta");
  expect_error_naming<InvalidArgumentError>(
      [&] { thesis::mrpi_outer_shrinking(ex15_A(), E, Box(Eigen::VectorXd::Ones(1), 2 * Eigen::VectorXd::Ones(1)), Phi, P, 2.0, 0.1); },
      "delta");
  expect_error_naming<InvalidArgumentError>([&] { thesis::mrpi_outer_shrinking(ex15_A(), E, d, Phi, P, 1.0, 0.1); }, "Phi0");
  expect_error_naming<DimensionError>(
      [&] { thesis::mrpi_outer_shrinking(ex15_A(), Eigen::MatrixXd::Ones(3, 1), d, Phi, P, 2.0, 0.1); }, "E");
  expect_error_naming<NotPositiveDefiniteError>(
      [&] { thesis::mrpi_outer_shrinking(ex15_A(), E, d, Phi, (Eigen::MatrixXd(2, 2) << 1, 0, 0, -1).finished(), 2.0, 0.1); }, "P");
  expect_error_naming<InfeasibleError>([&] { thesis::mrpi_outer_shrinking(unstable, E, Eigen::VectorXd::Ones(1), 2.0, 0.1); }, "A");
  expect_error_naming<InvalidArgumentError>([&] { thesis::mrpi_outer_shrinking(ex15_A(), E, Eigen::VectorXd::Ones(1), 1.0, 0.1); }, "mu");
}

// ---------------------------------------------------------------- C ABI

std::string last_error() { return sb_last_error(); }

TEST(ThesisInvariantCapi, PolytopeRoundTripAndAlgorithm1) {
  // polytope from vertices (row-major, one point per row)
  const double pts[] = {0, 0, 2, 0, 0, 2, 2, 2, 1, 1};
  sb_polytope* p = nullptr;
  ASSERT_EQ(sb_polytope_from_vertices(2, 5, pts, &p), SB_OK) << last_error();
  int n = 0, nv = 0, nf = 0;
  ASSERT_EQ(sb_polytope_sizes(p, &n, &nv, &nf), SB_OK);
  EXPECT_EQ(n, 2);
  EXPECT_EQ(nv, 4);
  EXPECT_EQ(nf, 4);
  std::vector<double> V(nv * 2), H(nf * 2), b(nf);
  ASSERT_EQ(sb_polytope_get(p, V.data(), H.data(), b.data()), SB_OK);
  const double q[] = {1, 1, 3, 1};
  int inside[2] = {-1, -1};
  ASSERT_EQ(sb_polytope_contains(p, 2, q, 1e-9, inside), SB_OK);
  EXPECT_EQ(inside[0], 1);
  EXPECT_EQ(inside[1], 0);
  double lo[2], hi[2], r = 0;
  ASSERT_EQ(sb_polytope_bounding_box(p, lo, hi), SB_OK);
  EXPECT_EQ(lo[0], 0.0);
  EXPECT_EQ(hi[1], 2.0);
  ASSERT_EQ(sb_polytope_max_vertex_norm(p, &r), SB_OK);
  EXPECT_NEAR(r, std::sqrt(8.0), 1e-15);
  sb_polytope* s = nullptr;
  const double blo[] = {-1, -1}, bhi[] = {1, 1};
  ASSERT_EQ(sb_polytope_minkowski_box(p, blo, bhi, &s), SB_OK);
  ASSERT_EQ(sb_polytope_bounding_box(s, lo, hi), SB_OK);
  EXPECT_EQ(lo[0], -1.0);
  EXPECT_EQ(hi[0], 3.0);
  sb_polytope_free(s);
  // H-rep round trip
  const double c[] = {1, 1};
  ASSERT_EQ(sb_polytope_from_halfspaces(2, nf, H.data(), b.data(), c, &s), SB_OK) << last_error();
  int nv2 = 0;
  sb_polytope_sizes(s, nullptr, &nv2, nullptr);
  EXPECT_EQ(nv2, 4);
  sb_polytope_free(s);
  sb_polytope_free(p);

  // ellipsoid box and Φ_v
  const double P[] = {1, 1, 1, 4}, c0[] = {0, 0};
  ASSERT_EQ(sb_ellipsoid_bounding_box(2, P, c0, 1.0, lo, hi), SB_OK);
  EXPECT_NEAR(hi[0], std::sqrt(4.0 / 3.0), 1e-12);
  ASSERT_EQ(sb_polyhedral_rpi(2, P, 1.0, 1.3, 0, &p), SB_OK) << last_error();
  sb_polytope_sizes(p, &n, &nv, &nf);
  V.resize(nv * 2);
  sb_polytope_get(p, V.data(), nullptr, nullptr);
  const Eigen::Map<const Eigen::Matrix<double, 2, 2, Eigen::RowMajor>> Pm(P);
  for (int j = 0; j < nv; ++j) {
    const Eigen::Vector2d v(V[2 * j], V[2 * j + 1]);
    EXPECT_LE(v.dot(Pm * v), 1.3);
  }
  sb_polytope_free(p);

  // Algorithm 1 on Ex 1.5 through the C ABI equals the C++ result
  const double A[] = {0.2, 0.2, -0.2, 0.5}, E[] = {0, 1}, wbar[] = {1};
  sb_mrpi* m = nullptr;
  ASSERT_EQ(sb_mrpi_algorithm1(2, 1, A, E, wbar, 2.0, 1e-3, SB_MRPI_STOP_RADIUS, 0, 0, &m), SB_OK) << last_error();
  int ks = 0, has_sets = 0, has_design = 0;
  double beta = 0;
  ASSERT_EQ(sb_mrpi_info(m, &n, &ks, &beta, &has_sets, &has_design), SB_OK);
  EXPECT_EQ(has_sets, 1);
  EXPECT_EQ(has_design, 1);
  const auto ref = thesis::mrpi_outer_shrinking(ex15_A(), ex15_E(), Eigen::VectorXd::Ones(1), 2.0, 1e-3);
  EXPECT_EQ(ks, ref.shrinking.k_star);
  EXPECT_NEAR(beta, ref.shrinking.beta, 1e-6);
  std::vector<double> rb(ks + 1), bl((ks + 1) * 2), bh((ks + 1) * 2);
  ASSERT_EQ(sb_mrpi_sequences(m, rb.data(), nullptr, nullptr), SB_OK);
  EXPECT_LE(rb[ks], 1e-3);
  ASSERT_EQ(sb_mrpi_boxes(m, bl.data(), bh.data()), SB_OK);
  sb_polytope* last = nullptr;
  ASSERT_EQ(sb_mrpi_set(m, ks, &last), SB_OK);
  ASSERT_EQ(sb_polytope_bounding_box(last, lo, hi), SB_OK);
  EXPECT_NEAR(hi[1], bh[2 * ks + 1], 1e-9);
  sb_polytope_free(last);
  double Pd[4], gamma = 0, cin = 0, cout = 0;
  ASSERT_EQ(sb_mrpi_design(m, Pd, &gamma, &cin, &cout), SB_OK);
  EXPECT_LT(cin, cout);
  EXPECT_NEAR(gamma, ref.brl.gamma, 1e-5 * ref.brl.gamma);
  // a Φ_0-given, boxes-only run from the C ABI
  sb_polytope* phi0 = nullptr;
  ASSERT_EQ(sb_mrpi_set(m, 0, &phi0), SB_OK);
  sb_mrpi* mb = nullptr;
  const double dlo[] = {-1}, dhi[] = {1};
  ASSERT_EQ(sb_mrpi_shrinking(2, 1, A, E, dlo, dhi, phi0, Pd, cout, 1e-3, SB_MRPI_STOP_RADIUS, 2.0, 0, 1, &mb), SB_OK)
      << last_error();
  int ks2 = 0;
  sb_mrpi_info(mb, nullptr, &ks2, nullptr, &has_sets, &has_design);
  EXPECT_EQ(has_sets, 0);
  EXPECT_EQ(has_design, 0);
  EXPECT_EQ(sb_mrpi_set(mb, 1, &last), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_mrpi_design(mb, Pd, nullptr, nullptr, nullptr), SB_ERR_INVALID_ARGUMENT);
  sb_mrpi_free(mb);
  sb_polytope_free(phi0);
  sb_mrpi_free(m);
}

TEST(ThesisInvariantCapi, BadInput) {
  const double P[] = {1, 0, 0, 1}, Pbad[] = {1, 0, 0, -1};
  sb_polytope* p = nullptr;
  EXPECT_EQ(sb_polyhedral_rpi(2, P, 2.0, 1.0, 0, &p), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("c_out:"), std::string::npos) << last_error();
  EXPECT_EQ(sb_polyhedral_rpi(2, Pbad, 1.0, 2.0, 0, &p), SB_ERR_NOT_POSITIVE_DEFINITE);
  EXPECT_NE(last_error().find("P:"), std::string::npos) << last_error();
  EXPECT_EQ(sb_polyhedral_rpi(2, nullptr, 1.0, 2.0, 0, &p), SB_ERR_INVALID_ARGUMENT);
  const double flat[] = {0, 0, 1, 1, 2, 2};
  EXPECT_EQ(sb_polytope_from_vertices(2, 3, flat, &p), SB_ERR_INVALID_ARGUMENT);
  const double A[] = {1.1, 0, 0, 0.5}, E[] = {0, 1}, wbar[] = {1};
  sb_mrpi* m = nullptr;
  EXPECT_EQ(sb_mrpi_algorithm1(2, 1, A, E, wbar, 2.0, 0.1, SB_MRPI_STOP_RADIUS, 0, 0, &m), SB_ERR_INFEASIBLE);
  EXPECT_NE(last_error().find("A:"), std::string::npos) << last_error();
  const double As[] = {0.2, 0.2, -0.2, 0.5};
  EXPECT_EQ(sb_mrpi_algorithm1(2, 1, As, E, wbar, 2.0, 0.0, SB_MRPI_STOP_RADIUS, 0, 0, &m), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("eps:"), std::string::npos) << last_error();
  EXPECT_EQ(sb_mrpi_algorithm1(2, 1, As, E, wbar, 2.0, 0.1, 7, 0, 0, &m), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("stop_rule:"), std::string::npos) << last_error();
  ASSERT_EQ(sb_polyhedral_rpi(2, P, 1.0, 2.0, 0, &p), SB_OK);
  const double dlo[] = {1}, dhi[] = {2};
  EXPECT_EQ(sb_mrpi_shrinking(2, 1, As, E, dlo, dhi, p, P, 2.0, 0.1, 0, 1.0, 0, 0, &m), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("delta:"), std::string::npos) << last_error();
  const double elo[] = {INFINITY}, ehi[] = {-INFINITY};  // the empty-box encoding
  EXPECT_EQ(sb_mrpi_shrinking(2, 1, As, E, elo, ehi, p, P, 2.0, 0.1, 0, 1.0, 0, 0, &m), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("delta:"), std::string::npos) << last_error();
  EXPECT_EQ(sb_mrpi_shrinking(2, 1, A, E, elo, ehi, nullptr, P, 2.0, 0.1, 0, 1.0, 0, 0, &m), SB_ERR_INVALID_ARGUMENT);
  sb_polytope_free(p);
}

}  // namespace
