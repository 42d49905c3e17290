/* tests/test_raster_misc.c -- culling and winding, depth functions, z write, depth bias, wireframe and point
 * fill pixel positions, POINTS and LINES, MSAA coverage and resolve on an edge, blend factors, determinism
 * across thread counts, RS_EINVAL on bad input, the target API (the deferred clear flushed plane by plane too) and
 * the stats counters. */
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

/* D3D9 defaults: cull CCW, solid, Gouraud, z LESSEQUAL on with write, no blending, full viewport. */
static rs_state def_state(int w, int h) { return test_rs_defaults(w, h); }

/* A vertex at screen (X, Y) of a w x h viewport, depth z (w = 1), colour c. */
static rs_vertex sv(double X, double Y, float z, rs_vec4 c, int w, int h)
{
    rs_vertex v;
    memset(&v, 0, sizeof v);
    v.pos = (rs_vec4){ (float)(X / (w * 0.5) - 1.0), (float)(1.0 - Y / (h * 0.5)), z, 1.0f };
    v.attr[RS_ATTR_COLOR0] = c;
    return v;
}

static const rs_vec4 WHITE = { 1, 1, 1, 1 }, ONE_RED = { 1.0f / 255, 0, 0, 0 };

/* Red channel of pixel (x, y) sample s. */
static int red(const rs_target *rt, int x, int y, int s)
{
    return (int)(rt->color[((size_t)y * rt->width + x) * rt->samples + s] & 0xffu);
}

/* Draw with a fresh context of `threads` threads. */
static int draw_t(int threads, const rs_state *st, rs_target *rt, int prim, const rs_vertex *v, size_t nv, size_t n,
                  rs_stats *s)
{
    rs_context *rs = rs_create(threads);
    int r = rs_draw(rs, st, rt, prim, v, nv, NULL, n, s);
    rs_destroy(rs);
    return r;
}

/* Clockwise / counter-clockwise triangles against the three cull modes. */
static void test_culling(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 64, 64, 1), RS_OK);
    rs_vertex cw[3] = { sv(10, 10, 0.5f, WHITE, 64, 64), sv(50, 10, 0.5f, WHITE, 64, 64), sv(10, 50, 0.5f, WHITE, 64, 64) };
    rs_vertex ccw[3] = { cw[0], cw[2], cw[1] };
    const int modes[3] = { RS_CULL_NONE, RS_CULL_CW, RS_CULL_CCW };
    const bool cw_drawn[3] = { true, false, true }, ccw_drawn[3] = { true, true, false };
    for (int m = 0; m < 3; m++)
        for (int w = 0; w < 2; w++) {
            rs_state st = def_state(64, 64);
            st.cull_mode = modes[m];
            rs_target_clear(&rt, 3, 0, 1.0f);
            rs_stats s;
            assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, w ? ccw : cw, 3, 1, &s), RS_OK);
            bool drawn = w ? ccw_drawn[m] : cw_drawn[m];
            assert_int_equal(red(&rt, 20, 20, 0), drawn ? 255 : 0);
            assert_int_equal(s.prims_culled, drawn ? 0 : 1);
            assert_int_equal(s.prims_drawn, drawn ? 1 : 0);
        }
    rs_target_free(&rt);
}

/* Every comparison function against stored depth 0.5 with incoming 0.25, 0.5, 0.75; z written only on pass. */
static void test_depth_funcs(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 8, 8, 1), RS_OK);
    const float zs[3] = { 0.25f, 0.5f, 0.75f };
    /* pass[func - 1][less, equal, greater] */
    const bool pass[8][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 },
                              { 0, 0, 1 }, { 1, 0, 1 }, { 0, 1, 1 }, { 1, 1, 1 } };
    for (int f = RS_CMP_NEVER; f <= RS_CMP_ALWAYS; f++)
        for (int k = 0; k < 3; k++) {
            rs_state st = def_state(8, 8);
            st.cull_mode = RS_CULL_NONE;
            st.z_func = f;
            rs_vertex v[3] = { sv(-10, -10, zs[k], WHITE, 8, 8), sv(30, -10, zs[k], WHITE, 8, 8), sv(-10, 30, zs[k], WHITE, 8, 8) };
            rs_target_clear(&rt, 3, 0, 0.5f);
            assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, v, 3, 1, NULL), RS_OK);
            bool p = pass[f - 1][k];
            assert_int_equal(red(&rt, 3, 3, 0), p ? 255 : 0);
            assert_true(rt.depth[3 * 8 + 3] == (p ? zs[k] : 0.5f));
        }
    /* z write off: colour passes, depth stays; z off: everything passes, depth stays */
    rs_state st = def_state(8, 8);
    st.cull_mode = RS_CULL_NONE;
    rs_vertex v[3] = { sv(-10, -10, 0.25f, WHITE, 8, 8), sv(30, -10, 0.25f, WHITE, 8, 8), sv(-10, 30, 0.25f, WHITE, 8, 8) };
    st.z_write = false;
    rs_target_clear(&rt, 3, 0, 0.5f);
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, v, 3, 1, NULL), RS_OK);
    assert_int_equal(red(&rt, 3, 3, 0), 255);
    assert_true(rt.depth[27] == 0.5f);
    st.z_write = true;
    st.z_enable = false;
    st.z_func = RS_CMP_NEVER;
    rs_target_clear(&rt, 3, 0, 0.0f);
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, v, 3, 1, NULL), RS_OK);
    assert_int_equal(red(&rt, 3, 3, 0), 255);
    assert_true(rt.depth[27] == 0.0f);
    rs_target_free(&rt);
}

/* Constant bias shifts the stored depth; slope-scaled bias adds scale * max(|dz/dx|, |dz/dy|); a biased
 * coplanar redraw passes or fails LESS accordingly. */
static void test_depth_bias(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 64, 64, 1), RS_OK);
    rs_state st = def_state(64, 64);
    st.cull_mode = RS_CULL_NONE;
    st.z_func = RS_CMP_ALWAYS;
    st.depth_bias = 0.125f;
    rs_vertex flat[3] = { sv(-64, -64, 0.5f, WHITE, 64, 64), sv(200, -64, 0.5f, WHITE, 64, 64), sv(-64, 200, 0.5f, WHITE, 64, 64) };
    rs_target_clear(&rt, 3, 0, 1.0f);
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, flat, 3, 1, NULL), RS_OK);
    assert_true(rt.depth[10 * 64 + 10] == 0.625f);
    /* depth = 0.25 + X / 256 at screen X: dz/dx = 1/256, dz/dy = 0 */
    st.depth_bias = 0.0625f;
    st.slope_scale_depth_bias = 2.0f;
    rs_vertex tilt[3] = { sv(-32, -32, 0.125f, WHITE, 64, 64), sv(96, -32, 0.625f, WHITE, 64, 64), sv(-32, 96, 0.125f, WHITE, 64, 64) };
    rs_target_clear(&rt, 3, 0, 1.0f);
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, tilt, 3, 1, NULL), RS_OK);
    for (int x = 0; x < 40; x++) {
        double want = 0.25 + x / 256.0 + 0.0625 + 2.0 / 256.0;
        assert_true(fabs(rt.depth[20 * 64 + x] - want) < 1e-6);
    }
    /* a coplanar redraw with LESS fails without bias and passes with a negative bias */
    st = def_state(64, 64);
    st.cull_mode = RS_CULL_NONE;
    st.z_func = RS_CMP_LESS;
    rs_target_clear(&rt, 3, 0, 1.0f);
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, tilt, 3, 1, NULL), RS_OK);
    rs_vertex red_tilt[3];
    for (int i = 0; i < 3; i++) { red_tilt[i] = tilt[i]; red_tilt[i].attr[0] = (rs_vec4){ 1, 0, 0, 1 }; }
    rs_stats s;
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, red_tilt, 3, 1, &s), RS_OK);
    assert_true(s.samples_tested > 1000);
    assert_int_equal(s.samples_written, 0);
    st.slope_scale_depth_bias = -1.0f;
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, red_tilt, 3, 1, &s), RS_OK);
    assert_int_equal(s.samples_written, s.samples_tested);
    assert_int_equal(rt.color[20 * 64 + 20], 0xff0000ffu);
    rs_target_free(&rt);
}

/* Wireframe of screen triangle (2,2), (12,2), (2,12): each edge from its start to before its end, one pixel
 * per major-axis step, every vertex once: additive blending counts each lit pixel exactly once. */
static void test_wireframe_pixels(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 16, 16, 1), RS_OK);
    rs_state st = def_state(16, 16);
    st.fill_mode = RS_FILL_WIREFRAME;
    st.z_enable = false;
    st.blend_enable = true;
    st.dst_blend = RS_BLEND_ONE;
    rs_vertex v[3] = { sv(2, 2, 0.5f, ONE_RED, 16, 16), sv(12, 2, 0.5f, ONE_RED, 16, 16), sv(2, 12, 0.5f, ONE_RED, 16, 16) };
    rs_target_clear(&rt, 3, 0, 1.0f);
    assert_int_equal(draw_t(2, &st, &rt, RS_PRIM_TRIANGLES, v, 3, 1, NULL), RS_OK);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++) {
            bool want = (y == 2 && x >= 2 && x <= 11) ||          /* (2,2) -> (12,2): x 2..11 */
                        (x + y == 14 && x >= 3 && x <= 12) ||     /* (12,2) -> (2,12): x 12..3 */
                        (x == 2 && y >= 3 && y <= 12);            /* (2,12) -> (2,2): y 12..3 */
            assert_int_equal(red(&rt, x, y, 0), want ? 1 : 0);
        }
    /* the same edges as a quad's two triangles: the shared diagonal is drawn by both (count 2) */
    rs_vertex q[6] = { v[0], v[1], v[2], v[1], sv(12, 12, 0.5f, ONE_RED, 16, 16), v[2] };
    st.cull_mode = RS_CULL_NONE;
    rs_target_clear(&rt, 3, 0, 1.0f);
    assert_int_equal(draw_t(2, &st, &rt, RS_PRIM_TRIANGLES, q, 6, 2, NULL), RS_OK);
    assert_int_equal(red(&rt, 7, 7, 0), 2);
    assert_int_equal(red(&rt, 12, 7, 0), 1);
    rs_target_free(&rt);
}

/* Point fill: one pixel per vertex, the nearest pixel centre (ties towards +x / +y). */
static void test_point_fill_pixels(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 32, 32, 1), RS_OK);
    rs_state st = def_state(32, 32);
    st.fill_mode = RS_FILL_POINT;
    st.cull_mode = RS_CULL_NONE;
    rs_vertex v[3] = { sv(5.4, 7.6, 0.5f, WHITE, 32, 32), sv(20.5, 3.5, 0.5f, WHITE, 32, 32), sv(12, 30, 0.5f, WHITE, 32, 32) };
    rs_target_clear(&rt, 3, 0, 1.0f);
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, v, 3, 1, NULL), RS_OK);
    int n = 0;
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++) {
            bool want = (x == 5 && y == 8) || (x == 21 && y == 4) || (x == 12 && y == 30);
            assert_int_equal(red(&rt, x, y, 0), want ? 255 : 0);
            n += want;
        }
    assert_int_equal(n, 3);
    rs_target_free(&rt);
}

/* POINTS and LINES primitives: pixel positions of points, a vertical, a steep and a shallow line. */
static void test_points_and_lines(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 32, 32, 1), RS_OK);
    rs_state st = def_state(32, 32);
    st.z_enable = false;
    st.blend_enable = true;
    st.dst_blend = RS_BLEND_ONE;
    rs_vertex p[3] = { sv(1, 1, 0.5f, ONE_RED, 32, 32), sv(30.2, 15.7, 0.5f, ONE_RED, 32, 32), sv(-3, 5, 0.5f, ONE_RED, 32, 32) };
    rs_target_clear(&rt, 3, 0, 1.0f);
    rs_stats s;
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_POINTS, p, 3, 3, &s), RS_OK);
    assert_int_equal(red(&rt, 1, 1, 0), 1);
    assert_int_equal(red(&rt, 30, 16, 0), 1);
    assert_int_equal(s.samples_written, 2); /* the third is off the viewport (scissored) */
    const double L[3][4] = { { 5, 2, 5, 10 }, { 12, 2, 16, 14 }, { 18, 20, 30.5, 23 } };
    for (int i = 0; i < 3; i++) {
        rs_vertex l[2] = { sv(L[i][0], L[i][1], 0.5f, ONE_RED, 32, 32), sv(L[i][2], L[i][3], 0.5f, ONE_RED, 32, 32) };
        rs_target_clear(&rt, 3, 0, 1.0f);
        assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_LINES, l, 2, 1, NULL), RS_OK);
        double dx = L[i][2] - L[i][0], dy = L[i][3] - L[i][1];
        bool xm = fabs(dx) >= fabs(dy);
        int lit = 0, want_n = 0;
        for (int y = 0; y < 32; y++)
            for (int x = 0; x < 32; x++) lit += red(&rt, x, y, 0);
        /* independent expectation: each major centre c in [start, end), minor = floor(exact + 0.5) */
        double m0 = xm ? L[i][0] : L[i][1], m1 = xm ? L[i][2] : L[i][3];
        for (int c = (int)ceil(m0); c < m1; c++) {
            double t = (c - m0) / (m1 - m0);
            double mn = xm ? L[i][1] + t * dy : L[i][0] + t * dx;
            int k = (int)floor(mn + 0.5);
            int x = xm ? c : k, y = xm ? k : c;
            assert_int_equal(red(&rt, x, y, 0), 1);
            want_n++;
        }
        assert_int_equal(lit, want_n);
    }
    rs_target_free(&rt);
}

/* 4x MSAA: a rectangle whose right edge is at X = 10.25 covers samples 0, 2, 3 of pixel 10 (at 9.875, 9.625,
 * 10.125; sample 1 at 10.375 is out): resolve (3*255 + 2) / 4 = 191.  An edge exactly through sample 3
 * (10.125, a right edge) leaves it out: (2*255 + 2) / 4 = 128.  Without MULTISAMPLEANTIALIAS the centre
 * decides for all four samples. */
static void test_msaa_resolve_edge(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 16, 4, 4), RS_OK);
    uint32_t out[16 * 4];
    const double edges[2] = { 10.25, 10.125 };
    const int want[2] = { 191, 128 };
    const unsigned want_mask[2] = { 0xd, 0x5 };
    for (int e = 0; e < 2; e++)
        for (int ms = 0; ms < 2; ms++) {
            rs_state st = def_state(16, 4);
            st.multisample = ms;
            rs_vertex v[6] = { sv(-8, -8, 0.5f, WHITE, 16, 4), sv(edges[e], -8, 0.5f, WHITE, 16, 4), sv(edges[e], 12, 0.5f, WHITE, 16, 4),
                               sv(-8, -8, 0.5f, WHITE, 16, 4), sv(edges[e], 12, 0.5f, WHITE, 16, 4), sv(-8, 12, 0.5f, WHITE, 16, 4) };
            rs_target_clear(&rt, 3, 0xff000000u, 1.0f);
            assert_int_equal(draw_t(2, &st, &rt, RS_PRIM_TRIANGLES, v, 6, 2, NULL), RS_OK);
            unsigned mask = 0;
            for (int s = 0; s < 4; s++) mask |= (red(&rt, 10, 1, s) == 255) << s;
            assert_int_equal(mask, ms ? want_mask[e] : 0xf);
            rs_target_resolve(&rt, out);
            assert_int_equal(out[1 * 16 + 10], (ms ? (uint32_t)want[e] * 0x010101u : 0xffffffu) | 0xff000000u);
            assert_int_equal(out[1 * 16 + 9], 0xffffffffu);
            assert_int_equal(out[1 * 16 + 11], 0xff000000u);
        }
    rs_target_free(&rt);
}

/* The resolve of 4-sample targets against its definition, per channel (sum of the 4 samples + 2) / 4, on random
 * samples with every channel's extremes mixed in (all 255: the largest sums; a channel's carry must not reach
 * the next). */
static void test_msaa_resolve_random(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 37, 5, 4), RS_OK);
    const size_t np = 37 * 5;
    uint64_t x = 0x9e3779b97f4a7c15ull;
    for (size_t k = 0; k < np * 4; k++) {
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t v = (uint32_t)(x >> 32);
        rt.color[k] = k % 7 == 0 ? 0xffffffffu : k % 11 == 0 ? 0u : k % 13 == 0 ? v | 0xff00ff00u : v;
    }
    uint32_t out[37 * 5];
    rs_target_resolve(&rt, out);
    for (size_t p = 0; p < np; p++) {
        uint32_t want = 0;
        for (int c = 0; c < 32; c += 8) {
            uint32_t sum = 0;
            for (int k = 0; k < 4; k++) sum += rt.color[p * 4 + (size_t)k] >> c & 0xffu;
            want |= (sum + 2) / 4 << c;
        }
        assert_int_equal(out[p], want);
    }
    rs_target_free(&rt);
}

/* Independent reference of one blended channel: round(s*fs/255) + round(d*fd/255), saturated. */
static int ref_channel(int sf, int df, const int *s, const int *d, int c)
{
    int f[2], m[2] = { sf, df };
    for (int k = 0; k < 2; k++) {
        switch (m[k]) {
        case RS_BLEND_ZERO: f[k] = 0; break;
        case RS_BLEND_ONE: f[k] = 255; break;
        case RS_BLEND_SRCCOLOR: f[k] = s[c]; break;
        case RS_BLEND_INVSRCCOLOR: f[k] = 255 - s[c]; break;
        case RS_BLEND_SRCALPHA: f[k] = s[3]; break;
        case RS_BLEND_INVSRCALPHA: f[k] = 255 - s[3]; break;
        case RS_BLEND_DESTALPHA: f[k] = d[3]; break;
        case RS_BLEND_INVDESTALPHA: f[k] = 255 - d[3]; break;
        case RS_BLEND_DESTCOLOR: f[k] = d[c]; break;
        case RS_BLEND_SRCALPHASAT: f[k] = c == 3 ? 255 : (s[3] < 255 - d[3] ? s[3] : 255 - d[3]); break;
        default: f[k] = 255 - d[c]; break;
        }
    }
    int v = (int)floor(s[c] * f[0] / 255.0 + 0.5) + (int)floor(d[c] * f[1] / 255.0 + 0.5);
    return v > 255 ? 255 : v;
}

/* All 11 x 11 source / destination factor pairs on one pixel. */
static void test_blend_factors(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 4, 4, 1), RS_OK);
    const int s8[4] = { 51, 102, 153, 204 }, d8[4] = { 200, 100, 50, 25 };
    const rs_vec4 src = { 0.2f, 0.4f, 0.6f, 0.8f };
    uint32_t dst = 200u | 100u << 8 | 50u << 16 | 25u << 24;
    for (int sf = RS_BLEND_ZERO; sf <= RS_BLEND_SRCALPHASAT; sf++)
        for (int df = RS_BLEND_ZERO; df <= RS_BLEND_SRCALPHASAT; df++) {
            rs_state st = def_state(4, 4);
            st.blend_enable = true;
            st.src_blend = sf;
            st.dst_blend = df;
            st.z_enable = false;
            rs_vertex v[3] = { sv(-4, -4, 0.5f, src, 4, 4), sv(12, -4, 0.5f, src, 4, 4), sv(-4, 12, 0.5f, src, 4, 4) };
            rs_target_clear(&rt, 3, dst, 1.0f);
            assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, v, 3, 1, NULL), RS_OK);
            uint32_t got = rt.color[5];
            for (int c = 0; c < 4; c++)
                assert_int_equal((int)((got >> (8 * c)) & 0xff), ref_channel(sf, df, s8, d8, c));
        }
    /* SRCALPHA / INVSRCALPHA, the usual "over": 0.8 of white over black = 204 */
    rs_state st = def_state(4, 4);
    st.blend_enable = true;
    st.src_blend = RS_BLEND_SRCALPHA;
    st.dst_blend = RS_BLEND_INVSRCALPHA;
    rs_vec4 w8 = { 1, 1, 1, 0.8f };
    rs_vertex v[3] = { sv(-4, -4, 0.5f, w8, 4, 4), sv(12, -4, 0.5f, w8, 4, 4), sv(-4, 12, 0.5f, w8, 4, 4) };
    rs_target_clear(&rt, 3, 0, 1.0f);
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, v, 3, 1, NULL), RS_OK);
    assert_int_equal(rt.color[5] & 0xff, 204);
    rs_target_free(&rt);
}

/* Small deterministic generator (xorshift64*), uniform in [0, 1). */
static double rnd(uint64_t *s)
{
    *s ^= *s >> 12; *s ^= *s << 25; *s ^= *s >> 27;
    return (double)((*s * 0x2545F4914F6CDD1DULL) >> 11) * (1.0 / 9007199254740992.0);
}

/* A large random scene (perspective, blending, depth, clipping, every fill mode) gives the same colour,
 * depth and AOV bytes and the same stats with 1, 2, 3 and 8 threads. */
static void test_determinism(void **state)
{
    (void)state;
    enum { N = 30000, S = 384 };
    rs_vertex *v = malloc(sizeof *v * N * 3);
    assert_non_null(v);
    uint64_t seed = 77;
    for (int i = 0; i < N; i++) {
        double cx = rnd(&seed) * 2.4 - 1.2, cy = rnd(&seed) * 2.4 - 1.2, r = i % 50 == 0 ? 1.5 : 0.08 * rnd(&seed);
        for (int k = 0; k < 3; k++) {
            rs_vertex *p = &v[3 * i + k];
            memset(p, 0, sizeof *p);
            float w = (float)(0.2 + 3 * rnd(&seed)) * (i % 97 == 0 && k == 0 ? -1.0f : 1.0f);
            p->pos = (rs_vec4){ (float)((cx + r * (rnd(&seed) - 0.5)) * w), (float)((cy + r * (rnd(&seed) - 0.5)) * w),
                                (float)(rnd(&seed) * 1.1 - 0.05) * w, w };
            p->attr[0] = (rs_vec4){ (float)rnd(&seed), (float)rnd(&seed), (float)rnd(&seed), (float)rnd(&seed) };
            p->attr[2] = (rs_vec4){ (float)rnd(&seed), 0, 0, 0 };
        }
    }
    rs_target ref[2];
    rs_stats ref_stats[2];
    const int threads[4] = { 1, 2, 3, 8 };
    for (int ti = 0; ti < 4; ti++)
        for (int ms = 0; ms < 2; ms++) {
            rs_target rt;
            assert_int_equal(rs_target_init(&rt, S, S, ms ? 4 : 1), RS_OK);
            if (!ms) assert_int_equal(rs_target_add_aov(&rt, RS_ATTR_TEXCOORD0, 1), RS_OK);
            rs_target_clear(&rt, 3, 0xff202020u, 1.0f);
            rs_context *rs = rs_create(threads[ti]);
            rs_stats s, total;
            memset(&total, 0, sizeof total);
            for (int pass = 0; pass < 3; pass++) {
                rs_state st = def_state(S, S);
                st.cull_mode = RS_CULL_NONE;
                st.fill_mode = pass == 0 ? RS_FILL_SOLID : (pass == 1 ? RS_FILL_WIREFRAME : RS_FILL_POINT);
                st.blend_enable = true;
                st.src_blend = RS_BLEND_SRCALPHA;
                st.dst_blend = RS_BLEND_INVSRCALPHA;
                st.z_func = RS_CMP_LESS;
                st.attr_mask |= 1u << RS_ATTR_TEXCOORD0;
                size_t n = pass == 0 ? N : N / 10;
                assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, (size_t)N * 3, NULL, n, &s), RS_OK);
                total.prims_drawn += s.prims_drawn;
                total.prims_clipped_away += s.prims_clipped_away;
                total.samples_tested += s.samples_tested;
                total.samples_written += s.samples_written;
            }
            rs_destroy(rs);
            if (ti == 0) {
                ref[ms] = rt;
                ref_stats[ms] = total;
                assert_true(total.samples_written > 100000);
                assert_true(total.prims_clipped_away > 0);
                continue;
            }
            size_t n = (size_t)S * S * rt.samples;
            assert_memory_equal(rt.color, ref[ms].color, n * sizeof *rt.color);
            assert_memory_equal(rt.depth, ref[ms].depth, n * sizeof *rt.depth);
            if (!ms) assert_memory_equal(rt.aov[0].data, ref[ms].aov[0].data, (size_t)S * S * sizeof(float));
            assert_memory_equal(&total, &ref_stats[ms], sizeof total);
            rs_target_free(&rt);
        }
    rs_target_free(&ref[0]);
    rs_target_free(&ref[1]);
    free(v);
}

/* RS_EINVAL for bad arguments, with nothing drawn. */
static void test_einval(void **state)
{
    (void)state;
    rs_context *rs = rs_create(1);
    rs_target rt, rt4;
    assert_int_equal(rs_target_init(&rt, 16, 16, 1), RS_OK);
    assert_int_equal(rs_target_init(&rt4, 16, 16, 4), RS_OK);
    rs_target_clear(&rt, 3, 0, 1.0f);
    rs_vertex v[3] = { sv(0, 0, 0.5f, WHITE, 16, 16), sv(16, 0, 0.5f, WHITE, 16, 16), sv(0, 16, 0.5f, WHITE, 16, 16) };
    uint32_t good_idx[3] = { 0, 1, 2 }, bad_idx[3] = { 0, 1, 3 };
    rs_state st = def_state(16, 16);
    rs_stats s;
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, good_idx, 1, &s), RS_OK);
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, bad_idx, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 2, NULL, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, &st, &rt, 3, v, 3, NULL, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, NULL, 3, NULL, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(NULL, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, NULL, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, &st, NULL, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, SIZE_MAX / 2, &s), RS_EINVAL);
    assert_int_equal(s.prims_in, 0);
    rs_state b;
    b = st; b.cull_mode = 0; assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    b = st; b.fill_mode = 4; assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    b = st; b.shade_mode = 3; assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    b = st; b.z_func = 9; assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    b = st; b.blend_enable = true; b.src_blend = RS_BLEND_SRCALPHASAT + 1;
    assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    b = st; b.depth_bias = NAN; assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    b = st; b.viewport.width = 17; assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    b = st; b.viewport.x = -1; assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    b = st; b.viewport.height = 0; assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    b = st; b.viewport.max_z = INFINITY; assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    /* blend factors are not checked when blending is off; z_func not when z is off */
    b = st; b.src_blend = 99; b.z_enable = false; b.z_func = 0;
    assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_OK);
    /* nothing was drawn by the failing calls: only the two valid draws touched the target */
    rs_target_clear(&rt, 3, 0, 1.0f);
    b = st; b.viewport.y = 8;
    assert_int_equal(rs_draw(rs, &b, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    for (int k = 0; k < 256; k++) assert_int_equal(rt.color[k], 0);
    /* target API */
    rs_target t;
    assert_int_equal(rs_target_init(&t, 0, 5, 1), RS_EINVAL);
    assert_int_equal(rs_target_init(&t, 5, RS_MAX_SIZE + 1, 1), RS_EINVAL);
    assert_int_equal(rs_target_init(&t, 5, 5, 2), RS_EINVAL);
    assert_int_equal(rs_target_init(NULL, 5, 5, 1), RS_EINVAL);
    assert_int_equal(rs_target_add_aov(&rt4, RS_ATTR_TEXCOORD0, 2), RS_EINVAL);
    assert_int_equal(rs_target_add_aov(&rt, RS_MAX_ATTR, 2), RS_EINVAL);
    assert_int_equal(rs_target_add_aov(&rt, 2, 5), RS_EINVAL);
    for (int k = 0; k < RS_MAX_AOV; k++) assert_int_equal(rs_target_add_aov(&rt, 2, 1), RS_OK);
    assert_int_equal(rs_target_add_aov(&rt, 2, 1), RS_EINVAL);
    /* a hand-made AOV plane on a 4-sample target is refused by rs_draw */
    float plane[16 * 16];
    rt4.n_aov = 1;
    rt4.aov[0] = (rs_aov){ 2, 1, plane };
    assert_int_equal(rs_draw(rs, &st, &rt4, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    rt4.n_aov = 0;
    rs_target_free(&rt);
    rs_target_free(&rt4);
    rs_target_free(&rt4); /* freeing twice is harmless */
    rs_destroy(rs);
    rs_destroy(NULL);
}

/* The counters of one draw: in, culled, clipped away, degenerate (zero area, NaN), drawn, samples. */
static void test_stats(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 32, 32, 4), RS_OK);
    rs_target_clear(&rt, 3, 0, 1.0f);
    rs_state st = def_state(32, 32);
    st.z_func = RS_CMP_LESS;
    rs_vertex v[15] = {
        sv(4, 4, 0.5f, WHITE, 32, 32), sv(20, 4, 0.5f, WHITE, 32, 32), sv(4, 20, 0.5f, WHITE, 32, 32),   /* drawn */
        sv(4, 4, 0.5f, WHITE, 32, 32), sv(4, 20, 0.5f, WHITE, 32, 32), sv(20, 4, 0.5f, WHITE, 32, 32),   /* CCW: culled */
        sv(4, 4, -0.5f, WHITE, 32, 32), sv(20, 4, -0.5f, WHITE, 32, 32), sv(4, 20, -0.5f, WHITE, 32, 32), /* clipped */
        sv(4, 4, 0.5f, WHITE, 32, 32), sv(8, 8, 0.5f, WHITE, 32, 32), sv(12, 12, 0.5f, WHITE, 32, 32),   /* zero area */
        sv(4, 4, 0.5f, WHITE, 32, 32), sv(20, 4, 0.5f, WHITE, 32, 32), sv(4, 20, 0.5f, WHITE, 32, 32),   /* NaN */
    };
    v[13].pos.y = NAN;
    rs_stats s;
    assert_int_equal(draw_t(2, &st, &rt, RS_PRIM_TRIANGLES, v, 15, 5, &s), RS_OK);
    assert_int_equal(s.prims_in, 5);
    assert_int_equal(s.prims_drawn, 1);
    assert_int_equal(s.prims_culled, 1);
    assert_int_equal(s.prims_clipped_away, 1);
    assert_int_equal(s.prims_degenerate, 2);
    uint64_t lit = 0;
    for (int k = 0; k < 32 * 32 * 4; k++) lit += rt.color[k] != 0;
    assert_true(lit > 4 * 100);
    assert_int_equal(s.samples_tested, lit);
    assert_int_equal(s.samples_written, lit);
    /* the same again fails LESS everywhere */
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, v, 15, 5, &s), RS_OK);
    assert_int_equal(s.samples_tested, lit);
    assert_int_equal(s.samples_written, 0);
    /* an empty draw */
    assert_int_equal(draw_t(1, &st, &rt, RS_PRIM_TRIANGLES, v, 0, 0, &s), RS_OK);
    assert_int_equal(s.prims_in, 0);
    assert_int_equal(s.samples_tested, 0);
    rs_target_free(&rt);
}

/* RS_MAX_OVERDRAW: a frame may cover the target RS_MAX_OVERDRAW times on average (and at least RS_MIN_WORK
 * pixels).  A triangle over the whole 64x64 target counts its clipped box, so RS_MAX_OVERDRAW copies fit
 * exactly and one more is refused (RS_EWORK, nothing drawn), in one draw or added to an earlier draw of the
 * same frame, for 1 and 2 threads alike; rs_target_clear_deferred starts a new frame.  Without a frame each
 * draw counts alone. */
static void test_work_bound(void **state)
{
    (void)state;
    enum { S = 64 };
    _Static_assert((uint64_t)RS_MAX_OVERDRAW * S * S >= RS_MIN_WORK, "the bound, not the floor, applies");
    const int n = RS_MAX_OVERDRAW + 1;
    rs_vertex *v = malloc(sizeof *v * 3 * (size_t)n);
    assert_non_null(v);
    for (int k = 0; k < n; k++) {
        v[3 * k] = sv(-1, -1, 0.5f, WHITE, S, S);
        v[3 * k + 1] = sv(600, -1, 0.5f, WHITE, S, S);
        v[3 * k + 2] = sv(-1, 600, 0.5f, WHITE, S, S);
    }
    rs_state st = def_state(S, S);
    st.z_enable = false;
    for (int threads = 1; threads <= 2; threads++) {
        rs_target rt;
        assert_int_equal(rs_target_init(&rt, S, S, 1), RS_OK);
        rs_context *rs = rs_create(threads);
        rs_target_clear_deferred(rs, &rt, 3, 0, 1.0f);
        rs_stats s;
        assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3 * (size_t)n, NULL, (size_t)n, &s), RS_EWORK);
        rs_target_flush(rs, &rt);
        assert_int_equal(red(&rt, 8, 8, 0), 0);                        /* nothing drawn */
        assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3 * (size_t)(n - 1), NULL, (size_t)(n - 1), &s),
                         RS_OK);                                        /* the refused draw counted nothing */
        assert_int_equal(s.prims_drawn, (uint64_t)(n - 1));
        assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_EWORK);  /* frame full */
        rs_target_clear_deferred(rs, &rt, 3, 0, 1.0f);                 /* a new frame */
        assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_OK);
        rs_target_flush(rs, &rt);
        assert_int_equal(red(&rt, 8, 8, 0), 255);
        rs_destroy(rs);
        rs = rs_create(threads);                                        /* no frame: each draw alone */
        for (int k = 0; k < 2; k++)
            assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3 * (size_t)(n - 1), NULL, (size_t)(n - 1), &s),
                             RS_OK);
        rs_destroy(rs);
        rs_target_free(&rt);
    }
    free(v);
}

/* Depth of pixel (x, y), sample 0. */
static float depth_at(const rs_target *rt, int x, int y) { return rt->depth[((size_t)y * rt->width + x) * rt->samples]; }

/* rs_target_flush_planes: a present's flush of the colour alone writes every tile's colour and leaves the depth of
 * the tiles no draw touched as it was (the deferred clear still deferred); a draw into such a tile afterwards sees
 * the deferred clear's depth; rs_target_flush writes it; the next frame's clear of both planes replaces it without
 * writing it; a clear of the colour alone writes the deferred depth first.  3 x 2 tiles (T = RS_TILE_SIZE on a
 * 1-sample target, half of it on a 4-sample one); the triangle drawn first lies in tile 0, the second in tile 5
 * (pixels 2T..3T-1 x T..2T-1). */
static void test_flush_planes(void **state)
{
    (void)state;
    const uint32_t bg = 0xff102030u, old = 0x11111111u;
    for (int run = 0; run < 4; run++) {   /* 1 and 2 threads, 1 and 4 samples */
        const int threads = 1 + run % 2, ns = run < 2 ? 1 : 4, T = ns > 1 ? RS_TILE_SIZE / 2 : RS_TILE_SIZE;
        const int W = 3 * T, H = 2 * T;
        rs_state st = def_state(W, H);
        const rs_vertex a[3] = { sv(4, 4, 0.5f, WHITE, W, H), sv(40, 4, 0.5f, WHITE, W, H),
                                 sv(4, 40, 0.5f, WHITE, W, H) };
        const rs_vertex b[3] = { sv(2 * T + 12, T + 6, 0.75f, WHITE, W, H), sv(2 * T + 52, T + 6, 0.75f, WHITE, W, H),
                                 sv(2 * T + 12, T + 46, 0.75f, WHITE, W, H) };
        rs_target rt;
        assert_int_equal(rs_target_init(&rt, W, H, ns), RS_OK);
        rs_target_clear(&rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, old, 0.25f);   /* what a flush must not keep */
        rs_context *rs = rs_create(threads);
        rs_stats s;
        rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, bg, 1.0f);
        assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, a, 3, NULL, 1, &s), RS_OK);
        rs_target_flush_planes(rs, &rt, RS_CLEAR_COLOR);
        assert_int_equal(red(&rt, 8, 8, 0), 255);                      /* drawn */
        assert_int_equal(rt.color[((size_t)50 * W + 50) * ns], bg);     /* tile 0, not covered: cleared */
        assert_true(depth_at(&rt, 50, 50) == 1.0f);                     /* tile 0 was drawn: both planes written */
        for (int y = 0; y < H; y += 9)
            for (int x = T; x < W; x += 7) {
                assert_int_equal(rt.color[((size_t)y * W + x) * ns], bg);   /* untouched tiles: colour cleared ... */
                assert_true(depth_at(&rt, x, y) == 0.25f);              /* ... their depth not yet written */
            }
        /* a draw into tile 5 now: its depth test meets the deferred clear's 1.0, not the 0.25 left in the plane */
        assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, b, 3, NULL, 1, &s), RS_OK);
        rs_target_flush_planes(rs, &rt, RS_CLEAR_COLOR);
        assert_int_equal(s.samples_written, s.samples_tested);
        assert_int_equal(red(&rt, 2 * T + 17, T + 11, 0), 255);
        assert_true(depth_at(&rt, 2 * T + 17, T + 11) == 0.75f && depth_at(&rt, 3 * T - 2, 2 * T - 2) == 1.0f);
        assert_true(depth_at(&rt, T + 36, T + 36) == 0.25f);             /* tile 4: still deferred */
        /* the next frame's clear of both planes: the deferred depth is replaced, never written */
        rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, bg, 0.5f);
        rs_target_flush_planes(rs, &rt, RS_CLEAR_COLOR);
        assert_true(depth_at(&rt, T + 36, T + 36) == 0.25f);
        assert_true(depth_at(&rt, 2 * T + 17, T + 11) == 0.75f);        /* written last frame, deferred again */
        rs_target_flush(rs, &rt);                                       /* and now written: the new frame's */
        assert_true(depth_at(&rt, T + 36, T + 36) == 0.5f && depth_at(&rt, 2 * T + 17, T + 11) == 0.5f &&
                    depth_at(&rt, 8, 8) == 0.5f);
        /* a clear of the colour alone keeps the depth: a deferred depth clear is written first */
        rs_target_clear(&rt, RS_CLEAR_DEPTH, 0, 0.25f);
        rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, bg, 1.0f);
        rs_target_flush_planes(rs, &rt, RS_CLEAR_COLOR);
        rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR, old, 0.0f);
        rs_target_flush(rs, &rt);
        assert_true(depth_at(&rt, T + 36, T + 36) == 1.0f && rt.color[((size_t)(T + 36) * W + T + 36) * ns] == old);
        rs_destroy(rs);
        rs_target_free(&rt);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_culling),
        cmocka_unit_test(test_depth_funcs),
        cmocka_unit_test(test_depth_bias),
        cmocka_unit_test(test_wireframe_pixels),
        cmocka_unit_test(test_point_fill_pixels),
        cmocka_unit_test(test_points_and_lines),
        cmocka_unit_test(test_msaa_resolve_edge),
        cmocka_unit_test(test_msaa_resolve_random),
        cmocka_unit_test(test_blend_factors),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_einval),
        cmocka_unit_test(test_stats),
        cmocka_unit_test(test_work_bound),
        cmocka_unit_test(test_flush_planes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
