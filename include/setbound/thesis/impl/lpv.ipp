// setbound — definitions of the functions declared in setbound/thesis/lpv.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/thesis/lpv.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace thesis {

SETBOUND_INLINE PolytopicWeights::PolytopicWeights(Eigen::MatrixXd theta)
    : theta_(std::move(theta)) {
  const Eigen::Index N = theta_.rows(), L = theta_.cols();
  if (N < 1 || L < 1) throw DimensionError("theta: expected shape (N, L) with N, L >= 1, got " +
                                           setbound::detail::shape_string(N, L));
  require_finite(theta_, "theta");
  lo_ = theta_.colwise().minCoeff().transpose();
  hi_ = theta_.colwise().maxCoeff().transpose();
  // Box: N = 2^L, every coordinate at lo or hi (lo < hi), all corners distinct.
  is_box_ = L < 30 && N == (Eigen::Index(1) << L) && (hi_.array() > lo_.array()).all();
  if (is_box_) {
    at_hi_.resize(N, L);
    std::vector<bool> seen(static_cast<size_t>(N), false);
    for (Eigen::Index i = 0; i < N && is_box_; ++i) {
      Eigen::Index code = 0;
      for (Eigen::Index j = 0; j < L; ++j) {
        if (theta_(i, j) == hi_(j)) at_hi_(i, j) = 1, code |= Eigen::Index(1) << j;
        else if (theta_(i, j) == lo_(j)) at_hi_(i, j) = 0;
        else is_box_ = false;
      }
      if (is_box_ && seen[static_cast<size_t>(code)]) is_box_ = false;
      if (is_box_) seen[static_cast<size_t>(code)] = true;
    }
  }
  scale_ = std::max(1.0, theta_.cwiseAbs().maxCoeff());
}

SETBOUND_INLINE void PolytopicWeights::compute(const Eigen::Ref<const Eigen::VectorXd>& rho, Eigen::Ref<Eigen::VectorXd> alpha) const {
  const Eigen::Index N = theta_.rows(), L = theta_.cols();
  if (rho.size() != L)
    throw DimensionError("rho: expected " + std::to_string(L) + " entries (the scheduling dimension), got " +
                         std::to_string(rho.size()));
  for (Eigen::Index j = 0; j < L; ++j)
    if (!std::isfinite(rho(j))) throw NotFiniteError("rho: entry " + std::to_string(j) + " is not finite");
  const double tol = 1e-9 * scale_;
  for (Eigen::Index j = 0; j < L; ++j)
    if (rho(j) < lo_(j) - tol || rho(j) > hi_(j) + tol) outside(rho, j);
  if (is_box_) {
    for (Eigen::Index i = 0; i < N; ++i) {
      double a = 1.0;
      for (Eigen::Index j = 0; j < L; ++j) {
        const double r = std::min(std::max(rho(j), lo_(j)), hi_(j));
        const double t = (r - lo_(j)) / (hi_(j) - lo_(j));
        a *= at_hi_(i, j) ? t : 1.0 - t;
      }
      alpha(i) = a;
    }
    return;
  }
  // LP: minimise s s.t. |Σ α_i θ_i − ρ|_j ≤ s, Σ α = 1, α ≥ 0 (s* = 0 iff ρ is inside).
  lmi::LinearProgram lp(static_cast<int>(N + 1));
  Eigen::VectorXd c = Eigen::VectorXd::Zero(N + 1);
  c(N) = 1.0;
  lp.set_objective(c);
  for (Eigen::Index j = 0; j < L; ++j) {
    lmi::LpRow up, dn;
    for (Eigen::Index i = 0; i < N; ++i) {
      up.emplace_back(static_cast<int>(i), theta_(i, j));
      dn.emplace_back(static_cast<int>(i), -theta_(i, j));
    }
    up.emplace_back(static_cast<int>(N), -1.0);
    dn.emplace_back(static_cast<int>(N), -1.0);
    lp.add_le(up, rho(j));
    lp.add_le(dn, -rho(j));
  }
  lmi::LpRow sum;
  for (Eigen::Index i = 0; i < N; ++i) {
    sum.emplace_back(static_cast<int>(i), 1.0);
    lp.add_le({{static_cast<int>(i), -1.0}}, 0.0);
  }
  lp.add_eq(sum, 1.0);
  const lmi::SolveResult res = lp.solve();
  if (res.status != lmi::SolveStatus::Optimal && res.status != lmi::SolveStatus::Inaccurate)
    throw NumericalError("rho: the LP for the polytopic weights failed");
  Eigen::VectorXd a = res.x.head(N).cwiseMax(0.0);
  a /= a.sum();
  const Eigen::VectorXd resid = theta_.transpose() * a - rho;
  if (resid.cwiseAbs().maxCoeff() > 1e-7 * scale_) {
    Eigen::Index j;
    resid.cwiseAbs().maxCoeff(&j);
    outside(rho, j);
  }
  alpha = a;
}

SETBOUND_INLINE Eigen::VectorXd PolytopicWeights::operator()(const Eigen::Ref<const Eigen::VectorXd>& rho) const {
  Eigen::VectorXd a(theta_.rows());
  compute(rho, a);
  return a;
}

SETBOUND_INLINE void PolytopicWeights::outside(const Eigen::Ref<const Eigen::VectorXd>& rho, Eigen::Index j) const {
  std::ostringstream s;
  s << "rho: (";
  for (Eigen::Index i = 0; i < rho.size(); ++i) s << (i ? ", " : "") << rho(i);
  s << ") is outside the scheduling polytope (component " << j << ", range [" << lo_(j) << ", " << hi_(j) << "])";
  throw InvalidArgumentError(s.str());
}

SETBOUND_INLINE LpvSystem::LpvSystem(std::vector<Eigen::MatrixXd> A_, std::vector<Eigen::MatrixXd> B_, std::vector<Eigen::MatrixXd> F_,
            Eigen::MatrixXd C_, Eigen::MatrixXd Z_, Eigen::MatrixXd theta_)
    : A(std::move(A_)), B(std::move(B_)), F(std::move(F_)), C(std::move(C_)), Z(std::move(Z_)),
      theta(std::move(theta_)) {
  const size_t N = A.size();
  if (N == 0) throw DimensionError("A: at least one vertex matrix is required");
  if (static_cast<size_t>(theta.rows()) != N)
    throw DimensionError("theta: expected " + std::to_string(N) + " rows (one vertex per A_i), got " +
                         std::to_string(theta.rows()));
  if (B.empty()) B.assign(N, Eigen::MatrixXd());
  if (B.size() != N) throw DimensionError("B: expected " + std::to_string(N) + " vertex matrices, got " + std::to_string(B.size()));
  if (F.size() != N) throw DimensionError("F: expected " + std::to_string(N) + " vertex matrices, got " + std::to_string(F.size()));
  // Validate each vertex through Plant (messages name the matrix and the vertex).
  for (size_t i = 0; i < N; ++i) {
    try {
      Plant p(A[i], B[i], C, F[i], Z);
      A[i] = p.A, B[i] = p.B, F[i] = p.F;
      if (i == 0) C = p.C, Z = p.Z;
    } catch (const Error& e) {
      const std::string msg = e.what();
      const auto colon = msg.find(':');
      const std::string what = msg.substr(0, colon), rest = colon == std::string::npos ? msg : msg.substr(colon);
      const std::string named = (what == "A" || what == "B" || what == "F") ? what + "[" + std::to_string(i) + "]" : what;
      throw Error(e.kind(), named + rest);
    }
    if (A[i].rows() != A[0].rows()) throw DimensionError("A[" + std::to_string(i) + "]: expected the size of A[0]");
    if (B[i].cols() != B[0].cols()) throw DimensionError("B[" + std::to_string(i) + "]: expected the columns of B[0]");
    if (F[i].cols() != F[0].cols()) throw DimensionError("F[" + std::to_string(i) + "]: expected the columns of F[0]");
  }
  weights = PolytopicWeights(theta);
}

SETBOUND_INLINE Eigen::Index LpvSystem::num_vertices() const { return static_cast<Eigen::Index>(A.size()); }

SETBOUND_INLINE Plant LpvSystem::vertex_plant(size_t i) const { return Plant(A.at(i), B.at(i), C, F.at(i), Z); }

SETBOUND_INLINE HinfGainLpv hinf_observer_gain_lpv(const LpvSystem& sys, const Eigen::MatrixXd& Q, const HinfOptions& opt) {
  opt.validate();
  const Eigen::MatrixXd Qd = hinf_detail::dissipation_or_identity(Q, sys.nx());
  for (size_t i = 0; i < sys.A.size(); ++i)
    hinf_detail::require_detectable(sys.A[i], sys.C, opt.detectability_tol, "A[" + std::to_string(i) + "], C");
  hinf_detail::VertexGainResult r =
      hinf_detail::hinf_vertex_gains(sys.A, sys.F, sys.C, sys.Z, Qd, opt, "hinf_observer_gain_lpv", false);
  HinfGainLpv h;
  h.P = std::move(r.P);
  h.Q = Qd;
  h.U = std::move(r.U);
  h.L = std::move(r.L);
  h.g = r.g;
  h.gamma = ell_rounding::round_up(std::sqrt(r.g));
  h.g_solver = r.g_solver;
  h.solve_time = r.solve_time;
  h.spectral_radius = r.spectral_radius;
  h.status = r.status;
  return h;
}

SETBOUND_INLINE EllipsoidalSMOptions default_lpv_options() {
  EllipsoidalSMOptions o;
  o.lambda_route = LambdaRoute::InputOrLogDet;
  return o;
}

SETBOUND_INLINE EllipsoidalSMDesign design_ellipsoidal_sm_observer_lpv(const LpvSystem& sys, const Eigen::VectorXd& wbar,
                                                              const EllipsoidalSMOptions& opt) {
  opt.validate();
  for (size_t i = 0; i < sys.A.size(); ++i)
    hinf_detail::require_detectable(sys.A[i], sys.C, opt.hinf.detectability_tol, "A[" + std::to_string(i) + "], C");
  return hinf_detail::design_vertices(sys.A, sys.F, sys.C, sys.Z, wbar, opt, [&](const Eigen::MatrixXd& Q) {
    return hinf_detail::hinf_vertex_gains(sys.A, sys.F, sys.C, sys.Z, Q, opt.hinf, "design_ellipsoidal_sm_observer_lpv",
                                          false);
  });
}

SETBOUND_INLINE LPVEllipsoidalSMObserver::LPVEllipsoidalSMObserver(const LpvSystem& sys, EllipsoidalSMDesign design, const Eigen::VectorXd& xhat0, double mu0)
    : design_(std::move(design)), sys_(sys) {
  const Eigen::Index n = sys.nx(), N = sys.num_vertices();
  if (design_.P.rows() != n || static_cast<Eigen::Index>(design_.L_vertices.size()) != N)
    throw DimensionError("design: its P and vertex gains do not match the LPV system (n_x = " + std::to_string(n) +
                         ", " + std::to_string(N) + " vertices)");
  for (const auto& Li : design_.L_vertices) require_shape(Li, n, sys.ny(), "design.L");
  alpha_ = Eigen::VectorXd::Zero(N);  // no step yet (a saved state holds it)
  Aa_.resize(n, n);
  Ba_.resize(n, sys.nu());
  La_.resize(n, sys.ny());
  Ao_.resize(n, n);
  absAo_.resize(n, n);
  absA_.resize(n, n);
  absB_.resize(n, sys.nu());
  absL_.resize(n, sys.ny());
  absC_ = sys.C.cwiseAbs();
  tmp_.resize(n);
  tmpu_.resize(sys.nu());
  tmpy_.resize(sys.ny());
  tmpn_.resize(n);
  Fa_.resize(n, sys.nd());
  absF_.resize(n, sys.nd());
  st_.init(design_, xhat0, mu0);
  rd_.init(design_, sys_.C, sys_.Z, st_);
}

SETBOUND_INLINE void LPVEllipsoidalSMObserver::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u,
            const Eigen::Ref<const Eigen::VectorXd>& rho) {
  if (y.size() != sys_.ny())
    throw DimensionError("y: expected " + std::to_string(sys_.ny()) + " entries, got " + std::to_string(y.size()));
  require_no_infinity(y, "y");
  hinf_detail::check_vec(u, sys_.nu(), "u");
  const bool all = rd_.screen_step(st_, sys_.C, y);  // may throw (policy Raise): nothing changed yet
  sys_.weights.compute(rho, alpha_);  // validates rho; the state is not changed yet
  const Eigen::Index N = sys_.num_vertices();
  Aa_.setZero();
  Ba_.setZero();
  La_.setZero();
  absA_.setZero();
  absB_.setZero();
  absL_.setZero();
  for (Eigen::Index i = 0; i < N; ++i) {
    const double a = alpha_(i);
    if (a == 0.0) continue;
    Aa_ += a * sys_.A[static_cast<size_t>(i)];
    Ba_ += a * sys_.B[static_cast<size_t>(i)];
    La_ += a * design_.L_vertices[static_cast<size_t>(i)];
    absA_ += a * sys_.A[static_cast<size_t>(i)].cwiseAbs();
    absB_ += a * sys_.B[static_cast<size_t>(i)].cwiseAbs();
    absL_ += a * design_.L_vertices[static_cast<size_t>(i)].cwiseAbs();
  }
  const double gk = 2.0 * ell_rounding::gamma(N + sys_.nx() + sys_.nu() + 2 * sys_.ny() + 4);
  if (!all) {
    // the step without some output (reading_screen.hpp), with A(ρ), B(ρ), F(ρ) widened by the
    // rounding of their combination (the same γ as the centre below)
    Fa_.setZero();
    absF_.setZero();
    for (Eigen::Index i = 0; i < N; ++i) {
      const double a = alpha_(i);
      if (a == 0.0) continue;
      Fa_ += a * sys_.F[static_cast<size_t>(i)];
      absF_ += a * sys_.F[static_cast<size_t>(i)].cwiseAbs();
    }
    const screen_detail::ModelWidening w{gk * absA_, gk * absB_, gk * absF_};
    rd_.fallback_step(st_, design_, Aa_, Ba_, Fa_, sys_.C, sys_.Z, y, u, &w);
    return;
  }
  Ao_ = Aa_;
  Ao_.noalias() -= La_ * sys_.C;
  st_.xnext.noalias() = Ao_ * st_.xhat;
  if (sys_.nu() > 0) st_.xnext.noalias() += Ba_ * u;
  st_.xnext.noalias() += La_ * y;
  // Centre rounding (forming the combinations, A_o and the products), a factor 2 for the
  // weights' own rounding: d = 2γ_K [(Σα|A_i| + Σα|L_i||C| + |A_o|)|x̂| + Σα|B_i||u| + Σα|L_i||y|].
  tmp_ = st_.xhat.cwiseAbs();
  tmpn_.noalias() = absC_ * tmp_;
  st_.d.noalias() = absL_ * tmpn_;
  st_.d.noalias() += absA_ * tmp_;
  absAo_ = Ao_.cwiseAbs();
  st_.d.noalias() += absAo_ * tmp_;
  if (sys_.nu() > 0) {
    tmpu_ = u.cwiseAbs();
    st_.d.noalias() += absB_ * tmpu_;
  }
  tmpy_ = y.cwiseAbs();
  st_.d.noalias() += absL_ * tmpy_;
  st_.d *= gk;
  st_.advance();
}

SETBOUND_INLINE std::vector<double> LPVEllipsoidalSMObserver::save_state() const {
  StateWriter w(StateKind::LPVEllipsoidalSMObserver, fingerprint());
  st_.save(w);
  w.vec(alpha_);
  return w.finish();
}

SETBOUND_INLINE void LPVEllipsoidalSMObserver::restore_state(const std::vector<double>& state) {
  long k = 0;
  Eigen::VectorXd xhat, alpha;
  double mu = 0;
  guard_state_memory(StateKind::LPVEllipsoidalSMObserver, [&] {
    StateReader r(state, StateKind::LPVEllipsoidalSMObserver, fingerprint());
    hinf_detail::SMState::read(r, sys_.nx(), k, xhat, mu);
    alpha = r.vec(sys_.num_vertices(), "weights");
    r.finish();
    // Convex weights of the vertices (only reported: a step recomputes them from ρ; before
    // the first step they are zeros). The tolerance covers the LP's rounding.
    if ((alpha.array() < -1e-9).any() || alpha.sum() > 1.0 + 1e-6)
      r.fail("weights must be non-negative with a sum of at most 1");
  });
  // Commit (a swap and SMState::apply: nothing throws).
  alpha_.swap(alpha);
  st_.apply(k, std::move(xhat), mu);
}

SETBOUND_INLINE StateFingerprint LPVEllipsoidalSMObserver::fingerprint() const {
  StateFingerprint f;
  for (const auto& A : sys_.A) f.add(A);
  for (const auto& B : sys_.B) f.add(B);
  for (const auto& L : design_.L_vertices) f.add(L);
  f.add(sys_.C).add(sys_.theta).add(design_.P).add(design_.e_inf).add(design_.lambda).add(design_.cbar).add(design_.lambda_max_P);
  return f;
}

}  // namespace thesis
}  // namespace setbound
