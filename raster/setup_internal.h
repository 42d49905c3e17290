/* raster/setup_internal.h -- what the two set-ups of raster/ share: setup.c (the reference set-up, which is the
 * definition: clip, project, snap, cull, emit) and setup_simd.c (its fast path: the shared pass and the four-lane
 * finish).  Private to raster/setup*.c; everything else in raster/ goes through raster_internal.h.
 *
 * Conventions (besides raster_internal.h's): positions are snapped to 1/256 pixel relative to the viewport centre
 * and stay within |x|, |y| <= 2^22 (setup.c's bit budget); a chunk's arrays (prims, ptile, attr) grow together, one
 * entry per pushed primitive, in submission order; the functions that both set-ups call are written once, here
 * (inline, for the per-triangle ones) or in setup.c (rs_*, out of line), so both give the same bytes.
 */
#ifndef INSTESS_SETUP_INTERNAL_H
#define INSTESS_SETUP_INTERNAL_H

#include <string.h>

#include "raster_internal.h"

/* A vertex after projection and snapping. */
typedef struct rs_svert {
    int64_t x, y;            /* 1/256 px relative to the viewport centre */
    float z;                 /* viewport depth */
    double iw;               /* 1 / w */
    const rs_vec4 *a;        /* attribute slots */
    bool edge, orig;
} rs_svert;

typedef float v4f __attribute__((vector_size(16)));
typedef double v4d __attribute__((vector_size(32)));
typedef double v2d __attribute__((vector_size(16)));

/* ---- setup.c: the reference set-up (the shared pass falls back to it, see setup_simd.c) ---- */
/* Grow chunk c's primitive, tile and attribute arrays (doubling); false (and c->oom) when out of memory. */
bool rs_setup_grow(const rs_job *j, rs_chunk *c);
/* Project clip-space vertex cv to snapped screen space; false when w <= 0 or the result is not finite. */
bool rs_project(const rs_job *j, const rs_cvert *cv, rs_svert *v);
/* Fill slot values of attribute block at: v0 from a, d1 = b - a, d2 = c - a (b, c may be NULL: 0); slots
 * COLOR0/COLOR1 come from `flat` (constant) when it is given.  (Smooth triangles use rs_fill_slot directly.) */
void rs_fill_attr(const rs_job *j, float *at, const rs_vec4 *a, const rs_vec4 *b, const rs_vec4 *c,
                  const rs_vec4 *flat);
/* Depth and perspective planes of triangle v[0..3) with doubled area `area2` (1/256^2 px^2 units) into t. */
void rs_tri_planes(const rs_job *j, const rs_svert *const v[3], int64_t area2, rs_tri *t);
/* Cull and emit the projected polygon pv[0..n) of input triangle v (the part after clipping and projection). */
void rs_finish_triangle(const rs_job *j, rs_chunk *c, const rs_vertex *const *v, const rs_svert *pv, int n);
/* Set up one input triangle v[0..3): clip, project, cull, emit (the definition). */
void rs_setup_triangle(const rs_job *j, rs_chunk *c, const rs_vertex *const *v);

/* ---- inline pieces of both set-ups ---- */

/* The ptile entry of a primitive with pixel box [x0, x1] x [y0, y1]. */
static inline uint32_t rs_tile_entry(const rs_job *j, int32_t x0, int32_t y0, int32_t x1, int32_t y1)
{
    const int b = j->tile_bits;
    bool one = ((x0 ^ x1) | (y0 ^ y1)) >> b == 0;
    return one ? (uint32_t)(y0 >> b) * (uint32_t)j->tiles_x + (uint32_t)(x0 >> b) : RS_MULTI_TILE;
}

/* Append one primitive to chunk c, its box and ptile entry left to the caller; returns it (and its attribute
 * block in *attr), NULL when out of memory. */
static inline rs_prim *rs_push_raw(const rs_job *j, rs_chunk *c, float **attr)
{
    if (c->oom) return NULL;
    if (c->n == c->cap && !rs_setup_grow(j, c)) return NULL;
    *attr = c->attr + c->n * (size_t)j->stride;
    return &c->prims[c->n++];
}

/* One interpolated slot: o[3q] = a[q], o[3q+1] = b[q] - a[q], o[3q+2] = c[q] - a[q] (4 lanes, same subtractions). */
static inline void rs_fill_slot(float *o, const rs_vec4 *a, const rs_vec4 *b, const rs_vec4 *c)
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

/* Pixel range [*lo, *hi] whose samples can touch [mn, mx] (1/256 px, absolute), clamped to [s0, s1). */
static inline void rs_pixel_range(const rs_job *j, int64_t mn, int64_t mx, int s0, int s1, int32_t *lo, int32_t *hi)
{
    _Static_assert(RS_SUB == 1 << RS_SUB_BITS, "floor / ceil division by RS_SUB as arithmetic shifts");
    int64_t a = -((j->omax - mn) >> RS_SUB_BITS), b = (mx + j->omax) >> RS_SUB_BITS; /* ceil, floor of / RS_SUB */
    *lo = (int32_t)(a < s0 ? s0 : a);
    *hi = (int32_t)(b > s1 - 1 ? s1 - 1 : b);
}

/* Edge function of the edge a -> b into slot e of t, with the top-left rule folded into ec. */
static inline void rs_tri_edge(const rs_svert *a, const rs_svert *b, int e, rs_tri *t)
{
    int64_t dx = b->x - a->x, dy = b->y - a->y;
    bool top_left = dy < 0 || (dy == 0 && dx > 0);
    RS_ASSERT(rs_within(dx, 23) && rs_within(dy, 23)); /* vertices within 2^22: rs_tri keeps ea, eb in int32 */
    t->ea[e] = (int32_t)-dy;
    t->eb[e] = (int32_t)dx;
    t->ec[e] = -(-dy * a->x + dx * a->y) - (top_left ? 0 : 1);
}

/* Edge functions of triangle v[0..3) (doubled area > 0) into t. */
static inline void rs_tri_edges(const rs_svert *const v[3], rs_tri *t)
{
    rs_tri_edge(v[0], v[1], 0, t);
    rs_tri_edge(v[1], v[2], 1, t);
    rs_tri_edge(v[2], v[0], 2, t);
}

/* Add a triangle of doubled area area2 (1/256^2 px^2) and pixel box [x0, x1] x [y0, y1] to c's work: the
 * smaller of its area and its box, exactly, in RS_WORK_UNIT (saturating; RS_MAX_OVERDRAW). */
static inline void rs_count_work(rs_chunk *c, int64_t area2, int32_t x0, int32_t y0, int32_t x1, int32_t y1)
{
    uint64_t a = (uint64_t)(area2 < 0 ? -area2 : area2);
    uint64_t b = (uint64_t)(x1 - x0 + 1) * (uint64_t)(y1 - y0 + 1) * RS_WORK_UNIT;
    uint64_t w = c->work + (a < b ? a : b);
    c->work = w < c->work ? UINT64_MAX : w;
}

#endif
