/* raster/setup.c -- primitive set-up, the reference (scalar) one: clip, project, snap, cull, then triangles /
 * lines / points into a chunk's arrays in submission order.  This is the definition; setup_simd.c is its fast path
 * for triangles (the shared pass and the four-lane finish) and bin.c bins a chunk's primitives to tiles.
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
 *  (<= 2^23) and products of a coordinate and a difference (<= 2^47 each, sums < 2^49).  The claims are
 *  RS_ASSERTs where the values are made (live in the INSTESS_CHECKS build).
 *
 *  The float planes (depth, perspective barycentrics) are computed in double from the snapped positions and
 *  evaluated at (X - V0) / 256, which is exact in float (at most 2^24 units of 1/256 px).
 *
 * The definition
 * --------------
 *  rs_setup_triangle (clip, project, cull, emit_front) is the definition, and the reference path's only route;
 *  setup_simd.c's shared pass gives the same rs_prim bytes and falls back to it for triangles that need clipping
 *  (or a fill mode other than solid).  Lines and points are set up here only.
 */
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#ifdef __SSE2__
#include <immintrin.h>
#endif

#include "setup_internal.h"

/* Grow chunk c's primitive, tile and attribute arrays (doubling); false (and c->oom) when out of memory. */
bool rs_setup_grow(const rs_job *j, rs_chunk *c)
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
    c->attr_cap = cap * st;
    c->cap = cap;
    return true;
}

/* Chunk c's attribute array made to hold c->cap primitives of j's stride (a chunk kept from a draw with fewer
 * interpolated slots -- before a pixel shader, say -- has a smaller one); false (and c->oom) when out of memory. */
static bool fit_attr(const rs_job *j, rs_chunk *c)
{
    size_t need = c->cap * (size_t)(j->stride ? j->stride : 1);
    if (c->attr_cap >= need) return true;
    float *a = realloc(c->attr, need * sizeof *a);
    if (!a) return c->oom = true, false;
    c->attr = a, c->attr_cap = need;
    return true;
}

/* rs_push_raw with pixel box [x0, x1] x [y0, y1] (inside the scissor) and its ptile entry set. */
static inline rs_prim *push(const rs_job *j, rs_chunk *c, int32_t x0, int32_t y0, int32_t x1, int32_t y1, float **attr)
{
    rs_prim *p = rs_push_raw(j, c, attr);
    if (!p) return NULL;
    c->ptile[c->n - 1] = rs_tile_entry(j, x0, y0, x1, y1);
    p->x0 = x0; p->x1 = x1; p->y0 = y0; p->y1 = y1;
    return p;
}

/* llrint (round half to even, the default rounding mode) of |x| <= 2^22, inline. */
static inline int64_t round_even(double x)
{
    RS_ASSERT(fabs(x) <= 0x1p22); /* rs_project's clamp to the guard band */
#ifdef __SSE2__
    return (int64_t)_mm_cvtsd_si64(_mm_set_sd(x));
#else
    return (int64_t)llrint(x);
#endif
}

/* Project clip-space vertex cv to snapped screen space; false when w <= 0 or the result is not finite. */
bool rs_project(const rs_job *j, const rs_cvert *cv, rs_svert *v)
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
static int64_t poly_area(const rs_svert *v, int n)
{
    int64_t s = 0;
    for (int i = 1; i + 1 < n; i++)
        s += (v[i].x - v[0].x) * (v[i + 1].y - v[0].y) - (v[i].y - v[0].y) * (v[i + 1].x - v[0].x);
    RS_ASSERT(n <= RS_MAX_POLY && rs_within(s, 51)); /* the bit budget above */
    return s;
}

/* Fill slot values of attribute block at: v0 from a, d1 = b - a, d2 = c - a (b, c may be NULL: 0); slots
 * COLOR0/COLOR1 come from `flat` (constant) when it is given.  (Smooth triangles use rs_fill_slot directly.) */
void rs_fill_attr(const rs_job *j, float *at, const rs_vec4 *a, const rs_vec4 *b, const rs_vec4 *c,
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

/* fmax for doubles, inline (the libm call costs more than the comparison): a NaN argument gives the other. */
static inline double dmax(double a, double b) { return a > b || isnan(b) ? a : b; }

/* Depth and perspective planes of triangle v[0..3) with doubled area `area2` (1/256^2 px^2 units).  The double
 * operations are those of the scalar formulas (noted per line), grouped into 2- and 4-lane vectors. */
void rs_tri_planes(const rs_job *j, const rs_svert *const v[3], int64_t area2, rs_tri *t)
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

/* Emit triangle v[0..3) of doubled area `area` > 0 (clockwise) with its pixel box, edges, planes and slots; back:
 * the input triangle was counter-clockwise (two-sided stencil). */
static void emit_front(const rs_job *j, rs_chunk *c, const rs_svert *const v[3], int64_t area, const rs_vec4 *flat,
                       bool back)
{
    int64_t mnx = v[0]->x, mxx = v[0]->x, mny = v[0]->y, mxy = v[0]->y;
    for (int i = 1; i < 3; i++) {
        mnx = v[i]->x < mnx ? v[i]->x : mnx; mxx = v[i]->x > mxx ? v[i]->x : mxx;
        mny = v[i]->y < mny ? v[i]->y : mny; mxy = v[i]->y > mxy ? v[i]->y : mxy;
    }
    int32_t x0, x1, y0, y1;
    rs_pixel_range(j, mnx + j->cx, mxx + j->cx, j->sx0, j->sx1, &x0, &x1);
    rs_pixel_range(j, mny + j->cy, mxy + j->cy, j->sy0, j->sy1, &y0, &y1);
    if (x0 > x1 || y0 > y1) return;
    float *at;
    rs_prim *p = push(j, c, x0, y0, x1, y1, &at);
    if (!p) return;
    rs_count_work(c, area, x0, y0, x1, y1);
    p->kind = RS_K_TRI;
    p->back = back;
    rs_tri_edges(v, &p->u.t);
    p->u.t.vx = (int32_t)v[0]->x;
    p->u.t.vy = (int32_t)v[0]->y;
    rs_tri_planes(j, v, area, &p->u.t);
    if (flat) rs_fill_attr(j, at, v[0]->a, v[1]->a, v[2]->a, flat);
    else for (int s = 0; s < j->n_slots; s++) rs_fill_slot(at + s * RS_ATTR_STRIDE, &v[0]->a[j->slot[s]],
                                                         &v[1]->a[j->slot[s]], &v[2]->a[j->slot[s]]);
}

/* Emit fan triangle (a, b, c) of a polygon whose area has sign `sign`; slivers that snapping made zero or
 * flipped are skipped (they would double-cover).  flat: the provoking vertex's slots, or NULL. */
static void emit_tri(const rs_job *j, rs_chunk *c, const rs_svert *a, const rs_svert *b, const rs_svert *d, int sign,
                     const rs_vec4 *flat)
{
    int64_t area = (b->x - a->x) * (d->y - a->y) - (b->y - a->y) * (d->x - a->x);
    if (area == 0 || (area > 0) != (sign > 0)) return;
    const rs_svert *v[3] = { a, area > 0 ? b : d, area > 0 ? d : b };
    emit_front(j, c, v, area > 0 ? area : -area, flat, sign < 0);
}

/* Emit the line a -> b: one pixel per major-axis pixel centre in [start, end) (the last pixel is not drawn).
 * Returns false only when the snapped line has zero length (degenerate). */
static bool emit_line(const rs_job *j, rs_chunk *c, const rs_svert *a, const rs_svert *b, const rs_vec4 *flat)
{
    int64_t xa = a->x + j->cx, ya = a->y + j->cy, xb = b->x + j->cx, yb = b->y + j->cy;
    RS_ASSERT(rs_within(xa, 23) && rs_within(ya, 23) && rs_within(xb, 23) && rs_within(yb, 23));
    int64_t dx = xb - xa, dy = yb - ya;
    if (dx == 0 && dy == 0) return false;
    bool xm = llabs(dx) >= llabs(dy);
    int64_t ma = xm ? xa : ya, mb = xm ? xb : yb;
    int64_t i0, i1;
    if (mb > ma) { i0 = rs_ceil_div(ma, RS_SUB); i1 = rs_ceil_div(mb, RS_SUB) - 1; }
    else { i0 = rs_floor_div(mb, RS_SUB) + 1; i1 = rs_floor_div(ma, RS_SUB); }
    const rs_svert *s = mb > ma ? a : b, *e = mb > ma ? b : a;   /* walk towards +major */
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
    rs_fill_attr(j, at, s->a, e->a, NULL, flat);
    return true;
}

/* Emit a one-pixel point at the pixel centre nearest to v (ties towards +x / +y), if inside the scissor. */
static void emit_point(const rs_job *j, rs_chunk *c, const rs_svert *v, const rs_vec4 *flat)
{
    int64_t px = rs_floor_div(v->x + j->cx + RS_SUB / 2, RS_SUB), py = rs_floor_div(v->y + j->cy + RS_SUB / 2, RS_SUB);
    if (px < j->sx0 || px >= j->sx1 || py < j->sy0 || py >= j->sy1) return;
    float *at;
    rs_prim *p = push(j, c, (int32_t)px, (int32_t)py, (int32_t)px, (int32_t)py, &at);
    if (!p) return;
    p->kind = RS_K_POINT;
    p->u.p.z = v->z + j->st->depth_bias;
    rs_fill_attr(j, at, v->a, NULL, NULL, flat);
}

/* The homogeneous position of a pre-transformed vertex (X, Y, Z, RHW) (rs_state.pretransformed): w = 1 / RHW and
 * (X - centre, Y - centre, Z) times w, which the job's pretransformed projection maps back to X, Y (in 1/256 px
 * from the centre) and depth Z; false when not finite (RHW 0, say). */
static bool pretransformed_pos(const rs_job *j, const rs_vec4 *p, double *h)
{
    double w = 1.0 / (double)p->w;
    h[0] = ((double)p->x - (double)j->cx / RS_SUB) * w;
    h[1] = ((double)p->y - (double)j->cy / RS_SUB) * w;
    h[2] = (double)p->z * w;
    h[3] = w;
    return isfinite(h[0]) && isfinite(h[1]) && isfinite(h[2]) && isfinite(h[3]);
}

/* Load n input vertices into clip vertices; false if a position is not finite.  *and / *or: outcodes of the
 * job's clip planes (clip_mask). */
static bool load(const rs_job *j, const rs_vertex *const *v, int n, rs_cvert *cv, unsigned *oand, unsigned *oor)
{
    *oand = ~0u;
    *oor = 0;
    for (int i = 0; i < n; i++) {
        const rs_vec4 *p = &v[i]->pos;
        if (!isfinite(p->x) || !isfinite(p->y) || !isfinite(p->z) || !isfinite(p->w)) return false;
        cv[i] = (rs_cvert){ .p = { p->x, p->y, p->z, p->w }, .a = v[i]->attr, .edge = true, .orig = true };
        if (j->st->pretransformed && !pretransformed_pos(j, p, cv[i].p)) return false;
        unsigned oc = rs_outcode(j, cv[i].p) & j->clip_mask;
        *oand &= oc;
        *oor |= oc;
    }
    return true;
}

/* Draw the clipped, projected polygon pv[0..n) of one input triangle according to the fill mode. */
static void emit_polygon(const rs_job *j, rs_chunk *c, const rs_svert *pv, int n, int64_t area, const rs_vec4 *flat)
{
    int fm = j->st->fill_mode;
    for (int i = 0; i < n; i++) {
        if (fm == RS_FILL_SOLID && i >= 1 && i + 1 < n) emit_tri(j, c, &pv[0], &pv[i], &pv[i + 1], area > 0 ? 1 : -1, flat);
        else if (fm == RS_FILL_WIREFRAME && pv[i].edge) emit_line(j, c, &pv[i], &pv[(i + 1) % n], flat);
        else if (fm == RS_FILL_POINT && pv[i].orig) emit_point(j, c, &pv[i], flat);
    }
}

/* Cull and emit the projected polygon pv[0..n) of input triangle v (the part after clipping and projection). */
void rs_finish_triangle(const rs_job *j, rs_chunk *c, const rs_vertex *const *v, const rs_svert *pv, int n)
{
    int64_t area = poly_area(pv, n);
    if (area == 0) { c->degenerate++; return; }
    int cm = j->st->cull_mode;
    if ((cm == RS_CULL_CCW && area < 0) || (cm == RS_CULL_CW && area > 0)) { c->culled++; return; }
    c->drawn++;
    emit_polygon(j, c, pv, n, area, j->flat ? v[0]->attr : NULL);
}

/* Set up one input triangle v[0..3): clip, project, cull, emit. */
void rs_setup_triangle(const rs_job *j, rs_chunk *c, const rs_vertex *const *v)
{
    rs_cvert poly[RS_MAX_POLY];
    unsigned oand, oor;
    if (!load(j, v, 3, poly, &oand, &oor)) { c->degenerate++; return; }
    if (oand) { c->clipped++; return; }
    rs_clipbuf cb;
    cb.n_pool = 0;
    int n = oor ? rs_clip_poly(j, poly, 3, oor, &cb) : 3;
    if (n < 3) { c->clipped++; return; }
    rs_svert pv[RS_MAX_POLY];
    for (int i = 0; i < n; i++)
        if (!rs_project(j, &poly[i], &pv[i])) { c->clipped++; return; }
    rs_finish_triangle(j, c, v, pv, n);
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
    rs_svert pv[2];
    if (!rs_project(j, &cv[0], &pv[0]) || !rs_project(j, &cv[1], &pv[1])) { c->clipped++; return; }
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
    rs_svert pv;
    if (oor || !rs_project(j, &cv, &pv)) { c->clipped++; return; }
    c->drawn++;
    emit_point(j, c, &pv, NULL);
}

void rs_setup_chunk(const rs_job *j, rs_chunk *c)
{
    c->n = 0;
    c->culled = c->clipped = c->degenerate = c->drawn = c->work = 0;
    c->oom = false;
    if (!fit_attr(j, c)) return;
    size_t vpp = j->prim == RS_PRIM_TRIANGLES ? 3 : (j->prim == RS_PRIM_LINES ? 2 : 1);
    if (vpp == 3 && j->pv && j->idx) { /* the shared pass's triangles: indices straight to the projected vertices */
        j->kern->setup_shared(j, c);
        return;
    }
    for (size_t k = c->first; k < c->first + c->count && !c->oom; k++) {
        const rs_vertex *v[3];
        uint32_t id[3];
        for (size_t i = 0; i < vpp; i++) {
            id[i] = (uint32_t)(j->idx ? j->idx[k * vpp + i] : k * vpp + i);
            v[i] = &j->verts[id[i]];
        }
        if (vpp == 3) rs_setup_triangle(j, c, v);
        else if (vpp == 2) setup_line(j, c, v);
        else setup_point(j, c, v);
    }
}
