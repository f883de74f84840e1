#!/usr/bin/env bash
# `cmake --install` to a temporary prefix, then the installed bristle used as a
# user would, from outside the source tree: a brush by name (found in the
# install's share/bristle/brushes), a trajectory piped in with `--trajectory -`,
# the PNG piped out with `-o -` into `bristle compare -` against a render made
# the ordinary way (files in, a file out); the layout (only the public API's
# headers: docs/api.md), the man page, and a project of someone else's built
# with find_package(bristle) against it, using the public API alone.
#
#   check-install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(realpath "$1")
src=$(realpath "$2")
tmp=$(mktemp -d /tmp/bristle-install-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "check-install: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
cd "$tmp"
[[ "$PWD" != "$src"* ]] || fail "the test must run outside the source tree"
bin=$tmp/prefix/bin/bristle

for f in bin/bristle share/bristle/brushes/round.json share/bristle/brushes/fan.json \
         share/bristle/trajectories/s-curve.csv share/bristle/paintings/petals.json \
         share/bristle/paintings/petals/dot.csv share/bristle/sheets/library.json \
         share/bristle/batch/standard.json share/bristle/blender/bristle_brush.py \
         share/bristle/docs/README.md share/bristle/docs/errors.md share/bristle/docs/api.md \
         share/man/man1/bristle.1 include/bristle/render.h include/bristle/brush.h \
         include/bristle/trajectory.h include/bristle/simulation.h include/bristle/png.h \
         include/bristle/error.h include/bristle/version.h \
         lib/libbristle.a lib/libbristle_engine.a lib/cmake/bristle/bristleConfig.cmake; do
  [[ -f prefix/$f ]] || fail "prefix/$f was not installed"
done
# Only the public API's headers are installed (docs/api.md): no internal one
# (the engine's, render's, the Ipopt shims), and none of them includes anything
# but the standard library and each other.
for f in include/bristle/engine include/bristle/render include/bristle/haptics \
         include/bristle/bristle include/bristle/api; do
  [[ ! -e prefix/$f ]] || fail "prefix/$f was installed"
done
internal=$(find prefix/include -name dense_kkt.h -o -name gl_program.h -o -name temp_files.h \
           -o -name ipopt_timers.h -o -name brush_library.h -o -name stroke_setup.h)
[[ -z "$internal" ]] || fail "internal headers were installed: $internal"
[[ "$(find prefix/include -type f | wc -l)" -ge 7 ]] || fail "the public headers are missing"
while IFS= read -r h; do
  bad=$(grep -E '^[[:space:]]*#[[:space:]]*include' "$h" |
        grep -vE '#[[:space:]]*include[[:space:]]*(<[a-z_]+>|"bristle/[a-z_]+\.h")' || true)
  [[ -z "$bad" ]] || fail "$h includes more than the standard library and bristle/: $bad"
done < <(find prefix/include -type f)

# A name is the install's brush: the installed copy does not look in the source tree.
out=$("$bin" validate round)
[[ "$out" == "$tmp/prefix/share/bristle/brushes/round.json: ok (brush 'round',"* ]] ||
  fail "validate round: $out"
"$bin" brushes | grep -q '^round ' || fail "bristle brushes does not list the installed library"

# The pipe against the ordinary render.
head -60 "$src/scenes/trajectories/straight-pull.csv" > short.csv
env -u GALLIUM_DRIVER "$build/cli/bristle" render -q --brush "$src/scenes/brushes/round.json" \
  --trajectory short.csv -o ordinary.png
env -u GALLIUM_DRIVER "$bin" render -q --brush round --trajectory - -o - < short.csv |
  "$bin" compare ordinary.png - > compare.txt || fail "compare: $(cat compare.txt)"
grep -q "ordinary.png and -: identical pixels" compare.txt || fail "compare said: $(cat compare.txt)"

# Installed scenes keep their relative paths.
"$bin" validate prefix/share/bristle/paintings/petals.json prefix/share/bristle/sheets/library.json \
  >/dev/null || fail "the installed painting or sheet does not validate"

# The man page renders and has a section for every command.
MANWIDTH=100 man -l prefix/share/man/man1/bristle.1 2>/dev/null | col -b > man.txt
for c in render preview validate brushes pigments record replay sheet batch compare; do
  grep -q "^ *bristle $c\$" man.txt || fail "the man page has no section 'bristle $c'"
done
grep -q -- "--trajectory" man.txt || fail "the man page lacks the render options"
# EXAMPLES one per line (help2man alone folds them into one paragraph), with
# the install's paths: an installed user has no source tree.
sed -n '/^EXAMPLES/,/^[A-Z]/p' man.txt > examples.txt
for e in "bristle brushes" "bristle pigments" "bristle preview fan -o fan.png"; do
  grep -q "^[[:space:]]*$e\$" examples.txt || fail "the man page's EXAMPLES lack the line '$e'"
done
grep -q "/share/bristle/trajectories/s-curve.csv" examples.txt ||
  fail "the man page's EXAMPLES do not use the installed scenes"
! grep -q "scenes/" man.txt || fail "the man page names source-tree paths: $(grep -m1 scenes/ man.txt)"
grep -q "^ENVIRONMENT" man.txt && grep -q "BRISTLE_BRUSH_PATH" man.txt ||
  fail "the man page has no ENVIRONMENT section naming BRISTLE_BRUSH_PATH"
# find_package(bristle): an outside project links the installed libraries.
cmake -S "$src/tests/install/consumer" -B consumer -DCMAKE_PREFIX_PATH="$tmp/prefix" \
  -DCMAKE_BUILD_TYPE=Release >consumer.log 2>&1 || fail "configuring the consumer: $(tail -5 consumer.log)"
cmake --build consumer >>consumer.log 2>&1 || fail "building the consumer: $(tail -5 consumer.log)"
out=$(env -u GALLIUM_DRIVER consumer/consumer stroke.png 2>&1) || fail "the consumer failed: $out"
[[ "$(head -1 <<<"$out")" == "bristle 0."*": brush 'round', 7 spines, hair "*" mm" ]] ||
  fail "consumer said: $(head -1 <<<"$out")"
grep -qE "^stroke: [0-9]+ x [0-9]+ px, [1-9][0-9]* px darker than the paper$" <<<"$out" ||
  fail "the consumer's stroke: $out"
grep -qE "^simulation: contact from step [0-9]+$" <<<"$out" ||
  fail "the consumer's simulation never touched the paper: $out"
"$bin" compare stroke.png stroke.png >/dev/null || fail "the consumer's PNG does not read back"

# The Python module (docs/python.md): the install's package imports with
# Debian's python3 from lib/python3/dist-packages, finds the install's brush
# library without BRISTLE_BRUSH_PATH, and paints the installed bristle's pixels.
python=${BRISTLE_PYTHON:-/usr/bin/python3}
[[ -x $python ]] || python=python3
[[ -f prefix/lib/python3/dist-packages/bristle/__init__.py ]] ||
  fail "the Python package was not installed in lib/python3/dist-packages"
out=$(env -u GALLIUM_DRIVER -u BRISTLE_BRUSH_PATH \
      PYTHONPATH="$tmp/prefix/lib/python3/dist-packages" "$python" -c '
import bristle
brush = bristle.Brush("round")
print(brush.path)
image = bristle.render(brush, bristle.Trajectory.load("short.csv"), px_per_mm=2)
bristle.save_png("python.png", image)
' 2>&1) || fail "the installed Python module: $out"
[[ "$out" == "$tmp/prefix/share/bristle/brushes/round.json" ]] ||
  fail "the installed Python module's round is not the install's: $out"
env -u GALLIUM_DRIVER "$bin" render -q --brush round --trajectory short.csv --px-per-mm 2 \
  -o cli2.png
"$bin" compare cli2.png python.png > compare.txt || fail "Python vs CLI: $(cat compare.txt)"
grep -q "identical pixels" compare.txt || fail "the installed module's pixels: $(cat compare.txt)"
echo "check-install: ok ($tmp/prefix)"
