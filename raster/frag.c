/* raster/frag.c -- the per-fragment back end shared by triangles, lines and points: shading (colour and AOV
 * planes from an attribute block), 8-bit alpha blending, and the depth test of lines and points.
 *
 * Blending (8-bit math): source and destination are RGBA8; each factor is an 8-bit value f in 0..255 standing
 * for f/255; a product a*f/255 is rounded to nearest (exactly: t = a*f + 128, (t + (t >> 8)) >> 8), and the
 * two products are added and saturated at 255:  out = min(255, round(s*fs/255) + round(d*fd/255)).
 * ONE is 255, so ONE/ONE adds exactly and ONE/ZERO copies exactly.
 */
#include "raster_internal.h"

/* round(a * f / 255) for a, f in 0..255, exact. */
static inline uint32_t mul8(uint32_t a, uint32_t f)
{
    RS_ASSERT(a <= 255 && f <= 255);
    uint32_t t = a * f + 128u;
    return (t + (t >> 8)) >> 8;
}

/* 8-bit factor of blend mode m for channel c (0..3 = R, G, B, A) given source s and destination d. */
static uint32_t factor(int m, int c, uint32_t s, uint32_t d)
{
    uint32_t sc = (s >> (8 * c)) & 0xffu, dc = (d >> (8 * c)) & 0xffu;
    uint32_t sa = s >> 24, da = d >> 24;
    switch (m) {
    case RS_BLEND_ZERO: return 0;
    case RS_BLEND_ONE: return 255;
    case RS_BLEND_SRCCOLOR: return sc;
    case RS_BLEND_INVSRCCOLOR: return 255 - sc;
    case RS_BLEND_SRCALPHA: return sa;
    case RS_BLEND_INVSRCALPHA: return 255 - sa;
    case RS_BLEND_DESTALPHA: return da;
    case RS_BLEND_INVDESTALPHA: return 255 - da;
    case RS_BLEND_DESTCOLOR: return dc;
    case RS_BLEND_INVDESTCOLOR: return 255 - dc;
    case RS_BLEND_SRCALPHASAT: return c == 3 ? 255 : (sa < 255 - da ? sa : 255 - da);
    default: return 0;
    }
}

uint32_t rs_blend(int sf, int df, uint32_t src, uint32_t dst)
{
    uint32_t r = 0;
    for (int c = 0; c < 4; c++) {
        uint32_t sc = (src >> (8 * c)) & 0xffu, dc = (dst >> (8 * c)) & 0xffu;
        uint32_t v = mul8(sc, factor(sf, c, src, dst)) + mul8(dc, factor(df, c, src, dst));
        r |= (v > 255u ? 255u : v) << (8 * c);
    }
    return r;
}

void rs_write_aov(const rs_job *j, const float *a, float b1, float b2, int x, int y)
{
    const rs_target *rt = j->rt;
    size_t px = (size_t)y * (size_t)rt->width + (size_t)x;
    for (int k = 0; k < rt->n_aov; k++) {
        int comps = rt->aov[k].comps, s = j->aov_idx[k];
        float *d = rt->aov[k].data + px * (size_t)comps;
        for (int q = 0; q < comps; q++) {
            const float *p = a + s * RS_ATTR_STRIDE + q * 3;
            d[q] = s < 0 ? 0.0f : p[0] + b1 * p[1] + b2 * p[2];
        }
    }
}

void rs_frag_const_z(const rs_job *j, rs_tile *t, int x, int y, unsigned cov, float z, const float *a,
                     float b1, float b2)
{
    const rs_state *st = j->st;
    size_t base = rs_tile_index(t, x, y) * (size_t)j->samples;
    float *dep = t->depth + base;
    z = rs_zclamp(z, j->zlo, j->zhi);
    if (j->ext) { /* pixel.c's states: lines and points use the front (clockwise) stencil states */
        const float zs[4] = { z, z, z, z };
        rs_frag_ext(j, t, x, y, cov, zs, false, a, b1, b2);
        return;
    }
    unsigned pass = cov;
    if (st->z_enable) {
        pass = 0;
        for (int s = 0; s < j->samples; s++) {
            if (!(cov & (1u << s)) || !rs_zpass(st->z_func, z, dep[s])) continue;
            pass |= 1u << s;
            if (st->z_write) dep[s] = z;
        }
    }
    t->tested += (uint64_t)__builtin_popcount(cov);
    if (!pass) return;
    t->written += (uint64_t)__builtin_popcount(pass);
    rs_write_color(j, t->color + base, pass, rs_shade_color(j, a, b1, b2));
    if (j->rt->n_aov > 0) rs_write_aov(j, a, b1, b2, x, y);
}
