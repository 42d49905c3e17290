/* core/math.h -- the HLSL-like vector and matrix types and the D3DX-style matrix functions.
 *
 * Conventions: left-handed spaces as D3D9; row vectors, v' = mul(v, M): a matrix's translation is its 4th row and
 * M = World * View * Proj applies World first.  float4x4.m[row][col].  The short inline helpers that shaders use
 * (f3, add3, dot3, saturate, mul4, ...) are in core/hlsl.h, which is not installed: they would otherwise land in
 * every user's namespace.
 */
#ifndef INSTESS_CORE_MATH_H
#define INSTESS_CORE_MATH_H

#include <stdbool.h>

#include "api.h"
#include "../raster/raster.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct float2 { float x, y; } float2;
typedef struct float3 { float x, y, z; } float3;
typedef rs_vec4 float4;                       /* { x, y, z, w } */
typedef struct float4x4 { float m[4][4]; } float4x4; /* m[row][col], row vectors */

INSTESS_API float4x4 mat_identity(void);
/* A * B (apply A first, then B, for row vectors). */
INSTESS_API float4x4 mat_mul(const float4x4 *a, const float4x4 *b);
INSTESS_API float4x4 mat_translation(float x, float y, float z);
INSTESS_API float4x4 mat_scaling(float x, float y, float z);
/* D3DXMatrixRotationX/Y/Z: angle in radians, left-handed (clockwise looking down the axis to the origin). */
INSTESS_API float4x4 mat_rotation_x(float a);
INSTESS_API float4x4 mat_rotation_y(float a);
INSTESS_API float4x4 mat_rotation_z(float a);
/* D3DXMatrixLookAtLH. */
INSTESS_API float4x4 mat_look_at_lh(float3 eye, float3 at, float3 up);
/* D3DXMatrixPerspectiveFovLH: fovy in radians, aspect = width / height, z in [zn, zf] -> [0, 1].  Degenerate
 * arguments (tan(fovy / 2) == 0, aspect 0, zn == zf), where D3DX would divide by zero, give the zero matrix (what
 * it transforms is not drawn); so does mat_ortho_lh for w or h 0 or zn == zf. */
INSTESS_API float4x4 mat_perspective_fov_lh(float fovy, float aspect, float zn, float zf);
/* D3DXMatrixOrthoLH. */
INSTESS_API float4x4 mat_ortho_lh(float w, float h, float zn, float zf);
/* Transpose; inverse (returns false, and identity, when singular; false and nothing written for a NULL pointer).
 * mat_mul and mat_transpose read a NULL matrix as the zero matrix. */
INSTESS_API float4x4 mat_transpose(const float4x4 *a);
INSTESS_API bool mat_inverse(const float4x4 *a, float4x4 *out);

#ifdef __cplusplus
}
#endif
#endif
