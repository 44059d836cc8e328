#!/usr/bin/env bash
# Issue 32's 2-core figures in alternating runs, medians, on the real cloth-ball frames:
#  - the whole process (`mccd run` in 10 sub-steps) on 2 threads against 1, and its 1-thread
#    time against an older build;
#  - the paper's flow: 5 sub-steps against one step (times in steps), on 1 and on 2 threads;
#  - fbd against phc in 10 sub-steps on 2 threads (times in steps).
# Usage: perf/two_core_floors.sh NEW/bin/mccd OLD/bin/mccd [ROUNDS]
# Needs the data in $MCCD_DATA_DIR or ../shared/data.
set -euo pipefail
new=$1 old=$2 rounds=${3:-7}
data=${MCCD_DATA_DIR:-$(cd "$(dirname "$0")/../.." && pwd)/shared/data}
frames=$data/toi/cloth-ball/frames
steps() {
  "$@" --quiet --exit-zero | sed -nE 's/^time: ([0-9.]+) (m?s) in steps.*/\1 \2/p' |
    awk '{ print ($2 == "ms") ? $1 / 1000 : $1 }'
}
wall() {
  local s
  s=$(date +%s.%N)
  "$@" --quiet --exit-zero >/dev/null
  echo "$(date +%s.%N) - $s" | bc -l
}
median() { sort -g | awk '{ a[NR] = $1 } END { print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2 }'; }
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
for ((r = 0; r < rounds; ++r)); do
  wall "$new" run "$frames" --substeps 10 --threads 1 >>"$d/w1"
  wall "$new" run "$frames" --substeps 10 --threads 2 >>"$d/w2"
  wall "$old" run "$frames" --substeps 10 --threads 1 >>"$d/old1"
  steps "$new" run "$frames" --substeps 5 --threads 1 >>"$d/s5_1"
  steps "$new" run "$frames" --substeps 1 --threads 1 >>"$d/s1_1"
  steps "$new" run "$frames" --substeps 5 --threads 2 >>"$d/s5_2"
  steps "$new" run "$frames" --substeps 1 --threads 2 >>"$d/s1_2"
  steps "$new" run "$frames" --substeps 10 --threads 2 --method fbd >>"$d/fbd"
  steps "$new" run "$frames" --substeps 10 --threads 2 --method phc >>"$d/phc"
done
ratio() { echo "$1 / $2" | bc -l; }
echo "# $(date -u +%FT%TZ) $(uptime | sed 's/.*load/load/') rounds=$rounds"
w1=$(median <"$d/w1") w2=$(median <"$d/w2") o1=$(median <"$d/old1")
printf 'whole process, 10 sub-steps: 1 thread %.3f s, 2 threads %.3f s: %.3fx; 1 thread against the old build %.3f\n' \
  "$w1" "$w2" "$(ratio "$w1" "$w2")" "$(ratio "$w1" "$o1")"
paste "$d/w1" "$d/w2" | awk '{ printf "%.3f ", $1 / $2 } END { print "(each round, 1 thread / 2 threads)" }'
a=$(median <"$d/s5_1") b=$(median <"$d/s1_1") c=$(median <"$d/s5_2") e=$(median <"$d/s1_2")
printf '5 sub-steps / one step, steps only: 1 thread %.3f, 2 threads %.3f\n' "$(ratio "$a" "$b")" "$(ratio "$c" "$e")"
f=$(median <"$d/fbd") p=$(median <"$d/phc")
printf 'fbd / phc, 10 sub-steps, 2 threads, steps only: %.3f\n' "$(ratio "$f" "$p")"
paste "$d/fbd" "$d/phc" | awk '{ printf "%.3f ", $1 / $2 } END { print "(each round)" }'
