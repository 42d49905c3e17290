/* tess/lod.c -- per-edge levels of detail (tess/tess.h, "adaptive level of detail"): the mesh's edges keyed by their
 * welded end points, and one level per edge from that edge alone, so both of its triangles agree. */
#include "tess_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One triangle corner's edge: welded ends a < b, the triangle and the edge's index k in it. */
typedef struct corner_edge { uint32_t a, b, tri, k; } corner_edge;

static int corner_edge_cmp(const void *x, const void *y)
{
    const corner_edge *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    if (p->tri != q->tri) return p->tri < q->tri ? -1 : 1;
    return p->k < q->k ? -1 : (p->k > q->k);
}

void tess_lod_edges_free(tess_lod_edges *e)
{
    free(e->ends), free(e->nrm), free(e->faces), free(e->n_faces), free(e->tri_edge), free(e->level);
    memset(e, 0, sizeof *e);
}

/* The normal triangle t has at the corner welded to w. */
static float3 corner_normal(const is_mesh *m, uint32_t t, uint32_t w)
{
    for (int c = 0; c < 3; c++)
        if (m->welded[3 * (size_t)t + c] == w) return m->normals[m->indices[3 * (size_t)t + c]];
    return f3(0, 0, 0);
}

/* Sorted corner edges c[0..n) in; the unique edges written to e (arrays allocated by the caller). */
static void fill_edges(const is_mesh *m, const corner_edge *c, size_t n, tess_lod_edges *e)
{
    size_t k = 0;
    for (size_t i = 0; i < n; k++) {
        size_t j = i;
        e->ends[k][0] = c[i].a, e->ends[k][1] = c[i].b;
        e->nrm[k][0] = corner_normal(m, c[i].tri, c[i].a), e->nrm[k][1] = corner_normal(m, c[i].tri, c[i].b);
        e->faces[k][0] = e->faces[k][1] = UINT32_MAX;
        for (; j < n && c[j].a == c[i].a && c[j].b == c[i].b; j++) {
            if (j - i < 2) e->faces[k][j - i] = c[j].tri;
            e->tri_edge[3 * (size_t)c[j].tri + c[j].k] = (uint32_t)k;
        }
        e->n_faces[k] = (uint32_t)(j - i);
        i = j;
    }
    e->n_edges = k;
}

int tess_lod_edges_build(const is_mesh *m, tess_lod_edges *e, char *err, size_t errlen)
{
    memset(e, 0, sizeof *e);
    const size_t n = 3 * m->n_triangles;
    corner_edge *c = malloc(n * sizeof *c);
    e->ends = malloc(n * sizeof *e->ends), e->nrm = malloc(n * sizeof *e->nrm);
    e->faces = malloc(n * sizeof *e->faces), e->n_faces = malloc(n * sizeof *e->n_faces);
    e->tri_edge = malloc(n * sizeof *e->tri_edge), e->level = malloc(n ? n : 1);
    if (!c || !e->ends || !e->nrm || !e->faces || !e->n_faces || !e->tri_edge || !e->level) {
        free(c);
        tess_lod_edges_free(e);
        return snprintf(err, errlen, "%s: out of memory for the edges of %zu triangles", m->name, m->n_triangles), -1;
    }
    for (size_t i = 0; i < n; i++) {
        uint32_t t = (uint32_t)(i / 3), k = (uint32_t)(i % 3);
        uint32_t a = m->welded[i], b = m->welded[3 * (size_t)t + (k + 1) % 3];
        c[i] = (corner_edge){a < b ? a : b, a < b ? b : a, t, k};
    }
    qsort(c, n, sizeof *c, corner_edge_cmp);
    fill_edges(m, c, n, e);
    free(c);
    return 0;
}

/* A level from a real number of segments: rounded up, clamped to the parameters' range. */
static int clamp_level(const tess_lod_params *p, double x)
{
    if (!(x < (double)p->max_level)) return p->max_level; /* NaN too */
    int l = (int)ceil(x);
    return l < p->min_level ? p->min_level : l > p->max_level ? p->max_level : l;
}

/* Object position in, pixel position out; false when it is not in front of the eye. */
static bool to_pixels(const tess_lod_params *p, float3 v, double *x, double *y)
{
    float4 c = mul4(f4_of(v, 1.0f), &p->wvp);
    if (!(c.w > 1e-6f)) return false;
    *x = (double)c.x / c.w * 0.5 * p->width, *y = (double)c.y / c.w * 0.5 * p->height;
    return true;
}

/* The N-Patch's control points of the border curve from (pa, na) to (pb, nb): b300, b210, b120, b030. */
static void edge_polygon(float3 pa, float3 na, float3 pb, float3 nb, float3 q[4])
{
    float wab = dot3(sub3(pb, pa), na), wba = dot3(sub3(pa, pb), nb);
    q[0] = pa, q[3] = pb;
    q[1] = scale3(sub3(add3(scale3(pa, 2.0f), pb), scale3(na, wab)), 1.0f / 3.0f);
    q[2] = scale3(sub3(add3(scale3(pb, 2.0f), pa), scale3(nb, wba)), 1.0f / 3.0f);
}

/* Edge k's level as p says (without the silhouette rule). */
static int edge_level(const tess_lod_params *p, const is_mesh *m, const tess_lod_edges *e, size_t k)
{
    const float3 pa = m->positions[e->ends[k][0]], pb = m->positions[e->ends[k][1]];
    if (p->mode == TESS_LOD_DISTANCE) {
        float3 mid = scale3(add3(pa, pb), 0.5f);
        float4 v = mul4(f4_of(mid, 1.0f), &p->world_view);
        return v.z > 0.0f ? clamp_level(p, (double)p->max_level * p->ref_depth / v.z) : p->max_level;
    }
    float3 q[4];
    edge_polygon(pa, e->nrm[k][0], pb, e->nrm[k][1], q);
    double len = 0.0, x0, y0, x1, y1;
    if (!to_pixels(p, q[0], &x0, &y0)) return p->max_level;
    for (int i = 1; i < 4; i++, x0 = x1, y0 = y1) {
        if (!to_pixels(p, q[i], &x1, &y1)) return p->max_level;
        len += hypot(x1 - x0, y1 - y0);
    }
    return clamp_level(p, len / p->target_px);
}

/* Triangle t's facing in view space: the sign of its normal against the direction to the eye (+1, -1, 0). */
static int facing(const tess_lod_params *p, const is_mesh *m, uint32_t t)
{
    float3 v[3];
    for (int c = 0; c < 3; c++) v[c] = f3_of(mul4(f4_of(m->positions[m->indices[3 * (size_t)t + c]], 1.0f), &p->world_view));
    double f = dot3(cross3(sub3(v[1], v[0]), sub3(v[2], v[0])), neg3(v[0]));
    return (f > 0) - (f < 0);
}

void tess_lod_levels(const tess_lod_params *p, const is_mesh *m, tess_lod_edges *e, uint64_t *hist)
{
    memset(hist, 0, (CORE_LOD_MAX_LEVEL + 1) * sizeof *hist);
    for (size_t k = 0; k < e->n_edges; k++) {
        int l = p->mode == TESS_LOD_UNIFORM ? p->max_level : edge_level(p, m, e, k);
        if (p->silhouette && e->n_faces[k] == 2 && facing(p, m, e->faces[k][0]) * facing(p, m, e->faces[k][1]) < 0)
            l = p->max_level;
        e->level[k] = (uint8_t)l;
        hist[l]++;
    }
}
