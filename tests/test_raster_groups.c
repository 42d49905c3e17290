/* tests/test_raster_groups.c -- grouped pieces (rs_source.group_prims): each instance of a piece is binned to tiles
 * as one entry and its triangles are set up inside the tile pass.  Frames of many small warped grid instances --
 * straddling tile borders, partly off screen, some folded (back-facing triangles), some with collapsed rows
 * (degenerate triangles), a few pieces with a vertex behind the near plane or past the guard band (those pieces take
 * the per-triangle path) -- under random states (cull mode, depth function and writes, blending, scissor, viewport)
 * must give the same bytes and counters grouped, ungrouped, with groups that do not match the instances, and on the
 * reference path, for 1 and 2 threads, with the scene on and off, on every instruction set the CPU has.
 * Deterministic: a fixed seed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../raster/raster.h"
#include "util/raster_util.h"

enum { W = 300, H = 200, DRAWS = 12, PIECES = 4, INST = 6, N = 5 };
enum { VERTS = (N + 1) * (N + 1), PRIMS = 2 * N * N };   /* per instance: an (N+1) x (N+1) grid, 2 N^2 triangles */

/* The frame's data: per draw its states and PIECES pieces of INST grid instances. */
typedef struct frame {
    rs_state st[DRAWS];
    rs_vertex v[DRAWS][PIECES][INST * VERTS];
} frame;
static uint32_t g_idx[INST * PRIMS * 3];   /* instance k's grid over its vertices k * VERTS ... (filled once) */

/* A draw source's context: draw d of frame f. */
typedef struct src_ctx { const frame *f; int d; } src_ctx;

/* rs_produce_fn: piece p of the draw, as it is. */
static size_t produce(void *ctx, size_t piece, int slot, rs_vertex **verts, size_t *n_verts, const uint32_t **idx)
{
    const src_ctx *c = ctx;
    (void)slot;
    *verts = (rs_vertex *)c->f->v[c->d][piece], *n_verts = INST * VERTS, *idx = g_idx;
    return INST * PRIMS;
}

/* The grid's index list: per quad (r, c) the triangles (A, B, C) and (B, D, C), instance after instance. */
static void make_indices(void)
{
    uint32_t *o = g_idx;
    for (uint32_t k = 0; k < INST; k++)
        for (uint32_t r = 0; r < N; r++)
            for (uint32_t c = 0; c < N; c++) {
                uint32_t a = k * VERTS + r * (N + 1) + c, b = a + 1, d = a + N + 1, e = d + 1;
                *o++ = a, *o++ = b, *o++ = d, *o++ = b, *o++ = e, *o++ = d;
            }
}

/* Random states on the fast path: cull, depth function and writes, blending, scissor, viewport offsets. */
static rs_state random_state(uint64_t *s)
{
    rs_state st = {.cull_mode = RS_CULL_NONE + (int)(test_rnd(s) % 3), .fill_mode = RS_FILL_SOLID,
                   .shade_mode = RS_SHADE_GOURAUD, .z_enable = true, .z_write = test_rnd(s) % 4 != 0,
                   .z_func = test_rnd(s) % 3 == 0 ? RS_CMP_LESS : (test_rnd(s) % 2 ? RS_CMP_LESSEQUAL : RS_CMP_GREATER),
                   .src_blend = RS_BLEND_ONE, .dst_blend = RS_BLEND_ZERO, .attr_mask = 1u << RS_ATTR_COLOR0,
                   .viewport = {0, 0, W, H, 0.0f, 1.0f}};
    if (test_rnd(s) % 4 == 0)
        st.blend_enable = true, st.src_blend = RS_BLEND_SRCALPHA, st.dst_blend = RS_BLEND_INVSRCALPHA;
    if (test_rnd(s) % 4 == 0)
        st.viewport = (rs_viewport){(int)(test_rnd(s) % 90), (int)(test_rnd(s) % 60), 190, 130, 0.0f, 1.0f};
    if (test_rnd(s) % 4 == 0) {
        int x0 = (int)(test_rnd(s) % 200), y0 = (int)(test_rnd(s) % 120);
        st.scissor_enable = true, st.scissor = (rs_rect){x0, y0, x0 + 90, y0 + 70};
    }
    return st;
}

/* One grid instance into v[0..VERTS): a warped square of half-size r around a random centre (partly off screen at
 * times), folded (back-facing triangles) or with a collapsed row (degenerate ones) now and then; `far`: one vertex
 * behind the near plane or past the guard band (the piece then needs clipping). */
static void make_instance(uint64_t *s, rs_vertex *v, bool far)
{
    const float w = test_frnd(s, 0.6f, 1.8f), cx = test_frnd(s, -1.2f, 1.2f), cy = test_frnd(s, -1.2f, 1.2f);
    const float r = test_frnd(s, 0.03f, 0.5f), z = test_frnd(s, 0.05f, 0.95f);
    const int fold = test_rnd(s) % 4 == 0 ? (int)(test_rnd(s) % (N + 1)) : -1;
    const int flat = test_rnd(s) % 4 == 0 ? (int)(test_rnd(s) % (N + 1)) : -1;
    for (int i = 0; i <= N; i++)
        for (int k = 0; k <= N; k++) {
            rs_vertex *o = &v[i * (N + 1) + k];
            memset(o, 0, sizeof *o);
            float x = cx + r * (2.0f * (float)k / N - 1.0f) + test_frnd(s, -0.2f, 0.2f) * r / N;
            float y = cy + r * (2.0f * (float)i / N - 1.0f) + test_frnd(s, -0.2f, 0.2f) * r / N;
            if (k == fold) x -= 2.5f * r / N;   /* this column crosses the previous one: triangles turn round */
            o->pos = (rs_vec4){x * w, y * w, (z + test_frnd(s, -0.04f, 0.04f)) * w, w};
            o->attr[RS_ATTR_COLOR0] =
                (rs_vec4){test_frnd(s, 0, 1), test_frnd(s, 0, 1), test_frnd(s, 0, 1), test_frnd(s, 0.3f, 1)};
            if (i == flat && i > 0) o->pos = o[-(N + 1)].pos;   /* the row above again: zero-area triangles */
        }
    if (far) {
        rs_vertex *o = &v[test_rnd(s) % VERTS];
        if (test_rnd(s) % 2) o->pos.z = -0.5f * o->pos.w;        /* behind the near plane */
        else o->pos.x = 400.0f * o->pos.w;                   /* past the guard band */
    }
}

/* A frame: random states, and pieces of instances (one piece in five with a vertex that needs clipping). */
static void make_frame(frame *f, uint64_t seed)
{
    uint64_t s = seed;
    for (int d = 0; d < DRAWS; d++) {
        f->st[d] = random_state(&s);
        for (int p = 0; p < PIECES; p++) {
            const int far = test_rnd(&s) % 5 == 0 ? (int)(test_rnd(&s) % INST) : -1;
            for (int k = 0; k < INST; k++) make_instance(&s, &f->v[d][p][k * VERTS], k == far);
        }
    }
}

/* What a frame drew: the planes and the summed counters. */
typedef struct result {
    uint32_t color[W * H];
    float depth[W * H];
    rs_stats sum;
} result;

/* How a frame is drawn. */
typedef struct how { bool scene, reference; int threads, isa; size_t group; } how;

/* Draw frame f on a fresh context as h says (group: the sources' group_prims). */
static void draw_frame(const frame *f, how h, result *out)
{
    rs_context *rs = rs_create(h.threads);
    rs_target rt;
    assert_non_null(rs);
    assert_int_equal(rs_set_isa(rs, h.isa), RS_OK);
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_stats sink = {0}, s;
    memset(&out->sum, 0, sizeof out->sum);
    rs_set_reference_path(rs, h.reference);
    rs_set_scene(rs, h.scene ? &sink : NULL);
    rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0xff402010u, 1.0f);
    src_ctx ctx[DRAWS];   /* a recorded draw's source context lives until the flush */
    for (int d = 0; d < DRAWS; d++) {
        ctx[d] = (src_ctx){f, d};
        rs_source src = {PIECES, PIECES * INST * PRIMS, INST * VERTS, produce, &ctx[d], h.group, 0};
        assert_int_equal(rs_draw_source(rs, &f->st[d], &rt, &src, &s), RS_OK);
        test_rs_stats_add(&out->sum, &s);
    }
    test_rs_frame_end(rs, &rt, &sink, &out->sum, out->color, out->depth, W * H);
}

/* Compare two results byte for byte (planes and counters). */
static void same(const result *a, const result *b)
{
    test_rs_same_frame(a->color, a->depth, &a->sum, b->color, b->depth, &b->sum, W * H);
}

/* Grouped (by instance, and by runs of 7 or 1000 triangles) against the reference path and the per-triangle path,
 * scene on and off, 1 and 2 threads, every instruction set. */
static void test_groups_same_bytes(void **state)
{
    (void)state;
    make_indices();
    frame *f = malloc(sizeof *f);
    result *ref = malloc(sizeof *ref), *r = malloc(sizeof *r);
    assert_true(f && ref && r);
    static const size_t groups[] = { PRIMS, 7, 1000, 0 };
    for (uint64_t seed = 1; seed <= 4; seed++) {
        make_frame(f, 0x9e3779b97f4a7c15ull * seed);
        draw_frame(f, (how){ false, true, 1, RS_ISA_AVX2, PRIMS }, ref);
        assert_true(ref->sum.samples_written > 0 && ref->sum.prims_culled > 0 && ref->sum.prims_degenerate > 0);
        for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
            if (!rs_isa_supported(isa)) continue;
            for (int threads = 1; threads <= 2; threads++)
                for (size_t g = 0; g < sizeof groups / sizeof *groups; g++) {
                    draw_frame(f, (how){ true, false, threads, isa, groups[g] }, r);
                    same(ref, r);
                    draw_frame(f, (how){ false, false, threads, isa, groups[g] }, r);
                    same(ref, r);
                }
        }
    }
    free(f), free(ref), free(r);
}

/* One big instance: a 40 x 40 grid over pixels ~(22..117, 22..118): four tiles, the most a group may meet (more
 * are set up per triangle), 3,200 triangles of ~2.5 pixels, many on the tile borders x = 64 and y = 64. */
enum { BN = 40, BVERTS = (BN + 1) * (BN + 1), BPRIMS = 2 * BN * BN };
typedef struct big { rs_vertex v[BVERTS]; uint32_t idx[3 * BPRIMS]; } big;

/* rs_produce_fn: the one piece of a big instance. */
static size_t produce_big(void *ctx, size_t piece, int slot, rs_vertex **verts, size_t *n_verts, const uint32_t **idx)
{
    big *b = ctx;
    (void)piece, (void)slot;
    *verts = b->v, *n_verts = BVERTS, *idx = b->idx;
    return BPRIMS;
}

/* One instance over four tiles (its triangles in every tile they meet, one group binned to all four), grouped
 * against the reference path, 1 and 2 threads. */
static void test_group_over_tiles(void **state)
{
    (void)state;
    big *b = malloc(sizeof *b);
    uint32_t *col[3];
    assert_non_null(b);
    uint64_t s = 12345;
    for (int i = 0; i <= BN; i++)
        for (int k = 0; k <= BN; k++) {
            rs_vertex *o = &b->v[i * (BN + 1) + k];
            memset(o, 0, sizeof *o);
            o->pos = (rs_vec4){-0.85f + 0.63f * (float)k / BN + test_frnd(&s, -0.003f, 0.003f),
                               -0.18f + 0.96f * (float)i / BN + test_frnd(&s, -0.003f, 0.003f),
                               test_frnd(&s, 0.1f, 0.9f), 1.0f};
            o->attr[RS_ATTR_COLOR0] = (rs_vec4){ test_frnd(&s, 0, 1), test_frnd(&s, 0, 1), test_frnd(&s, 0, 1), 1.0f };
        }
    uint32_t *o = b->idx;
    for (uint32_t r = 0; r < BN; r++)
        for (uint32_t c = 0; c < BN; c++) {
            uint32_t a = r * (BN + 1) + c, bb = a + 1, d = a + BN + 1, e = d + 1;
            *o++ = a, *o++ = bb, *o++ = d, *o++ = bb, *o++ = e, *o++ = d;
        }
    rs_state st = {.cull_mode = RS_CULL_NONE, .fill_mode = RS_FILL_SOLID, .shade_mode = RS_SHADE_GOURAUD,
                   .z_enable = true, .z_write = true, .z_func = RS_CMP_LESSEQUAL, .src_blend = RS_BLEND_ONE,
                   .dst_blend = RS_BLEND_ZERO, .attr_mask = 1u << RS_ATTR_COLOR0, .viewport = {0, 0, W, H, 0.0f, 1.0f}};
    rs_stats stats[3];
    for (int pass = 0; pass < 3; pass++) {   /* reference, grouped on 1 thread, grouped on 2 */
        rs_context *rs = rs_create(pass == 2 ? 2 : 1);
        rs_set_reference_path(rs, pass == 0);
        rs_target rt;
        assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
        rs_target_clear(&rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0, 1.0f);
        rs_source src = {1, BPRIMS, BVERTS, produce_big, b, BPRIMS, 0};
        assert_int_equal(rs_draw_source(rs, &st, &rt, &src, &stats[pass]), RS_OK);
        col[pass] = malloc(sizeof(uint32_t) * W * H);
        assert_non_null(col[pass]);
        memcpy(col[pass], rt.color, sizeof(uint32_t) * W * H);
        rs_target_free(&rt);
        rs_destroy(rs);
    }
    assert_true(stats[0].samples_written >= 90 * 90);
    for (int pass = 1; pass < 3; pass++) {
        assert_memory_equal(col[0], col[pass], sizeof(uint32_t) * W * H);
        assert_int_equal(stats[0].samples_tested, stats[pass].samples_tested);
        assert_int_equal(stats[0].samples_written, stats[pass].samples_written);
        assert_int_equal(stats[0].prims_drawn, stats[pass].prims_drawn);
    }
    free(col[0]), free(col[1]), free(col[2]), free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_groups_same_bytes),
        cmocka_unit_test(test_group_over_tiles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
