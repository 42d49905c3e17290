/* tests/test_vtf.c -- vertex texture fetch: SetTexture / SetSamplerState on D3DVERTEXTEXTURESAMPLER0..3 (257..260)
 * reach a C vertex shader as c->s[0..3], whose tex2Dlod reads the bound texture with those states; the colours of
 * points placed by such a shader are checked texel by texel, and a grid displaced by a fetched height renders the
 * same bytes on 1 and 2 threads, on the reference path and on every instruction set this CPU has. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "../core/device_internal.h"
#include "../core/hlsl.h"

enum { W = 16, H = 16 };

/* One point: pixel (x, y) in POSITION0.xy; TEXCOORD0 = (u, v, 0, lod); TEXCOORD1.x = the vertex sampler k. */
typedef struct point_vertex { float x, y, u, v, z, lod, k; } point_vertex;
static const is_vertex_element point_decl[] = {
    {0, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0},
    {0, 8, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, 0},
    {0, 24, IS_DECLTYPE_FLOAT1, 0, IS_DECLUSAGE_TEXCOORD, 1}, IS_DECL_END};

/* The point at its pixel, coloured by tex2Dlod of vertex sampler k at TEXCOORD0. */
static void vs_fetch_colour(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    float x = in->position[0].x, y = in->position[0].y;
    out->pos = f4(2.0f * x / W - 1.0f, 1.0f - 2.0f * y / H, 0.5f, 1.0f);
    out->attr[RS_ATTR_COLOR0] = tex2Dlod(&c->s[(int)in->texcoord[1].x], in->texcoord[0]);
}
static const is_vertex_shader vs_fetch = {.name = "fetch", .main = vs_fetch_colour, .outputs = IS_OUT_COLOR0};

/* A w x h A8R8G8B8 texture (levels as given) whose texel (i, j) of level l is the D3DCOLOR argb(l, i, j). */
static is_texture *colour_texture(is_device *dev, unsigned w, unsigned h, unsigned levels,
                                  uint32_t (*argb)(unsigned, unsigned, unsigned))
{
    is_texture *t;
    assert_int_equal(dev_create_texture(dev, w, h, levels, 0, IS_FMT_A8R8G8B8, &t), IS_OK);
    for (unsigned l = 0; l < tex_get_level_count(t); l++) {
        is_locked_rect lr;
        is_texture_desc d;
        tex_get_level_desc(t, l, &d);
        assert_int_equal(tex_lock_rect(t, l, &lr, NULL, 0), IS_OK);
        for (unsigned j = 0; j < d.height; j++)
            for (unsigned i = 0; i < d.width; i++) ((uint32_t *)((char *)lr.bits + j * lr.pitch))[i] = argb(l, i, j);
        tex_unlock_rect(t, l);
    }
    return t;
}
static uint32_t distinct(unsigned l, unsigned i, unsigned j)
{
    return IS_COLOR_ARGB(255, 10 + 40 * i, 20 + 50 * j, 30 + 100 * l);
}
static uint32_t other(unsigned l, unsigned i, unsigned j) { return IS_COLOR_ARGB(255, 200, 7 * i + 1, 9 * j + 2); }

/* Draw the points on dev and return the target. */
static const rs_target *draw_points(is_device *dev, const point_vertex *p, unsigned n)
{
    is_vertex_buffer *vb;
    is_vertex_declaration *decl;
    assert_int_equal(dev_create_vertex_buffer(dev, n * sizeof *p, &vb), IS_OK);
    memcpy(vb_lock(vb), p, n * sizeof *p);
    assert_int_equal(dev_create_vertex_declaration(dev, point_decl, &decl), IS_OK);
    dev_set_vertex_declaration(dev, decl);
    dev_set_vertex_shader(dev, &vs_fetch);
    dev_set_stream_source(dev, 0, vb, 0, sizeof *p);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_POINTLIST, 0, n), IS_OK);
    vb_release(vb);
    decl_release(decl);
    return dev_render_target(dev);
}

/* The target's pixel (x, y) as a D3DCOLOR (the target stores RGBA8: r in the low byte). */
static uint32_t pixel_argb(const rs_target *rt, int x, int y)
{
    uint32_t c = rt->color[y * rt->width + x];
    return IS_COLOR_ARGB(c >> 24, c & 0xff, (c >> 8) & 0xff, (c >> 16) & 0xff);
}

/* Every texel through its centre, outside [0, 1] under WRAP and CLAMP, a level by tex2Dlod's lod, and the
 * samplers 257..260 as s[0..3]; on 1 and 2 threads and the reference path. */
static void test_vtf_points(void **state)
{
    for (int run = 0; run < 3; run++) {
        is_device *dev = dev_create(W, H, 1, NULL, 0);
        dev_set_threads(dev, run == 1 ? 2 : 1);
        dev_set_reference_path(dev, run == 2);
        is_texture *t = colour_texture(dev, 4, 4, 0, distinct), *t3 = colour_texture(dev, 2, 2, 1, other);
        assert_int_equal(dev_set_texture(dev, IS_VERTEXTEXTURESAMPLER(0), t), IS_OK);
        assert_int_equal(dev_set_texture(dev, IS_VERTEXTEXTURESAMPLER(3), t3), IS_OK);
        assert_int_equal(dev_set_sampler_state(dev, IS_VERTEXTEXTURESAMPLER(0), IS_SAMP_ADDRESSV, IS_TADDRESS_CLAMP),
                         IS_OK);
        assert_int_equal(dev_set_sampler_state(dev, IS_VERTEXTEXTURESAMPLER(0), IS_SAMP_MIPFILTER, IS_TEXF_POINT),
                         IS_OK);
        point_vertex p[24];
        uint32_t want[24];
        unsigned n = 0;
        for (unsigned j = 0; j < 4; j++)
            for (unsigned i = 0; i < 4; i++, n++) {
                p[n] = (point_vertex){(float)i, (float)j, (i + 0.5f) / 4, (j + 0.5f) / 4, 0, 0, 0};
                want[n] = distinct(0, i, j);
            }
        p[n] = (point_vertex){5, 0, -0.125f, 0.375f, 0, 0, 0}, want[n++] = distinct(0, 3, 1);  /* u wraps (default) */
        p[n] = (point_vertex){6, 0, 0.375f, -0.125f, 0, 0, 0}, want[n++] = distinct(0, 1, 0);  /* v clamps (set) */
        p[n] = (point_vertex){7, 0, 0.375f, 1.625f, 0, 0, 0}, want[n++] = distinct(0, 1, 3);
        p[n] = (point_vertex){8, 0, 0.75f, 0.25f, 0, 1, 0}, want[n++] = distinct(1, 1, 0);     /* lod 1: 2x2 level */
        p[n] = (point_vertex){9, 0, 0.75f, 0.75f, 0, 2, 0}, want[n++] = distinct(2, 0, 0);     /* lod 2: 1x1 */
        p[n] = (point_vertex){10, 0, 0.75f, 0.25f, 0, 0, 3}, want[n++] = other(0, 1, 0);        /* s3 = sampler 260 */
        p[n] = (point_vertex){11, 0, 0.25f, 0.75f, 0, 5, 3}, want[n++] = other(0, 0, 1);        /* s3: no mipmapping */
        p[n] = (point_vertex){12, 0, 0.5f, 0.5f, 0, 0, 1}, want[n++] = IS_COLOR_ARGB(255, 0, 0, 0); /* s1: empty */
        const rs_target *rt = draw_points(dev, p, n);
        for (unsigned k = 0; k < n; k++) {
            uint32_t got = pixel_argb(rt, (int)p[k].x, (int)p[k].y);
            if (got != want[k]) fail_msg("run %d, point %u: %08x, want %08x", run, k, got, want[k]);
        }
        /* a state set on a pixel sampler does not reach the vertex shader's */
        assert_int_equal(dev_set_sampler_state(dev, 0, IS_SAMP_ADDRESSU, IS_TADDRESS_CLAMP), IS_OK);
        rt = draw_points(dev, p, n);
        assert_int_equal(pixel_argb(rt, 5, 0), distinct(0, 3, 1));
        /* SetTexture(NULL) empties s0: the fetch reads (0, 0, 0, 1) */
        assert_int_equal(dev_set_texture(dev, IS_VERTEXTEXTURESAMPLER(0), NULL), IS_OK);
        rt = draw_points(dev, p, n);
        assert_int_equal(pixel_argb(rt, 1, 1), IS_COLOR_ARGB(255, 0, 0, 0));
        dev_destroy(dev);
    }
}

/* ---------------- a displaced grid: the same bytes on every route ---------------- */

enum { GRID = 24 };

/* A vertex of the grid at (x, y) in [0, 1]^2 (POSITION0), raised by 0.6 h (h the height texture's value, linear
 * filtered, at (x, y) with lod 0.5 between its two levels) and tilted into view; coloured by h. */
static void vs_height(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    float x = in->position[0].x, y = in->position[0].y;
    float h = tex2Dlod(&c->s[0], f4(x, y, 0, 0.5f)).x;
    float4 p = f4(1.6f * x - 0.8f, 1.6f * y - 0.8f, 0.5f - 0.3f * h, 1.0f);
    out->pos = f4(p.x + 0.3f * h, p.y - 0.2f * h, p.z, 1.0f);
    out->attr[RS_ATTR_COLOR0] = f4(h, 0.5f * h, 1.0f - h, 1.0f);
}
static const is_vertex_shader vs_grid = {.name = "height", .main = vs_height, .outputs = IS_OUT_COLOR0};

/* A height in [0, 1] at texel (i, j) of level 0 (a bumpy pattern). */
static float bump(unsigned l, unsigned i, unsigned j) { return (float)((i * 7 + j * 13 + (i * j) % 5) % 16) / 15.0f; }

/* The colour and depth bytes of the displaced grid drawn with `threads` threads, reference path or not, isa. */
static void render_grid(int threads, bool reference, int isa, uint32_t *color, float *depth)
{
    is_device *dev = dev_create(64, 64, 1, NULL, 0);
    dev_set_threads(dev, threads);
    dev_set_reference_path(dev, reference);
    assert_int_equal(dev_set_isa(dev, isa), 0);
    is_texture *t;
    assert_int_equal(dev_create_texture(dev, 8, 8, 2, 0, IS_FMT_R32F, &t), IS_OK);
    is_locked_rect lr;
    tex_lock_rect(t, 0, &lr, NULL, 0);
    for (unsigned j = 0; j < 8; j++)
        for (unsigned i = 0; i < 8; i++) ((float *)lr.bits)[j * 8 + i] = bump(0, i, j);
    tex_unlock_rect(t, 0);
    assert_int_equal(tex_filter_texture(t), IS_OK);
    dev_set_texture(dev, IS_VERTEXTEXTURESAMPLER(0), t);
    dev_set_sampler_state(dev, IS_VERTEXTEXTURESAMPLER(0), IS_SAMP_MINFILTER, IS_TEXF_LINEAR);
    dev_set_sampler_state(dev, IS_VERTEXTEXTURESAMPLER(0), IS_SAMP_MIPFILTER, IS_TEXF_LINEAR);
    is_vertex_buffer *vb;
    is_index_buffer *ib;
    assert_int_equal(dev_create_vertex_buffer(dev, (GRID + 1) * (GRID + 1) * 8, &vb), IS_OK);
    assert_int_equal(dev_create_index_buffer(dev, GRID * GRID * 6 * 4, IS_FMT_INDEX32, &ib), IS_OK);
    float *v = vb_lock(vb);
    for (int j = 0; j <= GRID; j++)
        for (int i = 0; i <= GRID; i++) {
            v[2 * (j * (GRID + 1) + i)] = (float)i / GRID;
            v[2 * (j * (GRID + 1) + i) + 1] = (float)j / GRID;
        }
    uint32_t *idx = ib_lock(ib);
    for (int j = 0, n = 0; j < GRID; j++)
        for (int i = 0; i < GRID; i++) {
            uint32_t a = (uint32_t)(j * (GRID + 1) + i), b = a + 1, c = a + GRID + 1, d = c + 1;
            idx[n++] = a, idx[n++] = c, idx[n++] = b, idx[n++] = b, idx[n++] = c, idx[n++] = d;
        }
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    is_vertex_declaration *decl;
    dev_create_vertex_declaration(dev, el, &decl);
    dev_set_vertex_declaration(dev, decl);
    dev_set_stream_source(dev, 0, vb, 0, 8);
    dev_set_indices(dev, ib);
    dev_set_vertex_shader(dev, &vs_grid);
    dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, (GRID + 1) * (GRID + 1), 0,
                                                 GRID * GRID * 2), IS_OK);
    const rs_target *rt = dev_render_target(dev);
    memcpy(color, rt->color, 64 * 64 * sizeof *color);
    memcpy(depth, rt->depth, 64 * 64 * sizeof *depth);
    decl_release(decl);
    vb_release(vb);
    ib_release(ib);
    dev_destroy(dev);
}

static void test_vtf_same_bytes_everywhere(void **state)
{
    static uint32_t c0[64 * 64], c1[64 * 64];
    static float d0[64 * 64], d1[64 * 64];
    is_device *probe = dev_create(8, 8, 1, NULL, 0);
    int isa = dev_isa(probe);
    bool avx512 = dev_set_isa(probe, RS_ISA_AVX512) == 0;
    dev_destroy(probe);
    render_grid(1, false, isa, c0, d0);
    int covered = 0, distinct_colours = 0;
    for (int p = 0; p < 64 * 64; p++) covered += c0[p] != 0;
    for (int p = 1; p < 64 * 64; p++) distinct_colours += c0[p] != c0[p - 1] && c0[p] && c0[p - 1];
    assert_true(covered > 1000);          /* the grid is drawn */
    assert_true(distinct_colours > 100);  /* and shaded by the fetched heights */
    const struct { int threads; bool ref; int isa; } runs[] = {
        {2, false, isa}, {1, true, isa}, {2, true, isa}, {2, false, RS_ISA_AVX2}, {2, false, RS_ISA_AVX512}};
    for (size_t r = 0; r < sizeof runs / sizeof runs[0]; r++) {
        if (runs[r].isa == RS_ISA_AVX512 && !avx512) continue;
        render_grid(runs[r].threads, runs[r].ref, runs[r].isa, c1, d1);
        assert_memory_equal(c0, c1, sizeof c0);
        assert_memory_equal(d0, d1, sizeof d0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vtf_points),
        cmocka_unit_test(test_vtf_same_bytes_everywhere),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
