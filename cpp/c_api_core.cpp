// setbound — C ABI: library information and the per-thread last-error message.
#include <string>

#include "c_api_common.hpp"

namespace setbound::capi {
namespace {
thread_local std::string g_last_error;
}
void set_last_error(const std::string& message) noexcept {
  try {
    g_last_error = message;
  } catch (...) {
    // Assigning can only fail on allocation; keep the previous message then.
  }
}
}  // namespace setbound::capi

extern "C" {

const char* sb_version(void) { return SETBOUND_VERSION_STRING; }

int sb_abi_version(void) { return SETBOUND_ABI_VERSION_NUMBER; }

const char* sb_last_error(void) { return setbound::capi::g_last_error.c_str(); }

const char* sb_status_name(int status) {
  if (status == SB_OK) return "ok";
  if (status < static_cast<int>(setbound::ErrorKind::Inconsistent) || status > 0) return "unknown status";
  return setbound::error_kind_name(static_cast<setbound::ErrorKind>(status));
}

}  // extern "C"
