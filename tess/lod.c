/* tess/lod.c -- per-edge levels of detail (tess/tess.h, "adaptive level of detail"): the mesh's welded edges
 * (meshes.h's edge table), and one level per edge from that edge alone, so both of its triangles agree. */
#include "tess_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void tess_lod_edges_free(tess_lod_edges *e)
{
    if (!e) return;
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

int tess_lod_edges_build(const is_mesh *m, tess_lod_edges *e, char *err, size_t errlen)
{
    if (!e) return snprintf(err, errlen, "tess_lod_edges_build: NULL edges"), -1;
    memset(e, 0, sizeof *e);
    if (!m || (m->n_triangles && (!m->edges || !m->tri_edge || !m->welded || !m->normals)))
        return snprintf(err, errlen, "tess_lod_edges_build: no mesh, or one without its edge table"), -1;
    const size_t ne = m->n_edges, nt3 = 3 * m->n_triangles;
    e->ends = malloc((ne ? ne : 1) * sizeof *e->ends), e->nrm = malloc((ne ? ne : 1) * sizeof *e->nrm);
    e->faces = malloc((ne ? ne : 1) * sizeof *e->faces), e->n_faces = malloc((ne ? ne : 1) * sizeof *e->n_faces);
    e->tri_edge = malloc((nt3 ? nt3 : 1) * sizeof *e->tri_edge), e->level = malloc(ne ? ne : 1);
    if (!e->ends || !e->nrm || !e->faces || !e->n_faces || !e->tri_edge || !e->level) {
        tess_lod_edges_free(e);
        return snprintf(err, errlen, "%s: out of memory for the edges of %zu triangles", m->name, m->n_triangles), -1;
    }
    for (size_t k = 0; k < ne; k++) {   /* the mesh's welded edges, with the normals of their first triangle */
        const is_mesh_edge *E = &m->edges[k];
        e->ends[k][0] = E->ends[0], e->ends[k][1] = E->ends[1];
        e->faces[k][0] = E->faces[0], e->faces[k][1] = E->faces[1];
        e->n_faces[k] = E->n_faces;
        e->nrm[k][0] = corner_normal(m, E->faces[0], E->ends[0]), e->nrm[k][1] = corner_normal(m, E->faces[0], E->ends[1]);
    }
    memcpy(e->tri_edge, m->tri_edge, nt3 * sizeof *e->tri_edge);
    e->n_edges = ne;
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

/* The projected control polygon x[0..4), y[0..4) of an edge's cubic in; the segments (real) for which its polyline
 * lies within `target` pixels of the cubic (tess.h, the deviation mode): sqrt(3/4 max|second difference| / target). */
static double deviation_segments(const double x[4], const double y[4], double target)
{
    const double d1 = hypot(x[0] - 2.0 * x[1] + x[2], y[0] - 2.0 * y[1] + y[2]);
    const double d2 = hypot(x[1] - 2.0 * x[2] + x[3], y[1] - 2.0 * y[2] + y[3]);
    return sqrt(0.75 * (d1 > d2 ? d1 : d2) / target);
}

/* A vertex in pixels (to_pixels; ok false: not in front of the eye). */
typedef struct vpix { double x, y; bool ok; } vpix;

/* m's vertices in pixels for the modes that project edges (screen, deviation), so that each edge looks its ends up
 * instead of projecting them again (the same doubles); NULL for the other modes or when out of memory (the ends are
 * then projected per edge). */
static vpix *project_vertices(const tess_lod_params *p, const is_mesh *m)
{
    if (p->mode == TESS_LOD_UNIFORM || p->mode == TESS_LOD_DISTANCE || !(p->target_px > 0.0f) || !m->n_vertices)
        return NULL;
    vpix *v = malloc(m->n_vertices * sizeof *v);
    for (size_t i = 0; v && i < m->n_vertices; i++) v[i].ok = to_pixels(p, m->positions[i], &v[i].x, &v[i].y);
    return v;
}

/* Edge k's level as p says (without the silhouette rule); vp: the vertices in pixels, or NULL. */
static int edge_level(const tess_lod_params *p, const is_mesh *m, const tess_lod_edges *e, const vpix *vp, size_t k)
{
    const float3 pa = m->positions[e->ends[k][0]], pb = m->positions[e->ends[k][1]];
    if (p->mode == TESS_LOD_DISTANCE) {
        float3 mid = scale3(add3(pa, pb), 0.5f);
        float4 v = mul4(f4_of(mid, 1.0f), &p->world_view);
        return v.z > 0.0f ? clamp_level(p, (double)p->max_level * p->ref_depth / v.z) : p->max_level;
    }
    if (!(p->target_px > 0.0f)) return p->max_level;   /* no pixels per segment (0, negative, NaN): the finest */
    float3 q[4];
    edge_polygon(pa, e->nrm[k][0], pb, e->nrm[k][1], q);
    double x[4], y[4];
    if (vp) {   /* the ends looked up, the inner control points projected */
        const vpix *a = &vp[e->ends[k][0]], *b = &vp[e->ends[k][1]];
        if (!a->ok || !b->ok || !to_pixels(p, q[1], &x[1], &y[1]) || !to_pixels(p, q[2], &x[2], &y[2]))
            return p->max_level;
        x[0] = a->x, y[0] = a->y, x[3] = b->x, y[3] = b->y;
    } else {
        for (int i = 0; i < 4; i++)
            if (!to_pixels(p, q[i], &x[i], &y[i])) return p->max_level;
    }
    if (p->mode == TESS_LOD_DEVIATION) return clamp_level(p, deviation_segments(x, y, p->target_px));
    double len = 0.0;
    for (int i = 1; i < 4; i++) len += hypot(x[i] - x[i - 1], y[i] - y[i - 1]);
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

/* p with its levels in 1..CORE_LOD_MAX_LEVEL and min_level <= max_level (min lowered to max). */
static tess_lod_params clamped_params(const tess_lod_params *in)
{
    tess_lod_params p = *in;
    p.max_level = p.max_level < 1 ? 1 : p.max_level > CORE_LOD_MAX_LEVEL ? CORE_LOD_MAX_LEVEL : p.max_level;
    p.min_level = p.min_level < 1 ? 1 : p.min_level > p.max_level ? p.max_level : p.min_level;
    return p;
}

void tess_lod_levels(const tess_lod_params *params, const is_mesh *m, tess_lod_edges *e, uint64_t *hist)
{
    if (!params || !m || !e || !hist) return;
    memset(hist, 0, (CORE_LOD_MAX_LEVEL + 1) * sizeof *hist);
    const tess_lod_params clamped = clamped_params(params), *p = &clamped;
    vpix *vp = project_vertices(p, m);
    for (size_t k = 0; k < e->n_edges; k++) {
        int l = p->mode == TESS_LOD_UNIFORM ? p->max_level : edge_level(p, m, e, vp, k);
        if (p->silhouette && e->n_faces[k] == 2 && facing(p, m, e->faces[k][0]) * facing(p, m, e->faces[k][1]) < 0)
            l = p->max_level;
        e->level[k] = (uint8_t)l;
        hist[l]++;
    }
    free(vp);
}
