// The C ABI of the LMI solver: every sb_lmi_* entry point, statuses, certificates and the
// validation errors (status code + a message that names the argument).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>
#include <vector>

#include "c_api_common.hpp"

namespace {

struct Handle {
  sb_lmi_problem* p = nullptr;
  explicit Handle(int m) { EXPECT_EQ(sb_lmi_problem_create(m, &p), SB_OK); }
  ~Handle() { sb_lmi_problem_free(p); }
};

std::string last() { return sb_last_error(); }

// [[x0, 1], [1, 1]] ⪰ 0 (x0 ≥ 1) plus the 1×1 block x1 ≥ 2, row-major data.
void add_simple_blocks(sb_lmi_problem* p) {
  const double F0[4] = {0, 1, 1, 1};
  const double Fs[8] = {1, 0, 0, 0, /* x1 */ 0, 0, 0, 0};
  int idx = -1;
  ASSERT_EQ(sb_lmi_add_block(p, 2, F0, Fs, &idx), SB_OK) << last();
  EXPECT_EQ(idx, 0);
  const double G0[1] = {-2};
  const double Gs[2] = {0, 1};
  ASSERT_EQ(sb_lmi_add_block(p, 1, G0, Gs, &idx), SB_OK) << last();
  EXPECT_EQ(idx, 1);
}

}  // namespace

TEST(LmiCApi, SolveLinearProblemAndReadDuals) {
  Handle h(2);
  add_simple_blocks(h.p);
  const double c[2] = {1, 3};
  ASSERT_EQ(sb_lmi_set_objective(h.p, c), SB_OK);
  int m = 0, nb = 0;
  ASSERT_EQ(sb_lmi_problem_size(h.p, &m, &nb), SB_OK);
  EXPECT_EQ(m, 2);
  EXPECT_EQ(nb, 2);
  sb_lmi_result r{};
  double x[2];
  ASSERT_EQ(sb_lmi_solve(h.p, &r, x), SB_OK) << last();
  EXPECT_EQ(r.status, SB_LMI_OPTIMAL);
  EXPECT_NEAR(x[0], 1.0, 1e-7);
  EXPECT_NEAR(x[1], 2.0, 1e-7);
  EXPECT_NEAR(r.objective, 7.0, 1e-6);
  EXPECT_GT(r.iterations, 0);
  EXPECT_GT(r.solve_time, 0.0);
  // Dual feasibility: tr(F_bi Z_b) summed over blocks equals c_i.
  double Z0[4], Z1[1];
  ASSERT_EQ(sb_lmi_dual(h.p, 0, Z0), SB_OK);
  ASSERT_EQ(sb_lmi_dual(h.p, 1, Z1), SB_OK);
  EXPECT_NEAR(Z0[0], 1.0, 1e-6);
  EXPECT_NEAR(Z1[0], 3.0, 1e-6);
  EXPECT_EQ(sb_lmi_dual(h.p, 2, Z0), SB_ERR_INVALID_ARGUMENT);

  // Verified margin of given points.
  double margin = 0;
  const double inside[2] = {3, 5};
  ASSERT_EQ(sb_lmi_margin(h.p, inside, &margin), SB_OK);
  EXPECT_GT(margin, 0.0);
  const double outside[2] = {0.5, 5};
  ASSERT_EQ(sb_lmi_margin(h.p, outside, &margin), SB_OK);
  EXPECT_LT(margin, 0.0);
}

TEST(LmiCApi, UpdateOptionsEqualitiesFeasibilityInfeasibility) {
  Handle h(2);
  add_simple_blocks(h.p);
  const double c[2] = {1, 1};
  ASSERT_EQ(sb_lmi_set_objective(h.p, c), SB_OK);
  ASSERT_EQ(sb_lmi_set_threads(h.p, 2), SB_OK) << last();  // kept by set_options; 3 blocks: 2 threads
  ASSERT_EQ(sb_lmi_set_options(h.p, 50, 1e-8, 1e-9, 5.0), SB_OK) << last();
#if defined(_OPENMP)
  EXPECT_EQ(sb_lmi_threads_available(), 1);  // the objects are compiled like this test (CMake: SETBOUND_OPENMP)
#else
  EXPECT_EQ(sb_lmi_threads_available(), 0);
#endif
  // x1 ≥ 4 now (update of block 1 values only).
  const double G0[1] = {-4}, Gs[2] = {0, 1};
  ASSERT_EQ(sb_lmi_update_block(h.p, 1, 1, G0, Gs), SB_OK) << last();
  sb_lmi_result r{};
  double x[2];
  ASSERT_EQ(sb_lmi_solve(h.p, &r, x), SB_OK);
  EXPECT_EQ(r.status, SB_LMI_OPTIMAL);
  EXPECT_NEAR(x[1], 4.0, 1e-7);
  // Equality x0 − x1 = 1 moves the optimum to x = (5, 4).
  const double A[2] = {1, -1}, b[1] = {1};
  ASSERT_EQ(sb_lmi_set_equalities(h.p, 1, A, b), SB_OK);
  ASSERT_EQ(sb_lmi_solve(h.p, &r, x), SB_OK);
  EXPECT_EQ(r.status, SB_LMI_OPTIMAL);
  EXPECT_NEAR(x[0], 5.0, 1e-6);
  double y[1];
  ASSERT_EQ(sb_lmi_dual_eq(h.p, y), SB_OK);
  EXPECT_TRUE(std::isfinite(y[0]));
  // Feasibility class: a certified strictly feasible point.
  ASSERT_EQ(sb_lmi_solve_class(h.p, SB_LMI_CLASS_FEASIBILITY, &r, x), SB_OK) << last();
  EXPECT_EQ(r.status, SB_LMI_OPTIMAL);
  EXPECT_GT(r.margin, 0.0);
  EXPECT_GT(x[1], 4.0);
  EXPECT_EQ(sb_lmi_solve_class(h.p, 7, &r, x), SB_ERR_INVALID_ARGUMENT);
  // Infeasible: x1 ≤ −1 as well.
  ASSERT_EQ(sb_lmi_set_equalities(h.p, 0, nullptr, nullptr), SB_OK);
  const double H0[1] = {-1}, Hs[2] = {0, -1};
  ASSERT_EQ(sb_lmi_add_block(h.p, 1, H0, Hs, nullptr), SB_OK);
  ASSERT_EQ(sb_lmi_solve(h.p, &r, x), SB_OK);
  EXPECT_EQ(r.status, SB_LMI_INFEASIBLE);
  EXPECT_TRUE(std::isnan(x[0]));
  double Z1[1], Z2[1];
  ASSERT_EQ(sb_lmi_dual(h.p, 1, Z1), SB_OK);
  ASSERT_EQ(sb_lmi_dual(h.p, 2, Z2), SB_OK);
  // Certificate: −4 z1 − z2 (+ block 0 part) = −1, z1 − z2 = 0 for x1, z ≥ 0.
  EXPECT_GE(Z1[0], 0.0);
  EXPECT_NEAR(Z1[0] - Z2[0], 0.0, 1e-7);
  ASSERT_EQ(sb_lmi_solve_class(h.p, SB_LMI_CLASS_FEASIBILITY, &r, x), SB_OK);
  EXPECT_EQ(r.status, SB_LMI_INFEASIBLE);
}

TEST(LmiCApi, MaxdetAndGevp) {
  // max log det diag(x0, x1) s.t. x0 + x1 ≤ 1 → x = (1/2, 1/2).
  Handle h(2);
  const double F0[1] = {1}, Fs[2] = {-1, -1};
  ASSERT_EQ(sb_lmi_add_block(h.p, 1, F0, Fs, nullptr), SB_OK);
  const double G0[4] = {0, 0, 0, 0};
  const double Gs[8] = {1, 0, 0, 0, 0, 0, 0, 1};
  ASSERT_EQ(sb_lmi_set_logdet(h.p, 2, G0, Gs), SB_OK) << last();
  sb_lmi_result r{};
  double x[2];
  ASSERT_EQ(sb_lmi_solve(h.p, &r, x), SB_OK) << last();
  EXPECT_EQ(r.status, SB_LMI_OPTIMAL);
  EXPECT_NEAR(x[0], 0.5, 1e-6);
  EXPECT_NEAR(x[1], 0.5, 1e-6);
  EXPECT_NEAR(r.objective, 2 * std::log(2.0), 1e-6);
  ASSERT_EQ(sb_lmi_set_logdet(h.p, 0, nullptr, nullptr), SB_OK);

  // GEVP: min λ s.t. λ I − diag(x0, 1 − x0 ... ) with the block x0 + x1 ≤ 1:
  // A(x) = diag(x0, x1) + diag(0, 0), B = I → λ* = min max(x0, x1) with x0 + x1 ≤ 1 and
  // x0, x1 unbounded below → unbounded; add x ≥ 0.3 via A0 shift instead: A = diag(x0+1, 2−x0).
  Handle g(1);
  const double L0[1] = {3}, Ls[1] = {1};  // x0 ≥ −3
  ASSERT_EQ(sb_lmi_add_block(g.p, 1, L0, Ls, nullptr), SB_OK);
  const double U0[1] = {3}, Us[1] = {-1};  // x0 ≤ 3
  ASSERT_EQ(sb_lmi_add_block(g.p, 1, U0, Us, nullptr), SB_OK);
  const double A0[4] = {1, 0, 0, 2}, As[4] = {1, 0, 0, -1};
  const double B0[4] = {1, 0, 0, 1}, Bs[4] = {0, 0, 0, 0};
  double lambda = 0, xg[1];
  ASSERT_EQ(sb_lmi_solve_gevp(g.p, 2, A0, As, B0, Bs, 0.0, 1.0, 1e-7, &r, &lambda, xg), SB_OK) << last();
  EXPECT_EQ(r.status, SB_LMI_OPTIMAL);
  EXPECT_NEAR(lambda, 1.5, 1e-6);  // x0 = 0.5
  EXPECT_NEAR(xg[0], 0.5, 1e-3);
  EXPECT_LE(r.dual_objective, 1.5);
  const double Abad[4] = {1, 2, 0, 2};
  EXPECT_EQ(sb_lmi_solve_gevp(g.p, 2, Abad, As, B0, Bs, 0.0, 1.0, 1e-7, &r, &lambda, xg), SB_ERR_NOT_SYMMETRIC);
  EXPECT_EQ(last().rfind("sb_lmi_solve_gevp: A0:", 0), 0u) << last();
}

TEST(LmiCApi, BadInputsGiveErrorsNamingTheArgument) {
  sb_lmi_problem* p = nullptr;
  EXPECT_EQ(sb_lmi_problem_create(0, &p), SB_ERR_DIMENSION);
  EXPECT_EQ(p, nullptr);
  EXPECT_EQ(sb_lmi_problem_create(2, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_lmi_problem_free(nullptr), SB_OK);
  sb_lmi_result r{};
  double x[2];
  EXPECT_EQ(sb_lmi_solve(nullptr, &r, x), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(last().find("problem: null pointer"), std::string::npos) << last();

  Handle h(2);
  // Zero blocks.
  EXPECT_EQ(sb_lmi_solve(h.p, &r, x), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(last().find("blocks:"), std::string::npos) << last();
  const double ns[4] = {1, 2, 0, 1}, id[4] = {1, 0, 0, 1};
  const double Fs[8] = {1, 0, 0, 1, 0, 0, 0, 0};
  EXPECT_EQ(sb_lmi_add_block(h.p, 2, ns, Fs, nullptr), SB_ERR_NOT_SYMMETRIC);
  EXPECT_EQ(last().rfind("sb_lmi_add_block: F0:", 0), 0u) << last();
  const double Fns[8] = {1, 0, 0, 1, 0, 1, 0, 0};
  EXPECT_EQ(sb_lmi_add_block(h.p, 2, id, Fns, nullptr), SB_ERR_NOT_SYMMETRIC);
  EXPECT_EQ(last().rfind("sb_lmi_add_block: Fs[1]:", 0), 0u) << last();
  const double nan[4] = {NAN, 0, 0, 1};
  EXPECT_EQ(sb_lmi_add_block(h.p, 2, nan, Fs, nullptr), SB_ERR_NOT_FINITE);
  EXPECT_EQ(sb_lmi_add_block(h.p, 0, id, Fs, nullptr), SB_ERR_DIMENSION);
  EXPECT_EQ(sb_lmi_add_block(h.p, 2, nullptr, Fs, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_lmi_add_block(h.p, 2, id, nullptr, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_NE(last().find("Fs: null pointer"), std::string::npos) << last();
  ASSERT_EQ(sb_lmi_add_block(h.p, 2, id, Fs, nullptr), SB_OK);
  EXPECT_EQ(sb_lmi_update_block(h.p, 1, 2, id, Fs), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_lmi_update_block(h.p, 0, 3, id, Fs), SB_ERR_DIMENSION);
  EXPECT_EQ(sb_lmi_update_block(h.p, 0, 2, ns, Fs), SB_ERR_NOT_SYMMETRIC);
  const double cnan[2] = {NAN, 1};
  EXPECT_EQ(sb_lmi_set_objective(h.p, cnan), SB_ERR_NOT_FINITE);
  EXPECT_EQ(last().rfind("sb_lmi_set_objective: c:", 0), 0u) << last();
  EXPECT_EQ(sb_lmi_set_equalities(h.p, 1, nullptr, nullptr), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_lmi_set_equalities(h.p, -1, id, id), SB_ERR_DIMENSION);
  EXPECT_EQ(sb_lmi_set_options(h.p, 0, NAN, 0, 0), SB_ERR_NOT_FINITE);
  EXPECT_EQ(sb_lmi_set_threads(h.p, 0), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(last().rfind("sb_lmi_set_threads: threads:", 0), 0u) << last();
  EXPECT_EQ(sb_lmi_set_threads(nullptr, 2), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_lmi_set_logdet(h.p, 2, ns, Fs), SB_ERR_NOT_SYMMETRIC);
  EXPECT_EQ(sb_lmi_solve(h.p, nullptr, x), SB_ERR_INVALID_ARGUMENT);
  double margin;
  EXPECT_EQ(sb_lmi_margin(h.p, cnan, &margin), SB_ERR_NOT_FINITE);
  EXPECT_EQ(sb_lmi_margin(h.p, x, nullptr), SB_ERR_INVALID_ARGUMENT);
  Handle fresh(1);
  EXPECT_EQ(sb_lmi_dual(fresh.p, 0, x), SB_ERR_INVALID_ARGUMENT);  // not solved yet
  EXPECT_EQ(sb_lmi_dual_eq(fresh.p, x), SB_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(sb_lmi_problem_size(nullptr, nullptr, nullptr), SB_ERR_INVALID_ARGUMENT);
}
