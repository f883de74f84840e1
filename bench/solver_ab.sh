#!/usr/bin/env bash
# Two bristle builds side by side (docs/PERFORMANCE.md): each library brush
# renders a gesture with one build, then the other, one process at a time, and
# the table gives wall time, solver iterations, failed spine solves and the
# SSIM of the two images, with the ratios new / old. Run it on an otherwise
# idle machine; the iterations and the SSIM do not depend on the load.
#
#   bench/solver_ab.sh OLD NEW [SOLVER] [GESTURE]
#     OLD, NEW  two bristle executables (e.g. a worktree's build and build/)
#     SOLVER    ipopt (the default solver) or slsqp; default ipopt
#     GESTURE   a trajectory; default the depth S-curve
set -euo pipefail
cd "$(dirname "$0")/.."
[[ $# -ge 2 ]] || { echo "usage: bench/solver_ab.sh OLD NEW [SOLVER] [GESTURE]" >&2; exit 64; }
old=$1 new=$2 solver=${3:-ipopt} gesture=${4:-scenes/trajectories/depth/s-curve.csv}
unset GALLIUM_DRIVER
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# One render: prints "wall iterations failed" and leaves the image in $out/$2.png.
run() {
  local bin=$1 tag=$2 brush=$3 start end
  start=$(date +%s.%N)
  "$bin" render --solver "$solver" --brush "$brush" --trajectory "$gesture" \
    -o "$out/$tag.png" --stats "$out/$tag.json" > /dev/null 2> "$out/$tag.log"
  end=$(date +%s.%N)
  local its failed
  # From the summary line on stderr, which older builds' --stats lack
  # (no solver_iterations there).
  its=$(sed -n 's/.*), \([0-9]*\) solver iterations.*/\1/p' "$out/$tag.log")
  failed=$(sed -n 's/.*"failed_spine_solves": *\([0-9]*\).*/\1/p' "$out/$tag.json")
  awk -v a="$start" -v b="$end" -v i="${its:-0}" -v f="${failed:-0}" \
    'BEGIN { printf "%.2f %d %d\n", b - a, i, f }'
}
echo "$(basename "$gesture"), solver $solver"
echo
echo "| brush | wall old (s) | wall new (s) | new / old | iterations old | iterations new | new / old | failed spine solves old / new | SSIM new vs old |"
echo "|---|---|---|---|---|---|---|---|---|"
n=0
for brush in round flat bright filbert badger fan calligraphy; do
  # Alternate which build goes first, so that neither always runs on a
  # warmer (or busier) machine.
  if (( n++ % 2 == 0 )); then
    o=$(run "$old" old "$brush"); w=$(run "$new" new "$brush")
  else
    w=$(run "$new" new "$brush"); o=$(run "$old" old "$brush")
  fi
  ssim=$("$new" compare "$out/old.png" "$out/new.png" --align canvas --min-ssim 0 2>&1 |
    sed -n 's/.*SSIM (luma) *\([0-9.]*\).*/\1/p' | head -1)
  read -r ow oi of <<< "$o"
  read -r nw ni nf <<< "$w"
  awk -v b="$brush" -v ow="$ow" -v nw="$nw" -v oi="$oi" -v ni="$ni" -v of="$of" -v nf="$nf" \
    -v s="${ssim:-identical}" 'BEGIN {
      printf "| %s | %.1f | %.1f | %.2f | %d | %d | %.2f | %d / %d | %s |\n",
        b, ow, nw, nw / ow, oi, ni, (oi > 0 ? ni / oi : 0), of, nf, s }'
done
