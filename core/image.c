/* core/image.c -- images in memory and image files written through the outputs of a run (core/output.c).
 * The codec (encode, read, compare, text) is core/image.cpp, the one file that uses OpenImageIO; see core.h. */
#include "device_internal.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


/* path's extension (from the last '.' of its file name), or "" when there is none. */
static const char *extension_of(const char *path)
{
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

int image_check_path(const char *path, char *err, size_t errlen)
{
    if (!path || !*path) return core_set_err(err, errlen, "empty image path"), -1;
    if (image_format_of(path) == IS_IMAGE_NONE) {
        core_set_err(err, errlen, "%s: unknown image extension \"%s\" (use .png or .exr)", path, extension_of(path));
        return -1;
    }
    const char *slash = strrchr(path, '/');
    if (extension_of(path) == (slash ? slash + 1 : path)) {
        core_set_err(err, errlen, "%s: the file name has no stem before its extension", path);
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
    if (!img) return core_set_err(err, errlen, "image_alloc: NULL image"), -1;
    memset(img, 0, sizeof *img);
    if (!channel_names || !parse_names(img, channel_names)) {
        core_set_err(err, errlen, "image_alloc: bad channel names \"%s\" (1 to %d names of 1 to 15 characters)",
                channel_names ? channel_names : "(null)", IS_IMAGE_MAX_CHANNELS);
        memset(img, 0, sizeof *img);
        return -1;
    }
    if (width <= 0 || height <= 0 || width > IS_IMAGE_MAX_DIM || height > IS_IMAGE_MAX_DIM) {
        core_set_err(err, errlen, "image_alloc: bad size %dx%d (1 to %d pixels each way)", width, height,
                IS_IMAGE_MAX_DIM);
        memset(img, 0, sizeof *img);
        return -1;
    }
    img->data = calloc((size_t)width * (size_t)height * (size_t)img->channels, sizeof(float));
    if (!img->data) {
        core_set_err(err, errlen, "image_alloc: out of memory for %dx%d x %d channels", width, height, img->channels);
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
    for (int c = 0; c < img->channels; c++)
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

int image_write_output(is_outputs *o, int k, const is_image *img, const is_image_meta *meta, char *err,
                       size_t errlen)
{
    const char *path = o->f[k].path;
    if (image_check_path(path, err, errlen) != 0) return -1;
    unsigned char *bytes = NULL;
    size_t len = 0;
    if (image_encode(img, image_format_of(path), meta, path, &bytes, &len, err, errlen) != 0) return -1;
    int rc = outputs_write(o, k, bytes, len, err, errlen);
    free(bytes);
    return rc;
}

int image_write(const is_image *img, const char *path, const is_image_meta *meta, char *err, size_t errlen)
{
    if (image_check_path(path, err, errlen) != 0) return -1;
    is_outputs o;
    outputs_init(&o);
    int k = outputs_add(&o, path, err, errlen);
    int rc = k < 0 ? -1 : image_write_output(&o, k, img, meta, err, errlen);
    if (rc == 0) return outputs_commit(&o, err, errlen);
    outputs_abort(&o);
    return -1;
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
        core_set_err(err, errlen, "the images differ in shape: %dx%d [%s] against %dx%d [%s]", a->width, a->height,
                     channel_names_of(a, na, sizeof na), b->width, b->height, channel_names_of(b, nb, sizeof nb));
    }
    return same;
}

is_image_verdict image_check(const is_image *actual, const is_image *reference, float fail_thresh,
                             float fail_percent, const char *diff_path, is_image_diff *res, char *err, size_t errlen)
{
    memset(res, 0, sizeof *res);
    if (!same_shape(actual, reference, err, errlen)) return IS_IMAGE_SHAPE_DIFFERS;
    if (image_compare(actual, reference, fail_thresh, fail_thresh, res, NULL, err, errlen) != 0)
        return IS_IMAGE_IO_ERROR;
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
    memset(res, 0, sizeof *res);
    is_image_verdict v = IS_IMAGE_IO_ERROR;
    if (image_read(&ia, a, err, errlen) == 0 && image_read(&ib, b, err, errlen) == 0)
        v = image_check(&ia, &ib, fail_thresh, fail_percent, diff_path, res, err, errlen);
    image_free(&ia);
    image_free(&ib);
    return v;
}
