/* tests/test_step.c -- the technique one instance at a time: --instances N draws the patches of the first N mesh
 * triangles (the instanced draw's count, SetStreamSourceFreq(0, INDEXEDDATA | N)); the three paths agree on it,
 * N = 0 and N >= the triangle count are the whole mesh, each added instance only adds pixels over the background
 * (a convex mesh), and --lod refuses it.  The viewer's playback (the X key) steps through these renders: its
 * frames are the program's files with --instances 1, 2, ... */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/prog.h"

static char dir[256];

static int setup(void **state)
{
    (void)state;
    return prog_mkdtemp(dir, "step");
}
static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

/* Render "cube ARGS" into dir/name (PNG); the exit code. */
static int render(const char *name, const char *args)
{
    char path[512];
    const char *err;
    return prog_run(dir, &err, "", "cube --size 96x96 --level 3 --cull none -q %s -o %s", args,
                    prog_path(dir, name, path, sizeof path));
}

static bool same(const char *a, const char *b)
{
    char pa[512], pb[512];
    return prog_same_pixels(prog_path(dir, a, pa, sizeof pa), prog_path(dir, b, pb, sizeof pb));
}

/* The three paths draw the same first N patches; 0 and >= 12 are the whole cube; 5 is neither 4 nor all. */
static void test_instances(void **state)
{
    (void)state;
    const char *n_patch = "--patch npatch --normals linear";
    char args[256];
    for (int n = 1; n <= 12; n += 5) {
        snprintf(args, sizeof args, "%s --instances %d", n_patch, n);
        assert_int_equal(render("i.png", args), 0);
        snprintf(args, sizeof args, "%s --instances %d --path cpu", n_patch, n);
        assert_int_equal(render("c.png", args), 0);
        snprintf(args, sizeof args, "%s --instances %d --path npatch-mode", n_patch, n);
        assert_int_equal(render("m.png", args), 0);
        assert_true(same("i.png", "c.png"));
        assert_true(same("i.png", "m.png"));
    }
    assert_int_equal(render("all.png", ""), 0);
    assert_int_equal(render("zero.png", "--instances 0"), 0);
    assert_int_equal(render("many.png", "--instances 99"), 0);
    assert_int_equal(render("five.png", "--instances 5"), 0);
    assert_int_equal(render("four.png", "--instances 4"), 0);
    assert_true(same("all.png", "zero.png"));
    assert_true(same("all.png", "many.png"));
    assert_false(same("all.png", "five.png"));
    assert_false(same("four.png", "five.png"));
    const char *err;
    char path[512];
    assert_int_equal(prog_run(dir, &err, "", "cube --instances 3 --lod screen -o %s", prog_path(dir, "l.png", path, sizeof path)), 2);
    assert_non_null(strstr(err, "--instances"));
    assert_false(prog_exists(dir, "l.png"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_instances),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
