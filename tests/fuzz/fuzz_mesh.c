/* tests/fuzz/fuzz_mesh.c -- libFuzzer harness: arbitrary bytes as raw mesh arrays (counts, floats, indices;
 * layout in fuzz_targets.c) into mesh_create, then validation, welding, adjacency, instances, tessellation and
 * a 32x32 render with the patch, level, grid, path, fill and camera the bytes choose.  Every pixel of the
 * render must be finite and in range. */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz_targets.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* One input; an invariant broken aborts (libFuzzer keeps the input). */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char why[1024];
    if (fuzz_mesh_input(data, size, why, sizeof why) != 0) {
        fprintf(stderr, "fuzz_mesh: invariant broken: %s\n", why);
        abort();
    }
    return 0;
}
