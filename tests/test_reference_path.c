/* tests/test_reference_path.c -- the optimized draw path (batched shading, shared vertex projection, 8-pixel
 * spans) writes exactly the bytes of the scalar reference path (dev_set_reference_path(dev, true)): scenes
 * shaped like the benchmark's A (one cube, high level), B (many cubes, geometry-bound) and C (one cube, low level,
 * fill-bound), smaller, with every patch, 1 and 2 threads, plus the cases that leave the fast paths: near-plane
 * clipping, a target width that is not a multiple of 8, 4 samples, AOV planes, the wireframe overlay, the
 * device's N-patch mode and CPU tessellation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cli/scene.h"

/* The cube, or side x side copies of it 3 apart in the z = 0 plane (the benchmark's scene B layout). */
static void make_cubes(int side, is_mesh *out)
{
    char err[256];
    is_mesh cube = {0};
    assert_int_equal(mesh_builtin("cube", &cube, err, sizeof err), 0);
    if (side == 1) {
        *out = cube;
        return;
    }
    size_t copies = (size_t)side * (size_t)side, nv = cube.n_vertices, nt = cube.n_triangles;
    float3 *p = malloc(copies * nv * sizeof *p), *n = malloc(copies * nv * sizeof *n);
    uint32_t *idx = malloc(copies * nt * 3 * sizeof *idx);
    assert_non_null(p), assert_non_null(n), assert_non_null(idx);
    for (size_t c = 0; c < copies; c++) {
        float ox = ((float)(c % (size_t)side) - 0.5f * (float)(side - 1)) * 3.0f;
        float oy = ((float)(c / (size_t)side) - 0.5f * (float)(side - 1)) * 3.0f;
        for (size_t k = 0; k < nv; k++) p[c * nv + k] = add3(cube.positions[k], f3(ox, oy, 0.0f)), n[c * nv + k] = cube.normals[k];
        for (size_t k = 0; k < 3 * nt; k++) idx[c * 3 * nt + k] = (uint32_t)(c * nv) + cube.indices[k];
    }
    is_mesh_data md = {copies * nv, copies * nt, p, n, NULL, idx};
    assert_int_equal(mesh_create(out, "cubes", &md, NULL, err, sizeof err), 0);
    free(p), free(n), free(idx);
    mesh_free(&cube);
}

/* Render o (mesh m) on a fresh device with the reference path on or off; returns the device. */
static is_device *render(const scene_opts *o, const is_mesh *m, unsigned aovs, bool reference)
{
    char err[256];
    core_grid g;
    assert_int_equal(core_grid_make(o->grid, o->level, &g), 0);
    is_device *dev = dev_create(o->width, o->height, aovs ? 1 : o->msaa, err, sizeof err);
    assert_non_null(dev);
    dev_set_threads(dev, o->threads);
    dev_set_reference_path(dev, reference);
    assert_true(dev_reference_path(dev) == reference);
    for (int k = 0; aovs && k < 4; k++)
        assert_int_equal(rs_target_add_aov(dev_render_target(dev), RS_ATTR_TEXCOORD0 + 1 + k, k == 2 ? 1 : 3), RS_OK);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, o->background, 1.0f);
    int rc = scene_draw(dev, o, m, &g, NULL);
    if (rc) fprintf(stderr, "draw failed: %s\n", dev_last_error(dev));
    assert_int_equal(rc, 0);
    core_grid_free(&g);
    return dev;
}

/* Both paths give the same colour, depth and AOV bytes and the same statistics; returns the samples written. */
static uint64_t check_same(const scene_opts *o, const is_mesh *m, unsigned aovs)
{
    is_device *ref = render(o, m, aovs, true), *fast = render(o, m, aovs, false);
    const rs_target *a = dev_render_target(ref), *b = dev_render_target(fast);
    size_t n = (size_t)a->width * (size_t)a->height * (size_t)a->samples;
    assert_memory_equal(a->color, b->color, n * sizeof *a->color);
    assert_memory_equal(a->depth, b->depth, n * sizeof *a->depth);
    for (int k = 0; k < a->n_aov; k++)
        assert_memory_equal(a->aov[k].data, b->aov[k].data,
                            (size_t)a->width * (size_t)a->height * (size_t)a->aov[k].comps * sizeof(float));
    const rs_stats *sa = dev_stats(ref), *sb = dev_stats(fast);
    assert_memory_equal(sa, sb, sizeof *sa);
    assert_true(dev_vertices_shaded(ref) == dev_vertices_shaded(fast));
    uint64_t written = sa->samples_written;
    dev_destroy(ref);
    dev_destroy(fast);
    return written;
}

/* A scene: side x side cubes at `level` on a w x h target, 1 sample, camera distance d. */
static scene_opts scene(float level, int w, int h, float d)
{
    scene_opts o;
    scene_opts_default(&o);
    o.level = level, o.width = w, o.height = h, o.distance = d, o.msaa = 1;
    return o;
}

/* Every patch (and both thread counts) on one scene: same bytes, and something was drawn. */
static void all_patches(int side, float level, int w, int h, float d)
{
    is_mesh m;
    make_cubes(side, &m);
    for (int p = 0; p < VS_PATCH_COUNT; p++)
        for (int t = 1; t <= 2; t++) {
            scene_opts o = scene(level, w, h, d);
            o.patch = (vs_patch)p, o.threads = t;
            assert_true(check_same(&o, &m, 0) > 0);
        }
    mesh_free(&m);
}

/* A: one cube at a high level. */
static void test_scene_a(void **state) { (void)state; all_patches(1, 16, 160, 160, 3.2f); }
/* B: 16 cubes at a middle level (small triangles, most of the work in geometry). */
static void test_scene_b(void **state) { (void)state; all_patches(4, 6, 192, 192, 2.4f); }
/* C: one cube at a low level on a larger target (few large triangles). */
static void test_scene_c(void **state) { (void)state; all_patches(1, 2, 320, 320, 3.2f); }

/* The cases off the fast paths or at their edges, with the smoothed patch. */
static void test_edge_cases(void **state)
{
    (void)state;
    is_mesh m;
    make_cubes(1, &m);
    scene_opts o = scene(8, 131, 97, 1.1f); /* near-plane and guard-band clipping, width % 8 != 0 */
    o.threads = 2;
    check_same(&o, &m, 0);
    o = scene(8, 133, 101, 3.2f);
    o.msaa = 4; /* 4 samples: reference rasterizer on both, batched shading on one */
    assert_true(check_same(&o, &m, 0) > 0);
    o.msaa = 1;
    o.normals = VS_NORMALS_QUADRATIC;
    assert_true(check_same(&o, &m, SCENE_AOV_NORMAL) > 0); /* AOV planes */
    o.normals = VS_NORMALS_REAL;
    o.fill = SCENE_FILL_SOLID_WIRE; /* lines with depth bias over the solid */
    assert_true(check_same(&o, &m, 0) > 0);
    o.fill = SCENE_FILL_SOLID;
    o.normals = VS_NORMALS_LINEAR;
    o.patch = VS_PATCH_NPATCH;
    o.path = SCENE_PATH_NPATCH_MODE;
    assert_true(check_same(&o, &m, 0) > 0);
    o.path = SCENE_PATH_CPU;
    assert_true(check_same(&o, &m, 0) > 0);
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scene_a),
        cmocka_unit_test(test_scene_b),
        cmocka_unit_test(test_scene_c),
        cmocka_unit_test(test_edge_cases),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
