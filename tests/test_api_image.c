/* tests/test_api_image.c -- every public function of image/image.h with NULL pointers, sizes of zero, negative
 * and beyond IS_IMAGE_MAX_DIM, channel lists that are empty, too long or too many, images whose fields do not
 * describe their data (a hand-made struct), formats that do not exist, text sizes of 0, NaN and huge, and
 * message buffers of 0 and 1 bytes.  Each returns -1 (or a verdict of IS_IMAGE_IO_ERROR / SHAPE_DIFFERS) with a
 * message, never reads or writes outside the image's data (ASan in the sanitizer stage) and never prints.
 * The readers' hostile files are test_image's and test_tool's; this is the API itself.
 * tests/check_api_walkers.sh checks that every INSTESS_API function of image/image.h is named in this file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dlfcn.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../image/image.h"
#include "util/prog.h"

static char dir[256];

static int setup(void **state)
{
    (void)state;
    return prog_mkdtemp(dir, "api-image");
}

static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

/* Paths and formats: NULL, empty, odd names. */
static void test_paths(void **state)
{
    (void)state;
    char err[200], one[1] = {'x'};
    assert_int_equal(image_format_of(NULL), IS_IMAGE_NONE);
    assert_int_equal(image_format_of(""), IS_IMAGE_NONE);
    assert_int_equal(image_format_of(".png"), IS_IMAGE_PNG);   /* the format of the name; image_check_path judges it */
    assert_int_equal(image_format_of("a.PnG"), IS_IMAGE_PNG);
    assert_int_equal(image_format_of("a.pngx"), IS_IMAGE_NONE);
    assert_int_equal(image_format_of("dir.png/a"), IS_IMAGE_NONE);
    assert_int_equal(image_check_path(NULL, err, sizeof err), -1);
    assert_int_equal(image_check_path("", one, sizeof one), -1);
    assert_int_equal(one[0], 0);
    assert_int_equal(image_check_path(".png", err, sizeof err), -1);
    assert_int_equal(image_check_path("a.jpg", NULL, 0), -1);
    assert_int_equal(image_check_path("a.exr", NULL, 0), 0);
    assert_non_null(image_codec_build_version());
    assert_non_null(image_codec_install_dir());
}

/* image_alloc / image_free / image_channel_index / image_from_rgba8 at their edges. */
static void test_alloc(void **state)
{
    (void)state;
    is_image img;
    char err[200];
    const int sizes[][2] = {{0, 1}, {1, 0}, {-1, 5}, {IS_IMAGE_MAX_DIM + 1, 1}, {INT_MAX, INT_MAX}, {INT_MIN, 1}};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        assert_int_equal(image_alloc(&img, sizes[k][0], sizes[k][1], "R", err, sizeof err), -1);
        assert_null(img.data);
    }
    char many[IS_IMAGE_MAX_CHANNELS * 3 + 8] = "";
    for (int k = 0; k <= IS_IMAGE_MAX_CHANNELS; k++) strcat(many, k ? ",c" : "c");
    const char *bad_names[] = {NULL, "", ",", "R,,G", "R,", ",R", "ABCDEFGHIJKLMNOPQ", many};
    for (size_t k = 0; k < sizeof bad_names / sizeof bad_names[0]; k++) {
        assert_int_equal(image_alloc(&img, 2, 2, bad_names[k], err, sizeof err), -1);
        assert_null(img.data);
    }
    assert_int_equal(image_alloc(NULL, 2, 2, "R", err, sizeof err), -1);
    assert_int_equal(image_alloc(&img, 2, 2, "R,G,B,A", NULL, 0), 0);
    assert_int_equal(image_channel_index(&img, "B"), 2);
    assert_int_equal(image_channel_index(&img, NULL), -1);
    assert_int_equal(image_channel_index(NULL, "R"), -1);
    assert_int_equal(image_channel_index(&img, "r"), -1);
    uint32_t px[4] = {0xff0000ffu, 0, 0xffffffffu, 0x80808080u};
    image_from_rgba8(&img, px);
    image_from_rgba8(&img, NULL);
    image_from_rgba8(NULL, px);
    assert_true(img.data[0] == 1.0f && img.data[3] == 1.0f);
    image_free(&img);
    image_free(&img);
    image_free(NULL);
    /* a hand-made image with more channels than it may have: image_channel_index stops at the limit */
    is_image lie = {.width = 1, .height = 1, .channels = IS_IMAGE_MAX_CHANNELS + 100};
    assert_int_equal(image_channel_index(&lie, "X"), -1);
    lie.channels = -5;
    assert_int_equal(image_channel_index(&lie, "X"), -1);
}

/* Images that lie about themselves are refused by every function that would hand their data to the codec. */
static void test_bad_images(void **state)
{
    (void)state;
    char err[300];
    float data[4] = {0};
    is_image good;
    assert_int_equal(image_alloc(&good, 2, 2, "R", err, sizeof err), 0);
    is_image lies[] = {
        {.width = 2, .height = 2, .channels = 1, .data = NULL},
        {.width = 0, .height = 2, .channels = 1, .data = data},
        {.width = 2, .height = -2, .channels = 1, .data = data},
        {.width = 2, .height = 2, .channels = 0, .data = data},
        {.width = 2, .height = 2, .channels = IS_IMAGE_MAX_CHANNELS + 1, .data = data},
        {.width = IS_IMAGE_MAX_DIM + 1, .height = 1, .channels = 1, .data = data},
    };
    for (size_t k = 0; k < sizeof lies / sizeof lies[0]; k++) {
        is_image *b = &lies[k];
        unsigned char *bytes = (unsigned char *)"untouched";
        size_t len = 7;
        assert_int_equal(image_encode(b, IS_IMAGE_PNG, NULL, "lie", &bytes, &len, err, sizeof err), -1);
        assert_true(strlen(err) > 0);
        char path[600];
        assert_int_equal(image_write(b, prog_path(dir, "lie.png", path, sizeof path), NULL, err, sizeof err), -1);
        assert_false(prog_exists(dir, "lie.png"));
        is_image_diff res;
        assert_int_equal(image_compare(b, &good, 0, 0, &res, NULL, err, sizeof err), -1);
        assert_int_equal(image_compare(&good, b, 0, 0, &res, NULL, err, sizeof err), -1);
        is_image_verdict v = image_check(b, &good, 0, 0, NULL, &res, err, sizeof err);
        assert_true(v == IS_IMAGE_IO_ERROR || v == IS_IMAGE_SHAPE_DIFFERS);
        v = image_check(b, b, 0, 0, NULL, &res, err, sizeof err);
        assert_true(v == IS_IMAGE_IO_ERROR || v == IS_IMAGE_SHAPE_DIFFERS);
        const float white[4] = {1, 1, 1, 1};
        assert_int_equal(image_draw_text(b, 0, 10, "x", 12, white, err, sizeof err), -1);
        char names[40] = "untouched";
        if (b->channels < 1 || b->channels > IS_IMAGE_MAX_CHANNELS) {   /* names read only for counts an image has */
            assert_int_equal(image_file_channels(b, IS_IMAGE_EXR, names, sizeof names), 0);
            assert_string_equal(names, "");
        }
    }
    /* The channel lists: counts per format, NULL images and buffers, a list cut to the buffer. */
    assert_int_equal(image_file_channel_count(6, IS_IMAGE_PNG), 4);
    assert_int_equal(image_file_channel_count(6, IS_IMAGE_EXR), 6);
    assert_int_equal(image_file_channel_count(6, IS_IMAGE_NONE), 0);
    char names[8] = "ignored";
    assert_int_equal(image_file_channels(NULL, IS_IMAGE_PNG, names, sizeof names), 0);
    assert_string_equal(names, "");
    is_image rgba;
    assert_int_equal(image_alloc(&rgba, 1, 1, "R,G,B,A,Z", err, sizeof err), 0);
    assert_int_equal(image_file_channels(&rgba, IS_IMAGE_EXR, NULL, 99), strlen("R,G,B,A,Z"));
    assert_int_equal(image_file_channels(&rgba, IS_IMAGE_PNG, names, 4), strlen("R,G,B,A"));
    assert_string_equal(names, "R,G");
    image_free(&rgba);
    image_free(&good);
}

/* NULL arguments of the codec's functions, unknown formats, text at odd sizes, verdicts into no result. */
static void test_codec_calls(void **state)
{
    (void)state;
    char err[300], one[1] = {'x'};
    is_image img, other;
    assert_int_equal(image_alloc(&img, 8, 6, "R,G,B,A", err, sizeof err), 0);
    assert_int_equal(image_alloc(&other, 6, 8, "R,G,B,A", err, sizeof err), 0);
    unsigned char *bytes = NULL;
    size_t len = 0;
    assert_int_equal(image_encode(NULL, IS_IMAGE_PNG, NULL, "x", &bytes, &len, err, sizeof err), -1);
    assert_int_equal(image_encode(&img, IS_IMAGE_NONE, NULL, "x", &bytes, &len, err, sizeof err), -1);
    assert_int_equal(image_encode(&img, (is_image_format)99, NULL, "x", &bytes, &len, err, sizeof err), -1);
    assert_int_equal(image_encode(&img, IS_IMAGE_PNG, NULL, "x", NULL, &len, err, sizeof err), -1);
    assert_int_equal(image_encode(&img, IS_IMAGE_PNG, NULL, "x", &bytes, NULL, one, sizeof one), -1);
    assert_int_equal(one[0], 0);
    assert_int_equal(image_encode(&img, IS_IMAGE_EXR, NULL, NULL, &bytes, &len, err, sizeof err), 0);   /* no label */
    free(bytes);
    is_image_meta meta = {NULL, NULL};
    assert_int_equal(image_encode(&img, IS_IMAGE_PNG, &meta, "x", &bytes, &len, err, sizeof err), 0);
    free(bytes);
    assert_int_equal(image_write(NULL, "x.png", NULL, err, sizeof err), -1);
    assert_int_equal(image_write(&img, NULL, NULL, err, sizeof err), -1);
    assert_int_equal(image_read(NULL, "x.png", err, sizeof err), -1);
    is_image r;
    assert_int_equal(image_read(&r, NULL, err, sizeof err), -1);
    assert_null(r.data);
    assert_int_equal(image_read(&r, "", err, sizeof err), -1);
    is_image_diff res;
    assert_int_equal(image_compare(NULL, &img, 0, 0, &res, NULL, err, sizeof err), -1);
    assert_int_equal(image_compare(&img, &img, 0, 0, NULL, NULL, err, sizeof err), -1);
    assert_int_equal(image_compare(&img, &other, 0, 0, &res, NULL, err, sizeof err), -1);   /* shapes differ */
    assert_int_equal(image_check(NULL, &img, 0, 0, NULL, &res, err, sizeof err), IS_IMAGE_BAD_ARGUMENT);
    assert_int_equal(image_check(&img, NULL, 0, 0, NULL, &res, err, sizeof err), IS_IMAGE_BAD_ARGUMENT);
    assert_int_equal(image_check(&img, &img, 0, 0, NULL, NULL, err, sizeof err), IS_IMAGE_PASS);   /* no result */
    assert_int_equal(image_check(&img, &other, 0, 0, NULL, NULL, err, sizeof err), IS_IMAGE_SHAPE_DIFFERS);
    /* thresholds that are not numbers >= 0 would decide nothing (NaN passed everything): refused */
    const float thr[][2] = {{NAN, 0}, {0, NAN}, {-1.0f, 0}, {0, -1.0f}, {0, 100.5f}, {-INFINITY, 0}, {0, INFINITY}};
    for (size_t k = 0; k < sizeof thr / sizeof thr[0]; k++)
        assert_int_equal(image_check(&img, &img, thr[k][0], thr[k][1], NULL, &res, err, sizeof err),
                         IS_IMAGE_BAD_ARGUMENT);
    assert_int_equal(image_check(&img, &img, INFINITY, 100.0f, NULL, &res, err, sizeof err), IS_IMAGE_PASS);
    assert_int_equal(image_check(&img, &img, FLT_MAX, 0.0f, NULL, &res, err, sizeof err), IS_IMAGE_PASS);
    assert_int_equal(image_check_files(NULL, "b.png", 0, 0, NULL, &res, err, sizeof err), IS_IMAGE_BAD_ARGUMENT);
    assert_int_equal(image_check_files("a.png", NULL, 0, 0, NULL, &res, err, sizeof err), IS_IMAGE_BAD_ARGUMENT);
    assert_int_equal(image_check_files(NULL, NULL, 0, 0, NULL, NULL, NULL, 0), IS_IMAGE_BAD_ARGUMENT);
    assert_int_equal(image_check_files("nothere-a.png", "nothere-b.png", 0, 0, NULL, NULL, err, sizeof err),
                     IS_IMAGE_IO_ERROR);
    /* text: NULL image, text and colour; sizes 0, negative, NaN, huge; positions far outside; non-ASCII */
    const float white[4] = {1, 1, 1, 1};
    assert_int_equal(image_draw_text(NULL, 0, 0, "x", 12, white, err, sizeof err), -1);
    assert_int_equal(image_draw_text(&img, 0, 0, NULL, 12, white, err, sizeof err), -1);
    assert_int_equal(image_draw_text(&img, 0, 0, "x", 12, NULL, err, sizeof err), -1);
    const float sizes[] = {0.0f, -5.0f, NAN, INFINITY, 1e30f, 5000.0f};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        assert_int_equal(image_draw_text(&img, 0, 5, "x", sizes[k], white, err, sizeof err), -1);
        int w = 1, h = 1;
        assert_int_equal(image_text_size("x", sizes[k], &w, &h), -1);
    }
    const int pos[][2] = {{INT_MIN, INT_MIN}, {INT_MAX, INT_MAX}, {-100000, 3}, {3, 100000}};
    for (size_t k = 0; k < sizeof pos / sizeof pos[0]; k++)
        assert_true(image_draw_text(&img, pos[k][0], pos[k][1], "clipped\nlines", 10, white, err, sizeof err) >= -1);
    const float nan_colour[4] = {NAN, INFINITY, -1, 2};
    assert_true(image_draw_text(&img, 0, 5, "x", 10, nan_colour, err, sizeof err) >= -1);
    assert_true(image_draw_text(&img, 0, 5, "\xff\xfe\x01 bytes", 10, white, err, sizeof err) >= -1);
    int w = 7, h = 7;
    assert_int_equal(image_text_size(NULL, 12, &w, &h), -1);
    assert_int_equal(image_text_size("x", 12, NULL, &h), -1);
    assert_int_equal(image_text_size("", 12, &w, &h), 0);
    assert_true(w == 0 && h == 0);
    for (size_t k = 0; k < (size_t)img.width * img.height * img.channels; k++) assert_false(isnan(img.data[k]));
    image_free(&img);
    image_free(&other);
}

/* image_module_open: NULL and empty arguments, a relative path, a missing file, a folder, a file that is not ELF
 * (each refused with a message, nothing loaded); the build's codec module opens when asked for the symbol it
 * defines and is refused for one it does not. */
static void test_module_open(void **state)
{
    (void)state;
    char err[600], codec[4200], here[4096];
    assert_null(image_module_open(NULL, "codec_abi", err, sizeof err));
    assert_null(image_module_open("/x.so", NULL, err, sizeof err));
    assert_null(image_module_open("/x.so", "", NULL, 0));
    assert_null(image_module_open("libinstess_codec.so", "codec_abi", err, sizeof err));
    assert_non_null(strstr(err, "not an absolute path: refused"));
    assert_null(image_module_open("/nonexistent/lib.so", "codec_abi", err, sizeof err));
    assert_non_null(strstr(err, "/nonexistent/lib.so"));
    assert_null(image_module_open("/", "codec_abi", err, sizeof err));
    assert_non_null(strstr(err, "not a regular file: refused"));
    assert_null(image_module_open("/etc/passwd", "codec_abi", err, sizeof err));
    assert_non_null(strstr(err, "not a 64-bit ELF shared object"));
    /* the codec module beside this test program (the build links it there) */
    ssize_t n = readlink("/proc/self/exe", here, sizeof here - 1);
    assert_true(n > 0);
    here[n] = 0;
    *strrchr(here, '/') = 0;
    snprintf(codec, sizeof codec, "%s/libinstess_codec.so", here);
    assert_null(image_module_open(codec, "no_such_symbol", err, sizeof err));
    assert_non_null(strstr(err, "does not define no_such_symbol"));
    void *h = image_module_open(codec, "codec_abi", err, sizeof err);
    if (!h) fail_msg("%s", err);
    dlclose(h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_paths),
        cmocka_unit_test(test_alloc),
        cmocka_unit_test(test_bad_images),
        cmocka_unit_test(test_codec_calls),
        cmocka_unit_test(test_module_open),
    };
    return cmocka_run_group_tests_name("api_image", tests, setup, teardown);
}
