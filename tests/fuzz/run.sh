#!/usr/bin/env bash
# tests/fuzz/run.sh SECONDS NAME... -- run each libFuzzer harness build-fuzz/fuzz/fuzz_NAME for SECONDS seconds,
# one at a time, under nice -n 19 (the machine is shared), starting from the seeds in tests/fuzz/corpus/NAME
# (copied, so the repository's corpus stays small) plus tests/fuzz/regressions/NAME/.  -fork=1 with
# -ignore_crashes/-ignore_timeouts/-ignore_ooms keeps one fuzzing process going past a crash; every crash,
# timeout or OOM input is saved in build-fuzz/artifacts/NAME/.  Prints runs, seconds and artifacts per harness
# and exits non-zero when a harness left a new artifact.
set -u
secs=${1:-60}; shift
fb=${FUZZ_B:-build-fuzz}
status=0
for name in "$@"; do
  bin="$fb/fuzz/fuzz_$name"
  corpus="$fb/corpus/$name"; art="$fb/artifacts/$name"; log="$fb/fuzz_$name.log"
  mkdir -p "$corpus" "$art"
  cp -n tests/fuzz/corpus/"$name"/* "$corpus"/ 2>/dev/null
  cp -n tests/fuzz/regressions/"$name"/* "$corpus"/ 2>/dev/null   # not import-assimp/: known assimp crashes
  before=$(ls "$art" | wc -l)
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
  after=$(ls "$art" | wc -l)
  echo "fuzz_$name: $((end - start)) s, ${runs:-0} runs, corpus $(ls "$corpus" | wc -l), artifacts $after (new $((after - before))); log $log"
  [ "$after" -gt "$before" ] && status=1
done
exit $status
