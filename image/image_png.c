/* image/image_png.c -- PNG files through libpng, without OpenImageIO.
 *
 * Why: every process that wrote or read a PNG loaded the codec module and with it OpenImageIO's ~260 libraries,
 * about 0.4 s of binding symbols (measured with perf: three quarters of the time in the dynamic loader's
 * symbol lookup, OpenVDB and GDAL alone half of the relocations) for a few milliseconds of work.  PNG is what
 * renders, goldens and diff images are written in, so it goes through libpng (two small libraries) here, and
 * `instess -o x.png` or `instess compare a.png b.png` never load OpenImageIO.
 *
 * Same files, same values as the module (tests/test_image.c compares both, value for value):
 *  - writing: the first four channels (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA), clamped to [0, 1] and rounded
 *    to 8 bits (NaN as 0), colour stored as given (no premultiplication); tEXt "Software" and "Description"
 *    (OpenImageIO's names for Software and ImageDescription); no time, so one render writes the same bytes;
 *  - reading: every PNG, expanded as OpenImageIO's reader expands it (a palette to RGB, grey of 1, 2 or 4 bits
 *    to 8, a tRNS transparency key to an alpha channel), comes back as k / 255 or k / 65535 with OpenImageIO's
 *    channel names (Y, A for grey), values as stored (no gamma applied, no premultiplication).  No PNG goes to
 *    the module: OpenImageIO 2.4 left libpng's default handlers, which printed on the caller's stderr; here
 *    libpng's errors go into err and its warnings are dropped.  The size limits of image/image.h are checked
 *    from the header, with the module's messages, and so is deflate's ratio: a header declaring more samples
 *    than the file's bytes can inflate to is refused before any allocation. */
#include "image_internal.h"

#include <png.h>
#include <setjmp.h>
#include <sys/stat.h>

/* What libpng's error callback needs: where to put the message. */
typedef struct png_ctx {
    char msg[256];
} png_ctx;

/* libpng's error callback: keep the message, leave through png_jmpbuf. */
static void on_png_error(png_structp p, png_const_charp msg)
{
    png_ctx *c = png_get_error_ptr(p);
    snprintf(c->msg, sizeof c->msg, "%s", msg);
    png_longjmp(p, 1);
}

/* libpng's warnings (a bad ancillary chunk, which libpng skips) are not errors. */
static void on_png_warning(png_structp p, png_const_charp msg)
{
    (void)p, (void)msg;
}

/* ---------------------------------------- writing ---------------------------------------- */

/* A growing buffer for the encoded bytes. */
typedef struct png_out {
    unsigned char *bytes;
    size_t len, cap;
    bool failed;
} png_out;

/* libpng's write callback: append n bytes (an error when out of memory). */
static void png_append(png_structp p, png_bytep data, size_t n)
{
    png_out *o = png_get_io_ptr(p);
    if (o->len + n > o->cap) {
        size_t cap = o->cap ? o->cap : 65536;
        while (cap < o->len + n) cap *= 2;
        unsigned char *b = realloc(o->bytes, cap);
        if (!b) o->failed = true, png_error(p, "out of memory for the encoded bytes");
        o->bytes = b, o->cap = cap;
    }
    memcpy(o->bytes + o->len, data, n);
    o->len += n;
}

static void png_flush_nothing(png_structp p) { (void)p; }

/* Value v of a channel as an 8-bit PNG sample: clamped to [0, 1], NaN as 0, rounded. */
static unsigned char quantize8(float v)
{
    v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;   /* also maps NaN to 0 */
    return (unsigned char)(v * 255.0f + 0.5f);
}

/* The body of image_png_encode between setjmp and the clean-up: header, text, rows into o. */
static void encode_rows(png_structp p, png_infop info, const is_image *img, const is_image_meta *meta, int nch,
                        unsigned char *row)
{
    static const int types[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                 PNG_COLOR_TYPE_RGB_ALPHA};
    png_set_IHDR(p, info, (png_uint_32)img->width, (png_uint_32)img->height, 8, types[nch - 1], PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_text text[2];
    int nt = 0;
    memset(text, 0, sizeof text);
    if (meta && meta->software)
        text[nt].compression = PNG_TEXT_COMPRESSION_NONE, text[nt].key = "Software",
        text[nt++].text = (char *)meta->software;
    if (meta && meta->description)
        text[nt].compression = PNG_TEXT_COMPRESSION_NONE, text[nt].key = "Description",
        text[nt++].text = (char *)meta->description;
    if (nt) png_set_text(p, info, text, nt);
    png_write_info(p, info);
    for (int y = 0; y < img->height; y++) {
        const float *src = img->data + (size_t)y * (size_t)img->width * (size_t)img->channels;
        for (int x = 0; x < img->width; x++)
            for (int c = 0; c < nch; c++) row[(size_t)x * (size_t)nch + (size_t)c] = quantize8(src[(size_t)x * (size_t)img->channels + (size_t)c]);
        png_write_row(p, row);
    }
    png_write_end(p, info);
}

int image_png_encode(const is_image *img, const is_image_meta *meta, const char *label, unsigned char **bytes,
                     size_t *len, char *err, size_t errlen)
{
    int nch = image_file_channel_count(img->channels, IS_IMAGE_PNG);
    png_ctx ctx = {""};
    png_out out = {0};
    unsigned char *row = malloc((size_t)img->width * 4);
    png_structp p = row ? png_create_write_struct(PNG_LIBPNG_VER_STRING, &ctx, on_png_error, on_png_warning) : NULL;
    png_infop info = p ? png_create_info_struct(p) : NULL;
    if (!info) {
        png_destroy_write_struct(&p, NULL);
        free(row);
        return image_set_err(err, errlen, "%s: out of memory for the PNG encoder", label), -1;
    }
    int rc = -1;
    if (setjmp(png_jmpbuf(p)) == 0) {
        png_set_write_fn(p, &out, png_append, png_flush_nothing);
        encode_rows(p, info, img, meta, nch, row);
        rc = 0;
    }
    png_destroy_write_struct(&p, &info);
    free(row);
    if (rc != 0) {
        free(out.bytes);
        return image_set_err(err, errlen, "%s: encoding failed: %s", label, ctx.msg), -1;
    }
    *bytes = out.bytes, *len = out.len;
    return 0;
}

/* ---------------------------------------- reading ---------------------------------------- */

/* The channel names OpenImageIO gives a PNG of n channels. */
static const char *png_channel_names(int n)
{
    static const char *const names[4] = {"Y", "Y,A", "R,G,B", "R,G,B,A"};
    return names[n - 1];
}

/* Row `y` of raw samples (bit depth 8 or 16, big-endian) as floats into img. */
static void convert_row(is_image *img, int y, const unsigned char *row, int depth)
{
    size_t n = (size_t)img->width * (size_t)img->channels;
    float *dst = img->data + (size_t)y * n;
    if (depth == 8)
        for (size_t k = 0; k < n; k++) dst[k] = (float)row[k] * (1.0f / 255.0f);
    else
        for (size_t k = 0; k < n; k++) dst[k] = (float)((row[2 * k] << 8) | row[2 * k + 1]) * (1.0f / 65535.0f);
}

/* What reading the header decided. */
enum { PNG_TAKEN = 0, PNG_FAILED = -1, PNG_TO_MODULE = 1 };

/* deflate's best ratio (RFC 1951: a 258-byte match in 2 bits, about 1032 to 1): the samples a PNG of n bytes can
 * hold at most, so that a header declaring more is refused before any allocation. */
#define PNG_MAX_DEFLATE_RATIO 1032ull

/* The input of one read: the file and its size. */
typedef struct png_in {
    FILE *f;
    long long size;
} png_in;

/* libpng's read callback: n bytes from the file, or an error saying the file ends early. */
static void png_read_bytes(png_structp p, png_bytep data, size_t n)
{
    png_in *in = png_get_io_ptr(p);
    if (fread(data, 1, n, in->f) != n)
        png_error(p, ferror(in->f) ? "read error" : "truncated: the file ends before the image does");
}

/* The transformations that give every PNG as 8- or 16-bit samples (palette to RGB, grey below 8 bits to 8, a
 * tRNS transparency key to an alpha channel), as OpenImageIO's PNG reader applies them; the number of passes. */
static int set_expansions(png_structp p, png_infop info)
{
    int type = png_get_color_type(p, info), depth = png_get_bit_depth(p, info);
    if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(p);
    if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(p);
    if (png_get_valid(p, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(p);
    int passes = png_set_interlace_handling(p);
    png_read_update_info(p, info);
    return passes;
}

/* The header of the open PNG p (in: the file): PNG_TAKEN with img allocated and *passes set, or PNG_FAILED with
 * the message for the sizes refused -- sides, values, and samples more than the file's bytes can inflate to. */
static int read_header(png_structp p, png_infop info, const png_in *in, const char *path, is_image *img,
                       int *passes, char *err, size_t errlen)
{
    png_read_info(p, info);
    png_uint_32 w = png_get_image_width(p, info), h = png_get_image_height(p, info);
    /* the inflated bytes: a filter byte and the samples per row (interlaced: at least the samples) */
    unsigned long long raw = (unsigned long long)png_get_rowbytes(p, info) * h;
    *passes = set_expansions(p, info);
    if (*passes == 1) raw += h;
    int nch = png_get_channels(p, info);
    if (w > IS_IMAGE_MAX_DIM || h > IS_IMAGE_MAX_DIM) {
        image_set_err(err, errlen, "%s: unsupported size %ux%ux1 with %d channels (at most %d channels, %d pixels "
                      "wide)", path, (unsigned)w, (unsigned)h, nch, IS_IMAGE_MAX_CHANNELS, IS_IMAGE_MAX_DIM);
        return PNG_FAILED;
    }
    unsigned long long values = (unsigned long long)w * h * (unsigned)nch;
    if (values > IS_IMAGE_MAX_VALUES) {
        image_set_err(err, errlen, "%s: the header declares %ux%u pixels with %d channels (%llu values), more than "
                      "the limit of %llu (1 GiB of floats); nothing decoded", path, (unsigned)w, (unsigned)h, nch,
                      values, (unsigned long long)IS_IMAGE_MAX_VALUES);
        return PNG_FAILED;
    }
    if (raw > (unsigned long long)in->size * PNG_MAX_DEFLATE_RATIO) {
        image_set_err(err, errlen, "%s: the header declares %ux%u pixels (%llu bytes of samples), more than the "
                      "file's %lld bytes can hold (deflate packs at most %llu to 1); nothing decoded", path,
                      (unsigned)w, (unsigned)h, raw, in->size, PNG_MAX_DEFLATE_RATIO);
        return PNG_FAILED;
    }
    return image_alloc(img, (int)w, (int)h, png_channel_names(nch), err, errlen) == 0 ? PNG_TAKEN : PNG_FAILED;
}

/* The pixels of p into img (allocated, the expansions set); rows is a buffer of one row, or of the whole image
 * when interlaced (passes > 1). */
static void read_pixels(png_structp p, png_infop info, is_image *img, int passes, unsigned char *rows,
                        size_t rowbytes)
{
    int depth = png_get_bit_depth(p, info);
    if (passes == 1) {
        for (int y = 0; y < img->height; y++) {
            png_read_row(p, rows, NULL);
            convert_row(img, y, rows, depth);
        }
    } else {
        for (int pass = 0; pass < passes; pass++)
            for (int y = 0; y < img->height; y++) png_read_row(p, rows + (size_t)y * rowbytes, NULL);
        for (int y = 0; y < img->height; y++) convert_row(img, y, rows + (size_t)y * rowbytes, depth);
    }
    png_read_end(p, NULL);
}

/* The state of one read, kept outside the setjmp frame (volatile: changed after setjmp). */
typedef struct png_read_state {
    png_structp p;
    png_infop info;
    unsigned char *rows;
    int decided, passes;
} png_read_state;

/* Read the PNG in `in` into img: PNG_TAKEN or PNG_FAILED (message in err).  libpng's errors and warnings go
 * to on_png_error / on_png_warning: nothing is printed on the caller's stderr. */
static int read_png(png_in *in, const char *path, is_image *img, char *err, size_t errlen)
{
    png_ctx ctx = {""};
    volatile png_read_state s = {NULL, NULL, NULL, PNG_FAILED, 1};
    s.p = png_create_read_struct(PNG_LIBPNG_VER_STRING, &ctx, on_png_error, on_png_warning);
    s.info = s.p ? png_create_info_struct(s.p) : NULL;
    if (!s.info) {
        png_structp p = s.p;
        png_destroy_read_struct(&p, NULL, NULL);
        return image_set_err(err, errlen, "%s: out of memory for the PNG decoder", path), PNG_FAILED;
    }
    int rc = PNG_FAILED;
    if (setjmp(png_jmpbuf(s.p)) == 0) {
        png_set_read_fn(s.p, in, png_read_bytes);
        png_set_user_limits(s.p, 0x7fffffff, 0x7fffffff);   /* the sizes are checked above, with our messages */
        int passes = 1;
        s.decided = read_header(s.p, s.info, in, path, img, &passes, err, errlen);
        s.passes = passes;
        if (s.decided == PNG_TAKEN) {
            size_t rowbytes = png_get_rowbytes(s.p, s.info);
            s.rows = malloc(rowbytes * (passes == 1 ? 1 : (size_t)img->height));
            if (!s.rows) png_error(s.p, "out of memory for the rows");
            read_pixels(s.p, s.info, img, passes, s.rows, rowbytes);
        }
        rc = s.decided;
    } else {   /* libpng's error: the file is bad */
        image_set_err(err, errlen, "%s: cannot read: %s", path, ctx.msg);
    }
    if (rc != PNG_TAKEN && s.decided == PNG_TAKEN) image_free(img);
    png_structp p = s.p;
    png_infop info = s.info;
    png_destroy_read_struct(&p, &info, NULL);
    free(s.rows);
    return rc == PNG_TAKEN ? PNG_TAKEN : PNG_FAILED;
}

int image_png_read(is_image *img, const char *path, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f) return PNG_TO_MODULE;   /* image_read has said why already; the module says it again */
    struct stat st;
    png_in in = {f, fstat(fileno(f), &st) == 0 ? (long long)st.st_size : 0};
    unsigned char sig[8];
    int rc = PNG_TO_MODULE;
    if (fread(sig, 1, sizeof sig, f) == sizeof sig && png_sig_cmp(sig, 0, sizeof sig) == 0) {
        rewind(f);
        memset(img, 0, sizeof *img);
        rc = read_png(&in, path, img, err, errlen);
    }
    fclose(f);
    return rc;
}
