/* raster/span.c -- the fast path of triangle rasterization on 1-sample targets: 8 pixels at a time (8 lanes of
 * AVX2): coverage from the edge functions, then depth test, depth write, perspective-correct colour and colour
 * write for the 8 pixels at once.
 *
 * Exactness: every lane performs the same float operations in the same order as tri_pixel in tri.c (the
 * reference path), without FMA (-ffp-contract=off) and with IEEE division, so both paths write the same bytes.
 * The planes are split into an x part (the left operand of each sum: z2 + z0 * sx, s2 + s0 * fx, ...), computed
 * once per group of lanes, and a y part (z1 * sy, s1 * fy, ...), computed once per row; each lane adds the two,
 * as tri_pixel does.  An alpha channel that does not vary over the triangle gets the value its interpolation
 * would give without evaluating it (alpha_const).  Coverage is exact integer arithmetic (int64, or int32 where
 * the values provably fit).
 * Lanes lie inside one 64x64 tile (one thread), so loading and storing back untouched lanes is safe, except
 * past the right end of the target, where span8 copies only the pixels that exist in and out.
 *
 * The walks (rs_tri_fast picks one per triangle):
 *  - small triangles (box at most 8 wide, edge coefficients at most 2^13): no block tests, 32-bit edge values;
 *    boxes of at most 4x8 or 8x2 pixels in the plain modes take the stamp walk: the coverage of the whole box
 *    first, then only its covered pixels packed into the lanes (one pass of 8 for almost every triangle of a
 *    tessellated grid, where the 4x2 walk below drew about a third of its lanes), depth read by a gather and the
 *    passing pixels written one by one; larger boxes go 4x2 pixels at a time (two rows in the 8 lanes) when at
 *    most 4 wide, the others one row of 8 lanes;
 *  - medium ones (box at most 32 wide, the same coefficients): the span walk, no blocks either: each row's
 *    coverage over a window of 2 or 4 groups of 8 columns (32-bit edge values), then 8-lane groups from the
 *    row's first covered pixel until its covered interval is done, so lanes hold only covered pixels' runs;
 *  - the others: the box's groups of 8 columns (from its left column when it is narrow, 8-aligned otherwise),
 *    each cut into blocks of up to 8 rows with a trivial reject / accept test; full blocks skip coverage,
 *    partial blocks step int32 edge values when the edges that cross the block provably fit (int64 otherwise).
 * Each walk is instantiated with the depth state as compile-time constants for the common states (depth test
 * LESSEQUAL or LESS with writes, no blending, no AOV planes) and once with the job's values for the rest;
 * blending and AOV planes go through span8 (per-pixel write-out, as the reference).
 * rs_tri_run is the grid rows' entry (setup_simd.c's grid_tile): a step's up to 8 triangles, the mode picked once
 * and each triangle's walk from the set-up lanes (coef_small) and its clipped box, rs_tri_fast only for the rest.
 * (Measured on scene B and dropped: the job's and tile's constants read once per step into locals or a struct --
 * the run's loop has no registers left for them, the compiler spills them and it costs more than the reloads.) */
#include "raster_internal.h"

#include <string.h>

_Static_assert(RS_BLOCK == 8, "a block row is one group of 8 lanes");
_Static_assert(RS_TILE == 64, "a tile row has at most 8 groups and a tile at most 64 rows");

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

/* 8-bit lane mask -> -1 / 0 lanes. */
static inline v8i lanes_of(unsigned m) { return (bi((int32_t)m) & lane_bit) == lane_bit; }
/* -1 / 0 lanes (or any sign bits) -> 8-bit lane mask. */
static inline unsigned mask_of(v8i m) { return (unsigned)_mm256_movemask_ps((__m256)m); }
/* Lanes l0..l1 as an 8-bit mask. */
static inline unsigned lane_range(int l0, int l1) { return ((2u << l1) - 1u) & ~((1u << l0) - 1u); }

/* |X| < 2^24 in every lane: the offsets (1/256 px) whose conversion to float is exact (for RS_ASSERT). */
static inline bool lanes_exact(v8i X) { return mask_of((X >= bi(1 << 24)) | (X <= bi(-(1 << 24)))) == 0; }

/* rs_zclamp per lane: z >= lo ? (z <= hi ? z : hi) : lo (NaN -> lo). */
static inline v8f zclamp8(v8f z, v8f lo, v8f hi) { return sel(z >= lo, sel(z <= hi, z, hi), lo); }

/* rs_zpass per lane for compare function f. */
ALWAYS_INLINE v8i zpass8(int f, v8f z, v8f d)
{
    switch (f) {
    case RS_CMP_NEVER: return bi(0);
    case RS_CMP_LESS: return z < d;
    case RS_CMP_EQUAL: return z == d;
    case RS_CMP_LESSEQUAL: return z <= d;
    case RS_CMP_GREATER: return z > d;
    case RS_CMP_NOTEQUAL: return z != d;
    case RS_CMP_GREATEREQUAL: return z >= d;
    default: return bi(-1);
    }
}

/* rs_to8 per lane: saturate (NaN -> 0), * 255 + 0.5, truncate.  max(c, 0) is c > 0 ? c : 0 (NaN -> +0, as the
 * reference's 0.0f), then min(., 1) is . < 1 ? . : 1: the reference's c > 0 ? (c < 1 ? c : 1) : 0 exactly. */
static inline v8i to8_8(v8f c)
{
    v8f s = (v8f)_mm256_min_ps(_mm256_max_ps((__m256)c, _mm256_setzero_ps()), (__m256)bf(1.0f));
    return __builtin_convertvector(s * bf(255.0f) + bf(0.5f), v8i);
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
        if (m.zw) store_lanes(d0, d1, split, (__m256i)sel(pass, z, d));
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
    store_lanes(c0, c1, split, (__m256i)seli(pass, src, (v8i)load_lanes(c0, c1, split)));
}

/* ---- the small-triangle walks ---- */

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

/* The 4x2 walk of a box at most 4 pixels wide (columns gx..gx+3 inside tile t), two rows per step. */
ALWAYS_INLINE void walk_quads(fctx *c, zmode m, const rs_job *j, const rs_tile *t, int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = c->tr;
    const int gx = x0 + 4 <= t->x1 ? x0 : t->x1 - 4;
    const uint32_t X = (uint32_t)((int64_t)gx * RS_SUB - j->cx), Y = (uint32_t)((int64_t)y0 * RS_SUB - j->cy);
    v8u e[3], dy[3];
    edges32(tr, X, Y, quad_col, quad_row, 2, e, dy);
    const unsigned row = ((1u << (x1 - x0 + 1)) - 1u) << (x0 - gx);
    const rows8 r = rows8_at(j, tr, bi((int32_t)((int64_t)gx * RS_SUB - j->cx - tr->vx)) + quad_col * RS_SUB);
    v8i Yl = bi((int32_t)((int64_t)y0 * RS_SUB - j->cy - tr->vy)) + quad_row * RS_SUB;
    size_t o = fidx(c, gx, y0);
    for (int y = y0; y <= y1; y += 2) {
        unsigned box = y + 1 <= y1 ? row | row << 4 : row;
        unsigned cov = box & ~mask_of((v8i)(e[0] | e[1] | e[2])); /* sign bit: some edge < 0 */
        if (cov) {
            ypart yp = ypart_at(j, tr, Yl);
            frag8(c, m, true, cov, o, y + 1 < t->y1 ? o + c->w : o, &r, &yp);
        }
        for (int i = 0; i < 3; i++) e[i] += dy[i];
        Yl += bi(2 * RS_SUB);
        o += 2 * c->w;
    }
}

/* The row walk of a box at most 8 pixels wide: lanes gx..gx+7 inside tile t, one row per step. */
ALWAYS_INLINE void walk_rows(fctx *c, zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a,
                             int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = c->tr;
    const int gx = x0 + 8 <= t->x1 ? x0 : t->x1 - 8;
    const uint32_t X = (uint32_t)((int64_t)gx * RS_SUB - j->cx), Y = (uint32_t)((int64_t)y0 * RS_SUB - j->cy);
    v8u e[3], dy[3];
    edges32(tr, X, Y, lane_idx, bi(0), 1, e, dy);
    const unsigned box = ((1u << (x1 - x0 + 1)) - 1u) << (x0 - gx);
    const rows8 r = rows8_at(j, tr, bi((int32_t)((int64_t)gx * RS_SUB - j->cx - tr->vx)) + lane_idx * RS_SUB);
    int32_t Yr = (int32_t)((int64_t)y0 * RS_SUB - j->cy - tr->vy);
    size_t o = fidx(c, gx, y0);
    for (int y = y0; y <= y1; y++) {
        unsigned cov = box & ~mask_of((v8i)(e[0] | e[1] | e[2])); /* sign bit: some edge < 0 */
        if (cov && m.plain) {
            ypart yp = ypart_at(j, tr, bi(Yr));
            frag8(c, m, false, cov, o, 0, &r, &yp);
        } else if (cov) {
            span8(j, t, p, a, gx, y, cov);
        }
        for (int i = 0; i < 3; i++) e[i] += dy[i];
        Yr += RS_SUB;
        o += c->w;
    }
}

/* ---- the stamp walk: boxes at most 8 wide, plain modes ---- */

/* The positions of the first (at most 8) set bits of *cov, one byte each from the low byte; they are cleared from
 * *cov and their count goes to *n. */
static inline uint64_t take8(uint64_t *cov, int *n)
{
    uint64_t ids = 0, c = *cov;
    int k = 0;
    do {
        ids |= (uint64_t)__builtin_ctzll(c) << (8 * k++);
        c &= c - 1;
    } while (c && k < 8);
    *cov = c, *n = k;
    return ids;
}

/* The positions of the set bits of the 16-bit mask m (at most 8 of them), one byte each from the low byte, as
 * take8 gives them: _pdep_u64 spreads each bit of m over its nibble (times 0xf), _pext_u64 keeps those nibbles of
 * 0xfedcba9876543210 (each nibble its own position), and the last _pdep_u64 widens the 8 low nibbles to bytes.
 * (BMI2's pdep / pext take one instruction each: fast on Intel since Haswell and on AMD since Zen 3, microcoded
 * and slow on Zen 1 and 2.) */
static inline uint64_t pack16(unsigned m)
{
    const uint64_t nib = _pext_u64(0xfedcba9876543210ull, _pdep_u64(m, 0x1111111111111111ull) * 0xfu);
    return _pdep_u64(nib, 0x0f0f0f0f0f0f0f0full);
}

/* Depth-test (mode m), shade and write nl (1..8) covered pixels of a stamp W = 1 << wbits pixels wide whose
 * corner pixel is at index o of tile t's planes (pitch w) and at Xs, Ys from vertex 0 of triangle tr (1/256 px):
 * lane l holds stamp position ids byte l (column id % W, row id / W).  Per lane the x and y parts of the planes as
 * rows8_at and ypart_at give them for that pixel (the same integer offsets, so the same floats: see below) and
 * frag8's operations (pc: the colour slot, NULL: white; alpha always interpolated); the depth is read by a gather,
 * the passing lanes are written one by one (a triangle's pixels are distinct: their order does not matter). */
ALWAYS_INLINE void stamp_pass(zmode m, const rs_job *j, rs_tile *t, const rs_tri *tr, const float *pc, bool vl,
                              int wbits, uint64_t ids, int nl, size_t o, int32_t w, int32_t Xs, int32_t Ys)
{
    const v8i id = (v8i)_mm256_cvtepu8_epi32(_mm_cvtsi64_si128((long long)ids));
    const v8i col = id & bi((1 << wbits) - 1), row = id >> wbits;
    const v8i off = row * bi(w) + col;
    /* rows8_at and ypart_at without their sample offsets: on a 1-sample target sox[0] = soy[0] = 0 (draw.c), and
     * fx + 0.0f is fx (fx is an integer times 1/256, never -0) */
    RS_ASSERT(j->sox[0] == 0 && j->soy[0] == 0);
    const float k = 1.0f / RS_SUB;
    const v8f fx = __builtin_convertvector(bi(Xs) + (col << RS_SUB_BITS), v8f) * bf(k);
    const v8f fy = __builtin_convertvector(bi(Ys) + (row << RS_SUB_BITS), v8f) * bf(k);
    const rows8 r = {bf(tr->z[2]) + bf(tr->z[0]) * fx, bf(tr->s[2]) + bf(tr->s[0]) * fx,
                     bf(tr->q1[2]) + bf(tr->q1[0]) * fx, bf(tr->q2[2]) + bf(tr->q2[0]) * fx};
    const ypart y = {bf(tr->z[1]) * fy, bf(tr->s[1]) * fy, bf(tr->q1[1]) * fy, bf(tr->q2[1]) * fy};
    float *dep = t->depth + o;
    v8i pass = lane_idx < bi(nl);
    v8f z = bf(0.0f);
    if (m.ze) { /* lanes past nl read the stamp's position 0 (id 0): a pixel of the box, so inside the planes */
        const v8f d = (v8f)_mm256_i32gather_ps(dep, (__m256i)off, 4);
        z = zclamp8(r.zx + y.zy, bf(j->zlo), bf(j->zhi));
        pass &= zpass8(m.zf, z, d);
    }
    t->tested += (uint64_t)nl;
    unsigned pm = mask_of(pass);
    if (!pm) return;
    t->written += (uint64_t)__builtin_popcount(pm);
    const v8f rr = bf(1.0f) / (r.sx + y.sy);
    const v8f b1 = (r.q1x + y.q1y) * rr;
    const v8f b2 = (r.q2x + y.q2y) * rr;
    const v8i src = pc ? shade8_l(pc, -1, b1, b2, vl) : bi(-1);
    int32_t ov[8]; /* unaligned: no realignment of the stack for them */
    float zv[8];
    uint32_t cv[8];
    _mm256_storeu_si256((__m256i *)ov, (__m256i)off);
    _mm256_storeu_si256((__m256i *)cv, (__m256i)src);
    uint32_t *col0 = t->color + o;
    if (m.ze && m.zw) {
        _mm256_storeu_ps(zv, (__m256)z);
        do {
            const int l = __builtin_ctz(pm);
            dep[ov[l]] = zv[l];
            col0[ov[l]] = cv[l];
        } while (pm &= pm - 1);
    } else {
        do {
            const int l = __builtin_ctz(pm);
            col0[ov[l]] = cv[l];
        } while (pm &= pm - 1);
    }
}

/* stamp_pass out of line, with the mode as a value: the passes after a band's first (more than 8 covered pixels),
 * kept apart so that the common one-pass band's planes are not hoisted and spilled for them. */
static __attribute__((noinline)) void stamp_pass_rt(zmode m, const rs_job *j, rs_tile *t, const rs_tri *tr,
                                                    const float *pc, bool vl, int wbits, uint64_t ids, int nl,
                                                    size_t o, int32_t w, int32_t Xs, int32_t Ys)
{
    if (vl) stamp_pass(m, j, t, tr, pc, true, 2, ids, nl, o, w, Xs, Ys); /* (the grid rows' stamp lanes: 4 wide) */
    else if (wbits == 2) stamp_pass(m, j, t, tr, pc, false, 2, ids, nl, o, w, Xs, Ys);
    else stamp_pass(m, j, t, tr, pc, false, 3, ids, nl, o, w, Xs, Ys);
}

/* The stamp walk of the box [x0, x1] x [y0, y1] of triangle p (in tile t, mode m plain), at most W = 1 << wbits
 * (4 or 8) columns by 64 / W rows (positions row * W + column, below 64; walk_small gives it boxes of at most 4x8
 * or 8x2 pixels).  Coverage first, 8 positions per vector (two rows of 4, or one of 8) with 32-bit edge values
 * (modulo 2^32 as edges32: exact by coef_small), into one 64-bit mask; then the covered pixels packed into the
 * lanes (pack16, take8), 8 per pass (stamp_pass): one pass for almost every small triangle, where the 4x2 walk
 * drew a third of its lanes. */
ALWAYS_INLINE void walk_band(zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, bool vl,
                             int wbits, int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = &p->u.t;
    const int vr = wbits == 2 ? 2 : 1; /* rows per vector */
    const v8u Xl = bu((uint32_t)((int64_t)x0 * RS_SUB - j->cx)) +
                   ((wbits == 2 ? (v8u)quad_col : (v8u)lane_idx) << RS_SUB_BITS);
    const v8u Yl = bu((uint32_t)((int64_t)y0 * RS_SUB - j->cy)) + ((wbits == 2 ? (v8u)quad_row : bu(0)) << RS_SUB_BITS);
    const v8u eb0 = bu((uint32_t)tr->eb[0]), eb1 = bu((uint32_t)tr->eb[1]), eb2 = bu((uint32_t)tr->eb[2]);
    v8u e0 = Xl * bu((uint32_t)tr->ea[0]) + Yl * eb0 + bu((uint32_t)tr->ec[0]);
    v8u e1 = Xl * bu((uint32_t)tr->ea[1]) + Yl * eb1 + bu((uint32_t)tr->ec[1]);
    v8u e2 = Xl * bu((uint32_t)tr->ea[2]) + Yl * eb2 + bu((uint32_t)tr->ec[2]);
    const int ds = RS_SUB_BITS + vr - 1; /* vr rows in 1/256 px, as a shift */
    const v8u d0 = eb0 << ds, d1 = eb1 << ds, d2 = eb2 << ds;
    const unsigned cols = (1u << (x1 - x0 + 1)) - 1u, vbox = wbits == 2 ? cols * 0x11u : cols;
    const int nv = (y1 - y0) / vr + 1; /* vectors, at most 8 */
    RS_ASSERT(x1 - x0 < (1 << wbits) && nv <= 8);
    uint64_t cov = 0;
    for (int v = 0; v < nv; v++) {
        const unsigned bx = vr == 2 && 2 * v == y1 - y0 ? vbox & 0x0fu : vbox; /* the last row alone */
        cov |= (uint64_t)(bx & ~mask_of((v8i)(e0 | e1 | e2))) << (8 * v); /* sign bit: some edge < 0 */
        e0 += d0, e1 += d1, e2 += d2;
    }
    if (!cov) return;
    const float *pc = j->color_idx < 0 ? NULL : a + j->color_idx * RS_ATTR_STRIDE;
    const int32_t Xs = (int32_t)((int64_t)x0 * RS_SUB - j->cx - tr->vx);
    const int32_t Ys = (int32_t)((int64_t)y0 * RS_SUB - j->cy - tr->vy);
    const size_t o = rs_tile_index(t, x0, y0);
    const int32_t w = (int32_t)t->pitch;
    int n = __builtin_popcountll(cov);
    uint64_t ids;
    if (cov <= 0xffffu && n <= 8) { /* the common case: the positions at once (pack16) */
        ids = pack16((unsigned)cov);
        cov = 0;
    } else {
        ids = take8(&cov, &n);
    }
    stamp_pass(m, j, t, tr, pc, vl, wbits, ids, n, o, w, Xs, Ys);
    while (cov) { /* more than 8 covered pixels: out of line */
        ids = take8(&cov, &n);
        stamp_pass_rt(m, j, t, tr, pc, vl, wbits, ids, n, o, w, Xs, Ys);
    }
}

/* ---- the span walk ---- */

/* Span windows are at most this many groups of 8 columns wide (boxes up to 32 px; wider ones of coef_small
 * triangles, at most 33 px, take the block walk). */
#define SPAN_GROUPS 4

/* The x parts of the planes per column: column bx + i at index i, for the columns a span walk's groups can
 * reach (the window of SPAN_GROUPS groups, plus 8 past it). */
typedef struct xcols {
    float zx[8 * SPAN_GROUPS + 8], sx[8 * SPAN_GROUPS + 8], q1x[8 * SPAN_GROUPS + 8], q2x[8 * SPAN_GROUPS + 8];
} xcols;

/* Fill the first 8n columns of xc from column bx: per column the values rows8_at gives it (its X is the same
 * integer whichever group holds it, so the same floats). */
static inline void xcols_fill(xcols *xc, const rs_job *j, const rs_tri *tr, int bx, int n)
{
    for (int v = 0; v < n; v++) {
        const rows8 r = rows8_at(j, tr, bi((int32_t)((int64_t)(bx + 8 * v) * RS_SUB - j->cx - tr->vx)) +
                                            lane_idx * RS_SUB);
        memcpy(xc->zx + 8 * v, &r.zx, 32);
        memcpy(xc->sx + 8 * v, &r.sx, 32);
        memcpy(xc->q1x + 8 * v, &r.q1x, 32);
        memcpy(xc->q2x + 8 * v, &r.q2x, 32);
    }
}

/* The x parts of the 8 columns from bx + g. */
static inline rows8 xcols_at(const xcols *xc, int g)
{
    rows8 r;
    memcpy(&r.zx, xc->zx + g, 32);
    memcpy(&r.sx, xc->sx + g, 32);
    memcpy(&r.q1x, xc->q1x + g, 32);
    memcpy(&r.q2x, xc->q2x + g, 32);
    return r;
}

/* The span walk of a box 9 to 8 * ng pixels wide (coef_small, tile at least 8 wide), one row per step: the
 * row's coverage over a window of ng groups of 8 columns from x0 (x0 + 8 <= x1 < t->x1: the first group lies in
 * the tile), then 8-lane groups from the row's first covered column (moved left to stay inside the tile) until
 * every covered pixel is done, so groups hold only the row's covered interval.  (Measured on scene A, packing
 * the short runs of two rows into one call (4 + 4 lanes), listing the groups first and shading them in one
 * loop, or scalar per-edge interval stepping instead of the window's vector coverage made no gain or lost.) */
ALWAYS_INLINE void walk_spans(fctx *c, zmode m, int ng, const rs_job *j, rs_tile *t, const rs_prim *p,
                              const float *a, int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = c->tr;
    const int gmax = t->x1 - 8 - x0; /* the last group start inside the tile, >= 0 */
    RS_ASSERT(gmax >= 0 && x0 + 8 <= x1 && x1 < t->x1 && x1 - x0 < 8 * ng);
    const uint32_t X = (uint32_t)((int64_t)x0 * RS_SUB - j->cx), Y = (uint32_t)((int64_t)y0 * RS_SUB - j->cy);
    v8u e[3][SPAN_GROUPS], dy[3];
    for (int v = 0; v < ng; v++) {
        v8u ev[3];
        edges32(tr, X, Y, lane_idx + bi(8 * v), bi(0), 1, ev, dy);
        for (int i = 0; i < 3; i++) e[i][v] = ev[i];
    }
    const uint32_t box = (uint32_t)((2ull << (x1 - x0)) - 1u); /* box columns 0 .. x1 - x0 (< 8 * ng) */
    xcols xc; /* groups start at most at x1 - x0 and end 7 columns later */
    xcols_fill(&xc, j, tr, x0, (x1 - x0 + 7) / 8 + 1);
    int32_t Yr = (int32_t)((int64_t)y0 * RS_SUB - j->cy - tr->vy);
    size_t o = fidx(c, x0, y0);
    for (int y = y0; y <= y1; y++, Yr += RS_SUB, o += c->w) {
        uint32_t out = 0;
        for (int v = 0; v < ng; v++) /* sign bit: some edge < 0 */
            out |= mask_of((v8i)(e[0][v] | e[1][v] | e[2][v])) << (8 * v);
        for (int v = 0; v < ng; v++)
            for (int i = 0; i < 3; i++) e[i][v] += dy[i];
        uint32_t cov = box & ~out; /* window columns: bit i is column x0 + i */
        if (!cov) continue;
        const ypart yp = ypart_at(j, tr, bi(Yr));
        do { /* the group from the first pixel left, inside the tile (g <= x1 - x0: xc holds its columns) */
            int g = __builtin_ctz(cov);
            g = g < gmax ? g : gmax;
            const unsigned c8 = (cov >> g) & 0xffu;
            cov &= ~(0xffu << g);
            if (m.plain) {
                const rows8 r = xcols_at(&xc, g);
                frag8(c, m, false, c8, o + (size_t)g, 0, &r, &yp);
            } else {
                span8(j, t, p, a, x0 + g, y, c8);
            }
        } while (cov);
    }
}

/* ---- the block walk ---- */

/* Rows [y0, y1] of one block of column group gx (lanes lm, x parts r; yp[y - yb]: row y's y parts).  full:
 * every lane of lm is covered; else coverage from the int32 edge values e0, e1, e2 at the lanes of row y0,
 * stepped by d0, d1, d2 per row. */
ALWAYS_INLINE void block_rows(fctx *c, zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a,
                              int gx, int y0, int y1, unsigned lm, const rows8 *r, const ypart *yp, int yb,
                              bool full, v8u e0, v8u e1, v8u e2, v8u d0, v8u d1, v8u d2)
{
    const bool lanes = m.plain && gx + 8 <= j->rt->width;
    size_t o = fidx(c, gx, y0);
    for (int y = y0; y <= y1; y++, o += c->w) {
        unsigned cov = lm;
        if (!full) {
            cov &= ~mask_of((v8i)(e0 | e1 | e2)); /* sign bit: some edge < 0 */
            e0 += d0, e1 += d1, e2 += d2;
        }
        if (cov && lanes) frag8(c, m, false, cov, o, 0, r, &yp[y - yb]);
        else if (cov) span8(j, t, p, a, gx, y, cov);
    }
}

/* Rows [y0, y1] of one partial block of column group gx with int64 edge values e at lane l0 of row y0 (blocks
 * of huge triangles, whose edge values may not fit int32). */
ALWAYS_INLINE void block_rows64(fctx *c, zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a,
                                int gx, int l0, int y0, int y1, unsigned lm, const rows8 *r, const ypart *yp, int yb,
                                const int64_t *e)
{
    const rs_tri *tr = c->tr;
    v4q lo[3], hi[3], dy[3];
    for (int i = 0; i < 3; i++) {
        int64_t s = (int64_t)tr->ea[i] * RS_SUB, e0 = e[i] - (int64_t)l0 * s;
        lo[i] = (v4q){e0, e0 + s, e0 + 2 * s, e0 + 3 * s};
        hi[i] = lo[i] + 4 * s;
        int64_t d = (int64_t)tr->eb[i] * RS_SUB;
        dy[i] = (v4q){d, d, d, d};
    }
    const bool lanes = m.plain && gx + 8 <= j->rt->width;
    size_t o = fidx(c, gx, y0);
    for (int y = y0; y <= y1; y++, o += c->w) {
        v4q nl = lo[0] | lo[1] | lo[2], nh = hi[0] | hi[1] | hi[2]; /* sign bit: some edge < 0 */
        unsigned out = (unsigned)_mm256_movemask_pd((__m256d)nl) | (unsigned)_mm256_movemask_pd((__m256d)nh) << 4;
        unsigned cov = lm & ~out;
        if (cov && lanes) frag8(c, m, false, cov, o, 0, r, &yp[y - yb]);
        else if (cov) span8(j, t, p, a, gx, y, cov);
        for (int i = 0; i < 3; i++) lo[i] += dy[i], hi[i] += dy[i];
    }
}

/* The sign bits of int64 lanes 0..2 of v: the edges whose value in v is negative. */
static inline unsigned neg3(__m256i v) { return (unsigned)_mm256_movemask_pd((__m256d)v) & 7u; }

/* a * X + b * Y per edge for |X|, |Y| < 2^31: |a|, |b| <= 2^23 fit int32 (setup.c), so the signed 32 x 32-bit
 * products are the exact int64 ones. */
static inline __m256i edge_xy(const edges4 *E, int64_t X, int64_t Y)
{
    RS_ASSERT(X >= INT32_MIN && X <= INT32_MAX && Y >= INT32_MIN && Y <= INT32_MAX);
    return _mm256_add_epi64(_mm256_mul_epi32(E->a, _mm256_set1_epi64x(X)),
                            _mm256_mul_epi32(E->b, _mm256_set1_epi64x(Y)));
}

/* Int32 edge values for the lanes of a partial block: e[i] = edge i at lane l of the first row (ev: edge values
 * at lane l0, all edges), dy[i] its change per row; edges not in `cross` are 0 (inside everywhere).  Modulo
 * 2^32: exact for the lanes l0..l1 of the crossing edges (the caller checked that their values fit). */
static inline void edges_block32(const edges4 *E, __m256i ev, unsigned cross, int l0, v8u *e, v8u *dy)
{
    for (int i = 0; i < 3; i++) {
        if (!(cross & (1u << i))) {
            e[i] = dy[i] = bu(0);
            continue;
        }
        const __m256i at = _mm256_set1_epi32(2 * i); /* int32 lane 2i: the low half of edge i's 64-bit lane */
        v8u s = (v8u)_mm256_permutevar8x32_epi32(_mm256_slli_epi64(E->a, RS_SUB_BITS), at);
        e[i] = (v8u)_mm256_permutevar8x32_epi32(ev, at) + (v8u)(lane_idx - bi(l0)) * s;
        dy[i] = (v8u)_mm256_permutevar8x32_epi32(_mm256_slli_epi64(E->b, RS_SUB_BITS), at);
    }
}

/* Boxes narrower than this take column groups from their left column rather than 8-aligned ones. */
#define NARROW_BOX 32

/* The rows [y0, y1] (at most 64) of the box [x0, x1] of triangle p: its groups of 8 columns, each cut into
 * blocks of up to 8 rows (at multiples of 8) that are rejected, walked without coverage (full) or walked with
 * coverage.  The trivial test takes the extremes of each edge over the block's pixels (lanes l0..l1, its rows),
 * in int64, the three edges at once. */
ALWAYS_INLINE void walk_blocks(fctx *c, zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a,
                               int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = c->tr;
    ypart yp[RS_TILE];
    const int nrows = y1 - y0 + 1;
    const int32_t Y0 = (int32_t)((int64_t)y0 * RS_SUB - j->cy - tr->vy);
    for (int i = 0; i < nrows; i += 8) { /* the y parts of 8 rows at once, then spread to one row each */
        ypart v = ypart_at(j, tr, bi(Y0 + i * RS_SUB) + lane_idx * RS_SUB);
        for (int q = 0; q < 8 && i + q < nrows; q++) {
            v8i at = bi(q);
            yp[i + q].zy = (v8f)_mm256_permutevar8x32_ps((__m256)v.zy, (__m256i)at);
            yp[i + q].sy = (v8f)_mm256_permutevar8x32_ps((__m256)v.sy, (__m256i)at);
            yp[i + q].q1y = (v8f)_mm256_permutevar8x32_ps((__m256)v.q1y, (__m256i)at);
            yp[i + q].q2y = (v8f)_mm256_permutevar8x32_ps((__m256)v.q2y, (__m256i)at);
        }
    }
    const edges4 E = edges4_of(tr);
    const __m256i zero = _mm256_setzero_si256(), i32max = _mm256_set1_epi64x(INT32_MAX);
    /* narrow boxes: groups of 8 columns from x0 (fewer than 8-aligned ones), each moved left to stay inside the
     * tile; wide ones: 8-aligned groups (no loads across cache lines) */
    const bool from_x0 = x1 - x0 < NARROW_BOX && t->x1 - t->x0 >= 8;
    for (int col = from_x0 ? x0 : x0 & ~7; col <= x1; col += 8) { /* the box's columns col..col+7 */
        const int gx = from_x0 && col + 8 > t->x1 ? t->x1 - 8 : col;
        const int l0 = (x0 > col ? x0 : col) - gx, l1 = (x1 < col + 7 ? x1 : col + 7) - gx;
        const unsigned lm = lane_range(l0, l1);
        const rows8 r = rows8_at(j, tr, bi((int32_t)((int64_t)gx * RS_SUB - j->cx - tr->vx)) + lane_idx * RS_SUB);
        /* edge values at lane l0 of row y0 (|X|, |Y| <= 2^22: inside the viewport) and the x extent */
        RS_ASSERT(rs_within((int64_t)(gx + l0) * RS_SUB - j->cx, 22) && rs_within((int64_t)y0 * RS_SUB - j->cy, 22));
        const __m256i e0 = _mm256_add_epi64(edge_xy(&E, (int64_t)(gx + l0) * RS_SUB - j->cx,
                                                     (int64_t)y0 * RS_SUB - j->cy), E.c);
        const __m256i sx = _mm256_mul_epi32(E.a, _mm256_set1_epi64x((l1 - l0) * RS_SUB));
        const __m256i sxpos = _mm256_cmpgt_epi64(sx, zero);
        const __m256i sxp = _mm256_and_si256(sxpos, sx), sxn = _mm256_andnot_si256(sxpos, sx);
        const __m256i sxa = _mm256_sub_epi64(sxp, sxn); /* |sx| */
        for (int by = y0; by <= y1; by = (by | 7) + 1) {
            const int by1 = (by | 7) < y1 ? (by | 7) : y1;
            const __m256i ev = _mm256_add_epi64(e0, _mm256_mul_epi32(E.b, _mm256_set1_epi64x((by - y0) * RS_SUB)));
            const __m256i sy = _mm256_mul_epi32(E.b, _mm256_set1_epi64x((by1 - by) * RS_SUB));
            const __m256i sypos = _mm256_cmpgt_epi64(sy, zero);
            const __m256i syp = _mm256_and_si256(sypos, sy), syn = _mm256_andnot_si256(sypos, sy);
            const __m256i hi = _mm256_add_epi64(_mm256_add_epi64(ev, sxp), syp);
            const __m256i lo = _mm256_add_epi64(_mm256_add_epi64(ev, sxn), syn);
            if (neg3(hi)) continue; /* some edge < 0 over the whole block */
            const unsigned cross = neg3(lo); /* edges < 0 somewhere in the block (the others: >= 0 everywhere) */
            if (!cross) {
                const v8u z = bu(0);
                block_rows(c, m, j, t, p, a, gx, by, by1, lm, &r, yp, y0, true, z, z, z, z, z, z);
                continue;
            }
            /* a crossing edge (lo < 0 <= hi) has |values| <= hi - lo = |sx| + |sy| in the block */
            const __m256i span = _mm256_add_epi64(sxa, _mm256_sub_epi64(syp, syn));
            if (!(neg3(_mm256_cmpgt_epi64(span, i32max)) & cross)) {
                v8u ee[3], dv[3];
                edges_block32(&E, ev, cross, l0, ee, dv);
                block_rows(c, m, j, t, p, a, gx, by, by1, lm, &r, yp, y0, false, ee[0], ee[1], ee[2], dv[0], dv[1],
                           dv[2]);
            } else {
                int64_t e[4];
                _mm256_storeu_si256((__m256i *)e, ev);
                block_rows64(c, m, j, t, p, a, gx, l0, by, by1, lm, &r, yp, y0, e);
            }
        }
    }
}

/* ---- the instances ---- */

/* Triangle p's pixels [x0, x1] x [y0, y1] of tile t through the small-triangle walks (box at most 8 wide,
 * coef_small), in mode m. */
ALWAYS_INLINE void walk_small(zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0,
                              int y0, int x1, int y1)
{
    RS_ASSERT(x1 - x0 < 8 && box_fits32(j, &p->u.t, x0, y0, x1, y1)); /* coef_small's claim */
    if (m.plain && x1 - x0 < 4 && y1 - y0 < 8) { /* at most 32 pixels: the stamp walk */
        walk_band(m, j, t, p, a, false, 2, x0, y0, x1, y1);
    } else if (m.plain && y1 - y0 < 2) {
        walk_band(m, j, t, p, a, false, 3, x0, y0, x1, y1);
    } else { /* larger boxes, whose lanes the 4x2 and row walks fill better; blending or AOV planes */
        fctx c;
        fctx_make(&c, j, t, p, a);
        if (m.plain && x1 - x0 < 4) walk_quads(&c, m, j, t, x0, y0, x1, y1);
        else walk_rows(&c, m, j, t, p, a, x0, y0, x1, y1);
        t->tested += c.tested;
        t->written += c.written;
    }
}

/* The same through the span walk (box at most 8 * ng wide, coef_small, tile at least 8 wide). */
ALWAYS_INLINE void walk_span(zmode m, int ng, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0,
                             int y0, int x1, int y1)
{
    fctx c;
    fctx_make(&c, j, t, p, a);
    RS_ASSERT(box_fits32(j, &p->u.t, x0, y0, x1, y1)); /* coef_small's claim */
    walk_spans(&c, m, ng, j, t, p, a, x0, y0, x1, y1);
    t->tested += c.tested;
    t->written += c.written;
}
#define walk_span2(m, ...) walk_span(m, 2, __VA_ARGS__)
#define walk_span4(m, ...) walk_span(m, SPAN_GROUPS, __VA_ARGS__)

/* The same through the block walk (any triangle). */
ALWAYS_INLINE void walk_big(zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0,
                            int x1, int y1)
{
    fctx c;
    fctx_make(&c, j, t, p, a);
    for (int b = y0; b <= y1; b += RS_TILE) /* a tile has at most 64 rows; any box in bands of 64 */
        walk_blocks(&c, m, j, t, p, a, x0, b, x1, y1 - b < RS_TILE ? y1 : b + RS_TILE - 1);
    t->tested += c.tested;
    t->written += c.written;
}

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
INSTANCES(small, walk_small)
INSTANCES(span2, walk_span2)
INSTANCES(span4, walk_span4)
INSTANCES(big, walk_big)

typedef void walk_fn(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1, int y1);
/* walks[walk][mode]: walk 0 small, 1 and 2 span (2 or 4 groups), 3 block; mode: the job's span_mode (0 LESSEQUAL,
 * 1 LESS, 2 any).  rs_tri_fast runs walk 0 in mode 0 inline (small_le's entry is not called). */
static walk_fn *const walks[4][3] = {
    {small_le, small_less, small_any},
    {span2_le, span2_less, span2_any},
    {span4_le, span4_less, span4_any},
    {big_le, big_less, big_any},
};

void RS_KERNEL(rs_tri_fast)(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                            int y1)
{
    const int wbox = x1 - x0 + 1; /* small: the small-triangle and span walks' conditions */
    const bool small = t->x1 - t->x0 >= 8 && wbox <= 8 * SPAN_GROUPS && coef_small(&p->u.t);
    const int walk = !small ? 3 : wbox <= 8 ? 0 : wbox <= 16 ? 1 : 2;
    if (walk == 0 && j->span_mode == 0) /* the tessellated grids' case, inline: no second call */
        walk_small(MODE_LE, j, t, p, a, x0, y0, x1, y1);
    else
        walks[walk][j->span_mode](j, t, p, a, x0, y0, x1, y1);
}

/* ---- the grid rows' run (setup_simd.c's grid_tile): a step's triangles from the L1 scratch ---- */

/* rs_tri_run in mode m: the lanes of `stamp` straight to walk_band (their attribute blocks in shade8_l's vector
 * layout); the others of live whose triangle is coef_small (`small`, from the set-up lanes) with a box at most 8
 * pixels wide in a tile at least 8 wide -- rs_tri_fast's conditions for walk_small -- straight to walk_small; the
 * rest through rs_tri_fast.  Returns the count of the first two. */
ALWAYS_INLINE unsigned run_lanes(zmode m, const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa,
                                 size_t stride, const int32_t (*cb)[8], unsigned live, unsigned small, unsigned stamp)
{
    unsigned direct = 0;
    if (t->x1 - t->x0 >= 8) { /* the boxes' widths in lanes: rs_tri_fast's test */
        const v8i x0 = (v8i)_mm256_loadu_si256((const __m256i *)cb[0]);
        const v8i x1 = (v8i)_mm256_loadu_si256((const __m256i *)cb[2]);
        direct = live & small & mask_of(x1 - x0 < bi(8));
    }
    RS_ASSERT((stamp & ~direct) == 0 && (stamp == 0 || m.plain));
    for (; live; live &= live - 1) {
        const int l = __builtin_ctz(live);
        const float *a = sa + (size_t)l * stride;
        if (stamp >> l & 1u) walk_band(m, j, t, &sp[l], a, true, 2, cb[0][l], cb[1][l], cb[2][l], cb[3][l]);
        else if (direct >> l & 1u) walk_small(m, j, t, &sp[l], a, cb[0][l], cb[1][l], cb[2][l], cb[3][l]);
        else RS_KERNEL(rs_tri_fast)(j, t, &sp[l], a, cb[0][l], cb[1][l], cb[2][l], cb[3][l]);
    }
    return (unsigned)__builtin_popcount(direct);
}

/* run_lanes per mode (the job's span_mode), out of line: one dispatch per step instead of one per triangle. */
typedef unsigned run_fn(const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa, size_t stride,
                        const int32_t (*cb)[8], unsigned live, unsigned small, unsigned stamp);
#define RUN_INSTANCE(name, mode)                                                                                \
    static unsigned name(const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa, size_t stride,       \
                         const int32_t (*cb)[8], unsigned live, unsigned small, unsigned stamp)                 \
    {                                                                                                           \
        return run_lanes(mode, j, t, sp, sa, stride, cb, live, small, stamp);                                   \
    }
RUN_INSTANCE(run_le, MODE_LE)
RUN_INSTANCE(run_less, MODE_LESS)
RUN_INSTANCE(run_any, MODE_JOB(j))
static run_fn *const runs[3] = {run_le, run_less, run_any};

unsigned RS_KERNEL(rs_tri_run)(const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa, size_t stride,
                               const int32_t (*cb)[8], unsigned live, unsigned small, unsigned stamp)
{
    return runs[j->span_mode](j, t, sp, sa, stride, cb, live, small, stamp);
}

#else /* without AVX2 every draw takes the reference path (rs_span_ok is false) */

unsigned RS_KERNEL(rs_tri_run)(const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa, size_t stride,
                               const int32_t (*cb)[8], unsigned live, unsigned small, unsigned stamp)
{
    return 0;
}

void RS_KERNEL(rs_tri_fast)(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                            int y1)
{
}

#endif
