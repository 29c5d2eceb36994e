// setbound — ellipsoidal one-step predictors ([BenChabane2014], papers.md §1, §6.7).
//
//   x_{k+1} = A x_k + B u_k + E ω_k,   y_k = C x_k + D u_k + F ω_k,   ω_k ∈ B^{n_ω},
//
// estimated by E(P, x̄_k, ρ_k) = { x : (x − x̄_k)ᵀ P (x − x̄_k) ≤ ρ_k } with a shape P fixed
// offline, the centre x̄_{k+1} = A x̄_k + B u_k + L_k (y_k − C x̄_k − D u_k) (a one-step
// predictor: y_k gives the set for x_{k+1}) and a radius from the prediction LMI
//
//   M(β, Y, σ; A_j, ω) = [ βP          0      (P A_j − Y C)ᵀ ]
//                        [ 0           σ      ωᵀ(P E − Y F)ᵀ ]  ⪰ 0,   L = P⁻¹Y,
//                        [ P A_j − YC  (PE − YF)ω    P       ]
//
// at every vertex ω of the disturbance box (and every vertex A_j of an interval A). By a Schur
// complement it says β zᵀPz + σ ≥ (A_L z + E_L ω)ᵀ P (A_L z + E_L ω) (A_L = A − LC, E_L = E −
// LF), so z_k ∈ E(P, 0, ρ_k) ⇒ z_{k+1} ∈ E(P, 0, βρ_k + σ): the S-procedure of §1.1.
//
//  * design_ellipsoidal_offline (§1.1): (P, L, β, σ) once. The LMI is homogeneous in (P, Y, σ),
//    so it needs a lower-bound normalisation (§1.1, §8 item 1): LogDet (default) fixes σ = 1 and
//    maximises log det P, which for fixed β is exactly the minimum steady-state volume
//    V_n (σ/(1−β))^{n/2} / √det P; the result is rescaled to det P = 1. Ball imposes P ⪰ I and
//    minimises σ. PaperTrace imposes tr P ≤ 1 as printed: an *upper* bound, so the infimum is
//    σ = 0 with P → 0 (degenerate; P ends at the size of the LMI margin). β is searched on the
//    real criterion (§0.4): the steady-state volume for LogDet, ρ∞ = σ/(1−β) otherwise.
//  * EllipsoidalPredictor: Offline (ρ⁺ = βρ + σ), OnlineVertex (§1.2: per step min ρ⁺ over
//    (β, Y_k) with P fixed, the same vertex LMI with σ_k = ρ⁺ − βρ_k, written with σ_k as the
//    variable: min βρ_k + σ_k, σ_k ≤ σ; solved by an exact active set over the vertex blocks,
//    see EllOnlineProblem), OnlineScaled (§1.3 in the simplified S = diag(s) form: one LMI of
//    size 2n_x + n_ω and Σ s_i ≤ ρ⁺ − βρ_k). With an optimal design (σ = least σ at β_d for its
//    P) the bound σ_k ≤ σ forces β ≥ β_d: the online step then gains over the design only when
//    ρ_k is below the steady state, or when the design is not optimal (e.g. PaperTrace).
//
// Vertex lists: only the non-zero columns of [E; F] enter, and the ± symmetry of §0.2 halves
// the ω list (congruence with diag(I, −1, I) maps M(ω) to M(−ω), exactly, also in floating
// point). With an interval A (§6.7) the centre uses mid[A] = A_c and the error gets the extra
// term (A − A_c) x̄_k: OnlineVertex puts P(A_j − A_c) x̄_k into the σ row of every (A_j, ω) block
// (no halving then), OnlineScaled treats it as a box disturbance diag(rad[A] |x̄_k|) B^{n_x}.
// The offline *shape* design imposes the LMI at every A_j without that term (a robustly
// contracting gain); the Offline *predictor* cannot be used with an interval A, because the
// centre term has no a-priori bound.
//
// Guarantee in floating point (ellipsoidal/common.hpp): every (β, L, σ) that a step uses is
// certified by certify_psd on the LMI blocks rebuilt from those exact values, with an absolute
// slack that bounds the rounding made while forming them; the level is rounded up and
// enlarged for the rounding of the centre. An online step whose solve fails or whose result
// cannot be certified falls back to the design's certified (β, L, σ) (interval A: the design's
// (β, L) with the σ_k its blocks need), so a step never loses the guarantee.
//
// Real measurement data (issue 24, measurement_check.hpp). Before a step, every present output
// is tested against the support of E(P, x̄_k, ρ_k) in ±C_i: C_i x̄_k + D_i u ± (√(ρ_k q_i) + φ_i),
// with q_i ≥ C_i P⁻¹ C_iᵀ certified once (Schur complement [P, C_iᵀ; C_i, q_i] ⪰ 0). A missing
// (NaN) or impossible output is not used: the gain and the certificate above are for the full
// C, so such a step is a *partial step*: a gain with zero columns on the outputs not used (the
// design's L restricted to the outputs used, or L = 0: pure prediction), whichever certified
// level is smaller, with β and σ found for that fixed gain (β on a grid above the gain's
// contraction factor a² = max_j λ_max(P⁻¹ A_Ljᵀ P A_Lj), σ the least value the vertex blocks
// need at that β, certified by ell_interval_sigma). β may then exceed 1 (an unstable A
// without correction): the set grows, and stays guaranteed.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SVD>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/symmetric.hpp"
#include "setbound/core/state.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/ellipsoidal/common.hpp"
#include "setbound/estimators/measurement_check.hpp"
#include "setbound/lmi/classes.hpp"
#include "setbound/lmi/model.hpp"
#include "setbound/lmi/scalar_search.hpp"
#include "setbound/lmi/solver.hpp"
#include "setbound/sets/ellipsoid.hpp"

namespace setbound {

struct EllDesignOptions {
  EllNormalization normalization = EllNormalization::LogDet;
  double beta = std::numeric_limits<double>::quiet_NaN();  ///< fixed β in (0, 1); NaN = search
  double beta_lo = 1e-3, beta_hi = 1.0 - 1e-3;             ///< search interval
  lmi::ScalarSearchOptions search{};
};

struct EllDesign {
  LinearSystem system;              ///< the system designed for (descriptor: its equivalent system)
  Eigen::MatrixXd P, L;             ///< shape, gain (n_x × n_y)
  double beta = 0, sigma = 0;       ///< certified: ρ⁺ = βρ + σ is guaranteed
  double rho_inf = 0;               ///< σ / (1 − β), rounded up
  double volume_inf = 0;            ///< volume of E(P, ·, rho_inf)
  EllNormalization normalization = EllNormalization::LogDet;
  int vertex_blocks = 0;            ///< LMI blocks imposed (± halving, zero columns dropped, × vert[A])
};

enum class EllPredictorMode { Offline = 0, OnlineVertex = 1, OnlineScaled = 2 };

namespace detail {

/// Largest number of vertex blocks an ellipsoidal LMI may have (design or online step).
inline constexpr std::size_t kMaxEllVertexBlocks = 4096;
/// Margin (in the normalised units of the solver problems) with which LMIs are imposed.
inline constexpr double kEllLmiMargin = 1e-9;

/// One vertex of [A]: A_j = fl(A_c + D_j) and D_j = A_j − A_c exactly (each uncertain entry ±rad).
struct EllAVertex {
  Eigen::MatrixXd A, D;
};

std::vector<EllAVertex> ell_A_vertices(const LinearSystem& sys);

/// Columns of [E; F] that are not identically zero (the others never reach the error, §0.2).
std::vector<Eigen::Index> ell_active_columns(const Eigen::MatrixXd& E, const Eigen::MatrixXd& F);

Eigen::MatrixXd ell_select_columns(const Eigen::MatrixXd& M, const std::vector<Eigen::Index>& cols);

/// Vertices of B^m; with `halve` only those whose last component is +1 (§0.2). m = 0: one
/// empty vertex.
std::vector<Eigen::VectorXd> ell_box_vertices(Eigen::Index m, bool halve);

/// The system data every ellipsoidal LMI uses: A vertices, active disturbance columns.
struct EllLmiData {
  std::vector<EllAVertex> vertices;
  Eigen::MatrixXd C, Et, Ft;  ///< Et, Ft: the active columns of E, F
  std::vector<Eigen::Index> active;
  bool interval = false;

  explicit EllLmiData(const LinearSystem& sys);
  Eigen::Index m() const { return Et.cols(); }
  /// ‖[Et; Ft]‖_F, the disturbance scale used to normalise solver problems (1 when m = 0).
  double disturbance_scale() const;
};

/// P (A_j − L C) and P (E − L F) with elementwise bounds on their rounding errors. The bound
/// 2 γ_k |P| (|A_j| + |L||C|) covers the two products and the subtraction, and also a
/// relative perturbation of A_j by u (A_j = fl(A_c ± rad) is not the exact vertex).
struct EllGainTerms {
  std::vector<Eigen::MatrixXd> PAL, PAL_err;
  Eigen::MatrixXd PEL, PEL_err;
  Eigen::VectorXd g_err;  ///< bound on the rounding of PEL ω for any ω ∈ {±1}^m

  EllGainTerms(const Eigen::MatrixXd& P, const Eigen::MatrixXd& L, const EllLmiData& d,
               const Eigen::MatrixXd& Et, const Eigen::MatrixXd& Ft);
};

/// Certifies [βP, 0, PALᵀ; 0, σ, gᵀ; PAL, g, P] ⪰ 0 in exact arithmetic, where PAL and g are
/// known up to PAL_err and g_err (elementwise). For σ > 0 the σ row and column are first scaled
/// by a power of two 2^e (a congruence, exact in floating point) that brings σ to the size of
/// P's diagonal, so that the test does not depend on the size of σ relative to P (the
/// certification slack is relative to the trace).
double ell_pow2_scale(double v, double target);

bool ell_certify_vertex_block(const Eigen::MatrixXd& P, double beta, double sigma,
                                     const Eigen::MatrixXd& PAL, const Eigen::MatrixXd& PAL_err,
                                     const Eigen::VectorXd& g, const Eigen::VectorXd& g_err);

/// Certifies the scaled LMI (§1.3, S = diag(s)) [βP, PALᵀ, 0; PAL, P, PEL; 0, PELᵀ, diag(s)] ⪰ 0
/// (rows and columns of the s_i > 0 scaled by powers of two, as above).
bool ell_certify_scaled_block(const Eigen::MatrixXd& P, double beta, const Eigen::MatrixXd& PAL,
                                     const Eigen::MatrixXd& PAL_err, const Eigen::MatrixXd& PEL,
                                     const Eigen::MatrixXd& PEL_err, const Eigen::VectorXd& s);

/// Every block of the design LMI (halved ω list, every A vertex, no centre term) at (β, σ).
bool ell_certify_design(const Eigen::MatrixXd& P, const EllGainTerms& t, const EllLmiData& d,
                               const std::vector<Eigen::VectorXd>& omegas, double beta, double sigma);

/// The centre term of the interval case, P (A_j − A_c) x̄ for every vertex, with error bounds.
struct EllCentreTerms {
  std::vector<Eigen::VectorXd> Ph, Ph_err;
  EllCentreTerms(const Eigen::MatrixXd& P, const EllLmiData& d, const Eigen::VectorXd& c);
};

/// Interval A: certifies every (A_j, ω) block with the centre term at (β, σ) (full ω list).
bool ell_certify_interval(const Eigen::MatrixXd& P, const EllGainTerms& t, const EllCentreTerms& ct,
                                 const std::vector<Eigen::VectorXd>& omegas, double beta, double sigma);

/// Interval A: the least σ the blocks (A_j, ω) with centre term need at fixed (β, L):
/// σ ≥ vᵀK⁻¹v, K = [βP, PALᵀ; PAL, P], v = [0; g], enlarged until every block is certified.
/// Returns +inf when some K is not positive definite or nothing certifies.
double ell_interval_sigma(const Eigen::MatrixXd& P, const EllGainTerms& t, const EllCentreTerms& ct,
                                 const std::vector<Eigen::VectorXd>& omegas, double beta);

double ell_lambda_min_lower(const Eigen::MatrixXd& P);

void ell_check_detectable(const LinearSystem& sys, const std::string& pair);

/// When every disturbance column reaching the state is also seen, unmixed, in the outputs
/// (the rows of E lie in the row space of F, so E = L F has a solution), a gain can cancel the
/// disturbance exactly: the estimation set can shrink towards a point, the minimum-volume design
/// has no minimiser and P degenerates. Returns a sentence explaining that, or "".
std::string ell_cancellable_hint(const Eigen::MatrixXd& E, const Eigen::MatrixXd& F);

/// Symmetrises d.P exactly and checks the gain's shape and the scalars of a design handed to an
/// estimator (messages name the field).
void ell_check_design_values(EllDesign& d, Eigen::Index ny);

const char* ell_normalization_name(EllNormalization n);

/// The offline design on `sys`; `name` is the design's name in messages, `pair` the name of
/// the detectability pair.
EllDesign ell_design_impl(const LinearSystem& sys, const EllDesignOptions& opt, const std::string& name,
                                 const std::string& pair);

}  // namespace detail

/// Offline design of papers.md §1.1 (module comment). Throws NotDetectableError for an
/// undetectable (C, A) (every vertex of an interval A), InfeasibleError when the LMI has no
/// solution for the β searched, InvalidArgumentError for bad options.
EllDesign design_ellipsoidal_offline(const LinearSystem& sys, const EllDesignOptions& opt = {});

// ---------------------------------------------------------------------------------------
// The predictor.

namespace detail {

/// The per-step LMI of OnlineVertex / OnlineScaled, built once with lmi::Model. In normalised
/// units: P̂ = P/p, disturbance columns /s, so that the solver sees quantities of order one;
/// σ̂ = σ/(p s²), ρ̂ = ρ/(p s²), Ŷ = P̂ L. Per step only the objective β ρ̂_k + σ̂_k (and, for an
/// interval A, the constants holding the centre term) change.
///
/// OnlineVertex solves it by an exact active-set scheme: only the vertex blocks of a working
/// set W are given to the solver; every other block is then checked at the solution (by the
/// certification that is done anyway) and W grows until none is violated. The relaxed optimum
/// being feasible for the full problem, it is its optimum. W for the next step is the set of
/// blocks that are nearly active at this step's solution (the active vertices hardly change
/// from step to step). One LmiProblem and solver is kept per working set met (analysed once).
struct EllOnlineProblem {
  lmi::Model model;
  lmi::Var beta, Y, sk, s;  // sk: σ̂_k (vertex); s: diag(ŝ) (scaled)
  double p = 1, sc = 1;     // P̂ = P/p, disturbance scale
  struct Block {
    Eigen::MatrixXd F0;     // constant (normalised units, margin included, no centre term)
    lmi::BlockTerms terms;
    bool vertex = false;    // an (A_j, ω) block of OnlineVertex (active-set candidate)
    std::size_t a_vertex = 0, omega = 0;
    bool centre = false;    // holds the interval centre term
  };
  std::vector<Block> blocks;
  std::vector<Eigen::Index> centre_rows;  // scaled interval: rows i of rad[A] that are non-zero
  struct Sub {
    std::vector<int> ids;  // blocks of the full problem, in order
    lmi::LmiProblem problem;
    std::unique_ptr<lmi::InteriorPointSolver> solver;
  };
  std::map<std::string, std::unique_ptr<Sub>> subs;
  std::string working;  // '1' for vertex blocks in W (non-vertex blocks are always in)
  lmi::SolverOptions options;  // of every sub-problem's solver

  Sub& sub(const std::string& key);
};

}  // namespace detail

class EllipsoidalPredictor {
 public:
  EllipsoidalPredictor(EllDesign design, const Ellipsoid& x0, EllPredictorMode mode)
      : d_(std::move(design)), mode_(mode), data_(d_.system), cur_(check_x0(d_, x0)), x0_(cur_), reset_set_(cur_) {
    init();
  }
  EllipsoidalPredictor(const EllipsoidalPredictor& o);
  EllipsoidalPredictor& operator=(const EllipsoidalPredictor& o);
  EllipsoidalPredictor(EllipsoidalPredictor&&) = default;
  EllipsoidalPredictor& operator=(EllipsoidalPredictor&&) = default;

  const EllDesign& design() const { return d_; }
  EllPredictorMode mode() const { return mode_; }
  /// The set for x_k, k = steps_taken() (x0 converted to shape P).
  const Ellipsoid& current() const { return cur_; }
  Eigen::Index steps_taken() const { return k_; }
  /// β used by the last step (the design β for Offline, and before the first step).
  double last_beta() const { return last_beta_; }
  /// L used by the last step (the design gain before the first step).
  const Eigen::MatrixXd& last_gain() const { return last_L_; }
  /// Online steps whose solve failed or whose result could not be certified, and that used
  /// the design's (β, L) instead.
  Eigen::Index fallback_steps() const { return fallbacks_; }
  /// Online steps that solved the per-step LMI (the others reused the last solution, see
  /// set_reuse_tolerance, or are Offline steps).
  Eigen::Index online_solves() const { return solves_; }

  /// Parametric reuse of the online solution (default 1e-9; 0 re-solves at every step). The
  /// per-step LMI does not depend on ρ_k (only its objective β ρ_k + σ does, for a point A):
  /// the last certified (β, L, σ) stays a valid step for any ρ, and since the optimal value
  /// V(ρ) = min βρ + σ is concave with supergradient β ∈ (0, 1) at the last solve's ρ̄, reusing
  /// it costs at most |ρ_k − ρ̄| over the optimum. So the LMI is solved again only when ρ_k has
  /// moved by more than `tol`·ρ̄ since the last solve; in steady state (ρ_k converges
  /// geometrically) the step is then a few matrix-vector products. Not used with an interval A
  /// (the constants of the LMI change with x̄_k). Part of the saved state: no (an option).
  void set_reuse_tolerance(double tol);
  double reuse_tolerance() const { return reuse_tol_; }

  /// Uses y_k, u_k; computes, stores and returns the set for x_{k+1}. A NaN entry of y is a
  /// missing output; a present output outside the predicted output set is handled by the
  /// inconsistency policy (last_check() reports both). Unchanged on error.
  Ellipsoid step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);

  /// The consistency test of the readings y (NaN = missing) against the set X of x_k (shape P):
  /// per output Used / Missing / Inconsistent and its margin (measurement_check.hpp). Does not
  /// look at the policy and changes nothing.
  MeasurementCheck screen(const Ellipsoid& X, const Eigen::Ref<const Eigen::VectorXd>& y,
                          const Eigen::Ref<const Eigen::VectorXd>& u) const;
  /// Policy Raise: throws the InconsistentMeasurementError of the first inconsistent output of
  /// `chk` (a screening of X); does nothing when chk is not flagged.
  void raise_if_inconsistent(const MeasurementCheck& chk, const Ellipsoid& X, const Eigen::Ref<const Eigen::VectorXd>& y,
                             const Eigen::Ref<const Eigen::VectorXd>& u) const;
  /// The step from the current set with the outputs that `chk` marks Used (no screening: the
  /// caller screened, e.g. ImprovedEstimator); records chk as last_check(). Unchanged on error.
  Ellipsoid advance(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u,
                    const MeasurementCheck& chk);

  /// What a reading outside the predicted output set does (measurement_check.hpp); default
  /// Flag. `reset_set` (policy Reset; default: x0) is converted to shape P. Not part of the
  /// saved state (an option).
  void set_inconsistency_policy(OnInconsistency policy);
  void set_inconsistency_policy(OnInconsistency policy, const Ellipsoid& reset_set);
  OnInconsistency inconsistency_policy() const { return policy_; }
  /// The set policy Reset restarts from (shape P).
  const Ellipsoid& reset_set() const { return reset_set_; }
  /// The screening of the last step (before the first step: every output Unused).
  const MeasurementCheck& last_check() const { return last_check_; }
  /// Back to the initial set and the state right after construction (counters, working set,
  /// reuse point); the options and the policy are kept.
  void reset();

  /// The full mutable state (core/state.hpp): the current set, the step counter, the last β
  /// and gain, the fallback counter, the online working set, the online solve counter and the
  /// reuse point (set_reuse_tolerance). Restored into a predictor
  /// built from the same design and mode, the next steps are bit-for-bit those of this one.
  std::vector<double> save_state() const;
  /// Restores a state from save_state(); throws InvalidArgumentError ("state: ...") when it is
  /// corrupted, of another estimator kind or of another design. Unchanged on error.
  void restore_state(const std::vector<double>& state);

  /// restore_state in two halves (for an estimator that holds a predictor): parse_state
  /// validates everything and changes nothing, apply_state only moves (cannot throw).
  struct ParsedState {
    Eigen::Index k = 0, fallbacks = 0;
    double beta = 0;
    Eigen::MatrixXd L;
    std::unique_ptr<Ellipsoid> cur;
    std::string working;
    Eigen::Index solves = 0;
    struct {
      double rho, beta, sigma;
      Eigen::MatrixXd L;
    } reuse{std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0, Eigen::MatrixXd()};
  };
  ParsedState parse_state(const std::vector<double>& state) const;
  void apply_state(ParsedState&& p);

  /// Hash of the design data a state depends on (mode, P, L, β, σ, system).
  StateFingerprint fingerprint() const;

  /// Options of the interior-point solver of the online steps (default: lmi::SolverOptions{}).
  /// A solve that does not end Optimal/Inaccurate (e.g. max_iterations too small) makes the
  /// step fall back to the design's certified (β, L, σ), counted by fallback_steps(). Not part
  /// of the saved state (like the design). No effect on an Offline predictor.
  void set_online_solver_options(const lmi::SolverOptions& options);

  /// Replace the current set (e.g. by a corrected one); converted to shape P with with_shape.
  void reset(const Ellipsoid& x);

  /// Upper bounds q_i ≥ C_i P⁻¹ C_iᵀ (certified; +inf when certification failed: that output
  /// is then never declared inconsistent).
  const Eigen::VectorXd& output_spread() const { return q_; }

 private:
  enum class OnlineOutcome { Used, NotBetter, Failed };
  struct Choice {
    double beta;
    Eigen::MatrixXd L;
    double sigma;     // certified: ρ⁺ = βρ + σ
    double rho_next;  // that level, rounded up (before the centre rounding)
  };

  static Ellipsoid check_x0(const EllDesign& d, const Ellipsoid& x0);

  void init();

  /// The design's step: (β, L, σ) of the design; with an interval A the design's L with the σ_k
  /// that the centre term needs, at the design's β or a larger one (K(β) = [βP, A_Lᵀ P; P A_L, P]
  /// grows with β, and the optimal design leaves K(β_d) nearly singular), whichever certified
  /// level is smallest.
  Choice design_choice(double rho, const Eigen::VectorXd& c) const;

  void build_online();

  /// A partial step (some outputs not used, `use`): the better of the design's gain restricted
  /// to the outputs used and no correction, with (β, σ) certified for that gain (file comment).
  Choice partial_choice(double rho, const Eigen::VectorXd& c, const std::vector<bool>& use) const;

  /// The predicted interval of output i from X: centre C_i c, radius √(ρ q_i) (before D u, φ).
  void output_interval(const Ellipsoid& X, Eigen::Index i, double& center, double& radius, double& magnitude) const;

  /// Solves the online problem at (ρ_k, x̄_k); on success writes the certified choice into `ch`
  /// (OnlineVertex: only when its level is below the design's, which is feasible for the same
  /// problem, so a larger level only means an inaccurate solve).
  OnlineOutcome online_choice(double rho, const Eigen::VectorXd& c, Choice& ch);

  EllDesign d_;
  EllPredictorMode mode_;
  detail::EllLmiData data_;
  Ellipsoid cur_;
  Eigen::Index k_ = 0;
  double last_beta_ = 0;
  Eigen::MatrixXd last_L_;
  Eigen::Index fallbacks_ = 0;
  struct Reuse {
    double rho = std::numeric_limits<double>::quiet_NaN();  // ρ of the last certified solve (NaN: none)
    double beta = 0, sigma = 0;
    Eigen::MatrixXd L;
  } reuse_;
  double reuse_tol_ = 1e-9;
  Eigen::Index solves_ = 0;
  double lmax_up_ = 0;
  std::vector<Eigen::VectorXd> halved_, full_;
  std::unique_ptr<detail::EllGainTerms> design_terms_;
  std::unique_ptr<detail::EllOnlineProblem> on_;
  // Real measurement data: certified C_i P⁻¹ C_iᵀ bounds, noise bounds φ_i, the initial set
  // (reset()), the policy and its reset set, the last step's screening.
  Eigen::VectorXd q_, phi_;
  Ellipsoid x0_, reset_set_;
  OnInconsistency policy_ = OnInconsistency::Flag;
  MeasurementCheck last_check_;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/ellipsoidal/impl/lmi_estimators.ipp"
#endif
