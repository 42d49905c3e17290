#!/usr/bin/env bash
# tests/web_test.sh -- `make test-web`, the browser stage of make test: installs what it needs (scripts/setup.sh
# --web: the wasm toolchain, Chromium, node), builds the page (make web) and the program, then runs
# tests/web_test.mjs, which ends "web: N passed, N failed".  Only when the packages cannot be installed (no root
# or sudo, no network) is the stage skipped, and then it says so by name: "web: 0 passed, 0 failed, 1 skipped
# (...)", never counted as passed.  A page that does not build is a failure.
set -u
make=${MAKE:-make}
if ! setup_err=$(bash scripts/setup.sh --web 2>&1); then
  echo "$setup_err" | tail -n 3 | sed 's/^/    /'
  echo "SKIP the browser test: Chromium or the wasm toolchain cannot be installed (scripts/setup.sh --web failed)"
  echo "web: 0 passed, 0 failed, 1 skipped (browser test: Chromium or the wasm toolchain cannot be installed)"
  exit 0
fi
if ! $make --no-print-directory web build/instess >/dev/null 2>&1; then
  $make --no-print-directory web build/instess 2>&1 | tail -n 20
  echo "FAIL make web: the page does not build"
  echo "web: 0 passed, 1 failed"
  exit 1
fi
exec node tests/web_test.mjs out/web/index.html build/instess
