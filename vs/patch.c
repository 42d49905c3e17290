/* vs/patch.c -- the patches in object space: corners, canonical edge curves (watertightness, erratum 6),
 * interior formulas of flat, N-Patch (control points), PN-AEN and Phong tessellation, normals (linear,
 * quadratic, real) and derivatives.  The Gruen patches' formulas are in smooth.c, the N-Patch's listing form in
 * npatch.c. */
#include "vs_internal.h"

#include "../core/hlsl.h"
#include <string.h>

/* ---------------------------------------------------------------- small helpers */

int vs_cmp_bits(const float *a, const float *b, int n)
{
    for (int i = 0; i < n; i++) {
        uint32_t x, y;
        memcpy(&x, &a[i], 4);
        memcpy(&y, &b[i], 4);
        if (x != y) return x < y ? -1 : 1;
    }
    return 0;
}

/* a*x + b*y. */
static inline float3 comb2(float a, float3 x, float b, float3 y) { return add3(scale3(x, a), scale3(y, b)); }

/* The flat point b0 v0 + b1 v1 + b2 v2. */
static float3 flat_point(const vs_triangle *T, float3 b)
{
    return add3(add3(scale3(T->v[0], b.x), scale3(T->v[1], b.y)), scale3(T->v[2], b.z));
}

/* The (unnormalised) linear normal b0 n0 + b1 n1 + b2 n2, in the listing's order. */
static float3 linear_normal_raw(const vs_triangle *T, float3 b)
{
    return add3(add3(scale3(T->n[0], b.x), scale3(T->n[1], b.y)), scale3(T->n[2], b.z));
}

/* cross(v1 - v0, v2 - v0): the face normal direction used by every patch. */
static float3 face_normal_raw(const vs_triangle *T)
{
    return cross3(sub3(T->v[1], T->v[0]), sub3(T->v[2], T->v[0]));
}

/* Reflected mid-edge normal n_ij (seed 003): normalize(ni + nj - v (Pj - Pi)), v = f dot(Pj - Pi, ni + nj) /
 * dot(Pj - Pi, Pj - Pi); v = 0 for a zero-length edge.  Symmetric in (i, j) bit for bit. */
static float3 mid_normal(float3 Pi, float3 Pj, float3 ni, float3 nj, float f)
{
    float3 d = sub3(Pj, Pi), s = add3(ni, nj);
    float dd = dot3(d, d);
    float v = dd > 0.0f ? f * dot3(d, s) / dd : 0.0f;
    if (!isfinite(v)) v = 0.0f;
    return normalize3(sub3(s, scale3(d, v)));
}

/* ---------------------------------------------------------------- cubic Bezier triangles */

/* Control points c[i][j] = b_{i j (3-i-j)} (i for b0/v0, j for b1/v1), canonical scale (with the /3). */
typedef struct bez3 { float3 c[4][4]; } bez3;

/* Eq. 1.1.1 (seed 001 Eq. 2-4), with the tangent points of each edge end averaged over the two sides' normals
 * when aen (PN-AEN; nadj equal to n gives exactly the PN points). */
static void bez3_control_points(const vs_triangle *T, bool aen, bez3 *B)
{
    const float3 *v = T->v, *n = T->n;
    /* tangent point near v_i towards v_j of edge k (j = 0 for v_k, 1 for v_k+1) */
    float3 tp[3][2];
    for (int k = 0; k < 3; k++) {
        for (int e = 0; e < 2; e++) {
            int i = e == 0 ? k : (k + 1) % 3, j = e == 0 ? (k + 1) % 3 : k;
            float3 d = sub3(v[j], v[i]);
            float3 off = scale3(n[i], dot3(d, n[i]));
            if (aen) {
                float3 na = T->nadj[k][e];
                off = scale3(add3(off, scale3(na, dot3(d, na))), 0.5f);
            }
            tp[k][e] = scale3(sub3(add3(scale3(v[i], 2.0f), v[j]), off), 1.0f / 3.0f);
        }
    }
    memset(B, 0, sizeof *B);
    B->c[3][0] = v[0];
    B->c[0][3] = v[1];
    B->c[0][0] = v[2];
    B->c[2][1] = tp[0][0]; /* b210 */
    B->c[1][2] = tp[0][1]; /* b120 */
    B->c[0][2] = tp[1][0]; /* b021 */
    B->c[0][1] = tp[1][1]; /* b012 */
    B->c[1][0] = tp[2][0]; /* b102 */
    B->c[2][0] = tp[2][1]; /* b201 */
    float3 E = scale3(add3(add3(add3(B->c[2][1], B->c[1][2]), add3(B->c[0][2], B->c[0][1])),
                           add3(B->c[1][0], B->c[2][0])), 1.0f / 6.0f);
    float3 V = scale3(add3(add3(v[0], v[1]), v[2]), 1.0f / 3.0f);
    B->c[1][1] = add3(E, scale3(sub3(E, V), 0.5f)); /* b111 = E + (E - V) / 2 */
}

/* The Bernstein form sum c_ijk 3!/(i!j!k!) b0^i b1^j b2^k. */
static float3 bez3_eval(const bez3 *B, float3 b)
{
    float3 p = f3(0, 0, 0);
    static const float fact[4] = {1, 1, 2, 6};
    float pw0[4] = {1, b.x, b.x * b.x, b.x * b.x * b.x}, pw1[4] = {1, b.y, b.y * b.y, b.y * b.y * b.y},
          pw2[4] = {1, b.z, b.z * b.z, b.z * b.z * b.z};
    for (int i = 3; i >= 0; i--)
        for (int j = 3 - i; j >= 0; j--) {
            int k = 3 - i - j;
            float w = 6.0f / (fact[i] * fact[j] * fact[k]) * pw0[i] * pw1[j] * pw2[k];
            p = add3(p, scale3(B->c[i][j], w));
        }
    return p;
}

/* Partial derivatives of the homogeneous cubic by b0, b1, b2: 3 sum_{i+j+k=2} c_(.+e) 2!/(i!j!k!) b^... */
static void bez3_partials(const bez3 *B, float3 b, float3 d[3])
{
    static const float fact[3] = {1, 1, 2};
    float pw0[3] = {1, b.x, b.x * b.x}, pw1[3] = {1, b.y, b.y * b.y}, pw2[3] = {1, b.z, b.z * b.z};
    d[0] = d[1] = d[2] = f3(0, 0, 0);
    for (int i = 2; i >= 0; i--)
        for (int j = 2 - i; j >= 0; j--) {
            int k = 2 - i - j;
            float w = 3.0f * 2.0f / (fact[i] * fact[j] * fact[k]) * pw0[i] * pw1[j] * pw2[k];
            d[0] = add3(d[0], scale3(B->c[i + 1][j], w));
            d[1] = add3(d[1], scale3(B->c[i][j + 1], w));
            d[2] = add3(d[2], scale3(B->c[i][j], w)); /* k + 1: c[i][j] has k' = 3 - i - j = k + 1 */
        }
}

/* ---------------------------------------------------------------- Phong tessellation */

/* pi_i(q) = q - dot(q - v_i, n_i) n_i: projection onto the tangent plane of vertex i. */
static inline float3 phong_project(float3 q, float3 vi, float3 ni)
{
    return sub3(q, scale3(ni, dot3(sub3(q, vi), ni)));
}

/* Boubekeur and Alexa 2008: p* = (1 - alpha) p + alpha sum b_i pi_i(p), p the flat point. */
static float3 phong_formula(const vs_triangle *T, float3 b, float alpha)
{
    float3 p = flat_point(T, b);
    float3 q = add3(add3(scale3(phong_project(p, T->v[0], T->n[0]), b.x),
                         scale3(phong_project(p, T->v[1], T->n[1]), b.y)),
                    scale3(phong_project(p, T->v[2], T->n[2]), b.z));
    return add3(scale3(p, 1.0f - alpha), scale3(q, alpha));
}

/* Directional derivative of phong_formula along db (sum 0). */
static float3 phong_derivative(const vs_triangle *T, float3 b, float3 db, float alpha)
{
    float3 p = flat_point(T, b), dp = flat_point(T, db);
    float bw[3] = {b.x, b.y, b.z}, dw[3] = {db.x, db.y, db.z};
    float3 dq = f3(0, 0, 0);
    for (int i = 0; i < 3; i++) {
        float3 proj_dp = sub3(dp, scale3(T->n[i], dot3(dp, T->n[i])));
        dq = add3(dq, add3(scale3(phong_project(p, T->v[i], T->n[i]), dw[i]), scale3(proj_dp, bw[i])));
    }
    return add3(scale3(dp, 1.0f - alpha), scale3(dq, alpha));
}

/* ---------------------------------------------------------------- canonical edges (erratum 6) */

/* One end of an edge: position, own normal, neighbour's normal (PN-AEN) and its barycentric weight. */
typedef struct edge_end { float3 p, n, na; float w; } edge_end;

/* Total order of edge ends: position bits, then normal bits (n + na for PN-AEN, the same from both sides),
 * then the weight.  Both triangles of a shared edge put its ends in the same order. */
static int end_cmp(const edge_end *a, const edge_end *b, bool aen)
{
    float3 ka = aen ? add3(a->n, a->na) : a->n, kb = aen ? add3(b->n, b->na) : b->n;
    float fa[7] = {a->p.x, a->p.y, a->p.z, ka.x, ka.y, ka.z, a->w};
    float fb[7] = {b->p.x, b->p.y, b->p.z, kb.x, kb.y, kb.z, b->w};
    return vs_cmp_bits(fa, fb, 7);
}

/* The ends of edge k of T (v_k, v_k+1) with weights from bw, in canonical order. */
static void edge_ends(const vs_triangle *T, int k, const float bw[3], bool aen, edge_end *A, edge_end *B)
{
    int j = (k + 1) % 3;
    *A = (edge_end){T->v[k], T->n[k], T->nadj[k][0], bw[k]};
    *B = (edge_end){T->v[j], T->n[j], T->nadj[k][1], bw[j]};
    if (end_cmp(B, A, aen) < 0) {
        edge_end t = *A;
        *A = *B;
        *B = t;
    }
}

/* Cubic border curve in the listing's form: s^3 A + t^3 B + s^2 t b21 + s t^2 b12, b21 = 2A + B - offA,
 * b12 = 2B + A - offB (control points times 3, weights without the 3: erratum 1). */
static float3 edge_cubic(const edge_end *A, const edge_end *B, bool aen)
{
    float s = A->w, t = B->w;
    float3 dAB = sub3(B->p, A->p), dBA = sub3(A->p, B->p);
    float3 offA = scale3(A->n, dot3(dAB, A->n)), offB = scale3(B->n, dot3(dBA, B->n));
    if (aen) {
        offA = scale3(add3(offA, scale3(A->na, dot3(dAB, A->na))), 0.5f);
        offB = scale3(add3(offB, scale3(B->na, dot3(dBA, B->na))), 0.5f);
    }
    float3 b21 = sub3(add3(scale3(A->p, 2.0f), B->p), offA);
    float3 b12 = sub3(add3(scale3(B->p, 2.0f), A->p), offB);
    float3 p = add3(scale3(A->p, s * s * s), scale3(B->p, t * t * t));
    p = add3(p, scale3(b21, s * s * t));
    return add3(p, scale3(b12, s * t * t));
}

/* The point of edge k (weights from bw) of patch p, evaluated in canonical order. */
static float3 edge_position(vs_patch p, const vs_triangle *T, int k, const float bw[3], const vs_options *o)
{
    edge_end A, B;
    bool aen = p == VS_PATCH_PN_AEN;
    edge_ends(T, k, bw, aen, &A, &B);
    switch (p) {
    case VS_PATCH_FLAT:
        return comb2(A.w, A.p, B.w, B.p);
    case VS_PATCH_PHONG: {
        float3 q = comb2(A.w, A.p, B.w, B.p);
        float3 pr = comb2(A.w, phong_project(q, A.p, A.n), B.w, phong_project(q, B.p, B.n));
        return add3(scale3(q, 1.0f - o->phong_alpha), scale3(pr, o->phong_alpha));
    }
    case VS_PATCH_NPATCH: case VS_PATCH_SMOOTH_INITIAL: case VS_PATCH_SMOOTH: case VS_PATCH_PN_AEN:
        return edge_cubic(&A, &B, aen); /* the N-Patch border curve (pn-aen: averaged control points) */
    }
    return comb2(A.w, A.p, B.w, B.p);   /* not reached for a vs_patch */
}

/* Linear or quadratic normal of edge k, canonical order (unnormalised). */
static float3 edge_normal(const vs_triangle *T, int k, const float bw[3], const vs_options *o)
{
    edge_end A, B;
    edge_ends(T, k, bw, false, &A, &B);
    if (o->normals == VS_NORMALS_QUADRATIC) {
        float3 nAB = mid_normal(A.p, B.p, A.n, B.n, o->quad_factor);
        return add3(comb2(A.w * A.w, A.n, B.w * B.w, B.n), scale3(nAB, A.w * B.w));
    }
    return comb2(A.w, A.n, B.w, B.n);
}

/* ---------------------------------------------------------------- interior formulas and derivatives */

/* The interior formula of patch p (no edge handling). */
static float3 interior_position(vs_patch p, const vs_triangle *T, float3 b, const vs_options *o)
{
    switch (p) {
    case VS_PATCH_FLAT: return flat_point(T, b);
    case VS_PATCH_NPATCH:
        return vs_evaluate_npatch(T->v[0], T->v[1], T->v[2], T->n[0], T->n[1], T->n[2], b);
    case VS_PATCH_SMOOTH_INITIAL: return vs_smooth_initial_formula(T, b, NULL);
    case VS_PATCH_SMOOTH: return vs_smooth_formula(T, b, o->flags, NULL, NULL);
    case VS_PATCH_PHONG: return phong_formula(T, b, o->phong_alpha);
    case VS_PATCH_PN_AEN: {
        bez3 B;
        bez3_control_points(T, true, &B);
        return bez3_eval(&B, b);
    }
    }
    return flat_point(T, b);   /* not reached for a vs_patch */
}

/* Finite-difference step of the Gruen patches' derivatives: second-order schemes, so a large step keeps the
 * float rounding of the positions small (about 1e-5 relative) while the truncation is O(h^2). */
#define FD_H (1.0f / 128.0f)

/* First-order derivatives on the triangle (1 - h) b + h e_i, which contains b and stays inside the domain. */
static void fd_shrink(vs_patch p, const vs_triangle *T, float3 b, const vs_options *o, float h, float3 *du,
                      float3 *dv)
{
    float3 q0 = add3(scale3(b, 1.0f - h), f3(h, 0, 0));
    float3 q1 = add3(scale3(b, 1.0f - h), f3(0, h, 0));
    float3 q2 = add3(scale3(b, 1.0f - h), f3(0, 0, h));
    float3 p0 = vs_patch_position(p, T, q0, o);
    *du = scale3(sub3(vs_patch_position(p, T, q1, o), p0), 1.0f / h);
    *dv = scale3(sub3(vs_patch_position(p, T, q2, o), p0), 1.0f / h);
}

void vs_patch_derivatives(vs_patch p, const vs_triangle *T, float3 b, const vs_options *o, float3 *du,
                          float3 *dv)
{
    vs_options od = vs_default_options();
    if (!o) o = &od;
    switch (p) {
    case VS_PATCH_NPATCH:
    case VS_PATCH_PN_AEN: {
        bez3 B;
        float3 d[3];
        bez3_control_points(T, p == VS_PATCH_PN_AEN, &B);
        bez3_partials(&B, b, d);
        *du = sub3(d[1], d[0]);
        *dv = sub3(d[2], d[0]);
        return;
    }
    case VS_PATCH_PHONG:
        *du = phong_derivative(T, b, f3(-1, 1, 0), o->phong_alpha);
        *dv = phong_derivative(T, b, f3(-1, 0, 1), o->phong_alpha);
        return;
    case VS_PATCH_SMOOTH_INITIAL:
    case VS_PATCH_SMOOTH: {
        const float h = FD_H;
        float mn = fminf(b.x, fminf(b.y, b.z));
        if (mn >= 0.5f * h) { /* central differences */
            float3 e = f3(-0.5f * h, 0.5f * h, 0), f = f3(-0.5f * h, 0, 0.5f * h);
            float3 pu = vs_patch_position(p, T, add3(b, e), o), mu = vs_patch_position(p, T, sub3(b, e), o);
            float3 pv = vs_patch_position(p, T, add3(b, f), o), mv = vs_patch_position(p, T, sub3(b, f), o);
            *du = scale3(sub3(pu, mu), 1.0f / h);
            *dv = scale3(sub3(pv, mv), 1.0f / h);
        } else { /* near an edge: one-sided on the shrunken triangle, Richardson-extrapolated 2 D(h/2) - D(h) */
            float3 du1, dv1, du2, dv2;
            fd_shrink(p, T, b, o, h, &du1, &dv1);
            fd_shrink(p, T, b, o, 0.5f * h, &du2, &dv2);
            *du = sub3(scale3(du2, 2.0f), du1);
            *dv = sub3(scale3(dv2, 2.0f), dv1);
        }
        return;
    }
    case VS_PATCH_FLAT: break;
    }
    *du = sub3(T->v[1], T->v[0]);   /* flat */
    *dv = sub3(T->v[2], T->v[0]);
}

/* ---------------------------------------------------------------- the patch */

enum { AT_INTERIOR, AT_EDGE, AT_CORNER };

/* Where b lies: a corner (two components <= 0; k = the vertex), an edge (one; k = the edge) or inside.  bw gets
 * b with non-positive (and NaN) components set to 0. */
static int classify(float3 b, float bw[3], int *k)
{
    float in[3] = {b.x, b.y, b.z};
    int zeros = 0, zi = 0, nz = 0;
    for (int i = 0; i < 3; i++) {
        bw[i] = in[i] > 0.0f ? in[i] : 0.0f;
        if (bw[i] == 0.0f) zeros++, zi = i;
        else nz = i;
    }
    if (zeros >= 2) {
        *k = zeros == 3 ? 0 : nz;
        return AT_CORNER;
    }
    if (zeros == 1) {
        *k = (zi + 1) % 3; /* b2 == 0: edge 0 (v0-v1); b0 == 0: edge 1; b1 == 0: edge 2 */
        return AT_EDGE;
    }
    return AT_INTERIOR;
}

/* Position at a classified point, with the non-finite fallbacks. */
static float3 position_at(vs_patch p, const vs_triangle *T, float3 b, const float bw[3], int at, int k,
                          const vs_options *o)
{
    float3 P;
    if (at == AT_CORNER) return T->v[k];
    if (at == AT_EDGE) P = edge_position(p, T, k, bw, o);
    else P = interior_position(p, T, b, o);
    if (vs_finite3(P)) return P;
    P = flat_point(T, f3(bw[0], bw[1], bw[2]));
    if (vs_finite3(P)) return P;
    int m = bw[0] >= bw[1] ? (bw[0] >= bw[2] ? 0 : 2) : (bw[1] >= bw[2] ? 1 : 2);
    return T->v[m];
}

float3 vs_patch_position(vs_patch p, const vs_triangle *T, float3 b, const vs_options *o)
{
    if (!T) return f3(0, 0, 0);
    vs_options od = vs_default_options();
    if (!o) o = &od;
    float bw[3];
    int k = 0, at = classify(b, bw, &k);
    if (at != AT_INTERIOR) b = f3(bw[0], bw[1], bw[2]);
    return position_at(p, T, b, bw, at, k, o);
}

/* Unit (or zero) normal of patch p in mode o->normals at a classified point. */
static float3 normal_at(vs_patch p, const vs_triangle *T, float3 b, const float bw[3], int at, int k,
                        const vs_options *o)
{
    float3 nl = linear_normal_raw(T, b), N;
    bool vertex_plane = p != VS_PATCH_FLAT && p != VS_PATCH_PN_AEN; /* corner tangent plane = n_k */
    if (at == AT_CORNER && (o->normals != VS_NORMALS_REAL || vertex_plane)) {
        N = T->n[k];
    } else if (o->normals == VS_NORMALS_REAL) {
        float3 du, dv;
        vs_patch_derivatives(p, T, b, o, &du, &dv);
        N = cross3(du, dv);
        float3 ref = dot3(nl, nl) > 0.0f ? nl : face_normal_raw(T);
        if (dot3(N, ref) < 0.0f) N = neg3(N);
    } else if (at == AT_EDGE) {
        N = edge_normal(T, k, bw, o);
    } else if (o->normals == VS_NORMALS_QUADRATIC) {
        const float3 *v = T->v, *n = T->n;
        float f = o->quad_factor;
        float3 n01 = mid_normal(v[0], v[1], n[0], n[1], f), n12 = mid_normal(v[1], v[2], n[1], n[2], f),
               n20 = mid_normal(v[2], v[0], n[2], n[0], f);
        N = add3(add3(scale3(n[0], b.x * b.x), scale3(n[1], b.y * b.y)), scale3(n[2], b.z * b.z));
        N = add3(add3(N, scale3(n01, b.x * b.y)), add3(scale3(n12, b.y * b.z), scale3(n20, b.z * b.x)));
    } else {
        N = nl;
    }
    N = normalize3(N);
    if (vs_finite3(N) && dot3(N, N) > 0.0f) return N;
    N = normalize3(nl); /* fallbacks: linear normal, face normal, zero */
    if (vs_finite3(N) && dot3(N, N) > 0.0f) return N;
    N = normalize3(face_normal_raw(T));
    if (vs_finite3(N)) return N;
    return f3(0, 0, 0);
}

void vs_patch_eval(vs_patch p, const vs_triangle *T, float3 b, const vs_options *o, float3 *pos, float3 *nrm,
                   float3 *greg)
{
    vs_options od = vs_default_options();
    if (!o) o = &od;
    if (!T) {   /* no triangle: zeros */
        if (pos) *pos = f3(0, 0, 0);
        if (nrm) *nrm = f3(0, 0, 0);
        if (greg) *greg = f3(0, 0, 0);
        return;
    }
    float bw[3];
    int k = 0, at = classify(b, bw, &k);
    if (at != AT_INTERIOR) b = f3(bw[0], bw[1], bw[2]);
    if (pos) *pos = position_at(p, T, b, bw, at, k, o);
    if (nrm) *nrm = normal_at(p, T, b, bw, at, k, o);
    if (greg) {
        bool gregory = (unsigned)p < VS_PATCH_COUNT && vs_patches[p].gregory;
        *greg = gregory ? vs_gregory(f3(bw[0], bw[1], bw[2])) : f3(0, 0, 0);
    }
}

/* ---------------------------------------------------------------- instance data */

vs_triangle vs_triangle_make(const float3 v[3], const float3 n[3])
{
    vs_triangle T;
    memset(&T, 0, sizeof T);
    for (int k = 0; k < 3; k++) {   /* NULL positions or normals: zeros */
        T.v[k] = v ? v[k] : f3(0, 0, 0);
        T.n[k] = n ? n[k] : f3(0, 0, 0);
    }
    for (int k = 0; k < 3; k++) {
        T.opp[k] = T.v[(k + 2) % 3];
        T.nadj[k][0] = T.n[k];
        T.nadj[k][1] = T.n[(k + 1) % 3];
    }
    return T;
}

const vs_reg vs_nadj_regs[3][2] = {
    {{IS_DECLUSAGE_TEXCOORD, 13}, {IS_DECLUSAGE_NORMAL, 0}},
    {{IS_DECLUSAGE_TEXCOORD, 14}, {IS_DECLUSAGE_NORMAL, 1}},
    {{IS_DECLUSAGE_TEXCOORD, 15}, {IS_DECLUSAGE_TANGENT, 0}},
};

/* The input register of (usage, index) among those vs_nadj_regs uses. */
static float4 input_reg(const is_vs_input *in, vs_reg r)
{
    switch (r.usage) {
    case IS_DECLUSAGE_TEXCOORD: return in->texcoord[r.usage_index];
    case IS_DECLUSAGE_NORMAL: return in->normal[r.usage_index];
    case IS_DECLUSAGE_TANGENT: return in->tangent[0];
    default: return f4(0, 0, 0, 1);
    }
}

void vs_triangle_from_input(const is_vs_input *in, vs_triangle *T)
{
    if (!T) return;
    if (!in) {
        memset(T, 0, sizeof *T);
        return;
    }
    for (int k = 0; k < 3; k++) {
        T->v[k] = f3_of(in->texcoord[VS_IN_V0 + k]);
        T->n[k] = f3_of(in->texcoord[VS_IN_N0 + k]);
        T->opp[k] = f3_of(in->texcoord[VS_IN_OPP0 + k]);
        T->t[k] = f2_of(in->texcoord[VS_IN_T0 + k]);
    }
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 2; j++) {
            float3 na = f3_of(input_reg(in, vs_nadj_regs[k][j]));
            T->nadj[k][j] = dot3(na, na) > 0.0f ? na : T->n[(k + j) % 3];
        }
    T->id = in->texcoord[VS_IN_ID].x;
}
