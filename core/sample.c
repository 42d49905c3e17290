/* core/sample.c -- sampling a texture through a sampler: texel formats, address modes, point and linear
 * filtering with D3D9's texel centres, level selection and the level of detail (tex2Dlod, tex2Dgrad, tex2Dbias).
 * The rules are core/texture.h's; everything is scalar float (and double in tex_log2) in a fixed order. */
#include "device_internal.h"

#include <math.h>
#include <string.h>

/* A texel of the A8R8G8B8 / X8R8G8B8 layout at p (bytes B, G, R, A) as float4 (r, g, b, a); alpha 1 when !alpha. */
static inline float4 texel_8888(const unsigned char *p, bool alpha)
{
    return f4(p[2] / 255.0f, p[1] / 255.0f, p[0] / 255.0f, alpha ? p[3] / 255.0f : 1.0f);
}

/* A texel (i, j) inside level l of t as float4 (r, g, b, a), by the format table of texture.h. */
static float4 texel(const is_texture *t, const tex_level *l, size_t i, size_t j)
{
    const unsigned char *p = l->bits + (j * l->w + i) * t->bpp;
    float v[4];
    switch (t->format) {
    case IS_FMT_A8R8G8B8: return texel_8888(p, true);
    case IS_FMT_X8R8G8B8: return texel_8888(p, false);
    case IS_FMT_R32F: memcpy(v, p, 4); return f4(v[0], 1.0f, 1.0f, 1.0f);
    case IS_FMT_A32B32G32R32F: memcpy(v, p, 16); return f4(v[0], v[1], v[2], v[3]);
    default: return f4(0, 0, 0, 1);
    }
}

/* A coordinate in texel units made safe for integers: NaN as 0, beyond +-2^30 as +-2^30. */
static inline float clamp_coord(float x)
{
    if (x != x) return 0.0f;
    return x > 0x1p30f ? 0x1p30f : x < -0x1p30f ? -0x1p30f : x;
}

/* address() for an index outside [0, n): the address mode's rule; *outside set when BORDER finds it outside. */
static int64_t address_outside(uint32_t mode, int64_t i, int64_t n, bool *outside)
{
    int64_t m;
    switch (mode) {
    case IS_TADDRESS_MIRROR:
        m = i % (2 * n);
        if (m < 0) m += 2 * n;
        return m < n ? m : 2 * n - 1 - m;
    case IS_TADDRESS_CLAMP: return i < 0 ? 0 : i >= n ? n - 1 : i;
    case IS_TADDRESS_BORDER:
        if (i < 0 || i >= n) *outside = true;
        return i < 0 ? 0 : i >= n ? n - 1 : i;
    case IS_TADDRESS_MIRRORONCE:
        m = i < 0 ? -1 - i : i;
        return m >= n ? n - 1 : m;
    default: /* WRAP, and any value D3D9 does not define (DXVK decodes those as wrap too) */
        if ((n & (n - 1)) == 0) return i & (n - 1);   /* a power of two: the same index without a division */
        m = i % n;
        return m < 0 ? m + n : m;
    }
}

/* Texel index i of a side of n texels under address mode `mode`; *outside set when BORDER finds it outside. */
static inline int64_t address(uint32_t mode, int64_t i, int64_t n, bool *outside)
{
    if ((uint64_t)i < (uint64_t)n) return i;   /* inside: every mode keeps it (no division) */
    if (mode == IS_TADDRESS_WRAP && (n & (n - 1)) == 0) return i & (n - 1);   /* address_outside's, inline */
    return address_outside(mode, i, n, outside);
}

/* What every level of one sample shares: the sampler, its texture's format, the address modes and the border
 * colour (decoded only when an address mode is BORDER: no other mode reads it). */
typedef struct sample_ctx {
    const is_sampler *s;
    const is_texture *t;
    uint32_t mu, mv;
    float4 border;
} sample_ctx;

/* The texel at indices (i, j) of level l after the address modes, or the border colour. */
static float4 fetch(const sample_ctx *c, const tex_level *l, int64_t i, int64_t j)
{
    bool outside = false;
    int64_t x = address(c->mu, i, l->w, &outside);
    int64_t y = address(c->mv, j, l->h, &outside);
    return outside ? c->border : texel(c->t, l, (size_t)x, (size_t)y);
}

/* The texel at addressed indices (x, y) of level l, or the border colour when either side was outside. */
static inline float4 texel_or_border(const sample_ctx *c, const tex_level *l, int64_t x, bool ox, int64_t y, bool oy)
{
    return ox || oy ? c->border : texel(c->t, l, (size_t)x, (size_t)y);
}

/* a + (b - a) t per channel (exactly a at t = 0 and wherever a == b). */
static inline float4 lerp4(float4 a, float4 b, float t)
{
    return f4(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t, a.w + (b.w - a.w) * t);
}

/* Four floats, one per channel (r, g, b, a), for the 8-bit bilinear path: the same IEEE operations per channel as
 * float4's scalar code (conversion, division by 255, lerp4), four at a time. */
typedef float v4f __attribute__((vector_size(16)));

/* The texel at p of an 8-bit layout (bytes B, G, R, A) as (r, g, b, a) / 255; alpha 255 / 255 = 1 when !alpha. */
static inline v4f texel_8888_v(const unsigned char *p, bool alpha)
{
    typedef int v4i __attribute__((vector_size(16)));
    typedef unsigned v4u __attribute__((vector_size(16)));
    uint32_t w = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    v4u words = {w, w, w, w}, shift = {16, 8, 0, 24};   /* bytes 2, 1, 0, 3: R, G, B, A */
    v4i bytes = (v4i)((words >> shift) & 0xffu);
    v4f c = __builtin_convertvector(bytes, v4f);   /* exact: integers below 256 */
    if (!alpha) c[3] = 255.0f;
    return c / 255.0f;
}

/* The bilinear sample with weights (a, b) of the four texels (x0 | x1, y0 | y1), all inside, of 8-bit level l:
 * lerp4(lerp4(t00, t10, a), lerp4(t01, t11, a), b), channel by channel as the scalar path computes it. */
static inline float4 bilinear_8888(const tex_level *l, bool alpha, const int64_t x[2], const int64_t y[2], float a,
                                   float b)
{
    const unsigned char *r0 = l->bits + (size_t)y[0] * l->w * 4, *r1 = l->bits + (size_t)y[1] * l->w * 4;
    v4f t00 = texel_8888_v(r0 + x[0] * 4, alpha), t10 = texel_8888_v(r0 + x[1] * 4, alpha);
    v4f t01 = texel_8888_v(r1 + x[0] * 4, alpha), t11 = texel_8888_v(r1 + x[1] * 4, alpha);
    v4f av = {a, a, a, a}, bv = {b, b, b, b};
    v4f top = t00 + (t10 - t00) * av, bottom = t01 + (t11 - t01) * av;
    v4f r = top + (bottom - top) * bv;
    return f4(r[0], r[1], r[2], r[3]);
}

/* One level's sample at (u, v): point or bilinear with D3D9's texel centres. */
static float4 sample_level(const sample_ctx *c, unsigned level, float u, float v, bool linear)
{
    const tex_level *l = &c->t->lv[level];
    float x = clamp_coord(u * (float)l->w), y = clamp_coord(v * (float)l->h);
    if (!linear) return fetch(c, l, (int64_t)floorf(x), (int64_t)floorf(y));
    x = clamp_coord(x - 0.5f), y = clamp_coord(y - 0.5f);
    float fx = floorf(x), fy = floorf(y), a = x - fx, b = y - fy;
    int64_t i = (int64_t)fx, j = (int64_t)fy;
    bool ox[2] = {false, false}, oy[2] = {false, false};   /* each side addressed once for the four texels */
    int64_t xs[2] = {address(c->mu, i, l->w, &ox[0]), address(c->mu, i + 1, l->w, &ox[1])};
    int64_t ys[2] = {address(c->mv, j, l->h, &oy[0]), address(c->mv, j + 1, l->h, &oy[1])};
    is_format f = c->t->format;
    if ((f == IS_FMT_A8R8G8B8 || f == IS_FMT_X8R8G8B8) && !(ox[0] | ox[1] | oy[0] | oy[1]))
        return bilinear_8888(l, f == IS_FMT_A8R8G8B8, xs, ys, a, b);
    float4 t00 = texel_or_border(c, l, xs[0], ox[0], ys[0], oy[0]);
    float4 t10 = texel_or_border(c, l, xs[1], ox[1], ys[0], oy[0]);
    float4 t01 = texel_or_border(c, l, xs[0], ox[0], ys[1], oy[1]);
    float4 t11 = texel_or_border(c, l, xs[1], ox[1], ys[1], oy[1]);
    return lerp4(lerp4(t00, t10, a), lerp4(t01, t11, a), b);
}

/* A float from its bits (MIPMAPLODBIAS). */
static float state_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* The sample of s at (u, v) for level of detail lod (before the bias): texture.h's level selection. */
static float4 sample(const is_sampler *s, float u, float v, float lod)
{
    const is_texture *t = s->tex;
    if (!t) return f4(0, 0, 0, 1);
    float lambda = lod + state_float(s->state[IS_SAMP_MIPMAPLODBIAS]);
    if (lambda != lambda) lambda = 0.0f;
    sample_ctx c = {s, t, s->state[IS_SAMP_ADDRESSU], s->state[IS_SAMP_ADDRESSV], f4(0, 0, 0, 0)};
    if (c.mu == IS_TADDRESS_BORDER || c.mv == IS_TADDRESS_BORDER) {
        uint32_t bc = s->state[IS_SAMP_BORDERCOLOR];
        c.border = f4((float)((bc >> 16) & 0xff) / 255.0f, (float)((bc >> 8) & 0xff) / 255.0f,
                      (float)(bc & 0xff) / 255.0f, (float)(bc >> 24) / 255.0f);
    }
    bool linear = (lambda > 0.0f ? s->state[IS_SAMP_MINFILTER] : s->state[IS_SAMP_MAGFILTER]) > IS_TEXF_POINT;
    uint32_t mip = s->state[IS_SAMP_MIPFILTER];
    unsigned last = t->levels - 1;
    if (mip == IS_TEXF_NONE || last == 0) return sample_level(&c, 0, u, v, linear);
    float lo = (float)(s->state[IS_SAMP_MAXMIPLEVEL] < last ? s->state[IS_SAMP_MAXMIPLEVEL] : last);
    float lc = lambda < lo ? lo : lambda > (float)last ? (float)last : lambda;
    if (mip == IS_TEXF_POINT) return sample_level(&c, (unsigned)(ceilf(lc + 0.5f) - 1.0f), u, v, linear);
    unsigned l0 = (unsigned)lc;   /* lc >= 0: truncation is floor */
    float f = lc - (float)l0;
    float4 a = sample_level(&c, l0, u, v, linear);
    return l0 >= last || f == 0.0f ? a : lerp4(a, sample_level(&c, l0 + 1, u, v, linear), f);
}

float4 tex_sample_lod(const is_sampler *s, float4 t)
{
    if (!s) return f4(0, 0, 0, 1);   /* as an empty sampler */
    return sample(s, t.x, t.y, t.w);
}

float tex_log2(float x)
{
    if (x != x || x < 0.0f) return NAN;
    if (x == 0.0f) return -INFINITY;
    if (isinf(x)) return INFINITY;
    int e;
    double m = frexp((double)x, &e); /* x = m 2^e, m in [1/2, 1) */
    if (m < 0.70710678118654752) m *= 2.0, e--;
    /* ln m = 2 atanh(s), s = (m - 1) / (m + 1), |s| <= 0.1716: the series to s^13 is exact in double */
    double s = (m - 1.0) / (m + 1.0), s2 = s * s;
    double p = 1.0 / 13.0;
    p = 1.0 / 11.0 + s2 * p;
    p = 1.0 / 9.0 + s2 * p;
    p = 1.0 / 7.0 + s2 * p;
    p = 1.0 / 5.0 + s2 * p;
    p = 1.0 / 3.0 + s2 * p;
    p = 1.0 + s2 * p;
    return (float)((double)e + 2.0 * s * p * 1.4426950408889634);
}

float tex_lod_from_gradients(unsigned width, unsigned height, float2 ddx, float2 ddy)
{
    float ax = ddx.x * (float)width, ay = ddx.y * (float)height;
    float bx = ddy.x * (float)width, by = ddy.y * (float)height;
    float px = ax * ax + ay * ay, py = bx * bx + by * by;
    float rho2 = px > py || py != py ? px : py;
    return 0.5f * tex_log2(rho2); /* log2 of the longer footprint, sqrt(rho2) */
}

float4 tex_sample_grad(const is_sampler *s, float2 uv, float2 ddx, float2 ddy)
{
    if (!s || !s->tex) return f4(0, 0, 0, 1);
    return sample(s, uv.x, uv.y, tex_lod_from_gradients(s->tex->lv[0].w, s->tex->lv[0].h, ddx, ddy));
}

float4 tex_sample_bias(const is_sampler *s, float4 t, float2 ddx, float2 ddy)
{
    if (!s || !s->tex) return f4(0, 0, 0, 1);
    return sample(s, t.x, t.y, tex_lod_from_gradients(s->tex->lv[0].w, s->tex->lv[0].h, ddx, ddy) + t.w);
}
