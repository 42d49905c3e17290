/* raster/tri.c -- triangle rasterization inside one tile: 8x8 blocks with a trivial reject / accept test on
 * the integer edge functions, incremental int64 edge stepping inside partial blocks, per-sample depth from
 * the float depth plane, and perspective-correct shading once per pixel (at the pixel centre, D3D9 without
 * centroid sampling).  Shading and writes happen only for samples that pass the depth test.
 * This per-sample walk (tri_block, tri_pixel) is the reference: 1-sample targets off the reference path take
 * span.c's 8-lane walks instead, and 4-sample targets in plain states (no blending, AOV planes or pixel.c state)
 * tri_tile_msaa4, a pixel's four samples in lanes -- both write the same bytes.  A job with pixel.c's states (alpha test, stencil,
 * colour write mask...) takes tri_tile_ext, the same coverage and interpolation through rs_frag_ext; one with a
 * pixel shader takes tri_tile_quads, one shader call per 2x2 quad for all its covered pixels (tri_quad_ps), or per
 * pixel (tri_pixel_ps) where the quad would differ. */
#include "raster_internal.h"

#include <string.h>

/* Per-triangle constants of the walk: edge offsets of each sample and their range. */
typedef struct walk {
    int64_t eo[3][4];          /* ea*sox + eb*soy of sample s for edge e */
    int64_t omin[3], omax[3];  /* min / max over the samples of eo[e][.] */
    unsigned full;             /* mask of all samples */
} walk;

/* The plane of sum lambda_i / w_i of triangle tr at (fx, fy) (pixels from vertex 0): positive in front of the eye. */
static inline float tri_inv_w(const rs_tri *tr, float fx, float fy) { return tr->s[2] + tr->s[0] * fx + tr->s[1] * fy; }

/* Perspective barycentrics (*b1, *b2) of triangle tr at (fx, fy) whose tri_inv_w is sv. */
static inline void tri_bary_of(const rs_tri *tr, float fx, float fy, float sv, float *b1, float *b2)
{
    float r = 1.0f / sv;
    *b1 = (tr->q1[2] + tr->q1[0] * fx + tr->q1[1] * fy) * r;
    *b2 = (tr->q2[2] + tr->q2[0] * fx + tr->q2[1] * fy) * r;
}

/* tri_bary_of at the pixel centre (fx, fy), or at sample `first` when the centre lies far outside the triangle
 * (D3D9 shades at the centre, without centroid sampling, while it is in front of the eye). */
static inline void tri_bary(const rs_job *j, const rs_tri *tr, float fx, float fy, int first, float *b1, float *b2)
{
    const float k = 1.0f / RS_SUB;
    float sv = tri_inv_w(tr, fx, fy);
    if (!(sv > 0.0f)) {
        fx += (float)j->sox[first] * k;
        fy += (float)j->soy[first] * k;
        sv = tri_inv_w(tr, fx, fy);
    }
    tri_bary_of(tr, fx, fy, sv, b1, b2);
}

/* Depth-test, shade and write pixel (x, y) of triangle p with sample coverage cov. */
static void tri_pixel(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x, int y, unsigned cov)
{
    const rs_tri *tr = &p->u.t;
    const rs_state *st = j->st;
    const float k = 1.0f / RS_SUB;
    size_t base = rs_tile_index(t, x, y) * (size_t)j->samples;
    /* offsets from vertex 0 below 2^24 (1/256 px): exact in float (setup.c's bit budget) */
    RS_ASSERT(rs_within((int64_t)x * RS_SUB - j->cx - tr->vx, 24) &&
              rs_within((int64_t)y * RS_SUB - j->cy - tr->vy, 24));
    float fx = (float)((int64_t)x * RS_SUB - j->cx - tr->vx) * k;
    float fy = (float)((int64_t)y * RS_SUB - j->cy - tr->vy) * k;
    unsigned pass = cov;
    int first = __builtin_ctz(cov);
    if (st->z_enable) {
        float *dep = t->depth + base;
        pass = 0;
        for (int s = 0; s < j->samples; s++) {
            if (!(cov & (1u << s))) continue;
            float sx = fx + (float)j->sox[s] * k, sy = fy + (float)j->soy[s] * k;
            float z = rs_zclamp(tr->z[2] + tr->z[0] * sx + tr->z[1] * sy, j->zlo, j->zhi);
            if (!rs_zpass(st->z_func, z, dep[s])) continue;
            pass |= 1u << s;
            if (st->z_write) dep[s] = z;
        }
    }
    t->tested += (uint64_t)__builtin_popcount(cov);
    if (!pass) return;
    t->written += (uint64_t)__builtin_popcount(pass);
    float b1, b2;
    tri_bary(j, tr, fx, fy, first, &b1, &b2);
    rs_write_color(j, t->color + base, pass, rs_shade_color(j, a, b1, b2));
    if (j->rt->n_aov > 0) rs_write_aov(j, a, b1, b2, x, y);
}

/* Coverage mask of the samples of a pixel whose edge values at the centre are e[0..3). */
static inline unsigned coverage(const rs_job *j, const walk *w, const int64_t *e)
{
    unsigned cov = 0;
    for (int s = 0; s < j->samples; s++)
        if (e[0] + w->eo[0][s] >= 0 && e[1] + w->eo[1][s] >= 0 && e[2] + w->eo[2][s] >= 0) cov |= 1u << s;
    return cov;
}

/* Walk the pixels [x0, x1] x [y0, y1] (one block) with edge values e at (x0, y0); full: all inside. */
static void tri_block(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, const walk *w,
                      int x0, int y0, int x1, int y1, const int64_t *e, bool full)
{
    const rs_tri *tr = &p->u.t;
    int64_t row[3] = { e[0], e[1], e[2] };
    for (int y = y0; y <= y1; y++) {
        int64_t v[3] = { row[0], row[1], row[2] };
        for (int x = x0; x <= x1; x++) {
            unsigned cov = full ? w->full : coverage(j, w, v);
            if (cov) tri_pixel(j, t, p, a, x, y, cov);
            for (int i = 0; i < 3; i++) v[i] += (int64_t)tr->ea[i] * RS_SUB;
        }
        for (int i = 0; i < 3; i++) row[i] += (int64_t)tr->eb[i] * RS_SUB;
    }
}

/* Trivial test of block [x0, x0+nx] x [y0, y0+ny] with edge values e at (x0, y0): -1 outside, 1 inside, 0 partial. */
static int block_test(const rs_tri *tr, const walk *w, const int64_t *e, int nx, int ny)
{
    int r = 1;
    for (int i = 0; i < 3; i++) {
        int64_t sx = (int64_t)tr->ea[i] * RS_SUB * nx, sy = (int64_t)tr->eb[i] * RS_SUB * ny;
        int64_t hi = e[i] + (sx > 0 ? sx : 0) + (sy > 0 ? sy : 0) + w->omax[i];
        int64_t lo = e[i] + (sx < 0 ? sx : 0) + (sy < 0 ? sy : 0) + w->omin[i];
        if (hi < 0) return -1;
        if (lo < 0) r = 0;
    }
    return r;
}

/* The reference walk of triangle p's pixels [x0, x1] x [y0, y1] (its box clipped to tile t): 8x8 blocks.  Out of
 * line, so that rs_tri_tile's call of the fast path does not pay for this walk's frame. */
static __attribute__((noinline)) void tri_tile_ref(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a,
                                                   int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = &p->u.t;
    walk w;
    w.full = (1u << j->samples) - 1u;
    for (int i = 0; i < 3; i++) {
        w.omin[i] = w.omax[i] = 0;
        for (int s = 0; s < j->samples; s++) {
            int64_t o = (int64_t)tr->ea[i] * j->sox[s] + (int64_t)tr->eb[i] * j->soy[s];
            w.eo[i][s] = o;
            if (s == 0 || o < w.omin[i]) w.omin[i] = o;
            if (s == 0 || o > w.omax[i]) w.omax[i] = o;
        }
    }
    for (int by = y0; by <= y1; by = (by | (RS_BLOCK - 1)) + 1) {
        int by1 = (by | (RS_BLOCK - 1)) < y1 ? (by | (RS_BLOCK - 1)) : y1;
        for (int bx = x0; bx <= x1; bx = (bx | (RS_BLOCK - 1)) + 1) {
            int bx1 = (bx | (RS_BLOCK - 1)) < x1 ? (bx | (RS_BLOCK - 1)) : x1;
            int64_t X = (int64_t)bx * RS_SUB - j->cx, Y = (int64_t)by * RS_SUB - j->cy;
            int64_t e[3];
            for (int i = 0; i < 3; i++) e[i] = tr->ea[i] * X + tr->eb[i] * Y + tr->ec[i];
            int r = block_test(tr, &w, e, bx1 - bx, by1 - by);
            if (r >= 0) tri_block(j, t, p, a, &w, bx, by, bx1, by1, e, r > 0);
        }
    }
}

/* The pixel shader's quad around pixel (x, y) of triangle p (barycentrics (b1, b2) at the pixel), then the
 * pixel's lane through rs_frag_ps: each lane's inputs at its own centre from the triangle's planes, its own
 * inputs where the plane of 1/w is not positive (behind the eye); live = the lanes whose centre the triangle
 * covers (the top-left rule on the edge functions). */
static void tri_pixel_ps(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x, int y, unsigned cov,
                         float *zs, float b1, float b2)
{
    const rs_tri *tr = &p->u.t;
    const float k = 1.0f / RS_SUB;
    rs_ps_quad q;
    memset(&q, 0, sizeof q);
    int x0 = x & ~1, y0 = y & ~1, lane = (x - x0) + 2 * (y - y0);
    for (int l = 0; l < 4; l++) {
        int px = x0 + (l & 1), py = y0 + (l >> 1);
        int64_t X = (int64_t)px * RS_SUB - j->cx, Y = (int64_t)py * RS_SUB - j->cy;
        bool in = true;
        for (int e = 0; e < 3; e++) in &= (int64_t)tr->ea[e] * X + (int64_t)tr->eb[e] * Y + tr->ec[e] >= 0;
        if (in) q.live |= 1u << l;
        q.vpos[l][0] = (float)px, q.vpos[l][1] = (float)py;
        float fx = (float)(X - tr->vx) * k, fy = (float)(Y - tr->vy) * k;
        float sv = tri_inv_w(tr, fx, fy);
        float l1 = b1, l2 = b2;
        if (l != lane && sv > 0.0f) tri_bary_of(tr, fx, fy, sv, &l1, &l2);
        rs_ps_lane(j, a, l1, l2, q.v[l]);
    }
    q.live |= 1u << lane;   /* covered by a sample, if not at its centre */
    q.front = p->back == 0;
    q.need = 1u << lane;
    rs_frag_ps(j, t, x, y, cov, zs, p->back != 0, &q, lane, a, b1, b2);
}

/* Pixel (x, y) of triangle p with coverage cov: each covered sample's depth into zs and the perspective
 * barycentrics (as tri_pixel computes them) into *b1, *b2. */
static inline __attribute__((always_inline)) void tri_pixel_at(const rs_job *j, const rs_tri *tr, int x, int y,
                                                              unsigned cov, float *zs, float *b1, float *b2)
{
    const float k = 1.0f / RS_SUB;
    float fx = (float)((int64_t)x * RS_SUB - j->cx - tr->vx) * k;
    float fy = (float)((int64_t)y * RS_SUB - j->cy - tr->vy) * k;
    for (int s = 0; s < 4; s++) zs[s] = 0.0f;
    for (int s = 0; s < j->samples; s++) {
        float sx = fx + (float)j->sox[s] * k, sy = fy + (float)j->soy[s] * k;
        zs[s] = rs_zclamp(tr->z[2] + tr->z[0] * sx + tr->z[1] * sy, j->zlo, j->zhi);
    }
    tri_bary(j, tr, fx, fy, __builtin_ctz(cov), b1, b2);
}

/* Pixel (x, y) of triangle p with coverage cov for a job with pixel.c's states: tri_pixel_at, then rs_frag_ext
 * (or the pixel shader's quad around the pixel). */
static void tri_pixel_ext(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x, int y, unsigned cov)
{
    float zs[4], b1, b2;
    tri_pixel_at(j, &p->u.t, x, y, cov, zs, &b1, &b2);
    if (j->st->ps) tri_pixel_ps(j, t, p, a, x, y, cov, zs, b1, b2);
    else rs_frag_ext(j, t, x, y, cov, zs, p->back != 0, a, b1, b2);
}

/* The quad at (x0, y0) (even) of triangle p whose pixels have coverage cov[0..3] and whose centres the triangle
 * covers where `in` has the lane's bit, shaded by one call of the pixel shader for all its covered pixels; q is
 * the walk's quad, whose slots outside the job's are zero (only the job's slots, vPos and the masks are written
 * here).  False (nothing written to the target) when that quad would differ from the one tri_pixel_ps builds
 * around each covered pixel alone -- a helper lane behind the eye (it takes the shaded pixel's inputs there), or a
 * pixel covered by a sample but not at its centre (not live while its neighbours are shaded) -- so the bytes are
 * tri_pixel_ps's either way (a triangle's pixels are distinct: their order does not matter). */
static bool tri_quad_ps(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, rs_ps_quad *q, int x0, int y0,
                        const unsigned cov[4], unsigned in)
{
    const rs_tri *tr = &p->u.t;
    const float k = 1.0f / RS_SUB;
    unsigned need = 0;
    for (int l = 0; l < 4; l++) need |= (unsigned)(cov[l] != 0) << l;
    if (need & ~in) return false;
    float zs[4][4], b[4][2];
    for (int l = 0; l < 4; l++) {
        int px = x0 + (l & 1), py = y0 + (l >> 1);
        if (cov[l]) {
            tri_pixel_at(j, tr, px, py, cov[l], zs[l], &b[l][0], &b[l][1]);
        } else {
            int64_t X = (int64_t)px * RS_SUB - j->cx, Y = (int64_t)py * RS_SUB - j->cy;
            float fx = (float)(X - tr->vx) * k, fy = (float)(Y - tr->vy) * k, sv = tri_inv_w(tr, fx, fy);
            if (!(sv > 0.0f)) return false;
            tri_bary_of(tr, fx, fy, sv, &b[l][0], &b[l][1]);
        }
    }
    for (int l = 0; l < 4; l++) {
        rs_ps_lane(j, a, b[l][0], b[l][1], q->v[l]);
        q->vpos[l][0] = (float)(x0 + (l & 1)), q->vpos[l][1] = (float)(y0 + (l >> 1));
    }
    q->live = in, q->need = need, q->front = p->back == 0;
    rs_ps_out o;
    memset(&o, 0, sizeof o);
    j->st->ps(j->st->ps_ctx, q, &o);
    for (int l = 0; l < 4; l++)
        if (cov[l])
            rs_ps_write(j, t, x0 + (l & 1), y0 + (l >> 1), cov[l], zs[l], p->back != 0, &o, l, a, b[l][0], b[l][1]);
    return true;
}

/* The walk's bounds: the box [x0, x1] x [y0, y1] of the triangle in the tile, the walk's quad q and the edge
 * offsets w (with the pixel centre among the samples: a block that block_test accepts has every centre inside). */
typedef struct quad_walk {
    int x0, y0, x1, y1;
    walk w;
    rs_ps_quad q;
} quad_walk;

/* The quads of block [bx, bx1] x [by, by1] (bx, by even; bx1, by1 odd) of triangle p whose edge values at (bx, by)
 * are e (all = every sample and centre inside): each pixel's centre edge values stepped from e (exact integers),
 * its coverage, then tri_quad_ps, or pixel by pixel (tri_pixel_ext) where that would change a byte. */
static void tri_quads_block(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, quad_walk *qw, int bx,
                            int by, int bx1, int by1, const int64_t *e, bool all)
{
    const rs_tri *tr = &p->u.t;
    int64_t sa[3], sb[3], row[3], off[4][3];   /* steps of one pixel in x and y; lane l's offset from its quad */
    for (int i = 0; i < 3; i++) sa[i] = (int64_t)tr->ea[i] * RS_SUB, sb[i] = (int64_t)tr->eb[i] * RS_SUB, row[i] = e[i];
    for (int l = 0; l < 4; l++)
        for (int i = 0; i < 3; i++) off[l][i] = (l & 1 ? sa[i] : 0) + (l >> 1 ? sb[i] : 0);
    bool inbox = bx >= qw->x0 && bx1 <= qw->x1 && by >= qw->y0 && by1 <= qw->y1;   /* no pixel outside the box */
    const unsigned full[4] = {qw->w.full, qw->w.full, qw->w.full, qw->w.full};
    for (int qy = by; qy <= by1; qy += 2) {
        int64_t v[3] = { row[0], row[1], row[2] };
        for (int qx = bx; qx <= bx1; qx += 2) {
            unsigned cov[4], any = 0, in = 0;
            if (all && inbox) {   /* every lane inside, at its centre and every sample */
                memcpy(cov, full, sizeof cov), any = in = 0xfu;
            } else {
                for (int l = 0; l < 4; l++) {
                    int64_t ev[3] = {v[0] + off[l][0], v[1] + off[l][1], v[2] + off[l][2]};
                    in |= (unsigned)(all || (ev[0] >= 0 && ev[1] >= 0 && ev[2] >= 0)) << l;
                    int x = qx + (l & 1), y = qy + (l >> 1);
                    bool box = inbox || (x >= qw->x0 && x <= qw->x1 && y >= qw->y0 && y <= qw->y1);
                    any |= cov[l] = !box ? 0u : all ? qw->w.full : coverage(j, &qw->w, ev);
                }
            }
            if (any && !tri_quad_ps(j, t, p, a, &qw->q, qx, qy, cov, in))
                for (int l = 0; l < 4; l++)
                    if (cov[l]) tri_pixel_ext(j, t, p, a, qx + (l & 1), qy + (l >> 1), cov[l]);
            for (int i = 0; i < 3; i++) v[i] += 2 * sa[i];
        }
        for (int i = 0; i < 3; i++) row[i] += 2 * sb[i];
    }
}

/* The pixel-shader walk of triangle p's pixels [x0, x1] x [y0, y1] (inside one tile, whose quads it holds whole):
 * blocks of whole quads (at most 8x8 pixels) rejected or accepted whole by block_test, the others quad by quad
 * (tri_quads_block).  The quad's slots are zeroed once here: every call writes the same slots. */
static void tri_tile_quads(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                           int y1)
{
    const rs_tri *tr = &p->u.t;
    quad_walk qw = {.x0 = x0, .y0 = y0, .x1 = x1, .y1 = y1};
    qw.w.full = (1u << j->samples) - 1u;
    for (int i = 0; i < 3; i++) {
        qw.w.omin[i] = qw.w.omax[i] = 0;   /* the centre (offset 0) counts too */
        for (int s = 0; s < j->samples; s++) {
            int64_t o = (int64_t)tr->ea[i] * j->sox[s] + (int64_t)tr->eb[i] * j->soy[s];
            qw.w.eo[i][s] = o;
            if (o < qw.w.omin[i]) qw.w.omin[i] = o;
            if (o > qw.w.omax[i]) qw.w.omax[i] = o;
        }
    }
    memset(&qw.q, 0, sizeof qw.q);
    int qx1 = x1 | 1, qy1 = y1 | 1;
    for (int by = y0 & ~1; by <= qy1; by = (by | (RS_BLOCK - 1)) + 1) {
        int by1 = (by | (RS_BLOCK - 1)) < qy1 ? (by | (RS_BLOCK - 1)) : qy1;
        for (int bx = x0 & ~1; bx <= qx1; bx = (bx | (RS_BLOCK - 1)) + 1) {
            int bx1 = (bx | (RS_BLOCK - 1)) < qx1 ? (bx | (RS_BLOCK - 1)) : qx1;
            int64_t X = (int64_t)bx * RS_SUB - j->cx, Y = (int64_t)by * RS_SUB - j->cy, e[3];
            for (int i = 0; i < 3; i++) e[i] = tr->ea[i] * X + tr->eb[i] * Y + tr->ec[i];
            int r = block_test(tr, &qw.w, e, bx1 - bx, by1 - by);
            if (r >= 0) tri_quads_block(j, t, p, a, &qw, bx, by, bx1, by1, e, r > 0);
        }
    }
}

/* The walk of a job with pixel.c's states (rs_job.ext): every pixel of [x0, x1] x [y0, y1] with its exact sample
 * coverage (the coverage tri_tile_ref's blocks give, without their trivial accept / reject), through
 * tri_pixel_ext.  Apart from tri_tile_ref, so that the plain walk does not pay for the states' test. */
static __attribute__((noinline)) void tri_tile_ext(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a,
                                                   int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = &p->u.t;
    walk w;
    for (int i = 0; i < 3; i++)
        for (int s = 0; s < j->samples; s++) w.eo[i][s] = (int64_t)tr->ea[i] * j->sox[s] + (int64_t)tr->eb[i] * j->soy[s];
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            int64_t X = (int64_t)x * RS_SUB - j->cx, Y = (int64_t)y * RS_SUB - j->cy, e[3];
            for (int i = 0; i < 3; i++) e[i] = tr->ea[i] * X + tr->eb[i] * Y + tr->ec[i];
            unsigned cov = coverage(j, &w, e);
            if (cov) tri_pixel_ext(j, t, p, a, x, y, cov);
        }
}

#ifdef __AVX2__
#include <immintrin.h>
#endif

/* Four lanes of int64, float and int32 (GCC's vector extensions: AVX2 on x86, SIMD128 or plain code in the
 * browser's build; comparisons give -1 / 0 per lane with C's semantics -- NaN compares false but for != --, so
 * rs_zpass's and rs_zclamp's results per lane). */
typedef int64_t q4 __attribute__((vector_size(32)));
typedef float f4 __attribute__((vector_size(16)));
typedef int32_t i4 __attribute__((vector_size(16)));

/* Lanes of a where m is -1, of b where 0. */
static inline f4 sel4(i4 m, f4 a, f4 b) { return (f4)((m & (i4)a) | (~m & (i4)b)); }

/* The lanes of v where m is -1 stored to p[0..4), the others' memory untouched (a masked store; per lane without
 * AVX2), so that the walk writes exactly the samples the reference writes. */
static inline void store4_masked(void *p, i4 m, i4 v)
{
#ifdef __AVX2__
    _mm_maskstore_epi32((int *)p, (__m128i)m, (__m128i)v);
#else
    for (int s = 0; s < 4; s++)
        if (m[s]) {
            const int32_t x = v[s];   /* (no address of a vector's element in clang) */
            memcpy((char *)p + 4 * s, &x, 4);
        }
#endif
}

/* rs_zpass(f, z, d) per lane (-1: passes). */
static inline i4 zpass4(int f, f4 z, f4 d) { return RS_ZPASS_LANES(i4, f, z, d); }

/* rs_zclamp per lane: z >= lo ? (z <= hi ? z : hi) : lo (NaN -> lo). */
static inline f4 zclamp4(f4 z, f4 lo, f4 hi) { return sel4(z >= lo, sel4(z <= hi, z, hi), lo); }

/* The 4-sample walk (rs_tri_tile: 4 samples, plain states -- no blending, AOV planes or pixel.c state -- off the
 * reference path): tri_tile_ref's bytes and counters with a pixel's four samples in lanes -- its coverage from the
 * int64 edge values at the centre plus each sample's offset (coverage()'s integers), the pixel's four depths as
 * one load with rs_zclamp's and rs_zpass's float operations per lane in tri_pixel's order, the passing samples'
 * depth and colour by masked stores (store4_masked: no other byte written) -- pixel by pixel over the box
 * in rows (a triangle's pixels are distinct: their order does not matter); the colour once per pixel as tri_pixel
 * shades it. */
static __attribute__((noinline)) void tri_tile_msaa4(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a,
                                                     int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = &p->u.t;
    const rs_state *st = j->st;
    const float k = 1.0f / RS_SUB;
    q4 eo[3];
    int64_t sa[3];
    for (int i = 0; i < 3; i++) {
        for (int s = 0; s < 4; s++) eo[i][s] = (int64_t)tr->ea[i] * j->sox[s] + (int64_t)tr->eb[i] * j->soy[s];
        sa[i] = (int64_t)tr->ea[i] * RS_SUB;
    }
    f4 sxo, syo;
    for (int s = 0; s < 4; s++) sxo[s] = (float)j->sox[s] * k, syo[s] = (float)j->soy[s] * k;
    const f4 z0 = {tr->z[0], tr->z[0], tr->z[0], tr->z[0]}, z1 = {tr->z[1], tr->z[1], tr->z[1], tr->z[1]};
    const f4 z2 = {tr->z[2], tr->z[2], tr->z[2], tr->z[2]};
    const f4 lo = {j->zlo, j->zlo, j->zlo, j->zlo}, hi = {j->zhi, j->zhi, j->zhi, j->zhi};
    const i4 bit = {1, 2, 4, 8};
    const int64_t X0 = (int64_t)x0 * RS_SUB - j->cx;
    uint64_t tested = 0, written = 0;
    for (int y = y0; y <= y1; y++) {
        const int64_t Y = (int64_t)y * RS_SUB - j->cy;
        int64_t e[3];
        for (int i = 0; i < 3; i++) e[i] = tr->ea[i] * X0 + tr->eb[i] * Y + tr->ec[i];
        RS_ASSERT(rs_within(Y - tr->vy, 24));
        const float fy = (float)(Y - tr->vy) * k;
        const f4 zy = z1 * (fy + syo);   /* z[1] * sy */
        size_t base = rs_tile_index(t, x0, y) * 4u;
        for (int x = x0; x <= x1; x++, base += 4) {
            const q4 o = ((e[0] + eo[0]) | (e[1] + eo[1])) | (e[2] + eo[2]);   /* sign: some edge < 0 */
            for (int i = 0; i < 3; i++) e[i] += sa[i];
            const i4 in = {o[0] >= 0 ? -1 : 0, o[1] >= 0 ? -1 : 0, o[2] >= 0 ? -1 : 0, o[3] >= 0 ? -1 : 0};
            if (!(in[0] | in[1] | in[2] | in[3])) continue;
            const i4 cm = in & bit;
            const unsigned cov = (unsigned)(cm[0] | cm[1] | cm[2] | cm[3]);
            const int64_t X = (int64_t)x * RS_SUB - j->cx;
            RS_ASSERT(rs_within(X - tr->vx, 24));
            const float fx = (float)(X - tr->vx) * k;
            i4 ok = in;
            if (st->z_enable) {
                float *dep = t->depth + base;
                f4 d;
                memcpy(&d, dep, sizeof d);
                const f4 z = zclamp4((z2 + z0 * (fx + sxo)) + zy, lo, hi);
                ok &= zpass4(st->z_func, z, d);
                if (st->z_write) store4_masked(dep, ok, (i4)z);
            }
            tested += (uint64_t)__builtin_popcount(cov);
            const i4 pm = ok & bit;
            const unsigned pass = (unsigned)(pm[0] | pm[1] | pm[2] | pm[3]);
            if (!pass) continue;
            written += (uint64_t)__builtin_popcount(pass);
            float b1, b2;
            tri_bary(j, tr, fx, fy, __builtin_ctz(cov), &b1, &b2);
            const int32_t c = (int32_t)rs_shade_color(j, a, b1, b2);
            store4_masked(t->color + base, ok, (i4){c, c, c, c});
        }
    }
    t->tested += tested, t->written += written;
}

void rs_tri_tile(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a)
{
    int x0 = p->x0 > t->x0 ? p->x0 : t->x0, x1 = p->x1 < t->x1 - 1 ? p->x1 : t->x1 - 1;
    int y0 = p->y0 > t->y0 ? p->y0 : t->y0, y1 = p->y1 < t->y1 - 1 ? p->y1 : t->y1 - 1;
    if (x0 > x1 || y0 > y1) return;
    if (rs_span_ok(j)) j->kern->tri_fast(j, t, p, a, x0, y0, x1, y1); /* 1-sample targets: span.c, same bytes */
    else if (j->ext && j->st->ps) tri_tile_quads(j, t, p, a, x0, y0, x1, y1);   /* a pixel shader */
    else if (j->ext) tri_tile_ext(j, t, p, a, x0, y0, x1, y1);   /* pixel.c's other states */
    else if (j->walk4) tri_tile_msaa4(j, t, p, a, x0, y0, x1, y1);   /* 4 samples, plain states: in lanes */
    else tri_tile_ref(j, t, p, a, x0, y0, x1, y1);
}
