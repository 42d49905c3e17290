/* tests/test_hostile_images.c -- hostile input, round 3, family 1: `instess compare` and every image reader
 * (image_read, image_read_info, image_check, image_compare) on files anyone could hand them.  Each case is in
 * docs/robustness.md ("Round 3: images, files and environment") with its message.
 *
 * The PNG files are written here byte by byte (stored deflate blocks, so any header can be declared); the
 * tiled, multi-part and deep OpenEXR files come from oiiotool (scripts/setup.sh installs it).  Runs
 * build/instess or $INSTESS_BIN. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

char *realpath(const char *path, char *resolved);   /* POSIX; glibc declares it only with _DEFAULT_SOURCE */
int symlink(const char *target, const char *linkpath);
int mkfifo(const char *path, mode_t mode);

#include "util/prog.h"
#include "../core/core.h"
#include "../image/image.h"

static char dir[256];
static char out_buf[16384], err_buf[16384];

/* Run `instess ARGS` in dir (cd there) with stdout into out_buf and stderr into err_buf; the exit code.  A
 * command that would block forever (a FIFO opened) is killed after 120 s by `timeout` -- a bound, not a
 * measurement: the assertions are on the exit code and the message. */
static int run(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static int run(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = prog_vrun_in(dir, "timeout -s KILL 120", NULL, ">out.txt 2>err.txt", fmt, ap);
    va_end(ap);
    prog_read_text(dir, "out.txt", out_buf, sizeof out_buf);
    prog_read_text(dir, "err.txt", err_buf, sizeof err_buf);
    return rc;
}

/* The number of lines of s. */
static int lines_of(const char *s)
{
    int n = 0;
    for (; *s; s++) n += *s == '\n';
    return n;
}

/* Assert that the last run failed with `code`, its one line on stderr naming `name` and containing `what`
 * (libpng or OpenImageIO printing on their own would add lines). */
static void expect_refusal(int rc, int code, const char *name, const char *what)
{
    if (rc != code || !strstr(err_buf, name) || !strstr(err_buf, what) || lines_of(err_buf) != 1)
        print_message("MISMATCH expected exit %d naming %s with \"%s\", got %d:\n%s", code, name, what, rc, err_buf);
}

/* ------------------------------------------------------------ PNG bytes */

typedef struct bytes {
    unsigned char *b;
    size_t n, cap;
} bytes;

/* Append n bytes to o. */
static void put(bytes *o, const void *p, size_t n)
{
    if (o->n + n > o->cap) {
        o->cap = (o->n + n) * 2 + 64;
        o->b = realloc(o->b, o->cap);
        assert_non_null(o->b);
    }
    memcpy(o->b + o->n, p, n);
    o->n += n;
}

/* Append v big-endian. */
static void put32(bytes *o, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)(v >> 24), (unsigned char)(v >> 16), (unsigned char)(v >> 8),
                          (unsigned char)v};
    put(o, b, 4);
}

/* CRC-32 of PNG chunks (bitwise: the files are small). */
static uint32_t crc32_of(const unsigned char *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    for (size_t k = 0; k < n; k++) {
        c ^= p[k];
        for (int b = 0; b < 8; b++) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return ~c;
}

/* A chunk of type t with n bytes of data into o. */
static void chunk(bytes *o, const char *t, const unsigned char *data, size_t n)
{
    bytes c = {0};
    put(&c, t, 4);
    if (n) put(&c, data, n);
    put32(o, (uint32_t)n);
    put(o, c.b, c.n);
    put32(o, crc32_of(c.b, c.n));
    free(c.b);
}

/* raw (n bytes) as a zlib stream of stored blocks into o. */
static void zlib_stored(bytes *o, const unsigned char *raw, size_t n)
{
    put(o, "\x78\x01", 2);
    size_t k = 0;
    do {
        size_t len = n - k < 65535 ? n - k : 65535;
        unsigned char h[5] = {(unsigned char)(k + len == n), (unsigned char)len, (unsigned char)(len >> 8),
                              (unsigned char)~len, (unsigned char)(~len >> 8)};
        put(o, h, 5);
        if (len) put(o, raw + k, len);
        k += len;
    } while (k < n);
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < n; i++) a = (a + raw[i]) % 65521u, b = (b + a) % 65521u;
    put32(o, (b << 16) | a);
}

/* What a PNG file declares and holds: IHDR fields, optional PLTE and tRNS, the filtered scanlines (filter
 * byte 0 per row, passes in Adam7 order when interlaced). */
typedef struct png_desc {
    uint32_t w, h;
    int depth, ctype, interlace;
    const unsigned char *plte, *trns;
    size_t n_plte, n_trns;
    const unsigned char *raw;
    size_t n_raw;
} png_desc;

/* The bytes of the PNG file d into o (o->b malloc'ed). */
static void png_bytes(const png_desc *d, bytes *o)
{
    *o = (bytes){0};
    put(o, "\x89PNG\r\n\x1a\n", 8);
    unsigned char ihdr[13] = {(unsigned char)(d->w >> 24), (unsigned char)(d->w >> 16), (unsigned char)(d->w >> 8),
                              (unsigned char)d->w, (unsigned char)(d->h >> 24), (unsigned char)(d->h >> 16),
                              (unsigned char)(d->h >> 8), (unsigned char)d->h, (unsigned char)d->depth,
                              (unsigned char)d->ctype, 0, 0, (unsigned char)d->interlace};
    chunk(o, "IHDR", ihdr, 13);
    if (d->plte) chunk(o, "PLTE", d->plte, d->n_plte);
    if (d->trns) chunk(o, "tRNS", d->trns, d->n_trns);
    bytes z = {0};
    zlib_stored(&z, d->raw, d->n_raw);
    chunk(o, "IDAT", z.b, z.n);
    free(z.b);
    chunk(o, "IEND", NULL, 0);
}

/* Write the PNG file d as dir/name. */
static void write_png(const char *name, const png_desc *d)
{
    bytes o;
    png_bytes(d, &o);
    assert_true(prog_write_bytes(dir, name, o.b, o.n));
    free(o.b);
}

/* The filtered scanlines of w x h pixels of bpp bytes each (px, row-major), non-interlaced (interlace 0) or in
 * Adam7's seven passes (1), into o. */
static void scanlines(const unsigned char *px, uint32_t w, uint32_t h, int bpp, int interlace, bytes *o)
{
    static const int x0[7] = {0, 4, 0, 2, 0, 1, 0}, y0[7] = {0, 0, 4, 0, 2, 0, 1};
    static const int dx[7] = {8, 8, 4, 4, 2, 2, 1}, dy[7] = {8, 8, 8, 4, 4, 2, 2};
    *o = (bytes){0};
    for (int p = 0; p < (interlace ? 7 : 1); p++) {
        int sx = interlace ? x0[p] : 0, sy = interlace ? y0[p] : 0, ex = interlace ? dx[p] : 1,
            ey = interlace ? dy[p] : 1;
        if ((uint32_t)sx >= w) continue;   /* an empty pass has no rows at all */
        for (uint32_t y = (uint32_t)sy; y < h; y += (uint32_t)ey) {
            put(o, "", 1);
            for (uint32_t x = (uint32_t)sx; x < w; x += (uint32_t)ex) put(o, px + ((size_t)y * w + x) * bpp, (size_t)bpp);
        }
    }
}

/* A w x h test pattern of n channels of 8 bits: every value distinct enough to catch a swapped channel. */
static unsigned char *pattern8(uint32_t w, uint32_t h, int n)
{
    unsigned char *p = malloc((size_t)w * h * n);
    for (size_t k = 0; k < (size_t)w * h * n; k++) p[k] = (unsigned char)(k * 37u + (k / (size_t)n) * 11u + 5u);
    return p;
}

/* Write an 8-bit RGBA (ctype 6) or RGB (2) PNG of the pattern as dir/name. */
static void write_pattern_png(const char *name, uint32_t w, uint32_t h, int ctype, int interlace)
{
    int n = ctype == 6 ? 4 : 3;
    unsigned char *px = pattern8(w, h, n);
    bytes raw;
    scanlines(px, w, h, n, interlace, &raw);
    png_desc d = {.w = w, .h = h, .depth = 8, .ctype = ctype, .interlace = interlace, .raw = raw.b, .n_raw = raw.n};
    write_png(name, &d);
    free(raw.b);
    free(px);
}

/* A header-only PNG: IHDR declaring w x h (depth, ctype) and one IDAT of `idat` zero bytes stored. */
static void write_declaring_png(const char *name, uint32_t w, uint32_t h, int depth, int ctype, size_t idat)
{
    unsigned char *zero = calloc(idat + 1, 1);
    png_desc d = {.w = w, .h = h, .depth = depth, .ctype = ctype, .raw = zero, .n_raw = idat};
    write_png(name, &d);
    free(zero);
}

/* ------------------------------------------------------------ fixture */

static int setup(void **state)
{
    (void)state;
    if (prog_mkdtemp(dir, "himg") != 0) return -1;
    /* a.png / b.png: two renders of one size; c.png: another size; a.exr: RGBA, Z and a depth AOV */
    return run("--size 32x32 --level 2 -q -o a.png") || run("--size 32x32 --level 3 -q -o b.png") ||
           run("--size 48x48 -q -o c.png") || run("--size 32x32 -q --aov depth -o a.exr");
}

static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

/* dir/name as a path into buf. */
static const char *at(const char *name, char *buf, size_t len)
{
    return prog_path(dir, name, buf, len);
}

/* The whole file dir/name (malloc'ed, *n bytes). */
static unsigned char *slurp(const char *name, size_t *n)
{
    char p[512];
    unsigned char *b = prog_slurp(at(name, p, sizeof p), n);
    assert_non_null(b);
    return b;
}

/* ------------------------------------------------------------ NaN and infinities */

/* Two 4x2 images R,G,B,A,Z: equal, then with the values of one pixel's channel c set to va and vb. */
static void nonfinite_pair(is_image *a, is_image *b, int c, float va, float vb)
{
    char err[256];
    assert_int_equal(image_alloc(a, 4, 2, "R,G,B,A,Z", err, sizeof err), 0);
    assert_int_equal(image_alloc(b, 4, 2, "R,G,B,A,Z", err, sizeof err), 0);
    for (size_t k = 0; k < 4 * 2 * 5; k++) a->data[k] = b->data[k] = 0.25f + 0.01f * (float)k;
    a->data[5 * 5 + c] = va;
    b->data[5 * 5 + c] = vb;
}

/* image_check: NaN against a number, +inf against -inf and an infinity against a finite value fail whatever the
 * difference threshold (each counted as a non-finite mismatch; --failpercent still allows that many pixels); NaN against NaN and an infinity against itself match;
 * finite values as far apart as floats go do not overflow into a false match. */
static void test_nonfinite_library(void **state)
{
    (void)state;
    const struct { float a, b; is_image_verdict v; long nonfinite; } cases[] = {
        {NAN, 0.5f, IS_IMAGE_DIFFERENT, 1},          {0.5f, NAN, IS_IMAGE_DIFFERENT, 1},
        {INFINITY, -INFINITY, IS_IMAGE_DIFFERENT, 1}, {INFINITY, 1.0f, IS_IMAGE_DIFFERENT, 1},
        {-INFINITY, NAN, IS_IMAGE_DIFFERENT, 1},      {NAN, NAN, IS_IMAGE_PASS, 0},
        {-NAN, NAN, IS_IMAGE_PASS, 0},                {INFINITY, INFINITY, IS_IMAGE_PASS, 0},
        {-INFINITY, -INFINITY, IS_IMAGE_PASS, 0},     {3e38f, -3e38f, IS_IMAGE_DIFFERENT, 0},
    };
    for (int c = 0; c < 5; c += 4)   /* a colour channel and Z */
        for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
            is_image a, b;
            is_image_diff d;
            char err[256] = "";
            nonfinite_pair(&a, &b, c, cases[k].a, cases[k].b);
            /* the widest difference the program takes: --fail 1e30 (no pixel allowed to fail) */
            is_image_verdict v = image_check(&a, &b, cases[k].nonfinite ? 1e30f : 1.0f, 0.0f, NULL, &d, err,
                                             sizeof err);
            if (cases[k].v == IS_IMAGE_DIFFERENT && !cases[k].nonfinite)   /* 6e38 apart: beyond any threshold */
                v = image_check(&a, &b, 1e30f, 0.0f, NULL, &d, err, sizeof err);
            if (v != cases[k].v || d.n_nonfinite != cases[k].nonfinite)
                fail_msg("channel %d, %g against %g: verdict %d (want %d), %ld non-finite", c, (double)cases[k].a,
                         (double)cases[k].b, v, cases[k].v, d.n_nonfinite);
            if (cases[k].nonfinite) assert_int_equal(d.n_fail, 1);
            assert_true(isfinite(d.mean_error));
            image_free(&a);
            image_free(&b);
        }
}

/* The diff image marks a non-finite mismatch full red, like the largest difference. */
static void test_nonfinite_diff_image(void **state)
{
    (void)state;
    is_image a, b, d;
    is_image_diff res;
    char path[512], err[512];
    nonfinite_pair(&a, &b, 4, NAN, 0.5f);
    assert_int_equal(image_check(&a, &b, 0.0f, 0.0f, at("nan-diff.png", path, sizeof path), &res, err, sizeof err),
                     IS_IMAGE_DIFFERENT);
    assert_int_equal(image_read(&d, path, err, sizeof err), 0);
    const float *p = d.data + 5 * 4;   /* pixel (1, 1) */
    assert_true(p[0] == 1.0f && p[1] == 0.0f && p[2] == 0.0f);
    image_free(&a);
    image_free(&b);
    image_free(&d);
}

/* `instess compare` on OpenEXR files: NaN where the other has a number, +inf against -inf: exit 1 with the
 * count of non-finite mismatches, also with --fail 1e30; the same NaN in both: identical; --failpercent 100
 * allows every pixel to fail (the mismatch still reported). */
static void test_nonfinite_compare(void **state)
{
    (void)state;
    is_image a, b;
    char path[512], err[512];
    const struct { const char *name; int c; float va, vb; int code; } cases[] = {
        {"nan", 4, 0.5f, NAN, 1}, {"inf", 0, INFINITY, -INFINITY, 1}, {"nannan", 4, NAN, NAN, 0},
        {"redinf", 0, 0.5f, INFINITY, 1},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char na[64], nb[64];
        snprintf(na, sizeof na, "%s-a.exr", cases[k].name);
        snprintf(nb, sizeof nb, "%s-b.exr", cases[k].name);
        nonfinite_pair(&a, &b, cases[k].c, cases[k].va, cases[k].vb);
        assert_int_equal(image_write(&a, at(na, path, sizeof path), NULL, err, sizeof err), 0);
        assert_int_equal(image_write(&b, at(nb, path, sizeof path), NULL, err, sizeof err), 0);
        image_free(&a);
        image_free(&b);
        int rc = run("compare %s %s --fail 1e30", na, nb);
        if (rc != cases[k].code) fail_msg("%s: exit %d, want %d\n%s%s", cases[k].name, rc, cases[k].code, out_buf, err_buf);
        if (cases[k].code == 1) {
            assert_non_null(strstr(out_buf, "non-finite mismatches: 1 pixels"));
            assert_non_null(strstr(out_buf, "DIFFERENT"));
            assert_int_equal(run("compare %s %s --fail 1e30 --failpercent 100", na, nb), 0);
            assert_non_null(strstr(out_buf, "non-finite mismatches: 1 pixels"));
        } else {
            assert_non_null(strstr(out_buf, "identical"));
        }
    }
}

/* ------------------------------------------------------------ truncated, corrupt, bombs */

/* A PNG cut anywhere (inside the signature, the header, the data, before IEND) and one with a byte flipped in
 * each chunk: exit 4, one line naming the file (libpng prints nothing of its own). */
static void test_truncated_and_corrupt_png(void **state)
{
    (void)state;
    size_t n;
    unsigned char *good = slurp("a.png", &n);
    const size_t cuts[] = {1, 7, 8, 20, 33, 40, n / 2, n - 13, n - 1};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; k++) {
        assert_true(prog_write_bytes(dir, "cut.png", good, cuts[k]));
        int rc = run("compare a.png cut.png");
        expect_refusal(rc, 4, "cut.png", cuts[k] < 8 ? "Not a PNG file" : "truncated: the file ends before the image does");
    }
    const size_t flips[] = {12, 20, n / 2, n - 8};   /* IHDR's type, its width, IDAT's data, IEND's type */
    for (size_t k = 0; k < sizeof flips / sizeof flips[0]; k++) {
        unsigned char *bad = malloc(n);
        memcpy(bad, good, n);
        bad[flips[k]] ^= 0x5a;
        assert_true(prog_write_bytes(dir, "flip.png", bad, n));
        free(bad);
        int rc = run("compare flip.png a.png");
        expect_refusal(rc, 4, "flip.png", "flip.png: cannot read: ");   /* libpng's words: CRC, chunk type, data check */
    }
    /* a byte flipped in an ancillary chunk (the data of the render's oFFs chunk): libpng skips it, the pixels are read */
    good[45] ^= 0x5a;
    assert_true(prog_write_bytes(dir, "flip.png", good, n));
    assert_int_equal(run("compare flip.png a.png"), 0);
    assert_string_equal(err_buf, "");
    free(good);
}

/* An OpenEXR file cut short or with garbage in its pixel data: exit 4 naming it, one line. */
static void test_truncated_and_corrupt_exr(void **state)
{
    (void)state;
    size_t n;
    unsigned char *good = slurp("a.exr", &n);
    const size_t cuts[] = {3, 4, 100, n / 2, n - 1};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; k++) {
        assert_true(prog_write_bytes(dir, "cut.exr", good, cuts[k]));
        int rc = run("compare a.exr cut.exr");
        expect_refusal(rc, 4, "cut.exr", "OpenEXR");
    }
    unsigned char *bad = malloc(n);
    memcpy(bad, good, n);
    memset(bad + n - n / 3, 0x55, n / 4);
    assert_true(prog_write_bytes(dir, "garbage.exr", bad, n));
    free(bad);
    expect_refusal(run("compare garbage.exr a.exr"), 4, "garbage.exr", "cannot read pixels");
    free(good);
}

/* The bytes of the file dir/name with its OpenEXR dataWindow set to (0, 0)..(xmax, ymax) written as out. */
static void exr_with_window(const char *name, const char *out, int xmax, int ymax)
{
    size_t n;
    unsigned char *b = slurp(name, &n);
    static const char key[] = "dataWindow\0box2i\0";
    unsigned char *p = NULL;
    for (size_t k = 0; k + sizeof key + 20 < n && !p; k++)
        if (memcmp(b + k, key, sizeof key - 1) == 0) p = b + k + sizeof key - 1 + 4;
    assert_non_null(p);
    int32_t v[4] = {0, 0, xmax, ymax};
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 4; j++) p[4 * k + j] = (unsigned char)((uint32_t)v[k] >> (8 * j));
    assert_true(prog_write_bytes(dir, out, b, n));
    free(b);
}

/* Declared dimensions far beyond the file, and over the limits, refused from the header alone (before any
 * allocation: the messages say which check): PNG and OpenEXR. */
static void test_declared_dimensions(void **state)
{
    (void)state;
    /* PNG: sides beyond 65536, pixels beyond 2^26, and 8192x8192 RGBA16 (512 MiB of samples) in 100 bytes */
    write_declaring_png("wide.png", 70000, 1, 8, 6, 10);
    expect_refusal(run("compare wide.png a.png"), 4, "wide.png", "unsupported size 70000x1x1 with 4 channels (at most 32 channels, 65536 pixels wide)");
    write_declaring_png("bomb.png", 60000, 60000, 8, 6, 10);
    expect_refusal(run("compare a.png bomb.png"), 4, "bomb.png",
                   "the header declares 60000x60000 pixels with 4 channels (14400000000 values), more than the limit");
    write_declaring_png("deflate.png", 8192, 8192, 16, 6, 10);
    expect_refusal(run("compare a.png deflate.png"), 4, "deflate.png",
                   "8192x8192 pixels (536879104 bytes of samples), more than the file's");
    /* within the ratio: 256x256 grey in one stored row is only truncated */
    write_declaring_png("short.png", 256, 256, 8, 0, 257);
    expect_refusal(run("compare short.png short.png"), 4, "short.png", "");
    /* OpenEXR: a's dataWindow made 8192x8192 (more chunks than the file holds), 100000 wide, 60000x60000 */
    exr_with_window("a.exr", "win.exr", 8191, 8191);
    expect_refusal(run("compare a.exr win.exr"), 4, "win.exr",
                   "the header declares 8192x8192 pixels with 6 channels");
    exr_with_window("a.exr", "side.exr", 99999, 9);
    expect_refusal(run("compare side.exr a.exr"), 4, "side.exr", "unsupported size 100000x10x1");
    exr_with_window("a.exr", "big.exr", 59999, 59999);
    expect_refusal(run("compare big.exr a.exr"), 4, "big.exr", "big.exr");
    /* the library: image_read says the same, from the header, before any allocation */
    is_image img = {0};
    char path[512], err[1024];
    assert_int_equal(image_read(&img, at("bomb.png", path, sizeof path), err, sizeof err), -1);
    assert_non_null(strstr(err, "more than the limit"));
    assert_null(img.data);
}

/* ------------------------------------------------------------ shapes, formats, channels */

/* Sizes and channel sets that differ: exit 3 with both shapes, and no diff image. */
static void test_shapes_from_headers(void **state)
{
    (void)state;
    assert_int_equal(run("compare a.png c.png --diff d.png"), 3);
    assert_non_null(strstr(err_buf, "32x32 [R,G,B,A] against 48x48 [R,G,B,A]"));
    assert_false(prog_exists(dir, "d.png"));
    size_t n;
    unsigned char *c = slurp("c.png", &n);
    assert_true(prog_write_bytes(dir, "c-cut.png", c, n / 2));
    free(c);
    /* a truncated file of another size: unreadable (4), named -- the pixels are decoded before the shapes are
     * compared (each file's header is checked against the limits first) */
    expect_refusal(run("compare a.png c-cut.png"), 4, "c-cut.png", "truncated");
    write_pattern_png("rgb.png", 32, 32, 2, 0);
    assert_int_equal(run("compare a.png rgb.png"), 3);
    assert_non_null(strstr(err_buf, "[R,G,B,A] against 32x32 [R,G,B]"));
    assert_int_equal(run("compare a.exr a.png"), 3);
    assert_non_null(strstr(err_buf, "[R,G,B,A,Z,depth] against 32x32 [R,G,B,A]"));
    /* the same channel count under other names */
    is_image e;
    char path[512], err[512];
    assert_int_equal(image_alloc(&e, 32, 32, "R,G,B,A,Z,N.X", err, sizeof err), 0);
    assert_int_equal(image_write(&e, at("named.exr", path, sizeof path), NULL, err, sizeof err), 0);
    image_free(&e);
    assert_int_equal(run("compare a.exr named.exr"), 3);
    assert_non_null(strstr(err_buf, "[R,G,B,A,Z,depth] against 32x32 [R,G,B,A,Z,N.X]"));
}

/* PNG kinds against the plain 8-bit RGBA file of the same pixels: 16-bit, palette with and without tRNS,
 * grey of 1, 2, 4, 8 and 16 bits, grey and alpha, interlaced -- each read to k / (2^bits - 1) in the channels
 * Y / Y,A / R,G,B / R,G,B,A. */
static void test_png_kinds(void **state)
{
    (void)state;
    char path[512], err[512];
    const uint32_t w = 13, h = 7;   /* odd sizes: every Adam7 pass, rows that end mid-byte */
    unsigned char *px = pattern8(w, h, 4);
    /* 16 bits: each 8-bit value v stored as v * 257, which reads back as the same float as v / 255 */
    unsigned char *px16 = malloc((size_t)w * h * 8);
    for (size_t k = 0; k < (size_t)w * h * 4; k++) px16[2 * k] = px16[2 * k + 1] = px[k];
    for (int interlace = 0; interlace < 2; interlace++) {
        bytes raw;
        scanlines(px16, w, h, 8, interlace, &raw);
        png_desc d = {.w = w, .h = h, .depth = 16, .ctype = 6, .interlace = interlace, .raw = raw.b, .n_raw = raw.n};
        write_png(interlace ? "rgba16i.png" : "rgba16.png", &d);
        free(raw.b);
    }
    write_pattern_png("rgba8.png", w, h, 6, 0);
    write_pattern_png("rgba8i.png", w, h, 6, 1);
    assert_int_equal(run("compare rgba8.png rgba8i.png"), 0);
    assert_non_null(strstr(out_buf, "identical"));
    assert_int_equal(run("compare rgba8.png rgba16.png --fail 1e-6"), 0);
    assert_int_equal(run("compare rgba16i.png rgba16.png"), 0);
    is_image a, b;
    assert_int_equal(image_read(&a, at("rgba8.png", path, sizeof path), err, sizeof err), 0);
    assert_int_equal(image_read(&b, at("rgba16i.png", path, sizeof path), err, sizeof err), 0);
    for (size_t k = 0; k < (size_t)w * h * 4; k++) {
        assert_true(a.data[k] == (float)px[k] * (1.0f / 255.0f));
        assert_true(fabsf(b.data[k] - a.data[k]) < 1e-6f);
    }
    image_free(&a);
    image_free(&b);
    free(px16);

    /* palette of 4 entries, 2 bits per index; with tRNS the 4th entry is half transparent */
    const unsigned char plte[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30}, trns[4] = {255, 255, 255, 128};
    unsigned char idx[4 * 3];   /* 4x3 indices: a row of 4 two-bit indices is one byte */
    bytes raw = {0};
    for (int y = 0; y < 3; y++) {
        unsigned char row[2] = {0, (unsigned char)(0x1b ^ (y * 0x55))};   /* indices 0,1,2,3 permuted by row */
        put(&raw, row, 2);
        for (int x = 0; x < 4; x++) idx[y * 4 + x] = (unsigned char)((row[1] >> (6 - 2 * x)) & 3);
    }
    png_desc pd = {.w = 4, .h = 3, .depth = 2, .ctype = 3, .plte = plte, .n_plte = 12, .raw = raw.b, .n_raw = raw.n};
    write_png("pal.png", &pd);
    pd.trns = trns, pd.n_trns = 4;
    write_png("palt.png", &pd);
    free(raw.b);
    assert_int_equal(image_read(&a, at("pal.png", path, sizeof path), err, sizeof err), 0);
    assert_int_equal(image_read(&b, at("palt.png", path, sizeof path), err, sizeof err), 0);
    assert_int_equal(a.channels, 3);
    assert_string_equal(a.channel_names[2], "B");
    assert_int_equal(b.channels, 4);
    assert_string_equal(b.channel_names[3], "A");
    for (int p = 0; p < 12; p++)
        for (int c = 0; c < 3; c++) {
            float want = (float)plte[idx[p] * 3 + c] * (1.0f / 255.0f);
            assert_true(a.data[p * 3 + c] == want && b.data[p * 4 + c] == want);
            assert_true(b.data[p * 4 + 3] == (float)trns[idx[p]] * (1.0f / 255.0f));
        }
    image_free(&a);
    image_free(&b);

    /* grey of 1, 2, 4, 8, 16 bits: one row 0, 1, ..., max (cut to 8 values); grey and alpha */
    const int depths[] = {1, 2, 4, 8, 16};
    for (size_t k = 0; k < sizeof depths / sizeof depths[0]; k++) {
        int bits = depths[k], maxv = (1 << bits) - 1, nv = maxv < 7 ? maxv + 1 : 8;
        unsigned char row[1 + 16] = {0};
        for (int x = 0; x < nv; x++) {
            int v = x * maxv / (nv - 1);
            if (bits == 16) row[1 + 2 * x] = (unsigned char)(v >> 8), row[2 + 2 * x] = (unsigned char)v;
            else row[1 + x * bits / 8] |= (unsigned char)(v << (8 - bits - (x * bits) % 8));
        }
        png_desc gd = {.w = (uint32_t)nv, .h = 1, .depth = bits, .ctype = 0, .raw = row,
                       .n_raw = 1 + ((size_t)nv * bits + 7) / 8};
        write_png("grey.png", &gd);
        assert_int_equal(image_read(&a, at("grey.png", path, sizeof path), err, sizeof err), 0);
        assert_int_equal(a.channels, 1);
        assert_string_equal(a.channel_names[0], "Y");
        for (int x = 0; x < nv; x++) {
            double want = (double)(x * maxv / (nv - 1)) / maxv;
            if (fabs(a.data[x] - want) > 1e-6) fail_msg("%d bits, value %d: read %g, want %g", bits, x, (double)a.data[x], want);
        }
        image_free(&a);
    }
    /* RGB with a tRNS colour key: an alpha channel, 0 where the key matches (palette PNGs get theirs from
     * png_set_palette_to_rgb; this one only from png_set_tRNS_to_alpha) */
    unsigned char rgb[1 + 6] = {0, 10, 20, 30, 40, 50, 60};
    const unsigned char key[6] = {0, 10, 0, 20, 0, 30};   /* 16-bit samples of the key colour 10, 20, 30 */
    png_desc kd = {.w = 2, .h = 1, .depth = 8, .ctype = 2, .trns = key, .n_trns = 6, .raw = rgb, .n_raw = 7};
    write_png("rgbkey.png", &kd);
    assert_int_equal(image_read(&a, at("rgbkey.png", path, sizeof path), err, sizeof err), 0);
    assert_int_equal(a.channels, 4);
    assert_true(a.data[3] == 0.0f && a.data[7] == 1.0f && a.data[4] == 40.0f * (1.0f / 255.0f));
    image_free(&a);
    unsigned char ya[1 + 4] = {0, 10, 255, 200, 0};
    png_desc yd = {.w = 2, .h = 1, .depth = 8, .ctype = 4, .raw = ya, .n_raw = 5};
    write_png("ya.png", &yd);
    assert_int_equal(image_read(&a, at("ya.png", path, sizeof path), err, sizeof err), 0);
    assert_true(a.channels == 2 && !strcmp(a.channel_names[0], "Y") && !strcmp(a.channel_names[1], "A"));
    assert_true(a.data[3] == 0.0f && a.data[2] == 200.0f * (1.0f / 255.0f));
    image_free(&a);
    free(px);
}

/* image_read of file dir/name with the process's stderr into a file: the return code, the message in err, and
 * whatever was printed on stderr meanwhile in printed (libpng's default handlers print there). */
static int read_capturing_stderr(const char *name, char *err, size_t errlen, char *printed, size_t plen)
{
    char path[512], cap[512];
    fflush(stderr);
    int saved = dup(2);
    FILE *f = fopen(at("stderr.txt", cap, sizeof cap), "w+");
    assert_non_null(f);
    dup2(fileno(f), 2);
    is_image img;
    int rc = image_read(&img, at(name, path, sizeof path), err, errlen);
    if (rc == 0) image_free(&img);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    rewind(f);
    size_t n = fread(printed, 1, plen - 1, f);
    printed[n] = '\0';
    fclose(f);
    return rc;
}

/* libpng never prints on the caller's stderr: a palette PNG (which went to OpenImageIO, whose reader left libpng's
 * default handlers) with a damaged ancillary chunk (a warning: read, nothing printed), cut short, and with its
 * image data damaged (errors: -1 naming the file, nothing printed). */
static void test_png_messages_not_on_stderr(void **state)
{
    (void)state;
    const unsigned char plte[6] = {255, 0, 0, 0, 0, 255};
    unsigned char raw[3 * 2] = {0, 0x40, 0, 0x80, 0, 0xc0};   /* 3 rows of one byte: 1-bit indices */
    png_desc pd = {.w = 4, .h = 3, .depth = 1, .ctype = 3, .plte = plte, .n_plte = 6, .raw = raw, .n_raw = 6};
    bytes o;
    png_bytes(&pd, &o);
    /* a tEXt chunk with a wrong CRC after IHDR (8 + 25 bytes): libpng warns and skips it */
    bytes t = {0};
    put(&t, o.b, 33);
    chunk(&t, "tEXt", (const unsigned char *)"Comment\0hi", 10);
    t.b[t.n - 1] ^= 0xff;
    put(&t, o.b + 33, o.n - 33);
    assert_true(prog_write_bytes(dir, "warn.png", t.b, t.n));
    assert_true(prog_write_bytes(dir, "palcut.png", o.b, o.n - 20));
    o.b[o.n - 16] ^= 0x5a;   /* inside IDAT's zlib stream: the Adler-32 */
    assert_true(prog_write_bytes(dir, "palbad.png", o.b, o.n));
    free(o.b);
    free(t.b);
    char err[512] = "", printed[4096];
    assert_int_equal(read_capturing_stderr("warn.png", err, sizeof err, printed, sizeof printed), 0);
    assert_string_equal(printed, "");
    assert_int_equal(read_capturing_stderr("palcut.png", err, sizeof err, printed, sizeof printed), -1);
    assert_string_equal(printed, "");
    assert_non_null(strstr(err, "palcut.png: cannot read: truncated"));
    assert_int_equal(read_capturing_stderr("palbad.png", err, sizeof err, printed, sizeof printed), -1);
    assert_string_equal(printed, "");
    assert_non_null(strstr(err, "palbad.png: cannot read: "));
    expect_refusal(run("compare palbad.png palbad.png"), 4, "palbad.png", "cannot read");
}

/* Alpha is a channel like the others and colour is never premultiplied: two pixels of alpha 0 with different
 * colours differ (exit 1); the same file twice is identical. */
static void test_alpha_and_same_file(void **state)
{
    (void)state;
    unsigned char p1[1 + 4] = {0, 200, 10, 10, 0}, p2[1 + 4] = {0, 10, 200, 10, 0};
    png_desc d = {.w = 1, .h = 1, .depth = 8, .ctype = 6, .raw = p1, .n_raw = 5};
    write_png("clear1.png", &d);
    d.raw = p2;
    write_png("clear2.png", &d);
    assert_int_equal(run("compare clear1.png clear2.png"), 1);
    assert_non_null(strstr(out_buf, "failing pixels: 1 "));
    assert_int_equal(run("compare a.png a.png"), 0);
    assert_non_null(strstr(out_buf, "identical"));
    assert_int_equal(run("compare a.exr ./a.exr"), 0);
}

/* Tiled OpenEXR reads as the scanline file it came from; multi-part and deep files are refused by name. */
static void test_exr_kinds(void **state)
{
    (void)state;
    char cmd[1400];
    snprintf(cmd, sizeof cmd, "cd '%s' && oiiotool a.exr --tile 16 16 -o tiled.exr && "
             "oiiotool a.exr a.exr --siappend -o multi.exr && oiiotool a.exr --deepen -o deep.exr", dir);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(run("compare a.exr tiled.exr"), 0);
    assert_non_null(strstr(out_buf, "identical"));
    expect_refusal(run("compare a.exr multi.exr"), 4, "multi.exr",
                   "holds several parts or subimages: instess reads single-part images");
    expect_refusal(run("compare deep.exr a.exr"), 4, "deep.exr", "a deep image (several samples per pixel)");
}

/* ------------------------------------------------------------ odd paths */

/* A FIFO, /dev/zero, a folder, a missing file, a dangling link, an empty file, a large file of zeros and one
 * over the size limit (sparse): exit 4 at once (nothing opened that could block or be read for long); a link
 * to a good image is read. */
static void test_odd_inputs(void **state)
{
    (void)state;
    char path[512];
    assert_int_equal(mkfifo(at("fifo.png", path, sizeof path), 0600), 0);
    expect_refusal(run("compare a.png fifo.png"), 4, "fifo.png", "is a FIFO, not an image file");
    expect_refusal(run("compare /dev/zero a.png"), 4, "/dev/zero", "is a device, not an image file");
    expect_refusal(run("compare a.png ."), 4, ".: is a directory, not an image file", "");
    expect_refusal(run("compare a.png missing.png"), 4, "missing.png", "cannot open: No such file or directory");
    assert_int_equal(symlink("nowhere.png", at("dangling.png", path, sizeof path)), 0);
    expect_refusal(run("compare dangling.png a.png"), 4, "dangling.png", "No such file or directory");
    assert_true(prog_write_bytes(dir, "empty.png", "", 0));
    expect_refusal(run("compare a.png empty.png"), 4, "empty.png", "empty file, not an image");
    char cmd[700];
    snprintf(cmd, sizeof cmd, "truncate -s 200M '%s/zeros.png' && truncate -s 5G '%s/huge.exr'", dir, dir);
    assert_int_equal(system(cmd), 0);
    expect_refusal(run("compare zeros.png a.png"), 4, "zeros.png", "Not a PNG file");
    expect_refusal(run("compare a.exr huge.exr"), 4, "huge.exr",
                   "the file has 5368709120 bytes, more than the limit of 4294967296 for an image file; not opened");
    unlink(at("zeros.png", path, sizeof path));
    unlink(at("huge.exr", path, sizeof path));
    assert_int_equal(symlink("a.png", at("link.png", path, sizeof path)), 0);
    assert_int_equal(run("compare link.png a.png"), 0);
}

/* --diff: naming an input (or a link to one) is a usage error (2); a link elsewhere, a FIFO, a folder, a
 * missing folder are refused (4) before any image is read -- here the second image is truncated, and the
 * message is the --diff's -- and left as they were. */
static void test_diff_targets(void **state)
{
    (void)state;
    char path[512], target[64];
    assert_int_equal(symlink("a.png", at("to-a.png", path, sizeof path)), 0);
    assert_int_equal(run("compare a.png b.png --diff a.png"), 2);
    assert_int_equal(run("compare a.png b.png --diff to-a.png"), 2);
    assert_non_null(strstr(err_buf, "--diff names one of the images compared"));
    size_t n;
    unsigned char *b = slurp("b.png", &n);
    assert_true(prog_write_bytes(dir, "b-cut.png", b, n / 2));
    free(b);
    assert_true(prog_write_text(dir, "other.txt", "keep"));
    assert_int_equal(symlink("other.txt", at("to-other.png", path, sizeof path)), 0);
    assert_int_equal(mkfifo(at("fifo-diff.png", path, sizeof path), 0600), 0);
    assert_int_equal(mkdir(at("folder.png", path, sizeof path), 0700), 0);
    const struct { const char *diff, *what; } cases[] = {
        {"to-other.png", "is a symbolic link"}, {"fifo-diff.png", "is a FIFO"},
        {"folder.png", "is a directory"},       {"no/such/d.png", "cannot create a file in the folder no/such"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        int rc = run("compare a.png b-cut.png --diff %s", cases[k].diff);
        snprintf(target, sizeof target, "--diff %s", cases[k].diff);
        expect_refusal(rc, 4, target, cases[k].what);
    }
    size_t m;
    unsigned char *keep = slurp("other.txt", &m);
    assert_true(m == 4 && memcmp(keep, "keep", 4) == 0);
    free(keep);
    assert_int_equal(prog_entries_with(dir, ".instess-"), 0);
    /* a good --diff: written on a difference only */
    assert_int_equal(run("compare a.png a.png --diff same.png"), 0);
    assert_false(prog_exists(dir, "same.png"));
    assert_int_equal(run("compare a.png b.png --diff d.png"), 1);
    assert_true(prog_exists(dir, "d.png"));
}

/* Bad --fail and --failpercent values: usage errors (exit 2) naming the value, nothing read. */
static void test_bad_thresholds(void **state)
{
    (void)state;
    const char *bad[] = {"--fail nan",        "--fail inf",         "--fail -inf",     "--fail -1",
                         "--fail 1e31",       "--fail 1e999",       "--fail ''",       "--fail x",
                         "--fail 1,5",        "--fail 0.5x",        "--failpercent nan", "--failpercent -0.5",
                         "--failpercent 100.5", "--failpercent 50%", "--failpercent ''", "--failpercent 1e999",
                         "--fail=",           "--failpercent"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        int rc = run("compare a.png missing.png %s", bad[k]);
        if (rc != 2 || !strstr(err_buf, "instess compare: ") || strstr(err_buf, "missing.png"))
            fail_msg("%s: exit %d, want 2 before reading:\n%s", bad[k], rc, err_buf);
    }
    assert_int_equal(run("compare a.png b.png --fail 1e30 --failpercent 100"), 0);
    assert_int_equal(run("compare a.png b.png --fail 0 --failpercent 0"), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nonfinite_library),
        cmocka_unit_test(test_nonfinite_diff_image),
        cmocka_unit_test(test_nonfinite_compare),
        cmocka_unit_test(test_truncated_and_corrupt_png),
        cmocka_unit_test(test_truncated_and_corrupt_exr),
        cmocka_unit_test(test_declared_dimensions),
        cmocka_unit_test(test_shapes_from_headers),
        cmocka_unit_test(test_png_kinds),
        cmocka_unit_test(test_png_messages_not_on_stderr),
        cmocka_unit_test(test_alpha_and_same_file),
        cmocka_unit_test(test_exr_kinds),
        cmocka_unit_test(test_odd_inputs),
        cmocka_unit_test(test_diff_targets),
        cmocka_unit_test(test_bad_thresholds),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
