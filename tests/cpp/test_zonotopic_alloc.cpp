// The zonotopic estimator's step allocates nothing once its buffers are in use (segment
// minimisation and fixed gains, every reduction, known and interval A), except one small
// workspace inside Eigen's symmetric eigen-solver per PCA reduction. This binary interposes
// glibc's malloc with a counting one (Eigen allocates with malloc, not operator new), so it is
// a test file of its own; elsewhere, or under a sanitizer, the test is skipped.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <random>

#include "setbound/estimators/zonotopic.hpp"

#include "count_malloc.hpp"  // this executable counts allocations

using namespace setbound;

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
