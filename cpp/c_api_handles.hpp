// setbound — C ABI handle types shared by several translation units (internal header).
#pragma once

#include "c_api_common.hpp"
#include "setbound/core/linear_system.hpp"

struct sb_linear_system {
  setbound::LinearSystem system;
};

namespace setbound::capi {

inline const LinearSystem& system_arg(const sb_linear_system* s) {
  require_pointer(s, "system");
  return s->system;
}

}  // namespace setbound::capi
