// Missing and impossible readings (issue 24, estimators/measurement_check.hpp) in the zonotopic
// family, through C++ and the C ABI: NaN outputs are skipped and the true state stays inside;
// a reading outside the predicted output set is never used and is handled by the policy (Flag,
// Raise, Reset); fault-free data never raise an alarm; run() starts from the initial set.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "c_api_common.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/estimators/polytopic/exact_hull.hpp"
#include "setbound/estimators/measurement_check.hpp"
#include "setbound/estimators/zonotopic/volume_min.hpp"
#include "setbound/estimators/zonotopic/gain_estimator.hpp"
#include "measurement_test_data.hpp"
#include "test_helpers.hpp"

using namespace setbound;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

LinearSystem le13() { return setbound::testing::le13_known_a(); }

using setbound::testing::Record;

// jump_at >= 0: the state jumps by `jump` before that step (a violation of the model).
Record simulate(const LinearSystem& s, const Eigen::VectorXd& x0, int N, bool vertex, unsigned seed,
                int jump_at = -1, const Eigen::Vector2d& jump = Eigen::Vector2d::Zero()) {
  return setbound::testing::simulate_record(s, x0, N, vertex, seed, jump_at, jump);
}

Zonotope box3() { return Zonotope(Eigen::Vector2d::Zero(), 3.0 * Eigen::Matrix2d::Identity()); }

}  // namespace

TEST(MeasurementCheck, TestOutputIsOneSidedAndScaled) {
  // Inside, on the boundary and just beyond the rounding bound.
  EXPECT_FALSE(test_output(1.0, 0.0, 0.5, 0.5, 1.0, 4).inconsistent);
  EXPECT_FALSE(test_output(1.0 + 1e-15, 0.0, 0.5, 0.5, 1.0, 4).inconsistent);  // rounding, not a fault
  EXPECT_FALSE(test_output(1.0 + 1e-13, 0.0, 0.5, 0.5, 1.0, 4).inconsistent);  // within kReadingSlack
  EXPECT_TRUE(test_output(1.0 + 1e-9, 0.0, 0.5, 0.5, 1.0, 4).inconsistent);    // a fault, however small
  const OutputTest far = test_output(3.0, 0.0, 0.5, 0.5, 1.0, 4);
  EXPECT_TRUE(far.inconsistent);
  EXPECT_DOUBLE_EQ(far.margin, (3.0 - 1.0) / 0.5);  // in noise bounds
  EXPECT_DOUBLE_EQ(test_output(0.0, 0.0, 0.0, 0.5, 0.0, 4).margin, -1.0);  // centre of a point
  EXPECT_DOUBLE_EQ(test_output(2.0, 0.0, 1.0, 0.0, 1.0, 4).margin, 1.0);  // no noise: absolute
}

TEST(MeasurementCheck, MissingOutputsKeepTheTruthInsideAndContainTheExactHull) {
  const LinearSystem s = le13();
  for (bool vertex : {false, true})
    for (unsigned seed = 1; seed <= 4; ++seed) {
      Record r = simulate(s, Eigen::Vector2d(1.0, -1.0), 60, vertex, seed);
      std::mt19937 gen(100 + seed);
      std::bernoulli_distribution drop(0.2);
      int dropped = 0;
      for (Eigen::Index k = 0; k < r.Y.rows(); ++k)
        for (Eigen::Index i = 0; i < r.Y.cols(); ++i)
          if (drop(gen)) {
            r.Y(k, i) = kNaN;
            ++dropped;
          }
      ASSERT_GT(dropped, 10);
      ZonotopicEstimator est(s, box3(), segment_min_gain);
      const ZonotopeTrajectory t = est.run(r.Y);
      // The exact hull (2 n_x LPs per step over all past disturbances) is costly, above all
      // under the sanitizers: compared on the first 25 steps of one record per noise kind.
      const Eigen::Index nh = seed == 1 ? 25 : 0;
      const ExactHull hull = exact_hull(s, box3(), r.Y.topRows(nh));
      for (Eigen::Index k = 0; k < r.Y.rows(); ++k) {
        EXPECT_TRUE(t.sets[static_cast<std::size_t>(k)].contains(r.X.row(k).transpose(), 0.0))
            << "vertex " << vertex << " seed " << seed << " step " << k;
        EXPECT_FALSE(t.checks[static_cast<std::size_t>(k)].flagged());
        for (Eigen::Index i = 0; i < r.Y.cols(); ++i) {
          const OutputStatus st = t.checks[static_cast<std::size_t>(k)].status[static_cast<std::size_t>(i)];
          EXPECT_EQ(st, std::isnan(r.Y(k, i)) ? OutputStatus::Missing : OutputStatus::Used);
        }
        // The estimator's hull contains the exact hull of the data it used (the LPs of the exact
        // hull are solved to about 1e-9).
        for (Eigen::Index j = 0; k < nh && j < s.nx(); ++j) {
          EXPECT_LE(t.lower(k, j), hull.lower(k, j) + 1e-6);
          EXPECT_GE(t.upper(k, j), hull.upper(k, j) - 1e-6);
        }
      }
    }
}

TEST(MeasurementCheck, AllMissingIsAPurePrediction) {
  const LinearSystem s = le13();
  ZonotopicEstimator est(s, box3(), segment_min_gain);
  const Eigen::VectorXd none = Eigen::VectorXd::Constant(2, kNaN);
  const Zonotope predicted = est.prediction();
  est.update(none, Eigen::VectorXd(0));
  const Zonotope X = est.current_set();
  // Nothing was used: the set for x_0 is x_0's prior itself.
  EXPECT_TRUE(X.center().isApprox(predicted.center()));
  EXPECT_NEAR(X.interval_hull().hi(0), 3.0, 1e-12);
  EXPECT_EQ(est.last_check().status[0], OutputStatus::Missing);
  EXPECT_TRUE(std::isnan(est.last_check().margin(0)));
}

TEST(MeasurementCheck, FaultFreeDataNeverRaiseAnAlarm) {
  // Vertex disturbances put the readings on the boundary of the predicted output sets: the
  // case where a test without a rounding allowance would report false alarms.
  const LinearSystem s = le13();
  long steps = 0;
  for (unsigned seed = 1; seed <= 40; ++seed)
    for (bool volume : {false, true}) {
      const Record r = simulate(s, Eigen::Vector2d(0.5, 0.5), 100, true, seed);
      ZonotopicOptions opt;
      opt.on_inconsistency = OnInconsistency::Raise;  // an alarm would throw
      ZonotopicEstimator est(s, box3(), volume ? ZonotopeGain(volume_min_gain) : ZonotopeGain(segment_min_gain), opt);
      ASSERT_NO_THROW(est.run(r.Y)) << "seed " << seed;
      steps += r.Y.rows();
    }
  EXPECT_EQ(steps, 8000);
}

TEST(MeasurementCheck, GlitchIsFlaggedAndTheTruthStaysInside) {
  const LinearSystem s = le13();
  for (bool vertex : {false, true}) {
    Record r = simulate(s, Eigen::Vector2d(1.0, 1.0), 50, vertex, 7);
    for (double glitch : {5.0, 1e3, 1e12}) {
      Eigen::MatrixXd Y = r.Y;
      Y(20, 0) += glitch;
      ZonotopicEstimator est(s, box3(), segment_min_gain);
      const ZonotopeTrajectory t = est.run(Y);
      for (Eigen::Index k = 0; k < Y.rows(); ++k) {
        const MeasurementCheck& c = t.checks[static_cast<std::size_t>(k)];
        EXPECT_EQ(c.flagged(), k == 20) << "step " << k << " glitch " << glitch;
        EXPECT_TRUE(t.sets[static_cast<std::size_t>(k)].contains(r.X.row(k).transpose(), 0.0)) << "step " << k;
        EXPECT_TRUE((t.lower.row(k).array() <= t.upper.row(k).array()).all());
      }
      const MeasurementCheck& c20 = t.checks[20];
      EXPECT_EQ(c20.status[0], OutputStatus::Inconsistent);
      EXPECT_EQ(c20.status[1], OutputStatus::Used);
      EXPECT_GT(c20.margin(0), glitch / 0.2 * 0.5);
    }
  }
}

TEST(MeasurementCheck, RaiseNamesStepAndOutputAndLeavesTheEstimatorUnchanged) {
  const LinearSystem s = le13();
  Record r = simulate(s, Eigen::Vector2d(1.0, 1.0), 30, false, 3);
  r.Y(12, 1) -= 50.0;
  ZonotopicOptions opt;
  opt.on_inconsistency = OnInconsistency::Raise;
  ZonotopicEstimator est(s, box3(), segment_min_gain, opt);
  for (Eigen::Index k = 0; k < 12; ++k) est.update(r.Y.row(k).transpose(), Eigen::VectorXd(0));
  const std::vector<double> before = est.save_state();
  try {
    est.update(r.Y.row(12).transpose(), Eigen::VectorXd(0));
    ADD_FAILURE() << "expected InconsistentMeasurementError";
  } catch (const InconsistentMeasurementError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("step 12: output 1:", 0), 0u) << e.what();
  }
  EXPECT_EQ(est.save_state(), before);
  EXPECT_EQ(est.steps_taken(), 12);
}

TEST(MeasurementCheck, ResetRestartsFromTheResetSet) {
  // The state jumps at step 15 (the model is violated): the readings are impossible for the
  // prediction; Reset restarts from the wide set with that step's readings and holds the truth.
  const LinearSystem s = le13();
  const Record r = simulate(s, Eigen::Vector2d(1.0, 1.0), 40, true, 5, 15, Eigen::Vector2d(6.0, -6.0));
  ZonotopicOptions opt;
  opt.on_inconsistency = OnInconsistency::Reset;
  const Zonotope wide(Eigen::Vector2d::Zero(), 20.0 * Eigen::Matrix2d::Identity());
  ZonotopicEstimator est(s, box3(), segment_min_gain, opt);
  est.set_inconsistency_policy(OnInconsistency::Reset, wide);
  const ZonotopeTrajectory t = est.run(r.Y);
  for (Eigen::Index k = 0; k < r.Y.rows(); ++k) {
    EXPECT_EQ(t.checks[static_cast<std::size_t>(k)].reset, k == 15) << k;
    EXPECT_TRUE(t.sets[static_cast<std::size_t>(k)].contains(r.X.row(k).transpose(), 0.0)) << k;
  }
  EXPECT_TRUE(t.checks[15].flagged());
  // Without the reset the jump is flagged and the truth is lost.
  ZonotopicEstimator flag(s, box3(), segment_min_gain);
  const ZonotopeTrajectory f = flag.run(r.Y);
  EXPECT_TRUE(f.checks[15].flagged());
  EXPECT_FALSE(f.sets[15].contains(r.X.row(15).transpose(), 0.0));
  // A reset set of the wrong dimension or with too many generators is refused by name.
  setbound::testing::expect_error_naming<DimensionError>(
      [&] { est.set_inconsistency_policy(OnInconsistency::Reset, Zonotope(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity())); },
      "reset_set");
  setbound::testing::expect_error_naming<InvalidArgumentError>(
      [&] { est.set_inconsistency_policy(OnInconsistency::Reset, Zonotope(Eigen::Vector2d::Zero(), Eigen::MatrixXd::Ones(2, 500))); },
      "reset_set");
}

TEST(MeasurementCheck, RunStartsFromTheInitialSetAndInfinityIsAnError) {
  const LinearSystem s = le13();
  const Record r = simulate(s, Eigen::Vector2d(1.0, 1.0), 30, false, 9);
  ZonotopicEstimator est(s, box3(), segment_min_gain);
  const ZonotopeTrajectory a = est.run(r.Y);
  const ZonotopeTrajectory b = est.run(r.Y);
  EXPECT_EQ(a.lower, b.lower);
  EXPECT_EQ(a.upper, b.upper);
  Eigen::VectorXd y = r.Y.row(0).transpose();
  y(1) = std::numeric_limits<double>::infinity();
  setbound::testing::expect_error_naming<NotFiniteError>([&] { est.update(y, Eigen::VectorXd(0)); }, "y");
}

TEST(MeasurementCheck, CApiPoliciesStatusesAndErrors) {
  const LinearSystem s = le13();
  setbound::testing::CapiScenario scenario(20);
  const Record& r = scenario.r;
  sb_linear_system* sys = scenario.sys;
  const double p0[2] = {0, 0}, H0[4] = {3, 0, 0, 3};
  for (int policy : {SB_ON_INCONSISTENCY_FLAG, SB_ON_INCONSISTENCY_RAISE, SB_ON_INCONSISTENCY_RESET}) {
    sb_zonotopic* est = nullptr;
    ASSERT_EQ(sb_zonotopic_create(sys, SB_ZONO_GAIN_SEGMENT_MIN, nullptr, 20, 1, nullptr, 2, p0, H0, &est), SB_OK);
    ASSERT_EQ(sb_zonotopic_set_inconsistency_policy(est, policy, 0, nullptr, nullptr), SB_OK);
    double c[2], lo[2], hi[2];
    int m = 0;
    for (int k = 0; k < 20; ++k) {
      const Eigen::Vector2d y = r.Y.row(k).transpose();
      const int rc = sb_zonotopic_step(est, y.data(), nullptr, c, lo, hi, &m);
      if (!setbound::testing::expect_capi_screening(rc, k, policy, lo, hi, [&](int* st, double* mg, int* rs) {
            return sb_zonotopic_last_check(est, st, mg, rs);
          }))
        break;
    }
    // Back to the start: the same first step as a fresh estimator.
    ASSERT_EQ(sb_zonotopic_reset(est), SB_OK);
    const Eigen::Vector2d y0 = r.Y.row(0).transpose();
    ASSERT_EQ(sb_zonotopic_step(est, y0.data(), nullptr, c, lo, hi, &m), SB_OK);
    ZonotopicEstimator fresh(s, box3(), segment_min_gain);
    fresh.update(y0, Eigen::VectorXd(0));
    EXPECT_DOUBLE_EQ(lo[0], fresh.current_lower()(0));
    EXPECT_EQ(sb_zonotopic_set_inconsistency_policy(est, 7, 0, nullptr, nullptr), SB_ERR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(sb_last_error()).find("policy"), std::string::npos);
    const double inf_y[2] = {std::numeric_limits<double>::infinity(), 0.0};
    EXPECT_EQ(sb_zonotopic_step(est, inf_y, nullptr, c, lo, hi, &m), SB_ERR_NOT_FINITE);
    const double p3[3] = {0, 0, 0};
    EXPECT_EQ(sb_zonotopic_set_inconsistency_policy(est, SB_ON_INCONSISTENCY_RESET, -1, p3, nullptr),
              SB_ERR_DIMENSION);
    sb_zonotopic_free(est);
  }
}
