/* vs/batch8.c -- the batched entries of the N-Patch and smoothed-patch shaders: interior vertices evaluated 8 at a
 * time (one lane per vertex, GCC vector extensions), edge and corner vertices one by one.
 *
 * Exactness: each lane performs the operations of the listing-form functions (vs_evaluate_npatch, normal_at's
 * linear normal, vs_smooth_formula, vs_evaluate_curve, vs_gregory, vs_write_outputs_k) in the same order, with
 * IEEE division and square root and no contraction (-ffp-contract=off), so every lane gives the bits of the
 * per-vertex shader.  Values that depend only on the instance (control points, fn_k) are computed once per
 * instance by the same expressions.  The watertight edge and corner evaluation, the other normal modes and the
 * non-finite fallbacks are never vectorised: those vertices (and any lane whose result needs a fallback) go
 * through the per-vertex path. */
#include "vs_internal.h"

#include "../core/hlsl.h"
#include <stddef.h>

/* The colour outputs of out[0..n) saturated as the device does after any shader: grid_batch hands them over so
 * (core/device.h). */
static void sat_colors(is_vs_output *out, size_t n)
{
    for (size_t v = 0; v < n; v++) saturate_color_outputs(&out[v].attr[RS_ATTR_COLOR0]);
}

#ifdef __AVX2__
#include <immintrin.h>

typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));

/* Every lane set (-1). */
static const v8i all_lanes = {-1, -1, -1, -1, -1, -1, -1, -1};

/* Eight float3s, one per lane. */
typedef struct f3x8 { v8f x, y, z; } f3x8;

/* Broadcasts. */
static inline v8f bf(float x) { return (v8f){x, x, x, x, x, x, x, x}; }
static inline f3x8 b3(float3 a) { return (f3x8){bf(a.x), bf(a.y), bf(a.z)}; }

/* mask ? a : b per lane (mask lanes -1 or 0). */
static inline v8f sel(v8i m, v8f a, v8f b) { return (v8f)_mm256_blendv_ps((__m256)b, (__m256)a, (__m256)m); }
static inline f3x8 sel3(v8i m, f3x8 a, f3x8 b) { return (f3x8){sel(m, a.x, b.x), sel(m, a.y, b.y), sel(m, a.z, b.z)}; }

/* The float3 operations of core.h, per lane, same order. */
static inline f3x8 add(f3x8 a, f3x8 b) { return (f3x8){a.x + b.x, a.y + b.y, a.z + b.z}; }
static inline f3x8 sub(f3x8 a, f3x8 b) { return (f3x8){a.x - b.x, a.y - b.y, a.z - b.z}; }
static inline f3x8 scl(f3x8 a, v8f s) { return (f3x8){a.x * s, a.y * s, a.z * s}; }
static inline v8f dot(f3x8 a, f3x8 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/* normalize3: a zero (or non-positive length) vector stays as it is. */
static inline f3x8 normalize(f3x8 a)
{
    v8f l = (v8f)_mm256_sqrt_ps((__m256)dot(a, a));
    return sel3(l > bf(0.0f), scl(a, bf(1.0f) / l), a);
}
/* lerp3(a, b, t) = a + (b - a) t. */
static inline f3x8 lerp(f3x8 a, f3x8 b, v8f t) { return add(a, scl(sub(b, a), t)); }
/* vs_lerp3: t == 1 gives b exactly. */
static inline f3x8 vlerp(f3x8 a, f3x8 b, v8f t) { return sel3(t == bf(1.0f), b, lerp(a, b, t)); }
/* isfinite per lane (-1 / 0). */
static inline v8i finite(v8f a)
{
    v8f m = (v8f)((v8i)a & (v8i)bf(__builtin_inff()));
    return m != bf(__builtin_inff());
}
static inline v8i finite3(f3x8 a) { return finite(a.x) & finite(a.y) & finite(a.z); }
/* The device's colour saturation per lane (hlsl.h's saturate_color_outputs: x >= 0 ? x : 0, then <= 1 ? : 1; NaN gives 0, -0
 * stays -0): the and keeps x's bits where x >= 0, min(x, 1) is x <= 1 ? x : 1 for the non-NaN x left. */
static inline v8f sat8(v8f x)
{
    v8f p = (v8f)((v8i)x & (v8i)(x >= bf(0.0f)));
    return (v8f)_mm256_min_ps((__m256)p, (__m256)bf(1.0f));
}
/* -1 / 0 lanes -> 8-bit mask. */
static inline unsigned mask_of(v8i m) { return (unsigned)_mm256_movemask_ps((__m256)m); }

/* Lanes of 8 vertices: barycentrics and where each lane's outputs go (lanes past n_real are copies): lane i is
 * vertex idx[i] of the batch, its input in0 + idx[i], its output at byte off[i] (idx[i] * sizeof(is_vs_output))
 * from out0; idx and off point at the lanes' own arrays or at a plan group's (no per-group pointer array). */
typedef struct lanes8 {
    f3x8 b;
    f3x8 ap, bp, an, bn, b21, b12; /* edge lanes: the canonical ends, normals and inner control points */
    v8f s, t;                       /* edge lanes: the weights of the ends */
    const is_vs_input *in0;
    is_vs_output *out0;
    const int32_t *idx;
    const size_t *off;
    int32_t own_idx[8];
    size_t own_off[8];
    int n_real;
} lanes8;

/* ---------------------------------------------------------------- N-Patch */

/* vs_evaluate_npatch's instance part: the six control points (without the /3) and the centre term. */
typedef struct npatch_cp { float3 v[3], b102, b012, b201, b021, b210, b120, center; } npatch_cp;

/* The control points exactly as vs_evaluate_npatch computes them. */
static void npatch_cp_make(float3 v0, float3 v1, float3 v2, float3 n0, float3 n1, float3 n2, npatch_cp *c)
{
    c->v[0] = v0, c->v[1] = v1, c->v[2] = v2;
    c->b102 = sub3(add3(scale3(v2, 2.0f), v0), scale3(n2, dot3(sub3(v0, v2), n2)));
    c->b012 = sub3(add3(scale3(v2, 2.0f), v1), scale3(n2, dot3(sub3(v1, v2), n2)));
    c->b201 = sub3(add3(scale3(v0, 2.0f), v2), scale3(n0, dot3(sub3(v2, v0), n0)));
    c->b021 = sub3(add3(scale3(v1, 2.0f), v2), scale3(n1, dot3(sub3(v2, v1), n1)));
    c->b210 = sub3(add3(scale3(v0, 2.0f), v1), scale3(n0, dot3(sub3(v1, v0), n0)));
    c->b120 = sub3(add3(scale3(v1, 2.0f), v0), scale3(n1, dot3(sub3(v0, v1), n1)));
    float3 six = add3(add3(add3(c->b210, c->b120), add3(c->b021, c->b012)), add3(c->b102, c->b201));
    c->center = sub3(sub3(sub3(scale3(six, 0.5f), v0), v1), v2);
}

/* The cubic Bernstein products of b (without the 3s) in vs_evaluate_npatch's order and form: they depend on the
 * grid point alone, so the grid plan computes them once per grid (the same expressions, the same bits). */
enum { W_300, W_030, W_003, W_102, W_012, W_201, W_021, W_210, W_120, W_111, W_COUNT };
static inline void npatch_weights(f3x8 b, v8f w[W_COUNT])
{
    w[W_300] = b.x * b.x * b.x, w[W_030] = b.y * b.y * b.y, w[W_003] = b.z * b.z * b.z;
    w[W_102] = b.x * b.z * b.z, w[W_012] = b.y * b.z * b.z, w[W_201] = b.x * b.x * b.z;
    w[W_021] = b.y * b.y * b.z, w[W_210] = b.x * b.x * b.y, w[W_120] = b.x * b.y * b.y;
    w[W_111] = b.x * b.y * b.z;
}

/* The control points broadcast, in the order of the weights: cv[W_300] = v0, ..., cv[W_111] = center. */
static void npatch_cp_lanes(const npatch_cp *c, f3x8 cv[W_COUNT])
{
    cv[W_300] = b3(c->v[0]), cv[W_030] = b3(c->v[1]), cv[W_003] = b3(c->v[2]), cv[W_102] = b3(c->b102);
    cv[W_012] = b3(c->b012), cv[W_201] = b3(c->b201), cv[W_021] = b3(c->b021), cv[W_210] = b3(c->b210);
    cv[W_120] = b3(c->b120), cv[W_111] = b3(c->center);
}

/* vs_evaluate_npatch's vertex part, per lane, from the control points of npatch_cp_lanes and the weights of
 * npatch_weights: v0 w300 + v1 w030 + ... + center w111, in this order. */
static inline __attribute__((always_inline)) f3x8 npatch8_w(const f3x8 cv[W_COUNT], const v8f w[W_COUNT])
{
    f3x8 p = scl(cv[W_300], w[W_300]);
    for (int q = W_030; q < W_COUNT; q++) p = add(p, scl(cv[q], w[q]));
    return p;
}

/* ---------------------------------------------------------------- smoothed patch (Listing 1.1.2) */

/* vs_evaluate_curve per lane is three parts: the Bernstein weights at b (without the 3s; they depend on b alone),
 * the inner control points (on the ends alone) and the sum.  The weights (1-b)^3, b^3, (1-b)^2 b, (1-b) b^2: */
static inline void curve_weights(v8f b, v8f w[4])
{
    v8f b_ = bf(1.0f) - b;
    w[0] = b_ * b_ * b_, w[1] = b * b * b, w[2] = b_ * b_ * b, w[3] = b_ * b * b;
}
/* The inner control points b21, b12 of the curve from v0 to v1 with end normals n0, n1: */
static inline void curve_cp8(f3x8 v0, f3x8 v1, f3x8 n0, f3x8 n1, f3x8 *b21, f3x8 *b12)
{
    *b21 = sub(add(scl(v0, bf(2.0f)), v1), scl(n0, dot(sub(v1, v0), n0)));
    *b12 = sub(add(scl(v1, bf(2.0f)), v0), scl(n1, dot(sub(v0, v1), n1)));
}
/* The curve's point: v0 w0 + v1 w1 + b21 w2 + b12 w3, in this order. */
static inline f3x8 curve8_w(f3x8 v0, f3x8 v1, f3x8 b21, f3x8 b12, const v8f w[4])
{
    f3x8 p = add(scl(v0, w[0]), scl(v1, w[1]));
    p = add(p, scl(b21, w[2]));
    return add(p, scl(b12, w[3]));
}

/* edge_patch of smooth.c, the instance part of P_k: the ends va, vb of its edge, the far vertex vc, their normals,
 * broadcast, and the first curve's inner control points (curve_cp8 of the broadcasts: the same value in every
 * lane, computed once per instance). */
typedef struct pk_inst { f3x8 va, vb, vc, na, nb, nc, b21, b12; } pk_inst;
static void pk_make(float3 va, float3 vb, float3 vc, float3 na, float3 nb, float3 nc, pk_inst *E)
{
    E->va = b3(va), E->vb = b3(vb), E->vc = b3(vc), E->na = b3(na), E->nb = b3(nb), E->nc = b3(nc);
    curve_cp8(E->va, E->vb, E->na, E->nb, &E->b21, &E->b12);
}

/* edge_patch of smooth.c per lane: P_k from the border point at st of edge va-vb (curve weights w1 of st) to vc, at
 * ct (curve weights w2 of ct). */
static f3x8 edge_patch8_w(const pk_inst *E, v8f st, const v8f w1[4], const v8f w2[4])
{
    f3x8 pos = curve8_w(E->va, E->vb, E->b21, E->b12, w1);
    f3x8 norm = normalize(lerp(E->na, E->nb, st));
    f3x8 b21, b12;
    curve_cp8(pos, E->vc, norm, E->nc, &b21, &b12);
    return curve8_w(pos, E->vc, b21, b12, w2);
}

/* curve_param of smooth.c: bj / (bi + bj), 0.5 where the sum is not positive. */
static inline v8f param8(v8f bi, v8f bj)
{
    v8f den = bi + bj;
    return sel(den > bf(0.0f), bj / den, bf(0.5f));
}

/* The instance part of the smoothed patch: the N-Patch control points, fn_k, the triangle. */
typedef struct smooth_inst {
    const f3x8 *cv;
    float3 fn;
    const vs_triangle *T;
    bool shortcut;
    pk_inst pk[3]; /* P0..P2's instance parts (those the shortcut evaluates) */
} smooth_inst;

/* Does the smoothed patch evaluate P_k (fn_k of s)? */
static inline bool smooth_evals(const smooth_inst *s, int k)
{
    return !s->shortcut || (&s->fn.x)[k] != 1.0f;
}

/* What vs_smooth_formula computes from b alone (the grid plan keeps it per grid): the Gregory weights g (valid where
 * gok: the Gregory sum is positive), the curve parameters c, the centre blend bl and the curve weights of each
 * P_k (cw[k][0] at c_k along its edge, cw[k][1] at b_(k+2)%3 towards the far vertex). */
typedef struct smooth_w { f3x8 g, c; v8f bl; v8i gok; v8f cw[3][2][4]; } smooth_w;
static inline void smooth_weights(f3x8 b, smooth_w *w)
{
    v8f b0b2 = b.x * b.z, b0b1 = b.x * b.y, b1b2 = b.y * b.z, sum = b0b2 + b0b1 + b1b2;
    w->gok = sum > bf(0.0f);
    w->g = (f3x8){b0b2 / sum, b0b1 / sum, b1b2 / sum};
    w->c = (f3x8){param8(b.x, b.y), param8(b.y, b.z), param8(b.z, b.x)};
    w->bl = bf((float)(3 * 3 * 3)) * b.x * b.y * b.z;
    const v8f ct[3] = {b.z, b.x, b.y};
    for (int k = 0; k < 3; k++) curve_weights((&w->c.x)[k], w->cw[k][0]), curve_weights(ct[k], w->cw[k][1]);
}

/* vs_smooth_formula per lane (interior: every b > 0, Gregory sum > 0) from b's N-Patch weights w and its
 * smooth_weights sw; g gets the Gregory weights. */
static f3x8 smooth8_w(const smooth_inst *s, const v8f w[W_COUNT], const smooth_w *sw, f3x8 *g)
{
    *g = sw->g;
    const f3x8 c = sw->c;
    float fn0 = s->fn.x, fn1 = s->fn.y, fn2 = s->fn.z;
    f3x8 posN = npatch8_w(s->cv, w);
    const v8f bl = sw->bl;
    bool all_one = fn0 == 1.0f && fn1 == 1.0f && fn2 == 1.0f;
    if (s->shortcut && all_one) return posN;
    f3x8 pos0 = posN, pos1 = posN, pos2 = posN;
    if (smooth_evals(s, 0)) {
        v8f t = bf(fn0) + bl;
        pos0 = vlerp(edge_patch8_w(&s->pk[0], c.x, sw->cw[0][0], sw->cw[0][1]), posN, sel(t < bf(1.0f), t, bf(1.0f)));
    }
    if (smooth_evals(s, 1)) {
        v8f t = bf(fn1) + bl;
        pos1 = vlerp(edge_patch8_w(&s->pk[1], c.y, sw->cw[1][0], sw->cw[1][1]), posN, sel(t < bf(1.0f), t, bf(1.0f)));
    }
    if (smooth_evals(s, 2)) {
        v8f t = bf(fn2) + bl;
        pos2 = vlerp(edge_patch8_w(&s->pk[2], c.z, sw->cw[2][0], sw->cw[2][1]), posN, sel(t < bf(1.0f), t, bf(1.0f)));
    }
    if (all_one) return posN;
    return vlerp(add(add(scl(pos2, g->x), scl(pos0, g->y)), scl(pos1, g->z)), posN, bl);
}

/* ---------------------------------------------------------------- outputs */

/* Store float4 lanes (x, y, z, w) into register `r` of the outputs dst[0..n) of lanes 0..n-1 (a 4x8 transpose). */
static inline __attribute__((always_inline)) void store4(char *const dst[8], int n, int r, v8f x, v8f y, v8f z,
                                                        v8f w)
{
    __m256 t0 = _mm256_unpacklo_ps((__m256)x, (__m256)y), t1 = _mm256_unpackhi_ps((__m256)x, (__m256)y);
    __m256 t2 = _mm256_unpacklo_ps((__m256)z, (__m256)w), t3 = _mm256_unpackhi_ps((__m256)z, (__m256)w);
    __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xee);
    __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xee);
    const __m128 q[8] = {_mm256_castps256_ps128(u0), _mm256_castps256_ps128(u1), _mm256_castps256_ps128(u2),
                         _mm256_castps256_ps128(u3), _mm256_extractf128_ps(u0, 1), _mm256_extractf128_ps(u1, 1),
                         _mm256_extractf128_ps(u2, 1), _mm256_extractf128_ps(u3, 1)};
    const size_t off = r < 0 ? offsetof(is_vs_output, pos) : offsetof(is_vs_output, attr) + (size_t)r * sizeof(float4);
    if (n == 8) { /* a full group: eight stores, no loop */
#pragma GCC unroll 8
        for (int i = 0; i < 8; i++) _mm_storeu_ps((float *)(dst[i] + off), q[i]);
        return;
    }
    for (int i = 0; i < n; i++) _mm_storeu_ps((float *)(dst[i] + off), q[i]);
}

/* The matrices and the diffuse colour broadcast once per batch (w[3][c] is the 1 * W[3][c] of oPos's product);
 * sat: COLOR0 goes out saturated (grid_batch's outputs, core/device.h; the plain batch gives main's bytes). */
typedef struct consts8 { v8f w[4][4], m[3][3], diffuse[3]; bool sat; } consts8;
static void consts8_make(const vs_batch_consts *k, consts8 *K)
{
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) K->w[r][c] = r < 3 ? bf(k->wvp.m[r][c]) : bf(1.0f) * bf(k->wvp.m[r][c]);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) K->m[r][c] = bf(k->world.m[r][c]);
    K->diffuse[0] = bf(k->diffuse.x), K->diffuse[1] = bf(k->diffuse.y), K->diffuse[2] = bf(k->diffuse.z);
    K->sat = false;
}

/* vs_write_outputs_k per lane (K: consts8 of k); TEXCOORD0 (oTex) and TEXCOORD3 (id) are the instance's.  Only
 * oPos and the live outputs (k->live) are computed and stored; the others stay as the device left them (zero). */
static inline __attribute__((always_inline)) void outputs8(const vs_batch_consts *k, const consts8 *K,
                                                          const lanes8 *L, f3x8 pos, f3x8 normal, const float2 t[3],
                                                          float id, f3x8 g)
{
    const uint32_t live = k->live;
    v8f one = bf(1.0f), zero = bf(0.0f);
    v8f px[4];
#pragma GCC unroll 4
    for (int c = 0; c < 4; c++) px[c] = pos.x * K->w[0][c] + pos.y * K->w[1][c] + pos.z * K->w[2][c] + K->w[3][c];
    char *dst[8]; /* the lanes' outputs (a local array: the stores through it do not make the compiler reload it) */
    for (int i = 0; i < 8; i++) dst[i] = (char *)L->out0 + L->off[i];
    const int n = L->n_real;
    store4(dst, n, -1, px[0], px[1], px[2], px[3]);
    if (!(live & (IS_OUT_COLOR0 | IS_OUT_TEXCOORD(VS_OUT_TEX) | IS_OUT_TEXCOORD(VS_OUT_NORMAL) | IS_OUT_TEXCOORD(VS_OUT_BARY) | IS_OUT_TEXCOORD(VS_OUT_INSTANCE) |
                  IS_OUT_TEXCOORD(VS_OUT_GREGORY))))
        return;
    f3x8 N = {normal.x * K->m[0][0] + normal.y * K->m[1][0] + normal.z * K->m[2][0],
              normal.x * K->m[0][1] + normal.y * K->m[1][1] + normal.z * K->m[2][1],
              normal.x * K->m[0][2] + normal.y * K->m[1][2] + normal.z * K->m[2][2]};
    if (live & IS_OUT_COLOR0) {
        v8f d = N.x * bf(0.0f) + N.y * bf(0.0f) + N.z * bf(-1.0f);
        d = sel(d == d, d, zero);                                /* isnan(d) ? 0 : d */
        d = sel(d < zero, zero, sel(d > one, one, d));           /* saturate */
        v8f r = K->diffuse[0] * d, gr = K->diffuse[1] * d, bl = K->diffuse[2] * d;
        if (K->sat) r = sat8(r), gr = sat8(gr), bl = sat8(bl);
        store4(dst, n, RS_ATTR_COLOR0, r, gr, bl, one);
    }
    if (live & IS_OUT_TEXCOORD(VS_OUT_TEX)) {
        v8f tx = bf(t[0].x) * L->b.x + bf(t[1].x) * L->b.y + bf(t[2].x) * L->b.z;
        v8f ty = bf(t[0].y) * L->b.x + bf(t[1].y) * L->b.y + bf(t[2].y) * L->b.z;
        store4(dst, n, RS_ATTR_TEXCOORD0 + VS_OUT_TEX, tx, ty, zero, one);
    }
    if (live & IS_OUT_TEXCOORD(VS_OUT_NORMAL)) {
        f3x8 nn = normalize(N);
        store4(dst, n, RS_ATTR_TEXCOORD0 + VS_OUT_NORMAL, nn.x, nn.y, nn.z, zero);
    }
    if (live & IS_OUT_TEXCOORD(VS_OUT_BARY)) store4(dst, n, RS_ATTR_TEXCOORD0 + VS_OUT_BARY, L->b.x, L->b.y, L->b.z, one);
    if (live & IS_OUT_TEXCOORD(VS_OUT_INSTANCE)) store4(dst, n, RS_ATTR_TEXCOORD0 + VS_OUT_INSTANCE, bf(id), zero, zero, one);
    if (live & IS_OUT_TEXCOORD(VS_OUT_GREGORY)) store4(dst, n, RS_ATTR_TEXCOORD0 + VS_OUT_GREGORY, g.x, g.y, g.z, zero);
}

/* ---------------------------------------------------------------- the batch walk */

/* Edge k of an instance in canonical order (patch.c's edge_ends / edge_cubic): ends A, B and the inner control
 * points; ok false when both ends have the same position and normal bits (the order then depends on the
 * weights: such vertices stay per vertex). */
typedef struct edge_cp { float3 ap, bp, an, bn, b21, b12; bool ok, swapped; } edge_cp;

/* One instance as the batch sees it: the triangle, its texture coordinates and its patch's instance data. */
typedef struct inst8 {
    vs_patch p;
    vs_triangle T;
    vs_options o;
    npatch_cp cp;
    f3x8 cv[W_COUNT]; /* cp broadcast (npatch_cp_lanes) */
    f3x8 nv[3];       /* the normals broadcast */
    smooth_inst s;
    edge_cp e[3];
    consts8 K;        /* the batch's constants broadcast */
} inst8;

/* Edge k of T (v_k, v_k+1) in canonical order with edge_cubic's control points, as patch.c computes them. */
static void edge_cp_make(const vs_triangle *T, int k, edge_cp *e)
{
    int j = (k + 1) % 3;
    float fa[6] = {T->v[k].x, T->v[k].y, T->v[k].z, T->n[k].x, T->n[k].y, T->n[k].z};
    float fb[6] = {T->v[j].x, T->v[j].y, T->v[j].z, T->n[j].x, T->n[j].y, T->n[j].z};
    int c = vs_cmp_bits(fb, fa, 6);
    e->ok = c != 0;
    e->swapped = c < 0;
    int a = c < 0 ? j : k, b = c < 0 ? k : j;
    e->ap = T->v[a], e->bp = T->v[b], e->an = T->n[a], e->bn = T->n[b];
    float3 dAB = sub3(e->bp, e->ap), dBA = sub3(e->ap, e->bp);
    float3 offA = scale3(e->an, dot3(dAB, e->an)), offB = scale3(e->bn, dot3(dBA, e->bn));
    e->b21 = sub3(add3(scale3(e->ap, 2.0f), e->bp), offA);
    e->b12 = sub3(add3(scale3(e->bp, 2.0f), e->ap), offB);
}

/* The per-vertex path (the listing-form evaluation) for one vertex: the instance I and the vertex's POSITION0 (the
 * only register read from in, which is never shared: batch8). */
static void vertex1(const vs_batch_consts *k, const inst8 *I, const is_vs_input *in, is_vs_output *out)
{
    float3 b = f3_of(in->position[0]); // barycentric coords
    float3 pos, normal, g;
    vs_patch_eval(I->p, &I->T, b, &I->o, &pos, &normal, I->p == VS_PATCH_SMOOTH ? &g : NULL);
    if (I->p != VS_PATCH_SMOOTH) g = f3(0, 0, 0);
    float2 oTex = add2(add2(scale2(I->T.t[0], b.x), scale2(I->T.t[1], b.y)), scale2(I->T.t[2], b.z));
    vs_write_outputs_k(k, pos, normal, oTex, b, I->T.id, g, out);
    if (I->K.sat) saturate_color_outputs(&out->attr[RS_ATTR_COLOR0]); /* as outputs8's lanes (core/device.h) */
}

/* The lanes of L (below n_real) not in the 8-bit mask ok through the per-vertex path. */
static inline void fallback(const vs_batch_consts *k, const inst8 *I, const lanes8 *L, unsigned ok)
{
    for (unsigned bad = ~ok & ((1u << L->n_real) - 1u); bad; bad &= bad - 1u) {
        int i = __builtin_ctz(bad);
        vertex1(k, I, L->in0 + L->idx[i], L->out0 + L->idx[i]);
    }
}

/* Evaluate a full or partial group of lanes from their b-only values (w: npatch_weights, sw: smooth_weights, read
 * by the smoothed patch only); lanes needing a fallback go through vertex1. */
static void group8_w(const vs_batch_consts *k, const inst8 *I, lanes8 *L, const v8f w[W_COUNT], const smooth_w *sw)
{
    f3x8 b = L->b, g = {bf(0.0f), bf(0.0f), bf(0.0f)};
    v8i ok = all_lanes;
    f3x8 pos;
    if (I->p == VS_PATCH_SMOOTH) {
        ok &= sw->gok; /* vs_gregory's 0/0 case stays per vertex */
        pos = smooth8_w(&I->s, w, sw, &g);
    } else {
        pos = npatch8_w(I->cv, w);
    }
    ok &= finite3(pos);
    const f3x8 *n = I->nv;
    f3x8 nl = add(add(scl(n[0], b.x), scl(n[1], b.y)), scl(n[2], b.z)); /* linear_normal_raw */
    f3x8 N = normalize(nl);
    ok &= finite3(N) & (dot(N, N) > bf(0.0f));
    outputs8(k, &I->K, L, pos, N, I->T.t, I->T.id, g);
    fallback(k, I, L, mask_of(ok));
}

/* group8_w with the b-only values computed here. */
static void group8(const vs_batch_consts *k, const inst8 *I, lanes8 *L)
{
    v8f w[W_COUNT];
    smooth_w sw;
    npatch_weights(L->b, w);
    if (I->p == VS_PATCH_SMOOTH) smooth_weights(L->b, &sw);
    group8_w(k, I, L, w, &sw);
}

/* What edge_group8 computes from an edge lane's end weights (s, t) and b alone: the cubic products of edge_cubic
 * and, when gregory, the Gregory weights of bw (g valid where gok: the sum is positive). */
typedef struct edge_w { v8f sss, ttt, sst, stt; f3x8 g; v8i gok; } edge_w;
static inline void edge_weights(v8f s, v8f t, f3x8 b, bool gregory, edge_w *w)
{
    v8f zero = bf(0.0f);
    w->sss = s * s * s, w->ttt = t * t * t, w->sst = s * s * t, w->stt = s * t * t;
    if (!gregory) return;
    f3x8 bw = {sel(b.x > zero, b.x, zero), sel(b.y > zero, b.y, zero), sel(b.z > zero, b.z, zero)};
    v8f b0b2 = bw.x * bw.z, b0b1 = bw.x * bw.y, b1b2 = bw.y * bw.z, sum = b0b2 + b0b1 + b1b2;
    w->gok = sum > zero;
    w->g = (f3x8){b0b2 / sum, b0b1 / sum, b1b2 / sum};
}

/* Evaluate a group of edge lanes (edge_cubic, the linear edge normal, Gregory weights of bw) from their b-only
 * values w (edge_weights of L->s, L->t, L->b); lanes needing a fallback, and those not in ok, go through vertex1. */
static void edge_group8_w(const vs_batch_consts *k, const inst8 *I, lanes8 *L, const edge_w *w, v8i ok)
{
    v8f s = L->s, t = L->t, zero = bf(0.0f);
    f3x8 p = add(scl(L->ap, w->sss), scl(L->bp, w->ttt));
    p = add(p, scl(L->b21, w->sst));
    p = add(p, scl(L->b12, w->stt));
    ok &= finite3(p);
    f3x8 N = normalize(add(scl(L->an, s), scl(L->bn, t)));
    ok &= finite3(N) & (dot(N, N) > zero);
    f3x8 g = {zero, zero, zero};
    if (I->p == VS_PATCH_SMOOTH) {
        ok &= w->gok;
        g = w->g;
    }
    outputs8(k, &I->K, L, p, N, I->T.t, I->T.id, g);
    fallback(k, I, L, mask_of(ok));
}

/* edge_group8_w with the b-only values computed here. */
static void edge_group8(const vs_batch_consts *k, const inst8 *I, lanes8 *L)
{
    edge_w w;
    edge_weights(L->s, L->t, L->b, I->p == VS_PATCH_SMOOTH, &w);
    edge_group8_w(k, I, L, &w, all_lanes);
}

/* Lane i of L for vertex v (its input and output at L's bases). */
static inline void lane_at(lanes8 *L, int i, size_t v)
{
    L->own_idx[i] = (int32_t)v, L->own_off[i] = v * sizeof(is_vs_output);
}

/* Lanes over the batch in[0..), out[0..) with their own index arrays, empty. */
static void lanes_init(lanes8 *L, const is_vs_input *in, is_vs_output *out)
{
    L->in0 = in, L->out0 = out, L->idx = L->own_idx, L->off = L->own_off, L->n_real = 0;
    for (int i = 0; i < 8; i++) L->own_idx[i] = 0, L->own_off[i] = 0; /* (outputs8 reads all eight) */
}

/* Add edge vertex v (input in) of edge e with end weights (ws, wt) to the edge lanes; run them when full. */
static void push_edge(const vs_batch_consts *k, const inst8 *I, lanes8 *L, const edge_cp *e, float ws, float wt,
                      const is_vs_input *in, size_t v)
{
    int i = L->n_real++;
    L->b.x[i] = in->position[0].x, L->b.y[i] = in->position[0].y, L->b.z[i] = in->position[0].z;
    L->ap.x[i] = e->ap.x, L->ap.y[i] = e->ap.y, L->ap.z[i] = e->ap.z;
    L->bp.x[i] = e->bp.x, L->bp.y[i] = e->bp.y, L->bp.z[i] = e->bp.z;
    L->an.x[i] = e->an.x, L->an.y[i] = e->an.y, L->an.z[i] = e->an.z;
    L->bn.x[i] = e->bn.x, L->bn.y[i] = e->bn.y, L->bn.z[i] = e->bn.z;
    L->b21.x[i] = e->b21.x, L->b21.y[i] = e->b21.y, L->b21.z[i] = e->b21.z;
    L->b12.x[i] = e->b12.x, L->b12.y[i] = e->b12.y, L->b12.z[i] = e->b12.z;
    L->s[i] = ws, L->t[i] = wt;
    lane_at(L, i, v);
    if (L->n_real == 8) edge_group8(k, I, L), L->n_real = 0;
}

/* Add vertex v (input in) to the lanes; run the group when full. */
static void push_lane(const vs_batch_consts *k, const inst8 *I, lanes8 *L, const is_vs_input *in, size_t v)
{
    int i = L->n_real++;
    L->b.x[i] = in->position[0].x, L->b.y[i] = in->position[0].y, L->b.z[i] = in->position[0].z;
    lane_at(L, i, v);
    if (L->n_real == 8) group8(k, I, L), L->n_real = 0;
}

/* Run the partial groups: unused lanes repeat lane 0 (computed, not stored). */
static void flush_lanes(const vs_batch_consts *k, const inst8 *I, lanes8 *L, lanes8 *E)
{
    if (L->n_real) {
        for (int i = L->n_real; i < 8; i++) L->b.x[i] = L->b.x[0], L->b.y[i] = L->b.y[0], L->b.z[i] = L->b.z[0];
        group8(k, I, L);
        L->n_real = 0;
    }
    if (E->n_real) {
        for (int i = E->n_real; i < 8; i++) {
            f3x8 *f[] = {&E->b, &E->ap, &E->bp, &E->an, &E->bn, &E->b21, &E->b12};
            for (size_t q = 0; q < sizeof f / sizeof f[0]; q++)
                f[q]->x[i] = f[q]->x[0], f[q]->y[i] = f[q]->y[0], f[q]->z[i] = f[q]->z[0];
            E->s[i] = E->s[0], E->t[i] = E->t[0];
        }
        edge_group8(k, I, E);
        E->n_real = 0;
    }
}

/* Route vertex v of the lanes' batch (input in, output out): interior -> interior lanes, on a canonical edge ->
 * edge lanes, else (corners, degenerate edges, other normal modes) the per-vertex path. */
static void route(const vs_batch_consts *k, const inst8 *I, lanes8 *L, lanes8 *E, const is_vs_input *in,
                  is_vs_output *out, size_t v)
{
    const float4 b = in->position[0];
    float bw[3] = {b.x > 0.0f ? b.x : 0.0f, b.y > 0.0f ? b.y : 0.0f, b.z > 0.0f ? b.z : 0.0f};
    int zeros = (bw[0] == 0.0f) + (bw[1] == 0.0f) + (bw[2] == 0.0f);
    if (I->o.normals != VS_NORMALS_LINEAR || zeros >= 2) {
        vertex1(k, I, in, out);
    } else if (zeros == 0) {
        push_lane(k, I, L, in, v);
    } else {
        int zi = bw[0] == 0.0f ? 0 : (bw[1] == 0.0f ? 1 : 2), e = (zi + 1) % 3, j = (e + 1) % 3;
        const edge_cp *c = &I->e[e];
        if (!c->ok) vertex1(k, I, in, out); /* the weights keep with their ends through the swap */
        else push_edge(k, I, E, c, c->swapped ? bw[j] : bw[e], c->swapped ? bw[e] : bw[j], in, v);
    }
}

/* Read the instance of input r for patch p as the per-vertex shader does. */
static void inst_read(vs_patch p, const vs_batch_consts *k, const is_vs_input *r, inst8 *I)
{
    I->p = p;
    if (p == VS_PATCH_NPATCH) { /* VSInstancedNPatch: vs_triangle_make, default options but the normal mode */
        const float4 *T = r->texcoord;
        float3 v[3] = {f3_of(T[VS_IN_V0]), f3_of(T[VS_IN_V0 + 1]), f3_of(T[VS_IN_V0 + 2])};
        float3 nn[3] = {f3_of(T[VS_IN_N0]), f3_of(T[VS_IN_N0 + 1]), f3_of(T[VS_IN_N0 + 2])};
        I->T = vs_triangle_make(v, nn);
        for (int i = 0; i < 3; i++) I->T.t[i] = f2_of(r->texcoord[VS_IN_T0 + i]);
        I->T.id = r->texcoord[VS_IN_ID].x;
        I->o = vs_default_options();
        I->o.normals = k->o.normals;
        I->o.quad_factor = k->o.quad_factor;
    } else {
        vs_triangle_from_input(r, &I->T);
        I->o = k->o;
    }
    const float3 *v = I->T.v, *n = I->T.n;
    npatch_cp_make(v[0], v[1], v[2], n[0], n[1], n[2], &I->cp);
    npatch_cp_lanes(&I->cp, I->cv);
    for (int i = 0; i < 3; i++) I->nv[i] = b3(n[i]);
    if (p == VS_PATCH_SMOOTH) {
        I->s.cv = I->cv;
        I->s.fn = vs_smooth_fn(&I->T);
        I->s.T = &I->T;
        I->s.shortcut = !(I->o.flags & VS_FLAG_NO_SHORTCUT);
        for (int q = 0; q < 3; q++) /* P_q: edge v_q - v_q+1, far vertex v_q+2 */
            if (smooth_evals(&I->s, q))
                pk_make(v[q], v[(q + 1) % 3], v[(q + 2) % 3], n[q], n[(q + 1) % 3], n[(q + 2) % 3], &I->s.pk[q]);
    }
    for (int e = 0; e < 3; e++) edge_cp_make(&I->T, e, &I->e[e]);
}

/* Are the n >= 32 bytes at a and b the same bits?  32 at a time (the last block overlapping), one branch at the
 * end: n is a constant at every call, so the loop unrolls into a few loads and compares. */
static inline __attribute__((always_inline)) bool same_bytes(const void *a, const void *b, size_t n)
{
    const char *p = a, *q = b;
    __m256i eq = _mm256_set1_epi8(-1);
#pragma GCC unroll 16
    for (size_t o = 0; o < n; o += 32) {
        size_t at = o + 32 > n ? n - 32 : o;
        __m256i x = _mm256_loadu_si256((const __m256i *)(p + at)), y = _mm256_loadu_si256((const __m256i *)(q + at));
        eq = _mm256_and_si256(eq, _mm256_cmpeq_epi8(x, y));
    }
    return (unsigned)_mm256_movemask_epi8(eq) == 0xffffffffu;
}

/* The registers patch p's instance part reads: what same_inst compares. */
static uint32_t inst_regs(vs_patch p)
{
    if (p == VS_PATCH_NPATCH) return ((1u << (VS_IN_ID + 1)) - 1u) << IS_VS_REG_TEXCOORD;
    return IS_VS_REGS_INSTANCE;
}

/* Do a and b hold the same registers for patch p's instance data? */
static bool same_inst(vs_patch p, const is_vs_input *a, const is_vs_input *b)
{
    _Static_assert((VS_IN_ID + 1) * sizeof(float4) >= 32, "same_bytes compares at least 32 bytes");
    if (p == VS_PATCH_NPATCH) return same_bytes(a->texcoord, b->texcoord, (VS_IN_ID + 1) * sizeof(float4));
    return same_bytes((const char *)a + sizeof(float4), (const char *)b + sizeof(float4), sizeof *a - sizeof(float4));
}

/* The batch of patch p (npatch or smooth): interior vertices 8 at a time (linear normals), the rest one by one.
 * When the shared registers hold the whole instance and not POSITION0 (the device's fused path) the instance is
 * read once from in[0], the vertices are not compared, and each vertex's POSITION0 is its own; other shared masks
 * get complete inputs, 32 vertices at a time. */
static void batch8(vs_patch p, const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live,
                   uint32_t shared, is_vs_output *out)
{
    if (shared && ((inst_regs(p) & ~shared) || (shared & 1u))) {
        is_vs_input t[32];
        for (size_t b = 0; b < n; b += 32) {
            size_t m = n - b < 32 ? n - b : 32;
            for (size_t v = 0; v < m; v++) {
                const is_vs_input *r = is_vs_input_at(in, b + v, shared, &t[v]);
                if (r != &t[v]) t[v] = *r;
            }
            batch8(p, c, t, m, live, 0, out + b);
        }
        return;
    }
    vs_batch_consts k;
    vs_batch_consts_read(c, &k);
    k.live = live;
    inst8 I;
    consts8_make(&k, &I.K);
    lanes8 L, E;
    lanes_init(&L, in, out), lanes_init(&E, in, out);
    for (size_t v = 0; v < n; v++) {
        if (v == 0 || (!shared && !same_inst(p, &in[v], &in[v - 1]))) {
            flush_lanes(&k, &I, &L, &E);
            inst_read(p, &k, &in[v], &I);
        }
        route(&k, &I, &L, &E, &in[v], &out[v], v);
    }
    flush_lanes(&k, &I, &L, &E);
}

/* ---------------------------------------------------------------- the grid plan
 * The device's fused path shades every instance of a draw over the same grid points (the per-vertex registers;
 * the instance is in[0]'s shared registers).  Which vertices are interior, on an edge or corners, their lanes and
 * every value route and the group functions derive from b alone (npatch_weights, smooth_weights, edge_weights in
 * both end orders) are computed once per grid into the caller's workspace (is_vs_grid), by the same expressions:
 * each lane then performs exactly the operations of batch8's lanes, so the bytes are batch8's. */

/* Eight interior grid points (lanes past n_real repeat lane 0): b, their b-only values, their vertex indices. */
typedef struct plan_int {
    f3x8 b;
    v8f w[W_COUNT];
    smooth_w sw;
    int32_t idx[8];
    size_t off[8]; /* idx * sizeof(is_vs_output) */
    int32_t n_real;
} plan_int;

/* Eight edge grid points (sorted by edge; lanes past n_real repeat lane 0): b, the weights s, t of the ends of
 * their edge e in its own order (v_e, v_e+1), edge_weights of (s, t) (w[0]) and of (t, s) (w[1]: the instance's
 * canonical order swaps the ends), the lanes on each edge and the one edge of every lane (-1: several). */
typedef struct plan_edge {
    f3x8 b;
    v8f s, t;
    edge_w w[2];
    v8i on[3];
    int32_t idx[8];
    size_t off[8];
    int32_t n_real, edge;
} plan_edge;

/* Eight corner grid points (two or more weights <= 0; lanes past n_real repeat lane 0): b, the corner each lane
 * is (vs_patch_eval's: the last positive weight's vertex, v0 when none is), its Gregory weights (vs_gregory of bw,
 * the per-vertex function itself). */
typedef struct plan_corner {
    f3x8 b, g;
    v8i on[3];
    int32_t idx[8];
    size_t off[8];
    int32_t n_real;
} plan_corner;

#define PLAN_TAG 0x38686362u /* "bch8": a plan of this file */

/* The plan of a grid of n vertices: ig[0..n_int) interior groups, eg[0..n_edge) edge groups, cg[0..n_corner)
 * corner groups; one[0..n_one) the corners' vertices. */
typedef struct grid_plan {
    uint32_t tag;
    size_t n;
    uint32_t n_int, n_edge, n_corner, n_one;
    plan_int *ig;
    plan_edge *eg;
    plan_corner *cg;
    uint32_t *one;
} grid_plan;

/* Align p up to 64 bytes. */
static inline void *align64(void *p) { return (void *)(((uintptr_t)p + 63u) & ~(uintptr_t)63u); }

/* The workspace bytes the plan of n vertices needs (alignment slack included). */
static size_t plan_room(size_t n)
{
    size_t groups = n / 8 + 3; /* the corners' list, then plan_build's classification scratch behind it */
    return 7 * 64 + sizeof(grid_plan) + groups * (sizeof(plan_int) + sizeof(plan_edge) + sizeof(plan_corner)) +
           n * (3 * sizeof(uint32_t) + 1 + 2 * sizeof(float));
}

/* Where route sends grid point b: 0 interior, 1 edge (its edge *e, the weights *s at v_e and *t at v_e+1), 2 a
 * corner -- route's tests on bw, in its order. */
static int plan_kind(float4 b, int *e, float *s, float *t)
{
    float bw[3] = {b.x > 0.0f ? b.x : 0.0f, b.y > 0.0f ? b.y : 0.0f, b.z > 0.0f ? b.z : 0.0f};
    int zeros = (bw[0] == 0.0f) + (bw[1] == 0.0f) + (bw[2] == 0.0f);
    if (zeros >= 2) return 2;
    if (zeros == 0) return 0;
    int zi = bw[0] == 0.0f ? 0 : (bw[1] == 0.0f ? 1 : 2);
    *e = (zi + 1) % 3;
    *s = bw[*e], *t = bw[(*e + 1) % 3];
    return 1;
}

/* Fill the interior groups from the interior vertices list[0..m) of in. */
static void plan_interior(grid_plan *P, const is_vs_input *in, const uint32_t *list, size_t m)
{
    for (size_t a = 0; a < m; a += 8) {
        plan_int *G = &P->ig[P->n_int++];
        G->n_real = (int32_t)(m - a < 8 ? m - a : 8);
        for (int i = 0; i < 8; i++) {
            uint32_t v = list[a + (size_t)(i < G->n_real ? i : 0)];
            G->idx[i] = (int32_t)v, G->off[i] = v * sizeof(is_vs_output);
            G->b.x[i] = in[v].position[0].x, G->b.y[i] = in[v].position[0].y, G->b.z[i] = in[v].position[0].z;
        }
        npatch_weights(G->b, G->w);
        smooth_weights(G->b, &G->sw);
    }
}

/* Fill the edge groups from the edge vertices list[0..m) of in (sorted by edge; edge_of, s, t per vertex). */
static void plan_edges(grid_plan *P, const is_vs_input *in, const uint32_t *list, size_t m, const int8_t *edge_of,
                       const float *s, const float *t)
{
    for (size_t a = 0; a < m; a += 8) {
        plan_edge *G = &P->eg[P->n_edge++];
        G->n_real = (int32_t)(m - a < 8 ? m - a : 8);
        G->edge = edge_of[list[a]];
        for (int i = 0; i < 8; i++) {
            uint32_t v = list[a + (size_t)(i < G->n_real ? i : 0)];
            G->idx[i] = (int32_t)v, G->off[i] = v * sizeof(is_vs_output);
            G->b.x[i] = in[v].position[0].x, G->b.y[i] = in[v].position[0].y, G->b.z[i] = in[v].position[0].z;
            G->s[i] = s[v], G->t[i] = t[v];
            for (int e = 0; e < 3; e++) G->on[e][i] = edge_of[v] == e ? -1 : 0;
            if (edge_of[v] != G->edge) G->edge = -1;
        }
        edge_weights(G->s, G->t, G->b, true, &G->w[0]);
        edge_weights(G->t, G->s, G->b, true, &G->w[1]);
    }
}

/* Fill the corner groups from the corner vertices list[0..m) of in. */
static void plan_corners(grid_plan *P, const is_vs_input *in, const uint32_t *list, size_t m)
{
    for (size_t a = 0; a < m; a += 8) {
        plan_corner *G = &P->cg[P->n_corner++];
        G->n_real = (int32_t)(m - a < 8 ? m - a : 8);
        for (int i = 0; i < 8; i++) {
            uint32_t v = list[a + (size_t)(i < G->n_real ? i : 0)];
            float4 b = in[v].position[0];
            float bw[3] = {b.x > 0.0f ? b.x : 0.0f, b.y > 0.0f ? b.y : 0.0f, b.z > 0.0f ? b.z : 0.0f};
            int corner = bw[2] != 0.0f ? 2 : bw[1] != 0.0f ? 1 : 0; /* patch.c's classify: the last nonzero */
            float3 g = vs_gregory(f3(bw[0], bw[1], bw[2]));
            G->idx[i] = (int32_t)v, G->off[i] = v * sizeof(is_vs_output);
            G->b.x[i] = b.x, G->b.y[i] = b.y, G->b.z[i] = b.z;
            G->g.x[i] = g.x, G->g.y[i] = g.y, G->g.z[i] = g.z;
            for (int e = 0; e < 3; e++) G->on[e][i] = corner == e ? -1 : 0;
        }
    }
}

/* Build the plan of in[0..n) into P (room from plan_room: the lists go to the end of the workspace). */
static void plan_build(grid_plan *P, const is_vs_input *in, size_t n)
{
    size_t groups = n / 8 + 3;
    P->tag = PLAN_TAG, P->n = n, P->n_int = P->n_edge = P->n_corner = P->n_one = 0;
    P->ig = align64(P + 1);
    P->eg = align64(P->ig + groups);
    P->cg = align64(P->eg + groups);
    P->one = align64(P->cg + groups);
    /* scratch for the classification: interior and edge lists share `one`'s room behind it (n entries each) */
    uint32_t *ints = P->one + n, *edges = ints + n;
    int8_t *edge_of = (int8_t *)(edges + n);
    float *s = (float *)align64(edge_of + n), *t = s + n;
    size_t ni = 0, ne[3] = {0, 0, 0};
    for (size_t v = 0; v < n; v++) {
        int e = -1, kind = plan_kind(in[v].position[0], &e, &s[v], &t[v]);
        edge_of[v] = (int8_t)e;
        if (kind == 0) ints[ni++] = (uint32_t)v;
        else if (kind == 1) ne[e]++;
        else P->one[P->n_one++] = (uint32_t)v;
    }
    size_t at[3] = {0, ne[0], ne[0] + ne[1]};
    for (size_t v = 0; v < n; v++)
        if (edge_of[v] >= 0) edges[at[edge_of[v]]++] = (uint32_t)v;
    plan_interior(P, in, ints, ni);
    plan_edges(P, in, edges, ne[0] + ne[1] + ne[2], edge_of, s, t);
    plan_corners(P, in, P->one, P->n_one);
}

/* The plan of in[0..n) in workspace g: built when g is not ready or holds another grid's size or kind; NULL when
 * the workspace is too small (or n does not fit the plan's int32 indices). */
static const grid_plan *plan_get(is_vs_grid *g, const is_vs_input *in, size_t n)
{
    if (!g->mem || n > INT32_MAX || g->room < plan_room(n)) return NULL;
    grid_plan *P = align64(g->mem);
    if (g->ready && P->tag == PLAN_TAG && P->n == n) return P;
    plan_build(P, in, n);
    g->ready = true;
    return P;
}

/* The lanes of a plan group: b, and the inputs and outputs of its vertices (in + idx, at byte off from out). */
static inline void plan_lanes(lanes8 *L, f3x8 b, const int32_t idx[8], const size_t off[8], int n_real,
                              const is_vs_input *in, is_vs_output *out)
{
    L->b = b, L->n_real = n_real, L->idx = idx, L->off = off, L->in0 = in, L->out0 = out;
}

/* x with the lanes of m replaced by y's (a blend per float). */
static inline f3x8 pick3(f3x8 x, v8i m, f3x8 y) { return sel3(m, y, x); }

/* The edge groups of plan P for instance I: the ends and control points of each lane's edge in canonical order,
 * its end weights and edge_weights in that order; lanes on an edge without an order (ok false) go per vertex. */
static void plan_run_edges(const vs_batch_consts *k, const inst8 *I, const grid_plan *P, const is_vs_input *in,
                           is_vs_output *out)
{
    lanes8 L;
    for (uint32_t q = 0; q < P->n_edge; q++) {
        const plan_edge *G = &P->eg[q];
        plan_lanes(&L, G->b, G->idx, G->off, G->n_real, in, out);
        int e0 = G->edge >= 0 ? G->edge : 2;
        const edge_cp *c = &I->e[e0];
        L.ap = b3(c->ap), L.bp = b3(c->bp), L.an = b3(c->an), L.bn = b3(c->bn), L.b21 = b3(c->b21), L.b12 = b3(c->b12);
        v8i swap = c->swapped ? all_lanes : (v8i){0}, ok = c->ok ? all_lanes : (v8i){0};
        const edge_w *w = &G->w[c->swapped];
        edge_w mixed;
        if (G->edge < 0) { /* lanes of edges 0 and 1 over edge 2's */
            for (int e = 0; e < 2; e++) {
                const edge_cp *d = &I->e[e];
                v8i m = G->on[e];
                L.ap = pick3(L.ap, m, b3(d->ap)), L.bp = pick3(L.bp, m, b3(d->bp));
                L.an = pick3(L.an, m, b3(d->an)), L.bn = pick3(L.bn, m, b3(d->bn));
                L.b21 = pick3(L.b21, m, b3(d->b21)), L.b12 = pick3(L.b12, m, b3(d->b12));
                swap = d->swapped ? swap | m : swap & ~m;
                ok = d->ok ? ok | m : ok & ~m;
            }
            const edge_w *w0 = &G->w[0], *w1 = &G->w[1];
            mixed = *w;
            mixed.sss = sel(swap, w1->sss, w0->sss), mixed.ttt = sel(swap, w1->ttt, w0->ttt);
            mixed.sst = sel(swap, w1->sst, w0->sst), mixed.stt = sel(swap, w1->stt, w0->stt);
            w = &mixed;
        }
        L.s = sel(swap, G->t, G->s), L.t = sel(swap, G->s, G->t);
        edge_group8_w(k, I, &L, w, ok);
    }
}

/* The corner groups of plan P for instance I: vs_patch_eval's corner (position v_k, normal normalize(n_k), Gregory
 * weights of bw); lanes whose normal needs a fallback go per vertex. */
static void plan_run_corners(const vs_batch_consts *k, const inst8 *I, const grid_plan *P, const is_vs_input *in,
                             is_vs_output *out)
{
    lanes8 L;
    const f3x8 v0 = b3(I->T.v[0]), v1 = b3(I->T.v[1]), v2 = b3(I->T.v[2]);
    for (uint32_t q = 0; q < P->n_corner; q++) {
        const plan_corner *G = &P->cg[q];
        plan_lanes(&L, G->b, G->idx, G->off, G->n_real, in, out);
        f3x8 pos = pick3(pick3(v2, G->on[1], v1), G->on[0], v0);
        f3x8 N = normalize(pick3(pick3(I->nv[2], G->on[1], I->nv[1]), G->on[0], I->nv[0]));
        v8i ok = finite3(N) & (dot(N, N) > bf(0.0f));
        f3x8 g = {bf(0.0f), bf(0.0f), bf(0.0f)};
        if (I->p == VS_PATCH_SMOOTH) g = G->g;
        outputs8(k, &I->K, &L, pos, N, I->T.t, I->T.id, g);
        fallback(k, I, &L, mask_of(ok));
    }
}

/* Shade instance I (read from in[0]) over the grid of plan P: the interior, edge and corner groups. */
static void plan_run(const vs_batch_consts *k, const inst8 *I, const grid_plan *P, const is_vs_input *in,
                     is_vs_output *out)
{
    lanes8 L;
    for (uint32_t q = 0; q < P->n_int; q++) {
        const plan_int *G = &P->ig[q];
        plan_lanes(&L, G->b, G->idx, G->off, G->n_real, in, out);
        group8_w(k, I, &L, G->w, &G->sw);
    }
    plan_run_edges(k, I, P, in, out);
    plan_run_corners(k, I, P, in, out);
}

/* batch8 with the grid workspace g: the plan's path when the batch is the fused path's (the instance shared in
 * in[0], POSITION0 per vertex) with linear normals and g has room, else batch8 itself. */
static void grid_batch8(vs_patch p, const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live,
                        uint32_t shared, is_vs_grid *g, is_vs_output *out)
{
    vs_batch_consts k;
    vs_batch_consts_read(c, &k);
    k.live = live;
    bool fused = n && shared && !(inst_regs(p) & ~shared) && !(shared & 1u);
    const grid_plan *P = g && fused && k.o.normals == VS_NORMALS_LINEAR ? plan_get(g, in, n) : NULL;
    if (!P) {
        batch8(p, c, in, n, live, shared, out);
        sat_colors(out, n);
        return;
    }
    inst8 I;
    consts8_make(&k, &I.K);
    I.K.sat = true;
    inst_read(p, &k, in, &I);
    plan_run(&k, &I, P, in, out);
}

#else /* without AVX2: the per-vertex evaluation */

static void batch8(vs_patch p, const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live,
                   uint32_t shared, is_vs_output *out)
{
    if (p == VS_PATCH_SMOOTH) {
        vs_patch_batch(p, c, in, n, shared, out);
        return;
    }
    is_vs_input t;
    for (size_t v = 0; v < n; v++) vs_shader_npatch.main(c, is_vs_input_at(in, v, shared, &t), &out[v]);
}

static void grid_batch8(vs_patch p, const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live,
                        uint32_t shared, is_vs_grid *g, is_vs_output *out)
{
    batch8(p, c, in, n, live, shared, out);
    sat_colors(out, n);
}

static size_t plan_room(size_t n) { return 0; }

#endif

void vs_npatch_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                     is_vs_output *out)
{
    batch8(VS_PATCH_NPATCH, c, in, n, live, shared, out);
}

void vs_smooth_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                     is_vs_output *out)
{
    batch8(VS_PATCH_SMOOTH, c, in, n, live, shared, out);
}

void vs_npatch_grid_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                          is_vs_grid *grid, is_vs_output *out)
{
    grid_batch8(VS_PATCH_NPATCH, c, in, n, live, shared, grid, out);
}

void vs_smooth_grid_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                          is_vs_grid *grid, is_vs_output *out)
{
    grid_batch8(VS_PATCH_SMOOTH, c, in, n, live, shared, grid, out);
}

size_t vs_batch8_grid_room(size_t n)
{
    return n > SIZE_MAX / 64 ? 0 : plan_room(n);
}
