/* tests/test_api_pixel.c -- core/pixel.h: every public function with NULL devices, shaders and data, constant
 * registers at and past c223 (nothing changed by a refused call), samplers and coordinates that are NULL or out of
 * range; and the device's pixel stage: a shader's colour from its constants, a texture read through ps_tex2D with
 * D3D9's texel centres (point sampling of a 4x4 texture drawn 1:1), dev_reset back to the fixed path, and the
 * fixed path's bytes unchanged by setting and clearing a shader.  tests/check_api_walkers.sh checks that every
 * INSTESS_API function of core/pixel.h is named here. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <limits.h>
#include <math.h>
#include <string.h>

#include "../core/core.h"
#include "../vs/vs.h"
#include "util/dev_util.h"

#define N 4   /* the target and the texture: N x N */


/* The buffer and declaration of the last device made (they hold their device: released with it by destroy). */
static is_vertex_buffer *held_vb;
static is_vertex_declaration *held_decl;

/* dev_destroy, then the resources the device helper made (the device's struct goes with the last of them). */
static void destroy(is_device *dev) { tu_device_destroy(dev, &held_vb, &held_decl); }

/* A device drawing a screen-filling triangle (fixed shader, identity transform, normal towards the viewer: COLOR0
 * is the diffuse colour) whose TEXCOORD0 is the texture
 * coordinate mapping texel centres to pixel centres (u = (X + 0.5) / N at screen X). */
static is_device *device(void)
{
    /* clip x = X / (N/2) - 1 at pixel X; u = (X + 0.5) / N: at clip x = -1 (X = 0) u = 0.5/N, slope 1/N per pixel */
    const float verts[3][9] = {{-1, 1, 0.5f, 1, 0.5f / N, 0.5f / N, 0, 0, -1},
                               {3, 1, 0.5f, 1, 0.5f / N + 2.0f, 0.5f / N, 0, 0, -1},
                               {-1, -3, 0.5f, 1, 0.5f / N, 0.5f / N + 2.0f, 0, 0, -1}};
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITION, 0},
                                    {0, 16, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TEXCOORD, 0},
                                    {0, 24, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_NORMAL, 0}, IS_DECL_END};
    return tu_fixed_device(N, N, 1, verts, sizeof verts, sizeof verts[0], el, (float4){0.25f, 0.5f, 0.75f, 1},
                           &held_vb, &held_decl);
}

/* Draw once into a cleared target; the colour plane's bytes into out. */
static void draw(is_device *dev, uint32_t *out)
{
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0xff000000u, 1.0f), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
    assert_int_equal(dev_get_render_target_data(dev, out, N * N), IS_OK);
}

/* oC0 = c5. */
static void ps_constant(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out)
{
    (void)in;
    for (int k = 0; k < 4; k++) out->color[k] = c->c[5];
}
static const is_pixel_shader PS_CONSTANT = {"constant", ps_constant, 0};

/* oC0 = tex2D(s0, TEXCOORD0). */
static void ps_texture(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out)
{
    float2 uv[4];
    for (int k = 0; k < 4; k++) uv[k] = (float2){in->v[k][RS_ATTR_TEXCOORD0].x, in->v[k][RS_ATTR_TEXCOORD0].y};
    for (int k = 0; k < 4; k++) out->color[k] = ps_tex2D(&c->s[0], uv, k);
}
static const is_pixel_shader PS_TEXTURE = {"texture", ps_texture, 0};

static void test_arguments(void **state)
{
    (void)state;
    float data[4 * (IS_MAX_PS_CONSTANTS + 1)];
    const is_pixel_shader *got = &PS_CONSTANT;
    assert_int_equal(dev_set_pixel_shader(NULL, &PS_CONSTANT), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_pixel_shader(NULL, &got), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_pixel_shader_constant_f(NULL, 0, data, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_pixel_shader_constant_f(NULL, 0, data, 1), IS_ERR_INVALIDCALL);
    is_device *dev = device();
    assert_int_equal(dev_get_pixel_shader(dev, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_pixel_shader(dev, &got), IS_OK);
    assert_null(got);   /* the default: the fixed path */
    const is_pixel_shader empty = {"empty", NULL, 0};
    assert_int_equal(dev_set_pixel_shader(dev, &empty), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_pixel_shader(dev, &got), IS_OK);
    assert_null(got);
    for (int k = 0; k < 4 * (IS_MAX_PS_CONSTANTS + 1); k++) data[k] = (float)k;
    assert_int_equal(dev_set_pixel_shader_constant_f(dev, 0, data, IS_MAX_PS_CONSTANTS + 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_pixel_shader_constant_f(dev, IS_MAX_PS_CONSTANTS, data, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_pixel_shader_constant_f(dev, UINT_MAX, data, 2), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_pixel_shader_constant_f(dev, 0, NULL, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_pixel_shader_constant_f(dev, 0, NULL, 0), IS_OK);   /* nothing to copy */
    float back[8] = {1, 1, 1, 1, 1, 1, 1, 1};
    assert_int_equal(dev_get_pixel_shader_constant_f(dev, IS_MAX_PS_CONSTANTS - 2, back, 2), IS_OK);
    for (int k = 0; k < 8; k++) assert_true(back[k] == 0.0f);   /* refused calls wrote nothing */
    assert_int_equal(dev_set_pixel_shader_constant_f(dev, IS_MAX_PS_CONSTANTS - 1, data, 1), IS_OK);
    assert_int_equal(dev_get_pixel_shader_constant_f(dev, IS_MAX_PS_CONSTANTS - 1, back, 1), IS_OK);
    assert_memory_equal(back, data, 4 * sizeof(float));
    assert_int_equal(dev_get_pixel_shader_constant_f(dev, 0, NULL, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_pixel_shader_constant_f(dev, IS_MAX_PS_CONSTANTS, back, 1), IS_ERR_INVALIDCALL);
    /* sampling with nothing to sample: (0, 0, 0, 1); a lane out of 0..3 likewise */
    is_sampler empty_s = tex_sampler_default(NULL);
    float2 uv[4] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    float4 t = ps_tex2D(&empty_s, uv, 0);
    assert_true(t.x == 0 && t.y == 0 && t.z == 0 && t.w == 1);
    t = ps_tex2D(&empty_s, NULL, 0);
    assert_true(t.w == 1);
    t = ps_tex2Dbias(&empty_s, uv, NAN, 7);
    assert_true(t.x == 0 && t.w == 1);
    t = ps_tex2Dbias(NULL, uv, 1e30f, -1);
    assert_true(t.w == 1);
    float4 four[4] = {{9, 9, 9, 9}, {9, 9, 9, 9}, {9, 9, 9, 9}, {9, 9, 9, 9}};
    ps_tex2D_quad(&empty_s, uv, 0, four);           /* no lane: nothing written */
    assert_true(four[0].x == 9 && four[3].w == 9);
    ps_tex2D_quad(&empty_s, uv, 0xffffffffu, four);  /* bits past lane 3 ignored */
    for (int k = 0; k < 4; k++) assert_true(four[k].x == 0 && four[k].w == 1);
    four[1].w = 9;
    ps_tex2D_quad(NULL, NULL, 1u, four);
    assert_true(four[0].w == 1 && four[1].w == 9);
    ps_tex2D_quad(&empty_s, uv, 0xfu, NULL);         /* nowhere to write: nothing */
    destroy(dev);
}

/* A shader's colour is its constant; clearing it (or dev_reset) gives the fixed path's bytes back. */
static void test_constant_and_fixed(void **state)
{
    (void)state;
    is_device *dev = device();
    uint32_t fixed[N * N], shaded[N * N], again[N * N];
    draw(dev, fixed);
    assert_int_equal(fixed[0], 0xffbf8040u);   /* COLOR0 = (0.25, 0.5, 0.75, 1): 64, 128, 191 -> ABGR */
    const float c5[4] = {1.0f, 0.0f, 0.5f, 1.0f};
    assert_int_equal(dev_set_pixel_shader_constant_f(dev, 5, c5, 1), IS_OK);
    assert_int_equal(dev_set_pixel_shader(dev, &PS_CONSTANT), IS_OK);
    draw(dev, shaded);
    for (int p = 0; p < N * N; p++) assert_int_equal(shaded[p], 0xff8000ffu);
    assert_int_equal(dev_set_pixel_shader(dev, NULL), IS_OK);
    draw(dev, again);
    assert_memory_equal(again, fixed, sizeof fixed);
    destroy(dev);
}

/* tex2D through sampler 0: a 4x4 texture drawn 1:1 with point sampling gives each pixel its texel. */
static void test_texture(void **state)
{
    (void)state;
    is_device *dev = device();
    is_texture *tex;
    assert_int_equal(dev_create_texture(dev, N, N, 1, 0, IS_FMT_A8R8G8B8, &tex), IS_OK);
    is_locked_rect lr;
    assert_int_equal(tex_lock_rect(tex, 0, &lr, NULL, 0), IS_OK);
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            uint32_t argb = 0xff000000u | (uint32_t)(x * 60) << 16 | (uint32_t)(y * 70) << 8 | 0x33u;
            memcpy((unsigned char *)lr.bits + (size_t)y * lr.pitch + 4 * x, &argb, 4);
        }
    assert_int_equal(tex_unlock_rect(tex, 0), IS_OK);
    assert_int_equal(dev_set_texture(dev, 0, tex), IS_OK);
    assert_int_equal(dev_set_sampler_state(dev, 0, IS_SAMP_MINFILTER, IS_TEXF_POINT), IS_OK);
    assert_int_equal(dev_set_sampler_state(dev, 0, IS_SAMP_MAGFILTER, IS_TEXF_POINT), IS_OK);
    assert_int_equal(dev_set_pixel_shader(dev, &PS_TEXTURE), IS_OK);
    uint32_t px[N * N];
    draw(dev, px);
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++)   /* RGBA8 in memory: R = x * 60, G = y * 70, B = 0x33 */
            assert_int_equal(px[y * N + x], 0xff330000u | (uint32_t)(y * 70) << 8 | (uint32_t)(x * 60));
    dev_reset(dev);
    const is_pixel_shader *got = &PS_TEXTURE;
    assert_int_equal(dev_get_pixel_shader(dev, &got), IS_OK);
    assert_null(got);
    float c[4] = {9, 9, 9, 9};
    assert_int_equal(dev_get_pixel_shader_constant_f(dev, 5, c, 1), IS_OK);
    assert_true(c[0] == 0.0f);
    destroy(dev);
}

/* oC0 = (COLOR0.x, TEXCOORD0.x, 0, 1). */
static void ps_color_tex(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out)
{
    (void)c;
    for (int k = 0; k < 4; k++)
        out->color[k] = (float4){in->v[k][RS_ATTR_COLOR0].x, in->v[k][RS_ATTR_TEXCOORD0].x, 0, 1};
}

/* is_pixel_shader.inputs: 0 reads every slot; a mask reads its slots, the others (0, 0, 0, 0).  At pixel (0, 0)
 * COLOR0.x = 0.25 (64) and TEXCOORD0.x = 0.125 (32). */
static void test_inputs_mask(void **state)
{
    (void)state;
    const struct { uint32_t inputs, want; } rows[] = {
        {0, 0xff002040u},
        {1u << RS_ATTR_COLOR0, 0xff000040u},
        {1u << RS_ATTR_TEXCOORD0, 0xff002000u},
        {(1u << RS_ATTR_COLOR0) | (1u << RS_ATTR_TEXCOORD0), 0xff002040u},
        {1u << RS_ATTR_COLOR1, 0xff000000u},
    };
    is_device *dev = device();
    for (size_t r = 0; r < sizeof rows / sizeof rows[0]; r++) {
        const is_pixel_shader ps = {"color-tex", ps_color_tex, rows[r].inputs};
        uint32_t px[N * N];
        assert_int_equal(dev_set_pixel_shader(dev, &ps), IS_OK);
        draw(dev, px);
        assert_int_equal(px[0], rows[r].want);
    }
    assert_int_equal(dev_set_pixel_shader(dev, NULL), IS_OK);
    destroy(dev);
}

/* ps_tex2D_quad gives ps_tex2D's values lane by lane (trilinear over a mip chain, WRAP, quads from magnified to
 * many levels down, the longer footprint along x or y, as floats bit for bit) and leaves the lanes outside its
 * mask alone. */
static void test_tex2D_quad(void **state)
{
    (void)state;
    is_device *dev = device();
    is_texture *tex;
    assert_int_equal(dev_create_texture(dev, 16, 8, 0, 0, IS_FMT_A8R8G8B8, &tex), IS_OK);
    unsigned levels = 0;
    for (unsigned l = 0; l < 16; l++) {
        is_locked_rect lr;
        if (tex_lock_rect(tex, l, &lr, NULL, 0) != IS_OK) break;
        levels++;
        unsigned w = 16u >> l ? 16u >> l : 1u, h = 8u >> l ? 8u >> l : 1u;
        for (unsigned y = 0; y < h; y++)
            for (unsigned x = 0; x < w; x++) {
                uint32_t v = (x * 37u + y * 91u + l * 13u) * 2654435761u;
                memcpy((unsigned char *)lr.bits + (size_t)y * lr.pitch + 4 * x, &v, 4);
            }
        assert_int_equal(tex_unlock_rect(tex, l), IS_OK);
    }
    assert_true(levels == 5);
    is_sampler s = tex_sampler_default(tex);
    s.state[IS_SAMP_MINFILTER] = s.state[IS_SAMP_MAGFILTER] = s.state[IS_SAMP_MIPFILTER] = IS_TEXF_LINEAR;
    for (int q = 0; q < 40; q++) {
        float scale = 0.01f * (float)(1 << (q % 10)), u0 = -0.7f + 0.13f * (float)q, v0 = 0.31f - 0.07f * (float)q;
        float dy = q % 2 ? 3.0f * scale : scale;   /* odd quads: the longer footprint along y */
        float2 uv[4] = {{u0, v0}, {u0 + scale, v0 + 0.3f * scale}, {u0 - 0.2f * scale, v0 + dy},
                        {u0 + 0.8f * scale, v0 + 1.3f * scale}};
        unsigned lanes = (unsigned)(q % 16);
        float4 got[4];
        for (int k = 0; k < 4; k++) got[k] = (float4){-1, -1, -1, -1};
        ps_tex2D_quad(&s, uv, lanes, got);
        for (int k = 0; k < 4; k++) {
            float4 want = lanes & (1u << k) ? ps_tex2D(&s, uv, k) : (float4){-1, -1, -1, -1};
            assert_memory_equal(&got[k], &want, sizeof want);
        }
    }
    destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_arguments),
        cmocka_unit_test(test_constant_and_fixed),
        cmocka_unit_test(test_texture),
        cmocka_unit_test(test_inputs_mask),
        cmocka_unit_test(test_tex2D_quad),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
