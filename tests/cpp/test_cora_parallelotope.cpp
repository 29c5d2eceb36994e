// CORA's ROPO (estimators/zonotopic/parallelotope.hpp) and the Rauch–Tung–Striebel smoother
// (estimators/point/rts_smoother.hpp): the truth stays in every set (random and vertex
// disturbances, 20 seeded random systems, both reductions), ROPO contains the exact hull, the
// Vicino–Zappa step against hand-computed 2-D cases, degenerate cases, inconsistent readings,
// saved states bit-for-bit, bad input named in C++ and through the C ABI; RTS against the Kalman
// filter, a hand-computed scalar smoother and the covariance ordering.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <random>

#include "setbound/estimators/polytopic/exact_hull.hpp"
#include "setbound/estimators/point/kalman.hpp"
#include "setbound/estimators/point/rts_smoother.hpp"
#include "setbound/estimators/zonotopic/parallelotope.hpp"
#include "c_api_common.hpp"
#include "test_helpers.hpp"

using namespace setbound;
using namespace setbound::testing;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

LinearSystem random_system(int trial, std::mt19937& gen) {
  std::normal_distribution<double> nrm;
  const int n = 2 + trial % 3, ny = 1 + trial % 2, nu = 1, nw = n + ny;
  MatrixXd A(n, n), C(ny, n), B(n, nu), D = MatrixXd::Zero(ny, nu), E = MatrixXd::Zero(n, nw),
      F = MatrixXd::Zero(ny, nw);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = nrm(gen) / std::sqrt(double(n));
  A *= (trial % 2 ? 1.05 : 0.9) / Eigen::EigenSolver<MatrixXd>(A).eigenvalues().cwiseAbs().maxCoeff();
  for (int i = 0; i < ny; ++i)
    for (int j = 0; j < n; ++j) C(i, j) = nrm(gen);
  for (int i = 0; i < n; ++i) B(i, 0) = nrm(gen), E(i, i) = 0.05;
  for (int i = 0; i < ny; ++i) F(i, n + i) = 0.1;
  if (trial % 4 == 3) {
    D(0, 0) = 0.3;   // an input feed-through
    F(0, 0) = 0.02;  // ω_0 drives the state and the first output together
  }
  return LinearSystem(A, C, E, F, B, D);
}

struct Record {
  MatrixXd X, Y, U;  // rows: x_k, y_k, u_k
};

Record simulate(const LinearSystem& sys, std::mt19937& gen, bool vertex, int N, const VectorXd& x0) {
  Record r{MatrixXd(N, sys.nx()), MatrixXd(N, sys.ny()), MatrixXd(N, sys.nu())};
  VectorXd x = x0;
  for (int k = 0; k < N; ++k) {
    const VectorXd w = draw_disturbance(gen, sys.nw(), vertex);
    const VectorXd u = VectorXd::Constant(sys.nu(), std::sin(0.3 * k));
    r.X.row(k) = x.transpose();
    r.U.row(k) = u.transpose();
    r.Y.row(k) = (sys.C() * x + sys.D() * u + sys.F() * w).transpose();
    x = sys.A() * x + sys.B() * u + sys.E() * w;
  }
  return r;
}

ParallelotopeOptions opts(ZonotopeReduction red, Convention conv = Convention::Setbound,
                          OnInconsistency pol = OnInconsistency::Flag) {
  ParallelotopeOptions o;
  o.reduction = red;
  o.convention = conv;
  o.on_inconsistency = pol;
  return o;
}

ParallelotopeEstimator::Set unit_box2() {
  return {VectorXd::Zero(2), VectorXd::Zero(2), MatrixXd::Identity(2, 2)};
}

}  // namespace

TEST(Ropo, ContainsTheTruthOnRandomSystems) {
  std::mt19937 gen(21);
  int steps = 0, violations = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const LinearSystem sys = random_system(trial, gen);
    const Eigen::Index n = sys.nx();
    const Zonotope X0(VectorXd::Zero(n), MatrixXd::Identity(n, n));
    for (ZonotopeReduction red : {ZonotopeReduction::Girard, ZonotopeReduction::Pca})
      for (bool vertex : {false, true}) {
        const Record r = simulate(sys, gen, vertex, 60, 0.9 * draw_disturbance(gen, n, vertex));
        ParallelotopeEstimator est(sys, X0, opts(red));
        const auto t = est.run(r.Y, r.U);
        for (int k = 0; k < 60; ++k) {
          ++steps;
          const VectorXd x = r.X.row(k).transpose();
          if (!t.sets[size_t(k)].contains(x, 1e-9) || (x.array() < t.lower.row(k).transpose().array()).any() ||
              (x.array() > t.upper.row(k).transpose().array()).any())
            ++violations;
          EXPECT_FALSE(t.checks[size_t(k)].flagged()) << "trial " << trial << " step " << k;
        }
        EXPECT_EQ(est.current_generators().cols(), n);  // a parallelotope after every correction
      }
  }
  EXPECT_EQ(violations, 0);
  EXPECT_EQ(steps, 24 * 2 * 2 * 60);
}

TEST(Ropo, ContainsTheExactHull) {
  std::mt19937 gen(5);
  for (int trial = 0; trial < 6; ++trial) {
    const LinearSystem sys = random_system(trial, gen);
    const Eigen::Index n = sys.nx();
    const Zonotope X0(VectorXd::Zero(n), MatrixXd::Identity(n, n));
    const Record r = simulate(sys, gen, trial % 2 == 1, 10, 0.5 * draw_disturbance(gen, n, false));
    const ExactHull h = exact_hull(sys, X0, r.Y, r.U);
    for (ZonotopeReduction red : {ZonotopeReduction::Girard, ZonotopeReduction::Pca}) {
      ParallelotopeEstimator est(sys, X0, opts(red));
      const auto t = est.run(r.Y, r.U);
      const MatrixXd tol = 1e-8 * (MatrixXd::Ones(10, n) + h.upper.cwiseAbs() + h.lower.cwiseAbs());
      EXPECT_TRUE((t.lower.array() <= h.lower.array() + tol.array()).all()) << "trial " << trial;
      EXPECT_TRUE((t.upper.array() >= h.upper.array() - tol.array()).all()) << "trial " << trial;
      // ROPO is not exact: it is wider somewhere (sanity of the comparison itself).
      EXPECT_GT((t.upper - t.lower).sum(), (h.upper - h.lower).sum());
    }
  }
}

TEST(Ropo, VicinoZappaShrinksToTheHandComputedBox) {
  // Θ = [−1, 1]², strip 1.5 <= x1 + x2 <= 2.5: tightened to [1.5, 2] (σ' = 0.25); stage 2 gives
  // ξ_j ∈ [0.5, 1] for both generators, so Θ'' = [0.5, 1]², the bounding box of the triangle
  // {x1, x2 <= 1, x1 + x2 >= 1.5}; both scores are 0.25 <= σ = 0.5: no swap.
  VectorXd c(2);
  c << 1, 1;
  for (Convention conv : {Convention::Setbound, Convention::Cora}) {
    auto X = unit_box2();
    EXPECT_FALSE(ParallelotopeEstimator::vicino_zappa(X, c, 2.0, 0.5, conv));
    // CORA's arithmetic is exact here; setbound's bounds are rounded outward (by ~1e-14).
    const double tol = conv == Convention::Cora ? 1e-15 : 1e-13;
    EXPECT_EIGEN_NEAR(X.p, VectorXd::Constant(2, 0.75), tol);
    EXPECT_EIGEN_NEAR(X.G, (0.25 * MatrixXd::Identity(2, 2)), tol);
    EXPECT_LE(X.r.maxCoeff(), 1e-14);
    if (conv == Convention::Cora) {
      EXPECT_TRUE(X.r.isZero(0));
    } else {  // an outer bound of the exact box [0.5, 1]²
      const VectorXd e = X.G.cwiseAbs().rowwise().sum() + X.r;
      EXPECT_TRUE(((X.p - e).array() <= 0.5).all() && ((X.p + e).array() >= 1.0).all());
    }
  }
}

TEST(Ropo, VicinoZappaSwapsToTheHandComputedParallelogram) {
  // Θ = [−1, 1]², strip |x1 + 0.1 x2| <= 0.2 (inside the range [−1.1, 1.1]): stage 2 shrinks ξ1 to
  // [−0.3, 0.3]; scores 0.3 > σ = 0.2 and 0.1: column 1 is replaced, λ = (1, 0):
  // T = [[0.2, −0.1], [0, 1]], the intersection itself (a parallelogram).
  VectorXd c(2);
  c << 1, 0.1;
  MatrixXd T(2, 2);
  T << 0.2, -0.1, 0, 1;
  for (Convention conv : {Convention::Setbound, Convention::Cora}) {
    auto X = unit_box2();
    EXPECT_TRUE(ParallelotopeEstimator::vicino_zappa(X, c, 0.0, 0.2, conv));
    EXPECT_EIGEN_NEAR(X.p, VectorXd::Zero(2), 1e-15);
    EXPECT_EIGEN_NEAR(X.G, T, 1e-15);
    EXPECT_LE(X.r.maxCoeff(), 1e-14);
  }
  // A shifted strip: the result is the parallelogram {|x1 + 0.1 x2 − 0.1| <= 0.2, |x2| <= 1}.
  auto X = unit_box2();
  ParallelotopeEstimator::vicino_zappa(X, c, 0.1, 0.2, Convention::Setbound);
  const Zonotope Z(X.p, X.G);
  VectorXd inside(2), outside(2);
  inside << 0.4, -1.0;   // x1 + 0.1 x2 − 0.1 = 0.2: on the strip's edge, |x2| = 1
  outside << 0.45, 0.0;  // 0.35 outside the strip (but inside the old box)
  EXPECT_TRUE(Z.contains(inside, 1e-12));
  EXPECT_FALSE(Z.contains(outside, 1e-12));
  EXPECT_NEAR(X.p(0), 0.1, 1e-15);
}

TEST(Ropo, DegenerateCases) {
  // W = 0: the prediction has n columns at most, no reduction happens and a collapsed generator
  // stays a zero column (CORA would index out of range after dropping it); a zero row of C is
  // tested and not applied; an exact output (σ = 0) collapses the set onto its hyperplane.
  MatrixXd A(2, 2), C(2, 2), E = MatrixXd::Zero(2, 1), F = MatrixXd::Zero(2, 1);
  A << 0.5, 0.1, 0, 0.8;
  C << 1, 0, 0, 0;
  const LinearSystem sys(A, C, E, F);
  const Zonotope X0(VectorXd::Zero(2), MatrixXd::Identity(2, 2));
  ParallelotopeEstimator est(sys, X0, opts(ZonotopeReduction::Girard));
  VectorXd x(2);
  x << 0.3, -0.4;
  for (int k = 0; k < 6; ++k) {
    const VectorXd y = C * x;
    est.update(y, VectorXd(0));
    EXPECT_EQ(est.current_generators().cols(), 2);
    EXPECT_TRUE(est.current_set().contains(x, 1e-9)) << k;
    EXPECT_LE(est.current_upper()(0) - est.current_lower()(0), 1e-12);  // x1 known exactly
    EXPECT_EQ(est.last_check().status[1], OutputStatus::Used);
    x = A * x;
  }
  // K_j = 0 for every generator: the strip along x2 leaves the x1 generator untouched.
  auto X = unit_box2();
  VectorXd c(2);
  c << 0, 1;
  ParallelotopeEstimator::vicino_zappa(X, c, 0.5, 0.25, Convention::Setbound);
  EXPECT_NEAR(X.G(0, 0), 1.0, 0.0);
  EXPECT_NEAR(X.p(1), 0.5, 1e-15);
  EXPECT_NEAR(X.G(1, 1), 0.25, 1e-15);
}

TEST(Ropo, CoraConventionStartsWithR0AndPadsItsParallelotope) {
  std::mt19937 gen(9);
  const LinearSystem sys = random_system(1, gen);
  const Eigen::Index n = sys.nx();
  MatrixXd G0(n, 1);
  G0.setConstant(0.5);  // R0 with one generator: fewer than n
  const Zonotope X0(VectorXd::Zero(n), G0);
  ParallelotopeEstimator est(sys, X0, opts(ZonotopeReduction::Pca, Convention::Cora));
  const Record r = simulate(sys, gen, false, 20, VectorXd::Constant(n, 0.2));
  const auto t = est.run(r.Y, r.U);
  EXPECT_EIGEN_NEAR(t.sets[0].generators(), G0, 0.0);  // row 0 is R0 itself, y_0 unused
  EXPECT_EQ(t.checks[0].status[0], OutputStatus::Unused);
  for (size_t k = 1; k < 20; ++k) {
    EXPECT_EQ(t.sets[k].generators().cols(), n);
    EXPECT_TRUE(est.current_box().isZero(0));
  }
  // CORA normalises by σ_i: an output without noise is refused there.
  MatrixXd F0 = MatrixXd::Zero(sys.ny(), sys.nw());
  const LinearSystem exact(sys.A(), sys.C(), sys.E(), F0, sys.B(), sys.D());
  expect_error_naming<InvalidArgumentError>(
      [&] { ParallelotopeEstimator(exact, X0, opts(ZonotopeReduction::Girard, Convention::Cora)); }, "F");
  expect_error_naming<InvalidArgumentError>(
      [&] {
        ParallelotopeEstimator(sys, X0, opts(ZonotopeReduction::Girard, Convention::Cora, OnInconsistency::Raise));
      },
      "on_inconsistency");
}

TEST(Ropo, InconsistentReadingsFollowThePolicy) {
  std::mt19937 gen(3);
  const LinearSystem sys = random_system(0, gen);
  const Eigen::Index n = sys.nx();
  const Zonotope X0(VectorXd::Zero(n), MatrixXd::Identity(n, n));
  const VectorXd u = VectorXd::Zero(1);
  const VectorXd far = VectorXd::Constant(sys.ny(), 1e3);
  ParallelotopeEstimator flag(sys, X0, opts(ZonotopeReduction::Girard));
  flag.update(VectorXd::Zero(sys.ny()), u);
  flag.update(far, u);
  EXPECT_TRUE(flag.last_check().flagged());
  EXPECT_GT(flag.last_check().margin(0), 1.0);
  ParallelotopeEstimator raise(sys, X0, opts(ZonotopeReduction::Girard, Convention::Setbound, OnInconsistency::Raise));
  raise.update(VectorXd::Zero(sys.ny()), u);
  const auto saved = raise.save_state();
  EXPECT_THROW(raise.update(far, u), InconsistentMeasurementError);
  EXPECT_TRUE(same_bits(saved, raise.save_state()));  // unchanged
  ParallelotopeEstimator reset(sys, X0, opts(ZonotopeReduction::Girard, Convention::Setbound, OnInconsistency::Reset));
  reset.update(VectorXd::Zero(sys.ny()), u);
  reset.update(far, u);
  EXPECT_TRUE(reset.last_check().reset);
  // Missing outputs are skipped.
  VectorXd y = VectorXd::Constant(sys.ny(), std::numeric_limits<double>::quiet_NaN());
  flag.update(y, u);
  EXPECT_EQ(flag.last_check().status[0], OutputStatus::Missing);
}

TEST(Ropo, SavedStateContinuesBitForBit) {
  std::mt19937 gen(11);
  const LinearSystem sys = random_system(2, gen);
  const Eigen::Index n = sys.nx();
  const Zonotope X0(VectorXd::Zero(n), MatrixXd::Identity(n, n));
  const Record r = simulate(sys, gen, true, 16, VectorXd::Zero(n));
  for (Convention conv : {Convention::Setbound, Convention::Cora})
    for (ZonotopeReduction red : {ZonotopeReduction::Girard, ZonotopeReduction::Pca})
      for (int k0 : {0, 1, 7}) {
        ParallelotopeEstimator a(sys, X0, opts(red, conv)), b(sys, X0, opts(red, conv));
        for (int k = 0; k < k0; ++k) a.update(r.Y.row(k).transpose(), r.U.row(k).transpose());
        b.restore_state(a.save_state());
        for (int k = k0; k < 16; ++k) {
          a.update(r.Y.row(k).transpose(), r.U.row(k).transpose());
          b.update(r.Y.row(k).transpose(), r.U.row(k).transpose());
          ASSERT_TRUE(same_bits(a.save_state(), b.save_state()));
          ASSERT_TRUE(a.current_lower() == b.current_lower() && a.current_upper() == b.current_upper());
        }
        ParallelotopeEstimator c(sys, X0, opts(red == ZonotopeReduction::Pca ? ZonotopeReduction::Girard
                                                                             : ZonotopeReduction::Pca, conv));
        expect_error_naming<InvalidArgumentError>([&] { c.restore_state(a.save_state()); }, "state");
      }
}

TEST(Ropo, BadInputIsNamed) {
  std::mt19937 gen(13);
  const LinearSystem sys = random_system(1, gen);
  const Eigen::Index n = sys.nx();
  const Zonotope X0(VectorXd::Zero(n), MatrixXd::Identity(n, n));
  expect_error_naming<DimensionError>(
      [&] { ParallelotopeEstimator(sys, Zonotope(VectorXd::Zero(n + 1), MatrixXd::Identity(n + 1, n + 1))); }, "x0");
  expect_error_naming<InvalidArgumentError>([&] { ParallelotopeEstimator(sys, X0, opts(ZonotopeReduction::Combastel)); },
                                            "reduction");
  ParallelotopeEstimator est(sys, X0);
  expect_error_naming<DimensionError>([&] { est.update(VectorXd::Zero(sys.ny() + 1), VectorXd::Zero(1)); }, "y");
  expect_error_naming<DimensionError>([&] { est.update(VectorXd::Zero(sys.ny()), VectorXd::Zero(2)); }, "u");
  VectorXd yinf = VectorXd::Zero(sys.ny());
  yinf(0) = std::numeric_limits<double>::infinity();
  expect_error_naming<NotFiniteError>([&] { est.update(yinf, VectorXd::Zero(1)); }, "y");
  EXPECT_EQ(est.steps_taken(), 0);
  expect_error_naming<InvalidArgumentError>([&] { est.current_set(); }, "estimator");
}

TEST(Ropo, CApiRoundTripAndErrors) {
  std::mt19937 gen(17);
  const LinearSystem sys = random_system(0, gen);
  const int n = int(sys.nx()), ny = int(sys.ny());
  // a system handle through the C ABI
  using RM = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RM A = sys.A(), B = sys.B(), C = sys.C(), D = sys.D(), E = sys.E(), F = sys.F();
  sb_linear_system* s = nullptr;
  ASSERT_EQ(sb_linear_system_create(n, ny, int(sys.nu()), int(sys.nw()), A.data(), B.data(), C.data(), D.data(),
                                    E.data(), F.data(), nullptr, &s),
            SB_OK)
      << sb_last_error();
  const VectorXd p0 = VectorXd::Zero(n);
  const RM H0 = MatrixXd::Identity(n, n);
  sb_ropo_options o;
  ASSERT_EQ(sb_ropo_default_options(&o), SB_OK);
  EXPECT_EQ(o.reduction, SB_ZONO_REDUCE_GIRARD);
  sb_ropo* h = nullptr;
  ASSERT_EQ(sb_ropo_create(s, &o, n, p0.data(), H0.data(), &h), SB_OK) << sb_last_error();
  const Record r = simulate(sys, gen, false, 8, VectorXd::Zero(n));
  const RM Y = r.Y, U = r.U;
  RM ctr(8, n), lo(8, n), hi(8, n);
  ASSERT_EQ(sb_ropo_run(h, 8, Y.data(), U.data(), ctr.data(), lo.data(), hi.data()), SB_OK) << sb_last_error();
  ParallelotopeEstimator ref(sys, Zonotope(p0, MatrixXd::Identity(n, n)));
  const auto t = ref.run(r.Y, r.U);
  EXPECT_EIGEN_NEAR(MatrixXd(lo), t.lower, 0.0);
  EXPECT_EIGEN_NEAR(MatrixXd(hi), t.upper, 0.0);
  VectorXd theta(n), box(n);
  RM T(n, n);
  ASSERT_EQ(sb_ropo_parallelotope(h, theta.data(), T.data(), box.data()), SB_OK);
  EXPECT_EIGEN_NEAR(MatrixXd(T), ref.current_generators(), 0.0);
  int m = 0;
  EXPECT_EQ(sb_ropo_current_set(h, &m, theta.data(), nullptr), SB_ERR_BUFFER_TOO_SMALL);
  EXPECT_EQ(m, int(ref.current_set().num_generators()));
  int size = 0;
  ASSERT_EQ(sb_ropo_state_size(h, &size), SB_OK);
  std::vector<double> st(size_t(size) + 0);
  ASSERT_EQ(sb_ropo_save_state(h, st.data(), size), SB_OK);
  EXPECT_TRUE(same_bits(st, ref.save_state()));
  st[0] += 1;
  EXPECT_EQ(sb_ropo_restore_state(h, st.data(), size), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(std::string(sb_last_error()).find("sb_ropo_restore_state: state"), 0u) << sb_last_error();
  // bad options, NULL handles, bad dimensions
  o.reduction = SB_ZONO_REDUCE_COMBASTEL;
  sb_ropo* bad = nullptr;
  EXPECT_EQ(sb_ropo_create(s, &o, n, p0.data(), H0.data(), &bad), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("options.reduction"), std::string::npos) << sb_last_error();
  EXPECT_EQ(bad, nullptr);
  sb_ropo_default_options(&o);
  o.on_inconsistency = 7;
  EXPECT_EQ(sb_ropo_create(s, &o, n, p0.data(), H0.data(), &bad), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("options.on_inconsistency"), std::string::npos) << sb_last_error();
  EXPECT_EQ(sb_ropo_create(s, nullptr, -1, p0.data(), H0.data(), &bad), SB_ERR_DIMENSION);
  EXPECT_EQ(sb_ropo_step(nullptr, Y.data(), U.data(), nullptr, nullptr, nullptr, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_ropo_step(h, nullptr, U.data(), nullptr, nullptr, nullptr, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_ropo_run(h, -1, Y.data(), U.data(), nullptr, nullptr, nullptr), SB_ERR_DIMENSION);
  EXPECT_EQ(sb_ropo_free(nullptr), SB_OK);
  // RTS through the C ABI: bad covariance named
  const RM Sw = 0.01 * MatrixXd::Identity(n, n), Sv = 0.01 * MatrixXd::Identity(ny, ny), P0 = MatrixXd::Identity(n, n);
  RM xs(8, n);
  ASSERT_EQ(sb_rts_smooth(s, p0.data(), P0.data(), Sw.data(), Sv.data(), 8, Y.data(), U.data(), 1, xs.data(), nullptr,
                          nullptr, nullptr),
            SB_OK)
      << sb_last_error();
  const RM Svbad = MatrixXd::Zero(ny, ny);
  EXPECT_EQ(sb_rts_smooth(s, p0.data(), P0.data(), Sw.data(), Svbad.data(), 8, Y.data(), U.data(), 1, xs.data(),
                          nullptr, nullptr, nullptr),
            SB_ERR_NOT_POSITIVE_DEFINITE);
  EXPECT_NE(std::string(sb_last_error()).find("Sigma_v"), std::string::npos) << sb_last_error();
  EXPECT_EQ(sb_rts_smooth(s, p0.data(), P0.data(), Sw.data(), Sv.data(), 8, Y.data(), U.data(), 2, xs.data(), nullptr,
                          nullptr, nullptr),
            SB_ERR_INVALID_ARGUMENT);
  sb_ropo_free(h);
  sb_linear_system_free(s);
}

// ---- Rauch–Tung–Striebel ------------------------------------------------------------------------

TEST(Rts, LastSmoothedStateIsTheKalmanFiltersLast) {
  std::mt19937 gen(31);
  for (int trial = 0; trial < 6; ++trial) {
    const LinearSystem sys = random_system(trial, gen);
    const Eigen::Index n = sys.nx(), ny = sys.ny();
    const Record r = simulate(sys, gen, false, 25, VectorXd::Zero(n));
    const MatrixXd Sw = 0.01 * MatrixXd::Identity(n, n) + 0.001 * MatrixXd::Ones(n, n);
    const MatrixXd Sv = 0.04 * MatrixXd::Identity(ny, ny);
    const MatrixXd P0 = 0.5 * MatrixXd::Identity(n, n);
    const RtsResult s = rts_smooth(sys, VectorXd::Zero(n), P0, Sw, Sv, r.Y, r.U);
    // An independent Kalman filter with W on ω = [w; v].
    MatrixXd E = MatrixXd::Zero(n, n + ny), F = MatrixXd::Zero(ny, n + ny), W = MatrixXd::Zero(n + ny, n + ny);
    E.leftCols(n).setIdentity();
    F.rightCols(ny).setIdentity();
    W.topLeftCorner(n, n) = Sw;
    W.bottomRightCorner(ny, ny) = Sv;
    KalmanFilter kf(LinearSystem(sys.A(), sys.C(), E, F, sys.B(), sys.D()), VectorXd::Zero(n), P0, W);
    for (int k = 0; k < 25; ++k) kf.step(r.Y.row(k).transpose(), r.U.row(k).transpose());
    EXPECT_EIGEN_NEAR(VectorXd(s.smoothed.row(24).transpose()), kf.mean(), 1e-12);
    EXPECT_EIGEN_NEAR(s.smoothed_cov[24], kf.covariance(), 1e-12);
    // Smoothing does not increase the error covariance: P^s_k <= P_k (trace and Loewner order).
    for (int k = 0; k < 25; ++k) {
      EXPECT_LE(s.smoothed_cov[size_t(k)].trace(), s.filtered_cov[size_t(k)].trace() * (1 + 1e-12));
      const MatrixXd diff = s.filtered_cov[size_t(k)] - s.smoothed_cov[size_t(k)];
      EXPECT_GE(Eigen::SelfAdjointEigenSolver<MatrixXd>(diff).eigenvalues().minCoeff(), -1e-12);
    }
  }
}

TEST(Rts, ScalarTwoStepsByHand) {
  // x+ = x + w, y = x + v, Σ_w = 1, Σ_v = 1, x0 = 0, P0 = 1, y = (1, 2).
  // Forward: P_0|−1 = 1, K_0 = 1/2, x̂_0 = 0.5, P_0 = 0.5; M_1 = 1.5, K_1 = 0.6, x̂_1 = 0.5 + 0.6·1.5 = 1.4,
  // P_1 = 0.6. Backward: J_0 = 0.5/1.5 = 1/3, x^s_0 = 0.5 + (1.4 − 0.5)/3 = 0.8,
  // P^s_0 = 0.5 + (0.6 − 1.5)/9 = 0.4.
  MatrixXd one = MatrixXd::Ones(1, 1);
  const LinearSystem sys(one, one, MatrixXd::Zero(1, 1), MatrixXd::Zero(1, 1));
  MatrixXd Y(2, 1);
  Y << 1, 2;
  const RtsResult r = rts_smooth(sys, VectorXd::Zero(1), one, one, one, Y);
  EXPECT_NEAR(r.filtered(0, 0), 0.5, 1e-15);
  EXPECT_NEAR(r.filtered(1, 0), 1.4, 1e-15);
  EXPECT_NEAR(r.smoothed(1, 0), 1.4, 1e-15);
  EXPECT_NEAR(r.smoothed(0, 0), 0.8, 1e-15);
  EXPECT_NEAR(r.smoothed_cov[0](0, 0), 0.4, 1e-15);
  EXPECT_NEAR(r.smoothed_cov[1](0, 0), 0.6, 1e-15);
  // CORA's indexing: x̂_0 = x0 (y_0 unused): M_1 = 2, K_1 = 2/3, x̂_1 = 4/3, P_1 = 2/3;
  // J_0 = 1/2, x^s_0 = 0 + (4/3 − 0)/2 = 2/3.
  RtsOptions cora;
  cora.use_first_measurement = false;
  const RtsResult c = rts_smooth(sys, VectorXd::Zero(1), one, one, one, Y, MatrixXd(), cora);
  EXPECT_NEAR(c.filtered(0, 0), 0.0, 0.0);
  EXPECT_NEAR(c.smoothed(1, 0), 4.0 / 3.0, 1e-15);
  EXPECT_NEAR(c.smoothed(0, 0), 2.0 / 3.0, 1e-15);
}

TEST(Rts, SingularPredictionUsesThePseudoInverse) {
  // Σ_w = 0, P0 = 0 in the second coordinate: M_{k+1} singular, J_k through its pseudo-inverse.
  MatrixXd A = MatrixXd::Identity(2, 2), C(1, 2);
  C << 1, 0;
  const LinearSystem sys(A, C, MatrixXd::Zero(2, 1), MatrixXd::Zero(1, 1));
  MatrixXd P0 = MatrixXd::Zero(2, 2), Sw = MatrixXd::Zero(2, 2);
  P0(0, 0) = 1;
  Sw(0, 0) = 0.1;
  MatrixXd Y(3, 1);
  Y << 0.5, 0.7, 0.6;
  const RtsResult r = rts_smooth(sys, VectorXd::Zero(2), P0, Sw, 0.1 * MatrixXd::Identity(1, 1), Y);
  EXPECT_TRUE(r.smoothed.allFinite());
  EXPECT_EIGEN_NEAR(VectorXd(r.smoothed.col(1)), VectorXd::Zero(3), 0.0);
}

TEST(Rts, BadInputIsNamed) {
  MatrixXd one = MatrixXd::Ones(1, 1);
  const LinearSystem sys(one, one, MatrixXd::Zero(1, 1), MatrixXd::Zero(1, 1));
  const MatrixXd Y = MatrixXd::Zero(3, 1);
  expect_error_naming<DimensionError>([&] { rts_smooth(sys, VectorXd::Zero(2), one, one, one, Y); }, "x0");
  expect_error_naming<NotPositiveDefiniteError>([&] { rts_smooth(sys, VectorXd::Zero(1), -one, one, one, Y); }, "P0");
  expect_error_naming<NotPositiveDefiniteError>(
      [&] { rts_smooth(sys, VectorXd::Zero(1), one, one, MatrixXd::Zero(1, 1), Y); }, "Sigma_v");
  expect_error_naming<DimensionError>(
      [&] { rts_smooth(sys, VectorXd::Zero(1), one, MatrixXd::Identity(2, 2), one, Y); }, "Sigma_w");
  expect_error_naming<DimensionError>([&] { rts_smooth(sys, VectorXd::Zero(1), one, one, one, MatrixXd::Zero(3, 2)); },
                                      "y");
  MatrixXd Yinf = Y;
  Yinf(1, 0) = std::numeric_limits<double>::infinity();
  expect_error_naming<NotFiniteError>([&] { rts_smooth(sys, VectorXd::Zero(1), one, one, one, Yinf); }, "y");
}
