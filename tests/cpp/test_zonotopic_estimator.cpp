// The zonotopic estimator structure (papers.md §3.1) with the segment-minimisation gain
// (§5.1): containment of the true state under random and vertex disturbances, for known and
// interval A, and the model's validation.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "setbound/core/linear_system.hpp"
#include "setbound/estimators/zonotopic/gain_estimator.hpp"
#include "test_helpers.hpp"

using namespace setbound;
using setbound::testing::expect_error_naming;

namespace {

// EX-LE13 (papers §3.5): x+ = [0 -0.5; 1 1+0.3δ] x + F_w ω, y = C x + 0.2 v.
LinearSystem le13(bool interval_A) {
  Eigen::MatrixXd A(2, 2), C(2, 2), E(2, 3), F(2, 3), Arad = Eigen::MatrixXd::Zero(2, 2);
  A << 0, -0.5, 1, 1;
  C << -2, 1, 1, 1;
  E << -0.12, 0, 0, 0.02, 0, 0;  // ω = [w; v1; v2]
  F << 0, 0.2, 0, 0, 0, 0.2;
  if (interval_A) Arad(1, 1) = 0.3;
  return LinearSystem(A, C, E, F, {}, {}, Arad);
}

struct RunStats {
  int steps = 0, violations = 0;
};

// Simulates the true system with A_true ∈ [A] and ω drawn uniformly or at box vertices, and
// checks x_k ∈ X̂_k at every step with the exact membership test.
RunStats simulate(const LinearSystem& sys, const Eigen::MatrixXd& A_true, const Eigen::VectorXd& x0,
             const Zonotope& X0, bool vertex, unsigned seed, int N, ZonotopicOptions opt = {}) {
  std::mt19937 gen(seed);
  auto draw = [&](Eigen::Index n) { return setbound::testing::draw_disturbance(gen, n, vertex); };
  ZonotopicEstimator est(sys, X0, segment_min_gain, opt);
  Eigen::VectorXd x = x0, u = Eigen::VectorXd::Zero(sys.nu());
  RunStats r;
  for (int k = 0; k < N; ++k) {
    const Eigen::VectorXd w = draw(sys.nw());
    if (sys.nu() > 0) u = 2.0 * draw(sys.nu());
    const Eigen::VectorXd y = sys.C() * x + sys.D() * u + sys.F() * w;
    const Zonotope X = est.step(y, u);
    ++r.steps;
    if (!X.contains(x, 0.0)) ++r.violations;
    x = A_true * x + sys.B() * u + sys.E() * draw(sys.nw());
  }
  return r;
}

}  // namespace

const ZonotopeReduction kReductions[] = {ZonotopeReduction::Combastel, ZonotopeReduction::Girard,
                                         ZonotopeReduction::Pca};

ZonotopicOptions with_reduction(ZonotopeReduction r, Eigen::Index limit = 20) {
  ZonotopicOptions o;
  o.max_generators = limit;
  o.reduction = r;
  return o;
}

TEST(ZonotopicEstimator, ContainsTruthOnLe13KnownA) {
  const LinearSystem sys = le13(false);
  const Zonotope X0(Eigen::Vector2d::Zero(), 3.0 * Eigen::Matrix2d::Identity());
  for (ZonotopeReduction red : kReductions)
    for (bool vertex : {false, true})
      for (unsigned seed = 1; seed <= 5; ++seed) {
        std::mt19937 g(seed);
        std::uniform_real_distribution<double> u(-3, 3);
        const Eigen::Vector2d x0(vertex ? 3.0 : u(g), vertex ? -3.0 : u(g));
        const RunStats r = simulate(sys, sys.A(), x0, X0, vertex, seed, 100, with_reduction(red, 6 + seed));
        EXPECT_EQ(r.violations, 0) << "seed " << seed << (vertex ? " vertex" : " random") << " reduction "
                                   << static_cast<int>(red);
      }
}

TEST(ZonotopicEstimator, ContainsTruthOnLe13IntervalA) {
  const LinearSystem sys = le13(true);
  const Zonotope X0(Eigen::Vector2d::Zero(), 3.0 * Eigen::Matrix2d::Identity());
  for (ZonotopeReduction red : kReductions)
    for (double delta : {-1.0, -0.3, 0.5, 1.0})
      for (bool vertex : {false, true}) {
        Eigen::MatrixXd A_true = sys.A();
        A_true(1, 1) += 0.3 * delta;
        const RunStats r = simulate(sys, A_true, Eigen::Vector2d(3.0, 3.0), X0, vertex, 7, 100, with_reduction(red));
        EXPECT_EQ(r.violations, 0) << "delta " << delta;
      }
}

TEST(ZonotopicEstimator, ContainsTruthOnRandomSystemsWithInputs) {
  std::mt19937 gen(42);
  std::normal_distribution<double> nrm;
  int total = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 2 + trial % 3, ny = 1 + trial % 2, nu = 1, nw = n + ny;
    Eigen::MatrixXd A(n, n), C(ny, n), B(n, nu), E = Eigen::MatrixXd::Zero(n, nw),
        F = Eigen::MatrixXd::Zero(ny, nw);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) A(i, j) = nrm(gen) / std::sqrt(double(n));
    if (trial % 2) A *= 1.3 / std::abs(Eigen::EigenSolver<Eigen::MatrixXd>(A).eigenvalues().array().abs().maxCoeff());
    for (int i = 0; i < ny; ++i)
      for (int j = 0; j < n; ++j) C(i, j) = nrm(gen);
    for (int i = 0; i < n; ++i) B(i, 0) = nrm(gen), E(i, i) = 0.05;
    for (int i = 0; i < ny; ++i) F(i, n + i) = 0.1;
    if (!check_detectability(A, C).detectable) continue;
    const LinearSystem sys(A, C, E, F, B);
    const Zonotope X0(Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n));
    for (bool vertex : {false, true}) {
      const RunStats r = simulate(sys, A, Eigen::VectorXd::Constant(n, vertex ? 1.0 : 0.3), X0, vertex,
                                  100 + trial, 60, with_reduction(kReductions[trial % 3], 8));
      EXPECT_EQ(r.violations, 0) << "trial " << trial;
      total += r.steps;
    }
  }
  EXPECT_GE(total, 1500);
}

TEST(ZonotopicEstimator, ReductionLimitAndStripOrderAreHonoured) {
  const LinearSystem sys = le13(false);
  const Zonotope X0(Eigen::Vector2d::Zero(), 3.0 * Eigen::Matrix2d::Identity());
  for (ZonotopeReduction red : kReductions) {
    ZonotopicEstimator est(sys, X0, segment_min_gain, ZonotopicOptions{5, true, {1, 0}, red});
    Eigen::Vector2d y(0.1, -0.2);
    for (int k = 0; k < 10; ++k) {
      const Zonotope X = est.step(y, Eigen::VectorXd(0));
      // At most 5 generators; the pending rounding box (not counted) until the first reduction.
      EXPECT_LE(est.current_generators().cols(), 5);
      EXPECT_LE(X.num_generators(), est.reduced_last_step() ? 5 : 5 + 2);
      if (est.reduced_last_step()) EXPECT_EQ(est.current_box().maxCoeff(), 0.0);
      EXPECT_LE(est.current_box().maxCoeff(), 1e-13 * (est.current_upper() - est.current_lower()).maxCoeff());
    }
    EXPECT_TRUE(est.reduced_last_step());
  }
  EXPECT_THROW(ZonotopicEstimator(sys, X0, segment_min_gain, ZonotopicOptions{1, true, {}}), InvalidArgumentError);
  EXPECT_THROW(ZonotopicEstimator(sys, X0, segment_min_gain, ZonotopicOptions{20, true, {0, 0}}),
               InvalidArgumentError);
}

TEST(ZonotopicEstimator, FastPathAgreesWithTheGenericPath) {
  // Segment minimisation runs on the n×n Gram matrix with one product per step; the same rule
  // as an opaque callable goes strip by strip through the generator matrix. Same sets up to
  // rounding, for known and interval A, with inputs, for every reduction.
  std::mt19937 gen(5);
  std::normal_distribution<double> nrm;
  const auto opaque = [](const Zonotope& Z, const StripMeasurement& m) { return segment_min_gain(Z, m); };
  for (bool interval : {false, true})
    for (ZonotopeReduction red : kReductions) {
      const int n = 3, ny = 2;
      Eigen::MatrixXd A(n, n), C(ny, n), B(n, 1), E = Eigen::MatrixXd::Zero(n, n + ny),
                      F = Eigen::MatrixXd::Zero(ny, n + ny), D(ny, 1), Arad = Eigen::MatrixXd::Zero(n, n);
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) A(i, j) = 0.5 * nrm(gen);
        B(i, 0) = nrm(gen);
        E(i, i) = 0.05;
      }
      for (int i = 0; i < ny; ++i) {
        for (int j = 0; j < n; ++j) C(i, j) = nrm(gen);
        F(i, n + i) = 0.1;
        D(i, 0) = 0.3 * nrm(gen);
      }
      if (interval) Arad(0, 1) = 0.02;
      const LinearSystem sys(A, C, E, F, B, D, Arad);
      const Zonotope X0(Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n));
      ZonotopicEstimator fast(sys, X0, segment_min_gain, with_reduction(red, 9));
      ZonotopicEstimator slow(sys, X0, opaque, with_reduction(red, 9));
      for (int k = 0; k < 40; ++k) {
        Eigen::VectorXd y(ny), u(1);
        for (int i = 0; i < ny; ++i) y(i) = 0.2 * nrm(gen);
        u(0) = nrm(gen);
        fast.update(y, u);
        slow.update(y, u);
        const double scale = (slow.current_upper() - slow.current_lower()).maxCoeff();
        ASSERT_EQ(fast.current_generators().cols(), slow.current_generators().cols()) << "k " << k;
        EXPECT_LT((fast.current_lower() - slow.current_lower()).cwiseAbs().maxCoeff(), 1e-9 * scale) << "k " << k;
        EXPECT_LT((fast.current_upper() - slow.current_upper()).cwiseAbs().maxCoeff(), 1e-9 * scale) << "k " << k;
      }
    }
}

TEST(ZonotopicEstimator, AThrowingRuleLeavesTheStateUnchanged) {
  const LinearSystem sys = le13(false);
  const Zonotope X0(Eigen::Vector2d::Zero(), 3.0 * Eigen::Matrix2d::Identity());
  int calls = 0;
  bool fail = false;
  const auto rule = [&](const Zonotope& Z, const StripMeasurement& m) -> Eigen::VectorXd {
    ++calls;
    if (fail && m.output == 1) throw NumericalError("rule: failed on purpose");
    return segment_min_gain(Z, m);
  };
  ZonotopicEstimator est(sys, X0, rule, with_reduction(ZonotopeReduction::Pca, 6));
  ZonotopicEstimator ref(sys, X0, segment_min_gain, with_reduction(ZonotopeReduction::Pca, 6));
  const Eigen::Vector2d y(0.1, -0.2);
  for (int k = 0; k < 5; ++k) est.update(y, Eigen::VectorXd(0)), ref.update(y, Eigen::VectorXd(0));
  const Eigen::VectorXd lo = est.current_lower();
  fail = true;
  EXPECT_THROW(est.update(y, Eigen::VectorXd(0)), NumericalError);  // after the first strip
  EXPECT_EQ(est.steps_taken(), 5);
  EXPECT_EQ(est.current_lower(), lo);
  fail = false;
  est.update(y, Eigen::VectorXd(0));
  ref.update(y, Eigen::VectorXd(0));
  EXPECT_LT((est.current_lower() - ref.current_lower()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((est.current_upper() - ref.current_upper()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(calls, 10);
}

TEST(ZonotopicEstimator, TheRoundingBoxStaysNegligibleWithoutReduction) {
  // No reduction for 150 steps (a generous limit): the pending box is carried through the
  // whole step transform and stays at rounding level relative to the set.
  const LinearSystem sys = le13(false);
  const Zonotope X0(Eigen::Vector2d::Zero(), 3.0 * Eigen::Matrix2d::Identity());
  ZonotopicEstimator est(sys, X0, segment_min_gain, with_reduction(ZonotopeReduction::Girard, 500));
  std::mt19937 gen(9);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::Vector2d x(1.0, -2.0);
  for (int k = 0; k < 150; ++k) {
    const Eigen::VectorXd w = (Eigen::VectorXd(3) << U(gen), U(gen), U(gen)).finished();
    est.update(sys.C() * x + sys.F() * w, Eigen::VectorXd(0));
    ASSERT_FALSE(est.reduced_last_step());
    const double radius = ((est.current_upper() - est.current_lower()) / 2).minCoeff();
    EXPECT_LE(est.current_box().maxCoeff(), 1e-12 * radius) << "k " << k;
    x = sys.A() * x + sys.E() * w;
  }
  EXPECT_EQ(est.current_generators().cols(), 4 + 149 * 3);  // X0, 2 strips, then E and 2 strips
}

TEST(ZonotopicEstimator, FixedGainsAreChecked) {
  const LinearSystem sys = le13(false);
  const Zonotope X0(Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity());
  expect_error_naming<DimensionError>(
      [&] { ZonotopicEstimator(sys, X0, ZonotopeGain::fixed(Eigen::MatrixXd::Zero(3, 2))); }, "lambdas");
  Eigen::MatrixXd bad = Eigen::MatrixXd::Zero(2, 2);
  bad(0, 0) = std::nan("");
  expect_error_naming<NotFiniteError>([&] { ZonotopeGain::fixed(bad); }, "lambdas");
}

TEST(ZonotopicEstimator, WithoutFirstMeasurementTheFirstSetIsX0) {
  const LinearSystem sys = le13(false);
  const Zonotope X0(Eigen::Vector2d(1, 2), 3.0 * Eigen::Matrix2d::Identity());
  ZonotopicEstimator est(sys, X0, segment_min_gain, ZonotopicOptions{20, false, {}});
  const Zonotope first = est.step(Eigen::Vector2d(0, 3), Eigen::VectorXd(0));
  EXPECT_EIGEN_NEAR(first.center(), X0.center(), 0.0);
  EXPECT_EIGEN_NEAR(first.generators(), X0.generators(), 0.0);
}

TEST(ZonotopicEstimator, CorrectionShrinksAndKeepsConsistentPoints) {
  // Points of X that satisfy the strip stay in the corrected set (Property 6).
  const LinearSystem sys = le13(false);
  const Zonotope X(Eigen::Vector2d(0.2, -0.1), (Eigen::Matrix2d() << 2, 0.5, -0.3, 1).finished());
  ZonotopicEstimator est(sys, X, segment_min_gain);
  const Eigen::Vector2d y(0.4, 0.7);
  const Zonotope Xc = est.correct(X, y, Eigen::VectorXd(0));
  EXPECT_LT(Xc.volume(), X.volume());
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int kept = 0;
  for (int s = 0; s < 20000; ++s) {
    const Eigen::Vector2d x = X.center() + X.generators() * Eigen::Vector2d(u(gen), u(gen));
    const Eigen::Vector2d r = sys.C() * x - y;
    if (std::abs(r(0)) <= 0.2 && std::abs(r(1)) <= 0.2) {
      ++kept;
      EXPECT_TRUE(Xc.contains(x, 0.0));
    }
  }
  EXPECT_GT(kept, 50);
}

TEST(ZonotopicEstimator, BadInputLeavesStateUnchanged) {
  const LinearSystem sys = le13(false);
  const Zonotope X0(Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity());
  ZonotopicEstimator est(sys, X0, segment_min_gain);
  // (a NaN reading is a missing one, not an error: test_measurement_check.cpp)
  EXPECT_THROW(est.step(Eigen::Vector2d(std::numeric_limits<double>::infinity(), 0), Eigen::VectorXd(0)),
               NotFiniteError);
  EXPECT_THROW(est.step(Eigen::Vector3d(0, 0, 0), Eigen::VectorXd(0)), DimensionError);
  EXPECT_EQ(est.steps_taken(), 0);
  EXPECT_EIGEN_NEAR(est.prediction().generators(), X0.generators(), 0.0);
  EXPECT_THROW(ZonotopicEstimator(sys, Zonotope(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity()),
                                  segment_min_gain),
               DimensionError);
}

TEST(LinearSystem, ValidatesShapesAndNamesArguments) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(2, 2), C(1, 2), E = Eigen::MatrixXd::Identity(2, 2),
                  F = Eigen::MatrixXd::Zero(1, 2);
  C << 1, 0;
  EXPECT_NO_THROW(LinearSystem(A, C, E, F));
  try {
    LinearSystem(A, C, E, Eigen::MatrixXd::Zero(2, 2));
    FAIL();
  } catch (const DimensionError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("F:", 0), 0u) << e.what();
  }
  EXPECT_THROW(LinearSystem(Eigen::MatrixXd::Zero(2, 3), C, E, F), DimensionError);
  Eigen::MatrixXd An = A;
  An(0, 1) = std::nan("");
  EXPECT_THROW(LinearSystem(An, C, E, F), NotFiniteError);
  EXPECT_THROW(LinearSystem(A, C, E, F, {}, {}, -Eigen::MatrixXd::Ones(2, 2)), InvalidArgumentError);
  const LinearSystem s(A, C, E, F, {}, {}, (Eigen::MatrixXd(2, 2) << 0.1, 0, 0, 0.2).finished());
  EXPECT_TRUE(s.uncertain_A());
  const auto V = s.A_vertices();
  ASSERT_EQ(V.size(), 4u);
  for (const auto& v : V) EXPECT_NEAR(std::abs(v(0, 0) - 1.0) + std::abs(v(1, 1) - 1.0), 0.3, 1e-15);
}

TEST(LinearSystem, DetectabilityIsThePbhTest) {
  Eigen::MatrixXd A(2, 2), C(1, 2);
  A << 1.2, 0, 0, 0.5;
  C << 0, 1;  // sees only the stable mode
  const auto r = check_detectability(A, C);
  EXPECT_FALSE(r.detectable);
  EXPECT_NEAR(r.mode.real(), 1.2, 1e-12);
  try {
    require_detectable(A, C);
    FAIL();
  } catch (const NotDetectableError& e) {
    EXPECT_NE(std::string(e.what()).find("1.2"), std::string::npos) << e.what();
  }
  C << 1, 0;  // sees the unstable mode; the stable one need not be seen
  EXPECT_TRUE(check_detectability(A, C).detectable);
  A << 0, 1, -1, 0;  // rotation, |λ| = 1: must be observable
  C << 1, 0;
  EXPECT_TRUE(check_detectability(A, C).detectable);
  C << 0, 0;
  EXPECT_FALSE(check_detectability(A, C).detectable);
}

// Segment minimisation screens a reading with a cheap lower bound of the output set's radius
// from its kept Gram matrix first: the margin it reports is exact when the reading is outside or
// undecided, and an upper bound (<= 0) otherwise: never below the exact margin, never of the
// other sign. One output, so the set tested is the prior A X̂ ⊕ B u ⊕ E B^{n_ω}.
TEST(ZonotopicEstimator, ScreeningMarginsBoundTheExactOnes) {
  std::mt19937 gen(31);
  std::normal_distribution<double> nrm;
  int exact = 0, bounded = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const int n = 2 + trial % 3, nw = n + 1;
    Eigen::MatrixXd A(n, n), C(1, n), B(n, 1), E = Eigen::MatrixXd::Zero(n, nw), F = Eigen::MatrixXd::Zero(1, nw);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) A(i, j) = nrm(gen) / std::sqrt(double(n));
    for (int j = 0; j < n; ++j) C(0, j) = nrm(gen);
    for (int i = 0; i < n; ++i) B(i, 0) = nrm(gen), E(i, i) = 0.05;
    F(0, n) = 0.1;
    const LinearSystem sys(A, C, E, F, B);
    ZonotopicEstimator est(sys, Zonotope(Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n)), segment_min_gain,
                           with_reduction(kReductions[trial % 3], 4 * n));
    std::mt19937 g2(trial);
    Eigen::VectorXd x = 0.5 * setbound::testing::draw_disturbance(g2, n, false);
    for (int k = 0; k < 80; ++k) {
      const Eigen::VectorXd w = setbound::testing::draw_disturbance(g2, nw, k % 2 == 0);
      const Eigen::VectorXd u = Eigen::VectorXd::Constant(1, std::sin(0.3 * k));
      Eigen::VectorXd y = C * x + F * w;
      if (k % 4 == 1) y(0) += k % 8 == 1 ? 0.5 : -0.5;  // some readings near or beyond the edge
      const bool first = k == 0;
      Eigen::VectorXd center;
      double radius = 0.0;
      if (!first) {
        const Zonotope Z = est.current_set();
        const Eigen::VectorXd uprev = Eigen::VectorXd::Constant(1, std::sin(0.3 * (k - 1)));
        center = A * Z.center() + B * uprev;
        radius = (C * A * Z.generators()).cwiseAbs().sum() + (C * E).cwiseAbs().sum();
      }
      est.step(y, u);
      if (first) continue;
      const double sig = 0.1;
      const double m_exact = (std::abs(y(0) - C.row(0).dot(center)) - radius - sig) / sig;
      const double m = est.last_check().margin(0);
      // Rounding differs between the two computations in proportion to the numbers involved.
      const double tol = 1e-9 * (1.0 + std::abs(m_exact) + (radius + std::abs(C.row(0).dot(center))) / sig);
      EXPECT_GE(m, m_exact - tol) << "trial " << trial << " step " << k;
      if (m_exact > tol) EXPECT_NEAR(m, m_exact, tol) << "trial " << trial << " step " << k;
      if (std::abs(m - m_exact) <= tol) ++exact;
      else ++bounded;
      x = A * x + B * u + E * w;
    }
  }
  EXPECT_GT(exact, 20);
  EXPECT_GT(bounded, 100);  // the cheap bound decides most readings
}
