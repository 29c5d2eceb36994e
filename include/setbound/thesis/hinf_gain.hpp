// setbound — H∞ observer gains and the Bounded-Real-Lemma RPI ellipsoid of the thesis
// (thesis.md §3.4, §4.2, §5.3).
//
//  * hinf_observer_gain: LMI (2.35) — minimise g = γ² over P ≻ 0, U, subject to
//        [ −P + Q        0        AᵀP − CᵀUᵀ ]
//        [ 0            −g I_m    [PF, −UZ]ᵀ ]  ≼ 0,        L = P⁻¹U,
//        [ PA − UC      [PF, −UZ]  −P        ]
//    i.e. the dissipation inequality V(e⁺) − V(e) ≤ −eᵀQe + γ² wᵀw for e⁺ = A_o e + E w,
//    A_o = A − LC, E = [F, −LZ] (Q = I: 2.10/2.22).
//  * brl_ellipsoidal_rpi: LMI (1.48) for x⁺ = A x + E w (the same LMI with U = 0, Q = I),
//    and the RPI ellipsoid Ψ = {xᵀPx ≤ λ_max(P) γ² w̄ᵀw̄} (1.55).
//
// Guarantee in floating point: the LMI is imposed with a small margin, and the returned
// design is certified — the block matrix rebuilt from the returned P, from the gain L that is
// actually returned (A_o = A − LC, E = [F, −LZ], i.e. PA_o instead of PA − UC) and from the
// returned g passes a Cholesky test with a slack covering the rounding (certify_psd). If the
// solver's point misses by a rounding error, g is enlarged slightly until the certificate
// holds; the returned g is the certified one (≥ the solver's optimum by a relative 1e-6 or
// less). A_o is checked Schur stable.
//
// Non-uniqueness (thesis.md §4.2): the optimal γ is unique; L and P are not. Compare γ, never
// L or P elementwise.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/symmetric.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/ellipsoidal/common.hpp"
#include "setbound/lmi/classes.hpp"
#include "setbound/lmi/model.hpp"
#include "setbound/thesis/plant.hpp"

namespace setbound::thesis {

struct HinfOptions {
  lmi::SolverOptions solver{};  // interior-point options
  /// The LMIs are imposed as −M ⪰ margin·scale·I, scale = max(1, ‖Q‖_max). Keeps the solver's
  /// point strictly inside so that the certificate passes; the cost on γ² is O(margin).
  double margin = 1e-9;
  /// Relative slack of the PSD certificate (covers the rounding of forming the block matrix).
  double certificate_slack = 1e-12;
  /// At most this many enlargements of g (by 1e-9·4^k relative) before the certificate gives up.
  int certify_attempts = 12;
  /// PBH tolerance of the detectability test (relative to max(1, ‖[A; C]‖)).
  double detectability_tol = 1e-9;

  void validate() const;
};

struct HinfGain {
  Eigen::MatrixXd P, U, L, Q;  // L = P⁻¹U; Q is the dissipation matrix used (I when none given)
  double gamma = 0, g = 0;     // g = γ² (certified), γ = √g rounded up
  double g_solver = 0;         // the solver's optimum of g (before certification)
  lmi::SolveStatus status = lmi::SolveStatus::NumericalError;
  int iterations = 0;
  double solve_time = 0;       // seconds
  double spectral_radius = 0;  // of A − LC (< 1)
};

/// One γ of a grid search (hinf_observer_gain_first_feasible): LMI (2.35) at the fixed level
/// g = γ², solved as a feasibility problem. `status`: Optimal = a certified solution (the last
/// trial of a successful search); Infeasible = the solver's certificate of infeasibility;
/// MaxIterations = not solved (iteration or time limit); NumericalError / Inaccurate = not
/// solved or not certified (numerical trouble).
struct GammaTrial {
  double gamma = 0;
  lmi::SolveStatus status = lmi::SolveStatus::NumericalError;
  int iterations = 0;
};

/// Result of a γ grid search: the certified gain at the first γ that gave one (g = γ², enlarged
/// by a relative 1e-9·4^k at most if the certificate needs it) and every γ tried, in order.
struct GammaGridGain {
  HinfGain gain;
  std::vector<GammaTrial> trials;
};

struct BrlRpi {
  Eigen::MatrixXd P;
  double gamma = 0, g = 0;  // g = γ² (certified)
  double level = 0;         // Ψ = {xᵀPx ≤ level}, level = λ_max(P) γ² w̄ᵀw̄ (1.55), rounded up
  double g_solver = 0;
  double solve_time = 0;
};

namespace hinf_detail {

/// An upper bound of λ_max(P), P symmetric: the computed eigenvalue plus a backward-error
/// bound of the symmetric eigensolver (8 n eps ‖P‖_F), rounded up.
double lambda_max_up(const Eigen::MatrixXd& P);

double spectral_radius(const Eigen::MatrixXd& A);

/// PBH test: every eigenvalue z of A with |z| ≥ 1 must be observable, i.e. [A − zI; C] has
/// full column rank. Throws NotDetectableError naming `name`.
void require_detectable(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C, double tol,
                               const std::string& name);

Eigen::MatrixXd dissipation_or_identity(const Eigen::MatrixXd& Q, Eigen::Index n);

/// The negated dissipation block matrix −M ⪰ 0 of (2.35)/(3.13)/(1.48) for given numbers:
///   [ P − Q, 0, −A_oᵀP ; 0, g I, −EᵀP ; −P A_o, −P E, P ].
Eigen::MatrixXd dissipation_block(const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q,
                                         const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& E, double g);

/// certify_psd after an exact diagonal scaling D M D by powers of two (D_ii ≈ 1/√M_ii): the
/// scaling does not change definiteness and is exact in floating point, and it keeps the
/// certificate's slack (relative to the trace) from swamping the small eigenvalues of badly
/// scaled matrices (P with a large condition number).
bool certify_psd_scaled(const Eigen::MatrixXd& M, double slack);

/// True when the dissipation inequality with (P, Q, A_o, E, g) is certified (Cholesky).
bool certify_dissipation(const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& Ao,
                                const Eigen::MatrixXd& E, double g, double slack);

struct VertexGainResult {
  Eigen::MatrixXd P;
  std::vector<Eigen::MatrixXd> U, L;
  double g = 0, g_solver = 0, solve_time = 0, spectral_radius = 0;
  lmi::SolveStatus status = lmi::SolveStatus::NumericalError;
  int iterations = 0;
  /// False when the solver gave no point (fixed-g mode only; `status` says why). A solved
  /// result with an empty P was not certified (the caller may retry with a larger margin).
  bool solved = true;
};

/// The solver's verdict in words for messages: "infeasible" (certificate), "not solved
/// (iteration limit)", "not solved (numerical trouble: <status>)".
std::string solve_verdict(lmi::SolveStatus s);

/// The vertex LMIs (3.13) with a common P (one vertex = LMI 2.35): minimise g. `what` names
/// the caller in messages. C may have zero rows only with `no_gain` (the BRL: U = 0, L = 0).
/// With fixed_g > 0 the level is fixed (g = fixed_g, no objective: a feasibility problem solved
/// by lmi::find_feasible, which certifies infeasibility); a point the solver does not give
/// returns `solved = false` with its status instead of throwing.
VertexGainResult hinf_vertex_gains_once(const std::vector<Eigen::MatrixXd>& As,
                                               const std::vector<Eigen::MatrixXd>& Fs, const Eigen::MatrixXd& C,
                                               const Eigen::MatrixXd& Z, const Eigen::MatrixXd& Q,
                                               const HinfOptions& opt, const std::string& what, bool no_gain,
                                               double margin, double& needed_margin, double fixed_g = 0.0);

struct GammaSearch {
  VertexGainResult gain;
  std::vector<GammaTrial> trials;
};

/// The vertex LMIs at g = γ² for γ = gammas[0], gammas[1], … until one has a certified
/// solution (the margin escalates as in hinf_vertex_gains). Throws InfeasibleError when every γ
/// is certified infeasible, NumericalError naming the counts ("infeasible" / "not solved
/// (iteration limit)" / "not solved (numerical trouble)") when some γ was not decided.
GammaSearch first_feasible_gamma(const std::vector<Eigen::MatrixXd>& As, const std::vector<Eigen::MatrixXd>& Fs,
                                 const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z, const Eigen::MatrixXd& Q,
                                 const std::vector<double>& gammas, const HinfOptions& opt, const std::string& what);

/// gammas: non-empty, finite, > 0, strictly increasing, at most kMaxGammas values.
void require_gamma_grid(const std::vector<double>& gammas);
constexpr int kMaxGammas = 10000;  // = SB_HINF_MAX_GAMMAS of setbound.h

/// The vertex LMIs (3.13) with a common P (one vertex = LMI 2.35): minimise g, certified.
/// `what` names the caller in messages. With `no_gain` (the BRL) U = 0, L = 0.
/// The margin starts at opt.margin·max(1, ‖Q‖) and, when the certificate fails because the
/// solution is large, the LMI is re-solved with a margin of 8× the certificate's slack.
VertexGainResult hinf_vertex_gains(const std::vector<Eigen::MatrixXd>& As,
                                          const std::vector<Eigen::MatrixXd>& Fs, const Eigen::MatrixXd& C,
                                          const Eigen::MatrixXd& Z, const Eigen::MatrixXd& Q,
                                          const HinfOptions& opt, const std::string& what, bool no_gain);

}  // namespace hinf_detail

/// LMI (2.35) with dissipation matrix Q (empty = I_n): minimise g = γ². L = P⁻¹U, E = [F, −LZ].
/// Throws NotDetectableError when (A, C) is not detectable, InfeasibleError when the LMI fails,
/// NumericalError when the solution cannot be certified.
HinfGain hinf_observer_gain(const Plant& plant, const Eigen::MatrixXd& Q = {}, const HinfOptions& opt = {});

/// CORA's γ grid of its H∞ designs (ESO-C/D, Hinf-G): linspace(1, 50, 100).
std::vector<double> cora_gamma_grid();

/// LMI (2.35) with dissipation matrix Q (empty = I_n) at the first γ of `gammas` (increasing,
/// > 0) for which it has a certified solution: CORA's search (priv_observe_gain_ESO_C/D), not a
/// minimisation, so γ ≥ the optimum of hinf_observer_gain by up to one grid step. Every γ is a
/// feasibility problem of lmi::find_feasible (a γ is skipped only on a certificate of
/// infeasibility or when the solver does not decide it; `trials` says which). Errors: as
/// first_feasible_gamma, NotDetectableError when (A, C) is not detectable.
GammaGridGain hinf_observer_gain_first_feasible(const Plant& plant, const Eigen::MatrixXd& Q = {},
                                                const std::vector<double>& gammas = cora_gamma_grid(),
                                                const HinfOptions& opt = {});

/// LMI (1.48) for x⁺ = A x + E w with |w| ≤ w̄ componentwise (so wᵀw ≤ w̄ᵀw̄):
/// minimise γ²; level = λ_max(P) γ² w̄ᵀw̄ (1.55), rounded up. A must be Schur stable.
BrlRpi brl_ellipsoidal_rpi(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E, const Eigen::VectorXd& wbar,
                                  const HinfOptions& opt = {});

}  // namespace setbound::thesis

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/thesis/impl/hinf_gain.ipp"
#endif
