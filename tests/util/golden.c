/* tests/util/golden.c -- golden-image checks (see golden.h). */
#include "golden.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define GOLDEN_PATH_MAX 1024

/* Weak references: the Makefile links every tests/util object into EVERY test binary, and a strong reference
 * here would pull core/image.o, and with it OpenImageIO (0.2 s of start-up), into tests that never touch
 * images.  A test that has an image to check has called image_alloc, which links image.o and resolves these. */
#pragma weak image_write
#pragma weak image_read
#pragma weak image_check
#pragma weak image_free

/* The golden directory: $INSTESS_GOLDEN_DIR or tests/golden. */
const char *golden_dir(void)
{
    const char *d = getenv("INSTESS_GOLDEN_DIR");
    return d && *d ? d : "tests/golden";
}

/* The failure directory: $INSTESS_FAILURE_DIR or tests/failures. */
const char *golden_failure_dir(void)
{
    const char *d = getenv("INSTESS_FAILURE_DIR");
    return d && *d ? d : "tests/failures";
}

/* True when `make goldens` asks for the goldens to be rewritten. */
static int regenerating(const char *stem)
{
    const char *r = getenv("INSTESS_REGENERATE_GOLDENS");
    if (!r || strcmp(r, "1") != 0) return 0;
    const char *only = getenv("INSTESS_GOLDENS_ONLY");
    if (!only || !*only) return 1;
    size_t n = strlen(stem);
    for (const char *p = only; *p;) {   /* a comma-separated list of golden names */
        size_t len = strcspn(p, ",");
        if (len == n && strncmp(p, stem, n) == 0) return 1;
        p += len + (p[len] == ',');
    }
    return 0;
}

/* mkdir -p; 0 or -1 (errno set). */
static int mkdir_p(const char *dir)
{
    char buf[GOLDEN_PATH_MAX];
    if (snprintf(buf, sizeof buf, "%s", dir) >= (int)sizeof buf)
        return errno = ENAMETOOLONG, -1;
    for (char *p = buf + 1; *p; p++)
        if (*p == '/') {
            *p = '\0';
            if (mkdir(buf, 0755) != 0 && errno != EEXIST)
                return -1;
            *p = '/';
        }
    return mkdir(buf, 0755) != 0 && errno != EEXIST ? -1 : 0;
}

/* Split name into stem and extension (".exr" if name ends so, else ".png"). */
static void split_name(const char *name, char *stem, size_t n, const char **ext)
{
    size_t len = strlen(name);
    int exr = len > 4 && strcmp(name + len - 4, ".exr") == 0;
    int png = len > 4 && strcmp(name + len - 4, ".png") == 0;
    *ext = exr ? ".exr" : ".png";
    snprintf(stem, n, "%.*s", (int)(exr || png ? len - 4 : len), name);
}

/* Print the failure banner and the regeneration hint. */
static void report_hint(const char *name, const char *golden)
{
    fprintf(stderr,
            "golden %s: if the new image is intended, regenerate with `make goldens` (INSTESS_REGENERATE_GOLDENS=1),\n"
            "  look at %s, and commit it saying why\n",
            name, golden);
}

/* Write the golden (regeneration mode). */
static int regenerate(const is_image *actual, const char *name, const char *golden, const is_image_meta *meta)
{
    char err[GOLDEN_PATH_MAX + 256];
    if (mkdir_p(golden_dir()) != 0) {
        fprintf(stderr, "golden %s: FAILURE: cannot create %s: %s\n", name, golden_dir(), strerror(errno));
        return -1;
    }
    if (image_write(actual, golden, meta, err, sizeof err) != 0) {
        fprintf(stderr, "golden %s: FAILURE: cannot write the golden: %s\n", name, err);
        return -1;
    }
    fprintf(stderr, "golden %s: regenerated %s\n", name, golden);
    return 0;
}

/* Write actual to the failure directory and read it back (the image as the golden format stores it). */
static int store_actual(const is_image *actual, const char *name, const char *path, const is_image_meta *meta,
                        is_image *got)
{
    char err[GOLDEN_PATH_MAX + 256];
    if (mkdir_p(golden_failure_dir()) != 0) {
        fprintf(stderr, "golden %s: FAILURE: cannot create %s: %s\n", name, golden_failure_dir(), strerror(errno));
        return -1;
    }
    if (image_write(actual, path, meta, err, sizeof err) != 0 || image_read(got, path, err, sizeof err) != 0) {
        fprintf(stderr, "golden %s: FAILURE: %s\n", name, err);
        return -1;
    }
    return 0;
}

/* Compare got with the golden by image_check, the pixel-diff test `instess compare` runs; 0 when it passes, -1
 * (with a report, and the diff image when the pixels differ) otherwise. */
static int compare_golden(const is_image *got, const is_image *gold, const char *name, const char *golden,
                          const char *actual_path, const char *diff_path, float fail_thresh, float fail_percent)
{
    char err[GOLDEN_PATH_MAX + 256];
    is_image_diff d;
    is_image_verdict v = image_check(got, gold, fail_thresh, fail_percent, diff_path, &d, err, sizeof err);
    if (v == IS_IMAGE_PASS)
        return 0;
    if (v != IS_IMAGE_DIFFERENT) {
        fprintf(stderr, "golden %s: FAILURE: actual %s against the golden %s: %s\n", name, actual_path, golden, err);
        return -1;
    }
    double pct = 100.0 * (double)d.n_fail / (double)d.n_pixels;
    fprintf(stderr,
            "golden %s: FAILURE: %ld of %ld pixels (%.4f%%, allowed %.4f%%) differ by more than %g from %s;\n"
            "  max error %g (pixel %d,%d, channel %d), mean error %g; actual: %s; diff: %s\n",
            name, d.n_fail, d.n_pixels, pct, (double)fail_percent, (double)fail_thresh, golden, (double)d.max_error,
            d.max_x, d.max_y, d.max_channel, d.mean_error, actual_path, diff_path);
    return -1;
}

/* See golden.h. */
int golden_check(const is_image *actual, const char *name, float fail_thresh, float fail_percent)
{
    char stem[256], golden[GOLDEN_PATH_MAX], actual_path[GOLDEN_PATH_MAX], diff_path[GOLDEN_PATH_MAX], err[256];
    const char *ext;
    if (!image_write || !image_read || !image_check || !image_free) {
        fprintf(stderr, "golden_check: FAILURE: core/image.o is not linked into this test\n");
        return -1;
    }
    if (!actual || !actual->data || !name || !*name || strchr(name, '/')) {
        fprintf(stderr, "golden_check: FAILURE: invalid arguments (name \"%s\")\n", name ? name : "(null)");
        return -1;
    }
    split_name(name, stem, sizeof stem, &ext);
    snprintf(golden, sizeof golden, "%s/%s%s", golden_dir(), stem, ext);
    snprintf(actual_path, sizeof actual_path, "%s/%s.actual%s", golden_failure_dir(), stem, ext);
    snprintf(diff_path, sizeof diff_path, "%s/%s.diff.png", golden_failure_dir(), stem);
    is_image_meta meta = {"instess " INSTESS_VERSION, name};
    if (regenerating(stem))
        return regenerate(actual, name, golden, &meta);
    is_image got = {0}, gold = {0};
    int r = store_actual(actual, name, actual_path, &meta, &got);
    if (r == 0 && access(golden, F_OK) != 0) {
        fprintf(stderr, "golden %s: FAILURE: the golden %s is missing; actual in %s\n", name, golden, actual_path);
        r = -1;
    } else if (r == 0 && image_read(&gold, golden, err, sizeof err) != 0) {
        fprintf(stderr, "golden %s: FAILURE: %s\n", name, err);
        r = -1;
    } else if (r == 0) {
        unlink(diff_path);  /* a stale diff of an earlier run would mislead */
        r = compare_golden(&got, &gold, name, golden, actual_path, diff_path, fail_thresh, fail_percent);
    }
    if (r == 0)
        unlink(actual_path);
    else
        report_hint(name, golden);
    image_free(&got);
    image_free(&gold);
    return r;
}
