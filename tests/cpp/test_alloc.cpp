// Allocation tests: the steady-state steps and the LMI solver's solve() must not use the heap.
// This executable replaces glibc's malloc family with counting versions (count_malloc.hpp), so
// it is built on its own, from the headers only (no library objects), and never with the
// sanitizers (AddressSanitizer owns malloc): in a SETBOUND_SANITIZE build it is the one test
// executable compiled without -fsanitize (tests/cpp/CMakeLists.txt), so CI still runs these
// checks while the other C++ tests run under ASan + UBSan.
//
// The LMI test has two independent layers: Eigen's runtime check (EIGEN_RUNTIME_NO_MALLOC +
// set_is_malloc_allowed(false), with eigen_assert redirected to a counter because Release
// builds define NDEBUG) and the interposed malloc, which also catches std::vector growth or any
// other heap use, even inside an out-of-line Eigen function.
#define EIGEN_RUNTIME_NO_MALLOC
#include <atomic>
namespace {
std::atomic<long> g_eigen_assert_failures{0};
}
#define eigen_assert(x) ((x) ? (void)0 : (void)g_eigen_assert_failures.fetch_add(1))

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdlib>
#include <random>
#include <vector>

#include "setbound/estimators/zonotopic/gain_estimator.hpp"
#include "setbound/lmi/classes.hpp"
#include "setbound/lmi/problem.hpp"
#include "setbound/lmi/solver.hpp"
#include "setbound/thesis/hinf_gain.hpp"
#include "setbound/thesis/lpv.hpp"

#include "count_malloc.hpp"  // this executable counts allocations
#include "thesis_test_systems.hpp"

using namespace setbound;
using namespace setbound::lmi;
using namespace setbound::thesis;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using setbound::testing::ch2_plant;
using setbound::testing::ch3_ex1;

namespace {

MatrixXd random_symmetric(std::mt19937& rng, int n) {
  std::normal_distribution<double> N(0.0, 1.0);
  MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = N(rng);
  return 0.5 * (A + A.transpose());
}


// Ch. 2 example (thesis.md §4.8).

}  // namespace

// --- zonotopic estimator (moved from test_zonotopic_alloc.cpp) ---
TEST(ZonotopicEstimatorAllocations, NoneInTheSteadyState) {
#ifndef SETBOUND_COUNT_MALLOC
  GTEST_SKIP() << "malloc cannot be counted here (not glibc, or a sanitizer build)";
#endif
  for (int n : {2, 6, 30})
    for (bool interval : {false, true})
      for (bool fixed : {false, true})
        for (ZonotopeReduction red : {ZonotopeReduction::Combastel, ZonotopeReduction::Girard, ZonotopeReduction::Pca}) {
          std::mt19937 gen(static_cast<unsigned>(n));
          std::normal_distribution<double> N;
          const int ny = n > 2 ? 4 : 1;
          Eigen::MatrixXd A(n, n), C(ny, n), B(n, 1), Arad = Eigen::MatrixXd::Zero(n, n);
          Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, n + ny), F = Eigen::MatrixXd::Zero(ny, n + ny);
          for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) A(i, j) = 0.3 * N(gen) / std::sqrt(double(n));
            E(i, i) = 0.01;
            B(i, 0) = N(gen);
          }
          for (int i = 0; i < ny; ++i) {
            for (int j = 0; j < n; ++j) C(i, j) = N(gen);
            F(i, n + i) = 0.1;
          }
          if (interval) Arad(0, n - 1) = 0.01;
          const LinearSystem sys(A, C, E, F, B, Eigen::MatrixXd(), Arad);
          ZonotopicOptions opt;
          opt.max_generators = (n == 30 ? 40 : 10) * n;
          opt.reduction = red;
          const ZonotopeGain gain =
              fixed ? ZonotopeGain::fixed(0.1 * Eigen::MatrixXd::Ones(ny, n)) : ZonotopeGain(segment_min_gain);
          ZonotopicEstimator est(sys, Zonotope(Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n)), gain, opt);
          Eigen::VectorXd y(ny), u(1);
          long before = 0;
          int reduced = 0;
          const int warm = n == 30 ? 40 : 30;
          for (int k = 0; k < warm + 30; ++k) {
            for (int i = 0; i < ny; ++i) y(i) = 0.1 * N(gen);
            u(0) = N(gen);
            if (k == warm) before = g_allocations.load();
            est.update(y, u);
            if (k >= warm) reduced += est.reduced_last_step() ? 1 : 0;
          }
          // PCA: Eigen's SelfAdjointEigenSolver allocates one Householder workspace per call.
          const long allowed = red == ZonotopeReduction::Pca ? 30 : 0;
          EXPECT_LE(g_allocations.load() - before, allowed)
              << "n " << n << " interval " << interval << " fixed " << fixed << " reduction " << static_cast<int>(red);
          EXPECT_EQ(reduced, 30) << "the steady state is the reducing one";
        }
}

TEST(ZonotopicEstimatorAllocations, TheCounterSeesEigenAllocations) {
#ifndef SETBOUND_COUNT_MALLOC
  GTEST_SKIP() << "malloc cannot be counted here";
#endif
  const long before = g_allocations.load();
  Eigen::VectorXd v = Eigen::VectorXd::Random(1000);
  EXPECT_GT(g_allocations.load() - before, 0);
  EXPECT_LE(v.cwiseAbs().maxCoeff(), 1.0);
}

// --- LMI solver (moved from test_lmi_solver.cpp) ---
TEST(LmiSolver, SolveDoesNotAllocateAfterSetup) {
#ifndef SETBOUND_COUNT_MALLOC
  GTEST_SKIP() << "malloc cannot be counted here";
#endif
  // Positive control: the interposed malloc sees an Eigen allocation and a vector growth.
  const long probe_before = g_allocations.load();
  {
    MatrixXd probe = MatrixXd::Random(20, 20);
    std::vector<int> v;
    v.push_back(1);
    volatile double sink = probe.sum() + v[0];
    (void)sink;
  }
  ASSERT_GE(g_allocations.load() - probe_before, 2) << "the malloc interposer is not active";

  // Online-sized problem: 4 blocks (7×7, 5×5, 3×3, 1×1), 12 variables, dense and sparse
  // coefficients, one equality.
  std::mt19937 rng(21);
  const int m = 12;
  LmiProblem p(m);
  VectorXd x0 = VectorXd::Random(m);
  VectorXd c = VectorXd::Zero(m);
  for (int n : {7, 5, 3, 1}) {
    std::vector<MatrixXd> Fs;
    MatrixXd F0 = MatrixXd::Identity(n, n);
    const MatrixXd Z0 = MatrixXd::Identity(n, n) + 0.1 * random_symmetric(rng, n).cwiseAbs();
    for (int i = 0; i < m; ++i) {
      MatrixXd Fi = (i % 3 == 0) ? MatrixXd(MatrixXd::Zero(n, n)) : random_symmetric(rng, n);
      if (i % 3 == 1) {  // sparse coefficient
        Fi.setZero();
        Fi(0, 0) = 1.0;
        if (n > 1) Fi(1, 0) = Fi(0, 1) = 0.5;
      }
      F0 -= x0(i) * Fi;
      c(i) += (Fi * Z0).trace();
      Fs.push_back(Fi);
    }
    p.add_block(F0, Fs);
  }
  MatrixXd Aeq = MatrixXd::Zero(1, m);
  Aeq(0, 1) = 1.0;
  VectorXd beq(1);
  beq << x0(1);
  p.set_equalities(Aeq, beq);
  p.set_objective(c);
  InteriorPointSolver solver(p);
  const SolveResult& first = solver.solve();  // warm-up (solver allocates nothing here either)
  ASSERT_EQ(first.status, SolveStatus::Optimal);
  const double obj = first.objective;

  g_eigen_assert_failures = 0;
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  const SolveResult& r = solver.solve();
  Eigen::internal::set_is_malloc_allowed(true);
  const long used = g_allocations.load() - before;
  EXPECT_EQ(g_eigen_assert_failures.load(), 0) << "Eigen allocated (or asserted) inside solve()";
  EXPECT_EQ(used, 0) << "the heap was used inside solve()";
  ASSERT_EQ(r.status, SolveStatus::Optimal);
  EXPECT_NEAR(r.objective, obj, 1e-12 * std::max(1.0, std::abs(obj)));
  EXPECT_GT(r.margin, -1e-6);
}

// --- thesis H-infinity observers (moved from test_thesis_hinf.cpp) ---
TEST(ThesisHinfObservers, StepDoesNotAllocate) {
#ifndef SETBOUND_COUNT_MALLOC
  GTEST_SKIP() << "malloc cannot be counted here";
#endif
  const Plant p = ch2_plant();
  const EllipsoidalSMDesign d = design_ellipsoidal_sm_observer(p, VectorXd::Ones(2));
  EllipsoidalSMObserver obs(p, d, VectorXd::Zero(2), 2.0);
  const LpvSystem sys = ch3_ex1();
  const EllipsoidalSMDesign dl = design_ellipsoidal_sm_observer_lpv(sys, VectorXd::Ones(2));
  LPVEllipsoidalSMObserver ol(sys, dl, VectorXd::Zero(2), 2.0);
  VectorXd u = VectorXd::Ones(1), rho = VectorXd::Constant(1, 0.07);
  // Readings of the true systems from x_0 = 0 without disturbance: consistent with the model, so
  // every step is the normal one (a step without some output restarts and may allocate).
  MatrixXd Al(2, 2);
  Al << 1, 0.07, 0, 1;  // A(ρ) and B(ρ) of ch3_ex1 at ρ = 0.07
  VectorXd Bl(2);
  Bl << 0, 0.07;
  VectorXd x = VectorXd::Zero(2), xl = VectorXd::Zero(2), t(2), y(1), yl(1);
  auto advance = [&] {
    y.noalias() = p.C * x;
    yl.noalias() = sys.C * xl;
    obs.step(y, u);
    ol.step(yl, u, rho);
    t.noalias() = p.A * x;
    t.noalias() += p.B * u;
    x.swap(t);
    t.noalias() = Al * xl;
    t += Bl * u(0);
    xl.swap(t);
  };
  advance();
  {
    const long c0 = g_allocations.load();
    VectorXd probe = VectorXd::Random(64);  // the counter sees Eigen's heap allocations
    EXPECT_GT(g_allocations.load(), c0);
    EXPECT_TRUE(probe.allFinite());
  }
  const long before = g_allocations.load();
  for (int k = 0; k < 100; ++k) advance();
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_FALSE(obs.last_check().flagged());
  EXPECT_FALSE(ol.last_check().flagged());
}
