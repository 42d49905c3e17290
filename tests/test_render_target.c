/* tests/test_render_target.c -- render targets and surfaces (core/surface.c, core/device.h "render targets and
 * surfaces"): rendering into a RENDERTARGET texture and sampling it 1:1 in the next draw (bytes compared with the
 * pattern computed by hand), GetRenderTargetData into a system-memory surface, SetRenderTarget's reset of the
 * viewport and scissor rectangle (Wine's d3d9 test_set_rt_vp_scissor), depth-stencil surfaces larger, smaller
 * and missing (Clear refused without one, as wined3d), refused calls that change nothing, and the releases. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../core/core.h"

enum { W = 16, H = 16, T = 8 };
#define BLACK IS_COLOR_ARGB(255, 0, 0, 0)

/* Pre-transformed vertices: screen x, y, z, rhw and TEXCOORD0. */
typedef struct tl { float x, y, z, rhw, u, v; } tl;

/* The pattern: pixel (x, y) gets RGBA bytes (16x + 8, 16y + 8, 200 - x - y, 255 - 3x). */
static uint32_t pattern_rgba(int x, int y)
{
    return (uint32_t)(16 * x + 8) | (uint32_t)(16 * y + 8) << 8 | (uint32_t)(200 - x - y) << 16 |
           (uint32_t)(255 - 3 * x) << 24;
}

/* oC0 = the pattern at vPos. */
static void ps_pattern(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out)
{
    (void)c;
    for (int k = 0; k < 4; k++) {
        uint32_t p = pattern_rgba((int)in->vpos[k][0], (int)in->vpos[k][1]);
        out->color[k] = (rs_vec4){(float)(p & 0xff) / 255.0f, (float)(p >> 8 & 0xff) / 255.0f,
                                  (float)(p >> 16 & 0xff) / 255.0f, (float)(p >> 24) / 255.0f};
    }
}
static const is_pixel_shader PS_PATTERN = {"pattern", ps_pattern, 0};

/* oC0 = tex2D(s0, TEXCOORD0). */
static void ps_texture(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out)
{
    float2 uv[4];
    for (int k = 0; k < 4; k++) uv[k] = (float2){in->v[k][RS_ATTR_TEXCOORD0].x, in->v[k][RS_ATTR_TEXCOORD0].y};
    for (int k = 0; k < 4; k++) out->color[k] = ps_tex2D(&c->s[0], uv, k);
}
static const is_pixel_shader PS_TEXTURE = {"texture", ps_texture, 0};

/* oC0 = white. */
static void ps_white(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out)
{
    (void)c, (void)in;
    for (int k = 0; k < 4; k++) out->color[k] = (rs_vec4){1.0f, 1.0f, 1.0f, 1.0f};
}
static const is_pixel_shader PS_WHITE = {"white", ps_white, 0};

/* A device with a pre-transformed declaration and a buffer of 6 vertices bound. */
typedef struct fixture { is_device *dev; is_vertex_buffer *vb; is_vertex_declaration *decl; } fixture;

static fixture setup(void)
{
    fixture f;
    f.dev = dev_create(W, H, 1, NULL, 0);
    assert_non_null(f.dev);
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITIONT, 0},
                                    {0, 16, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TEXCOORD, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(f.dev, el, &f.decl), IS_OK);
    assert_int_equal(dev_create_vertex_buffer(f.dev, 6 * sizeof(tl), &f.vb), IS_OK);
    assert_int_equal(dev_set_vertex_declaration(f.dev, f.decl), IS_OK);
    assert_int_equal(dev_set_stream_source(f.dev, 0, f.vb, 0, sizeof(tl)), IS_OK);
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_CULLMODE, IS_CULL_NONE), IS_OK);
    return f;
}

static void teardown(fixture *f)
{
    decl_release(f->decl);
    vb_release(f->vb);
    dev_destroy(f->dev);
}

/* Draw the rectangle x0..x1, y0..y1 (screen coordinates of its corners) at depth z, texture coordinates 0..1. */
static is_result draw_rect(fixture *f, float x0, float y0, float x1, float y1, float z)
{
    const tl q[6] = {{x0, y0, z, 1, 0, 0}, {x1, y0, z, 1, 1, 0}, {x0, y1, z, 1, 0, 1},
                     {x1, y0, z, 1, 1, 0}, {x1, y1, z, 1, 1, 1}, {x0, y1, z, 1, 0, 1}};
    memcpy(vb_lock(f->vb), q, sizeof q);
    vb_unlock(f->vb);
    return dev_draw_primitive(f->dev, IS_PT_TRIANGLELIST, 0, 2);
}

/* Render the pattern into a T x T texture, read it back through GetRenderTargetData, then draw the texture 1:1 onto
 * the back buffer (pixel (i, j) samples texel (i, j) at its centre) and compare bytes with the pattern. */
static void test_render_to_texture(void **state)
{
    (void)state;
    fixture f = setup();
    is_texture *tex;
    is_surface *level, *bb, *ds, *sys;
    assert_int_equal(dev_create_texture(f.dev, T, T, 1, IS_USAGE_RENDERTARGET, IS_FMT_A8R8G8B8, &tex), IS_OK);
    assert_int_equal(tex_get_surface_level(tex, 0, &level), IS_OK);
    is_surface *again = NULL;
    assert_int_equal(tex_get_surface_level(tex, 0, &again), IS_OK);
    assert_ptr_equal(again, level);
    assert_int_equal(dev_get_render_target(f.dev, 0, &bb), IS_OK);
    assert_int_equal(dev_get_depth_stencil_surface(f.dev, &ds), IS_OK);
    assert_int_equal(dev_set_render_target(f.dev, 0, level), IS_OK);
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, BLACK, 1.0f), IS_OK);
    assert_int_equal(dev_set_pixel_shader(f.dev, &PS_PATTERN), IS_OK);
    assert_int_equal(draw_rect(&f, -0.5f, -0.5f, T - 0.5f, T - 0.5f, 0.5f), IS_OK);
    /* read back: GetRenderTargetData of the current target, bytes B, G, R, A */
    assert_int_equal(dev_create_offscreen_plain_surface(f.dev, T, T, IS_FMT_A8R8G8B8, &sys), IS_OK);
    assert_int_equal(dev_get_render_target_surface_data(f.dev, level, sys), IS_OK);
    int pitch;
    void *bits;
    assert_int_equal(surf_lock_rect(sys, NULL, &pitch, &bits), IS_OK);
    assert_int_equal(pitch, T * 4);
    for (int y = 0; y < T; y++)
        for (int x = 0; x < T; x++) {
            const unsigned char *b = (const unsigned char *)bits + y * pitch + x * 4;
            uint32_t p = pattern_rgba(x, y);
            assert_int_equal(b[0], p >> 16 & 0xff);   /* B */
            assert_int_equal(b[1], p >> 8 & 0xff);    /* G */
            assert_int_equal(b[2], p & 0xff);         /* R */
            assert_int_equal(b[3], p >> 24);          /* A */
        }
    assert_int_equal(surf_unlock_rect(sys), IS_OK);
    /* sample it in the next draw, on the back buffer */
    assert_int_equal(dev_set_render_target(f.dev, 0, bb), IS_OK);
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, BLACK, 1.0f), IS_OK);
    assert_int_equal(dev_set_texture(f.dev, 0, tex), IS_OK);
    assert_int_equal(dev_set_pixel_shader(f.dev, &PS_TEXTURE), IS_OK);
    assert_int_equal(draw_rect(&f, -0.5f, -0.5f, T - 0.5f, T - 0.5f, 0.5f), IS_OK);
    uint32_t px[W * H];
    assert_int_equal(dev_get_render_target_data(f.dev, px, W * H), IS_OK);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            assert_int_equal(px[y * W + x], x < T && y < T ? pattern_rgba(x, y) : 0xff000000u);
    /* the texture cannot be locked (D3DPOOL_DEFAULT) */
    is_locked_rect lr;
    assert_int_equal(tex_lock_rect(tex, 0, &lr, NULL, 0), IS_ERR_INVALIDCALL);
    surf_release(level);   /* the texture's: nothing happens */
    assert_int_equal(dev_set_render_target(f.dev, 0, level), IS_OK);
    tex_release(tex);      /* the target goes back to the back buffer, viewport and all */
    is_surface *cur;
    assert_int_equal(dev_get_render_target(f.dev, 0, &cur), IS_OK);
    assert_ptr_equal(cur, bb);
    is_viewport vp;
    assert_int_equal(dev_get_viewport(f.dev, &vp), IS_OK);
    assert_int_equal(vp.width, W);
    surf_release(sys);
    teardown(&f);
}

/* SetRenderTarget sets the viewport and the scissor rectangle to the whole new target, also to the same target
 * and while a stateblock is recorded; GetRenderTarget reads it back. */
static void test_viewport_reset(void **state)
{
    (void)state;
    fixture f = setup();
    is_surface *rt, *bb;
    assert_int_equal(dev_create_render_target(f.dev, 5, 7, IS_FMT_X8R8G8B8, IS_MULTISAMPLE_NONE, &rt), IS_OK);
    assert_int_equal(dev_get_render_target(f.dev, 0, &bb), IS_OK);
    const is_viewport small = {1, 2, 3, 4, 0.25f, 0.5f};
    const is_rect sc = {1, 1, 2, 2};
    is_viewport vp;
    is_rect r;
    for (int round = 0; round < 3; round++) {
        assert_int_equal(dev_set_viewport(f.dev, &small), IS_OK);
        assert_int_equal(dev_set_scissor_rect(f.dev, &sc), IS_OK);
        is_state_block *sb = NULL;
        if (round == 2) assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
        assert_int_equal(dev_set_render_target(f.dev, 0, round == 1 ? bb : rt), IS_OK);
        if (round == 2) assert_int_equal(dev_end_state_block(f.dev, &sb), IS_OK), sb_release(sb);
        unsigned w = round == 1 ? W : 5, h = round == 1 ? H : 7;
        assert_int_equal(dev_get_viewport(f.dev, &vp), IS_OK);
        assert_int_equal(vp.x, 0), assert_int_equal(vp.y, 0);
        assert_int_equal(vp.width, w), assert_int_equal(vp.height, h);
        assert_true(vp.min_z == 0.0f && vp.max_z == 1.0f);
        assert_int_equal(dev_get_scissor_rect(f.dev, &r), IS_OK);
        assert_true(r.left == 0 && r.top == 0 && r.right == (int)w && r.bottom == (int)h);
        assert_int_equal(dev_render_target(f.dev)->width, (int)w);
    }
    is_surface *cur;
    assert_int_equal(dev_get_render_target(f.dev, 0, &cur), IS_OK);
    assert_ptr_equal(cur, rt);
    /* the smaller target draws and clears: the device's auto depth (16x16) is used by its top-left part */
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, IS_COLOR_ARGB(255, 9, 8, 7), 1.0f), IS_OK);
    is_surface *sys;
    assert_int_equal(dev_create_offscreen_plain_surface(f.dev, 5, 7, IS_FMT_X8R8G8B8, &sys), IS_OK);
    assert_int_equal(dev_get_render_target_surface_data(f.dev, rt, sys), IS_OK);
    int pitch;
    void *bits;
    assert_int_equal(surf_lock_rect(sys, NULL, &pitch, &bits), IS_OK);
    assert_int_equal(((uint32_t *)bits)[5 * 7 - 1], IS_COLOR_ARGB(255, 9, 8, 7));
    assert_int_equal(surf_unlock_rect(sys), IS_OK);
    surf_release(rt);   /* the current target: the back buffer again */
    assert_int_equal(dev_get_render_target(f.dev, 0, &cur), IS_OK);
    assert_ptr_equal(cur, bb);
    assert_int_equal(dev_get_viewport(f.dev, &vp), IS_OK);
    assert_int_equal(vp.width, W);
    surf_release(sys);
    teardown(&f);
}

/* Depth-stencil surfaces: a larger one is used by its top-left part (depth kept across targets), a smaller one
 * and none turn the depth test off (DXVK; the runtime's result is undefined); Clear of depth or stencil without one
 * is refused; stencil clear on D24X8 is refused. */
static void test_depth_stencil(void **state)
{
    (void)state;
    fixture f = setup();
    is_surface *rt, *big, *small, *nostencil, *auto_ds, *got;
    assert_int_equal(dev_create_render_target(f.dev, T, T, IS_FMT_A8R8G8B8, 0, &rt), IS_OK);
    assert_int_equal(dev_create_depth_stencil_surface(f.dev, 12, 12, IS_FMT_D24S8, 0, &big), IS_OK);
    assert_int_equal(dev_create_depth_stencil_surface(f.dev, 4, 4, IS_FMT_D24S8, 0, &small), IS_OK);
    assert_int_equal(dev_create_depth_stencil_surface(f.dev, T, T, IS_FMT_D24X8, 0, &nostencil), IS_OK);
    assert_int_equal(dev_get_depth_stencil_surface(f.dev, &auto_ds), IS_OK);
    assert_int_equal(dev_set_render_target(f.dev, 0, rt), IS_OK);
    assert_int_equal(dev_set_pixel_shader(f.dev, &PS_PATTERN), IS_OK);
    uint32_t px[W * H];
    /* larger: a near rectangle, then a far one over it fails the depth test */
    assert_int_equal(dev_set_depth_stencil_surface(f.dev, big), IS_OK);
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, BLACK, 1.0f), IS_OK);
    assert_int_equal(draw_rect(&f, -0.5f, -0.5f, 3.5f, 3.5f, 0.25f), IS_OK);
    /* switching targets away and back keeps the depth the larger surface holds */
    assert_int_equal(dev_set_depth_stencil_surface(f.dev, auto_ds), IS_OK);
    assert_int_equal(dev_set_depth_stencil_surface(f.dev, big), IS_OK);
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET, BLACK, 1.0f), IS_OK);
    assert_int_equal(draw_rect(&f, -0.5f, -0.5f, T - 0.5f, T - 0.5f, 0.75f), IS_OK);
    assert_int_equal(dev_get_render_target_data(f.dev, px, T * T), IS_OK);
    assert_int_equal(px[0], 0xff000000u);                    /* behind the near rectangle's depth */
    assert_int_equal(px[5 * T + 5], pattern_rgba(5, 5));
    /* smaller: accepted (as the runtime), but not used: no depth test, its contents kept */
    assert_int_equal(dev_set_depth_stencil_surface(f.dev, small), IS_OK);
    assert_int_equal(dev_get_depth_stencil_surface(f.dev, &got), IS_OK);
    assert_ptr_equal(got, small);
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET, BLACK, 1.0f), IS_OK);
    assert_int_equal(draw_rect(&f, -0.5f, -0.5f, T - 0.5f, T - 0.5f, 0.75f), IS_OK);
    assert_int_equal(dev_set_pixel_shader(f.dev, &PS_WHITE), IS_OK);
    assert_int_equal(draw_rect(&f, -0.5f, -0.5f, T - 0.5f, T - 0.5f, 1.0f), IS_OK);   /* no depth test */
    assert_int_equal(dev_get_render_target_data(f.dev, px, T * T), IS_OK);
    assert_int_equal(px[0], 0xffffffffu);
    assert_int_equal(px[T * T - 1], 0xffffffffu);
    assert_int_equal(dev_set_pixel_shader(f.dev, &PS_PATTERN), IS_OK);
    assert_int_equal(draw_rect(&f, -0.5f, -0.5f, T - 0.5f, T - 0.5f, 1.0f), IS_OK);
    /* none: Clear of depth or stencil refused, nothing changed; colour still clears and draws */
    assert_int_equal(dev_set_depth_stencil_surface(f.dev, NULL), IS_OK);
    got = small;
    assert_int_equal(dev_get_depth_stencil_surface(f.dev, &got), IS_ERR_NOTFOUND);
    assert_null(got);
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, IS_COLOR_ARGB(255, 1, 2, 3), 1.0f),
                     IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_data(f.dev, px, T * T), IS_OK);
    assert_int_equal(px[0], pattern_rgba(0, 0));               /* the refused Clear wrote nothing */
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_STENCIL, 0, 1.0f), IS_ERR_INVALIDCALL);
    assert_int_equal(draw_rect(&f, -0.5f, -0.5f, T - 0.5f, T - 0.5f, 0.5f), IS_OK);
    /* no stencil bits: a stencil clear is refused, a depth clear is not */
    assert_int_equal(dev_set_depth_stencil_surface(f.dev, nostencil), IS_OK);
    assert_int_equal(dev_clear_rects_stencil(f.dev, 0, NULL, IS_CLEAR_STENCIL, 0, 1.0f, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
    /* a depth surface is not a render target, nor a target a depth surface; a multisampled target with a
     * one-sample depth surface draws without depth */
    assert_int_equal(dev_set_render_target(f.dev, 0, big), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_depth_stencil_surface(f.dev, rt), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_depth_stencil_surface(f.dev, &got), IS_OK);
    assert_ptr_equal(got, nostencil);
    surf_release(nostencil);   /* the current depth surface: none afterwards */
    assert_int_equal(dev_get_depth_stencil_surface(f.dev, &got), IS_ERR_NOTFOUND);
    surf_release(big), surf_release(small), surf_release(rt);
    teardown(&f);
}

/* Refused calls change nothing: bad indices, NULL, another device's surface, wrong usages and formats, a
 * released surface's slot; GetRenderTargetData's rules; dev_reset and dev_destroy with a texture target. */
static void test_refused(void **state)
{
    (void)state;
    fixture f = setup();
    is_device *other = dev_create(4, 4, 4, NULL, 0);
    is_surface *rt, *foreign, *sys, *sys_x, *cur, *bb, *msaa;
    assert_int_equal(dev_get_render_target(f.dev, 0, &bb), IS_OK);
    assert_int_equal(dev_create_render_target(f.dev, T, T, IS_FMT_A8R8G8B8, 0, &rt), IS_OK);
    assert_int_equal(dev_create_render_target(other, 4, 4, IS_FMT_A8R8G8B8, 0, &foreign), IS_OK);
    assert_int_equal(dev_create_render_target(f.dev, T, T, IS_FMT_A8R8G8B8, IS_MULTISAMPLE_4_SAMPLES, &msaa), IS_OK);
    assert_int_equal(dev_create_offscreen_plain_surface(f.dev, T, T, IS_FMT_A8R8G8B8, &sys), IS_OK);
    assert_int_equal(dev_create_offscreen_plain_surface(f.dev, T, T, IS_FMT_X8R8G8B8, &sys_x), IS_OK);
    const is_viewport vp0 = {1, 1, 2, 2, 0.0f, 1.0f};
    assert_int_equal(dev_set_viewport(f.dev, &vp0), IS_OK);
    assert_int_equal(dev_set_render_target(f.dev, 1, rt), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_render_target(f.dev, 0, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_render_target(f.dev, 0, foreign), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_render_target(f.dev, 0, sys), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_depth_stencil_surface(f.dev, foreign), IS_ERR_INVALIDCALL);
    is_viewport vp;
    assert_int_equal(dev_get_viewport(f.dev, &vp), IS_OK);
    assert_memory_equal(&vp, &vp0, sizeof vp);
    assert_int_equal(dev_get_render_target(f.dev, 0, &cur), IS_OK);
    assert_ptr_equal(cur, bb);
    assert_int_equal(dev_get_render_target(f.dev, 1, &cur), IS_ERR_INVALIDCALL);
    /* formats and sizes */
    is_surface *none = bb;
    assert_int_equal(dev_create_render_target(f.dev, T, T, IS_FMT_R32F, 0, &none), IS_ERR_NOTAVAILABLE);
    assert_null(none);
    assert_int_equal(dev_create_render_target(f.dev, 0, T, IS_FMT_A8R8G8B8, 0, &none), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_render_target(f.dev, T, T, IS_FMT_A8R8G8B8, 2, &none), IS_ERR_NOTAVAILABLE);
    assert_int_equal(dev_create_depth_stencil_surface(f.dev, T, T, IS_FMT_A8R8G8B8, 0, &none), IS_ERR_NOTAVAILABLE);
    assert_int_equal(dev_create_offscreen_plain_surface(f.dev, T, T, IS_FMT_D24S8, &none), IS_ERR_NOTAVAILABLE);
    is_texture *t = NULL;
    assert_int_equal(dev_create_texture(f.dev, T, T, 1, IS_USAGE_RENDERTARGET, IS_FMT_A32B32G32R32F, &t),
                     IS_ERR_NOTAVAILABLE);
    assert_null(t);
    /* GetRenderTargetData: a multisampled source, another format, a render target as destination */
    assert_int_equal(dev_get_render_target_surface_data(f.dev, msaa, sys), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_surface_data(f.dev, rt, sys_x), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_surface_data(f.dev, rt, msaa), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_surface_data(f.dev, sys, sys), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_surface_data(f.dev, bb, sys), IS_ERR_INVALIDCALL); /* 16x16 into 8x8 */
    assert_int_equal(dev_get_render_target_surface_data(f.dev, rt, sys), IS_OK);
    /* locks: render targets are not lockable; a system-memory surface once at a time */
    int pitch;
    void *bits;
    assert_int_equal(surf_lock_rect(rt, NULL, &pitch, &bits), IS_ERR_INVALIDCALL);
    const is_rect half = {4, 4, 8, 8}, out = {4, 4, 9, 8};
    assert_int_equal(surf_lock_rect(sys, &out, &pitch, &bits), IS_ERR_INVALIDCALL);
    assert_int_equal(surf_lock_rect(sys, &half, &pitch, &bits), IS_OK);
    assert_int_equal(surf_lock_rect(sys, NULL, &pitch, &bits), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_render_target_surface_data(f.dev, rt, sys), IS_ERR_INVALIDCALL);   /* locked */
    assert_int_equal(surf_unlock_rect(sys), IS_OK);
    assert_int_equal(surf_unlock_rect(sys), IS_ERR_INVALIDCALL);
    /* a texture target at dev_reset (the back buffer again) and at dev_destroy */
    assert_int_equal(dev_create_texture(f.dev, T, T, 0, IS_USAGE_RENDERTARGET | IS_USAGE_AUTOGENMIPMAP,
                                        IS_FMT_A8R8G8B8, &t), IS_OK);
    is_surface *lv;
    assert_int_equal(tex_get_surface_level(t, 1, &lv), IS_ERR_INVALIDCALL);   /* one level shown */
    assert_int_equal(tex_get_surface_level(t, 0, &lv), IS_OK);
    assert_int_equal(dev_set_render_target(f.dev, 0, lv), IS_OK);
    assert_int_equal(dev_clear(f.dev, IS_CLEAR_TARGET, IS_COLOR_ARGB(255, 40, 80, 120), 1.0f), IS_OK);
    dev_reset(f.dev);
    assert_int_equal(dev_get_render_target(f.dev, 0, &cur), IS_OK);
    assert_ptr_equal(cur, bb);
    /* the clear reached the texels and (AUTOGENMIPMAP) its last level */
    is_sampler s = tex_sampler_default(t);
    s.state[IS_SAMP_MIPFILTER] = IS_TEXF_POINT;
    for (int lod = 0; lod < 4; lod++) {
        float4 c = tex_sample_lod(&s, (float4){0.5f, 0.5f, 0.0f, (float)lod});
        assert_true(c.x == 40.0f / 255.0f && c.y == 80.0f / 255.0f && c.z == 120.0f / 255.0f && c.w == 1.0f);
    }
    assert_int_equal(dev_set_render_target(f.dev, 0, lv), IS_OK);
    surf_release(rt), surf_release(foreign), surf_release(sys), surf_release(sys_x), surf_release(msaa);
    dev_destroy(other);
    decl_release(f.decl);
    vb_release(f.vb);
    dev_destroy(f.dev);   /* with the texture still the target */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_render_to_texture), cmocka_unit_test(test_viewport_reset),
        cmocka_unit_test(test_depth_stencil), cmocka_unit_test(test_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
