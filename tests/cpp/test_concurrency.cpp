// Concurrency (issue 8): independent estimator objects used from several threads at once give
// bit-for-bit the results of sequential use, and the C ABI's last-error message is per thread.
// Issue 26: ONE handle of every mutable kind shared by eight threads, with the discipline that
// docs/c_api.md ("Threads") documents for it (every call on the handle under one mutex): the
// handle has no thread affinity, so the result equals a sequential replay, in the order the
// mutex admitted the calls, bit for bit (the test runs under ASan/UBSan in CI).
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
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "test_helpers.hpp"
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

using setbound::testing::same_bits;

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

// ---- one handle shared by eight threads (issue 26) ------------------------------------------

namespace {

constexpr int kSharers = 8;

// Disturbance sample j of step i of thread t, in [-0.9, 0.9]. Every kind below is driven with
// x = 0, u = 0 and y = (its output matrix) * w: every interleaving of the threads' streams is
// then a measurement sequence of the true trajectory x = 0, so the estimators that intersect
// with the measurements never meet an inconsistent one, whatever order the mutex picks.
double wave(int t, int i, int j) { return 0.9 * std::sin(1.7 * i + 2.3 * t + 0.9 * j + 0.5); }

// A mutable handle kind: make() creates a fresh handle (its designs are owned by the kind);
// step(h, t, i, out) does step i of thread t and appends its outputs; save(h, out) writes the
// saved state (empty function for the LMI problem, which has none); release(h) frees it.
struct SharedKind {
  std::string name;
  int steps_per_thread;
  std::function<void*()> make;
  std::function<int(void*, int, int, std::vector<double>&)> step;
  std::function<int(const void*, std::vector<double>&)> save;
  std::function<void(void*)> release;
};

template <class H, class SizeFn, class SaveFn>
int save_with(const void* h, std::vector<double>& out, SizeFn size, SaveFn save) {
  int n = 0;
  if (const int rc = size(static_cast<const H*>(h), &n); rc != SB_OK) return rc;
  out.assign(static_cast<size_t>(n), 0.0);
  return save(static_cast<const H*>(h), out.data(), n);
}

struct Logged {
  int thread, index;
};

// The test: eight threads step one handle, every call on it under one mutex; each thread also
// takes snapshots (saved states) under the mutex. The log records the order in which the
// mutex admitted the steps; a fresh handle replayed sequentially in that order must give every
// step's outputs and every snapshot bit for bit.
void check_shared_handle(const SharedKind& kind) {
  SCOPED_TRACE(kind.name);
  void* shared = kind.make();
  ASSERT_NE(shared, nullptr) << sb_last_error();
  std::mutex mutex;  // the user's discipline for a shared handle (docs/c_api.md, "Threads")
  std::vector<Logged> log;
  std::vector<std::pair<size_t, std::vector<double>>> snapshots;  // (steps admitted before, state)
  std::vector<std::vector<std::vector<double>>> outputs(kSharers);
  std::vector<std::string> failures(kSharers);
  std::atomic<int> ready{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < kSharers; ++t) {
    threads.emplace_back([&, t] {
      ready.fetch_add(1);
      while (ready.load() < kSharers) std::this_thread::yield();
      auto& mine = outputs[static_cast<size_t>(t)];
      mine.resize(static_cast<size_t>(kind.steps_per_thread));
      for (int i = 0; i < kind.steps_per_thread; ++i) {
        {
          std::lock_guard<std::mutex> lock(mutex);
          const int rc = kind.step(shared, t, i, mine[static_cast<size_t>(i)]);
          if (rc != SB_OK) {
            failures[static_cast<size_t>(t)] = "step " + std::to_string(i) + ": " + sb_last_error();
            return;
          }
          log.push_back({t, i});
        }
        std::this_thread::yield();  // let a waiting thread in: std::mutex is not fair
        if (kind.save && i % 3 == 1) {
          std::lock_guard<std::mutex> lock(mutex);
          std::vector<double> state;
          if (kind.save(shared, state) != SB_OK) {
            failures[static_cast<size_t>(t)] = std::string("save: ") + sb_last_error();
            return;
          }
          snapshots.emplace_back(log.size(), std::move(state));
        }
      }
    });
  }
  for (auto& th : threads) th.join();
  for (int t = 0; t < kSharers; ++t) ASSERT_EQ(failures[static_cast<size_t>(t)], "") << "thread " << t;
  ASSERT_EQ(log.size(), static_cast<size_t>(kSharers * kind.steps_per_thread));

  // Each thread's steps were admitted in its own program order (the log is a real interleaving).
  std::vector<int> next(kSharers, 0);
  for (const Logged& e : log) ASSERT_EQ(e.index, next[static_cast<size_t>(e.thread)]++) << "thread " << e.thread;
  // How often the handle changed threads (for the record: the scheduler decides, so it is not
  // asserted beyond what any order gives).
  int switches = 0;
  for (size_t k = 1; k < log.size(); ++k) switches += log[k].thread != log[k - 1].thread;
  ::testing::Test::RecordProperty("thread_switches", switches);
  EXPECT_GE(switches, kSharers - 1);

  // Sequential replay on a fresh handle, in the order the mutex admitted the steps.
  void* replay = kind.make();
  ASSERT_NE(replay, nullptr) << sb_last_error();
  std::vector<std::vector<double>> states_after(log.size() + 1);  // state after each prefix
  if (kind.save) ASSERT_EQ(kind.save(replay, states_after[0]), SB_OK) << sb_last_error();
  for (size_t k = 0; k < log.size(); ++k) {
    std::vector<double> out;
    ASSERT_EQ(kind.step(replay, log[k].thread, log[k].index, out), SB_OK) << sb_last_error();
    ASSERT_TRUE(same_bits(out, outputs[static_cast<size_t>(log[k].thread)][static_cast<size_t>(log[k].index)]))
        << "step " << k << " of the replay (thread " << log[k].thread << ", step " << log[k].index << ")";
    if (kind.save) ASSERT_EQ(kind.save(replay, states_after[k + 1]), SB_OK) << sb_last_error();
  }
  if (kind.save) {
    std::vector<double> final_shared;
    ASSERT_EQ(kind.save(shared, final_shared), SB_OK) << sb_last_error();
    EXPECT_TRUE(same_bits(final_shared, states_after.back())) << "final state";
    EXPECT_FALSE(same_bits(states_after.front(), states_after.back()));  // the steps did something
    EXPECT_FALSE(snapshots.empty());
    for (const auto& [prefix, state] : snapshots)
      EXPECT_TRUE(same_bits(state, states_after[prefix])) << "snapshot after " << prefix << " steps";
  }
  kind.release(replay);
  kind.release(shared);
}

// ---- the kinds ----

// Ellipsoidal estimators on the file's system (nx 2, ny 1, nu 1, nw 2; y = F w = 0.1 w_1).
void check_ellipsoidal(int method, int steps) {
  sb_linear_system* sys = nullptr;
  ASSERT_EQ(sb_linear_system_create(2, 1, 1, 2, A, B, C, nullptr, E, F, nullptr, &sys), SB_OK) << sb_last_error();
  sb_ell_design* d = nullptr;
  ASSERT_EQ(sb_ell_design_offline(sys, SB_ELL_NORM_LOGDET, std::nan(""), &d), SB_OK) << sb_last_error();
  const char* names[] = {"offline", "online vertex", "online scaled", "improved"};
  SharedKind kind{
      std::string("ellipsoidal ") + names[method], steps,
      [&]() -> void* {
        sb_ellipsoidal* h = nullptr;
        const double P0[] = {4.0, 0.0, 0.0, 4.0};
        sb_ellipsoidal_create(d, method, SB_ELL_CORR_DET_NORMALIZED, SB_ELL_FEEDBACK_FIXED_SHAPE,
                              SB_ELL_ONLINE_VERTEX, nullptr, P0, zero2, 1.0, &h);
        return h;
      },
      [](void* h, int t, int i, std::vector<double>& out) {
        const double y = 0.1 * wave(t, i, 1), u = 0.0;
        double P[4], c[2], rho, lo[2], hi[2];
        const int rc = sb_ellipsoidal_step(static_cast<sb_ellipsoidal*>(h), &y, &u, P, c, &rho, lo, hi);
        out.insert(out.end(), {P[0], P[1], P[2], P[3], c[0], c[1], rho, lo[0], lo[1], hi[0], hi[1]});
        return rc;
      },
      [](const void* h, std::vector<double>& out) {
        return save_with<sb_ellipsoidal>(h, out, sb_ellipsoidal_state_size, sb_ellipsoidal_save_state);
      },
      [](void* h) { sb_ellipsoidal_free(static_cast<sb_ellipsoidal*>(h)); }};
  check_shared_handle(kind);
  sb_ell_design_free(d);
  sb_linear_system_free(sys);
}

}  // namespace

TEST(SharedHandle, EllipsoidalOfflineEqualsReplayInAdmissionOrder) { check_ellipsoidal(SB_ELL_OFFLINE, 400); }
TEST(SharedHandle, EllipsoidalOnlineVertexEqualsReplayInAdmissionOrder) { check_ellipsoidal(SB_ELL_ONLINE_VERTEX, 40); }
TEST(SharedHandle, EllipsoidalOnlineScaledEqualsReplayInAdmissionOrder) { check_ellipsoidal(SB_ELL_ONLINE_SCALED, 40); }
TEST(SharedHandle, EllipsoidalImprovedEqualsReplayInAdmissionOrder) { check_ellipsoidal(SB_ELL_IMPROVED, 10); }

TEST(SharedHandle, EllipsoidalDescriptorEqualsReplayInAdmissionOrder) {
  // EX-ME19 (papers.md §4.2): nx 3, ny 2, nu 2, nw 5; y = F w = (0.5 w_3, 1.5 w_4).
  const double Ed[9] = {1, 0, 0, 0, 1, 0, 0, 0, 0};
  const double Ad[9] = {0.5, 0, 0, 0.8, 0.95, 0, -1, 0.5, 1};
  const double Bd[6] = {1, 0, 0, 1, 0, 0};
  const double Cd[6] = {1, 0, 1, 1, -1, 0};
  const double Dd[15] = {0.1, 0, 0, 0, 0, 0, 1.5, 0, 0, 0, 0, 0, 0.6, 0, 0};
  const double Fd[10] = {0, 0, 0, 0.5, 0, 0, 0, 0, 0, 1.5};
  sb_descriptor_system* ds = nullptr;
  ASSERT_EQ(sb_descriptor_system_create(3, 2, 2, 5, Ed, Ad, Bd, Cd, Dd, Fd, &ds), SB_OK) << sb_last_error();
  sb_ell_design* d = nullptr;
  ASSERT_EQ(sb_ell_design_descriptor(ds, SB_ELL_NORM_LOGDET, std::nan(""), &d), SB_OK) << sb_last_error();
  SharedKind kind{
      "ellipsoidal descriptor", 10,
      [&]() -> void* {
        const double P0[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, c0[3] = {0, 0, 0};
        sb_ellipsoidal* h = nullptr;
        sb_ellipsoidal_create(d, SB_ELL_DESCRIPTOR, 0, 0, 0, ds, P0, c0, 9.0, &h);
        return h;
      },
      [](void* h, int t, int i, std::vector<double>& out) {
        const double y[2] = {0.5 * wave(t, i, 3), 1.5 * wave(t, i, 4)}, u[2] = {0.0, 0.0};
        double P[9], c[3], rho, lo[3], hi[3];
        const int rc = sb_ellipsoidal_step(static_cast<sb_ellipsoidal*>(h), y, u, P, c, &rho, lo, hi);
        out.insert(out.end(), P, P + 9);
        out.insert(out.end(), {c[0], c[1], c[2], rho, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]});
        return rc;
      },
      [](const void* h, std::vector<double>& out) {
        return save_with<sb_ellipsoidal>(h, out, sb_ellipsoidal_state_size, sb_ellipsoidal_save_state);
      },
      [](void* h) { sb_ellipsoidal_free(static_cast<sb_ellipsoidal*>(h)); }};
  check_shared_handle(kind);
  sb_ell_design_free(d);
  sb_descriptor_system_free(ds);
}

TEST(SharedHandle, KalmanEqualsReplayInAdmissionOrder) {
  sb_linear_system* sys = nullptr;
  ASSERT_EQ(sb_linear_system_create(2, 1, 1, 2, A, B, C, nullptr, E, F, nullptr, &sys), SB_OK) << sb_last_error();
  SharedKind kind{
      "Kalman", 1000,
      [&]() -> void* {
        sb_kalman* h = nullptr;
        sb_kalman_create(sys, zero2, I2, nullptr, &h);
        return h;
      },
      [](void* h, int t, int i, std::vector<double>& out) {
        const double y = 0.1 * wave(t, i, 1), u = 0.0;
        double m[2], P[4];
        const int rc = sb_kalman_step(static_cast<sb_kalman*>(h), &y, &u, m, P);
        out.insert(out.end(), {m[0], m[1], P[0], P[1], P[2], P[3]});
        return rc;
      },
      [](const void* h, std::vector<double>& out) {
        return save_with<sb_kalman>(h, out, sb_kalman_state_size, sb_kalman_save_state);
      },
      [](void* h) { sb_kalman_free(static_cast<sb_kalman*>(h)); }};
  check_shared_handle(kind);
  sb_linear_system_free(sys);
}

namespace {

void check_zonotopic(int gain, const char* name, int steps) {
  sb_linear_system* sys = nullptr;
  ASSERT_EQ(sb_linear_system_create(2, 1, 1, 2, A, B, C, nullptr, E, F, nullptr, &sys), SB_OK) << sb_last_error();
  std::vector<double> lambdas;
  if (gain == SB_ZONO_GAIN_FIXED) {  // the P-radius design's gains
    lambdas.resize(2);
    double P[4], beta, tau, psi;
    ASSERT_EQ(sb_pradius_design(sys, 1, nullptr, 0, 1e-3, 1 - 1e-3, lambdas.data(), P, &beta, &tau, &psi, nullptr), SB_OK)
        << sb_last_error();
  }
  SharedKind kind{
      std::string("zonotopic ") + name, steps,
      [&]() -> void* {
        sb_zonotopic* h = nullptr;
        const double H0[] = {2.0, 0.0, 0.0, 2.0};
        sb_zonotopic_create(sys, gain, lambdas.empty() ? nullptr : lambdas.data(), 6, 1, nullptr, 2, zero2, H0, &h);
        return h;
      },
      [](void* h, int t, int i, std::vector<double>& out) {
        const double y = 0.1 * wave(t, i, 1), u = 0.0;
        double c[2], lo[2], hi[2];
        int m = 0;
        auto* z = static_cast<sb_zonotopic*>(h);
        int rc = sb_zonotopic_step(z, &y, &u, c, lo, hi, &m);
        if (rc != SB_OK) return rc;
        std::vector<double> p(2), H(static_cast<size_t>(2 * m));
        int cap = m;
        rc = sb_zonotopic_last_set(z, &cap, p.data(), H.data());
        out.insert(out.end(), {c[0], c[1], lo[0], lo[1], hi[0], hi[1], static_cast<double>(m), p[0], p[1]});
        out.insert(out.end(), H.begin(), H.end());
        return rc;
      },
      [](const void* h, std::vector<double>& out) {
        return save_with<sb_zonotopic>(h, out, sb_zonotopic_state_size, sb_zonotopic_save_state);
      },
      [](void* h) { sb_zonotopic_free(static_cast<sb_zonotopic*>(h)); }};
  check_shared_handle(kind);
  sb_linear_system_free(sys);
}

}  // namespace

TEST(SharedHandle, ZonotopicSegmentMinEqualsReplayInAdmissionOrder) {
  check_zonotopic(SB_ZONO_GAIN_SEGMENT_MIN, "segment", 400);
}
TEST(SharedHandle, ZonotopicVolumeMinEqualsReplayInAdmissionOrder) {
  check_zonotopic(SB_ZONO_GAIN_VOLUME_MIN, "volume", 60);
}
TEST(SharedHandle, ZonotopicFixedGainEqualsReplayInAdmissionOrder) {
  check_zonotopic(SB_ZONO_GAIN_FIXED, "P-radius", 400);
}

namespace {

void check_hinf(bool lpv) {
  sb_hinf_design* d = nullptr;
  if (lpv) {  // two vertices A(r) = [1 r; 0 1], B = F = [0; r], r in {0.05, 0.1}; theta = r
    const double Av[] = {1, 0.05, 0, 1, 1, 0.1, 0, 1}, Bv[] = {0, 0.05, 0, 0.1}, Zv[] = {0.01};
    const double theta[] = {0.05, 0.1}, wbar[] = {1.0, 1.0};
    ASSERT_EQ(sb_hinf_design_create(2, 2, 1, 1, 1, 1, 1, Av, Bv, C, Bv, Zv, theta, wbar, nullptr, SB_LAMBDA_DEFAULT,
                                    2, &d),
              SB_OK)
        << sb_last_error();
  } else {
    const double wbar[] = {1.0, 1.0};
    ASSERT_EQ(sb_hinf_design_create(1, 2, 1, 1, 1, 1, 0, A, B, C, Fh, Zh, nullptr, wbar, nullptr, SB_LAMBDA_DEFAULT,
                                    2, &d),
              SB_OK)
        << sb_last_error();
  }
  SharedKind kind{
      lpv ? "H-infinity LPV" : "H-infinity", 1000,
      [&]() -> void* {
        sb_hinf_observer* h = nullptr;
        sb_hinf_observer_create(d, zero2, 2.0, &h);
        return h;
      },
      [lpv](void* h, int t, int i, std::vector<double>& out) {
        const double y = (lpv ? 0.01 : 0.1) * wave(t, i, 1), u = 0.0, rho = 0.075 + 0.02 * wave(t, i, 2);
        double c[2], lo[2], hi[2], mu;
        const int rc = sb_hinf_observer_step(static_cast<sb_hinf_observer*>(h), &y, &u, lpv ? &rho : nullptr, c, lo,
                                             hi, &mu);
        out.insert(out.end(), {c[0], c[1], lo[0], lo[1], hi[0], hi[1], mu});
        return rc;
      },
      [](const void* h, std::vector<double>& out) {
        return save_with<sb_hinf_observer>(h, out, sb_hinf_observer_state_size, sb_hinf_observer_save_state);
      },
      [](void* h) { sb_hinf_observer_free(static_cast<sb_hinf_observer*>(h)); }};
  check_shared_handle(kind);
  sb_hinf_design_free(d);
}

}  // namespace

TEST(SharedHandle, HinfObserverEqualsReplayInAdmissionOrder) { check_hinf(false); }
TEST(SharedHandle, HinfLpvObserverEqualsReplayInAdmissionOrder) { check_hinf(true); }

TEST(SharedHandle, IntervalLuenbergerEqualsReplayInAdmissionOrder) {
  const double lo0[] = {-1.0, -1.0}, hi0[] = {1.0, 1.0}, dlo[] = {-1.0}, dhi[] = {1.0};
  SharedKind kind{
      "interval Luenberger", 1000,
      [&]() -> void* {
        sb_interval_luenberger* h = nullptr;
        sb_interval_luenberger_create(2, 1, 1, 1, 1, A, B, C, Fh, Zh, nullptr, lo0, hi0, zero2, dlo, dhi, dlo, dhi,
                                      SB_IOBS_TIGHT, &h);
        return h;
      },
      [](void* h, int t, int i, std::vector<double>& out) {
        const double y = 0.1 * wave(t, i, 1), u = 0.0;
        double xh[2], lo[2], hi[2];
        const int rc = sb_interval_luenberger_step(static_cast<sb_interval_luenberger*>(h), &y, &u, xh, lo, hi);
        out.insert(out.end(), {xh[0], xh[1], lo[0], lo[1], hi[0], hi[1]});
        return rc;
      },
      [](const void* h, std::vector<double>& out) {
        return save_with<sb_interval_luenberger>(h, out, sb_interval_luenberger_state_size,
                                                 sb_interval_luenberger_save_state);
      },
      [](void* h) { sb_interval_luenberger_free(static_cast<sb_interval_luenberger*>(h)); }};
  check_shared_handle(kind);
}

TEST(SharedHandle, IntervalNonlinearEqualsReplayInAdmissionOrder) {
  // thesis §6.6 plant (F = I): A = [0.3 -0.7; 0.6 -0.5], B = I, C = [1 0], Z = [1]; window 4,
  // so the window wraps during the run
  const double An[] = {0.3, -0.7, 0.6, -0.5}, Zn[] = {1.0};
  const double lo0[] = {-2.0, -2.0}, hi0[] = {2.0, 2.0}, vlo[] = {-0.1}, vhi[] = {0.1};
  SharedKind kind{
      "interval nonlinear", 1000,
      [&]() -> void* {
        sb_interval_nonlinear* h = nullptr;
        sb_interval_nonlinear_create(2, 2, 1, 1, An, I2, C, Zn, nullptr, lo0, hi0, zero2, vlo, vhi, 4, &h);
        return h;
      },
      [](void* h, int t, int i, std::vector<double>& out) {
        const double y = 0.1 * wave(t, i, 1), u[2] = {0.0, 0.0};
        const double r = 0.2 + 0.15 * wave(t, i, 2), c = 0.1 * wave(t, i, 3);
        const double hlo[] = {c - r, c - r}, hhi[] = {c + r, c + r};
        double xh[2], lo[2], hi[2];
        const int rc =
            sb_interval_nonlinear_step(static_cast<sb_interval_nonlinear*>(h), &y, u, hlo, hhi, xh, lo, hi);
        out.insert(out.end(), {xh[0], xh[1], lo[0], lo[1], hi[0], hi[1]});
        return rc;
      },
      [](const void* h, std::vector<double>& out) {
        return save_with<sb_interval_nonlinear>(h, out, sb_interval_nonlinear_state_size,
                                                sb_interval_nonlinear_save_state);
      },
      [](void* h) { sb_interval_nonlinear_free(static_cast<sb_interval_nonlinear*>(h)); }};
  check_shared_handle(kind);
}

TEST(SharedHandle, IntervalInvariantEqualsReplayInAdmissionOrder) {
  const double lo0[] = {-1.0, -1.0}, hi0[] = {1.0, 1.0}, dlo[] = {-1.0}, dhi[] = {1.0};
  sb_interval_invariant_design* d = nullptr;
  ASSERT_EQ(sb_interval_invariant_design_create(2, 1, 1, 1, 1, A, B, C, Fh, Zh, nullptr, nullptr, std::nan(""), lo0,
                                                hi0, zero2, dlo, dhi, dlo, dhi, 2.0, 0.0, 0.01, SB_IOBS_TIGHT, &d),
            SB_OK)
      << sb_last_error();
  SharedKind kind{
      "interval invariant", 1000,
      [&]() -> void* {
        sb_interval_invariant* h = nullptr;
        sb_interval_invariant_create(d, &h);
        return h;
      },
      [](void* h, int t, int i, std::vector<double>& out) {
        const double y = 0.1 * wave(t, i, 1), u = 0.0;
        double xh[2], lo[2], hi[2];
        const int rc = sb_interval_invariant_step(static_cast<sb_interval_invariant*>(h), &y, &u, xh, lo, hi);
        out.insert(out.end(), {xh[0], xh[1], lo[0], lo[1], hi[0], hi[1]});
        return rc;
      },
      [](const void* h, std::vector<double>& out) {
        return save_with<sb_interval_invariant>(h, out, sb_interval_invariant_state_size,
                                                sb_interval_invariant_save_state);
      },
      [](void* h) { sb_interval_invariant_free(static_cast<sb_interval_invariant*>(h)); }};
  check_shared_handle(kind);
  sb_interval_invariant_design_free(d);
}

TEST(SharedHandle, LmiProblemEqualsReplayInAdmissionOrder) {
  // min c . x  s.t. [1 + x0, x1; x1, 1 - x0] >= 0 (the unit disc in (x0, x1)). Even calls of a
  // thread set the objective, odd ones solve (and take the verified margin of the solution):
  // a solve sees the objective of whichever thread the mutex admitted last, so the results
  // depend on the order. The problem keeps its solver between solves.
  SharedKind kind{
      "LMI problem", 100,
      []() -> void* {
        sb_lmi_problem* h = nullptr;
        if (sb_lmi_problem_create(2, &h) != SB_OK) return nullptr;
        const double F0[] = {1, 0, 0, 1}, Fs[] = {1, 0, 0, -1, 0, 1, 1, 0}, c0[] = {1.0, 0.0};
        if (sb_lmi_add_block(h, 2, F0, Fs, nullptr) != SB_OK || sb_lmi_set_objective(h, c0) != SB_OK) {
          sb_lmi_problem_free(h);
          return nullptr;
        }
        return h;
      },
      [](void* h, int t, int i, std::vector<double>& out) {
        auto* p = static_cast<sb_lmi_problem*>(h);
        if (i % 2 == 0) {
          const double c[] = {wave(t, i, 0), wave(t, i, 1) + 0.05};
          return sb_lmi_set_objective(p, c);
        }
        sb_lmi_result r{};
        double x[2], margin;
        int rc = sb_lmi_solve(p, &r, x);
        if (rc != SB_OK) return rc;
        rc = sb_lmi_margin(p, x, &margin);
        out.insert(out.end(), {static_cast<double>(r.status), static_cast<double>(r.iterations), r.objective,
                               r.dual_objective, r.margin, x[0], x[1], margin});
        return rc;
      },
      {},  // no saved state: the outputs of every solve are compared
      [](void* h) { sb_lmi_problem_free(static_cast<sb_lmi_problem*>(h)); }};
  check_shared_handle(kind);
}
