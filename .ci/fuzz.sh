#!/usr/bin/env bash
# Fuzzes every target of tests/fuzz for SECONDS_PER_TARGET (default 60) on the ASan + UBSan
# build (.ci/asan.sh first), two at a time, each from build-asan/fuzz/corpus/<name> (seeded
# from tests/fuzz/corpus/<name>; it grows across runs in the same build folder). A crash, a
# leak, a sanitizer report or an input slower than 10 s stops the run; the input is left in
# build-asan/fuzz/artifacts/ (add it to tests/fuzz/regressions/<name>/ with a fix).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
targets=(obj ply query_csv toi_truth)
out=build-asan/fuzz
mkdir -p "$out/artifacts" "$out/logs"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
run() {
  local name=$1
  mkdir -p "$out/corpus/$name"
  cp -n tests/fuzz/corpus/"$name"/* "$out/corpus/$name/"
  build-asan/bin/fuzz_"$name" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -dict=tests/fuzz/"$name".dict -artifact_prefix="$out/artifacts/$name-" "$out/corpus/$name" \
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
