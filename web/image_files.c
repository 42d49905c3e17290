/* web/image_files.c -- the browser build has no image files: the page draws into its canvas and reads no texture
 * or height map from a disk (no libpng, no OpenImageIO in WebAssembly).  image_read, which core/texture_file.c
 * calls, refuses with a message that says so; the rest of image/ (image/image.c) is compiled as it is. */
#include "../image/image.h"

#include <stdio.h>

/* img, path -> -1 always: "path: image files are not read in the browser build". */
int image_read(is_image *img, const char *path, char *err, size_t errlen)
{
    (void)img;
    if (err && errlen) snprintf(err, errlen, "%s: image files are not read in the browser build", path ? path : "(null)");
    return -1;
}
