#!/usr/bin/env bash
# No function of the library or the CLI is longer than 100 lines
# (docs/design.md, "Style habits", item 13). Measures with universal-ctags,
# which gives each function's first and last line; prints every function past
# the limit as FILE:LINE NAME (LINES lines) and exits 1, else exits 0.
#
#   tests/function_length.sh [SOURCE_DIR]     (default: the current folder)
set -euo pipefail
cd "${1:-.}"
readonly limit=100
command -v ctags >/dev/null || { echo "function_length.sh: ctags not found (scripts/install-deps installs universal-ctags)" >&2; exit 2; }
ctags --version | grep -q "Universal Ctags" ||
  { echo "function_length.sh: ctags is not universal-ctags, which gives the end lines" >&2; exit 2; }
dirs=(engine render batch cli haptics input)
# A sanity floor: ctags must see the functions at all (a version that drops
# the end field would otherwise pass every time).
seen=$(ctags -R --languages=C++ --kinds-C++=f --fields=+ne -f - "${dirs[@]}" | grep -c $'\tend:' || true)
if (( seen < 200 )); then
  echo "function_length.sh: ctags reported only $seen functions with an end line" >&2
  exit 2
fi
long=$(ctags -R --languages=C++ --kinds-C++=f --fields=+ne -f - "${dirs[@]}" |
  awk -F'\t' -v limit="$limit" '{
    line = ""; end = "";
    for (i = 4; i <= NF; i++) {
      if ($i ~ /^line:/) line = substr($i, 6);
      if ($i ~ /^end:/) end = substr($i, 5);
    }
    if (line != "" && end != "" && end - line + 1 > limit)
      printf "%s:%s %s (%d lines)\n", $2, line, $1, end - line + 1;
  }' | sort -u)
if [[ -n $long ]]; then
  echo "functions longer than $limit lines (split them, docs/design.md \"Style habits\" item 13):"
  echo "$long"
  exit 1
fi
echo "function_length.sh: $seen functions, none longer than $limit lines"
