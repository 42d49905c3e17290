/* vs/explain.c -- what the patch shaders publish to the pipeline inspector (is_vs_explain_fn, core/inspect.h):
 * the numbers a shader computes for one vertex, by name, from the same functions its main body calls, so that they
 * are the render's numbers.  Every patch shader publishes
 *   b       the barycentrics of the grid point (POSITION0), w = 0
 *   where   x = 0 inside the triangle, 1 on an edge (y = the edge k: v_k - v_(k+1)%3), 2 at a corner (y = the
 *           vertex): on an edge or at a corner the patch is the edge curve or the vertex (vs.h, watertightness)
 *   pos     the patch point in object space (w = 1), whose transform by c0..c3 is oPos
 *   normal  the object-space unit normal the shader lights with (w = 0)
 * and the smoothed patches add Listing 1.1.2's intermediates at b (meaningful inside the triangle):
 *   g       the Gregory weights (Eq. 1.1.8)
 *   c       the border-curve parameters (Eq. 1.1.7)                                         (smooth only)
 *   fn      the face-normal factors fn0..fn2 (Eq. 1.1.10), bl the centre blend 27 b0 b1 b2  (smooth only)
 *   posN    the N-Patch point, P0..P2 the edge patches blended towards it (Eq. 1.1.11)      (smooth only)
 */
#include "vs_internal.h"

/* Append (name, v) to vals if there is room; the new count. */
static unsigned put(is_vs_value *vals, unsigned n, unsigned max, const char *name, float4 v)
{
    if (vals && n < max) vals[n] = (is_vs_value){name, v};
    return n < max ? n + 1 : n;
}

/* Where b lies: (0) inside, (1, k) on edge k, (2, k) at vertex k -- the patches' own classification rule
 * (components <= 0 and NaN are zero). */
static float4 where_of(float3 b)
{
    float w[3] = {b.x > 0.0f ? b.x : 0.0f, b.y > 0.0f ? b.y : 0.0f, b.z > 0.0f ? b.z : 0.0f};
    int zeros = (w[0] == 0.0f) + (w[1] == 0.0f) + (w[2] == 0.0f);
    if (zeros >= 2) {
        int k = w[0] != 0.0f ? 0 : w[1] != 0.0f ? 1 : w[2] != 0.0f ? 2 : 0;
        return f4(2.0f, (float)k, 0.0f, 0.0f);
    }
    if (zeros == 1) return f4(1.0f, (float)(w[2] == 0.0f ? 0 : w[0] == 0.0f ? 1 : 2), 0.0f, 0.0f);
    return f4(0.0f, 0.0f, 0.0f, 0.0f);
}

/* The values of patch p for the inputs in (constants c): see the top of the file. */
static unsigned explain_patch(vs_patch p, const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals,
                              unsigned max)
{
    if (!c || !in) return 0;
    float3 b = f3_of(in->position[0]);
    vs_triangle tri;
    vs_triangle_from_input(in, &tri);
    vs_options o = vs_options_from_constants(c);
    float3 pos, normal, g;
    vs_patch_eval(p, &tri, b, &o, &pos, &normal, &g);
    unsigned n = 0;
    n = put(vals, n, max, "b", f4_of(b, 0.0f));
    n = put(vals, n, max, "where", where_of(b));
    n = put(vals, n, max, "pos", f4_of(pos, 1.0f));
    n = put(vals, n, max, "normal", f4_of(normal, 0.0f));
    if (p == VS_PATCH_SMOOTH_INITIAL || p == VS_PATCH_SMOOTH) {
        vs_smooth_trace tr;
        float3 gi;
        if (p == VS_PATCH_SMOOTH) (void)vs_smooth_traced(&tri, b, o.flags, &gi, NULL, &tr);
        else (void)vs_smooth_initial_formula(&tri, b, &gi);
        n = put(vals, n, max, "g", f4_of(gi, 0.0f));
        if (p == VS_PATCH_SMOOTH) {
            n = put(vals, n, max, "c", f4_of(tr.c, 0.0f));
            n = put(vals, n, max, "fn", f4_of(tr.fn, 0.0f));
            n = put(vals, n, max, "bl", f4(tr.bl, 0.0f, 0.0f, 0.0f));
            n = put(vals, n, max, "posN", f4_of(tr.posN, 1.0f));
            n = put(vals, n, max, "P0", f4_of(tr.pos[0], 1.0f));
            n = put(vals, n, max, "P1", f4_of(tr.pos[1], 1.0f));
            n = put(vals, n, max, "P2", f4_of(tr.pos[2], 1.0f));
        }
    }
    return n;
}

/* The explain stage of each patch shader (vs_internal.h): explain_patch of its patch. */
unsigned vs_explain_flat(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max)
{
    return explain_patch(VS_PATCH_FLAT, c, in, vals, max);
}
unsigned vs_explain_npatch(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max)
{
    return explain_patch(VS_PATCH_NPATCH, c, in, vals, max);
}
unsigned vs_explain_smooth_initial(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max)
{
    return explain_patch(VS_PATCH_SMOOTH_INITIAL, c, in, vals, max);
}
unsigned vs_explain_smooth(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max)
{
    return explain_patch(VS_PATCH_SMOOTH, c, in, vals, max);
}
unsigned vs_explain_phong(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max)
{
    return explain_patch(VS_PATCH_PHONG, c, in, vals, max);
}
unsigned vs_explain_pn_aen(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max)
{
    return explain_patch(VS_PATCH_PN_AEN, c, in, vals, max);
}
