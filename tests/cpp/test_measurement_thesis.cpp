// Missing and impossible readings in the thesis observers (issue 24; thesis/reading_screen.hpp):
// the H∞ set-membership observers (LTI, LPV) and the interval observers (Luenberger, nonlinear,
// invariant). The plant is EX-LE13 in the thesis's letters (d = the state disturbance, v = the
// output noise, unit boxes), the same record as the other families' tests.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "measurement_test_data.hpp"
#include "setbound/thesis/hinf_observer.hpp"
#include "setbound/thesis/interval_observer.hpp"
#include "setbound/thesis/lpv.hpp"
#include "test_helpers.hpp"
#include "thesis_test_systems.hpp"

using namespace setbound;
using namespace setbound::thesis;
using setbound::testing::draw_disturbance;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// EX-LE13 as a thesis plant: x⁺ = A x + F d, y = C x + Z v, d ∈ [−1, 1], v ∈ [−1, 1]².
/// with_identity_F: the nonlinear observer's form, x⁺ = A x + h with [h] = F[d].
Plant le13_plant(bool identity_F = false) {
  const LinearSystem s = setbound::testing::le13_known_a();
  MatrixXd F = s.E().leftCols(1), Z = s.F().rightCols(2);
  if (identity_F) F = MatrixXd::Identity(2, 2);
  return Plant(s.A(), MatrixXd(2, 0), s.C(), F, Z);
}

Box unit(Eigen::Index n) { return Box(-VectorXd::Ones(n), VectorXd::Ones(n)); }
Box x0_box() { return Box(-3 * VectorXd::Ones(2), 3 * VectorXd::Ones(2)); }
Box h_box() {  // F[d] of le13 for the nonlinear observer
  VectorXd r(2);
  r << 0.12, 0.02;
  return Box(-r, r);
}

/// Truth and readings of the thesis plant from (1, 1); d, v uniform or at the box's vertices.
setbound::testing::Record record(int N, bool vertex, unsigned seed) {
  const Plant p = le13_plant();
  std::mt19937 gen(seed);
  setbound::testing::Record r{MatrixXd(N, 2), MatrixXd(N, 2)};
  VectorXd x = VectorXd::Ones(2);
  for (int k = 0; k < N; ++k) {
    const VectorXd w = draw_disturbance(gen, 3, vertex);
    r.X.row(k) = x.transpose();
    r.Y.row(k) = (p.C * x + p.Z * w.tail(2)).transpose();
    x = p.A * x + p.F * w.head(1);
  }
  return r;
}

/// One observer of each kind behind one interface (the box of x_k, a step, the check, states).
struct Observer {
  std::string name;
  std::function<void(const VectorXd&)> step;
  std::function<VectorXd()> lower, upper;
  std::function<const MeasurementCheck&()> check;
  std::function<void(OnInconsistency, const Box&)> policy;
  std::function<std::vector<double>()> save;
  std::function<void(const std::vector<double>&)> restore;
};

template <class Obs, class StepFn>
Observer wrap(std::string name, std::shared_ptr<Obs> o, StepFn step) {
  Observer w;
  w.name = std::move(name);
  w.step = [o, step](const VectorXd& y) { step(*o, y); };
  w.lower = [o] { return VectorXd(o->lower()); };
  w.upper = [o] { return VectorXd(o->upper()); };
  w.check = [o]() -> const MeasurementCheck& { return o->last_check(); };
  w.policy = [o](OnInconsistency p, const Box& b) { o->set_inconsistency_policy(p, b); };
  w.save = [o] { return o->save_state(); };
  w.restore = [o](const std::vector<double>& s) { o->restore_state(s); };
  return w;
}

const EllipsoidalSMDesign& sm_design() {
  static const EllipsoidalSMDesign d = design_ellipsoidal_sm_observer(le13_plant(), VectorXd::Ones(3));
  return d;
}
const InvariantObserverDesign& invariant_design() {
  static const InvariantObserverDesign d =
      offline_error_sequence(le13_plant(), x0_box(), VectorXd::Zero(2), unit(1), unit(2));
  return d;
}

std::vector<std::string> kinds() { return {"sm", "luenberger", "nonlinear", "invariant"}; }

Observer make(const std::string& kind) {
  const VectorXd none(0);
  if (kind == "sm") {
    const EllipsoidalSMDesign& d = sm_design();
    const Box X = x0_box();
    const VectorXd c = X.mid();
    const double mu0 = mu0_from_vertices(d, box_corners(X.lo() - c, X.hi() - c));
    auto o = std::make_shared<EllipsoidalSMObserver>(le13_plant(), d, c, mu0);
    return wrap("sm", o, [none](EllipsoidalSMObserver& ob, const VectorXd& y) { ob.step(y, none); });
  }
  if (kind == "luenberger") {
    const Plant p = le13_plant();
    const HinfGain g = hinf_observer_gain(p);
    auto o = std::make_shared<IntervalLuenbergerObserver>(p, g.L, x0_box(), VectorXd::Zero(2), unit(1), unit(2));
    return wrap("luenberger", o, [none](IntervalLuenbergerObserver& ob, const VectorXd& y) { ob.step(y, none); });
  }
  if (kind == "nonlinear") {
    auto o = std::make_shared<NonlinearIntervalObserver>(
        design_nonlinear_interval_observer(le13_plant(true), x0_box(), VectorXd::Zero(2), unit(2)));
    return wrap("nonlinear", o,
                [none](NonlinearIntervalObserver& ob, const VectorXd& y) { ob.step(y, none, h_box()); });
  }
  auto o = std::make_shared<IntervalInvariantObserver>(invariant_design());
  return wrap("invariant", o, [none](IntervalInvariantObserver& ob, const VectorXd& y) { ob.step(y, none); });
}

bool inside(const Observer& o, const VectorXd& x) {
  const VectorXd lo = o.lower(), hi = o.upper();
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (!(lo(i) <= x(i) + 1e-12 && x(i) <= hi(i) + 1e-12)) return false;
  return true;
}

}  // namespace

TEST(MeasurementThesis, MissingOutputsKeepTheTruthInside) {
  for (const std::string& kind : kinds())
    for (bool vertex : {false, true}) {
      SCOPED_TRACE(kind + (vertex ? " vertex" : " uniform"));
      setbound::testing::Record r = record(120, vertex, vertex ? 3u : 4u);
      std::mt19937 gen(17);
      std::uniform_real_distribution<double> U(0, 1);
      std::vector<std::vector<bool>> missing(120, std::vector<bool>(2));
      for (int k = 0; k < 120; ++k)
        for (int i = 0; i < 2; ++i)
          if ((missing[std::size_t(k)][std::size_t(i)] = U(gen) < 0.2)) r.Y(k, i) = kNaN;
      Observer o = make(kind), full = make(kind);
      double width = 0, width_full = 0;
      const setbound::testing::Record clean = record(120, vertex, vertex ? 3u : 4u);
      for (int k = 0; k < 120; ++k) {
        ASSERT_TRUE(inside(o, r.X.row(k).transpose())) << "step " << k;
        width += (o.upper() - o.lower()).sum();
        width_full += (full.upper() - full.lower()).sum();
        o.step(r.Y.row(k).transpose());
        full.step(clean.Y.row(k).transpose());
        for (int i = 0; i < 2; ++i)
          EXPECT_EQ(o.check().status[std::size_t(i)],
                    missing[std::size_t(k)][std::size_t(i)] ? OutputStatus::Missing : OutputStatus::Used);
        EXPECT_FALSE(o.check().flagged());
      }
      // the sets stay useful: not more than 3× the width with every sample (measured ≈ 1.1–2.3×)
      EXPECT_LT(width, 3.0 * width_full) << width / width_full;
    }
}

TEST(MeasurementThesis, NoReadingAtAllIsAnIntervalPrediction) {
  // y entirely missing: the box of x_{k+1} contains A[x_k] + F[d] (interval observers: their
  // set is the box) and the image of the ellipsoid (SM observer, below).
  for (const std::string& kind : {"luenberger", "nonlinear", "invariant"}) {
    SCOPED_TRACE(kind);
    Observer o = make(kind);
    const VectorXd lo = o.lower(), hi = o.upper();
    o.step(VectorXd::Constant(2, kNaN));
    const Plant p = le13_plant();
    // every corner of [x_0] mapped by A (plus the disturbance's extreme values) lies inside
    for (int c = 0; c < 4; ++c) {
      VectorXd x(2);
      x << ((c & 1) ? hi(0) : lo(0)), ((c & 2) ? hi(1) : lo(1));
      for (double d : {-1.0, 1.0}) EXPECT_TRUE(inside(o, p.A * x + p.F * VectorXd::Constant(1, d)));
    }
    EXPECT_EQ(o.check().status[0], OutputStatus::Missing);
  }
  const EllipsoidalSMDesign& d = sm_design();
  const Plant p = le13_plant();
  EllipsoidalSMObserver sm(p, d, VectorXd::Zero(2), 4.0);
  const VectorXd c = sm.center();
  const double level = sm.mu() * d.cbar;
  Eigen::LLT<MatrixXd> llt(d.P);
  const MatrixXd U = llt.matrixU();  // P = UᵀU: e = √level U⁻¹ z, ‖z‖ = 1, is on the boundary
  sm.step(VectorXd::Constant(2, kNaN), VectorXd(0));
  for (int j = 0; j < 64; ++j) {
    const double t = 2 * M_PI * j / 64.0;
    const VectorXd z = (VectorXd(2) << std::cos(t), std::sin(t)).finished();
    const VectorXd x = c + std::sqrt(level) * U.triangularView<Eigen::Upper>().solve(z);
    for (double dd : {-1.0, 1.0}) {
      const VectorXd xn = p.A * x + p.F * VectorXd::Constant(1, dd);
      const VectorXd e = xn - sm.center();
      EXPECT_LE(e.dot(d.P * e), sm.mu() * d.cbar * (1 + 1e-12));
      EXPECT_TRUE((sm.lower().array() <= xn.array()).all() && (xn.array() <= sm.upper().array()).all());
    }
  }
}

TEST(MeasurementThesis, FaultFreeDataNeverRaiseAnAlarm) {
  for (const std::string& kind : kinds())
    for (bool vertex : {false, true}) {
      SCOPED_TRACE(kind);
      const setbound::testing::Record r = record(2000, vertex, 23u);
      Observer o = make(kind);
      o.policy(OnInconsistency::Raise, Box());
      for (int k = 0; k < 2000; ++k) {
        ASSERT_TRUE(inside(o, r.X.row(k).transpose())) << k;
        ASSERT_NO_THROW(o.step(r.Y.row(k).transpose())) << k;
      }
    }
}

TEST(MeasurementThesis, GlitchIsFlaggedTheTruthStaysInsideAndBoundsNeverInvert) {
  for (const std::string& kind : kinds())
    for (double glitch : {5.0, 1e3, 1e12}) {
      SCOPED_TRACE(kind + " " + std::to_string(glitch));
      setbound::testing::Record r = record(60, true, 5u);
      r.Y(20, 0) += glitch;
      Observer o = make(kind);
      for (int k = 0; k < 60; ++k) {
        ASSERT_TRUE(inside(o, r.X.row(k).transpose())) << k;
        ASSERT_TRUE((o.lower().array() <= o.upper().array()).all());
        o.step(r.Y.row(k).transpose());
        EXPECT_EQ(o.check().flagged(), k == 20) << k;
        if (k == 20) {
          EXPECT_EQ(o.check().status[0], OutputStatus::Inconsistent);
          EXPECT_EQ(o.check().status[1], OutputStatus::Used);
          EXPECT_GT(o.check().margin(0), 1.0);
        }
      }
    }
}

TEST(MeasurementThesis, RaiseNamesStepAndOutputAndLeavesTheObserverUnchanged) {
  for (const std::string& kind : kinds()) {
    SCOPED_TRACE(kind);
    setbound::testing::Record r = record(30, false, 6u);
    r.Y(12, 1) -= 50;
    Observer o = make(kind);
    o.policy(OnInconsistency::Raise, Box());
    for (int k = 0; k < 12; ++k) o.step(r.Y.row(k).transpose());
    const std::vector<double> before = o.save();
    try {
      o.step(r.Y.row(12).transpose());
      FAIL() << "no exception";
    } catch (const InconsistentMeasurementError& e) {
      EXPECT_NE(std::string(e.what()).find("step 12: output 1:"), std::string::npos) << e.what();
    }
    EXPECT_EQ(o.save(), before);
  }
}

TEST(MeasurementThesis, ResetRestartsFromTheResetBox) {
  // The model is violated (the state jumps by (6, −6) before step 15): the flag policy loses
  // the truth, the reset policy restarts from the wide box and keeps it from then on.
  for (const std::string& kind : kinds()) {
    SCOPED_TRACE(kind);
    setbound::testing::Record r = record(45, true, 8u);
    const Plant p = le13_plant();
    VectorXd jump(2);
    jump << 6, -6;
    // re-simulate from step 15 with the jump (same disturbances are not needed: any admissible)
    std::mt19937 gen(99);
    VectorXd x = r.X.row(15).transpose() + jump;
    for (int k = 15; k < 45; ++k) {
      const VectorXd w = draw_disturbance(gen, 3, true);
      r.X.row(k) = x.transpose();
      r.Y.row(k) = (p.C * x + p.Z * w.tail(2)).transpose();
      x = p.A * x + p.F * w.head(1);
    }
    Observer flag = make(kind), reset = make(kind);
    reset.policy(OnInconsistency::Reset, Box(-20 * VectorXd::Ones(2), 20 * VectorXd::Ones(2)));
    bool flag_lost = false;
    for (int k = 0; k < 45; ++k) {
      if (k > 15 && !inside(flag, r.X.row(k).transpose())) flag_lost = true;
      if (k != 15) EXPECT_TRUE(inside(reset, r.X.row(k).transpose())) << k;
      flag.step(r.Y.row(k).transpose());
      reset.step(r.Y.row(k).transpose());
      if (k == 15) {
        EXPECT_TRUE(flag.check().flagged());
        EXPECT_TRUE(reset.check().reset);
        EXPECT_TRUE(reset.check().flagged());  // the report keeps the test that triggered it
      } else if (k > 15) {
        EXPECT_FALSE(reset.check().flagged()) << k;
      }
    }
    EXPECT_TRUE(flag_lost);
  }
}

TEST(MeasurementThesis, SavedStateAfterARestartContinuesBitForBit) {
  for (const std::string& kind : kinds()) {
    SCOPED_TRACE(kind);
    setbound::testing::Record r = record(60, false, 9u);
    r.Y(10, 0) = kNaN;
    r.Y(25, 1) = kNaN;
    r.Y(26, 0) = kNaN;
    Observer a = make(kind), b = make(kind);
    for (int k = 0; k < 27; ++k) a.step(r.Y.row(k).transpose());  // the last step restarted
    b.restore(a.save());
    EXPECT_EQ(b.lower(), a.lower());
    EXPECT_EQ(b.upper(), a.upper());
    for (int k = 27; k < 60; ++k) {
      a.step(r.Y.row(k).transpose());
      b.step(r.Y.row(k).transpose());
      ASSERT_EQ(a.lower(), b.lower()) << k;
      ASSERT_EQ(a.upper(), b.upper()) << k;
    }
    // a corrupted restart box is refused by name, the observer unchanged
    std::vector<double> s = a.save();
    const std::vector<double> before = s;
    if (kind == "sm") continue;  // its state (x̂, μ, k) has no restart box
    s[s.size() - 1] = s[s.size() - 4] - 1.0;  // restart upper[1] < restart lower[1]
    EXPECT_THROW(b.restore(s), InvalidArgumentError);
    EXPECT_EQ(b.save(), before);
  }
}

TEST(MeasurementThesis, LpvObserverMissingAndGlitchedReadings) {
  const LpvSystem sys = setbound::testing::ch3_ex1();
  const std::vector<MatrixXd>& A = sys.A;
  const std::vector<MatrixXd>& B = sys.B;
  const MatrixXd& C = sys.C;
  const MatrixXd& Z = sys.Z;
  const EllipsoidalSMDesign d = design_ellipsoidal_sm_observer_lpv(sys, VectorXd::Ones(2));
  VectorXd lo(2), hi(2);
  lo << -0.1, -2.1;
  hi << 0.1, -1.9;
  const double mu0 = mu0_from_vertices(d, box_corners(lo, hi));
  for (bool vertex : {false, true}) {
    LPVEllipsoidalSMObserver obs(sys, d, VectorXd((VectorXd(2) << 0, -2).finished()), mu0);
    std::mt19937 gen(vertex ? 31 : 32);
    std::uniform_real_distribution<double> U(0, 1), R(0.05, 0.1);
    VectorXd x(2);
    x << 0.05, -2;
    for (int k = 0; k < 150; ++k) {
      for (int i = 0; i < 2; ++i) {
        EXPECT_LE(obs.lower()(i), x(i) + 1e-12) << k;
        EXPECT_GE(obs.upper()(i), x(i) - 1e-12) << k;
      }
      const double r = R(gen);
      const double a = (0.1 - r) / 0.05;
      const MatrixXd Ar = a * A[0] + (1 - a) * A[1], Br = a * B[0] + (1 - a) * B[1];
      const VectorXd w = draw_disturbance(gen, 2, vertex);
      const VectorXd u = VectorXd::Constant(1, std::sin(0.1 * k));
      VectorXd y = C * x + Z * w.tail(1);
      if (U(gen) < 0.2) y(0) = kNaN;
      if (k == 60) y(0) += 1e3;
      obs.step(y, u, VectorXd::Constant(1, r));
      EXPECT_EQ(obs.last_check().flagged(), k == 60) << k;
      x = Ar * x + Br * u + Br * w.head(1);
    }
  }
}

TEST(MeasurementThesis, CApiPoliciesStatusesAndReset) {
  using setbound::testing::CapiScenario;
  using setbound::testing::expect_capi_screening;
  const int N = 20;
  const Plant p = le13_plant();
  const Eigen::Matrix<double, 2, 2, Eigen::RowMajor> A = p.A, C = p.C, Zm = p.Z;
  const Eigen::Matrix<double, 2, 1> F = p.F;
  const double x0lo[2] = {-3, -3}, x0hi[2] = {3, 3}, xh0[2] = {0, 0}, dlo[1] = {-1}, dhi[1] = {1},
               vlo[2] = {-1, -1}, vhi[2] = {1, 1}, rlo[2] = {-20, -20}, rhi[2] = {20, 20}, hlo[2] = {-0.12, -0.02},
               hhi[2] = {0.12, 0.02};
  for (int policy : {SB_ON_INCONSISTENCY_FLAG, SB_ON_INCONSISTENCY_RAISE, SB_ON_INCONSISTENCY_RESET}) {
    SCOPED_TRACE(policy);
    CapiScenario sc(N);
    const double* rl = policy == SB_ON_INCONSISTENCY_RESET ? rlo : nullptr;
    const double* rh = policy == SB_ON_INCONSISTENCY_RESET ? rhi : nullptr;
    sb_interval_luenberger* lu = nullptr;
    ASSERT_EQ(sb_interval_luenberger_create(2, 0, 2, 1, 2, A.data(), nullptr, C.data(), F.data(), Zm.data(), nullptr,
                                            x0lo, x0hi, xh0, dlo, dhi, vlo, vhi, SB_IOBS_TIGHT, &lu),
              SB_OK)
        << sb_last_error();
    sb_interval_nonlinear* nl = nullptr;
    ASSERT_EQ(sb_interval_nonlinear_create(2, 0, 2, 2, A.data(), nullptr, C.data(), Zm.data(), nullptr, x0lo, x0hi,
                                           xh0, vlo, vhi, 0, &nl),
              SB_OK)
        << sb_last_error();
    sb_interval_invariant_design* idz = nullptr;
    ASSERT_EQ(sb_interval_invariant_design_create(2, 0, 2, 1, 2, A.data(), nullptr, C.data(), F.data(), Zm.data(),
                                                  nullptr, nullptr, 0.0, x0lo, x0hi, xh0, dlo, dhi, vlo, vhi, 2.0,
                                                  0.0, 0.01, SB_IOBS_TIGHT, &idz),
              SB_OK)
        << sb_last_error();
    sb_interval_invariant* inv = nullptr;
    ASSERT_EQ(sb_interval_invariant_create(idz, &inv), SB_OK);
    const double wbar[3] = {1, 1, 1};
    sb_hinf_design* hd = nullptr;
    ASSERT_EQ(sb_hinf_design_create(1, 2, 0, 2, 1, 2, 0, A.data(), nullptr, C.data(), F.data(), Zm.data(), nullptr,
                                    wbar, nullptr, SB_LAMBDA_LOGDET, 0, &hd),
              SB_OK)
        << sb_last_error();
    double mu0 = 0;
    ASSERT_EQ(sb_hinf_design_mu0_box(hd, x0lo, x0hi, &mu0), SB_OK);
    sb_hinf_observer* sm = nullptr;
    ASSERT_EQ(sb_hinf_observer_create(hd, xh0, mu0, &sm), SB_OK);
    ASSERT_EQ(sb_interval_luenberger_set_inconsistency_policy(lu, policy, rl, rh), SB_OK) << sb_last_error();
    ASSERT_EQ(sb_interval_nonlinear_set_inconsistency_policy(nl, policy, rl, rh), SB_OK) << sb_last_error();
    ASSERT_EQ(sb_interval_invariant_set_inconsistency_policy(inv, policy, rl, rh), SB_OK) << sb_last_error();
    ASSERT_EQ(sb_hinf_observer_set_inconsistency_policy(sm, policy, rl, rh), SB_OK) << sb_last_error();
    bool go[4] = {true, true, true, true};
    for (int k = 0; k < N; ++k) {
      const Eigen::Vector2d y = sc.r.Y.row(k).transpose();
      double xh[2], lo[2], hi[2], c[2], mu;
      if (go[0])
        go[0] = expect_capi_screening(sb_interval_luenberger_step(lu, y.data(), nullptr, xh, lo, hi), k, policy, lo, hi,
                                      [&](int* s, double* m, int* r) { return sb_interval_luenberger_last_check(lu, s, m, r); });
      if (go[1])
        go[1] = expect_capi_screening(sb_interval_nonlinear_step(nl, y.data(), nullptr, hlo, hhi, xh, lo, hi), k, policy,
                                      lo, hi,
                                      [&](int* s, double* m, int* r) { return sb_interval_nonlinear_last_check(nl, s, m, r); });
      if (go[2])
        go[2] = expect_capi_screening(sb_interval_invariant_step(inv, y.data(), nullptr, xh, lo, hi), k, policy, lo, hi,
                                      [&](int* s, double* m, int* r) { return sb_interval_invariant_last_check(inv, s, m, r); });
      if (go[3])
        go[3] = expect_capi_screening(sb_hinf_observer_step(sm, y.data(), nullptr, nullptr, c, lo, hi, &mu), k, policy,
                                      lo, hi,
                                      [&](int* s, double* m, int* r) { return sb_hinf_observer_last_check(sm, s, m, r); });
    }
    // bad arguments are refused by name
    EXPECT_EQ(sb_interval_luenberger_set_inconsistency_policy(lu, 7, nullptr, nullptr), SB_ERR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(sb_last_error()).find("policy"), std::string::npos);
    EXPECT_EQ(sb_hinf_observer_set_inconsistency_policy(sm, SB_ON_INCONSISTENCY_RESET, rlo, nullptr),
              SB_ERR_INVALID_ARGUMENT);
    const double inf_lo[2] = {-INFINITY, 0};
    EXPECT_NE(sb_interval_invariant_set_inconsistency_policy(inv, SB_ON_INCONSISTENCY_RESET, inf_lo, rhi), SB_OK);
    const double yinf[2] = {INFINITY, 0};
    double xh[2], lo[2], hi[2];
    EXPECT_EQ(sb_interval_luenberger_step(lu, yinf, nullptr, xh, lo, hi), SB_ERR_NOT_FINITE);
    EXPECT_NE(std::string(sb_last_error()).find("y: entry 0 is inf"), std::string::npos) << sb_last_error();
    sb_hinf_observer_free(sm);
    sb_hinf_design_free(hd);
    sb_interval_invariant_free(inv);
    sb_interval_invariant_design_free(idz);
    sb_interval_nonlinear_free(nl);
    sb_interval_luenberger_free(lu);
  }
}
