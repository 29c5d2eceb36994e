// The C ABI of the ellipsoidal family: a design and every estimator kind through sb_* calls,
// the state left unchanged by a bad step, and the validation errors (status + a message that
// names the argument).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "c_api_common.hpp"

namespace {

std::string last() { return sb_last_error(); }

bool names(const std::string& what) { return last().find(what) != std::string::npos; }

// EX-ME17a (papers.md §2.5), row-major.
struct Me17 {
  sb_linear_system* sys = nullptr;
  Me17() {
    const double A[4] = {-0.8, 0.2, -0.3, 0.1};
    const double C[2] = {-2.0, 1.0};
    const double E[4] = {-0.12, 0.0, 0.02, 0.0};
    const double F[2] = {0.0, 0.2};
    EXPECT_EQ(sb_linear_system_create(2, 1, 0, 2, A, nullptr, C, nullptr, E, F, nullptr, &sys), SB_OK) << last();
  }
  ~Me17() { sb_linear_system_free(sys); }
};

const double kP0[4] = {1, 0, 0, 1};
const double kC0[2] = {0.2, -0.1};

}  // namespace

TEST(EllipsoidalCApi, DesignAndEveryPredictorAndFilter) {
  Me17 m;
  sb_ell_design* d = nullptr;
  ASSERT_EQ(sb_ell_design_offline(m.sys, SB_ELL_NORM_LOGDET, std::nan(""), &d), SB_OK) << last();
  double P[4], L[2], sc[4];
  int blocks = 0, norm = -1;
  ASSERT_EQ(sb_ell_design_get(d, P, L, sc, &blocks, &norm), SB_OK);
  EXPECT_EQ(norm, SB_ELL_NORM_LOGDET);
  EXPECT_GT(sc[0], 0.0);
  EXPECT_LT(sc[0], 1.0);
  EXPECT_NEAR(sc[2], sc[1] / (1 - sc[0]), 1e-12 * sc[2]);
  EXPECT_EQ(blocks, 2);  // n_ω = 2 → 4 vertices, halved by the ± symmetry
  for (int method : {SB_ELL_OFFLINE, SB_ELL_ONLINE_VERTEX, SB_ELL_ONLINE_SCALED, SB_ELL_IMPROVED}) {
    sb_ellipsoidal* e = nullptr;
    ASSERT_EQ(sb_ellipsoidal_create(d, method, SB_ELL_CORR_DET_NORMALIZED, SB_ELL_FEEDBACK_OUTER_BOUND,
                                    SB_ELL_ONLINE_VERTEX, nullptr, kP0, kC0, 1.0, &e),
              SB_OK)
        << last();
    int is_filter = -1, steps = -1, nx = 0, ny = 0, nu = -1;
    ASSERT_EQ(sb_ellipsoidal_info(e, &is_filter, &steps, &nx, &ny, &nu), SB_OK);
    EXPECT_EQ(is_filter, method == SB_ELL_IMPROVED ? 1 : 0);
    EXPECT_EQ(steps, 0);
    EXPECT_EQ(nx, 2);
    EXPECT_EQ(ny, 1);
    EXPECT_EQ(nu, 0);
    double Pk[4], c[2], rho = 0, lo[2], hi[2];
    const double y[1] = {0.3};
    ASSERT_EQ(sb_ellipsoidal_step(e, y, nullptr, Pk, c, &rho, lo, hi), SB_OK) << last();
    EXPECT_GT(rho, 0.0);
    for (int i = 0; i < 2; ++i) EXPECT_LE(lo[i], hi[i]);
    // An infinite measurement is refused by name and the estimator keeps its state (NaN means
    // a missing output, tests/cpp/test_measurement_ellipsoidal.cpp).
    double c_before[2], rho_before = 0;
    ASSERT_EQ(sb_ellipsoidal_current(e, nullptr, c_before, &rho_before, nullptr, nullptr), SB_OK);
    const double bad[1] = {std::numeric_limits<double>::infinity()};
    EXPECT_EQ(sb_ellipsoidal_step(e, bad, nullptr, Pk, c, &rho, lo, hi), SB_ERR_NOT_FINITE);
    EXPECT_TRUE(names("y")) << last();
    double c_after[2], rho_after = 0;
    ASSERT_EQ(sb_ellipsoidal_current(e, nullptr, c_after, &rho_after, nullptr, nullptr), SB_OK);
    EXPECT_EQ(c_before[0], c_after[0]);
    EXPECT_EQ(c_before[1], c_after[1]);
    EXPECT_EQ(rho_before, rho_after);
    ASSERT_EQ(sb_ellipsoidal_info(e, nullptr, &steps, nullptr, nullptr, nullptr), SB_OK);
    EXPECT_EQ(steps, 1);
    double beta = 0, Lk[2];
    int fallback = -1;
    ASSERT_EQ(sb_ellipsoidal_last_step(e, &beta, Lk, &fallback), SB_OK);
    EXPECT_GT(beta, 0.0);
    EXPECT_LT(beta, 1.0);
    EXPECT_TRUE(fallback == 0 || fallback == 1);
    sb_ellipsoidal_free(e);
  }
  sb_ell_design_free(d);
}

TEST(EllipsoidalCApi, ErrorsNameTheArgument) {
  Me17 m;
  sb_ell_design* d = nullptr;
  EXPECT_EQ(sb_ell_design_offline(nullptr, SB_ELL_NORM_LOGDET, std::nan(""), &d), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(names("system")) << last();
  EXPECT_EQ(sb_ell_design_offline(m.sys, 7, std::nan(""), &d), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(names("normalization")) << last();
  EXPECT_EQ(sb_ell_design_offline(m.sys, SB_ELL_NORM_BALL, 1.5, &d), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(names("beta")) << last();
  EXPECT_EQ(d, nullptr);

  // Undetectable pair: an unstable mode that C does not see.
  const double A[4] = {1.2, 0.0, 0.0, 0.5};
  const double C[2] = {0.0, 1.0};
  const double E[2] = {0.1, 0.1};
  const double F[1] = {0.1};
  sb_linear_system* und = nullptr;
  ASSERT_EQ(sb_linear_system_create(2, 1, 0, 1, A, nullptr, C, nullptr, E, F, nullptr, &und), SB_OK);
  EXPECT_EQ(sb_ell_design_offline(und, SB_ELL_NORM_LOGDET, std::nan(""), &d), SB_ERR_NOT_DETECTABLE);
  EXPECT_TRUE(names("detectab")) << last();
  sb_linear_system_free(und);

  ASSERT_EQ(sb_ell_design_offline(m.sys, SB_ELL_NORM_BALL, 0.5, &d), SB_OK) << last();
  sb_ellipsoidal* e = nullptr;
  const double Pbad[4] = {1, 0, 0, -1};
  EXPECT_EQ(sb_ellipsoidal_create(d, SB_ELL_OFFLINE, 0, 0, 0, nullptr, Pbad, kC0, 1.0, &e),
            SB_ERR_NOT_POSITIVE_DEFINITE);
  EXPECT_TRUE(names("P")) << last();
  EXPECT_EQ(sb_ellipsoidal_create(d, 42, 0, 0, 0, nullptr, kP0, kC0, 1.0, &e), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(names("method")) << last();
  EXPECT_EQ(sb_ellipsoidal_create(d, SB_ELL_IMPROVED, 9, 1, 1, nullptr, kP0, kC0, 1.0, &e), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(names("option")) << last();
  EXPECT_EQ(sb_ellipsoidal_create(d, SB_ELL_IMPROVED, 1, 9, 1, nullptr, kP0, kC0, 1.0, &e), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(names("feedback")) << last();
  EXPECT_EQ(sb_ellipsoidal_create(d, SB_ELL_DESCRIPTOR, 0, 0, 0, nullptr, kP0, kC0, 1.0, &e), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(names("descriptor")) << last();
  EXPECT_EQ(sb_ellipsoidal_create(d, SB_ELL_OFFLINE, 0, 0, 0, nullptr, kP0, kC0, -1.0, &e), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(names("rho")) << last();
  EXPECT_EQ(e, nullptr);
  EXPECT_EQ(sb_ellipsoidal_step(nullptr, kC0, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr),
            SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(names("estimator")) << last();
  sb_ell_design_free(d);
}

TEST(EllipsoidalCApi, DescriptorAndKalman) {
  // EX-ME19 (papers.md §4.2).
  const double E[9] = {1, 0, 0, 0, 1, 0, 0, 0, 0};
  const double A[9] = {0.5, 0, 0, 0.8, 0.95, 0, -1, 0.5, 1};
  const double B[6] = {1, 0, 0, 1, 0, 0};
  const double C[6] = {1, 0, 1, 1, -1, 0};
  const double D[15] = {0.1, 0, 0, 0, 0, 0, 1.5, 0, 0, 0, 0, 0, 0.6, 0, 0};
  const double F[10] = {0, 0, 0, 0.5, 0, 0, 0, 0, 0, 1.5};
  sb_descriptor_system* ds = nullptr;
  ASSERT_EQ(sb_descriptor_system_create(3, 2, 2, 5, E, A, B, C, D, F, &ds), SB_OK) << last();
  double T[9], N[6];
  ASSERT_EQ(sb_descriptor_system_tn(ds, T, N), SB_OK);
  EXPECT_NEAR(T[0], 2.0 / 3.0, 1e-14);
  EXPECT_NEAR(N[4], 1.0, 1e-14);
  // [E; C] rank deficient: C sees only x1.
  const double Cbad[6] = {1, 0, 0, 1, 0, 0};
  sb_descriptor_system* bad = nullptr;
  EXPECT_NE(sb_descriptor_system_create(3, 2, 2, 5, E, A, B, Cbad, D, F, &bad), SB_OK);
  EXPECT_TRUE(names("observab")) << last();
  EXPECT_EQ(bad, nullptr);
  sb_ell_design* d = nullptr;
  ASSERT_EQ(sb_ell_design_descriptor(ds, SB_ELL_NORM_LOGDET, std::nan(""), &d), SB_OK) << last();
  const double P0[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double c0[3] = {0, 0, 0};
  sb_ellipsoidal* e = nullptr;
  ASSERT_EQ(sb_ellipsoidal_create(d, SB_ELL_DESCRIPTOR, 0, 0, 0, ds, P0, c0, 1.0, &e), SB_OK) << last();
  const double y[2] = {0.1, -0.2}, u[2] = {1.0, -2.0};
  double c[3], rho = 0;
  ASSERT_EQ(sb_ellipsoidal_step(e, y, u, nullptr, c, &rho, nullptr, nullptr), SB_OK) << last();
  ASSERT_EQ(sb_ellipsoidal_step(e, y, u, nullptr, c, &rho, nullptr, nullptr), SB_OK) << last();
  EXPECT_GT(rho, 0.0);
  // A descriptor design cannot drive a plain predictor, and vice versa.
  sb_ellipsoidal* wrong = nullptr;
  EXPECT_EQ(sb_ellipsoidal_create(d, SB_ELL_OFFLINE, 0, 0, 0, nullptr, P0, c0, 1.0, &wrong), SB_ERR_INVALID_ARGUMENT);
  EXPECT_TRUE(names("design")) << last();
  sb_ellipsoidal_free(e);
  sb_ell_design_free(d);
  sb_descriptor_system_free(ds);

  Me17 m;
  sb_kalman* k = nullptr;
  const double mean0[2] = {5, 5}, cov0[4] = {1, 0, 0, 1}, cov_bad[4] = {1, 0, 0, -1};
  EXPECT_EQ(sb_kalman_create(m.sys, mean0, cov_bad, nullptr, &k), SB_ERR_NOT_POSITIVE_DEFINITE);
  EXPECT_TRUE(names("cov0")) << last();
  ASSERT_EQ(sb_kalman_create(m.sys, mean0, cov0, nullptr, &k), SB_OK) << last();
  double mean[2], cov[4];
  const double yk[1] = {-5.0};
  ASSERT_EQ(sb_kalman_step(k, yk, nullptr, mean, cov), SB_OK) << last();
  EXPECT_NEAR(cov[1], cov[2], 1e-14);
  EXPECT_GT(cov[0], 0.0);
  sb_kalman_free(k);
}
