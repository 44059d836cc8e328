# Sanitizer and fuzzing builds of the whole tree (library, tools, tests), with clang:
#   -DMCCD_SANITIZE=address,undefined   ASan + UBSan, every UBSan report fatal
#   -DMCCD_SANITIZE=thread              TSan (against an instrumented TBB: .ci/tbb-tsan.sh)
#   -DMCCD_FUZZ=ON                      the libFuzzer targets of tests/fuzz (with ASan + UBSan)
# MCCD_SANITIZE_FLAGS holds the flags, for builds that must match (the install consumer).
set(MCCD_SANITIZE "" CACHE STRING "Build everything with -fsanitize=<list>: address,undefined or thread (clang)")
option(MCCD_FUZZ "Build the libFuzzer targets in tests/fuzz (clang, with MCCD_SANITIZE)" OFF)

set(MCCD_SANITIZE_FLAGS "")
if(MCCD_SANITIZE OR MCCD_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "MCCD_SANITIZE and MCCD_FUZZ need clang (configure with -DCMAKE_CXX_COMPILER=clang++)")
  endif()
  if(MCCD_FUZZ AND NOT MCCD_SANITIZE MATCHES "address")
    message(FATAL_ERROR "MCCD_FUZZ needs MCCD_SANITIZE=address,undefined")
  endif()
  set(MCCD_SANITIZE_FLAGS -fsanitize=${MCCD_SANITIZE} -fno-omit-frame-pointer)
  if(MCCD_SANITIZE MATCHES "undefined")
    # Every UBSan report stops the program, so a test fails on it. The ignore list holds one
    # entry: vptr checks in oneTBB's flow-graph header (see the file).
    list(APPEND MCCD_SANITIZE_FLAGS -fno-sanitize-recover=all
         -fsanitize-ignorelist=${PROJECT_SOURCE_DIR}/cmake/ubsan-ignorelist.txt)
  endif()
  add_compile_options(${MCCD_SANITIZE_FLAGS})
  add_link_options(${MCCD_SANITIZE_FLAGS})
endif()
