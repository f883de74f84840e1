#!/usr/bin/env bash
# Simulation and drawing in turns (--threads 1) against simulating ahead on a
# second thread (--threads 2), side by side: for each library brush, one
# render each way before the next brush, and a check that both wrote the same
# PNG bytes (docs/PERFORMANCE.md, "Simulation and drawing on two threads").
#
#   bench/threads_ab.sh GESTURE [SOLVER] [BRISTLE]
#     GESTURE  a trajectory CSV
#     SOLVER   ipopt (the default) or slsqp
#     BRISTLE  default build/cli/bristle
# Prints one line per brush: brush, solver, gesture, wall s in turns, wall s
# ahead, their ratio, and "same" or "DIFFERENT".
set -euo pipefail
gesture=$(realpath "$1")
solver=${2:-ipopt}
cd "$(dirname "$0")/.."
bristle=$(realpath "${3:-build/cli/bristle}")
unset GALLIUM_DRIVER
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for brush in flat bright filbert fan round calligraphy badger; do
  declare -A wall
  for threads in 1 2; do
    start=$(date +%s.%N)
    "$bristle" render -q --solver "$solver" --brush "$brush" --trajectory "$gesture" \
      -o "$out/$threads.png" --threads "$threads"
    end=$(date +%s.%N)
    wall[$threads]=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }')
  done
  same=$(cmp -s "$out/1.png" "$out/2.png" && echo same || echo DIFFERENT)
  awk -v b="$brush" -v s="$solver" -v g="$(basename "$gesture")" -v t="${wall[1]}" \
    -v a="${wall[2]}" -v m="$same" 'BEGIN { printf "%s %s %s %.2f %.2f %.2f %s\n", b, s, g, t, a, a / t, m }'
done
