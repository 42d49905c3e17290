/* tests/test_image.c -- the image API of image/image.h (image/image_oiio.cpp) and the golden helper (tests/util/golden.c).
 * Every test works in its own temporary directory under /tmp, removed afterwards. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../core/core.h"
#include "util/golden.h"

#define PATH_LEN 1024
static const is_image_meta META = {"instess " INSTESS_VERSION, "build/instess --mesh cube -o \"out/a b.png\""};

/* ---------------------------------------------------------------- helpers */

typedef struct fixture { char dir[256]; } fixture;

/* remove a directory tree (files and subdirectories only). */
static void rm_tree(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    char p[PATH_LEN];
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        struct stat st;
        if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode))
            rm_tree(p);
        else
            unlink(p);
    }
    closedir(d);
    rmdir(dir);
}

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    snprintf(f->dir, sizeof f->dir, "/tmp/instess-test-image-XXXXXX");
    if (!f || !mkdtemp(f->dir))
        return -1;
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    rm_tree(f->dir);
    free(f);
    return 0;
}

/* dir/name into buf. */
static const char *in_dir(char *buf, const fixture *f, const char *name)
{
    snprintf(buf, PATH_LEN, "%s/%s", f->dir, name);
    return buf;
}

/* Number of entries of dir (without . and ..); with `tmp_seen` set if one looks like a temporary. */
static int count_entries(const char *dir, int *tmp_seen)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    int n = 0;
    *tmp_seen = 0;
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        n++;
        if (strstr(e->d_name, ".instess-"))
            *tmp_seen = 1;
    }
    closedir(d);
    return n;
}

/* Assert dir holds exactly n entries, none a temporary. */
static void assert_dir_entries(const char *dir, int n)
{
    int tmp_seen;
    assert_int_equal(count_entries(dir, &tmp_seen), n);
    assert_false(tmp_seen);
}

/* The whole file into a malloc'd buffer (*len bytes); NULL if unreadable. */
static unsigned char *slurp(const char *path, size_t *len)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return NULL;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    unsigned char *b = malloc((size_t)n + 1);
    *len = fread(b, 1, (size_t)n, fp);
    fclose(fp);
    return b;
}

/* Output of `iinfo -v path` (metadata as OpenImageIO reads it), or NULL if iinfo is not installed. */
static char *iinfo(const char *path)
{
    char cmd[PATH_LEN + 64];
    snprintf(cmd, sizeof cmd, "iinfo -v '%s' 2>&1", path);
    FILE *p = popen(cmd, "r");
    if (!p)
        return NULL;
    static char out[16384];
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = '\0';
    int rc = pclose(p);
    return rc == 0 ? out : NULL;
}

/* Index of channel `name` of img, or -1. */
static int chan(const is_image *img, const char *name)
{
    for (int c = 0; c < img->channels; c++)
        if (!strcmp(img->channel_names[c], name))
            return c;
    return -1;
}

/* Pointer to value (x, y, c) of img. */
static float *px(const is_image *img, int x, int y, int c)
{
    return img->data + ((size_t)y * img->width + x) * img->channels + c;
}

/* A w x h test pattern in the given channels: value (x, y, c) depends on all three, colour in [0, 1]. */
static void make_pattern(is_image *img, int w, int h, const char *names)
{
    char err[256] = "";
    assert_int_equal(image_alloc(img, w, h, names, err, sizeof err), 0);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < img->channels; c++)
                *px(img, x, y, c) = c < 4 ? (float)((x * 37 + y * 11 + c * 53) % 256) / 255.0f * 0.999f + 0.0003f
                                          : 0.001f * (float)(x + 100 * y) + 0.123456789f * (float)c;
}

/* Bytes of a PNG quantization of v (what the 8-bit file stores). */
static float quant8(float v)
{
    v = v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
    return (float)(int)(v * 255.0f + 0.5f) * (1.0f / 255.0f);
}

/* ---------------------------------------------------------------- allocation */

/* image_alloc parses names and rejects bad sizes / names; image_from_rgba8 unpacks R | G<<8 | B<<16 | A<<24. */
static void test_alloc_and_from_rgba8(void **state)
{
    (void)state;
    is_image img;
    char err[256];
    assert_int_equal(image_alloc(&img, 3, 2, "R,G,B,A,Z,N.X", err, sizeof err), 0);
    assert_int_equal(img.channels, 6);
    assert_string_equal(img.channel_names[5], "N.X");
    for (int i = 0; i < 3 * 2 * 6; i++)
        assert_true(img.data[i] == 0.0f);
    uint32_t rgba[6] = {0x80402010u, 0xff000000u, 0x000000ffu, 0, 0xffffffffu, 0x01020304u};
    image_from_rgba8(&img, rgba);
    assert_float_equal(*px(&img, 0, 0, 0), 0x10 / 255.0, 1e-7);
    assert_float_equal(*px(&img, 0, 0, 1), 0x20 / 255.0, 1e-7);
    assert_float_equal(*px(&img, 0, 0, 2), 0x40 / 255.0, 1e-7);
    assert_float_equal(*px(&img, 0, 0, 3), 0x80 / 255.0, 1e-7);
    assert_true(*px(&img, 1, 0, 3) == 1.0f && *px(&img, 1, 0, 0) == 0.0f);
    assert_true(*px(&img, 2, 0, 0) == 1.0f && *px(&img, 2, 0, 3) == 0.0f);
    assert_true(*px(&img, 0, 0, 4) == 0.0f); /* Z untouched */
    image_free(&img);
    assert_null(img.data);
    image_free(&img); /* twice is harmless */

    const char *bad_names[] = {"", "R,,G", "R,", "ThisNameIsTooLong16", NULL};
    for (int i = 0; bad_names[i]; i++) {
        err[0] = '\0';
        assert_int_equal(image_alloc(&img, 4, 4, bad_names[i], err, sizeof err), -1);
        assert_true(strlen(err) > 0);
        assert_null(img.data);
    }
    assert_int_equal(image_alloc(&img, 4, 4, NULL, err, sizeof err), -1);
    int bad_sizes[][2] = {{0, 4}, {4, 0}, {-1, 4}, {100000, 4}, {4, 1 << 20}};
    for (int i = 0; i < 5; i++) {
        err[0] = '\0';
        assert_int_equal(image_alloc(&img, bad_sizes[i][0], bad_sizes[i][1], "R,G,B,A", err, sizeof err), -1);
        assert_non_null(strstr(err, "size"));
    }
    char many[40 * 4] = "";
    for (int i = 0; i < IS_IMAGE_MAX_CHANNELS + 1; i++)
        strcat(many, i ? ",C" : "C");
    assert_int_equal(image_alloc(&img, 4, 4, many, err, sizeof err), -1);
}

/* ---------------------------------------------------------------- round trips */

/* PNG: the first four channels as 8 bits rounded to nearest (Z dropped), names R,G,B,A, colour not
 * premultiplied (translucent pixels keep their colour), Software and ImageDescription stored. */
static void test_png_roundtrip(void **state)
{
    fixture *f = *state;
    char path[PATH_LEN], err[PATH_LEN + 256] = "";
    is_image img, back;
    make_pattern(&img, 13, 7, "R,G,B,A,Z");
    *px(&img, 1, 1, 0) = 0.5f / 255.0f + 1e-4f;  /* rounds up to 1 */
    *px(&img, 2, 1, 0) = 0.5f / 255.0f - 1e-4f;  /* rounds down to 0 */
    *px(&img, 3, 1, 0) = 1.7f;                   /* clamped */
    *px(&img, 4, 1, 0) = -0.2f;                  /* clamped */
    *px(&img, 5, 1, 0) = 0.8f, *px(&img, 5, 1, 3) = 0.25f; /* translucent: colour must stay 0.8 */
    assert_int_equal(image_write(&img, in_dir(path, f, "a.png"), &META, err, sizeof err), 0);
    assert_int_equal(image_read(&back, path, err, sizeof err), 0);
    assert_int_equal(back.width, 13);
    assert_int_equal(back.height, 7);
    assert_int_equal(back.channels, 4);
    const char *names[] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; c++)
        assert_string_equal(back.channel_names[c], names[c]);
    for (int y = 0; y < 7; y++)
        for (int x = 0; x < 13; x++)
            for (int c = 0; c < 4; c++)
                assert_true(*px(&back, x, y, c) == quant8(*px(&img, x, y, c)));
    assert_true(*px(&back, 1, 1, 0) == 1.0f / 255.0f);
    assert_true(*px(&back, 2, 1, 0) == 0.0f);
    assert_true(*px(&back, 3, 1, 0) == 1.0f);
    assert_true(*px(&back, 4, 1, 0) == 0.0f);
    assert_float_equal(*px(&back, 5, 1, 0), 204.0 / 255.0, 1e-6);
    char *info = iinfo(path);
    if (!info)
        skip(); /* openimageio-tools missing: scripts/setup.sh installs it */
    assert_non_null(strstr(info, "instess " INSTESS_VERSION));
    assert_non_null(strstr(info, "build/instess --mesh cube -o"));
    assert_non_null(strstr(info, "Software"));
    assert_non_null(strstr(info, "uint8 png"));
    image_free(&img);
    image_free(&back);
}

/* EXR: R, G, B, A as half; Z and AOV channels ("N.X", ...) as float with their names; metadata stored. */
static void test_exr_roundtrip(void **state)
{
    fixture *f = *state;
    char path[PATH_LEN], err[PATH_LEN + 256] = "";
    is_image img, back;
    make_pattern(&img, 9, 5, "R,G,B,A,Z,N.X,N.Y,N.Z");
    *px(&img, 0, 0, 0) = 0.1f;          /* not a half: must come back rounded to half */
    *px(&img, 0, 0, 4) = 1234.56789f;   /* float Z must be exact */
    *px(&img, 0, 0, 5) = -0.987654321f; /* float AOV must be exact */
    assert_int_equal(image_write(&img, in_dir(path, f, "a.exr"), &META, err, sizeof err), 0);
    assert_int_equal(image_read(&back, path, err, sizeof err), 0);
    assert_int_equal(back.width, 9);
    assert_int_equal(back.height, 5);
    assert_int_equal(back.channels, 8);
    for (int c = 0; c < 8; c++) {
        int b = chan(&back, img.channel_names[c]);
        assert_true(b >= 0);
        for (int y = 0; y < 5; y++)
            for (int x = 0; x < 9; x++) {
                float v = *px(&img, x, y, c), r = *px(&back, x, y, b);
                if (c < 4)
                    assert_true(fabsf(v - r) <= fabsf(v) * (1.0f / 2048.0f) + 1e-7f); /* half precision */
                else
                    assert_true(v == r);                                               /* float exact */
            }
    }
    assert_true(*px(&back, 0, 0, chan(&back, "R")) != 0.1f);
    assert_float_equal(*px(&back, 0, 0, chan(&back, "R")), 0.1, 1e-4);
    char *info = iinfo(path);
    if (!info)
        skip();
    assert_non_null(strstr(info, "R (half)"));
    assert_non_null(strstr(info, "A (half)"));
    assert_non_null(strstr(info, "Z (float)"));
    assert_non_null(strstr(info, "N.X (float)"));
    assert_non_null(strstr(info, "instess " INSTESS_VERSION));
    assert_non_null(strstr(info, "ImageDescription"));
    assert_non_null(strstr(info, "build/instess --mesh cube -o"));
    image_free(&img);
    image_free(&back);
}

/* ---------------------------------------------------------------- failures */

/* A failed write returns -1 with a message naming the path, and leaves nothing behind: a missing directory,
 * unknown / missing extensions, an empty or NULL path, a directory at the target, an invalid image. */
static void test_write_failures_leave_nothing(void **state)
{
    fixture *f = *state;
    char path[PATH_LEN], err[PATH_LEN + 256];
    is_image img;
    make_pattern(&img, 4, 4, "R,G,B,A");
    const char *bad[] = {"missing/dir/a.png", "a.tif", "a.jpg", "a", "a.png.bak", ".png", NULL};
    for (int i = 0; bad[i]; i++) {
        err[0] = '\0';
        assert_int_equal(image_write(&img, in_dir(path, f, bad[i]), &META, err, sizeof err), -1);
        assert_non_null(strstr(err, path));
        assert_dir_entries(f->dir, 0);
    }
    assert_int_equal(image_write(&img, in_dir(path, f, "missing/a.png"), &META, err, sizeof err), -1);
    assert_non_null(strstr(err, "No such file or directory"));
    assert_int_equal(image_write(&img, in_dir(path, f, "a.tif"), &META, err, sizeof err), -1);
    assert_non_null(strstr(err, "unknown image extension"));
    err[0] = '\0';
    assert_int_equal(image_write(&img, "", &META, err, sizeof err), -1);
    assert_true(strlen(err) > 0);
    assert_int_equal(image_write(&img, NULL, &META, err, sizeof err), -1);

    /* a directory where the file should be: stays a directory, nothing else appears */
    assert_int_equal(mkdir(in_dir(path, f, "d.png"), 0755), 0);
    assert_int_equal(image_write(&img, path, &META, err, sizeof err), -1);
    assert_non_null(strstr(err, "is a directory"));
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_true(S_ISDIR(st.st_mode));
    assert_dir_entries(f->dir, 1);

    /* invalid images */
    is_image bad_img = img;
    bad_img.width = 0;
    assert_int_equal(image_write(&bad_img, in_dir(path, f, "b.png"), &META, err, sizeof err), -1);
    bad_img = img;
    bad_img.data = NULL;
    assert_int_equal(image_write(&bad_img, path, &META, err, sizeof err), -1);
    assert_int_equal(image_write(NULL, path, &META, err, sizeof err), -1);
    assert_dir_entries(f->dir, 1);
    image_free(&img);
}

/* Write `img` to path with the file size limit at `limit` bytes (a full disk): must fail. */
static int write_with_fsize_limit(const is_image *img, const char *path, rlim_t limit, char *err, size_t n)
{
    struct rlimit old, lim;
    getrlimit(RLIMIT_FSIZE, &old);
    void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
    lim = old;
    lim.rlim_cur = limit;
    setrlimit(RLIMIT_FSIZE, &lim);
    int r = image_write(img, path, &META, err, n);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, prev);
    return r;
}

/* An existing image stays byte-for-byte intact when a later write to its path fails: a write that runs out of
 * space half-way (RLIMIT_FSIZE, for PNG and EXR) and an invalid image; no temporary is left. */
static void test_failed_write_keeps_previous(void **state)
{
    fixture *f = *state;
    const char *names[] = {"keep.png", "keep.exr"};
    for (int i = 0; i < 2; i++) {
        char path[PATH_LEN], err[PATH_LEN + 256] = "";
        is_image small, big;
        make_pattern(&small, 8, 8, "R,G,B,A,Z");
        make_pattern(&big, 256, 256, "R,G,B,A,Z");
        uint32_t rng = 12345u;
        for (int k = 0; k < 256 * 256 * 5; k++) {  /* noise: the file is far above the limit */
            rng = rng * 1664525u + 1013904223u;
            big.data[k] = (float)(rng >> 8) / 16777216.0f;
        }
        assert_int_equal(image_write(&small, in_dir(path, f, names[i]), &META, err, sizeof err), 0);
        size_t len0, len1;
        unsigned char *before = slurp(path, &len0);
        assert_non_null(before);
        err[0] = '\0';
        assert_int_equal(write_with_fsize_limit(&big, path, 20000, err, sizeof err), -1);
        assert_non_null(strstr(err, path));
        unsigned char *after = slurp(path, &len1);
        assert_non_null(after);
        assert_int_equal(len0, len1);
        assert_memory_equal(before, after, len0);
        is_image bad = small;
        bad.channels = 0;
        assert_int_equal(image_write(&bad, path, &META, err, sizeof err), -1);
        free(after);
        after = slurp(path, &len1);
        assert_int_equal(len0, len1);
        assert_memory_equal(before, after, len0);
        assert_dir_entries(f->dir, i + 1);
        free(before);
        free(after);
        image_free(&small);
        image_free(&big);
    }
}

/* Successful writes and overwrites (PNG, EXR, upper-case extension) leave exactly the targets, readable by all
 * (0644), each replaced by the new content; no temporary files remain. */
static void test_no_temporaries_left(void **state)
{
    fixture *f = *state;
    char path[PATH_LEN], err[PATH_LEN + 256] = "";
    is_image a, b, back;
    make_pattern(&a, 6, 4, "R,G,B,A,Z");
    make_pattern(&b, 6, 4, "R,G,B,A,Z");
    b.data[0] = 1.0f, a.data[0] = 0.0f;
    const char *names[] = {"x.png", "x.exr", "UP.PNG"};
    for (int i = 0; i < 3; i++) {
        assert_int_equal(image_write(&a, in_dir(path, f, names[i]), &META, err, sizeof err), 0);
        assert_int_equal(image_write(&b, path, &META, err, sizeof err), 0);  /* overwrite */
        assert_int_equal(image_read(&back, path, err, sizeof err), 0);
        assert_true(back.data[0] == 1.0f);
        image_free(&back);
        struct stat st;
        assert_int_equal(stat(path, &st), 0);
        assert_int_equal(st.st_mode & 0777, 0644);
        assert_dir_entries(f->dir, i + 1);
    }
    /* a relative path (no directory part) works too */
    char cwd[PATH_LEN];
    assert_non_null(getcwd(cwd, sizeof cwd));
    assert_int_equal(chdir(f->dir), 0);
    int r = image_write(&a, "rel.png", &META, err, sizeof err);
    assert_int_equal(chdir(cwd), 0);
    assert_int_equal(r, 0);
    assert_dir_entries(f->dir, 4);
    image_free(&a);
    image_free(&b);
}

/* image_read of a missing or non-image file fails with the path in the message. */
static void test_read_failures(void **state)
{
    fixture *f = *state;
    char path[PATH_LEN], err[PATH_LEN + 256] = "";
    is_image img;
    assert_int_equal(image_read(&img, in_dir(path, f, "none.png"), err, sizeof err), -1);
    assert_non_null(strstr(err, path));
    assert_null(img.data);
    FILE *fp = fopen(in_dir(path, f, "junk.png"), "w");
    fputs("not a png", fp);
    fclose(fp);
    assert_int_equal(image_read(&img, path, err, sizeof err), -1);
    assert_non_null(strstr(err, path));
    assert_int_equal(image_read(&img, "", err, sizeof err), -1);
}

/* ---------------------------------------------------------------- compare */

/* image_compare: identical images give zero error; one pixel changed in two channels counts as ONE failing
 * pixel with the exact max error at its pixel and channel; the diff image is written, that pixel (the largest
 * difference) full red, the warning yellow dimmed by its amplified difference, the others not red.
 * Mismatched sizes are an error. */
static void test_compare_finds_changed_pixel(void **state)
{
    fixture *f = *state;
    char path[PATH_LEN], err[PATH_LEN + 256] = "";
    is_image a, b, d;
    make_pattern(&a, 10, 6, "R,G,B,A,Z");
    make_pattern(&b, 10, 6, "R,G,B,A,Z");
    is_image_diff res;
    assert_int_equal(image_compare(&a, &b, 0.0f, 0.0f, &res, NULL, err, sizeof err), 0);
    assert_int_equal(res.n_fail, 0);
    assert_true(res.max_error == 0.0f && res.mean_error == 0.0);
    assert_int_equal(res.n_pixels, 60);

    *px(&b, 7, 3, 1) += 0.25f;
    *px(&b, 7, 3, 4) -= 0.5f; /* Z differs too */
    *px(&b, 2, 2, 0) += 0.01f; /* a warning, not a failure */
    assert_int_equal(image_compare(&a, &b, 0.1f, 0.005f, &res, in_dir(path, f, "diff.png"), err, sizeof err), 0);
    assert_int_equal(res.n_fail, 1);
    assert_int_equal(res.n_warn, 2);
    assert_float_equal(res.max_error, 0.5, 1e-6);
    assert_true(res.max_x == 7 && res.max_y == 3 && res.max_channel == 4);
    assert_true(res.mean_error > 0.0);
    assert_int_equal(image_read(&d, path, err, sizeof err), 0);
    assert_int_equal(d.width, 10);
    assert_int_equal(d.height, 6);
    assert_true(*px(&d, 7, 3, 0) == 1.0f && *px(&d, 7, 3, 1) == 0.0f && *px(&d, 7, 3, 2) == 0.0f);
    /* yellow at 0.35 + 0.65 * 0.01 / 0.5 = 0.363 of full brightness (8-bit: 93/255) */
    assert_true(*px(&d, 2, 2, 0) == 93.0f / 255.0f && *px(&d, 2, 2, 1) == 93.0f / 255.0f && *px(&d, 2, 2, 2) == 0.0f);
    for (int y = 0; y < 6; y++)
        for (int x = 0; x < 10; x++)
            if (!(x == 7 && y == 3) && !(x == 2 && y == 2))
                assert_false(*px(&d, x, y, 0) == 1.0f && *px(&d, x, y, 1) == 0.0f);
    image_free(&d);

    is_image c;
    make_pattern(&c, 10, 5, "R,G,B,A,Z");
    err[0] = '\0';
    assert_int_equal(image_compare(&a, &c, 0.1f, 0.1f, &res, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "differ"));
    image_free(&a);
    image_free(&b);
    image_free(&c);
}

/* ---------------------------------------------------------------- golden_check */

/* Point the golden and failure directories into the fixture, and clear the regeneration flag. */
static void golden_env(const fixture *f, char *gdir, char *fdir)
{
    in_dir(gdir, f, "golden");
    in_dir(fdir, f, "failures");
    setenv("INSTESS_GOLDEN_DIR", gdir, 1);
    setenv("INSTESS_FAILURE_DIR", fdir, 1);
    unsetenv("INSTESS_REGENERATE_GOLDENS");
}

/* Restore the environment of the process. */
static void golden_env_reset(void)
{
    unsetenv("INSTESS_GOLDEN_DIR");
    unsetenv("INSTESS_FAILURE_DIR");
    unsetenv("INSTESS_REGENERATE_GOLDENS");
}

/* True if the file exists. */
static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* golden_check (PNG): a missing golden FAILS (keeping the actual image); regeneration writes the golden and
 * passes; then the same image passes at threshold 0; a changed pixel fails with .actual and .diff written;
 * the same change passes when the allowed percentage covers it; a size change fails. */
static void test_golden_missing_then_regenerated(void **state)
{
    fixture *f = *state;
    char gdir[PATH_LEN], fdir[PATH_LEN], p[PATH_LEN];
    golden_env(f, gdir, fdir);
    is_image img;
    make_pattern(&img, 20, 10, "R,G,B,A,Z");
    assert_string_equal(golden_dir(), gdir);

    assert_int_equal(golden_check(&img, "pattern", 0.0f, 0.0f), -1);
    assert_true(exists(in_dir(p, f, "failures/pattern.actual.png")));
    assert_false(exists(in_dir(p, f, "golden/pattern.png")));

    setenv("INSTESS_REGENERATE_GOLDENS", "1", 1);
    assert_int_equal(golden_check(&img, "pattern", 0.0f, 0.0f), 0);
    assert_true(exists(in_dir(p, f, "golden/pattern.png")));
    unsetenv("INSTESS_REGENERATE_GOLDENS");

    assert_int_equal(golden_check(&img, "pattern", 0.0f, 0.0f), 0);
    assert_false(exists(in_dir(p, f, "failures/pattern.actual.png"))); /* cleaned up on success */
    assert_int_equal(golden_check(&img, "pattern.png", 0.0f, 0.0f), 0);  /* explicit extension */

    *px(&img, 3, 4, 2) = *px(&img, 3, 4, 2) > 0.5f ? 0.0f : 1.0f;   /* 1 pixel of 200 = 0.5% */
    assert_int_equal(golden_check(&img, "pattern", 2.0f / 255.0f, 0.0f), -1);
    assert_true(exists(in_dir(p, f, "failures/pattern.actual.png")));
    assert_true(exists(in_dir(p, f, "failures/pattern.diff.png")));
    assert_int_equal(golden_check(&img, "pattern", 2.0f / 255.0f, 0.4f), -1);
    assert_int_equal(golden_check(&img, "pattern", 2.0f / 255.0f, 0.5f), 0);
    assert_int_equal(golden_check(&img, "pattern", 1.0f, 0.0f), 0);
    assert_false(exists(in_dir(p, f, "failures/pattern.diff.png")));  /* stale diff removed on success */

    is_image other;
    make_pattern(&other, 20, 11, "R,G,B,A");
    assert_int_equal(golden_check(&other, "pattern", 1.0f, 100.0f), -1);
    assert_int_equal(golden_check(&other, "bad/name", 1.0f, 100.0f), -1);
    image_free(&other);
    image_free(&img);
    golden_env_reset();
}

/* golden_check (EXR): Z and AOV channels take part; a change in Z alone fails. */
static void test_golden_exr(void **state)
{
    fixture *f = *state;
    char gdir[PATH_LEN], fdir[PATH_LEN], p[PATH_LEN];
    golden_env(f, gdir, fdir);
    is_image img;
    make_pattern(&img, 8, 8, "R,G,B,A,Z,N.X");
    assert_int_equal(golden_check(&img, "deep.exr", 0.0f, 0.0f), -1);
    setenv("INSTESS_REGENERATE_GOLDENS", "1", 1);
    assert_int_equal(golden_check(&img, "deep.exr", 0.0f, 0.0f), 0);
    unsetenv("INSTESS_REGENERATE_GOLDENS");
    assert_true(exists(in_dir(p, f, "golden/deep.exr")));
    assert_int_equal(golden_check(&img, "deep.exr", 0.0f, 0.0f), 0);
    *px(&img, 1, 1, 4) += 1e-3f;
    assert_int_equal(golden_check(&img, "deep.exr", 1e-4f, 0.0f), -1);
    assert_true(exists(in_dir(p, f, "failures/deep.actual.exr")));
    assert_true(exists(in_dir(p, f, "failures/deep.diff.png")));
    image_free(&img);
    golden_env_reset();
}

/* ---------------------------------------------------------------- text */

/* image_draw_text changes RGB pixels inside the text's box only, raises alpha there, leaves Z alone;
 * image_text_size is positive and grows with the text; bad arguments are errors; "" draws nothing. */
static void test_draw_text(void **state)
{
    fixture *f = *state;
    char err[256] = "", path[PATH_LEN];
    is_image img;
    assert_int_equal(image_alloc(&img, 64, 32, "R,G,B,A,Z", err, sizeof err), 0);
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 64; x++)
            *px(&img, x, y, 4) = 0.5f;
    int w, h, w2, h2;
    assert_int_equal(image_text_size("Hi", 16.0f, &w, &h), 0);
    assert_true(w > 4 && w < 40 && h > 8 && h < 32);
    assert_int_equal(image_text_size("Hi there", 16.0f, &w2, &h2), 0);
    assert_true(w2 > w);
    assert_int_equal(image_text_size("", 16.0f, &w2, &h2), 0);
    assert_true(w2 == 0 && h2 == 0);
    assert_int_equal(image_text_size(NULL, 16.0f, &w2, &h2), -1);

    const float white[4] = {1, 1, 1, 1};
    assert_int_equal(image_draw_text(&img, 4, 20, "Hi", 16.0f, white, err, sizeof err), 0);
    int changed = 0, full = 0;
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 64; x++) {
            float r = *px(&img, x, y, 0), a = *px(&img, x, y, 3);
            assert_true(*px(&img, x, y, 4) == 0.5f);            /* Z untouched */
            assert_true(*px(&img, x, y, 1) == r && *px(&img, x, y, 2) == r);
            assert_true(r == a);                                 /* white over transparent black */
            if (r > 0.0f) {
                changed++;
                full += r == 1.0f;
                assert_true(x >= 4 && x < 4 + w + 1 && y > 20 - h && y <= 21); /* inside the box */
            }
        }
    assert_true(changed > 20);
    assert_true(full > 5);
    assert_int_equal(image_write(&img, in_dir(path, f, "text.png"), &META, err, sizeof err), 0);

    /* half-transparent red over the white text: blends */
    const float red[4] = {1, 0, 0, 0.5f};
    assert_int_equal(image_draw_text(&img, -2, 20, "MMMM", 20.0f, red, err, sizeof err), 0); /* clipped left */
    int blended = 0;
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 64; x++)
            blended += *px(&img, x, y, 0) > 0.0f && *px(&img, x, y, 1) > 0.4f && *px(&img, x, y, 1) < 0.6f;
    assert_true(blended > 0);

    /* nothing drawn: empty text, text outside the image */
    float *copy = malloc(64 * 32 * 5 * sizeof(float));
    memcpy(copy, img.data, 64 * 32 * 5 * sizeof(float));
    assert_int_equal(image_draw_text(&img, 4, 20, "", 16.0f, white, err, sizeof err), 0);
    assert_int_equal(image_draw_text(&img, 500, 500, "far", 16.0f, white, err, sizeof err), 0);
    assert_memory_equal(copy, img.data, 64 * 32 * 5 * sizeof(float));
    free(copy);

    assert_int_equal(image_draw_text(&img, 4, 20, NULL, 16.0f, white, err, sizeof err), -1);
    assert_int_equal(image_draw_text(&img, 4, 20, "x", 0.0f, white, err, sizeof err), -1);
    assert_int_equal(image_draw_text(&img, 4, 20, "x", 16.0f, NULL, err, sizeof err), -1);
    assert_int_equal(image_draw_text(&img, 4, 20, "b\xe2\x82\x80", 16.0f, white, err, sizeof err), -1);
    assert_non_null(strstr(err, "ASCII"));
    assert_int_equal(image_text_size("\xce\xb1", 16.0f, &w2, &h2), -1);
    assert_int_equal(image_draw_text(&img, 4, 12, "two\nlines", 10.0f, white, err, sizeof err), 0);
    is_image z;
    assert_int_equal(image_alloc(&z, 4, 4, "Z", err, sizeof err), 0);
    assert_int_equal(image_draw_text(&z, 0, 3, "x", 4.0f, white, err, sizeof err), -1);
    assert_non_null(strstr(err, "R, G, B"));
    image_free(&z);
    image_free(&img);
}

/* image_check, the pixel-diff test of the goldens and `instess compare`: identical passes; one failing pixel of
 * 60 fails at 0% and passes at 2% (1.67%); a diff image is written only on a failure; a different size or
 * channel list is SHAPE_DIFFERS naming both shapes; an unreadable file is IO_ERROR naming it. */
/* Non-finite values never pass for finite ones: +inf against -inf, NaN against a number (even with generous
 * thresholds), inf against a large number; NaN against NaN and an infinity against the same one do pass.
 * (OpenImageIO's differences of such values are not numbers: +inf vs -inf and NaN channels passed.) */
static void test_image_check_nonfinite(void **state)
{
    (void)state;
    char err[256];
    is_image a, b;
    is_image_diff d;
    make_pattern(&a, 4, 3, "R,G,B,A");
    make_pattern(&b, 4, 3, "R,G,B,A");
    *px(&a, 1, 1, 0) = INFINITY, *px(&b, 1, 1, 0) = -INFINITY;
    assert_int_equal(image_check(&a, &b, 0.0f, 0.0f, NULL, &d, err, sizeof err), IS_IMAGE_DIFFERENT);
    assert_true(d.n_fail == 1 && d.n_nonfinite == 1 && isinf(d.max_error));
    *px(&b, 1, 1, 0) = INFINITY;
    assert_int_equal(image_check(&a, &b, 0.0f, 0.0f, NULL, &d, err, sizeof err), IS_IMAGE_PASS);
    *px(&a, 2, 0, 3) = NAN;   /* NaN against a number, with thresholds that allow everything finite */
    assert_int_equal(image_check(&a, &b, 1e30f, 0.0f, NULL, &d, err, sizeof err), IS_IMAGE_DIFFERENT);
    assert_true(d.n_fail == 1 && d.n_nonfinite == 1);
    *px(&b, 2, 0, 3) = NAN;
    assert_int_equal(image_check(&a, &b, 0.0f, 0.0f, NULL, &d, err, sizeof err), IS_IMAGE_PASS);
    *px(&b, 3, 2, 1) = INFINITY;   /* an infinity against 3e38 */
    *px(&a, 3, 2, 1) = 3e38f;
    assert_int_equal(image_check(&a, &b, 1e30f, 0.0f, NULL, &d, err, sizeof err), IS_IMAGE_DIFFERENT);
    assert_true(d.n_nonfinite == 1);
    image_free(&a);
    image_free(&b);
}

static void test_image_check_verdicts(void **state)
{
    fixture *f = *state;
    char path[PATH_LEN], pa[PATH_LEN], pb[PATH_LEN], err[PATH_LEN + 256] = "";
    is_image a, b, c;
    is_image_diff d;
    make_pattern(&a, 10, 6, "R,G,B,A");
    make_pattern(&b, 10, 6, "R,G,B,A");
    assert_int_equal(image_check(&a, &b, 0.0f, 0.0f, in_dir(path, f, "d0.png"), &d, err, sizeof err), IS_IMAGE_PASS);
    assert_true(d.max_error == 0.0f && d.n_fail == 0 && d.n_pixels == 60);
    assert_int_equal(access(path, F_OK), -1);
    *px(&b, 4, 5, 2) += 0.2f;
    assert_int_equal(image_check(&a, &b, 0.1f, 2.0f, path, &d, err, sizeof err), IS_IMAGE_PASS);
    assert_int_equal(d.n_fail, 1);
    assert_int_equal(access(path, F_OK), -1);
    assert_int_equal(image_check(&a, &b, 0.1f, 1.5f, path, &d, err, sizeof err), IS_IMAGE_DIFFERENT);
    assert_true(d.max_x == 4 && d.max_y == 5 && d.max_channel == 2);
    assert_int_equal(access(path, F_OK), 0);
    assert_int_equal(image_check(&a, &b, 0.25f, 0.0f, NULL, &d, err, sizeof err), IS_IMAGE_PASS);
    make_pattern(&c, 10, 6, "R,G,B,Z");
    assert_int_equal(image_check(&a, &c, 0.0f, 100.0f, NULL, &d, err, sizeof err), IS_IMAGE_SHAPE_DIFFERS);
    assert_non_null(strstr(err, "[R,G,B,A] against 10x6 [R,G,B,Z]"));
    image_free(&c);
    make_pattern(&c, 10, 5, "R,G,B,A");
    assert_int_equal(image_check(&a, &c, 0.0f, 100.0f, NULL, &d, err, sizeof err), IS_IMAGE_SHAPE_DIFFERS);
    image_free(&c);
    assert_int_equal(image_write(&a, in_dir(pa, f, "a.png"), &META, err, sizeof err), 0);
    assert_int_equal(image_write(&b, in_dir(pb, f, "b.png"), &META, err, sizeof err), 0);
    assert_int_equal(image_check_files(pa, pb, 0.1f, 0.0f, NULL, &d, err, sizeof err), IS_IMAGE_DIFFERENT);
    assert_int_equal(image_check_files(pa, pa, 0.0f, 0.0f, NULL, &d, err, sizeof err), IS_IMAGE_PASS);
    assert_int_equal(image_check_files(pa, in_dir(path, f, "none.png"), 0.0f, 0.0f, NULL, &d, err, sizeof err),
                     IS_IMAGE_IO_ERROR);
    assert_non_null(strstr(err, "none.png"));
    image_free(&a);
    image_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_alloc_and_from_rgba8),
        cmocka_unit_test_setup_teardown(test_png_roundtrip, setup, teardown),
        cmocka_unit_test_setup_teardown(test_exr_roundtrip, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_failures_leave_nothing, setup, teardown),
        cmocka_unit_test_setup_teardown(test_failed_write_keeps_previous, setup, teardown),
        cmocka_unit_test_setup_teardown(test_no_temporaries_left, setup, teardown),
        cmocka_unit_test_setup_teardown(test_read_failures, setup, teardown),
        cmocka_unit_test_setup_teardown(test_compare_finds_changed_pixel, setup, teardown),
        cmocka_unit_test_setup_teardown(test_golden_missing_then_regenerated, setup, teardown),
        cmocka_unit_test_setup_teardown(test_golden_exr, setup, teardown),
        cmocka_unit_test_setup_teardown(test_draw_text, setup, teardown),
        cmocka_unit_test(test_image_check_nonfinite),
        cmocka_unit_test_setup_teardown(test_image_check_verdicts, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
