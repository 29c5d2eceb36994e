// setbound — definitions of the functions declared in setbound/estimators/ellipsoidal/lmi_estimators.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/ellipsoidal/lmi_estimators.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace detail {

SETBOUND_INLINE std::vector<EllAVertex> ell_A_vertices(const LinearSystem& sys) {
  const int q = sys.uncertain_entries();
  if (q > kMaxUncertainEntries) (void)sys.A_vertices();  // throws the library's message
  std::vector<std::pair<Eigen::Index, Eigen::Index>> idx;
  for (Eigen::Index j = 0; j < sys.nx(); ++j)
    for (Eigen::Index i = 0; i < sys.nx(); ++i)
      if (sys.A_rad()(i, j) > 0) idx.emplace_back(i, j);
  std::vector<EllAVertex> out;
  for (unsigned long s = 0; s < (1ul << q); ++s) {
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(sys.nx(), sys.nx());
    for (int b = 0; b < q; ++b) {
      const auto [i, j] = idx[static_cast<std::size_t>(b)];
      D(i, j) = ((s >> b) & 1ul) ? sys.A_rad()(i, j) : -sys.A_rad()(i, j);
    }
    out.push_back({sys.A() + D, D});
  }
  return out;
}

SETBOUND_INLINE std::vector<Eigen::Index> ell_active_columns(const Eigen::MatrixXd& E, const Eigen::MatrixXd& F) {
  std::vector<Eigen::Index> cols;
  for (Eigen::Index j = 0; j < E.cols(); ++j)
    if ((E.col(j).array() != 0.0).any() || (F.col(j).array() != 0.0).any()) cols.push_back(j);
  return cols;
}

SETBOUND_INLINE Eigen::MatrixXd ell_select_columns(const Eigen::MatrixXd& M, const std::vector<Eigen::Index>& cols) {
  Eigen::MatrixXd out(M.rows(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t j = 0; j < cols.size(); ++j) out.col(static_cast<Eigen::Index>(j)) = M.col(cols[j]);
  return out;
}

SETBOUND_INLINE std::vector<Eigen::VectorXd> ell_box_vertices(Eigen::Index m, bool halve) {
  std::vector<Eigen::VectorXd> out;
  if (m == 0) {
    out.emplace_back(0);
    return out;
  }
  const Eigen::Index free = halve ? m - 1 : m;
  for (unsigned long s = 0; s < (1ul << free); ++s) {
    Eigen::VectorXd w = Eigen::VectorXd::Ones(m);
    for (Eigen::Index i = 0; i < free; ++i)
      if ((s >> i) & 1ul) w(i) = -1.0;
    out.push_back(std::move(w));
  }
  return out;
}

SETBOUND_INLINE EllLmiData::EllLmiData(const LinearSystem& sys)
    : vertices(ell_A_vertices(sys)), C(sys.C()), active(ell_active_columns(sys.E(), sys.F())),
      interval(sys.uncertain_A()) {
  Et = ell_select_columns(sys.E(), active);
  Ft = ell_select_columns(sys.F(), active);
}

SETBOUND_INLINE double EllLmiData::disturbance_scale() const {
  const double s = std::sqrt(Et.squaredNorm() + Ft.squaredNorm());
  return s > 0 ? s : 1.0;
}

SETBOUND_INLINE EllGainTerms::EllGainTerms(const Eigen::MatrixXd& P, const Eigen::MatrixXd& L, const EllLmiData& d,
               const Eigen::MatrixXd& Et, const Eigen::MatrixXd& Ft) {
  const Eigen::Index n = P.rows(), ny = L.cols(), m = Et.cols();
  const double g = 2.0 * ell_rounding::gamma(n + ny + 3);
  const Eigen::MatrixXd aP = P.cwiseAbs(), aL = L.cwiseAbs();
  const Eigen::MatrixXd LC = aL * d.C.cwiseAbs();
  for (const EllAVertex& v : d.vertices) {
    PAL.push_back(P * (v.A - L * d.C));
    PAL_err.push_back(g * aP * (v.A.cwiseAbs() + LC));
  }
  PEL = P * (Et - L * Ft);
  PEL_err = g * aP * (Et.cwiseAbs() + aL * Ft.cwiseAbs());
  g_err = PEL_err.rowwise().sum() + 2.0 * ell_rounding::gamma(m + 1) * PEL.cwiseAbs().rowwise().sum();
}

SETBOUND_INLINE double ell_pow2_scale(double v, double target) {
  if (!(v > 0) || !(target > 0)) return 1.0;
  const int e = static_cast<int>(std::lround(0.5 * std::log2(target / v)));
  return std::ldexp(1.0, std::max(-500, std::min(500, e)));
}

SETBOUND_INLINE bool ell_certify_vertex_block(const Eigen::MatrixXd& P, double beta, double sigma,
                                     const Eigen::MatrixXd& PAL, const Eigen::MatrixXd& PAL_err,
                                     const Eigen::VectorXd& g, const Eigen::VectorXd& g_err) {
  const Eigen::Index n = P.rows();
  if (!(sigma >= 0) || !std::isfinite(sigma)) return false;
  const double f = ell_pow2_scale(sigma, P.diagonal().maxCoeff());
  const Eigen::VectorXd gs = g * f, gs_err = g_err * f;
  const double ss = sigma * f * f;
  if (!gs.allFinite() || !std::isfinite(ss)) return false;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * n + 1, 2 * n + 1);
  M.topLeftCorner(n, n) = beta * P;
  M(n, n) = ss;
  M.block(n + 1, 0, n, n) = PAL;
  M.block(0, n + 1, n, n) = PAL.transpose();
  M.block(n + 1, n, n, 1) = gs;
  M.block(n, n + 1, 1, n) = gs.transpose();
  M.bottomRightCorner(n, n) = P;
  // ‖Δ‖_2 ≤ ‖Δ‖_F for the symmetric error matrix Δ (βP: one rounding per entry).
  const double err2 = (ell_rounding::kEps * beta * P.cwiseAbs()).squaredNorm() + 2.0 * PAL_err.squaredNorm() +
                      2.0 * gs_err.squaredNorm();
  return certify_psd(M, ell_rounding::round_up(std::sqrt(err2) * (1.0 + 1e-10)));
}

SETBOUND_INLINE bool ell_certify_scaled_block(const Eigen::MatrixXd& P, double beta, const Eigen::MatrixXd& PAL,
                                     const Eigen::MatrixXd& PAL_err, const Eigen::MatrixXd& PEL,
                                     const Eigen::MatrixXd& PEL_err, const Eigen::VectorXd& s) {
  const Eigen::Index n = P.rows(), m = s.size();
  Eigen::MatrixXd Q = PEL, Q_err = PEL_err;
  Eigen::VectorXd d = s;
  const double target = P.diagonal().maxCoeff();
  for (Eigen::Index i = 0; i < m; ++i) {
    if (!(s(i) >= 0) || !std::isfinite(s(i))) return false;
    const double f = ell_pow2_scale(s(i), target);
    Q.col(i) *= f;
    Q_err.col(i) *= f;
    d(i) = s(i) * f * f;
  }
  if (!Q.allFinite() || !d.allFinite()) return false;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * n + m, 2 * n + m);
  M.topLeftCorner(n, n) = beta * P;
  M.block(n, 0, n, n) = PAL;
  M.block(0, n, n, n) = PAL.transpose();
  M.block(n, n, n, n) = P;
  if (m > 0) {
    M.block(n, 2 * n, n, m) = Q;
    M.block(2 * n, n, m, n) = Q.transpose();
    M.bottomRightCorner(m, m) = d.asDiagonal();
  }
  const double err2 = (ell_rounding::kEps * beta * P.cwiseAbs()).squaredNorm() + 2.0 * PAL_err.squaredNorm() +
                      2.0 * Q_err.squaredNorm();
  return certify_psd(M, ell_rounding::round_up(std::sqrt(err2) * (1.0 + 1e-10)));
}

SETBOUND_INLINE bool ell_certify_design(const Eigen::MatrixXd& P, const EllGainTerms& t, const EllLmiData& d,
                               const std::vector<Eigen::VectorXd>& omegas, double beta, double sigma) {
  for (std::size_t j = 0; j < d.vertices.size(); ++j)
    for (const Eigen::VectorXd& w : omegas) {
      const Eigen::VectorXd g = d.m() > 0 ? Eigen::VectorXd(t.PEL * w) : Eigen::VectorXd::Zero(P.rows());
      if (!ell_certify_vertex_block(P, beta, sigma, t.PAL[j], t.PAL_err[j], g, t.g_err)) return false;
    }
  return true;
}

SETBOUND_INLINE EllCentreTerms::EllCentreTerms(const Eigen::MatrixXd& P, const EllLmiData& d, const Eigen::VectorXd& c) {
  const Eigen::Index n = P.rows();
  const double g = 2.0 * ell_rounding::gamma(2 * n + 2);
  for (const EllAVertex& v : d.vertices) {
    Ph.push_back(P * (v.D * c));
    Ph_err.push_back(g * (P.cwiseAbs() * (v.D.cwiseAbs() * c.cwiseAbs())));
  }
}

SETBOUND_INLINE bool ell_certify_interval(const Eigen::MatrixXd& P, const EllGainTerms& t, const EllCentreTerms& ct,
                                 const std::vector<Eigen::VectorXd>& omegas, double beta, double sigma) {
  const Eigen::Index n = P.rows();
  for (std::size_t j = 0; j < t.PAL.size(); ++j)
    for (const Eigen::VectorXd& w : omegas) {
      const Eigen::VectorXd pew = t.PEL.cols() > 0 ? Eigen::VectorXd(t.PEL * w) : Eigen::VectorXd::Zero(n);
      const Eigen::VectorXd g = pew + ct.Ph[j];
      const Eigen::VectorXd ge =
          t.g_err + ct.Ph_err[j] + 2.0 * ell_rounding::gamma(2) * (pew.cwiseAbs() + ct.Ph[j].cwiseAbs());
      if (!ell_certify_vertex_block(P, beta, sigma, t.PAL[j], t.PAL_err[j], g, ge)) return false;
    }
  return true;
}

// The least σ the blocks need at fixed (β, L), uncertified: max over (A_j, ω) of vᵀK⁻¹v with
// K = [βP, PALᵀ; PAL, P], v = [0; g]; +inf when some K is not positive definite. Used by
// ell_interval_sigma (which then certifies) and by the predictor's partial steps (to rank β).
SETBOUND_INLINE double ell_sigma_need(const Eigen::MatrixXd& P, const EllGainTerms& t, const EllCentreTerms& ct,
                                      const std::vector<Eigen::VectorXd>& omegas, double beta) {
  const Eigen::Index n = P.rows();
  const double inf = std::numeric_limits<double>::infinity();
  double need = 0;
  for (std::size_t j = 0; j < t.PAL.size(); ++j) {
    Eigen::MatrixXd K(2 * n, 2 * n);
    K << beta * P, t.PAL[j].transpose(), t.PAL[j], P;
    Eigen::LLT<Eigen::MatrixXd> llt(K);
    if (llt.info() != Eigen::Success) return inf;
    for (const Eigen::VectorXd& w : omegas) {
      Eigen::VectorXd v = Eigen::VectorXd::Zero(2 * n);
      v.tail(n) = (t.PEL.cols() > 0 ? Eigen::VectorXd(t.PEL * w) : Eigen::VectorXd::Zero(n)) + ct.Ph[j];
      need = std::max(need, llt.matrixL().solve(v).squaredNorm());
    }
  }
  return std::isfinite(need) ? need : inf;
}

SETBOUND_INLINE double ell_interval_sigma(const Eigen::MatrixXd& P, const EllGainTerms& t, const EllCentreTerms& ct,
                                 const std::vector<Eigen::VectorXd>& omegas, double beta) {
  const double inf = std::numeric_limits<double>::infinity();
  const double need = ell_sigma_need(P, t, ct, omegas, beta);
  if (!std::isfinite(need)) return inf;
  double sigma = need * (1.0 + 1e-9) + std::numeric_limits<double>::min();
  for (int attempt = 0; attempt < 12; ++attempt, sigma = sigma * 4.0 + std::numeric_limits<double>::min())
    if (ell_certify_interval(P, t, ct, omegas, beta, sigma)) return sigma;
  return inf;
}

SETBOUND_INLINE double ell_lambda_min_lower(const Eigen::MatrixXd& P) {
  const double lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P, Eigen::EigenvaluesOnly).eigenvalues()(0);
  double mu = lmin * (1.0 - 1e-8);
  for (int k = 0; k < 60 && mu > 0; ++k, mu *= 0.5) {
    Eigen::MatrixXd S = P;
    S.diagonal().array() -= mu;
    if (certify_psd(S)) return mu;
  }
  return 0.0;
}

SETBOUND_INLINE void ell_check_detectable(const LinearSystem& sys, const std::string& pair) {
  require_detectable(sys.A(), sys.C(), pair);
  if (sys.uncertain_A()) {
    const std::vector<Eigen::MatrixXd> V = sys.A_vertices();
    for (std::size_t j = 0; j < V.size(); ++j)
      require_detectable(V[j], sys.C(), pair + " at vertex " + std::to_string(j) + " of [A]");
  }
}

SETBOUND_INLINE std::string ell_cancellable_hint(const Eigen::MatrixXd& E, const Eigen::MatrixXd& F) {
  if (E.cols() == 0 || E.isZero(0.0)) return "";
  Eigen::MatrixXd FE(F.rows() + E.rows(), F.cols());
  FE << F, E;
  const Eigen::JacobiSVD<Eigen::MatrixXd> sf(F), sfe(FE);
  auto rank = [](const Eigen::JacobiSVD<Eigen::MatrixXd>& sv) {
    const Eigen::VectorXd& v = sv.singularValues();
    if (v.size() == 0 || v(0) == 0.0) return Eigen::Index{0};
    return static_cast<Eigen::Index>((v.array() > 1e-10 * v(0)).count());
  };
  if (rank(sfe) > rank(sf)) return "";
  return "; note E, F: the disturbance can be cancelled exactly by a gain (E = L F is solvable: the outputs "
         "see every disturbance that drives the state, with no noise of their own), so the estimation set can "
         "shrink towards a point and the design degenerates — add output noise to the model or use a fixed beta "
         "with the Ball normalisation";
}

SETBOUND_INLINE void ell_check_design_values(EllDesign& d, Eigen::Index ny) {
  d.P = (0.5 * (d.P + d.P.transpose())).eval();
  require_shape(d.L, d.P.rows(), ny, "design.L");
  require_finite(d.L, "design.L");
  if (!(d.beta > 0 && d.beta < 1)) {
    std::ostringstream s;
    s << "design.beta: must be in (0, 1), got " << d.beta;
    throw InvalidArgumentError(s.str());
  }
  require_nonnegative(d.sigma, "design.sigma");
}

SETBOUND_INLINE const char* ell_normalization_name(EllNormalization n) {
  switch (n) {
    case EllNormalization::LogDet: return "LogDet";
    case EllNormalization::Ball: return "Ball";
    case EllNormalization::PaperTrace: return "PaperTrace";
  }
  return "unknown";
}

SETBOUND_INLINE EllDesign ell_design_impl(const LinearSystem& sys, const EllDesignOptions& opt, const std::string& name,
                                 const std::string& pair) {
  using lmi::AffineExpr;
  // --- options --------------------------------------------------------------------------
  if (opt.normalization != EllNormalization::LogDet && opt.normalization != EllNormalization::Ball &&
      opt.normalization != EllNormalization::PaperTrace)
    throw InvalidArgumentError("normalization: unknown value " + std::to_string(static_cast<int>(opt.normalization)));
  const bool fixed_beta = !std::isnan(opt.beta);
  if (fixed_beta && !(opt.beta > 0 && opt.beta < 1)) {
    std::ostringstream s;
    s << "beta: must be in (0, 1) (or NaN to search it), got " << opt.beta;
    throw InvalidArgumentError(s.str());
  }
  if (!fixed_beta && !(opt.beta_lo > 0 && opt.beta_lo < opt.beta_hi && opt.beta_hi < 1))
    throw InvalidArgumentError("beta_lo, beta_hi: need 0 < beta_lo < beta_hi < 1");
  // --- system -----------------------------------------------------------------------------
  ell_check_detectable(sys, pair);  // before any LMI
  const EllLmiData d(sys);
  const Eigen::Index n = sys.nx(), ny = sys.ny(), m = d.m();
  const std::vector<Eigen::VectorXd> omegas = ell_box_vertices(m, true);
  const std::size_t blocks = d.vertices.size() * omegas.size();
  if (m > 24 || blocks > kMaxEllVertexBlocks)
    throw InvalidArgumentError("E, F: " + std::to_string(m) + " active disturbance columns and " +
                               std::to_string(d.vertices.size()) + " vertices of [A] need too many LMI blocks (at most " +
                               std::to_string(kMaxEllVertexBlocks) + ")");
  if (m == 0 && opt.normalization == EllNormalization::LogDet)
    throw InvalidArgumentError("E, F: no disturbance reaches the estimation error ([E; F] = 0), so the LogDet design "
                               "is unbounded (the steady-state volume can be made arbitrarily small); use "
                               "EllNormalization::Ball");
  // The LMI is homogeneous of degree 2 in the disturbance scale: solve with [E; F]/s, then σ = s² σ'.
  const double s = d.disturbance_scale();
  const Eigen::MatrixXd Es = d.Et / s, Fs = d.Ft / s;

  lmi::Model model;
  const lmi::Var P = model.symmetric(static_cast<int>(n));
  const lmi::Var Y = model.full(static_cast<int>(n), static_cast<int>(ny));
  lmi::Var sig;
  const bool logdet = opt.normalization == EllNormalization::LogDet;
  if (!logdet) sig = model.scalar();
  auto build = [&](double beta) {
    model.clear_constraints();
    const AffineExpr PE = m > 0 ? AffineExpr(P * Es - Y * Fs) : AffineExpr();
    for (const EllAVertex& v : d.vertices) {
      const AffineExpr PA = P * v.A - Y * d.C;
      for (const Eigen::VectorXd& w : omegas) {
        const AffineExpr g = m > 0 ? PE * Eigen::MatrixXd(w) : AffineExpr::zero(n, 1);
        const AffineExpr sg = logdet ? AffineExpr(1.0) : AffineExpr(sig);
        model.add_lmi(lmi::sym_block({{beta * P}, {AffineExpr::zero(1, n), sg}, {PA, g, P}}), kEllLmiMargin);
      }
    }
    switch (opt.normalization) {
      case EllNormalization::LogDet: model.add_logdet(P); break;
      case EllNormalization::Ball:
        model.add_lmi(P - Eigen::MatrixXd::Identity(n, n));
        model.minimize(sig);
        break;
      case EllNormalization::PaperTrace: {
        AffineExpr tr(0.0);
        for (Eigen::Index i = 0; i < n; ++i) tr = tr + P.block(i, i, 1, 1);
        model.add_lmi(AffineExpr(1.0) - tr);  // tr P ≤ 1, as printed (degenerate)
        model.minimize(sig);
        break;
      }
    }
  };
  build(fixed_beta ? opt.beta : 0.5 * (opt.beta_lo + opt.beta_hi));
  lmi::LmiProblem problem = model.build();
  std::unique_ptr<lmi::InteriorPointSolver> solver;
  if (!logdet) solver = std::make_unique<lmi::InteriorPointSolver>(problem);

  // Criterion: log of the steady-state volume (LogDet) or of ρ∞ (Ball, PaperTrace), up to
  // constants; +inf where the LMI is infeasible. The best point is kept.
  Eigen::VectorXd best_x;
  double best_value = std::numeric_limits<double>::infinity(), best_beta = 0;
  bool unbounded = false;
  auto criterion = [&](double beta) -> double {
    build(beta);
    model.update(problem);
    lmi::SolveResult res;
    if (logdet) res = lmi::solve(problem);
    else res = solver->solve();
    if (res.status == lmi::SolveStatus::Unbounded) unbounded = true;
    if (res.status != lmi::SolveStatus::Optimal && res.status != lmi::SolveStatus::Inaccurate)
      return std::numeric_limits<double>::infinity();
    // The point must satisfy the LMI (it was imposed with a margin): an "inaccurate" solve
    // of an infeasible β can return a point that does not. An Optimal point meets the LMI up to
    // the solver's primal residual (1e-8 relative to data of order one here, the problem being
    // normalised), which can exceed the 1e-9 margin: such a point is kept, and the certification
    // below raises σ (or a searched β) to cover the difference or rejects the design.
    const double accept = res.status == lmi::SolveStatus::Optimal ? 0.5 * kEllLmiMargin + 1e-7 : 0.5 * kEllLmiMargin;
    if (!(res.margin > -accept)) return std::numeric_limits<double>::infinity();
    const Eigen::MatrixXd Pv = model.value(P, res.x);
    Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (Pv + Pv.transpose()));
    if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
    double v;
    if (logdet) {
      const double logdetP = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
      v = 0.5 * static_cast<double>(n) * std::log(1.0 / (1.0 - beta)) - 0.5 * logdetP;
    } else {
      const double sv = model.scalar_value(sig, res.x);
      if (!(sv > 0)) return std::numeric_limits<double>::infinity();
      v = std::log(sv / (1.0 - beta));
    }
    if (!std::isfinite(v)) return std::numeric_limits<double>::infinity();
    if (v < best_value) {
      best_value = v;
      best_beta = beta;
      best_x = res.x;
    }
    return v;
  };
  if (fixed_beta) {
    criterion(opt.beta);
  } else {
    lmi::minimize_scalar(criterion, opt.beta_lo, opt.beta_hi, opt.search);
  }
  if (!std::isfinite(best_value)) {
    if (unbounded)
      throw InvalidArgumentError("E, F: " + name + ": the " + ell_normalization_name(opt.normalization) +
                                 " design is unbounded (the disturbance can be cancelled by a gain); use "
                                 "EllNormalization::Ball");
    std::ostringstream msg;
    msg << name << ": the prediction LMI (setbound docs: Methods › Ellipsoidal estimation › Offline design) is infeasible ";
    if (fixed_beta) msg << "at beta = " << opt.beta;
    else msg << "for every beta in (" << opt.beta_lo << ", " << opt.beta_hi << ")";
    msg << " with the " << ell_normalization_name(opt.normalization) << " normalisation"
        << ell_cancellable_hint(d.Et, d.Ft);
    throw InfeasibleError(msg.str());
  }

  // --- read back, normalise, certify ----------------------------------------------------
  Eigen::MatrixXd Pv = model.value(P, best_x);
  symmetrize(Pv);
  const Eigen::MatrixXd Yv = model.value(Y, best_x);
  double sigma = s * s * (logdet ? 1.0 : model.scalar_value(sig, best_x));
  Eigen::LLT<Eigen::MatrixXd> llt(Pv);
  const Eigen::MatrixXd L = llt.solve(Yv);
  if (logdet) {  // rescale (P, Y, σ) to det P = 1 (L is unchanged)
    const double t = std::exp(-2.0 * llt.matrixLLT().diagonal().array().log().sum() / static_cast<double>(n));
    Pv *= t;
    sigma *= t;
  }
  EllDesign out{sys, Pv, L, best_beta, 0.0, 0.0, 0.0, opt.normalization, static_cast<int>(blocks)};
  if (!Pv.allFinite() || !L.allFinite() || !std::isfinite(sigma))
    throw NumericalError(name + ": the solver returned a non-finite design");
  const EllGainTerms terms(Pv, L, d, d.Et, d.Ft);
  const double base = std::max(sigma, 0.0);
  double sig_c = base, beta_c = best_beta;
  bool ok = false;
  // Certification first raises σ (relative 1e-9 … 1e-3). When the shortfall is in the other
  // blocks (badly scaled systems: the rounding slack exceeds the LMI margin there), a searched β
  // is raised towards 1 as well: β only enters as βP in the (1,1) block, so the same (P, L, σ)
  // satisfies the LMI at any larger β with extra slack (β_c − β)P. A fixed β is never changed.
  const double bumps[] = {0.0, 1e-8, 1e-6, 1e-4, 1e-2};
  for (double bump : bumps) {
    if (bump > 0 && fixed_beta) break;
    beta_c = best_beta + bump * (1.0 - best_beta);
    sig_c = base;
    for (double delta = 1e-9; delta <= 1e-3; delta *= 4.0) {
      if (ell_certify_design(Pv, terms, d, omegas, beta_c, sig_c)) {
        ok = true;
        break;
      }
      sig_c = base * (1.0 + delta) + (base == 0 ? delta * std::numeric_limits<double>::min() : 0.0);
    }
    if (ok) break;
  }
  out.beta = beta_c;
  if (!ok)
    throw NumericalError(name + ": the designed (P, L, beta, sigma) could not be certified in floating point "
                                "(the LMI is too close to infeasibility at the chosen beta)" +
                         ell_cancellable_hint(d.Et, d.Ft));
  out.sigma = sig_c;
  out.rho_inf = ell_rounding::round_up(sig_c / (1.0 - beta_c));
  out.volume_inf = out.rho_inf > 0 ? Ellipsoid(Pv, Eigen::VectorXd::Zero(n), out.rho_inf).volume() : 0.0;
  return out;
}

}  // namespace detail
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE EllDesign design_ellipsoidal_offline(const LinearSystem& sys, const EllDesignOptions& opt) {
  return detail::ell_design_impl(sys, opt, "design_ellipsoidal_offline", "(C, A)");
}

}  // namespace setbound

namespace setbound {
namespace detail {

SETBOUND_INLINE auto EllOnlineProblem::sub(const std::string& key) -> Sub& {
  auto it = subs.find(key);
  if (it != subs.end()) return *it->second;
  if (subs.size() >= 64) subs.clear();
  auto sp = std::make_unique<Sub>();
  sp->problem.reset(model.num_vars());
  for (std::size_t b = 0; b < blocks.size(); ++b)
    if (!blocks[b].vertex || key[b] == '1') {
      sp->ids.push_back(static_cast<int>(b));
      sp->problem.add_block_terms(blocks[b].F0, blocks[b].terms);
    }
  sp->solver = std::make_unique<lmi::InteriorPointSolver>(sp->problem, options);
  Sub& out = *sp;
  subs.emplace(key, std::move(sp));
  return out;
}

}  // namespace detail
}  // namespace setbound

namespace setbound {

SETBOUND_INLINE EllipsoidalPredictor::EllipsoidalPredictor(const EllipsoidalPredictor& o)
    : d_(o.d_), mode_(o.mode_), data_(d_.system), cur_(o.cur_), x0_(o.x0_), reset_set_(o.reset_set_) {
  init();
  policy_ = o.policy_;
  last_check_ = o.last_check_;
  if (on_ && o.on_) on_->working = o.on_->working;  // same next solve as the original
  if (on_ && o.on_) set_online_solver_options(o.on_->options);
  k_ = o.k_;
  last_beta_ = o.last_beta_;
  last_L_ = o.last_L_;
  fallbacks_ = o.fallbacks_;
  reuse_ = o.reuse_;
  reuse_tol_ = o.reuse_tol_;
  solves_ = o.solves_;
}

SETBOUND_INLINE EllipsoidalPredictor& EllipsoidalPredictor::operator=(const EllipsoidalPredictor& o) {
  if (this != &o) *this = EllipsoidalPredictor(o);
  return *this;
}

SETBOUND_INLINE void EllipsoidalPredictor::set_reuse_tolerance(double tol) {
  if (!(tol >= 0.0) || !std::isfinite(tol)) throw InvalidArgumentError("tol: must be finite and >= 0");
  reuse_tol_ = tol;
}

SETBOUND_INLINE Ellipsoid EllipsoidalPredictor::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  const LinearSystem& sys = d_.system;
  detail::require_length(y.size(), sys.ny(), "y");
  require_no_infinity(y, "y");
  if (!(u.size() == sys.nu() || (u.size() == 0 && sys.nu() == 0)))
    detail::require_length(u.size(), sys.nu(), "u");
  require_finite(u, "u");
  MeasurementCheck chk = screen(cur_, y, u);
  if (!chk.flagged()) return advance(y, u, chk);
  if (policy_ == OnInconsistency::Raise) raise_if_inconsistent(chk, cur_, y, u);
  if (policy_ == OnInconsistency::Flag) return advance(y, u, chk);
  // Reset: restart from the reset set and use the outputs consistent with it; the report keeps
  // the test that triggered the reset.
  const MeasurementCheck again = screen(reset_set_, y, u);
  const Ellipsoid before = cur_;
  cur_ = reset_set_;
  try {
    advance(y, u, again);
  } catch (...) {
    cur_ = before;
    throw;
  }
  last_check_ = chk;
  last_check_.reset = true;
  return cur_;
}

SETBOUND_INLINE void EllipsoidalPredictor::output_interval(const Ellipsoid& X, Eigen::Index i, double& center,
                                                           double& radius, double& magnitude) const {
  const Eigen::VectorXd& c = X.center();
  const auto Ci = d_.system.C().row(i);
  center = Ci.dot(c);
  radius = std::isfinite(q_(i)) ? ell_rounding::round_up(std::sqrt(ell_rounding::round_up(X.level() * q_(i))))
                                : std::numeric_limits<double>::infinity();
  magnitude = Ci.cwiseAbs().dot(c.cwiseAbs()) + (std::isfinite(radius) ? radius : 0.0);
}

SETBOUND_INLINE MeasurementCheck EllipsoidalPredictor::screen(const Ellipsoid& X, const Eigen::Ref<const Eigen::VectorXd>& y,
                                                              const Eigen::Ref<const Eigen::VectorXd>& u) const {
  const LinearSystem& sys = d_.system;
  const Eigen::Index ny = sys.ny(), nu = sys.nu();
  MeasurementCheck chk;
  chk.clear(ny, OutputStatus::Used);
  for (Eigen::Index i = 0; i < ny; ++i) {
    if (std::isnan(y(i))) {
      chk.status[static_cast<std::size_t>(i)] = OutputStatus::Missing;
      continue;
    }
    double center = 0, radius = 0, magnitude = 0;
    output_interval(X, i, center, radius, magnitude);
    double yi = y(i);
    if (nu > 0) {
      yi -= sys.D().row(i).dot(u);
      magnitude += sys.D().row(i).cwiseAbs().dot(u.cwiseAbs());
    }
    if (!std::isfinite(radius)) continue;  // no certified spread: never declared inconsistent
    const OutputTest t = test_output(yi, center, radius, phi_(i), magnitude, sys.nx() + nu + 4);
    chk.margin(i) = t.margin;
    if (t.inconsistent) chk.status[static_cast<std::size_t>(i)] = OutputStatus::Inconsistent;
  }
  return chk;
}

SETBOUND_INLINE void EllipsoidalPredictor::raise_if_inconsistent(const MeasurementCheck& chk, const Ellipsoid& X,
                                                                 const Eigen::Ref<const Eigen::VectorXd>& y,
                                                                 const Eigen::Ref<const Eigen::VectorXd>& u) const {
  const Eigen::Index i = chk.first_inconsistent();
  if (i < 0) return;
  double center = 0, radius = 0, magnitude = 0;
  output_interval(X, i, center, radius, magnitude);
  if (d_.system.nu() > 0) center += d_.system.D().row(i).dot(u);
  throw_inconsistent(k_, i, y(i), center, radius, phi_(i), chk.margin(i));
}

SETBOUND_INLINE Ellipsoid EllipsoidalPredictor::advance(const Eigen::Ref<const Eigen::VectorXd>& y,
                                                        const Eigen::Ref<const Eigen::VectorXd>& u,
                                                        const MeasurementCheck& chk) {
  const LinearSystem& sys = d_.system;
  const Eigen::Index ny = sys.ny();
  detail::require_length(y.size(), ny, "y");
  if (!(u.size() == sys.nu() || (u.size() == 0 && sys.nu() == 0)))
    detail::require_length(u.size(), sys.nu(), "u");
  if (static_cast<Eigen::Index>(chk.status.size()) != ny || chk.margin.size() != ny)
    throw DimensionError("chk: expected the screening of " + std::to_string(ny) + " outputs");
  std::vector<bool> use(static_cast<std::size_t>(ny));
  bool all = true;
  Eigen::VectorXd yv = y;
  for (Eigen::Index i = 0; i < ny; ++i) {
    const bool used = chk.status[static_cast<std::size_t>(i)] == OutputStatus::Used;
    use[static_cast<std::size_t>(i)] = used;
    all = all && used;
    if (!used) yv(i) = 0.0;  // its gain column is zero: the value never enters
    else if (!std::isfinite(yv(i))) throw NotFiniteError("y: entry " + std::to_string(i) + " is used and not finite");
  }
  require_finite(u, "u");
  const Eigen::VectorXd uv = u;
  const Eigen::VectorXd& c = cur_.center();
  const double rho = cur_.level();

  Choice ch{0.0, Eigen::MatrixXd(), 0.0, 0.0};
  bool failed = false;
  if (all) {
    ch = design_choice(rho, c);
    if (mode_ != EllPredictorMode::Offline) {
      try {
        failed = online_choice(rho, c, ch) == OnlineOutcome::Failed;
      } catch (const std::exception&) {
        failed = true;  // a numerical failure of the solver: the design step is always valid
      }
    }
  } else {
    ch = partial_choice(rho, c, use);
  }
  // Centre and level.
  const Eigen::VectorXd cn = sys.A() * c + sys.B() * uv + ch.L * (yv - sys.C() * c - sys.D() * uv);
  const Eigen::VectorXd dc = center_rounding_bound(sys.A(), sys.B(), ch.L, sys.C(), sys.D(), c, yv, uv);
  const double rn = level_with_center_error(ch.rho_next, lmax_up_, dc);
  Ellipsoid next(d_.P, cn, rn);
  cur_ = next;
  ++k_;
  last_beta_ = ch.beta;
  last_L_ = ch.L;
  last_check_ = chk;
  if (failed) ++fallbacks_;
  return next;
}

SETBOUND_INLINE auto EllipsoidalPredictor::partial_choice(double rho, const Eigen::VectorXd& c,
                                                          const std::vector<bool>& use) const -> Choice {
  using ell_rounding::round_up;
  const Eigen::Index n = d_.system.nx();
  Eigen::MatrixXd Ls = d_.L;
  bool any = false;
  for (std::size_t i = 0; i < use.size(); ++i) {
    if (use[i]) any = true;
    else Ls.col(static_cast<Eigen::Index>(i)).setZero();
  }
  std::vector<Eigen::MatrixXd> gains{Ls};
  if (any) gains.push_back(Eigen::MatrixXd::Zero(n, d_.L.cols()));
  const std::vector<Eigen::VectorXd>& omegas = data_.interval ? full_ : halved_;
  const detail::EllCentreTerms ct(d_.P, data_, c);
  const Eigen::LLT<Eigen::MatrixXd> pllt(d_.P);
  Choice best{1.0, Ls, 0.0, std::numeric_limits<double>::infinity()};
  static constexpr double kEta[] = {1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0, 3.0, 10.0, 100.0};
  for (const Eigen::MatrixXd& L : gains) {
    const detail::EllGainTerms t(d_.P, L, data_, data_.Et, data_.Ft);
    // a² = max_j λ_max(P⁻¹ A_Ljᵀ P A_Lj) = max_j ‖R A_Lj R⁻¹‖₂² with P = RᵀR, and
    // R A_L R⁻¹ = R⁻ᵀ (P A_L) R⁻¹ (only a starting point for β: σ is certified below).
    double a2 = 0;
    for (const Eigen::MatrixXd& PAL : t.PAL) {
      const Eigen::MatrixXd Y = pllt.matrixL().solve(PAL);                                  // R⁻ᵀ PAL
      const Eigen::MatrixXd M = pllt.matrixL().solve(Y.transpose()).transpose();            // R⁻ᵀ PAL R⁻¹
      a2 = std::max(a2, Eigen::JacobiSVD<Eigen::MatrixXd>(M).singularValues()(0));
    }
    a2 *= a2;
    // σ(β) needed at each β of the grid (uncertified, cheap); then certify in order of level.
    std::vector<std::pair<double, double>> cand;  // (level, β)
    for (double eta : kEta) {
      const double beta = std::max(a2 * (1.0 + eta), eta * 1e-9);
      const double need = detail::ell_sigma_need(d_.P, t, ct, omegas, beta);
      if (std::isfinite(need)) cand.emplace_back(beta * rho + need, beta);
    }
    std::sort(cand.begin(), cand.end());
    for (const auto& [level, beta] : cand) {
      if (!(level < best.rho_next)) break;
      const double sigma = detail::ell_interval_sigma(d_.P, t, ct, omegas, beta);
      if (!std::isfinite(sigma)) continue;
      const double r = round_up(round_up(beta * rho) + sigma);
      if (r < best.rho_next) best = {beta, L, sigma, r};
      break;
    }
  }
  if (!std::isfinite(best.rho_next))
    throw NumericalError("y: the prediction with the outputs present could not be certified (P is too badly "
                         "conditioned for the gain restricted to them)");
  return best;
}

SETBOUND_INLINE void EllipsoidalPredictor::set_inconsistency_policy(OnInconsistency policy) {
  set_inconsistency_policy(policy, x0_);
}

SETBOUND_INLINE void EllipsoidalPredictor::set_inconsistency_policy(OnInconsistency policy, const Ellipsoid& reset_set) {
  if (static_cast<int>(policy) < 0 || static_cast<int>(policy) > 2)
    throw InvalidArgumentError("on_inconsistency: must be Flag, Raise or Reset");
  if (reset_set.dimension() != d_.system.nx())
    throw DimensionError("reset_set: expected an ellipsoid of dimension " + std::to_string(d_.system.nx()) + ", got " +
                         std::to_string(reset_set.dimension()));
  Ellipsoid r = reset_set.with_shape(d_.P);
  policy_ = policy;
  reset_set_ = std::move(r);
}

SETBOUND_INLINE void EllipsoidalPredictor::reset() {
  cur_ = x0_;
  k_ = 0;
  fallbacks_ = 0;
  solves_ = 0;
  reuse_ = Reuse{};
  last_beta_ = d_.beta;
  last_L_ = d_.L;
  if (on_) on_->working.assign(on_->blocks.size(), '1');
  last_check_.clear(d_.system.ny());
}

SETBOUND_INLINE std::vector<double> EllipsoidalPredictor::save_state() const {
  StateWriter w(StateKind::EllipsoidalPredictor, fingerprint());
  w.count(k_).count(fallbacks_).scalar(last_beta_).mat(last_L_);
  w.mat(cur_.shape()).vec(cur_.center()).scalar(cur_.level());
  const bool rv = std::isfinite(reuse_.rho);
  w.count(solves_).count(rv ? 1 : 0).scalar(rv ? reuse_.rho : 0.0).scalar(rv ? reuse_.beta : 0.0);
  w.scalar(rv ? reuse_.sigma : 0.0).mat(rv ? reuse_.L : Eigen::MatrixXd(Eigen::MatrixXd::Zero(d_.L.rows(), d_.L.cols())));
  w.text(on_ ? on_->working : std::string());  // last: tests read it from the end
  return w.finish();
}

SETBOUND_INLINE void EllipsoidalPredictor::restore_state(const std::vector<double>& state) {
  apply_state(guard_state_memory(StateKind::EllipsoidalPredictor, [&] { return parse_state(state); }));
}

SETBOUND_INLINE auto EllipsoidalPredictor::parse_state(const std::vector<double>& state) const -> ParsedState {
  const Eigen::Index n = d_.system.nx(), ny = d_.system.ny();
  StateReader r(state, StateKind::EllipsoidalPredictor, fingerprint());
  ParsedState p;
  const long long k = r.count("steps"), fb = r.count("fallback_steps");
  p.beta = r.scalar("last_beta");
  p.L = r.mat(n, ny, "last_gain");
  Eigen::MatrixXd P = r.mat(n, n, "shape");
  Eigen::VectorXd c = r.vec(n, "center");
  const double rho = r.scalar("level");
  const long long sv = r.count("online_solves");
  const bool rv = r.count("reuse_valid", 0, 1) == 1;
  const double rrho = r.scalar("reuse_rho"), rbeta = r.scalar("reuse_beta"), rsig = r.scalar("reuse_sigma");
  Eigen::MatrixXd rL = r.mat(n, ny, "reuse_gain");
  p.working = r.text("working_set");
  r.finish();
  if (sv > k) r.fail("online_solves exceeds steps");
  if (rv) {
    if (!(rrho > 0) || !(rbeta > 0 && rbeta < 1) || !(rsig >= 0)) r.fail("the saved reuse point is invalid");
    p.reuse = {rrho, rbeta, rsig, std::move(rL)};
  }
  p.solves = static_cast<Eigen::Index>(sv);
  if (fb > k) r.fail("fallback_steps exceeds steps");
  if (!(p.beta > 0) || !std::isfinite(p.beta)) r.fail("last_beta is not positive and finite");
  const std::size_t nb = on_ ? on_->blocks.size() : 0;
  if (p.working.size() != nb || p.working.find_first_not_of("01") != std::string::npos)
    r.fail("working_set does not match the online problem of this predictor");
  try {
    p.cur = std::make_unique<Ellipsoid>(std::move(P), std::move(c), rho);
  } catch (const Error& e) {
    r.fail(std::string("the saved set is invalid (") + e.what() + ")");
  }
  p.k = static_cast<Eigen::Index>(k);
  p.fallbacks = static_cast<Eigen::Index>(fb);
  return p;
}

SETBOUND_INLINE void EllipsoidalPredictor::apply_state(ParsedState&& p) {
  cur_ = std::move(*p.cur);
  k_ = p.k;
  fallbacks_ = p.fallbacks;
  last_beta_ = p.beta;
  last_L_ = std::move(p.L);
  if (on_) on_->working = std::move(p.working);
  solves_ = p.solves;
  reuse_ = {p.reuse.rho, p.reuse.beta, p.reuse.sigma, std::move(p.reuse.L)};
}

SETBOUND_INLINE StateFingerprint EllipsoidalPredictor::fingerprint() const {
  StateFingerprint f;
  f.add_int(static_cast<int>(mode_)).add(d_.P).add(d_.L).add(d_.beta).add(d_.sigma);
  const LinearSystem& s = d_.system;
  f.add(s.A()).add(s.A_rad()).add(s.B()).add(s.C()).add(s.D()).add(s.E()).add(s.F());
  return f;
}

SETBOUND_INLINE void EllipsoidalPredictor::set_online_solver_options(const lmi::SolverOptions& options) {
  options.validate();
  if (!on_) return;
  on_->options = options;
  for (auto& kv : on_->subs) kv.second->solver->set_options(options);
}

SETBOUND_INLINE void EllipsoidalPredictor::reset(const Ellipsoid& x) {
  if (x.dimension() != d_.system.nx())
    throw DimensionError("x: expected an ellipsoid of dimension " + std::to_string(d_.system.nx()) + ", got " +
                         std::to_string(x.dimension()));
  cur_ = x.with_shape(d_.P);
}

SETBOUND_INLINE Ellipsoid EllipsoidalPredictor::check_x0(const EllDesign& d, const Ellipsoid& x0) {
  const Eigen::Index n = d.system.nx();
  require_shape(d.P, n, n, "design.P");
  require_positive_definite(d.P, "design.P");
  if (x0.dimension() != n)
    throw DimensionError("x0: expected an ellipsoid of dimension " + std::to_string(n) + ", got " +
                         std::to_string(x0.dimension()));
  return x0.with_shape(0.5 * (d.P + d.P.transpose()));
}

SETBOUND_INLINE void EllipsoidalPredictor::init() {
  const LinearSystem& sys = d_.system;
  const Eigen::Index n = sys.nx();
  if (mode_ != EllPredictorMode::Offline && mode_ != EllPredictorMode::OnlineVertex &&
      mode_ != EllPredictorMode::OnlineScaled)
    throw InvalidArgumentError("mode: unknown predictor mode " + std::to_string(static_cast<int>(mode_)));
  detail::ell_check_design_values(d_, sys.ny());
  if (mode_ == EllPredictorMode::Offline && data_.interval)
    throw InvalidArgumentError(
        "mode: the Offline predictor cannot be used with an interval A: the centre term (A - mid[A]) x_k of the "
        "error has no a-priori bound (setbound docs: Methods › Ellipsoidal estimation › Interval uncertainty on A); use OnlineVertex or OnlineScaled");
  halved_ = detail::ell_box_vertices(data_.m(), true);
  if (data_.m() > 24 || data_.vertices.size() * halved_.size() * (data_.interval ? 2 : 1) >
                            detail::kMaxEllVertexBlocks)
    throw InvalidArgumentError("design.system: too many disturbance columns / vertices of [A] for the vertex LMIs");
  if (data_.interval) full_ = detail::ell_box_vertices(data_.m(), false);
  lmax_up_ = ell_rounding::lambda_max_upper(d_.P);
  design_terms_ = std::make_unique<detail::EllGainTerms>(d_.P, d_.L, data_, data_.Et, data_.Ft);
  // The design must be certified: it is the Offline step and every online step's fallback.
  if (!data_.interval) {
    if (!detail::ell_certify_design(d_.P, *design_terms_, data_, halved_, d_.beta, d_.sigma))
      throw InvalidArgumentError("design: the prediction LMI does not hold (certified) at the design's (P, L, beta, "
                                 "sigma) for this system");
  } else {
    // Robust contraction at every vertex: [βP, A_Lᵀ P; P A_L, P] ≻ 0 (the σ row is per step).
    for (std::size_t j = 0; j < data_.vertices.size(); ++j) {
      const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
      if (!detail::ell_certify_vertex_block(d_.P, d_.beta, 1.0, design_terms_->PAL[j], design_terms_->PAL_err[j],
                                            zero, zero))
        throw InvalidArgumentError("design: (beta, L) does not contract in the P-norm at vertex " +
                                   std::to_string(j) + " of [A]");
    }
  }
  last_beta_ = d_.beta;
  last_L_ = d_.L;
  if (mode_ != EllPredictorMode::Offline) build_online();
  // Consistency test data: φ_i and certified q_i ≥ C_i P⁻¹ C_iᵀ. The Schur complement
  // [P, f C_iᵀ; f C_i, f² q_i] ⪰ 0 (f a power of two bringing f² q_i to the size of P's
  // diagonal: an exact congruence) proves the bound in exact arithmetic.
  const Eigen::Index ny = sys.ny();
  phi_.resize(ny);
  q_.resize(ny);
  const Eigen::LLT<Eigen::MatrixXd> pllt(d_.P);
  for (Eigen::Index i = 0; i < ny; ++i) {
    phi_(i) = sys.output_noise_bound(i);
    const Eigen::VectorXd ci = sys.C().row(i).transpose();
    if ((ci.array() == 0.0).all()) {
      q_(i) = 0.0;
      continue;
    }
    const double q = pllt.matrixL().solve(ci).squaredNorm();
    q_(i) = std::numeric_limits<double>::infinity();
    for (double bump : {1e-12, 1e-9, 1e-6, 1e-3, 1e-1, 1.0, 10.0}) {
      const double qb = q * (1.0 + bump) + std::numeric_limits<double>::min();
      const double f = detail::ell_pow2_scale(qb, d_.P.diagonal().maxCoeff());
      Eigen::MatrixXd M(n + 1, n + 1);
      M.topLeftCorner(n, n) = d_.P;
      M.block(0, n, n, 1) = f * ci;
      M.block(n, 0, 1, n) = f * ci.transpose();
      M(n, n) = qb * f * f;
      if (certify_psd(M)) {
        q_(i) = qb;
        break;
      }
    }
  }
  last_check_.clear(ny);
}

SETBOUND_INLINE auto EllipsoidalPredictor::design_choice(double rho, const Eigen::VectorXd& c) const -> Choice {
  using ell_rounding::round_up;
  if (!data_.interval) return {d_.beta, d_.L, d_.sigma, round_up(round_up(d_.beta * rho) + d_.sigma)};
  const detail::EllCentreTerms ct(d_.P, data_, c);
  Choice best{d_.beta, d_.L, 0.0, std::numeric_limits<double>::infinity()};
  for (double f : {0.0, 0.25, 0.5, 0.75, 0.9}) {
    const double beta = d_.beta + f * (1.0 - d_.beta);
    const double sigma = detail::ell_interval_sigma(d_.P, *design_terms_, ct, full_, beta);
    if (!std::isfinite(sigma)) continue;
    const double r = round_up(round_up(beta * rho) + sigma);
    if (r < best.rho_next) best = {beta, d_.L, sigma, r};
  }
  if (!std::isfinite(best.rho_next))
    throw NumericalError("design: the interval-A prediction step could not be certified at the design's gain "
                         "(the centre term is too large for the conditioning of P)");
  return best;
}

SETBOUND_INLINE void EllipsoidalPredictor::build_online() {
  using lmi::AffineExpr;
  const LinearSystem& sys = d_.system;
  const Eigen::Index n = sys.nx(), ny = sys.ny(), m = data_.m();
  on_ = std::make_unique<detail::EllOnlineProblem>();
  detail::EllOnlineProblem& o = *on_;
  o.p = lmax_up_;
  o.sc = data_.disturbance_scale();
  const Eigen::MatrixXd Ph = d_.P / o.p, Es = data_.Et / o.sc, Fs = data_.Ft / o.sc;
  const double sig_hat = d_.sigma / (o.p * o.sc * o.sc);
  lmi::Model& mod = o.model;
  o.beta = mod.scalar();
  o.Y = mod.full(static_cast<int>(n), static_cast<int>(ny));
  const double margin = detail::kEllLmiMargin;
  std::vector<detail::EllOnlineProblem::Block> info;  // per added LMI, in order
  if (mode_ == EllPredictorMode::OnlineVertex) {
    o.sk = mod.scalar();
    const std::vector<Eigen::VectorXd>& omegas = data_.interval ? full_ : halved_;
    const AffineExpr PE = m > 0 ? AffineExpr(Ph * Es - o.Y * Fs) : AffineExpr();
    for (std::size_t j = 0; j < data_.vertices.size(); ++j) {
      const AffineExpr PA = Ph * data_.vertices[j].A - o.Y * data_.C;
      for (std::size_t w = 0; w < omegas.size(); ++w) {
        const AffineExpr g = m > 0 ? PE * Eigen::MatrixXd(omegas[w]) : AffineExpr::zero(n, 1);
        mod.add_lmi(lmi::sym_block({{o.beta * Ph}, {AffineExpr::zero(1, n), o.sk}, {PA, g, AffineExpr(Ph)}}), margin);
        detail::EllOnlineProblem::Block bi;
        bi.vertex = true;
        bi.a_vertex = j;
        bi.omega = w;
        bi.centre = data_.interval;
        info.push_back(std::move(bi));
      }
    }
    if (!data_.interval) {
      mod.add_lmi(AffineExpr(sig_hat) - o.sk);  // ρ⁺ ≤ βρ_k + σ
      info.emplace_back();
    }
    mod.minimize(o.sk);
  } else {
    // Scaled (§1.3, S = diag(s)); an interval A adds the centre box diag(rad[A] |x̄_k|) as
    // extra columns (constant per step, no gain on them since F is zero there).
    if (data_.interval)
      for (Eigen::Index i = 0; i < n; ++i)
        if ((sys.A_rad().row(i).array() > 0).any()) o.centre_rows.push_back(i);
    const Eigen::Index mc = static_cast<Eigen::Index>(o.centre_rows.size());
    const Eigen::Index mt = m + mc;
    if (mt > 0) o.s = mod.diagonal(static_cast<int>(mt));
    for (std::size_t j = 0; j < data_.vertices.size(); ++j) {
      const AffineExpr PA = Ph * data_.vertices[j].A - o.Y * data_.C;
      if (mt > 0) {
        AffineExpr PEt = AffineExpr::zero(n, mt);
        if (m > 0) {
          AffineExpr PE = Ph * Es - o.Y * Fs;
          if (mc > 0) PE = lmi::block_matrix({{PE, AffineExpr::zero(n, mc)}});
          PEt = PE;
        }
        mod.add_lmi(lmi::sym_block({{o.beta * Ph}, {PA, AffineExpr(Ph)}, {AffineExpr::zero(mt, n), PEt.transpose(), o.s}}),
                    margin);
      } else {
        mod.add_lmi(lmi::sym_block({{o.beta * Ph}, {PA, AffineExpr(Ph)}}), margin);
      }
      detail::EllOnlineProblem::Block bi;
      bi.a_vertex = j;
      bi.centre = data_.interval && mc > 0;
      info.push_back(std::move(bi));
    }
    AffineExpr sum(0.0);
    for (Eigen::Index i = 0; i < mt; ++i) sum = sum + o.s.block(i, i, 1, 1);
    if (!data_.interval) {
      mod.add_lmi(AffineExpr(sig_hat) - sum);  // Σ s_i ≤ σ
      info.emplace_back();
    }
    mod.minimize(sum);
  }
  mod.add_lmi(o.beta - AffineExpr(1e-9));        // β > 0
  mod.add_lmi(AffineExpr(1.0 - 1e-9) - o.beta);  // β < 1
  info.emplace_back();
  info.emplace_back();
  const lmi::LmiProblem full = mod.build();
  for (std::size_t b = 0; b < info.size(); ++b) {
    const lmi::LmiBlock& blk = full.block(static_cast<int>(b));
    info[b].F0 = blk.constant;
    for (const auto& co : blk.coefficients) info[b].terms.emplace_back(co.var, co.dense);
  }
  o.blocks = std::move(info);
  o.working.assign(o.blocks.size(), '1');
  o.sub(o.working);  // the full problem, analysed now
}

SETBOUND_INLINE auto EllipsoidalPredictor::online_choice(double rho, const Eigen::VectorXd& c, Choice& ch) -> OnlineOutcome {
  using ell_rounding::round_up;
  const LinearSystem& sys = d_.system;
  const Eigen::Index n = sys.nx(), m = data_.m();
  detail::EllOnlineProblem& o = *on_;
  const double unit = o.p * o.sc * o.sc;  // σ = unit · σ̂
  const bool vertex_mode = mode_ == EllPredictorMode::OnlineVertex;
  if (!data_.interval && reuse_tol_ > 0 && std::isfinite(reuse_.rho) &&
      std::abs(rho - reuse_.rho) <= reuse_tol_ * reuse_.rho) {
    const double rho_next = round_up(round_up(reuse_.beta * rho) + reuse_.sigma);
    if (vertex_mode && !(rho_next < ch.rho_next)) return OnlineOutcome::NotBetter;
    ch = {reuse_.beta, reuse_.L, reuse_.sigma, rho_next};
    return OnlineOutcome::Used;
  }
  reuse_.rho = std::numeric_limits<double>::quiet_NaN();  // valid again once this solve certifies
  ++solves_;
  // Objective β ρ̂_k + σ̂_k.
  Eigen::VectorXd cvec = Eigen::VectorXd::Zero(o.model.num_vars());
  cvec(o.beta.index()(0, 0)) = rho / unit;
  if (vertex_mode) {
    cvec(o.sk.index()(0, 0)) = 1.0;
  } else {
    for (Eigen::Index i = 0; i < o.s.index().rows(); ++i) cvec(o.s.index()(i, i)) = 1.0;
  }
  // Interval A: the constants with the centre term of this step.
  std::unique_ptr<detail::EllCentreTerms> ct;
  Eigen::MatrixXd Ec;  // scaled interval: the centre box columns, half-widths rounded up
  std::vector<Eigen::MatrixXd> F0now(o.blocks.size());
  if (data_.interval) {
    ct = std::make_unique<detail::EllCentreTerms>(d_.P, data_, c);
    const Eigen::MatrixXd Ph = d_.P / o.p;
    const Eigen::Index mc = static_cast<Eigen::Index>(o.centre_rows.size());
    if (!vertex_mode && mc > 0) {
      Eigen::VectorXd ebox = (sys.A_rad() * c.cwiseAbs()) * (1.0 + 2.0 * ell_rounding::gamma(n + 2));
      Ec = Eigen::MatrixXd::Zero(n, mc);
      for (Eigen::Index i = 0; i < mc; ++i) {
        const Eigen::Index r = o.centre_rows[static_cast<std::size_t>(i)];
        Ec(r, i) = round_up(ebox(r));
      }
    }
    for (std::size_t b = 0; b < o.blocks.size(); ++b) {
      const auto& blk = o.blocks[b];
      if (!blk.centre) continue;
      Eigen::MatrixXd F0 = blk.F0;
      if (vertex_mode) {
        const Eigen::VectorXd h = Ph * (data_.vertices[blk.a_vertex].D * c) / o.sc;
        F0.block(n + 1, n, n, 1) += h;
        F0.block(n, n + 1, 1, n) += h.transpose();
      } else {
        const Eigen::MatrixXd PEc = Ph * Ec / o.sc;
        F0.block(n, 2 * n + m, n, mc) += PEc;
        F0.block(2 * n + m, n, mc, n) += PEc.transpose();
      }
      F0now[b] = std::move(F0);
    }
  }
  const std::vector<Eigen::VectorXd>& omegas = data_.interval ? full_ : halved_;
  auto vertex_block_ok = [&](const detail::EllGainTerms& t, const detail::EllOnlineProblem::Block& blk,
                             double beta, double sigma) {
    const Eigen::VectorXd pew = m > 0 ? Eigen::VectorXd(t.PEL * omegas[blk.omega]) : Eigen::VectorXd::Zero(n);
    if (!data_.interval)
      return detail::ell_certify_vertex_block(d_.P, beta, sigma, t.PAL[blk.a_vertex], t.PAL_err[blk.a_vertex], pew,
                                              t.g_err);
    const std::size_t j = blk.a_vertex;
    const Eigen::VectorXd ge = t.g_err + ct->Ph_err[j] +
                               2.0 * ell_rounding::gamma(2) * (pew.cwiseAbs() + ct->Ph[j].cwiseAbs());
    return detail::ell_certify_vertex_block(d_.P, beta, sigma, t.PAL[j], t.PAL_err[j], pew + ct->Ph[j], ge);
  };

  for (int round = 0; round <= static_cast<int>(o.blocks.size()); ++round) {
    detail::EllOnlineProblem::Sub& sp = o.sub(o.working);
    for (std::size_t i = 0; i < sp.ids.size(); ++i) {
      const auto& blk = o.blocks[static_cast<std::size_t>(sp.ids[i])];
      if (blk.centre) sp.problem.update_block_terms(static_cast<int>(i), F0now[static_cast<std::size_t>(sp.ids[i])], blk.terms);
    }
    sp.problem.set_objective(cvec);
    const lmi::SolveResult& res = sp.solver->solve();
    const bool all_in = o.working.find('0') == std::string::npos;
    if (res.status != lmi::SolveStatus::Optimal && res.status != lmi::SolveStatus::Inaccurate) {
      if (all_in) return OnlineOutcome::Failed;
      o.working.assign(o.blocks.size(), '1');  // retry with every block
      continue;
    }
    const Eigen::VectorXd x = res.x;
    if (!x.allFinite()) return OnlineOutcome::Failed;
    const double beta = x(o.beta.index()(0, 0));
    if (!(beta > 0 && beta < 1)) return OnlineOutcome::Failed;
    const Eigen::MatrixXd Yh = o.model.value(o.Y, x);
    const Eigen::MatrixXd L = (d_.P / o.p).llt().solve(Yh);  // L = P̂⁻¹Ŷ = P⁻¹Y
    if (!L.allFinite()) return OnlineOutcome::Failed;
    const detail::EllGainTerms terms(d_.P, L, data_, data_.Et, data_.Ft);

    // The solver's point satisfies the LMIs only up to its residual tolerance. Each block is
    // M ⪰ 0 ⇔ (Schur complement on the constant P block) a 2×2 block matrix that grows with
    // β and σ (resp. s), so a joint relative bump β' = β + δ(1 − β), σ' = σ(1 + δ) + δσ_ref
    // restores strict feasibility at a relative cost δ; the smallest δ that certifies is used.
    const double sig_ref = std::max(ch.sigma, std::numeric_limits<double>::min());
    auto bumped_beta = [&](double delta) { return beta + delta * (1.0 - beta); };
    static constexpr double kBumps[] = {0.0, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4};
    if (vertex_mode) {
      const double s0 = std::max(0.0, x(o.sk.index()(0, 0)) * unit);
      // Blocks outside W that the relaxed solution violates join W: solve again.
      bool grew = false;
      for (std::size_t b = 0; b < o.blocks.size(); ++b)
        if (o.blocks[b].vertex && o.working[b] == '0' &&
            !vertex_block_ok(terms, o.blocks[b], bumped_beta(1e-6), s0 * (1 + 1e-6) + 1e-6 * sig_ref)) {
          o.working[b] = '1';
          grew = true;
        }
      if (grew) continue;
      double sigma = s0, beta_c = beta;
      bool ok = false;
      for (double delta : kBumps) {
        beta_c = bumped_beta(delta);
        sigma = s0 * (1.0 + delta) + delta * sig_ref;
        ok = true;
        for (std::size_t b = 0; b < o.blocks.size() && ok; ++b)
          if (o.blocks[b].vertex) ok = vertex_block_ok(terms, o.blocks[b], beta_c, sigma);
        if (ok) break;
      }
      if (!ok) return OnlineOutcome::Failed;
      // Next working set: the blocks nearly active at this solution (at least one).
      std::string next(o.blocks.size(), '0');
      double least = std::numeric_limits<double>::infinity();
      std::size_t argleast = 0;
      Eigen::MatrixXd F;
      for (std::size_t b = 0; b < o.blocks.size(); ++b) {
        const auto& blk = o.blocks[b];
        if (!blk.vertex) continue;
        F = blk.centre ? F0now[b] : blk.F0;
        for (const auto& [v, Fv] : blk.terms) F.noalias() += x(v) * Fv;
        const double lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(F, Eigen::EigenvaluesOnly).eigenvalues()(0);
        if (lmin < 1e-5) next[b] = '1';
        if (lmin < least) least = lmin, argleast = b;
      }
      next[argleast] = '1';
      o.working = next;
      const double rho_next = round_up(round_up(beta_c * rho) + sigma);
      if (!data_.interval) reuse_ = {rho, beta_c, sigma, L};
      if (!(rho_next < ch.rho_next)) return OnlineOutcome::NotBetter;
      ch = {beta_c, L, sigma, rho_next};
      return OnlineOutcome::Used;
    }

    // OnlineScaled.
    const Eigen::Index mc = static_cast<Eigen::Index>(o.centre_rows.size());
    Eigen::VectorXd sv = Eigen::VectorXd::Zero(m + mc);
    for (Eigen::Index i = 0; i < m + mc; ++i) sv(i) = std::max(0.0, x(o.s.index()(i, i)) * unit);
    // PEL with the centre columns appended (interval): P (E' − L F'), F' = [F, 0].
    Eigen::MatrixXd PEL = terms.PEL, PEL_err = terms.PEL_err;
    if (mc > 0) {
      PEL.conservativeResize(n, m + mc);
      PEL_err.conservativeResize(n, m + mc);
      PEL.rightCols(mc) = d_.P * Ec;
      PEL_err.rightCols(mc) = 2.0 * ell_rounding::gamma(n + 2) * (d_.P.cwiseAbs() * Ec);
    }
    const Eigen::VectorXd s0 = sv;
    const double m_all = static_cast<double>(std::max<Eigen::Index>(1, s0.size()));
    double beta_c = beta;
    bool ok = false;
    for (double delta : kBumps) {
      beta_c = bumped_beta(delta);
      sv = s0 * (1.0 + delta) + Eigen::VectorXd::Constant(s0.size(), delta * sig_ref / m_all);
      ok = true;
      for (std::size_t j = 0; j < terms.PAL.size() && ok; ++j)
        ok = detail::ell_certify_scaled_block(d_.P, beta_c, terms.PAL[j], terms.PAL_err[j], PEL, PEL_err, sv);
      if (ok) break;
    }
    if (!ok) return OnlineOutcome::Failed;
    // Σ s_i rounded up: z⁺ᵀPz⁺ ≤ βρ_k + ωᵀ diag(s) ω ≤ βρ_k + Σ s_i. The paper's method as
    // is: it may end above the offline radius (papers.md §1.3).
    const double sigma = round_up(sv.sum() * (1.0 + 2.0 * ell_rounding::gamma(sv.size() + 1)));
    if (!data_.interval) reuse_ = {rho, beta_c, sigma, L};
    ch = {beta_c, L, sigma, round_up(round_up(beta_c * rho) + sigma)};
    return OnlineOutcome::Used;
  }
  return OnlineOutcome::Failed;
}

}  // namespace setbound
