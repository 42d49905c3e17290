/* tests/test_cli.c -- the `instess` program as a user runs it: exit codes (0 / 1 input error / 2 usage error),
 * messages naming the input, nothing written on failure, PNG and EXR (channels R, G, B, A, Z and AOVs), OBJ
 * export.  Runs build/instess, or $INSTESS_BIN (the sanitizer build's), which make test builds first. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "util/prog.h"
#include "../core/core.h"

static char dir[256];

/* Run `build/instess ARGS` with stderr captured into *err_out (static buffer); returns the exit code. */
static int run(const char *args, const char **err_out)
{
    static char errbuf[8192];
    char cmd[2400], errfile[300];
    snprintf(errfile, sizeof errfile, "%s/stderr.txt", dir);
    const char *bin = getenv("INSTESS_BIN") ? getenv("INSTESS_BIN") : "build/instess";
    snprintf(cmd, sizeof cmd, "%s %s 2>%s >/dev/null", bin, args, errfile);
    int st = system(cmd);
    FILE *f = fopen(errfile, "r");
    size_t n = f ? fread(errbuf, 1, sizeof errbuf - 1, f) : 0;
    if (f) fclose(f);
    errbuf[n] = 0;
    if (err_out) *err_out = errbuf;
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128;
}

static bool exists(const char *name)
{
    char p[512];
    struct stat s;
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return stat(p, &s) == 0;
}

/* Number of entries in the work directory besides stderr.txt. */
static int entries(void)
{
    char cmd[400];
    snprintf(cmd, sizeof cmd, "test $(ls -A %s | grep -v '^stderr.txt$' | wc -l) -eq 0", dir);
    return system(cmd) == 0 ? 0 : 1;
}

static int setup(void **state)
{
    snprintf(dir, sizeof dir, "/tmp/instess-cli-XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static void test_usage_errors(void **state)
{
    const char *err;
    const char *bad[] = {"--bogus -o X.png", "--level", "--level 0 -o X.png", "--level -3 -o X.png",
                         "--level 1000000 -o X.png", "--size 0x10 -o X.png", "--size 1000000x1000000 -o X.png",
                         "--size 12 -o X.png", "--msaa 3 -o X.png", "--patch curvy -o X.png", "--fill dots -o X.png",
                         "--threads -1 -o X.png", "", "-o X.tiff", "--aov normal -o X.png", "--level 2.5 -o X.png",
                         "--path cpu --patch smooth -o X.png", "--yaw abc -o X.png",
                         "--mesh cube extra -o X.png", "cube extra -o X.png"};
    char args[1024];
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char *x = strstr(bad[k], "X.");
        if (x) snprintf(args, sizeof args, "%.*s%s/%s", (int)(x - bad[k]), bad[k], dir, x);
        else snprintf(args, sizeof args, "%s", bad[k]);
        int rc = run(args, &err);
        if (rc != 2) fprintf(stderr, "args '%s' gave %d: %s\n", args, rc, err);
        assert_int_equal(rc, 2);
        assert_non_null(strstr(err, "instess:"));
        assert_int_equal(entries(), 0);
    }
    assert_int_equal(run("--help", NULL), 0);
    assert_int_equal(run("--version", &err), 0);
}

static void test_input_errors(void **state)
{
    const char *err;
    char args[1024];
    snprintf(args, sizeof args, "--mesh %s/missing.obj -o %s/a.png", dir, dir);
    assert_int_equal(run(args, &err), 1);
    assert_non_null(strstr(err, "missing.obj"));
    assert_false(exists("a.png"));
    /* an unwritable output: a directory in the way */
    snprintf(args, sizeof args, "mkdir -p %s/b.png", dir);
    assert_int_equal(system(args), 0);
    snprintf(args, sizeof args, "--mesh cube --level 2 --size 64x64 -o %s/b.png", dir);
    assert_int_equal(run(args, &err), 1);
    assert_non_null(strstr(err, "b.png"));
    snprintf(args, sizeof args, "rmdir %s/b.png", dir);
    assert_int_equal(system(args), 0);
    /* a previous image survives a failed render */
    snprintf(args, sizeof args, "--mesh cube --level 2 --size 64x64 -q -o %s/keep.png", dir);
    assert_int_equal(run(args, NULL), 0);
    is_image before = {0}, after = {0};
    char p[512], e[256];
    snprintf(p, sizeof p, "%s/keep.png", dir);
    assert_int_equal(image_read(&before, p, e, sizeof e), 0);
    snprintf(args, sizeof args, "--mesh %s/missing.obj -o %s/keep.png", dir, dir);
    assert_int_equal(run(args, NULL), 1);
    assert_int_equal(image_read(&after, p, e, sizeof e), 0);
    assert_memory_equal(before.data, after.data, sizeof(float) * 64 * 64 * 4);
    image_free(&before), image_free(&after);
    snprintf(args, sizeof args, "rm -f %s/keep.png", dir);
    assert_int_equal(system(args), 0);
}

static void test_png_and_exr(void **state)
{
    char args[1400], p[512], e[256];
    snprintf(args, sizeof args, "--mesh cube --patch flat --level 2 --size 80x60 -q -o %s/cube.png", dir);
    assert_int_equal(run(args, NULL), 0);
    snprintf(args, sizeof args,
             "--mesh tetrahedron --patch smooth --level 5 --size 80x60 --msaa 1 --aov normal,bary,instance,gregory "
             "-q -o %s/tet.exr --export-obj %s/tet.obj",
             dir, dir);
    assert_int_equal(run(args, NULL), 0);
    is_image img = {0};
    snprintf(p, sizeof p, "%s/cube.png", dir);
    assert_int_equal(image_read(&img, p, e, sizeof e), 0);
    assert_int_equal(img.width, 80);
    assert_int_equal(img.height, 60);
    assert_int_equal(img.channels, 4);
    image_free(&img);
    snprintf(p, sizeof p, "%s/tet.exr", dir);
    assert_int_equal(image_read(&img, p, e, sizeof e), 0);
    const char *names[] = {"R", "G", "B", "A", "Z", "N.X", "N.Y", "N.Z", "bary.X", "bary.Y", "bary.Z", "instance",
                           "gregory.X", "gregory.Y", "gregory.Z"};
    assert_int_equal(img.channels, 15);
    int at[15]; /* OpenEXR stores channels by name, so find each one (the reader groups layers) */
    for (int c = 0; c < 15; c++) {
        at[c] = -1;
        for (int k = 0; k < img.channels; k++)
            if (strcmp(img.channel_names[k], names[c]) == 0) at[c] = k;
        assert_true(at[c] >= 0);
    }
    /* the centre pixel is on the tetrahedron: depth inside (0, 1), barycentrics sum to 1, a normal */
    const float *px = &img.data[(30 * 80 + 40) * img.channels];
    assert_true(px[at[4]] > 0.0f && px[at[4]] < 1.0f);
    assert_float_equal(px[at[8]] + px[at[9]] + px[at[10]], 1.0f, 1e-3);
    /* unit normals at the vertices, interpolated across each small triangle: length slightly below 1 */
    float len2 = px[at[5]] * px[at[5]] + px[at[6]] * px[at[6]] + px[at[7]] * px[at[7]];
    assert_true(len2 > 0.8f && len2 < 1.001f);
    assert_true(px[at[11]] >= 0.0f && px[at[11]] <= 3.0f && px[at[11]] == (float)(int)px[at[11]]);
    image_free(&img);
    /* OBJ: 4 triangles x 21 grid points, 4 x 25 faces */
    snprintf(args, sizeof args, "test $(grep -c '^v ' %s/tet.obj) -eq 84 && test $(grep -c '^vn ' %s/tet.obj) -eq 84 "
                                "&& test $(grep -c '^f ' %s/tet.obj) -eq 100", dir, dir, dir);
    assert_int_equal(system(args), 0);
}

/* A primitive-generator grid renders its clamped level and says so on stderr, even with -q; a level inside
 * the range says nothing. */
static void test_clamped_level_is_said(void **state)
{
    (void)state;
    const char *err;
    char args[600];
    const struct { const char *grid, *level, *said; } cases[] = {
        {"pg-fractional-odd", "100", "--level 100 is outside the range of --grid pg-fractional-odd; rendering level 63"},
        {"pg-fractional-even", "1", "--level 1 is outside the range of --grid pg-fractional-even; rendering level 2"},
        {"pg-equal", "64.5", "rendering level 64"}};
    for (int k = 0; k < 3; k++) {
        snprintf(args, sizeof args, "--grid %s --level %s --size 16x16 -q -o %s/a.png", cases[k].grid, cases[k].level,
                 dir);
        assert_int_equal(run(args, &err), 0);
        if (!strstr(err, cases[k].said)) fail_msg("%s: stderr was: %s", cases[k].grid, err);
    }
    snprintf(args, sizeof args, "--grid pg-fractional-odd --level 7.5 --size 16x16 -q -o %s/a.png", dir);
    assert_int_equal(run(args, &err), 0);
    assert_string_equal(err, "");
    char p[512];
    snprintf(p, sizeof p, "%s/a.png", dir);
    unlink(p);
}


/* Whether dir/a and dir/b decode to the same pixels. */
static bool same_pixels(const char *a, const char *b)
{
    char pa[512], pb[512];
    snprintf(pa, sizeof pa, "%s/%s", dir, a);
    snprintf(pb, sizeof pb, "%s/%s", dir, b);
    return prog_same_pixels(pa, pb);
}

/* What people expect of a command line: no arguments print the usage (exit 2); the mesh may be positional
 * (the same image as --mesh), but not both; an unknown value lists the valid ones; every subcommand takes
 * --help. */
static void test_command_line_conventions(void **state)
{
    (void)state;
    const char *err;
    assert_int_equal(run("", &err), 2);
    assert_non_null(strstr(err, "usage: instess"));
    char args[600];
    snprintf(args, sizeof args, "tests/data/meshes/box.obj --size 24x24 -q -o %s/pos.png", dir);
    assert_int_equal(run(args, &err), 0);
    snprintf(args, sizeof args, "--mesh tests/data/meshes/box.obj --size 24x24 -q -o %s/opt.png", dir);
    assert_int_equal(run(args, &err), 0);
    assert_true(same_pixels("pos.png", "opt.png"));
    snprintf(args, sizeof args, "--mesh cube tests/data/meshes/box.obj -o %s/two.png", dir);
    assert_int_equal(run(args, &err), 2);
    assert_non_null(strstr(err, "the mesh is given by --mesh"));
    snprintf(args, sizeof args, "--patch curvy -o %s/x.png", dir);
    assert_int_equal(run(args, &err), 2);
    assert_non_null(strstr(err, "one of: flat | npatch | smooth-initial | smooth | phong | pn-aen"));
    snprintf(args, sizeof args, "--normals bent -o %s/x.png", dir);
    assert_int_equal(run(args, &err), 2);
    assert_non_null(strstr(err, "one of: linear | quadratic | real"));
    assert_int_equal(run("smoothness --help", &err), 0);
    assert_int_equal(run("figures --help", &err), 0);
    assert_int_equal(run("--help", &err), 0);
    char p[512];
    const char *names[] = {"pos.png", "opt.png"};
    for (int k = 0; k < 2; k++) snprintf(p, sizeof p, "%s/%s", dir, names[k]), unlink(p);
    assert_false(exists("two.png"));
    assert_false(exists("x.png"));
}

/* The image codec (OpenImageIO) is a module loaded on the first image call: a copy of the program without
 * the module beside it still answers --help and reports usage errors, and a render fails with exit 1 naming
 * the module, writing nothing. */
static void test_codec_loaded_on_demand(void **state)
{
    (void)state;
    const char *bin = getenv("INSTESS_BIN") ? getenv("INSTESS_BIN") : "build/instess";
    char cmd[2400], copy[512], err_path[512];
    snprintf(copy, sizeof copy, "%s/lonely/instess", dir);
    snprintf(cmd, sizeof cmd, "mkdir -p %s/lonely && cp %s %s", dir, bin, copy);
    assert_int_equal(system(cmd), 0);
    snprintf(err_path, sizeof err_path, "%s/lonely/err.txt", dir);
    snprintf(cmd, sizeof cmd, "%s --help >/dev/null 2>%s", copy, err_path);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s --patch curvy -o %s/x.png 2>%s", copy, dir, err_path);
    int st = system(cmd);
    assert_int_equal(WEXITSTATUS(st), 2);
    snprintf(cmd, sizeof cmd, "%s --size 16x16 -q -o %s/x.png 2>%s", copy, dir, err_path);
    st = system(cmd);
    assert_int_equal(WEXITSTATUS(st), 1);
    FILE *f = fopen(err_path, "r");
    char msg[2048] = "";
    size_t n = f ? fread(msg, 1, sizeof msg - 1, f) : 0;
    if (f) fclose(f);
    msg[n] = 0;
    print_message("  without the module: %s", msg);
    assert_non_null(strstr(msg, "cannot load libinstess_codec.so"));
    assert_false(exists("x.png"));
    snprintf(cmd, sizeof cmd, "rm -rf %s/lonely", dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_usage_errors),
        cmocka_unit_test(test_input_errors),
        cmocka_unit_test(test_png_and_exr),
        cmocka_unit_test(test_clamped_level_is_said),
        cmocka_unit_test(test_command_line_conventions),
        cmocka_unit_test(test_codec_loaded_on_demand),
    };
    return cmocka_run_group_tests_name("cli", tests, setup, teardown);
}
