// setbound — shared helpers for the GoogleTest suites.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace setbound::testing {

/// Bit-for-bit equality of two double vectors (saved states, replayed runs): NaN payloads and
/// signed zeros count. empty() first: memcmp with the null data() of an empty vector is undefined.
inline bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

/// gtest predicate: matrices of equal shape whose entries differ by at most `tol`.
template <class A, class B>
::testing::AssertionResult eigen_near(const char* ea, const char* eb, const char*,
                                      const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b,
                                      double tol) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    return ::testing::AssertionFailure() << ea << " is " << a.rows() << "x" << a.cols() << " but "
                                         << eb << " is " << b.rows() << "x" << b.cols();
  const double diff = (a - b).cwiseAbs().maxCoeff();
  if (diff <= tol) return ::testing::AssertionSuccess();
  std::ostringstream s;
  s << ea << " and " << eb << " differ by " << diff << " > " << tol << "\n"
    << ea << " =\n" << a << "\n" << eb << " =\n" << b;
  return ::testing::AssertionFailure() << s.str();
}

/// Runs f, which must throw Err with a message starting "<name>:" (errors name their argument).
template <class Err, class F>
void expect_error_naming(F&& f, const std::string& name) {
  try {
    f();
    ADD_FAILURE() << "expected an exception naming " << name;
  } catch (const Err& e) {
    EXPECT_EQ(std::string(e.what()).rfind(name + ":", 0), 0u) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

/// A disturbance drawn uniformly in the unit box [-1, 1]^n, or at one of its vertices (each
/// component ±1 with equal probability): the random and worst-case inputs of containment tests.
inline Eigen::VectorXd draw_disturbance(std::mt19937& gen, Eigen::Index n, bool vertex) {
  std::uniform_real_distribution<double> unif(-1.0, 1.0);  // stateless: same sequence as one kept
  Eigen::VectorXd w(n);
  for (Eigen::Index i = 0; i < n; ++i) w(i) = vertex ? (unif(gen) < 0 ? -1.0 : 1.0) : unif(gen);
  return w;
}

/// An r × c matrix of independent N(0, scale²) entries.
inline Eigen::MatrixXd random_normal(int r, int c, std::mt19937& rng, double scale = 1.0) {
  std::normal_distribution<double> g;
  Eigen::MatrixXd A(r, c);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) A(i, j) = scale * g(rng);
  return A;
}

}  // namespace setbound::testing

#define EXPECT_EIGEN_NEAR(a, b, tol) \
  EXPECT_PRED_FORMAT3(::setbound::testing::eigen_near, a, b, tol)
#define ASSERT_EIGEN_NEAR(a, b, tol) \
  ASSERT_PRED_FORMAT3(::setbound::testing::eigen_near, a, b, tol)
