// Volume minimisation (papers.md §5.2) and the exact reference hull, both LPs on the bundled
// solver: optimality against brute force, and every estimator's hull containing the exact one.
#include <gtest/gtest.h>

#include <iomanip>
#include <random>
#include <vector>

#include "setbound/estimators/polytopic/exact_hull.hpp"
#include "setbound/estimators/zonotopic/pradius.hpp"
#include "setbound/estimators/zonotopic/volume_min.hpp"
#include "setbound/lmi/l1.hpp"
#include "setbound/lmi/lp.hpp"
#include "test_helpers.hpp"

using namespace setbound;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {
double family_volume(const Zonotope& Z, const Strip& s, const VectorXd& lambda) {
  return Z.intersect_strip_family(s, lambda).volume();
}

LinearSystem le13_known() {
  MatrixXd A(2, 2), C(2, 2), E(2, 3), F(2, 3);
  A << 0, -0.5, 1, 1;
  C << -2, 1, 1, 1;
  E << -0.12, 0, 0, 0.02, 0, 0;
  F << 0, 0.2, 0, 0, 0, 0.2;
  return LinearSystem(A, C, E, F);
}
}  // namespace

// The weighted-L1 method of the volume minimisation against the same LP on the general solver.
double l1_objective(const MatrixXd& G, const VectorXd& h, const VectorXd& gamma, const VectorXd& x) {
  return (gamma.array() * (G * x - h).array().abs()).sum();
}

VectorXd l1_by_lp(const MatrixXd& G, const VectorXd& h, const VectorXd& gamma) {
  const int T = static_cast<int>(G.rows()), n = static_cast<int>(G.cols());
  lmi::LinearProgram lp(n + T);
  VectorXd obj = VectorXd::Zero(n + T);
  obj.tail(T) = gamma;
  lp.set_objective(obj);
  for (int t = 0; t < T; ++t) {  // s_t ≥ ±(g_tᵀx − h_t)
    lmi::LpRow a{{n + t, -1.0}}, b{{n + t, -1.0}};
    for (int i = 0; i < n; ++i) a.emplace_back(i, G(t, i)), b.emplace_back(i, -G(t, i));
    lp.add_le(a, h(t));
    lp.add_le(b, -h(t));
  }
  const lmi::SolveResult r = lp.solve();
  EXPECT_TRUE(r.status == lmi::SolveStatus::Optimal || r.status == lmi::SolveStatus::Inaccurate);
  return r.x.head(n);
}

TEST(WeightedL1, MatchesTheLpOnRandomProblems) {
  std::mt19937 g(11);
  std::normal_distribution<double> N;
  std::uniform_real_distribution<double> U(0.01, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 1 + trial % 6, T = n + 1 + (trial * 13) % 60;
    MatrixXd G(T, n);
    VectorXd h(T), gamma(T);
    for (int t = 0; t < T; ++t) {
      for (int i = 0; i < n; ++i) G(t, i) = N(g) * std::pow(10.0, trial % 5 - 2);
      h(t) = trial % 2 ? N(g) : (t == 0 ? 1.0 : 0.0);
      gamma(t) = U(g) * (t == 0 ? 1.0 + trial : 1.0);
    }
    if (trial % 4 == 3) {  // repeated rows and tiny weights (as for repeated generators)
      G.row(T - 1) = G.row(T - 2);
      gamma(T - 1) = 1e-6;
    }
    const lmi::WeightedL1Result r = lmi::minimize_weighted_l1(G, h, gamma);
    EXPECT_TRUE(r.converged) << "trial " << trial;
    const double f = l1_objective(G, h, gamma, r.x), flp = l1_objective(G, h, gamma, l1_by_lp(G, h, gamma));
    EXPECT_NEAR(r.objective, f, 1e-12 * std::max(1.0, f));
    EXPECT_LE(f, flp + 1e-7 * std::max(1.0, flp)) << "trial " << trial << std::setprecision(17) << " " << f << " " << flp << " gap " << r.relative_gap << " lb " << r.lower_bound;  // at least as good as the LP
    EXPECT_LE(r.lower_bound, f * (1 + 1e-9) + 1e-12);
    EXPECT_GE(r.lower_bound, f - 1e-7 * std::max(1.0, f));  // the dual bound closes the gap
  }
}

TEST(WeightedL1, TrivialAndBadInput) {
  MatrixXd G(3, 2);
  G << 1, 0, 0, 1, 0, 0;  // the last row is a constant term
  VectorXd h(3), gamma(3);
  h << 2, -1, 5;
  gamma << 1, 0, 3;  // the second row has no weight
  const lmi::WeightedL1Result r = lmi::minimize_weighted_l1(G, h, gamma);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.x(0), 2.0, 1e-7);
  EXPECT_NEAR(r.objective, 15.0, 1e-6);  // 3 |0 − 5|
  EXPECT_THROW(lmi::minimize_weighted_l1(G, h.head(2), gamma), DimensionError);
  VectorXd bad = gamma;
  bad(0) = -1;
  EXPECT_THROW(lmi::minimize_weighted_l1(G, h, bad), InvalidArgumentError);
  MatrixXd Gn = G;
  Gn(0, 0) = std::nan("");
  EXPECT_THROW(lmi::minimize_weighted_l1(Gn, h, gamma), InvalidArgumentError);
  const lmi::WeightedL1Result z = lmi::minimize_weighted_l1(MatrixXd(0, 2), VectorXd(0), VectorXd(0));
  EXPECT_TRUE(z.converged && z.x.isZero(0) && z.objective == 0.0);
}

TEST(VolumeMin, LpOptimumBeatsEveryOtherGain) {
  std::mt19937 gen(8);
  std::normal_distribution<double> N;
  for (int trial = 0; trial < 12; ++trial) {
    const int n = 2 + trial % 2, m = n + 2 + trial % 3;
    MatrixXd H(n, m);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) H(i, j) = N(gen);
    VectorXd c(n);
    for (int i = 0; i < n; ++i) c(i) = N(gen);
    const Zonotope Z(VectorXd::Zero(n), H);
    const Strip s(c, 0.3 * N(gen), 0.2 + 0.1 * trial);
    const StripMeasurement meas{s, 0};
    const VectorXd lam = volume_min_gain(Z, meas);
    const double best = family_volume(Z, s, lam);
    EXPECT_LE(best, family_volume(Z, s, segment_min_gain(Z, meas)) * (1 + 1e-7));
    EXPECT_LE(best, family_volume(Z, s, VectorXd::Zero(n)) * (1 + 1e-7));
    // Brute force: random and local perturbations never do better.
    for (int k = 0; k < 400; ++k) {
      VectorXd l(n);
      for (int i = 0; i < n; ++i) l(i) = (k < 200 ? 0.05 : 1.0) * N(gen);
      if (k < 200) l += lam;
      EXPECT_LE(best, family_volume(Z, s, l) * (1 + 1e-6)) << "trial " << trial << " k " << k;
    }
  }
}

TEST(VolumeMin, TooManySubsetsIsAClearError) {
  // C(22, 7) = 170544 subsets of n − 1 = 7 generators: above kVolumeMinMaxSubsets.
  const Zonotope Z(VectorXd::Zero(8), MatrixXd::Identity(8, 22));
  VectorXd c = VectorXd::Zero(8);
  c(0) = 1;
  try {
    volume_min_gain(Z, StripMeasurement{Strip(c, 0.0, 0.1), 0});
    FAIL() << "expected InvalidArgumentError";
  } catch (const InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("C(22, 7)"), std::string::npos) << e.what();
  }
  // C(14, 6) = 3003 (an n_x = 7 estimator with n_x + 2 generators kept and 5 disturbances) is fine.
  const Zonotope Z7(VectorXd::Zero(7), MatrixXd::Random(7, 14));
  const VectorXd lambda = volume_min_gain(Z7, StripMeasurement{Strip(VectorXd::Unit(7, 2), 0.1, 0.2), 0});
  EXPECT_TRUE(lambda.allFinite());
}

TEST(VolumeMin, EstimatorContainsTruth) {
  const LinearSystem sys = le13_known();
  std::mt19937 gen(2);
  std::uniform_real_distribution<double> U(-1, 1);
  for (bool vertex : {false, true}) {
    auto draw = [&](int n) {
      VectorXd w(n);
      for (int i = 0; i < n; ++i) w(i) = vertex ? (U(gen) < 0 ? -1 : 1) : U(gen);
      return w;
    };
    ZonotopicEstimator est(sys, Zonotope(VectorXd::Zero(2), 3 * MatrixXd::Identity(2, 2)), volume_min_gain);
    VectorXd x = 3 * draw(2);
    for (int k = 0; k < 60; ++k) {
      ASSERT_TRUE(est.step(sys.C() * x + sys.F() * draw(3), VectorXd(0)).contains(x, 0.0)) << k;
      x = sys.A() * x + sys.E() * draw(3);
    }
  }
}

TEST(ExactHull, ContainsTruthAndIsInsideEveryEstimator) {
  const LinearSystem sys = le13_known();
  const Zonotope X0(VectorXd::Zero(2), 3 * MatrixXd::Identity(2, 2));
  const PRadiusDesign d = design_pradius(sys);
  for (bool vertex : {false, true}) {
    std::mt19937 gen(vertex ? 5 : 6);
    std::uniform_real_distribution<double> U(-1, 1);
    auto draw = [&](int n) {
      VectorXd w(n);
      for (int i = 0; i < n; ++i) w(i) = vertex ? (U(gen) < 0 ? -1 : 1) : U(gen);
      return w;
    };
    const int N = 8;
    MatrixXd Y(N, 2), X(N, 2);
    VectorXd x = 3 * draw(2);
    for (int k = 0; k < N; ++k) {
      const VectorXd w = draw(3);
      X.row(k) = x.transpose();
      Y.row(k) = (sys.C() * x + sys.F() * w).transpose();
      x = sys.A() * x + sys.E() * w;  // the same ω_k drives y_k and x_{k+1}
    }
    const ExactHull hull = exact_hull(sys, X0, Y);
    const double tol = 1e-6;
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < 2; ++i) {
        EXPECT_LE(hull.lower(k, i), X(k, i) + tol);
        EXPECT_GE(hull.upper(k, i), X(k, i) - tol);
        EXPECT_LE(hull.lower(k, i), hull.upper(k, i) + tol);
      }
    for (const ZonotopeGain& rule : std::vector<ZonotopeGain>{segment_min_gain, volume_min_gain, pradius_gain(d)}) {
      ZonotopicEstimator est(sys, X0, rule);
      const ZonotopeTrajectory t = est.run(Y);
      for (int k = 0; k < N; ++k)
        for (int i = 0; i < 2; ++i) {
          EXPECT_LE(t.lower(k, i), hull.lower(k, i) + tol) << "k " << k;
          EXPECT_GE(t.upper(k, i), hull.upper(k, i) - tol) << "k " << k;
        }
    }
  }
}

TEST(ExactHull, RejectsIntervalAAndInconsistentData) {
  MatrixXd A(1, 1), C(1, 1), E(1, 2), F(1, 2), Arad(1, 1);
  A << 0.5;
  C << 1;
  E << 0.1, 0;
  F << 0, 0.1;
  Arad << 0.1;
  const Zonotope X0(VectorXd::Zero(1), MatrixXd::Identity(1, 1));
  EXPECT_THROW(exact_hull(LinearSystem(A, C, E, F, {}, {}, Arad), X0, MatrixXd::Zero(3, 1)), InvalidArgumentError);
  MatrixXd Y(2, 1);
  Y << 5.0, 0.0;  // |x_0| ≤ 1 and |noise| ≤ 0.1: y_0 = 5 is impossible
  EXPECT_THROW(exact_hull(LinearSystem(A, C, E, F), X0, Y), InfeasibleError);
}
