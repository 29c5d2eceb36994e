// setbound — internal helpers for the C ABI translation units (not installed).
//
// The C ABI is the only place where C++ exceptions are caught (ARCHITECTURE.md): every
// exported function body runs inside sb::guard(), which turns any exception into a
// status code plus the thread-local last-error message.
#pragma once

#include <Eigen/Core>
#include <exception>
#include <new>
#include <string>
#include <vector>
#include <algorithm>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/estimators/measurement_check.hpp"
#include "setbound/sets/box.hpp"

#ifndef SETBOUND_C_API_DECLARED  // setbound.h may enter a translation unit only once
#define SETBOUND_C_API_DECLARED
extern "C" {
#pragma GCC visibility push(default)
#include "setbound/setbound.h"
#pragma GCC visibility pop
}
#endif

namespace setbound::capi {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using ConstRowMap = Eigen::Map<const RowMatrix>;
using RowMap = Eigen::Map<RowMatrix>;
using ConstVecMap = Eigen::Map<const Eigen::VectorXd>;
using VecMap = Eigen::Map<Eigen::VectorXd>;

void set_last_error(const std::string& message) noexcept;

/// Copies a result into a caller's row-major buffer; a null `out` means "not wanted".
inline void write_matrix(const Eigen::MatrixXd& M, double* out) {
  if (out != nullptr && M.size() > 0) RowMap(out, M.rows(), M.cols()) = M;
}
inline void write_vector(const Eigen::VectorXd& v, double* out) {
  if (out != nullptr && v.size() > 0) VecMap(out, v.size()) = v;
}

/// Runs `body` and converts every exception into a status code and last-error message.
template <class Body>
int guard(const char* function, Body&& body) noexcept {
  try {
    body();
    return SB_OK;
  } catch (const setbound::Error& e) {
    set_last_error(std::string(function) + ": " + e.what());
    return e.code();
  } catch (const std::bad_alloc&) {
    set_last_error(std::string(function) + ": out of memory");
    return SB_ERR_INTERNAL;
  } catch (const std::exception& e) {
    set_last_error(std::string(function) + ": internal error: " + e.what());
    return SB_ERR_INTERNAL;
  } catch (...) {
    set_last_error(std::string(function) + ": internal error: unknown exception");
    return SB_ERR_INTERNAL;
  }
}

/// Null-pointer check for an argument; the message names it.
inline void require_pointer(const void* p, const char* name) {
  if (p == nullptr) throw InvalidArgumentError(std::string(name) + ": null pointer");
}

/// A dimension argument must be positive (or non-negative when `allow_zero`).
inline void require_dimension(int d, const char* name, bool allow_zero = false) {
  if (d < 0 || (d == 0 && !allow_zero))
    throw DimensionError(std::string(name) + ": dimension must be " +
                         (allow_zero ? ">= 0" : "> 0") + ", got " + std::to_string(d));
}

/// View a caller's row-major array as a matrix after checking the pointer and dimensions.
inline ConstRowMap matrix_arg(const double* data, int rows, int cols, const char* name) {
  require_dimension(rows, name, true);
  require_dimension(cols, name, true);
  if (rows > 0 && cols > 0) require_pointer(data, name);
  return ConstRowMap(data, rows, cols);
}

inline ConstVecMap vector_arg(const double* data, int n, const char* name) {
  require_dimension(n, name, true);
  if (n > 0) require_pointer(data, name);
  return ConstVecMap(data, n);
}

/// A box from lower/upper end arrays of length n (n = 0: the empty-dimensional box, the pointers
/// may then be NULL). The messages name the argument.
inline Box box_arg(const double* lo, const double* hi, int n, const std::string& name) {
  require_dimension(n, name.c_str(), true);
  if (n > 0) {
    require_pointer(lo, (name + " (lower ends)").c_str());
    require_pointer(hi, (name + " (upper ends)").c_str());
  }
  return Box(ConstVecMap(lo, n), ConstVecMap(hi, n), name);
}

/// SB_ON_INCONSISTENCY_* as the C++ policy; other values are refused with their name.
inline OnInconsistency inconsistency_policy_arg(int policy) {
  switch (policy) {
    case SB_ON_INCONSISTENCY_FLAG: return OnInconsistency::Flag;
    case SB_ON_INCONSISTENCY_RAISE: return OnInconsistency::Raise;
    case SB_ON_INCONSISTENCY_RESET: return OnInconsistency::Reset;
    default:
      throw InvalidArgumentError("policy: unknown inconsistency policy " + std::to_string(policy) +
                                 " (SB_ON_INCONSISTENCY_FLAG = 0, _RAISE = 1, _RESET = 2)");
  }
}

/// A step's screening (sb_*_last_check): statuses as SB_OUTPUT_* codes, margins, the reset flag;
/// NULL outputs are skipped.
inline void check_out(const MeasurementCheck& c, int* status, double* margin, int* reset) {
  const Eigen::Index ny = c.margin.size();
  for (Eigen::Index i = 0; i < ny; ++i) {
    if (status != nullptr) status[i] = static_cast<int>(c.status[static_cast<std::size_t>(i)]);
    if (margin != nullptr) margin[i] = c.margin(i);
  }
  if (reset != nullptr) *reset = c.reset ? 1 : 0;
}

/// Saved states (sb_*_state_size / _save_state / _restore_state): the size, a copy into the
/// caller's buffer of capacity n, and the caller's n values as the blob to restore.
inline void state_size_out(const std::vector<double>& s, int* n) {
  require_pointer(n, "n");
  *n = static_cast<int>(s.size());
}
inline void state_copy_out(const std::vector<double>& s, double* state, int n) {
  require_pointer(state, "state");
  if (n < 0 || static_cast<std::size_t>(n) < s.size())
    throw BufferTooSmallError("state: the buffer holds " + std::to_string(n) + " values, the state needs " +
                              std::to_string(s.size()) + " (see the *_state_size function)");
  std::copy(s.begin(), s.end(), state);
}
/// The copy is the restore's first allocation: running out of memory here is reported like a
/// refused state (the restore functions map std::bad_alloc the same way, core/state.hpp), with
/// the object untouched, rather than as the firewall's generic internal "out of memory".
inline std::vector<double> state_arg(const double* state, int n) {
  if (n < 0) throw InvalidArgumentError("n: must be >= 0, got " + std::to_string(n));
  if (n > 0) require_pointer(state, "state");
  try {
    return std::vector<double>(state, state + n);
  } catch (const std::bad_alloc&) {
    throw InvalidArgumentError("state: out of memory while copying its " + std::to_string(n) +
                               " values; nothing was changed");
  }
}

}  // namespace setbound::capi
