// Missing and impossible readings (issue 24, estimators/measurement_check.hpp) in the ellipsoidal
// family, through C++ and the C ABI: the predictors (offline, online vertex, online scaled) and
// the improved filter skip NaN outputs with a partial step that stays certified, never use a
// reading outside the predicted output set (policies Flag, Raise, Reset), keep the true state
// inside, never report lower > upper, and contain the exact hull of the data they used; the
// Kalman filter corrects with the outputs present; the descriptor estimator refuses a missing
// output with a message that says why.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "c_api_common.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/estimators/ellipsoidal/descriptor.hpp"
#include "setbound/estimators/ellipsoidal/lmi_estimators.hpp"
#include "setbound/estimators/polytopic/exact_hull.hpp"
#include "setbound/estimators/ellipsoidal/improved_estimator.hpp"
#include "setbound/estimators/point/kalman.hpp"
#include "setbound/estimators/measurement_check.hpp"
#include "measurement_test_data.hpp"
#include "test_helpers.hpp"

using namespace setbound;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

LinearSystem le13() { return setbound::testing::le13_known_a(); }

// An unstable A that only the correction stabilises: without output 1 (the only one that sees
// x2) the partial step has β > 1.
LinearSystem unstable() {
  Eigen::MatrixXd A(2, 2), C(2, 2), E(2, 4), F(2, 4);
  A << 0.9, 0.2, 0, 1.15;
  C << 1, 0, 0, 1;
  E << 0.05, 0, 0, 0, 0, 0.05, 0, 0;
  F << 0, 0, 0.1, 0, 0, 0, 0, 0.1;
  return LinearSystem(A, C, E, F);
}

using setbound::testing::Record;

Record simulate(const LinearSystem& s, const Eigen::VectorXd& x0, int N, bool vertex, unsigned seed,
                int jump_at = -1, const Eigen::VectorXd& jump = Eigen::VectorXd()) {
  return setbound::testing::simulate_record(s, x0, N, vertex, seed, jump_at, jump);
}

// 20 % of the readings missing (at least one step with every output missing).
void drop(Eigen::MatrixXd& Y, unsigned seed) {
  std::mt19937 gen(seed);
  std::bernoulli_distribution miss(0.2);
  for (Eigen::Index k = 0; k < Y.rows(); ++k)
    for (Eigen::Index i = 0; i < Y.cols(); ++i)
      if (miss(gen)) Y(k, i) = kNaN;
  Y.row(Y.rows() / 2).setConstant(kNaN);
}

const EllDesign& design_le13() {
  static const EllDesign d = design_ellipsoidal_offline(le13());
  return d;
}

Ellipsoid ball(double r, Eigen::Index n = 2) { return Ellipsoid(Eigen::MatrixXd::Identity(n, n), Eigen::VectorXd::Zero(n), r * r); }

const EllPredictorMode kModes[] = {EllPredictorMode::Offline, EllPredictorMode::OnlineVertex,
                                   EllPredictorMode::OnlineScaled};

// Box contains box, with a relative slack for the LP rounding of the exact hull.
void expect_box_contains(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, const Eigen::VectorXd& in_lo,
                         const Eigen::VectorXd& in_hi, const std::string& what) {
  for (Eigen::Index i = 0; i < lo.size(); ++i) {
    const double tol = 1e-9 * (1.0 + std::abs(in_lo(i)) + std::abs(in_hi(i)));
    EXPECT_LE(lo(i), in_lo(i) + tol) << what << " coordinate " << i;
    EXPECT_GE(hi(i), in_hi(i) - tol) << what << " coordinate " << i;
  }
}

}  // namespace

TEST(MeasurementEllipsoidal, OutputSpreadIsCertifiedAndTight) {
  const EllDesign& d = design_le13();
  EllipsoidalPredictor p(d, ball(3), EllPredictorMode::Offline);
  const Eigen::MatrixXd Pinv = d.P.inverse();
  for (Eigen::Index i = 0; i < 2; ++i) {
    const double q = d.system.C().row(i) * Pinv * d.system.C().row(i).transpose();
    EXPECT_GE(p.output_spread()(i), q * (1 - 1e-12));
    EXPECT_LE(p.output_spread()(i), q * (1 + 1e-5));  // certified, not a blanket bound
  }
}

TEST(MeasurementEllipsoidal, MissingOutputsKeepTheTruthInsideAndContainTheExactHull) {
  const LinearSystem s = le13();
  const EllDesign& d = design_le13();
  // The ellipsoidal x0 (ball of radius 3) contains the box x0 of the exact hull.
  const Zonotope box(Eigen::Vector2d::Zero(), 2.0 * Eigen::Matrix2d::Identity());
  for (bool vertex : {false, true})
    for (unsigned seed = 1; seed <= 2; ++seed) {  // 2 x 2 records: 150 s under the sanitizers with 3
      Record r = simulate(s, Eigen::Vector2d(1.0, -1.0), 40, vertex, seed);
      drop(r.Y, 50 + seed);
      const ExactHull ex = exact_hull(s, box, r.Y);
      for (EllPredictorMode mode : kModes) {
        EllipsoidalPredictor p(d, ball(3), mode);
        for (Eigen::Index k = 0; k < r.Y.rows(); ++k) {
          // The set for x_k (y_0 … y_{k-1} used) contains x_k and the exact hull at k.
          ASSERT_TRUE(p.current().contains(r.X.row(k).transpose(), 1e-9)) << "mode " << int(mode) << " step " << k;
          const BoundingBox b = p.current().bounding_box();
          expect_box_contains(b.lo, b.hi, ex.lower.row(k).transpose(), ex.upper.row(k).transpose(), "predictor");
          p.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
          for (Eigen::Index i = 0; i < 2; ++i)
            EXPECT_EQ(p.last_check().status[static_cast<std::size_t>(i)],
                      std::isnan(r.Y(k, i)) ? OutputStatus::Missing : OutputStatus::Used);
        }
      }
      ImprovedEstimator f(d, ball(3));
      for (Eigen::Index k = 0; k < r.Y.rows(); ++k) {
        f.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
        ASSERT_TRUE(f.current().contains(r.X.row(k).transpose(), 1e-9)) << "improved step " << k;
        ASSERT_TRUE((f.lower().array() <= r.X.row(k).transpose().array() + 1e-9).all() &&
                    (f.upper().array() >= r.X.row(k).transpose().array() - 1e-9).all())
            << "improved bounds, step " << k;
        expect_box_contains(f.lower(), f.upper(), ex.lower.row(k).transpose(), ex.upper.row(k).transpose(), "improved");
      }
    }
}

TEST(MeasurementEllipsoidal, UnstableWithoutAnOutputStaysGuaranteedAndRestores) {
  const LinearSystem s = unstable();
  const EllDesign d = design_ellipsoidal_offline(s);
  for (bool vertex : {false, true}) {
    Record r = simulate(s, Eigen::Vector2d(0.5, 0.5), 40, vertex, 3);
    for (Eigen::Index k = 10; k < 20; ++k) r.Y(k, 1) = kNaN;  // x2 unobserved for 10 steps
    EllipsoidalPredictor p(d, ball(1), EllPredictorMode::OnlineVertex);
    double beta_max = 0;
    std::vector<double> mid;
    for (Eigen::Index k = 0; k < r.Y.rows(); ++k) {
      ASSERT_TRUE(p.current().contains(r.X.row(k).transpose(), 1e-9)) << "step " << k;
      p.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
      beta_max = std::max(beta_max, p.last_beta());
      if (k == 15) mid = p.save_state();
    }
    EXPECT_GT(beta_max, 1.0);  // the set grew while x2 was not measured: β > 1 is certified too
    // A state saved after a step with β > 1 restores, and the run continues identically.
    EllipsoidalPredictor q(d, ball(1), EllPredictorMode::OnlineVertex);
    q.restore_state(mid);
    EllipsoidalPredictor p2(d, ball(1), EllPredictorMode::OnlineVertex);
    for (Eigen::Index k = 0; k <= 15; ++k) p2.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
    for (Eigen::Index k = 16; k < r.Y.rows(); ++k) {
      q.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
      p2.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
      EXPECT_EQ(q.current().level(), p2.current().level()) << k;
    }
  }
}

TEST(MeasurementEllipsoidal, FaultFreeDataNeverRaiseAnAlarm) {
  const LinearSystem s = le13();
  const EllDesign& d = design_le13();
  for (bool vertex : {false, true}) {
    const Record r = simulate(s, Eigen::Vector2d(2.0, -1.5), 400, vertex, vertex ? 21 : 22);
    for (EllPredictorMode mode : kModes) {
      EllipsoidalPredictor p(d, ball(3), mode);
      p.set_inconsistency_policy(OnInconsistency::Raise);  // a false alarm throws
      for (Eigen::Index k = 0; k < r.Y.rows(); ++k) p.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
    }
    ImprovedEstimator f(d, ball(3));
    f.set_inconsistency_policy(OnInconsistency::Raise);
    for (Eigen::Index k = 0; k < 150; ++k) f.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
  }
}

TEST(MeasurementEllipsoidal, GlitchIsFlaggedTheTruthStaysInsideAndBoundsNeverInvert) {
  const LinearSystem s = le13();
  const EllDesign& d = design_le13();
  for (double glitch : {5.0, 1e3, 1e12}) {
    Record r = simulate(s, Eigen::Vector2d(1.0, 1.0), 50, false, 7);
    r.Y(20, 0) += glitch;
    for (EllPredictorMode mode : kModes) {
      EllipsoidalPredictor p(d, ball(3), mode);
      for (Eigen::Index k = 0; k < r.Y.rows(); ++k) {
        ASSERT_TRUE(p.current().contains(r.X.row(k).transpose(), 1e-9)) << glitch << " step " << k;
        p.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
        EXPECT_EQ(p.last_check().flagged(), k == 20) << glitch << " step " << k;
      }
    }
    // The report: the improved estimator returned rows with lower > upper after a +5 glitch.
    ImprovedEstimator f(d, ball(3));
    for (Eigen::Index k = 0; k < r.Y.rows(); ++k) {
      f.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
      ASSERT_TRUE((f.lower().array() <= f.upper().array()).all()) << glitch << " step " << k;
      ASSERT_TRUE(f.current().contains(r.X.row(k).transpose(), 1e-9)) << glitch << " step " << k;
      EXPECT_EQ(f.last_check().flagged(), k == 20) << glitch << " step " << k;
      if (k == 20) {
        EXPECT_EQ(f.last_check().status[0], OutputStatus::Inconsistent);
        EXPECT_EQ(f.last_check().status[1], OutputStatus::Used);
        EXPECT_GT(f.last_check().margin(0), 1.0);
      }
    }
  }
}

TEST(MeasurementEllipsoidal, JointlyImpossibleReadingsAreFlaggedNotInverted) {
  // Two outputs that measure the same coordinate: each reading is possible alone, together
  // they are not (they disagree by more than both noise bounds).
  Eigen::MatrixXd A(2, 2), C(2, 2), E(2, 4), F(2, 4);
  A << 0.5, 0.1, 0, 0.5;
  C << 1, 0, 1, 1e-3;
  E << 0.1, 0, 0, 0, 0, 0.1, 0, 0;
  F << 0, 0, 0.05, 0, 0, 0, 0, 0.05;
  const LinearSystem s(A, C, E, F);
  const EllDesign d = design_ellipsoidal_offline(s);
  ImprovedEstimator f(d, ball(2));
  // x ≈ 0: readings 0.8 and -0.8 of the same coordinate (each within the predicted ±2).
  f.step(Eigen::Vector2d(0.8, -0.8), Eigen::VectorXd(0));
  EXPECT_TRUE(f.last_check().flagged());
  EXPECT_TRUE((f.lower().array() <= f.upper().array()).all());
  ImprovedEstimator g(d, ball(2));
  g.set_inconsistency_policy(OnInconsistency::Raise);
  try {
    g.step(Eigen::Vector2d(0.8, -0.8), Eigen::VectorXd(0));
    FAIL() << "no InconsistentMeasurementError";
  } catch (const InconsistentMeasurementError& e) {
    EXPECT_NE(std::string(e.what()).find("step 0: outputs 0 1"), std::string::npos) << e.what();
  }
  EXPECT_EQ(g.steps_taken(), 0);
}

TEST(MeasurementEllipsoidal, RaiseNamesStepAndOutputAndLeavesTheEstimatorUnchanged) {
  const LinearSystem s = le13();
  Record r = simulate(s, Eigen::Vector2d(1.0, 1.0), 12, false, 5);
  r.Y(9, 1) += 30.0;
  for (EllPredictorMode mode : kModes) {
    EllipsoidalPredictor p(design_le13(), ball(3), mode);
    p.set_inconsistency_policy(OnInconsistency::Raise);
    for (Eigen::Index k = 0; k < 9; ++k) p.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
    const std::vector<double> before = p.save_state();
    try {
      p.step(r.Y.row(9).transpose(), Eigen::VectorXd(0));
      FAIL() << "no InconsistentMeasurementError";
    } catch (const InconsistentMeasurementError& e) {
      EXPECT_NE(std::string(e.what()).find("step 9: output 1:"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("predicted output set"), std::string::npos) << e.what();
    }
    EXPECT_EQ(p.save_state(), before);
  }
  ImprovedEstimator f(design_le13(), ball(3));
  f.set_inconsistency_policy(OnInconsistency::Raise);
  for (Eigen::Index k = 0; k < 9; ++k) f.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
  const std::vector<double> before = f.save_state();
  EXPECT_THROW(f.step(r.Y.row(9).transpose(), Eigen::VectorXd(0)), InconsistentMeasurementError);
  EXPECT_EQ(f.save_state(), before);
}

TEST(MeasurementEllipsoidal, ResetRestartsFromTheResetSet) {
  const LinearSystem s = le13();
  // The state jumps at step 25 (a model violation): with policy Reset and a large reset set the
  // estimators contain the truth again right after the flagged step.
  Eigen::VectorXd jump(2);
  jump << 6.0, -6.0;
  const Record r = simulate(s, Eigen::Vector2d(1.0, 1.0), 45, false, 9, 25, jump);
  const Ellipsoid big = ball(40);
  for (EllPredictorMode mode : kModes) {
    EllipsoidalPredictor p(design_le13(), ball(3), mode);
    p.set_inconsistency_policy(OnInconsistency::Reset, big);
    EXPECT_EQ(p.reset_set().shape(), design_le13().P);
    int resets = 0;
    for (Eigen::Index k = 0; k < r.Y.rows(); ++k) {
      if (k < 25 || k > 26) ASSERT_TRUE(p.current().contains(r.X.row(k).transpose(), 1e-9)) << k;
      p.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
      if (p.last_check().reset) {
        ++resets;
        EXPECT_TRUE(p.last_check().flagged());
      }
    }
    EXPECT_GE(resets, 1);
  }
  ImprovedEstimator f(design_le13(), ball(3));
  f.set_inconsistency_policy(OnInconsistency::Reset, big);
  int resets = 0;
  for (Eigen::Index k = 0; k < r.Y.rows(); ++k) {
    f.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
    if (f.last_check().reset) ++resets;
    if (k < 25 || resets > 0) ASSERT_TRUE(f.current().contains(r.X.row(k).transpose(), 1e-9)) << k;
  }
  EXPECT_GE(resets, 1);
  // reset() goes back to the start: the same run twice gives the same sets.
  f.reset();
  ImprovedEstimator g(design_le13(), ball(3));
  g.set_inconsistency_policy(OnInconsistency::Reset, big);
  for (Eigen::Index k = 0; k < 30; ++k) {
    f.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
    g.step(r.Y.row(k).transpose(), Eigen::VectorXd(0));
    ASSERT_EQ(f.current().level(), g.current().level()) << k;
    ASSERT_EQ(f.lower(), g.lower()) << k;
  }
}

TEST(MeasurementEllipsoidal, KalmanCorrectsWithTheOutputsPresent) {
  const LinearSystem s = le13();
  const Record r = simulate(s, Eigen::Vector2d(1.0, 1.0), 5, false, 2);
  const Eigen::Vector2d m0(0.5, 0.5);
  const Eigen::Matrix2d G0 = Eigen::Matrix2d::Identity();
  // Nothing measured: a pure prediction.
  KalmanFilter kf(s, m0, G0);
  kf.step(Eigen::Vector2d(kNaN, kNaN), Eigen::VectorXd(0));
  EXPECT_TRUE(kf.mean().isApprox(m0));
  EXPECT_TRUE(kf.covariance().isApprox(G0));
  EXPECT_TRUE(kf.predicted_mean().isApprox(s.A() * m0));
  // Output 1 missing: the filter of the system with output 0 only.
  KalmanFilter full(s, m0, G0);
  full.step(Eigen::Vector2d(r.Y(0, 0), kNaN), Eigen::VectorXd(0));
  const LinearSystem s0(s.A(), s.C().topRows(1), s.E(), s.F().topRows(1));
  KalmanFilter one(s0, m0, G0);
  one.step(Eigen::VectorXd::Constant(1, r.Y(0, 0)), Eigen::VectorXd(0));
  EXPECT_TRUE(full.mean().isApprox(one.mean(), 1e-12));
  EXPECT_TRUE(full.covariance().isApprox(one.covariance(), 1e-12));
  EXPECT_TRUE(full.predicted_covariance().isApprox(one.predicted_covariance(), 1e-12));
  EXPECT_EQ(full.gain()(0, 1), 0.0);
  EXPECT_THROW(full.step(Eigen::Vector2d(std::numeric_limits<double>::infinity(), 0.0), Eigen::VectorXd(0)),
               NotFiniteError);
}

TEST(MeasurementEllipsoidal, CApiPoliciesStatusesResetAndDescriptorRefusal) {
  setbound::testing::CapiScenario scenario(16);
  const Record& r = scenario.r;
  sb_linear_system* sys = scenario.sys;
  sb_ell_design* design = nullptr;
  ASSERT_EQ(sb_ell_design_offline(sys, SB_ELL_NORM_LOGDET, kNaN, &design), SB_OK) << sb_last_error();
  const double P0[4] = {1, 0, 0, 1}, c0[2] = {0, 0};
  for (int method : {SB_ELL_OFFLINE, SB_ELL_ONLINE_VERTEX, SB_ELL_IMPROVED})
    for (int policy : {SB_ON_INCONSISTENCY_FLAG, SB_ON_INCONSISTENCY_RAISE, SB_ON_INCONSISTENCY_RESET}) {
      sb_ellipsoidal* est = nullptr;
      ASSERT_EQ(sb_ellipsoidal_create(design, method, SB_ELL_CORR_DET_NORMALIZED, SB_ELL_FEEDBACK_FIXED_SHAPE,
                                      SB_ELL_ONLINE_VERTEX, nullptr, P0, c0, 9.0, &est),
                SB_OK)
          << sb_last_error();
      ASSERT_EQ(sb_ellipsoidal_set_inconsistency_policy(est, policy, nullptr, nullptr, 0.0), SB_OK);
      double P[4], c[2], rho, lo[2], hi[2], margin[2];
      int status[2], reset = -1;
      ASSERT_EQ(sb_ellipsoidal_last_check(est, status, margin, &reset), SB_OK);  // before any step
      EXPECT_EQ(status[0], SB_OUTPUT_UNUSED);
      for (int k = 0; k < 16; ++k) {
        const Eigen::Vector2d y = r.Y.row(k).transpose();
        const int rc = sb_ellipsoidal_step(est, y.data(), nullptr, P, c, &rho, lo, hi);
        if (!setbound::testing::expect_capi_screening(rc, k, policy, lo, hi, [&](int* st, double* mg, int* rs) {
              return sb_ellipsoidal_last_check(est, st, mg, rs);
            }))
          break;
      }
      // Back to the start: the same first step as a fresh estimator.
      double P1[4], c1[2], rho1;
      ASSERT_EQ(sb_ellipsoidal_reset(est), SB_OK);
      const Eigen::Vector2d y0 = r.Y.row(0).transpose();
      ASSERT_EQ(sb_ellipsoidal_step(est, y0.data(), nullptr, P, c, &rho, lo, hi), SB_OK);
      sb_ellipsoidal* fresh = nullptr;
      ASSERT_EQ(sb_ellipsoidal_create(design, method, SB_ELL_CORR_DET_NORMALIZED, SB_ELL_FEEDBACK_FIXED_SHAPE,
                                      SB_ELL_ONLINE_VERTEX, nullptr, P0, c0, 9.0, &fresh),
                SB_OK);
      ASSERT_EQ(sb_ellipsoidal_step(fresh, y0.data(), nullptr, P1, c1, &rho1, lo, hi), SB_OK);
      EXPECT_EQ(rho, rho1);
      EXPECT_EQ(c[0], c1[0]);
      sb_ellipsoidal_free(fresh);
      EXPECT_EQ(sb_ellipsoidal_set_inconsistency_policy(est, 7, nullptr, nullptr, 0.0), SB_ERR_INVALID_ARGUMENT);
      EXPECT_NE(std::string(sb_last_error()).find("policy"), std::string::npos);
      const double bad_P[4] = {1, 0, 0, -1};
      EXPECT_NE(sb_ellipsoidal_set_inconsistency_policy(est, SB_ON_INCONSISTENCY_RESET, bad_P, c0, 1.0), SB_OK);
      const double inf_y[2] = {std::numeric_limits<double>::infinity(), 0.0};
      EXPECT_EQ(sb_ellipsoidal_step(est, inf_y, nullptr, P, c, &rho, lo, hi), SB_ERR_NOT_FINITE);
      sb_ellipsoidal_free(est);
    }
  sb_ell_design_free(design);
}

TEST(MeasurementEllipsoidal, DescriptorRefusesAMissingOutputAndSaysWhy) {
  // E x+ = A x + D w with E singular; the state is fixed through y (papers.md §4.1).
  Eigen::MatrixXd Ed(2, 2), A(2, 2), C(1, 2), D(2, 1), F(1, 1);
  Ed << 1, 0, 0, 0;
  A << 0.5, 0.1, 0.2, -1;
  C << 0, 1;
  D << 0.1, 0;
  F << 0.1;
  const DescriptorSystem ds(Ed, A, C, D, F);
  const EllDesign d = design_descriptor_offline(ds);
  DescriptorEstimator est(d, ds, ball(3));
  est.step(Eigen::VectorXd::Constant(1, 0.1), Eigen::VectorXd(0));
  try {
    est.step(Eigen::VectorXd::Constant(1, kNaN), Eigen::VectorXd(0));
    FAIL() << "a missing output was accepted";
  } catch (const NotFiniteError& e) {
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("descriptor"), std::string::npos) << e.what();
  }
  EXPECT_EQ(est.steps_taken(), 0);
}
