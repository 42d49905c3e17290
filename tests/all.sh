#!/usr/bin/env bash
# tests/all.sh -- `make test`: the unit/numerical/golden tests, the staged install with the example
# (tests/install_check.sh), the Python package's tests (tests/python_check.sh), the same tests under ASan+UBSan,
# allocation failure at every allocation of a render, a compare and an import (make faults: tests/faults.sh, about
# half a minute), valgrind on the renderer, and the page of `make web` in headless Chromium against the program
# (tests/web_test.sh; skipped, by name, only when Chromium or the wasm toolchain cannot be installed), one stage
# after the other (each runs even if an earlier one failed), then one total line:
# "total: N passed, N failed" (", N skipped" when tests skipped themselves: never counted as passed).  Each
# stage's wall time is printed after it, and all of them at the end.
# Exit status 0 only if every stage passed.
set -u
make=${MAKE:-make}
passed=0; failed=0; skipped=0; status=0; times=""
for stage in test-unit install-check python-check sanitize faults valgrind test-web; do
  echo "== $stage"
  start=$SECONDS
  log=$(mktemp)
  $make --no-print-directory "$stage" 2>&1 | tee "$log"
  rc=${PIPESTATUS[0]}
  line=$(grep -E '^[a-z-]+: [0-9]+ passed, [0-9]+ failed' "$log" | tail -n1)
  rm -f "$log"
  p=$(echo "$line" | sed -nE 's/.* ([0-9]+) passed.*/\1/p'); f=$(echo "$line" | sed -nE 's/.* ([0-9]+) failed.*/\1/p')
  k=$(echo "$line" | sed -nE 's/.* ([0-9]+) skipped.*/\1/p')
  p=${p:-0}; f=${f:-0}; skipped=$((skipped + ${k:-0}))
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; echo "== $stage failed before running its tests (exit $rc)"; fi
  [ "$rc" -ne 0 ] && status=1
  passed=$((passed + p)); failed=$((failed + f))
  echo "== $stage: $((SECONDS - start)) s"
  times="$times $stage $((SECONDS - start)) s;"
done
echo "== stage times:$times"
echo "total: $passed passed, $failed failed$([ "$skipped" -gt 0 ] && echo ", $skipped skipped")"
exit $status
