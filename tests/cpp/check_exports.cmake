# Fails unless every dynamic symbol defined by LIBRARY is part of the C ABI (sb_*) or of the
# compiled C++ API (namespace setbound, cmake/setbound.map); in particular no Eigen or libstdc++
# instantiation may leave the library. Needs both kinds to be there.
execute_process(COMMAND nm -D --defined-only -C ${LIBRARY}
  OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nm failed on ${LIBRARY}")
endif()
string(REPLACE "\n" ";" lines "${out}")
set(c_count 0)
set(cpp_count 0)
foreach(line ${lines})
  # "<address> <type> <demangled name>": the name may contain spaces.
  string(REGEX REPLACE "^[0-9a-fA-F]* *[A-Za-z] " "" sym "${line}")
  if(sym STREQUAL "" OR line MATCHES "^[0-9a-fA-F]* A ")  # version-node absolute symbols
    continue()
  endif()
  if(sym MATCHES "^sb_")
    math(EXPR c_count "${c_count} + 1")
  elseif(sym MATCHES "^setbound::")
    math(EXPR cpp_count "${cpp_count} + 1")
  else()
    message(FATAL_ERROR "symbol outside the C ABI and namespace setbound is exported: ${sym}")
  endif()
endforeach()
if(c_count LESS 4 OR cpp_count LESS 4)
  message(FATAL_ERROR "expected the sb_* C ABI and the setbound:: C++ API to be exported, found ${c_count} and ${cpp_count} symbols")
endif()
message(STATUS "${c_count} sb_* and ${cpp_count} setbound:: symbols exported, nothing else")
