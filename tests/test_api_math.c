/* tests/test_api_math.c -- every public function of core/math.h with NULL matrices, zero, huge and non-finite
 * arguments: each returns a matrix (the zero matrix for degenerate projections: a field of view whose tangent is
 * 0, an aspect of 0, zn == zf, an orthographic box of width or height 0), never divides by zero (the sanitizer
 * stage has UBSan's float-divide-by-zero on), never reads through a NULL pointer.
 * tests/check_api_walkers.sh checks that every INSTESS_API function of core/math.h is named in this file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <string.h>

#include "../core/core.h"

static const float edge[] = {0.0f, -0.0f, 1.0f, -1.0f, 1e-45f, 1e-30f, 1e30f, FLT_MAX, -FLT_MAX, INFINITY,
                             -INFINITY, NAN, 3.14159265f, 6.28318531f};
enum { N_EDGE = sizeof edge / sizeof edge[0] };

/* Whether every entry of m is 0. */
static bool is_zero(const float4x4 *m)
{
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            if (m->m[i][j] != 0.0f) return false;
    return true;
}

/* NULL matrices: mat_mul and mat_transpose read them as zero, mat_inverse refuses them. */
static void test_null_matrices(void **state)
{
    (void)state;
    float4x4 id = mat_identity(), out;
    float4x4 r = mat_mul(NULL, &id);
    assert_true(is_zero(&r));
    r = mat_mul(&id, NULL);
    assert_true(is_zero(&r));
    r = mat_mul(NULL, NULL);
    assert_true(is_zero(&r));
    r = mat_transpose(NULL);
    assert_true(is_zero(&r));
    assert_false(mat_inverse(NULL, &out));
    assert_false(mat_inverse(&id, NULL));
    assert_false(mat_inverse(NULL, NULL));
    assert_true(mat_inverse(&id, &out));
    assert_memory_equal(&out, &id, sizeof id);
}

/* Degenerate projections: the zero matrix, without a division by zero. */
static void test_degenerate_projections(void **state)
{
    (void)state;
    float4x4 p = mat_perspective_fov_lh(0.0f, 1.0f, 0.1f, 10.0f);   /* tan(0) = 0 */
    assert_true(is_zero(&p));
    p = mat_perspective_fov_lh(1.0f, 0.0f, 0.1f, 10.0f);
    assert_true(is_zero(&p));
    p = mat_perspective_fov_lh(1.0f, 1.0f, 5.0f, 5.0f);
    assert_true(is_zero(&p));
    p = mat_ortho_lh(0.0f, 1.0f, 0.0f, 1.0f);
    assert_true(is_zero(&p));
    p = mat_ortho_lh(1.0f, 0.0f, 0.0f, 1.0f);
    assert_true(is_zero(&p));
    p = mat_ortho_lh(1.0f, 1.0f, 2.0f, 2.0f);
    assert_true(is_zero(&p));
    p = mat_perspective_fov_lh(1.0f, 1.0f, 0.1f, 10.0f);   /* an ordinary one is not */
    assert_false(is_zero(&p));
    assert_true(p.m[2][3] == 1.0f);
}

/* Every function over every pair of edge values: returns, and the projections of finite, non-degenerate
 * arguments are finite. */
static void test_edge_values(void **state)
{
    (void)state;
    for (int a = 0; a < N_EDGE; a++) {
        float x = edge[a];
        float4x4 m[] = {mat_translation(x, x, x), mat_scaling(x, 1, x), mat_rotation_x(x), mat_rotation_y(x),
                        mat_rotation_z(x)};
        for (size_t k = 0; k < sizeof m / sizeof m[0]; k++) {
            float4x4 t = mat_transpose(&m[k]), inv, prod = mat_mul(&m[k], &t);
            (void)prod;
            (void)mat_inverse(&m[k], &inv);
        }
        for (int b = 0; b < N_EDGE; b++) {
            float y = edge[b];
            float4x4 p = mat_perspective_fov_lh(x, y, x, y);
            p = mat_perspective_fov_lh(y, 1.0f, 0.5f, x);
            p = mat_ortho_lh(x, y, y, x);
            (void)p;
            float4x4 v = mat_look_at_lh((float3){x, y, x}, (float3){y, x, 0}, (float3){0, y, x});
            v = mat_look_at_lh((float3){x, x, x}, (float3){x, x, x}, (float3){0, 0, 0});   /* eye == at, no up */
            (void)v;
        }
    }
    float4x4 sing = mat_scaling(0, 1, 1), inv;
    assert_false(mat_inverse(&sing, &inv));   /* singular: false and the identity */
    float4x4 id = mat_identity();
    assert_memory_equal(&inv, &id, sizeof id);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_null_matrices),
        cmocka_unit_test(test_degenerate_projections),
        cmocka_unit_test(test_edge_values),
    };
    return cmocka_run_group_tests_name("api_math", tests, NULL, NULL);
}
