#!/usr/bin/env bash
# tests/faults.sh BIN -- allocation failure, everywhere (`make faults`, a stage of make test).  BIN is the
# fault-injection build of the program (tests/fault/fault.c: INSTESS_FAULT_AT=N fails its N-th allocation).
# Five operations -- two renders (a built-in mesh to a PNG; PN-AEN with per-edge levels and a wireframe), a compare
# of two identical images, an import of an OBJ file rendered to an EXR with an AOV, and the same file on the CPU
# path with the OBJ export -- are run once without a fault, which counts their allocations, then once for every N
# from 1 to that count (SQLite's transient malloc test).  A run whose fault fired must end
#  - in the operation's error: its exit code (1; compare: 4, an image that cannot be read), a message on stderr
#    starting "instess: ", no output file and no temporary left, or
#  - in success, with the output byte-identical to the run without a fault (a fallback that recovered);
# and never in a sanitizer report (AddressSanitizer, LeakSanitizer, UndefinedBehaviorSanitizer), an assertion,
# a signal, or the wrong answer (compare saying "different").  Prints one line per failing run, one summary
# line per operation, then "faults: N passed, M failed" (N and M count runs).  Exit status 0 when none failed.
# The runs go FAULT_JOBS at a time (default: the cores).
set -u
bin=$(realpath "$1") || exit 2
jobs=${FAULT_JOBS:-$(nproc)}
work=$(mktemp -d "${TMPDIR:-/tmp}/instess-faults-XXXXXX") || exit 2
trap 'rm -rf "$work"' EXIT
export OMP_WAIT_POLICY=passive

# The inputs: two identical small PNGs for compare, a small OBJ for the import.
printf 'v 0 0 0\nv 0 1 0\nv 1 0 0\nv 0 0 1\nvn 0 0 -1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n' > "$work/tet.obj"
"$bin" -q --threads 1 --size 24x20 --level 2 -o "$work/a.png" || { echo "faults: cannot make the inputs"; exit 1; }
cp "$work/a.png" "$work/b.png"

# The operations: name, output files (relative to the run's folder, comma-separated; "-" for none), exit code of
# an error, arguments.
ops=(
  "render|out.png|1|-q --threads 1 --size 40x32 --level 3 --mesh tetrahedron -o out.png"
  "render-lod|out.png|1|-q --threads 1 --size 40x32 --mesh icosahedron --patch pn-aen --lod screen --fill solid+wire -o out.png"
  "compare|-|4|compare $work/a.png $work/b.png"
  "import|out.exr|1|-q --threads 1 --size 32x24 --level 2 --aov normal --mesh $work/tet.obj -o out.exr"
  "export|out.png,out.obj|1|-q --threads 1 --size 32x24 --level 2 --mesh $work/tet.obj --path cpu --patch npatch --export-obj out.obj -o out.png"
)

# same_outputs DIR NAME OUTS: whether every output of the run in DIR equals the run without a fault.
same_outputs() {
  local o
  for o in ${3//,/ }; do cmp -s "$1/$o" "$work/$2.ref.$o" || return 1; done
}
# any_output DIR OUTS: whether any output (or a temporary) exists in DIR.
any_output() {
  local o
  for o in ${2//,/ }; do [ -e "$1/$o" ] && return 0; done
  ls -A "$1" | grep -q '\.tmp$'
}
export -f same_outputs any_output

# run_one OP N: run operation OP with its N-th allocation failing in folder $work/OP-N; prints "ok" or the reason
# (with the run's stderr: its message, and the stack of the allocation that failed).
run_one() {
  local op=$1 n=$2 name out code args dir rc fired err
  IFS='|' read -r name out code args <<< "$op"
  dir="$work/$name-$n"
  mkdir -p "$dir" && cd "$dir" || { echo "$name N=$n: no folder"; return; }
  # shellcheck disable=SC2086
  INSTESS_FAULT_AT=$n INSTESS_FAULT_REPORT="$dir/.report" INSTESS_FAULT_TRACE=1 timeout 120 "$bin" $args \
    >"$dir/.stdout" 2>"$dir/.stderr"
  rc=$?
  fired=0
  [ -e "$dir/.report.fired" ] && fired=1   # in this process or in a forked import child
  err=$(head -c 8000 "$dir/.stderr")
  show() { echo "$err" | head -n "$1" | sed 's/^/    /'; }
  if grep -qE 'ERROR: (Address|Leak)Sanitizer|SUMMARY: [A-Za-z]*Sanitizer|runtime error:|Assertion|Segmentation' \
       "$dir/.stderr" || [ "$rc" -gt 128 ]; then
    echo "$name N=$n: exit $rc with a sanitizer report, an assertion or a signal:"; show 40
  elif [ "$rc" -eq 0 ]; then
    if [ "$out" != "-" ] && ! same_outputs "$dir" "$name" "$out"; then
      echo "$name N=$n: exit 0 (fault fired: $fired) but $out differs from the run without a fault:"; show 24
    elif [ "$out" = "-" ] && ! grep -q 'identical' "$dir/.stdout"; then
      echo "$name N=$n: exit 0 without the verdict \"identical\" on stdout"; show 12
    else
      echo ok
    fi
  elif [ "$rc" -eq "$code" ]; then
    if [ "$fired" != 1 ]; then
      echo "$name N=$n: exit $rc although no allocation failed:"; show 8
    elif ! grep -qE '^instess( compare)?: ' "$dir/.stderr"; then
      echo "$name N=$n: exit $rc without a message:"; show 8
    elif [ "$out" != "-" ] && any_output "$dir" "$out"; then
      echo "$name N=$n: exit $rc but an output or a temporary was left: $(ls -A "$dir" | grep -v '^\.')"
    else
      echo ok
    fi
  else
    echo "$name N=$n: exit $rc (expected 0 or $code):"; show 24
  fi
  rm -rf "$dir"
}
export -f run_one
export work bin

passed=0; failed=0
for op in "${ops[@]}"; do
  IFS='|' read -r name out code args <<< "$op"
  dir="$work/$name-0"
  mkdir -p "$dir"
  # shellcheck disable=SC2086
  (cd "$dir" && INSTESS_FAULT_REPORT="$dir/.report" "$bin" $args >"$dir/.stdout" 2>"$dir/.stderr")
  rc=$?
  read -r total _ < "$dir/.report" 2>/dev/null || total=0
  if [ "$rc" -ne 0 ] || [ "$total" -eq 0 ]; then
    echo "$name: the run without a fault failed (exit $rc, $total allocations):"; sed 's/^/    /' "$dir/.stderr" | head
    failed=$((failed + 1)); continue
  fi
  for o in ${out//,/ }; do [ "$o" != "-" ] && cp "$dir/$o" "$work/$name.ref.$o"; done
  log="$work/$name.log"
  seq 1 "$total" | xargs -P "$jobs" -I{} bash -c 'run_one "$0" {}' "$op" > "$log"
  p=$(grep -c '^ok$' "$log"); f=$(grep -c '^[a-z]* N=' "$log")
  grep -v '^ok$' "$log"
  echo "$name: $total allocations, each failed once: $p runs clean, $f not"
  passed=$((passed + p)); failed=$((failed + f))
done
echo "faults: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
