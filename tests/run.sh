#!/usr/bin/env bash
# tests/run.sh BIN... -- run each cmocka test binary, count its tests, and end with "N passed, N failed".
# A binary that crashes, hangs (timeout) or prints no cmocka summary counts as one failed test, so a crash is
# never mistaken for success.  Exit status: 0 only if nothing failed.
set -u
passed=0; failed=0; bad_bins=()
log_dir=${TEST_LOG_DIR:-build/test-logs}
mkdir -p "$log_dir"
for bin in "$@"; do
  name=$(basename "$bin")
  log="$log_dir/$name.log"
  timeout "${TEST_TIMEOUT:-600}" "$bin" >"$log" 2>&1
  rc=$?
  p=$(grep -E '^\[  PASSED  \] [0-9]+ test' "$log" | tail -n1 | sed -E 's/.*\] ([0-9]+) test.*/\1/')
  f=$(grep -E '^\[  FAILED  \] [0-9]+ test' "$log" | tail -n1 | sed -E 's/.*\] ([0-9]+) test.*/\1/')
  p=${p:-0}; f=${f:-0}
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi   # crashed, timed out or failed outside a test
  if [ "$p" -eq 0 ] && [ "$f" -eq 0 ]; then f=1; fi    # ran no test at all
  passed=$((passed + p)); failed=$((failed + f))
  if [ "$f" -ne 0 ]; then
    bad_bins+=("$name"); printf 'FAIL %-28s %3d passed, %d failed (exit %d; log %s)\n' "$name" "$p" "$f" "$rc" "$log"
    grep -E '^\[  (FAILED|ERROR) +\]|error:|Failure|failure' "$log" | head -n 20 | sed 's/^/    /'
  else
    printf 'ok   %-28s %3d passed\n' "$name" "$p"
  fi
done
echo "${TEST_LABEL:-tests}: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
