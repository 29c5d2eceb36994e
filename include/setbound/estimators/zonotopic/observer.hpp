// setbound — one zonotopic skeleton for CORA's zonotopic observer catalogue, the gain rule being
// the varying part (spec cora_observers.md §1.3, §2.2–§2.11).
//
// Two skeletons share the state (a zonotope p ⊕ G B^m plus a pending rounding box, below), the
// order reduction and the rounding analysis:
//
//   strip-based (a filter; row k of a run is the set for x_k after y_k):
//     X̂_k = reduce(Corr(X̄_k, y_k)),   X̄_{k+1} = A X̂_k ⊕ (B u_k) ⊕ E B^{n_ω}
//     Corr with an n×q weight Λ on the strips |C_S x − y_S| ≤ σ_S ([Le2013 ISIC] Prop. 1):
//       p' = p + Λ (y_S − C_S p),   G' = [(I − Λ C_S) G, Λ diag(σ_S)]
//     one output at a time (q = 1, "S-I": segment minimisation = FRad-A, the volume-minimising
//     LP = VolMin-A, Bravo = VolMin-B, fixed λ_i = PRad-A) or all outputs at once ("S-II":
//     Wang's Kalman-like Λ = FRad-B, a fixed Λ = PRad-B/C/D);
//   intersection-free (a predictor; row k is the set for x_k from y_0 … y_{k−1}):
//     X_{k+1} = reduce((A − L_k C) X_k ⊕ (B u_k + L_k (y_k − D u_k)) ⊕ (E − L_k F) B^{n_ω})
//     with Combastel's adaptive L_k (FRad-C) or a fixed L (PRad-E, Nom-G).
//
// Guarantee: both corrections are outer bounds for ANY weight (x = x + Λ(y − C x − v) for the
// strip update, x_{k+1} = (A − LC) x_k + L(y_k − D u_k − F ω_k) + B u_k + E ω_k for the
// propagation), so the rule only decides the size. In the propagation the disturbance ω_k of
// y_k and of x_{k+1} is the same vector (setbound's model), hence the combined columns E − L F;
// with CORA's model (E = [G_W, 0], F = [0, G_V]) they are CORA's [−L G_V, G_W].
//
// Floating point: every step bounds the rounding of its products (Higham's γ_k) and of the
// computed I − ΛC / A − LC, and collects it in a pending axis-aligned box B_r that is carried
// (|M| r through a map) but never counted as generators; the reduction absorbs it
// (zonotope_reduction.hpp), and a box above 1e-6 of the set's largest radius becomes
// generators. CORA's generator counts and choices are therefore unchanged.
//
// Cost: one n × n map per step. A filter keeps its prior implicit (A·X̂_{k−1} ⊕ B u ⊕ E) and
// composes the prediction and the strips into one map T (K A for S-II, K_q…K_1 A for S-I) and
// the new columns N, so the n × m generators are touched once (T G) instead of four times;
// the gains come from the n × n Gram matrix S = G Gᵀ kept with the current set (R̄ = A S Aᵀ +
// E Eᵀ), never from products with G. The rounding of T, N and the centre are carried as bounds
// dT, dN, e and land in the box: |T_exact − T| <= dT gives dT (rs|G| + r) + |T| (γ rs|G| + r).
// Bravo's candidates are not a linear map of the set (a column is replaced), so Bravo keeps the
// prior implicit too but forms its columns [A G, E] once per step (map_current) and runs its
// strips on them in place; its Gram matrix follows the set (A S Aᵀ + E Eᵀ, then the strips'
// and the reduction's rank updates) instead of being recomputed from the columns.
// Bravo's strips skip what cannot change the choice: by Cauchy–Schwarz in the metric of S every
// candidate scores at least σ²/(cᵀSc), so a strip with σ² >= cᵀSc keeps the set with an n²
// test and no pass over the columns (tank30: 18 of its 21 strips per step once settled); for
// n > 8 the leverage scores g_jᵀS⁻¹g_j are computed only for the columns whose lower bound
// ‖g_j‖²/λ_max(S) can still win (generator_kernels.hpp). A banded A (a chain of tanks) maps the
// columns by its diagonals, and an output that reads one state reads one row of G.
//
// Negligible generators (Setbound's convention): a column below 1e-12 of the set's radius in
// every coordinate (|g_ij| <= 1e-12 rs|G|_i) moves into the pending box at the end of a step
// (an outer bound; the box stays far below its 1e-6 threshold). Bravo's replacing strips
// project every other column onto the strip's hyperplane, so in a long run the old columns
// collapse to rounding noise (vehicle6 at CORA's order 100: 464 of 600 columns below 1e-12 of
// the largest). Kept, they cost every pass and could even be chosen (a candidate's score does
// not depend on the column's length); moved to the box, the count settles (vehicle6: ~140) and
// the order limit counts only columns that matter. The Cora convention keeps them (CORA's counts).
//
// Conventions (Convention): Setbound (default) runs the papers' algorithms; Cora
// reproduces CORA's behaviour where it differs and stays guaranteed:
//   * FRad-B (§2.4): Cora builds the gain from A P Aᵀ + G_W G_Wᵀ with P = G Gᵀ of the
//     *predicted* set (A and W applied twice, sic); Setbound uses the paper's R̄ = P of the
//     predicted set (= A P_{k−1} Aᵀ + G_W G_Wᵀ of the previous corrected set, Wang 2018 Thm. 2).
//   * VolMin-B (§2.2): Cora tests |cᵀg_j| > 10¹⁰·eps absolutely; Setbound relative to |c|ᵀ|g_j|.
//   * strip-based skeleton: Cora does not reduce the first corrected set (§1.3).
// CORA's omission of the constant c in the intersection-free skeleton (§1.3, sic) is not
// reproducible by a guaranteed estimator: setbound's model has c inside B u, and setbound.cora
// refuses a model with c ≠ 0 under the Cora convention.
//
// Explicit prior. Two cases keep the filter's prior as explicit columns, predicted at the end of
// each step, and correct it as the first step corrects x0 (strip_update on the set): the volume-
// minimising rule (its LP needs the generators before each strip, and costs far more than the
// map) and an interval [A] ∈ [mid − rad, mid + rad] (papers.md §3.1, [Le2013] §3.4): the
// prediction is mid·X ⊕ B u ⊕ E ⊕ box(rad·rs|G|) ⊕ box(rad·|p|) (the two boxes as diagonal
// columns, as ZonotopicEstimator forms them) and the pending box goes through |mid| + rad. The
// intersection-free rules need a known A (their map A − L C would be an interval matrix).
//
// Missing outputs (NaN entries of y) are skipped: their strips are not applied, their columns of
// Λ / L are zero for the step (still valid).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "setbound/core/convention.hpp"
#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/state.hpp"
#include "setbound/estimators/measurement_check.hpp"
#include "setbound/sets/generator_kernels.hpp"
#include "setbound/sets/zonotope.hpp"
#include "setbound/sets/zonotope_reduction.hpp"

namespace setbound {

/// The gain rules of the shared skeleton, by skeleton (the values are the C ABI's).
enum class ZonotopicRule {
  SegmentMin = 1,   ///< S-I, [Alamo2005] segment minimisation (CORA FRad-A)
  Bravo = 2,        ///< S-I, Bravo 2006 candidate parallelotopes (CORA VolMin-B)
  FixedStrips = 3,  ///< S-I, λ_i = column i of a given n×p gain (CORA PRad-A)
  Wang = 4,         ///< S-II, Wang et al. 2018 Kalman-like Λ (CORA FRad-B)
  FixedLambda = 5,  ///< S-II, a given n×p Λ (CORA PRad-B, PRad-C, PRad-D)
  Combastel = 6,    ///< intersection-free, Combastel 2015 adaptive L_k (CORA FRad-C)
  FixedGain = 7,    ///< intersection-free, a given n×p L (CORA PRad-E, Nom-G)
  VolumeMin = 8,    ///< S-I, [Alamo2005] exact volume minimisation by an LP per strip (CORA VolMin-A)
};

/// Whether the rule runs the intersection-free (predictor) skeleton.
bool is_intersection_free(ZonotopicRule rule);
/// Whether the rule needs a given gain (FixedStrips, FixedLambda, FixedGain).
bool needs_gain(ZonotopicRule rule);

struct ZonotopicObserverOptions {
  ZonotopicRule rule = ZonotopicRule::SegmentMin;
  Eigen::MatrixXd gain;               ///< n_x × n_y, for the fixed rules only
  Eigen::Index max_generators = 20;   ///< reduction limit (>= n_x), rounding box not counted
  ZonotopeReduction reduction = ZonotopeReduction::Combastel;
  Convention convention = Convention::Setbound;
  /// Setbound only (CORA tests nothing, so Cora accepts only Flag): what a reading outside the
  /// output set of the set it corrects (filter: the prior; predictor: the current set) does
  /// (measurement_check.hpp): skipped and flagged, an InconsistentMeasurementError, or a
  /// restart from x0 corrected with the readings consistent with it.
  OnInconsistency on_inconsistency = OnInconsistency::Flag;
};

/// Sets of one run: row k of center/lower/upper and element k of `sets` bound x_k.
struct ZonotopicObserverTrajectory {
  Eigen::MatrixXd center, lower, upper;  ///< N × n_x
  std::vector<Zonotope> sets;
};

class ZonotopicObserver {
 public:
  ZonotopicObserver(LinearSystem system, const Zonotope& x0, ZonotopicObserverOptions options);

  const LinearSystem& system() const { return sys_; }
  const ZonotopicObserverOptions& options() const { return opt_; }
  /// True for the strip-based rules (row k uses y_k), false for the intersection-free ones.
  bool is_filter() const { return !is_intersection_free(opt_.rule); }
  Eigen::Index steps_taken() const { return k_; }

  /// Uses y_k (NaN entries: missing outputs) and u_k. Filter: the current set becomes the set
  /// for x_k, and the prior is predicted to x_{k+1}. Predictor: the current set becomes the set
  /// for x_{k+1}. On error the observer is unchanged.
  void update(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);
  Zonotope step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
    update(y, u);
    return current_set();
  }

  /// Whether current_set() exists (a filter before its first step has none; a predictor's
  /// current set is x0 before its first step).
  bool has_current() const { return has_current_; }
  /// The current set, the pending rounding box as axis-aligned generators.
  Zonotope current_set() const;
  /// Generator count of current_set() (the columns and the non-zero box entries), without forming it.
  Eigen::Index current_num_generators() const;
  const Eigen::VectorXd& current_center() const { return cur_.p; }
  const Eigen::VectorXd& current_lower() const { return lo_; }
  const Eigen::VectorXd& current_upper() const { return hi_; }
  /// The weight of the last correction (n × n_y; Λ, the λ_i as columns, or L; zero columns for
  /// missing outputs). For Bravo, column i is the λ of the chosen candidate (zero: no change).
  const Eigen::MatrixXd& last_gain() const { return gain_last_; }
  /// Screening of the last update: per output used / missing / inconsistent, and its margin
  /// (NaN: missing, or not tested under the Cora convention). A margin <= 0 may be an upper
  /// bound (the reading is inside by at least |margin|): a reading well inside is decided by a
  /// cheap lower bound of the output set's radius, the exact radius is computed otherwise.
  const MeasurementCheck& last_check() const { return last_check_; }
  /// Changes the inconsistency policy from the next step on (Setbound convention only).
  void set_inconsistency_policy(OnInconsistency policy);

  /// Back to the state of construction (options kept).
  void reset();

  /// Runs rows of Y (N × n_y) and U (N × n_u; empty when n_u = 0) from x0 (reset() first).
  /// Row k is the set for x_k: after y_k (filter), from y_0 … y_{k−1} (predictor; row 0 = x0).
  ZonotopicObserverTrajectory run(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U = Eigen::MatrixXd());

  std::vector<double> save_state() const;
  /// Restores a state of save_state() into an observer of the same system and options; throws
  /// InvalidArgumentError ("state: ...") otherwise, unchanged on error.
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

  /// A set with its pending rounding box: p ⊕ G B ⊕ box(r).
  struct Set {
    Eigen::VectorXd p, r;
    Eigen::MatrixXd G;
  };

 private:
  using Mat = Eigen::MatrixXd;
  using Vec = Eigen::VectorXd;
  static constexpr double kBoxToGenerators = 1e-6;
  /// A generator below this fraction of the set's radius in every coordinate goes into the box
  /// under Setbound's convention (see "Negligible generators" above).
  static constexpr double kNegligibleGenerator = 1e-12;
  /// Bravo's threshold on |cᵀg_j| (spec §2.2): absolute under Cora, relative to |c|ᵀ|g_j| otherwise.
  static constexpr double kBravoThreshold = 1e10 * std::numeric_limits<double>::epsilon();

  void setup();
  void load_initial();
  /// One step with the screened readings (inconsistent ones already NaN).
  void advance(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u);
  /// chk_ and yscr_ for this step: missing outputs, then (Setbound) screen() with the impossible
  /// readings turned into missing ones in yscr_.
  void screen_readings(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u);
  /// Tests every present reading against the output set of the set this step corrects
  /// (filter: the prior, explicit or A·cur ⊕ E; predictor: the current set); Raise throws here.
  void screen(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, MeasurementCheck& chk);
  /// y_i − D_i u for the present outputs and their half-widths (widened by that rounding).
  void shifted(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, std::vector<Eigen::Index>& rows,
               Vec& ys, Vec& sig) const;

  // ---- explicit sets (the filter's first step from x0) and Bravo's in-place strips ----------
  /// The strip update of X with weight Lam (n × q) on rows `rows` (values ys, half-widths sig);
  /// the columns Λ diag(σ) are appended (Bravo's replacing update is bravo_update).
  static void strip_update(Set& X, const Mat& Lam, const Mat& CS, const Vec& ys, const Vec& sig);
  /// Bravo's strips (present outputs `rows`, values ys, half-widths sig) on the set
  /// p ⊕ G.leftCols(m) B ⊕ box(r) in place, whose Gram matrix is bravo_S_ (kept up to date);
  /// the λ of each chosen candidate goes to `gain`. The column count does not change.
  void bravo_correct(Mat& G, Eigen::Index m, Vec& p, Vec& r, const std::vector<Eigen::Index>& rows, const Vec& ys,
                     const Vec& sig, Mat& gain);
  /// The Bravo candidate for one strip of G.leftCols(m), whose Gram matrix is bravo_S_: λ (zero:
  /// the set itself) and the column it replaces (−1). Leaves cᵀg_j in bravo_a_ for the update.
  Eigen::Index bravo_choice(const Mat& G, Eigen::Index m, const Eigen::Ref<const Vec>& c, double sig, Vec& lam);
  /// Bravo's strip update in place: p + λ(y − cᵀp), g_i − λ cᵀg_i, column j replaced by σλ, with
  /// the rounding bounds of strip_update; bravo_S_ follows (K S Kᵀ + σ² λλᵀ, exact since K g_j = 0)
  /// and, in the same pass, the scores and the winner of the next strip (normal cn, half-width
  /// sig_next; cn null after the last strip).
  void bravo_update(Mat& G, Eigen::Index m, Vec& p, Vec& r, const Vec& lam, const Eigen::Ref<const Vec>& c, double y,
                    double sig, Eigen::Index j, const Vec* cn, double sig_next);
  /// bravo_llt_ and bravo_Linv_ from bravo_S_; false when S is (numerically) singular.
  bool bravo_factor();
  /// How the passes score the candidates of a strip with half-width sig (CORA's floor on |cᵀg|).
  detail::StripScoring bravo_scoring(double sig) const;
  /// The strip-based correction of X with y_k; the weight used goes to `gain` (n × n_y).
  void correct(Set& X, const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, Mat& gain);

  // ---- one map per step from the current set (no copy, no allocation in the steady state) --
  /// Filter, k >= 1: the corrected set for x_k straight from the one for x_{k−1}: the prediction
  /// A and the strips compose into one n × n map T (and the columns N of E and of the strips),
  /// applied to the generators once. Writes the new set (map_current); returns its column count.
  Eigen::Index correct_from_current(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, Mat& gain);
  /// Bravo's filter, k >= 1: the prior's columns [A G, E] written once into W_ (map_current),
  /// its Gram matrix A S Aᵀ + E Eᵀ from the kept one, then bravo_correct in place. Returns the
  /// column count of W_.
  Eigen::Index bravo_from_current(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, Mat& gain);
  /// Predictor: the set for x_{k+1} from the current one; returns its column count.
  Eigen::Index propagate(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, Mat& gain);
  /// The new set pw_ ⊕ [T G, N_] B ⊕ box(rw_) from the current set p ⊕ G B ⊕ box(r), given the
  /// computed centre pc_ and the bound ec_ of its error, T with |T − T_exact| <= dT and the
  /// columns N_ with row sums of their error <= dN_. Returns the column count of W_.
  Eigen::Index map_current(const Mat& T, const Mat& dT, Eigen::Index nN, double g);
  /// R = A S Aᵀ + E Eᵀ: the Gram matrix of the (implicit) prior from the current set's.
  void prior_gram(Mat& R);
  /// Drops zero columns of the first m of W, turns a large box r into generators, reduces when
  /// above the limit; w = rs|W| rounded up. W needs room for m + n columns. Returns the count.
  /// With S, the Gram matrix of W's columns is kept up to date through the box columns and the
  /// reduction (rank updates; it feeds the gains only, so its rounding costs no guarantee).
  Eigen::Index finish_set(Mat& W, Eigen::Index m, Vec& r, Vec& w, bool reduce, Mat* S);
  /// The current set's hull; its row sums and Gram matrix from its columns when asked.
  void refresh_current(bool row_sums, bool gram);
  void ensure_columns(Mat& M, Eigen::Index cols) const;
  static Mat solve_gain(const Mat& num, const Mat& S);
  /// Wang, Puig, Cembrano 2018 Thm. 2 (FRad-B): Lam = R̄ C_Sᵀ (C_S R̄ C_Sᵀ + (F Fᵀ)_SS)⁻¹ from R
  /// = the predicted set's G Gᵀ (n × n; overwritten: CORA's convention maps it a second time,
  /// A R Aᵀ + E Eᵀ, spec §2.4). The one formula of both steps' paths (explicit or implicit prior).
  void wang_gain(Mat& R, const Mat& CS, const std::vector<Eigen::Index>& rows, Mat& Lam);
  /// C_S: the rows `rows` of C (the present outputs), q × n.
  static void gather_rows(const Mat& C, const std::vector<Eigen::Index>& rows, Mat& CS);
  /// S += (F Fᵀ)_SS, the present outputs' block of the noise Gram matrix (q × q).
  void add_noise_block(const std::vector<Eigen::Index>& rows, Mat& S) const;
  /// Explicit-prior filters: prior_ = the set for x_{k+1} from the current one and u_k, as
  /// columns [mid·G, E, diag(rad·w), diag(rad·|p|)] with every rounding in its box.
  void predict_explicit(const Eigen::Ref<const Vec>& u);

  LinearSystem sys_;
  ZonotopicObserverOptions opt_;
  Zonotope x0_;
  Eigen::Index n_ = 0;
  bool needs_gram_ = false;
  bool explicit_prior_ = false;  // the prior is kept as columns (VolumeMin, interval [A])
  bool gram_from_strips_ = false;  // this step's R_ is the corrected set's Gram matrix (segment min.)
  Mat Enz_;           // non-zero columns of E (strip-based prediction)
  Vec sigma_;         // Σ_j |F_ij| rounded up
  Mat FFt_, EEt_;     // F Fᵀ, E Eᵀ (Wang, Combastel)
  Mat absA_, absB_, absC_;
  Vec rsE_;           // rs|Enz|
  std::vector<Eigen::Index> fcols_, ecols_;  // ω columns with F ≠ 0, then those with F = 0, E ≠ 0

  // filter: prior_ = the set for x_0 before y_0; after the first step the prior is implicit,
  // A·cur_ ⊕ E, and prior_ holds its centre and that centre's error only. Predictor: cur_ only.
  Set prior_, cur_;
  Vec w_cur_;          // rs|cur_.G| rounded up
  Mat S_cur_;          // ≈ cur_.G cur_.Gᵀ, updated per step (the gains, Bravo, the screening)
  bool has_current_ = false;
  Eigen::Index k_ = 0;
  Vec lo_, hi_;
  Mat gain_last_;
  MeasurementCheck chk_, last_check_;  // the step's screening (scratch), the last one reported
  detail::ReductionWorkspace rws_;

  // Scratch of one step (sized once; the steady state does not allocate).
  Mat W_, N_, T_, Snew_, dT_, absT_, R_, RC_, Sq_, CS_, CSA_, CSE_, ARC_, Lam_, absL_, absCS_, K_, dK_, gainw_;
  Vec pw_, rw_, ww_, pc_, pn_, ec_, dN_, lam_, al_, t_, v_, sc_, cN_, innov_, yfull_, yabs_, tmp_;
  std::vector<Eigen::Index> rows_, screen_rows_;
  // Bravo: the Gram matrix of the set being corrected (from the kept S_cur_, then rank updates
  // through its strips), L⁻¹ of its Cholesky factor, and the candidate pass's per-column values.
  // bravo_ready_: a = cᵀg_j of the next strip's normal and h the current leverage scores (NaN
  // where the update's cancellation asks for a recomputation), from bravo_update's pass.
  // bravo_w_ >= rs|G| of the set being corrected: a bound carried through the strips, not a pass.
  Mat bravo_S_, bravo_Linv_;
  // Factored from an empty matrix at construction: Eigen 3.4's default LLT leaves its `info`
  // uninitialised, and copying the observer (update works on a copy) read it (UBSan: invalid
  // enum load, seen when an earlier test left garbage in the reused memory).
  Eigen::LLT<Mat, Eigen::Lower> bravo_llt_{Mat()};
  Eigen::Index bravo_next_ = -1;  // the next strip's winner from bravo_update's pass (bravo_ready_)
  // Whether bravo_S_ is factored with the scores h of the current columns (Scored), numerically
  // singular (Flat: every choice is the set itself until S changes) or neither (Unknown).
  enum class BravoState { Unknown, Scored, Flat };
  BravoState bravo_state_ = BravoState::Unknown;
  Vec bravo_a_, bravo_h_, bravo_w_, bravo_z_, bravo_res_, bravo_c_, bravo_cn_;
  bool bravo_ready_ = false;
  Vec ys_, sig_, screen_ys_, screen_sig_, yscr_, ta_, wp_;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/zonotopic/impl/observer.ipp"
#endif
