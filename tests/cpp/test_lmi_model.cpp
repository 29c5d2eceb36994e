// Modelling helpers (lmi/model.hpp) and the spec's LMIs written with them.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "setbound/lmi/classes.hpp"
#include "setbound/lmi/model.hpp"
#include "setbound/lmi/scalar_search.hpp"
#include "setbound/lmi/solver.hpp"
#include "test_helpers.hpp"

using namespace setbound;
using namespace setbound::lmi;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {
double lambda_min(const MatrixXd& M) { return Eigen::SelfAdjointEigenSolver<MatrixXd>(M).eigenvalues()(0); }
}  // namespace

TEST(LmiModel, ExpressionAlgebraEvaluatesLikeMatrices) {
  Model model;
  const Var P = model.symmetric(3);
  const Var Y = model.full(3, 2);
  const Var s = model.scalar();
  EXPECT_EQ(model.num_vars(), 6 + 6 + 1);
  const MatrixXd A = MatrixXd::Random(3, 3), C = MatrixXd::Random(2, 3), E = MatrixXd::Random(3, 4),
                 F = MatrixXd::Random(2, 4);
  const double beta = 0.37;
  const AffineExpr e1 = A.transpose() * P - C.transpose() * Y.transpose();
  const AffineExpr e2 = P * E - Y * F;
  const AffineExpr e3 = beta * P + s * MatrixXd::Identity(3, 3) - 2.0 * P;
  for (int trial = 0; trial < 5; ++trial) {
    const VectorXd x = VectorXd::Random(model.num_vars());
    const MatrixXd Pv = model.value(P, x), Yv = model.value(Y, x);
    const double sv = model.scalar_value(s, x);
    EXPECT_EIGEN_NEAR(Pv, Pv.transpose(), 0.0);
    EXPECT_EIGEN_NEAR(e1.evaluate(x), MatrixXd(A.transpose() * Pv - C.transpose() * Yv.transpose()), 1e-12);
    EXPECT_EIGEN_NEAR(e2.evaluate(x), MatrixXd(Pv * E - Yv * F), 1e-12);
    EXPECT_EIGEN_NEAR(e3.evaluate(x), MatrixXd(beta * Pv + sv * MatrixXd::Identity(3, 3) - 2.0 * Pv), 1e-12);
    const AffineExpr blk = sym_block({{P}, {e2.transpose(), s * MatrixXd::Identity(4, 4)}});
    const MatrixXd B = blk.evaluate(x);
    EXPECT_EQ(B.rows(), 7);
    EXPECT_EIGEN_NEAR(B, B.transpose(), 0.0);
    EXPECT_EIGEN_NEAR(B.block(3, 0, 4, 3), MatrixXd((Pv * E - Yv * F).transpose()), 1e-12);
  }
  EXPECT_THROW(P * MatrixXd::Ones(2, 2), DimensionError);
  EXPECT_THROW(P + Y, DimensionError);
  EXPECT_THROW(P * P, InvalidArgumentError);  // not affine
  EXPECT_THROW(sym_block({{P}, {Y}}), DimensionError);  // lower triangle rows need i+1 blocks
  EXPECT_THROW(model.add_lmi(P * A), NotSymmetricError);
  EXPECT_THROW(model.add_lmi(Y), DimensionError);
}

TEST(LmiModel, LyapunovDesignAndUpdateWithoutReanalysis) {
  // min tr P s.t. AᵀPA − P ⪯ −I (strict via margin), P ⪰ 0: the Lyapunov equation solution.
  Model model;
  const Var P = model.symmetric(2);
  MatrixXd A(2, 2);
  A << 0.5, 0.4, -0.2, 0.7;
  auto build = [&](const MatrixXd& Am) {
    model.clear_constraints();
    model.add_lmi(P - Am.transpose() * P * Am - MatrixXd::Identity(2, 2));
    model.add_lmi(P, 1e-9);
    model.minimize(P.block(0, 0, 1, 1) + P.block(1, 1, 1, 1));
  };
  build(A);
  LmiProblem prob = model.build();
  InteriorPointSolver solver(prob);
  const auto version = prob.structure_version();
  for (int k = 0; k < 3; ++k) {
    const MatrixXd Am = A * (1.0 - 0.2 * k);
    build(Am);
    model.update(prob);
    EXPECT_EQ(prob.structure_version(), version);
    const SolveResult& r = solver.solve();
    ASSERT_EQ(r.status, SolveStatus::Optimal);
    // The optimum solves P − AᵀPA = I (Stein equation) — compare with a direct solve.
    // Pexact = Σ_k (Aᵀ)^k A^k (converges: A is Schur stable).
    MatrixXd Pexact = MatrixXd::Zero(2, 2), Ak = MatrixXd::Identity(2, 2);
    for (int it = 0; it < 3000; ++it, Ak = Ak * Am) Pexact += Ak.transpose() * Ak;
    EXPECT_EIGEN_NEAR(model.value(P, r.x), Pexact, 1e-5 * Pexact.norm());
  }
}

TEST(LmiModel, EqualitiesFromSymmetricExpressionsUseTheLowerTriangle) {
  Model model;
  const Var P = model.symmetric(3);
  MatrixXd S = MatrixXd::Random(3, 3);
  S = S * S.transpose() + MatrixXd::Identity(3, 3);
  model.add_equality(P, S);  // 6 rows, not 9 (duplicate rows would make Aeq rank deficient)
  model.add_lmi(P);
  model.minimize(P.block(0, 0, 1, 1));
  const LmiProblem prob = model.build();
  EXPECT_EQ(prob.num_equalities(), 6);
  const SolveResult r = solve_linear(prob);
  ASSERT_EQ(r.status, SolveStatus::Optimal);
  EXPECT_EIGEN_NEAR(model.value(P, r.x), S, 1e-8);
  EXPECT_THROW(model.add_equality(AffineExpr(MatrixXd::Ones(1, 1)), MatrixXd::Zero(1, 1)), InfeasibleError);
}

// ---- EX-BC14 offline design (papers.md §1.1, §1.4) ----------------------------------------

namespace {
struct ExBc14 {
  MatrixXd A{3, 3}, E{3, 5}, C{2, 3}, F{2, 5};
  ExBc14() {
    A << 1, 0, 0.2, 0, 0.8, 1, 0, 0, 1;
    E << 0.1, 0, 0, 0, 0, 0, 0.05, 0, 0, 0, 0, 0, 0.05, 0, 0;
    C << 1, 0, 2, 0, -1, 1;
    F << 0, 0, 0, 0.15, 0, 0, 0, 0, 0, 0.15;
  }
};

// Vertices of B^5; with `halve`, only one of each ±ω pair (§0.2 sign symmetry).
std::vector<VectorXd> box_vertices(int n, bool halve) {
  std::vector<VectorXd> v;
  const int count = 1 << n;
  for (int k = 0; k < count; ++k) {
    VectorXd w(n);
    for (int i = 0; i < n; ++i) w(i) = (k >> i) & 1 ? 1.0 : -1.0;
    if (halve && w(n - 1) < 0) continue;
    v.push_back(w);
  }
  return v;
}

struct OfflineDesign {
  Model model;
  Var P, Y, sigma;
  LmiProblem problem;
};

// min σ s.t. the Theorem-1 LMI at every vertex (β fixed) and P ⪰ I (§1.1 normalisation).
void build_offline(OfflineDesign& d, const ExBc14& s, double beta, bool halve) {
  d.model.clear_constraints();
  const AffineExpr PAYC = d.P * s.A - d.Y * s.C;
  const AffineExpr PEYF = d.P * s.E - d.Y * s.F;
  for (const VectorXd& w : box_vertices(5, halve))
    d.model.add_lmi(sym_block({{beta * d.P}, {AffineExpr::zero(1, 3), d.sigma}, {PAYC, PEYF * MatrixXd(w), d.P}}));
  d.model.add_lmi(d.P - MatrixXd::Identity(3, 3));
  d.model.minimize(d.sigma);
}
}  // namespace

TEST(LmiSpec, ExBc14OfflineDesignContainsEveryDisturbance) {
  const ExBc14 s;
  const double beta = 0.8;
  OfflineDesign d;
  d.P = d.model.symmetric(3);
  d.Y = d.model.full(3, 2);
  d.sigma = d.model.scalar();
  build_offline(d, s, beta, true);
  d.problem = d.model.build();
  EXPECT_EQ(d.problem.num_blocks(), 17);
  const SolveResult r = solve_linear(d.problem);
  ASSERT_EQ(r.status, SolveStatus::Optimal);
  EXPECT_GT(r.margin, -1e-7);
  const MatrixXd P = d.model.value(d.P, r.x), Y = d.model.value(d.Y, r.x);
  const double sigma = d.model.scalar_value(d.sigma, r.x);
  EXPECT_GT(sigma, 0.0);
  EXPECT_GE(lambda_min(P), 1.0 - 1e-7);

  // Same optimum with all 32 vertices (the ± symmetry of §0.2 is exact).
  OfflineDesign full;
  full.P = full.model.symmetric(3);
  full.Y = full.model.full(3, 2);
  full.sigma = full.model.scalar();
  build_offline(full, s, beta, false);
  const SolveResult r32 = solve_linear(full.model.build());
  ASSERT_EQ(r32.status, SolveStatus::Optimal);
  EXPECT_NEAR(r32.objective, r.objective, 1e-6 * std::max(1.0, std::abs(r.objective)));

  // Guarantee (§1.1): z ∈ E(P, 0, 1), ω ∈ B^5 ⇒ e⁺ = (A − LC)z + (E − LF)ω ∈ E(P, 0, β + σ).
  const MatrixXd L = P.llt().solve(Y);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-1, 1);
  const Eigen::LLT<MatrixXd> llt(P);
  double worst = 0;
  for (int k = 0; k < 4000; ++k) {
    VectorXd u(3), w(5);
    for (int i = 0; i < 3; ++i) u(i) = U(rng);
    u.normalize();
    for (int i = 0; i < 5; ++i) w(i) = (k % 2) ? (U(rng) > 0 ? 1.0 : -1.0) : U(rng);
    const VectorXd z = llt.matrixU().solve(u);  // zᵀPz = 1
    const VectorXd e = (s.A - L * s.C) * z + (s.E - L * s.F) * w;
    worst = std::max(worst, e.dot(P * e) / (beta + sigma));
  }
  EXPECT_LE(worst, 1.0 + 1e-6);
  EXPECT_GT(worst, 0.5);  // and the bound is not vacuous

  // β search on ρ∞ = σ/(1 − β) reusing the problem (§0.4): values change, structure does not.
  InteriorPointSolver solver(d.problem);
  const auto version = d.problem.structure_version();
  auto crit = [&](double b) {
    build_offline(d, s, b, true);
    d.model.update(d.problem);
    const SolveResult& rr = solver.solve();
    return rr.status == SolveStatus::Optimal ? rr.objective / (1 - b) : std::numeric_limits<double>::infinity();
  };
  ScalarSearchOptions so;
  so.grid_points = 9;
  const ScalarSearchResult best = minimize_scalar(crit, 0.0, 1.0, so);
  EXPECT_EQ(d.problem.structure_version(), version);
  ASSERT_TRUE(best.found());
  EXPECT_LE(best.value, sigma / (1 - beta) + 1e-9);  // no worse than the fixed β = 0.8
  EXPECT_LE(best.value, crit(best.argmin + 0.02) + 1e-6);
  EXPECT_LE(best.value, crit(best.argmin - 0.02) + 1e-6);
}
