#!/usr/bin/env bash
# Measures `mccd batch` as 2 ranks x 1 thread (mpirun) against 1 rank x 2 threads, alternating
# runs with --exit-zero (a non-zero status makes mpirun abort the job, which costs about 2 s), (also 1 rank x 2 threads under mpirun, and mpirun alone), and prints each run's wall time and the medians; likewise `mccd run` on one sequence
# split over 2 ranks against one process with 2 threads.
#   tools/mpi/measure.sh MCCD SEQUENCES_DIR [ROUNDS]    (SEQUENCES_DIR from make_cloth_sequences.py)
set -euo pipefail
mccd=$1 dir=$2 rounds=${3:-5}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
secs() { local t0 t1; t0=$(date +%s.%N); "$@" >/dev/null 2>&1 || true; t1=$(date +%s.%N); echo "$t1 - $t0" | bc; }
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
declare -A t
uptime
for ((i = 0; i < rounds; ++i)); do
  t[b2r]+="$(secs mpirun -n 2 --oversubscribe --bind-to core "$mccd" batch "$dir/list.txt" --out "$out/a" --threads 1 --quiet --exit-zero) "
  t[b1r]+="$(secs "$mccd" batch "$dir/list.txt" --out "$out/b" --threads 2 --quiet --exit-zero) "
  t[b1m]+="$(secs mpirun -n 1 --bind-to none "$mccd" batch "$dir/list.txt" --out "$out/e" --threads 2 --quiet --exit-zero) "
  t[nop]+="$(secs mpirun -n 2 --oversubscribe "$mccd" --version) "
  t[r2r]+="$(secs mpirun -n 2 --oversubscribe --bind-to core "$mccd" run "$dir/cloth5/frame%03d.ply" --contacts "$out/c.csv" --threads 1 --quiet --exit-zero) "
  t[r1r]+="$(secs "$mccd" run "$dir/cloth5/frame%03d.ply" --contacts "$out/d.csv" --threads 2 --quiet --exit-zero) "
done
uptime
for k in b2r b1r b1m nop r2r r1r; do
  printf '%s: %s -> median %s s\n' "$k" "${t[$k]}" "$(tr ' ' '\n' <<<"${t[$k]}" | grep . | median)"
done
echo "b2r: batch, mpirun -n 2, 1 thread each; b1r: batch, one process, 2 threads;"
echo "b1m: batch, mpirun -n 1 --bind-to none, 2 threads; nop: mpirun -n 2 mccd --version (the launcher alone)"
echo "r2r: run of the largest sequence, mpirun -n 2, 1 thread each; r1r: the same run, one process, 2 threads"
