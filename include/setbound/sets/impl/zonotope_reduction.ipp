// setbound — definitions of the functions declared in setbound/sets/zonotope_reduction.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/sets/zonotope_reduction.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace rounding_bounds {

SETBOUND_INLINE double gamma(Eigen::Index k) {
  const double ku = static_cast<double>(k + 2) * kUnitRoundoff;
  return 2.0 * ku / (1.0 - ku);
}

}  // namespace rounding_bounds
}  // namespace setbound

namespace setbound {
namespace detail {

SETBOUND_INLINE void reserve_reduction_workspace(ReductionWorkspace& ws, Eigen::Index n, Eigen::Index capacity) {
  if (ws.key.size() < capacity) ws.key.resize(capacity);
  ws.order.reserve(static_cast<std::size_t>(capacity));
  if (ws.Gred.rows() != n || ws.Gred.cols() < capacity) ws.Gred.resize(n, capacity);
  if (ws.QtG.rows() != n || ws.QtG.cols() < capacity) ws.QtG.resize(n, capacity);
}

SETBOUND_INLINE void reduction_keys(ZonotopeReduction method, const Eigen::MatrixXd& H, Eigen::Index m, Eigen::VectorXd& key,
                                    Eigen::Index from) {
  if (key.size() < m) key.conservativeResize(std::max<Eigen::Index>(m, 2 * key.size()));
  const Eigen::Index n = H.rows();
  const bool euclid = method == ZonotopeReduction::Combastel;
  double* out = key.data();
  switch (n) {
    case 1: return reduction_keys_fixed<1>(euclid, H, from, m, out);
    case 2: return reduction_keys_fixed<2>(euclid, H, from, m, out);
    case 3: return reduction_keys_fixed<3>(euclid, H, from, m, out);
    case 4: return reduction_keys_fixed<4>(euclid, H, from, m, out);
    case 5: return reduction_keys_fixed<5>(euclid, H, from, m, out);
    case 6: return reduction_keys_fixed<6>(euclid, H, from, m, out);
    case 7: return reduction_keys_fixed<7>(euclid, H, from, m, out);
    case 8: return reduction_keys_fixed<8>(euclid, H, from, m, out);
    default: break;
  }
  const double* base = H.data();
  // Four columns at a time: independent accumulators instead of one dependency chain.
  Eigen::Index j = from;
  for (; j + 4 <= m; j += 4) {
    const double* g0 = base + j * n;
    const double *g1 = g0 + n, *g2 = g1 + n, *g3 = g2 + n;
    double a0 = 0, a1 = 0, a2 = 0, a3 = 0, b0 = 0, b1 = 0, b2 = 0, b3 = 0;
    if (euclid) {
      for (Eigen::Index i = 0; i < n; ++i) a0 += g0[i] * g0[i], a1 += g1[i] * g1[i], a2 += g2[i] * g2[i], a3 += g3[i] * g3[i];
      out[j] = std::sqrt(a0), out[j + 1] = std::sqrt(a1), out[j + 2] = std::sqrt(a2), out[j + 3] = std::sqrt(a3);
    } else {  // ‖g‖₁ − ‖g‖∞ (MATLAB: vecnorm(G,1,1) − vecnorm(G,Inf,1))
      for (Eigen::Index i = 0; i < n; ++i) {
        const double x0 = std::abs(g0[i]), x1 = std::abs(g1[i]), x2 = std::abs(g2[i]), x3 = std::abs(g3[i]);
        a0 += x0, a1 += x1, a2 += x2, a3 += x3;
        b0 = std::max(b0, x0), b1 = std::max(b1, x1), b2 = std::max(b2, x2), b3 = std::max(b3, x3);
      }
      out[j] = a0 - b0, out[j + 1] = a1 - b1, out[j + 2] = a2 - b2, out[j + 3] = a3 - b3;
    }
  }
  for (; j < m; ++j) {
    const double* g = base + j * n;
    double a = 0, b = 0;
    if (euclid) {
      for (Eigen::Index i = 0; i < n; ++i) a += g[i] * g[i];
      out[j] = std::sqrt(a);
    } else {
      for (Eigen::Index i = 0; i < n; ++i) a += std::abs(g[i]), b = std::max(b, std::abs(g[i]));
      out[j] = a - b;
    }
  }
}

SETBOUND_INLINE Eigen::Index compact_sum_keys(ZonotopeReduction method, Eigen::MatrixXd& W, Eigen::Index m,
                                              Eigen::VectorXd& w, Eigen::VectorXd& key) {
  if (key.size() < m) key.conservativeResize(std::max<Eigen::Index>(m, 2 * key.size()));
  const bool euclid = method == ZonotopeReduction::Combastel;
  double* out = key.data();
  switch (W.rows()) {
    case 1: return compact_sum_keys_fixed<1>(euclid, W, m, w, out);
    case 2: return compact_sum_keys_fixed<2>(euclid, W, m, w, out);
    case 3: return compact_sum_keys_fixed<3>(euclid, W, m, w, out);
    case 4: return compact_sum_keys_fixed<4>(euclid, W, m, w, out);
    case 5: return compact_sum_keys_fixed<5>(euclid, W, m, w, out);
    case 6: return compact_sum_keys_fixed<6>(euclid, W, m, w, out);
    case 7: return compact_sum_keys_fixed<7>(euclid, W, m, w, out);
    case 8: return compact_sum_keys_fixed<8>(euclid, W, m, w, out);
    default: {
      const Eigen::Index k = compact_and_sum(W, m, w, true);
      reduction_keys(method, W, k, key);
      return k;
    }
  }
}

SETBOUND_INLINE void axis_box(const Eigen::VectorXd& wred, const Eigen::VectorXd* r, Eigen::Index count, Eigen::VectorXd& s) {
  const double infl = 1.0 + static_cast<double>(count + 4) * std::numeric_limits<double>::epsilon();
  s = wred;
  if (r) s += *r;
  s *= infl;
}

SETBOUND_INLINE bool pca_box(const Eigen::VectorXd* r, Eigen::Index k, ReductionWorkspace& ws) {
  using rounding_bounds::gamma;
  const double u = rounding_bounds::kUnitRoundoff;
  const Eigen::Index n = ws.Gred.rows();
  const auto Gred = ws.Gred.leftCols(k);
  ws.eig.compute(ws.gram);
  if (ws.eig.info() != Eigen::Success) return false;
  // Descending eigenvalues, as CORA's svd(cov) orders its basis.
  ws.Q = ws.eig.eigenvectors().rowwise().reverse();
  ws.QtQ.noalias() = ws.Q.transpose() * ws.Q;
  const Eigen::MatrixXd& absQ = ws.absQ = ws.Q.cwiseAbs();
  ws.bound = (ws.QtQ - Eigen::MatrixXd::Identity(n, n)).cwiseAbs() * (1.0 + u);
  ws.bound.noalias() += (gamma(n) + 3.0 * u) * (absQ.transpose() * absQ);
  const double f = ws.bound.rowwise().sum().maxCoeff() * (1.0 + gamma(n));
  if (!(f < 0.5)) return false;
  const double eta = f * std::sqrt(1.0 + f) / (1.0 - f) * (1.0 + 4.0 * u);
  double mass = 0.0;  // Σ‖g_j‖₂ + ‖r‖₂
  for (Eigen::Index j = 0; j < k; ++j) mass += Gred.col(j).norm();
  if (r) mass += r->norm();
  if (ws.QtG.rows() != n || ws.QtG.cols() < k) ws.QtG.resize(n, std::max<Eigen::Index>(k, 2 * ws.QtG.cols()));
  ws.Qt = ws.Q.transpose();
  transform_generators(ws.Qt, ws.Gred, ws.QtG, k);
  ws.s = ws.QtG.leftCols(k).cwiseAbs().rowwise().sum();
  ws.s.noalias() += (gamma(n) + u) * (absQ.transpose() * ws.wred);
  if (r) ws.s.noalias() += (1.0 + u) * (absQ.transpose() * *r);
  ws.s.array() += eta * mass;
  ws.s *= 1.0 + gamma(k + n + 8);
  // fl(Q_ij s_j) has relative error <= u only for normal results: refuse tiny boxes.
  if (!(ws.s.minCoeff() > 1e-280) || !ws.s.allFinite()) return false;
  ws.W = ws.Q * ws.s.asDiagonal();
  return true;
}

SETBOUND_INLINE Eigen::Index reduce_in_place(ZonotopeReduction method, Eigen::MatrixXd& H, Eigen::Index m, Eigen::Index limit,
                                             const Eigen::VectorXd* r, ReductionWorkspace& ws, bool want_gram, bool keys_ready,
                                             Eigen::VectorXd* w) {
  const Eigen::Index n = H.rows();
  ws.reduced_count = 0;
  if (m <= limit) return m;
  const Eigen::Index keep = limit - n, nred = m - keep;
  // Which columns: the nred smallest keys, ties to the lower index (MATLAB mink).
  if (!keys_ready) reduction_keys(method, H, m, ws.key);
  const double* key = ws.key.data();
  auto less = [key](Eigen::Index a, Eigen::Index b) { return key[a] < key[b] || (key[a] == key[b] && a < b); };
  ws.order.clear();
  if (nred * 16 < m) {
    // Few to reduce (the estimators' steady state): a max-heap of the nred smallest so far.
    // A column at or above the heap's top key cannot enter: one comparison, no call.
    for (Eigen::Index j = 0; j < m; ++j) {
      if (static_cast<Eigen::Index>(ws.order.size()) < nred) {
        ws.order.push_back(j);
        std::push_heap(ws.order.begin(), ws.order.end(), less);
      } else if (key[j] < key[ws.order.front()]) {  // j > every index in the heap: ties stay out
        std::pop_heap(ws.order.begin(), ws.order.end(), less);
        ws.order.back() = j;
        std::push_heap(ws.order.begin(), ws.order.end(), less);
      }
    }
  } else {
    ws.order.resize(static_cast<std::size_t>(m));
    std::iota(ws.order.begin(), ws.order.end(), Eigen::Index{0});
    if (nred < m)
      std::nth_element(ws.order.begin(), ws.order.begin() + static_cast<std::ptrdiff_t>(nred), ws.order.end(), less);
    ws.order.resize(static_cast<std::size_t>(nred));
  }
  std::sort(ws.order.begin(), ws.order.end());  // the reduced columns, in index order
  // Gather the reduced columns and close the gaps.
  if (ws.Gred.rows() != n || ws.Gred.cols() < nred) ws.Gred.resize(n, std::max<Eigen::Index>(nred, 2 * ws.Gred.cols()));
  double* const base = H.data();
  Eigen::Index kk = 0;
  // Fixed n: one pass that also sums the kept columns (the caller's row sums); otherwise runs
  // of kept columns move as blocks.
  double acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  const Eigen::Index* const reduced = ws.order.data();
  double* const gred = ws.Gred.data();
  bool summed = true;
  switch (n) {
    case 1: kk = gather_and_sum_fixed<1>(base, m, reduced, nred, gred, acc); break;
    case 2: kk = gather_and_sum_fixed<2>(base, m, reduced, nred, gred, acc); break;
    case 3: kk = gather_and_sum_fixed<3>(base, m, reduced, nred, gred, acc); break;
    case 4: kk = gather_and_sum_fixed<4>(base, m, reduced, nred, gred, acc); break;
    case 5: kk = gather_and_sum_fixed<5>(base, m, reduced, nred, gred, acc); break;
    case 6: kk = gather_and_sum_fixed<6>(base, m, reduced, nred, gred, acc); break;
    case 7: kk = gather_and_sum_fixed<7>(base, m, reduced, nred, gred, acc); break;
    case 8: kk = gather_and_sum_fixed<8>(base, m, reduced, nred, gred, acc); break;
    default: {
      summed = false;
      Eigen::Index from = 0;
      for (Eigen::Index t = 0; t < nred; ++t) {
        const Eigen::Index j = ws.order[static_cast<std::size_t>(t)];
        std::copy(base + j * n, base + (j + 1) * n, ws.Gred.data() + t * n);
        if (j > from) {
          if (kk != from) std::memmove(base + kk * n, base + from * n, static_cast<std::size_t>((j - from) * n) * sizeof(double));
          kk += j - from;
        }
        from = j + 1;
      }
      if (m > from) {
        if (kk != from) std::memmove(base + kk * n, base + from * n, static_cast<std::size_t>((m - from) * n) * sizeof(double));
        kk += m - from;
      }
    }
  }
  const auto Gred = ws.Gred.leftCols(nred);
  ws.wred = Gred.cwiseAbs().rowwise().sum() * (1.0 + static_cast<double>(nred + 2) * std::numeric_limits<double>::epsilon());
  if (method == ZonotopeReduction::Pca || want_gram) gram(ws.Gred, nred, ws.gram);
  bool boxed = false;
  if (method == ZonotopeReduction::Pca) boxed = pca_box(r, nred, ws);
  if (!boxed) {
    axis_box(ws.wred, r, nred, ws.s);
    ws.W = ws.s.asDiagonal();
  }
  // Append the non-zero box columns (CORA keeps zero ones, but never counts them).
  for (Eigen::Index i = 0; i < n; ++i)
    if (ws.W.col(i).cwiseAbs().maxCoeff() > 0) {
      H.col(kk++) = ws.W.col(i);
      if (summed)
        for (Eigen::Index l = 0; l < n; ++l) acc[l] += std::abs(ws.W(l, i));
    }
  ws.reduced_count = nred;
  if (w) {
    if (summed) {
      w->resize(n);
      const double infl = 1.0 + static_cast<double>(kk + 2) * std::numeric_limits<double>::epsilon();
      for (Eigen::Index l = 0; l < n; ++l) (*w)(l) = acc[l] * infl;
    } else {
      compact_and_sum(H, kk, *w, false);
    }
  }
  return kk;
}

SETBOUND_INLINE Eigen::Index finish_generators(ZonotopeReduction method, Eigen::MatrixXd& W, Eigen::Index m, Eigen::Index limit,
                                               bool reduce, double box_threshold, Eigen::VectorXd& r, Eigen::VectorXd& w,
                                               ReductionWorkspace& ws, Eigen::MatrixXd* S, double negligible) {
  const Eigen::Index n = W.rows();
  ws.reduced_count = 0;
  // The keys come with the pass that drops zero columns when a reduction may follow (a box
  // adds at most n columns).
  const bool keys = reduce && m + n > limit;
  Eigen::Index k = keys ? compact_sum_keys(method, W, m, w, ws.key) : compact_and_sum(W, m, w, true);
  // Negligible columns join the pending box (w stays a bound; S loses far less than its rounding).
  if (negligible > 0.0) k = absorb_negligible(W, k, w, negligible, r, keys ? ws.key.data() : nullptr);
  bool boxed = false;
  const double scale = k > 0 ? w.maxCoeff() : 0.0;
  if (r.maxCoeff() > box_threshold * scale) {
    // A pending box that is no longer negligible becomes generators (counted).
    const Eigen::Index k0 = k;
    for (Eigen::Index i = 0; i < n; ++i)
      if (r(i) > 0) {
        W.col(k).setZero();
        W(i, k++) = r(i);
        if (S) (*S)(i, i) += r(i) * r(i);
      }
    r.setZero();
    if (keys) reduction_keys(method, W, k, ws.key, k0);
    boxed = true;
  }
  if (reduce && k > limit) {
    const Eigen::Index before = k;
    k = reduce_in_place(method, W, k, limit, &r, ws, S != nullptr, keys, &w);
    r.setZero();
    if (S) {
      // The reduced columns leave, their box columns (the last ones) come in.
      const Eigen::Index box_cols = k - (before - ws.reduced_count);
      *S -= ws.gram;
      add_gram(W, k - box_cols, box_cols, *S);
    }
    return k;
  }
  if (boxed) compact_and_sum(W, k, w, false);
  return k;
}

}  // namespace detail
}  // namespace setbound
