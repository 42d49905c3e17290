#!/usr/bin/env bash
# tests/python_check.sh -- `make python-check`, a stage of `make test`: the Python package's tests (python/tests,
# pytest) on Debian's python3 and this build's library (INSTESS_LIBDIR, INSTESS_BIN from the Makefile).  Each
# test's result is printed as it finishes (pytest -v); the stage ends with "python: N passed, M failed" (and
# ", N skipped").  A run that crashes or reports no count counts as one failure.
set -u
py=${PYTHON:-/usr/bin/python3}
root=$(cd "$(dirname "$0")/.." && pwd)
if ! "$py" -c 'import numpy, pytest' 2>/dev/null; then
  echo "FAIL python: $py cannot import numpy and pytest (scripts/setup.sh installs python3-numpy and python3-pytest)"
  echo "python: 0 passed, 1 failed"
  exit 1
fi
log=$(mktemp)
trap 'rm -f "$log"' EXIT
cd "$root" || exit 2
PYTHONPATH="$root/python${PYTHONPATH:+:$PYTHONPATH}" PYTHONDONTWRITEBYTECODE=1 \
  "$py" -m pytest -v --tb=short -p no:cacheprovider python/tests 2>&1 | tee "$log"
rc=${PIPESTATUS[0]}
summary=$(grep -E '^=+ .*(passed|failed|error|skipped).* in [0-9.]+s' "$log" | tail -n1)
count() { echo "$summary" | grep -oE "[0-9]+ $1" | grep -oE '^[0-9]+' || echo 0; }
p=$(count passed); f=$(count failed); e=$(count error); k=$(count skipped)
f=$((f + e))
if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi   # pytest itself failed (collection, crash)
if [ "$p" -eq 0 ] && [ "$f" -eq 0 ]; then f=1; fi    # ran nothing
echo "python: $p passed, $f failed$([ "$k" -gt 0 ] && echo ", $k skipped")"
[ "$f" -eq 0 ]
