// setbound — definitions of the functions declared in setbound/sets/generator_kernels.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/sets/generator_kernels.hpp"
#include "setbound/core/config.hpp"

#include <algorithm>

namespace setbound {
namespace detail {

SETBOUND_INLINE void transform_generators(const Eigen::MatrixXd& T, const Eigen::MatrixXd& G, Eigen::MatrixXd& W,
                                          Eigen::Index m) {
  switch (T.rows()) {
    case 1: W.leftCols(m).noalias() = T(0, 0) * G.leftCols(m); return;
    case 2: return transform_generators_fixed<2>(T, G, W, m);
    case 3: return transform_generators_fixed<3>(T, G, W, m);
    case 4: return transform_generators_fixed<4>(T, G, W, m);
    case 5: return transform_generators_fixed<5>(T, G, W, m);
    case 6: return transform_generators_fixed<6>(T, G, W, m);
    case 7: return transform_generators_fixed<7>(T, G, W, m);
    case 8: return transform_generators_fixed<8>(T, G, W, m);
    default:
      if (transform_generators_banded(T, G, W, m)) return;
      W.leftCols(m).noalias() = T * G.leftCols(m);
  }
}

SETBOUND_INLINE bool transform_generators_banded(const Eigen::MatrixXd& T, const Eigen::MatrixXd& G, Eigen::MatrixXd& W,
                                                 Eigen::Index m) {
  // T by its non-zero diagonals (T(i, i + d) for the offsets d that have one), on the stack:
  // worth it when there are at most n/4 of them (a quarter of the blocked product's
  // multiplications or fewer; tank30's A, a chain of tanks, has 2). Per column each diagonal
  // is one contiguous multiply-add over the rows, which the compiler vectorises.
  constexpr Eigen::Index kMaxRows = 64, kMaxDiagonals = 16;
  const Eigen::Index n = T.rows();
  if (n > kMaxRows || T.cols() != n) return false;
  const Eigen::Index limit = std::min<Eigen::Index>(kMaxDiagonals, n / 4);
  Eigen::Index offset[kMaxDiagonals];
  Eigen::Index count = 0;
  for (Eigen::Index d = -(n - 1); d <= n - 1; ++d) {
    bool any = false;
    for (Eigen::Index i = std::max<Eigen::Index>(0, -d); i < std::min(n, n - d) && !any; ++i) any = T(i, i + d) != 0.0;
    if (!any) continue;
    if (count == limit) return false;
    offset[count++] = d;
  }
  double diag[kMaxDiagonals][kMaxRows];
  for (Eigen::Index q = 0; q < count; ++q)
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Index k = i + offset[q];
      diag[q][i] = k >= 0 && k < n ? T(i, k) : 0.0;
    }
  // Each entry sums a subset of the dense product's terms (γ_k with k <= n: the callers'
  // rounding bounds γ_n |T||G| stay valid); zeros inside a diagonal add exact zeros.
  for (Eigen::Index j = 0; j < m; ++j) {
    const double* g = G.data() + j * n;
    double* w = W.data() + j * n;
    for (Eigen::Index i = 0; i < n; ++i) w[i] = 0.0;
    for (Eigen::Index q = 0; q < count; ++q) {
      const Eigen::Index d = offset[q];
      const Eigen::Index lo = std::max<Eigen::Index>(0, -d), hi = std::min(n, n - d);
      const double* t = diag[q];
      for (Eigen::Index i = lo; i < hi; ++i) w[i] += t[i] * g[i + d];
    }
  }
  return true;
}

SETBOUND_INLINE void gram(const Eigen::MatrixXd& G, Eigen::Index m, Eigen::MatrixXd& S) {
  const Eigen::Index n = G.rows();
  switch (n) {
    case 1: S.resize(1, 1); S(0, 0) = G.row(0).head(m).squaredNorm(); return;
    case 2: return gram_fixed<2>(G, m, S);
    case 3: return gram_fixed<3>(G, m, S);
    case 4: return gram_fixed<4>(G, m, S);
    case 5: return gram_fixed<5>(G, m, S);
    case 6: return gram_fixed<6>(G, m, S);
    case 7: return gram_fixed<7>(G, m, S);
    case 8: return gram_fixed<8>(G, m, S);
    default:
      // Half the flops of G Gᵀ: the lower triangle by a rank-m update, mirrored.
      S.setZero(n, n);
      S.selfadjointView<Eigen::Lower>().rankUpdate(G.leftCols(m));
      for (Eigen::Index j = 1; j < n; ++j)
        for (Eigen::Index i = 0; i < j; ++i) S(i, j) = S(j, i);
  }
}

SETBOUND_INLINE void add_gram(const Eigen::MatrixXd& G, Eigen::Index from, Eigen::Index count, Eigen::MatrixXd& S) {
  if (count <= 0) return;
  // Eigen sends a product with more than ~20 rows + columns + depth to its blocked GEMM, whose
  // packing costs more than a few rank-1 updates (a step adds ~10 columns to a 6-state set).
  switch (G.rows()) {
    case 2: return add_gram_fixed<2>(G, from, count, S);
    case 3: return add_gram_fixed<3>(G, from, count, S);
    case 4: return add_gram_fixed<4>(G, from, count, S);
    case 5: return add_gram_fixed<5>(G, from, count, S);
    case 6: return add_gram_fixed<6>(G, from, count, S);
    case 7: return add_gram_fixed<7>(G, from, count, S);
    case 8: return add_gram_fixed<8>(G, from, count, S);
    default: S.noalias() += G.middleCols(from, count) * G.middleCols(from, count).transpose();
  }
}

SETBOUND_INLINE double abs_projection_sum(const Eigen::MatrixXd& G, Eigen::Index m,
                                          const Eigen::Ref<const Eigen::VectorXd>& t) {
  // Eigen's GEMV Gᵀt runs a dot product of length n per column with its blocking overhead:
  // for a few rows the fixed-size loop below is about 3× fewer instructions (vehicle6).
  switch (G.rows()) {
    case 1: return abs_projection_sum_fixed<1>(G, m, t);
    case 2: return abs_projection_sum_fixed<2>(G, m, t);
    case 3: return abs_projection_sum_fixed<3>(G, m, t);
    case 4: return abs_projection_sum_fixed<4>(G, m, t);
    case 5: return abs_projection_sum_fixed<5>(G, m, t);
    case 6: return abs_projection_sum_fixed<6>(G, m, t);
    case 7: return abs_projection_sum_fixed<7>(G, m, t);
    case 8: return abs_projection_sum_fixed<8>(G, m, t);
    default: {
      double s = 0.0;
      for (Eigen::Index j = 0; j < m; ++j) s += std::abs(G.col(j).dot(t));
      return s;
    }
  }
}

SETBOUND_INLINE void column_products(const Eigen::MatrixXd& G, Eigen::Index from, Eigen::Index count,
                                     const Eigen::Ref<const Eigen::VectorXd>& c, double* a) {
  // A normal with few non-zeros (an output that reads one state: tank30's C) reads those rows
  // only, instead of the whole matrix through a product.
  constexpr Eigen::Index kMaxTerms = 8;
  const Eigen::Index n = G.rows();
  Eigen::Index idx[kMaxTerms];
  double val[kMaxTerms];
  Eigen::Index nnz = 0;
  for (Eigen::Index i = 0; i < n && nnz <= kMaxTerms; ++i)
    if (c(i) != 0.0) {
      if (nnz < kMaxTerms) idx[nnz] = i, val[nnz] = c(i);
      ++nnz;
    }
  if (nnz > kMaxTerms || 4 * nnz > n) {
    Eigen::Map<Eigen::VectorXd>(a, count).noalias() = G.middleCols(from, count).transpose() * c;
    return;
  }
  const double* base = G.data() + from * n;
  for (Eigen::Index j = 0; j < count; ++j) {
    const double* g = base + j * n;
    double acc = 0.0;
    for (Eigen::Index q = 0; q < nnz; ++q) acc += val[q] * g[idx[q]];
    a[j] = acc;
  }
}

SETBOUND_INLINE Eigen::Index strip_candidates(const Eigen::MatrixXd& G, Eigen::Index m,
                                              const Eigen::Ref<const Eigen::VectorXd>& c, const Eigen::MatrixXd& L,
                                              double* a, double* h, const StripScoring& score) {
  switch (G.rows()) {
    case 1: return strip_pass_fixed<1, true>(G, m, c, &L, a, h, score);
    case 2: return strip_pass_fixed<2, true>(G, m, c, &L, a, h, score);
    case 3: return strip_pass_fixed<3, true>(G, m, c, &L, a, h, score);
    case 4: return strip_pass_fixed<4, true>(G, m, c, &L, a, h, score);
    case 5: return strip_pass_fixed<5, true>(G, m, c, &L, a, h, score);
    case 6: return strip_pass_fixed<6, true>(G, m, c, &L, a, h, score);
    case 7: return strip_pass_fixed<7, true>(G, m, c, &L, a, h, score);
    case 8: return strip_pass_fixed<8, true>(G, m, c, &L, a, h, score);
    default: break;
  }
  // Larger n (tank30: n = 30, m ≈ 3 000): with a bound of S's largest eigenvalue, the scores
  // h_j = ‖L g_j‖² (n²/2 each) are computed lazily, for the columns whose lower bound
  // ‖g_j‖²/λ_max can still win (tank30: ~6 %); later strips compute the rest when they need them.
  // Without the bound: L G through Eigen's triangular product, a column block at a time.
  if (score.lmax > 0.0) {
    column_products(G, 0, m, c, a);
    std::fill(h, h + m, std::numeric_limits<double>::quiet_NaN());
    return score_columns(score, G, m, a, h);
  }
  constexpr Eigen::Index kBlock = 256;
  Eigen::MatrixXd Z;
  for (Eigen::Index j0 = 0; j0 < m; j0 += kBlock) {
    const Eigen::Index nb = std::min(kBlock, m - j0);
    const auto Gb = G.middleCols(j0, nb);
    column_products(G, j0, nb, c, a + j0);
    Z.noalias() = L.triangularView<Eigen::Lower>() * Gb;
    Eigen::Map<Eigen::VectorXd>(h + j0, nb) = Z.colwise().squaredNorm().transpose();
  }
  return score_columns(score, G, m, a, h);
}

SETBOUND_INLINE Eigen::Index strip_scores(const Eigen::MatrixXd& G, Eigen::Index m,
                                          const Eigen::Ref<const Eigen::VectorXd>& c, double* a, double* h,
                                          const StripScoring& score) {
  switch (G.rows()) {
    case 1: return strip_pass_fixed<1, false>(G, m, c, nullptr, a, h, score);
    case 2: return strip_pass_fixed<2, false>(G, m, c, nullptr, a, h, score);
    case 3: return strip_pass_fixed<3, false>(G, m, c, nullptr, a, h, score);
    case 4: return strip_pass_fixed<4, false>(G, m, c, nullptr, a, h, score);
    case 5: return strip_pass_fixed<5, false>(G, m, c, nullptr, a, h, score);
    case 6: return strip_pass_fixed<6, false>(G, m, c, nullptr, a, h, score);
    case 7: return strip_pass_fixed<7, false>(G, m, c, nullptr, a, h, score);
    case 8: return strip_pass_fixed<8, false>(G, m, c, nullptr, a, h, score);
    default: break;
  }
  column_products(G, 0, m, c, a);
  return score_columns(score, G, m, a, h);
}

SETBOUND_INLINE Eigen::Index bravo_advance(Eigen::MatrixXd& G, Eigen::Index m, const Eigen::VectorXd& lam, double sig,
                                           Eigen::Index j, const Eigen::VectorXd& z, double* a, double* h,
                                           Eigen::VectorXd& residual, const Eigen::VectorXd* cn,
                                           const StripScoring& next) {
  switch (G.rows()) {
    case 1: return bravo_advance_fixed<1>(G, m, lam, sig, j, z, a, h, residual, cn, next);
    case 2: return bravo_advance_fixed<2>(G, m, lam, sig, j, z, a, h, residual, cn, next);
    case 3: return bravo_advance_fixed<3>(G, m, lam, sig, j, z, a, h, residual, cn, next);
    case 4: return bravo_advance_fixed<4>(G, m, lam, sig, j, z, a, h, residual, cn, next);
    case 5: return bravo_advance_fixed<5>(G, m, lam, sig, j, z, a, h, residual, cn, next);
    case 6: return bravo_advance_fixed<6>(G, m, lam, sig, j, z, a, h, residual, cn, next);
    case 7: return bravo_advance_fixed<7>(G, m, lam, sig, j, z, a, h, residual, cn, next);
    case 8: return bravo_advance_fixed<8>(G, m, lam, sig, j, z, a, h, residual, cn, next);
    default: break;
  }
  // Larger n: O(n m) products over the whole matrix (tank30: n = 30, m ≈ 3 000), instead of
  // the O(n² m) triangular product a fresh score would cost.
  Eigen::Map<Eigen::VectorXd> av(a, m), hv(h, m);
  const double ihj = 1.0 / hv(j);
  const Eigen::VectorXd e = G.leftCols(m).transpose() * z;
  G.leftCols(m).noalias() -= lam * av.transpose();
  residual = G.col(j).cwiseAbs();
  G.col(j) = sig * lam;
  for (Eigen::Index k = 0; k < m; ++k) {
    if (k == j) {
      hv(k) = 1.0;
      continue;
    }
    hv(k) = downdated_leverage(hv(k), hv(k) - e(k) * e(k) * ihj);
  }
  if (!cn) return -1;
  column_products(G, 0, m, *cn, a);
  return score_columns(next, G, m, a, h);
}

SETBOUND_INLINE Eigen::Index compact_and_sum(Eigen::MatrixXd& W, Eigen::Index m, Eigen::VectorXd& w, bool drop_zeros) {
  switch (W.rows()) {
    case 1: return compact_and_sum_fixed<1>(W, m, w, drop_zeros);
    case 2: return compact_and_sum_fixed<2>(W, m, w, drop_zeros);
    case 3: return compact_and_sum_fixed<3>(W, m, w, drop_zeros);
    case 4: return compact_and_sum_fixed<4>(W, m, w, drop_zeros);
    case 5: return compact_and_sum_fixed<5>(W, m, w, drop_zeros);
    case 6: return compact_and_sum_fixed<6>(W, m, w, drop_zeros);
    case 7: return compact_and_sum_fixed<7>(W, m, w, drop_zeros);
    case 8: return compact_and_sum_fixed<8>(W, m, w, drop_zeros);
    default: return compact_and_sum_fixed<Eigen::Dynamic>(W, m, w, drop_zeros);
  }
}

SETBOUND_INLINE Eigen::Index absorb_negligible(Eigen::MatrixXd& W, Eigen::Index m, const Eigen::VectorXd& w, double tau,
                                               Eigen::VectorXd& r, double* key) {
  const Eigen::Index n = W.rows();
  if (!(tau > 0.0) || m == 0) return m;
  double* const base = W.data();
  const double* const wd = w.data();
  Eigen::Index k = 0, absorbed = 0;
  for (Eigen::Index j = 0; j < m; ++j) {
    const double* g = base + j * n;
    Eigen::Index i = 0;  // a column is left at its first row above the limit (most at row 0)
    while (i < n && std::abs(g[i]) <= tau * wd[i]) ++i;
    if (i == n) {
      r += Eigen::Map<const Eigen::VectorXd>(g, n).cwiseAbs();
      ++absorbed;
      continue;
    }
    if (k != j) {
      std::copy(g, g + n, base + k * n);  // k < j: no overlap
      if (key) key[k] = key[j];
    }
    ++k;
  }
  // r + a sum of `absorbed` nonnegative columns, added one by one: rounded up by gamma(absorbed).
  if (absorbed > 0) r *= 1.0 + static_cast<double>(absorbed + 2) * std::numeric_limits<double>::epsilon();
  return k;
}

}  // namespace detail
}  // namespace setbound
