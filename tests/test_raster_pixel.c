/* tests/test_raster_pixel.c -- the rasterizer's D3D9 per-pixel and clipping states beyond depth and blending
 * (raster/pixel.c, clip.c, draw.c): the scissor rectangle, the colour write mask, the alpha test, the stencil
 * test and its operations (one- and two-sided), user clip planes, CLIPPING FALSE and pre-transformed vertices.
 * Every expected pixel is computed by hand from D3D9's rules; every draw is made on the reference path and the
 * fast path, on 1 and 2 threads and on each instruction set the CPU runs, and all of them must give the same
 * bytes (colour, depth and stencil). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../raster/raster.h"
#include "util/raster_util.h"

#define W 8
#define H 8
#define CLEAR_RGBA 0x11223344u

/* A vertex at screen (X, Y) of the full W x H viewport, depth z (w = 1), colour c. */
static rs_vertex sv(double X, double Y, float z, rs_vec4 c)
{
    rs_vertex v;
    memset(&v, 0, sizeof v);
    v.pos = (rs_vec4){ (float)(X / (W * 0.5) - 1.0), (float)(1.0 - Y / (H * 0.5)), z, 1.0f };
    v.attr[RS_ATTR_COLOR0] = c;
    return v;
}

static const rs_vec4 WHITE = { 1, 1, 1, 1 };

/* Two clockwise triangles covering the screen rectangle [x0, x1] x [y0, y1] at depth z in colour c. */
static void quad(rs_vertex *v, double x0, double y0, double x1, double y1, float z, rs_vec4 c)
{
    v[0] = sv(x0, y0, z, c), v[1] = sv(x1, y0, z, c), v[2] = sv(x0, y1, z, c);
    v[3] = sv(x1, y0, z, c), v[4] = sv(x1, y1, z, c), v[5] = sv(x0, y1, z, c);
}

/* A target of W x H x samples in a known state: colour CLEAR_RGBA, depth 1, stencil `sten`. */
static void fresh(rs_target *rt, int samples, uint32_t sten)
{
    assert_int_equal(rs_target_init(rt, W, H, samples), RS_OK);
    assert_non_null(rt->stencil);
    rs_target_clear(rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, CLEAR_RGBA, 1.0f);
    rs_target_clear_stencil(rt, 0, 0, W, H, sten);
}

/* Copy of a target's planes (to compare paths). */
typedef struct planes {
    uint32_t color[W * H * 4];
    float depth[W * H * 4];
    uint8_t stencil[W * H * 4];
} planes;

static void save(const rs_target *rt, planes *p)
{
    size_t n = (size_t)W * H * (size_t)rt->samples;
    memcpy(p->color, rt->color, n * 4), memcpy(p->depth, rt->depth, n * 4), memcpy(p->stencil, rt->stencil, n);
}

/* Draw the draws d[0..nd) (each a state and triangles) onto rt in every path, thread count and instruction set
 * the CPU runs, starting each time from rt's contents; rt ends with the reference path's result and every other
 * run must equal it byte for byte. */
typedef struct draw { rs_state st; const rs_vertex *v; size_t n_tris; } draw;
static void draw_all_paths(rs_target *rt, const draw *d, int nd)
{
    planes *start = malloc(sizeof *start), *ref = malloc(sizeof *ref), *got = malloc(sizeof *got);
    assert_true(start && ref && got);
    save(rt, start);
    size_t n = (size_t)W * H * (size_t)rt->samples;
    bool have_ref = false;
    for (int path = 0; path < 2; path++)
        for (int threads = 1; threads <= 2; threads++)
            for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
                if (!rs_isa_supported(isa)) continue;
                memcpy(rt->color, start->color, n * 4), memcpy(rt->depth, start->depth, n * 4);
                memcpy(rt->stencil, start->stencil, n);
                rs_context *rs = rs_create(threads);
                assert_non_null(rs);
                rs_set_reference_path(rs, path == 0);
                assert_int_equal(rs_set_isa(rs, isa), RS_OK);
                for (int k = 0; k < nd; k++)
                    assert_int_equal(rs_draw(rs, &d[k].st, rt, RS_PRIM_TRIANGLES, d[k].v, 3 * d[k].n_tris, NULL,
                                             d[k].n_tris, NULL), RS_OK);
                rs_destroy(rs);
                save(rt, got);
                if (!have_ref) {
                    *ref = *got, have_ref = true;
                    continue;
                }
                if (memcmp(got->color, ref->color, n * 4) || memcmp(got->depth, ref->depth, n * 4) ||
                    memcmp(got->stencil, ref->stencil, n))
                    fail_msg("path %d, %d threads, isa %d: bytes differ from the reference path", path, threads, isa);
            }
    memcpy(rt->color, ref->color, n * 4), memcpy(rt->depth, ref->depth, n * 4), memcpy(rt->stencil, ref->stencil, n);
    free(start), free(ref), free(got);
}

/* Colour (packed RGBA8) of pixel (x, y), sample s. */
static uint32_t px(const rs_target *rt, int x, int y, int s) { return rt->color[((size_t)y * W + x) * rt->samples + s]; }
static uint8_t sten(const rs_target *rt, int x, int y) { return rt->stencil[((size_t)y * W + x) * rt->samples]; }

/* The scissor: only pixels inside both the viewport and the rectangle are drawn; an empty rectangle draws
 * nothing; with the test off the rectangle is ignored. */
static void test_scissor(void **state)
{
    (void)state;
    rs_vertex v[6];
    quad(v, -1, -1, W + 1, H + 1, 0.5f, WHITE);
    struct { bool on; rs_rect r; rs_viewport vp; int x0, y0, x1, y1; } cases[] = {
        { true, { 2, 3, 6, 5 }, { 0, 0, W, H, 0, 1 }, 2, 3, 6, 5 },
        { true, { -5, -5, 3, 100 }, { 0, 0, W, H, 0, 1 }, 0, 0, 3, H },     /* clipped to the target */
        { true, { 2, 2, 7, 7 }, { 4, 0, 4, 4, 0, 1 }, 4, 2, 7, 4 },         /* and to the viewport */
        { true, { 6, 6, 2, 2 }, { 0, 0, W, H, 0, 1 }, 0, 0, 0, 0 },         /* inverted: empty */
        { true, { 0, 0, 4, 4 }, { 5, 5, 3, 3, 0, 1 }, 0, 0, 0, 0 },         /* outside the viewport */
        { false, { 2, 3, 6, 5 }, { 0, 0, W, H, 0, 1 }, 0, 0, W, H },        /* test off */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        rs_target rt;
        fresh(&rt, 1, 0);
        draw d = { test_rs_defaults(W, H), v, 2 };
        d.st.viewport = cases[c].vp;
        d.st.scissor_enable = cases[c].on;
        d.st.scissor = cases[c].r;
        draw_all_paths(&rt, &d, 1);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                bool in = x >= cases[c].x0 && x < cases[c].x1 && y >= cases[c].y0 && y < cases[c].y1;
                if (px(&rt, x, y, 0) != (in ? 0xffffffffu : CLEAR_RGBA))
                    fail_msg("case %zu: pixel (%d, %d) is %08x", c, x, y, px(&rt, x, y, 0));
            }
        rs_target_free(&rt);
    }
}

/* COLORWRITEENABLE: disabled channels keep the target's bytes, with and without blending, on 1 and 4 samples. */
static void test_color_write_mask(void **state)
{
    (void)state;
    rs_vertex v[6];
    quad(v, -1, -1, W + 1, H + 1, 0.5f, (rs_vec4){ 1.0f, 0.0f, 1.0f, 1.0f });   /* RGBA8 ff 00 ff ff */
    for (int samples = 1; samples <= 4; samples += 3)
        for (int blend = 0; blend < 2; blend++) {
            rs_target rt;
            fresh(&rt, samples, 0);
            draw d = { test_rs_defaults(W, H), v, 2 };
            d.st.color_write_disable = 1u | 4u;   /* COLORWRITEENABLE = GREEN | ALPHA */
            d.st.blend_enable = blend;
            d.st.dst_blend = RS_BLEND_ONE;        /* ONE, ONE: adds, saturating */
            draw_all_paths(&rt, &d, 1);
            /* clear: R 0x44, G 0x33, B 0x22, A 0x11; source R ff, G 00, B ff, A ff */
            uint32_t g = blend ? 0x33u : 0x00u, a = 0xffu;
            uint32_t want = 0x44u | g << 8 | 0x22u << 16 | a << 24;
            for (int s = 0; s < samples; s++) assert_int_equal(px(&rt, 3, 3, s), want);
            rs_target_free(&rt);
        }
}

/* A job with pixel.c's states on a 4-sample target covers samples as the plain walk: a quad whose right edge is
 * X = 4 covers samples 0 and 2 of pixel 4 (x offsets -2/16 and -6/16 px) and not 1 and 3 (+6/16, +2/16). */
static void test_ext_sample_coverage(void **state)
{
    (void)state;
    rs_vertex v[6];
    quad(v, -1, -1, 4, H + 1, 0.5f, WHITE);
    for (int ext = 0; ext < 2; ext++) {
        rs_target rt;
        fresh(&rt, 4, 0);
        draw d = { test_rs_defaults(W, H), v, 2 };
        d.st.color_write_disable = ext ? 8u : 0u;   /* alpha not written */
        draw_all_paths(&rt, &d, 1);
        uint32_t lit = ext ? 0x11ffffffu : 0xffffffffu;
        for (int s = 0; s < 4; s++) {
            assert_int_equal(px(&rt, 3, 3, s), lit);
            assert_int_equal(px(&rt, 4, 3, s), s == 0 || s == 2 ? lit : CLEAR_RGBA);
            assert_int_equal(px(&rt, 5, 3, s), CLEAR_RGBA);
        }
        rs_target_free(&rt);
    }
}

/* The alpha test on the 8-bit alpha: 0.5 is stored as 128 (round to nearest); against ALPHAREF 128 each function
 * passes or fails as D3D9's "alpha func ref"; a failing pixel writes neither colour nor depth nor stencil. */
static void test_alpha_test(void **state)
{
    (void)state;
    rs_vertex v[6];
    quad(v, -1, -1, W + 1, H + 1, 0.25f, (rs_vec4){ 0.0f, 1.0f, 0.0f, 0.5f });
    const bool pass[8] = { false, false, true, true, false, false, true, true }; /* NEVER..ALWAYS, 128 vs 128 */
    for (int f = RS_CMP_NEVER; f <= RS_CMP_ALWAYS; f++) {
        rs_target rt;
        fresh(&rt, 1, 7);
        draw d = { test_rs_defaults(W, H), v, 2 };
        d.st.alpha_test = true, d.st.alpha_func = f, d.st.alpha_ref = 0x180;   /* low 8 bits: 128 */
        d.st.stencil_enable = true;
        d.st.stencil_cw = (rs_stencil_ops){ RS_CMP_ALWAYS, RS_STENCILOP_ZERO, RS_STENCILOP_ZERO, RS_STENCILOP_ZERO };
        d.st.stencil_mask = d.st.stencil_write_mask = 0xff;
        draw_all_paths(&rt, &d, 1);
        bool p = pass[f - 1];
        assert_int_equal(px(&rt, 4, 4, 0), p ? 0x8000ff00u : CLEAR_RGBA);
        assert_true(rt.depth[4 * W + 4] == (p ? 0.25f : 1.0f));
        assert_int_equal(sten(&rt, 4, 4), p ? 0 : 7);
        rs_target_free(&rt);
    }
    /* 128 is GREATER than 127 */
    rs_target rt;
    fresh(&rt, 1, 0);
    draw d = { test_rs_defaults(W, H), v, 2 };
    d.st.alpha_test = true, d.st.alpha_func = RS_CMP_GREATER, d.st.alpha_ref = 127;
    draw_all_paths(&rt, &d, 1);
    assert_int_equal(px(&rt, 1, 1, 0), 0x8000ff00u);
    rs_target_free(&rt);
}

/* Stencil value after one draw of a full quad whose stencil test passes (or not) and whose depth test passes (or
 * not) with operation op on stored value s0, reference ref and write mask wm. */
static uint8_t stencil_after(int op, uint8_t s0, uint32_t ref, uint32_t wm, bool stencil_pass, bool depth_pass)
{
    rs_vertex v[6];
    quad(v, -1, -1, W + 1, H + 1, depth_pass ? 0.25f : 0.75f, WHITE);
    rs_target rt;
    fresh(&rt, 1, s0);
    rs_target_clear(&rt, RS_CLEAR_DEPTH, 0, 0.5f);
    draw d = { test_rs_defaults(W, H), v, 2 };
    d.st.stencil_enable = true;
    d.st.stencil_ref = ref, d.st.stencil_mask = 0xff, d.st.stencil_write_mask = wm;
    int keep = RS_STENCILOP_KEEP;
    d.st.stencil_cw = (rs_stencil_ops){ stencil_pass ? RS_CMP_ALWAYS : RS_CMP_NEVER, stencil_pass ? keep : op,
                                        stencil_pass && !depth_pass ? op : keep, stencil_pass && depth_pass ? op : keep };
    draw_all_paths(&rt, &d, 1);
    uint8_t r = sten(&rt, 5, 2);
    /* colour and depth only where both pass */
    assert_int_equal(px(&rt, 5, 2, 0), stencil_pass && depth_pass ? 0xffffffffu : CLEAR_RGBA);
    assert_true(rt.depth[2 * W + 5] == (stencil_pass && depth_pass ? 0.25f : 0.5f));
    rs_target_free(&rt);
    return r;
}

/* Every stencil operation, on each outcome (FAIL, ZFAIL, PASS), with wrap-around and saturation, through the
 * write mask. */
static void test_stencil_ops(void **state)
{
    (void)state;
    for (int o = 0; o < 3; o++) {
        bool sp = o > 0, dp = o == 2;
        assert_int_equal(stencil_after(RS_STENCILOP_KEEP, 0x5a, 3, 0xff, sp, dp), 0x5a);
        assert_int_equal(stencil_after(RS_STENCILOP_ZERO, 0x5a, 3, 0xff, sp, dp), 0x00);
        assert_int_equal(stencil_after(RS_STENCILOP_REPLACE, 0x5a, 0x1c3, 0xff, sp, dp), 0xc3);
        assert_int_equal(stencil_after(RS_STENCILOP_INCRSAT, 0xff, 3, 0xff, sp, dp), 0xff);
        assert_int_equal(stencil_after(RS_STENCILOP_INCRSAT, 0x5a, 3, 0xff, sp, dp), 0x5b);
        assert_int_equal(stencil_after(RS_STENCILOP_DECRSAT, 0x00, 3, 0xff, sp, dp), 0x00);
        assert_int_equal(stencil_after(RS_STENCILOP_DECRSAT, 0x5a, 3, 0xff, sp, dp), 0x59);
        assert_int_equal(stencil_after(RS_STENCILOP_INVERT, 0x5a, 3, 0xff, sp, dp), 0xa5);
        assert_int_equal(stencil_after(RS_STENCILOP_INCR, 0xff, 3, 0xff, sp, dp), 0x00);
        assert_int_equal(stencil_after(RS_STENCILOP_DECR, 0x00, 3, 0xff, sp, dp), 0xff);
        /* the write mask: REPLACE 0xff over 0x30 through 0x0f writes the low nibble only */
        assert_int_equal(stencil_after(RS_STENCILOP_REPLACE, 0x30, 0xff, 0x0f, sp, dp), 0x3f);
    }
}

/* The stencil test "(ref & mask) func (stencil & mask)": ref on the left, both masked. */
static void test_stencil_func(void **state)
{
    (void)state;
    rs_vertex v[6];
    quad(v, -1, -1, W + 1, H + 1, 0.5f, WHITE);
    struct { int func; uint32_t ref, mask; uint8_t stored; bool pass; } cases[] = {
        { RS_CMP_LESS, 2, 0xff, 3, true },        /* 2 < 3 */
        { RS_CMP_LESS, 3, 0xff, 2, false },
        { RS_CMP_GREATER, 3, 0xff, 2, true },
        { RS_CMP_EQUAL, 0x13, 0x0f, 0x23, true }, /* 3 == 3 under the mask */
        { RS_CMP_EQUAL, 0x13, 0xff, 0x23, false },
        { RS_CMP_NOTEQUAL, 0x13, 0x0f, 0x23, false },
        { RS_CMP_LESSEQUAL, 0x105, 0xff, 5, true }, /* ref's low 8 bits */
        { RS_CMP_NEVER, 0, 0, 0, false },
        { RS_CMP_ALWAYS, 9, 0xff, 1, true },
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        rs_target rt;
        fresh(&rt, 1, cases[c].stored);
        draw d = { test_rs_defaults(W, H), v, 2 };
        d.st.stencil_enable = true;
        d.st.stencil_ref = cases[c].ref, d.st.stencil_mask = cases[c].mask, d.st.stencil_write_mask = 0xff;
        d.st.stencil_cw = (rs_stencil_ops){ cases[c].func, RS_STENCILOP_KEEP, RS_STENCILOP_KEEP, RS_STENCILOP_KEEP };
        draw_all_paths(&rt, &d, 1);
        if ((px(&rt, 2, 6, 0) == 0xffffffffu) != cases[c].pass) fail_msg("case %zu", c);
        rs_target_free(&rt);
    }
}

/* The classic two passes: mark the left half (colour writes off, REPLACE 1), then draw the whole screen where
 * the stencil EQUALs 1; and two-sided stencil: a counter-clockwise triangle runs the CCW operations, a clockwise
 * one the others, one-sided both run the clockwise ones.  Also on a 4-sample target (per sample). */
static void test_stencil_mark_and_two_sided(void **state)
{
    (void)state;
    for (int samples = 1; samples <= 4; samples += 3) {
        rs_vertex left[6], all[6];
        quad(left, -1, -1, 4.5, H + 1, 0.5f, WHITE);   /* pixels 0..4, and all samples of each */
        quad(all, -1, -1, W + 1, H + 1, 0.5f, (rs_vec4){ 0, 0, 1, 1 });
        rs_target rt;
        fresh(&rt, samples, 0);
        draw d[2] = { { test_rs_defaults(W, H), left, 2 }, { test_rs_defaults(W, H), all, 2 } };
        for (int k = 0; k < 2; k++) {
            d[k].st.stencil_enable = true;
            d[k].st.stencil_ref = 1, d[k].st.stencil_mask = d[k].st.stencil_write_mask = 0xff;
            d[k].st.z_enable = false;
        }
        d[0].st.color_write_disable = 0xf;
        d[0].st.stencil_cw = (rs_stencil_ops){ RS_CMP_ALWAYS, RS_STENCILOP_KEEP, RS_STENCILOP_KEEP, RS_STENCILOP_REPLACE };
        d[1].st.stencil_cw = (rs_stencil_ops){ RS_CMP_EQUAL, RS_STENCILOP_KEEP, RS_STENCILOP_KEEP, RS_STENCILOP_KEEP };
        draw_all_paths(&rt, d, 2);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                assert_int_equal(sten(&rt, x, y), x < 5 ? 1 : 0);
                assert_int_equal(px(&rt, x, y, samples - 1), x < 5 ? 0xffff0000u : CLEAR_RGBA);
            }
        rs_target_free(&rt);
    }
    /* two-sided: cw triangle covering the top-left, ccw the bottom-right (cull none) */
    rs_vertex t[6] = { sv(0, 0, 0.5f, WHITE), sv(8, 0, 0.5f, WHITE), sv(0, 8, 0.5f, WHITE),
                       sv(8, 0, 0.5f, WHITE), sv(0, 8, 0.5f, WHITE), sv(8, 8, 0.5f, WHITE) };
    for (int two = 0; two < 2; two++) {
        rs_target rt;
        fresh(&rt, 1, 10);
        draw d = { test_rs_defaults(W, H), t, 2 };
        d.st.cull_mode = RS_CULL_NONE;
        d.st.stencil_enable = true, d.st.stencil_two_sided = two;
        d.st.stencil_mask = d.st.stencil_write_mask = 0xff;
        d.st.stencil_cw = (rs_stencil_ops){ RS_CMP_ALWAYS, RS_STENCILOP_KEEP, RS_STENCILOP_KEEP, RS_STENCILOP_INCR };
        d.st.stencil_ccw = (rs_stencil_ops){ RS_CMP_ALWAYS, RS_STENCILOP_KEEP, RS_STENCILOP_KEEP, RS_STENCILOP_DECR };
        draw_all_paths(&rt, &d, 1);
        assert_int_equal(sten(&rt, 1, 1), 11);              /* clockwise: INCR */
        assert_int_equal(sten(&rt, 6, 6), two ? 9 : 11);    /* counter-clockwise: DECR when two-sided */
        rs_target_free(&rt);
    }
}

/* User clip planes in clip space: x >= 0 keeps pixels 4..7 of 8 (pixel 4's centre lies on the plane: kept, the
 * new edge is a left edge); two planes keep their intersection; disabled planes and CLIPPING FALSE clip nothing. */
static void test_clip_planes(void **state)
{
    (void)state;
    rs_vertex v[6];
    quad(v, -1, -1, W + 1, H + 1, 0.5f, WHITE);
    struct { uint32_t enable; bool no_clipping; int x0, y0; } cases[] = {
        { 1u, false, 4, 0 }, { 3u, false, 4, 4 }, { 0u, false, 0, 0 }, { 3u, true, 0, 0 }, { 2u, false, 0, 4 },
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        rs_target rt;
        fresh(&rt, 1, 0);
        draw d = { test_rs_defaults(W, H), v, 2 };
        d.st.clip_plane_enable = cases[c].enable;
        d.st.no_clipping = cases[c].no_clipping;
        d.st.clip_plane[0][0] = 1.0f;          /* x >= 0 */
        d.st.clip_plane[1][1] = -1.0f;         /* y <= 0: the lower half of the screen */
        d.st.clip_plane[2][3] = -1.0f;         /* never inside, but not enabled */
        draw_all_paths(&rt, &d, 1);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                bool in = x >= cases[c].x0 && y >= cases[c].y0;
                if (px(&rt, x, y, 0) != (in ? 0xffffffffu : CLEAR_RGBA)) fail_msg("case %zu: pixel (%d, %d)", c, x, y);
            }
        rs_target_free(&rt);
    }
}

/* CLIPPING FALSE: a triangle in front of the near plane (z < 0) or behind the far plane (z > w) is drawn with its
 * depth clamped to the viewport's range instead of clipped away. */
static void test_no_clipping(void **state)
{
    (void)state;
    const float zs[2] = { -0.5f, 1.5f };
    for (int k = 0; k < 2; k++)
        for (int clip = 0; clip < 2; clip++) {
            rs_vertex v[6];
            quad(v, -1, -1, W + 1, H + 1, zs[k], WHITE);
            rs_target rt;
            fresh(&rt, 1, 0);
            draw d = { test_rs_defaults(W, H), v, 2 };
            d.st.no_clipping = !clip;
            d.st.viewport.min_z = 0.25f, d.st.viewport.max_z = 0.75f;
            draw_all_paths(&rt, &d, 1);
            float want = k == 0 ? 0.25f : 0.75f;
            assert_int_equal(px(&rt, 3, 3, 0), clip ? CLEAR_RGBA : 0xffffffffu);
            assert_true(rt.depth[3 * W + 3] == (clip ? 1.0f : want));
            rs_target_free(&rt);
        }
}

/* A pre-transformed vertex (X, Y, Z, RHW): screen pixels and depth as given, whatever the viewport's mapping
 * (here a viewport of the right half with depth range [0.5, 1]). */
static rs_vertex tv(float X, float Y, float Z, float rhw, float red)
{
    rs_vertex v;
    memset(&v, 0, sizeof v);
    v.pos = (rs_vec4){ X, Y, Z, rhw };
    v.attr[RS_ATTR_COLOR0] = (rs_vec4){ red, 0, 0, 1 };
    return v;
}

/* Pre-transformed vertices: a rectangle from (2, 1) to (6, 5) covers pixels 2..5 x 1..4 (top-left rule) at depth
 * Z; the viewport clips (scissors) but does not map; attributes are perspective-correct in RHW: red 0 at rhw 1
 * on the left edge and 1 at rhw 1/4 on the right one reads t/4 / (t/4 + 1 - t) at t = x/8 (0.2 at x = 4: 51). */
static void test_pretransformed(void **state)
{
    (void)state;
    rs_vertex v[6] = { tv(2, 1, 0.25f, 1, 1), tv(6, 1, 0.25f, 1, 1), tv(2, 5, 0.25f, 1, 1),
                       tv(6, 1, 0.25f, 1, 1), tv(6, 5, 0.25f, 1, 1), tv(2, 5, 0.25f, 1, 1) };
    rs_target rt;
    fresh(&rt, 1, 0);
    draw d = { test_rs_defaults(W, H), v, 2 };
    d.st.pretransformed = true;
    d.st.viewport = (rs_viewport){ 0, 0, W, H, 0.5f, 1.0f };
    draw_all_paths(&rt, &d, 1);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            bool in = x >= 2 && x < 6 && y >= 1 && y < 5;
            assert_int_equal(px(&rt, x, y, 0), in ? 0xff0000ffu : CLEAR_RGBA);
            assert_true(rt.depth[y * W + x] == (in ? 0.25f : 1.0f));
        }
    rs_target_free(&rt);
    /* the viewport scissors: the right half only */
    fresh(&rt, 1, 0);
    d.st.viewport = (rs_viewport){ 4, 0, 4, H, 0, 1 };
    draw_all_paths(&rt, &d, 1);
    assert_int_equal(px(&rt, 3, 2, 0), CLEAR_RGBA);
    assert_int_equal(px(&rt, 4, 2, 0), 0xff0000ffu);
    rs_target_free(&rt);
    /* perspective */
    rs_vertex p[6] = { tv(0, 0, 0.5f, 1, 0), tv(8, 0, 0.5f, 0.25f, 1), tv(0, 8, 0.5f, 1, 0),
                       tv(8, 0, 0.5f, 0.25f, 1), tv(8, 8, 0.5f, 0.25f, 1), tv(0, 8, 0.5f, 1, 0) };
    fresh(&rt, 1, 0);
    d.v = p;
    d.st.viewport = (rs_viewport){ 0, 0, W, H, 0, 1 };
    draw_all_paths(&rt, &d, 1);
    for (int x = 0; x < W; x++) {
        double t = x / 8.0, want = t / 4 / (t / 4 + 1 - t);
        int r = (int)(px(&rt, x, 2, 0) & 0xff);
        if (abs(r - (int)(want * 255 + 0.5)) > 1) fail_msg("pixel %d: red %d, want %.2f", x, r, want * 255);
    }
    assert_int_equal(px(&rt, 4, 2, 0) & 0xff, 51);
    /* CLIPPING TRUE clips Z outside [0, 1]; FALSE clamps it */
    rs_vertex f[3] = { tv(0, 0, 1.5f, 1, 1), tv(8, 0, 1.5f, 1, 1), tv(0, 8, 1.5f, 1, 1) };
    rs_target_clear(&rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, CLEAR_RGBA, 1.0f);
    d.v = f, d.n_tris = 1, d.st.z_func = RS_CMP_ALWAYS;
    draw_all_paths(&rt, &d, 1);
    assert_int_equal(px(&rt, 1, 1, 0), CLEAR_RGBA);
    d.st.no_clipping = true;
    draw_all_paths(&rt, &d, 1);
    assert_int_equal(px(&rt, 1, 1, 0), 0xff0000ffu);
    assert_true(rt.depth[1 * W + 1] == 1.0f);
    rs_target_free(&rt);
}

/* Lines and points go through the same states: a line across row 2 and a point at (6, 6) with colour writes of
 * red only and stencil REPLACE write red over the cleared bytes and the stencil reference (the clockwise states);
 * with the alpha test failing they write nothing. */
static void test_lines_points(void **state)
{
    (void)state;
    rs_vertex line[2] = { sv(0, 2, 0.5f, (rs_vec4){ 1, 1, 1, 0.5f }), sv(W, 2, 0.5f, (rs_vec4){ 1, 1, 1, 0.5f }) };
    rs_vertex pt[1] = { sv(6, 6, 0.5f, (rs_vec4){ 1, 1, 1, 0.5f }) };
    for (int fail = 0; fail < 2; fail++) {
        rs_target rt;
        fresh(&rt, 1, 0);
        rs_state st = test_rs_defaults(W, H);
        st.color_write_disable = 0xe;   /* red only */
        st.stencil_enable = true, st.stencil_ref = 9, st.stencil_mask = st.stencil_write_mask = 0xff;
        st.stencil_cw = (rs_stencil_ops){ RS_CMP_ALWAYS, RS_STENCILOP_KEEP, RS_STENCILOP_KEEP, RS_STENCILOP_REPLACE };
        st.stencil_two_sided = true;   /* lines and points still take the clockwise states */
        st.stencil_ccw = (rs_stencil_ops){ RS_CMP_NEVER, RS_STENCILOP_ZERO, RS_STENCILOP_ZERO, RS_STENCILOP_ZERO };
        st.alpha_test = true, st.alpha_func = fail ? RS_CMP_GREATER : RS_CMP_LESSEQUAL, st.alpha_ref = 128;
        rs_context *rs = rs_create(2);
        assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_LINES, line, 2, NULL, 1, NULL), RS_OK);
        assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_POINTS, pt, 1, NULL, 1, NULL), RS_OK);
        rs_destroy(rs);
        uint32_t want = fail ? CLEAR_RGBA : (CLEAR_RGBA & ~0xffu) | 0xffu;
        assert_int_equal(px(&rt, 3, 2, 0), want);
        assert_int_equal(px(&rt, 6, 6, 0), want);
        assert_int_equal(px(&rt, 3, 3, 0), CLEAR_RGBA);
        assert_int_equal(sten(&rt, 3, 2), fail ? 0 : 9);
        assert_int_equal(sten(&rt, 6, 6), fail ? 0 : 9);
        rs_target_free(&rt);
    }
}

/* Bad values of the states that are on are refused (RS_EINVAL, nothing drawn); off, they are not read. */
static void test_bad_states(void **state)
{
    (void)state;
    rs_vertex v[6];
    quad(v, -1, -1, W + 1, H + 1, 0.5f, WHITE);
    rs_target rt;
    fresh(&rt, 1, 0);
    rs_context *rs = rs_create(1);
    rs_state st = test_rs_defaults(W, H);
    st.alpha_func = 99;
    st.stencil_cw.func = 0;
    st.clip_plane[0][0] = NAN;
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 6, NULL, 2, NULL), RS_OK);
    rs_state a = st;
    a.alpha_test = true;
    assert_int_equal(rs_draw(rs, &a, &rt, RS_PRIM_TRIANGLES, v, 6, NULL, 2, NULL), RS_EINVAL);
    rs_state s = st;
    s.stencil_enable = true;
    assert_int_equal(rs_draw(rs, &s, &rt, RS_PRIM_TRIANGLES, v, 6, NULL, 2, NULL), RS_EINVAL);
    rs_state c = st;
    c.clip_plane_enable = 1;
    assert_int_equal(rs_draw(rs, &c, &rt, RS_PRIM_TRIANGLES, v, 6, NULL, 2, NULL), RS_EINVAL);
    rs_destroy(rs);
    rs_target_free(&rt);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scissor), cmocka_unit_test(test_color_write_mask),
        cmocka_unit_test(test_ext_sample_coverage), cmocka_unit_test(test_alpha_test),
        cmocka_unit_test(test_stencil_ops), cmocka_unit_test(test_stencil_func),
        cmocka_unit_test(test_stencil_mark_and_two_sided), cmocka_unit_test(test_clip_planes),
        cmocka_unit_test(test_no_clipping), cmocka_unit_test(test_pretransformed), cmocka_unit_test(test_lines_points),
        cmocka_unit_test(test_bad_states),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
