/* tests/test_raster_stamps.c -- span.c's stamp walk (walk_band, walk_bands, stamp_pass): the triangles whose box in
 * a tile is at most 8 pixels wide, drawn in a plain mode (no blending, no AOV planes), have their coverage found
 * first and their covered pixels packed into the lanes.  Every triangle here has such a box (they are made in pixel
 * units, at most 7.5 pixels wide; some up to 30 rows tall, so that boxes take two bands and more than 8 covered
 * pixels take a second pass), placed around multiples of 64 (tile borders among them) and the target's right and bottom
 * edges (widths and heights that are not multiples of 4, 8 or 64), with every depth function, depth writes on and off
 * and depth off; they are drawn with a deferred clear (the tile buffers) and with an immediate one (the target's
 * planes), on 1 and 2 threads, with each instruction set the CPU has; and a deferred clear of one plane only (the
 * tile buffer takes the other from the target).  Every byte of colour and depth and every counter must equal the
 * reference path's.  Deterministic: a fixed xorshift seed. */
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

/* n triangles in a w x h target, each inside a box at most 7.5 pixels wide (tall ones up to 30 rows), in clip
 * space (viewport = the whole target), with random depth, w and colours. */
static rs_vertex *small_triangles(uint64_t *s, int n, int w, int h)
{
    rs_vertex *v = calloc((size_t)n * 3, sizeof *v);
    assert_non_null(v);
    for (int i = 0; i < n; i++) {
        float cx = test_near_edge(s, w, -6.0f, 6.0f), cy = test_near_edge(s, h, -6.0f, 6.0f);
        float bw = test_rnd(s) % 2 ? test_frnd(s, 0.3f, 3.5f) : test_frnd(s, 3.5f, 7.5f);
        float bh = test_rnd(s) % 5 == 0 ? test_frnd(s, 8.0f, 30.0f) : test_frnd(s, 0.3f, 7.5f);
        for (int k = 0; k < 3; k++) {
            rs_vertex *q = &v[3 * i + k];
            float px = cx + test_frnd(s, 0.0f, bw), py = cy + test_frnd(s, 0.0f, bh);
            float wv = test_rnd(s) % 3 == 0 ? test_frnd(s, 0.5f, 2.0f) : 1.0f;
            q->pos = (rs_vec4){(px / (float)w * 2.0f - 1.0f) * wv, (1.0f - py / (float)h * 2.0f) * wv,
                               test_frnd(s, 0.0f, 1.0f) * wv, wv};
            q->attr[RS_ATTR_COLOR0] =
                (rs_vec4){test_frnd(s, -0.2f, 1.2f), test_frnd(s, -0.2f, 1.2f), test_frnd(s, -0.2f, 1.2f),
                          test_rnd(s) % 2 ? 1.0f : test_frnd(s, 0.0f, 1.0f)};
        }
    }
    return v;
}

/* One target size: every depth state, deferred and immediate clear, 1 and 2 threads, each instruction set, the
 * fast path's bytes and counters against the reference path's. */
static void one_size(uint64_t *s, int w, int h)
{
    const int n = 1500;
    for (int zc = 0; zc < 2 + RS_CMP_ALWAYS; zc++) { /* 0: depth off, 1: no writes (LESSEQUAL), then each function */
        rs_state st;
        memset(&st, 0, sizeof st);
        st.cull_mode = RS_CULL_NONE, st.fill_mode = RS_FILL_SOLID, st.shade_mode = RS_SHADE_GOURAUD;
        st.attr_mask = 1u << RS_ATTR_COLOR0;
        st.z_enable = zc != 0, st.z_write = zc != 1;
        st.z_func = zc < 2 ? RS_CMP_LESSEQUAL : zc - 1;
        st.viewport = (rs_viewport){0, 0, w, h, 0.0f, 1.0f};
        const float clear_z = st.z_func == RS_CMP_GREATER || st.z_func == RS_CMP_GREATEREQUAL ? 0.0f : 0.6f;
        rs_vertex *v = small_triangles(s, n, w, h);
        char what[96];
        snprintf(what, sizeof what, "%dx%d, depth %d/%d/%d", w, h, st.z_enable, st.z_func, st.z_write);
        test_rs_paths_agree(w, h, &st, v, n, clear_z, 500, what);
        free(v);
    }
}

/* Target sizes whose width and height are not multiples of 4, 8 or 64 (and one that is), so that boxes meet the
 * tile borders and the right and bottom edges at every offset. */
static void test_stamps_same_bytes(void **state)
{
    (void)state;
    uint64_t s = 0x5eed5eedull;
    const int sizes[][2] = {{67, 61}, {130, 131}, {197, 70}, {128, 128}, {9, 203}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) one_size(&s, sizes[i][0], sizes[i][1]);
}

/* A deferred clear of one plane (the tile buffer takes the other from the target, target.c's
 * rs_tile_buffer_begin) against the same immediate clear on the reference path, at a width and height that are
 * not multiples of 64. */
static void test_partial_deferred_clear(void **state)
{
    (void)state;
    uint64_t s = 0xc1ea7ull;
    const int w = 150, h = 77, n = 1500;
    rs_state st;
    memset(&st, 0, sizeof st);
    st.cull_mode = RS_CULL_NONE, st.fill_mode = RS_FILL_SOLID, st.shade_mode = RS_SHADE_GOURAUD;
    st.attr_mask = 1u << RS_ATTR_COLOR0;
    st.z_enable = st.z_write = true, st.z_func = RS_CMP_LESSEQUAL;
    st.viewport = (rs_viewport){0, 0, w, h, 0.0f, 1.0f};
    rs_vertex *v = small_triangles(&s, n, w, h);
    for (unsigned flags = RS_CLEAR_COLOR; flags <= RS_CLEAR_DEPTH; flags <<= 1) {
        rs_target rt[2];
        rs_stats stats[2][2];
        for (int k = 0; k < 2; k++) { /* k = 0: reference, immediate; 1: fast, deferred */
            assert_int_equal(rs_target_init(&rt[k], w, h, 1), RS_OK);
            test_rs_draw_twice(&rt[k], &st, v, n, k == 0, RS_ISA_AVX2, 2, k == 1, flags, 0.6f, stats[k]);
        }
        assert_memory_equal(rt[0].color, rt[1].color, (size_t)w * (size_t)h * 4);
        assert_memory_equal(rt[0].depth, rt[1].depth, (size_t)w * (size_t)h * 4);
        assert_memory_equal(&stats[0][1].samples_written, &stats[1][1].samples_written, sizeof(uint64_t));
        for (int k = 0; k < 2; k++) rs_target_free(&rt[k]);
    }
    free(v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stamps_same_bytes),
        cmocka_unit_test(test_partial_deferred_clear),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
