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

/// S = G.leftCols(m) G.leftCols(m)ᵀ (n × n, symmetric; the Gram matrix the gain rules use).
void gram(const Eigen::MatrixXd& G, Eigen::Index m, Eigen::MatrixXd& S);

/// Σ_j |g_jᵀ t| over the first m columns of G (t of length n): the support of G B^m in the
/// direction t, in one pass without a temporary.
double abs_projection_sum(const Eigen::MatrixXd& G, Eigen::Index m, const Eigen::Ref<const Eigen::VectorXd>& t);

/// Removes exactly-zero columns among the first m of W (keeping the order) when `drop_zeros`,
/// and sets w = rs|W| over the kept columns, rounded up (a bound of the computed sums). Returns
/// the kept column count.
Eigen::Index compact_and_sum(Eigen::MatrixXd& W, Eigen::Index m, Eigen::VectorXd& w, bool drop_zeros = true);

template <int N>
void transform_generators_fixed(const Eigen::MatrixXd& T, const Eigen::MatrixXd& G, Eigen::MatrixXd& W, Eigen::Index m) {
  const Eigen::Matrix<double, N, N> Tf = T;
  Eigen::Map<const Eigen::Matrix<double, N, Eigen::Dynamic>> Gm(G.data(), N, m);
  Eigen::Map<Eigen::Matrix<double, N, Eigen::Dynamic>> Wm(W.data(), N, m);
  Wm.noalias() = Tf.lazyProduct(Gm);
}

template <int N>
void gram_fixed(const Eigen::MatrixXd& G, Eigen::Index m, Eigen::MatrixXd& S) {
  // Column by column (rank-1 updates of a register-sized matrix): the row-times-row form of
  // Gm Gmᵀ reads the columns with a stride of N and was 3× slower.
  using Col = Eigen::Matrix<double, N, 1>;
  Eigen::Matrix<double, N, N> Sf = Eigen::Matrix<double, N, N>::Zero();
  const double* const base = G.data();
  for (Eigen::Index j = 0; j < m; ++j) {
    const Eigen::Map<const Col> g(base + j * N);
    Sf.noalias() += g * g.transpose();
  }
  S = Sf;
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
