/* image/image.h -- images in memory (float channels with names), image files (PNG through libpng, EXR and the
 * rest through OpenImageIO), and the pixel-diff verdict that golden tests need.
 *
 * Conventions: pixels are floats, row-major, top row first, `channels` interleaved; colour channels hold display
 * values in [0, 1].  Functions return 0, or -1 with a message in err (errlen bytes, NUL-terminated); no globals,
 * nothing printed.  NULL images, paths and outputs, and images whose fields do not describe their data, are -1
 * (image_check: IS_IMAGE_BAD_ARGUMENT); tests/test_api_image.c walks every function.  OpenImageIO is loaded only
 * on the first call that needs it (an EXR or another format written or read, text): PNG files (every kind) and
 * comparisons never load it.
 */
#ifndef INSTESS_IMAGE_H
#define INSTESS_IMAGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/api.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The parts: image/image.c holds the pixels and writes one file at a time atomically; image/image_png.c encodes
 * and decodes PNG with libpng; image/image_diff.c compares (image_compare) and draws the diff image; the rest of
 * the codec (EXR, other formats, text) is image/image_oiio.cpp, the only code that touches OpenImageIO, built as
 * the module libinstess_codec.so that image/image_codec.c opens on the first call that needs it (OpenImageIO's
 * ~260 libraries take about 0.4 s to load).  The valgrind stage's build (tests/valgrind/) links another codec
 * with the same four functions in place of image/image_codec.c. */
#define IS_IMAGE_MAX_CHANNELS 32
#define IS_IMAGE_MAX_DIM 65536
/* The most values (width x height x channels) image_read decodes: 2^28 floats, 1 GiB.  A file declaring more is
 * refused from its header, before any pixel is decoded (a few hundred bytes of PNG can declare gigapixels). */
#define IS_IMAGE_MAX_VALUES (1ull << 28)
/* The largest file image_read opens: 4 GiB (an OpenEXR file of IS_IMAGE_MAX_VALUES floats, uncompressed, is about
 * 1 GiB).  A larger file is refused by its size, before it is opened. */
#define IS_IMAGE_MAX_FILE_BYTES (4ull << 30)
typedef struct is_image {
    int width, height, channels;
    char channel_names[IS_IMAGE_MAX_CHANNELS][16];  /* "R", "G", "B", "A", "Z", "N.X", ... */
    float *data;  /* width*height*channels floats, row-major, top row first, colour in [0, 1] */
} is_image;

typedef struct is_image_meta {
    const char *software;     /* "instess 0.1.0" */
    const char *description;  /* what was rendered (the program stores scene_describe's canonical text) */
} is_image_meta;

/* The file formats image files are written in, chosen by the extension (case-insensitive). */
typedef enum is_image_format { IS_IMAGE_NONE, IS_IMAGE_PNG, IS_IMAGE_EXR } is_image_format;
/* The format of path's extension (.png, .exr), or IS_IMAGE_NONE. */
INSTESS_API is_image_format image_format_of(const char *path);
/* How many of img's channels a file of format fmt holds: its first four for PNG (1 grey, 2 grey and alpha, 3 RGB,
 * 4 RGBA), all of them for EXR (0 for IS_IMAGE_NONE). */
INSTESS_API int image_file_channel_count(int channels, is_image_format fmt);
/* The names of the channels a file of format fmt holds of img, joined by commas ("R,G,B,A") into buf, as much as
 * fits in len (NUL-terminated when len > 0); the length of the whole list, as snprintf.  NULL images, images whose
 * channel count is out of 1..IS_IMAGE_MAX_CHANNELS and a NULL buf (then read as len 0) give an empty list. */
INSTESS_API size_t image_file_channels(const is_image *img, is_image_format fmt, char *buf, size_t len);
/* 0 if path can name an image file (a known extension after a non-empty stem), else -1 with a message. */
INSTESS_API int image_check_path(const char *path, char *err, size_t errlen);

/* The OpenImageIO version the codec module was built against (from the build; "unknown" if it was not told),
 * without loading the module. */
INSTESS_API const char *image_codec_build_version(void);

/* Allocate an image with the given channel names (comma-separated, e.g. "R,G,B,A,Z"); 0 or -1. */
INSTESS_API int image_alloc(is_image *img, int width, int height, const char *channel_names, char *err, size_t errlen);
INSTESS_API void image_free(is_image *img);
/* Index of the channel called name, or -1. */
INSTESS_API int image_channel_index(const is_image *img, const char *name);
/* Fill the channels R, G, B and A of img (those it has) from packed RGBA8 pixels, one per pixel (R in the low
 * byte, as dev_get_render_target_data gives them), each value k becoming k / 255; other channels are left. */
INSTESS_API void image_from_rgba8(is_image *img, const uint32_t *rgba);
/* Encode img as fmt into a malloc'd buffer (*bytes, *len; free it): .png 8-bit, its first four channels (1 grey,
 * 2 grey and alpha, 3 RGB, 4 RGBA; the others dropped), .exr RGBA half and other channels float; label names
 * the file in messages.  0 or -1. */
INSTESS_API int image_encode(const is_image *img, is_image_format fmt, const is_image_meta *meta, const char *label,
                 unsigned char **bytes, size_t *len, char *err, size_t errlen);
/* Write one image file: encoded in memory, written to a temporary in the same folder (mkstemp) and renamed onto
 * path, which must be a regular file or absent; nothing is left at path on failure; 0 or -1. */
INSTESS_API int image_write(const is_image *img, const char *path, const is_image_meta *meta, char *err, size_t errlen);
/* Read any file OpenImageIO reads into floats (PNGs through libpng, with the same names and values: Y for grey,
 * k / 255 or k / 65535); 0 or -1.  Every PNG is read through libpng (a palette, a transparency key and grey under 8 bits expanded as OpenImageIO expands them), its
 * messages into err, never on stderr; other files through OpenImageIO's reader of their extension alone (a file
 * that reader refuses is not tried with every other reader).  Only a regular file, not empty and at most
 * IS_IMAGE_MAX_FILE_BYTES, is opened (a FIFO, a device such as /dev/zero or a folder is refused with what it
 * is); the header is checked first (IS_IMAGE_MAX_DIM, IS_IMAGE_MAX_CHANNELS, IS_IMAGE_MAX_VALUES, and for PNG
 * the samples deflate can hold in the file's bytes; deep images, and files of several parts or subimages, are
 * refused: instess reads one flat image), then the pixels are decoded. */
INSTESS_API int image_read(is_image *img, const char *path, char *err, size_t errlen);

typedef struct is_image_diff {
    float max_error;        /* largest per-channel absolute difference */
    double mean_error;
    long n_fail, n_warn;    /* values above the fail / warn thresholds */
    long n_pixels;
    int max_x, max_y, max_channel;  /* where max_error is (the first such value) */
    long n_nonfinite;       /* image_check: failing pixels with a non-finite mismatch (NaN in one image only, or an
                               infinity the other image does not hold) */
} is_image_diff;
/* Compare a and b (same size and channel count) as OpenImageIO 2.4's ImageBufAlgo::compare does (the same
 * numbers, computed here: image/image_diff.c); if diff_path is not NULL, also write a visual diff image there.
 * Returns 0 when compared (see *res), -1 when they cannot be compared. */
INSTESS_API int image_compare(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, is_image_diff *res,
                  const char *diff_path, char *err, size_t errlen);
/* Notes on the above (image/image_diff.c): n_fail / n_warn count PIXELS (a pixel counts once however many of its
 * channels exceed the threshold); mean_error is over all values.  The diff image shows the dimmed first image
 * plus |a - b| scaled so the largest difference is full brightness; failing pixels red, warning yellow, from
 * 35% to full brightness by their largest difference over the image's largest (amplified).
 * image_read overwrites *img without freeing it (image_free an earlier image first).  PNG colour is stored as
 * given (unassociated alpha: no premultiplication either way), channels 8-bit k/255. */

/* The verdicts of image_check (the program `instess compare` maps them to its exit codes). */
typedef enum is_image_verdict {
    IS_IMAGE_PASS = 0,          /* identical, or within the thresholds */
    IS_IMAGE_DIFFERENT = 1,     /* more than fail_percent % of the pixels differ by more than fail_thresh */
    IS_IMAGE_SHAPE_DIFFERS = 2, /* width, height or channels (count or names) differ: not compared */
    IS_IMAGE_IO_ERROR = 3,      /* an image cannot be read, or the diff image cannot be written */
    IS_IMAGE_BAD_ARGUMENT = 4   /* a NULL image or path, or a threshold that is not a number >= 0 (fail_percent:
                                   0..100; NaN would pass everything): not compared */
} is_image_verdict;
/* The pixel-diff test of actual against reference, as the golden tests and `instess compare` run it: a pixel
 * fails when one of its channels differs by more than fail_thresh, is NaN in one image and not in the other, or
 * is infinite and not the same infinity in the other (counted here value by value, not by OpenImageIO, whose
 * differences of non-finite values are not numbers; n_nonfinite counts those pixels), and the test passes
 * when at most fail_percent percent of the pixels fail (0 and 0: any difference fails).  *res gets the counts
 * and the largest difference (zeroed when not compared).  On IS_IMAGE_DIFFERENT, if diff_path is not NULL,
 * the amplified diff image (see the notes above) is written there as a run of its own (image_write); nothing
 * is written otherwise.  Anything but IS_IMAGE_PASS / IS_IMAGE_DIFFERENT leaves the reason in err. */
INSTESS_API is_image_verdict image_check(const is_image *actual, const is_image *reference, float fail_thresh,
                             float fail_percent, const char *diff_path, is_image_diff *res, char *err, size_t errlen);
/* The folder the codec module is installed in, as the Makefile compiled it in (LIBDIR/instess; see
 * image/image_codec.c for where the module is looked for). */
INSTESS_API const char *image_codec_install_dir(void);
/* dlopen (RTLD_NOW | RTLD_LOCAL) the plug-in module at `path` after the checks the codec module gets, none of
 * which runs code of the file: path absolute; a regular file; it and its folder owned by root or this user and
 * not writable by every user (a sticky folder excepted); a 64-bit ELF shared object whose dynamic symbols define
 * `symbol`.  The handle, or NULL with the reason in err naming path (the program's window module is loaded so). */
INSTESS_API void *image_module_open(const char *path, const char *symbol, char *err, size_t errlen);
/* image_check of the image files a and b (read with image_read); IS_IMAGE_IO_ERROR names the unreadable one. */
INSTESS_API is_image_verdict image_check_files(const char *a, const char *b, float fail_thresh, float fail_percent,
                                   const char *diff_path, is_image_diff *res, char *err, size_t errlen);

/* Text for diagrams, in DejaVu Sans (/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf), rendered by
 * OpenImageIO's render_text and composited "over" the channels R, G, B (and A if present) with colour rgba
 * (not premultiplied, each 0..1; rgba[3] is the opacity); other channels (Z, AOVs) are untouched.  (x, y) is the left end
 * of the first line's baseline; '\n' starts a new line size_px lower; size_px is rounded to whole pixels
 * (1..4096).  Text must be printable ASCII (OpenImageIO 2.4 draws other characters wrongly: write "alpha",
 * "b0").  Pixels outside the image are clipped.  Returns 0, or -1 with a message in err. */
INSTESS_API int image_draw_text(is_image *img, int x, int y, const char *text, float size_px, const float rgba[4], char *err,
                    size_t errlen);
/* Width and height in pixels of the box that image_draw_text(text, size_px) covers (0 x 0 for ""); 0 or -1. */
INSTESS_API int image_text_size(const char *text, float size_px, int *w, int *h);

#ifdef __cplusplus
}
#endif
#endif
