// Ellipsoidal estimators from C++: per-step medians of every method, the offline design time
// and the Kalman step, on EX-BC14 (papers.md §1.4) and a random 6-state system. Built with
// -DSETBOUND_BUILD_BENCH=ON. Output: a table on stdout, and with a file argument the lines
// "system<TAB>what<TAB>ms" that bench/bench_ellipsoidal.py --cpp merges into docs/benchmarks.md.
//
//   build/bench/bench_ellipsoidal_cpp [steps] [out.tsv]
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "bench_stats.hpp"
#include "setbound/estimators/ellipsoidal/lmi_estimators.hpp"
#include "setbound/estimators/ellipsoidal/improved_estimator.hpp"
#include "setbound/estimators/point/kalman.hpp"

using namespace setbound;
using Clock = std::chrono::steady_clock;

using setbound_bench::median;

namespace {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

LinearSystem bc14() {
  Eigen::MatrixXd A(3, 3), E(3, 5), C(2, 3), F(2, 5);
  A << 1, 0, 0.2, 0, 0.8, 1, 0, 0, 1;
  E << 0.1, 0, 0, 0, 0, 0, 0.05, 0, 0, 0, 0, 0, 0.05, 0, 0;
  C << 1, 0, 2, 0, -1, 1;
  F << 0, 0, 0, 0.15, 0, 0, 0, 0, 0, 0.15;
  return LinearSystem(A, C, E, F);
}

/// splitmix64 with uniforms from the top 53 bits and Box-Muller normals: the generator of
/// bench_ellipsoidal.py too, so that both programs time the same random system.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double normal() {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(6.283185307179586 * u2);
  }
  Eigen::MatrixXd normals(int rows, int cols) {  // row by row, as the Python side
    Eigen::MatrixXd M(rows, cols);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) M(i, j) = normal();
    return M;
  }
};

LinearSystem random6(std::uint64_t seed) {
  SplitMix64 g{seed};
  for (;;) {
    Eigen::MatrixXd A = g.normals(6, 6);
    A *= 0.9 / A.eigenvalues().cwiseAbs().maxCoeff();
    const Eigen::MatrixXd C = g.normals(2, 6);
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(6, 6), F = Eigen::MatrixXd::Zero(2, 6);
    E.leftCols(4) = 0.1 * g.normals(6, 4);
    F(0, 4) = 0.1;
    F(1, 5) = 0.1;
    if (check_detectability(A, C).detectable) return LinearSystem(A, C, E, F);
  }
}

/// Measurements of a simulated run (uniform disturbances), one column per step.
Eigen::MatrixXd simulate(const LinearSystem& s, int steps, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(s.nx());
  Eigen::MatrixXd Y(s.ny(), steps);
  for (int k = 0; k < steps; ++k) {
    Eigen::VectorXd w(s.nw());
    for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = U(gen);
    Y.col(k) = s.C() * x + s.F() * w;
    x = s.A() * x + s.E() * w;
  }
  return Y;
}

struct Row {
  std::string system, what;
  double ms;
};

void bench(const std::string& label, const LinearSystem& s, int steps, std::vector<Row>& rows) {
  const Ellipsoid x0(Eigen::MatrixXd::Identity(s.nx(), s.nx()), Eigen::VectorXd::Zero(s.nx()), 1.0);
  std::vector<double> dt;
  EllDesign d = [&] {
    std::vector<double> t;
    std::optional<EllDesign> out;
    for (int r = 0; r < 3; ++r) {
      const auto t0 = Clock::now();
      out.emplace(design_ellipsoidal_offline(s));
      t.push_back(ms_since(t0));
    }
    rows.push_back({label, "offline design", median(t)});
    return *out;
  }();
  const Eigen::MatrixXd Y = simulate(s, steps, 1);
  const Eigen::VectorXd u(0);
  auto time_steps = [&](const std::string& what, const std::function<void(const Eigen::VectorXd&)>& step) {
    std::vector<double> t;
    for (int k = 0; k < steps; ++k) {
      const Eigen::VectorXd y = Y.col(k);
      const auto t0 = Clock::now();
      step(y);
      if (k >= 5) t.push_back(ms_since(t0));
    }
    rows.push_back({label, what, median(t)});
  };
  {
    EllipsoidalPredictor e(d, x0, EllPredictorMode::Offline);
    time_steps("offline step", [&](const Eigen::VectorXd& y) { e.step(y, u); });
  }
  {
    EllipsoidalPredictor e(d, x0, EllPredictorMode::OnlineVertex);
    time_steps("online vertex step", [&](const Eigen::VectorXd& y) { e.step(y, u); });
  }
  {
    EllipsoidalPredictor e(d, x0, EllPredictorMode::OnlineScaled);
    time_steps("online scaled step", [&](const Eigen::VectorXd& y) { e.step(y, u); });
  }
  // The same with the LMI solved at every step (set_reuse_tolerance(0)): the cost of one
  // online LMI solve with its certification.
  {
    EllipsoidalPredictor e(d, x0, EllPredictorMode::OnlineVertex);
    e.set_reuse_tolerance(0.0);
    time_steps("online vertex step, solve every step", [&](const Eigen::VectorXd& y) { e.step(y, u); });
  }
  {
    EllipsoidalPredictor e(d, x0, EllPredictorMode::OnlineScaled);
    e.set_reuse_tolerance(0.0);
    time_steps("online scaled step, solve every step", [&](const Eigen::VectorXd& y) { e.step(y, u); });
  }
  {
    ImprovedEstimator e(d, x0);
    time_steps("improved step", [&](const Eigen::VectorXd& y) { e.step(y, u); });
  }
  {
    ImprovedCorrector c(s, CorrectionOption::DetNormalized);
    EllipsoidalPredictor e(d, x0, EllPredictorMode::Offline);
    time_steps("improved correction alone", [&](const Eigen::VectorXd& y) {
      c.correct(e.current(), y, u);
      e.step(y, u);
    });
  }
  {
    KalmanFilter kf(s, Eigen::VectorXd::Zero(s.nx()), Eigen::MatrixXd::Identity(s.nx(), s.nx()));
    time_steps("Kalman step", [&](const Eigen::VectorXd& y) { kf.step(y, u); });
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 300;
  std::vector<Row> rows;
  bench("EX-BC14 (n=3, n_y=2, n_ω=5)", bc14(), steps, rows);
  bench("random 6-state (n_y=2, n_ω=6)", random6(6), steps, rows);
  std::printf("%-34s %-38s %12s\n", "system", "what", "median ms");
  for (const Row& r : rows) std::printf("%-34s %-38s %12.4f\n", r.system.c_str(), r.what.c_str(), r.ms);
  if (argc > 2) {
    std::ofstream out(argv[2]);
    for (const Row& r : rows) out << r.system << '\t' << r.what << '\t' << r.ms << '\n';
  }
  return 0;
}
