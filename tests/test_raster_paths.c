/* tests/test_raster_paths.c -- the rasterizer's fast paths (8-lane spans, small-triangle and block walks, the
 * shared vertex projection) against its scalar reference path on random draws: every byte of colour, depth and
 * AOV planes and every counter must agree.  The draws vary what the fast paths specialise on: triangle size (from
 * sub-pixel slivers to guard-band sized), w (perspective), depth function and writes, blending, flat shading,
 * AOV planes, a missing COLOR0, odd target widths, viewport offsets, an inverted depth range, 1 or 2 threads.
 * Each draw is made twice, so the depth tests see earlier writes.  Deterministic: a fixed xorshift seed. */
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

/* Random render states and viewport for a w x h target (no culling, solid fill). */
static rs_state random_state(uint64_t *s, int w, int h)
{
    rs_state st;
    memset(&st, 0, sizeof st);
    st.cull_mode = RS_CULL_NONE;
    st.fill_mode = RS_FILL_SOLID;
    st.shade_mode = test_rnd(s) % 8 == 0 ? RS_SHADE_FLAT : RS_SHADE_GOURAUD;
    int zc = (int)(test_rnd(s) % 4); /* 0: no depth, 1: LESSEQUAL, 2: LESS, 3: any function (the specialised ones) */
    st.z_enable = zc != 0;
    st.z_write = test_rnd(s) % 5 != 0;
    st.z_func = zc == 1 ? RS_CMP_LESSEQUAL : zc == 2 ? RS_CMP_LESS : 1 + (int)(test_rnd(s) % 8);
    st.blend_enable = test_rnd(s) % 6 == 0;
    st.src_blend = RS_BLEND_SRCALPHA, st.dst_blend = RS_BLEND_INVSRCALPHA;
    st.attr_mask = test_rnd(s) % 10 == 0 ? 0 : 0x3ffu;
    int vx = test_rnd(s) % 3 == 0 ? (int)(test_rnd(s) % (unsigned)(w > 1 ? w / 2 : 1)) : 0;
    int vy = test_rnd(s) % 3 == 0 ? (int)(test_rnd(s) % (unsigned)(h > 1 ? h / 2 : 1)) : 0;
    st.viewport.x = vx, st.viewport.y = vy;
    st.viewport.width = w - vx - (test_rnd(s) % 3 == 0 ? (int)(test_rnd(s) % (unsigned)(w - vx)) : 0);
    st.viewport.height = h - vy - (test_rnd(s) % 3 == 0 ? (int)(test_rnd(s) % (unsigned)(h - vy)) : 0);
    st.viewport.min_z = test_rnd(s) % 5 == 0 ? 0.7f : 0.0f;
    st.viewport.max_z = test_rnd(s) % 5 == 0 ? 0.3f : 1.0f;
    return st;
}

/* n random triangles (3n vertices) of one size class around random centres, some with w != 1 (deep: also w from
 * 0.002 to 60 in a quarter of the vertices: steep planes of 1/w). */
static rs_vertex *random_triangles(uint64_t *s, int n, bool deep)
{
    rs_vertex *v = calloc((size_t)n * 3, sizeof *v);
    assert_non_null(v);
    float scale = test_rnd(s) % 3 == 0 ? 0.02f : test_rnd(s) % 2 ? 0.3f : test_rnd(s) % 2 ? 3.0f : 80.0f;
    for (int i = 0; i < n; i++) {
        float cx = test_frnd(s, -1.2f, 1.2f), cy = test_frnd(s, -1.2f, 1.2f);
        for (int k = 0; k < 3; k++) {
            rs_vertex *q = &v[3 * i + k];
            float w = test_rnd(s) % 4 == 0 ? test_frnd(s, 0.2f, 3.0f) : 1.0f;
            if (deep && test_rnd(s) % 4 == 0) w = test_rnd(s) % 2 ? test_frnd(s, 0.002f, 0.05f) : test_frnd(s, 5.0f, 60.0f);
            q->pos = (rs_vec4){(cx + test_frnd(s, -scale, scale)) * w, (cy + test_frnd(s, -scale, scale)) * w,
                               test_frnd(s, -0.1f, 1.1f) * w, w};
            for (int a = 0; a < RS_MAX_ATTR; a++)
                q->attr[a] = (rs_vec4){test_frnd(s, -0.2f, 1.2f), test_frnd(s, -0.2f, 1.2f), test_frnd(s, -0.2f, 1.2f),
                                       test_rnd(s) % 2 ? 1.0f : test_frnd(s, 0.0f, 1.0f)};
        }
    }
    return v;
}

/* One random case on targets of `samples` (1 or 4) samples per pixel: the same draw (twice) on the reference and the
 * fast path; fails on any differing byte. */
static void one_case(uint64_t *s, int it, int samples)
{
    int w = 1 + (int)(test_rnd(s) % 300), h = 1 + (int)(test_rnd(s) % 300);
    if (test_rnd(s) % 4 == 0) w = 8 * (1 + (int)(test_rnd(s) % 40));
    int n_aov = samples == 1 && test_rnd(s) % 6 == 0 ? 1 + (int)(test_rnd(s) % 2) : 0;   /* (AOV planes: 1 sample only) */
    rs_target rt[2];
    for (int k = 0; k < 2; k++) {
        assert_int_equal(rs_target_init(&rt[k], w, h, samples), RS_OK);
        for (int q = 0; q < n_aov; q++)
            assert_int_equal(rs_target_add_aov(&rt[k], RS_ATTR_TEXCOORD0 + q, 1 + q), RS_OK);
    }
    rs_state st = random_state(s, w, h);
    int n = 1 + (int)(test_rnd(s) % 400), threads = 1 + (int)(test_rnd(s) % 2);
    rs_vertex *v = random_triangles(s, n, samples > 1);
    float clear_z = st.z_func == RS_CMP_GREATER || st.z_func == RS_CMP_GREATEREQUAL ? 0.0f : 1.0f;
    rs_stats stats[2];
    for (int k = 0; k < 2; k++) { /* k = 0: reference, 1: fast */
        rs_context *rs = rs_create(threads);
        assert_non_null(rs);
        rs_set_reference_path(rs, k == 0);
        rs_target_clear(&rt[k], 3, 0x11223344u, clear_z);
        for (int pass = 0; pass < 2; pass++)
            assert_int_equal(rs_draw(rs, &st, &rt[k], RS_PRIM_TRIANGLES, v, (size_t)n * 3, NULL, (size_t)n, &stats[k]),
                             RS_OK);
        rs_destroy(rs);
    }
    size_t np = (size_t)w * (size_t)h, ns = np * (size_t)samples;
    if (memcmp(rt[0].color, rt[1].color, ns * 4) || memcmp(rt[0].depth, rt[1].depth, ns * 4))
        fail_msg("case %d (%dx%d x %d samples, %d triangles, z %d/%d/%d, blend %d): colour or depth differ", it, w, h,
                 samples, n, st.z_enable, st.z_func, st.z_write, st.blend_enable);
    for (int q = 0; q < n_aov; q++)
        if (memcmp(rt[0].aov[q].data, rt[1].aov[q].data, np * sizeof(float) * (size_t)(1 + q)))
            fail_msg("case %d: AOV plane %d differs", it, q);
    assert_memory_equal(&stats[0], &stats[1], sizeof stats[0]);
    free(v);
    for (int k = 0; k < 2; k++) rs_target_free(&rt[k]);
}

/* 300 random draws, the fast path byte for byte equal to the reference. */
static void test_random_draws(void **state)
{
    (void)state;
    uint64_t s = 88172645463325252ull;
    for (int it = 0; it < 300; it++) one_case(&s, it, 1);
}

/* 200 random draws on 4-sample targets (tri.c's 4-sample walk against tri_tile_ref), some triangles deep in w.
 * (Not reached here, nor by test_reference_path: a depth outside the viewport's range after clipping, for the
 * clamp, and a pixel covered by a sample whose centre has a plane of 1/w not positive, which both walks shade
 * through the same tri_bary.) */
static void test_random_draws_msaa4(void **state)
{
    (void)state;
    uint64_t s = 0x9e3779b97f4a7c15ull;
    for (int it = 0; it < 200; it++) one_case(&s, it, 4);
}

/* The same with indexed draws whose vertices are shared (the shared projection pass of tessellated meshes):
 * a strip of tiny triangles, as a tessellated patch hands over. */
static void test_shared_vertices(void **state)
{
    (void)state;
    uint64_t s = 12345u;
    for (int it = 0; it < 40; it++) {
        int w = 64 + (int)(test_rnd(&s) % 200), h = 64 + (int)(test_rnd(&s) % 200), cols = 2 + (int)(test_rnd(&s) % 60);
        rs_state st = random_state(&s, w, h);
        st.cull_mode = test_rnd(&s) % 2 ? RS_CULL_CCW : RS_CULL_NONE;
        size_t nv = 2 * (size_t)cols, nt = 2 * (size_t)(cols - 1);
        rs_vertex *v = random_triangles(&s, cols, false); /* 3 * cols vertices: the first 2 * cols are used */
        float x0 = test_frnd(&s, -1.0f, 0.5f), y0 = test_frnd(&s, -1.0f, 0.8f), dx = test_frnd(&s, 0.001f, 0.05f);
        for (size_t i = 0; i < nv; i++) {
            float wv = v[i].pos.w;
            v[i].pos.x = (x0 + dx * (float)(i / 2) + test_frnd(&s, -0.3f, 0.3f) * dx) * wv;
            v[i].pos.y = (y0 + (i % 2 ? dx : 0.0f) + test_frnd(&s, -0.3f, 0.3f) * dx) * wv;
        }
        uint32_t *idx = malloc(3 * nt * sizeof *idx);
        assert_non_null(idx);
        for (size_t t = 0; t < nt; t++) {
            uint32_t a = (uint32_t)(t / 2) * 2;
            uint32_t tri[2][3] = {{a, a + 2, a + 1}, {a + 1, a + 2, a + 3}};
            memcpy(&idx[3 * t], tri[t % 2], sizeof tri[0]);
        }
        rs_target rt[2];
        rs_stats stats[2];
        for (int k = 0; k < 2; k++) {
            assert_int_equal(rs_target_init(&rt[k], w, h, 1), RS_OK);
            rs_context *rs = rs_create(1 + (int)(it % 2));
            rs_set_reference_path(rs, k == 0);
            rs_target_clear(&rt[k], 3, 0u,
                            st.z_func == RS_CMP_GREATER || st.z_func == RS_CMP_GREATEREQUAL ? 0.0f : 1.0f);
            assert_int_equal(rs_draw(rs, &st, &rt[k], RS_PRIM_TRIANGLES, v, nv, idx, nt, &stats[k]), RS_OK);
            rs_destroy(rs);
        }
        assert_memory_equal(rt[0].color, rt[1].color, (size_t)w * (size_t)h * 4);
        assert_memory_equal(rt[0].depth, rt[1].depth, (size_t)w * (size_t)h * 4);
        assert_memory_equal(&stats[0], &stats[1], sizeof stats[0]);
        free(v), free(idx);
        for (int k = 0; k < 2; k++) rs_target_free(&rt[k]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_draws),
        cmocka_unit_test(test_random_draws_msaa4),
        cmocka_unit_test(test_shared_vertices),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
