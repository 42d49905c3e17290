/* vs/npatch.c -- the original N-Patch (seed 000, Eq. 1.1.1-1.1.2; Listing 1.1.2's evaluateNPatch), the device's
 * N-patch evaluator and the instanced N-Patch shader. */
#include "vs_internal.h"

#include "../core/hlsl.h"
/* evaluateNPatch of Listing 1.1.2, errata 1 and 2 resolved: the control points lack the /3 of Eq. 1.1.1 and the
 * weights lack the 3 (the products are the same), b111's 6 b111 = 0.5 * (sum of the six) - v0 - v1 - v2. */
float3 vs_evaluate_npatch(float3 v0, float3 v1, float3 v2, float3 n0, float3 n1, float3 n2, float3 b)
{
    float3 b102 = sub3(add3(scale3(v2, 2.0f), v0), scale3(n2, dot3(sub3(v0, v2), n2)));
    float3 b012 = sub3(add3(scale3(v2, 2.0f), v1), scale3(n2, dot3(sub3(v1, v2), n2)));
    float3 b201 = sub3(add3(scale3(v0, 2.0f), v2), scale3(n0, dot3(sub3(v2, v0), n0)));
    float3 b021 = sub3(add3(scale3(v1, 2.0f), v2), scale3(n1, dot3(sub3(v2, v1), n1)));
    float3 b210 = sub3(add3(scale3(v0, 2.0f), v1), scale3(n0, dot3(sub3(v1, v0), n0)));
    float3 b120 = sub3(add3(scale3(v1, 2.0f), v0), scale3(n1, dot3(sub3(v0, v1), n1)));
    float3 p = scale3(v0, b.x * b.x * b.x);
    p = add3(p, scale3(v1, b.y * b.y * b.y));
    p = add3(p, scale3(v2, b.z * b.z * b.z));
    p = add3(p, scale3(b102, b.x * b.z * b.z));
    p = add3(p, scale3(b012, b.y * b.z * b.z));
    p = add3(p, scale3(b201, b.x * b.x * b.z));
    p = add3(p, scale3(b021, b.y * b.y * b.z));
    p = add3(p, scale3(b210, b.x * b.x * b.y));
    p = add3(p, scale3(b120, b.x * b.y * b.y));
    float3 six = add3(add3(add3(b210, b120), add3(b021, b012)), add3(b102, b201));
    float3 center = sub3(sub3(sub3(scale3(six, 0.5f), v0), v1), v2);
    return add3(p, scale3(center, b.x * b.y * b.z));
}

/* The options' view of an N-patch evaluation: the one function the device, the CPU path and the shader use. */
static void npatch_eval(const float3 v[3], const float3 n[3], float3 b, uint32_t position_degree,
                        vs_normals normals, float quad_factor, float3 *pos, float3 *nrm)
{
    vs_triangle T = vs_triangle_make(v, n);
    vs_options o = vs_default_options();
    o.normals = normals;
    o.quad_factor = quad_factor;
    vs_patch p = position_degree == IS_DEGREE_LINEAR ? VS_PATCH_FLAT : VS_PATCH_NPATCH;
    vs_patch_eval(p, &T, b, &o, pos, nrm, NULL);
}

void vs_npatch_evaluate(const float3 v[3], const float3 n[3], float3 b, uint32_t position_degree,
                        uint32_t normal_degree, float3 *pos, float3 *nrm)
{
    if (!v || !n) {   /* no triangle: the origin, no normal */
        if (pos) *pos = f3(0, 0, 0);
        if (nrm) *nrm = f3(0, 0, 0);
        return;
    }
    vs_normals nm = normal_degree == IS_DEGREE_QUADRATIC ? VS_NORMALS_QUADRATIC
                  : normal_degree == VS_DEGREE_REAL      ? VS_NORMALS_REAL
                                                         : VS_NORMALS_LINEAR;
    float3 p, q;
    npatch_eval(v, n, b, position_degree, nm, 2.0f, &p, &q);
    if (pos) *pos = p;
    if (nrm) *nrm = q;
}

/* The N-Patch through instancing: Listing 1.1.2's inputs, posN only. */
static void VSInstancedNPatch(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    float3 b = f3_of(in->position[0]); // barycentric coords
    const float4 *T = in->texcoord;
    float3 v[3] = {f3_of(T[VS_IN_V0]), f3_of(T[VS_IN_V0 + 1]), f3_of(T[VS_IN_V0 + 2])};
    float3 n[3] = {f3_of(T[VS_IN_N0]), f3_of(T[VS_IN_N0 + 1]), f3_of(T[VS_IN_N0 + 2])};
    float2 t0 = f2_of(T[VS_IN_T0]), t1 = f2_of(T[VS_IN_T0 + 1]), t2 = f2_of(T[VS_IN_T0 + 2]);
    vs_options o = vs_options_from_constants(c);
    float3 posN, normal;
    npatch_eval(v, n, b, IS_DEGREE_CUBIC, o.normals, o.quad_factor, &posN, &normal);
    float2 oTex = add2(add2(scale2(t0, b.x), scale2(t1, b.y)), scale2(t2, b.z));
    vs_write_outputs(c, posN, normal, oTex, b, in->texcoord[VS_IN_ID].x, f3(0, 0, 0), out);
}

const is_vertex_shader vs_shader_npatch = {"npatch", VSInstancedNPatch, VS_OUTPUTS, vs_npatch_batch,
                                           vs_npatch_hull, vs_explain_npatch, vs_npatch_grid_batch,
                                           vs_batch8_grid_room};
