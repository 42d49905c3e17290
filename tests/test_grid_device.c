/* tests/test_grid_device.c -- the device tells the rasterizer when a draw's instances are the regular grid
 * (core/draw_fused.c: core_grid_regular_level once per draw, rs_source.grid_level): cubes drawn with the regular
 * grid take the rasterizer's grid rows (the chunks' grid_groups count), drawn with the primitive generator's grid
 * at the same level (another index list) they do not; drawn with the regular grid's list mirrored (the winding of
 * the adaptive buckets' odd ranges: core_grid_regular_level_mirrored, rs_source.grid_mirrored) they do, and so do
 * adaptive draws (--lod screen: every bucket a regular grid of moved points, tess/instancing.c); either way the
 * bytes and statistics are the reference path's, 1 and 2 threads, every instruction set the CPU has. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../core/device_internal.h"
#include "../raster/raster_internal.h"
#include "util/patch_util.h"

/* Grid groups the rasterizer of dev set up from rows in its last set-up (every chunk of a fresh device's frame). */
static uint64_t grid_groups(const is_device *dev)
{
    uint64_t n = 0;
    for (size_t c = 0; c < dev->rs->n_chunks_cap; c++) n += dev->rs->chunks[c].grid_groups;
    return n;
}

/* Render o (mesh m) on a fresh device, reference path or the fast paths of instruction set isa; with grid g when
 * it is not NULL (else o's grid, or o's adaptive levels). */
static is_device *render_grid(const scene_opts *o, const is_mesh *m, bool reference, int isa, const core_grid *g)
{
    char err[256];
    is_device *dev = dev_create(o->width, o->height, 1, err, sizeof err);
    assert_non_null(dev);
    dev_set_threads(dev, o->threads);
    dev_set_reference_path(dev, reference);
    if (!reference) assert_int_equal(dev_set_isa(dev, isa), 0);
    if (g) {
        dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, o->background, 1.0f);
        assert_int_equal(scene_draw(dev, o, m, g, NULL), 0);
    } else {
        assert_int_equal(clear_and_draw(dev, o, m), 0);
    }
    assert_non_null(dev_render_target(dev));
    return dev;
}

/* render_grid with o's own grid. */
static is_device *render(const scene_opts *o, const is_mesh *m, bool reference, int isa)
{
    return render_grid(o, m, reference, isa, NULL);
}

/* o drawn on the reference path and on the fast paths of every instruction set, 1 and 2 threads (grid g, or o's
 * own when NULL): the same bytes and statistics, and the grid rows taken (rows) or not. */
static void same_as_reference(scene_opts o, const is_mesh *m, const core_grid *g, bool rows)
{
    for (int threads = 1; threads <= 2; threads++) {
        o.threads = threads;
        is_device *ref = render_grid(&o, m, true, 0, g);
        const rs_target *a = dev_render_target(ref);
        const size_t n = (size_t)a->width * (size_t)a->height;
        for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
            if (!rs_isa_supported(isa)) continue;
            is_device *fast = render_grid(&o, m, false, isa, g);
            const rs_target *b = dev_render_target(fast);
            assert_memory_equal(a->color, b->color, n * sizeof *a->color);
            assert_memory_equal(a->depth, b->depth, n * sizeof *a->depth);
            assert_memory_equal(dev_stats(ref), dev_stats(fast), sizeof(rs_stats));
            if (rows) assert_true(grid_groups(fast) > 0);
            else assert_int_equal(grid_groups(fast), 0);
            dev_destroy(fast);
        }
        assert_true(dev_stats(ref)->samples_written > 0);
        dev_destroy(ref);
    }
}

/* 4 x 4 cubes at level 6 (192 x 192: small triangles, many instances in one tile, some over tile borders) with the
 * regular grid and with the primitive generator's: the reference path's bytes, and the grid rows taken only for
 * the regular grid. */
static void test_device_tells_grid(void **state)
{
    (void)state;
    is_mesh m;
    assert_int_equal(cubes_mesh(4, &m), 0);
    static const core_grid_kind kinds[] = { CORE_GRID_REGULAR, CORE_GRID_PG_EQUAL };
    for (size_t g = 0; g < sizeof kinds / sizeof *kinds; g++)
        for (int threads = 1; threads <= 2; threads++) {
            scene_opts o;
            scene_opts_default(&o);
            o.level = 6, o.width = 192, o.height = 192, o.distance = 2.4f, o.msaa = 1, o.threads = threads;
            o.grid = kinds[g];
            is_device *ref = render(&o, &m, true, 0);
            const rs_target *a = dev_render_target(ref);
            const size_t n = (size_t)a->width * (size_t)a->height;
            for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
                if (!rs_isa_supported(isa)) continue;
                is_device *fast = render(&o, &m, false, isa);
                const rs_target *b = dev_render_target(fast);
                assert_memory_equal(a->color, b->color, n * sizeof *a->color);
                assert_memory_equal(a->depth, b->depth, n * sizeof *a->depth);
                assert_memory_equal(dev_stats(ref), dev_stats(fast), sizeof(rs_stats));
                if (kinds[g] == CORE_GRID_REGULAR) assert_true(grid_groups(fast) > 0);
                else assert_int_equal(grid_groups(fast), 0);
                dev_destroy(fast);
            }
            assert_true(dev_stats(ref)->samples_written > 0);
            dev_destroy(ref);
        }
    mesh_free(&m);
}

/* The cubes drawn with the regular level-6 grid's list mirrored (each triangle's second and third index swapped:
 * the other winding, so under the default cull the cubes' insides are drawn) take the grid rows, with the
 * reference path's bytes; and adaptive draws (--lod screen, levels 2..8 over the cubes' edges: buckets of both
 * parities) take them too. */
static void test_device_tells_mirrored_and_adaptive(void **state)
{
    (void)state;
    is_mesh m;
    assert_int_equal(cubes_mesh(4, &m), 0);
    scene_opts o;
    scene_opts_default(&o);
    o.level = 6, o.width = 192, o.height = 192, o.distance = 2.4f, o.msaa = 1;
    core_grid g;
    assert_int_equal(core_grid_make(CORE_GRID_REGULAR, 6.0f, &g), 0);
    for (size_t t = 0; t < g.n_triangles; t++) {
        const uint32_t k = g.idx[3 * t + 1];
        g.idx[3 * t + 1] = g.idx[3 * t + 2], g.idx[3 * t + 2] = k;
    }
    same_as_reference(o, &m, &g, true);
    core_grid_free(&g);
    o.lod = TESS_LOD_SCREEN, o.min_level = 2, o.max_level = 8, o.lod_target = 3.0f;
    same_as_reference(o, &m, NULL, true);
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_device_tells_grid),
        cmocka_unit_test(test_device_tells_mirrored_and_adaptive),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
