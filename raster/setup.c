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
 *      A = -(Yk - Yi), B = Xk - Xi            |A|, |B| <= 2^23
 *      C = -(A*Xi + B*Yi) - bias             |C| <= 2 * 2^23 * 2^22 = 2^46
 *      E(X, Y) = A*X + B*Y + C               |E| <= 2^45 + 2^45 + 2^46 = 2^47
 *  The 8x8 block test adds at most (|A| + |B|) * (7*256 + 96) < 2^24 * 2^11 = 2^35 (96 = the largest sample
 *  offset in 1/256 px), and the doubled polygon area (the sum of at most 10 fan cross products, each <= 2^47)
 *  stays below 2^51.  Everything fits int64 (2^63) with 12 bits to spare.  Lines use absolute coordinates
 *  (<= 2^23) and products of a coordinate and a difference (<= 2^47 each, sums < 2^49).
 *
 *  The float planes (depth, perspective barycentrics) are computed in double from the snapped positions and
 *  evaluated at (X - V0) / 256, which is exact in float (at most 2^24 units of 1/256 px).
 */
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

/* Grow chunk c's primitive and attribute arrays (doubling); false (and c->oom) when out of memory. */
static bool grow(const rs_job *j, rs_chunk *c)
{
    size_t cap = c->cap ? c->cap * 2 : 256;
    size_t st = j->stride ? (size_t)j->stride : 1;
    rs_prim *p = realloc(c->prims, cap * sizeof *p);
    if (p) c->prims = p;
    float *a = p ? realloc(c->attr, cap * st * sizeof *a) : NULL;
    if (!p || !a) {
        c->oom = true;
        return false;
    }
    c->attr = a;
    c->cap = cap;
    return true;
}

/* Append one primitive to chunk c; returns it (and its attribute block in *attr), NULL when out of memory. */
static inline rs_prim *push(const rs_job *j, rs_chunk *c, float **attr)
{
    if (c->oom) return NULL;
    if (c->n == c->cap && !grow(j, c)) return NULL;
    *attr = c->attr + c->n * (size_t)j->stride;
    return &c->prims[c->n++];
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
    t->ea[e] = -dy;
    t->eb[e] = dx;
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
    rs_prim *p = push(j, c, &at);
    if (!p) return;
    p->kind = RS_K_TRI;
    p->x0 = x0; p->x1 = x1; p->y0 = y0; p->y1 = y1;
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
    rs_prim *p = push(j, c, &at);
    if (!p) return true;
    p->kind = RS_K_LINE;
    p->x0 = (int32_t)(xm ? i0 : nlo); p->x1 = (int32_t)(xm ? i1 : nhi);
    p->y0 = (int32_t)(xm ? nlo : i0); p->y1 = (int32_t)(xm ? nhi : i1);
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
    rs_prim *p = push(j, c, &at);
    if (!p) return;
    p->kind = RS_K_POINT;
    p->x0 = p->x1 = (int32_t)px;
    p->y0 = p->y1 = (int32_t)py;
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

/* A vertex after the shared pass (rs_project_vertices): outcode and projection, done once per vertex. */
struct rs_pvert {
    pvert p;
    unsigned oc;     /* outcode (valid when finite) */
    bool finite;     /* load() would accept the position */
    bool projected;  /* project() succeeded (p valid) */
    bool ready;      /* finite, inside every clip plane (oc == 0) and projected: no triangle check needed */
};

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
    out->finite = isfinite(q->x) && isfinite(q->y) && isfinite(q->z) && isfinite(q->w);
    out->oc = ~0u;
    out->projected = out->ready = false;
    if (!out->finite) return;
    rs_cvert cv;
    cv.p[0] = q->x, cv.p[1] = q->y, cv.p[2] = q->z, cv.p[3] = q->w;
    cv.a = v->attr, cv.edge = true, cv.orig = true;
    out->oc = outcode6(j, cv.p);
    out->projected = project(j, &cv, &out->p);
    out->ready = out->oc == 0 && out->projected;
}

#ifdef __AVX2__
typedef int64_t v4q __attribute__((vector_size(32)));

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
    v4f zf = __builtin_convertvector(zd, v4f);
    int32_t ix[4], iy[4];
    memcpy(ix, &rx, 16), memcpy(iy, &ry, 16);
    for (int i = 0; i < 4; i++) {
        rs_pvert *o = &out[i];
        o->finite = fin[i] != 0;
        o->oc = o->finite ? (unsigned)oc[i] : ~0u;
        o->projected = ok[i] != 0;
        o->ready = o->projected && oc[i] == 0;
        if (!o->projected) continue;
        o->p = (pvert){ .x = ix[i], .y = iy[i], .z = zf[i], .iw = iw[i], .a = v[i].attr, .edge = true, .orig = true };
    }
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

/* setup_triangle_shared for a triangle with some vertex not `ready` or a fill mode other than solid. */
static void setup_triangle_checked(const rs_job *j, rs_chunk *c, const uint32_t *k)
{
    const rs_pvert *a = &j->pv[k[0]], *b = &j->pv[k[1]], *d = &j->pv[k[2]];
    const rs_vertex *const v[3] = { &j->verts[k[0]], &j->verts[k[1]], &j->verts[k[2]] };
    if (!a->finite || !b->finite || !d->finite || ((a->oc | b->oc | d->oc) && !(a->oc & b->oc & d->oc))) {
        setup_triangle(j, c, v);
        return;
    }
    if (a->oc & b->oc & d->oc) { c->clipped++; return; }
    if (!a->projected || !b->projected || !d->projected) { c->clipped++; return; }
    pvert pv[3] = { a->p, b->p, d->p };
    finish_triangle(j, c, v, pv, 3);
}

/* Set up triangle v[0..3) whose vertices k[0..3) were projected by the shared pass: same outcome as
 * setup_triangle, which it falls back to when a vertex is not finite or the triangle needs clipping. */
static void setup_triangle_shared(const rs_job *j, rs_chunk *c, const uint32_t *k)
{
    const rs_pvert *a = &j->pv[k[0]], *b = &j->pv[k[1]], *d = &j->pv[k[2]];
    if (!(a->ready & b->ready & d->ready) || j->st->fill_mode != RS_FILL_SOLID) {
        setup_triangle_checked(j, c, k);
        return;
    }
    /* finish_triangle and emit_polygon for a solid unclipped triangle, without copying the vertices */
    const pvert *p0 = &a->p, *p1 = &b->p, *p2 = &d->p;
    int64_t area = (p1->x - p0->x) * (p2->y - p0->y) - (p1->y - p0->y) * (p2->x - p0->x);
    if (area == 0) { c->degenerate++; return; }
    int cm = j->st->cull_mode;
    if ((cm == RS_CULL_CCW && area < 0) || (cm == RS_CULL_CW && area > 0)) { c->culled++; return; }
    c->drawn++;
    const pvert *const ov[3] = { p0, area > 0 ? p1 : p2, area > 0 ? p2 : p1 }; /* emit_tri, area known */
    emit_front(j, c, ov, area > 0 ? area : -area, j->flat ? j->verts[k[0]].attr : NULL);
}

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

void rs_setup_chunk(const rs_job *j, rs_chunk *c)
{
    c->n = 0;
    c->culled = c->clipped = c->degenerate = c->drawn = 0;
    c->oom = false;
    size_t vpp = j->prim == RS_PRIM_TRIANGLES ? 3 : (j->prim == RS_PRIM_LINES ? 2 : 1);
    if (vpp == 3 && j->pv && j->idx) { /* the shared pass's triangles: indices straight to the projected vertices */
        for (size_t k = c->first; k < c->first + c->count && !c->oom; k++) setup_triangle_shared(j, c, &j->idx[3 * k]);
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

/* Does primitive p lie in one tile? */
static inline bool one_tile(const rs_prim *p)
{
    return ((p->x0 ^ p->x1) | (p->y0 ^ p->y1)) >> RS_TILE_BITS == 0;
}

/* The tile of p's top-left pixel. */
static inline size_t tile_of(const rs_job *j, const rs_prim *p)
{
    return (size_t)(p->y0 >> RS_TILE_BITS) * (size_t)j->tiles_x + (size_t)(p->x0 >> RS_TILE_BITS);
}

void rs_bin_chunk(const rs_job *j, rs_chunk *c)
{
    size_t nt = (size_t)j->n_tiles;
    if (c->oom || !reserve((void **)&c->bin_off, &c->bin_off_cap, nt + 1, sizeof *c->bin_off)) {
        c->oom = true;
        return;
    }
    size_t *cnt = NULL; /* counts in size_t to detect a uint32 overflow before filling */
    cnt = calloc(nt + 1, sizeof *cnt);
    if (!cnt) { c->oom = true; return; }
    for (size_t k = 0; k < c->n; k++) {
        const rs_prim *p = &c->prims[k];
        if (one_tile(p)) { cnt[tile_of(j, p) + 1]++; continue; }
        for (int ty = p->y0 >> RS_TILE_BITS; ty <= p->y1 >> RS_TILE_BITS; ty++)
            for (int tx = p->x0 >> RS_TILE_BITS; tx <= p->x1 >> RS_TILE_BITS; tx++)
                cnt[(size_t)ty * (size_t)j->tiles_x + (size_t)tx + 1]++;
    }
    for (size_t t = 1; t <= nt; t++) cnt[t] += cnt[t - 1];
    size_t total = cnt[nt];
    if (total > UINT32_MAX || !reserve((void **)&c->bin_idx, &c->idx_cap, total ? total : 1, sizeof *c->bin_idx)) {
        free(cnt);
        c->oom = true;
        return;
    }
    for (size_t t = 0; t <= nt; t++) c->bin_off[t] = (uint32_t)cnt[t];
    free(cnt);
    for (size_t k = 0; k < c->n; k++) {   /* bin_off[t] runs as the fill cursor of tile t */
        const rs_prim *p = &c->prims[k];
        if (one_tile(p)) { c->bin_idx[c->bin_off[tile_of(j, p)]++] = (uint32_t)k; continue; }
        for (int ty = p->y0 >> RS_TILE_BITS; ty <= p->y1 >> RS_TILE_BITS; ty++)
            for (int tx = p->x0 >> RS_TILE_BITS; tx <= p->x1 >> RS_TILE_BITS; tx++)
                c->bin_idx[c->bin_off[(size_t)ty * (size_t)j->tiles_x + (size_t)tx]++] = (uint32_t)k;
    }
    for (size_t t = nt; t > 0; t--) c->bin_off[t] = c->bin_off[t - 1];
    c->bin_off[0] = 0;
    c->n_idx = total;
}
