/* image/image_internal.h -- what image/'s files share and nothing else sees.  Private to image/. */
#ifndef INSTESS_IMAGE_INTERNAL_H
#define INSTESS_IMAGE_INTERNAL_H

#include "image.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* printf into err (when err and errlen are given), always NUL-terminated: the message of a failed call. */
void image_set_err(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

#endif
