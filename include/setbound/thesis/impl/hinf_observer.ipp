// setbound — definitions of the functions declared in setbound/thesis/hinf_observer.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/thesis/hinf_observer.hpp"
#include "setbound/core/config.hpp"

#include "setbound/thesis/interval_observer.hpp"  // iobs_detail::certified_rate (the missing-output step)

namespace setbound {
namespace thesis {
namespace hinf_detail {

SETBOUND_INLINE void require_wbar(const Eigen::VectorXd& wbar, Eigen::Index m) {
  if (wbar.size() != m)
    throw DimensionError("wbar: expected " + std::to_string(m) + " entries (m = n_d + n_v), got " +
                         std::to_string(wbar.size()));
  require_finite(wbar, "wbar");
  if ((wbar.array() < 0).any()) throw InvalidArgumentError("wbar: the bounds must be >= 0");
}

/// The computed inverse X of P ≻ 0 and a bound err ≥ ‖P⁻¹ − X‖₂ (r ≥ ‖I − P X‖ with the
/// rounding of the product, err = ‖X‖ r/(1 − r)); `what` names the quantity in the error.
SETBOUND_INLINE Eigen::MatrixXd inverse_with_error(const Eigen::MatrixXd& P, double& err, const char* what) {
  const Eigen::Index n = P.rows();
  Eigen::LLT<Eigen::MatrixXd> llt(P);
  if (llt.info() != Eigen::Success) throw NotPositiveDefiniteError("P: matrix is not positive definite");
  Eigen::MatrixXd X = llt.solve(Eigen::MatrixXd::Identity(n, n));
  symmetrize(X);
  const Eigen::MatrixXd R = Eigen::MatrixXd::Identity(n, n) - P * X;
  const double r = R.norm() + ell_rounding::gamma(n + 2) * P.norm() * X.norm();
  if (!(r < 0.5)) throw NumericalError(std::string("P: too ill-conditioned to bound ") + what + " reliably");
  err = X.norm() * r / (1.0 - r);
  return X;
}

SETBOUND_INLINE Eigen::VectorXd inverse_diagonal_upper(const Eigen::MatrixXd& P) {
  const Eigen::Index n = P.rows();
  double err = 0;
  const Eigen::MatrixXd X = inverse_with_error(P, err, "diag(P^-1)");
  const double eps = ell_rounding::kEps;
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i) d(i) = ell_rounding::round_up(X(i, i) + err + eps * std::abs(X(i, i)));
  return d;
}

SETBOUND_INLINE void finish_design(EllipsoidalSMDesign& d) {
  using ell_rounding::round_up;
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
  const Eigen::Index n = d.P.rows();
  d.e_inf.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) d.e_inf(i) = round_up(std::sqrt(round_up(d.cbar * di(i))));
  d.lambda_max_P = lambda_max_up(d.P);
}

SETBOUND_INLINE double lambda_min_certified(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& P) {
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

SETBOUND_INLINE double certify_lambda(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
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

SETBOUND_INLINE Normalised normalise(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
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

SETBOUND_INLINE void add_normalised_lmis(lmi::Model& model, const lmi::AffineExpr& Qt, const Normalised& z, double margin) {
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

SETBOUND_INLINE Eigen::MatrixXd refine_q(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
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

SETBOUND_INLINE double direct_lambda(const Eigen::MatrixXd& P, const std::vector<Eigen::MatrixXd>& Aos,
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

SETBOUND_INLINE Eigen::MatrixXd discrete_lyapunov(const Eigen::MatrixXd& A, const Eigen::MatrixXd& W) {
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
}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {

SETBOUND_INLINE ErrorRpi ellipsoidal_error_rpi(const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q, double g,
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

SETBOUND_INLINE Eigen::MatrixXd refine_dissipation_matrix(const Plant& plant, const HinfGain& gain, const HinfOptions& opt) {
  opt.validate();
  require_shape(gain.L, plant.nx(), plant.ny(), "L");
  require_positive_definite(gain.P, "P");
  return hinf_detail::refine_q(gain.P, {Eigen::MatrixXd(plant.A - gain.L * plant.C)}, {plant.error_input(gain.L)},
                               gain.g, opt);
}

SETBOUND_INLINE double direct_dissipation_lambda(const Plant& plant, const HinfGain& gain, const HinfOptions& opt) {
  opt.validate();
  require_shape(gain.L, plant.nx(), plant.ny(), "L");
  return hinf_detail::direct_lambda(gain.P, {Eigen::MatrixXd(plant.A - gain.L * plant.C)}, {plant.error_input(gain.L)},
                                    gain.g, opt);
}

SETBOUND_INLINE Eigen::MatrixXd uniform_covariance(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  require_finite(lo, "lo");
  require_finite(hi, "hi");
  if (lo.size() != hi.size()) throw DimensionError("hi: expected the size of lo");
  if ((hi.array() < lo.array()).any()) throw InvalidArgumentError("hi: must be >= lo componentwise");
  return ((hi - lo).array().square() / 12.0).matrix().asDiagonal();
}

SETBOUND_INLINE CovarianceDissipation covariance_dissipation_matrix(const std::vector<Eigen::MatrixXd>& Aos,
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
  symmetrize(c.Q);
  return c;
}

SETBOUND_INLINE CovarianceDissipation covariance_dissipation_matrix(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& E,
                                                           const Eigen::MatrixXd& W) {
  return covariance_dissipation_matrix(std::vector<Eigen::MatrixXd>{Ao}, std::vector<Eigen::MatrixXd>{E}, W);
}

SETBOUND_INLINE ChebyshevEllipsoid chebyshev_error_ellipsoid(const Eigen::MatrixXd& V, double t) {
  require_positive_definite(V, "V");
  require_positive(t, "t");
  ChebyshevEllipsoid c;
  c.shape = V.llt().solve(Eigen::MatrixXd::Identity(V.rows(), V.cols()));
  c.level = t * t;
  c.probability_lower = std::max(0.0, 1.0 - static_cast<double>(V.rows()) / (t * t));
  return c;
}

SETBOUND_INLINE void EllipsoidalSMOptions::validate() const {
  hinf.validate();
  if (passes < 1) throw InvalidArgumentError("passes: must be >= 1");
}

SETBOUND_INLINE EllipsoidalSMDesign design_ellipsoidal_sm_observer(const Plant& plant, const Eigen::VectorXd& wbar,
                                                          const EllipsoidalSMOptions& opt) {
  opt.validate();
  hinf_detail::require_detectable(plant.A, plant.C, opt.hinf.detectability_tol, "A, C");
  return hinf_detail::design_vertices({plant.A}, {plant.F}, plant.C, plant.Z, wbar, opt, [&](const Eigen::MatrixXd& Q) {
    return hinf_detail::hinf_vertex_gains({plant.A}, {plant.F}, plant.C, plant.Z, Q, opt.hinf,
                                          "design_ellipsoidal_sm_observer", false);
  });
}

SETBOUND_INLINE double mu0_from_ball(const EllipsoidalSMDesign& d, double radius) {
  require_nonnegative(radius, "radius");
  using ell_rounding::round_up;
  return std::max(1.0, round_up(round_up(d.lambda_max_P * round_up(radius * radius)) / d.cbar));
}

SETBOUND_INLINE double mu0_from_vertices(const EllipsoidalSMDesign& d, const Eigen::MatrixXd& vertices) {
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

SETBOUND_INLINE Eigen::MatrixXd box_corners(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  require_finite(lo, "lo");
  require_finite(hi, "hi");
  if (lo.size() != hi.size())
    throw DimensionError("hi: expected length " + std::to_string(lo.size()) + " (the length of lo), got " +
                         std::to_string(hi.size()));
  if (lo.size() == 0 || lo.size() > 20)
    throw DimensionError("lo: the box's 2^n corners are enumerated for 1 <= n <= 20, got n = " +
                         std::to_string(lo.size()) + " (mu0_from_box bounds larger boxes)");
  if ((hi.array() < lo.array()).any()) throw InvalidArgumentError("hi: must be >= lo componentwise");
  const Eigen::Index n = lo.size();
  Eigen::MatrixXd V(n, Eigen::Index(1) << n);
  for (Eigen::Index j = 0; j < V.cols(); ++j)
    for (Eigen::Index i = 0; i < n; ++i) V(i, j) = ((j >> i) & 1) ? hi(i) : lo(i);
  return V;
}

SETBOUND_INLINE double mu0_from_box(const EllipsoidalSMDesign& d, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  const Eigen::Index n = d.P.rows();
  if (lo.size() != n) throw DimensionError("lo: expected length " + std::to_string(n) + ", got " + std::to_string(lo.size()));
  if (hi.size() != n) throw DimensionError("hi: expected length " + std::to_string(n) + ", got " + std::to_string(hi.size()));
  require_finite(lo, "lo");
  require_finite(hi, "hi");
  if ((hi.array() < lo.array()).any()) throw InvalidArgumentError("hi: must be >= lo componentwise");
  if (n <= 20) return mu0_from_vertices(d, box_corners(lo, hi));
  // 2ⁿ corners are too many: vᵀPv <= |v|ᵀ|P||v| <= rᵀ|P|r for every v in the box (|v| <= r).
  using ell_rounding::round_up;
  const Eigen::VectorXd r = lo.cwiseAbs().cwiseMax(hi.cwiseAbs());
  const double q = r.dot(d.P.cwiseAbs() * r);
  const double q_up = round_up(q * (1.0 + 2.0 * ell_rounding::gamma(n + 2)));  // sums of non-negative terms
  const double by_abs = std::max(1.0, round_up(q_up / d.cbar));
  const double by_ball = mu0_from_ball(d, round_up(std::sqrt(round_up(r.squaredNorm() * (1.0 + 2.0 * ell_rounding::gamma(n + 1))))));
  return std::min(by_abs, by_ball);
}

}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {
namespace hinf_detail {

SETBOUND_INLINE double up(double x) { return std::nextafter(x, std::numeric_limits<double>::infinity()); }

SETBOUND_INLINE double down(double x) { return std::nextafter(x, -std::numeric_limits<double>::infinity()); }

SETBOUND_INLINE void SMState::init(const EllipsoidalSMDesign& des, const Eigen::VectorXd& xhat0, double mu0) {
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

SETBOUND_INLINE void SMState::advance() {
  using ell_rounding::round_up;
  double mu1 = round_up(round_up(one_minus_lambda * mu) + lambda);
  const double lvl = level_with_center_error(round_up(mu1 * cbar), lambda_max_P, d);
  mu = round_up(lvl / cbar);
  if (mu < mu1) mu = mu1;
  xhat.swap(xnext);
  ++k;
  update_box();
}

SETBOUND_INLINE void SMState::save(StateWriter& w) const { w.count(k).vec(xhat).scalar(mu); }

SETBOUND_INLINE void SMState::read(StateReader& r, Eigen::Index n, long& k_out, Eigen::VectorXd& xhat_out, double& mu_out) {
  k_out = static_cast<long>(r.count("steps"));
  xhat_out = r.vec(n, "xhat");
  mu_out = r.scalar("mu");
  if (!(mu_out > 0)) r.fail("mu must be positive");
}

SETBOUND_INLINE void SMState::apply(long k_in, Eigen::VectorXd&& xhat_in, double mu_in) noexcept {
  k = k_in;
  xhat = std::move(xhat_in);
  mu = mu_in;
  update_box();
}

SETBOUND_INLINE void SMState::update_box() {
  using ell_rounding::round_up;
  const double s = round_up(std::sqrt(mu));
  for (Eigen::Index i = 0; i < xhat.size(); ++i) {
    const double r = round_up(e_inf(i) * s);
    lower(i) = down(xhat(i) - r);
    upper(i) = up(xhat(i) + r);
  }
}

SETBOUND_INLINE Eigen::VectorXd output_gram_upper(const Eigen::MatrixXd& P, const Eigen::MatrixXd& C) {
  const Eigen::Index n = P.rows();
  double err = 0;
  const Eigen::MatrixXd X = inverse_with_error(P, err, "C P^-1 C^T");
  const Eigen::MatrixXd Xabs = X.cwiseAbs();
  Eigen::VectorXd q(C.rows());
  for (Eigen::Index i = 0; i < C.rows(); ++i) {
    const Eigen::VectorXd c = C.row(i).transpose();
    const double v = c.dot(X * c) + ell_rounding::gamma(2 * n + 2) * c.cwiseAbs().dot(Xabs * c.cwiseAbs());
    q(i) = ell_rounding::round_up(std::max(v, 0.0) + err * c.squaredNorm() * (1.0 + ell_rounding::gamma(n + 1)));
  }
  return q;
}

SETBOUND_INLINE double mu_from_box(const EllipsoidalSMDesign& d, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                                   const Eigen::VectorXd& xhat) {
  const Eigen::Index n = xhat.size();
  Eigen::VectorXd elo(n), ehi(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    elo(i) = rounding::sub_down(lo(i), xhat(i));
    ehi(i) = rounding::sub_up(hi(i), xhat(i));
  }
  if (n <= 12) return mu0_from_vertices(d, box_corners(elo, ehi));
  // vᵀPv ≤ |v|ᵀ|P||v| ≤ rᵀ|P|r for every v in the box
  const Eigen::VectorXd r = elo.cwiseAbs().cwiseMax(ehi.cwiseAbs());
  const double q = r.dot(d.P.cwiseAbs() * r) * (1.0 + ell_rounding::gamma(2 * n + 2));
  using ell_rounding::round_up;
  return std::max(1.0, round_up(round_up(q) / d.cbar));
}

SETBOUND_INLINE void SMReadings::init(const EllipsoidalSMDesign& des, const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z,
                                      const SMState& st) {
  const Eigen::Index nv = Z.cols(), nd = des.wbar.size() - nv;
  qC = output_gram_upper(des.P, C);
  const Eigen::VectorXd wd = des.wbar.head(nd), wv = des.wbar.tail(nv);
  d = Box(-wd, wd, "d");
  v = Box(-wv, wv, "v");
  Zabs = Z.cwiseAbs();
  screen.init(C.rows(), Box(st.lower, st.upper, "x0"));
  const double lm = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(des.P, Eigen::EigenvaluesOnly).eigenvalues().minCoeff();
  const double low = lm - 8.0 * static_cast<double>(des.P.rows()) * ell_rounding::kEps * des.P.norm();
  lambda_min_P = low > 0 ? low : 0.0;
}

SETBOUND_INLINE bool SMReadings::screen_step(const SMState& st, const Eigen::MatrixXd& C,
                                             const Eigen::Ref<const Eigen::VectorXd>& y) {
  using ell_rounding::round_up;
  const Eigen::Index ny = C.rows(), n = C.cols();
  const double level = round_up(st.mu * st.cbar);
  for (Eigen::Index i = 0; i < ny; ++i) {
    double c = 0, mag = 0;
    for (Eigen::Index j = 0; j < n; ++j) {
      c += C(i, j) * st.xhat(j);
      mag += std::abs(C(i, j) * st.xhat(j));
    }
    const double rad = round_up(std::sqrt(round_up(level * qC(i))));
    const double ph = Zabs.row(i).dot(v.hi());
    screen.center(i) = c;  // v is centred: Z_i mid(v) = 0
    screen.radius(i) = rad;
    screen.phi(i) = ph;
    screen.magnitude(i) = mag + rad + ph;
  }
  const bool all = screen.screen(y, n + Zabs.cols() + 4);
  if (!all && screen.policy == OnInconsistency::Raise) screen.raise_first(st.k, y);
  return all;
}

SETBOUND_INLINE void SMReadings::fallback_step(SMState& st, const EllipsoidalSMDesign& des, const Eigen::MatrixXd& A,
                                               const Eigen::MatrixXd& B, const Eigen::MatrixXd& F,
                                               const Eigen::MatrixXd& C, const Eigen::MatrixXd& Z,
                                               const Eigen::Ref<const Eigen::VectorXd>& y,
                                               const Eigen::Ref<const Eigen::VectorXd>& u,
                                               const screen_detail::ModelWidening* widen, const Eigen::MatrixXd* L) {
  using ell_rounding::round_up;
  Eigen::VectorXd lo = st.lower, hi = st.upper;
  const MeasurementCheck use = screen_detail::apply_reset(screen, C, Z, v, y, lo, hi);
  const Box next = screen_detail::fallback_prediction(A, B, F, C, Z, lo, hi, y, u, d, v, use, Box(), widen);
  Eigen::VectorXd xh = next.mid();
  double mu = mu_from_box(des, next.lo(), next.hi(), xh);
  if (L != nullptr && !screen.check.reset && lambda_min_P > 0) {
    // (b): the Luenberger step with G = L on the outputs used
    const Eigen::Index n = A.rows(), ny = C.rows(), nu = B.cols();
    Eigen::MatrixXd G = *L;
    Eigen::VectorXd ys = Eigen::VectorXd::Zero(ny);
    for (Eigen::Index i = 0; i < ny; ++i) {
      if (use.status[std::size_t(i)] == OutputStatus::Used) ys(i) = y(i);
      else G.col(i).setZero();
    }
    const Eigen::MatrixXd Ao = A - G * C;
    const Eigen::MatrixXd T = 2.0 * ell_rounding::gamma(ny + 2) * (A.cwiseAbs() + G.cwiseAbs() * C.cwiseAbs());
    double alpha = -1;
    try {
      alpha = iobs_detail::certified_rate(Ao, des.P, "L");
    } catch (const NumericalError&) {
      alpha = -1;  // not certified: keep (a)
    }
    if (alpha >= 0) {
      const double kappa = std::sqrt(round_up(des.lambda_max_P / lambda_min_P)) * (1.0 + 4 * ell_rounding::kEps);
      alpha = round_up(alpha + round_up(kappa * round_up(T.norm())));
      // Σ_j w̄_j ‖col_j‖_P of E = [F, −G Z] (its rounding through √λ_max(P))
      const Eigen::Index nd = F.cols(), nv = Z.cols();
      const double slm = round_up(std::sqrt(des.lambda_max_P));
      double delta = 0;
      for (Eigen::Index j = 0; j < nd + nv; ++j) {
        const double wj = des.wbar(j);
        if (wj == 0) continue;
        Eigen::VectorXd c(n), cerr = Eigen::VectorXd::Zero(n);
        if (j < nd) {
          c = F.col(j);
        } else {
          c = -G * Z.col(j - nd);
          cerr = 2.0 * ell_rounding::gamma(ny + 2) * (G.cwiseAbs() * Zabs.col(j - nd));
        }
        const double q = c.dot(des.P * c) + ell_rounding::gamma(2 * n + 2) * c.cwiseAbs().dot(des.P.cwiseAbs() * c.cwiseAbs());
        const double cn = round_up(std::sqrt(std::max(q, 0.0))) + round_up(slm * round_up(cerr.norm()));
        delta = round_up(delta + round_up(wj * cn));
      }
      // the centre x̂⁺ = A x̂ + B u + G(y_S − C x̂) and a bound of its rounding error
      Eigen::VectorXd xc = A * st.xhat + G * (ys - C * st.xhat);
      Eigen::VectorXd dm = A.cwiseAbs() * st.xhat.cwiseAbs() + G.cwiseAbs() * (ys.cwiseAbs() + C.cwiseAbs() * st.xhat.cwiseAbs());
      if (nu > 0) {
        xc += B * u;
        dm += B.cwiseAbs() * u.cwiseAbs();
      }
      const double cerr = round_up(slm * round_up((2.0 * ell_rounding::gamma(n + nu + 2 * ny + 4) * dm).norm()));
      const double s = round_up(round_up(alpha * round_up(std::sqrt(round_up(st.mu * st.cbar)))) + delta + cerr);
      const double mu_b = round_up(round_up(s * s) / st.cbar);
      if (xc.allFinite() && std::isfinite(mu_b) && mu_b < mu) {
        mu = mu_b;
        xh = std::move(xc);
      }
    }
  }
  st.apply(st.k + 1, std::move(xh), mu);
}

SETBOUND_INLINE void check_vec(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Index n, const char* name) {
  if (v.size() != n)
    throw DimensionError(std::string(name) + ": expected " + std::to_string(n) + " entries, got " + std::to_string(v.size()));
  for (Eigen::Index i = 0; i < n; ++i)
    if (!std::isfinite(v(i)))
      throw NotFiniteError(std::string(name) + ": entry " + std::to_string(i) + " is not finite");
}

}  // namespace hinf_detail
}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {

SETBOUND_INLINE EllipsoidalSMObserver::EllipsoidalSMObserver(const Plant& plant, EllipsoidalSMDesign design, const Eigen::VectorXd& xhat0, double mu0)
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
  A_ = plant.A;
  C_ = plant.C;
  F_ = plant.F;
  Z_ = plant.Z;
  tmp_.resize(n);
  tmpu_.resize(plant.nu());
  tmpy_.resize(plant.ny());
  st_.init(design_, xhat0, mu0);
  rd_.init(design_, C_, Z_, st_);
}

SETBOUND_INLINE void EllipsoidalSMObserver::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  if (y.size() != L_.cols())
    throw DimensionError("y: expected " + std::to_string(L_.cols()) + " entries, got " + std::to_string(y.size()));
  require_no_infinity(y, "y");
  hinf_detail::check_vec(u, B_.cols(), "u");
  if (!rd_.screen_step(st_, C_, y)) {  // may throw (policy Raise): nothing changed yet
    rd_.fallback_step(st_, design_, A_, B_, F_, C_, Z_, y, u, nullptr, &L_);
    return;
  }
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

SETBOUND_INLINE std::vector<double> EllipsoidalSMObserver::save_state() const {
  StateWriter w(StateKind::EllipsoidalSMObserver, fingerprint());
  st_.save(w);
  return w.finish();
}

SETBOUND_INLINE void EllipsoidalSMObserver::restore_state(const std::vector<double>& state) {
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

SETBOUND_INLINE StateFingerprint EllipsoidalSMObserver::fingerprint() const {
  StateFingerprint f;
  f.add(Ao_).add(B_).add(L_).add(Ma_).add(design_.P).add(design_.e_inf).add(design_.lambda).add(design_.cbar);
  f.add(design_.lambda_max_P);
  return f;
}

}  // namespace thesis
}  // namespace setbound
