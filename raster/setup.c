/* raster/setup.c -- primitive setup: clip, project, snap, cull, then triangles / lines / points into a chunk's
 * arrays in submission order; and binning of a chunk's primitives to tiles.
 *
 * Fixed point and the bit budget of the edge functions
 * ------------------------------------------------------
 *  Positions are snapped to 1/256 pixel (RS_SUB_BITS = 8) *relative to the viewport centre* (cx, cy): the
 *  centre is a multiple of 1/2 pixel, so snapping relative to it equals snapping absolute screen coordinates.
 *  Clipping against the guard band |x| <= gx*w, |y| <= gy*w (gx = (RS_GUARD_BAND - 1) / (width/2)) and a clamp
 *  after the divide keep every snapped coordinate within |X|, |Y| <= RS_GUARD_BAND * 256 = 2^14 * 2^8 = 2^22.
 *  Samples lie inside the viewport, whose half-size is at most RS_MAX_SIZE / 2 = 2^13 px, so they obey the same
 *  bound.  An edge from Vi to Vk:
 *      A = -(Yk - Yi), B = Xk - Xi            |A|, |B| <= 2^23 (rs_tri keeps them in int32)
 *      C = -(A*Xi + B*Yi) - bias             |C| <= 2 * 2^23 * 2^22 = 2^46
 *      E(X, Y) = A*X + B*Y + C               |E| <= 2^45 + 2^45 + 2^46 = 2^47
 *  The 8x8 block test adds at most (|A| + |B|) * (7*256 + 96) < 2^24 * 2^11 = 2^35 (96 = the largest sample
 *  offset in 1/256 px), and the doubled polygon area (the sum of at most 10 fan cross products, each <= 2^47)
 *  stays below 2^51.  Everything fits int64 (2^63) with 12 bits to spare.  Lines use absolute coordinates
 *  (<= 2^23) and products of a coordinate and a difference (<= 2^47 each, sums < 2^49).
 *
 *  The float planes (depth, perspective barycentrics) are computed in double from the snapped positions and
 *  evaluated at (X - V0) / 256, which is exact in float (at most 2^24 units of 1/256 px).
 *
 * The definition and the fast path
 * --------------------------------
 *  setup_triangle (clip, project, cull, emit_front) is the definition, and the reference path's only route.  The
 *  shared pass (indexed triangles off the reference path, rs_draw's and rs_draw_source's) first projects every
 *  vertex once into a 24-byte record (rs_project_vertices, four vertices in double lanes); setup_shared then
 *  culls each triangle from its three records and pushes a front-facing one at once (pixel box, ptile entry,
 *  attribute slots) but queues its edges and planes, which finish4 computes for four triangles at a time: the
 *  edge functions in int32 / int64 lanes and tri_planes' double operations in double lanes, per lane the same
 *  operations in the same order as the scalar functions, so the same rs_prim bytes.  A triangle whose vertices
 *  are not all inside the clip volume (or a fill mode other than solid) goes back to the definition, in
 *  submission order.
 *
 *  Binning: push records each primitive's tile (or RS_MULTI_TILE) in the chunk's ptile array, so rs_bin_chunk's
 *  two passes (count, fill) read 4 bytes per primitive and the box only of primitives over several tiles.
 */
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#ifdef __SSE2__
#include <immintrin.h>
#endif

#include "raster_internal.h"

/* A vertex after projection and snapping. */
typedef struct pvert {
    int64_t x, y;            /* 1/256 px relative to the viewport centre */
    float z;                 /* viewport depth */
    double iw;               /* 1 / w */
    const rs_vec4 *a;        /* attribute slots */
    bool edge, orig;
} pvert;

/* Grow chunk c's primitive, tile and attribute arrays (doubling); false (and c->oom) when out of memory. */
static bool grow(const rs_job *j, rs_chunk *c)
{
    size_t cap = c->cap ? c->cap * 2 : 256;
    size_t st = j->stride ? (size_t)j->stride : 1;
    rs_prim *p = realloc(c->prims, cap * sizeof *p);
    if (p) c->prims = p;
    uint32_t *t = p ? realloc(c->ptile, cap * sizeof *t) : NULL;
    if (t) c->ptile = t;
    float *a = t ? realloc(c->attr, cap * st * sizeof *a) : NULL;
    if (!a) {
        c->oom = true;
        return false;
    }
    c->attr = a;
    c->cap = cap;
    return true;
}

/* The ptile entry of a primitive with pixel box [x0, x1] x [y0, y1]. */
static inline uint32_t tile_entry(const rs_job *j, int32_t x0, int32_t y0, int32_t x1, int32_t y1)
{
    bool one = ((x0 ^ x1) | (y0 ^ y1)) >> RS_TILE_BITS == 0;
    return one ? (uint32_t)(y0 >> RS_TILE_BITS) * (uint32_t)j->tiles_x + (uint32_t)(x0 >> RS_TILE_BITS) : RS_MULTI_TILE;
}

/* Append one primitive to chunk c, its box and ptile entry left to the caller; returns it (and its attribute
 * block in *attr), NULL when out of memory. */
static inline rs_prim *push_raw(const rs_job *j, rs_chunk *c, float **attr)
{
    if (c->oom) return NULL;
    if (c->n == c->cap && !grow(j, c)) return NULL;
    *attr = c->attr + c->n * (size_t)j->stride;
    return &c->prims[c->n++];
}

/* push_raw with pixel box [x0, x1] x [y0, y1] (inside the scissor) and its ptile entry set. */
static inline rs_prim *push(const rs_job *j, rs_chunk *c, int32_t x0, int32_t y0, int32_t x1, int32_t y1, float **attr)
{
    rs_prim *p = push_raw(j, c, attr);
    if (!p) return NULL;
    c->ptile[c->n - 1] = tile_entry(j, x0, y0, x1, y1);
    p->x0 = x0; p->x1 = x1; p->y0 = y0; p->y1 = y1;
    return p;
}

/* llrint (round half to even, the default rounding mode) of |x| <= 2^22, inline. */
static inline int64_t round_even(double x)
{
#ifdef __SSE2__
    return (int64_t)_mm_cvtsd_si64(_mm_set_sd(x));
#else
    return (int64_t)llrint(x);
#endif
}

/* Project clip-space vertex cv to snapped screen space; false when w <= 0 or the result is not finite. */
static bool project(const rs_job *j, const rs_cvert *cv, pvert *v)
{
    double w = cv->p[3];
    if (!(w > 0.0)) return false;
    double fx = cv->p[0] / w * j->sx_scale, fy = cv->p[1] / w * j->sy_scale;
    double zw = cv->p[2] / w, iw = 1.0 / w;
    if (!isfinite(fx) || !isfinite(fy) || !isfinite(zw) || !isfinite(iw)) return false;
    const double lim = (double)RS_GUARD_BAND * RS_SUB;
    fx = fx < -lim ? -lim : (fx > lim ? lim : fx);
    fy = fy < -lim ? -lim : (fy > lim ? lim : fy);
    v->x = round_even(fx);
    v->y = round_even(fy);
    v->z = (float)(j->zoff + j->zscale * zw);
    v->iw = iw;
    v->a = cv->a;
    v->edge = cv->edge;
    v->orig = cv->orig;
    return true;
}

/* Doubled signed area of snapped polygon v[0..n) (> 0: clockwise on screen, the D3D9 front face). */
static int64_t poly_area(const pvert *v, int n)
{
    int64_t s = 0;
    for (int i = 1; i + 1 < n; i++)
        s += (v[i].x - v[0].x) * (v[i + 1].y - v[0].y) - (v[i].y - v[0].y) * (v[i + 1].x - v[0].x);
    return s;
}

typedef float v4f __attribute__((vector_size(16)));
typedef double v4d __attribute__((vector_size(32)));
typedef double v2d __attribute__((vector_size(16)));

/* One interpolated slot: o[3q] = a[q], o[3q+1] = b[q] - a[q], o[3q+2] = c[q] - a[q] (4 lanes, same subtractions). */
static inline void fill_slot(float *o, const rs_vec4 *a, const rs_vec4 *b, const rs_vec4 *c)
{
    v4f v0, v1, v2;
    memcpy(&v0, a, 16), memcpy(&v1, b, 16), memcpy(&v2, c, 16);
    v4f d1 = v1 - v0, d2 = v2 - v0;
    v4f t = __builtin_shufflevector(v0, d1, 0, 4, 1, 5);            /* a.x d1.x a.y d1.y */
    v4f u = __builtin_shufflevector(v0, d1, 2, 6, 3, 7);            /* a.z d1.z a.w d1.w */
    v4f y = __builtin_shufflevector(d1, d2, 1, 5, 2, 6);            /* d1.y d2.y d1.z d2.z */
    v4f o0 = __builtin_shufflevector(t, d2, 0, 1, 4, 2);            /* a.x d1.x d2.x a.y */
    v4f o1 = __builtin_shufflevector(y, u, 0, 1, 4, 5);             /* d1.y d2.y a.z d1.z */
    v4f w = __builtin_shufflevector(y, u, 3, 6, 7, 7);              /* d2.z a.w d1.w - */
    v4f o2 = __builtin_shufflevector(w, d2, 0, 1, 2, 7);            /* d2.z a.w d1.w d2.w */
    memcpy(o, &o0, 16), memcpy(o + 4, &o1, 16), memcpy(o + 8, &o2, 16);
}

/* Fill slot values of attribute block at: v0 from a, d1 = b - a, d2 = c - a (b, c may be NULL: 0); slots
 * COLOR0/COLOR1 come from `flat` (constant) when it is given.  (Smooth triangles use fill_slot directly.) */
static void fill_attr(const rs_job *j, float *at, const rs_vec4 *a, const rs_vec4 *b, const rs_vec4 *c,
                      const rs_vec4 *flat)
{
    for (int s = 0; s < j->n_slots; s++) {
        int k = j->slot[s];
        bool fl = flat && (k == RS_ATTR_COLOR0 || k == RS_ATTR_COLOR1);
        const float *v0 = fl ? &flat[k].x : &a[k].x;
        for (int q = 0; q < 4; q++) {
            float *o = at + s * RS_ATTR_STRIDE + q * 3;
            o[0] = v0[q];
            o[1] = (fl || !b) ? 0.0f : (&b[k].x)[q] - v0[q];
            o[2] = (fl || !c) ? 0.0f : (&c[k].x)[q] - v0[q];
        }
    }
}

/* Pixel range [*lo, *hi] whose samples can touch [mn, mx] (1/256 px, absolute), clamped to [s0, s1). */
static void pixel_range(const rs_job *j, int64_t mn, int64_t mx, int s0, int s1, int32_t *lo, int32_t *hi)
{
    _Static_assert(RS_SUB == 1 << RS_SUB_BITS, "floor / ceil division by RS_SUB as arithmetic shifts");
    int64_t a = -((j->omax - mn) >> RS_SUB_BITS), b = (mx + j->omax) >> RS_SUB_BITS; /* ceil, floor of / RS_SUB */
    *lo = (int32_t)(a < s0 ? s0 : a);
    *hi = (int32_t)(b > s1 - 1 ? s1 - 1 : b);
}

/* Edge function of the edge a -> b into slot e of t, with the top-left rule folded into ec. */
static inline void tri_edge(const pvert *a, const pvert *b, int e, rs_tri *t)
{
    int64_t dx = b->x - a->x, dy = b->y - a->y;
    bool top_left = dy < 0 || (dy == 0 && dx > 0);
    t->ea[e] = (int32_t)-dy; /* |dx|, |dy| <= 2^23 */
    t->eb[e] = (int32_t)dx;
    t->ec[e] = -(-dy * a->x + dx * a->y) - (top_left ? 0 : 1);
}

/* Edge functions of triangle v[0..3) (doubled area > 0) into t. */
static inline void tri_edges(const pvert *const v[3], rs_tri *t)
{
    tri_edge(v[0], v[1], 0, t);
    tri_edge(v[1], v[2], 1, t);
    tri_edge(v[2], v[0], 2, t);
}

/* fmax for doubles, inline (the libm call costs more than the comparison): a NaN argument gives the other. */
static inline double dmax(double a, double b) { return a > b || isnan(b) ? a : b; }

/* Depth and perspective planes of triangle v[0..3) with doubled area `area2` (1/256^2 px^2 units).  The double
 * operations are those of the scalar formulas (noted per line), grouped into 2- and 4-lane vectors. */
static void tri_planes(const rs_job *j, const pvert *const v[3], int64_t area2, rs_tri *t)
{
    const double k = 1.0 / RS_SUB;
    double x1 = (double)(v[1]->x - v[0]->x) * k, y1 = (double)(v[1]->y - v[0]->y) * k;
    double x2 = (double)(v[2]->x - v[0]->x) * k, y2 = (double)(v[2]->y - v[0]->y) * k;
    double ar = 1.0 / ((double)area2 * k * k);
    v4d l = (v4d){ y2, -x2, -y1, x1 } * ar;             /* l1a, l1b, l2a, l2b: the lambda1, lambda2 planes */
    v2d l1 = { l[0], l[1] }, l2 = { l[2], l[3] };
    double z0 = v[0]->z, dz1 = v[1]->z - z0, dz2 = v[2]->z - z0;
    v2d zab = dz1 * l1 + dz2 * l2;                        /* za = dz1 l1a + dz2 l2a, zb = dz1 l1b + dz2 l2b */
    double bias = j->st->depth_bias + j->st->slope_scale_depth_bias * dmax(fabs(zab[0]), fabs(zab[1]));
    t->z[0] = (float)zab[0];
    t->z[1] = (float)zab[1];
    t->z[2] = (float)(z0 + bias);
    double m = dmax(v[0]->iw, dmax(v[1]->iw, v[2]->iw));
    v4d n = (v4d){ v[0]->iw, v[1]->iw, v[2]->iw, v[2]->iw } / m;  /* n0, n1, n2 */
    v4d q = (v4d){ n[1], n[1], n[2], n[2] } * l;          /* n1 l1a, n1 l1b, n2 l2a, n2 l2b */
    v2d s = (n[1] - n[0]) * l1 + (n[2] - n[0]) * l2;      /* (n1 - n0) l1. + (n2 - n0) l2. */
    t->q1[0] = (float)q[0]; t->q1[1] = (float)q[1]; t->q1[2] = 0.0f;
    t->q2[0] = (float)q[2]; t->q2[1] = (float)q[3]; t->q2[2] = 0.0f;
    t->s[0] = (float)s[0];
    t->s[1] = (float)s[1];
    t->s[2] = (float)n[0];
}

/* Add a triangle of doubled area area2 (1/256^2 px^2) and pixel box [x0, x1] x [y0, y1] to c's work: the
 * smaller of its area and its box, exactly, in RS_WORK_UNIT (saturating; RS_MAX_OVERDRAW). */
static inline void count_work(rs_chunk *c, int64_t area2, int32_t x0, int32_t y0, int32_t x1, int32_t y1)
{
    uint64_t a = (uint64_t)(area2 < 0 ? -area2 : area2);
    uint64_t b = (uint64_t)(x1 - x0 + 1) * (uint64_t)(y1 - y0 + 1) * RS_WORK_UNIT;
    uint64_t w = c->work + (a < b ? a : b);
    c->work = w < c->work ? UINT64_MAX : w;
}

/* Emit triangle v[0..3) of doubled area `area` > 0 (clockwise) with its pixel box, edges, planes and slots. */
static void emit_front(const rs_job *j, rs_chunk *c, const pvert *const v[3], int64_t area, const rs_vec4 *flat)
{
    int64_t mnx = v[0]->x, mxx = v[0]->x, mny = v[0]->y, mxy = v[0]->y;
    for (int i = 1; i < 3; i++) {
        mnx = v[i]->x < mnx ? v[i]->x : mnx; mxx = v[i]->x > mxx ? v[i]->x : mxx;
        mny = v[i]->y < mny ? v[i]->y : mny; mxy = v[i]->y > mxy ? v[i]->y : mxy;
    }
    int32_t x0, x1, y0, y1;
    pixel_range(j, mnx + j->cx, mxx + j->cx, j->sx0, j->sx1, &x0, &x1);
    pixel_range(j, mny + j->cy, mxy + j->cy, j->sy0, j->sy1, &y0, &y1);
    if (x0 > x1 || y0 > y1) return;
    float *at;
    rs_prim *p = push(j, c, x0, y0, x1, y1, &at);
    if (!p) return;
    count_work(c, area, x0, y0, x1, y1);
    p->kind = RS_K_TRI;
    tri_edges(v, &p->u.t);
    p->u.t.vx = (int32_t)v[0]->x;
    p->u.t.vy = (int32_t)v[0]->y;
    tri_planes(j, v, area, &p->u.t);
    if (flat) fill_attr(j, at, v[0]->a, v[1]->a, v[2]->a, flat);
    else for (int s = 0; s < j->n_slots; s++) fill_slot(at + s * RS_ATTR_STRIDE, &v[0]->a[j->slot[s]],
                                                         &v[1]->a[j->slot[s]], &v[2]->a[j->slot[s]]);
}

/* Emit fan triangle (a, b, c) of a polygon whose area has sign `sign`; slivers that snapping made zero or
 * flipped are skipped (they would double-cover).  flat: the provoking vertex's slots, or NULL. */
static void emit_tri(const rs_job *j, rs_chunk *c, const pvert *a, const pvert *b, const pvert *d, int sign,
                     const rs_vec4 *flat)
{
    int64_t area = (b->x - a->x) * (d->y - a->y) - (b->y - a->y) * (d->x - a->x);
    if (area == 0 || (area > 0) != (sign > 0)) return;
    const pvert *v[3] = { a, area > 0 ? b : d, area > 0 ? d : b };
    emit_front(j, c, v, area > 0 ? area : -area, flat);
}

/* Emit the line a -> b: one pixel per major-axis pixel centre in [start, end) (the last pixel is not drawn).
 * Returns false only when the snapped line has zero length (degenerate). */
static bool emit_line(const rs_job *j, rs_chunk *c, const pvert *a, const pvert *b, const rs_vec4 *flat)
{
    int64_t xa = a->x + j->cx, ya = a->y + j->cy, xb = b->x + j->cx, yb = b->y + j->cy;
    int64_t dx = xb - xa, dy = yb - ya;
    if (dx == 0 && dy == 0) return false;
    bool xm = llabs(dx) >= llabs(dy);
    int64_t ma = xm ? xa : ya, mb = xm ? xb : yb;
    int64_t i0, i1;
    if (mb > ma) { i0 = rs_ceil_div(ma, RS_SUB); i1 = rs_ceil_div(mb, RS_SUB) - 1; }
    else { i0 = rs_floor_div(mb, RS_SUB) + 1; i1 = rs_floor_div(ma, RS_SUB); }
    const pvert *s = mb > ma ? a : b, *e = mb > ma ? b : a;   /* walk towards +major */
    rs_line l;
    l.xmajor = xm;
    l.m0 = (xm ? s->x + j->cx : s->y + j->cy);
    l.n0 = (xm ? s->y + j->cy : s->x + j->cx);
    l.dm = llabs(mb - ma);
    l.dn = (xm ? e->y - s->y : e->x - s->x);
    int s0 = xm ? j->sx0 : j->sy0, s1 = xm ? j->sx1 : j->sy1;
    int t0 = xm ? j->sy0 : j->sx0, t1 = xm ? j->sy1 : j->sx1;
    i0 = i0 < s0 ? s0 : i0;
    i1 = i1 > s1 - 1 ? s1 - 1 : i1;
    if (i0 > i1) return true;
    int64_t n0 = rs_line_minor(&l, i0), n1 = rs_line_minor(&l, i1);
    int64_t nlo = n0 < n1 ? n0 : n1, nhi = n0 < n1 ? n1 : n0;
    nlo = nlo < t0 ? t0 : nlo;
    nhi = nhi > t1 - 1 ? t1 - 1 : nhi;
    if (nlo > nhi) return true;
    float *at;
    rs_prim *p = push(j, c, (int32_t)(xm ? i0 : nlo), (int32_t)(xm ? nlo : i0), (int32_t)(xm ? i1 : nhi),
                      (int32_t)(xm ? nhi : i1), &at);
    if (!p) return true;
    p->kind = RS_K_LINE;
    double dz = (double)e->z - s->z;
    double slope = fabs(dz) / ((double)l.dm / RS_SUB);
    l.z0 = (float)(s->z + j->st->depth_bias + j->st->slope_scale_depth_bias * slope);
    l.dz = (float)dz;
    double m = fmax(s->iw, e->iw);
    l.w0 = (float)(s->iw / m);
    l.w1 = (float)(e->iw / m);
    p->u.l = l;
    fill_attr(j, at, s->a, e->a, NULL, flat);
    return true;
}

/* Emit a one-pixel point at the pixel centre nearest to v (ties towards +x / +y), if inside the scissor. */
static void emit_point(const rs_job *j, rs_chunk *c, const pvert *v, const rs_vec4 *flat)
{
    int64_t px = rs_floor_div(v->x + j->cx + RS_SUB / 2, RS_SUB), py = rs_floor_div(v->y + j->cy + RS_SUB / 2, RS_SUB);
    if (px < j->sx0 || px >= j->sx1 || py < j->sy0 || py >= j->sy1) return;
    float *at;
    rs_prim *p = push(j, c, (int32_t)px, (int32_t)py, (int32_t)px, (int32_t)py, &at);
    if (!p) return;
    p->kind = RS_K_POINT;
    p->u.p.z = v->z + j->st->depth_bias;
    fill_attr(j, at, v->a, NULL, NULL, flat);
}

/* Load n input vertices into clip vertices; false if a position is not finite.  *and / *or: outcodes. */
static bool load(const rs_job *j, const rs_vertex *const *v, int n, rs_cvert *cv, unsigned *oand, unsigned *oor)
{
    *oand = ~0u;
    *oor = 0;
    for (int i = 0; i < n; i++) {
        const rs_vec4 *p = &v[i]->pos;
        if (!isfinite(p->x) || !isfinite(p->y) || !isfinite(p->z) || !isfinite(p->w)) return false;
        cv[i] = (rs_cvert){ .p = { p->x, p->y, p->z, p->w }, .a = v[i]->attr, .edge = true, .orig = true };
        unsigned oc = rs_outcode(j, cv[i].p);
        *oand &= oc;
        *oor |= oc;
    }
    return true;
}

/* Draw the clipped, projected polygon pv[0..n) of one input triangle according to the fill mode. */
static void emit_polygon(const rs_job *j, rs_chunk *c, const pvert *pv, int n, int64_t area, const rs_vec4 *flat)
{
    int fm = j->st->fill_mode;
    for (int i = 0; i < n; i++) {
        if (fm == RS_FILL_SOLID && i >= 1 && i + 1 < n) emit_tri(j, c, &pv[0], &pv[i], &pv[i + 1], area > 0 ? 1 : -1, flat);
        else if (fm == RS_FILL_WIREFRAME && pv[i].edge) emit_line(j, c, &pv[i], &pv[(i + 1) % n], flat);
        else if (fm == RS_FILL_POINT && pv[i].orig) emit_point(j, c, &pv[i], flat);
    }
}

/* Cull and emit the projected polygon pv[0..n) of input triangle v (the part after clipping and projection). */
static void finish_triangle(const rs_job *j, rs_chunk *c, const rs_vertex *const *v, const pvert *pv, int n)
{
    int64_t area = poly_area(pv, n);
    if (area == 0) { c->degenerate++; return; }
    int cm = j->st->cull_mode;
    if ((cm == RS_CULL_CCW && area < 0) || (cm == RS_CULL_CW && area > 0)) { c->culled++; return; }
    c->drawn++;
    emit_polygon(j, c, pv, n, area, j->flat ? v[0]->attr : NULL);
}

/* Set up one input triangle v[0..3): clip, project, cull, emit. */
static void setup_triangle(const rs_job *j, rs_chunk *c, const rs_vertex *const *v)
{
    rs_cvert poly[RS_MAX_POLY];
    unsigned oand, oor;
    if (!load(j, v, 3, poly, &oand, &oor)) { c->degenerate++; return; }
    if (oand) { c->clipped++; return; }
    rs_clipbuf cb;
    cb.n_pool = 0;
    int n = oor ? rs_clip_poly(j, poly, 3, oor, &cb) : 3;
    if (n < 3) { c->clipped++; return; }
    pvert pv[RS_MAX_POLY];
    for (int i = 0; i < n; i++)
        if (!project(j, &poly[i], &pv[i])) { c->clipped++; return; }
    finish_triangle(j, c, v, pv, n);
}

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
    PV_FINITE = 1,    /* load() would accept the position */
    PV_PROJECTED = 2, /* project() succeeded (x, y, z, iw valid) */
    PV_READY = 4      /* finite, inside every clip plane (oc == 0) and projected: no triangle check needed */
};
_Static_assert(sizeof(rs_pvert) == 24, "rs_pvert: x, y, z, flags, oc, pad, iw without padding");

size_t rs_pvert_size(void) { return sizeof(rs_pvert); }

/* rs_outcode inline: bit k set when p is outside clip plane k (clip.c's plane_dist, same expressions). */
static inline unsigned outcode6(const rs_job *j, const double *p)
{
    _Static_assert(RS_CLIP_PLANES == 6, "near, far and four guard-band planes");
    return (unsigned)!(p[2] >= 0.0) | (unsigned)!(p[3] - p[2] >= 0.0) << 1 |
           (unsigned)!(p[0] + j->gx * p[3] >= 0.0) << 2 | (unsigned)!(j->gx * p[3] - p[0] >= 0.0) << 3 |
           (unsigned)!(p[1] + j->gy * p[3] >= 0.0) << 4 | (unsigned)!(j->gy * p[3] - p[1] >= 0.0) << 5;
}

/* What load() and project() give for one vertex, without building the clip vertex's other fields. */
void rs_project_vertex(const rs_job *j, const rs_vertex *v, rs_pvert *out)
{
    const rs_vec4 *q = &v->pos;
    *out = (rs_pvert){ 0 };
    if (!(isfinite(q->x) && isfinite(q->y) && isfinite(q->z) && isfinite(q->w))) return;
    rs_cvert cv;
    cv.p[0] = q->x, cv.p[1] = q->y, cv.p[2] = q->z, cv.p[3] = q->w;
    cv.a = v->attr, cv.edge = true, cv.orig = true;
    unsigned oc = outcode6(j, cv.p);
    pvert p;
    bool pr = project(j, &cv, &p);
    out->oc = (uint8_t)oc;
    out->flags = (uint8_t)(PV_FINITE | (pr ? PV_PROJECTED : 0) | (pr && oc == 0 ? PV_READY : 0));
    if (!pr) return;
    out->x = (int32_t)p.x, out->y = (int32_t)p.y, out->z = p.z, out->iw = p.iw;
}

/* The projected vertex of record r (attribute slots a), as project() gives it. */
static inline pvert pvert_of(const rs_pvert *r, const rs_vec4 *a)
{
    return (pvert){ .x = r->x, .y = r->y, .z = r->z, .iw = r->iw, .a = a, .edge = true, .orig = true };
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

/* project's clamp per lane: x < -lim ? -lim : (x > lim ? lim : x). */
static inline v4d clamp4(v4d x, double lim)
{
    v4d hi = { lim, lim, lim, lim }, lo = -hi;
    v4q l = x < lo, h = x > hi;
    v4q r = ((v4q)lo & l) | (~l & (((v4q)hi & h) | ((v4q)x & ~h)));
    return (v4d)r;
}

/* rs_project_vertex for the four vertices v[0..4): outcode6 and project per lane with the same double
 * operations (a value is finite iff x - x == 0; llrint is cvtpd2dq, exact for the clamped |x| <= 2^22). */
static void project4(const rs_job *j, const rs_vertex *v, rs_pvert *out)
{
    v4d x = { v[0].pos.x, v[1].pos.x, v[2].pos.x, v[3].pos.x }, y = { v[0].pos.y, v[1].pos.y, v[2].pos.y, v[3].pos.y };
    v4d z = { v[0].pos.z, v[1].pos.z, v[2].pos.z, v[3].pos.z }, w = { v[0].pos.w, v[1].pos.w, v[2].pos.w, v[3].pos.w };
    v4q fin = (x - x == 0.0) & (y - y == 0.0) & (z - z == 0.0) & (w - w == 0.0);
    v4q oc = (~(z >= 0.0) & 1) | (~(w - z >= 0.0) & 2) | (~(x + j->gx * w >= 0.0) & 4) |
             (~(j->gx * w - x >= 0.0) & 8) | (~(y + j->gy * w >= 0.0) & 16) | (~(j->gy * w - y >= 0.0) & 32);
    v4d fx = x / w * j->sx_scale, fy = y / w * j->sy_scale, zw = z / w, iw = 1.0 / w;
    v4q ok = fin & (w > 0.0) & (fx - fx == 0.0) & (fy - fy == 0.0) & (zw - zw == 0.0) & (iw - iw == 0.0);
    const double lim = (double)RS_GUARD_BAND * RS_SUB;
    fx = clamp4(fx, lim);
    fy = clamp4(fy, lim);
    __m128i rx = _mm256_cvtpd_epi32((__m256d)fx), ry = _mm256_cvtpd_epi32((__m256d)fy);
    v4d zd = (double)j->zoff + (double)j->zscale * zw;
    __m128i zf = _mm_castps_si128(_mm256_cvtpd_ps((__m256d)zd));
    /* the records' first 16 bytes in int32 lanes (0 where not projected), then transposed into place */
    const __m256i even = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
    __m128i fin32 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32((__m256i)fin, even));
    __m128i ok32 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32((__m256i)ok, even));
    __m128i oc32 = _mm_and_si128(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32((__m256i)oc, even)), fin32);
    __m128i ready = _mm_and_si128(ok32, _mm_cmpeq_epi32(oc32, _mm_setzero_si128()));
    __m128i fl = _mm_or_si128(_mm_or_si128(_mm_and_si128(fin32, _mm_set1_epi32(PV_FINITE)),
                                           _mm_and_si128(ok32, _mm_set1_epi32(PV_PROJECTED))),
                              _mm_or_si128(_mm_and_si128(ready, _mm_set1_epi32(PV_READY)), _mm_slli_epi32(oc32, 8)));
    char *const dst[4] = { (char *)&out[0], (char *)&out[1], (char *)&out[2], (char *)&out[3] };
    _Static_assert(offsetof(rs_pvert, y) == 4 && offsetof(rs_pvert, z) == 8 && offsetof(rs_pvert, flags) == 12 &&
                   offsetof(rs_pvert, oc) == 13 && offsetof(rs_pvert, iw) == 16, "rs_pvert's layout as project4 writes it");
    store_t32(_mm_castsi128_ps(_mm_and_si128(rx, ok32)), _mm_castsi128_ps(_mm_and_si128(ry, ok32)),
              _mm_castsi128_ps(_mm_and_si128(zf, ok32)), _mm_castsi128_ps(fl), dst, 0);   /* little endian: flags, oc */
    __m256d w4 = (__m256d)((v4q)iw & ok);
    __m128d w01 = _mm256_castpd256_pd128(w4), w23 = _mm256_extractf128_pd(w4, 1);
    _mm_storel_pd(&out[0].iw, w01), _mm_storeh_pd(&out[1].iw, w01);
    _mm_storel_pd(&out[2].iw, w23), _mm_storeh_pd(&out[3].iw, w23);
}
#endif

void rs_project_vertices(const rs_job *j, const rs_vertex *v, size_t n, rs_pvert *out)
{
    size_t i = 0;
#ifdef __AVX2__
    for (; i + 4 <= n; i += 4) project4(j, v + i, out + i);
#endif
    for (; i < n; i++) rs_project_vertex(j, &v[i], &out[i]);
}

/* Set up triangle k[0..3) of the shared pass when some vertex is not `ready` or the fill mode is not solid: the
 * same outcome as setup_triangle, which it falls back to when a vertex is not finite or the triangle needs
 * clipping. */
static void setup_triangle_checked(const rs_job *j, rs_chunk *c, const uint32_t *k)
{
    const rs_pvert *a = &j->pv[k[0]], *b = &j->pv[k[1]], *d = &j->pv[k[2]];
    const rs_vertex *const v[3] = { &j->verts[k[0]], &j->verts[k[1]], &j->verts[k[2]] };
    if (!(a->flags & b->flags & d->flags & PV_FINITE) || ((a->oc | b->oc | d->oc) && !(a->oc & b->oc & d->oc))) {
        setup_triangle(j, c, v);
        return;
    }
    if (a->oc & b->oc & d->oc) { c->clipped++; return; }
    if (!(a->flags & b->flags & d->flags & PV_PROJECTED)) { c->clipped++; return; }
    pvert pv[3] = { pvert_of(a, v[0]->attr), pvert_of(b, v[1]->attr), pvert_of(d, v[2]->attr) };
    finish_triangle(j, c, v, pv, 3);
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

/* emit_front's pixel box of the triangle with vertex records v[0..3): x0, y0, x1, y1 into box; false when it is
 * empty. */
static inline bool tri_box(const rs_job *j, const box_consts *bc, const rs_pvert *const v[3], int32_t box[4])
{
#ifdef __AVX2__
    /* pixel_range in int32 lanes (x0, y0, x1, y1): |coordinate| <= 2^22, 0 <= cx, cy < RS_MAX_SIZE * 256 = 2^22 and
     * omax <= 96, so the sums stay below 2^24; ceil(u / 256) = -((-u) >> 8) on the first two lanes, floor on the
     * last two */
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
    pixel_range(j, mnx + j->cx, mxx + j->cx, j->sx0, j->sx1, &box[0], &box[2]);
    pixel_range(j, mny + j->cy, mxy + j->cy, j->sy0, j->sy1, &box[1], &box[3]);
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
    rs_prim *p = push_raw(j, c, &at);
    if (!p) return false;
    count_work(c, area, box[0], box[1], box[2], box[3]);
    c->ptile[c->n - 1] = tile_entry(j, box[0], box[1], box[2], box[3]);
    _Static_assert(offsetof(rs_prim, y0) == 4 && offsetof(rs_prim, x1) == 8 && offsetof(rs_prim, y1) == 12,
                   "rs_prim's box as tri_box writes it");
    memcpy(&p->x0, box, sizeof box);
    p->kind = RS_K_TRI;
    const rs_vec4 *a0 = j->verts[id[0]].attr, *a1 = j->verts[id[1]].attr, *a2 = j->verts[id[2]].attr;
    if (j->flat) fill_attr(j, at, a0, a1, a2, a0);
    else for (int s = 0; s < j->n_slots; s++) fill_slot(at + s * RS_ATTR_STRIDE, &a0[j->slot[s]], &a1[j->slot[s]],
                                                         &a2[j->slot[s]]);
    return true;
}

/* Edges, vertex 0 and planes of queued triangle q, one at a time: emit_front's tri_edges and tri_planes. */
static void finish_one(const rs_job *j, rs_chunk *c, const queued *q)
{
    pvert pv[3] = { pvert_of(q->v[0], NULL), pvert_of(q->v[1], NULL), pvert_of(q->v[2], NULL) };
    const pvert *const v[3] = { &pv[0], &pv[1], &pv[2] };
    rs_tri *t = &c->prims[q->prim].u.t;
    tri_edges(v, t);
    t->vx = q->v[0]->x;
    t->vy = q->v[0]->y;
    int64_t area = (pv[1].x - pv[0].x) * (pv[2].y - pv[0].y) - (pv[1].y - pv[0].y) * (pv[2].x - pv[0].x);
    tri_planes(j, v, area, t);
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

/* tri_edge of edge i -> k of four triangles, the same integer values: ea, eb in int32 lanes, ec in int64 lanes.
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

/* dmax per lane: a where a > b or b is NaN, else b. */
static inline v4d max4(v4d a, v4d b)
{
    v4q m = (a > b) | (b != b);
    return (v4d)(((v4q)a & m) | ((v4q)b & ~m));
}

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

/* finish_one for queued triangles q[0..n) (room for 4; lanes n..3 repeat q[0]), one per lane:
 * tri_edge's integer operations in int32 / int64 lanes and tri_planes' double operations in double lanes, per lane
 * the same operations in the same order, so the same bytes. */
static void finish4(const rs_job *j, rs_chunk *c, queued q[4], int n)
{
    for (int t = n; t < 4; t++) q[t] = q[0];
    __m128i x[3], y[3];
    __m128 zf[3];
    gather4(q, 0, &x[0], &y[0], &zf[0]);   /* (unrolled by hand: gcc keeps loops over these arrays in memory) */
    gather4(q, 1, &x[1], &y[1], &zf[1]);
    gather4(q, 2, &x[2], &y[2], &zf[2]);
    __m128i ea[3], eb[3];
    __m256i ec[3];
    edge4(x[0], y[0], x[1], y[1], &ea[0], &eb[0], &ec[0]);
    edge4(x[1], y[1], x[2], y[2], &ea[1], &eb[1], &ec[1]);
    edge4(x[2], y[2], x[0], y[0], &ea[2], &eb[2], &ec[2]);
    /* tri_planes: the differences are exact in int32 and in double; so is the doubled area, products of
     * integers below 2^23 and their difference below 2^47 being integers below 2^53, the value (double)area2 */
    const double k = 1.0 / RS_SUB;
    v4d dx1 = (v4d)_mm256_cvtepi32_pd(_mm_sub_epi32(x[1], x[0])), dy1 = (v4d)_mm256_cvtepi32_pd(_mm_sub_epi32(y[1], y[0]));
    v4d dx2 = (v4d)_mm256_cvtepi32_pd(_mm_sub_epi32(x[2], x[0])), dy2 = (v4d)_mm256_cvtepi32_pd(_mm_sub_epi32(y[2], y[0]));
    v4d area = dx1 * dy2 - dy1 * dx2;
    v4d x1 = dx1 * k, y1 = dy1 * k, x2 = dx2 * k, y2 = dy2 * k;
    v4d ar = 1.0 / (area * k * k);
    v4d l1a = y2 * ar, l1b = -x2 * ar, l2a = -y1 * ar, l2b = x1 * ar;
    v4d z0 = (v4d)_mm256_cvtps_pd(zf[0]);
    v4d dz1 = (v4d)_mm256_cvtps_pd(zf[1]) - z0, dz2 = (v4d)_mm256_cvtps_pd(zf[2]) - z0;
    v4d za = dz1 * l1a + dz2 * l2a, zb = dz1 * l1b + dz2 * l2b;
    v4d bias = (double)j->st->depth_bias + (double)j->st->slope_scale_depth_bias * max4(abs4(za), abs4(zb));
    v4d w0 = { q[0].v[0]->iw, q[1].v[0]->iw, q[2].v[0]->iw, q[3].v[0]->iw };
    v4d w1 = { q[0].v[1]->iw, q[1].v[1]->iw, q[2].v[1]->iw, q[3].v[1]->iw };
    v4d w2 = { q[0].v[2]->iw, q[1].v[2]->iw, q[2].v[2]->iw, q[3].v[2]->iw };
    v4d m = max4(w0, max4(w1, w2));
    v4d n0 = w0 / m, n1 = w1 / m, n2 = w2 / m;
    v4d s0 = (n1 - n0) * l1a + (n2 - n0) * l2a, s1 = (n1 - n0) * l1b + (n2 - n0) * l2b;
    /* the stores: lanes t >= n repeat lane 0's values into q[0]'s primitive, the same bytes */
    char *const tr[4] = { (char *)&c->prims[q[0].prim].u.t, (char *)&c->prims[q[1].prim].u.t,
                          (char *)&c->prims[q[2].prim].u.t, (char *)&c->prims[q[3].prim].u.t };
    _Static_assert(offsetof(rs_tri, eb) == 12 && offsetof(rs_tri, ec) == 24 && offsetof(rs_tri, vx) == 48 &&
                   offsetof(rs_tri, vy) == 52 && offsetof(rs_tri, z) == 56 && offsetof(rs_tri, q1) == 68 &&
                   offsetof(rs_tri, q2) == 80 && offsetof(rs_tri, s) == 92 && sizeof(rs_tri) == 104,
                   "rs_tri's layout as finish4 writes it");
    /* rs_tri in groups of 16, 8, 32, 16, 16 and 16 bytes */
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
#define F4(v) _mm256_cvtpd_ps((__m256d)(v))
    const __m128 zero = _mm_setzero_ps();
    store_t32(F4(za), F4(zb), F4(z0 + bias), F4(n1 * l1a), tr, offsetof(rs_tri, z));   /* z[0..3), q1[0] */
    store_t32(F4(n1 * l1b), zero, F4(n2 * l2a), F4(n2 * l2b), tr, offsetof(rs_tri, q1[1])); /* q1[1..3), q2[0..2) */
    store_t32(zero, F4(s0), F4(s1), F4(n0), tr, offsetof(rs_tri, q2[2]));              /* q2[2], s[0..3) */
#undef F4
}
#endif

/* Set up one input line v[0]-v[1]. */
static void setup_line(const rs_job *j, rs_chunk *c, const rs_vertex *const *v)
{
    rs_cvert cv[2];
    unsigned oand, oor;
    if (!load(j, v, 2, cv, &oand, &oor)) { c->degenerate++; return; }
    rs_clipbuf cb;
    cb.n_pool = 0;
    if (oand || (oor && !rs_clip_line(j, cv, oor, &cb))) { c->clipped++; return; }
    pvert pv[2];
    if (!project(j, &cv[0], &pv[0]) || !project(j, &cv[1], &pv[1])) { c->clipped++; return; }
    if (pv[0].x == pv[1].x && pv[0].y == pv[1].y) { c->degenerate++; return; }
    c->drawn++;
    emit_line(j, c, &pv[0], &pv[1], j->flat ? v[0]->attr : NULL);
}

/* Set up one input point: dropped when outside the clip volume (near, far, guard band). */
static void setup_point(const rs_job *j, rs_chunk *c, const rs_vertex *const *v)
{
    rs_cvert cv;
    unsigned oand, oor;
    if (!load(j, v, 1, &cv, &oand, &oor)) { c->degenerate++; return; }
    pvert pv;
    if (oor || !project(j, &cv, &pv)) { c->clipped++; return; }
    c->drawn++;
    emit_point(j, c, &pv, NULL);
}

/* Edges and planes of queued triangles q[0..n) (n <= 4; q has room for 4): in lanes, or one by one when alone. */
static void finish_queued(const rs_job *j, rs_chunk *c, queued q[4], int n)
{
#ifdef __AVX2__
    if (n > 1) {
        finish4(j, c, q, n);
        return;
    }
#endif
    for (int t = 0; t < n; t++) finish_one(j, c, &q[t]);
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

/* Doubled signed area of the triangle of records a, b, d, as finish_triangle's poly_area computes it: the
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
 * setup_triangle gives.  A ready, solid, front-facing triangle is pushed with its box and slots at once, in
 * submission order, and queued; its edges and planes are written four triangles at a time (finish_queued). */
static void setup_shared(const rs_job *j, rs_chunk *c)
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
        /* finish_triangle and emit_polygon for a solid unclipped triangle */
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
        if (nq == 4) finish_queued(j, c, q, nq), nq = 0;
    }
    finish_queued(j, c, q, nq);
    c->culled += culled, c->degenerate += degenerate, c->drawn += drawn;
}

void rs_setup_chunk(const rs_job *j, rs_chunk *c)
{
    c->n = 0;
    c->culled = c->clipped = c->degenerate = c->drawn = c->work = 0;
    c->oom = false;
    size_t vpp = j->prim == RS_PRIM_TRIANGLES ? 3 : (j->prim == RS_PRIM_LINES ? 2 : 1);
    if (vpp == 3 && j->pv && j->idx) { /* the shared pass's triangles: indices straight to the projected vertices */
        setup_shared(j, c);
        return;
    }
    for (size_t k = c->first; k < c->first + c->count && !c->oom; k++) {
        const rs_vertex *v[3];
        uint32_t id[3];
        for (size_t i = 0; i < vpp; i++) {
            id[i] = (uint32_t)(j->idx ? j->idx[k * vpp + i] : k * vpp + i);
            v[i] = &j->verts[id[i]];
        }
        if (vpp == 3) setup_triangle(j, c, v);
        else if (vpp == 2) setup_line(j, c, v);
        else setup_point(j, c, v);
    }
}

/* Grow *buf (elements of `size` bytes, capacity *cap) to hold n; false when out of memory. */
static bool reserve(void **buf, size_t *cap, size_t n, size_t size)
{
    if (n <= *cap) return true;
    size_t nc = *cap ? *cap : 64;
    while (nc < n) nc *= 2;
    void *p = realloc(*buf, nc * size);
    if (!p) return false;
    *buf = p;
    *cap = nc;
    return true;
}

/* Add 1 to cnt[t] for every tile t that primitive p's box touches (a primitive over several tiles). */
static void count_tiles(const rs_job *j, const rs_prim *p, uint32_t *cnt)
{
    for (int ty = p->y0 >> RS_TILE_BITS; ty <= p->y1 >> RS_TILE_BITS; ty++)
        for (int tx = p->x0 >> RS_TILE_BITS; tx <= p->x1 >> RS_TILE_BITS; tx++)
            cnt[(size_t)ty * (size_t)j->tiles_x + (size_t)tx]++;
}

/* Append primitive k (box of p) to the bin of every tile it touches; cur[t]: tile t's fill cursor. */
static void fill_tiles(const rs_job *j, const rs_prim *p, uint32_t k, uint32_t *cur, uint32_t *idx)
{
    for (int ty = p->y0 >> RS_TILE_BITS; ty <= p->y1 >> RS_TILE_BITS; ty++)
        for (int tx = p->x0 >> RS_TILE_BITS; tx <= p->x1 >> RS_TILE_BITS; tx++)
            idx[cur[(size_t)ty * (size_t)j->tiles_x + (size_t)tx]++] = k;
}

/* The number of tiles primitive p's box touches. */
static size_t tiles_of(const rs_prim *p)
{
    return (size_t)((p->x1 >> RS_TILE_BITS) - (p->x0 >> RS_TILE_BITS) + 1) *
           (size_t)((p->y1 >> RS_TILE_BITS) - (p->y0 >> RS_TILE_BITS) + 1);
}

/* Count chunk c's bin entries into cnt[t + 1] (zeroed by the caller); returns their total, or more than
 * UINT32_MAX when they do not fit (the counts are then partial). */
static size_t count_bins(const rs_job *j, const rs_chunk *c, uint32_t *cnt)
{
    size_t total = c->n;
    for (size_t k = 0; k < c->n; k++) {
        uint32_t t = c->ptile[k];
        if (t != RS_MULTI_TILE) { cnt[t + 1]++; continue; }
        total += tiles_of(&c->prims[k]) - 1;
        if (total > UINT32_MAX) return total;
        count_tiles(j, &c->prims[k], cnt + 1);
    }
    return total;
}

/* Fill chunk c's bin_idx from the bins' starts off[t] (which end as the bins' ends), in primitive order. */
static void fill_bins(const rs_job *j, const rs_chunk *c, uint32_t *off)
{
    for (size_t k = 0; k < c->n; k++) {
        uint32_t t = c->ptile[k];
        if (t != RS_MULTI_TILE) c->bin_idx[off[t]++] = (uint32_t)k;
        else fill_tiles(j, &c->prims[k], (uint32_t)k, off, c->bin_idx);
    }
}

void rs_bin_chunk(const rs_job *j, rs_chunk *c)
{
    size_t nt = (size_t)j->n_tiles;
    if (c->oom || !reserve((void **)&c->bin_off, &c->bin_off_cap, nt + 1, sizeof *c->bin_off)) {
        c->oom = true;
        return;
    }
    uint32_t *off = c->bin_off;
    memset(off, 0, (nt + 1) * sizeof *off);
    size_t total = count_bins(j, c, off);
    if (total > UINT32_MAX || !reserve((void **)&c->bin_idx, &c->idx_cap, total ? total : 1, sizeof *c->bin_idx)) {
        c->oom = true;
        return;
    }
    for (size_t t = 1; t <= nt; t++) off[t] += off[t - 1];   /* off[t]: start of bin t */
    fill_bins(j, c, off);                                    /* off[t]: end of bin t */
    memmove(off + 1, off, nt * sizeof *off);
    off[0] = 0;
    c->n_idx = total;
}
