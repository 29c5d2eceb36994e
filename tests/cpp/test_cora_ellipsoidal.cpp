// CORA's ESO-A / ESO-B (estimators/ellipsoidal/bounding_ellipsoid.hpp, spec cora_observers.md
// §2.13, §2.14): the default convention contains the true state on seeded random systems with
// random and vertex disturbances, the correction shrinks the set, the CORA convention follows its
// recursion by hand on a scalar case, saved states replay bit for bit, bad input is refused with
// the argument named (C++ and C ABI).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "setbound/estimators/ellipsoidal/bounding_ellipsoid.hpp"
#include "setbound/estimators/interval/cora_interval_observer.hpp"
#include "c_api_common.hpp"
#include "test_helpers.hpp"

using setbound::BoundingEllipsoidEstimator;
using setbound::BoundingEllipsoidOptions;
using setbound::BoundingRule;
using setbound::Convention;
using setbound::LinearSystem;
using setbound::testing::expect_error_naming;

namespace {

Eigen::MatrixXd rnd(std::mt19937& g, Eigen::Index r, Eigen::Index c, double s = 1.0) {
  std::normal_distribution<double> N(0.0, 1.0);
  Eigen::MatrixXd M(r, c);
  for (Eigen::Index j = 0; j < c; ++j)
    for (Eigen::Index i = 0; i < r; ++i) M(i, j) = s * N(g);
  return M;
}

struct Case {
  LinearSystem sys;
  Eigen::VectorXd x0c;
  Eigen::MatrixXd Q0;
};

// A random system with a spectral radius around 0.95 and a box disturbance ω (E, F separate).
Case random_case(unsigned seed) {
  std::mt19937 g(seed);
  std::uniform_int_distribution<int> dn(1, 4), dp(1, 3);
  const int n = dn(g), p = dp(g), nw = n, nv = p;
  Eigen::MatrixXd A = rnd(g, n, n);
  const double rho = A.eigenvalues().cwiseAbs().maxCoeff();
  A *= (0.5 + 0.6 * std::uniform_real_distribution<double>(0, 1)(g)) / std::max(rho, 1e-9);
  const Eigen::MatrixXd C = rnd(g, p, n);
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, nw + nv), F = Eigen::MatrixXd::Zero(p, nw + nv);
  E.leftCols(nw) = rnd(g, n, nw, 0.05);
  F.rightCols(nv) = rnd(g, p, nv, 0.1);
  const Eigen::MatrixXd B = rnd(g, n, 1);
  Eigen::MatrixXd G0 = rnd(g, n, n);
  return {LinearSystem(A, C, E, F, B), rnd(g, n, 1), G0 * G0.transpose() + Eigen::MatrixXd::Identity(n, n)};
}

// Runs the estimator on a trajectory started inside x0 and counts the steps whose set misses the truth.
int violations(const Case& c, BoundingRule rule, bool vertex, unsigned seed, int steps = 60) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const Eigen::Index n = c.sys.nx(), m = c.sys.nw();
  BoundingEllipsoidOptions opt;
  opt.rule = rule;
  opt.step_cap = 0.5;
  BoundingEllipsoidEstimator est(c.sys, {}, {}, c.x0c, c.Q0, 1.0, opt);
  // x0 on the boundary of the initial ellipsoid (direction random)
  Eigen::VectorXd d = rnd(g, n, 1);
  Eigen::LLT<Eigen::MatrixXd> l(c.Q0);
  Eigen::VectorXd x = c.x0c + (l.matrixL() * d) / d.norm();
  int bad = 0;
  for (int k = 0; k < steps; ++k) {
    Eigen::VectorXd w(m), u(1);
    for (Eigen::Index i = 0; i < m; ++i) w(i) = vertex ? (U(g) < 0 ? -1.0 : 1.0) : U(g);
    u(0) = std::sin(0.3 * k);
    const Eigen::VectorXd y = c.sys.C() * x + c.sys.F() * w;
    est.step(y, u);
    if (!est.ellipsoid().contains(x, 0.0)) ++bad;
    const auto box = est.bounding_box();
    if (((x - box.lo).array() < 0).any() || ((box.hi - x).array() < 0).any()) ++bad;
    x = c.sys.A() * x + c.sys.B() * u + c.sys.E() * w;
  }
  return bad;
}

}  // namespace

TEST(BoundingEllipsoid, ContainsTheTruthOnRandomSystemsWithRandomAndVertexDisturbances) {
  for (unsigned seed = 0; seed < 24; ++seed) {
    const Case c = random_case(seed);
    for (BoundingRule rule : {BoundingRule::Gollamudi, BoundingRule::Liu})
      for (bool vertex : {false, true})
        EXPECT_EQ(violations(c, rule, vertex, 1000 + seed), 0)
            << "seed " << seed << " rule " << static_cast<int>(rule) << " vertex " << vertex;
  }
}

TEST(BoundingEllipsoid, MeasurementsShrinkTheSetAndLambdaIsReported) {
  const Case c = random_case(3);
  BoundingEllipsoidOptions opt;
  opt.rule = BoundingRule::Liu;
  BoundingEllipsoidEstimator est(c.sys, {}, {}, c.x0c, 100.0 * c.Q0, 1.0, opt);
  const double v0 = est.ellipsoid().log_volume();
  Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  // An innovation away from zero (Gollamudi's rule updates only when σ² + δᵀδ exceeds the noise level).
  est.step(c.sys.C() * c.x0c + Eigen::VectorXd::Constant(c.sys.ny(), 3.0), u);
  EXPECT_GT(est.last_lambda(), 0.0);
  EXPECT_LT(est.ellipsoid().log_volume(), v0);
  EXPECT_EQ(est.steps(), 1);
}

TEST(BoundingEllipsoid, CoraConventionFollowsItsRecursionByHandOnAScalarSystem) {
  // x+ = 0.5 x + w, y = x + v, Q_W = 0.01, Q_V = 0.04, x0 = E(0, 1): CORA's first ESO-B step
  // with y = 1 (σ² = 0.3, V̄ = 5; σ² + δᵀδ > 1): g = 25, β = 0.7, λ = (1 − √(g/ω))/(1 − g).
  LinearSystem sys((Eigen::MatrixXd(1, 1) << 0.5).finished(), Eigen::MatrixXd::Identity(1, 1),
                   Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 1));
  BoundingEllipsoidOptions opt;
  opt.rule = BoundingRule::Liu;
  opt.convention = Convention::Cora;
  BoundingEllipsoidEstimator est(sys, Eigen::MatrixXd::Constant(1, 1, 0.01), Eigen::MatrixXd::Constant(1, 1, 0.04),
                                 Eigen::VectorXd::Zero(1), Eigen::MatrixXd::Identity(1, 1), 1.0, opt);
  est.step(Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd());
  const double s = 0.3, dd = 1.0, g = 25.0, beta = (1 - s) / dd, omega = 1 + beta * (g - 1);
  const double lam = (1 - std::sqrt(g / omega)) / (1 - g);
  const double Qt = 0.04 / lam + 1.0 / (1 - lam), K = 1.0 / (1 - lam) / Qt;
  EXPECT_NEAR(est.last_lambda(), lam, 1e-15);
  EXPECT_GT(lam, 0.0);
  EXPECT_NEAR(est.center()(0), K * 1.0, 1e-15);
  EXPECT_NEAR(est.shape()(0, 0), (1 - lam) * (1 - K), 1e-15);
}

TEST(BoundingEllipsoid, SavedStatesReplayBitForBit) {
  const Case c = random_case(5);
  BoundingEllipsoidEstimator a(c.sys, {}, {}, c.x0c, c.Q0, 1.0);
  std::mt19937 g(9);
  std::vector<Eigen::VectorXd> ys;
  for (int k = 0; k < 8; ++k) ys.push_back(rnd(g, c.sys.ny(), 1, 0.2));
  const Eigen::VectorXd u = Eigen::VectorXd::Ones(1);
  for (int k = 0; k < 4; ++k) a.step(ys[k], u);
  const auto state = a.save_state();
  BoundingEllipsoidEstimator b(c.sys, {}, {}, c.x0c, c.Q0, 1.0);
  b.restore_state(state);
  for (int k = 4; k < 8; ++k) {
    a.step(ys[k], u);
    b.step(ys[k], u);
  }
  EXPECT_TRUE(setbound::testing::same_bits(a.save_state(), b.save_state()));
  BoundingEllipsoidOptions liu;
  liu.rule = BoundingRule::Liu;
  BoundingEllipsoidEstimator other(c.sys, {}, {}, c.x0c, c.Q0, 1.0, liu);
  expect_error_naming<setbound::InvalidArgumentError>([&] { other.restore_state(state); }, "state");
}

// Every saved state restores, at every step, for both rules and conventions: the shapes must be
// exactly symmetric. They were not when symmetrised by `M = 0.5 * (M + M.transpose())` (Eigen
// aliasing), and a state saved mid-run was refused by restore_state (found by test_threads.py).
TEST(BoundingEllipsoid, EveryStateSavedMidRunRestores) {
  for (unsigned seed = 0; seed < 12; ++seed) {
    const Case c = random_case(seed);
    for (const BoundingRule rule : {BoundingRule::Gollamudi, BoundingRule::Liu})
      for (const Convention conv : {Convention::Setbound, Convention::Cora}) {
        BoundingEllipsoidOptions opt;
        opt.rule = rule;
        opt.convention = conv;
        opt.step_cap = 0.5;
        BoundingEllipsoidEstimator a(c.sys, {}, {}, c.x0c, c.Q0, 1.0, opt);
        BoundingEllipsoidEstimator b(c.sys, {}, {}, c.x0c, c.Q0, 1.0, opt);
        std::mt19937 g(seed + 100);
        for (int k = 0; k < 25; ++k) {
          const Eigen::VectorXd y = rnd(g, c.sys.ny(), 1, 0.2), u = Eigen::VectorXd::Constant(1, std::sin(0.3 * k));
          if (conv == Convention::Cora) {  // CORA's unguarded recursion may break down: an error, not NaN
            try {
              a.step(y, u);
            } catch (const setbound::NumericalError&) {
              break;
            }
          } else {
            a.step(y, u);
          }
          const auto state = a.save_state();
          ASSERT_NO_THROW(b.restore_state(state)) << "seed " << seed << ", step " << k;
          EXPECT_TRUE(setbound::testing::same_bits(b.save_state(), state));
        }
      }
  }
}

TEST(BoundingEllipsoid, BadInputIsRefusedWithTheArgumentNamed) {
  const Case c = random_case(1);
  const Eigen::Index n = c.sys.nx(), p = c.sys.ny();
  using setbound::DimensionError;
  using setbound::InvalidArgumentError;
  using setbound::NotFiniteError;
  using setbound::NotPositiveDefiniteError;
  expect_error_naming<DimensionError>([&] { BoundingEllipsoidEstimator(c.sys, {}, {}, Eigen::VectorXd::Zero(n + 1), c.Q0, 1.0); }, "x0");
  expect_error_naming<NotPositiveDefiniteError>(
      [&] { BoundingEllipsoidEstimator(c.sys, {}, {}, c.x0c, -c.Q0, 1.0); }, "Q0");
  expect_error_naming<NotPositiveDefiniteError>(
      [&] { BoundingEllipsoidEstimator(c.sys, -Eigen::MatrixXd::Identity(n, n), {}, c.x0c, c.Q0, 1.0); }, "QW");
  BoundingEllipsoidOptions liu;
  liu.rule = BoundingRule::Liu;
  expect_error_naming<NotPositiveDefiniteError>(
      [&] { BoundingEllipsoidEstimator(c.sys, {}, Eigen::MatrixXd::Zero(p, p), c.x0c, c.Q0, 1.0, liu); }, "QV");
  BoundingEllipsoidOptions cap;
  cap.step_cap = 1.0;
  expect_error_naming<InvalidArgumentError>([&] { BoundingEllipsoidEstimator(c.sys, {}, {}, c.x0c, c.Q0, 1.0, cap); },
                                            "step_cap");
  BoundingEllipsoidEstimator est(c.sys, {}, {}, c.x0c, c.Q0, 1.0);
  const auto before = est.save_state();
  Eigen::VectorXd y = Eigen::VectorXd::Zero(p);
  y(0) = std::nan("");
  expect_error_naming<NotFiniteError>([&] { est.step(y, Eigen::VectorXd::Zero(1)); }, "y");
  expect_error_naming<DimensionError>([&] { est.step(Eigen::VectorXd::Zero(p + 1), Eigen::VectorXd::Zero(1)); }, "y");
  expect_error_naming<DimensionError>([&] { est.step(Eigen::VectorXd::Zero(p), Eigen::VectorXd::Zero(2)); }, "u");
  EXPECT_TRUE(setbound::testing::same_bits(est.save_state(), before));
}

TEST(BoundingEllipsoid, CApiCreatesStepsAndRefusesBadInput) {
  const Case c = random_case(2);
  const int n = static_cast<int>(c.sys.nx()), p = static_cast<int>(c.sys.ny());
  using RM = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RM A = c.sys.A(), B = c.sys.B(), C = c.sys.C(), E = c.sys.E(), F = c.sys.F();
  sb_linear_system* sysp = nullptr;
  ASSERT_EQ(sb_linear_system_create(n, p, 1, static_cast<int>(c.sys.nw()), A.data(), B.data(), C.data(), nullptr,
                                    E.data(), F.data(), nullptr, &sysp),
            SB_OK)
      << sb_last_error();
  RM Q0 = c.Q0;
  sb_bounding_ellipsoid* h = nullptr;
  ASSERT_EQ(sb_bounding_ellipsoid_create(sysp, nullptr, nullptr, c.x0c.data(), Q0.data(), 1.0, SB_BE_X0_SHAPE,
                                         SB_BE_LIU, SB_CONVENTION_SETBOUND, 1e-4, &h),
            SB_OK)
      << sb_last_error();
  std::vector<double> y(p, 0.0), u(1, 0.0), lo(n), hi(n), P(n * n), cc(n);
  double rho = 0;
  EXPECT_EQ(sb_bounding_ellipsoid_step(h, y.data(), u.data(), P.data(), cc.data(), &rho, lo.data(), hi.data()), SB_OK);
  for (int i = 0; i < n; ++i) EXPECT_LE(lo[i], hi[i]);
  int steps = 0;
  EXPECT_EQ(sb_bounding_ellipsoid_info(h, nullptr, nullptr, &steps), SB_OK);
  EXPECT_EQ(steps, 1);
  EXPECT_EQ(sb_bounding_ellipsoid_step(h, nullptr, u.data(), nullptr, nullptr, nullptr, nullptr, nullptr),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("y"), std::string::npos);
  sb_bounding_ellipsoid_free(h);
  sb_bounding_ellipsoid* bad = nullptr;
  EXPECT_EQ(sb_bounding_ellipsoid_create(sysp, nullptr, nullptr, c.x0c.data(), Q0.data(), 1.0, SB_BE_X0_SHAPE, 7,
                                         SB_CONVENTION_SETBOUND, 1e-4, &bad),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("rule"), std::string::npos);
  EXPECT_EQ(sb_bounding_ellipsoid_create(sysp, nullptr, nullptr, c.x0c.data(), Q0.data(), 1.0, 5, SB_BE_LIU,
                                         SB_CONVENTION_SETBOUND, 1e-4, &bad),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_bounding_ellipsoid_create(sysp, nullptr, nullptr, c.x0c.data(), Q0.data(), 1.0, SB_BE_X0_SHAPE,
                                         SB_BE_LIU, 3, 1e-4, &bad),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("convention"), std::string::npos);
  EXPECT_EQ(bad, nullptr);
  sb_linear_system_free(sysp);
}

TEST(CoraIntervalObserver, FollowsCorasLaggedRecursionByHand) {
  // x+ = 0.5 x + 0.1 w, y = x + 0.2 v, R0 = 1 + [-1, 1], L = 0.25; A_o = 0.25.
  LinearSystem sys((Eigen::MatrixXd(1, 1) << 0.5).finished(), Eigen::MatrixXd::Identity(1, 1),
                   (Eigen::MatrixXd(1, 2) << 0.1, 0.0).finished(), (Eigen::MatrixXd(1, 2) << 0.0, 0.2).finished());
  setbound::CoraIntervalObserver obs(sys, Eigen::VectorXd::Ones(1), Eigen::MatrixXd::Ones(1, 1),
                                     Eigen::MatrixXd::Constant(1, 1, 0.25));
  const Eigen::VectorXd u(0);
  obs.step(Eigen::VectorXd::Constant(1, 2.0), u);  // row 0: □R0 = [0, 2]
  EXPECT_DOUBLE_EQ(obs.box().lo(0), 0.0);
  EXPECT_DOUBLE_EQ(obs.box().hi(0), 2.0);
  obs.step(Eigen::VectorXd::Constant(1, 0.0), u);  // row 1: c0 + □R0 = 1 + [0, 2] (centre twice)
  EXPECT_DOUBLE_EQ(obs.box().lo(0), 1.0);
  EXPECT_DOUBLE_EQ(obs.box().hi(0), 3.0);
  // the update used y_0 = 2: x̂ = 0.5 + 0.25 (2 − 1) = 0.75; X = 0.25 R0 = 0.25 + 0.25[−1, 1];
  // S = □D = [−(0.1 + 0.05), 0.15]. Row 2 = 0.75 + 0.25 + [−0.25 − 0.15, 0.25 + 0.15].
  obs.step(Eigen::VectorXd::Constant(1, 0.0), u);
  EXPECT_NEAR(obs.box().lo(0), 1.0 - 0.4, 1e-15);
  EXPECT_NEAR(obs.box().hi(0), 1.0 + 0.4, 1e-15);
  const auto state = obs.save_state();
  setbound::CoraIntervalObserver twin(sys, Eigen::VectorXd::Ones(1), Eigen::MatrixXd::Ones(1, 1),
                                      Eigen::MatrixXd::Constant(1, 1, 0.25));
  twin.restore_state(state);
  obs.step(Eigen::VectorXd::Constant(1, 0.3), u);
  twin.step(Eigen::VectorXd::Constant(1, 0.3), u);
  EXPECT_TRUE(setbound::testing::same_bits(obs.save_state(), twin.save_state()));
  expect_error_naming<setbound::DimensionError>(
      [&] { setbound::CoraIntervalObserver(sys, Eigen::VectorXd::Ones(1), Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(2, 1)); },
      "L");
  expect_error_naming<setbound::NotFiniteError>([&] { obs.step(Eigen::VectorXd::Constant(1, NAN), u); }, "y");
}
