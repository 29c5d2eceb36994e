// Thesis Ch. 2–3 H∞ set-membership observers from C++: offline design times (Algorithm 2 on
// the Ch. 2 example, Algorithm 3 on Ch. 3 Ex 1 and the Lorenz Ex 2, BRL on Ex 1.5) and the
// per-step time of EllipsoidalSMObserver and LPVEllipsoidalSMObserver (n ≤ 4; medians of
// repeated runs). Built with -DSETBOUND_BUILD_BENCH=ON. Output: a markdown table.
//
//   build/bench_hinf_cpp [steps]
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "bench_stats.hpp"
#include "setbound/thesis/lpv.hpp"

using namespace setbound;
using namespace setbound::thesis;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using Clock = std::chrono::steady_clock;

using setbound_bench::median;

namespace {

double time_ms(const std::function<void()>& f, int reps) {
  std::vector<double> t;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = Clock::now();
    f();
    t.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  return median(t);
}

Plant ch2() {
  MatrixXd A(2, 2), B(2, 1), F(2, 1), C(1, 2), Z(1, 1);
  A << 0.2, 0.2, 0, 0.5;
  B << 1, 1;
  F << 0, 0.1;
  C << 1, 0;
  Z << 0.1;
  return Plant(A, B, C, F, Z);
}

Plant random4(std::mt19937& rng) {
  std::normal_distribution<double> N;
  MatrixXd A(4, 4), B(4, 1), F(4, 2), C(2, 4), Z = 0.1 * MatrixXd::Identity(2, 2);
  for (Eigen::Index i = 0; i < A.size(); ++i) A(i) = N(rng);
  A *= 0.95 / hinf_detail::spectral_radius(A);
  for (Eigen::Index i = 0; i < B.size(); ++i) B(i) = N(rng);
  for (Eigen::Index i = 0; i < F.size(); ++i) F(i) = 0.3 * N(rng);
  for (Eigen::Index i = 0; i < C.size(); ++i) C(i) = N(rng);
  return Plant(A, B, C, F, Z);
}

LpvSystem ex1() {
  std::vector<MatrixXd> A, B;
  for (double r : {0.05, 0.1}) {
    MatrixXd a(2, 2), b(2, 1);
    a << 1, r, 0, 1;
    b << 0, r;
    A.push_back(a);
    B.push_back(b);
  }
  MatrixXd C(1, 2), Z(1, 1), th(2, 1);
  C << 1, 0;
  Z << 0.01;
  th << 0.05, 0.1;
  return LpvSystem(A, B, B, C, Z, th);
}

LpvSystem lorenz() {
  const double Ts = 0.08, s = 1, eta = 10;
  MatrixXd th(4, 2);
  th << -1, 9, -1, 11, 1, 9, 1, 11;
  std::vector<MatrixXd> A, B;
  for (int i = 0; i < 4; ++i) {
    const double r1 = th(i, 0), r2 = th(i, 1);
    MatrixXd a(3, 3), b(3, 1);
    a << 1 - Ts * s, Ts * s, 0, 0, 1 - Ts * eta, -Ts * r1, 0, Ts * r1, 1 - Ts * r2;
    b << 0, Ts * r1, 0;
    A.push_back(a);
    B.push_back(b);
  }
  MatrixXd C(1, 3), Z = MatrixXd::Zero(1, 1);
  C << 1, 0, 0;
  return LpvSystem(A, B, B, C, Z, th);
}

template <class StepFn>
double per_step_ns(StepFn step, int steps, int reps) {
  std::vector<double> t;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k) step(k);
    t.push_back(std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / steps);
  }
  return median(t);
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 100000;
  std::mt19937 rng(1);
  std::printf("| what | system | n | time |\n|---|---|---|---|\n");
  // Offline designs.
  {
    MatrixXd A(2, 2), E(2, 1);
    A << 0.2, 0.2, -0.2, 0.5;
    E << 0, 1;
    VectorXd wbar = VectorXd::Ones(1);
    std::printf("| brl_ellipsoidal_rpi | Ex 1.5 | 2 | %.2f ms |\n", time_ms([&] { brl_ellipsoidal_rpi(A, E, wbar); }, 21));
  }
  const Plant p2 = ch2();
  std::printf("| hinf_observer_gain (2.35) | Ch. 2 | 2 | %.2f ms |\n", time_ms([&] { hinf_observer_gain(p2); }, 21));
  EllipsoidalSMDesign d2;
  std::printf("| design_ellipsoidal_sm_observer (Alg. 2) | Ch. 2 | 2 | %.2f ms |\n",
              time_ms([&] { d2 = design_ellipsoidal_sm_observer(p2, VectorXd::Ones(2)); }, 11));
  const Plant p4 = random4(rng);
  EllipsoidalSMDesign d4;
  std::printf("| design_ellipsoidal_sm_observer (Alg. 2) | random | 4 | %.2f ms |\n",
              time_ms([&] { d4 = design_ellipsoidal_sm_observer(p4, VectorXd::Constant(4, 0.5)); }, 11));
  const LpvSystem l1 = ex1();
  EllipsoidalSMDesign dl1;
  std::printf("| design_ellipsoidal_sm_observer_lpv (Alg. 3) | Ch. 3 Ex 1 | 2 | %.2f ms |\n",
              time_ms([&] { dl1 = design_ellipsoidal_sm_observer_lpv(l1, VectorXd::Ones(2)); }, 11));
  const LpvSystem l2 = lorenz();
  EllipsoidalSMDesign dl2;
  EllipsoidalSMOptions o2 = default_lpv_options();
  o2.w_covariance = 4.0 / 3.0 * MatrixXd::Identity(2, 2);
  VectorXd wb2(2);
  wb2 << 2, 0;
  std::printf("| design_ellipsoidal_sm_observer_lpv (Alg. 3) | Ch. 3 Ex 2 (Lorenz) | 3 | %.2f ms |\n",
              time_ms([&] { dl2 = design_ellipsoidal_sm_observer_lpv(l2, wb2, o2); }, 11));
  // Online steps (inputs precomputed; no allocation in step()).
  const int T = 1024;
  std::uniform_real_distribution<double> U(-1, 1);
  auto make = [&](Eigen::Index rows) {
    MatrixXd M(rows, T);
    for (Eigen::Index i = 0; i < M.size(); ++i) M(i) = U(rng);
    return M;
  };
  {
    const MatrixXd Y = make(1), Uu = make(1);
    EllipsoidalSMObserver obs(p2, d2, VectorXd::Zero(2), 2.0);
    std::printf("| EllipsoidalSMObserver::step | Ch. 2 | 2 | %.0f ns |\n",
                per_step_ns([&](int k) { obs.step(Y.col(k % T), Uu.col(k % T)); }, steps, 7));
  }
  {
    const MatrixXd Y = make(2), Uu = make(1);
    EllipsoidalSMObserver obs(p4, d4, VectorXd::Zero(4), 2.0);
    std::printf("| EllipsoidalSMObserver::step | random | 4 | %.0f ns |\n",
                per_step_ns([&](int k) { obs.step(Y.col(k % T), Uu.col(k % T)); }, steps, 7));
  }
  {
    const MatrixXd Y = make(1), Uu = make(1);
    MatrixXd R(1, T);
    for (int k = 0; k < T; ++k) R(0, k) = 0.075 + 0.025 * U(rng);
    LPVEllipsoidalSMObserver obs(l1, dl1, VectorXd::Zero(2), 2.0);
    std::printf("| LPVEllipsoidalSMObserver::step | Ch. 3 Ex 1 (N = 2) | 2 | %.0f ns |\n",
                per_step_ns([&](int k) { obs.step(Y.col(k % T), Uu.col(k % T), R.col(k % T)); }, steps, 7));
  }
  {
    const MatrixXd Y = make(1), Uu = make(1);
    MatrixXd R(2, T);
    for (int k = 0; k < T; ++k) R(0, k) = U(rng), R(1, k) = 10 + U(rng);
    LPVEllipsoidalSMObserver obs(l2, dl2, VectorXd::Zero(3), 2.0);
    std::printf("| LPVEllipsoidalSMObserver::step | Ch. 3 Ex 2 (N = 4) | 3 | %.0f ns |\n",
                per_step_ns([&](int k) { obs.step(Y.col(k % T), Uu.col(k % T), R.col(k % T)); }, steps, 7));
  }
  return 0;
}
