/* tests/valgrind/codec_raw.c -- the image codec of the valgrind build: the four codec functions of image/image.h
 * (encode, read, text) without OpenImageIO, linked in place of image/image_codec.c.  PNG goes through the
 * library's own libpng code (image/image_png.c) as in the program, and image_compare is the library's (C), so
 * memcheck sees both; every other file is "encoded" raw, as below.
 *
 * Why: OpenImageIO loads libjxl and with it libhwy, whose start-up code executes RDTSCP; valgrind 3.19's
 * emulated CPU claims RDTSCP on machines that lack it (AMD EPYC here), and every process that loads libhwy
 * dies of SIGILL under valgrind before main.  The renderer's own code -- device, rasterizer, shaders, meshes,
 * the program's paths and its output files -- is all the same in this build; only the encoding differs.
 *
 * "Encoding" (not PNG) writes the image exactly as it is in memory, whatever the extension: a text header
 * "instess-raw 1\n<width> <height> <channels>\n<name>,<name>,...\n" then width*height*channels floats in the
 * machine's byte order.  tests/valgrind.sh compares the file of a run under memcheck with the file of the same
 * run without valgrind, byte for byte.  Reading gives the image back; text is not needed by the scenes
 * valgrind runs and fails with a message. */
#include "../../core/core.h"
#include "../../image/image_internal.h"   /* image_png_encode, image_png_read */

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* snprintf into err if given. */
#define SET_ERR(...) ((void)(err && errlen ? snprintf(err, errlen, __VA_ARGS__) : 0))

int image_encode(const is_image *img, is_image_format fmt, const is_image_meta *meta, const char *label,
                 unsigned char **bytes, size_t *len, char *err, size_t errlen)
{
    if (fmt == IS_IMAGE_PNG) return image_png_encode(img, meta, label ? label : "image", bytes, len, err, errlen);
    char head[64 + IS_IMAGE_MAX_CHANNELS * 16];
    int n = snprintf(head, sizeof head, "instess-raw 1\n%d %d %d\n", img->width, img->height, img->channels);
    for (int c = 0; c < img->channels; c++)
        n += snprintf(head + n, sizeof head - (size_t)n, "%s%s", c ? "," : "", img->channel_names[c]);
    n += snprintf(head + n, sizeof head - (size_t)n, "\n");
    size_t data = (size_t)img->width * img->height * img->channels * sizeof(float);
    *bytes = malloc((size_t)n + data);
    if (!*bytes) return SET_ERR("%s: out of memory", label), -1;
    memcpy(*bytes, head, (size_t)n);
    memcpy(*bytes + n, img->data, data);
    *len = (size_t)n + data;
    return 0;
}

int image_read(is_image *img, const char *path, char *err, size_t errlen)
{
    int png = image_png_read(img, path, err, errlen);
    if (png != 1) return png;
    memset(img, 0, sizeof *img);
    FILE *f = fopen(path, "rb");
    int w, h, c;
    char names[IS_IMAGE_MAX_CHANNELS * 16 + 1];
    int ok = f && fscanf(f, "instess-raw 1\n%d %d %d\n%512s", &w, &h, &c, names) == 4 && fgetc(f) == '\n';
    ok = ok && image_alloc(img, w, h, names, err, errlen) == 0 && img->channels == c;
    size_t n = ok ? (size_t)w * h * c : 0;
    ok = ok && fread(img->data, sizeof(float), n, f) == n;
    if (f) fclose(f);
    if (!ok) image_free(img), SET_ERR("%s: not an instess-raw image", path);
    return ok ? 0 : -1;
}

int image_draw_text(is_image *img, int x, int y, const char *text, float size_px, const float rgba[4], char *err,
                    size_t errlen)
{
    (void)img, (void)x, (void)y, (void)text, (void)size_px, (void)rgba;
    return SET_ERR("image_draw_text: not in the valgrind build (no OpenImageIO)"), -1;
}

int image_text_size(const char *text, float size_px, int *w, int *h)
{
    (void)text, (void)size_px, (void)w, (void)h;
    return -1;
}

/* No module in this build (the man page of this build names no folder). */
const char *image_codec_install_dir(void)
{
    return "(none: the valgrind build has no codec module)";
}
