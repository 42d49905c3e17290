/* core/math.c -- D3DX-style matrices for row vectors (v' = mul(v, M)); see core.h for the conventions. */
#include "core.h"
#include "hlsl.h"

/* Identity matrix. */
float4x4 mat_identity(void)
{
    float4x4 r = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
    return r;
}

/* a * b: transforms by a first, then by b (a NULL matrix reads as the zero matrix). */
float4x4 mat_mul(const float4x4 *a, const float4x4 *b)
{
    float4x4 r = {{{0}}};
    if (!a || !b) return r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] + a->m[i][2] * b->m[2][j] +
                        a->m[i][3] * b->m[3][j];
    return r;
}

/* D3DXMatrixTranslation: the offset sits in the fourth row. */
float4x4 mat_translation(float x, float y, float z)
{
    float4x4 r = mat_identity();
    r.m[3][0] = x, r.m[3][1] = y, r.m[3][2] = z;
    return r;
}

/* D3DXMatrixScaling. */
float4x4 mat_scaling(float x, float y, float z)
{
    float4x4 r = mat_identity();
    r.m[0][0] = x, r.m[1][1] = y, r.m[2][2] = z;
    return r;
}

/* D3DXMatrixRotationX: y' = y cos - z sin, z' = y sin + z cos (row-vector form). */
float4x4 mat_rotation_x(float a)
{
    float4x4 r = mat_identity();
    float c = cosf(a), s = sinf(a);
    r.m[1][1] = c, r.m[1][2] = s, r.m[2][1] = -s, r.m[2][2] = c;
    return r;
}

/* D3DXMatrixRotationY. */
float4x4 mat_rotation_y(float a)
{
    float4x4 r = mat_identity();
    float c = cosf(a), s = sinf(a);
    r.m[0][0] = c, r.m[0][2] = -s, r.m[2][0] = s, r.m[2][2] = c;
    return r;
}

/* D3DXMatrixRotationZ. */
float4x4 mat_rotation_z(float a)
{
    float4x4 r = mat_identity();
    float c = cosf(a), s = sinf(a);
    r.m[0][0] = c, r.m[0][1] = s, r.m[1][0] = -s, r.m[1][1] = c;
    return r;
}

/* D3DXMatrixLookAtLH: zaxis = normalize(at - eye), xaxis = normalize(cross(up, zaxis)), yaxis = cross(z, x). */
float4x4 mat_look_at_lh(float3 eye, float3 at, float3 up)
{
    float3 z = normalize3(sub3(at, eye));
    float3 x = normalize3(cross3(up, z));
    float3 y = cross3(z, x);
    float4x4 r = {{{x.x, y.x, z.x, 0},
                   {x.y, y.y, z.y, 0},
                   {x.z, y.z, z.z, 0},
                   {-dot3(x, eye), -dot3(y, eye), -dot3(z, eye), 1}}};
    return r;
}

/* D3DXMatrixPerspectiveFovLH: [xs 0 0 0; 0 ys 0 0; 0 0 zf/(zf-zn) 1; 0 0 -zn*zf/(zf-zn) 0]. */
float4x4 mat_perspective_fov_lh(float fovy, float aspect, float zn, float zf)
{
    float t = tanf(fovy * 0.5f);
    if (t == 0.0f || aspect == 0.0f || zf == zn) return (float4x4){{{0}}};   /* degenerate: math.h */
    float ys = 1.0f / t;
    float xs = ys / aspect;
    float q = zf / (zf - zn);
    float4x4 r = {{{xs, 0, 0, 0}, {0, ys, 0, 0}, {0, 0, q, 1}, {0, 0, -zn * q, 0}}};
    return r;
}

/* D3DXMatrixOrthoLH: [2/w 0 0 0; 0 2/h 0 0; 0 0 1/(zf-zn) 0; 0 0 zn/(zn-zf) 1]. */
float4x4 mat_ortho_lh(float w, float h, float zn, float zf)
{
    if (w == 0.0f || h == 0.0f || zf == zn) return (float4x4){{{0}}};   /* degenerate: math.h */
    float4x4 r = {{{2.0f / w, 0, 0, 0}, {0, 2.0f / h, 0, 0}, {0, 0, 1.0f / (zf - zn), 0},
                   {0, 0, zn / (zn - zf), 1}}};
    return r;
}

/* Transpose. */
float4x4 mat_transpose(const float4x4 *a)
{
    float4x4 r = {{{0}}};
    if (!a) return r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) r.m[i][j] = a->m[j][i];
    return r;
}

/* Inverse by Gauss-Jordan elimination with partial pivoting (in double); false and identity if singular. */
bool mat_inverse(const float4x4 *a, float4x4 *out)
{
    if (!a || !out) return false;
    double m[4][8];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 8; j++) m[i][j] = j < 4 ? a->m[i][j] : (j - 4 == i);
    for (int c = 0; c < 4; c++) {
        int p = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(m[r][c]) > fabs(m[p][c])) p = r;
        if (!(fabs(m[p][c]) > 1e-30)) {
            *out = mat_identity();
            return false;
        }
        for (int j = 0; j < 8; j++) {
            double t = m[c][j];
            m[c][j] = m[p][j], m[p][j] = t;
        }
        double inv = 1.0 / m[c][c];
        for (int j = 0; j < 8; j++) m[c][j] *= inv;
        for (int r = 0; r < 4; r++) {
            if (r == c) continue;
            double f = m[r][c];
            for (int j = 0; j < 8; j++) m[r][j] -= f * m[c][j];
        }
    }
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) out->m[i][j] = (float)m[i][j + 4];
    return true;
}
