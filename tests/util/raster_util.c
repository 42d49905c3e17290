/* tests/util/raster_util.c -- rasterizer states shared by the raster tests. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "raster_util.h"
#include "../../core/core.h"

#include <stdlib.h>
#include <string.h>

rs_state test_rs_defaults(int w, int h)
{
    rs_state st;
    memset(&st, 0, sizeof st);
    st.cull_mode = RS_CULL_CCW;
    st.fill_mode = RS_FILL_SOLID;
    st.shade_mode = RS_SHADE_GOURAUD;
    st.z_enable = true;
    st.z_write = true;
    st.z_func = RS_CMP_LESSEQUAL;
    st.src_blend = RS_BLEND_ONE;
    st.dst_blend = RS_BLEND_ZERO;
    st.multisample = true;
    st.attr_mask = 1u << RS_ATTR_COLOR0;
    st.viewport = (rs_viewport){0, 0, w, h, 0.0f, 1.0f};
    return st;
}

rs_state test_rs_additive(int w, int h)
{
    rs_state st = test_rs_defaults(w, h);
    st.cull_mode = RS_CULL_NONE;
    st.z_enable = false;
    st.z_write = false;
    st.blend_enable = true;
    st.dst_blend = RS_BLEND_ONE;
    return st;
}

void test_rs_stats_add(rs_stats *sum, const rs_stats *s)
{
    sum->prims_in += s->prims_in, sum->prims_culled += s->prims_culled, sum->prims_drawn += s->prims_drawn;
    sum->prims_clipped_away += s->prims_clipped_away, sum->prims_degenerate += s->prims_degenerate;
    sum->samples_tested += s->samples_tested, sum->samples_written += s->samples_written;
}

void test_rs_frame_end(rs_context *rs, rs_target *rt, const rs_stats *sink, rs_stats *sum, uint32_t *color,
                       float *depth, size_t n)
{
    rs_flush(rs);
    test_rs_stats_add(sum, sink);
    rs_target_flush(rs, rt);
    memcpy(color, rt->color, n * sizeof *color);
    memcpy(depth, rt->depth, n * sizeof *depth);
    rs_target_free(rt);
    rs_destroy(rs);
}

void test_rs_same_frame(const uint32_t *color_a, const float *depth_a, const rs_stats *sum_a, const uint32_t *color_b,
                        const float *depth_b, const rs_stats *sum_b, size_t n)
{
    assert_memory_equal(color_a, color_b, n * sizeof *color_a);
    assert_memory_equal(depth_a, depth_b, n * sizeof *depth_a);
    assert_memory_equal(sum_a, sum_b, sizeof *sum_a);
}

uint32_t test_rnd(uint64_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return (uint32_t)(*s >> 11);
}

float test_frnd(uint64_t *s, float lo, float hi)
{
    return lo + (hi - lo) * (float)(test_rnd(s) & 0xffffff) / 16777216.0f;
}

float test_near_edge(uint64_t *s, int n, float lo, float hi)
{
    int k = (int)(test_rnd(s) % 3);
    float c = k == 0   ? (float)(64 * (int)(test_rnd(s) % (unsigned)(n / 64 + 1)))
              : k == 1 ? (float)n
                       : test_frnd(s, 0.0f, (float)n);
    return c + test_frnd(s, lo, hi);
}

void test_rs_draw_twice(rs_target *rt, const rs_state *st, const rs_vertex *v, int n, bool reference, int isa,
                        int threads, bool deferred, unsigned flags, float clear_z, rs_stats stats[2])
{
    rs_context *rs = rs_create(threads);
    assert_non_null(rs);
    rs_set_reference_path(rs, reference);
    if (!reference) assert_int_equal(rs_set_isa(rs, isa), RS_OK);
    rs_target_clear(rt, 3, 0x55667788u, 0.35f);
    if (deferred) rs_target_clear_deferred(rs, rt, flags, 0x11223344u, clear_z);
    else rs_target_clear(rt, flags, 0x11223344u, clear_z);
    for (int pass = 0; pass < 2; pass++)
        assert_int_equal(rs_draw(rs, st, rt, RS_PRIM_TRIANGLES, v, (size_t)n * 3, NULL, (size_t)n, &stats[pass]),
                         RS_OK);
    rs_target_flush(rs, rt);
    rs_destroy(rs);
}

void test_rs_paths_agree(int w, int h, const rs_state *st, const rs_vertex *v, int n, float clear_z,
                         uint64_t min_tested, const char *what)
{
    const unsigned both = RS_CLEAR_COLOR | RS_CLEAR_DEPTH;
    const size_t np = (size_t)w * (size_t)h;
    rs_target ref;
    rs_stats rst[2];
    assert_int_equal(rs_target_init(&ref, w, h, 1), RS_OK);
    test_rs_draw_twice(&ref, st, v, n, true, RS_ISA_AVX2, 1, false, both, clear_z, rst);
    if (rst[0].samples_tested <= min_tested)
        fail_msg("%s: only %llu samples tested", what, (unsigned long long)rst[0].samples_tested);
    for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
        if (!rs_isa_supported(isa)) continue;
        for (int k = 0; k < 4; k++) { /* deferred or not, 1 or 2 threads */
            rs_target rt;
            rs_stats fst[2];
            assert_int_equal(rs_target_init(&rt, w, h, 1), RS_OK);
            test_rs_draw_twice(&rt, st, v, n, false, isa, 1 + k / 2, k % 2 == 0, both, clear_z, fst);
            if (memcmp(ref.color, rt.color, np * 4) || memcmp(ref.depth, rt.depth, np * 4))
                fail_msg("%s, isa %d, %s clear, %d threads: colour or depth differ", what, isa,
                         k % 2 == 0 ? "deferred" : "immediate", 1 + k / 2);
            for (int pass = 0; pass < 2; pass++)
                if (rst[pass].samples_tested != fst[pass].samples_tested ||
                    rst[pass].samples_written != fst[pass].samples_written)
                    fail_msg("%s, isa %d, pass %d: samples tested %llu / %llu, written %llu / %llu", what, isa, pass,
                             (unsigned long long)rst[pass].samples_tested, (unsigned long long)fst[pass].samples_tested,
                             (unsigned long long)rst[pass].samples_written,
                             (unsigned long long)fst[pass].samples_written);
            rs_target_free(&rt);
        }
    }
    rs_target_free(&ref);
}

uint32_t *test_grid_instances(int L, size_t inst)
{
    const size_t points = core_grid_points(L), prims = core_grid_triangles(L);
    uint32_t *idx = malloc(3 * inst * prims * sizeof *idx);
    float3 *bary = malloc(points * sizeof *bary);
    assert_true(idx && bary);
    assert_int_equal(core_grid_regular(L, bary, idx), points);
    for (size_t k = 1; k < inst; k++)
        for (size_t t = 0; t < 3 * prims; t++) idx[k * 3 * prims + t] = idx[t] + (uint32_t)(k * points);
    free(bary);
    return idx;
}
