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
/* ==== end intervals ==== */

/* ==== ellipsoids, zonotopes, strips (sets/ellipsoid.hpp, zonotope.hpp, strip.hpp) ==== */
/* ==== end ellipsoids, zonotopes, strips ==== */

/* ==== LMI solver (lmi/) ==== */
/* ==== end LMI solver ==== */
