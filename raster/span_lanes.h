/* raster/span_lanes.h -- what the 8-lane walks share (private to raster/: span.c, span_wide.c): the lane types and
 * helpers, the per-pixel operations of a group of 8 lanes (frag8, span8, shade8), the x / y parts of the planes,
 * the 32-bit edge values, the depth-state modes and the macros that instantiate a walk per mode.
 *
 * Conventions (both files):
 *  - exactness: every lane performs the same float operations in the same order as tri_pixel in tri.c (the
 *    reference path), without FMA (-ffp-contract=off) and with IEEE division, so every walk writes the reference's
 *    bytes.  The planes are split into an x part (the left operand of each sum: z2 + z0 * sx, s2 + s0 * fx, ...),
 *    computed once per group of lanes, and a y part (z1 * sy, s1 * fy, ...), computed once per row; each lane adds
 *    the two, as tri_pixel does.  Coverage is exact integer arithmetic (int64, or int32 where the values provably
 *    fit: coef_small);
 *  - lanes lie inside one tile (one thread), so loading and storing back untouched lanes is safe,
 *    except past the right end of the target, where span8 copies only the pixels that exist in and out;
 *  - a walk's arguments are rs_tri_fast's: job j, tile t, triangle p, attribute block a, box [x0, x1] x [y0, y1]
 *    clipped to the tile; its counters go to t->tested / t->written.
 * Everything here exists only with AVX2 (__AVX2__); both files are compiled once per instruction set (RS_KERNEL). */
#ifndef RASTER_SPAN_LANES_H
#define RASTER_SPAN_LANES_H

#include "raster_internal.h"

#include <string.h>

_Static_assert(RS_BLOCK == 8, "a block row is one group of 8 lanes");
_Static_assert(RS_TILE_MIN % 8 == 0, "a tile row is whole groups of 8 lanes");

#ifdef __AVX2__
#include <immintrin.h>

#define ALWAYS_INLINE static inline __attribute__((always_inline))

typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));
typedef uint32_t v8u __attribute__((vector_size(32)));
typedef int64_t v4q __attribute__((vector_size(32)));

/* Lane indices 0..7 as ints. */
static const v8i lane_idx = {0, 1, 2, 3, 4, 5, 6, 7};
static const v8i lane_bit = {1, 2, 4, 8, 16, 32, 64, 128};
/* Lane i of the 4x2 walk is column i & 3 of row i >> 2. */
static const v8i quad_col = {0, 1, 2, 3, 0, 1, 2, 3};
static const v8i quad_row = {0, 0, 0, 0, 1, 1, 1, 1};

/* Broadcast a float / an int to 8 lanes. */
static inline v8f bf(float x) { return (v8f){x, x, x, x, x, x, x, x}; }
static inline v8i bi(int32_t x) { return (v8i){x, x, x, x, x, x, x, x}; }
static inline v8u bu(uint32_t x) { return (v8u){x, x, x, x, x, x, x, x}; }

/* mask ? a : b per lane (mask lanes are -1 or 0). */
static inline v8f sel(v8i mask, v8f a, v8f b) { return (v8f)_mm256_blendv_ps((__m256)b, (__m256)a, (__m256)mask); }
static inline v8i seli(v8i mask, v8i a, v8i b)
{
    return (v8i)_mm256_blendv_ps((__m256)b, (__m256)a, (__m256)mask);
}

/* mask ? a : b per lane by mask's sign bits, as one vblendvps: sel's intrinsic is folded into a compare with 0
 * and a blend, one instruction more per group when the mask has two uses. */
static inline v8f blend_sign(v8i mask, v8f a, v8f b)
{
    v8f r;
    __asm__("vblendvps %3, %2, %1, %0" : "=x"(r) : "x"(b), "x"(a), "x"(mask));
    return r;
}

/* 8-bit lane mask -> -1 / 0 lanes. */
static inline v8i lanes_of(unsigned m) { return (bi((int32_t)m) & lane_bit) == lane_bit; }
/* -1 / 0 lanes (or any sign bits) -> 8-bit lane mask. */
static inline unsigned mask_of(v8i m) { return (unsigned)_mm256_movemask_ps((__m256)m); }
/* Lanes l0..l1 as an 8-bit mask. */
static inline unsigned lane_range(int l0, int l1) { return ((2u << l1) - 1u) & ~((1u << l0) - 1u); }

/* |X| < 2^24 in every lane: the offsets (1/256 px) whose conversion to float is exact (for RS_ASSERT). */
static inline bool lanes_exact(v8i X) { return mask_of((X >= bi(1 << 24)) | (X <= bi(-(1 << 24)))) == 0; }

/* rs_zclamp per lane, z >= lo ? (z <= hi ? z : hi) : lo (NaN -> lo), in three instructions: min(hi, z) is
 * hi < z ? hi : z, which is z <= hi ? z : hi but for a NaN z (then z), and the outer test's blend gives lo for
 * that: the same bits per lane, -0 and NaN included. */
static inline v8f zclamp8(v8f z, v8f lo, v8f hi)
{
    return sel(z >= lo, (v8f)_mm256_min_ps((__m256)hi, (__m256)z), lo);
}

/* rs_zpass per lane for compare function f. */
ALWAYS_INLINE v8i zpass8(int f, v8f z, v8f d) { return RS_ZPASS_LANES(v8i, f, z, d); }

/* rs_to8 per lane: saturate (NaN -> 0), * 255 + 0.5, truncate.  max(c, 0) is c > 0 ? c : 0 (NaN -> +0, as the
 * reference's 0.0f), then min(., 1) is . < 1 ? . : 1: the reference's c > 0 ? (c < 1 ? c : 1) : 0 exactly. */
static inline v8i to8_8(v8f c)
{
    v8f s = (v8f)_mm256_min_ps(_mm256_max_ps((__m256)c, _mm256_setzero_ps()), (__m256)bf(1.0f));
    return __builtin_convertvector(s * bf(255.0f) + bf(0.5f), v8i);
}

/* to8_8 for a channel that then goes through shade8's saturating packs (packusdw, then packuswb), which do the
 * lower saturation: min(1, c) is 1 < c ? 1 : c (c when NaN), then * 255 + 0.5 and truncation as rs_to8.  Per
 * lane the same 8 bits after the packs: c in (0, 1] gives rs_to8's operations; c > 1 gives 1, as rs_sat; c <= 0
 * (-0, -inf included) gives at most 0.5, truncated to 0 or to a negative int32 (0x80000000 when out of range),
 * which packusdw makes 0, as rs_sat's 0 -> 0.5 -> 0; NaN stays NaN, truncated to 0x80000000: 0, as rs_sat's NaN
 * -> 0.  packusdw leaves 0..255, which packuswb keeps.  One instruction less per channel than to8_8 (the max). */
static inline __m256i to8_8p(v8f c)
{
    const v8f s = (v8f)_mm256_min_ps((__m256)bf(1.0f), (__m256)c);
    return _mm256_cvttps_epi32((__m256)(s * bf(255.0f) + bf(0.5f)));
}

/* The 8-bit alpha of colour slot p when its alpha does not vary (p[10], p[11] are zeros), else -1.  Then
 * (p9 + b1 * p10) + b2 * p11 is p9 (or a zero when p9 is one) when b1 * p10 + b2 * p11 is not NaN, and NaN
 * when it is (b1 or b2 not finite): rs_to8 gives rs_to8(p9), resp. 0, exactly what shade8 computes from it. */
static inline int alpha_const(const float *p)
{
    return p && p[10] == 0.0f && p[11] == 0.0f ? (int)rs_to8(p[9]) : -1;
}

/* rs_shade_color per lane at barycentrics (b1, b2) from the colour slot's 12 coefficients p; a8: p's
 * alpha_const (>= 0: the alpha channel from it, see there).  vl: p holds them as v0, d1, d2 (four channels each,
 * the grid rows' stamp lanes: rs_tri_run) instead of rs_fill_slot's v0, d1, d2 per channel -- the same floats. */
ALWAYS_INLINE v8i shade8_l(const float *p, int a8, v8f b1, v8f b2, bool vl)
{
#define P(c, k) bf(vl ? p[4 * (k) + (c)] : p[3 * (c) + (k)]) /* channel c's v0 (k = 0), d1 (1), d2 (2) */
    __m256i r = (__m256i)to8_8(P(0, 0) + b1 * P(0, 1) + b2 * P(0, 2));
    __m256i g = (__m256i)to8_8(P(1, 0) + b1 * P(1, 1) + b2 * P(1, 2));
    __m256i b = (__m256i)to8_8(P(2, 0) + b1 * P(2, 1) + b2 * P(2, 2));
    __m256i al;
    if (a8 >= 0) {
        v8f t = b1 * P(3, 1) + b2 * P(3, 2);
        al = _mm256_and_si256((__m256i)_mm256_cmp_ps((__m256)t, (__m256)t, _CMP_ORD_Q), _mm256_set1_epi32(a8));
    } else {
        al = (__m256i)to8_8(P(3, 0) + b1 * P(3, 1) + b2 * P(3, 2));
    }
#undef P
    /* channels are 0..255, so the saturating packs are plain narrowing: per 128-bit half, bytes
     * r0..r3 g0..g3 b0..b3 a0..a3, then interleaved into r | g << 8 | b << 16 | a << 24 per pixel */
    __m256i x = _mm256_packus_epi16(_mm256_packus_epi32(r, g), _mm256_packus_epi32(b, al));
    const __m256i order = _mm256_setr_epi8(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15,
                                           0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15);
    return (v8i)_mm256_shuffle_epi8(x, order);
}
/* shade8_l with rs_fill_slot's layout. */
ALWAYS_INLINE v8i shade8(const float *p, int a8, v8f b1, v8f b2) { return shade8_l(p, a8, b1, b2, false); }

/* rs_shade_color per lane for job j (white without COLOR0), attribute block a. */
static inline v8i shade8_job(const rs_job *j, const float *a, v8f b1, v8f b2)
{
    return j->color_idx < 0 ? bi(-1) : shade8(a + j->color_idx * RS_ATTR_STRIDE, -1, b1, b2);
}

/* Copy the n (<= 8) existing values of a group in or out of a full 8-lane vector. */
static inline void load8(void *v, const void *src, int n)
{
    if (n == 8) memcpy(v, src, 32);
    else memcpy(v, src, (size_t)n * 4);
}
static inline void store8(void *dst, const void *v, int n)
{
    if (n == 8) memcpy(dst, v, 32);
    else memcpy(dst, v, (size_t)n * 4);
}

/* Depth-test, shade and write the covered pixels `cov` (bit i: pixel gx + i) of row y of triangle p, any state
 * (blending and AOV planes per pixel, as the reference), n = the pixels of the group inside the target. */
static void span8(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int gx, int y, unsigned cov)
{
    const rs_tri *tr = &p->u.t;
    const rs_state *st = j->st;
    const float k = 1.0f / RS_SUB;
    const int n = j->rt->width - gx < 8 ? j->rt->width - gx : 8;
    const size_t base = rs_tile_index(t, gx, y);
    v8i X = bi((int32_t)((int64_t)gx * RS_SUB - j->cx - tr->vx)) + lane_idx * RS_SUB;
    RS_ASSERT(lanes_exact(X) && rs_within((int64_t)y * RS_SUB - j->cy - tr->vy, 24));
    v8f fx = __builtin_convertvector(X, v8f) * bf(k);
    float fy = (float)((int64_t)y * RS_SUB - j->cy - tr->vy) * k;
    v8i pass = lanes_of(cov);
    if (st->z_enable) {
        float *dep = t->depth + base;
        v8f d = bf(0.0f);
        load8(&d, dep, n);
        v8f sx = fx + bf((float)j->sox[0] * k);
        float sy = fy + (float)j->soy[0] * k;
        v8f z = zclamp8(bf(tr->z[2]) + bf(tr->z[0]) * sx + bf(tr->z[1] * sy), bf(j->zlo), bf(j->zhi));
        pass &= zpass8(st->z_func, z, d);
        if (st->z_write) {
            d = sel(pass, z, d);
            store8(dep, &d, n);
        }
    }
    unsigned pm = mask_of(pass);
    t->tested += (uint64_t)__builtin_popcount(cov);
    if (!pm) return;
    t->written += (uint64_t)__builtin_popcount(pm);
    v8f sv = bf(tr->s[2]) + bf(tr->s[0]) * fx + bf(tr->s[1] * fy);
    v8f r = bf(1.0f) / sv;
    v8f b1 = (bf(tr->q1[2]) + bf(tr->q1[0]) * fx + bf(tr->q1[1] * fy)) * r;
    v8f b2 = (bf(tr->q2[2]) + bf(tr->q2[0]) * fx + bf(tr->q2[1] * fy)) * r;
    v8i src = shade8_job(j, a, b1, b2);
    uint32_t *col = t->color + base;
    if (st->blend_enable || j->rt->n_aov > 0) { /* rare: per pixel, as the reference */
        for (int i = 0; i < 8; i++) {
            if (!(pm & (1u << i))) continue;
            rs_write_color(j, col + i, 1u, (uint32_t)src[i]);
            if (j->rt->n_aov > 0) rs_write_aov(j, a, b1[i], b2[i], gx + i, y);
        }
        return;
    }
    v8i c = bi(0);
    load8(&c, col, n);
    c = seli(pass, src, c);
    store8(col, &c, n);
}

/* ---- the plain lanes: no blending, no AOV planes, all 8 lanes inside the target ---- */

/* The state a walk is specialised for: compile-time constants in the common instances, the job's values in
 * the generic one.  plain: no blending and no AOV planes (else rows go through span8). */
typedef struct zmode {
    bool ze, zw;     /* depth test, depth write */
    int zf;          /* RS_CMP_* */
    bool plain;
} zmode;

/* Per-triangle constants of a walk and its sample counters (added to the tile's at the end). */
typedef struct fctx {
    const rs_tri *tr;
    float *depth;          /* the tile's storage (rs_tile: the target's planes or the tile buffer) */
    uint32_t *color;
    size_t w;              /* row stride in pixels */
    int ox, oy;            /* the pixel at index 0 */
    v8f zlo, zhi;          /* depth clamp */
    const float *pc;       /* the colour slot's 12 coefficients (v0, d1, d2 per channel), NULL: white */
    int a8;                /* alpha_const(pc) */
    uint64_t tested, written;
} fctx;

/* The x parts of the planes for one lane layout (same values, same order as tri_pixel's left operands). */
typedef struct rows8 {
    v8f zx, sx, q1x, q2x;  /* z2 + z0 * sx, s2 + s0 * fx, q1_2 + q1_0 * fx, q2_2 + q2_0 * fx */
} rows8;

/* The y parts of the planes (per lane: one row, or two rows in the 4x2 walk). */
typedef struct ypart {
    v8f zy, sy, q1y, q2y;  /* z1 * sy, s1 * fy, q1_1 * fy, q2_1 * fy */
} ypart;

/* Index of pixel (x, y) in c's planes (rs_tile_index). */
static inline size_t fidx(const fctx *c, int x, int y) { return (size_t)(y - c->oy) * c->w + (size_t)(x - c->ox); }

/* Fill c for triangle p of job j drawn in tile t. */
static inline void fctx_make(fctx *c, const rs_job *j, const rs_tile *t, const rs_prim *p, const float *a)
{
    c->tr = &p->u.t;
    c->depth = t->depth;
    c->color = t->color;
    c->w = t->pitch;
    c->ox = t->ox, c->oy = t->oy;
    c->zlo = bf(j->zlo);
    c->zhi = bf(j->zhi);
    c->pc = j->color_idx < 0 ? NULL : a + j->color_idx * RS_ATTR_STRIDE;
    c->a8 = alpha_const(c->pc);
    c->tested = c->written = 0;
}

/* x parts for lane offsets X (1/256 px, relative to the viewport centre, minus vertex 0). */
static inline rows8 rows8_at(const rs_job *j, const rs_tri *tr, v8i X)
{
    const float k = 1.0f / RS_SUB;
    RS_ASSERT(lanes_exact(X));
    v8f fx = __builtin_convertvector(X, v8f) * bf(k); /* |X| < 2^24: exact in float, as tri_pixel's */
    v8f sx = fx + bf((float)j->sox[0] * k);
    rows8 r;
    r.zx = bf(tr->z[2]) + bf(tr->z[0]) * sx;
    r.sx = bf(tr->s[2]) + bf(tr->s[0]) * fx;
    r.q1x = bf(tr->q1[2]) + bf(tr->q1[0]) * fx;
    r.q2x = bf(tr->q2[2]) + bf(tr->q2[0]) * fx;
    return r;
}

/* y parts for lane offsets Y (1/256 px, relative to the viewport centre, minus vertex 0). */
static inline ypart ypart_at(const rs_job *j, const rs_tri *tr, v8i Y)
{
    const float k = 1.0f / RS_SUB;
    RS_ASSERT(lanes_exact(Y));
    v8f fy = __builtin_convertvector(Y, v8f) * bf(k);
    ypart y;
    y.zy = bf(tr->z[1]) * (fy + bf((float)j->soy[0] * k));
    y.sy = bf(tr->s[1]) * fy;
    y.q1y = bf(tr->q1[1]) * fy;
    y.q2y = bf(tr->q2[1]) * fy;
    return y;
}

/* 8 lanes from p0 (split: lanes 0..3 from p0, 4..7 from p1, two rows of the 4x2 walk). */
ALWAYS_INLINE __m256i load_lanes(const void *p0, const void *p1, bool split)
{
    if (!split) return _mm256_loadu_si256((const __m256i *)p0);
    return _mm256_inserti128_si256(_mm256_castsi128_si256(_mm_loadu_si128((const __m128i *)p0)),
                                   _mm_loadu_si128((const __m128i *)p1), 1);
}
ALWAYS_INLINE void store_lanes(void *p0, void *p1, bool split, __m256i v)
{
    if (!split) {
        _mm256_storeu_si256((__m256i *)p0, v);
        return;
    }
    /* lanes 4..7 first: when p1 == p0 (no second row) they are p0's old values, then overwritten */
    _mm_storeu_si128((__m128i *)p1, _mm256_extracti128_si256(v, 1));
    _mm_storeu_si128((__m128i *)p0, _mm256_castsi256_si128(v));
}

/* Depth-test (mode m), shade and write the lanes in cov whose pixels are at offsets o0 (lanes 0..7, or 0..3
 * when split) and o1 (lanes 4..7 when split; o1 == o0 when there is no second row: then lanes 4..7 are not
 * covered, load row o0 and are stored before lanes 0..3) of the target's planes, with planes x + y parts. */
ALWAYS_INLINE void frag8(fctx *c, zmode m, bool split, unsigned cov, size_t o0, size_t o1, const rows8 *r,
                         const ypart *y)
{
    v8i pass = lanes_of(cov);
    if (m.ze) {
        float *d0 = c->depth + o0, *d1 = c->depth + o1;
        v8f d = (v8f)load_lanes(d0, d1, split);
        v8f z = zclamp8(r->zx + y->zy, c->zlo, c->zhi);
        pass &= zpass8(m.zf, z, d);
        if (m.zw) store_lanes(d0, d1, split, (__m256i)blend_sign(pass, z, d));
    }
    unsigned pm = mask_of(pass);
    c->tested += (uint64_t)__builtin_popcount(cov);
    if (!pm) return;
    c->written += (uint64_t)__builtin_popcount(pm);
    v8f rr = bf(1.0f) / (r->sx + y->sy);
    v8f b1 = (r->q1x + y->q1y) * rr;
    v8f b2 = (r->q2x + y->q2y) * rr;
    v8i src = c->pc ? shade8(c->pc, c->a8, b1, b2) : bi(-1);
    uint32_t *c0 = c->color + o0, *c1 = c->color + o1;
    store_lanes(c0, c1, split, (__m256i)blend_sign(pass, (v8f)src, (v8f)load_lanes(c0, c1, split)));
}

/* ---- the edge values ---- */

/* Are all of triangle tr's edge coefficients ea, eb at most 2^13 (its extent at most 32 px both ways)?  Then the
 * edge values of pixels less than 128 px from each vertex both ways are below 2^29 + 1 in magnitude (|ea| * 256
 * * 128 + |eb| * 256 * 128, plus the top-left bias): exact in int32.  The walks that rely on it evaluate edges
 * at most 7 columns left of the box and 32 right of its first column, and the box lies within 33 px of each
 * vertex. */
static inline bool coef_small(const rs_tri *tr)
{
    const v8i u = (v8i)_mm256_loadu_si256((const __m256i *)tr->ea); /* ea[0..2], eb[0..2], ec[0] (not tested) */
    const v8i big = (u > bi(8192)) | (u < bi(-8192));
    return _mm256_testz_si256((__m256i)big, _mm256_setr_epi32(-1, -1, -1, -1, -1, -1, 0, 0));
}
_Static_assert(offsetof(rs_tri, eb) == offsetof(rs_tri, ea) + 3 * sizeof(int32_t) &&
               offsetof(rs_tri, ec) == offsetof(rs_tri, eb) + 3 * sizeof(int32_t) &&
               offsetof(rs_tri, vx) == offsetof(rs_tri, ec) + 3 * sizeof(int64_t),
               "the walks read the edge coefficients four at a time (the fourth lane is not used)");

/* Do the three edges' exact values fit int32 at every pixel of [x0, x1] x [y0, y1] (at its corners: the edge
 * functions are linear)?  The precondition of the 32-bit walks (coef_small's claim), for RS_ASSERT. */
static inline bool box_fits32(const rs_job *j, const rs_tri *tr, int x0, int y0, int x1, int y1)
{
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 4; k++) {
            int64_t X = (int64_t)(k & 1 ? x1 : x0) * RS_SUB - j->cx, Y = (int64_t)(k & 2 ? y1 : y0) * RS_SUB - j->cy;
            int64_t e = (int64_t)tr->ea[i] * X + (int64_t)tr->eb[i] * Y + tr->ec[i];
            if (e < INT32_MIN || e > INT32_MAX) return false;
        }
    return true;
}

/* The three edges' coefficients ea, eb, ec as int64 lanes 0..2 (lane 3: whatever follows in rs_tri). */
typedef struct edges4 {
    __m256i a, b, c;
} edges4;

/* Triangle tr's edges4: ea and eb sign-extended from int32, ec as stored. */
static inline edges4 edges4_of(const rs_tri *tr)
{
    return (edges4){_mm256_cvtepi32_epi64(_mm_loadu_si128((const __m128i *)tr->ea)),
                    _mm256_cvtepi32_epi64(_mm_loadu_si128((const __m128i *)tr->eb)),
                    _mm256_loadu_si256((const __m256i *)tr->ec)};
}

/* The three edges' values e[i] at the lanes (column col, row row) of a walk whose lane 0 is at (X, Y) (1/256 px
 * relative to the centre; only the low 32 bits matter), and their change dy[i] over `rows` rows.  Computed
 * modulo 2^32 (the low halves of 64-bit products are those of the full products): the true values of the
 * walked pixels fit in int32 (coef_small), so the wrapped ones are the same. */
static inline void edges32(const rs_tri *tr, uint32_t X, uint32_t Y, v8i col, v8i row, int rows, v8u *e, v8u *dy)
{
    const edges4 Q = edges4_of(tr); /* lanes 0..2 (as 64 bits): edges 0..2 */
    const __m256i a = Q.a, b = Q.b, c = Q.c;
    v8u E = (v8u)_mm256_add_epi64(_mm256_add_epi64(_mm256_mul_epu32(a, _mm256_set1_epi32((int)X)),
                                                   _mm256_mul_epu32(b, _mm256_set1_epi32((int)Y))), c);
    v8u A = (v8u)_mm256_slli_epi64(a, RS_SUB_BITS), B = (v8u)_mm256_slli_epi64(b, RS_SUB_BITS);
    for (int i = 0; i < 3; i++) { /* int32 lane 2i: the low half of edge i's 64-bit lane */
        const __m256i at = _mm256_set1_epi32(2 * i);
        v8u Bi = (v8u)_mm256_permutevar8x32_epi32((__m256i)B, at);
        e[i] = (v8u)_mm256_permutevar8x32_epi32((__m256i)E, at) +
               (v8u)col * (v8u)_mm256_permutevar8x32_epi32((__m256i)A, at) + (v8u)row * Bi;
        dy[i] = Bi * bu((uint32_t)rows);
    }
}

/* rs_tri_fast's medium triangles: boxes at most this many groups of 8 columns wide (up to 32 px) of coef_small
 * triangles, walked from each row's first column (span_wide.c); wider ones take its 8-aligned walk. */
#define SPAN_GROUPS 4

/* The modes: depth test LESSEQUAL (D3D9's default) or LESS with writes, no blending, no AOV planes; any other
 * state with the job's values. */
#define MODE_LE ((zmode){true, true, RS_CMP_LESSEQUAL, true})
#define MODE_LESS ((zmode){true, true, RS_CMP_LESS, true})
#define MODE_JOB(j) ((zmode){(j)->st->z_enable, (j)->st->z_write, (j)->st->z_func, \
                             !(j)->st->blend_enable && (j)->rt->n_aov == 0})

/* One instance of each walk per mode (same arguments as rs_tri_fast). */
#define INSTANCE(name, walk, mode)                                                                              \
    static void name(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,     \
                     int y1)                                                                                    \
    {                                                                                                           \
        walk(mode, j, t, p, a, x0, y0, x1, y1);                                                                 \
    }
/* The three instances of a walk: name_le (LESSEQUAL with writes), name_less (LESS with writes), name_any. */
#define INSTANCES(name, walk)                                                                                   \
    INSTANCE(name##_le, walk, MODE_LE)                                                                          \
    INSTANCE(name##_less, walk, MODE_LESS)                                                                      \
    INSTANCE(name##_any, walk, MODE_JOB(j))
#endif /* __AVX2__ */
#endif
