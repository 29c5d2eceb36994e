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
#include "setbound/thesis/hinf_gain.hpp"

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

inline void require_wbar(const Eigen::VectorXd& wbar, Eigen::Index m) {
  if (wbar.size() != m)
    throw DimensionError("wbar: expected " + std::to_string(m) + " entries (m = n_d + n_v), got " +
                         std::to_string(wbar.size()));
  require_finite(wbar, "wbar");
  if ((wbar.array() < 0).any()) throw InvalidArgumentError("wbar: the bounds must be >= 0");
}

/// Upper bound of diag(P⁻¹) for P ≻ 0: computed inverse plus a residual bound.
inline Eigen::VectorXd inverse_diagonal_upper(const Eigen::MatrixXd& P) {
  const Eigen::Index n = P.rows();
  Eigen::LLT<Eigen::MatrixXd> llt(P);
  if (llt.info() != Eigen::Success) throw NotPositiveDefiniteError("P: matrix is not positive definite");
  Eigen::MatrixXd X = llt.solve(Eigen::MatrixXd::Identity(n, n));
  X = 0.5 * (X + X.transpose());
  const Eigen::MatrixXd R = Eigen::MatrixXd::Identity(n, n) - P * X;
  const double eps = ell_rounding::kEps;
  const double r = R.norm() + ell_rounding::gamma(n + 2) * P.norm() * X.norm();
  if (!(r < 0.5)) throw NumericalError("P: too ill-conditioned to bound diag(P^-1) reliably");
  const double err = X.norm() * r / (1.0 - r);
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i) d(i) = ell_rounding::round_up(X(i, i) + err + eps * std::abs(X(i, i)));
  return d;
}

/// λ_min(Q, P): the smallest generalised eigenvalue, rounded down until Q − λP ⪰ 0 is certified.
inline double lambda_min_certified(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& P) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(Q, P, Eigen::EigenvaluesOnly);
  if (ges.info() != Eigen::Success) throw NumericalError("Q, P: the generalised eigenvalue problem failed");
  double lam = ges.eigenvalues().minCoeff();
  if (!(lam > 0)) throw NotPositiveDefiniteError("Q: lambda_min(Q, P) is not positive");
  for (int k = 0; k < 40; ++k) {
    if (certify_psd(Q - lam * P, 0.0, 1e-13)) return lam;
    lam *= 1.0 - 1e-12 * std::pow(4.0, k);
  }
  throw NumericalError("Q, P: Q - lambda P >= 0 could not be certified");
}

/// Largest λ' ≤ λ (lowered by relative steps) with the dissipation LMI for Q = λ'P certified at
/// every vertex. This is the inequality the online recursion relies on.
inline double certify_lambda(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
                             const std::vector<Eigen::MatrixXd>& Es, double g, double lambda, double slack) {
  double lam = std::min(lambda, 1.0);
  for (int k = 0; k < 16; ++k) {
    bool ok = true;
    for (size_t i = 0; i < Aos.size() && ok; ++i)
      ok = certify_dissipation(P, lam * P, Aos[i], Es[i], g, slack);
    if (ok) return lam;
    lam *= 1.0 - 1e-9 * std::pow(4.0, k);
  }
  throw NumericalError("lambda: the dissipation inequality with Q = lambda P could not be certified");
}

/// Normalised vertex data for the fixed-P problems: with P = RᵀR (Cholesky), Ã = R A_o R⁻¹ and
/// Ẽ = R E/√g the dissipation LMI becomes [[I − Q̃, 0, −Ãᵀ], [0, I, −Ẽᵀ], [−Ã, −Ẽ, I]] ⪰ 0 with
/// Q = Rᵀ Q̃ R — well scaled whatever the size of P and g.
struct Normalised {
  Eigen::MatrixXd R;
  std::vector<Eigen::MatrixXd> At, Et;
};
inline Normalised normalise(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
                            const std::vector<Eigen::MatrixXd>& Es, double g) {
  Eigen::LLT<Eigen::MatrixXd> llt(P);
  if (llt.info() != Eigen::Success) throw NotPositiveDefiniteError("P: matrix is not positive definite");
  Normalised z;
  z.R = llt.matrixU();
  const Eigen::MatrixXd Rinv = z.R.inverse();
  for (size_t i = 0; i < Aos.size(); ++i) {
    z.At.push_back(z.R * Aos[i] * Rinv);
    z.Et.push_back(z.R * Es[i] / std::sqrt(g));
  }
  return z;
}

inline void add_normalised_lmis(lmi::Model& model, const lmi::AffineExpr& Qt, const Normalised& z, double margin) {
  const Eigen::Index n = z.R.rows();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  for (size_t i = 0; i < z.At.size(); ++i) {
    const Eigen::Index m = z.Et[i].cols();
    model.add_lmi(lmi::sym_block({{lmi::AffineExpr(I) - Qt},
                                  {lmi::AffineExpr::zero(m, n), lmi::AffineExpr(Eigen::MatrixXd(Eigen::MatrixXd::Identity(m, m)))},
                                  {lmi::AffineExpr(Eigen::MatrixXd(-z.At[i])), lmi::AffineExpr(Eigen::MatrixXd(-z.Et[i])), lmi::AffineExpr(I)}}),
                  margin);
  }
}

/// (2.36)/(3.20) with P, g and the vertices fixed: maximise log det Q (solved in the
/// normalised coordinates above; log det Q = log det Q̃ + const).
inline Eigen::MatrixXd refine_q(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
                                const std::vector<Eigen::MatrixXd>& Es, double g, const HinfOptions& opt) {
  const int n = static_cast<int>(P.rows());
  const Normalised z = normalise(P, Aos, Es, g);
  lmi::Model model;
  lmi::Var Qt = model.symmetric(n);
  add_normalised_lmis(model, Qt, z, opt.margin);
  model.add_logdet(Qt);
  const lmi::LmiProblem problem = model.build();
  const lmi::SolveResult res = lmi::solve(problem, opt.solver);
  if (res.status != lmi::SolveStatus::Optimal && res.status != lmi::SolveStatus::Inaccurate)
    throw NumericalError(std::string("refine_dissipation_matrix: the log-det problem (2.36) failed (solver status: ") +
                         lmi::status_name(res.status) + ")");
  Eigen::MatrixXd Qv = z.R.transpose() * model.value(Qt, res.x) * z.R;
  return 0.5 * (Qv + Qv.transpose());
}

/// [proposed] maximise λ subject to (2.36) with Q = λP at every vertex (Q̃ = λI).
inline double direct_lambda(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
                            const std::vector<Eigen::MatrixXd>& Es, double g, const HinfOptions& opt) {
  const Eigen::Index n = P.rows();
  const Normalised z = normalise(P, Aos, Es, g);
  lmi::Model model;
  lmi::Var lam = model.scalar();
  add_normalised_lmis(model, lam * Eigen::MatrixXd::Identity(n, n), z, opt.margin);
  model.add_lmi(lam);
  model.maximize(lam);
  const lmi::LmiProblem problem = model.build();
  const lmi::SolveResult res = lmi::solve(problem, opt.solver);
  if (res.status != lmi::SolveStatus::Optimal && res.status != lmi::SolveStatus::Inaccurate)
    throw NumericalError(std::string("refine_dissipation_matrix: the direct lambda problem failed (solver status: ") +
                         lmi::status_name(res.status) + ")");
  return model.scalar_value(lam, res.x);
}

/// Solves A V Aᵀ − V = −W (A Schur) by the Kronecker form (n ≤ a few tens).
inline Eigen::MatrixXd discrete_lyapunov(const Eigen::MatrixXd& A, const Eigen::MatrixXd& W) {
  const Eigen::Index n = A.rows();
  Eigen::MatrixXd K = Eigen::MatrixXd::Identity(n * n, n * n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) K.block(i * n, j * n, n, n) -= A(i, j) * A;  // vec(AVAᵀ) = (A⊗A) vec V
  Eigen::Map<const Eigen::VectorXd> w(W.data(), n * n);
  Eigen::VectorXd v = K.partialPivLu().solve(w);
  Eigen::MatrixXd V = Eigen::Map<Eigen::MatrixXd>(v.data(), n, n);
  return 0.5 * (V + V.transpose());
}

}  // namespace hinf_detail

/// Prop 2.2/2.3: λ = λ_min(Q, P), c̄ = γ²w̄ᵀw̄/λ, ē∞ = sqrt(diag(c̄ P⁻¹)). With Q = I this is
/// Prop 2.2 (c̄ = λ_max(P) γ² w̄ᵀw̄). The dissipation LMI with (P, Q, g) is the caller's.
inline ErrorRpi ellipsoidal_error_rpi(const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q, double g,
                                      const Eigen::VectorXd& wbar) {
  require_positive_definite(P, "P");
  require_shape(Q, P.rows(), P.cols(), "Q");
  require_positive_definite(Q, "Q");
  require_positive(g, "g");
  require_finite(wbar, "wbar");
  if ((wbar.array() < 0).any()) throw InvalidArgumentError("wbar: the bounds must be >= 0");
  using ell_rounding::round_up;
  ErrorRpi r;
  r.lambda = hinf_detail::lambda_min_certified(Q, P);
  r.wtw = round_up(wbar.squaredNorm());
  r.cbar = round_up(round_up(g * r.wtw) / r.lambda);
  const Eigen::VectorXd d = hinf_detail::inverse_diagonal_upper(P);
  r.e_inf.resize(P.rows());
  for (Eigen::Index i = 0; i < P.rows(); ++i) r.e_inf(i) = round_up(std::sqrt(round_up(r.cbar * d(i))));
  return r;
}

/// (2.36): with P, γ and L fixed, maximise log det Q subject to the dissipation LMI. Returns Q_ref.
inline Eigen::MatrixXd refine_dissipation_matrix(const Plant& plant, const HinfGain& gain, const HinfOptions& opt = {}) {
  opt.validate();
  require_shape(gain.L, plant.nx(), plant.ny(), "L");
  require_positive_definite(gain.P, "P");
  return hinf_detail::refine_q(gain.P, {Eigen::MatrixXd(plant.A - gain.L * plant.C)}, {plant.error_input(gain.L)},
                               gain.g, opt);
}

/// [proposed] the largest λ with (2.36) for Q = λP (the best λ over all admissible Q).
inline double direct_dissipation_lambda(const Plant& plant, const HinfGain& gain, const HinfOptions& opt = {}) {
  opt.validate();
  require_shape(gain.L, plant.nx(), plant.ny(), "L");
  return hinf_detail::direct_lambda(gain.P, {Eigen::MatrixXd(plant.A - gain.L * plant.C)}, {plant.error_input(gain.L)},
                                    gain.g, opt);
}

/// Covariance of a vector uniform on the box [lo, hi]: diag((hi − lo)²/12).
inline Eigen::MatrixXd uniform_covariance(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  require_finite(lo, "lo");
  require_finite(hi, "hi");
  if (lo.size() != hi.size()) throw DimensionError("hi: expected the size of lo");
  if ((hi.array() < lo.array()).any()) throw InvalidArgumentError("hi: must be >= lo componentwise");
  return ((hi - lo).array().square() / 12.0).matrix().asDiagonal();
}

struct CovarianceDissipation {
  Eigen::MatrixXd V;  // steady-state error covariance (average over the vertices for LPV)
  Eigen::MatrixXd Q;  // V⁻¹
};

/// (2.43)–(2.44)/(3.60)–(3.61): V_i solves A_o,i V_i A_o,iᵀ − V_i = −E_i W E_iᵀ, V = mean V_i, Q = V⁻¹.
/// W is the covariance of w (m×m), e.g. uniform_covariance(−w̄, w̄) = diag(w̄²/3).
inline CovarianceDissipation covariance_dissipation_matrix(const std::vector<Eigen::MatrixXd>& Aos,
                                                           const std::vector<Eigen::MatrixXd>& Es,
                                                           const Eigen::MatrixXd& W) {
  if (Aos.empty() || Aos.size() != Es.size()) throw DimensionError("Ao, E: expected the same non-zero number of vertices");
  const Eigen::Index n = Aos[0].rows(), m = Es[0].cols();
  require_shape(W, m, m, "W");
  require_finite(W, "W");
  require_symmetric(W, "W");
  CovarianceDissipation c;
  c.V = Eigen::MatrixXd::Zero(n, n);
  for (size_t i = 0; i < Aos.size(); ++i) {
    require_shape(Aos[i], n, n, "Ao");
    require_shape(Es[i], n, m, "E");
    if (!(hinf_detail::spectral_radius(Aos[i]) < 1.0))
      throw InvalidArgumentError("Ao: not Schur stable; the steady-state covariance does not exist");
    c.V += hinf_detail::discrete_lyapunov(Aos[i], Es[i] * W * Es[i].transpose());
  }
  c.V /= static_cast<double>(Aos.size());
  Eigen::LLT<Eigen::MatrixXd> llt(c.V);
  if (llt.info() != Eigen::Success)
    throw NotPositiveDefiniteError("V: the error covariance is singular (the disturbance does not excite every error "
                                   "direction); Q = V^-1 does not exist");
  c.Q = llt.solve(Eigen::MatrixXd::Identity(n, n));
  c.Q = 0.5 * (c.Q + c.Q.transpose());
  return c;
}

inline CovarianceDissipation covariance_dissipation_matrix(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& E,
                                                           const Eigen::MatrixXd& W) {
  return covariance_dissipation_matrix(std::vector<Eigen::MatrixXd>{Ao}, std::vector<Eigen::MatrixXd>{E}, W);
}

/// (2.41): {eᵀV⁻¹e ≤ t²} holds with probability ≥ 1 − n/t² (Chebyshev, reporting only).
struct ChebyshevEllipsoid {
  Eigen::MatrixXd shape;  // V⁻¹
  double level = 0;       // t²
  double probability_lower = 0;  // max(0, 1 − n/t²)
};
inline ChebyshevEllipsoid chebyshev_error_ellipsoid(const Eigen::MatrixXd& V, double t) {
  require_positive_definite(V, "V");
  require_positive(t, "t");
  ChebyshevEllipsoid c;
  c.shape = V.llt().solve(Eigen::MatrixXd::Identity(V.rows(), V.cols()));
  c.level = t * t;
  c.probability_lower = std::max(0.0, 1.0 - static_cast<double>(V.rows()) / (t * t));
  return c;
}

struct EllipsoidalSMOptions {
  HinfOptions hinf{};
  LambdaRoute lambda_route = LambdaRoute::LogDet;
  int passes = 2;                // Algorithm 2/3 executes exactly two
  Eigen::MatrixXd w_covariance;  // m×m covariance of w for (2.44); empty: uniform on [−w̄, w̄]
  void validate() const {
    hinf.validate();
    if (passes < 1) throw InvalidArgumentError("passes: must be >= 1");
  }
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
  const EllipsoidalSMPass& f = d.passes.back();
  d.L_vertices = f.L;
  d.L = f.L.front();
  d.P = f.P;
  d.Q_input = f.Q_input;
  d.Q_refined = f.Q_refined;
  d.g = f.g;
  d.gamma = f.gamma;
  d.lambda = f.lambda;
  d.lambda_input = f.lambda_input;
  d.lambda_refined = f.lambda_refined;
  d.cbar = round_up(round_up(d.g * d.wtw) / d.lambda);
  const Eigen::VectorXd di = inverse_diagonal_upper(d.P);
  d.e_inf.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) d.e_inf(i) = round_up(std::sqrt(round_up(d.cbar * di(i))));
  d.lambda_max_P = lambda_max_up(d.P);
  return d;
}

}  // namespace hinf_detail

/// Algorithm 2 (two passes): Q = I → (2.35) → L → refine (2.36) → λ; Q = V⁻¹ (2.43–2.44) → again.
/// wbar: half-widths of the centred disturbance box (w̄ᵀw̄ is the 2-norm bound).
inline EllipsoidalSMDesign design_ellipsoidal_sm_observer(const Plant& plant, const Eigen::VectorXd& wbar,
                                                          const EllipsoidalSMOptions& opt = {}) {
  opt.validate();
  hinf_detail::require_detectable(plant.A, plant.C, opt.hinf.detectability_tol, "A, C");
  return hinf_detail::design_vertices({plant.A}, {plant.F}, plant.C, plant.Z, wbar, opt, [&](const Eigen::MatrixXd& Q) {
    return hinf_detail::hinf_vertex_gains({plant.A}, {plant.F}, plant.C, plant.Z, Q, opt.hinf,
                                          "design_ellipsoidal_sm_observer", false);
  });
}

/// μ0 from a ball ‖e_0‖₂ ≤ radius: max(1, λ_max(P) radius²/c̄) (2.65–2.67), rounded up.
inline double mu0_from_ball(const EllipsoidalSMDesign& d, double radius) {
  require_nonnegative(radius, "radius");
  using ell_rounding::round_up;
  return std::max(1.0, round_up(round_up(d.lambda_max_P * round_up(radius * radius)) / d.cbar));
}

/// μ0 from the vertices (columns, n×p) of a polytope containing e_0 = x_0 − x̂_0:
/// max(1, max_j v_jᵀPv_j / c̄) (3.73–3.74), rounded up.
inline double mu0_from_vertices(const EllipsoidalSMDesign& d, const Eigen::MatrixXd& vertices) {
  if (vertices.rows() != d.P.rows() || vertices.cols() == 0)
    throw DimensionError("vertices: expected shape (" + std::to_string(d.P.rows()) + ", p) with p >= 1, got " +
                         setbound::detail::shape_string(vertices.rows(), vertices.cols()));
  require_finite(vertices, "vertices");
  using ell_rounding::round_up;
  double mx = 0;
  const double rel = 1.0 + ell_rounding::gamma(2 * d.P.rows() + 2);
  for (Eigen::Index j = 0; j < vertices.cols(); ++j) {
    const Eigen::VectorXd v = vertices.col(j);
    // |fl(vᵀPv) − vᵀPv| ≤ γ |v|ᵀ|P||v|
    const double q = v.dot(d.P * v) + ell_rounding::gamma(2 * d.P.rows() + 2) * v.cwiseAbs().dot(d.P.cwiseAbs() * v.cwiseAbs());
    mx = std::max(mx, q * rel);
  }
  return std::max(1.0, round_up(round_up(mx) / d.cbar));
}

/// The 2ⁿ corners of the box [lo, hi] as columns (for mu0_from_vertices with E_0 = [x_0] − x̂_0).
inline Eigen::MatrixXd box_corners(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  require_finite(lo, "lo");
  require_finite(hi, "hi");
  if (lo.size() != hi.size() || lo.size() == 0 || lo.size() > 20) throw DimensionError("hi: expected the size of lo (1..20)");
  if ((hi.array() < lo.array()).any()) throw InvalidArgumentError("hi: must be >= lo componentwise");
  const Eigen::Index n = lo.size();
  Eigen::MatrixXd V(n, Eigen::Index(1) << n);
  for (Eigen::Index j = 0; j < V.cols(); ++j)
    for (Eigen::Index i = 0; i < n; ++i) V(i, j) = ((j >> i) & 1) ? hi(i) : lo(i);
  return V;
}

namespace hinf_detail {

inline double up(double x) { return std::nextafter(x, std::numeric_limits<double>::infinity()); }
inline double down(double x) { return std::nextafter(x, -std::numeric_limits<double>::infinity()); }

/// Shared online state: x̂, μ and the output box. The level update includes the centre error d.
struct SMState {
  Eigen::VectorXd xhat, xnext, d, lower, upper, e_inf;
  double mu = 1, lambda = 0, cbar = 0, lambda_max_P = 0, one_minus_lambda = 0;
  long k = 0;

  void init(const EllipsoidalSMDesign& des, const Eigen::VectorXd& xhat0, double mu0) {
    const Eigen::Index n = des.P.rows();
    require_shape(xhat0, n, 1, "xhat0");
    require_finite(xhat0, "xhat0");
    require_positive(mu0, "mu0");
    xhat = xhat0;
    xnext.resize(n);
    d.resize(n);
    lower.resize(n);
    upper.resize(n);
    e_inf = des.e_inf;
    lambda = des.lambda;
    cbar = des.cbar;
    lambda_max_P = des.lambda_max_P;
    one_minus_lambda = ell_rounding::round_up(1.0 - lambda);
    mu = mu0;
    k = 0;
    update_box();
  }
  /// μ⁺ = (1 − λ)μ + λ, then the level μ⁺c̄ enlarged for the centre error d (already in `d`).
  void advance() {
    using ell_rounding::round_up;
    double mu1 = round_up(round_up(one_minus_lambda * mu) + lambda);
    const double lvl = level_with_center_error(round_up(mu1 * cbar), lambda_max_P, d);
    mu = round_up(lvl / cbar);
    if (mu < mu1) mu = mu1;
    xhat.swap(xnext);
    ++k;
    update_box();
  }
  void save(StateWriter& w) const { w.count(k).vec(xhat).scalar(mu); }
  /// Reads k, x̂, μ (validated) into this state; call on a copy or after all other reads.
  static void read(StateReader& r, Eigen::Index n, long& k_out, Eigen::VectorXd& xhat_out, double& mu_out) {
    k_out = static_cast<long>(r.count("steps"));
    xhat_out = r.vec(n, "xhat");
    mu_out = r.scalar("mu");
    if (!(mu_out > 0)) r.fail("mu must be positive");
  }
  /// Commits a state read by read(): no allocation (x̂ is moved in, the box has its size), so
  /// it cannot throw and a restore is all-or-nothing.
  void apply(long k_in, Eigen::VectorXd&& xhat_in, double mu_in) noexcept {
    k = k_in;
    xhat = std::move(xhat_in);
    mu = mu_in;
    update_box();
  }
  void update_box() {
    using ell_rounding::round_up;
    const double s = round_up(std::sqrt(mu));
    for (Eigen::Index i = 0; i < xhat.size(); ++i) {
      const double r = round_up(e_inf(i) * s);
      lower(i) = down(xhat(i) - r);
      upper(i) = up(xhat(i) + r);
    }
  }
};

inline void check_vec(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Index n, const char* name) {
  if (v.size() != n)
    throw DimensionError(std::string(name) + ": expected " + std::to_string(n) + " entries, got " + std::to_string(v.size()));
  for (Eigen::Index i = 0; i < n; ++i)
    if (!std::isfinite(v(i)))
      throw NotFiniteError(std::string(name) + ": entry " + std::to_string(i) + " is not finite");
}

}  // namespace hinf_detail

/// Online observer (2.68–2.71): x̂⁺ = (A − LC)x̂ + Bu + Ly, μ⁺ = (1 − λ)μ + λ,
/// box x̂ ± ē∞√μ. A one-step predictor: after k steps the box bounds x_k (it used y_0..y_{k−1}).
/// step() does not allocate.
class EllipsoidalSMObserver {
 public:
  EllipsoidalSMObserver(const Plant& plant, EllipsoidalSMDesign design, const Eigen::VectorXd& xhat0, double mu0)
      : design_(std::move(design)) {
    const Eigen::Index n = plant.nx();
    if (design_.P.rows() != n || design_.L.rows() != n || design_.L.cols() != plant.ny())
      throw DimensionError("design: its P and L do not match the plant (n_x = " + std::to_string(n) + ")");
    Ao_ = plant.A - design_.L * plant.C;
    B_ = plant.B;
    L_ = design_.L;
    // Rounding of Ao (γ_{ny+2}(|A| + |L||C|)) and of the products (γ_k): |x̂⁺ − exact| ≤ Ma|x̂| + Mb|u| + Ml|y|.
    const double gk = ell_rounding::gamma(n + plant.nu() + plant.ny() + 4);
    const double ga = ell_rounding::gamma(plant.ny() + 2);
    Ma_ = 2.0 * (gk * Ao_.cwiseAbs() + ga * (plant.A.cwiseAbs() + L_.cwiseAbs() * plant.C.cwiseAbs()));
    Mb_ = 2.0 * gk * B_.cwiseAbs();
    Ml_ = 2.0 * gk * L_.cwiseAbs();
    tmp_.resize(n);
    tmpu_.resize(plant.nu());
    tmpy_.resize(plant.ny());
    st_.init(design_, xhat0, mu0);
  }

  void step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
    hinf_detail::check_vec(y, L_.cols(), "y");
    hinf_detail::check_vec(u, B_.cols(), "u");
    st_.xnext.noalias() = Ao_ * st_.xhat;
    if (B_.cols() > 0) st_.xnext.noalias() += B_ * u;
    st_.xnext.noalias() += L_ * y;
    tmp_ = st_.xhat.cwiseAbs();
    st_.d.noalias() = Ma_ * tmp_;
    if (B_.cols() > 0) {
      tmpu_ = u.cwiseAbs();
      st_.d.noalias() += Mb_ * tmpu_;
    }
    tmpy_ = y.cwiseAbs();
    st_.d.noalias() += Ml_ * tmpy_;
    st_.advance();
  }

  /// Full mutable state (core/state.hpp): x̂_k, μ_k and k (the box follows from them).
  std::vector<double> save_state() const {
    StateWriter w(StateKind::EllipsoidalSMObserver, fingerprint());
    st_.save(w);
    return w.finish();
  }
  /// Restores a state from save_state() (same plant and design); throws InvalidArgumentError
  /// ("state: ...") otherwise. Unchanged on error.
  void restore_state(const std::vector<double>& state) {
    long k = 0;
    Eigen::VectorXd xhat;
    double mu = 0;
    guard_state_memory(StateKind::EllipsoidalSMObserver, [&] {
      StateReader r(state, StateKind::EllipsoidalSMObserver, fingerprint());
      hinf_detail::SMState::read(r, Ao_.rows(), k, xhat, mu);
      r.finish();
    });
    st_.apply(k, std::move(xhat), mu);  // moves and writes into sized buffers: cannot throw
  }
  StateFingerprint fingerprint() const {
    StateFingerprint f;
    f.add(Ao_).add(B_).add(L_).add(Ma_).add(design_.P).add(design_.e_inf).add(design_.lambda).add(design_.cbar);
    f.add(design_.lambda_max_P);
    return f;
  }

  void reset(const Eigen::VectorXd& xhat0, double mu0) { st_.init(design_, xhat0, mu0); }

  const Eigen::VectorXd& center() const { return st_.xhat; }
  const Eigen::VectorXd& lower() const { return st_.lower; }
  const Eigen::VectorXd& upper() const { return st_.upper; }
  double mu() const { return st_.mu; }
  long steps() const { return st_.k; }
  const EllipsoidalSMDesign& design() const { return design_; }

 private:
  EllipsoidalSMDesign design_;
  Eigen::MatrixXd Ao_, B_, L_, Ma_, Mb_, Ml_;
  Eigen::VectorXd tmp_, tmpu_, tmpy_;
  hinf_detail::SMState st_;
};

}  // namespace setbound::thesis
