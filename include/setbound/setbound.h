/* setbound — C ABI.
 *
 * This header is plain C and is also read as-is by the Python package (cffi ABI mode,
 * ffi.cdef), so it contains only declarations: no include guards, no #include, no
 * #ifdef, no function-like macros. Including it twice is harmless (C11/C++: identical
 * typedefs and macros may be repeated). C++ code includes it inside extern "C" { }.
 *
 * Conventions, used by every function below:
 *   - Every function returns int: SB_OK (0) on success, a negative SB_ERR_* code on
 *     failure. After a failure, sb_last_error() returns a message naming the offending
 *     argument; the message is per thread and stays valid until the next failing call
 *     on that thread.
 *   - Matrices cross as `const double*` in ROW-MAJOR (C) order with their dimensions
 *     given by the arguments and the documentation; vectors are contiguous arrays.
 *   - Output arrays are allocated by the caller with the documented size. Where an
 *     output size is not known in advance, the caller passes its capacity in an in/out
 *     `int*` argument; on SB_ERR_BUFFER_TOO_SMALL it holds the size needed.
 *   - Handles are opaque (typedef struct sb_xxx sb_xxx); every handle type has an
 *     sb_xxx_free(), which accepts NULL. Passing NULL where a handle is required is an
 *     SB_ERR_INVALID_ARGUMENT, never a crash.
 *   - No C++ exception crosses this boundary.
 *   - Intervals are pairs (lo, hi) with lo <= hi; infinite ends are allowed, NaN never.
 *     The empty interval is (+inf, -inf).
 */

/* ---- status codes ------------------------------------------------------------------ */
#define SB_OK 0
#define SB_ERR_INVALID_ARGUMENT -1
#define SB_ERR_DIMENSION -2
#define SB_ERR_NOT_FINITE -3
#define SB_ERR_NOT_SYMMETRIC -4
#define SB_ERR_NOT_POSITIVE_DEFINITE -5
#define SB_ERR_INFEASIBLE -6
#define SB_ERR_NOT_DETECTABLE -7
#define SB_ERR_NUMERICAL -8
#define SB_ERR_BUFFER_TOO_SMALL -9
#define SB_ERR_INTERNAL -10
/* A measurement that no state of the model can produce, under the policy
 * SB_ON_INCONSISTENCY_RAISE; the message names the step and the output. */
#define SB_ERR_INCONSISTENT -11

/* ---- library information ----------------------------------------------------------- */
/* Version string of the library, e.g. "0.1.0". Never NULL. */
const char* sb_version(void);
/* ABI version; the Python package checks it at import and refuses a mismatch. */
int sb_abi_version(void);
/* Message of the last failed call on this thread ("" if none). Never NULL. */
const char* sb_last_error(void);
/* Name of a status code, e.g. "dimension mismatch". Never NULL. */
const char* sb_status_name(int status);

/* ==== intervals, boxes, interval matrices (sets/interval.hpp, box.hpp, interval_matrix.hpp) ==== */
/* Arrays of n intervals cross as two arrays lo[n], hi[n]. Every result contains the exact real
 * result of the set operation, also after floating-point rounding (outward rounding that stays
 * exact when the operation is exact). Input intervals must satisfy lo <= hi (or be the empty
 * encoding (+inf, -inf)); NaN gives SB_ERR_NOT_FINITE, lo > hi SB_ERR_INVALID_ARGUMENT, and an
 * unknown op code SB_ERR_INVALID_ARGUMENT. Outputs may alias inputs of the same size. */
#define SB_IV_ADD 1
#define SB_IV_SUB 2
#define SB_IV_MUL 3
#define SB_IV_DIV 4
#define SB_IV_INTERSECT 5
#define SB_IV_HULL 6
#define SB_IV_NEG 11
#define SB_IV_RECIP 12
#define SB_IV_SQR 13
#define SB_IV_SQRT 14
#define SB_IV_EXP 15
#define SB_IV_SIN 16
#define SB_IV_COS 17
#define SB_IV_ABS 18
/* out_i = a_i (op) b_i for i < n; op is one of SB_IV_ADD..SB_IV_HULL. Division by [0,0] and an
 * empty intersection give the empty encoding. */
int sb_interval_binary(int op, int n, const double* alo, const double* ahi, const double* blo,
                       const double* bhi, double* lo, double* hi);
/* out_i = op(x_i) for i < n; op is one of SB_IV_NEG..SB_IV_ABS. */
int sb_interval_unary(int op, int n, const double* xlo, const double* xhi, double* lo,
                      double* hi);
/* out_i = x_i^p (integer power; p < 0 is the reciprocal of x_i^(-p)). */
int sb_interval_pow(int n, const double* xlo, const double* xhi, int p, double* lo, double* hi);
/* Guaranteed upper bound of the volume prod_i (hi_i - lo_i) of a box (0 when empty). */
int sb_box_volume(int n, const double* lo, const double* hi, double* volume);
/* y = M [x]: M is rows x cols (row-major, finite), [x] has cols components, [y] rows. The
 * result is the interval hull [Mc - |M|r, Mc + |M|r], enclosed under rounding. */
int sb_matrix_mul_box(int rows, int cols, const double* M, const double* xlo, const double* xhi,
                      double* ylo, double* yhi);
/* [y] = [M][x] (Remark 1.2): [M] = [Mlo, Mhi] is rows x cols (row-major). */
int sb_imatrix_mul_box(int rows, int cols, const double* Mlo, const double* Mhi,
                       const double* xlo, const double* xhi, double* ylo, double* yhi);
/* [R] = [M] N for a real N (inner x cols): [M] is rows x inner, [R] rows x cols, row-major. */
int sb_imatrix_mul_matrix(int rows, int inner, int cols, const double* Mlo, const double* Mhi,
                          const double* N, double* Rlo, double* Rhi);
/* vert[M]: the 2^q matrices taking each of the q uncertain entries (lo < hi) at one end.
 * *count is in: capacity of out in matrices, out: 2^q. out holds count * rows * cols doubles,
 * matrix after matrix, each row-major; uncertain entries are numbered in row-major order and
 * entry k is at its upper end in matrix v iff bit k of v is set. q > 20 gives
 * SB_ERR_INVALID_ARGUMENT; a capacity below 2^q gives SB_ERR_BUFFER_TOO_SMALL with *count = 2^q
 * (out may then be NULL). */
int sb_imatrix_vertices(int rows, int cols, const double* lo, const double* hi, int* count,
                        double* out);
/* ||[M]|| = max_i sum_j |[m_ij]| (max row sum of magnitudes), rounded up. */
int sb_imatrix_norm(int rows, int cols, const double* lo, const double* hi, double* norm);
/* ==== end intervals ==== */

/* ==== ellipsoids, zonotopes, strips (sets/ellipsoid.hpp, zonotope.hpp, strip.hpp) ==== */
/* Sets cross the ABI as arrays (no handles). An ellipsoid is (n, P [n x n], c [n], rho):
 * E = { x : (x - c)^T P (x - c) <= rho }, P symmetric positive definite, rho >= 0 a LEVEL
 * (not a squared radius). A zonotope is (n, m, p [n], H [n x m, row-major]):
 * Z = { p + H z : z in [-1, 1]^m }; m may be 0 (H may then be NULL). A strip is
 * (c [n], y, phi): S = { x : |c^T x - y| <= phi }. Point and direction batches are
 * row-major npoints x n arrays. n >= 1 everywhere. */

/* Zonotope reduction methods for sb_zonotope_reduce. */
#define SB_REDUCE_COMBASTEL 1
#define SB_REDUCE_GIRARD 2
#define SB_REDUCE_PCA 3

/* Validates an ellipsoid (P SPD, c finite, rho >= 0 finite); SB_OK if valid. */
int sb_ellipsoid_validate(int n, const double* P, const double* c, double rho);
/* Interval hull c_i -/+ sqrt(rho (P^-1)_ii) (rounded outward); lo, hi: n. */
int sb_ellipsoid_bounding_box(int n, const double* P, const double* c, double rho, double* lo,
                              double* hi);
/* Volume V_n rho^(n/2) / sqrt(det P) and its natural log (log_volume may be NULL). */
int sb_ellipsoid_volume(int n, const double* P, const double* c, double rho, double* volume,
                        double* log_volume);
/* inside[k] = 1 if (x_k - c)^T P (x_k - c) <= rho (1 + rel_tol), else 0; points: npoints x n. */
int sb_ellipsoid_contains(int n, const double* P, const double* c, double rho, int npoints,
                          const double* points, double rel_tol, int* inside);
/* values[k] = max_{x in E} a_k^T x = a_k^T c + sqrt(rho a_k^T P^-1 a_k); directions: ndir x n. */
int sb_ellipsoid_support(int n, const double* P, const double* c, double rho, int ndir,
                         const double* directions, double* values);
/* Image of E under x -> M x + b (M n x n invertible): P_out = M^-T P M^-1 (n x n),
 * c_out = M c + b (n), rho_out = rho. */
int sb_ellipsoid_affine_map(int n, const double* P, const double* c, double rho, const double* M,
                            const double* b, double* P_out, double* c_out, double* rho_out);
/* Smallest level rho_out with E(P, c, rho) inside E(P_new, c, rho_out), rounded up and
 * certified: rho * lambda_max(P^-1/2 P_new P^-1/2) * (1 + delta), delta ~ 16 n eps. */
int sb_ellipsoid_level_for_shape(int n, const double* P, const double* c, double rho,
                                 const double* P_new, double* rho_out);

/* Validates a zonotope (p, H finite); SB_OK if valid. */
int sb_zonotope_validate(int n, int m, const double* p, const double* H);
/* Interval hull p_i -/+ sum_j |H_ij| (rounded outward); lo, hi: n. */
int sb_zonotope_interval_hull(int n, int m, const double* p, const double* H, double* lo,
                              double* hi);
/* Exact volume 2^n sum_S |det H_S|; SB_ERR_INVALID_ARGUMENT if C(m, n) > 5e6. */
int sb_zonotope_volume(int n, int m, const double* p, const double* H, double* volume);
/* Exact P-radius max_{s in {-1,1}^m} s^T H^T P H s (P n x n SPD); refused for m > 24.
 * vertex (m entries of +-1, may be NULL) receives a maximising sign vector. */
int sb_zonotope_pradius(int n, int m, const double* p, const double* H, const double* P,
                        double* radius, double* vertex);
/* values[k] = d_k^T p + ||H^T d_k||_1; directions: ndir x n. */
int sb_zonotope_support(int n, int m, const double* p, const double* H, int ndir,
                        const double* directions, double* values);
/* Exact membership (up to rel_tol) of each point; refused if C(m, rank-1) > 5e6. */
int sb_zonotope_contains(int n, int m, const double* p, const double* H, int npoints,
                         const double* points, double rel_tol, int* inside);
/* Order reduction to at most `limit` (>= n) generators; method SB_REDUCE_COMBASTEL (keep
 * the limit-n longest columns, box the rest), SB_REDUCE_GIRARD (keep the limit-n largest
 * ||g||_1 - ||g||_inf, box the rest) or SB_REDUCE_PCA (CORA's 'pca': Girard's choice, the rest
 * boxed in the eigenbasis of its Gram matrix). The centre is unchanged; zero columns are
 * dropped. The result has at most min(m, limit) generators. *m_out: in = capacity of H_out in columns (H_out holds
 * n * capacity doubles), out = the number of generators written; H_out then starts with
 * the compact n x (*m_out) row-major generator matrix. SB_ERR_BUFFER_TOO_SMALL sets
 * *m_out to the count needed. */
int sb_zonotope_reduce(int n, int m, const double* p, const double* H, int method, int limit,
                       int* m_out, double* H_out);
/* Zonotope/strip family ([Le2013] Property 6): Z intersected with {|c^T x - y| <= phi}
 * is contained in p_out + H_out B^(m+1), p_out = p + lambda (y - c^T p) (n),
 * H_out = [(I - lambda c^T) H, phi lambda] (n x (m+1)). c, lambda: n. */
int sb_zonotope_intersect_strip(int n, int m, const double* p, const double* H, const double* c,
                                double y, double phi, const double* lambda, double* p_out,
                                double* H_out);
/* Interval-matrix image: for every A in [mid - rad, mid + rad] (k x n, rad >= 0),
 * A Z is contained in p_out + H_out B^(m+2k) with p_out = mid p (k) and
 * H_out = [mid H, rs(rad |H|), diag(rad |p|)] (k x (m + 2k)). */
int sb_zonotope_interval_linear_map(int k, int n, int m, const double* mid, const double* rad,
                                    const double* p, const double* H, double* p_out,
                                    double* H_out);

/* inside[k] = 1 if |c^T x_k - y| <= phi (up to rel_tol), else 0; points: npoints x n. */
int sb_strip_contains(int n, const double* c, double y, double phi, int npoints,
                      const double* points, double rel_tol, int* inside);
/* ==== end ellipsoids, zonotopes, strips ==== */

/* ==== LMI solver (lmi/) ==== */
/* Problem form (lmi/problem.hpp): minimise c^T x subject to, for every block b,
 *   F_b0 + sum_i x_i F_bi >= 0 (positive semidefinite; 1x1 blocks are linear inequalities),
 *   optional Aeq x = beq, optional objective term -log det(G0 + sum_i x_i G_i) (maxdet).
 * Block data: F0 is n x n, Fs is num_vars x n x n (row-major, Fs[i] = F_bi), all symmetric
 * and finite. The structure is analysed when a block is added; sb_lmi_update_block only
 * replaces values (no re-analysis unless a new variable starts touching the block). */
typedef struct sb_lmi_problem sb_lmi_problem;

/* Solve statuses (sb_lmi_result.status). */
#define SB_LMI_OPTIMAL 0
#define SB_LMI_INFEASIBLE 1
#define SB_LMI_UNBOUNDED 2
#define SB_LMI_MAX_ITERATIONS 3
#define SB_LMI_NUMERICAL_ERROR 4
#define SB_LMI_INACCURATE 5

/* Problem classes for sb_lmi_solve_class. */
#define SB_LMI_CLASS_AUTO 0
#define SB_LMI_CLASS_FEASIBILITY 1

typedef struct sb_lmi_result {
  int status;              /* SB_LMI_* */
  int iterations;          /* interior-point (or Newton) iterations */
  double objective;        /* c^T x (minus log det G(x) for maxdet) */
  double dual_objective;
  double margin;           /* verified: Cholesky of F_b(x) - margin*I succeeded for all b */
  double solve_time;       /* seconds, measured in C++ */
  double gap;              /* duality gap (s^T z, or nu/t for maxdet) */
  double relative_gap;
  double primal_residual;
  double dual_residual;
} sb_lmi_result;

/* num_vars in 1 .. SB_LMI_MAX_VARS (a solve forms the dense num_vars x num_vars Schur
 * complement: 32 GiB at the bound); a larger count is SB_ERR_DIMENSION. */
#define SB_LMI_MAX_VARS 65536
int sb_lmi_problem_create(int num_vars, sb_lmi_problem** out);
/* Accepts NULL. */
int sb_lmi_problem_free(sb_lmi_problem* problem);
/* c: num_vars entries. */
int sb_lmi_set_objective(sb_lmi_problem* problem, const double* c);
/* Adds the block F0 + sum_i x_i Fs[i] >= 0 of size n; *block_index (may be NULL) gets its index. */
int sb_lmi_add_block(sb_lmi_problem* problem, int n, const double* F0, const double* Fs, int* block_index);
/* Replaces the values of block `block` (same size n). */
int sb_lmi_update_block(sb_lmi_problem* problem, int block, int n, const double* F0, const double* Fs);
/* Objective term -log det(G0 + sum_i x_i Gs[i]) (n x n); n = 0 removes it. */
int sb_lmi_set_logdet(sb_lmi_problem* problem, int n, const double* G0, const double* Gs);
/* Aeq: rows x num_vars, beq: rows; rows = 0 removes the equalities. */
int sb_lmi_set_equalities(sb_lmi_problem* problem, int rows, const double* Aeq, const double* beq);
/* Solver options; a value <= 0 keeps the default (max_iterations 100, gap_rel 1e-7,
 * feas 1e-8, time_limit 30 s). */
int sb_lmi_set_options(sb_lmi_problem* problem, int max_iterations, double gap_rel, double feas, double time_limit);
/* Threads over the LMI blocks inside each solve (1 ... 256; default 1 = serial; kept by
 * sb_lmi_set_options). Pays off from a few dozen blocks; results agree with the serial
 * solve to rounding. Without OpenMP in the build (sb_lmi_threads_available() == 0) the
 * solve runs serially whatever is set. */
int sb_lmi_set_threads(sb_lmi_problem* problem, int threads);
int sb_lmi_threads_available(void);
int sb_lmi_problem_size(const sb_lmi_problem* problem, int* num_vars, int* num_blocks);
/* Solves (maxdet when a log-det term is set, linear objective otherwise); x: num_vars
 * entries (may be NULL). For SB_LMI_INFEASIBLE x is NaN and sb_lmi_dual returns the
 * certificate Z (Z_b >= 0, sum_b tr(F_b0 Z_b) + beq^T y = -1, tr(F_bi Z) = (Aeq^T y)_i). */
int sb_lmi_solve(sb_lmi_problem* problem, sb_lmi_result* result, double* x);
/* Like sb_lmi_solve with a problem class: SB_LMI_CLASS_FEASIBILITY stops at the first
 * strictly feasible point (status OPTIMAL means "certified feasible", margin > 0). */
int sb_lmi_solve_class(sb_lmi_problem* problem, int problem_class, sb_lmi_result* result, double* x);
/* Dual matrix (or infeasibility certificate) of block `block` from the last solve, n x n. */
int sb_lmi_dual(const sb_lmi_problem* problem, int block, double* Z);
/* Equality multipliers (or certificate part) from the last solve, `rows` entries. */
int sb_lmi_dual_eq(const sb_lmi_problem* problem, double* y);
/* Verified margin of a given point x (num_vars entries). */
int sb_lmi_margin(const sb_lmi_problem* problem, const double* x, double* margin);
/* Generalised eigenvalue problem: minimise lambda s.t. lambda*B(x) - A(x) >= 0, B(x) > 0 and
 * the problem's blocks; A0, B0 n x n, As, Bs num_vars x n x n. [lambda_lo, lambda_hi] is
 * an initial bracket guess (expanded as needed), tol the relative bracket width. */
int sb_lmi_solve_gevp(sb_lmi_problem* problem, int n, const double* A0, const double* As, const double* B0,
                      const double* Bs, double lambda_lo, double lambda_hi, double tol,
                      sb_lmi_result* result, double* lambda, double* x);
/* ==== end LMI solver ==== */

/* ==== models (core/linear_system.hpp) ==== */
/* x+ = A x + B u + E w,  y = C x + D u + F w,  w in [-1, 1]^nw  (papers.md §0.3).
 * A: nx x nx, C: ny x nx, E: nx x nw, F: ny x nw, B: nx x nu and D: ny x nu (both may be NULL:
 * B = NULL needs nu = 0, D = NULL means D = 0). A_rad (nx x nx, entries >= 0, may be NULL)
 * makes A uncertain: A in [A - A_rad, A + A_rad], with A the midpoint. */
typedef struct sb_linear_system sb_linear_system;
int sb_linear_system_create(int nx, int ny, int nu, int nw, const double* A, const double* B,
                            const double* C, const double* D, const double* E, const double* F,
                            const double* A_rad, sb_linear_system** out);
int sb_linear_system_free(sb_linear_system* system);
int sb_linear_system_dims(const sb_linear_system* system, int* nx, int* ny, int* nu, int* nw);
/* PBH test of (C, A). *detectable = 1 or 0; when 0, (mode_re, mode_im) is an eigenvalue with
 * |lambda| >= 1 that C does not see (the pointers may be NULL). */
int sb_check_detectability(int nx, int ny, const double* A, const double* C, int* detectable,
                           double* mode_re, double* mode_im);
/* ==== end models ==== */

/* ==== zonotopic estimators (estimators/zonotopic/gain_estimator.hpp) ==== */
/* The estimator structure of papers.md §3.1: prediction, strip-by-strip correction with a gain
 * rule, reduction to at most max_generators generators. Time indexing: step k takes y_k and
 * u_k and returns the set for x_k (after using y_k), then predicts x_{k+1} with u_k. */
typedef struct sb_zonotopic sb_zonotopic;
/* Gain rules: segment minimisation ([Alamo2005], papers.md §5.1), or fixed gains lambda_i
 * given as the rows of `lambdas` (ny x nx), e.g. a P-radius design. */
#define SB_ZONO_GAIN_SEGMENT_MIN 1
#define SB_ZONO_GAIN_FIXED 2
/* [Alamo2005] volume minimisation (papers.md §5.2): an LP per strip on the bundled solver. */
#define SB_ZONO_GAIN_VOLUME_MIN 3
/* x0 = p0 + H0 [-1,1]^m0 (H0 nx x m0, row-major). strip_order: NULL or a permutation of
 * 0..ny-1. use_first_measurement = 0 returns X0 unchanged at step 0 ([Le2013]). lambdas: NULL
 * unless gain = SB_ZONO_GAIN_FIXED. max_generators in nx .. SB_ZONO_MAX_GENERATORS (work
 * matrices of nx x max_generators are allocated up front). */
#define SB_ZONO_MAX_GENERATORS 100000
int sb_zonotopic_create(const sb_linear_system* system, int gain, const double* lambdas,
                        int max_generators, int use_first_measurement, const int* strip_order,
                        int m0, const double* p0, const double* H0, sb_zonotopic** out);
/* P-radius gain design ([Le2013], papers.md §3.2 approach 1 / §3.3 approach 2), beta chosen
 * in (beta_lo, beta_hi) by a scalar search maximising tau. strip_order: NULL (0..ny-1) or a
 * permutation; try_all_orders = 1 (approach 2) keeps the best of the ny! orders. Outputs:
 * lambdas (ny x nx, row i = lambda_i), P (ny x nx x nx, P of output i), beta and tau (ny),
 * psi, order_out (ny, the order used; may be NULL). Infeasible designs give
 * SB_ERR_INFEASIBLE with a message naming the output. */
int sb_pradius_design(const sb_linear_system* system, int approach, const int* strip_order,
                      int try_all_orders, double beta_lo, double beta_hi, double* lambdas,
                      double* P, double* beta, double* tau, double* psi, int* order_out);
int sb_zonotopic_free(sb_zonotopic* estimator);
/* One step: y (ny), u (nu; NULL when nu = 0). A NaN entry of y is a missing output (not
 * used); every present output is first tested against the predicted output set and a reading
 * outside it is handled by the inconsistency policy (SB_ON_INCONSISTENCY_*; see
 * sb_zonotopic_last_check). Writes the centre, the interval hull (lower, upper, nx each) and
 * the number of generators *m of the set for x_k; its generators are then read with
 * sb_zonotopic_last_set. On error the estimator is unchanged. */
int sb_zonotopic_step(sb_zonotopic* estimator, const double* y, const double* u, double* center,
                      double* lower, double* upper, int* m);
/* The set returned by the last step: p (nx) and H (nx x m, row-major); *m in: capacity in
 * columns, out: the number of generators. */
int sb_zonotopic_last_set(const sb_zonotopic* estimator, int* m, double* p, double* H);
/* Order reduction of the estimator (from its next step on): SB_ZONO_REDUCE_COMBASTEL (the
 * default, papers.md §0.1), SB_ZONO_REDUCE_GIRARD (CORA's default) or SB_ZONO_REDUCE_PCA
 * (CORA's 'pca', used by its observer examples). At most max_generators generators are kept;
 * the pending rounding box (~1e-15 relative) is not counted and is absorbed by the reduction,
 * so before the first reduction a set may carry up to nx extra axis-aligned generators. */
#define SB_ZONO_REDUCE_COMBASTEL 1
#define SB_ZONO_REDUCE_GIRARD 2
#define SB_ZONO_REDUCE_PCA 3
int sb_zonotopic_set_reduction(sb_zonotopic* estimator, int method);
/* Missing and impossible readings (estimators/measurement_check.hpp). A reading outside the
 * output set the estimator predicts (c_i' X + D_i u +- phi_i) cannot come from any state of the
 * model: the estimator never uses it, and under
 *   SB_ON_INCONSISTENCY_FLAG  (the default) skips it, uses the other outputs, marks the step;
 *   SB_ON_INCONSISTENCY_RAISE returns SB_ERR_INCONSISTENT naming the step and the output (the
 *                             estimator is unchanged);
 *   SB_ON_INCONSISTENCY_RESET restarts from the reset set (p, H: nx and nx x m row-major; p NULL:
 *                             the initial set) and corrects it with the outputs consistent with it.
 * The test accounts for rounding: a consistent reading is never declared inconsistent. */
#define SB_ON_INCONSISTENCY_FLAG 0
#define SB_ON_INCONSISTENCY_RAISE 1
#define SB_ON_INCONSISTENCY_RESET 2
int sb_zonotopic_set_inconsistency_policy(sb_zonotopic* estimator, int policy, int m, const double* p,
                                          const double* H);
/* What the last step did with each output: status (ny) one of SB_OUTPUT_*; margin (ny) the
 * distance of the reading from the predicted output set in units of the output's noise bound
 * (absolute when it has none), > 0 outside, <= 0 inside, NaN when missing or not tested; *reset
 * = 1 when the step restarted from the reset set (the statuses and margins are then those of
 * the test that triggered it). NULL outputs are skipped. */
#define SB_OUTPUT_USED 0
#define SB_OUTPUT_MISSING 1
#define SB_OUTPUT_INCONSISTENT 2
#define SB_OUTPUT_UNUSED 3
int sb_zonotopic_last_check(const sb_zonotopic* estimator, int* status, double* margin, int* reset);
/* Back to the state of construction (prior = initial set, no step taken); options kept. */
int sb_zonotopic_reset(sb_zonotopic* estimator);
/* The number of steps taken (a filter: the last step's set bounds x_{steps-1}). */
int sb_zonotopic_steps(const sb_zonotopic* estimator, int* steps);
/* The exact reference: interval hull of the exact consistent state set at each step (2 nx
 * LPs per step over x0 = p0 + H0 xi and all disturbances; known A only). Y: N x ny, U: N x nu
 * (NULL when nu = 0); lower, upper: N x nx. Row k uses y_0..y_k (y_1..y_k when
 * use_first_measurement = 0); NaN entries of Y are missing outputs (no constraint).
 * Inconsistent data give SB_ERR_INFEASIBLE. */
int sb_exact_hull(const sb_linear_system* system, int m0, const double* p0, const double* H0,
                  int N, const double* Y, const double* U, int use_first_measurement,
                  double* lower, double* upper);
/* Saved state of the estimator (see "saved states" at the end of this header). */
int sb_zonotopic_state_size(const sb_zonotopic* estimator, int* n);
int sb_zonotopic_save_state(const sb_zonotopic* estimator, double* state, int n);
int sb_zonotopic_restore_state(sb_zonotopic* estimator, const double* state, int n);
/* ==== end zonotopic estimators ==== */

/* ==== constrained zonotopes (sets/constrained_zonotope.hpp, sets/polygon_projection.hpp) ====
 * Scott et al., Automatica 69 (2016). A constrained zonotope crosses the ABI as arrays
 * (n, ng, nc, c [n], G [n x ng], A [nc x ng], b [nc], r [n]), all row-major:
 *   Z = { c + G xi + diag(r) eta : A xi = b, ||xi||_inf <= 1, ||eta||_inf <= 1 }.
 * r >= 0 is the rounding box that keeps every operation an outer bound after floating-point
 * rounding (a few ulps of the set's size); it may be NULL on input (zero) and is always written
 * on output. ng and nc may be 0 (their arrays may then be NULL). n >= 1.
 * Functions that return a set take `int* ng_out, int* nc_out`: in, the capacity of G_out /
 * A_out in columns and of A_out / b_out in rows; out, the result's sizes (a buffer too small
 * gives SB_ERR_BUFFER_TOO_SMALL with the needed sizes written). G_out is written n x ng_out and
 * A_out nc_out x ng_out, contiguous. Queries are certified: the hull contains the exact hull,
 * "empty" and "not a member" are reported only with a verified certificate. */
int sb_czono_validate(int n, int ng, int nc, const double* c, const double* G, const double* A,
                      const double* b, const double* r);
/* Interval hull (2n LPs on one warm-started basis): lo, hi (n). *empty = 1 when Z is certified
 * empty (lo = +inf, hi = -inf then). */
int sb_czono_interval_hull(int n, int ng, int nc, const double* c, const double* G, const double* A,
                           const double* b, const double* r, double* lo, double* hi, int* empty);
/* values[k] >= max_{x in Z} d_k^T x (certified; -inf when Z is certified empty); directions: ndir x n. */
int sb_czono_support(int n, int ng, int nc, const double* c, const double* G, const double* A,
                     const double* b, const double* r, int ndir, const double* directions, double* values);
/* inside[k] = 0 only when x_k is certified outside Z (points: npoints x n). */
int sb_czono_contains(int n, int ng, int nc, const double* c, const double* G, const double* A,
                      const double* b, const double* r, int npoints, const double* points, int* inside);
/* Emptiness: *empty = 1 only with a verified certificate y (nc; may be NULL) with
 * y^T b - ||A^T y||_1 >= *margin > 0; *conclusive = 0 when the LP could decide neither way
 * (treated as not empty). */
int sb_czono_emptiness(int n, int ng, int nc, const double* c, const double* G, const double* A,
                       const double* b, const double* r, int* empty, int* conclusive, double* certificate,
                       double* margin);
/* K Z (K: k x n): c_out (k), G_out (k x ng), r_out (k); the constraints are unchanged. */
int sb_czono_linear_map(int n, int ng, int nc, const double* c, const double* G, const double* A,
                        const double* b, const double* r, int k, const double* K, double* c_out,
                        double* G_out, double* r_out);
/* Z1 + Z2 (both in R^n): ng1 + ng2 generators, nc1 + nc2 constraints. A zonotope is a
 * constrained zonotope with nc = 0. */
int sb_czono_minkowski_sum(int n, int ng1, int nc1, const double* c1, const double* G1, const double* A1,
                           const double* b1, const double* r1, int ng2, int nc2, const double* c2,
                           const double* G2, const double* A2, const double* b2, const double* r2,
                           int* ng_out, int* nc_out, double* c_out, double* G_out, double* A_out,
                           double* b_out, double* r_out);
/* Generalized intersection Z1 cap_R Z2 = { x in Z1 : R x in Z2 } (Scott 2016 eq. 13), Z2 in R^k,
 * R: k x n (NULL: the identity, k = n). ng1 + ng2 generators, nc1 + nc2 + k constraints. Exact
 * intersection with the output set: Z2 = y - V, R = C. */
int sb_czono_intersect(int n, int ng1, int nc1, const double* c1, const double* G1, const double* A1,
                       const double* b1, const double* r1, int k, int ng2, int nc2, const double* c2,
                       const double* G2, const double* A2, const double* b2, const double* r2,
                       const double* R, int* ng_out, int* nc_out, double* c_out, double* G_out,
                       double* A_out, double* b_out, double* r_out);
/* Z cap { x : |h^T x - y| <= sigma } (sigma >= 0): one generator and one constraint more. */
int sb_czono_intersect_strip(int n, int ng, int nc, const double* c, const double* G, const double* A,
                             const double* b, const double* r, const double* h, double y, double sigma,
                             int* ng_out, int* nc_out, double* c_out, double* G_out, double* A_out,
                             double* b_out, double* r_out);
/* Z cap { x : h^T x <= d }: one generator and one constraint more. */
int sb_czono_intersect_halfspace(int n, int ng, int nc, const double* c, const double* G, const double* A,
                                 const double* b, const double* r, const double* h, double d, int* ng_out,
                                 int* nc_out, double* c_out, double* G_out, double* A_out, double* b_out,
                                 double* r_out);
/* Reductions (each result contains Z):
 *   SB_CZONO_REDUCE_CORA         CORA's conZonotope/reduce: the lift [c; -b] + [G; A] B reduced with
 *                                `technique` (SB_REDUCE_GIRARD or SB_REDUCE_PCA) to order n + nc
 *                                generators (order >= 1);
 *   SB_CZONO_REDUCE_LIMITS       Scott's constraint elimination to max_constraints rows, then the
 *                                lift reduction to max_generators (>= n + max_constraints) columns;
 *   SB_CZONO_REMOVE_ZERO         zero constraint rows removed (exact);
 *   SB_CZONO_ELIMINATE           Scott's rescaling and elimination to max_constraints rows;
 *   SB_CZONO_RESCALE             Scott's rescaling (interval bounds of xi) without elimination.
 * Unused numeric arguments are ignored. The result is never larger than Z (ng_out <= ng,
 * nc_out <= nc). */
#define SB_CZONO_REDUCE_CORA 1
#define SB_CZONO_REDUCE_LIMITS 2
#define SB_CZONO_REMOVE_ZERO 3
#define SB_CZONO_ELIMINATE 4
#define SB_CZONO_RESCALE 5
int sb_czono_reduce(int n, int ng, int nc, const double* c, const double* G, const double* A, const double* b,
                    const double* r, int method, int technique, double order, int max_generators,
                    int max_constraints, int* ng_out, int* nc_out, double* c_out, double* G_out, double* A_out,
                    double* b_out, double* r_out);
/* The projection of Z onto coordinates (i, j) as a convex polygon (for plots): its vertices in
 * counter-clockwise order, vertices (nv x 2, row-major); *nv in: capacity in vertices, out: the
 * count (0 when Z is certified empty; 1 or 2 for a point or a segment). Found by support points
 * until every edge is a facet (relative tolerance 1e-9 of the set's size): exact up to the LP's
 * rounding, not certified (use the hull or the support function for guarantees). */
int sb_czono_projection_polygon(int n, int ng, int nc, const double* c, const double* G, const double* A,
                                const double* b, const double* r, int i, int j, int* nv, double* vertices);

/* The constrained-zonotope estimators CZN-A and CZN-B (estimators/constrained_zonotopic/estimator.hpp):
 * prediction X+ = A X + B u + E B^nw (exact); correction by the exact intersection with the output
 * set y - D u - F B^nw (SB_CZN_EXACT_OUTPUT, CORA's CZN-A) or by the output strips in the Wang
 * gain's representation (SB_CZN_WANG_STRIPS, CZN-B: the same set, another representation);
 * reduction: none (the exact consistent set; memory grows every step), CORA's (SB_CZN_REDUCE_CORA
 * at `order`, CORA's zonotopeOrder) or setbound's bounded mode (SB_CZN_REDUCE_LIMITS, the default
 * of the Python layer: at most max_constraints rows and max_generators generators; -1 for 4 nx
 * and 20 nx + max_constraints). technique: SB_REDUCE_GIRARD or SB_REDUCE_PCA. Time indexing as
 * sb_zonotopic (a filter). The system must have a known A. */
typedef struct sb_czonotopic sb_czonotopic;
#define SB_CZN_EXACT_OUTPUT 0
#define SB_CZN_WANG_STRIPS 1
#define SB_CZN_REDUCE_NONE 0
#define SB_CZN_REDUCE_CORA 1
#define SB_CZN_REDUCE_LIMITS 2
/* The largest max_constraints / max_generators accepted (LPs of that size are allocated per step). */
#define SB_CZN_MAX_SIZE 100000
int sb_czonotopic_create(const sb_linear_system* system, int correction, int reduction, int technique,
                         double order, int max_constraints, int max_generators, int use_first_measurement,
                         int ng0, int nc0, const double* c0, const double* G0, const double* A0,
                         const double* b0, const double* r0, sb_czonotopic** out);
int sb_czonotopic_free(sb_czonotopic* estimator);
/* The effective limits (after the -1 defaults) and options. Any output may be NULL. */
int sb_czonotopic_options(const sb_czonotopic* estimator, int* correction, int* reduction, int* technique,
                          double* order, int* max_constraints, int* max_generators);
/* One step: y (ny; NaN = missing), u (nu; NULL when nu = 0). Writes the certified interval hull
 * (lower, upper: nx) and the sizes of the set for x_k (ng, nc; may be NULL), read with
 * sb_czonotopic_last_set. Screening and policies as sb_zonotopic; readings that are each
 * possible but jointly impossible flag every used output (margin NaN). On error the estimator
 * is unchanged. */
int sb_czonotopic_step(sb_czonotopic* estimator, const double* y, const double* u, double* lower,
                       double* upper, int* ng, int* nc);
/* The set of the last step; *ng_out, *nc_out in: capacities, out: sizes (see above). */
int sb_czonotopic_last_set(const sb_czonotopic* estimator, int* ng_out, int* nc_out, double* c,
                           double* G, double* A, double* b, double* r);
/* The set the next step corrects: after k steps the prediction A X + B u (+) E B^nw for x_k
 * (before y_k), before the first step the initial set. Buffers as sb_czonotopic_last_set. */
int sb_czonotopic_prediction(const sb_czonotopic* estimator, int* ng_out, int* nc_out, double* c,
                             double* G, double* A, double* b, double* r);
/* As sb_zonotopic_set_inconsistency_policy; the reset set is a constrained zonotope (c NULL:
 * the initial set). */
int sb_czonotopic_set_inconsistency_policy(sb_czonotopic* estimator, int policy, int ng, int nc,
                                           const double* c, const double* G, const double* A,
                                           const double* b, const double* r);
int sb_czonotopic_last_check(const sb_czonotopic* estimator, int* status, double* margin, int* reset);
int sb_czonotopic_reset(sb_czonotopic* estimator);
int sb_czonotopic_steps(const sb_czonotopic* estimator, int* steps);
/* Saved state (see "saved states" at the end of this header). */
int sb_czonotopic_state_size(const sb_czonotopic* estimator, int* n);
int sb_czonotopic_save_state(const sb_czonotopic* estimator, double* state, int n);
int sb_czonotopic_restore_state(sb_czonotopic* estimator, const double* state, int n);
/* ==== end constrained zonotopes ==== */

/* ==== ellipsoidal estimators (estimators/ellipsoidal/lmi_estimators.hpp, improved_correction.hpp,
 *      descriptor.hpp, estimators/point/kalman.hpp) ==== */
/* Sets are E(P, c, rho) = {x : (x - c)^T P (x - c) <= rho} (papers.md §0.1). */
typedef struct sb_ell_design sb_ell_design;
typedef struct sb_descriptor_system sb_descriptor_system;
typedef struct sb_ellipsoidal sb_ellipsoidal;
typedef struct sb_kalman sb_kalman;
/* Normalisation of the offline LMI (papers.md §1.1): log det P >= 0 (minimum steady-state
 * volume, the default), P >= I, or the printed tr P <= 1 (degenerate; reproduction only). */
#define SB_ELL_NORM_LOGDET 0
#define SB_ELL_NORM_BALL 1
#define SB_ELL_NORM_PAPER_TRACE 2
/* Offline design (papers.md §1.1, robust over vert[A] when A is uncertain). beta: a fixed
 * value in (0, 1), or NaN to choose it by a scalar search on the criterion. Undetectable
 * (C, A) gives SB_ERR_NOT_DETECTABLE, an infeasible design SB_ERR_INFEASIBLE. */
int sb_ell_design_offline(const sb_linear_system* system, int normalization, double beta,
                          sb_ell_design** out);
/* E x+ = A x + B u + D w,  y = C x + F w,  w in [-1, 1]^nw  (papers.md §4). E, A: nx x nx,
 * C: ny x nx, D: nx x nw, F: ny x nw, B: nx x nu (NULL when nu = 0). The rank conditions
 * are checked; a failure names the condition. */
int sb_descriptor_system_create(int nx, int ny, int nu, int nw, const double* E, const double* A,
                                const double* B, const double* C, const double* D, const double* F,
                                sb_descriptor_system** out);
int sb_descriptor_system_free(sb_descriptor_system* system);
/* T (nx x nx) and N (nx x ny) with T E + N C = I, [T N] = pinv([E; C]). */
int sb_descriptor_system_tn(const sb_descriptor_system* system, double* T, double* N);
/* Offline design for a descriptor system (papers.md §4.1): w_k and w_{k+1} independent. */
int sb_ell_design_descriptor(const sb_descriptor_system* system, int normalization, double beta,
                             sb_ell_design** out);
int sb_ell_design_free(sb_ell_design* design);
int sb_ell_design_dims(const sb_ell_design* design, int* nx, int* ny);
/* P (nx x nx), L (nx x ny), scalars[4] = {beta, sigma, rho_inf, volume_inf}, *vertex_blocks
 * and *normalization; any output pointer may be NULL. */
int sb_ell_design_get(const sb_ell_design* design, double* P, double* L, double* scalars,
                      int* vertex_blocks, int* normalization);

/* Estimators. Predictors (OFFLINE, ONLINE_VERTEX, ONLINE_SCALED) are one-step predictors:
 * step k takes y_k, u_k and returns the set for x_{k+1}. Filters (IMPROVED, DESCRIPTOR)
 * return the set for x_k after using y_k. sb_ellipsoidal_info tells which. */
#define SB_ELL_OFFLINE 0
#define SB_ELL_ONLINE_VERTEX 1
#define SB_ELL_ONLINE_SCALED 2
#define SB_ELL_IMPROVED 3
#define SB_ELL_DESCRIPTOR 4
/* Improved correction: normalisation of the corrected set (papers.md §6.5). */
#define SB_ELL_CORR_FIXED_SHAPE 0
#define SB_ELL_CORR_DET_NORMALIZED 1
#define SB_ELL_CORR_BALL_NORMALIZED 2
/* What the improved estimator feeds back to the prediction (papers.md §6.6): (i) nothing (the
 * corrected set is only reported, intersected with the prediction), (ii) the P-shaped outer
 * bound of the corrected set when its level is below the prediction's, (iii) the fixed-shape
 * correction (option A) solved in addition, or (ii) when smaller (recommended). */
#define SB_ELL_FEEDBACK_NONE 0
#define SB_ELL_FEEDBACK_OUTER_BOUND 1
#define SB_ELL_FEEDBACK_FIXED_SHAPE 2
/* Initial set x0 = E(P0, c0, rho0) (converted to the design's shape). For IMPROVED, `option`
 * is an SB_ELL_CORR_*, `feedback` an SB_ELL_FEEDBACK_* and `predictor` the prediction method
 * (SB_ELL_ONLINE_VERTEX, SB_ELL_ONLINE_SCALED or SB_ELL_OFFLINE); they are ignored otherwise.
 * DESCRIPTOR needs the descriptor system (NULL otherwise) and a design made by
 * sb_ell_design_descriptor. */
int sb_ellipsoidal_create(const sb_ell_design* design, int method, int option, int feedback, int predictor,
                          const sb_descriptor_system* descriptor, const double* P0, const double* c0,
                          double rho0, sb_ellipsoidal** out);
int sb_ellipsoidal_free(sb_ellipsoidal* estimator);
/* *is_filter = 1 for IMPROVED and DESCRIPTOR; *steps = steps taken; *nx, *ny, *nu. */
int sb_ellipsoidal_info(const sb_ellipsoidal* estimator, int* is_filter, int* steps, int* nx, int* ny,
                        int* nu);
/* The estimator's current set (predictors: the set for x_k before y_k is used, k = steps
 * taken; filters: the set returned by the last step). P (nx x nx), c (nx), rho; lower and
 * upper (nx) are the guaranteed interval bounds reported for it (for IMPROVED the
 * intersection of the hulls of the corrected and the predicted sets). NULL outputs are
 * skipped. */
int sb_ellipsoidal_current(const sb_ellipsoidal* estimator, double* P, double* c, double* rho,
                           double* lower, double* upper);
/* One step with y (ny) and u (nu; NULL when nu = 0); writes the new current set as above.
 * A NaN entry of y is a missing output (DESCRIPTOR: an error, its state is fixed through every
 * output); readings outside the predicted output set follow the inconsistency policy below. On
 * error (wrong data, +-inf) the estimator is unchanged. */
int sb_ellipsoidal_step(sb_ellipsoidal* estimator, const double* y, const double* u, double* P,
                        double* c, double* rho, double* lower, double* upper);
/* Per-step diagnostics of the last step: beta and gain L (nx x ny) of the prediction (the
 * design's for OFFLINE and DESCRIPTOR), and *fallback = 1 when the online LMI could not be
 * solved and certified and the design's certified values were used instead. */
int sb_ellipsoidal_last_step(const sb_ellipsoidal* estimator, double* beta, double* L, int* fallback);
/* Online predictors (ONLINE_VERTEX / ONLINE_SCALED): the per-step LMI is solved again only when
 * rho_k moved by more than tol * rho of the last solve (default 1e-9, 0 = solve every step);
 * otherwise the last certified (beta, L, sigma) is reused, at most |delta rho| above the optimum.
 * Not used with an interval A. sb_ellipsoidal_online_solves: the number of steps that solved
 * the LMI (0 for the other methods). */
int sb_ellipsoidal_set_reuse_tolerance(sb_ellipsoidal* estimator, double tol);
int sb_ellipsoidal_online_solves(const sb_ellipsoidal* estimator, int* solves);
/* Missing and impossible readings, as for sb_zonotopic (SB_ON_INCONSISTENCY_*, SB_OUTPUT_*):
 * each present output is tested against the support of the predicted set E(P, c, rho) in
 * +-C_i; the reset set of SB_ON_INCONSISTENCY_RESET is E(P0, c0, rho0) (P0 nx x nx row-major, c0
 * nx; P0 NULL: the initial set), converted to the design's shape. DESCRIPTOR: every output is
 * needed, so only SB_ON_INCONSISTENCY_FLAG is accepted and no reading is tested. */
int sb_ellipsoidal_set_inconsistency_policy(sb_ellipsoidal* estimator, int policy, const double* P0,
                                            const double* c0, double rho0);
int sb_ellipsoidal_last_check(const sb_ellipsoidal* estimator, int* status, double* margin, int* reset);
/* Back to the state of construction (the initial set, no step taken); options kept. */
int sb_ellipsoidal_reset(sb_ellipsoidal* estimator);

/* Kalman filter baseline (papers.md §2.3, Joseph form), NOT guaranteed: omega ~ N(0, W)
 * (W nw x nw, NULL = identity), x0 ~ N(mean0, cov0). Step k uses y_k and returns the mean
 * and covariance of x_k given y_0..y_k; NaN entries of y are missing outputs (the correction
 * uses the others). */
int sb_kalman_create(const sb_linear_system* system, const double* mean0, const double* cov0,
                     const double* W, sb_kalman** out);
int sb_kalman_free(sb_kalman* filter);
int sb_kalman_step(sb_kalman* filter, const double* y, const double* u, double* mean, double* cov);
/* The mean and covariance of x_k after the last step (the prior before the first step) and the
 * number of steps; NULL outputs are skipped. */
int sb_kalman_current(const sb_kalman* filter, double* mean, double* cov, int* steps);
/* Saved states (see "saved states" at the end of this header). */
int sb_ellipsoidal_state_size(const sb_ellipsoidal* estimator, int* n);
int sb_ellipsoidal_save_state(const sb_ellipsoidal* estimator, double* state, int n);
int sb_ellipsoidal_restore_state(sb_ellipsoidal* estimator, const double* state, int n);
int sb_kalman_state_size(const sb_kalman* filter, int* n);
int sb_kalman_save_state(const sb_kalman* filter, double* state, int n);
int sb_kalman_restore_state(sb_kalman* filter, const double* state, int n);
/* ==== end ellipsoidal estimators ==== */

/* ==== thesis Ch. 1-3: H-infinity set-membership observers (thesis.md §3.4, §4, §5) ====
 * Vertex data is stacked: A is nvert blocks of nx x nx (row-major each, one after the other),
 * B nvert blocks of nx x nu, F nvert blocks of nx x nd, L/U nvert blocks of nx x ny. The LTI
 * case is nvert = 1. C (ny x nx) and Z (ny x nv) are common. wbar (m = nd + nv) are the
 * half-widths of the centred disturbance box (the bound is w'w <= wbar'wbar). */
typedef struct sb_hinf_design sb_hinf_design;
typedef struct sb_hinf_observer sb_hinf_observer;

#define SB_LAMBDA_DEFAULT -1
#define SB_LAMBDA_LOGDET 0
#define SB_LAMBDA_DIRECT 1
#define SB_LAMBDA_INPUT_OR_LOGDET 2
#define SB_LAMBDA_LARGEST 3

/* LMI (2.35) (nvert = 1) or the vertex LMIs (3.13) with a common P: minimise g = gamma^2.
 * Q (nx x nx) is the dissipation matrix, NULL = identity. Outputs (NULL skipped): P (nx x nx),
 * U and L = P^-1 U (nvert blocks of nx x ny), gamma, g. */
int sb_hinf_observer_gain(int nvert, int nx, int ny, int nd, int nv, const double* A, const double* C,
                          const double* F, const double* Z, const double* Q, double* P, double* U,
                          double* L, double* gamma, double* g);
/* LMI (1.48) for x+ = A x + E w, |w| <= wbar: P (nx x nx), gamma, g, level of
 * Psi = {x'Px <= level} (1.55). */
int sb_brl_ellipsoidal_rpi(int nx, int m, const double* A, const double* E, const double* wbar, double* P,
                           double* gamma, double* g, double* level);
/* Prop 2.2/2.3: lambda = lambda_min(Q, P), cbar = g wbar'wbar / lambda, e_inf (nx). */
int sb_ellipsoidal_error_rpi(int nx, const double* P, const double* Q, double g, int m, const double* wbar,
                             double* lambda, double* cbar, double* e_inf);
/* (2.36)/(3.20) with P, L (nvert blocks) and g fixed: route SB_LAMBDA_LOGDET writes the
 * log-det-refined Q_ref (nx x nx) and lambda = lambda_min(Q_ref, P); SB_LAMBDA_DIRECT writes
 * lambda = max lambda with Q = lambda P (Q_ref = lambda P). */
int sb_refine_dissipation_matrix(int nvert, int nx, int ny, int nd, int nv, const double* A, const double* C,
                                 const double* F, const double* Z, const double* P, const double* L, double g,
                                 int route, double* Q_ref, double* lambda);
/* (2.43)/(3.60-3.61): V = mean_i V_i with Ao_i V_i Ao_i' - V_i = -E_i W E_i', Q = V^-1.
 * Ao: nvert blocks nx x nx, E: nvert blocks nx x m, W (m x m). */
int sb_covariance_dissipation_matrix(int nvert, int nx, int m, const double* Ao, const double* E,
                                     const double* W, double* V, double* Q);
/* (2.41): shape V^-1, level t^2, probability lower bound 1 - n/t^2. */
int sb_chebyshev_error_ellipsoid(int nx, const double* V, double t, double* shape, double* level,
                                 double* probability);
/* (3.2): alpha (nvert) with alpha >= 0, sum 1, theta' alpha = rho; theta is nvert x nrho (one
 * vertex per row). Box polytopes (any vertex order): closed form; otherwise an LP. */
int sb_polytopic_weights(int nvert, int nrho, const double* theta, const double* rho, double* alpha);

/* Algorithm 2 (nrho = 0, nvert = 1) or Algorithm 3 (theta nvert x nrho given). W (m x m) is the
 * covariance of w for (2.44), NULL = uniform on [-wbar, wbar]. lambda_route: SB_LAMBDA_*.
 * passes: 2 in the thesis (<= 0 means 2), at most SB_HINF_MAX_PASSES (each pass solves the
 * LMIs again). */
#define SB_HINF_MAX_PASSES 100
int sb_hinf_design_create(int nvert, int nx, int nu, int ny, int nd, int nv, int nrho, const double* A,
                          const double* B, const double* C, const double* F, const double* Z,
                          const double* theta, const double* wbar, const double* W, int lambda_route,
                          int passes, sb_hinf_design** out);
int sb_hinf_design_free(sb_hinf_design* design);
int sb_hinf_design_dims(const sb_hinf_design* design, int* nvert, int* nx, int* nu, int* ny, int* nd,
                        int* nv, int* nrho, int* npasses);
/* P, Q_input, Q_refined, V (nx x nx), L (nvert blocks nx x ny), e_inf (nx), scalars (9):
 * gamma, g, lambda, lambda_input, lambda_refined, cbar, wbar'wbar, lambda_max(P) bound,
 * design time [s]. */
int sb_hinf_design_get(const sb_hinf_design* design, double* P, double* L, double* Q_input,
                       double* Q_refined, double* V, double* e_inf, double* scalars);
/* Pass `pass` (0-based): P, L, Q_input, Q_refined, scalars (7): g, gamma, lambda_input,
 * lambda_refined, lambda_direct (NaN unless computed), lambda, refinement_failed. */
int sb_hinf_design_pass(const sb_hinf_design* design, int pass, double* P, double* L, double* Q_input,
                        double* Q_refined, double* scalars);
/* mu0 from a ball ||e0|| <= radius (2.65-2.67), from vertices of a polytope containing
 * e0 = x0 - xhat0 (npoints x nx, one per row; 3.73-3.74), or from the box [lo, hi] of e0. */
int sb_hinf_design_mu0_ball(const sb_hinf_design* design, double radius, double* mu0);
int sb_hinf_design_mu0_vertices(const sb_hinf_design* design, int npoints, const double* vertices, double* mu0);
int sb_hinf_design_mu0_box(const sb_hinf_design* design, const double* lo, const double* hi, double* mu0);

/* Online observer (2.68-2.71) or (3.63-3.66), a one-step predictor: after k steps the box
 * bounds x_k. rho (nrho) is required for LPV designs and ignored (may be NULL) for LTI. */
int sb_hinf_observer_create(const sb_hinf_design* design, const double* xhat0, double mu0,
                            sb_hinf_observer** out);
int sb_hinf_observer_free(sb_hinf_observer* observer);
int sb_hinf_observer_current(const sb_hinf_observer* observer, double* center, double* lower,
                             double* upper, double* mu, int* steps);
/* One step with y_k, u_k (NULL when nu = 0), rho_k; writes the bounds of x_{k+1}. NaN entries
 * of y: missing outputs (see the inconsistency policy below). On error the observer is
 * unchanged. */
int sb_hinf_observer_step(sb_hinf_observer* observer, const double* y, const double* u, const double* rho,
                          double* center, double* lower, double* upper, double* mu);
/* T steps: Y (T x ny), U (T x nu or NULL), R (T x nrho or NULL); outputs have T + 1 rows
 * (row 0 = the current set). On error the observer is unchanged. */
int sb_hinf_observer_run(sb_hinf_observer* observer, int T, const double* Y, const double* U, const double* R,
                         double* centers, double* lowers, double* uppers, double* mus);
/* Missing and impossible readings, as for sb_zonotopic (SB_ON_INCONSISTENCY_*, SB_OUTPUT_*): a
 * NaN entry of y is a missing output; every present output is tested against the support of
 * the observer's ellipsoid in +-C_i plus its noise bound. A step without some output is made in
 * interval arithmetic (the box narrowed by the outputs present, then A[x] + B u + F[d]) and the
 * recursion restarts from the predicted box. The reset box of SB_ON_INCONSISTENCY_RESET is
 * [reset_lo, reset_hi] (nx each; NULL: the box of the initial ellipsoid). */
int sb_hinf_observer_set_inconsistency_policy(sb_hinf_observer* observer, int policy, const double* reset_lo,
                                              const double* reset_hi);
int sb_hinf_observer_last_check(const sb_hinf_observer* observer, int* status, double* margin, int* reset);
/* Saved state (see "saved states" at the end of this header). */
int sb_hinf_observer_state_size(const sb_hinf_observer* observer, int* n);
int sb_hinf_observer_save_state(const sb_hinf_observer* observer, double* state, int n);
int sb_hinf_observer_restore_state(sb_hinf_observer* observer, const double* state, int n);
/* ==== end thesis H-infinity observers ==== */
/* ==== ESO-D: CORA's H-infinity set-membership observer (Martinez, Loukkas, Meslem 2020, LTI case;
 * include/setbound/thesis/eso_d.hpp) ====
 * The design (a) LMI (2.35) with Q = I at the first feasible gamma of a grid, (b) the Lyapunov
 * LMI V >= 0, Ao V Ao' - V <= -E W E' (its least-trace solution: the Lyapunov equation's), Q = V^-1,
 * (c) LMI (2.35) with that Q, gamma from the grid's start; lambda = lambda_min(Q, P). The result is
 * an sb_hinf_design: sb_hinf_design_get / _pass (pass 0 = step (a), 1 = step (c)) / _mu0_* and
 * sb_hinf_observer_create take it. Plant as sb_hinf_design_create with nvert = 1, nrho = 0;
 * wbar (m = nd + nv) the half-widths of the centred box of w; W (m x m) the covariance of step
 * (b), NULL = diag(wbar^2/3); gammas (ngammas, strictly increasing, > 0) the grid of both
 * searches, ngammas = 0 (gammas NULL) = CORA's linspace(1, 50, 100). No gamma feasible:
 * SB_ERR_INFEASIBLE ("infeasible for every gamma"); some gamma not decided by the solver:
 * SB_ERR_NUMERICAL ("not solved (iteration limit)" counts in the message). */
#define SB_HINF_MAX_GAMMAS 10000
int sb_eso_d_design_create(int nx, int nu, int ny, int nd, int nv, const double* A, const double* B,
                           const double* C, const double* F, const double* Z, const double* wbar,
                           const double* W, int ngammas, const double* gammas, sb_hinf_design** out);
/* The gamma values a grid design tried, in order: search 0 = step (a), 1 = step (c). *count in:
 * capacity of gammas / status (either may be NULL; both NULL: only the count is written), out:
 * the number tried. status[i]: SB_LMI_OPTIMAL (a certified solution: the last one),
 * SB_LMI_INFEASIBLE (certificate of infeasibility), SB_LMI_MAX_ITERATIONS (not solved: iteration
 * limit), SB_LMI_NUMERICAL_ERROR / SB_LMI_INACCURATE (not solved or not certified). A design of
 * sb_hinf_design_create (gamma minimised, no grid): SB_ERR_INVALID_ARGUMENT. */
int sb_hinf_design_gammas(const sb_hinf_design* design, int search, int* count, double* gammas, int* status);
/* The shift delta of step (b): 0 when V solves Ao V Ao' - V = -E W E' (the least-trace V), delta > 0
 * when that V was singular and the right-hand side became -(E W E' + delta I). */
int sb_eso_d_design_lyapunov_shift(const sb_hinf_design* design, double* shift);
/* ==== end ESO-D ==== */
/* ==== thesis Chapter 1: polytopes and invariant sets (thesis.md §3.3–3.6) ====
 * Polytopes are full-dimensional, held in both representations: vertices (nvertices x n,
 * row-major, one vertex per row) and {x : H x <= b} (H nfacets x n with unit-norm rows).
 * Query the sizes with sb_polytope_sizes, then fill caller-allocated arrays. */
typedef struct sb_polytope sb_polytope;
/* conv of npoints points (npoints x n, one per row); they must span R^n. */
int sb_polytope_from_vertices(int n, int npoints, const double* points, sb_polytope** out);
/* {x : H x <= b} (H m x n), bounded, with `interior` (n) strictly inside. */
int sb_polytope_from_halfspaces(int n, int m, const double* H, const double* b, const double* interior,
                                sb_polytope** out);
int sb_polytope_free(sb_polytope* polytope);
int sb_polytope_sizes(const sb_polytope* polytope, int* n, int* nvertices, int* nfacets);
/* vertices (nvertices x n), H (nfacets x n), b (nfacets); NULL outputs are skipped. */
int sb_polytope_get(const sb_polytope* polytope, double* vertices, double* H, double* b);
/* inside[i] = 1 when H p_i <= b + tol (points npoints x n). */
int sb_polytope_contains(const sb_polytope* polytope, int npoints, const double* points, double tol, int* inside);
/* M P (M rows x n; the image must be full-dimensional). */
int sb_polytope_linear_map(const sb_polytope* polytope, int rows, const double* M, sb_polytope** out);
int sb_polytope_minkowski_sum(const sb_polytope* a, const sb_polytope* b, sb_polytope** out);
/* P + [lo, hi] (n each; zero widths allowed). */
int sb_polytope_minkowski_box(const sb_polytope* polytope, const double* lo, const double* hi, sb_polytope** out);
/* a P (a > 0). */
int sb_polytope_scale(const sb_polytope* polytope, double a, sb_polytope** out);
int sb_polytope_bounding_box(const sb_polytope* polytope, double* lo, double* hi);
int sb_polytope_max_vertex_norm(const sb_polytope* polytope, double* radius);

/* (1.40), the ellipsoid projection box: sb_ellipsoid_bounding_box (sets section above). */
/* (1.57)-(1.58): c_out = mu lmax(P) gamma^2 wbar_sq, c_in = (mu lmax(P) - mu + 1) gamma^2 wbar_sq. */
int sb_expanded_ellipsoid_levels(int n, const double* P, double gamma, double wbar_sq, double mu, double* c_in,
                                 double* c_out);
/* §3.5: polytope with {x'Px <= c_in} in it and it in {x'Px <= c_out}; max_vertices <= 0 = default. */
int sb_polyhedral_rpi(int n, const double* P, double c_in, double c_out, int max_vertices, sb_polytope** out);
/* beta = smallest beta with A'PA <= beta^2 P. */
int sb_contraction_rate(int n, const double* A, const double* P, double* beta);

/* Algorithm 1 (mRPI outer shrinking). eps is a RADIUS. Stop rules: */
#define SB_MRPI_STOP_RADIUS 0          /* beta^k sqrt(c_out / lmin(P)) <= eps (rigorous) */
#define SB_MRPI_STOP_SHRINKING_INDEX 1 /* beta^k sqrt(mu lmax(P) / lmin(P)) <= eps (Ex 1.5) */
#define SB_MRPI_STOP_VERTEX_NORM 2     /* max over vertices v of Phi_0 of |A^k v| <= eps */
typedef struct sb_mrpi sb_mrpi;
/* From a given Phi_0 inside {x'Px <= c_out}: x+ = A x + E w, w in [dlo, dhi] (m each, contains
 * 0), A n x n, E n x m. mu: of the shrinking index (>= 1); max_iterations <= 0 = default;
 * boxes_only = 1 skips the polytopes Phi_k (k >= 1). */
int sb_mrpi_shrinking(int n, int m, const double* A, const double* E, const double* dlo, const double* dhi,
                      const sb_polytope* phi0, const double* P, double c_out, double eps, int stop_rule, double mu,
                      int max_iterations, int boxes_only, sb_mrpi** out);
/* Algorithm 1 from the data: BRL (1.48), Phi_v between the ellipsoids of mu (> 1), shrinking with
 * w in [-wbar, wbar]. */
int sb_mrpi_algorithm1(int n, int m, const double* A, const double* E, const double* wbar, double mu, double eps,
                       int stop_rule, int max_iterations, int boxes_only, sb_mrpi** out);
int sb_mrpi_free(sb_mrpi* mrpi);
/* *has_sets = 0 for boxes_only results; *has_design = 1 for sb_mrpi_algorithm1 results. */
int sb_mrpi_info(const sb_mrpi* mrpi, int* n, int* k_star, double* beta, int* has_sets, int* has_design);
/* Arrays of length k_star + 1; NULL outputs are skipped. */
int sb_mrpi_sequences(const sb_mrpi* mrpi, double* radius_bound, double* vertex_radius, double* shrinking_index);
/* Exact (outward-rounded) boxes of Phi_0..Phi_k*: lo, hi (k_star + 1) x n row-major. */
int sb_mrpi_boxes(const sb_mrpi* mrpi, double* lo, double* hi);
/* A new handle with a copy of Phi_k (0 <= k <= k_star; k = 0 always available). */
int sb_mrpi_set(const sb_mrpi* mrpi, int k, sb_polytope** out);
/* Algorithm 1 results only: P (n x n), gamma, c_in, c_out. */
int sb_mrpi_design(const sb_mrpi* mrpi, double* P, double* gamma, double* c_in, double* c_out);
/* ==== end thesis Chapter 1 ==== */
/* ==== thesis Ch. 4: interval observers (thesis.md §6, docs/thesis_interval.md) ==== */
/* Error-box recursion variants: TIGHT = exact interval hull A_o^k[e0] + sum_i (A_o^i E)[w];
 * WRAPPED = the thesis's (4.10-4.11) with [g0] = E[w] boxed first; NAIVE = (4.15). */
#define SB_IOBS_TIGHT 0
#define SB_IOBS_WRAPPED 1
#define SB_IOBS_NAIVE 2
/* The boxes [e_0..e_steps] of e+ = Ao e + E w (Ao n x n Schur, E n x m, e0 and w boxes as lo/hi
 * arrays); lo and hi are (steps+1) x n row-major. Guaranteed in floating point. */
int sb_interval_error_recursion(int n, int m, const double* Ao, const double* E, const double* e0_lo,
                                const double* e0_hi, const double* w_lo, const double* w_hi, int steps,
                                int variant, double* lo, double* hi);
/* The limit box [g] = sum_{i>=0} A_o^i E [w] (TIGHT) or sum A_o^i (E[w]) (WRAPPED); lo, hi (n). */
int sb_interval_error_limit(int n, int m, const double* Ao, const double* E, const double* w_lo,
                            const double* w_hi, int variant, double* lo, double* hi);

/* Interval Luenberger observer (§6.2) on the thesis plant x+ = A x + B u + F d, y = C x + Z v
 * (A nx x nx, B nx x nu, C ny x nx, F nx x nd, Z ny x nv; B, F, Z may be NULL when nu, nd, nv = 0).
 * L (nx x ny): the gain; NULL = the H-infinity gain of LMI (4.13) (Q = I). x0 box, xhat0 in it,
 * d box (nd), v box (nv). variant: SB_IOBS_TIGHT or SB_IOBS_WRAPPED. A one-step predictor: the
 * current box before any step is [x0]; step(y_k, u_k) gives the box of x_{k+1}. */
typedef struct sb_interval_luenberger sb_interval_luenberger;
int sb_interval_luenberger_create(int nx, int nu, int ny, int nd, int nv, const double* A, const double* B,
                                  const double* C, const double* F, const double* Z, const double* L,
                                  const double* x0_lo, const double* x0_hi, const double* xhat0,
                                  const double* d_lo, const double* d_hi, const double* v_lo,
                                  const double* v_hi, int variant, sb_interval_luenberger** out);
int sb_interval_luenberger_free(sb_interval_luenberger* observer);
/* *steps taken, *freeze_index (from this step on the error box is constant), *contraction (the
 * certified factor used for the rounding allowances), *gamma (H-infinity gamma of the design,
 * NaN for a user gain). NULL outputs are skipped. */
int sb_interval_luenberger_info(const sb_interval_luenberger* observer, int* steps, int* freeze_index,
                                double* contraction, double* gamma);
/* L (nx x ny) and, when the gain was designed, P (nx x nx, else left untouched). */
int sb_interval_luenberger_gain(const sb_interval_luenberger* observer, double* L, double* P);
int sb_interval_luenberger_current(const sb_interval_luenberger* observer, double* xhat, double* lo,
                                   double* hi);
/* NaN entries of y: missing outputs (see the inconsistency policy below). On error (wrong
 * data, +-inf) the observer is unchanged. u may be NULL when nu = 0. */
int sb_interval_luenberger_step(sb_interval_luenberger* observer, const double* y, const double* u,
                                double* xhat, double* lo, double* hi);

/* Nonlinear interval observer (§6.6): x+ = A x + h(p, x, k) + B u, y = C x + Z v; L NULL = the
 * H-infinity gain of LMI (4.46) (F = I). window = how many past h boxes are convolved exactly
 * (<= 0: default 256; at most SB_INTERVAL_MAX_WINDOW, the work per step grows with it; the
 * window used is min(window, the number of stored powers of A_o)). step takes the inclusion box [h]_k = [h_lo, h_hi] (nx) of h(p, x_k, k)
 * valid for every x_k in the current box. */
#define SB_INTERVAL_MAX_WINDOW 100000
typedef struct sb_interval_nonlinear sb_interval_nonlinear;
int sb_interval_nonlinear_create(int nx, int nu, int ny, int nv, const double* A, const double* B,
                                 const double* C, const double* Z, const double* L, const double* x0_lo,
                                 const double* x0_hi, const double* xhat0, const double* v_lo,
                                 const double* v_hi, int window, sb_interval_nonlinear** out);
int sb_interval_nonlinear_free(sb_interval_nonlinear* observer);
int sb_interval_nonlinear_info(const sb_interval_nonlinear* observer, int* steps, int* window, double* gamma);
int sb_interval_nonlinear_gain(const sb_interval_nonlinear* observer, double* L, double* P);
int sb_interval_nonlinear_current(const sb_interval_nonlinear* observer, double* xhat, double* lo, double* hi);
int sb_interval_nonlinear_step(sb_interval_nonlinear* observer, const double* y, const double* u,
                               const double* h_lo, const double* h_hi, double* xhat, double* lo, double* hi);

/* Invariant-set interval observer (§6.3): offline design then table look-up online. L NULL = the
 * H-infinity design of LMI (4.13); otherwise L (nx x ny), P (nx x nx) and gamma must satisfy
 * (4.13) (checked by a certificate). Centred disturbance; mu > 1 (thesis: 2); inflation lambda
 * >= 1 or 0 = the smallest admissible; epsilon > 0 is a radius; variant TIGHT or WRAPPED. */
typedef struct sb_interval_invariant_design sb_interval_invariant_design;
int sb_interval_invariant_design_create(int nx, int nu, int ny, int nd, int nv, const double* A, const double* B,
                                        const double* C, const double* F, const double* Z, const double* L,
                                        const double* P, double gamma, const double* x0_lo, const double* x0_hi,
                                        const double* xhat0, const double* d_lo, const double* d_hi,
                                        const double* v_lo, const double* v_hi, double mu, double inflation,
                                        double epsilon, int variant, sb_interval_invariant_design** out);
int sb_interval_invariant_design_free(sb_interval_invariant_design* design);
/* Sizes and scalars (NULL outputs skipped): k_star, the vertex and facet counts of Phi_0, gamma,
 * beta, mu, inflation (lambda used), inflation_min (smallest admissible), epsilon, c_in, c_out. */
int sb_interval_invariant_design_info(const sb_interval_invariant_design* design, int* k_star, int* phi0_vertices,
                                      int* phi0_facets, double* gamma, double* beta, double* mu, double* inflation,
                                      double* inflation_min, double* epsilon, double* c_in, double* c_out);
/* L (nx x ny), P (nx x nx), E (nx x m). */
int sb_interval_invariant_design_matrices(const sb_interval_invariant_design* design, double* L, double* P,
                                          double* E);
/* lo, hi: (k_star+1) x nx row-major, the error boxes [s_0..s_k*]; shrinking: (k_star+1). */
int sb_interval_invariant_design_sequence(const sb_interval_invariant_design* design, double* lo, double* hi,
                                          double* shrinking);
/* Phi_0: vertices (nx x p row-major, one vertex per column), H (f x nx) and b (f): {x : H x <= b}. */
int sb_interval_invariant_design_phi0(const sb_interval_invariant_design* design, double* vertices, double* H,
                                      double* b);
typedef struct sb_interval_invariant sb_interval_invariant;
int sb_interval_invariant_create(const sb_interval_invariant_design* design, sb_interval_invariant** out);
int sb_interval_invariant_free(sb_interval_invariant* observer);
int sb_interval_invariant_info(const sb_interval_invariant* observer, int* steps);
int sb_interval_invariant_current(const sb_interval_invariant* observer, double* xhat, double* lo, double* hi);
int sb_interval_invariant_step(sb_interval_invariant* observer, const double* y, const double* u, double* xhat,
                               double* lo, double* hi);
/* Missing and impossible readings of the three interval observers, as for sb_hinf_observer:
 * present outputs are tested against C_i[x_k] + Z_i[v] (the observer's box); a step without
 * some output is made in interval arithmetic and the error bound restarts from the predicted
 * box. Reset box [reset_lo, reset_hi] (NULL: the initial box x0). */
int sb_interval_luenberger_set_inconsistency_policy(sb_interval_luenberger* observer, int policy,
                                                    const double* reset_lo, const double* reset_hi);
int sb_interval_luenberger_last_check(const sb_interval_luenberger* observer, int* status, double* margin,
                                      int* reset);
int sb_interval_nonlinear_set_inconsistency_policy(sb_interval_nonlinear* observer, int policy,
                                                   const double* reset_lo, const double* reset_hi);
int sb_interval_nonlinear_last_check(const sb_interval_nonlinear* observer, int* status, double* margin,
                                     int* reset);
int sb_interval_invariant_set_inconsistency_policy(sb_interval_invariant* observer, int policy,
                                                   const double* reset_lo, const double* reset_hi);
int sb_interval_invariant_last_check(const sb_interval_invariant* observer, int* status, double* margin,
                                     int* reset);
/* Saved states (see "saved states" at the end of this header). */
int sb_interval_luenberger_state_size(const sb_interval_luenberger* observer, int* n);
int sb_interval_luenberger_save_state(const sb_interval_luenberger* observer, double* state, int n);
int sb_interval_luenberger_restore_state(sb_interval_luenberger* observer, const double* state, int n);
int sb_interval_nonlinear_state_size(const sb_interval_nonlinear* observer, int* n);
int sb_interval_nonlinear_save_state(const sb_interval_nonlinear* observer, double* state, int n);
int sb_interval_nonlinear_restore_state(sb_interval_nonlinear* observer, const double* state, int n);
int sb_interval_invariant_state_size(const sb_interval_invariant* observer, int* n);
int sb_interval_invariant_save_state(const sb_interval_invariant* observer, double* state, int n);
int sb_interval_invariant_restore_state(sb_interval_invariant* observer, const double* state, int n);
/* ==== end thesis Ch. 4 ==== */

/* ==== saved states (core/state.hpp) ====
 * Every estimator handle (sb_ellipsoidal, sb_kalman, sb_zonotopic, sb_czonotopic, sb_hinf_observer,
 * sb_interval_luenberger, sb_interval_nonlinear, sb_interval_invariant) has
 *   sb_xxx_state_size(handle, int* n)             the number of doubles of its state now,
 *   sb_xxx_save_state(handle, double* state, int n)   writes it (n = capacity; too small:
 *                                                  SB_ERR_BUFFER_TOO_SMALL),
 *   sb_xxx_restore_state(handle, const double* state, int n)  reads n doubles back.
 * The state is the full mutable state (current set, step counter, last gain, working sets,
 * windows); restored into a handle created with the same design and arguments the estimator
 * continues bit-for-bit as the saved one. The state starts with a tag (estimator kind), a
 * format version and a fingerprint of the design; a state of another kind, version or design,
 * truncated, with extra values or with a non-finite value gives SB_ERR_INVALID_ARGUMENT with a
 * message starting with "state", and the handle is unchanged. The size may change between
 * steps (zonotopic: the generator count). */
/* ==== end saved states ==== */

/* ==== CORA catalogue, ellipsoidal and interval part (issue 22; estimators/ellipsoidal/) ====
 * CORA's linearSysDT/observe names: ESO-A, ESO-B (bounding ellipsoids). convention (shared by
 * every CORA-catalogue handle, the zonotopic observers below included):
 * SB_CONVENTION_SETBOUND = the papers' algorithm, guaranteed after rounding (default);
 * SB_CONVENTION_CORA = CORA's exact behaviour (its saved numbers; not guaranteed where CORA is not). */
typedef struct sb_bounding_ellipsoid sb_bounding_ellipsoid;
#define SB_CONVENTION_SETBOUND 0
#define SB_CONVENTION_CORA 1
#define SB_BE_GOLLAMUDI 0
#define SB_BE_LIU 1
/* How x0 is given: SB_BE_X0_SHAPE {x : (x - q0)^T Q0^-1 (x - q0) <= rho0} (CORA's ellipsoid(Q, q));
 * SB_BE_X0_INVERSE {x : (x - q0)^T Q0 (x - q0) <= rho0} (setbound's E(P, c, rho)). */
#define SB_BE_X0_SHAPE 0
#define SB_BE_X0_INVERSE 1
/* Shape of an ellipsoid enclosing the zonotope {G b : |b|_inf <= 1} (G n x m row-major): m' G G^T
 * with m' the number of non-zero columns, rounded so that it stays an outer bound. Q: n x n. */
int sb_enclosing_ellipsoid_shape(int n, int m, const double* G, double* Q);
/* x+ = A x + B u + w, w in E(0, QW); y = C x + D u + v, v in E(0, QV); E(q, Q) = {q + Q^(1/2) b :
 * |b|_2 <= 1}. QW (nx x nx) symmetric PSD, QV (ny x ny) symmetric PSD (PD for SB_BE_LIU); NULL:
 * the enclosing ellipsoids of E w and F w, w in [-1, 1]^nw, of `system`. x0: q0 (nx), Q0 (nx x nx,
 * positive definite) and rho0 > 0 read as x0_form says. rule: SB_BE_GOLLAMUDI (ESO-A) or
 * SB_BE_LIU (ESO-B); step_cap: Gollamudi's cap alpha on the step, in (0, 1) (CORA: 1e-4). */
int sb_bounding_ellipsoid_create(const sb_linear_system* system, const double* QW, const double* QV,
                                 const double* q0, const double* Q0, double rho0, int x0_form, int rule,
                                 int convention, double step_cap, sb_bounding_ellipsoid** out);
int sb_bounding_ellipsoid_free(sb_bounding_ellipsoid* estimator);
/* One step: corrects the prediction for x_k with y_k (ny, finite; the first step corrects x0),
 * writes that set, then predicts x_{k+1} with u_k (nu; NULL when nu = 0). The set as
 * E(P, c, rho) = {x : (x - c)^T P (x - c) <= rho} (P nx x nx) and its interval hull lower/upper
 * (guaranteed and rounded outward in the setbound convention; CORA's q +- sqrt(diag Q) in the cora
 * convention). NULL outputs are skipped. On error the estimator is unchanged. */
int sb_bounding_ellipsoid_step(sb_bounding_ellipsoid* estimator, const double* y, const double* u, double* P,
                               double* c, double* rho, double* lower, double* upper);
/* The set of the last step (x0 before the first step), as for sb_bounding_ellipsoid_step. */
int sb_bounding_ellipsoid_current(const sb_bounding_ellipsoid* estimator, double* P, double* c, double* rho,
                                  double* lower, double* upper);
/* The same set in shape form {x : (x - c)^T Q^-1 (x - c) <= 1}, Q nx x nx. */
int sb_bounding_ellipsoid_shape(const sb_bounding_ellipsoid* estimator, double* Q);
/* lambda of the last correction (0: the set was not changed by y), *inconsistent = 1 when the last
 * reading contradicted the prediction (the prediction was kept), the number of steps taken. */
int sb_bounding_ellipsoid_info(const sb_bounding_ellipsoid* estimator, double* lambda, int* inconsistent,
                               int* steps);
/* The noise shapes in use: QW (nx x nx), QV (ny x ny). */
int sb_bounding_ellipsoid_noise(const sb_bounding_ellipsoid* estimator, double* QW, double* QV);
/* Back to x0, no step taken. */
int sb_bounding_ellipsoid_reset(sb_bounding_ellipsoid* estimator);
int sb_bounding_ellipsoid_state_size(const sb_bounding_ellipsoid* estimator, int* n);
int sb_bounding_ellipsoid_save_state(const sb_bounding_ellipsoid* estimator, double* state, int n);
int sb_bounding_ellipsoid_restore_state(sb_bounding_ellipsoid* estimator, const double* state, int n);
/* CORA's interval observer as CORA runs it (Hinf-G with a given gain; estimators/interval/
 * cora_interval_observer.hpp): x+ = A x + B u + E w, y = C x + F w (D must be zero), R0 the zonotope
 * (c0, G0) with G0 nx x m, L nx x ny. Row k of CORA's result per step: row 0 is the hull of R0, row
 * k >= 1 lags one step (it is computed before the update with y_{k-1}). Not guaranteed (no
 * rounding control, CORA's quirks); setbound's guaranteed version is sb_interval_luenberger. */
typedef struct sb_cora_interval sb_cora_interval;
int sb_cora_interval_create(const sb_linear_system* system, const double* c0, int m, const double* G0,
                            const double* L, sb_cora_interval** out);
int sb_cora_interval_free(sb_cora_interval* observer);
/* One step with y (ny) and u (nu; NULL when nu = 0); writes the row's interval lower/upper (nx;
 * NULL skipped). On error the observer is unchanged. */
int sb_cora_interval_step(sb_cora_interval* observer, const double* y, const double* u, double* lower,
                          double* upper);
/* The last row's interval (R0's hull before the first step) and the number of steps. */
int sb_cora_interval_current(const sb_cora_interval* observer, double* lower, double* upper, int* steps);
int sb_cora_interval_reset(sb_cora_interval* observer);
int sb_cora_interval_state_size(const sb_cora_interval* observer, int* n);
int sb_cora_interval_save_state(const sb_cora_interval* observer, double* state, int n);
int sb_cora_interval_restore_state(sb_cora_interval* observer, const double* state, int n);
/* ==== end CORA catalogue, ellipsoidal and interval part ==== */
/* ==== CORA's zonotopic observers (estimators/zonotopic/observer.hpp) ====
 * One zonotopic skeleton, the gain rule as the varying part (CORA's names in brackets):
 * strip-based filters (step k uses y_k and returns the set for x_k, then predicts x_{k+1}):
 *   SB_ZOBS_SEGMENT_MIN  [FRad-A]   segment minimisation per strip (Alamo 2005)
 *   SB_ZOBS_VOLUME_MIN   [VolMin-A] exact volume minimisation per strip, an LP (Alamo 2005)
 *   SB_ZOBS_BRAVO        [VolMin-B] Bravo's candidate parallelotopes per strip (Bravo 2006)
 *   SB_ZOBS_FIXED_STRIPS [PRad-A]   lambda_i = column i of `gain` per strip
 *   SB_ZOBS_WANG         [FRad-B]   Wang et al. 2018 Kalman-like weight, all strips at once
 *   SB_ZOBS_FIXED_LAMBDA [PRad-B/C/D] a given weight `gain`, all strips at once
 * intersection-free predictors (step k uses y_k and returns the set for x_{k+1}):
 *   SB_ZOBS_COMBASTEL    [FRad-C]   Combastel 2015 adaptive gain L_k
 *   SB_ZOBS_FIXED_GAIN   [PRad-E, Nom-G] a given gain L = `gain`
 * Every rule is guaranteed (any weight gives an outer bound). `gain`: nx x ny row-major for
 * the three fixed rules, NULL otherwise. convention: SB_CONVENTION_SETBOUND (the papers'
 * algorithms) or SB_CONVENTION_CORA (CORA's behaviour where it differs: FRad-B's doubled
 * A and W, VolMin-B's absolute threshold, no reduction of the first strip-based set).
 * reduction: SB_ZONO_REDUCE_*; max_generators in nx .. SB_ZONO_MAX_GENERATORS. An interval A
 * (sb_linear_system with A_rad) is accepted by the strip-based rules (the prior is then kept as
 * columns, as for SB_ZOBS_VOLUME_MIN); the intersection-free rules need a known A. */
typedef struct sb_zono_observer sb_zono_observer;
#define SB_ZOBS_SEGMENT_MIN 1
#define SB_ZOBS_BRAVO 2
#define SB_ZOBS_FIXED_STRIPS 3
#define SB_ZOBS_WANG 4
#define SB_ZOBS_FIXED_LAMBDA 5
#define SB_ZOBS_COMBASTEL 6
#define SB_ZOBS_FIXED_GAIN 7
#define SB_ZOBS_VOLUME_MIN 8
int sb_zono_observer_create(const sb_linear_system* system, int rule, const double* gain, int max_generators,
                            int reduction, int convention, int m0, const double* p0, const double* H0,
                            sb_zono_observer** out);
int sb_zono_observer_free(sb_zono_observer* observer);
/* One step: y (ny; NaN entries are missing outputs), u (nu; NULL when nu = 0). Writes the
 * centre, the interval hull (lower, upper: nx each) and the generator count *m of the current
 * set (filters: x_k; predictors: x_{k+1}). On error the observer is unchanged. */
int sb_zono_observer_step(sb_zono_observer* observer, const double* y, const double* u, double* center,
                          double* lower, double* upper, int* m);
/* The current set: *m in: capacity in columns, out: the generator count; p (nx), H (nx x m,
 * row-major). A predictor's current set before its first step is x0; a filter has none. */
int sb_zono_observer_current_set(const sb_zono_observer* observer, int* m, double* p, double* H);
/* The weight of the last step (nx x ny row-major; zero columns: missing or unused outputs). */
int sb_zono_observer_last_gain(const sb_zono_observer* observer, double* gain);
/* What a reading outside the output set of the set a step corrects (filters: the prior;
 * predictors: the current set, with F's bound) does, from the next step on: SB_ON_INCONSISTENCY_FLAG
 * (default: skipped, reported), _RAISE (SB_ERR_INCONSISTENT, the observer unchanged) or _RESET
 * (restart from x0, corrected with the readings consistent with it). Convention CORA tests
 * nothing and accepts only FLAG. */
int sb_zono_observer_set_inconsistency_policy(sb_zono_observer* observer, int policy);
/* The screening of the last step (status: ny SB_OUTPUT_* codes; margin: ny, in units of the
 * output's noise bound, NaN when missing or not tested; *reset: 1 after a restart). A margin
 * <= 0 may be an upper bound: a reading well inside is decided by a lower bound of the radius. */
int sb_zono_observer_last_check(const sb_zono_observer* observer, int* status, double* margin, int* reset);
int sb_zono_observer_reset(sb_zono_observer* observer);
int sb_zono_observer_steps(const sb_zono_observer* observer, int* steps);
/* Saved state (see "saved states" above). */
int sb_zono_observer_state_size(const sb_zono_observer* observer, int* n);
int sb_zono_observer_save_state(const sb_zono_observer* observer, double* state, int n);
int sb_zono_observer_restore_state(sb_zono_observer* observer, const double* state, int n);
/* Offline gains of the intersection-free rules (estimators/zonotopic/designs.hpp), on the
 * bundled LMI solver: SB_ZOBS_DESIGN_PRAD_E (CORA's PRad-E LMI, beta by bisection, maximal trace
 * P; needs E of full row rank) or SB_ZOBS_DESIGN_NOM_G (CORA's condition (A - LC)'P(A - LC) <= P,
 * the analytic centre of its slice P >= I, trace P <= 10 t*, t* its least trace). Outputs: gain L = P^-1 Y (nx x ny),
 * P (nx x nx), Y (nx x ny), *beta (PRad-E: beta; Nom-G: 1); row-major; P, Y, beta may be NULL. No
 * feasible design:
 * SB_ERR_INFEASIBLE with the reason. */
#define SB_ZOBS_DESIGN_PRAD_E 1
#define SB_ZOBS_DESIGN_NOM_G 2
/* ... and of the strip-based rules with fixed weights: SB_ZOBS_DESIGN_PRAD_B (CORA's PRad-B LMI,
 * all strips: the weight for SB_ZOBS_FIXED_LAMBDA) and SB_ZOBS_DESIGN_PRAD_A (that design for
 * each output alone: the columns for SB_ZOBS_FIXED_STRIPS); *beta, P, Y: of the last output. */
#define SB_ZOBS_DESIGN_PRAD_B 3
#define SB_ZOBS_DESIGN_PRAD_A 4
/* ... and SB_ZOBS_DESIGN_PRAD_C / SB_ZOBS_DESIGN_PRAD_D (Wang et al. CDC 2018 / TAC 2019: CORA's
 * SDPs are unbounded / infeasible as coded; setbound maximises lambda_min(P) under the papers'
 * P-radius condition, PRad-C with diagonal multipliers and the budget trace G + trace O <= 1 - beta,
 * PRad-D with CORA's identity multipliers; beta chosen by a scalar search): the weight for
 * SB_ZOBS_FIXED_LAMBDA; *beta is the chosen contraction. */
#define SB_ZOBS_DESIGN_PRAD_C 5
#define SB_ZOBS_DESIGN_PRAD_D 6
int sb_zono_gain_design(const sb_linear_system* system, int method, double* gain, double* P, double* Y,
                        double* beta);
/* sb_zono_gain_design with the limits of every LMI solve of the design: max_iterations (per solve)
 * and time_limit (seconds per solve); 0 keeps the default (100 iterations, 30 s), a negative or
 * NaN value is SB_ERR_INVALID_ARGUMENT / SB_ERR_NOT_FINITE. A design whose solves all stop at a
 * limit gives SB_ERR_NUMERICAL with a message that says so ("time limit"/"iteration limit"). */
int sb_zono_gain_design_limits(const sb_linear_system* system, int method, int max_iterations, double time_limit,
                               double* gain, double* P, double* Y, double* beta);
/* ==== end CORA's zonotopic observers ==== */
/* ==== CORA's ROPO parallelotopes and the Rauch-Tung-Striebel smoother (issue 22;
 * estimators/zonotopic/parallelotope.hpp, estimators/point/rts_smoother.hpp) ====
 * ROPO (Vicino & Zappa 1996): the set is a parallelotope theta + T [-1, 1]^nx (T nx x nx). Each
 * step: the prior A X + B u + E w is reduced to a parallelotope (CORA's order-1 reduction:
 * SB_ZONO_REDUCE_GIRARD = the interval hull, SB_ZONO_REDUCE_PCA = a PCA-oriented box), then the
 * strips of the outputs present are applied one after another with the Vicino-Zappa step
 * (tighten the strip, shrink each generator segment, keep the least-volume candidate).
 * convention: SB_CONVENTION_SETBOUND (guaranteed after rounding: a pending rounding box is
 * carried, readings are screened with SB_ON_INCONSISTENCY_* as for sb_zonotopic; step k uses
 * y_k) or SB_CONVENTION_CORA (CORA's priv_observe_ROPO as it is: step 0 returns x0 without using
 * y_0, no rounding control, no emptiness check: not guaranteed; every output needs a noise
 * bound). A filter: step k returns the set for x_k, then predicts x_{k+1} with u_k. */
typedef struct sb_ropo sb_ropo;
typedef struct sb_ropo_options {
  int reduction;        /* SB_ZONO_REDUCE_GIRARD (default) or SB_ZONO_REDUCE_PCA */
  int convention;       /* SB_CONVENTION_SETBOUND (default) or SB_CONVENTION_CORA */
  int on_inconsistency; /* SB_ON_INCONSISTENCY_* (default FLAG; RESET restarts from x0); CORA: FLAG only */
} sb_ropo_options;
/* Fills *options with the defaults (girard, setbound, flag). */
int sb_ropo_default_options(sb_ropo_options* options);
/* x0 = p0 + H0 [-1, 1]^m0 (H0 nx x m0 row-major; any zonotope: it is reduced to a parallelotope at
 * the first correction). options: NULL for the defaults. Known A only. */
int sb_ropo_create(const sb_linear_system* system, const sb_ropo_options* options, int m0, const double* p0,
                   const double* H0, sb_ropo** out);
int sb_ropo_free(sb_ropo* estimator);
/* One step: y (ny; NaN entries are missing outputs), u (nu; NULL when nu = 0). Writes the centre,
 * the interval hull (lower, upper: nx each; outward rounded in the setbound convention) and the
 * generator count *m of the set for x_k (nx plus the non-zero entries of the rounding box; NULL
 * outputs are skipped). On error the estimator is unchanged. */
int sb_ropo_step(sb_ropo* estimator, const double* y, const double* u, double* center, double* lower,
                 double* upper, int* m);
/* Runs N rows of Y (N x ny) and U (N x nu; NULL when nu = 0) from x0 (as after sb_ropo_reset) and
 * writes row k of center, lower, upper (N x nx each, row-major; NULL skipped): the set for x_k.
 * On error the estimator is unchanged; on success it holds the state after the last row. */
int sb_ropo_run(sb_ropo* estimator, int N, const double* Y, const double* U, double* center, double* lower,
                double* upper);
/* The set of the last step: centre p (nx) and generators H (nx x m, row-major): the parallelotope's
 * nx columns T (zero columns kept; in the cora convention step 0 returns x0's generators), then
 * the rounding box as axis-aligned columns. *m in: capacity in columns, out: the count (too
 * small: SB_ERR_BUFFER_TOO_SMALL with the count needed). No step taken: SB_ERR_INVALID_ARGUMENT. */
int sb_ropo_current_set(const sb_ropo* estimator, int* m, double* p, double* H);
/* The parallelotope of the last step apart: theta (nx), T (nx x nx row-major) and the rounding box
 * radius box (nx; the set is theta + T [-1,1]^nx + [-box, box]); NULL outputs are skipped. Not a
 * parallelotope (cora convention, step 0 with x0 of another generator count): SB_ERR_INVALID_ARGUMENT. */
int sb_ropo_parallelotope(const sb_ropo* estimator, double* theta, double* T, double* box);
/* What the last step did with each output (SB_OUTPUT_*, margins, reset flag), as for
 * sb_zonotopic_last_check; NULL outputs are skipped. */
int sb_ropo_last_check(const sb_ropo* estimator, int* status, double* margin, int* reset);
int sb_ropo_reset(sb_ropo* estimator);
int sb_ropo_steps(const sb_ropo* estimator, int* steps);
/* Saved state (see "saved states" above). */
int sb_ropo_state_size(const sb_ropo* estimator, int* n);
int sb_ropo_save_state(const sb_ropo* estimator, double* state, int n);
int sb_ropo_restore_state(sb_ropo* estimator, const double* state, int n);
/* Rauch-Tung-Striebel smoother (point estimates, NOT guaranteed): x+ = A x + B u + w,
 * y = C x + D u + v, w ~ N(0, Sigma_w), v ~ N(0, Sigma_v), x_0 ~ N(x0, P0), with A, B, C, D of
 * `system` (its E, F are not used; known A only). x0 (nx), P0 (nx x nx, symmetric PSD), Sigma_w
 * (nx x nx, symmetric PSD), Sigma_v (ny x ny, symmetric positive definite), Y (N x ny; NaN entries
 * are missing outputs), U (N x nu; NULL when nu = 0). use_first_measurement = 1: y_0 corrects the
 * prior (the textbook); 0: CORA's indexing (the estimate of x_0 is x0, y_0 unused). Outputs (NULL
 * skipped): smoothed (N x nx) x^s_k, smoothed_cov (N x nx x nx) P^s_k, filtered (N x nx) the
 * forward Kalman filter's x_k|k, filtered_cov (N x nx x nx) its P_k|k; row-major, matrix after
 * matrix. */
int sb_rts_smooth(const sb_linear_system* system, const double* x0, const double* P0, const double* Sigma_w,
                  const double* Sigma_v, int N, const double* Y, const double* U, int use_first_measurement,
                  double* smoothed, double* smoothed_cov, double* filtered, double* filtered_cov);
/* ==== end ROPO and RTS ==== */
