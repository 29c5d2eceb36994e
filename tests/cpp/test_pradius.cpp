// P-radius gain design ([Le2013], papers.md §3.2–3.3) and the estimator using it.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "setbound/estimators/zonotopic/pradius.hpp"
#include "test_helpers.hpp"

using namespace setbound;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// EX-LE13 (papers §3.5), ω = [w; v1; v2].
LinearSystem le13(double rad = 0.3) {
  MatrixXd A(2, 2), C(2, 2), E(2, 3), F(2, 3), Arad = MatrixXd::Zero(2, 2);
  A << 0, -0.5, 1, 1;
  C << -2, 1, 1, 1;
  E << -0.12, 0, 0, 0.02, 0, 0;
  F << 0, 0.2, 0, 0, 0, 0.2;
  Arad(1, 1) = rad;
  return LinearSystem(A, C, E, F, {}, {}, Arad);
}

double spectral_radius(const MatrixXd& M) {
  return Eigen::EigenSolver<MatrixXd>(M).eigenvalues().cwiseAbs().maxCoeff();
}

// The LMI's meaning, for strip position t of the design: for every θ, γ, η,
//   ‖κ_t (K G θ + K F_w γ + Σ v_l η_l) + φ_t λ_t η_t‖²_P ≤ β θᵀPθ + ‖F_w γ‖² + Σ φ_l² η_l² + φ_t² η_t²
// (approach 1: K = I, no earlier strips). Returns the worst ratio lhs / rhs over samples.
double worst_certificate_ratio(const LinearSystem& sys, const PRadiusDesign& d, std::size_t t, unsigned seed) {
  const Eigen::Index n = sys.nx();
  const Eigen::Index o = d.strip_order[t];
  std::vector<Eigen::Index> prev;
  if (d.approach == PRadiusApproach::Coupled) prev.assign(d.strip_order.begin(), d.strip_order.begin() + t);
  auto kappa = [&](Eigen::Index i) {
    return MatrixXd(MatrixXd::Identity(n, n) - d.lambdas.row(i).transpose() * sys.C().row(i));
  };
  const MatrixXd& P = d.P[static_cast<std::size_t>(o)];
  std::mt19937 gen(seed);
  std::normal_distribution<double> N;
  double worst = 0;
  for (const MatrixXd& G : sys.A_vertices())
    for (int s = 0; s < 3000; ++s) {
      VectorXd theta(n), gamma(sys.nw());
      for (Eigen::Index i = 0; i < n; ++i) theta(i) = N(gen);
      for (Eigen::Index i = 0; i < sys.nw(); ++i) gamma(i) = N(gen);
      // Propagate through the earlier strips exactly as the estimator does.
      VectorXd e = G * theta + sys.E() * gamma;
      double rhs = d.beta(o) * theta.dot(P * theta) + (sys.E() * gamma).squaredNorm();
      for (Eigen::Index l : prev) {
        const double eta = N(gen), phi = sys.output_noise_bound(l);
        e = kappa(l) * e + phi * d.lambdas.row(l).transpose() * eta;
        rhs += phi * phi * eta * eta;
      }
      const double eta = N(gen), phi = sys.output_noise_bound(o);
      e = kappa(o) * e + phi * d.lambdas.row(o).transpose() * eta;
      rhs += phi * phi * eta * eta;
      worst = std::max(worst, e.dot(P * e) / rhs);
    }
  return worst;
}

}  // namespace

TEST(PRadiusDesign, SequentialLe13CertifiesTheRecursionAndContracts) {
  const LinearSystem sys = le13();
  const PRadiusDesign d = design_pradius(sys);
  ASSERT_EQ(d.lambdas.rows(), 2);
  EXPECT_NEAR(d.psi, 0.0148, 1e-12);  // ψ = F_wᵀF_w (papers §3.5)
  for (Eigen::Index i = 0; i < 2; ++i) {
    EXPECT_GT(d.tau(i), 0.0);
    EXPECT_GT(d.beta(i), 0.0);
    EXPECT_LT(d.beta(i), 1.0);
    // Closed loop κ_i G_j is Schur for both vertices of [A] (papers §3.6).
    const MatrixXd kappa = MatrixXd::Identity(2, 2) - d.lambdas.row(i).transpose() * sys.C().row(i);
    for (const MatrixXd& G : sys.A_vertices()) EXPECT_LT(spectral_radius(kappa * G), 1.0);
    EXPECT_LE(worst_certificate_ratio(sys, d, static_cast<std::size_t>(i), 11), 1.0 + 1e-6);
    // (1 − β) P / (φ² + ψ) ⪰ τ I
    const double norm = d.psi + std::pow(sys.output_noise_bound(i), 2);
    const double lmin = Eigen::SelfAdjointEigenSolver<MatrixXd>(d.P[i]).eigenvalues().minCoeff();
    EXPECT_GE((1 - d.beta(i)) * lmin / norm, d.tau(i) * (1 - 1e-6));
  }
}

TEST(PRadiusDesign, BetaMaximisesTau) {
  const LinearSystem sys = le13();
  const PRadiusDesign d = design_pradius(sys);
  for (double shift : {-0.1, 0.1}) {
    PRadiusOptions o;
    const double b = d.beta(0) + shift;
    if (b <= 0.01 || b >= 0.99) continue;
    o.beta_lo = std::min(b, b + 0.01);
    o.beta_hi = b + 0.01;
    o.strip_order = {0, 1};
    const PRadiusDesign other = design_pradius(sys, o);
    EXPECT_LE(other.tau(0), d.tau(0) * (1 + 1e-6)) << "beta " << b;
  }
}

TEST(PRadiusDesign, CoupledCertifiesItsRecursion) {
  const LinearSystem sys = le13();
  PRadiusOptions o;
  o.approach = PRadiusApproach::Coupled;
  const PRadiusDesign d2 = design_pradius(sys, o);
  const PRadiusDesign d1 = design_pradius(sys);
  // Strip 0 is designed alone in both approaches (papers §3.3).
  EXPECT_EIGEN_NEAR(d2.lambdas.row(0), d1.lambdas.row(0), 1e-5);
  for (std::size_t t = 0; t < 2; ++t) EXPECT_LE(worst_certificate_ratio(sys, d2, t, 5), 1.0 + 1e-6);
  EXPECT_GT(d2.tau(1), 0.0);
}

TEST(PRadiusEstimator, ContainsTruthWithIntervalA) {
  const LinearSystem sys = le13();
  for (auto approach : {PRadiusApproach::Sequential, PRadiusApproach::Coupled}) {
    PRadiusOptions o;
    o.approach = approach;
    const PRadiusDesign d = design_pradius(sys, o);
    for (double delta : {-1.0, 0.4, 1.0})
      for (bool vertex : {false, true}) {
        MatrixXd A_true = sys.A();
        A_true(1, 1) += 0.3 * delta;
        std::mt19937 gen(static_cast<unsigned>(100 * delta + 7 + vertex));
        std::uniform_real_distribution<double> U(-1, 1);
        auto draw = [&](int n) {
          VectorXd w(n);
          for (int i = 0; i < n; ++i) w(i) = vertex ? (U(gen) < 0 ? -1 : 1) : U(gen);
          return w;
        };
        ZonotopicEstimator est(sys, Zonotope(VectorXd::Zero(2), 3 * MatrixXd::Identity(2, 2)), pradius_gain(d));
        VectorXd x = 3 * draw(2);
        for (int k = 0; k < 100; ++k) {
          const VectorXd y = sys.C() * x + sys.F() * draw(3);
          ASSERT_TRUE(est.step(y, VectorXd(0)).contains(x, 0.0)) << "k " << k;
          x = A_true * x + sys.E() * draw(3);
        }
      }
  }
}

TEST(PRadiusEstimator, PRadiusRecursionHoldsAlongARun) {
  // Single output, known A: L_k ≤ β L_{k−1} + ψ + φ² with L the exact P-radius (§3.2).
  MatrixXd A(2, 2), C(1, 2), E(2, 2), F(1, 2);
  A << 0, -0.5, 1, 1;
  C << -2, 1;
  E << -0.12, 0, 0.02, 0;
  F << 0, 0.2;
  const LinearSystem sys(A, C, E, F);
  const PRadiusDesign d = design_pradius(sys);
  const MatrixXd& P = d.P[0];
  const double phi = 0.2;
  ZonotopicOptions opt;
  opt.max_generators = 40;  // no reduction: the recursion is about the unreduced sets
  // Start from a point so that the exact P-radius (≤ 24 generators) covers several steps.
  ZonotopicEstimator est(sys, Zonotope(VectorXd::Zero(2), MatrixXd::Zero(2, 0)), pradius_gain(d), opt);
  std::mt19937 gen(4);
  std::uniform_real_distribution<double> U(-0.2, 0.2);
  double L_prev = -1;
  int checked = 0;
  for (int k = 0; k < 9; ++k) {
    const Zonotope X = est.step(VectorXd::Constant(1, U(gen)), VectorXd(0));
    if (X.num_generators() > kPRadiusMaxGenerators) break;
    const double L = X.pradius(P);
    if (L_prev >= 0) {
      // The rounding box adds ~1e-15 relative; allow for it.
      EXPECT_LE(L, (d.beta(0) * L_prev + d.psi + phi * phi) * (1 + 1e-9)) << "k " << k;
      ++checked;
    }
    L_prev = L;
  }
  EXPECT_GE(checked, 5);
}

TEST(PRadiusDesign, BadInputAndInfeasibility) {
  const LinearSystem sys = le13();
  PRadiusOptions o;
  o.strip_order = {0, 0};
  EXPECT_THROW(design_pradius(sys, o), InvalidArgumentError);
  o.strip_order = {};
  o.beta_lo = 0.9;
  o.beta_hi = 0.5;
  EXPECT_THROW(design_pradius(sys, o), InvalidArgumentError);
  // C sees only the stable mode: no strip gain can contract the unstable one.
  MatrixXd A(2, 2), C(1, 2), E = 0.1 * MatrixXd::Identity(2, 2), F(1, 2);
  A << 1.5, 0, 0, 0.5;
  C << 0, 1;
  F << 0, 0;
  F(0, 1) = 0.1;
  try {
    design_pradius(LinearSystem(A, C, E, F));
    FAIL() << "expected InfeasibleError";
  } catch (const InfeasibleError& e) {
    EXPECT_NE(std::string(e.what()).find("output 0"), std::string::npos) << e.what();
  }
}
