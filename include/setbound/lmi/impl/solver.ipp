// setbound — definitions of the functions declared in setbound/lmi/solver.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/lmi/solver.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace lmi {

SETBOUND_INLINE const char* status_name(SolveStatus s) {
  switch (s) {
    case SolveStatus::Optimal: return "optimal";
    case SolveStatus::Infeasible: return "infeasible";
    case SolveStatus::Unbounded: return "unbounded";
    case SolveStatus::MaxIterations: return "max_iterations";
    case SolveStatus::NumericalError: return "numerical_error";
    case SolveStatus::Inaccurate: return "inaccurate";
  }
  return "unknown";
}

SETBOUND_INLINE void SolverOptions::validate() const {
  if (max_iterations <= 0) throw InvalidArgumentError("max_iterations: must be > 0");
  require_positive(time_limit, "time_limit");
  require_positive(gap_rel, "gap_rel");
  require_positive(gap_abs, "gap_abs");
  require_positive(feas, "feas");
  require_positive(reduced_gap_rel, "reduced_gap_rel");
  require_positive(reduced_gap_abs, "reduced_gap_abs");
  require_positive(reduced_feas, "reduced_feas");
  if (!(step_fraction > 0.5 && step_fraction < 1.0))
    throw InvalidArgumentError("step_fraction: must be in (0.5, 1)");
  if (threads < 1 || threads > 256) throw InvalidArgumentError("threads: must be in 1 … 256");
}

SETBOUND_INLINE void MarginChecker::setup(const LmiProblem& p) {
  const size_t nb = static_cast<size_t>(p.num_blocks());
  F_.resize(nb);
  int nmax = 0;
  for (size_t b = 0; b < nb; ++b) {
    const int n = p.block(static_cast<int>(b)).size;
    F_[b].resize(n, n);
    nmax = std::max(nmax, n);
  }
  work_.resize(static_cast<Eigen::Index>(nmax) * nmax);
  wv_.resize(nmax);
  ev_.resize(nmax);
}

SETBOUND_INLINE double MarginChecker::margin(const LmiProblem& p, const Eigen::VectorXd& x, int skip_var) {
  double lam = std::numeric_limits<double>::infinity();
  double scale = 1.0;
  const size_t nb = F_.size();
  if (nb == 0) return lam;
  for (size_t b = 0; b < nb; ++b) {
    const LmiBlock& blk = p.block(static_cast<int>(b));
    evaluate(p, blk, x, skip_var, F_[b]);
    if (!F_[b].allFinite()) return -std::numeric_limits<double>::infinity();
    const int n = static_cast<int>(F_[b].rows());
    std::copy(F_[b].data(), F_[b].data() + static_cast<long>(n) * n, work_.data());
    const double lb = kernels::sym_lambda_min(n, work_.data(), wv_.data(), ev_.data());
    if (!std::isfinite(lb)) return -std::numeric_limits<double>::infinity();
    lam = std::min(lam, lb);
    scale = std::max(scale, F_[b].cwiseAbs().maxCoeff());
  }
  // Candidates δ = λ_min − 4^k·ε·n·scale: the eigenvalue estimate is only accurate to
  // rounding, the Cholesky success is what we certify (ARCHITECTURE.md "Guarantees").
  double slack = 8.0 * std::numeric_limits<double>::epsilon() * scale;
  for (int attempt = 0; attempt < 12; ++attempt, slack *= 4.0) {
    const double delta = lam - slack;
    bool ok = true;
    for (size_t b = 0; b < nb && ok; ++b) {
      const int n = static_cast<int>(F_[b].rows());
      std::copy(F_[b].data(), F_[b].data() + static_cast<long>(n) * n, work_.data());
      for (int i = 0; i < n; ++i) work_.data()[i * (n + 1)] -= delta;  // F_b − δI (leading dim n)
      ok = kernels::cholesky(n, work_.data(), work_.data());
    }
    if (ok) return delta;
  }
  return -std::numeric_limits<double>::infinity();
}

SETBOUND_INLINE void MarginChecker::evaluate(const LmiProblem& p, const LmiBlock& blk, const Eigen::VectorXd& x, int skip_var,
                       Eigen::MatrixXd& out) {
  out = blk.constant;
  for (const auto& co : blk.coefficients) {
    if (co.var == skip_var) continue;
    const double xi = x[co.var];
    if (xi != 0.0) out.noalias() += xi * co.dense;
  }
  (void)p;
}

SETBOUND_INLINE void ArmForm::build(const LmiBlock& blk, const int* order, int count) {
  n = blk.size;
  k = count;
  start.resize(static_cast<size_t>(k) + 1);
  start[0] = 0;
  row.clear();
  gstart_.clear();
  gall_.clear();
  cnt_.assign(static_cast<size_t>(n), 0);
  is_row_.assign(static_cast<size_t>(n), 0);
  for (int j = 0; j < k; ++j) {
    const Coefficient& co = blk.coefficients[static_cast<size_t>(order ? order[j] : j)];
    ent_.clear();
    if (co.kind == CoefficientKind::Sparse) {
      ent_.assign(co.entries.begin(), co.entries.end());
    } else {
      for (int c = 0; c < n; ++c)
        for (int r = 0; r <= c; ++r)
          if (co.dense(r, c) != 0.0) ent_.push_back({r, c, co.dense(r, c)});
    }
    touched_.clear();
    for (const SparseEntry& e : ent_) {
      if (cnt_[static_cast<size_t>(e.row)]++ == 0) touched_.push_back(e.row);
      if (e.col != e.row && cnt_[static_cast<size_t>(e.col)]++ == 0) touched_.push_back(e.col);  // a diagonal entry counts once
    }
    used_.assign(ent_.size(), 0);
    size_t left = ent_.size();
    while (left > 0) {
      // The row with the most uncovered non-zeros (the lowest index among equals) becomes an arm.
      int r = -1;
      for (int v : touched_)
        if (cnt_[static_cast<size_t>(v)] > 0 &&
            (r < 0 || cnt_[static_cast<size_t>(v)] > cnt_[static_cast<size_t>(r)] ||
             (cnt_[static_cast<size_t>(v)] == cnt_[static_cast<size_t>(r)] && v < r)))
          r = v;
      if (r < 0) break;  // cannot happen (every uncovered entry counts in its rows)
      row.push_back(r);
      const size_t g0 = gall_.size();
      gstart_.push_back(static_cast<int>(g0));
      for (size_t i = 0; i < ent_.size(); ++i) {
        const SparseEntry& e = ent_[i];
        if (used_[i] || (e.row != r && e.col != r)) continue;
        used_[i] = 1;
        --left;
        --cnt_[static_cast<size_t>(r)];
        if (e.row == e.col) {
          gall_.emplace_back(r, 0.5 * e.value);
        } else {
          const int other = e.row == r ? e.col : e.row;
          --cnt_[static_cast<size_t>(other)];
          gall_.emplace_back(other, e.value);
        }
      }
      std::sort(gall_.begin() + static_cast<long>(g0), gall_.end());
    }
    for (int v : touched_) cnt_[static_cast<size_t>(v)] = 0;
    start[static_cast<size_t>(j) + 1] = static_cast<int>(row.size());
  }
  const int na = static_cast<int>(row.size());
  gstart_.push_back(static_cast<int>(gall_.size()));
  // Equal vectors g are stored once: sorted by a hash of their entries, then compared.
  hash_.resize(static_cast<size_t>(na));
  for (int a = 0; a < na; ++a) {
    std::uint64_t h = 1469598103934665603ull;
    for (int t = gstart_[static_cast<size_t>(a)]; t < gstart_[static_cast<size_t>(a) + 1]; ++t) {
      std::uint64_t bits;
      const double v = gall_[static_cast<size_t>(t)].second + 0.0;  // −0 as +0
      std::memcpy(&bits, &v, sizeof bits);
      for (std::uint64_t x : {static_cast<std::uint64_t>(gall_[static_cast<size_t>(t)].first), bits}) {
        h ^= x;
        h *= 1099511628211ull;
        h ^= h >> 29;
      }
    }
    hash_[static_cast<size_t>(a)] = h;
  }
  auto same = [&](int a, int b) {
    const int la = gstart_[static_cast<size_t>(a) + 1] - gstart_[static_cast<size_t>(a)];
    const int lb = gstart_[static_cast<size_t>(b) + 1] - gstart_[static_cast<size_t>(b)];
    return la == lb && std::equal(gall_.begin() + gstart_[static_cast<size_t>(a)],
                                  gall_.begin() + gstart_[static_cast<size_t>(a) + 1],
                                  gall_.begin() + gstart_[static_cast<size_t>(b)]);
  };
  order_.resize(static_cast<size_t>(na));
  for (int a = 0; a < na; ++a) order_[static_cast<size_t>(a)] = a;
  std::sort(order_.begin(), order_.end(), [&](int a, int b) {
    return hash_[static_cast<size_t>(a)] != hash_[static_cast<size_t>(b)] ? hash_[static_cast<size_t>(a)] < hash_[static_cast<size_t>(b)]
                                                                          : a < b;
  });
  vec.assign(static_cast<size_t>(na), -1);
  nvec = 0;
  for (int i = 0; i < na; ++i) {
    const int a = order_[static_cast<size_t>(i)];
    // Compare with the representatives of the run of equal hashes seen so far.
    for (int i2 = i - 1; i2 >= 0 && hash_[static_cast<size_t>(order_[static_cast<size_t>(i2)])] == hash_[static_cast<size_t>(a)]; --i2) {
      const int b = order_[static_cast<size_t>(i2)];
      if (same(a, b)) {
        vec[static_cast<size_t>(a)] = vec[static_cast<size_t>(b)];
        break;
      }
    }
    if (vec[static_cast<size_t>(a)] < 0) vec[static_cast<size_t>(a)] = nvec++;
  }
  if (G.rows() != n || G.cols() < nvec) G.resize(n, std::max<Eigen::Index>(nvec, G.cols()));
  G.leftCols(nvec).setZero();
  for (int a = 0; a < na; ++a)
    for (int t = gstart_[static_cast<size_t>(a)]; t < gstart_[static_cast<size_t>(a) + 1]; ++t)
      G(gall_[static_cast<size_t>(t)].first, vec[static_cast<size_t>(a)]) = gall_[static_cast<size_t>(t)].second;
  for (Eigen::MatrixXd* M : {&H, &WG})
    if (M->rows() != n || M->cols() < nvec) M->resize(n, G.cols());
  if (HH.rows() < nvec) HH.resize(G.cols(), G.cols());
  if (W.rows() != n) W.resize(n, n);
}

SETBOUND_INLINE double ArmForm::cost() const {
  const double na = static_cast<double>(row.size()), nn = n, u = nvec;
  double pairs = 0;  // Σ_{i ≤ j} arms_i·arms_j ≈ na²/2, two multiply-adds each
  pairs = na * na;
  return pairs + 2.0 * na * nn * (nn + 1) / 2 + nn * nn * nn + 2.0 * nn * nn * u + nn * u * u;
}

SETBOUND_INLINE void ArmForm::prepare(const double* T) {
  Eigen::Map<const Eigen::MatrixXd> Tm(T, n, n);
  W.noalias() = Tm.transpose() * Tm;
  if (nvec == 0) return;
  H.leftCols(nvec).noalias() = Tm * G.leftCols(nvec);
  WG.leftCols(nvec).noalias() = Tm.transpose() * H.leftCols(nvec);
  HH.topLeftCorner(nvec, nvec).noalias() = H.leftCols(nvec).transpose() * H.leftCols(nvec);
}

SETBOUND_INLINE void ArmForm::gram(const double* s, double* out, long ldg) const {
  const double* Wd = W.data();
  const double* WGd = WG.data();
  const double* HHd = HH.data();
  const long ldw = W.rows(), ldwg = WG.rows(), ldh = HH.rows();
  for (int j = 0; j < k; ++j) {
    const int b0 = start[static_cast<size_t>(j)], b1 = start[static_cast<size_t>(j) + 1];
    for (int i = 0; i <= j; ++i) {
      double acc = 0.0;
      for (int a = start[static_cast<size_t>(i)]; a < start[static_cast<size_t>(i) + 1]; ++a) {
        const int ra = row[static_cast<size_t>(a)], ua = vec[static_cast<size_t>(a)];
        const double* Wa = Wd + static_cast<long>(ra) * ldw;      // W(·, r_a) = W(r_a, ·)
        const double* HHa = HHd + static_cast<long>(ua) * ldh;    // HH(·, u_a)
        const double* WGa = WGd + static_cast<long>(ua) * ldwg;   // WG(·, u_a)
        for (int b = b0; b < b1; ++b) {
          const int rb = row[static_cast<size_t>(b)], ub = vec[static_cast<size_t>(b)];
          acc += Wa[rb] * HHa[ub] + WGd[ra + static_cast<long>(ub) * ldwg] * WGa[rb];
        }
      }
      out[i + static_cast<long>(j) * ldg] = 2.0 * s[i] * s[j] * acc;
    }
  }
}

SETBOUND_INLINE void ArmForm::svec_column(int j, const double* T, double s, double* out) const {
  const int sv = kernels::svec_size(n);
  std::fill(out, out + sv, 0.0);
  for (int a = start[static_cast<size_t>(j)]; a < start[static_cast<size_t>(j) + 1]; ++a) {
    const double* q = T + static_cast<long>(row[static_cast<size_t>(a)]) * n;
    const double* h = H.data() + static_cast<long>(vec[static_cast<size_t>(a)]) * H.rows();
    int idx = 0;
    for (int c = 0; c < n; ++c) {
      const double qc = q[c], hc = h[c];
      out[idx++] += 2.0 * qc * hc;
      for (int r = c + 1; r < n; ++r) out[idx++] += q[r] * hc + h[r] * qc;
    }
  }
  int idx = 0;
  for (int c = 0; c < n; ++c) {
    out[idx++] *= s;
    for (int r = c + 1; r < n; ++r) out[idx++] *= s * kernels::kSqrt2;
  }
}

SETBOUND_INLINE double ArmForm::trace(int j) const {
  double t = 0.0;
  for (int a = start[static_cast<size_t>(j)]; a < start[static_cast<size_t>(j) + 1]; ++a)
    t += WG(row[static_cast<size_t>(a)], vec[static_cast<size_t>(a)]);
  return 2.0 * t;
}

SETBOUND_INLINE Eigen::Index InteriorPointSolver::BlockWork::vrow(int slot, int r) const {
  return il ? static_cast<Eigen::Index>(r) * cp + slot : static_cast<Eigen::Index>(slot) * n + r;
}

SETBOUND_INLINE void InteriorPointSolver::congruence_t(int n, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& X, Eigen::MatrixXd& T, double* C) {
  if (n <= kLargeBlock) return kernels::congruence_t(n, Q.data(), X.data(), T.data(), C);
  Eigen::Map<Eigen::MatrixXd> Cm(C, n, n);
  T.noalias() = X * Q;
  Cm.noalias() = Q.transpose() * T;
}

SETBOUND_INLINE void InteriorPointSolver::congruence_n(int n, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& X, Eigen::MatrixXd& T, Eigen::MatrixXd& C) {
  if (n <= kLargeBlock) return kernels::congruence_n(n, Q.data(), X.data(), T.data(), C.data());
  T.noalias() = X * Q.transpose();
  C.noalias() = Q * T;
  T = 0.5 * (C + C.transpose());
  C = T;
}

SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::setup() {
  const LmiProblem& p = *p_;
  p.require_solvable();
  m_ = p.num_vars();
  pe_ = p.num_equalities();
  nu_ = p.degree();
  const size_t nb = static_cast<size_t>(p.num_blocks());
  w_.clear();
  w_.resize(nb);
  for (size_t b = 0; b < nb; ++b) {
    const LmiBlock& blk = p.block(static_cast<int>(b));
    BlockWork& w = w_[b];
    const int n = blk.size;
    w.n = n;
    w.k = static_cast<int>(blk.coefficients.size());
    w.sv = kernels::svec_size(n);
    w.col.assign(static_cast<size_t>(w.k), 0);
    w.var.assign(static_cast<size_t>(w.k), 0);
    for (Eigen::MatrixXd* M : {&w.S, &w.Z, &w.dS, &w.dZ, &w.rz, &w.R, &w.Q, &w.Qt, &w.Ls, &w.Lz, &w.tmp, &w.tmp2,
                               &w.Wds, &w.Wdz, &w.Wds_a, &w.Wdz_a, &w.U, &w.best_Z})
      M->setZero(n, n);
    w.il = n <= kernels::kInterleavedMax;
    w.cp = kernels::gram_padded(w.k) + 4;  // ≥ k + 2 columns, and the Gram tiles' reach from column 2
    w.V.setZero(static_cast<Eigen::Index>(n) * (w.il ? w.cp : w.k + 2), n);  // room for every coefficient dense
    w.P.setZero(w.V.rows(), n);
    w.T.setZero(w.V.rows(), n);
    w.Fs.setZero(w.sv, w.cp);
    w.f0.setZero(w.sv);
    w.As.setZero(w.sv, w.k);
    w.G.setZero(w.k, w.k);
    for (Eigen::VectorXd* v : {&w.a0, &w.ss, &w.zs, &w.rs, &w.bs, &w.ws}) v->setZero(w.sv);
    for (Eigen::VectorXd* v : {&w.xl, &w.gl, &w.f0f}) v->setZero(w.k);
    w.cs.assign(static_cast<size_t>(w.k), 1.0);
    for (Eigen::VectorXd* v : {&w.lambda, &w.isq, &w.wv, &w.ev}) v->setZero(n);
  }
  margin_.setup(p);
  for (Eigen::VectorXd* v : {&c_, &d_, &xo_, &x_, &rx_, &g_, &t1_, &t2_, &r1_, &cdx_, &x1_, &dx_, &dx_a_, &bx_, &best_x_, &xhat_})
    v->setZero(m_);
  for (Eigen::VectorXd* v : {&r_, &beq_, &yo_, &y_, &ry_, &gy_, &t3_, &ry2_, &r2_, &cdy_, &y1_, &dy_, &dy_a_, &by_, &best_y_})
    v->setZero(pe_);
  M_.setZero(m_, m_);
  K_.setZero(m_, m_);
  Lk_.setZero(m_ <= kSmallSchur ? m_ : 0, m_ <= kSmallSchur ? m_ : 0);
  Uk_.setZero(Lk_.rows(), Lk_.cols());
  Ldinv_.setZero(m_);
  // Factorise identities once so that the LLT objects own storage of the right size (no
  // allocation in solve()); move-assigning size-only LLT temporaries copied uninitialised
  // flags (UBSan).
  K_.setIdentity();
  if (m_ > kSmallSchur) lltK_.compute(K_);
  KinvAt_.setZero(m_, pe_);
  SA_.setZero(pe_, pe_);
  SA_.setIdentity();
  lltSA_.compute(SA_);
  AtA_.setZero(m_, m_);
  Aeq_.setZero(pe_, m_);
  result_.x.setZero(m_);
  result_.y.setZero(pe_);
  result_.Z.resize(nb);
  for (size_t b = 0; b < nb; ++b) result_.Z[b].setZero(w_[b].n, w_[b].n);
  part_.clear();
  allocate_partials();
  version_ = p.structure_version();
  values_loaded_ = ~std::uint64_t{0};  // the arrays above are zero: re-read at the next solve
}

// The starting point of CVXOPT's conelp (and Clarabel's for symmetric cones): with the scaling
// W = I (S = Z = I), the primal point minimises ‖F(x)‖_F subject to Ax = b and the dual point
// minimises ‖Z‖_F subject to tr(F_i Z) = c_i + (Aᵀy)_i; each is then shifted into the interior
// by (1 + t)I when its smallest eigenvalue −t is not safely positive. τ = κ = 1. Both are
// solves with the W = I Schur complement (one factorisation). Compared with the unit start
// x = 0, S = Z = I it saved 2–3 of 11–19 iterations on the online problems of papers.md §1.3
// and on random dense LMIs (bench/bench_lmi.py).
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::least_squares_start() {
  auto unit_start = [&] {
    x_.setZero();
    y_.setZero();
    for (auto& w : w_) {
      w.S.setIdentity();
      w.Z.setIdentity();
    }
    tau_ = kappa_ = 1.0;
  };
  unit_start();
  residuals();
  if (!scale_and_assemble()) return unit_start();
  bx_.setZero();
  if (pe_ > 0) by_ = beq_;
  kkt_solve(bx_, by_, true, 0.0, false, x1_, y1_);  // primal: x1 (S = F(x1))
  bx_ = -c_;
  if (pe_ > 0) by_.setZero();
  kkt_solve(bx_, by_, false, 0.0, false, dx_, dy_);  // dual: Z = −Σ dx_i F_i, y = dy
  if (!x1_.allFinite() || !dx_.allFinite() || !dy_.allFinite()) return unit_start();
  double ts = -std::numeric_limits<double>::infinity(), tz = ts, ns = 0, nz = 0;
  for (auto& w : w_) {
    // S = F̂(x1), Z = −Σ dx_i F̂_i (equilibrated data, in svec)
    for (int j = 0; j < w.k; ++j) w.xl(j) = x1_(w.var[static_cast<size_t>(j)]);
    w.ws = w.a0;
    kernels::gemv_n_add(w.sv, w.k, 1.0, w.As.data(), w.xl.data(), w.ws.data());
    kernels::svec_unpack(w.n, w.ws.data(), w.S.data());
    for (int j = 0; j < w.k; ++j) w.xl(j) = dx_(w.var[static_cast<size_t>(j)]);
    w.ws.setZero();
    kernels::gemv_n_add(w.sv, w.k, -1.0, w.As.data(), w.xl.data(), w.ws.data());
    kernels::svec_unpack(w.n, w.ws.data(), w.Z.data());
    w.tmp = w.S;
    ts = std::max(ts, -kernels::sym_lambda_min(w.n, w.tmp.data(), w.wv.data(), w.ev.data()));
    w.tmp = w.Z;
    tz = std::max(tz, -kernels::sym_lambda_min(w.n, w.tmp.data(), w.wv.data(), w.ev.data()));
    ns += w.S.squaredNorm();
    nz += w.Z.squaredNorm();
  }
  if (!std::isfinite(ts) || !std::isfinite(tz) || !std::isfinite(ns) || !std::isfinite(nz)) return unit_start();
  const double shift_s = ts >= -1e-8 * std::max(std::sqrt(ns), 1.0) ? 1.0 + ts : 0.0;
  const double shift_z = tz >= -1e-8 * std::max(std::sqrt(nz), 1.0) ? 1.0 + tz : 0.0;
  for (auto& w : w_) {
    w.S.diagonal().array() += shift_s;
    w.Z.diagonal().array() += shift_z;
  }
  x_ = x1_;
  if (pe_ > 0) y_ = dy_;
  tau_ = kappa_ = 1.0;
}

// Ruiz equilibration, as Clarabel does it (CVXOPT does not): the problem is solved in the
// variables x̂ = D⁻¹x with every block multiplied by a scalar e_b (keeps the cone) and every
// equality row by r_j. Five sweeps (Clarabel: ten; five did as well here, at half the cost)
// scale the rows (svec entries, equality rows) and columns
// (variables) of the constraint data by the inverse square roots of their largest entries
// (a norm below 1e-4 is left alone, scalings stay below 1e4); a block's scale is then the mean
// of its rows' scales. On the online ellipsoidal LMIs of papers.md §1.2 (which mix P̂ ~ 1 with
// disturbance terms ~ 1e-2) it saved a fifth of the iterations. Works on the svec data held in
// As (load_values()); termination is judged in the problem's own units (residuals()).
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::equilibrate() {
  const LmiProblem& p = *p_;
  d_.setOnes();
  if (pe_ > 0) r_.setOnes();
  for (auto& w : w_) w.ws.setOnes();  // per-row (svec entry) scales during the sweeps
  constexpr double lo = 1e-4, hi = 1e4;
  auto limit = [&](double v) { return v < lo ? 1.0 : std::min(v, hi); };
  for (int sweep = 0; sweep < 5; ++sweep) {
    xo_.setZero();  // column maxima
    for (auto& w : w_) {
      for (int j = 0; j < w.k; ++j) {
        const int v = w.var[static_cast<size_t>(j)];
        const double* a = w.As.col(j).data();
        double cm = 0;
        for (int t = 0; t < w.sv; ++t) {
          const double x = std::abs(a[t]) * w.ws(t);
          cm = std::max(cm, x);
          w.bs(t) = j == 0 ? x * d_(v) : std::max(w.bs(t), x * d_(v));  // row maxima
        }
        xo_(v) = std::max(xo_(v), cm * d_(v));
      }
      if (w.k == 0) continue;
      for (int t = 0; t < w.sv; ++t) w.ws(t) /= std::sqrt(limit(w.bs(t)));
    }
    for (int j = 0; j < pe_; ++j) {
      double rm = 0;
      for (int i = 0; i < m_; ++i) {
        const double a = r_(j) * d_(i) * std::abs(p.eq_matrix()(j, i));
        xo_(i) = std::max(xo_(i), a);
        rm = std::max(rm, a);
      }
      r_(j) /= std::sqrt(limit(rm));
    }
    for (int i = 0; i < m_; ++i) d_(i) /= std::sqrt(limit(xo_(i)));
  }
  for (auto& w : w_) {
    w.e = w.ws.mean();
    if (!(w.e > 0) || !std::isfinite(w.e)) w.e = 1.0;
  }
  for (int i = 0; i < m_; ++i)
    if (!(d_(i) > 0) || !std::isfinite(d_(i))) d_(i) = 1.0;
  for (int j = 0; j < pe_; ++j)
    if (!(r_(j) > 0) || !std::isfinite(r_(j))) r_(j) = 1.0;
  // Apply: coefficients e_b d_i F_bi (As, the stacked V), constants e_b F_b0, cost D c.
  for (auto& w : w_) {
    const int n = w.n;
    for (int j = 0; j < w.k; ++j) {
      w.cs[static_cast<size_t>(j)] = w.e * d_(w.var[static_cast<size_t>(j)]);
      w.As.col(j) *= w.cs[static_cast<size_t>(j)];
    }
    w.a0 *= w.e;
    for (int c = 0; c < n; ++c)
      for (int r = 0; r < n; ++r) w.V(w.vrow(0, r), c) *= w.e;
    for (int j = 0; j < w.kd; ++j)
      for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) w.V(w.vrow(2 + j, r), c) *= w.cs[static_cast<size_t>(j)];
  }
  if (pe_ > 0) {
    Aeq_ = r_.asDiagonal() * p.eq_matrix() * d_.asDiagonal();
    beq_ = r_.cwiseProduct(p.eq_rhs());
    AtA_.noalias() = Aeq_.transpose() * Aeq_;
  }
}

// Copies the problem's current values into the solver's stacked / svec forms (equilibrate()
// then scales them) and orders each block's coefficients (dense first). Runs at the start of
// every solve: values may have been updated since setup (no allocation: every array was sized
// for the worst case).
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::load_values() {
  const LmiProblem& p = *p_;
  for (size_t b = 0; b < w_.size(); ++b) {
    const LmiBlock& blk = p.block(static_cast<int>(b));
    BlockWork& w = w_[b];
    const int n = w.n;
    const long rows = w.V.rows();
    int t = 0;
    for (int pass = 0; pass < 2; ++pass)
      for (int j = 0; j < w.k; ++j) {
        const Coefficient& co = blk.coefficients[static_cast<size_t>(j)];
        if ((co.kind == CoefficientKind::Dense) != (pass == 0)) continue;
        w.col[static_cast<size_t>(t)] = j;
        w.var[static_cast<size_t>(t)] = co.var;
        kernels::svec_pack(n, co.dense.data(), w.As.col(t).data());
        ++t;
      }
    w.var0 = w.k > 0 ? w.var[0] : -1;
    for (int j = 1; j < w.k && w.var0 >= 0; ++j)
      if (w.var[static_cast<size_t>(j)] != w.var0 + j) w.var0 = -1;
    w.kd = 0;
    for (int j = 0; j < w.k; ++j)
      if (blk.coefficients[static_cast<size_t>(w.col[static_cast<size_t>(j)])].kind == CoefficientKind::Dense) ++w.kd;
    // V: slot 0 = F0, slot 1 = rz (per iteration), slots 2… = dense coefficients; the slots of
    // coefficients that are sparse now are zeroed (their columns of Fs are filled from entries).
    auto put = [&](int slot, const Eigen::MatrixXd* F) {
      for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) w.V(w.vrow(slot, r), c) = F ? (*F)(r, c) : 0.0;
    };
    put(0, &blk.constant);
    for (int j = 0; j < w.k; ++j)
      put(2 + j, j < w.kd ? &blk.coefficients[static_cast<size_t>(w.col[static_cast<size_t>(j)])].dense : nullptr);
    (void)rows;
    kernels::svec_pack(n, blk.constant.data(), w.a0.data());
    // Arm form (ArmForm) for a block beyond the fixed-size kernels whose coefficients are all
    // sparse (then `col` is the identity), where its cost estimate is below half that of the Gram
    // product of the dense scaled coefficients (the Gram kernel runs near peak, the arm sums do not).
    w.arm = false;
    if (n > kernels::kFixedMax && w.kd == 0 && w.k > 0) {
      w.arms.build(blk, nullptr, w.k);
      const double gram = static_cast<double>(w.sv) * w.k * w.k;
      w.arm = 2.0 * w.arms.cost() < gram;
    }
  }
}

// With alpha > 0, first applies the last step to each block's S and Z:
// ds = R (W⁻ᵀds) Rᵀ, dz = Q (W dz) Qᵀ (x, y, τ, κ are updated by the caller).
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::residuals(double alpha) {
  // rx = Aᵀy + Gᵀz + cτ;  ry = bτ − Ax;  rz = S − (F0 τ + Σ x_i F_i);  rτ = κ + cᵀx + bᵀy + hᵀz
  // In svec form (kernels.hpp): ⟨F_j, Z⟩ = svec(F_j)ᵀsvec(Z), one product per block.
  rx_ = c_ * tau_;
  for_block_ranges([&](int t, int begin, int end) {
    Partial& pt = part_[static_cast<size_t>(t)];
    Eigen::VectorXd& rx = t == 0 ? rx_ : pt.v;
    if (t > 0) rx.setZero();
    pt.hz = pt.sz = pt.rn = 0.0;
    for (int b = begin; b < end; ++b) {
      BlockWork& w = w_[static_cast<size_t>(b)];
      if (pending_best_z_) w.best_Z = w.Z * (w.e * best_z_scale_);
      if (alpha > 0.0) {
        congruence_n(w.n, w.R, w.Wds, w.tmp, w.dS);  // symmetric by construction
        congruence_n(w.n, w.Q, w.Wdz, w.tmp, w.dZ);
        w.S += alpha * w.dS;
        w.Z += alpha * w.dZ;
      }
      kernels::svec_pack(w.n, w.S.data(), w.ss.data());
      kernels::svec_pack(w.n, w.Z.data(), w.zs.data());
      for (int j = 0; j < w.k; ++j) w.xl(j) = x_(w.var[static_cast<size_t>(j)]);
      kernels::gemv_t(w.sv, w.k, w.As.data(), w.zs.data(), w.gl.data());
      w.rs = w.ss - tau_ * w.a0;
      kernels::gemv_n_add(w.sv, w.k, -1.0, w.As.data(), w.xl.data(), w.rs.data());
      kernels::svec_unpack(w.n, w.rs.data(), w.rz.data());
      scatter_sub(w, rx);
      pt.hz += w.a0.dot(w.zs);
      pt.sz += w.ss.dot(w.zs);
      pt.rn += w.rs.squaredNorm() / (w.e * w.e);  // in the problem's units (equilibrate())
    }
  });
  pending_best_z_ = false;
  double hz = 0, sz = 0, rznorm2 = 0;
  for (size_t t = 0; t < used_; ++t) {
    if (t > 0) rx_ += part_[t].v;  // the partials hold −Σ gl
    hz += part_[t].hz;
    sz += part_[t].sz;
    rznorm2 += part_[t].rn;
  }
  hz_ = hz;
  sz_ = sz;
  double by = 0;
  if (pe_ > 0) {
    rx_.noalias() += Aeq_.transpose() * y_;
    ry_ = beq_ * tau_;
    ry_.noalias() -= Aeq_ * x_;
    by = beq_.dot(y_);
  }
  rtau_ = kappa_ + c_.dot(x_) + by + hz;
  // Metrics of the current iterate (x/τ, y/τ, z/τ).
  pcost_ = c_.dot(x_) / tau_;
  dcost_ = -(by + hz) / tau_;
  gap_ = sz / (tau_ * tau_);
  const double pres_y = pe_ > 0 ? ry_.cwiseQuotient(r_).norm() / resy0_ : 0.0;
  pres_ = std::max(pres_y, std::sqrt(rznorm2) / resz0_) / tau_;
  dres_ = rx_.cwiseQuotient(d_).norm() / resx0_ / tau_;
  const double dgap = std::max(gap_, std::abs(pcost_ - dcost_));
  relgap_ = dgap / std::max(1.0, std::min(std::abs(pcost_), std::abs(dcost_)));
}

// One Partial per thread that for_block_ranges will use (allocates only when that number or
// the problem's size changed: setup(), or set_options() with another thread count).
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::allocate_partials() {
  int nt = 1;
#if defined(_OPENMP)
  nt = std::max(1, std::min(opt_.threads, static_cast<int>(w_.size())));
#endif
  if (static_cast<int>(part_.size()) == nt && (nt == 1 || part_[1].v.size() == m_)) return;
  part_.assign(static_cast<size_t>(nt), Partial{});
  for (size_t t = 1; t < part_.size(); ++t) {
    part_[t].M.setZero(m_, m_);
    part_[t].v.setZero(m_);
  }
}

// M += block w's Gram matrix (upper half of its k×k G), scattered by its variables into the
// upper triangle of M only (factor_assembled mirrors the sum once).
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::scatter_schur(const BlockWork& w, Eigen::MatrixXd& M) const {
  if (w.var0 >= 0) {  // a contiguous run of variables (all of them, in a dense problem): by columns
    for (int j = 0; j < w.k; ++j) M.col(w.var0 + j).segment(w.var0, j + 1) += w.G.col(j).head(j + 1);
    return;
  }
  for (int j = 0; j < w.k; ++j) {
    const int vj = w.var[static_cast<size_t>(j)];
    for (int i = 0; i <= j; ++i) {
      const int vi = w.var[static_cast<size_t>(i)];
      M(std::min(vi, vj), std::max(vi, vj)) += w.G(i, j);
    }
  }
}

// g −= block w's gl, scattered by its variables.
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::scatter_sub(const BlockWork& w, Eigen::VectorXd& g) const {
  for (int j = 0; j < w.k; ++j) g(w.var[static_cast<size_t>(j)]) -= w.gl(j);
}

// NT scaling of block w, first part: the Cholesky factors L_s, L_z, G = L_zᵀ L_s (in tmp) and
// H = GᵀG = L_sᵀ Z L_s (in tmp2), whose eigen-decomposition V Λ² Vᵀ (V over H in tmp2, Λ² in
// wv) scale_block_finish() takes. false if S or Z is not positive definite.
SETBOUND_INLINE bool InteriorPointSolver:: InteriorPointSolver::scale_block_factor(BlockWork& w) {
  const int n = w.n;
  double* Ls = w.Ls.data();
  double* Lz = w.Lz.data();
  if (!kernels::cholesky(n, w.S.data(), Ls) || !kernels::cholesky(n, w.Z.data(), Lz)) return false;
  double* G = w.tmp.data();
  kernels::mul_tn(n, Lz, Ls, G);
  kernels::mul_tn(n, G, G, w.tmp2.data());
  return true;
}

// Second part, after the eigen-decomposition of H (eig_ok: it succeeded): Λ, R = L_s V Λ^{-1/2}
// and Q = L_s⁻ᵀ V Λ^{1/2}. false if the scaling cannot be formed.
SETBOUND_INLINE bool InteriorPointSolver:: InteriorPointSolver::scale_block_finish(BlockWork& w, bool eig_ok) {
  const int n = w.n;
  double* Ls = w.Ls.data();
  double* G = w.tmp.data();
  double* V = w.tmp2.data();
  bool ok = eig_ok;
  if (ok) {
    const double lo = w.wv.minCoeff(), hi = w.wv.maxCoeff();
    ok = lo > 1e-10 * hi;
    if (ok) w.lambda = w.wv.cwiseSqrt();
  }
  if (!ok) {
    // Badly centred pair: the squared singular values lose the small ones; the one-sided
    // Jacobi SVD of G itself (still in tmp: the eigensolvers only wrote V) keeps them accurate.
    if (!kernels::one_sided_jacobi(n, G, V, w.lambda.data())) return false;
  }
  for (int i = 0; i < n; ++i) {
    const double l = w.lambda(i);
    if (!(l > 0) || !std::isfinite(l)) return false;
    w.isq(i) = 1.0 / std::sqrt(l);
  }
  // R = L_s V Λ^{-1/2}
  if (n <= kLargeBlock) kernels::mul_nn(n, Ls, V, w.R.data());
  else w.R.noalias() = w.Ls * w.tmp2;
  for (int j = 0; j < n; ++j) w.R.col(j) *= w.isq(j);
  // Q = L_s⁻ᵀ V Λ^{1/2}: back substitution with the upper triangular L_sᵀ, for all columns of
  // Q at once (one row of Q per step: row i = column i of Qᵀ, contiguous), so that the n
  // divisions of a row do not wait on each other.
  double* sq = w.wv.data();  // the eigenvalues Λ² are in λ now
  for (int j = 0; j < n; ++j) sq[j] = 1.0 / w.isq(j);
  double* Qt = w.Qt.data();
  for (int i = n - 1; i >= 0; --i) {
    double* qi = Qt + static_cast<long>(i) * n;  // row i of Q
    const double* Li = Ls + static_cast<long>(i) * n;  // column i of L_s = row i of L_sᵀ
    for (int j = 0; j < n; ++j) qi[j] = V[i + static_cast<long>(j) * n] * sq[j];
    for (int k = i + 1; k < n; ++k) {
      const double l = Li[k];
      const double* qk = Qt + static_cast<long>(k) * n;
      for (int j = 0; j < n; ++j) qi[j] -= l * qk[j];
    }
    const double d = Li[i];
    for (int j = 0; j < n; ++j) qi[j] /= d;
  }
  w.Q = w.Qt.transpose();
  return true;
}

// One pass over the blocks: NT scaling, Schur contribution (into M_), and the block part of
// the τ-direction's right-hand side (g_ = −c − Σ ⟨F̃_j, F̃0⟩, kkt_block_rhs with F0); then the
// factorisations. false if a block's scaling or the Schur complement failed.
SETBOUND_INLINE bool InteriorPointSolver:: InteriorPointSolver::scale_and_assemble() {
  M_.setZero();
  g_ = -c_;
  for_block_ranges([&](int t, int begin, int end) {
    Partial& pt = part_[static_cast<size_t>(t)];
    Eigen::MatrixXd& M = t == 0 ? M_ : pt.M;
    Eigen::VectorXd& g = t == 0 ? g_ : pt.v;
    if (t > 0) {
      M.setZero();
      g.setZero();
    }
    pt.ok = true;
    pt.f0sq = 0.0;
    // Runs of up to four consecutive blocks of the same size share one batched eigensolver
    // call (kernels::sym_eig_batch) where that pays; the others take sym_eig one by one.
    for (int b = begin; b < end && pt.ok;) {
      const int n = w_[static_cast<size_t>(b)].n;
      int e = b + 1;
      while (e < end && e - b < 4 && w_[static_cast<size_t>(e)].n == n) ++e;
      for (int i = b; i < e && pt.ok; ++i) pt.ok = scale_block_factor(w_[static_cast<size_t>(i)]);
      if (!pt.ok) break;
      unsigned batched = 0u;
      if (kernels::eig_batch_pays(n, e - b)) {
        double* H[4];
        double* lam2[4];
        for (int i = b; i < e; ++i) {
          H[i - b] = w_[static_cast<size_t>(i)].tmp2.data();
          lam2[i - b] = w_[static_cast<size_t>(i)].wv.data();
        }
        batched = kernels::sym_eig_batch(n, e - b, H, lam2);
      }
      for (int i = b; i < e; ++i) {
        BlockWork& w = w_[static_cast<size_t>(i)];
        const bool eig_ok = ((batched >> (i - b)) & 1u) != 0u || kernels::sym_eig(n, w.tmp2.data(), w.wv.data(), w.ev.data());
        pt.ok = scale_block_finish(w, eig_ok);
        if (!pt.ok) break;
        assemble_block(i);
        scatter_schur(w, M);
        kkt_block_rhs(w, true, 0.0, false);
        scatter_sub(w, g);
        pt.f0sq += w.f0sq;
      }
      b = e;
    }
  });
  bool scaled = true;
  f0sq_ = 0.0;
  for (size_t t = 0; t < used_; ++t) {
    scaled = scaled && part_[t].ok;
    f0sq_ += part_[t].f0sq;
  }
  return scaled && factor_assembled();
}

// M_ = Σ_b (block b's Gram matrix, scattered by its variables), already summed per thread;
// adds the threads' partials and factorises.
SETBOUND_INLINE bool InteriorPointSolver:: InteriorPointSolver::factor_assembled() {
  for (size_t t = 1; t < used_; ++t) M_ += part_[t].M;
  for (int j = 0; j < m_; ++j)  // scatter_schur filled the upper triangle
    for (int i = j + 1; i < m_; ++i) M_(i, j) = M_(j, i);
  // Equalities: K = M + ρAᵀA keeps K positive definite when M is singular on ker A;
  // the reduced system is equivalent for any ρ > 0 (see solve_reduced).
  const double mscale = std::max(1.0, M_.diagonal().cwiseAbs().maxCoeff());
  K_ = M_;
  if (pe_ > 0) {
    rho_ = mscale / std::max(1.0, AtA_.diagonal().maxCoeff());
    K_.noalias() += rho_ * AtA_;
  }
  // Tiny static regularisation against exact singularity; iterative refinement in
  // solve_reduced removes its effect on the directions.
  K_.diagonal().array() += 1e-13 * mscale;
  if (!factor_schur()) return false;
  if (pe_ > 0) {
    KinvAt_ = Aeq_.transpose();
    for (int i = 0; i < pe_; ++i) solve_schur(KinvAt_.col(i).data());
    SA_.noalias() = Aeq_ * KinvAt_;
    SA_.diagonal().array() += 1e-14 * std::max(1.0, SA_.diagonal().maxCoeff());
    lltSA_.compute(SA_);
    if (lltSA_.info() != Eigen::Success) return false;
  }
  return true;
}

// Block b's scaled coefficients F̃ (svec), their Gram matrix G and ⟨F̃_j, F̃0⟩, ‖F̃0‖².
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::assemble_block(int b) {
  const LmiProblem& p = *p_;
  const LmiBlock& blk = p.block(b);
  BlockWork& w = w_[static_cast<size_t>(b)];
  const int n = w.n, sv = w.sv;
  // Slot 1 of V holds rz, so that QᵀF0Q, QᵀrzQ and every dense QᵀF_jQ come out of the same
  // products (kernels::congruence_svec).
  for (int c = 0; c < n; ++c)
    for (int r = 0; r < n; ++r) w.V(w.vrow(1, r), c) = w.rz(r, c);
  const int cnt = w.kd + 2;
  const long ldv = w.V.rows();
  if (n <= kLargeBlock) {
    kernels::congruence_svec(n, cnt, w.cp, w.V.data(), ldv, w.Q.data(), w.P.data(), w.T.data(), w.Fs.data());
  } else {
    w.P.topRows(static_cast<Eigen::Index>(cnt) * n).noalias() = w.V.topRows(static_cast<Eigen::Index>(cnt) * n) * w.Q;
    for (int t = 0; t < cnt; ++t) {
      w.tmp.noalias() = w.P.middleRows(static_cast<Eigen::Index>(t) * n, n).transpose() * w.Q;
      kernels::detail::svec_pack_column(n, w.tmp.data(), n, w.Fs.data(), w.cp, t);
    }
  }
  const double* Fc = w.Fs.data() + 2;  // columns 2 … k + 1 of the row-major Fs
  if (w.arm) {
    // Arm form (all coefficients sparse, kd = 0): F̃_j = QᵀF_jQ with T = Qᵀ (q_r = row r of Q).
    w.arms.prepare(w.Qt.data());
    // Eight columns at a time through the work array T (unused here: no dense coefficients), so
    // that the row-major Fs is written in runs of eight (a column alone touches one cache line per
    // svec entry: a fifth of a tank30 iteration).
    constexpr int kRun = 8;
    const bool runs = w.T.size() >= static_cast<Eigen::Index>(sv) * kRun;
    for (int j0 = 0; j0 < w.k; j0 += runs ? kRun : 1) {
      const int cnt_j = runs ? std::min(kRun, w.k - j0) : 1;
      for (int t = 0; t < cnt_j; ++t) {
        double* out = runs ? w.T.data() + static_cast<long>(t) * sv : w.ws.data();
        w.arms.svec_column(j0 + t, w.Qt.data(), w.cs[static_cast<size_t>(j0 + t)], out);
      }
      if (!runs) {
        w.Fs.col(2 + j0) = w.ws;
        continue;
      }
      const double* buf = w.T.data();
      for (int r = 0; r < sv; ++r) {
        double* dst = w.Fs.data() + static_cast<long>(r) * w.cp + 2 + j0;
        for (int t = 0; t < cnt_j; ++t) dst[t] = buf[r + static_cast<long>(t) * sv];
      }
    }
    w.arms.gram(w.cs.data(), w.G.data(), w.k);
    w.f0 = w.Fs.col(0);
    kernels::gemv_rm_t(sv, w.k, Fc, w.cp, w.f0.data(), w.f0f.data());
    w.f0sq = w.f0.squaredNorm();
    return;
  }
  // Sparse coefficients: QᵀFQ = Σ f_rc (q_r q_cᵀ + q_c q_rᵀ) over the upper-triangle entries
  // (q_r = row r of Q = column r of Qᵀ), accumulated straight into svec (lower triangle).
  for (int j = w.kd; j < w.k; ++j) {
    const Coefficient& co = blk.coefficients[static_cast<size_t>(w.col[static_cast<size_t>(j)])];
    const double sc = w.cs[static_cast<size_t>(j)];
    double* o = w.ws.data();  // work; copied into column 2 + j of Fs below
    std::fill(o, o + sv, 0.0);
    for (const auto& e : co.entries) {
      const double* qr = w.Qt.data() + static_cast<long>(e.row) * n;
      const double* qc = w.Qt.data() + static_cast<long>(e.col) * n;
      const double ev = sc * e.value;
      int idx = 0;
      if (e.row == e.col) {
        for (int b2 = 0; b2 < n; ++b2) {
          const double f = ev * qr[b2];
          for (int a = b2; a < n; ++a) o[idx++] += qr[a] * f;
        }
      } else {
        for (int b2 = 0; b2 < n; ++b2) {
          const double fc = ev * qc[b2], fr = ev * qr[b2];
          for (int a = b2; a < n; ++a) o[idx++] += qr[a] * fc + qc[a] * fr;
        }
      }
    }
    int idx = 0;
    for (int b2 = 0; b2 < n; ++b2) {
      ++idx;  // diagonal
      for (int a = b2 + 1; a < n; ++a) o[idx++] *= kernels::kSqrt2;
    }
    w.Fs.col(2 + j) = w.ws;
  }
  // Schur complement: the Gram matrix of the scaled coefficients (upper half, mirrored).
  kernels::gram_upper(sv, w.k, Fc, w.cp, w.G.data(), w.k);
  // ⟨F̃_j, F̃0⟩ and ‖F̃0‖², used by both directions of the iteration.
  w.f0 = w.Fs.col(0);
  kernels::gemv_rm_t(sv, w.k, Fc, w.cp, w.f0.data(), w.f0f.data());
  w.f0sq = w.f0.squaredNorm();
}

// Cholesky factorisation of K and solves with it: the kernels' loops up to kSmallSchur
// variables (Eigen's dynamic-size LLT costs more in dispatch than in flops there), Eigen's
// blocked LLT above.
SETBOUND_INLINE bool InteriorPointSolver:: InteriorPointSolver::factor_schur() {
  if (m_ <= kSmallSchur) {
    if (!kernels::cholesky(m_, K_.data(), Lk_.data())) return false;
    for (int i = 0; i < m_; ++i) Ldinv_(i) = 1.0 / Lk_(i, i);  // the solves multiply
    Uk_ = Lk_.transpose();
    return true;
  }
  lltK_.compute(K_);
  return lltK_.info() == Eigen::Success;
}

SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::solve_schur(double* b) {
  if (m_ <= kSmallSchur) return kernels::cholesky_solve(m_, Lk_.data(), Uk_.data(), Ldinv_.data(), b);
  Eigen::Map<Eigen::VectorXd> v(b, m_);
  lltK_.solveInPlace(v);
}

// Solves M dx + Aᵀdy = g, A dx = by (K = M + ρAᵀA formulation), with up to two steps of
// iterative refinement (the second only when the first still changed dx noticeably).
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::solve_reduced(const Eigen::VectorXd& g, const Eigen::VectorXd& by,
                                                Eigen::VectorXd& dx, Eigen::VectorXd& dy) {
  auto base = [&](const Eigen::VectorXd& gg, const Eigen::VectorXd& bb, Eigen::VectorXd& ox, Eigen::VectorXd& oy) {
    t1_ = gg;
    if (pe_ > 0) t1_.noalias() += rho_ * Aeq_.transpose() * bb;
    solve_schur(t1_.data());  // t1 = K⁻¹(g + ρAᵀb)
    if (pe_ > 0) {
      oy.noalias() = Aeq_ * t1_;
      oy -= bb;
      lltSA_.solveInPlace(oy);
      ox = t1_;
      ox.noalias() -= KinvAt_ * oy;
    } else {
      ox = t1_;
    }
  };
  base(g, by, dx, dy);
  for (int it = 0; it < 2; ++it) {
    r1_ = g;
    kernels::gemv_t(m_, m_, M_.data(), dx.data(), t2_.data());  // M dx (M symmetric)
    r1_ -= t2_;
    if (pe_ > 0) {
      r1_.noalias() -= Aeq_.transpose() * dy;
      r2_ = by;
      r2_.noalias() -= Aeq_ * dx;
    }
    base(r1_, r2_, cdx_, cdy_);
    dx += cdx_;
    if (pe_ > 0) dy += cdy_;
    if (cdx_.cwiseAbs().maxCoeff() <= 1e-14 * dx.cwiseAbs().maxCoeff() &&
        (pe_ == 0 || cdy_.cwiseAbs().maxCoeff() <= 1e-14 * dy.cwiseAbs().maxCoeff()))
      break;
  }
}

// Solves the KKT system  Aᵀdy + Gᵀdz = bx,  A dx = by,  G dx − WᵀW dz = bz  where
//   bz = use_F0 ? F0 : −eta_rz·rz − Wᵀ(U)   (U = λ⁻¹◇ds_rhs held in w.U when with_u).
// On return w.bs = svec(Qᵀ bz Q) (needed to form W dz = −Σ dx_j F̃_j − B̃).
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::kkt_solve(const Eigen::VectorXd& bx, const Eigen::VectorXd& by, bool use_F0,
                                            double eta_rz, bool with_u, Eigen::VectorXd& dx, Eigen::VectorXd& dy) {
  g_ = bx;
  for_block_ranges([&](int t, int begin, int end) {
    Eigen::VectorXd& g = t == 0 ? g_ : part_[static_cast<size_t>(t)].v;
    if (t > 0) g.setZero();
    for (int b = begin; b < end; ++b) {
      kkt_block_rhs(w_[static_cast<size_t>(b)], use_F0, eta_rz, with_u);
      scatter_sub(w_[static_cast<size_t>(b)], g);
    }
  });
  kkt_finish(by, dx, dy);
}

// The block part of kkt_solve: w.bs = B̃ and w.gl_j = ⟨F̃_j, B̃⟩. For use_F0 these are F̃0 and
// ⟨F̃_j, F̃0⟩ = f0f, which assemble_block computed already (with the same operations).
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::kkt_block_rhs(BlockWork& w, bool use_F0, double eta_rz, bool with_u) {
  if (use_F0) {
    w.bs = w.f0;
    w.gl = w.f0f;
    return;
  }
  w.bs = -eta_rz * w.Fs.col(1);  // svec(Qᵀ rz Q), formed once per iteration
  if (with_u) {                  // QᵀR U RᵀQ = U since QᵀR = I
    kernels::svec_pack(w.n, w.U.data(), w.ws.data());
    w.bs -= w.ws;
  }
  kernels::gemv_rm_t(w.sv, w.k, w.Fs.data() + 2, w.cp, w.bs.data(), w.gl.data());
}

// The rest of kkt_solve: g_ = bx − Σ_b gl_b, summed per thread (thread 0's part in g_ itself).
SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::kkt_finish(const Eigen::VectorXd& by, Eigen::VectorXd& dx, Eigen::VectorXd& dy) {
  for (size_t t = 1; t < used_; ++t) g_ += part_[t].v;  // the partials hold −Σ gl
  solve_reduced(g_, by, dx, dy);
}

SETBOUND_INLINE double InteriorPointSolver:: InteriorPointSolver::max_step_scaled(BlockWork& w, const Eigen::MatrixXd& X, double cap) {
  // Largest α with Λ + αX ⪰ 0: α = −1/λ_min(M), M = Λ^{-1/2} X Λ^{-1/2}, when that is negative.
  // Only α < cap matters to the caller: if I + cap·M factorises, the block does not limit it.
  const int n = w.n;
  double* M = w.tmp.data();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) M[i + static_cast<long>(j) * n] = X(i, j) * w.isq(i) * w.isq(j);
  if (std::isfinite(cap)) {
    double* T = w.tmp2.data();
    for (int i = 0; i < n * n; ++i) T[i] = cap * M[i];
    for (int i = 0; i < n; ++i) T[i + static_cast<long>(i) * n] += 1.0;
    if (kernels::positive_definite(n, T, T)) return cap;
  }
  const double e = kernels::sym_lambda_min(n, M, w.wv.data(), w.ev.data());
  if (!std::isfinite(e)) return 0.0;  // no safe step: reported as a numerical error
  return e >= 0 ? std::numeric_limits<double>::infinity() : -1.0 / e;
}

// One Newton direction of the embedding. Predictor: eta = 1, sigma = 0; corrector adds the
// second-order term (W⁻ᵀds_a)∘(W dz_a) and centring σμ (Mehrotra).
// Returns the largest step keeping every cone interior, capped at `cap` (the caller uses
// min(1, …)). Within a range of blocks the bound found so far is the cap of the next block
// (max_step_scaled skips the eigenvalues of blocks that do not limit it); the minimum over
// the ranges is the same exact λ_min bound whatever the ranges (up to near-ties within
// rounding, where a block passing its Cholesky test at the cap returns the cap).
SETBOUND_INLINE double InteriorPointSolver:: InteriorPointSolver::direction(double eta, double sigma, double mu, bool corrector, double cap) {
  // u0: bx = −η rx, by = η ry, bz = −η rz − Wᵀ U.
  bx_ = -eta * rx_;
  if (pe_ > 0) by_ = eta * ry_;
  g_ = bx_;
  // ds_rhs = −λ∘λ + σμe − corr  ⇒  U = λ⁻¹◇ds_rhs: U_ij = 2 ds_rhs_ij / (λ_i + λ_j)
  for_block_ranges([&](int t, int begin, int end) {
    Partial& pt = part_[static_cast<size_t>(t)];
    Eigen::VectorXd& g = t == 0 ? g_ : pt.v;
    if (t > 0) g.setZero();
    pt.hb = 0.0;
    for (int b = begin; b < end; ++b) {
      BlockWork& w = w_[static_cast<size_t>(b)];
      if (corrector) {
        kernels::mul_nn(w.n, w.Wds_a.data(), w.Wdz_a.data(), w.tmp.data());
        w.tmp2 = 0.5 * (w.tmp + w.tmp.transpose());  // (Wds_a)∘(Wdz_a)
      }
      for (int j = 0; j < w.n; ++j)
        for (int i = 0; i < w.n; ++i) {
          double r = (i == j) ? (-w.lambda(i) * w.lambda(i) + sigma * mu) : 0.0;
          if (corrector) r -= w.tmp2(i, j);
          w.U(i, j) = 2.0 * r / (w.lambda(i) + w.lambda(j));
        }
      kkt_block_rhs(w, false, eta, true);
      scatter_sub(w, g);
      pt.hb -= w.f0.dot(w.bs);
    }
  });
  double dk_rhs = -tau_ * kappa_ + sigma * mu;
  if (corrector) dk_rhs -= dtau_a_ * dkappa_a_;
  kkt_finish(by_, dx_, dy_);
  // hᵀdz0 = <F̃0, W dz0>,  W dz0 = −Σ dx_j F̃_j − B̃0
  double cx0 = c_.dot(dx_) + (pe_ > 0 ? beq_.dot(dy_) : 0.0);
  double cx1 = c_.dot(x1_) + (pe_ > 0 ? beq_.dot(y1_) : 0.0);
  for (size_t t = 0; t < used_; ++t) cx0 += part_[t].hb;
  cx1 -= f0sq_;
  for (const auto& w : w_) {  // f0f: written in the scaling pass, read-only since
    double hz0 = 0, hz1 = 0;
    for (int j = 0; j < w.k; ++j) {
      const int v = w.var[static_cast<size_t>(j)];
      hz0 -= dx_(v) * w.f0f(j);
      hz1 -= x1_(v) * w.f0f(j);
    }
    cx0 += hz0;
    cx1 += hz1;
  }
  dtau_ = (-eta * rtau_ - dk_rhs / tau_ - cx0) / (cx1 - kappa_ / tau_);
  dx_ += dtau_ * x1_;
  if (pe_ > 0) dy_ += dtau_ * y1_;
  dkappa_ = (dk_rhs - kappa_ * dtau_) / tau_;
  for_block_ranges([&](int t, int begin, int end) {
    double a = cap;
    for (int b = begin; b < end; ++b) {
      BlockWork& w = w_[static_cast<size_t>(b)];
      // W dz = −Σ dx_j F̃_j − B̃0 − dτ F̃0;  W⁻ᵀds = U − W dz
      for (int j = 0; j < w.k; ++j) w.xl(j) = dx_(w.var[static_cast<size_t>(j)]);
      w.ws = -w.bs - dtau_ * w.f0;
      kernels::gemv_rm_n_add(w.sv, w.k, -1.0, w.Fs.data() + 2, w.cp, w.xl.data(), w.ws.data());
      kernels::svec_unpack(w.n, w.ws.data(), w.Wdz.data());
      w.Wds = w.U - w.Wdz;
      a = std::min(a, max_step_scaled(w, w.Wds, a));
      a = std::min(a, max_step_scaled(w, w.Wdz, a));
      if (!corrector) {  // kept for the corrector's second-order term
        w.Wds_a = w.Wds;
        w.Wdz_a = w.Wdz;
      }
    }
    part_[static_cast<size_t>(t)].amax = a;
  });
  double amax = cap;
  for (size_t t = 0; t < used_; ++t) amax = std::min(amax, part_[t].amax);
  if (dtau_ < 0) amax = std::min(amax, -tau_ / dtau_);
  if (dkappa_ < 0) amax = std::min(amax, -kappa_ / dkappa_);
  return amax;
}

SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::record_best(double merit) {
  if (!(merit < best_merit_)) return;
  best_merit_ = merit;
  // In the problem's units (equilibrate()): x = D x̂, y = R ŷ, Z_b = e_b Ẑ_b.
  best_x_ = x_.cwiseProduct(d_) / tau_;
  if (pe_ > 0) best_y_ = y_.cwiseProduct(r_) / tau_;
  pending_best_z_ = true;  // w.best_Z = w.Z·e/τ, done in the next pass over the blocks (residuals())
  best_z_scale_ = 1.0 / tau_;
  best_pcost_ = pcost_;
  best_dcost_ = dcost_;
  best_gap_ = gap_;
  best_relgap_ = relgap_;
  best_pres_ = pres_;
  best_dres_ = dres_;
}

SETBOUND_INLINE void InteriorPointSolver:: InteriorPointSolver::finish(SolveStatus status) {
  // Returns the best iterate for non-converged statuses, the current one otherwise.
  result_.status = status;
  if (pending_best_z_) {
    for (auto& w : w_) w.best_Z = w.Z * (w.e * best_z_scale_);
    pending_best_z_ = false;
  }
  // Objective values and dual variables are those of the normalised objective c/cscale_.
  const double cs = cscale_;
  if (status == SolveStatus::Optimal) {
    result_.x = x_.cwiseProduct(d_) / tau_;
    if (pe_ > 0) result_.y = y_.cwiseProduct(r_) * (cs / tau_);
    for (size_t b = 0; b < w_.size(); ++b) result_.Z[b] = w_[b].Z * (cs * w_[b].e / tau_);
    result_.objective = cs * pcost_;
    result_.dual_objective = cs * dcost_;
    result_.gap = cs * gap_;
    result_.relative_gap = relgap_;
    result_.primal_residual = pres_;
    result_.dual_residual = dres_;
  } else if (status == SolveStatus::Infeasible || status == SolveStatus::Unbounded) {
    // set by caller
  } else {
    result_.x = best_x_;
    if (pe_ > 0) result_.y = cs * best_y_;
    for (size_t b = 0; b < w_.size(); ++b) result_.Z[b] = cs * w_[b].best_Z;
    result_.objective = cs * best_pcost_;
    result_.dual_objective = cs * best_dcost_;
    result_.gap = cs * best_gap_;
    result_.relative_gap = best_relgap_;
    result_.primal_residual = best_pres_;
    result_.dual_residual = best_dres_;
    if (best_pres_ <= opt_.reduced_feas && best_dres_ <= opt_.reduced_feas &&
        (best_gap_ <= opt_.reduced_gap_abs || best_relgap_ <= opt_.reduced_gap_rel))
      result_.status = SolveStatus::Inaccurate;
  }
  const bool has_point = result_.status == SolveStatus::Optimal || result_.status == SolveStatus::Inaccurate ||
                         result_.status == SolveStatus::MaxIterations || result_.status == SolveStatus::NumericalError;
  if (opt_.compute_margin && has_point && result_.x.allFinite())
    result_.margin = margin_.margin(*p_, result_.x, opt_.feasibility_var);
  else
    result_.margin = -std::numeric_limits<double>::infinity();
}

SETBOUND_INLINE const SolveResult& InteriorPointSolver:: InteriorPointSolver::solve() {
  const auto t0 = std::chrono::steady_clock::now();
  const LmiProblem& p = *p_;
  if (p.structure_version() != version_) setup();
  p.require_solvable();
  if (p.num_blocks() == 0) throw InvalidArgumentError("blocks: the problem has no LMI block (add at least one)");

  // A small objective (‖c‖ < 1) is scaled up to ‖c‖ = 1 inside the iteration: the gap
  // tolerances are absolute below |objective| = 1, so min 1e-6·x stopped with x off by 1e-3.
  // Larger objectives are left as they are (scaling them down cost iterations on the benchmark
  // problems). Results are scaled back in finish().
  {
    const double cn = p.objective().norm();
    cscale_ = (cn > 0 && std::isfinite(cn)) ? std::min(cn, 1.0) : 1.0;
    c_ = p.objective() / cscale_;
  }
  resx0_ = std::max(1.0, c_.norm());
  resy0_ = std::max(1.0, pe_ > 0 ? p.eq_rhs().norm() : 0.0);
  double h2 = 0;
  for (const auto& blk : p.blocks()) h2 += blk.constant.squaredNorm();
  resz0_ = std::max(1.0, std::sqrt(h2));
  // The data are re-read and re-equilibrated only when they changed (values_version); a new
  // objective alone keeps the scaling (it does not depend on c).
  if (p.values_version() != values_loaded_ || p.structure_version() != values_structure_) {
    load_values();
    equilibrate();
    values_loaded_ = p.values_version();
    values_structure_ = p.structure_version();
  }
  c_ = c_.cwiseProduct(d_);

  // Start: the least-squares point of CVXOPT's conelp (falls back to the unit start x = 0,
  // y = 0, S = Z = I, τ = κ = 1 when it cannot be formed).
  step_alpha_ = 0.0;
  pending_best_z_ = false;
  allocate_partials();
  least_squares_start();
  best_merit_ = std::numeric_limits<double>::infinity();
  result_.x.setZero();
  result_.margin = -std::numeric_limits<double>::infinity();

  const double nu1 = static_cast<double>(nu_ + 1);
  int iter = 0;
  SolveStatus status = SolveStatus::MaxIterations;
  MarginChecker& mc = margin_;
  for (;; ++iter) {
    residuals(step_alpha_);
    step_alpha_ = 0.0;
    const double merit = std::max({pres_, dres_, std::min(relgap_, gap_ / opt_.gap_abs * opt_.gap_rel)});
    if (std::isfinite(merit)) record_best(merit);

    // --- termination ---
    if (pres_ <= opt_.feas && dres_ <= opt_.feas && (gap_ <= opt_.gap_abs || relgap_ <= opt_.gap_rel)) {
      status = SolveStatus::Optimal;
      break;
    }
    if (opt_.feasibility_var >= 0 && x_(opt_.feasibility_var) < 0) {
      xhat_ = x_.cwiseProduct(d_) / tau_;
      if (mc.margin(p, xhat_, opt_.feasibility_var) > 0) {
        status = SolveStatus::Optimal;
        break;
      }
    }
    {
      // Primal infeasibility certificate: Gᵀz + Aᵀy ≈ 0 with hᵀz + bᵀy < 0.
      const double ny = -(hz_ + (pe_ > 0 ? beq_.dot(y_) : 0.0));  // hᵀz of this iterate (residuals())
      if (ny > 0) {
        // ‖Aᵀy + Gᵀz‖ = ‖rx − cτ‖, which does not involve c: measured on its own (not relative
        // to ‖c‖), so that the normalised certificate's residual is within feas.
        const double r = (rx_ - c_ * tau_).cwiseQuotient(d_).norm();
        if (r <= opt_.feas * ny) {
          status = SolveStatus::Infeasible;
          break;
        }
      }
      // Dual infeasibility (unbounded): Gx + s ≈ 0, Ax ≈ 0, cᵀx < 0.
      const double cx = -c_.dot(x_);
      if (cx > 0) {
        double r2 = 0;
        for (auto& w : w_) r2 = std::max(r2, (w.rs + tau_ * w.a0).norm() / w.e / resz0_);
        if (pe_ > 0) r2 = std::max(r2, (ry_ - beq_ * tau_).cwiseQuotient(r_).norm() / resy0_);
        if (r2 <= opt_.feas * cx) {
          status = SolveStatus::Unbounded;
          break;
        }
      }
    }
    if (iter >= opt_.max_iterations) {
      status = SolveStatus::MaxIterations;
      break;
    }
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > opt_.time_limit) {
      status = SolveStatus::MaxIterations;
      break;
    }

    // --- Newton system ---
    const double mu = (sz_ + tau_ * kappa_) / nu1;  // ⟨S, Z⟩ from residuals()
    // τ-direction: K (x1, y1, z1) = (−c, b, h), its g_ formed in the pass over the blocks.
    if (!scale_and_assemble()) {
      status = SolveStatus::NumericalError;
      break;
    }
    if (pe_ > 0) by_ = beq_;
    kkt_finish(by_, x1_, y1_);

    const double alpha_a = std::min(1.0, direction(1.0, 0.0, mu, false, 1.0));
    dtau_a_ = dtau_;
    dkappa_a_ = dkappa_;
    // Centring and step fraction adapt to the predictor's step α_a (as in SDPT3): after a
    // short α_a the iterate is far from the central path, so σ = (1 − α_a)^e uses e = 1.5 rather
    // than Mehrotra's 3 (more centring), rising to 3 only for α_a → 1 (e = max(1.5, 3α_a²)); the
    // fraction of the largest step goes from step_fraction − 0.09 up to step_fraction as α_a → 1.
    // Against the fixed (1 − α_a)³ and 0.99: 8–10 % fewer iterations over random sets of small
    // and of 16–40-block problems (docs/benchmarks.md, "LMI solver").
    const double sigma = std::pow(1.0 - alpha_a, std::max(1.5, 3.0 * alpha_a * alpha_a));
    const double fraction = opt_.step_fraction - 0.09 * (1.0 - alpha_a);
    const double amax = direction(1.0 - sigma, sigma, mu, true, 1.0 / fraction);
    const double alpha = std::min(1.0, fraction * amax);
    if (!(alpha > 1e-12) || !dx_.allFinite()) {
      status = SolveStatus::NumericalError;
      break;
    }
    // Update; the blocks' S and Z follow in residuals() (one pass over the blocks).
    x_ += alpha * dx_;
    if (pe_ > 0) y_ += alpha * dy_;
    tau_ += alpha * dtau_;
    kappa_ += alpha * dkappa_;
    step_alpha_ = alpha;  // the blocks' S and Z are updated by the next residuals()
  }

  result_.iterations = iter;
  if (status == SolveStatus::Infeasible) {
    const double ny = -(hz_ + (pe_ > 0 ? beq_.dot(y_) : 0.0));  // as in the certificate test
    for (size_t b = 0; b < w_.size(); ++b) result_.Z[b] = w_[b].Z * (w_[b].e / ny);
    if (pe_ > 0) result_.y = y_.cwiseProduct(r_) / ny;
    result_.x.setConstant(std::numeric_limits<double>::quiet_NaN());
    result_.objective = std::numeric_limits<double>::infinity();
    result_.dual_objective = std::numeric_limits<double>::infinity();
    finish(status);
  } else if (status == SolveStatus::Unbounded) {
    xo_ = x_.cwiseProduct(d_);
    const double cx = -p.objective().dot(xo_);
    result_.x = xo_ / cx;  // ray with cᵀx = −1
    result_.objective = -std::numeric_limits<double>::infinity();
    result_.dual_objective = -std::numeric_limits<double>::infinity();
    finish(status);
  } else {
    finish(status);
  }
  result_.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result_;
}

SETBOUND_INLINE SolveResult solve_linear(const LmiProblem& problem, const SolverOptions& options) {
  InteriorPointSolver s(problem, options);
  return s.solve();
}

}  // namespace lmi
}  // namespace setbound
