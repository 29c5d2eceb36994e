// setbound — definitions of the functions declared in setbound/estimators/measurement_check.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/measurement_check.hpp"
#include "setbound/core/config.hpp"

#include <cmath>

#include <algorithm>
#include <sstream>

#include "setbound/core/error.hpp"

namespace setbound {

SETBOUND_INLINE bool MeasurementCheck::flagged() const { return first_inconsistent() >= 0; }

SETBOUND_INLINE Eigen::Index MeasurementCheck::first_inconsistent() const {
  for (std::size_t i = 0; i < status.size(); ++i)
    if (status[i] == OutputStatus::Inconsistent) return static_cast<Eigen::Index>(i);
  return -1;
}

SETBOUND_INLINE double gram_radius_lower_bound(double tSt, double S_max, double t2) {
  const double q2 = tSt - 1e-10 * S_max * t2;
  return q2 > 0 ? 0.9 * std::sqrt(q2) : 0.0;
}

SETBOUND_INLINE OutputTest test_output(double y, double center, double radius, double phi, double magnitude,
                                       Eigen::Index terms) {
  // gap > 0: the reading lies outside center ± (radius + φ) by gap.
  const double gap = std::abs(y - center) - radius - phi;
  // Each rounded term is off by at most γ_terms times its magnitude (Higham, Thm 3.5); the
  // factor 2 covers the subtraction and the comparison themselves. kReadingSlack covers the
  // reading itself: a measurement computed in floating point (a simulator, a sensor's own
  // arithmetic) is off by a few ulps of ITS terms, which can add up over a long simulated run.
  const double k = static_cast<double>(terms + 4) * std::numeric_limits<double>::epsilon();
  const double gamma = k / (1.0 - k);
  const double tol = (2.0 * gamma + kReadingSlack) * (magnitude + std::abs(y) + phi) +
                     std::numeric_limits<double>::denorm_min();
  const double scale = phi > 0 ? phi : 1.0;
  return {gap / scale, gap > tol};
}

SETBOUND_INLINE void require_no_infinity(const Eigen::Ref<const Eigen::VectorXd>& y, const std::string& name) {
  for (Eigen::Index i = 0; i < y.size(); ++i)
    if (std::isinf(y(i))) {
      std::ostringstream s;
      s << name << ": entry " << i << " is " << y(i) << "; a reading must be finite (NaN marks a missing one)";
      throw NotFiniteError(s.str());
    }
}

SETBOUND_INLINE void throw_inconsistent(Eigen::Index step, Eigen::Index output, double y, double center, double radius,
                                        double phi, double margin) {
  std::ostringstream s;
  s.precision(6);
  s << "step " << step << ": output " << output << ": the reading " << y
    << " cannot be produced by the model: the predicted output set is [" << (center - radius - phi) << ", "
    << (center + radius + phi) << "] and the reading lies " << margin
    << (phi > 0 ? " noise bounds" : "") << " outside it (a fault, a glitch or a wrong model)";
  throw InconsistentMeasurementError(s.str());
}

}  // namespace setbound
