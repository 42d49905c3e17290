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

/* printf into err (when err and errlen are given), always NUL-terminated: the message of a failed call. */
void image_set_err(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

#ifdef __cplusplus
}
#endif

#endif
