// setbound — definitions of the functions declared in setbound/estimators/zonotopic/volume_min.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/zonotopic/volume_min.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace detail {

SETBOUND_INLINE Eigen::VectorXd cofactor_vector(const Eigen::MatrixXd& M) {
  const Eigen::Index n = M.rows();
  Eigen::VectorXd w(n);
  if (n == 1) {
    w(0) = 1.0;
    return w;
  }
  Eigen::MatrixXd minor(n - 1, n - 1);
  for (Eigen::Index i = 0; i < n; ++i) {
    minor.topRows(i) = M.topRows(i);
    minor.bottomRows(n - 1 - i) = M.bottomRows(n - 1 - i);
    w(i) = ((i % 2) ? -1.0 : 1.0) * minor.determinant();
  }
  return w;
}

}  // namespace detail
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE Eigen::VectorXd volume_min_gain(const Zonotope& Z, const StripMeasurement& meas) {
  const Eigen::Index n = Z.dimension(), m = Z.num_generators();
  const Eigen::MatrixXd& H = Z.generators();
  const Eigen::VectorXd& c = meas.strip.normal();
  const double phi = meas.strip.half_width();
  if (detail::binomial(m, n - 1) > kVolumeMinMaxSubsets)
    throw InvalidArgumentError("volume_min_gain: C(" + std::to_string(m) + ", " + std::to_string(n - 1) +
                               ") generator subsets exceed the limit of " +
                               std::to_string(static_cast<long>(kVolumeMinMaxSubsets)) +
                               "; reduce the zonotope order or use segment minimisation");
  double a = 0.0;
  if (m >= n) {
    Eigen::MatrixXd HS(n, n);
    detail::for_each_subset(m, n, [&](const std::vector<Eigen::Index>& idx) {
      for (Eigen::Index j = 0; j < n; ++j) HS.col(j) = H.col(idx[static_cast<std::size_t>(j)]);
      a += std::abs(HS.determinant());
    });
  }
  std::vector<Eigen::VectorXd> w;
  {
    Eigen::MatrixXd HT(n, n - 1);
    detail::for_each_subset(m, n - 1, [&](const std::vector<Eigen::Index>& idx) {
      for (Eigen::Index j = 0; j + 1 < n; ++j) HT.col(j) = H.col(idx[static_cast<std::size_t>(j)]);
      Eigen::VectorXd wt = detail::cofactor_vector(HT);
      if (wt.cwiseAbs().maxCoeff() > 0) w.push_back(std::move(wt));
    });
  }
  if (w.empty() || phi == 0.0) return segment_min_gain(Z, meas);
  // Rows: a |cᵀλ − 1| and φ |w_Tᵀλ|.
  const Eigen::Index T = static_cast<Eigen::Index>(w.size()) + 1;
  Eigen::MatrixXd G(T, n);
  Eigen::VectorXd h = Eigen::VectorXd::Zero(T), gamma(T);
  G.row(0) = c.transpose();
  h(0) = 1.0;
  gamma(0) = a;
  for (std::size_t t = 0; t < w.size(); ++t) {
    G.row(static_cast<Eigen::Index>(t) + 1) = w[t].transpose();
    gamma(static_cast<Eigen::Index>(t) + 1) = phi;
  }
  if (!G.allFinite() || !std::isfinite(a)) return segment_min_gain(Z, meas);
  const lmi::WeightedL1Result res = lmi::minimize_weighted_l1(G, h, gamma);
  if (!(res.converged || res.relative_gap <= 1e-6)) return segment_min_gain(Z, meas);
  Eigen::VectorXd lambda = res.x;
  if (!lambda.allFinite()) return segment_min_gain(Z, meas);
  return lambda;
}

}  // namespace setbound
