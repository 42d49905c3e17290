/* tests/test_option_edges.c -- every numeric option of the option table (cli/run/options.c) at its edges: each
 * end of its range is taken and renders an image without a NaN (an EXR with AOVs, every value finite) and a
 * --stats json that is valid JSON; just past each end, and values that are not plain numbers (empty, NaN,
 * infinities, beyond double, hexadecimal, with spaces, with a decimal comma, followed by letters) are refused
 * with exit 2 and a message that names the option and its valid range, nothing written.  The table below must
 * name every option that takes a value (test_every_option_classified), so that a new option gets its edges here.
 * Runs the program ($INSTESS_BIN or build/instess). */
#define _DEFAULT_SOURCE
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
#include <unistd.h>

#include "util/prog.h"
#include "../cli/run/scene.h"

static char dir[256];

static int setup(void **state)
{
    (void)state;
    return prog_mkdtemp(dir, "option-edges");
}

static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

/* Run `instess ARGS` with stdout into dir/stdout.txt and stderr into *err; the exit code. */
static int run(const char **err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int run(const char **err, const char *fmt, ...)
{
    static char errbuf[8192];
    va_list ap;
    va_start(ap, fmt);
    int rc = prog_vrun_in(dir, NULL, NULL, ">stdout.txt 2>stderr.txt", fmt, ap);
    va_end(ap);
    prog_read_text(dir, "stderr.txt", errbuf, sizeof errbuf);
    if (err) *err = errbuf;
    return rc;
}

/* One numeric option: the values that must be taken (its range's ends), those that must be refused (just past
 * them), the part of its message that states the range, and what else the option needs to act. */
typedef struct num_option {
    const char *name, *range;
    const char *good[4], *bad[6];
    const char *with;
} num_option;

static const num_option options[] = {
    {"level", "1..256", {"1", "256", "2.5"}, {"0", "256.01", "-1"}, "--grid pg-equal --mesh tetrahedron"},
    {"instances", "0..2147483647", {"0", "2147483647", "3"}, {"-1", "2147483648", "1.5"}, ""},
    {"size", "1..16384", {"1x1", "16384x1", "1x16384"}, {"0x1", "16385x1", "16384x16384", "1x", "x1", "1X1"}, ""},
    {"yaw", "-1000000..1000000", {"-1000000", "1000000", "-0"}, {"1000000.1", "-1e7"}, ""},
    {"pitch", "-1000000..1000000", {"-1000000", "1000000", "90"}, {"-1000000.5", "1e300"}, ""},
    {"distance", "1.01..1000", {"1.01", "1000"}, {"1.0099", "1000.001", "0", "-3.2"}, ""},
    {"fov", "1..170", {"1", "170"}, {"0.999", "170.001", "180", "0"}, ""},
    {"phong-alpha", "0..1", {"0", "1"}, {"-0.001", "1.001"}, "--patch phong"},
    {"n110-factor", "1..2", {"1", "2", "1.5"}, {"0.999", "2.001", "0"}, "--normals quadratic"},
    {"msaa", "1 or 4", {"1", "4"}, {"0", "2", "3", "5"}, ""},
    {"threads", "0..256", {"0", "1", "256"}, {"-1", "257"}, ""},
    {"lod-target", "0.25..4096", {"0.25", "4096"}, {"0.249", "4097", "0", "-1"}, "--lod screen"},
    {"lod-deviation", "0.125..64", {"0.125", "64"}, {"0.124", "64.01", "0", "-1"}, "--lod deviation"},
    {"min-level", "1..64", {"1", "8"}, {"0", "65", "-1"}, "--lod distance --max-level 8"},
    {"max-level", "1..64", {"1", "64"}, {"0", "65"}, "--lod distance"},
    {"import-timeout", "1..86400", {"1", "86400"}, {"0", "86401", "-5"}, ""},
    {"max-memory", "16..1048576", {"16", "1048576"}, {"15", "1048577", "0"}, ""},
    {"max-file-size", "1..1048576", {"1", "1048576"}, {"0", "1048577"}, ""},
    {"max-import-memory", "16..1048576", {"16", "1048576"}, {"15", "1048577"}, ""},
    {"displace-scale", "-10..10", {"-10", "10"}, {"-10.01", "10.01"}, "--displace height.png"},
    {"color", "each 0..1", {"0,0,0", "1,1,1", "#ffffff", "#000000"}, {"1.01,0,0", "-0.01,0,0", "0,0", "0,0,0,0",
                                                                      "#fffff", "#gggggg"}, ""},
    {"background", "each 0..1", {"0,0,0", "1,1,1", "#A0b1C2"}, {"0,1.5,0", "#12345", "1,1", "0,0,2"}, ""},
    {"light", "finite numbers, not all zero", {"1,0,0", "1e30,1e30,0", "1e-30,1e-30,0", "-3.4e38,0,0"},
     {"0,0,0", "0,0,1e-50", "1e39,0,0", "1,1"}, ""},
    {"d3d9-adaptive", "four finite numbers", {"depth", "0,0,1,0", "0,0,0,0", "1e38,1e38,1e38,1e38"},
     {"1,2,3", "1e39,0,0,0", "0,0,1,0,5", "deep"}, "--path npatch-mode --patch npatch --level 8"},
};
enum { N_OPTIONS = sizeof options / sizeof options[0] };

/* Values that are no plain number, refused by every numeric option (where a list is taken, in its first place). */
static const char *const junk[] = {"''", "nan", "NaN", "inf", "-inf", "infinity", "1e999", "0x10", "' 5'", "'5 '",
                                   "1,5", "5abc", "abc", "--", "+-1", "1e", "."};

/* The options that take a value that is not a number (names, files, lists). */
static const char *const non_numeric[] = {"mesh", "patch", "normals", "grid", "path", "up", "fill", "fit", "cull",
                                          "lod", "wire-levels", "aov", "displace", "export-obj", "output", "stats",
                                          "shading", "texture",
                                          NULL};

/* Every option of the table that takes a value is either here or in non_numeric. */
static void test_every_option_classified(void **state)
{
    (void)state;
    for (size_t k = 0; k < scene_option_count; k++) {
        const scene_option *o = &scene_options[k];
        if (!o->metavar) continue;
        bool found = false;
        for (int i = 0; i < N_OPTIONS; i++) found |= strcmp(options[i].name, o->name) == 0;
        for (int i = 0; non_numeric[i]; i++) found |= strcmp(non_numeric[i], o->name) == 0;
        if (!found) fprintf(stderr, "--%s takes a value: give its edges in test_option_edges.c\n", o->name);
        assert_true(found);
    }
}

/* Junk value v for option o on a command line: in the first place of a list, the others good. */
static void value_of(const num_option *o, const char *v, char *buf, size_t len)
{
    if (!strcmp(o->name, "color") || !strcmp(o->name, "background") || !strcmp(o->name, "light"))
        snprintf(buf, len, "%s,0,1", v);
    else if (!strcmp(o->name, "d3d9-adaptive")) snprintf(buf, len, "%s,0,1,0", v);
    else if (!strcmp(o->name, "size")) snprintf(buf, len, "%sx8", v);
    else snprintf(buf, len, "%s", v);
}

/* Just past each end and junk: exit 2, a message naming the option and its range, nothing written. */
static void test_refused(void **state)
{
    (void)state;
    const char *err;
    for (int i = 0; i < N_OPTIONS; i++) {
        const num_option *o = &options[i];
        for (int b = 0; b < 6 + (int)(sizeof junk / sizeof junk[0]); b++) {
            char v[200];
            if (b < 6 && !o->bad[b]) continue;
            if (b < 6) snprintf(v, sizeof v, "'%s'", o->bad[b]);
            else value_of(o, junk[b - 6], v, sizeof v);
            int rc = run(&err, "--%s %s %s -q --size 8x8 -o out.png", o->name, v, o->with);
            char want[100];
            snprintf(want, sizeof want, "--%s", o->name);
            if (rc != 2 || !strstr(err, want) || !strstr(err, o->range))
                fprintf(stderr, "--%s %s: exit %d, said: %s", o->name, v, rc, err);
            assert_int_equal(rc, 2);
            assert_non_null(strstr(err, want));
            assert_non_null(strstr(err, o->range));
            assert_false(prog_exists(dir, "out.png"));
        }
    }
}

/* Whether dir/name is an image whose every value is finite (depth, +inf on the background by design, is not
 * asked for). */
static bool all_finite(const char *name)
{
    char p[600], err[400];
    is_image img = {0};
    if (image_read(&img, prog_path(dir, name, p, sizeof p), err, sizeof err) != 0) return false;
    size_t n = (size_t)img.width * img.height * img.channels, bad = 0;
    for (size_t k = 0; k < n; k++) bad += !isfinite(img.data[k]);
    image_free(&img);
    return bad == 0;
}

/* Whether dir/stdout.txt is one valid JSON object (python3's json module decides). */
static bool stdout_is_json(void)
{
    char cmd[800];
    snprintf(cmd, sizeof cmd, "python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert isinstance(d, dict)' "
             "'%s/stdout.txt' 2>/dev/null", dir);
    return system(cmd) == 0;
}

/* Each end of each range: exit 0, an EXR with AOVs whose every value is finite, --stats json valid. */
static void test_taken(void **state)
{
    (void)state;
    const char *err;
    /* the height map --displace-scale needs */
    assert_int_equal(run(&err, "-q --size 8x8 --level 1 -o height.png"), 0);
    for (int i = 0; i < N_OPTIONS; i++) {
        const num_option *o = &options[i];
        for (int g = 0; g < 4 && o->good[g]; g++) {
            const char *v = o->good[g];
            bool big = !strcmp(o->name, "size");
            int rc = run(&err, "--%s '%s' %s %s --level 2 --stats json --aov normal,bary,instance,gregory -o out.exr",
                         o->name, v, o->with, big ? "" : "--size 12x10");
            if (rc != 0) fprintf(stderr, "--%s %s: exit %d, said: %s", o->name, v, rc, err);
            assert_int_equal(rc, 0);
            if (!all_finite("out.exr") || !stdout_is_json())
                fprintf(stderr, "--%s %s: an image value is not finite, or --stats json is not JSON\n", o->name, v);
            assert_true(all_finite("out.exr"));
            assert_true(stdout_is_json());
        }
    }
}

/* A value changed on the way is said on stderr: a primitive-generator grid's level beyond its range. */
static void test_clamps_said(void **state)
{
    (void)state;
    const char *err;
    assert_int_equal(run(&err, "--grid pg-fractional-odd --level 64 --size 8x8 -q -o clamp.png"), 0);
    assert_non_null(strstr(err, "--level 64 is outside the range of --grid pg-fractional-odd; rendering level 63"));
    assert_int_equal(run(&err, "--grid pg-fractional-even --level 1 --size 8x8 -q -o clamp.png"), 0);
    assert_non_null(strstr(err, "rendering level 2"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_option_classified),
        cmocka_unit_test(test_refused),
        cmocka_unit_test(test_taken),
        cmocka_unit_test(test_clamps_said),
    };
    return cmocka_run_group_tests_name("option_edges", tests, setup, teardown);
}
