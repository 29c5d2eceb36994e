// Thesis Chapter 4 interval observers from C++: per-step time of every online observer and the
// offline design times on Ex 4.5.1 (n = 2), Ex 4.5.2 (n = 4) and the nonlinear Ex 4.6.3
// (thesis.md §6.4–6.6). Built with -DSETBOUND_BUILD_BENCH=ON. Prints a markdown table with the
// median over `repeats` runs of `steps` steps each.
//
//   build/bench/bench_interval_obs_cpp [steps] [repeats]
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bench_stats.hpp"
#include "setbound/thesis/interval_observer.hpp"

using namespace setbound;
using namespace setbound::thesis;
using Clock = std::chrono::steady_clock;
using Eigen::MatrixXd;
using Eigen::VectorXd;

using setbound_bench::median;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

Box sym(Eigen::Index n, double r) { return Box(VectorXd::Constant(n, -r), VectorXd::Constant(n, r)); }

Plant ex451() {
  MatrixXd A(2, 2), B(2, 2), F(2, 1), C(1, 2), Z(1, 1);
  A << -1.1267, -1.3503, 1.1095, 1.2673;
  B << 0.0951, -0.1977, -0.2894, 0.1099;
  F << -0.1606, 0.1254;
  C << -0.2512, 0.1723;
  Z << -0.1542;
  return Plant(A, B, C, F, Z);
}

Plant ex452() {
  MatrixXd A(4, 4), B(4, 1), F(4, 4), C(1, 4), Z(1, 1);
  A << -0.1321, 1.1732, -0.1794, 0.1522, -0.8148, 0.1689, 0.3771, 0.9308, -0.0871, 0.4465, -0.0722, -0.3125, 0.0804,
      0.2929, -0.1056, -0.0631;
  B << 0.2598, -0.6342, 0.3125, -0.7458;
  F << 0.1264, 0, 0, -0.1267, 0, 0.09321, 0, 0, 0.0958, 0, 0.1325, 0, 0.1052, 0, 0, 0.2189;
  C << 0.3502, 0, 0.9298, 0.2398;
  Z << 0.2905;
  return Plant(A, B, C, F, Z);
}

Plant ex463() {
  MatrixXd A(2, 2), C(1, 2), Z(1, 1);
  A << 0.3, -0.7, 0.6, -0.5;
  C << 1, 0;
  Z << 1;
  return Plant(A, MatrixXd::Identity(2, 2), C, MatrixXd::Identity(2, 2), Z);
}

// Per-step time (ns) of obs.step over precomputed y/u sequences, median over repeats; the
// observer is rebuilt (untimed) for every repeat.
template <class Make, class Step>
double per_step_ns(Make make, Step step, int steps, int repeats) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    auto obs = make();
    const auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k) step(obs, k);
    t.push_back(seconds_since(t0) * 1e9 / steps);
  }
  return median(t);
}

template <class F>
double time_ms(F f, int repeats) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    f();
    t.push_back(seconds_since(t0) * 1e3);
  }
  return median(t);
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 20000;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 7;
  std::printf("| system | observer / design | n | median time |\n|---|---|---|---|\n");

  struct Case {
    const char* name;
    Plant plant;
    Box x0, d, v;
    VectorXd xhat0;
    double epsilon, inflation;
  };
  VectorXd xh4(4);
  xh4 << -2.5, 2.5, -2.5, 2.5;
  std::vector<Case> cases{{"Ex 4.5.1", ex451(), sym(2, 3), sym(1, 1), sym(1, 1), VectorXd::Zero(2), 0.01, 11},
                          {"Ex 4.5.2", ex452(), sym(4, 3), sym(4, 2), sym(1, 1), xh4, 0.05, 2}};
  for (const Case& c : cases) {
    const Eigen::Index n = c.plant.nx(), ny = c.plant.ny(), nu = c.plant.nu();
    std::vector<VectorXd> ys, us;
    for (int k = 0; k < steps; ++k) {
      ys.push_back(VectorXd::Constant(ny, 0.1 * std::sin(0.01 * k)));
      us.push_back(VectorXd::Constant(nu, 0.3 * std::cos(0.02 * k)));
    }
    HinfGain gain;
    const double t_gain = time_ms([&] { gain = hinf_observer_gain(c.plant); }, 3);
    std::printf("| %s | design: H∞ gain, LMI (4.13) | %d | %.3f ms |\n", c.name, int(n), t_gain);
    InvariantObserverOptions io;
    io.epsilon = c.epsilon;
    io.inflation = c.inflation;
    // the 4-D Φ_0 (thousands of vertices) dominates: time it once there
    std::optional<InvariantObserverDesign> D;
    const double t_off =
        time_ms([&] { D.emplace(offline_error_sequence(c.plant, gain, c.x0, c.xhat0, c.d, c.v, io)); }, n > 2 ? 1 : 5);
    std::printf("| %s | design: offline_error_sequence (Φ_0 with %d vertices, k* = %d) | %d | %.3f ms |\n", c.name,
                int(D->phi0.num_vertices()), D->k_star, int(n), t_off);
    const double t_lu_make = time_ms([&] { IntervalLuenbergerObserver o(c.plant, gain.L, c.x0, c.xhat0, c.d, c.v); }, 5);
    std::printf("| %s | IntervalLuenbergerObserver construction (power table) | %d | %.3f ms |\n", c.name, int(n),
                t_lu_make);
    for (auto variant : {ErrorRecursion::Tight, ErrorRecursion::Wrapped}) {
      const double ns = per_step_ns(
          [&] { return IntervalLuenbergerObserver(c.plant, gain.L, c.x0, c.xhat0, c.d, c.v, {variant}); },
          [&](IntervalLuenbergerObserver& o, int k) { o.step(ys[std::size_t(k)], us[std::size_t(k)]); }, steps,
          repeats);
      std::printf("| %s | IntervalLuenbergerObserver step (%s) | %d | %.0f ns |\n", c.name,
                  variant == ErrorRecursion::Tight ? "tight" : "wrapped", int(n), ns);
    }
    const double ns_inv = per_step_ns([&] { return IntervalInvariantObserver(*D); },
                                      [&](IntervalInvariantObserver& o, int k) {
                                        o.step(ys[std::size_t(k)], us[std::size_t(k)]);
                                      },
                                      steps, repeats);
    std::printf("| %s | IntervalInvariantObserver step | %d | %.0f ns |\n", c.name, int(n), ns_inv);
  }
  {
    const Plant p = ex463();
    VectorXd xh(2);
    xh << -2, 2;
    HinfGain gain;
    const double t_gain = time_ms([&] { gain = hinf_observer_gain(p); }, 3);
    std::printf("| Ex 4.6.3 | design: H∞ gain, LMI (4.46) | 2 | %.3f ms |\n", t_gain);
    std::vector<VectorXd> ys, us;
    for (int k = 0; k < steps; ++k) {
      ys.push_back(VectorXd::Constant(1, 0.1 * std::sin(0.01 * k)));
      VectorXd u(2);
      u << std::sin(0.1 * k), std::cos(0.2 * k);
      us.push_back(u);
    }
    const Box hb = sym(2, 0.8);
    NonlinearIntervalObserver probe(p, gain.L, sym(2, 3), xh, sym(1, 0.2));
    const double ns_box = per_step_ns([&] { return NonlinearIntervalObserver(p, gain.L, sym(2, 3), xh, sym(1, 0.2)); },
                                      [&](NonlinearIntervalObserver& o, int k) {
                                        o.step(ys[std::size_t(k)], us[std::size_t(k)], hb);
                                      },
                                      steps, repeats);
    std::printf("| Ex 4.6.3 | NonlinearIntervalObserver step, box given (window W = %d) | 2 | %.0f ns |\n",
                probe.window(), ns_box);
    auto hfun = [](const Box& xb, long k) {
      const Interval delta(-0.8, 0.8);
      std::vector<Interval> h{delta * ia::sin(Interval(0.5 * double(k)) * xb[1]),
                              delta * ia::sin(Interval(0.3 * double(k)))};
      return Box::from_intervals(h);
    };
    const double ns_fun =
        per_step_ns([&] { return NonlinearIntervalObserver(p, gain.L, sym(2, 3), xh, sym(1, 0.2), hfun); },
                    [&](NonlinearIntervalObserver& o, int k) { o.step(ys[std::size_t(k)], us[std::size_t(k)]); },
                    steps, repeats);
    std::printf("| Ex 4.6.3 | NonlinearIntervalObserver step, interval sin functor | 2 | %.0f ns |\n", ns_fun);
  }
  return 0;
}
