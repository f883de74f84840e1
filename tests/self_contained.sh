#!/usr/bin/env bash
# The repository explains itself: no file may cite design notes that
# live outside it, or a folder of one particular machine, because a user's clone
# has neither. What those notes said is in docs/design.md; cite that instead
# (`docs/design.md, "Heading"`).
#
#   tests/self_contained.sh [SOURCE_DIR]     (default: the current folder)
#
# Checks the files git tracks, plus new files it does not ignore yet; outside a
# git checkout, every file but .git, the build folders and out/. Prints each hit
# as FILE:LINE: TEXT and exits 1; exits 0 when there is none. This file itself is
# skipped: it has to name what it looks for.
set -euo pipefail
cd "${1:-.}"
self=tests/self_contained.sh

# The outside notes by name, the folder they were kept in, and machine paths.
# Each is written with a bracket ([S] matches S) so that this list does not
# match itself in a plain grep of the repository.
patterns=(
  'SOLVER-NOTE[S]' 'ARCHITECTUR[E]\.md' '[S]TYLE\.md' 'DEBIAN-DEPENDENCIE[S]'
  'openhaptics-hdap[i]' '\.\./share[d]' '/wor[k]/' '/hom[e]/' '/User[s]/'
)
regex=$(IFS='|'; echo "${patterns[*]}")

# NUL-separated paths relative to the source folder.
list_files() {
  local top
  if command -v git >/dev/null 2>&1 && top=$(git rev-parse --show-toplevel 2>/dev/null) &&
      [[ $(cd "$top" && pwd -P) == $(pwd -P) ]]; then
    git ls-files -z --cached --others --exclude-standard
  else
    find . \( -path ./.git -o -path ./build -o -path './build-*' -o -path ./out \
              -o -name __pycache__ \) -prune -o -type f -print0 | sed -z 's|^\./||'
  fi
}

hits=()
checked=0
while IFS= read -r -d '' f; do
  [[ -f $f && $f != "$self" ]] || continue
  checked=$((checked + 1))
  # -I: binary files (images, fuzz inputs) hold no citations.
  set +e
  out=$(grep -nIE -- "$regex" "$f")
  rc=$?
  set -e
  case $rc in
    0) while IFS= read -r line; do hits+=("$f:${line%%:*}: ${line#*:}"); done <<<"$out" ;;
    1) ;;
    *) echo "self_contained: cannot read $f" >&2; exit 2 ;;
  esac
done < <(list_files)

if [[ $checked -eq 0 ]]; then
  echo "self_contained: no files found under $(pwd)" >&2
  exit 2
fi
if [[ ${#hits[@]} -gt 0 ]]; then
  echo "self_contained: ${#hits[@]} reference(s) to files outside the repository or to" \
       "one machine's folders (cite docs/design.md instead):"
  printf '%s\n' "${hits[@]}"
  exit 1
fi
echo "self_contained: $checked files, no outside references"
