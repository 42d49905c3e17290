/* vs/smoothness.c -- smoothness in numbers: normal angles across shared edges and the bulge of a patch. */
#include "vs_internal.h"

#include "../core/hlsl.h"
#include <stdlib.h>
#include <string.h>

/* One half-edge: triangle t, edge k, endpoint position bits ordered (lo, hi). */
typedef struct half_edge { uint32_t key[6]; uint32_t tri; uint8_t k; } half_edge;

/* The bit pattern of a float3. */
static void bits3(float3 a, uint32_t o[3])
{
    memcpy(&o[0], &a.x, 4);
    memcpy(&o[1], &a.y, 4);
    memcpy(&o[2], &a.z, 4);
}

/* qsort order of half-edges: key, then triangle, then edge. */
static int he_cmp(const void *pa, const void *pb)
{
    const half_edge *a = pa, *b = pb;
    for (int i = 0; i < 6; i++)
        if (a->key[i] != b->key[i]) return a->key[i] < b->key[i] ? -1 : 1;
    if (a->tri != b->tri) return a->tri < b->tri ? -1 : 1;
    return (int)a->k - (int)b->k;
}

static bool same3(float3 a, float3 b) { return memcmp(&a, &b, sizeof a) == 0; }

int vs_smoothness(vs_patch p, const vs_options *o, const float3 *pos, const float3 *nrm, size_t nv,
                  const uint32_t *idx, size_t nt, const float3 *opp, int spe, vs_smoothness_result *res)
{
    if (!res || !pos || !nrm || !idx || nt == 0 || spe < 1 || (unsigned)p >= VS_PATCH_COUNT || nt > UINT32_MAX / 3)
        return -1;
    memset(res, 0, sizeof *res);
    for (size_t i = 0; i < 3 * nt; i++)
        if (idx[i] >= nv) return -1;
    vs_options ro = o ? *o : vs_default_options();
    ro.normals = VS_NORMALS_REAL;
    vs_triangle *T = calloc(nt, sizeof *T);
    half_edge *he = malloc(3 * nt * sizeof *he);
    int32_t *mate = malloc(3 * nt * sizeof *mate); /* half-edge index of the other side, -1 if none */
    if (!T || !he || !mate) {
        free(T), free(he), free(mate);
        return -1;
    }
    /* bounding box and triangles */
    float3 lo = pos[idx[0]], hi = lo;
    for (size_t t = 0; t < nt; t++) {
        float3 v[3], n[3];
        for (int k = 0; k < 3; k++) {
            v[k] = pos[idx[3 * t + k]], n[k] = nrm[idx[3 * t + k]];
            lo = f3(fminf(lo.x, v[k].x), fminf(lo.y, v[k].y), fminf(lo.z, v[k].z));
            hi = f3(fmaxf(hi.x, v[k].x), fmaxf(hi.y, v[k].y), fmaxf(hi.z, v[k].z));
        }
        T[t] = vs_triangle_make(v, n);
        T[t].id = (float)t;
        for (int k = 0; k < 3; k++) {
            half_edge *h = &he[3 * t + k];
            uint32_t a[3], b[3];
            bits3(v[k], a);
            bits3(v[(k + 1) % 3], b);
            bool swap = memcmp(a, b, sizeof a) > 0;
            memcpy(h->key, swap ? b : a, sizeof a);
            memcpy(h->key + 3, swap ? a : b, sizeof a);
            h->tri = (uint32_t)t;
            h->k = (uint8_t)k;
            mate[3 * t + k] = -1;
        }
    }
    double diag = sqrt((double)(hi.x - lo.x) * (hi.x - lo.x) + (double)(hi.y - lo.y) * (hi.y - lo.y) +
                       (double)(hi.z - lo.z) * (hi.z - lo.z));
    /* match edges by position bits */
    qsort(he, 3 * nt, sizeof *he, he_cmp);
    for (size_t i = 0; i < 3 * nt;) {
        size_t j = i + 1;
        while (j < 3 * nt && memcmp(he[j].key, he[i].key, sizeof he[i].key) == 0) j++;
        if (j - i == 1) res->boundary_edges++;
        else if (j - i > 2) res->nonmanifold_edges++;
        else {
            res->shared_edges++;
            mate[3 * he[i].tri + he[i].k] = (int32_t)(3 * he[i + 1].tri + he[i + 1].k);
            mate[3 * he[i + 1].tri + he[i + 1].k] = (int32_t)(3 * he[i].tri + he[i].k);
        }
        i = j;
    }
    /* opposite vertices and the neighbours' normals (PN-AEN) */
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t m = mate[3 * t + k];
            if (opp) T[t].opp[k] = opp[3 * t + k];
            if (m < 0) continue;
            const vs_triangle *N = &T[m / 3];
            int mk = m % 3;
            if (!opp) T[t].opp[k] = N->v[(mk + 2) % 3];
            for (int e = 0; e < 2; e++) {
                float3 at = T[t].v[(k + e) % 3];
                T[t].nadj[k][e] = same3(N->v[mk], at) ? N->n[mk] : N->n[(mk + 1) % 3];
            }
        }
    /* normals across shared edges */
    double sum = 0.0;
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t m = mate[3 * t + k];
            if (m < 0 || (size_t)m < 3 * t + (size_t)k) continue; /* each shared edge once */
            const vs_triangle *A = &T[t], *B = &T[m / 3];
            int mk = m % 3;
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
                double d = (double)na.x * nb.x + (double)na.y * nb.y + (double)na.z * nb.z;
                double ang = acos(d > 1.0 ? 1.0 : d < -1.0 ? -1.0 : d) * (180.0 / 3.14159265358979323846);
                if (ang > res->max_angle_deg) res->max_angle_deg = ang;
                if (ang > *edge_max) *edge_max = ang;
                sum += ang;
                res->samples++;
            }
        }
    res->mean_angle_deg = res->samples ? sum / (double)res->samples : 0.0;
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
    free(T), free(he), free(mate);
    return 0;
}
