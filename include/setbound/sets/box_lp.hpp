// setbound — linear programs over the unit box with equality rows, the engine of constrained
// zonotopes (spec cora_observers.md §1.5, §2.17; Scott et al. 2016 §3):
//
//   maximise gᵀξ   subject to   A ξ = b,   −1 <= ξ_j <= 1.
//
// The interval hull, the support function, the membership and the emptiness test of a constrained
// zonotope {c + Gξ : Aξ = b, ‖ξ‖∞ <= 1} are all LPs of this form with the same rows and different
// objectives (the hull alone is 2n of them), so one BoxLP is built per set and solved many times:
// a dense bounded-variable simplex (variables at either bound, no slack columns) whose basis is
// kept between objectives. Phase 1 is a primal simplex; each objective after it starts with a dual
// simplex from the kept basis (in a boxed LP every basis is dual feasible once the non-basic
// variables sit at the bounds their reduced costs prefer; bound-flipping ratio test, perturbed
// costs against stalling), finished by the primal simplex on the true costs.
//
// Why a simplex of our own: these LPs are small (tens to a few hundred columns, a few to a hundred
// rows) and solved thousands of times per second; the per-call set-up of a general solver costs more
// than the solve (docs/benchmarks.md "LP engine": this code, the LMI solver's interior point and
// HiGHS side by side).
//
// Guarantee. The simplex runs in floating point and may be inexact; the numbers it returns are not
// trusted. What is returned comes from weak duality, which holds for *any* vector μ:
//
//   max {gᵀξ : Aξ = b, ‖ξ‖∞ <= 1}  <=  μᵀb + ‖g − Aᵀμ‖₁          (gᵀξ = μᵀAξ + (g − Aᵀμ)ᵀξ),
//
// evaluated with an a-priori bound on its rounding errors (Higham, Accuracy and Stability, §3.1),
// so the returned bound is >= the exact maximum whatever the simplex did; with the optimal dual μ
// it equals the maximum up to that rounding. Likewise a vector y with yᵀb − ‖Aᵀy‖₁ > 0 (evaluated
// as a certified lower bound) proves that no ξ exists (for a feasible ξ, yᵀb = yᵀAξ <= ‖Aᵀy‖₁):
// emptiness is reported only with such a certificate. When the simplex cannot decide (an almost
// empty set whose certificate does not verify, or a breakdown), the status says so and the bounds
// fall back to valid ones (μ = 0: the unconstrained box), never to guesses.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace setbound {

namespace box_lp_detail {

// Tolerances of the floating-point simplex. They decide only which basis is found, never what is
// returned (the returned numbers are certified by duality), so they aim at robustness.
inline constexpr double kPivotTol = 1e-9;        // relative to the entering column's largest entry
inline constexpr double kReducedCostTol = 1e-10;  // relative to the largest cost
// Primal feasibility (rows scaled): phase 1 ends feasible when its objective is below it, and the
// dual simplex treats a basic variable within it of its box as inside.
inline constexpr double kFeasibilityTol = 1e-9;
// Pivots between fresh factorisations (at least r). A factorisation costs about 2r pivots' worth of
// work; at 64 they were ~11 % of a vehicle6 CZN step (3 per step). Drift in between only loosens
// the certified bounds, and maximize() refactorises on demand when its bound and its point
// disagree, so the interval is set by cost: 256 (vehicle6 ~10 %, tank30 ~15 % faster per step).
inline constexpr int kRefactorEvery = 256;
inline constexpr double kDualPerturbation = 1e-7;  // relative cost perturbation of the dual simplex

/// max |v_i|, 0 for an empty vector (Eigen's maxCoeff asserts on those).
template <class V>
double max_abs(const V& v) {
  return v.size() ? v.cwiseAbs().maxCoeff() : 0.0;
}

/// The certified total of qᵀw + ‖Mᵀw‖₁ (M: k×m) from its computed parts, summed in any order:
/// t = fl(qᵀw), tb = fl(|q|ᵀ|w|), R = fl(Σ_j |(Mᵀw)_j|), Aa = fl(Σ_j (|M|ᵀ|w|)_j).
double certified_total(double t, double tb, double R, double Aa, Eigen::Index k, Eigen::Index m);

/// A certified upper bound of qᵀw + ‖Mᵀw‖₁ (M: k×m, q and w: length k), the form both duality
/// bounds take: Higham's bound |fl(s) − s| <= γ_k Σ|terms| for each inner product (any summation
/// order, FMA or not), the final additions rounded upward.
double upper_bound_q_plus_l1(const Eigen::Ref<const Eigen::MatrixXd>& M, const Eigen::Ref<const Eigen::VectorXd>& q,
                             const Eigen::Ref<const Eigen::VectorXd>& w);

}  // namespace box_lp_detail

class BoxLP {
 public:
  /// What phase 1 found about {ξ : Aξ = b, ‖ξ‖∞ <= 1}.
  enum class Feasibility {
    feasible,      ///< a basis satisfying the rows (to the simplex's tolerance) was found
    empty,         ///< certified empty: infeasibility_certificate() proves it
    inconclusive,  ///< neither (almost empty set, or numerical breakdown): bounds fall back
  };

  /// The result of one maximisation.
  struct Bound {
    double value;           ///< certified upper bound of max gᵀξ (+inf never; the empty set gives -inf)
    double estimate;        ///< the simplex's optimum gᵀξ* (not certified; NaN when not feasible)
    Eigen::VectorXd dual;   ///< the μ that gave `value` (length rows(); zeros on fallback)
    Eigen::VectorXd point;  ///< the simplex's maximiser ξ* (empty when not feasible)
    bool optimal;           ///< the simplex reached optimality (false: iteration limit, fallback)
  };

  /// Validates: A finite with at least one column ("A"), b finite of length rows(A) ("b").
  /// A may have zero rows (then the feasible set is the whole box).
  BoxLP(Eigen::MatrixXd A, Eigen::VectorXd b);

  Eigen::Index rows() const { return A_.rows(); }
  Eigen::Index cols() const { return A_.cols(); }
  const Eigen::MatrixXd& A() const { return A_; }
  const Eigen::VectorXd& b() const { return b_; }

  /// Runs phase 1 (once; later calls return the stored answer).
  Feasibility feasibility();
  /// A y with a certified yᵀb − ‖Aᵀy‖₁ > 0 when feasibility() is empty (else an empty vector).
  const Eigen::VectorXd& infeasibility_certificate() { feasibility(); return certificate_; }
  /// The certified lower bound of yᵀb − ‖Aᵀy‖₁ for the certificate (> 0 when empty).
  double certificate_margin() { feasibility(); return certificate_margin_; }

  /// max gᵀξ over the set, warm-started from the basis of the previous call. g must have length
  /// cols() and be finite. On an empty set value = −inf (certified); when inconclusive, value is
  /// the valid bound ‖g‖₁ (μ = 0) and optimal = false.
  Bound maximize(const Eigen::Ref<const Eigen::VectorXd>& g);

  /// Simplex pivots done so far (all calls), for benchmarks and tests.
  long pivots() const { return pivots_; }

  /// Replaces the LP by one whose rows and columns extend this one's: A_new = [A 0; A_r A_c]
  /// (the old rows unchanged and zero in the new columns), b_new = [b; b_r]. This is what a
  /// generalized intersection does to a constrained zonotope's rows ([Scott2016] eq. 13), so the
  /// LP of a set and the LP of its intersection with a measurement share a warm start: the basis
  /// of the old rows stays feasible for them, the new columns start at their lower bound, and
  /// phase 1 (run by the next query) only has to drive the new rows' artificials to zero instead
  /// of starting over. When this LP was empty or inconclusive, phase 1 starts afresh. Validates
  /// the shapes and the unchanged blocks ("A", "b"; InvalidArgumentError/DimensionError).
  void extend(Eigen::MatrixXd A_new, Eigen::VectorXd b_new);

 private:
  void phase1();                                // cold start: every ξ at −1, artificials basic
  void phase1_run();                            // drives the artificials out from any start
  void scale_rows();                            // row_scale_, As_, bs_, absA_ from A_, b_
  void refactor();                              // T = B⁻¹A, beta = x_B, from the original data
  Eigen::VectorXd duals(const Eigen::VectorXd& cost) const;  // solves Bᵀμ = c_B (cost: all m + r)
  Eigen::VectorXd basic_costs(const Eigen::VectorXd& cost) const;    // c_B: cost of each row's basic variable
  Eigen::VectorXd reduced_costs(const Eigen::VectorXd& cost) const;  // cost − Tᵀ c_B
  // The box of variable k when basic: ξ in [−1, 1]; an artificial is fixed at 0 (phase 1 lets it
  // be positive, see run_simplex).
  double lower_of(int k) const { return k < A_.cols() ? -1.0 : 0.0; }
  double upper_of(int k) const { return k < A_.cols() ? 1.0 : 0.0; }
  double dual_bound(const Eigen::Ref<const Eigen::VectorXd>& g, const Eigen::VectorXd& mu) const;
  Eigen::VectorXd point() const;  // the current basic solution ξ (non-basic at their bounds)
  bool run_simplex(const Eigen::VectorXd& cost, long max_pivots);  // minimises costᵀx; false: limit
  // Minimises costᵀx from the current basis by the dual simplex: every non-basic variable first
  // goes to the bound its reduced cost prefers (a boxed LP is then dual feasible), then basic
  // variables outside their bounds leave one by one. false: limit, or no entering column (the
  // caller falls back to the primal simplex from the saved basis).
  bool run_dual_simplex(const Eigen::VectorXd& cost, long max_pivots);
  // Updates the tableau and the reduced costs d of `cost` for `enter` replacing row's basic
  // variable (col_ holds the entering column); refactorises every max(kRefactorEvery, r) pivots.
  void pivot(Eigen::Index row, int enter, const Eigen::VectorXd& cost, Eigen::VectorXd& d);

  Eigen::MatrixXd A_;  // original rows (zero rows kept: they are checked in phase 1)
  Eigen::VectorXd b_;
  Eigen::VectorXd row_scale_;  // rows are scaled to unit max-norm for the simplex
  Eigen::MatrixXd As_;         // scaled A
  Eigen::VectorXd bs_;         // scaled b
  Eigen::MatrixXd absA_;       // |A| (for the certified bounds of every query)
  bool warm_ = false;          // phase 1 continues from a basis set by extend()

  // Simplex state: variables 0..m-1 are ξ, m..m+r-1 the artificials (column s_i e_i).
  Eigen::VectorXd art_sign_;   // s_i
  std::vector<int> basis_;     // basic variable of each row
  std::vector<signed char> state_;  // per variable: 0 basic, -1 at lower, +1 at upper
  // B⁻¹ [As | S], r × (m + r), stored by rows: a pivot subtracts multiples of the pivot row from
  // every other row, which is then a contiguous (vectorised) operation.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> T_;
  Eigen::VectorXd col_;        // scratch: the entering column of T (no allocation per pivot)
  std::vector<std::pair<double, int>> cand_;  // scratch: the dual simplex's ratio-test candidates
  Eigen::VectorXd scan_w_, scan_ratio_;       // scratch: the ratio test's w_j and ratios, every column
  std::vector<int> cand_index_;               // scratch: the candidates' columns
  Eigen::VectorXd perturb_frac_;         // the dual simplex's cost perturbation per column, in [0.5, 1)
  std::vector<int> saved_basis_;         // scratch: maximize's fallback basis for the primal simplex
  std::vector<signed char> saved_state_;
  Eigen::VectorXd beta_;       // values of the basic variables
  bool phase1_done_ = false;
  Feasibility feasibility_ = Feasibility::inconclusive;
  Eigen::VectorXd certificate_;
  double certificate_margin_ = 0.0;
  long pivots_ = 0;
  int since_refactor_ = 0;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/box_lp.ipp"
#endif
