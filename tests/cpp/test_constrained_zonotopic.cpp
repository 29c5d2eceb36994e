// The constrained-zonotope estimators CZN-A and CZN-B (spec cora_observers.md §2.17, §2.18):
// CORA's saved hull, the library's exact consistent-set hull (LPs on the interior-point solver, an
// independent computation), containment under random and vertex disturbances, real data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "setbound/estimators/constrained_zonotopic/estimator.hpp"
#include "setbound/estimators/polytopic/exact_hull.hpp"
#include "test_helpers.hpp"

using setbound::ConstrainedZonotope;
using setbound::ConstrainedZonotopicEstimator;
using setbound::CZCorrection;
using setbound::CZOptions;
using setbound::CZReduction;
using setbound::LinearSystem;
using setbound::OnInconsistency;
using setbound::OutputStatus;
using setbound::Zonotope;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

/// The 2-state example of CORA's test_linearSysDT_observe_02_2dim.m (data:
/// ../shared/benchmarks/cora_linearSysDT_observe/alamo2005_2d_cora_unittest.json): W and V as
/// separate columns of the unit-box disturbance.
LinearSystem cora_2d() {
  MatrixXd A(2, 2), C(1, 2), E(2, 2), F(1, 2);
  A << 0, -0.5, 1, 1;
  C << -2, 1;
  E << -0.12, 0, 0.02, 0;
  F << 0, 0.2;
  return LinearSystem(A, C, E, F);
}

MatrixXd cora_2d_y() {
  const double y[20] = {0.0234670727523143, -4.328236471896203, -4.1973096745991345, -1.9546081148402012,
                        0.0983604258227819, 1.1666132024783362,  1.107317638717911,   0.4263920687095986,
                        -0.009268218571361, -0.3069527304071071, -0.1292621672249405, -0.0195793311301101,
                        -0.0751745657276915, 0.0774426557519688, 0.2618198630568284,  -0.0222441951122745,
                        0.0464232298590576, -0.1385809053684645, 0.0876767710448164,  -0.109466733731803};
  MatrixXd Y(20, 1);
  for (int k = 0; k < 20; ++k) Y(k, 0) = y[k];
  return Y;
}

MatrixXd randn(int r, int c, std::mt19937& rng, double scale = 1.0) {
  return setbound::testing::random_normal(r, c, rng, scale);
}

VectorXd unit_box(int m, std::mt19937& rng, bool vertex) { return setbound::testing::draw_disturbance(rng, m, vertex); }

struct Record {
  LinearSystem sys;
  Zonotope x0;
  MatrixXd X, Y;  // true states and outputs, row k
};

/// A stable-ish random system with E = [E_d, 0], F = [0, F_v] and a simulated record.
Record simulate(int n, int ny, int N, std::mt19937& rng, bool vertex) {
  MatrixXd A = randn(n, n, rng);
  A *= 0.9 / std::max(1.0, A.operatorNorm());
  const MatrixXd C = randn(ny, n, rng);
  MatrixXd E = MatrixXd::Zero(n, n + ny), F = MatrixXd::Zero(ny, n + ny);
  E.leftCols(n) = randn(n, n, rng, 0.05);
  F.rightCols(ny) = (0.02 + 0.1 * randn(ny, 1, rng).cwiseAbs().array()).matrix().asDiagonal();
  Record r{LinearSystem(A, C, E, F), Zonotope(VectorXd::Zero(n), 2.0 * MatrixXd::Identity(n, n)), MatrixXd(N, n), MatrixXd(N, ny)};
  VectorXd x = 2.0 * unit_box(n, rng, vertex);
  for (int k = 0; k < N; ++k) {
    const VectorXd w = unit_box(n + ny, rng, vertex);
    r.X.row(k) = x.transpose();
    r.Y.row(k) = (C * x + F * w).transpose();
    x = A * x + E * w;
  }
  return r;
}

bool inside(const VectorXd& x, const VectorXd& lo, const VectorXd& hi) {
  return ((x.array() >= lo.array()) && (x.array() <= hi.array())).all();
}

}  // namespace

TEST(ConstrainedZonotopic, ReproducesCorasSavedHullOnThe2dExample) {
  // CORA's saved final hull for CZN-A and CZN-B (test_linearSysDT_observe_02_2dim.m, order 20,
  // girard; no reduction triggers in 20 steps): lower (-0.1062309346120359, -0.2540037859300612),
  // upper (0.1411256696418789, 0.212784605551955). CORA's test tolerance is 1e-6.
  const VectorXd lo = (VectorXd(2) << -0.1062309346120359, -0.2540037859300612).finished();
  const VectorXd hi = (VectorXd(2) << 0.1411256696418789, 0.212784605551955).finished();
  for (CZCorrection method : {CZCorrection::ExactOutput, CZCorrection::WangStrips}) {
    CZOptions opt;
    opt.correction = method;
    opt.reduction = CZReduction::Cora;
    opt.order = 20;
    ConstrainedZonotopicEstimator est(cora_2d(), ConstrainedZonotope(Zonotope(VectorXd::Zero(2), 3.0 * MatrixXd::Identity(2, 2))), opt);
    const auto t = est.run(cora_2d_y());
    const VectorXd l = t.lower.row(19).transpose(), u = t.upper.row(19).transpose();
    EXPECT_LE((l - lo).cwiseAbs().maxCoeff(), 1e-6) << "method " << static_cast<int>(method) << " lower " << l.transpose();
    EXPECT_LE((u - hi).cwiseAbs().maxCoeff(), 1e-6) << "method " << static_cast<int>(method) << " upper " << u.transpose();
    EXPECT_TRUE((l.array() <= lo.array() + 1e-12).all());  // and it is an outer bound of CORA's (exact) one
    EXPECT_TRUE((u.array() >= hi.array() - 1e-12).all());
  }
}

TEST(ConstrainedZonotopic, WithoutReductionItIsTheExactConsistentSet) {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 6; ++trial) {
    const Record r = simulate(2 + trial % 2, 1 + trial % 2, 12, rng, trial % 2 == 0);
    const auto exact = setbound::exact_hull(r.sys, r.x0, r.Y);
    for (CZCorrection method : {CZCorrection::ExactOutput, CZCorrection::WangStrips}) {
      CZOptions opt;
      opt.correction = method;
      opt.reduction = CZReduction::None;
      ConstrainedZonotopicEstimator est(r.sys, ConstrainedZonotope(r.x0), opt);
      const auto t = est.run(r.Y);
      EXPECT_LE((t.lower - exact.lower).cwiseAbs().maxCoeff(), 1e-7) << "trial " << trial;
      EXPECT_LE((t.upper - exact.upper).cwiseAbs().maxCoeff(), 1e-7) << "trial " << trial;
    }
  }
}

TEST(ConstrainedZonotopic, ContainsTheTruthAtEveryStepWithReduction) {
  std::mt19937 rng(37);
  int steps = 0;
  // CORA's reduction keeps every constraint row (n_c grows by n_y per step), so the LPs grow
  // with the horizon: 30 steps per record keep this test at a few seconds.
  for (int trial = 0; trial < 16; ++trial) {
    const bool vertex = trial % 2 == 0;
    const Record r = simulate(2 + trial % 3, 1 + trial % 2, 30, rng, vertex);
    for (CZCorrection method : {CZCorrection::ExactOutput, CZCorrection::WangStrips}) {
      CZOptions opt;
      opt.correction = method;
      opt.reduction = CZReduction::Cora;
      opt.order = 2;  // a tight limit: the reduction runs at every step
      opt.technique = trial % 3 == 0 ? setbound::ZonotopeReduction::Pca : setbound::ZonotopeReduction::Girard;
      ConstrainedZonotopicEstimator est(r.sys, ConstrainedZonotope(r.x0), opt);
      const auto t = est.run(r.Y);
      for (int k = 0; k < r.Y.rows(); ++k, ++steps) {
        const VectorXd x = r.X.row(k).transpose();
        ASSERT_TRUE(inside(x, t.lower.row(k).transpose(), t.upper.row(k).transpose()))
            << "trial " << trial << " step " << k << (vertex ? " (vertex)" : " (random)");
        ASSERT_TRUE(t.sets[static_cast<size_t>(k)].contains(x)) << "trial " << trial << " step " << k;
        ASSERT_FALSE(t.checks[static_cast<size_t>(k)].flagged()) << "false alarm, trial " << trial << " step " << k;
      }
      // bounded memory: generators <= order·n + constraints after every reduction
      const auto& last = t.sets.back();
      EXPECT_LE(last.num_generators(), 2 * r.sys.nx() + last.num_constraints());
    }
  }
  EXPECT_GE(steps, 960);
}

TEST(ConstrainedZonotopic, BoundedModeContainsTheTruthWithBoundedSize) {
  std::mt19937 rng(43);
  int steps = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const bool vertex = trial % 2 == 0;
    const Record r = simulate(2 + trial % 3, 1 + trial % 2, 120, rng, vertex);
    CZOptions opt;  // the default: Limits (4 n_x rows, 20 n_x + 4 n_x generators)
    opt.correction = trial % 4 < 2 ? CZCorrection::ExactOutput : CZCorrection::WangStrips;
    ConstrainedZonotopicEstimator est(r.sys, ConstrainedZonotope(r.x0), opt);
    const auto t = est.run(r.Y);
    const Eigen::Index n = r.sys.nx();
    for (int k = 0; k < r.Y.rows(); ++k, ++steps) {
      const VectorXd x = r.X.row(k).transpose();
      ASSERT_TRUE(inside(x, t.lower.row(k).transpose(), t.upper.row(k).transpose()))
          << "trial " << trial << " step " << k << (vertex ? " (vertex)" : " (random)");
      ASSERT_FALSE(t.checks[static_cast<size_t>(k)].flagged()) << "false alarm, trial " << trial << " step " << k;
      const auto& Z = t.sets[static_cast<size_t>(k)];
      ASSERT_LE(Z.num_constraints(), 4 * n);
      ASSERT_LE(Z.num_generators(), 24 * n);
    }
  }
  EXPECT_GE(steps, 1400);
}

TEST(ConstrainedZonotopic, MissingSamplesAndAGlitch) {
  std::mt19937 rng(41);
  const Record r = simulate(3, 2, 45, rng, true);
  MatrixXd Y = r.Y;
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < Y.rows(); ++k)
    for (int i = 0; i < Y.cols(); ++i)
      if (u(rng) < 0.2) Y(k, i) = std::numeric_limits<double>::quiet_NaN();
  Y(30, 0) = r.Y(30, 0) + 5.0;  // an impossible reading
  ConstrainedZonotopicEstimator est(r.sys, ConstrainedZonotope(r.x0), CZOptions{});
  const auto t = est.run(Y);
  for (int k = 0; k < Y.rows(); ++k) {
    ASSERT_TRUE(inside(r.X.row(k).transpose(), t.lower.row(k).transpose(), t.upper.row(k).transpose())) << "step " << k;
    for (int i = 0; i < Y.cols(); ++i) {
      const auto s = t.checks[static_cast<size_t>(k)].status[static_cast<size_t>(i)];
      if (std::isnan(Y(k, i))) EXPECT_EQ(s, OutputStatus::Missing);
      else if (k == 30 && i == 0) EXPECT_EQ(s, OutputStatus::Inconsistent);
      else EXPECT_EQ(s, OutputStatus::Used) << "false alarm at step " << k << " output " << i;
    }
  }
  EXPECT_GT(t.checks[30].margin(0), 1.0);  // several noise bounds outside
  // Raise: the estimator throws at step 30 and is left as it was.
  CZOptions raise;
  raise.on_inconsistency = OnInconsistency::Raise;
  ConstrainedZonotopicEstimator r2(r.sys, ConstrainedZonotope(r.x0), raise);
  for (int k = 0; k < 30; ++k) r2.update(Y.row(k).transpose(), VectorXd(0));
  const VectorXd lo = r2.current_lower();
  EXPECT_THROW(r2.update(Y.row(30).transpose(), VectorXd(0)), setbound::InconsistentMeasurementError);
  EXPECT_EQ(r2.steps_taken(), 30);
  EXPECT_EQ(r2.current_lower(), lo);
  // run() twice gives the same result (it starts from the initial set).
  const auto again = est.run(Y);
  EXPECT_EQ(again.lower, t.lower);
  EXPECT_EQ(again.upper, t.upper);
}

// The optimistic screening (estimator.ipp, update): readings are used at once and screened one by
// one only when the corrected set is not found feasible. Checked against the exact screening done
// here on the prediction (certified support values of C_i X): the same status for every reading,
// the exact margin for a step that was screened, and otherwise a margin that is an upper bound of
// the exact one (the hull LPs' points span part of C_i X) and <= 0 (the reading is consistent).
TEST(ConstrainedZonotopic, OptimisticScreeningAgreesWithTheExactOne) {
  int screened_steps = 0, optimistic_steps = 0;
  for (int seed = 0; seed < 6; ++seed) {
    std::mt19937 rng(900 + seed);
    const int n = 2 + seed % 3, ny = 1 + seed % 2;
    const Record r = simulate(n, ny, 60, rng, seed % 2 == 0);
    for (int mode = 0; mode < 3; ++mode) {
      CZOptions o;
      o.correction = mode == 1 ? CZCorrection::WangStrips : CZCorrection::ExactOutput;
      o.reduction = mode == 2 ? CZReduction::None : CZReduction::Limits;
      ConstrainedZonotopicEstimator est(r.sys, ConstrainedZonotope(r.x0), o);
      const int N = mode == 2 ? 15 : 60;  // without reduction the set grows every step
      for (int k = 0; k < N; ++k) {
        const ConstrainedZonotope X = est.prediction();
        const setbound::BoundingBox out = X.image_bounds(r.sys.C());
        VectorXd y = r.Y.row(k).transpose();
        // Glitches: every 7th step one reading lies 0.3 to 3 noise bounds outside C_i X.
        const bool glitch = k % 7 == 3;
        if (glitch) {
          const int i = k % ny;
          const double sig = r.sys.F().row(i).cwiseAbs().sum();
          y(i) = out.hi(i) + sig * (1.3 + 0.3 * (k % 10));
        }
        est.update(y, VectorXd(0));
        const auto& chk = est.last_check();
        bool any_flag = false;
        VectorXd exact_margin(ny);
        for (int i = 0; i < ny; ++i) {
          const double sig = r.sys.F().row(i).cwiseAbs().sum();
          const double center = 0.5 * out.lo(i) + 0.5 * out.hi(i), radius = 0.5 * out.hi(i) - 0.5 * out.lo(i);
          const double exact = (std::abs(y(i) - center) - radius - sig) / sig;
          exact_margin(i) = exact;
          const bool bad = exact > 1e-9;
          any_flag = any_flag || bad;
          ASSERT_EQ(chk.status[static_cast<size_t>(i)], bad ? OutputStatus::Inconsistent : OutputStatus::Used)
              << "seed " << seed << " mode " << mode << " step " << k << " output " << i << " exact margin " << exact;
        }
        for (int i = 0; i < ny; ++i) {
          const double exact = exact_margin(i);
          if (any_flag) {
            EXPECT_NEAR(chk.margin(i), exact, 1e-6 * (1.0 + std::abs(exact))) << "screened step " << k;
          } else {
            EXPECT_GE(chk.margin(i), exact - 1e-6) << "seed " << seed << " mode " << mode << " step " << k;
            EXPECT_LE(chk.margin(i), 1e-6) << "seed " << seed << " mode " << mode << " step " << k;
          }
        }
        (any_flag ? screened_steps : optimistic_steps) += 1;
        ASSERT_TRUE(inside(r.X.row(k).transpose(), est.current_lower(), est.current_upper())) << "step " << k;
      }
    }
  }
  EXPECT_GT(screened_steps, 20);
  EXPECT_GT(optimistic_steps, 200);
}

TEST(ConstrainedZonotopic, BadInputIsNamed) {
  const LinearSystem s = cora_2d();
  const ConstrainedZonotope x0(Zonotope(VectorXd::Zero(2), MatrixXd::Identity(2, 2)));
  CZOptions bad;
  bad.order = 0.5;
  setbound::testing::expect_error_naming<setbound::InvalidArgumentError>([&] { ConstrainedZonotopicEstimator(s, x0, bad); }, "order");
  setbound::testing::expect_error_naming<setbound::DimensionError>(
      [&] { ConstrainedZonotopicEstimator(s, ConstrainedZonotope(Zonotope(VectorXd::Zero(3), MatrixXd::Identity(3, 3)))); }, "x0");
  ConstrainedZonotopicEstimator est(s, x0);
  setbound::testing::expect_error_naming<setbound::DimensionError>([&] { est.update(VectorXd::Zero(2), VectorXd(0)); }, "y");
  setbound::testing::expect_error_naming<setbound::NotFiniteError>(
      [&] { est.update(VectorXd::Constant(1, INFINITY), VectorXd(0)); }, "y");
  setbound::testing::expect_error_naming<setbound::DimensionError>([&] { est.run(MatrixXd::Zero(3, 2)); }, "Y");
  EXPECT_EQ(est.steps_taken(), 0);
}

TEST(ConstrainedZonotopic, RoundingBoxDoesNotWrapOverLongRuns) {
  // A rotation by 30° (ρ(A) = 0.999) has ρ(|A|) = 1.37: a rounding box kept apart and mapped by
  // |A| at every step grew by that factor per step (from ~1e-16 to a useless hull after a few
  // hundred steps, seen on vehicle6 over 10 000 steps). reduce_limits turns it into generators.
  const double t = std::acos(-1.0) / 6.0;
  MatrixXd A(2, 2), C(1, 2), E = MatrixXd::Zero(2, 3), F = MatrixXd::Zero(1, 3);
  A << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  A *= 0.999;
  C << 1, 0;
  E(0, 0) = 0.02;
  E(1, 1) = 0.02;
  F(0, 2) = 0.1;
  const LinearSystem sys(A, C, E, F);
  std::mt19937 rng(61);
  ConstrainedZonotopicEstimator est(sys, ConstrainedZonotope(Zonotope(VectorXd::Zero(2), MatrixXd::Identity(2, 2))));
  VectorXd x = unit_box(2, rng, false);
  // The hull's width stays bounded too. Before CZN-A's new rows were written with the
  // least-squares gain (2026-11-28) it grew from the generators: 0.8 at steps 20–60, 2.7 at step
  // 100 (sum over both coordinates). Now about 0.35–0.65 over 600 steps; segment minimisation
  // settles at 1.09 on this system.
  double widest = 0.0;
  for (int k = 0; k < 600; ++k) {
    const VectorXd w = unit_box(3, rng, k % 2 == 0);
    est.update(C * x + F * w, VectorXd(0));
    ASSERT_TRUE(inside(x, est.current_lower(), est.current_upper())) << "step " << k;
    if (k >= 20) widest = std::max(widest, (est.current_upper() - est.current_lower()).sum());
    // The reduction absorbs the rounding box into its basis of generators, leaving only that
    // absorption's own residual: a few ulps, at every step (no growth from step to step).
    const auto& X = est.current_set();
    const double xsize = (X.center().cwiseAbs() + X.generators().cwiseAbs().rowwise().sum()).maxCoeff();
    ASSERT_LE(X.rounding_radius().maxCoeff(), 1e-15 * xsize) << "step " << k;
    // One step's rounding of the prediction: a few ulps of its magnitude |c| + |G|·1.
    const auto& P = est.prediction();
    const double size = (P.center().cwiseAbs() + P.generators().cwiseAbs().rowwise().sum()).maxCoeff();
    ASSERT_LE(P.rounding_radius().maxCoeff(), 1e-13 * size) << "step " << k;
    x = A * x + E * unit_box(3, rng, k % 3 == 0);
  }
  EXPECT_LT(widest, 1.0);
}
