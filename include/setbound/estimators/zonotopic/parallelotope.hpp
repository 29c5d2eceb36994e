// setbound — recursive optimal parallelotopes (CORA's ROPO; Vicino & Zappa, "Sequential
// approximation of feasible parameter sets for identification with set membership uncertainty",
// IEEE TAC 41(6), 1996; spec cora_observers.md §2.19).
//
// The state is a parallelotope Θ = θ ⊕ T B^n (T n×n; zero columns allowed, see below). One step
// (a filter: row k of a run is the set for x_k after y_k):
//
//   prior:       X̄_k = A X̂_{k−1} ⊕ (B u_{k−1}) ⊕ E B^{n_ω}      (the constant c is inside B u)
//   reduce:      X̄_k → a parallelotope: CORA's reduce(Z, technique, 1): `Girard` = the interval
//                hull (every generator boxed), `Pca` = a PCA-oriented box (sets/zonotope_reduction.hpp)
//   correct:     for each output i = 1..p, the Vicino–Zappa step with the strip
//                |C_i x − (y_i − D_i u)| ≤ σ_i (σ_i = Σ_j |F_ij|, normalised p = C_iᵀ/σ_i in CORA):
//     1. tighten the strip to its overlap with the range of C_i x over Θ (both hyperplanes then
//        touch Θ ∩ strip's range);
//     2. shrink each generator segment ξ_j ∈ [−1, 1] to what the strip allows with the other ξ free
//        (θ and t_j move accordingly; K_j = C_i t_j = 0 keeps [−1, 1]);
//     3. of the n + 1 parallelotopes bounded by n of the n + 1 slab pairs (Θ's n face pairs and
//        the tightened strip), keep the one of least volume: either Θ itself, or Θ with the face
//        pair of t_j replaced by the strip (volume × σ'/(C_i t_j)), which is the strip update
//        θ' = θ + λ(y' − C_iθ), t_i' = t_i − λ C_i t_i, t_j' = λσ' with λ = t_j / (C_i t_j).
//   Every candidate of stage 3 contains the intersection exactly, so the step is an outer bound.
//
// Conventions (Convention):
//   * Setbound (default, guaranteed): step k corrects with y_k from step 0 on (the initial set
//     is first reduced to a parallelotope), as every zonotopic filter of the library. Every set is
//     an outer bound after floating-point rounding: rounding errors of the prediction, of stage 2
//     and of stage 3 are bounded (Higham's γ_k) and collected in a pending axis box B_r (the set is
//     Θ ⊕ B_r); the strip passes through the box by widening it by |C_i| r (stage 2) and by the
//     strip update's |I − λC_i| r (stage 3), as in observer.hpp; the reduction absorbs the box.
//     The bounds of stages 1–2 are rounded outward. A reading outside the predicted output set
//     (an empty intersection) is detected with the library's test (measurement_check.hpp) against
//     the set before its strip and handled by the policy (flag: skip that output; raise:
//     InconsistentMeasurementError, unchanged; reset: restart from x0 and correct from there).
//     Stage 3 swaps column j* (the largest C_i t_j) when C_i t_j* > σ_i, as CORA: a swap multiplies
//     the volume by σ'/(C_i t_j*), and after stage 2 a tightened strip (σ' < σ_i) leaves every
//     C_i t_j <= σ' in exact arithmetic, so swaps only pay for untightened strips (σ' = σ_i);
//     testing against σ_i keeps rounding from swapping candidates of equal volume.
//   * Cora: CORA's priv_observe_ROPO.m as it is: time indexing S' (row 0 is R0 itself, y_0
//     unused and not reduced; then predict–reduce–correct), CORA's normalised arithmetic with no
//     rounding control, no emptiness check (its test is commented out: an empty intersection
//     gives a meaningless set). Not guaranteed. Needs σ_i > 0 for every output (CORA divides by it).
//
// Degenerate cases (both conventions):
//   * K_j = C_i t_j = 0 (or, Setbound, not certified positive): ξ_j keeps [−1, 1] (stage 2), and
//     t_j is never the swapped column (its score is 0).
//   * A generator collapsing to zero (stage 2 with ρ⁺_j + ρ⁻_j = 0, a strip of zero width): the
//     column stays in T as a zero column; the next prediction adds W and the reduction rebuilds
//     n columns.
//   * Fewer than n independent generators after the reduction (no reduction happens when the
//     predicted set has at most n non-zero columns, e.g. W = 0; girard/pca boxes with zero rows):
//     CORA then indexes T out of range (its loop runs over n columns; with pca's unreduced set it
//     silently uses only the first n columns, zero ones included). Here the exactly-zero columns
//     are dropped and T is padded with zero columns to n: the same set, always n columns.
//   * A zero row C_i carries no information on x: its strip is tested (Setbound) and not applied
//     (CORA would divide by ‖p‖² = 0).
//
// Missing outputs (NaN entries of y) are skipped: their strips are not applied.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "setbound/core/convention.hpp"
#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/state.hpp"
#include "setbound/estimators/measurement_check.hpp"
#include "setbound/sets/zonotope.hpp"
#include "setbound/sets/zonotope_reduction.hpp"

namespace setbound {

struct ParallelotopeOptions {
  /// Girard (CORA's default: the interval hull) or Pca (a PCA-oriented box). Combastel is refused
  /// (at order 1 it is Girard's box).
  ZonotopeReduction reduction = ZonotopeReduction::Girard;
  Convention convention = Convention::Setbound;
  /// Setbound only (Cora has no emptiness check and accepts only Flag): what a reading outside
  /// the predicted output set does (measurement_check.hpp); Reset restarts from x0.
  OnInconsistency on_inconsistency = OnInconsistency::Flag;
};

/// Sets of one run: row k of center/lower/upper and element k of the lists describe x_k.
struct ParallelotopeTrajectory {
  Eigen::MatrixXd center, lower, upper;  ///< N × n_x
  std::vector<Zonotope> sets;
  std::vector<MeasurementCheck> checks;
};

class ParallelotopeEstimator {
 public:
  ParallelotopeEstimator(LinearSystem system, const Zonotope& x0, ParallelotopeOptions options = {});

  const LinearSystem& system() const { return sys_; }
  const ParallelotopeOptions& options() const { return opt_; }
  Eigen::Index steps_taken() const { return k_; }

  /// Uses y_k (NaN entries: missing outputs) and u_k: the current set becomes the set for x_k and
  /// the prior is predicted to x_{k+1}. On error (bad input, policy Raise, overflow) the estimator
  /// is unchanged.
  void update(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);
  Zonotope step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
    update(y, u);
    return current_set();
  }

  bool has_current() const { return has_current_; }
  /// The set of the last step: centre ⊕ generators B ⊕ box(current_box()); after a correction the
  /// generators are the n×n parallelotope T (Cora, step 0: R0's generators).
  const Eigen::VectorXd& current_center() const { return cur_.p; }
  const Eigen::MatrixXd& current_generators() const { return cur_.G; }
  /// The pending rounding box (always zero in the Cora convention).
  const Eigen::VectorXd& current_box() const { return cur_.r; }
  const Eigen::VectorXd& current_lower() const { return lo_; }
  const Eigen::VectorXd& current_upper() const { return hi_; }
  /// The set of the last step, the rounding box as axis-aligned generators after T.
  Zonotope current_set() const;
  /// Screening of the last update: per output used / missing / inconsistent / unused, margins.
  const MeasurementCheck& last_check() const { return last_check_; }

  /// Back to the state of construction (options kept).
  void reset();

  /// Runs rows of Y (N × n_y) and U (N × n_u; empty when n_u = 0) from x0 (reset() first).
  ParallelotopeTrajectory run(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U = Eigen::MatrixXd());

  /// The state: step counter, the prior (set for x_{k+1} before reduction) and the current set
  /// (centre, box, generators each). The screening of the last step is not part of it.
  std::vector<double> save_state() const;
  /// Restores a state of save_state() into an estimator of the same system and options; throws
  /// InvalidArgumentError ("state: ...") otherwise, unchanged on error.
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

  /// A set with its pending rounding box: p ⊕ G B ⊕ box(r).
  struct Set {
    Eigen::VectorXd p, r;
    Eigen::MatrixXd G;
  };

  /// One Vicino–Zappa step of the parallelotope X (p, n×n G, box r) with the strip
  /// |cᵀx − y| ≤ sigma, in the given convention (Setbound: outward rounded, the strip widened by
  /// the box; Cora: CORA's normalised arithmetic). Exposed for tests. Returns whether stage 3
  /// swapped a column.
  static bool vicino_zappa(Set& X, const Eigen::Ref<const Eigen::VectorXd>& c, double y, double sigma,
                           Convention convention);

 private:
  using Mat = Eigen::MatrixXd;
  using Vec = Eigen::VectorXd;
  static constexpr double kBoxToGenerators = 1e-6;

  void load_initial();
  /// y_i − D_i u and its half-width (widened by that rounding) for output i.
  double shifted(Eigen::Index i, const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, double& sig) const;
  /// Reduces X to n columns (CORA's order-1 reduction), absorbing the box when it reduces, and
  /// pads with zero columns.
  void to_parallelotope(Set& X);
  /// The strips of the outputs present, one after another; the screening goes to chk. Throws
  /// under policy Raise.
  void correct(Set& X, const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, MeasurementCheck& chk) const;
  void predict(Set& X, const Eigen::Ref<const Vec>& u) const;
  void hull(const Set& X);

  LinearSystem sys_;
  ParallelotopeOptions opt_;
  Zonotope x0_;
  Eigen::Index n_ = 0;
  Mat Enz_;    // non-zero columns of E
  Vec sigma_;  // Σ_j |F_ij| rounded up

  Set prior_, cur_;
  bool has_current_ = false;
  Eigen::Index k_ = 0;
  Vec lo_, hi_;
  MeasurementCheck last_check_;
  detail::ReductionWorkspace rws_;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/zonotopic/impl/parallelotope.ipp"
#endif
