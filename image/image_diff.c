/* image/image_diff.c -- image_compare and its visual diff, in C.
 *
 * Why not OpenImageIO's ImageBufAlgo::compare, as before: loading OpenImageIO's ~260 libraries costs about
 * 0.4 s (binding their symbols), so `instess compare` of two small PNGs took ~0.5 s, almost all of it the load.
 * This file computes the same numbers the same way -- the values compared one by one in the order of the
 * pixels, the error sums in double over batches of 4096 pixels, the non-finite rules (NaN may match NaN, an
 * infinity any infinity; the first non-finite mismatch makes the largest error infinite and counts nothing) --
 * so `instess compare` and the golden tests keep their verdicts and numbers.  tests/test_image.c checks every
 * field against the codec module's codec_compare (OpenImageIO 2.4's compare) on random and non-finite images.
 * The diff image (red: fail, yellow: warn) is the one the module drew. */
#include "image_internal.h"

#include <math.h>
#include <stdbool.h>

/* std::min / std::max of two floats, as C++ defines them (the first argument when they compare equal or one is
 * NaN): the diff image keeps the pixels the C++ code drew. */
static float min_f(float a, float b) { return b < a ? b : a; }
static float max_f(float a, float b) { return a < b ? b : a; }

bool image_valid(const is_image *img, const char *what, char *err, size_t errlen)
{
    if (img && img->data && img->width > 0 && img->height > 0 && img->width <= IS_IMAGE_MAX_DIM &&
        img->height <= IS_IMAGE_MAX_DIM && img->channels > 0 && img->channels <= IS_IMAGE_MAX_CHANNELS)
        return true;
    image_set_err(err, errlen, "%s: invalid image (%dx%d, %d channels, data %s)", what, img ? img->width : 0,
                  img ? img->height : 0, img ? img->channels : 0, img && img->data ? "set" : "NULL");
    return false;
}

/* The running result of a comparison. */
typedef struct compare_acc {
    double max_error;
    int max_x, max_y, max_c;
    long n_fail, n_warn;
} compare_acc;

/* One value pair (x, y, channel c) into r, batch (the sum of |a - b|) and the pixel's failed / warned flags. */
static void compare_value(compare_acc *r, int x, int y, int c, float a, float b, double *batch, bool *failed,
                          bool *warned, float fail_thresh, float warn_thresh)
{
    if (!isfinite(a) || !isfinite(b)) {
        if (!!isnan(a) == !!isnan(b) && !!isinf(a) == !!isinf(b)) return;   /* NaN matches NaN, inf any inf */
        if (isfinite(r->max_error)) {   /* the first non-finite mismatch: the largest error is infinite */
            r->max_error = INFINITY, r->max_x = x, r->max_y = y, r->max_c = c;
            return;
        }
    }
    /* OpenImageIO 2.4 also tests a relative difference (|a - b| over the mean of |a| and |b|) against a relative
     * threshold, 0 here: a difference counts only when that is above 0 or NaN, so a NaN difference (whose
     * mean is NaN, taken as 0) counts as no failure.  image_check counts those itself. */
    float mean_abs = (float)((double)fabsf(a) * 0.5 + (double)fabsf(b) * 0.5);
    double f = fabsf(a - b);
    if (isinf(f)) f = fabs((double)a - (double)b);   /* finite values whose float difference overflows (3e38, -3e38):
                                                        the exact difference, so the mean stays a number */
    double rel = mean_abs > 0.0f ? f / mean_abs : 0.0;
    *batch += f;
    if (!(f <= r->max_error)) r->max_error = f, r->max_x = x, r->max_y = y, r->max_c = c;   /* NaN too */
    if (!*warned && !(f <= warn_thresh) && !(rel <= 0.0)) r->n_warn++, *warned = true;
    if (!*failed && !(f <= fail_thresh) && !(rel <= 0.0)) r->n_fail++, *failed = true;
}

/* The statistics of a against b (same shape) into res. */
static void compare_values(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh,
                           is_image_diff *res)
{
    enum { BATCH = 4096 };   /* pixels per partial sum, as OpenImageIO's compare */
    compare_acc r = {0};
    size_t n = (size_t)a->width * (size_t)a->height, ch = (size_t)a->channels;
    double total = 0.0;
    for (size_t p0 = 0; p0 < n; p0 += BATCH) {
        double batch = 0.0;
        for (size_t p = p0; p < n && p < p0 + BATCH; p++) {
            bool failed = false, warned = false;
            int x = (int)(p % (size_t)a->width), y = (int)(p / (size_t)a->width);
            for (size_t c = 0; c < ch; c++)
                compare_value(&r, x, y, (int)c, a->data[p * ch + c], b->data[p * ch + c], &batch, &failed, &warned,
                              fail_thresh, warn_thresh);
        }
        total += batch;
    }
    res->max_error = (float)r.max_error;
    res->mean_error = total / (double)(n * ch);
    res->n_fail = r.n_fail;
    res->n_warn = r.n_warn;
    res->n_pixels = (long)n;
    res->max_x = r.max_x, res->max_y = r.max_y, res->max_channel = r.max_c;
}

/* How far apart values a and b are for the diff image: |a - b|, 0 for NaN against NaN or an infinity against the
 * same infinity, and infinite for a non-finite mismatch (NaN against a number, unequal infinities) -- which
 * image_check counts as failing, so the diff image shows it at full brightness (std::max dropped the NaN). */
static float value_distance(float a, float b)
{
    if (isfinite(a) && isfinite(b)) return fabsf(a - b);
    if (isnan(a) || isnan(b)) return isnan(a) && isnan(b) ? 0.0f : INFINITY;
    return a == b ? 0.0f : INFINITY;
}

/* The visual diff of a and b into d (R, G, B, A of a's size): the dimmed luminance of a plus |a - b| of the
 * first three channels scaled so that max_err is full brightness; a pixel with a channel above fail_thresh is
 * red, above warn_thresh yellow, from 35% to full brightness by its largest difference over max_err. */
static void fill_diff(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, float max_err,
                      is_image *d)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    int ch = a->channels, nc = ch < 3 ? ch : 3;
    float scale = max_err > 0.0f ? 1.0f / max_err : 0.0f;
    for (size_t p = 0; p < n; p++) {
        const float *pa = a->data + p * (size_t)ch, *pb = b->data + p * (size_t)ch;
        float worst = 0.0f, lum = 0.0f, out[3];
        for (int c = 0; c < ch; c++) worst = max_f(worst, value_distance(pa[c], pb[c]));
        for (int c = 0; c < 3; c++) {
            int k = c < nc - 1 ? c : nc - 1;
            lum += (c < nc ? pa[c] : pa[0]) / 3.0f;
            out[c] = fabsf(pa[k] - pb[k]) * scale;
        }
        float *o = d->data + p * 4;
        for (int c = 0; c < 3; c++) o[c] = min_f(1.0f, 0.2f * min_f(max_f(lum, 0.0f), 1.0f) + out[c]);
        o[3] = 1.0f;
        /* amplified: the largest is full red, and so is a non-finite mismatch */
        float level = isinf(worst) ? 1.0f : 0.35f + 0.65f * min_f(1.0f, worst * scale);
        if (worst > warn_thresh) o[0] = level, o[1] = level, o[2] = 0.0f;
        if (worst > fail_thresh) o[0] = level, o[1] = 0.0f, o[2] = 0.0f;
    }
}

/* Write the visual diff of a and b (largest difference max_err) to path; 0 or -1. */
static int write_diff(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, float max_err,
                      const char *path, char *err, size_t errlen)
{
    is_image d;
    if (image_alloc(&d, a->width, a->height, "R,G,B,A", err, errlen) != 0) return -1;
    fill_diff(a, b, fail_thresh, warn_thresh, max_err, &d);
    is_image_meta meta = {"instess " INSTESS_VERSION, "image_compare visual diff (red: fail, yellow: warn)"};
    int rc = image_write(&d, path, &meta, err, errlen);
    image_free(&d);
    return rc;
}

int image_compare(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, is_image_diff *res,
                  const char *diff_path, char *err, size_t errlen)
{
    if (!image_valid(a, "image_compare (first image)", err, errlen) ||
        !image_valid(b, "image_compare (second image)", err, errlen))
        return -1;
    if (!res) return image_set_err(err, errlen, "image_compare: NULL result"), -1;
    if (a->width != b->width || a->height != b->height || a->channels != b->channels) {
        image_set_err(err, errlen, "image_compare: sizes differ (%dx%d with %d channels vs %dx%d with %d channels)",
                      a->width, a->height, a->channels, b->width, b->height, b->channels);
        return -1;
    }
    compare_values(a, b, fail_thresh, warn_thresh, res);
    return diff_path ? write_diff(a, b, fail_thresh, warn_thresh, res->max_error, diff_path, err, errlen) : 0;
}
