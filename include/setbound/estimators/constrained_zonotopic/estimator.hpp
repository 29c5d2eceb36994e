// setbound — the constrained-zonotope estimators CZN-A and CZN-B (spec cora_observers.md §2.17,
// §2.18; [Scott2016]; Alanwar et al., arXiv:2010.11097, for CZN-B's gain).
//
//   prediction:  X⁺ = A X + B u ⊕ E B^{n_w}                        (W = E·box, exact)
//   correction (CZN-A, ExactOutput): X ∩ {x : y − D u − C x ∈ F B^{n_w}}  (V used as a set);
//       in the bounded mode (Limits) the new rows are then written with the least-squares gain
//       Λ = P Cᵀ (C P Cᵀ + V Vᵀ)⁻¹, P = G Gᵀ (substitute_rows: the same set), so the reduction
//       works on small generators (without it CZN-A drifted on vehicle6; see correct()).
//   correction (CZN-B, WangStrips):  the same strips |C_i x + D_i u − y_i| <= σ_i, σ_i = Σ_j |F_ij|,
//       written with CORA's representation change c' = c + Λ(y − Cc), G' = [(I − ΛC)G, Λ diag σ],
//       Λ = R̄Cᵀ(CR̄Cᵀ + F Fᵀ)⁻¹, R̄ = A GGᵀAᵀ + EEᵀ (A applied twice, as CORA does: sic);
//       the set is the same, the representation differs (so they differ only after a reduction).
//   reduction: CORA's lift (ConstrainedZonotope::reduce_cora) after every correction but the
//       first, at `order` (CORA's zonotopeOrder), or none, or (the default, Limits) guided by
//       the hull LPs' multipliers: the cheapest generators absorbed into a basis of the set's own
//       columns, Scott's elimination (rows ranked by the duals), the lift reduction to limits
//       (ConstrainedZonotope::reduce_limits with a HullSensitivity).
//
// One LP per step (Limits and None): the LP of the corrected set answers the emptiness test and
// the interval hull on one warm basis (and, when a step must screen its readings, the screening's
// LP on the predicted set's rows is extended to the corrected set's: BoxLP::extend, the
// intersection only appends rows and columns). The hull
// reported (current_lower/upper) is that of the corrected set before the reduction: it holds
// every state consistent with the data, and current_set() (reduced) contains it. With CORA's
// reduction the hull is the reduced set's, as CORA computes it. The hull LPs' duals also rank the
// rows for Scott's elimination (ConstrainedZonotope::eliminate_constraints with row weights).
//
// The state disturbance and the output noise share ω in LinearSystem; they are treated as
// independent here (an outer bound; exact for the usual E = [E_d, 0], F = [0, F_v]).
//
// Time indexing (as every estimator of the library): step(y_k, u_k) returns the set for x_k
// after using y_k, then predicts x_{k+1} with u_k. The first set is the initial set corrected
// with y_0 and not reduced (CORA: R{1} = Corr(R0, y_1)).
//
// Real data (issue 24): NaN outputs are missing (not used). Limits and None first use every present
// reading at once: when phase 1 finds a point of the corrected set, that point produces every
// reading, so each is consistent, and their margins are upper bounds of the exact ones (measured
// against the output interval the hull LPs' points span, a part of C_i X; like the zonotopic
// filters' screen). Otherwise (and always with CORA's reduction) each present reading is tested
// against the predicted output set [C_i X] + D_i u ± σ_i, whose ends are certified support values
// (LPs), and an impossible one is handled by `on_inconsistency`. Readings that are each possible
// but jointly impossible leave a certified-empty set: every output of the step is then reported
// inconsistent (margin NaN) and the policy applies to the step. (Consequence of the first path: a
// reading outside C_i X ± σ_i by less than the simplex's feasibility tolerance, 1e-9 of its
// row's scale, counts as consistent.)
#pragma once

#include <Eigen/Core>
#include <vector>

#include "setbound/core/linear_system.hpp"
#include "setbound/core/state.hpp"
#include "setbound/estimators/measurement_check.hpp"
#include "setbound/sets/constrained_zonotope.hpp"
#include "setbound/sets/zonotope.hpp"

namespace setbound {

enum class CZCorrection : int {
  ExactOutput = 0,  ///< CZN-A: intersection with the output set y − D u − F B (exact)
  WangStrips = 1,   ///< CZN-B: strips with the Wang gain's representation
};

enum class CZReduction : int {
  None = 0,    ///< the exact consistent set; memory grows by n_w + n_y columns and n_y rows per step
  Cora = 1,    ///< CORA's lift reduction at `order` (conZonotope/reduce.m); rows are never removed
  Limits = 2,  ///< setbound's bounded mode: Scott's constraint elimination to max_constraints, then
               ///< the lift reduction to max_generators (ConstrainedZonotope::reduce_limits)
};

struct CZOptions {
  CZCorrection correction = CZCorrection::ExactOutput;
  CZReduction reduction = CZReduction::Limits;
  ZonotopeReduction technique = ZonotopeReduction::Girard;  ///< of the lifted zonotope
  double order = 20.0;                ///< Cora: CORA's zonotopeOrder, at most order·n + n_c generators
  Eigen::Index max_constraints = -1;  ///< Limits: rows kept (-1: 4 n_x)
  Eigen::Index max_generators = -1;   ///< Limits: generators kept (-1: 20 n_x + max_constraints)
  bool use_first_measurement = true;  ///< correct the initial set with y_0 (CORA's loop)
  OnInconsistency on_inconsistency = OnInconsistency::Flag;
};

/// Sets of one run: row k of lower/upper and element k of the lists describe x_k.
struct CZTrajectory {
  Eigen::MatrixXd lower, upper;  ///< N × n_x interval hulls (certified)
  std::vector<ConstrainedZonotope> sets;
  std::vector<MeasurementCheck> checks;
};

class ConstrainedZonotopicEstimator {
 public:
  /// Validates the options ("order" >= 1 and finite) and that x0 lives in R^{n_x} ("x0"). The
  /// system must have a known A (an interval A is refused: "system").
  ConstrainedZonotopicEstimator(LinearSystem system, ConstrainedZonotope x0, CZOptions options = {});

  const LinearSystem& system() const { return sys_; }
  const CZOptions& options() const { return opt_; }
  Eigen::Index steps_taken() const { return k_; }

  /// Back to the initial set, no step taken.
  void reset();
  /// The policy from the next step on; `reset_set` (policy Reset) defaults to x0.
  void set_inconsistency_policy(OnInconsistency policy);
  void set_inconsistency_policy(OnInconsistency policy, const ConstrainedZonotope& reset_set);

  /// Uses y_k (NaN entries missing) and u_k, then predicts x_{k+1}. On error (bad input, policy
  /// Raise) the estimator is unchanged.
  void update(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);
  const ConstrainedZonotope& step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
    update(y, u);
    return current_set();
  }

  bool has_current() const { return has_current_; }
  /// The set for x_k of the last update (throws InvalidArgumentError before the first).
  const ConstrainedZonotope& current_set() const;
  const Eigen::VectorXd& current_lower() const { return lo_; }
  const Eigen::VectorXd& current_upper() const { return hi_; }
  const MeasurementCheck& last_check() const { return check_; }
  /// The set for x_{k+1} before its measurement.
  const ConstrainedZonotope& prediction() const { return prior_; }

  /// Runs over the rows of Y (N × n_y) and U (N × n_u, or empty when n_u = 0) from the initial
  /// set (reset() first: the same data give the same result).
  CZTrajectory run(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U = Eigen::MatrixXd());

  /// Full mutable state (core/state.hpp): the step counter, the prior for x_{k+1}, the current set
  /// and its hull, the last screening. Restored into an estimator made with the same system and
  /// options (the initial set may differ) it continues bit-for-bit; refused otherwise
  /// (InvalidArgumentError "state: ..."), the estimator unchanged.
  std::vector<double> save_state() const;
  void restore_state(const std::vector<double>& state);
  /// Hash of what a state depends on: the system matrices and the options that shape the sets.
  StateFingerprint fingerprint() const;

  /// One correction of X with (y, u) by the estimator's method, for the outputs in `used`
  /// (indices into y). No screening, no reduction. The set is exact (up to outward rounding);
  /// its parametrisation depends on the method and, for CZN-A, on the reduction (see above).
  ConstrainedZonotope correct(const ConstrainedZonotope& X, const Eigen::Ref<const Eigen::VectorXd>& y,
                              const Eigen::Ref<const Eigen::VectorXd>& u, const std::vector<Eigen::Index>& used) const;
  /// A X + B u ⊕ E B.
  ConstrainedZonotope predict(const ConstrainedZonotope& X, const Eigen::Ref<const Eigen::VectorXd>& u) const;

 private:
  /// Screens the present outputs of y against X (LPs on `lp`, built on X's rows); returns the
  /// consistent ones (policy Raise throws). Fills chk.
  std::vector<Eigen::Index> screen(const ConstrainedZonotope& X, BoxLP& lp, const Eigen::Ref<const Eigen::VectorXd>& y,
                                   const Eigen::Ref<const Eigen::VectorXd>& u, MeasurementCheck& chk) const;
  /// The margins of the readings used by the optimistic path (see update): against the output
  /// interval spanned by `points` (the hull LPs' points of the corrected set, inside X), so each is
  /// an upper bound of the exact margin against C_i X up to the simplex's tolerance.
  void optimistic_margins(const Eigen::MatrixXd& points, const Eigen::Ref<const Eigen::VectorXd>& y,
                          const Eigen::Ref<const Eigen::VectorXd>& u, MeasurementCheck& chk) const;

  LinearSystem sys_;
  ConstrainedZonotope x0_;
  CZOptions opt_;
  ConstrainedZonotope reset_set_;
  ConstrainedZonotope prior_;
  ConstrainedZonotope current_;
  Eigen::VectorXd sigma_;  // strip half-widths Σ_j |F_ij|, rounded up
  Eigen::VectorXd lo_, hi_;
  MeasurementCheck check_;
  bool has_current_ = false;
  Eigen::Index k_ = 0;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/constrained_zonotopic/impl/estimator.ipp"
#endif
