/* core/adaptive.c -- D3D9's adaptive tessellation rule for the N-patch mode (core/device.h, "Adaptive N-patch mode"):
 * per-vertex levels from the eye depth and TESSFACTOR, per-edge levels as their mean, out-of-range and clamping. */
#include "core.h"
#include "hlsl.h"

/* S, F, V and Mdm in; T = S * F / dot(V, Mdm) out (float arithmetic, left to right, so a test can redo it).  A
 * depth of (+-)0 gives IEEE's quotient without dividing (the sanitizer build traps float division by zero): +-inf
 * by the signs, NaN for 0 / 0. */
float core_adaptive_vertex_level(float segments, float factor, float4 v, float4 mdm)
{
    const float z = v.x * mdm.x + v.y * mdm.y + v.z * mdm.z + v.w * mdm.w, num = segments * factor;
    if (z == 0.0f) return num == 0.0f || isnan(num) ? NAN : copysignf(INFINITY, num) * copysignf(1.0f, z);
    return num / z;
}

/* T_1, T_2, MIN and MAX in; the edge's level out: the mean, MAX when above MAX, negative or NaN, then at least MIN. */
float core_adaptive_edge_level(float t1, float t2, float min_level, float max_level)
{
    float te = (t1 + t2) / 2.0f;
    if (!(te <= max_level) || te < 0.0f) te = max_level; /* !(<=) is also true for NaN */
    if (te < min_level) te = min_level;
    return te;
}
