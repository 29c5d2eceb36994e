// Ellipsoidal estimation for descriptor systems ([Merhy2019], papers.md §4): T, N, the
// equivalent system, the rank conditions, the design with independent w_k, w_{k+1} and the
// estimator's guarantee.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "setbound/estimators/ellipsoidal/descriptor.hpp"
#include "ell_test_systems.hpp"
#include "test_helpers.hpp"

using namespace setbound;
using setbound::testing::me19;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kPi = 3.14159265358979323846;

const EllDesign& me19_design() {
  static const EllDesign d = design_descriptor_offline(me19());
  return d;
}

// A descriptor system in semi-explicit form after a change of coordinates, so that it can be
// simulated exactly: with ξ = N x, M E_s N = E, …, E_s = diag(I_r, 0),
//   ξ1⁺ = A11 ξ1 + A12 ξ2 + B1 u + D1 w,    0 = A21 ξ1 + A22 ξ2 + B2 u + D2 w   (A22 invertible).
struct SemiExplicit {
  MatrixXd A11, A12, A21, A22, B1, B2, D1, D2, Ninv;
  Eigen::Index r = 0;
  VectorXd algebraic(const VectorXd& xi1, const VectorXd& u, const VectorXd& w) const {
    VectorXd rhs = A21 * xi1 + D2 * w;
    if (B2.cols() > 0) rhs += B2 * u;
    return -A22.lu().solve(rhs);
  }
  VectorXd state(const VectorXd& xi1, const VectorXd& xi2) const {
    VectorXd xi(xi1.size() + xi2.size());
    xi << xi1, xi2;
    return Ninv * xi;
  }
  VectorXd next(const VectorXd& xi1, const VectorXd& xi2, const VectorXd& u, const VectorXd& w) const {
    VectorXd v = A11 * xi1 + A12 * xi2 + D1 * w;
    if (B1.cols() > 0) v += B1 * u;
    return v;
  }
};

SemiExplicit me19_semi() {
  const DescriptorSystem s = me19();
  SemiExplicit se;
  se.r = 2;
  se.A11 = s.A().topLeftCorner(2, 2);
  se.A12 = s.A().topRightCorner(2, 1);
  se.A21 = s.A().bottomLeftCorner(1, 2);
  se.A22 = s.A().bottomRightCorner(1, 1);
  se.B1 = s.B().topRows(2);
  se.B2 = s.B().bottomRows(1);
  se.D1 = s.D().topRows(2);
  se.D2 = s.D().bottomRows(1);
  se.Ninv = MatrixXd::Identity(3, 3);
  return se;
}

VectorXd draw(std::mt19937& gen, Eigen::Index n, bool vertex) {
  std::uniform_real_distribution<double> U(-1, 1);
  VectorXd w(n);
  for (Eigen::Index i = 0; i < n; ++i) w(i) = vertex ? (U(gen) < 0 ? -1.0 : 1.0) : U(gen);
  return w;
}

// Runs the estimator on a simulated trajectory and checks x_k ∈ step(y_k, u_k) at every k.
// `input(k)` gives u_k; x_0 is drawn by `first` (ξ1_0 and w_0 → x_0). Returns steps checked.
int run_contains(DescriptorEstimator& est, const DescriptorSystem& sys, const SemiExplicit& se, VectorXd xi1,
                 int steps, bool vertex, unsigned seed, const std::function<VectorXd(int)>& input,
                 VectorXd w0 = VectorXd()) {
  std::mt19937 gen(seed);
  int checked = 0;
  for (int k = 0; k < steps; ++k) {
    const VectorXd u = input(k);
    const VectorXd w = (k == 0 && w0.size() > 0) ? w0 : draw(gen, sys.nw(), vertex);
    const VectorXd xi2 = se.algebraic(xi1, u, w);
    const VectorXd x = se.state(xi1, xi2);
    // The simulated state satisfies the descriptor equation of the previous step by construction.
    const VectorXd y = sys.C() * x + sys.F() * w;
    const Ellipsoid set = est.step(y, u);
    const bool in = set.contains(x, 1e-9);
    EXPECT_TRUE(in) << "k " << k << " seed " << seed;
    if (!in) return checked;
    ++checked;
    xi1 = se.next(xi1, xi2, u, w);
  }
  return checked;
}

VectorXd me19_input(int k) {
  const double t = k * 5.0 * kPi / 50.0;
  VectorXd u(2);
  u << 0.5 * std::sin(t) + 1.0, -2.0 * std::cos(t);
  return u;
}

// Smallest relative eigenvalue of the §4.1 LMI over every (w_a, w_b) ∈ {±1}^{n_w} × {±1}^{n_w}
// (all 4^{n_w}, independent), written directly from T, N, A, C, D, F.
double worst_descriptor_lmi(const DescriptorSystem& s, const EllDesign& d) {
  const Eigen::Index n = s.nx(), nw = s.nw();
  const MatrixXd& P = d.P;
  const MatrixXd Y = P * d.L;
  const MatrixXd PA = P * s.T() * s.A() - Y * s.C();
  const MatrixXd G = P * s.T() * s.D() - Y * s.F(), H = P * s.N() * s.F();
  double worst = std::numeric_limits<double>::infinity();
  for (unsigned long a = 0; a < (1ul << nw); ++a)
    for (unsigned long b = 0; b < (1ul << nw); ++b) {
      VectorXd wa(nw), wb(nw);
      for (Eigen::Index i = 0; i < nw; ++i) {
        wa(i) = ((a >> i) & 1ul) ? -1.0 : 1.0;
        wb(i) = ((b >> i) & 1ul) ? -1.0 : 1.0;
      }
      const VectorXd g = G * wa - H * wb;
      MatrixXd M = MatrixXd::Zero(2 * n + 1, 2 * n + 1);
      M.topLeftCorner(n, n) = d.beta * P;
      M(n, n) = d.sigma;
      M.block(n + 1, 0, n, n) = PA;
      M.block(0, n + 1, n, n) = PA.transpose();
      M.block(n + 1, n, n, 1) = g;
      M.block(n, n + 1, 1, n) = g.transpose();
      M.bottomRightCorner(n, n) = P;
      worst = std::min(worst, Eigen::SelfAdjointEigenSolver<MatrixXd>(M, Eigen::EigenvaluesOnly).eigenvalues()(0) / M.norm());
    }
  return worst;
}

// Seeded random descriptor systems (n_x = 3 or 4, one or two algebraic equations), through a
// random well-conditioned change of coordinates; resampled until the rank conditions hold and
// (C, T A) is detectable.
struct RandomDescriptor {
  DescriptorSystem sys;
  SemiExplicit se;
  EllDesign design;
};

RandomDescriptor random_descriptor(std::mt19937& gen, bool unstable, Eigen::Index n, Eigen::Index r, Eigen::Index ny,
                                   Eigen::Index nu) {
  std::normal_distribution<double> N;
  std::uniform_real_distribution<double> U(0, 1);
  auto rnd = [&](Eigen::Index a, Eigen::Index b, double s) {
    MatrixXd M(a, b);
    for (Eigen::Index i = 0; i < M.size(); ++i) M.data()[i] = s * N(gen);
    return M;
  };
  const Eigen::Index q = n - r, nw = r + ny + 1;
  for (int attempt = 0;; ++attempt) {
    if (attempt == 200) throw std::runtime_error("random_descriptor: no admissible system in 200 draws");
    SemiExplicit se;
    se.r = r;
    se.A11 = rnd(r, r, 1.0);
    se.A12 = rnd(r, q, 0.3);
    se.A21 = rnd(q, r, 1.0);
    se.A22 = MatrixXd::Identity(q, q) + rnd(q, q, 0.2);
    // Scale the reduced dynamics A11 − A12 A22⁻¹ A21 to the wanted spectral radius.
    const MatrixXd red = se.A11 - se.A12 * se.A22.lu().solve(se.A21);
    const double rho = Eigen::EigenSolver<MatrixXd>(red).eigenvalues().cwiseAbs().maxCoeff();
    const double target = unstable ? 1.05 + 0.25 * U(gen) : 0.3 + 0.6 * U(gen);
    se.A11 *= target / rho;
    se.A12 *= target / rho;
    se.B1 = rnd(r, nu, 1.0);
    se.B2 = rnd(q, nu, 1.0);
    se.D1 = MatrixXd::Zero(r, nw);
    se.D1.leftCols(r) = rnd(r, r, 0.1);
    se.D2 = MatrixXd::Zero(q, nw);
    se.D2.col(nw - 1) = rnd(q, 1, 0.1);  // a disturbance in the algebraic equations
    MatrixXd F = MatrixXd::Zero(ny, nw);
    for (Eigen::Index i = 0; i < ny; ++i) F(i, r + i) = 0.05 + 0.1 * U(gen);
    const MatrixXd Mc = MatrixXd::Identity(n, n) + rnd(n, n, 0.3), Nc = MatrixXd::Identity(n, n) + rnd(n, n, 0.3);
    MatrixXd Es = MatrixXd::Zero(n, n), As(n, n), Bs(n, nu), Ds(n, nw);
    Es.topLeftCorner(r, r).setIdentity();
    As << se.A11, se.A12, se.A21, se.A22;
    Bs << se.B1, se.B2;
    Ds << se.D1, se.D2;
    se.Ninv = Nc.inverse();
    const MatrixXd C = rnd(ny, n, 1.0);
    try {
      DescriptorSystem sys(Mc * Es * Nc, Mc * As * Nc, C, Mc * Ds, F, Mc * Bs);
      if (!check_detectability(sys.equivalent().A(), C).detectable) continue;
      EllDesignOptions o;
      o.search.grid_points = 6;
      o.search.max_evaluations = 14;
      EllDesign d = design_descriptor_offline(sys, o);
      return {std::move(sys), std::move(se), std::move(d)};
    } catch (const NotDetectableError&) {
      continue;
    } catch (const InfeasibleError&) {
      continue;
    }
  }
}

}  // namespace

TEST(DescriptorSystem, Me19TAndNArePinvOfEC) {
  const DescriptorSystem s = me19();
  MatrixXd T(3, 3), N(3, 2);
  T << 2.0 / 3, 1.0 / 3, 0, 1.0 / 3, 2.0 / 3, 0, -2.0 / 3, -1.0 / 3, 0;
  N << 0, 1.0 / 3, 0, -1.0 / 3, 1, -1.0 / 3;
  EXPECT_EIGEN_NEAR(s.T(), T, 1e-12);
  EXPECT_EIGEN_NEAR(s.N(), N, 1e-12);
  EXPECT_EIGEN_NEAR(MatrixXd(s.T() * s.E() + s.N() * s.C()), MatrixXd::Identity(3, 3), 1e-14);
  // [E; C] has a zero row (the third row of E): its column of pinv is exactly zero.
  EXPECT_TRUE((s.T().col(2).array() == 0.0).all());
  EXPECT_EQ(s.nx(), 3);
  EXPECT_EQ(s.ny(), 2);
  EXPECT_EQ(s.nu(), 2);
  EXPECT_EQ(s.nw(), 5);
}

TEST(DescriptorSystem, EquivalentSystemStacksWkAndWk1) {
  const DescriptorSystem s = me19();
  const LinearSystem eq = s.equivalent();
  EXPECT_EQ(eq.nw(), 10);
  EXPECT_EIGEN_NEAR(eq.A(), MatrixXd(s.T() * s.A()), 0.0);
  EXPECT_EIGEN_NEAR(eq.B(), MatrixXd(s.T() * s.B()), 0.0);
  EXPECT_EIGEN_NEAR(eq.E().leftCols(5), MatrixXd(s.T() * s.D()), 0.0);
  EXPECT_EIGEN_NEAR(eq.E().rightCols(5), MatrixXd(-(s.N() * s.F())), 0.0);
  EXPECT_EIGEN_NEAR(eq.F().leftCols(5), s.F(), 0.0);
  EXPECT_EIGEN_NEAR(eq.F().rightCols(5), MatrixXd::Zero(2, 5), 0.0);
  EXPECT_EIGEN_NEAR(eq.D(), MatrixXd::Zero(2, 2), 0.0);
}

TEST(DescriptorDesign, Me19KeepsWkAndWk1Independent) {
  const DescriptorSystem s = me19();
  const EllDesign& d = me19_design();
  // Active columns of [T D, −N F; F, 0]: w_k components 1, 2 (T D), 4, 5 (F); w_k's third
  // component only enters the algebraic row, which T discards (T's third column is zero);
  // w_{k+1} components 4, 5 (N F). 6 columns: 2^6 vertices, 32 after the ± symmetry.
  EXPECT_EQ(d.vertex_blocks, 32);
  EXPECT_GT(d.beta, 0.0);
  EXPECT_LT(d.beta, 1.0);
  // Independent re-check at all 4^5 = 1024 vertices (w_a, w_b).
  EXPECT_GE(worst_descriptor_lmi(s, d), -1e-13);
  // Imposing only coupled vertices (w_b = w_a) gives a smaller steady-state volume, which is no
  // valid certificate: its LMI fails at some independent vertex (papers §4.1 warning, §4.2).
  const LinearSystem eq = s.equivalent();
  const LinearSystem coupled(eq.A(), eq.C(), eq.E().leftCols(5) + eq.E().rightCols(5), s.F(), eq.B());
  EllDesignOptions o;
  o.search.grid_points = 6;
  o.search.max_evaluations = 14;
  const EllDesign dc = design_ellipsoidal_offline(coupled, o);
  EXPECT_LT(dc.volume_inf, d.volume_inf * (1 - 1e-3));
  EXPECT_LT(worst_descriptor_lmi(s, dc), -1e-6);
}

TEST(DescriptorEstimator, Me19ContainsTheTruth) {
  const DescriptorSystem s = me19();
  const SemiExplicit se = me19_semi();
  const Ellipsoid x0(1e-9 * MatrixXd::Identity(3, 3), VectorXd::Zero(3), 1e-9);  // the unit ball
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> U(-0.4, 0.4);
  int steps = 0;
  for (int run = 0; run < 10; ++run) {
    const bool vertex = run % 2 == 1;
    // x_0 in the unit ball: ξ1_0 and w_0 drawn until the algebraic component keeps it inside.
    VectorXd xi1(2), w0;
    for (;;) {
      xi1 << U(gen), U(gen);
      w0 = draw(gen, 5, vertex);
      if (se.state(xi1, se.algebraic(xi1, me19_input(0), w0)).norm() <= 1.0) break;
    }
    DescriptorEstimator est(me19_design(), s, x0);
    steps += run_contains(est, s, se, xi1, 50, vertex, 40u + static_cast<unsigned>(run), me19_input, w0);
    EXPECT_EQ(est.steps_taken(), 49);
  }
  EXPECT_EQ(steps, 500);
}

TEST(DescriptorEstimator, RandomSystemsContainTheTruth) {
  std::mt19937 gen(99);
  int steps = 0;
  for (int i = 0; i < 5; ++i) {
    // (n_x, algebraic equations, n_y, n_u); the equivalent system has r + 1 + 2 n_y active
    // disturbance columns (w_k: state, algebraic and output parts; w_{k+1}: output part).
    // Infinite observability needs n_y ≥ the number of algebraic equations.
    const int sizes[5][4] = {{3, 1, 1, 0}, {3, 1, 1, 1}, {3, 2, 2, 0}, {4, 1, 1, 1}, {3, 1, 2, 0}};
    const Eigen::Index n = sizes[i][0], r = n - sizes[i][1], ny = sizes[i][2], nu = sizes[i][3];
    RandomDescriptor rd = random_descriptor(gen, i % 2 == 0, n, r, ny, nu);
    EXPECT_GE(worst_descriptor_lmi(rd.sys, rd.design), -1e-13) << "system " << i;
    std::mt19937 g2(500 + static_cast<unsigned>(i));
    for (bool vertex : {false, true}) {
      const VectorXd xi1 = draw(g2, r, false);
      const VectorXd w0 = draw(g2, rd.sys.nw(), vertex);
      auto input = [&](int k) { return nu > 0 ? VectorXd::Constant(nu, std::sin(0.3 * k)) : VectorXd(0); };
      const VectorXd x_0 = rd.se.state(xi1, rd.se.algebraic(xi1, input(0), w0));
      const Ellipsoid x0(MatrixXd::Identity(n, n), VectorXd::Zero(n), x_0.squaredNorm() + 1.0);
      DescriptorEstimator est(rd.design, rd.sys, x0);
      steps += run_contains(est, rd.sys, rd.se, xi1, 150, vertex, 700u + static_cast<unsigned>(2 * i + vertex), input, w0);
    }
  }
  EXPECT_EQ(steps, 5 * 2 * 150);
}

TEST(DescriptorEstimator, FollowsTheRecursion) {
  const DescriptorSystem s = me19();
  const EllDesign& d = me19_design();
  const Ellipsoid x0(MatrixXd::Identity(3, 3), VectorXd::Zero(3), 1.0);
  DescriptorEstimator est(d, s, x0);
  EXPECT_EQ(est.steps_taken(), 0);
  const VectorXd y0 = VectorXd::Constant(2, 0.3), u0 = me19_input(0);
  const Ellipsoid first = est.step(y0, u0);
  EXPECT_EQ(est.steps_taken(), 0);  // the first call returns x_0's set
  EXPECT_TRUE(first.shape().isApprox(d.P));
  EXPECT_NEAR(first.level(), x0.level_for_shape(d.P), 1e-12 * first.level());
  const VectorXd y1(VectorXd::Constant(2, -0.2)), u1 = me19_input(1);
  const Ellipsoid second = est.step(y1, u1);
  EXPECT_EQ(est.steps_taken(), 1);
  const VectorXd c = s.T() * s.A() * first.center() + s.T() * s.B() * u0 + s.N() * y1 +
                     d.L * (y0 - s.C() * first.center());
  EXPECT_EIGEN_NEAR(second.center(), c, 1e-12);
  const double rho = d.beta * first.level() + d.sigma;
  EXPECT_GE(second.level(), rho);
  EXPECT_LE(second.level(), rho * (1 + 1e-9));  // the rounding enlargements are tiny
  EXPECT_EQ(est.current().level(), second.level());
}

TEST(DescriptorSystem, RankConditionsAreChecked) {
  using setbound::testing::expect_error_naming;
  MatrixXd E = MatrixXd::Zero(3, 3), A(3, 3), D = 0.1 * MatrixXd::Identity(3, 3), F = MatrixXd::Zero(2, 3);
  E(0, 0) = E(1, 1) = 1;
  A << 0.5, 0, 0, 0, 0.9, 0, 0, 0, 1;
  // Infinite observability: [E; C] misses the third direction.
  {
    MatrixXd C(2, 3);
    C << 1, 0, 0, 0, 1, 0;
    try {
      DescriptorSystem(E, A, C, D, F);
      ADD_FAILURE() << "expected NotDetectableError";
    } catch (const NotDetectableError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("E, C:", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find("infinite observability"), std::string::npos) << e.what();
    }
  }
  // Finite observability: the mode 0.9 (x2) is not seen by C.
  {
    MatrixXd C(2, 3);
    C << 1, 0, 0, 0, 0, 1;
    try {
      DescriptorSystem(E, A, C, D, F);
      ADD_FAILURE() << "expected NotDetectableError";
    } catch (const NotDetectableError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("E, A, C:", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find("finite observability"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("0.9"), std::string::npos) << e.what();
    }
  }
  // Both hold, yet (C, T A) is not detectable: the estimator structure of §4 (T from pinv)
  // cannot use the algebraic equation, and the design says so.
  {
    MatrixXd E2(2, 2), A2(2, 2), C2(1, 2), D2 = 0.1 * MatrixXd::Identity(2, 2), F2(1, 2);
    E2 << 1, 0, 0, 0;
    A2 << 2, 0.3, 1, 0.5;
    C2 << 0, 1;
    F2 << 0, 0.1;
    const DescriptorSystem s(E2, A2, C2, D2, F2);
    try {
      design_descriptor_offline(s);
      ADD_FAILURE() << "expected NotDetectableError";
    } catch (const NotDetectableError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("(C, TA):", 0), 0u) << e.what();
    }
  }
}

TEST(DescriptorSystem, RejectsBadShapes) {
  using setbound::testing::expect_error_naming;
  const DescriptorSystem s = me19();
  expect_error_naming<DimensionError>([&] { DescriptorSystem(MatrixXd::Identity(2, 2), s.A(), s.C(), s.D(), s.F()); }, "E");
  expect_error_naming<DimensionError>([&] { DescriptorSystem(s.E(), s.A(), MatrixXd::Ones(2, 2), s.D(), s.F()); }, "C");
  expect_error_naming<DimensionError>([&] { DescriptorSystem(s.E(), s.A(), s.C(), MatrixXd::Ones(2, 5), s.F()); }, "D");
  expect_error_naming<DimensionError>([&] { DescriptorSystem(s.E(), s.A(), s.C(), s.D(), MatrixXd::Ones(2, 4)); }, "F");
  expect_error_naming<DimensionError>([&] { DescriptorSystem(s.E(), s.A(), s.C(), s.D(), s.F(), MatrixXd::Ones(2, 2)); }, "B");
  MatrixXd An = s.A();
  An(0, 1) = std::numeric_limits<double>::quiet_NaN();
  expect_error_naming<NotFiniteError>([&] { DescriptorSystem(s.E(), An, s.C(), s.D(), s.F()); }, "A");
}

TEST(DescriptorEstimator, RejectsBadInputAndKeepsItsState) {
  using setbound::testing::expect_error_naming;
  const DescriptorSystem s = me19();
  const EllDesign& d = me19_design();
  const Ellipsoid x0(MatrixXd::Identity(3, 3), VectorXd::Zero(3), 1.0);
  expect_error_naming<DimensionError>(
      [&] { DescriptorEstimator(d, s, Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 1.0)); }, "x0");
  EllDesign broken = d;
  broken.sigma = 0.5 * d.sigma;
  expect_error_naming<InvalidArgumentError>([&] { DescriptorEstimator(broken, s, x0); }, "design");
  EllDesign bad_beta = d;
  bad_beta.beta = 0.0;
  expect_error_naming<InvalidArgumentError>([&] { DescriptorEstimator(bad_beta, s, x0); }, "design.beta");
  DescriptorEstimator est(d, s, x0);
  est.step(VectorXd::Zero(2), me19_input(0));
  est.step(VectorXd::Zero(2), me19_input(1));
  const Ellipsoid before = est.current();
  expect_error_naming<DimensionError>([&] { est.step(VectorXd::Zero(3), me19_input(2)); }, "y");
  expect_error_naming<DimensionError>([&] { est.step(VectorXd::Zero(2), VectorXd::Zero(1)); }, "u");
  VectorXd bad = VectorXd::Zero(2);
  bad(1) = std::numeric_limits<double>::infinity();
  expect_error_naming<NotFiniteError>([&] { est.step(bad, me19_input(2)); }, "y");
  EXPECT_EQ(est.steps_taken(), 1);
  EXPECT_EIGEN_NEAR(est.current().center(), before.center(), 0.0);
  EXPECT_EQ(est.current().level(), before.level());
}
