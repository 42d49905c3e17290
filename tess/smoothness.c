/* tess/smoothness.c -- smoothness in numbers: normal angles across the mesh's shared edges (its welded-edge table)
 * and the bulge of a patch (tess/tess.h). */
#include "tess_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static bool same3(float3 a, float3 b) { return memcmp(&a, &b, sizeof a) == 0; }

/* The band across an edge where tess_smoothness looks for valleys: offsets j / VALLEY_STEPS_INV, j = 1 ..
 * VALLEY_STEPS, of the way from the edge to each side's opposite corner (up to 1/16). */
#define VALLEY_STEPS 8
#define VALLEY_STEPS_INV 128.0f

/* The angle in degrees between unit vectors a and b (in double, clamped). */
static double angle_deg(float3 a, float3 b)
{
    double d = (double)a.x * b.x + (double)a.y * b.y + (double)a.z * b.z;
    return acos(d > 1.0 ? 1.0 : d < -1.0 ? -1.0 : d) * (180.0 / 3.14159265358979323846);
}

/* The largest valley across the shared edge k of A (edge mk of B, reversed or not) at edge parameter wt: for the
 * points of the two sides s = j / 128 of the way to their opposite corners (j = 1..8), the angle between their
 * real normals where the normals lean towards each other (dot(nA - nB, PB - PA) > 0: a concave fold), else 0. */
static double valley_at(vs_patch p, const vs_triangle *A, int k, const vs_triangle *B, int mk, bool reversed,
                        float wt, const vs_options *ro)
{
    double worst = 0.0;
    float ws = 1.0f - wt;
    for (int j = 1; j <= VALLEY_STEPS; j++) {
        float s = (float)j / VALLEY_STEPS_INV, r = 1.0f - s;
        float ba[3] = {0, 0, 0}, bb[3] = {0, 0, 0};
        ba[k] = r * ws, ba[(k + 1) % 3] = r * wt, ba[(k + 2) % 3] = s;
        bb[mk] = r * (reversed ? wt : ws), bb[(mk + 1) % 3] = r * (reversed ? ws : wt), bb[(mk + 2) % 3] = s;
        float3 pa, pb, na, nb;
        vs_patch_eval(p, A, f3(ba[0], ba[1], ba[2]), ro, &pa, &na, NULL);
        vs_patch_eval(p, B, f3(bb[0], bb[1], bb[2]), ro, &pb, &nb, NULL);
        if (dot3(sub3(na, nb), sub3(pb, pa)) <= 0.0f) continue;   /* leaning apart, or parallel */
        double ang = angle_deg(na, nb);
        if (ang > worst) worst = ang;
    }
    return worst;
}

/* The half-edge (3 t' + k') across edge k of triangle t from the mesh's edge table, or -1 when the edge has not
 * exactly two triangles. */
static int32_t mate_of(const is_mesh *m, size_t t, int k)
{
    uint32_t e = m->tri_edge[3 * t + k];
    const is_mesh_edge *E = &m->edges[e];
    if (E->n_faces != 2) return -1;
    size_t other = E->faces[0] == t ? E->faces[1] : E->faces[0];
    for (int j = 0; j < 3; j++)
        if (m->tri_edge[3 * other + j] == e) return (int32_t)(3 * other + (size_t)j);
    return -1;
}

int tess_smoothness(const is_mesh *m, vs_patch p, const vs_options *o, int spe, vs_smoothness_result *res)
{
    if (!res || !m || !m->positions || !m->edges || !m->tri_edge || m->n_triangles == 0 || spe < 1 ||
        spe > TESS_SMOOTHNESS_MAX_SAMPLES ||
        (unsigned)p >= VS_PATCH_COUNT || m->n_triangles > UINT32_MAX / 3)
        return -1;
    memset(res, 0, sizeof *res);
    const size_t nt = m->n_triangles;
    vs_options ro = o ? *o : vs_default_options();
    ro.normals = VS_NORMALS_REAL;
    vs_triangle *T = calloc(nt, sizeof *T);
    int32_t *mate = malloc(3 * nt * sizeof *mate); /* half-edge index of the other side, -1 if none */
    if (!T || !mate) {
        free(T), free(mate);
        return -1;
    }
    /* bounding box and triangles */
    float3 lo = m->positions[m->indices[0]], hi = lo;
    for (size_t t = 0; t < nt; t++) {
        float3 v[3], n[3];
        for (int k = 0; k < 3; k++) {
            v[k] = m->positions[m->indices[3 * t + k]], n[k] = m->normals[m->indices[3 * t + k]];
            lo = f3(fminf(lo.x, v[k].x), fminf(lo.y, v[k].y), fminf(lo.z, v[k].z));
            hi = f3(fmaxf(hi.x, v[k].x), fmaxf(hi.y, v[k].y), fmaxf(hi.z, v[k].z));
            mate[3 * t + k] = mate_of(m, t, k);
        }
        T[t] = vs_triangle_make(v, n);
        T[t].id = (float)t;
    }
    double diag = sqrt((double)(hi.x - lo.x) * (hi.x - lo.x) + (double)(hi.y - lo.y) * (hi.y - lo.y) +
                       (double)(hi.z - lo.z) * (hi.z - lo.z));
    for (size_t e = 0; e < m->n_edges; e++) {   /* the edges' kinds, from the mesh's edge table */
        uint32_t nf = m->edges[e].n_faces;
        if (nf == 1) res->boundary_edges++;
        else if (nf > 2) res->nonmanifold_edges++;
        else res->shared_edges++;
    }
    /* opposite vertices and the neighbours' normals (PN-AEN) */
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t mt = mate[3 * t + k];
            if (mt < 0) continue;
            const vs_triangle *N = &T[mt / 3];
            int mk = mt % 3;
            T[t].opp[k] = N->v[(mk + 2) % 3];
            for (int e = 0; e < 2; e++) {
                float3 at = T[t].v[(k + e) % 3];
                T[t].nadj[k][e] = same3(N->v[mk], at) ? N->n[mk] : N->n[(mk + 1) % 3];
            }
        }
    /* normals across shared edges, and in a band across them */
    double sum = 0.0, sum_feature = 0.0;
    size_t n_feature = 0;
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t mt = mate[3 * t + k];
            if (mt < 0 || (size_t)mt < 3 * t + (size_t)k) continue; /* each shared edge once */
            const vs_triangle *A = &T[t], *B = &T[mt / 3];
            int mk = mt % 3;
            bool reversed = same3(B->v[mk], A->v[(k + 1) % 3]);
            float3 fa = normalize3(cross3(sub3(A->v[1], A->v[0]), sub3(A->v[2], A->v[0])));
            float3 fb = normalize3(cross3(sub3(B->v[1], B->v[0]), sub3(B->v[2], B->v[0])));
            bool coplanar = fabs((double)dot3(fa, fb)) > 1.0 - 1e-6;
            double *edge_max = coplanar ? &res->max_angle_coplanar_deg : &res->max_angle_feature_deg;
            for (int i = 0; i < spe; i++) {
                float wt = ((float)i + 0.5f) / (float)spe, ws = 1.0f - wt;
                float ba[3] = {0, 0, 0}, bb[3] = {0, 0, 0};
                ba[k] = ws, ba[(k + 1) % 3] = wt;
                bb[mk] = reversed ? wt : ws, bb[(mk + 1) % 3] = reversed ? ws : wt;
                float3 na, nb;
                vs_patch_eval(p, A, f3(ba[0], ba[1], ba[2]), &ro, NULL, &na, NULL);
                vs_patch_eval(p, B, f3(bb[0], bb[1], bb[2]), &ro, NULL, &nb, NULL);
                double ang = angle_deg(na, nb);
                if (ang > res->max_angle_deg) res->max_angle_deg = ang;
                if (ang > *edge_max) *edge_max = ang;
                sum += ang;
                if (!coplanar) sum_feature += ang, n_feature++;
                res->samples++;
                double valley = valley_at(p, A, k, B, mk, reversed, wt, &ro);
                if (valley > res->max_valley_deg) res->max_valley_deg = valley;
            }
        }
    res->mean_angle_deg = res->samples ? sum / (double)res->samples : 0.0;
    res->mean_angle_feature_deg = n_feature ? sum_feature / (double)n_feature : 0.0;
    /* distance from the flat triangle: interior points of the level-8 grid */
    const int L = 8;
    for (size_t t = 0; t < nt && diag > 0.0; t++) {
        float3 f = normalize3(cross3(sub3(T[t].v[1], T[t].v[0]), sub3(T[t].v[2], T[t].v[0])));
        if (!(dot3(f, f) > 0.0f)) continue;
        for (int j = 1; j < L; j++)
            for (int i = 1; i + j < L; i++) {
                float3 b = f3((float)(L - i - j) / L, (float)i / L, (float)j / L);
                float3 P = vs_patch_position(p, &T[t], b, &ro);
                double dist = fabs((double)dot3(sub3(P, T[t].v[0]), f)) / diag;
                if (dist > res->max_distance) res->max_distance = dist;
            }
    }
    free(T), free(mate);
    return 0;
}
