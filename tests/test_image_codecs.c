/* tests/test_image_codecs.c -- the library's own PNG codec (image/image_png.c, libpng) and comparison
 * (image/image_diff.c) against the OpenImageIO module they replace for speed (libinstess_codec.so beside this
 * program, called directly: codec_read, codec_encode, codec_compare).  Value for value, bit for bit:
 *  - reading PNGs of every kind the fast path takes (8 and 16 bits; grey, grey + alpha, RGB, RGBA; interlaced;
 *    a gAMA chunk), every 8-bit and every 16-bit value, gives the module's channel names and floats; the PNGs it
 *    leaves to the module (palette with tRNS, 4-bit grey) read as the module reads them;
 *  - PNGs written by the library read back (through the module) as the module's own PNGs of the same image;
 *  - image_compare gives the module's every field (largest error and where, mean error to the last bit, failing
 *    and warning pixels) on random images with NaN and infinities, and the same diff image. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <dlfcn.h>
#include <limits.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../image/image_internal.h"   /* image_codec_host: the module is called directly, as the reference */

/* The module's entry points. */
typedef struct oiio_codec {
    int (*encode)(const is_image *, is_image_format, const is_image_meta *, const char *, unsigned char **, size_t *,
                  char *, size_t);
    int (*read)(is_image *, const char *, char *, size_t);
    int (*compare)(const is_image *, const is_image *, float, float, is_image_diff *, const char *, char *, size_t);
} oiio_codec;

/* The module beside this program, opened and handed the library's functions as image/image_codec.c does. */
static oiio_codec open_module(void)
{
    char exe[PATH_MAX], path[PATH_MAX + 32];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    assert_true(n > 0);
    exe[n] = 0;
    *strrchr(exe, '/') = 0;
    snprintf(path, sizeof path, "%s/libinstess_codec.so", exe);
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) fail_msg("cannot open %s: %s", path, dlerror());
    oiio_codec c;
    void (*set_host)(const image_codec_host *);
    *(void **)&c.encode = dlsym(h, "codec_encode");
    *(void **)&c.read = dlsym(h, "codec_read");
    *(void **)&c.compare = dlsym(h, "codec_compare");
    *(void **)&set_host = dlsym(h, "codec_set_host");
    assert_true(c.encode && c.read && c.compare && set_host);
    static const image_codec_host host = {image_alloc, image_channel_index, image_free, image_write};
    set_host(&host);
    return c;
}

typedef struct fixture { char dir[64]; oiio_codec oiio; } fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    if (!f) return -1;
    snprintf(f->dir, sizeof f->dir, "/tmp/instess-test-codecs-XXXXXX");
    if (!mkdtemp(f->dir)) return -1;
    f->oiio = open_module();
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    DIR *d = opendir(f->dir);
    struct dirent *e;
    char p[PATH_MAX];
    while (d && (e = readdir(d)) != NULL)
        if (e->d_name[0] != '.') snprintf(p, sizeof p, "%s/%s", f->dir, e->d_name), unlink(p);
    if (d) closedir(d);
    rmdir(f->dir);
    free(f);
    return 0;
}

/* A small deterministic generator (xorshift32). */
static uint32_t next_u32(uint32_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 17, *s ^= *s << 5;
    return *s;
}

/* Assert a and b have the same size, channel names and values, bit for bit; `what` names the case. */
static void assert_same_image(const is_image *a, const is_image *b, const char *what)
{
    if (a->width != b->width || a->height != b->height || a->channels != b->channels)
        fail_msg("%s: %dx%dx%d against %dx%dx%d", what, a->width, a->height, a->channels, b->width, b->height,
                 b->channels);
    for (int c = 0; c < a->channels; c++)
        if (strcmp(a->channel_names[c], b->channel_names[c]))
            fail_msg("%s: channel %d is %s against %s", what, c, a->channel_names[c], b->channel_names[c]);
    size_t n = (size_t)a->width * a->height * a->channels;
    for (size_t k = 0; k < n; k++)
        if (memcmp(&a->data[k], &b->data[k], sizeof(float)))
            fail_msg("%s: value %zu is %.9g against %.9g", what, k, (double)a->data[k], (double)b->data[k]);
}

/* ---------------------------------------------------------------- reading */

/* One test PNG's layout. */
typedef struct png_case {
    const char *name;
    int color_type, depth, interlace, w, h;
    bool gamma;
} png_case;

/* Write a PNG of case c with libpng directly: samples from a generator, which also visits every value of the
 * depth in order first (0, 1, ..., 255 or 65535). */
static void write_case(const char *path, const png_case *c)
{
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    png_structp p = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(p);
    assert_true(p && info);
    if (setjmp(png_jmpbuf(p))) fail_msg("libpng failed writing %s", path);
    png_init_io(p, fp);
    png_set_IHDR(p, info, (png_uint_32)c->w, (png_uint_32)c->h, c->depth, c->color_type, c->interlace,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (c->gamma) png_set_gAMA(p, info, 1.0 / 2.2);
    if (c->color_type == PNG_COLOR_TYPE_PALETTE) {
        png_color pal[4] = {{0, 0, 0}, {255, 0, 0}, {10, 200, 30}, {255, 255, 255}};
        png_byte trns[2] = {0, 128};
        png_set_PLTE(p, info, pal, 4);
        png_set_tRNS(p, info, trns, 2, NULL);
    }
    png_write_info(p, info);
    int nch = png_get_channels(p, info), bpv = c->depth == 16 ? 2 : 1;
    size_t rowbytes = png_get_rowbytes(p, info);
    unsigned char *img = calloc(rowbytes, (size_t)c->h);
    png_bytep *rows = calloc((size_t)c->h, sizeof *rows);
    uint32_t s = 12345, k = 0, top = c->depth == 16 ? 65535u : (1u << c->depth) - 1u;
    for (int y = 0; y < c->h; y++) {
        rows[y] = img + (size_t)y * rowbytes;
        if (c->depth < 8 || c->color_type == PNG_COLOR_TYPE_PALETTE) {   /* packed or indexed: small values */
            for (size_t b = 0; b < rowbytes; b++) rows[y][b] = (unsigned char)(next_u32(&s) & (c->color_type == PNG_COLOR_TYPE_PALETTE ? 0x3 : 0xff));
            continue;
        }
        for (int v = 0; v < c->w * nch; v++, k++) {
            uint32_t val = k <= top ? k : next_u32(&s) % (top + 1);
            if (bpv == 2) rows[y][2 * v] = (unsigned char)(val >> 8), rows[y][2 * v + 1] = (unsigned char)val;
            else rows[y][v] = (unsigned char)val;
        }
    }
    png_write_image(p, rows);
    png_write_end(p, info);
    png_destroy_write_struct(&p, &info);
    fclose(fp);
    free(rows);
    free(img);
}

/* Every PNG kind: image_read (libpng for most, the module for the rest) gives what the module gives. */
static void test_png_read_as_module(void **state)
{
    fixture *f = *state;
    static const png_case cases[] = {
        {"grey8", PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_NONE, 31, 9, false},
        {"greyalpha8", PNG_COLOR_TYPE_GRAY_ALPHA, 8, PNG_INTERLACE_NONE, 17, 8, false},
        {"rgb8", PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_NONE, 40, 7, false},
        {"rgba8", PNG_COLOR_TYPE_RGB_ALPHA, 8, PNG_INTERLACE_NONE, 33, 5, false},
        {"rgba8-adam7", PNG_COLOR_TYPE_RGB_ALPHA, 8, PNG_INTERLACE_ADAM7, 29, 13, false},
        {"rgb8-gamma", PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_NONE, 24, 6, true},
        {"grey16-all-values", PNG_COLOR_TYPE_GRAY, 16, PNG_INTERLACE_NONE, 256, 256, false},
        {"greyalpha16", PNG_COLOR_TYPE_GRAY_ALPHA, 16, PNG_INTERLACE_NONE, 21, 11, false},
        {"rgb16", PNG_COLOR_TYPE_RGB, 16, PNG_INTERLACE_ADAM7, 19, 17, false},
        {"rgba16", PNG_COLOR_TYPE_RGB_ALPHA, 16, PNG_INTERLACE_NONE, 23, 9, true},
        {"palette-trns", PNG_COLOR_TYPE_PALETTE, 8, PNG_INTERLACE_NONE, 12, 6, false},   /* left to the module */
        {"grey4", PNG_COLOR_TYPE_GRAY, 4, PNG_INTERLACE_NONE, 14, 3, false},             /* left to the module */
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char path[PATH_MAX], err[512] = "";
        snprintf(path, sizeof path, "%s/%s.png", f->dir, cases[k].name);
        write_case(path, &cases[k]);
        is_image ours, theirs;
        if (image_read(&ours, path, err, sizeof err) != 0) fail_msg("%s: %s", cases[k].name, err);
        if (f->oiio.read(&theirs, path, err, sizeof err) != 0) fail_msg("%s (module): %s", cases[k].name, err);
        assert_same_image(&ours, &theirs, cases[k].name);
        image_free(&ours);
        image_free(&theirs);
    }
}

/* A PNG cut short, and one whose header declares more than IS_IMAGE_MAX_DIM: messages name the file, nothing is
 * left allocated. */
static void test_png_read_bad(void **state)
{
    fixture *f = *state;
    char path[PATH_MAX], cut[PATH_MAX], err[512] = "";
    png_case c = {"big", PNG_COLOR_TYPE_RGB_ALPHA, 8, PNG_INTERLACE_NONE, 64, 64, false};
    snprintf(path, sizeof path, "%s/whole.png", f->dir);
    snprintf(cut, sizeof cut, "%s/cut.png", f->dir);
    write_case(path, &c);
    FILE *in = fopen(path, "rb"), *out = fopen(cut, "wb");
    unsigned char buf[200];
    assert_int_equal(fread(buf, 1, sizeof buf, in), sizeof buf);
    fwrite(buf, 1, sizeof buf, out);
    fclose(in), fclose(out);
    is_image img;
    assert_int_equal(image_read(&img, cut, err, sizeof err), -1);
    assert_non_null(strstr(err, cut));
    assert_null(img.data);
    /* the width in IHDR (bytes 16..19) raised to 70000: refused from the header, with the module's words */
    FILE *fp = fopen(path, "r+b");
    unsigned char w[4] = {0, 1, 0x11, 0x70};
    fseek(fp, 16, SEEK_SET), fwrite(w, 1, 4, fp), fclose(fp);
    assert_int_equal(image_read(&img, path, err, sizeof err), -1);
    assert_non_null(strstr(err, path));
    assert_null(img.data);
}

/* ---------------------------------------------------------------- writing */

/* Images of 1 to 5 channels with values inside, outside and between the 8-bit steps (and NaN): the library's
 * PNG and the module's PNG of the same image read back (by the module) alike. */
static void test_png_write_as_module(void **state)
{
    fixture *f = *state;
    static const char *const names[] = {"Y", "Y,A", "R,G,B", "R,G,B,A", "R,G,B,A,Z"};
    uint32_t s = 777;
    for (int k = 0; k < 5; k++) {
        char err[512] = "", pa[PATH_MAX], pb[PATH_MAX];
        is_image img, a, b;
        assert_int_equal(image_alloc(&img, 37, 11, names[k], err, sizeof err), 0);
        size_t n = (size_t)img.width * img.height * img.channels;
        for (size_t v = 0; v < n; v++) {
            uint32_t r = next_u32(&s);
            img.data[v] = v < 256 ? (float)v / 255.0f : r % 17 == 0 ? NAN : r % 13 == 0 ? -0.5f : r % 11 == 0 ? 1.5f
                        : (float)(r % 100000) / 99999.0f;
        }
        is_image_meta meta = {"instess test", "one description"};
        unsigned char *bytes = NULL;
        size_t len = 0;
        assert_int_equal(image_encode(&img, IS_IMAGE_PNG, &meta, "ours", &bytes, &len, err, sizeof err), 0);
        snprintf(pa, sizeof pa, "%s/ours%d.png", f->dir, k);
        FILE *fp = fopen(pa, "wb");
        assert_int_equal(fwrite(bytes, 1, len, fp), len);
        fclose(fp);
        free(bytes);
        assert_int_equal(f->oiio.encode(&img, IS_IMAGE_PNG, &meta, "theirs", &bytes, &len, err, sizeof err), 0);
        snprintf(pb, sizeof pb, "%s/theirs%d.png", f->dir, k);
        fp = fopen(pb, "wb");
        assert_int_equal(fwrite(bytes, 1, len, fp), len);
        fclose(fp);
        free(bytes);
        assert_int_equal(f->oiio.read(&a, pa, err, sizeof err), 0);
        assert_int_equal(f->oiio.read(&b, pb, err, sizeof err), 0);
        assert_same_image(&a, &b, names[k]);
        image_free(&a);
        image_free(&b);
        image_free(&img);
    }
}

/* ---------------------------------------------------------------- comparing */

/* Assert every field image_compare fills is the module's, bit for bit. */
static void assert_same_diff(const is_image_diff *x, const is_image_diff *y, const char *what)
{
    if (memcmp(&x->max_error, &y->max_error, sizeof x->max_error) || memcmp(&x->mean_error, &y->mean_error,
                                                                            sizeof x->mean_error))
        fail_msg("%s: max %.9g mean %.17g against max %.9g mean %.17g", what, (double)x->max_error, x->mean_error,
                 (double)y->max_error, y->mean_error);
    if (x->n_fail != y->n_fail || x->n_warn != y->n_warn || x->n_pixels != y->n_pixels)
        fail_msg("%s: fail %ld warn %ld of %ld against fail %ld warn %ld of %ld", what, x->n_fail, x->n_warn,
                 x->n_pixels, y->n_fail, y->n_warn, y->n_pixels);
    if (x->max_x != y->max_x || x->max_y != y->max_y || x->max_channel != y->max_channel)
        fail_msg("%s: largest at %d,%d channel %d against %d,%d channel %d", what, x->max_x, x->max_y,
                 x->max_channel, y->max_x, y->max_y, y->max_channel);
}

/* A pair of w x h images of ch channels: b is a plus noise on some values; `special` plants non-finite values
 * (0 none, 1 NaN against numbers and NaN, 2 infinities of both signs against numbers and each other, 3 both);
 * special 4 adds differences of every size from 1e-30 to 1e30, whose double sums depend on their grouping (the
 * mean error is summed in batches of 4096 pixels, as the module does). */
static void make_pair(is_image *a, is_image *b, int w, int h, int ch, int special, uint32_t seed)
{
    static const char *const names[] = {"R", "R,G", "R,G,B", "R,G,B,A", "R,G,B,A,Z"};
    char err[256];
    assert_int_equal(image_alloc(a, w, h, names[ch - 1], err, sizeof err), 0);
    assert_int_equal(image_alloc(b, w, h, names[ch - 1], err, sizeof err), 0);
    uint32_t s = seed;
    size_t n = (size_t)w * h * ch;
    for (size_t k = 0; k < n; k++) {
        uint32_t r = next_u32(&s);
        a->data[k] = (float)(r % 1000) / 999.0f;
        b->data[k] = a->data[k] + (r % 7 == 0 ? (float)((int)(r >> 8) % 2001 - 1000) * 1e-4f : 0.0f);
        if (special & 1 && r % 97 == 0) a->data[k] = NAN;
        if (special & 1 && r % 89 == 0) b->data[k] = NAN;
        if (special & 1 && r % 83 == 0) a->data[k] = b->data[k] = NAN;
        if (special & 2 && r % 79 == 0) a->data[k] = r & 256 ? INFINITY : -INFINITY;
        if (special & 2 && r % 73 == 0) b->data[k] = -INFINITY, a->data[k] = INFINITY;
        if (special & 2 && r % 71 == 0) a->data[k] = b->data[k] = INFINITY;
        if (special & 4 && r % 3 == 0) b->data[k] = a->data[k] + powf(10.0f, (float)((int)(r >> 9) % 61 - 30));
    }
}

/* Random pairs (one over several 4096-pixel batches), with and without NaN and infinities, at several
 * thresholds: image_compare gives the module's numbers; the diff images are the same pixels. */
static void test_compare_as_module(void **state)
{
    fixture *f = *state;
    static const struct { int w, h, ch; } sizes[] = {{3, 2, 1}, {70, 60, 5}, {130, 40, 4}, {9, 7, 2}, {64, 65, 3}};
    static const float thresholds[][2] = {{0.0f, 0.0f}, {0.05f, 0.01f}, {1e-3f, 1e-3f}, {0.2f, 0.0f}};
    int cases = 0;
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++)
        for (int special = 0; special < 8; special++)
            for (size_t t = 0; t < sizeof thresholds / sizeof thresholds[0]; t++) {
                is_image a, b;
                is_image_diff ours, theirs;
                char err[512] = "", what[128];
                make_pair(&a, &b, sizes[k].w, sizes[k].h, sizes[k].ch, special, (uint32_t)(1 + k * 31 + special * 7 + t));
                snprintf(what, sizeof what, "%dx%dx%d, special %d, thresholds %g/%g", sizes[k].w, sizes[k].h,
                         sizes[k].ch, special, (double)thresholds[t][0], (double)thresholds[t][1]);
                memset(&ours, 0, sizeof ours), memset(&theirs, 0, sizeof theirs);
                assert_int_equal(image_compare(&a, &b, thresholds[t][0], thresholds[t][1], &ours, NULL, err, sizeof err), 0);
                assert_int_equal(f->oiio.compare(&a, &b, thresholds[t][0], thresholds[t][1], &theirs, NULL, err,
                                                 sizeof err), 0);
                assert_same_diff(&ours, &theirs, what);
                if (special == 0 && t == 1) {   /* the diff images, finite pairs */
                    char pa[PATH_MAX], pb[PATH_MAX];
                    is_image da, db;
                    snprintf(pa, sizeof pa, "%s/diff-ours.png", f->dir);
                    snprintf(pb, sizeof pb, "%s/diff-theirs.png", f->dir);
                    assert_int_equal(image_compare(&a, &b, thresholds[t][0], thresholds[t][1], &ours, pa, err, sizeof err), 0);
                    assert_int_equal(f->oiio.compare(&a, &b, thresholds[t][0], thresholds[t][1], &theirs, pb, err,
                                                     sizeof err), 0);
                    assert_int_equal(image_read(&da, pa, err, sizeof err), 0);
                    assert_int_equal(image_read(&db, pb, err, sizeof err), 0);
                    assert_same_image(&da, &db, what);
                    image_free(&da);
                    image_free(&db);
                }
                image_free(&a);
                image_free(&b);
                cases++;
            }
    assert_int_equal(cases, 160);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_png_read_as_module, setup, teardown),
        cmocka_unit_test_setup_teardown(test_png_read_bad, setup, teardown),
        cmocka_unit_test_setup_teardown(test_png_write_as_module, setup, teardown),
        cmocka_unit_test_setup_teardown(test_compare_as_module, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
