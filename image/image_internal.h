/* image/image_internal.h -- what image/'s files share and nothing else sees.  Private to image/. */
#ifndef INSTESS_IMAGE_INTERNAL_H
#define INSTESS_IMAGE_INTERNAL_H

#include "image.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The library functions the codec module calls, handed to it when it is loaded (codec_set_host): the module
 * has no undefined symbol of the library, so it loads the same whether the library is a static part of the
 * program, a shared library opened with RTLD_GLOBAL, or one opened with RTLD_LOCAL (Python's ctypes, plugin
 * hosts), whose symbols the module could not see. */
typedef struct image_codec_host {
    int (*alloc)(is_image *img, int width, int height, const char *channel_names, char *err, size_t errlen);
    int (*channel_index)(const is_image *img, const char *name);
    void (*free)(is_image *img);
    int (*write)(const is_image *img, const char *path, const is_image_meta *meta, char *err, size_t errlen);
} image_codec_host;

/* True if img is an image this library encodes or compares (data, 1..IS_IMAGE_MAX_DIM pixels each way, 1..
 * IS_IMAGE_MAX_CHANNELS channels); else false with "what: invalid image (...)" in err (image/image_diff.c). */
bool image_valid(const is_image *img, const char *what, char *err, size_t errlen);

/* PNG through libpng (image/image_png.c): encode img's first four channels as image_encode does for .png; 0 or
 * -1.  Read path into img: 0, -1 with a message, or 1 when path is not a PNG (by its signature) or cannot be
 * opened: the caller asks the module.  Every PNG is decoded here (libpng's messages into err, never stderr). */
int image_png_encode(const is_image *img, const is_image_meta *meta, const char *label, unsigned char **bytes,
                     size_t *len, char *err, size_t errlen);
int image_png_read(is_image *img, const char *path, char *err, size_t errlen);

/* printf into err (when err and errlen are given), always NUL-terminated: the message of a failed call. */
void image_set_err(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* The folder of path (a file's path) into dir ("." if it has none; image_module.c). */
void image_dir_of(const char *path, char *dir, size_t len);

#ifdef __cplusplus
}
#endif

#endif
