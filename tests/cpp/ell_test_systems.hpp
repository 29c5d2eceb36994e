// The example systems of the ellipsoidal papers, shared by the ellipsoidal C++ tests.
#pragma once

#include <Eigen/Core>

#include "setbound/core/linear_system.hpp"
#include "setbound/estimators/ellipsoidal/descriptor.hpp"

namespace setbound::testing {

/// EX-BC14 (papers.md §1.4): 3 states, 2 outputs, 5 disturbances.
inline LinearSystem bc14() {
  Eigen::MatrixXd A(3, 3), E(3, 5), C(2, 3), F(2, 5);
  A << 1, 0, 0.2, 0, 0.8, 1, 0, 0, 1;
  E << 0.1, 0, 0, 0, 0, 0, 0.05, 0, 0, 0, 0, 0, 0.05, 0, 0;
  C << 1, 0, 2, 0, -1, 1;
  F << 0, 0, 0, 0.15, 0, 0, 0, 0, 0, 0.15;
  return LinearSystem(A, C, E, F);
}

/// EX-ME17a / EX-ME17b (papers.md §2.5), ω = [w; v]; a_rad > 0 makes A(0,0) and A(1,1) uncertain.
inline LinearSystem me17(bool unstable, double a_rad = 0.0) {
  Eigen::MatrixXd A(2, 2), E(2, 2), C(1, 2), F(1, 2);
  A << (unstable ? -1.5 : -0.8), 0.2, -0.3, 0.1;
  E << -0.12, 0, 0.02, 0;
  C << -2, 1;
  F << 0, 0.2;
  if (a_rad == 0.0) return LinearSystem(A, C, E, F);
  Eigen::MatrixXd Arad = Eigen::MatrixXd::Zero(2, 2);
  Arad(0, 0) = Arad(1, 1) = a_rad;
  return LinearSystem(A, C, E, F, {}, {}, Arad);
}

// EX-ME19 (papers §4.2): the descriptor example.
inline DescriptorSystem me19() {
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(3, 3), A(3, 3), B(3, 2), C(2, 3), D(3, 5), F(2, 5);
  E(0, 0) = E(1, 1) = 1;
  A << 0.5, 0, 0, 0.8, 0.95, 0, -1, 0.5, 1;
  B << 1, 0, 0, 1, 0, 0;
  C << 1, 0, 1, 1, -1, 0;
  D << 0.1, 0, 0, 0, 0, 0, 1.5, 0, 0, 0, 0, 0, 0.6, 0, 0;
  F << 0, 0, 0, 0.5, 0, 0, 0, 0, 0, 1.5;
  return DescriptorSystem(E, A, C, D, F, B);
}

}  // namespace setbound::testing
