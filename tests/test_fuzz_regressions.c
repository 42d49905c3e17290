/* tests/test_fuzz_regressions.c -- replay the fuzzers' inputs without libFuzzer , through the
 * same code paths as the harnesses (tests/fuzz/fuzz_targets.c, compiled into this test):
 *  - tests/fuzz/regressions/mesh/      raw mesh arrays that once broke an invariant: fuzz_mesh_input;
 *  - tests/fuzz/regressions/import/    files that once crashed our import code: fuzz_import_input, in this
 *                                       process and through the forked child;
 *  - tests/fuzz/regressions/import-assimp/  files that crash or hang assimp itself (third-party): only through
 *                                       the forked child of meshes/import.c, which must turn each into an error
 *                                       naming the input (in this process they would take the test down);
 *  - the seed corpora tests/fuzz/corpus/mesh/ and import/: valid meshes, which must load and render.
 * Each input must keep every invariant of the harness (see fuzz_targets.h). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz/fuzz_targets.c"
#include "util/prog.h"

/* How to replay a folder's inputs. */
typedef enum { REPLAY_MESH, REPLAY_IMPORT_BOTH, REPLAY_IMPORT_CHILD, REPLAY_IMPORT_LOADS } replay_kind;


/* Replay one input; fails the test with the broken invariant. */
static void replay_one(const char *path, replay_kind kind)
{
    size_t n = 0;
    uint8_t *d = prog_slurp(path, &n);
    assert_non_null(d);
    char why[1024] = "";
    int rc = 0;
    if (kind == REPLAY_MESH) rc = fuzz_mesh_input(d, n, why, sizeof why);
    if (kind == REPLAY_IMPORT_BOTH || kind == REPLAY_IMPORT_LOADS) rc = fuzz_import_input(d, n, false, 0, why, sizeof why);
    if (rc == 0 && kind != REPLAY_MESH) rc = fuzz_import_input(d, n, true, 2000, why, sizeof why);
    if (rc == 0 && kind == REPLAY_IMPORT_LOADS) {
        /* a seed is a valid mesh: it must load */
        is_mesh m;
        char err[1024];
        const char *hint = fuzz_sniff_format(d, n);
        if (mesh_load_memory(d, n, hint, path, NULL, &m, err, sizeof err) != 0) fail_msg("seed %s: %s", path, err);
        mesh_free(&m);
    }
    free(d);
    if (rc != 0) fail_msg("%s: %s", path, why);
    print_message("  ok %s\n", path);
}

/* Replay every file of folder (sorted); returns how many. */
static int replay_dir(const char *folder, replay_kind kind)
{
    struct dirent **names;
    int n = scandir(folder, &names, NULL, alphasort), count = 0;
    for (int k = 0; k < n; k++) {
        if (names[k]->d_name[0] != '.' && strcmp(names[k]->d_name, "README.md") != 0) {
            char p[1024];
            snprintf(p, sizeof p, "%s/%s", folder, names[k]->d_name);
            replay_one(p, kind);
            count++;
        }
        free(names[k]);
    }
    if (n >= 0) free(names);
    return count;
}

static void test_mesh_regressions(void **state)
{
    (void)state;
    assert_true(replay_dir("tests/fuzz/regressions/mesh", REPLAY_MESH) > 0);
}

static void test_import_regressions(void **state)
{
    (void)state;
    replay_dir("tests/fuzz/regressions/import", REPLAY_IMPORT_BOTH);
}

/* assimp's own crashes and hangs: errors through the child process, never a crash of ours. */
static void test_assimp_crashes_isolated(void **state)
{
    (void)state;
    assert_true(replay_dir("tests/fuzz/regressions/import-assimp", REPLAY_IMPORT_CHILD) > 0);
}

static void test_seed_corpora(void **state)
{
    (void)state;
    assert_true(replay_dir("tests/fuzz/corpus/mesh", REPLAY_MESH) > 0);
    assert_true(replay_dir("tests/fuzz/corpus/import", REPLAY_IMPORT_LOADS) > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mesh_regressions),
        cmocka_unit_test(test_import_regressions),
        cmocka_unit_test(test_assimp_crashes_isolated),
        cmocka_unit_test(test_seed_corpora),
    };
    return cmocka_run_group_tests_name("fuzz_regressions", tests, NULL, NULL);
}
