/* tests/test_vs_grid.c -- the patch shaders' grid workspace (is_vertex_shader.grid_batch, core/device.h): the
 * per-grid plan (which points are interior, on an edge or corners, their Bernstein products, Gregory weights and
 * curve parameters, computed once per grid) gives exactly the bytes of the per-vertex evaluation (`main`) and of
 * the plain batch (with the colours saturated, as grid_batch hands them over), on regular, adaptive and
 * primitive-generator grids and grid points with negative zeros, tiny and slightly negative weights, for the
 * N-Patch and the smoothed patch, every normal mode, with and without the
 * smooth shortcut, with every instance family of tests/test_reference_path.c (degenerate edges, zero normals,
 * huge coordinates, boundary edges); the workspace's states (not ready, ready for another grid, too small,
 * absent, holding garbage); and the device's fused path, which must rebuild the plan when the grid of a draw
 * changes (same vertex count, points permuted), against the reference path. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/patch_util.h"
#include "../core/grid.h"
#include "../core/hlsl.h"

/* The grids of the test: kind 0..7 regular levels, 8..11 adaptive patterns, 12..13 primitive-generator grids,
 * 14 odd points (negative zeros, tiny and slightly negative weights, no positive weight, a NaN weight, random
 * points); n points into *g. */
enum { GRIDS = 15 };
static void make_grid(int kind, core_grid *g, uint32_t *st)
{
    static const int regular[8] = {1, 2, 3, 5, 7, 8, 16, 33};
    static const int adaptive[4][3] = {{1, 2, 3}, {4, 4, 7}, {8, 3, 5}, {16, 1, 16}};
    if (kind < 8) {
        assert_int_equal(core_grid_make(CORE_GRID_REGULAR, (float)regular[kind], g), 0);
    } else if (kind < 12) {
        assert_int_equal(core_grid_adaptive(adaptive[kind - 8], g), 0);
    } else if (kind == 12) {
        assert_int_equal(core_grid_make(CORE_GRID_PG_FRACTIONAL_ODD, 5.3f, g), 0);
    } else if (kind == 13) {
        const float outer[3] = {3.0f, 5.5f, 7.0f};
        assert_int_equal(core_grid_pg(CORE_GRID_PG_FRACTIONAL_EVEN, 4.5f, outer, g), 0);
    } else {
        assert_int_equal(core_grid_make(CORE_GRID_REGULAR, 9.0f, g), 0);
        for (size_t v = 0; v < g->n_points; v++) {
            float3 *b = &g->bary[v];
            if (v % 11 == 3) b->x = -0.0f;
            if (v % 13 == 5) b->y = -1e-7f;
            if (v % 17 == 7) *b = f3(1e-30f, 1e-30f, 1.0f);
            if (v % 19 == 9) *b = f3(lcg_float(st, 0, 1), lcg_float(st, 0, 1), lcg_float(st, 0, 1));
            if (v % 23 == 1) *b = f3(0.0f, -0.0f, 1.0f);
            if (v % 29 == 2) *b = f3(0.0f, 0.0f, 0.0f);     /* no positive weight: vertex 0 */
            if (v % 31 == 4) *b = f3(-0.5f, 0.0f, 1.5f);    /* outside the triangle: corner 2 */
            if (v % 37 == 6) *b = f3(NAN, 0.5f, 0.5f);      /* a NaN weight reads as 0 */
        }
    }
}

/* The inputs of one instance over the grid as a batch with these shared registers gets them (the device's fused
 * path: POSITION0 per vertex): sh with the shared registers in sh[0] only (poisoned elsewhere); full with every
 * register in every vertex, the shared ones sh[0]'s (what `main` is given). */
static void make_inputs(const is_vs_input *inst, const core_grid *g, uint32_t shared, is_vs_input *sh,
                        is_vs_input *full)
{
    for (size_t v = 0; v < g->n_points; v++) {
        full[v] = sh[v] = *inst;
        full[v].position[0] = sh[v].position[0] = f4_of(g->bary[v], 1);
        for (int r = 0; v && r < IS_VS_INPUT_REGS; r++)
            if (shared & (1u << r)) {
                ((float4 *)&full[v])[r] = ((const float4 *)&full[0])[r]; /* what is_vs_input_at gives */
                ((float4 *)&sh[v])[r] = f4(NAN, -1e30f, NAN, 7);
            }
    }
}

/* Do a and b hold the same bytes in oPos and the outputs of live (every byte for ~0u)? */
static bool same_live(const is_vs_output *a, const is_vs_output *b, uint32_t live)
{
    if (live == ~0u) return memcmp(a, b, sizeof *a) == 0;
    if (memcmp(&a->pos, &b->pos, sizeof a->pos) != 0) return false;
    for (int k = 0; k < RS_MAX_ATTR; k++)
        if ((live & (1u << k)) && memcmp(&a->attr[k], &b->attr[k], sizeof a->attr[k]) != 0) return false;
    return true;
}

/* The constants of normal mode `mode % 3`, the smooth shortcut off for mode >= 3; a diffuse colour outside
 * [0, 1] (what grid_batch saturates and batch does not). */
static void constants(int mode, is_vs_constants *c)
{
    float4x4 wvp = {{{1, 0.2f, 0, 0}, {0, 1, 0.1f, 0}, {0.3f, 0, 1, 1}, {0, 0, 3, 4}}};
    float4x4 world = mat_rotation_y(0.5f);
    vs_options o = vs_default_options();
    o.normals = (vs_normals)(mode % 3);
    o.flags = mode >= 3 ? VS_FLAG_NO_SHORTCUT : 0u;
    memset(c, 0, sizeof *c);
    vs_set_constants(c, &wvp, &world, f4(1.75f, 0.7f, -0.6f, 1), &o);
}

/* Buffers of n vertices for one comparison. */
typedef struct bufs {
    is_vs_input *sh, *full;
    is_vs_output *ref, *plain, *grid;
    size_t n;
} bufs;
static void bufs_make(bufs *B, size_t n)
{
    B->n = n;
    B->sh = calloc(n, sizeof *B->sh), B->full = calloc(n, sizeof *B->full);
    B->ref = calloc(n, sizeof *B->ref), B->plain = calloc(n, sizeof *B->plain), B->grid = calloc(n, sizeof *B->grid);
    assert_true(B->sh && B->full && B->ref && B->plain && B->grid);
}
static void bufs_free(bufs *B) { free(B->sh), free(B->full), free(B->ref), free(B->plain), free(B->grid); }

/* The device's saturation of the colour outputs (core's saturate_colors) on o. */
static void saturated(is_vs_output *o) { saturate_color_outputs(&o->attr[RS_ATTR_COLOR0]); }

/* Shade B's inputs with main (complete inputs), batch and grid_batch (workspace ws) of s; batch must give main's
 * bytes, grid_batch main's and batch's with the colours saturated (is_vs_grid_batch_fn), every vertex in oPos and
 * the live outputs (every byte for ~0u: the others may stay unwritten, as is_vs_batch_fn allows).  what names the
 * case. */
static void compare(const is_vertex_shader *s, const is_vs_constants *c, bufs *B, uint32_t live, uint32_t shared,
                    is_vs_grid *ws, const char *what)
{
    size_t n = B->n;
    memset(B->ref, 0, n * sizeof *B->ref), memset(B->plain, 0, n * sizeof *B->plain);
    memset(B->grid, 0, n * sizeof *B->grid);
    for (size_t v = 0; v < n; v++) s->main(c, &B->full[v], &B->ref[v]);
    s->batch(c, B->sh, n, live, shared, B->plain);
    s->grid_batch(c, B->sh, n, live, shared, ws, B->grid);
    for (size_t v = 0; v < n; v++) {
        if (!same_live(&B->ref[v], &B->plain[v], live))
            fail_msg("%s %s: vertex %zu: batch differs from main", s->name, what, v);
        saturated(&B->ref[v]), saturated(&B->plain[v]);
        if (!same_live(&B->ref[v], &B->grid[v], live))
            fail_msg("%s %s: vertex %zu (b = %a %a %a) differs from main", s->name, what, v, B->full[v].position[0].x,
                     B->full[v].position[0].y, B->full[v].position[0].z);
        if (!same_live(&B->plain[v], &B->grid[v], live))
            fail_msg("%s %s: vertex %zu differs from batch", s->name, what, v);
    }
}

/* The grid shaders: the N-Patch and the smoothed patch take a workspace, the others none. */
static void test_grid_shaders(void **state)
{
    (void)state;
    for (int s = 0; vs_shaders[s]; s++) {
        bool grid = vs_shaders[s] == &vs_shader_npatch || vs_shaders[s] == &vs_shader_smooth;
        assert_true((vs_shaders[s]->grid_batch != NULL) == grid);
        assert_true((vs_shaders[s]->grid_room != NULL) == grid);
    }
#ifdef __AVX2__
    assert_true(vs_shader_npatch.grid_room(153) > 0);
#endif
    assert_int_equal(vs_shader_npatch.grid_room((size_t)-1), 0); /* no size overflows */
}

/* Every grid, shader, normal mode and instance family: the plan's bytes are main's and batch's; one workspace per
 * grid and shader, made ready by the first instance and used by the others. */
static void test_grid_batch_same_bytes(void **state)
{
    (void)state;
    uint32_t st = 4242u;
    const is_vertex_shader *shaders[2] = {&vs_shader_npatch, &vs_shader_smooth};
    const uint32_t masks[2] = {((1u << (VS_IN_ID + 1)) - 1u) << IS_VS_REG_TEXCOORD, IS_VS_REGS_INSTANCE};
    for (int kind = 0; kind < GRIDS; kind++) {
        core_grid g;
        make_grid(kind, &g, &st);
        bufs B;
        bufs_make(&B, g.n_points);
        for (int si = 0; si < 2; si++)
            for (int mode = 0; mode < 6; mode++) {
                const is_vertex_shader *s = shaders[si];
                is_vs_constants c;
                constants(mode, &c);
                size_t room = s->grid_room(g.n_points);
                void *mem = malloc(room ? room : 1);
                assert_non_null(mem);
                is_vs_grid ws = {mem, room, false};
                for (int t = 0; t < 10; t++) {
                    is_vs_input inst;
                    random_instance_regs(&st, t, &inst);
                    uint32_t shared = masks[(t + si) % 2];
                    make_inputs(&inst, &g, shared, B.sh, B.full);
                    char what[96];
                    snprintf(what, sizeof what, "grid %d mode %d instance %d", kind, mode, t);
                    compare(s, &c, &B, t % 3 ? IS_OUT_COLOR0 : ~0u, shared, &ws, what);
#ifdef __AVX2__
                    if (mode % 3 == VS_NORMALS_LINEAR) assert_true(ws.ready); /* the plan was used */
#endif
                }
                free(mem);
            }
        bufs_free(&B);
        core_grid_free(&g);
    }
}

/* The workspace's states: ready for a grid of another size (rebuilt), ready with garbage in it (rebuilt), too
 * small or absent (the plain batch: ready stays false), shared by both shaders, and batches that are not the fused
 * path's (nothing shared, POSITION0 shared): always main's bytes. */
static void test_grid_workspace_states(void **state)
{
    (void)state;
    uint32_t st = 99u;
    core_grid g1, g2;
    make_grid(4, &g1, &st);  /* level 7: 36 points */
    make_grid(6, &g2, &st);  /* level 16: 153 points */
    bufs B1, B2;
    bufs_make(&B1, g1.n_points), bufs_make(&B2, g2.n_points);
    is_vs_constants c;
    constants(0, &c);
    const uint32_t shared = IS_VS_REGS_INSTANCE;
    size_t room = vs_shader_npatch.grid_room(g2.n_points);
    unsigned char *mem = malloc(room ? room : 1);
    assert_non_null(mem);
    is_vs_input inst;
    random_instance_regs(&st, 0, &inst);
    make_inputs(&inst, &g1, shared, B1.sh, B1.full);
    make_inputs(&inst, &g2, shared, B2.sh, B2.full);
    is_vs_grid ws = {mem, room, false};
    compare(&vs_shader_npatch, &c, &B2, ~0u, shared, &ws, "level 16");
    compare(&vs_shader_smooth, &c, &B1, ~0u, shared, &ws, "level 7 after level 16, ready");
    compare(&vs_shader_npatch, &c, &B2, ~0u, shared, &ws, "level 16 after level 7, ready");
    memset(mem, 0xab, room ? room : 1);
    ws.ready = true;
    compare(&vs_shader_smooth, &c, &B2, ~0u, shared, &ws, "garbage, ready");
    is_vs_grid small = {mem, room ? room - 1 : 0, false};
    compare(&vs_shader_npatch, &c, &B2, ~0u, shared, &small, "workspace one byte short");
    assert_false(small.ready);
    is_vs_grid none = {NULL, room, false};
    compare(&vs_shader_smooth, &c, &B2, IS_OUT_COLOR0, shared, &none, "no memory");
    assert_false(none.ready);
    compare(&vs_shader_npatch, &c, &B2, ~0u, shared, NULL, "no workspace");
    for (int k = 0; k < 2; k++) { /* not the fused path's batches: the workspace is not used */
        uint32_t m = k ? IS_VS_REGS_ALL : 0u;
        make_inputs(&inst, &g2, m, B2.sh, B2.full);
        ws.ready = false;
        compare(&vs_shader_npatch, &c, &B2, ~0u, m, &ws, k ? "POSITION0 shared" : "nothing shared");
        assert_false(ws.ready);
    }
    free(mem);
    bufs_free(&B1), bufs_free(&B2);
    core_grid_free(&g1), core_grid_free(&g2);
}

/* g's points in reverse order and its triangles' indices renamed to match: the same triangles, other per-vertex
 * registers at every index. */
static void reverse_grid(core_grid *g)
{
    size_t n = g->n_points;
    for (size_t v = 0; v < n / 2; v++) {
        float3 t = g->bary[v];
        g->bary[v] = g->bary[n - 1 - v], g->bary[n - 1 - v] = t;
    }
    for (size_t k = 0; k < 3 * g->n_triangles; k++) g->idx[k] = (uint32_t)(n - 1 - g->idx[k]);
}

/* The image of scene o drawn with grid g on dev (cleared first). */
static void draw_image(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g, uint32_t *rgba)
{
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, o->background, 1.0f), IS_OK);
    assert_int_equal(scene_draw(dev, o, m, g, NULL), 0);
    assert_int_equal(dev_get_render_target_data(dev, rgba, (size_t)o->width * (size_t)o->height), IS_OK);
}

/* The options of the device grid tests: 160x120, level 6, the N-Patch (p 0) or the smoothed patch (p 1) with
 * linear normals (the 8-lane path's: the default, real normals, goes per vertex), on `threads` threads. */
static scene_opts grid_test_opts(int p, int threads)
{
    scene_opts o;
    scene_opts_default(&o);
    o.width = 160, o.height = 120, o.threads = threads, o.level = 6;
    o.patch = p ? VS_PATCH_SMOOTH : VS_PATCH_NPATCH;
    o.normals = VS_NORMALS_LINEAR;
    return o;
}

/* The fused path draws a grid, then the same grid with its points reversed (same vertex count: a plan kept from
 * the first draw would put every vertex's outputs at another index), then the first again, on one device: each
 * image is the reference path's, for the N-Patch and the smoothed patch, on 1 and 2 threads. */
static void test_device_grid_changes(void **state)
{
    (void)state;
    is_mesh m;
    assert_int_equal(cubes_mesh(2, &m), 0);
    for (int p = 0; p < 2; p++)
        for (int threads = 1; threads <= 2; threads++) {
            const scene_opts o = grid_test_opts(p, threads);
            core_grid g[2];
            assert_int_equal(core_grid_make(CORE_GRID_REGULAR, 6.0f, &g[0]), 0);
            assert_int_equal(core_grid_make(CORE_GRID_REGULAR, 6.0f, &g[1]), 0);
            reverse_grid(&g[1]);
            char err[256];
            is_device *fast = dev_create(o.width, o.height, 1, err, sizeof err);
            is_device *ref = dev_create(o.width, o.height, 1, err, sizeof err);
            assert_non_null(fast), assert_non_null(ref);
            dev_set_threads(fast, threads), dev_set_threads(ref, threads);
            dev_set_reference_path(ref, true);
            size_t px = (size_t)o.width * (size_t)o.height;
            uint32_t *a = malloc(px * sizeof *a), *b = malloc(px * sizeof *b);
            assert_true(a && b);
            for (int d = 0; d < 3; d++) {
                draw_image(fast, &o, &m, &g[d % 2], a);
                draw_image(ref, &o, &m, &g[d % 2], b);
                size_t diff = 0;
                for (size_t k = 0; k < px; k++) diff += a[k] != b[k];
                if (diff)
                    fail_msg("patch %d, %d threads, draw %d: %zu pixels differ from the reference path", p, threads,
                             d, diff);
            }
            free(a), free(b);
            dev_destroy(fast), dev_destroy(ref);
            core_grid_free(&g[0]), core_grid_free(&g[1]);
        }
    mesh_free(&m);
}

/* On dev (whose shader and constants scene_draw set), grid g0 bound by tess_bind_instanced and drawn, then the
 * same vertex and index buffers locked and rewritten with grid g1 (the same sizes: the same buffer pointers) and
 * drawn again: the two images into img[0] and img[1]. */
static void draw_rewritten(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g0,
                           const core_grid *g1, uint32_t *img[2])
{
    tess_resources r = {0};
    assert_int_equal(tess_bind_instanced(dev, m, g0, &r), IS_OK);
    const size_t px = (size_t)o->width * (size_t)o->height;
    for (int d = 0; d < 2; d++) {
        if (d == 1) {   /* Lock, new contents, Unlock: stream 0's points and the indices of g1 */
            memcpy(vb_lock(r.vb0), g1->bary, g1->n_points * sizeof(float3));
            vb_unlock(r.vb0);
            uint16_t *ix = ib_lock(r.ib);
            for (size_t k = 0; k < 3 * g1->n_triangles; k++) ix[k] = (uint16_t)g1->idx[k];
            ib_unlock(r.ib);
        }
        assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, o->background, 1.0f), IS_OK);
        assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, r.n_vertices, 0, r.n_prims), IS_OK);
        assert_int_equal(dev_get_render_target_data(dev, img[d], px), IS_OK);
    }
    tess_resources_free(&r);
}

/* The fused path keeps a slot's input registers and grid plan from one draw to the next when their per-vertex
 * values are the same; here the stream-0 buffer is rewritten between two draws (Lock, the points reversed,
 * Unlock: the same buffer, the same size, the same layout), and the second draw must render the new grid: both
 * images are the reference path's, and the first is scene_draw's, for both patches on 1 and 2 threads. */
static void test_device_grid_rewritten(void **state)
{
    (void)state;
    is_mesh m;
    assert_int_equal(cubes_mesh(2, &m), 0);
    for (int p = 0; p < 2; p++)
        for (int threads = 1; threads <= 2; threads++) {
            const scene_opts o = grid_test_opts(p, threads);
            core_grid g[2];
            assert_int_equal(core_grid_make(CORE_GRID_REGULAR, 6.0f, &g[0]), 0);
            assert_int_equal(core_grid_make(CORE_GRID_REGULAR, 6.0f, &g[1]), 0);
            reverse_grid(&g[1]);
            is_device *dev[2];
            const size_t px = (size_t)o.width * (size_t)o.height;
            uint32_t *img[2][2], *first = malloc(px * sizeof *first);
            assert_non_null(first);
            for (int d = 0; d < 2; d++) {   /* 0: the fused path, 1: the reference path */
                dev[d] = dev_create(o.width, o.height, 1, NULL, 0);
                assert_non_null(dev[d]);
                dev_set_threads(dev[d], threads);
                dev_set_reference_path(dev[d], d == 1);
                img[d][0] = malloc(px * sizeof(uint32_t)), img[d][1] = malloc(px * sizeof(uint32_t));
                assert_true(img[d][0] && img[d][1]);
                draw_image(dev[d], &o, &m, &g[0], first);   /* the shader and constants */
                draw_rewritten(dev[d], &o, &m, &g[0], &g[1], img[d]);
                assert_memory_equal(img[d][0], first, px * sizeof *first);
            }
            for (int k = 0; k < 2; k++) {
                size_t diff = 0;
                for (size_t q = 0; q < px; q++) diff += img[0][k][q] != img[1][k][q];
                if (diff)
                    fail_msg("patch %d, %d threads, draw %d: %zu pixels differ from the reference path", p, threads,
                             k, diff);
            }
            for (int d = 0; d < 2; d++) free(img[d][0]), free(img[d][1]), dev_destroy(dev[d]);
            free(first);
            core_grid_free(&g[0]), core_grid_free(&g[1]);
        }
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_shaders),
        cmocka_unit_test(test_grid_batch_same_bytes),
        cmocka_unit_test(test_grid_workspace_states),
        cmocka_unit_test(test_device_grid_changes),
        cmocka_unit_test(test_device_grid_rewritten),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
