# Install setbound from BUILD_DIR into a scratch prefix, then build and run the consumer.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGV}\n${out}\n${err}")
  endif()
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
# A sanitized libsetbound needs the sanitizer runtimes loaded first: link the consumer with them.
# The header-only consumer (two translation units compiling the headers' definitions inline, about
# a minute and a half of CPU) is built once, in the unsanitized build: it checks the headers, not
# the library.
set(extra)
if(SANITIZE)
  # The consumer is compiled with ASan too: Eigen allocates differently under __SANITIZE_ADDRESS__
  # (no "malloc is already aligned"), so matrices crossing into a sanitized library must agree.
  set(extra "-DCMAKE_CXX_FLAGS=-fsanitize=address,undefined"
      "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined" -DSETBOUND_CONSUMER_HEADER_ONLY=OFF)
endif()
run(${CMAKE_COMMAND} -S ${CONSUMER_SOURCE} -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release ${extra})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build -j 2)
# The consumer must find libsetbound through its RPATH into the installed prefix.
run(${WORK_DIR}/build/setbound_consumer)
run(${WORK_DIR}/build/setbound_quickstart)
if(NOT SANITIZE)
  run(${WORK_DIR}/build/setbound_consumer_header_only)
endif()
