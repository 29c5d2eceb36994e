// setbound — primal-dual interior-point method for the LMI form of problem.hpp.
//
// Conic view (CVXOPT coneprog notation): minimise cᵀx s.t. Gx + s = h, Ax = b, s ⪰ 0 with
// G x = −Σ x_i F_i (blockwise), h = F0, so s = F(x). Dual: maximise −hᵀz − bᵀy with
// Gᵀz + Aᵀy + c = 0, z ⪰ 0, i.e. tr(F_i Z) = c_i + (Aᵀy)_i.
//
// Algorithm (ARCHITECTURE.md "Solver"; CVXOPT/Clarabel/ECOS were read as references):
//  * homogeneous self-dual embedding in (x, y, s, z, τ, κ), so that infeasibility
//    (τ → 0, hᵀz + bᵀy < 0) and unboundedness (cᵀx < 0) come with certificates;
//  * Nesterov–Todd scaling per block: R with RᵀZR = R⁻¹SR⁻ᵀ = Λ, computed from the
//    Cholesky factors of S and Z and the singular vectors of G = L_zᵀL_s (an SVD for large
//    blocks, the symmetric eigendecomposition of GᵀG for blocks ≤ 8×8); Q = R⁻ᵀ;
//  * Schur complement M_ij = Σ_b tr(F_bi T_b F_bj T_b), T_b = QQᵀ, assembled block by block
//    as a Gram matrix of svec(F̃_bi), F̃_bi = QᵀF_biQ (only variables that touch a block
//    contribute; sparse coefficients are scaled by rank-one updates); dense Cholesky;
//  * Mehrotra predictor–corrector with σ = (1 − α_aff)³; step lengths from λ_min of the
//    scaled directions, skipped (one Cholesky) for blocks that do not limit the step;
//  * two-tier termination (full / reduced tolerances → "inaccurate"), best iterate kept.
// All work arrays are allocated in setup(); solve() itself does not allocate. Blocks of size
// ≤ 8 (the online case) run fixed-size kernels (detail::dispatch_size), larger ones the same
// code on dynamic-size maps.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <chrono>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include "setbound/lmi/problem.hpp"

namespace setbound::lmi {

enum class SolveStatus : int {
  Optimal = 0,
  Infeasible = 1,
  Unbounded = 2,
  MaxIterations = 3,   // iteration or time limit reached before any tolerance was met
  NumericalError = 4,
  Inaccurate = 5,      // only the reduced tolerances were met (best iterate returned)
};

inline const char* status_name(SolveStatus s) {
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

struct SolverOptions {
  int max_iterations = 100;
  double time_limit = 30.0;          // seconds, checked once per iteration
  double gap_rel = 1e-7;             // relative duality gap
  double gap_abs = 1e-9;             // absolute duality gap
  double feas = 1e-8;                // relative primal/dual residuals, certificate residuals
  double reduced_gap_rel = 5e-5;     // "inaccurate" tier
  double reduced_gap_abs = 5e-7;
  double reduced_feas = 1e-5;
  double step_fraction = 0.99;
  bool compute_margin = true;
  // Feasibility mode (classes.hpp): stop at the first iterate where x[feasibility_var] < 0
  // and the verified margin of all blocks, evaluated without that variable, is positive.
  int feasibility_var = -1;
  // Per-block kernels for blocks of size ≤ 8 run on fixed-size Eigen types (no heap, unrolled
  // products, stack eigensolvers). false forces the dynamic-size path everywhere; both paths
  // compute the same iterates up to rounding (tests compare them).
  bool fixed_size_kernels = true;

  void validate() const {
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
  }
};

struct SolveResult {
  SolveStatus status = SolveStatus::NumericalError;
  int iterations = 0;
  double objective = std::numeric_limits<double>::quiet_NaN();       // cᵀx (primal)
  double dual_objective = std::numeric_limits<double>::quiet_NaN();  // −(hᵀz + bᵀy)
  double gap = std::numeric_limits<double>::quiet_NaN();             // sᵀz
  double relative_gap = std::numeric_limits<double>::quiet_NaN();
  double primal_residual = std::numeric_limits<double>::quiet_NaN();
  double dual_residual = std::numeric_limits<double>::quiet_NaN();
  double margin = -std::numeric_limits<double>::infinity();          // verified, see verified_margin()
  double solve_time = 0.0;                                           // seconds
  Eigen::VectorXd x;                     // primal point (or the unboundedness ray)
  Eigen::VectorXd y;                     // equality multipliers (or certificate part)
  std::vector<Eigen::MatrixXd> Z;        // dual matrices (or the infeasibility certificate,
                                         // normalised so that Σ tr(F_b0 Z_b) + beqᵀy = −1)
};

namespace detail {

/// Largest block size with a fixed-size kernel. Online LMIs have blocks of at most 7×7
/// (papers.md §1.4, §3.2); at these sizes dynamic-size Eigen code is dominated by loop and
/// dispatch overhead and the eigensolvers by their generic paths.
constexpr int kMaxFixedBlock = 8;

/// Calls f(std::integral_constant<int, N>) with N = n for 1 ≤ n ≤ kMaxFixedBlock when `fixed`,
/// N = Eigen::Dynamic otherwise. Kernels are written once as generic lambdas over N and map
/// the (preallocated, dynamic) work arrays with fixed-size Eigen::Map.
template <class F>
inline void dispatch_size(int n, bool fixed, F&& f) {
  if (fixed) {
    switch (n) {
      case 1: f(std::integral_constant<int, 1>{}); return;
      case 2: f(std::integral_constant<int, 2>{}); return;
      case 3: f(std::integral_constant<int, 3>{}); return;
      case 4: f(std::integral_constant<int, 4>{}); return;
      case 5: f(std::integral_constant<int, 5>{}); return;
      case 6: f(std::integral_constant<int, 6>{}); return;
      case 7: f(std::integral_constant<int, 7>{}); return;
      case 8: f(std::integral_constant<int, 8>{}); return;
      default: break;
    }
  }
  f(std::integral_constant<int, Eigen::Dynamic>{});
}

/// Length of svec for an N×N block (Dynamic stays Dynamic).
template <int N>
constexpr int svec_size() {
  return N == Eigen::Dynamic ? Eigen::Dynamic : N * (N + 1) / 2;
}

/// svec: upper triangle by columns, off-diagonals ×√2, so that svec(A)·svec(B) = tr(AB) for
/// symmetric A, B. The Schur complement is a Gram matrix of svec'd scaled coefficients, which
/// halves its cost against full vec and keeps it positive semidefinite in floating point.
template <class M>
inline void pack_svec(const M& A, double* v) {
  constexpr double r2 = 1.4142135623730951;
  const Eigen::Index n = A.rows();
  Eigen::Index k = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < j; ++i) v[k++] = r2 * 0.5 * (A(i, j) + A(j, i));
    v[k++] = A(j, j);
  }
}

template <class M>
inline void unpack_svec(const double* v, M& A) {
  constexpr double ir2 = 0.7071067811865476;
  const Eigen::Index n = A.rows();
  Eigen::Index k = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < j; ++i) A(i, j) = A(j, i) = ir2 * v[k++];
    A(j, j) = v[k++];
  }
}

/// A ← (A + Aᵀ)/2 in place.
template <class M>
inline void symmetrize(M& A) {
  const Eigen::Index n = A.rows();
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < j; ++i) A(i, j) = A(j, i) = 0.5 * (A(i, j) + A(j, i));
}

/// λ_min of a small symmetric matrix (fixed N ≥ 1), for step lengths only. Householder
/// tridiagonalisation, then Laguerre's iteration on the characteristic polynomial
/// p(x) = det(T − xI) of the tridiagonal T (three-term recurrence for p, p′, p″) started left
/// of the Gershgorin bound. p has only real roots, so Laguerre's iteration started left of
/// them increases monotonically to the smallest one and converges cubically, also for
/// clustered eigenvalues (it is exact in one step for an n-fold root). This is 3–5× cheaper
/// than Eigen's QR-based eigenvalue solver at these sizes; the result agrees with it to about
/// 1e-10·‖A‖ (tests compare them), far below what the step fraction (0.99) absorbs.
template <int N, class M>
inline double lambda_min_small(const M& A) {
  static_assert(N >= 1, "fixed size only");
  using Vec = Eigen::Matrix<double, N, 1>;
  using SubVec = Eigen::Matrix<double, (N > 1 ? N - 1 : 1), 1>;
  if constexpr (N == 1) {
    return A(0, 0);
  } else {
    Vec d;
    SubVec e;
    if constexpr (N == 2) {
      d << A(0, 0), A(1, 1);
      e << A(1, 0);
    } else {
      const Eigen::Tridiagonalization<Eigen::Matrix<double, N, N>> tri(A);
      d = tri.diagonal();
      e = tri.subDiagonal();
    }
    if (!d.allFinite() || !e.allFinite()) return std::numeric_limits<double>::quiet_NaN();
    double s = 0;
    for (int i = 0; i < N; ++i) {
      double r = std::abs(d(i));
      if (i > 0) r += std::abs(e(i - 1));
      if (i < N - 1) r += std::abs(e(i));
      s = std::max(s, r);
    }
    if (s == 0) return 0.0;
    // Scale to ‖T‖ ≤ 1 so that p and its derivatives stay far from overflow (N ≤ 8).
    d /= s;
    e /= s;
    double x = 1.0;
    for (int i = 0; i < N; ++i) {
      double r = d(i);
      if (i > 0) r -= std::abs(e(i - 1));
      if (i < N - 1) r -= std::abs(e(i));
      x = std::min(x, r);
    }
    x -= 1e-3;  // strictly left of the spectrum
    const SubVec e2 = e.cwiseAbs2();
    constexpr double n = N;
    for (int it = 0; it < 60; ++it) {
      double p0 = 1, p1 = d(0) - x, q0 = 0, q1 = -1, r0 = 0, r1 = 0;
      for (int i = 1; i < N; ++i) {
        const double a = d(i) - x, b = e2(i - 1);
        const double p2 = a * p1 - b * p0;
        const double q2 = a * q1 - p1 - b * q0;
        const double r2 = a * r1 - 2.0 * q1 - b * r0;
        p0 = p1;
        p1 = p2;
        q0 = q1;
        q1 = q2;
        r0 = r1;
        r1 = r2;
      }
      // p > 0 strictly left of the spectrum; p ≤ 0 means rounding put x on (or just past)
      // λ_min, where the iteration would head for the next root: stop there.
      if (!(p1 > 0)) break;
      // G = p′/p = −Σ 1/(λ_i − x) < 0 left of the spectrum, H = G² − p″/p = Σ 1/(λ_i − x)².
      const double G = q1 / p1, H = G * G - r1 / p1;
      const double den = G - std::sqrt(std::max(0.0, (n - 1) * (n * H - G * G)));
      if (!(den < 0)) break;
      const double step = -n / den;
      x += step;
      if (!(step > 4 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(x)))) break;
    }
    return x * s;
  }
}

}  // namespace detail

/// Workspace and verified margin of a point, reusable without allocation.
class MarginChecker {
 public:
  void setup(const LmiProblem& p) {
    const size_t nb = static_cast<size_t>(p.num_blocks());
    F_.resize(nb);
    llt_.clear();
    eig_.clear();
    for (size_t b = 0; b < nb; ++b) {
      const int n = p.block(static_cast<int>(b)).size;
      F_[b].resize(n, n);
      llt_.emplace_back(n);
      eig_.emplace_back(n);
    }
  }

  /// Largest δ among a few candidates for which the Cholesky factorisation of F_b(x) − δI
  /// succeeded for every block (δ < 0: x is not feasible). `skip_var` ≥ 0 evaluates the
  /// blocks as if x[skip_var] were 0 (feasibility mode's auxiliary variable).
  double margin(const LmiProblem& p, const Eigen::VectorXd& x, int skip_var = -1) {
    double lam = std::numeric_limits<double>::infinity();
    double scale = 1.0;
    const size_t nb = F_.size();
    if (nb == 0) return lam;
    for (size_t b = 0; b < nb; ++b) {
      const LmiBlock& blk = p.block(static_cast<int>(b));
      evaluate(p, blk, x, skip_var, F_[b]);
      if (!F_[b].allFinite()) return -std::numeric_limits<double>::infinity();
      lam = std::min(lam, lambda_min(b));
      scale = std::max(scale, F_[b].cwiseAbs().maxCoeff());
    }
    // Candidates δ = λ_min − 4^k·ε·n·scale: the eigenvalue estimate is only accurate to
    // rounding, the Cholesky success is what we certify (ARCHITECTURE.md "Guarantees").
    double slack = 8.0 * std::numeric_limits<double>::epsilon() * scale;
    for (int attempt = 0; attempt < 12; ++attempt, slack *= 4.0) {
      const double delta = lam - slack;
      bool ok = true;
      for (size_t b = 0; b < nb && ok; ++b) {
        F_[b].diagonal().array() -= delta;
        ok = cholesky_ok(b);
        F_[b].diagonal().array() += delta;
      }
      if (ok) return delta;
    }
    return -std::numeric_limits<double>::infinity();
  }

 private:
  // Fixed-size eigensolver / Cholesky for small blocks (stack only), the preallocated dynamic
  // ones otherwise. The certificate is the Cholesky success either way.
  double lambda_min(size_t b) {
    double e = 0;
    const int n = static_cast<int>(F_[b].rows());
    detail::dispatch_size(n, true, [&](auto NC) {
      constexpr int N = decltype(NC)::value;
      if constexpr (N == Eigen::Dynamic) {
        eig_[b].compute(F_[b], Eigen::EigenvaluesOnly);
        e = eig_[b].eigenvalues()(0);
      } else {
        const Eigen::Map<const Eigen::Matrix<double, N, N>> F(F_[b].data());
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es;
        es.compute(F, Eigen::EigenvaluesOnly);
        e = es.eigenvalues()(0);
      }
    });
    return e;
  }
  bool cholesky_ok(size_t b) {
    bool ok = false;
    const int n = static_cast<int>(F_[b].rows());
    detail::dispatch_size(n, true, [&](auto NC) {
      constexpr int N = decltype(NC)::value;
      if constexpr (N == Eigen::Dynamic) {
        llt_[b].compute(F_[b]);
        ok = llt_[b].info() == Eigen::Success;
      } else {
        const Eigen::Map<const Eigen::Matrix<double, N, N>> F(F_[b].data());
        Eigen::LLT<Eigen::Matrix<double, N, N>> llt(F);
        ok = llt.info() == Eigen::Success;
      }
    });
    return ok;
  }

  static void evaluate(const LmiProblem& p, const LmiBlock& blk, const Eigen::VectorXd& x, int skip_var,
                       Eigen::MatrixXd& out) {
    out = blk.constant;
    for (const auto& co : blk.coefficients) {
      if (co.var == skip_var) continue;
      const double xi = x[co.var];
      if (xi != 0.0) out.noalias() += xi * co.dense;
    }
    (void)p;
  }
  std::vector<Eigen::MatrixXd> F_;
  std::vector<Eigen::LLT<Eigen::MatrixXd>> llt_;
  std::vector<Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>> eig_;
};

class InteriorPointSolver {
 public:
  explicit InteriorPointSolver(const LmiProblem& problem, SolverOptions options = {})
      : p_(&problem), opt_(options) {
    opt_.validate();
    setup();
  }

  const SolverOptions& options() const { return opt_; }
  void set_options(const SolverOptions& o) {
    o.validate();
    opt_ = o;
  }
  const LmiProblem& problem() const { return *p_; }

  /// Solves the linear-objective problem (the logdet term, if any, is ignored here; use
  /// solve_maxdet in classes.hpp). No allocation unless the problem's structure changed.
  const SolveResult& solve();

  /// (Re)allocates all work arrays for the current structure of the problem.
  void setup();

 private:
  struct BlockWork {
    int n = 0, k = 0;
    std::vector<int> vars;  // variables touching the block (coefficient order)
    Eigen::MatrixXd S, Z, dS, dZ, rz, rzt, R, Q, LzLs, tmp, tmp2, Bt, Wds, Wdz, Wds_a, Wdz_a, U, best_Z;
    Eigen::MatrixXd Fv;     // d×k (d = n(n+1)/2), column j = svec(QᵀF_{vars[j]}Q)
    Eigen::VectorXd f0v;    // svec(QᵀF0Q)
    Eigen::VectorXd btv;    // svec(B̃) of the last kkt_solve
    Eigen::VectorXd wv;     // svec work vector
    Eigen::VectorXd fvf0;   // k: svec(F̃_j)·svec(F̃0)
    Eigen::VectorXd dxs;    // k: dx gathered on vars
    Eigen::VectorXd lambda, isq;
    Eigen::LLT<Eigen::MatrixXd> llt_s, llt_z;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd;
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;
  };

  // --- helpers (inline below) ---
  void residuals();
  bool scaling();
  bool assemble_and_factor();
  void solve_reduced(const Eigen::VectorXd& g, const Eigen::VectorXd& by, Eigen::VectorXd& dx, Eigen::VectorXd& dy);
  void kkt_solve(const Eigen::VectorXd& bx, const Eigen::VectorXd& by, bool use_F0, double eta_rz,
                 bool with_u, Eigen::VectorXd& dx, Eigen::VectorXd& dy);
  double max_step_scaled(BlockWork& w, const Eigen::MatrixXd& X, double bound);
  bool fixed() const { return opt_.fixed_size_kernels; }
  void direction(double eta, double sigma, double mu, bool corrector);
  double step_length();
  void record_best(double merit);
  void finish(SolveStatus status);

  // Small blocks (n ≤ 16, the online case) use coefficient-based products: Eigen's GEMM
  // packing costs more than the arithmetic at these sizes.
  template <class Out, class L, class R>
  static void mul(Out&& out, const L& a, const R& b) {
    if (a.rows() <= 16 && b.cols() <= 16 && a.cols() <= 16) out.noalias() = a.lazyProduct(b);
    else out.noalias() = a * b;
  }

  static void sym_product(const Eigen::VectorXd& lam, const Eigen::MatrixXd& X, Eigen::MatrixXd& out) {
    // Λ ∘ X = (ΛX + XΛ)/2 for diagonal Λ.
    const Eigen::Index n = X.rows();
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index i = 0; i < n; ++i) out(i, j) = 0.5 * (lam(i) + lam(j)) * X(i, j);
  }

  const LmiProblem* p_;
  SolverOptions opt_;
  std::uint64_t version_ = ~std::uint64_t{0};
  int m_ = 0, pe_ = 0, nu_ = 0;
  std::vector<BlockWork> w_;
  MarginChecker margin_;
  // iterate
  Eigen::VectorXd x_, y_;
  double tau_ = 1, kappa_ = 1;
  // residuals
  Eigen::VectorXd rx_, ry_;
  double rtau_ = 0;
  // linear algebra
  Eigen::MatrixXd M_, K_, KinvAt_, SA_, AtA_;
  Eigen::LLT<Eigen::MatrixXd> lltK_, lltSA_;
  double rho_ = 1;
  Eigen::VectorXd g_, gy_, t1_, t2_, t3_, ry2_, r1_, r2_, cdx_, cdy_;
  // directions: x1/y1 (τ-direction), dx/dy
  Eigen::VectorXd x1_, y1_, dx_, dy_, dx_a_, dy_a_, bx_, by_;
  double dtau_ = 0, dkappa_ = 0, dtau_a_ = 0, dkappa_a_ = 0;
  // norms for relative residuals
  double resx0_ = 1, resy0_ = 1, resz0_ = 1;
  // best iterate
  double best_merit_ = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_x_, best_y_, xhat_;
  double best_pcost_ = 0, best_dcost_ = 0, best_gap_ = 0, best_relgap_ = 0, best_pres_ = 0, best_dres_ = 0;
  // current metrics
  double pcost_ = 0, dcost_ = 0, gap_ = 0, relgap_ = 0, pres_ = 0, dres_ = 0;
  SolveResult result_;
};

// ---------------------------------------------------------------------------------------

// The member functions below are inline for header-only users of setbound. Inside setbound's
// own build every translation unit except cpp/lmi_solver.cpp defines SETBOUND_LMI_EXTERN_SOLVER
// and sees the declarations only: the fixed-size kernels (nine instantiations per member
// function) are then compiled once instead of in every file that solves an LMI.
#ifndef SETBOUND_LMI_SOLVER_INLINE
#define SETBOUND_LMI_SOLVER_INLINE inline
#endif
#ifndef SETBOUND_LMI_EXTERN_SOLVER

SETBOUND_LMI_SOLVER_INLINE void InteriorPointSolver::setup() {
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
    w.vars.clear();
    for (const auto& co : blk.coefficients) w.vars.push_back(co.var);
    for (Eigen::MatrixXd* M : {&w.S, &w.Z, &w.dS, &w.dZ, &w.rz, &w.rzt, &w.R, &w.Q, &w.LzLs, &w.tmp, &w.tmp2,
                               &w.Bt, &w.Wds, &w.Wdz, &w.Wds_a, &w.Wdz_a, &w.U, &w.best_Z})
      M->setZero(n, n);
    const int d = n * (n + 1) / 2;
    w.Fv.setZero(d, w.k);
    for (Eigen::VectorXd* v : {&w.f0v, &w.btv, &w.wv}) v->setZero(d);
    w.fvf0.setZero(w.k);
    w.dxs.setZero(w.k);
    w.lambda.setZero(n);
    w.isq.setZero(n);
    w.llt_s = Eigen::LLT<Eigen::MatrixXd>(n);
    w.llt_z = Eigen::LLT<Eigen::MatrixXd>(n);
    w.svd = Eigen::JacobiSVD<Eigen::MatrixXd>(n, n, Eigen::ComputeFullU | Eigen::ComputeFullV);
    w.eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(n);
  }
  margin_.setup(p);
  for (Eigen::VectorXd* v : {&x_, &rx_, &g_, &t1_, &t2_, &r1_, &cdx_, &x1_, &dx_, &dx_a_, &bx_, &best_x_, &xhat_})
    v->setZero(m_);
  for (Eigen::VectorXd* v : {&y_, &ry_, &gy_, &t3_, &ry2_, &r2_, &cdy_, &y1_, &dy_, &dy_a_, &by_, &best_y_})
    v->setZero(pe_);
  M_.setZero(m_, m_);
  K_.setZero(m_, m_);
  lltK_ = Eigen::LLT<Eigen::MatrixXd>(m_);
  KinvAt_.setZero(m_, pe_);
  SA_.setZero(pe_, pe_);
  lltSA_ = Eigen::LLT<Eigen::MatrixXd>(pe_);
  AtA_.setZero(m_, m_);
  if (pe_ > 0) AtA_.noalias() = p.eq_matrix().transpose() * p.eq_matrix();
  result_.x.setZero(m_);
  result_.y.setZero(pe_);
  result_.Z.resize(nb);
  for (size_t b = 0; b < nb; ++b) result_.Z[b].setZero(w_[b].n, w_[b].n);
  version_ = p.structure_version();
}

SETBOUND_LMI_SOLVER_INLINE void InteriorPointSolver::residuals() {
  // rx = Aᵀy + Gᵀz + cτ;  ry = bτ − Ax;  rz = S − (F0 τ + Σ x_i F_i);  rτ = κ + cᵀx + bᵀy + hᵀz
  const LmiProblem& p = *p_;
  rx_ = p.objective() * tau_;
  double hz = 0;
  for (size_t b = 0; b < w_.size(); ++b) {
    const LmiBlock& blk = p.block(static_cast<int>(b));
    BlockWork& w = w_[b];
    detail::dispatch_size(w.n, fixed(), [&](auto NC) {
      constexpr int N = decltype(NC)::value;
      using Mat = Eigen::Matrix<double, N, N>;
      const int n = w.n;
      Eigen::Map<Mat> rz(w.rz.data(), n, n);
      const Eigen::Map<const Mat> S(w.S.data(), n, n), Z(w.Z.data(), n, n), F0(blk.constant.data(), n, n);
      rz = S - tau_ * F0;
      for (const auto& co : blk.coefficients) {
        const Eigen::Map<const Mat> F(co.dense.data(), n, n);
        rx_(co.var) -= F.cwiseProduct(Z).sum();
        rz.noalias() -= x_(co.var) * F;
      }
      hz += F0.cwiseProduct(Z).sum();
    });
  }
  double by = 0;
  if (pe_ > 0) {
    rx_.noalias() += p.eq_matrix().transpose() * y_;
    ry_ = p.eq_rhs() * tau_;
    ry_.noalias() -= p.eq_matrix() * x_;
    by = p.eq_rhs().dot(y_);
  }
  rtau_ = kappa_ + p.objective().dot(x_) + by + hz;
  // Metrics of the current iterate (x/τ, y/τ, z/τ).
  double sz = 0, rznorm2 = 0;
  for (auto& w : w_) {
    sz += w.S.cwiseProduct(w.Z).sum();
    rznorm2 += w.rz.squaredNorm();
  }
  pcost_ = p.objective().dot(x_) / tau_;
  dcost_ = -(by + hz) / tau_;
  gap_ = sz / (tau_ * tau_);
  const double pres_y = pe_ > 0 ? ry_.norm() / resy0_ : 0.0;
  pres_ = std::max(pres_y, std::sqrt(rznorm2) / resz0_) / tau_;
  dres_ = rx_.norm() / resx0_ / tau_;
  const double dgap = std::max(gap_, std::abs(pcost_ - dcost_));
  relgap_ = dgap / std::max(1.0, std::min(std::abs(pcost_), std::abs(dcost_)));
}

SETBOUND_LMI_SOLVER_INLINE bool InteriorPointSolver::scaling() {
  bool ok = true;
  for (auto& w : w_) {
    detail::dispatch_size(w.n, fixed(), [&](auto NC) {
      constexpr int N = decltype(NC)::value;
      if constexpr (N == Eigen::Dynamic) {
        w.llt_s.compute(w.S);
        if (w.llt_s.info() != Eigen::Success) { ok = false; return; }
        w.llt_z.compute(w.Z);
        if (w.llt_z.info() != Eigen::Success) { ok = false; return; }
        // L_zᵀ L_s = U Λ Vᵀ;  R = L_s V Λ^{-1/2};  Q = R⁻ᵀ = L_z U Λ^{-1/2}.
        // (The dynamic SelfAdjointEigenSolver allocates a Householder workspace when
        // eigenvectors are requested; JacobiSVD with preallocated storage does not.)
        w.tmp = w.llt_s.matrixL();
        w.tmp2 = w.llt_z.matrixL();
        mul(w.LzLs, w.tmp2.transpose(), w.tmp);
        w.svd.compute(w.LzLs);
        w.lambda = w.svd.singularValues();
        if (!(w.lambda.minCoeff() > 0) || !w.lambda.allFinite()) { ok = false; return; }
        w.isq = w.lambda.cwiseSqrt().cwiseInverse();
        mul(w.R, w.tmp, w.svd.matrixV());
        w.R.array().rowwise() *= w.isq.transpose().array();
        mul(w.Q, w.tmp2, w.svd.matrixU());
        w.Q.array().rowwise() *= w.isq.transpose().array();
      } else {
        using Mat = Eigen::Matrix<double, N, N>;
        using Vec = Eigen::Matrix<double, N, 1>;
        const Eigen::Map<const Mat> S(w.S.data()), Z(w.Z.data());
        Eigen::Map<Mat> Ls(w.tmp.data()), Lz(w.tmp2.data()), G(w.LzLs.data()), H(w.dS.data()), R(w.R.data()),
            Q(w.Q.data());
        Eigen::Map<Vec> lam(w.lambda.data()), isq(w.isq.data());
        const Eigen::LLT<Mat> llt_s(S);
        if (llt_s.info() != Eigen::Success) { ok = false; return; }
        const Eigen::LLT<Mat> llt_z(Z);
        if (llt_z.info() != Eigen::Success) { ok = false; return; }
        Ls = llt_s.matrixL();
        Lz = llt_z.matrixL();
        // Same NT scaling as the dynamic path, with the SVD of G = L_zᵀL_s replaced by the
        // symmetric eigendecomposition GᵀG = L_sᵀ Z L_s = V Λ² Vᵀ (a fixed-size eigensolver
        // is several times cheaper than JacobiSVD). G is formed from the Cholesky factors as
        // before, so its entries carry the same relative accuracy; squaring only involves the
        // spread of Λ within one block, which stays small near the central path.
        //   R = L_s V Λ^{-1/2}:  RᵀZR = Λ,  R⁻¹SR⁻ᵀ = Λ;   Q = R⁻ᵀ = L_s⁻ᵀ V Λ^{1/2}
        // (triangular solve, so QᵀR = I to rounding, which kkt_solve relies on).
        G.noalias() = Lz.transpose().lazyProduct(Ls);
        H.noalias() = G.transpose().lazyProduct(G);
        detail::symmetrize(H);
        const Eigen::SelfAdjointEigenSolver<Mat> es(H);
        if (es.info() != Eigen::Success) { ok = false; return; }
        const Vec& l2 = es.eigenvalues();
        if (!(l2.minCoeff() > 0) || !l2.allFinite()) { ok = false; return; }
        lam = l2.cwiseSqrt();
        isq = lam.cwiseSqrt().cwiseInverse();
        R.noalias() = Ls.lazyProduct(es.eigenvectors());
        R.array().rowwise() *= isq.transpose().array();
        Q = es.eigenvectors();
        Q.array().rowwise() *= lam.cwiseSqrt().transpose().array();
        Ls.transpose().template triangularView<Eigen::Upper>().solveInPlace(Q);
      }
    });
    if (!ok) return false;
  }
  return true;
}

SETBOUND_LMI_SOLVER_INLINE bool InteriorPointSolver::assemble_and_factor() {
  const LmiProblem& p = *p_;
  M_.setZero();
  for (size_t b = 0; b < w_.size(); ++b) {
    const LmiBlock& blk = p.block(static_cast<int>(b));
    BlockWork& w = w_[b];
    detail::dispatch_size(w.n, fixed(), [&](auto NC) {
      constexpr int N = decltype(NC)::value;
      constexpr int D = detail::svec_size<N>();
      using Mat = Eigen::Matrix<double, N, N>;
      using SVec = Eigen::Matrix<double, D, 1>;
      const int n = w.n;
      const int d = n * (n + 1) / 2;
      const Eigen::Map<const Mat> Q(w.Q.data(), n, n);
      Eigen::Map<Mat> tmp(w.tmp.data(), n, n), Ft(w.tmp2.data(), n, n), rzt(w.rzt.data(), n, n);
      // svec(QᵀFQ) from P = FQ and only the upper triangle of QᵀP (dots of columns):
      // n³ + n²(n+1)/2 multiplications instead of 2n³.
      auto scaled_svec = [&](const auto& F, double* v) {
        constexpr double r2 = 1.4142135623730951;
        mul(tmp, F, Q);
        int idx = 0;
        for (int c = 0; c < n; ++c) {
          for (int r = 0; r < c; ++r) v[idx++] = r2 * Q.col(r).dot(tmp.col(c));
          v[idx++] = Q.col(c).dot(tmp.col(c));
        }
      };
      for (int j = 0; j < w.k; ++j) {
        const Coefficient& co = blk.coefficients[static_cast<size_t>(j)];
        if (co.kind == CoefficientKind::Sparse) {
          // QᵀFQ = Σ f_rc (q_r q_cᵀ + q_c q_rᵀ) over the upper-triangle entries (q_r = row r
          // of Q); pack_svec symmetrises, so an off-diagonal entry adds 2 f q_r q_cᵀ.
          Ft.setZero();
          for (const auto& e : co.entries) {
            const double f = e.row == e.col ? e.value : 2.0 * e.value;
            Ft.noalias() += f * Q.row(e.row).transpose() * Q.row(e.col);
          }
          detail::pack_svec(Ft, w.Fv.col(j).data());
        } else {
          scaled_svec(Eigen::Map<const Mat>(co.dense.data(), n, n), w.Fv.col(j).data());
        }
      }
      const Eigen::Map<const Mat> F0(blk.constant.data(), n, n), rz(w.rz.data(), n, n);
      scaled_svec(F0, w.f0v.data());
      // Qᵀ rz Q is shared by the predictor and the corrector right-hand sides.
      mul(tmp, rz, Q);
      mul(rzt, Q.transpose(), tmp);
      detail::symmetrize(rzt);
      const Eigen::Map<const SVec> f0(w.f0v.data(), d);
      // Schur complement M_ij += svec(F̃_i)·svec(F̃_j) (upper triangle, mirrored).
      for (int j = 0; j < w.k; ++j) {
        const Eigen::Map<const SVec> fj(w.Fv.col(j).data(), d);
        w.fvf0(j) = fj.dot(f0);
        const int vj = w.vars[static_cast<size_t>(j)];
        for (int i = 0; i < j; ++i) {
          const double v = Eigen::Map<const SVec>(w.Fv.col(i).data(), d).dot(fj);
          const int vi = w.vars[static_cast<size_t>(i)];
          M_(vi, vj) += v;
          M_(vj, vi) += v;
        }
        M_(vj, vj) += fj.squaredNorm();
      }
    });
  }
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
  lltK_.compute(K_);
  if (lltK_.info() != Eigen::Success) return false;
  if (pe_ > 0) {
    KinvAt_ = p.eq_matrix().transpose();
    lltK_.solveInPlace(KinvAt_);
    SA_.noalias() = p.eq_matrix() * KinvAt_;
    SA_.diagonal().array() += 1e-14 * std::max(1.0, SA_.diagonal().maxCoeff());
    lltSA_.compute(SA_);
    if (lltSA_.info() != Eigen::Success) return false;
  }
  return true;
}

// Solves M dx + Aᵀdy = g, A dx = by (K = M + ρAᵀA formulation), with one refinement step.
SETBOUND_LMI_SOLVER_INLINE void InteriorPointSolver::solve_reduced(const Eigen::VectorXd& g, const Eigen::VectorXd& by,
                                                Eigen::VectorXd& dx, Eigen::VectorXd& dy) {
  const LmiProblem& p = *p_;
  auto base = [&](const Eigen::VectorXd& gg, const Eigen::VectorXd& bb, Eigen::VectorXd& ox, Eigen::VectorXd& oy) {
    t1_ = gg;
    if (pe_ > 0) t1_.noalias() += rho_ * p.eq_matrix().transpose() * bb;
    lltK_.solveInPlace(t1_);  // t1 = K⁻¹(g + ρAᵀb)
    if (pe_ > 0) {
      oy.noalias() = p.eq_matrix() * t1_;
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
    r1_.noalias() -= M_ * dx;
    if (pe_ > 0) {
      r1_.noalias() -= p.eq_matrix().transpose() * dy;
      r2_ = by;
      r2_.noalias() -= p.eq_matrix() * dx;
    }
    base(r1_, r2_, cdx_, cdy_);
    dx += cdx_;
    if (pe_ > 0) dy += cdy_;
  }
}

// Solves the KKT system  Aᵀdy + Gᵀdz = bx,  A dx = by,  G dx − WᵀW dz = bz  where
//   bz = use_F0 ? F0 : −eta_rz·rz − Wᵀ(U)   (U = λ⁻¹◇ds_rhs held in w.U when with_u).
// On return w.btv = svec(Qᵀ bz Q) (needed to form W dz = −Σ dx_j F̃_j − B̃).
SETBOUND_LMI_SOLVER_INLINE void InteriorPointSolver::kkt_solve(const Eigen::VectorXd& bx, const Eigen::VectorXd& by, bool use_F0,
                                            double eta_rz, bool with_u, Eigen::VectorXd& dx, Eigen::VectorXd& dy) {
  g_ = bx;
  for (auto& w : w_) {
    detail::dispatch_size(w.n, fixed(), [&](auto NC) {
      constexpr int N = decltype(NC)::value;
      constexpr int D = detail::svec_size<N>();
      using Mat = Eigen::Matrix<double, N, N>;
      using SVec = Eigen::Matrix<double, D, 1>;
      const int n = w.n;
      const int d = n * (n + 1) / 2;
      Eigen::Map<SVec> bt(w.btv.data(), d);
      if (use_F0) {
        bt = Eigen::Map<const SVec>(w.f0v.data(), d);
      } else {
        // B̃ = −η Qᵀ rz Q − U  (QᵀR U RᵀQ = U since QᵀR = I)
        Eigen::Map<Mat> Bt(w.Bt.data(), n, n);
        const Eigen::Map<const Mat> rzt(w.rzt.data(), n, n), U(w.U.data(), n, n);
        Bt = -eta_rz * rzt;
        if (with_u) Bt -= U;
        detail::pack_svec(Bt, w.btv.data());
      }
      // g_i −= <F̃_i, B̃>
      for (int j = 0; j < w.k; ++j)
        g_(w.vars[static_cast<size_t>(j)]) -= Eigen::Map<const SVec>(w.Fv.col(j).data(), d).dot(bt);
    });
  }
  solve_reduced(g_, by, dx, dy);
}

SETBOUND_LMI_SOLVER_INLINE double InteriorPointSolver::max_step_scaled(BlockWork& w, const Eigen::MatrixXd& X, double bound) {
  // Largest α with Λ + αX ⪰ 0: α = −1/λ_min(Λ^{-1/2} X Λ^{-1/2}) when that is negative.
  // Only values below `bound` matter to the caller (step_length): when I + bound·T is
  // positive definite (one small Cholesky), α ≥ bound and +∞ is returned without an
  // eigenvalue computation.
  double e = 0;
  bool skip = false;
  detail::dispatch_size(w.n, fixed(), [&](auto NC) {
    constexpr int N = decltype(NC)::value;
    using Mat = Eigen::Matrix<double, N, N>;
    const int n = w.n;
    Eigen::Map<Mat> T(w.tmp.data(), n, n);
    const Eigen::Map<const Mat> Xm(X.data(), n, n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) T(i, j) = Xm(i, j) * w.isq(i) * w.isq(j);
    if constexpr (N == Eigen::Dynamic) {
      w.eig.compute(w.tmp, Eigen::EigenvaluesOnly);
      e = w.eig.eigenvalues()(0);
    } else {
      const Mat B = Mat::Identity() + bound * T;
      const Eigen::LLT<Mat> llt(B);
      if (llt.info() == Eigen::Success && std::isfinite(bound)) {
        skip = true;
        return;
      }
      e = detail::lambda_min_small<N>(T);
    }
  });
  if (skip) return std::numeric_limits<double>::infinity();
  return e >= 0 ? std::numeric_limits<double>::infinity() : -1.0 / e;
}

// One Newton direction of the embedding. Predictor: eta = 1, sigma = 0; corrector adds the
// second-order term (W⁻ᵀds_a)∘(W dz_a) and centring σμ (Mehrotra).
SETBOUND_LMI_SOLVER_INLINE void InteriorPointSolver::direction(double eta, double sigma, double mu, bool corrector) {
  const LmiProblem& p = *p_;
  // ds_rhs = −λ∘λ + σμe − corr  ⇒  U = λ⁻¹◇ds_rhs: U_ij = 2 ds_rhs_ij / (λ_i + λ_j)
  for (auto& w : w_) {
    detail::dispatch_size(w.n, fixed(), [&](auto NC) {
      constexpr int N = decltype(NC)::value;
      using Mat = Eigen::Matrix<double, N, N>;
      const int n = w.n;
      Eigen::Map<Mat> T(w.tmp.data(), n, n), U(w.U.data(), n, n);
      const Eigen::Map<const Mat> A(w.Wds_a.data(), n, n), B(w.Wdz_a.data(), n, n);
      if (corrector) mul(T, A, B);
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          double r = (i == j) ? (-w.lambda(i) * w.lambda(i) + sigma * mu) : 0.0;
          if (corrector) r -= 0.5 * (T(i, j) + T(j, i));  // (Wds_a)∘(Wdz_a)
          U(i, j) = 2.0 * r / (w.lambda(i) + w.lambda(j));
        }
    });
  }
  double dk_rhs = -tau_ * kappa_ + sigma * mu;
  if (corrector) dk_rhs -= dtau_a_ * dkappa_a_;
  // u0: bx = −η rx, by = η ry, bz = −η rz − Wᵀ U.
  bx_ = -eta * rx_;
  if (pe_ > 0) by_ = eta * ry_;
  kkt_solve(bx_, by_, false, eta, true, dx_, dy_);
  // hᵀdz0 = <F̃0, W dz0>,  W dz0 = −Σ dx_j F̃_j − B̃0
  double cx0 = p.objective().dot(dx_) + (pe_ > 0 ? p.eq_rhs().dot(dy_) : 0.0);
  double cx1 = p.objective().dot(x1_) + (pe_ > 0 ? p.eq_rhs().dot(y1_) : 0.0);
  for (auto& w : w_) {
    double hz0 = -w.f0v.dot(w.btv), hz1 = -w.f0v.squaredNorm();
    for (int j = 0; j < w.k; ++j) {
      const double fj = w.fvf0(j);
      hz0 -= dx_(w.vars[static_cast<size_t>(j)]) * fj;
      hz1 -= x1_(w.vars[static_cast<size_t>(j)]) * fj;
    }
    cx0 += hz0;
    cx1 += hz1;
  }
  dtau_ = (-eta * rtau_ - dk_rhs / tau_ - cx0) / (cx1 - kappa_ / tau_);
  dx_ += dtau_ * x1_;
  if (pe_ > 0) dy_ += dtau_ * y1_;
  dkappa_ = (dk_rhs - kappa_ * dtau_) / tau_;
  for (auto& w : w_) {
    detail::dispatch_size(w.n, fixed(), [&](auto NC) {
      constexpr int N = decltype(NC)::value;
      constexpr int D = detail::svec_size<N>();
      using Mat = Eigen::Matrix<double, N, N>;
      using SVec = Eigen::Matrix<double, D, 1>;
      const int n = w.n;
      const int d = n * (n + 1) / 2;
      // W dz = −Σ dx_j F̃_j − B̃0 − dτ F̃0;  W⁻ᵀds = U − W dz
      Eigen::Map<SVec> wv(w.wv.data(), d);
      wv = -Eigen::Map<const SVec>(w.btv.data(), d) - dtau_ * Eigen::Map<const SVec>(w.f0v.data(), d);
      for (int j = 0; j < w.k; ++j)
        wv.noalias() -= dx_(w.vars[static_cast<size_t>(j)]) * Eigen::Map<const SVec>(w.Fv.col(j).data(), d);
      Eigen::Map<Mat> Wdz(w.Wdz.data(), n, n), Wds(w.Wds.data(), n, n);
      const Eigen::Map<const Mat> U(w.U.data(), n, n);
      detail::unpack_svec(w.wv.data(), Wdz);
      Wds = U - Wdz;
    });
  }
}

SETBOUND_LMI_SOLVER_INLINE double InteriorPointSolver::step_length() {
  // The callers use min(1, α_max) (predictor) and min(1, step_fraction·α_max) (corrector), so
  // α_max is only needed exactly below cap = 2/step_fraction; above it the result is
  // clamped to cap. Blocks are tested against the running minimum, so a block that does not
  // limit the step costs one small Cholesky instead of an eigenvalue computation.
  double amax = 2.0 / opt_.step_fraction;
  if (dtau_ < 0) amax = std::min(amax, -tau_ / dtau_);
  if (dkappa_ < 0) amax = std::min(amax, -kappa_ / dkappa_);
  for (auto& w : w_) {
    amax = std::min(amax, max_step_scaled(w, w.Wds, amax));
    amax = std::min(amax, max_step_scaled(w, w.Wdz, amax));
  }
  return amax;
}

SETBOUND_LMI_SOLVER_INLINE void InteriorPointSolver::record_best(double merit) {
  if (!(merit < best_merit_)) return;
  best_merit_ = merit;
  best_x_ = x_ / tau_;
  if (pe_ > 0) best_y_ = y_ / tau_;
  for (auto& w : w_) w.best_Z = w.Z / tau_;
  best_pcost_ = pcost_;
  best_dcost_ = dcost_;
  best_gap_ = gap_;
  best_relgap_ = relgap_;
  best_pres_ = pres_;
  best_dres_ = dres_;
}

SETBOUND_LMI_SOLVER_INLINE void InteriorPointSolver::finish(SolveStatus status) {
  // Returns the best iterate for non-converged statuses, the current one otherwise.
  result_.status = status;
  if (status == SolveStatus::Optimal) {
    result_.x = x_ / tau_;
    if (pe_ > 0) result_.y = y_ / tau_;
    for (size_t b = 0; b < w_.size(); ++b) result_.Z[b] = w_[b].Z / tau_;
    result_.objective = pcost_;
    result_.dual_objective = dcost_;
    result_.gap = gap_;
    result_.relative_gap = relgap_;
    result_.primal_residual = pres_;
    result_.dual_residual = dres_;
  } else if (status == SolveStatus::Infeasible || status == SolveStatus::Unbounded) {
    // set by caller
  } else {
    result_.x = best_x_;
    if (pe_ > 0) result_.y = best_y_;
    for (size_t b = 0; b < w_.size(); ++b) result_.Z[b] = w_[b].best_Z;
    result_.objective = best_pcost_;
    result_.dual_objective = best_dcost_;
    result_.gap = best_gap_;
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

SETBOUND_LMI_SOLVER_INLINE const SolveResult& InteriorPointSolver::solve() {
  const auto t0 = std::chrono::steady_clock::now();
  const LmiProblem& p = *p_;
  if (p.structure_version() != version_) setup();
  p.require_solvable();
  if (p.num_blocks() == 0) throw InvalidArgumentError("blocks: the problem has no LMI block (add at least one)");

  resx0_ = std::max(1.0, p.objective().norm());
  resy0_ = std::max(1.0, pe_ > 0 ? p.eq_rhs().norm() : 0.0);
  double h2 = 0;
  for (const auto& blk : p.blocks()) h2 += blk.constant.squaredNorm();
  resz0_ = std::max(1.0, std::sqrt(h2));
  if (pe_ > 0) AtA_.noalias() = p.eq_matrix().transpose() * p.eq_matrix();

  // Standard embedding start: x = 0, y = 0, S = Z = I, τ = κ = 1 (on the central ray).
  x_.setZero();
  y_.setZero();
  for (auto& w : w_) {
    w.S.setIdentity();
    w.Z.setIdentity();
  }
  tau_ = kappa_ = 1.0;
  best_merit_ = std::numeric_limits<double>::infinity();
  result_.x.setZero();
  result_.margin = -std::numeric_limits<double>::infinity();

  const double nu1 = static_cast<double>(nu_ + 1);
  int iter = 0;
  SolveStatus status = SolveStatus::MaxIterations;
  MarginChecker& mc = margin_;
  for (;; ++iter) {
    residuals();
    const double merit = std::max({pres_, dres_, std::min(relgap_, gap_ / opt_.gap_abs * opt_.gap_rel)});
    if (std::isfinite(merit)) record_best(merit);

    // --- termination ---
    if (pres_ <= opt_.feas && dres_ <= opt_.feas && (gap_ <= opt_.gap_abs || relgap_ <= opt_.gap_rel)) {
      status = SolveStatus::Optimal;
      break;
    }
    if (opt_.feasibility_var >= 0 && x_(opt_.feasibility_var) < 0) {
      xhat_ = x_ / tau_;
      if (mc.margin(p, xhat_, opt_.feasibility_var) > 0) {
        status = SolveStatus::Optimal;
        break;
      }
    }
    {
      // Primal infeasibility certificate: Gᵀz + Aᵀy ≈ 0 with hᵀz + bᵀy < 0.
      double hz = 0;
      for (size_t b = 0; b < w_.size(); ++b) hz += p.block(static_cast<int>(b)).constant.cwiseProduct(w_[b].Z).sum();
      const double ny = -(hz + (pe_ > 0 ? p.eq_rhs().dot(y_) : 0.0));
      if (ny > 0) {
        // ‖Aᵀy + Gᵀz‖ = ‖rx − cτ‖
        const double r = (rx_ - p.objective() * tau_).norm() / resx0_;
        if (r <= opt_.feas * ny) {
          status = SolveStatus::Infeasible;
          break;
        }
      }
      // Dual infeasibility (unbounded): Gx + s ≈ 0, Ax ≈ 0, cᵀx < 0.
      const double cx = -p.objective().dot(x_);
      if (cx > 0) {
        double r2 = 0;
        for (auto& w : w_) r2 = std::max(r2, (w.rz + tau_ * p.block(static_cast<int>(&w - w_.data())).constant).norm() / resz0_);
        if (pe_ > 0) r2 = std::max(r2, (ry_ - p.eq_rhs() * tau_).norm() / resy0_);
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
    double sz = 0;
    for (auto& w : w_) sz += w.S.cwiseProduct(w.Z).sum();
    const double mu = (sz + tau_ * kappa_) / nu1;
    if (!scaling() || !assemble_and_factor()) {
      status = SolveStatus::NumericalError;
      break;
    }
    // τ-direction: K (x1, y1, z1) = (−c, b, h)
    bx_ = -p.objective();
    if (pe_ > 0) by_ = p.eq_rhs();
    kkt_solve(bx_, by_, true, 0.0, false, x1_, y1_);

    direction(1.0, 0.0, mu, false);
    double alpha_a = std::min(1.0, step_length());
    for (auto& w : w_) {
      w.Wds_a = w.Wds;
      w.Wdz_a = w.Wdz;
    }
    dtau_a_ = dtau_;
    dkappa_a_ = dkappa_;
    const double sigma = std::pow(1.0 - alpha_a, 3);
    direction(1.0 - sigma, sigma, mu, true);
    const double amax = step_length();
    const double alpha = std::min(1.0, opt_.step_fraction * amax);
    if (!(alpha > 1e-12) || !dx_.allFinite()) {
      status = SolveStatus::NumericalError;
      break;
    }
    // Update: ds = R (W⁻ᵀds) Rᵀ, dz = Q (W dz) Qᵀ.
    x_ += alpha * dx_;
    if (pe_ > 0) y_ += alpha * dy_;
    for (auto& w : w_) {
      detail::dispatch_size(w.n, fixed(), [&](auto NC) {
        constexpr int N = decltype(NC)::value;
        using Mat = Eigen::Matrix<double, N, N>;
        const int n = w.n;
        Eigen::Map<Mat> T(w.tmp.data(), n, n), dS(w.dS.data(), n, n), dZ(w.dZ.data(), n, n), S(w.S.data(), n, n),
            Z(w.Z.data(), n, n);
        const Eigen::Map<const Mat> R(w.R.data(), n, n), Q(w.Q.data(), n, n), Wds(w.Wds.data(), n, n),
            Wdz(w.Wdz.data(), n, n);
        mul(T, R, Wds);
        mul(dS, T, R.transpose());
        mul(T, Q, Wdz);
        mul(dZ, T, Q.transpose());
        S += alpha * dS;
        Z += alpha * dZ;
        detail::symmetrize(S);
        detail::symmetrize(Z);
      });
    }
    tau_ += alpha * dtau_;
    kappa_ += alpha * dkappa_;
  }

  result_.iterations = iter;
  if (status == SolveStatus::Infeasible) {
    double hz = 0;
    for (size_t b = 0; b < w_.size(); ++b) hz += p.block(static_cast<int>(b)).constant.cwiseProduct(w_[b].Z).sum();
    const double ny = -(hz + (pe_ > 0 ? p.eq_rhs().dot(y_) : 0.0));
    for (size_t b = 0; b < w_.size(); ++b) result_.Z[b] = w_[b].Z / ny;
    if (pe_ > 0) result_.y = y_ / ny;
    result_.x.setConstant(std::numeric_limits<double>::quiet_NaN());
    result_.objective = std::numeric_limits<double>::infinity();
    result_.dual_objective = std::numeric_limits<double>::infinity();
    finish(status);
  } else if (status == SolveStatus::Unbounded) {
    const double cx = -p.objective().dot(x_);
    result_.x = x_ / cx;  // ray with cᵀx = −1
    result_.objective = -std::numeric_limits<double>::infinity();
    result_.dual_objective = -std::numeric_limits<double>::infinity();
    finish(status);
  } else {
    finish(status);
  }
  result_.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result_;
}

/// Convenience: one solve of a linear-objective problem.
#endif  // SETBOUND_LMI_EXTERN_SOLVER

inline SolveResult solve_linear(const LmiProblem& problem, const SolverOptions& options = {}) {
  InteriorPointSolver s(problem, options);
  return s.solve();
}

}  // namespace setbound::lmi
