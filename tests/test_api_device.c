/* tests/test_api_device.c -- every public function of core/device.h called as a hostile or careless program
 * would: a NULL device, NULL pointers, zero and huge sizes, render states and primitive types that do not exist,
 * strides and offsets that do not match the buffers, draws without a shader, a declaration or buffers, or with
 * buffers too small, and handles of another device or already released.  Each call must return (an error where
 * D3D9 returns D3DERR_INVALIDCALL, changing nothing), never crash, never read or write outside its buffers (the
 * sanitizer stage runs this under ASan and UBSan) and never print.
 *
 * What issue 27 settles (whether a draw that reads past a vertex buffer's end fails or reads zeros) is not pinned
 * here: such a draw must only return one of the two answers without reading out of bounds.
 * tests/check_api_walkers.sh checks that every INSTESS_API function of core/device.h is named in this file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/core.h"

enum { W = 16, H = 12 };

/* A shader that writes oPos from POSITION0 and white. */
static void vs_pos(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    (void)c;
    out->pos = in->position[0];
    out->attr[RS_ATTR_COLOR0] = (float4){1, 1, 1, 1};
}
static const is_vertex_shader shader = {.name = "pos", .main = vs_pos, .outputs = IS_OUT_COLOR0};

static const is_vertex_element pos_decl[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};

static uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}

/* Whether a draw's answer is one of the two a draw may give (drawn, or refused as an invalid call). */
static bool ok_or_invalid(is_result r) { return r == IS_OK || r == IS_ERR_INVALIDCALL; }

/* A NULL device: every function returns (IS_ERR_INVALIDCALL, NULL, 0 or a message), none dereferences it. */
static void test_null_device(void **state)
{
    (void)state;
    is_vertex_buffer *vb = NULL;
    is_index_buffer *ib = NULL;
    is_vertex_declaration *decl = NULL;
    const is_vertex_shader *vs = NULL;
    uint32_t u = 0;
    float f[4] = {0};
    unsigned off = 0, stride = 0;
    is_viewport vp = {0, 0, 1, 1, 0, 1};
    is_rect rect = {0, 0, 1, 1};
    uint32_t px[4];
    dev_destroy(NULL);
    dev_reset(NULL);
    assert_non_null(dev_last_error(NULL));
    assert_string_equal(dev_debug_log(NULL), "");
    dev_set_threads(NULL, 2);
    dev_set_timing(NULL, true);
    dev_set_patch_cull(NULL, true);
    assert_int_equal(dev_set_present_flags(NULL, IS_PRESENTFLAG_DISCARD_DEPTHSTENCIL), IS_ERR_INVALIDCALL);
    dev_set_reference_path(NULL, true);
    assert_false(dev_reference_path(NULL));
    assert_int_equal(dev_set_isa(NULL, 0), -1);
    (void)dev_isa(NULL);
    assert_int_equal(dev_create_vertex_buffer(NULL, 64, &vb), IS_ERR_INVALIDCALL);
    assert_null(vb);
    assert_int_equal(dev_create_index_buffer(NULL, 64, IS_FMT_INDEX16, &ib), IS_ERR_INVALIDCALL);
    assert_null(ib);
    assert_int_equal(dev_create_vertex_declaration(NULL, pos_decl, &decl), IS_ERR_INVALIDCALL);
    assert_null(decl);
    assert_int_equal(dev_set_vertex_declaration(NULL, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_vertex_declaration(NULL, &decl), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_stream_source(NULL, 0, NULL, 0, 0), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_stream_source(NULL, 0, &vb, &off, &stride), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_stream_source_freq(NULL, 0, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_stream_source_freq(NULL, 0, &u), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_indices(NULL, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_indices(NULL, &ib), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_shader(NULL, &shader), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_vertex_shader(NULL, &vs), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_shader_constant_f(NULL, 0, f, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_vertex_shader_constant_f(NULL, 0, f, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_render_state(NULL, IS_RS_ZENABLE, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_state(NULL, IS_RS_ZENABLE, &u), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_viewport(NULL, &vp), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_viewport(NULL, &vp), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_npatch_mode(NULL, 4.0f), IS_ERR_INVALIDCALL);
    assert_true(dev_get_npatch_mode(NULL) == 0.0f);
    assert_int_equal(dev_set_npatch_evaluator(NULL, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_clear_rects(NULL, 1, &rect, IS_CLEAR_TARGET, 0, 1.0f), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_clear(NULL, IS_CLEAR_TARGET, 0, 1.0f), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_draw_primitive(NULL, IS_PT_TRIANGLELIST, 0, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_draw_indexed_primitive(NULL, IS_PT_TRIANGLELIST, 0, 0, 3, 0, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_draw_primitive_up(NULL, IS_PT_TRIANGLELIST, 1, f, 16), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_draw_indexed_primitive_up(NULL, IS_PT_TRIANGLELIST, 0, 3, 1, &u, IS_FMT_INDEX16, f, 16),
                     IS_ERR_INVALIDCALL);
    is_state_block *sb = (is_state_block *)0x1;
    assert_int_equal(dev_begin_state_block(NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_end_state_block(NULL, &sb), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_state_block(NULL, IS_SBT_ALL, &sb), IS_ERR_INVALIDCALL);
    assert_null(sb);
    assert_int_equal(sb_capture(NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(sb_apply(NULL), IS_ERR_INVALIDCALL);
    sb_release(NULL);
    assert_null(dev_render_target(NULL));
    assert_null(dev_present(NULL));
    assert_int_equal(dev_flush(NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_data(NULL, px, 4), IS_ERR_INVALIDCALL);
    const rs_stats *st = dev_stats(NULL);
    assert_non_null(st);   /* zero counters */
    assert_int_equal(st->prims_in, 0);
    assert_int_equal(dev_vertices_shaded(NULL), 0);
    assert_int_equal(dev_instances_culled(NULL), 0);
    /* the handles' own functions with NULL handles */
    assert_null(vb_lock(NULL));
    vb_unlock(NULL);
    assert_int_equal(vb_size(NULL), 0);
    vb_release(NULL);
    assert_null(ib_lock(NULL));
    ib_unlock(NULL);
    assert_int_equal(ib_size(NULL), 0);
    ib_release(NULL);
    decl_release(NULL);
}

/* dev_create with sizes and sample counts out of range: NULL and a message, also with a tiny or no buffer. */
static void test_create_sizes(void **state)
{
    (void)state;
    const int bad[][3] = {{0, 1, 1}, {1, 0, 1}, {-1, 1, 1}, {1, -5, 1}, {INT_MIN, INT_MIN, 1}, {INT_MAX, 1, 1},
                          {1, RS_MAX_SIZE + 1, 1}, {1, 1, 0}, {1, 1, 2}, {1, 1, 8}, {1, 1, -4}, {1, 1, INT_MAX}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char err[200] = "";
        assert_null(dev_create(bad[k][0], bad[k][1], bad[k][2], err, sizeof err));
        assert_true(strlen(err) > 0);
        char tiny[1] = {'x'};
        assert_null(dev_create(bad[k][0], bad[k][1], bad[k][2], tiny, sizeof tiny));
        assert_int_equal(tiny[0], 0);   /* NUL-terminated in a buffer of one byte */
        assert_null(dev_create(bad[k][0], bad[k][1], bad[k][2], NULL, 0));
        assert_null(dev_create(bad[k][0], bad[k][1], bad[k][2], NULL, 100));   /* no buffer, a length */
    }
    is_device *dev = dev_create(1, 1, 4, NULL, 0);   /* the smallest target */
    assert_non_null(dev);
    dev_destroy(dev);
}

/* Resources: NULL outputs, zero and huge sizes, unknown formats, bad declarations. */
static void test_resources(void **state)
{
    (void)state;
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    assert_non_null(dev);
    is_vertex_buffer *vb = NULL;
    is_index_buffer *ib = NULL;
    is_vertex_declaration *decl = NULL;
    assert_int_equal(dev_create_vertex_buffer(dev, 64, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_vertex_buffer(dev, 0, &vb), IS_ERR_INVALIDCALL);
    assert_null(vb);
    assert_int_equal(dev_create_vertex_buffer(dev, SIZE_MAX, &vb), IS_ERR_OUTOFMEMORY);
    assert_null(vb);
    assert_int_equal(dev_create_vertex_buffer(dev, (size_t)1 << 62, &vb), IS_ERR_OUTOFMEMORY);
    assert_null(vb);
    assert_true(strlen(dev_last_error(dev)) > 0);
    assert_int_equal(dev_create_index_buffer(dev, 64, IS_FMT_INDEX16, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_index_buffer(dev, 0, IS_FMT_INDEX16, &ib), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_index_buffer(dev, 64, (is_format)0, &ib), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_index_buffer(dev, 64, (is_format)-1, &ib), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_index_buffer(dev, SIZE_MAX, IS_FMT_INDEX32, &ib), IS_ERR_OUTOFMEMORY);
    assert_null(ib);
    /* declarations: NULL, empty, unknown type, usage, method, stream, unaligned offsets, too many elements */
    assert_int_equal(dev_create_vertex_declaration(dev, NULL, &decl), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_vertex_declaration(dev, pos_decl, NULL), IS_ERR_INVALIDCALL);
    const is_vertex_element end_only[] = {IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(dev, end_only, &decl), IS_ERR_INVALIDCALL);
    const is_vertex_element bad[][2] = {
        {{0, 0, 99, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END},
        {{0, 0, IS_DECLTYPE_UNUSED, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END},
        {{0, 0, IS_DECLTYPE_FLOAT3, 7, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END},
        {{0, 0, IS_DECLTYPE_FLOAT3, 0, 200, 0}, IS_DECL_END},
        {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 255}, IS_DECL_END},
        {{IS_MAX_STREAMS, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END},
        {{0xFE, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END},
        {{0, 2, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        decl = NULL;
        assert_int_equal(dev_create_vertex_declaration(dev, bad[k], &decl), IS_ERR_INVALIDCALL);
        assert_null(decl);
    }
    is_vertex_element many[IS_MAX_ELEMENTS + 2];
    for (int k = 0; k < IS_MAX_ELEMENTS + 1; k++)
        many[k] = (is_vertex_element){(uint16_t)(k % IS_MAX_STREAMS), (uint16_t)(16 * (k / IS_MAX_STREAMS)),
                                      IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, (uint8_t)(k % 16)};
    many[IS_MAX_ELEMENTS + 1] = (is_vertex_element)IS_DECL_END;
    assert_int_equal(dev_create_vertex_declaration(dev, many, &decl), IS_ERR_INVALIDCALL);
    /* the largest offset an element may have does not wrap its end */
    const is_vertex_element far[] = {{0, 0xFFFC, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    is_result r = dev_create_vertex_declaration(dev, far, &decl);
    assert_true(ok_or_invalid(r));
    if (r == IS_OK) decl_release(decl);
    dev_destroy(dev);
}

/* Setters and getters with NULL outputs, streams, registers and states beyond the last, values out of range:
 * refused, nothing changed. */
static void test_state_edges(void **state)
{
    (void)state;
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    assert_non_null(dev);
    float c[4 * IS_MAX_VS_CONSTANTS] = {0};
    uint32_t u;
    assert_int_equal(dev_get_stream_source_freq(dev, 0, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_stream_source_freq(dev, IS_MAX_STREAMS, &u), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_stream_source_freq(dev, UINT_MAX, &u), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_stream_source_freq(dev, UINT_MAX, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_stream_source(dev, UINT_MAX, NULL, 0, 0), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_stream_source(dev, IS_MAX_STREAMS, NULL, NULL, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_stream_source(dev, 0, NULL, NULL, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_vertex_declaration(dev, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_indices(dev, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_vertex_shader(dev, NULL), IS_ERR_INVALIDCALL);
    /* constants: NULL data, registers beyond c255, a start + count that wraps around */
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, 0, NULL, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, IS_MAX_VS_CONSTANTS, c, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, 1, c, IS_MAX_VS_CONSTANTS), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, 2, c, UINT_MAX), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, UINT_MAX, c, 2), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, 0, c, IS_MAX_VS_CONSTANTS), IS_OK);
    assert_int_equal(dev_get_vertex_shader_constant_f(dev, 0, NULL, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_vertex_shader_constant_f(dev, UINT_MAX, c, 2), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_vertex_shader_constant_f(dev, 2, c, UINT_MAX), IS_ERR_INVALIDCALL);
    assert_true(ok_or_invalid(dev_set_vertex_shader_constant_f(dev, 0, c, 0)));   /* nothing to set */
    /* a shader without a function */
    const is_vertex_shader empty = {.name = NULL, .main = NULL};
    assert_int_equal(dev_set_vertex_shader(dev, &empty), IS_ERR_INVALIDCALL);
    /* render states that do not exist, values out of range, float states not finite */
    const int unknown[] = {-1, 0, 1, 6, 255, 256, 1000, INT_MAX, INT_MIN};
    for (size_t k = 0; k < sizeof unknown / sizeof unknown[0]; k++) {
        assert_int_equal(dev_set_render_state(dev, (is_rs)unknown[k], 1), IS_ERR_INVALIDCALL);
        assert_int_equal(dev_get_render_state(dev, (is_rs)unknown[k], &u), IS_ERR_INVALIDCALL);
    }
    assert_int_equal(dev_get_render_state(dev, IS_RS_CULLMODE, NULL), IS_ERR_INVALIDCALL);
    const struct { is_rs s; uint32_t v; } bad_values[] = {
        {IS_RS_FILLMODE, 0}, {IS_RS_FILLMODE, 4}, {IS_RS_FILLMODE, UINT32_MAX}, {IS_RS_CULLMODE, 0},
        {IS_RS_CULLMODE, 4}, {IS_RS_ZFUNC, 0}, {IS_RS_ZFUNC, 9}, {IS_RS_SRCBLEND, 0}, {IS_RS_DESTBLEND, 99},
        {IS_RS_DEPTHBIAS, 0x7fc00000u /* NaN */}, {IS_RS_SLOPESCALEDEPTHBIAS, 0x7f800000u /* inf */},
        {IS_RS_MINTESSELLATIONLEVEL, 0x7fc00000u}, {IS_RS_MAXTESSELLATIONLEVEL, 0xff800000u /* -inf */},
        {IS_RS_SRCBLEND, 14 /* BLENDFACTOR */}, {IS_RS_ADAPTIVETESS_X, 0x7fc00000u},
        {IS_RS_ADAPTIVETESS_W, 0x7f800000u}, {IS_RS_ENABLEADAPTIVETESSELLATION, 2},
        {IS_RS_POSITIONDEGREE, 0}, {IS_RS_NORMALDEGREE, 7}, {IS_RS_PATCHEDGESTYLE, 2},
    };
    for (size_t k = 0; k < sizeof bad_values / sizeof bad_values[0]; k++) {
        uint32_t before = 0, after = 0;
        assert_int_equal(dev_get_render_state(dev, bad_values[k].s, &before), IS_OK);
        assert_int_equal(dev_set_render_state(dev, bad_values[k].s, bad_values[k].v), IS_ERR_INVALIDCALL);
        assert_int_equal(dev_get_render_state(dev, bad_values[k].s, &after), IS_OK);
        assert_int_equal(before, after);
    }
    /* viewports: NULL, empty, outside the target (also by wrapping x + width), depth ranges out of order or NaN */
    const is_viewport bad_vp[] = {{0, 0, 0, H, 0, 1}, {0, 0, W, 0, 0, 1}, {0, 0, W, H, -0.1f, 1},
                                  {0, 0, W, H, 0, 1.5f}, {0, 0, W, H, NAN, 1}, {0, 0, W, H, 0, NAN}};
    is_viewport vp0, vp1;
    assert_int_equal(dev_get_viewport(dev, &vp0), IS_OK);
    assert_int_equal(dev_set_viewport(dev, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_viewport(dev, NULL), IS_ERR_INVALIDCALL);
    for (size_t k = 0; k < sizeof bad_vp / sizeof bad_vp[0]; k++)
        assert_int_equal(dev_set_viewport(dev, &bad_vp[k]), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_viewport(dev, &vp1), IS_OK);
    assert_memory_equal(&vp0, &vp1, sizeof vp0);
    /* what the runtime takes: beyond the target (also wrapping x + width), MinZ >= MaxZ; read back as given */
    const is_viewport odd_vp[] = {{W, 0, 1, H, 0, 1}, {1, 0, UINT32_MAX, H, 0, 1}, {UINT32_MAX, 0, 2, H, 0, 1},
                                  {UINT32_MAX, UINT32_MAX, UINT32_MAX, UINT32_MAX, 1, 1}, {0, 0, W, H, 0.5f, 0.25f}};
    for (size_t k = 0; k < sizeof odd_vp / sizeof odd_vp[0]; k++) {
        assert_int_equal(dev_set_viewport(dev, &odd_vp[k]), IS_OK);
        assert_int_equal(dev_get_viewport(dev, &vp1), IS_OK);
        assert_memory_equal(&odd_vp[k], &vp1, sizeof vp1);
        assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET, 0, 1.0f), IS_OK);
    }
    assert_int_equal(dev_set_viewport(dev, &vp0), IS_OK);
    /* N-patch segments: every float is stored and read back, as the runtime does (below 1 or NaN: off) */
    const float odd_seg[] = {NAN, INFINITY, -INFINITY, 1e30f, 257.0f, FLT_MAX, -5.0f};
    for (size_t k = 0; k < sizeof odd_seg / sizeof odd_seg[0]; k++) {
        assert_int_equal(dev_set_npatch_mode(dev, odd_seg[k]), IS_OK);
        float back = dev_get_npatch_mode(dev);
        assert_memory_equal(&back, &odd_seg[k], sizeof back);
    }
    assert_int_equal(dev_set_npatch_evaluator(dev, NULL), IS_OK);
    /* threads and ISA out of range */
    dev_set_threads(dev, -7);
    dev_set_threads(dev, INT_MAX);
    dev_set_threads(dev, 0);
    int isa = dev_isa(dev);
    assert_int_equal(dev_set_isa(dev, -1), -1);
    assert_int_equal(dev_set_isa(dev, 99), -1);
    assert_int_equal(dev_set_isa(dev, INT_MIN), -1);
    assert_int_equal(dev_isa(dev), isa);
    dev_set_timing(dev, true);
    dev_set_patch_cull(dev, true);
    assert_int_equal(dev_set_present_flags(dev, UINT_MAX), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_present_flags(dev, IS_PRESENTFLAG_DISCARD_DEPTHSTENCIL | 0x80000000u), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_present_flags(dev, 0), IS_OK);
    dev_set_reference_path(dev, true);
    assert_true(dev_reference_path(dev));
    dev_set_reference_path(dev, false);
    /* clears: unknown flags, z out of [0, 1] or NaN, rectangles empty, reversed, outside the target, huge */
    assert_int_equal(dev_clear(dev, 0x80, 0, 1.0f), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_clear(dev, IS_CLEAR_ZBUFFER, 0, NAN), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_clear(dev, IS_CLEAR_ZBUFFER, 0, -1.0f), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_clear(dev, IS_CLEAR_ZBUFFER, 0, 2.0f), IS_ERR_INVALIDCALL);
    const is_rect rects[] = {{0, 0, 0, 0}, {5, 5, 1, 1}, {-100, -100, 100000, 100000}, {INT32_MIN, INT32_MIN,
                             INT32_MAX, INT32_MAX}, {W, H, W + 5, H + 5}, {INT32_MAX, 0, INT32_MIN, 1}};
    assert_true(ok_or_invalid(dev_clear_rects(dev, 6, rects, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0xff00ff00u, 0.5f)));
    assert_true(ok_or_invalid(dev_clear_rects(dev, UINT_MAX, NULL, IS_CLEAR_TARGET, 0, 1.0f)));
    assert_true(ok_or_invalid(dev_clear_rects(dev, 0, rects, IS_CLEAR_TARGET, 0, 1.0f)));
    /* the target's data into a buffer too small, or none */
    uint32_t px[W * H];
    assert_int_equal(dev_get_render_target_data(dev, NULL, W * H), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_data(dev, px, W * H - 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_data(dev, px, 0), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_data(dev, px, W * H), IS_OK);
    assert_non_null(dev_render_target(dev));
    assert_true(dev_present(dev) == dev_render_target(dev));   /* the same target, its colour written */
    assert_int_equal(dev_flush(dev), IS_OK);   /* nothing recorded: nothing to report */
    assert_non_null(dev_stats(dev));
    (void)dev_vertices_shaded(dev);
    (void)dev_instances_culled(dev);
    assert_true(dev_get_npatch_mode(dev) < 1.0f);
    dev_reset(dev);
    dev_destroy(dev);
}

/* A device with the position shader, a FLOAT4 position declaration and a vertex buffer of n vertices bound
 * with stride 16 (the triangle (-1,-1), (0,1), (1,-1) repeated), and a 16-bit index buffer of ni indices 0, 1, 2, ... */
typedef struct draw_fixture {
    is_device *dev;
    is_vertex_buffer *vb;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
} draw_fixture;

static void fixture_make(draw_fixture *f, size_t n, size_t ni)
{
    f->dev = dev_create(W, H, 1, NULL, 0);
    assert_non_null(f->dev);
    assert_int_equal(dev_create_vertex_buffer(f->dev, n * 16, &f->vb), IS_OK);
    float *v = vb_lock(f->vb);
    assert_non_null(v);
    static const float tri[3][4] = {{-1, -1, 0.5f, 1}, {0, 1, 0.5f, 1}, {1, -1, 0.5f, 1}};
    for (size_t k = 0; k < n; k++) memcpy(v + 4 * k, tri[k % 3], 16);
    vb_unlock(f->vb);
    assert_int_equal(vb_size(f->vb), n * 16);
    assert_int_equal(dev_create_index_buffer(f->dev, ni * 2, IS_FMT_INDEX16, &f->ib), IS_OK);
    uint16_t *idx = ib_lock(f->ib);
    for (size_t k = 0; k < ni; k++) idx[k] = (uint16_t)k;
    ib_unlock(f->ib);
    assert_int_equal(ib_size(f->ib), ni * 2);
    assert_int_equal(dev_create_vertex_declaration(f->dev, pos_decl, &f->decl), IS_OK);
}

static void fixture_bind(draw_fixture *f)
{
    assert_int_equal(dev_set_vertex_shader(f->dev, &shader), IS_OK);
    assert_int_equal(dev_set_vertex_declaration(f->dev, f->decl), IS_OK);
    assert_int_equal(dev_set_stream_source(f->dev, 0, f->vb, 0, 16), IS_OK);
    assert_int_equal(dev_set_indices(f->dev, f->ib), IS_OK);
}

static void fixture_free(draw_fixture *f)
{
    vb_release(f->vb);
    ib_release(f->ib);
    decl_release(f->decl);
    dev_destroy(f->dev);
}

/* Draws without a shader, a declaration, a vertex or an index buffer: refused with a message; primitive types
 * that do not exist; zero and huge primitive counts; starts and vertex ranges beyond the buffers. */
static void test_draw_edges(void **state)
{
    (void)state;
    draw_fixture f;
    fixture_make(&f, 6, 6);
    is_device *dev = f.dev;
    /* nothing bound */
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_ERR_INVALIDCALL);
    assert_true(strlen(dev_last_error(dev)) > 0);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 3, 0, 1), IS_ERR_INVALIDCALL);
    dev_set_vertex_shader(dev, &shader);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_ERR_INVALIDCALL);   /* no declaration */
    dev_set_vertex_declaration(dev, f.decl);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);   /* no buffer: reads zeros */
    assert_true(strlen(dev_debug_log(dev)) > 0);
    dev_set_stream_source(dev, 0, f.vb, 0, 16);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 3, 0, 1), IS_ERR_INVALIDCALL);
    fixture_bind(&f);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 2), IS_OK);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2), IS_OK);
    /* primitive types that do not exist */
    const int types[] = {0, 7, -1, 100, INT_MAX, INT_MIN};
    for (size_t k = 0; k < sizeof types / sizeof types[0]; k++) {
        assert_int_equal(dev_draw_primitive(dev, (is_primtype)types[k], 0, 1), IS_ERR_INVALIDCALL);
        assert_int_equal(dev_draw_indexed_primitive(dev, (is_primtype)types[k], 0, 0, 3, 0, 1), IS_ERR_INVALIDCALL);
    }
    /* every primitive type at counts of zero, one, and far beyond the buffers */
    for (int t = IS_PT_POINTLIST; t <= IS_PT_TRIANGLEFAN; t++) {
        const unsigned counts[] = {0, 1, 2, 7, 1u << 20, UINT_MAX / 3, UINT_MAX / 2, UINT_MAX - 1, UINT_MAX};
        for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
            assert_true(ok_or_invalid(dev_draw_primitive(dev, (is_primtype)t, 0, counts[k])));
            assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, (is_primtype)t, 0, 0, 6, 0, counts[k])));
        }
        /* starts and vertex ranges beyond the buffers, negative and huge base vertices */
        const unsigned starts[] = {5, 6, 100, UINT_MAX - 2, UINT_MAX};
        for (size_t k = 0; k < sizeof starts / sizeof starts[0]; k++) {
            assert_true(ok_or_invalid(dev_draw_primitive(dev, (is_primtype)t, starts[k], 1)));
            assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, (is_primtype)t, 0, 0, 6, starts[k], 1)));
            assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, (is_primtype)t, 0, starts[k], 6, 0, 1)));
            assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, (is_primtype)t, 0, 0, starts[k], 0, 1)));
            assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, (is_primtype)t, 0, starts[k], starts[k], 0, 1)));
        }
        /* the UP draws: strides of 0 and up to what the array holds (a UP draw reads the count's worth of the
         * caller's memory, which the caller must own, as in D3D9), counts beyond the device's caps (refused
         * before anything is read), NULL data, bad index formats; each leaves stream 0 unset, so rebind */
        static const float up_v[6][4] = {{0}};
        static const uint16_t up_i[6] = {0, 1, 2, 3, 4, 65535};
        const unsigned up_strides[] = {0, 4, 8, 16};
        for (size_t k = 0; k < sizeof up_strides / sizeof up_strides[0]; k++) {
            assert_true(ok_or_invalid(dev_draw_primitive_up(dev, (is_primtype)t, 1, up_v, up_strides[k])));
            assert_true(ok_or_invalid(dev_draw_indexed_primitive_up(dev, (is_primtype)t, 0, 6, 1, up_i, IS_FMT_INDEX16,
                                                                    up_v, up_strides[k])));
            fixture_bind(&f);
        }
        assert_int_equal(dev_draw_primitive_up(dev, (is_primtype)t, UINT_MAX, up_v, 16), IS_ERR_INVALIDCALL);
        assert_int_equal(dev_draw_indexed_primitive_up(dev, (is_primtype)t, UINT_MAX, UINT_MAX, 1, up_i,
                                                       IS_FMT_INDEX16, up_v, 16), IS_ERR_INVALIDCALL);
        assert_int_equal(dev_draw_primitive_up(dev, (is_primtype)t, 1, NULL, 16), IS_ERR_INVALIDCALL);
        assert_int_equal(dev_draw_indexed_primitive_up(dev, (is_primtype)t, 0, 6, 1, up_i, (is_format)0, up_v, 16),
                         IS_ERR_INVALIDCALL);
        assert_int_equal(dev_draw_indexed_primitive_up(dev, (is_primtype)t, 0, 6, 1, NULL, IS_FMT_INDEX32, up_v, 16),
                         IS_ERR_INVALIDCALL);
        fixture_bind(&f);
        const int bases[] = {-1, -3, -6, 1, 3, 100, INT_MAX, INT_MIN};
        for (size_t k = 0; k < sizeof bases / sizeof bases[0]; k++)
            assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, (is_primtype)t, bases[k], 0, 6, 0, 2)));
    }
    fixture_free(&f);
}

/* Strides and offsets that do not match the buffer: stride 0 (every vertex reads the first), smaller than the
 * element, huge, an offset at or beyond the end; indices that name vertices past the buffer; a 32-bit index
 * buffer of an odd size.  The draw answers (drawn or refused) and reads nothing outside the buffers. */
static void test_draw_strides(void **state)
{
    (void)state;
    draw_fixture f;
    fixture_make(&f, 6, 6);
    fixture_bind(&f);
    is_device *dev = f.dev;
    const unsigned strides[] = {0, 4, 8, 12, 16, 20, 96, 4096, 1u << 20, UINT_MAX - 3, UINT_MAX};
    const unsigned offsets[] = {0, 4, 80, 92, 96, 100, 1u << 30, UINT_MAX - 3};
    for (size_t s = 0; s < sizeof strides / sizeof strides[0]; s++)
        for (size_t o = 0; o < sizeof offsets / sizeof offsets[0]; o++) {
            is_result r = dev_set_stream_source(dev, 0, f.vb, offsets[o], strides[s]);
            assert_true(ok_or_invalid(r));
            if (r != IS_OK) continue;
            assert_true(ok_or_invalid(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 2)));
            assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2)));
            assert_true(ok_or_invalid(dev_draw_primitive(dev, IS_PT_POINTLIST, 0, 6)));
        }
    assert_int_equal(dev_set_stream_source(dev, 0, f.vb, 3, 16), IS_ERR_INVALIDCALL);   /* not DWORD-aligned */
    dev_set_stream_source(dev, 0, f.vb, 0, 16);
    /* indices beyond the vertex buffer (65535, 7) and beyond num_vertices */
    uint16_t *idx = ib_lock(f.ib);
    idx[1] = 65535, idx[4] = 7;
    ib_unlock(f.ib);
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2)));
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 3, 0, 2)));
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 65536, 0, 2)));
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, -65535, 0, 6, 0, 2)));
    /* a 32-bit index buffer of 10 bytes (two and a half indices) and indices near 2^32 */
    is_index_buffer *ib32;
    assert_int_equal(dev_create_index_buffer(dev, 10, IS_FMT_INDEX32, &ib32), IS_OK);
    uint32_t *i32 = ib_lock(ib32);
    i32[0] = 0, i32[1] = UINT32_MAX;
    ib_unlock(ib32);
    assert_int_equal(dev_set_indices(dev, ib32), IS_OK);
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 1)));
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_LINELIST, 0, 0, 6, 0, 1)));
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_POINTLIST, 1, 0, 6, 0, 2)));
    ib_release(ib32);
    /* a buffer too small for one vertex of the declaration (8 bytes for a FLOAT4) */
    is_vertex_buffer *small;
    assert_int_equal(dev_create_vertex_buffer(dev, 8, &small), IS_OK);
    assert_int_equal(dev_set_stream_source(dev, 0, small, 0, 16), IS_OK);
    assert_true(ok_or_invalid(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1)));
    assert_true(ok_or_invalid(dev_draw_primitive(dev, IS_PT_POINTLIST, 0, 1)));
    vb_release(small);
    fixture_free(&f);
}

/* Instanced draws with frequencies that do not fit the buffers: instance counts of 2^30 - 1, dividers of
 * 2^30 - 1 and 1, an instance stream too small, INSTANCEDATA on a stream the declaration does not read, and the
 * N-patch mode (with and without an evaluator, adaptive on) over the same bindings. */
static void test_draw_instancing(void **state)
{
    (void)state;
    draw_fixture f;
    fixture_make(&f, 6, 6);
    fixture_bind(&f);
    is_device *dev = f.dev;
    static const is_vertex_element two[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITION, 0},
                                            {1, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, 0}, IS_DECL_END};
    is_vertex_declaration *d2;
    assert_int_equal(dev_create_vertex_declaration(dev, two, &d2), IS_OK);
    is_vertex_buffer *inst;
    assert_int_equal(dev_create_vertex_buffer(dev, 3 * 16, &inst), IS_OK);
    dev_set_vertex_declaration(dev, d2);
    dev_set_stream_source(dev, 1, inst, 0, 16);
    const uint32_t counts[] = {1, 2, 3, 4, 1000, (1u << 30) - 1};
    const uint32_t dividers[] = {1, 2, 1000, (1u << 30) - 1};
    for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++)
        for (size_t d = 0; d < sizeof dividers / sizeof dividers[0]; d++) {
            assert_true(ok_or_invalid(dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | counts[c])));
            assert_true(ok_or_invalid(dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | dividers[d])));
            /* a count of 2^30 - 1 instances of a triangle covering the target: the work bound refuses it, or the
             * buffer check does; neither may take minutes */
            is_result r = dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 3, 0, 1);
            assert_true(r == IS_OK || r == IS_ERR_INVALIDCALL || r == IS_ERR_OUTOFMEMORY);
        }
    /* INSTANCEDATA on a stream the declaration does not read, and a plain divider on stream 0 */
    dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | 2);
    dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1);
    assert_true(ok_or_invalid(dev_set_stream_source_freq(dev, 5, IS_STREAMSOURCE_INSTANCEDATA | 1)));
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 3, 0, 1)));
    dev_set_stream_source_freq(dev, 0, 7);
    assert_true(ok_or_invalid(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 2)));
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2)));
    /* the N-patch mode without an evaluator, then adaptive with extreme levels */
    dev_set_stream_source_freq(dev, 0, 1);
    dev_set_stream_source_freq(dev, 1, 1);
    dev_set_vertex_declaration(dev, f.decl);
    assert_int_equal(dev_set_npatch_mode(dev, 4.0f), IS_OK);
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2)));
    dev_set_render_state(dev, IS_RS_ENABLEADAPTIVETESSELLATION, 1);
    dev_set_render_state(dev, IS_RS_MAXTESSELLATIONLEVEL, float_bits(FLT_MAX));
    dev_set_render_state(dev, IS_RS_MINTESSELLATIONLEVEL, float_bits(1e30f));
    dev_set_render_state(dev, IS_RS_ADAPTIVETESS_Z, float_bits(0.0f));   /* depth 0: T = S / 0 */
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2)));
    dev_set_npatch_mode(dev, 256.0f);
    dev_set_render_state(dev, IS_RS_PATCHEDGESTYLE, IS_PATCHEDGE_CONTINUOUS);
    assert_true(ok_or_invalid(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2)));
    dev_set_npatch_mode(dev, 0.0f);
    vb_release(inst);
    decl_release(d2);
    fixture_free(&f);
}

/* Stateblocks with every kind of bad argument: NULL outputs, types out of range, calls in the wrong order, and a
 * long recording of every setter with extreme values (refused ones record nothing); blocks outliving their
 * device. */
static void test_state_blocks(void **state)
{
    (void)state;
    draw_fixture f;
    fixture_make(&f, 6, 6);
    is_device *dev = f.dev;
    is_state_block *sb = NULL, *rec = NULL;
    const int types[] = {0, 4, -1, 100, INT_MAX, INT_MIN};
    for (size_t k = 0; k < sizeof types / sizeof types[0]; k++)
        assert_int_equal(dev_create_state_block(dev, (is_state_block_type)types[k], &sb), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_state_block(dev, IS_SBT_VERTEXSTATE, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_end_state_block(dev, &rec), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_begin_state_block(dev), IS_OK);
    assert_int_equal(dev_begin_state_block(dev), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_end_state_block(dev, NULL), IS_ERR_INVALIDCALL);
    fixture_bind(&f);
    const float c[4] = {1, 2, 3, 4};
    for (unsigned r = 0; r < 300; r += 7) (void)dev_set_render_state(dev, (is_rs)r, UINT32_MAX);
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, IS_MAX_VS_CONSTANTS - 1, c, 1), IS_OK);
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, IS_MAX_VS_CONSTANTS, c, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_stream_source_freq(dev, IS_MAX_STREAMS - 1, UINT32_MAX >> 2), IS_OK);
    assert_int_equal(dev_end_state_block(dev, &rec), IS_OK);
    assert_non_null(rec);
    assert_int_equal(dev_create_state_block(dev, IS_SBT_ALL, &sb), IS_OK);
    assert_int_equal(sb_apply(rec), IS_OK);
    assert_int_equal(sb_capture(rec), IS_OK);
    assert_int_equal(sb_apply(sb), IS_OK);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2), IS_ERR_INVALIDCALL);
    fixture_bind(&f);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2), IS_OK);
    dev_destroy(dev);   /* the blocks outlive it: refused, then released safely */
    f.dev = NULL;
    assert_int_equal(sb_capture(sb), IS_ERR_INVALIDCALL);
    assert_int_equal(sb_apply(rec), IS_ERR_INVALIDCALL);
    sb_release(sb);
    sb_release(rec);
    vb_release(f.vb);
    ib_release(f.ib);
    decl_release(f.decl);
}

/* The adaptive levels' formula at its edges: never NaN out of the edge rule, whatever goes in. */
static void test_adaptive_levels(void **state)
{
    (void)state;
    const float v[] = {0.0f, -0.0f, 1.0f, -1.0f, 1e-45f, 1e30f, FLT_MAX, INFINITY, -INFINITY, NAN};
    const size_t n = sizeof v / sizeof v[0];
    for (size_t a = 0; a < n; a++)
        for (size_t b = 0; b < n; b++) {
            float4 p = {v[a], v[b], v[(a + b) % n], 1}, mdm = {v[b], 0, v[a], v[(a * b) % n]};
            (void)core_adaptive_vertex_level(v[a], v[b], p, mdm);   /* may be anything: the edge rule clamps */
            for (size_t c = 0; c < n; c++) {
                float lo = 1.0f, hi = 64.0f;
                float e = core_adaptive_edge_level(v[a], v[b], lo, hi);
                assert_true(e >= lo && e <= hi);
                /* MIN > MAX: MIN wins (the documented order); out-of-range states never come from the device */
                e = core_adaptive_edge_level(v[a], v[c], 8.0f, 2.0f);
                assert_true(e == 8.0f || (e >= 2.0f && e <= 8.0f));
                assert_false(isnan(core_adaptive_edge_level(v[a], v[b], v[c] >= 1 ? v[c] : 1.0f, 64.0f)));
            }
        }
}

/* Ownership: another device's resources and released ones are refused by the setters (compared as pointers,
 * never read); dev_destroy releases the memory of what is left, and the handles it leaves are safe to release
 * after it (as D3D9's, which hold a reference to their device). */
static void test_ownership(void **state)
{
    (void)state;
    draw_fixture a, b;
    fixture_make(&a, 6, 6);
    fixture_make(&b, 6, 6);
    assert_int_equal(dev_set_stream_source(b.dev, 0, a.vb, 0, 16), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_indices(b.dev, a.ib), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_declaration(b.dev, a.decl), IS_ERR_INVALIDCALL);
    /* a released buffer, declaration and index buffer: refused (the pointers name freed memory) */
    is_vertex_buffer *gone_vb;
    is_index_buffer *gone_ib;
    is_vertex_declaration *gone_decl;
    assert_int_equal(dev_create_vertex_buffer(b.dev, 64, &gone_vb), IS_OK);
    assert_int_equal(dev_create_index_buffer(b.dev, 64, IS_FMT_INDEX16, &gone_ib), IS_OK);
    assert_int_equal(dev_create_vertex_declaration(b.dev, pos_decl, &gone_decl), IS_OK);
    vb_release(gone_vb);
    ib_release(gone_ib);
    decl_release(gone_decl);
    assert_int_equal(dev_set_stream_source(b.dev, 0, gone_vb, 0, 16), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(b.dev), "not a live"));
    assert_int_equal(dev_set_indices(b.dev, gone_ib), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_declaration(b.dev, gone_decl), IS_ERR_INVALIDCALL);
    /* a handle that is no handle at all (a stack address) */
    char junk[256] = {0};
    assert_int_equal(dev_set_stream_source(b.dev, 0, (is_vertex_buffer *)junk, 0, 16), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_indices(b.dev, (is_index_buffer *)junk), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_declaration(b.dev, (is_vertex_declaration *)junk), IS_ERR_INVALIDCALL);
    /* b draws with its own buffers after a's are bound on a and a is destroyed */
    fixture_bind(&a);
    fixture_bind(&b);
    dev_destroy(a.dev);
    assert_null(vb_lock(a.vb));   /* dev_destroy released the buffers' memory */
    assert_int_equal(vb_size(a.vb), 0);
    assert_null(ib_lock(a.ib));
    assert_int_equal(ib_size(a.ib), 0);
    assert_int_equal(dev_clear(b.dev, IS_CLEAR_TARGET, 0, 1.0f), IS_OK);
    assert_int_equal(dev_draw_indexed_primitive(b.dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2), IS_OK);
    vb_unlock(a.vb);
    ib_unlock(a.ib);
    vb_release(a.vb);   /* after dev_destroy: no use-after-free, and the device's last bytes go with the last */
    ib_release(a.ib);
    decl_release(a.decl);
    /* getters hand out what was set */
    is_vertex_buffer *gvb;
    is_index_buffer *gib;
    is_vertex_declaration *gdecl;
    const is_vertex_shader *gvs;
    unsigned off, stride;
    assert_int_equal(dev_get_stream_source(b.dev, 0, &gvb, &off, &stride), IS_OK);
    assert_ptr_equal(gvb, b.vb);
    assert_int_equal(dev_get_indices(b.dev, &gib), IS_OK);
    assert_ptr_equal(gib, b.ib);
    assert_int_equal(dev_get_vertex_declaration(b.dev, &gdecl), IS_OK);
    assert_ptr_equal(gdecl, b.decl);
    assert_int_equal(dev_get_vertex_shader(b.dev, &gvs), IS_OK);
    assert_ptr_equal(gvs, &shader);
    /* releasing bound resources unbinds them: the next draw reads zeros (robust reads), not freed memory */
    vb_release(b.vb), b.vb = NULL;
    assert_int_equal(dev_get_stream_source(b.dev, 0, &gvb, &off, &stride), IS_OK);
    assert_null(gvb);
    assert_int_equal(dev_draw_indexed_primitive(b.dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2), IS_OK);
    /* a device destroyed with resources never released: dev_destroy frees their memory (LeakSanitizer counts
     * only the handles, released here) */
    draw_fixture c;
    fixture_make(&c, 3, 3);
    fixture_bind(&c);
    dev_destroy(c.dev);
    c.dev = NULL;
    vb_release(c.vb), ib_release(c.ib), decl_release(c.decl);
    fixture_free(&b);
}

/* The render-target and surface functions (core/surface.c): a NULL or destroyed device, NULL surfaces and
 * outputs, zero and huge sizes, unknown formats and multisample types, indices past the one target, surfaces of
 * another device, released ones and junk, locks out of range; releases after dev_destroy. */
static void test_surfaces(void **state)
{
    (void)state;
    is_surface *s = (is_surface *)1, *t = NULL, *sys = NULL, *ds = NULL;
    is_surface_desc desc;
    int pitch = 0;
    void *bits = NULL;
    const is_rect huge = {INT_MIN, INT_MIN, INT_MAX, INT_MAX};
    /* NULL device */
    assert_int_equal(dev_create_render_target(NULL, 4, 4, IS_FMT_A8R8G8B8, 0, &s), IS_ERR_INVALIDCALL);
    assert_null(s);
    assert_int_equal(dev_create_depth_stencil_surface(NULL, 4, 4, IS_FMT_D24S8, 0, &s), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_offscreen_plain_surface(NULL, 4, 4, IS_FMT_A8R8G8B8, &s), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_get_surface_level(NULL, 0, &s), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_render_target(NULL, 0, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target(NULL, 0, &s), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_depth_stencil_surface(NULL, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_depth_stencil_surface(NULL, &s), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_surface_data(NULL, NULL, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(surf_get_desc(NULL, &desc), IS_ERR_INVALIDCALL);
    assert_int_equal(surf_lock_rect(NULL, NULL, &pitch, &bits), IS_ERR_INVALIDCALL);
    assert_int_equal(surf_unlock_rect(NULL), IS_ERR_INVALIDCALL);
    surf_release(NULL);
    /* sizes, formats, multisample types, NULL outputs */
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    const unsigned sizes[][2] = {{0, 4}, {4, 0}, {RS_MAX_SIZE + 1, 4}, {4, UINT_MAX}};
    for (int k = 0; k < 4; k++) {
        assert_int_equal(dev_create_render_target(dev, sizes[k][0], sizes[k][1], IS_FMT_A8R8G8B8, 0, &s),
                         IS_ERR_INVALIDCALL);
        assert_int_equal(dev_create_depth_stencil_surface(dev, sizes[k][0], sizes[k][1], IS_FMT_D24S8, 0, &s),
                         IS_ERR_INVALIDCALL);
        assert_int_equal(dev_create_offscreen_plain_surface(dev, sizes[k][0], sizes[k][1], IS_FMT_A8R8G8B8, &s),
                         IS_ERR_INVALIDCALL);
    }
    assert_int_equal(dev_create_render_target(dev, 4, 4, (is_format)0, 0, &s), IS_ERR_NOTAVAILABLE);
    assert_int_equal(dev_create_render_target(dev, 4, 4, IS_FMT_A8R8G8B8, UINT_MAX, &s), IS_ERR_NOTAVAILABLE);
    assert_int_equal(dev_create_depth_stencil_surface(dev, 4, 4, (is_format)-1, 0, &s), IS_ERR_NOTAVAILABLE);
    assert_int_equal(dev_create_render_target(dev, 4, 4, IS_FMT_A8R8G8B8, 0, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_depth_stencil_surface(dev, 4, 4, IS_FMT_D24S8, 0, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_offscreen_plain_surface(dev, 4, 4, IS_FMT_A8R8G8B8, NULL), IS_ERR_INVALIDCALL);
    assert_null(s);
    assert_int_equal(dev_create_render_target(dev, 4, 4, IS_FMT_A8R8G8B8, 0, &t), IS_OK);
    assert_int_equal(dev_create_depth_stencil_surface(dev, 4, 4, IS_FMT_D16, IS_MULTISAMPLE_4_SAMPLES, &ds), IS_OK);
    assert_int_equal(dev_create_offscreen_plain_surface(dev, 4, 4, IS_FMT_A8R8G8B8, &sys), IS_OK);
    assert_int_equal(surf_get_desc(ds, &desc), IS_OK);
    assert_true(desc.format == IS_FMT_D16 && desc.usage == IS_USAGE_DEPTHSTENCIL && desc.width == 4 &&
                desc.multisample == IS_MULTISAMPLE_4_SAMPLES);
    assert_int_equal(surf_get_desc(t, NULL), IS_ERR_INVALIDCALL);
    /* getters and setters at their edges */
    assert_int_equal(dev_get_render_target(dev, 0, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target(dev, UINT_MAX, &s), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_depth_stencil_surface(dev, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_render_target(dev, UINT_MAX, t), IS_ERR_INVALIDCALL);
    char junk[sizeof(is_surface_desc) * 64] = {0};
    assert_int_equal(dev_set_render_target(dev, 0, (is_surface *)junk), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_depth_stencil_surface(dev, (is_surface *)junk), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_surface_data(dev, t, (is_surface *)junk), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_surface_data(dev, t, NULL), IS_ERR_INVALIDCALL);
    /* locks */
    assert_int_equal(surf_lock_rect(sys, NULL, NULL, &bits), IS_ERR_INVALIDCALL);
    assert_int_equal(surf_lock_rect(sys, NULL, &pitch, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(surf_lock_rect(sys, &huge, &pitch, &bits), IS_ERR_INVALIDCALL);
    assert_int_equal(surf_lock_rect(ds, NULL, &pitch, &bits), IS_ERR_INVALIDCALL);
    assert_int_equal(surf_unlock_rect(sys), IS_ERR_INVALIDCALL);
    /* texture levels */
    is_texture *tex;
    assert_int_equal(dev_create_texture(dev, 4, 4, 2, 0, IS_FMT_R32F, &tex), IS_OK);
    assert_int_equal(tex_get_surface_level(tex, 2, &s), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_get_surface_level(tex, UINT_MAX, &s), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_get_surface_level(tex, 1, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_get_surface_level(tex, 1, &s), IS_OK);
    assert_int_equal(dev_set_render_target(dev, 0, s), IS_ERR_INVALIDCALL);   /* not a RENDERTARGET texture */
    surf_release(s);   /* the texture's: nothing */
    assert_int_equal(surf_get_desc(s, &desc), IS_OK);
    assert_true(desc.width == 2 && desc.usage == 0);
    /* another device's surfaces, released ones */
    is_device *other = dev_create(4, 4, 1, NULL, 0);
    assert_int_equal(dev_set_render_target(other, 0, t), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_depth_stencil_surface(other, ds), IS_ERR_INVALIDCALL);
    is_surface *gone;
    assert_int_equal(dev_create_render_target(dev, 4, 4, IS_FMT_A8R8G8B8, 0, &gone), IS_OK);
    surf_release(gone);
    assert_int_equal(dev_set_render_target(dev, 0, gone), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_render_target(dev, 0, t), IS_OK);
    assert_int_equal(dev_set_depth_stencil_surface(dev, ds), IS_OK);   /* 4 samples with a 1-sample target */
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
    /* destroyed: surfaces released afterwards are safe; the destroyed device refuses */
    dev_destroy(dev);
    assert_int_equal(surf_get_desc(t, &desc), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_render_target(dev, 0, t), IS_ERR_INVALIDCALL);
    surf_release(t), surf_release(ds), surf_release(sys);
    dev_destroy(other);
}

/* The scissor, clip-plane and stencil-clear functions (core/raster_states.c): a NULL or destroyed device, NULL
 * pointers, indices at the limits (clamped to the last plane, as the runtime), planes not finite, rectangles
 * reversed or at the int limits, flags and values out of range; and a draw with every state of that file on. */
static void test_raster_state_edges(void **state)
{
    (void)state;
    is_rect r = {0, 0, 1, 1};
    float p[4] = {0, 0, 0, 1};
    assert_int_equal(dev_set_scissor_rect(NULL, &r), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_scissor_rect(NULL, &r), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_clip_plane(NULL, 0, p), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_clip_plane(NULL, 0, p), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_clear_rects_stencil(NULL, 1, &r, IS_CLEAR_STENCIL, 0, 1.0f, 0), IS_ERR_INVALIDCALL);
    draw_fixture f;
    fixture_make(&f, 6, 6);
    fixture_bind(&f);
    is_device *dev = f.dev;
    assert_int_equal(dev_set_scissor_rect(dev, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_scissor_rect(dev, NULL), IS_ERR_INVALIDCALL);
    const is_rect odd[] = {{INT32_MIN, INT32_MIN, INT32_MAX, INT32_MAX}, {INT32_MAX, INT32_MAX, INT32_MIN, INT32_MIN},
                           {5, 5, 5, 5}, {W, H, W + 9, H + 9}};
    assert_int_equal(dev_set_render_state(dev, IS_RS_SCISSORTESTENABLE, 1), IS_OK);
    for (size_t k = 0; k < sizeof odd / sizeof odd[0]; k++) {
        assert_int_equal(dev_set_scissor_rect(dev, &odd[k]), IS_OK);
        assert_int_equal(dev_get_scissor_rect(dev, &r), IS_OK);
        assert_memory_equal(&r, &odd[k], sizeof r);
        assert_int_equal(dev_clear_rects_stencil(dev, 4, odd, IS_CLEAR_TARGET | IS_CLEAR_STENCIL, 0, 0.5f, UINT32_MAX),
                         IS_OK);
        assert_int_equal(dev_clear_rects_stencil(dev, 0, NULL, IS_CLEAR_STENCIL | IS_CLEAR_ZBUFFER, 0, 0.5f, 0), IS_OK);
        assert_true(ok_or_invalid(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 2)));
    }
    assert_int_equal(dev_clear_rects_stencil(dev, 0, NULL, 0x10, 0, 0.5f, 0), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_clear_rects_stencil(dev, 0, NULL, IS_CLEAR_STENCIL, 0, NAN, 0), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_clear_rects_stencil(dev, UINT_MAX, NULL, IS_CLEAR_STENCIL, 0, 1.0f, 0), IS_OK);
    const unsigned idx[] = {0, 5, 6, 100, UINT_MAX};
    for (size_t k = 0; k < sizeof idx / sizeof idx[0]; k++) {
        assert_int_equal(dev_set_clip_plane(dev, idx[k], p), IS_OK);
        assert_int_equal(dev_get_clip_plane(dev, idx[k], p), IS_OK);
        assert_int_equal(dev_set_clip_plane(dev, idx[k], NULL), IS_ERR_INVALIDCALL);
        assert_int_equal(dev_get_clip_plane(dev, idx[k], NULL), IS_ERR_INVALIDCALL);
    }
    const float bad[3][4] = {{NAN, 0, 0, 0}, {0, INFINITY, 0, 0}, {0, 0, 0, -INFINITY}};
    for (int k = 0; k < 3; k++) assert_int_equal(dev_set_clip_plane(dev, 2, bad[k]), IS_ERR_INVALIDCALL);
    const float huge[4] = {FLT_MAX, -FLT_MAX, FLT_MAX, FLT_MAX};
    assert_int_equal(dev_set_clip_plane(dev, 3, huge), IS_OK);
    /* every state on at once, with extreme values */
    const struct { is_rs rs; uint32_t v; } on[] = {
        {IS_RS_ALPHATESTENABLE, 1}, {IS_RS_ALPHAREF, UINT32_MAX}, {IS_RS_ALPHAFUNC, IS_CMP_LESSEQUAL},
        {IS_RS_STENCILENABLE, 1}, {IS_RS_STENCILREF, UINT32_MAX}, {IS_RS_STENCILMASK, 0},
        {IS_RS_STENCILPASS, IS_STENCILOP_INVERT}, {IS_RS_TWOSIDEDSTENCILMODE, 1},
        {IS_RS_CCW_STENCILFAIL, IS_STENCILOP_DECR}, {IS_RS_CLIPPLANEENABLE, UINT32_MAX}, {IS_RS_CLIPPING, 0},
        {IS_RS_COLORWRITEENABLE, UINT32_MAX}, {IS_RS_CULLMODE, IS_CULL_NONE}};
    for (size_t k = 0; k < sizeof on / sizeof on[0]; k++) assert_int_equal(dev_set_render_state(dev, on[k].rs, on[k].v), IS_OK);
    assert_int_equal(dev_set_scissor_rect(dev, &odd[0]), IS_OK);
    assert_true(ok_or_invalid(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 2)));
    assert_true(ok_or_invalid(dev_draw_primitive(dev, IS_PT_LINELIST, 0, 3)));
    assert_true(ok_or_invalid(dev_draw_primitive(dev, IS_PT_POINTLIST, 0, 6)));
    assert_int_equal(dev_set_render_state(dev, IS_RS_CLIPPING, 1), IS_OK);
    assert_true(ok_or_invalid(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 2)));
    dev_destroy(dev);
    assert_int_equal(dev_set_scissor_rect(dev, &r), IS_ERR_INVALIDCALL);   /* destroyed: its struct lives on */
    assert_int_equal(dev_get_clip_plane(dev, 0, p), IS_ERR_INVALIDCALL);
    f.dev = NULL;
    fixture_free(&f);
}

/* SetFVF / GetFVF with NULL devices and outputs, every bit pattern class the runtime refuses (nothing changed). */
static void test_fvf_edges(void **state)
{
    (void)state;
    uint32_t v = 5;
    assert_int_equal(dev_set_fvf(NULL, 0x004u), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_fvf(NULL, &v), IS_ERR_INVALIDCALL);
    char err[128];
    is_device *dev = dev_create(4, 4, 1, err, sizeof err);
    assert_int_equal(dev_get_fvf(dev, NULL), IS_ERR_INVALIDCALL);
    const uint32_t bad[] = {0u, 0x006u, 0x00eu, 0x4002u, 0xffffffffu, 0x004u | 0xf00u, 0x1000u | 0x002u};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) assert_int_equal(dev_set_fvf(dev, bad[k]), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_fvf(dev, &v), IS_OK);
    assert_int_equal(v, 0u);
    assert_int_equal(dev_set_fvf(dev, 0x002u | 0x800u | 0xffff0000u), IS_OK);   /* 8 sets, every size code */
    dev_destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_null_device),   cmocka_unit_test(test_create_sizes),
        cmocka_unit_test(test_resources),     cmocka_unit_test(test_state_edges),
        cmocka_unit_test(test_draw_edges),    cmocka_unit_test(test_draw_strides),
        cmocka_unit_test(test_draw_instancing), cmocka_unit_test(test_adaptive_levels),
        cmocka_unit_test(test_ownership),     cmocka_unit_test(test_state_blocks),
        cmocka_unit_test(test_raster_state_edges), cmocka_unit_test(test_fvf_edges), cmocka_unit_test(test_surfaces),
    };
    return cmocka_run_group_tests_name("api_device", tests, NULL, NULL);
}
