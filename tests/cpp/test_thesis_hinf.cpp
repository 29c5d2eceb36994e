// Thesis Ch. 1 (BRL RPI), Ch. 2 and Ch. 3: H∞ set-membership observers (thesis.md §3.4, §4, §5).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <random>

#include "setbound/thesis/hinf_gain.hpp"
#include "c_api_common.hpp"  // the C ABI (setbound.h) through the library's objects
#include "thesis_test_systems.hpp"

// The observers' step() allocation test lives in test_alloc.cpp (it interposes malloc).

using namespace setbound;
using namespace setbound::thesis;
using Eigen::MatrixXd;
using Eigen::VectorXd;

using setbound::testing::ch2_plant;
using setbound::testing::ch3_ex1;

namespace {

MatrixXd M2(double a, double b, double c, double d) {
  MatrixXd M(2, 2);
  M << a, b, c, d;
  return M;
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

// ---------------------------------------------------------------------------------------
// Chapter 2: Algorithm 2 and the online observer.
#include "setbound/thesis/lpv.hpp"

namespace {

// Simulates the plant and the observer; checks e_kᵀPe_k ≤ μ_k c̄ and lower ≤ x ≤ upper at every
// step. mode 0: uniform w, 1: bang-bang (vertex) w. Returns the largest ratio eᵀPe/(μc̄).
double run_lti(const Plant& p, const EllipsoidalSMDesign& d, const VectorXd& x0, const VectorXd& xhat0, double mu0,
               int steps, int mode, std::mt19937& rng, bool check_mu = true) {
  EllipsoidalSMObserver obs(p, d, xhat0, mu0);
  std::uniform_real_distribution<double> U(-1, 1);
  VectorXd x = x0;
  double worst = 0;
  for (int k = 0; k < steps; ++k) {
    const VectorXd e = x - obs.center();
    const double ratio = e.dot(d.P * e) / (obs.mu() * d.cbar);
    worst = std::max(worst, ratio);
    EXPECT_LE(ratio, 1.0 + 1e-9) << "step " << k;
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      EXPECT_LE(obs.lower()(i), x(i)) << "step " << k;
      EXPECT_GE(obs.upper()(i), x(i)) << "step " << k;
    }
    if (check_mu) {  // μ_k = 1 + (1 − λ)^k (μ_0 − 1), up to the documented rounding inflation
      // (centre rounding: up to ~1.5e-9 relative per step in these runs, accumulated over up to
      // 80 steps; a wrong recursion would be off by O(λ))
      const double closed = 1 + std::pow(1 - d.lambda, k) * (mu0 - 1);
      EXPECT_NEAR(obs.mu(), closed, 3e-9 * (k + 1) * closed) << "step " << k;
      EXPECT_GE(obs.mu(), closed * (1 - 1e-15));
    }
    VectorXd w(p.m());
    for (Eigen::Index i = 0; i < w.size(); ++i) {
      const double s = mode == 0 ? U(rng) : (U(rng) < 0 ? -1.0 : 1.0);
      w(i) = s * d.wbar(i);
    }
    VectorXd u = VectorXd::Constant(p.nu(), k < 9 ? 1.0 : 0.0);
    const VectorXd y = p.C * x + p.Z * w.tail(p.nv());
    obs.step(y, u);
    x = p.A * x + p.B * u + p.F * w.head(p.nd());
  }
  return worst;
}

}  // namespace

TEST(ThesisHinf, Ch2Algorithm2AndContainment) {
  const Plant p = ch2_plant();
  const VectorXd wbar = VectorXd::Ones(2);
  const EllipsoidalSMDesign d = design_ellipsoidal_sm_observer(p, wbar);
  ASSERT_EQ(d.passes.size(), 2u);
  EXPECT_GT(d.lambda, 0);
  EXPECT_LE(d.lambda, 1);
  // λ is λ_min(Q_ref, P) (LogDet route), c̄ = γ²w̄ᵀw̄/λ, ē∞ = sqrt(diag(c̄P⁻¹)).
  const double lam = Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd>(d.Q_refined, d.P).eigenvalues().minCoeff();
  EXPECT_NEAR(d.lambda, lam, 1e-9 * lam);
  EXPECT_NEAR(d.cbar, d.g * 2 / d.lambda, 1e-12 * d.cbar);
  const VectorXd einf = (d.cbar * d.P.inverse().diagonal()).cwiseSqrt();
  EXPECT_TRUE(((d.e_inf - einf).cwiseAbs().array() <= 1e-10 * einf.array()).all());
  EXPECT_TRUE((d.e_inf.array() >= einf.array() * (1 - 1e-15)).all());
  // Pass 2 uses Q = V⁻¹ with A_o V A_oᵀ − V = −E diag(w̄²/3) Eᵀ from pass 1.
  const MatrixXd Ao1 = p.A - d.passes[0].L[0] * p.C, E1 = p.error_input(d.passes[0].L[0]);
  const MatrixXd V = d.passes[1].Q_input.inverse();
  EXPECT_LE((Ao1 * V * Ao1.transpose() - V + E1 * E1.transpose() / 3.0).norm(), 1e-10 * V.norm());
  // The certified inequality behind the recursion.
  const MatrixXd Ao = p.A - d.L * p.C;
  EXPECT_TRUE(hinf_detail::certify_dissipation(d.P, d.lambda * d.P, Ao, p.error_input(d.L), d.g, 1e-12));
  EXPECT_TRUE(hinf_detail::certify_dissipation(d.P, d.Q_refined * (1 - 1e-6), Ao, p.error_input(d.L), d.g, 0));
  // Refined Q has a larger log det than any scaled-down feasible competitor: Q_input scaled to feasibility.
  EXPECT_GE(std::log(d.Q_refined.determinant()), std::log(d.Q_input.determinant()) - 1e-6);
  // μ0 from the box x0 ∈ [−1, 1] × {0}, x̂0 = 0, and from the ball of radius 1 (γ_ε = 1).
  VectorXd lo(2), hi(2);
  lo << -1, 0;
  hi << 1, 0;
  const double mu_v = mu0_from_vertices(d, box_corners(lo, hi));
  const double mu_b = mu0_from_ball(d, 1.0);
  EXPECT_NEAR(mu_v, std::max(1.0, d.P(0, 0) / d.cbar), 1e-12 * mu_v);
  const double lmax = Eigen::SelfAdjointEigenSolver<MatrixXd>(d.P).eigenvalues().maxCoeff();
  EXPECT_NEAR(mu_b, std::max(1.0, lmax / d.cbar), 1e-12 * mu_b);
  EXPECT_LE(mu_v, mu_b * (1 + 1e-12));
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    VectorXd x0(2);
    x0 << (trial % 2 ? (trial % 4 == 1 ? 1.0 : -1.0) : std::uniform_real_distribution<double>(-1, 1)(rng)), 0;
    run_lti(p, d, x0, VectorXd::Zero(2), mu_v, 60, trial % 2, rng);
  }
}

TEST(ThesisHinf, LambdaRoutesAreOrderedAndValid) {
  const Plant p = ch2_plant();
  EllipsoidalSMOptions o;
  o.lambda_route = LambdaRoute::Largest;
  const EllipsoidalSMDesign d = design_ellipsoidal_sm_observer(p, VectorXd::Ones(2), o);
  for (const auto& ps : d.passes) {
    EXPECT_GE(ps.lambda_direct, ps.lambda_refined * (1 - 1e-6));  // direct is the best over all Q
    EXPECT_GE(ps.lambda_direct, ps.lambda_input * (1 - 1e-6));
    const double best = std::max({ps.lambda_direct, ps.lambda_refined, ps.lambda_input});
    EXPECT_NEAR(ps.lambda, best, 1e-6 * best);  // certification may lower it by a relative 1e-9·4^k
    EXPECT_LE(ps.lambda, best);
  }
  const MatrixXd Ao = p.A - d.L * p.C;
  EXPECT_TRUE(hinf_detail::certify_dissipation(d.P, d.lambda * d.P, Ao, p.error_input(d.L), d.g, 1e-12));
  std::mt19937 rng(3);
  run_lti(p, d, VectorXd::Zero(2), VectorXd::Zero(2), 1.0, 40, 1, rng);
}

TEST(ThesisHinf, RandomSystemsContainment) {
  std::mt19937 rng(11);
  std::normal_distribution<double> N01;
  int done = 0;
  for (int s = 0; done < 6 && s < 40; ++s) {
    const int n = 2 + s % 3, ny = 1 + s % 2, nd = 1 + (s % 2), nv = ny;
    MatrixXd A(n, n), C(ny, n), F(n, nd), Z = 0.1 * MatrixXd::Identity(ny, nv), B(n, 1);
    for (Eigen::Index i = 0; i < A.size(); ++i) A(i) = N01(rng);
    A *= 1.1 / hinf_detail::spectral_radius(A);
    for (Eigen::Index i = 0; i < C.size(); ++i) C(i) = N01(rng);
    for (Eigen::Index i = 0; i < F.size(); ++i) F(i) = 0.3 * N01(rng);
    for (Eigen::Index i = 0; i < B.size(); ++i) B(i) = N01(rng);
    const Plant p(A, B, C, F, Z);
    const VectorXd wbar = VectorXd::Constant(nd + nv, 0.5);
    EllipsoidalSMDesign d;
    try {
      d = design_ellipsoidal_sm_observer(p, wbar);
    } catch (const NotDetectableError&) {
      continue;
    }
    ++done;
    for (const auto& ps : d.passes) EXPECT_FALSE(ps.refinement_failed) << "seed " << s << " |P| " << ps.P.norm();
    const VectorXd lo = -VectorXd::Ones(n), hi = VectorXd::Ones(n);
    const double mu0 = mu0_from_vertices(d, box_corners(lo, hi));
    for (int mode = 0; mode < 2; ++mode) {
      VectorXd x0(n);
      for (int i = 0; i < n; ++i) x0(i) = mode ? (N01(rng) < 0 ? -1.0 : 1.0) : std::uniform_real_distribution<double>(-1, 1)(rng);
      run_lti(p, d, x0, VectorXd::Zero(n), mu0, 80, mode, rng);
    }
  }
  EXPECT_EQ(done, 6);
}

TEST(ThesisHinf, ObserverBadInputLeavesStateUnchanged) {
  const Plant p = ch2_plant();
  const EllipsoidalSMDesign d = design_ellipsoidal_sm_observer(p, VectorXd::Ones(2));
  EllipsoidalSMObserver obs(p, d, VectorXd::Zero(2), 2.0);
  obs.step(VectorXd::Ones(1), VectorXd::Ones(1));
  const VectorXd c = obs.center();
  const double mu = obs.mu();
  VectorXd ynan(1);
  ynan << INFINITY;  // NaN is a missing reading (issue 24)
  try {
    obs.step(ynan, VectorXd::Ones(1));
    FAIL();
  } catch (const NotFiniteError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("y:", 0), 0u) << e.what();
  }
  EXPECT_THROW(obs.step(VectorXd::Ones(2), VectorXd::Ones(1)), DimensionError);
  EXPECT_THROW(obs.step(VectorXd::Ones(1), VectorXd::Ones(3)), DimensionError);
  EXPECT_EQ(obs.center(), c);
  EXPECT_EQ(obs.mu(), mu);
  EXPECT_EQ(obs.steps(), 1);
  EXPECT_THROW(design_ellipsoidal_sm_observer(p, VectorXd::Ones(3)), DimensionError);
  EXPECT_THROW(EllipsoidalSMObserver(p, d, VectorXd::Zero(2), -1.0), InvalidArgumentError);
}

// ---------------------------------------------------------------------------------------
// Chapter 3.

namespace {


}  // namespace

TEST(ThesisLpv, WeightsClosedFormLpAndErrors) {
  MatrixXd theta(4, 2);  // Ch. 3 Ex 2 order: [−1, 9], [−1, 11], [1, 9], [1, 11]
  theta << -1, 9, -1, 11, 1, 9, 1, 11;
  PolytopicWeights w(theta);
  EXPECT_TRUE(w.is_box());
  MatrixXd tri(3, 2);  // a triangle: LP route
  tri << 0, 0, 2, 0, 0, 2;
  PolytopicWeights wt(tri);
  EXPECT_FALSE(wt.is_box());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0, 1);
  for (int k = 0; k < 20; ++k) {
    VectorXd rho(2);
    rho << -1 + 2 * U(rng), 9 + 2 * U(rng);
    const VectorXd a = w(rho);
    EXPECT_NEAR(a.sum(), 1.0, 1e-14);
    EXPECT_GE(a.minCoeff(), 0.0);
    EXPECT_LE((theta.transpose() * a - rho).norm(), 1e-13);
    VectorXd r2(2);
    r2 << U(rng), U(rng);
    r2 *= U(rng) * 2 / std::max(1.0, r2.sum());
    const VectorXd b = wt(r2);
    EXPECT_NEAR(b.sum(), 1.0, 1e-12);
    EXPECT_GE(b.minCoeff(), 0.0);
    EXPECT_LE((tri.transpose() * b - r2).norm(), 1e-7);
  }
  VectorXd out(2);
  out << 1.5, 10;
  try {
    w(out);
    FAIL();
  } catch (const InvalidArgumentError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("rho:", 0), 0u) << e.what();
  }
  VectorXd out2(2);
  out2 << 1.5, 1.5;
  EXPECT_THROW(wt(out2), InvalidArgumentError);
  EXPECT_THROW(w(VectorXd::Zero(3)), DimensionError);
}

TEST(ThesisLpv, Ex1DesignAndContainment) {
  const LpvSystem sys = ch3_ex1();
  const EllipsoidalSMDesign d = design_ellipsoidal_sm_observer_lpv(sys, VectorXd::Ones(2));
  ASSERT_EQ(d.L_vertices.size(), 2u);
  EXPECT_GT(d.lambda, 0);
  EXPECT_LE(d.lambda, 1);
  EXPECT_NEAR(d.lambda, std::max(d.lambda_input, d.lambda_refined), 1e-8 * d.lambda);
  for (size_t i = 0; i < 2; ++i) {
    const MatrixXd Ao = sys.A[i] - d.L_vertices[i] * sys.C;
    EXPECT_LT(hinf_detail::spectral_radius(Ao), 1.0);
    MatrixXd E(2, 2);
    E << sys.F[i], -d.L_vertices[i] * sys.Z;
    EXPECT_TRUE(hinf_detail::certify_dissipation(d.P, d.lambda * d.P, Ao, E, d.g, 1e-12));
  }
  VectorXd lo(2), hi(2);
  lo << -0.1, -2;
  hi << 0.1, -2;
  const double mu0 = mu0_from_vertices(d, box_corners(lo, hi));
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(-1, 1), R(0.05, 0.1);
  for (int trial = 0; trial < 10; ++trial) {
    LPVEllipsoidalSMObserver obs(sys, d, VectorXd::Zero(2), mu0);
    VectorXd x(2);
    x << 0.1 * U(rng), -2;
    for (int k = 0; k < 100; ++k) {
      const VectorXd e = x - obs.center();
      EXPECT_LE(e.dot(d.P * e), obs.mu() * d.cbar * (1 + 1e-9));
      for (int i = 0; i < 2; ++i) {
        EXPECT_LE(obs.lower()(i), x(i));
        EXPECT_GE(obs.upper()(i), x(i));
      }
      const double closed = 1 + std::pow(1 - d.lambda, k) * (mu0 - 1);
      EXPECT_NEAR(obs.mu(), closed, 1e-7 * closed);
      double r = trial % 2 ? (U(rng) < 0 ? 0.05 : 0.1) : R(rng);
      VectorXd rho(1);
      rho << r;
      VectorXd w(2);
      for (int i = 0; i < 2; ++i) w(i) = trial % 2 ? (U(rng) < 0 ? -1.0 : 1.0) : U(rng);
      VectorXd u = VectorXd::Constant(1, k < 10 ? 10.0 : 0.0);
      const VectorXd y = sys.C * x + sys.Z * w.tail(1);
      obs.step(y, u, rho);
      MatrixXd A = M2(1, r, 0, 1);
      VectorXd b(2);
      b << 0, r;
      x = A * x + b * u(0) + b * w(0);
    }
    // ρ outside: error naming rho, state unchanged.
    const VectorXd c = obs.center();
    VectorXd bad(1);
    bad << 0.2;
    try {
      obs.step(VectorXd::Zero(1), VectorXd::Zero(1), bad);
      FAIL();
    } catch (const InvalidArgumentError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("rho:", 0), 0u) << e.what();
    }
    EXPECT_EQ(obs.center(), c);
  }
}

TEST(ThesisHinfCapi, DesignObserverAndErrors) {
  // Ch. 2 through the C ABI: design, μ0 from the box, a few steps; then bad input.
  const double A[] = {0.2, 0.2, 0, 0.5}, B[] = {1, 1}, C[] = {1, 0}, F[] = {0, 0.1}, Z[] = {0.1}, wbar[] = {1, 1};
  sb_hinf_design* d = nullptr;
  ASSERT_EQ(sb_hinf_design_create(1, 2, 1, 1, 1, 1, 0, A, B, C, F, Z, nullptr, wbar, nullptr, SB_LAMBDA_DEFAULT, 2, &d),
            SB_OK)
      << sb_last_error();
  double sc[9];
  ASSERT_EQ(sb_hinf_design_get(d, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, sc), SB_OK);
  const EllipsoidalSMDesign ref = design_ellipsoidal_sm_observer(ch2_plant(), VectorXd::Ones(2));
  EXPECT_NEAR(sc[0], ref.gamma, 1e-9 * ref.gamma);
  EXPECT_NEAR(sc[2], ref.lambda, 1e-9);
  const double lo[] = {-1, 0}, hi[] = {1, 0};
  double mu0 = 0;
  ASSERT_EQ(sb_hinf_design_mu0_box(d, lo, hi, &mu0), SB_OK);
  sb_hinf_observer* o = nullptr;
  const double x0[] = {0, 0};
  ASSERT_EQ(sb_hinf_observer_create(d, x0, mu0, &o), SB_OK);
  double c[2], l[2], h[2], mu = 0;
  const double y[] = {0.2}, u[] = {1};
  ASSERT_EQ(sb_hinf_observer_step(o, y, u, nullptr, c, l, h, &mu), SB_OK);
  const double ynan[] = {INFINITY};  // NaN is a missing reading (issue 24)
  EXPECT_EQ(sb_hinf_observer_step(o, ynan, u, nullptr, c, l, h, &mu), SB_ERR_NOT_FINITE);
  EXPECT_EQ(std::string(sb_last_error()).rfind("sb_hinf_observer_step: y:", 0), 0u) << sb_last_error();
  int steps = 0;
  ASSERT_EQ(sb_hinf_observer_current(o, nullptr, nullptr, nullptr, nullptr, &steps), SB_OK);
  EXPECT_EQ(steps, 1);
  sb_hinf_observer_free(o);
  sb_hinf_design_free(d);
  // Not detectable: x2 unstable and unobserved.
  const double Abad[] = {0.2, 0, 0, 1.2};
  EXPECT_EQ(sb_hinf_design_create(1, 2, 1, 1, 1, 1, 0, Abad, B, C, F, Z, nullptr, wbar, nullptr, -1, 2, &d),
            SB_ERR_NOT_DETECTABLE);
  EXPECT_NE(std::string(sb_last_error()).find("A, C: the pair (A, C) is not detectable"), std::string::npos);
  // ρ outside the polytope.
  const double theta[] = {0, 0, 2, 0, 0, 2}, rho[] = {1.5, 1.5};
  double alpha[3];
  EXPECT_EQ(sb_polytopic_weights(3, 2, theta, rho, alpha), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("rho: (1.5, 1.5) is outside"), std::string::npos) << sb_last_error();
  EXPECT_EQ(sb_brl_ellipsoidal_rpi(2, 1, Abad, F, wbar, nullptr, nullptr, nullptr, nullptr), SB_ERR_INFEASIBLE);
}

// μ0 from a box beyond 20 dimensions (ESO-C on tank30: its 2^30 corners cannot be enumerated):
// an upper bound of every corner's vᵀPv/c̄ (the guarantee needs μ0 >= the true maximum), equal to
// the corners' maximum where they can be enumerated, and bad boxes named.
TEST(ThesisHinf, Mu0FromBoxBoundsEveryCornerBeyondTwentyDimensions) {
  std::mt19937 rng(11);
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_int_distribution<int> bit(0, 1);
  for (const Eigen::Index n : {Eigen::Index(6), Eigen::Index(22), Eigen::Index(30)}) {
    EllipsoidalSMDesign d;
    MatrixXd M(n, n);
    for (Eigen::Index i = 0; i < M.size(); ++i) M.data()[i] = N(rng);
    d.P = M * M.transpose() / static_cast<double>(n) + MatrixXd::Identity(n, n);
    d.cbar = 0.5;
    d.lambda_max_P = ell_rounding::lambda_max_upper(d.P);
    VectorXd lo(n), hi(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      lo(i) = -1.0 - 0.5 * std::abs(N(rng));
      hi(i) = 0.3 * std::abs(N(rng));
    }
    const double mu = mu0_from_box(d, lo, hi);
    if (n <= 20) {
      EXPECT_EQ(mu, mu0_from_vertices(d, box_corners(lo, hi)));
    } else {
      for (int trial = 0; trial < 2000; ++trial) {  // random corners
        VectorXd v(n);
        for (Eigen::Index i = 0; i < n; ++i) v(i) = bit(rng) ? hi(i) : lo(i);
        EXPECT_GE(mu, v.dot(d.P * v) / d.cbar);
      }
      EXPECT_LE(mu, ell_rounding::round_up(d.lambda_max_P * lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).squaredNorm() / d.cbar) * 1.01);
      EXPECT_THROW(box_corners(lo, hi), DimensionError);
    }
    EXPECT_GE(mu, 1.0);
    VectorXd bad = hi;
    bad(0) = lo(0) - 1.0;
    EXPECT_THROW(mu0_from_box(d, lo, bad), InvalidArgumentError);
    EXPECT_THROW(mu0_from_box(d, lo, VectorXd(hi.head(n - 1))), DimensionError);
    bad(0) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(mu0_from_box(d, lo, bad), NotFiniteError);
  }
}
