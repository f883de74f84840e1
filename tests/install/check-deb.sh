#!/usr/bin/env bash
# The Debian package: `cpack -G DEB` builds it, its Depends name the shared
# libraries the executable links (dpkg-shlibdeps), `dpkg -i` installs it to
# /usr, the installed bristle renders a named brush from /usr/share/bristle
# and `man bristle` shows its page; `dpkg -r` removes it again. Root only
# (exit 77, skipped, otherwise); refuses to touch a bristle package that was
# installed before.
#
#   check-deb.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(realpath "$1")
src=$(realpath "$2")
fail() { echo "check-deb: $*" >&2; exit 1; }
if [[ $(id -u) -ne 0 ]]; then echo "check-deb: skipped: dpkg -i needs root"; exit 77; fi
command -v dpkg-shlibdeps >/dev/null || fail "dpkg-shlibdeps missing (scripts/install-deps installs dpkg-dev)"
if dpkg-query -W -f='${Status}' bristle 2>/dev/null | grep -q "install ok installed"; then
  fail "a bristle package is installed already; remove it (dpkg -r bristle) to run this test"
fi
[[ ! -e /usr/bin/bristle ]] || fail "/usr/bin/bristle exists and is not from a bristle package"

tmp=$(mktemp -d /tmp/bristle-deb-XXXXXX)
installed=0
cleanup() {
  if [[ $installed -eq 1 ]]; then dpkg -r bristle >/dev/null 2>&1 || true; fi
  rm -rf "$tmp"
}
trap cleanup EXIT

cpack -G DEB --config "$build/CPackConfig.cmake" -B "$tmp/pkg" >"$tmp/cpack.log" 2>&1 ||
  fail "cpack failed: $(tail -5 "$tmp/cpack.log")"
deb=$(ls "$tmp"/pkg/bristle_*.deb)
depends=$(dpkg-deb -f "$deb" Depends)
for lib in libipopt libosmesa libpng fonts-dejavu-core; do
  [[ "$depends" == *"$lib"* ]] || fail "Depends lacks $lib: $depends"
done

dpkg -i "$deb" >"$tmp/dpkg.log" 2>&1 || fail "dpkg -i failed: $(tail -5 "$tmp/dpkg.log")"
installed=1
cd "$tmp"
out=$(/usr/bin/bristle validate round)
[[ "$out" == "/usr/share/bristle/brushes/round.json: ok (brush 'round',"* ]] ||
  fail "validate round: $out"
head -60 "$src/scenes/trajectories/straight-pull.csv" > short.csv
env -u GALLIUM_DRIVER "$build/cli/bristle" render -q --brush "$src/scenes/brushes/round.json" \
  --trajectory short.csv -o ordinary.png
env -u GALLIUM_DRIVER /usr/bin/bristle render -q --brush round --trajectory - -o - < short.csv |
  /usr/bin/bristle compare ordinary.png - >/dev/null || fail "the packaged render differs"
# Debian's python3 finds the packaged module (/usr/lib/python3/dist-packages)
# and its brushes in /usr/share/bristle.
out=$(env -u GALLIUM_DRIVER -u BRISTLE_BRUSH_PATH /usr/bin/python3 -c \
      'import bristle; print(bristle.Brush("round").path)' 2>&1) ||
  fail "import bristle after dpkg -i: $out"
[[ "$out" == "/usr/share/bristle/brushes/round.json" ]] || fail "the packaged module's round: $out"
MANWIDTH=100 man -P cat bristle 2>/dev/null | col -b > man.txt
grep -q "^ *bristle render\$" man.txt || fail "man bristle: no page, or no section 'bristle render'"

dpkg -r bristle >/dev/null 2>&1 || fail "dpkg -r bristle failed"
installed=0
[[ ! -e /usr/bin/bristle && ! -e /usr/share/bristle/brushes/round.json &&
   ! -e /usr/lib/python3/dist-packages/bristle ]] ||
  fail "dpkg -r left files behind"
echo "check-deb: ok ($(basename "$deb"); Depends: $depends)"
