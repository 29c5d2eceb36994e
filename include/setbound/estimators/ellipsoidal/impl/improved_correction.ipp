// setbound — definitions of the functions declared in setbound/estimators/ellipsoidal/improved_correction.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/ellipsoidal/improved_correction.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE void ImprovedCorrectionOptions::validate(CorrectionOption option) const {
  require_positive(margin, "margin");
  if (margin > 1e-3) throw InvalidArgumentError("margin: must be <= 1e-3 (it is relative to the unit prior ball)");
  if (tau_at_most_one && option == CorrectionOption::DetNormalized)
    throw InvalidArgumentError(
        "tau_at_most_one: tau <= 1 is not homogeneous and cannot be combined with the DetNormalized "
        "rescaling; use level_at_least_tau_rho, or FixedShape / BallNormalized");
  solver.validate();
}

}  // namespace setbound

namespace setbound {
namespace detail {

SETBOUND_INLINE Eigen::MatrixXd symmetrized(const Eigen::MatrixXd& M) {
  Eigen::MatrixXd S(M.rows(), M.cols());
  for (Eigen::Index j = 0; j < M.cols(); ++j)
    for (Eigen::Index i = j; i < M.rows(); ++i) S(i, j) = S(j, i) = 0.5 * (M(i, j) + M(j, i));
  return S;
}

SETBOUND_INLINE double frobenius_up(const Eigen::MatrixXd& M) { return ell_rounding::round_up(M.norm() * (1.0 + 1e-15)); }

SETBOUND_INLINE bool certify_psd_scaled(const Eigen::MatrixXd& M, const Eigen::MatrixXd& Err) {
  const Eigen::Index n = M.rows();
  Eigen::VectorXd D(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(M(i, i) > 0) || !std::isfinite(M(i, i))) return false;
    int e = 0;
    (void)std::frexp(std::sqrt(M(i, i)), &e);
    D(i) = std::ldexp(1.0, -e);
  }
  const Eigen::MatrixXd Ms = D.asDiagonal() * M * D.asDiagonal();
  const Eigen::MatrixXd Es = D.asDiagonal() * Err * D.asDiagonal();
  return certify_psd(Ms, frobenius_up(Es));
}

SETBOUND_INLINE Eigen::VectorXd accurate_innovation(const Eigen::VectorXd& y, const Eigen::MatrixXd& C, const Eigen::VectorXd& c,
                                           const Eigen::MatrixXd& D, const Eigen::VectorXd& u, Eigen::VectorXd& eps) {
  using ell_rounding::round_up;
  const Eigen::Index ny = y.size();
  const Eigen::Index N = 1 + C.cols() + (u.size() > 0 ? D.cols() : 0);
  const double gN = ell_rounding::gamma(N);
  Eigen::VectorXd e(ny);
  eps.resize(ny);
  for (Eigen::Index i = 0; i < ny; ++i) {
    double s = y(i), err = 0.0, mag = std::abs(y(i));
    auto add = [&](double a, double b) {  // s + err += a·b
      const double h = a * b;
      const double l = std::fma(a, b, -h);  // a·b = h + l exactly
      const double t = s + h;               // TwoSum(s, h)
      const double z = t - s;
      const double q = (s - (t - z)) + (h - z);
      s = t;
      err += q + l;
      mag += std::abs(h);
    };
    for (Eigen::Index j = 0; j < C.cols(); ++j) add(-C(i, j), c(j));
    if (u.size() > 0)
      for (Eigen::Index j = 0; j < D.cols(); ++j) add(-D(i, j), u(j));
    e(i) = s + err;
    eps(i) = round_up(2.0 * (ell_rounding::kEps / 2) * std::abs(e(i)) + 2.0 * gN * gN * round_up(mag * (1.0 + gN)) +
                      std::numeric_limits<double>::denorm_min());
  }
  return e;
}

SETBOUND_INLINE bool certify_improved(ImprovedCertificate& k, const Ellipsoid& pred, const Eigen::VectorXd& y,
                             const Eigen::VectorXd& u, const LinearSystem& sys) {
  using ell_rounding::gamma;
  using ell_rounding::round_up;
  const Eigen::Index n = sys.nx(), ny = sys.ny(), nw = sys.nw();
  const Eigen::MatrixXd& P = pred.shape();
  const Eigen::VectorXd& c = pred.center();
  const double rho = pred.level();
  const Eigen::MatrixXd& C = sys.C();
  const Eigen::MatrixXd& F = sys.F();
  if (!k.Pp.allFinite() || !k.d.allFinite() || !k.H.allFinite() || !k.mu.allFinite() || !std::isfinite(k.tau) ||
      !std::isfinite(k.rho))
    return false;
  if (k.tau < 0 || (k.mu.array() < 0).any() || k.rho < 0) return false;
  if ((k.Pp - k.Pp.transpose()).cwiseAbs().maxCoeff() != 0.0) return false;
  if ((k.H - k.H.transpose()).cwiseAbs().maxCoeff() != 0.0) return false;
  // P' ≻ 0 (certify_psd subtracts a positive δ, so success is strict).
  if (!certify_psd_scaled(k.Pp, Eigen::MatrixXd::Zero(n, n))) return false;

  // Innovation e₀ = y − D u − C c (compensated) and a componentwise bound ε of its rounding.
  Eigen::VectorXd eps;
  const Eigen::VectorXd e0 = accurate_innovation(y, C, c, sys.D(), u, eps);
  // w = fl(P' d), |w − P'd| ≤ γ_{n+1} |P'||d| componentwise.
  const Eigen::VectorXd w = k.Pp * k.d;
  const Eigen::VectorXd w_err = round_up(gamma(n + 1)) * (k.Pp.cwiseAbs() * k.d.cwiseAbs());

  const Eigen::MatrixXd HC = k.H * C;  // ny × n
  const Eigen::MatrixXd aH = k.H.cwiseAbs(), aC = C.cwiseAbs();
  const Eigen::VectorXd ae0 = e0.cwiseAbs();
  const double smu = k.mu.sum();
  // Every entry of (L) is a sum of at most 2 n_y + n_ω + 4 products of ≤ 3 factors.
  const double g = round_up(gamma(2 * ny + nw + 8));
  const Eigen::Index N = 2 * n + 1;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(N, N), Err = Eigen::MatrixXd::Zero(N, N);
  M.topLeftCorner(n, n) = k.tau * P + C.transpose() * HC;
  Err.topLeftCorner(n, n) = g * (k.tau * P.cwiseAbs() + aC.transpose() * aH * aC);
  const Eigen::RowVectorXd m21 = -(e0.transpose() * HC);
  M.block(n, 0, 1, n) = m21;
  M.block(0, n, n, 1) = m21.transpose();
  // forming, plus the innovation error δ (|δ| ≤ ε): Δ(2,1) = −δᵀ H C.
  const Eigen::RowVectorXd err21 = g * (ae0.transpose() * aH * aC) + eps.transpose() * aH * aC;
  Err.block(n, 0, 1, n) = err21;
  Err.block(0, n, n, 1) = err21.transpose();
  M(n, n) = k.rho - k.tau * rho - smu + e0.dot(k.H * e0);
  // forming, plus Δ(2,2) = 2 e₀ᵀ H δ + δᵀ H δ.
  Err(n, n) = g * (k.rho + k.tau * rho + smu + ae0.dot(aH * ae0)) + 2.0 * ae0.dot(aH * eps) + eps.dot(aH * eps);
  M.block(n + 1, 0, n, n) = k.Pp;
  M.block(0, n + 1, n, n) = k.Pp;
  M.block(n + 1, n, n, 1) = -w;
  M.block(n, n + 1, 1, n) = -w.transpose();
  Err.block(n + 1, n, n, 1) = w_err;
  Err.block(n, n + 1, 1, n) = w_err.transpose();
  M.block(n + 1, n + 1, n, n) = k.Pp;
  if (!M.allFinite() || !Err.allFinite()) return false;
  // The (2,2) entry is a sum of O(ρ) terms that cancel down to about margin·ρ, so its rounding
  // bound is the largest part of Err after scaling. When the certificate fails, raise ρ' (which
  // only adds to that entry) in steps of 8·4^j times its error bound, up to 1e-4 (ρ' + τρ).
  const double rho_cap = 1e-4 * (k.rho + k.tau * rho);
  double bump = 0;
  for (int j = 0;; ++j) {
    if (certify_psd_scaled(M, Err * (1.0 + 1e-12))) break;
    const double step = round_up(8.0 * std::pow(4.0, j) * Err(n, n));
    if (!(step > 0) || bump + step > rho_cap) return false;
    bump += step;
    M(n, n) += step;
    Err(n, n) = round_up(Err(n, n) + g * step);
  }
  if (bump > 0) k.rho = round_up(k.rho + bump);

  // (C1): diag(μ) − Fᵀ H F ⪰ 0. A zero column j of F gives a zero row and column (μ_j = 0 is
  // then required and enough), so the check runs on the non-zero columns.
  std::vector<Eigen::Index> cols;
  for (Eigen::Index j = 0; j < nw; ++j) {
    if ((F.col(j).array() != 0.0).any()) cols.push_back(j);
    else if (k.mu(j) != 0.0) return false;
  }
  if (!cols.empty()) {
    const Eigen::Index kc = static_cast<Eigen::Index>(cols.size());
    Eigen::MatrixXd Fr(ny, kc);
    Eigen::VectorXd mur(kc);
    for (Eigen::Index j = 0; j < kc; ++j) {
      Fr.col(j) = F.col(cols[static_cast<std::size_t>(j)]);
      mur(j) = k.mu(cols[static_cast<std::size_t>(j)]);
    }
    const Eigen::MatrixXd N1 = Eigen::MatrixXd(mur.asDiagonal()) - Fr.transpose() * (k.H * Fr);
    const Eigen::MatrixXd E1 =
        round_up(gamma(2 * ny + 4)) * (Eigen::MatrixXd(mur.asDiagonal()) + Fr.cwiseAbs().transpose() * (aH * Fr.cwiseAbs()));
    if (!N1.allFinite() || !certify_psd_scaled(N1, E1)) return false;
  }
  return true;
}

}  // namespace detail
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE ImprovedCorrector::ImprovedCorrector(const LinearSystem& sys, CorrectionOption option,
                    const ImprovedCorrectionOptions& options)
    : sys_(sys), option_(option), opt_(options) {
  if (option != CorrectionOption::FixedShape && option != CorrectionOption::DetNormalized &&
      option != CorrectionOption::BallNormalized)
    throw InvalidArgumentError("option: unknown correction option " + std::to_string(static_cast<int>(option)));
  opt_.validate(option_);
  init();
}

SETBOUND_INLINE ImprovedCorrector& ImprovedCorrector::operator=(const ImprovedCorrector& o) {
  if (this != &o) *this = ImprovedCorrector(o);
  return *this;
}

SETBOUND_INLINE CorrectionResult ImprovedCorrector::correct(const Ellipsoid& predicted, const Eigen::Ref<const Eigen::VectorXd>& y,
                           const Eigen::Ref<const Eigen::VectorXd>& u) {
  CorrectionResult r = correct_one(predicted, y, u);
  if (fixed_) {  // rule (iii): the FixedShape optimum, if it is the smaller P-shaped bound
    CorrectionResult a = fixed_->correct_one(predicted, y, u);
    if (a.fixed_shape.level() < r.fixed_shape.level()) r.fixed_shape = std::move(a.fixed_shape);
  }
  return r;
}

SETBOUND_INLINE CorrectionResult ImprovedCorrector::correct_one(const Ellipsoid& predicted, const Eigen::Ref<const Eigen::VectorXd>& y_in,
                               const Eigen::Ref<const Eigen::VectorXd>& u_in) {
  const Eigen::Index n = sys_.nx(), ny = sys_.ny(), nw = sys_.nw();
  if (predicted.dimension() != n)
    throw DimensionError("predicted: expected an ellipsoid of dimension " + std::to_string(n) + ", got " +
                         std::to_string(predicted.dimension()));
  detail::require_length(y_in.size(), ny, "y");
  require_finite(y_in, "y");
  if (u_in.size() != sys_.nu())
    throw DimensionError("u: expected length " + std::to_string(sys_.nu()) + ", got " + std::to_string(u_in.size()));
  require_finite(u_in, "u");
  const Eigen::VectorXd y = y_in, u = u_in;

  CorrectionResult fallback{predicted, predicted, 1.0, Eigen::MatrixXd::Zero(ny, ny), Eigen::VectorXd::Zero(nw), false};
  if (predicted.level() == 0.0) return fallback;  // a single point: nothing to improve
  try {
    detail::ImprovedCertificate cert;
    if (!solve(predicted, y, u, cert)) return fallback;
    CorrectionResult trivial = fallback;  // the prediction with its exact trivial certificate
    trivial.improved_solved = true;
    if (!better_than_prediction(cert.Pp, cert.rho, predicted)) return trivial;
    if (!detail::certify_improved(cert, predicted, y, u, sys_)) return fallback;
    // Centre c' = fl(c + d): |c' − (c + d)| ≤ u |c'| (one rounding per component).
    const Eigen::VectorXd cp = predicted.center() + cert.d;
    const Eigen::VectorXd dc = ell_rounding::round_up(ell_rounding::kEps) * cp.cwiseAbs();
    const double level =
        level_with_center_error(cert.rho, ell_rounding::lambda_max_upper(cert.Pp), dc);
    if (!std::isfinite(level) || !cp.allFinite()) return fallback;
    Ellipsoid improved(cert.Pp, cp, level);
    // FixedShape certifies (1 − θ) P; the same set written with P (level rounded up, certified).
    if (option_ == CorrectionOption::FixedShape) improved = improved.with_shape(predicted.shape());
    // Not better than the prediction in the mode's own criterion: keep the prediction.
    if (!better_than_prediction(improved.shape(), improved.level(), predicted)) return trivial;
    CorrectionResult r = trivial;
    r.improved = improved;
    // FixedShape returned the certified E((1 − θ) P, c', ρ') as E(P, c', ρ'' ≥ ρ'/(1 − θ)): the
    // same multipliers divided by 1 − θ certify it.
    const double scale = option_ == CorrectionOption::FixedShape ? 1.0 / (1.0 - 10.0 * opt_.margin) : 1.0;
    r.tau = cert.tau * scale;
    r.H = cert.H * scale;
    r.mu = cert.mu * scale;
    if (option_ == CorrectionOption::FixedShape) {
      r.fixed_shape = improved;  // shape P
    } else {
      try {
        Ellipsoid fs = improved.with_shape(predicted.shape());
        if (fs.level() < predicted.level()) r.fixed_shape = std::move(fs);
      } catch (const NumericalError&) {
        // the pair (P', P) is too ill-conditioned to certify the change of shape: keep the prediction
      }
    }
    return r;
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::Numerical || e.kind() == ErrorKind::NotPositiveDefinite ||
        e.kind() == ErrorKind::NotFinite || e.kind() == ErrorKind::Infeasible)
      return fallback;
    throw;
  }
}

SETBOUND_INLINE void ImprovedCorrector::init() {
  const Eigen::Index n = sys_.nx(), ny = sys_.ny();
  // Columns of F that are zero do not enter (C1): drop them (their μ_i is 0).
  for (Eigen::Index j = 0; j < sys_.nw(); ++j)
    if ((sys_.F().col(j).array() != 0.0).any()) cols_.push_back(j);
  Fr_.resize(ny, static_cast<Eigen::Index>(cols_.size()));
  for (std::size_t j = 0; j < cols_.size(); ++j) Fr_.col(static_cast<Eigen::Index>(j)) = sys_.F().col(cols_[j]);
  rank_deficient_ = true;
  if (Fr_.cols() >= ny) {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(Fr_);
    const Eigen::VectorXd& sv = svd.singularValues();
    rank_deficient_ = !(sv(ny - 1) > 1e-10 * sv(0));
  }
  st_ = std::make_unique<State>();
  State& s = *st_;
  s.has_mu = Fr_.cols() > 0;
  s.has_rho = option_ != CorrectionOption::DetNormalized;
  s.H = s.model.symmetric(static_cast<int>(ny));
  s.tau = s.model.scalar();
  if (s.has_mu) s.mu = s.model.diagonal(static_cast<int>(Fr_.cols()));
  if (s.has_rho) s.rho = s.model.scalar();
  // Structure from a generic data set (all couplings present); values are replaced per call.
  build(Eigen::MatrixXd::Ones(ny, n), Eigen::VectorXd::Ones(ny), Eigen::VectorXd::Ones(ny),
        0.5 * Eigen::MatrixXd::Identity(n, n));
  s.problem = s.model.build();
  if (option_ != CorrectionOption::DetNormalized)
    s.solver = std::make_unique<lmi::InteriorPointSolver>(s.problem, opt_.solver);
  if (opt_.fixed_shape_by_lmi && option_ != CorrectionOption::FixedShape) {
    ImprovedCorrectionOptions o = opt_;
    o.fixed_shape_by_lmi = false;
    fixed_ = std::make_unique<ImprovedCorrector>(sys_, CorrectionOption::FixedShape, o);
  }
}

SETBOUND_INLINE void ImprovedCorrector::build(const Eigen::MatrixXd& Ct, const Eigen::VectorXd& et, const Eigen::VectorXd& scale,
             const Eigen::MatrixXd& G) {
  using lmi::AffineExpr;
  State& s = *st_;
  const Eigen::Index n = sys_.nx(), k = Fr_.cols();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  s.model.clear_constraints();
  const AffineExpr rho = s.has_rho ? AffineExpr(s.rho) : AffineExpr(1.0);
  AffineExpr smu = AffineExpr(0.0);
  if (s.has_mu) smu = Eigen::MatrixXd(Eigen::MatrixXd::Ones(1, k)) * s.mu * Eigen::MatrixXd(Eigen::MatrixXd::Ones(k, 1));
  const Eigen::MatrixXd etT = et.transpose();
  const AffineExpr HC = s.H * Ct;  // ny × n
  const AffineExpr Q = s.tau * I + Eigen::MatrixXd(Ct.transpose()) * HC;
  const AffineExpr qT = etT * HC;  // 1 × n
  const AffineExpr corner = rho - s.tau - smu + etT * s.H * Eigen::MatrixXd(et);
  s.model.add_lmi(lmi::sym_block({{Q}, {qT, corner}}), opt_.margin);
  if (s.has_mu) {
    const Eigen::MatrixXd Fs = scale.asDiagonal() * Fr_;
    s.model.add_lmi(s.mu - Eigen::MatrixXd(Fs.transpose()) * s.H * Fs, opt_.margin);
    s.model.add_lmi(s.mu);  // μ ≥ 0
  }
  s.model.add_lmi(s.tau);  // τ ≥ 0
  if (opt_.tau_at_most_one) s.model.add_lmi(AffineExpr(1.0) - s.tau);
  if (opt_.level_at_least_tau_rho) s.model.add_lmi(rho - s.tau);  // ρ̃' ≥ τ (the prior level is 1)
  switch (option_) {
    case CorrectionOption::FixedShape:
      s.model.add_lmi(Q - I);  // no margin: it would cut off τ = 1 when rank C < n_x
      s.model.add_lmi(rho);  // ρ̃' ≥ 0
      s.model.minimize(rho);
      break;
    case CorrectionOption::BallNormalized:
      s.model.add_lmi(Q - G);
      s.model.add_lmi(rho);
      s.model.minimize(rho);
      break;
    case CorrectionOption::DetNormalized:
      if (rank_deficient_) s.model.add_lmi(AffineExpr(Eigen::MatrixXd(kShapeCap * I)) - Q);
      s.model.add_logdet(Q);
      break;
  }
}

SETBOUND_INLINE bool ImprovedCorrector::solve(const Ellipsoid& pred, const Eigen::VectorXd& y, const Eigen::VectorXd& u,
             detail::ImprovedCertificate& out) {
  State& s = *st_;
  const Eigen::Index n = sys_.nx(), ny = sys_.ny(), nw = sys_.nw();
  const double rho = pred.level(), srho = std::sqrt(rho);
  Eigen::LLT<Eigen::MatrixXd> llt(pred.shape());  // P = L Lᵀ = Rᵀ R, R = Lᵀ
  if (llt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd Lf = llt.matrixL();
  const Eigen::MatrixXd R = Lf.transpose();
  // √ρ C R⁻¹ = √ρ (L⁻¹ Cᵀ)ᵀ
  Eigen::MatrixXd CRi = Lf.triangularView<Eigen::Lower>().solve(sys_.C().transpose()).transpose();
  CRi *= srho;
  Eigen::VectorXd e0_err;
  const Eigen::VectorXd e0 = detail::accurate_innovation(y, sys_.C(), pred.center(), sys_.D(), u, e0_err);
  Eigen::VectorXd scale(ny);
  for (Eigen::Index i = 0; i < ny; ++i) {
    const double f = sys_.F().row(i).cwiseAbs().sum();
    const double cn = CRi.row(i).cwiseAbs().sum();
    scale(i) = f > 0 ? 1.0 / f : (cn > 0 ? 1.0 / cn : 1.0);
  }
  const Eigen::MatrixXd Ct = scale.asDiagonal() * CRi;
  const Eigen::VectorXd et = scale.asDiagonal() * e0;
  Eigen::MatrixXd G = Eigen::MatrixXd::Identity(n, n);
  if (option_ == CorrectionOption::BallNormalized) {
    // P' = Rᵀ P̃' R ⪰ λ_min(P) I  ⇔  P̃' ⪰ λ_min(P) R⁻ᵀ R⁻¹ (⪯ I, so P̃' = I is feasible).
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(pred.shape(), Eigen::EigenvaluesOnly);
    const double lmin = eig.eigenvalues()(0);
    const Eigen::MatrixXd Ri = R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(n, n));
    G = detail::symmetrized(lmin * (Ri.transpose() * Ri));
  }
  if (!Ct.allFinite() || !et.allFinite() || !G.allFinite()) return false;
  build(Ct, et, scale, G);
  s.model.update(s.problem);
  Eigen::VectorXd x;
  if (option_ == CorrectionOption::DetNormalized) {
    const lmi::SolveResult r = lmi::solve(s.problem, opt_.solver);
    // The barrier method keeps its iterates strictly feasible; a non-positive verified margin
    // means phase I did not find a feasible point.
    if (r.status == lmi::SolveStatus::Infeasible || r.status == lmi::SolveStatus::Unbounded || !(r.margin > 0))
      return false;
    x = r.x;
  } else {
    const lmi::SolveResult& r = s.solver->solve();
    if (r.status != lmi::SolveStatus::Optimal && r.status != lmi::SolveStatus::Inaccurate) return false;
    x = r.x;
  }
  if (x.size() != s.model.num_vars() || !x.allFinite()) return false;

  // Multipliers in the normalised coordinates.
  const Eigen::MatrixXd Ht = detail::symmetrized(s.model.value(s.H, x));
  double tau = std::max(0.0, s.model.scalar_value(s.tau, x));
  Eigen::VectorXd mut = Eigen::VectorXd::Zero(Fr_.cols());
  if (s.has_mu) mut = s.model.value(s.mu, x).diagonal().cwiseMax(0.0);
  double rhot = s.has_rho ? std::max(0.0, s.model.scalar_value(s.rho, x)) : 1.0;
  // Q, q and the (L) certificate: centre d̃ = Q⁻¹ q, shape P̃' slightly inside Q (P̃' = Q
  // makes (L) singular): (1 − θ) Q for DetNormalized and BallNormalized, (1 − θ) I for
  // FixedShape (Q ⪰ I), θ = 10·margin.
  const Eigen::MatrixXd HCt = Ht * Ct;
  const Eigen::MatrixXd Qv = detail::symmetrized(tau * Eigen::MatrixXd::Identity(n, n) + Ct.transpose() * HCt);
  const Eigen::VectorXd qv = HCt.transpose() * et;
  Eigen::LLT<Eigen::MatrixXd> lq(Qv);
  if (lq.info() != Eigen::Success) return false;
  const Eigen::VectorXd dt = lq.solve(qv);  // centre shift in η coordinates
  Eigen::MatrixXd Pt;
  const double theta = 10.0 * opt_.margin;
  switch (option_) {
    case CorrectionOption::FixedShape: Pt = (1.0 - theta) * Eigen::MatrixXd::Identity(n, n); break;
    case CorrectionOption::BallNormalized:
    case CorrectionOption::DetNormalized: Pt = (1.0 - theta) * Qv; break;
  }
  Eigen::MatrixXd Hs = Ht;
  if (option_ == CorrectionOption::DetNormalized) {
    // Rescale every variable by t = det(P̃')^(−1/n) so that det P' = det P.
    Eigen::LLT<Eigen::MatrixXd> lp(Pt);
    if (lp.info() != Eigen::Success) return false;
    const double logdet = 2.0 * lp.matrixLLT().diagonal().array().log().sum();
    const double t = std::exp(-logdet / static_cast<double>(n));
    if (!(t > 0) || !std::isfinite(t)) return false;
    Pt *= t;
    Hs *= t;
    tau *= t;
    mut *= t;
    rhot *= t;
  }
  // Back to the original coordinates.
  if (option_ == CorrectionOption::FixedShape) {
    out.Pp = (1.0 - theta) * pred.shape();  // converted back to P by correct()
  } else {
    out.Pp = detail::symmetrized(R.transpose() * Pt * R);
  }
  out.d = srho * R.triangularView<Eigen::Upper>().solve(dt);
  out.H = detail::symmetrized(rho * (scale.asDiagonal() * Hs * scale.asDiagonal()));
  out.tau = tau;
  out.mu = Eigen::VectorXd::Zero(nw);
  for (std::size_t j = 0; j < cols_.size(); ++j) out.mu(cols_[j]) = rho * mut(static_cast<Eigen::Index>(j));
  out.rho = ell_rounding::round_up(rho * rhot);
  return true;
}

SETBOUND_INLINE bool ImprovedCorrector::better_than_prediction(const Eigen::MatrixXd& Pp, double level, const Ellipsoid& pred) const {
  if (!(level >= 0) || !std::isfinite(level)) return false;
  if (option_ == CorrectionOption::BallNormalized) return level < pred.level();
  Eigen::LLT<Eigen::MatrixXd> a(Pp), b(pred.shape());
  if (a.info() != Eigen::Success || b.info() != Eigen::Success) return false;
  // log vol' − log vol = (n/2) log(ρ'/ρ) − (1/2)(log det P' − log det P)
  const double ld = 2.0 * (a.matrixLLT().diagonal().array().log().sum() - b.matrixLLT().diagonal().array().log().sum());
  const double nn = static_cast<double>(Pp.rows());
  if (level == 0.0) return true;
  return 0.5 * nn * std::log(level / pred.level()) - 0.5 * ld < 0.0;
}

SETBOUND_INLINE CorrectionResult improved_correction(const Ellipsoid& predicted, const Eigen::Ref<const Eigen::VectorXd>& y,
                                            const Eigen::Ref<const Eigen::VectorXd>& u, const LinearSystem& sys,
                                            CorrectionOption option,
                                            const ImprovedCorrectionOptions& options) {
  ImprovedCorrector corrector(sys, option, options);
  return corrector.correct(predicted, y, u);
}

}  // namespace setbound
