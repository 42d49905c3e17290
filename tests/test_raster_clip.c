/* tests/test_raster_clip.c -- homogeneous clipping: near and far planes with analytically known covered regions,
 * geometry behind the eye, huge coordinates (guard band, 1e30, FLT_MAX), NaN / inf, the viewport scissor, and
 * lines / points against the clip volume.  Coverage is counted with additive blending (1/255 per draw). */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "../raster/raster.h"
#include "util/raster_util.h"

enum { W = 64, H = 64 };

/* Additive-counting states for a full W x H viewport, no culling, no depth. */
static rs_state add_state(void) { return test_rs_additive(W, H); }

/* A clip-space vertex whose colour adds 1 to the red channel. */
static rs_vertex cv(float x, float y, float z, float w)
{
    rs_vertex v;
    memset(&v, 0, sizeof v);
    v.pos = (rs_vec4){ x, y, z, w };
    v.attr[RS_ATTR_COLOR0] = (rs_vec4){ 1.0f / 255.0f, 0.0f, 0.0f, 0.0f };
    return v;
}

/* Red-channel count of pixel (x, y), sample 0. */
static int cnt(const rs_target *rt, int x, int y) { return (int)(rt->color[((size_t)y * rt->width + x) * rt->samples] & 0xffu); }

/* Clear, draw n primitives of `prim` from consecutive vertices with state st, return stats. */
static rs_stats draw(rs_target *rt, const rs_state *st, int prim, const rs_vertex *v, size_t n)
{
    rs_context *rs = rs_create(2);
    rs_stats s;
    rs_target_clear(rt, 3, 0, 1.0f);
    size_t vpp = prim == RS_PRIM_TRIANGLES ? 3 : (prim == RS_PRIM_LINES ? 2 : 1);
    assert_int_equal(rs_draw(rs, st, rt, prim, v, n * vpp, NULL, n, &s), RS_OK);
    rs_destroy(rs);
    return s;
}

/* Expect count c_in for pixels where inside(x, y) and 0 elsewhere, within the rectangle. */
static void expect_region(const rs_target *rt, bool (*inside)(int, int), int c_in)
{
    long bad = 0;
    for (int y = 0; y < rt->height; y++)
        for (int x = 0; x < rt->width; x++) {
            int want = inside(x, y) ? c_in : 0;
            if (cnt(rt, x, y) != want && bad++ < 5) fprintf(stderr, "pixel %d,%d: %d, want %d\n", x, y, cnt(rt, x, y), want);
        }
    assert_int_equal(bad, 0);
}

static bool lower_half(int x, int y) { (void)x; return y >= H / 2; }
static bool all_px(int x, int y) { (void)x; (void)y; return true; }
static bool no_px(int x, int y) { (void)x; (void)y; return false; }
static bool left_half(int x, int y) { (void)y; return x < W / 2; }
static bool rows_23_54(int x, int y) { (void)x; return y >= 23 && y <= 54; }

/* A quad (two triangles sharing the diagonal) from four corners. */
static void quad(rs_vertex *v, rs_vertex a, rs_vertex b, rs_vertex c, rs_vertex d)
{
    v[0] = a; v[1] = b; v[2] = c; v[3] = a; v[4] = c; v[5] = d;
}

/* Orthographic quad with z = -y crossing the near plane z = 0 at the screen's middle row: exactly the lower
 * half (rows H/2.., the clipped edge is a top edge through the centres of row H/2) is covered, once. */
static void test_near_plane_half(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_state st = add_state();
    rs_vertex v[6];
    quad(v, cv(-3, 3, -3, 1), cv(3, 3, -3, 1), cv(3, -3, 3, 1), cv(-3, -3, 3, 1));
    rs_stats s = draw(&rt, &st, RS_PRIM_TRIANGLES, v, 2);
    expect_region(&rt, lower_half, 1);
    assert_int_equal(s.prims_drawn, 2);
    /* z = 0.3 - y: the near plane is at y = 0.3 (screen Y = 0.7 * 32 = 22.4) and the far plane z = 1 at
       y = -0.7 (Y = 54.4): rows 23..54 */
    quad(v, cv(-3, 3, -2.7f, 1), cv(3, 3, -2.7f, 1), cv(3, -3, 3.3f, 1), cv(-3, -3, 3.3f, 1));
    draw(&rt, &st, RS_PRIM_TRIANGLES, v, 2);
    expect_region(&rt, rows_23_54, 1);
    rs_target_free(&rt);
}

/* A perspective ground plane y = -1 (view space) from 5 units behind the eye (w < 0) to 50 in front, x in
 * [-50, 50], with a 90-degree projection (zn 1, zf 100): the projected plane covers the samples below the
 * image of its far edge, Y = (1 + 1/50) * 32 = 32.64 (so sample 0 of row 33, at 32.625, is out), each once. */
static void test_ground_plane_behind_eye(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 4), RS_OK);
    rs_state st = add_state();
    const float zn = 1, zf = 100, q = zf / (zf - zn);
    rs_vertex c[4];
    const float pts[4][3] = { { -50, -1, -5 }, { 50, -1, -5 }, { 50, -1, 50 }, { -50, -1, 50 } };
    for (int i = 0; i < 4; i++) c[i] = cv(pts[i][0], pts[i][1], pts[i][2] * q - zn * q, pts[i][2]);
    rs_vertex v[6];
    quad(v, c[0], c[1], c[2], c[3]);
    rs_stats s = draw(&rt, &st, RS_PRIM_TRIANGLES, v, 2);
    /* sample k of pixel (x, y) is at y + oy[k]: covered iff below the far edge, exactly once */
    static const double oy[4] = { -6.0 / 16, -2.0 / 16, 2.0 / 16, 6.0 / 16 };
    const double edge = 32.0 * (1.0 + 1.0 / 50.0);
    long bad = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int k = 0; k < 4; k++)
                bad += (int)(rt.color[((size_t)y * W + x) * 4 + k] & 0xff) != (y + oy[k] > edge ? 1 : 0);
    assert_int_equal(bad, 0);
    assert_int_equal(s.prims_drawn, 2);
    assert_int_equal(s.prims_clipped_away, 0);
    rs_target_free(&rt);
}

/* Entirely behind the eye (w < 0), and beyond the far plane: nothing drawn, counted as clipped away. */
static void test_behind_eye(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_state st = add_state();
    rs_vertex v[9] = { cv(-1, -1, -2, -1), cv(1, -1, -2, -1), cv(0, 1, -2, -1),     /* behind */
                       cv(-1, -1, 1, -1), cv(1, -1, 1, -1), cv(0, 1, 1, -1),        /* w < 0 < z: beyond far */
                       cv(-1, -1, 2, 1), cv(1, -1, 2, 1), cv(0, 1, 3, 1) };         /* beyond far */
    rs_stats s = draw(&rt, &st, RS_PRIM_TRIANGLES, v, 3);
    expect_region(&rt, no_px, 0);
    assert_int_equal(s.prims_in, 3);
    assert_int_equal(s.prims_clipped_away, 3);
    assert_int_equal(s.prims_drawn, 0);
    assert_int_equal(s.samples_tested, 0);
    rs_target_free(&rt);
}

/* Crossing the far plane: z = 1 + 0.5 x (w = 1) keeps x <= 0, the left half; the clipped edge is a right edge
 * through the centres of column W/2, which stays out. */
static void test_far_plane_half(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_state st = add_state();
    rs_vertex v[6];
    quad(v, cv(-3, 3, -0.5f, 1), cv(3, 3, 2.5f, 1), cv(3, -3, 2.5f, 1), cv(-3, -3, -0.5f, 1));
    draw(&rt, &st, RS_PRIM_TRIANGLES, v, 2);
    expect_region(&rt, left_half, 1);
    rs_target_free(&rt);
}

/* Huge coordinates: quads of two triangles with corners at 1e4 (guard band), 1e30 and FLT_MAX cover every
 * pixel exactly once; a huge w is just a point far away. */
static void test_huge_coordinates(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 4), RS_OK);
    rs_state st = add_state();
    const float big[] = { 1e4f, 1e8f, 1e30f, FLT_MAX };
    for (int i = 0; i < 4; i++) {
        float b = big[i];
        rs_vertex v[6];
        quad(v, cv(-b, b, 0.5f, 1), cv(b, b, 0.5f, 1), cv(b, -b, 0.5f, 1), cv(-b, -b, 0.5f, 1));
        rs_stats s = draw(&rt, &st, RS_PRIM_TRIANGLES, v, 2);
        expect_region(&rt, all_px, 1);
        assert_int_equal(s.prims_drawn, 2);
        /* one triangle spanning the screen with huge values */
        rs_vertex t[3] = { cv(-b, -b, 0.5f, 1), cv(0, b, 0.5f, 1), cv(b, -b, 0.5f, 1) };
        draw(&rt, &st, RS_PRIM_TRIANGLES, t, 1);
        assert_int_equal(cnt(&rt, 32, 32), 1);
        assert_int_equal(cnt(&rt, 0, 63), 1);
    }
    /* huge w and z: (x, y, z, w) scaled by 1e30 is the same point */
    rs_vertex v[6];
    float k = 1e30f;
    quad(v, cv(-2 * k, 2 * k, 0.5f * k, k), cv(2 * k, 2 * k, 0.5f * k, k), cv(2 * k, -2 * k, 0.5f * k, k),
         cv(-2 * k, -2 * k, 0.5f * k, k));
    draw(&rt, &st, RS_PRIM_TRIANGLES, v, 2);
    expect_region(&rt, all_px, 1);
    /* a sliver from 1e30 to a point: no crash, sane counts */
    rs_vertex s3[3] = { cv(1e30f, 1e30f, 0.5f, 1), cv(0, 0, 0.5f, 1), cv(1e30f, 1e30f * 1.0000001f, 0.5f, 1) };
    draw(&rt, &st, RS_PRIM_TRIANGLES, s3, 1);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) assert_true(cnt(&rt, x, y) <= 1);
    rs_target_free(&rt);
}

/* NaN and inf anywhere in a position drop the triangle (counted degenerate); valid ones still draw. */
static void test_nan_inf(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_state st = add_state();
    float nan = NAN, inf = INFINITY;
    rs_vertex v[6 * 3];
    float bad[6] = { nan, inf, -inf, nan, inf, nan };
    for (int i = 0; i < 6; i++) {
        rs_vertex t[3] = { cv(-3, 3, 0.5f, 1), cv(3, 3, 0.5f, 1), cv(0, -3, 0.5f, 1) };
        (&t[i % 3].pos.x)[i % 4] = bad[i];
        memcpy(&v[3 * i], t, sizeof t);
    }
    rs_stats s = draw(&rt, &st, RS_PRIM_TRIANGLES, v, 6);
    expect_region(&rt, no_px, 0);
    assert_int_equal(s.prims_degenerate, 6);
    assert_int_equal(s.prims_drawn, 0);
    /* NaN colours on a valid triangle: drawn, the colour saturates to 0 */
    rs_vertex q[6];
    quad(q, cv(-3, 3, 0.5f, 1), cv(3, 3, 0.5f, 1), cv(3, -3, 0.5f, 1), cv(-3, -3, 0.5f, 1));
    q[1].attr[RS_ATTR_COLOR0].x = nan;
    s = draw(&rt, &st, RS_PRIM_TRIANGLES, q, 2);
    assert_int_equal(s.prims_drawn, 2);
    /* NaN / inf lines and points */
    rs_vertex l[4] = { cv(nan, 0, 0.5f, 1), cv(1, 0, 0.5f, 1), cv(0, 0, 0.5f, inf), cv(0.5f, 0.5f, 0.5f, 1) };
    s = draw(&rt, &st, RS_PRIM_LINES, l, 2);
    assert_int_equal(s.prims_degenerate, 2);
    s = draw(&rt, &st, RS_PRIM_POINTS, l, 4);
    assert_int_equal(s.prims_degenerate, 2);
    assert_int_equal(s.prims_drawn, 2);
    rs_target_free(&rt);
}

static bool in_vp(int x, int y) { return x >= 10 && x < 40 && y >= 20 && y < 60; }

/* A viewport smaller than the target: a clip-space quad reaching into the guard band covers exactly the
 * viewport rectangle (the scissor). */
static void test_viewport_scissor(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_state st = add_state();
    st.viewport = (rs_viewport){ 10, 20, 30, 40, 0.0f, 1.0f };
    rs_vertex v[6];
    quad(v, cv(-5, 5, 0.5f, 1), cv(5, 5, 0.5f, 1), cv(5, -5, 0.5f, 1), cv(-5, -5, 0.5f, 1));
    draw(&rt, &st, RS_PRIM_TRIANGLES, v, 2);
    expect_region(&rt, in_vp, 1);
    /* exactly the clip volume [-1, 1]^2 also maps onto the viewport rectangle */
    quad(v, cv(-1, 1, 0.5f, 1), cv(1, 1, 0.5f, 1), cv(1, -1, 0.5f, 1), cv(-1, -1, 0.5f, 1));
    draw(&rt, &st, RS_PRIM_TRIANGLES, v, 2);
    expect_region(&rt, in_vp, 1);
    rs_target_free(&rt);
}

/* Lines crossing the near plane are clipped to their visible part; points outside the volume are dropped. */
static void test_lines_points_clip(void **state)
{
    (void)state;
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_state st = add_state();
    /* line along row 32 (y = 0) with z = -x: the near plane keeps x <= 0 and the far plane x >= -1, so the
       visible part runs from screen X = 0 to X = 32; the walk is half-open: columns 0..31 */
    rs_vertex l[2] = { cv(-2, 0, 2, 1), cv(2, 0, -2, 1) };
    rs_stats s = draw(&rt, &st, RS_PRIM_LINES, l, 1);
    assert_int_equal(s.prims_drawn, 1);
    for (int x = 0; x < W; x++) assert_int_equal(cnt(&rt, x, 32), x < 32 ? 1 : 0);
    for (int x = 0; x < W; x++) assert_int_equal(cnt(&rt, x, 31) + cnt(&rt, x, 33), 0);
    /* reversed: the walk starts at X = 32 and leaves out X = 0: columns 1..32 */
    rs_vertex l2[2] = { cv(2, 0, -2, 1), cv(-2, 0, 2, 1) };
    draw(&rt, &st, RS_PRIM_LINES, l2, 1);
    for (int x = 0; x < W; x++) assert_int_equal(cnt(&rt, x, 32), x >= 1 && x <= 32 ? 1 : 0);
    /* a line entirely behind the eye */
    rs_vertex l3[2] = { cv(-1, 0, -1, -1), cv(1, 0, -1, -1) };
    s = draw(&rt, &st, RS_PRIM_LINES, l3, 1);
    assert_int_equal(s.prims_clipped_away, 1);
    /* points: inside, behind, beyond far */
    rs_vertex p[3] = { cv(0, 0, 0.5f, 1), cv(0, 0, -0.5f, 1), cv(0, 0, 1.5f, 1) };
    s = draw(&rt, &st, RS_PRIM_POINTS, p, 3);
    assert_int_equal(s.prims_drawn, 1);
    assert_int_equal(s.prims_clipped_away, 2);
    assert_int_equal(cnt(&rt, 32, 32), 1);
    rs_target_free(&rt);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_near_plane_half),
        cmocka_unit_test(test_ground_plane_behind_eye),
        cmocka_unit_test(test_behind_eye),
        cmocka_unit_test(test_far_plane_half),
        cmocka_unit_test(test_huge_coordinates),
        cmocka_unit_test(test_nan_inf),
        cmocka_unit_test(test_viewport_scissor),
        cmocka_unit_test(test_lines_points_clip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
