// setbound — definitions of the functions declared in setbound/lmi/classes.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/lmi/classes.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace lmi {

SETBOUND_INLINE const SolveResult& FeasibilitySolver::solve() {
  if (orig_->structure_version() != orig_version_) build();
  else sync_values();
  const SolveResult& r = solver_->solve();
  const int m = orig_->num_vars();
  result_ = r;
  result_.x = r.x.head(m);
  result_.Z.resize(static_cast<size_t>(orig_->num_blocks()));
  const double t = r.x.size() > m ? r.x(m) : 0.0;
  if (r.status == SolveStatus::Optimal || r.status == SolveStatus::Inaccurate ||
      r.status == SolveStatus::MaxIterations || r.status == SolveStatus::NumericalError) {
    result_.margin = margin_.margin(*orig_, result_.x);
    if (result_.margin > 0) {
      result_.status = SolveStatus::Optimal;
    } else if (t > 0 && certificate(r)) {
      // t* > 0: the auxiliary dual, normalised and verified, certifies infeasibility
      // (also when the auxiliary solve stalled on an unbounded optimal face).
      result_.status = SolveStatus::Infeasible;
      result_.x.setConstant(std::numeric_limits<double>::quiet_NaN());
    } else if (r.status == SolveStatus::Optimal) {
      // t* ≈ 0 and no certified interior point: feasible at best on the boundary.
      result_.status = SolveStatus::Inaccurate;
    }
  } else if (r.status == SolveStatus::Infeasible) {
    // Only the equalities can make the auxiliary problem infeasible.
    for (int b = 0; b < orig_->num_blocks(); ++b) result_.Z[static_cast<size_t>(b)] = r.Z[static_cast<size_t>(b)];
  }
  if (result_.status != SolveStatus::Optimal && result_.status != SolveStatus::Infeasible) {
    for (int b = 0; b < orig_->num_blocks(); ++b) result_.Z[static_cast<size_t>(b)] = r.Z[static_cast<size_t>(b)];
  }
  result_.objective = t;
  return result_;
}

SETBOUND_INLINE bool FeasibilitySolver::certificate(const SolveResult& r) {
  const LmiProblem& p = *orig_;
  double nu = 0;
  for (int b = 0; b < p.num_blocks(); ++b) nu -= p.block(b).constant.cwiseProduct(r.Z[static_cast<size_t>(b)]).sum();
  if (p.num_equalities() > 0) nu -= p.eq_rhs().dot(r.y);
  if (!(nu > 0) || !std::isfinite(nu)) return false;
  Eigen::VectorXd res = Eigen::VectorXd::Zero(p.num_vars());
  for (int b = 0; b < p.num_blocks(); ++b) {
    Eigen::MatrixXd& Z = result_.Z[static_cast<size_t>(b)];
    Z = r.Z[static_cast<size_t>(b)] / nu;
    Eigen::LLT<Eigen::MatrixXd> llt(Z + 1e-14 * std::max(1.0, Z.cwiseAbs().maxCoeff()) * Eigen::MatrixXd::Identity(Z.rows(), Z.cols()));
    if (llt.info() != Eigen::Success) return false;
    for (const auto& co : p.block(b).coefficients) res(co.var) += co.dense.cwiseProduct(Z).sum();
  }
  if (p.num_equalities() > 0) {
    result_.y = r.y / nu;
    res.noalias() -= p.eq_matrix().transpose() * result_.y;
  }
  return res.cwiseAbs().maxCoeff() <= opt_.reduced_feas;
}

SETBOUND_INLINE BlockTerms FeasibilitySolver::terms_of(const LmiBlock& blk, int m) {
  BlockTerms terms;
  for (const auto& co : blk.coefficients) terms.emplace_back(co.var, co.dense);
  terms.emplace_back(m, Eigen::MatrixXd::Identity(blk.size, blk.size));
  return terms;
}

SETBOUND_INLINE void FeasibilitySolver::build() {
  const LmiProblem& p = *orig_;
  p.require_solvable();
  if (p.num_blocks() == 0) throw InvalidArgumentError("blocks: the problem has no LMI block (add at least one)");
  const int m = p.num_vars();
  aux_.reset(m + 1);
  for (const auto& blk : p.blocks()) aux_.add_block_terms(blk.constant, terms_of(blk, m));
  Eigen::MatrixXd one = Eigen::MatrixXd::Ones(1, 1);
  aux_.add_block_terms(one, {{m, one}});  // t ≥ −1 keeps the auxiliary problem bounded
  Eigen::VectorXd c = Eigen::VectorXd::Zero(m + 1);
  c(m) = 1.0;
  aux_.set_objective(c);
  if (p.num_equalities() > 0) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(p.num_equalities(), m + 1);
    A.leftCols(m) = p.eq_matrix();
    aux_.set_equalities(A, p.eq_rhs());
  }
  SolverOptions o = opt_;
  o.feasibility_var = m;
  solver_ = std::make_unique<InteriorPointSolver>(aux_, o);
  margin_.setup(p);
  orig_version_ = p.structure_version();
}

SETBOUND_INLINE void FeasibilitySolver::sync_values() {
  const LmiProblem& p = *orig_;
  const int m = p.num_vars();
  for (int b = 0; b < p.num_blocks(); ++b) aux_.update_block_terms(b, p.block(b).constant, terms_of(p.block(b), m));
  if (p.num_equalities() > 0) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(p.num_equalities(), m + 1);
    A.leftCols(m) = p.eq_matrix();
    aux_.set_equalities(A, p.eq_rhs());
  }
}

SETBOUND_INLINE SolveResult find_feasible(const LmiProblem& problem, const SolverOptions& options) {
  FeasibilitySolver s(problem, options);
  return s.solve();
}

}  // namespace lmi
}  // namespace setbound

namespace setbound {
namespace lmi {
namespace detail {

SETBOUND_INLINE bool barrier_value(BarrierTerm& t, const LmiProblem& p, const Eigen::VectorXd& x, double& value) {
  p.evaluate_block(*t.blk, x, t.F);
  t.llt.compute(t.F);
  if (t.llt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd& L = t.llt.matrixLLT();
  double ld = 0;
  for (int i = 0; i < t.blk->size; ++i) {
    if (!(L(i, i) > 0)) return false;
    ld += 2.0 * std::log(L(i, i));
  }
  value = -ld;
  return std::isfinite(value);
}

SETBOUND_INLINE void barrier_derivatives(BarrierTerm& t, Eigen::VectorXd& g, Eigen::MatrixXd& H) {
  constexpr int kLarge = 24;
  const int n = t.blk->size;
  const int k = static_cast<int>(t.blk->coefficients.size());
  t.Linv.setIdentity(n, n);
  t.llt.matrixL().solveInPlace(t.Linv);
  if (!t.arm_decided) {
    t.arm_decided = true;
    bool sparse = n > kernels::kFixedMax && k > 0;
    for (const Coefficient& co : t.blk->coefficients) sparse = sparse && co.kind == CoefficientKind::Sparse;
    if (sparse) {
      t.arms.build(*t.blk, nullptr, k);
      t.arm = 2.0 * t.arms.cost() < 0.5 * static_cast<double>(n) * n * k * k;
      if (t.arm) {
        t.gram.resize(k, k);
        t.ones.setOnes(k);
      }
    }
  }
  if (t.arm) {
    // tr F̃_i F̃_j and tr F̃_i from the arm form with T = L⁻¹ (q_r = column r of L⁻¹).
    t.arms.prepare(t.Linv.data());
    t.arms.gram(t.ones.data(), t.gram.data(), k);
    for (int j = 0; j < k; ++j) {
      const int vj = t.blk->coefficients[static_cast<size_t>(j)].var;
      g(vj) -= t.weight * t.arms.trace(j);
      for (int i = 0; i <= j; ++i) {
        const int vi = t.blk->coefficients[static_cast<size_t>(i)].var;
        const double d = t.weight * t.gram(i, j);
        H(vi, vj) += d;
        if (vi != vj) H(vj, vi) += d;
      }
    }
    return;
  }
  t.Ft.resize(static_cast<Eigen::Index>(n) * n, k);
  t.tmp.resize(n, n);
  for (int j = 0; j < k; ++j) {
    const Coefficient& co = t.blk->coefficients[static_cast<size_t>(j)];
    Eigen::Map<Eigen::MatrixXd> Fj(t.Ft.col(j).data(), n, n);
    if (co.kind == CoefficientKind::Sparse && 2 * static_cast<int>(co.entries.size()) < n) {
      // Σ f_rc (l_r l_cᵀ + l_c l_rᵀ) over the upper-triangle entries (l_r = column r of L⁻¹).
      Fj.setZero();
      for (const auto& e : co.entries) {
        const double* lr = t.Linv.data() + static_cast<long>(e.row) * n;
        const double* lc = t.Linv.data() + static_cast<long>(e.col) * n;
        for (int b = 0; b < n; ++b) {
          double* col = Fj.data() + static_cast<long>(b) * n;
          if (e.row == e.col) {
            const double f = e.value * lr[b];
            for (int a = 0; a < n; ++a) col[a] += lr[a] * f;
          } else {
            const double fc = e.value * lc[b], fr = e.value * lr[b];
            for (int a = 0; a < n; ++a) col[a] += lr[a] * fc + lc[a] * fr;
          }
        }
      }
    } else if (n <= kLarge) {
      kernels::congruence_n(n, t.Linv.data(), co.dense.data(), t.tmp.data(), Fj.data());
    } else {
      t.tmp.noalias() = co.dense * t.Linv.transpose();
      Fj.noalias() = t.Linv * t.tmp;
    }
    g(co.var) -= t.weight * Fj.trace();
  }
  // Gram matrix of the F̃_i (upper half, mirrored).
  for (int j = 0; j < k; ++j) {
    const int vj = t.blk->coefficients[static_cast<size_t>(j)].var;
    for (int i = 0; i <= j; ++i) {
      const int vi = t.blk->coefficients[static_cast<size_t>(i)].var;
      const double d = t.weight * t.Ft.col(i).dot(t.Ft.col(j));
      H(vi, vj) += d;
      if (vi != vj) H(vj, vi) += d;
    }
  }
}

}  // namespace detail
}  // namespace lmi
}  // namespace setbound

namespace setbound {
namespace lmi {

SETBOUND_INLINE SolveResult solve_maxdet(const LmiProblem& p, const SolverOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  opt.validate();
  p.require_solvable();
  if (!p.has_logdet()) throw InvalidArgumentError("logdet: the problem has no log-det term");
  const int m = p.num_vars();
  const int pe = p.num_equalities();

  // Phase I on the blocks plus G ≻ 0.
  LmiProblem ph1(m);
  for (const auto& blk : p.blocks()) {
    BlockTerms terms;
    for (const auto& co : blk.coefficients) terms.emplace_back(co.var, co.dense);
    ph1.add_block_terms(blk.constant, terms);
  }
  {
    BlockTerms terms;
    for (const auto& co : p.logdet_block().coefficients) terms.emplace_back(co.var, co.dense);
    ph1.add_block_terms(p.logdet_block().constant, terms);
  }
  if (pe > 0) ph1.set_equalities(p.eq_matrix(), p.eq_rhs());
  SolveResult res = find_feasible(ph1, opt);
  if (res.status != SolveStatus::Optimal) {
    if (res.status == SolveStatus::Infeasible) res.Z.resize(static_cast<size_t>(p.num_blocks()));
    res.iterations = res.iterations;
    res.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  int iterations = res.iterations;
  Eigen::VectorXd x = res.x;

  // Constructed in place (reserved: never moved), so the LLT members are never copied before
  // their first compute().
  std::vector<detail::BarrierTerm> terms;
  terms.reserve(p.blocks().size() + 1);
  for (const auto& blk : p.blocks()) terms.emplace_back(&blk);
  terms.emplace_back(&p.logdet_block());
  detail::BarrierTerm& G = terms.back();
  const double nu = static_cast<double>(p.degree());
  const Eigen::VectorXd& c = p.objective();

  auto phi = [&](const Eigen::VectorXd& xx, double t, double& val) {
    double v = t * c.dot(xx);
    for (auto& term : terms) {
      double b;
      if (!detail::barrier_value(term, p, xx, b)) return false;
      v += (&term == &G ? t : 1.0) * b;
    }
    val = v;
    return std::isfinite(val);
  };

  // Centring accuracy: the objective error of an approximate centre is about λ²/(2t) (λ the
  // Newton decrement of φ_t), so the final centre is computed to λ²/2 ≤ 1e-11·t. The
  // intermediate centres only start the next one: λ²/2 ≤ 1e-4 (or the final accuracy, when that is
  // looser) keeps them well inside Newton's
  // quadratic region, and saves the steps of converging them fully. When a loosely centred
  // point already meets the gap test, it is re-centred tightly at the same t before stopping.
  constexpr double kLooseCentring = 1e-4;
  bool tight = false;
  double t = 1.0;
  const double growth = 20.0;
  const int max_newton = 10 * opt.max_iterations;
  SolveStatus status = SolveStatus::MaxIterations;
  Eigen::VectorXd g(m), dx(m), xn(m);
  Eigen::MatrixXd H(m, m);
  double obj = 0, last_dec = 0;
  bool done = false;
  while (!done) {
    // Centre for the current t by damped Newton with backtracking.
    for (;;) {
      if (iterations >= max_newton ||
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > opt.time_limit) {
        done = true;
        break;
      }
      double f0;
      if (!phi(x, t, f0)) {
        status = SolveStatus::NumericalError;
        done = true;
        break;
      }
      g = t * c;
      H.setZero();
      for (auto& term : terms) {
        term.weight = (&term == &G) ? t : 1.0;
        detail::barrier_derivatives(term, g, H);
      }
      // Newton step with equalities: [H Aᵀ; A 0][dx; w] = [−g; beq − Aeq x].
      const double hs = std::max(1.0, H.diagonal().cwiseAbs().maxCoeff());
      if (pe > 0) {
        Eigen::MatrixXd KKT = Eigen::MatrixXd::Zero(m + pe, m + pe);
        KKT.topLeftCorner(m, m) = H;
        KKT.topRightCorner(m, pe) = p.eq_matrix().transpose();
        KKT.bottomLeftCorner(pe, m) = p.eq_matrix();
        Eigen::VectorXd rhs(m + pe);
        rhs.head(m) = -g;
        rhs.tail(pe) = p.eq_rhs() - p.eq_matrix() * x;
        Eigen::VectorXd sol = KKT.fullPivLu().solve(rhs);
        dx = sol.head(m);
      } else {
        Eigen::LDLT<Eigen::MatrixXd> ldlt(H + 1e-14 * hs * Eigen::MatrixXd::Identity(m, m));
        dx = ldlt.solve(-g);
      }
      if (!dx.allFinite()) {
        status = SolveStatus::NumericalError;
        done = true;
        break;
      }
      const double dec2 = dx.dot(H * dx);
      last_dec = dec2;
      ++iterations;
      const double final_tol = 1e-11 * std::max(1.0, t);
      if (dec2 / 2.0 <= (tight ? final_tol : std::max(kLooseCentring, final_tol))) break;
      // Backtracking line search (Armijo, α = 0.25, β = 0.5).
      double s = 1.0, f1 = 0;
      const double slope = g.dot(dx);
      bool accepted = false;
      for (int ls = 0; ls < 60; ++ls, s *= 0.5) {
        xn = x + s * dx;
        if (phi(xn, t, f1) && f1 <= f0 + 0.25 * s * slope) {
          accepted = true;
          break;
        }
      }
      if (!accepted) break;  // no progress possible at this t: rounding limit reached
      x = xn;
      if (x.norm() > 1e12) {
        status = SolveStatus::Unbounded;
        done = true;
        break;
      }
    }
    if (done) break;
    // Objective value and the ν/t gap of the centre.
    double ldG;
    if (!detail::barrier_value(G, p, x, ldG)) {
      status = SolveStatus::NumericalError;
      break;
    }
    obj = c.dot(x) + ldG;
    const double gap = nu / t;
    if (gap <= opt.gap_abs || gap <= opt.gap_rel * std::max(1.0, std::abs(obj))) {
      if (!tight) {
        tight = true;  // re-centre at this t to the final accuracy
        continue;
      }
      status = SolveStatus::Optimal;
      break;
    }
    t *= growth;
  }
  (void)last_dec;
  SolveResult out;
  out.status = status;
  out.iterations = iterations;
  out.x = x;
  double ldG = std::numeric_limits<double>::quiet_NaN();
  if (x.allFinite() && detail::barrier_value(G, p, x, ldG)) out.objective = c.dot(x) + ldG;
  out.gap = nu / t;
  out.relative_gap = out.gap / std::max(1.0, std::abs(out.objective));
  out.dual_objective = out.objective - out.gap;
  out.primal_residual = pe > 0 ? (p.eq_matrix() * x - p.eq_rhs()).norm() / std::max(1.0, p.eq_rhs().norm()) : 0.0;
  out.dual_residual = 0.0;
  if (pe > 0) out.y = Eigen::VectorXd::Zero(pe);
  // Dual estimate at the centre: Z_b = F_b(x)⁻¹ / t.
  out.Z.resize(static_cast<size_t>(p.num_blocks()));
  for (int b = 0; b < p.num_blocks(); ++b) {
    Eigen::MatrixXd F;
    p.evaluate_block(p.block(b), x, F);
    out.Z[static_cast<size_t>(b)] = F.inverse() / t;
  }
  if (status != SolveStatus::Optimal && status != SolveStatus::Unbounded && out.relative_gap <= opt.reduced_gap_rel)
    out.status = SolveStatus::Inaccurate;
  MarginChecker mc;
  mc.setup(p);
  out.margin = status == SolveStatus::Unbounded ? -std::numeric_limits<double>::infinity() : mc.margin(p, x);
  out.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

SETBOUND_INLINE SolveResult solve(const LmiProblem& p, const SolverOptions& opt) {
  if (p.has_logdet()) return solve_maxdet(p, opt);
  return solve_linear(p, opt);
}

SETBOUND_INLINE GevpResult solve_gevp(const LmiProblem& constraints, const Eigen::Ref<const Eigen::MatrixXd>& A0,
                             const BlockTerms& A_terms, const Eigen::Ref<const Eigen::MatrixXd>& B0,
                             const BlockTerms& B_terms, const GevpOptions& go) {
  const auto t0 = std::chrono::steady_clock::now();
  const int m = constraints.num_vars();
  if (!(go.tol > 0)) throw InvalidArgumentError("tol: must be > 0");
  if (!(go.lambda_lo < go.lambda_hi)) throw InvalidArgumentError("lambda_lo: must be < lambda_hi");
  require_shape(B0, A0.rows(), A0.cols(), "B0");
  const int n = static_cast<int>(A0.rows());
  // Union of the variables touching A or B gives a fixed structure for every λ.
  std::vector<Eigen::MatrixXd> Ai(static_cast<size_t>(m), Eigen::MatrixXd::Zero(n, n)),
      Bi(static_cast<size_t>(m), Eigen::MatrixXd::Zero(n, n));
  std::vector<char> touch(static_cast<size_t>(m), 0);
  for (const auto& [v, F] : A_terms) {
    if (v < 0 || v >= m) throw InvalidArgumentError("A_terms: variable index out of range");
    require_shape(F, n, n, "A_terms");
    Ai[static_cast<size_t>(v)] += F;
    touch[static_cast<size_t>(v)] = 1;
  }
  for (const auto& [v, F] : B_terms) {
    if (v < 0 || v >= m) throw InvalidArgumentError("B_terms: variable index out of range");
    require_shape(F, n, n, "B_terms");
    Bi[static_cast<size_t>(v)] += F;
    touch[static_cast<size_t>(v)] = 1;
  }
  LmiProblem prob(m);
  for (const auto& blk : constraints.blocks()) {
    BlockTerms terms;
    for (const auto& co : blk.coefficients) terms.emplace_back(co.var, co.dense);
    prob.add_block_terms(blk.constant, terms);
  }
  if (constraints.num_equalities() > 0) prob.set_equalities(constraints.eq_matrix(), constraints.eq_rhs());
  {
    BlockTerms bt;
    for (int v = 0; v < m; ++v)
      if (touch[static_cast<size_t>(v)]) bt.emplace_back(v, Bi[static_cast<size_t>(v)]);
    prob.add_block_terms(B0 - go.b_margin * Eigen::MatrixXd::Identity(n, n), bt);
  }
  const int lam_block = prob.add_block_terms(Eigen::MatrixXd::Identity(n, n), {});  // placeholder
  auto set_lambda = [&](double lam) {
    BlockTerms terms;
    for (int v = 0; v < m; ++v)
      if (touch[static_cast<size_t>(v)])
        terms.emplace_back(v, lam * Bi[static_cast<size_t>(v)] - Ai[static_cast<size_t>(v)]);
    prob.update_block_terms(lam_block, lam * B0 - A0, terms);
  };
  GevpResult out;
  FeasibilitySolver* fs = nullptr;
  std::unique_ptr<FeasibilitySolver> holder;
  auto feasible = [&](double lam, Eigen::VectorXd* xout, double* margin) -> int {
    set_lambda(lam);
    if (!holder) holder = std::make_unique<FeasibilitySolver>(prob, go.solver);
    fs = holder.get();
    const SolveResult& r = fs->solve();
    out.solves++;
    out.iterations += r.iterations;
    if (r.status == SolveStatus::Optimal) {
      if (xout) *xout = r.x;
      if (margin) *margin = r.margin;
      return 1;
    }
    if (r.status == SolveStatus::Infeasible) return 0;
    return -1;  // undecided
  };
  double lo = go.lambda_lo, hi = go.lambda_hi;
  Eigen::VectorXd xbest;
  double mbest = 0;
  int f_hi = feasible(hi, &xbest, &mbest);
  bool f_hi_prev_infeasible = false;
  for (int k = 0; f_hi != 1 && k < go.max_bracket; ++k) {
    f_hi_prev_infeasible = f_hi == 0;
    lo = hi;  // not certified feasible: move the upper end up (geometrically)
    hi = hi + std::max(1.0, std::abs(hi)) * 2.0;
    f_hi = feasible(hi, &xbest, &mbest);
  }
  if (f_hi != 1) {
    out.status = SolveStatus::Infeasible;
    out.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }
  bool f_lo_certified_ = f_hi_prev_infeasible;
  if (lo == go.lambda_lo) {
    Eigen::VectorXd xlo;
    double mlo = 0;
    int f_lo = feasible(lo, &xlo, &mlo);
    for (int k = 0; f_lo == 1 && k < go.max_bracket; ++k) {
      hi = lo;  // certified feasible: it becomes the upper end
      xbest = xlo;
      mbest = mlo;
      lo = lo - std::max(1.0, std::abs(lo)) * 2.0;
      f_lo = feasible(lo, &xlo, &mlo);
    }
    f_lo_certified_ = f_lo == 0;
    if (f_lo == 1) {
      out.status = SolveStatus::Unbounded;
      out.lambda = lo;
      out.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return out;
    }
  }
  // Bisection: keep the certified upper end and its point. An undecided midpoint (neither a
  // certified point nor a certificate — typical within solver accuracy of λ*) is treated as
  // a lower end, which is conservative for the returned λ (always backed by a certified
  // point); `lower` only moves on certificates.
  double lo_cert = (f_lo_certified_ ? lo : -std::numeric_limits<double>::infinity());
  while (hi - lo > go.tol * std::max(1.0, std::abs(hi))) {
    const double mid = 0.5 * (lo + hi);
    Eigen::VectorXd xm;
    double mm = 0;
    const int f = feasible(mid, &xm, &mm);
    if (f == 1) {
      hi = mid;
      xbest = xm;
      mbest = mm;
    } else {
      lo = mid;
      if (f == 0) lo_cert = mid;
    }
  }
  // Undecided midpoints left the certified lower end behind: certify points below the
  // bracket at growing distances (certificates exist at any λ < λ*, their scale grows with
  // the distance).
  const double width_target = std::max(100.0 * go.tol, 1e-3) * std::max(1.0, std::abs(hi));
  for (double d = go.tol * std::max(1.0, std::abs(hi)); hi - lo_cert > width_target && d < width_target; d *= 4.0) {
    if (feasible(lo - d, nullptr, nullptr) == 0) lo_cert = lo - d;
  }
  // Certificates cannot exist arbitrarily close to λ* (the certificate's scale ν = t* → 0),
  // so "optimal" asks for a certified lower end within max(100·tol, 1e-3) relative; the
  // certified bracket [lower, λ] is always reported.
  const bool tight = hi - lo_cert <= std::max(100.0 * go.tol, 1e-3) * std::max(1.0, std::abs(hi));
  out.status = tight ? SolveStatus::Optimal : SolveStatus::Inaccurate;
  out.lambda = hi;
  out.lower = lo_cert;
  out.x = xbest;
  out.margin = mbest;
  out.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace lmi
}  // namespace setbound
