#!/usr/bin/env bash
# Fuzzes each libFuzzer target of tests/fuzz (clang, ASan + UBSan) for SECONDS_PER_TARGET
# (default 60), two at a time, from <build>/corpus/<name> (seeded from tests/fuzz/corpus/<name>;
# it grows across runs in the same build folder), also running tests/fuzz/regressions/<name>/.
# The build: $MCCD_FUZZ_BUILD when set (a folder configured with -DMCCD_FUZZ=ON, as .ci/asan.sh
# leaves build-asan/; .ci/run passes it), else build-fuzz/, configured here with only the
# library and the targets. A crash, a leak, a sanitizer report or an input slower than 10 s
# fails the run; the input is left in <build>/artifacts/ (fix it, and add it to
# tests/fuzz/regressions/<name>/).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${MCCD_FUZZ_BUILD:-build-fuzz}
if [ -z "${MCCD_FUZZ_BUILD:-}" ]; then
  cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DMCCD_SANITIZE=address,undefined -DMCCD_FUZZ=ON -DMCCD_BUILD_TESTS=OFF -DMCCD_BUILD_TOOLS=OFF -DMCCD_BUILD_PERF=OFF
fi
seconds=${1:-60}
targets=(obj ply query_csv toi_truth)
cmake --build "$out" -j2 --target "${targets[@]/#/fuzz_}"
mkdir -p "$out/artifacts" "$out/logs"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1:suppressions=$PWD/cmake/ubsan.supp}
run() {
  local name=$1
  mkdir -p "$out/corpus/$name"
  cp -n tests/fuzz/corpus/"$name"/* "$out/corpus/$name/"
  local regressions=()
  [ -d tests/fuzz/regressions/"$name" ] && regressions=(tests/fuzz/regressions/"$name")
  "$out"/bin/fuzz_"$name" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -dict=tests/fuzz/"$name".dict -artifact_prefix="$out/artifacts/$name-" "$out/corpus/$name" "${regressions[@]}" \
    >"$out/logs/$name.log" 2>&1
}
status=0
for ((i = 0; i < ${#targets[@]}; i += 2)); do
  pids=()
  for name in "${targets[@]:i:2}"; do
    run "$name" &
    pids+=("$!:$name")
  done
  for entry in "${pids[@]}"; do
    if ! wait "${entry%%:*}"; then
      echo "fuzz_${entry#*:}: FAILED; the log's end:"
      tail -40 "$out/logs/${entry#*:}.log"
      status=1
    fi
  done
done
for name in "${targets[@]}"; do
  # the final stats: executions, coverage (edges), features, corpus size
  printf 'fuzz_%-10s %s\n' "$name" "$(grep -E '^(#[0-9]+|stat::number_of_executed_units)' "$out/logs/$name.log" |
    tail -1) $(grep -oE 'cov: [0-9]+ ft: [0-9]+ corp: [0-9]+/[0-9]+[a-zA-Z]*' "$out/logs/$name.log" | tail -1)"
done
exit $status
