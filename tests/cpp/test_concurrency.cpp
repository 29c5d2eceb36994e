// Concurrency (issue 8): independent estimator objects used from several threads at once give
// bit-for-bit the results of sequential use, and the C ABI's last-error message is per thread.
//
// The estimators are driven through the C ABI (one handle per object, as C, C++ and Python users
// of the shared library do); only c_api_common.hpp is included, which keeps this file's build
// small. Families: ellipsoidal online (an LMI per step on the bundled solver), zonotopic
// segment minimisation, Kalman, the interval Luenberger observer and the H-infinity
// set-membership observer. Designs are made inside each run, so the solver's own state is
// exercised concurrently as well.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "c_api_common.hpp"

namespace {

// x+ = A x + B u + E w, y = C x + F w (nx = 2, ny = 1, nu = 1, nw = 2)
const double A[] = {0.5, 0.1, 0.0, 0.4};
const double B[] = {1.0, 0.0};
const double C[] = {1.0, 0.0};
const double E[] = {0.1, 0.0, 0.0, 0.1};
const double F[] = {0.0, 0.1};
const double Fh[] = {0.1, 0.1};  // thesis plant: F d (nd = 1), Z v (nv = 1)
const double Zh[] = {0.1};
const double I2[] = {1.0, 0.0, 0.0, 1.0};
const double zero2[] = {0.0, 0.0};
constexpr int kSteps = 25;

#define SB_CHECK(call)                                                   \
  do {                                                                   \
    const int rc_ = (call);                                              \
    if (rc_ != SB_OK) {                                                  \
      ADD_FAILURE() << #call << " -> " << rc_ << ": " << sb_last_error(); \
      return out;                                                        \
    }                                                                    \
  } while (0)

// Deterministic measurements of a simulated trajectory (the same for every run).
std::vector<double> measurements() {
  std::vector<double> y(kSteps);
  double x0 = 0.3, x1 = -0.2;
  for (int k = 0; k < kSteps; ++k) {
    const double w0 = std::sin(0.7 * k), w1 = std::cos(1.3 * k), u = 0.1 * std::sin(0.2 * k);
    y[static_cast<size_t>(k)] = x0 + 0.1 * w1;
    const double n0 = 0.5 * x0 + 0.1 * x1 + u + 0.1 * w0, n1 = 0.4 * x1 + 0.1 * w1;
    x0 = n0;
    x1 = n1;
  }
  return y;
}

double input(int k) { return 0.1 * std::sin(0.2 * k); }

std::vector<double> run_ellipsoidal() {
  std::vector<double> out;
  const std::vector<double> y = measurements();
  sb_linear_system* sys = nullptr;
  SB_CHECK(sb_linear_system_create(2, 1, 1, 2, A, B, C, nullptr, E, F, nullptr, &sys));
  sb_ell_design* d = nullptr;
  SB_CHECK(sb_ell_design_offline(sys, SB_ELL_NORM_LOGDET, std::nan(""), &d));
  sb_ellipsoidal* est = nullptr;
  SB_CHECK(sb_ellipsoidal_create(d, SB_ELL_ONLINE_VERTEX, 0, 0, 0, nullptr, I2, zero2, 1.0, &est));
  for (int k = 0; k < kSteps; ++k) {
    double P[4], c[2], rho, lo[2], hi[2];
    const double u = input(k);
    SB_CHECK(sb_ellipsoidal_step(est, &y[static_cast<size_t>(k)], &u, P, c, &rho, lo, hi));
    out.insert(out.end(), {P[0], P[1], P[2], P[3], c[0], c[1], rho, lo[0], lo[1], hi[0], hi[1]});
  }
  sb_ellipsoidal_free(est);
  sb_ell_design_free(d);
  sb_linear_system_free(sys);
  return out;
}

std::vector<double> run_zonotopic() {
  std::vector<double> out;
  const std::vector<double> y = measurements();
  sb_linear_system* sys = nullptr;
  SB_CHECK(sb_linear_system_create(2, 1, 1, 2, A, B, C, nullptr, E, F, nullptr, &sys));
  sb_zonotopic* est = nullptr;
  SB_CHECK(sb_zonotopic_create(sys, SB_ZONO_GAIN_SEGMENT_MIN, nullptr, 8, 1, nullptr, 2, zero2, I2, &est));
  for (int k = 0; k < kSteps; ++k) {
    double c[2], lo[2], hi[2];
    int m = 0;
    const double u = input(k);
    SB_CHECK(sb_zonotopic_step(est, &y[static_cast<size_t>(k)], &u, c, lo, hi, &m));
    std::vector<double> p(2), H(static_cast<size_t>(2 * m));
    int cap = m;
    SB_CHECK(sb_zonotopic_last_set(est, &cap, p.data(), H.data()));
    out.insert(out.end(), {c[0], c[1], lo[0], lo[1], hi[0], hi[1], static_cast<double>(m)});
    out.insert(out.end(), H.begin(), H.end());
  }
  sb_zonotopic_free(est);
  sb_linear_system_free(sys);
  return out;
}

std::vector<double> run_kalman() {
  std::vector<double> out;
  const std::vector<double> y = measurements();
  sb_linear_system* sys = nullptr;
  SB_CHECK(sb_linear_system_create(2, 1, 1, 2, A, B, C, nullptr, E, F, nullptr, &sys));
  sb_kalman* kf = nullptr;
  SB_CHECK(sb_kalman_create(sys, zero2, I2, nullptr, &kf));
  for (int k = 0; k < kSteps; ++k) {
    double m[2], P[4];
    const double u = input(k);
    SB_CHECK(sb_kalman_step(kf, &y[static_cast<size_t>(k)], &u, m, P));
    out.insert(out.end(), {m[0], m[1], P[0], P[1], P[2], P[3]});
  }
  sb_kalman_free(kf);
  sb_linear_system_free(sys);
  return out;
}

std::vector<double> run_interval_observer() {
  std::vector<double> out;
  const std::vector<double> y = measurements();
  const double lo0[] = {-1.0, -1.0}, hi0[] = {1.0, 1.0}, dlo[] = {-1.0}, dhi[] = {1.0};
  sb_interval_luenberger* obs = nullptr;
  SB_CHECK(sb_interval_luenberger_create(2, 1, 1, 1, 1, A, B, C, Fh, Zh, nullptr, lo0, hi0, zero2, dlo, dhi, dlo,
                                         dhi, SB_IOBS_TIGHT, &obs));
  for (int k = 0; k < kSteps; ++k) {
    double xh[2], lo[2], hi[2];
    const double u = input(k);
    SB_CHECK(sb_interval_luenberger_step(obs, &y[static_cast<size_t>(k)], &u, xh, lo, hi));
    out.insert(out.end(), {xh[0], xh[1], lo[0], lo[1], hi[0], hi[1]});
  }
  sb_interval_luenberger_free(obs);
  return out;
}

std::vector<double> run_hinf_observer() {
  std::vector<double> out;
  const std::vector<double> y = measurements();
  const double wbar[] = {1.0, 1.0};
  sb_hinf_design* d = nullptr;
  SB_CHECK(sb_hinf_design_create(1, 2, 1, 1, 1, 1, 0, A, B, C, Fh, Zh, nullptr, wbar, nullptr, SB_LAMBDA_DEFAULT, 2,
                                 &d));
  sb_hinf_observer* obs = nullptr;
  SB_CHECK(sb_hinf_observer_create(d, zero2, 2.0, &obs));
  for (int k = 0; k < kSteps; ++k) {
    double c[2], lo[2], hi[2], mu;
    const double u = input(k);
    SB_CHECK(sb_hinf_observer_step(obs, &y[static_cast<size_t>(k)], &u, nullptr, c, lo, hi, &mu));
    out.insert(out.end(), {c[0], c[1], lo[0], lo[1], hi[0], hi[1], mu});
  }
  sb_hinf_observer_free(obs);
  sb_hinf_design_free(d);
  return out;
}

using Run = std::vector<double> (*)();
const Run kFamilies[] = {run_ellipsoidal, run_zonotopic, run_kalman, run_interval_observer, run_hinf_observer};
const char* const kNames[] = {"ellipsoidal online", "zonotopic", "Kalman", "interval Luenberger", "H-infinity"};
constexpr int kFamilyCount = 5;

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

}  // namespace

TEST(Concurrency, IndependentEstimatorsOnFourThreadsMatchSequentialBitForBit) {
  std::vector<std::vector<double>> reference;
  for (int f = 0; f < kFamilyCount; ++f) {
    reference.push_back(kFamilies[f]());
    ASSERT_FALSE(reference.back().empty()) << kNames[f];
    for (double v : reference.back()) ASSERT_TRUE(std::isfinite(v)) << kNames[f];
  }
  constexpr int kThreads = 4;
  // every thread runs every family, starting at a different one, so different families (and
  // the same family) run at the same time on different threads
  std::vector<std::vector<std::vector<double>>> results(kThreads);
  std::atomic<int> ready{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([t, &results, &ready] {
      ready.fetch_add(1);
      while (ready.load() < kThreads) std::this_thread::yield();
      results[static_cast<size_t>(t)].resize(kFamilyCount);
      for (int r = 0; r < 2; ++r)
        for (int i = 0; i < kFamilyCount; ++i) {
          const int f = (t + i) % kFamilyCount;
          results[static_cast<size_t>(t)][static_cast<size_t>(f)] = kFamilies[f]();
        }
    });
  }
  for (auto& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t)
    for (int f = 0; f < kFamilyCount; ++f)
      EXPECT_TRUE(same_bits(results[static_cast<size_t>(t)][static_cast<size_t>(f)], reference[static_cast<size_t>(f)]))
          << kNames[f] << " on thread " << t;
}

TEST(Concurrency, OneSharedDesignFeedsEstimatorsOnSeveralThreads) {
  // Objects built from one shared (const) design: creating and stepping them concurrently only
  // reads the design.
  sb_linear_system* sys = nullptr;
  ASSERT_EQ(sb_linear_system_create(2, 1, 1, 2, A, B, C, nullptr, E, F, nullptr, &sys), SB_OK);
  sb_ell_design* d = nullptr;
  ASSERT_EQ(sb_ell_design_offline(sys, SB_ELL_NORM_LOGDET, 0.7, &d), SB_OK);
  const std::vector<double> y = measurements();
  auto run = [&](std::vector<double>& out) {
    sb_ellipsoidal* est = nullptr;
    if (sb_ellipsoidal_create(d, SB_ELL_ONLINE_SCALED, 0, 0, 0, nullptr, I2, zero2, 1.0, &est) != SB_OK) return;
    for (int k = 0; k < kSteps; ++k) {
      double P[4], c[2], rho;
      const double u = input(k);
      if (sb_ellipsoidal_step(est, &y[static_cast<size_t>(k)], &u, P, c, &rho, nullptr, nullptr) != SB_OK) break;
      out.insert(out.end(), {P[0], P[1], P[2], P[3], c[0], c[1], rho});
    }
    sb_ellipsoidal_free(est);
  };
  std::vector<double> ref;
  run(ref);
  ASSERT_EQ(ref.size(), static_cast<size_t>(7 * kSteps));
  std::vector<std::vector<double>> outs(3);
  std::vector<std::thread> th;
  for (auto& o : outs) th.emplace_back(run, std::ref(o));
  for (auto& t : th) t.join();
  for (const auto& o : outs) EXPECT_TRUE(same_bits(o, ref));
  sb_ell_design_free(d);
  sb_linear_system_free(sys);
}

TEST(Concurrency, LastErrorIsPerThread) {
  // Thread A keeps provoking a NaN error, thread B a dimension error; each must always read its
  // own message, also while the other thread overwrites its own.
  std::atomic<int> ready{0};
  std::atomic<int> wrong_a{0}, wrong_b{0};
  constexpr int kIters = 2000;
  std::thread a([&] {
    ready.fetch_add(1);
    while (ready.load() < 2) std::this_thread::yield();
    const double P[] = {1.0}, c[] = {std::nan("")};
    for (int i = 0; i < kIters; ++i) {
      const int rc = sb_ellipsoid_validate(1, P, c, 1.0);
      const std::string msg = sb_last_error();
      if (rc != SB_ERR_NOT_FINITE || msg.rfind("sb_ellipsoid_validate: c", 0) != 0) wrong_a.fetch_add(1);
    }
  });
  std::thread b([&] {
    ready.fetch_add(1);
    while (ready.load() < 2) std::this_thread::yield();
    for (int i = 0; i < kIters; ++i) {
      const int rc = sb_box_volume(-3, nullptr, nullptr, nullptr);
      const std::string msg = sb_last_error();
      if (rc != SB_ERR_DIMENSION || msg.rfind("sb_box_volume: ", 0) != 0 || msg.find("-3") == std::string::npos)
        wrong_b.fetch_add(1);
    }
  });
  a.join();
  b.join();
  EXPECT_EQ(wrong_a.load(), 0);
  EXPECT_EQ(wrong_b.load(), 0);
  // this thread made no failing call: its message is untouched by the others
  const double P[] = {1.0}, c[] = {0.0};
  EXPECT_EQ(sb_ellipsoid_validate(1, P, c, 1.0), SB_OK);
}
