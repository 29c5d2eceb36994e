// A zero row of C (issue 26 point 6): an output that measures only noise (and possibly D u)
// says nothing about x. Every gain rule skips its strip, volume minimisation included (it used
// to fail at the first step: a Strip cannot have a zero normal). Skipping is exact, so the
// sets are bit-for-bit those of the same system without that output (not merely as tight:
// a λ = 0 correction would only have added rounding terms), and they contain the true state.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "setbound/estimators/zonotopic/volume_min.hpp"
#include "setbound/estimators/zonotopic/gain_estimator.hpp"

using namespace setbound;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

double wave(int k, int j) {
  const double s = std::sin(1.3 * k + 0.7 * j + 0.1 * k * j);
  return (k + j) % 5 == 0 ? (s >= 0 ? 1.0 : -1.0) : s;
}

/// ME17-like system with a second output y2 = 0.5 u + 0.3 w3 (zero row of C).
LinearSystem with_noise_output(double a_rad) {
  MatrixXd A(2, 2), C(2, 2), E(2, 3), F(2, 3), B(2, 1), D(2, 1);
  A << -0.8, 0.2, -0.3, 0.1;
  C << -2, 1, 0, 0;
  E << -0.12, 0, 0, 0.02, 0, 0;
  F << 0, 0.2, 0, 0, 0, 0.3;
  B << 1, 0.5;
  D << 0.1, 0.5;
  return LinearSystem(A, C, E, F, B, D, MatrixXd::Constant(2, 2, a_rad));
}
/// The same system without the second output.
LinearSystem without_it(const LinearSystem& s) {
  return LinearSystem(s.A(), s.C().topRows(1), s.E(), s.F().topRows(1), s.B(), s.D().topRows(1), s.A_rad());
}

struct Trace {
  std::vector<VectorXd> x, y, u;
};
Trace simulate(const LinearSystem& s, int N) {
  Trace r;
  VectorXd x = VectorXd::Zero(2);
  for (int k = 0; k < N; ++k) {
    VectorXd w(3), u(1);
    for (int j = 0; j < 3; ++j) w(j) = wave(k, j);
    u << 0.5 * std::cos(0.4 * k);
    r.x.push_back(x);
    r.y.push_back(s.C() * x + s.D() * u + s.F() * w);
    r.u.push_back(u);
    x = s.A() * x + s.B() * u + s.E() * w;
  }
  return r;
}

void expect_same_as_without_the_output(const ZonotopeGain& full_gain, const ZonotopeGain& reduced_gain, double a_rad,
                                       const std::string& what) {
  SCOPED_TRACE(what);
  const LinearSystem full = with_noise_output(a_rad), reduced = without_it(full);
  const Trace r = simulate(full, 30);
  ZonotopicOptions opt;
  opt.max_generators = 5;
  const Zonotope x0(VectorXd::Zero(2), 2.0 * MatrixXd::Identity(2, 2));
  ZonotopicEstimator a(full, x0, full_gain, opt), b(reduced, x0, reduced_gain, opt);
  for (int k = 0; k < 30; ++k) {
    const Zonotope za = a.step(r.y[size_t(k)], r.u[size_t(k)]);
    const Zonotope zb = b.step(r.y[size_t(k)].head(1), r.u[size_t(k)]);
    ASSERT_TRUE(za.center() == zb.center() && za.generators() == zb.generators()) << "step " << k;
    ASSERT_TRUE(a.current_lower() == b.current_lower() && a.current_upper() == b.current_upper()) << "step " << k;
    const VectorXd& x = r.x[size_t(k)];
    ASSERT_TRUE((a.current_lower().array() <= x.array()).all() && (x.array() <= a.current_upper().array()).all())
        << "step " << k << ": the true state is outside the set";
  }
}

TEST(ZonotopicZeroRowOfC, VolumeMinimisationSkipsTheStrip) {
  expect_same_as_without_the_output(volume_min_gain, volume_min_gain, 0.0, "volume_min");
}

TEST(ZonotopicZeroRowOfC, EveryGainRuleSkipsTheStrip) {
  MatrixXd lam(2, 2), lam1(1, 2);
  lam << -0.3, 0.1, 7.0, -5.0;  // the zero row's gain is never used
  lam1 << -0.3, 0.1;
  for (double a_rad : {0.0, 0.01}) {
    expect_same_as_without_the_output(segment_min_gain, segment_min_gain, a_rad, "segment_min");
    expect_same_as_without_the_output(ZonotopeGain::fixed(lam), ZonotopeGain::fixed(lam1), a_rad, "fixed");
    expect_same_as_without_the_output(volume_min_gain, volume_min_gain, a_rad, "volume_min");
  }
  // A custom rule is never called for the zero row (it would receive a strip without a normal).
  int calls = 0;
  ZonotopeGainRule counting = [&calls](const Zonotope& Z, const StripMeasurement& m) {
    ++calls;
    EXPECT_EQ(m.output, 0);
    return segment_min_gain(Z, m);
  };
  const LinearSystem full = with_noise_output(0.0);
  const Trace r = simulate(full, 5);
  ZonotopicEstimator e(full, Zonotope(VectorXd::Zero(2), MatrixXd::Identity(2, 2)), counting);
  for (int k = 0; k < 5; ++k) e.step(r.y[size_t(k)], r.u[size_t(k)]);
  EXPECT_EQ(calls, 5);
}

}  // namespace
