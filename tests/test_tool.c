/* tests/test_tool.c -- instess as a tool for scripts: `instess compare` (each exit code, the thresholds, the
 * amplified diff image, the same counts as image_check, the goldens' test) and `--stats json` (valid JSON,
 * parsed here, with every figure of the text statistics).  Runs build/instess or $INSTESS_BIN. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

char *realpath(const char *path, char *resolved);   /* POSIX; glibc declares it only with _DEFAULT_SOURCE */

#include "util/prog.h"
#include "../core/core.h"
#include "../image/image.h"

static char dir[256];
static char out_buf[16384], err_buf[16384];

/* Run `instess ARGS` in dir (cd there) with stdout into out_buf and stderr into err_buf; the exit code. */
static int run(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static int run(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = prog_vrun_in(dir, NULL, NULL, ">out.txt 2>err.txt", fmt, ap);
    va_end(ap);
    prog_read_text(dir, "out.txt", out_buf, sizeof out_buf);
    prog_read_text(dir, "err.txt", err_buf, sizeof err_buf);
    return rc;
}

static int setup(void **state)
{
    if (prog_mkdtemp(dir, "tool") != 0) return -1;
    /* a and b: the same cube at levels 2 and 3; c: another size; bad.png: not an image */
    return run("--size 48x48 --level 2 -q -o a.png") || run("--size 48x48 --level 3 -q -o b.png") ||
           run("--size 32x32 -q -o c.png") || !prog_write_text(dir, "bad.png", "not a PNG\n");
}

static int teardown(void **state)
{
    prog_rmdir(dir);
    return 0;
}

/* The integer after `key` in text (e.g. "failing pixels: "), or -1. */
static long number_after(const char *text, const char *key)
{
    const char *p = strstr(text, key);
    return p ? strtol(p + strlen(key), NULL, 10) : -1;
}

/* Exit 0: identical images, and different ones within --fail or --failpercent; exit 1 beyond them, at the
 * failing percentage's boundary; the counts are image_check's (the goldens' test) on the same files. */
static void test_compare_pass_and_different(void **state)
{
    char pa[512], pb[512];
    assert_int_equal(run("compare a.png a.png"), 0);
    assert_non_null(strstr(out_buf, "identical"));
    assert_non_null(strstr(out_buf, "largest difference: 0 "));

    assert_int_equal(run("compare a.png b.png"), 1);
    assert_non_null(strstr(out_buf, "DIFFERENT"));
    long n_fail = number_after(out_buf, "failing pixels: ");
    assert_true(n_fail > 0 && n_fail < 48 * 48);
    is_image_diff d;
    char err[1024];
    assert_int_equal(image_check_files(prog_path(dir, "a.png", pa, sizeof pa), prog_path(dir, "b.png", pb, sizeof pb),
                                       0.0f, 0.0f, NULL, &d, err, sizeof err), IS_IMAGE_DIFFERENT);
    assert_int_equal(d.n_fail, n_fail);
    char largest[64];
    snprintf(largest, sizeof largest, "largest difference: %g (pixel %d,%d", (double)d.max_error, d.max_x, d.max_y);
    assert_non_null(strstr(out_buf, largest));

    assert_int_equal(run("compare a.png b.png --fail 1"), 0);
    assert_non_null(strstr(out_buf, "within the thresholds"));
    double pct = 100.0 * (double)n_fail / (48.0 * 48.0);
    assert_int_equal(run("compare a.png b.png --failpercent %.6f", pct + 1e-4), 0);
    assert_int_equal(run("compare a.png b.png --failpercent %.6f", pct - 1e-4), 1);
    assert_int_equal(run("compare a.png b.png --failpercent=100 --fail=0"), 0);
    assert_false(prog_exists(dir, "d.png"));
    assert_int_equal(run("compare a.png b.png --fail 1 --diff d.png"), 0);
    assert_false(prog_exists(dir, "d.png"));   /* no diff image when they pass */
}

/* --diff writes the amplified diff image on a difference: the pixel of the largest difference full red, the
 * other failing pixels red at 35% or more, passing pixels not red. */
static void test_compare_diff_image(void **state)
{
    char path[512], err[1024];
    assert_int_equal(run("compare b.png a.png --diff d.png"), 1);
    assert_non_null(strstr(out_buf, "diff image: d.png"));
    is_image img = {0}, a = {0}, b = {0};
    assert_int_equal(image_read(&img, prog_path(dir, "d.png", path, sizeof path), err, sizeof err), 0);
    assert_int_equal(image_read(&a, prog_path(dir, "a.png", path, sizeof path), err, sizeof err), 0);
    assert_int_equal(image_read(&b, prog_path(dir, "b.png", path, sizeof path), err, sizeof err), 0);
    assert_true(img.width == 48 && img.height == 48);
    long x = number_after(out_buf, "(pixel "), y = number_after(strstr(out_buf, "(pixel ") + 7, ",");
    const float *m = img.data + ((size_t)y * 48 + (size_t)x) * (size_t)img.channels;
    assert_true(m[0] == 1.0f && m[1] == 0.0f && m[2] == 0.0f);
    long red = 0, failing = 0;
    for (size_t p = 0; p < 48 * 48; p++) {
        const float *q = img.data + p * (size_t)img.channels;
        bool differs = false;
        for (int c = 0; c < 4; c++) differs |= a.data[p * 4 + (size_t)c] != b.data[p * 4 + (size_t)c];
        bool is_red = q[0] >= 0.34f &&   /* 35% in 8 bits: 89/255 */
                       q[1] == 0.0f && q[2] == 0.0f;
        failing += differs;
        red += is_red;
        assert_true(differs == is_red);
    }
    assert_int_equal(failing, number_after(out_buf, "failing pixels: "));
    assert_int_equal(red, failing);
    image_free(&img);
    image_free(&a);
    image_free(&b);
}

/* Exit 3 for a size mismatch (no diff written), 4 for a missing or unreadable image (named), 2 for usage
 * errors (an input is never overwritten by --diff). */
static void test_compare_errors(void **state)
{
    assert_int_equal(run("compare a.png c.png --diff e.png"), 3);
    assert_non_null(strstr(err_buf, "48x48 [R,G,B,A] against 32x32"));
    assert_false(prog_exists(dir, "e.png"));
    assert_int_equal(run("compare a.png missing.png"), 4);
    assert_non_null(strstr(err_buf, "missing.png"));
    assert_int_equal(run("compare bad.png a.png"), 4);
    assert_non_null(strstr(err_buf, "bad.png"));
    const char *usage[] = {"compare", "compare a.png", "compare a.png b.png c.png", "compare a.png b.png --fail -1",
                           "compare a.png b.png --fail x", "compare a.png b.png --failpercent 101",
                           "compare a.png b.png --bogus", "compare a.png b.png --diff d.txt",
                           "compare a.png b.png --diff b.png", "compare a.png b.png --fail"};
    for (size_t k = 0; k < sizeof usage / sizeof usage[0]; k++) {
        int rc = run("%s", usage[k]);
        if (rc != 2 || !strstr(err_buf, "instess compare: ")) fail_msg("%s: exit %d, %s", usage[k], rc, err_buf);
    }
    assert_int_equal(run("compare a.png c.png"), 3);   /* b.png is still the level-3 image, not a diff */
    assert_int_equal(run("compare b.png a.png"), 1);
    assert_int_equal(run("compare --help"), 0);
    assert_non_null(strstr(out_buf, "--failpercent P"));
}

/* ------------------------------------ a small JSON reader ------------------------------------ */

/* A JSON text's members: the top-level object's keys with the spans of their values, nested objects' keys
 * as "outer.inner". */
typedef struct json_doc {
    int n;
    char key[32][64];
    const char *val[32];
    int len[32];
} json_doc;

static const char *json_value(const char *p, json_doc *d, const char *prefix);

static const char *json_ws(const char *p)
{
    while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r') p++;
    return p;
}

/* A string at p (after its opening quote is checked); its end, or NULL.  The decoded text into out. */
static const char *json_string(const char *p, char *out, size_t len)
{
    if (*p++ != '"') return NULL;
    size_t n = 0;
    for (; *p != '"'; p++) {
        if ((unsigned char)*p < 0x20) return NULL;
        char c = *p;
        if (c == '\\') {
            c = *++p;
            if (c == 'u') {
                for (int k = 1; k <= 4; k++) if (!isxdigit((unsigned char)p[k])) return NULL;
                c = (char)strtol((char[]){p[3], p[4], 0}, NULL, 16), p += 4;
            } else if (!strchr("\"\\/bfnrt", c)) return NULL;
        }
        if (n + 1 < len) out[n++] = c;
    }
    out[n] = 0;
    return p + 1;
}

/* A number (JSON's grammar); its end, or NULL. */
static const char *json_number(const char *p)
{
    const char *s = p;
    if (*p == '-') p++;
    if (*p == '0') p++;
    else if (isdigit((unsigned char)*p)) while (isdigit((unsigned char)*p)) p++;
    else return NULL;
    if (*p == '.') { if (!isdigit((unsigned char)*++p)) return NULL; while (isdigit((unsigned char)*p)) p++; }
    if (*p == 'e' || *p == 'E') {
        p += p[1] == '+' || p[1] == '-' ? 2 : 1;
        if (!isdigit((unsigned char)*p)) return NULL;
        while (isdigit((unsigned char)*p)) p++;
    }
    return p > s ? p : NULL;
}

/* An object's members, recorded in d with prefix; its end, or NULL. */
static const char *json_object(const char *p, json_doc *d, const char *prefix)
{
    p = json_ws(p + 1);
    if (*p == '}') return p + 1;
    for (;;) {
        char key[64], full[160];
        p = json_string(json_ws(p), key, sizeof key);
        if (!p || *(p = json_ws(p)) != ':') return NULL;
        snprintf(full, sizeof full, "%s%s%s", prefix, *prefix ? "." : "", key);
        const char *v = json_ws(p + 1);
        p = json_value(v, d, full);
        if (!p || d->n >= 32) return NULL;
        if (strlen(full) >= sizeof d->key[0]) return NULL;
        memcpy(d->key[d->n], full, strlen(full) + 1);
        d->val[d->n] = v, d->len[d->n++] = (int)(p - v);
        p = json_ws(p);
        if (*p == '}') return p + 1;
        if (*p++ != ',') return NULL;
    }
}

static const char *json_value(const char *p, json_doc *d, const char *prefix)
{
    p = json_ws(p);
    char tmp[512];
    if (*p == '{') return json_object(p, d, prefix);
    if (*p == '"') return json_string(p, tmp, sizeof tmp);
    if (!strncmp(p, "true", 4) || !strncmp(p, "null", 4)) return p + 4;
    if (!strncmp(p, "false", 5)) return p + 5;
    return json_number(p);
}

/* Parse text (one object and nothing else but white space) into d; true when valid. */
static bool json_parse(const char *text, json_doc *d)
{
    d->n = 0;
    const char *p = json_ws(text);
    if (*p != '{') return false;
    p = json_value(p, d, "");
    return p && *json_ws(p) == 0;
}

/* The raw value of key in d (into buf), or NULL. */
static const char *json_get(const json_doc *d, const char *key, char *buf, size_t len)
{
    for (int k = 0; k < d->n; k++)
        if (!strcmp(d->key[k], key)) return snprintf(buf, len, "%.*s", d->len[k], d->val[k]), buf;
    return NULL;
}

/* A multi-part EXR (two subimages, made with oiiotool, which the set-up installs) is refused by name: only its first
 * part was compared, without a word. */
static void test_compare_multipart(void **state)
{
    (void)state;
    assert_int_equal(run("--size 16x16 -q -o part.exr"), 0);
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "cd '%s' && oiiotool part.exr part.exr --siappend -o multi.exr", dir);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(run("compare multi.exr part.exr"), 4);
    assert_non_null(strstr(err_buf, "multi.exr: holds several parts or subimages"));
}

/* The reader itself rejects what is not JSON (so that the test below can fail). */
static void test_json_reader(void **state)
{
    json_doc d;
    assert_true(json_parse("{\"a\": 1, \"b\": {\"c\": \"x\\\"y\"}, \"d\": -0.5e3}\n", &d));
    char buf[64];
    assert_string_equal(json_get(&d, "b.c", buf, sizeof buf), "\"x\\\"y\"");
    const char *bad[] = {"{\"a\": 1,}", "{\"a\" 1}", "{\"a\": 01}", "{\"a\": \"x\ty\"}", "{\"a\": 1} x", "{'a': 1}",
                         "{\"a\": \"\\q\"}", "", "{\"a\": 1"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        if (json_parse(bad[k], &d)) fail_msg("accepted %s", bad[k]);
}

/* The value of key as an integer (must be present). */
static long long json_int(const json_doc *d, const char *key)
{
    char buf[64];
    if (!json_get(d, key, buf, sizeof buf)) fail_msg("no \"%s\" in the JSON", key);
    return strtoll(buf, NULL, 10);
}

/* --stats json: one valid JSON object on stdout with every figure of the text form (run with the same
 * options), nothing on stderr; also with -q; names with quotes and backslashes escaped; the shortcut's counts
 * only for the smoothed patch. */
static void test_stats_json(void **state)
{
    assert_int_equal(run("--size 40x40 --level 3 -o text.png"), 0);
    static char text[sizeof err_buf];
    memcpy(text, err_buf, sizeof text);
    assert_int_equal(run("--size 40x40 --level 3 --stats json -o 'we\"ird\\name.png'"), 0);
    assert_string_equal(err_buf, "");
    json_doc d;
    if (!json_parse(out_buf, &d)) fail_msg("not JSON: %s", out_buf);
    char buf[256], want[256];
    assert_string_equal(json_get(&d, "output", buf, sizeof buf), "\"we\\\"ird\\\\name.png\"");
    assert_string_equal(json_get(&d, "mesh", buf, sizeof buf), "\"cube\"");
    /* "instess: cube: 12 triangles x 10 grid points, 120 vertices shaded, 45 triangles drawn, ..." */
    snprintf(want, sizeof want, "cube: %lld triangles x %lld grid points, %lld vertices shaded, %lld triangles drawn",
             json_int(&d, "triangles"), json_int(&d, "grid_points"), json_int(&d, "vertices_shaded"),
             json_int(&d, "triangles_drawn"));
    if (!strstr(text, want)) fail_msg("text statistics %s lack \"%s\"", text, want);
    snprintf(want, sizeof want, "per-edge shortcut: %lld of %lld P_k evaluations skipped",
             json_int(&d, "shortcut.skipped"), json_int(&d, "shortcut.evaluations"));
    if (!strstr(text, want)) fail_msg("text statistics %s lack \"%s\"", text, want);
    assert_non_null(json_get(&d, "ms", buf, sizeof buf));
    assert_true(json_int(&d, "grid_triangles") == 9 && json_int(&d, "triangles") == 12);

    assert_int_equal(run("--size 40x40 --patch npatch -q --stats json -o q.png"), 0);
    assert_string_equal(err_buf, "");
    assert_true(json_parse(out_buf, &d));
    assert_null(json_get(&d, "shortcut.skipped", buf, sizeof buf));
    assert_true(json_int(&d, "vertices_shaded") > 0);
    assert_int_equal(run("--stats yaml -o y.png"), 2);
    assert_non_null(strstr(err_buf, "text | json"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compare_pass_and_different),
        cmocka_unit_test(test_compare_diff_image),
        cmocka_unit_test(test_compare_errors),
        cmocka_unit_test(test_compare_multipart),
        cmocka_unit_test(test_json_reader),
        cmocka_unit_test(test_stats_json),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
