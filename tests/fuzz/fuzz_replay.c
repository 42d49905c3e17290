/* tests/fuzz/fuzz_replay.c -- `build-fuzz/fuzz/fuzz_replay FILE...` (libFuzzer's run-these-files mode): each
 * input through the program's own import path, the forked child of meshes/import.c (fuzz_import_input with
 * sandboxed = true, a 5 s limit), with every invariant of fuzz_targets.h.  tests/fuzz/run.sh uses it on the
 * artifacts of fuzz_import: a crash, hang or memory blow-up inside assimp counts as contained when this replay
 * keeps the invariants (the child turned it into an error naming the input).  Prints one line per input; an
 * input that breaks an invariant aborts (exit non-zero). */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz_targets.h"
#include "../../meshes/meshes.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* One input: the child's message, then the invariants. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char why[1024] = "", err[1024] = "", label[64];
    const char *hint = fuzz_sniff_format(data, size);
    snprintf(label, sizeof label, "fuzz-input.%s", hint);
    is_mesh_options mo = {.import_timeout_ms = 5000};
    is_mesh m;
    int rc = mesh_load_memory(size ? data : NULL, size, hint, label, &mo, &m, err, sizeof err);
    if (rc == 0) mesh_free(&m);
    if (fuzz_import_input(data, size, true, 5000, why, sizeof why) != 0) {
        fprintf(stderr, "fuzz_replay: NOT CONTAINED: %s\n", why);
        abort();
    }
    fprintf(stderr, "fuzz_replay: contained: %s\n", rc == 0 ? "the import child read it as a valid mesh" : err);
    return 0;
}
