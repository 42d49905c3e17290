/* tests/test_api_raster.c -- every public function of raster/raster.h with NULL contexts, targets and states,
 * targets whose fields do not match (no depth plane, more AOV planes than exist, sizes beyond the limit),
 * render states and viewports out of range, primitive types that do not exist, counts that overflow, indices
 * past the vertices, and draw sources whose producer returns pieces that break their promise (more vertices than
 * max_verts, indices past its vertices, no vertices).  Each call returns RS_EINVAL / RS_ENOMEM / RS_EWORK or
 * draws, and never reads or writes outside the arrays it was given (ASan in the sanitizer stage).
 * tests/check_api_walkers.sh checks that every INSTESS_API function of raster/raster.h is named in this file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../raster/raster.h"

enum { W = 32, H = 24 };

static rs_state default_state(void)
{
    rs_state st = {.cull_mode = RS_CULL_NONE, .fill_mode = RS_FILL_SOLID, .shade_mode = RS_SHADE_GOURAUD,
                   .z_enable = true, .z_write = true, .z_func = RS_CMP_LESSEQUAL, .src_blend = RS_BLEND_ONE,
                   .dst_blend = RS_BLEND_ZERO, .attr_mask = 1u << RS_ATTR_COLOR0,
                   .viewport = {0, 0, W, H, 0.0f, 1.0f}};
    return st;
}

/* A triangle covering the middle of the target. */
static void triangle(rs_vertex v[3])
{
    memset(v, 0, 3 * sizeof *v);
    v[0].pos = (rs_vec4){-0.5f, -0.5f, 0.5f, 1}, v[1].pos = (rs_vec4){0, 0.5f, 0.5f, 1};
    v[2].pos = (rs_vec4){0.5f, -0.5f, 0.5f, 1};
    for (int k = 0; k < 3; k++) v[k].attr[RS_ATTR_COLOR0] = (rs_vec4){1, 1, 1, 1};
}

/* NULL everywhere: errors, no crash. */
static void test_null(void **state)
{
    (void)state;
    rs_destroy(NULL);
    rs_set_threads(NULL, 4);
    rs_set_reference_path(NULL, true);
    rs_set_timing(NULL, true);
    rs_set_scene(NULL, NULL);
    rs_flush(NULL);
    assert_true(rs_threads(NULL) >= 1);
    assert_int_equal(rs_set_isa(NULL, RS_ISA_AVX2), RS_EINVAL);
    (void)rs_isa(NULL);
    assert_int_equal(rs_max_pieces(NULL), 0);
    assert_int_equal(rs_target_init(NULL, 4, 4, 1), RS_EINVAL);
    rs_target_free(NULL);
    assert_int_equal(rs_target_add_aov(NULL, RS_ATTR_TEXCOORD0, 3), RS_EINVAL);
    rs_target_clear(NULL, RS_CLEAR_COLOR, 0, 1.0f);
    rs_target_clear_rect(NULL, 0, 0, 1, 1, RS_CLEAR_COLOR, 0, 1.0f);
    rs_target_clear_deferred(NULL, NULL, RS_CLEAR_COLOR, 0, 1.0f);
    rs_target_flush(NULL, NULL);
    rs_target_flush_planes(NULL, NULL, RS_CLEAR_COLOR);
    rs_target_resolve(NULL, NULL);
    assert_int_equal(rs_isa_parse(NULL), -1);
    assert_int_equal(rs_isa_parse("no-such-isa"), -1);
    assert_null(rs_isa_name(-1));
    assert_null(rs_isa_name(RS_ISA_COUNT));
    assert_null(rs_isa_name(INT_MAX));
    assert_true(rs_isa_supported(RS_ISA_AVX2));
    assert_false(rs_isa_supported(-1));
    assert_false(rs_isa_supported(INT_MAX));
    assert_true(rs_isa_supported(rs_isa_best()));
    rs_stats s;
    rs_vertex v[3];
    triangle(v);
    rs_state st = default_state();
    rs_context *rs = rs_create(1);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    assert_int_equal(rs_draw(NULL, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, NULL, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, &st, NULL, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, NULL, 3, NULL, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_OK);   /* no counters */
    assert_int_equal(rs_draw_source(NULL, &st, &rt, NULL, &s), RS_EINVAL);
    assert_int_equal(rs_draw_source(rs, &st, &rt, NULL, &s), RS_EINVAL);
    rs_source nofn = {.n_pieces = 1, .n_prims = 1, .max_verts = 3};
    assert_int_equal(rs_draw_source(rs, &st, &rt, &nofn, &s), RS_EINVAL);
    rs_target_resolve(&rt, NULL);
    rs_stats sink = {0};   /* the scene: a queued draw of a refused source, then a destroy with a draw queued */
    rs_set_scene(rs, &sink);
    rs_flush(rs);
    rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0, 1.0f);
    assert_int_equal(rs_draw_source(rs, &st, &rt, &nofn, &s), RS_EINVAL);
    rs_flush(rs);
    assert_int_equal(sink.samples_tested, 0u);
    rs_target_free(&rt);
    rs_target_free(&rt);   /* twice: a zeroed target */
    rs_destroy(rs);
}

/* Targets: sizes out of range, sample counts that do not exist, AOV planes beyond the limit or on 4 samples;
 * hand-made targets whose fields do not match their planes. */
static void test_targets(void **state)
{
    (void)state;
    rs_target rt;
    const int bad[][3] = {{0, 1, 1}, {1, 0, 1}, {-1, 5, 1}, {RS_MAX_SIZE + 1, 1, 1}, {INT_MAX, INT_MAX, 4},
                          {4, 4, 0}, {4, 4, 2}, {4, 4, -1}, {INT_MIN, 4, 1}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        assert_int_equal(rs_target_init(&rt, bad[k][0], bad[k][1], bad[k][2]), RS_EINVAL);
        assert_null(rt.color);
        rs_target_free(&rt);
    }
    assert_int_equal(rs_target_init(&rt, 4, 4, 4), RS_OK);
    assert_int_equal(rs_target_add_aov(&rt, RS_ATTR_TEXCOORD0, 3), RS_EINVAL);   /* 4 samples: no AOV */
    rs_target_free(&rt);
    assert_int_equal(rs_target_init(&rt, 4, 4, 1), RS_OK);
    const int aov_bad[][2] = {{-1, 3}, {RS_MAX_ATTR, 3}, {RS_ATTR_TEXCOORD0, 0}, {RS_ATTR_TEXCOORD0, 5},
                              {INT_MAX, INT_MAX}};
    for (size_t k = 0; k < sizeof aov_bad / sizeof aov_bad[0]; k++)
        assert_int_equal(rs_target_add_aov(&rt, aov_bad[k][0], aov_bad[k][1]), RS_EINVAL);
    for (int k = 0; k < RS_MAX_AOV; k++) assert_int_equal(rs_target_add_aov(&rt, RS_ATTR_TEXCOORD0, 1), RS_OK);
    assert_int_equal(rs_target_add_aov(&rt, RS_ATTR_TEXCOORD0, 1), RS_EINVAL);   /* full */
    /* clears of rectangles outside, reversed, at the int limits */
    rs_target_clear_rect(&rt, INT_MIN, INT_MIN, INT_MAX, INT_MAX, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 1, 0.5f);
    rs_target_clear_rect(&rt, 3, 3, 1, 1, RS_CLEAR_COLOR, 1, 0.5f);
    rs_target_clear_rect(&rt, 100, 100, 200, 200, RS_CLEAR_COLOR, 1, 0.5f);
    rs_target_clear(&rt, 0xffffffffu, 7, NAN);
    uint32_t out[16];
    rs_target_resolve(&rt, out);
    rs_target_free(&rt);
    /* hand-made targets that lie about themselves: no depth plane, n_aov beyond RS_MAX_AOV or negative, an AOV
     * without data, a width the planes do not have a side for */
    uint32_t color[16] = {0};
    float depth[16] = {0};
    rs_context *rs = rs_create(1);
    rs_state st = default_state();
    st.viewport = (rs_viewport){0, 0, 4, 4, 0, 1};
    rs_vertex v[3];
    triangle(v);
    rs_target lies[] = {
        {.width = 4, .height = 4, .samples = 1, .color = color, .depth = NULL},
        {.width = 4, .height = 4, .samples = 1, .color = NULL, .depth = depth},
        {.width = 4, .height = 4, .samples = 1, .color = color, .depth = depth, .n_aov = RS_MAX_AOV + 5},
        {.width = 4, .height = 4, .samples = 1, .color = color, .depth = depth, .n_aov = -3},
        {.width = 4, .height = 4, .samples = 1, .color = color, .depth = depth, .n_aov = 1,
         .aov = {{RS_ATTR_TEXCOORD0, 3, NULL}}},
        {.width = 4, .height = 4, .samples = 3, .color = color, .depth = depth},
        {.width = 0, .height = 4, .samples = 1, .color = color, .depth = depth},
        {.width = -4, .height = -4, .samples = 1, .color = color, .depth = depth},
    };
    for (size_t k = 0; k < sizeof lies / sizeof lies[0]; k++) {
        rs_target *t = &lies[k];
        rs_target_clear(t, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0, 1.0f);
        rs_target_clear_rect(t, 0, 0, 4, 4, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0, 1.0f);
        rs_target_resolve(t, out);
        rs_target_clear_deferred(rs, t, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0, 1.0f);
        rs_target_flush_planes(rs, t, RS_CLEAR_COLOR);
        rs_target_flush(rs, t);
        assert_int_equal(rs_target_add_aov(t, RS_ATTR_TEXCOORD0, 1), RS_EINVAL);   /* none of them is a target */
        assert_int_equal(rs_draw(rs, &st, t, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
        assert_int_equal(rs_max_pieces(t), 0);
    }
    rs_destroy(rs);
}

/* States and viewports out of range, primitive types that do not exist, counts that overflow, indices past the
 * vertices: RS_EINVAL and nothing drawn. */
static void test_draw_args(void **state)
{
    (void)state;
    rs_context *rs = rs_create(2);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 4), RS_OK);
    rs_vertex v[3];
    triangle(v);
    rs_stats s;
    rs_state good = default_state();
    rs_state bad[16];
    int n = 0;
    bad[n] = good, bad[n++].cull_mode = 0;
    bad[n] = good, bad[n++].fill_mode = 99;
    bad[n] = good, bad[n++].shade_mode = -1;
    bad[n] = good, bad[n++].z_func = 0;
    bad[n] = good, bad[n].blend_enable = true, bad[n++].src_blend = 77;
    bad[n] = good, bad[n++].depth_bias = NAN;
    bad[n] = good, bad[n++].slope_scale_depth_bias = INFINITY;
    bad[n] = good, bad[n++].viewport = (rs_viewport){-1, 0, W, H, 0, 1};
    bad[n] = good, bad[n++].viewport = (rs_viewport){1, 0, W, H, 0, 1};
    bad[n] = good, bad[n++].viewport = (rs_viewport){0, 0, 0, H, 0, 1};
    bad[n] = good, bad[n++].viewport = (rs_viewport){INT_MAX, 0, INT_MAX, H, 0, 1};
    bad[n] = good, bad[n++].viewport = (rs_viewport){0, 0, W, H, NAN, 1};
    for (int k = 0; k < n; k++)
        assert_int_equal(rs_draw(rs, &bad[k], &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_EINVAL);
    /* attributes masks with bits beyond the slots are ignored */
    rs_state wide = good;
    wide.attr_mask = 0xffffffffu;
    assert_int_equal(rs_draw(rs, &wide, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_OK);
    const int prims[] = {0, 3, 5, -1, INT_MAX};
    for (size_t k = 0; k < sizeof prims / sizeof prims[0]; k++)
        assert_int_equal(rs_draw(rs, &good, &rt, prims[k], v, 3, NULL, 1, &s), RS_EINVAL);
    const size_t counts[] = {2, SIZE_MAX, SIZE_MAX / 3 + 1, SIZE_MAX / sizeof(rs_vertex)};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
        assert_int_equal(rs_draw(rs, &good, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, counts[k], &s), RS_EINVAL);
        assert_int_equal(rs_draw(rs, &good, &rt, RS_PRIM_LINES, v, 3, NULL, counts[k], &s), RS_EINVAL);
        assert_int_equal(rs_draw(rs, &good, &rt, RS_PRIM_POINTS, v, 3, NULL, counts[k] == 2 ? 4 : counts[k], &s),
                         RS_EINVAL);
    }
    const uint32_t idx_bad[] = {0, 1, 3}, idx_max[] = {0, UINT32_MAX, 1};
    assert_int_equal(rs_draw(rs, &good, &rt, RS_PRIM_TRIANGLES, v, 3, idx_bad, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, &good, &rt, RS_PRIM_TRIANGLES, v, 3, idx_max, 1, &s), RS_EINVAL);
    assert_int_equal(rs_draw(rs, &good, &rt, RS_PRIM_TRIANGLES, v, 0, NULL, 0, &s), RS_OK);   /* nothing */
    /* non-finite positions and attributes: dropped, not errors */
    rs_vertex nf[3];
    triangle(nf);
    nf[1].pos.x = NAN, nf[2].pos.w = INFINITY, nf[0].attr[RS_ATTR_COLOR0].x = NAN;
    assert_int_equal(rs_draw(rs, &good, &rt, RS_PRIM_TRIANGLES, nf, 3, NULL, 1, &s), RS_OK);
    triangle(nf);
    nf[0].attr[RS_ATTR_COLOR0] = (rs_vec4){NAN, INFINITY, -INFINITY, 1e30f};
    assert_int_equal(rs_draw(rs, &good, &rt, RS_PRIM_TRIANGLES, nf, 3, NULL, 1, &s), RS_OK);
    nf[0].pos = (rs_vec4){FLT_MAX, -FLT_MAX, FLT_MAX, 1e-38f};
    for (int p = RS_PRIM_POINTS; p <= RS_PRIM_TRIANGLES; p *= 2)
        assert_int_equal(rs_draw(rs, &good, &rt, p, nf, 3, NULL, p == RS_PRIM_POINTS ? 3 : 1, &s), RS_OK);
    rs_set_threads(rs, -5);
    rs_set_threads(rs, INT_MAX);
    assert_true(rs_threads(rs) >= 1);
    rs_set_threads(rs, 1);
    rs_set_reference_path(rs, true);
    rs_set_timing(rs, true);
    assert_int_equal(rs_draw(rs, &good, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s), RS_OK);
    assert_int_equal(rs_set_isa(rs, -1), RS_EINVAL);
    assert_int_equal(rs_set_isa(rs, RS_ISA_COUNT), RS_EINVAL);
    assert_int_equal(rs_isa_parse(rs_isa_name(rs_isa(rs))), rs_isa(rs));
    rs_target_free(&rt);
    rs_destroy(rs);
}

/* A draw source whose producer breaks its promise in the way its ctx says. */
typedef enum { P_GOOD, P_BAD_INDEX, P_NO_VERTS, P_TOO_MANY_VERTS, P_TOO_MANY_PRIMS, P_NO_INDICES } producer_kind;
typedef struct producer {
    producer_kind kind;
    int bad_at;         /* P_BAD_INDEX: the index past the vertices */
    size_t prims;       /* triangles of each piece (0: 1) */
    rs_vertex v[2][8];
    uint32_t idx[2][12];
} producer;

static size_t produce(void *ctx, size_t piece, int slot, rs_vertex **verts, size_t *n_verts, const uint32_t **idx)
{
    producer *p = ctx;
    (void)piece;
    int s = slot & 1;
    triangle(p->v[s]);
    for (int k = 0; k < 12; k++) p->idx[s][k] = (uint32_t)(k % 3);
    *verts = p->v[s], *n_verts = 3, *idx = p->idx[s];
    switch (p->kind) {
    case P_GOOD: return p->prims ? p->prims : 1;
    case P_BAD_INDEX: p->idx[s][p->bad_at] = 1000000; return p->prims ? p->prims : 1;
    case P_NO_VERTS: *verts = NULL, *n_verts = 0; return 1;
    case P_TOO_MANY_VERTS: *n_verts = 8; return 1;   /* more than the source's max_verts (3) */
    case P_TOO_MANY_PRIMS: return 4;                  /* more than its n_prims over all pieces */
    case P_NO_INDICES: *idx = NULL; return 1;
    }
    return 0;
}

static void test_draw_source(void **state)
{
    (void)state;
    rs_context *rs = rs_create(2);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_state st = default_state();
    rs_stats s;
    for (int kind = P_GOOD; kind <= P_NO_INDICES; kind++) {
        producer p = {.kind = (producer_kind)kind, .bad_at = 2};
        rs_source src = {.n_pieces = 2, .n_prims = 2, .max_verts = 3, .produce = produce, .ctx = &p};
        int r = rs_draw_source(rs, &st, &rt, &src, &s);
        if (kind == P_GOOD) assert_int_equal(r, RS_OK);
        else assert_int_equal(r, RS_EINVAL);
    }
    for (int at = -1; at < 12; at++) {   /* pieces of 4 triangles: a bad index at any of the 12 places */
        producer q = {.kind = at < 0 ? P_GOOD : P_BAD_INDEX, .bad_at = at, .prims = 4};
        rs_source src = {.n_pieces = 2, .n_prims = 8, .max_verts = 3, .produce = produce, .ctx = &q};
        assert_int_equal(rs_draw_source(rs, &st, &rt, &src, &s), at < 0 ? RS_OK : RS_EINVAL);
    }
    producer p = {.kind = P_GOOD};
    rs_source many = {.n_pieces = SIZE_MAX, .n_prims = 1, .max_verts = 3, .produce = produce, .ctx = &p};
    assert_int_equal(rs_draw_source(rs, &st, &rt, &many, &s), RS_EINVAL);
    rs_source huge = {.n_pieces = 1, .n_prims = 1, .max_verts = SIZE_MAX, .produce = produce, .ctx = &p};
    assert_int_equal(rs_draw_source(rs, &st, &rt, &huge, &s), RS_ENOMEM);
    rs_source none = {.n_pieces = 0, .n_prims = 0, .max_verts = 0, .produce = produce, .ctx = &p};
    assert_int_equal(rs_draw_source(rs, &st, &rt, &none, &s), RS_OK);
    /* recorded (the scene, a frame): the promises are checked at the flush, the error kept for rs_scene_error and
     * the draw dropped whole (nothing of it in the sink) */
    assert_int_equal(rs_scene_error(NULL), RS_OK);
    rs_stats sink = {0};
    rs_set_scene(rs, &sink);
    for (int kind = P_GOOD; kind <= P_NO_INDICES; kind++) {
        rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0, 1.0f);
        memset(&sink, 0, sizeof sink);
        producer q = {.kind = (producer_kind)kind};
        rs_source src = {.n_pieces = 2, .n_prims = 2, .max_verts = 3, .produce = produce, .ctx = &q};
        assert_int_equal(rs_draw_source(rs, &st, &rt, &src, &s), RS_OK);
        assert_int_equal(s.prims_in, 0u);   /* its counters come with the flush */
        rs_flush(rs);
        assert_int_equal(rs_scene_error(rs), kind == P_GOOD ? RS_OK : RS_EINVAL);
        assert_int_equal(rs_scene_error(rs), RS_OK);   /* forgotten once read */
        assert_int_equal(sink.prims_in, kind == P_GOOD ? 2u : 0u);
    }
    rs_set_scene(rs, NULL);
    rs_target_free(&rt);
    rs_destroy(rs);
}

/* rs_target_clear_stencil: NULL, a target without a stencil plane (hand-made), rectangles outside, reversed and
 * at the int limits, values beyond 8 bits (their low byte); and the states of raster/pixel.c out of range (alpha
 * and stencil functions, stencil operations, clip planes not finite): RS_EINVAL when on, unread when off. */
static void test_stencil_and_pixel_states(void **state)
{
    (void)state;
    rs_target_clear_stencil(NULL, 0, 0, 1, 1, 1);
    uint32_t color[16] = {0};
    float depth[16] = {0};
    rs_target hand = {.width = 4, .height = 4, .samples = 1, .color = color, .depth = depth};
    rs_target_clear_stencil(&hand, 0, 0, 4, 4, 1);   /* no plane: nothing */
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 4, 4, 4), RS_OK);
    rs_target_clear_stencil(&rt, INT_MIN, INT_MIN, INT_MAX, INT_MAX, 0x1234);
    for (int k = 0; k < 64; k++) assert_int_equal(rt.stencil[k], 0x34);
    rs_target_clear_stencil(&rt, 3, 3, 1, 1, 0);
    rs_target_clear_stencil(&rt, 100, 100, 200, 200, 0);
    rs_target_clear_stencil(&rt, 1, 1, 2, 2, UINT32_MAX);
    assert_int_equal(rt.stencil[(1 * 4 + 1) * 4 + 3], 0xff);
    assert_int_equal(rt.stencil[0], 0x34);
    rs_context *rs = rs_create(1);
    rs_vertex v[3];
    triangle(v);
    rs_state st = default_state();
    st.viewport = (rs_viewport){0, 0, 4, 4, 0, 1};
    st.scissor_enable = true;
    st.scissor = (rs_rect){INT_MIN, INT_MIN, INT_MAX, INT_MAX};
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_OK);
    st.scissor = (rs_rect){INT_MAX, INT_MAX, INT_MIN, INT_MIN};
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_OK);
    const int bad[] = {0, -1, 9, INT_MAX, INT_MIN};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        rs_state a = default_state();
        a.viewport = st.viewport;
        a.alpha_test = true, a.alpha_func = bad[k];
        assert_int_equal(rs_draw(rs, &a, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
        rs_state s = default_state();
        s.viewport = st.viewport;
        s.stencil_enable = true;
        s.stencil_cw = (rs_stencil_ops){RS_CMP_ALWAYS, RS_STENCILOP_KEEP, bad[k], RS_STENCILOP_KEEP};
        assert_int_equal(rs_draw(rs, &s, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
        s.stencil_cw.zfail = RS_STENCILOP_KEEP;
        s.stencil_two_sided = true;
        s.stencil_ccw = (rs_stencil_ops){bad[k], RS_STENCILOP_KEEP, RS_STENCILOP_KEEP, RS_STENCILOP_KEEP};
        assert_int_equal(rs_draw(rs, &s, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    }
    rs_state c = default_state();
    c.viewport = st.viewport;
    c.clip_plane_enable = 1u << 5;
    c.clip_plane[5][2] = INFINITY;
    assert_int_equal(rs_draw(rs, &c, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_EINVAL);
    c.clip_plane_enable = ~(1u << 5) & 0x3fu;   /* the others (zero planes: everything inside) */
    assert_int_equal(rs_draw(rs, &c, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_OK);
    rs_destroy(rs);
    rs_target_free(&rt);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_null),
        cmocka_unit_test(test_targets),
        cmocka_unit_test(test_draw_args),
        cmocka_unit_test(test_draw_source),
        cmocka_unit_test(test_stencil_and_pixel_states),
    };
    return cmocka_run_group_tests_name("api_raster", tests, NULL, NULL);
}
