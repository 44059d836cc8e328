#!/usr/bin/env bash
# Side-by-side timing of two builds of the `mccd` tool: alternating runs, medians of the time
# each run prints for its steps. Usage:
#   perf/ab.sh OLD/bin/mccd NEW/bin/mccd [ROUNDS] [THREADS]
# Workloads: toi-check cloth-ball (one real step), run cloth-ball in 10 sub-steps, and the
# generated cloth and spheres sequences (--size 8, 30 steps). Needs the data in
# $MCCD_DATA_DIR or ../shared/data. Prints one line per workload: old, new, old/new.
set -euo pipefail
old=$1 new=$2 rounds=${3:-5} threads=${4:-1}
data=${MCCD_DATA_DIR:-$(cd "$(dirname "$0")/../.." && pwd)/shared/data}
cb=$data/toi/cloth-ball
# the seconds a run reports for its steps: toi-check's "time S s", run's "time: T in steps"
toi() { "$1" toi-check "$cb" --threads "$threads" | sed -nE 's/^ *time ([0-9.]+) s.*/\1/p' | head -1; }
run() {
  "$1" run "${@:2}" --threads "$threads" --quiet --exit-zero |
    sed -nE 's/^time: ([0-9.]+) (m?s) in steps.*/\1 \2/p' | awk '{ print ($2 == "ms") ? $1 / 1000 : $1 }'
}
substeps() { run "$1" "$cb/frames" --substeps 10; }
cloth() { run "$1" --scene cloth --size 8 --frames 31; }
spheres() { run "$1" --scene spheres --size 8 --frames 31; }
median() { sort -g | awk '{ a[NR] = $1 } END { print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2 }'; }
measure() {
  local name=$1 fo fn mo mn
  fo=$(mktemp) fn=$(mktemp)
  for ((r = 0; r < rounds; ++r)); do
    "$name" "$old" >>"$fo"
    "$name" "$new" >>"$fn"
  done
  mo=$(median <"$fo") mn=$(median <"$fn")
  printf '%-10s old %8.4f s  new %8.4f s  old/new %.3f\n' "$name" "$mo" "$mn" "$(echo "$mo / $mn" | bc -l)"
  rm -f "$fo" "$fn"
}
echo "# $(date -u +%FT%TZ) $(uptime | sed 's/.*load/load/') threads=$threads rounds=$rounds"
for w in ${WORKLOADS:-toi substeps cloth spheres}; do measure "$w"; done
