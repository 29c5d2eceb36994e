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
/* ==== end ellipsoids, zonotopes, strips ==== */

/* ==== LMI solver (lmi/) ==== */
/* ==== end LMI solver ==== */
