/* tests/test_d3d9_pixel.c -- the device's D3D9 per-pixel and clipping API (core/raster_states.c): the render
 * states' values, SetScissorRect (default: the whole target, as the runtime sets it) with the scissor test on
 * draws and on Clear, Clear's stencil, COLORWRITEENABLE, the alpha test, the stencil test with two-sided stencil,
 * SetClipPlane (the runtime's index clamp) with CLIPPLANEENABLE and CLIPPING FALSE, and pre-transformed vertices
 * (POSITIONT without a vertex shader).  Pixels are computed by hand; each draw is also made on the reference path
 * and on 1 and 2 threads, which must give the same image. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../core/device.h"

enum { W = 8, H = 8 };
#define BLUE IS_COLOR_ARGB(255, 0, 0, 255)
#define BLUE_RGBA 0xffff0000u   /* BLUE as the target stores it (R in the low byte) */
#define BLACK IS_COLOR_ARGB(255, 0, 0, 0)

/* A vertex of the test shader: screen pixel (X, Y) (converted to clip space), depth z, D3DCOLOR (ARGB). */
typedef struct vtx { float x, y, z; uint32_t argb; } vtx;

static vtx at(double X, double Y, float z, uint32_t argb)
{
    return (vtx){(float)(X / (W * 0.5) - 1.0), (float)(1.0 - Y / (H * 0.5)), z, argb};
}

/* oPos = (x, y, z, 1), oD0 = COLOR0. */
static void vs_main(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    (void)c;
    out->pos = (rs_vec4){in->position[0].x, in->position[0].y, in->position[0].z, 1.0f};
    out->attr[RS_ATTR_COLOR0] = (rs_vec4){in->color[0].x, in->color[0].y, in->color[0].z, in->color[0].w};
}
static const is_vertex_shader vs = {.name = "xy_color", .main = vs_main, .outputs = IS_OUT_COLOR0};

/* A device with the test shader, its declaration and a vertex buffer of 64 vertices bound. */
typedef struct fixture { is_device *dev; is_vertex_buffer *vb; is_vertex_declaration *decl; } fixture;

static fixture setup(int samples)
{
    fixture f;
    f.dev = dev_create(W, H, samples, NULL, 0);
    assert_non_null(f.dev);
    assert_int_equal(dev_create_vertex_buffer(f.dev, 64 * sizeof(vtx), &f.vb), IS_OK);
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
                                    {0, 12, IS_DECLTYPE_D3DCOLOR, 0, IS_DECLUSAGE_COLOR, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(f.dev, el, &f.decl), IS_OK);
    assert_int_equal(dev_set_vertex_declaration(f.dev, f.decl), IS_OK);
    assert_int_equal(dev_set_vertex_shader(f.dev, &vs), IS_OK);
    assert_int_equal(dev_set_stream_source(f.dev, 0, f.vb, 0, sizeof(vtx)), IS_OK);
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_CULLMODE, IS_CULL_NONE), IS_OK);
    return f;
}

static void teardown(fixture *f)
{
    decl_release(f->decl);
    vb_release(f->vb);
    dev_destroy(f->dev);
}

/* Two triangles covering screen rectangle [x0, x1] x [y0, y1] at depth z in colour argb, into v[0..6). */
static void quad(vtx *v, double x0, double y0, double x1, double y1, float z, uint32_t argb)
{
    v[0] = at(x0, y0, z, argb), v[1] = at(x1, y0, z, argb), v[2] = at(x0, y1, z, argb);
    v[3] = at(x1, y0, z, argb), v[4] = at(x1, y1, z, argb), v[5] = at(x0, y1, z, argb);
}

/* Draw the n triangles in the buffer, and check the reference path and 2 threads give the same image; the image
 * (resolved) into px. */
static void draw(fixture *f, const vtx *v, unsigned n_tris, uint32_t *px)
{
    memcpy(vb_lock(f->vb), v, 3 * n_tris * sizeof *v);
    vb_unlock(f->vb);
    rs_target *rt = dev_render_target(f->dev);
    size_t n = (size_t)W * H * (size_t)rt->samples;
    uint32_t *c0 = malloc(n * 4), *c1 = malloc(n * 4);
    float *d0 = malloc(n * 4);
    uint8_t *s0 = malloc(n);
    assert_true(c0 && c1 && d0 && s0);
    memcpy(c0, rt->color, n * 4), memcpy(d0, rt->depth, n * 4), memcpy(s0, rt->stencil, n);
    uint32_t *first = NULL;
    for (int run = 0; run < 3; run++) {
        rt = dev_render_target(f->dev);
        memcpy(rt->color, c0, n * 4), memcpy(rt->depth, d0, n * 4), memcpy(rt->stencil, s0, n);
        dev_set_reference_path(f->dev, run == 1);
        dev_set_threads(f->dev, run == 2 ? 2 : 1);
        assert_int_equal(dev_draw_primitive(f->dev, IS_PT_TRIANGLELIST, 0, n_tris), IS_OK);
        rt = dev_render_target(f->dev);
        if (!first) {
            first = c1;
            memcpy(first, rt->color, n * 4);
        } else {
            assert_memory_equal(rt->color, first, n * 4);
        }
    }
    dev_set_reference_path(f->dev, false);
    dev_set_threads(f->dev, 0);
    assert_int_equal(dev_get_render_target_data(f->dev, px, W * H), IS_OK);
    free(c0), free(c1), free(d0), free(s0);
}

/* The new states: values refused change nothing; values the runtime stores are read back. */
static void test_state_values(void **state)
{
    (void)state;
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    const struct { is_rs rs; uint32_t bad; } bad[] = {
        {IS_RS_ALPHAFUNC, 0}, {IS_RS_ALPHAFUNC, 9}, {IS_RS_STENCILFUNC, 0}, {IS_RS_CCW_STENCILFUNC, 9},
        {IS_RS_STENCILFAIL, 0}, {IS_RS_STENCILZFAIL, 9}, {IS_RS_STENCILPASS, UINT32_MAX},
        {IS_RS_CCW_STENCILFAIL, 0}, {IS_RS_CCW_STENCILZFAIL, 9}, {IS_RS_CCW_STENCILPASS, 0},
        {IS_RS_ALPHATESTENABLE, 2}, {IS_RS_STENCILENABLE, 2}, {IS_RS_CLIPPING, 2}, {IS_RS_SCISSORTESTENABLE, 2},
        {IS_RS_TWOSIDEDSTENCILMODE, 2}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        uint32_t before, after;
        assert_int_equal(dev_get_render_state(dev, bad[k].rs, &before), IS_OK);
        assert_int_equal(dev_set_render_state(dev, bad[k].rs, bad[k].bad), IS_ERR_INVALIDCALL);
        assert_int_equal(dev_get_render_state(dev, bad[k].rs, &after), IS_OK);
        assert_int_equal(before, after);
    }
    const struct { is_rs rs; uint32_t v; } good[] = {
        {IS_RS_ALPHAREF, 0x1234}, {IS_RS_STENCILREF, 0xFFFFFFFF}, {IS_RS_STENCILMASK, 0x0F},
        {IS_RS_STENCILWRITEMASK, 0}, {IS_RS_CLIPPLANEENABLE, 0xFFFFFFFF}, {IS_RS_COLORWRITEENABLE, 0x1F},
        {IS_RS_STENCILPASS, IS_STENCILOP_DECR}, {IS_RS_CCW_STENCILFUNC, IS_CMP_NEVER}, {IS_RS_CLIPPING, 0}};
    for (size_t k = 0; k < sizeof good / sizeof good[0]; k++) {
        uint32_t v;
        assert_int_equal(dev_set_render_state(dev, good[k].rs, good[k].v), IS_OK);
        assert_int_equal(dev_get_render_state(dev, good[k].rs, &v), IS_OK);
        assert_int_equal(v, good[k].v);
    }
    /* D3D9's numeric values */
    assert_int_equal(IS_RS_SCISSORTESTENABLE, 174);
    assert_int_equal(IS_RS_COLORWRITEENABLE, 168);
    assert_int_equal(IS_RS_ALPHAFUNC, 25);
    assert_int_equal(IS_RS_STENCILWRITEMASK, 59);
    assert_int_equal(IS_RS_CLIPPLANEENABLE, 152);
    assert_int_equal(IS_RS_CCW_STENCILFUNC, 189);
    dev_destroy(dev);
}

/* SetScissorRect: the whole target on a new device and after dev_reset; any rectangle is stored; the test draws
 * only inside it (and the viewport), and is ignored when off. */
static void test_scissor(void **state)
{
    (void)state;
    fixture f = setup(1);
    is_rect r;
    assert_int_equal(dev_get_scissor_rect(f.dev, &r), IS_OK);
    assert_true(r.left == 0 && r.top == 0 && r.right == W && r.bottom == H);
    const is_rect odd = {7, 7, -3, 2};
    assert_int_equal(dev_set_scissor_rect(f.dev, &odd), IS_OK);
    assert_int_equal(dev_get_scissor_rect(f.dev, &r), IS_OK);
    assert_memory_equal(&r, &odd, sizeof r);
    assert_int_equal(dev_set_scissor_rect(f.dev, NULL), IS_ERR_INVALIDCALL);
    const is_rect s = {1, 2, 5, 7};
    assert_int_equal(dev_set_scissor_rect(f.dev, &s), IS_OK);
    vtx v[6];
    uint32_t px[W * H];
    quad(v, -1, -1, W + 1, H + 1, 0.5f, BLUE);
    for (int on = 0; on < 2; on++) {
        assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
        assert_int_equal(dev_set_render_state(f.dev, IS_RS_SCISSORTESTENABLE, (uint32_t)on), IS_OK);
        draw(&f, v, 2, px);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                bool in = !on || (x >= 1 && x < 5 && y >= 2 && y < 7);
                assert_int_equal(px[y * W + x], in ? BLUE_RGBA : 0u);
            }
    }
    dev_reset(f.dev);
    assert_int_equal(dev_get_scissor_rect(f.dev, &r), IS_OK);
    assert_true(r.left == 0 && r.top == 0 && r.right == W && r.bottom == H);
    teardown(&f);
}

/* Clear with the scissor test on clears the viewport, its rectangles and the scissor rectangle's common part;
 * the stencil is cleared with the same pixels, to the value's low 8 bits (0 through dev_clear). */
static void test_clear_scissor_and_stencil(void **state)
{
    (void)state;
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    uint32_t px[W * H];
    const is_rect s = {2, 0, 6, 5};
    assert_int_equal(dev_set_scissor_rect(dev, &s), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_SCISSORTESTENABLE, 1), IS_OK);
    assert_int_equal(dev_clear_rects_stencil(dev, 0, NULL, IS_CLEAR_TARGET | IS_CLEAR_STENCIL, BLUE, 1.0f, 0x1AB),
                     IS_OK);
    assert_int_equal(dev_get_render_target_data(dev, px, W * H), IS_OK);
    const rs_target *rt = dev_render_target(dev);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            bool in = x >= 2 && x < 6 && y < 5;
            assert_int_equal(px[y * W + x], in ? BLUE_RGBA : 0xff000000u);
            assert_int_equal(rt->stencil[y * W + x], in ? 0xAB : 0);
        }
    /* a rectangle and the scissor: only their common part */
    const is_rect q = {4, 3, 8, 8};
    assert_int_equal(dev_clear_rects_stencil(dev, 1, &q, IS_CLEAR_STENCIL, 0, 1.0f, 7), IS_OK);
    rt = dev_render_target(dev);
    assert_int_equal(rt->stencil[3 * W + 4], 7);
    assert_int_equal(rt->stencil[3 * W + 6], 0);     /* outside the scissor */
    assert_int_equal(rt->stencil[5 * W + 4], 0);     /* below it */
    assert_int_equal(rt->stencil[3 * W + 3], 0xAB);  /* outside the rectangle */
    /* scissor off: the whole target, through dev_clear (stencil 0) */
    assert_int_equal(dev_set_render_state(dev, IS_RS_SCISSORTESTENABLE, 0), IS_OK);
    assert_int_equal(dev_clear(dev, IS_CLEAR_STENCIL, 0, 1.0f), IS_OK);
    rt = dev_render_target(dev);
    for (int p = 0; p < W * H; p++) assert_int_equal(rt->stencil[p], 0);
    assert_int_equal(dev_clear_rects_stencil(dev, 0, NULL, 8u, 0, 1.0f, 0), IS_ERR_INVALIDCALL);   /* bad flag */
    dev_destroy(dev);
}

/* COLORWRITEENABLE GREEN | ALPHA: red and blue keep the cleared bytes. */
static void test_color_write_enable(void **state)
{
    (void)state;
    fixture f = setup(4);
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET, IS_COLOR_ARGB(0x11, 0x44, 0x33, 0x22), 1.0f), IS_OK);
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_COLORWRITEENABLE,
                                          IS_COLORWRITEENABLE_GREEN | IS_COLORWRITEENABLE_ALPHA), IS_OK);
    vtx v[6];
    uint32_t px[W * H];
    quad(v, -1, -1, W + 1, H + 1, 0.5f, IS_COLOR_ARGB(0xff, 0xff, 0x00, 0xff));
    draw(&f, v, 2, px);
    assert_int_equal(px[3 * W + 3], 0xff220044u);   /* A ff, B 22 kept, G 00, R 44 kept */
    teardown(&f);
}

/* The alpha test on COLOR0's 8-bit alpha (0x80) against ALPHAREF: GREATER 0x7F passes, GREATER 0x80 fails (and
 * writes no depth: a later draw at a farther depth still passes LESSEQUAL). */
static void test_alpha_test(void **state)
{
    (void)state;
    fixture f = setup(1);
    vtx v[6];
    uint32_t px[W * H];
    quad(v, -1, -1, W + 1, H + 1, 0.25f, IS_COLOR_ARGB(0x80, 0, 0xff, 0));
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_ALPHATESTENABLE, 1), IS_OK);
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_ALPHAFUNC, IS_CMP_GREATER), IS_OK);
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_ALPHAREF, 0x80), IS_OK);
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
    draw(&f, v, 2, px);
    assert_int_equal(px[4 * W + 4], 0u);
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_ALPHATESTENABLE, 0), IS_OK);
    quad(v, -1, -1, W + 1, H + 1, 0.75f, BLUE);
    draw(&f, v, 2, px);
    assert_int_equal(px[4 * W + 4], BLUE_RGBA);   /* the failed pixels wrote no depth */
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_ALPHATESTENABLE, 1), IS_OK);
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_ALPHAREF, 0x17F), IS_OK);   /* low 8 bits: 0x7F */
    quad(v, -1, -1, W + 1, H + 1, 0.25f, IS_COLOR_ARGB(0x80, 0, 0xff, 0));
    draw(&f, v, 2, px);
    assert_int_equal(px[4 * W + 4], 0x8000ff00u);
    teardown(&f);
}

/* Stencil through the device: mark the top rows with REPLACE (colour writes off), draw the screen where the
 * stencil EQUALs the reference; two-sided: the counter-clockwise triangle runs the CCW_ operation. */
static void test_stencil(void **state)
{
    (void)state;
    fixture f = setup(1);
    vtx v[6];
    uint32_t px[W * H];
    is_device *dev = f.dev;
    assert_int_equal(dev_clear_rects_stencil(dev, 0, NULL, IS_CLEAR_TARGET | IS_CLEAR_STENCIL, BLACK, 1.0f, 0), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_ZENABLE, IS_ZB_FALSE), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_STENCILENABLE, 1), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_STENCILREF, 5), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_STENCILPASS, IS_STENCILOP_REPLACE), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_COLORWRITEENABLE, 0), IS_OK);
    quad(v, -1, -1, W + 1, 2.5, 0.5f, BLUE);   /* rows 0..2 */
    draw(&f, v, 2, px);
    assert_int_equal(px[0], 0xff000000u);      /* nothing written */
    assert_int_equal(dev_set_render_state(dev, IS_RS_COLORWRITEENABLE, 0xF), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_STENCILPASS, IS_STENCILOP_KEEP), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_STENCILFUNC, IS_CMP_EQUAL), IS_OK);
    quad(v, -1, -1, W + 1, H + 1, 0.5f, BLUE);
    draw(&f, v, 2, px);
    const rs_target *rt = dev_render_target(dev);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            assert_int_equal(px[y * W + x], y < 3 ? BLUE_RGBA : 0xff000000u);
            assert_int_equal(rt->stencil[y * W + x], y < 3 ? 5 : 0);
        }
    /* two-sided: clockwise top-left triangle INCRSAT, counter-clockwise bottom-right DECR (wraps 0 -> 255) */
    assert_int_equal(dev_clear_rects_stencil(dev, 0, NULL, IS_CLEAR_STENCIL, 0, 1.0f, 0), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_STENCILFUNC, IS_CMP_ALWAYS), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_STENCILPASS, IS_STENCILOP_INCRSAT), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_CCW_STENCILPASS, IS_STENCILOP_DECR), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_TWOSIDEDSTENCILMODE, 1), IS_OK);
    vtx t[6] = {at(0, 0, 0.5f, BLUE), at(8, 0, 0.5f, BLUE), at(0, 8, 0.5f, BLUE),
                at(8, 0, 0.5f, BLUE), at(0, 8, 0.5f, BLUE), at(8, 8, 0.5f, BLUE)};
    draw(&f, t, 2, px);
    rt = dev_render_target(dev);
    assert_int_equal(rt->stencil[1 * W + 1], 1);
    assert_int_equal(rt->stencil[6 * W + 6], 255);
    teardown(&f);
}

/* SetClipPlane / GetClipPlane (indices past the last clamp to it, as the runtime); the plane x >= 0 in clip space
 * keeps pixels 4..7; CLIPPLANEENABLE 0 or CLIPPING FALSE keep everything. */
static void test_clip_planes(void **state)
{
    (void)state;
    fixture f = setup(1);
    is_device *dev = f.dev;
    float p[4], got[4];
    assert_int_equal(dev_get_clip_plane(dev, 0, got), IS_OK);
    assert_true(got[0] == 0 && got[1] == 0 && got[2] == 0 && got[3] == 0);
    const float last[4] = {0, 0, 0, 3};
    assert_int_equal(dev_set_clip_plane(dev, 9, last), IS_OK);          /* plane 5 */
    assert_int_equal(dev_get_clip_plane(dev, 5, got), IS_OK);
    assert_memory_equal(got, last, sizeof got);
    assert_int_equal(dev_get_clip_plane(dev, UINT32_MAX, got), IS_OK);  /* plane 5 too */
    assert_memory_equal(got, last, sizeof got);
    const float nan_plane[4] = {NAN, 0, 0, 0};
    assert_int_equal(dev_set_clip_plane(dev, 1, nan_plane), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_clip_plane(dev, 1, NULL), IS_ERR_INVALIDCALL);
    p[0] = 1, p[1] = 0, p[2] = 0, p[3] = 0;
    assert_int_equal(dev_set_clip_plane(dev, 0, p), IS_OK);
    vtx v[6];
    uint32_t px[W * H];
    quad(v, -1, -1, W + 1, H + 1, 0.5f, BLUE);
    const struct { uint32_t enable, clipping; int x0; } cases[] = {{1, 1, 4}, {0, 1, 0}, {1, 0, 0}, {1u << 5, 1, 0}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        assert_int_equal(dev_set_render_state(dev, IS_RS_CLIPPLANEENABLE, cases[c].enable), IS_OK);
        assert_int_equal(dev_set_render_state(dev, IS_RS_CLIPPING, cases[c].clipping), IS_OK);
        assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, BLACK, 1.0f), IS_OK);
        draw(&f, v, 2, px);
        for (int x = 0; x < W; x++) assert_int_equal(px[3 * W + x], x >= cases[c].x0 ? BLUE_RGBA : 0xff000000u);
    }
    /* CLIPPING FALSE: a quad before the near plane is drawn (depth clamped to MinZ), TRUE clips it */
    assert_int_equal(dev_set_render_state(dev, IS_RS_CLIPPLANEENABLE, 0), IS_OK);
    quad(v, -1, -1, W + 1, H + 1, -0.5f, BLUE);
    for (uint32_t clipping = 0; clipping < 2; clipping++) {
        assert_int_equal(dev_set_render_state(dev, IS_RS_CLIPPING, clipping), IS_OK);
        assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, BLACK, 1.0f), IS_OK);
        draw(&f, v, 2, px);
        assert_int_equal(px[2 * W + 2], clipping ? 0xff000000u : BLUE_RGBA);
        assert_true(dev_render_target(dev)->depth[2 * W + 2] == (clipping ? 1.0f : 0.0f));
    }
    teardown(&f);
}

/* Pre-transformed vertices: POSITIONT (x, y, z, rhw) and COLOR0 without a vertex shader draw at the given pixels
 * and depth; without COLOR0 they are white; a vertex shader set takes precedence (POSITIONT is then its
 * position input); a declaration with both POSITION0 and POSITIONT is refused. */
static void test_pretransformed(void **state)
{
    (void)state;
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    typedef struct { float x, y, z, rhw; uint32_t argb; } tl;
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITIONT, 0},
                                    {0, 16, IS_DECLTYPE_D3DCOLOR, 0, IS_DECLUSAGE_COLOR, 0}, IS_DECL_END};
    const is_vertex_element el_white[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITIONT, 0}, IS_DECL_END};
    const is_vertex_element el_both[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITIONT, 0},
                                         {0, 16, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    is_vertex_declaration *decl, *white, *both = (is_vertex_declaration *)1;
    assert_int_equal(dev_create_vertex_declaration(dev, el, &decl), IS_OK);
    assert_int_equal(dev_create_vertex_declaration(dev, el_white, &white), IS_OK);
    assert_int_equal(dev_create_vertex_declaration(dev, el_both, &both), IS_ERR_INVALIDCALL);
    assert_null(both);
    is_vertex_buffer *vb;
    assert_int_equal(dev_create_vertex_buffer(dev, 6 * sizeof(tl), &vb), IS_OK);
    const uint32_t c = IS_COLOR_ARGB(255, 0, 255, 0);
    const tl q[6] = {{2, 1, 0.25f, 1, c}, {6, 1, 0.25f, 1, c}, {2, 5, 0.25f, 1, c},
                     {6, 1, 0.25f, 1, c}, {6, 5, 0.25f, 1, c}, {2, 5, 0.25f, 1, c}};
    memcpy(vb_lock(vb), q, sizeof q);
    vb_unlock(vb);
    assert_int_equal(dev_set_stream_source(dev, 0, vb, 0, sizeof(tl)), IS_OK);
    uint32_t px[W * H], ref[W * H];
    for (int d = 0; d < 2; d++) {
        assert_int_equal(dev_set_vertex_declaration(dev, d ? white : decl), IS_OK);
        for (int path = 0; path < 2; path++) {
            dev_set_reference_path(dev, path);
            assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, BLACK, 1.0f), IS_OK);
            assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 2), IS_OK);
            assert_int_equal(dev_get_render_target_data(dev, path ? px : ref, W * H), IS_OK);
        }
        assert_memory_equal(px, ref, sizeof px);
        const rs_target *rt = dev_render_target(dev);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                bool in = x >= 2 && x < 6 && y >= 1 && y < 5;
                assert_int_equal(px[y * W + x], in ? (d ? 0xffffffffu : 0xff00ff00u) : 0xff000000u);
                assert_true(rt->depth[y * W + x] == (in ? 0.25f : 1.0f));
            }
    }
    const is_vertex_shader *got = (const is_vertex_shader *)1;
    assert_int_equal(dev_get_vertex_shader(dev, &got), IS_OK);
    assert_null(got);   /* the pass-through was bound for the draws only */
    /* a shader set: it runs, reading POSITIONT as its position (here pixels 2..6 as clip x: off screen) */
    assert_int_equal(dev_set_vertex_declaration(dev, decl), IS_OK);
    assert_int_equal(dev_set_vertex_shader(dev, &vs), IS_OK);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, BLACK, 1.0f), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 2), IS_OK);
    assert_int_equal(dev_get_render_target_data(dev, px, W * H), IS_OK);
    for (int p = 0; p < W * H; p++) assert_int_equal(px[p], 0xff000000u);
    decl_release(decl);
    decl_release(white);
    vb_release(vb);
    dev_destroy(dev);
}

/* An instanced "patch": oPos = b0 t0 + b1 t1 + b2 t2 (b = POSITION0, the grid point; t0..t2 = TEXCOORD0..2, the
 * instance's clip-space corners), white; its hull is the three corners exactly. */
static void vs_patch_main(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    (void)c;
    const float4 b = in->position[0], *t = in->texcoord;
    out->pos = (rs_vec4){b.x * t[0].x + b.y * t[1].x + b.z * t[2].x, b.x * t[0].y + b.y * t[1].y + b.z * t[2].y,
                         b.x * t[0].z + b.y * t[1].z + b.z * t[2].z, b.x * t[0].w + b.y * t[1].w + b.z * t[2].w};
    out->attr[RS_ATTR_COLOR0] = (rs_vec4){1, 1, 1, 1};
}
static bool vs_patch_hull(const is_vs_constants *c, const is_vs_input *in, is_patch_hull *h)
{
    (void)c;
    h->n_pos = 3, h->degree = 0, h->err = 1e-6;
    for (int k = 0; k < 3; k++) {
        const float4 t = in->texcoord[k];
        h->pos[k][0] = t.x, h->pos[k][1] = t.y, h->pos[k][2] = t.z, h->pos[k][3] = t.w;
    }
    return true;
}
static const is_vertex_shader vs_patch = {.name = "patch", .main = vs_patch_main, .outputs = IS_OUT_COLOR0,
                                          .hull = vs_patch_hull};

/* The pre-tessellation cull (dev_set_patch_cull) proves instances invisible against the near and far planes,
 * which CLIPPING FALSE does not clip against: an instance wholly before the near plane (z = -0.5 w) is drawn
 * with CLIPPING FALSE (depth clamped to 0) with the cull on as off; with CLIPPING TRUE it is clipped (and culled). */
static void test_patch_cull_no_clipping(void **state)
{
    (void)state;
    is_device *dev = dev_create(W, H, 1, NULL, 0);
    const float grid[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const float inst[12] = {-3, 3, -0.5f, 1, 3, 3, -0.5f, 1, -3, -3, -0.5f, 1};   /* clockwise, the whole screen */
    const uint16_t idx[3] = {0, 1, 2};
    is_vertex_buffer *g, *in;
    is_index_buffer *ib;
    assert_int_equal(dev_create_vertex_buffer(dev, sizeof grid, &g), IS_OK);
    assert_int_equal(dev_create_vertex_buffer(dev, sizeof inst, &in), IS_OK);
    assert_int_equal(dev_create_index_buffer(dev, sizeof idx, IS_FMT_INDEX16, &ib), IS_OK);
    memcpy(vb_lock(g), grid, sizeof grid), memcpy(vb_lock(in), inst, sizeof inst), memcpy(ib_lock(ib), idx, sizeof idx);
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
                                    {1, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, 0},
                                    {1, 16, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, 1},
                                    {1, 32, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, 2}, IS_DECL_END};
    is_vertex_declaration *decl;
    assert_int_equal(dev_create_vertex_declaration(dev, el, &decl), IS_OK);
    assert_int_equal(dev_set_vertex_declaration(dev, decl), IS_OK);
    assert_int_equal(dev_set_vertex_shader(dev, &vs_patch), IS_OK);
    assert_int_equal(dev_set_stream_source(dev, 0, g, 0, 12), IS_OK);
    assert_int_equal(dev_set_stream_source(dev, 1, in, 0, 48), IS_OK);
    assert_int_equal(dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | 1), IS_OK);
    assert_int_equal(dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1), IS_OK);
    assert_int_equal(dev_set_indices(dev, ib), IS_OK);
    for (uint32_t clipping = 0; clipping < 2; clipping++)
        for (int cull = 0; cull < 2; cull++) {
            dev_set_patch_cull(dev, cull);
            assert_int_equal(dev_set_render_state(dev, IS_RS_CLIPPING, clipping), IS_OK);
            assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, BLACK, 1.0f), IS_OK);
            assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 3, 0, 1), IS_OK);
            uint32_t px[W * H];
            assert_int_equal(dev_get_render_target_data(dev, px, W * H), IS_OK);
            assert_int_equal(px[3 * W + 3], clipping ? 0xff000000u : 0xffffffffu);
            if (!clipping) assert_true(dev_render_target(dev)->depth[3 * W + 3] == 0.0f);
            if (cull) assert_int_equal(dev_instances_culled(dev), clipping ? 1 : 0);
        }
    decl_release(decl), vb_release(g), vb_release(in), ib_release(ib);
    dev_destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_state_values), cmocka_unit_test(test_scissor),
        cmocka_unit_test(test_clear_scissor_and_stencil), cmocka_unit_test(test_color_write_enable),
        cmocka_unit_test(test_alpha_test), cmocka_unit_test(test_stencil), cmocka_unit_test(test_clip_planes),
        cmocka_unit_test(test_pretransformed), cmocka_unit_test(test_patch_cull_no_clipping),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
