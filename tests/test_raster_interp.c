/* tests/test_raster_interp.c -- attribute interpolation: perspective-correct values across a tilted quad
 * against the analytic ray-plane intersection (tolerance 2e-4 in the parameter, 1 LSB in colour), Gouraud
 * colours against screen-space barycentrics, flat shading with the first vertex's colour (also when that
 * vertex is clipped away), several slots through AOV planes, and perspective-correct lines. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../raster/raster.h"
#include "util/raster_util.h"

/* Opaque states: no culling, depth off, Gouraud, colour and TEXCOORD0 interpolated, full viewport. */
static rs_state base_state(int w, int h)
{
    rs_state st = test_rs_defaults(w, h);
    st.cull_mode = RS_CULL_NONE;
    st.z_enable = false;
    st.z_write = false;
    st.attr_mask |= 1u << RS_ATTR_TEXCOORD0;
    return st;
}

/* A vertex from clip position p, colour c and TEXCOORD0 t. */
static rs_vertex vtx(rs_vec4 p, rs_vec4 c, rs_vec4 t)
{
    rs_vertex v;
    memset(&v, 0, sizeof v);
    v.pos = p;
    v.attr[RS_ATTR_COLOR0] = c;
    v.attr[RS_ATTR_TEXCOORD0] = t;
    return v;
}

/* Channel ch (0 R .. 3 A) of pixel (x, y), sample 0. */
static int chan(const rs_target *rt, int x, int y, int ch)
{
    return (int)((rt->color[((size_t)y * rt->width + x) * rt->samples] >> (8 * ch)) & 0xffu);
}

/* ---- the tilted quad ---- */
enum { QW = 128, QH = 128 };
static const double XS = 1.5, YS = 1.5, ZN = 1.0, ZF = 100.0;
static const double O[3] = { -1.5, -1.2, 3.0 }, E1[3] = { 3.0, 0.0, 2.5 }, E2[3] = { 0.0, 2.4, 1.0 };

/* Clip position of view-space point P with the test's perspective projection (D3D: row vectors, z in [0, w]). */
static rs_vec4 project(const double *P)
{
    double q = ZF / (ZF - ZN);
    return (rs_vec4){ (float)(P[0] * XS), (float)(P[1] * YS), (float)(P[2] * q - ZN * q), (float)P[2] };
}

/* View-space point O + u E1 + v E2. */
static void quad_point(double u, double v, double *P)
{
    for (int i = 0; i < 3; i++) P[i] = O[i] + u * E1[i] + v * E2[i];
}

/* Analytic (u, v) seen through pixel centre (px, py): solve O + u E1 + v E2 = s d by Cramer's rule. */
static void analytic_uv(double px, double py, double *u, double *v)
{
    double d[3] = { ((px - QW / 2.0) / (QW / 2.0)) / XS, ((QH / 2.0 - py) / (QH / 2.0)) / YS, 1.0 };
    /* columns: E1, E2, -d; right side: -O */
    double m[3][3], r[3];
    for (int i = 0; i < 3; i++) { m[i][0] = E1[i]; m[i][1] = E2[i]; m[i][2] = -d[i]; r[i] = -O[i]; }
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    double du = r[0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (r[1] * m[2][2] - m[1][2] * r[2]) +
                m[0][2] * (r[1] * m[2][1] - m[1][1] * r[2]);
    double dv = m[0][0] * (r[1] * m[2][2] - m[1][2] * r[2]) - r[0] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                m[0][2] * (m[1][0] * r[2] - r[1] * m[2][0]);
    *u = du / det;
    *v = dv / det;
}

/* Screen position of view-space point P. */
static void screen_of(const double *P, double *X, double *Y)
{
    *X = (1.0 + P[0] * XS / P[2]) * QW / 2.0;
    *Y = (1.0 - P[1] * YS / P[2]) * QH / 2.0;
}

static void test_perspective_quad(void **state)
{
    (void)state;
    rs_context *rs = rs_create(2);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, QW, QH, 1), RS_OK);
    assert_int_equal(rs_target_add_aov(&rt, RS_ATTR_TEXCOORD0, 2), RS_OK);
    rs_target_clear(&rt, 3, 0, 1.0f);
    rs_state st = base_state(QW, QH);
    const double uv[4][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } };
    rs_vertex c[4];
    for (int i = 0; i < 4; i++) {
        double P[3];
        quad_point(uv[i][0], uv[i][1], P);
        c[i] = vtx(project(P), (rs_vec4){ (float)uv[i][0], (float)uv[i][1], 0.5f, 1.0f },
                   (rs_vec4){ (float)uv[i][0], (float)uv[i][1], 0.0f, 0.0f });
    }
    rs_vertex v[6] = { c[0], c[1], c[2], c[0], c[2], c[3] };
    rs_stats s;
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 6, NULL, 2, &s), RS_OK);
    /* screen positions of triangle 0 for the affine comparison */
    double sx[3], sy[3];
    for (int i = 0; i < 3; i++) {
        double P[3];
        quad_point(uv[i][0], uv[i][1], P);
        screen_of(P, &sx[i], &sy[i]);
    }
    double maxerr = 0, max_affine = 0;
    long covered = 0;
    for (int y = 0; y < QH; y++)
        for (int x = 0; x < QW; x++) {
            if (chan(&rt, x, y, 3) != 255) continue;
            covered++;
            double u, w;
            analytic_uv(x, y, &u, &w);
            const float *a = rt.aov[0].data + ((size_t)y * QW + x) * 2;
            double e = fmax(fabs(a[0] - u), fabs(a[1] - w));
            maxerr = fmax(maxerr, e);
            assert_true(abs(chan(&rt, x, y, 0) - (int)(u * 255 + 0.5)) <= 1);
            assert_true(abs(chan(&rt, x, y, 1) - (int)(w * 255 + 0.5)) <= 1);
            assert_int_equal(chan(&rt, x, y, 2), 128);
            /* screen-space (affine) interpolation inside triangle 0: u_affine = lambda1 + lambda2 */
            double ar = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sy[1] - sy[0]) * (sx[2] - sx[0]);
            double l1 = ((x - sx[0]) * (sy[2] - sy[0]) - (y - sy[0]) * (sx[2] - sx[0])) / ar;
            double l2 = ((sx[1] - sx[0]) * (y - sy[0]) - (sy[1] - sy[0]) * (x - sx[0])) / ar;
            if (l1 >= 0 && l2 >= 0 && l1 + l2 <= 1) max_affine = fmax(max_affine, fabs(l1 + l2 - u));
        }
    fprintf(stderr, "perspective quad: %ld pixels, max error %.3g (affine would be off by %.3g)\n", covered, maxerr,
            max_affine);
    assert_true(covered > 3000);
    assert_true(maxerr < 2e-4);
    assert_true(max_affine > 0.02); /* the test does distinguish perspective-correct from affine */
    rs_target_free(&rt);
    rs_destroy(rs);
}

/* Gouraud with w = 1: colour = screen barycentric mix, within 1 LSB. */
static void test_gouraud_ortho(void **state)
{
    (void)state;
    enum { S = 64 };
    rs_context *rs = rs_create(1);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, S, S, 1), RS_OK);
    rs_target_clear(&rt, 3, 0, 1.0f);
    rs_state st = base_state(S, S);
    /* screen (2,2), (60,2), (2,60): clockwise on screen */
    rs_vec4 p0 = { 2.0f / 32 - 1, 1 - 2.0f / 32, 0.5f, 1 }, p1 = { 60.0f / 32 - 1, 1 - 2.0f / 32, 0.5f, 1 },
            p2 = { 2.0f / 32 - 1, 1 - 60.0f / 32, 0.5f, 1 };
    rs_vec4 z = { 0, 0, 0, 0 };
    rs_vertex v[3] = { vtx(p0, (rs_vec4){ 1, 0, 0, 1 }, z), vtx(p1, (rs_vec4){ 0, 1, 0, 1 }, z),
                       vtx(p2, (rs_vec4){ 0, 0, 1, 1 }, z) };
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 3, NULL, 1, NULL), RS_OK);
    long n = 0;
    for (int y = 0; y < S; y++)
        for (int x = 0; x < S; x++) {
            if (chan(&rt, x, y, 3) == 0) continue;
            double l1 = (x - 2) / 58.0, l2 = (y - 2) / 58.0, l0 = 1 - l1 - l2;
            assert_true(abs(chan(&rt, x, y, 0) - (int)(l0 * 255 + 0.5)) <= 1);
            assert_true(abs(chan(&rt, x, y, 1) - (int)(l1 * 255 + 0.5)) <= 1);
            assert_true(abs(chan(&rt, x, y, 2) - (int)(l2 * 255 + 0.5)) <= 1);
            n++;
        }
    assert_int_equal(n, 58 * 59 / 2); /* centres with x, y >= 2 and x + y < 62 (the hypotenuse is a right edge) */
    rs_target_free(&rt);
    rs_destroy(rs);
}

/* Flat shading: every pixel, line pixel and point has the first vertex's colour, whatever the winding and
 * also when the first vertex is clipped away by the near plane. */
static void test_flat_first_vertex(void **state)
{
    (void)state;
    enum { S = 64 };
    rs_context *rs = rs_create(2);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, S, S, 1), RS_OK);
    rs_state st = base_state(S, S);
    st.shade_mode = RS_SHADE_FLAT;
    rs_vec4 z = { 0, 0, 0, 0 };
    const rs_vec4 red = { 1, 0, 0, 1 }, green = { 0, 1, 0, 1 }, blue = { 0, 0, 1, 1 };
    const uint32_t red8 = 0xff0000ffu;
    /* three triangles: clockwise, counter-clockwise, first vertex behind the near plane (z < 0) */
    rs_vertex tris[3][3] = {
        { vtx((rs_vec4){ -0.9f, 0.9f, 0.5f, 1 }, red, z), vtx((rs_vec4){ 0.9f, 0.9f, 0.5f, 1 }, green, z),
          vtx((rs_vec4){ -0.9f, -0.9f, 0.5f, 1 }, blue, z) },
        { vtx((rs_vec4){ -0.9f, 0.9f, 0.5f, 1 }, red, z), vtx((rs_vec4){ -0.9f, -0.9f, 0.5f, 1 }, green, z),
          vtx((rs_vec4){ 0.9f, 0.9f, 0.5f, 1 }, blue, z) },
        { vtx((rs_vec4){ 0.0f, 2.0f, -1.0f, 1 }, red, z), vtx((rs_vec4){ 0.9f, -0.9f, 0.5f, 1 }, green, z),
          vtx((rs_vec4){ -0.9f, -0.9f, 0.5f, 1 }, blue, z) },
    };
    const int fills[3] = { RS_FILL_SOLID, RS_FILL_WIREFRAME, RS_FILL_POINT };
    for (int f = 0; f < 3; f++)
        for (int t = 0; t < 3; t++) {
            st.fill_mode = fills[f];
            rs_target_clear(&rt, 3, 0, 1.0f);
            rs_stats s;
            assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, tris[t], 3, NULL, 1, &s), RS_OK);
            long n = 0;
            for (int k = 0; k < S * S; k++) {
                if (rt.color[k] == 0) continue;
                assert_int_equal(rt.color[k], red8);
                n++;
            }
            if (fills[f] == RS_FILL_POINT) assert_int_equal(n, t == 2 ? 2 : 3); /* input vertices only */
            else assert_true(n >= 20);
        }
    /* the same triangle with Gouraud shading is not all red */
    st.shade_mode = RS_SHADE_GOURAUD;
    st.fill_mode = RS_FILL_SOLID;
    rs_target_clear(&rt, 3, 0, 1.0f);
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, tris[0], 3, NULL, 1, NULL), RS_OK);
    assert_int_not_equal(rt.color[40 * S + 10], red8);
    rs_target_free(&rt);
    rs_destroy(rs);
}

/* Several slots through AOV planes (w = 1, values linear in screen space), a slot outside attr_mask reads 0
 * and an unwritten COLOR0 is white. */
static void test_slots_and_aov(void **state)
{
    (void)state;
    enum { S = 32 };
    rs_context *rs = rs_create(1);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, S, S, 1), RS_OK);
    assert_int_equal(rs_target_add_aov(&rt, RS_ATTR_TEXCOORD0 + 7, 4), RS_OK);
    assert_int_equal(rs_target_add_aov(&rt, RS_ATTR_COLOR1, 3), RS_OK);
    assert_int_equal(rs_target_add_aov(&rt, RS_ATTR_TEXCOORD0 + 3, 1), RS_OK); /* not in attr_mask */
    rs_target_clear(&rt, 3, 0, 1.0f);
    rs_state st = base_state(S, S);
    st.attr_mask = (1u << (RS_ATTR_TEXCOORD0 + 7)) | (1u << RS_ATTR_COLOR1);
    /* a quad covering the screen: screen X from -16 to 48 */
    const float X[4] = { -16, 48, 48, -16 }, Y[4] = { -16, -16, 48, 48 };
    rs_vertex c[4];
    for (int i = 0; i < 4; i++) {
        memset(&c[i], 0, sizeof c[i]);
        c[i].pos = (rs_vec4){ X[i] / 16 - 1, 1 - Y[i] / 16, 0.5f, 1 };
        c[i].attr[RS_ATTR_TEXCOORD0 + 7] = (rs_vec4){ X[i], Y[i], X[i] + Y[i], 7 };
        c[i].attr[RS_ATTR_COLOR1] = (rs_vec4){ Y[i] * 2, 1, -X[i], 0 };
        c[i].attr[RS_ATTR_TEXCOORD0 + 3] = (rs_vec4){ 5, 5, 5, 5 };
    }
    rs_vertex v[6] = { c[0], c[1], c[2], c[0], c[2], c[3] };
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_TRIANGLES, v, 6, NULL, 2, NULL), RS_OK);
    for (int y = 0; y < S; y++)
        for (int x = 0; x < S; x++) {
            const float *a = rt.aov[0].data + ((size_t)y * S + x) * 4, *b = rt.aov[1].data + ((size_t)y * S + x) * 3;
            assert_true(fabsf(a[0] - x) < 1e-4f && fabsf(a[1] - y) < 1e-4f && fabsf(a[2] - (x + y)) < 1e-4f);
            assert_true(fabsf(a[3] - 7) < 1e-5f);
            assert_true(fabsf(b[0] - 2 * y) < 1e-4f && fabsf(b[1] - 1) < 1e-5f && fabsf(b[2] + x) < 1e-4f);
            assert_true(rt.aov[2].data[(size_t)y * S + x] == 0.0f);
            assert_int_equal(rt.color[y * S + x], 0xffffffffu);
        }
    rs_target_free(&rt);
    rs_destroy(rs);
}

/* Lines: colour along a horizontal line (w = 1) and a perspective-correct parameter along a line whose ends
 * have w = 1 and w = 4. */
static void test_line_interpolation(void **state)
{
    (void)state;
    enum { S = 64 };
    rs_context *rs = rs_create(1);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, S, S, 1), RS_OK);
    assert_int_equal(rs_target_add_aov(&rt, RS_ATTR_TEXCOORD0, 1), RS_OK);
    rs_target_clear(&rt, 3, 0, 1.0f);
    rs_state st = base_state(S, S);
    rs_vertex l[4] = {
        vtx((rs_vec4){ -1, 0.5f, 0.5f, 1 }, (rs_vec4){ 0, 0, 0, 1 }, (rs_vec4){ 0, 0, 0, 0 }),
        vtx((rs_vec4){ 1, 0.5f, 0.5f, 1 }, (rs_vec4){ 1, 0, 0, 1 }, (rs_vec4){ 1, 0, 0, 0 }),
        /* row 48 (y = -0.5): from screen X 0 (w 1) to X 64 (w 4), u 0 -> 1 */
        vtx((rs_vec4){ -1, -0.5f, 0.5f, 1 }, (rs_vec4){ 0, 0, 0, 1 }, (rs_vec4){ 0, 0, 0, 0 }),
        vtx((rs_vec4){ 4, -2.0f, 2.0f, 4 }, (rs_vec4){ 0, 0, 0, 1 }, (rs_vec4){ 1, 0, 0, 0 }),
    };
    assert_int_equal(rs_draw(rs, &st, &rt, RS_PRIM_LINES, l, 4, NULL, 2, NULL), RS_OK);
    for (int x = 0; x < S; x++) {
        assert_true(abs(chan(&rt, x, 16, 0) - (int)(x / 64.0 * 255 + 0.5)) <= 1);
        assert_int_equal(chan(&rt, x, 16, 3), 255);
        double t = x / 64.0, u = (t / 4) / ((1 - t) + t / 4);
        float got = rt.aov[0].data[48 * S + x];
        assert_true(fabs(got - u) < 1e-5);
        assert_int_equal(chan(&rt, x, 48, 3), 255);
    }
    rs_target_free(&rt);
    rs_destroy(rs);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_perspective_quad),
        cmocka_unit_test(test_gouraud_ortho),
        cmocka_unit_test(test_flat_first_vertex),
        cmocka_unit_test(test_slots_and_aov),
        cmocka_unit_test(test_line_interpolation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
