#!/usr/bin/env bash
# The cost of rendering a gesture on one core, over an ensemble of presses
# (docs/PERFORMANCE.md, "Side by side, in one run"). A brush with
# hair volume on a tablet recording can take a third more or fewer solver
# iterations after a change of round-off, so one render says little. Each
# brush renders the gesture pressed 0, 0.02, 0.04 and 0.06 mm deeper, with
# --threads 1, two renders at a time; the table gives the sums of solver
# iterations and of CPU seconds (user time) and the CPU seconds per second of
# gesture. With a second build, each render runs with both, and the table
# adds the ratios second / first. Run it on an otherwise idle machine; the
# iterations do not depend on the load.
#
#   bench/ensemble.sh SOLVER GESTURE BRISTLE [BRISTLE2] [-- BRUSH...]
#     SOLVER    ipopt or slsqp
#     GESTURE   a bristle trajectory (CSV)
#     BRISTLE   a bristle executable; BRISTLE2 another one to compare with
#     BRUSH     library brushes; default all seven
#   BRISTLE_ENSEMBLE_OFFSETS overrides the press offsets (mm, space separated).
set -euo pipefail
cd "$(dirname "$0")/.."
usage() { echo "usage: bench/ensemble.sh SOLVER GESTURE BRISTLE [BRISTLE2] [-- BRUSH...]" >&2; exit 64; }
[[ $# -ge 3 ]] || usage
solver=$1 gesture=$2
shift 2
bins=()
while [[ $# -gt 0 && $1 != -- ]]; do bins+=("$1"); shift; done
[[ ${#bins[@]} -ge 1 && ${#bins[@]} -le 2 ]] || usage
[[ $# -gt 0 ]] && shift
brushes=("$@")
[[ ${#brushes[@]} -gt 0 ]] || brushes=(round flat bright filbert badger fan calligraphy)
offsets=${BRISTLE_ENSEMBLE_OFFSETS:-"0 0.02 0.04 0.06"}
[[ -f $gesture ]] || { echo "bench/ensemble.sh: $gesture: no such file" >&2; exit 66; }
unset GALLIUM_DRIVER
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
span=$(awk -F, '!/^#/ && $1 ~ /^-?[0-9.]+$/ { if (n++ == 0) t0 = $1; t1 = $1 }
                END { printf "%.3f", t1 - t0 }' "$gesture")

# One render: "<build index> <brush> <iterations> <user seconds>".
cat > "$out/one.sh" <<'EOF'
#!/usr/bin/env bash
set -euo pipefail
idx=$1 bin=$2 brush=$3 dz=$4 solver=$5 gesture=$6 dir=$7
tag=$dir/$idx-$brush-$dz
/usr/bin/time -f %U -o "$tag.time" "$bin" render -q --solver "$solver" --brush "$brush" \
  --trajectory "$gesture" --offset-mm 0 0 "$dz" --threads 1 -o "$tag.png" --stats "$tag.json"
its=$(sed -n 's/.*"solver_iterations": *\([0-9]*\).*/\1/p' "$tag.json")
echo "$idx $brush ${its:-0} $(tail -1 "$tag.time")"
EOF
chmod +x "$out/one.sh"
for brush in "${brushes[@]}"; do
  for dz in $offsets; do
    for i in "${!bins[@]}"; do
      printf '%s\0' "$i" "${bins[$i]}" "$brush" "$dz" "$solver" "$gesture" "$out"
    done
  done
done | xargs -0 -n 7 -P 2 "$out/one.sh" > "$out/runs.txt"

count=$(wc -w <<< "$offsets")
echo "$(basename "$gesture") ($span s), solver $solver, offsets $offsets mm, --threads 1"
echo
if [[ ${#bins[@]} -eq 1 ]]; then
  echo "| brush | iterations | CPU s | CPU s per s of gesture |"
  echo "|---|---:|---:|---:|"
else
  echo "| brush | iterations 1 | iterations 2 | 2 / 1 | CPU s 1 | CPU s 2 | 2 / 1 | CPU s per s of gesture, 1 and 2 |"
  echo "|---|---:|---:|---:|---:|---:|---:|---|"
fi
for brush in "${brushes[@]}"; do
  awk -v b="$brush" -v n="${#bins[@]}" -v span="$span" -v count="$count" '
    $2 == b { it[$1] += $3; cpu[$1] += $4 }
    END {
      per0 = cpu[0] / (count * span)
      if (n == 1) { printf "| %s | %d | %.1f | %.2f |\n", b, it[0], cpu[0], per0; exit }
      per1 = cpu[1] / (count * span)
      printf "| %s | %d | %d | %.2f | %.1f | %.1f | %.2f | %.2f, %.2f |\n", b, it[0], it[1],
             it[0] ? it[1] / it[0] : 0, cpu[0], cpu[1], cpu[0] ? cpu[1] / cpu[0] : 0, per0, per1
    }' "$out/runs.txt"
done
