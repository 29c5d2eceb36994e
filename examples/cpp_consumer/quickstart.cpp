#include <setbound/setbound.hpp>
#include <iostream>
using namespace setbound;

int main() {
  Eigen::MatrixXd A(2, 2), C(2, 2), E(2, 3), F(2, 3), Y(3, 2);
  A << 0, -0.5, 1, 1;             C << -2, 1, 1, 1;
  E << -0.12, 0, 0, 0.02, 0, 0;   F << 0, 0.2, 0, 0, 0, 0.2;
  Y << 0.1, -0.2, 0.3, 0.1, -0.1, 0.2;               // y_0, y_1, y_2
  ZonotopicEstimator est(LinearSystem(A, C, E, F), Zonotope(Eigen::Vector2d::Zero(), 3 * Eigen::Matrix2d::Identity()),
                         segment_min_gain);
  ZonotopeTrajectory t = est.run(Y);                  // row k: guaranteed bounds of x_k
  std::cout << t.lower.row(2) << "\n" << t.upper.row(2) << "\n";
}
