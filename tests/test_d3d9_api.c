/* tests/test_d3d9_api.c -- the device behaving as the Direct3D 9 runtime does where the documentation says less
 * or otherwise (issue 27): SetViewport's depth range and viewports beyond the target, robust reads past a buffer's
 * end or from an unbound stream, the UP draws, the FLOAT16 / UDEC3 / DEC3N element types and render-state values
 * the runtime takes.  Every expected value is computed by hand from the rule it checks. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/device_internal.h"

#include "../core/hlsl.h"

/* oPos = POSITION0 (clip space, all four components), oD0 = TEXCOORD0. */
static void vs_clip_main(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    out->pos = in->position[0];
    out->attr[RS_ATTR_COLOR0] = in->texcoord[0];
}
static const is_vertex_shader vs_clip = {.name = "clip", .main = vs_clip_main, .outputs = IS_OUT_COLOR0};

/* A vertex of the clip fixture: clip-space position and colour. */
typedef struct clip_vertex { float pos[4], col[4]; } clip_vertex;
static const is_vertex_element clip_decl[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITION, 0},
                                              {0, 16, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, 0}, IS_DECL_END};

/* A w x h device drawing clip_vertex triangles: no culling, cleared to black and depth 1; *vb holds n vertices. */
static is_device *clip_device(int w, int h, const clip_vertex *v, size_t n, is_vertex_buffer **vb,
                              is_vertex_declaration **decl)
{
    is_device *dev = dev_create(w, h, 1, NULL, 0);
    assert_non_null(dev);
    assert_int_equal(dev_create_vertex_buffer(dev, n * sizeof *v, vb), IS_OK);
    memcpy(vb_lock(*vb), v, n * sizeof *v);
    assert_int_equal(dev_create_vertex_declaration(dev, clip_decl, decl), IS_OK);
    assert_int_equal(dev_set_vertex_declaration(dev, *decl), IS_OK);
    assert_int_equal(dev_set_vertex_shader(dev, &vs_clip), IS_OK);
    assert_int_equal(dev_set_stream_source(dev, 0, *vb, 0, sizeof *v), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE), IS_OK);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
    return dev;
}

/* Release what clip_device made. */
static void clip_release(is_device *dev, is_vertex_buffer *vb, is_vertex_declaration *decl)
{
    decl_release(decl);
    vb_release(vb);
    dev_destroy(dev);
}

/* ---------------- SetViewport ---------------- */

/* The depth written at pixel (x, y) by a triangle covering the target at clip z = 0.5 with viewport depth range
 * [min_z, max_z]; the viewport reads back as set. */
static float depth_with_range(float min_z, float max_z)
{
    const clip_vertex tri[3] = {{{-3, -1, 0.5f, 1}, {1, 1, 1, 1}}, {{1, 3, 0.5f, 1}, {1, 1, 1, 1}},
                                {{1, -1, 0.5f, 1}, {1, 1, 1, 1}}};
    is_vertex_buffer *vb;
    is_vertex_declaration *decl;
    is_device *dev = clip_device(8, 8, tri, 3, &vb, &decl);
    is_viewport vp = {0, 0, 8, 8, min_z, max_z}, got;
    assert_int_equal(dev_set_viewport(dev, &vp), IS_OK);
    assert_int_equal(dev_get_viewport(dev, &got), IS_OK);
    assert_memory_equal(&got, &vp, sizeof vp);   /* stored as given */
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
    const rs_target *rt = dev_render_target(dev);
    assert_int_equal(rt->color[4 * 8 + 4] & 0xff, 255);   /* drawn */
    float d = rt->depth[4 * 8 + 4];
    clip_release(dev, vb, decl);
    return d;
}

/* MinZ == MaxZ draws with MaxZ = MinZ + 0.001, and MinZ > MaxZ is accepted and drawn the same way (the runtime's
 * rule as DXVK records it): depth = MinZ + 0.5 * 0.001 at clip z 0.5; an ordinary range maps z linearly. */
static void test_viewport_depth_range(void **state)
{
    (void)state;
    assert_true(depth_with_range(0.25f, 0.75f) == 0.5f);
    float max_z = 0.3f + 0.001f, want = 0.3f + 0.5f * (max_z - 0.3f);
    float d = depth_with_range(0.3f, 0.3f);
    print_message("  MinZ = MaxZ = 0.3: depth %.9g (want %.9g)\n", (double)d, (double)want);
    assert_true(fabsf(d - want) <= 1e-7f);
    max_z = 0.6f + 0.001f, want = 0.6f + 0.5f * (max_z - 0.6f);
    d = depth_with_range(0.6f, 0.2f);
    assert_true(fabsf(d - want) <= 1e-7f);
}

/* A colourful scene of clip-space triangles: a gradient over the whole viewport and a small triangle partly
 * outside it. */
static const clip_vertex scene[6] = {
    {{-1, -1, 0.5f, 1}, {1, 0, 0, 1}}, {{-1, 1, 0.5f, 1}, {0, 1, 0, 1}}, {{1, -1, 0.5f, 1}, {0, 0, 1, 1}},
    {{0.2f, 0.3f, 0.25f, 1}, {1, 1, 0, 1}}, {{1.7f, 0.9f, 0.25f, 1}, {0, 1, 1, 1}}, {{0.9f, -0.6f, 0.25f, 2}, {1, 0, 1, 1}}};

/* The scene drawn on a tw x th target with viewport vp: the resolved pixels (tw * th) into px. */
static void draw_scene(int tw, int th, const is_viewport *vp, uint32_t *px)
{
    is_vertex_buffer *vb;
    is_vertex_declaration *decl;
    is_device *dev = clip_device(tw, th, scene, 6, &vb, &decl);
    assert_int_equal(dev_set_viewport(dev, vp), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 2), IS_OK);
    assert_int_equal(dev_get_render_target_data(dev, px, (size_t)tw * th), IS_OK);
    clip_release(dev, vb, decl);
}

/* A viewport reaching beyond the target is accepted and drawn clipped to the target: the target's pixels are
 * those of the same viewport on a target large enough to hold it; one outside the target draws nothing. */
static void test_viewport_beyond_target(void **state)
{
    (void)state;
    const is_viewport cases[] = {{8, 4, 20, 16, 0, 1}, {0, 0, 40, 24, 0, 1}, {13, 9, 3, 2, 0, 1}, {3, 10, 11, 30, 0, 1}};
    uint32_t small[16 * 16], big[64 * 64];
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        draw_scene(16, 16, &cases[c], small);
        draw_scene(64, 64, &cases[c], big);
        int lit = 0;
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 16; x++) {
                if (small[y * 16 + x] != big[y * 64 + x])
                    fail_msg("viewport %zu: pixel (%d, %d) 0x%08x, on the large target 0x%08x", c, x, y,
                             small[y * 16 + x], big[y * 64 + x]);
                lit += (small[y * 16 + x] & 0xffffff) != 0;
            }
        assert_true(lit > 0);
    }
    const is_viewport outside = {20, 2, 8, 8, 0, 1};
    draw_scene(16, 16, &outside, small);
    for (int p = 0; p < 16 * 16; p++) assert_int_equal(small[p], 0u);   /* as cleared */
    /* what is still refused: a NULL viewport, a width or height of 0, a depth outside [0, 1] */
    is_device *dev = dev_create(4, 4, 1, NULL, 0);
    const is_viewport bad[] = {{0, 0, 0, 4, 0, 1}, {0, 0, 4, 0, 0, 1}, {0, 0, 4, 4, -0.1f, 1}, {0, 0, 4, 4, 0, 1.5f},
                               {0, 0, 4, 4, NAN, 1}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        assert_int_equal(dev_set_viewport(dev, &bad[k]), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_viewport(dev, NULL), IS_ERR_INVALIDCALL);
    is_viewport got;
    assert_int_equal(dev_get_viewport(dev, &got), IS_OK);
    assert_true(got.width == 4 && got.height == 4 && got.max_z == 1.0f);   /* unchanged */
    /* Clear with a viewport beyond the target clears its part inside the target */
    const is_viewport vp = {2, 1, 100, 100, 0, 1};
    assert_int_equal(dev_set_viewport(dev, &vp), IS_OK);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET, IS_COLOR_ARGB(255, 255, 0, 0), 1.0f), IS_OK);
    uint32_t px[16];
    assert_int_equal(dev_get_render_target_data(dev, px, 16), IS_OK);
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) assert_int_equal(px[y * 4 + x], x >= 2 && y >= 1 ? 0xff0000ffu : 0xff000000u);
    dev_destroy(dev);
}

/* ---------------- robust reads ---------------- */

/* Lines in s. */
static int count_lines(const char *s)
{
    int n = 0;
    for (; *s; s++) n += *s == '\n';
    return n;
}

/* Points at pixel x = 2k (k the vertex), y = TEXCOORD0.x, colour R = POSITION0.y (a per-vertex tag, / 255) and G =
 * TEXCOORD0.y (a per-instance tag, / 255) on a 32 x 8 target. */
static void vs_tagged_main(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    out->pos = f4((2.0f * in->position[0].x + 0.25f) / 16.0f - 1.0f, 1.0f - 2.0f * (in->texcoord[0].x + 0.25f) / 8.0f,
                  0.5f, 1.0f);
    out->attr[RS_ATTR_COLOR0] = f4(in->position[0].y / 255.0f, in->texcoord[0].y / 255.0f, 0, 1);
}
static const is_vertex_shader vs_tagged = {.name = "tagged", .main = vs_tagged_main, .outputs = IS_OUT_COLOR0};

/* Reads past a vertex buffer's end, or from a stream without a buffer, return zeros and the draw succeeds; the
 * debug log gets one line per such draw, whatever the number of reads outside; the instanced path (fused, and
 * the reference path) reads zeros for the instances past the per-instance buffer's end. */
static void test_robust_reads(void **state)
{
    (void)state;
    for (int reference = 0; reference < 2; reference++) {
        is_device *dev = dev_create(32, 8, 1, NULL, 0);
        dev_set_reference_path(dev, reference != 0);
        is_vertex_buffer *vb0, *vb1;
        /* stream 0: 3 vertices (x = k, tag 100 + k) of the 8 the draw reads; stream 1: 2 instances (y, tag) of 4 */
        assert_int_equal(dev_create_vertex_buffer(dev, 3 * 8, &vb0), IS_OK);
        assert_int_equal(dev_create_vertex_buffer(dev, 2 * 8, &vb1), IS_OK);
        float (*v0)[2] = vb_lock(vb0), (*v1)[2] = vb_lock(vb1);
        for (int k = 0; k < 3; k++) v0[k][0] = (float)(k + 1), v0[k][1] = (float)(100 + k);
        for (int i = 0; i < 2; i++) v1[i][0] = (float)(2 + 2 * i), v1[i][1] = (float)(50 + i);
        static const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0},
                                               {1, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TEXCOORD, 0}, IS_DECL_END};
        is_vertex_declaration *decl;
        assert_int_equal(dev_create_vertex_declaration(dev, el, &decl), IS_OK);
        dev_set_vertex_declaration(dev, decl);
        dev_set_vertex_shader(dev, &vs_tagged);
        dev_set_stream_source(dev, 0, vb0, 0, 8);
        dev_set_stream_source(dev, 1, vb1, 0, 8);
        assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
        assert_string_equal(dev_debug_log(dev), "");
        /* 5 points, vertices 0..4: 3 and 4 read zeros (x 0, tag 0); stream 1 per vertex: 2..4 read zeros */
        assert_int_equal(dev_draw_primitive(dev, IS_PT_POINTLIST, 0, 5), IS_OK);
        assert_int_equal(count_lines(dev_debug_log(dev)), 1);
        assert_non_null(strstr(dev_debug_log(dev), "past its 24-byte buffer from vertex 3"));
        const rs_target *rt = dev_render_target(dev);
        for (int k = 0; k < 3; k++) assert_int_equal(rt->color[(k < 2 ? 2 + 2 * k : 0) * 32 + 2 * (k + 1)] & 0xff,
                                                     100 + k);
        assert_int_equal(rt->color[0] & 0xffff, 0);   /* vertices 3 and 4: (0, 0), black */
        /* instanced: 4 instances of vertices 0..1 (indexed); instances 2, 3 read zeros: y = 0, tag 0 */
        assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
        is_index_buffer *ib;
        assert_int_equal(dev_create_index_buffer(dev, 4, IS_FMT_INDEX16, &ib), IS_OK);
        const uint16_t idx[2] = {0, 1};
        memcpy(ib_lock(ib), idx, 4);
        dev_set_indices(dev, ib);
        dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | 4);
        dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1);
        assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_POINTLIST, 0, 0, 2, 0, 2), IS_OK);
        assert_int_equal(count_lines(dev_debug_log(dev)), 2);
        assert_non_null(strstr(dev_debug_log(dev), "from instance element 2"));
        rt = dev_render_target(dev);
        for (int i = 0; i < 2; i++)
            for (int k = 0; k < 2; k++) {
                uint32_t px = rt->color[(2 + 2 * i) * 32 + 2 * (k + 1)];
                assert_int_equal(px & 0xff, 100 + k);
                assert_int_equal((px >> 8) & 0xff, 50 + i);
            }
        for (int k = 0; k < 2; k++) assert_int_equal(rt->color[0 * 32 + 2 * (k + 1)] & 0xffff, 100 + k);
        /* an unbound stream: every read zeros, one line */
        dev_set_stream_source(dev, 1, NULL, 0, 0);
        assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_POINTLIST, 0, 0, 2, 0, 2), IS_OK);
        assert_int_equal(count_lines(dev_debug_log(dev)), 3);
        assert_non_null(strstr(dev_debug_log(dev), "stream 1, which has no vertex buffer"));
        /* vertex numbers past 2^32 - 1 are refused, not wrapped to vertex 0 */
        assert_int_equal(dev_draw_primitive(dev, IS_PT_POINTLIST, UINT32_MAX - 1, 2), IS_OK);
        assert_int_equal(dev_draw_primitive(dev, IS_PT_POINTLIST, UINT32_MAX - 1, 3), IS_ERR_INVALIDCALL);
        assert_int_equal(count_lines(dev_debug_log(dev)), 4);
        /* in bounds: nothing logged */
        dev_set_stream_source(dev, 1, vb1, 0, 8);
        dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | 2);
        assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_POINTLIST, 0, 0, 2, 0, 2), IS_OK);
        assert_int_equal(count_lines(dev_debug_log(dev)), 4);
        decl_release(decl);
        vb_release(vb0);
        vb_release(vb1);
        ib_release(ib);
        dev_destroy(dev);
    }
    assert_string_equal(dev_debug_log(NULL), "");
}

/* The debug log keeps the latest lines: many draws leave it bounded, ending with a whole line. */
static void test_debug_log_bounded(void **state)
{
    (void)state;
    is_device *dev = dev_create(4, 4, 1, NULL, 0);
    static const is_vertex_element el[] = {{3, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    is_vertex_declaration *decl;
    assert_int_equal(dev_create_vertex_declaration(dev, el, &decl), IS_OK);
    dev_set_vertex_declaration(dev, decl);
    dev_set_vertex_shader(dev, &vs_tagged);
    for (int k = 0; k < 200; k++) assert_int_equal(dev_draw_primitive(dev, IS_PT_POINTLIST, 0, 1), IS_OK);
    const char *log = dev_debug_log(dev);
    size_t len = strlen(log);
    assert_true(len > 0 && len < 2048 && log[len - 1] == '\n' && strncmp(log, "DrawPrimitive:", 14) == 0);
    assert_true(count_lines(log) > 10 && count_lines(log) < 200);
    decl_release(decl);
    dev_destroy(dev);
}

/* ---------------- UP draws ---------------- */

/* DrawPrimitiveUP and DrawIndexedPrimitiveUP draw the caller's memory exactly as the same data in buffers does;
 * afterwards stream 0 is unset (and the indices, for the indexed call), as the runtime leaves them; a count of 0
 * changes nothing; NULL data, a stride of 0 and a bad index format are refused, changing nothing. */
static void test_up_draws(void **state)
{
    (void)state;
    uint32_t want[16 * 16], got[16 * 16];
    is_vertex_buffer *vb, *other, *gvb;
    is_vertex_declaration *decl;
    is_index_buffer *ib, *gib;
    unsigned off, stride;
    /* the reference: the scene from a vertex buffer, indexed through a buffer */
    is_device *dev = clip_device(16, 16, scene, 6, &vb, &decl);
    const uint16_t idx16[6] = {3, 4, 5, 0, 1, 2};
    assert_int_equal(dev_create_index_buffer(dev, sizeof idx16, IS_FMT_INDEX16, &ib), IS_OK);
    memcpy(ib_lock(ib), idx16, sizeof idx16);
    dev_set_indices(dev, ib);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 6, 0, 2), IS_OK);
    assert_int_equal(dev_get_render_target_data(dev, want, 16 * 16), IS_OK);
    /* DrawIndexedPrimitiveUP with 32-bit indices: the same pixels; stream 0 and the indices unset */
    assert_int_equal(dev_create_vertex_buffer(dev, 64, &other), IS_OK);
    dev_set_stream_source(dev, 0, other, 16, 32);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
    const uint32_t idx32[6] = {3, 4, 5, 0, 1, 2};
    assert_int_equal(dev_draw_indexed_primitive_up(dev, IS_PT_TRIANGLELIST, 0, 6, 2, idx32, IS_FMT_INDEX32, scene,
                                                   sizeof scene[0]), IS_OK);
    assert_int_equal(dev_get_render_target_data(dev, got, 16 * 16), IS_OK);
    assert_memory_equal(got, want, sizeof want);
    assert_int_equal(dev_get_stream_source(dev, 0, &gvb, &off, &stride), IS_OK);
    assert_true(gvb == NULL && off == 0 && stride == 0);
    assert_int_equal(dev_get_indices(dev, &gib), IS_OK);
    assert_null(gib);
    assert_string_equal(dev_debug_log(dev), "");
    /* DrawPrimitiveUP in the index order above: the same pixels; stream 0 unset, the indices kept */
    const clip_vertex in_order[6] = {scene[3], scene[4], scene[5], scene[0], scene[1], scene[2]};
    dev_set_stream_source(dev, 0, other, 0, 32);
    dev_set_indices(dev, ib);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
    assert_int_equal(dev_draw_primitive_up(dev, IS_PT_TRIANGLELIST, 2, in_order, sizeof in_order[0]), IS_OK);
    assert_int_equal(dev_get_render_target_data(dev, got, 16 * 16), IS_OK);
    assert_memory_equal(got, want, sizeof want);
    assert_int_equal(dev_get_stream_source(dev, 0, &gvb, &off, &stride), IS_OK);
    assert_true(gvb == NULL && off == 0 && stride == 0);
    assert_int_equal(dev_get_indices(dev, &gib), IS_OK);
    assert_ptr_equal(gib, ib);
    /* refused or empty: nothing changes */
    dev_set_stream_source(dev, 0, other, 16, 32);
    assert_int_equal(dev_draw_primitive_up(dev, IS_PT_TRIANGLELIST, 2, NULL, 32), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_draw_primitive_up(dev, IS_PT_TRIANGLELIST, 2, scene, 0), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_draw_primitive_up(dev, (is_primtype)9, 2, scene, 32), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_draw_primitive_up(dev, IS_PT_TRIANGLELIST, 0, scene, 32), IS_OK);
    assert_int_equal(dev_draw_indexed_primitive_up(dev, IS_PT_TRIANGLELIST, 0, 6, 2, idx32, IS_FMT_A8R8G8B8, scene,
                                                   32), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_draw_indexed_primitive_up(dev, IS_PT_TRIANGLELIST, 0, 6, 2, NULL, IS_FMT_INDEX16, scene,
                                                   32), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_draw_indexed_primitive_up(dev, IS_PT_TRIANGLELIST, 0, 0, 2, idx16, IS_FMT_INDEX16, scene,
                                                   32), IS_OK);
    assert_int_equal(dev_get_stream_source(dev, 0, &gvb, &off, &stride), IS_OK);
    assert_true(gvb == other && off == 16 && stride == 32);
    assert_int_equal(dev_get_indices(dev, &gib), IS_OK);
    assert_ptr_equal(gib, ib);
    /* an index outside MinVertexIndex + NumVertices is refused as DrawIndexedPrimitive refuses it */
    assert_int_equal(dev_draw_indexed_primitive_up(dev, IS_PT_TRIANGLELIST, 0, 5, 2, idx16, IS_FMT_INDEX16, scene,
                                                   32), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(dev), "DrawIndexedPrimitiveUP"));
    dev_set_vertex_declaration(dev, NULL);
    assert_int_equal(dev_draw_primitive_up(dev, IS_PT_TRIANGLELIST, 2, scene, 32), IS_ERR_INVALIDCALL);
    vb_release(other);
    ib_release(ib);
    clip_release(dev, vb, decl);
}

/* ---------------- render-state values the runtime takes ---------------- */

/* The clear colour of draw_blended's target, with alpha da. */
#define BLEND_CLEAR(da) IS_COLOR_ARGB(da, 90, 140, 200)

/* The scene drawn with blending on, SRCBLEND src and DESTBLEND dst, over a target cleared to BLEND_CLEAR(da):
 * pixels into px; the states read back as set. */
static void draw_blended_over(uint32_t src, uint32_t dst, uint32_t da, uint32_t *px)
{
    clip_vertex v[6];
    memcpy(v, scene, sizeof v);
    for (int k = 0; k < 6; k++) v[k].col[3] = 0.25f + 0.1f * (float)k;   /* varied source alpha */
    is_vertex_buffer *vb;
    is_vertex_declaration *decl;
    is_device *dev = clip_device(16, 16, v, 6, &vb, &decl);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET, BLEND_CLEAR(da), 1.0f), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_ALPHABLENDENABLE, 1), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_SRCBLEND, src), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_DESTBLEND, dst), IS_OK);
    uint32_t a = 0, b = 0;
    assert_int_equal(dev_get_render_state(dev, IS_RS_SRCBLEND, &a), IS_OK);
    assert_int_equal(dev_get_render_state(dev, IS_RS_DESTBLEND, &b), IS_OK);
    assert_true(a == src && b == dst);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 2), IS_OK);
    assert_int_equal(dev_get_render_target_data(dev, px, 16 * 16), IS_OK);
    clip_release(dev, vb, decl);
}

/* draw_blended_over on a target with alpha 0. */
static void draw_blended(uint32_t src, uint32_t dst, uint32_t *px) { draw_blended_over(src, dst, 0, px); }

/* round(a * f / 255) by the textbook formula (no tie can occur: 255 is odd). */
static uint32_t mul255(uint32_t a, uint32_t f) { return (2u * a * f + 255u) / 510u; }

/* SRCBLEND SRCALPHASAT, DESTBLEND ONE over a target with alpha 128: each covered pixel is, by hand from D3D9's
 * definition, min(255, round(Cs * f) + Cd) with f = min(As, 255 - Ad) for R, G, B and min(255, As + Ad) for
 * alpha (its factor is 1); the source Cs, As is the same scene drawn ONE / ZERO.  Both sides of the min occur. */
static void test_blend_srcalphasat(void **state)
{
    (void)state;
    const uint32_t da = 128, argb = BLEND_CLEAR(da);   /* the target holds R in its low byte: */
    const uint32_t clear = (argb & 0xff00ff00u) | (argb >> 16 & 0xffu) | (argb & 0xffu) << 16;
    uint32_t src[256], got[256];
    draw_blended_over(IS_BLEND_ONE, IS_BLEND_ZERO, da, src);
    draw_blended_over(IS_BLEND_SRCALPHASAT, IS_BLEND_ONE, da, got);
    int below = 0, above = 0;
    for (int p = 0; p < 256; p++) {
        if (src[p] == clear) { assert_int_equal(got[p], clear); continue; }
        uint32_t as = src[p] >> 24, f = as < 255 - da ? as : 255 - da, want = 0;
        below += as < 255 - da, above += as > 255 - da;
        for (int c = 0; c < 4; c++) {
            uint32_t cs = (src[p] >> (8 * c)) & 0xffu, cd = (clear >> (8 * c)) & 0xffu;
            uint32_t v = (c == 3 ? cs : mul255(cs, f)) + cd;
            want |= (v > 255u ? 255u : v) << (8 * c);
        }
        assert_int_equal(got[p], want);
    }
    assert_true(below > 0 && above > 0);
}

/* Blend factors the runtime takes beyond the ten of D3D9's first table: BOTHSRCALPHA / BOTHINVSRCALPHA as
 * SRCBLEND set both factors (DESTBLEND overridden), as DESTBLEND they read as SRCALPHA / INVSRCALPHA; SRCALPHASAT
 * on a target with alpha 0 has SRCALPHA's colour factor (min(As, 1 - 0) = As; test_blend_srcalphasat has the
 * rest).  BLENDFACTOR (14) is refused. */
static void test_blend_values(void **state)
{
    (void)state;
    uint32_t want[256], got[256], plain[256];
    draw_blended(IS_BLEND_ONE, IS_BLEND_ZERO, plain);
    draw_blended(IS_BLEND_SRCALPHA, IS_BLEND_INVSRCALPHA, want);
    assert_memory_not_equal(want, plain, sizeof want);   /* the blend shows */
    draw_blended(IS_BLEND_BOTHSRCALPHA, IS_BLEND_ZERO, got);
    assert_memory_equal(got, want, sizeof want);
    draw_blended(IS_BLEND_INVSRCALPHA, IS_BLEND_SRCALPHA, want);
    draw_blended(IS_BLEND_BOTHINVSRCALPHA, IS_BLEND_ONE, got);
    assert_memory_equal(got, want, sizeof want);
    draw_blended(IS_BLEND_ONE, IS_BLEND_SRCALPHA, want);
    draw_blended(IS_BLEND_ONE, IS_BLEND_BOTHSRCALPHA, got);
    assert_memory_equal(got, want, sizeof want);
    draw_blended(IS_BLEND_SRCALPHA, IS_BLEND_ONE, want);
    draw_blended(IS_BLEND_SRCALPHASAT, IS_BLEND_ONE, got);
    for (int p = 0; p < 256; p++)   /* the colour the same; alpha's factor is 1, not As */
        assert_int_equal(got[p] & 0xffffffu, want[p] & 0xffffffu);
    is_device *dev = dev_create(4, 4, 1, NULL, 0);
    assert_int_equal(dev_set_render_state(dev, IS_RS_SRCBLEND, 14), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_render_state(dev, IS_RS_DESTBLEND, 0), IS_ERR_INVALIDCALL);
    dev_destroy(dev);
}

/* What the N-patch evaluator saw: calls, and the degrees of the last call. */
typedef struct eval_seen { unsigned long calls; uint32_t pos_degree, normal_degree; } eval_seen;
static eval_seen seen;
static void eval_record(const float3 v[3], const float3 n[3], float3 b, uint32_t pd, uint32_t nd, float3 *pos,
                        float3 *nrm)
{
    seen.calls++, seen.pos_degree = pd, seen.normal_degree = nd;
    *pos = add3(add3(scale3(v[0], b.x), scale3(v[1], b.y)), scale3(v[2], b.z));
    *nrm = n[0];
}

/* One triangle in N-patch mode with `segments`, NORMALDEGREE nd, adaptive when max_level is not 0 (MIN and MAX
 * then min_level, max_level): seen records the evaluator's calls; the states read back as set. */
static void draw_npatch(float segments, uint32_t nd, float min_level, float max_level)
{
    const float tri[3][6] = {{0, 0, 0.5f, 0, 0, -1}, {0.5f, 0, 0.5f, 0, 0, -1}, {0, 0.5f, 0.5f, 0, 0, -1}};
    is_device *dev = dev_create(16, 16, 1, NULL, 0);
    dev_set_threads(dev, 1);
    is_vertex_buffer *vb;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
    assert_int_equal(dev_create_vertex_buffer(dev, sizeof tri, &vb), IS_OK);
    memcpy(vb_lock(vb), tri, sizeof tri);
    assert_int_equal(dev_create_index_buffer(dev, 6, IS_FMT_INDEX16, &ib), IS_OK);
    const uint16_t idx[3] = {0, 1, 2};
    memcpy(ib_lock(ib), idx, sizeof idx);
    static const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
                                           {0, 12, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_NORMAL, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(dev, el, &decl), IS_OK);
    dev_set_vertex_declaration(dev, decl);
    dev_set_stream_source(dev, 0, vb, 0, sizeof tri[0]);
    dev_set_indices(dev, ib);
    dev_set_vertex_shader(dev, &vs_clip);
    dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE);
    dev_set_npatch_evaluator(dev, eval_record);
    assert_int_equal(dev_set_npatch_mode(dev, segments), IS_OK);
    float back = dev_get_npatch_mode(dev);
    assert_memory_equal(&back, &segments, sizeof back);
    assert_int_equal(dev_set_render_state(dev, IS_RS_NORMALDEGREE, nd), IS_OK);
    uint32_t got;
    assert_int_equal(dev_get_render_state(dev, IS_RS_NORMALDEGREE, &got), IS_OK);
    assert_int_equal(got, nd);
    if (max_level != 0.0f) {
        uint32_t mn, mx;
        memcpy(&mn, &min_level, 4), memcpy(&mx, &max_level, 4);
        assert_int_equal(dev_set_render_state(dev, IS_RS_ENABLEADAPTIVETESSELLATION, 1), IS_OK);
        assert_int_equal(dev_set_render_state(dev, IS_RS_MINTESSELLATIONLEVEL, mn), IS_OK);
        assert_int_equal(dev_set_render_state(dev, IS_RS_MAXTESSELLATIONLEVEL, mx), IS_OK);
        assert_int_equal(dev_get_render_state(dev, IS_RS_MAXTESSELLATIONLEVEL, &got), IS_OK);
        assert_int_equal(got, mx);
    }
    memset(&seen, 0, sizeof seen);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 3, 0, 1), IS_OK);
    decl_release(decl), vb_release(vb), ib_release(ib);
    dev_destroy(dev);
}

/* NORMALDEGREE CUBIC is stored and evaluated as QUADRATIC; SetNPatchMode beyond 256 is stored and drawn at 256;
 * MIN / MAXTESSELLATIONLEVEL below 1 are stored and an edge gets at least one segment. */
static void test_npatch_values(void **state)
{
    (void)state;
    draw_npatch(4.0f, IS_DEGREE_CUBIC, 0, 0);
    assert_int_equal(seen.calls, 15);   /* level 4: 5 * 6 / 2 points */
    assert_int_equal(seen.normal_degree, IS_DEGREE_QUADRATIC);
    assert_int_equal(seen.pos_degree, IS_DEGREE_CUBIC);
    draw_npatch(4.0f, IS_DEGREE_LINEAR, 0, 0);
    assert_int_equal(seen.normal_degree, IS_DEGREE_LINEAR);
    draw_npatch(1000.0f, IS_DEGREE_LINEAR, 0, 0);
    assert_int_equal(seen.calls, 257ul * 258ul / 2ul);   /* level 256 */
    draw_npatch(INFINITY, IS_DEGREE_LINEAR, 0, 0);
    assert_int_equal(seen.calls, 257ul * 258ul / 2ul);
    draw_npatch(NAN, IS_DEGREE_LINEAR, 0, 0);
    assert_int_equal(seen.calls, 0);   /* off: drawn as plain triangles */
    draw_npatch(8.0f, IS_DEGREE_LINEAR, 0.25f, 0.5f);   /* every edge level 0.5: one segment, the triangle */
    assert_int_equal(seen.calls, 3);
    draw_npatch(8.0f, IS_DEGREE_LINEAR, -3.0f, 0.75f);
    assert_int_equal(seen.calls, 3);
    draw_npatch(8.0f, IS_DEGREE_LINEAR, 0.5f, 2.0f);    /* the levels still clamp as D3D9's rule says: 2 */
    assert_int_equal(seen.calls, 6);
}

/* ---------------- element types ---------------- */

/* FLOAT16_2 / FLOAT16_4 convert every half exactly (normal, subnormal, signed zero, infinities, NaN), UDEC3 and
 * DEC3N unpack 10-bit fields (x in the low bits, the top two bits ignored) to (x, y, z, 1): values by hand. */
static void test_decl_types_float16_dec3(void **state)
{
    (void)state;
    const uint16_t h[8] = {0x3C00, 0xC000, 0x7BFF, 0x0001, 0x03FF, 0x8000, 0x3555, 0x0400};
    const float want[8] = {1.0f, -2.0f, 65504.0f, 0x1p-24f, 1023.0f * 0x1p-24f, -0.0f, 0.333251953125f, 0x1p-14f};
    for (int k = 0; k < 8; k += 4) {
        float4 r = decl_fetch(IS_DECLTYPE_FLOAT16_4, (const unsigned char *)&h[k]);
        const float got[4] = {r.x, r.y, r.z, r.w};
        for (int c = 0; c < 4; c++) {
            if (memcmp(&got[c], &want[k + c], 4) != 0)
                fail_msg("half 0x%04x: %a, want %a", h[k + c], (double)got[c], (double)want[k + c]);
        }
    }
    float4 r = decl_fetch(IS_DECLTYPE_FLOAT16_2, (const unsigned char *)&h[2]);
    assert_true(r.x == 65504.0f && r.y == 0x1p-24f && r.z == 0.0f && r.w == 1.0f);
    const uint16_t special[4] = {0x7C00, 0xFC00, 0x7E00, 0xFE01};
    r = decl_fetch(IS_DECLTYPE_FLOAT16_4, (const unsigned char *)special);
    assert_true(isinf(r.x) && r.x > 0 && isinf(r.y) && r.y < 0 && isnan(r.z) && isnan(r.w));
    uint32_t u = 1023u | 0u << 10 | 512u << 20 | 3u << 30;
    r = decl_fetch(IS_DECLTYPE_UDEC3, (const unsigned char *)&u);
    assert_true(r.x == 1023.0f && r.y == 0.0f && r.z == 512.0f && r.w == 1.0f);
    u = 511u | 512u << 10 | 1023u << 20 | 1u << 31;   /* 511, -512, -1 */
    r = decl_fetch(IS_DECLTYPE_DEC3N, (const unsigned char *)&u);
    assert_true(r.x == 1.0f && r.y == -1.0f && r.z == -1.0f / 511.0f && r.w == 1.0f);
    u = 1u | 513u << 10 | 0u << 20;                     /* 1, -511, 0 */
    r = decl_fetch(IS_DECLTYPE_DEC3N, (const unsigned char *)&u);
    assert_true(r.x == 1.0f / 511.0f && r.y == -1.0f && r.z == 0.0f);
    /* declarations take them with their sizes: FLOAT16_4 reads 8 bytes (an element at +4 overlaps it) */
    is_device *dev = dev_create(4, 4, 1, NULL, 0);
    is_vertex_declaration *d;
    const is_vertex_element ok[] = {{0, 0, IS_DECLTYPE_FLOAT16_4, 0, IS_DECLUSAGE_POSITION, 0},
                                    {0, 8, IS_DECLTYPE_UDEC3, 0, IS_DECLUSAGE_TEXCOORD, 0},
                                    {0, 12, IS_DECLTYPE_DEC3N, 0, IS_DECLUSAGE_NORMAL, 0},
                                    {0, 16, IS_DECLTYPE_FLOAT16_2, 0, IS_DECLUSAGE_TEXCOORD, 1}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(dev, ok, &d), IS_OK);
    decl_release(d);
    const is_vertex_element overlap[] = {{0, 0, IS_DECLTYPE_FLOAT16_4, 0, IS_DECLUSAGE_POSITION, 0},
                                         {0, 4, IS_DECLTYPE_UDEC3, 0, IS_DECLUSAGE_TEXCOORD, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(dev, overlap, &d), IS_ERR_INVALIDCALL);
    dev_destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_viewport_depth_range),
        cmocka_unit_test(test_viewport_beyond_target),
        cmocka_unit_test(test_decl_types_float16_dec3),
        cmocka_unit_test(test_robust_reads),
        cmocka_unit_test(test_up_draws),
        cmocka_unit_test(test_blend_values),
        cmocka_unit_test(test_blend_srcalphasat),
        cmocka_unit_test(test_npatch_values),
        cmocka_unit_test(test_debug_log_bounded),
    };
    return cmocka_run_group_tests_name("d3d9_api", tests, NULL, NULL);
}
