#!/usr/bin/env bash
# tests/run.sh BIN... -- run each cmocka test binary, count its tests, and end with "N passed, N failed" (and
# ", N skipped" when a test skipped itself: a test that cannot run on this machine, such as the AVX-512 one on a
# CPU without it, is reported, never counted as passed).
# The binaries run TEST_JOBS at a time (default: the number of cores; many of them spend their time starting
# the program or waiting for it), each with its own log; each result is printed as soon as its binary ends.  Idle
# OpenMP threads sleep (OMP_WAIT_POLICY=passive unless set).
# A binary that crashes, hangs (timeout) or prints no cmocka summary counts as one failed test, so a crash is
# never mistaken for success.  Exit status: 0 only if nothing failed.
set -u
passed=0; failed=0; skipped=0
log_dir=${TEST_LOG_DIR:-build/test-logs}
jobs=${TEST_JOBS:-$(nproc)}
# Idle OpenMP threads sleep instead of spinning, so that binaries running side by side do not steal each
# other's cores (results do not depend on it: images are the same for any thread count and schedule).
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
mkdir -p "$log_dir"

# counts BIN: "passed failed skipped rc" of a finished binary, from its log and exit code.  A binary that
# crashed, timed out or failed outside a test, or ran no test at all, counts one failure.
counts() {
  local name log rc p f k
  name=$(basename "$1"); log="$log_dir/$name.log"
  rc=$(cat "$log_dir/$name.rc" 2>/dev/null || echo 127)
  p=$(grep -E '^\[  PASSED  \] [0-9]+ test' "$log" | tail -n1 | sed -E 's/.*\] ([0-9]+) test.*/\1/')
  f=$(grep -E '^\[  FAILED  \] [0-9]+ test' "$log" | tail -n1 | sed -E 's/.*\] ([0-9]+) test.*/\1/')
  k=$(grep -E '^\[  SKIPPED \] [0-9]+ test' "$log" | tail -n1 | sed -E 's/.*\] ([0-9]+) test.*/\1/')
  p=${p:-0}; f=${f:-0}; k=${k:-0}
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi
  if [ "$p" -eq 0 ] && [ "$f" -eq 0 ]; then f=1; fi
  echo "$p $f $k $rc"
}

# run_one BIN: run it with its log and exit code in $log_dir, then print its result at once (one write, so
# the lines of binaries finishing together do not mix).
run_one() {
  local name log p f k rc out
  name=$(basename "$1"); log="$log_dir/$name.log"
  timeout "${TEST_TIMEOUT:-600}" "$1" >"$log" 2>&1
  echo $? >"$log_dir/$name.rc"
  read -r p f k rc < <(counts "$1")
  if [ "$f" -ne 0 ]; then
    out=$(printf 'FAIL %-28s %3d passed, %d failed (exit %d; log %s)\n' "$name" "$p" "$f" "$rc" "$log"
          grep -E '^\[  (FAILED|ERROR) +\]|error:|Failure|failure' "$log" | head -n 20 | sed 's/^/    /')
  else
    out=$(printf 'ok   %-28s %3d passed%s' "$name" "$p" "$([ "$k" -gt 0 ] && echo ", $k skipped: $(grep -E '^\[  SKIPPED \] [a-z_]' "$log" | sed -E 's/.*\] //' | sort -u | tr '\n' ' ')")")
  fi
  printf '%s\n' "$out"
}
export -f run_one counts
export log_dir
for bin in "$@"; do rm -f "$log_dir/$(basename "$bin").log" "$log_dir/$(basename "$bin").rc"; done   # no stale result
printf '%s\0' "$@" | xargs -0 -n 1 -P "$jobs" bash -c 'run_one "$0"'

for bin in "$@"; do   # the totals
  read -r p f k rc < <(counts "$bin")
  passed=$((passed + p)); failed=$((failed + f)); skipped=$((skipped + k))
done
echo "${TEST_LABEL:-tests}: $passed passed, $failed failed$([ "$skipped" -gt 0 ] && echo ", $skipped skipped")"
[ "$failed" -eq 0 ]
