// setbound — the generator-matrix kernels every zonotopic estimator runs once per step: the
// product T·G of a small n × n transform with the n × m generators, the Gram matrix G Gᵀ, the
// support ‖Gᵀt‖₁ of G B^m in a direction, and the pass that drops exactly-zero columns while
// summing |G| by rows. Eigen's blocked product packs its operands,
// which costs more than the product itself for a few rows; fixed-size kernels for n <= 8 keep
// the columns in registers (vehicle6: n = 6, m = 600).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>

namespace setbound {
namespace detail {

/// W.leftCols(m) = T · G.leftCols(m) (T n × n; W must have room for m columns; W ≠ G).
void transform_generators(const Eigen::MatrixXd& T, const Eigen::MatrixXd& G, Eigen::MatrixXd& W, Eigen::Index m);

/// The same product by the non-zero diagonals of a banded T (n <= 64, at most n/4 and 16
/// diagonals), without allocating; false (W untouched) when T is not that sparse.
bool transform_generators_banded(const Eigen::MatrixXd& T, const Eigen::MatrixXd& G, Eigen::MatrixXd& W,
                                 Eigen::Index m);

/// S = G.leftCols(m) G.leftCols(m)ᵀ (n × n, symmetric; the Gram matrix the gain rules use).
void gram(const Eigen::MatrixXd& G, Eigen::Index m, Eigen::MatrixXd& S);

/// S += G.middleCols(from, count) G.middleCols(from, count)ᵀ (S n × n; the rank updates of a
/// kept Gram matrix: a step's new columns, a reduction's box columns).
void add_gram(const Eigen::MatrixXd& G, Eigen::Index from, Eigen::Index count, Eigen::MatrixXd& S);

/// Σ_j |g_jᵀ t| over the first m columns of G (t of length n): the support of G B^m in the
/// direction t, in one pass without a temporary.
double abs_projection_sum(const Eigen::MatrixXd& G, Eigen::Index m, const Eigen::Ref<const Eigen::VectorXd>& t);

/// a[j] = cᵀ g_{from + j} for j < count; a normal with at most n/4 (and 8) non-zeros reads only
/// those rows.
void column_products(const Eigen::MatrixXd& G, Eigen::Index from, Eigen::Index count,
                     const Eigen::Ref<const Eigen::VectorXd>& c, double* a);

/// How a pass scores Bravo's candidates for a strip (estimators/zonotopic/observer.hpp,
/// bravo_choice): half-width sig, candidates with |cᵀg_j| > floor, score (sig / cᵀg_j)² h_j, the
/// first minimiser below 1 wins (-1: none); a NaN h_j is recomputed as ‖L g_j‖² (L lower
/// triangular, the inverse Cholesky factor of the strip's Gram matrix) when its candidate is scored.
struct StripScoring {
  double sig = 0.0;
  double floor = 0.0;
  const Eigen::MatrixXd* L = nullptr;
  /// An upper bound of the largest eigenvalue of the strip's Gram matrix S (0: none). Then a NaN
  /// h_j is only computed when its lower bound ‖g_j‖²/lmax (h_j = g_jᵀS⁻¹g_j) could win.
  double lmax = 0.0;
};

/// One pass over the first m columns of G for the strip with normal c (Bravo's candidates):
/// a_j = cᵀg_j and h_j = ‖L g_j‖² with L lower triangular (n × n; only its lower triangle is
/// read), scored as `score` says. Returns the winner.
Eigen::Index strip_candidates(const Eigen::MatrixXd& G, Eigen::Index m, const Eigen::Ref<const Eigen::VectorXd>& c,
                              const Eigen::MatrixXd& L, double* a, double* h, const StripScoring& score);

/// The same pass when the set has not changed since its scores were computed (the last strip
/// chose the set itself): a_j = cᵀg_j only, the scores h_j kept (NaN ones recomputed).
Eigen::Index strip_scores(const Eigen::MatrixXd& G, Eigen::Index m, const Eigen::Ref<const Eigen::VectorXd>& c,
                          double* a, double* h, const StripScoring& score);

/// Bravo's strip update and the next strip's candidate values in one pass over the first m
/// columns of G (estimators/zonotopic/observer.hpp, bravo_update): g_i ← g_i − λ a_i with
/// a_i = cᵀg_i given; column j is the replaced one: its computed residual's |·| goes to
/// `residual` and it becomes σλ. The leverage scores h_i = g_iᵀ S⁻¹ g_i follow without
/// S'⁻¹: h_i ← h_i − (zᵀg_i)² / h_j (z = S⁻¹g_j, g_i before the update), h_j ← 1; an h_i
/// that loses more than 8 digits to that cancellation becomes NaN (the caller recomputes it).
/// With cn (the next strip's normal, may be null): a_i ← cnᵀg_i of the updated columns, scored
/// for that strip as `next` says (the scores' L is the updated set's); returns the next strip's
/// winner (-1 without cn).
Eigen::Index bravo_advance(Eigen::MatrixXd& G, Eigen::Index m, const Eigen::VectorXd& lam, double sig, Eigen::Index j,
                           const Eigen::VectorXd& z, double* a, double* h, Eigen::VectorXd& residual,
                           const Eigen::VectorXd* cn, const StripScoring& next);

/// The running winner of a strip's candidates. Its score (σ/a_b)² h_b is kept as the pair
/// (h_b, a_b²), so a candidate wins when h_k a_b² < h_b a_k²: no division per column (the
/// start (1, σ²) is the set itself's score 1). With σ = 0 every score is 0: the first admissible
/// candidate wins and stays.
struct StripWinner {
  explicit StripWinner(double sig) : a2(sig * sig), zero(sig == 0.0) {}
  double h = 1.0, a2;
  bool zero;
  Eigen::Index index = -1;
};

/// The scoring of one candidate (a = cᵀg, h its leverage score, NaN: recompute ‖L g‖² from the
/// column g); updates the running winner.
template <int N>
inline void score_candidate(const StripScoring& sc, Eigen::Index k, double a, double* h, const double* g,
                            StripWinner& w) {
  if (!(std::abs(a) > sc.floor) || (w.zero && w.index >= 0)) return;
  double hk = h[k];
  const double a2 = a * a;
  if (std::isnan(hk)) {
    const Eigen::Index n = N == Eigen::Dynamic ? sc.L->rows() : N;
    const Eigen::Map<const Eigen::VectorXd> gk(g, n);
    // h_k >= ‖g_k‖²/λ_max(S): a column that cannot beat the winner keeps its NaN (the margin
    // covers the rounding of both sides, so the winner is the one a computed h would give).
    if (sc.lmax > 0.0 && gk.squaredNorm() / sc.lmax * (1.0 - 1e-9) * w.a2 >= w.h * a2) return;
    hk = (sc.L->triangularView<Eigen::Lower>() * gk).squaredNorm();
    h[k] = hk;
  }
  if (hk * w.a2 < w.h * a2) {
    w.h = hk;
    w.a2 = a2;
    w.index = k;
  }
}

/// Every column of G.leftCols(m) scored with its a_k = a[k] (the dynamic-n passes, after their
/// products); returns the winner.
inline Eigen::Index score_columns(const StripScoring& sc, const Eigen::MatrixXd& G, Eigen::Index m, const double* a,
                                  double* h) {
  StripWinner winner(sc.sig);
  for (Eigen::Index k = 0; k < m; ++k) score_candidate<Eigen::Dynamic>(sc, k, a[k], h, G.col(k).data(), winner);
  return winner.index;
}

/// A leverage score after a rank-one downdate: h_new = h_old − (zᵀg)²/h_j, kept when it keeps
/// more than 8 of h_old's digits, NaN otherwise (the candidate's scoring then recomputes it).
inline double downdated_leverage(double h_old, double h_new) {
  return h_new > 1e-8 * h_old ? h_new : std::numeric_limits<double>::quiet_NaN();
}

/// Removes exactly-zero columns among the first m of W (keeping the order) when `drop_zeros`,
/// and sets w = rs|W| over the kept columns, rounded up (a bound of the computed sums). Returns
/// the kept column count.
Eigen::Index compact_and_sum(Eigen::MatrixXd& W, Eigen::Index m, Eigen::VectorXd& w, bool drop_zeros = true);

/// Moves the negligible columns among the first m of W into the box r and removes them (keeping
/// the order of the others, and of key's entries alongside when key is given): a column is
/// negligible when |g_ij| <= tau w_i in every row i, w >= rs|W| (compact_and_sum's). The box
/// grows by their |g_j| summed and rounded up, so the set only grows (an outer bound); w stays a
/// bound of the kept columns' row sums. Returns the kept column count. The Gram matrix of the
/// set loses at most m tau² w wᵀ: far below the rounding of a carried G Gᵀ for tau <= 1e-9.
Eigen::Index absorb_negligible(Eigen::MatrixXd& W, Eigen::Index m, const Eigen::VectorXd& w, double tau,
                               Eigen::VectorXd& r, double* key = nullptr);

template <int N>
void transform_generators_fixed(const Eigen::MatrixXd& T, const Eigen::MatrixXd& G, Eigen::MatrixXd& W, Eigen::Index m) {
  const Eigen::Matrix<double, N, N> Tf = T;
  Eigen::Map<const Eigen::Matrix<double, N, Eigen::Dynamic>> Gm(G.data(), N, m);
  Eigen::Map<Eigen::Matrix<double, N, Eigen::Dynamic>> Wm(W.data(), N, m);
  Wm.noalias() = Tf.lazyProduct(Gm);
}

template <int N>
Eigen::Matrix<double, N, N> gram_of_columns(const double* base, Eigen::Index count) {
  // Column by column (rank-1 updates of a register-sized matrix): the row-times-row form of
  // Gm Gmᵀ reads the columns with a stride of N and was 3× slower.
  using Col = Eigen::Matrix<double, N, 1>;
  Eigen::Matrix<double, N, N> Sf = Eigen::Matrix<double, N, N>::Zero();
  for (Eigen::Index j = 0; j < count; ++j) {
    const Eigen::Map<const Col> g(base + j * N);
    Sf.noalias() += g * g.transpose();
  }
  return Sf;
}

template <int N>
void gram_fixed(const Eigen::MatrixXd& G, Eigen::Index m, Eigen::MatrixXd& S) {
  S = gram_of_columns<N>(G.data(), m);
}

template <int N>
void add_gram_fixed(const Eigen::MatrixXd& G, Eigen::Index from, Eigen::Index count, Eigen::MatrixXd& S) {
  S += gram_of_columns<N>(G.data() + from * N, count);
}

template <int N>
double abs_projection_sum_fixed(const Eigen::MatrixXd& G, Eigen::Index m, const Eigen::Ref<const Eigen::VectorXd>& t) {
  using Col = Eigen::Matrix<double, N, 1>;
  const Eigen::Index n = G.rows();
  const Col tf = t;
  const double* const base = G.data();
  double s = 0.0;
  for (Eigen::Index j = 0; j < m; ++j) s += std::abs(Eigen::Map<const Col>(base + j * n, n).dot(tf));
  return s;
}

#if defined(__GNUC__)
// Two columns at once, one per lane of a GCC/Clang vector (SSE2 on x86-64, NEON on arm64): each
// lane does the scalar loop's operations in the scalar loop's order, so the values are the scalar
// loop's, bit for bit, while the per-column dot products (serial sums) run two at a time.
#define SETBOUND_COLUMN_PAIRS 1
typedef double ColumnPair __attribute__((vector_size(16)));
#endif

/// Σ_i coef_i g_i in the order i = 0 … N−1: one column (V = double) or two (V = ColumnPair).
template <int N, class V>
inline V column_dot(const V* coef, const V* g) {
  V s = V();
  for (int i = 0; i < N; ++i) s += coef[i] * g[i];
  return s;
}

/// ‖L g‖² with L lower triangular (its N × N coefficients by rows), the same order for both widths.
template <int N, class V>
inline V column_leverage(const V* L, const V* g) {
  V hh = V();
  for (int r = 0; r < N; ++r) {
    V z = V();
    for (int k = 0; k <= r; ++k) z += L[r * N + k] * g[k];
    hh += z * z;
  }
  return hh;
}

/// strip_candidates (fresh leverage scores, `leverage`) and strip_scores (kept ones) on a
/// compile-time N: the column, c and the triangle stay in registers.
template <int N, bool leverage>
Eigen::Index strip_pass_fixed(const Eigen::MatrixXd& G, Eigen::Index m, const Eigen::Ref<const Eigen::VectorXd>& c,
                              const Eigen::MatrixXd* L, double* a, double* h, const StripScoring& score) {
  double cf[N], Lf[leverage ? N * N : 1];
  for (int i = 0; i < N; ++i) {
    cf[i] = c(i);
    if constexpr (leverage)
      for (int k = 0; k < N; ++k) Lf[i * N + k] = (*L)(i, k);
  }
  const double* const base = G.data();
  StripWinner winner(score.sig);
  Eigen::Index j = 0;
#if defined(SETBOUND_COLUMN_PAIRS)
  // The coefficients broadcast once (SSE2 has no broadcasting load; aligned memory operands fold).
  ColumnPair cp[N], Lp[leverage ? N * N : 1];
  for (int i = 0; i < N; ++i) {
    cp[i] = ColumnPair{cf[i], cf[i]};
    if constexpr (leverage)
      for (int k = 0; k < N; ++k) Lp[i * N + k] = ColumnPair{Lf[i * N + k], Lf[i * N + k]};
  }
  for (; j + 1 < m; j += 2) {
    const double* g0 = base + j * N;
    const double* g1 = g0 + N;
    ColumnPair g[N];
    for (int i = 0; i < N; ++i) g[i] = ColumnPair{g0[i], g1[i]};
    const ColumnPair s = column_dot<N>(cp, g);
    a[j] = s[0];
    a[j + 1] = s[1];
    if constexpr (leverage) {
      const ColumnPair hh = column_leverage<N>(Lp, g);
      h[j] = hh[0];
      h[j + 1] = hh[1];
    }
    score_candidate<N>(score, j, s[0], h, g0, winner);
    score_candidate<N>(score, j + 1, s[1], h, g1, winner);
  }
#endif
  for (; j < m; ++j) {
    const double* g = base + j * N;
    const double s = column_dot<N>(cf, g);
    a[j] = s;
    if constexpr (leverage) h[j] = column_leverage<N>(Lf, g);
    score_candidate<N>(score, j, s, h, g, winner);
  }
  return winner.index;
}

template <int N>
Eigen::Index bravo_advance_fixed(Eigen::MatrixXd& G, Eigen::Index m, const Eigen::VectorXd& lam, double sig,
                                 Eigen::Index j, const Eigen::VectorXd& z, double* a, double* h,
                                 Eigen::VectorXd& residual, const Eigen::VectorXd* cn, const StripScoring& next) {
  double lf[N], zf[N], cf[N];
  for (int i = 0; i < N; ++i) {
    lf[i] = lam(i);
    zf[i] = z(i);
    cf[i] = cn ? (*cn)(i) : 0.0;
  }
  const double ihj = 1.0 / h[j];
  double* const base = G.data();
  StripWinner winner(next.sig);
  auto column = [&](Eigen::Index k) {
    double* g = base + k * N;
    const double ak = a[k];
    double e = 0.0;
    for (int i = 0; i < N; ++i) {
      e += zf[i] * g[i];
      g[i] -= lf[i] * ak;
    }
    if (k == j) {
      residual.resize(N);
      for (int i = 0; i < N; ++i) {
        residual(i) = std::abs(g[i]);
        g[i] = sig * lf[i];
      }
      h[k] = 1.0;
    } else {
      h[k] = downdated_leverage(h[k], h[k] - e * e * ihj);
    }
    if (!cn) return;
    double s = 0.0;
    for (int i = 0; i < N; ++i) s += cf[i] * g[i];
    a[k] = s;
    score_candidate<N>(next, k, s, h, g, winner);
  };
  Eigen::Index k = 0;
#if defined(SETBOUND_COLUMN_PAIRS)
  ColumnPair zp[N], lp[N], cp[N];
  for (int i = 0; i < N; ++i) {
    zp[i] = ColumnPair{zf[i], zf[i]};
    lp[i] = ColumnPair{lf[i], lf[i]};
    cp[i] = ColumnPair{cf[i], cf[i]};
  }
  for (; k + 1 < m; k += 2) {
    if (k == j || k + 1 == j) {
      column(k);
      column(k + 1);
      continue;
    }
    double* g0 = base + k * N;
    double* g1 = g0 + N;
    const ColumnPair ak = {a[k], a[k + 1]};
    ColumnPair e = {0.0, 0.0}, s = {0.0, 0.0};
    for (int i = 0; i < N; ++i) {
      ColumnPair gi = {g0[i], g1[i]};
      e += zp[i] * gi;
      gi -= lp[i] * ak;
      s += cp[i] * gi;
      g0[i] = gi[0];
      g1[i] = gi[1];
    }
    const ColumnPair hv = {h[k], h[k + 1]};
    const ColumnPair hn = hv - e * e * ihj;
    h[k] = downdated_leverage(hv[0], hn[0]);
    h[k + 1] = downdated_leverage(hv[1], hn[1]);
    if (!cn) continue;
    a[k] = s[0];
    a[k + 1] = s[1];
    score_candidate<N>(next, k, s[0], h, g0, winner);
    score_candidate<N>(next, k + 1, s[1], h, g1, winner);
  }
#endif
  for (; k < m; ++k) column(k);
  return winner.index;
}

template <int N>
Eigen::Index compact_and_sum_fixed(Eigen::MatrixXd& W, Eigen::Index m, Eigen::VectorXd& w, bool drop_zeros) {
  using Col = Eigen::Matrix<double, N, 1>;
  const Eigen::Index n = W.rows();
  // A fixed-size accumulator lives in registers; a dynamic one is w itself (no allocation).
  Col acc_fixed;
  if constexpr (N != Eigen::Dynamic) acc_fixed.setZero();
  else w.setZero(n);
  auto& acc = [&]() -> auto& {
    if constexpr (N != Eigen::Dynamic) return acc_fixed;
    else return w;
  }();
  double* const base = W.data();
  Eigen::Index k = 0;
  for (Eigen::Index j = 0; j < m; ++j) {
    const Eigen::Map<const Col> col(base + j * n, n);
    acc += col.cwiseAbs();
    if (drop_zeros && (col.array() == 0.0).all()) continue;
    if (k != j) Eigen::Map<Col>(base + k * n, n) = col;  // k < j: no overlap
    ++k;
  }
  const double infl = 1.0 + static_cast<double>(k + 2) * std::numeric_limits<double>::epsilon();
  if constexpr (N != Eigen::Dynamic) w = acc_fixed * infl;
  else w *= infl;
  return k;
}

}  // namespace detail
}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/generator_kernels.ipp"
#endif
