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
