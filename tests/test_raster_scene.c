/* tests/test_raster_scene.c -- the frame's scene (rs_set_scene): rs_draw_source draws into the target of a frame
 * (rs_target_clear_deferred) are recorded, then set up (one region) and rasterized together (one tile pass) at
 * rs_flush / rs_target_flush.  A frame
 * of many small draws, each with its own states (cull mode, depth function and writes, blending, scissor,
 * viewport), with lines drawn by rs_draw in between and a draw on a second target, must give the same bytes and
 * counters as the same frame drawn draw by draw (scene off) and on the reference path, for 1 and 2 threads; the
 * queued draws' samples arrive in the sink only when the queue is flushed; a present (the colour flushed alone)
 * fills the untouched tiles' colour in the draws' tile pass and leaves their depth deferred, and the next frame's
 * clear of the same colour does not fill them again when nothing wrote them.  Deterministic: a fixed seed. */
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

enum { W = 200, H = 150, DRAWS = 40, PIECES = 3, PER_PIECE = 6 };

/* The frame's data: per draw its states and PIECES pieces of PER_PIECE triangles (3 vertices each). */
typedef struct frame {
    rs_state st[DRAWS];
    rs_vertex v[DRAWS][PIECES][3 * PER_PIECE];
    rs_vertex line[DRAWS][2];
} frame;

/* A draw source's context: draw d of frame f. */
typedef struct src_ctx { const frame *f; int d; } src_ctx;
static uint32_t g_idx[3 * PER_PIECE];   /* 0, 1, 2, ... (read only once filled) */

/* rs_produce_fn: piece p of the draw, as it is. */
static size_t produce(void *ctx, size_t piece, int slot, rs_vertex **verts, size_t *n_verts, const uint32_t **idx)
{
    const src_ctx *c = ctx;
    (void)slot;
    *verts = (rs_vertex *)c->f->v[c->d][piece], *n_verts = 3 * PER_PIECE, *idx = g_idx;
    return PER_PIECE;
}

/* Random states: cull, depth function and writes, blending, scissor, viewport offsets (all on the fast path). */
static rs_state random_state(uint64_t *s)
{
    rs_state st = {.cull_mode = RS_CULL_NONE + (int)(test_rnd(s) % 3),
                   .fill_mode = RS_FILL_SOLID,
                   .shade_mode = RS_SHADE_GOURAUD,
                   .z_enable = true,
                   .z_write = test_rnd(s) % 4 != 0,
                   .z_func = test_rnd(s) % 2 ? RS_CMP_LESSEQUAL : RS_CMP_GREATER,
                   .src_blend = RS_BLEND_ONE,
                   .dst_blend = RS_BLEND_ZERO,
                   .attr_mask = 1u << RS_ATTR_COLOR0,
                   .viewport = {0, 0, W, H, 0.0f, 1.0f}};
    if (test_rnd(s) % 4 == 0)
        st.blend_enable = true, st.src_blend = RS_BLEND_SRCALPHA, st.dst_blend = RS_BLEND_INVSRCALPHA;
    if (test_rnd(s) % 4 == 0)
        st.viewport = (rs_viewport){(int)(test_rnd(s) % 60), (int)(test_rnd(s) % 40), 120, 100, 0.0f, 1.0f};
    if (test_rnd(s) % 4 == 0) {
        int x0 = (int)(test_rnd(s) % 150), y0 = (int)(test_rnd(s) % 100);
        st.scissor_enable = true, st.scissor = (rs_rect){x0, y0, x0 + 50, y0 + 50};
    }
    return st;
}

/* A random vertex in clip space (some w != 1), with a random colour. */
static rs_vertex random_vertex(uint64_t *s)
{
    rs_vertex v;
    memset(&v, 0, sizeof v);
    float w = test_frnd(s, 0.5f, 2.0f);
    v.pos = (rs_vec4){test_frnd(s, -1.1f, 1.1f) * w, test_frnd(s, -1.1f, 1.1f) * w, test_frnd(s, 0.0f, 1.0f) * w, w};
    v.attr[RS_ATTR_COLOR0] = (rs_vec4){test_frnd(s, 0, 1), test_frnd(s, 0, 1), test_frnd(s, 0, 1), test_frnd(s, 0, 1)};
    return v;
}

/* Small triangles around random centres (a tile or a few each), and a line per draw. */
static void make_frame(frame *f, uint64_t seed)
{
    uint64_t s = seed;
    for (int k = 0; k < 3 * PER_PIECE; k++) g_idx[k] = (uint32_t)k;
    for (int d = 0; d < DRAWS; d++) {
        f->st[d] = random_state(&s);
        for (int p = 0; p < PIECES; p++)
            for (int t = 0; t < PER_PIECE; t++) {
                rs_vertex c = random_vertex(&s);
                float r = test_frnd(&s, 0.02f, 0.4f) * c.pos.w;
                for (int k = 0; k < 3; k++) {
                    rs_vertex v = c;
                    v.pos.x += test_frnd(&s, -r, r), v.pos.y += test_frnd(&s, -r, r);
                    v.attr[RS_ATTR_COLOR0].x = test_frnd(&s, 0, 1);
                    f->v[d][p][3 * t + k] = v;
                }
            }
        f->line[d][0] = random_vertex(&s), f->line[d][1] = random_vertex(&s);
    }
}

/* What a frame drew: the planes of both targets and the summed counters. */
typedef struct result {
    uint32_t color[W * H], color2[W * H];
    float depth[W * H];
    rs_stats sum;
} result;

/* Draw frame f on a fresh context: scene on or off, reference path or not, `threads` threads; every 7th draw is
 * followed by a line (rs_draw: the queue first), draw 20 also goes to a second target (the queue flushed). */
static void draw_frame(const frame *f, bool scene, bool reference, int threads, result *out)
{
    rs_context *rs = rs_create(threads);
    rs_target rt, rt2;
    assert_non_null(rs);
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    assert_int_equal(rs_target_init(&rt2, W, H, 1), RS_OK);
    rs_stats sink = {0}, s;
    memset(&out->sum, 0, sizeof out->sum);
    rs_set_reference_path(rs, reference);
    rs_set_scene(rs, scene ? &sink : NULL);
    rs_target_clear(&rt2, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0x11223344u, 1.0f);
    rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0xff402010u, 1.0f);
    src_ctx ctx[DRAWS];   /* a recorded draw's source context lives until the flush */
    for (int d = 0; d < DRAWS; d++) {
        ctx[d] = (src_ctx){f, d};
        rs_source src = {PIECES, PIECES * PER_PIECE, 3 * PER_PIECE, produce, &ctx[d], 0, 0};
        rs_state st = f->st[d];   /* changed below after the draw: the queued draw keeps its own copy */
        assert_int_equal(rs_draw_source(rs, &st, &rt, &src, &s), RS_OK);
        test_rs_stats_add(&out->sum, &s);
        st.cull_mode = RS_CULL_NONE, st.z_func = RS_CMP_ALWAYS, st.viewport.x = 3;
        if (d % 7 == 6) {
            assert_int_equal(rs_draw(rs, &f->st[d], &rt, RS_PRIM_LINES, f->line[d], 2, NULL, 1, &s), RS_OK);
            test_rs_stats_add(&out->sum, &s);
        }
        if (d == 20) {
            assert_int_equal(rs_draw_source(rs, &f->st[d], &rt2, &src, &s), RS_OK);
            test_rs_stats_add(&out->sum, &s);
        }
    }
    if (scene) {   /* the draws after the last line not rasterized yet: their samples come with the flush */
        const uint64_t before = sink.samples_tested;
        rs_flush(rs);
        assert_true(sink.samples_tested > before);
        rs_flush(rs);   /* twice: nothing more */
    }
    test_rs_stats_add(&out->sum, &sink);
    rs_target_flush(rs, &rt);
    memcpy(out->color, rt.color, sizeof out->color);
    memcpy(out->depth, rt.depth, sizeof out->depth);
    memcpy(out->color2, rt2.color, sizeof out->color2);
    rs_target_free(&rt);
    rs_target_free(&rt2);
    rs_destroy(rs);
}

/* Compare two results byte for byte (planes and counters). */
static void same(const result *a, const result *b)
{
    assert_memory_equal(a->color, b->color, sizeof a->color);
    assert_memory_equal(a->depth, b->depth, sizeof a->depth);
    assert_memory_equal(a->color2, b->color2, sizeof a->color2);
    assert_memory_equal(&a->sum, &b->sum, sizeof a->sum);
}

/* The scene against draw by draw and the reference path, 1 and 2 threads, a few frames. */
static void test_scene_same_bytes(void **state)
{
    (void)state;
    frame *f = malloc(sizeof *f);
    result *ref = malloc(sizeof *ref), *r = malloc(sizeof *r);
    assert_true(f && ref && r);
    for (uint64_t seed = 1; seed <= 4; seed++) {
        make_frame(f, 0x9e3779b97f4a7c15ull * seed);
        draw_frame(f, false, true, 1, ref);
        assert_true(ref->sum.samples_written > 0);
        for (int threads = 1; threads <= 2; threads++) {
            draw_frame(f, false, false, threads, r);
            same(ref, r);
            draw_frame(f, true, false, threads, r);
            same(ref, r);
        }
    }
    free(f), free(ref), free(r);
}

/* Without a deferred clear (no frame) or with the scene off a draw is rasterized at once; with it, only at the
 * flush (the target untouched before). */
static void test_scene_defers(void **state)
{
    (void)state;
    frame *f = malloc(sizeof *f);
    assert_non_null(f);
    make_frame(f, 77);
    rs_context *rs = rs_create(2);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_stats sink = {0}, s;
    rs_set_scene(rs, &sink);
    src_ctx c = {f, 0};
    rs_source src = {PIECES, PIECES * PER_PIECE, 3 * PER_PIECE, produce, &c, 0, 0};
    rs_state st = f->st[0];
    st.cull_mode = RS_CULL_NONE, st.z_func = RS_CMP_LESSEQUAL, st.blend_enable = false, st.scissor_enable = false,
    st.viewport = (rs_viewport){0, 0, W, H, 0.0f, 1.0f};
    rs_target_clear(&rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0, 1.0f);
    assert_int_equal(rs_draw_source(rs, &st, &rt, &src, &s), RS_OK);   /* no frame: drawn now */
    assert_true(s.samples_written > 0);
    rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0, 1.0f);
    assert_int_equal(rs_draw_source(rs, &st, &rt, &src, &s), RS_OK);   /* recorded: its counters at the flush */
    assert_int_equal(s.samples_written, 0u);
    assert_int_equal(s.prims_drawn, 0u);
    assert_int_equal(sink.samples_written, 0u);
    assert_int_equal(sink.prims_drawn, 0u);
    rs_target_flush(rs, &rt);
    assert_true(sink.samples_written > 0);
    assert_true(sink.prims_drawn > 0);
    rs_set_scene(rs, NULL);   /* off: drawn now again */
    assert_int_equal(rs_draw_source(rs, &st, &rt, &src, &s), RS_OK);
    assert_true(s.samples_tested > 0);
    rs_target_free(&rt);
    rs_destroy(rs);
    free(f);
}

/* A frame's clear reaches every pixel no draw touched at rs_target_flush, on targets whose planes take the
 * streaming stores (1024 and 2048 wide, 4 MB and more) and on ones that do not (odd widths): one small triangle,
 * then every other pixel holds the clear colour and depth, and the clear value is not the one before. */
static void test_flush_fills_untouched_tiles(void **state)
{
    (void)state;
    const int sizes[][2] = {{1024, 1024}, {2048, 1040}, {1000, 999}, {1536, 700}};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        const int w = sizes[k][0], h = sizes[k][1];
        rs_target rt;
        assert_int_equal(rs_target_init(&rt, w, h, 1), RS_OK);
        rs_target_clear(&rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0x01020304u, 0.25f);
        rs_context *rs = rs_create(2);
        rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0xff402010u, 1.0f);
        rs_state st = test_rs_defaults(w, h);
        st.cull_mode = RS_CULL_NONE;
        rs_vertex v[3];
        memset(v, 0, sizeof v);
        v[0].pos = (rs_vec4){-1.0f, 1.0f, 0.5f, 1.0f}, v[1].pos = (rs_vec4){-0.98f, 1.0f, 0.5f, 1.0f};
        v[2].pos = (rs_vec4){-1.0f, 0.98f, 0.5f, 1.0f};
        assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_OK);
        rs_target_flush(rs, &rt);
        size_t cleared = 0;
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                size_t p = (size_t)y * (size_t)w + (size_t)x;
                if (x < RS_TILE_SIZE && y < RS_TILE_SIZE) continue;   /* the triangle's tile */
                if (rt.color[p] != 0xff402010u || rt.depth[p] != 1.0f)
                    fail_msg("%dx%d: pixel (%d, %d) holds %08x, depth %g", w, h, x, y, rt.color[p], rt.depth[p]);
                cleared++;
            }
        assert_int_equal(cleared, (size_t)w * (size_t)h - RS_TILE_SIZE * RS_TILE_SIZE);
        rs_destroy(rs);
        rs_target_free(&rt);
    }
}

/* The tiles the frames' draws can touch (viewports inside W x H): x < DRAWN_X, y < DRAWN_Y. */
enum { DRAWN_X = (W + RS_TILE_SIZE - 1) / RS_TILE_SIZE * RS_TILE_SIZE,
       DRAWN_Y = (H + RS_TILE_SIZE - 1) / RS_TILE_SIZE * RS_TILE_SIZE };
_Static_assert(DRAWN_X < 448 && DRAWN_Y < 320, "draw_present's target has tiles no draw touches");

/* Frame f's draws (no lines, no second target) into a fresh 448x320 target whose planes held colour `old` and
 * depth 0.25 before the frame's clear, on `threads` threads, scene on or off; present: the colour flushed alone
 * first (rs_target_flush_planes: with the scene on, the tiles no draw touched are filled in the draws' tile pass),
 * and then the tiles outside the draws' viewports (x >= DRAWN_X or y >= DRAWN_Y) must hold the clear colour and
 * the old depth.  The planes after rs_target_flush into color / depth (448 x 320 each). */
static void draw_present(const frame *f, bool scene, unsigned clear, unsigned present, int threads, uint32_t *color,
                         float *depth)
{
    enum { PW = 448, PH = 320 };
    const uint32_t old = 0x01020304u, bg = 0xff402010u;
    rs_context *rs = rs_create(threads);
    rs_target rt;
    assert_non_null(rs);
    assert_int_equal(rs_target_init(&rt, PW, PH, 1), RS_OK);
    rs_target_clear(&rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, old, 0.25f);
    rs_stats sink = {0}, s;
    rs_set_scene(rs, scene ? &sink : NULL);
    rs_target_clear_deferred(rs, &rt, clear, bg, 1.0f);
    src_ctx ctx[DRAWS];
    for (int d = 0; d < DRAWS; d++) {
        ctx[d] = (src_ctx){f, d};
        rs_source src = {PIECES, PIECES * PER_PIECE, 3 * PER_PIECE, produce, &ctx[d], 0, 0};
        assert_int_equal(rs_draw_source(rs, &f->st[d], &rt, &src, &s), RS_OK);
    }
    if (present) {
        rs_target_flush_planes(rs, &rt, present);
        if (scene) assert_true(sink.samples_written > 0);   /* the queue ran */
        for (int y = 0; y < PH && clear == (RS_CLEAR_COLOR | RS_CLEAR_DEPTH); y += 3)
            for (int x = 0; x < PW; x += 5) {
                const size_t p = (size_t)y * PW + (size_t)x;
                if (x < DRAWN_X && y < DRAWN_Y) continue;
                if (rt.color[p] != bg || rt.depth[p] != 0.25f)
                    fail_msg("pixel (%d, %d) after the present: %08x, depth %g", x, y, rt.color[p], rt.depth[p]);
            }
    }
    rs_target_flush(rs, &rt);
    memcpy(color, rt.color, PW * PH * sizeof *color);
    memcpy(depth, rt.depth, PW * PH * sizeof *depth);
    rs_target_free(&rt);
    rs_destroy(rs);
}

enum { PRESENT_PIXELS = 448 * 320 };   /* draw_present's target */

/* A frame (make_frame's, a fixed seed) and two colour and depth buffers of draw_present's target. */
typedef struct present_run {
    frame f;
    uint32_t c[2][PRESENT_PIXELS];
    float d[2][PRESENT_PIXELS];
} present_run;

/* A present_run, its frame made; free() releases it. */
static present_run *present_run_new(void)
{
    present_run *r = malloc(sizeof *r);
    assert_non_null(r);
    make_frame(&r->f, 0x51ed270b27u);
    return r;
}

/* The present (the colour alone) after a scene: the tiles no draw touched get the clear colour in the draws' tile
 * pass and keep their depth's clear deferred; the bytes after the full flush are those of the frame drawn draw by
 * draw and flushed whole, 1 and 2 threads. */
static void test_present_fused(void **state)
{
    (void)state;
    present_run *r = present_run_new();
    draw_present(&r->f, false, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0, 1, r->c[0], r->d[0]);
    for (int threads = 1; threads <= 2; threads++)
        for (int scene = 0; scene < 2; scene++) {
            draw_present(&r->f, scene, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, RS_CLEAR_COLOR, threads, r->c[1], r->d[1]);
            assert_memory_equal(r->c[0], r->c[1], sizeof r->c[0]);
            assert_memory_equal(r->d[0], r->d[1], sizeof r->d[0]);
        }
    free(r);
}

/* A present that discards the depth (RS_DISCARD_DEPTH, D3DPRESENTFLAG_DISCARD_DEPTHSTENCIL): the colour of the
 * frame drawn and flushed whole, and the depth the frame's deferred clear -- drawn in tile buffers (the scene's
 * draws) or in the target (draw by draw) --, 1 and 2 threads; a frame whose clear kept the depth keeps its drawn
 * depth. */
static void test_present_discard(void **state)
{
    (void)state;
    present_run *r = present_run_new();
    const unsigned both = RS_CLEAR_COLOR | RS_CLEAR_DEPTH, discard = RS_CLEAR_COLOR | RS_DISCARD_DEPTH;
    draw_present(&r->f, false, both, 0, 1, r->c[0], r->d[0]);
    size_t drawn = 0;
    for (size_t p = 0; p < PRESENT_PIXELS; p++) drawn += r->d[0][p] != 1.0f;
    assert_true(drawn > 1000);   /* the frame draws depth (which the discard must drop) */
    for (int threads = 1; threads <= 2; threads++)
        for (int scene = 0; scene < 2; scene++) {
            draw_present(&r->f, scene, both, discard, threads, r->c[1], r->d[1]);
            assert_memory_equal(r->c[0], r->c[1], sizeof r->c[0]);
            for (size_t p = 0; p < PRESENT_PIXELS; p++)
                if (r->d[1][p] != 1.0f)
                    fail_msg("threads %d, scene %d: depth %g at %zu, not the clear's", threads, scene, r->d[1][p], p);
        }
    draw_present(&r->f, false, RS_CLEAR_COLOR, 0, 1, r->c[0], r->d[0]);   /* the depth not cleared: kept as drawn */
    for (int scene = 0; scene < 2; scene++) {
        draw_present(&r->f, scene, RS_CLEAR_COLOR, discard, 2, r->c[1], r->d[1]);
        assert_memory_equal(r->c[0], r->c[1], sizeof r->c[0]);
        assert_memory_equal(r->d[0], r->d[1], sizeof r->d[0]);
    }
    free(r);
}

/* Draws [d0, d1) of frame f into rt on rs after a deferred clear of colour bg (colour and depth), then the colour
 * flushed with `flush` (rs_target_flush_planes' planes): the frame's colour into color (448 x 320). */
static void frame_into(rs_context *rs, rs_target *rt, const frame *f, int d0, int d1, uint32_t bg, unsigned flush,
                       uint32_t *color)
{
    rs_stats s;
    src_ctx ctx[DRAWS];
    rs_target_clear_deferred(rs, rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, bg, 1.0f);
    for (int d = d0; d < d1; d++) {
        ctx[d] = (src_ctx){f, d};
        rs_source src = {PIECES, PIECES * PER_PIECE, 3 * PER_PIECE, produce, &ctx[d], 0, 0};
        assert_int_equal(rs_draw_source(rs, &f->st[d], rt, &src, &s), RS_OK);
    }
    rs_target_flush_planes(rs, rt, flush);
    memcpy(color, rt->color, PRESENT_PIXELS * sizeof *color);
}

/* Presents remember the tiles they filled with the clear colour and the next frame's clear of that colour does not
 * fill them again (RS_PRESENT): a sequence of frames on one target -- fewer draws than the frame before (tiles
 * drawn, then untouched: filled again), the same again (tiles skipped), tiles filled, then drawn, then untouched
 * (filled again), another clear colour, a flush without RS_PRESENT after which the caller writes the planes, a
 * discarding present -- gives, after each present, the colour of the same frame drawn on a fresh target; 1 and 2
 * threads, scene on and off, and on the reference path, which draws in the target after the tile's fill (a frame of
 * one draw, whose tiles are drawn once each, then one of none).  (The draws touch only the tiles at x < DRAWN_X,
 * y < DRAWN_Y.) */
static void test_present_clean_tiles(void **state)
{
    (void)state;
    enum { PW = 448, PH = 320 };
    present_run *r = present_run_new();
    const uint32_t a = 0xff402010u, b = 0xff102040u;
    const unsigned pr = RS_CLEAR_COLOR | RS_PRESENT;
    /* per frame: draws [0, n), clear colour, present planes, and whether the caller writes the plane before it */
    const struct { int n; uint32_t bg; unsigned flush; bool scribble; } seq[] = {
        {DRAWS, a, pr, false}, {8, a, pr, false}, {8, a, pr, false}, {3, a, pr | RS_DISCARD_DEPTH, false},
        {DRAWS, a, pr, false}, {3, a, pr, false}, {1, a, pr, false}, {0, a, pr, false}, {3, b, pr, false},
        {3, b, pr, false}, {3, b, pr, true},
        {3, b, RS_CLEAR_COLOR, false}, {8, b, pr, false},
    };
    for (int threads = 1; threads <= 2; threads++)
        for (int scene = 0; scene < 3; scene++) {   /* scene off, on, and the reference path (drawn in the target) */
            rs_context *rs = rs_create(threads);
            rs_stats sink = {0};
            rs_target rt;
            assert_non_null(rs);
            assert_int_equal(rs_target_init(&rt, PW, PH, 1), RS_OK);
            rs_set_scene(rs, scene == 1 ? &sink : NULL);
            rs_set_reference_path(rs, scene == 2);
            for (size_t k = 0; k < sizeof seq / sizeof seq[0]; k++) {
                if (seq[k].scribble) {   /* the planes written by their owner after a flush that is not a present */
                    rs_target_flush(rs, &rt);
                    for (size_t p = 0; p < PRESENT_PIXELS; p++) rt.color[p] = (uint32_t)p * 2654435761u;
                }
                frame_into(rs, &rt, &r->f, 0, seq[k].n, seq[k].bg, seq[k].flush, r->c[1]);
                rs_context *fresh = rs_create(threads);
                rs_target ft;
                assert_non_null(fresh);
                assert_int_equal(rs_target_init(&ft, PW, PH, 1), RS_OK);
                frame_into(fresh, &ft, &r->f, 0, seq[k].n, seq[k].bg, RS_CLEAR_COLOR, r->c[0]);
                for (size_t p = 0; p < PRESENT_PIXELS; p++)
                    if (r->c[0][p] != r->c[1][p])
                        fail_msg("threads %d, scene %d, frame %zu: pixel (%zu, %zu) %08x, a fresh target's %08x",
                                 threads, scene, k, p % PW, p / PW, r->c[1][p], r->c[0][p]);
                rs_target_free(&ft);
                rs_destroy(fresh);
            }
            rs_target_free(&rt);
            rs_destroy(rs);
        }
    free(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scene_same_bytes),
        cmocka_unit_test(test_scene_defers),
        cmocka_unit_test(test_flush_fills_untouched_tiles),
        cmocka_unit_test(test_present_fused),
        cmocka_unit_test(test_present_discard),
        cmocka_unit_test(test_present_clean_tiles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
