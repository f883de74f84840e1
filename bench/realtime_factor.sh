#!/usr/bin/env bash
# Real-time factor: seconds of wall time per second of gesture, for each
# library brush on a gesture, with a solver (docs/PERFORMANCE.md, "Real-time
# factor"). Each render is the whole `bristle render` command at the default
# resolution, one process at a time; run it on an otherwise idle machine.
#
#   bench/realtime_factor.sh [BRISTLE] [SOLVER] [GESTURE...]
#     BRISTLE  default build/cli/bristle
#     SOLVER   ipopt (the default) or slsqp; default: both
#     GESTURE  trajectory or recording files; default: the depth S-curve and
#              the MyPaint excerpt (scenes/recordings/painting30sec-excerpt.dat)
# Prints one markdown row per brush and gesture: wall s, gesture s, factor.
set -euo pipefail
cd "$(dirname "$0")/.."
bristle=${1:-build/cli/bristle}
solvers=${2:-"ipopt slsqp"}
shift 2 2>/dev/null || shift $#
gestures=("$@")
[[ ${#gestures[@]} -gt 0 ]] ||
  gestures=(scenes/trajectories/depth/s-curve.csv scenes/recordings/painting30sec-excerpt.dat)
unset GALLIUM_DRIVER
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# The gesture's length: the span of its times (a recording's as imported).
span() {
  local csv=$1
  if [[ $csv != *.csv ]] || ! head -1 "$csv" | grep -q bristle-trajectory; then
    "$bristle" import "$csv" --brush round -o "$out/g.csv" --quiet
    csv=$out/g.csv
  fi
  awk -F, '!/^#/ && $1 ~ /^-?[0-9.]+$/ { if (n++ == 0) t0 = $1; t1 = $1 } END { printf "%.3f", t1 - t0 }' "$csv"
}
echo "| brush | gesture | solver | wall (s) | gesture (s) | wall / gesture |"
echo "|---|---|---|---|---|---|"
for g in "${gestures[@]}"; do
  g_s=$(span "$g")
  for solver in $solvers; do
    for brush in round flat bright filbert badger fan calligraphy; do
      start=$(date +%s.%N)
      "$bristle" render -q --solver "$solver" --brush "$brush" --trajectory "$g" -o "$out/r.png"
      end=$(date +%s.%N)
      awk -v b="$brush" -v g="$(basename "$g")" -v s="$solver" -v t0="$start" -v t1="$end" \
        -v d="$g_s" 'BEGIN { w = t1 - t0; printf "| %s | %s | %s | %.2f | %.2f | %.2f |\n", b, g, s, w, d, w / d }'
    done
  done
done
