// Constrained zonotopes and their LP engine (spec cora_observers.md §1.5, §2.17; [Scott2016]).
//
// Independent references: a brute-force LP optimum (enumeration of the basic solutions of the
// box-and-rows polytope for small sizes), an exact polygon (a 2-D zonotope's vertices clipped by
// half-planes, Sutherland–Hodgman) for hulls of intersections, and sampling for images and sums.
// The Python tests compare the same LPs with SciPy's HiGHS.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "setbound/sets/box_lp.hpp"
#include "setbound/sets/constrained_zonotope.hpp"
#include "test_helpers.hpp"

using setbound::BoxLP;
using setbound::ConstrainedZonotope;
using setbound::HalfSpace;
using setbound::Strip;
using setbound::Zonotope;
using setbound::testing::expect_error_naming;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

MatrixXd randn(int r, int c, std::mt19937& rng, double scale = 1.0) {
  return setbound::testing::random_normal(r, c, rng, scale);
}

VectorXd box_point(int m, std::mt19937& rng, bool vertex) { return setbound::testing::draw_disturbance(rng, m, vertex); }

/// max gᵀξ over {Aξ = b, ‖ξ‖∞ <= 1} by enumerating basic solutions: choose which m − rank(A)
/// variables sit at ±1, solve the rest from the rows (least squares, accepted when consistent and
/// inside the box). Exponential: only for m <= 7. Returns −inf when no basic solution exists.
double brute_force_max(const MatrixXd& A, const VectorXd& b, const VectorXd& g) {
  const int m = static_cast<int>(A.cols()), q = static_cast<int>(A.rows());
  double best = -std::numeric_limits<double>::infinity();
  for (int mask = 0; mask < (1 << m); ++mask) {       // which variables are free (basic)
    std::vector<int> freev, fixedv;
    for (int j = 0; j < m; ++j) ((mask >> j) & 1 ? freev : fixedv).push_back(j);
    if (static_cast<int>(freev.size()) > q) continue;
    for (int signs = 0; signs < (1 << fixedv.size()); ++signs) {
      VectorXd xi = VectorXd::Zero(m);
      for (size_t k = 0; k < fixedv.size(); ++k) xi(fixedv[k]) = (signs >> k) & 1 ? 1.0 : -1.0;
      VectorXd rhs = b - A * xi;
      if (!freev.empty()) {
        MatrixXd Af(q, static_cast<int>(freev.size()));
        for (size_t k = 0; k < freev.size(); ++k) Af.col(static_cast<int>(k)) = A.col(freev[k]);
        const VectorXd sol = Af.colPivHouseholderQr().solve(rhs);
        for (size_t k = 0; k < freev.size(); ++k) xi(freev[k]) = sol(static_cast<int>(k));
        rhs = b - A * xi;
      }
      if (rhs.size() && rhs.cwiseAbs().maxCoeff() > 1e-9) continue;
      if (xi.cwiseAbs().maxCoeff() > 1.0 + 1e-9) continue;
      best = std::max(best, g.dot(xi));
    }
  }
  return best;
}

using Polygon = std::vector<Eigen::Vector2d>;

/// The vertices of a 2-D zonotope in counter-clockwise order (generators sorted by angle).
Polygon zonotope_polygon(const VectorXd& c, const MatrixXd& G) {
  std::vector<Eigen::Vector2d> gens;
  for (int j = 0; j < G.cols(); ++j) {
    Eigen::Vector2d g = G.col(j);
    if (g.norm() == 0) continue;
    if (g.y() < 0 || (g.y() == 0 && g.x() < 0)) g = -g;  // upper half-plane
    gens.push_back(g);
  }
  std::sort(gens.begin(), gens.end(), [](const auto& a, const auto& b) { return std::atan2(a.y(), a.x()) < std::atan2(b.y(), b.x()); });
  Eigen::Vector2d start = c.head<2>();
  for (const auto& g : gens) start -= g;
  Polygon P{start};
  for (const auto& g : gens) P.push_back(P.back() + 2 * g);
  for (const auto& g : gens) P.push_back(P.back() - 2 * g);
  P.pop_back();
  return P;
}

/// Sutherland–Hodgman: P ∩ {x : aᵀx <= f}.
Polygon clip(const Polygon& P, const Eigen::Vector2d& a, double f) {
  Polygon out;
  for (size_t i = 0; i < P.size(); ++i) {
    const auto& p = P[i];
    const auto& q = P[(i + 1) % P.size()];
    const double sp = a.dot(p) - f, sq = a.dot(q) - f;
    if (sp <= 0) out.push_back(p);
    if ((sp < 0 && sq > 0) || (sp > 0 && sq < 0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
  }
  return out;
}

ConstrainedZonotope strip_set(const VectorXd& c, const MatrixXd& G, const std::vector<Strip>& strips) {
  ConstrainedZonotope Z(Zonotope(c, G));
  for (const auto& s : strips) Z = Z.intersect_strip(s);
  return Z;
}

/// A random zonotope c ⊕ G B (n × m) cut by `ns` random strips through one of its points, and up
/// to 60 points of the cut set (sampled ξ kept when inside every strip): the reductions' fixture.
struct CutZonotope {
  VectorXd c;
  MatrixXd G;
  std::vector<Strip> strips;
  ConstrainedZonotope Z;
  std::vector<VectorXd> points;
};

CutZonotope random_cut_zonotope(int n, int m, int ns, std::mt19937& rng) {
  CutZonotope f{randn(n, 1, rng), MatrixXd(), {}, ConstrainedZonotope(Zonotope(VectorXd::Zero(n), MatrixXd::Zero(n, 0))), {}};
  f.G = randn(n, m, rng);
  const VectorXd x0 = f.c + f.G * box_point(m, rng, false);
  for (int k = 0; k < ns; ++k) {
    const VectorXd h = randn(n, 1, rng);
    f.strips.emplace_back(h, h.dot(x0), 0.1 + 0.2 * std::abs(randn(1, 1, rng)(0)));
  }
  f.Z = strip_set(f.c, f.G, f.strips);
  for (int k = 0; k < 4000 && f.points.size() < 60; ++k) {
    const VectorXd x = f.c + f.G * box_point(m, rng, k % 3 == 0);
    bool in = true;
    for (const auto& s : f.strips) in = in && s.contains(x, 0.0);
    if (in) f.points.push_back(x);
  }
  return f;
}

}  // namespace

// ---------------------------------------------------------------- BoxLP

TEST(BoxLP, MatchesBruteForceOnRandomFeasibleLPs) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 300; ++trial) {
    const int m = 2 + trial % 6, q = trial % std::min(m, 4);
    const MatrixXd A = randn(q, m, rng);
    const VectorXd b = A * (0.8 * box_point(m, rng, false));  // feasible by construction
    BoxLP lp(A, b);
    ASSERT_EQ(lp.feasibility(), BoxLP::Feasibility::feasible) << "trial " << trial;
    for (int k = 0; k < 3; ++k) {  // three objectives on one basis (warm starts)
      const VectorXd g = randn(m, 1, rng);
      const auto res = lp.maximize(g);
      const double exact = brute_force_max(A, b, g);
      EXPECT_TRUE(res.optimal);
      EXPECT_GE(res.value, exact - 1e-12) << "certified bound below the optimum, trial " << trial;
      EXPECT_NEAR(res.value, exact, 1e-9 * (1 + std::abs(exact))) << "trial " << trial;
      EXPECT_NEAR(res.estimate, exact, 1e-9 * (1 + std::abs(exact)));
      ASSERT_EQ(res.point.size(), m);
      EXPECT_LE(res.point.cwiseAbs().maxCoeff(), 1.0 + 1e-12);
      if (q) {
        EXPECT_LE((A * res.point - b).cwiseAbs().maxCoeff(), 1e-9);
      }
    }
  }
}

// The warm-started queries (dual simplex with bound flips and perturbed costs, then the primal
// simplex on the true costs) on LPs shaped like a constrained zonotope's hull LPs: tens of rows,
// a few hundred columns, objectives ±(row of G) with many zero entries (noise and slack columns),
// which makes every dual step degenerate. Optimality is checked without trusting the solver: the
// returned point is feasible, so g·ξ* <= max <= value, and the gap must be rounding-sized.
TEST(BoxLP, WarmStartedHullQueriesAreOptimalOnLargeDegenerateLPs) {
  std::mt19937 rng(41);
  for (int trial = 0; trial < 12; ++trial) {
    const int q = 8 + 4 * (trial % 4), n = 2 + trial % 5, m = 4 * q + 20 * (trial % 3);
    MatrixXd A = randn(q, m, rng);
    // Private noise columns (one per row, zero elsewhere and zero in G), as a measurement's rows.
    MatrixXd G = randn(n, m, rng);
    for (int i = 0; i < q; ++i) {
      A.col(m - q + i).setZero();
      A(i, m - q + i) = 0.1 + 0.05 * i;
    }
    G.rightCols(q).setZero();
    const VectorXd b = A * (0.9 * box_point(m, rng, false));
    BoxLP lp(A, b);
    ASSERT_EQ(lp.feasibility(), BoxLP::Feasibility::feasible) << "trial " << trial;
    BoxLP twin(A, b);
    for (int i = 0; i < n; ++i) {
      for (double s : {1.0, -1.0}) {
        const VectorXd g = s * G.row(i).transpose();
        const auto res = lp.maximize(g);
        ASSERT_TRUE(res.optimal) << "trial " << trial;
        ASSERT_EQ(res.point.size(), m);
        EXPECT_LE(res.point.cwiseAbs().maxCoeff(), 1.0 + 1e-9) << "trial " << trial;
        EXPECT_LE((A * res.point - b).cwiseAbs().maxCoeff(), 1e-8) << "trial " << trial;
        const double scale = 1.0 + g.cwiseAbs().sum();
        EXPECT_GE(res.value, g.dot(res.point) - 1e-8 * scale) << "trial " << trial;
        EXPECT_LE(res.value - g.dot(res.point), 1e-8 * scale) << "optimality gap, trial " << trial << " i " << i;
        // Deterministic: the same queries on the same LP give the same bits.
        EXPECT_EQ(twin.maximize(g).value, res.value) << "trial " << trial;
      }
    }
  }
}

TEST(BoxLP, CertifiesEmptinessAndOnlyWithAVerifiedCertificate) {
  // ξ1 + ξ2 = 3 has no solution in the box: y = 1 gives yᵀb − ‖Aᵀy‖₁ = 3 − 2 = 1.
  BoxLP lp(MatrixXd::Constant(1, 2, 1.0), VectorXd::Constant(1, 3.0));
  EXPECT_EQ(lp.feasibility(), BoxLP::Feasibility::empty);
  const VectorXd y = lp.infeasibility_certificate();
  ASSERT_EQ(y.size(), 1);
  EXPECT_GT(y(0) * 3.0 - 2.0 * std::abs(y(0)), 0.0);
  EXPECT_GT(lp.certificate_margin(), 0.0);
  EXPECT_EQ(lp.maximize(VectorXd::Ones(2)).value, -std::numeric_limits<double>::infinity());
  // Exactly on the boundary (ξ = (1, 1)): feasible, never "empty".
  BoxLP edge(MatrixXd::Constant(1, 2, 1.0), VectorXd::Constant(1, 2.0));
  EXPECT_EQ(edge.feasibility(), BoxLP::Feasibility::feasible);
  EXPECT_NEAR(edge.maximize(VectorXd::Ones(2)).value, 2.0, 1e-12);
  // A zero row: 0 = 0 is redundant, 0 = 1 is empty with the certificate e_i.
  MatrixXd Z(2, 3);
  Z << 1, 2, 0, 0, 0, 0;
  BoxLP redundant(Z, VectorXd::Zero(2));
  EXPECT_EQ(redundant.feasibility(), BoxLP::Feasibility::feasible);
  EXPECT_NEAR(redundant.maximize(VectorXd::Unit(3, 0)).value, 1.0, 1e-12);
  VectorXd bz(2);
  bz << 0, 1;
  BoxLP contradiction(Z, bz);
  EXPECT_EQ(contradiction.feasibility(), BoxLP::Feasibility::empty);
}

TEST(BoxLP, RandomInfeasibleSystemsAreCertified) {
  std::mt19937 rng(11);
  int empty = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int m = 2 + trial % 5, q = 1 + trial % 3;
    const MatrixXd A = randn(q, m, rng);
    const VectorXd b = randn(q, 1, rng, 4.0);
    BoxLP lp(A, b);
    const auto f = lp.feasibility();
    const double reference = brute_force_max(A, b, VectorXd::Zero(m));  // −inf iff empty
    if (f == BoxLP::Feasibility::empty) {
      ++empty;
      EXPECT_EQ(reference, -std::numeric_limits<double>::infinity()) << "certified empty but feasible, trial " << trial;
      const VectorXd y = lp.infeasibility_certificate();
      EXPECT_GT(y.dot(b) - (A.transpose() * y).cwiseAbs().sum(), 0.0);
    } else {
      EXPECT_EQ(f, BoxLP::Feasibility::feasible);
      EXPECT_GT(reference, -std::numeric_limits<double>::infinity()) << "missed an empty set, trial " << trial;
    }
  }
  EXPECT_GT(empty, 20);  // the draw produces both kinds
}

TEST(BoxLP, DegenerateAndRedundantRows) {
  // Duplicated and scaled rows, and a variable that appears nowhere: still the right optimum.
  MatrixXd A(3, 4);
  A << 1, 1, 0, 0, 2, 2, 0, 0, 0, 1, -1, 0;
  VectorXd b(3);
  b << 0.5, 1.0, 0.0;
  BoxLP lp(A, b);
  ASSERT_EQ(lp.feasibility(), BoxLP::Feasibility::feasible);
  for (int k = 0; k < 4; ++k) {
    for (double s : {1.0, -1.0}) {
      const VectorXd g = s * VectorXd::Unit(4, k);
      EXPECT_NEAR(lp.maximize(g).value, brute_force_max(A, b, g), 1e-10) << "k " << k << " s " << s;
    }
  }
  // A row that pins ξ (1 variable, value 1): the single feasible point.
  BoxLP pin(MatrixXd::Constant(1, 1, 2.0), VectorXd::Constant(1, 2.0));
  EXPECT_NEAR(pin.maximize(VectorXd::Constant(1, -1.0)).value, -1.0, 1e-12);
}

TEST(BoxLP, BadInputIsNamed) {
  MatrixXd A = MatrixXd::Ones(2, 3);
  expect_error_naming<setbound::DimensionError>([&] { BoxLP(A, VectorXd::Zero(3)); }, "b");
  A(1, 1) = std::numeric_limits<double>::quiet_NaN();
  expect_error_naming<setbound::NotFiniteError>([&] { BoxLP(A, VectorXd::Zero(2)); }, "A");
  BoxLP ok(MatrixXd::Ones(1, 3), VectorXd::Zero(1));
  expect_error_naming<setbound::DimensionError>([&] { ok.maximize(VectorXd::Zero(2)); }, "g");
  expect_error_naming<setbound::NotFiniteError>([&] { ok.maximize(VectorXd::Constant(3, INFINITY)); }, "g");
}

// ---------------------------------------------------------------- ConstrainedZonotope

TEST(ConstrainedZonotope, WithoutConstraintsItIsTheZonotope) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 1 + trial % 4, m = 1 + trial % 6;
    const Zonotope z(randn(n, 1, rng, 3.0), randn(n, m, rng));
    const ConstrainedZonotope cz(z);
    const auto hz = z.interval_hull(), hc = cz.interval_hull();
    EXPECT_LE((hc.lo - hz.lo).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LE((hc.hi - hz.hi).cwiseAbs().maxCoeff(), 1e-12);
    for (int k = 0; k < 5; ++k) {
      const VectorXd d = randn(n, 1, rng);
      EXPECT_GE(cz.support(d), z.support(d) - 1e-12);
      EXPECT_NEAR(cz.support(d), z.support(d), 1e-10 * (1 + std::abs(z.support(d))));
    }
    EXPECT_FALSE(cz.is_empty());
  }
}

TEST(ConstrainedZonotope, StripIntersectionHullIsTheExactPolygonsHull) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    const VectorXd c = randn(2, 1, rng);
    const MatrixXd G = randn(2, 2 + trial % 4, rng);
    std::vector<Strip> strips;
    Polygon P = zonotope_polygon(c, G);
    const int ns = 1 + trial % 3;
    const VectorXd x = c + G * box_point(static_cast<int>(G.cols()), rng, false);  // in every strip: non-empty
    for (int k = 0; k < ns; ++k) {
      const VectorXd h = randn(2, 1, rng);
      const double phi = 0.05 + 0.3 * std::abs(randn(1, 1, rng)(0));
      strips.emplace_back(h, h.dot(x), phi);
      P = clip(P, h, h.dot(x) + phi);
      P = clip(P, -h, -h.dot(x) + phi);
    }
    const ConstrainedZonotope Z = strip_set(c, G, strips);
    EXPECT_EQ(Z.num_constraints(), ns);
    ASSERT_FALSE(P.empty());
    const auto hull = Z.interval_hull();
    // The same bounds through image_bounds (support in ±e_i on one LP basis).
    const auto ib = Z.image_bounds(MatrixXd::Identity(2, 2));
    EXPECT_LE((ib.lo - hull.lo).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
    EXPECT_LE((ib.hi - hull.hi).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
    for (int i = 0; i < 2; ++i) {
      double lo = INFINITY, hi = -INFINITY;
      for (const auto& p : P) lo = std::min(lo, p(i)), hi = std::max(hi, p(i));
      EXPECT_LE(hull.lo(i), lo + 1e-12) << "trial " << trial;  // contains the exact hull
      EXPECT_GE(hull.hi(i), hi - 1e-12) << "trial " << trial;
      EXPECT_NEAR(hull.lo(i), lo, 1e-9) << "trial " << trial;  // and is tight
      EXPECT_NEAR(hull.hi(i), hi, 1e-9) << "trial " << trial;
    }
  }
}

TEST(ConstrainedZonotope, MembershipIsExactAwayFromTheBoundary) {
  std::mt19937 rng(9);
  const VectorXd c = VectorXd::Zero(2);
  MatrixXd G(2, 3);
  G << 1, 0, 0.5, 0, 1, 0.5;
  const Strip s(Eigen::Vector2d(1, 1), 0.0, 0.3);  // |x1 + x2| <= 0.3
  const ConstrainedZonotope Z = ConstrainedZonotope(Zonotope(c, G)).intersect_strip(s);
  int inside = 0, outside = 0;
  for (int k = 0; k < 2000; ++k) {
    const VectorXd x = 2.0 * box_point(2, rng, false);
    const double t = std::abs(x(0) + x(1));
    const bool in_z = Zonotope(c, G).contains(x);  // the zonotope's own exact membership test
    const bool exact = in_z && t <= 0.3;
    const bool got = Z.contains(x);
    const bool near_boundary = std::abs(t - 0.3) < 1e-9;
    if (!near_boundary) {
      EXPECT_EQ(got, exact) << x.transpose();
    }
    (exact ? inside : outside)++;
  }
  EXPECT_GT(inside, 50);
  EXPECT_GT(outside, 500);
  // Points of the set built from its own parameters are members, vertices included.
  for (int k = 0; k < 200; ++k) {
    const VectorXd z = box_point(3, rng, k % 2 == 0);
    const VectorXd x = G * z;
    if (std::abs(x(0) + x(1)) <= 0.3) {
      EXPECT_TRUE(Z.contains(x)) << x.transpose();
    }
  }
}

TEST(ConstrainedZonotope, ImagesAndSumsContainEveryImagePoint) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 2 + trial % 3;
    const VectorXd c = randn(n, 1, rng);
    const MatrixXd G = randn(n, n + 2, rng);
    const VectorXd h = randn(n, 1, rng);
    const VectorXd xs = c + G * box_point(n + 2, rng, false);
    const ConstrainedZonotope Z = ConstrainedZonotope(Zonotope(c, G)).intersect_strip(Strip(h, h.dot(xs), 0.2));
    const MatrixXd K = randn(n, n, rng);
    const Zonotope W(randn(n, 1, rng, 0.1), randn(n, 2, rng, 0.1));
    const ConstrainedZonotope image = Z.linear_map(K).minkowski_sum(W).translate(VectorXd::Ones(n));
    EXPECT_EQ(image.num_generators(), Z.num_generators() + 2);
    const auto hull = image.interval_hull();
    for (int k = 0; k < 100; ++k) {
      // A point of Z: sample ξ until it satisfies the strip (rejection).
      VectorXd x;
      for (int tries = 0; tries < 1000; ++tries) {
        const VectorXd cand = c + G * box_point(n + 2, rng, k % 3 == 0);
        if (std::abs(h.dot(cand) - h.dot(xs)) <= 0.2) { x = cand; break; }
      }
      if (!x.size()) continue;
      const VectorXd w = W.center() + W.generators() * box_point(2, rng, k % 2 == 0);
      const VectorXd y = K * x + w + VectorXd::Ones(n);
      EXPECT_TRUE(image.contains(y)) << "trial " << trial;
      EXPECT_TRUE(((y.array() >= hull.lo.array()) && (y.array() <= hull.hi.array())).all()) << "trial " << trial;
    }
  }
}

TEST(ConstrainedZonotope, OutputSetIntersectionEqualsStripsForABoxNoise) {
  std::mt19937 rng(17);
  for (int trial = 0; trial < 30; ++trial) {
    const VectorXd c = randn(3, 1, rng);
    const MatrixXd G = randn(3, 5, rng);
    const MatrixXd C = randn(2, 3, rng);
    const VectorXd sigma = (VectorXd(2) << 0.1, 0.3).finished();
    const VectorXd x = c + G * box_point(5, rng, false);
    const VectorXd y = C * x + (VectorXd(2) << 0.05, -0.2).finished();
    const ConstrainedZonotope Z(Zonotope(c, G));
    const auto exact = Z.intersect_output(C, y, Zonotope(VectorXd::Zero(2), sigma.asDiagonal().toDenseMatrix()));
    const auto strips = Z.intersect_strip(Strip(C.row(0).transpose(), y(0), 0.1)).intersect_strip(Strip(C.row(1).transpose(), y(1), 0.3));
    const auto he = exact.interval_hull(), hs = strips.interval_hull();
    EXPECT_LE((he.lo - hs.lo).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LE((he.hi - hs.hi).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_TRUE(exact.contains(x));
    // The box noise has a generator private to each row: the rounding slack is folded into it,
    // so the exact intersection adds no column beyond V's.
    EXPECT_EQ(exact.num_generators(), 5 + 2);
  }
}

TEST(ConstrainedZonotope, DisjointIntersectionIsCertifiedEmpty) {
  const ConstrainedZonotope a = ConstrainedZonotope::from_bounds(VectorXd::Zero(2), VectorXd::Ones(2));
  const ConstrainedZonotope b = ConstrainedZonotope::from_bounds(VectorXd::Constant(2, 1.5), VectorXd::Constant(2, 2.0));
  const auto e = a.intersect(b).emptiness();
  EXPECT_TRUE(e.empty);
  EXPECT_TRUE(e.conclusive);
  EXPECT_GT(e.margin, 0.0);
  const auto hull = a.intersect(b).interval_hull();
  EXPECT_TRUE(std::isinf(hull.lo(0)) && hull.lo(0) > 0);
  EXPECT_EQ(a.intersect(b).support(VectorXd::Ones(2)), -std::numeric_limits<double>::infinity());
  // Touching boxes (a common corner) are not empty, and the corner is a member.
  const ConstrainedZonotope touch = ConstrainedZonotope::from_bounds(VectorXd::Ones(2), VectorXd::Constant(2, 2.0));
  EXPECT_FALSE(a.intersect(touch).is_empty());
  EXPECT_TRUE(a.intersect(touch).contains(VectorXd::Ones(2)));
  // A strip beside the set: empty with a certificate.
  const auto miss = a.intersect_strip(Strip(Eigen::Vector2d(1, 0), 5.0, 0.5));
  EXPECT_TRUE(miss.is_empty());
}

TEST(ConstrainedZonotope, HalfSpaceCutsExactlyWhatItShould) {
  const ConstrainedZonotope box = ConstrainedZonotope::from_bounds(VectorXd::Constant(2, -1.0), VectorXd::Ones(2));
  const auto cut = box.intersect_halfspace(HalfSpace{Eigen::Vector2d(1, 1), 0.5});  // x1 + x2 <= 0.5
  const auto h = cut.interval_hull();
  EXPECT_NEAR(h.hi(0), 1.0, 1e-12);  // (1, −0.5) is in the set
  EXPECT_NEAR(h.lo(0), -1.0, 1e-12);
  EXPECT_NEAR(cut.support(Eigen::Vector2d(1, 1)), 0.5, 1e-9);
  EXPECT_GE(cut.support(Eigen::Vector2d(1, 1)), 0.5);
  EXPECT_FALSE(cut.contains(Eigen::Vector2d(0.5, 0.5)));
  EXPECT_TRUE(cut.contains(Eigen::Vector2d(0.25, 0.25)));
  // A half-space holding the whole set changes nothing; one missing it gives the empty set.
  EXPECT_EQ(box.intersect_halfspace(HalfSpace{Eigen::Vector2d(1, 0), 3.0}).num_constraints(), 0);
  EXPECT_TRUE(box.intersect_halfspace(HalfSpace{Eigen::Vector2d(1, 0), -3.0}).is_empty());
}

TEST(ConstrainedZonotope, RoundingBoxKeepsTinyExactSetsGuaranteed) {
  // A noise-free measurement (σ = 0) pins x1 + x2 exactly; the set it leaves is a segment, and
  // rounding of the rows must not make it "empty" nor lose the true point.
  std::mt19937 rng(23);
  for (int trial = 0; trial < 200; ++trial) {
    const VectorXd c = randn(2, 1, rng);
    const MatrixXd G = randn(2, 3, rng);
    const VectorXd x = c + G * box_point(3, rng, trial % 2 == 0);
    const VectorXd h = randn(2, 1, rng);
    const auto Z = ConstrainedZonotope(Zonotope(c, G)).linear_map(1.1 * MatrixXd::Identity(2, 2))
                       .intersect_output(h.transpose(), VectorXd::Constant(1, 1.1 * h.dot(x)), Zonotope(VectorXd::Zero(1), MatrixXd::Zero(1, 1)));
    EXPECT_FALSE(Z.is_empty()) << "trial " << trial;
    EXPECT_TRUE(Z.contains(1.1 * x)) << "trial " << trial;
    EXPECT_GT(Z.rounding_radius().maxCoeff(), 0.0);
    EXPECT_LT(Z.rounding_radius().maxCoeff(), 1e-12);
  }
}

TEST(ConstrainedZonotope, ConstraintEliminationAndLimitsKeepEveryPoint) {
  std::mt19937 rng(29);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 2 + trial % 2, m = n + 3, ns = 2 + trial % 3;
    const CutZonotope f = random_cut_zonotope(n, m, ns, rng);
    const ConstrainedZonotope& Z = f.Z;
    const std::vector<VectorXd>& pts = f.points;
    const auto hz = Z.interval_hull();
    // Rescaling describes the same set: same hull (up to rounding), every point kept.
    const ConstrainedZonotope S = Z.rescale();
    const auto hs = S.interval_hull();
    EXPECT_TRUE((hs.lo.array() <= hz.lo.array() + 1e-12).all() && (hs.hi.array() >= hz.hi.array() - 1e-12).all());
    EXPECT_LE((hs.lo - hz.lo).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
    EXPECT_LE((hs.hi - hz.hi).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
    for (const auto& x : pts) EXPECT_TRUE(S.contains(x)) << "trial " << trial;
    for (int keep = ns - 1; keep >= 0; --keep) {
      const ConstrainedZonotope R = Z.eliminate_constraints(keep);
      EXPECT_LE(R.num_constraints(), keep);
      const auto hr = R.interval_hull();
      EXPECT_TRUE((hr.lo.array() <= hz.lo.array() + 1e-12).all()) << "trial " << trial << " keep " << keep;
      EXPECT_TRUE((hr.hi.array() >= hz.hi.array() - 1e-12).all()) << "trial " << trial << " keep " << keep;
      for (const auto& x : pts) EXPECT_TRUE(R.contains(x)) << "trial " << trial << " keep " << keep;
    }
    const ConstrainedZonotope L = Z.reduce_limits(n + 2, 1);
    EXPECT_LE(L.num_constraints(), 1);
    EXPECT_LE(L.num_generators(), n + 2);
    for (const auto& x : pts) EXPECT_TRUE(L.contains(x)) << "trial " << trial;
    // Rows ranked by the hull LPs' dual weights (the estimators' default) keep every point too,
    // and the weighted hull is the plain one.
    BoxLP lp(Z.constraint_matrix(), Z.constraint_vector());
    ConstrainedZonotope::HullSensitivity sens;
    const auto hw = Z.interval_hull(lp, sens);
    const VectorXd& weight = sens.row_weight;
    ASSERT_EQ(weight.size(), Z.num_constraints());
    ASSERT_EQ(sens.box_cost.size(), Z.num_generators());
    EXPECT_GE(weight.minCoeff(), 0.0);
    EXPECT_GE(sens.box_cost.minCoeff(), 0.0);
    EXPECT_EQ(hw.lo, hz.lo);
    EXPECT_EQ(hw.hi, hz.hi);
    // box_cost is what boxing a generator adds to Σ width_i⁻¹·(hull growth) with the LPs'
    // multipliers kept, so re-optimised LPs can only do better: the growth of the boxed set's hull
    // is at most the cost (up to rounding); and the boxed set keeps every point.
    const VectorXd width = hz.hi - hz.lo;
    for (Eigen::Index j = 0; j < Z.num_generators(); ++j) {
      const ConstrainedZonotope B = Z.box_generators({j});
      const auto hb = B.interval_hull();
      EXPECT_TRUE((hb.lo.array() <= hz.lo.array() + 1e-12).all() && (hb.hi.array() >= hz.hi.array() - 1e-12).all())
          << "trial " << trial << " generator " << j;
      const double growth = ((hb.hi - hb.lo - width).array() / width.array()).sum();
      EXPECT_LE(growth, sens.box_cost(j) + 1e-9) << "trial " << trial << " generator " << j;
      for (const auto& x : pts) EXPECT_TRUE(B.contains(x)) << "trial " << trial << " generator " << j;
    }
    for (int keep = ns - 1; keep >= 0; --keep) {
      const ConstrainedZonotope R = Z.eliminate_constraints(keep, weight);
      EXPECT_LE(R.num_constraints(), keep);
      const auto hr = R.interval_hull();
      EXPECT_TRUE((hr.lo.array() <= hz.lo.array() + 1e-12).all()) << "trial " << trial << " keep " << keep;
      EXPECT_TRUE((hr.hi.array() >= hz.hi.array() - 1e-12).all()) << "trial " << trial << " keep " << keep;
      for (const auto& x : pts) EXPECT_TRUE(R.contains(x)) << "trial " << trial << " keep " << keep;
    }
    for (int extra = 0; extra <= 4; extra += 2) {  // guided by the hull LPs, at several limits
      const ConstrainedZonotope LW = Z.reduce_limits(n + 1 + extra, 1, setbound::ZonotopeReduction::Girard, sens);
      EXPECT_LE(LW.num_constraints(), 1);
      EXPECT_LE(LW.num_generators(), n + 1 + extra);
      for (const auto& x : pts) EXPECT_TRUE(LW.contains(x)) << "trial " << trial << " extra " << extra;
    }
    expect_error_naming<setbound::DimensionError>([&] { Z.eliminate_constraints(0, VectorXd::Zero(ns + 1)); }, "row_weight");
    auto bad = sens;
    bad.row_weight = VectorXd::Constant(ns, NAN);
    expect_error_naming<setbound::NotFiniteError>(
        [&] { Z.reduce_limits(n + 2, 1, setbound::ZonotopeReduction::Girard, bad); }, "row_weight");
    bad = sens;
    bad.box_cost.conservativeResize(Z.num_generators() + 1);
    expect_error_naming<setbound::DimensionError>(
        [&] { Z.reduce_limits(n + 2, 1, setbound::ZonotopeReduction::Girard, bad); }, "box_cost");
    bad = sens;
    bad.duals.conservativeResize(Eigen::NoChange, 2 * n + 1);
    expect_error_naming<setbound::DimensionError>(
        [&] { Z.reduce_limits(n + 2, 1, setbound::ZonotopeReduction::Girard, bad); }, "duals");
    bad = sens;
    bad.width(0) = -1.0;
    expect_error_naming<setbound::InvalidArgumentError>(
        [&] { Z.reduce_limits(n + 2, 1, setbound::ZonotopeReduction::Girard, bad); }, "width");
    expect_error_naming<setbound::InvalidArgumentError>([&] { Z.box_generators({0, 0}); }, "which");
    expect_error_naming<setbound::InvalidArgumentError>([&] { Z.box_generators({Z.num_generators()}); }, "which");
  }
  // A row that already keeps its variable in [−1, 1] is eliminated without loss: the box
  // [−1, 1]² cut by |x1| <= 2 (no cut at all) keeps its hull exactly.
  const auto box = ConstrainedZonotope::from_bounds(VectorXd::Constant(2, -1.0), VectorXd::Ones(2));
  const auto cut = box.intersect_strip(Strip(Eigen::Vector2d(1, 0), 0.0, 2.0));
  const auto h = cut.eliminate_constraints(0).interval_hull();
  EXPECT_NEAR(h.lo(0), -1.0, 1e-12);
  EXPECT_NEAR(h.hi(0), 1.0, 1e-12);
  setbound::testing::expect_error_naming<setbound::InvalidArgumentError>([&] { cut.eliminate_constraints(-1); }, "max_constraints");
  setbound::testing::expect_error_naming<setbound::InvalidArgumentError>([&] { cut.reduce_limits(2, 1); }, "max_generators");
}

TEST(ConstrainedZonotope, AbsorbingGeneratorsIntoABasisKeepsEveryPointAndAddsNoColumn) {
  // absorb_generators (reduce_limits' default path): the absorbed columns leave, the basis columns
  // grow, only row slack may be added; every point of the set stays, support values only grow.
  std::mt19937 rng(31);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 2 + trial % 3, m = n + 6, ns = 1 + trial % 3;
    const CutZonotope f = random_cut_zonotope(n, m, ns, rng);
    const ConstrainedZonotope& Z = f.Z;
    const std::vector<Eigen::Index> basis = Z.absorbing_basis();
    ASSERT_EQ(static_cast<int>(basis.size()), n) << "trial " << trial;
    std::vector<Eigen::Index> which;
    for (Eigen::Index j = 0; j < Z.num_generators() && static_cast<int>(which.size()) < 3 + trial % 3; ++j)
      if (std::find(basis.begin(), basis.end(), j) == basis.end()) which.push_back(j);
    const ConstrainedZonotope B = Z.absorb_generators(basis, which);
    EXPECT_LE(B.num_generators(), Z.num_generators() - static_cast<Eigen::Index>(which.size()) + Z.num_constraints());
    EXPECT_EQ(B.num_constraints(), Z.num_constraints());
    for (const auto& x : f.points) EXPECT_TRUE(B.contains(x)) << "trial " << trial;
    for (int d = 0; d < 8; ++d) {
      const VectorXd dir = randn(n, 1, rng);
      EXPECT_GE(B.support(dir), Z.support(dir) - 1e-12) << "trial " << trial << " direction " << d;
    }
    // Absorbing nothing changes nothing but the basis' rounding.
    const auto h0 = Z.interval_hull(), h1 = Z.absorb_generators(basis, {}).interval_hull();
    EXPECT_LE((h1.lo - h0.lo).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LE((h1.hi - h0.hi).cwiseAbs().maxCoeff(), 1e-12);
    // Named errors: a basis of the wrong size, repeated, overlapping `which`, or dependent.
    expect_error_naming<setbound::InvalidArgumentError>(
        [&] { Z.absorb_generators(std::vector<Eigen::Index>(basis.begin(), basis.end() - 1), which); }, "basis");
    std::vector<Eigen::Index> twice = basis;
    twice.back() = twice.front();
    expect_error_naming<setbound::InvalidArgumentError>([&] { Z.absorb_generators(twice, which); }, "basis");
    expect_error_naming<setbound::InvalidArgumentError>([&] { Z.absorb_generators(basis, {basis[0]}); }, "which");
    expect_error_naming<setbound::InvalidArgumentError>([&] { Z.absorb_generators(basis, {Z.num_generators()}); }, "which");
  }
  // Two equal columns are no basis; and a set with fewer columns than n has none to offer.
  MatrixXd G2(2, 3);
  G2 << 1, 1, 0.5, 2, 2, -1;
  const auto Z2 = ConstrainedZonotope::from_parts(VectorXd::Zero(2), G2, MatrixXd(0, 3), VectorXd(0), VectorXd::Zero(2));
  expect_error_naming<setbound::InvalidArgumentError>([&] { Z2.absorb_generators({0, 1}, {2}); }, "basis");
  EXPECT_EQ(Z2.absorbing_basis().size(), 2u);
  const auto Z1 = ConstrainedZonotope::from_parts(VectorXd::Zero(2), G2.leftCols(1), MatrixXd(0, 1), VectorXd(0), VectorXd::Zero(2));
  EXPECT_TRUE(Z1.absorbing_basis().empty());
}

TEST(ConstrainedZonotope, GuidedReductionWithoutABasisBoxesOnTheAxes) {
  // Generators of rank 1 in R^2 (all along (1, 2), plus one tiny other direction would make a
  // basis; here none): absorbing_basis() has nothing to offer, so reduce_limits' guided path falls
  // back to boxing the cheapest generators on the axes. The result keeps the limits and every point.
  MatrixXd G(2, 6);
  for (int j = 0; j < 6; ++j) G.col(j) = (0.2 + 0.1 * j) * Eigen::Vector2d(1.0, 2.0);
  const VectorXd c = Eigen::Vector2d(0.3, -0.1);
  std::vector<Strip> strips{Strip(Eigen::Vector2d(1.0, 0.5), 0.2, 0.4), Strip(Eigen::Vector2d(0.3, 1.0), -0.1, 0.6)};
  const ConstrainedZonotope Z = strip_set(c, G, strips);
  ASSERT_TRUE(Z.absorbing_basis().empty());
  BoxLP lp(Z.constraint_matrix(), Z.constraint_vector());
  ConstrainedZonotope::HullSensitivity sens;
  const auto hz = Z.interval_hull(lp, sens);
  const ConstrainedZonotope R = Z.reduce_limits(4, 1, setbound::ZonotopeReduction::Girard, sens);
  EXPECT_LE(R.num_generators(), 4);
  EXPECT_LE(R.num_constraints(), 1);
  const auto hr = R.interval_hull();
  EXPECT_TRUE((hr.lo.array() <= hz.lo.array() + 1e-12).all() && (hr.hi.array() >= hz.hi.array() - 1e-12).all());
  std::mt19937 rng(5);
  int kept = 0;
  for (int k = 0; k < 4000 && kept < 60; ++k) {
    const VectorXd x = c + G * box_point(6, rng, k % 3 == 0);
    bool in = true;
    for (const auto& st : strips) in = in && st.contains(x, 0.0);
    if (!in) continue;
    ++kept;
    EXPECT_TRUE(R.contains(x));
  }
  EXPECT_GT(kept, 0);
}

TEST(ConstrainedZonotope, BadInputIsNamed) {
  expect_error_naming<setbound::DimensionError>([] { ConstrainedZonotope(VectorXd::Zero(2), MatrixXd::Zero(3, 1), MatrixXd::Zero(0, 1), VectorXd(0)); }, "G");
  expect_error_naming<setbound::DimensionError>([] { ConstrainedZonotope(VectorXd::Zero(2), MatrixXd::Zero(2, 2), MatrixXd::Zero(1, 3), VectorXd::Zero(1)); }, "A");
  expect_error_naming<setbound::DimensionError>([] { ConstrainedZonotope(VectorXd::Zero(2), MatrixXd::Zero(2, 2), MatrixXd::Zero(1, 2), VectorXd::Zero(2)); }, "b");
  expect_error_naming<setbound::NotFiniteError>([] { ConstrainedZonotope(VectorXd::Constant(2, NAN), MatrixXd::Zero(2, 2), MatrixXd::Zero(0, 2), VectorXd(0)); }, "c");
  expect_error_naming<setbound::DimensionError>([] { ConstrainedZonotope(VectorXd(0), MatrixXd::Zero(0, 2), MatrixXd::Zero(0, 2), VectorXd(0)); }, "c");
  const ConstrainedZonotope Z = ConstrainedZonotope::from_bounds(VectorXd::Zero(2), VectorXd::Ones(2));
  expect_error_naming<setbound::DimensionError>([&] { Z.linear_map(MatrixXd::Ones(2, 3)); }, "K");
  expect_error_naming<setbound::DimensionError>([&] { Z.image_bounds(MatrixXd::Ones(2, 3)); }, "K");
  expect_error_naming<setbound::DimensionError>([&] { Z.contains(VectorXd::Zero(3)); }, "x");
  expect_error_naming<setbound::NotFiniteError>([&] { Z.support(VectorXd::Constant(2, NAN)); }, "d");
  expect_error_naming<setbound::DimensionError>([&] { Z.intersect(Z, MatrixXd::Ones(3, 2)); }, "R");
  expect_error_naming<setbound::DimensionError>([&] { Z.intersect_output(MatrixXd::Ones(1, 2), VectorXd::Zero(2), Zonotope(VectorXd::Zero(1), MatrixXd::Ones(1, 1))); }, "y");
  expect_error_naming<setbound::InvalidArgumentError>([] { ConstrainedZonotope::from_bounds(VectorXd::Ones(2), VectorXd::Zero(2)); }, "lo");
}

// ---------------------------------------------------------------- one LP per estimator step

TEST(BoxLP, ExtendedLPAgreesWithAFreshOne) {
  // extend() keeps the old rows' basis and adds rows and columns (what an intersection does to a
  // constrained zonotope); every answer must be that of an LP built on the extended data.
  std::mt19937 rng(53);
  int empty = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int m0 = 2 + trial % 5, q0 = trial % std::min(m0, 3), dm = 1 + trial % 3, dq = 1 + trial % 2;
    const MatrixXd A0 = randn(q0, m0, rng);
    const VectorXd xi0 = 0.8 * box_point(m0, rng, false);
    MatrixXd A = MatrixXd::Zero(q0 + dq, m0 + dm);
    A.topLeftCorner(q0, m0) = A0;
    A.bottomRows(dq) = randn(dq, m0 + dm, rng);
    VectorXd xi(m0 + dm);
    xi << xi0, 0.8 * box_point(dm, rng, false);
    VectorXd b = A * xi;  // feasible, except every fourth trial: new rows far away
    if (trial % 4 == 3) b.tail(dq).array() += 50.0;
    BoxLP warm(A0, A0 * xi0);
    ASSERT_EQ(warm.feasibility(), BoxLP::Feasibility::feasible);
    warm.maximize(randn(m0, 1, rng));  // a basis that is not phase 1's
    warm.extend(A, b);
    BoxLP fresh(A, b);
    ASSERT_EQ(warm.feasibility(), fresh.feasibility()) << "trial " << trial;
    if (warm.feasibility() == BoxLP::Feasibility::empty) {
      ++empty;
      EXPECT_GT(warm.certificate_margin(), 0.0);
      EXPECT_EQ(warm.maximize(randn(m0 + dm, 1, rng)).value, -std::numeric_limits<double>::infinity());
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const VectorXd g = randn(m0 + dm, 1, rng);
      const double exact = m0 + dm <= 7 ? brute_force_max(A, b, g) : fresh.maximize(g).value;
      const auto res = warm.maximize(g);
      EXPECT_GE(res.value, exact - 1e-12) << "trial " << trial;
      EXPECT_NEAR(res.value, exact, 1e-9 * (1 + std::abs(exact))) << "trial " << trial;
    }
  }
  EXPECT_GE(empty, 40);
  // The old rows must stay, and be zero in the new columns.
  BoxLP lp(MatrixXd::Ones(1, 2), VectorXd::Zero(1));
  expect_error_naming<setbound::InvalidArgumentError>([&] { lp.extend(MatrixXd::Ones(1, 3), VectorXd::Zero(1)); }, "A");
  expect_error_naming<setbound::InvalidArgumentError>([&] { lp.extend(2.0 * MatrixXd::Ones(2, 2), VectorXd::Zero(2)); }, "A");
  expect_error_naming<setbound::DimensionError>([&] { lp.extend(MatrixXd::Ones(0, 2), VectorXd::Zero(0)); }, "A");
  expect_error_naming<setbound::DimensionError>([&] { lp.extend(MatrixXd::Ones(1, 2), VectorXd::Zero(2)); }, "b");
}

TEST(ConstrainedZonotope, QueriesOnAKeptLPMatchTheFreshOnesAndRedundantRowsGo) {
  std::mt19937 rng(59);
  int dropped = 0, kept = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 2 + trial % 2, m = n + 2;
    const VectorXd c = randn(n, 1, rng);
    const MatrixXd G = randn(n, m, rng);
    const VectorXd x0 = c + G * box_point(m, rng, false);
    // A cutting strip through x0, then one wider than the whole set (redundant) and a second
    // cutting one: the first and last must stay, the wide one must go.
    const VectorXd h1 = randn(n, 1, rng), h2 = randn(n, 1, rng), h3 = randn(n, 1, rng);
    const double wide = h2.cwiseAbs().dot(G.cwiseAbs().rowwise().sum()) + std::abs(h2.dot(c - x0)) + 1.0;
    const ConstrainedZonotope Z0(c, G, MatrixXd(0, m), VectorXd(0));
    const ConstrainedZonotope Z = Z0.intersect_strip(Strip(h1, h1.dot(x0), 0.05))
                                      .intersect_strip(Strip(h2, h2.dot(x0), wide))
                                      .intersect_strip(Strip(h3, h3.dot(x0), 0.05));
    // One LP extended from the first intersection's, as the estimator does.
    const ConstrainedZonotope Z1 = Z0.intersect_strip(Strip(h1, h1.dot(x0), 0.05));
    BoxLP lp(Z1.constraint_matrix(), Z1.constraint_vector());
    const auto b1 = Z1.image_bounds(h1.transpose(), lp);
    EXPECT_LE(b1.hi(0) - b1.lo(0), 0.1 + 1e-9);
    lp.extend(Z.constraint_matrix(), Z.constraint_vector());
    EXPECT_FALSE(Z.emptiness(lp).empty);
    const auto hk = Z.interval_hull(lp), hf = Z.interval_hull();
    EXPECT_LE((hk.lo - hf.lo).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
    EXPECT_LE((hk.hi - hf.hi).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
    const MatrixXd K = randn(3, n, rng);
    const auto ik = Z.image_bounds(K, lp), ifr = Z.image_bounds(K);
    EXPECT_LE((ik.lo - ifr.lo).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LE((ik.hi - ifr.hi).cwiseAbs().maxCoeff(), 1e-9);
    const ConstrainedZonotope R = Z.remove_redundant_constraints(lp);
    EXPECT_LE(R.num_constraints(), 2) << "the wide strip cuts nothing, trial " << trial;
    dropped += 3 - static_cast<int>(R.num_constraints());
    kept += static_cast<int>(R.num_constraints());
    // The same set: equal support in many directions (certified, so only rounding differs),
    // and every sampled point of Z is in R.
    for (int k = 0; k < 20; ++k) {
      const VectorXd d = randn(n, 1, rng);
      EXPECT_NEAR(R.support(d), Z.support(d), 1e-9 * (1 + std::abs(Z.support(d)))) << "trial " << trial;
    }
    for (int k = 0; k < 3000; ++k) {
      const VectorXd x = c + G * box_point(m, rng, k % 3 == 0);
      if (std::abs(h1.dot(x - x0)) <= 0.05 && std::abs(h3.dot(x - x0)) <= 0.05) EXPECT_TRUE(R.contains(x));
    }
  }
  EXPECT_GE(dropped, 40);
  EXPECT_GE(kept, 60);  // the cutting strips stay (a cutting strip's noise term reaches ±1)
  const ConstrainedZonotope Z = ConstrainedZonotope::from_bounds(VectorXd::Zero(2), VectorXd::Ones(2))
                                    .intersect_strip(Strip(Eigen::Vector2d(1, 1), 1.0, 0.1));
  BoxLP other(MatrixXd::Ones(1, 3), VectorXd::Zero(1));
  expect_error_naming<setbound::InvalidArgumentError>([&] { Z.interval_hull(other); }, "lp");
  expect_error_naming<setbound::InvalidArgumentError>([&] { Z.remove_redundant_constraints(other); }, "lp");
}
