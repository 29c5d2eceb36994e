// setbound — the zonotopic estimator structure of papers.md §3.1 (Algorithm 1 of [Le2013]).
//
//   prediction (A known):  p⁺ = A p + B u,  H⁺ = [A H, E]
//   prediction ([A]):      p⁺ = mid[A] p + B u,  H⁺ = [mid[A] H, rs(rad[A]|H|), diag(rad[A]|p|), E]
//   correction, strip by strip (|c_iᵀx + D_i u − y_i| ≤ φ_i, φ_i = Σ_j |F_ij|):
//                          p̂ = p + λ_i (y_i − D_i u − c_iᵀ p),  Ĥ = [(I − λ_i c_iᵀ) H, φ_i λ_i]
//   reduction to at most s generators (options.reduction: Combastel, papers §0.1; Girard; or
//   CORA's PCA), when more than s non-zero generators are left after the correction.
//
// Guarantee: x_k ∈ X̂_k for ANY choice of λ_i ([Le2013] Property 6), because prediction,
// correction and reduction are all outer approximations. The gain rule only changes the size.
//
// Floating point. The products A p, A H, λ(y − cᵀp) and (I − λcᵀ)H are rounded. Their errors
// are bounded (Higham's γ_k) and collected in one pending box B_r, carried exactly through
// later corrections ((Z ⊕ B_r) ∩ S ⊆ family(Z) ⊕ κB_r ⊆ family(Z) ⊕ box(|κ|r), κ = I − λcᵀ) and
// predictions (A B_r ⊆ box(|A| r)). The reduction absorbs the box into its replacement
// generators, so the box never counts toward max_generators and never changes which generators
// are kept (CORA's choices are reproduced); between reductions a set is Z ⊕ B_r, reported with
// up to n_x extra axis-aligned generators. Should the box grow above 1e-6 of the set's largest
// radius before a reduction (a long run with no reduction), it is appended as generators. It
// is ~1e-15 of the radius on small systems, up to ~1e-11 of the largest radius on tank30.
//
// Speed. Segment minimisation and fixed gains need only the n×n Gram matrix S = H Hᵀ and the
// strip data, so the generator matrix is not touched strip by strip: the corrections and the
// next prediction accumulate into an n×n transform T (H_k = T H_{k−1} ⊕ new columns), applied
// once per step with one matrix product; S is updated alongside (rank-two updates, the
// reduction's removed and added columns). Other gain rules (volume minimisation, user rules)
// receive the set before each strip as a Zonotope. All buffers are allocated at construction.
//
// Time indexing (identical for every estimator of the library): measurements y_0 … y_{N−1},
// inputs u_0 … u_{N−1}; row k of a trajectory is a set for x_k. step(y_k, u_k) returns the set
// for x_k after using y_k (this family is a filter) and then predicts x_{k+1} with u_k.
// With use_first_measurement = false the first step returns X_0 unchanged, as [Le2013] does.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <functional>
#include <limits>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/state.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/measurement_check.hpp"
#include "setbound/sets/generator_kernels.hpp"
#include "setbound/sets/strip.hpp"
#include "setbound/sets/zonotope.hpp"

namespace setbound {

/// One-strip correction: the output-i row (c, D_i u, φ) of the model and the gain λ.
struct StripMeasurement {
  Strip strip;   // |cᵀx − (y_i − D_i u)| ≤ φ
  Eigen::Index output;
};

/// λ rule: given the set before the strip and the strip, return λ (any λ is guaranteed).
using ZonotopeGainRule = std::function<Eigen::VectorXd(const Zonotope&, const StripMeasurement&)>;

/// [Alamo2005] segment minimisation (papers.md §5.1): λ* = H Hᵀ c / (cᵀ H Hᵀ c + φ²), the
/// minimiser of ‖(I − λcᵀ)H‖_F² + φ²‖λ‖². With nothing to gain (H Hᵀ c = 0) λ = 0.
Eigen::VectorXd segment_min_gain(const Zonotope& Z, const StripMeasurement& m);

/// The estimator's gain rule. Segment minimisation (segment_min_gain, also inside a
/// ZonotopeGainRule) and fixed gains (ZonotopeGain::fixed, pradius_gain) are recognised and
/// run on the estimator's fast path; any other callable gets the set before each strip.
class ZonotopeGain {
 public:
  enum class Kind { SegmentMin, Fixed, Custom };
  using Function = Eigen::VectorXd (*)(const Zonotope&, const StripMeasurement&);

  ZonotopeGain(Function f);
  ZonotopeGain(ZonotopeGainRule rule);
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, Function> &&
                                              !std::is_same_v<std::decay_t<F>, ZonotopeGain> &&
                                              !std::is_same_v<std::decay_t<F>, ZonotopeGainRule> &&
                                              std::is_invocable_r_v<Eigen::VectorXd, F&, const Zonotope&,
                                                                    const StripMeasurement&>>>
  ZonotopeGain(F f) : ZonotopeGain(ZonotopeGainRule(std::move(f))) {}  // NOLINT

  /// Fixed gains: row i is λ_i of output i (e.g. an offline P-radius design).
  static ZonotopeGain fixed(Eigen::MatrixXd lambdas);

  Kind kind() const { return kind_; }
  const Eigen::MatrixXd& lambdas() const { return lambdas_; }
  explicit operator bool() const;

  Eigen::VectorXd operator()(const Zonotope& Z, const StripMeasurement& m) const;

 private:
  ZonotopeGain() = default;
  Kind kind_ = Kind::Custom;
  ZonotopeGainRule rule_;
  Eigen::MatrixXd lambdas_;
};

struct ZonotopicOptions {
  Eigen::Index max_generators = 20;   ///< reduction limit s (>= n_x), rounding box not counted
  bool use_first_measurement = true;  ///< intersect X_0 with the strips of y_0 (CORA's loop)
  std::vector<Eigen::Index> strip_order;  ///< order of the outputs; empty = 0, 1, …, n_y − 1
  /// Combastel (papers §0.1), Girard (CORA's default) or Pca (CORA's observer examples).
  ZonotopeReduction reduction = ZonotopeReduction::Combastel;
  /// A reading outside the predicted output set (measurement_check.hpp): Flag (skip it and mark
  /// the step), Raise (InconsistentMeasurementError, estimator unchanged) or Reset (restart from
  /// the reset set, by default x0, and correct with the outputs consistent with it).
  OnInconsistency on_inconsistency = OnInconsistency::Flag;
};

/// Sets of one run: row k of center/lower/upper and element k of the lists describe x_k.
struct ZonotopeTrajectory {
  Eigen::MatrixXd center, lower, upper;  ///< N × n_x
  std::vector<Zonotope> sets;
  std::vector<MeasurementCheck> checks;  ///< which outputs each step used, and the margins
};

class ZonotopicEstimator {
 public:
  ZonotopicEstimator(LinearSystem system, const Zonotope& x0, ZonotopeGain gain, ZonotopicOptions options = {});

  const LinearSystem& system() const { return sys_; }
  const ZonotopicOptions& options() const { return opt_; }
  /// Changes the reduction method from the next step on (every method is guaranteed).
  void set_reduction(ZonotopeReduction method) { opt_.reduction = method; }
  /// Changes the inconsistency policy from the next step on; `reset_set` (Reset only; default
  /// x0) must have the state dimension and at most max(max_generators, generators of x0)
  /// generators.
  void set_inconsistency_policy(OnInconsistency policy);
  void set_inconsistency_policy(OnInconsistency policy, const Zonotope& reset_set);
  Eigen::Index steps_taken() const { return k_; }
  /// Back to the state of construction: the prior is x0 again, no step taken (the options,
  /// the reduction method and the policy are kept).
  void reset();

  /// Set for the next state x_{k+1} (before its measurement is used), the pending rounding
  /// box included as generators.
  Zonotope prediction() const;

  /// Uses y_k (and u_k for D u_k), then predicts x_{k+1} with u_k; the set for x_k is then
  /// available from the current_*() accessors. NaN entries of y are missing outputs (not used);
  /// each present output is first tested against the predicted output set and an impossible
  /// reading is handled by the policy (last_check() reports both). On any error the estimator
  /// is unchanged.
  void update(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);

  /// update(), returning the set for x_k.
  Zonotope step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
    update(y, u);
    return current_set();
  }

  // ---- the set for x_k of the last update: centre ⊕ generators B ⊕ box(current_box) ----
  bool has_current() const { return has_current_; }
  const Eigen::VectorXd& current_center() const { return cur_p_; }
  /// n × m generators of the last set (the rounding box excluded, see current_box()).
  Eigen::Block<const Eigen::MatrixXd, Eigen::Dynamic, Eigen::Dynamic, true> current_generators() const {
    return H_[cur_].leftCols(m_);
  }
  /// Radius of the pending rounding box (zero after a step that reduced).
  const Eigen::VectorXd& current_box() const { return cur_r_; }
  const Eigen::VectorXd& current_lower() const { return cur_lo_; }
  const Eigen::VectorXd& current_upper() const { return cur_hi_; }
  /// Screening of the last update: per output used / missing / inconsistent / unused, margins.
  /// A margin > 0 is exact. With segment minimisation (which keeps the Gram matrix) a margin
  /// <= 0 may be an upper bound (the reading is inside by at least |margin|): a reading well
  /// inside is decided by a cheap lower bound of the output set's radius, as the observers do.
  const MeasurementCheck& last_check() const { return last_check_; }
  /// Whether the last update ran the order reduction.
  bool reduced_last_step() const { return reduced_; }
  /// Generator count of current_set(): the generators plus the non-zero box entries.
  Eigen::Index current_num_generators() const;
  /// The last set as one zonotope (the rounding box as axis-aligned generators).
  Zonotope current_set() const;

  /// Runs over rows of Y (N × n_y; NaN entries are missing) and U (N × n_u, or empty when
  /// n_u = 0) from the initial set: reset() first, so the same data give the same result.
  ZonotopeTrajectory run(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U = Eigen::MatrixXd());

  /// Strip-by-strip correction (papers §3.1) of X, followed by the reduction (NaN outputs are
  /// skipped; an inconsistent output is skipped, or raises under policy Raise).
  Zonotope correct(const Zonotope& X, const Eigen::Ref<const Eigen::VectorXd>& y,
                   const Eigen::Ref<const Eigen::VectorXd>& u) const;

  /// Prediction of x_{k+1} from a set for x_k (exact for known A, [Le2013] inclusion for [A]).
  Zonotope predict(const Zonotope& X, const Eigen::Ref<const Eigen::VectorXd>& u) const;

  /// Full mutable state (core/state.hpp): the prior for x_{k+1} (centre, the lazy transform T,
  /// its generators and pending boxes, the Gram matrix of segment minimisation), the set of the
  /// last step and its hull, the step counter and the reduction method (set_reduction).
  std::vector<double> save_state() const;
  /// Restores a state from save_state() into an estimator made with the same system, gain rule
  /// and options (the initial set may differ); throws InvalidArgumentError ("state: ...")
  /// otherwise. Unchanged on error, also on memory exhaustion.
  ///
  /// The saved capacity is the saving estimator's work-array size, max(generators of its x0, s)
  /// + the columns one step adds + n; x0 is not part of the design, so after the first step no
  /// design bound exists for it and it never sizes an allocation here: the work arrays are sized
  /// by the generators the blob actually carries (as if x0 had had that many), and kept when the
  /// current ones are large enough. save_state() then reports this estimator's own capacity;
  /// the steps do not depend on it.
  void restore_state(const std::vector<double>& state);
  /// Hash of what a state depends on: the system, the gain rule's kind and fixed gains, and
  /// the options fixed at construction (a custom callable rule is not hashed).
  StateFingerprint fingerprint() const;

 private:
  using Mat = Eigen::MatrixXd;
  using Vec = Eigen::VectorXd;
  /// Pending box above this fraction of the largest radius: appended as generators.
  static constexpr double kBoxToGenerators = 1e-6;

  static Zonotope with_box(const Vec& p, const Eigen::Ref<const Mat>& H, const Vec& r);

  // ---- model data, fixed at construction ---------------------------------------------------
  void setup_model();

  void allocate(Eigen::Index m0);

  /// The prior set p ⊕ H B, exactly (T = I, no pending box).
  void load_prior(const Zonotope& X);

  Eigen::Index mG() const { return mG_; }
  const Mat& G() const { return H_[cur_]; }

  // ---- correction and reduction: writes the current set, the prior stays untouched until
  // the very end (nothing is committed if a gain rule throws) ------------------------------
  void correct_and_reduce(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, bool correct);

  /// Tests output i (y_i − D_i u, half-width φ) against the support interval center ± radius of
  /// the set before its strip (measurement_check.hpp) and records the result in chk_; throws
  /// under policy Raise. Returns whether the strip is used.
  bool screen_output(Eigen::Index i, double yi, double phi, double center, double radius, double magnitude,
                     Eigen::Index terms, const Eigen::Ref<const Vec>& y);

  /// y_i − D_i u and the strip half-width, widened by the rounding of D_i u when D_i ≠ 0.
  double shifted_measurement(Eigen::Index i, const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u,
                             double& phi) const;

  /// W = [T G, N] explicitly; the carried box |T| rA and the product's rounding are added to
  /// r. Returns the column count.
  Eigen::Index materialize_prior(Mat& W, Vec& r) const;

  /// t = |I − λcᵀ| r (the exact |κ|, with λ = lam_), rounded to nearest (the caller inflates).
  void abs_kappa_times(const Eigen::Ref<const Vec>& c, const Vec& r, Vec& t) const;

  /// Strip by strip on the explicit generator matrix, for gain rules that need the set.
  Eigen::Index explicit_strips(Mat& W, Eigen::Index m, const Eigen::Ref<const Vec>& y,
                               const Eigen::Ref<const Vec>& u);

  // ---- prediction of the next prior from the current set ----------------------------------
  void predict_prior(const Eigen::Ref<const Vec>& u);

  LinearSystem sys_;
  ZonotopeGain gain_;
  ZonotopicOptions opt_;
  Eigen::Index n_ = 0, cap_ = 0, capN_ = 0;
  bool lazy_ = false, want_S_ = false, interval_ = false;
  Mat absMid_, absA_, Enz_, EEt_, Ct_, absCt_, absB_, absD_;
  Vec phi_;
  std::vector<bool> D_used_, c_zero_;

  // The prior (the set for x_{k+1}): p_ ⊕ [T_ G, N_] B ⊕ T_ box(rA_) ⊕ box(rP_), with
  // G = H_[cur_].leftCols(mG_); S_ ≈ its Gram matrix (segment minimisation), wG_ = rs|G|
  // rounded up.
  Vec p_, rA_, rP_, wG_;
  Mat T_, N_, S_;
  bool T_identity_ = true;
  Eigen::Index mG_ = 0, mN_ = 0;

  // The current set (x_k): cur_p_ ⊕ H_[cur_].leftCols(m_) B ⊕ box(cur_r_), and its hull.
  Mat H_[2];
  int cur_ = 0;
  Eigen::Index m_ = 0;
  Vec cur_p_, cur_r_, cur_w_, cur_lo_, cur_hi_;
  bool has_current_ = false, reduced_ = false;
  Eigen::Index k_ = 0;

  // Missing and impossible readings: the initial set (reset()), the reset set of policy Reset,
  // the screening of the step being computed (chk_) and of the last committed one.
  Zonotope x0_, reset_set_;
  MeasurementCheck chk_, last_check_;

  // Scratch.
  Vec pc_, rc_, wH_, wGA_, lam_, sc_, v_, t_, e_, cN_, uabs_;
  Mat Tc_, Nc_, Sc_, absT_;
  detail::ReductionWorkspace rws_;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/zonotopic/impl/gain_estimator.ipp"
#endif
