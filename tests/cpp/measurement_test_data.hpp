// setbound — the data of the real-measurement tests (issue 24): EX-LE13 with a known A and a
// simulated record, shared by test_measurement_check.cpp (zonotopic) and
// test_measurement_ellipsoidal.cpp and test_measurement_thesis.cpp.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "c_api_common.hpp"  // the C ABI (setbound.h, once per translation unit)

#include "setbound/core/linear_system.hpp"
#include "test_helpers.hpp"

namespace setbound::testing {

/// EX-LE13 (papers §3.5) with a known A: x+ = [0 -0.5; 1 1] x + F_w ω, y = C x + 0.2 v.
inline LinearSystem le13_known_a() {
  Eigen::MatrixXd A(2, 2), C(2, 2), E(2, 3), F(2, 3);
  A << 0, -0.5, 1, 1;
  C << -2, 1, 1, 1;
  E << -0.12, 0, 0, 0.02, 0, 0;
  F << 0, 0.2, 0, 0, 0, 0.2;
  return LinearSystem(A, C, E, F);
}

/// N × n_x true states and N × n_y readings of a simulated run.
struct Record {
  Eigen::MatrixXd X, Y;
};

/// The true system from x0 with ω uniform or at the vertices of its box (draw_disturbance).
/// jump_at >= 0: the state jumps by `jump` before that step (a violation of the model).
inline Record simulate_record(const LinearSystem& s, const Eigen::VectorXd& x0, int N, bool vertex, unsigned seed,
                              int jump_at = -1, const Eigen::VectorXd& jump = Eigen::VectorXd()) {
  std::mt19937 gen(seed);
  Record r{Eigen::MatrixXd(N, s.nx()), Eigen::MatrixXd(N, s.ny())};
  Eigen::VectorXd x = x0;
  for (int k = 0; k < N; ++k) {
    if (k == jump_at) x += jump;
    const Eigen::VectorXd w = draw_disturbance(gen, s.nw(), vertex);
    r.X.row(k) = x.transpose();
    r.Y.row(k) = (s.C() * x + s.F() * w).transpose();
    x = s.A() * x + s.E() * w;
  }
  return r;
}

/// The C ABI scenario of both test files: the record of N steps of EX-LE13 from (1, 1) (seed 11)
/// with a glitch on output 0 at step 8 (40, far outside) and output 1 missing at step 5, and the
/// system as a C handle (freed with the object).
struct CapiScenario {
  Record r;
  sb_linear_system* sys = nullptr;

  explicit CapiScenario(int N) : r(simulate_record(le13_known_a(), Eigen::Vector2d(1.0, 1.0), N, false, 11)) {
    r.Y(8, 0) = 40.0;
    r.Y(5, 1) = std::numeric_limits<double>::quiet_NaN();
    const LinearSystem s = le13_known_a();
    const Eigen::Matrix<double, 2, 2, Eigen::RowMajor> A = s.A(), C = s.C();
    const Eigen::Matrix<double, 2, 3, Eigen::RowMajor> E = s.E(), F = s.F();
    EXPECT_EQ(sb_linear_system_create(2, 2, 0, 3, A.data(), nullptr, C.data(), nullptr, E.data(), F.data(), nullptr,
                                      &sys),
              SB_OK);
  }
  ~CapiScenario() { sb_linear_system_free(sys); }
  CapiScenario(const CapiScenario&) = delete;
  CapiScenario& operator=(const CapiScenario&) = delete;
};

/// The C ABI scenario's checks: a glitch on output 0 at step 8 (far outside), output 1
/// missing at step 5. Checks step k's return code `rc` and its screening, read with
/// `last_check(status, margin, &reset)` (the family's sb_*_last_check), under `policy`; returns
/// false when the run stops there (RAISE at the glitch, whose message names the step and output).
template <class LastCheck>
bool expect_capi_screening(int rc, int k, int policy, const double* lo, const double* hi, LastCheck&& last_check) {
  if (k == 8 && policy == SB_ON_INCONSISTENCY_RAISE) {
    EXPECT_EQ(rc, SB_ERR_INCONSISTENT);
    EXPECT_NE(std::string(sb_last_error()).find("step 8: output 0:"), std::string::npos) << sb_last_error();
    return false;
  }
  EXPECT_EQ(rc, SB_OK) << sb_last_error();
  int status[2] = {-1, -1}, reset = -1;
  double margin[2] = {0, 0};
  EXPECT_EQ(last_check(status, margin, &reset), SB_OK);
  EXPECT_EQ(status[0], k == 8 ? SB_OUTPUT_INCONSISTENT : SB_OUTPUT_USED) << k;
  EXPECT_EQ(status[1], k == 5 ? SB_OUTPUT_MISSING : SB_OUTPUT_USED) << k;
  EXPECT_EQ(reset, (k == 8 && policy == SB_ON_INCONSISTENCY_RESET) ? 1 : 0) << k;
  if (k == 8) EXPECT_GT(margin[0], 10.0);
  if (k == 5) EXPECT_TRUE(std::isnan(margin[1]));
  EXPECT_TRUE(lo[0] <= hi[0] && lo[1] <= hi[1]);
  return true;
}

}  // namespace setbound::testing
