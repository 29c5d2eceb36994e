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
//    Cholesky factors of S and Z and the right singular vectors V of G = L_zᵀL_s (the
//    eigenvectors of GᵀG = L_sᵀ Z L_s, whose eigenvalues Λ² stay within a modest ratio on the
//    central path; when that ratio exceeds 1e10 a one-sided Jacobi SVD of G, accurate for
//    tiny singular values, is used instead): R = L_s V Λ^{-1/2}, Q = R⁻ᵀ = L_s⁻ᵀ V Λ^{1/2};
//  * Schur complement M_ij = Σ_b tr(F_bi T_b F_bj T_b), T_b = QQᵀ, assembled block by block
//    as a Gram matrix of the scaled coefficients F̃_bi = QᵀF_biQ (only variables that touch a
//    block contribute; sparse coefficients are scaled by rank-one updates); for large blocks
//    whose coefficients are all sparse, from the arm form of the coefficients instead (ArmForm:
//    products of a few rows and sparse vectors), when that is cheaper; dense Cholesky;
//  * Mehrotra predictor–corrector with σ = (1 − α_aff)³; step lengths from λ_min of the
//    scaled directions, skipped (one Cholesky factorisation) for blocks that do not limit it;
//  * two-tier termination (full / reduced tolerances → "inaccurate"), best iterate kept.
// All work arrays are allocated in setup(); solve() itself does not allocate. The per-block
// dense work (blocks are small: 1…16 in the online problems) runs on the plain loops of
// kernels.hpp, which at these sizes are several times faster than Eigen's dynamic-size
// decompositions and need no per-size template instantiation.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>
#if defined(_OPENMP)
#include <omp.h>
#endif

#include "setbound/lmi/kernels.hpp"
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

const char* status_name(SolveStatus s);

struct SolverOptions {
  int max_iterations = 100;
  double time_limit = 30.0;          // seconds, checked once per iteration
  double gap_rel = 1e-7;             // relative duality gap
  double gap_abs = 1e-9;             // absolute duality gap
  double feas = 1e-8;                // relative primal/dual residuals, certificate residuals
  double reduced_gap_rel = 5e-5;     // "inaccurate" tier
  double reduced_gap_abs = 5e-7;
  double reduced_feas = 1e-5;
  double step_fraction = 0.99;       // of the largest step, after a full predictor step (solve())
  bool compute_margin = true;
  // Feasibility mode (classes.hpp): stop at the first iterate where x[feasibility_var] < 0
  // and the verified margin of all blocks, evaluated without that variable, is positive.
  int feasibility_var = -1;
  // Threads over the blocks inside solve() (per-block scaling, Schur contributions, directions,
  // step lengths, residuals). Takes effect in builds with OpenMP (the C ABI library is one);
  // elsewhere solve() runs serially whatever is set. Every block does the same operations
  // whatever the thread count; the sums over blocks are formed per thread and then added, so
  // results agree with the serial solve to rounding. Pays off from a few dozen blocks
  // (docs/benchmarks.md "LMI solver"); 1 = serial.
  int threads = 1;

  void validate() const;
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

/// The "arm form" of a block's coefficients, for the Schur complement of large blocks with many
/// sparse coefficients. Each coefficient is written as F_j = Σ_a (e_{r_a} g_aᵀ + g_a e_{r_a}ᵀ)
/// over a few "arms" a: a row r_a of the block and a sparse vector g_a (the entries of F_j in
/// row r_a that no earlier arm of F_j covers, half the diagonal one). The arms are chosen
/// greedily (the row with the most uncovered non-zeros first), so that a variable entering a
/// block through whole rows or columns (x_ij of a matrix variable X in a product X·A, A·X) has
/// one or two arms. With T (n×n) the block's congruence F̃ = T F Tᵀ (the solver: T = Qᵀ; the
/// barrier of solve_maxdet: T = L⁻¹), q_r = T e_r and h_a = T g_a, F̃_j = Σ_a (q_{r_a} h_aᵀ + h_a q_{r_a}ᵀ) and
///   ⟨F̃_i, F̃_j⟩ = 2 Σ_{a ∈ i, b ∈ j} [ W(r_a, r_b) (h_a·h_b) + (q_{r_a}·h_b)(h_a·q_{r_b}) ],
/// W = TᵀT: from W, TᵀT G and (TG)ᵀ(TG) (G: the distinct g vectors as columns; equal vectors —
/// the same row of A in x_ij·A for every i — are stored once), the Gram matrix of k coefficients
/// costs about (Σ_j arms_j)² instead of the n(n+1)/2·k² of the products of the dense scaled
/// coefficients (the sparsity-exploiting formulas of Fujisawa, Kojima & Nakata 1997, in the
/// low-rank form of the coefficients). Tank30's PRad-E LMI (111×111, 1 095 variables): about 2.2
/// arms per coefficient and 160 distinct vectors.
struct ArmForm {
  int n = 0, k = 0, nvec = 0;
  std::vector<int> start;     // k + 1: the arms of coefficient j are start[j] … start[j + 1] − 1
  std::vector<int> row, vec;  // per arm: its row r_a and its column of G
  Eigen::MatrixXd G;          // n × nvec: the distinct g vectors (unscaled)
  Eigen::MatrixXd W, H, WG, HH;  // prepare(): TᵀT, T G, Tᵀ T G, (TG)ᵀ(TG)

  /// Arm form of the coefficients blk.coefficients[order[j]], j < count (order: null = 0, 1, …).
  void build(const LmiBlock& blk, const int* order, int count);
  /// Estimated multiply-adds of one prepare() + gram() + k svec_add() calls.
  double cost() const;
  /// W, H, WG, HH for the congruence T (n×n, column-major: q_r = column r of T).
  void prepare(const double* T);
  /// Upper triangle of G_ij = s_i s_j ⟨F̃_i, F̃_j⟩ (k×k, leading dimension ldg).
  void gram(const double* s, double* out, long ldg) const;
  /// out (length n(n+1)/2, svec) = s · svec(F̃_j) (after prepare(); T as given there).
  void svec_column(int j, const double* T, double s, double* out) const;
  /// tr(F̃_j) = 2 Σ_a q_{r_a}·h_a (after prepare()).
  double trace(int j) const;

 private:
  std::vector<int> cnt_, touched_, order_, gstart_;
  std::vector<char> is_row_, used_;
  std::vector<SparseEntry> ent_;
  std::vector<std::pair<int, double>> gall_;
  std::vector<std::uint64_t> hash_;
};

/// Workspace and verified margin of a point, reusable without allocation.
class MarginChecker {
 public:
  void setup(const LmiProblem& p);

  /// Largest δ among a few candidates for which the Cholesky factorisation of F_b(x) − δI
  /// succeeded for every block (δ < 0: x is not feasible). `skip_var` ≥ 0 evaluates the
  /// blocks as if x[skip_var] were 0 (feasibility mode's auxiliary variable).
  double margin(const LmiProblem& p, const Eigen::VectorXd& x, int skip_var = -1);

 private:
  static void evaluate(const LmiProblem& p, const LmiBlock& blk, const Eigen::VectorXd& x, int skip_var,
                       Eigen::MatrixXd& out);
  std::vector<Eigen::MatrixXd> F_;
  Eigen::VectorXd work_;  // nmax² storage, used as an n×n matrix with leading dimension n
  Eigen::VectorXd wv_, ev_;
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
  // Per-block work. The scaled coefficients are kept in svec form (kernels.hpp): column 0 of
  // Fs is svec(QᵀF0Q), column 1 svec(Qᵀ rz Q), columns 2… the coefficients in the order of
  // `col`: first the dense ones (computed together from the stacked V), then the sparse ones
  // (rank-one updates). The order is refreshed at every solve (load_values), because a value
  // update may turn a sparse coefficient dense and back.
  struct BlockWork {
    int n = 0, k = 0, sv = 0, kd = 0;  // size, coefficients, svec length, dense coefficients
    std::vector<int> col;   // coefficient index (into LmiBlock::coefficients) of Fs column 2 + j
    std::vector<int> var;   // its variable
    int var0 = -1;          // var[j] = var0 + j for every j (a contiguous run), else −1
    Eigen::MatrixXd S, Z, dS, dZ, rz, R, Q, Qt, Ls, Lz, tmp, tmp2, Wds, Wdz, Wds_a, Wdz_a, U, best_Z;
    // V holds F0, rz and the dense coefficients in `col` order as matrices ("slots") 0, 1, 2…:
    // for n ≤ kernels::kInterleavedMax interleaved by row (row r·cp + slot = row r of the
    // slot's matrix; (n·cp)×n, unused slots zero), else stacked (row slot·n + r; (n·(k+2))×n).
    Eigen::MatrixXd V;
    Eigen::MatrixXd P, T;   // work of V's shape (kernels::congruence_svec)
    // sv×cp, row-major: column 0 svec(QᵀF0Q), 1 svec(QᵀrzQ), 2 + j svec(QᵀF_jQ) (see above);
    // columns from k + 2 on are zero padding for the Gram kernel's tiles.
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> Fs;
    Eigen::VectorXd f0;     // column 0 of Fs, contiguous
    Eigen::MatrixXd As;     // sv×k: svec(F_j), unscaled, same column order (residuals)
    Eigen::MatrixXd G;      // k×k: Gram matrix of the scaled coefficients (upper triangle)
    Eigen::VectorXd a0, ss, zs, rs, bs, ws;  // svec(F0), svec(S), svec(Z), svec(rz), svec(B̃), work
    Eigen::VectorXd xl, gl, f0f;  // x gathered by `var`, products per column, ⟨F̃_j, F̃0⟩
    Eigen::VectorXd lambda, isq, wv, ev;
    double f0sq = 0;        // ‖F̃0‖²
    double e = 1;           // equilibration: the block is solved as e·F_b (equilibrate())
    std::vector<double> cs; // e·d_var per Fs column (scale of the stored coefficient)
    bool il = false;        // V interleaved (n ≤ kernels::kInterleavedMax)
    bool arm = false;       // Schur contribution and sparse Fs columns from the arm form (load_values)
    ArmForm arms;
    int cp = 0;             // columns of Fs (and slots of an interleaved V)
    Eigen::Index vrow(int slot, int r) const;
  };
  // Per-thread partial results of the loops over blocks (for_block_ranges): thread t > 0
  // accumulates into part_[t] what thread 0 accumulates into the solver's own arrays, and the
  // partials are added serially in thread order. Nothing a worker writes in one pass over its
  // blocks is read by the others before the pass ends, and the blocks' own arrays stay with
  // the thread that owns them (the first version, which reduced over the blocks' arrays on
  // the calling thread, spent a fifth of its time moving cache lines between the cores).
  struct Partial {
    Eigen::MatrixXd M;      // Schur complement (threads > 0)
    Eigen::VectorXd v;      // rx or g (threads > 0)
    double hz = 0, sz = 0, rn = 0, amax = 0, hb = 0, f0sq = 0;
    bool ok = true;
  };

  // --- helpers (inline below) ---
  void load_values();
  void equilibrate();
  void least_squares_start();
  void residuals(double alpha = 0.0);
  template <class F>
  void for_block_ranges(F&& f);
  void scatter_schur(const BlockWork& w, Eigen::MatrixXd& M) const;
  void scatter_sub(const BlockWork& w, Eigen::VectorXd& g) const;
  bool scale_block_factor(BlockWork& w);
  bool scale_block_finish(BlockWork& w, bool eig_ok);
  void allocate_partials();
  void assemble_block(int b);
  bool factor_schur();
  void solve_schur(double* b);
  bool scale_and_assemble();
  bool factor_assembled();
  void solve_reduced(const Eigen::VectorXd& g, const Eigen::VectorXd& by, Eigen::VectorXd& dx, Eigen::VectorXd& dy);
  void kkt_block_rhs(BlockWork& w, bool use_F0, double eta_rz, bool with_u);
  void kkt_finish(const Eigen::VectorXd& by, Eigen::VectorXd& dx, Eigen::VectorXd& dy);
  void kkt_solve(const Eigen::VectorXd& bx, const Eigen::VectorXd& by, bool use_F0, double eta_rz,
                 bool with_u, Eigen::VectorXd& dx, Eigen::VectorXd& dy);
  double max_step_scaled(BlockWork& w, const Eigen::MatrixXd& X, double cap);
  double direction(double eta, double sigma, double mu, bool corrector, double cap);
  void record_best(double merit);
  void finish(SolveStatus status);

  // C = QᵀXQ and C = QXQᵀ (X symmetric) on the block's work array T: the kernels' loops for
  // small blocks, Eigen's blocked products above kLargeBlock (no allocation up to Eigen's
  // stack limit for its blocking workspace).
  static constexpr int kLargeBlock = 24;
  static constexpr int kSmallSchur = 64;  // Schur complements up to this size use kernels::cholesky
  static void congruence_t(int n, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& X, Eigen::MatrixXd& T, double* C);
  static void congruence_n(int n, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& X, Eigen::MatrixXd& T, Eigen::MatrixXd& C);

  const LmiProblem* p_;
  SolverOptions opt_;
  std::uint64_t version_ = ~std::uint64_t{0};
  int m_ = 0, pe_ = 0, nu_ = 0;
  std::vector<BlockWork> w_;
  std::vector<Partial> part_;
  size_t used_ = 1;              // partials written by the last for_block_ranges
  double f0sq_ = 0;              // Σ_b ‖F̃0_b‖² (scaling pass)
  bool pending_best_z_ = false;  // record_best() left the copy of Z to the next pass over the blocks
  double best_z_scale_ = 1.0;
  double hz_ = 0;                // hᵀz of the current iterate (residuals())
  MarginChecker margin_;
  // iterate
  Eigen::VectorXd x_, y_;
  double tau_ = 1, kappa_ = 1;
  Eigen::VectorXd c_;   // D c / cscale_ (see solve(), equilibrate())
  double cscale_ = 1;
  std::uint64_t values_loaded_ = ~std::uint64_t{0}, values_structure_ = ~std::uint64_t{0};
  Eigen::VectorXd d_, r_;  // equilibration: x = D x̂ (d_), equality rows scaled by r_
  Eigen::MatrixXd Aeq_;    // R Aeq D
  Eigen::VectorXd beq_;    // R beq
  Eigen::VectorXd xo_, yo_;  // work: iterates in the problem's units
  // residuals
  Eigen::VectorXd rx_, ry_;
  double rtau_ = 0;
  double step_alpha_ = 0;  // step taken by the last iteration, applied to S, Z in residuals()
  double sz_ = 0;          // ⟨S, Z⟩ summed over the blocks (residuals())
  // linear algebra
  Eigen::MatrixXd M_, K_, Lk_, Uk_, KinvAt_, SA_, AtA_;  // Uk_ = Lk_ᵀ
  Eigen::VectorXd Ldinv_;  // 1 / diag(Lk_)
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







// Calls f(t, begin, end) for thread t on contiguous ranges of blocks that together cover all of them: one
// range per thread when opt_.threads > 1 in an OpenMP build, else f(0, number of blocks). f
// must write only the work of its own blocks (and may read shared state).
template <class F>
inline void InteriorPointSolver::for_block_ranges(F&& f) {
  const int nb = static_cast<int>(w_.size());
#if defined(_OPENMP)
  const int nt = std::min(static_cast<int>(part_.size()), nb);
  if (nt > 1) {
#pragma omp parallel num_threads(nt)
    {
      const int t = omp_get_thread_num(), count = omp_get_num_threads();  // count ≤ nt
      if (t == 0) used_ = static_cast<size_t>(count);
      f(t, static_cast<int>(static_cast<long>(nb) * t / count), static_cast<int>(static_cast<long>(nb) * (t + 1) / count));
    }
    return;
  }
#endif
  used_ = 1;
  f(0, 0, nb);
}



















/// Convenience: one solve of a linear-objective problem.
SolveResult solve_linear(const LmiProblem& problem, const SolverOptions& options = {});

}  // namespace setbound::lmi

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/lmi/impl/solver.ipp"
#endif
