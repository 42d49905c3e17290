#!/usr/bin/env bash
# tests/valgrind.sh BIN -- run the renderer on a few scenes, and compare on PNGs, under valgrind (memcheck): no
# errors, no definite leaks, and the same files as the same run without valgrind.  BIN is the valgrind build of
# instess (tests/valgrind/codec_raw.c: no OpenImageIO in the process; PNG through libpng as in the program).  Ends with "valgrind: N passed, N failed".
set -u
bin=${1:-build/tests/valgrind/instess}
out=$(mktemp -d /tmp/instess-vg-XXXXXX)
trap 'rm -rf "$out"' EXIT
passed=0; failed=0
fail() { failed=$((failed + 1)); echo "FAIL valgrind $1"; }

# The stage must really run: valgrind present, the binary built, and no OpenImageIO loaded into it.
if ! command -v valgrind >/dev/null 2>&1 || [ ! -x "$bin" ]; then
  echo "FAIL valgrind: valgrind or $bin is missing"; echo "valgrind: 0 passed, 1 failed"; exit 1
fi
if ldd "$bin" | grep -q -E 'OpenImageIO|libhwy'; then
  echo "FAIL valgrind: $bin loads OpenImageIO"; echo "valgrind: 0 passed, 1 failed"; exit 1
fi

# run NAME EXPECTED_EXIT ARGS...: memcheck's own error exit code is 99.  Every output path named in ARGS is
# written under $out/vg/; the same command then runs without valgrind into $out/native/ and every file must be
# the same bytes.
run() {
  local name=$1 want=$2; shift 2
  mkdir -p "$out/vg" "$out/native"
  local vg_args=("${@//@/$out/vg/}") nat_args=("${@//@/$out/native/}")
  valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
       --show-leak-kinds=definite "$bin" "${vg_args[@]}" >"$out/$name.log" 2>&1
  local rc=$?
  if [ "$rc" -ne "$want" ]; then
    fail "$name (exit $rc, wanted $want; log below)"; sed 's/^/    /' "$out/$name.log" | head -n 40; return
  fi
  "$bin" "${nat_args[@]}" >/dev/null 2>&1
  local diffs
  diffs=$(diff -r "$out/vg" "$out/native" 2>&1)
  if [ -n "$diffs" ]; then fail "$name (files differ from the run without valgrind: $diffs)"; return; fi
  passed=$((passed + 1)); echo "ok   valgrind $name"
  rm -rf "$out/vg" "$out/native"
}
run flat-cube   0 --mesh cube --patch flat --level 3 --size 64x64 -q -o @a.png
run smooth-tet  0 --mesh tetrahedron --patch smooth --level 6 --size 64x48 --fill solid+wire -q -o @b.png
run npatch-mode 0 --mesh icosahedron --patch npatch --path npatch-mode --normals quadratic --level 4 --size 64x64 -q -o @c.png
run cpu-path    0 --mesh sphere --patch npatch --path cpu --level 3 --size 64x64 --msaa 1 -q -o @d.png
run pn-aen-aov  0 --mesh cylinder --patch pn-aen --level 4 --size 48x48 --msaa 1 --aov normal,bary,instance,gregory \
                   -q -o @e.exr --export-obj @e.obj
run pg-grid     0 --mesh octahedron --patch phong --grid pg-fractional-odd --level 3.5 --size 64x64 -q -o @f.png
run obj-import  0 --mesh tests/data/meshes/box.obj --patch smooth --normals real --level 4 --size 48x48 -q -o @g.png
run bad-mesh    1 --mesh "$out/missing.obj" -q -o @h.png   # an input error: exit 1, no valgrind error, no file
# compare (image_compare in C) on PNGs read through libpng; a difference writes its diff image as PNG
g=tests/golden
run compare-same 0 compare $g/batch-cube-npatch-linear.png $g/batch-cube-npatch-linear.png
run compare-diff 1 compare $g/batch-cube-npatch-linear.png $g/batch-cube-npatch-quadratic.png --diff @d.png
if [ -n "$(ls -A "$out" | grep -v '\.log$')" ]; then fail "outputs left behind: $(ls -A "$out")"; fi
echo "valgrind: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
