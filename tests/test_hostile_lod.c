/* tests/test_hostile_lod.c -- hostile input, round 3, family 3: levels of detail and D3D9's adaptive mode fed values
 * at and beyond their edges, on meshes whose coordinates make the arithmetic overflow.  Each case is in
 * docs/robustness.md ("Round 3: levels of detail and D3D9's adaptive mode") with what happens.
 *
 * The option ranges themselves (--lod-target 0.25..4096, --min-level / --max-level 1..64, four finite numbers for
 * --d3d9-adaptive) are refused at their ends and with junk by tests/test_option_edges.c; min > max, --export-obj
 * closed and watertight by tests/test_adaptive_cracks.c; the pattern pool and open meshes by
 * tests/test_lod_edges.c.  This file takes the values the parser lets through and the run must survive: a
 * depth (dot(V, Mdm)) that overflows to +-inf or becomes NaN (inf - inf), cameras at the ends of their ranges with
 * the finest screen target, and --stats json of every such run.  Runs build/instess or $INSTESS_BIN. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

char *realpath(const char *path, char *resolved);   /* POSIX; glibc declares it only with _DEFAULT_SOURCE */

#include "util/prog.h"
#include "../core/core.h"
#include "../image/image.h"

static char dir[256];

static int setup(void **state)
{
    (void)state;
    return prog_mkdtemp(dir, "hlod");
}

static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

/* Run `instess ARGS` in dir (cd there) with stdout into dir/s.json and stderr into *err; the exit code. */
static int run(const char **err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int run(const char **err, const char *fmt, ...)
{
    static char errbuf[16384];
    va_list ap;
    va_start(ap, fmt);
    int rc = prog_vrun_in(dir, "timeout -s KILL 300", NULL, ">s.json 2>err.txt", fmt, ap);
    va_end(ap);
    prog_read_text(dir, "err.txt", errbuf, sizeof errbuf);
    *err = errbuf;
    return rc;
}

/* Whether every value of dir/name (an OpenEXR file) is finite, but for the depth channel, whose background is
 * +inf by design (no surface there): finite or +inf.  Prints the first bad value. */
static bool exr_values_sound(const char *name)
{
    char p[600], err[512];
    is_image img;
    if (image_read(&img, prog_path(dir, name, p, sizeof p), err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return false;
    }
    int depth = image_channel_index(&img, "depth");
    bool ok = true;
    size_t n = (size_t)img.width * (size_t)img.height;
    for (size_t k = 0; k < n * (size_t)img.channels && ok; k++) {
        float v = img.data[k];
        int c = (int)(k % (size_t)img.channels);
        ok = isfinite(v) || (c == depth && v == INFINITY);
        if (!ok) fprintf(stderr, "%s: pixel %zu channel %s is %g\n", name, k / (size_t)img.channels,
                         img.channel_names[c], (double)v);
    }
    image_free(&img);
    return ok;
}

/* Whether dir/name holds one JSON object that Python's json module reads, with only finite numbers (json.load
 * takes NaN and Infinity unless told not to). */
static bool json_sound(const char *name)
{
    char p[600], cmd[1400];
    snprintf(cmd, sizeof cmd, "python3 -c 'import json,sys; json.load(open(sys.argv[1]), parse_constant=lambda c: "
             "sys.exit(\"not a number: \" + c))' '%s'", prog_path(dir, name, p, sizeof p));
    return system(cmd) == 0;
}

/* A tetrahedron with coordinates of +-1000 (x * 1e38 overflows float) into dir/big.obj. */
static void write_big_tetrahedron(void)
{
    assert_true(prog_write_text(dir, "big.obj", "v -1000 -1000 -1000\nv 1000 -1000 -1000\nv 0 1000 -1000\n"
                                                "v 0 0 1000\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"));
}

/* D3D9's adaptive mode with Mdm vectors the parser takes (four finite floats) whose dot product with the big
 * tetrahedron's vertices overflows: +inf, -inf, and NaN (1000 * 1e38 - 1000 * 1e38 = inf - inf).  The rule
 * (core_adaptive_edge_level): NaN and negative levels are MAX, then at least MIN; every run exits 0 with sound
 * values and --stats json, and NaN depths give the image of the non-adaptive mode at --level. */
static void test_adaptive_overflowing_depths(void **state)
{
    (void)state;
    const char *err;
    write_big_tetrahedron();
    const char *base = "--mesh big.obj --patch npatch --path npatch-mode --size 48x48 -q --level 6";
    static const char *const mdm[] = {
        "1e38,-1e38,0,0",         /* vertex 1: -inf + inf = NaN; vertex 2: inf + inf */
        "1e38,1e38,1e38,1e38",    /* +inf and -inf by vertex */
        "-1e38,-1e38,-1e38,-1e38", "3e38,-3e38,3e38,-3e38", /* every sum an overflow, NaN for some */
        "1e-38,1e-38,1e-38,1e-45", /* depths of denormals: levels beyond every MAX */
        "0,0,0,-0",               /* a depth of -0: -inf */
    };
    for (size_t k = 0; k < sizeof mdm / sizeof mdm[0]; k++) {
        int rc = run(&err, "%s --d3d9-adaptive %s --aov normal,depth --stats json -o ad.exr", base, mdm[k]);
        if (rc != 0) fail_msg("--d3d9-adaptive %s: exit %d: %s", mdm[k], rc, err);
        assert_true(exr_values_sound("ad.exr"));
        assert_true(json_sound("s.json"));
    }
    /* every depth NaN (each vertex's x and y terms overflow with opposite signs): the mode at MAX = --level */
    assert_true(prog_write_text(dir, "nan.obj", "v 1000 1000 0\nv 2000 1000 0\nv 1000 2000 0\nv 1500 1500 1000\n"
                                                "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"));
    assert_int_equal(run(&err, "--mesh nan.obj --patch npatch --path npatch-mode --size 48x48 -q --level 6 "
                         "-o nan-plain.png"), 0);
    assert_int_equal(run(&err, "--mesh nan.obj --patch npatch --path npatch-mode --size 48x48 -q --level 6 "
                         "--d3d9-adaptive 1e38,-1e38,0,0 -o nan-ad.png"), 0);
    char a[600], b[600];
    assert_true(prog_same_pixels(prog_path(dir, "nan-ad.png", a, sizeof a), prog_path(dir, "nan-plain.png", b,
                                                                                         sizeof b)));
}

/* --lod screen at its finest target (0.25 pixels) with --max-level 64, the camera at the ends of its ranges
 * (--distance 1.01 and 1000, --fov 1 and 170): each run renders with sound values and --stats json, or stops at
 * once on the memory budget with a message naming it -- never a crash, a hang or NaN. */
static void test_lod_extreme_cameras(void **state)
{
    (void)state;
    const char *err;
    static const char *const cams[] = {"--distance 1.01 --fov 170", "--distance 1.01 --fov 1",
                                       "--distance 1000 --fov 1", "--distance 1000 --fov 170",
                                       "--distance 1.01 --fov 1 --yaw 1000000 --pitch -1000000"};
    static const char *const modes[] = {"--lod screen --lod-target 0.25", "--lod distance --silhouette"};
    for (size_t k = 0; k < sizeof cams / sizeof cams[0]; k++)
        for (size_t m = 0; m < sizeof modes / sizeof modes[0]; m++) {
            int rc = run(&err, "--mesh sphere --patch pn-aen %s %s --max-level 64 --size 64x64 -q --max-memory 256 "
                         "--aov normal,depth --stats json -o cam.exr", modes[m], cams[k]);
            if (rc == 1 && strstr(err, "more than the memory budget of 256 MiB")) {
                assert_false(prog_exists(dir, "cam.exr"));
                continue;
            }
            if (rc != 0) fail_msg("%s %s: exit %d: %s", modes[m], cams[k], rc, err);
            assert_true(exr_values_sound("cam.exr"));
            assert_true(json_sound("s.json"));
            char p[600];
            remove(prog_path(dir, "cam.exr", p, sizeof p));
        }
}

/* Levels at the ends of their ranges together: --min-level = --max-level = 64 (every edge at 64), 1 and 1, and
 * --lod distance on the tetrahedron whose coordinates are 1000: exit 0, sound values and --stats json. */
static void test_lod_level_ends(void **state)
{
    (void)state;
    const char *err;
    write_big_tetrahedron();
    static const char *const args[] = {
        "--mesh icosahedron --lod screen --min-level 64 --max-level 64",
        "--mesh icosahedron --lod distance --min-level 1 --max-level 1",
        "--mesh big.obj --lod distance --max-level 64 --silhouette",
        "--mesh big.obj --lod screen --lod-target 4096 --max-level 64",
    };
    for (size_t k = 0; k < sizeof args / sizeof args[0]; k++) {
        int rc = run(&err, "%s --size 48x48 -q --aov normal,depth --stats json -o lv.exr", args[k]);
        if (rc != 0) fail_msg("%s: exit %d: %s", args[k], rc, err);
        assert_true(exr_values_sound("lv.exr"));
        assert_true(json_sound("s.json"));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_adaptive_overflowing_depths),
        cmocka_unit_test(test_lod_extreme_cameras),
        cmocka_unit_test(test_lod_level_ends),
    };
    return cmocka_run_group_tests_name("hostile_lod", tests, setup, teardown);
}
