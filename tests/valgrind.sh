#!/usr/bin/env bash
# tests/valgrind.sh BIN -- run the renderer on a few scenes under valgrind (memcheck): no errors, no definite
# leaks.  Ends with "valgrind: N passed, N failed".
set -u
bin=${1:-build/instess}
out=$(mktemp -d /tmp/instess-vg-XXXXXX)
trap 'rm -rf "$out"' EXIT
passed=0; failed=0
# run NAME EXPECTED_EXIT ARGS...: valgrind's own error exit code is 99.
run() {
  local name=$1 want=$2; shift 2
  valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
       --show-leak-kinds=definite "$bin" "$@" >"$out/$name.log" 2>&1
  local rc=$?
  if [ "$rc" -eq "$want" ]; then
    passed=$((passed + 1)); echo "ok   valgrind $name"
  else
    failed=$((failed + 1)); echo "FAIL valgrind $name (exit $rc, wanted $want; log below)"; sed 's/^/    /' "$out/$name.log" | head -n 40
  fi
}
run flat-cube   0 --mesh cube --patch flat --level 3 --size 64x64 -q -o "$out/a.png"
run smooth-tet  0 --mesh tetrahedron --patch smooth --level 6 --size 64x48 --fill solid+wire -q -o "$out/b.png"
run npatch-mode 0 --mesh icosahedron --patch npatch --path npatch-mode --normals quadratic --level 4 --size 64x64 -q -o "$out/c.png"
run cpu-path    0 --mesh sphere --patch npatch --path cpu --level 3 --size 64x64 --msaa 1 -q -o "$out/d.png"
run pn-aen-aov  0 --mesh cylinder --patch pn-aen --level 4 --size 48x48 --msaa 1 --aov normal,bary,instance,gregory \
                   -q -o "$out/e.exr" --export-obj "$out/e.obj"
run pg-grid     0 --mesh octahedron --patch phong --grid pg-fractional-odd --level 3.5 --size 64x64 -q -o "$out/f.png"
run bad-mesh    1 --mesh "$out/missing.obj" -q -o "$out/g.png"   # an input error: exit 1, no valgrind error
echo "valgrind: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
