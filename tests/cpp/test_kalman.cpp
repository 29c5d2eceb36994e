// Kalman baseline (papers.md §2.3): exact conditional moments against batch Gaussian
// conditioning (also with correlated noise), steady state against an independently iterated
// Riccati equation, Monte Carlo mean square error against trace(G), Joseph-form symmetry and
// semidefiniteness, bad input.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "setbound/estimators/point/kalman.hpp"
#include "ell_test_systems.hpp"
#include "test_helpers.hpp"

using setbound::KalmanFilter;
using setbound::LinearSystem;
using setbound::testing::expect_error_naming;

using setbound::testing::bc14;
using setbound::testing::me17;

namespace {

Eigen::MatrixXd random_matrix(std::mt19937& g, Eigen::Index r, Eigen::Index c, double scale = 1.0) {
  std::normal_distribution<double> N(0.0, 1.0);
  Eigen::MatrixXd M(r, c);
  for (Eigen::Index j = 0; j < c; ++j)
    for (Eigen::Index i = 0; i < r; ++i) M(i, j) = scale * N(g);
  return M;
}

Eigen::MatrixXd random_spd(std::mt19937& g, Eigen::Index n, double floor = 0.1) {
  const Eigen::MatrixXd M = random_matrix(g, n, n);
  return M * M.transpose() + floor * Eigen::MatrixXd::Identity(n, n);
}

// Standard (non-Joseph) Riccati iteration for the predicted covariance with cross-covariance
// S = E W Fᵀ: P⁺ = A P Aᵀ + Q − (A P Cᵀ + S)(C P Cᵀ + R)⁻¹(A P Cᵀ + S)ᵀ. Returns the fixed point.
Eigen::MatrixXd riccati_fixed_point(const LinearSystem& s, const Eigen::MatrixXd& W) {
  const Eigen::MatrixXd Q = s.E() * W * s.E().transpose(), R = s.F() * W * s.F().transpose(),
                        S = s.E() * W * s.F().transpose();
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(s.nx(), s.nx());
  for (int it = 0; it < 100000; ++it) {
    const Eigen::MatrixXd M = s.A() * P * s.C().transpose() + S;
    Eigen::MatrixXd Pn = s.A() * P * s.A().transpose() + Q -
                         M * (s.C() * P * s.C().transpose() + R).ldlt().solve(M.transpose());
    Pn = 0.5 * (Pn + Pn.transpose()).eval();
    const double diff = (Pn - P).cwiseAbs().maxCoeff();
    P = Pn;
    if (diff < 1e-15 * std::max(1.0, P.cwiseAbs().maxCoeff()) && it > 10) break;
  }
  return P;
}

// Batch reference: v = [x_0; ω_0; …; ω_{N−1}] ~ N(m, Σ); x_k and y_k are affine in v, so
// E[x_k | y_0..y_j] and its covariance follow from one Gaussian conditioning.
struct Batch {
  Eigen::Index n, ny, nw, N;
  Eigen::VectorXd m;
  Eigen::MatrixXd Sigma;
  std::vector<Eigen::MatrixXd> Tx, Ty;  // x_k = Tx[k] v + bx[k], y_k = Ty[k] v + by[k]
  std::vector<Eigen::VectorXd> bx, by;
};

Batch make_batch(const LinearSystem& s, const Eigen::VectorXd& m0, const Eigen::MatrixXd& G0,
                 const Eigen::MatrixXd& W, const std::vector<Eigen::VectorXd>& u, Eigen::Index N) {
  Batch b;
  b.n = s.nx();
  b.ny = s.ny();
  b.nw = s.nw();
  b.N = N;
  const Eigen::Index dim = b.n + N * b.nw;
  b.m = Eigen::VectorXd::Zero(dim);
  b.m.head(b.n) = m0;
  b.Sigma = Eigen::MatrixXd::Zero(dim, dim);
  b.Sigma.topLeftCorner(b.n, b.n) = G0;
  for (Eigen::Index k = 0; k < N; ++k) b.Sigma.block(b.n + k * b.nw, b.n + k * b.nw, b.nw, b.nw) = W;
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(b.n, dim);
  T.leftCols(b.n).setIdentity();
  Eigen::VectorXd c = Eigen::VectorXd::Zero(b.n);
  for (Eigen::Index k = 0; k <= N; ++k) {
    b.Tx.push_back(T);
    b.bx.push_back(c);
    if (k == N) break;
    Eigen::MatrixXd Ty = s.C() * T;
    Ty.block(0, b.n + k * b.nw, b.ny, b.nw) += s.F();
    b.Ty.push_back(Ty);
    b.by.push_back(s.C() * c + s.D() * u[static_cast<size_t>(k)]);
    Eigen::MatrixXd Tn = s.A() * T;
    Tn.block(0, b.n + k * b.nw, b.n, b.nw) += s.E();
    T = Tn;
    c = s.A() * c + s.B() * u[static_cast<size_t>(k)];
  }
  return b;
}

// E[x_k | y_0..y_j], Cov[x_k | y_0..y_j].
std::pair<Eigen::VectorXd, Eigen::MatrixXd> condition(const Batch& b, const std::vector<Eigen::VectorXd>& y,
                                                      Eigen::Index k, Eigen::Index j) {
  const Eigen::Index dim = b.m.size();
  Eigen::MatrixXd Y((j + 1) * b.ny, dim);
  Eigen::VectorXd yc((j + 1) * b.ny);
  for (Eigen::Index i = 0; i <= j; ++i) {
    Y.middleRows(i * b.ny, b.ny) = b.Ty[static_cast<size_t>(i)];
    yc.segment(i * b.ny, b.ny) = y[static_cast<size_t>(i)] - b.by[static_cast<size_t>(i)];
  }
  const Eigen::MatrixXd& T = b.Tx[static_cast<size_t>(k)];
  const Eigen::MatrixXd SY = b.Sigma * Y.transpose();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(Y * SY);
  const Eigen::MatrixXd TSY = T * SY;
  const Eigen::VectorXd mean = T * b.m + b.bx[static_cast<size_t>(k)] + TSY * ldlt.solve(yc - Y * b.m);
  Eigen::MatrixXd cov = T * b.Sigma * T.transpose() - TSY * ldlt.solve(TSY.transpose());
  return {mean, cov};
}

void expect_matches_batch(const LinearSystem& s, const Eigen::MatrixXd& W, std::mt19937& g) {
  const Eigen::Index N = 6;
  const Eigen::VectorXd m0 = random_matrix(g, s.nx(), 1);
  const Eigen::MatrixXd G0 = random_spd(g, s.nx());
  std::vector<Eigen::VectorXd> u, y;
  for (Eigen::Index k = 0; k < N; ++k) u.push_back(random_matrix(g, s.nu(), 1));
  // Any data will do (the conditional moments are affine in y); simulate a plausible run.
  Eigen::LLT<Eigen::MatrixXd> Wl(W), Gl(G0);
  Eigen::VectorXd x = m0 + Gl.matrixL() * random_matrix(g, s.nx(), 1);
  for (Eigen::Index k = 0; k < N; ++k) {
    const Eigen::VectorXd w = Wl.matrixL() * random_matrix(g, s.nw(), 1);
    y.push_back(s.C() * x + s.D() * u[static_cast<size_t>(k)] + s.F() * w);
    x = s.A() * x + s.B() * u[static_cast<size_t>(k)] + s.E() * w;
  }
  const Batch b = make_batch(s, m0, G0, W, u, N);
  KalmanFilter kf(s, m0, G0, W);
  for (Eigen::Index k = 0; k < N; ++k) {
    kf.step(y[static_cast<size_t>(k)], u[static_cast<size_t>(k)]);
    const auto [mk, Gk] = condition(b, y, k, k);
    const auto [mp, Gp] = condition(b, y, k + 1, k);
    const double sc = 1.0 + mk.cwiseAbs().maxCoeff() + Gk.cwiseAbs().maxCoeff();
    EXPECT_EIGEN_NEAR(kf.mean(), mk, 1e-8 * sc) << "k = " << k;
    EXPECT_EIGEN_NEAR(kf.covariance(), Gk, 1e-8 * sc) << "k = " << k;
    EXPECT_EIGEN_NEAR(kf.predicted_mean(), mp, 1e-8 * (1.0 + mp.cwiseAbs().maxCoeff() + Gp.cwiseAbs().maxCoeff()));
    EXPECT_EIGEN_NEAR(kf.predicted_covariance(), Gp, 1e-8 * (1.0 + Gp.cwiseAbs().maxCoeff()));
  }
}

}  // namespace

TEST(Kalman, MatchesBatchConditioningUncorrelatedNoise) {
  std::mt19937 g(11);
  // [Merhy2017]'s stacking: ω = [w; v], E = [E_w 0], F = [0 F_v]; with inputs and D ≠ 0.
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::Index n = 3, ny = 2, nu = 2;
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, 5), F = Eigen::MatrixXd::Zero(ny, 5);
    E.leftCols(3) = random_matrix(g, n, 3, 0.3);
    F.rightCols(2) = random_matrix(g, ny, 2, 0.5);
    LinearSystem s(random_matrix(g, n, n, 0.5), random_matrix(g, ny, n), E, F, random_matrix(g, n, nu),
                   random_matrix(g, ny, nu));
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(5, 5);
    W.topLeftCorner(3, 3) = random_spd(g, 3);
    W.bottomRightCorner(2, 2) = random_spd(g, 2);
    KalmanFilter probe(s, Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n), W);
    EXPECT_FALSE(probe.correlated_noise());
    EXPECT_EQ(probe.decorrelation_gain().cwiseAbs().maxCoeff(), 0.0);
    expect_matches_batch(s, W, g);
  }
}

TEST(Kalman, MatchesBatchConditioningCorrelatedNoise) {
  std::mt19937 g(12);
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::Index n = 3, ny = 2, nu = 1, nw = 4;
    // One ω drives state and output: E W Fᵀ ≠ 0.
    LinearSystem s(random_matrix(g, n, n, 0.5), random_matrix(g, ny, n), random_matrix(g, n, nw, 0.5),
                   random_matrix(g, ny, nw, 0.5), random_matrix(g, n, nu), random_matrix(g, ny, nu));
    const Eigen::MatrixXd W = random_spd(g, nw);
    KalmanFilter probe(s, Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n), W);
    ASSERT_TRUE(probe.correlated_noise());
    expect_matches_batch(s, W, g);
  }
}

TEST(Kalman, CorrelationMattersInTheBatchCheck) {
  // Sanity of the previous test: on the same kind of system, the recursion that ignores the
  // cross-covariance (the §2.3 equations with Q = E W Eᵀ, R = F W Fᵀ) is measurably wrong, so
  // the batch comparison does detect a missing decorrelation.
  std::mt19937 g(13);
  const Eigen::Index n = 3, ny = 2, nw = 4;
  LinearSystem s(random_matrix(g, n, n, 0.5), random_matrix(g, ny, n), random_matrix(g, n, nw, 0.5),
                 random_matrix(g, ny, nw, 0.5));
  const Eigen::MatrixXd W = random_spd(g, nw);
  const Eigen::MatrixXd Q = s.E() * W * s.E().transpose(), R = s.F() * W * s.F().transpose();
  KalmanFilter kf(s, Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n), W);
  Eigen::MatrixXd Gp = Eigen::MatrixXd::Identity(n, n);
  for (int k = 0; k < 5; ++k) {
    kf.step(Eigen::VectorXd::Zero(ny), Eigen::VectorXd());
    const Eigen::MatrixXd K = Gp * s.C().transpose() * (s.C() * Gp * s.C().transpose() + R).inverse();
    const Eigen::MatrixXd G = (Eigen::MatrixXd::Identity(n, n) - K * s.C()) * Gp;
    Gp = s.A() * G * s.A().transpose() + Q;
  }
  EXPECT_GT((kf.predicted_covariance() - Gp).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(Kalman, SteadyStateMatchesRiccatiFixedPoint) {
  struct Case {
    LinearSystem s;
    Eigen::MatrixXd W;
  };
  std::mt19937 g(21);
  std::vector<Case> cases{{me17(false), Eigen::MatrixXd::Identity(2, 2)},
                          {me17(true), Eigen::MatrixXd::Identity(2, 2)},
                          {bc14(), Eigen::MatrixXd::Identity(5, 5)}};
  {
    // Correlated noise on a stable random system.
    const Eigen::Index n = 3, ny = 2, nw = 4;
    Eigen::MatrixXd A = random_matrix(g, n, n);
    A *= 0.8 / A.eigenvalues().cwiseAbs().maxCoeff();
    cases.push_back({LinearSystem(A, random_matrix(g, ny, n), random_matrix(g, n, nw, 0.5),
                                  random_matrix(g, ny, nw, 0.5)),
                     random_spd(g, nw)});
  }
  for (const Case& c : cases) {
    const Eigen::MatrixXd P = riccati_fixed_point(c.s, c.W);
    const Eigen::MatrixXd R = c.s.F() * c.W * c.s.F().transpose();
    const Eigen::MatrixXd K = P * c.s.C().transpose() * (c.s.C() * P * c.s.C().transpose() + R).inverse();
    const Eigen::MatrixXd Gss = P - K * c.s.C() * P;
    KalmanFilter kf(c.s, Eigen::VectorXd::Zero(c.s.nx()), 4.0 * Eigen::MatrixXd::Identity(c.s.nx(), c.s.nx()), c.W);
    std::mt19937 gy(5);
    for (int k = 0; k < 400; ++k) kf.step(random_matrix(gy, c.s.ny(), 1), Eigen::VectorXd());
    const double sc = P.cwiseAbs().maxCoeff();
    EXPECT_EIGEN_NEAR(kf.predicted_covariance(), P, 1e-9 * sc);
    EXPECT_EIGEN_NEAR(kf.covariance(), Gss, 1e-9 * sc);
    EXPECT_EIGEN_NEAR(kf.gain(), K, 1e-8 * std::max(1.0, K.cwiseAbs().maxCoeff()));
  }
}

TEST(Kalman, MeanSquareErrorMatchesCovarianceTrace) {
  // EX-ME17a with Gaussian noise (G_w = G_v = 1) and a Gaussian initial state: the filter is
  // then the exact conditional mean, so E‖x_k − x̂_{k|k}‖² = tr G_{k|k} and the error covariance
  // is G_{k|k}. Checked at several k over 20000 independent runs (5σ tolerances).
  const LinearSystem s = me17(false);
  Eigen::VectorXd m0(2);
  m0 << 5, 5;
  const Eigen::MatrixXd G0 = Eigen::MatrixXd::Identity(2, 2);
  const int runs = 20000, horizon = 12;
  std::mt19937 g(31);
  std::normal_distribution<double> N(0.0, 1.0);
  std::vector<Eigen::MatrixXd> err_outer(horizon, Eigen::MatrixXd::Zero(2, 2));
  std::vector<Eigen::VectorXd> err_sum(horizon, Eigen::VectorXd::Zero(2));
  std::vector<Eigen::MatrixXd> Gk(horizon);
  KalmanFilter kf(s, m0, G0);
  for (int r = 0; r < runs; ++r) {
    kf.reset(m0, G0);
    Eigen::VectorXd x(2);
    x << m0(0) + N(g), m0(1) + N(g);
    for (int k = 0; k < horizon; ++k) {
      Eigen::VectorXd w(2);
      w << N(g), N(g);
      const Eigen::VectorXd y = s.C() * x + s.F() * w;
      kf.step(y, Eigen::VectorXd());
      const Eigen::VectorXd e = x - kf.mean();
      err_outer[static_cast<size_t>(k)] += e * e.transpose();
      err_sum[static_cast<size_t>(k)] += e;
      if (r == 0) Gk[static_cast<size_t>(k)] = kf.covariance();
      x = s.A() * x + s.E() * w;
    }
  }
  for (int k : {0, 1, 5, horizon - 1}) {
    const Eigen::MatrixXd& G = Gk[static_cast<size_t>(k)];
    const Eigen::MatrixXd emp = err_outer[static_cast<size_t>(k)] / runs;
    // ‖e‖² has variance 2 tr(G²) for Gaussian e; the mean of `runs` copies has std √(2 tr G²/runs).
    const double sd_trace = std::sqrt(2.0 * (G * G).trace() / runs);
    EXPECT_NEAR(emp.trace(), G.trace(), 5.0 * sd_trace) << "k = " << k;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        const double sd = std::sqrt((G(i, i) * G(j, j) + G(i, j) * G(i, j)) / runs);
        EXPECT_NEAR(emp(i, j), G(i, j), 5.0 * sd) << "k = " << k << " entry " << i << j;
      }
    const Eigen::VectorXd mean_err = err_sum[static_cast<size_t>(k)] / runs;
    for (int i = 0; i < 2; ++i) EXPECT_NEAR(mean_err(i), 0.0, 5.0 * std::sqrt(G(i, i) / runs));
  }
  // The test can tell a good filter from a poor one: the error after the first correction is
  // well below the prior's (tr G_{0|−1} = 2).
  EXPECT_LT(Gk[0].trace(), 1.5);
}

TEST(Kalman, JosephFormKeepsCovarianceSymmetricPositiveSemidefinite) {
  // Ill-conditioned: a very precise output (F W Fᵀ ~ 1e-12) on a vague prior (G ~ 1e6).
  std::mt19937 g(41);
  const Eigen::Index n = 3, ny = 1, nw = 4;
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, nw), F = Eigen::MatrixXd::Zero(ny, nw);
  E.leftCols(3) = 1e-3 * Eigen::MatrixXd::Identity(3, 3);
  F(0, 3) = 1e-6;
  Eigen::MatrixXd A(3, 3);
  A << 0.9, 1, 0, 0, 0.9, 1, 0, 0, 0.9;
  Eigen::MatrixXd C(1, 3);
  C << 1, 0, 0;
  LinearSystem s(A, C, E, F);
  KalmanFilter kf(s, Eigen::VectorXd::Zero(n), 1e6 * Eigen::MatrixXd::Identity(n, n));
  for (int k = 0; k < 300; ++k) {
    kf.step(random_matrix(g, ny, 1), Eigen::VectorXd());
    const Eigen::MatrixXd& G = kf.covariance();
    ASSERT_TRUE((G - G.transpose()).cwiseAbs().maxCoeff() == 0.0) << "k = " << k;
    ASSERT_TRUE((kf.predicted_covariance() - kf.predicted_covariance().transpose()).cwiseAbs().maxCoeff() == 0.0);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(G);
    ASSERT_GE(eig.eigenvalues()(0), -1e-14 * G.cwiseAbs().maxCoeff()) << "k = " << k;
  }
}

TEST(Kalman, BoxIsMeanPlusMinusSigmas) {
  const LinearSystem s = me17(false);
  Eigen::VectorXd m0(2);
  m0 << 5, 5;
  KalmanFilter kf(s, m0, Eigen::MatrixXd::Identity(2, 2));
  Eigen::VectorXd y(1);
  y << -4.0;
  kf.step(y, Eigen::VectorXd());
  const setbound::BoundingBox b = kf.box(2.0);
  for (int i = 0; i < 2; ++i) {
    EXPECT_DOUBLE_EQ(b.hi(i) - kf.mean()(i), 2.0 * std::sqrt(kf.covariance()(i, i)));
    EXPECT_DOUBLE_EQ(kf.mean()(i) - b.lo(i), 2.0 * std::sqrt(kf.covariance()(i, i)));
  }
  EXPECT_EQ(kf.steps(), 1);
}

TEST(Kalman, BadInput) {
  using namespace setbound;
  const LinearSystem s = me17(false);
  const Eigen::VectorXd m0 = Eigen::VectorXd::Ones(2);
  const Eigen::MatrixXd G0 = Eigen::MatrixXd::Identity(2, 2);
  expect_error_naming<DimensionError>([&] { KalmanFilter(s, Eigen::VectorXd::Ones(3), G0); }, "mean0");
  Eigen::VectorXd mnan = m0;
  mnan(1) = std::nan("");
  expect_error_naming<NotFiniteError>([&] { KalmanFilter(s, mnan, G0); }, "mean0");
  expect_error_naming<DimensionError>([&] { KalmanFilter(s, m0, Eigen::MatrixXd::Identity(3, 3)); }, "cov0");
  Eigen::MatrixXd Gind(2, 2);
  Gind << 1, 2, 2, 1;
  expect_error_naming<NotPositiveDefiniteError>([&] { KalmanFilter(s, m0, Gind); }, "cov0");
  Eigen::MatrixXd Gasym(2, 2);
  Gasym << 1, 0.5, 0, 1;
  expect_error_naming<NotSymmetricError>([&] { KalmanFilter(s, m0, Gasym); }, "cov0");
  expect_error_naming<DimensionError>([&] { KalmanFilter(s, m0, G0, Eigen::MatrixXd::Identity(3, 3)); }, "omega_cov");
  expect_error_naming<NotPositiveDefiniteError>([&] { KalmanFilter(s, m0, G0, -Eigen::MatrixXd::Identity(2, 2)); },
                                                "omega_cov");
  Eigen::MatrixXd Wnan = Eigen::MatrixXd::Identity(2, 2);
  Wnan(0, 0) = std::numeric_limits<double>::infinity();
  expect_error_naming<NotFiniteError>([&] { KalmanFilter(s, m0, G0, Wnan); }, "omega_cov");
  // Singular output noise: the output-noise component has zero variance, or F = 0.
  Eigen::MatrixXd Wsing = Eigen::MatrixXd::Identity(2, 2);
  Wsing(1, 1) = 0.0;
  expect_error_naming<NotPositiveDefiniteError>([&] { KalmanFilter(s, m0, G0, Wsing); }, "F");
  {
    Eigen::MatrixXd C(2, 2), F(2, 2), E = Eigen::MatrixXd::Identity(2, 2);
    C << 1, 0, 0, 1;
    F << 1, 0, 1, 0;  // two outputs, one noise: F W Fᵀ has rank 1
    const LinearSystem s2(s.A(), C, E, F);
    expect_error_naming<NotPositiveDefiniteError>([&] { KalmanFilter(s2, m0, G0); }, "F");
  }
  // Steps: bad y / u leave the filter unchanged.
  KalmanFilter kf(s, m0, G0);
  Eigen::VectorXd y(1);
  y << 0.3;
  kf.step(y, Eigen::VectorXd());
  const Eigen::VectorXd x_before = kf.mean(), xp_before = kf.predicted_mean();
  const Eigen::MatrixXd G_before = kf.covariance();
  expect_error_naming<DimensionError>([&] { kf.step(Eigen::VectorXd::Ones(2), Eigen::VectorXd()); }, "y");
  Eigen::VectorXd ynan(1);  // ±inf: NaN is a missing output (test_measurement_ellipsoidal.cpp)
  ynan << -std::numeric_limits<double>::infinity();
  expect_error_naming<NotFiniteError>([&] { kf.step(ynan, Eigen::VectorXd()); }, "y");
  expect_error_naming<DimensionError>([&] { kf.step(y, Eigen::VectorXd::Ones(1)); }, "u");
  expect_error_naming<InvalidArgumentError>([&] { (void)kf.box(0.0); }, "nsigma");
  expect_error_naming<DimensionError>([&] { kf.reset(Eigen::VectorXd::Ones(1), G0); }, "mean0");
  EXPECT_EQ(kf.mean(), x_before);
  EXPECT_EQ(kf.predicted_mean(), xp_before);
  EXPECT_EQ(kf.covariance(), G_before);
  EXPECT_EQ(kf.steps(), 1);
}

TEST(Kalman, StepTiming) {
  // Median over 1000 steps on the §2.5 (n_x = 2, n_y = 1) and §1.4 (n_x = 3, n_y = 2, n_ω = 5)
  // sizes; printed for the report, not asserted (hardware dependent).
  for (const LinearSystem& s : {me17(false), bc14()}) {
    KalmanFilter kf(s, Eigen::VectorXd::Zero(s.nx()), Eigen::MatrixXd::Identity(s.nx(), s.nx()));
    std::mt19937 g(3);
    std::vector<double> t;
    const Eigen::VectorXd u;
    for (int k = 0; k < 1000; ++k) {
      const Eigen::VectorXd y = random_matrix(g, s.ny(), 1);
      const auto t0 = std::chrono::steady_clock::now();
      kf.step(y, u);
      t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::nth_element(t.begin(), t.begin() + 500, t.end());
    std::cout << "[ timing ] Kalman step n_x = " << s.nx() << ", n_y = " << s.ny() << ": median "
              << t[500] * 1e6 << " us\n";
    EXPECT_TRUE(kf.mean().allFinite());
  }
}
