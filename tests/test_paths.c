/* tests/test_paths.c -- the three ways D3D9 offered to draw an N-Patch give identical images :
 * (a) the device's N-patch mode, (b) tessellation through instancing with the N-Patch vertex shader, (c) CPU
 * tessellation into a dynamic vertex buffer drawn without instancing.  Also: images do not depend on the thread
 * count (determinism), and the golden images of the flat, N-Patch and smoothed cube and tetrahedron. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "../cli/run/scene.h"
#include "util/golden.h"

/* Render mesh `name` with o into img (asserting success). */
static void render(const scene_opts *o, const char *name, is_image *img)
{
    is_mesh m = {0};
    char err[512];
    assert_int_equal(mesh_builtin(name, &m, err, sizeof err), 0);
    memset(img, 0, sizeof *img);
    int rc = scene_render_mesh(o, &m, img, NULL, err, sizeof err);
    if (rc) fprintf(stderr, "render failed: %s\n", err);
    assert_int_equal(rc, 0);
    mesh_free(&m);
}

/* Number of values that differ between two images of the same size. */
static long differences(const is_image *a, const is_image *b)
{
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->channels, b->channels);
    long n = 0;
    for (long k = 0; k < (long)a->width * a->height * a->channels; k++) n += memcmp(&a->data[k], &b->data[k], 4) != 0;
    return n;
}

/* Count pixels that are not the background (the object is on screen). */
static long object_pixels(const is_image *a)
{
    long n = 0;
    for (long p = 0; p < (long)a->width * a->height; p++) n += a->data[p * a->channels + 4] < 1.0f;
    return n;
}

static void test_three_npatch_paths_identical(void **state)
{
    const char *meshes[] = {"tetrahedron", "cube", "icosahedron", "sphere"};
    const int levels[] = {1, 3, 8};
    const vs_normals normals[] = {VS_NORMALS_LINEAR, VS_NORMALS_QUADRATIC};
    const vs_patch patches[] = {VS_PATCH_NPATCH, VS_PATCH_FLAT};
    for (size_t mi = 0; mi < 4; mi++)
        for (size_t li = 0; li < 3; li++)
            for (size_t ni = 0; ni < 2; ni++)
                for (size_t pi = 0; pi < 2; pi++) {
                    scene_opts o;
                    scene_opts_default(&o);
                    o.width = o.height = 96, o.level = (float)levels[li], o.normals = normals[ni];
                    o.patch = patches[pi], o.fill = SCENE_FILL_SOLID_WIRE;
                    is_image a, b, c;
                    o.path = SCENE_PATH_INSTANCED;
                    render(&o, meshes[mi], &a);
                    o.path = SCENE_PATH_NPATCH_MODE;
                    render(&o, meshes[mi], &b);
                    o.path = SCENE_PATH_CPU;
                    render(&o, meshes[mi], &c);
                    assert_true(object_pixels(&a) > 500);
                    long dab = differences(&a, &b), dac = differences(&a, &c);
                    if (dab || dac)
                        fprintf(stderr, "%s level %d normals %d patch %d: %ld / %ld values differ\n", meshes[mi],
                                levels[li], (int)normals[ni], (int)patches[pi], dab, dac);
                    assert_int_equal(dab, 0);
                    assert_int_equal(dac, 0);
                    image_free(&a), image_free(&b), image_free(&c);
                }
}

/* PATCHEDGESTYLE CONTINUOUS: N-patch mode at a fractional level tessellates with the fractional_even pattern, and
 * equals the instanced and CPU paths on that grid. */
static void test_continuous_npatch_paths_identical(void **state)
{
    const float levels[] = {1.0f, 2.3f, 3.6f, 5.5f};
    for (size_t li = 0; li < 4; li++) {
        scene_opts o;
        scene_opts_default(&o);
        o.width = o.height = 96, o.level = levels[li], o.patch = VS_PATCH_NPATCH, o.grid = CORE_GRID_PG_FRACTIONAL_EVEN;
        o.fill = SCENE_FILL_SOLID_WIRE;
        o.normals = VS_NORMALS_LINEAR;   /* the fixed-function paths' normals (real ones only on the instanced path) */
        is_image a, b, c;
        o.path = SCENE_PATH_INSTANCED;
        render(&o, "sphere", &a);
        o.path = SCENE_PATH_NPATCH_MODE;
        render(&o, "sphere", &b);
        o.path = SCENE_PATH_CPU;
        render(&o, "sphere", &c);
        assert_int_equal(differences(&a, &b), 0);
        assert_int_equal(differences(&a, &c), 0);
        image_free(&a), image_free(&b), image_free(&c);
    }
    /* and the fractional level really changes the picture (continuous, not truncated) */
    scene_opts o;
    scene_opts_default(&o);
    o.width = o.height = 96, o.patch = VS_PATCH_NPATCH, o.grid = CORE_GRID_PG_FRACTIONAL_EVEN;
    o.fill = SCENE_FILL_WIRE, o.path = SCENE_PATH_NPATCH_MODE;
    is_image a, b;
    o.level = 3.2f;
    render(&o, "sphere", &a);
    o.level = 3.7f;
    render(&o, "sphere", &b);
    assert_true(differences(&a, &b) > 50);
    image_free(&a), image_free(&b);
}

/* The N-Patch and the flat patch really differ (the comparison above is not vacuous). */
static void test_paths_compare_something(void **state)
{
    scene_opts o;
    scene_opts_default(&o);
    o.width = o.height = 96, o.level = 6, o.patch = VS_PATCH_NPATCH;
    is_image a, b;
    render(&o, "cube", &a);
    o.patch = VS_PATCH_FLAT;
    render(&o, "cube", &b);
    assert_true(differences(&a, &b) > 100);
    image_free(&a), image_free(&b);
}

static void test_threads_do_not_change_bytes(void **state)
{
    const vs_patch patches[] = {VS_PATCH_NPATCH, VS_PATCH_SMOOTH, VS_PATCH_PHONG};
    for (size_t pi = 0; pi < 3; pi++) {
        scene_opts o;
        scene_opts_default(&o);
        o.width = 300, o.height = 200, o.level = 12, o.patch = patches[pi], o.fill = SCENE_FILL_SOLID_WIRE;
        is_image img[3];
        const int threads[3] = {1, 2, 4};
        for (int t = 0; t < 3; t++) {
            o.threads = threads[t];
            render(&o, "sphere", &img[t]);
        }
        assert_int_equal(differences(&img[0], &img[1]), 0);
        assert_int_equal(differences(&img[0], &img[2]), 0);
        for (int t = 0; t < 3; t++) image_free(&img[t]);
    }
}

/* Golden images: 160x160, 4x MSAA, PNG.  Thresholds: the render is deterministic for the documented build
 * configuration, so a pixel fails when any channel differs by more than 1/255 (one step of 8-bit rounding), and
 * at most 0.1% of the pixels may fail (a few pixels of slack for libm differences in the camera's sin/cos on
 * another glibc); anything more is a real change. */
static void golden(const char *name, const char *mesh, vs_patch p, scene_fill fill)
{
    scene_opts o;
    scene_opts_default(&o);
    o.width = o.height = 160, o.level = 8, o.patch = p, o.fill = fill;
    o.normals = VS_NORMALS_LINEAR;   /* the goldens were rendered with D3D9's normals, the default until real normals became it */
    is_image img;
    render(&o, mesh, &img);
    assert_int_equal(golden_check(&img, name, 1.0f / 255.0f, 0.1f), 0);
    image_free(&img);
}

static void test_golden_flat_cube(void **state) { golden("flat-cube", "cube", VS_PATCH_FLAT, SCENE_FILL_SOLID_WIRE); }
static void test_golden_npatch_cube(void **state) { golden("npatch-cube", "cube", VS_PATCH_NPATCH, SCENE_FILL_SOLID); }
static void test_golden_smooth_cube(void **state) { golden("smooth-cube", "cube", VS_PATCH_SMOOTH, SCENE_FILL_SOLID); }
static void test_golden_npatch_tetrahedron(void **state)
{
    golden("npatch-tetrahedron", "tetrahedron", VS_PATCH_NPATCH, SCENE_FILL_SOLID);
}
static void test_golden_smooth_tetrahedron(void **state)
{
    golden("smooth-tetrahedron", "tetrahedron", VS_PATCH_SMOOTH, SCENE_FILL_SOLID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_three_npatch_paths_identical), cmocka_unit_test(test_paths_compare_something),
        cmocka_unit_test(test_continuous_npatch_paths_identical),
        cmocka_unit_test(test_threads_do_not_change_bytes),  cmocka_unit_test(test_golden_flat_cube),
        cmocka_unit_test(test_golden_npatch_cube),           cmocka_unit_test(test_golden_smooth_cube),
        cmocka_unit_test(test_golden_npatch_tetrahedron),    cmocka_unit_test(test_golden_smooth_tetrahedron),
    };
    return cmocka_run_group_tests_name("paths", tests, NULL, NULL);
}
