// setbound — definitions of the functions declared in setbound/lmi/kernels.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/lmi/kernels.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace lmi {
namespace kernels {
namespace detail {

SETBOUND_INLINE bool cholesky_rt(int n, const double* A, double* L) {
  for (int j = 0; j < n; ++j) {
    double* Lj = L + static_cast<long>(j) * n;
    const double* Aj = A + static_cast<long>(j) * n;
    for (int i = 0; i < j; ++i) Lj[i] = 0.0;
    double d = Aj[j];
    for (int k = 0; k < j; ++k) {
      const double v = L[j + static_cast<long>(k) * n];
      d -= v * v;
    }
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    d = std::sqrt(d);
    Lj[j] = d;
    const double inv = 1.0 / d;
    for (int i = j + 1; i < n; ++i) Lj[i] = Aj[i];
    for (int k = 0; k < j; ++k) {
      const double* Lk = L + static_cast<long>(k) * n;
      const double f = Lk[j];
      if (f == 0.0) continue;
      for (int i = j + 1; i < n; ++i) Lj[i] -= f * Lk[i];
    }
    for (int i = j + 1; i < n; ++i) Lj[i] *= inv;
  }
  return true;
}

SETBOUND_INLINE void mul_nn_rt(int n, const double* A, const double* B, double* C) {
  for (int j = 0; j < n; ++j) {
    double* Cj = C + static_cast<long>(j) * n;
    for (int i = 0; i < n; ++i) Cj[i] = 0.0;
    for (int k = 0; k < n; ++k) {
      const double b = B[k + static_cast<long>(j) * n];
      if (b == 0.0) continue;
      const double* Ak = A + static_cast<long>(k) * n;
      for (int i = 0; i < n; ++i) Cj[i] += Ak[i] * b;
    }
  }
}

SETBOUND_INLINE void mul_tn_rt(int n, const double* A, const double* B, double* C) {
  for (int j = 0; j < n; ++j) {
    const double* Bj = B + static_cast<long>(j) * n;
    for (int i = 0; i < n; ++i) {
      const double* Ai = A + static_cast<long>(i) * n;
      double s = 0.0;
      for (int k = 0; k < n; ++k) s += Ai[k] * Bj[k];
      C[i + static_cast<long>(j) * n] = s;
    }
  }
}

SETBOUND_INLINE void mul_nt_rt(int n, const double* A, const double* B, double* C) {
  for (int i = 0; i < n * n; ++i) C[i] = 0.0;
  for (int k = 0; k < n; ++k) {
    const double* Ak = A + static_cast<long>(k) * n;
    for (int j = 0; j < n; ++j) {
      const double b = B[j + static_cast<long>(k) * n];
      if (b == 0.0) continue;
      double* Cj = C + static_cast<long>(j) * n;
      for (int i = 0; i < n; ++i) Cj[i] += Ak[i] * b;
    }
  }
}

SETBOUND_INLINE void congruence_t_rt(int n, const double* Q, const double* X, double* T, double* C) {
  mul_nn_rt(n, X, Q, T);  // T = X Q
  for (int j = 0; j < n; ++j) {
    const double* Tj = T + static_cast<long>(j) * n;
    for (int i = 0; i <= j; ++i) {
      const double* Qi = Q + static_cast<long>(i) * n;
      double s = 0.0;
      for (int k = 0; k < n; ++k) s += Qi[k] * Tj[k];
      C[i + static_cast<long>(j) * n] = s;
      C[j + static_cast<long>(i) * n] = s;
    }
  }
}

SETBOUND_INLINE void congruence_n_rt(int n, const double* Q, const double* X, double* T, double* C) {
  mul_nt_rt(n, X, Q, T);  // T = X Qᵀ  (column j of T = X q_j, q_j = row j of Q)
  // C(i, j) = Σ_k Q(i, k) T(k, j)
  for (int j = 0; j < n; ++j) {
    double* Cj = C + static_cast<long>(j) * n;
    for (int i = 0; i < n; ++i) Cj[i] = 0.0;
    const double* Tj = T + static_cast<long>(j) * n;
    for (int k = 0; k < n; ++k) {
      const double t = Tj[k];
      if (t == 0.0) continue;
      const double* Qk = Q + static_cast<long>(k) * n;
      for (int i = 0; i < n; ++i) Cj[i] += Qk[i] * t;
    }
  }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < j; ++i) {
      const double s = 0.5 * (C[i + static_cast<long>(j) * n] + C[j + static_cast<long>(i) * n]);
      C[i + static_cast<long>(j) * n] = s;
      C[j + static_cast<long>(i) * n] = s;
    }
}

}  // namespace detail
}  // namespace kernels
}  // namespace lmi
}  // namespace setbound

namespace setbound {
namespace lmi {
namespace kernels {

SETBOUND_INLINE bool cholesky(int n, const double* A, double* L) {
  return with_size(n, [&](auto N) -> bool {
    if constexpr (decltype(N)::value == 0) return detail::cholesky_rt(n, A, L);
    else return fixed::cholesky<decltype(N)::value>(A, L);
  });
}

SETBOUND_INLINE bool positive_definite(int n, const double* A, double* work) {
  return with_size(n, [&](auto N) -> bool {
    if constexpr (decltype(N)::value == 0) return detail::cholesky_rt(n, A, work);
    else return fixed::positive_definite<decltype(N)::value>(A);
  });
}

SETBOUND_INLINE void mul_nn(int n, const double* A, const double* B, double* C) {
  with_size(n, [&](auto N) {
    if constexpr (decltype(N)::value == 0) detail::mul_nn_rt(n, A, B, C);
    else fixed::mul_nn<decltype(N)::value>(A, B, C);
  });
}

SETBOUND_INLINE void mul_tn(int n, const double* A, const double* B, double* C) {
  with_size(n, [&](auto N) {
    if constexpr (decltype(N)::value == 0) detail::mul_tn_rt(n, A, B, C);
    else fixed::mul_tn<decltype(N)::value>(A, B, C);
  });
}

SETBOUND_INLINE void mul_nt(int n, const double* A, const double* B, double* C) {
  with_size(n, [&](auto N) {
    if constexpr (decltype(N)::value == 0) detail::mul_nt_rt(n, A, B, C);
    else fixed::mul_nt<decltype(N)::value>(A, B, C);
  });
}

SETBOUND_INLINE void congruence_t(int n, const double* Q, const double* X, double* T, double* C) {
  with_size(n, [&](auto N) {
    if constexpr (decltype(N)::value == 0) detail::congruence_t_rt(n, Q, X, T, C);
    else fixed::congruence_t<decltype(N)::value>(Q, X, T, C);
  });
}

SETBOUND_INLINE void congruence_n(int n, const double* Q, const double* X, double* T, double* C) {
  with_size(n, [&](auto N) {
    if constexpr (decltype(N)::value == 0) detail::congruence_n_rt(n, Q, X, T, C);
    else fixed::congruence_n<decltype(N)::value>(Q, X, T, C);
  });
}

}  // namespace kernels
}  // namespace lmi
}  // namespace setbound

namespace setbound {
namespace lmi {
namespace kernels {
namespace detail {

SETBOUND_INLINE void svec_pack_rt(int n, const double* X, double* v) {
  int t = 0;
  for (int j = 0; j < n; ++j) {
    v[t++] = X[j + static_cast<long>(j) * n];
    for (int i = j + 1; i < n; ++i) v[t++] = kSqrt2 * X[i + static_cast<long>(j) * n];
  }
}

SETBOUND_INLINE void svec_unpack_rt(int n, const double* v, double* X) {
  const double r = 1.0 / kSqrt2;
  int t = 0;
  for (int j = 0; j < n; ++j) {
    X[j + static_cast<long>(j) * n] = v[t++];
    for (int i = j + 1; i < n; ++i) {
      const double x = r * v[t++];
      X[i + static_cast<long>(j) * n] = x;
      X[j + static_cast<long>(i) * n] = x;
    }
  }
}

SETBOUND_INLINE void stacked_mul_rt(int rows, int n, const double* V, long ldv, const double* Q, double* P, long ld) {
  for (int c = 0; c < n; ++c) {
    double* pc = P + c * ld;
    for (int r = 0; r < rows; ++r) pc[r] = 0.0;
    for (int l = 0; l < n; ++l) {
      const double q = Q[l + static_cast<long>(c) * n];
      const double* vl = V + l * ldv;
      for (int r = 0; r < rows; ++r) pc[r] += vl[r] * q;
    }
  }
}

SETBOUND_INLINE void svec_pack_column(int n, const double* C, long ldc, double* out, long cp, int t) {
  long idx = 0;
  for (int c = 0; c < n; ++c) {
    out[idx++ * cp + t] = C[c + c * ldc];
    for (int r = c + 1; r < n; ++r) out[idx++ * cp + t] = kSqrt2 * C[r + c * ldc];
  }
}

SETBOUND_INLINE void stacked_congruence_svec_rt(int n, int count, const double* V, long ld, const double* Q, double* P,
                                       double* T, double* out, long cp) {
  const int rows = count * n;
  stacked_mul_rt(rows, n, V, ld, Q, P, ld);
  for (int t = 0; t < count; ++t)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) T[t * n + i + j * ld] = P[t * n + j + i * ld];
  stacked_mul_rt(rows, n, T, ld, Q, P, ld);
  for (int t = 0; t < count; ++t) svec_pack_column(n, P + static_cast<long>(t) * n, ld, out, cp, t);
}

SETBOUND_INLINE double hypot2(double a, double b) {
  const double s2 = a * a + b * b;
  if (s2 > 1e-250 && s2 < 1e250) return std::sqrt(s2);
  const double x = std::abs(a), y = std::abs(b);
  if (x > y) {
    const double r = y / x;
    return x * std::sqrt(1.0 + r * r);
  }
  if (y == 0.0) return 0.0;
  const double r = x / y;
  return y * std::sqrt(1.0 + r * r);
}

SETBOUND_INLINE void tridiagonalize(int n, double* a, double* d, double* e, bool vectors) {
  // The loops run along rows (k innermost in A(i, k)); a symmetric matrix stored by columns is
  // the same array stored by rows, so A is addressed row-major here for contiguous access, and
  // the accumulated Z is transposed back to column-major at the end.
  auto A = [a, n](int i, int j) -> double& { return a[j + static_cast<long>(i) * n]; };
  for (int i = n - 1; i > 0; --i) {
    const int l = i - 1;
    double h = 0.0;
    if (l > 0) {
      double scale = 0.0;
      for (int k = 0; k <= l; ++k) scale += std::abs(A(i, k));
      if (scale == 0.0) {
        e[i] = A(i, l);
      } else {
        for (int k = 0; k <= l; ++k) {
          A(i, k) /= scale;
          h += A(i, k) * A(i, k);
        }
        double f = A(i, l);
        double g = f >= 0.0 ? -std::sqrt(h) : std::sqrt(h);
        e[i] = scale * g;
        h -= f * g;
        A(i, l) = f - g;
        f = 0.0;
        for (int j = 0; j <= l; ++j) {
          if (vectors) A(j, i) = A(i, j) / h;
          g = 0.0;
          for (int k = 0; k <= j; ++k) g += A(j, k) * A(i, k);
          for (int k = j + 1; k <= l; ++k) g += A(k, j) * A(i, k);
          e[j] = g / h;
          f += e[j] * A(i, j);
        }
        const double hh = f / (h + h);
        for (int j = 0; j <= l; ++j) {
          f = A(i, j);
          e[j] = g = e[j] - hh * f;
          for (int k = 0; k <= j; ++k) A(j, k) -= f * e[k] + g * A(i, k);
        }
      }
    } else {
      e[i] = A(i, l);
    }
    d[i] = h;
  }
  d[0] = 0.0;
  e[0] = 0.0;
  if (!vectors) {
    for (int i = 0; i < n; ++i) d[i] = A(i, i);
    return;
  }
  for (int i = 0; i < n; ++i) {
    const int l = i - 1;
    if (d[i] != 0.0) {
      for (int j = 0; j <= l; ++j) {
        double g = 0.0;
        for (int k = 0; k <= l; ++k) g += A(i, k) * A(k, j);
        for (int k = 0; k <= l; ++k) A(k, j) -= g * A(k, i);
      }
    }
    d[i] = A(i, i);
    A(i, i) = 1.0;
    for (int j = 0; j <= l; ++j) A(j, i) = A(i, j) = 0.0;
  }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < j; ++i) std::swap(a[i + static_cast<long>(j) * n], a[j + static_cast<long>(i) * n]);
}

SETBOUND_INLINE bool tridiagonal_ql(int n, double* d, double* e, double* z) {
  for (int i = 1; i < n; ++i) e[i - 1] = e[i];
  e[n - 1] = 0.0;
  constexpr double eps = std::numeric_limits<double>::epsilon();
  for (int l = 0; l < n; ++l) {
    int iter = 0;
    int m;
    do {
      for (m = l; m < n - 1; ++m) {
        const double dd = std::abs(d[m]) + std::abs(d[m + 1]);
        if (std::abs(e[m]) <= eps * dd) break;
      }
      if (m != l) {
        if (iter++ == 60) return false;
        double g = (d[l + 1] - d[l]) / (2.0 * e[l]);
        double r = hypot2(g, 1.0);
        g = d[m] - d[l] + e[l] / (g + (g >= 0.0 ? std::abs(r) : -std::abs(r)));
        double s = 1.0, c = 1.0, p = 0.0;
        int i;
        for (i = m - 1; i >= l; --i) {
          double f = s * e[i];
          const double b = c * e[i];
          e[i + 1] = (r = hypot2(f, g));
          if (r == 0.0) {
            d[i + 1] -= p;
            e[m] = 0.0;
            break;
          }
          const double ir = 1.0 / r;
          s = f * ir;
          c = g * ir;
          g = d[i + 1] - p;
          r = (d[i] - g) * s + 2.0 * c * b;
          d[i + 1] = g + (p = s * r);
          g = c * r - b;
          if (z) {
            double* zi = z + static_cast<long>(i) * n;
            double* zi1 = z + static_cast<long>(i + 1) * n;
            for (int k = 0; k < n; ++k) {
              f = zi1[k];
              zi1[k] = s * zi[k] + c * f;
              zi[k] = c * zi[k] - s * f;
            }
          }
        }
        if (r == 0.0 && i >= l) continue;
        d[l] -= p;
        e[l] = g;
        e[m] = 0.0;
      }
    } while (m != l);
  }
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(d[i])) return false;
  return true;
}

SETBOUND_INLINE double tridiagonal_lambda_min(int n, const double* d, const double* e) {
  double scale = 0.0, x = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    const double r = (i > 0 ? std::abs(e[i]) : 0.0) + (i + 1 < n ? std::abs(e[i + 1]) : 0.0);
    x = std::min(x, d[i] - r);
    scale = std::max(scale, std::abs(d[i]) + r);
  }
  if (!std::isfinite(x) || !std::isfinite(scale)) return std::numeric_limits<double>::quiet_NaN();
  if (scale == 0.0) return 0.0;
  constexpr double eps = std::numeric_limits<double>::epsilon();
  x -= 4.0 * eps * scale;
  const double dn = static_cast<double>(n);
  for (int it = 0; it < 60; ++it) {
    double p0 = 0.0, p1 = 1.0, q0 = 0.0, q1 = 0.0, r0 = 0.0, r1 = 0.0;  // p, p′, p″ at i−1, i
    for (int i = 0; i < n; ++i) {
      const double a = d[i] - x, b = i > 0 ? e[i] * e[i] : 0.0;
      const double p2 = a * p1 - b * p0;
      const double q2 = -p1 + a * q1 - b * q0;
      const double r2 = -2.0 * q1 + a * r1 - b * r0;
      p0 = p1, p1 = p2, q0 = q1, q1 = q2, r0 = r1, r1 = r2;
      const double m = std::abs(p1);
      if (m > 1e100 || (m < 1e-100 && m > 0.0)) {
        const double f = 1.0 / m;
        p0 *= f, p1 *= f, q0 *= f, q1 *= f, r0 *= f, r1 *= f;
      }
    }
    if (!(p1 > 0.0)) return x;  // at (or, by rounding, past) the smallest root: x is safe
    const double G = q1 / p1, H = G * G - r1 / p1;
    const double disc = std::max(0.0, (dn - 1.0) * (dn * H - G * G));
    const double den = G - std::sqrt(disc);  // G < 0 left of every root
    if (!(den < 0.0) || !std::isfinite(den)) return x;
    const double step = -dn / den;  // > 0
    const double xn = x + step;
    if (!(step > 2.0 * eps * std::max(std::abs(x), scale))) return xn;
    x = xn;
  }
  return x;
}

}  // namespace detail
}  // namespace kernels
}  // namespace lmi
}  // namespace setbound

namespace setbound {
namespace lmi {
namespace kernels {

SETBOUND_INLINE bool sym_eig(int n, double* A, double* w, double* e) {
  if (n == 1) {
    w[0] = A[0];
    A[0] = 1.0;
    return std::isfinite(w[0]);
  }
  detail::tridiagonalize(n, A, w, e, true);
  return detail::tridiagonal_ql(n, w, e, A);
}

SETBOUND_INLINE bool sym_eigenvalues(int n, double* A, double* w, double* e) {
  if (n == 1) {
    w[0] = A[0];
    return std::isfinite(w[0]);
  }
  detail::tridiagonalize(n, A, w, e, false);
  return detail::tridiagonal_ql(n, w, e, nullptr);
}

SETBOUND_INLINE double sym_lambda_min(int n, double* A, double* w, double* e) {
  if (n == 1) return std::isfinite(A[0]) ? A[0] : std::numeric_limits<double>::quiet_NaN();
  detail::tridiagonalize(n, A, w, e, false);
  return detail::tridiagonal_lambda_min(n, w, e);
}

SETBOUND_INLINE bool one_sided_jacobi(int n, double* G, double* V, double* sv) {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  for (int i = 0; i < n * n; ++i) V[i] = 0.0;
  for (int i = 0; i < n; ++i) V[i + static_cast<long>(i) * n] = 1.0;
  for (int sweep = 0; sweep < 60; ++sweep) {
    bool rotated = false;
    for (int p = 0; p < n - 1; ++p) {
      for (int q = p + 1; q < n; ++q) {
        double* gp = G + static_cast<long>(p) * n;
        double* gq = G + static_cast<long>(q) * n;
        double a = 0.0, b = 0.0, c = 0.0;
        for (int k = 0; k < n; ++k) {
          a += gp[k] * gp[k];
          b += gq[k] * gq[k];
          c += gp[k] * gq[k];
        }
        if (!(std::abs(c) > 4.0 * eps * std::sqrt(a * b))) {
          if (!std::isfinite(c)) return false;
          continue;
        }
        rotated = true;
        const double zeta = (b - a) / (2.0 * c);
        const double t = (zeta >= 0.0 ? 1.0 : -1.0) / (std::abs(zeta) + std::sqrt(1.0 + zeta * zeta));
        const double cs = 1.0 / std::sqrt(1.0 + t * t), sn = cs * t;
        for (int k = 0; k < n; ++k) {
          const double x = gp[k], y = gq[k];
          gp[k] = cs * x - sn * y;
          gq[k] = sn * x + cs * y;
        }
        double* vp = V + static_cast<long>(p) * n;
        double* vq = V + static_cast<long>(q) * n;
        for (int k = 0; k < n; ++k) {
          const double x = vp[k], y = vq[k];
          vp[k] = cs * x - sn * y;
          vq[k] = sn * x + cs * y;
        }
      }
    }
    if (!rotated) {
      for (int i = 0; i < n; ++i) {
        double s2 = 0.0;
        const double* gi = G + static_cast<long>(i) * n;
        for (int k = 0; k < n; ++k) s2 += gi[k] * gi[k];
        sv[i] = std::sqrt(s2);
        if (!std::isfinite(sv[i])) return false;
      }
      return true;
    }
  }
  return false;
}

SETBOUND_INLINE unsigned sym_eig_batch(int n, int count, double* const* A, double* const* w) {
#if defined(__GNUC__)
  if (count < 1 || count > 4) return 0u;
  return with_size(n, [&](auto N) -> unsigned {  // N = 0 above kFixedMax: not handled either
    constexpr int Nv = decltype(N)::value;
    if constexpr (Nv < 2 || Nv > kEigBatchMax) return 0u;
    else return detail::sym_eig_batch_fixed<Nv>(count, A, w);
  });
#else
  (void)n, (void)count, (void)A, (void)w;
  return 0u;
#endif
}

SETBOUND_INLINE void svec_pack(int n, const double* X, double* v) {
  with_size(n, [&](auto N) {
    if constexpr (decltype(N)::value == 0) detail::svec_pack_rt(n, X, v);
    else fixed::svec_pack<decltype(N)::value>(X, v);
  });
}

SETBOUND_INLINE void svec_unpack(int n, const double* v, double* X) {
  with_size(n, [&](auto N) {
    if constexpr (decltype(N)::value == 0) detail::svec_unpack_rt(n, v, X);
    else fixed::svec_unpack<decltype(N)::value>(v, X);
  });
}

SETBOUND_INLINE void stacked_mul(int rows, int n, const double* V, long ldv, const double* Q, double* P, long ldp) {
  with_size(n, [&](auto N) {
    if constexpr (decltype(N)::value == 0) detail::stacked_mul_rt(rows, n, V, ldv, Q, P, ldp);
    else fixed::stacked_mul<decltype(N)::value>(rows, V, ldv, Q, P, ldp);
  });
}

SETBOUND_INLINE void cholesky_solve(int n, const double* L, const double* U, const double* dinv, double* b) {
  for (int j = 0; j < n; ++j) {  // L y = b, by columns of L
    const double* Lj = L + static_cast<long>(j) * n;
    const double yj = b[j] * dinv[j];
    b[j] = yj;
    for (int i = j + 1; i < n; ++i) b[i] -= Lj[i] * yj;
  }
  for (int j = n - 1; j >= 0; --j) {  // Lᵀ x = y, by columns of U = Lᵀ
    const double* Uj = U + static_cast<long>(j) * n;
    const double xj = b[j] * dinv[j];
    b[j] = xj;
    for (int i = 0; i < j; ++i) b[i] -= Uj[i] * xj;
  }
}

}  // namespace kernels
}  // namespace lmi
}  // namespace setbound
