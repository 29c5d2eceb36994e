// Strips S = { x : |c^T x - y| <= phi } (spec papers.md §0.1) and their C ABI.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "c_api_common.hpp"
#include "setbound/sets/strip.hpp"
#include "test_helpers.hpp"

using setbound::Strip;
using Eigen::VectorXd;

TEST(Strip, ContainsBoundaryAndWidth) {
  const Strip S(Eigen::Vector2d(3, 4), 1.0, 0.5);  // |3 x1 + 4 x2 - 1| <= 0.5
  EXPECT_DOUBLE_EQ(S.width(), 2 * 0.5 / 5.0);     // distance between the hyperplanes
  EXPECT_TRUE(S.contains(Eigen::Vector2d(0.5, 0)));   // 1.5 - 1 = 0.5: on the boundary
  EXPECT_TRUE(S.contains(Eigen::Vector2d(0, 0.125))); // 0.5 - 1 = -0.5: other boundary
  EXPECT_FALSE(S.contains(Eigen::Vector2d(0.5 + 1e-9, 0)));
  EXPECT_FALSE(S.contains(Eigen::Vector2d(0, 0)));
  // Moving along the normal by the width crosses the whole strip.
  const Eigen::Vector2d on_low(0, 0.125), n = Eigen::Vector2d(3, 4) / 5.0;
  EXPECT_TRUE(S.contains(on_low + 0.999999 * S.width() * n));
  EXPECT_FALSE(S.contains(on_low + 1.000001 * S.width() * n));
  // phi = 0: a hyperplane.
  const Strip H(Eigen::Vector2d(1, 0), 2.0, 0.0);
  EXPECT_TRUE(H.contains(Eigen::Vector2d(2, 17)));
  EXPECT_FALSE(H.contains(Eigen::Vector2d(2.001, 0)));
  EXPECT_EQ(H.width(), 0.0);
}

TEST(Strip, HalfSpacesDescribeTheSameSet) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  const Strip S(Eigen::Vector3d(1, -2, 0.5), 0.3, 1.2);
  const auto [upper, lower] = S.half_spaces();
  int in = 0, out = 0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d x(g(rng), g(rng), g(rng));
    const bool by_halfspaces = upper.a.dot(x) <= upper.b && lower.a.dot(x) <= lower.b;
    EXPECT_EQ(S.contains(x, 0.0), by_halfspaces);
    (by_halfspaces ? in : out)++;
  }
  EXPECT_GT(in, 100);  // both outcomes are exercised
  EXPECT_GT(out, 100);
}

TEST(Strip, ValidationNamesTheArgument) {
  auto expect_named = [](auto&& f, const std::string& name, int code) {
    try {
      f();
      ADD_FAILURE() << "expected an error naming " << name;
    } catch (const setbound::Error& e) {
      EXPECT_EQ(e.code(), code) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind(name + ":", 0), 0u) << e.what();
    }
  };
  expect_named([] { Strip(VectorXd::Zero(2), 0, 1); }, "c", SB_ERR_INVALID_ARGUMENT);
  expect_named([] { Strip(VectorXd(), 0, 1); }, "c", SB_ERR_DIMENSION);
  expect_named([] { Strip(Eigen::Vector2d(1, std::nan("")), 0, 1); }, "c", SB_ERR_NOT_FINITE);
  expect_named([] { Strip(Eigen::Vector2d(1, 0), std::nan(""), 1); }, "y", SB_ERR_NOT_FINITE);
  expect_named([] { Strip(Eigen::Vector2d(1, 0), 0, -1); }, "phi", SB_ERR_INVALID_ARGUMENT);
  expect_named([] { Strip(Eigen::Vector2d(1, 0), 0, INFINITY); }, "phi", SB_ERR_NOT_FINITE);
  const Strip S(Eigen::Vector2d(1, 0), 0, 1);
  expect_named([&] { S.contains(Eigen::Vector3d(1, 0, 0)); }, "x", SB_ERR_DIMENSION);
}

TEST(StripCApi, ContainsAndErrors) {
  const double c[2] = {3, 4};
  const double pts[6] = {0.5, 0, 0, 0.125, 0, 0};
  int inside[3] = {-1, -1, -1};
  ASSERT_EQ(sb_strip_contains(2, c, 1.0, 0.5, 3, pts, 1e-12, inside), SB_OK) << sb_last_error();
  EXPECT_EQ(inside[0], 1);
  EXPECT_EQ(inside[1], 1);
  EXPECT_EQ(inside[2], 0);
  EXPECT_EQ(sb_strip_contains(2, c, 1.0, 0.5, 0, nullptr, 0.0, nullptr), SB_OK);  // empty batch
  EXPECT_EQ(sb_strip_contains(2, c, 1.0, -0.5, 3, pts, 0.0, inside), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(std::string(sb_last_error()).rfind("sb_strip_contains: phi:", 0), 0u) << sb_last_error();
  EXPECT_EQ(sb_strip_contains(2, nullptr, 1.0, 0.5, 3, pts, 0.0, inside), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(std::string(sb_last_error()), "sb_strip_contains: c: null pointer");
  EXPECT_EQ(sb_strip_contains(2, c, 1.0, 0.5, 3, pts, 0.0, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_strip_contains(0, c, 1.0, 0.5, 3, pts, 0.0, inside), SB_ERR_DIMENSION);
  EXPECT_EQ(sb_strip_contains(2, c, NAN, 0.5, 3, pts, 0.0, inside), SB_ERR_NOT_FINITE);
}
