#!/usr/bin/env bash
# Two builds side by side on a lent machine, interleaved finely: for every scene, method and
# thread count, ROUNDS rounds, each running build A and then build B (`mccd run`, the steps'
# time it prints). A whole-sweep-per-build comparison moved by 20-35% with the lent machine's
# phases (perf/results/history.md, 2026-11-27); alternating run by run does not.
# Usage: perf/device_ab.sh A_BIN_DIR B_BIN_DIR DATA_DIR OUT_FILE
#   each BIN_DIR holds mccd (and lib/ with the libtbb it links, when carried); A_BIN_DIR also
#   mccd_scenes (the generated scenes are made once, in $CACHE, default /tmp/mccd-scenes).
#   SCENES (cloth-ball,n-body,bart,skirt,toi,toi-5sub,drape), METHODS (fbd,phc), THREADS
#   (1,2,16), ROUNDS (3) and STEPS (6: the generated scenes' last frame intervals) tune it.
#   The drape simulates its 10 frames serially before each run (about 8 s there and here): at
#   the defaults its 36 runs take about 5 minutes, a lent machine's budget of 15 for a session.
#   Name the scenes (SCENES) and leave it out unless it is what the call is for.
# Prints, and writes to OUT_FILE, one line per variant: the medians of A and B (ms in steps
# per frame interval) and A / B.
set -euo pipefail
a=$1 b=$2 data=$3 out=$4
cache=${CACHE:-/tmp/mccd-scenes}
[ -d "$a/lib" ] && export LD_LIBRARY_PATH="$a/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
IFS=, read -ra scenes <<<"${SCENES:-cloth-ball,n-body,bart,skirt,toi,toi-5sub,drape}"
IFS=, read -ra methods <<<"${METHODS:-fbd,phc}"
IFS=, read -ra threads <<<"${THREADS:-1,2,16}"
rounds=${ROUNDS:-3} steps=${STEPS:-6}
gen=()
for s in "${scenes[@]}"; do case $s in cloth-ball | n-body | bart | skirt) gen+=("$s") ;; esac; done
[ ${#gen[@]} -gt 0 ] && "$a/mccd_scenes" --cache "$cache" "${gen[@]}" >/dev/null
# The arguments of `mccd run` for a scene, and the frame intervals its steps cover.
scene_args() {
  case $1 in
    toi) args=("$data/toi/cloth-ball/frames") intervals=1 ;;
    toi-5sub) args=("$data/toi/cloth-ball/frames" --substeps 5) intervals=1 ;;
    drape) args=(--scene drape --size 200 --frames 10) intervals=9 ;;
    *)
      local dir
      dir=$(find "$cache" -maxdepth 1 -type d -name "$1-full-seed1*" | head -1)
      mapfile -t args < <(find "$dir" -name 'frame_*.ply' | sort | tail -n $((steps + 1)))
      intervals=$steps ;;
  esac
}
# ms in steps per frame interval of one run
timed() {
  local bin=$1 m=$2 t=$3 text
  text=$("$bin/mccd" run "${args[@]}" --method "$m" --threads "$t" --quiet --exit-zero)
  sed -nE 's/^time: ([0-9.]+) (m?s) in steps.*/\1 \2/p' <<<"$text" |
    awk -v n="$intervals" '{ print (($2 == "ms") ? $1 : $1 * 1000) / n }'
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
{
  echo "# $(date -u '+%F %T') UTC, $(nproc) threads, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), load $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "# A = $a, B = $b; $rounds rounds, each A then B; ms in steps per frame interval, medians"
  printf '%-12s %-4s %3s %10s %10s %8s\n' scene method T A B A/B
} | tee "$out"
for s in "${scenes[@]}"; do
  scene_args "$s"
  for m in "${methods[@]}"; do
    for t in "${threads[@]}"; do
      ta=() tb=()
      for ((r = 0; r < rounds; ++r)); do
        ta+=("$(timed "$a" "$m" "$t")")
        tb+=("$(timed "$b" "$m" "$t")")
      done
      ma=$(printf '%s\n' "${ta[@]}" | median) mb=$(printf '%s\n' "${tb[@]}" | median)
      printf '%-12s %-4s %3s %10.3f %10.3f %8.3f\n' "$s" "$m" "$t" "$ma" "$mb" "$(awk -v x="$ma" -v y="$mb" 'BEGIN { print x / y }')" | tee -a "$out"
    done
  done
done
echo "# end $(date -u '+%T') UTC, load $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$out"
