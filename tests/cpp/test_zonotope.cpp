// Zonotopes p ⊕ H B^m (spec papers.md §0.1, §3.1) and their C ABI.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "c_api_common.hpp"
#include "setbound/sets/generator_kernels.hpp"
#include "setbound/sets/zonotope.hpp"
#include "test_helpers.hpp"

using setbound::testing::expect_error_naming;

using setbound::Strip;
using setbound::Zonotope;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

MatrixXd random_matrix(int r, int c, std::mt19937& rng, double scale = 1.0) {
  std::normal_distribution<double> g;
  MatrixXd A(r, c);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) A(i, j) = scale * g(rng);
  return A;
}

VectorXd random_vector(int n, std::mt19937& rng, double scale = 1.0) { return random_matrix(n, 1, rng, scale); }

Zonotope random_zonotope(int n, int m, std::mt19937& rng) {
  return Zonotope(random_vector(n, rng, 2.0), random_matrix(n, m, rng));
}

/// z in B^m: a vertex (all ±1) when `vertex`, else uniform in the box.
VectorXd random_box_point(int m, std::mt19937& rng, bool vertex) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VectorXd z(m);
  for (int j = 0; j < m; ++j) z(j) = vertex ? (u(rng) < 0 ? -1.0 : 1.0) : u(rng);
  return z;
}

VectorXd sample_in(const Zonotope& Z, std::mt19937& rng, bool vertex) {
  return Z.center() + Z.generators() * random_box_point(static_cast<int>(Z.num_generators()), rng, vertex);
}

/// Outer ⊇ inner checked through support functions: h_inner(d) <= h_outer(d) for many d
/// (necessary and, over all d, sufficient for containment of convex sets).
void expect_support_dominates(const Zonotope& outer, const Zonotope& inner, std::mt19937& rng, int ndir = 400) {
  const int n = static_cast<int>(inner.dimension());
  for (int k = 0; k < ndir; ++k) {
    const VectorXd d = random_vector(n, rng);
    const double ho = outer.support(d), hi = inner.support(d);
    EXPECT_LE(hi, ho + 1e-10 * (1.0 + std::abs(ho))) << "direction " << d.transpose();
  }
}

/// Area of the convex hull of 2-D points (monotone chain + shoelace): an independent
/// volume for 2-D zonotopes.
double hull_area(std::vector<Eigen::Vector2d> pts) {
  std::sort(pts.begin(), pts.end(), [](const auto& a, const auto& b) {
    return a(0) < b(0) || (a(0) == b(0) && a(1) < b(1));
  });
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a(0) - o(0)) * (b(1) - o(1)) - (a(1) - o(1)) * (b(0) - o(0));
  };
  std::vector<Eigen::Vector2d> h(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], pts[i - 1]) <= 0) --k;
    h[k++] = pts[i - 1];
  }
  double area = 0;
  for (size_t i = 0; i + 1 < k; ++i) area += h[i](0) * h[i + 1](1) - h[i + 1](0) * h[i](1);
  return 0.5 * std::abs(area);
}

std::vector<VectorXd> all_vertices(const Zonotope& Z) {
  const int m = static_cast<int>(Z.num_generators());
  std::vector<VectorXd> v;
  for (long mask = 0; mask < (1L << m); ++mask) {
    VectorXd s(m);
    for (int j = 0; j < m; ++j) s(j) = (mask >> j) & 1 ? 1.0 : -1.0;
    v.push_back(Z.center() + Z.generators() * s);
  }
  return v;
}

}  // namespace

// ---- basic operations ---------------------------------------------------------------------

TEST(Zonotope, MinkowskiSumLinearMapTranslateAndOrder) {
  std::mt19937 rng(1);
  const Zonotope A = random_zonotope(3, 4, rng), B = random_zonotope(3, 2, rng);
  const Zonotope S = A + B;
  EXPECT_EQ(S.num_generators(), 6);
  EXPECT_DOUBLE_EQ(S.order(), 2.0);
  EXPECT_EIGEN_NEAR(S.center(), VectorXd(A.center() + B.center()), 0.0);
  for (int k = 0; k < 100; ++k) {
    // Support function of a Minkowski sum is additive.
    const VectorXd d = random_vector(3, rng);
    EXPECT_NEAR(S.support(d), A.support(d) + B.support(d), 1e-12 * (1 + std::abs(S.support(d))));
  }
  const MatrixXd K = random_matrix(2, 3, rng);
  const Zonotope KA = A.linear_map(K);
  EXPECT_EQ(KA.dimension(), 2);
  for (int k = 0; k < 100; ++k) {
    const VectorXd z = random_box_point(4, rng, false);
    const VectorXd image = KA.center() + KA.generators() * z;
    EXPECT_EIGEN_NEAR(image, VectorXd(K * (A.center() + A.generators() * z)), 1e-12);
  }
  const VectorXd b = random_vector(3, rng);
  EXPECT_EIGEN_NEAR(A.translate(b).center(), VectorXd(A.center() + b), 0.0);
  EXPECT_EIGEN_NEAR(A.translate(b).generators(), A.generators(), 0.0);
}

TEST(Zonotope, SupportAndIntervalHullMatchVertexEnumeration) {
  std::mt19937 rng(2);
  const Zonotope Z = random_zonotope(3, 6, rng);
  const auto verts = all_vertices(Z);
  const auto hull = Z.interval_hull();
  for (int i = 0; i < 3; ++i) {
    double mx = -1e300, mn = 1e300;
    for (const auto& v : verts) {
      mx = std::max(mx, v(i));
      mn = std::min(mn, v(i));
    }
    EXPECT_NEAR(hull.hi(i), mx, 1e-12);
    EXPECT_NEAR(hull.lo(i), mn, 1e-12);
    EXPECT_GE(hull.hi(i), mx);  // rounded outward, never inward
    EXPECT_LE(hull.lo(i), mn);
  }
  for (int k = 0; k < 50; ++k) {
    const VectorXd d = random_vector(3, rng);
    double best = -1e300;
    for (const auto& v : verts) best = std::max(best, d.dot(v));
    EXPECT_NEAR(Z.support(d), best, 1e-12 * (1 + std::abs(best)));
  }
}

TEST(Zonotope, RemoveZeroGenerators) {
  MatrixXd H(2, 4);
  H << 1, 0, 0, 2, 0, 0, 1e-20, 3;
  const Zonotope Z(VectorXd::Zero(2), H);
  EXPECT_EQ(Z.remove_zero_generators().num_generators(), 3);
  EXPECT_EQ(Z.remove_zero_generators(1e-15).num_generators(), 2);
  EXPECT_EIGEN_NEAR(Z.remove_zero_generators(1e-15).generators().col(1), Eigen::Vector2d(2, 3), 0.0);
}

// ---- volume -------------------------------------------------------------------------------

TEST(Zonotope, VolumeOfBoxesAndParallelotopes) {
  // Box p ⊕ diag(a) B^n has volume prod 2 a_i.
  const Zonotope box(VectorXd::Ones(3), Eigen::Vector3d(0.5, 2.0, 3.0).asDiagonal().toDenseMatrix());
  EXPECT_NEAR(box.volume(), 1.0 * 4.0 * 6.0, 1e-12);
  // Parallelotope: 2^n |det H|.
  std::mt19937 rng(3);
  const MatrixXd H = random_matrix(4, 4, rng);
  EXPECT_NEAR(Zonotope(VectorXd::Zero(4), H).volume(), 16.0 * std::abs(H.determinant()), 1e-10);
  // Fewer generators than dimensions: flat, volume 0.
  EXPECT_EQ(Zonotope(VectorXd::Zero(3), random_matrix(3, 2, rng)).volume(), 0.0);
}

TEST(Zonotope, VolumeMatchesPolygonAreaIn2D) {
  std::mt19937 rng(4);
  for (int m = 1; m <= 7; ++m) {
    const Zonotope Z = random_zonotope(2, m, rng);
    std::vector<Eigen::Vector2d> pts;
    for (const auto& v : all_vertices(Z)) pts.emplace_back(v(0), v(1));
    EXPECT_NEAR(Z.volume(), m < 2 ? 0.0 : hull_area(pts), 1e-10 * (1 + Z.volume())) << "m = " << m;
  }
}

TEST(Zonotope, VolumeScalesByAbsDetUnderLinearMaps) {
  std::mt19937 rng(5);
  const Zonotope Z = random_zonotope(3, 7, rng);
  for (int k = 0; k < 5; ++k) {
    const MatrixXd M = random_matrix(3, 3, rng);
    EXPECT_NEAR(Z.linear_map(M).volume(), std::abs(M.determinant()) * Z.volume(), 1e-9 * Z.volume());
  }
}

TEST(Zonotope, VolumeRefusesHugeEnumerations) {
  std::mt19937 rng(6);
  // C(60, 10) ≈ 7.5e10 > 5e6.
  const Zonotope Z = random_zonotope(10, 60, rng);
  expect_error_naming<setbound::InvalidArgumentError>([&] { Z.volume(); }, "H");
}

// ---- P-radius -----------------------------------------------------------------------------

TEST(Zonotope, PRadiusSimpleCases) {
  // Unit box in R^2, P = I: max ||s||^2 = 2.
  EXPECT_NEAR(Zonotope(VectorXd::Zero(2), MatrixXd::Identity(2, 2)).pradius(MatrixXd::Identity(2, 2)), 2.0, 1e-14);
  // H = diag(a, b), P = diag(p1, p2): p1 a^2 + p2 b^2.
  const Zonotope D(VectorXd::Ones(2), Eigen::Vector2d(3, 0.5).asDiagonal().toDenseMatrix());
  EXPECT_NEAR(D.pradius(Eigen::Vector2d(2, 7).asDiagonal().toDenseMatrix()), 2 * 9 + 7 * 0.25, 1e-13);
  // One generator g: g^T P g.
  MatrixXd g(2, 1);
  g << 1, -2;
  MatrixXd P(2, 2);
  P << 2, 1, 1, 3;
  EXPECT_NEAR(Zonotope(VectorXd::Zero(2), g).pradius(P), (g.transpose() * P * g)(0, 0), 1e-13);
  EXPECT_EQ(Zonotope(VectorXd::Zero(2), MatrixXd(2, 0)).pradius(P), 0.0);
}

TEST(Zonotope, PRadiusIsAttainedAtAVertexAndBoundsTheSet) {
  std::mt19937 rng(7);
  for (int m = 1; m <= 12; m += 3) {
    const Zonotope Z = random_zonotope(3, m, rng);
    MatrixXd A = random_matrix(3, 3, rng);
    const MatrixXd P = A * A.transpose() + 0.1 * MatrixXd::Identity(3, 3);
    const auto r = Z.pradius_with_vertex(P);
    // Brute force over all 2^m vertices.
    double best = 0;
    for (const auto& v : all_vertices(Z)) best = std::max(best, (v - Z.center()).dot(P * (v - Z.center())));
    EXPECT_NEAR(r.value, best, 1e-10 * best);
    ASSERT_EQ(r.vertex.size(), m);
    EXPECT_TRUE((r.vertex.array().abs() == 1.0).all());
    const VectorXd e = Z.generators() * r.vertex;
    EXPECT_NEAR(e.dot(P * e), r.value, 1e-12 * r.value);
    for (int k = 0; k < 200; ++k) {
      const VectorXd x = sample_in(Z, rng, false) - Z.center();
      EXPECT_LE(x.dot(P * x), r.value * (1 + 1e-12));
    }
  }
}

TEST(Zonotope, PRadiusValidation) {
  std::mt19937 rng(8);
  const Zonotope Z = random_zonotope(2, 3, rng);
  MatrixXd indef(2, 2);
  indef << 1, 2, 2, 1;
  expect_error_naming<setbound::NotPositiveDefiniteError>([&] { Z.pradius(indef); }, "P");
  expect_error_naming<setbound::DimensionError>([&] { Z.pradius(MatrixXd::Identity(3, 3)); }, "P");
  expect_error_naming<setbound::InvalidArgumentError>(
      [&] { random_zonotope(2, 25, rng).pradius(MatrixXd::Identity(2, 2)); }, "H");
}

// ---- exact membership test ----------------------------------------------------------------

TEST(Zonotope, ContainsIsExactOnSupportPointsIn2DAnd3D) {
  std::mt19937 rng(9);
  for (int n = 1; n <= 3; ++n) {
    const Zonotope Z = random_zonotope(n, n + 3, rng);
    for (int k = 0; k < 200; ++k) {
      EXPECT_TRUE(Z.contains(sample_in(Z, rng, k % 2 == 0))) << "n = " << n;
      // The maximiser of d^T x is a vertex p + H sign(H^T d); pushed out along d it must fail.
      const VectorXd d = random_vector(n, rng);
      const VectorXd s = (Z.generators().transpose() * d).array().sign().matrix();
      const VectorXd xs = Z.center() + Z.generators() * s;
      EXPECT_TRUE(Z.contains(xs));
      EXPECT_FALSE(Z.contains(xs + 1e-5 * d.normalized())) << "n = " << n;
    }
  }
}

TEST(Zonotope, ContainsHandlesFlatZonotopes) {
  // A segment in R^2 and a flat parallelogram in R^3.
  MatrixXd g(2, 2);
  g << 1, 2, 1, 2;  // both generators along (1, 1): the segment from -(3,3) to (3,3)
  const Zonotope seg(VectorXd::Zero(2), g);
  EXPECT_TRUE(seg.contains(Eigen::Vector2d(2.9, 2.9)));
  EXPECT_TRUE(seg.contains(Eigen::Vector2d(3, 3)));
  EXPECT_FALSE(seg.contains(Eigen::Vector2d(3.01, 3.01)));
  EXPECT_FALSE(seg.contains(Eigen::Vector2d(1.0, 1.01)));
  MatrixXd H(3, 2);
  H << 1, 0, 0, 1, 0, 0;  // the square [-1, 1]^2 x {0}
  const Zonotope sq(Eigen::Vector3d(0, 0, 1), H);
  EXPECT_TRUE(sq.contains(Eigen::Vector3d(0.5, -1, 1)));
  EXPECT_FALSE(sq.contains(Eigen::Vector3d(0.5, -1, 1.001)));
  EXPECT_FALSE(sq.contains(Eigen::Vector3d(1.01, 0, 1)));
  const Zonotope pt(Eigen::Vector2d(1, 2), MatrixXd(2, 0));
  EXPECT_TRUE(pt.contains(Eigen::Vector2d(1, 2)));
  EXPECT_FALSE(pt.contains(Eigen::Vector2d(1, 2.01)));
}

// ---- reduction ----------------------------------------------------------------------------

TEST(Zonotope, CombastelReductionContainsTheOriginal) {
  std::mt19937 rng(10);
  for (int trial = 0; trial < 12; ++trial) {
    const int n = 2 + trial % 3, m = 3 * n + trial;
    const Zonotope Z = random_zonotope(n, m, rng);
    for (int s = n; s < m; s += 2) {
      const Zonotope R = Z.reduce_combastel(s);
      ASSERT_EQ(R.num_generators(), s);
      EXPECT_EIGEN_NEAR(R.center(), Z.center(), 0.0);
      expect_support_dominates(R, Z, rng, 200);
      for (int k = 0; k < 100; ++k) EXPECT_TRUE(R.contains(sample_in(Z, rng, k % 2 == 0))) << n << " " << s;
      // The kept columns (first, in their original order) are the s - n longest ones (papers §0.1).
      std::vector<double> norms, kept;
      for (int j = 0; j < m; ++j) norms.push_back(Z.generators().col(j).norm());
      for (int j = 0; j < s - n; ++j) kept.push_back(R.generators().col(j).norm());
      std::sort(norms.rbegin(), norms.rend());
      std::sort(kept.rbegin(), kept.rend());
      for (int j = 0; j < s - n; ++j) EXPECT_NEAR(kept[j], norms[j], 1e-14);
    }
  }
}

TEST(Zonotope, CombastelReductionEdgeCases) {
  std::mt19937 rng(11);
  const Zonotope Z = random_zonotope(3, 8, rng);
  // s = n boxes everything: the result is the interval hull.
  const Zonotope box = Z.reduce_combastel(3);
  const auto h1 = Z.interval_hull(), h2 = box.interval_hull();
  EXPECT_EIGEN_NEAR(h1.hi, h2.hi, 1e-12);
  EXPECT_EIGEN_NEAR(h1.lo, h2.lo, 1e-12);
  // m <= s: unchanged.
  EXPECT_EIGEN_NEAR(Z.reduce_combastel(8).generators(), Z.generators(), 0.0);
  EXPECT_EIGEN_NEAR(Z.reduce_combastel(20).generators(), Z.generators(), 0.0);
  expect_error_naming<setbound::InvalidArgumentError>([&] { Z.reduce_combastel(2); }, "s");
}

TEST(Zonotope, GirardReductionContainsTheOriginal) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 12; ++trial) {
    const int n = 2 + trial % 3, m = 4 * n + trial;
    const Zonotope Z = random_zonotope(n, m, rng);
    for (double order : {1.0, 1.5, 2.0, 3.0}) {
      const Zonotope R = Z.reduce_girard(order);
      EXPECT_LE(R.num_generators(), static_cast<Eigen::Index>(std::floor(order * n)));
      expect_support_dominates(R, Z, rng, 200);
      for (int k = 0; k < 100; ++k) EXPECT_TRUE(R.contains(sample_in(Z, rng, k % 2 == 0)));
    }
  }
  // Axis-aligned generators cost nothing to box, so Girard keeps the oblique ones.
  MatrixXd H(2, 4);
  H << 1, 0, 1, 0.1, 0, 1, 1, 0;
  const Zonotope Z(VectorXd::Zero(2), H);
  const Zonotope R = Z.reduce_girard_to(3);
  ASSERT_EQ(R.num_generators(), 3);
  EXPECT_EIGEN_NEAR(R.generators().col(0), Eigen::Vector2d(1, 1), 0.0);
  EXPECT_NEAR(R.generators()(0, 1), 1.1, 1e-14);  // boxed: |1| + |0| + |0.1|
  EXPECT_NEAR(R.generators()(1, 2), 1.0, 1e-14);
  expect_error_naming<setbound::InvalidArgumentError>([&] { Z.reduce_girard(0.5); }, "order");
  expect_error_naming<setbound::InvalidArgumentError>([&] { Z.reduce_girard_to(1); }, "limit");
}

/// Σ_j |g_jᵀ d| of the generators, in long double (64-bit significand): its own rounding is
/// ~2000 times below the double-precision margins of the reductions, so comparing two such
/// sums without tolerance checks the containment of the generator parts exactly enough.
long double generator_support(const MatrixXd& H, const VectorXd& d) {
  long double s = 0.0L;
  for (Eigen::Index j = 0; j < H.cols(); ++j) {
    long double t = 0.0L;
    for (Eigen::Index i = 0; i < H.rows(); ++i) t += static_cast<long double>(H(i, j)) * d(i);
    s += t < 0 ? -t : t;
  }
  return s;
}

/// outer ⊇ inner ⊕ box(r), same centre: h_outer(d) >= h_inner(d) + |d|ᵀ r for random
/// directions, the coordinate axes and the directions of outer's last `extra` columns (the
/// replacement box, where a PCA box is tight), compared without tolerance. Columns the two
/// share bit for bit (the kept generators) add the same term to both supports and are left
/// out first, so a huge kept generator cannot hide the comparison of the boxed part.
void expect_strict_support_dominates(const Zonotope& outer, const Zonotope& inner, std::mt19937& rng,
                                     const VectorXd& r = VectorXd(), int extra = 0) {
  const int n = static_cast<int>(inner.dimension());
  ASSERT_EQ(outer.center(), inner.center());
  std::vector<bool> used(static_cast<std::size_t>(inner.num_generators()), false);
  std::vector<Eigen::Index> outer_rest;
  for (Eigen::Index j = 0; j < outer.num_generators(); ++j) {
    bool shared = false;
    for (Eigen::Index i = 0; i < inner.num_generators() && !shared; ++i)
      if (!used[static_cast<std::size_t>(i)] && inner.generators().col(i) == outer.generators().col(j))
        used[static_cast<std::size_t>(i)] = shared = true;
    if (!shared) outer_rest.push_back(j);
  }
  MatrixXd Ho(n, static_cast<Eigen::Index>(outer_rest.size())), Hi(n, 0);
  for (std::size_t j = 0; j < outer_rest.size(); ++j) Ho.col(static_cast<Eigen::Index>(j)) = outer.generators().col(outer_rest[j]);
  for (Eigen::Index i = 0; i < inner.num_generators(); ++i)
    if (!used[static_cast<std::size_t>(i)]) {
      Hi.conservativeResize(n, Hi.cols() + 1);
      Hi.col(Hi.cols() - 1) = inner.generators().col(i);
    }
  std::vector<VectorXd> dirs;
  for (int k = 0; k < 300; ++k) dirs.push_back(random_vector(n, rng));
  for (int i = 0; i < n; ++i) dirs.push_back(VectorXd::Unit(n, i));
  const Eigen::Index m = outer.num_generators();
  for (int j = 0; j < extra && j < m; ++j) {
    const VectorXd w = outer.generators().col(m - 1 - j);
    if (w.norm() > 0) dirs.push_back(w / w.norm());
  }
  for (const VectorXd& d : dirs) {
    long double hi = generator_support(Hi, d);
    for (Eigen::Index i = 0; r.size() > 0 && i < n; ++i) hi += std::abs(static_cast<long double>(d(i))) * r(i);
    const long double ho = generator_support(Ho, d);
    EXPECT_LE(hi, ho) << "direction " << d.transpose();
  }
}

/// Sampled points of `inner` are in `outer` (exact membership; skipped when the facet
/// enumeration of `outer` would be long).
void expect_samples_inside(const Zonotope& outer, const Zonotope& inner, std::mt19937& rng, int count) {
  if (setbound::detail::binomial(outer.num_generators(), outer.dimension() - 1) > 3000) return;
  for (int k = 0; k < count; ++k) EXPECT_TRUE(outer.contains(sample_in(inner, rng, k % 2 == 0)));
}

TEST(Zonotope, PcaReductionContainsTheOriginal) {
  std::mt19937 rng(21);
  for (int trial = 0; trial < 16; ++trial) {
    const int n = std::vector<int>{2, 3, 4, 6}[trial % 4], m = 3 * n + 2 * trial;
    // Mixed scales: some generators 1e4 times longer than others.
    MatrixXd H = random_matrix(n, m, rng);
    for (int j = 0; j < m; j += 3) H.col(j) *= 1e4;
    const Zonotope Z(random_vector(n, rng, 2.0), H);
    for (int s = n; s < m; s += 1 + m / 6) {
      const Zonotope R = Z.reduce_pca(s);
      ASSERT_LE(R.num_generators(), s);
      expect_strict_support_dominates(R, Z, rng, VectorXd(), n);
      expect_samples_inside(R, Z, rng, 60);
      // The kept columns are Z's columns with the largest ||g||_1 - ||g||_inf, in order.
      std::vector<std::pair<double, int>> key;
      for (int j = 0; j < m; ++j)
        key.push_back({H.col(j).cwiseAbs().sum() - H.col(j).cwiseAbs().maxCoeff(), j});
      std::sort(key.begin(), key.end(), [](auto a, auto b) { return a.first > b.first || (a.first == b.first && a.second > b.second); });
      std::vector<int> kept;
      for (int j = 0; j < s - n; ++j) kept.push_back(key[static_cast<std::size_t>(j)].second);
      std::sort(kept.begin(), kept.end());
      for (int j = 0; j < s - n; ++j) EXPECT_EQ(R.generators().col(j), H.col(kept[static_cast<std::size_t>(j)]));
    }
  }
}

TEST(Zonotope, PcaBoxIsThePrincipalComponentBox) {
  // CORA's priv_reducePCA: U from svd(cov([G, -G]')), box diag(sum|U' G|), generators U*box.
  // An independent SVD of the reduced columns gives the same box up to the order and sign of
  // the columns and the certified inflation (~1e-15 relative).
  std::mt19937 rng(22);
  for (int n : {2, 3, 5}) {
    const VectorXd scale = random_vector(n, rng).cwiseAbs() + VectorXd::Constant(n, 0.1);
    const MatrixXd Gred = scale.asDiagonal() * random_matrix(n, 4 * n, rng);  // distinct axis lengths
    const Zonotope Z(VectorXd::Zero(n), Gred);
    const Zonotope R = Z.reduce_pca(n);  // everything is reduced
    ASSERT_EQ(R.num_generators(), n);
    Eigen::JacobiSVD<MatrixXd> svd(Gred * Gred.transpose(), Eigen::ComputeFullU);
    const MatrixXd U = svd.matrixU();
    const VectorXd box = (U.transpose() * Gred).cwiseAbs().rowwise().sum();
    for (int i = 0; i < n; ++i) {  // column i of R is ±U_i box_i (descending, as CORA's svd)
      const VectorXd ref = U.col(i) * box(i);
      const VectorXd got = R.generators().col(i);
      const double err = std::min((got - ref).norm(), (got + ref).norm());
      EXPECT_LT(err, 1e-12 * box.maxCoeff()) << "n " << n << " column " << i;
      EXPECT_GE(got.norm(), ref.norm());  // never smaller than the exact box
    }
  }
}

TEST(Zonotope, PcaReductionOnDegenerateInputs) {
  std::mt19937 rng(23);
  // Repeated eigenvalues (any rotation is an eigenbasis), parallel generators (a rank-one Gram
  // matrix: the other box sides are only the certified slack) and a single huge generator.
  std::vector<MatrixXd> cases;
  cases.push_back(0.001 * MatrixXd::Identity(4, 4).replicate(1, 3));
  MatrixXd par(3, 9);
  for (int j = 0; j < 9; ++j) par.col(j) = (1.0 + j) * Eigen::Vector3d(1, -2, 0.5);
  cases.push_back(par);
  MatrixXd huge = random_matrix(3, 8, rng, 1e-3);
  huge.col(0) *= 1e9;
  cases.push_back(huge);
  for (const MatrixXd& H : cases) {
    const int n = static_cast<int>(H.rows());
    const Zonotope Z(random_vector(n, rng), H);
    for (int s = n; s < H.cols(); ++s) {
      const Zonotope R = Z.reduce_pca(s);
      ASSERT_LE(R.num_generators(), s);
      ASSERT_TRUE(R.generators().allFinite());
      expect_strict_support_dominates(R, Z, rng, VectorXd(), n);
      expect_samples_inside(R, Z, rng, 40);
    }
  }
}

TEST(Zonotope, ReductionAbsorbsAPendingBox) {
  // The estimators' rounding box B_r is absorbed by the replacement generators, uncounted.
  std::mt19937 rng(24);
  for (auto method : {setbound::ZonotopeReduction::Combastel, setbound::ZonotopeReduction::Girard,
                      setbound::ZonotopeReduction::Pca}) {
    for (int trial = 0; trial < 6; ++trial) {
      const int n = 2 + trial % 3, m = 5 * n;
      const Zonotope Z(random_vector(n, rng), random_matrix(n, m, rng));
      const VectorXd r = random_vector(n, rng).cwiseAbs() * (trial % 2 ? 1e-15 : 0.3);
      MatrixXd H = Z.generators();
      setbound::detail::ReductionWorkspace ws;
      const Eigen::Index k = setbound::detail::reduce_in_place(method, H, m, 2 * n, &r, ws);
      ASSERT_LE(k, 2 * n);
      ASSERT_EQ(ws.reduced_count, m - n);
      const Zonotope R(Z.center(), H.leftCols(k));
      expect_strict_support_dominates(R, Z, rng, r, n);
      // Nothing to reduce: H untouched and the box is not absorbed.
      MatrixXd H2 = Z.generators();
      EXPECT_EQ(setbound::detail::reduce_in_place(method, H2, m, m, &r, ws), m);
      EXPECT_EQ(ws.reduced_count, 0);
      EXPECT_EQ(H2, Z.generators());
    }
  }
}

TEST(Zonotope, GirardAndPcaReduceTiesLowerIndexFirst) {
  // MATLAB's mink (CORA's pickedGenerators): among equal keys the lower index is reduced.
  MatrixXd H(2, 5);
  H << 1, 0, 1, 0, 2,
       0, 1, 0, 1, 2;  // keys 0, 0, 0, 0, 2: two of the four axis columns must go
  const Zonotope Z(VectorXd::Zero(2), H);
  const Zonotope R = Z.reduce_girard_to(4);  // keep 2: columns 3 and 4 (ties: highest kept)
  ASSERT_EQ(R.num_generators(), 4);
  EXPECT_EQ(R.generators().col(0), H.col(3));
  EXPECT_EQ(R.generators().col(1), H.col(4));
  EXPECT_NEAR(R.generators()(0, 2), 2.0, 1e-14);  // box of columns 0, 1, 2: rs = (2, 1)
  EXPECT_NEAR(R.generators()(1, 3), 1.0, 1e-14);
}

// ---- zonotope / strip family (Property 6) -------------------------------------------------

TEST(Zonotope, StripFamilyExactCase) {
  // Z = [-1, 1]^2, S = {|x1 - 0.5| <= 0.1}, lambda = e1: the result is [0.4, 0.6] x [-1, 1],
  // exactly Z ∩ S.
  const Zonotope Z(VectorXd::Zero(2), MatrixXd::Identity(2, 2));
  const Strip S(Eigen::Vector2d(1, 0), 0.5, 0.1);
  const Zonotope R = Z.intersect_strip_family(S, Eigen::Vector2d(1, 0));
  ASSERT_EQ(R.num_generators(), 3);
  const auto h = R.interval_hull();
  EXPECT_EIGEN_NEAR(h.lo, Eigen::Vector2d(0.4, -1), 1e-14);
  EXPECT_EIGEN_NEAR(h.hi, Eigen::Vector2d(0.6, 1), 1e-14);
  // lambda = 0 gives Z back (plus a zero generator).
  const Zonotope R0 = Z.intersect_strip_family(S, VectorXd::Zero(2));
  EXPECT_EIGEN_NEAR(R0.remove_zero_generators().generators(), Z.generators(), 0.0);
}

TEST(Zonotope, StripFamilyContainsTheIntersectionForRandomLambda) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 2 + trial % 2, m = 3 + trial % 4;
    const Zonotope Z = random_zonotope(n, m, rng);
    const VectorXd c = random_vector(n, rng);
    // A strip through the zonotope: centred at the image of a random point of Z.
    const double y = c.dot(sample_in(Z, rng, false));
    const double phi = 0.05 + 0.5 * std::abs(u(rng));
    const Strip S(c, y, phi);
    const VectorXd lambda = random_vector(n, rng, trial % 3 == 0 ? 3.0 : 0.3);
    const Zonotope R = Z.intersect_strip_family(S, lambda);
    EXPECT_EQ(R.num_generators(), m + 1);
    int tested = 0;
    for (int k = 0; k < 2000 && tested < 200; ++k) {
      const VectorXd x = sample_in(Z, rng, false);
      if (!S.contains(x)) continue;
      ++tested;
      EXPECT_TRUE(R.contains(x)) << "trial " << trial;
    }
    EXPECT_GT(tested, 10);
  }
}

// ---- interval matrices (Property 4 and the §3.1 prediction) -------------------------------

TEST(Zonotope, IntervalLinearMapContainsEveryImage) {
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 2 + trial % 2, k = 2 + (trial / 2) % 2, m = 2 + trial % 3;
    const Zonotope Z = random_zonotope(n, m, rng);
    const MatrixXd mid = random_matrix(k, n, rng);
    MatrixXd rad = random_matrix(k, n, rng, 0.2).cwiseAbs();
    if (trial % 4 == 0) rad(0, 0) = 0.0;  // a certain entry
    const Zonotope R = setbound::interval_linear_map(mid, rad, Z);
    ASSERT_EQ(R.num_generators(), m + 2 * k);
    for (int s = 0; s < 200; ++s) {
      MatrixXd A(k, n);
      const bool vertex = s % 2 == 0;  // vertices of [A] and of Z are the hardest cases
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < n; ++j)
          A(i, j) = mid(i, j) + rad(i, j) * (vertex ? (u(rng) < 0 ? -1.0 : 1.0) : u(rng));
      const VectorXd x = A * sample_in(Z, rng, vertex);
      EXPECT_TRUE(R.contains(x)) << "trial " << trial;
      for (int t = 0; t < 5; ++t) {
        const VectorXd d = random_vector(k, rng);
        EXPECT_LE(d.dot(x), R.support(d) + 1e-10 * (1 + std::abs(R.support(d))));
      }
    }
  }
  // Point interval matrix (rad = 0): the exact linear image plus zero boxes.
  const Zonotope Z = random_zonotope(2, 3, rng);
  const MatrixXd A = random_matrix(2, 2, rng);
  const Zonotope R = setbound::interval_linear_map(A, MatrixXd::Zero(2, 2), Z);
  EXPECT_EIGEN_NEAR(R.remove_zero_generators().generators(), Z.linear_map(A).generators(), 1e-15);
  expect_error_naming<setbound::InvalidArgumentError>(
      [&] { setbound::interval_linear_map(A, -MatrixXd::Ones(2, 2), Z); }, "rad");
  expect_error_naming<setbound::DimensionError>(
      [&] { setbound::interval_linear_map(A, MatrixXd::Zero(2, 3), Z); }, "rad");
  expect_error_naming<setbound::DimensionError>(
      [&] { setbound::interval_linear_map(MatrixXd::Zero(2, 3), MatrixXd::Zero(2, 3), Z); }, "mid");
}

TEST(Zonotope, IntervalGeneratorInclusionProperty4) {
  // p ⊕ [M] B^m ⊆ p ⊕ [mid M, rs(rad M)] B^(m+n) for every M in [M].
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(-1, 1);
  const int n = 2, m = 4;
  const VectorXd p = random_vector(n, rng);
  const MatrixXd mid = random_matrix(n, m, rng);
  const MatrixXd rad = random_matrix(n, m, rng, 0.3).cwiseAbs();
  const Zonotope R = setbound::interval_generator_inclusion(p, mid, rad);
  ASSERT_EQ(R.num_generators(), m + n);
  for (int s = 0; s < 500; ++s) {
    MatrixXd M(n, m);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) M(i, j) = mid(i, j) + rad(i, j) * (s % 2 ? u(rng) : (u(rng) < 0 ? -1 : 1));
    EXPECT_TRUE(R.contains(p + M * random_box_point(m, rng, s % 2 == 0)));
  }
}

// ---- validation ---------------------------------------------------------------------------

TEST(Zonotope, ConstructorErrorsNameTheArgument) {
  using namespace setbound;
  expect_error_naming<DimensionError>([] { Zonotope(VectorXd::Zero(2), MatrixXd::Zero(3, 2)); }, "H");
  expect_error_naming<DimensionError>([] { Zonotope(VectorXd(), MatrixXd()); }, "p");
  VectorXd p = VectorXd::Zero(2);
  p(0) = std::nan("");
  expect_error_naming<NotFiniteError>([&] { Zonotope(p, MatrixXd::Identity(2, 2)); }, "p");
  MatrixXd H = MatrixXd::Identity(2, 2);
  H(1, 0) = std::numeric_limits<double>::infinity();
  expect_error_naming<NotFiniteError>([&] { Zonotope(VectorXd::Zero(2), H); }, "H");
  const Zonotope Z(VectorXd::Zero(2), MatrixXd::Identity(2, 2));
  expect_error_naming<DimensionError>([&] { Z.support(VectorXd::Zero(3)); }, "d");
  expect_error_naming<DimensionError>([&] { Z.linear_map(MatrixXd::Zero(2, 3)); }, "M");
  expect_error_naming<DimensionError>(
      [&] { Z.intersect_strip_family(Strip(VectorXd::Ones(3), 0, 1), VectorXd::Zero(2)); }, "c");
  expect_error_naming<DimensionError>(
      [&] { Z.intersect_strip_family(Strip(VectorXd::Ones(2), 0, 1), VectorXd::Zero(3)); }, "lambda");
}

// ---- C ABI --------------------------------------------------------------------------------

TEST(ZonotopeCApi, MatchesCxx) {
  // Row-major H (2 x 3) = [[1, 0, 2], [0, 1, -1]].
  const double p[2] = {1.0, -1.0};
  const double H[6] = {1, 0, 2, 0, 1, -1};
  MatrixXd Hm(2, 3);
  Hm << 1, 0, 2, 0, 1, -1;
  const Zonotope Z(Eigen::Vector2d(1, -1), Hm);
  ASSERT_EQ(sb_zonotope_validate(2, 3, p, H), SB_OK);

  double lo[2], hi[2];
  ASSERT_EQ(sb_zonotope_interval_hull(2, 3, p, H, lo, hi), SB_OK) << sb_last_error();
  EXPECT_NEAR(hi[0], 1 + 3, 1e-14);
  EXPECT_NEAR(lo[1], -1 - 2, 1e-14);

  double vol = 0;
  ASSERT_EQ(sb_zonotope_volume(2, 3, p, H, &vol), SB_OK);
  EXPECT_NEAR(vol, 4.0 * (1 + 1 + 2), 1e-13);  // |det| of the pairs: 1, |-1|, |0*(-1) - 2*1| = 2

  const double P[4] = {2, 0, 0, 1};
  double rad = 0, vertex[3];
  ASSERT_EQ(sb_zonotope_pradius(2, 3, p, H, P, &rad, vertex), SB_OK);
  EXPECT_NEAR(rad, Z.pradius(Eigen::Vector2d(2, 1).asDiagonal().toDenseMatrix()), 1e-13);
  const VectorXd e = Hm * Eigen::Map<VectorXd>(vertex, 3);
  EXPECT_NEAR(2 * e(0) * e(0) + e(1) * e(1), rad, 1e-13);
  ASSERT_EQ(sb_zonotope_pradius(2, 3, p, H, P, &rad, nullptr), SB_OK);

  const double dirs[4] = {1, 0, 1, 1};
  double h[2];
  ASSERT_EQ(sb_zonotope_support(2, 3, p, H, 2, dirs, h), SB_OK);
  EXPECT_NEAR(h[0], hi[0], 1e-13);
  EXPECT_NEAR(h[1], Z.support(Eigen::Vector2d(1, 1)), 1e-14);

  const double pts[4] = {1, -1, 4.5, -1};
  int inside[2] = {-1, -1};
  ASSERT_EQ(sb_zonotope_contains(2, 3, p, H, 2, pts, 1e-9, inside), SB_OK);
  EXPECT_EQ(inside[0], 1);
  EXPECT_EQ(inside[1], 0);

  // Reduction to 2 generators (= n): Combastel and Girard give the interval hull, PCA the box
  // in the principal axes, which is what Zonotope::reduce_pca computes.
  int mout = 2;
  double Hout[6];
  mout = 3;
  ASSERT_EQ(sb_zonotope_reduce(2, 3, p, H, SB_REDUCE_PCA, 2, &mout, Hout), SB_OK) << sb_last_error();
  ASSERT_EQ(mout, 2);
  EXPECT_EIGEN_NEAR(setbound::capi::ConstRowMap(Hout, 2, 2), Z.reduce_pca(2).generators(), 0.0);
  for (int method : {SB_REDUCE_COMBASTEL, SB_REDUCE_GIRARD}) {
    mout = 3;
    ASSERT_EQ(sb_zonotope_reduce(2, 3, p, H, method, 2, &mout, Hout), SB_OK) << sb_last_error();
    ASSERT_EQ(mout, 2);
    EXPECT_NEAR(Hout[0], 3.0, 1e-14);  // compact 2 x 2 row-major: diag(3, 2)
    EXPECT_EQ(Hout[1], 0.0);
    EXPECT_EQ(Hout[2], 0.0);
    EXPECT_NEAR(Hout[3], 2.0, 1e-14);
  }
  // Unchanged when m <= limit; a too-small buffer reports the needed count.
  mout = 3;
  ASSERT_EQ(sb_zonotope_reduce(2, 3, p, H, SB_REDUCE_COMBASTEL, 5, &mout, Hout), SB_OK);
  EXPECT_EQ(mout, 3);
  EXPECT_EIGEN_NEAR(setbound::capi::ConstRowMap(Hout, 2, 3), Hm, 0.0);
  mout = 1;
  EXPECT_EQ(sb_zonotope_reduce(2, 3, p, H, SB_REDUCE_COMBASTEL, 2, &mout, Hout), SB_ERR_BUFFER_TOO_SMALL);
  EXPECT_EQ(mout, 2);

  const double c[2] = {1, 0}, lam[2] = {1, 0};
  double pout[2], Hs[8];
  ASSERT_EQ(sb_zonotope_intersect_strip(2, 3, p, H, c, 0.5, 0.1, lam, pout, Hs), SB_OK);
  const Zonotope Rs = Z.intersect_strip_family(Strip(Eigen::Vector2d(1, 0), 0.5, 0.1), Eigen::Vector2d(1, 0));
  EXPECT_EIGEN_NEAR(Eigen::Map<VectorXd>(pout, 2), Rs.center(), 0.0);
  EXPECT_EIGEN_NEAR(setbound::capi::ConstRowMap(Hs, 2, 4), Rs.generators(), 0.0);

  // Interval linear map with k = 1 (a row): mid = [1, 1], rad = [0.5, 0].
  const double mid[2] = {1, 1}, radm[2] = {0.5, 0};
  double pk[1], Hk[5];
  ASSERT_EQ(sb_zonotope_interval_linear_map(1, 2, 3, mid, radm, p, H, pk, Hk), SB_OK) << sb_last_error();
  EXPECT_NEAR(pk[0], 0.0, 1e-15);
  EXPECT_NEAR(Hk[0], 1, 1e-15);
  EXPECT_NEAR(Hk[1], 1, 1e-15);
  EXPECT_NEAR(Hk[2], 1, 1e-15);
  EXPECT_NEAR(Hk[3], 0.5 * 3, 1e-14);  // rs(rad |H|) = 0.5 (1 + 0 + 2)
  EXPECT_NEAR(Hk[4], 0.5 * 1, 1e-14);  // rad |p| = 0.5 * 1
}

TEST(ZonotopeCApi, ErrorPaths) {
  const double p[2] = {1.0, -1.0};
  const double H[6] = {1, 0, 2, 0, 1, -1};
  double lo[2], hi[2], v;
  EXPECT_EQ(sb_zonotope_interval_hull(2, 3, nullptr, H, lo, hi), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(std::string(sb_last_error()), "sb_zonotope_interval_hull: p: null pointer");
  EXPECT_EQ(sb_zonotope_interval_hull(2, 3, p, nullptr, lo, hi), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_zonotope_interval_hull(2, 0, p, nullptr, lo, hi), SB_OK);  // m = 0: H may be NULL
  EXPECT_EQ(lo[0], 1.0);
  EXPECT_EQ(sb_zonotope_interval_hull(2, -1, p, H, lo, hi), SB_ERR_DIMENSION);
  EXPECT_EQ(sb_zonotope_volume(0, 3, p, H, &v), SB_ERR_DIMENSION);
  const double Hnan[6] = {1, 0, std::nan(""), 0, 1, -1};
  EXPECT_EQ(sb_zonotope_validate(2, 3, p, Hnan), SB_ERR_NOT_FINITE);
  EXPECT_EQ(std::string(sb_last_error()).rfind("sb_zonotope_validate: H: entry (0, 2)", 0), 0u) << sb_last_error();
  const double Pbad[4] = {1, 2, 2, 1};
  EXPECT_EQ(sb_zonotope_pradius(2, 3, p, H, Pbad, &v, nullptr), SB_ERR_NOT_POSITIVE_DEFINITE);
  EXPECT_EQ(sb_zonotope_pradius(2, 3, p, H, nullptr, &v, nullptr), SB_ERR_INVALID_ARGUMENT);
  int mout = 3;
  double Hout[6];
  EXPECT_EQ(sb_zonotope_reduce(2, 3, p, H, 7, 2, &mout, Hout), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("method:"), std::string::npos);
  EXPECT_EQ(sb_zonotope_reduce(2, 3, p, H, SB_REDUCE_GIRARD, 1, &mout, Hout), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("limit:"), std::string::npos);
  EXPECT_EQ(sb_zonotope_reduce(2, 3, p, H, SB_REDUCE_GIRARD, 2, nullptr, Hout), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_zonotope_reduce(2, 3, p, H, SB_REDUCE_GIRARD, 2, &mout, nullptr), SB_ERR_INVALID_ARGUMENT);
  const double c[2] = {1, 0}, lam[2] = {1, 0}, zero[2] = {0, 0};
  double pout[2], Hs[8];
  EXPECT_EQ(sb_zonotope_intersect_strip(2, 3, p, H, c, 0.5, -0.1, lam, pout, Hs), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("phi:"), std::string::npos);
  EXPECT_EQ(sb_zonotope_intersect_strip(2, 3, p, H, zero, 0.5, 0.1, lam, pout, Hs), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("c:"), std::string::npos);
  EXPECT_EQ(sb_zonotope_intersect_strip(2, 3, p, H, c, 0.5, 0.1, nullptr, pout, Hs), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("lambda:"), std::string::npos);
  const double mid[2] = {1, 1}, radneg[2] = {-0.5, 0};
  double pk[1], Hk[5];
  EXPECT_EQ(sb_zonotope_interval_linear_map(1, 2, 3, mid, radneg, p, H, pk, Hk), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(sb_last_error()).find("rad:"), std::string::npos);
  EXPECT_EQ(sb_zonotope_interval_linear_map(0, 2, 3, mid, radneg, p, H, pk, Hk), SB_ERR_DIMENSION);
  double hv[1];
  const double nandir[2] = {std::nan(""), 1};
  EXPECT_EQ(sb_zonotope_support(2, 3, p, H, 1, nandir, hv), SB_ERR_NOT_FINITE);
  int inside[1];
  EXPECT_EQ(sb_zonotope_contains(2, 3, p, H, 1, nullptr, 0.0, inside), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_zonotope_contains(2, 3, p, H, 1, p, -1.0, inside), SB_ERR_INVALID_ARGUMENT);
}

// The generator kernels (sets/generator_kernels.hpp) have fixed-size paths for n <= 8 and a
// dynamic one above: every path against Eigen's plain expressions, on the first m of more columns.
TEST(GeneratorKernels, FixedAndDynamicPathsAgreeWithEigen) {
  std::mt19937 gen(3);
  std::normal_distribution<double> nrm;
  for (int n = 1; n <= 11; ++n) {
    const Eigen::Index m = 37, cap = 45;
    Eigen::MatrixXd G(n, cap), T(n, n), W(n, cap);
    Eigen::VectorXd t(n);
    for (Eigen::Index j = 0; j < cap; ++j)
      for (int i = 0; i < n; ++i) G(i, j) = nrm(gen);
    for (int i = 0; i < n; ++i) {
      t(i) = nrm(gen);
      for (int j = 0; j < n; ++j) T(i, j) = nrm(gen);
    }
    const auto Gm = G.leftCols(m);
    const double s = setbound::detail::abs_projection_sum(G, m, t);
    const double s_ref = (Gm.transpose() * t).cwiseAbs().sum();
    EXPECT_NEAR(s, s_ref, 1e-12 * s_ref) << "n " << n;
    setbound::detail::transform_generators(T, G, W, m);
    EXPECT_LE((W.leftCols(m) - T * Gm).cwiseAbs().maxCoeff(), 1e-12 * (T.cwiseAbs() * Gm.cwiseAbs()).maxCoeff()) << "n " << n;
    Eigen::MatrixXd S;
    setbound::detail::gram(G, m, S);
    const Eigen::MatrixXd S_ref = Gm * Gm.transpose();
    EXPECT_LE((S - S_ref).cwiseAbs().maxCoeff(), 1e-12 * S_ref.cwiseAbs().maxCoeff()) << "n " << n;
  }
}

// The structured paths of the dynamic size: T·G by the non-zero diagonals of a banded T (a chain
// of tanks: tank30's A has 2), cᵀg_j reading only the rows where c is non-zero (an output that
// reads one state). Against Eigen's dense products; a T or c that is not sparse enough takes the
// dense path (the banded kernel declines it and leaves W untouched).
TEST(GeneratorKernels, BandedTransformsAndSparseNormalsAgreeWithDenseProducts) {
  namespace d = setbound::detail;
  std::mt19937 gen(13);
  std::normal_distribution<double> nrm;
  for (int n : {12, 16, 30, 40}) {  // 3 diagonals: at most n/4
    const Eigen::Index m = 301, cap = 310;
    MatrixXd G(n, cap), W = MatrixXd::Constant(n, cap, 7.0);
    for (Eigen::Index j = 0; j < cap; ++j)
      for (int i = 0; i < n; ++i) G(i, j) = nrm(gen) * (1.0 + j % 4);
    const auto Gm = G.leftCols(m);
    // Banded: the diagonal, the first sub-diagonal and one far super-diagonal (with zeros inside).
    MatrixXd T = MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) {
      T(i, i) = nrm(gen);
      if (i > 0 && i % 3 != 0) T(i, i - 1) = nrm(gen);
      if (i + 5 < n) T(i, i + 5) = nrm(gen);
    }
    ASSERT_TRUE(d::transform_generators_banded(T, G, W, m)) << "n " << n;
    const double scale = (T.cwiseAbs() * Gm.cwiseAbs()).maxCoeff();
    EXPECT_LE((W.leftCols(m) - T * Gm).cwiseAbs().maxCoeff(), 1e-14 * scale) << "n " << n;
    EXPECT_TRUE((W.rightCols(cap - m).array() == 7.0).all()) << "n " << n;  // only the first m columns
    // Through the dispatching kernel, the same.
    MatrixXd W2(n, cap);
    d::transform_generators(T, G, W2, m);
    EXPECT_EQ(W2.leftCols(m), W.leftCols(m)) << "n " << n;
    // More than n/4 diagonals: declined, W untouched.
    MatrixXd Tdense = T;
    for (int q = 1; q <= n / 4 + 1; ++q) Tdense(0, q) = 1.0 + q;
    MatrixXd W3 = MatrixXd::Constant(n, cap, 7.0);
    EXPECT_FALSE(d::transform_generators_banded(Tdense, G, W3, m)) << "n " << n;
    EXPECT_TRUE((W3.array() == 7.0).all());
    // cᵀg_j: one and two non-zeros (sparse path), then a dense normal.
    for (int nz : {1, 2, n}) {
      VectorXd c = VectorXd::Zero(n);
      for (int q = 0; q < nz; ++q) c((q * 7 + 3) % n) = nrm(gen);
      VectorXd a(m + 5);
      a.setConstant(-3.0);
      d::column_products(G, 4, m - 4, c, a.data());
      const VectorXd ref = G.middleCols(4, m - 4).transpose() * c;
      EXPECT_LE((a.head(m - 4) - ref).cwiseAbs().maxCoeff(), 1e-14 * (G.cwiseAbs().transpose() * c.cwiseAbs()).maxCoeff())
          << "n " << n << " nz " << nz;
      EXPECT_EQ(a(m - 4), -3.0);  // nothing written past count
    }
  }
}

// Negligible columns (|g_ij| <= τ w_i in every row, w the row sums) leave the matrix for the box:
// the others keep their order (and their keys theirs), the box grows by at least each absorbed
// column's |g| (so the result contains the input in every direction), and τ = 0 keeps every column.
TEST(GeneratorKernels, NegligibleColumnsJoinTheBoxAndTheRestKeepsItsOrder) {
  namespace d = setbound::detail;
  std::mt19937 gen(17);
  std::normal_distribution<double> nrm;
  for (int n : {1, 3, 6, 11}) {
    const Eigen::Index m = 60;
    MatrixXd W(n, m);
    std::vector<bool> tiny(m);
    for (Eigen::Index j = 0; j < m; ++j) {
      // Every third column is tiny in every row; every fifth tiny in all rows but one.
      const bool all = j % 3 == 1, one_big = j % 5 == 2 && !all;
      tiny[static_cast<std::size_t>(j)] = all;
      for (int i = 0; i < n; ++i) W(i, j) = nrm(gen) * (all || (one_big && i != n - 1) ? 1e-15 : 1.0);
    }
    const MatrixXd W0 = W;
    VectorXd w;
    d::compact_and_sum(W, m, w, false);
    VectorXd key(m);
    for (Eigen::Index j = 0; j < m; ++j) key(j) = static_cast<double>(j);
    VectorXd r = VectorXd::Constant(n, 1e-3);
    const VectorXd r0 = r;
    MatrixXd Wk = W;
    VectorXd rk = r;
    EXPECT_EQ(d::absorb_negligible(Wk, m, w, 0.0, rk), m);
    EXPECT_EQ(Wk, W);
    EXPECT_EQ(rk, r);
    const Eigen::Index k = d::absorb_negligible(W, m, w, 1e-12, r, key.data());
    VectorXd absorbed = VectorXd::Zero(n);
    Eigen::Index q = 0;
    for (Eigen::Index j = 0; j < m; ++j) {
      if (tiny[static_cast<std::size_t>(j)]) {
        absorbed += W0.col(j).cwiseAbs();
        continue;
      }
      ASSERT_LT(q, k) << "n " << n;
      EXPECT_EQ(W.col(q), W0.col(j)) << "n " << n << " column " << j;
      EXPECT_EQ(key(q), static_cast<double>(j)) << "n " << n;
      ++q;
    }
    EXPECT_EQ(q, k) << "n " << n;
    EXPECT_TRUE((r.array() >= (r0 + absorbed).array()).all()) << "n " << n;
    EXPECT_TRUE((r.array() <= (r0 + absorbed).array() * (1.0 + 1e-12)).all()) << "n " << n;
  }
}

// The passes of a step's end (sets/zonotope_reduction.hpp): the fused compaction + keys pass and
// the reduction's gather + row-sum pass give exactly what the separate passes give (same keys,
// so the same columns are reduced; same sums in the same order), on the fixed-size paths (n <= 8)
// and the dynamic one, with zero columns to drop; add_gram is the Gram matrix's rank update.
TEST(GeneratorKernels, FusedPassesEqualTheSeparateOnes) {
  using setbound::ZonotopeReduction;
  namespace d = setbound::detail;
  std::mt19937 gen(5);
  std::normal_distribution<double> nrm;
  for (int n = 1; n <= 11; ++n) {
    for (auto method : {ZonotopeReduction::Combastel, ZonotopeReduction::Girard, ZonotopeReduction::Pca}) {
      const Eigen::Index m = 40, limit = 2 * n + 1;  // below the ~34 non-zero columns: always reduces
      MatrixXd W(n, m + n);
      for (Eigen::Index j = 0; j < m + n; ++j)
        for (int i = 0; i < n; ++i) W(i, j) = (j % 7 == 3) ? 0.0 : nrm(gen) * (1.0 + j % 5);
      W(0, 10) = 1e-200;  // tiny but not zero: kept (its square underflows)
      // compact_sum_keys against compact_and_sum + reduction_keys.
      MatrixXd A = W, B = W;
      VectorXd wa, wb, ka, kb;
      const Eigen::Index k = d::compact_sum_keys(method, A, m, wa, ka);
      const Eigen::Index k2 = d::compact_and_sum(B, m, wb, true);
      d::reduction_keys(method, B, k2, kb);
      ASSERT_EQ(k, k2) << "n " << n;
      EXPECT_EQ(A.leftCols(k), B.leftCols(k)) << "n " << n;
      EXPECT_EQ(wa, wb) << "n " << n;
      EXPECT_EQ(ka.head(k), kb.head(k)) << "n " << n;
      // reduce_in_place with the keys given and the row sums asked for, against the plain call.
      const VectorXd r = VectorXd::Constant(n, 1e-3);
      d::ReductionWorkspace w1, w2;
      w1.key = ka;
      VectorXd wr, wc;
      MatrixXd A2 = A, B2 = B;
      const Eigen::Index ra = d::reduce_in_place(method, A2, k, limit, &r, w1, false, true, &wr);
      const Eigen::Index rb = d::reduce_in_place(method, B2, k, limit, &r, w2);
      ASSERT_EQ(ra, rb) << "n " << n;
      EXPECT_EQ(A2.leftCols(ra), B2.leftCols(rb)) << "n " << n;
      d::compact_and_sum(B2, rb, wc, false);
      EXPECT_EQ(wr, wc) << "n " << n;
      // add_gram: a rank update of a symmetric matrix.
      MatrixXd S = MatrixXd::Identity(n, n), S_ref = S;
      d::add_gram(W, 5, 9, S);
      S_ref += W.middleCols(5, 9) * W.middleCols(5, 9).transpose();
      EXPECT_LE((S - S_ref).cwiseAbs().maxCoeff(), 1e-12 * S_ref.cwiseAbs().maxCoeff()) << "n " << n;
      // finish_generators: its Gram matrix follows the box columns and the reduction, w is the
      // row sums of what it returns, and the result contains the input with the box.
      MatrixXd F = W;
      VectorXd rf = VectorXd::Constant(n, 0.5), wf;
      MatrixXd Sf = W.leftCols(m) * W.leftCols(m).transpose();
      d::ReductionWorkspace w3;
      const Eigen::Index kf = d::finish_generators(method, F, m, limit, true, 1e-6, rf, wf, w3, &Sf);
      ASSERT_LE(kf, limit);
      EXPECT_GT(w3.reduced_count, 0);
      EXPECT_TRUE(rf.isZero(0));
      VectorXd wf_ref;
      MatrixXd Fc = F;
      d::compact_and_sum(Fc, kf, wf_ref, false);
      EXPECT_EQ(wf, wf_ref) << "n " << n;
      const MatrixXd Sf_ref = F.leftCols(kf) * F.leftCols(kf).transpose();
      EXPECT_LE((Sf - Sf_ref).cwiseAbs().maxCoeff(), 1e-10 * Sf_ref.cwiseAbs().maxCoeff()) << "n " << n;
      for (int trial = 0; trial < 20; ++trial) {
        VectorXd t(n);
        for (int i = 0; i < n; ++i) t(i) = nrm(gen);
        const double before = (W.leftCols(m).transpose() * t).cwiseAbs().sum() + 0.5 * t.cwiseAbs().sum();
        const double after = (F.leftCols(kf).transpose() * t).cwiseAbs().sum();
        EXPECT_GE(after, before * (1.0 - 1e-12)) << "n " << n;
      }
    }
  }
}

// Bravo's scoring inside the passes (sets/generator_kernels.hpp, used by the VolMin-B observer):
// each pass returns the first minimiser of (σ/a_j)² h_j below 1 over |a_j| > floor, a NaN h_j
// recomputed as ‖L g_j‖² (the passes compare h_k a_b² < h_b a_k², without a division; a
// different winner is accepted only within rounding of the same score). Against a plain scan of
// the same values (σ = 0 included: the first admissible column), on the fixed-size paths
// (n <= 8) and the dynamic one: strip_candidates (a and h fresh), strip_scores (a fresh, h kept,
// some NaN) and bravo_advance (the update, then the next strip's a and winner).
TEST(GeneratorKernels, BravoPassesPickTheFirstMinimiser) {
  namespace d = setbound::detail;
  std::mt19937 gen(17);
  std::normal_distribution<double> nrm;
  auto scan = [](const Eigen::VectorXd& a, const Eigen::VectorXd& h, double sig, double floor) {
    Eigen::Index w = -1;
    double best = 1.0;
    for (Eigen::Index j = 0; j < a.size(); ++j) {
      if (!(std::abs(a(j)) > floor)) continue;
      const double s = sig / a(j), score = s * s * h(j);
      if (score < best) {
        best = score;
        w = j;
      }
    }
    return w;
  };
  // The winner from recomputed values: the plain scan's unless two scores are within rounding.
  auto expect_same_or_tied = [](Eigen::Index w, Eigen::Index w_ref, const Eigen::VectorXd& a, const Eigen::VectorXd& h,
                                double sig, int trial) {
    if (w == w_ref) return;
    ASSERT_GE(w, 0) << "trial " << trial;
    ASSERT_GE(w_ref, 0) << "trial " << trial;
    const auto score = [&](Eigen::Index j) { return std::pow(sig / a(j), 2) * h(j); };
    EXPECT_NEAR(score(w), score(w_ref), 1e-8 * score(w_ref)) << "trial " << trial;
  };
  int winners = 0, none = 0;
  for (int trial = 0; trial < 220; ++trial) {
    const int n = 1 + trial % 11;
    const Eigen::Index m = n + 3 + trial % 17;
    Eigen::MatrixXd G(n, m);
    for (Eigen::Index j = 0; j < m; ++j)
      for (int i = 0; i < n; ++i) G(i, j) = nrm(gen) * (1.0 + static_cast<double>(j % 4));
    Eigen::VectorXd c(n), cn(n);
    for (int i = 0; i < n; ++i) {
      c(i) = nrm(gen);
      cn(i) = nrm(gen);
    }
    const Eigen::MatrixXd S = G * G.transpose();
    const Eigen::LLT<Eigen::MatrixXd> llt(S);
    const Eigen::MatrixXd L = Eigen::MatrixXd(llt.matrixL()).inverse();
    // Every eleventh strip noise-free (σ = 0: every score is 0, the first admissible column wins).
    const double sig = trial % 11 == 4 ? 0.0 : std::exp(1.5 * nrm(gen));
    const double floor = trial % 3 == 0 ? 0.5 : 0.0;  // CORA's absolute threshold, exaggerated
    d::StripScoring sc;
    sc.sig = sig;
    sc.floor = floor;
    sc.L = &L;
    // Fresh pass.
    Eigen::VectorXd a(m), h(m);
    const Eigen::Index w1 = d::strip_candidates(G, m, c, L, a.data(), h.data(), sc);
    const Eigen::VectorXd a_ref = G.transpose() * c;
    const Eigen::VectorXd h_ref = (L.triangularView<Eigen::Lower>() * G).colwise().squaredNorm().transpose();
    EXPECT_LE((a - a_ref).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + a_ref.cwiseAbs().maxCoeff())) << "trial " << trial;
    EXPECT_LE((h - h_ref).cwiseAbs().maxCoeff(), 1e-10) << "trial " << trial;
    expect_same_or_tied(w1, scan(a, h, sig, floor), a, h, sig, trial);
    (w1 >= 0 ? winners : none) += 1;
    // Kept scores, a few of them NaN (recomputed when scored).
    Eigen::VectorXd h2 = h;
    for (Eigen::Index j = trial % 3; j < m; j += 3) h2(j) = std::nan("");
    Eigen::VectorXd a2(m);
    const Eigen::Index w2 = d::strip_scores(G, m, cn, a2.data(), h2.data(), sc);
    expect_same_or_tied(w2, scan(a2, h, sig, floor), a2, h, sig, trial);
    if (w2 >= 0) EXPECT_NEAR(h2(w2), h_ref(w2), 1e-10) << "trial " << trial;  // recomputed if it was NaN
    // The update with the fresh winner, then the next strip (normal cn) scored in the same pass;
    // the reference scores are fresh leverage scores of the updated columns.
    if (w1 < 0 || sig == 0.0) continue;  // (σ = 0 flattens the set: no next scores to compare)
    const Eigen::VectorXd lam = G.col(w1) / a(w1);
    const Eigen::VectorXd z = llt.solve(G.col(w1));
    Eigen::MatrixXd Gu = G;
    Eigen::VectorXd residual;
    const Eigen::MatrixXd S_next = [&] {
      Eigen::MatrixXd R = G - lam * a.transpose();
      R.col(w1) = sig * lam;
      return Eigen::MatrixXd(R * R.transpose());
    }();
    const Eigen::MatrixXd L_next = Eigen::MatrixXd(Eigen::LLT<Eigen::MatrixXd>(S_next).matrixL()).inverse();
    d::StripScoring next = sc;
    next.L = &L_next;
    Eigen::VectorXd a3 = a, h3 = h;
    const Eigen::Index w3 = d::bravo_advance(Gu, m, lam, sig, w1, z, a3.data(), h3.data(), residual, &cn, next);
    Eigen::MatrixXd R = G - lam * a.transpose();
    EXPECT_LE(residual.maxCoeff(), 1e-9 * (1.0 + G.col(w1).cwiseAbs().maxCoeff())) << "trial " << trial;
    R.col(w1) = sig * lam;
    EXPECT_LE((Gu - R).cwiseAbs().maxCoeff(), 1e-10 * (1.0 + R.cwiseAbs().maxCoeff())) << "trial " << trial;
    const Eigen::VectorXd a3_ref = R.transpose() * cn;
    const Eigen::VectorXd h3_ref = (L_next.triangularView<Eigen::Lower>() * R).colwise().squaredNorm().transpose();
    EXPECT_LE((a3 - a3_ref).cwiseAbs().maxCoeff(), 1e-9 * (1.0 + a3_ref.cwiseAbs().maxCoeff())) << "trial " << trial;
    for (Eigen::Index j = 0; j < m; ++j)
      if (!std::isnan(h3(j))) EXPECT_NEAR(h3(j), h3_ref(j), 1e-7) << "trial " << trial << " column " << j;
    expect_same_or_tied(w3, scan(a3_ref, h3_ref, sig, floor), a3_ref, h3_ref, sig, trial);
  }
  EXPECT_GE(winners, 40);  // both outcomes occur (211 and 9 with this seed)
  EXPECT_GE(none, 5);
}
