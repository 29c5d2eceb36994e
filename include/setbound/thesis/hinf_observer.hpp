// setbound — the ellipsoidal-invariant-set H∞ observer of the thesis, Chapter 2 (thesis.md §4):
// error RPI ellipsoid (Prop 2.2/2.3), refinement of the dissipation matrix (2.36), covariance
// dissipation matrix (2.41–2.44), Algorithm 2 and the online observer (2.68–2.71).
//
// The shared pieces take *vertex lists* (A_o,i, E_i) so that Chapter 3 (lpv.hpp) reuses them
// with N vertices and a common P; the LTI case is N = 1.
//
// Guarantee in floating point. Everything the online bound relies on is one inequality,
//   V(e⁺) ≤ (1 − λ) V(e) + g wᵀw   for V = eᵀPe, every vertex (A_o,i, E_i),
// i.e. the dissipation LMI with Q := λP. The design certifies exactly that matrix (Cholesky
// with slack, certify_psd) for the returned P, L_i, g and λ, lowering λ by a relative 1e-9·4^k
// if needed. Online, the centre x̂ is computed in floating point; its rounding error is bounded
// componentwise (d) and the level μ c̄ is enlarged to (√(μc̄) + √λ_max(P)‖d‖)² (a relative change
// of order 1e-16), and the box x̂ ± ē∞√μ is rounded outwards. ē∞ = sqrt(diag(c̄ P⁻¹)) uses an
// upper bound of diag(P⁻¹) (computed inverse plus a residual bound).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "setbound/core/state.hpp"
#include "setbound/core/symmetric.hpp"
#include "setbound/thesis/hinf_gain.hpp"
#include "setbound/thesis/reading_screen.hpp"

namespace setbound::thesis {

/// How λ is obtained from a pass (thesis.md §4.4, §5.8).
///  LogDet: λ_min(Q_ref, P), Q_ref from the log-det refinement (2.36) — Algorithm 2 as printed.
///  Direct: [proposed] maximise λ subject to (2.36) with Q = λP (the best λ over all Q).
///  InputOrLogDet: the larger of λ_min(Q_input, P) and the LogDet value (Ch. 3 Ex 2, §5.8).
///  Largest: the largest of the three.
/// Every candidate gives a valid bound.
enum class LambdaRoute { LogDet = 0, Direct = 1, InputOrLogDet = 2, Largest = 3 };

struct ErrorRpi {
  double lambda = 0;  // λ_min(Q, P), rounded down so that Q − λP ⪰ 0 is certified
  double cbar = 0;    // c̄ = γ² w̄ᵀw̄ / λ (rounded up); Ψ = {eᵀPe ≤ c̄}
  double wtw = 0;     // w̄ᵀw̄ (rounded up)
  Eigen::VectorXd e_inf;  // sqrt(diag(c̄ P⁻¹)) (rounded up)
};

namespace hinf_detail {

void require_wbar(const Eigen::VectorXd& wbar, Eigen::Index m);

/// Upper bound of diag(P⁻¹) for P ≻ 0: computed inverse plus a residual bound.
Eigen::VectorXd inverse_diagonal_upper(const Eigen::MatrixXd& P);

/// λ_min(Q, P): the smallest generalised eigenvalue, rounded down until Q − λP ⪰ 0 is certified.
double lambda_min_certified(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& P);

/// Largest λ' ≤ λ (lowered by relative steps) with the dissipation LMI for Q = λ'P certified at
/// every vertex. This is the inequality the online recursion relies on.
double certify_lambda(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
                             const std::vector<Eigen::MatrixXd>& Es, double g, double lambda, double slack);

/// Normalised vertex data for the fixed-P problems: with P = RᵀR (Cholesky), Ã = R A_o R⁻¹ and
/// Ẽ = R E/√g the dissipation LMI becomes [[I − Q̃, 0, −Ãᵀ], [0, I, −Ẽᵀ], [−Ã, −Ẽ, I]] ⪰ 0 with
/// Q = Rᵀ Q̃ R — well scaled whatever the size of P and g.
struct Normalised {
  Eigen::MatrixXd R;
  std::vector<Eigen::MatrixXd> At, Et;
};
Normalised normalise(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
                            const std::vector<Eigen::MatrixXd>& Es, double g);

void add_normalised_lmis(lmi::Model& model, const lmi::AffineExpr& Qt, const Normalised& z, double margin);

/// (2.36)/(3.20) with P, g and the vertices fixed: maximise log det Q (solved in the
/// normalised coordinates above; log det Q = log det Q̃ + const).
Eigen::MatrixXd refine_q(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
                                const std::vector<Eigen::MatrixXd>& Es, double g, const HinfOptions& opt);

/// [proposed] maximise λ subject to (2.36) with Q = λP at every vertex (Q̃ = λI).
double direct_lambda(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
                            const std::vector<Eigen::MatrixXd>& Es, double g, const HinfOptions& opt);

/// Solves A V Aᵀ − V = −W (A Schur) by the Kronecker form (n ≤ a few tens).
Eigen::MatrixXd discrete_lyapunov(const Eigen::MatrixXd& A, const Eigen::MatrixXd& W);

}  // namespace hinf_detail

/// Prop 2.2/2.3: λ = λ_min(Q, P), c̄ = γ²w̄ᵀw̄/λ, ē∞ = sqrt(diag(c̄ P⁻¹)). With Q = I this is
/// Prop 2.2 (c̄ = λ_max(P) γ² w̄ᵀw̄). The dissipation LMI with (P, Q, g) is the caller's.
ErrorRpi ellipsoidal_error_rpi(const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q, double g,
                                      const Eigen::VectorXd& wbar);

/// (2.36): with P, γ and L fixed, maximise log det Q subject to the dissipation LMI. Returns Q_ref.
Eigen::MatrixXd refine_dissipation_matrix(const Plant& plant, const HinfGain& gain, const HinfOptions& opt = {});

/// [proposed] the largest λ with (2.36) for Q = λP (the best λ over all admissible Q).
double direct_dissipation_lambda(const Plant& plant, const HinfGain& gain, const HinfOptions& opt = {});

/// Covariance of a vector uniform on the box [lo, hi]: diag((hi − lo)²/12).
Eigen::MatrixXd uniform_covariance(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);

struct CovarianceDissipation {
  Eigen::MatrixXd V;  // steady-state error covariance (average over the vertices for LPV)
  Eigen::MatrixXd Q;  // V⁻¹
};

/// (2.43)–(2.44)/(3.60)–(3.61): V_i solves A_o,i V_i A_o,iᵀ − V_i = −E_i W E_iᵀ, V = mean V_i, Q = V⁻¹.
/// W is the covariance of w (m×m), e.g. uniform_covariance(−w̄, w̄) = diag(w̄²/3).
CovarianceDissipation covariance_dissipation_matrix(const std::vector<Eigen::MatrixXd>& Aos,
                                                           const std::vector<Eigen::MatrixXd>& Es,
                                                           const Eigen::MatrixXd& W);

CovarianceDissipation covariance_dissipation_matrix(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& E,
                                                           const Eigen::MatrixXd& W);

/// (2.41): {eᵀV⁻¹e ≤ t²} holds with probability ≥ 1 − n/t² (Chebyshev, reporting only).
struct ChebyshevEllipsoid {
  Eigen::MatrixXd shape;  // V⁻¹
  double level = 0;       // t²
  double probability_lower = 0;  // max(0, 1 − n/t²)
};
ChebyshevEllipsoid chebyshev_error_ellipsoid(const Eigen::MatrixXd& V, double t);

struct EllipsoidalSMOptions {
  HinfOptions hinf{};
  LambdaRoute lambda_route = LambdaRoute::LogDet;
  int passes = 2;                // Algorithm 2/3 executes exactly two
  Eigen::MatrixXd w_covariance;  // m×m covariance of w for (2.44); empty: uniform on [−w̄, w̄]
  void validate() const;
};

struct EllipsoidalSMPass {
  Eigen::MatrixXd Q_input, P, Q_refined;
  std::vector<Eigen::MatrixXd> L;  // one per vertex (one for LTI)
  double g = 0, gamma = 0;
  double lambda_input = 0, lambda_refined = 0;
  double lambda_direct = std::numeric_limits<double>::quiet_NaN();  // only when the route asks for it
  double lambda = 0;  // chosen by the route and certified
  bool refinement_failed = false;  // the log-det refinement did not converge; Q_refined = Q_input
};

struct EllipsoidalSMDesign {
  std::vector<Eigen::MatrixXd> L_vertices;  // L_i (LTI: one)
  Eigen::MatrixXd L, P, Q_input, Q_refined, V;  // L = L_vertices[0]; V of the last covariance step
  double gamma = 0, g = 0, lambda = 0, lambda_input = 0, lambda_refined = 0, cbar = 0, wtw = 0;
  Eigen::VectorXd wbar, e_inf;
  double lambda_max_P = 0;  // upper bound of λ_max(P)
  std::vector<EllipsoidalSMPass> passes;
  double design_time = 0;  // seconds (solver time)
};

namespace hinf_detail {

/// The design's result from its last pass (d.wtw set, d.passes not empty): L, P, Q, g, γ, λ
/// copied, c̄ = g w̄ᵀw̄/λ and ē∞ = sqrt(diag(c̄P⁻¹)) rounded up, the bound of λ_max(P).
/// Shared by Algorithm 2/3 and the ESO-D design (eso_d.hpp).
void finish_design(EllipsoidalSMDesign& d);

/// Algorithm 2/3 on vertex data. gain_fn(Q) returns the vertex gain result for dissipation Q.
template <class GainFn>
EllipsoidalSMDesign design_vertices(const std::vector<Eigen::MatrixXd>& As, const std::vector<Eigen::MatrixXd>& Fs,
                                    const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Eigen::VectorXd& wbar,
                                    const EllipsoidalSMOptions& opt, GainFn gain_fn) {
  using ell_rounding::round_up;
  const Eigen::Index n = As[0].rows(), nd = Fs[0].cols(), nv = Z.cols(), m = nd + nv;
  require_wbar(wbar, m);
  Eigen::MatrixXd W = opt.w_covariance;
  if (W.size() == 0) W = uniform_covariance(-wbar, wbar);
  require_shape(W, m, m, "w_covariance");
  require_finite(W, "w_covariance");
  EllipsoidalSMDesign d;
  d.wbar = wbar;
  d.wtw = round_up(wbar.squaredNorm());
  Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(n, n);
  for (int pass = 0; pass < opt.passes; ++pass) {
    VertexGainResult r = gain_fn(Q);
    d.design_time += r.solve_time;
    std::vector<Eigen::MatrixXd> Aos(As.size()), Es(As.size());
    for (size_t i = 0; i < As.size(); ++i) {
      Aos[i] = As[i] - r.L[i] * C;
      Es[i].resize(n, m);
      if (nd > 0) Es[i].leftCols(nd) = Fs[i];
      if (nv > 0) Es[i].rightCols(nv) = -r.L[i] * Z;
    }
    EllipsoidalSMPass p;
    p.Q_input = Q;
    p.P = r.P;
    p.L = r.L;
    p.g = r.g;
    p.gamma = round_up(std::sqrt(r.g));
    p.lambda_input = lambda_min_certified(Q, r.P);
    try {
      p.Q_refined = refine_q(r.P, Aos, Es, r.g, opt.hinf);
      p.lambda_refined = lambda_min_certified(p.Q_refined, r.P);
    } catch (const NumericalError&) {
      // The log-det problem did not converge (badly scaled data): Q_input is a valid
      // dissipation matrix for this (P, L, g), so the pass falls back to it (reported).
      p.refinement_failed = true;
      p.Q_refined = Q;
      p.lambda_refined = p.lambda_input;
    }
    double lam = p.lambda_refined;
    if (opt.lambda_route == LambdaRoute::InputOrLogDet || opt.lambda_route == LambdaRoute::Largest)
      lam = std::max(lam, p.lambda_input);
    if (opt.lambda_route == LambdaRoute::Direct || opt.lambda_route == LambdaRoute::Largest) {
      p.lambda_direct = direct_lambda(r.P, Aos, Es, r.g, opt.hinf);
      lam = opt.lambda_route == LambdaRoute::Direct ? p.lambda_direct : std::max(lam, p.lambda_direct);
    }
    if (!(lam > 0)) throw NumericalError("lambda: the design gave lambda <= 0");
    p.lambda = certify_lambda(r.P, Aos, Es, r.g, lam, opt.hinf.certificate_slack);
    const bool last = pass + 1 == opt.passes;
    if (!last) {
      CovarianceDissipation cov = covariance_dissipation_matrix(Aos, Es, W);
      d.V = cov.V;
      Q = cov.Q;
    }
    d.passes.push_back(std::move(p));
  }
  finish_design(d);
  return d;
}

}  // namespace hinf_detail

/// Algorithm 2 (two passes): Q = I → (2.35) → L → refine (2.36) → λ; Q = V⁻¹ (2.43–2.44) → again.
/// wbar: half-widths of the centred disturbance box (w̄ᵀw̄ is the 2-norm bound).
EllipsoidalSMDesign design_ellipsoidal_sm_observer(const Plant& plant, const Eigen::VectorXd& wbar,
                                                          const EllipsoidalSMOptions& opt = {});

/// μ0 from a ball ‖e_0‖₂ ≤ radius: max(1, λ_max(P) radius²/c̄) (2.65–2.67), rounded up.
double mu0_from_ball(const EllipsoidalSMDesign& d, double radius);

/// μ0 from the vertices (columns, n×p) of a polytope containing e_0 = x_0 − x̂_0:
/// max(1, max_j v_jᵀPv_j / c̄) (3.73–3.74), rounded up.
double mu0_from_vertices(const EllipsoidalSMDesign& d, const Eigen::MatrixXd& vertices);

/// The 2ⁿ corners of the box [lo, hi] as columns (for mu0_from_vertices with E_0 = [x_0] − x̂_0),
/// n <= 20.
Eigen::MatrixXd box_corners(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);

/// μ0 for e_0 = x_0 − x̂_0 in the box [lo, hi] (length n each, lo <= hi): for n <= 20 the exact
/// maximum over its 2ⁿ corners (mu0_from_vertices ∘ box_corners); beyond, where the corners are
/// too many, the smaller of two upper bounds of max vᵀPv over the box with r = max(|lo|, |hi|):
/// rᵀ|P|r and λ_max(P) rᵀr (mu0_from_ball) — guaranteed, possibly larger than the corners' max.
double mu0_from_box(const EllipsoidalSMDesign& d, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);

namespace hinf_detail {

double up(double x);
double down(double x);

/// Shared online state: x̂, μ and the output box. The level update includes the centre error d.
struct SMState {
  Eigen::VectorXd xhat, xnext, d, lower, upper, e_inf;
  double mu = 1, lambda = 0, cbar = 0, lambda_max_P = 0, one_minus_lambda = 0;
  long k = 0;

  void init(const EllipsoidalSMDesign& des, const Eigen::VectorXd& xhat0, double mu0);
  /// μ⁺ = (1 − λ)μ + λ, then the level μ⁺c̄ enlarged for the centre error d (already in `d`).
  void advance();
  void save(StateWriter& w) const;
  /// Reads k, x̂, μ (validated) into this state; call on a copy or after all other reads.
  static void read(StateReader& r, Eigen::Index n, long& k_out, Eigen::VectorXd& xhat_out, double& mu_out);
  /// Commits a state read by read(): no allocation (x̂ is moved in, the box has its size), so
  /// it cannot throw and a restore is all-or-nothing.
  void apply(long k_in, Eigen::VectorXd&& xhat_in, double mu_in) noexcept;
  void update_box();
};

void check_vec(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Index n, const char* name);

/// Certified upper bounds of C_i P⁻¹ C_iᵀ (the squared support of {eᵀPe ≤ 1} in ±C_i).
Eigen::VectorXd output_gram_upper(const Eigen::MatrixXd& P, const Eigen::MatrixXd& C);

/// μ ≥ 1 with every point of [lo, hi] − x̂ in {eᵀPe ≤ μc̄}: the box's corners for n ≤ 12,
/// rᵀ|P|r with r = max(|lo − x̂|, |hi − x̂|) beyond (rounded up).
double mu_from_box(const EllipsoidalSMDesign& d, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                   const Eigen::VectorXd& xhat);

/// Missing and impossible readings of the SM observers (reading_screen.hpp): the data both
/// observers keep for them.
struct SMReadings {
  ReadingScreen screen;
  Eigen::VectorXd qC;   // output_gram_upper(P, C)
  Box d, v;             // the centred boxes [−w̄_d, w̄_d], [−w̄_v, w̄_v] of the design
  Eigen::MatrixXd Zabs;
  double lambda_min_P = 0;  // lower bound of λ_min(P) (0: unknown, the ellipsoidal route is skipped)

  void init(const EllipsoidalSMDesign& des, const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const SMState& st);
  /// Tests y against the support of the current ellipsoid {(x − x̂)ᵀP(x − x̂) ≤ μc̄} in ±C_i
  /// plus |Z_i| w̄_v; throws under policy Raise (nothing changed). True: every output is used.
  bool screen_step(const SMState& st, const Eigen::MatrixXd& C, const Eigen::Ref<const Eigen::VectorXd>& y);
  /// The step without some output, two guaranteed candidates, the one of smaller level kept:
  ///  (a) interval prediction of the (narrowed) box of x_k — or of the reset box under policy
  ///      Reset — and a restart of st at k+1 from it (x̂ its centre, μ from its corners);
  ///  (b) (LTI, `L` given, no reset) the Luenberger step with the gain restricted to the outputs
  ///      used, G = L with the other columns zero: e⁺ = (A − GC)e + F d − G Z v, so
  ///      ‖e⁺‖_P ≤ α‖e‖_P + Σ_j w̄_j ‖[F, −GZ]_j‖_P with α ≥ ‖A − GC‖_P certified (rounding of
  ///      A − GC and of the centre included). No box conversion: the set does not inflate by
  ///      the ellipsoid ↔ box factors at every missing sample.
  void fallback_step(SMState& st, const EllipsoidalSMDesign& des, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                     const Eigen::MatrixXd& F, const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z,
                     const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u,
                     const screen_detail::ModelWidening* widen = nullptr, const Eigen::MatrixXd* L = nullptr);
};

}  // namespace hinf_detail

/// Online observer (2.68–2.71): x̂⁺ = (A − LC)x̂ + Bu + Ly, μ⁺ = (1 − λ)μ + λ,
/// box x̂ ± ē∞√μ. A one-step predictor: after k steps the box bounds x_k (it used y_0..y_{k−1}).
/// step() does not allocate.
class EllipsoidalSMObserver {
 public:
  EllipsoidalSMObserver(const Plant& plant, EllipsoidalSMDesign design, const Eigen::VectorXd& xhat0, double mu0);

  /// NaN entries of y are missing outputs; every present reading is tested against the support
  /// of the current ellipsoid (reading_screen.hpp). A step without some output is made in
  /// interval arithmetic and restarts the recursion from the predicted box (x̂ its midpoint, μ
  /// from its corners). ±inf, wrong sizes: an error, the observer unchanged.
  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u);

  /// Full mutable state (core/state.hpp): x̂_k, μ_k and k (the box follows from them).
  std::vector<double> save_state() const;
  /// Restores a state from save_state() (same plant and design); throws InvalidArgumentError
  /// ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state);
  StateFingerprint fingerprint() const;

  void reset(const Eigen::VectorXd& xhat0, double mu0) {
    st_.init(design_, xhat0, mu0);
    rd_.screen.check.clear(C_.rows(), OutputStatus::Used);
  }

  /// Policy for impossible readings; `reset_box` (size 0: keep; default the box of the initial
  /// ellipsoid) is where policy Reset restarts.
  void set_inconsistency_policy(OnInconsistency policy, const Box& reset_box = Box()) {
    rd_.screen.set_policy(policy, reset_box, C_.cols());
  }
  OnInconsistency inconsistency_policy() const { return rd_.screen.policy; }
  /// The screening of the last step (every output Used before the first).
  const MeasurementCheck& last_check() const { return rd_.screen.check; }

  const Eigen::VectorXd& center() const { return st_.xhat; }
  const Eigen::VectorXd& lower() const { return st_.lower; }
  const Eigen::VectorXd& upper() const { return st_.upper; }
  double mu() const { return st_.mu; }
  long steps() const { return st_.k; }
  const EllipsoidalSMDesign& design() const { return design_; }

 private:
  EllipsoidalSMDesign design_;
  Eigen::MatrixXd Ao_, B_, L_, Ma_, Mb_, Ml_, A_, C_, F_, Z_;
  Eigen::VectorXd tmp_, tmpu_, tmpy_;
  hinf_detail::SMState st_;
  hinf_detail::SMReadings rd_;
};

}  // namespace setbound::thesis

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/thesis/impl/hinf_observer.ipp"
#endif
