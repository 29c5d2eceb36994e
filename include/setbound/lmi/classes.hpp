// setbound — problem classes on top of the interior-point core (solver.hpp):
//   * feasibility: find a strictly feasible point, stopping at the first certified one;
//   * generalised eigenvalue problems (GEVP) by bracketing between certified feasible points
//     and infeasibility certificates;
//   * maxdet: minimise cᵀx − log det G(x) subject to the LMIs (Vandenberghe–Boyd–Wu 1998),
//     by a primal barrier path-following method with damped Newton steps.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "setbound/lmi/problem.hpp"
#include "setbound/lmi/solver.hpp"

namespace setbound::lmi {

// ---------------------------------------------------------------------------------------
// Feasibility: minimise t s.t. F_b(x) + t I ⪰ 0, t ≥ −1, Aeq x = beq. The solver stops at the
// first iterate with t < 0 whose blocks F_b(x) pass the verified-margin test. If instead the
// optimum t* is positive, the dual of the auxiliary problem is an infeasibility certificate
// of the original one (Σ tr(F_b0 Z_b) + beqᵀy = −t* < 0, tr(F_bi Z) = (Aeqᵀy)_i).
class FeasibilitySolver {
 public:
  explicit FeasibilitySolver(const LmiProblem& problem, SolverOptions options = {})
      : orig_(&problem), opt_(options) {
    build();
  }

  /// Re-reads the values of the original problem (same structure) and solves.
  const SolveResult& solve();

 private:
  // Normalises the auxiliary dual into result_.Z / result_.y and checks it: Z_b ⪰ 0
  // (Cholesky), Σ tr(F_b0 Z_b) + beqᵀy = −1 and |Σ_b tr(F_bi Z_b) − (Aeqᵀy)_i| ≤ reduced_feas.
  bool certificate(const SolveResult& r);

  static BlockTerms terms_of(const LmiBlock& blk, int m);
  void build();
  void sync_values();

  const LmiProblem* orig_;
  SolverOptions opt_;
  LmiProblem aux_;
  std::unique_ptr<InteriorPointSolver> solver_;
  MarginChecker margin_;
  std::uint64_t orig_version_ = 0;
  SolveResult result_;
};

SolveResult find_feasible(const LmiProblem& problem, const SolverOptions& options = {});

// ---------------------------------------------------------------------------------------
// Maxdet (VBW 1998): minimise cᵀx − log det G(x) s.t. F_b(x) ⪰ 0, Aeq x = beq.
// Phase I: a strictly feasible point of {F_b ⪰ 0, G ≻ 0} from FeasibilitySolver. Phase II:
// central path of φ_t(x) = t(cᵀx − log det G(x)) − Σ_b log det F_b(x); the centre for
// parameter t is ν/t-suboptimal (ν = Σ_b n_b), so t grows until ν/t meets the gap tolerance.
namespace detail {

struct BarrierTerm {
  explicit BarrierTerm(const LmiBlock* b) : blk(b) {}
  const LmiBlock* blk;
  double weight = 1.0;
  Eigen::MatrixXd F, Linv, Ft;  // F(x), L⁻¹ (Cholesky), stacked L⁻¹F_iL⁻ᵀ (n²×k)
  Eigen::MatrixXd tmp;          // n×n work
  Eigen::LLT<Eigen::MatrixXd> llt;
  // Arm form of the coefficients (ArmForm, solver.hpp), decided at the first derivatives: for a
  // block beyond the fixed-size kernels whose coefficients are all sparse, when it is cheaper than
  // the n²k²/2 of the dot products of the dense L⁻¹F_iL⁻ᵀ (Nom-G's analytic centre on tank30).
  bool arm_decided = false, arm = false;
  ArmForm arms;
  Eigen::MatrixXd gram;         // k×k: the arm form's Gram matrix (upper triangle)
  Eigen::VectorXd ones;         // k unit scales for ArmForm::gram
};

// −log det F(x) value; false when F(x) is not positive definite.
bool barrier_value(BarrierTerm& t, const LmiProblem& p, const Eigen::VectorXd& x, double& value);

// Adds weight·(gradient, Hessian) of −log det F at the point of the last barrier_value call:
// g_i −= tr F̃_i, H_ij += tr F̃_i F̃_j with F̃_i = L⁻¹F_iL⁻ᵀ (from the arm form where it pays,
// with T = L⁻¹). The congruences run on the
// solver's small-matrix kernels (fixed-size up to kernels::kFixedMax); Eigen's blocked product
// only pays off for large blocks.
void barrier_derivatives(BarrierTerm& t, Eigen::VectorXd& g, Eigen::MatrixXd& H);

}  // namespace detail

SolveResult solve_maxdet(const LmiProblem& p, const SolverOptions& opt = {});

/// Dispatches on the problem class: maxdet when a log-det term is set, linear otherwise.
SolveResult solve(const LmiProblem& p, const SolverOptions& opt = {});

// ---------------------------------------------------------------------------------------
// Generalised eigenvalue problem: minimise λ s.t. λB(x) − A(x) ⪰ 0, B(x) ⪰ b_margin·I and the
// LMIs of `constraints`. For fixed λ this is a feasibility problem; λ is bracketed between a
// value with a certified feasible point (upper) and one with an infeasibility certificate
// (lower), then bisected until hi − lo ≤ tol·max(1, |hi|).
struct GevpResult {
  SolveStatus status = SolveStatus::NumericalError;
  double lambda = std::numeric_limits<double>::quiet_NaN();  // certified upper value
  double lower = -std::numeric_limits<double>::infinity();    // certified infeasible below
  Eigen::VectorXd x;                                          // certified point at `lambda`
  double margin = -std::numeric_limits<double>::infinity();
  int solves = 0;
  int iterations = 0;
  double solve_time = 0;
};

struct GevpOptions {
  double lambda_lo = 0.0;   // initial guess of a lower end (moved down if feasible)
  double lambda_hi = 1.0;   // initial guess of an upper end (moved up if infeasible)
  double tol = 1e-6;        // relative bracket width
  double b_margin = 1e-9;   // B(x) ⪰ b_margin·I
  int max_bracket = 60;
  SolverOptions solver;
};

GevpResult solve_gevp(const LmiProblem& constraints, const Eigen::Ref<const Eigen::MatrixXd>& A0,
                             const BlockTerms& A_terms, const Eigen::Ref<const Eigen::MatrixXd>& B0,
                             const BlockTerms& B_terms, const GevpOptions& go = {});

}  // namespace setbound::lmi

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/lmi/impl/classes.ipp"
#endif
