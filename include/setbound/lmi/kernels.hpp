// setbound — small dense kernels of the interior-point solver (solver.hpp).
//
// The solver's per-block work is on matrices of size 1…16 in the online problems (papers.md
// §1.2–§1.3: 7×7 and 11×11 blocks). At these sizes Eigen's dynamic-size decompositions spend
// most of their time in dispatch and generic code paths (a 7×7 JacobiSVD took ~45% of an online
// step), and Eigen's fixed-size instantiations per block size cost minutes of compile time in
// every translation unit that includes the solver. These kernels are plain loops on column-major
// arrays: no allocation, no Eigen. The products and the Cholesky factorisation have fixed-size
// instantiations for n ≤ kFixedMax (plain loops, cheap to compile), chosen at run time by a
// switch on n, and a run-time-size version above.
//
//  * cholesky: L Lᵀ = A, reports failure (A not numerically positive definite);
//  * products of square matrices (Aᵀ/A × B/Bᵀ);
//  * symmetric eigen-decomposition (Householder tridiagonalisation with accumulated
//    reflections, then the implicit QL iteration with Wilkinson-type shifts — the classical
//    tred2/tql2 scheme of Wilkinson & Reinsch, Handbook for Automatic Computation II), with or
//    without eigenvectors; and the eigen-decompositions of up to four same-size matrices at
//    once by a cyclic Jacobi iteration in the four SIMD lanes (sym_eig_batch; the NT scaling's
//    runs of equal blocks, where one QL iteration per block waits on its own latency).
// All matrices are n×n, column-major, leading dimension n. Work arrays are supplied by the
// caller (sizes stated per function).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "setbound/core/config.hpp"
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace setbound::lmi::kernels {

/// The Schur-complement kernels are compiled twice where the compiler can dispatch at run time
/// (SETBOUND_HAS_KERNEL_CLONES, core/config.hpp: GCC ≥ 12 / Clang ≥ 14, x86-64 Linux, ifunc): for
/// x86-64-v3 (AVX2, FMA) and the baseline; `flatten` inlines the fixed-size kernels into each clone
/// so that they get its instruction set. The library stays runnable on any x86-64. Define
/// SETBOUND_NO_KERNEL_CLONES to disable.
#if SETBOUND_HAS_KERNEL_CLONES
#define SETBOUND_KERNEL_CLONES __attribute__((target_clones("arch=x86-64-v3", "default"), flatten))
#else
#define SETBOUND_KERNEL_CLONES
#endif

/// Complete unrolling of the short fixed-size inner loops (N ≤ 16): -O3 does it unasked, -O2
/// (CMake's RelWithDebInfo) does not, and then the row loop around them is not vectorised
/// (a solve of the 32-block benchmark took 5.8 ms instead of 3.9 ms).
#if defined(__clang__)
#define SETBOUND_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define SETBOUND_UNROLL _Pragma("GCC unroll 16")
#else
#define SETBOUND_UNROLL
#endif

/// Block sizes up to kFixedMax run on fixed-size instantiations (namespace `fixed`): with the
/// size known at compile time the loops are unrolled and vectorised, and the column being
/// accumulated lives in registers (a run-time-size loop must reload it: C may alias A or B).
/// 3–9× faster than the run-time loops at n = 3…7. They perform the same floating-point
/// operations in the same order as the run-time loops (no FMA contraction at the default
/// -O3 for x86-64), so results do not depend on the path.
inline constexpr int kFixedMax = 16;

namespace detail {

/// L (lower, strict upper part set to 0) with L Lᵀ = A; false if a pivot is not > 0 or not
/// finite (A indefinite or too close to singular for the factorisation). L may alias A.
bool cholesky_rt(int n, const double* A, double* L);

/// C = A B.
void mul_nn_rt(int n, const double* A, const double* B, double* C);

/// C = Aᵀ B.
void mul_tn_rt(int n, const double* A, const double* B, double* C);

/// C = A Bᵀ.
void mul_nt_rt(int n, const double* A, const double* B, double* C);

/// Symmetric C = Qᵀ X Q for symmetric X (only X's values are read, both triangles);
/// T is n×n work.
void congruence_t_rt(int n, const double* Q, const double* X, double* T, double* C);

/// Symmetric C = Q X Qᵀ for symmetric X; T is n×n work.
void congruence_n_rt(int n, const double* Q, const double* X, double* T, double* C);

}  // namespace detail

namespace fixed {

template <int N>
inline bool cholesky(const double* A, double* L) {
  double a[N * N];
  for (int i = 0; i < N * N; ++i) a[i] = A[i];
  for (int j = 0; j < N; ++j) {
    double d = a[j + j * N];
    for (int k = 0; k < j; ++k) d -= a[j + k * N] * a[j + k * N];
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    d = std::sqrt(d);
    a[j + j * N] = d;
    const double inv = 1.0 / d;
    for (int k = 0; k < j; ++k) {
      const double f = a[j + k * N];
      for (int i = j + 1; i < N; ++i) a[i + j * N] -= f * a[i + k * N];
    }
    for (int i = j + 1; i < N; ++i) a[i + j * N] *= inv;
  }
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) L[i + j * N] = i < j ? 0.0 : a[i + j * N];
  return true;
}

/// Whether the symmetric A (lower triangle read) is positive definite: the pivots of its LDLᵀ
/// factorisation (right-looking, no square roots: the chain from one pivot to the next is a
/// division and two multiply-adds) are all > 0 and finite.
template <int N>
inline bool positive_definite(const double* A) {
  double a[N * N];
  for (int i = 0; i < N * N; ++i) a[i] = A[i];
  for (int j = 0; j < N; ++j) {
    const double d = a[j + j * N];
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    const double inv = 1.0 / d;
    for (int k = j + 1; k < N; ++k) {
      const double l = a[k + j * N] * inv;
      for (int i = k; i < N; ++i) a[i + k * N] -= a[i + j * N] * l;
    }
  }
  return true;
}

template <int N>
inline void mul_nn(const double* A, const double* B, double* C) {
  for (int j = 0; j < N; ++j) {
    double c[N] = {};
    for (int k = 0; k < N; ++k) {
      const double b = B[k + j * N];
      for (int i = 0; i < N; ++i) c[i] += A[i + k * N] * b;
    }
    for (int i = 0; i < N; ++i) C[i + j * N] = c[i];
  }
}

template <int N>
inline void mul_tn(const double* A, const double* B, double* C) {
  double c[N * N];
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) {
      double s = 0.0;
      for (int k = 0; k < N; ++k) s += A[k + i * N] * B[k + j * N];
      c[i + j * N] = s;
    }
  for (int i = 0; i < N * N; ++i) C[i] = c[i];
}

template <int N>
inline void mul_nt(const double* A, const double* B, double* C) {
  for (int j = 0; j < N; ++j) {
    double c[N] = {};
    for (int k = 0; k < N; ++k) {
      const double b = B[j + k * N];
      for (int i = 0; i < N; ++i) c[i] += A[i + k * N] * b;
    }
    for (int i = 0; i < N; ++i) C[i + j * N] = c[i];
  }
}

template <int N>
inline void congruence_t(const double* Q, const double* X, double* T, double* C) {
  mul_nn<N>(X, Q, T);
  for (int j = 0; j < N; ++j)
    for (int i = 0; i <= j; ++i) {
      double s = 0.0;
      for (int k = 0; k < N; ++k) s += Q[k + i * N] * T[k + j * N];
      C[i + j * N] = s;
      C[j + i * N] = s;
    }
}

template <int N>
inline void congruence_n(const double* Q, const double* X, double* T, double* C) {
  mul_nt<N>(X, Q, T);
  double c[N * N];
  for (int j = 0; j < N; ++j) {
    double* cj = c + j * N;
    for (int i = 0; i < N; ++i) cj[i] = 0.0;
    for (int k = 0; k < N; ++k) {
      const double t = T[k + j * N];
      for (int i = 0; i < N; ++i) cj[i] += Q[i + k * N] * t;
    }
  }
  for (int j = 0; j < N; ++j)
    for (int i = 0; i <= j; ++i) {
      const double s = i == j ? c[i + j * N] : 0.5 * (c[i + j * N] + c[j + i * N]);
      C[i + j * N] = s;
      C[j + i * N] = s;
    }
}

}  // namespace fixed

/// Calls f(std::integral_constant<int, n>) for 1 ≤ n ≤ kFixedMax, f(integral_constant<int, 0>)
/// (the run-time-size path) otherwise.
template <class F>
inline decltype(auto) with_size(int n, F&& f) {
  using std::integral_constant;
  switch (n) {
    case 1: return f(integral_constant<int, 1>{});
    case 2: return f(integral_constant<int, 2>{});
    case 3: return f(integral_constant<int, 3>{});
    case 4: return f(integral_constant<int, 4>{});
    case 5: return f(integral_constant<int, 5>{});
    case 6: return f(integral_constant<int, 6>{});
    case 7: return f(integral_constant<int, 7>{});
    case 8: return f(integral_constant<int, 8>{});
    case 9: return f(integral_constant<int, 9>{});
    case 10: return f(integral_constant<int, 10>{});
    case 11: return f(integral_constant<int, 11>{});
    case 12: return f(integral_constant<int, 12>{});
    case 13: return f(integral_constant<int, 13>{});
    case 14: return f(integral_constant<int, 14>{});
    case 15: return f(integral_constant<int, 15>{});
    case 16: return f(integral_constant<int, 16>{});
    default: return f(integral_constant<int, 0>{});
  }
}
static_assert(kFixedMax == 16, "with_size has one case per fixed size");

/// L (lower, strict upper part set to 0) with L Lᵀ = A (only the lower triangle of A is read);
/// false if a pivot is not > 0 or not finite (A indefinite or too close to singular for the
/// factorisation). L may alias A.
bool cholesky(int n, const double* A, double* L);

/// Whether the symmetric A (n×n, lower triangle read) is positive definite (fixed::positive_definite);
/// `work` holds n·n doubles for the sizes above kFixedMax (A itself may be passed).
bool positive_definite(int n, const double* A, double* work);

/// C = A B.
void mul_nn(int n, const double* A, const double* B, double* C);

/// C = Aᵀ B.
void mul_tn(int n, const double* A, const double* B, double* C);

/// C = A Bᵀ.
void mul_nt(int n, const double* A, const double* B, double* C);

/// Symmetric C = Qᵀ X Q for symmetric X (only X's values are read, both triangles);
/// T is n×n work.
void congruence_t(int n, const double* Q, const double* X, double* T, double* C);

/// Symmetric C = Q X Qᵀ for symmetric X; T is n×n work.
void congruence_n(int n, const double* Q, const double* X, double* T, double* C);

// ---------------------------------------------------------------------------------------
// Kernels of the Schur complement (solver.hpp, assemble_block). A block's coefficients are
// handled in the symmetric vectorisation svec: the lower triangle by columns with the
// off-diagonal entries multiplied by √2, so that ⟨X, Y⟩_F = svec(X)ᵀsvec(Y) at n(n+1)/2
// instead of n² products. The dense coefficients F_t of a block are stacked vertically,
// V = [F_1; …; F_k] ((n·k)×n), so that all the products F_t Q are one tall product V·Q whose
// inner loops run over n·k contiguous rows (vectorised), instead of k small n×n products.

inline constexpr double kSqrt2 = 1.4142135623730951;

/// Length of svec for an n×n matrix.
inline constexpr int svec_size(int n) { return n * (n + 1) / 2; }

namespace fixed {

template <int N>
inline void svec_pack(const double* X, double* v) {
  int t = 0;
  for (int j = 0; j < N; ++j) {
    v[t++] = X[j + j * N];
    for (int i = j + 1; i < N; ++i) v[t++] = kSqrt2 * X[i + j * N];
  }
}

template <int N>
inline void svec_unpack(const double* v, double* X) {
  constexpr double r = 1.0 / kSqrt2;
  int t = 0;
  for (int j = 0; j < N; ++j) {
    X[j + j * N] = v[t++];
    for (int i = j + 1; i < N; ++i) {
      const double x = r * v[t++];
      X[i + j * N] = x;
      X[j + i * N] = x;
    }
  }
}

/// P = V Q with V rows×N (leading dimension ldv), Q N×N; P rows×N (leading dimension ld).
/// The row loop is innermost with the N entries of Q's column in registers: contiguous loads
/// of V, no reduction, so the compiler vectorises it along the rows.
template <int N>
inline void stacked_mul(int rows, const double* V, long ldv, const double* Q, double* P, long ld) {
  for (int c = 0; c < N; ++c) {
    double q[N];
    for (int l = 0; l < N; ++l) q[l] = Q[l + c * N];
    double* pc = P + c * ld;
    for (int r = 0; r < rows; ++r) {
      double acc = V[r] * q[0];
      SETBOUND_UNROLL for (int l = 1; l < N; ++l) acc += V[r + l * ldv] * q[l];
      pc[r] = acc;
    }
  }
}

/// Row-major scaled coefficients (solver.hpp): for the blocks of up to 8 rows the stacked
/// matrices are interleaved by row (row r·cp + t of V = row r of matrix t, cp = padded count),
/// and out (svec length × cp, row-major: entry (idx, t) at out[idx·cp + t]) gets svec(QᵀF_tQ)
/// in column t. P is work of V's shape. First P = V Q (rows r·cp + t = row r of F_tQ = column
/// r of QᵀF_t, F_t symmetric), then each lower-triangle entry (i, c) of all the QᵀF_tQ at once:
/// Σ_r P(r·cp + t, i) Q(r, c), contiguous in t. No transposes; the Gram kernel and the
/// products with the coefficients read `out` as it is.
template <int N>
inline void interleaved_congruence_svec(int count, int cp, const double* V, long ld, const double* Q, double* P,
                                        double* out) {
  // Only the first `count` slots hold matrices (the others: sparse coefficients, whose columns
  // the caller fills, and padding), rounded up to whole vectors.
  const int tn = std::min(cp, (count + 3) / 4 * 4);
  for (int r = 0; r < N; ++r) stacked_mul<N>(tn, V + static_cast<long>(r) * cp, ld, Q, P + static_cast<long>(r) * cp, ld);
  int idx = 0;
  for (int c = 0; c < N; ++c) {
    double q[N];
    for (int r = 0; r < N; ++r) q[r] = Q[r + c * N];
    for (int i = c; i < N; ++i, ++idx) {
      const double s = i == c ? 1.0 : kSqrt2;
      const double* Pi = P + static_cast<long>(i) * ld;
      double* o = out + static_cast<long>(idx) * cp;
      for (int t = 0; t < tn; ++t) {
        double acc = Pi[t] * q[0];
        SETBOUND_UNROLL for (int r = 1; r < N; ++r) acc += Pi[t + static_cast<long>(r) * cp] * q[r];
        o[t] = s * acc;
      }
    }
  }
}

}  // namespace fixed

namespace detail {

void svec_pack_rt(int n, const double* X, double* v);

void svec_unpack_rt(int n, const double* v, double* X);

void stacked_mul_rt(int rows, int n, const double* V, long ldv, const double* Q, double* P, long ld);

/// Column t of the row-major out (svec length × cp) = svec(C), C n×n with leading dimension ldc.
void svec_pack_column(int n, const double* C, long ldc, double* out, long cp, int t);

void stacked_congruence_svec_rt(int n, int count, const double* V, long ld, const double* Q, double* P,
                                       double* T, double* out, long cp);

}  // namespace detail

namespace detail {

double hypot2(double a, double b);

/// Householder reduction of the symmetric A (both triangles given) to tridiagonal form:
/// d = diagonal, e[i] = the (i, i−1) element (e[0] = 0). With `vectors`, A is replaced by
/// the orthogonal Z with Zᵀ A_in Z = T; otherwise A is destroyed.
void tridiagonalize(int n, double* a, double* d, double* e, bool vectors);

/// Implicit QL iteration on the tridiagonal (d, e) of tridiagonalize(); eigenvalues into d,
/// eigenvectors (columns) accumulated into z when z != nullptr. false if an eigenvalue did not
/// converge in 60 iterations.
bool tridiagonal_ql(int n, double* d, double* e, double* z);

/// Smallest eigenvalue of the symmetric tridiagonal (d, e) of tridiagonalize() by Laguerre's
/// iteration on p(x) = det(T − xI) (three-term recurrences for p, p′, p″, rescaled against
/// overflow), started left of the Gershgorin bound. p has only real roots, so the iterates
/// increase monotonically to the smallest one and converge cubically, also for clustered
/// eigenvalues; the result is never right of it by more than rounding. NaN on non-finite data.
double tridiagonal_lambda_min(int n, const double* d, const double* e);

}  // namespace detail

/// Eigen-decomposition of the symmetric A (n×n, both triangles): on success w holds the
/// eigenvalues (no particular order) and A the orthonormal eigenvectors (column i ↔ w[i]).
/// `e` is work of length n. false if the iteration did not converge or A is not finite.
bool sym_eig(int n, double* A, double* w, double* e);

/// Eigenvalues only; A is destroyed; `e` is work of length n.
bool sym_eigenvalues(int n, double* A, double* w, double* e);

/// Smallest eigenvalue of the symmetric A (destroyed); w, e work of length n. NaN when the
/// iteration failed.
double sym_lambda_min(int n, double* A, double* w, double* e);

/// Singular values and right singular vectors of the square G by one-sided (Hestenes) Jacobi:
/// rotations V of the columns of G until they are mutually orthogonal (relative to their
/// norms), which determines even tiny singular values to high relative accuracy (Demmel &
/// Veselić). On return G holds G·V (columns = σ_i u_i), V the rotations, sv the column norms.
/// false if no convergence within 60 sweeps or non-finite data.
bool one_sided_jacobi(int n, double* G, double* V, double* sv);

#if defined(__GNUC__)
namespace detail {
/// Four doubles in one SIMD register (GCC vector extensions; two SSE2 registers in the baseline
/// clone), for the batched eigensolver's lanes and the Gram / gemv register tiles.
typedef double v4d __attribute__((vector_size(32)));
typedef double v4d_u __attribute__((vector_size(32), aligned(8), may_alias));  // unaligned loads

// (The lane helpers take and return through references: by value, a 32-byte vector changes the
// calling convention between the baseline and the AVX clone, which GCC warns about.)
inline void lanes_sqrt(const v4d& x, v4d& y) {
#if defined(__SSE2__)
  const __m128d lo = _mm_sqrt_pd(_mm_set_pd(x[1], x[0])), hi = _mm_sqrt_pd(_mm_set_pd(x[3], x[2]));
  y = v4d{_mm_cvtsd_f64(lo), _mm_cvtsd_f64(_mm_unpackhi_pd(lo, lo)), _mm_cvtsd_f64(hi), _mm_cvtsd_f64(_mm_unpackhi_pd(hi, hi))};
#else
  y = v4d{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}

/// 1/√x for x ∈ [1, 2] without the divider: a quadratic fit (relative error 5.8e-3) and three
/// Newton steps (5e-5, 4e-9, rounding).
inline void lanes_rsqrt_1_2(const v4d& x, v4d& y) {
  y = (0.14262018513400665 * x - 0.7119622800751336) * x + 1.5635806899664277;
  const v4d hx = 0.5 * x;
  for (int k = 0; k < 3; ++k) y = y * (1.5 - hx * y * y);
}

/// Cyclic Jacobi on four symmetric N×N matrices at once, lane l of every entry belonging to
/// matrix l: A (upper triangle, column-major, N·N entries) is diagonalised in place, V
/// accumulates the rotations. Parallel (round-robin) ordering: the ⌊N/2⌋ rotations of a round
/// touch disjoint index pairs, so their angles are independent. Rutishauser's update of the
/// diagonal; a rotation is skipped when its off-diagonal entry is below ε·√(a_pp a_qq) in every
/// lane (the relative criterion of Demmel & Veselić), and the sweeps stop when a whole sweep was
/// skipped. false after 40 sweeps without that.
template <int N>
inline bool jacobi_lanes(v4d* A, v4d* V) {
  constexpr int P = N + (N & 1);  // round-robin players (one dummy when N is odd)
  constexpr double eps2 = std::numeric_limits<double>::epsilon() * std::numeric_limits<double>::epsilon();
  for (int i = 0; i < N * N; ++i) V[i] = v4d{0.0, 0.0, 0.0, 0.0};
  for (int i = 0; i < N; ++i) V[i + i * N] = v4d{1.0, 1.0, 1.0, 1.0};
  for (int sweep = 0; sweep < 40; ++sweep) {
    bool rotated = false;
    // Unrolled, the rounds' index pairs are constants and so are all the addresses below
    // (7×7: 0.68 → 0.60 µs per matrix).
    SETBOUND_UNROLL
    for (int round = 0; round < P - 1; ++round) {
      int pp[P / 2], qq[P / 2];
      int np = 0;
      for (int k = 0; k < P / 2; ++k) {
        const int a = k == 0 ? P - 1 : (round + k) % (P - 1);
        const int b = k == 0 ? round : (round + P - 1 - k) % (P - 1);
        if (a >= N || b >= N) continue;
        pp[np] = std::min(a, b);
        qq[np] = std::max(a, b);
        ++np;
      }
      v4d cs[P / 2], sn[P / 2], tn[P / 2];
      bool active[P / 2];
      for (int k = 0; k < np; ++k) {
        const int p = pp[k], q = qq[k];
        const v4d app = A[p + p * N], aqq = A[q + q * N], apq = A[p + q * N];
        const v4d dd = app * aqq;
        const auto big = apq * apq > eps2 * (dd >= 0.0 ? dd : -dd);
        active[k] = big[0] || big[1] || big[2] || big[3];
        if (!active[k]) continue;
        // tan θ = sign(d)·o / (|d| + √(d² + o²)) with d = a_qq − a_pp, o = 2a_pq: |t| ≤ 1.
        const v4d d = aqq - app, o = 2.0 * apq;
        v4d r, c;
        lanes_sqrt(d * d + o * o, r);
        const v4d h = (d >= 0.0 ? d : -d) + r;
        const v4d t = h > 0.0 ? (d >= 0.0 ? o : -o) / h : v4d{0.0, 0.0, 0.0, 0.0};
        lanes_rsqrt_1_2(1.0 + t * t, c);
        cs[k] = c;
        sn[k] = c * t;
        tn[k] = t;
      }
      for (int k = 0; k < np; ++k) {
        if (!active[k]) continue;
        rotated = true;
        const int p = pp[k], q = qq[k];
        const v4d c = cs[k], s = sn[k], t = tn[k];
        for (int r = 0; r < N; ++r) {
          if (r == p || r == q) continue;
          v4d& x = A[r < p ? r + p * N : p + r * N];
          v4d& y = A[r < q ? r + q * N : q + r * N];
          const v4d xv = x, yv = y;
          x = c * xv - s * yv;
          y = s * xv + c * yv;
        }
        const v4d apq = A[p + q * N];
        A[p + p * N] -= t * apq;
        A[q + q * N] += t * apq;
        A[p + q * N] = v4d{0.0, 0.0, 0.0, 0.0};
        v4d* vp = V + p * N;
        v4d* vq = V + q * N;
        for (int r = 0; r < N; ++r) {
          const v4d x = vp[r], y = vq[r];
          vp[r] = c * x - s * y;
          vq[r] = s * x + c * y;
        }
      }
    }
    if (!rotated) return true;
  }
  return false;
}

/// sym_eig_batch for a fixed N: packs the matrices with finite upper triangles into lanes (the
/// other lanes repeat one of them: a NaN would be skipped by the rotation test, not caught),
/// runs jacobi_lanes, unpacks the lanes whose results are finite.
template <int N>
SETBOUND_KERNEL_CLONES inline unsigned sym_eig_batch_fixed(int count, double* const* A, double* const* w) {
  unsigned finite_in = 0u;
  for (int l = 0; l < count; ++l) {
    bool finite = true;
    for (int j = 0; j < N; ++j)
      for (int i = 0; i <= j; ++i) finite = finite && std::isfinite(A[l][i + j * N]);
    if (finite) finite_in |= 1u << l;
  }
  if (finite_in == 0u) return 0u;
  int src[4];
  int first = 0;
  while (!((finite_in >> first) & 1u)) ++first;
  for (int l = 0; l < 4; ++l) src[l] = l < count && ((finite_in >> l) & 1u) ? l : first;
  alignas(32) v4d a[N * N];
  alignas(32) v4d v[N * N];
  for (int j = 0; j < N; ++j)
    for (int i = 0; i <= j; ++i)
      for (int l = 0; l < 4; ++l) a[i + j * N][l] = A[src[l]][i + j * N];
  if (!jacobi_lanes<N>(a, v)) return 0u;
  unsigned ok = 0u;
  for (int l = 0; l < count; ++l) {
    if (!((finite_in >> l) & 1u)) continue;
    bool finite = true;
    for (int i = 0; i < N; ++i) finite = finite && std::isfinite(a[i + i * N][l]);
    for (int i = 0; i < N * N; ++i) finite = finite && std::isfinite(v[i][l]);
    if (!finite) continue;
    ok |= 1u << l;
    for (int i = 0; i < N; ++i) w[l][i] = a[i + i * N][l];
    for (int i = 0; i < N * N; ++i) A[l][i] = v[i][l];
  }
  return ok;
}
}  // namespace detail
#endif

/// Largest block size sym_eig_batch() handles (larger: 0, the caller uses sym_eig()).
inline constexpr int kEigBatchMax = 10;

/// Whether sym_eig_batch() on count matrices of size n beats count calls of sym_eig(): per
/// matrix (ns, 2-core EPYC VM, AVX2 clone), n = 7: QL 1270, batches of 2 / 3 / 4 1270 / 860 /
/// 650; n = 5: 720 against 640 / 450 / 340; n = 10: 2490 against 3220 / 2240 / 1730.
inline constexpr bool eig_batch_pays(int n, int count) {
  return n >= 2 && n <= kEigBatchMax && (count >= 3 || (count == 2 && n <= 6));
}

/// Eigen-decompositions of count ≤ 4 symmetric n×n matrices A[0 … count−1] (column-major, the
/// upper triangle is read) in one pass of a four-lane Jacobi iteration: the lanes of a SIMD
/// register carry the four matrices through the same rotations, which keeps the divider and
/// the FMA units busy where the QL iteration of one small matrix waits on its own latency
/// (7×7: 0.60 µs against 1.7 µs per matrix with four matrices). Returns the bit mask of the
/// matrices done: for those, w[l] holds the eigenvalues (no particular order) and A[l] the
/// orthonormal eigenvectors, as sym_eig() gives them; the others (non-finite data, no
/// convergence, n outside 2 … kEigBatchMax, or no vector extensions) are left untouched for
/// sym_eig().
unsigned sym_eig_batch(int n, int count, double* const* A, double* const* w);

// --- dispatchers of the Schur-complement kernels (see svec above) ---

/// v = svec(X) (X symmetric, only its lower triangle is read).
void svec_pack(int n, const double* X, double* v);

/// X = smat(v), both triangles written.
void svec_unpack(int n, const double* v, double* X);

/// P = V Q: V is rows×n (leading dimension ldv), Q n×n, P rows×n (leading dimension ldp).
void stacked_mul(int rows, int n, const double* V, long ldv, const double* Q, double* P, long ldp);

/// Blocks of up to this size keep their coefficients interleaved by row (see
/// fixed::interleaved_congruence_svec); larger ones stacked (rows t·n + r of V = row r of F_t).
inline constexpr int kInterleavedMax = 8;

/// Column t of out (row-major, svec length × cp: entry (idx, t) at out[idx·cp + t]) =
/// svec(Qᵀ F_t Q) for t < count. n ≤ kInterleavedMax: V interleaved (row r·cp + t = row r of
/// F_t, cp ≥ count rounded up to 4, finite rows past count); columns up to count rounded up
/// to 4 are written. Larger n: V stacked (row t·n + r = row r of F_t, leading dimension ld),
/// columns t < count written.
/// P and T are work arrays of V's shape.
SETBOUND_KERNEL_CLONES inline void congruence_svec(int n, int count, int cp, const double* V, long ld, const double* Q,
                                                   double* P, double* T, double* out) {
  with_size(n, [&](auto N) {
    constexpr int Nv = decltype(N)::value;
    if constexpr (Nv == 0) {
      detail::stacked_congruence_svec_rt(n, count, V, ld, Q, P, T, out, cp);
    } else if constexpr (Nv <= kInterleavedMax) {
      fixed::interleaved_congruence_svec<Nv>(count, cp, V, ld, Q, P, out);
    } else {
      // From n = 9 on the tall products lose to one small congruence per matrix (measured:
      // 1.4 against 2.0 µs for three 13×13 matrices; twice as fast the other way at n = 7).
      for (int t = 0; t < count; ++t) {
        double* F = T + static_cast<long>(t) * Nv * Nv;  // T has room: (count·n)·n entries
        for (int c = 0; c < Nv; ++c)
          for (int r = 0; r < Nv; ++r) F[r + c * Nv] = V[t * Nv + r + c * ld];
        double* C = P + Nv * Nv;
        fixed::congruence_t<Nv>(Q, F, P, C);
        detail::svec_pack_column(Nv, C, Nv, out, cp, t);
      }
    }
  });
}

/// y_j = ⟨a_j, x⟩ for the k columns a_j of A (length s each, leading dimension s): Aᵀx with
/// four columns at a time (Eigen's dynamic-size GEMV costs more in dispatch than in flops at
/// the solver's sizes, s ≤ 136, k ≤ a few dozen).
SETBOUND_KERNEL_CLONES inline void gemv_t(int s, int k, const double* A, const double* x, double* y) {
  int j = 0;
  for (; j + 4 <= k; j += 4) {
    const double* a0 = A + static_cast<long>(j) * s;
    const double* a1 = a0 + s;
    const double* a2 = a1 + s;
    const double* a3 = a2 + s;
    double y0 = 0.0, y1 = 0.0, y2 = 0.0, y3 = 0.0;
    for (int t = 0; t < s; ++t) {
      const double xt = x[t];
      y0 += a0[t] * xt;
      y1 += a1[t] * xt;
      y2 += a2[t] * xt;
      y3 += a3[t] * xt;
    }
    y[j] = y0;
    y[j + 1] = y1;
    y[j + 2] = y2;
    y[j + 3] = y3;
  }
  for (; j < k; ++j) {
    const double* a = A + static_cast<long>(j) * s;
    double acc = 0.0;
    for (int t = 0; t < s; ++t) acc += a[t] * x[t];
    y[j] = acc;
  }
}

#if defined(__GNUC__)
namespace detail {
/// Rows i0 … i0+3 × columns c0 … c0+4·NV−1 of FᵀF from the row-major F (s rows, leading
/// dimension ldf): 4·NV accumulators of four lanes stay in registers over the s rows (rank-one
/// updates: four broadcasts and NV loads per 4·NV fused multiply-adds). Entries with row or
/// column ≥ k are not stored.
template <int NV>
inline void gram_tile(int s, const double* F, long ldf, int i0, int c0, int k, double* G, long ldg) {
  v4d acc[4][NV];
  for (int r = 0; r < 4; ++r)
    for (int q = 0; q < NV; ++q) acc[r][q] = v4d{0.0, 0.0, 0.0, 0.0};
  const double* row = F;
  for (int t = 0; t < s; ++t, row += ldf) {
    v4d b[NV];
    for (int q = 0; q < NV; ++q) b[q] = *reinterpret_cast<const v4d_u*>(row + c0 + 4 * q);
    for (int r = 0; r < 4; ++r) {
      const double a = row[i0 + r];
      for (int q = 0; q < NV; ++q) acc[r][q] += a * b[q];
    }
  }
  for (int r = 0; r < 4 && i0 + r < k; ++r)
    for (int q = 0; q < NV; ++q)
      for (int l = 0; l < 4; ++l) {
        const int j = c0 + 4 * q + l;
        if (j < k) G[i0 + r + static_cast<long>(j) * ldg] = acc[r][q][l];
      }
}
}  // namespace detail
#endif

/// Columns a row of F must have for gram_upper(): k rounded up to a multiple of 4 (the tiles
/// read them; entries past k may hold anything finite).
inline constexpr int gram_padded(int k) { return (k + 3) / 4 * 4; }

/// Upper triangle of the Gram matrix G = FᵀF of the k columns of the row-major F (s rows,
/// leading dimension ldf ≥ gram_padded(k) readable entries per row); G is k×k with leading
/// dimension ldg. Register tiles of 4×12 (detail::gram_tile): 1.15 → 0.36 µs against column
/// dot products at s = 28, k = 20 (AVX2). Some entries below the diagonal are written too
/// (with their correct values).
SETBOUND_KERNEL_CLONES inline void gram_upper(int s, int k, const double* F, long ldf, double* G, long ldg) {
#if defined(__GNUC__)
  for (int i0 = 0; i0 < k; i0 += 4) {
    for (int c0 = i0; c0 < k;) {
      const int left = (k - c0 + 3) / 4;
      if (left >= 3) {
        detail::gram_tile<3>(s, F, ldf, i0, c0, k, G, ldg);
        c0 += 12;
      } else if (left == 2) {
        detail::gram_tile<2>(s, F, ldf, i0, c0, k, G, ldg);
        c0 += 8;
      } else {
        detail::gram_tile<1>(s, F, ldf, i0, c0, k, G, ldg);
        c0 += 4;
      }
    }
  }
#else
  for (int j = 0; j < k; ++j)
    for (int i = 0; i <= j; ++i) {
      double acc = 0.0;
      for (int t = 0; t < s; ++t) acc += F[t * ldf + i] * F[t * ldf + j];
      G[i + static_cast<long>(j) * ldg] = acc;
    }
#endif
}

#if defined(__GNUC__)
namespace detail {
/// y_j = Σ_t A(t, j) x_t for the columns j0 … j0+4·NV−1 (those < k stored): 4·NV sums in
/// registers over the s rows.
template <int NV>
inline void gemv_rm_t_tile(int s, const double* A, long lda, const double* x, int j0, int k, double* y) {
  v4d acc[NV];
  for (int q = 0; q < NV; ++q) acc[q] = v4d{0.0, 0.0, 0.0, 0.0};
  const double* row = A + j0;
  for (int t = 0; t < s; ++t, row += lda) {
    const double xt = x[t];
    for (int q = 0; q < NV; ++q) acc[q] += xt * *reinterpret_cast<const v4d_u*>(row + 4 * q);
  }
  for (int q = 0; q < NV; ++q)
    for (int l = 0; l < 4 && j0 + 4 * q + l < k; ++l) y[j0 + 4 * q + l] = acc[q][l];
}
}  // namespace detail
#endif

/// y_j = Σ_t A(t, j) x_t for the row-major A (s×k, leading dimension lda ≥ gram_padded(k)
/// readable, finite entries per row): Aᵀx with the sums in registers, twelve columns per pass
/// over the rows (accumulating in y itself made every row a store-to-load chain: 6 % of a
/// solve of the 32-block benchmark).
SETBOUND_KERNEL_CLONES inline void gemv_rm_t(int s, int k, const double* A, long lda, const double* x, double* y) {
#if defined(__GNUC__)
  for (int j0 = 0; j0 < k;) {
    const int left = (k - j0 + 3) / 4;
    if (left >= 3) {
      detail::gemv_rm_t_tile<3>(s, A, lda, x, j0, k, y);
      j0 += 12;
    } else if (left == 2) {
      detail::gemv_rm_t_tile<2>(s, A, lda, x, j0, k, y);
      j0 += 8;
    } else {
      detail::gemv_rm_t_tile<1>(s, A, lda, x, j0, k, y);
      j0 += 4;
    }
  }
#else
  for (int j = 0; j < k; ++j) y[j] = 0.0;
  for (int t = 0; t < s; ++t) {
    const double xt = x[t];
    const double* a = A + t * lda;
    for (int j = 0; j < k; ++j) y[j] += a[j] * xt;
  }
#endif
}

/// y_t += alpha · Σ_j A(t, j) x_j for the row-major A (s×k, leading dimension lda): four rows
/// at a time, each row's dot product in a four-lane register (so the additions are not one
/// dependent chain), the four reduced together at the end.
SETBOUND_KERNEL_CLONES inline void gemv_rm_n_add(int s, int k, double alpha, const double* A, long lda, const double* x, double* y) {
  const int k4 = k / 4 * 4;
  int t = 0;
#if defined(__GNUC__)
  for (; t + 4 <= s; t += 4) {
    const double* a = A + t * lda;
    detail::v4d acc[4] = {};
    for (int j = 0; j < k4; j += 4) {
      const detail::v4d xv = *reinterpret_cast<const detail::v4d_u*>(x + j);
      for (int r = 0; r < 4; ++r) acc[r] += *reinterpret_cast<const detail::v4d_u*>(a + r * lda + j) * xv;
    }
    for (int r = 0; r < 4; ++r) {
      double sum = (acc[r][0] + acc[r][1]) + (acc[r][2] + acc[r][3]);
      for (int j = k4; j < k; ++j) sum += a[r * lda + j] * x[j];
      y[t + r] += alpha * sum;
    }
  }
#endif
  for (; t < s; ++t) {
    const double* a = A + t * lda;
    double a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0;
    for (int j = 0; j < k4; j += 4) {
      a0 += a[j] * x[j];
      a1 += a[j + 1] * x[j + 1];
      a2 += a[j + 2] * x[j + 2];
      a3 += a[j + 3] * x[j + 3];
    }
    for (int j = k4; j < k; ++j) a0 += a[j] * x[j];
    y[t] += alpha * ((a0 + a1) + (a2 + a3));
  }
}

/// y += alpha · A x for A s×k (leading dimension s).
SETBOUND_KERNEL_CLONES inline void gemv_n_add(int s, int k, double alpha, const double* A, const double* x, double* y) {
  int j = 0;
  for (; j + 4 <= k; j += 4) {
    const double* a0 = A + static_cast<long>(j) * s;
    const double* a1 = a0 + s;
    const double* a2 = a1 + s;
    const double* a3 = a2 + s;
    const double x0 = alpha * x[j], x1 = alpha * x[j + 1], x2 = alpha * x[j + 2], x3 = alpha * x[j + 3];
    for (int t = 0; t < s; ++t) y[t] += a0[t] * x0 + a1[t] * x1 + a2[t] * x2 + a3[t] * x3;
  }
  for (; j < k; ++j) {
    const double* a = A + static_cast<long>(j) * s;
    const double xj = alpha * x[j];
    for (int t = 0; t < s; ++t) y[t] += a[t] * xj;
  }
}

/// Solves L Lᵀ x = b in place (L lower triangular n×n, leading dimension n, from cholesky();
/// dinv = 1 / diag(L), so that the substitutions multiply instead of dividing).
/// Both substitutions run by columns (axpy updates, no chains of dependent additions): L y = b
/// with the columns of L, Lᵀ x = y with the columns of U = Lᵀ (leading dimension n, the
/// caller's copy).
void cholesky_solve(int n, const double* L, const double* U, const double* dinv, double* b);

}  // namespace setbound::lmi::kernels

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/lmi/impl/kernels.ipp"
#endif
