/* tests/test_texture.c -- textures and samplers (core/texture.h) against values computed by hand: creation and its
 * invalid calls, ownership (foreign and released textures refused), locking, the texel formats, D3D9's texel
 * centres, every address mode, MIN/MAG/MIPFILTER, MAXMIPLEVEL, MIPMAPLODBIAS, BORDERCOLOR, the level of detail of
 * tex2Dgrad / tex2Dbias, the box-filtered mip chain (D3DXFilterTexture, AUTOGENMIPMAP), and textures from PNG,
 * BMP, TGA and EXR files. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../core/device_internal.h"
#include "../core/hlsl.h"
#include "../image/image.h"

/* A float's bits (MIPMAPLODBIAS). */
static uint32_t fbits(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}

/* An R32F texture w x h with `levels` levels, texel (i, j) of level l = val(l, i, j). */
static is_texture *r32f(is_device *dev, unsigned w, unsigned h, unsigned levels,
                        float (*val)(unsigned, unsigned, unsigned))
{
    is_texture *t = NULL;
    assert_int_equal(dev_create_texture(dev, w, h, levels, 0, IS_FMT_R32F, &t), IS_OK);
    for (unsigned l = 0; l < tex_get_level_count(t); l++) {
        is_locked_rect lr;
        is_texture_desc d;
        assert_int_equal(tex_get_level_desc(t, l, &d), IS_OK);
        assert_int_equal(tex_lock_rect(t, l, &lr, NULL, 0), IS_OK);
        for (unsigned j = 0; j < d.height; j++)
            for (unsigned i = 0; i < d.width; i++) ((float *)((char *)lr.bits + j * lr.pitch))[i] = val(l, i, j);
        assert_int_equal(tex_unlock_rect(t, l), IS_OK);
    }
    return t;
}

/* 10, 20, 30, ... along a row (level 0), i.e. 10 (i + 1) + 100 j. */
static float ramp(unsigned l, unsigned i, unsigned j) { return (float)(10 * (i + 1) + 100 * j + 1000 * l); }
/* Level l everywhere holds l + 1. */
static float level_no(unsigned l, unsigned i, unsigned j) { return (float)(l + 1); }
/* 0 then 1 (a 2-texel ramp). */
static float zero_one(unsigned l, unsigned i, unsigned j) { return (float)(i + j); }

/* The red channel of tex2Dlod(s, (u, v, 0, lod)). */
static float red(const is_sampler *s, float u, float v, float lod) { return tex2Dlod(s, f4(u, v, 0, lod)).x; }

/* ---------------- creation, ownership, locking ---------------- */

static void test_create_and_levels(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = NULL;
    is_texture_desc d;
    assert_int_equal(dev_create_texture(dev, 8, 2, 0, 0, IS_FMT_A8R8G8B8, &t), IS_OK);
    assert_int_equal(tex_get_level_count(t), 4); /* 8x2, 4x1, 2x1, 1x1 */
    const unsigned want[4][2] = {{8, 2}, {4, 1}, {2, 1}, {1, 1}};
    for (unsigned l = 0; l < 4; l++) {
        assert_int_equal(tex_get_level_desc(t, l, &d), IS_OK);
        assert_int_equal(d.width, want[l][0]);
        assert_int_equal(d.height, want[l][1]);
        assert_int_equal(d.format, IS_FMT_A8R8G8B8);
    }
    assert_int_equal(tex_get_level_desc(t, 4, &d), IS_ERR_INVALIDCALL);
    is_locked_rect lr;
    assert_int_equal(tex_lock_rect(t, 1, &lr, NULL, 0), IS_OK);
    assert_int_equal(lr.pitch, 16);
    for (int k = 0; k < 16; k++) assert_int_equal(((unsigned char *)lr.bits)[k], 0); /* texels start zero */
    assert_int_equal(tex_lock_rect(t, 1, &lr, NULL, 0), IS_ERR_INVALIDCALL);       /* locked already */
    assert_non_null(strstr(dev_last_error(dev), "locked already"));
    assert_int_equal(tex_unlock_rect(t, 1), IS_OK);
    assert_int_equal(tex_unlock_rect(t, 1), IS_ERR_INVALIDCALL);                    /* not locked */
    assert_int_equal(tex_lock_rect(t, 4, &lr, NULL, 0), IS_ERR_INVALIDCALL);        /* no such level */
    /* a rect: the pointer is at its first texel; outside or empty rects are refused */
    is_rect r = {1, 1, 3, 2};
    assert_int_equal(tex_lock_rect(t, 0, &lr, &r, 0), IS_OK);
    assert_ptr_equal(lr.bits, t->lv[0].bits + (8 + 1) * 4);
    assert_int_equal(tex_unlock_rect(t, 0), IS_OK);
    const is_rect bad[] = {{-1, 0, 2, 2}, {0, 0, 9, 2}, {0, 0, 8, 3}, {2, 0, 2, 1}, {3, 0, 2, 1}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        assert_int_equal(tex_lock_rect(t, 0, &lr, &bad[k], 0), IS_ERR_INVALIDCALL);
    assert_int_equal(t->locked, 0u); /* refused locks lock nothing */

    /* invalid creations create nothing and set the output to NULL, as Wine's CreateTexture does */
    is_texture *u = (is_texture *)&u;
    assert_int_equal(dev_create_texture(dev, 0, 4, 1, 0, IS_FMT_R32F, &u), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_texture(dev, 4, IS_MAX_TEXTURE_SIZE + 1, 1, 0, IS_FMT_R32F, &u), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_texture(dev, 4, 4, 4, 0, IS_FMT_R32F, &u), IS_ERR_INVALIDCALL); /* 3 at most */
    assert_int_equal(dev_create_texture(dev, 4, 4, 2, IS_USAGE_AUTOGENMIPMAP, IS_FMT_R32F, &u), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_texture(dev, 4, 4, 1, IS_USAGE_RENDERTARGET, IS_FMT_R32F, &u), IS_ERR_NOTAVAILABLE);
    assert_int_equal(dev_create_texture(dev, 4, 4, 1, 0, IS_FMT_INDEX16, &u), IS_ERR_NOTAVAILABLE);
    assert_null(u);
    assert_ptr_equal(dev->textures, t); /* only t is alive */
    assert_int_equal(dev_create_texture(dev, 4, 4, 3, 0, IS_FMT_R32F, &u), IS_OK);
    assert_int_equal(tex_get_level_count(u), 3);
    dev_destroy(dev); /* releases t and u (the sanitizer build checks for leaks) */
}

static void test_ownership(void **state)
{
    is_device *a = dev_create(8, 8, 1, NULL, 0), *b = dev_create(8, 8, 1, NULL, 0);
    is_texture *ta, *tb, *got;
    assert_int_equal(dev_create_texture(a, 2, 2, 1, 0, IS_FMT_R32F, &ta), IS_OK);
    assert_int_equal(dev_create_texture(b, 2, 2, 1, 0, IS_FMT_R32F, &tb), IS_OK);
    assert_int_equal(dev_set_texture(a, IS_VERTEXTEXTURESAMPLER(1), ta), IS_OK);
    assert_int_equal(dev_set_texture(a, 3, ta), IS_OK);
    /* foreign: refused, with a message, nothing changed */
    assert_int_equal(dev_set_texture(a, IS_VERTEXTEXTURESAMPLER(1), tb), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(a), "not a live texture of this device"));
    assert_int_equal(dev_get_texture(a, IS_VERTEXTEXTURESAMPLER(1), &got), IS_OK);
    assert_ptr_equal(got, ta);
    assert_ptr_equal(a->consts.s[1].tex, ta); /* the vertex shader's s1 */
    /* released: unbound from every sampler, and refused afterwards (compared as a pointer, never read) */
    tex_release(ta);
    assert_int_equal(dev_get_texture(a, IS_VERTEXTEXTURESAMPLER(1), &got), IS_OK);
    assert_null(got);
    assert_int_equal(dev_get_texture(a, 3, &got), IS_OK);
    assert_null(got);
    assert_int_equal(dev_set_texture(a, 0, ta), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_texture(a, 0, &got), IS_OK);
    assert_null(got);
    /* indices D3D9 does not have: ignored with IS_OK, as the runtime */
    assert_int_equal(dev_set_texture(b, 16, tb), IS_OK);
    assert_int_equal(dev_set_texture(b, IS_VERTEXTEXTURESAMPLER(4), tb), IS_OK);
    assert_int_equal(dev_get_texture(b, 16, &got), IS_OK);
    assert_null(got);
    assert_int_equal(dev_set_texture(b, IS_DMAPSAMPLER, tb), IS_OK);
    assert_int_equal(dev_get_texture(b, IS_DMAPSAMPLER, &got), IS_OK);
    assert_ptr_equal(got, tb);
    dev_destroy(a);
    dev_destroy(b);
}

static void test_sampler_states(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    const uint32_t defaults[IS_SAMP_COUNT] = {
        [IS_SAMP_ADDRESSU] = IS_TADDRESS_WRAP, [IS_SAMP_ADDRESSV] = IS_TADDRESS_WRAP,
        [IS_SAMP_ADDRESSW] = IS_TADDRESS_WRAP, [IS_SAMP_BORDERCOLOR] = 0, [IS_SAMP_MAGFILTER] = IS_TEXF_POINT,
        [IS_SAMP_MINFILTER] = IS_TEXF_POINT, [IS_SAMP_MIPFILTER] = IS_TEXF_NONE, [IS_SAMP_MIPMAPLODBIAS] = 0,
        [IS_SAMP_MAXMIPLEVEL] = 0, [IS_SAMP_MAXANISOTROPY] = 1, [IS_SAMP_SRGBTEXTURE] = 0,
        [IS_SAMP_ELEMENTINDEX] = 0, [IS_SAMP_DMAPOFFSET] = 0};
    const unsigned samplers[] = {0, 15, IS_DMAPSAMPLER, IS_VERTEXTEXTURESAMPLER(0), IS_VERTEXTEXTURESAMPLER(3)};
    /* D3D9's numbers */
    assert_int_equal(IS_SAMP_MINFILTER, 6);
    assert_int_equal(IS_SAMP_MAXMIPLEVEL, 9);
    assert_int_equal(IS_TADDRESS_BORDER, 4);
    assert_int_equal(IS_VERTEXTEXTURESAMPLER(0), 257);
    assert_int_equal(IS_FMT_A32B32G32R32F, 116);
    for (size_t k = 0; k < sizeof samplers / sizeof samplers[0]; k++)
        for (int s = IS_SAMP_ADDRESSU; s < IS_SAMP_COUNT; s++) {
            uint32_t v = 99;
            assert_int_equal(dev_get_sampler_state(dev, samplers[k], (is_samp)s, &v), IS_OK);
            assert_int_equal(v, defaults[s]);
            assert_int_equal(dev_set_sampler_state(dev, samplers[k], (is_samp)s, 1000u + (uint32_t)s), IS_OK);
            assert_int_equal(dev_get_sampler_state(dev, samplers[k], (is_samp)s, &v), IS_OK);
            assert_int_equal(v, 1000u + (uint32_t)s); /* any value is stored, as the runtime */
        }
    assert_int_equal(dev->consts.s[3].state[IS_SAMP_MIPFILTER], 1000u + IS_SAMP_MIPFILTER);
    uint32_t v = 7;
    assert_int_equal(dev_set_sampler_state(dev, 20, IS_SAMP_MINFILTER, 2), IS_OK); /* no such sampler */
    assert_int_equal(dev_get_sampler_state(dev, 20, IS_SAMP_MINFILTER, &v), IS_OK);
    assert_int_equal(v, 0);
    assert_int_equal(dev_set_sampler_state(dev, 0, (is_samp)0, 2), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_sampler_state(dev, 0, (is_samp)IS_SAMP_COUNT, 2), IS_ERR_INVALIDCALL);
    /* dev_reset: the defaults again, textures unbound but still the device's */
    is_texture *t, *got;
    assert_int_equal(dev_create_texture(dev, 2, 2, 1, 0, IS_FMT_R32F, &t), IS_OK);
    assert_int_equal(dev_set_texture(dev, IS_VERTEXTEXTURESAMPLER(0), t), IS_OK);
    dev_reset(dev);
    for (size_t k = 0; k < sizeof samplers / sizeof samplers[0]; k++)
        for (int s = IS_SAMP_ADDRESSU; s < IS_SAMP_COUNT; s++) {
            assert_int_equal(dev_get_sampler_state(dev, samplers[k], (is_samp)s, &v), IS_OK);
            assert_int_equal(v, defaults[s]);
        }
    assert_int_equal(dev_get_texture(dev, IS_VERTEXTEXTURESAMPLER(0), &got), IS_OK);
    assert_null(got);
    assert_int_equal(dev_set_texture(dev, IS_VERTEXTEXTURESAMPLER(0), t), IS_OK);
    is_sampler d = tex_sampler_default(t);
    for (int s = IS_SAMP_ADDRESSU; s < IS_SAMP_COUNT; s++) assert_int_equal(d.state[s], defaults[s]);
    dev_destroy(dev);
}

/* ---------------- formats and texel centres ---------------- */

static void test_formats(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    const is_format fmts[4] = {IS_FMT_A8R8G8B8, IS_FMT_X8R8G8B8, IS_FMT_R32F, IS_FMT_A32B32G32R32F};
    const float want[4][4] = {{64 / 255.0f, 32 / 255.0f, 16 / 255.0f, 128 / 255.0f},
                              {64 / 255.0f, 32 / 255.0f, 16 / 255.0f, 1.0f},
                              {0.5f, 1.0f, 1.0f, 1.0f},
                              {1.0f, 2.0f, 3.0f, 4.0f}};
    for (int k = 0; k < 4; k++) {
        is_texture *t;
        is_locked_rect lr;
        assert_int_equal(dev_create_texture(dev, 1, 1, 1, 0, fmts[k], &t), IS_OK);
        assert_int_equal(tex_lock_rect(t, 0, &lr, NULL, 0), IS_OK);
        if (k < 2) *(uint32_t *)lr.bits = 0x80402010u;   /* D3DCOLOR A 0x80, R 0x40, G 0x20, B 0x10 */
        else if (k == 2) *(float *)lr.bits = 0.5f;
        else memcpy(lr.bits, (const float[4]){1, 2, 3, 4}, 16); /* R, G, B, A in memory */
        tex_unlock_rect(t, 0);
        is_sampler s = tex_sampler_default(t);
        float4 c = tex2Dlod(&s, f4(0.5f, 0.5f, 0, 0));
        assert_true(c.x == want[k][0] && c.y == want[k][1] && c.z == want[k][2] && c.w == want[k][3]);
    }
    is_sampler empty = tex_sampler_default(NULL);
    float4 c = tex2Dlod(&empty, f4(0.5f, 0.5f, 0, 0));
    assert_true(c.x == 0 && c.y == 0 && c.z == 0 && c.w == 1);
    dev_destroy(dev);
}

/* The 8-bit formats under LINEAR (bilinear reads four texels at once): every byte value in each channel, read at
 * the texel centres (weights 0: the texel as is), decoded as byte / 255 with R, G, B from bytes 2, 1, 0 and A from
 * byte 3 (X8R8G8B8: 1); and the border colour with ADDRESSV BORDER alone. */
static void test_formats_linear(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    for (int k = 0; k < 2; k++) {
        is_texture *t;
        is_locked_rect lr;
        assert_int_equal(dev_create_texture(dev, 256, 2, 1, 0, k ? IS_FMT_X8R8G8B8 : IS_FMT_A8R8G8B8, &t), IS_OK);
        assert_int_equal(tex_lock_rect(t, 0, &lr, NULL, 0), IS_OK);
        for (int j = 0; j < 2; j++)
            for (unsigned i = 0; i < 256; i++) {
                unsigned char *p = (unsigned char *)lr.bits + j * lr.pitch + i * 4;
                p[0] = (unsigned char)i, p[1] = (unsigned char)(255 - i);
                p[2] = (unsigned char)(i * 7), p[3] = (unsigned char)(i ^ 0x55);
            }
        tex_unlock_rect(t, 0);
        is_sampler s = tex_sampler_default(t);
        s.state[IS_SAMP_MAGFILTER] = s.state[IS_SAMP_MINFILTER] = IS_TEXF_LINEAR;
        for (unsigned i = 0; i < 256; i++) {
            float4 c = tex2Dlod(&s, f4((i + 0.5f) / 256.0f, 0.25f, 0, 0));
            float want[4] = {(float)(unsigned char)(i * 7) / 255.0f, (float)(255 - i) / 255.0f, (float)i / 255.0f,
                             k ? 1.0f : (float)(i ^ 0x55) / 255.0f};
            if (c.x != want[0] || c.y != want[1] || c.z != want[2] || c.w != want[3])
                fail_msg("format %d, texel %u: %g %g %g %g", k, i, c.x, c.y, c.z, c.w);
        }
        s.state[IS_SAMP_ADDRESSV] = IS_TADDRESS_BORDER;   /* ADDRESSU stays WRAP */
        s.state[IS_SAMP_BORDERCOLOR] = 0x80ff4020u;
        float4 c = tex2Dlod(&s, f4(0.5f, -1.0f, 0, 0));
        assert_true(c.x == 1.0f && c.y == 64 / 255.0f && c.z == 32 / 255.0f && c.w == 128 / 255.0f);
    }
    dev_destroy(dev);
}

/* POINT: texel (i, j) covers [i, i + 1) x [j, j + 1) in texel units; the boundary belongs to the right texel. */
static void test_point_texel_centres(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = r32f(dev, 4, 2, 1, ramp); /* row 0: 10 20 30 40; row 1: 110 120 130 140 */
    is_sampler s = tex_sampler_default(t);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 2; j++) {
            float u = (i + 0.5f) / 4, v = (j + 0.5f) / 2;
            assert_true(red(&s, u, v, 0) == 10 * (i + 1) + 100 * j);           /* centre */
            assert_true(red(&s, i / 4.0f, j / 2.0f, 0) == 10 * (i + 1) + 100 * j); /* left / top edge: inside */
        }
    assert_true(red(&s, nextafterf(0.25f, 0), 0.25f, 0) == 10); /* just left of texel 1's edge */
    assert_true(red(&s, 0.25f, nextafterf(0.5f, 0), 0) == 20);  /* just above row 1 */
    assert_true(red(&s, 0.25f, 0.5f, 0) == 120);
    dev_destroy(dev);
}

/* LINEAR: x = u w - 1/2; at a texel centre the texel itself, between centres the blend by the fraction. */
static void test_linear_texel_centres(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = r32f(dev, 2, 2, 1, zero_one); /* 0 1 / 1 2 */
    is_sampler s = tex_sampler_default(t);
    s.state[IS_SAMP_MAGFILTER] = IS_TEXF_LINEAR;
    s.state[IS_SAMP_ADDRESSU] = s.state[IS_SAMP_ADDRESSV] = IS_TADDRESS_CLAMP;
    assert_true(red(&s, 0.25f, 0.25f, 0) == 0.0f);   /* texel (0, 0)'s centre */
    assert_true(red(&s, 0.75f, 0.25f, 0) == 1.0f);   /* texel (1, 0) */
    assert_true(red(&s, 0.5f, 0.25f, 0) == 0.5f);    /* halfway */
    assert_true(red(&s, 0.375f, 0.25f, 0) == 0.25f); /* x = 0.75 - 0.5 */
    assert_true(red(&s, 0.5f, 0.5f, 0) == 1.0f);     /* the four texels' mean: (0 + 1 + 1 + 2) / 4 */
    assert_true(red(&s, 0.375f, 0.375f, 0) == 0.5f); /* a = b = 0.25: 0.25 + (1.25 - 0.25) 0.25 */
    assert_true(red(&s, 0.375f, 0.625f, 0) == 1.0f); /* a = 0.25, b = 0.75: 0.25 + (1.25 - 0.25) 0.75 */
    assert_true(red(&s, 0.0f, 0.25f, 0) == 0.0f);    /* clamped: texels -1 and 0 are both texel 0 */
    s.state[IS_SAMP_ADDRESSU] = IS_TADDRESS_WRAP;
    assert_true(red(&s, 0.0f, 0.25f, 0) == 0.5f);    /* wrapped: texel -1 is texel 1 */
    dev_destroy(dev);
}

/* ---------------- address modes ---------------- */

static void test_address_modes_u(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = r32f(dev, 4, 1, 1, ramp); /* 10 20 30 40 */
    is_sampler s = tex_sampler_default(t);
    s.state[IS_SAMP_BORDERCOLOR] = 0x80ff4020u;
    /* u -> texel index i = floor(4u): -6, -2, -1, 4, 5, 9 */
    const float us[] = {-1.375f, -0.375f, -0.125f, 1.125f, 1.375f, 2.375f};
    const struct { uint32_t mode; float want[6]; } rows[] = {
        {IS_TADDRESS_WRAP, {30, 30, 40, 10, 20, 20}},
        {IS_TADDRESS_MIRROR, {30, 20, 10, 40, 30, 20}},      /* period 8: 0 1 2 3 3 2 1 0 */
        {IS_TADDRESS_CLAMP, {10, 10, 10, 40, 40, 40}},
        {IS_TADDRESS_MIRRORONCE, {40, 20, 10, 40, 40, 40}},  /* -1 - i for i < 0, then clamped */
        {IS_TADDRESS_BORDER, {1, 1, 1, 1, 1, 1}},            /* BORDERCOLOR's red: 0xff */
        {77, {30, 30, 40, 10, 20, 20}},                      /* unknown: wraps (DXVK) */
    };
    for (size_t r = 0; r < sizeof rows / sizeof rows[0]; r++) {
        s.state[IS_SAMP_ADDRESSU] = rows[r].mode;
        for (int k = 0; k < 6; k++) {
            float got = red(&s, us[k], 0.5f, 0);
            if (got != rows[r].want[k])
                fail_msg("mode %u, u %g: %g, want %g", rows[r].mode, us[k], got, rows[r].want[k]);
        }
        for (int i = 0; i < 4; i++) assert_true(red(&s, (i + 0.5f) / 4, 0.5f, 0) == 10 * (i + 1)); /* inside: as is */
    }
    /* BORDER returns the whole colour (A 0x80, R 0xff, G 0x40, B 0x20) */
    s.state[IS_SAMP_ADDRESSU] = IS_TADDRESS_BORDER;
    float4 c = tex2Dlod(&s, f4(-0.125f, 0.5f, 0, 0));
    assert_true(c.x == 1.0f && c.y == 64 / 255.0f && c.z == 32 / 255.0f && c.w == 128 / 255.0f);
    /* ADDRESSU does not act on v: wrapping v of a 1-texel-high texture stays texel row 0 */
    s.state[IS_SAMP_ADDRESSU] = IS_TADDRESS_CLAMP;
    assert_true(red(&s, 0.375f, 7.5f, 0) == 20);
    /* huge and NaN coordinates: at +-2^30 texels and 0 */
    s.state[IS_SAMP_ADDRESSU] = IS_TADDRESS_WRAP;
    assert_true(red(&s, 1e30f, 0.5f, 0) == 10);   /* 2^30 mod 4 = 0 */
    assert_true(red(&s, NAN, 0.5f, 0) == 10);
    dev_destroy(dev);
}

static void test_address_modes_v(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = r32f(dev, 1, 4, 1, ramp); /* column: 10 110 210 310 */
    is_sampler s = tex_sampler_default(t);
    s.state[IS_SAMP_BORDERCOLOR] = 0x00000080u; /* red 0 */
    const float vs[] = {-0.375f, -0.125f, 1.125f, 1.375f};   /* rows -2, -1, 4, 5 */
    const struct { uint32_t mode; float want[4]; } rows[] = {
        {IS_TADDRESS_WRAP, {210, 310, 10, 110}},
        {IS_TADDRESS_MIRROR, {110, 10, 310, 210}},
        {IS_TADDRESS_CLAMP, {10, 10, 310, 310}},
        {IS_TADDRESS_BORDER, {0, 0, 0, 0}},
        {IS_TADDRESS_MIRRORONCE, {110, 10, 310, 310}},
    };
    for (size_t r = 0; r < sizeof rows / sizeof rows[0]; r++) {
        s.state[IS_SAMP_ADDRESSV] = rows[r].mode;
        s.state[IS_SAMP_ADDRESSU] = IS_TADDRESS_BORDER; /* u inside: U's mode plays no part */
        for (int k = 0; k < 4; k++) assert_true(red(&s, 0.5f, vs[k], 0) == rows[r].want[k]);
    }
    dev_destroy(dev);
}

/* BORDER under LINEAR: the border colour takes part in the blend as a texel. */
static void test_border_linear(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = r32f(dev, 2, 1, 1, zero_one); /* 0 1 */
    is_sampler s = tex_sampler_default(t);
    s.state[IS_SAMP_MAGFILTER] = IS_TEXF_LINEAR;
    s.state[IS_SAMP_ADDRESSU] = IS_TADDRESS_BORDER;
    s.state[IS_SAMP_BORDERCOLOR] = 0xffffffffu;          /* red 1 */
    assert_true(red(&s, 0.0f, 0.5f, 0) == 0.5f);          /* border 1 and texel 0 (0), halfway */
    assert_true(red(&s, 1.0f, 0.5f, 0) == 1.0f);          /* texel 1 (1) and border (1) */
    s.state[IS_SAMP_BORDERCOLOR] = 0x00000000u;
    assert_true(red(&s, 1.0f, 0.5f, 0) == 0.5f);
    assert_true(red(&s, 0.125f, 0.5f, 0) == 0.0f);        /* x = -0.25: border 0 and texel 0 (0) */
    dev_destroy(dev);
}

/* ---------------- filters and levels ---------------- */

static void test_min_mag_filter(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = r32f(dev, 2, 1, 1, zero_one);
    is_sampler s = tex_sampler_default(t);
    s.state[IS_SAMP_ADDRESSU] = IS_TADDRESS_CLAMP;
    /* at u = 0.5: POINT reads texel 1 (x = 1.0), LINEAR the blend 0.5 */
    assert_true(red(&s, 0.5f, 0.5f, 0) == 1.0f);
    s.state[IS_SAMP_MAGFILTER] = IS_TEXF_LINEAR;
    assert_true(red(&s, 0.5f, 0.5f, -1.0f) == 0.5f); /* magnified: MAGFILTER */
    assert_true(red(&s, 0.5f, 0.5f, 0.0f) == 0.5f);  /* lambda 0 is magnification */
    assert_true(red(&s, 0.5f, 0.5f, 0.5f) == 1.0f);  /* minified: MINFILTER POINT */
    s.state[IS_SAMP_MINFILTER] = IS_TEXF_ANISOTROPIC; /* any filter above POINT is LINEAR (DXVK) */
    assert_true(red(&s, 0.5f, 0.5f, 0.5f) == 0.5f);
    s.state[IS_SAMP_MAGFILTER] = IS_TEXF_NONE;        /* NONE samples as POINT */
    assert_true(red(&s, 0.5f, 0.5f, -1.0f) == 1.0f);
    /* MIPMAPLODBIAS takes part in the choice even without mipmapping */
    s.state[IS_SAMP_MAGFILTER] = IS_TEXF_POINT;
    s.state[IS_SAMP_MIPMAPLODBIAS] = fbits(1.0f);
    assert_true(red(&s, 0.5f, 0.5f, -0.5f) == 0.5f);  /* -0.5 + 1 > 0: MINFILTER (linear) */
    dev_destroy(dev);
}

static void test_mip_filter(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = r32f(dev, 4, 4, 0, level_no); /* levels 4x4, 2x2, 1x1 hold 1, 2, 3 */
    is_sampler s = tex_sampler_default(t);
    const float lods[] = {-3, 0, 0.5f, 0.51f, 1.49f, 1.5f, 1.6f, 2, 10, INFINITY, -INFINITY, NAN};
    const float none[] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    const float point[] = {1, 1, 1, 2, 2, 2, 3, 3, 3, 3, 1, 1};   /* nearest level, halves down */
    const float linear[] = {1, 1, 1.5f, 1.51f, 2.49f, 2.5f, 2.6f, 3, 3, 3, 1, 1};
    for (size_t k = 0; k < sizeof lods / sizeof lods[0]; k++) {
        s.state[IS_SAMP_MIPFILTER] = IS_TEXF_NONE;
        assert_true(red(&s, 0.3f, 0.6f, lods[k]) == none[k]);
        s.state[IS_SAMP_MIPFILTER] = IS_TEXF_POINT;
        float got = red(&s, 0.3f, 0.6f, lods[k]);
        if (got != point[k]) fail_msg("POINT lod %g: %g", lods[k], got);
        s.state[IS_SAMP_MIPFILTER] = IS_TEXF_LINEAR;
        float want = 1 + (2 - 1) * (lods[k] - 0); /* the blend of levels floor and floor + 1, as computed here */
        if (lods[k] >= 1 && lods[k] < 2) want = 2 + (3 - 2) * (lods[k] - 1);
        if (!(lods[k] > 0) || lods[k] != lods[k]) want = 1;
        if (lods[k] >= 2) want = 3;
        assert_true(want == linear[k] || fabsf(want - linear[k]) < 1e-6f);
        got = red(&s, 0.3f, 0.6f, lods[k]);
        if (got != want) fail_msg("LINEAR lod %g: %g, want %g", lods[k], got, want);
    }
    dev_destroy(dev);
}

/* MAXMIPLEVEL: the most detailed level used (Wine's maxmip_test: ignored without a MIPFILTER; past the chain the
 * last level). */
static void test_max_mip_level(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = r32f(dev, 4, 4, 0, level_no);
    is_sampler s = tex_sampler_default(t);
    const float want_point[4] = {1, 2, 3, 3}, want_none[4] = {1, 1, 1, 1};
    for (uint32_t m = 0; m < 4; m++) {
        s.state[IS_SAMP_MAXMIPLEVEL] = m;
        s.state[IS_SAMP_MIPFILTER] = IS_TEXF_NONE;
        assert_true(red(&s, 0.5f, 0.5f, -2) == want_none[m]);
        s.state[IS_SAMP_MIPFILTER] = IS_TEXF_POINT;
        assert_true(red(&s, 0.5f, 0.5f, -2) == want_point[m]);  /* magnified, still clamped up */
        assert_true(red(&s, 0.5f, 0.5f, 0.0f) == want_point[m]);
        s.state[IS_SAMP_MIPFILTER] = IS_TEXF_LINEAR;
        assert_true(red(&s, 0.5f, 0.5f, 0.25f) == (m == 0 ? 1.25f : want_point[m]));
    }
    s.state[IS_SAMP_MAXMIPLEVEL] = 1;
    assert_true(red(&s, 0.5f, 0.5f, 1.5f) == 2.5f); /* above MAXMIPLEVEL the level of detail counts */
    dev_destroy(dev);
}

static void test_lod_bias(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = r32f(dev, 4, 4, 0, level_no);
    is_sampler s = tex_sampler_default(t);
    s.state[IS_SAMP_MIPFILTER] = IS_TEXF_POINT;
    s.state[IS_SAMP_MIPMAPLODBIAS] = fbits(1.0f);
    assert_true(red(&s, 0.5f, 0.5f, 0) == 2);       /* tex2Dlod's lod 0 + bias 1 */
    s.state[IS_SAMP_MIPMAPLODBIAS] = fbits(-1.0f);
    assert_true(red(&s, 0.5f, 0.5f, 1.25f) == 1);   /* 0.25: level 0 */
    assert_true(red(&s, 0.5f, 0.5f, 2.75f) == 3);   /* 1.75: level 2 */
    s.state[IS_SAMP_MIPFILTER] = IS_TEXF_LINEAR;
    s.state[IS_SAMP_MIPMAPLODBIAS] = fbits(0.5f);
    assert_true(red(&s, 0.5f, 0.5f, 0.25f) == 1.75f);
    s.state[IS_SAMP_MIPMAPLODBIAS] = fbits(NAN);    /* NaN lambda reads as 0 */
    assert_true(red(&s, 0.5f, 0.5f, 1.0f) == 1);
    dev_destroy(dev);
}

/* ---------------- level of detail from derivatives ---------------- */

static void test_log2(void **state)
{
    for (int e = -126; e < 128; e++) assert_true(tex_log2(ldexpf(1.0f, e)) == (float)e); /* exact at powers of 2 */
    assert_true(tex_log2(0.0f) == -INFINITY);
    assert_true(tex_log2(INFINITY) == INFINITY);
    assert_true(isnan(tex_log2(-1.0f)) && isnan(tex_log2(NAN)));
    /* within 1 ulp of the double-precision logarithm, over a sweep */
    for (float x = 1e-30f; x < 1e30f; x *= 1.0173f) {
        float got = tex_log2(x), ref = (float)log2((double)x);
        float ulp = nextafterf(fabsf(ref), INFINITY) - fabsf(ref);
        if (fabsf(got - ref) > ulp) fail_msg("log2(%a) = %a, libm %a", x, got, ref);
    }
}

static void test_grad_and_bias(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t = r32f(dev, 8, 8, 0, level_no); /* levels 8, 4, 2, 1 hold 1, 2, 3, 4 */
    is_sampler s = tex_sampler_default(t);
    s.state[IS_SAMP_MIPFILTER] = IS_TEXF_POINT;
    /* footprint along x: (du/dx * 8, dv/dx * 8) */
    assert_true(tex_lod_from_gradients(8, 8, f2(0.25f, 0), f2(0, 0.125f)) == 1.0f);  /* max(2, 1) texels */
    assert_true(tex_lod_from_gradients(8, 8, f2(0, 0.125f), f2(0.5f, 0)) == 2.0f);   /* max(1, 4) */
    assert_true(tex_lod_from_gradients(8, 4, f2(0, 0.5f), f2(0, 0)) == 1.0f);        /* height 4: 2 texels */
    assert_true(tex_lod_from_gradients(8, 8, f2(0, 0), f2(0, 0)) == -INFINITY);
    float l = tex_lod_from_gradients(8, 8, f2(0.375f, 0.5f), f2(0, 0)); /* (3, 4): length 5 */
    assert_true(fabsf(l - (float)log2(5.0)) <= 3e-7f);
    assert_true(tex2Dgrad(&s, f2(0.5f, 0.5f), f2(0.25f, 0), f2(0, 0.25f)).x == 2);
    assert_true(tex2Dgrad(&s, f2(0.5f, 0.5f), f2(1.0f, 0), f2(0, 0)).x == 4);
    assert_true(tex2Dgrad(&s, f2(0.5f, 0.5f), f2(0, 0), f2(0, 0)).x == 1);
    assert_true(tex2Dbias(&s, f4(0.5f, 0.5f, 0, 1.0f), f2(0.25f, 0), f2(0, 0.25f)).x == 3);  /* 1 + 1 */
    assert_true(tex2Dbias(&s, f4(0.5f, 0.5f, 0, -1.0f), f2(0.25f, 0), f2(0, 0.25f)).x == 1); /* 1 - 1 */
    s.state[IS_SAMP_MIPMAPLODBIAS] = fbits(1.0f);
    assert_true(tex2Dbias(&s, f4(0.5f, 0.5f, 0, 1.0f), f2(0.25f, 0), f2(0, 0.25f)).x == 4);  /* 1 + 1 + 1 */
    is_sampler empty = tex_sampler_default(NULL);
    assert_true(tex2Dgrad(&empty, f2(0.5f, 0.5f), f2(1, 0), f2(0, 1)).w == 1.0f);
    dev_destroy(dev);
}

/* ---------------- mip chains ---------------- */

static void test_filter_texture_box(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t;
    is_locked_rect lr;
    assert_int_equal(dev_create_texture(dev, 3, 2, 0, 0, IS_FMT_A8R8G8B8, &t), IS_OK); /* 3x2, 1x1 */
    assert_int_equal(tex_get_level_count(t), 2);
    const uint32_t px[6] = {0x00000000u, 0x01020304u, 0xffffffffu, 0x00000001u, 0x01000003u, 0x80808080u};
    assert_int_equal(tex_lock_rect(t, 0, &lr, NULL, 0), IS_OK);
    memcpy(lr.bits, px, sizeof px);
    tex_unlock_rect(t, 0);
    tex_generate_mip_sub_levels(t);   /* not AUTOGENMIPMAP: nothing, as D3D9 */
    assert_int_equal(*(uint32_t *)t->lv[1].bits, 0u);
    assert_int_equal(tex_filter_texture(t), IS_OK);
    /* texels (0, 0), (1, 0), (0, 1), (1, 1) (column 2 dropped: odd side), bytes (sum + 2) / 4:
     * B: (0 + 4 + 1 + 3 + 2) / 4 = 2; G: (0 + 3 + 0 + 0 + 2) / 4 = 1; R: (0 + 2 + 0 + 0 + 2) / 4 = 1;
     * A: (0 + 1 + 0 + 1 + 2) / 4 = 1 */
    assert_int_equal(*(uint32_t *)t->lv[1].bits, 0x01010102u);
    assert_int_equal(tex_lock_rect(t, 1, &lr, NULL, 0), IS_OK);
    assert_int_equal(tex_filter_texture(t), IS_ERR_INVALIDCALL); /* a level is locked */
    tex_unlock_rect(t, 1);

    /* floats: ((a + b) + (c + d)) / 4; a side of 1 repeats its texel (4x1 -> 2x1 -> 1x1) */
    is_texture *f;
    assert_int_equal(dev_create_texture(dev, 4, 1, 0, 0, IS_FMT_A32B32G32R32F, &f), IS_OK);
    assert_int_equal(tex_lock_rect(f, 0, &lr, NULL, 0), IS_OK);
    const float v[16] = {1, 2, 3, 4, 3, 2, 1, 0, 0.5f, 0.5f, 0.5f, 0.5f, -1, 10, 100, 1000};
    memcpy(lr.bits, v, sizeof v);
    tex_unlock_rect(f, 0);
    assert_int_equal(tex_filter_texture(f), IS_OK);
    const float *l1 = (const float *)f->lv[1].bits, *l2 = (const float *)f->lv[2].bits;
    const float want1[8] = {2, 2, 2, 2, -0.25f, 5.25f, 50.25f, 500.25f};
    for (int k = 0; k < 8; k++) assert_true(l1[k] == want1[k]);
    const float want2[4] = {0.875f, 3.625f, 26.125f, 251.125f};
    for (int k = 0; k < 4; k++) assert_true(l2[k] == want2[k]);
    dev_destroy(dev);
}

static void test_autogen(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t;
    is_locked_rect lr;
    assert_int_equal(dev_create_texture(dev, 2, 2, 0, IS_USAGE_AUTOGENMIPMAP, IS_FMT_R32F, &t), IS_OK);
    assert_int_equal(tex_get_level_count(t), 1);                              /* one level shown */
    assert_int_equal(tex_lock_rect(t, 1, &lr, NULL, 0), IS_ERR_INVALIDCALL);  /* the sublevel is not */
    is_sampler s = tex_sampler_default(t);
    s.state[IS_SAMP_MIPFILTER] = IS_TEXF_POINT;
    assert_int_equal(tex_lock_rect(t, 0, &lr, NULL, 0), IS_OK);
    memcpy(lr.bits, (const float[4]){1, 2, 3, 6}, 16);
    assert_true(red(&s, 0.5f, 0.5f, 1) == 0);  /* not generated while locked */
    assert_int_equal(tex_unlock_rect(t, 0), IS_OK);
    assert_true(red(&s, 0.5f, 0.5f, 1) == 3);  /* the unlock generated level 1: (1 + 2 + 3 + 6) / 4 */
    assert_int_equal(tex_lock_rect(t, 0, &lr, NULL, IS_LOCK_READONLY), IS_OK);
    ((float *)lr.bits)[3] = 10;                /* written anyway, under a read-only lock */
    assert_int_equal(tex_unlock_rect(t, 0), IS_OK);
    assert_true(red(&s, 0.5f, 0.5f, 1) == 3);  /* a read-only unlock generates nothing */
    tex_generate_mip_sub_levels(t);
    assert_true(red(&s, 0.5f, 0.5f, 1) == 4);  /* (1 + 2 + 3 + 10) / 4 */
    dev_destroy(dev);
}

/* ---------------- textures from image files ---------------- */

typedef struct fixture { char dir[64]; } fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    if (!f) return -1;
    snprintf(f->dir, sizeof f->dir, "/tmp/instess-test-texture-XXXXXX");
    if (!mkdtemp(f->dir)) return free(f), -1;
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    DIR *d = opendir(f->dir);
    struct dirent *e;
    char p[400];
    while (d && (e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
            snprintf(p, sizeof p, "%s/%s", f->dir, e->d_name), unlink(p);
    if (d) closedir(d);
    rmdir(f->dir);
    free(f);
    return 0;
}

/* Write n bytes to dir/name; the path into buf. */
static const char *write_file(const fixture *f, const char *name, const void *bytes, size_t n, char *buf)
{
    snprintf(buf, 160, "%s/%s", f->dir, name);
    FILE *fp = fopen(buf, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(bytes, 1, n, fp), n);
    fclose(fp);
    return buf;
}

/* A 2x2 image's texels as a texture read back: top-left, top-right, bottom-left, bottom-right (r, g, b). */
static void expect_2x2(is_device *dev, const char *path, const unsigned char want[4][3])
{
    is_texture *t = NULL;
    if (dev_create_texture_from_file(dev, path, IS_FMT_A8R8G8B8, 1, &t) != IS_OK) fail_msg("%s", dev_last_error(dev));
    const unsigned char *b = t->lv[0].bits;
    for (int k = 0; k < 4; k++) {
        assert_int_equal(b[4 * k + 2], want[k][0]);
        assert_int_equal(b[4 * k + 1], want[k][1]);
        assert_int_equal(b[4 * k + 0], want[k][2]);
        assert_int_equal(b[4 * k + 3], 255);
    }
    tex_release(t);
}

static void test_texture_files(void **state)
{
    fixture *f = *state;
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    char path[160];
    const unsigned char want[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {10, 20, 30}};
    /* a BMP: 24-bit, rows bottom-up, B G R, each row padded to 4 bytes */
    unsigned char bmp[54 + 16] = {'B', 'M', 70, 0, 0, 0, 0, 0, 0, 0, 54, 0, 0, 0, 40, 0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0,
                                  1, 0, 24, 0, 0, 0, 0, 0, 16, 0, 0, 0, 0x13, 0x0b, 0, 0, 0x13, 0x0b, 0, 0};
    const unsigned char rows[16] = {255, 0, 0, 30, 20, 10, 0, 0,   /* bottom row: blue, (10, 20, 30) */
                                    0, 0, 255, 0, 255, 0, 0, 0};   /* top row: red, green */
    memcpy(bmp + 54, rows, 16);
    expect_2x2(dev, write_file(f, "t.bmp", bmp, sizeof bmp, path), want);
    /* a TGA: uncompressed true colour, 24 bits, origin top-left (descriptor bit 5), B G R */
    unsigned char tga[18 + 12] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 2, 0, 24, 0x20,
                                  0, 0, 255, 0, 255, 0, 255, 0, 0, 30, 20, 10};
    expect_2x2(dev, write_file(f, "t.tga", tga, sizeof tga, path), want);
    /* a PNG and an EXR written by image/ */
    is_image img = {0};
    char err[256];
    assert_int_equal(image_alloc(&img, 2, 2, "R,G,B,A", err, sizeof err), 0);
    for (int k = 0; k < 4; k++)
        for (int c = 0; c < 3; c++) img.data[4 * k + c] = want[k][c] / 255.0f;
    for (int k = 0; k < 4; k++) img.data[4 * k + 3] = 1;
    snprintf(path, sizeof path, "%s/t.png", f->dir);
    assert_int_equal(image_write(&img, path, NULL, err, sizeof err), 0);
    expect_2x2(dev, path, want);
    const float hdr[4] = {0.5f, 2.0f, -0.25f, 1024.0f}; /* exact in half */
    for (int k = 0; k < 4; k++) img.data[4 * k] = hdr[k];
    snprintf(path, sizeof path, "%s/t.exr", f->dir);
    assert_int_equal(image_write(&img, path, NULL, err, sizeof err), 0);
    is_texture *t;
    assert_int_equal(dev_create_texture_from_file(dev, path, IS_FMT_R32F, 0, &t), IS_OK);
    assert_int_equal(tex_get_level_count(t), 2);
    for (int k = 0; k < 4; k++) assert_true(((float *)t->lv[0].bits)[k] == hdr[k]);
    assert_true(((float *)t->lv[1].bits)[0] == (0.5f + 2.0f + (-0.25f + 1024.0f)) * 0.25f);
    image_free(&img);
    /* grey: one channel becomes r = g = b */
    assert_int_equal(image_alloc(&img, 1, 1, "Y", err, sizeof err), 0);
    img.data[0] = 0.5f;
    snprintf(path, sizeof path, "%s/grey.exr", f->dir);
    assert_int_equal(image_write(&img, path, NULL, err, sizeof err), 0);
    assert_int_equal(dev_create_texture_from_file(dev, path, IS_FMT_A32B32G32R32F, 1, &t), IS_OK);
    const float *g = (const float *)t->lv[0].bits;
    assert_true(g[0] == 0.5f && g[1] == 0.5f && g[2] == 0.5f && g[3] == 1.0f);
    image_free(&img);
    /* errors name the file and create nothing */
    is_texture *before = dev->textures;
    snprintf(path, sizeof path, "%s/missing.png", f->dir);
    assert_int_equal(dev_create_texture_from_file(dev, path, IS_FMT_R32F, 1, &t), IS_ERR_NOTAVAILABLE);
    assert_non_null(strstr(dev_last_error(dev), path));
    write_file(f, "junk.png", "not a png", 9, path);
    assert_int_equal(dev_create_texture_from_file(dev, path, IS_FMT_R32F, 1, &t), IS_ERR_NOTAVAILABLE);
    assert_non_null(strstr(dev_last_error(dev), path));
    snprintf(path, sizeof path, "%s/t.tga", f->dir);
    assert_int_equal(dev_create_texture_from_file(dev, path, IS_FMT_INDEX32, 1, &t), IS_ERR_NOTAVAILABLE);
    assert_non_null(strstr(dev_last_error(dev), path));
    assert_ptr_equal(dev->textures, before);
    dev_destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_create_and_levels),   cmocka_unit_test(test_ownership),
        cmocka_unit_test(test_sampler_states),      cmocka_unit_test(test_formats),
        cmocka_unit_test(test_point_texel_centres), cmocka_unit_test(test_linear_texel_centres),
        cmocka_unit_test(test_address_modes_u),     cmocka_unit_test(test_address_modes_v),
        cmocka_unit_test(test_border_linear),       cmocka_unit_test(test_min_mag_filter),
        cmocka_unit_test(test_mip_filter),          cmocka_unit_test(test_max_mip_level),
        cmocka_unit_test(test_lod_bias),            cmocka_unit_test(test_log2),
        cmocka_unit_test(test_grad_and_bias),       cmocka_unit_test(test_filter_texture_box),
        cmocka_unit_test(test_autogen),             cmocka_unit_test(test_formats_linear),
        cmocka_unit_test_setup_teardown(test_texture_files, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
