/* vs/smooth.c -- Gruen's smoothed N-Patches: the intermediate patch (Listing 1.1.1) and the final patch
 * (Listing 1.1.2, Eq. 1.1.9-1.1.11), errata resolved (docs/errata.md), and the per-edge shortcut. */
#include "vs_internal.h"

#include "../core/hlsl.h"
/* evaluateCurve of Listing 1.1.1 (Eq. 1.1.5): the cubic from v0 to v1 with end normals n0, n1 at b; the inner
 * control points lack the /3 and the weights the 3 (erratum 1: the same curve). */
float3 vs_evaluate_curve(float3 v0, float3 v1, float3 n0, float3 n1, float b)
{
    float b_ = 1.0f - b;
    // compute internal control points
    float3 b21 = sub3(add3(scale3(v0, 2.0f), v1), scale3(n0, dot3(sub3(v1, v0), n0)));
    float3 b12 = sub3(add3(scale3(v1, 2.0f), v0), scale3(n1, dot3(sub3(v0, v1), n1)));
    // evaluate curve
    float3 p = add3(scale3(v0, b_ * b_ * b_), scale3(v1, b * b * b));
    p = add3(p, scale3(b21, b_ * b_ * b));
    return add3(p, scale3(b12, b_ * b * b));
}

float3 vs_gregory(float3 b)
{
    float3 g; // gregory coords
    float b0b2 = b.x * b.z, b0b1 = b.x * b.y, b1b2 = b.y * b.z;
    float sum = b0b2 + b0b1 + b1b2;
    // compute gregory coords from barycentric coords; 0/0 only at a corner (erratum 4, not the 0.999 test)
    if (!(sum > 0.0f)) {
        if (b.x >= b.y && b.x >= b.z)
            g = f3(0.5f, 0.5f, 0.0f); // v0: edges v2-v0 (g.x) and v0-v1 (g.y)
        else if (b.y >= b.z)
            g = f3(0.0f, 0.5f, 0.5f); // v1: edges v0-v1 and v1-v2
        else
            g = f3(0.5f, 0.0f, 0.5f); // v2: edges v1-v2 and v2-v0
    } else {
        g.x = b0b2 / sum;
        g.y = b0b1 / sum;
        g.z = b1b2 / sum;
    }
    return g;
}

/* Curve parameter st = bj / (bi + bj) (Eq. 1.1.7: bj / (1 - bk)), 0.5 where bi = bj = 0 (erratum 4). */
static float curve_param(float bi, float bj)
{
    float den = bi + bj;
    return den > 0.0f ? bj / den : 0.5f;
}

/* P_k of Fig. 1.1.5: the curve from the border point at st (edge va-vb) to the opposite vertex vc, at ct. */
static float3 edge_patch(float3 va, float3 vb, float3 vc, float3 na, float3 nb, float3 nc, float st, float ct)
{
    float3 pos = vs_evaluate_curve(va, vb, na, nb, st);
    float3 norm = normalize3(lerp3(na, nb, st));
    return vs_evaluate_curve(pos, vc, norm, nc, ct);
}

float3 vs_smooth_initial_formula(const vs_triangle *T, float3 b, float3 *gout)
{
    if (!T) return f3(0, 0, 0);
    float3 v0 = T->v[0], v1 = T->v[1], v2 = T->v[2];
    float3 n0 = T->n[0], n1 = T->n[1], n2 = T->n[2];
    float3 g = vs_gregory(b); // gregory coords
    float3 c;                 // parameters for border curves/edges
    c.x = curve_param(b.x, b.y);
    c.y = curve_param(b.y, b.z);
    c.z = curve_param(b.z, b.x);
    // compute points on border curves
    float3 pos0 = vs_evaluate_curve(v0, v1, n0, n1, c.x);
    float3 pos1 = vs_evaluate_curve(v1, v2, n1, n2, c.y);
    float3 pos2 = vs_evaluate_curve(v2, v0, n2, n0, c.z);
    // compute interpolated normals
    float3 norm0 = normalize3(lerp3(n0, n1, c.x));
    float3 norm1 = normalize3(lerp3(n1, n2, c.y));
    float3 norm2 = normalize3(lerp3(n2, n0, c.z));
    // evaluate points on each of the three curves
    pos0 = vs_evaluate_curve(pos0, v2, norm0, n2, b.z);
    pos1 = vs_evaluate_curve(pos1, v0, norm1, n0, b.x);
    pos2 = vs_evaluate_curve(pos2, v1, norm2, n1, b.y);
    // gregory blend points on curves
    if (gout) *gout = g;
    return add3(add3(scale3(pos2, g.x), scale3(pos0, g.y)), scale3(pos1, g.z));
}

/* |dot(nf, face normal of (a, b, o))|: fn of one edge; 1 on a boundary (o = own third vertex), for a
 * degenerate face and within 2^-20 of 1. */
static float edge_fn(float3 nf, float3 a, float3 b, float3 o, float3 third)
{
    if (o.x == third.x && o.y == third.y && o.z == third.z) return 1.0f; // boundary / non-manifold: N-Patch
    float3 nn = normalize3(cross3(sub3(b, a), sub3(o, a)));
    if (!(dot3(nf, nf) > 0.0f) || !(dot3(nn, nn) > 0.0f)) return 1.0f;
    float d = fabsf(dot3(nf, nn));
    return d >= 1.0f - 0x1p-20f || !isfinite(d) ? 1.0f : d;
}

float3 vs_smooth_fn(const vs_triangle *T)
{
    if (!T) return f3(0, 0, 0);
    float3 v0 = T->v[0], v1 = T->v[1], v2 = T->v[2];
    // own face normal, and the neighbour across edge k traversed the other way: (v1, v0, opp0) etc.
    float3 nf = normalize3(cross3(sub3(v1, v0), sub3(v2, v0)));
    float fn0 = edge_fn(nf, v1, v0, T->opp[0], v2); // edge v0-v1 -> pos0
    float fn1 = edge_fn(nf, v2, v1, T->opp[1], v0); // edge v1-v2 -> pos1
    float fn2 = edge_fn(nf, v0, v2, T->opp[2], v1); // edge v2-v0 -> pos2
    return f3(fn0, fn1, fn2);
}

float3 vs_smooth_formula(const vs_triangle *T, float3 b, uint32_t flags, float3 *gout, int *p_evals)
{
    return vs_smooth_traced(T, b, flags, gout, p_evals, NULL);
}

float3 vs_smooth_traced(const vs_triangle *T, float3 b, uint32_t flags, float3 *gout, int *p_evals,
                        vs_smooth_trace *tr)
{
    if (!T) return f3(0, 0, 0);
    float3 v0 = T->v[0], v1 = T->v[1], v2 = T->v[2];
    float3 n0 = T->n[0], n1 = T->n[1], n2 = T->n[2];
    bool shortcut = !(flags & VS_FLAG_NO_SHORTCUT);
    float3 g = vs_gregory(b); // gregory coords
    float3 c;                 // parameters for border curves/edges
    c.x = curve_param(b.x, b.y);
    c.y = curve_param(b.y, b.z);
    c.z = curve_param(b.z, b.x);
    if (gout) *gout = g;
    if (p_evals) *p_evals = 0;
    // face normal based blending factors
    float3 fn = vs_smooth_fn(T);
    float fn0 = fn.x, fn1 = fn.y, fn2 = fn.z;
    // evaluate N-Patch
    float3 posN = vs_evaluate_npatch(v0, v1, v2, n0, n1, n2, b);
    // blend factor to blend towards N-Patch based on vicinity of the center of the tri
    float bl = 3 * 3 * 3 * b.x * b.y * b.z;
    if (tr) *tr = (vs_smooth_trace){.c = c, .fn = fn, .posN = posN, .bl = bl, .g = g,
                                    .pos = {posN, posN, posN}};
    // every bf is 1: pos0 = pos1 = pos2 = posN, and the Gregory blend of three posN is posN exactly
    bool all_one = fn0 == 1.0f && fn1 == 1.0f && fn2 == 1.0f;
    if (shortcut && all_one) return posN;
    // blend each patch towards the N-Patch (where fn_k == 1, lerp(P_k, posN, 1) is posN: skip P_k)
    float3 pos0 = posN, pos1 = posN, pos2 = posN;
    if (!shortcut || fn0 != 1.0f) {
        pos0 = vs_lerp3(edge_patch(v0, v1, v2, n0, n1, n2, c.x, b.z), posN, fminf(1.0f, fn0 + bl));
        if (p_evals) ++*p_evals;
        if (tr) tr->pos[0] = pos0;
    }
    if (!shortcut || fn1 != 1.0f) {
        pos1 = vs_lerp3(edge_patch(v1, v2, v0, n1, n2, n0, c.y, b.x), posN, fminf(1.0f, fn1 + bl));
        if (p_evals) ++*p_evals;
        if (tr) tr->pos[1] = pos1;
    }
    if (!shortcut || fn2 != 1.0f) {
        pos2 = vs_lerp3(edge_patch(v2, v0, v1, n2, n0, n1, c.z, b.y), posN, fminf(1.0f, fn2 + bl));
        if (p_evals) ++*p_evals;
        if (tr) tr->pos[2] = pos2;
    }
    if (all_one) return posN; // (without the shortcut: after evaluating every P_k)
    // gregory blend points on curves and blend with N-Patch again
    return vs_lerp3(add3(add3(scale3(pos2, g.x), scale3(pos0, g.y)), scale3(pos1, g.z)), posN, bl);
}

uint64_t vs_smooth_shortcut_savings(const vs_triangle *tris, size_t n, int level, uint64_t *total)
{
    uint64_t interior = level >= 3 ? (uint64_t)(level - 1) * (uint64_t)(level - 2) / 2 : 0, saved = 0;
    if (!tris) n = 0;
    for (size_t i = 0; i < n; i++) {
        float3 fn = vs_smooth_fn(&tris[i]);
        saved += interior * (uint64_t)((fn.x == 1.0f) + (fn.y == 1.0f) + (fn.z == 1.0f));
    }
    if (total) *total = interior * 3u * (uint64_t)n;
    return saved;
}

/* Listing 1.1.1 (VSInstancedPatch, initial implementation): the Gregory blend of P0, P1, P2. */
static void VSInstancedPatchInitial(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    vs_run_patch(VS_PATCH_SMOOTH_INITIAL, c, in, out);
}

/* Listing 1.1.2 (VSInstancedPatch, final): P0..P2 blended towards the N-Patch by fn0..fn2 and bl. */
static void VSInstancedPatch(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    vs_run_patch(VS_PATCH_SMOOTH, c, in, out);
}

/* The batched entries (vs.h): the same evaluation with the instance's triangle read once. */
static void VSInstancedPatchInitialBatch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live,
                                         uint32_t shared, is_vs_output *out)
{
    vs_patch_batch(VS_PATCH_SMOOTH_INITIAL, c, in, n, shared, out);
}

const is_vertex_shader vs_shader_smooth_initial = {"smooth-initial", VSInstancedPatchInitial, VS_OUTPUTS,
                                                   VSInstancedPatchInitialBatch, NULL, vs_explain_smooth_initial,
                                                   NULL, NULL};
const is_vertex_shader vs_shader_smooth = {"smooth", VSInstancedPatch, VS_OUTPUTS, vs_smooth_batch, NULL,
                                           vs_explain_smooth, vs_smooth_grid_batch, vs_batch8_grid_room};
