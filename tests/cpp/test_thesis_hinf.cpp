// Thesis Ch. 1 (BRL RPI), Ch. 2 and Ch. 3: H∞ set-membership observers (thesis.md §3.4, §4, §5).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <random>

#include "setbound/thesis/hinf_gain.hpp"

using namespace setbound;
using namespace setbound::thesis;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

MatrixXd M2(double a, double b, double c, double d) {
  MatrixXd M(2, 2);
  M << a, b, c, d;
  return M;
}

// Ch. 2 example (thesis.md §4.8).
Plant ch2_plant() {
  MatrixXd B(2, 1), F(2, 1), C(1, 2), Z(1, 1);
  B << 1, 1;
  F << 0, 0.1;
  C << 1, 0;
  Z << 0.1;
  return Plant(M2(0.2, 0.2, 0, 0.5), B, C, F, Z);
}

// σ_max(G(e^{jω})) for G = (zI − A)⁻¹E.
double gain_at(const MatrixXd& A, const MatrixXd& E, double w) {
  const Eigen::Index n = A.rows();
  Eigen::MatrixXcd M = -A.cast<std::complex<double>>();
  M.diagonal().array() += std::polar(1.0, w);
  Eigen::MatrixXcd G = M.partialPivLu().solve(E.cast<std::complex<double>>());
  (void)n;
  return Eigen::JacobiSVD<Eigen::MatrixXcd>(G).singularValues()(0);
}

// H∞ norm of (A, E, I, 0) by frequency gridding then golden-section refinement.
double hinf_norm(const MatrixXd& A, const MatrixXd& E) {
  const int K = 4000;
  double best = -1, wb = 0;
  for (int k = 0; k <= K; ++k) {
    const double w = M_PI * k / K;
    const double v = gain_at(A, E, w);
    if (v > best) best = v, wb = w;
  }
  double a = std::max(0.0, wb - M_PI / K), b = std::min(M_PI, wb + M_PI / K);
  const double r = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 100; ++it) {
    const double c = b - r * (b - a), d = a + r * (b - a);
    if (gain_at(A, E, c) > gain_at(A, E, d)) b = d;
    else a = c;
  }
  return std::max(best, gain_at(A, E, 0.5 * (a + b)));
}

}  // namespace

TEST(ThesisBrl, Example15GammaIsTheHinfNormAndPsiIsInvariant) {
  const MatrixXd A = M2(0.2, 0.2, -0.2, 0.5);
  MatrixXd E(2, 1);
  E << 0, 1;
  VectorXd wbar(1);
  wbar << 1.0;
  const BrlRpi b = brl_ellipsoidal_rpi(A, E, wbar);
  const double norm = hinf_norm(A, E);
  EXPECT_NEAR(b.gamma, norm, 1e-5 * norm);
  EXPECT_GE(b.g, b.g_solver);
  // LMI (1.48) holds with the returned P, g.
  EXPECT_TRUE(hinf_detail::certify_dissipation(b.P, MatrixXd::Identity(2, 2), A, E, b.g, 1e-12));
  // level = λ_max(P) γ² w̄ᵀw̄ (1.55).
  const double lmax = Eigen::SelfAdjointEigenSolver<MatrixXd>(b.P).eigenvalues().maxCoeff();
  EXPECT_NEAR(b.level, lmax * b.g * wbar.squaredNorm(), 1e-9 * b.level);
  EXPECT_GE(b.level, lmax * b.g * wbar.squaredNorm());
  // Invariance: boundary points × disturbance corners stay inside.
  Eigen::LLT<MatrixXd> llt(b.P);
  const MatrixXd Linv = llt.matrixL().solve(MatrixXd::Identity(2, 2)).transpose();  // P = LLᵀ, x = L⁻ᵀ z
  for (int k = 0; k < 720; ++k) {
    VectorXd z(2);
    z << std::cos(k * M_PI / 360), std::sin(k * M_PI / 360);
    const VectorXd x = Linv * z * std::sqrt(b.level);
    EXPECT_NEAR(x.dot(b.P * x), b.level, 1e-9 * b.level);
    for (double w : {-1.0, 1.0}) {
      const VectorXd xp = A * x + E * w;
      EXPECT_LE(xp.dot(b.P * xp), b.level * (1 + 1e-9));
    }
  }
}

TEST(ThesisHinf, Ch2GainIsCertifiedAndStable) {
  const Plant p = ch2_plant();
  const HinfGain h = hinf_observer_gain(p);
  EXPECT_GT(h.gamma, 0);
  EXPECT_NEAR(h.gamma * h.gamma, h.g, 1e-12 * h.g);
  EXPECT_TRUE((h.P * h.L - h.U).norm() <= 1e-9 * h.U.norm() + 1e-12);
  const MatrixXd Ao = p.A - h.L * p.C;
  EXPECT_LT(hinf_detail::spectral_radius(Ao), 1.0);
  EXPECT_TRUE(hinf_detail::certify_dissipation(h.P, h.Q, Ao, p.error_input(h.L), h.g, 1e-12));
  // γ is optimal: the closed-loop H∞ norm from w to the Q-weighted error bounds γ from below
  // (with Q = I, ‖(A_o, E, I, 0)‖∞ ≤ γ), and the solver's γ² is within 1e-6 of the certified one.
  EXPECT_LE(hinf_norm(Ao, p.error_input(h.L)), h.gamma * (1 + 1e-9));
  EXPECT_LE(h.g - h.g_solver, 1e-6 * h.g);
}

TEST(ThesisHinf, NotDetectableAndBadInput) {
  MatrixXd B(2, 1), F(2, 1), C(1, 2), Z(1, 1);
  B << 1, 1;
  F << 0, 0.1;
  C << 1, 0;
  Z << 0.1;
  // The unstable mode 1.2 of x2 is not seen by y = x1.
  const Plant bad(M2(0.2, 0.0, 0, 1.2), B, C, F, Z);
  try {
    hinf_observer_gain(bad);
    FAIL() << "expected NotDetectableError";
  } catch (const NotDetectableError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("A, C:", 0), 0u) << e.what();
  }
  EXPECT_THROW(hinf_observer_gain(ch2_plant(), MatrixXd::Identity(3, 3)), DimensionError);
  EXPECT_THROW(hinf_observer_gain(ch2_plant(), -MatrixXd::Identity(2, 2)), NotPositiveDefiniteError);
  VectorXd wbar(1);
  wbar << 1;
  MatrixXd E(2, 1);
  E << 0, 1;
  EXPECT_THROW(brl_ellipsoidal_rpi(M2(1.2, 0, 0, 0.1), E, wbar), InfeasibleError);
  EXPECT_THROW(brl_ellipsoidal_rpi(M2(0.2, 0, 0, 0.1), E, VectorXd::Ones(2)), DimensionError);
  wbar(0) = NAN;
  EXPECT_THROW(brl_ellipsoidal_rpi(M2(0.2, 0, 0, 0.1), E, wbar), NotFiniteError);
}
