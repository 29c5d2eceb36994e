// Ellipsoids E(P, c, rho) (spec papers.md §0.1, thesis.md §1 and §3.3) and their C ABI.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>
#include <string>

#include "c_api_common.hpp"
#include "setbound/sets/ellipsoid.hpp"
#include "test_helpers.hpp"

using setbound::testing::expect_error_naming;

using setbound::Ellipsoid;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kPi = 3.14159265358979323846;

MatrixXd random_spd(int n, std::mt19937& rng, double floor = 0.1) {
  std::normal_distribution<double> g;
  MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = g(rng);
  return A * A.transpose() + floor * MatrixXd::Identity(n, n);
}

VectorXd random_vector(int n, std::mt19937& rng, double scale = 1.0) {
  std::normal_distribution<double> g;
  VectorXd v(n);
  for (int i = 0; i < n; ++i) v(i) = scale * g(rng);
  return v;
}

/// A point of E: c + sqrt(rho) L^-T u with ||u|| <= 1 (P = L L^T), so (x-c)^T P (x-c) = rho |u|^2.
/// With on_boundary the point has |u| = 1.
VectorXd sample_in(const Ellipsoid& E, std::mt19937& rng, bool on_boundary = false) {
  const int n = static_cast<int>(E.dimension());
  VectorXd u = random_vector(n, rng);
  u.normalize();
  if (!on_boundary) u *= std::pow(std::uniform_real_distribution<double>(0, 1)(rng), 1.0 / n);
  Eigen::LLT<MatrixXd> llt(E.shape());
  return E.center() + std::sqrt(E.level()) * llt.matrixU().solve(u);
}

double quad(const Ellipsoid& E, const VectorXd& x) {
  return (x - E.center()).dot(E.shape() * (x - E.center()));
}

}  // namespace

// ---- volume -------------------------------------------------------------------------------

TEST(Ellipsoid, VolumeOfUnitBallsIsVn) {
  // V_2 = pi, V_3 = 4 pi / 3 (papers §0.1); V_1 = 2 (the segment [-1, 1]).
  EXPECT_NEAR(Ellipsoid(MatrixXd::Identity(1, 1), VectorXd::Zero(1), 1.0).volume(), 2.0, 1e-14);
  EXPECT_NEAR(Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 1.0).volume(), kPi, 1e-14);
  EXPECT_NEAR(Ellipsoid(MatrixXd::Identity(3, 3), VectorXd::Ones(3), 1.0).volume(), 4.0 * kPi / 3.0, 1e-13);
}

TEST(Ellipsoid, VolumeOfAxisAlignedEllipseAndLevelScaling) {
  // {x : x1^2/a^2 + x2^2/b^2 <= 1} has area pi a b; with level rho the semi-axes grow by sqrt(rho).
  const double a = 3.0, b = 0.5, rho = 2.5;
  MatrixXd P = VectorXd((VectorXd(2) << 1 / (a * a), 1 / (b * b)).finished()).asDiagonal();
  const Ellipsoid E(P, VectorXd::Zero(2), rho);
  EXPECT_NEAR(E.volume(), kPi * a * b * rho, 1e-12);
  // (P, rho) and (tP, t rho) are the same set.
  EXPECT_NEAR(Ellipsoid(7.0 * P, VectorXd::Zero(2), 7.0 * rho).volume(), E.volume(), 1e-12);
  EXPECT_NEAR(E.log_volume(), std::log(kPi * a * b * rho), 1e-13);
  EXPECT_EQ(Ellipsoid(P, VectorXd::Zero(2), 0.0).volume(), 0.0);
}

TEST(Ellipsoid, LogVolumeDoesNotOverflowInHighDimension) {
  // det(1e4 I_200) = 1e800 overflows a double; the log-det path must not.
  const int n = 200;
  const Ellipsoid E(1e4 * MatrixXd::Identity(n, n), VectorXd::Zero(n), 1.0);
  const double expected = 0.5 * n * std::log(kPi) - std::lgamma(0.5 * n + 1) - 0.5 * n * std::log(1e4);
  EXPECT_TRUE(std::isfinite(E.log_volume()));
  EXPECT_NEAR(E.log_volume(), expected, 1e-9 * std::abs(expected));
}

// ---- bounding box (thesis (1.40), Example 1.3/1.4) ----------------------------------------

TEST(Ellipsoid, BoundingBoxOfThesisExample13UsesInverse) {
  // c = 0, P = [[1, 1], [1, 4]], rho = 1. P^-1 = [[4, -1], [-1, 1]] / 3, so (1.40) gives
  // half-widths sqrt(4/3) and sqrt(1/3). The thesis's printed box (from diag(P)) would be
  // 1/sqrt(1) = 1 and 1/sqrt(4) = 0.5 — it must not come out.
  MatrixXd P(2, 2);
  P << 1, 1, 1, 4;
  const Ellipsoid E(P, VectorXd::Zero(2), 1.0);
  const auto box = E.bounding_box();
  EXPECT_NEAR(box.hi(0), std::sqrt(4.0 / 3.0), 1e-13);
  EXPECT_NEAR(box.hi(1), std::sqrt(1.0 / 3.0), 1e-13);
  EXPECT_EIGEN_NEAR(box.lo, -box.hi, 0.0);
  EXPECT_GT(std::abs(box.hi(0) - 1.0), 0.1);
  EXPECT_GT(std::abs(box.hi(1) - 0.5), 0.05);
  // Each bound is attained on the boundary at c ± rho^1/2 P^-1 e_i / sqrt((P^-1)_ii).
  const MatrixXd Pinv = P.inverse();
  for (int i = 0; i < 2; ++i) {
    const VectorXd xs = Pinv.col(i) / std::sqrt(Pinv(i, i));
    EXPECT_NEAR(quad(E, xs), 1.0, 1e-13);
    EXPECT_NEAR(xs(i), box.hi(i), 1e-12);
    EXPECT_NEAR(-xs(i), box.lo(i), 1e-12);
    EXPECT_EIGEN_NEAR(E.support_point(VectorXd::Unit(2, i)), xs, 1e-13);
  }
}

TEST(Ellipsoid, BoundingBoxIsTightAndContainsSamples) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 1 + trial % 5;
    const Ellipsoid E(random_spd(n, rng), random_vector(n, rng, 3.0), 0.1 + trial);
    const auto box = E.bounding_box();
    for (int i = 0; i < n; ++i) {
      // Attained: the support point of e_i lies on the boundary and reaches the bound.
      const VectorXd up = E.support_point(VectorXd::Unit(n, i));
      const VectorXd dn = E.support_point(-VectorXd::Unit(n, i));
      EXPECT_NEAR(quad(E, up), E.level(), 1e-9 * E.level());
      EXPECT_NEAR(up(i), box.hi(i), 1e-9 * (1 + std::abs(box.hi(i))));
      EXPECT_NEAR(dn(i), box.lo(i), 1e-9 * (1 + std::abs(box.lo(i))));
    }
    for (int k = 0; k < 200; ++k) {
      const VectorXd x = sample_in(E, rng, k % 2 == 0);
      EXPECT_TRUE((x.array() <= box.hi.array()).all() && (x.array() >= box.lo.array()).all());
    }
  }
}

// ---- containment and support function -----------------------------------------------------

TEST(Ellipsoid, ContainsSamplesAndRejectsScaledBoundaryPoints) {
  std::mt19937 rng(5);
  const Ellipsoid E(random_spd(3, rng), random_vector(3, rng), 2.0);
  for (int k = 0; k < 500; ++k) {
    const VectorXd x = sample_in(E, rng, k % 3 == 0);
    EXPECT_TRUE(E.contains(x));
    // Just outside along the ray from the centre: 1 + 1e-6 times as far.
    const VectorXd out = E.center() + (1.0 + 1e-6) * (E.boundary_point(x - E.center()) - E.center());
    EXPECT_FALSE(E.contains(out));
    EXPECT_NEAR(quad(E, E.boundary_point(x - E.center())), E.level(), 1e-10);
  }
  const Ellipsoid point(MatrixXd::Identity(2, 2), VectorXd::Ones(2), 0.0);
  EXPECT_TRUE(point.contains(VectorXd::Ones(2)));
  EXPECT_FALSE(point.contains(VectorXd::Ones(2) * (1 + 1e-9)));
}

TEST(Ellipsoid, SupportFunctionBoundsSamplesAndIsAttained) {
  std::mt19937 rng(6);
  const int n = 4;
  const Ellipsoid E(random_spd(n, rng), random_vector(n, rng), 1.7);
  for (int t = 0; t < 50; ++t) {
    const VectorXd a = random_vector(n, rng);
    const double h = E.support(a);
    for (int k = 0; k < 100; ++k) EXPECT_LE(a.dot(sample_in(E, rng, true)), h + 1e-10);
    const VectorXd xs = E.support_point(a);
    EXPECT_NEAR(a.dot(xs), h, 1e-10 * (1 + std::abs(h)));
    EXPECT_NEAR(quad(E, xs), E.level(), 1e-10);
    // h(a) = a^T c + sqrt(rho a^T P^-1 a), via an independent inverse.
    EXPECT_NEAR(h, a.dot(E.center()) + std::sqrt(E.level() * a.dot(E.shape().inverse() * a)), 1e-10);
  }
}

// ---- affine map ---------------------------------------------------------------------------

TEST(Ellipsoid, AffineMapMapsSamplesAndScalesVolume) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 10; ++trial) {
    const int n = 2 + trial % 3;
    const Ellipsoid E(random_spd(n, rng), random_vector(n, rng), 0.5 + trial);
    MatrixXd M = random_spd(n, rng) + MatrixXd::Random(n, n);  // generic, invertible
    const VectorXd b = random_vector(n, rng);
    const Ellipsoid F = E.affine_map(M, b);
    EXPECT_NEAR(F.volume(), std::abs(M.determinant()) * E.volume(), 1e-9 * F.volume());
    EXPECT_EIGEN_NEAR(F.center(), VectorXd(M * E.center() + b), 1e-12);
    for (int k = 0; k < 100; ++k) {
      const VectorXd x = sample_in(E, rng, true);  // boundary maps to boundary
      EXPECT_NEAR(quad(F, M * x + b), F.level(), 1e-8 * F.level());
    }
  }
}

TEST(Ellipsoid, AffineMapRejectsSingularM) {
  const Ellipsoid E(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 1.0);
  MatrixXd M(2, 2);
  M << 1, 2, 2, 4;
  expect_error_naming<setbound::InvalidArgumentError>([&] { E.affine_map(M, VectorXd::Zero(2)); }, "M");
  expect_error_naming<setbound::DimensionError>([&] { E.affine_map(MatrixXd::Identity(3, 3), VectorXd::Zero(2)); },
                                                "M");
  expect_error_naming<setbound::DimensionError>([&] { E.affine_map(MatrixXd::Identity(2, 2), VectorXd::Zero(3)); },
                                                "b");
}

// ---- change of shape ----------------------------------------------------------------------

TEST(Ellipsoid, LevelForShapeKnownValues) {
  // E(I, 0, rho) ⊆ E(diag(2, 5), 0, rho') iff rho' >= 5 rho (lambda_max of diag(2, 5)).
  const Ellipsoid ball(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 3.0);
  const double r = ball.level_for_shape(VectorXd((VectorXd(2) << 2, 5).finished()).asDiagonal().toDenseMatrix());
  EXPECT_GE(r, 15.0);
  EXPECT_LE(r, 15.0 * (1 + 1e-12));
  // E(diag(4, 1), 0, 1) ⊆ E(I, 0, rho') iff rho' >= max(1/4, 1) = 1.
  const Ellipsoid E(VectorXd((VectorXd(2) << 4, 1).finished()).asDiagonal(), VectorXd::Zero(2), 1.0);
  EXPECT_GE(E.level_for_shape(MatrixXd::Identity(2, 2)), 1.0);
  EXPECT_LE(E.level_for_shape(MatrixXd::Identity(2, 2)), 1.0 + 1e-12);
  // Same shape: the level is kept (rounded up by at most a few ulps).
  EXPECT_GE(E.level_for_shape(E.shape()), 1.0);
  EXPECT_LE(E.level_for_shape(E.shape()), 1.0 + 1e-12);
}

TEST(Ellipsoid, WithShapeContainsOriginalAndIsTight) {
  std::mt19937 rng(8);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 1 + trial % 4;
    const Ellipsoid E(random_spd(n, rng), random_vector(n, rng), 0.2 + trial);
    const MatrixXd Pn = random_spd(n, rng);
    const Ellipsoid F = E.with_shape(Pn);
    EXPECT_EIGEN_NEAR(F.shape(), Pn, 1e-15);
    EXPECT_EIGEN_NEAR(F.center(), E.center(), 0.0);
    // Certificate: (rho'/rho) P - P_new is PSD (independent check with eigenvalues).
    Eigen::SelfAdjointEigenSolver<MatrixXd> es(F.level() / E.level() * E.shape() - Pn);
    EXPECT_GE(es.eigenvalues().minCoeff(), -1e-12 * Pn.norm());
    double worst = 0.0;
    for (int k = 0; k < 300; ++k) {
      const VectorXd x = sample_in(E, rng, k % 2 == 0);
      EXPECT_TRUE(F.contains(x, 0.0)) << "trial " << trial;
      worst = std::max(worst, quad(F, x));
    }
    // Tight: the generalised eigenvector direction of E reaches rho' (up to the round-up).
    Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> ges(Pn, E.shape());
    const VectorXd v = ges.eigenvectors().col(n - 1);
    const VectorXd xb = E.boundary_point(v);
    EXPECT_NEAR(quad(F, xb), F.level(), 1e-8 * F.level());
    EXPECT_LE(worst, F.level());
  }
}

// ---- validation ---------------------------------------------------------------------------

TEST(Ellipsoid, ConstructorErrorsNameTheArgument) {
  using namespace setbound;
  MatrixXd nonsym(2, 2);
  nonsym << 2, 1, 0, 2;
  MatrixXd indef(2, 2);
  indef << 1, 2, 2, 1;
  expect_error_naming<NotSymmetricError>([&] { Ellipsoid(nonsym, VectorXd::Zero(2), 1.0); }, "P");
  expect_error_naming<NotPositiveDefiniteError>([&] { Ellipsoid(indef, VectorXd::Zero(2), 1.0); }, "P");
  expect_error_naming<DimensionError>([&] { Ellipsoid(MatrixXd::Identity(2, 3), VectorXd::Zero(2), 1.0); }, "P");
  expect_error_naming<DimensionError>([&] { Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(3), 1.0); }, "c");
  VectorXd nanc = VectorXd::Zero(2);
  nanc(1) = std::nan("");
  expect_error_naming<NotFiniteError>([&] { Ellipsoid(MatrixXd::Identity(2, 2), nanc, 1.0); }, "c");
  expect_error_naming<InvalidArgumentError>([&] { Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), -1.0); },
                                            "rho");
  expect_error_naming<NotFiniteError>(
      [&] { Ellipsoid(MatrixXd::Identity(2, 2), VectorXd::Zero(2), std::numeric_limits<double>::infinity()); },
      "rho");
  const Ellipsoid E(MatrixXd::Identity(2, 2), VectorXd::Zero(2), 1.0);
  expect_error_naming<NotPositiveDefiniteError>([&] { E.level_for_shape(indef); }, "P_new");
  expect_error_naming<DimensionError>([&] { E.contains(VectorXd::Zero(3)); }, "x");
  expect_error_naming<DimensionError>([&] { E.support(VectorXd::Zero(1)); }, "a");
}

// ---- C ABI --------------------------------------------------------------------------------

TEST(EllipsoidCApi, MatchesCxxAndReportsErrors) {
  // Row-major P = [[1, 1], [1, 4]] (symmetric, so the layout does not matter here).
  const double P[4] = {1, 1, 1, 4};
  const double c[2] = {1.0, -2.0};
  double lo[2], hi[2];
  ASSERT_EQ(sb_ellipsoid_validate(2, P, c, 2.0), SB_OK);
  ASSERT_EQ(sb_ellipsoid_bounding_box(2, P, c, 2.0, lo, hi), SB_OK) << sb_last_error();
  EXPECT_NEAR(hi[0], 1.0 + std::sqrt(2.0 * 4.0 / 3.0), 1e-13);
  EXPECT_NEAR(lo[1], -2.0 - std::sqrt(2.0 / 3.0), 1e-13);

  double vol = 0, logvol = 0;
  ASSERT_EQ(sb_ellipsoid_volume(2, P, c, 2.0, &vol, &logvol), SB_OK);
  EXPECT_NEAR(vol, kPi * 2.0 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(logvol, std::log(vol), 1e-13);
  ASSERT_EQ(sb_ellipsoid_volume(2, P, c, 2.0, &vol, nullptr), SB_OK);

  const double pts[6] = {1.0, -2.0, 1.0 + hi[0] - 1.0 + 1e-3, -2.0, 1.0, -2.0 + 0.1};
  int inside[3] = {-1, -1, -1};
  ASSERT_EQ(sb_ellipsoid_contains(2, P, c, 2.0, 3, pts, 1e-12, inside), SB_OK);
  EXPECT_EQ(inside[0], 1);
  EXPECT_EQ(inside[1], 0);
  EXPECT_EQ(inside[2], 1);

  const double dirs[4] = {1, 0, 0, -1};
  double h[2];
  ASSERT_EQ(sb_ellipsoid_support(2, P, c, 2.0, 2, dirs, h), SB_OK);
  EXPECT_NEAR(h[0], hi[0], 1e-12);
  EXPECT_NEAR(h[1], -lo[1], 1e-12);

  // Affine map: row-major M = [[2, 0], [1, 1]] is NOT symmetric, so this checks the layout.
  const double M[4] = {2, 0, 1, 1};
  const double b[2] = {0.5, 0.0};
  double Pout[4], cout[2], rout = 0;
  ASSERT_EQ(sb_ellipsoid_affine_map(2, P, c, 2.0, M, b, Pout, cout, &rout), SB_OK) << sb_last_error();
  EXPECT_NEAR(cout[0], 2.0 * 1.0 + 0.5, 1e-14);
  EXPECT_NEAR(cout[1], 1.0 * 1.0 - 2.0, 1e-14);
  EXPECT_EQ(rout, 2.0);
  MatrixXd Mm(2, 2);
  Mm << 2, 0, 1, 1;
  MatrixXd Pm(2, 2);
  Pm << 1, 1, 1, 4;
  const MatrixXd expected = Mm.inverse().transpose() * Pm * Mm.inverse();
  EXPECT_EIGEN_NEAR(setbound::capi::ConstRowMap(Pout, 2, 2), expected, 1e-12);

  const double Pnew[4] = {2, 0, 0, 5};
  double rnew = 0;
  ASSERT_EQ(sb_ellipsoid_level_for_shape(2, P, c, 2.0, Pnew, &rnew), SB_OK);
  EXPECT_NEAR(rnew, setbound::Ellipsoid(Pm, Eigen::Vector2d(1, -2), 2.0).level_for_shape(
                        Eigen::Vector2d(2, 5).asDiagonal().toDenseMatrix()), 1e-12);

  // Error paths: status code and a message naming the argument.
  EXPECT_EQ(sb_ellipsoid_bounding_box(2, nullptr, c, 1.0, lo, hi), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(std::string(sb_last_error()), "sb_ellipsoid_bounding_box: P: null pointer");
  EXPECT_EQ(sb_ellipsoid_bounding_box(2, P, c, 1.0, nullptr, hi), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("lo: null pointer"), std::string::npos);
  EXPECT_EQ(sb_ellipsoid_bounding_box(0, P, c, 1.0, lo, hi), SB_ERR_DIMENSION);
  const double Pindef[4] = {1, 2, 2, 1};
  EXPECT_EQ(sb_ellipsoid_volume(2, Pindef, c, 1.0, &vol, nullptr), SB_ERR_NOT_POSITIVE_DEFINITE);
  EXPECT_NE(std::string(sb_last_error()).find("P: matrix is not positive definite"), std::string::npos);
  const double Pnonsym[4] = {1, 0.5, 0, 1};
  EXPECT_EQ(sb_ellipsoid_validate(2, Pnonsym, c, 1.0), SB_ERR_NOT_SYMMETRIC);
  EXPECT_EQ(sb_ellipsoid_validate(2, P, c, -1.0), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("rho:"), std::string::npos);
  const double nanpts[2] = {std::nan(""), 0.0};
  EXPECT_EQ(sb_ellipsoid_contains(2, P, c, 1.0, 1, nanpts, 0.0, inside), SB_ERR_NOT_FINITE);
  EXPECT_NE(std::string(sb_last_error()).find("points:"), std::string::npos);
  EXPECT_EQ(sb_ellipsoid_contains(2, P, c, 1.0, -1, pts, 0.0, inside), SB_ERR_DIMENSION);
  EXPECT_EQ(sb_ellipsoid_support(2, P, c, 1.0, 1, nullptr, h), SB_ERR_INVALID_ARGUMENT);
  const double Msing[4] = {1, 2, 2, 4};
  EXPECT_EQ(sb_ellipsoid_affine_map(2, P, c, 1.0, Msing, b, Pout, cout, &rout), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("M: matrix must be invertible"), std::string::npos);
  EXPECT_EQ(sb_ellipsoid_level_for_shape(2, P, c, 1.0, Pindef, &rnew), SB_ERR_NOT_POSITIVE_DEFINITE);
  EXPECT_NE(std::string(sb_last_error()).find("P_new:"), std::string::npos);
  EXPECT_EQ(sb_ellipsoid_level_for_shape(2, P, c, 1.0, Pnew, nullptr), SB_ERR_INVALID_ARGUMENT);
}
