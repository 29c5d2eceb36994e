// setbound — thesis Chapter 4: interval observers with an explicit error enclosure
// (thesis.md §6; Loukkas 2018, §4.2–4.6). Method reference: docs/thesis_interval.md.
//
//   interval_error_recursion      §6.2: the error boxes of e⁺ = A_o e + E w, three variants
//                                 (Tight = exact interval hull, Wrapped = the thesis's formula
//                                 with [g_0] = E[w] boxed first, Naive = (4.15)).
//   interval_error_limit          the limit box [g] = Σ_{i≥0} A_o^i[g_0] (4.19–4.23).
//   IntervalLuenbergerObserver    §6.2 online: x̂ (4.9) plus the error box (4.10–4.12).
//   NonlinearIntervalObserver     §6.6: x⁺ = A x + h(p, x, k) + B u with a per-step inclusion
//                                 box of h (a functor), E = [I, −LZ].
//   offline_error_sequence +      §6.3: the precomputed sequence [s_0..s_k*] with the
//   IntervalInvariantObserver     invariant-set tail (polyhedral RPI set Φ_0 of §3.5).
//
// Guarantee in floating point. The boxes enclose the errors of the EXACT real system
// (x⁺ = A x + B u + F d, y = C x + Z v with the given matrices, and the exact gain L) with
// respect to the observer state x̂ the code actually stores. Every rounding is accounted for:
//  * the radii |M|r and their sums are rounded upwards (directed rounding of interval.hpp);
//  * the powers M_i ≈ A_o^i, N_i ≈ A_o^i E are computed in floating point; their deviation
//    from the exact powers, the deviation of fl(A − LC) and fl(−LZ) from the exact matrices,
//    the rounding of the centre recursion and of the observer update x̂⁺ are all collected in
//    scalar bounds in the norm ‖x‖_P = √(xᵀPx) of a certified Lyapunov matrix P of A_o
//    (‖A_o x‖_P ≤ β‖x‖_P, β < 1 certified by a Cholesky factorisation with margin), so they
//    contract instead of piling up; the final bound |x_j| ≤ ‖x‖_P/√λ_min(P) turns them into a
//    componentwise radius. These scalars are rounding-level (~1e-15 relative) quantities
//    bounded with generous safety factors (γ_k with factor 2, round_up) rather than by
//    directed rounding.
//  * Powers are computed until they are negligible (index K, ‖A_o^K‖ ≤ 1e-12 or the cap
//    kMaxPowers); for k ≥ K the remaining terms are bounded by the geometric P-norm bound
//    Σ_{i≥K} β^{i−K}(…) (a certified outer bound), so the box is constant for k ≥ K. Before
//    K the tight variant is the exact hull up to these rounding-level terms.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/state.hpp"
#include "setbound/core/symmetric.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/box.hpp"
#include "setbound/sets/interval.hpp"
#include "setbound/sets/polytope.hpp"
#include "setbound/thesis/hinf_gain.hpp"
#include "setbound/thesis/reading_screen.hpp"
#include "setbound/thesis/invariant.hpp"
#include "setbound/thesis/plant.hpp"

namespace setbound::thesis {

/// Which error-box recursion (thesis.md §6.2).
///  Tight   — [e_k] = A_o^k[e_0] + Σ_{i<k} (A_o^i E)[w]: the exact interval hull (attained).
///  Wrapped — the thesis's (4.10–4.11): [g_0] = E[w] boxed first, then Σ A_o^i[g_0]; ⊇ Tight.
///  Naive   — (4.15): [e_{k+1}] = A_o[e_k] + [g_0], re-boxing every step (wrapping effect).
enum class ErrorRecursion { Tight = 0, Wrapped = 1, Naive = 2 };

namespace iobs_detail {

inline constexpr double kEps = std::numeric_limits<double>::epsilon();
inline constexpr int kMaxPowers = 20000;        // cap of the stored power table
inline constexpr double kNegligible = 1e-12;    // ‖A_o^K‖_max (and ‖A_o^K E‖ relative) at freeze

/// γ_k = k u/(1 − k u), u = eps/2, with a safety factor 2 (Higham's bound of a k-term dot product).
double gam(Eigen::Index k);
/// x(1 + 4 eps) + tiny: an upper bound of a non-negative quantity computed with a few roundings.
double up(double x);

std::string num(double v);

double spectral_radius(const Eigen::MatrixXd& M);

/// A certified contraction of the exact A_o = A_fl + Θ (|Θ| ≤ theta entrywise) in the norm
/// ‖x‖_P: ‖A_o x‖_P ≤ beta ‖x‖_P with beta < 1.
struct Contraction {
  Eigen::MatrixXd P;
  double beta = 1;
  double sqrt_lmax = 1;  // ≥ √λ_max(P)
  double inv_sqrt_lmin = 1;  // ≥ 1/√λ_min(P): |x_j| ≤ inv_sqrt_lmin ‖x‖_P
  double sqrt_kappa = 1;  // ≥ √(λ_max/λ_min)
};

Contraction certify_contraction(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& theta,
                                       const std::string& name);

/// ‖M e_l‖_P for each column l, rounded up.
Eigen::VectorXd column_P_norms(const Eigen::MatrixXd& M, const Contraction& c);

/// |M| r rounded upwards (r ≥ 0), written into out (no allocation).
void abs_mul_up(const Eigen::MatrixXd& M, const double* r, double* out);

/// Rounding-certified powers of the error system e⁺ = A_o e + E w (A_o, E exact up to the
/// entrywise bounds theta, e_err of their floating-point versions).
struct ErrorPowers {
  Eigen::MatrixXd Ao, E, Ao_abs_up;  // Ao_abs_up ≥ |A_o exact| entrywise
  Eigen::MatrixXd theta, e_err;
  Contraction ctr;
  std::vector<Eigen::MatrixXd> M, N;  // M_i ≈ A_o^i, N_i ≈ A_o^i E, i = 0..K
  std::vector<double> d, q;           // ‖A_o^i − M_i‖_{P→P} ≤ d_i, ‖A_o^iE − N_i‖_{2→P} ≤ q_i
  int K = 0;
};

ErrorPowers build_powers(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& theta, const Eigen::MatrixXd& E,
                                const Eigen::MatrixXd& e_err, int min_steps, const std::string& name);

/// The error boxes of A_o^k[e_0] + Σ_{i<k} (tight: (A_o^iE)[Δw]; wrapped: A_o^i(E[Δw])) for a
/// centred disturbance box ±rw, k = 0..K, and the constant box valid for every k > K (the
/// last entry). Entry k covers every k' ≥ k when k = lo.size() − 1.
struct ErrorBoxTable {
  std::vector<Eigen::VectorXd> lo, hi;
  const Eigen::VectorXd& lo_at(long k) const;
  const Eigen::VectorXd& hi_at(long k) const;
};

ErrorBoxTable error_box_table(const ErrorPowers& p, const Eigen::VectorXd& c0, const Eigen::VectorXd& r0,
                                     const Eigen::VectorXd& rw, ErrorRecursion variant);

/// Rounding bound of the centre recursion c⁺ = A_fl c + Ecw (Ecw = fl(E_fl c_w)), measured
/// against the exact c⁺ = A_o c + E c_w: |·| ≤ γ(|A_fl||c| + |Ecw|) + Θ|c| + ecw_err.
double center_step_perturbation_P(const ErrorPowers& p, const Eigen::VectorXd& c, const Eigen::VectorXd& Ecw,
                                         const Eigen::VectorXd& ecw_err, Eigen::VectorXd& work);

/// Entrywise bounds of fl(A − fl(L C)) − (A − LC) and fl(−L Z) − (−LZ).
Eigen::MatrixXd ao_error_bound(const Eigen::MatrixXd& A, const Eigen::MatrixXd& L, const Eigen::MatrixXd& C);
Eigen::MatrixXd lz_error_bound(const Eigen::MatrixXd& L, const Eigen::MatrixXd& Z);

void require_box(const Box& b, Eigen::Index n, const std::string& name);

void require_vec(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Index n, const char* name);

/// Centre and (rounded-up) radius of a box.
void mid_rad(const Box& b, Eigen::VectorXd& c, Eigen::VectorXd& r);

/// Stacked box [d] × [v].
Box stack_boxes(const Box& a, const Box& b);

/// The Luenberger update x̂⁺ = A x̂ + B u + L (y − C x̂) + a, written into xn, with a bound on
/// the rounding error (componentwise magnitude, then its 2-norm is returned). No allocation:
/// `innov` (ny) and `work` (n) are scratch.
double luenberger_update(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                                const Eigen::MatrixXd& L, const Eigen::VectorXd& x, const double* u, const double* y,
                                const double* a, double a_err, Eigen::VectorXd& xn, Eigen::VectorXd& innov,
                                Eigen::VectorXd& innov_mag, Eigen::VectorXd& work);

}  // namespace iobs_detail

// ---------------------------------------------------------------------------------------------
// interval_error_recursion and its limit (§6.2)
// ---------------------------------------------------------------------------------------------

/// The error boxes [e_0], …, [e_steps] of e_{k+1} = A_o e_k + E w_k for every e_0 ∈ e0 and
/// w_k ∈ w (A_o n×n Schur, E n×m, taken as exact real matrices). Tight: the exact interval
/// hull A_o^k[e_0] + Σ_{i<k}(A_o^iE)[w] (attained by a sign-pattern trajectory); Wrapped: the
/// thesis formula (4.10–4.11) with [g_0] = E[w]; Naive: (4.15). Guaranteed in floating point
/// (file comment). Throws naming Ao, E, e0, w, steps.
std::vector<Box> interval_error_recursion(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& E, const Box& e0,
                                                 const Box& w, int steps,
                                                 ErrorRecursion variant = ErrorRecursion::Tight);

/// The limit box [g] = lim [e_k] = Σ_{i≥0} A_o^i E[w] (tight) or Σ A_o^i(E[w]) (wrapped):
/// an outer bound that is tight up to the truncation tail (‖A_o^K‖ ≤ 1e-12) and rounding.
Box interval_error_limit(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& E, const Box& w,
                                ErrorRecursion variant = ErrorRecursion::Tight);

namespace iobs_detail {

/// What the three interval observers share for real data (reading_screen.hpp): the reading
/// policy and the last screening, the step counter, and the restart of the error bound after a
/// step without some output (from the predicted box [rlo_, rhi_] at step k0_).
class BoxObserverReadings {
 public:
  /// Policy for impossible readings; `reset_box` (size 0: keep; default the initial box) is
  /// where policy Reset restarts.
  void set_inconsistency_policy(OnInconsistency policy, const Box& reset_box = Box()) {
    screen_.set_policy(policy, reset_box, rlo_.size());
  }
  OnInconsistency inconsistency_policy() const { return screen_.policy; }
  /// The screening of the last step (every output Used before the first).
  const MeasurementCheck& last_check() const { return screen_.check; }
  /// Steps since the last restart (a step without some output restarts the error bound).
  long steps_since_restart() const { return k_ - k0_; }

 protected:
  ReadingScreen screen_;
  Box dbox_, vbox_;
  bool restarted_ = false;
  long k_ = 0, k0_ = 0;
  Eigen::VectorXd rlo_, rhi_;  // the initial box, then the box of the last restart
};

}  // namespace iobs_detail

// ---------------------------------------------------------------------------------------------
// IntervalLuenbergerObserver (§6.2)
// ---------------------------------------------------------------------------------------------

namespace iobs_detail {
void fingerprint_plant_table(StateFingerprint& f, const Plant& p, const Eigen::MatrixXd& L, const ErrorBoxTable& t);
}  // namespace iobs_detail

struct IntervalObserverOptions {
  ErrorRecursion variant = ErrorRecursion::Tight;  // Tight (default) or Wrapped (the thesis's numbers)
};

/// x̂_{k+1} = A x̂_k + B u_k + L (y_k − C x̂_k) (4.9) and [x_k] = x̂_k + [e_k] (4.12), with
/// [e_k] from the tight (or wrapped) recursion; a one-step predictor: current() before any
/// step is [x_0], step(y_k, u_k) returns the box of x_{k+1}. The radii |A_o^k|r_0 + Σ|A_o^iE|r_w
/// are tabulated at construction (up to the freeze index K, then constant); the centre of the
/// disturbance part and the rounding residue are updated per step: O(n² + n n_y + n n_u) per
/// step, no allocation.
class IntervalLuenbergerObserver : public iobs_detail::BoxObserverReadings {
 public:
  IntervalLuenbergerObserver(const Plant& plant, const Eigen::MatrixXd& L, const Box& x0,
                             const Eigen::VectorXd& xhat0, const Box& d, const Box& v,
                             const IntervalObserverOptions& opt = {});

  Eigen::Index nx() const { return plant_.nx(); }
  Eigen::Index ny() const { return plant_.ny(); }
  Eigen::Index nu() const { return plant_.nu(); }
  long steps() const { return k_; }
  const Eigen::MatrixXd& gain() const { return L_; }
  const Eigen::MatrixXd& Ao() const { return Ao_; }
  const Eigen::MatrixXd& E() const { return E_; }
  /// Certified contraction factor of A_o in its Lyapunov norm (used for the rounding residue).
  double contraction() const { return powers_.ctr.beta; }
  /// Index from which the error box is constant (the power table's freeze index K + 1).
  int freeze_index() const { return powers_.K + 1; }
  ErrorRecursion variant() const { return variant_; }
  const Eigen::VectorXd& xhat() const { return xhat_; }
  const Eigen::VectorXd& lower() const { return lo_; }
  const Eigen::VectorXd& upper() const { return hi_; }
  Box current() const { return Box(lo_, hi_, "current"); }

  /// Uses y_k and u_k (u ignored when n_u = 0); afterwards lower()/upper() bound x_{k+1}.
  /// NaN entries of y are missing outputs, readings outside C_i[x_k] + Z_i[v] are impossible
  /// (policy below); a step without some output is made in interval arithmetic and restarts the
  /// error table from the predicted box (reading_screen.hpp). Throws (naming y or u) on wrong
  /// sizes or ±inf; the observer is then unchanged.
  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);


  /// Full mutable state (core/state.hpp): x̂_k, the centre of the disturbance part, the
  /// rounding residue ξ_k and k (the box follows from them and the tabulated radii), and the
  /// box and step of the last restart.
  std::vector<double> save_state() const;
  /// Restores a state from save_state() into an observer made with the same plant, gain,
  /// boxes and variant; throws InvalidArgumentError ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

 private:
  void update_bounds();

  Plant plant_;
  Eigen::MatrixXd L_, Ao_, E_;
  ErrorRecursion variant_ = ErrorRecursion::Tight;
  iobs_detail::ErrorPowers powers_;
  iobs_detail::ErrorBoxTable table_;
  Eigen::VectorXd Ecw_, ecw_err_;
  bool has_cw_ = false;
  Eigen::VectorXd xhat_, cc_, xn_, cn_, work_, innov_, innov_mag_, lo_, hi_;
  double xi_ = 0;
  Eigen::VectorXd rw_;  // radii of the disturbance box w = (d, v)
  iobs_detail::ErrorBoxTable rtable_;  // the table of the last restart
  /// Restarts from the box X of x_k at step k (allocates: the table of X's radius).
  void restart(const Box& X, long k);
};

// ---------------------------------------------------------------------------------------------
// NonlinearIntervalObserver (§6.6)
// ---------------------------------------------------------------------------------------------

/// Inclusion function of the unknown nonlinearity: given the current state box [x_k] and k,
/// returns a box [h]_k ∋ h(p, x_k, k) for every p ∈ [p] and x_k ∈ [x_k] (the thesis's constant
/// box [h] is the simplest such functor).
using NonlinearityBox = std::function<Box(const Box& x_box, long k)>;

struct NonlinearObserverOptions {
  int window = 256;  // at most this many past [h] radii are convolved exactly (then a certified tail)
};

/// x⁺ = A x + h(p, x, k) + B u, y = C x + Z v (4.40); the plant's F must be I_n (the error
/// input is E = [I, −LZ], thesis.md §6.6). Observer x̂⁺ = A x̂ + ĥ_k + B u + L(y − C x̂) with
/// ĥ_k = mid([h]_k). Error box, kept exact when [h]_k varies per step:
///   [e_k] = A_o^k[e_0] + Σ_{i<k} A_o^i([h]_{k−1−i} − ĥ_{k−1−i}) + Σ_{i<k} (A_o^i(−LZ))[v]
/// — the v part is tabulated (constant box), the h part is the convolution of the stored past
/// radii r_h,j with the stored powers |A_o^i| over a window of W = min(K, window) steps; the
/// older terms (i ≥ W) are bounded by the geometric P-norm tail with the componentwise maximum
/// of the radii that left the window. Per step O(W n²).
class NonlinearIntervalObserver : public iobs_detail::BoxObserverReadings {
 public:
  NonlinearIntervalObserver(const Plant& plant, const Eigen::MatrixXd& L, const Box& x0, const Eigen::VectorXd& xhat0,
                            const Box& v, NonlinearityBox h = {}, const NonlinearObserverOptions& opt = {});

  Eigen::Index nx() const { return plant_.nx(); }
  Eigen::Index ny() const { return plant_.ny(); }
  Eigen::Index nu() const { return plant_.nu(); }
  long steps() const { return k_; }
  int window() const { return W_; }
  const Eigen::MatrixXd& gain() const { return L_; }
  const Eigen::VectorXd& xhat() const { return xhat_; }
  const Eigen::VectorXd& lower() const { return lo_; }
  const Eigen::VectorXd& upper() const { return hi_; }
  Box current() const { return Box(lo_, hi_, "current"); }

  /// Step with the functor given at construction ([h]_k = h([x_k], k)).
  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);

  /// Step with an explicit inclusion box [h]_k of h(p, x_k, k) (must hold for every x_k ∈ [x_k]).
  /// Missing and impossible readings as IntervalLuenbergerObserver::step (the fallback adds [h]_k).
  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u, const Box& hbox);


  /// Full mutable state (core/state.hpp): x̂_k, the centre of the v part, ξ_k, k and the
  /// error-sequence window (the last W radii of [h], the maxima of the radii that left it).
  std::vector<double> save_state() const;
  /// Restores a state from save_state() into an observer made with the same plant, gain, boxes
  /// and window; throws InvalidArgumentError ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

 private:
  void update_bounds();

  Plant plant_;
  Eigen::MatrixXd L_, Ao_;
  NonlinearityBox h_;
  iobs_detail::ErrorPowers powers_;
  iobs_detail::ErrorBoxTable table_;
  Eigen::VectorXd Ecw_, ecw_err_;
  bool has_cw_ = false;
  int W_ = 1;
  Eigen::VectorXd mW_;
  double Dw_ = 0;
  Eigen::MatrixXd ring_;
  Eigen::VectorXd Rmax_;
  double rmax_norm_ = 0, rmax_norm_out_ = 0;
  Eigen::VectorXd xhat_, cc_, xn_, cn_, work_, hc_, hr_, conv_, tmp_, innov_, innov_mag_, lo_, hi_;
  double xi_ = 0;
  Eigen::VectorXd rv_;  // radii of the output noise box
  iobs_detail::ErrorBoxTable rtable_;
  /// Restarts from the box X of x_k at step k: the table of X's radius, an empty window.
  void restart(const Box& X, long k);
};


// ---------------------------------------------------------------------------------------------
// Observers with the H∞ gain (Prop 4.2, LMI 4.13 = 2.22 with Q = I; Prop 4.6, LMI 4.46)
// ---------------------------------------------------------------------------------------------

/// IntervalLuenbergerObserver with L from hinf_observer_gain(plant) (Q = I, LMI 4.13). The
/// design (γ, P, L) is written to *gain_out when given.
IntervalLuenbergerObserver design_interval_luenberger(const Plant& plant, const Box& x0,
                                                             const Eigen::VectorXd& xhat0, const Box& d, const Box& v,
                                                             const IntervalObserverOptions& opt = {},
                                                             const HinfOptions& hopt = {}, HinfGain* gain_out = nullptr);

/// NonlinearIntervalObserver with L from LMI (4.46) (= 2.22 with F = I; the plant's F must be I).
NonlinearIntervalObserver design_nonlinear_interval_observer(const Plant& plant, const Box& x0,
                                                                    const Eigen::VectorXd& xhat0, const Box& v,
                                                                    NonlinearityBox h = {},
                                                                    const NonlinearObserverOptions& opt = {},
                                                                    const HinfOptions& hopt = {},
                                                                    HinfGain* gain_out = nullptr);

// ---------------------------------------------------------------------------------------------
// offline_error_sequence + IntervalInvariantObserver (§6.3)
// ---------------------------------------------------------------------------------------------

struct InvariantObserverOptions {
  double mu = 2.0;          // μ > 1 of Ψ̄(μ), Ψ̄⁺(μ) (1.57–1.58); the thesis uses 2
  double inflation = 0.0;   // λ ≥ 1 with [e_0] ⊆ λΦ_0 (4.31); 0 = the smallest such λ
  double epsilon = 0.01;    // ε, a RADIUS: k* is the first k with λβ^k·√(c_out/λ_min(P)) ≤ ε
  ErrorRecursion variant = ErrorRecursion::Tight;  // interval part; Wrapped reproduces Table 4.1 rows 1–2
  PolyhedralRpiOptions polytope{};
};

/// Everything the offline design of §6.3 computes.
struct InvariantObserverDesign {
  explicit InvariantObserverDesign(Plant p) : plant(std::move(p)) {}

  Plant plant;
  Eigen::MatrixXd L, P, E;     // gain, H∞ Lyapunov matrix (4.13), E = [F, −LZ]
  double gamma = 0, beta = 0;  // γ of (4.13); β = smallest with A_oᵀPA_o ⪯ β²P (certified, rounded up)
  double mu = 2, inflation = 1, inflation_min = 1, epsilon = 0.01;
  double c_in = 0, c_out = 0;  // levels of Ψ̄⁺(μ) and Ψ̄(μ) (Δw radius, w̄ᵀw̄ = Σ rad(w_i)²)
  double wbar_sq = 0;
  int k_star = 0;
  Polytope phi0;                           // Φ_0 (not inflated)
  Eigen::VectorXd w_center, w_radius;      // centred disturbance w = w_c + Δw
  Box x0;
  Eigen::VectorXd xhat0;
  std::vector<Box> sequence;               // error boxes [s_0] … [s_k*]; [s_k] = [s_k*] for k ≥ k*
  std::vector<double> shrinking_index;     // ρ(k) = β^k √(μ λ_max(P)/λ_min(P)), k = 0..k*
  ErrorRecursion variant = ErrorRecursion::Tight;
  // rounding allowance of the online point observer (certified Lyapunov contraction of A_o)
  double rounding_beta = 0, rounding_sqrt_lmax = 0, rounding_inv_sqrt_lmin = 0;
  Eigen::VectorXd Ecw;                     // fl(E w_c) added to x̂ (4.34)
  double Ecw_err = 0;                      // ‖E w_c − fl(E w_c)‖₂ bound

  /// The box [s_k] (k ≥ 0; constant for k ≥ k*).
  const Box& box_at(long k) const;
};

namespace iobs_detail {

/// β = √λ_max(A_oᵀPA_o, P) rounded up and certified: β²P − A_oᵀPA_o ⪰ 0 (Cholesky with slack).
double certified_rate(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& P, const std::string& name);

/// The rounding bound of L Z as a block of E's (n × m, zero on the d columns).
Eigen::MatrixXd sequence_e_err(const InvariantObserverDesign& D);

/// The part of the §6.3 design that depends on the initial box: inflation (inflation_opt, 0 =
/// the smallest), k*, ρ(k) and the error boxes [s_0] … [s_k*] for [e_0] = [x0] − x̂0. Used by
/// the design and by the observer's restart after a step without some output.
void fill_error_sequence(InvariantObserverDesign& D, const Box& x0, const Eigen::VectorXd& xhat0, double inflation_opt);

}  // namespace iobs_detail

/// §6.3 offline design for a given H∞ design (L, P, γ satisfying the dissipation LMI (4.13),
/// certified here: a HinfGain from hinf_observer_gain, or user values that pass the check).
/// [e_0] = [x_0] − x̂_0; the disturbance is centred (w = w_c + Δw) and x̂ gets E w_c (4.34).
InvariantObserverDesign offline_error_sequence(const Plant& plant, const HinfGain& gain, const Box& x0,
                                                      const Eigen::VectorXd& xhat0, const Box& d, const Box& v,
                                                      const InvariantObserverOptions& opt = {});

/// §6.3 with the H∞ gain of LMI (4.13) designed here.
InvariantObserverDesign offline_error_sequence(const Plant& plant, const Box& x0, const Eigen::VectorXd& xhat0,
                                                      const Box& d, const Box& v,
                                                      const InvariantObserverOptions& opt = {},
                                                      const HinfOptions& hopt = {});

/// Online part of §6.3: x̂⁺ = A x̂ + B u + L(y − C x̂) + E w_c (4.34) and the table look-up
/// [x_k] = x̂_k + [s_min(k,k*)], widened by the certified rounding allowance of x̂. One-step
/// predictor (current() before any step is x̂_0 + [s_0] = [x_0] up to rounding). O(n² + n n_y
/// + n n_u) per step, no allocation.
class IntervalInvariantObserver : public iobs_detail::BoxObserverReadings {
 public:
  explicit IntervalInvariantObserver(InvariantObserverDesign design);

  const InvariantObserverDesign& design() const { return D_; }
  Eigen::Index nx() const { return D_.plant.nx(); }
  Eigen::Index ny() const { return D_.plant.ny(); }
  Eigen::Index nu() const { return D_.plant.nu(); }
  long steps() const { return k_; }
  const Eigen::VectorXd& xhat() const { return xhat_; }
  const Eigen::VectorXd& lower() const { return lo_; }
  const Eigen::VectorXd& upper() const { return hi_; }
  Box current() const { return Box(lo_, hi_, "current"); }

  /// Missing and impossible readings as IntervalLuenbergerObserver::step; the restart refills
  /// the error sequence for the predicted box (iobs_detail::fill_error_sequence, smallest
  /// inflation); design() keeps the construction's.
  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);


  /// Full mutable state (core/state.hpp): x̂_k, the rounding residue ξ_k, k and the box and
  /// step of the last restart.
  std::vector<double> save_state() const;
  /// Restores a state from save_state() (same design); throws InvalidArgumentError
  /// ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

 private:
  void update_bounds();

  InvariantObserverDesign D_;
  Eigen::VectorXd xhat_, xn_, work_, innov_, innov_mag_, lo_, hi_;
  double xi_ = 0;
  std::vector<Box> rseq_;  // the error sequence of the last restart ([s_k] for k − k0 ≥ k*: the last)
  const Box& active_box() const;
  /// Restarts from the box X of x_k at step k (allocates: a new error sequence).
  void restart(const Box& X, long k);
};

}  // namespace setbound::thesis

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/thesis/impl/interval_observer.ipp"
#endif
