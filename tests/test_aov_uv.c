/* tests/test_aov_uv.c -- the uv AOV (cli/run/scene.c's scene_aov_table; issue 28, item 5): an .exr output of a
 * render with --texture gets the channels uv.U, uv.V (TEXCOORD0.xy, the coordinates the texture is sampled at)
 * by itself, in the table's place among the other AOVs (before depth, whose values stay right); --aov uv asks
 * for them without a texture and gives the same values; a PNG output, or no texture, adds none.  The values:
 * the built-in sphere's longitude-latitude coordinates (meshes/builtin.c: u = 1/2 + atan2(z, -x) / 2 pi,
 * v = acos(y) / pi), seen head-on (--yaw 0 --pitch 0, the camera looking along +z at the point (0, 0, -1)), are
 * (1/4, 1/2) at the image centre; u falls to the right (towards the seam at +x, where the patch's coordinates
 * run a little past 1) and v grows downwards; the background is 0. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../cli/run/scene.h"
#include "util/prog.h"

enum { N = 64 };

/* The table and scene_aovs_of: uv only with a texture and an .exr output; the names parse. */
static void test_aovs_of(void **state)
{
    (void)state;
    scene_opts o;
    scene_opts_default(&o);
    o.aovs = SCENE_AOV_NORMAL;
    o.output = "a.exr";
    assert_int_equal(scene_aovs_of(&o), SCENE_AOV_NORMAL);
    o.texture = "t.png";
    assert_int_equal(scene_aovs_of(&o), SCENE_AOV_NORMAL | SCENE_AOV_UV);
    o.output = "a.PNG";
    assert_int_equal(scene_aovs_of(&o), SCENE_AOV_NORMAL);
    o.output = NULL;
    assert_int_equal(scene_aovs_of(&o), SCENE_AOV_NORMAL);
    unsigned m = 0;
    assert_true(scene_parse_aovs("uv,depth", &m));
    assert_int_equal(m, SCENE_AOV_UV | SCENE_AOV_DEPTH);
    assert_false(scene_parse_aovs("uv,texcoord", &m));
    /* one entry per bit, every bit a power of two */
    unsigned all = 0;
    for (int k = 0; k < SCENE_AOV_COUNT; k++) {
        assert_int_equal(scene_aov_table[k].bit & (scene_aov_table[k].bit - 1), 0);
        assert_int_equal(all & scene_aov_table[k].bit, 0);
        all |= scene_aov_table[k].bit;
    }
}

/* Render the sphere head-on into dir/name with extra arguments; read it into img. */
static void render(const char *dir, const char *extra, const char *name, is_image *img)
{
    char path[512], err[256];
    const char *e;
    assert_int_equal(prog_run(dir, &e, "", "sphere --level 3 --size %dx%d --msaa 1 --yaw 0 --pitch 0 %s -q -o %s", N, N,
                              extra, prog_path(dir, name, path, sizeof path)), 0);
    assert_int_equal(image_read(img, path, err, sizeof err), 0);
}

static void test_uv_channels(void **state)
{
    (void)state;
    char dir[256], tpath[512], extra[700], err[256];
    assert_int_equal(prog_mkdtemp(dir, "aov_uv"), 0);
    is_image t;
    assert_int_equal(image_alloc(&t, 4, 4, "R,G,B,A", err, sizeof err), 0);
    for (int p = 0; p < 16 * 4; p++) t.data[p] = 1.0f;
    assert_int_equal(image_write(&t, prog_path(dir, "t.png", tpath, sizeof tpath), NULL, err, sizeof err), 0);
    image_free(&t);
    is_image a, b, c;
    snprintf(extra, sizeof extra, "--texture %s --aov normal,depth", tpath);
    render(dir, extra, "a.exr", &a);
    render(dir, "--aov uv", "b.exr", &b);
    render(dir, "--aov normal,depth", "c.exr", &c);
    int ua = image_channel_index(&a, "uv.U"), va = image_channel_index(&a, "uv.V");
    int ub = image_channel_index(&b, "uv.U"), vb = image_channel_index(&b, "uv.V");
    int da = image_channel_index(&a, "depth"), dc = image_channel_index(&c, "depth");
    /* (an EXR file orders its channels by name: the values below check each plane landed in its channel) */
    assert_true(ua >= 0 && va >= 0 && da >= 0 && ub >= 0 && vb >= 0 && dc >= 0);
    assert_int_equal(a.channels, 11), assert_int_equal(b.channels, 7);
    assert_int_equal(image_channel_index(&c, "uv.U"), -1);
    int covered = 0;
    for (int p = 0; p < N * N; p++) {
        const float *pa = a.data + p * a.channels, *pb = b.data + p * b.channels, *pc = c.data + p * c.channels;
        assert_true(pa[ua] == pb[ub] && pa[va] == pb[vb]);    /* the same coordinates, texture or not */
        assert_true(pa[da] == pc[dc] || (isinf(pa[da]) && isinf(pc[dc])));   /* depth in its place, untouched */
        if (pa[image_channel_index(&a, "Z")] >= 1.0f) {
            assert_true(pa[ua] == 0.0f && pa[va] == 0.0f);    /* the background */
            continue;
        }
        covered++;
        assert_true(isfinite(pa[ua]) && isfinite(pa[va]));
    }
    assert_true(covered > N * N / 4);
    /* head-on: (0.5, 0.5) in the middle, u to the right, v downwards */
    const float *mid = a.data + ((N / 2) * N + N / 2) * a.channels;
    const float *right = a.data + ((N / 2) * N + N / 2 + 8) * a.channels;
    const float *below = a.data + ((N / 2 + 8) * N + N / 2) * a.channels;
    assert_true(fabsf(mid[ua] - 0.25f) < 0.01f && fabsf(mid[va] - 0.5f) < 0.01f);
    assert_true(right[ua] < mid[ua] - 0.02f && fabsf(right[va] - mid[va]) < 0.01f);
    assert_true(below[va] > mid[va] + 0.05f && fabsf(below[ua] - mid[ua]) < 0.02f);
    image_free(&a), image_free(&b), image_free(&c);
    /* a PNG output: no AOVs, and the texture still renders */
    snprintf(extra, sizeof extra, "--texture %s", tpath);
    render(dir, extra, "d.png", &a);
    assert_int_equal(image_channel_index(&a, "uv.U"), -1);
    image_free(&a);
    prog_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_aovs_of),
        cmocka_unit_test(test_uv_channels),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
