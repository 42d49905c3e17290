#!/usr/bin/env bash
# tests/check_api_walkers.sh [ROOT] -- every function and object the installed headers mark INSTESS_API is named
# in its header's API walker, the test program tests/test_api_<name>.c of header <folder>/<name>.h (core/device.h:
# tests/test_api_device.c), which calls it with NULL pointers, zero and huge sizes and values out of range
# (docs/robustness.md, "Round 3: library API, viewer and numbers").  A header with INSTESS_API names and no walker,
# or a name its walker never mentions, is printed; then "api walkers: N passed, M failed" (N headers complete, M
# not); exit status 1 when M > 0.  The names come from tests/api_names.py, the list install_check compares with
# the shared library's exports.  ROOT: the repository (default: this script's parent folder).
set -u
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root" || { echo "api walkers: no folder $root"; exit 2; }
passed=0; failed=0
for h in $(sed -n '/^PUB_HDR/,/^[^ ]/p' Makefile | sed 's/^PUB_HDR *=//; s/\\//g' | tr ' ' '\n' | grep '\.h$'); do
  names=$(python3 tests/api_names.py "$h" 2>/dev/null)
  [ -z "$names" ] && continue   # an umbrella or a header of macros only
  walker=tests/test_api_$(basename "$h" .h).c
  if [ ! -f "$walker" ]; then
    echo "$h: no API walker ($walker)"
    failed=$((failed + 1))
    continue
  fi
  missing=""
  for n in $names; do
    grep -qw -- "$n" "$walker" || missing="$missing $n"
  done
  if [ -n "$missing" ]; then
    echo "$walker: never names$missing (of $h)"
    failed=$((failed + 1))
  else
    passed=$((passed + 1))
  fi
done
echo "api walkers: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
