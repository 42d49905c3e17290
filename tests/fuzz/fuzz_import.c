/* tests/fuzz/fuzz_import.c -- libFuzzer harness: arbitrary bytes as a mesh file through assimp (in this
 * process, so that libFuzzer sees the coverage of our import code and its interceptors see assimp's string
 * compares), then validation, welding, adjacency, instances and a 32x32 render (fuzz_targets.c).
 *
 * assimp is a third-party library: a crash or a hang inside it stops this in-process harness, and is kept as an
 * artifact, but it is not an instess bug as long as the program's path survives it.  tests/fuzz/run.sh runs
 * this harness with -fork=1 -ignore_crashes=1 -ignore_timeouts=1 so the campaign goes on past them; every
 * artifact is then replayed through the forked-child import of meshes/import.c (fuzz_import_input with
 * sandboxed = true, tests/test_fuzz_regressions.c), which must turn it into an error naming the input. */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz_targets.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* One input; an invariant broken in our code aborts (libFuzzer keeps the input). */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char why[1024];
    if (fuzz_import_input(data, size, false, 0, why, sizeof why) != 0) {
        fprintf(stderr, "fuzz_import: invariant broken: %s\n", why);
        abort();
    }
    return 0;
}
