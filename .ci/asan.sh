#!/usr/bin/env bash
# ASan + UBSan build of the whole tree with g++ (library, tools, tests, benchmarks) in
# build-asan/, and the whole suite on it. Every UBSan report is fatal; the only ones dropped
# are named in cmake/ubsan.supp (in oneTBB's flow-graph header).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMCCD_SANITIZE=address,undefined
cmake --build build-asan -j2
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}
ctest --test-dir build-asan --output-on-failure -j2
