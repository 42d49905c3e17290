/* raster/span.c -- the fast path of triangle rasterization on 1-sample targets: each row of an 8x8 block is
 * one group of 8 pixels (8 lanes of AVX2), coverage from the int64 edge functions 4 lanes at a time, then depth
 * test, depth write, perspective-correct colour and colour write for the 8 pixels at once.
 *
 * Exactness: every lane performs the same float operations in the same order as tri_pixel in tri.c (the
 * reference path), without FMA (-ffp-contract=off) and with IEEE division, so both paths write the same bytes.
 * Lanes are the pixels gx..gx+7 of an 8-aligned group; a group lies inside one 64x64 tile (one thread), so
 * loading and storing back untouched lanes is safe, except past the right end of the target, where only the
 * pixels that exist are copied in and out.
 *
 * Two walks feed the rows: 8x8 blocks (rs_tri_block_fast, after tri.c's block test) and, for triangles at most 8
 * pixels wide inside a tile, the small-triangle walk (rs_tri_small: one row of 8 lanes starting at the triangle's
 * left column, moved left to stay inside the tile, 32-bit edge values, no block test).  Rows without blending or
 * AOV planes go through row8, which takes the per-triangle halves of the planes from rows8 (computed once per
 * group, the same sums in the same order). */
#include "raster_internal.h"

#include <string.h>

_Static_assert(RS_BLOCK == 8, "a block row is one group of 8 lanes");

#ifdef __AVX2__
#include <immintrin.h>

typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));
typedef uint32_t v8u __attribute__((vector_size(32)));
typedef int64_t v4q __attribute__((vector_size(32)));

/* Lane indices 0..7 as ints. */
static const v8i lane_idx = {0, 1, 2, 3, 4, 5, 6, 7};
static const v8i lane_bit = {1, 2, 4, 8, 16, 32, 64, 128};

/* Broadcast a float / an int to 8 lanes. */
static inline v8f bf(float x) { return (v8f){x, x, x, x, x, x, x, x}; }
static inline v8i bi(int32_t x) { return (v8i){x, x, x, x, x, x, x, x}; }

/* mask ? a : b per lane (mask lanes are -1 or 0). */
static inline v8f sel(v8i mask, v8f a, v8f b) { return (v8f)_mm256_blendv_ps((__m256)b, (__m256)a, (__m256)mask); }
static inline v8i seli(v8i mask, v8i a, v8i b) { return (mask & a) | (~mask & b); }

/* 8-bit lane mask -> -1 / 0 lanes. */
static inline v8i lanes_of(unsigned m) { return (bi((int32_t)m) & lane_bit) != 0; }
/* -1 / 0 lanes -> 8-bit lane mask. */
static inline unsigned mask_of(v8i m) { return (unsigned)_mm256_movemask_ps((__m256)m); }

/* rs_zclamp per lane: z >= lo ? (z <= hi ? z : hi) : lo (NaN -> lo). */
static inline v8f zclamp8(v8f z, float lo, float hi)
{
    return sel(z >= bf(lo), sel(z <= bf(hi), z, bf(hi)), bf(lo));
}

/* rs_zpass per lane for compare function f. */
static inline v8i zpass8(int f, v8f z, v8f d)
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

/* rs_to8 per lane: saturate (NaN -> 0), * 255 + 0.5, truncate. */
static inline v8i to8_8(v8f c)
{
    v8f s = sel(c > bf(0.0f), sel(c < bf(1.0f), c, bf(1.0f)), bf(0.0f));
    return __builtin_convertvector(s * bf(255.0f) + bf(0.5f), v8i);
}

/* rs_shade_color per lane at barycentrics (b1, b2). */
static inline v8i shade8(const rs_job *j, const float *a, v8f b1, v8f b2)
{
    if (j->color_idx < 0) return bi(-1);
    const float *p = a + j->color_idx * RS_ATTR_STRIDE;
    v8i r = to8_8(bf(p[0]) + b1 * bf(p[1]) + b2 * bf(p[2]));
    v8i g = to8_8(bf(p[3]) + b1 * bf(p[4]) + b2 * bf(p[5]));
    v8i b = to8_8(bf(p[6]) + b1 * bf(p[7]) + b2 * bf(p[8]));
    v8i al = to8_8(bf(p[9]) + b1 * bf(p[10]) + b2 * bf(p[11]));
    return r | g << 8 | b << 16 | al << 24;
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

/* Depth-test, shade and write the covered pixels `cov` (bit i: pixel gx + i) of row y of triangle p. */
static void span8(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int gx, int y, unsigned cov)
{
    const rs_tri *tr = &p->u.t;
    const rs_state *st = j->st;
    const float k = 1.0f / RS_SUB;
    const int n = j->rt->width - gx < 8 ? j->rt->width - gx : 8;
    const size_t base = (size_t)y * (size_t)j->rt->width + (size_t)gx;
    v8i X = bi((int32_t)((int64_t)gx * RS_SUB - j->cx - tr->vx)) + lane_idx * RS_SUB;
    v8f fx = __builtin_convertvector(X, v8f) * bf(k);
    float fy = (float)((int64_t)y * RS_SUB - j->cy - tr->vy) * k;
    v8i pass = lanes_of(cov);
    if (st->z_enable) {
        float *dep = j->rt->depth + base;
        v8f d = bf(0.0f);
        load8(&d, dep, n);
        v8f sx = fx + bf((float)j->sox[0] * k);
        float sy = fy + (float)j->soy[0] * k;
        v8f z = zclamp8(bf(tr->z[2]) + bf(tr->z[0]) * sx + bf(tr->z[1] * sy), j->zlo, j->zhi);
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
    v8i src = shade8(j, a, b1, b2);
    uint32_t *col = j->rt->color + base;
    if (st->blend_enable || j->rt->n_aov > 0) { /* rare: per pixel, as the reference */
        for (int i = 0; i < 8; i++) {
            if (!(pm & (1u << i))) continue;
            rs_write_color(j, base + (size_t)i, 1u, (uint32_t)src[i]);
            if (j->rt->n_aov > 0) rs_write_aov(j, a, b1[i], b2[i], gx + i, y);
        }
        return;
    }
    v8i c = bi(0);
    load8(&c, col, n);
    c = seli(pass, src, c);
    store8(col, &c, n);
}

/* span8's per-triangle terms for a fixed group gx, computed once for all rows (same values, same order: the
 * x-dependent part of each plane is the left operand of its sum). */
typedef struct rows8 {
    v8f zx, sx, q1x, q2x;        /* z2 + z0 * sx, s2 + s0 * fx, q1_2 + q1_0 * fx, q2_2 + q2_0 * fx */
} rows8;

/* Fill r for triangle p, group gx. */
static inline void rows8_make(const rs_job *j, const rs_prim *p, int gx, rows8 *r)
{
    const rs_tri *tr = &p->u.t;
    const float k = 1.0f / RS_SUB;
    v8i X = bi((int32_t)((int64_t)gx * RS_SUB - j->cx - tr->vx)) + lane_idx * RS_SUB;
    v8f fx = __builtin_convertvector(X, v8f) * bf(k);
    v8f sx = fx + bf((float)j->sox[0] * k);
    r->zx = bf(tr->z[2]) + bf(tr->z[0]) * sx;
    r->sx = bf(tr->s[2]) + bf(tr->s[0]) * fx;
    r->q1x = bf(tr->q1[2]) + bf(tr->q1[0]) * fx;
    r->q2x = bf(tr->q2[2]) + bf(tr->q2[0]) * fx;
}

/* span8 for row y of a group with precomputed terms r (no blending, no AOV planes: the caller checks). */
static inline void row8(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, const rows8 *r, int gx, int y,
                        unsigned cov)
{
    const rs_tri *tr = &p->u.t;
    const rs_state *st = j->st;
    const float k = 1.0f / RS_SUB;
    const size_t base = (size_t)y * (size_t)j->rt->width + (size_t)gx;
    float fy = (float)((int64_t)y * RS_SUB - j->cy - tr->vy) * k;
    v8i pass = lanes_of(cov);
    if (st->z_enable) {
        float *dep = j->rt->depth + base;
        v8f d;
        memcpy(&d, dep, 32);
        float sy = fy + (float)j->soy[0] * k;
        v8f z = zclamp8(r->zx + bf(tr->z[1] * sy), j->zlo, j->zhi);
        pass &= zpass8(st->z_func, z, d);
        if (st->z_write) {
            d = sel(pass, z, d);
            memcpy(dep, &d, 32);
        }
    }
    unsigned pm = mask_of(pass);
    t->tested += (uint64_t)__builtin_popcount(cov);
    if (!pm) return;
    t->written += (uint64_t)__builtin_popcount(pm);
    v8f rr = bf(1.0f) / (r->sx + bf(tr->s[1] * fy));
    v8f b1 = (r->q1x + bf(tr->q1[1] * fy)) * rr;
    v8f b2 = (r->q2x + bf(tr->q2[1] * fy)) * rr;
    v8i src = shade8(j, a, b1, b2);
    uint32_t *col = j->rt->color + base;
    v8i cv;
    memcpy(&cv, col, 32);
    cv = seli(pass, src, cv);
    memcpy(col, &cv, 32);
}

/* Does the fast path handle this job?  1-sample targets only (4-sample ones take the reference path). */
bool rs_span_ok(const rs_job *j) { return j->samples == 1 && !j->reference; }

void rs_tri_block_fast(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                       int y1, const int64_t *e, bool full)
{
    const rs_tri *tr = &p->u.t;
    const int gx = x0 & ~7, l0 = x0 - gx;
    const unsigned lm = ((1u << (x1 - x0 + 1)) - 1u) << l0;
    v4q lo[3], hi[3], dy[3];
    for (int i = 0; i < 3; i++) {
        int64_t s = tr->ea[i] * RS_SUB, e0 = e[i] - (int64_t)l0 * s;
        lo[i] = (v4q){e0, e0 + s, e0 + 2 * s, e0 + 3 * s};
        hi[i] = lo[i] + 4 * s;
        int64_t d = tr->eb[i] * RS_SUB;
        dy[i] = (v4q){d, d, d, d};
    }
    const bool plain = !j->st->blend_enable && j->rt->n_aov == 0 && gx + 8 <= j->rt->width;
    rows8 r;
    rows8_make(j, p, gx, &r);
    for (int y = y0; y <= y1; y++) {
        unsigned cov = lm;
        if (!full) {
            v4q nl = (lo[0] | lo[1] | lo[2]), nh = (hi[0] | hi[1] | hi[2]); /* sign bit: some edge < 0 */
            unsigned out = (unsigned)_mm256_movemask_pd((__m256d)nl) | (unsigned)_mm256_movemask_pd((__m256d)nh) << 4;
            cov &= ~out;
        }
        if (cov && plain) row8(j, t, p, a, &r, gx, y, cov);
        else if (cov) span8(j, t, p, a, gx, y, cov);
        for (int i = 0; i < 3; i++) lo[i] += dy[i], hi[i] += dy[i];
    }
}

/* Lane i of the 4x2 walk is column i & 3 of row i >> 2. */
static const v8i quad_col = {0, 1, 2, 3, 0, 1, 2, 3};
static const v8i quad_row = {0, 0, 0, 0, 1, 1, 1, 1};

/* Two values as 4 + 4 lanes. */
static inline v8f halves(float lo, float hi) { return (v8f){lo, lo, lo, lo, hi, hi, hi, hi}; }

/* Load / store the 4 + 4 values of rows `p` and `p + stride` (the second only when `two`). */
static inline v8i load_quad(const uint32_t *p, size_t stride, bool two)
{
    v8i v = bi(0);
    memcpy(&v, p, 16);
    if (two) memcpy((char *)&v + 16, p + stride, 16);
    return v;
}
static inline void store_quad(uint32_t *p, size_t stride, bool two, v8i v)
{
    memcpy(p, &v, 16);
    if (two) memcpy(p + stride, (char *)&v + 16, 16);
}

/* span8 for the 4x2 pixels gx..gx+3 of rows y and y + 1 (lanes 4..7; `two`: row y + 1 lies in the tile) with
 * coverage cov, no blending, no AOV planes: each pixel gets tri_pixel's operations in the same order (the
 * x-dependent part r of each plane, then its row's y term). */
static void quad8(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, const rows8 *r, int gx, int y,
                  bool two, unsigned cov)
{
    const rs_tri *tr = &p->u.t;
    const rs_state *st = j->st;
    const float k = 1.0f / RS_SUB;
    const size_t w = (size_t)j->rt->width, base = (size_t)y * w + (size_t)gx;
    float fy0 = (float)((int64_t)y * RS_SUB - j->cy - tr->vy) * k;
    float fy1 = (float)((int64_t)(y + 1) * RS_SUB - j->cy - tr->vy) * k;
    v8i pass = lanes_of(cov);
    if (st->z_enable) {
        uint32_t *dep = (uint32_t *)j->rt->depth + base;
        v8f d = (v8f)load_quad(dep, w, two);
        float sy0 = fy0 + (float)j->soy[0] * k, sy1 = fy1 + (float)j->soy[0] * k;
        v8f z = zclamp8(r->zx + halves(tr->z[1] * sy0, tr->z[1] * sy1), j->zlo, j->zhi);
        pass &= zpass8(st->z_func, z, d);
        if (st->z_write) store_quad(dep, w, two, (v8i)sel(pass, z, d));
    }
    unsigned pm = mask_of(pass);
    t->tested += (uint64_t)__builtin_popcount(cov);
    if (!pm) return;
    t->written += (uint64_t)__builtin_popcount(pm);
    v8f rr = bf(1.0f) / (r->sx + halves(tr->s[1] * fy0, tr->s[1] * fy1));
    v8f b1 = (r->q1x + halves(tr->q1[1] * fy0, tr->q1[1] * fy1)) * rr;
    v8f b2 = (r->q2x + halves(tr->q2[1] * fy0, tr->q2[1] * fy1)) * rr;
    v8i src = shade8(j, a, b1, b2);
    uint32_t *col = j->rt->color + base;
    store_quad(col, w, two, seli(pass, src, load_quad(col, w, two)));
}

/* The 4x2 walk of a triangle at most 4 pixels wide (columns gx..gx+3 inside tile t), two rows per step; 32-bit
 * edge values as rs_tri_small's. */
static void tri_quads(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = &p->u.t;
    const int gx = x0 + 4 <= t->x1 ? x0 : t->x1 - 4;
    const int64_t X = (int64_t)gx * RS_SUB - j->cx, Y = (int64_t)y0 * RS_SUB - j->cy;
    v8i e[3], dy[3];
    for (int i = 0; i < 3; i++) {
        e[i] = bi((int32_t)(tr->ea[i] * X + tr->eb[i] * Y + tr->ec[i])) + quad_col * (int32_t)(tr->ea[i] * RS_SUB) +
               quad_row * (int32_t)(tr->eb[i] * RS_SUB);
        dy[i] = bi((int32_t)(tr->eb[i] * 2 * RS_SUB));
    }
    const unsigned row = ((1u << (x1 - x0 + 1)) - 1u) << (x0 - gx);
    rows8 r;
    v8i Xl = bi((int32_t)((int64_t)gx * RS_SUB - j->cx - tr->vx)) + quad_col * RS_SUB;
    v8f fx = __builtin_convertvector(Xl, v8f) * bf(1.0f / RS_SUB);
    v8f sx = fx + bf((float)j->sox[0] * (1.0f / RS_SUB));
    r.zx = bf(tr->z[2]) + bf(tr->z[0]) * sx;
    r.sx = bf(tr->s[2]) + bf(tr->s[0]) * fx;
    r.q1x = bf(tr->q1[2]) + bf(tr->q1[0]) * fx;
    r.q2x = bf(tr->q2[2]) + bf(tr->q2[0]) * fx;
    for (int y = y0; y <= y1; y += 2) {
        unsigned box = y + 1 <= y1 ? row | row << 4 : row;
        unsigned cov = box & ~mask_of(e[0] | e[1] | e[2]) & 0xffu; /* sign bit: some edge < 0 */
        if (cov) quad8(j, t, p, a, &r, gx, y, y + 1 < t->y1, cov);
        for (int i = 0; i < 3; i++) e[i] += dy[i];
    }
}

/* Does triangle p take the small-triangle path in tile t: its clipped box [x0, x1] at most 8 pixels wide, the
 * tile at least 8 wide, and every edge coefficient at most 2^13 (extent below 32 px) so that the edge values of
 * the walked pixels (within 8 px of the box) stay below 2^28: exact in int32. */
static bool small_ok(const rs_tile *t, const rs_tri *tr, int x0, int x1)
{
    if (x1 - x0 >= 8 || t->x1 - t->x0 < 8) return false;
    for (int i = 0; i < 3; i++)
        if (tr->ea[i] < -8192 || tr->ea[i] > 8192 || tr->eb[i] < -8192 || tr->eb[i] > 8192) return false;
    return true;
}

bool rs_tri_small(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = &p->u.t;
    if (!small_ok(t, tr, x0, x1)) return false;
    const bool plain = !j->st->blend_enable && j->rt->n_aov == 0;
    if (plain && x1 - x0 < 4 && y1 > y0) {
        tri_quads(j, t, p, a, x0, y0, x1, y1);
        return true;
    }
    const int gx = x0 + 8 <= t->x1 ? x0 : t->x1 - 8; /* 8 lanes gx..gx+7, all inside the tile */
    const int64_t X = (int64_t)gx * RS_SUB - j->cx, Y = (int64_t)y0 * RS_SUB - j->cy;
    v8i e[3], dy[3];
    for (int i = 0; i < 3; i++) {
        e[i] = bi((int32_t)(tr->ea[i] * X + tr->eb[i] * Y + tr->ec[i])) + lane_idx * (int32_t)(tr->ea[i] * RS_SUB);
        dy[i] = bi((int32_t)(tr->eb[i] * RS_SUB));
    }
    const unsigned box = ((1u << (x1 - x0 + 1)) - 1u) << (x0 - gx);
    rows8 r;
    rows8_make(j, p, gx, &r);
    for (int y = y0; y <= y1; y++) {
        unsigned cov = box & ~mask_of(e[0] | e[1] | e[2]) & 0xffu; /* sign bit: some edge < 0 */
        if (cov && plain) row8(j, t, p, a, &r, gx, y, cov);
        else if (cov) span8(j, t, p, a, gx, y, cov);
        for (int i = 0; i < 3; i++) e[i] += dy[i];
    }
    return true;
}

#else /* without AVX2 every draw takes the reference path */

bool rs_tri_small(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1, int y1)
{
    return false;
}

bool rs_span_ok(const rs_job *j) { return false; }

void rs_tri_block_fast(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                       int y1, const int64_t *e, bool full)
{
}

#endif
