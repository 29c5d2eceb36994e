// setbound — definitions of the functions declared in setbound/thesis/hinf_gain.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/thesis/hinf_gain.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace thesis {

SETBOUND_INLINE void HinfOptions::validate() const {
  solver.validate();
  require_nonnegative(margin, "margin");
  require_nonnegative(certificate_slack, "certificate_slack");
  if (certify_attempts < 1) throw InvalidArgumentError("certify_attempts: must be >= 1");
  require_positive(detectability_tol, "detectability_tol");
}

}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {
namespace hinf_detail {

SETBOUND_INLINE double lambda_max_up(const Eigen::MatrixXd& P) {
  const double lm = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  return ell_rounding::round_up(lm + 8.0 * static_cast<double>(P.rows()) * ell_rounding::kEps * P.norm());
}

SETBOUND_INLINE double spectral_radius(const Eigen::MatrixXd& A) {
  if (A.size() == 0) return 0.0;
  return Eigen::EigenSolver<Eigen::MatrixXd>(A, false).eigenvalues().cwiseAbs().maxCoeff();
}

SETBOUND_INLINE void require_detectable(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C, double tol,
                               const std::string& name) {
  const Eigen::Index n = A.rows();
  Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
  const double scale = std::max({1.0, A.cwiseAbs().maxCoeff(), C.cwiseAbs().maxCoeff()});
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::complex<double> z = es.eigenvalues()(i);
    if (std::abs(z) < 1.0 - 1e-12) continue;
    Eigen::MatrixXcd M(n + C.rows(), n);
    M.topRows(n) = A.cast<std::complex<double>>();
    M.topRows(n).diagonal().array() -= z;
    M.bottomRows(C.rows()) = C.cast<std::complex<double>>();
    Eigen::JacobiSVD<Eigen::MatrixXcd> svd(M);
    const double smin = svd.singularValues()(n - 1);
    if (smin <= tol * scale * static_cast<double>(n)) {
      std::ostringstream s;
      s << name << ": the pair (A, C) is not detectable (the mode z = " << z.real()
        << (z.imag() >= 0 ? "+" : "") << z.imag() << "i with |z| = " << std::abs(z)
        << " >= 1 is unobservable from C); no stable observer gain exists";
      throw NotDetectableError(s.str());
    }
  }
}

SETBOUND_INLINE Eigen::MatrixXd dissipation_or_identity(const Eigen::MatrixXd& Q, Eigen::Index n) {
  if (Q.size() == 0) return Eigen::MatrixXd::Identity(n, n);
  require_shape(Q, n, n, "Q");
  require_positive_definite(Q, "Q");
  return 0.5 * (Q + Q.transpose());
}

SETBOUND_INLINE Eigen::MatrixXd dissipation_block(const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q,
                                         const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& E, double g) {
  const Eigen::Index n = P.rows(), m = E.cols();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * n + m, 2 * n + m);
  M.topLeftCorner(n, n) = P - Q;
  M.block(n, n, m, m).diagonal().setConstant(g);
  const Eigen::MatrixXd PAo = P * Ao, PE = P * E;
  M.block(n + m, 0, n, n) = -PAo;
  M.block(0, n + m, n, n) = -PAo.transpose();
  M.block(n + m, n, n, m) = -PE;
  M.block(n, n + m, m, n) = -PE.transpose();
  M.bottomRightCorner(n, n) = P;
  return M;
}

SETBOUND_INLINE bool certify_psd_scaled(const Eigen::MatrixXd& M, double slack) {
  const Eigen::Index n = M.rows();
  if (M.cols() != n || !M.allFinite()) return false;
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(M(i, i) > 0)) return false;
    d(i) = std::ldexp(1.0, -static_cast<int>(std::lround(0.5 * std::log2(M(i, i)))));
  }
  const Eigen::MatrixXd S = d.asDiagonal() * M * d.asDiagonal();
  return certify_psd(S, 0.0, slack);
}

SETBOUND_INLINE bool certify_dissipation(const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& Ao,
                                const Eigen::MatrixXd& E, double g, double slack) {
  return certify_psd_scaled(dissipation_block(P, Q, Ao, E, g), slack);
}

SETBOUND_INLINE VertexGainResult hinf_vertex_gains_once(const std::vector<Eigen::MatrixXd>& As,
                                               const std::vector<Eigen::MatrixXd>& Fs, const Eigen::MatrixXd& C,
                                               const Eigen::MatrixXd& Z, const Eigen::MatrixXd& Q,
                                               const HinfOptions& opt, const std::string& what, bool no_gain,
                                               double margin, double& needed_margin, double fixed_g) {
  const bool fixed = fixed_g > 0;
  const int n = static_cast<int>(As.front().rows());
  const int ny = static_cast<int>(C.rows());
  const int nd = static_cast<int>(Fs.front().cols());
  const int nv = static_cast<int>(Z.cols());
  const int m = nd + nv;
  const size_t N = As.size();
  lmi::Model model;
  lmi::Var P = model.symmetric(n);
  std::vector<lmi::Var> U;
  if (!no_gain)
    for (size_t i = 0; i < N; ++i) U.push_back(model.full(n, ny));
  lmi::Var g;
  if (!fixed) g = model.scalar();
  const Eigen::MatrixXd Im = Eigen::MatrixXd::Identity(m, m);
  const lmi::AffineExpr gI = fixed ? lmi::AffineExpr(Eigen::MatrixXd(fixed_g * Im)) : lmi::AffineExpr(g * Im);
  for (size_t i = 0; i < N; ++i) {
    lmi::AffineExpr PAo = P * As[i];
    if (!no_gain) PAo = PAo - U[i] * C;
    lmi::AffineExpr PE;
    if (nd > 0 && nv > 0) PE = lmi::block_matrix({{P * Fs[i], -(U[i] * Z)}});
    else if (nd > 0) PE = P * Fs[i];
    else PE = no_gain ? lmi::AffineExpr::zero(n, m) : -(U[i] * Z);
    model.add_lmi(lmi::sym_block({{P - Q}, {lmi::AffineExpr::zero(m, n), gI}, {-PAo, -PE, P}}), margin);
  }
  if (!fixed) model.minimize(g);
  const lmi::LmiProblem problem = model.build();
  // Fixed level: a feasibility problem. find_feasible stops at its first certified strictly
  // feasible iterate (Optimal) or proves infeasibility (Infeasible); anything else is "not
  // solved", never read as infeasible.
  const lmi::SolveResult res = fixed ? lmi::find_feasible(problem, opt.solver) : lmi::solve(problem, opt.solver);
  VertexGainResult out;
  out.status = res.status;
  out.iterations = res.iterations;
  out.solve_time = res.solve_time;
  if (fixed && res.status != lmi::SolveStatus::Optimal) {
    out.solved = false;
    return out;
  }
  if (res.status != lmi::SolveStatus::Optimal && res.status != lmi::SolveStatus::Inaccurate)
    // The class stays InfeasibleError for callers that skip infeasible systems; the message
    // says whether the solver proved infeasibility or stopped (iteration limit, numerics).
    throw InfeasibleError(what + ": the H-infinity LMI is " + solve_verdict(res.status) + " (solver status: " +
                          lmi::status_name(res.status) + ", " + std::to_string(res.iterations) + " iterations" +
                          (res.status == lmi::SolveStatus::MaxIterations && res.iterations < opt.solver.max_iterations
                               ? ": the time limit of " + std::to_string(static_cast<int>(opt.solver.time_limit)) +
                                     " s per solve stopped it (HinfOptions::solver.time_limit in C++)"
                               : std::string()) +
                          ")");
  out.P = model.value(P, res.x);
  symmetrize(out.P);  // not 0.5 * (P + Pᵀ) into P: that aliases (core/symmetric.hpp)
  out.g_solver = fixed ? fixed_g : model.scalar_value(g, res.x);
  Eigen::LLT<Eigen::MatrixXd> llt(out.P);
  if (llt.info() != Eigen::Success) throw NumericalError(what + ": the solver returned a P that is not positive definite");
  for (size_t i = 0; i < N; ++i) {
    if (no_gain) {
      out.U.emplace_back(Eigen::MatrixXd::Zero(n, std::max(ny, 0)));
      out.L.emplace_back(Eigen::MatrixXd::Zero(n, std::max(ny, 0)));
    } else {
      out.U.push_back(model.value(U[i], res.x));
      out.L.push_back(llt.solve(out.U.back()));
    }
  }
  // Certificate with the returned L (A_o = A − LC, E = [F, −LZ]); enlarge g if needed.
  std::vector<Eigen::MatrixXd> Aos(N), Es(N);
  for (size_t i = 0; i < N; ++i) {
    Aos[i] = no_gain ? As[i] : Eigen::MatrixXd(As[i] - out.L[i] * C);
    Es[i].resize(n, m);
    if (nd > 0) Es[i].leftCols(nd) = Fs[i];
    if (nv > 0) Es[i].rightCols(nv) = no_gain ? Eigen::MatrixXd::Zero(n, nv) : Eigen::MatrixXd(-out.L[i] * Z);
    out.spectral_radius = std::max(out.spectral_radius, spectral_radius(Aos[i]));
  }
  if (!(out.spectral_radius < 1.0))
    throw NumericalError(what + ": the gain returned by the solver does not make A - LC Schur stable (spectral radius " +
                         std::to_string(out.spectral_radius) + ")");
  double gc = std::max(out.g_solver, 0.0);
  bool ok = false;
  for (int k = 0; k < opt.certify_attempts && !ok; ++k) {
    if (k > 0) gc = gc * (1.0 + 1e-9 * std::pow(4.0, k)) + 1e-12;
    ok = true;
    for (size_t i = 0; i < N && ok; ++i) ok = certify_dissipation(out.P, Q, Aos[i], Es[i], gc, opt.certificate_slack);
  }
  // The slack the certificate subtracts (see certify_psd), for a retry with a larger margin.
  double tr = 0;
  for (size_t i = 0; i < N; ++i)
    tr = std::max(tr, dissipation_block(out.P, Q, Aos[i], Es[i], gc).diagonal().cwiseAbs().sum());
  needed_margin = (ell_rounding::gamma(2 * n + m + 1) * 4.0 + opt.certificate_slack) * tr;
  if (!ok) {  // empty P: not certified
    VertexGainResult nc;
    nc.status = out.status;
    nc.iterations = out.iterations;
    nc.solve_time = out.solve_time;
    return nc;
  }
  out.g = gc;
  return out;
}

SETBOUND_INLINE VertexGainResult hinf_vertex_gains(const std::vector<Eigen::MatrixXd>& As,
                                          const std::vector<Eigen::MatrixXd>& Fs, const Eigen::MatrixXd& C,
                                          const Eigen::MatrixXd& Z, const Eigen::MatrixXd& Q,
                                          const HinfOptions& opt, const std::string& what, bool no_gain) {
  double margin = opt.margin * std::max(1.0, Q.cwiseAbs().maxCoeff());
  double needed = 0, time = 0;
  for (int attempt = 0; attempt < 3; ++attempt) {
    VertexGainResult r = hinf_vertex_gains_once(As, Fs, C, Z, Q, opt, what, no_gain, margin, needed);
    time += r.solve_time;
    if (r.P.size() > 0) {
      r.solve_time = time;
      return r;
    }
    margin = std::max(margin * 10.0, 8.0 * needed);
  }
  throw NumericalError(what + ": the LMI solution could not be certified in floating point (margin " +
                       std::to_string(margin) + ")");
}

SETBOUND_INLINE std::string solve_verdict(lmi::SolveStatus s) {
  switch (s) {
    case lmi::SolveStatus::Infeasible: return "infeasible";
    case lmi::SolveStatus::MaxIterations: return "not solved (iteration limit)";
    default: return std::string("not solved (numerical trouble: ") + lmi::status_name(s) + ")";
  }
}

SETBOUND_INLINE void require_gamma_grid(const std::vector<double>& gammas) {
  if (gammas.empty()) throw InvalidArgumentError("gammas: the gamma grid is empty");
  if (gammas.size() > static_cast<size_t>(kMaxGammas))
    throw InvalidArgumentError("gammas: at most " + std::to_string(kMaxGammas) + " values (each one is an SDP), got " +
                               std::to_string(gammas.size()));
  for (size_t i = 0; i < gammas.size(); ++i) {
    if (!std::isfinite(gammas[i])) throw NotFiniteError("gammas: entry " + std::to_string(i) + " is not finite");
    if (!(gammas[i] > 0)) throw InvalidArgumentError("gammas: entry " + std::to_string(i) + " must be > 0");
    if (i > 0 && !(gammas[i] > gammas[i - 1]))
      throw InvalidArgumentError("gammas: must be strictly increasing (entry " + std::to_string(i) + ")");
  }
}

SETBOUND_INLINE GammaSearch first_feasible_gamma(const std::vector<Eigen::MatrixXd>& As,
                                                 const std::vector<Eigen::MatrixXd>& Fs, const Eigen::MatrixXd& C,
                                                 const Eigen::MatrixXd& Z, const Eigen::MatrixXd& Q,
                                                 const std::vector<double>& gammas, const HinfOptions& opt,
                                                 const std::string& what) {
  require_gamma_grid(gammas);
  GammaSearch out;
  double time = 0;
  int infeasible = 0, iteration_limit = 0, other = 0;
  for (const double gm : gammas) {
    GammaTrial t;
    t.gamma = gm;
    const double g2 = gm * gm;
    double margin = opt.margin * std::max(1.0, Q.cwiseAbs().maxCoeff()), needed = 0;
    for (int attempt = 0; attempt < 3; ++attempt) {
      VertexGainResult r = hinf_vertex_gains_once(As, Fs, C, Z, Q, opt, what, false, margin, needed, g2);
      t.iterations += r.iterations;
      time += r.solve_time;
      if (!r.solved) {  // the solver's verdict on this γ (with this margin)
        t.status = r.status;
        break;
      }
      if (r.P.size() > 0) {  // certified
        t.status = lmi::SolveStatus::Optimal;
        out.trials.push_back(t);
        r.solve_time = time;
        r.iterations = t.iterations;
        out.gain = std::move(r);
        return out;
      }
      t.status = lmi::SolveStatus::NumericalError;  // solved, not certified: retry with a larger margin
      margin = std::max(margin * 10.0, 8.0 * needed);
    }
    out.trials.push_back(t);
    if (t.status == lmi::SolveStatus::Infeasible) ++infeasible;
    else if (t.status == lmi::SolveStatus::MaxIterations) ++iteration_limit;
    else ++other;
  }
  std::ostringstream s;
  s << what << ": LMI (2.35) at gamma = " << gammas.front() << " .. " << gammas.back() << " (" << gammas.size()
    << " values)";
  if (iteration_limit == 0 && other == 0) {
    s << " is infeasible for every gamma of the grid (a certificate of infeasibility for each)";
    throw InfeasibleError(s.str());
  }
  s << ": no gamma gave a certified solution; infeasible at " << infeasible << ", not solved (iteration limit) at "
    << iteration_limit << ", not solved or not certified (numerical trouble) at " << other
    << " (raise the solver's max_iterations / time_limit, or give a grid that reaches larger gamma)";
  throw NumericalError(s.str());
}

}  // namespace hinf_detail
}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {

SETBOUND_INLINE HinfGain hinf_observer_gain(const Plant& plant, const Eigen::MatrixXd& Q, const HinfOptions& opt) {
  opt.validate();
  const Eigen::Index n = plant.nx();
  const Eigen::MatrixXd Qd = hinf_detail::dissipation_or_identity(Q, n);
  hinf_detail::require_detectable(plant.A, plant.C, opt.detectability_tol, "A, C");
  hinf_detail::VertexGainResult r =
      hinf_detail::hinf_vertex_gains({plant.A}, {plant.F}, plant.C, plant.Z, Qd, opt, "hinf_observer_gain", false);
  HinfGain h;
  h.P = std::move(r.P);
  h.U = std::move(r.U.front());
  h.L = std::move(r.L.front());
  h.Q = Qd;
  h.g = r.g;
  h.gamma = ell_rounding::round_up(std::sqrt(r.g));
  h.g_solver = r.g_solver;
  h.status = r.status;
  h.iterations = r.iterations;
  h.solve_time = r.solve_time;
  h.spectral_radius = r.spectral_radius;
  return h;
}

SETBOUND_INLINE std::vector<double> cora_gamma_grid() {
  // MATLAB's linspace(1, 50, 100): d1 + (0:n-1)·(d2 − d1)/(n − 1), the last point exactly d2.
  std::vector<double> g(100);
  for (int i = 0; i < 100; ++i) g[static_cast<size_t>(i)] = 1.0 + i * (49.0 / 99.0);
  g.back() = 50.0;
  return g;
}

SETBOUND_INLINE GammaGridGain hinf_observer_gain_first_feasible(const Plant& plant, const Eigen::MatrixXd& Q,
                                                                const std::vector<double>& gammas,
                                                                const HinfOptions& opt) {
  opt.validate();
  hinf_detail::require_gamma_grid(gammas);
  const Eigen::MatrixXd Qd = hinf_detail::dissipation_or_identity(Q, plant.nx());
  hinf_detail::require_detectable(plant.A, plant.C, opt.detectability_tol, "A, C");
  hinf_detail::GammaSearch r = hinf_detail::first_feasible_gamma({plant.A}, {plant.F}, plant.C, plant.Z, Qd, gammas,
                                                                 opt, "hinf_observer_gain_first_feasible");
  GammaGridGain out;
  HinfGain& h = out.gain;
  h.P = std::move(r.gain.P);
  h.U = std::move(r.gain.U.front());
  h.L = std::move(r.gain.L.front());
  h.Q = Qd;
  h.g = r.gain.g;
  h.gamma = ell_rounding::round_up(std::sqrt(r.gain.g));
  h.g_solver = r.gain.g_solver;
  h.status = r.gain.status;
  h.iterations = r.gain.iterations;
  h.solve_time = r.gain.solve_time;
  h.spectral_radius = r.gain.spectral_radius;
  out.trials = std::move(r.trials);
  return out;
}

SETBOUND_INLINE BrlRpi brl_ellipsoidal_rpi(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E, const Eigen::VectorXd& wbar,
                                  const HinfOptions& opt) {
  opt.validate();
  if (A.rows() == 0) throw DimensionError("A: the state dimension must be >= 1");
  require_square(A, "A");
  require_finite(A, "A");
  const Eigen::Index n = A.rows();
  if (E.rows() != n || E.cols() == 0)
    throw DimensionError("E: expected shape (" + std::to_string(n) + ", m) with m >= 1, got " +
                         setbound::detail::shape_string(E.rows(), E.cols()));
  require_finite(E, "E");
  if (wbar.size() != E.cols())
    throw DimensionError("wbar: expected " + std::to_string(E.cols()) + " entries (the columns of E), got " +
                         std::to_string(wbar.size()));
  require_finite(wbar, "wbar");
  if ((wbar.array() < 0).any()) throw InvalidArgumentError("wbar: the bounds must be >= 0");
  const double rho = hinf_detail::spectral_radius(A);
  if (!(rho < 1.0))
    throw InfeasibleError("A: not Schur stable (spectral radius " + std::to_string(rho) +
                          " >= 1); the bounded-real-lemma LMI (1.48) has no solution");
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  hinf_detail::VertexGainResult r = hinf_detail::hinf_vertex_gains({A}, {E}, Eigen::MatrixXd::Zero(0, n),
                                                         Eigen::MatrixXd::Zero(0, 0), I, opt, "brl_ellipsoidal_rpi", true);
  BrlRpi b;
  b.P = std::move(r.P);
  b.g = r.g;
  b.gamma = ell_rounding::round_up(std::sqrt(r.g));
  b.g_solver = r.g_solver;
  b.solve_time = r.solve_time;
  using ell_rounding::round_up;
  const double wtw = round_up(wbar.squaredNorm());
  b.level = round_up(round_up(hinf_detail::lambda_max_up(b.P) * b.g) * wtw);
  return b;
}

}  // namespace thesis
}  // namespace setbound
