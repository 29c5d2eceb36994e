// setbound — definitions of the functions declared in setbound/estimators/ellipsoidal/common.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/ellipsoidal/common.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace ell_rounding {

SETBOUND_INLINE double gamma(Eigen::Index k) {
  const double ku = static_cast<double>(k + 2) * (kEps / 2);
  return 2.0 * ku / (1.0 - ku);
}

SETBOUND_INLINE double round_up(double x) { return x >= 0 ? x * (1.0 + 4.0 * kEps) + std::numeric_limits<double>::denorm_min()
                                                 : x * (1.0 - 4.0 * kEps); }

SETBOUND_INLINE double lambda_max_upper(const Eigen::MatrixXd& P) {
  return round_up(P.cwiseAbs().rowwise().sum().maxCoeff() * (1.0 + gamma(P.cols())));
}

}  // namespace ell_rounding
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE bool certify_psd(const Eigen::MatrixXd& M, double absolute_slack, double relative_slack) {
  const Eigen::Index n = M.rows();
  if (n == 0) return true;
  if (M.cols() != n || !M.allFinite()) return false;
  const double tr = M.diagonal().cwiseAbs().sum();
  const double delta = ell_rounding::gamma(n + 1) * tr * 4.0 + relative_slack * tr + absolute_slack;
  Eigen::MatrixXd S = 0.5 * (M + M.transpose());
  S.diagonal().array() -= delta;
  Eigen::LLT<Eigen::MatrixXd> llt(S);
  return llt.info() == Eigen::Success;
}

SETBOUND_INLINE Eigen::VectorXd center_rounding_bound(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                             const Eigen::MatrixXd& L, const Eigen::MatrixXd& C,
                                             const Eigen::MatrixXd& D, const Eigen::VectorXd& c,
                                             const Eigen::VectorXd& y, const Eigen::VectorXd& u) {
  using ell_rounding::gamma;
  const Eigen::VectorXd ac = c.cwiseAbs(), au = u.cwiseAbs();
  // innovation e = y − C c − D u and its magnitude bound
  Eigen::VectorXd e_mag = y.cwiseAbs() + C.cwiseAbs() * ac;
  if (D.size() > 0 && u.size() > 0) e_mag += D.cwiseAbs() * au;
  const Eigen::Index k = A.cols() + (B.size() > 0 ? B.cols() : 0) + L.cols() + 4;
  Eigen::VectorXd mag = A.cwiseAbs() * ac + L.cwiseAbs() * e_mag;
  if (B.size() > 0 && u.size() > 0) mag += B.cwiseAbs() * au;
  return ell_rounding::round_up(2.0 * gamma(k)) * mag;
}

SETBOUND_INLINE double level_with_center_error(double rho, double lambda_max_upper, const Eigen::VectorXd& d) {
  using ell_rounding::round_up;
  const double dn = round_up(d.norm());
  const double s = round_up(std::sqrt(round_up(rho))) + round_up(std::sqrt(lambda_max_upper) * dn);
  return round_up(round_up(s) * round_up(s));
}

}  // namespace setbound
