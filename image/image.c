/* image/image.c -- images in memory (files are written by image/image_write.c).
 * The codec (encode, read, compare, text) is image/image_oiio.cpp, the one file that uses OpenImageIO; see
 * image/image.h. */
#include "image_internal.h"

#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


/* path's extension (from the last '.' of its file name), or "" when there is none. */
static const char *extension_of(const char *path)
{
    if (!path) return "";
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(path, '.');
    return dot && (!slash || dot > slash) ? dot : "";
}

is_image_format image_format_of(const char *path)
{
    const char *ext = extension_of(path);
    char low[8] = {0};
    for (size_t k = 0; ext[k] && k + 1 < sizeof low; k++) low[k] = (char)tolower((unsigned char)ext[k]);
    if (strlen(ext) >= sizeof low) return IS_IMAGE_NONE;
    return !strcmp(low, ".png") ? IS_IMAGE_PNG : !strcmp(low, ".exr") ? IS_IMAGE_EXR : IS_IMAGE_NONE;
}

int image_file_channel_count(int channels, is_image_format fmt)
{
    return fmt == IS_IMAGE_PNG ? (channels < 4 ? channels : 4) : fmt == IS_IMAGE_EXR ? channels : 0;
}

size_t image_file_channels(const is_image *img, is_image_format fmt, char *buf, size_t len)
{
    size_t n = 0;
    if (buf && len) buf[0] = 0;
    else len = 0;
    int count = img && img->channels > 0 && img->channels <= IS_IMAGE_MAX_CHANNELS
                    ? image_file_channel_count(img->channels, fmt) : 0;   /* NULL or lying images: no names */
    for (int c = 0; c < count; c++) {
        int k = snprintf(n < len ? buf + n : NULL, n < len ? len - n : 0, "%s%s", c ? "," : "", img->channel_names[c]);
        if (k > 0) n += (size_t)k;
    }
    return n;
}

int image_check_path(const char *path, char *err, size_t errlen)
{
    if (!path || !*path) return image_set_err(err, errlen, "empty image path"), -1;
    if (image_format_of(path) == IS_IMAGE_NONE) {
        image_set_err(err, errlen, "%s: unknown image extension \"%s\" (use .png or .exr)", path, extension_of(path));
        return -1;
    }
    const char *slash = strrchr(path, '/');
    if (extension_of(path) == (slash ? slash + 1 : path)) {
        image_set_err(err, errlen, "%s: the file name has no stem before its extension", path);
        return -1;
    }
    return 0;
}

/* Split "R,G,B" into img's channel names; false if a name is empty or too long, or there are too many. */
static bool parse_names(is_image *img, const char *list)
{
    int n = 0;
    for (const char *p = list;; n++) {
        size_t len = strcspn(p, ",");
        if (len == 0 || len >= sizeof img->channel_names[0] || n >= IS_IMAGE_MAX_CHANNELS) return false;
        memcpy(img->channel_names[n], p, len);
        img->channel_names[n][len] = 0;
        if (!p[len]) break;
        p += len + 1;
    }
    img->channels = n + 1;
    return true;
}

int image_alloc(is_image *img, int width, int height, const char *channel_names, char *err, size_t errlen)
{
    if (!img) return image_set_err(err, errlen, "image_alloc: NULL image"), -1;
    memset(img, 0, sizeof *img);
    if (!channel_names || !parse_names(img, channel_names)) {
        image_set_err(err, errlen, "image_alloc: bad channel names \"%s\" (1 to %d names of 1 to 15 characters)",
                channel_names ? channel_names : "(null)", IS_IMAGE_MAX_CHANNELS);
        memset(img, 0, sizeof *img);
        return -1;
    }
    if (width <= 0 || height <= 0 || width > IS_IMAGE_MAX_DIM || height > IS_IMAGE_MAX_DIM) {
        image_set_err(err, errlen, "image_alloc: bad size %dx%d (1 to %d pixels each way)", width, height,
                IS_IMAGE_MAX_DIM);
        memset(img, 0, sizeof *img);
        return -1;
    }
    img->data = calloc((size_t)width * (size_t)height * (size_t)img->channels, sizeof(float));
    if (!img->data) {
        image_set_err(err, errlen, "image_alloc: out of memory for %dx%d x %d channels", width, height, img->channels);
        memset(img, 0, sizeof *img);
        return -1;
    }
    img->width = width, img->height = height;
    return 0;
}

void image_free(is_image *img)
{
    if (!img) return;
    free(img->data);
    memset(img, 0, sizeof *img);
}

int image_channel_index(const is_image *img, const char *name)
{
    for (int c = 0; img && name && c < img->channels && c < IS_IMAGE_MAX_CHANNELS; c++)
        if (!strcmp(img->channel_names[c], name)) return c;
    return -1;
}

#ifndef INSTESS_OIIO_VERSION
#define INSTESS_OIIO_VERSION "unknown"
#endif
const char *image_codec_build_version(void)
{
    return INSTESS_OIIO_VERSION[0] ? INSTESS_OIIO_VERSION : "unknown";
}

void image_from_rgba8(is_image *img, const uint32_t *rgba)
{
    if (!img || !img->data || !rgba) return;
    int idx[4] = {image_channel_index(img, "R"), image_channel_index(img, "G"), image_channel_index(img, "B"),
                  image_channel_index(img, "A")};
    size_t n = (size_t)img->width * img->height;
    for (size_t p = 0; p < n; p++)
        for (int k = 0; k < 4; k++)
            if (idx[k] >= 0) img->data[p * img->channels + idx[k]] = (float)((rgba[p] >> (8 * k)) & 0xffu) * (1.0f / 255.0f);
}

void image_set_err(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

/* The channel names of img joined by commas into buf; buf. */
static const char *channel_names_of(const is_image *img, char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = 0;
    for (int c = 0; c < img->channels && used < len; c++)
        used += (size_t)snprintf(buf + used, len - used, "%s%s", c ? "," : "", img->channel_names[c]);
    return buf;
}

/* True when a and b have one width, height and list of channel names; else false with both shapes in err. */
static bool same_shape(const is_image *a, const is_image *b, char *err, size_t errlen)
{
    bool same = a->width == b->width && a->height == b->height && a->channels == b->channels;
    for (int c = 0; same && c < a->channels; c++) same = strcmp(a->channel_names[c], b->channel_names[c]) == 0;
    if (!same) {
        char na[IS_IMAGE_MAX_CHANNELS * 17], nb[IS_IMAGE_MAX_CHANNELS * 17];
        image_set_err(err, errlen, "the images differ in shape: %dx%d [%s] against %dx%d [%s]", a->width, a->height,
                     channel_names_of(a, na, sizeof na), b->width, b->height, channel_names_of(b, nb, sizeof nb));
    }
    return same;
}

/* Whether values x and y differ for the test: NaN against a number, infinities not equal, or finite and more
 * than thresh apart; *nonfinite is set when a non-finite value is why. */
static bool values_differ(float x, float y, float thresh, bool *nonfinite)
{
    if (isnan(x) || isnan(y)) return (*nonfinite = isnan(x) != isnan(y));
    if (isinf(x) || isinf(y)) return (*nonfinite = x != y);
    return fabsf(x - y) > thresh;
}

/* The failing pixels of a and b (same shape) at thresh into res->n_fail, those failing by a non-finite value
 * into res->n_nonfinite; a non-finite mismatch also makes max_error infinite. */
static void count_failing(const is_image *a, const is_image *b, float thresh, is_image_diff *res)
{
    size_t n = (size_t)a->width * (size_t)a->height, ch = (size_t)a->channels;
    res->n_fail = res->n_nonfinite = 0;
    for (size_t p = 0; p < n; p++) {
        bool fail = false, nonfinite = false;
        for (size_t c = 0; c < ch; c++) {
            bool nf = false;
            if (values_differ(a->data[p * ch + c], b->data[p * ch + c], thresh, &nf)) fail = true;
            nonfinite |= nf;
        }
        res->n_fail += fail;
        res->n_nonfinite += nonfinite;
    }
    if (res->n_nonfinite) res->max_error = INFINITY;
}

/* Whether fail_thresh (>= 0, +inf allowed) and fail_percent (0..100) can decide a test; else why in err. */
static bool thresholds_ok(float fail_thresh, float fail_percent, char *err, size_t errlen)
{
    if (fail_thresh >= 0.0f && fail_percent >= 0.0f && fail_percent <= 100.0f) return true;   /* NaN fails */
    image_set_err(err, errlen, "image_check: thresholds %g and %g%% (a difference >= 0, a percentage 0..100)",
                  (double)fail_thresh, (double)fail_percent);
    return false;
}

is_image_verdict image_check(const is_image *actual, const is_image *reference, float fail_thresh,
                             float fail_percent, const char *diff_path, is_image_diff *res, char *err, size_t errlen)
{
    is_image_diff none;
    if (!res) res = &none;   /* the verdict alone */
    memset(res, 0, sizeof *res);
    if (!actual || !reference) return image_set_err(err, errlen, "image_check: NULL image"), IS_IMAGE_BAD_ARGUMENT;
    if (!thresholds_ok(fail_thresh, fail_percent, err, errlen)) return IS_IMAGE_BAD_ARGUMENT;
    if (!same_shape(actual, reference, err, errlen)) return IS_IMAGE_SHAPE_DIFFERS;
    if (image_compare(actual, reference, fail_thresh, fail_thresh, res, NULL, err, errlen) != 0)
        return IS_IMAGE_IO_ERROR;
    count_failing(actual, reference, fail_thresh, res);
    if (100.0 * (double)res->n_fail <= (double)fail_percent * (double)res->n_pixels) return IS_IMAGE_PASS;
    is_image_diff again;
    if (diff_path && image_compare(actual, reference, fail_thresh, fail_thresh, &again, diff_path, err, errlen) != 0)
        return IS_IMAGE_IO_ERROR;
    return IS_IMAGE_DIFFERENT;
}

is_image_verdict image_check_files(const char *a, const char *b, float fail_thresh, float fail_percent,
                                   const char *diff_path, is_image_diff *res, char *err, size_t errlen)
{
    is_image ia = {0}, ib = {0};
    is_image_diff none;
    if (!res) res = &none;
    memset(res, 0, sizeof *res);
    if (!a || !b) return image_set_err(err, errlen, "image_check_files: NULL path"), IS_IMAGE_BAD_ARGUMENT;
    if (!thresholds_ok(fail_thresh, fail_percent, err, errlen)) return IS_IMAGE_BAD_ARGUMENT;
    is_image_verdict v = IS_IMAGE_IO_ERROR;
    if (image_read(&ia, a, err, errlen) == 0 && image_read(&ib, b, err, errlen) == 0)
        v = image_check(&ia, &ib, fail_thresh, fail_percent, diff_path, res, err, errlen);
    image_free(&ia);
    image_free(&ib);
    return v;
}
