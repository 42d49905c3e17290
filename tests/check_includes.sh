#!/usr/bin/env bash
# tests/check_includes.sh [ROOT] -- the include rules of the layout (README, "Layout"):
#  1. a folder's private header stays in its folder: no file outside a folder includes that folder's
#     *_internal.h (tests/ may: the tests look inside).  As in Mesa's llvmpipe, where lp_setup includes lp_rast.h
#     and never lp_rast_priv.h, the one way into a folder is its public header.
#  2. the library (core/ raster/ vs/ meshes/ image/ tess/) includes nothing of the program (cli/);
#  3. bench/ includes no program header either: it measures the library;
#  4. an installed header (the Makefile's PUB_HDR) includes only installed headers: never core/hlsl.h (the short
#     helper names stay out of users' namespaces), never a private or program header.
# A file's folder is the first component of its path, or the first two under cli/ (cli/run, cli/figures,
# cli/view).  Private headers: every */*_internal.h in the tree belongs to the folder it is in.  Prints each
# offending include as FILE:LINE, then "includes: N passed, M failed" (N files without, M files with a broken
# rule); exit status 1 when M > 0.  ROOT: the repository (default: this script's parent folder).
set -u
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root" || { echo "includes: no folder $root"; exit 2; }

folder_of() { case $1 in cli/*/*) echo "${1%/*}" ;; *) echo "${1%%/*}" ;; esac; }

declare -A owner=()      # private header path -> its folder
while IFS= read -r h; do
  h=${h#./}
  owner[$h]=$(folder_of "$h")
done < <(find . -mindepth 2 -name '*_internal.h' -not -path './build*' -not -path './.git/*' -not -path './out/*')

declare -A installed=()
for h in $(sed -n '/^PUB_HDR/,/^[^ ]/p' Makefile | sed 's/^PUB_HDR *=//; s/\\//g' | tr ' ' '\n' | grep '\.h$'); do
  installed[$h]=1
done

# The sources: tracked and untracked files git does not ignore, or (outside a git checkout) the tree without the
# build folders.
list_sources() {
  if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    git ls-files --cached --others --exclude-standard -- '*.c' '*.h' '*.cpp' | sort -u
  else
    find . \( -path './build*' -o -path './.git' -o -path './out' \) -prune -o \
         \( -name '*.c' -o -name '*.h' -o -name '*.cpp' \) -type f -print | sed 's#^\./##' | sort
  fi
}

# The path an #include "X" of file f names, relative to the root (normalised), or "" for <...> includes.
resolve() {
  local f=$1 inc=$2
  realpath -m --relative-to=. "$(dirname "$f")/$inc"
}

passed=0; failed=0
while IFS= read -r f; do
  [ -f "$f" ] || continue            # listed by git but deleted in the work tree
  dir=$(folder_of "$f"); top=${f%%/*}
  bad=0
  while IFS=: read -r line inc; do
    target=$(resolve "$f" "$inc")
    want=${owner[$target]:-}
    why=""
    if [ -n "$want" ] && [ "$dir" != "$want" ] && [ "$top" != tests ]; then
      why="which is private to $want/ (include its public header instead)"
    elif [[ $target == cli/* ]] && [[ $top =~ ^(core|raster|vs|meshes|image|tess|bench)$ ]]; then
      why="a header of the program: the library and bench/ never include the program"
    elif [ -n "${installed[$f]:-}" ] && [ -z "${installed[$target]:-}" ]; then
      why="which is not installed, from an installed header"
    fi
    if [ -n "$why" ]; then
      echo "$f:$line: includes $inc, $why"
      bad=1
    fi
  done < <(grep -nE '^[[:space:]]*#[[:space:]]*include[[:space:]]*"[^"]*"' "$f" |
           sed -E 's/^([0-9]+):[^"]*"([^"]*)".*/\1:\2/')
  if [ "$bad" -eq 0 ]; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
done < <(list_sources)

echo "includes: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
