// CORA's ESO-D design (thesis/eso_d.hpp; Martinez, Loukkas, Meslem 2020, LTI case) feeding the
// thesis's EllipsoidalSMObserver: the three LMIs at the designed point, λ, the γ searches, the box
// recursion against a hand computation, containment, bad input (C++ and C ABI).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>

#include "setbound/thesis/eso_d.hpp"
#include "c_api_common.hpp"  // the C ABI (setbound.h) through the library's objects
#include "thesis_test_systems.hpp"

using namespace setbound;
using namespace setbound::thesis;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

double min_eig(const MatrixXd& M) {
  return Eigen::SelfAdjointEigenSolver<MatrixXd>(0.5 * (M + M.transpose()), Eigen::EigenvaluesOnly).eigenvalues()(0);
}

// −(LMI 2.35) at (P, L, g) with dissipation Q: must be ⪰ 0 (eigenvalues ≥ −1e-8 relative).
void expect_lmi_holds(const Plant& p, const MatrixXd& P, const MatrixXd& L, const MatrixXd& Q, double g,
                      const char* what) {
  const MatrixXd M = hinf_detail::dissipation_block(P, Q, p.A - L * p.C, p.error_input(L), g);
  EXPECT_GE(min_eig(M), -1e-8 * std::max(1.0, M.cwiseAbs().maxCoeff())) << what;
  EXPECT_GE(min_eig(P), 0.0) << what;
}

// Plant with y = x1 (+ noise), a lightly damped rotation; d on both states.
Plant small_plant() {
  MatrixXd A(2, 2), B(2, 1), C(1, 2), F(2, 2), Z(1, 1);
  A << 0.9, 0.2, -0.2, 0.8;
  B << 0, 1;
  C << 1, 0;
  F << 0.05, 0, 0, 0.05;
  Z << 0.1;
  return Plant(A, B, C, F, Z);
}

}  // namespace

TEST(EsoD, ThreeLmisHoldAtTheDesignedPointAndLambdaIsTheGeneralizedMinimum) {
  const Plant p = small_plant();
  const VectorXd wbar = VectorXd::Ones(3);
  const EsoDDesign d = design_eso_d(p, wbar);
  ASSERT_EQ(d.sm.passes.size(), 2u);
  const std::vector<double> grid = cora_gamma_grid();
  ASSERT_EQ(grid.size(), 100u);
  EXPECT_EQ(grid.front(), 1.0);
  EXPECT_EQ(grid.back(), 50.0);
  for (int s = 0; s < 2; ++s) {
    const EllipsoidalSMPass& ps = d.sm.passes[static_cast<size_t>(s)];
    const auto& tr = s == 0 ? d.trials_a : d.trials_c;
    // The search: every γ before the last one failed, the last one is certified, in grid order.
    ASSERT_FALSE(tr.empty());
    for (size_t i = 0; i < tr.size(); ++i) {
      EXPECT_EQ(tr[i].gamma, grid[i]);
      EXPECT_EQ(tr[i].status == lmi::SolveStatus::Optimal, i + 1 == tr.size());
    }
    const double gm = tr.back().gamma;
    EXPECT_GE(ps.g, gm * gm);
    EXPECT_LE(ps.g, gm * gm * (1 + 1e-5));
    // (a)/(c): LMI (2.35) at the designed (P, L, g) with Q = I / V⁻¹; then with Q := λP.
    expect_lmi_holds(p, ps.P, ps.L.front(), ps.Q_input, ps.g, s == 0 ? "(a)" : "(c)");
    expect_lmi_holds(p, ps.P, ps.L.front(), ps.lambda * ps.P, ps.g, "Q = lambda P");
    // λ = min generalized eigenvalue of (Q, P), certified (rounded down by a relative 1e-9 at most).
    Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> ges(ps.Q_input, ps.P, Eigen::EigenvaluesOnly);
    const double lmin = ges.eigenvalues().minCoeff();
    EXPECT_GT(ps.lambda, 0.0);
    EXPECT_LE(ps.lambda, 1.0);
    EXPECT_LE(ps.lambda, lmin);
    EXPECT_GE(ps.lambda, lmin * (1 - 1e-8));
    EXPECT_GE(min_eig(ps.Q_input - ps.lambda * ps.P), -1e-12 * ps.P.norm());
  }
  EXPECT_TRUE(d.sm.passes[0].Q_input.isIdentity());
  // (b): V ⪰ 0 and A_o V A_oᵀ − V ⪯ −E (I/3) Eᵀ with (A_o, E) of step (a); Q of (c) = V⁻¹.
  const MatrixXd La = d.sm.passes[0].L.front();
  const MatrixXd Ao = p.A - La * p.C, E = p.error_input(La);
  EXPECT_TRUE(d.W.isApprox(MatrixXd::Identity(3, 3) / 3.0));
  const MatrixXd R = -(Ao * d.sm.V * Ao.transpose() - d.sm.V + E * d.W * E.transpose());
  EXPECT_GE(min_eig(R), -1e-8 * std::max(1.0, d.sm.V.cwiseAbs().maxCoeff()));
  EXPECT_GT(min_eig(d.sm.V), 0.0);
  EXPECT_EQ(d.lyapunov_shift, 0.0);
  // Least trace: the Lyapunov equation holds with equality.
  EXPECT_LE(R.cwiseAbs().maxCoeff(), 1e-12 * std::max(1.0, d.sm.V.cwiseAbs().maxCoeff()));
  EXPECT_LE((d.sm.passes[1].Q_input * d.sm.V - MatrixXd::Identity(2, 2)).cwiseAbs().maxCoeff(), 1e-9);
  // The design's result is pass (c); Y = P L.
  EXPECT_EQ(d.sm.L, d.sm.passes[1].L.front());
  EXPECT_LE((d.sm.P * d.sm.L - d.Y).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, d.Y.cwiseAbs().maxCoeff()));
  EXPECT_NEAR(d.sm.cbar, d.sm.g * 3.0 / d.sm.lambda, 1e-12 * d.sm.cbar);
}

TEST(EsoD, BoxRecursionMatchesAHandComputation) {
  // n = 1: x⁺ = 0.8x + u + 0.1d, y = x + 0.2v. After the design, the observer must be
  // x̂⁺ = (a − L)x̂ + u + L y, μ⁺ = (1 − λ)μ + λ, box x̂ ± sqrt(c̄ μ / P) with c̄ = γ² w̄ᵀw̄ / λ.
  MatrixXd A(1, 1), B(1, 1), C(1, 1), F(1, 1), Z(1, 1);
  A << 0.8;
  B << 1;
  C << 1;
  F << 0.1;
  Z << 0.2;
  const Plant p(A, B, C, F, Z);
  const VectorXd wbar = VectorXd::Ones(2);
  const EsoDDesign d = design_eso_d(p, wbar);
  const double L = d.sm.L(0, 0), P = d.sm.P(0, 0), lam = d.sm.lambda, g = d.sm.g;
  const double cbar = g * 2.0 / lam;
  EXPECT_NEAR(d.sm.cbar, cbar, 1e-13 * cbar);
  EXPECT_NEAR(d.sm.e_inf(0), std::sqrt(cbar / P), 1e-12);
  // For n = 1, λ = Q/P exactly (Q = V⁻¹ of step (b)).
  EXPECT_NEAR(lam, d.sm.passes[1].Q_input(0, 0) / P, 1e-9 * lam);
  // Step (b) for n = 1: V = (0.1² + L_a² 0.2²)/3 / (1 − (0.8 − L_a)²).
  const double La = d.sm.passes[0].L.front()(0, 0);
  EXPECT_NEAR(d.sm.V(0, 0), (0.01 + La * La * 0.04) / 3.0 / (1 - (0.8 - La) * (0.8 - La)), 1e-12);
  VectorXd x0(1);
  x0 << 0.3;
  const double mu0 = 4.0;
  EllipsoidalSMObserver obs(p, d.sm, x0, mu0);
  double xh = 0.3, mu = mu0;
  const double us[] = {0.1, 0.0, -0.3, 0.2};
  for (int k = 0; k < 4; ++k) {
    VectorXd y(1), u(1);
    const double yk = xh + (k % 2 ? -0.1 : 0.1);  // a reading inside the observer's output set (used)
    y << yk;
    u << us[k];
    obs.step(y, u);
    EXPECT_EQ(obs.last_check().status[0], OutputStatus::Used);
    xh = (0.8 - L) * xh + us[k] + L * yk;
    mu = (1 - lam) * mu + lam;
    const double half = std::sqrt(cbar * mu / P);
    EXPECT_NEAR(obs.center()(0), xh, 1e-14);
    EXPECT_NEAR(obs.mu(), mu, 1e-12 * mu);
    EXPECT_GE(mu * (1 + 1e-9), obs.mu());
    // The observer's box is the hand box, rounded outwards (relative 1e-12 at most).
    EXPECT_LE(obs.lower()(0), xh - half);
    EXPECT_GE(obs.upper()(0), xh + half);
    EXPECT_NEAR(obs.upper()(0) - obs.lower()(0), 2 * half, 1e-10 * half);
  }
}

TEST(EsoD, RandomSystemsContainTheTruthWithRandomAndVertexDisturbances) {
  std::mt19937 rng(2020);
  std::normal_distribution<double> N01;
  std::uniform_real_distribution<double> U11(-1, 1);
  int done = 0;
  for (int s = 0; done < 10 && s < 40; ++s) {
    const int n = 2 + s % 3, ny = 1 + s % 2, nd = n, nv = ny;
    MatrixXd A(n, n), C(ny, n), F = 0.05 * MatrixXd::Identity(n, nd), Z = 0.1 * MatrixXd::Identity(ny, nv), B(n, 1);
    for (Eigen::Index i = 0; i < A.size(); ++i) A(i) = N01(rng);
    A *= (s % 2 ? 1.05 : 0.9) / hinf_detail::spectral_radius(A);
    for (Eigen::Index i = 0; i < C.size(); ++i) C(i) = N01(rng);
    for (Eigen::Index i = 0; i < B.size(); ++i) B(i) = N01(rng);
    const Plant p(A, B, C, F, Z);
    const VectorXd wbar = VectorXd::Ones(nd + nv);
    EsoDDesign d;
    try {
      d = design_eso_d(p, wbar);
    } catch (const NotDetectableError&) {
      continue;
    } catch (const InfeasibleError&) {
      continue;  // γ beyond the grid: counted by `done`
    }
    ++done;
    const VectorXd lo = -VectorXd::Ones(n), hi = VectorXd::Ones(n);
    const double mu0 = mu0_from_vertices(d.sm, box_corners(lo, hi));
    for (int vertex = 0; vertex < 2; ++vertex) {
      EllipsoidalSMObserver obs(p, d.sm, VectorXd::Zero(n), mu0);
      VectorXd x(n);
      for (int i = 0; i < n; ++i) x(i) = vertex ? (N01(rng) < 0 ? -1.0 : 1.0) : U11(rng);
      for (int k = 0; k < 120; ++k) {
        ASSERT_TRUE(((obs.lower().array() <= x.array()) && (x.array() <= obs.upper().array())).all())
            << "seed " << s << " vertex " << vertex << " step " << k;
        VectorXd w(nd + nv);
        for (int i = 0; i < nd + nv; ++i) w(i) = vertex ? (N01(rng) < 0 ? -1.0 : 1.0) : U11(rng);
        VectorXd u(1);
        u << std::sin(0.1 * k);
        const VectorXd y = C * x + Z * w.tail(nv);
        obs.step(y, u);
        x = A * x + B * u + F * w.head(nd);
      }
    }
  }
  EXPECT_EQ(done, 10);
}

TEST(EsoD, BadInputIsNamed) {
  const Plant p = small_plant();
  EXPECT_THROW(design_eso_d(p, VectorXd::Ones(2)), DimensionError);
  VectorXd wn = VectorXd::Ones(3);
  wn(1) = NAN;
  EXPECT_THROW(design_eso_d(p, wn), NotFiniteError);
  EsoDOptions bad;
  bad.gammas = {2.0, 1.0};
  EXPECT_THROW(design_eso_d(p, VectorXd::Ones(3), bad), InvalidArgumentError);
  bad.gammas = {1.0, NAN};
  EXPECT_THROW(design_eso_d(p, VectorXd::Ones(3), bad), NotFiniteError);
  bad.gammas = {};
  bad.w_covariance = MatrixXd::Identity(2, 2);
  EXPECT_THROW(design_eso_d(p, VectorXd::Ones(3), bad), DimensionError);
  // Unobservable unstable mode.
  MatrixXd A(2, 2), C(1, 2);
  A << 0.5, 0, 0, 1.2;
  C << 1, 0;
  EXPECT_THROW(design_eso_d(Plant(A, p.B, C, p.F, p.Z), VectorXd::Ones(3)), NotDetectableError);
  // Infeasible: a grid below the optimal γ (every γ with a certificate of infeasibility).
  EsoDOptions low;
  low.gammas = {0.001, 0.002};
  try {
    design_eso_d(p, VectorXd::Ones(3), low);
    ADD_FAILURE() << "expected InfeasibleError";
  } catch (const InfeasibleError& e) {
    EXPECT_NE(std::string(e.what()).find("step (a)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("infeasible for every gamma"), std::string::npos) << e.what();
  }
  // Iteration limit: one iteration cannot prove infeasibility at these γ, so each is "not solved
  // (iteration limit)" — a NumericalError, never reported as "infeasible".
  EsoDOptions lim = low;
  lim.hinf.solver.max_iterations = 1;
  try {
    design_eso_d(p, VectorXd::Ones(3), lim);
    ADD_FAILURE() << "expected NumericalError";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("infeasible at 0, not solved (iteration limit) at 2"), std::string::npos)
        << e.what();
  }
  // The shared search through the thesis API, and its verdict words.
  const GammaGridGain gg = hinf_observer_gain_first_feasible(p);
  EXPECT_EQ(gg.trials.back().status, lmi::SolveStatus::Optimal);
  EXPECT_GE(gg.gain.gamma, hinf_observer_gain(p).gamma * (1 - 1e-6));
  EXPECT_EQ(hinf_detail::solve_verdict(lmi::SolveStatus::MaxIterations), "not solved (iteration limit)");
  EXPECT_EQ(hinf_detail::solve_verdict(lmi::SolveStatus::Infeasible), "infeasible");
}

TEST(EsoDCapi, DesignIsAThesisDesignHandle) {
  const double A[] = {0.9, 0.2, -0.2, 0.8}, B[] = {0, 1}, C[] = {1, 0}, F[] = {0.05, 0, 0, 0.05}, Z[] = {0.1},
               wbar[] = {1, 1, 1};
  sb_hinf_design* d = nullptr;
  ASSERT_EQ(sb_eso_d_design_create(2, 1, 1, 2, 1, A, B, C, F, Z, wbar, nullptr, 0, nullptr, &d), SB_OK)
      << sb_last_error();
  const EsoDDesign ref = design_eso_d(small_plant(), VectorXd::Ones(3));
  double sc[9];
  ASSERT_EQ(sb_hinf_design_get(d, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, sc), SB_OK);
  EXPECT_EQ(sc[0], ref.sm.gamma);
  EXPECT_EQ(sc[2], ref.sm.lambda);
  int npass = 0;
  ASSERT_EQ(sb_hinf_design_dims(d, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, &npass), SB_OK);
  EXPECT_EQ(npass, 2);
  int count = 0;
  ASSERT_EQ(sb_hinf_design_gammas(d, 1, &count, nullptr, nullptr), SB_OK);
  EXPECT_EQ(count, static_cast<int>(ref.trials_c.size()));
  std::vector<double> gm(static_cast<size_t>(count));
  std::vector<int> st(static_cast<size_t>(count));
  int small = count - 1;
  if (count > 1) {
    EXPECT_EQ(sb_hinf_design_gammas(d, 1, &small, gm.data(), st.data()), SB_ERR_BUFFER_TOO_SMALL);
    EXPECT_EQ(small, count);
  }
  ASSERT_EQ(sb_hinf_design_gammas(d, 1, &count, gm.data(), st.data()), SB_OK);
  EXPECT_EQ(st.back(), SB_LMI_OPTIMAL);
  EXPECT_EQ(gm.back(), ref.trials_c.back().gamma);
  EXPECT_EQ(sb_hinf_design_gammas(d, 2, &count, nullptr, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("search:"), std::string::npos) << sb_last_error();
  double shift = -1;
  ASSERT_EQ(sb_eso_d_design_lyapunov_shift(d, &shift), SB_OK);
  EXPECT_EQ(shift, 0.0);
  // The thesis observer runs on it.
  sb_hinf_observer* o = nullptr;
  const double x0[] = {0, 0};
  ASSERT_EQ(sb_hinf_observer_create(d, x0, 2.0, &o), SB_OK) << sb_last_error();
  double c[2], l[2], h[2], mu = 0;
  const double y[] = {0.2}, u[] = {1};
  ASSERT_EQ(sb_hinf_observer_step(o, y, u, nullptr, c, l, h, &mu), SB_OK);
  EXPECT_NEAR(mu, (1 - ref.sm.lambda) * 2.0 + ref.sm.lambda, 1e-12);
  sb_hinf_observer_free(o);
  sb_hinf_design_free(d);
  // An Algorithm-2 design has no γ grid.
  ASSERT_EQ(sb_hinf_design_create(1, 2, 1, 1, 2, 1, 0, A, B, C, F, Z, nullptr, wbar, nullptr, SB_LAMBDA_DEFAULT, 2, &d),
            SB_OK)
      << sb_last_error();
  EXPECT_EQ(sb_hinf_design_gammas(d, 0, &count, nullptr, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("design: not a gamma-grid design"), std::string::npos);
  EXPECT_EQ(sb_eso_d_design_lyapunov_shift(d, &shift), SB_ERR_INVALID_ARGUMENT);
  sb_hinf_design_free(d);
  // Bad input: NULL out, shapes, NaN, grid, not detectable, infeasible grid.
  EXPECT_EQ(sb_eso_d_design_create(2, 1, 1, 2, 1, A, B, C, F, Z, wbar, nullptr, 0, nullptr, nullptr),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_eso_d_design_create(0, 1, 1, 2, 1, A, B, C, F, Z, wbar, nullptr, 0, nullptr, &d), SB_ERR_DIMENSION);
  const double wnan[] = {1, NAN, 1};
  EXPECT_EQ(sb_eso_d_design_create(2, 1, 1, 2, 1, A, B, C, F, Z, wnan, nullptr, 0, nullptr, &d), SB_ERR_NOT_FINITE);
  EXPECT_NE(std::string(sb_last_error()).find("wbar"), std::string::npos) << sb_last_error();
  EXPECT_EQ(sb_eso_d_design_create(2, 1, 1, 2, 1, A, B, C, F, Z, wbar, nullptr, 3, nullptr, &d),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("gammas"), std::string::npos) << sb_last_error();
  EXPECT_EQ(sb_eso_d_design_create(2, 1, 1, 2, 1, A, B, C, F, Z, wbar, nullptr, SB_HINF_MAX_GAMMAS + 1, wbar, &d),
            SB_ERR_INVALID_ARGUMENT);
  const double Abad[] = {0.5, 0, 0, 1.2};
  EXPECT_EQ(sb_eso_d_design_create(2, 1, 1, 2, 1, Abad, B, C, F, Z, wbar, nullptr, 0, nullptr, &d),
            SB_ERR_NOT_DETECTABLE);
  const double low[] = {0.001, 0.002};
  EXPECT_EQ(sb_eso_d_design_create(2, 1, 1, 2, 1, A, B, C, F, Z, wbar, nullptr, 2, low, &d), SB_ERR_INFEASIBLE);
  EXPECT_NE(std::string(sb_last_error()).find("infeasible for every gamma"), std::string::npos) << sb_last_error();
  EXPECT_EQ(d, nullptr);
}
