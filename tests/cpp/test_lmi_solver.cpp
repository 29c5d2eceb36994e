// The interior-point core (lmi/solver.hpp), the problem classes (lmi/classes.hpp) and the
// scalar search (lmi/scalar_search.hpp): exact known optima, certificates checked by hand,
// verified margins, degenerate inputs.
//
// The allocation test of solve() lives in test_alloc.cpp (it interposes malloc, which the
// sanitizers own).
#include <cstdlib>

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "setbound/lmi/classes.hpp"
#include "setbound/lmi/kernels.hpp"
#include "setbound/lmi/problem.hpp"
#include "setbound/lmi/scalar_search.hpp"
#include "setbound/lmi/solver.hpp"
#include "test_helpers.hpp"

using namespace setbound;
using namespace setbound::lmi;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

MatrixXd random_symmetric(std::mt19937& rng, int n) {
  std::normal_distribution<double> N(0.0, 1.0);
  MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = N(rng);
  return 0.5 * (A + A.transpose());
}

double lambda_min(const MatrixXd& M) { return Eigen::SelfAdjointEigenSolver<MatrixXd>(M).eigenvalues()(0); }

MatrixXd block_value(const LmiProblem& p, int b, const VectorXd& x) {
  MatrixXd F;
  p.evaluate_block(p.block(b), x, F);
  return F;
}

// min t s.t. t I − A ⪰ 0 has the optimum λ_max(A).
LmiProblem max_eigenvalue_problem(const MatrixXd& A) {
  LmiProblem p(1);
  p.add_block(-A, {MatrixXd::Identity(A.rows(), A.cols())});
  p.set_objective(VectorXd::Ones(1));
  return p;
}

}  // namespace

TEST(LmiSolver, KnownOptimumSchurComplement) {
  // [[x, 1], [1, 1]] ⪰ 0  ⇔  x ≥ 1 (Schur complement, papers.md §0.2).
  LmiProblem p(1);
  MatrixXd F0(2, 2), F1(2, 2);
  F0 << 0, 1, 1, 1;
  F1 << 1, 0, 0, 0;
  p.add_block(F0, {F1});
  p.set_objective(VectorXd::Ones(1));
  const SolveResult r = solve_linear(p);
  ASSERT_EQ(r.status, SolveStatus::Optimal);
  EXPECT_NEAR(r.x(0), 1.0, 1e-7);
  EXPECT_NEAR(r.objective, 1.0, 1e-7);
  EXPECT_LE(r.relative_gap, 1e-7);
  EXPECT_GT(r.solve_time, 0.0);
  // Optimum on the boundary: the verified margin is ~0 (slightly negative or positive).
  EXPECT_LT(std::abs(r.margin), 1e-6);
}

TEST(LmiSolver, MaxEigenvalueOfRandomMatrices) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    // Sizes 1…7 (the kernels' loops) and two above InteriorPointSolver's large-block
    // threshold (Eigen's blocked products).
    const int n = trial < 18 ? 1 + trial % 7 : 30 + trial;
    const MatrixXd A = random_symmetric(rng, n);
    const LmiProblem p = max_eigenvalue_problem(A);
    const SolveResult r = solve_linear(p);
    ASSERT_EQ(r.status, SolveStatus::Optimal) << trial;
    const double lmax = Eigen::SelfAdjointEigenSolver<MatrixXd>(A).eigenvalues()(n - 1);
    EXPECT_NEAR(r.objective, lmax, 1e-7 * std::max(1.0, std::abs(lmax))) << trial;
    // Dual: Z ⪰ 0, tr Z = 1, and tr(−A Z) = −λ_max (strong duality).
    EXPECT_NEAR(r.Z[0].trace(), 1.0, 1e-7);
    EXPECT_GE(lambda_min(r.Z[0]), -1e-8);
    EXPECT_NEAR((A * r.Z[0]).trace(), lmax, 1e-6 * std::max(1.0, std::abs(lmax)));
  }
}

TEST(LmiSolver, VerifiedMarginIsACholeskyCertificate) {
  std::mt19937 rng(11);
  LmiProblem p(2);
  const MatrixXd F1 = random_symmetric(rng, 4), F2 = random_symmetric(rng, 4);
  p.add_block(MatrixXd::Identity(4, 4) * 3.0, {F1, F2});
  MarginChecker mc;
  mc.setup(p);
  for (int k = 0; k < 10; ++k) {
    VectorXd x = VectorXd::Random(2);
    const MatrixXd F = block_value(p, 0, x);
    const double m = mc.margin(p, x);
    const double lmin = lambda_min(F);
    EXPECT_LE(m, lmin);                        // never claims more than is true
    EXPECT_GE(m, lmin - 1e-12 * (1 + F.cwiseAbs().maxCoeff()));  // and is tight
    MatrixXd shifted = F - m * MatrixXd::Identity(4, 4);
    EXPECT_EQ(Eigen::LLT<MatrixXd>(shifted).info(), Eigen::Success);
  }
}

TEST(LmiSolver, InfeasibleComesWithAVerifiedCertificate) {
  // Block 1: [[x, 1], [1, −1 − x]]... simpler: x ≥ 1 and x ≤ −1 as a 2×2 diagonal block plus
  // a dense 3×3 block that does not help.
  std::mt19937 rng(3);
  LmiProblem p(2);
  MatrixXd F0 = MatrixXd::Zero(2, 2), F1 = MatrixXd::Zero(2, 2), F2 = MatrixXd::Zero(2, 2);
  F0 << -1, 0, 0, -1;
  F1 << 1, 0, 0, -1;  // x0 − 1 ≥ 0, −x0 − 1 ≥ 0
  p.add_block(F0, {F1, F2});
  const MatrixXd G1 = random_symmetric(rng, 3), G2 = random_symmetric(rng, 3);
  p.add_block(MatrixXd::Identity(3, 3), {G1, G2});
  p.set_objective(VectorXd::Ones(2));
  const SolveResult r = solve_linear(p);
  ASSERT_EQ(r.status, SolveStatus::Infeasible);
  // Σ tr(F_b0 Z_b) = −1, tr(F_bi Z) = 0, Z ⪰ 0 — checked here, not trusted.
  double f0z = 0, f1z = 0, f2z = 0;
  f0z = (F0 * r.Z[0]).trace() + r.Z[1].trace();
  f1z = (F1 * r.Z[0]).trace() + (G1 * r.Z[1]).trace();
  f2z = (F2 * r.Z[0]).trace() + (G2 * r.Z[1]).trace();
  EXPECT_NEAR(f0z, -1.0, 1e-9);
  EXPECT_NEAR(f1z, 0.0, 1e-7);
  EXPECT_NEAR(f2z, 0.0, 1e-7);
  EXPECT_GE(lambda_min(r.Z[0]), -1e-9);
  EXPECT_GE(lambda_min(r.Z[1]), -1e-9);
}

TEST(LmiSolver, UnboundedComesWithARay) {
  // min −x0 s.t. [[1 + x0, x1], [x1, 1 + x0]] ⪰ 0: x0 → ∞ is a ray.
  LmiProblem p(2);
  MatrixXd F1 = MatrixXd::Identity(2, 2), F2(2, 2);
  F2 << 0, 1, 1, 0;
  p.add_block(MatrixXd::Identity(2, 2), {F1, F2});
  VectorXd c(2);
  c << -1, 0;
  p.set_objective(c);
  const SolveResult r = solve_linear(p);
  ASSERT_EQ(r.status, SolveStatus::Unbounded);
  EXPECT_NEAR(c.dot(r.x), -1.0, 1e-9);
  const MatrixXd D = r.x(0) * F1 + r.x(1) * F2;
  EXPECT_GE(lambda_min(D), -1e-8);
}

TEST(LmiSolver, EqualityConstraints) {
  // min x0 + x1 s.t. diag(x0, x1) ⪰ 0... with x0 − x1 = 1 and x0 + 2x1 ≥ ... use λ_max:
  // min t s.t. tI − A − s B ⪰ 0, s = 0.5 (equality) → λ_max(A + 0.5 B).
  std::mt19937 rng(5);
  const MatrixXd A = random_symmetric(rng, 4), B = random_symmetric(rng, 4);
  LmiProblem p(2);
  p.add_block(-A, {MatrixXd::Identity(4, 4), -B});
  VectorXd c(2);
  c << 1, 0;
  p.set_objective(c);
  MatrixXd Aeq(1, 2);
  Aeq << 0, 1;
  VectorXd beq(1);
  beq << 0.5;
  p.set_equalities(Aeq, beq);
  const SolveResult r = solve_linear(p);
  ASSERT_EQ(r.status, SolveStatus::Optimal);
  const MatrixXd C = A + 0.5 * B;
  const double lmax = Eigen::SelfAdjointEigenSolver<MatrixXd>(C).eigenvalues()(3);
  EXPECT_NEAR(r.objective, lmax, 1e-7 * std::max(1.0, std::abs(lmax)));
  EXPECT_NEAR(r.x(1), 0.5, 1e-8);
}

TEST(LmiSolver, UpdateValuesWithoutReanalysisAndReuseSolver) {
  std::mt19937 rng(9);
  MatrixXd A = random_symmetric(rng, 5);
  LmiProblem p = max_eigenvalue_problem(A);
  InteriorPointSolver solver(p);
  const auto version = p.structure_version();
  for (int k = 0; k < 5; ++k) {
    A = random_symmetric(rng, 5);
    p.update_block(0, -A, {MatrixXd::Identity(5, 5)});
    EXPECT_EQ(p.structure_version(), version);
    const SolveResult& r = solver.solve();
    ASSERT_EQ(r.status, SolveStatus::Optimal);
    const double lmax = Eigen::SelfAdjointEigenSolver<MatrixXd>(A).eigenvalues()(4);
    EXPECT_NEAR(r.objective, lmax, 1e-7 * std::max(1.0, std::abs(lmax)));
  }
  // A new variable touching the block is a structural change (re-analysis, new version).
  LmiProblem q(2);
  q.add_block_terms(MatrixXd::Identity(2, 2), {{0, MatrixXd::Identity(2, 2)}});
  const auto v0 = q.structure_version();
  q.update_block_terms(0, MatrixXd::Identity(2, 2), {{0, MatrixXd::Identity(2, 2)}});
  EXPECT_EQ(q.structure_version(), v0);
  q.update_block_terms(0, MatrixXd::Identity(2, 2), {{1, MatrixXd::Identity(2, 2)}});
  EXPECT_NE(q.structure_version(), v0);
}

namespace {

// Random strictly feasible, bounded problem with `nb` dense blocks of size n (as the (b)
// benchmark), plus sparse coefficients (a variable on one entry) and optionally an equality.
LmiProblem random_block_problem(std::mt19937& rng, int nb, int n, int m, bool equality) {
  std::normal_distribution<double> N(0.0, 1.0);
  VectorXd x0(m), c = VectorXd::Zero(m);
  for (int i = 0; i < m; ++i) x0(i) = N(rng);
  LmiProblem p(m);
  for (int b = 0; b < nb; ++b) {
    std::vector<MatrixXd> Fs;
    MatrixXd F0 = (1.0 + 0.5 * (b % 3)) * MatrixXd::Identity(n, n);
    const MatrixXd R = random_symmetric(rng, n);
    const MatrixXd Z0 = R * R + 0.1 * MatrixXd::Identity(n, n);  // strictly dual feasible: bounded
    for (int i = 0; i < m; ++i) {
      MatrixXd Fi = random_symmetric(rng, n);
      if (i % 5 == 4) {  // sparse coefficient: one symmetric pair of entries
        Fi.setZero();
        Fi(b % n, (b + 1) % n) = Fi((b + 1) % n, b % n) = 1.0;
      }
      F0 -= x0(i) * Fi;
      c(i) += (Fi * Z0).trace();
      Fs.push_back(Fi);
    }
    p.add_block(F0, Fs);
  }
  p.set_objective(c);
  if (equality) {
    MatrixXd Aeq = MatrixXd::Zero(1, m);
    Aeq(0, 0) = 1.0;
    Aeq(0, 1) = -1.0;
    VectorXd beq(1);
    beq << x0(0) - x0(1);
    p.set_equalities(Aeq, beq);
  }
  return p;
}

}  // namespace

TEST(LmiSolver, ThreadsGiveTheSerialResultToRounding) {
  // SolverOptions::threads splits the loops over blocks (OpenMP builds; serial otherwise).
  // The threads' partial sums are added in another order than the serial loop's, so results
  // may differ by rounding only; statuses, certificates and iterations must not.
  std::mt19937 rng(41);
  for (int trial = 0; trial < 4; ++trial) {
    const int nb = trial == 3 ? 3 : 16 + 8 * trial;  // trial 3: fewer blocks than threads
    LmiProblem p = random_block_problem(rng, nb, trial == 1 ? 5 : 7, 12, trial == 2);
    SolverOptions serial;
    const SolveResult r1 = solve_linear(p, serial);
    ASSERT_EQ(r1.status, SolveStatus::Optimal) << "trial " << trial;
    for (int threads : {2, 4}) {
      SolverOptions o;
      o.threads = threads;
      InteriorPointSolver solver(p, o);
      for (int rep = 0; rep < 2; ++rep) {  // a second solve reuses the threads' work arrays
        const SolveResult& r2 = solver.solve();
        ASSERT_EQ(r2.status, SolveStatus::Optimal) << "trial " << trial << " threads " << threads;
        EXPECT_LE(std::abs(r2.iterations - r1.iterations), 1);
        EXPECT_NEAR(r2.objective, r1.objective, 1e-8 * std::max(1.0, std::abs(r1.objective)));
        // x itself is only determined to about √(gap) along flat directions of the optimum
        // (1e-4 relative differences seen here); the objective and feasibility decide.
        EXPECT_LE((r2.x - r1.x).norm(), 1e-3 * std::max(1.0, r1.x.norm()));
        EXPECT_GT(r2.margin, 0.0);
        for (int b = 0; b < p.num_blocks(); ++b) EXPECT_GE(lambda_min(block_value(p, b, r2.x)), 0.0);
      }
    }
  }
  // An infeasible problem keeps its certificate with threads: the (b)-sized problem plus a
  // block that contradicts it (x0 ≥ 1 and x0 ≤ −1).
  LmiProblem q = random_block_problem(rng, 20, 6, 8, false);
  MatrixXd F0 = -MatrixXd::Identity(2, 2), F1 = MatrixXd::Zero(2, 2);
  F1(0, 0) = 1.0;
  F1(1, 1) = -1.0;
  std::vector<MatrixXd> Fs(8, MatrixXd::Zero(2, 2));
  Fs[0] = F1;
  q.add_block(F0, Fs);
  SolverOptions o;
  o.threads = 2;
  const SolveResult r = solve_linear(q, o);
  ASSERT_EQ(r.status, SolveStatus::Infeasible);
  double f0z = 0;
  for (int b = 0; b < q.num_blocks(); ++b) {
    f0z += (q.block(b).constant * r.Z[static_cast<size_t>(b)]).trace();
    EXPECT_GE(lambda_min(r.Z[static_cast<size_t>(b)]), -1e-9);
  }
  EXPECT_NEAR(f0z, -1.0, 1e-8);
  // Bad thread counts are refused by name.
  for (int bad : {0, -1, 257}) {
    SolverOptions b;
    b.threads = bad;
    EXPECT_THROW(
        {
          try {
            InteriorPointSolver s(q, b);
          } catch (const InvalidArgumentError& e) {
            EXPECT_NE(std::string(e.what()).find("threads"), std::string::npos);
            throw;
          }
        },
        InvalidArgumentError);
  }
}

TEST(LmiSolver, StatusesForLimits) {
  std::mt19937 rng(2);
  const LmiProblem p = max_eigenvalue_problem(random_symmetric(rng, 6));
  SolverOptions o;
  o.max_iterations = 2;
  const SolveResult r = solve_linear(p, o);
  EXPECT_TRUE(r.status == SolveStatus::MaxIterations || r.status == SolveStatus::Inaccurate);
  EXPECT_EQ(r.iterations, 2);
  EXPECT_TRUE(r.x.allFinite());  // the best iterate is returned
}

TEST(LmiSolver, DegenerateInputsGiveClearErrors) {
  EXPECT_THROW(LmiProblem(0), DimensionError);
  LmiProblem empty;
  EXPECT_THROW(empty.set_objective(VectorXd::Ones(1)), InvalidArgumentError);
  LmiProblem p(2);
  EXPECT_THROW(solve_linear(p), InvalidArgumentError);  // zero blocks
  MatrixXd ns(2, 2);
  ns << 1, 2, 0, 1;
  try {
    p.add_block(ns, {MatrixXd::Identity(2, 2), MatrixXd::Identity(2, 2)});
    FAIL();
  } catch (const NotSymmetricError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("F0:", 0), 0u) << e.what();
  }
  try {
    p.add_block(MatrixXd::Identity(2, 2), {MatrixXd::Identity(2, 2), ns});
    FAIL();
  } catch (const NotSymmetricError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("Fs[1]:", 0), 0u) << e.what();
  }
  MatrixXd nan = MatrixXd::Identity(2, 2);
  nan(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(p.add_block(nan, {MatrixXd::Identity(2, 2), MatrixXd::Identity(2, 2)}), NotFiniteError);
  EXPECT_THROW(p.add_block(MatrixXd::Identity(2, 2), {MatrixXd::Identity(3, 3), MatrixXd::Identity(2, 2)}),
               DimensionError);
  EXPECT_THROW(p.add_block(MatrixXd::Identity(2, 2), {MatrixXd::Identity(2, 2)}), DimensionError);
  EXPECT_THROW(p.set_objective(VectorXd::Ones(3)), DimensionError);
  EXPECT_THROW(p.set_equalities(MatrixXd::Ones(1, 3), VectorXd::Ones(1)), DimensionError);
  EXPECT_EQ(p.num_blocks(), 0);  // nothing half-added
  SolverOptions bad;
  bad.gap_rel = -1;
  EXPECT_THROW(bad.validate(), InvalidArgumentError);
}

// ---- problem classes -------------------------------------------------------------------

namespace {
// Lyapunov LMI for x_{k+1} = A x_k: P − AᵀPA ⪰ 0, P ⪰ I, P symmetric 2×2 (3 variables).
LmiProblem lyapunov(const MatrixXd& A) {
  LmiProblem p(3);
  std::vector<MatrixXd> E(3, MatrixXd::Zero(2, 2));
  E[0](0, 0) = 1;
  E[1](0, 1) = E[1](1, 0) = 1;
  E[2](1, 1) = 1;
  std::vector<MatrixXd> L;
  for (auto& Ei : E) L.push_back(Ei - A.transpose() * Ei * A);
  p.add_block(MatrixXd::Zero(2, 2), L);
  p.add_block(-MatrixXd::Identity(2, 2), E);
  return p;
}
}  // namespace

// --- kernels.hpp: the solver's small dense routines, against Eigen's ---------------------

namespace {

/// Random symmetric test matrices of the kinds the solver meets: generic, clustered
/// eigenvalues (a multiple of I plus a tiny perturbation, as near the central path), rank
/// one, diagonal with a wide range, and exactly diagonal.
MatrixXd kernel_test_matrix(std::mt19937& rng, int n, int kind) {
  const MatrixXd X = random_symmetric(rng, n);
  switch (kind % 5) {
    case 0: return X;
    case 1: return 3.0 * MatrixXd::Identity(n, n) + 1e-9 * X;
    case 2: {
      const VectorXd v = X.col(0);
      return v * v.transpose();
    }
    case 3: {
      VectorXd d(n);
      for (int i = 0; i < n; ++i) d(i) = std::pow(10.0, -6.0 + 12.0 * i / std::max(1, n - 1));
      return d.asDiagonal();
    }
    default: return MatrixXd(X.diagonal().asDiagonal());
  }
}

}  // namespace

TEST(LmiKernels, SymmetricEigenDecompositionMatchesEigen) {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + trial % 20;
    const MatrixXd A = kernel_test_matrix(rng, n, trial / 20);
    MatrixXd V = A;
    VectorXd w(n), e(n);
    ASSERT_TRUE(kernels::sym_eig(n, V.data(), w.data(), e.data())) << trial;
    const double s = std::max(A.norm(), 1e-300);
    EXPECT_LE((A * V - V * w.asDiagonal()).norm(), 1e-13 * s) << trial;
    EXPECT_LE((V.transpose() * V - MatrixXd::Identity(n, n)).norm(), 1e-13 * n) << trial;
    VectorXd ws = w;
    std::sort(ws.data(), ws.data() + n);
    const VectorXd ref = Eigen::SelfAdjointEigenSolver<MatrixXd>(A, Eigen::EigenvaluesOnly).eigenvalues();
    EXPECT_LE((ws - ref).cwiseAbs().maxCoeff(), 1e-13 * s) << trial;
    // Eigenvalues only, and the smallest one (used by the step lengths and the margin).
    MatrixXd B = A;
    VectorXd w2(n);
    ASSERT_TRUE(kernels::sym_eigenvalues(n, B.data(), w2.data(), e.data()));
    std::sort(w2.data(), w2.data() + n);
    EXPECT_LE((w2 - ref).cwiseAbs().maxCoeff(), 1e-13 * s) << trial;
    B = A;
    const double lmin = kernels::sym_lambda_min(n, B.data(), w2.data(), e.data());
    EXPECT_NEAR(lmin, ref(0), 1e-13 * s) << trial;
  }
}

TEST(LmiKernels, BatchedEigenDecompositionMatchesEigen) {
  // The four-lane Jacobi eigensolver of the NT scaling: every matrix of a batch of 1 … 4
  // (mixed kinds: indefinite, clustered, rank one, graded, diagonal) is decomposed like
  // Eigen's solver does it; sizes outside 2 … kEigBatchMax and non-finite matrices are
  // reported as not done and left untouched, without spoiling the others of their batch.
  std::mt19937 rng(35);
  for (int trial = 0; trial < 480; ++trial) {
    const int n = 1 + trial % 12;
    const int count = 1 + (trial / 12) % 4;
    std::vector<MatrixXd> A(static_cast<size_t>(count)), V(static_cast<size_t>(count));
    std::vector<VectorXd> w(static_cast<size_t>(count), VectorXd::Zero(n));
    double* pa[4];
    double* pw[4];
    const int bad = trial % 7 == 3 ? trial % count : -1;  // this matrix gets a NaN
    for (int l = 0; l < count; ++l) {
      A[l] = kernel_test_matrix(rng, n, (trial / 48 + l) % 5);
      if ((trial + l) % 6 == 5) {  // as in the NT scaling: GᵀG, columns of G graded over 8 decades
        MatrixXd G = random_symmetric(rng, n);
        for (int j = 0; j < n; ++j) G.col(j) *= std::pow(10.0, -4.0 * ((j * 5) % n) / std::max(1, n - 1));
        A[l] = G.transpose() * G;
      }
      if (l == bad) A[l](n - 1, 0) = A[l](0, n - 1) = std::numeric_limits<double>::quiet_NaN();
      V[l] = A[l];
      pa[l] = V[l].data();
      pw[l] = w[l].data();
    }
    const unsigned done = kernels::sym_eig_batch(n, count, pa, pw);
    for (int l = 0; l < count; ++l) {
      const bool expect = n >= 2 && n <= kernels::kEigBatchMax && l != bad;
      ASSERT_EQ(((done >> l) & 1u) != 0u, expect) << trial << " lane " << l;
      if (!expect) {
        EXPECT_TRUE(V[l].cwiseEqual(A[l]).count() + V[l].array().isNaN().count() == n * n) << trial;
        continue;
      }
      const double s = std::max(A[l].norm(), 1e-300);
      EXPECT_LE((A[l] * V[l] - V[l] * w[l].asDiagonal()).norm(), 1e-13 * s) << trial << " lane " << l;
      EXPECT_LE((V[l].transpose() * V[l] - MatrixXd::Identity(n, n)).norm(), 1e-13 * n) << trial << " lane " << l;
      VectorXd ws = w[l];
      std::sort(ws.data(), ws.data() + n);
      const VectorXd ref = Eigen::SelfAdjointEigenSolver<MatrixXd>(A[l], Eigen::EigenvaluesOnly).eigenvalues();
      EXPECT_LE((ws - ref).cwiseAbs().maxCoeff(), 1e-13 * s) << trial << " lane " << l;
    }
  }
  // The rule of when a batch pays is consistent with the sizes it accepts.
  EXPECT_FALSE(kernels::eig_batch_pays(kernels::kEigBatchMax + 1, 4));
  EXPECT_FALSE(kernels::eig_batch_pays(1, 4));
  EXPECT_TRUE(kernels::eig_batch_pays(7, 4));
}

TEST(LmiKernels, LambdaMinApproachesFromTheLeft) {
  // The step length α = −1/λ_min must not be overestimated: λ_min is never above the true
  // value by more than rounding, also for clustered and repeated smallest eigenvalues.
  std::mt19937 rng(32);
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 2 + trial % 12;
    const MatrixXd Qm = Eigen::HouseholderQR<MatrixXd>(random_symmetric(rng, n)).householderQ();
    VectorXd d = VectorXd::Random(n);
    const int rep = 1 + trial % n;  // the smallest eigenvalue repeated `rep` times
    for (int i = 0; i < rep; ++i) d(i) = -1.5;
    const MatrixXd A = Qm * d.asDiagonal() * Qm.transpose();
    MatrixXd B = 0.5 * (A + A.transpose());
    VectorXd w(n), e(n);
    const double lmin = kernels::sym_lambda_min(n, B.data(), w.data(), e.data());
    EXPECT_LE(lmin, -1.5 + 1e-13 * n) << trial;
    EXPECT_GE(lmin, -1.5 - 1e-12 * n) << trial;
  }
}

TEST(LmiKernels, OneSidedJacobiKeepsSmallSingularValuesAccurate) {
  // Graded G = D₁ X D₂ (condition ~1e12): the one-sided Jacobi SVD (the NT scaling's fallback
  // for badly centred pairs) must give singular values and an orthogonal V like Eigen's SVD.
  std::mt19937 rng(33);
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 1 + trial % 10;
    VectorXd d1(n), d2(n);
    for (int i = 0; i < n; ++i) {
      d1(i) = std::pow(10.0, -3.0 + 6.0 * i / std::max(1, n - 1));
      d2(i) = std::pow(10.0, 3.0 - 6.0 * ((i * 7) % n) / std::max(1, n - 1));
    }
    const MatrixXd G0 = d1.asDiagonal() * random_symmetric(rng, n) * d2.asDiagonal();
    MatrixXd G = G0, V(n, n);
    VectorXd sv(n);
    ASSERT_TRUE(kernels::one_sided_jacobi(n, G.data(), V.data(), sv.data())) << trial;
    EXPECT_LE((V.transpose() * V - MatrixXd::Identity(n, n)).norm(), 1e-13 * n) << trial;
    EXPECT_LE((G0 * V - G).norm(), 1e-13 * G0.norm()) << trial;
    VectorXd s1 = sv;
    std::sort(s1.data(), s1.data() + n);
    VectorXd s2 = Eigen::JacobiSVD<MatrixXd>(G0).singularValues();
    std::sort(s2.data(), s2.data() + n);
    for (int i = 0; i < n; ++i) EXPECT_NEAR(s1(i), s2(i), 1e-9 * s2(i) + 1e-15 * s2(n - 1)) << trial;
  }
}

TEST(LmiKernels, RowMajorGemvMatchesEigen) {
  // gemv_rm_t (register tiles of 12/8/4 columns, rows padded to a multiple of 4 columns) and
  // gemv_rm_n_add against Eigen, for every k that changes the tiling and for row offsets as
  // the solver uses them (column 2 of the stored coefficients).
  std::mt19937 rng(36);
  std::normal_distribution<double> nd;
  for (int k = 1; k <= 30; ++k) {
    for (int s : {1, 6, 28}) {
      const long lda = kernels::gram_padded(k) + 4;
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> A(s, lda);
      for (long i = 0; i < A.size(); ++i) A.data()[i] = nd(rng);
      VectorXd x(s), xk(k), y(k + 1), z(s);
      for (int i = 0; i < s; ++i) x(i) = nd(rng), z(i) = nd(rng);
      for (int i = 0; i < k; ++i) xk(i) = nd(rng);
      y.setConstant(7.0);  // y(k) must stay untouched
      kernels::gemv_rm_t(s, k, A.data() + 2, lda, x.data(), y.data());
      const VectorXd ref = A.middleCols(2, k).transpose() * x;
      EXPECT_LE((y.head(k) - ref).norm(), 1e-13 * (1.0 + ref.norm())) << k << " " << s;
      EXPECT_EQ(y(k), 7.0) << k << " " << s;
      const VectorXd zref = z - 0.5 * A.middleCols(2, k) * xk;
      kernels::gemv_rm_n_add(s, k, -0.5, A.data() + 2, lda, xk.data(), z.data());
      EXPECT_LE((z - zref).norm(), 1e-13 * (1.0 + zref.norm())) << k << " " << s;
    }
  }
}

TEST(LmiKernels, CholeskyAndProducts) {
  // n = 1…20: the fixed-size instantiations (n ≤ kernels::kFixedMax) and the run-time loops.
  static_assert(kernels::kFixedMax < 20, "the test must reach the run-time-size path");
  std::mt19937 rng(34);
  for (int trial = 0; trial < 160; ++trial) {
    const int n = 1 + trial % 20;
    const MatrixXd X = random_symmetric(rng, n), Y = random_symmetric(rng, n) + MatrixXd::Random(n, n);
    const MatrixXd P = X * X + MatrixXd::Identity(n, n);
    MatrixXd L(n, n), C(n, n), T(n, n);
    ASSERT_TRUE(kernels::cholesky(n, P.data(), L.data()));
    EXPECT_LE((L * L.transpose() - P).norm(), 1e-13 * P.norm());
    EXPECT_EQ(MatrixXd(L.triangularView<Eigen::StrictlyUpper>()).norm(), 0.0);
    MatrixXd Lal = P;  // in place, as the step-length test uses it
    ASSERT_TRUE(kernels::cholesky(n, Lal.data(), Lal.data()));
    EXPECT_EQ((Lal - L).norm(), 0.0);
    MatrixXd Ind = P;
    Ind(n - 1, n - 1) = -1.0 - P.norm();  // indefinite
    EXPECT_FALSE(kernels::cholesky(n, Ind.data(), L.data()));
    MatrixXd Nan = P;
    Nan(0, 0) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(kernels::cholesky(n, Nan.data(), L.data()));
    // The step-length test (LDLᵀ pivots, no square roots) agrees with the Cholesky test, also
    // just inside and just outside the cone (λ_min shifted to ±1e-6 of the norm).
    const double lmin = Eigen::SelfAdjointEigenSolver<MatrixXd>(P).eigenvalues()(0);
    for (const double shift : {1e-6, -1e-6}) {
      MatrixXd B = P - (lmin - shift * P.norm()) * MatrixXd::Identity(n, n);
      MatrixXd W = B;
      EXPECT_EQ(kernels::positive_definite(n, B.data(), W.data()), shift > 0) << n << " " << shift;
      W = B;
      EXPECT_EQ(kernels::positive_definite(n, W.data(), W.data()), shift > 0) << n << " " << shift;
    }
    L = P;
    EXPECT_TRUE(kernels::positive_definite(n, P.data(), L.data()));
    L = Ind;
    EXPECT_FALSE(kernels::positive_definite(n, Ind.data(), L.data()));
    L = Nan;
    EXPECT_FALSE(kernels::positive_definite(n, Nan.data(), L.data()));
    const double tol = 1e-13 * (1.0 + X.norm() * Y.norm());
    kernels::mul_nn(n, X.data(), Y.data(), C.data());
    EXPECT_LE((C - X * Y).norm(), tol);
    kernels::mul_tn(n, Y.data(), X.data(), C.data());
    EXPECT_LE((C - Y.transpose() * X).norm(), tol);
    kernels::mul_nt(n, X.data(), Y.data(), C.data());
    EXPECT_LE((C - X * Y.transpose()).norm(), tol);
    kernels::congruence_t(n, Y.data(), X.data(), T.data(), C.data());
    EXPECT_LE((C - Y.transpose() * X * Y).norm(), tol * Y.norm());
    kernels::congruence_n(n, Y.data(), X.data(), T.data(), C.data());
    EXPECT_LE((C - Y * X * Y.transpose()).norm(), tol * Y.norm());
  }
}

TEST(LmiClasses, FeasibilityStopsAtACertifiedPoint) {
  MatrixXd A(2, 2);
  A << 0.5, 1.0, 0.0, 0.8;  // Schur stable
  const LmiProblem p = lyapunov(A);
  const SolveResult r = find_feasible(p);
  ASSERT_EQ(r.status, SolveStatus::Optimal);
  ASSERT_GT(r.margin, 0.0);
  // Independent check of the certified point.
  MatrixXd P(2, 2);
  P << r.x(0), r.x(1), r.x(1), r.x(2);
  EXPECT_GT(lambda_min(P - A.transpose() * P * A), 0.0);
  EXPECT_GT(lambda_min(P - MatrixXd::Identity(2, 2)), 0.0);
}

TEST(LmiClasses, FeasibilityOfAnUnstableSystemIsCertifiedInfeasible) {
  MatrixXd A(2, 2);
  A << 1.1, 0.3, 0.0, 0.5;  // eigenvalue 1.1: no Lyapunov matrix exists
  const LmiProblem p = lyapunov(A);
  const SolveResult r = find_feasible(p);
  ASSERT_EQ(r.status, SolveStatus::Infeasible);
  double f0z = 0;
  std::vector<double> fiz(3, 0.0);
  for (int b = 0; b < 2; ++b) {
    f0z += p.block(b).constant.cwiseProduct(r.Z[static_cast<size_t>(b)]).sum();
    for (const auto& co : p.block(b).coefficients) fiz[static_cast<size_t>(co.var)] += co.dense.cwiseProduct(r.Z[static_cast<size_t>(b)]).sum();
    EXPECT_GE(lambda_min(r.Z[static_cast<size_t>(b)]), -1e-9);
  }
  EXPECT_NEAR(f0z, -1.0, 1e-9);
  // FeasibilitySolver accepts a certificate whose residual is within reduced_feas (1e-5): the
  // auxiliary problem's dual residual (1e-8) is divided by its optimum t* when normalised
  for (double v : fiz) EXPECT_NEAR(v, 0.0, SolverOptions{}.reduced_feas);
}

TEST(LmiClasses, MaxdetClosedForms) {
  // max log det X s.t. X ⪯ S (X symmetric 3×3): the optimum is X = S.
  std::mt19937 rng(4);
  const MatrixXd R = random_symmetric(rng, 3);
  const MatrixXd S = R * R.transpose() + MatrixXd::Identity(3, 3);
  LmiProblem p(6);
  std::vector<MatrixXd> E;
  for (int j = 0; j < 3; ++j)
    for (int i = j; i < 3; ++i) {
      MatrixXd Ei = MatrixXd::Zero(3, 3);
      Ei(i, j) = Ei(j, i) = 1;
      E.push_back(Ei);
    }
  std::vector<MatrixXd> negE;
  for (auto& Ei : E) negE.push_back(-Ei);
  p.add_block(S, negE);
  p.set_logdet(MatrixXd::Zero(3, 3), E);
  const SolveResult r = solve_maxdet(p);
  ASSERT_EQ(r.status, SolveStatus::Optimal);
  MatrixXd X(3, 3);
  int k = 0;
  for (int j = 0; j < 3; ++j)
    for (int i = j; i < 3; ++i, ++k) X(i, j) = X(j, i) = r.x(k);
  EXPECT_EIGEN_NEAR(X, S, 1e-6 * S.norm());
  EXPECT_NEAR(r.objective, -std::log(S.determinant()), 1e-6);

  // min −Σ log x_i s.t. Σ x_i ≤ 1, x ≥ 0 (diagonal G): x_i = 1/n.
  const int n = 4;
  LmiProblem q(n);
  std::vector<MatrixXd> ones(n, -MatrixXd::Ones(1, 1)), Gd;
  q.add_block(MatrixXd::Ones(1, 1), ones);
  for (int i = 0; i < n; ++i) {
    MatrixXd Ei = MatrixXd::Zero(n, n);
    Ei(i, i) = 1;
    Gd.push_back(Ei);
  }
  q.set_logdet(MatrixXd::Zero(n, n), Gd);
  const SolveResult s = solve(q);
  ASSERT_EQ(s.status, SolveStatus::Optimal);
  EXPECT_EIGEN_NEAR(s.x, VectorXd::Constant(n, 1.0 / n), 1e-6);
  EXPECT_NEAR(s.objective, n * std::log(static_cast<double>(n)), 1e-6);
}

TEST(LmiClasses, GevpBracketsTheEigenvalue) {
  // min λ s.t. λI − diag(x, 2 − x) ⪰ 0, −1 ≤ x ≤ 3: λ* = 1 at x = 1.
  LmiProblem cons(1);
  MatrixXd one = MatrixXd::Ones(1, 1);
  cons.add_block(one, {one});         // x ≥ −1
  cons.add_block(3 * one, {-one});    // x ≤ 3
  MatrixXd A0 = MatrixXd::Zero(2, 2), A1 = MatrixXd::Zero(2, 2);
  A0(1, 1) = 2;
  A1(0, 0) = 1;
  A1(1, 1) = -1;
  GevpOptions go;
  go.lambda_lo = 0.0;
  go.lambda_hi = 5.0;
  go.tol = 1e-7;
  const GevpResult g = solve_gevp(cons, A0, {{0, A1}}, MatrixXd::Identity(2, 2), {}, go);
  ASSERT_EQ(g.status, SolveStatus::Optimal);
  EXPECT_NEAR(g.lambda, 1.0, 1e-6);
  EXPECT_LE(g.lower, 1.0);
  EXPECT_GE(g.lambda, 1.0 - 1e-12);  // the certified upper value never undercuts λ*
  EXPECT_GT(g.margin, 0.0);
  // The certified point satisfies λB − A(x) ≻ 0 at the returned λ.
  EXPECT_GT(g.lambda - g.x(0), 0.0);
  EXPECT_GT(g.lambda - (2 - g.x(0)), 0.0);

  // Constant pencil: λ* = λ_max(B⁻¹A) for B ≻ 0.
  std::mt19937 rng(8);
  const MatrixXd Am = random_symmetric(rng, 3);
  const MatrixXd Rb = random_symmetric(rng, 3);
  const MatrixXd Bm = Rb * Rb + MatrixXd::Identity(3, 3);
  LmiProblem dummy(1);
  dummy.add_block(one, {one});
  const GevpResult h = solve_gevp(dummy, Am, {}, Bm, {}, go);
  Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> ges(Am, Bm);
  ASSERT_EQ(h.status, SolveStatus::Optimal);
  EXPECT_NEAR(h.lambda, ges.eigenvalues()(2), 1e-6 * std::max(1.0, std::abs(ges.eigenvalues()(2))));
}

TEST(LmiScalarSearch, FindsTheMinimumAndSkipsInfeasibleValues) {
  int calls = 0;
  auto f = [&](double b) {
    ++calls;
    if (b > 0.8) return std::numeric_limits<double>::infinity();  // "LMI infeasible"
    return (b - 0.3137) * (b - 0.3137) + 2.0;
  };
  const ScalarSearchResult r = minimize_scalar(f, 0.0, 1.0);
  ASSERT_TRUE(r.found());
  EXPECT_NEAR(r.argmin, 0.3137, 1e-4);
  EXPECT_NEAR(r.value, 2.0, 1e-8);
  EXPECT_EQ(r.evaluations, calls);
  const ScalarSearchResult none = minimize_scalar([](double) { return std::numeric_limits<double>::infinity(); }, 0, 1);
  EXPECT_FALSE(none.found());
  EXPECT_THROW(minimize_scalar(f, 1.0, 0.0), InvalidArgumentError);
  EXPECT_THROW(minimize_scalar([](double) -> double { throw NumericalError("x"); }, 0.0, 1.0), NumericalError);
}

TEST(LmiScalarSearch, BetaSearchOnAnLmiReusesOneProblem) {
  // σ(β) = min σ s.t. [[βP − AᵀPA, 0], [0, σ − 1]]... use the decay LMI: for x⁺ = a x + w,
  // |w| ≤ 1, the radius bound ρ∞ = σ/(1−β) with [[β − a², −a], [−a, σ − 1]] ⪰ 0 (p = 1):
  // σ(β) = 1 + a²/(β − a²) for β > a², and the minimiser of σ/(1−β) is β* = |a|.
  const double a = 0.6;
  LmiProblem p(1);  // variable: σ
  MatrixXd F0(2, 2), F1(2, 2);
  F1 << 0, 0, 0, 1;
  F0 << 0.7 - a * a, -a, -a, -1;
  p.add_block(F0, {F1});
  p.set_objective(VectorXd::Ones(1));
  InteriorPointSolver solver(p);
  const auto version = p.structure_version();
  auto crit = [&](double beta) {
    MatrixXd G0(2, 2);
    G0 << beta - a * a, -a, -a, -1;
    p.update_block(0, G0, {F1});
    const SolveResult& r = solver.solve();
    if (r.status != SolveStatus::Optimal) return std::numeric_limits<double>::infinity();
    return r.objective / (1 - beta);
  };
  const ScalarSearchResult r = minimize_scalar(crit, 0.0, 1.0);
  EXPECT_EQ(p.structure_version(), version);
  ASSERT_TRUE(r.found());
  EXPECT_NEAR(r.argmin, a, 1e-3);
  EXPECT_NEAR(r.value, 1.0 / ((1 - a) * (1 - a)), 1e-5);
}

// --- arm form of sparse coefficients (ArmForm; the Schur complement of large sparse blocks) ---

namespace {
// Block coefficients of a matrix variable X (n×n symmetric) entering as [[X A + Aᵀ X, ·], ...]-like
// rows: x_ij multiplies E_ij A + Aᵀ E_ji (+ the transpose), a few rows each, as in the designs.
std::vector<MatrixXd> row_structured_coefficients(std::mt19937& rng, int n, int count) {
  std::normal_distribution<double> N(0.0, 1.0);
  MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = (i + 2 * j) % 3 == 0 ? N(rng) : 0.0;  // sparse rows, repeated patterns
  std::vector<MatrixXd> Fs;
  for (int t = 0; t < count; ++t) {
    const int i = t % n, j = (t / n + i) % n;
    MatrixXd E = MatrixXd::Zero(n, n);
    E(i, j) = 1.0;
    MatrixXd F = E * A + A.transpose() * E.transpose();
    F(j, j) += 0.5;  // a diagonal entry outside the arms of rows i
    Fs.push_back(0.5 * (F + F.transpose()));
  }
  return Fs;
}
}  // namespace

TEST(LmiArmForm, GramTraceAndSvecMatchTheDenseScaledCoefficients) {
  std::mt19937 rng(5);
  const int n = 19, k = 40;
  const std::vector<MatrixXd> Fs = row_structured_coefficients(rng, n, k);
  LmiProblem p(k);
  p.add_block(MatrixXd::Identity(n, n), Fs);
  const LmiBlock& blk = p.block(0);
  ArmForm arms;
  arms.build(blk, nullptr, static_cast<int>(blk.coefficients.size()));
  const int kk = static_cast<int>(blk.coefficients.size());
  ASSERT_EQ(arms.k, kk);
  EXPECT_LT(arms.nvec, static_cast<int>(arms.row.size()));  // equal arm vectors are stored once
  MatrixXd T = MatrixXd::Random(n, n) + 3.0 * MatrixXd::Identity(n, n);
  arms.prepare(T.data());
  VectorXd s = VectorXd::LinSpaced(kk, 0.5, 2.0);
  MatrixXd G = MatrixXd::Zero(kk, kk);
  arms.gram(s.data(), G.data(), kk);
  VectorXd col(n * (n + 1) / 2), ref(n * (n + 1) / 2);
  for (int j = 0; j < kk; ++j) {
    const MatrixXd Fj = T * blk.coefficients[static_cast<size_t>(j)].dense * T.transpose();
    EXPECT_NEAR(arms.trace(j), Fj.trace(), 1e-11 * (1.0 + Fj.norm()));
    arms.svec_column(j, T.data(), s(j), col.data());
    kernels::svec_pack(n, MatrixXd(s(j) * Fj).data(), ref.data());
    EXPECT_LT((col - ref).norm(), 1e-12 * (1.0 + ref.norm())) << "coefficient " << j;
    for (int i = 0; i <= j; ++i) {
      const MatrixXd Fi = T * blk.coefficients[static_cast<size_t>(i)].dense * T.transpose();
      const double want = s(i) * s(j) * (Fi.cwiseProduct(Fj)).sum();
      EXPECT_NEAR(G(i, j), want, 1e-11 * (1.0 + std::abs(want) + Fi.norm() * Fj.norm())) << i << ", " << j;
    }
  }
}

TEST(LmiArmForm, SolveAgreesWithTheDensePath) {
  // A 20×20 block with 60 row-structured sparse coefficients takes the arm form; the same problem
  // with one more variable whose coefficient is dense (fixed to 0 by an equality) takes the Gram
  // path. Same optimum.
  std::mt19937 rng(11);
  const int n = 20, k = 60;
  std::vector<MatrixXd> Fs = row_structured_coefficients(rng, n, k);
  VectorXd c(k);
  MatrixXd Z0 = MatrixXd::Identity(n, n);
  for (int i = 0; i < k; ++i) c(i) = (Fs[static_cast<size_t>(i)] * Z0).trace();  // bounded: Z0 ≻ 0 dual feasible
  const MatrixXd F0 = 2.0 * MatrixXd::Identity(n, n);
  LmiProblem arm(k);
  arm.add_block(F0, Fs);
  arm.set_objective(c);
  std::vector<MatrixXd> Fd = Fs;
  Fd.push_back(random_symmetric(rng, n));
  LmiProblem dense(k + 1);
  dense.add_block(F0, Fd);
  VectorXd cd = VectorXd::Zero(k + 1);
  cd.head(k) = c;
  dense.set_objective(cd);
  MatrixXd Aeq = MatrixXd::Zero(1, k + 1);
  Aeq(0, k) = 1.0;
  dense.set_equalities(Aeq, VectorXd::Zero(1));
  const SolveResult ra = solve_linear(arm);
  const SolveResult rd = solve_linear(dense);
  ASSERT_EQ(ra.status, SolveStatus::Optimal);
  ASSERT_EQ(rd.status, SolveStatus::Optimal);
  EXPECT_NEAR(ra.objective, rd.objective, 1e-6 * (1.0 + std::abs(rd.objective)));
  EXPECT_GT(ra.margin, -1e-7);
}
