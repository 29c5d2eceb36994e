// setbound — the thesis examples the C++ tests share (one definition instead of a copy per file).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "setbound/thesis/lpv.hpp"
#include "setbound/thesis/plant.hpp"

namespace setbound::testing {

/// Ch. 2 example (thesis.md §4.8): x⁺ = [0.2 0.2; 0 0.5] x + [1; 1] u + [0; 0.1] d, y = x_1 + 0.1 v.
inline thesis::Plant ch2_plant() {
  Eigen::MatrixXd A(2, 2), B(2, 1), F(2, 1), C(1, 2), Z(1, 1);
  A << 0.2, 0.2, 0, 0.5;
  B << 1, 1;
  F << 0, 0.1;
  C << 1, 0;
  Z << 0.1;
  return thesis::Plant(A, B, C, F, Z);
}

/// Ch. 3 Ex 1 (thesis.md §5): A(ρ) = [1 ρ; 0 1], B(ρ) = F(ρ) = [0; ρ], ρ ∈ [0.05, 0.1],
/// y = x_1 + z v (the thesis: z = 0.01).
inline thesis::LpvSystem ch3_ex1(double z = 0.01) {
  std::vector<Eigen::MatrixXd> A, B, F;
  for (double r : {0.05, 0.1}) {
    Eigen::MatrixXd a(2, 2), b(2, 1);
    a << 1, r, 0, 1;
    b << 0, r;
    A.push_back(a);
    B.push_back(b);
    F.push_back(b);
  }
  Eigen::MatrixXd C(1, 2), Zm(1, 1), theta(2, 1);
  C << 1, 0;
  Zm << z;
  theta << 0.05, 0.1;
  return thesis::LpvSystem(A, B, F, C, Zm, theta);
}

}  // namespace setbound::testing
