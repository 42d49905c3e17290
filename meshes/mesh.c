/* meshes/mesh.c -- mesh creation: validation, degenerate triangles, welding, normals; stats, instances. */
#include "meshes.h"
#include "mesh_internal.h"

#include "../core/hlsl.h"
#include "../vs/vs.h"   /* VS_IN_*: the registers of Listing 1.1.2 the declaration fills */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <meshoptimizer.h>

/* Height / longest edge below which a triangle counts as collinear (about FLT_EPSILON: its float normal
 * would be rounding noise). */
#define DEGENERATE_RATIO 1e-7
/* File normals shorter than this (or non-finite) are replaced: only zero and denormal ones, whose direction
 * float cannot hold.  Any other length is normalized in double: a normal is a direction, and a file that stores
 * area-weighted normals of a mesh in micrometres or light years must not lose them (scale invariance). */
#define MIN_NORMAL_LENGTH ((double)FLT_MIN)

/* Write a formatted message into err (if any). */
void mesh_set_err(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

/* mesh_warn: see mesh_internal.h. */
void mesh_warn(const is_mesh_options *opt, const char *fmt, ...)
{
    if (!opt || !opt->warn) return;
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    opt->warn(opt->warn_user, msg);
}

/* ------------------------------------------------ small double math ------------------------------------------------ */

typedef struct d3 { double x, y, z; } d3;

/* float3 -> double vector. */
static d3 d3_of(float3 a) { return (d3){a.x, a.y, a.z}; }
/* a - b. */
static d3 d3_sub(d3 a, d3 b) { return (d3){a.x - b.x, a.y - b.y, a.z - b.z}; }
/* a . b. */
static double d3_dot(d3 a, d3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/* a x b. */
static d3 d3_cross(d3 a, d3 b)
{
    return (d3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/* a / |a| as float3, or zero when |a| is zero or not finite. */
static float3 d3_unit(d3 a)
{
    double l = sqrt(d3_dot(a, a));
    if (!(l > 0.0) || !isfinite(l)) return f3(0.0f, 0.0f, 0.0f);
    return f3((float)(a.x / l), (float)(a.y / l), (float)(a.z / l));
}

/* Whether all components are finite. */
static bool finite3(float3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

/* mesh_compute_face_normal: see meshes.h. */
float3 mesh_compute_face_normal(float3 v0, float3 v1, float3 v2)
{
    d3 p0 = d3_of(v0);
    return d3_unit(d3_cross(d3_sub(d3_of(v1), p0), d3_sub(d3_of(v2), p0)));
}

/* ------------------------------------------------ allocation ------------------------------------------------ */

/* mesh_free: see meshes.h. */
void mesh_free(is_mesh *m)
{
    if (!m) return;
    free(m->positions);
    free(m->normals);
    free(m->texcoords);
    free(m->indices);
    free(m->welded);
    free(m->opposite);
    free(m->edges);
    free(m->tri_edge);
    memset(m, 0, sizeof *m);
}

/* Allocate the arrays of m for nv vertices and nt triangles; false when out of memory. */
static bool mesh_alloc(is_mesh *m, size_t nv, size_t nt)
{
    m->n_vertices = nv;
    m->n_triangles = nt;
    m->positions = malloc((nv ? nv : 1) * sizeof(float3));
    m->normals = malloc((nv ? nv : 1) * sizeof(float3));
    m->texcoords = calloc(nv ? nv : 1, sizeof(float2));
    m->indices = malloc((nt ? nt : 1) * 3 * sizeof(uint32_t));
    m->welded = malloc((nt ? nt : 1) * 3 * sizeof(uint32_t));
    m->opposite = malloc((nt ? nt : 1) * 3 * sizeof(uint32_t));
    return m->positions && m->normals && m->texcoords && m->indices && m->welded && m->opposite;
}

/* ------------------------------------------------ validation ------------------------------------------------ */

/* Check sizes, indices, positions and texcoords of the input; the first bad element is reported. */
static int validate(const char *label, const is_mesh_data *in, char *err, size_t errlen)
{
    if (in->n_vertices >= UINT32_MAX || in->n_triangles > (SIZE_MAX / 16) / 3) {
        mesh_set_err(err, errlen, "%s: too large (%zu vertices, %zu triangles; at most 2^32-1 vertices)", label,
                in->n_vertices, in->n_triangles);
        return IS_MESH_ERR_INVALID;
    }
    if (in->n_triangles == 0 || in->n_vertices == 0) {
        mesh_set_err(err, errlen, "%s: no triangles", label);
        return IS_MESH_ERR_EMPTY;
    }
    if (!in->positions || !in->indices) {
        mesh_set_err(err, errlen, "%s: missing positions or indices", label);
        return IS_MESH_ERR_ARG;
    }
    for (size_t i = 0; i < 3 * in->n_triangles; i++) {
        if (in->indices[i] >= in->n_vertices) {
            mesh_set_err(err, errlen, "%s: triangle %zu, corner %zu: vertex index %u is out of range (%zu vertices)",
                    label, i / 3, i % 3, in->indices[i], in->n_vertices);
            return IS_MESH_ERR_INVALID;
        }
    }
    for (size_t v = 0; v < in->n_vertices; v++) {
        float3 p = in->positions[v];
        if (!finite3(p)) {
            mesh_set_err(err, errlen, "%s: vertex %zu has a non-finite position (%g, %g, %g)", label, v, p.x, p.y, p.z);
            return IS_MESH_ERR_INVALID;
        }
        if (in->texcoords && !(isfinite(in->texcoords[v].x) && isfinite(in->texcoords[v].y))) {
            mesh_set_err(err, errlen, "%s: vertex %zu has a non-finite texcoord (%g, %g)", label, v,
                    in->texcoords[v].x, in->texcoords[v].y);
            return IS_MESH_ERR_INVALID;
        }
    }
    return IS_MESH_OK;
}

/* ------------------------------------------------ degenerate triangles ------------------------------------------------ */

/* Repeated index, zero or non-finite area, or collinear: height <= DEGENERATE_RATIO x longest edge (in double,
 * so huge coordinates do not overflow). */
static bool triangle_degenerate(const float3 *pos, const uint32_t *t)
{
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return true;
    d3 p0 = d3_of(pos[t[0]]), p1 = d3_of(pos[t[1]]), p2 = d3_of(pos[t[2]]);
    d3 e0 = d3_sub(p1, p0), e1 = d3_sub(p2, p0), e2 = d3_sub(p2, p1);
    d3 c = d3_cross(e0, e1);
    double a2 = d3_dot(c, c);                  /* (2 area)^2 */
    double l2 = fmax(d3_dot(e0, e0), fmax(d3_dot(e1, e1), d3_dot(e2, e2)));
    if (!(a2 > 0.0) || !isfinite(a2) || !isfinite(l2)) return true;
    return a2 <= DEGENERATE_RATIO * DEGENERATE_RATIO * l2 * l2;
}

/* Copy the non-degenerate triangles of `in` into m->indices; returns how many were kept. */
static size_t keep_triangles(is_mesh *m, const is_mesh_data *in)
{
    size_t kept = 0;
    for (size_t t = 0; t < in->n_triangles; t++) {
        const uint32_t *tri = in->indices + 3 * t;
        if (triangle_degenerate(in->positions, tri)) continue;
        memcpy(m->indices + 3 * kept, tri, 3 * sizeof(uint32_t));
        kept++;
    }
    return kept;
}

/* Copy the vertices used by m's triangles from `in` (keeping their order), renumbering the indices; fills
 * m->n_vertices.  normal_bad[v] (new numbering) is set where there is no input normal.  false: no memory. */
static bool keep_vertices(is_mesh *m, const is_mesh_data *in, bool *normal_bad)
{
    uint32_t *map = malloc(in->n_vertices * sizeof(uint32_t));
    if (!map) return false;
    memset(map, 0xff, in->n_vertices * sizeof(uint32_t));
    for (size_t i = 0; i < 3 * m->n_triangles; i++) map[m->indices[i]] = 0;
    size_t nv = 0;
    for (size_t v = 0; v < in->n_vertices; v++) {
        if (map[v] == UINT32_MAX) continue;
        map[v] = (uint32_t)nv;
        m->positions[nv] = in->positions[v];
        m->texcoords[nv] = in->texcoords ? in->texcoords[v] : f2(0.0f, 0.0f);
        m->normals[nv] = in->normals ? in->normals[v] : f3(0.0f, 0.0f, 0.0f);
        normal_bad[nv] = !in->normals;
        nv++;
    }
    for (size_t i = 0; i < 3 * m->n_triangles; i++) m->indices[i] = map[m->indices[i]];
    free(map);
    m->n_vertices = nv;
    return true;
}

/* ------------------------------------------------ welding ------------------------------------------------ */

/* m->welded = shadow index buffer of the positions with -0.0 turned into +0.0.  false: no memory. */
static bool weld(is_mesh *m)
{
    float3 *canon = malloc(m->n_vertices * sizeof(float3));
    if (!canon) return false;
    for (size_t v = 0; v < m->n_vertices; v++) {
        float3 p = m->positions[v];
        canon[v] = f3(p.x + 0.0f, p.y + 0.0f, p.z + 0.0f);   /* -0 + 0 = +0 in round-to-nearest */
    }
    if (m->n_triangles)   /* meshoptimizer asserts its arrays even for no triangle */
        meshopt_generateShadowIndexBuffer(m->welded, m->indices, 3 * m->n_triangles, canon, m->n_vertices,
                                          sizeof(float3), sizeof(float3));
    free(canon);
    return true;
}

/* Number of distinct values in m->welded. */
static size_t count_welded(const is_mesh *m)
{
    bool *seen = calloc(m->n_vertices ? m->n_vertices : 1, sizeof(bool));
    if (!seen) return 0;
    size_t n = 0;
    for (size_t i = 0; i < 3 * m->n_triangles; i++) {
        if (!seen[m->welded[i]]) { seen[m->welded[i]] = true; n++; }
    }
    free(seen);
    return n;
}

/* ------------------------------------------------ normals ------------------------------------------------ */

/* Angle at corner p0 between p1 - p0 and p2 - p0 (radians, double). */
static double corner_angle(d3 p0, d3 p1, d3 p2)
{
    d3 a = d3_sub(p1, p0), b = d3_sub(p2, p0);
    d3 c = d3_cross(a, b);
    return atan2(sqrt(d3_dot(c, c)), d3_dot(a, b));
}

/* Add each triangle's unit face normal, weighted by its corner angles, to acc[welded vertex]; first[w] gets
 * the face normal of the first triangle at w (the fallback when the sum cancels). */
static void accumulate_normals(const is_mesh *m, d3 *acc, d3 *first, bool *has_first)
{
    for (size_t t = 0; t < m->n_triangles; t++) {
        const uint32_t *tri = m->indices + 3 * t;
        d3 p[3] = {d3_of(m->positions[tri[0]]), d3_of(m->positions[tri[1]]), d3_of(m->positions[tri[2]])};
        float3 fn = mesh_compute_face_normal(m->positions[tri[0]], m->positions[tri[1]], m->positions[tri[2]]);
        d3 n = d3_of(fn);
        for (int c = 0; c < 3; c++) {
            uint32_t w = m->welded[3 * t + c];
            double a = corner_angle(p[c], p[(c + 1) % 3], p[(c + 2) % 3]);
            acc[w].x += a * n.x; acc[w].y += a * n.y; acc[w].z += a * n.z;
            if (!has_first[w]) { first[w] = n; has_first[w] = true; }
        }
    }
}

/* Angle-weighted normal per welded vertex, written to every vertex with bad[v] (all when `all`).  Returns the
 * number of vertices written; false-ish (SIZE_MAX) when out of memory. */
static size_t recompute_normals(is_mesh *m, const bool *bad, bool all)
{
    size_t nv = m->n_vertices;
    d3 *acc = calloc(nv, sizeof(d3)), *first = calloc(nv, sizeof(d3));
    bool *has_first = calloc(nv, sizeof(bool));
    uint32_t *canon = malloc(nv * sizeof(uint32_t));
    size_t n = SIZE_MAX;
    if (acc && first && has_first && canon) {
        accumulate_normals(m, acc, first, has_first);
        for (size_t i = 0; i < 3 * m->n_triangles; i++) canon[m->indices[i]] = m->welded[i];
        n = 0;
        for (size_t v = 0; v < nv; v++) {
            if (!all && !bad[v]) continue;
            float3 r = d3_unit(acc[canon[v]]);
            m->normals[v] = (r.x == 0.0f && r.y == 0.0f && r.z == 0.0f) ? d3_unit(first[canon[v]]) : r;
            n++;
        }
    }
    free(acc); free(first); free(has_first); free(canon);
    return n;
}

/* Normalize the given normals (in double) and flag zero / non-finite ones in bad[]. */
static void normalize_file_normals(is_mesh *m, bool *bad)
{
    for (size_t v = 0; v < m->n_vertices; v++) {
        if (bad[v]) continue;
        float3 n = m->normals[v];
        d3 d = d3_of(n);
        double l = sqrt(d3_dot(d, d));
        if (!finite3(n) || !(l > MIN_NORMAL_LENGTH) || !isfinite(l)) { bad[v] = true; continue; }
        m->normals[v] = d3_unit(d);
    }
}

/* Set m's normals from the input (normalized) or recomputed; fills the normal counts of stats. */
static int make_normals(is_mesh *m, bool have_file_normals, bool force, bool *bad)
{
    bool all = force || !have_file_normals;
    if (!all) normalize_file_normals(m, bad);
    size_t n = recompute_normals(m, bad, all);
    if (n == SIZE_MAX) return IS_MESH_ERR_NOMEM;
    m->stats.normals_computed = all;
    m->stats.normals_replaced = all ? 0 : n;
    return IS_MESH_OK;
}

/* ------------------------------------------------ adjacency ------------------------------------------------ */

/* One directed triangle edge, keyed by its welded end points (a < b). */
typedef struct edge_rec {
    uint32_t a, b;        /* welded vertex ids, a < b */
    uint32_t tri;
    uint8_t k;            /* edge index 0..2 within tri */
    uint8_t forward;      /* 1 when the triangle runs a -> b */
} edge_rec;

/* Order by (a, b, tri, k): a total order, so the result does not depend on qsort's stability. */
static int edge_cmp(const void *pa, const void *pb)
{
    const edge_rec *x = pa, *y = pb;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    if (x->b != y->b) return x->b < y->b ? -1 : 1;
    if (x->tri != y->tri) return x->tri < y->tri ? -1 : 1;
    return (int)x->k - (int)y->k;
}

/* One run r[0..n) of records sharing a welded edge into the table (edge index e), counting the edge's kind. */
static void add_edge(is_mesh *m, const edge_rec *r, size_t n, uint32_t e)
{
    is_mesh_edge *E = &m->edges[e];
    *E = (is_mesh_edge){{r[0].a, r[0].b}, {r[0].tri, n > 1 ? r[1].tri : UINT32_MAX}, (uint32_t)n};
    for (size_t i = 0; i < n; i++) m->tri_edge[3 * (size_t)r[i].tri + r[i].k] = e;
    if (n == 2 && r[0].forward == r[1].forward) m->stats.inconsistent_edges++;
    if (n == 1) m->stats.boundary_edges++;
    else if (n > 2) m->stats.nonmanifold_edges++;
}

/* The opposite vertex of edge k of triangle t from the edge table: the third vertex of the one neighbour across
 * it, or t's own third vertex on a boundary or non-manifold edge. */
static uint32_t opposite_of(const is_mesh *m, size_t t, int k)
{
    const is_mesh_edge *E = &m->edges[m->tri_edge[3 * t + k]];
    size_t other = E->n_faces == 2 ? (E->faces[0] == t ? E->faces[1] : E->faces[0]) : t;
    int ok = k;
    if (other != t)
        for (int j = 2; j >= 0; j--)   /* the first corner of `other` on the edge */
            if (m->tri_edge[3 * other + j] == m->tri_edge[3 * t + k]) ok = j;
    return m->indices[3 * other + (ok + 2) % 3];
}

/* The welded-edge table (edges, tri_edge) and the opposite vertices from a sorted edge list.
 * meshopt_generateAdjacencyIndexBuffer (0.18) is not used: for a boundary edge it returns the edge's first
 * vertex (not the third one we want), it finds neighbours only through the reversed directed edge (so
 * inconsistently wound neighbours look like boundaries), and on non-manifold edges it picks whichever triangle
 * its hash table saw first, without telling us. */
static int build_adjacency(is_mesh *m)
{
    size_t ne = 3 * m->n_triangles;
    edge_rec *e = malloc((ne ? ne : 1) * sizeof(edge_rec));
    free(m->edges), free(m->tri_edge);
    m->edges = malloc((ne ? ne : 1) * sizeof *m->edges);
    m->tri_edge = malloc((ne ? ne : 1) * sizeof *m->tri_edge);
    m->n_edges = 0;
    if (!e || !m->edges || !m->tri_edge) return free(e), IS_MESH_ERR_NOMEM;
    for (size_t t = 0; t < m->n_triangles; t++) {
        for (int k = 0; k < 3; k++) {
            uint32_t a = m->welded[3 * t + k], b = m->welded[3 * t + (k + 1) % 3];
            e[3 * t + k] = (edge_rec){a < b ? a : b, a < b ? b : a, (uint32_t)t, (uint8_t)k, (uint8_t)(a < b)};
        }
    }
    qsort(e, ne, sizeof(edge_rec), edge_cmp);
    m->stats.edges = m->stats.boundary_edges = m->stats.nonmanifold_edges = m->stats.inconsistent_edges = 0;
    for (size_t i = 0, j; i < ne; i = j) {
        for (j = i + 1; j < ne && e[j].a == e[i].a && e[j].b == e[i].b; j++) {}
        add_edge(m, e + i, j - i, (uint32_t)m->n_edges++);
    }
    m->stats.edges = m->n_edges;
    free(e);
    for (size_t t = 0; t < m->n_triangles; t++)
        for (int k = 0; k < 3; k++) m->opposite[3 * t + k] = opposite_of(m, t, k);
    return IS_MESH_OK;
}

/* mesh_update_topology: see meshes.h. */
int mesh_update_topology(is_mesh *m, char *err, size_t errlen)
{
    if (!m) {
        mesh_set_err(err, errlen, "mesh_update_topology: NULL mesh");
        return IS_MESH_ERR_ARG;
    }
    if (m->n_triangles && (!m->indices || !m->positions || !m->welded || !m->opposite)) {
        mesh_set_err(err, errlen, "%s: not a mesh of mesh_create (missing positions, indices or their topology)",
                     m->name);
        return IS_MESH_ERR_ARG;
    }
    for (size_t i = 0; i < 3 * m->n_triangles; i++)   /* the caller may have changed them */
        if (m->indices[i] >= m->n_vertices) {
            mesh_set_err(err, errlen, "%s: triangle %zu, corner %zu: vertex index %u is out of range (%zu vertices)",
                         m->name, i / 3, i % 3, m->indices[i], m->n_vertices);
            return IS_MESH_ERR_INVALID;
        }
    if (!weld(m) || build_adjacency(m) != IS_MESH_OK) {
        mesh_set_err(err, errlen, "%s: out of memory building adjacency", m->name);
        return IS_MESH_ERR_NOMEM;
    }
    m->stats.welded_vertices = count_welded(m);
    return IS_MESH_OK;
}

/* ------------------------------------------------ creation ------------------------------------------------ */

/* Warn about what was dropped, replaced or odd in the finished mesh. */
static void report_warnings(const is_mesh *m, const char *label, const is_mesh_options *opt)
{
    const is_mesh_stats *s = &m->stats;
    if (s->degenerates_dropped)
        mesh_warn(opt, "%s: dropped %zu degenerate triangle(s) (repeated vertex, zero area or collinear)", label,
                  s->degenerates_dropped);
    if (s->normals_replaced)
        mesh_warn(opt, "%s: replaced %zu zero, non-finite or missing normal(s) by recomputed ones", label,
                  s->normals_replaced);
    if (s->nonmanifold_edges)
        mesh_warn(opt, "%s: %zu non-manifold edge(s) (3+ triangles): treated like boundaries", label,
                  s->nonmanifold_edges);
    if (s->inconsistent_edges)
        mesh_warn(opt, "%s: %zu edge(s) between inconsistently wound triangles", label, s->inconsistent_edges);
}

/* The steps of mesh_create after validation; m is allocated for the input's sizes. */
static int build(is_mesh *m, const char *label, const is_mesh_data *in, const is_mesh_options *opt,
                 char *err, size_t errlen)
{
    size_t kept = keep_triangles(m, in);
    m->stats.degenerates_dropped = in->n_triangles - kept;
    m->n_triangles = kept;
    if (kept == 0) {
        mesh_set_err(err, errlen, "%s: no triangles left: all %zu are degenerate", label, in->n_triangles);
        return IS_MESH_ERR_EMPTY;
    }
    bool *bad = malloc(in->n_vertices * sizeof(bool));
    int rc = bad && keep_vertices(m, in, bad) ? IS_MESH_OK : IS_MESH_ERR_NOMEM;
    if (rc == IS_MESH_OK) rc = mesh_update_topology(m, err, errlen);
    if (rc == IS_MESH_OK) rc = make_normals(m, in->normals != NULL, opt && opt->recompute_normals, bad);
    free(bad);
    if (rc == IS_MESH_ERR_NOMEM) mesh_set_err(err, errlen, "%s: out of memory", label);
    m->stats.vertices = m->n_vertices;
    m->stats.triangles = m->n_triangles;
    return rc;
}

/* mesh_create: see meshes.h. */
int mesh_create(is_mesh *out, const char *label, const is_mesh_data *in, const is_mesh_options *opt,
                char *err, size_t errlen)
{
    if (!out || !in) {
        mesh_set_err(err, errlen, "mesh_create: NULL argument");
        return IS_MESH_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    if (!label) label = "<mesh>";
    int rc = validate(label, in, err, errlen);
    if (rc != IS_MESH_OK) return rc;
    snprintf(out->name, sizeof out->name, "%s", label);
    if (!mesh_alloc(out, in->n_vertices, in->n_triangles)) {
        mesh_free(out);
        mesh_set_err(err, errlen, "%s: out of memory (%zu vertices, %zu triangles)", label, in->n_vertices,
                in->n_triangles);
        return IS_MESH_ERR_NOMEM;
    }
    rc = build(out, label, in, opt, err, errlen);
    if (rc != IS_MESH_OK) { mesh_free(out); return rc; }
    report_warnings(out, label, opt);
    return IS_MESH_OK;
}

/* mesh_stats: see meshes.h. */
is_mesh_stats mesh_stats(const is_mesh *m) { return m ? m->stats : (is_mesh_stats){0}; }

/* ------------------------------------------------ instances ------------------------------------------------ */

_Static_assert(sizeof(is_patch_instance) == 136, "is_patch_instance must be packed (34 floats)");
_Static_assert(offsetof(is_patch_instance, opp) == 72 && offsetof(is_patch_instance, t) == 108 &&
               offsetof(is_patch_instance, instance_id) == 132, "is_patch_instance layout");

/* mesh_build_instances: see meshes.h. */
size_t mesh_build_instances(const is_mesh *m, is_patch_instance *out)
{
    if (!m || !out) return 0;
    for (size_t t = 0; t < m->n_triangles; t++) {
        is_patch_instance *p = out + t;
        for (int k = 0; k < 3; k++) {
            uint32_t v = m->indices[3 * t + k];
            p->v[k] = m->positions[v];
            p->n[k] = m->normals[v];
            p->opp[k] = m->positions[m->opposite[3 * t + k]];
            p->t[k] = m->texcoords[v];
        }
        p->instance_id = (float)t;
    }
    return m->n_triangles;
}

/* Listing 1.1.2's registers (vs/vs.h's VS_IN_*), each at its field of is_patch_instance. */
#define PI_ELEM(field, type, idx) \
    { 1, (uint16_t)offsetof(is_patch_instance, field), (type), 0, IS_DECLUSAGE_TEXCOORD, (idx) }

_Static_assert(sizeof(is_patch_instance) == 136, "is_patch_instance: 136 bytes without padding (meshes.h)");
const is_vertex_element mesh_patch_declaration[MESH_PATCH_DECLARATION_COUNT] = {
    { 0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0 },
    PI_ELEM(v[0], IS_DECLTYPE_FLOAT3, VS_IN_V0),      PI_ELEM(v[1], IS_DECLTYPE_FLOAT3, VS_IN_V0 + 1),
    PI_ELEM(v[2], IS_DECLTYPE_FLOAT3, VS_IN_V0 + 2),  PI_ELEM(n[0], IS_DECLTYPE_FLOAT3, VS_IN_N0),
    PI_ELEM(n[1], IS_DECLTYPE_FLOAT3, VS_IN_N0 + 1),  PI_ELEM(n[2], IS_DECLTYPE_FLOAT3, VS_IN_N0 + 2),
    PI_ELEM(opp[0], IS_DECLTYPE_FLOAT3, VS_IN_OPP0),  PI_ELEM(opp[1], IS_DECLTYPE_FLOAT3, VS_IN_OPP0 + 1),
    PI_ELEM(opp[2], IS_DECLTYPE_FLOAT3, VS_IN_OPP0 + 2), PI_ELEM(t[0], IS_DECLTYPE_FLOAT2, VS_IN_T0),
    PI_ELEM(t[1], IS_DECLTYPE_FLOAT2, VS_IN_T0 + 1),  PI_ELEM(t[2], IS_DECLTYPE_FLOAT2, VS_IN_T0 + 2),
    PI_ELEM(instance_id, IS_DECLTYPE_FLOAT1, VS_IN_ID),
    IS_DECL_END
};
