// setbound — definitions of the functions declared in setbound/estimators/zonotopic/strip_swap.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/zonotopic/strip_swap.hpp"
#include "setbound/core/config.hpp"

#include <cmath>

namespace setbound {
namespace detail {

SETBOUND_INLINE void strip_swap_terms(const Eigen::VectorXd& p, const Eigen::VectorXd& lam,
                                      const Eigen::VectorXd& abs_lam, const Eigen::Ref<const Eigen::VectorXd>& c,
                                      double y, const Eigen::VectorXd& w, double g, Eigen::VectorXd& pn,
                                      Eigen::VectorXd& abs_p, Eigen::VectorXd& box) {
  const auto ac = c.cwiseAbs();  // an expression: no vector allocated per strip
  const double innov = y - c.dot(p);
  pn = p + lam * innov;
  abs_p = p.cwiseAbs();
  box += 2.0 * g * (abs_p + abs_lam * (std::abs(y) + ac.dot(abs_p)) + pn.cwiseAbs());  // the centre
  box += 2.0 * g * (w + abs_lam * ac.dot(w));                                          // the generators
}

}  // namespace detail
}  // namespace setbound
