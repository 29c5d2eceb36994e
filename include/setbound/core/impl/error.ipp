// setbound — definitions of the functions declared in setbound/core/error.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/core/error.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE const char* error_kind_name(ErrorKind k) noexcept {
  switch (k) {
    case ErrorKind::InvalidArgument: return "invalid argument";
    case ErrorKind::Dimension: return "dimension mismatch";
    case ErrorKind::NotFinite: return "not finite";
    case ErrorKind::NotSymmetric: return "not symmetric";
    case ErrorKind::NotPositiveDefinite: return "not positive definite";
    case ErrorKind::Infeasible: return "infeasible";
    case ErrorKind::NotDetectable: return "not detectable";
    case ErrorKind::Numerical: return "numerical error";
    case ErrorKind::BufferTooSmall: return "buffer too small";
    case ErrorKind::Internal: return "internal error";
    case ErrorKind::Inconsistent: return "inconsistent measurement";
  }
  return "unknown error";
}

}  // namespace setbound
