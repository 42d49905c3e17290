/* tests/test_raster_ps.c -- the rasterizer's pixel shader (raster.h, rs_ps_fn): the inputs are the fixed path's
 * interpolation (a shader returning TEXCOORD0 writes the bytes the fixed path writes for the same values in
 * COLOR0, perspective included), vPos is the pixel, vFace the winding, ddx / ddy are the quad's lane differences
 * also on the triangle's edge pixels (helper lanes), texkill leaves colour and depth untouched, oDepth replaces the
 * depth, lines run the shader too, and the bytes do not depend on the thread count or the instruction set. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "../raster/raster.h"
#include "util/raster_util.h"

#define W 32
#define H 24
#define CLEAR 0x11223344u

/* A vertex at screen (X, Y) with clip w (the position scaled by w: the same screen point), depth z, TEXCOORD0 t
 * and COLOR0 t too. */
static rs_vertex vtx(double X, double Y, float z, float w, rs_vec4 t)
{
    rs_vertex v;
    memset(&v, 0, sizeof v);
    v.pos = (rs_vec4){(float)((X / (W * 0.5) - 1.0) * w), (float)((1.0 - Y / (H * 0.5)) * w), z * w, w};
    v.attr[RS_ATTR_COLOR0] = t;
    v.attr[RS_ATTR_TEXCOORD0] = t;
    return v;
}

/* Three triangles of different sizes, windings and depths in w (perspective), with varied TEXCOORD0. */
static void scene(rs_vertex *v)
{
    v[0] = vtx(1.3, 1.1, 0.2f, 1.0f, (rs_vec4){0, 0.1f, 0.9f, 1});
    v[1] = vtx(29.7, 3.2, 0.5f, 3.0f, (rs_vec4){1, 0.4f, 0.2f, 1});
    v[2] = vtx(4.1, 22.6, 0.8f, 0.5f, (rs_vec4){0.3f, 1, 0.5f, 0.5f});
    v[3] = vtx(30.5, 4.0, 0.3f, 2.0f, (rs_vec4){0.9f, 0.9f, 0.1f, 1});
    v[5] = vtx(31.0, 23.5, 0.1f, 1.0f, (rs_vec4){0.2f, 0.5f, 0.7f, 1});   /* counter-clockwise on screen */
    v[4] = vtx(12.0, 23.0, 0.6f, 1.5f, (rs_vec4){0.6f, 0.0f, 1.0f, 1});
    v[6] = vtx(10.0, 2.0, 0.05f, 1.0f, (rs_vec4){0.5f, 0.5f, 0.5f, 1});
    v[7] = vtx(14.0, 2.0, 0.05f, 1.0f, (rs_vec4){0.5f, 0.5f, 0.5f, 1});
    v[8] = vtx(10.0, 6.0, 0.05f, 1.0f, (rs_vec4){0.5f, 0.5f, 0.5f, 1});
}

static rs_state state(void)
{
    rs_state st = test_rs_defaults(W, H);
    st.cull_mode = RS_CULL_NONE;
    st.multisample = false;
    st.attr_mask = (1u << RS_ATTR_COLOR0) | (1u << RS_ATTR_TEXCOORD0);
    return st;
}

/* Draw the scene with st into a fresh 1-sample target on `threads` threads (reference path or not). */
static void draw(rs_target *rt, const rs_state *st, int threads, bool reference, int isa, int prim)
{
    rs_vertex v[9];
    scene(v);
    assert_int_equal(rs_target_init(rt, W, H, 1), RS_OK);
    rs_target_clear(rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, CLEAR, 1.0f);
    rs_context *rs = rs_create(threads);
    rs_set_reference_path(rs, reference);
    if (rs_isa_supported(isa)) rs_set_isa(rs, isa);
    size_t n = prim == RS_PRIM_TRIANGLES ? 3 : prim == RS_PRIM_LINES ? 4 : 9;
    assert_int_equal(rs_draw(rs, st, rt, prim, v, 9, NULL, n, NULL), RS_OK);
    rs_destroy(rs);
}

/* oC0 = TEXCOORD0 of each lane. */
static void ps_texcoord(const void *ctx, const rs_ps_quad *q, rs_ps_out *o)
{
    (void)ctx;
    for (int k = 0; k < 4; k++) o->color[k] = q->v[k][RS_ATTR_TEXCOORD0];
}

/* The shader's inputs are the fixed path's interpolation: oC0 = TEXCOORD0 gives COLOR0's bytes, for triangles,
 * lines and points, on 1 and 2 threads and every instruction set. */
static void test_inputs_are_the_fixed_interpolation(void **state_)
{
    (void)state_;
    const int prims[] = {RS_PRIM_TRIANGLES, RS_PRIM_LINES, RS_PRIM_POINTS};
    for (size_t p = 0; p < 3; p++) {
        rs_state fixed = state(), ps = state();
        ps.ps = ps_texcoord;
        rs_target a, b;
        draw(&a, &fixed, 1, true, RS_ISA_AVX2, prims[p]);
        for (int threads = 1; threads <= 2; threads++)
            for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
                draw(&b, &ps, threads, false, isa, prims[p]);
                assert_memory_equal(a.color, b.color, (size_t)W * H * 4);
                assert_memory_equal(a.depth, b.depth, (size_t)W * H * 4);
                rs_target_free(&b);
            }
        rs_target_free(&a);
    }
}

/* oC0 = (vPos.x / 255, vPos.y / 255, vFace, lane's live bit). */
static void ps_vpos(const void *ctx, const rs_ps_quad *q, rs_ps_out *o)
{
    (void)ctx;
    for (int k = 0; k < 4; k++)
        o->color[k] = (rs_vec4){q->vpos[k][0] / 255.0f, q->vpos[k][1] / 255.0f, q->front ? 1.0f : 0.0f,
                                (q->live >> k) & 1u ? 1.0f : 0.0f};
}

/* vPos is the pixel, vFace the winding (the second triangle is counter-clockwise on screen), a written pixel is live. */
static void test_vpos_vface(void **state_)
{
    (void)state_;
    rs_state st = state();
    st.ps = ps_vpos;
    rs_target rt;
    draw(&rt, &st, 2, false, RS_ISA_AVX2, RS_PRIM_TRIANGLES);
    int seen[2] = {0, 0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint32_t c = rt.color[y * W + x];
            if (c == CLEAR) continue;
            assert_int_equal(c & 0xffu, (uint32_t)x);
            assert_int_equal((c >> 8) & 0xffu, (uint32_t)y);
            assert_int_equal(c >> 24, 255u);
            seen[((c >> 16) & 0xffu) == 255u]++;
        }
    assert_true(seen[0] > 20 && seen[1] > 20);   /* both windings drawn, told apart */
    rs_target_free(&rt);
}

/* oC0.x = ddx(TEXCOORD0.x) * 6, oC0.y = 0.75 + ddy(TEXCOORD0.y) * 16, from the quad's lanes. */
static void ps_derivatives(const void *ctx, const rs_ps_quad *q, rs_ps_out *o)
{
    (void)ctx;
    float dx = q->v[1][RS_ATTR_TEXCOORD0].x - q->v[0][RS_ATTR_TEXCOORD0].x;
    float dy = q->v[2][RS_ATTR_TEXCOORD0].y - q->v[0][RS_ATTR_TEXCOORD0].y;
    for (int k = 0; k < 4; k++) o->color[k] = (rs_vec4){dx * 6.0f, 0.75f + dy * 16.0f, 0, 1};
}

/* An affine attribute (w = 1) u = X / 16, v = -Y / 32: ddx(u) = 1/16 and ddy(v) = -1/32 at every pixel,
 * those on the triangle's edges too (their quads have helper lanes outside the triangle). */
static void test_derivatives(void **state_)
{
    (void)state_;
    rs_vertex v[3];
    const double P[3][2] = {{0.5, 0.5}, {30.5, 1.5}, {2.5, 21.5}};
    for (int k = 0; k < 3; k++)
        v[k] = vtx(P[k][0], P[k][1], 0.5f, 1.0f, (rs_vec4){(float)(P[k][0] / 16), (float)(-P[k][1] / 32), 0, 1});
    rs_state st = state();
    st.ps = ps_derivatives;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_target_clear(&rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, CLEAR, 1.0f);
    rs_context *rs = rs_create(1);
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_OK);
    int n = 0;
    for (int p = 0; p < W * H; p++) {
        if (rt.color[p] == CLEAR) continue;
        assert_int_equal(rt.color[p] & 0xffu, 96u);           /* 6/16 = 0.375: 96 */
        assert_int_equal((rt.color[p] >> 8) & 0xffu, 64u);    /* 0.75 - 16/32 = 0.25: 64 */
        n++;
    }
    assert_true(n > 250);
    rs_destroy(rs);
    rs_target_free(&rt);
}

/* Lanes at odd x are killed; the others write (0, 1, 0, 1) at depth 0.25 (oDepth). */
static void ps_kill_depth(const void *ctx, const rs_ps_quad *q, rs_ps_out *o)
{
    (void)ctx;
    for (int k = 0; k < 4; k++) {
        o->color[k] = (rs_vec4){0, 1, 0, 1};
        o->depth[k] = 0.25f;
        if ((int)q->vpos[k][0] & 1) o->kill |= 1u << k;
    }
    o->depth_written = true;
}

/* texkill: killed pixels keep the clear's colour and depth; the others have the shader's colour and depth. */
static void test_kill_and_depth(void **state_)
{
    (void)state_;
    rs_state st = state();
    st.ps = ps_kill_depth;
    rs_target rt;
    draw(&rt, &st, 2, false, RS_ISA_AVX2, RS_PRIM_TRIANGLES);
    int drawn = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint32_t c = rt.color[y * W + x];
            float z = rt.depth[y * W + x];
            if (x & 1) assert_true(c == CLEAR && z == 1.0f);
            else if (c != CLEAR) assert_true(c == 0xff00ff00u && z == 0.25f), drawn++;
        }
    assert_true(drawn > 40);
    rs_target_free(&rt);
}

/* A context that drew with one interpolated slot draws with a pixel shader (every slot): its chunks' attribute
 * arrays grow to the new stride (they overflowed: the viewer crashed on its second frame with --shading pixel), and
 * the bytes are those of a fresh context. */
static void test_stride_grows(void **state_)
{
    (void)state_;
    enum { N = 600 };
    static rs_vertex v[3 * N];
    for (int k = 0; k < N; k++) {   /* many small triangles: the chunks grow their arrays for one slot */
        double x = 1 + (k % 29), y = 1 + (k / 29) % 21;
        v[3 * k] = vtx(x, y, 0.5f, 1.0f, (rs_vec4){0.2f, 0.4f, 0.6f, 1});
        v[3 * k + 1] = vtx(x + 0.9, y, 0.5f, 1.0f, (rs_vec4){0.8f, 0.4f, 0.1f, 1});
        v[3 * k + 2] = vtx(x, y + 0.9, 0.5f, 1.0f, (rs_vec4){0.1f, 0.9f, 0.3f, 1});
    }
    rs_state one = state(), ps = state();
    one.attr_mask = 1u << RS_ATTR_COLOR0;
    ps.ps = ps_texcoord;
    ps.attr_mask = (1u << RS_MAX_ATTR) - 1u;
    rs_target a, b;
    assert_int_equal(rs_target_init(&a, W, H, 1), RS_OK);
    assert_int_equal(rs_target_init(&b, W, H, 1), RS_OK);
    rs_context *used = rs_create(1), *fresh = rs_create(1);
    rs_target_clear(&a, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, CLEAR, 1.0f);
    assert_int_equal(rs_draw(used, &one, &a, RS_PRIM_TRIANGLES, v, 3 * N, NULL, N, NULL), RS_OK);
    rs_target_clear(&a, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, CLEAR, 1.0f);
    assert_int_equal(rs_draw(used, &ps, &a, RS_PRIM_TRIANGLES, v, 3 * N, NULL, N, NULL), RS_OK);
    rs_target_clear(&b, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, CLEAR, 1.0f);
    assert_int_equal(rs_draw(fresh, &ps, &b, RS_PRIM_TRIANGLES, v, 3 * N, NULL, N, NULL), RS_OK);
    assert_memory_equal(a.color, b.color, (size_t)W * H * 4);
    rs_destroy(used);
    rs_destroy(fresh);
    rs_target_free(&a);
    rs_target_free(&b);
}

/* Calls and shaded lanes of the counting shader (its ctx). */
typedef struct ps_count { unsigned calls, lanes; } ps_count;

/* oC0 = TEXCOORD0; counts its calls and the lanes it is asked for (need). */
static void ps_counting(const void *ctx, const rs_ps_quad *q, rs_ps_out *o)
{
    ps_count *c = (ps_count *)ctx;
    c->calls++, c->lanes += (unsigned)__builtin_popcount(q->need);
    for (int k = 0; k < 4; k++) o->color[k] = q->v[k][RS_ATTR_TEXCOORD0];
}

/* The shader runs once per 2x2 quad, for all its covered pixels (need), not once per pixel: one triangle over the
 * whole W x H target (W / 2 * H / 2 quads) takes that many calls and asks for every pixel once; on 4 samples as
 * well (every pixel's centre covered). */
static void test_one_call_per_quad(void **state_)
{
    (void)state_;
    for (int samples = 1; samples <= 4; samples += 3) {
        rs_vertex v[3] = {vtx(-1, -1, 0.5f, 1.0f, (rs_vec4){0, 0, 0, 1}), vtx(3 * W, -1, 0.5f, 2.0f, (rs_vec4){1, 0, 0, 1}),
                          vtx(-1, 3 * H, 0.5f, 0.5f, (rs_vec4){0, 1, 0, 1})};
        rs_target rt;
        assert_int_equal(rs_target_init(&rt, W, H, samples), RS_OK);
        rs_target_clear(&rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, CLEAR, 1.0f);
        rs_state st = state();
        st.multisample = samples > 1;
        ps_count c = {0, 0};
        st.ps = ps_counting, st.ps_ctx = &c;
        rs_context *rs = rs_create(1);
        assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_OK);
        rs_destroy(rs);
        assert_int_equal(c.calls, (W / 2) * (H / 2));
        assert_int_equal(c.lanes, W * H);
        rs_target_free(&rt);
    }
}

/* oC0 = (the quad's live mask, its need mask, the lane) / 255. */
static void ps_masks(const void *ctx, const rs_ps_quad *q, rs_ps_out *o)
{
    (void)ctx;
    for (int k = 0; k < 4; k++)
        o->color[k] = (rs_vec4){(float)q->live / 255.0f, (float)q->need / 255.0f, (float)k / 255.0f, 1};
}

/* Draw triangle v[0..2] of the scene with ps_masks on a fresh target of `samples` samples (1 thread). */
static void draw_masks(rs_target *rt, int samples)
{
    rs_vertex v[9];
    scene(v);
    assert_int_equal(rs_target_init(rt, W, H, samples), RS_OK);
    rs_target_clear(rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, CLEAR, 1.0f);
    rs_state st = state();
    st.multisample = samples > 1;
    st.ps = ps_masks;
    rs_context *rs = rs_create(1);
    assert_int_equal(rs_draw(rs, &st, rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_OK);
    rs_destroy(rs);
}

/* live is the quad's lanes whose centre the triangle covers, helper lanes included: on one sample the written
 * pixels of the quad; on four samples those plus the shaded pixel (covered by a sample, maybe not at its centre).
 * The lane written is the pixel's, and need holds it. */
static void test_live_lanes(void **state_)
{
    (void)state_;
    rs_target one, four;
    draw_masks(&one, 1);
    draw_masks(&four, 4);
    int partial = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            unsigned centres = 0, lane = (unsigned)((x & 1) + 2 * (y & 1));
            for (unsigned l = 0; l < 4; l++) {
                int px = (x & ~1) + (int)(l & 1), py = (y & ~1) + (int)(l >> 1);
                centres |= (unsigned)(one.color[py * W + px] != CLEAR) << l;
            }
            uint32_t c1 = one.color[y * W + x];
            if (c1 != CLEAR) {
                assert_int_equal(c1 & 0xffu, centres);
                assert_int_equal((c1 >> 16) & 0xffu, lane);
                assert_true((c1 >> 8) & (1u << lane));
                partial += centres != 0xfu;
            }
            for (int s = 0; s < 4; s++) {
                uint32_t c4 = four.color[(size_t)(y * W + x) * 4 + (size_t)s];
                if (c4 == CLEAR) continue;
                assert_int_equal(c4 & 0xffu, centres | 1u << lane);
                assert_int_equal((c4 >> 16) & 0xffu, lane);
            }
        }
    assert_true(partial > 10);   /* edge quads with helper lanes seen */
    rs_target_free(&one);
    rs_target_free(&four);
}

/* oC0 = (-0.5, 1.5, NaN, 0.5) in lane 0, (0.25, -inf, +inf, 0.999) in the others. */
static void ps_out_of_range(const void *ctx, const rs_ps_quad *q, rs_ps_out *o)
{
    (void)ctx, (void)q;
    o->color[0] = (rs_vec4){-0.5f, 1.5f, NAN, 0.5f};
    for (int k = 1; k < 4; k++) o->color[k] = (rs_vec4){0.25f, -INFINITY, INFINITY, 0.999f};
}

/* The shader's colour is saturated (NaN as 0) and rounded to 8 bits as the fixed path's: 0.5 -> 128, 0.25 -> 64,
 * 0.999 -> 255. */
static void test_output_saturated(void **state_)
{
    (void)state_;
    rs_state st = state();
    st.ps = ps_out_of_range;
    rs_target rt;
    draw(&rt, &st, 1, false, RS_ISA_AVX2, RS_PRIM_TRIANGLES);
    int seen[2] = {0, 0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint32_t c = rt.color[y * W + x];
            if (c == CLEAR) continue;
            bool lane0 = (x & 1) == 0 && (y & 1) == 0;
            assert_int_equal(c, lane0 ? 0x8000ff00u : 0xffff0040u);
            seen[lane0]++;
        }
    assert_true(seen[0] > 20 && seen[1] > 20);
    rs_target_free(&rt);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_inputs_are_the_fixed_interpolation),
        cmocka_unit_test(test_vpos_vface),
        cmocka_unit_test(test_derivatives),
        cmocka_unit_test(test_kill_and_depth),
        cmocka_unit_test(test_stride_grows),
        cmocka_unit_test(test_one_call_per_quad),
        cmocka_unit_test(test_live_lanes),
        cmocka_unit_test(test_output_saturated),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
