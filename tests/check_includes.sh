#!/usr/bin/env bash
# tests/check_includes.sh [ROOT] -- each folder's private header stays in its folder: no .c, .h or .cpp file
# outside a folder includes that folder's *_internal.h (tests/ may: the tests look inside).  As in Mesa's
# llvmpipe, where lp_setup includes lp_rast.h and never lp_rast_priv.h, the one way into a folder is its public
# header (raster/raster.h, vs/vs.h, meshes/meshes.h, core/core.h).
#
# Private headers: the table below (also headers that do not exist yet, such as vs_internal.h), plus every
# */*_internal.h found in the tree, which belongs to the folder it is in.  A file's folder is the first component
# of its path.  Prints each offending include as FILE:LINE, then "includes: N passed, M failed" (N files without,
# M files with a private include from outside); exit status 1 when M > 0.  ROOT: the repository (default: this
# script's parent folder).
set -u
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root" || { echo "includes: no folder $root"; exit 2; }

# header (file name) -> the folder it is private to
declare -A owner=(
  [raster_internal.h]=raster
  [setup_internal.h]=raster
  [vs_internal.h]=vs
  [mesh_internal.h]=meshes
  [device_internal.h]=core
)
while IFS= read -r h; do
  h=${h#./}
  owner[${h##*/}]=${h%%/*}
done < <(find . -mindepth 2 -name '*_internal.h' -not -path './build*' -not -path './.git/*' -not -path './out/*')

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

passed=0; failed=0
while IFS= read -r f; do
  [ -f "$f" ] || continue            # listed by git but deleted in the work tree
  dir=${f%%/*}
  bad=0
  if [ "$dir" != tests ]; then
    # "LINE:HEADER" for every #include "..." or <...> of a *_internal.h
    while IFS=: read -r line hdr; do
      base=${hdr##*/}
      want=${owner[$base]:-}
      if [ -n "$want" ] && [ "$dir" != "$want" ]; then
        echo "$f:$line: includes $hdr, which is private to $want/ (include its public header instead)"
        bad=1
      fi
    done < <(grep -nE '^[[:space:]]*#[[:space:]]*include[[:space:]]*["<][^">]*_internal\.h[">]' "$f" |
             sed -E 's/^([0-9]+):[^"<]*["<]([^">]*)[">].*/\1:\2/')
  fi
  if [ "$bad" -eq 0 ]; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
done < <(list_sources)

echo "includes: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
