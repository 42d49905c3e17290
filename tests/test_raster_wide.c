/* tests/test_raster_wide.c -- span_wide.c's interval walk: triangles whose box in a tile is wider than 8 pixels
 * have each row's covered interval computed from the edges' crossing columns (row_spans, in doubles), then groups
 * of 8 lanes over it: from the row's first column for medium triangles (box at most 32 wide, moved left at a tile's
 * right end), 8-aligned for larger ones (through span8 past the target's right end), the groups between a row's
 * first and last without a lane mask.  The triangles here: medium (9 to 32 pixels wide) and large (up to several
 * tiles, some past the guard band), placed around multiples of 64 (tile and band borders) and the target's right and
 * bottom edges (sizes that are not multiples of 8 or 64), some with their vertices on pixel centres and half pixels and
 * axis-aligned edges (crossings exactly at a pixel: the top-left rule and row_spans' integer case; horizontal
 * edges: its A = 0 case); vertex colours with a constant alpha (the walk's specialised shading) or a varying one,
 * or no COLOR0 (white); every depth function, depth writes off, depth off, blending (span8's per-pixel path);
 * deferred and immediate clears (tile buffers or the target's planes), 1 and 2 threads, each instruction set the
 * CPU has, and a viewport that does not start at a tile border.  Every byte of colour and depth and every counter
 * must equal the reference path's.  Deterministic: a fixed xorshift seed. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../raster/raster.h"
#include "util/raster_util.h"

/* v snapped to half pixels when snap (edges through pixel centres: exact crossings). */
static float snapped(float v, bool snap) { return snap ? (float)(int)(v * 2.0f) * 0.5f : v; }

/* n triangles in the viewport (x, y, w, h) of the target, in clip space: medium ones (box 9 to 32 pixels wide,
 * 1 to 40 tall) and, one in `big`, large ones (33 to 300 pixels, a few far past the target); a third with snapped
 * vertices (some right triangles with a horizontal and a vertical edge); random depth, w and colours, the alpha
 * constant per triangle (1 or one random value) or per vertex. */
static rs_vertex *wide_triangles(uint64_t *s, int n, int big, const rs_viewport *vp)
{
    rs_vertex *v = calloc((size_t)n * 3, sizeof *v);
    assert_non_null(v);
    for (int i = 0; i < n; i++) {
        const bool large = test_rnd(s) % (unsigned)big == 0, snap = test_rnd(s) % 3 == 0,
                   right = snap && test_rnd(s) % 2;
        const float bw = large ? (test_rnd(s) % 8 == 0 ? test_frnd(s, 300.0f, 3000.0f) : test_frnd(s, 33.0f, 300.0f))
                               : test_frnd(s, 9.0f, 32.9f);
        const float bh = large ? test_frnd(s, 2.0f, 300.0f) : test_frnd(s, 1.0f, 40.0f);
        const float cx = (float)vp->x + test_near_edge(s, vp->width, -40.0f, 8.0f),
                    cy = (float)vp->y + test_near_edge(s, vp->height, -40.0f, 8.0f);
        const bool aconst = test_rnd(s) % 2;
        const float alpha = test_rnd(s) % 2 ? 1.0f : test_frnd(s, 0.0f, 1.0f);
        for (int k = 0; k < 3; k++) {
            rs_vertex *q = &v[3 * i + k];
            float px = snapped(cx + test_frnd(s, 0.0f, bw), snap), py = snapped(cy + test_frnd(s, 0.0f, bh), snap);
            if (right && k > 0) { /* (cx, cy), (cx + bw, cy), (cx, cy + bh) or the reverse */
                px = snapped(k == 1 ? cx + bw : cx, true), py = snapped(k == 1 ? cy : cy + bh, true);
                if (i % 2) px = snapped(2.0f * cx + bw - px, true);
            } else if (right) {
                px = snapped(cx, true), py = snapped(cy, true);
            }
            const float wv = test_rnd(s) % 3 == 0 ? test_frnd(s, 0.5f, 2.0f) : 1.0f;
            const float nx = (px - (float)vp->x) / (float)vp->width * 2.0f - 1.0f;
            const float ny = 1.0f - (py - (float)vp->y) / (float)vp->height * 2.0f;
            q->pos = (rs_vec4){nx * wv, ny * wv, test_frnd(s, 0.0f, 1.0f) * wv, wv};
            q->attr[RS_ATTR_COLOR0] = (rs_vec4){test_frnd(s, -0.2f, 1.2f), test_frnd(s, -0.2f, 1.2f),
                                                test_frnd(s, -0.2f, 1.2f), aconst ? alpha : test_frnd(s, 0.0f, 1.0f)};
        }
    }
    return v;
}

/* The states of case zc: 0 depth off, 1 LESSEQUAL without writes, 2 .. 9 each function with writes (LESSEQUAL and
 * LESS: the walk's specialised instances), 10 blending (LESSEQUAL), 11 no COLOR0 (white, LESSEQUAL). */
static rs_state case_state(int zc, const rs_viewport *vp)
{
    rs_state st;
    memset(&st, 0, sizeof st);
    st.cull_mode = RS_CULL_NONE, st.fill_mode = RS_FILL_SOLID, st.shade_mode = RS_SHADE_GOURAUD;
    st.attr_mask = zc == 11 ? 0u : 1u << RS_ATTR_COLOR0;
    st.z_enable = zc != 0, st.z_write = zc != 1;
    st.z_func = zc >= 2 && zc < 2 + RS_CMP_ALWAYS ? zc - 1 : RS_CMP_LESSEQUAL;
    st.blend_enable = zc == 10;
    st.src_blend = RS_BLEND_SRCALPHA, st.dst_blend = RS_BLEND_INVSRCALPHA;
    st.viewport = *vp;
    return st;
}

/* One target size and viewport: every state of case_state, deferred and immediate clear, 1 and 2 threads, each
 * instruction set, the fast path's bytes and counters against the reference path's. */
static void one_size(uint64_t *s, int w, int h, rs_viewport vp)
{
    const int n = 400;
    for (int zc = 0; zc < 12; zc++) {
        const rs_state st = case_state(zc, &vp);
        const float clear_z = st.z_func == RS_CMP_GREATER || st.z_func == RS_CMP_GREATEREQUAL ? 0.0f : 0.6f;
        rs_vertex *v = wide_triangles(s, n, 6, &vp);
        char what[64];
        snprintf(what, sizeof what, "%dx%d, case %d", w, h, zc);
        test_rs_paths_agree(w, h, &st, v, n, clear_z, 5000, what);
        free(v);
    }
}

/* Target sizes whose width and height are not multiples of 8 or 64 (and one that is), the whole target as the
 * viewport. */
static void test_wide_same_bytes(void **state)
{
    (void)state;
    uint64_t s = 0x3a1d3a1dull;
    const int sizes[][2] = {{67, 61}, {197, 130}, {128, 128}, {203, 77}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        one_size(&s, sizes[i][0], sizes[i][1], (rs_viewport){0, 0, sizes[i][0], sizes[i][1], 0.0f, 1.0f});
}

/* A viewport that starts inside a tile and ends before the target's right edge (tiles narrowed to it: the walks'
 * groups must stay inside them). */
static void test_wide_viewport(void **state)
{
    (void)state;
    uint64_t s = 0x77e1c0deull;
    one_size(&s, 230, 150, (rs_viewport){21, 13, 170, 121, 0.0f, 1.0f});
    one_size(&s, 140, 90, (rs_viewport){61, 5, 75, 80, 0.0f, 1.0f});
}

/* Triangles with a nearly vertical edge from 1/256 pixel above a pixel's sample to 1/256 pixel beside the sample
 * rows below (edge function exactly 0 or +-1 at that sample: with the top-left bias, the one exact crossing of a
 * right edge, row_spans' end = q + 1 case, which the random triangles almost never meet), the third vertex left or
 * right of it (the edge a right or a left one), medium and large; a 128-pixel target so that the clip coordinates
 * are exact in float.  Bytes and counters against the reference path's, each instruction set. */
static void test_wide_exact_edges(void **state)
{
    (void)state;
    uint64_t s = 0xed9eed9eull;
    const int w = 128, h = 128, n = 600;
    const rs_viewport vp = {0, 0, w, h, 0.0f, 1.0f};
    rs_vertex *v = calloc((size_t)n * 3, sizeof *v);
    assert_non_null(v);
    for (int i = 0; i < n; i++) {
        const float xs = (float)(20 + (int)(test_rnd(&s) % 88)), ys = (float)(2 + (int)(test_rnd(&s) % 60));
        const float d = 1.0f / 256.0f, len = (float)(2 + (int)(test_rnd(&s) % 60));
        const float width = test_rnd(&s) % 3 ? test_frnd(&s, 9.0f, 32.0f) : test_frnd(&s, 33.0f, 90.0f);
        const float side = test_rnd(&s) % 2 ? width : -width;
        const float px[3] = {xs, xs + (test_rnd(&s) % 2 ? d : -d), xs + side};
        const float py[3] = {ys + (test_rnd(&s) % 4 ? -d : d), ys + len, ys + test_frnd(&s, 0.0f, len)};
        for (int k = 0; k < 3; k++)
            v[3 * i + k].pos = (rs_vec4){px[k] / (float)w * 2.0f - 1.0f, 1.0f - py[k] / (float)h * 2.0f,
                                         test_frnd(&s, 0.0f, 1.0f), 1.0f},
            v[3 * i + k].attr[RS_ATTR_COLOR0] = (rs_vec4){test_frnd(&s, 0.0f, 1.0f), test_frnd(&s, 0.0f, 1.0f),
                                                          test_frnd(&s, 0.0f, 1.0f), 1.0f};
    }
    const rs_state st = case_state(1, &vp); /* no depth writes: every triangle's pixels are tested */
    rs_target ref;
    rs_stats rst[2];
    assert_int_equal(rs_target_init(&ref, w, h, 1), RS_OK);
    test_rs_draw_twice(&ref, &st, v, n, true, RS_ISA_AVX2, 1, false, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0.6f, rst);
    for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
        if (!rs_isa_supported(isa)) continue;
        rs_target rt;
        rs_stats fst[2];
        assert_int_equal(rs_target_init(&rt, w, h, 1), RS_OK);
        test_rs_draw_twice(&rt, &st, v, n, false, isa, 1, false, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0.6f, fst);
        assert_memory_equal(ref.color, rt.color, (size_t)w * (size_t)h * 4);
        assert_int_equal(rst[0].samples_tested, fst[0].samples_tested);
        assert_int_equal(rst[0].samples_written, fst[0].samples_written);
        rs_target_free(&rt);
    }
    rs_target_free(&ref);
    free(v);
}

/* A colour channel for test_wide_colour_range: one of the values around and far past the ends of [0, 1] --
 * huge ones (their * 255 + 0.5 past int32: a conversion's 0x80000000 if not saturated first), -0, infinities --
 * or an ordinary one. */
static float odd_channel(uint64_t *s)
{
    static const float v[] = {-3.0e10f, -70000.0f, -1.5f, -0.0f, 0.0f, 1.0f, 1.0001f, 129.0f, 300.0f, 3.0e10f,
                              INFINITY, -INFINITY};
    return test_rnd(s) % 3 ? v[test_rnd(s) % (sizeof v / sizeof v[0])] : test_frnd(s, 0.0f, 1.0f);
}

/* Colours far outside [0, 1], infinities (interpolated to infinities and NaN) in every channel, a constant alpha
 * or a varying one, on medium and large triangles: the walk's shading (to8_8p: the packs do the lower saturation)
 * must give the reference's bytes. */
static void test_wide_colour_range(void **state)
{
    (void)state;
    uint64_t s = 0xc01011full;
    const int w = 197, h = 130, n = 300;
    const rs_viewport vp = {0, 0, w, h, 0.0f, 1.0f};
    for (int zc = 0; zc < 3; zc++) { /* depth off, LESSEQUAL without writes, LESS with writes */
        const rs_state st = case_state(zc == 2 ? 3 : zc, &vp);
        rs_vertex *v = wide_triangles(&s, n, 4, &vp);
        for (int i = 0; i < n; i++) {
            const bool aconst = test_rnd(&s) % 2;
            const float alpha = odd_channel(&s);
            for (int k = 0; k < 3; k++)
                v[3 * i + k].attr[RS_ATTR_COLOR0] =
                    (rs_vec4){odd_channel(&s), odd_channel(&s), odd_channel(&s), aconst ? alpha : odd_channel(&s)};
        }
        char what[64];
        snprintf(what, sizeof what, "colour range, case %d", zc);
        test_rs_paths_agree(w, h, &st, v, n, 0.6f, 3000, what);
        free(v);
    }
}

/* A viewport depth range of [0.25, 0.75] and a depth bias of +-0.3 (with a slope-scaled one): depths below and
 * above the range, clamped to it per pixel (the walk's zclamp8), against the reference path, LESSEQUAL and LESS
 * with writes, GREATER without. */
static void test_wide_depth_clamp(void **state)
{
    (void)state;
    uint64_t s = 0xde9c1a39ull;
    const int w = 203, h = 77, n = 300;
    const rs_viewport vp = {0, 0, w, h, 0.25f, 0.75f};
    const int cases[] = {2, 3, 6};
    for (int c = 0; c < 3; c++)
        for (int b = 0; b < 2; b++) {
            rs_state st = case_state(cases[c], &vp);
            st.depth_bias = b ? 0.3f : -0.3f;
            st.slope_scale_depth_bias = 0.01f;
            st.z_write = cases[c] != 6;
            rs_vertex *v = wide_triangles(&s, n, 4, &vp);
            char what[64];
            snprintf(what, sizeof what, "depth clamp, case %d, bias %d", cases[c], b);
            test_rs_paths_agree(w, h, &st, v, n, cases[c] == 6 ? 0.0f : 1.0f, 3000, what); /* (all pass at first) */
            free(v);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wide_same_bytes),
        cmocka_unit_test(test_wide_viewport),
        cmocka_unit_test(test_wide_exact_edges),
        cmocka_unit_test(test_wide_colour_range),
        cmocka_unit_test(test_wide_depth_clamp),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
