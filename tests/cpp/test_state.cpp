// Saved states of every estimator (core/state.hpp): save → continue ≡ restore into a fresh
// estimator → continue (bit-for-bit), save → mutate → restore → continue, corrupted states
// refused with the estimator unchanged, failed steps leave the state unchanged, and the C ABI.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "test_helpers.hpp"
#include "thesis_test_systems.hpp"
#include "ell_test_systems.hpp"
#include "setbound/estimators/ellipsoidal/descriptor.hpp"
#include "setbound/estimators/ellipsoidal/lmi_estimators.hpp"
#include "setbound/estimators/ellipsoidal/improved_estimator.hpp"
#include "setbound/estimators/point/kalman.hpp"
#include "setbound/estimators/zonotopic/volume_min.hpp"
#include "setbound/estimators/zonotopic/gain_estimator.hpp"
#include "setbound/thesis/hinf_observer.hpp"
#include "setbound/thesis/interval_observer.hpp"
#include "setbound/thesis/lpv.hpp"

using namespace setbound;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using setbound::testing::same_bits;

void append(std::vector<double>& out, const Eigen::Ref<const MatrixXd>& m) {
  for (Eigen::Index j = 0; j < m.cols(); ++j)
    for (Eigen::Index i = 0; i < m.rows(); ++i) out.push_back(m(i, j));
}

/// One estimator under test, type-erased (one non-template checker keeps the compile time low).
struct Subject {
  std::function<std::vector<double>()> save;
  std::function<void(const std::vector<double>&)> restore;
  std::function<void(int)> step;                     // valid step number i (deterministic data)
  std::function<std::vector<double>()> sets;         // the reported set(s), every number
  std::vector<std::pair<std::string, std::function<void(int)>>> bad_steps;  // must throw (name)
};
using Factory = std::function<Subject()>;

/// A Subject whose save/restore are the estimator's own save_state / restore_state.
template <class Est>
Subject saving_subject(const std::shared_ptr<Est>& e) {
  Subject s;
  s.save = [e] { return e->save_state(); };
  s.restore = [e](const std::vector<double>& b) { e->restore_state(b); };
  return s;
}

/// Deterministic disturbance in [-1, 1] (vertex-like values included).
double wave(int k, int j) {
  const double s = std::sin(1.3 * k + 0.7 * j + 0.1 * k * j);
  return (k + j) % 5 == 0 ? (s >= 0 ? 1.0 : -1.0) : s;
}

/// Measurements and inputs of the true system (simulated with deterministic disturbances).
struct Data {
  std::vector<VectorXd> y, u;
};
Data simulate(const LinearSystem& s, int N) {
  Data d;
  VectorXd x = VectorXd::Zero(s.nx());
  for (int k = 0; k < N; ++k) {
    VectorXd w(s.nw()), u(s.nu());
    for (Eigen::Index j = 0; j < s.nw(); ++j) w(j) = wave(k, int(j));
    for (Eigen::Index j = 0; j < s.nu(); ++j) u(j) = 0.5 * std::cos(0.4 * k + j);
    VectorXd y = s.C() * x + s.F() * w;
    if (s.nu() > 0) y += s.D() * u;
    d.y.push_back(y);
    d.u.push_back(u);
    x = s.A() * x + s.E() * w;
    if (s.nu() > 0) x += s.B() * u;
  }
  return d;
}

void expect_state_error(const std::function<void()>& f, const std::string& what) {
  try {
    f();
    ADD_FAILURE() << what << ": no error";
  } catch (const InvalidArgumentError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("state: ", 0), 0u) << what << ": " << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": wrong error type: " << e.what();
  }
}

/// The properties of the module comment for one estimator kind; `other` is an estimator of the
/// same kind made from another design (its state must be refused), `foreign` a blob of another
/// kind.
void check_subject(const Factory& make, const Factory& other, const std::vector<double>& foreign, int k, int N) {
  // Reference: k steps, save, N more steps.
  Subject a = make();
  for (int i = 0; i < k; ++i) a.step(i);
  const std::vector<double> s = a.save();
  ASSERT_GE(s.size(), kStateHeader);
  std::vector<std::vector<double>> ref_sets, ref_states;
  for (int i = k; i < k + N; ++i) {
    a.step(i);
    ref_sets.push_back(a.sets());
    ref_states.push_back(a.save());
  }
  // The state did change (otherwise the comparisons below prove nothing).
  EXPECT_FALSE(same_bits(ref_states.back(), s));

  // A fresh estimator from the same design, restored, continues identically.
  {
    Subject b = make();
    b.restore(s);
    EXPECT_TRUE(same_bits(b.save(), s)) << "save(restore(s)) != s";
    for (int i = k; i < k + N; ++i) {
      b.step(i);
      ASSERT_TRUE(same_bits(b.sets(), ref_sets[size_t(i - k)])) << "fresh restore: step " << i;
      ASSERT_TRUE(same_bits(b.save(), ref_states[size_t(i - k)])) << "fresh restore: state at step " << i;
    }
  }
  // Save → mutate (more steps, on the same object) → restore → continue identically.
  {
    a.step(k + N);
    a.restore(s);
    for (int i = k; i < k + N; ++i) {
      a.step(i);
      ASSERT_TRUE(same_bits(a.sets(), ref_sets[size_t(i - k)])) << "restore after mutation: step " << i;
    }
  }
  // Corrupted states: clear error naming the state, the estimator unchanged.
  {
    Subject c = make();
    for (int i = 0; i < k; ++i) c.step(i);
    const std::vector<double> before = c.save();
    std::vector<std::pair<std::string, std::vector<double>>> bad;
    std::vector<double> t = s;
    t[0] += 1;
    bad.emplace_back("wrong tag", t);
    t = s;
    t[1] = 99;
    bad.emplace_back("wrong version", t);
    bad.emplace_back("truncated", std::vector<double>(s.begin(), s.end() - 1));
    bad.emplace_back("header only", std::vector<double>(s.begin(), s.begin() + kStateHeader));
    bad.emplace_back("too short", std::vector<double>(s.begin(), s.begin() + 2));
    t = s;
    t.push_back(0.0);
    bad.emplace_back("extra value", t);
    for (size_t i = kStateHeader; i < s.size(); i += std::max<size_t>(1, (s.size() - kStateHeader) / 7)) {
      t = s;
      t[i] = kNaN;
      bad.emplace_back("NaN at " + std::to_string(i), t);
    }
    t = s;
    t.back() = std::numeric_limits<double>::infinity();
    bad.emplace_back("Inf at the end", t);
    t = s;
    t[2] += 1;
    bad.emplace_back("fingerprint", t);
    bad.emplace_back("another estimator kind", foreign);
    bad.emplace_back("another design", other().save());
    for (const auto& item : bad) {
      const std::vector<double>& blob = item.second;
      expect_state_error([&] { c.restore(blob); }, item.first);
      ASSERT_TRUE(same_bits(c.save(), before)) << item.first << ": the state changed";
    }
    // Still usable and identical to the reference.
    c.step(k);
    EXPECT_TRUE(same_bits(c.sets(), ref_sets[0]));
  }
  // Failed steps: an error, the state unchanged, and the next valid step as if nothing happened.
  {
    Subject d = make();
    for (int i = 0; i < k; ++i) d.step(i);
    for (const auto& [what, bad_step] : d.bad_steps) {
      const std::vector<double> before = d.save();
      bool threw = false;
      try {
        bad_step(k);
      } catch (const Error& e) {
        threw = true;
        const std::string msg = e.what();
        EXPECT_TRUE(msg.rfind("y", 0) == 0 || msg.rfind("u", 0) == 0 || msg.rfind("rho", 0) == 0 ||
                    msg.rfind("h", 0) == 0)
            << what << ": the message does not start with the argument: " << msg;
      }
      EXPECT_TRUE(threw) << what << ": no error";
      ASSERT_TRUE(same_bits(d.save(), before)) << what << ": the state changed";
    }
    d.step(k);
    EXPECT_TRUE(same_bits(d.sets(), ref_sets[0])) << "after failed steps";
  }
}

VectorXd nan_at(VectorXd v, Eigen::Index i) {
  v(i) = kNaN;
  return v;
}

VectorXd inf_at(VectorXd v, Eigen::Index i) {
  v(i) = std::numeric_limits<double>::infinity();
  return v;
}

/// The usual bad measurements / inputs for an estimator with step(y, u).
template <class E>
void add_bad_yu(Subject& s, E* e, const Data& d) {
  // An infinite reading is an error for every estimator (NaN is a missing reading where those are
  // accepted, test_measurement_check.cpp).
  s.bad_steps.emplace_back("Inf y", [e, d](int i) { e->step(inf_at(d.y[size_t(i)], 0), d.u[size_t(i)]); });
  s.bad_steps.emplace_back("short y", [e, d](int i) {
    e->step(d.y[size_t(i)].head(d.y[size_t(i)].size() - 1), d.u[size_t(i)]);
  });
  s.bad_steps.emplace_back("long y", [e, d](int i) {
    VectorXd y(d.y[size_t(i)].size() + 1);
    y << d.y[size_t(i)], 0.0;
    e->step(y, d.u[size_t(i)]);
  });
  if (d.u[0].size() > 0) {
    s.bad_steps.emplace_back("NaN u", [e, d](int i) { e->step(d.y[size_t(i)], nan_at(d.u[size_t(i)], 0)); });
    s.bad_steps.emplace_back("short u", [e, d](int i) { e->step(d.y[size_t(i)], VectorXd(0)); });
  }
}

void append_ellipsoid(std::vector<double>& v, const Ellipsoid& E) {
  append(v, E.shape());
  append(v, E.center());
  v.push_back(E.level());
}

// ---- systems -------------------------------------------------------------------------------

/// EX-ME17a with an input (B, D ≠ 0) so that u takes part.
LinearSystem me17u(double a_rad = 0.0) {
  const LinearSystem s = setbound::testing::me17(false, a_rad);
  MatrixXd B(2, 1), D(1, 1);
  B << 1, 0.5;
  D << 0.1;
  return LinearSystem(s.A(), s.C(), s.E(), s.F(), B, D, s.A_rad());
}

// ---- ellipsoidal -------------------------------------------------------------------------------

Factory predictor_factory(const EllDesign& design, EllPredictorMode mode, const Data& d) {
  return [design, mode, d] {
    auto e = std::make_shared<EllipsoidalPredictor>(design, Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 4.0),
                                                    mode);
    Subject s = saving_subject(e);
    s.step = [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)]); };
    s.sets = [e] {
      std::vector<double> v;
      append_ellipsoid(v, e->current());
      v.push_back(e->last_beta());
      append(v, e->last_gain());
      v.push_back(double(e->fallback_steps()));
      return v;
    };
    add_bad_yu(s, e.get(), d);
    return s;
  };
}

TEST(StateEllipsoidal, PredictorsContinueIdentically) {
  const LinearSystem sys = me17u();
  const Data d = simulate(sys, 40);
  EllDesignOptions o1, o2;
  o1.beta = 0.7;
  o2.beta = 0.8;
  const EllDesign d1 = design_ellipsoidal_offline(sys, o1), d2 = design_ellipsoidal_offline(sys, o2);
  const std::vector<double> foreign = KalmanFilter(sys, VectorXd::Zero(2), MatrixXd::Identity(2, 2)).save_state();
  for (EllPredictorMode mode : {EllPredictorMode::Offline, EllPredictorMode::OnlineVertex, EllPredictorMode::OnlineScaled}) {
    SCOPED_TRACE(static_cast<int>(mode));
    check_subject(predictor_factory(d1, mode, d), predictor_factory(d2, mode, d), foreign, 6, 8);
  }
  // A state of another mode (same design) is refused too.
  const std::vector<double> sv = EllipsoidalPredictor(d1, Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 4.0),
                                                      EllPredictorMode::OnlineVertex)
                                     .save_state();
  EllipsoidalPredictor off(d1, Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 4.0), EllPredictorMode::Offline);
  expect_state_error([&] { off.restore_state(sv); }, "another mode");
}

TEST(StateEllipsoidal, IntervalAOnlinePredictorsContinueIdentically) {
  const LinearSystem sys = me17u(0.02);
  const Data d = simulate(sys, 30);
  EllDesignOptions o1, o2;
  o1.beta = 0.75;
  o2.beta = 0.85;
  const EllDesign d1 = design_ellipsoidal_offline(sys, o1), d2 = design_ellipsoidal_offline(sys, o2);
  const std::vector<double> foreign = KalmanFilter(me17u(), VectorXd::Zero(2), MatrixXd::Identity(2, 2)).save_state();
  for (EllPredictorMode mode : {EllPredictorMode::OnlineVertex, EllPredictorMode::OnlineScaled}) {
    SCOPED_TRACE(static_cast<int>(mode));
    check_subject(predictor_factory(d1, mode, d), predictor_factory(d2, mode, d), foreign, 5, 6);
  }
}

/// The online working set is part of the state: a predictor restored at step k solves the same
/// sub-problem as the original (the online vertex step's result depends on it only through the
/// active-set path, so the check above would not see a wrong working set on every system; here
/// the saved working set must be a proper subset, not the initial "all blocks").
TEST(StateEllipsoidal, OnlineVertexWorkingSetIsSaved) {
  const LinearSystem sys = setbound::testing::bc14();
  const Data d = simulate(sys, 12);
  EllDesignOptions o;
  o.beta = 0.8;
  const EllDesign des = design_ellipsoidal_offline(sys, o);
  EllipsoidalPredictor a(des, Ellipsoid(MatrixXd::Identity(3, 3), VectorXd::Zero(3), 1.0), EllPredictorMode::OnlineVertex);
  for (int i = 0; i < 6; ++i) a.step(d.y[size_t(i)], d.u[size_t(i)]);
  const std::vector<double> s = a.save_state();
  // The working set is the text at the end: its characters are '0'/'1' codes.
  bool has_zero = false;
  for (size_t i = s.size() - 1; i > 0 && (s[i] == '0' || s[i] == '1'); --i) has_zero |= s[i] == '0';
  EXPECT_TRUE(has_zero) << "the working set after 6 steps should not hold every block";
  EllipsoidalPredictor b(des, Ellipsoid(MatrixXd::Identity(3, 3), VectorXd::Zero(3), 1.0), EllPredictorMode::OnlineVertex);
  b.restore_state(s);
  for (int i = 6; i < 12; ++i) {
    const Ellipsoid ea = a.step(d.y[size_t(i)], d.u[size_t(i)]), eb = b.step(d.y[size_t(i)], d.u[size_t(i)]);
    std::vector<double> va, vb;
    append_ellipsoid(va, ea);
    append_ellipsoid(vb, eb);
    ASSERT_TRUE(same_bits(va, vb)) << "step " << i;
    ASSERT_TRUE(same_bits(a.save_state(), b.save_state()));
  }
  EXPECT_EQ(a.fallback_steps(), b.fallback_steps());
}

/// A solver failure inside an online step (forced: one interior-point iteration) is not an
/// error: the step uses the design's certified (β, L, σ) — the Offline step — and counts in
/// fallback_steps(); a normal solve does not.
TEST(StateEllipsoidal, ForcedSolverFailureFallsBackToTheDesignStep) {
  const LinearSystem sys = me17u();
  const Data d = simulate(sys, 12);
  EllDesignOptions o;
  o.beta = 0.7;
  const EllDesign des = design_ellipsoidal_offline(sys, o);
  for (EllPredictorMode mode : {EllPredictorMode::OnlineVertex, EllPredictorMode::OnlineScaled}) {
    SCOPED_TRACE(static_cast<int>(mode));
    EllipsoidalPredictor p(des, Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 4.0), mode);
    for (int i = 0; i < 4; ++i) p.step(d.y[size_t(i)], d.u[size_t(i)]);
    EXPECT_EQ(p.fallback_steps(), 0);
    lmi::SolverOptions bad;
    bad.max_iterations = 1;
    EXPECT_THROW(p.set_online_solver_options(lmi::SolverOptions{0}), InvalidArgumentError);
    p.set_online_solver_options(bad);
    for (int i = 4; i < 8; ++i) {
      const Ellipsoid before = p.current();
      const VectorXd &y = d.y[size_t(i)], &u = d.u[size_t(i)];
      const Ellipsoid next = p.step(y, u);
      EXPECT_EQ(p.fallback_steps(), i - 3);
      const EllDesign& D = p.design();
      EXPECT_EQ(p.last_beta(), D.beta);
      EXPECT_TRUE(p.last_gain() == D.L);
      // The design step, computed from the design's values.
      const LinearSystem& S = D.system;
      const VectorXd& c = before.center();
      const double rho_next = ell_rounding::round_up(ell_rounding::round_up(D.beta * before.level()) + D.sigma);
      const VectorXd cn = S.A() * c + S.B() * u + D.L * (y - S.C() * c - S.D() * u);
      const VectorXd dc = center_rounding_bound(S.A(), S.B(), D.L, S.C(), S.D(), c, y, u);
      const double rn = level_with_center_error(rho_next, ell_rounding::lambda_max_upper(D.P), dc);
      EXPECT_TRUE(next.center() == cn) << "step " << i;
      EXPECT_EQ(next.level(), rn) << "step " << i;
    }
    // The fallback counter is part of the state.
    EllipsoidalPredictor q(des, Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 4.0), mode);
    q.restore_state(p.save_state());
    EXPECT_EQ(q.fallback_steps(), 4);
    // With the default options again the online step is used (smaller than the design's).
    p.set_online_solver_options(lmi::SolverOptions{});
    p.step(d.y[8], d.u[8]);
    EXPECT_EQ(p.fallback_steps(), 4);
  }
}

Factory improved_factory(const EllDesign& design, CorrectionOption opt, ImprovedFeedback fb, const Data& d) {
  return [design, opt, fb, d] {
    auto e = std::make_shared<ImprovedEstimator>(design, Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 4.0), opt,
                                                 fb, EllPredictorMode::OnlineVertex);
    Subject s = saving_subject(e);
    s.step = [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)]); };
    s.sets = [e] {
      std::vector<double> v;
      append_ellipsoid(v, e->current());
      append_ellipsoid(v, e->prediction());
      append(v, e->lower());
      append(v, e->upper());
      v.push_back(e->last_correction_failed() ? 1.0 : 0.0);
      return v;
    };
    add_bad_yu(s, e.get(), d);
    return s;
  };
}

TEST(StateEllipsoidal, ImprovedEstimatorContinuesIdentically) {
  const LinearSystem sys = me17u();
  const Data d = simulate(sys, 20);
  EllDesignOptions o1, o2;
  o1.beta = 0.7;
  o2.beta = 0.8;
  const EllDesign d1 = design_ellipsoidal_offline(sys, o1), d2 = design_ellipsoidal_offline(sys, o2);
  const std::vector<double> foreign =
      EllipsoidalPredictor(d1, Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 4.0), EllPredictorMode::Offline)
          .save_state();
  check_subject(improved_factory(d1, CorrectionOption::DetNormalized, ImprovedFeedback::FixedShape, d),
                improved_factory(d2, CorrectionOption::DetNormalized, ImprovedFeedback::FixedShape, d), foreign, 4, 5);
  // Another correction option is another design.
  check_subject(improved_factory(d1, CorrectionOption::BallNormalized, ImprovedFeedback::OuterBound, d),
                improved_factory(d1, CorrectionOption::FixedShape, ImprovedFeedback::OuterBound, d), foreign, 3, 4);
}

TEST(StateEllipsoidal, DescriptorEstimatorContinuesIdentically) {
  const DescriptorSystem sys = setbound::testing::me19();
  Data d;
  for (int k = 0; k < 30; ++k) {
    VectorXd y(2), u(2);
    y << std::sin(0.3 * k), 0.5 * std::cos(0.2 * k);
    u << 0.1 * std::cos(0.5 * k), 0.2 * std::sin(0.1 * k);
    d.y.push_back(y);
    d.u.push_back(u);
  }
  EllDesignOptions o1, o2;
  o1.beta = 0.7;
  o2.beta = 0.8;
  const EllDesign d1 = design_descriptor_offline(sys, o1), d2 = design_descriptor_offline(sys, o2);
  auto factory = [&](const EllDesign& des) -> Factory {
    return [des, sys, d] {
      auto e = std::make_shared<DescriptorEstimator>(des, sys, Ellipsoid(MatrixXd::Identity(3, 3), VectorXd::Zero(3), 9.0));
      Subject s = saving_subject(e);
      s.step = [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)]); };
      s.sets = [e] {
        std::vector<double> v;
        append_ellipsoid(v, e->current());
        return v;
      };
      add_bad_yu(s, e.get(), d);
      return s;
    };
  };
  const std::vector<double> foreign = KalmanFilter(me17u(), VectorXd::Zero(2), MatrixXd::Identity(2, 2)).save_state();
  check_subject(factory(d1), factory(d2), foreign, 3, 5);
  // Saved before the first step (nothing remembered yet).
  check_subject(factory(d1), factory(d2), foreign, 0, 3);
}

TEST(StateEllipsoidal, KalmanFilterContinuesIdentically) {
  const LinearSystem sys = me17u();
  const Data d = simulate(sys, 20);
  auto factory = [&](double w) -> Factory {
    return [sys, d, w] {
      auto e = std::make_shared<KalmanFilter>(sys, VectorXd::Zero(2), MatrixXd::Identity(2, 2),
                                              w * MatrixXd::Identity(2, 2));
      Subject s = saving_subject(e);
      s.step = [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)]); };
      s.sets = [e] {
        std::vector<double> v;
        append(v, e->mean());
        append(v, e->covariance());
        append(v, e->predicted_mean());
        append(v, e->gain());
        return v;
      };
      add_bad_yu(s, e.get(), d);
      return s;
    };
  };
  const std::vector<double> foreign =
      ZonotopicEstimator(sys, Zonotope(VectorXd::Zero(2), MatrixXd::Identity(2, 2)), segment_min_gain).save_state();
  check_subject(factory(1.0), factory(2.0), foreign, 4, 6);
}

// ---- zonotopic -------------------------------------------------------------------------------

Factory zono_factory(const LinearSystem& sys, const ZonotopeGain& gain, Eigen::Index max_gen, const Data& d,
                     ZonotopeReduction red) {
  return [sys, gain, max_gen, d, red] {
    ZonotopicOptions opt;
    opt.max_generators = max_gen;
    auto e = std::make_shared<ZonotopicEstimator>(sys, Zonotope(VectorXd::Zero(sys.nx()), 2.0 * MatrixXd::Identity(sys.nx(), sys.nx())),
                                                  gain, opt);
    e->set_reduction(red);  // mutable: part of the state
    Subject s = saving_subject(e);
    s.step = [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)]); };
    s.sets = [e] {
      std::vector<double> v;
      const Zonotope Z = e->current_set();
      append(v, Z.center());
      append(v, Z.generators());
      append(v, e->current_lower());
      append(v, e->current_upper());
      const Zonotope P = e->prediction();
      append(v, P.center());
      append(v, P.generators());
      return v;
    };
    add_bad_yu(s, e.get(), d);
    return s;
  };
}

TEST(StateZonotopic, EveryGainRuleContinuesIdentically) {
  const std::vector<double> foreign = KalmanFilter(me17u(), VectorXd::Zero(2), MatrixXd::Identity(2, 2)).save_state();
  for (double a_rad : {0.0, 0.02}) {
    const LinearSystem sys = me17u(a_rad);
    const Data d = simulate(sys, 40);
    MatrixXd lam(1, 2), lam2(1, 2);
    lam << -0.3, 0.1;
    lam2 << -0.2, 0.1;
    SCOPED_TRACE(a_rad);
    // Segment minimisation (lazy path with the Gram matrix), with PCA reduction set after
    // construction (the fresh estimator has Combastel: the restored method must be used).
    check_subject(zono_factory(sys, segment_min_gain, 4, d, ZonotopeReduction::Pca),
                  zono_factory(sys, segment_min_gain, 5, d, ZonotopeReduction::Pca), foreign, 7, 8);
    // Fixed gains (P-radius), Girard reduction.
    check_subject(zono_factory(sys, ZonotopeGain::fixed(lam), 4, d, ZonotopeReduction::Girard),
                  zono_factory(sys, ZonotopeGain::fixed(lam2), 4, d, ZonotopeReduction::Girard), foreign, 5, 6);
    // Volume minimisation (explicit path: the rule sees the set).
    check_subject(zono_factory(sys, volume_min_gain, 4, d, ZonotopeReduction::Combastel),
                  zono_factory(sys, segment_min_gain, 4, d, ZonotopeReduction::Combastel), foreign, 5, 5);
  }
}

TEST(StateZonotopic, SavedBeforeTheFirstStepAndIntoAnotherInitialSet) {
  const LinearSystem sys = me17u();
  const Data d = simulate(sys, 20);
  ZonotopicOptions opt;
  opt.max_generators = 6;
  ZonotopicEstimator a(sys, Zonotope(VectorXd::Zero(2), MatrixXd::Identity(2, 2)), segment_min_gain, opt);
  for (int i = 0; i < 5; ++i) a.step(d.y[size_t(i)], d.u[size_t(i)]);
  const std::vector<double> s = a.save_state();
  // The initial set is not part of the design: a state restores into an estimator made with
  // another x0 (even with more generators, i.e. another work-array capacity).
  MatrixXd H0 = MatrixXd::Random(2, 9);
  ZonotopicEstimator b(sys, Zonotope(VectorXd::Ones(2), H0), segment_min_gain, opt);
  b.restore_state(s);
  for (int i = 5; i < 15; ++i) {
    const Zonotope za = a.step(d.y[size_t(i)], d.u[size_t(i)]), zb = b.step(d.y[size_t(i)], d.u[size_t(i)]);
    std::vector<double> va, vb;
    append(va, za.center());
    append(va, za.generators());
    append(vb, zb.center());
    append(vb, zb.generators());
    ASSERT_TRUE(same_bits(va, vb)) << "step " << i;
  }
  // And back: b's state (capacity of the 9-generator x0) into a.
  a.restore_state(b.save_state());
  const Zonotope za = a.step(d.y[15], d.u[15]), zb = b.step(d.y[15], d.u[15]);
  EXPECT_TRUE(za.center() == zb.center() && za.generators() == zb.generators());
}

// ---- thesis observers ------------------------------------------------------------------------

thesis::Plant ch2_plant(double a12 = 0.2) {
  MatrixXd A(2, 2), B(2, 1), F(2, 1), C(1, 2), Z(1, 1);
  A << 0.2, a12, 0, 0.5;
  B << 1, 1;
  F << 0, 0.1;
  C << 1, 0;
  Z << 0.1;
  return thesis::Plant(A, B, C, F, Z);
}

Data plant_data(const thesis::Plant& p, int N) {
  Data d;
  VectorXd x = VectorXd::Zero(p.nx());
  for (int k = 0; k < N; ++k) {
    VectorXd dd(p.F.cols()), v(p.Z.cols()), u(p.nu());
    for (Eigen::Index j = 0; j < dd.size(); ++j) dd(j) = wave(k, int(j));
    for (Eigen::Index j = 0; j < v.size(); ++j) v(j) = wave(k + 3, int(j));
    for (Eigen::Index j = 0; j < u.size(); ++j) u(j) = 0.5 * std::cos(0.3 * k + j);
    d.y.push_back(p.C * x + p.Z * v);
    d.u.push_back(u);
    x = p.A * x + p.F * dd;
    if (p.nu() > 0) x += p.B * u;
  }
  return d;
}

template <class O>
void append_box(std::vector<double>& v, const O& o) {
  append(v, o.lower());
  append(v, o.upper());
}

/// The compared state of the interval observers: the estimate x̂ and the box.
template <class O>
std::function<std::vector<double>()> xhat_and_box(const std::shared_ptr<O>& e) {
  return [e] {
    std::vector<double> v;
    append(v, e->xhat());
    append_box(v, *e);
    return v;
  };
}

TEST(StateThesis, EllipsoidalSMObserverContinuesIdentically) {
  using namespace thesis;
  const Plant p1 = ch2_plant(), p2 = ch2_plant(0.25);
  const Data d = plant_data(p1, 30);
  const EllipsoidalSMDesign des1 = design_ellipsoidal_sm_observer(p1, VectorXd::Ones(2));
  const EllipsoidalSMDesign des2 = design_ellipsoidal_sm_observer(p2, VectorXd::Ones(2));
  auto factory = [&](const Plant& p, const EllipsoidalSMDesign& des) -> Factory {
    return [p, des, d] {
      auto e = std::make_shared<EllipsoidalSMObserver>(p, des, VectorXd::Zero(2), 2.0);
      Subject s = saving_subject(e);
      s.step = [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)]); };
      s.sets = [e] {
        std::vector<double> v;
        append(v, e->center());
        append_box(v, *e);
        v.push_back(e->mu());
        return v;
      };
      add_bad_yu(s, e.get(), d);
      return s;
    };
  };
  const std::vector<double> foreign = KalmanFilter(me17u(), VectorXd::Zero(2), MatrixXd::Identity(2, 2)).save_state();
  check_subject(factory(p1, des1), factory(p2, des2), foreign, 5, 8);
}

TEST(StateThesis, LPVEllipsoidalSMObserverContinuesIdentically) {
  using namespace thesis;
  const LpvSystem s1 = setbound::testing::ch3_ex1(0.01), s2 = setbound::testing::ch3_ex1(0.02);
  const EllipsoidalSMDesign des1 = design_ellipsoidal_sm_observer_lpv(s1, VectorXd::Ones(2));
  const EllipsoidalSMDesign des2 = design_ellipsoidal_sm_observer_lpv(s2, VectorXd::Ones(2));
  Data d;
  std::vector<VectorXd> rho;
  for (int k = 0; k < 30; ++k) {
    d.y.push_back(VectorXd::Constant(1, std::sin(0.2 * k)));
    d.u.push_back(VectorXd::Constant(1, 0.3 * std::cos(0.1 * k)));
    rho.push_back(VectorXd::Constant(1, 0.075 + 0.025 * std::sin(0.7 * k)));
  }
  auto factory = [&](const LpvSystem& sys, const EllipsoidalSMDesign& des) -> Factory {
    return [sys, des, d, rho] {
      auto e = std::make_shared<LPVEllipsoidalSMObserver>(sys, des, VectorXd::Zero(2), 2.0);
      Subject s = saving_subject(e);
      s.step = [e, d, rho](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)], rho[size_t(i)]); };
      s.sets = [e] {
        std::vector<double> v;
        append(v, e->center());
        append_box(v, *e);
        append(v, e->weights());
        v.push_back(e->mu());
        return v;
      };
      s.bad_steps.emplace_back("inf y", [e, d, rho](int i) { e->step(inf_at(d.y[size_t(i)], 0), d.u[size_t(i)], rho[size_t(i)]); });
      s.bad_steps.emplace_back("NaN u", [e, d, rho](int i) { e->step(d.y[size_t(i)], nan_at(d.u[size_t(i)], 0), rho[size_t(i)]); });
      s.bad_steps.emplace_back("long y", [e, d, rho](int i) { e->step(VectorXd::Zero(2), d.u[size_t(i)], rho[size_t(i)]); });
      s.bad_steps.emplace_back("NaN rho", [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)], VectorXd::Constant(1, kNaN)); });
      s.bad_steps.emplace_back("rho outside", [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)], VectorXd::Constant(1, 5.0)); });
      s.bad_steps.emplace_back("short rho", [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)], VectorXd(0)); });
      return s;
    };
  };
  const std::vector<double> foreign = KalmanFilter(me17u(), VectorXd::Zero(2), MatrixXd::Identity(2, 2)).save_state();
  check_subject(factory(s1, des1), factory(s2, des2), foreign, 5, 8);
}

thesis::Plant ex451(double a00 = -1.1267) {
  MatrixXd A(2, 2), B(2, 2), F(2, 1), C(1, 2), Z(1, 1);
  A << a00, -1.3503, 1.1095, 1.2673;
  B << 0.0951, -0.1977, -0.2894, 0.1099;
  F << -0.1606, 0.1254;
  C << -0.2512, 0.1723;
  Z << -0.1542;
  return thesis::Plant(A, B, C, F, Z);
}

Box box_sym(Eigen::Index n, double r) { return Box(VectorXd::Constant(n, -r), VectorXd::Constant(n, r)); }

TEST(StateThesis, IntervalLuenbergerObserverContinuesIdentically) {
  using namespace thesis;
  const Plant p = ex451();
  const Data d = plant_data(p, 40);
  Box dbox(VectorXd::Constant(1, -0.5), VectorXd::Constant(1, 1.0));  // not centred: the centre offset moves
  auto factory = [&](double x0r, ErrorRecursion var) -> Factory {
    return [p, d, dbox, x0r, var] {
      IntervalObserverOptions opt;
      opt.variant = var;
      auto e = std::make_shared<IntervalLuenbergerObserver>(
          design_interval_luenberger(p, box_sym(2, x0r), VectorXd::Zero(2), dbox, box_sym(1, 1), opt));
      Subject s = saving_subject(e);
      s.step = [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)]); };
      s.sets = xhat_and_box(e);
      add_bad_yu(s, e.get(), d);
      return s;
    };
  };
  const std::vector<double> foreign = KalmanFilter(me17u(), VectorXd::Zero(2), MatrixXd::Identity(2, 2)).save_state();
  check_subject(factory(3, ErrorRecursion::Tight), factory(4, ErrorRecursion::Tight), foreign, 4, 8);
  check_subject(factory(3, ErrorRecursion::Wrapped), factory(3, ErrorRecursion::Tight), foreign, 4, 8);
}

TEST(StateThesis, NonlinearIntervalObserverWindowIsSaved) {
  using namespace thesis;
  MatrixXd A(2, 2), C(1, 2), Z(1, 1);
  A << 0.3, -0.7, 0.6, -0.5;
  C << 1, 0;
  Z << 1;
  const Plant p(A, MatrixXd::Identity(2, 2), C, MatrixXd::Identity(2, 2), Z);
  Data d;
  std::vector<Box> hb;
  for (int k = 0; k < 40; ++k) {
    d.y.push_back(VectorXd::Constant(1, std::sin(0.4 * k)));
    VectorXd u(2);
    u << std::sin(0.1 * k), std::cos(0.2 * k);
    d.u.push_back(u);
    const double r = 0.2 + 0.15 * std::sin(0.9 * k);  // varying radii: the window matters
    hb.emplace_back(VectorXd::Constant(2, 0.1 * std::cos(k) - r), VectorXd::Constant(2, 0.1 * std::cos(k) + r));
  }
  auto factory = [&](int window) -> Factory {
    return [p, d, hb, window] {
      NonlinearObserverOptions opt;
      opt.window = window;
      auto e = std::make_shared<NonlinearIntervalObserver>(
          design_nonlinear_interval_observer(p, box_sym(2, 2), VectorXd::Zero(2), box_sym(1, 0.1), {}, opt));
      Subject s = saving_subject(e);
      s.step = [e, d, hb](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)], hb[size_t(i)]); };
      s.sets = xhat_and_box(e);
      s.bad_steps.emplace_back("inf y", [e, d, hb](int i) { e->step(inf_at(d.y[size_t(i)], 0), d.u[size_t(i)], hb[size_t(i)]); });
      s.bad_steps.emplace_back("NaN u", [e, d, hb](int i) { e->step(d.y[size_t(i)], nan_at(d.u[size_t(i)], 1), hb[size_t(i)]); });
      s.bad_steps.emplace_back("short u", [e, d, hb](int i) { e->step(d.y[size_t(i)], VectorXd::Zero(1), hb[size_t(i)]); });
      s.bad_steps.emplace_back("h of wrong size", [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)], box_sym(3, 1)); });
      s.bad_steps.emplace_back("unbounded h", [e, d](int i) {
        e->step(d.y[size_t(i)], d.u[size_t(i)],
                Box(VectorXd::Constant(2, -std::numeric_limits<double>::infinity()), VectorXd::Zero(2)));
      });
      s.bad_steps.emplace_back("no h functor", [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)]); });
      return s;
    };
  };
  const std::vector<double> foreign = KalmanFilter(me17u(), VectorXd::Zero(2), MatrixXd::Identity(2, 2)).save_state();
  // window 4, saved after 9 steps: the ring buffer has wrapped and radii have left it.
  check_subject(factory(4), factory(5), foreign, 9, 10);
}

TEST(StateThesis, IntervalInvariantObserverContinuesIdentically) {
  using namespace thesis;
  const Plant p = ex451();
  const Data d = plant_data(p, 40);
  auto factory = [&](double x0r) -> Factory {
    return [p, d, x0r] {
      auto e = std::make_shared<IntervalInvariantObserver>(
          offline_error_sequence(p, box_sym(2, x0r), VectorXd::Zero(2), box_sym(1, 1), box_sym(1, 1)));
      Subject s = saving_subject(e);
      s.step = [e, d](int i) { e->step(d.y[size_t(i)], d.u[size_t(i)]); };
      s.sets = xhat_and_box(e);
      add_bad_yu(s, e.get(), d);
      return s;
    };
  };
  const std::vector<double> foreign = KalmanFilter(me17u(), VectorXd::Zero(2), MatrixXd::Identity(2, 2)).save_state();
  check_subject(factory(3), factory(4), foreign, 4, 8);
}

}  // namespace

// ---- C ABI -----------------------------------------------------------------------------------

#include "c_api_common.hpp"  // the C ABI (setbound.h) through the library's objects

namespace {

std::string last_error() { return sb_last_error(); }

TEST(StateCapi, EllipsoidalSaveRestoreAndErrors) {
  const double A[] = {-0.8, 0.2, -0.3, 0.1}, C[] = {-2, 1}, E[] = {-0.12, 0, 0.02, 0}, F[] = {0, 0.2};
  sb_linear_system* sys = nullptr;
  ASSERT_EQ(sb_linear_system_create(2, 1, 0, 2, A, nullptr, C, nullptr, E, F, nullptr, &sys), SB_OK);
  sb_ell_design* des = nullptr;
  ASSERT_EQ(sb_ell_design_offline(sys, SB_ELL_NORM_LOGDET, 0.7, &des), SB_OK);
  const double P0[] = {1, 0, 0, 1}, c0[] = {0, 0};
  sb_ellipsoidal *a = nullptr, *b = nullptr;
  ASSERT_EQ(sb_ellipsoidal_create(des, SB_ELL_ONLINE_VERTEX, 0, 0, 0, nullptr, P0, c0, 4.0, &a), SB_OK);
  ASSERT_EQ(sb_ellipsoidal_create(des, SB_ELL_ONLINE_VERTEX, 0, 0, 0, nullptr, P0, c0, 4.0, &b), SB_OK);
  double P[4], c[2], rho, lo[2], hi[2];
  for (int k = 0; k < 5; ++k) {
    const double y = std::sin(0.5 * k);
    ASSERT_EQ(sb_ellipsoidal_step(a, &y, nullptr, P, c, &rho, lo, hi), SB_OK);
  }
  int n = 0;
  ASSERT_EQ(sb_ellipsoidal_state_size(a, &n), SB_OK);
  ASSERT_GT(n, 4);
  std::vector<double> s(static_cast<size_t>(n));
  EXPECT_EQ(sb_ellipsoidal_save_state(a, s.data(), n - 1), SB_ERR_BUFFER_TOO_SMALL);
  EXPECT_EQ(last_error().rfind("sb_ellipsoidal_save_state: state:", 0), 0u) << last_error();
  ASSERT_EQ(sb_ellipsoidal_save_state(a, s.data(), n), SB_OK);
  ASSERT_EQ(sb_ellipsoidal_restore_state(b, s.data(), n), SB_OK);
  for (int k = 5; k < 10; ++k) {
    const double y = std::sin(0.5 * k);
    double Pb[4], cb[2], rhob, lob[2], hib[2];
    ASSERT_EQ(sb_ellipsoidal_step(a, &y, nullptr, P, c, &rho, lo, hi), SB_OK);
    ASSERT_EQ(sb_ellipsoidal_step(b, &y, nullptr, Pb, cb, &rhob, lob, hib), SB_OK);
    EXPECT_EQ(std::memcmp(c, cb, sizeof c), 0);
    EXPECT_EQ(std::memcmp(&rho, &rhob, sizeof rho), 0);
    EXPECT_EQ(std::memcmp(lo, lob, sizeof lo), 0);
  }
  // Corrupted: the handle is unchanged.
  std::vector<double> before(static_cast<size_t>(n));
  ASSERT_EQ(sb_ellipsoidal_save_state(b, before.data(), n), SB_OK);
  s[0] = 1.0;
  EXPECT_EQ(sb_ellipsoidal_restore_state(b, s.data(), n), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(last_error().rfind("sb_ellipsoidal_restore_state: state:", 0), 0u) << last_error();
  EXPECT_EQ(sb_ellipsoidal_restore_state(b, before.data(), n - 1), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_ellipsoidal_restore_state(b, nullptr, n), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_ellipsoidal_restore_state(nullptr, before.data(), n), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_ellipsoidal_state_size(a, nullptr), SB_ERR_INVALID_ARGUMENT);
  std::vector<double> after(static_cast<size_t>(n));
  ASSERT_EQ(sb_ellipsoidal_save_state(b, after.data(), n), SB_OK);
  EXPECT_TRUE(same_bits(before, after));
  // A Kalman state is refused by the ellipsoidal handle.
  const double m0[] = {0, 0}, G0[] = {1, 0, 0, 1};
  sb_kalman* kf = nullptr;
  ASSERT_EQ(sb_kalman_create(sys, m0, G0, nullptr, &kf), SB_OK);
  int nk = 0;
  ASSERT_EQ(sb_kalman_state_size(kf, &nk), SB_OK);
  std::vector<double> ks(static_cast<size_t>(nk));
  ASSERT_EQ(sb_kalman_save_state(kf, ks.data(), nk), SB_OK);
  EXPECT_EQ(sb_ellipsoidal_restore_state(b, ks.data(), nk), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("KalmanFilter"), std::string::npos) << last_error();
  EXPECT_EQ(sb_kalman_restore_state(kf, ks.data(), nk), SB_OK);
  sb_kalman_free(kf);
  sb_ellipsoidal_free(a);
  sb_ellipsoidal_free(b);
  sb_ell_design_free(des);
  sb_linear_system_free(sys);
}

TEST(StateCapi, ZonotopicAndIntervalObserverRoundTrip) {
  const double A[] = {-0.8, 0.2, -0.3, 0.1}, C[] = {-2, 1}, E[] = {-0.12, 0, 0.02, 0}, F[] = {0, 0.2};
  sb_linear_system* sys = nullptr;
  ASSERT_EQ(sb_linear_system_create(2, 1, 0, 2, A, nullptr, C, nullptr, E, F, nullptr, &sys), SB_OK);
  const double p0[] = {0, 0}, H0[] = {1, 0, 0, 1};
  sb_zonotopic *a = nullptr, *b = nullptr;
  ASSERT_EQ(sb_zonotopic_create(sys, SB_ZONO_GAIN_SEGMENT_MIN, nullptr, 4, 1, nullptr, 2, p0, H0, &a), SB_OK);
  ASSERT_EQ(sb_zonotopic_create(sys, SB_ZONO_GAIN_SEGMENT_MIN, nullptr, 4, 1, nullptr, 2, p0, H0, &b), SB_OK);
  double c[2], lo[2], hi[2];
  int m = 0;
  for (int k = 0; k < 6; ++k) {
    const double y = std::sin(0.5 * k);
    ASSERT_EQ(sb_zonotopic_step(a, &y, nullptr, c, lo, hi, &m), SB_OK);
  }
  int n = 0;
  ASSERT_EQ(sb_zonotopic_state_size(a, &n), SB_OK);
  std::vector<double> s(static_cast<size_t>(n));
  ASSERT_EQ(sb_zonotopic_save_state(a, s.data(), n), SB_OK);
  ASSERT_EQ(sb_zonotopic_restore_state(b, s.data(), n), SB_OK);
  for (int k = 6; k < 12; ++k) {
    const double y = std::sin(0.5 * k);
    double cb[2], lob[2], hib[2];
    int mb = 0;
    ASSERT_EQ(sb_zonotopic_step(a, &y, nullptr, c, lo, hi, &m), SB_OK);
    ASSERT_EQ(sb_zonotopic_step(b, &y, nullptr, cb, lob, hib, &mb), SB_OK);
    EXPECT_EQ(std::memcmp(lo, lob, sizeof lo), 0);
    EXPECT_EQ(std::memcmp(hi, hib, sizeof hi), 0);
    EXPECT_EQ(m, mb);
  }
  s.push_back(0.0);
  EXPECT_EQ(sb_zonotopic_restore_state(b, s.data(), n + 1), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(last_error().rfind("sb_zonotopic_restore_state: state:", 0), 0u) << last_error();
  sb_zonotopic_free(a);
  sb_zonotopic_free(b);
  sb_linear_system_free(sys);

  // Interval Luenberger observer.
  const double Ai[] = {0.5, 0.1, 0, 0.4}, Ci[] = {1, 0}, Fi[] = {0.1, 0.1}, Zi[] = {0.1};
  const double x0lo[] = {-1, -1}, x0hi[] = {1, 1}, xh0[] = {0, 0}, dlo[] = {-1}, dhi[] = {1};
  sb_interval_luenberger *oa = nullptr, *ob = nullptr;
  ASSERT_EQ(sb_interval_luenberger_create(2, 0, 1, 1, 1, Ai, nullptr, Ci, Fi, Zi, nullptr, x0lo, x0hi, xh0, dlo, dhi,
                                          dlo, dhi, SB_IOBS_TIGHT, &oa),
            SB_OK);
  ASSERT_EQ(sb_interval_luenberger_create(2, 0, 1, 1, 1, Ai, nullptr, Ci, Fi, Zi, nullptr, x0lo, x0hi, xh0, dlo, dhi,
                                          dlo, dhi, SB_IOBS_TIGHT, &ob),
            SB_OK);
  double xh[2];
  for (int k = 0; k < 4; ++k) {
    const double y = 0.1 * k;
    ASSERT_EQ(sb_interval_luenberger_step(oa, &y, nullptr, xh, lo, hi), SB_OK);
  }
  ASSERT_EQ(sb_interval_luenberger_state_size(oa, &n), SB_OK);
  s.assign(size_t(n), 0.0);
  ASSERT_EQ(sb_interval_luenberger_save_state(oa, s.data(), n), SB_OK);
  ASSERT_EQ(sb_interval_luenberger_restore_state(ob, s.data(), n), SB_OK);
  double xhb[2], lob[2], hib[2];
  ASSERT_EQ(sb_interval_luenberger_current(ob, xhb, lob, hib), SB_OK);
  ASSERT_EQ(sb_interval_luenberger_current(oa, xh, lo, hi), SB_OK);
  EXPECT_EQ(std::memcmp(lo, lob, sizeof lo), 0);
  EXPECT_EQ(std::memcmp(hi, hib, sizeof hi), 0);
  s[3] = kNaN;
  EXPECT_EQ(sb_interval_luenberger_restore_state(ob, s.data(), n), SB_ERR_INVALID_ARGUMENT);
  sb_interval_luenberger_free(oa);
  sb_interval_luenberger_free(ob);
}

}  // namespace
