#!/usr/bin/env bash
# ASan + UBSan build of the whole tree with clang (library, tools, tests, benchmarks, fuzz
# targets) in build-asan/, and the whole suite on it. Every UBSan report is fatal; the only
# one ignored is named in cmake/ubsan-ignorelist.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DMCCD_SANITIZE=address,undefined -DMCCD_FUZZ=ON
cmake --build build-asan -j2
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
ctest --test-dir build-asan --output-on-failure -j2
