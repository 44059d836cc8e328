# Sanitizer and fuzzing builds of the whole tree (library, tools, tests):
#   -DMCCD_SANITIZE=address,undefined   ASan + UBSan (g++ or clang); every UBSan report fatal
#   -DMCCD_SANITIZE=thread              TSan, against an instrumented TBB (.ci/tbb-tsan.sh)
#   -DMCCD_FUZZ=ON                      the libFuzzer targets of tests/fuzz (clang, with ASan)
# MCCD_SANITIZE_FLAGS holds the flags, for builds that must match (the install consumer), and
# MCCD_SANITIZE_ENV the environment every test runs with (one VAR=value entry, or none).
set(MCCD_SANITIZE "" CACHE STRING "Build everything with -fsanitize=<list>: address,undefined or thread")
option(MCCD_FUZZ "Build the libFuzzer targets in tests/fuzz (clang, with MCCD_SANITIZE=address,undefined)" OFF)

set(MCCD_SANITIZE_FLAGS "")
set(MCCD_SANITIZE_ENV "")
if(MCCD_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang" OR NOT MCCD_SANITIZE MATCHES "address")
    message(FATAL_ERROR "MCCD_FUZZ needs clang and MCCD_SANITIZE=address,undefined "
                        "(-DCMAKE_CXX_COMPILER=clang++ -DMCCD_SANITIZE=address,undefined)")
  endif()
endif()
if(MCCD_SANITIZE)
  set(MCCD_SANITIZE_FLAGS -fsanitize=${MCCD_SANITIZE} -fno-omit-frame-pointer)
  if(MCCD_SANITIZE MATCHES "undefined")
    # Every UBSan report stops the program, so the test fails. vptr reports stay recoverable
    # only so that cmake/ubsan.supp can drop those located in oneTBB's flow-graph header;
    # halt_on_error makes any other one fatal.
    list(APPEND MCCD_SANITIZE_FLAGS -fno-sanitize-recover=all -fsanitize-recover=vptr)
    set(MCCD_SANITIZE_ENV
        "UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:suppressions=${PROJECT_SOURCE_DIR}/cmake/ubsan.supp")
  endif()
  add_compile_options(${MCCD_SANITIZE_FLAGS})
  add_link_options(${MCCD_SANITIZE_FLAGS})
endif()

# Adds MCCD_SANITIZE_ENV to the environment of the given tests.
function(mccd_sanitize_tests)
  if(MCCD_SANITIZE_ENV)
    set_property(TEST ${ARGN} APPEND PROPERTY ENVIRONMENT "${MCCD_SANITIZE_ENV}")
  endif()
endfunction()
