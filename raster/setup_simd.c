/* raster/setup_simd.c -- the fast path of triangle set-up (off the reference path): the shared pass and the
 * four-lane finish.  setup.c's rs_setup_triangle is the definition; every function here gives its bytes.
 *
 *  The shared pass (indexed triangles off the reference path, rs_draw's and rs_draw_source's) first projects every
 *  vertex once into a 24-byte record (rs_project_vertices, four vertices in double lanes); rs_setup_shared then
 *  culls each triangle from its three records and pushes a front-facing one at once (pixel box, ptile entry,
 *  attribute slots) but queues its edges and planes, which finish4 computes for four triangles at a time: the
 *  edge functions in int32 / int64 lanes and rs_tri_planes' double operations in double lanes, per lane the same
 *  operations in the same order as the scalar functions, so the same rs_prim bytes.  A triangle whose vertices
 *  are not all inside the clip volume (or a fill mode other than solid) goes back to the definition, in
 *  submission order.  Without AVX2 the same records are finished one triangle at a time (finish_one).
 *  Grouped pieces (rs_setup_groups, rs_group_tile) and their grid groups, set up from the grid's vertex rows ("grid
 *  rows" below), reuse finish4's operations (finish4_lanes): raster_internal.h says how.
 */
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#ifdef __SSE2__
#include <immintrin.h>
#endif

#include "setup_internal.h"

/* A vertex after the shared pass (rs_project_vertices): outcode and projection, done once per vertex, in a
 * compact record (24 bytes, no padding: ready3, area3, tri_box and finish4 read the first 16 bytes as one
 * vector).  The attribute slots are not in it: they are the job's verts[i].attr for record i. */
struct rs_pvert {
    int32_t x, y;    /* snapped position, 1/256 px relative to the viewport centre (|x|, |y| <= 2^22; 0 unless
                        projected) */
    float z;         /* viewport depth (0 unless projected) */
    uint8_t flags;   /* PV_* */
    uint8_t oc;      /* outcode (0 unless finite) */
    uint16_t pad;    /* 0 */
    double iw;       /* 1 / w (0 unless projected) */
};
enum {
    PV_FINITE = 1,    /* setup.c's load() would accept the position */
    PV_PROJECTED = 2, /* rs_project() succeeded (x, y, z, iw valid) */
    PV_READY = 4      /* finite, inside every clip plane (oc == 0) and projected: no triangle check needed */
};
_Static_assert(sizeof(rs_pvert) == 24, "rs_pvert: x, y, z, flags, oc, pad, iw without padding");

#ifndef RS_KERNEL_AVX512 /* one definition, in the AVX2 copy */
size_t rs_pvert_size(void) { return sizeof(rs_pvert); }
#endif

/* rs_outcode inline: bit k set when p is outside clip plane k (clip.c's plane_dist, same expressions). */
static inline unsigned outcode6(const rs_job *j, const double *p)
{
    _Static_assert(RS_CLIP_PLANES == 6, "near, far and four guard-band planes");
    return (unsigned)!(p[2] >= 0.0) | (unsigned)!(p[3] - p[2] >= 0.0) << 1 |
           (unsigned)!(p[0] + j->gx * p[3] >= 0.0) << 2 | (unsigned)!(j->gx * p[3] - p[0] >= 0.0) << 3 |
           (unsigned)!(p[1] + j->gy * p[3] >= 0.0) << 4 | (unsigned)!(j->gy * p[3] - p[1] >= 0.0) << 5;
}

/* What setup.c's load() and rs_project() give for one vertex, without building the clip vertex's other fields. */
void RS_KERNEL(rs_project_vertex)(const rs_job *j, const rs_vertex *v, rs_pvert *out)
{
    const rs_vec4 *q = &v->pos;
    *out = (rs_pvert){ 0 };
    if (!(isfinite(q->x) && isfinite(q->y) && isfinite(q->z) && isfinite(q->w))) return;
    rs_cvert cv;
    cv.p[0] = q->x, cv.p[1] = q->y, cv.p[2] = q->z, cv.p[3] = q->w;
    cv.a = v->attr, cv.edge = true, cv.orig = true;
    unsigned oc = outcode6(j, cv.p);
    rs_svert p;
    bool pr = rs_project(j, &cv, &p);
    out->oc = (uint8_t)oc;
    out->flags = (uint8_t)(PV_FINITE | (pr ? PV_PROJECTED : 0) | (pr && oc == 0 ? PV_READY : 0));
    if (!pr) return;
    out->x = (int32_t)p.x, out->y = (int32_t)p.y, out->z = p.z, out->iw = p.iw;
}

/* The projected vertex of record r (attribute slots a), as rs_project() gives it. */
static inline rs_svert svert_of(const rs_pvert *r, const rs_vec4 *a)
{
    return (rs_svert){ .x = r->x, .y = r->y, .z = r->z, .iw = r->iw, .a = a, .edge = true, .orig = true };
}

#ifdef __AVX2__
typedef int64_t v4q __attribute__((vector_size(32)));

/* Store rows r0..r3 of a 4x4 matrix of 32-bit values transposed: column t to base[t] + off. */
static inline void store_t32(__m128 r0, __m128 r1, __m128 r2, __m128 r3, char *const base[4], size_t off)
{
    __m128 a = _mm_unpacklo_ps(r0, r1), b = _mm_unpackhi_ps(r0, r1);   /* 00 10 01 11, 02 12 03 13 */
    __m128 c = _mm_unpacklo_ps(r2, r3), d = _mm_unpackhi_ps(r2, r3);   /* 20 30 21 31, 22 32 23 33 */
    _mm_storeu_ps((float *)(base[0] + off), _mm_movelh_ps(a, c));
    _mm_storeu_ps((float *)(base[1] + off), _mm_movehl_ps(c, a));
    _mm_storeu_ps((float *)(base[2] + off), _mm_movelh_ps(b, d));
    _mm_storeu_ps((float *)(base[3] + off), _mm_movehl_ps(d, b));
}

/* rs_project's clamp per lane: x < -lim ? -lim : (x > lim ? lim : x). */
static inline v4d clamp4(v4d x, double lim)
{
    v4d hi = { lim, lim, lim, lim }, lo = -hi;
    v4q l = x < lo, h = x > hi;
    v4q r = ((v4q)lo & l) | (~l & (((v4q)hi & h) | ((v4q)x & ~h)));
    return (v4d)r;
}

/* The first 16 bytes of four records (x, y, z in int32 lanes and the flags, oc and pad int32; 0 where not
 * projected) and their 1/w (0 where not projected), in lanes; or, for the rows (proj4 without records), x, y, z and
 * 1/w as projected (not zeroed) and in ready the lanes that are PV_READY (-1). */
typedef struct proj4_lanes { __m128i x, y, z, fl; __m256d iw; v4q ready; } proj4_lanes;

/* rs_project_vertex for the four vertices v[0..4) in lanes: outcode6 and rs_project per lane with the same double
 * operations (a value is finite iff x - x == 0; llrint is cvtpd2dq, exact for the clamped |x| <= 2^22).  Without
 * records (the rows: read only when every vertex of the piece is ready, where the zeroing changes nothing) the
 * outcode is only tested for zero: the six plane tests ANDed. */
static inline __attribute__((always_inline)) void proj4(const rs_job *j, const rs_vertex *v, bool records,
                                                        proj4_lanes *o)
{
    /* the four positions transposed (fewer instructions than gathering the sixteen floats one by one) */
    __m128 p0 = _mm_loadu_ps(&v[0].pos.x), p1 = _mm_loadu_ps(&v[1].pos.x);
    __m128 p2 = _mm_loadu_ps(&v[2].pos.x), p3 = _mm_loadu_ps(&v[3].pos.x);
    _MM_TRANSPOSE4_PS(p0, p1, p2, p3);
    v4d x = (v4d)_mm256_cvtps_pd(p0), y = (v4d)_mm256_cvtps_pd(p1);
    v4d z = (v4d)_mm256_cvtps_pd(p2), w = (v4d)_mm256_cvtps_pd(p3);
    v4q fin = (x - x == 0.0) & (y - y == 0.0) & (z - z == 0.0) & (w - w == 0.0);
    v4d fx = x / w * j->sx_scale, fy = y / w * j->sy_scale, zw = z / w, iw = 1.0 / w;
    v4q ok = fin & (w > 0.0) & (fx - fx == 0.0) & (fy - fy == 0.0) & (zw - zw == 0.0) & (iw - iw == 0.0);
    const double lim = (double)RS_GUARD_BAND * RS_SUB;
    fx = clamp4(fx, lim);
    fy = clamp4(fy, lim);
    RS_ASSERT(_mm256_movemask_pd((__m256d)((~ok) | ((fx >= -lim) & (fx <= lim) & (fy >= -lim) & (fy <= lim)))) == 15);
    __m128i rx = _mm256_cvtpd_epi32((__m256d)fx), ry = _mm256_cvtpd_epi32((__m256d)fy);
    v4d zd = (double)j->zoff + (double)j->zscale * zw;
    __m128i zf = _mm_castps_si128(_mm256_cvtpd_ps((__m256d)zd));
    if (!records) {
        const v4q inside = (z >= 0.0) & (w - z >= 0.0) & (x + j->gx * w >= 0.0) & (j->gx * w - x >= 0.0) &
                           (y + j->gy * w >= 0.0) & (j->gy * w - y >= 0.0);
        o->ready = ok & inside;
        o->x = rx, o->y = ry, o->z = zf, o->iw = (__m256d)iw;
        return;
    }
    v4q oc = (~(z >= 0.0) & 1) | (~(w - z >= 0.0) & 2) | (~(x + j->gx * w >= 0.0) & 4) |
             (~(j->gx * w - x >= 0.0) & 8) | (~(y + j->gy * w >= 0.0) & 16) | (~(j->gy * w - y >= 0.0) & 32);
    /* the records' first 16 bytes in int32 lanes (0 where not projected) */
    const __m256i even = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
    __m128i fin32 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32((__m256i)fin, even));
    __m128i ok32 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32((__m256i)ok, even));
    __m128i oc32 = _mm_and_si128(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32((__m256i)oc, even)), fin32);
    __m128i ready = _mm_and_si128(ok32, _mm_cmpeq_epi32(oc32, _mm_setzero_si128()));
    o->fl = _mm_or_si128(_mm_or_si128(_mm_and_si128(fin32, _mm_set1_epi32(PV_FINITE)),
                                      _mm_and_si128(ok32, _mm_set1_epi32(PV_PROJECTED))),
                         _mm_or_si128(_mm_and_si128(ready, _mm_set1_epi32(PV_READY)), _mm_slli_epi32(oc32, 8)));
    o->x = _mm_and_si128(rx, ok32), o->y = _mm_and_si128(ry, ok32), o->z = _mm_and_si128(zf, ok32);
    o->iw = (__m256d)((v4q)iw & ok);
}

/* rs_project_vertex for the four vertices v[0..4): proj4's lanes transposed into the records. */
static void project4(const rs_job *j, const rs_vertex *v, rs_pvert *out)
{
    proj4_lanes o;
    proj4(j, v, true, &o);
    char *const dst[4] = { (char *)&out[0], (char *)&out[1], (char *)&out[2], (char *)&out[3] };
    _Static_assert(offsetof(rs_pvert, y) == 4 && offsetof(rs_pvert, z) == 8 && offsetof(rs_pvert, flags) == 12 &&
                   offsetof(rs_pvert, oc) == 13 && offsetof(rs_pvert, iw) == 16, "rs_pvert's layout as project4 writes it");
    store_t32(_mm_castsi128_ps(o.x), _mm_castsi128_ps(o.y), _mm_castsi128_ps(o.z), _mm_castsi128_ps(o.fl), dst,
              0);   /* little endian: flags, oc */
    __m128d w01 = _mm256_castpd256_pd128(o.iw), w23 = _mm256_extractf128_pd(o.iw, 1);
    _mm_storel_pd(&out[0].iw, w01), _mm_storeh_pd(&out[1].iw, w01);
    _mm_storel_pd(&out[2].iw, w23), _mm_storeh_pd(&out[3].iw, w23);
}
#endif

void RS_KERNEL(rs_project_vertices)(const rs_job *j, const rs_vertex *v, size_t n, rs_pvert *out)
{
    size_t i = 0;
#ifdef __AVX2__
    for (; i + 4 <= n; i += 4) project4(j, v + i, out + i);
#endif
    for (; i < n; i++) RS_KERNEL(rs_project_vertex)(j, &v[i], &out[i]);
}

/* Set up triangle k[0..3) of the shared pass when some vertex is not `ready` or the fill mode is not solid: the
 * same outcome as rs_setup_triangle, which it falls back to when a vertex is not finite or the triangle needs
 * clipping. */
static void setup_triangle_checked(const rs_job *j, rs_chunk *c, const uint32_t *k)
{
    const rs_pvert *a = &j->pv[k[0]], *b = &j->pv[k[1]], *d = &j->pv[k[2]];
    const rs_vertex *const v[3] = { &j->verts[k[0]], &j->verts[k[1]], &j->verts[k[2]] };
    if (!(a->flags & b->flags & d->flags & PV_FINITE) || ((a->oc | b->oc | d->oc) && !(a->oc & b->oc & d->oc))) {
        rs_setup_triangle(j, c, v);
        return;
    }
    if (a->oc & b->oc & d->oc) { c->clipped++; return; }
    if (!(a->flags & b->flags & d->flags & PV_PROJECTED)) { c->clipped++; return; }
    rs_svert pv[3] = { svert_of(a, v[0]->attr), svert_of(b, v[1]->attr), svert_of(d, v[2]->attr) };
    rs_finish_triangle(j, c, v, pv, 3);
}

/* A front-facing triangle pushed by push_front, waiting for its edges and planes: its primitive's index in the
 * chunk and its vertex records in clockwise order. */
typedef struct queued {
    const rs_pvert *v[3];
    size_t prim;
} queued;

/* The job's constants of tri_box. */
typedef struct box_consts {
#ifdef __AVX2__
    __m128i off, lo, hi;   /* added to (min x, min y, max x, max y); the clamps below and above */
#else
    int unused;
#endif
} box_consts;

/* tri_box's constants for job j. */
static box_consts box_consts_of(const rs_job *j)
{
    box_consts b;
    /* tri_box's int32 sums: 0 <= cx, cy < RS_MAX_SIZE * 256 = 2^22 (the viewport's centre), omax <= 96 */
    RS_ASSERT(j->cx >= 0 && j->cx < (1 << 22) && j->cy >= 0 && j->cy < (1 << 22) && j->omax >= 0 && j->omax <= 96);
#ifdef __AVX2__
    int32_t cx = (int32_t)j->cx, cy = (int32_t)j->cy;
    b.off = _mm_setr_epi32(cx - j->omax, cy - j->omax, cx + j->omax, cy + j->omax);
    b.lo = _mm_setr_epi32(j->sx0, j->sy0, INT32_MIN, INT32_MIN);
    b.hi = _mm_setr_epi32(INT32_MAX, INT32_MAX, j->sx1 - 1, j->sy1 - 1);
#else
    b.unused = 0;
#endif
    return b;
}

/* The pixel box of setup.c's emit_front for the triangle with vertex records v[0..3): x0, y0, x1, y1 into box;
 * false when it is empty. */
static inline bool tri_box(const rs_job *j, const box_consts *bc, const rs_pvert *const v[3], int32_t box[4])
{
#ifdef __AVX2__
    /* rs_pixel_range in int32 lanes (x0, y0, x1, y1): |coordinate| <= 2^22, 0 <= cx, cy < RS_MAX_SIZE * 256 = 2^22
     * and omax <= 96 (asserted in box_consts_of), so the sums stay below 2^24; ceil(u / 256) = -((-u) >> 8) on the
     * first two lanes, floor on the last two */
    __m128i a = _mm_loadu_si128((const __m128i *)v[0]), b = _mm_loadu_si128((const __m128i *)v[1]);
    __m128i d = _mm_loadu_si128((const __m128i *)v[2]);
    __m128i mn = _mm_min_epi32(_mm_min_epi32(a, b), d), mx = _mm_max_epi32(_mm_max_epi32(a, b), d);
    __m128i u = _mm_add_epi32(_mm_unpacklo_epi64(mn, mx), bc->off);
    const __m128i neg = _mm_setr_epi32(-1, -1, 1, 1);
    __m128i r = _mm_sign_epi32(_mm_srai_epi32(_mm_sign_epi32(u, neg), RS_SUB_BITS), neg);
    r = _mm_min_epi32(_mm_max_epi32(r, bc->lo), bc->hi);
    _mm_storeu_si128((__m128i *)box, r);
    __m128i gt = _mm_cmpgt_epi32(r, _mm_shuffle_epi32(r, _MM_SHUFFLE(1, 0, 3, 2)));   /* x0 > x1, y0 > y1 */
    return (_mm_movemask_ps(_mm_castsi128_ps(gt)) & 3) == 0;
#else
    (void)bc;
    int64_t mnx = v[0]->x, mxx = v[0]->x, mny = v[0]->y, mxy = v[0]->y;
    for (int i = 1; i < 3; i++) {
        mnx = v[i]->x < mnx ? v[i]->x : mnx; mxx = v[i]->x > mxx ? v[i]->x : mxx;
        mny = v[i]->y < mny ? v[i]->y : mny; mxy = v[i]->y > mxy ? v[i]->y : mxy;
    }
    rs_pixel_range(j, mnx + j->cx, mxx + j->cx, j->sx0, j->sx1, &box[0], &box[2]);
    rs_pixel_range(j, mny + j->cy, mxy + j->cy, j->sy0, j->sy1, &box[1], &box[3]);
    return box[0] <= box[2] && box[1] <= box[3];
#endif
}

/* Push triangle v[0..3) (clockwise, records of vertices id[0..3)) with emit_front's pixel box, kind and slots,
 * its edges and planes left to finish_queued; false (nothing pushed) when the box is empty or memory ran out. */
static bool push_front(const rs_job *j, rs_chunk *c, const box_consts *bc, const rs_pvert *const v[3],
                       const uint32_t id[3], int64_t area)
{
    int32_t box[4];
    if (!tri_box(j, bc, v, box)) return false;
    float *at;
    rs_prim *p = rs_push_raw(j, c, &at);
    if (!p) return false;
    rs_count_work(c, area, box[0], box[1], box[2], box[3]);
    c->ptile[c->n - 1] = rs_tile_entry(j, box[0], box[1], box[2], box[3]);
    _Static_assert(offsetof(rs_prim, y0) == 4 && offsetof(rs_prim, x1) == 8 && offsetof(rs_prim, y1) == 12,
                   "rs_prim's box as tri_box writes it");
    memcpy(&p->x0, box, sizeof box);
    p->kind = RS_K_TRI;
    const rs_vec4 *a0 = j->verts[id[0]].attr, *a1 = j->verts[id[1]].attr, *a2 = j->verts[id[2]].attr;
    if (j->flat) rs_fill_attr(j, at, a0, a1, a2, a0);
    else for (int s = 0; s < j->n_slots; s++) rs_fill_slot(at + s * RS_ATTR_STRIDE, &a0[j->slot[s]], &a1[j->slot[s]],
                                                            &a2[j->slot[s]]);
    return true;
}

/* Edges, vertex 0 and planes of queued triangle q, one at a time: emit_front's rs_tri_edges and rs_tri_planes
 * (setup.c). */
static void finish_one(const rs_job *j, rs_prim *prims, const queued *q)
{
    rs_svert pv[3] = { svert_of(q->v[0], NULL), svert_of(q->v[1], NULL), svert_of(q->v[2], NULL) };
    const rs_svert *const v[3] = { &pv[0], &pv[1], &pv[2] };
    rs_tri *t = &prims[q->prim].u.t;
    rs_tri_edges(v, t);
    t->vx = q->v[0]->x;
    t->vy = q->v[0]->y;
    int64_t area = (pv[1].x - pv[0].x) * (pv[2].y - pv[0].y) - (pv[1].y - pv[0].y) * (pv[2].x - pv[0].x);
    rs_tri_planes(j, v, area, t);
}

#ifdef __AVX2__
/* Vertex s of four queued triangles in lanes: x, y (int32) and z (float) from the first 16 bytes of each record. */
static inline void gather4(const queued *q, int s, __m128i *x, __m128i *y, __m128 *z)
{
    __m128i r0 = _mm_loadu_si128((const __m128i *)q[0].v[s]), r1 = _mm_loadu_si128((const __m128i *)q[1].v[s]);
    __m128i r2 = _mm_loadu_si128((const __m128i *)q[2].v[s]), r3 = _mm_loadu_si128((const __m128i *)q[3].v[s]);
    __m128i t0 = _mm_unpacklo_epi32(r0, r1), t1 = _mm_unpacklo_epi32(r2, r3);  /* x0 x1 y0 y1, x2 x3 y2 y3 */
    __m128i t2 = _mm_unpackhi_epi32(r0, r1), t3 = _mm_unpackhi_epi32(r2, r3);  /* z0 z1 f0 f1, z2 z3 f2 f3 */
    *x = _mm_unpacklo_epi64(t0, t1);
    *y = _mm_unpackhi_epi64(t0, t1);
    *z = _mm_castsi128_ps(_mm_unpacklo_epi64(t2, t3));
}

/* rs_tri_edge of edge i -> k of four triangles, the same integer values: ea, eb in int32 lanes, ec in int64 lanes.
 * The inputs are int32 lanes (|x|, |y| <= 2^22, so the differences fit int32 and the products, by mul_epi32,
 * int64). */
static inline void edge4(__m128i xi, __m128i yi, __m128i xk, __m128i yk, __m128i *ea, __m128i *eb, __m256i *ec)
{
    const __m128i zero = _mm_setzero_si128();
    __m128i dx = _mm_sub_epi32(xk, xi), dy = _mm_sub_epi32(yk, yi);
    __m128i tl = _mm_or_si128(_mm_cmpgt_epi32(zero, dy),                    /* top_left: -1, else 0 */
                              _mm_and_si128(_mm_cmpeq_epi32(dy, zero), _mm_cmpgt_epi32(dx, zero)));
    *ea = _mm_sub_epi32(zero, dy);
    *eb = dx;
    __m256i a = _mm256_cvtepi32_epi64(*ea), b = _mm256_cvtepi32_epi64(dx);
    __m256i s = _mm256_add_epi64(_mm256_mul_epi32(a, _mm256_cvtepi32_epi64(xi)),
                                 _mm256_mul_epi32(b, _mm256_cvtepi32_epi64(yi)));   /* -dy * x + dx * y */
    /* -s - (top_left ? 0 : 1) = -s - 1 - tl */
    *ec = _mm256_sub_epi64(_mm256_sub_epi64(_mm256_sub_epi64(_mm256_setzero_si256(), s), _mm256_set1_epi64x(1)),
                           _mm256_cvtepi32_epi64(tl));
}

/* |x| per lane. */
static inline v4d abs4(v4d x) { return (v4d)((v4q)x & ~(v4q)(v4d){ -0.0, -0.0, -0.0, -0.0 }); }

/* dmax per lane for a, b not NaN: a where a > b, else b (maxpd; dmax's NaN case cannot arise in finish4_lanes). */
static inline v4d max4(v4d a, v4d b) { return (v4d)_mm256_max_pd((__m256d)a, (__m256d)b); }

/* Store rows r0..r3 of a 4x4 matrix of int64 transposed: column t (lane t of every row) to base[t] + off. */
static inline void store_t64(__m256i r0, __m256i r1, __m256i r2, __m256i r3, char *const base[4], size_t off)
{
    __m256i a = _mm256_unpacklo_epi64(r0, r1), b = _mm256_unpackhi_epi64(r0, r1);   /* 00 10 02 12, 01 11 03 13 */
    __m256i c = _mm256_unpacklo_epi64(r2, r3), d = _mm256_unpackhi_epi64(r2, r3);   /* 20 30 22 32, 21 31 23 33 */
    _mm256_storeu_si256((__m256i *)(base[0] + off), _mm256_permute2x128_si256(a, c, 0x20));
    _mm256_storeu_si256((__m256i *)(base[1] + off), _mm256_permute2x128_si256(b, d, 0x20));
    _mm256_storeu_si256((__m256i *)(base[2] + off), _mm256_permute2x128_si256(a, c, 0x31));
    _mm256_storeu_si256((__m256i *)(base[3] + off), _mm256_permute2x128_si256(b, d, 0x31));
}

/* The job's depth bias and slope-scale depth bias as doubles in lanes (rs_tri_planes' (double) conversions). */
typedef struct bias4 { v4d depth, slope; } bias4;

/* bias4 of job j. */
static inline bias4 bias4_of(const rs_job *j)
{
    const double d = (double)j->st->depth_bias, s = (double)j->st->slope_scale_depth_bias;
    return (bias4){ { d, d, d, d }, { s, s, s, s } };
}

/* rs_tri_edges and vertex 0 of four triangles, one per lane, from their vertices in lanes (x, y int32, in clockwise
 * order) into the rs_tri at tr[0..4): rs_tri_edge's integer operations in int32 / int64 lanes, the same values. */
static inline __attribute__((always_inline)) void finish4_edges(const __m128i x[3], const __m128i y[3],
                                                                char *const tr[4])
{
    __m128i ea[3], eb[3];
    __m256i ec[3];
    edge4(x[0], y[0], x[1], y[1], &ea[0], &eb[0], &ec[0]);
    edge4(x[1], y[1], x[2], y[2], &ea[1], &eb[1], &ec[1]);
    edge4(x[2], y[2], x[0], y[0], &ea[2], &eb[2], &ec[2]);
    _Static_assert(offsetof(rs_tri, eb) == 12 && offsetof(rs_tri, ec) == 24 && offsetof(rs_tri, vx) == 48 &&
                   offsetof(rs_tri, vy) == 52 && offsetof(rs_tri, z) == 56 && offsetof(rs_tri, q1) == 68 &&
                   offsetof(rs_tri, q2) == 80 && offsetof(rs_tri, s) == 92 && sizeof(rs_tri) == 104,
                   "rs_tri's layout as finish4 writes it");
    /* rs_tri in groups of 16, 8, 32, 16, 16 and 16 bytes (the planes: finish4_planes) */
    store_t32(_mm_castsi128_ps(ea[0]), _mm_castsi128_ps(ea[1]), _mm_castsi128_ps(ea[2]), _mm_castsi128_ps(eb[0]), tr,
              offsetof(rs_tri, ea));                                       /* ea[0..3), eb[0] */
    __m128i e12lo = _mm_unpacklo_epi32(eb[1], eb[2]), e12hi = _mm_unpackhi_epi32(eb[1], eb[2]); /* eb[1], eb[2] */
    const size_t b1 = offsetof(rs_tri, eb[1]);
    _mm_storel_epi64((__m128i *)(tr[0] + b1), e12lo);
    _mm_storel_epi64((__m128i *)(tr[1] + b1), _mm_unpackhi_epi64(e12lo, e12lo));
    _mm_storel_epi64((__m128i *)(tr[2] + b1), e12hi);
    _mm_storel_epi64((__m128i *)(tr[3] + b1), _mm_unpackhi_epi64(e12hi, e12hi));
    __m256i vxy = _mm256_setr_m128i(_mm_unpacklo_epi32(x[0], y[0]), _mm_unpackhi_epi32(x[0], y[0]));
    store_t64(ec[0], ec[1], ec[2], vxy, tr, offsetof(rs_tri, ec));         /* ec[0..3), vx and vy */
}

/* rs_tri_planes of the four triangles of finish4_edges (zf float, w0..w2 the 1/w of vertices 0..2; the job's
 * bias4) into tr[0..4):
 * its double operations in double lanes, per lane the same operations in the same order, so the same bytes.  No
 * value is NaN: the vertices are ready (0 <= z <= w, w > 0, 1/w finite), so the 1/w are finite and positive and
 * za, zb finite (|area| >= 1: |l1a| etc. below 2^31), and max4 is dmax. */
static inline __attribute__((always_inline)) void finish4_planes(const bias4 *bs, const __m128i x[3],
                                                                 const __m128i y[3], const __m128 zf[3], v4d w0,
                                                                 v4d w1, v4d w2, const __m256d *live,
                                                                 char *const tr[4])
{
    /* rs_tri_planes: the differences are exact in int32 and in double; so is the doubled area, products of
     * integers below 2^23 and their difference below 2^47 being integers below 2^53, the value (double)area2 */
    const double k = 1.0 / RS_SUB;
    v4d dx1 = (v4d)_mm256_cvtepi32_pd(_mm_sub_epi32(x[1], x[0])), dy1 = (v4d)_mm256_cvtepi32_pd(_mm_sub_epi32(y[1], y[0]));
    v4d dx2 = (v4d)_mm256_cvtepi32_pd(_mm_sub_epi32(x[2], x[0])), dy2 = (v4d)_mm256_cvtepi32_pd(_mm_sub_epi32(y[2], y[0]));
    v4d area = dx1 * dy2 - dy1 * dx2;
    const __m256d one = _mm256_set1_pd(1.0);
    if (live) area = (v4d)_mm256_blendv_pd(one, (__m256d)area, *live);   /* (see grid_finish_half) */
    v4d x1 = dx1 * k, y1 = dy1 * k, x2 = dx2 * k, y2 = dy2 * k;
    v4d ar = 1.0 / (area * k * k);
    v4d l1a = y2 * ar, l1b = -x2 * ar, l2a = -y1 * ar, l2b = x1 * ar;
    v4d z0 = (v4d)_mm256_cvtps_pd(zf[0]);
    v4d dz1 = (v4d)_mm256_cvtps_pd(zf[1]) - z0, dz2 = (v4d)_mm256_cvtps_pd(zf[2]) - z0;
    v4d za = dz1 * l1a + dz2 * l2a, zb = dz1 * l1b + dz2 * l2b;
    v4d bias = bs->depth + bs->slope * max4(abs4(za), abs4(zb));
    v4d m = max4(w0, max4(w1, w2));
    if (live) m = (v4d)_mm256_blendv_pd(one, (__m256d)m, *live);
    v4d n0 = w0 / m, n1 = w1 / m, n2 = w2 / m;
    v4d s0 = (n1 - n0) * l1a + (n2 - n0) * l2a, s1 = (n1 - n0) * l1b + (n2 - n0) * l2b;
#define F4(v) _mm256_cvtpd_ps((__m256d)(v))
    const __m128 zero = _mm_setzero_ps();
    /* z[0..3), q1[0] | q1[1..3), q2[0..2): 32 bytes per triangle, two 4x4 transposes side by side */
    const __m256 r0 = _mm256_setr_m128(F4(za), F4(n1 * l1b)), r1 = _mm256_setr_m128(F4(zb), zero);
    const __m256 r2 = _mm256_setr_m128(F4(z0 + bias), F4(n2 * l2a)), r3 = _mm256_setr_m128(F4(n1 * l1a), F4(n2 * l2b));
    const __m256d a = _mm256_castps_pd(_mm256_unpacklo_ps(r0, r1)), b = _mm256_castps_pd(_mm256_unpackhi_ps(r0, r1));
    const __m256d c = _mm256_castps_pd(_mm256_unpacklo_ps(r2, r3)), d = _mm256_castps_pd(_mm256_unpackhi_ps(r2, r3));
    _mm256_storeu_pd((double *)(tr[0] + offsetof(rs_tri, z)), _mm256_unpacklo_pd(a, c));
    _mm256_storeu_pd((double *)(tr[1] + offsetof(rs_tri, z)), _mm256_unpackhi_pd(a, c));
    _mm256_storeu_pd((double *)(tr[2] + offsetof(rs_tri, z)), _mm256_unpacklo_pd(b, d));
    _mm256_storeu_pd((double *)(tr[3] + offsetof(rs_tri, z)), _mm256_unpackhi_pd(b, d));
    store_t32(zero, F4(s0), F4(s1), F4(n0), tr, offsetof(rs_tri, q2[2]));              /* q2[2], s[0..3) */
#undef F4
}

/* finish_one for four triangles, one per lane (finish4_edges, then finish4_planes: fewer values live in registers
 * at once), the same bytes. */
static inline __attribute__((always_inline)) void finish4_lanes(const rs_job *j, const __m128i x[3],
                                                                const __m128i y[3], const __m128 zf[3], v4d w0,
                                                                v4d w1, v4d w2, char *const tr[4])
{
    finish4_edges(x, y, tr);
    const bias4 b = bias4_of(j);
    finish4_planes(&b, x, y, zf, w0, w1, w2, NULL, tr);
}

/* finish_one for queued triangles q[0..n) (room for 4; lanes n..3 repeat q[0]), one per lane (finish4_lanes). */
static void finish4(const rs_job *j, rs_prim *prims, queued q[4], int n)
{
    for (int t = n; t < 4; t++) q[t] = q[0];
    __m128i x[3], y[3];
    __m128 zf[3];
    gather4(q, 0, &x[0], &y[0], &zf[0]);   /* (unrolled by hand: gcc keeps loops over these arrays in memory) */
    gather4(q, 1, &x[1], &y[1], &zf[1]);
    gather4(q, 2, &x[2], &y[2], &zf[2]);
    v4d w0 = { q[0].v[0]->iw, q[1].v[0]->iw, q[2].v[0]->iw, q[3].v[0]->iw };
    v4d w1 = { q[0].v[1]->iw, q[1].v[1]->iw, q[2].v[1]->iw, q[3].v[1]->iw };
    v4d w2 = { q[0].v[2]->iw, q[1].v[2]->iw, q[2].v[2]->iw, q[3].v[2]->iw };
    /* the stores: lanes t >= n repeat lane 0's values into q[0]'s primitive, the same bytes */
    char *const tr[4] = { (char *)&prims[q[0].prim].u.t, (char *)&prims[q[1].prim].u.t,
                          (char *)&prims[q[2].prim].u.t, (char *)&prims[q[3].prim].u.t };
    finish4_lanes(j, x, y, zf, w0, w1, w2, tr);
}
#endif

/* Edges and planes of queued triangles q[0..n) (n <= 4; q has room for 4) into prims[q[t].prim]: in lanes, or one
 * by one when alone. */
static void finish_queued(const rs_job *j, rs_prim *prims, queued q[4], int n)
{
#ifdef __AVX2__
    if (n > 1) {
        finish4(j, prims, q, n);
        return;
    }
#endif
    for (int t = 0; t < n; t++) finish_one(j, prims, &q[t]);
}

/* Are the records a, b, d all PV_READY? */
static inline bool ready3(const rs_pvert *a, const rs_pvert *b, const rs_pvert *d)
{
#ifdef __AVX2__
    __m128i h = _mm_and_si128(_mm_and_si128(_mm_loadu_si128((const __m128i *)a), _mm_loadu_si128((const __m128i *)b)),
                              _mm_loadu_si128((const __m128i *)d));   /* the same loads as area3 and tri_box */
    return _mm_extract_epi32(h, 3) & PV_READY;
#else
    return a->flags & b->flags & d->flags & PV_READY;
#endif
}

/* Doubled signed area of the triangle of records a, b, d, as rs_finish_triangle's poly_area computes it: the
 * differences (below 2^23) are exact in int32, their products in int64. */
static inline int64_t area3(const rs_pvert *a, const rs_pvert *b, const rs_pvert *d)
{
#ifdef __AVX2__
    __m128i ha = _mm_loadu_si128((const __m128i *)a);
    __m128i e1 = _mm_sub_epi32(_mm_loadu_si128((const __m128i *)b), ha);   /* dx1 dy1 - - */
    __m128i e2 = _mm_sub_epi32(_mm_loadu_si128((const __m128i *)d), ha);   /* dx2 dy2 - - */
    __m128i p = _mm_mul_epi32(_mm_shuffle_epi32(e1, _MM_SHUFFLE(1, 1, 0, 0)),
                              _mm_shuffle_epi32(e2, _MM_SHUFFLE(0, 0, 1, 1)));   /* dx1 dy2, dy1 dx2 */
    return _mm_cvtsi128_si64(_mm_sub_epi64(p, _mm_unpackhi_epi64(p, p)));
#else
    return (int64_t)(b->x - a->x) * (d->y - a->y) - (int64_t)(b->y - a->y) * (d->x - a->x);
#endif
}

/* Set up the shared pass's triangles of chunk c (indices j->idx into the records j->pv): per triangle what
 * rs_setup_triangle gives.  A ready, solid, front-facing triangle is pushed with its box and slots at once, in
 * submission order, and queued; its edges and planes are written four triangles at a time (finish_queued). */
void RS_KERNEL(rs_setup_shared)(const rs_job *j, rs_chunk *c)
{
    const rs_pvert *pv = j->pv;
    const uint32_t *idx = j->idx;
    queued q[4];
    int nq = 0;
    bool solid = j->st->fill_mode == RS_FILL_SOLID;
    bool cull_neg = j->st->cull_mode == RS_CULL_CCW, cull_pos = j->st->cull_mode == RS_CULL_CW;
    uint64_t culled = 0, degenerate = 0, drawn = 0;
    box_consts bc = box_consts_of(j);
    for (size_t k = c->first; k < c->first + c->count; k++) {
        const uint32_t *id = &idx[3 * k];
        const rs_pvert *a = &pv[id[0]], *b = &pv[id[1]], *d = &pv[id[2]];
        if (!ready3(a, b, d) || !solid) {
            setup_triangle_checked(j, c, id);
            if (c->oom) break;
            continue;
        }
        /* rs_finish_triangle and setup.c's emit_polygon for a solid unclipped triangle */
        int64_t area = area3(a, b, d);
        if (area == 0) { degenerate++; continue; }
        if ((cull_neg && area < 0) || (cull_pos && area > 0)) { culled++; continue; }
        drawn++;
        const rs_pvert *const v[3] = { a, area > 0 ? b : d, area > 0 ? d : b };   /* emit_tri, area known */
        const uint32_t ov[3] = { id[0], area > 0 ? id[1] : id[2], area > 0 ? id[2] : id[1] };
        size_t prim = c->n;
        if (!push_front(j, c, &bc, v, ov, area)) {
            if (c->oom) break;
            continue;
        }
        q[nq++] = (queued){ { v[0], v[1], v[2] }, prim };
        if (nq == 4) finish_queued(j, c->prims, q, nq), nq = 0;
    }
    finish_queued(j, c->prims, q, nq);
    c->culled += culled, c->degenerate += degenerate, c->drawn += drawn;
}

/* ---- grouped pieces (raster_internal.h): one bin entry per group, its triangles set up inside the tile pass ---- */

/* rs_setup_shared's decision for the ready triangle of indices id[0..3) into records pv: 0 degenerate, -1 culled,
 * else 1 with its records in clockwise order in v, their indices in ov and its doubled area in *area. */
static inline int group_tri(const rs_pvert *pv, const uint32_t *id, bool cull_neg, bool cull_pos,
                            const rs_pvert *v[3], uint32_t ov[3], int64_t *area)
{
    const rs_pvert *a = &pv[id[0]], *b = &pv[id[1]], *d = &pv[id[2]];
    const int64_t ar = area3(a, b, d);
    if (ar == 0) return 0;
    if ((cull_neg && ar < 0) || (cull_pos && ar > 0)) return -1;
    v[0] = a, v[1] = ar > 0 ? b : d, v[2] = ar > 0 ? d : b;   /* emit_tri, area known */
    ov[0] = id[0], ov[1] = ar > 0 ? id[1] : id[2], ov[2] = ar > 0 ? id[2] : id[1];
    *area = ar;
    return 1;
}

/* Keep the slots of piece v[0..nv) in chunk c and make room for np drawn triangles; false when out of memory
 * (c->oom set). */
static bool group_keep(const rs_job *j, rs_chunk *c, const rs_vertex *v, size_t nv, size_t np)
{
    const size_t ns = (size_t)j->n_slots;
    if (!rs_reserve((void **)&c->gattr, &c->gattr_cap, nv * ns + 1, sizeof(rs_vec4)) ||
        !rs_reserve((void **)&c->gtri, &c->gtri_cap, np, sizeof(rs_gtri))) {
        c->oom = true;
        return false;
    }
    if (ns == 1) {   /* (the usual case, COLOR0 alone: one copy per vertex) */
        const int s0 = j->slot[0];
        rs_vec4 *const ga = c->gattr;
        size_t i = 0;
        for (; i + 4 <= nv; i += 4)   /* (four per pass: half the loop's instructions) */
            ga[i] = v[i].attr[s0], ga[i + 1] = v[i + 1].attr[s0], ga[i + 2] = v[i + 2].attr[s0],
            ga[i + 3] = v[i + 3].attr[s0];
        for (; i < nv; i++) ga[i] = v[i].attr[s0];
        return true;
    }
    for (size_t i = 0; i < nv; i++)
        for (size_t s = 0; s < ns; s++) c->gattr[i * ns + s] = v[i].attr[j->slot[s]];
    return true;
}

/* Push group entry of drawn triangles [first, first + n) of c->gtri (level 0), or of grid level `level` over the
 * vertices from vbase with its row and step boxes at c->grow[first .. first + n), with pixel box u into chunk c; false when
 * out of memory. */
static bool group_push(const rs_job *j, rs_chunk *c, const int32_t u[4], size_t first, size_t n, size_t level,
                       size_t vbase)
{
    float *at;
    rs_prim *p = rs_push_raw(j, c, &at);
    if (!p) return false;
    c->ptile[c->n - 1] = rs_tile_entry(j, u[0], u[1], u[2], u[3]);
    p->x0 = u[0], p->y0 = u[1], p->x1 = u[2], p->y1 = u[3];
    p->kind = RS_K_GROUP, p->back = 0;
    p->u.g = (rs_group){ (uint32_t)first, (uint32_t)n, (uint32_t)level, (uint32_t)vbase };
    return true;
}

/* Groups whose box meets more tiles than this are set up per triangle (rs_setup_shared's records): the tile pass
 * would test each of their triangles in every tile and set up those over two tiles twice (scene A, large patches:
 * +16 % instructions per frame when every instance was grouped). */
#define GROUP_MAX_TILES 4

/* The tiles of job j pixel box u meets. */
static inline size_t box_tiles(const rs_job *j, const int32_t u[4])
{
    const int b = j->tile_bits;
    return (size_t)((u[2] >> b) - (u[0] >> b) + 1) * (size_t)((u[3] >> b) - (u[1] >> b) + 1);
}

/* Culled, degenerate and drawn triangles, counted. */
typedef struct tri_counts { uint64_t culled, degenerate, drawn; } tri_counts;

/* Set up triangles [g0, g0 + n) of the piece (indices idx into c->gpv, slots of j->verts) per triangle into chunk
 * c as rs_setup_shared does, counting into *tc those from `from` on (the earlier ones are counted); queue q (nq
 * entries) carries over.  False when out of memory. */
static bool group_as_triangles(const rs_job *j, rs_chunk *c, const box_consts *bc, const uint32_t *idx, size_t g0,
                               size_t n, size_t from, tri_counts *tc, queued q[4], int *nq)
{
    const rs_pvert *pv = c->gpv;
    const bool cull_neg = j->st->cull_mode == RS_CULL_CCW, cull_pos = j->st->cull_mode == RS_CULL_CW;
    for (size_t k = g0; k < g0 + n; k++) {
        const rs_pvert *tv[3];
        uint32_t ov[3];
        int64_t area;
        const int r = group_tri(pv, &idx[3 * k], cull_neg, cull_pos, tv, ov, &area);
        if (k >= from) tc->degenerate += r == 0, tc->culled += r < 0, tc->drawn += r > 0;
        if (r <= 0) continue;
        const size_t prim = c->n;
        if (!push_front(j, c, bc, tv, ov, area)) {
            if (c->oom) return false;
            continue;
        }
        q[(*nq)++] = (queued){ { tv[0], tv[1], tv[2] }, prim };
        if (*nq == 4) finish_queued(j, c->prims, q, *nq), *nq = 0;
    }
    return true;
}

/* ---- grid rows (raster_internal.h, grid groups): a grid group set up from its vertex rows, no index list ----
 *
 * Bit budget: vertices satisfy |x|, |y| <= 2^22 (setup.c); a grid group takes the row path only when its vertices
 * span less than 2^15 (1/256 px: 128 px) in x and in y (grid_extent_ok), so every vertex difference is below 2^15
 * in magnitude, each product of two below 2^30 and the doubled area, a difference of two products, below 2^31:
 * exact in int32 lanes (vpmulld), the same value as area3's int64.  The pixel boxes are tri_box's int32 sums
 * (below 2^24).  A triangle's box is at most 130 x 130 pixels, its work units (130^2 * 2^17 < 2^32) and |area|
 * (< 2^31) compare as uint32.  The edges' ec and the planes are finish4_lanes': int64 and double lanes. */
#ifdef __AVX2__

/* The rows of a grid piece in chunk c (c->gsoa): 1/w, x, y and z of each vertex, gsoa_cap entries each. */
typedef struct grid_cols {
    const double *w;
    const int32_t *x, *y;
    const float *z;
} grid_cols;

/* grid_cols of chunk c's gsoa. */
static inline grid_cols grid_cols_of(const rs_chunk *c)
{
    const double *w = c->gsoa;
    const int32_t *x = (const int32_t *)(w + c->gsoa_cap);
    return (grid_cols){ w, x, x + c->gsoa_cap, (const float *)(x + 2 * c->gsoa_cap) };
}

/* Project v[0..nv) (rs_project_vertices' values: proj4's lanes) straight into chunk c's rows (gsoa) with
 * RS_GRID_PAD zeros after them, and their flags' PV_READY ANDed into *all -- no records (rs_setup_groups makes them
 * only when a path that reads them comes up; the rows are read only when every vertex is ready); false (nothing
 * ANDed) when out of memory. */
static bool grid_rows_project(const rs_job *j, rs_chunk *c, const rs_vertex *v, size_t nv, unsigned *all)
{
    const size_t n = nv + RS_GRID_PAD, each = sizeof(double) + 2 * sizeof(int32_t) + sizeof(float);
    if (!rs_reserve(&c->gsoa, &c->gsoa_cap, n, each)) return false;   /* (all rewritten below) */
    const grid_cols g = grid_cols_of(c);
    double *w = (double *)g.w;
    int32_t *x = (int32_t *)g.x, *y = (int32_t *)g.y;
    float *z = (float *)g.z;
    size_t i = 0;
    v4q ready = { -1, -1, -1, -1 };   /* per lane: every vertex so far PV_READY */
    for (; i + 4 <= nv; i += 4) {
        proj4_lanes o;
        proj4(j, v + i, false, &o);
        _mm_storeu_si128((__m128i *)(x + i), o.x), _mm_storeu_si128((__m128i *)(y + i), o.y);
        _mm_storeu_si128((__m128i *)(z + i), o.z), _mm256_storeu_pd(w + i, o.iw);
        ready &= o.ready;
    }
    unsigned f = _mm256_movemask_pd((__m256d)ready) == 15 ? PV_READY : 0u;
    for (; i < nv; i++) {
        rs_pvert r;
        RS_KERNEL(rs_project_vertex)(j, &v[i], &r);
        w[i] = r.iw, x[i] = r.x, y[i] = r.y, z[i] = r.z, f &= r.flags;
    }
    for (; i < n; i++) w[i] = 0.0, x[i] = 0, y[i] = 0, z[i] = 0.0f;
    *all &= f;
    return true;
}

/* Do the vertices [v0, v0 + n) of rows g span less than 2^15 in x and in y (the bit budget above)? */
static bool grid_extent_ok(const grid_cols *g, size_t v0, size_t n)
{
    __m256i mnx = _mm256_set1_epi32(INT32_MAX), mny = mnx, mxx = _mm256_set1_epi32(INT32_MIN), mxy = mxx;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m256i x = _mm256_loadu_si256((const __m256i *)(g->x + v0 + i));
        const __m256i y = _mm256_loadu_si256((const __m256i *)(g->y + v0 + i));
        mnx = _mm256_min_epi32(mnx, x), mxx = _mm256_max_epi32(mxx, x);
        mny = _mm256_min_epi32(mny, y), mxy = _mm256_max_epi32(mxy, y);
    }
    int32_t a[8], b[8], cc[8], d[8];
    _mm256_storeu_si256((__m256i *)a, mnx), _mm256_storeu_si256((__m256i *)b, mxx);
    _mm256_storeu_si256((__m256i *)cc, mny), _mm256_storeu_si256((__m256i *)d, mxy);
    int64_t x0 = INT32_MAX, x1 = INT32_MIN, y0 = INT32_MAX, y1 = INT32_MIN;
    for (int k = 0; k < 8; k++) {
        x0 = a[k] < x0 ? a[k] : x0, x1 = b[k] > x1 ? b[k] : x1;
        y0 = cc[k] < y0 ? cc[k] : y0, y1 = d[k] > y1 ? d[k] : y1;
    }
    for (; i < n; i++) {
        const int64_t x = g->x[v0 + i], y = g->y[v0 + i];
        x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1, y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
    }
    return x1 - x0 < (1 << 15) && y1 - y0 < (1 << 15);
}

/* The job's constants of the row steps: tri_box's offsets and clamps, the cull, in int32 lanes. */
typedef struct grid_consts {
    __m256i offx0, offy0, offx1, offy1;   /* cx - omax, cy - omax, cx + omax, cy + omax */
    __m256i sx0, sy0, sx1, sy1;           /* the scissor, inclusive */
    __m256i cull_sign;                    /* -1: negative areas are culled (CCW), 1: positive ones (CW), 0: none */
} grid_consts;

/* grid_consts of job j (box_consts_of asserts tri_box's ranges).  The rows' triangles are the regular list's; a
 * mirrored source's list winds each the other way, so its areas have the other sign: its cull sign is negated. */
static grid_consts grid_consts_of(const rs_job *j)
{
    (void)box_consts_of(j);
    const int32_t cx = (int32_t)j->cx, cy = (int32_t)j->cy;
    const int32_t cull = j->st->cull_mode == RS_CULL_CCW ? -1 : j->st->cull_mode == RS_CULL_CW;
    return (grid_consts){ _mm256_set1_epi32(cx - j->omax), _mm256_set1_epi32(cy - j->omax),
                          _mm256_set1_epi32(cx + j->omax), _mm256_set1_epi32(cy + j->omax),
                          _mm256_set1_epi32(j->sx0), _mm256_set1_epi32(j->sy0), _mm256_set1_epi32(j->sx1 - 1),
                          _mm256_set1_epi32(j->sy1 - 1), _mm256_set1_epi32(j->grid_mirrored ? -cull : cull) };
}

/* tri_box's pixel range of coordinates [mn, mx] (offsets o0, o1) clamped to [lo, hi]: ceil((mn + o0) / 256) and
 * floor((mx + o1) / 256) by arithmetic shifts. */
static inline void grid_range(__m256i mn, __m256i mx, __m256i o0, __m256i o1, __m256i lo, __m256i hi, __m256i *r0,
                              __m256i *r1)
{
    const __m256i zero = _mm256_setzero_si256();
    *r0 = _mm256_max_epi32(_mm256_sub_epi32(zero, _mm256_srai_epi32(_mm256_sub_epi32(zero, _mm256_add_epi32(mn, o0)),
                                                                     RS_SUB_BITS)), lo);
    *r1 = _mm256_min_epi32(_mm256_srai_epi32(_mm256_add_epi32(mx, o1), RS_SUB_BITS), hi);
}

/* Eight consecutive triangles of a grid row in lanes, from its triangle 2i on: lane l is the up triangle (A, B, C)
 * of quad i + l/2 when l is even, its down triangle (B, D, C) when l is odd (A = r0[q], B = r0[q + 1], C = r1[q],
 * D = r1[q + 1]): their vertices in clockwise order (x, y; vertices 1 and 2 swapped where the area is negative, as
 * emit_tri does), doubled areas (area3's), pixel boxes (tri_box's) and drawn mask (in the row: lane below n; area
 * not 0; not culled). */
typedef struct step8 {
    __m256i x[3], y[3], area, pos, x0, y0, x1, y1, in, drawn;
} step8;

/* Lanes (v[0], v[1], v[1], v[2], v[2], v[3], v[3], v[4]), (v[1], u[1], v[2], u[2], .., v[4], u[4]) and (u[0], u[0],
 * u[1], u[1], .., u[3], u[3]) of rows v and u from index 0: vertices 0, 1 and 2 of eight consecutive triangles. */
static inline void grid_verts8(const int32_t *v, const int32_t *u, __m256i o[3])
{
    const __m256i v8 = _mm256_loadu_si256((const __m256i *)v), u8 = _mm256_loadu_si256((const __m256i *)u);
    o[0] = _mm256_permutevar8x32_epi32(v8, _mm256_setr_epi32(0, 1, 1, 2, 2, 3, 3, 4));
    const __m128i a = _mm_loadu_si128((const __m128i *)(v + 1)), b = _mm_loadu_si128((const __m128i *)(u + 1));
    o[1] = _mm256_setr_m128i(_mm_unpacklo_epi32(a, b), _mm_unpackhi_epi32(a, b));
    o[2] = _mm256_permutevar8x32_epi32(u8, _mm256_setr_epi32(0, 0, 1, 1, 2, 2, 3, 3));
}

/* The step at rows r0 (A, B) and r1 (C, D) of g from quad i on, n triangles left in the row, into o: its vertices,
 * areas and drawn mask (the pixel boxes: grid_step8_box). */
static inline __attribute__((always_inline)) void grid_step8_tri(const grid_cols *g, const grid_consts *k, size_t r0,
                                                                 size_t r1, int n, step8 *o)
{
    __m256i x[3], y[3];
    grid_verts8(g->x + r0, g->x + r1, x);
    grid_verts8(g->y + r0, g->y + r1, y);
    /* area3(v0, v1, v2), exact in int32 (the bit budget) */
    const __m256i dx1 = _mm256_sub_epi32(x[1], x[0]), dy1 = _mm256_sub_epi32(y[1], y[0]);
    const __m256i dx2 = _mm256_sub_epi32(x[2], x[0]), dy2 = _mm256_sub_epi32(y[2], y[0]);
    o->area = _mm256_sub_epi32(_mm256_mullo_epi32(dx1, dy2), _mm256_mullo_epi32(dy1, dx2));
    const __m256i zero = _mm256_setzero_si256();
    o->pos = _mm256_cmpgt_epi32(o->area, zero);
    o->x[0] = x[0], o->y[0] = y[0];
    o->x[1] = _mm256_blendv_epi8(x[2], x[1], o->pos), o->x[2] = _mm256_blendv_epi8(x[1], x[2], o->pos);
    o->y[1] = _mm256_blendv_epi8(y[2], y[1], o->pos), o->y[2] = _mm256_blendv_epi8(y[1], y[2], o->pos);
    /* drawn: in the row, area not 0 and not culled (areas of the sign cull_sign are: cull_sign * area > 0) */
    o->in = _mm256_cmpgt_epi32(_mm256_set1_epi32(n), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256i cul = _mm256_cmpgt_epi32(_mm256_sign_epi32(o->area, k->cull_sign), zero);
    o->drawn = _mm256_andnot_si256(_mm256_or_si256(_mm256_cmpeq_epi32(o->area, zero), cul), o->in);
}

/* The pixel boxes of step o (tri_box's, from its vertices). */
static inline __attribute__((always_inline)) void grid_step8_box(const grid_consts *k, step8 *o)
{
    grid_range(_mm256_min_epi32(_mm256_min_epi32(o->x[0], o->x[1]), o->x[2]),
               _mm256_max_epi32(_mm256_max_epi32(o->x[0], o->x[1]), o->x[2]), k->offx0, k->offx1, k->sx0, k->sx1,
               &o->x0, &o->x1);
    grid_range(_mm256_min_epi32(_mm256_min_epi32(o->y[0], o->y[1]), o->y[2]),
               _mm256_max_epi32(_mm256_max_epi32(o->y[0], o->y[1]), o->y[2]), k->offy0, k->offy1, k->sy0, k->sy1,
               &o->y0, &o->y1);
}

/* 8-lane int32 mask -> 8 bits. */
static inline unsigned mask8(__m256i m) { return (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(m)); }

/* Sum of 8 int32 lanes. */
static inline int32_t hsum8(__m256i v)
{
    __m128i m = _mm_add_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    m = _mm_add_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtsi128_si32(_mm_add_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1))));
}

/* First vertex of row k of the level-L grid whose vertices start at vbase (core_grid_index(L, 0, k)). */
static inline size_t grid_row_start(size_t vbase, size_t L, size_t k) { return vbase + k * (L + 1) - k * (k - 1) / 2; }

/* Row and step boxes (grow): per row of a grid group its pixel box, then one per step of the row (grid_step8_tri's
 * eight triangles), each the union of the boxes of its drawn triangles with a pixel, as int16 lanes x0, x1, y0, y1
 * (x0 > x1 when none: no tile meets it); the tile pass skips a row or step whose box misses the tile.  Measured and
 * dropped (h7b): one compare per row for all its steps (a masked 256-bit load of the row's up to 4 step boxes, a
 * mask of the steps in the tile, the loop over its bits) instead of grid_box_out per step: scene B npatch 92.96 ->
 * 93.35 M instructions per frame (rs_group_tile 27.77 -> 28.15 M): the per-step test is already a few instructions
 * and the mask's set-up is paid for every row that meets the tile. */

/* Steps of the row of nt triangles. */
static inline size_t grid_row_steps(int nt) { return (size_t)(nt + 7) / 8; }

/* Boxes (rows and steps) of a grid group of level L. */
static size_t grid_boxes(size_t L)
{
    size_t n = L;
    for (size_t r = 0; r < L; r++) n += grid_row_steps((int)(2 * (L - r) - 1));
    return n;
}

/* The box (x0, x1, y0, y1 in int16 lanes 0..3) of the least x0 (lane 0) and y0 (lane 4) in mn and the greatest x1
 * and y1 in mx (int16 lanes). */
static inline __m128i grid_box_of(__m128i mn, __m128i mx)
{
    return _mm_unpacklo_epi32(_mm_unpacklo_epi16(mn, mx), _mm_unpackhi_epi16(mn, mx));
}

/* Eight up or eight down triangles of a row in lanes, for the set-up region (grid_group_setup): their doubled areas
 * (area3's, vertices in the list's order), the lanes in the row (in), degenerate (zero) and drawn, and pixel boxes
 * (tri_box's; grid_tri8_box). */
typedef struct tri8 {
    __m256i area, zero, drawn, x0, y0, x1, y1;
} tri8;

/* tri8 of the triangles (a, b, c) in lanes (x, y of each), n of them in the row from lane 0 on. */
static inline __attribute__((always_inline)) void grid_tri8(const grid_consts *k, __m256i ax, __m256i ay, __m256i bx,
                                                            __m256i by, __m256i cx, __m256i cy, int n, tri8 *o)
{
    const __m256i zero = _mm256_setzero_si256();
    o->area = _mm256_sub_epi32(_mm256_mullo_epi32(_mm256_sub_epi32(bx, ax), _mm256_sub_epi32(cy, ay)),
                               _mm256_mullo_epi32(_mm256_sub_epi32(by, ay), _mm256_sub_epi32(cx, ax)));
    const __m256i in = _mm256_cmpgt_epi32(_mm256_set1_epi32(n), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256i z = _mm256_cmpeq_epi32(o->area, zero);
    const __m256i cul = _mm256_cmpgt_epi32(_mm256_sign_epi32(o->area, k->cull_sign), zero);
    o->zero = _mm256_and_si256(in, z);
    o->drawn = _mm256_andnot_si256(_mm256_or_si256(z, cul), in);
}

/* The pixel boxes of o (triangles (a, b, c) as given to grid_tri8). */
static inline __attribute__((always_inline)) void grid_tri8_box(const grid_consts *k, __m256i ax, __m256i ay,
                                                                __m256i bx, __m256i by, __m256i cx, __m256i cy,
                                                                tri8 *o)
{
    grid_range(_mm256_min_epi32(_mm256_min_epi32(ax, bx), cx), _mm256_max_epi32(_mm256_max_epi32(ax, bx), cx),
               k->offx0, k->offx1, k->sx0, k->sx1, &o->x0, &o->x1);
    grid_range(_mm256_min_epi32(_mm256_min_epi32(ay, by), cy), _mm256_max_epi32(_mm256_max_epi32(ay, by), cy),
               k->offy0, k->offy1, k->sy0, k->sy1, &o->y0, &o->y1);
}

/* The drawn triangles of o with a pixel (x0 <= x1, y0 <= y1), their rs_count_work added to the lanes of *work
 * (min(|area|, box pixels * RS_WORK_UNIT) as uint32: the bit budget); returns that mask. */
static inline __m256i grid_tri8_work(const tri8 *o, __m256i *work)
{
    const __m256i one = _mm256_set1_epi32(1);
    const __m256i pix = _mm256_andnot_si256(_mm256_or_si256(_mm256_cmpgt_epi32(o->x0, o->x1),
                                                            _mm256_cmpgt_epi32(o->y0, o->y1)), o->drawn);
    const __m256i bp = _mm256_mullo_epi32(_mm256_add_epi32(_mm256_sub_epi32(o->x1, o->x0), one),
                                          _mm256_add_epi32(_mm256_sub_epi32(o->y1, o->y0), one));
    _Static_assert(RS_WORK_UNIT == 1u << 17, "RS_WORK_UNIT as a shift");
    const __m256i wk = _mm256_and_si256(pix, _mm256_min_epu32(_mm256_abs_epi32(o->area), _mm256_slli_epi32(bp, 17)));
    *work = _mm256_add_epi64(*work, _mm256_add_epi64(_mm256_cvtepu32_epi64(_mm256_castsi256_si128(wk)),
                                                     _mm256_cvtepu32_epi64(_mm256_extracti128_si256(wk, 1))));
    return pix;
}

/* The set-up region's part of grid group (level L, vertices from vbase) in chunk c: counts its triangles into *tc
 * and its work into c->work as group_tri / tri_box / rs_count_work do per triangle, writes its row and step boxes
 * to boxes[0 .. grid_boxes(L)) and the union of its drawn triangles' boxes to u; returns whether any has a pixel.
 * Per row, eight quads at a time -- their up triangles (A, B, C) in one vector, their down ones (B, D, C) in
 * another, from plain loads of the rows (A, B = A + 1; C, D = C + 1) -- which are the tile pass's two steps. */
static bool grid_group_setup(const grid_cols *g, const grid_consts *k, rs_chunk *c, size_t L, size_t vbase,
                             tri_counts *tc, int16_t (*boxes)[4], int32_t u[4])
{
    const __m256i zero = _mm256_setzero_si256();
    const __m256i big = _mm256_set1_epi32(INT32_MAX), small = _mm256_set1_epi32(INT32_MIN);
    const __m128i none_mn = _mm_set1_epi16(INT16_MAX), none_mx = _mm_set1_epi16(INT16_MIN);
    const __m128i none = grid_box_of(none_mn, none_mx);
    __m256i work = zero;   /* 4 x uint64: below 2^28 triangles of below 2^31 units each */
    __m128i gmn = none_mn, gmx = none_mx;
    __m256i nz = zero, nd = zero;   /* per lane: minus the degenerate and the drawn triangles */
    size_t pos = 0;
    for (size_t r = 0; r < L; r++) {
        const size_t r0 = grid_row_start(vbase, L, r), r1 = r0 + (L + 1 - r);
        const int nq = (int)(L - r);   /* the row's quads: nq up triangles, nq - 1 down ones */
        const size_t row = pos++;
        __m128i rmn = none_mn, rmx = none_mx;
        for (int q = 0; q < nq; q += 8) {
            const int32_t *xa = g->x + r0 + q, *ya = g->y + r0 + q, *xc = g->x + r1 + q, *yc = g->y + r1 + q;
            const __m256i ax = _mm256_loadu_si256((const __m256i *)xa), ay = _mm256_loadu_si256((const __m256i *)ya);
            const __m256i bx = _mm256_loadu_si256((const __m256i *)(xa + 1));
            const __m256i by = _mm256_loadu_si256((const __m256i *)(ya + 1));
            const __m256i cx = _mm256_loadu_si256((const __m256i *)xc), cy = _mm256_loadu_si256((const __m256i *)yc);
            const __m256i dx = _mm256_loadu_si256((const __m256i *)(xc + 1));
            const __m256i dy = _mm256_loadu_si256((const __m256i *)(yc + 1));
            tri8 up, dn;
            grid_tri8(k, ax, ay, bx, by, cx, cy, nq - q, &up);
            grid_tri8(k, bx, by, dx, dy, cx, cy, nq - 1 - q, &dn);
            nz = _mm256_add_epi32(nz, _mm256_add_epi32(up.zero, dn.zero));
            nd = _mm256_add_epi32(nd, _mm256_add_epi32(up.drawn, dn.drawn));
            const size_t s0 = pos;
            const bool two = q + 4 < nq;   /* quads q + 4.. in the row: the second step */
            _mm_storel_epi64((__m128i *)boxes[s0], none);
            if (two) _mm_storel_epi64((__m128i *)boxes[s0 + 1], none);
            pos += two ? 2 : 1;
            if (!mask8(_mm256_or_si256(up.drawn, dn.drawn))) continue;   /* (half of scene B's: back faces) */
            grid_tri8_box(k, ax, ay, bx, by, cx, cy, &up);
            grid_tri8_box(k, bx, by, dx, dy, cx, cy, &dn);
            const __m256i pu = grid_tri8_work(&up, &work), pd = grid_tri8_work(&dn, &work);
            if (!mask8(_mm256_or_si256(pu, pd))) continue;
            /* the union of the boxes with a pixel per lane, then per half (a step) in int16 lanes (saturating: the
             * boxes are within RS_MAX_SIZE): lane 0 of a half the least x0 / greatest x1, lane 4 the same of y */
            const __m256i x0 = _mm256_min_epi32(_mm256_blendv_epi8(big, up.x0, pu), _mm256_blendv_epi8(big, dn.x0, pd));
            const __m256i y0 = _mm256_min_epi32(_mm256_blendv_epi8(big, up.y0, pu), _mm256_blendv_epi8(big, dn.y0, pd));
            const __m256i x1 = _mm256_max_epi32(_mm256_blendv_epi8(small, up.x1, pu), _mm256_blendv_epi8(small, dn.x1, pd));
            const __m256i y1 = _mm256_max_epi32(_mm256_blendv_epi8(small, up.y1, pu), _mm256_blendv_epi8(small, dn.y1, pd));
            __m256i mn = _mm256_packs_epi32(x0, y0), mx = _mm256_packs_epi32(x1, y1);
            mn = _mm256_min_epi16(mn, _mm256_srli_epi64(mn, 32)), mx = _mm256_max_epi16(mx, _mm256_srli_epi64(mx, 32));
            mn = _mm256_min_epi16(mn, _mm256_srli_epi32(mn, 16)), mx = _mm256_max_epi16(mx, _mm256_srli_epi32(mx, 16));
            const __m128i mn0 = _mm256_castsi256_si128(mn), mx0 = _mm256_castsi256_si128(mx);
            const __m128i mn1 = _mm256_extracti128_si256(mn, 1), mx1 = _mm256_extracti128_si256(mx, 1);
            _mm_storel_epi64((__m128i *)boxes[s0], grid_box_of(mn0, mx0));
            if (two) _mm_storel_epi64((__m128i *)boxes[s0 + 1], grid_box_of(mn1, mx1));
            rmn = _mm_min_epi16(rmn, _mm_min_epi16(mn0, mn1)), rmx = _mm_max_epi16(rmx, _mm_max_epi16(mx0, mx1));
        }
        _mm_storel_epi64((__m128i *)boxes[row], grid_box_of(rmn, rmx));
        gmn = _mm_min_epi16(gmn, rmn), gmx = _mm_max_epi16(gmx, rmx);
    }
    uint64_t wl[4];
    _mm256_storeu_si256((__m256i *)wl, work);
    const uint64_t sum = wl[0] + wl[1] + wl[2] + wl[3], w = c->work + sum;
    c->work = w < c->work ? UINT64_MAX : w;   /* rs_count_work's saturation: the same total in any order */
    /* each of the L * L triangles is degenerate, culled or drawn */
    const unsigned degenerate = (unsigned)-hsum8(nz), drawn = (unsigned)-hsum8(nd);
    tc->culled += L * L - degenerate - drawn, tc->degenerate += degenerate, tc->drawn += drawn;
    u[0] = (int16_t)_mm_extract_epi16(gmn, 0), u[1] = (int16_t)_mm_extract_epi16(gmn, 4);
    u[2] = (int16_t)_mm_extract_epi16(gmx, 0), u[3] = (int16_t)_mm_extract_epi16(gmx, 4);
    RS_ASSERT(u[0] > u[2] || (u[0] >= 0 && u[2] < RS_MAX_SIZE && u[1] >= 0 && u[3] < RS_MAX_SIZE));
    return u[0] <= u[2];
}
#endif

/* Can the piece of np triangles over nv vertices v in groups of `group` take the grid rows at `level` (0: no)?
 * Its rows projected (grid_rows_project, the flags ANDed into *all) and its row boxes made room for in chunk c;
 * false also when out of memory (the rs_gtri path then). */
static bool grid_piece(const rs_job *j, rs_chunk *c, const rs_vertex *v, size_t nv, size_t np, size_t group,
                       size_t level, unsigned *all)
{
#ifdef __AVX2__
    if (!level || group != level * level || level > RS_GRID_MAX_LEVEL) return false;
    const size_t boxes = (np / group + 1) * grid_boxes(level);
    return rs_reserve((void **)&c->grow, &c->grow_cap, boxes, sizeof *c->grow) && grid_rows_project(j, c, v, nv, all);
#else
    (void)j, (void)c, (void)v, (void)nv, (void)np, (void)group, (void)level, (void)all;
    return false;
#endif
}

/* Make the records c->gpv of the piece's vertices v[0..nv) when they are not made yet (*made): a grid piece's
 * vertices go to the rows only, and rs_setup_chunk after a false return reads records (the groups that read them
 * take group_records) -- the same values. */
static inline void records_made(const rs_job *j, rs_chunk *c, const rs_vertex *v, size_t nv, bool *made)
{
    if (*made) return;
    RS_KERNEL(rs_project_vertices)(j, v, nv, c->gpv);
    *made = true;
}

/* The records of a grid piece's vertices [a, a + m) from its rows: rs_setup_groups' group loop runs only when every
 * vertex is PV_READY, whose record is its rows' values (not zeroed), flags PV_FINITE | PV_PROJECTED | PV_READY and
 * outcode 0 -- what projecting it again would give, for a fifth of the instructions. */
static void records_of_rows(rs_chunk *c, size_t a, size_t m)
{
#ifdef __AVX2__
    const grid_cols g = grid_cols_of(c);
    rs_pvert *pv = c->gpv;
    for (size_t i = a; i < a + m; i++)
        pv[i] = (rs_pvert){ .x = g.x[i], .y = g.y[i], .z = g.z[i], .flags = PV_FINITE | PV_PROJECTED | PV_READY,
                            .oc = 0, .pad = 0, .iw = g.w[i] };
#else
    (void)c, (void)a, (void)m;   /* (no rows: every piece's records are made) */
#endif
}

/* The records a group of a grid piece of nv vertices reads, inside the group loop: those of its own vertices
 * [vb, vb + m) when it is full (the grid piece's promise, which the row path relies on too: instance k's triangles
 * index its vertices k * m ..), else all of them (*made then) -- from the rows (records_of_rows) when not made yet
 * (*made). */
static void group_records(rs_chunk *c, size_t nv, bool full, size_t vb, size_t m, bool *made)
{
    if (*made) return;
    if (full && vb + m <= nv) {
        records_of_rows(c, vb, m);
        return;
    }
    records_of_rows(c, 0, nv);
    *made = true;
}

bool RS_KERNEL(rs_setup_groups)(const rs_job *j, rs_chunk *c, const rs_vertex *v, size_t nv, const uint32_t *idx,
                                size_t np, size_t group, size_t level)
{
    const rs_pvert *pv = c->gpv;
    unsigned all = PV_READY;
    const bool grid = grid_piece(j, c, v, nv, np, group, level, &all);
    bool made = !grid;   /* the records (records_made) */
    if (!grid) {
        RS_KERNEL(rs_project_vertices)(j, v, nv, c->gpv);
        for (size_t i = 0; i < nv; i++) all &= pv[i].flags;
    }
    if (!all || group == 0 || np > UINT32_MAX / 3) {   /* rs_setup_shared's fallbacks: clipping */
        records_made(j, c, v, nv, &made);
        return false;
    }
    c->n = 0;
    c->culled = c->clipped = c->degenerate = c->drawn = c->work = 0;
    c->oom = false;
    if (!group_keep(j, c, v, nv, np)) return true;
    const bool cull_neg = j->st->cull_mode == RS_CULL_CCW, cull_pos = j->st->cull_mode == RS_CULL_CW;
    const box_consts bc = box_consts_of(j);
    uint64_t culled = 0, degenerate = 0, drawn = 0;   /* (locals: kept in registers) */
    size_t nt = 0;   /* drawn triangles kept */
    queued q[4];     /* the triangles of groups set up per triangle, waiting for finish_queued */
    int nq = 0;
    const size_t gverts = (level + 1) * (level + 2) / 2;   /* vertices of a grid group */
#ifdef __AVX2__
    const grid_cols gc = grid ? grid_cols_of(c) : (grid_cols){ 0 };
    const grid_consts gk = grid_consts_of(j);
    const size_t gboxes = grid ? grid_boxes(level) : 0;     /* its row and step boxes */
    size_t ng = 0;    /* row and step boxes kept */
#endif
    for (size_t g0 = 0; g0 < np; g0 += group) {
        const size_t n = np - g0 < group ? np - g0 : group, first = nt;
        const uint64_t work = c->work;
#ifdef __AVX2__
        const size_t vb = g0 / group * gverts;
        if (grid && n == group && vb + gverts <= nv && vb + gverts + RS_GRID_PAD <= UINT32_MAX && grid_extent_ok(&gc, vb, gverts)) {
            int32_t u[4] = { INT32_MAX, INT32_MAX, INT32_MIN, INT32_MIN };
            tri_counts tc = { 0, 0, 0 };
            const bool any = grid_group_setup(&gc, &gk, c, level, vb, &tc, c->grow + ng, u);
            culled += tc.culled, degenerate += tc.degenerate, drawn += tc.drawn;
            if (!any) continue;   /* no pixel of the group: no entry */
            if (box_tiles(j, u) <= GROUP_MAX_TILES) {
                if (!group_push(j, c, u, ng, gboxes, level, vb)) break;
                ng += gboxes, c->grid_groups++;
                continue;
            }
            c->work = work;   /* per triangle, as below: push_front counts the work again */
            group_records(c, nv, true, vb, gverts, &made);
            if (!group_as_triangles(j, c, &bc, idx, g0, n, g0 + n, &tc, q, &nq)) break;
            continue;
        }
#endif
        /* (this group reads them, and the tile pass its rs_gtri) */
        group_records(c, nv, n == group, g0 / group * gverts, gverts, &made);
        int32_t u[4] = { INT32_MAX, INT32_MAX, INT32_MIN, INT32_MIN };
        size_t k = g0;   /* the triangles before k are counted */
        bool big = false;
        for (size_t kb = g0; kb < g0 + n && !big; kb += 16) {   /* 16 at a time, then: too large already? */
            const size_t ke = g0 + n - kb < 16 ? g0 + n : kb + 16;
            for (k = kb; k < ke; k++) {
                const rs_pvert *tv[3];
                rs_gtri *o = &c->gtri[nt];
                int64_t area;
                const int r = group_tri(pv, &idx[3 * k], cull_neg, cull_pos, tv, o->v, &area);
                if (r <= 0) { degenerate += r == 0, culled += r < 0; continue; }
                drawn++;
                int32_t box[4];
                if (!tri_box(j, &bc, tv, box)) continue;
                RS_ASSERT(box[0] >= 0 && box[2] < RS_MAX_SIZE && box[1] >= 0 && box[3] < RS_MAX_SIZE);
                rs_count_work(c, area, box[0], box[1], box[2], box[3]);
                o->box[0] = (int16_t)box[0], o->box[1] = (int16_t)box[1], o->box[2] = (int16_t)box[2];
                o->box[3] = (int16_t)box[3];
                nt++;
                u[0] = box[0] < u[0] ? box[0] : u[0], u[1] = box[1] < u[1] ? box[1] : u[1];
                u[2] = box[2] > u[2] ? box[2] : u[2], u[3] = box[3] > u[3] ? box[3] : u[3];
            }
            big = nt > first && box_tiles(j, u) > GROUP_MAX_TILES;   /* it goes per triangle: stop here */
        }
        if (nt == first) continue;   /* no pixel of the group: no entry */
        if (!big) {
            if (!group_push(j, c, u, first, nt - first, 0, 0)) break;
            continue;
        }
        c->work = work, nt = first;   /* per triangle: push_front counts the work again */
        tri_counts tc = { 0, 0, 0 };
        const bool ok = group_as_triangles(j, c, &bc, idx, g0, n, k, &tc, q, &nq);
        culled += tc.culled, degenerate += tc.degenerate, drawn += tc.drawn;
        if (!ok) break;
    }
    finish_queued(j, c->prims, q, nq);
    c->culled += culled, c->degenerate += degenerate, c->drawn += drawn;
    return true;
}

/* The tile rectangle [x0, x1] x [y0, y1] (inclusive) in the form gtri_out tests. */
typedef struct tile_rect {
#ifdef __SSE2__
    __m128i lim;   /* int16 lanes x1, y1, x0, y0, x1, y1, x0, y0 */
#else
    int32_t x0, y0, x1, y1;
#endif
} tile_rect;

/* tile_rect of [x0, x1] x [y0, y1] (within RS_MAX_SIZE: int16). */
static inline tile_rect tile_rect_of(int32_t x0, int32_t y0, int32_t x1, int32_t y1)
{
#ifdef __SSE2__
    return (tile_rect){ _mm_setr_epi16((int16_t)x1, (int16_t)y1, (int16_t)x0, (int16_t)y0, (int16_t)x1, (int16_t)y1,
                                       (int16_t)x0, (int16_t)y0) };
#else
    return (tile_rect){ x0, y0, x1, y1 };
#endif
}

/* Does the box of r miss rectangle tr (box x0 > x1 or y0 > y1 of the rectangle, or box x1 < x0 or y1 < y0)? */
static inline bool gtri_out(const rs_gtri *r, const tile_rect *tr)
{
#ifdef __SSE2__
    _Static_assert(offsetof(rs_gtri, box) == 12, "rs_gtri's box as one 8-byte load");
    const __m128i b = _mm_loadl_epi64((const __m128i *)r->box);            /* x0 y0 x1 y1 */
    const __m128i gt = _mm_cmpgt_epi16(b, tr->lim), lt = _mm_cmpgt_epi16(tr->lim, b);
    return (_mm_movemask_epi8(gt) & 0x0f) | (_mm_movemask_epi8(lt) & 0xf0);
#else
    return r->box[0] > tr->x1 || r->box[1] > tr->y1 || r->box[2] < tr->x0 || r->box[3] < tr->y0;
#endif
}

/* Set up queued triangles q[0..n) into the scratch primitives sp (finish_queued) and rasterize them in order. */
static void group_flush(const rs_job *j, rs_tile *t, rs_prim *sp, float (*sa)[RS_MAX_ATTR * RS_ATTR_STRIDE],
                        queued q[4], int n)
{
    finish_queued(j, sp, q, n);
    for (int i = 0; i < n; i++) rs_tri_tile(j, t, &sp[i], sa[i]);
}

#ifdef __AVX2__
/* Does row or step box b (x0, x1, y0, y1) miss the tile whose x1, x0, y1, y0 are lim's int16 lanes 0..3? */
static inline bool grid_box_out(const int16_t b[4], __m128i lim)
{
    const __m128i v = _mm_loadl_epi64((const __m128i *)b);
    return (_mm_movemask_epi8(_mm_cmpgt_epi16(v, lim)) & 0x33) | (_mm_movemask_epi8(_mm_cmpgt_epi16(lim, v)) & 0xcc);
}

/* Attribute slot o of the triangle (a, b, c) as rs_tri_run's stamp lanes take it: v0 = a, d1 = b - a, d2 = c - a,
 * four channels each (rs_fill_slot's values without its interleaving). */
static inline void grid_fill_v(float *o, const rs_vec4 *a, const rs_vec4 *b, const rs_vec4 *c)
{
    const __m128 v0 = _mm_loadu_ps(&a->x);
    _mm_storeu_ps(o, v0);
    _mm_storeu_ps(o + 4, _mm_sub_ps(_mm_loadu_ps(&b->x), v0));
    _mm_storeu_ps(o + 8, _mm_sub_ps(_mm_loadu_ps(&c->x), v0));
}

/* grid_fill_v for the up and the down triangle of a quad, lanes l and l + 1 of a step whose lanes pos are the
 * positive areas (clockwise order as the step's): their slots at o and o + 12 from the quad's A (a[0]), B (a[1]),
 * C (c[0]) and D (c[1]) -- up (A, B, C), down (B, D, C), vertices 1 and 2 swapped where pos is not set -- with
 * the same subtractions. */
static inline void grid_fill_pair(float *o, const rs_vec4 *a, const rs_vec4 *c, __m256i pos, int l)
{
    _Static_assert(RS_ATTR_STRIDE == 12, "a stamp lane's block: one slot of 12 floats, the next lane's after it");
    const __m256 v0 = _mm256_loadu_ps(&a->x);                                    /* A | B */
    const __m256 v1 = _mm256_loadu2_m128(&c[1].x, &a[1].x);                        /* B | D */
    const __m256 v2 = _mm256_broadcast_ps((const __m128 *)&c->x);                 /* C | C */
    const __m256 p = _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(
        pos, _mm256_add_epi32(_mm256_set1_epi32(l), _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1))));
    const __m256 d1 = _mm256_sub_ps(_mm256_blendv_ps(v2, v1, p), v0), d2 = _mm256_sub_ps(_mm256_blendv_ps(v1, v2, p), v0);
    _mm_storeu_ps(o, _mm256_castps256_ps128(v0)), _mm_storeu_ps(o + 4, _mm256_castps256_ps128(d1));
    _mm_storeu_ps(o + 8, _mm256_castps256_ps128(d2)), _mm_storeu_ps(o + 12, _mm256_extractf128_ps(v0, 1));
    _mm_storeu_ps(o + 16, _mm256_extractf128_ps(d1, 1)), _mm_storeu_ps(o + 20, _mm256_extractf128_ps(d2, 1));
}

/* rs_fill_slot for the up and the down triangle of a quad (as grid_fill_pair): the same subtractions and the same
 * interleaving, two slots per vector (vshufps and vunpck* work on each 128-bit half alike). */
static inline void grid_fill_slot_pair(float *o, const rs_vec4 *a, const rs_vec4 *c, __m256i pos, int l)
{
    typedef float v8f __attribute__((vector_size(32)));
    const __m256 v0 = _mm256_loadu_ps(&a->x);                                    /* A | B */
    const __m256 v1 = _mm256_loadu2_m128(&c[1].x, &a[1].x);                        /* B | D */
    const __m256 v2 = _mm256_broadcast_ps((const __m128 *)&c->x);                 /* C | C */
    const __m256 p = _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(
        pos, _mm256_add_epi32(_mm256_set1_epi32(l), _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1))));
    const v8f f0 = (v8f)v0, d1 = (v8f)_mm256_sub_ps(_mm256_blendv_ps(v2, v1, p), v0);
    const v8f d2 = (v8f)_mm256_sub_ps(_mm256_blendv_ps(v1, v2, p), v0);
    /* rs_fill_slot's shuffles, per half (indices 0..3 / 8..11 the low halves, 4..7 / 12..15 the high ones) */
    const v8f t = __builtin_shufflevector(f0, d1, 0, 8, 1, 9, 4, 12, 5, 13);     /* a.x d1.x a.y d1.y */
    const v8f u = __builtin_shufflevector(f0, d1, 2, 10, 3, 11, 6, 14, 7, 15);   /* a.z d1.z a.w d1.w */
    const v8f y = __builtin_shufflevector(d1, d2, 1, 9, 2, 10, 5, 13, 6, 14);    /* d1.y d2.y d1.z d2.z */
    const v8f o0 = __builtin_shufflevector(t, d2, 0, 1, 8, 2, 4, 5, 12, 6);      /* a.x d1.x d2.x a.y */
    const v8f o1 = __builtin_shufflevector(y, u, 0, 1, 8, 9, 4, 5, 12, 13);      /* d1.y d2.y a.z d1.z */
    const v8f w = __builtin_shufflevector(y, u, 3, 10, 11, 11, 7, 14, 15, 15);   /* d2.z a.w d1.w - */
    const v8f o2 = __builtin_shufflevector(w, d2, 0, 1, 2, 11, 4, 5, 6, 15);     /* d2.z a.w d1.w d2.w */
    _mm_storeu_ps(o, _mm256_castps256_ps128((__m256)o0)), _mm_storeu_ps(o + 4, _mm256_castps256_ps128((__m256)o1));
    _mm_storeu_ps(o + 8, _mm256_castps256_ps128((__m256)o2));
    _mm_storeu_ps(o + 12, _mm256_extractf128_ps((__m256)o0, 1)), _mm_storeu_ps(o + 16, _mm256_extractf128_ps((__m256)o1, 1));
    _mm_storeu_ps(o + 20, _mm256_extractf128_ps((__m256)o2, 1));
}

/* Lanes 4h..4h+3 of an 8-lane int32 vector. */
static inline __m128i half4(__m256i v, int h) { return h ? _mm256_extracti128_si256(v, 1) : _mm256_castsi256_si128(v); }

/* rs_tri_edge of edge i -> k of eight triangles, one per int32 lane (edge4's values): ea, eb in int32 lanes, ec of
 * the even lanes in *ece and of the odd lanes in *eco (int64 lanes; mul_epi32 multiplies each 64-bit lane's low
 * half: xo, yo are xi, yi shifted down by 32, the odd lanes). */
static inline void edge8(__m256i xi, __m256i yi, __m256i xo, __m256i yo, __m256i xk, __m256i yk, __m256i *ea,
                         __m256i *eb, __m256i *ece, __m256i *eco)
{
    const __m256i zero = _mm256_setzero_si256(), ones = _mm256_set1_epi32(-1);
    const __m256i dx = _mm256_sub_epi32(xk, xi), dy = _mm256_sub_epi32(yk, yi);
    const __m256i tl = _mm256_or_si256(_mm256_cmpgt_epi32(zero, dy),              /* top_left: -1, else 0 */
                                       _mm256_and_si256(_mm256_cmpeq_epi32(dy, zero), _mm256_cmpgt_epi32(dx, zero)));
    const __m256i a = _mm256_sub_epi32(zero, dy);
    *ea = a, *eb = dx;
    /* s = -dy * x + dx * y; ec = -s - 1 - tl = ~s - tl (tl's lane widened to 64 bits by repeating it) */
    const __m256i se = _mm256_add_epi64(_mm256_mul_epi32(a, xi), _mm256_mul_epi32(dx, yi));
    const __m256i so = _mm256_add_epi64(_mm256_mul_epi32(_mm256_srli_epi64(a, 32), xo),
                                        _mm256_mul_epi32(_mm256_srli_epi64(dx, 32), yo));
    *ece = _mm256_sub_epi64(_mm256_xor_si256(se, ones), _mm256_shuffle_epi32(tl, _MM_SHUFFLE(2, 2, 0, 0)));
    *eco = _mm256_sub_epi64(_mm256_xor_si256(so, ones), _mm256_shuffle_epi32(tl, _MM_SHUFFLE(3, 3, 1, 1)));
}

/* Store rows r0..r3 of eight lanes of 32-bit values transposed: lane t (four values) to base + t * step. */
static inline void store8_t32(__m256i r0, __m256i r1, __m256i r2, __m256i r3, char *base, size_t step)
{
    const __m256d a = _mm256_castsi256_pd(_mm256_unpacklo_epi32(r0, r1)), b = _mm256_castsi256_pd(_mm256_unpackhi_epi32(r0, r1));
    const __m256d c = _mm256_castsi256_pd(_mm256_unpacklo_epi32(r2, r3)), d = _mm256_castsi256_pd(_mm256_unpackhi_epi32(r2, r3));
    const __m256d t0 = _mm256_unpacklo_pd(a, c), t1 = _mm256_unpackhi_pd(a, c);   /* lanes 0 | 4, 1 | 5 */
    const __m256d t2 = _mm256_unpacklo_pd(b, d), t3 = _mm256_unpackhi_pd(b, d);   /* lanes 2 | 6, 3 | 7 */
    _mm_storeu_pd((double *)(base), _mm256_castpd256_pd128(t0));   /* (unrolled: gcc keeps loops over arrays */
    _mm_storeu_pd((double *)(base + step), _mm256_castpd256_pd128(t1));   /* of vectors in memory) */
    _mm_storeu_pd((double *)(base + 2 * step), _mm256_castpd256_pd128(t2));
    _mm_storeu_pd((double *)(base + 3 * step), _mm256_castpd256_pd128(t3));
    _mm_storeu_pd((double *)(base + 4 * step), _mm256_extractf128_pd(t0, 1));
    _mm_storeu_pd((double *)(base + 5 * step), _mm256_extractf128_pd(t1, 1));
    _mm_storeu_pd((double *)(base + 6 * step), _mm256_extractf128_pd(t2, 1));
    _mm_storeu_pd((double *)(base + 7 * step), _mm256_extractf128_pd(t3, 1));
}

/* store_t64 to base + t * step for lane t. */
static inline void store4_t64(__m256i r0, __m256i r1, __m256i r2, __m256i r3, char *base, size_t step)
{
    __m256i a = _mm256_unpacklo_epi64(r0, r1), b = _mm256_unpackhi_epi64(r0, r1);   /* 00 10 02 12, 01 11 03 13 */
    __m256i c = _mm256_unpacklo_epi64(r2, r3), d = _mm256_unpackhi_epi64(r2, r3);   /* 20 30 22 32, 21 31 23 33 */
    _mm256_storeu_si256((__m256i *)(base), _mm256_permute2x128_si256(a, c, 0x20));
    _mm256_storeu_si256((__m256i *)(base + step), _mm256_permute2x128_si256(b, d, 0x20));
    _mm256_storeu_si256((__m256i *)(base + 2 * step), _mm256_permute2x128_si256(a, c, 0x31));
    _mm256_storeu_si256((__m256i *)(base + 3 * step), _mm256_permute2x128_si256(b, d, 0x31));
}

/* The three edges of eight triangles, one per int32 lane: ea, eb and the low 32 bits of ec (the stamp coverage's
 * values are modulo 2^32, exact by coef_small).  (Named fields, no arrays: gcc keeps arrays of vectors in memory.) */
typedef struct edges8 { __m256i a0, a1, a2, b0, b1, b2, c0, c1, c2; } edges8;

/* The low 32 bits of the int64 lanes of e (the even lanes' values) and of o (the odd lanes'), as eight int32 lanes. */
static inline __m256i lo32_pair(__m256i e, __m256i o) { return _mm256_blend_epi32(e, _mm256_slli_epi64(o, 32), 0xaa); }

/* The coverage's edge vectors of step o alone (grid_edges8's *ev, nothing stored): per edge i -> k ea = -dy, eb = dx
 * and ec's low 32 bits, ~(ea * x_i + eb * y_i) + 1 on a top-left edge, all modulo 2^32 (the same bits as edge8's
 * int64 values' low halves). */
static inline __attribute__((always_inline)) void grid_edge_vals8(const step8 *o, edges8 *ev)
{
    const __m256i zero = _mm256_setzero_si256(), ones = _mm256_set1_epi32(-1);
    __m256i a[3], b[3], c[3];
#pragma GCC unroll 3
    for (int e = 0; e < 3; e++) {
        const int k = e == 2 ? 0 : e + 1;
        const __m256i dx = _mm256_sub_epi32(o->x[k], o->x[e]), dy = _mm256_sub_epi32(o->y[k], o->y[e]);
        const __m256i tl = _mm256_or_si256(_mm256_cmpgt_epi32(zero, dy),
                                           _mm256_and_si256(_mm256_cmpeq_epi32(dy, zero), _mm256_cmpgt_epi32(dx, zero)));
        a[e] = _mm256_sub_epi32(zero, dy), b[e] = dx;
        const __m256i sv = _mm256_add_epi32(_mm256_mullo_epi32(a[e], o->x[e]), _mm256_mullo_epi32(dx, o->y[e]));
        c[e] = _mm256_sub_epi32(_mm256_xor_si256(sv, ones), tl);
    }
    *ev = (edges8){ a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2] };
}

/* finish4_edges for the eight lanes of step o into the rs_tri of sp[0..8) (every lane: the stores of lanes not
 * drawn or not in the tile are not read), and the same edges as vectors into *ev (grid_cov8's). */
static inline __attribute__((always_inline)) void grid_edges8(const step8 *o, rs_prim *sp, edges8 *ev)
{
    /* (unrolled by hand, no arrays: gcc keeps loops over arrays of vectors in memory) */
    const __m256i xo0 = _mm256_srli_epi64(o->x[0], 32), yo0 = _mm256_srli_epi64(o->y[0], 32);
    const __m256i xo1 = _mm256_srli_epi64(o->x[1], 32), yo1 = _mm256_srli_epi64(o->y[1], 32);
    const __m256i xo2 = _mm256_srli_epi64(o->x[2], 32), yo2 = _mm256_srli_epi64(o->y[2], 32);
    __m256i ea0, eb0, ece0, eco0, ea1, eb1, ece1, eco1, ea2, eb2, ece2, eco2;
    edge8(o->x[0], o->y[0], xo0, yo0, o->x[1], o->y[1], &ea0, &eb0, &ece0, &eco0);
    edge8(o->x[1], o->y[1], xo1, yo1, o->x[2], o->y[2], &ea1, &eb1, &ece1, &eco1);
    edge8(o->x[2], o->y[2], xo2, yo2, o->x[0], o->y[0], &ea2, &eb2, &ece2, &eco2);
    char *const t0 = (char *)&sp[0].u.t;
    const size_t st = sizeof *sp;
    store8_t32(ea0, ea1, ea2, eb0, t0 + offsetof(rs_tri, ea), st);   /* ea[0..3), eb[0] */
    const __m256i lo = _mm256_unpacklo_epi32(eb1, eb2), hi = _mm256_unpackhi_epi32(eb1, eb2);   /* eb[1..3) */
    char *const b1 = t0 + offsetof(rs_tri, eb[1]);
    const __m128d q01 = _mm_castsi128_pd(_mm256_castsi256_si128(lo)), q23 = _mm_castsi128_pd(_mm256_castsi256_si128(hi));
    const __m128d q45 = _mm_castsi128_pd(_mm256_extracti128_si256(lo, 1));
    const __m128d q67 = _mm_castsi128_pd(_mm256_extracti128_si256(hi, 1));
    _mm_storel_pd((double *)(b1), q01), _mm_storeh_pd((double *)(b1 + st), q01);
    _mm_storel_pd((double *)(b1 + 2 * st), q23), _mm_storeh_pd((double *)(b1 + 3 * st), q23);
    _mm_storel_pd((double *)(b1 + 4 * st), q45), _mm_storeh_pd((double *)(b1 + 5 * st), q45);
    _mm_storel_pd((double *)(b1 + 6 * st), q67), _mm_storeh_pd((double *)(b1 + 7 * st), q67);
    /* ec[0..3), vx and vy: the even lanes' and the odd lanes' rows (vx, vy of a lane as one int64) */
    const __m256i vxe = _mm256_blend_epi32(o->x[0], _mm256_slli_epi64(o->y[0], 32), 0xaa);
    const __m256i vxo = _mm256_blend_epi32(xo0, o->y[0], 0xaa);
    store4_t64(ece0, ece1, ece2, vxe, t0 + offsetof(rs_tri, ec), 2 * st);
    store4_t64(eco0, eco1, eco2, vxo, t0 + st + offsetof(rs_tri, ec), 2 * st);
    *ev = (edges8){ ea0, ea1, ea2, eb0, eb1, eb2, lo32_pair(ece0, eco0), lo32_pair(ece1, eco1), lo32_pair(ece2, eco2) };
}

/* Planes of lanes 4h..4h+3 of step o (rows r0, r1 from quad i on, as grid_step8_tri) into sp[0..4) (the edges:
 * grid_edges8): finish4_planes with the step's clockwise vertices, their z and 1/w from the rows' loads (the same
 * lanes as grid_verts8, swapped as o's). */
static inline void grid_finish_half(const bias4 *bias, const grid_cols *g, size_t r0, size_t r1, const step8 *o,
                                    int h, __m128i live, rs_prim *sp)
{
    const size_t q = (size_t)(2 * h);   /* the half's first quad, from i */
    const __m128i pos = half4(o->pos, h);
    /* lanes not live (not drawn, not in the tile, past the row: maybe no area, or padding's 1/w = 0) get area 1 and
     * greatest 1/w 1 in finish4_planes, so that no lane divides by zero or makes an infinity or a NaN (their vertices
     * are the rows' or the padding's: within 2^22, z and 1/w finite), as finish4's spare lanes repeat a real
     * triangle; their results are not used */
    const __m128i x[3] = { half4(o->x[0], h), half4(o->x[1], h), half4(o->x[2], h) };
    const __m128i y[3] = { half4(o->y[0], h), half4(o->y[1], h), half4(o->y[2], h) };
    __m128 zf[3];
    char *const tr[4] = { (char *)&sp[0].u.t, (char *)&sp[1].u.t, (char *)&sp[2].u.t, (char *)&sp[3].u.t };
    const __m128 za = _mm_loadu_ps(g->z + r0 + q), zb = _mm_loadu_ps(g->z + r0 + q + 1);
    const __m128 zc = _mm_loadu_ps(g->z + r1 + q), zd = _mm_loadu_ps(g->z + r1 + q + 1);
    zf[0] = _mm_shuffle_ps(za, za, _MM_SHUFFLE(2, 1, 1, 0));               /* r0: 0 1 1 2 */
    const __m128 z1 = _mm_unpacklo_ps(zb, zd), z2 = _mm_shuffle_ps(zc, zc, _MM_SHUFFLE(1, 1, 0, 0));
    const __m128 fpos = _mm_castsi128_ps(pos);
    zf[1] = _mm_blendv_ps(z2, z1, fpos), zf[2] = _mm_blendv_ps(z1, z2, fpos);
    const __m256d wa = _mm256_loadu_pd(g->w + r0 + q), wc = _mm256_loadu_pd(g->w + r1 + q);
    const __m128d wb = _mm_loadu_pd(g->w + r0 + q + 1), wd = _mm_loadu_pd(g->w + r1 + q + 1);
    const __m256d w0 = _mm256_permute4x64_pd(wa, _MM_SHUFFLE(2, 1, 1, 0));
    const __m256d w1 = _mm256_setr_m128d(_mm_unpacklo_pd(wb, wd), _mm_unpackhi_pd(wb, wd));
    const __m256d w2 = _mm256_permute4x64_pd(wc, _MM_SHUFFLE(1, 1, 0, 0));
    const __m256d pos64 = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(pos));
    const __m256d live64 = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(live));
    finish4_planes(bias, x, y, zf, (v4d)w0, (v4d)_mm256_blendv_pd(w2, w1, pos64), (v4d)_mm256_blendv_pd(w1, w2, pos64),
                   &live64, tr);
}

/* cov with bit `bit` set in the lanes whose edge values e0, e1, e2 are all >= 0 (the sign bit of e0 | e1 | e2
 * clear: walk_band's test), the others' unchanged. */
static inline __m256i cov_add(__m256i cov, __m256i e0, __m256i e1, __m256i e2, int bit)
{
    const __m256 s = _mm256_castsi256_ps(_mm256_or_si256(_mm256_or_si256(e0, e1), e2));
    return _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(_mm256_or_si256(cov, _mm256_set1_epi32(bit))),
                                                _mm256_castsi256_ps(cov), s));
}

/* The coverage of nr rows (1..8) of nc columns (1..4, a constant) per lane from the edge values e0..e2 at column 0
 * of row nr - 1, stepped by a0..a2 per column and b0..b2 per row (ea, eb times one pixel): bit r * 4 + c set where
 * position (c, r) is inside the three edges.  The rows from the last up, so that the mask moves by a shift. */
static inline __attribute__((always_inline)) __m256i grid_cov_rows(__m256i e0, __m256i e1, __m256i e2, __m256i a0,
                                                                   __m256i a1, __m256i a2, __m256i b0, __m256i b1,
                                                                   __m256i b2, int nr, int nc)
{
    __m256i d0 = b0, d1 = b1, d2 = b2;   /* -(b + (nc - 1) * a): from a row's last column to the first one above */
#pragma GCC unroll 4
    for (int c = 1; c < nc; c++) d0 = _mm256_add_epi32(d0, a0), d1 = _mm256_add_epi32(d1, a1), d2 = _mm256_add_epi32(d2, a2);
    const __m256i zero = _mm256_setzero_si256();
    d0 = _mm256_sub_epi32(zero, d0), d1 = _mm256_sub_epi32(zero, d1), d2 = _mm256_sub_epi32(zero, d2);
    __m256i cov = zero;
    for (int r = nr;;) {
#pragma GCC unroll 4
        for (int c = 0; c < nc; c++) {
            if (c) e0 = _mm256_add_epi32(e0, a0), e1 = _mm256_add_epi32(e1, a1), e2 = _mm256_add_epi32(e2, a2);
            cov = cov_add(cov, e0, e1, e2, 1 << c);
        }
        if (--r == 0) return cov;
        cov = _mm256_slli_epi32(cov, 4);
        e0 = _mm256_add_epi32(e0, d0), e1 = _mm256_add_epi32(e1, d1), e2 = _mm256_add_epi32(e2, d2);
    }
}

/* The stamp walk's coverage masks (span.c's walk_band with 4-wide stamps: bit row * 4 + column set for a covered
 * pixel of the box) of the lanes sv (-1 lanes, some) of a step whose edges are ev and clipped boxes x0, y0, x1, y1
 * (at most 4 x 8 in sv), all at once: per position the lanes' ea * X + eb * Y + ec modulo 2^32 at its sample point
 * (X, Y: 1/256 px from the centre, cx and cy's low halves in vcx, vcy: walk_band's values), over the columns and
 * rows of sv's widest and tallest box, masked to each lane's box.  The other lanes' masks are not meaningful. */
static inline __attribute__((always_inline)) __m256i grid_cov8(const edges8 *ev, __m256i x0, __m256i y0, __m256i x1,
                                                               __m256i y1, __m256i sv, __m256i vcx, __m256i vcy)
{
    /* each lane's box as a mask: columns 0..w of each row (a table indexed by w = x1 - x0, 0..3) and rows 0..h (by
     * h = y1 - y0, 0..7); or-ed over sv's lanes, its highest bit is in the tallest box's last row, its first row's
     * in the widest box's last column: the rows and columns to walk */
    const __m256i box = _mm256_and_si256(
        _mm256_permutevar8x32_epi32(_mm256_setr_epi32(0x11111111, 0x33333333, 0x77777777, -1, 0, 0, 0, 0),
                                    _mm256_sub_epi32(x1, x0)),
        _mm256_permutevar8x32_epi32(_mm256_setr_epi32(0xf, 0xff, 0xfff, 0xffff, 0xfffff, 0xffffff, 0xfffffff, -1),
                                    _mm256_sub_epi32(y1, y0)));
    __m256i u = _mm256_and_si256(box, sv);
    u = _mm256_or_si256(u, _mm256_permute2x128_si256(u, u, 1));
    u = _mm256_or_si256(u, _mm256_shuffle_epi32(u, _MM_SHUFFLE(1, 0, 3, 2)));
    u = _mm256_or_si256(u, _mm256_shuffle_epi32(u, _MM_SHUFFLE(2, 3, 0, 1)));
    const unsigned bits = (unsigned)_mm256_cvtsi256_si32(u);
    const int nr = ((31 - __builtin_clz(bits)) >> 2) + 1, nc = 32 - __builtin_clz(bits & 0xfu);
    /* column 0 of row nr - 1 */
    const __m256i X = _mm256_sub_epi32(_mm256_slli_epi32(x0, RS_SUB_BITS), vcx);
    const __m256i Y = _mm256_sub_epi32(_mm256_slli_epi32(_mm256_add_epi32(y0, _mm256_set1_epi32(nr - 1)), RS_SUB_BITS), vcy);
    const __m256i e0 = _mm256_add_epi32(_mm256_add_epi32(_mm256_mullo_epi32(ev->a0, X), _mm256_mullo_epi32(ev->b0, Y)), ev->c0);
    const __m256i e1 = _mm256_add_epi32(_mm256_add_epi32(_mm256_mullo_epi32(ev->a1, X), _mm256_mullo_epi32(ev->b1, Y)), ev->c1);
    const __m256i e2 = _mm256_add_epi32(_mm256_add_epi32(_mm256_mullo_epi32(ev->a2, X), _mm256_mullo_epi32(ev->b2, Y)), ev->c2);
    const __m256i a0 = _mm256_slli_epi32(ev->a0, RS_SUB_BITS), a1 = _mm256_slli_epi32(ev->a1, RS_SUB_BITS);
    const __m256i a2 = _mm256_slli_epi32(ev->a2, RS_SUB_BITS), b0 = _mm256_slli_epi32(ev->b0, RS_SUB_BITS);
    const __m256i b1 = _mm256_slli_epi32(ev->b1, RS_SUB_BITS), b2 = _mm256_slli_epi32(ev->b2, RS_SUB_BITS);
    __m256i cov;
    switch (nc) {   /* (the columns unrolled) */
    case 1: cov = grid_cov_rows(e0, e1, e2, a0, a1, a2, b0, b1, b2, nr, 1); break;
    case 2: cov = grid_cov_rows(e0, e1, e2, a0, a1, a2, b0, b1, b2, nr, 2); break;
    case 3: cov = grid_cov_rows(e0, e1, e2, a0, a1, a2, b0, b1, b2, nr, 3); break;
    default: cov = grid_cov_rows(e0, e1, e2, a0, a1, a2, b0, b1, b2, nr, 4); break;
    }
    return _mm256_and_si256(cov, box);
}

/* Rasterize grid group g of chunk c inside tile t: per row whose box meets the tile, eight triangles at a time
 * (grid_step8), those that are drawn and meet the tile set up from the rows (grid_finish_half) into the L1 scratch
 * and rasterized at once in the group's order by rs_tri_run (span.c: what rs_tri_tile does for them, with the box
 * clipped to the tile and the walk picked in these lanes; the stamp lanes' coverage computed here for the step at
 * once, grid_cov8). */
static void grid_tile(const rs_job *j, rs_tile *t, const rs_chunk *c, const rs_prim *gp)
{
    const grid_cols g = grid_cols_of(c);
    const grid_consts k = grid_consts_of(j);
    const bias4 bias = bias4_of(j);
    const size_t L = gp->u.g.level, vbase = gp->u.g.vbase, ns = (size_t)j->n_slots;
    const int16_t (*boxes)[4] = (const int16_t (*)[4])c->grow + gp->u.g.first;
    const int32_t tx0 = t->x0, ty0 = t->y0, tx1 = t->x1 - 1, ty1 = t->y1 - 1;
    const __m128i lim = _mm_setr_epi16((int16_t)tx1, (int16_t)tx0, (int16_t)ty1, (int16_t)ty0, 0, 0, 0, 0);
    const __m256i vtx0 = _mm256_set1_epi32(tx0), vty0 = _mm256_set1_epi32(ty0);
    const __m256i vtx1 = _mm256_set1_epi32(tx1), vty1 = _mm256_set1_epi32(ty1);
    const size_t stride = ns * RS_ATTR_STRIDE;
    const __m256i span_max = _mm256_set1_epi32(8192);   /* span.c's coef_small: |ea|, |eb| <= 2^13 */
    const __m256i four = _mm256_set1_epi32(4), eight = _mm256_set1_epi32(8);
    const __m256i vcx = _mm256_set1_epi32((int32_t)(uint32_t)j->cx), vcy = _mm256_set1_epi32((int32_t)(uint32_t)j->cy);
    const __m256i vox = _mm256_set1_epi32(t->ox), voy = _mm256_set1_epi32(t->oy);
    const __m256i vpitch = _mm256_set1_epi32((int32_t)t->pitch);   /* (tile offsets below 2^31: rs_tile_index) */
    const bool stamp_ok = ns == 1 && !j->st->blend_enable && j->rt->n_aov == 0 && t->x1 - t->x0 >= 8;
    _Alignas(64) rs_prim sp[8];                                    /* the scratch: 1 KB, in L1 ... */
    _Alignas(64) float sa[8 * RS_MAX_ATTR * RS_ATTR_STRIDE];       /* ... and 384 bytes of COLOR0 */
    _Alignas(32) rs_run_step rs;   /* rs_tri_run's arrays; cb: the boxes clipped to the tile */
    rs.pitch = (int32_t)t->pitch;
    uint64_t direct = 0;
    for (int l = 0; l < 8; l++) sp[l].kind = RS_K_TRI, sp[l].back = 0;
    const int16_t (*b)[4] = boxes;   /* the row's box, then its steps' */
    for (size_t r = 0; r < L; r++) {
        const int nt = (int)(2 * (L - r) - 1);
        if (grid_box_out(*b, lim)) {   /* (or no pixel in the row) */
            b += 1 + grid_row_steps(nt);
            continue;
        }
        b++;
        const size_t r0 = grid_row_start(vbase, L, r), r1 = r0 + (L + 1 - r);
        for (int i = 0; 2 * i < nt; i += 4) {
            if (grid_box_out(*b++, lim)) continue;   /* no triangle of the step meets the tile: trimmed */
            step8 o;
            const size_t q0 = r0 + (size_t)i, q1 = r1 + (size_t)i;
            grid_step8_tri(&g, &k, q0, q1, nt - 2 * i, &o);
            grid_step8_box(&k, &o);
            const __m256i cx0 = _mm256_max_epi32(o.x0, vtx0), cy0 = _mm256_max_epi32(o.y0, vty0);
            const __m256i cx1 = _mm256_min_epi32(o.x1, vtx1), cy1 = _mm256_min_epi32(o.y1, vty1);
            const __m256i live = _mm256_andnot_si256(_mm256_or_si256(_mm256_cmpgt_epi32(cx0, cx1),
                                                                     _mm256_cmpgt_epi32(cy0, cy1)), o.drawn);
            unsigned m = mask8(live);
            if (!m) continue;
            _mm256_store_si256((__m256i *)rs.cb[0], cx0), _mm256_store_si256((__m256i *)rs.cb[1], cy0);
            _mm256_store_si256((__m256i *)rs.cb[2], cx1), _mm256_store_si256((__m256i *)rs.cb[3], cy1);
            /* coef_small per lane: the edges' ea, eb are the vertices' differences, all within 2^13 when the
             * vertices' spans in x and in y are */
            const __m256i spx = _mm256_sub_epi32(_mm256_max_epi32(_mm256_max_epi32(o.x[0], o.x[1]), o.x[2]),
                                                 _mm256_min_epi32(_mm256_min_epi32(o.x[0], o.x[1]), o.x[2]));
            const __m256i spy = _mm256_sub_epi32(_mm256_max_epi32(_mm256_max_epi32(o.y[0], o.y[1]), o.y[2]),
                                                 _mm256_min_epi32(_mm256_min_epi32(o.y[0], o.y[1]), o.y[2]));
            const __m256i big = _mm256_or_si256(_mm256_cmpgt_epi32(spx, span_max), _mm256_cmpgt_epi32(spy, span_max));
            const unsigned small = ~mask8(big) & 0xffu;
            /* the stamp walk's lanes (rs_tri_run): COLOR0 alone, plain, coef_small, box at most 4 x 8 in a tile at
             * least 8 wide; their slot as v0, d1, d2 (no interleaving); their coverage here, for the step at once,
             * and the lanes that cover no pixel dropped (walk_band draws nothing for them; the test's counter
             * counts them still) */
            const __m256i sv = stamp_ok ? _mm256_andnot_si256(big, _mm256_and_si256(live, _mm256_and_si256(
                                              _mm256_cmpgt_epi32(four, _mm256_sub_epi32(cx1, cx0)),
                                              _mm256_cmpgt_epi32(eight, _mm256_sub_epi32(cy1, cy0)))))
                                        : _mm256_setzero_si256();
            unsigned stamp = mask8(sv);
            /* the edges: stored into the scratch's rs_tri for the walks that read them; a step whose live lanes are
             * all stamp lanes needs them only as the coverage's vectors, its stamp passes read the planes alone */
            edges8 ev;
            if (m & ~stamp) grid_edges8(&o, sp, &ev);
            else grid_edge_vals8(&o, &ev);
            if (stamp) {
                const __m256i cov = grid_cov8(&ev, cx0, cy0, cx1, cy1, sv, vcx, vcy);
                _mm256_store_si256((__m256i *)rs.covm, cov);
                /* the box corners as band_draw takes them: from vertex 0 (o.x[0], o.y[0]: lane l's vx, vy) in 1/256
                 * px modulo 2^32 (walk_band's int64 values' low halves), and rs_tile_index */
                const __m256i sx = _mm256_sub_epi32(_mm256_slli_epi32(cx0, RS_SUB_BITS), vcx);
                const __m256i sy = _mm256_sub_epi32(_mm256_slli_epi32(cy0, RS_SUB_BITS), vcy);
                _mm256_store_si256((__m256i *)rs.xs, _mm256_sub_epi32(sx, o.x[0]));
                _mm256_store_si256((__m256i *)rs.ys, _mm256_sub_epi32(sy, o.y[0]));
                const __m256i oy = _mm256_mullo_epi32(_mm256_sub_epi32(cy0, voy), vpitch);
                _mm256_store_si256((__m256i *)rs.off, _mm256_add_epi32(oy, _mm256_sub_epi32(cx0, vox)));
                const unsigned empty = stamp & mask8(_mm256_cmpeq_epi32(cov, _mm256_setzero_si256()));
                stamp &= ~empty, m &= ~empty;
                direct += (uint64_t)__builtin_popcount(empty);
                if (!m) continue;
            }
            for (int h = 0; h < 2; h++) {
                if (!((m >> (4 * h)) & 15)) continue;
                grid_finish_half(&bias, &g, q0, q1, &o, h, half4(live, h), sp + 4 * h);
            }
            /* (the scratch's rs_prim boxes are not written: rs_tri_run and span.c's walks read the clipped boxes cb
             * and the rs_tri alone) */
            const rs_vec4 *ga = c->gattr;
            unsigned rest = m;   /* the lanes whose slot is filled one at a time */
            const unsigned both = ns == 1 ? m & (m >> 1) & 0x55u : 0u;   /* quads with both triangles live */
            if (both) {   /* COLOR0 alone: both slots of a quad at once when both take the same layout */
                const unsigned ps = both & stamp & (stamp >> 1), pf = both & ~(stamp | stamp >> 1);
                for (unsigned f = ps; f; f &= f - 1) {
                    const int l = __builtin_ctz(f);
                    grid_fill_pair(sa + (size_t)l * stride, &ga[q0 + (size_t)(l / 2)], &ga[q1 + (size_t)(l / 2)], o.pos, l);
                }
                for (unsigned f = pf; f; f &= f - 1) {
                    const int l = __builtin_ctz(f);
                    grid_fill_slot_pair(sa + (size_t)l * stride, &ga[q0 + (size_t)(l / 2)], &ga[q1 + (size_t)(l / 2)],
                                        o.pos, l);
                }
                rest &= ~((ps | pf) | (ps | pf) << 1);
            }
            const unsigned pos = rest ? mask8(o.pos) : 0u;
            for (unsigned f = rest; f; f &= f - 1) {
                const int l = __builtin_ctz(f);
                /* lane l: the up (l even: A, B, C) or down (l odd: B, D, C) triangle of quad i + l/2, in the group's
                 * order; its vertices' indices (grid_verts8's lanes), 1 and 2 swapped as the step's */
                const size_t qd = (size_t)(l / 2), v0 = q0 + (size_t)((l + 1) / 2);
                const size_t v1 = (l & 1 ? q1 : q0) + qd + 1, v2 = q1 + qd;
                const size_t i0 = v0, i1 = pos >> l & 1u ? v1 : v2, i2 = pos >> l & 1u ? v2 : v1;
                float *a = sa + (size_t)l * stride;
                if (stamp >> l & 1u) grid_fill_v(a, &ga[i0], &ga[i1], &ga[i2]);
                else if (ns == 1) rs_fill_slot(a, &ga[i0], &ga[i1], &ga[i2]);   /* (COLOR0 alone) */
                else
                    for (size_t s = 0; s < ns; s++)
                        rs_fill_slot(a + s * RS_ATTR_STRIDE, &ga[i0 * ns + s], &ga[i1 * ns + s], &ga[i2 * ns + s]);
            }
            rs.live = m, rs.small = small, rs.stamp = stamp;
            direct += RS_KERNEL(rs_tri_run)(j, t, sp, sa, stride, &rs);
        }
    }
    /* the test's counter (raster_internal.h): once per group and tile; the chunk is the set-up region's, read-only
     * to the tile pass but for this */
    if (direct) __atomic_fetch_add(&((rs_chunk *)c)->grid_direct, direct, __ATOMIC_RELAXED);
}
#endif

void RS_KERNEL(rs_group_tile)(const rs_job *j, rs_tile *t, const rs_chunk *c, const rs_prim *g)
{
#ifdef __AVX2__
    if (g->u.g.level) {
        grid_tile(j, t, c, g);
        return;
    }
#endif
    const rs_pvert *pv = c->gpv;
    const size_t ns = (size_t)j->n_slots;
    const tile_rect tr = tile_rect_of(t->x0, t->y0, t->x1 - 1, t->y1 - 1);
    /* a group in one tile: each of its boxes (inside the scissor) meets the tile's rectangle */
    const bool all = ((g->x0 ^ g->x1) | (g->y0 ^ g->y1)) >> j->tile_bits == 0;
    _Alignas(64) rs_prim sp[4];                                   /* the scratch: ~2.5 KB, in L1 */
    _Alignas(64) float sa[4][RS_MAX_ATTR * RS_ATTR_STRIDE];
    queued q[4];
    int nq = 0;
    for (const rs_gtri *r = c->gtri + g->u.g.first, *end = r + g->u.g.count; r < end; r++) {
        if (!all && gtri_out(r, &tr)) continue;   /* not in this tile */
        rs_prim *p = &sp[nq];
        p->x0 = r->box[0], p->y0 = r->box[1], p->x1 = r->box[2], p->y1 = r->box[3];
        p->kind = RS_K_TRI, p->back = 0;
        const rs_vec4 *a0 = &c->gattr[r->v[0] * ns], *a1 = &c->gattr[r->v[1] * ns], *a2 = &c->gattr[r->v[2] * ns];
        for (size_t s = 0; s < ns; s++) rs_fill_slot(sa[nq] + s * RS_ATTR_STRIDE, &a0[s], &a1[s], &a2[s]);
        q[nq] = (queued){ { &pv[r->v[0]], &pv[r->v[1]], &pv[r->v[2]] }, (size_t)nq };
        if (++nq == 4) group_flush(j, t, sp, sa, q, nq), nq = 0;
    }
    if (nq) group_flush(j, t, sp, sa, q, nq);
}
