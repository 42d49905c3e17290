/* tests/test_device.c -- the D3D9-style device: stream frequencies and their invalid calls, declarations, vertex
 * fetch formats, render states, the instanced fetch order (observed through points drawn at encoded pixels), and
 * draw-call validation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/device_internal.h"

#include "../core/hlsl.h"
enum { W = 64, H = 64 };

/* ---------------- stream frequencies ---------------- */

static void test_freq_valid(void **state)
{
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    uint32_t f = 0;
    assert_int_equal(dev_get_stream_source_freq(dev, 0, &f), IS_OK);
    assert_int_equal(f, 1u); /* default */
    assert_int_equal(dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | 12), IS_OK);
    assert_int_equal(dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1), IS_OK);
    assert_int_equal(dev_set_stream_source_freq(dev, 2, IS_STREAMSOURCE_INSTANCEDATA | 3), IS_OK);
    assert_int_equal(dev_set_stream_source_freq(dev, 3, 2), IS_OK); /* a plain divider */
    dev_get_stream_source_freq(dev, 0, &f);
    assert_int_equal(f, IS_STREAMSOURCE_INDEXEDDATA | 12);
    dev_get_stream_source_freq(dev, 2, &f);
    assert_int_equal(f, IS_STREAMSOURCE_INSTANCEDATA | 3);
    /* stored as the runtime stores them (the documentation would refuse these): read back unchanged */
    const struct { unsigned stream; uint32_t setting; } stored[] = {
        {1, IS_STREAMSOURCE_INDEXEDDATA | 4}, {5, IS_STREAMSOURCE_INDEXEDDATA | 0},
        {0, IS_STREAMSOURCE_INDEXEDDATA | 0}, {3, IS_STREAMSOURCE_INSTANCEDATA | 0}};
    for (size_t k = 0; k < sizeof stored / sizeof stored[0]; k++) {
        assert_int_equal(dev_set_stream_source_freq(dev, stored[k].stream, stored[k].setting), IS_OK);
        assert_int_equal(dev_get_stream_source_freq(dev, stored[k].stream, &f), IS_OK);
        assert_int_equal(f, stored[k].setting);
    }
    dev_destroy(dev);
}

/* Every invalid case returns the error, leaves a message, and changes nothing. */
static void test_freq_invalid(void **state)
{
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    const struct { unsigned stream; uint32_t setting; } bad[] = {   /* what the runtime refuses, no more */
        {0, IS_STREAMSOURCE_INSTANCEDATA | 1},                                /* INSTANCEDATA on stream 0 */
        {0, IS_STREAMSOURCE_INSTANCEDATA | 0},
        {0, IS_STREAMSOURCE_INDEXEDDATA | IS_STREAMSOURCE_INSTANCEDATA | 1},  /* both flags */
        {1, IS_STREAMSOURCE_INDEXEDDATA | IS_STREAMSOURCE_INSTANCEDATA | 1},
        {2, 0},                                                               /* a setting of 0 */
        {IS_MAX_STREAMS, 1},                                                  /* no such stream */
    };
    assert_int_equal(dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | 5), IS_OK);
    assert_int_equal(dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 2), IS_OK);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        uint32_t before[IS_MAX_STREAMS];
        for (unsigned s = 0; s < IS_MAX_STREAMS; s++) dev_get_stream_source_freq(dev, s, &before[s]);
        dev->err[0] = 0;
        assert_int_equal(dev_set_stream_source_freq(dev, bad[k].stream, bad[k].setting), IS_ERR_INVALIDCALL);
        assert_true(strlen(dev_last_error(dev)) > 0);
        for (unsigned s = 0; s < IS_MAX_STREAMS; s++) {
            uint32_t now;
            dev_get_stream_source_freq(dev, s, &now);
            assert_int_equal(now, before[s]);
        }
    }
    dev_destroy(dev);
}

/* ---------------- declarations and fetch ---------------- */

static void test_declaration_validation(void **state)
{
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    is_vertex_declaration *d = NULL;
    const is_vertex_element ok[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
                                    {1, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_TEXCOORD, 0},
                                    {1, 12, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TEXCOORD, 11},
                                    IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(dev, ok, &d), IS_OK);
    assert_int_equal(d->n, 3u);
    assert_int_equal(d->stream_mask, 3u);
    decl_release(d);
    const is_vertex_element overlap[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
                                         {0, 8, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TEXCOORD, 0}, IS_DECL_END};
    const is_vertex_element dup[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_TEXCOORD, 2},
                                     {1, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TEXCOORD, 2}, IS_DECL_END};
    const is_vertex_element badtype[] = {{0, 0, 42, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    const is_vertex_element badstream[] = {{16, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    const is_vertex_element badindex[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_TEXCOORD, 16}, IS_DECL_END};
    const is_vertex_element misaligned[] = {{0, 2, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    const is_vertex_element empty[] = {IS_DECL_END};
    const is_vertex_element *bad[] = {overlap, dup, badtype, badstream, badindex, misaligned, empty};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        d = NULL;
        assert_int_equal(dev_create_vertex_declaration(dev, bad[k], &d), IS_ERR_INVALIDCALL);
        assert_null(d);
    }
    dev_destroy(dev);
}

static void test_fetch_formats(void **state)
{
    unsigned char buf[16];
    float4 r;
    float fl[4] = {1.5f, -2.0f, 3.25f, 9.0f};
    memcpy(buf, fl, 16);
    r = decl_fetch(IS_DECLTYPE_FLOAT2, buf);
    assert_true(r.x == 1.5f && r.y == -2.0f && r.z == 0.0f && r.w == 1.0f);
    r = decl_fetch(IS_DECLTYPE_FLOAT3, buf);
    assert_true(r.z == 3.25f && r.w == 1.0f);
    r = decl_fetch(IS_DECLTYPE_FLOAT4, buf);
    assert_true(r.w == 9.0f);
    const unsigned char bgra[4] = {255, 0, 51, 102}; /* D3DCOLOR in memory: B, G, R, A */
    r = decl_fetch(IS_DECLTYPE_D3DCOLOR, bgra);
    assert_float_equal(r.x, 0.2f, 1e-6);
    assert_float_equal(r.y, 0.0f, 1e-6);
    assert_float_equal(r.z, 1.0f, 1e-6);
    assert_float_equal(r.w, 0.4f, 1e-6);
    r = decl_fetch(IS_DECLTYPE_UBYTE4, bgra);
    assert_true(r.x == 255.0f && r.z == 51.0f && r.w == 102.0f);
    const int16_t sh[4] = {-32768, 32767, -5, 7};
    memcpy(buf, sh, 8);
    r = decl_fetch(IS_DECLTYPE_SHORT2, buf);
    assert_true(r.x == -32768.0f && r.y == 32767.0f && r.z == 0.0f && r.w == 1.0f);
    r = decl_fetch(IS_DECLTYPE_SHORT4, buf);
    assert_true(r.z == -5.0f && r.w == 7.0f);
    r = decl_fetch(IS_DECLTYPE_SHORT2N, buf);
    assert_true(r.x == -1.0f && r.y == 1.0f);
}

/* ---------------- render states ---------------- */

static void test_render_states(void **state)
{
    is_device *dev = dev_create(W, H, 4, NULL, 0);
    uint32_t v;
    assert_int_equal(dev_get_render_state(dev, IS_RS_CULLMODE, &v), IS_OK);
    assert_int_equal(v, IS_CULL_CCW);
    dev_get_render_state(dev, IS_RS_ZFUNC, &v);
    assert_int_equal(v, IS_CMP_LESSEQUAL);
    dev_get_render_state(dev, IS_RS_POSITIONDEGREE, &v);
    assert_int_equal(v, IS_DEGREE_CUBIC);
    dev_get_render_state(dev, IS_RS_NORMALDEGREE, &v);
    assert_int_equal(v, IS_DEGREE_LINEAR);
    assert_int_equal(dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_CULLMODE, 7), IS_ERR_INVALIDCALL);
    dev_get_render_state(dev, IS_RS_CULLMODE, &v);
    assert_int_equal(v, IS_CULL_NONE); /* unchanged by the invalid call */
    assert_int_equal(dev_set_render_state(dev, IS_RS_POSITIONDEGREE, IS_DEGREE_QUADRATIC), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_render_state(dev, IS_RS_NORMALDEGREE, 4), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(dev), "does not take value"));
    assert_int_equal(dev_set_render_state(dev, (is_rs)3, 1), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(dev), "unknown render state 3"));   /* not "bad value" */
    assert_int_equal(dev_set_render_state(dev, (is_rs)100000, 0), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(dev), "unknown render state 100000"));
    assert_int_equal(dev_set_npatch_mode(dev, NAN), IS_OK);   /* stored, as the runtime does: off */
    assert_true(isnan(dev_get_npatch_mode(dev)));
    assert_int_equal(dev_set_npatch_mode(dev, 4.0f), IS_OK);
    assert_true(dev_get_npatch_mode(dev) == 4.0f);
    is_viewport vp = {60, 0, 8, 8, 2, 1};   /* beyond the target: accepted (tests/test_d3d9_api.c); MinZ 2: not */
    assert_int_equal(dev_set_viewport(dev, &vp), IS_ERR_INVALIDCALL);
    vp = (is_viewport){8, 8, 16, 16, 0.25f, 0.75f};
    assert_int_equal(dev_set_viewport(dev, &vp), IS_OK);
    float c[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, 255, c, 2), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, 254, c, 2), IS_OK);
    assert_true(dev->consts.c[255].w == 8.0f);
    assert_null(dev_create(0, 10, 1, NULL, 0));
    assert_null(dev_create(10, 10, 3, NULL, 0));
    dev_destroy(dev);
}

/* ---------------- instanced fetch order ---------------- */

/* A shader that puts a point at pixel (x, y) = (POSITION0.x, TEXCOORD0.x) of a 64x64 target, with colour
 * R = POSITION0.y (the per-vertex tag) and G = TEXCOORD0.y (the per-instance tag), both / 255. */
static void vs_point_at(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    float x = in->position[0].x, y = in->texcoord[0].x;
    out->pos = f4(2.0f * x / W - 1.0f, 1.0f - 2.0f * y / H, 0.5f, 1.0f);
    out->attr[RS_ATTR_COLOR0] = f4(in->position[0].y / 255.0f, in->texcoord[0].y / 255.0f, 0, 1);
}
static const is_vertex_shader vs_point = {.name = "point_at", .main = vs_point_at, .outputs = IS_OUT_COLOR0};

/* The two-stream point fixture: stream 0 holds 16 records (x = 3k, vertex tag 100 + k), stream 1 16 records
 * (y = 2 + 3i, instance tag 10 + i), the index list {2, 0, 3, 1}, vs_point; the frequencies are the caller's. */
typedef struct points_fixture {
    is_device *dev;
    is_vertex_buffer *vb0, *vb1;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
} points_fixture;
static const uint16_t points_list[4] = {2, 0, 3, 1};

/* A device with the fixture bound. */
static points_fixture points_setup(void)
{
    points_fixture f;
    f.dev = dev_create(W, H, 1, NULL, 0);
    assert_non_null(f.dev);
    assert_int_equal(dev_create_vertex_buffer(f.dev, 16 * 8, &f.vb0), IS_OK);
    assert_int_equal(dev_create_vertex_buffer(f.dev, 8 * 16, &f.vb1), IS_OK);
    assert_int_equal(dev_create_index_buffer(f.dev, 4 * 2, IS_FMT_INDEX16, &f.ib), IS_OK);
    float (*v0)[2] = vb_lock(f.vb0), (*v1)[2] = vb_lock(f.vb1);
    for (int k = 0; k < 16; k++) v0[k][0] = (float)(3 * k), v0[k][1] = (float)(100 + k); /* x, vertex tag */
    for (int i = 0; i < 16; i++) v1[i][0] = (float)(2 + 3 * i), v1[i][1] = (float)(10 + i); /* y, instance tag */
    memcpy(ib_lock(f.ib), points_list, sizeof points_list);
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0},
                                    {1, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TEXCOORD, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(f.dev, el, &f.decl), IS_OK);
    dev_set_vertex_declaration(f.dev, f.decl);
    dev_set_vertex_shader(f.dev, &vs_point);
    dev_set_stream_source(f.dev, 0, f.vb0, 0, 8);
    dev_set_stream_source(f.dev, 1, f.vb1, 0, 8);
    dev_set_indices(f.dev, f.ib);
    return f;
}

/* Release the fixture and its device. */
static void points_teardown(points_fixture *f)
{
    decl_release(f->decl);
    vb_release(f->vb0);
    vb_release(f->vb1);
    ib_release(f->ib);
    dev_destroy(f->dev);
}

/* Vertices shaded by a draw of 4 points with stream 0 at f0 and stream 1 (instance tags, read by the shader) at
 * f1, indexed or not; *distinct gets the number of lit pixels (each (vertex, instance tag) lights its own). */
static uint64_t shaded_with(uint32_t f0, uint32_t f1, bool indexed, int *distinct)
{
    points_fixture f = points_setup();
    assert_int_equal(dev_set_stream_source_freq(f.dev, 0, f0), IS_OK);
    assert_int_equal(dev_set_stream_source_freq(f.dev, 1, f1), IS_OK);
    dev_clear(f.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
    if (indexed) assert_int_equal(dev_draw_indexed_primitive(f.dev, IS_PT_POINTLIST, 0, 0, 4, 0, 4), IS_OK);
    else assert_int_equal(dev_draw_primitive(f.dev, IS_PT_POINTLIST, 0, 4), IS_OK);
    uint64_t shaded = dev_vertices_shaded(f.dev);
    const rs_target *rt = dev_render_target(f.dev);
    *distinct = 0;
    for (int p = 0; p < W * H; p++) *distinct += (rt->color[p] & 0xffffff) != 0;
    points_teardown(&f);
    return shaded;
}

/* The runtime's instance count: stream 0's count when a stream the declaration reads is INSTANCEDATA (at least
 * 1: INDEXEDDATA | 0 draws once), 1 when none is; INSTANCEDATA | 0 gives every instance the first element; a
 * non-indexed draw draws its one instance. */
static void test_instance_count_rules(void **state)
{
    (void)state;
    const uint32_t IDX = IS_STREAMSOURCE_INDEXEDDATA, INST = IS_STREAMSOURCE_INSTANCEDATA;
    int lit;
    assert_int_equal(shaded_with(IDX | 3, INST | 1, true, &lit), 12);
    assert_int_equal(lit, 12);
    assert_int_equal(shaded_with(IDX | 0, INST | 1, true, &lit), 4);   /* at least one instance */
    assert_int_equal(lit, 4);
    assert_int_equal(shaded_with(IDX | 3, 1, true, &lit), 4);          /* no instanced stream: one */
    assert_int_equal(shaded_with(IDX | 3, INST | 0, true, &lit), 12);  /* three instances ... */
    assert_int_equal(lit, 4);                                           /* ... all reading element 0 */
    assert_int_equal(shaded_with(IDX | 3, INST | 1, false, &lit), 4);  /* non-indexed: one instance */
}

/* Draw `n_inst` instances (divider `div`) of an index list over 8 per-vertex records, with base vertex `base`;
 * check that exactly the expected (vertex, instance) combinations appear. */
static void check_instanced_fetch(unsigned n_inst, unsigned div, int base)
{
    points_fixture f = points_setup();
    is_device *dev = f.dev;
    const uint16_t *list = points_list;
    dev_set_threads(dev, 2);
    assert_int_equal(dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | n_inst), IS_OK);
    assert_int_equal(dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | div), IS_OK);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_POINTLIST, base, 0, 4, 0, 4), IS_OK);
    assert_int_equal(dev_vertices_shaded(dev), 4u * n_inst); /* post-transform cache: once per instance */
    const rs_target *rt = dev_render_target(dev);
    int expected = 0, found = 0;
    for (unsigned i = 0; i < n_inst; i++)
        for (int k = 0; k < 4; k++) {
            int vtx = list[k] + base, inst = (int)(i / div);
            int x = 3 * vtx, y = 2 + 3 * inst;
            uint32_t px = rt->color[y * W + x];
            assert_int_equal(px & 0xff, 100 + vtx);
            assert_int_equal((px >> 8) & 0xff, 10 + inst);
            expected++;
        }
    for (int p = 0; p < W * H; p++) found += (rt->color[p] & 0xffffff) != 0;
    int distinct_inst = (int)((n_inst + div - 1) / div);
    assert_int_equal(found, 4 * distinct_inst);
    (void)expected;
    points_teardown(&f);
}

static void test_instanced_fetch_order(void **state)
{
    check_instanced_fetch(1, 1, 0);
    check_instanced_fetch(5, 1, 0);
    check_instanced_fetch(6, 2, 3);
    check_instanced_fetch(7, 3, 1);
    check_instanced_fetch(16, 1, 4);
}

/* ---------------- draw validation ---------------- */

static void test_draw_errors(void **state)
{
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    is_vertex_buffer *vb;
    is_index_buffer *ib;
    dev_create_vertex_buffer(dev, 8 * 4, &vb);
    dev_create_index_buffer(dev, 2 * 6, IS_FMT_INDEX16, &ib);
    uint16_t *idx = ib_lock(ib);
    const uint16_t list[6] = {0, 1, 2, 2, 1, 9};
    memcpy(idx, list, sizeof list);
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    is_vertex_declaration *decl;
    dev_create_vertex_declaration(dev, el, &decl);
    /* no shader / declaration yet */
    dev_set_indices(dev, ib);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 4, 0, 1), IS_ERR_INVALIDCALL);
    dev_set_vertex_shader(dev, &vs_point);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 4, 0, 1), IS_ERR_INVALIDCALL);
    dev_set_vertex_declaration(dev, decl);
    /* no stream bound: the reads are zeros and the draw succeeds (robust reads, tests/test_d3d9_api.c) */
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 4, 0, 1), IS_OK);
    dev_set_stream_source(dev, 0, vb, 0, 8);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 4, 0, 1), IS_OK);
    /* index 9 outside MinVertexIndex + NumVertices */
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 4, 0, 2), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(dev), "index 9"));
    /* beyond the vertex buffer: zeros there, the draw succeeds */
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 2, 0, 4, 0, 1), IS_OK);
    /* beyond the index buffer, zero primitives, unknown type */
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 4, 3, 2), IS_ERR_INVALIDCALL);
    /* zero primitives or vertices: the runtime draws nothing and succeeds (whatever else is wrong then) */
    uint64_t drawn = dev_stats(dev)->prims_drawn;
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 4, 0, 0), IS_OK);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 0, 0, 1), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, (is_primtype)9, 0, 0), IS_OK);
    assert_true(dev_stats(dev)->prims_drawn == drawn);
    assert_int_equal(dev_draw_primitive(dev, (is_primtype)9, 0, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 2, 1), IS_OK);   /* past the end: zeros */
    /* a non-indexed draw with instancing set draws its one instance and succeeds, as the runtime does */
    dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | 2);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 4, 0, 1), IS_OK);
    /* a released buffer is unbound: the stream reads zeros */
    vb_release(vb);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 4, 0, 1), IS_OK);
    assert_non_null(strstr(dev_debug_log(dev), "no vertex buffer"));
    decl_release(decl);
    ib_release(ib);
    dev_destroy(dev);
}

/* Strips and fans become the same triangles as the equivalent list (strip winding alternates, as D3D9). */
static void vs_xy(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    out->pos = f4(in->position[0].x, in->position[0].y, 0.5f, 1.0f);
    out->attr[RS_ATTR_COLOR0] = f4(1, 1, 1, 1);
}
static const is_vertex_shader vs_pass = {.name = "xy", .main = vs_xy, .outputs = IS_OUT_COLOR0};

static uint64_t count_lit(const rs_target *rt)
{
    uint64_t n = 0;
    for (int p = 0; p < rt->width * rt->height; p++) n += (rt->color[p] & 0xff) != 0;
    return n;
}

static void test_strip_fan(void **state)
{
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    is_vertex_buffer *vb;
    dev_create_vertex_buffer(dev, 8 * 4, &vb);
    /* a quad as a strip: (-1,1) (1,1) (-1,-1) (1,-1): clockwise on screen for the first triangle */
    const float strip[8] = {-0.5f, 0.5f, 0.5f, 0.5f, -0.5f, -0.5f, 0.5f, -0.5f};
    memcpy(vb_lock(vb), strip, sizeof strip);
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    is_vertex_declaration *decl;
    dev_create_vertex_declaration(dev, el, &decl);
    dev_set_vertex_declaration(dev, decl);
    dev_set_vertex_shader(dev, &vs_pass);
    dev_set_stream_source(dev, 0, vb, 0, 8);
    dev_clear(dev, IS_CLEAR_TARGET, 0, 1.0f);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLESTRIP, 0, 2), IS_OK);
    uint64_t strip_px = count_lit(dev_render_target(dev));
    assert_int_equal(dev_stats(dev)->prims_culled, 0); /* both triangles front-facing under CULL_CCW */
    assert_int_equal(strip_px, 32u * 32u);
    /* the same quad as a fan: (-,+) (+,+) (+,-) (-,-) */
    const float fan[8] = {-0.5f, 0.5f, 0.5f, 0.5f, 0.5f, -0.5f, -0.5f, -0.5f};
    memcpy(vb_lock(vb), fan, sizeof fan);
    dev_clear(dev, IS_CLEAR_TARGET, 0, 1.0f);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLEFAN, 0, 2), IS_OK);
    assert_int_equal(count_lit(dev_render_target(dev)), strip_px);
    decl_release(decl);
    vb_release(vb);
    dev_destroy(dev);
}

/* ---------------- math and grid ---------------- */

static void test_math(void **state)
{
    float4x4 p = mat_perspective_fov_lh(1.0f, 2.0f, 0.5f, 10.0f);
    float ys = 1.0f / tanf(0.5f);
    assert_float_equal(p.m[1][1], ys, 1e-6);
    assert_float_equal(p.m[0][0], ys / 2.0f, 1e-6);
    assert_float_equal(p.m[2][2], 10.0f / 9.5f, 1e-6);
    assert_float_equal(p.m[2][3], 1.0f, 0);
    assert_float_equal(p.m[3][2], -0.5f * 10.0f / 9.5f, 1e-6);
    /* near plane maps to z = 0, far to z = w */
    float4 n = mul4(f4(0, 0, 0.5f, 1), &p), f = mul4(f4(0, 0, 10.0f, 1), &p);
    assert_float_equal(n.z / n.w, 0.0f, 1e-6);
    assert_float_equal(f.z / f.w, 1.0f, 1e-6);
    /* LookAtLH: the eye goes to the origin, the target onto +z */
    float4x4 v = mat_look_at_lh(f3(1, 2, -5), f3(1, 2, 0), f3(0, 1, 0));
    float4 e = mul4(f4(1, 2, -5, 1), &v), t = mul4(f4(1, 2, 0, 1), &v);
    assert_float_equal(e.x, 0, 1e-6);
    assert_float_equal(e.z, 0, 1e-6);
    assert_float_equal(t.z, 5.0f, 1e-6);
    /* RotationY by 90 degrees takes +x to -z (left-handed, D3DX) */
    float4x4 r = mat_rotation_y(1.57079632679f);
    float4 x = mul4(f4(1, 0, 0, 1), &r);
    assert_float_equal(x.z, -1.0f, 1e-6);
    /* mat_mul applies the left matrix first */
    float4x4 tr = mat_translation(1, 0, 0), sc = mat_scaling(2, 2, 2), ts = mat_mul(&tr, &sc);
    float4 o = mul4(f4(0, 0, 0, 1), &ts);
    assert_float_equal(o.x, 2.0f, 0);
    float4x4 inv;
    assert_true(mat_inverse(&ts, &inv));
    float4x4 id = mat_mul(&ts, &inv);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) assert_float_equal(id.m[i][j], i == j, 1e-6);
    float4x4 zero = {{{0}}};
    assert_false(mat_inverse(&zero, &inv));
}

static void test_grid(void **state)
{
    for (int L = 1; L <= 17; L++) {
        size_t np = core_grid_points(L), nt = core_grid_triangles(L);
        float3 *b = malloc(np * sizeof *b);
        uint32_t *idx = malloc(3 * nt * sizeof *idx);
        assert_int_equal(core_grid_regular(L, b, idx), np);
        assert_int_equal(np, (size_t)(L + 1) * (L + 2) / 2);
        double area = 0;
        for (size_t t = 0; t < nt; t++) {
            float3 p = b[idx[3 * t]], q = b[idx[3 * t + 1]], s = b[idx[3 * t + 2]];
            for (int c = 0; c < 3; c++) assert_true(idx[3 * t + c] < np);
            /* signed area in (b1, b2): all positive = same winding as (v0, v1, v2) */
            double a = ((double)q.y - p.y) * ((double)s.z - p.z) - ((double)q.z - p.z) * ((double)s.y - p.y);
            assert_true(a > 0);
            area += a / 2;
        }
        assert_float_equal(area, 0.5, 1e-9);
        /* mirrored edge points hold the same floats swapped; corners are exact */
        for (int i = 0; i <= L; i++) {
            float3 a = b[core_grid_index(L, i, 0)], m = b[core_grid_index(L, L - i, 0)];
            assert_true(a.x == m.y && a.y == m.x && a.z == 0.0f);
        }
        assert_true(b[core_grid_index(L, 0, 0)].x == 1.0f && b[core_grid_index(L, L, 0)].y == 1.0f &&
                    b[core_grid_index(L, 0, L)].z == 1.0f);
        free(b);
        free(idx);
    }
}

/* The render-state defaults table of core/device.h (its comment, the one place they are written for users) is
 * what a new device holds: every row is read from the header and checked with GetRenderState; the table names
 * every state set_default_states sets (22 rows). */
static void test_render_state_defaults_documented(void **state)
{
    (void)state;
    static const struct { const char *name; uint32_t value; } known[] = {
        {"IS_ZB_TRUE", IS_ZB_TRUE}, {"IS_FILL_SOLID", IS_FILL_SOLID}, {"IS_SHADE_GOURAUD", IS_SHADE_GOURAUD},
        {"IS_BLEND_ONE", IS_BLEND_ONE}, {"IS_BLEND_ZERO", IS_BLEND_ZERO}, {"IS_CULL_CCW", IS_CULL_CCW},
        {"IS_CMP_LESSEQUAL", IS_CMP_LESSEQUAL}, {"IS_DEGREE_CUBIC", IS_DEGREE_CUBIC},
        {"IS_DEGREE_LINEAR", IS_DEGREE_LINEAR}, {"IS_PATCHEDGE_DISCRETE", IS_PATCHEDGE_DISCRETE},
        /* core/raster_states.c's */
        {"IS_CMP_ALWAYS", IS_CMP_ALWAYS}, {"IS_STENCILOP_KEEP", IS_STENCILOP_KEEP}};
    static const struct { const char *name; is_rs rs; } states[] = {
        {"IS_RS_ZENABLE", IS_RS_ZENABLE}, {"IS_RS_FILLMODE", IS_RS_FILLMODE}, {"IS_RS_SHADEMODE", IS_RS_SHADEMODE},
        {"IS_RS_ZWRITEENABLE", IS_RS_ZWRITEENABLE}, {"IS_RS_SRCBLEND", IS_RS_SRCBLEND},
        {"IS_RS_DESTBLEND", IS_RS_DESTBLEND}, {"IS_RS_CULLMODE", IS_RS_CULLMODE}, {"IS_RS_ZFUNC", IS_RS_ZFUNC},
        {"IS_RS_ALPHABLENDENABLE", IS_RS_ALPHABLENDENABLE}, {"IS_RS_MULTISAMPLEANTIALIAS", IS_RS_MULTISAMPLEANTIALIAS},
        {"IS_RS_POSITIONDEGREE", IS_RS_POSITIONDEGREE}, {"IS_RS_NORMALDEGREE", IS_RS_NORMALDEGREE},
        {"IS_RS_PATCHEDGESTYLE", IS_RS_PATCHEDGESTYLE}, {"IS_RS_DEPTHBIAS", IS_RS_DEPTHBIAS},
        {"IS_RS_SLOPESCALEDEPTHBIAS", IS_RS_SLOPESCALEDEPTHBIAS},
        {"IS_RS_ENABLEADAPTIVETESSELLATION", IS_RS_ENABLEADAPTIVETESSELLATION},
        {"IS_RS_MINTESSELLATIONLEVEL", IS_RS_MINTESSELLATIONLEVEL},
        {"IS_RS_MAXTESSELLATIONLEVEL", IS_RS_MAXTESSELLATIONLEVEL}, {"IS_RS_ADAPTIVETESS_X", IS_RS_ADAPTIVETESS_X},
        {"IS_RS_ADAPTIVETESS_Y", IS_RS_ADAPTIVETESS_Y}, {"IS_RS_ADAPTIVETESS_Z", IS_RS_ADAPTIVETESS_Z},
        {"IS_RS_ADAPTIVETESS_W", IS_RS_ADAPTIVETESS_W},
        /* core/raster_states.c's */
        {"IS_RS_ALPHATESTENABLE", IS_RS_ALPHATESTENABLE}, {"IS_RS_ALPHAREF", IS_RS_ALPHAREF},
        {"IS_RS_ALPHAFUNC", IS_RS_ALPHAFUNC}, {"IS_RS_STENCILENABLE", IS_RS_STENCILENABLE},
        {"IS_RS_STENCILFAIL", IS_RS_STENCILFAIL}, {"IS_RS_STENCILZFAIL", IS_RS_STENCILZFAIL},
        {"IS_RS_STENCILPASS", IS_RS_STENCILPASS}, {"IS_RS_STENCILFUNC", IS_RS_STENCILFUNC},
        {"IS_RS_STENCILREF", IS_RS_STENCILREF}, {"IS_RS_STENCILMASK", IS_RS_STENCILMASK},
        {"IS_RS_STENCILWRITEMASK", IS_RS_STENCILWRITEMASK}, {"IS_RS_CLIPPING", IS_RS_CLIPPING},
        {"IS_RS_CLIPPLANEENABLE", IS_RS_CLIPPLANEENABLE}, {"IS_RS_COLORWRITEENABLE", IS_RS_COLORWRITEENABLE},
        {"IS_RS_SCISSORTESTENABLE", IS_RS_SCISSORTESTENABLE}, {"IS_RS_TWOSIDEDSTENCILMODE", IS_RS_TWOSIDEDSTENCILMODE},
        {"IS_RS_CCW_STENCILFAIL", IS_RS_CCW_STENCILFAIL}, {"IS_RS_CCW_STENCILZFAIL", IS_RS_CCW_STENCILZFAIL},
        {"IS_RS_CCW_STENCILPASS", IS_RS_CCW_STENCILPASS}, {"IS_RS_CCW_STENCILFUNC", IS_RS_CCW_STENCILFUNC}};
    FILE *f = fopen("core/device.h", "r");
    assert_non_null(f);
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    assert_non_null(dev);
    char line[256];
    int rows = 0;
    while (fgets(line, sizeof line, f)) {
        char st[64], val[64];
        if (sscanf(line, " * | %63s | %63[^|]|", st, val) != 2 || strncmp(st, "IS_RS_", 6) != 0) continue;
        is_rs rs = (is_rs)-1;
        for (size_t k = 0; k < sizeof states / sizeof states[0]; k++)
            if (!strcmp(states[k].name, st)) rs = states[k].rs;
        if ((int)rs < 0) fail_msg("core/device.h's defaults table names %s, which this test does not know", st);
        uint32_t want = 0, got = 0;
        float fv;
        bool found = false;
        for (size_t k = 0; k < sizeof known / sizeof known[0]; k++)
            if (!strncmp(val, known[k].name, strlen(known[k].name))) want = known[k].value, found = true;
        if (!found && strstr(val, "as its bits") && sscanf(val, "%ff", &fv) == 1) memcpy(&want, &fv, 4), found = true;
        char *end = NULL;
        unsigned long num = strtoul(val, &end, 0);   /* decimal or 0x... */
        if (!found && end != val) want = (uint32_t)num, found = true;
        if (!found) fail_msg("%s: cannot read the default '%s'", st, val);
        assert_int_equal(dev_get_render_state(dev, rs, &got), IS_OK);
        if (got != want) fail_msg("%s: the header says %s (0x%x), a new device holds 0x%x", st, val, want, got);
        rows++;
    }
    fclose(f);
    dev_destroy(dev);
    assert_int_equal(rows, (int)(sizeof states / sizeof states[0]));
}

/* GetRenderTargetData in one call: the resolved pixels of a cleared target; a NULL buffer or one too small is
 * refused. */
static void test_get_render_target_data(void **state)
{
    (void)state;
    is_device *dev = dev_create(5, 3, 4, NULL, 0);
    assert_non_null(dev);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET, IS_COLOR_ARGB(255, 10, 20, 30), 1.0f), IS_OK);
    uint32_t px[15];
    memset(px, 0, sizeof px);
    assert_int_equal(dev_get_render_target_data(dev, px, 14), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_data(dev, NULL, 15), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_data(NULL, px, 15), IS_ERR_INVALIDCALL);
    assert_int_equal(px[0], 0u);
    assert_int_equal(dev_get_render_target_data(dev, px, 15), IS_OK);
    for (int k = 0; k < 15; k++) assert_int_equal(px[k], 0xff1e140au);   /* R 10, G 20, B 30, A 255 */
    dev_destroy(dev);
}

/* Resources belong to their device: another device's buffers and declarations are refused by the setters; a
 * resource released after dev_destroy is no use-after-free (the sanitizer stage runs this under ASan). */
static void test_resource_ownership(void **state)
{
    (void)state;
    is_device *a = dev_create(8, 8, 1, NULL, 0), *b = dev_create(8, 8, 1, NULL, 0);
    assert_non_null(a);
    assert_non_null(b);
    is_vertex_buffer *vb;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
    static const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_buffer(a, 64, &vb), IS_OK);
    assert_int_equal(dev_create_index_buffer(a, 64, IS_FMT_INDEX16, &ib), IS_OK);
    assert_int_equal(dev_create_vertex_declaration(a, el, &decl), IS_OK);
    assert_int_equal(dev_set_stream_source(b, 0, vb, 0, 12), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_indices(b, ib), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_vertex_declaration(b, decl), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(b), "another device"));
    assert_int_equal(dev_set_stream_source(a, 0, vb, 0, 12), IS_OK);
    assert_int_equal(dev_set_indices(a, ib), IS_OK);
    dev_destroy(a);          /* with its resources still alive and bound */
    vb_release(vb);          /* then the resources: no use-after-free */
    ib_release(ib);
    decl_release(decl);
    assert_int_equal(dev_create_vertex_buffer(NULL, 64, &vb), IS_ERR_INVALIDCALL);
    dev_destroy(b);
}

/* The getter of every setter reads back what was set (and NULL / zeros before), refusing NULL outputs and
 * streams or registers out of range. */
static void test_getters(void **state)
{
    (void)state;
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_vertex_buffer *vb, *gvb = (is_vertex_buffer *)1;
    is_index_buffer *ib, *gib = (is_index_buffer *)1;
    is_vertex_declaration *decl, *gdecl = (is_vertex_declaration *)1;
    const is_vertex_shader *gvs = (const is_vertex_shader *)1;
    unsigned off = 1, stride = 1;
    assert_int_equal(dev_get_stream_source(dev, 3, &gvb, &off, &stride), IS_OK);
    assert_true(gvb == NULL && off == 0 && stride == 0);
    assert_int_equal(dev_get_indices(dev, &gib), IS_OK);
    assert_null(gib);
    assert_int_equal(dev_get_vertex_declaration(dev, &gdecl), IS_OK);
    assert_null(gdecl);
    assert_int_equal(dev_get_vertex_shader(dev, &gvs), IS_OK);
    assert_null(gvs);
    static const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_buffer(dev, 64, &vb), IS_OK);
    assert_int_equal(dev_create_index_buffer(dev, 64, IS_FMT_INDEX32, &ib), IS_OK);
    assert_int_equal(dev_create_vertex_declaration(dev, el, &decl), IS_OK);
    assert_int_equal(dev_set_stream_source(dev, 3, vb, 8, 12), IS_OK);
    assert_int_equal(dev_set_indices(dev, ib), IS_OK);
    assert_int_equal(dev_set_vertex_declaration(dev, decl), IS_OK);
    assert_int_equal(dev_set_vertex_shader(dev, &vs_point), IS_OK);
    const float c[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, 254, c, 2), IS_OK);
    assert_int_equal(dev_get_stream_source(dev, 3, &gvb, &off, &stride), IS_OK);
    assert_true(gvb == vb && off == 8 && stride == 12);
    assert_int_equal(dev_get_indices(dev, &gib), IS_OK);
    assert_ptr_equal(gib, ib);
    assert_int_equal(dev_get_vertex_declaration(dev, &gdecl), IS_OK);
    assert_ptr_equal(gdecl, decl);
    assert_int_equal(dev_get_vertex_shader(dev, &gvs), IS_OK);
    assert_ptr_equal(gvs, &vs_point);
    float got[8] = {0};
    assert_int_equal(dev_get_vertex_shader_constant_f(dev, 254, got, 2), IS_OK);
    assert_memory_equal(got, c, sizeof c);
    /* refused, nothing written */
    assert_int_equal(dev_get_vertex_shader_constant_f(dev, 255, got, 2), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_stream_source(dev, IS_MAX_STREAMS, &gvb, &off, &stride), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_stream_source(dev, 0, NULL, &off, &stride), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_indices(dev, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_vertex_declaration(NULL, &gdecl), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_vertex_shader(dev, NULL), IS_ERR_INVALIDCALL);
    vb_release(vb);   /* releasing unbinds: the getters say so */
    assert_int_equal(dev_get_stream_source(dev, 3, &gvb, &off, &stride), IS_OK);
    assert_null(gvb);
    ib_release(ib);
    decl_release(decl);
    dev_destroy(dev);
}

/* Clear clears the viewport, not the whole target, and with rectangles only their part of the viewport; count 0
 * with rectangles clears nothing (as the runtime does). */
static void test_clear_viewport_and_rects(void **state)
{
    (void)state;
    is_device *dev = dev_create(16, 8, 4, NULL, 0);
    uint32_t px[16 * 8];
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET, IS_COLOR_ARGB(255, 0, 0, 255), 1.0f), IS_OK);   /* blue */
    is_viewport vp = {4, 2, 8, 4, 0.0f, 1.0f};
    assert_int_equal(dev_set_viewport(dev, &vp), IS_OK);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET, IS_COLOR_ARGB(255, 255, 0, 0), 1.0f), IS_OK);   /* red */
    assert_int_equal(dev_get_render_target_data(dev, px, 16 * 8), IS_OK);
    for (int y = 0; y < 8; y++)
        for (int x = 0; x < 16; x++) {
            bool in = x >= 4 && x < 12 && y >= 2 && y < 6;
            assert_int_equal(px[y * 16 + x], in ? 0xff0000ffu : 0xffff0000u);
        }
    /* two rectangles, one partly outside the viewport: only their parts inside it turn green */
    const is_rect r[2] = {{0, 0, 6, 3}, {10, 5, 40, 40}};
    assert_int_equal(dev_clear_rects(dev, 2, r, IS_CLEAR_TARGET, IS_COLOR_ARGB(255, 0, 255, 0), 1.0f), IS_OK);
    assert_int_equal(dev_get_render_target_data(dev, px, 16 * 8), IS_OK);
    assert_int_equal(px[2 * 16 + 4], 0xff00ff00u);    /* (4, 2): in rect 0 and the viewport */
    assert_int_equal(px[2 * 16 + 6], 0xff0000ffu);    /* (6, 2): viewport, not rect 0 */
    assert_int_equal(px[0 * 16 + 0], 0xffff0000u);    /* (0, 0): rect 0, outside the viewport */
    assert_int_equal(px[5 * 16 + 11], 0xff00ff00u);   /* (11, 5): rect 1 inside the viewport */
    assert_int_equal(px[6 * 16 + 11], 0xffff0000u);   /* (11, 6): below the viewport */
    assert_int_equal(dev_clear_rects(dev, 0, r, IS_CLEAR_TARGET, IS_COLOR_ARGB(255, 9, 9, 9), 1.0f), IS_OK);
    uint32_t again[16 * 8];
    assert_int_equal(dev_get_render_target_data(dev, again, 16 * 8), IS_OK);
    assert_memory_equal(again, px, sizeof px);   /* nothing cleared */
    dev_destroy(dev);
}

/* Values the runtime accepts are stored and read back, with their fallback: SHADEMODE PHONG draws as GOURAUD,
 * ZENABLE USEW as TRUE (the same bytes). */
static void test_runtime_state_values(void **state)
{
    (void)state;
    uint32_t img[2][16 * 16];
    const struct { is_rs rs; uint32_t v, same_as; } cases[] = {
        {IS_RS_SHADEMODE, IS_SHADE_PHONG, IS_SHADE_GOURAUD}, {IS_RS_ZENABLE, IS_ZB_USEW, IS_ZB_TRUE}};
    for (size_t c = 0; c < 2; c++) {
        for (int k = 0; k < 2; k++) {
            is_device *dev = dev_create(16, 16, 1, NULL, 0);
            uint32_t v = k ? cases[c].v : cases[c].same_as, got = 0;
            assert_int_equal(dev_set_render_state(dev, cases[c].rs, v), IS_OK);
            assert_int_equal(dev_get_render_state(dev, cases[c].rs, &got), IS_OK);
            assert_int_equal(got, v);
            is_vertex_buffer *vb;
            assert_int_equal(dev_create_vertex_buffer(dev, 3 * 16, &vb), IS_OK);
            float (*p)[4] = vb_lock(vb);   /* x, y of the target (vs_point), colour tags */
            const float tri[3][4] = {{1, 1, 250, 10}, {14, 2, 10, 250}, {3, 14, 120, 120}};
            memcpy(p, tri, sizeof tri);
            static const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0},
                                                   {0, 8, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TEXCOORD, 0}, IS_DECL_END};
            is_vertex_declaration *decl;
            assert_int_equal(dev_create_vertex_declaration(dev, el, &decl), IS_OK);
            dev_set_vertex_declaration(dev, decl);
            dev_set_vertex_shader(dev, &vs_point);
            dev_set_stream_source(dev, 0, vb, 0, 16);
            dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE);
            dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
            assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
            assert_int_equal(dev_get_render_target_data(dev, img[k], 16 * 16), IS_OK);
            decl_release(decl);
            vb_release(vb);
            dev_destroy(dev);
        }
        assert_memory_equal(img[0], img[1], sizeof img[0]);
    }
}

/* The vertex shader's colour as given by its texcoord input, unclamped; the position in pixels. */
static void vs_raw_color_main(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    out->pos = f4(2.0f * in->position[0].x / W - 1.0f, 1.0f - 2.0f * in->position[0].y / H, 0.5f, 1.0f);
    out->attr[RS_ATTR_COLOR0] = in->texcoord[0];
}
static const is_vertex_shader vs_raw_color = {.name = "raw_color", .main = vs_raw_color_main,
                                              .outputs = IS_OUT_COLOR0};

/* COLOR0 is saturated per vertex before it is interpolated, as D3D9 does: a vertex colour of 2 (red) and -1
 * (green) counts as 1 and 0, so at the centroid of a triangle with the other two vertices black the red is about
 * a third (85 of 255), not two thirds (170, interpolating 2 and clamping the pixel). */
static void test_colors_saturated_per_vertex(void **state)
{
    (void)state;
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    is_vertex_buffer *vb;
    assert_int_equal(dev_create_vertex_buffer(dev, 3 * 24, &vb), IS_OK);
    float (*v)[6] = vb_lock(vb);   /* x, y, then the colour r, g, b, a */
    const float tri[3][6] = {{2, 2, 2, -1, 0, 1}, {60, 2, 0, 0, 0, 1}, {2, 60, 0, 0, 0, 1}};
    memcpy(v, tri, sizeof tri);
    static const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0},
                                           {0, 8, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, 0}, IS_DECL_END};
    is_vertex_declaration *decl;
    assert_int_equal(dev_create_vertex_declaration(dev, el, &decl), IS_OK);
    dev_set_vertex_declaration(dev, decl);
    dev_set_vertex_shader(dev, &vs_raw_color);
    dev_set_stream_source(dev, 0, vb, 0, 24);
    dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
    const rs_target *rt = dev_render_target(dev);
    uint32_t px = rt->color[21 * W + 21];   /* the centroid (21.3, 21.3) */
    print_message("  centroid: red %u, green %u\n", px & 0xff, (px >> 8) & 0xff);
    assert_true((px & 0xff) >= 80 && (px & 0xff) <= 90);
    assert_int_equal((px >> 8) & 0xff, 0);
    decl_release(decl);
    vb_release(vb);
    dev_destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_freq_valid),          cmocka_unit_test(test_freq_invalid),
        cmocka_unit_test(test_declaration_validation), cmocka_unit_test(test_fetch_formats),
        cmocka_unit_test(test_render_states),
        cmocka_unit_test(test_render_state_defaults_documented), cmocka_unit_test(test_get_render_target_data),
        cmocka_unit_test(test_resource_ownership), cmocka_unit_test(test_instance_count_rules),
        cmocka_unit_test(test_getters), cmocka_unit_test(test_clear_viewport_and_rects),
        cmocka_unit_test(test_runtime_state_values), cmocka_unit_test(test_colors_saturated_per_vertex),       cmocka_unit_test(test_instanced_fetch_order),
        cmocka_unit_test(test_draw_errors),         cmocka_unit_test(test_strip_fan),
        cmocka_unit_test(test_math),                cmocka_unit_test(test_grid),
    };
    return cmocka_run_group_tests_name("device", tests, NULL, NULL);
}
