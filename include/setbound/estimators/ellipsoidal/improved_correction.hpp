// setbound — the measurement-based ("improved") ellipsoidal correction of [Merhy2017] eq. (4),
// as reconstructed in papers.md §6.
//
// Given the predicted set x ∈ E(P, c, ρ) and the measurement y = C x + D u + F ω, ω ∈ B^{n_ω},
// the consistent set is
//
//     S = { x ∈ E(P, c, ρ) : ỹ − C x ∈ F B^{n_ω} },      ỹ = y − D u   (§6.2, §8 item 4).
//
// An ellipsoid E(P', c', ρ') ⊇ S is certified by multipliers τ ≥ 0 (prior ellipsoid), H = Hᵀ
// and μ ≥ 0 (the measurement, condition (C1): Fᵀ H F ⪯ diag μ) through the LMI (L) of §6.3.
//
// How it is solved here (changes of variables of (L)+(C1); the certificate that is checked at
// the end is (L) itself):
//
//  * Centred coordinates. x = c + ξ, c' = c + d. (L) is written with the innovation
//    e₀ = ỹ − C c in place of ỹ and with w = P' d in place of z = P' c': the (2,2) block becomes
//    ρ' − τρ − Σμ + e₀ᵀ H e₀, without the terms τ cᵀP c and ỹᵀH ỹ that cancel catastrophically
//    when the set is far from the origin.
//  * Normalised coordinates. With P = Rᵀ R (Cholesky) and η = R ξ / √ρ the prior becomes the
//    unit ball, and each output row i is scaled by s_i (1 / Σ_j |F_ij|, or 1 / ‖row i of C̃‖₁
//    for a noise-free output). The solver sees C̃ = S √ρ C R⁻¹, ẽ = S e₀, F̃ = S F, prior
//    (I, 0, 1). Back: P' = Rᵀ P̃' R, d = √ρ R⁻¹ d̃, ρ' = ρ ρ̃', H = ρ S H̃ S, μ = ρ μ̃, τ
//    unchanged. Columns of F that are zero are dropped (their μ_i is 0).
//  * Reduced LMI (P̃' and w eliminated). With Q = τI + C̃ᵀH̃C̃, q = C̃ᵀH̃ẽ and
//    s' = ẽᵀH̃ẽ − τ − Σμ̃, (L) says [[Ω, Γᵀ], [Γ, P̃']] ⪰ 0 with Ω = [[Q, −q], [−qᵀ, ρ̃' + s']]
//    and Γ = [P̃', −w]. Its Schur complement is Ω − Γᵀ P̃'⁻¹ Γ = [[Q − P̃', w − q], [·, ρ̃' + s' −
//    wᵀP̃'⁻¹w]] ⪰ 0, so every feasible point has Q ⪰ P̃' and (adding the PSD matrix Γᵀ P̃'⁻¹ Γ)
//    K = [[Q, q], [qᵀ, ρ̃' + s']] ⪰ 0. Conversely, if K ⪰ 0 and Q ⪰ P̃' ≻ 0, then d̃ = Q⁻¹q,
//    w = P̃' d̃ satisfy (L): the Schur complement above is then ⪰ 0, its minimum over [η; 1] being
//    ρ̃' + s' − qᵀQ⁻¹q. So the shape P̃' only enters through Q ⪰ P̃', and the three modes are
//      FixedShape      P̃' = I:       min ρ̃'  s.t.  K ⪰ 0, Q ⪰ I, (C1), μ ≥ 0, τ ≥ 0, ρ̃' ≥ 0;
//      BallNormalized  P̃' ⪰ G:       min ρ̃'  s.t.  K ⪰ 0, Q ⪰ G, (C1), …          (P̃' = Q);
//      DetNormalized   ρ̃' = 1:       max log det Q  s.t.  K ⪰ 0, (C1), …           (P̃' = Q);
//    an (n+1)-block instead of (2n+1) and n(n+1)/2 + n fewer variables (about 3× faster for
//    n_x = 3, n_y = 2), with the same optimum as (L). The certificate takes P̃' a hair inside Q,
//    (1 − θ) Q with θ = 10·margin, because P̃' = Q makes (L) singular; FixedShape certifies
//    P̃' = (1 − θ) I (Q ⪰ I is imposed without margin: a margin would cut off τ = 1, the optimum
//    whenever rank C < n_x) and returns that set written with P (Ellipsoid::with_shape), its
//    multipliers divided by 1 − θ. So BallNormalized's P' ⪰ (1 − θ) λ_min(P) I.
//
// Normalisation (§6.5; (L)+(C1) are jointly homogeneous in (P', z, H, τ, μ, ρ') so one is
// required):
//  * DetNormalized (default, option B): min ρ' s.t. log det P' ≥ log det P. By homogeneity this
//    is solved as ρ̃' = 1 fixed, maximise log det P̃' (maxdet), then every variable is multiplied
//    by t = det(P̃')^(−1/n) so that det P' = det P up to rounding; ρ' = t ρ is then directly
//    comparable to ρ (vol'/vol = (ρ'/ρ)^(n/2)). This is the minimum-volume ellipsoid of the
//    certificate family.
//  * BallNormalized (option C): min ρ' s.t. P' ⪰ λ_min(P) I, i.e. P̃' ⪰ G = λ_min(P) R⁻ᵀR⁻¹.
//    The papers' P' ⪰ I depends on the scale of P (and (P, ρ) ~ (tP, tρ)); λ_min(P) I is the
//    largest multiple of I below P, so the prediction itself is feasible, the result is
//    invariant under (P, ρ) → (tP, tρ), and the circumscribed-ball radius √(ρ'/λ_min(P)) never
//    exceeds that of the prediction. ρ' does not fix P' (any G ⪯ P̃' ⪯ Q works); the largest,
//    P̃' ≈ Q, is returned (the smallest volume among the optimal ellipsoids).
//  * FixedShape (option A): P' = P, min ρ'.
//
// Side constraints: τ ≥ 0 and μ ≥ 0 always; ρ' ≥ 0 in the modes that minimise ρ' (implied
// whenever S is non-empty; it keeps the problem bounded otherwise). Optional (off by default,
// §6.4: not needed for validity and slack in the spec's checks): ρ' ≥ τρ (non-strict; in the
// DetNormalized solve, where ρ̃' = 1, it reads τ ≤ 1 and survives the rescaling because it is
// homogeneous) and τ ≤ 1 (FixedShape and BallNormalized only: it is not homogeneous, so it
// cannot be combined with the DetNormalized rescaling — requesting it there is an error). When
// rank F < n_y (an output without noise, or dependent noise), S can be flat and the maxdet
// problem unbounded; then DetNormalized adds Q ⪯ 10⁸ I (in the normalised coordinates).
//
// Guarantee in floating point: the LMIs are imposed with a margin (options.margin, in the
// normalised coordinates), and the values that are returned are then certified in the
// original coordinates: (L) is rebuilt from the returned P', d, H, τ, μ, ρ' with w = fl(P' d),
// scaled exactly by a diagonal of powers of two (D (L) D has a unit-order diagonal; congruence
// keeps semidefiniteness), and certify_psd is given an absolute slack ‖D Err D‖_F where Err
// bounds elementwise (a) the rounding of forming (L) (γ_K·|terms|), (b) |fl(P'd) − P'd| and
// (c) the effect of the rounding of the innovation e₀ = y − D u − C c (computed with a
// compensated dot product, so a state far from the origin does not cost precision). The (2,2)
// entry of (L) is a cancelling sum; if the check fails, ρ' is raised (by at most 1e-4 (ρ' + τρ))
// until it passes. (C1) is certified the same way, P' ≻ 0 by certify_psd, τ ≥ 0 and μ ≥ 0
// exactly (negative round-off is clamped to 0 before certifying). That proves S ⊆ E(P', c + d, ρ') in exact arithmetic; the returned centre
// c' = fl(c + d) is then covered by level_with_center_error. If any step fails — solver
// failure, a value that does not certify, a non-finite number — the prediction is returned
// and improved_solved is false: this function never throws for numerical reasons.
//
// The prediction is itself a feasible point of every mode (P' = P, d = 0, ρ' = ρ, τ = 1, H = 0,
// μ = 0). If the certified result is not better than it in the mode's own criterion (volume for
// FixedShape / DetNormalized, ρ' for BallNormalized), the prediction is returned as `improved`
// with that trivial certificate (improved_solved stays true: the LMI was solved, it just did
// not help). So FixedShape and DetNormalized never increase the volume.
//
// fixed_shape (§6.6 rule (ii)): the P-shaped outer bound E(P, c', ρ' λ_max(P'^(−1/2) P P'^(−1/2)))
// of `improved` (Ellipsoid::with_shape, rounded up and certified there) if its level is below
// the prediction's, else the prediction. This is what a fixed-shape recursion feeds back. With
// options.fixed_shape_by_lmi the FixedShape problem is solved as well and `fixed_shape` is the
// smaller of the two (rule (iii)); FixedShape's optimum dominates rule (ii) (the P-shaped bound
// of any certified set is itself certified by the same multipliers), and in the recursions of
// the tests rule (ii) alone is rarely below the prediction while rule (iii) often is.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/ellipsoidal/common.hpp"
#include "setbound/lmi/classes.hpp"
#include "setbound/lmi/model.hpp"
#include "setbound/lmi/solver.hpp"
#include "setbound/sets/ellipsoid.hpp"

namespace setbound {

/// papers.md §6.5 options A, B, C.
enum class CorrectionOption { FixedShape = 0, DetNormalized = 1, BallNormalized = 2 };

struct ImprovedCorrectionOptions {
  /// Margin of the reduced LMI K and of (C1) in the normalised coordinates (prior = unit ball);
  /// the certificate's shape is taken 10·margin inside Q. It is what certification has to
  /// spare; the result is larger than the exact optimum by about that (relative).
  double margin = 1e-7;
  /// Optional side constraint ρ' ≥ τρ (non-strict), §6.4.
  bool level_at_least_tau_rho = false;
  /// Optional side constraint τ ≤ 1, §6.4. FixedShape and BallNormalized only.
  bool tau_at_most_one = false;
  /// DetNormalized / BallNormalized: also solve the FixedShape problem and make `fixed_shape`
  /// the smaller of the two P-shaped bounds (§6.6 rule (iii) on top of rule (ii)). FixedShape's
  /// optimum is the best P-shaped set of the certificate family, so it is never worse than the
  /// P-shaped bound of the DetNormalized set, and in a recursion it is often much better (the
  /// P-shaped bound of a thin DetNormalized set is rarely below the prediction). Costs a second
  /// (linear) LMI solve per correction.
  bool fixed_shape_by_lmi = false;
  /// Interior-point options (linear modes) / maxdet options (DetNormalized).
  lmi::SolverOptions solver{};

  void validate(CorrectionOption option) const;
};

struct CorrectionResult {
  /// E(P', c', ρ') ⊇ { x ∈ E(P, c, ρ) : y − C x − D u ∈ F B^{n_ω} } (or the prediction, see below).
  Ellipsoid improved;
  /// A P-shaped outer bound E(P, c'', ρ'') of the same set: the P-shaped bound of `improved` if
  /// its level is below the prediction's, else the prediction itself (§6.6 rule (ii)); with
  /// options.fixed_shape_by_lmi, the FixedShape optimum when that is smaller (rule (iii)).
  Ellipsoid fixed_shape;
  /// S-procedure multiplier of the prior ellipsoid (of the returned certificate).
  double tau = 1.0;
  /// (C1) multipliers: Fᵀ H F ⪯ diag(μ), in the original coordinates.
  Eigen::MatrixXd H;
  Eigen::VectorXd mu;
  /// false when the LMI solve failed or its result could not be certified: then `improved`
  /// is the prediction (τ = 1, H = 0, μ = 0), and so is `fixed_shape` (unless the additional
  /// FixedShape solve of options.fixed_shape_by_lmi gave a smaller certified one).
  bool improved_solved = false;
};

namespace detail {

/// (M + Mᵀ)/2 evaluated into a new matrix (exactly symmetric; no aliasing with M).
Eigen::MatrixXd symmetrized(const Eigen::MatrixXd& M);

/// Spectral-norm bound of a matrix from an elementwise bound: ‖E‖₂ ≤ ‖|E|‖_F, rounded up.
double frobenius_up(const Eigen::MatrixXd& M);

/// certify_psd after an exact diagonal scaling: M is PSD iff D M D is, for D diagonal positive.
/// D_i is the power of two nearest 1/√M_ii (so D M D has a unit-order diagonal and the scaling
/// itself is exact). Err bounds |M − M_exact| elementwise; it is scaled the same way and enters
/// certify_psd as the absolute slack ‖D Err D‖_F. A non-positive diagonal entry gives false.
bool certify_psd_scaled(const Eigen::MatrixXd& M, const Eigen::MatrixXd& Err);

/// e₀ = y − C c − D u by a compensated dot product per row (Ogita–Rump–Oishi Dot2: error-free
/// products with fma, error-free sums, the errors summed on the side), so that the innovation
/// is accurate to about one rounding of e₀ itself even when y and C c are many orders larger
/// (a state far from the origin). eps receives a componentwise bound of |fl − exact|:
/// 2u|ê₀| + 2γ_N² Σ|terms| (ORO 2005, Prop. 5.5: u|exact| + γ_N² Σ|terms|, with a factor 2).
Eigen::VectorXd accurate_innovation(const Eigen::VectorXd& y, const Eigen::MatrixXd& C, const Eigen::VectorXd& c,
                                           const Eigen::MatrixXd& D, const Eigen::VectorXd& u, Eigen::VectorXd& eps);

/// The values of a certificate of (L)+(C1) in the original (centred) coordinates.
struct ImprovedCertificate {
  Eigen::MatrixXd Pp;  // P'
  Eigen::VectorXd d;   // c' − c
  Eigen::MatrixXd H;
  Eigen::VectorXd mu;  // length n_ω
  double tau = 0;
  double rho = 0;      // ρ'
};

/// True when the certificate proves S ⊆ E(P', c + d, ρ') in exact arithmetic (see the file
/// comment); k.rho may be raised slightly (at most 1e-4 (ρ' + τρ)) to make it so. P, c, ρ are
/// the predicted set's; y, u the data.
bool certify_improved(ImprovedCertificate& k, const Ellipsoid& pred, const Eigen::VectorXd& y,
                             const Eigen::VectorXd& u, const LinearSystem& sys);

}  // namespace detail

/// The correction of papers.md §6 with the LMI built once per system (values updated per call).
/// Not thread-safe (one instance per estimator).
class ImprovedCorrector {
 public:
  ImprovedCorrector(const LinearSystem& sys, CorrectionOption option = CorrectionOption::DetNormalized,
                    const ImprovedCorrectionOptions& options = {});
  ImprovedCorrector(const ImprovedCorrector& o) : ImprovedCorrector(o.sys_, o.option_, o.opt_) {}
  ImprovedCorrector& operator=(const ImprovedCorrector& o);
  ImprovedCorrector(ImprovedCorrector&&) noexcept = default;
  ImprovedCorrector& operator=(ImprovedCorrector&&) noexcept = default;

  const LinearSystem& system() const { return sys_; }
  CorrectionOption option() const { return option_; }
  const ImprovedCorrectionOptions& options() const { return opt_; }

  /// Corrects the predicted set of x_k with the measurement y_k (and the input u_k, which
  /// enters through D). Throws only for bad arguments ("predicted", "y", "u").
  CorrectionResult correct(const Ellipsoid& predicted, const Eigen::Ref<const Eigen::VectorXd>& y,
                           const Eigen::Ref<const Eigen::VectorXd>& u);

 private:
  CorrectionResult correct_one(const Ellipsoid& predicted, const Eigen::Ref<const Eigen::VectorXd>& y_in,
                               const Eigen::Ref<const Eigen::VectorXd>& u_in);

  struct State {
    lmi::Model model;
    lmi::Var H, tau, mu, rho;
    bool has_mu = false, has_rho = false;
    lmi::LmiProblem problem;
    std::unique_ptr<lmi::InteriorPointSolver> solver;  // linear modes
  };

  void init();

  /// Writes the constraints of the reduced normalised problem for data (C̃, ẽ, output
  /// scaling, G) — see the file comment:
  ///   K = [ Q    q           ]  ⪰ margin·I,   Q = τ I + C̃ᵀ H̃ C̃,  q = C̃ᵀ H̃ ẽ,
  ///       [ qᵀ   ρ̃' + s'     ]                s' = ẽᵀ H̃ ẽ − τ − Σμ̃,
  /// (C1) μ̃ − F̃ᵀ H̃ F̃ ⪰ margin·I, μ̃ ≥ 0, τ ≥ 0, and per mode Q ⪰ I (FixedShape), Q ⪰ G
  /// (BallNormalized), max log det Q with ρ̃' = 1 (DetNormalized).
  void build(const Eigen::MatrixXd& Ct, const Eigen::VectorXd& et, const Eigen::VectorXd& scale,
             const Eigen::MatrixXd& G);

  /// Solves the reduced normalised problem for this prediction and data and maps the values
  /// back to an (L)-certificate in the original coordinates (uncertified). False when the
  /// solver gave nothing usable.
  bool solve(const Ellipsoid& pred, const Eigen::VectorXd& y, const Eigen::VectorXd& u,
             detail::ImprovedCertificate& out);

  /// The mode's own criterion: ρ' < ρ for BallNormalized (the prediction is feasible there with
  /// the same bound P' ⪰ λ_min(P) I), volume for FixedShape and DetNormalized.
  bool better_than_prediction(const Eigen::MatrixXd& Pp, double level, const Ellipsoid& pred) const;

  static constexpr double kShapeCap = 1e8;

  LinearSystem sys_;
  CorrectionOption option_;
  ImprovedCorrectionOptions opt_;
  std::vector<Eigen::Index> cols_;
  Eigen::MatrixXd Fr_;
  bool rank_deficient_ = false;
  std::unique_ptr<State> st_;
  std::unique_ptr<ImprovedCorrector> fixed_;  // fixed_shape_by_lmi
};

/// One correction (builds the LMI for this call; for a loop keep an ImprovedCorrector).
CorrectionResult improved_correction(const Ellipsoid& predicted, const Eigen::Ref<const Eigen::VectorXd>& y,
                                            const Eigen::Ref<const Eigen::VectorXd>& u, const LinearSystem& sys,
                                            CorrectionOption option = CorrectionOption::DetNormalized,
                                            const ImprovedCorrectionOptions& options = {});

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/ellipsoidal/impl/improved_correction.ipp"
#endif
