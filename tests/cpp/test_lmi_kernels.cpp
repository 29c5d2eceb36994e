// Tests of the fixed-size kernels of the LMI interior-point solver (solver.hpp): the small
// symmetric λ_min routine used for step lengths, the svec packing of the Schur complement, and
// the fixed-size path against the dynamic-size path on seeded random problems (same statuses,
// same optima, valid certificates).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "setbound/lmi/problem.hpp"
#include "setbound/lmi/solver.hpp"
#include "test_helpers.hpp"

using namespace setbound;
using namespace setbound::lmi;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

using setbound::testing::random_symmetric;

template <int N>
void check_lambda_min(std::mt19937& rng) {
  using Mat = Eigen::Matrix<double, N, N>;
  std::normal_distribution<double> nd(0.0, 1.0);
  for (int t = 0; t < 400; ++t) {
    Mat A = random_symmetric(rng, N);
    if (t % 4 == 1 && N > 1) {
      // Clustered smallest eigenvalues (double or nearly double).
      Eigen::SelfAdjointEigenSolver<Mat> es(A);
      Eigen::Matrix<double, N, 1> l = es.eigenvalues();
      l(1) = l(0) + (t % 8 == 1 ? 0.0 : 1e-9);
      A = es.eigenvectors() * l.asDiagonal() * es.eigenvectors().transpose();
      A = (0.5 * (A + A.transpose())).eval();
    } else if (t % 4 == 2) {
      A = Mat::Identity() * nd(rng) + 1e-12 * A;  // n-fold eigenvalue, perturbed
    } else if (t % 4 == 3) {
      A *= std::pow(10.0, (t % 17) - 8);  // scale invariance
    }
    const double expected = Eigen::SelfAdjointEigenSolver<Mat>(A, Eigen::EigenvaluesOnly).eigenvalues()(0);
    const double got = lmi::detail::lambda_min_small<N>(A);
    EXPECT_NEAR(got, expected, 1e-9 * A.norm()) << "N=" << N << " t=" << t;
  }
  // Exact cases: diagonal and zero matrices.
  Mat D = Mat::Zero();
  for (int i = 0; i < N; ++i) D(i, i) = 3.0 - i;
  EXPECT_NEAR(lmi::detail::lambda_min_small<N>(D), 3.0 - (N - 1), 1e-13);
  EXPECT_EQ(lmi::detail::lambda_min_small<N>(Mat::Zero().eval()), 0.0);
  Mat bad = Mat::Identity();
  bad(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(lmi::detail::lambda_min_small<N>(bad)));
}

// Strictly feasible (x0 interior) and bounded (c = Σ tr(F_i Z0) with Z0 ≻ 0) random problem
// with dense and sparse coefficients and variables that do not touch every block.
LmiProblem random_problem(std::mt19937& rng, const std::vector<int>& sizes, int m, bool with_eq) {
  std::normal_distribution<double> nd(0.0, 1.0);
  LmiProblem p(m);
  VectorXd x0(m);
  for (int i = 0; i < m; ++i) x0(i) = nd(rng);
  VectorXd c = VectorXd::Zero(m);
  for (size_t b = 0; b < sizes.size(); ++b) {
    const int n = sizes[b];
    BlockTerms terms;
    MatrixXd F0 = (0.5 + std::abs(nd(rng))) * MatrixXd::Identity(n, n);
    const MatrixXd G = random_symmetric(rng, n);
    const MatrixXd Z0 = G * G + 0.1 * MatrixXd::Identity(n, n);
    for (int i = 0; i < m; ++i) {
      if ((i + static_cast<int>(b)) % 5 == 4) continue;  // variable absent from this block
      MatrixXd Fi = random_symmetric(rng, n);
      if ((i + static_cast<int>(b)) % 3 == 1) {  // sparse coefficient
        Fi.setZero();
        Fi(0, 0) = nd(rng);
        if (n > 1) Fi(n - 1, 0) = Fi(0, n - 1) = nd(rng);
      }
      F0 -= x0(i) * Fi;
      c(i) += (Fi * Z0).trace();
      terms.emplace_back(i, Fi);
    }
    p.add_block_terms(F0, terms);
  }
  p.set_objective(c);
  if (with_eq) {
    MatrixXd A = MatrixXd::Zero(1, m);
    A(0, 0) = 1.0;
    A(0, m - 1) = -0.5;
    VectorXd b(1);
    b << x0(0) - 0.5 * x0(m - 1);
    p.set_equalities(A, b);
  }
  return p;
}

SolverOptions with_fixed(bool fixed) {
  SolverOptions o;
  o.fixed_size_kernels = fixed;
  return o;
}

}  // namespace

TEST(LmiKernels, LambdaMinSmallMatchesEigenSolver) {
  std::mt19937 rng(5);
  check_lambda_min<1>(rng);
  check_lambda_min<2>(rng);
  check_lambda_min<3>(rng);
  check_lambda_min<4>(rng);
  check_lambda_min<5>(rng);
  check_lambda_min<6>(rng);
  check_lambda_min<7>(rng);
  check_lambda_min<8>(rng);
}

TEST(LmiKernels, SvecInnerProductIsTraceOfProduct) {
  std::mt19937 rng(6);
  for (int n : {1, 2, 5, 7, 11}) {
    const MatrixXd A = random_symmetric(rng, n), B = random_symmetric(rng, n);
    VectorXd a(n * (n + 1) / 2), b(n * (n + 1) / 2);
    lmi::detail::pack_svec(A, a.data());
    lmi::detail::pack_svec(B, b.data());
    EXPECT_NEAR(a.dot(b), (A * B).trace(), 1e-12 * (1.0 + A.norm() * B.norm()));
    MatrixXd back(n, n);
    lmi::detail::unpack_svec(a.data(), back);
    EXPECT_LT((back - A).norm(), 1e-14 * (1.0 + A.norm()));
  }
}

TEST(LmiKernels, FixedSizePathAgreesWithDynamicPath) {
  std::mt19937 rng(7);
  const std::vector<std::vector<int>> shapes = {{7, 7, 5, 3}, {1, 2, 3, 4}, {8, 6, 1}, {7, 10, 2}, {5}};
  int instances = 0;
  for (int rep = 0; rep < 8; ++rep) {
    for (const auto& sizes : shapes) {
      const int m = 3 + static_cast<int>(rng() % 10);
      const LmiProblem p = random_problem(rng, sizes, m, rep % 2 == 1);
      InteriorPointSolver fixed_solver(p, with_fixed(true));
      InteriorPointSolver dynamic_solver(p, with_fixed(false));
      const SolveResult rf = fixed_solver.solve();
      const SolveResult rd = dynamic_solver.solve();
      ASSERT_EQ(rf.status, SolveStatus::Optimal) << "instance " << instances;
      ASSERT_EQ(rd.status, SolveStatus::Optimal) << "instance " << instances;
      EXPECT_NEAR(rf.objective, rd.objective, 1e-6 * std::max(1.0, std::abs(rd.objective)));
      EXPECT_LE(std::abs(rf.iterations - rd.iterations), 2);
      // Both points are feasible to the verified-margin standard and dual feasible.
      EXPECT_GT(rf.margin, -1e-6);
      EXPECT_LE(rf.primal_residual, 1e-8);
      EXPECT_LE(rf.dual_residual, 1e-8);
      for (const auto& Z : rf.Z) EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatrixXd>(Z).eigenvalues()(0), -1e-9);
      ++instances;
    }
  }
  EXPECT_EQ(instances, 40);
}

TEST(LmiKernels, FixedSizePathGivesTheSameInfeasibilityCertificate) {
  // F(x) = diag(x, −1 − x, A − xI) ⪰ 0 is infeasible (x ≥ 0 and x ≤ −1), in blocks of sizes
  // 1, 1 and 6 (fixed path) — the certificate must satisfy the Farkas conditions either way.
  std::mt19937 rng(8);
  LmiProblem p(1);
  p.add_block(MatrixXd::Zero(1, 1), {MatrixXd::Ones(1, 1)});
  p.add_block(-MatrixXd::Ones(1, 1), {-MatrixXd::Ones(1, 1)});
  const MatrixXd A = random_symmetric(rng, 6);
  p.add_block(A, {-MatrixXd::Identity(6, 6)});
  p.set_objective(VectorXd::Ones(1));
  for (bool fixed : {true, false}) {
    const SolveResult r = solve_linear(p, with_fixed(fixed));
    ASSERT_EQ(r.status, SolveStatus::Infeasible) << "fixed=" << fixed;
    double h = 0, g = 0;
    for (int b = 0; b < p.num_blocks(); ++b) {
      const MatrixXd& Z = r.Z[static_cast<size_t>(b)];
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatrixXd>(Z).eigenvalues()(0), -1e-9);
      h += (p.block(b).constant * Z).trace();
      for (const auto& co : p.block(b).coefficients) g += (co.dense * Z).trace();
    }
    EXPECT_NEAR(h, -1.0, 1e-9);  // Σ tr(F_b0 Z_b) = −1
    EXPECT_NEAR(g, 0.0, 1e-6);   // Σ tr(F_b1 Z_b) = 0
  }
}
