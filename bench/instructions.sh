#!/usr/bin/env bash
# The instructions a render executes, counted by Valgrind's callgrind: a
# measure of cost that does not move with the load of a shared machine, where
# CPU seconds drift 1.1-1.5x between sessions and by 5-10% between two runs
# of an ensemble (docs/PERFORMANCE.md, "Counting instructions"). Each brush
# renders the gesture once per build with --threads 1 and llvmpipe drawing on
# the calling thread (LP_NUM_THREADS=0), two renders at a time; the table
# gives the instructions (Ir), the solver iterations and, with a second
# build, the ratios second / first. Under callgrind a render runs about 50
# times slower, so give it a short gesture (a few tenths of a second of a
# tablet recording). Instructions are not time: a cache miss costs more than
# an add. Ratios of two builds on the same work are what this is for.
#
#   bench/instructions.sh GESTURE BRISTLE [BRISTLE2] [-- BRUSH...]
#     GESTURE   a bristle trajectory (CSV)
#     BRISTLE   a bristle executable; BRISTLE2 another one to compare with
#     BRUSH     library brushes; default round calligraphy badger
#   Extra render options (e.g. --solver slsqp) go in BRISTLE_RENDER_OPTIONS.
#   Needs valgrind (scripts/install-deps --bench).
set -euo pipefail
usage() { echo "usage: bench/instructions.sh GESTURE BRISTLE [BRISTLE2] [-- BRUSH...]" >&2; exit 64; }
[[ $# -ge 2 ]] || usage
gesture=$1
shift
bins=()
while [[ $# -gt 0 && $1 != -- ]]; do bins+=("$1"); shift; done
[[ ${#bins[@]} -ge 1 && ${#bins[@]} -le 2 ]] || usage
[[ $# -gt 0 ]] && shift
brushes=("$@")
[[ ${#brushes[@]} -gt 0 ]] || brushes=(round calligraphy badger)
[[ -f $gesture ]] || { echo "bench/instructions.sh: $gesture: no such file" >&2; exit 66; }
command -v valgrind >/dev/null ||
  { echo "bench/instructions.sh: valgrind not found (scripts/install-deps --bench installs it)" >&2; exit 69; }
for b in "${bins[@]}"; do
  [[ -x $b ]] || { echo "bench/instructions.sh: $b: not an executable" >&2; exit 66; }
done
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# Mesa compiles llvmpipe's shaders on first use and keeps them in its disk
# cache, keyed by the CPU it sees; Valgrind's CPU is not the host's, so the
# first render under Valgrind also counts the compiling (about 0.57 G of the
# round's 13 G on Tc). A private cache, filled by one render of the gesture
# per brush under Valgrind (without instrumentation, which is faster) before
# the counted ones, keeps that out of every count. (A warm-up with long steps
# missed a shader that the full render needs: 0.05 G in every count; so did
# warming up with the first brush only, for the brushes after it, in
# whichever build met the shader first.)
export MESA_SHADER_CACHE_DIR=$out/mesa
unset MESA_SHADER_CACHE_DISABLE
for brush in "${brushes[@]}"; do
  LP_NUM_THREADS=0 valgrind --tool=none --log-file="$out/warm.log" "${bins[0]}" render -q \
    --brush "$brush" --trajectory "$gesture" --threads 1 -o "$out/warm.png" ||
    { echo "bench/instructions.sh: the warm-up render of $brush failed (see above)" >&2; exit 70; }
done

# One render: "<build index> <brush> <iterations> <instructions>".
cat > "$out/one.sh" <<'EOF'
#!/usr/bin/env bash
set -euo pipefail
idx=$1 bin=$2 brush=$3 gesture=$4 dir=$5
tag=$dir/$idx-$brush
# shellcheck disable=SC2086  # the options are words on purpose
LP_NUM_THREADS=0 valgrind --tool=callgrind --callgrind-out-file="$tag.cg" --log-file="$tag.log" \
  "$bin" render -q --brush "$brush" --trajectory "$gesture" --threads 1 -o "$tag.png" \
  --stats "$tag.json" ${BRISTLE_RENDER_OPTIONS:-}
its=$(sed -n 's/.*"solver_iterations": *\([0-9]*\).*/\1/p' "$tag.json")
ir=$(sed -n 's/.*Collected : *\([0-9]*\).*/\1/p' "$tag.log")
echo "$idx $brush ${its:-0} ${ir:-0}"
EOF
chmod +x "$out/one.sh"
for brush in "${brushes[@]}"; do
  for i in "${!bins[@]}"; do
    printf '%s\0' "$i" "${bins[$i]}" "$brush" "$gesture" "$out"
  done
done | xargs -0 -n 5 -P 2 "$out/one.sh" > "$out/runs.txt"

echo "$(basename "$gesture"), --threads 1, LP_NUM_THREADS=0 ${BRISTLE_RENDER_OPTIONS:-}"
echo
if [[ ${#bins[@]} -eq 1 ]]; then
  echo "| brush | iterations | instructions (G) | per iteration (M) |"
  echo "|---|---:|---:|---:|"
else
  echo "| brush | iterations 1 | iterations 2 | instructions 1 (G) | instructions 2 (G) | 2 / 1 |"
  echo "|---|---:|---:|---:|---:|---:|"
fi
for brush in "${brushes[@]}"; do
  awk -v b="$brush" -v n="${#bins[@]}" '
    $2 == b { it[$1] = $3; ir[$1] = $4 }
    END {
      if (n == 1) {
        printf "| %s | %d | %.3f | %.2f |\n", b, it[0], ir[0] / 1e9, it[0] ? ir[0] / it[0] / 1e6 : 0
        exit
      }
      printf "| %s | %d | %d | %.3f | %.3f | %.4f |\n", b, it[0], it[1], ir[0] / 1e9, ir[1] / 1e9,
             ir[0] ? ir[1] / ir[0] : 0
    }' "$out/runs.txt"
done
