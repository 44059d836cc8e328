#!/usr/bin/env bash
# The 16-core sweep as one prepared script (README: "16 cores"): bench_core over every scene at
# the given thread counts, then the 200K-triangle drape through `mccd run` (each run simulates
# its frames serially first, about 8 s: DRAPE_THREADS=1,16 saves a minute of the call).
# Usage: perf/device_sweep.sh BIN_DIR DATA_DIR OUT_DIR [LABEL]
#   BIN_DIR holds bench_core and mccd (and lib/ with the libtbb they link, when carried);
#   THREADS (default 1,2,4,8,16), REPEATS (3), METHODS (phc,fbd), SCENES (all) and
#   DRAPE_FRAMES (10) and DRAPE_THREADS (the same as THREADS) tune it from the environment.
set -euo pipefail
bin=$1 data=$2 out=$3 label=${4:-sweep}
threads=${THREADS:-1,2,4,8,16}
[ -d "$bin/lib" ] && export LD_LIBRARY_PATH="$bin/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
mkdir -p "$out"
log="$out/$label.txt"
{
  echo "# $label: $(date -u '+%F %T') UTC, $(nproc) threads, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
} >"$log"
scenes=${SCENES:-cloth-ball,n-body,bart,skirt,cloth-ball-toi,cloth-ball-toi-5sub}
"$bin/bench_core" --threads "$threads" --repeats "${REPEATS:-3}" --methods "${METHODS:-phc,fbd}" \
  --scenes "$scenes" --data "$data" --cache "${CACHE:-/tmp/mccd-scenes}" --out "$out/$label" --no-plots \
  >>"$log" 2>&1
IFS=, read -ra counts <<<"${DRAPE_THREADS:-$threads}"
for t in "${counts[@]}"; do
  for r in 1 2 3; do
    # (exit status 1: collisions found, as expected here)
    text=$("$bin/mccd" run --scene drape --size 200 --frames "${DRAPE_FRAMES:-10}" --threads "$t") || [ $? -eq 1 ]
    echo "drape-200 threads $t run $r: $(grep '^time:' <<<"$text")" >>"$log"
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$log"
