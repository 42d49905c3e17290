/* core/hlsl.h -- short HLSL-style helpers on the types of core/math.h: f3(x, y, z), add3, sub3, scale3, dot3,
 * cross3, normalize3, lerp3, saturate, mul4 (row vector times matrix), tex2Dlod, ...
 *
 * Conventions: as core/math.h.  Used by the library, the program and the tests so that shaders read like their
 * HLSL listings; not installed (the names are short and unprefixed: in a user's program they would collide).
 * Every function is static inline and pure.
 */
#ifndef INSTESS_CORE_HLSL_H
#define INSTESS_CORE_HLSL_H

#include <math.h>

#include "math.h"
#include "texture.h"

static inline float2 f2(float x, float y) { return (float2){x, y}; }
static inline float3 f3(float x, float y, float z) { return (float3){x, y, z}; }
static inline float4 f4(float x, float y, float z, float w) { return (float4){x, y, z, w}; }
static inline float3 f3_of(float4 v) { return (float3){v.x, v.y, v.z}; }   /* v.xyz */
static inline float2 f2_of(float4 v) { return (float2){v.x, v.y}; }        /* v.xy  */
static inline float4 f4_of(float3 v, float w) { return (float4){v.x, v.y, v.z, w}; }

static inline float3 add3(float3 a, float3 b) { return f3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline float3 sub3(float3 a, float3 b) { return f3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline float3 scale3(float3 a, float s) { return f3(a.x * s, a.y * s, a.z * s); }
static inline float3 neg3(float3 a) { return f3(-a.x, -a.y, -a.z); }
static inline float dot3(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline float3 cross3(float3 a, float3 b)
{
    return f3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float length3(float3 a) { return sqrtf(dot3(a, a)); }
/* HLSL normalize(); a zero vector stays zero instead of becoming NaN. */
static inline float3 normalize3(float3 a)
{
    float l = length3(a);
    return l > 0.0f ? scale3(a, 1.0f / l) : a;
}
static inline float3 lerp3(float3 a, float3 b, float t) { return add3(a, scale3(sub3(b, a), t)); }
static inline float saturate(float x) { return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x); }
/* D3D9's saturation of a vertex colour output component: clamped to [0, 1], NaN to 0 (x >= 0 ? x : 0, then
 * x <= 1 ? x : 1; branch-free). */
static inline float saturate_color(float x)
{
    x = x >= 0.0f ? x : 0.0f;
    return x <= 1.0f ? x : 1.0f;
}
/* What D3D9 does to a vertex shader's colour outputs oD0 and oD1 (c[0], c[1]) per vertex, before they are
 * interpolated: every component through saturate_color. */
static inline void saturate_color_outputs(float4 c[2])
{
    for (int k = 0; k < 2; k++) {
        c[k].x = saturate_color(c[k].x), c[k].y = saturate_color(c[k].y);
        c[k].z = saturate_color(c[k].z), c[k].w = saturate_color(c[k].w);
    }
}
static inline float2 add2(float2 a, float2 b) { return f2(a.x + b.x, a.y + b.y); }
static inline float2 scale2(float2 a, float s) { return f2(a.x * s, a.y * s); }
static inline float4 scale4(float4 a, float s) { return f4(a.x * s, a.y * s, a.z * s, a.w * s); }

/* HLSL's texture functions (core/texture.h has the rules): tex2Dlod(&c->s[k], float4(u, v, 0, lod)) in a vertex
 * shader reads vertex texture sampler k. */
static inline float4 tex2Dlod(const is_sampler *s, float4 t) { return tex_sample_lod(s, t); }
static inline float4 tex2Dgrad(const is_sampler *s, float2 uv, float2 ddx, float2 ddy)
{
    return tex_sample_grad(s, uv, ddx, ddy);
}
static inline float4 tex2Dbias(const is_sampler *s, float4 t, float2 ddx, float2 ddy)
{
    return tex_sample_bias(s, t, ddx, ddy);
}

/* mul(v, M) for a row vector v. */
static inline float4 mul4(float4 v, const float4x4 *M)
{
    float4 r;
    r.x = v.x * M->m[0][0] + v.y * M->m[1][0] + v.z * M->m[2][0] + v.w * M->m[3][0];
    r.y = v.x * M->m[0][1] + v.y * M->m[1][1] + v.z * M->m[2][1] + v.w * M->m[3][1];
    r.z = v.x * M->m[0][2] + v.y * M->m[1][2] + v.z * M->m[2][2] + v.w * M->m[3][2];
    r.w = v.x * M->m[0][3] + v.y * M->m[1][3] + v.z * M->m[2][3] + v.w * M->m[3][3];
    return r;
}
/* mul(v, (float3x3)M): direction transform by the upper 3x3. */
static inline float3 mul3x3(float3 v, const float4x4 *M)
{
    return f3(v.x * M->m[0][0] + v.y * M->m[1][0] + v.z * M->m[2][0],
              v.x * M->m[0][1] + v.y * M->m[1][1] + v.z * M->m[2][1],
              v.x * M->m[0][2] + v.y * M->m[1][2] + v.z * M->m[2][2]);
}

#endif
