// Boxes (thesis §1 "Boxes", §3.1 box rows, Ex 1.2) and the real matrix × box product
// (§7 item 1: M[x] equals the hull of the images of the box's vertices), with the C ABI
// sb_matrix_mul_box / sb_box_volume and their error paths.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "c_api_common.hpp"
#include "setbound/sets/box.hpp"
#include "test_helpers.hpp"

using setbound::Box;
using setbound::Interval;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Box B2(double l0, double h0, double l1, double h1) {
  return Box(Eigen::Vector2d(l0, l1), Eigen::Vector2d(h0, h1));
}

::testing::AssertionResult same(const Box& got, const Box& want) {
  if (got.size() == want.size() &&
      ((got.is_empty() && want.is_empty()) || (got.lo() == want.lo() && got.hi() == want.hi())))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "got " << got << ", want " << want;
}

/// Hull of {M v : v a vertex of [x]} (exact for a linear map: the extremes of each row are
/// attained at vertices), in plain floating point.
std::pair<VectorXd, VectorXd> vertex_image_hull(const MatrixXd& M, const Box& x) {
  const int n = int(x.size());
  VectorXd lo = VectorXd::Constant(M.rows(), kInf), hi = VectorXd::Constant(M.rows(), -kInf);
  for (int v = 0; v < (1 << n); ++v) {
    VectorXd p(n);
    for (int j = 0; j < n; ++j) p(j) = (v >> j) & 1 ? x.hi()(j) : x.lo()(j);
    const VectorXd y = M * p;
    lo = lo.cwiseMin(y);
    hi = hi.cwiseMax(y);
  }
  return {lo, hi};
}

}  // namespace

TEST(BoxReference, Table31BoxRowsAreExact) {
  EXPECT_TRUE(same(B2(0, 1, 1, 3) + B2(-2, 4, 5, 6), B2(-2, 5, 6, 9)));
  EXPECT_TRUE(same(B2(0, 1, 2, 3) - B2(-2, 0, -3, -1), B2(0, 3, 3, 6)));
  EXPECT_TRUE(same(B2(0, 5, 1, 3).intersect(B2(3, 4, 2, 6)), B2(3, 4, 2, 3)));
  EXPECT_TRUE(same(B2(-2, 1, 0, 3).hull(B2(2, 6, 1, 4)), B2(-2, 6, 0, 4)));
}

TEST(BoxReference, Example12MeasuresEq11To17) {
  const Box x = B2(2, 6, 2, 4);
  EXPECT_EQ(x.volume(), 8);
  EXPECT_EIGEN_NEAR(x.width(), Eigen::Vector2d(4, 2), 0);
  EXPECT_EQ(x.max_width(), 4);
  EXPECT_EQ(x.max_radius(), 2);
  EXPECT_EIGEN_NEAR(x.mid(), Eigen::Vector2d(4, 3), 0);
  EXPECT_EIGEN_NEAR(x.rad(), Eigen::Vector2d(2, 1), 0);
  EXPECT_EQ(x.norm(), 6);
  EXPECT_EQ(B2(-7, 1, 2, 3).norm(), 7);
  // Midpoint–radius split (eqs 1.15–1.16): x = m + [Δx], [Δx] = ½[−1,1]𝕎.
  const auto [m, d] = x.split();
  EXPECT_EIGEN_NEAR(m, Eigen::Vector2d(4, 3), 0);
  EXPECT_TRUE(same(d, B2(-2, 2, -1, 1)));
  EXPECT_TRUE(same(Box::point(m) + d, x));
  EXPECT_TRUE(x[0] == Interval(2, 6));
  EXPECT_TRUE(x[1] == Interval(2, 4));
}

TEST(BoxReference, CentreRadiusSetOpsAndScaling) {
  const Box c = Box::from_center_radius(Eigen::Vector2d(1, -1), Eigen::Vector2d(2, 0.5));
  EXPECT_TRUE(same(c, B2(-1, 3, -1.5, -0.5)));
  // Inexact centre ± radius is rounded outward.
  const Box r = Box::from_center_radius(Eigen::Matrix<double, 1, 1>(0.1),
                                        Eigen::Matrix<double, 1, 1>(0.2));
  EXPECT_LE((long double)r.lo()(0), (long double)0.1 - (long double)0.2);
  EXPECT_GE((long double)r.hi()(0), (long double)0.1 + (long double)0.2);
  EXPECT_TRUE(same(-2.0 * B2(0, 1, -1, 3), B2(-2, 0, -6, 2)));
  EXPECT_TRUE(same(-B2(0, 1, -1, 3), B2(-1, 0, -3, 1)));
  EXPECT_TRUE(B2(0, 1, 0, 1).intersect(B2(2, 3, 0, 1)).is_empty());
  EXPECT_EQ(B2(0, 1, 0, 1).intersect(B2(2, 3, 0, 1)).volume(), 0);
  EXPECT_TRUE(B2(0, 1, 0, 1).contains(Eigen::Vector2d(1, 0.5)));
  EXPECT_FALSE(B2(0, 1, 0, 1).contains(Eigen::Vector2d(1.5, 0.5)));
  EXPECT_TRUE(B2(0, 1, 0, 1).subset(B2(-1, 1, 0, 2)));
  EXPECT_FALSE(B2(0, 1, 0, 1).subset(B2(0.5, 1, 0, 2)));
  EXPECT_TRUE(Box::empty(2).subset(B2(0, 0, 0, 0)));
  EXPECT_TRUE(same(Box::empty(2).hull(B2(0, 1, 0, 1)), B2(0, 1, 0, 1)));
  EXPECT_EQ(B2(0, kInf, 0, 1).volume(), kInf);
}

TEST(BoxValidation, BadCornersThrowNamedErrors) {
  try {
    Box(Eigen::Vector2d(0, 2), Eigen::Vector2d(1, 1), "x0");
    FAIL();
  } catch (const setbound::InvalidArgumentError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("x0 component 1:", 0), 0u) << e.what();
  }
  EXPECT_THROW(Box(Eigen::Vector2d(0, std::nan("")), Eigen::Vector2d(1, 1)),
               setbound::NotFiniteError);
  EXPECT_THROW(Box(Eigen::Vector2d(0, 0), Eigen::Vector3d(1, 1, 1)), setbound::DimensionError);
  EXPECT_THROW(Box::from_center_radius(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, -1)),
               setbound::InvalidArgumentError);
  EXPECT_THROW(B2(0, 1, 0, 1) + Box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()),
               setbound::DimensionError);
  EXPECT_THROW(B2(0, 1, 0, 1) * std::nan(""), setbound::NotFiniteError);
  EXPECT_THROW(multiply(MatrixXd::Ones(2, 3), B2(0, 1, 0, 1)), setbound::DimensionError);
  MatrixXd bad = MatrixXd::Ones(2, 2);
  bad(1, 0) = kInf;
  EXPECT_THROW(multiply(bad, B2(0, 1, 0, 1)), setbound::NotFiniteError);
}

TEST(MatrixTimesBox, ExactOnIntegerDataAndEqualsCentreRadiusForm) {
  MatrixXd M(2, 2);
  M << 1, -2, 3, 0.5;
  const Box x = B2(-1, 3, 2, 4);
  // c = (1, 3), r = (2, 1): Mc = (−5, 4.5), |M|r = (4, 6.5).
  EXPECT_TRUE(same(M * x, B2(-9, -1, -2, 11)));
}

TEST(MatrixTimesBox, EqualsHullOfVertexImagesAndContainsSamples) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(-3, 3), U01(0, 1);
  for (int trial = 0; trial < 300; ++trial) {
    const int p = 1 + int(rng() % 4), n = 1 + int(rng() % 5);
    MatrixXd M = MatrixXd::NullaryExpr(p, n, [&] { return U(rng); });
    VectorXd a = VectorXd::NullaryExpr(n, [&] { return U(rng); });
    VectorXd b = VectorXd::NullaryExpr(n, [&] { return U(rng); });
    const Box x(a.cwiseMin(b), a.cwiseMax(b));
    const Box y = multiply(M, x);
    const auto [vlo, vhi] = vertex_image_hull(M, x);
    // The vertex images are real points of the exact set, computed with rounding: the result
    // must contain them up to that rounding and be no larger than it beyond a few ulps.
    const double tol = 1e-13;
    EXPECT_TRUE(((y.lo() - vlo).array() <= tol).all()) << trial;
    EXPECT_TRUE(((vhi - y.hi()).array() <= tol).all()) << trial;
    EXPECT_EIGEN_NEAR(y.lo(), vlo, tol);
    EXPECT_EIGEN_NEAR(y.hi(), vhi, tol);
    // Centre–radius form [Mc − |M|r, Mc + |M|r] of the thesis.
    const VectorXd c = x.mid(), r = x.rad();
    EXPECT_EIGEN_NEAR(y.lo(), M * c - M.cwiseAbs() * r, tol);
    EXPECT_EIGEN_NEAR(y.hi(), M * c + M.cwiseAbs() * r, tol);
    // Guaranteed containment of sampled images, checked in long double.
    for (int s = 0; s < 20; ++s) {
      VectorXd pt(n);
      for (int j = 0; j < n; ++j) pt(j) = x.lo()(j) + (x.hi()(j) - x.lo()(j)) * U01(rng);
      pt = pt.cwiseMax(x.lo()).cwiseMin(x.hi());
      for (int i = 0; i < p; ++i) {
        // long double keeps 11 more bits than double: its error (≤ ~1e-18 of Σ|M_ij p_j|) is
        // far below the one-ulp (~1e-16 relative) steps the enclosure takes.
        long double acc = 0, scale = 0;
        for (int j = 0; j < n; ++j) {
          acc += (long double)M(i, j) * (long double)pt(j);
          scale += std::fabs((long double)M(i, j) * (long double)pt(j));
        }
        ASSERT_LE((long double)y.lo()(i), acc + 1e-18L * scale);
        ASSERT_GE((long double)y.hi()(i), acc - 1e-18L * scale);
      }
    }
  }
}

TEST(MatrixTimesBox, UnboundedComponentsAndEmptyBox) {
  MatrixXd M(2, 2);
  M << 1, 0, 2, 1;
  const Box x(Eigen::Vector2d(-kInf, 1), Eigen::Vector2d(kInf, 2));
  // Row 0 ignores the unbounded component (0·[−inf, inf] = 0); row 1 does not.
  const Box y = M * x;
  EXPECT_TRUE(y[0] == Interval(-kInf, kInf));
  EXPECT_TRUE(y[1] == Interval(-kInf, kInf));
  MatrixXd P(1, 2);
  P << 0, 3;
  EXPECT_TRUE(same(P * x, Box(Eigen::Matrix<double, 1, 1>(3), Eigen::Matrix<double, 1, 1>(6))));
  EXPECT_TRUE((M * Box::empty(2)).is_empty());
}

TEST(BoxCApi, MatrixMulBoxAndVolume) {
  const double M[] = {1, -2, 3, 0.5};  // row-major 2x2
  const double xlo[] = {-1, 2}, xhi[] = {3, 4};
  double ylo[2], yhi[2];
  ASSERT_EQ(sb_matrix_mul_box(2, 2, M, xlo, xhi, ylo, yhi), SB_OK) << sb_last_error();
  EXPECT_EQ(ylo[0], -9);
  EXPECT_EQ(yhi[0], -1);
  EXPECT_EQ(ylo[1], -2);
  EXPECT_EQ(yhi[1], 11);
  double v = 0;
  ASSERT_EQ(sb_box_volume(2, xlo, xhi, &v), SB_OK);
  EXPECT_EQ(v, 8);

  auto starts = [](const char* prefix) {
    return std::string(sb_last_error()).rfind(prefix, 0) == 0;
  };
  EXPECT_EQ(sb_matrix_mul_box(2, 2, nullptr, xlo, xhi, ylo, yhi), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_matrix_mul_box: M:")) << sb_last_error();
  const double Mnan[] = {1, std::nan(""), 0, 0};
  EXPECT_EQ(sb_matrix_mul_box(2, 2, Mnan, xlo, xhi, ylo, yhi), SB_ERR_NOT_FINITE);
  EXPECT_TRUE(starts("sb_matrix_mul_box: M:")) << sb_last_error();
  const double bad_hi[] = {3, 1};
  EXPECT_EQ(sb_matrix_mul_box(2, 2, M, xlo, bad_hi, ylo, yhi), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_matrix_mul_box: x component 1:")) << sb_last_error();
  EXPECT_EQ(sb_matrix_mul_box(2, 2, M, xlo, xhi, ylo, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_matrix_mul_box(-2, 2, M, xlo, xhi, ylo, yhi), SB_ERR_DIMENSION);
  EXPECT_EQ(sb_box_volume(2, xlo, xhi, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_box_volume: volume:")) << sb_last_error();
  EXPECT_EQ(sb_box_volume(2, xlo, bad_hi, &v), SB_ERR_INVALID_ARGUMENT);
}
