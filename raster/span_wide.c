/* raster/span_wide.c -- the fast path of triangle rasterization on 1-sample targets, larger triangles (span.c's
 * rs_tri_fast sends them here): 8 pixels at a time, the same per-pixel operations and bytes as span.c's walks and
 * tri.c's reference walk (span_lanes.h states how).
 *
 * The walks here:
 *  - medium triangles (box at most 32 wide, edge coefficients at most 2^13): the span walk, no blocks: each row's
 *    coverage over a window of 2 or 4 groups of 8 columns (32-bit edge values), then 8-lane groups from the row's
 *    first covered pixel until its covered interval is done, so lanes hold only covered pixels' runs;
 *  - the others: the block walk: the box's groups of 8 columns (from its left column when it is narrow, 8-aligned
 *    otherwise), each cut into blocks of up to 8 rows with a trivial reject / accept test; full blocks skip
 *    coverage, partial blocks step int32 edge values when the edges that cross the block provably fit (int64
 *    otherwise).
 * Each walk is instantiated per depth-state mode (span_lanes.h's INSTANCES). */
#include "span_lanes.h"

#ifdef __AVX2__

/* ---- the span walk ---- */

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

INSTANCES(span2, walk_span2)
INSTANCES(span4, walk_span4)
INSTANCES(big, walk_big)

typedef void walk_fn(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1, int y1);
/* walks[walk - 1][mode]: walk 1 and 2 span (2 or 4 groups), 3 block; mode: the job's span_mode (0 LESSEQUAL, 1
 * LESS, 2 any). */
static walk_fn *const walks[3][3] = {
    {span2_le, span2_less, span2_any},
    {span4_le, span4_less, span4_any},
    {big_le, big_less, big_any},
};

void RS_KERNEL(rs_tri_wide)(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                            int y1, int walk)
{
    RS_ASSERT(walk >= 1 && walk <= 3);
    walks[walk - 1][j->span_mode](j, t, p, a, x0, y0, x1, y1);
}

#else /* without AVX2 every draw takes the reference path (rs_span_ok is false) */

void RS_KERNEL(rs_tri_wide)(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                            int y1, int walk)
{
}

#endif
