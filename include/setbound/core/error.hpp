// setbound — error types shared by every layer.
//
// Every failure that a user can cause (bad shapes, NaN, indefinite matrices, infeasible
// designs, undetectable pairs) is reported by throwing one of these. Each carries an
// ErrorKind whose numeric value is the status code the C ABI returns (see setbound.h,
// SB_ERR_*), so the C boundary can translate without a lookup table.
#pragma once

#include <stdexcept>
#include <string>

namespace setbound {

enum class ErrorKind : int {
  InvalidArgument = -1,      // null pointer, unknown option, out-of-range scalar
  Dimension = -2,            // shapes that do not match
  NotFinite = -3,            // NaN or Inf where finite values are required
  NotSymmetric = -4,         // a matrix that must be symmetric is not
  NotPositiveDefinite = -5,  // a matrix that must be PD (or PSD) is not
  Infeasible = -6,           // a design or an intersection has no solution
  NotDetectable = -7,        // unobservable / undetectable / rank condition failed
  Numerical = -8,            // numerical breakdown (solver failure, ill-conditioning)
  BufferTooSmall = -9,       // C ABI only: an output buffer is too small
  Internal = -10,            // a bug: should never happen
  Inconsistent = -11,        // a measurement no state of the model can produce (policy "raise")
};

/// Human-readable name of an error kind (used in messages and by the C ABI).
const char* error_kind_name(ErrorKind k) noexcept;

/// Base class of every exception thrown by setbound.
class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const noexcept { return kind_; }
  int code() const noexcept { return static_cast<int>(kind_); }

 private:
  ErrorKind kind_;
};

#define SETBOUND_DEFINE_ERROR(Name, Kind)                                          \
  class Name : public Error {                                                     \
   public:                                                                        \
    explicit Name(const std::string& message) : Error(ErrorKind::Kind, message) {} \
  };

SETBOUND_DEFINE_ERROR(InvalidArgumentError, InvalidArgument)
SETBOUND_DEFINE_ERROR(DimensionError, Dimension)
SETBOUND_DEFINE_ERROR(NotFiniteError, NotFinite)
SETBOUND_DEFINE_ERROR(NotSymmetricError, NotSymmetric)
SETBOUND_DEFINE_ERROR(NotPositiveDefiniteError, NotPositiveDefinite)
SETBOUND_DEFINE_ERROR(InfeasibleError, Infeasible)
SETBOUND_DEFINE_ERROR(NotDetectableError, NotDetectable)
SETBOUND_DEFINE_ERROR(NumericalError, Numerical)
SETBOUND_DEFINE_ERROR(BufferTooSmallError, BufferTooSmall)
SETBOUND_DEFINE_ERROR(InternalError, Internal)
SETBOUND_DEFINE_ERROR(InconsistentMeasurementError, Inconsistent)

#undef SETBOUND_DEFINE_ERROR

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/core/impl/error.ipp"
#endif
