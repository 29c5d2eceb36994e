// Interval matrices (thesis §1.2.3, Remark 1.2, §1.2.6, §3.1 rows; papers.md §0.1: vert[M] and
// [M]N), with the C ABI sb_imatrix_* and its error paths.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "c_api_common.hpp"
#include "setbound/sets/interval_matrix.hpp"
#include "test_helpers.hpp"

using setbound::Box;
using setbound::Interval;
using setbound::IntervalMatrix;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

IntervalMatrix thesis_matrix() {  // [[ [0,1],[2,3] ],[ [1,2],[−1,4] ]]
  MatrixXd lo(2, 2), hi(2, 2);
  lo << 0, 2, 1, -1;
  hi << 1, 3, 2, 4;
  return IntervalMatrix(lo, hi);
}

struct Random {
  std::mt19937_64 rng{99};
  double u(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
  IntervalMatrix imatrix(int r, int c) {
    MatrixXd a = MatrixXd::NullaryExpr(r, c, [&] { return u(-2, 2); });
    MatrixXd b = MatrixXd::NullaryExpr(r, c, [&] { return u(-2, 2); });
    for (int i = 0; i < r; ++i)  // some certain (degenerate) entries
      for (int j = 0; j < c; ++j)
        if (u(0, 1) < 0.25) b(i, j) = a(i, j);
    return IntervalMatrix(a.cwiseMin(b), a.cwiseMax(b));
  }
  MatrixXd sample(const IntervalMatrix& M) {
    MatrixXd t = MatrixXd::NullaryExpr(M.rows(), M.cols(), [&] { return u(0, 1); });
    MatrixXd S = M.lo() + (M.hi() - M.lo()).cwiseProduct(t);
    return S.cwiseMax(M.lo()).cwiseMin(M.hi());
  }
  Box box(int n) {
    VectorXd a = VectorXd::NullaryExpr(n, [&] { return u(-3, 3); });
    VectorXd b = VectorXd::NullaryExpr(n, [&] { return u(-3, 3); });
    return Box(a.cwiseMin(b), a.cwiseMax(b));
  }
  VectorXd sample(const Box& x) {
    VectorXd t = VectorXd::NullaryExpr(x.size(), [&] { return u(0, 1); });
    VectorXd p = x.lo() + (x.hi() - x.lo()).cwiseProduct(t);
    return p.cwiseMax(x.lo()).cwiseMin(x.hi());
  }
};

/// Whether the long-double value of row i of S·p lies in [lo_i, hi_i] (the long double error
/// is far below the one-ulp outward steps of the enclosure).
bool contains_product(const VectorXd& lo, const VectorXd& hi, const MatrixXd& S,
                      const VectorXd& p) {
  for (Eigen::Index i = 0; i < S.rows(); ++i) {
    long double acc = 0, scale = 0;
    for (Eigen::Index j = 0; j < S.cols(); ++j) {
      acc += (long double)S(i, j) * (long double)p(j);
      scale += std::fabs((long double)S(i, j) * (long double)p(j));
    }
    if ((long double)lo(i) > acc + 1e-18L * scale || (long double)hi(i) < acc - 1e-18L * scale)
      return false;
  }
  return true;
}

}  // namespace

TEST(IntervalMatrixReference, Table31TimesIntervalVector) {
  const Box x(Eigen::Vector2d(1, 0), Eigen::Vector2d(2, 3));
  const Box y = thesis_matrix() * x;
  EXPECT_TRUE(y[0] == Interval(0, 11));
  EXPECT_TRUE(y[1] == Interval(-2, 16));
}

TEST(IntervalMatrixReference, Table31MidLoHiAndNorm) {
  MatrixXd lo(2, 2), hi(2, 2);
  lo << -1, 0, 2, -2;
  hi << 1, 3, 6, 0;
  const IntervalMatrix A(lo, hi);
  EXPECT_EIGEN_NEAR(A.lo(), lo, 0);
  EXPECT_EIGEN_NEAR(A.hi(), hi, 0);
  MatrixXd mid(2, 2), rad(2, 2);
  mid << 0, 1.5, 4, -1;
  rad << 1, 1.5, 2, 1;
  EXPECT_EIGEN_NEAR(A.mid(), mid, 0);
  EXPECT_EIGEN_NEAR(A.rad(), rad, 0);
  EXPECT_EIGEN_NEAR(A.width(), 2 * rad, 0);
  // ‖[A]‖ = max_i Σ_j |[a_ij]| = max(1 + 3, 6 + 2).
  EXPECT_EQ(A.norm(), 8);
  EXPECT_TRUE(A(1, 0) == Interval(2, 6));
  const IntervalMatrix B = IntervalMatrix::from_mid_rad(mid, rad);
  EXPECT_EIGEN_NEAR(B.lo(), lo, 0);
  EXPECT_EIGEN_NEAR(B.hi(), hi, 0);
  EXPECT_TRUE(A.contains(mid));
  EXPECT_FALSE(A.contains(mid + MatrixXd::Constant(2, 2, 2.5)));
  EXPECT_EQ(A.uncertain_count(), 4);
}

TEST(IntervalMatrixVertices, CountIsTwoToTheQAndEveryVertexIsACorner) {
  Random R;
  for (int trial = 0; trial < 30; ++trial) {
    const IntervalMatrix M = R.imatrix(1 + trial % 3, 1 + (trial / 3) % 3);
    const int q = M.uncertain_count();
    const auto V = M.vertices();
    ASSERT_EQ(V.size(), std::size_t(1) << q);
    std::set<std::vector<double>> distinct;
    for (const MatrixXd& v : V) {
      EXPECT_TRUE(M.contains(v));
      for (Eigen::Index i = 0; i < v.rows(); ++i)
        for (Eigen::Index j = 0; j < v.cols(); ++j)
          EXPECT_TRUE(v(i, j) == M.lo()(i, j) || v(i, j) == M.hi()(i, j));
      distinct.insert(std::vector<double>(v.data(), v.data() + v.size()));
    }
    EXPECT_EQ(distinct.size(), V.size());
  }
  // Too many uncertain entries: the limit is named.
  const IntervalMatrix big(MatrixXd::Zero(3, 7), MatrixXd::Ones(3, 7));
  try {
    big.vertices();
    FAIL();
  } catch (const setbound::InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("kMaxVertexEntries = 20"), std::string::npos);
    EXPECT_EQ(std::string(e.what()).rfind("M:", 0), 0u);
  }
  MatrixXd hi = MatrixXd::Ones(1, 2);
  hi(0, 1) = kInf;
  EXPECT_THROW(IntervalMatrix(MatrixXd::Zero(1, 2), hi).vertices(), setbound::NotFiniteError);
}

TEST(IntervalMatrixProducts, SampledProductsLieInTheEnclosures) {
  Random R;
  for (int trial = 0; trial < 200; ++trial) {
    const int p = 1 + trial % 4, n = 1 + (trial / 4) % 4, m = 1 + (trial / 16) % 3;
    const IntervalMatrix M = R.imatrix(p, n);
    const Box x = R.box(n);
    const Box y = M * x;
    VectorXd v = R.sample(x);
    const Box yv = M * v;
    MatrixXd N = MatrixXd::NullaryExpr(n, m, [&] { return R.u(-2, 2); });
    const IntervalMatrix MN = M * N;
    // [M]N has centre mid[M]N and radius rad[M]|N| (papers.md §0.1).
    EXPECT_EIGEN_NEAR(MN.mid(), M.mid() * N, 1e-13);
    EXPECT_EIGEN_NEAR(MN.rad(), M.rad() * N.cwiseAbs(), 1e-13);
    // [M][x] is the sum of interval products (Remark 1.2): check against the formula.
    for (int i = 0; i < p; ++i) {
      Interval s(0.0);
      for (int j = 0; j < n; ++j) s += M(i, j) * x[j];
      EXPECT_TRUE(y[i] == s);
    }
    for (int s = 0; s < 30; ++s) {
      const MatrixXd S = R.sample(M);
      const VectorXd pt = R.sample(x);
      ASSERT_TRUE(contains_product(y.lo(), y.hi(), S, pt)) << trial;
      ASSERT_TRUE(contains_product(yv.lo(), yv.hi(), S, v)) << trial;
      for (int c = 0; c < m; ++c)
        ASSERT_TRUE(contains_product(MN.lo().col(c), MN.hi().col(c), S, N.col(c))) << trial;
    }
    // With the vertices of [M] and of [x], the products attain the ends of [M][x] (each entry
    // appears once per row, so the interval sum is the exact hull): check tightness.
    if (M.uncertain_count() + n <= 12) {
      VectorXd lo = VectorXd::Constant(p, kInf), hi = VectorXd::Constant(p, -kInf);
      for (const MatrixXd& V : M.vertices())
        for (int b = 0; b < (1 << n); ++b) {
          VectorXd corner(n);
          for (int j = 0; j < n; ++j) corner(j) = (b >> j) & 1 ? x.hi()(j) : x.lo()(j);
          const VectorXd img = V * corner;
          lo = lo.cwiseMin(img);
          hi = hi.cwiseMax(img);
        }
      EXPECT_EIGEN_NEAR(y.lo(), lo, 1e-12);
      EXPECT_EIGEN_NEAR(y.hi(), hi, 1e-12);
    }
  }
}

TEST(IntervalMatrixValidation, BadInputsThrowNamedErrors) {
  MatrixXd lo = MatrixXd::Zero(2, 2), hi = MatrixXd::Ones(2, 2);
  hi(1, 0) = -1;
  try {
    IntervalMatrix(lo, hi, "A");
    FAIL();
  } catch (const setbound::InvalidArgumentError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("A entry (1, 0):", 0), 0u) << e.what();
  }
  hi(1, 0) = std::nan("");
  EXPECT_THROW(IntervalMatrix(lo, hi), setbound::NotFiniteError);
  EXPECT_THROW(IntervalMatrix(lo, MatrixXd::Ones(2, 3)), setbound::DimensionError);
  MatrixXd elo = lo, ehi = MatrixXd::Ones(2, 2);
  elo(0, 0) = kInf;
  ehi(0, 0) = -kInf;
  EXPECT_THROW(IntervalMatrix(elo, ehi), setbound::InvalidArgumentError);  // empty entry
  EXPECT_THROW(IntervalMatrix::from_mid_rad(lo, -MatrixXd::Ones(2, 2)),
               setbound::InvalidArgumentError);
  const IntervalMatrix M(lo, MatrixXd::Ones(2, 2));
  EXPECT_THROW(M * Box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), setbound::DimensionError);
  EXPECT_THROW(M * MatrixXd::Ones(3, 1), setbound::DimensionError);
  EXPECT_THROW(M * VectorXd::Constant(2, std::nan("")), setbound::NotFiniteError);
}

TEST(IntervalMatrixCApi, ProductsVerticesAndNorm) {
  const double Mlo[] = {0, 2, 1, -1}, Mhi[] = {1, 3, 2, 4};  // thesis matrix, row-major
  const double xlo[] = {1, 0}, xhi[] = {2, 3};
  double ylo[2], yhi[2];
  ASSERT_EQ(sb_imatrix_mul_box(2, 2, Mlo, Mhi, xlo, xhi, ylo, yhi), SB_OK) << sb_last_error();
  EXPECT_EQ(ylo[0], 0);
  EXPECT_EQ(yhi[0], 11);
  EXPECT_EQ(ylo[1], -2);
  EXPECT_EQ(yhi[1], 16);

  // [M]N with N = [[1, -1, 0], [2, 0, 1]] (2x3, row-major): centre mid[M]N, radius rad[M]|N|.
  const double N[] = {1, -1, 0, 2, 0, 1};
  double Rlo[6], Rhi[6];
  ASSERT_EQ(sb_imatrix_mul_matrix(2, 2, 3, Mlo, Mhi, N, Rlo, Rhi), SB_OK) << sb_last_error();
  const IntervalMatrix R = thesis_matrix() * (MatrixXd(2, 3) << 1, -1, 0, 2, 0, 1).finished();
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(Rlo[i * 3 + j], R.lo()(i, j));
      EXPECT_EQ(Rhi[i * 3 + j], R.hi()(i, j));
    }
  EXPECT_EQ(Rlo[0], 4);   // [0,1]·1 + [2,3]·2 = [4, 7]
  EXPECT_EQ(Rhi[0], 7);

  // Vertices: query the count with capacity 0, then fetch.
  const double Vlo[] = {0, 5, 1, 2}, Vhi[] = {1, 5, 1, 3};  // q = 2
  int count = 0;
  EXPECT_EQ(sb_imatrix_vertices(2, 2, Vlo, Vhi, &count, nullptr), SB_ERR_BUFFER_TOO_SMALL);
  EXPECT_EQ(count, 4);
  EXPECT_NE(std::string(sb_last_error()).find("count:"), std::string::npos);
  std::vector<double> out(std::size_t(count) * 4);
  ASSERT_EQ(sb_imatrix_vertices(2, 2, Vlo, Vhi, &count, out.data()), SB_OK) << sb_last_error();
  ASSERT_EQ(count, 4);
  // Entry order: uncertain entries (0,0) and (1,1); vertex v has entry k at hi iff bit k set.
  const double expect[4][4] = {{0, 5, 1, 2}, {1, 5, 1, 2}, {0, 5, 1, 3}, {1, 5, 1, 3}};
  for (int v = 0; v < 4; ++v)
    for (int k = 0; k < 4; ++k) EXPECT_EQ(out[std::size_t(v * 4 + k)], expect[v][k]);

  double norm = 0;
  ASSERT_EQ(sb_imatrix_norm(2, 2, Mlo, Mhi, &norm), SB_OK);
  EXPECT_EQ(norm, 6);  // max(1 + 3, 2 + 4)

  // Error paths.
  auto starts = [](const char* prefix) {
    return std::string(sb_last_error()).rfind(prefix, 0) == 0;
  };
  const double bad[] = {0, 2, 3, -1};  // entry (1,0): 3 > 2
  EXPECT_EQ(sb_imatrix_mul_box(2, 2, bad, Mhi, xlo, xhi, ylo, yhi), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_imatrix_mul_box: M entry (1, 0):")) << sb_last_error();
  EXPECT_EQ(sb_imatrix_mul_box(2, 2, Mlo, nullptr, xlo, xhi, ylo, yhi), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_imatrix_mul_box: M (upper bound):")) << sb_last_error();
  const double xnan[] = {std::nan(""), 0};
  EXPECT_EQ(sb_imatrix_mul_box(2, 2, Mlo, Mhi, xnan, xhi, ylo, yhi), SB_ERR_NOT_FINITE);
  EXPECT_TRUE(starts("sb_imatrix_mul_box: x component 0:")) << sb_last_error();
  const double Nnan[] = {1, 0, 0, std::nan(""), 0, 1};
  EXPECT_EQ(sb_imatrix_mul_matrix(2, 2, 3, Mlo, Mhi, Nnan, Rlo, Rhi), SB_ERR_NOT_FINITE);
  EXPECT_TRUE(starts("sb_imatrix_mul_matrix: N:")) << sb_last_error();
  EXPECT_EQ(sb_imatrix_mul_matrix(2, 2, 3, Mlo, Mhi, N, nullptr, Rhi), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_imatrix_vertices(2, 2, Vlo, Vhi, nullptr, out.data()), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_imatrix_vertices: count:")) << sb_last_error();
  std::vector<double> zlo(21, 0.0), zhi(21, 1.0);
  count = 1 << 22;
  EXPECT_EQ(sb_imatrix_vertices(3, 7, zlo.data(), zhi.data(), &count, nullptr),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(starts("sb_imatrix_vertices: M:")) << sb_last_error();
  EXPECT_EQ(sb_imatrix_norm(2, 2, Mlo, Mhi, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_imatrix_norm(-1, 2, Mlo, Mhi, &norm), SB_ERR_DIMENSION);
}
