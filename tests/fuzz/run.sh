#!/usr/bin/env bash
# tests/fuzz/run.sh SECONDS NAME... -- run each libFuzzer harness build-fuzz/fuzz/fuzz_NAME for SECONDS seconds,
# one at a time, under nice -n 19 (the machine is shared), starting from the seeds in tests/fuzz/corpus/NAME
# (copied, so the repository's corpus stays small) plus tests/fuzz/regressions/NAME/.  -fork=1 with
# -ignore_crashes/-ignore_timeouts/-ignore_ooms keeps one fuzzing process going past a crash; every crash,
# timeout or OOM input is saved in build-fuzz/artifacts/NAME/.  Prints runs, seconds and artifacts per harness.
#
# The import harness runs assimp in this process (for coverage), so assimp's own crashes, hangs and memory
# blow-ups become artifacts too.  Each new one is classified: replayed alone by the harness (5 s limit), its
# report's first frame outside the C library and the sanitizer runtime tells whether the finding is inside
# assimp (libassimp); replayed by fuzz_replay through the program's forked import child, it must become an error
# naming the input.  Both together: "contained" (reported, not a failure).  Anything else -- a finding in
# instess's code, in the mesh harness, or one the child does not contain -- is a failure: exit 1.
set -u
secs=${1:-60}; shift
fb=${FUZZ_B:-build-fuzz}
status=0

# Where the crash of a sanitizer / libFuzzer report (on stdin) happened: its first stack frame that is either in
# assimp (the library's module, or its functions and sources when symbolized) or in instess's own code (a file
# of core/, raster/, vs/, meshes/, cli/ or tests/); frames of the C library, the sanitizer runtime and libFuzzer
# in between are skipped.  "assimp", the instess frame, or "no stack".
first_frame() {
  sed -n '/ERROR: /,$p' | grep -E '^ *#[0-9]+ 0x' |
    grep -E 'libassimp|Assimp::|/code/[A-Za-z]+/|(^|[ /])(core|raster|vs|meshes|cli|tests)/[A-Za-z0-9_/]+\.(c|cpp|h):' |
    head -n1 | { read -r f || f=""; case "$f" in *libassimp*|*Assimp::*|*/code/*) echo assimp ;; "") echo "no stack" ;;
                                                  *) echo "$f" ;; esac; }
}

# Classify the new artifacts of the import harness; prints one line each; returns 1 if any is not contained.
classify_import() {
  local bin=$1 art=$2 list=$3 log=$4 rc=0 a kind where replay
  while read -r a; do
    [ -n "$a" ] || continue
    kind=${a##*/}; kind=${kind%%-*}
    if [ "$kind" = slow ]; then   # libFuzzer's -report_slow_units: an input that took over 10 s, not a crash
      echo "  slow (not a failure; hangs are 'timeout' artifacts): $art/$a"
      continue
    fi
    where=$(ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
            nice -n 19 "$bin" -runs=1 -timeout=5 -rss_limit_mb=2048 "$art/$a" 2>&1 | first_frame)
    # not reproduced alone: the report the campaign's log holds for it (the inner job's log before its name)
    [ "$where" = "no stack" ] && where=$(awk -v a="$a" '/log from the inner process/ { buf = "" } { buf = buf $0 "\n" }
                                             index($0, a) { printf "%s", buf; exit }' "$log" | first_frame)
    replay=$(ASAN_OPTIONS=detect_leaks=0 nice -n 19 "$fb/fuzz/fuzz_replay" "$art/$a" 2>&1 |
             grep -E '^fuzz_replay: ' | tail -n1)
    if [ "$where" = assimp ] && [ "${replay#fuzz_replay: contained: }" != "$replay" ]; then
      echo "  contained: $kind inside assimp, $art/$a; the import child: ${replay#fuzz_replay: contained: }"
    else
      echo "  FINDING: $kind in $where, $art/$a; replay through the import child: ${replay:-no result}"
      rc=1
    fi
  done <"$list"
  return $rc
}

for name in "$@"; do
  bin="$fb/fuzz/fuzz_$name"
  corpus="$fb/corpus/$name"; art="$fb/artifacts/$name"; log="$fb/fuzz_$name.log"
  mkdir -p "$corpus" "$art"
  cp -n tests/fuzz/corpus/"$name"/* "$corpus"/ 2>/dev/null
  cp -n tests/fuzz/regressions/"$name"/* "$corpus"/ 2>/dev/null   # not import-assimp/: known assimp crashes
  ls "$art" | sort >"$fb/artifacts-before-$name"
  start=$(date +%s)
  # assimp 5.2.5 leaks on many malformed PLY files (third-party; in the program it runs in a child process that
  # exits): the import harness does not check leaks; the mesh harness, make sanitize and valgrind check ours.
  leaks=1; [ "$name" = import ] && leaks=0
  ASAN_OPTIONS=detect_leaks=$leaks:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
  LSAN_OPTIONS=suppressions=tests/lsan.supp \
    nice -n 19 "$bin" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 -max_total_time="$secs" \
      -timeout=20 -rss_limit_mb=2048 -max_len=4096 -dict=tests/fuzz/mesh.dict -artifact_prefix="$art/" \
      "$corpus" >"$log" 2>&1
  end=$(date +%s)
  runs=$(grep -Eo '#[0-9]+' "$log" | tail -n1 | tr -d '#')
  ls "$art" | sort | comm -13 "$fb/artifacts-before-$name" - >"$fb/artifacts-new-$name"
  new=$(wc -l <"$fb/artifacts-new-$name")
  echo "fuzz_$name: $((end - start)) s, ${runs:-0} runs, corpus $(ls "$corpus" | wc -l), artifacts $(ls "$art" | wc -l) (new $new); log $log"
  [ "$new" -eq 0 ] && continue
  if [ "$name" = import ]; then
    classify_import "$bin" "$art" "$fb/artifacts-new-$name" "$log" || status=1
  else
    sed "s|^|  FINDING: $art/|" "$fb/artifacts-new-$name" | sed "s|FINDING: \(.*/slow-unit-\)|slow (not a failure): \1|"
    grep -qv '^slow-unit-' "$fb/artifacts-new-$name" && status=1
  fi
done
[ $status -eq 0 ] && echo "fuzz: no finding in instess (findings inside assimp, if any, were contained by the import child)"
exit $status
