#!/usr/bin/env bash
# tests/make_check.sh -- what `make test` needs from the Makefile's -j default, checked by running make (part of
# make test-unit): a make nested in a recipe (as tests/all.sh runs its stages) reads the Makefile without the
# warning "-jN forced in makefile: resetting jobserver mode" and its recipes run with the parent's jobserver
# (-j passes through); a top-level make without -j runs with one job per core, and a -j on its command line wins.
# Prints "make: N passed, M failed"; exit status 1 when M > 0.
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d /tmp/instess-make-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0; fail=0
check() {
  local name=$1; shift
  if ( "$@" ) >"$tmp/last.log" 2>&1; then pass=$((pass + 1)); echo "ok   $name"
  else fail=$((fail + 1)); echo "FAIL $name"; sed 's/^/    /' "$tmp/last.log" | head -n 20; fi
}
# flags.mk, read after the Makefile: a target that prints the MAKEFLAGS its recipes see.
printf 'make-check-flags:\n\t@echo "flags: $$MAKEFLAGS"\n' > "$tmp/flags.mk"
# outer.mk: a parent make that runs the Makefile nested, as `make test` runs tests/all.sh's stages.
printf 'outer:\n\t+@$(MAKE) --no-print-directory -C %s -f Makefile -f %s make-check-flags\n' "$root" "$tmp/flags.mk" \
  > "$tmp/outer.mk"
unset MAKEFLAGS MAKELEVEL MFLAGS

nested() {
  local out
  out=$(env -u MAKELEVEL make -j2 --no-print-directory -f "$tmp/outer.mk" 2>&1) || { echo "$out"; return 1; }
  echo "$out"
  ! grep -q 'warning' <<<"$out" && grep -q 'flags: .*-j2.*jobserver' <<<"$out"
}
check "a nested make shares the parent's jobserver (-j2 passes through), without a warning" nested

top_default() {
  local out
  out=$(cd "$root" && env -u MAKELEVEL make --no-print-directory -f Makefile -f "$tmp/flags.mk" make-check-flags 2>&1)
  echo "$out"
  grep -q -- "flags: .*-j$(nproc)" <<<"$out" && ! grep -q warning <<<"$out"
}
check "a top-level make without -j runs one job per core (-j$(nproc))" top_default

top_given() {
  local out
  out=$(cd "$root" && env -u MAKELEVEL make -j1 --no-print-directory -f Makefile -f "$tmp/flags.mk" make-check-flags 2>&1)
  echo "$out"
  grep -q -- 'flags: .*-j1' <<<"$out" && ! grep -q warning <<<"$out"
}
check "a -j on the command line wins over the default" top_given

echo "make: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
