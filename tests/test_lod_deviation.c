/* tests/test_lod_deviation.c -- the deviation mode of tess_lod_levels (TESS_LOD_DEVIATION, tess/tess.h): under an
 * affine view (orthographic, where the projected border curve is the cubic of the projected control points) every
 * edge's N-Patch border curve lies within the target of its polyline at the level chosen (checked at 256
 * parameters per edge, for bumpy sheets, several targets and level ranges), a flat sheet's straight edges take
 * min_level, no target (0, negative, NaN) or a corner behind the eye takes max_level, and the screen mode's levels
 * do not change with the new mode's code (the same sheet, against a copy of its rule). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/core.h"
#include "../core/hlsl.h"
#include "../meshes/meshes.h"
#include "../tess/tess.h"

enum { SHEET_N = 24, SIDE = 512 };

/* A deterministic number in [0, 1) from *s (a 64-bit LCG). */
static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* An N x N sheet over [-0.9, 0.9]^2 with heights bump * [0, 1) (normals computed by mesh_create) and its edges. */
static void sheet(double bump, uint64_t seed, is_mesh *m, tess_lod_edges *e)
{
    float3 p[SHEET_N * SHEET_N];
    uint32_t idx[6 * (SHEET_N - 1) * (SHEET_N - 1)], *q = idx;
    for (int j = 0; j < SHEET_N; j++)
        for (int i = 0; i < SHEET_N; i++)
            p[j * SHEET_N + i] = f3(-0.9f + 1.8f * (float)i / (SHEET_N - 1), -0.9f + 1.8f * (float)j / (SHEET_N - 1),
                                    (float)(bump * lcg(&seed)));
    for (int j = 0; j + 1 < SHEET_N; j++)
        for (int i = 0; i + 1 < SHEET_N; i++) {
            uint32_t a = (uint32_t)(j * SHEET_N + i), b = a + 1, c = a + SHEET_N, d = c + 1;
            *q++ = a, *q++ = b, *q++ = d, *q++ = a, *q++ = d, *q++ = c;
        }
    is_mesh_data md = {SHEET_N * SHEET_N, 2 * (SHEET_N - 1) * (SHEET_N - 1), p, NULL, NULL, idx};
    char err[256];
    assert_int_equal(mesh_create(m, "sheet", &md, NULL, err, sizeof err), 0);
    assert_int_equal(tess_lod_edges_build(m, e, err, sizeof err), 0);
}

/* Edge k's border-curve control points (tess/lod.c's edge_polygon: b300, b210, b120, b030) projected by p. */
static void edge_pixels(const tess_lod_params *p, const is_mesh *m, const tess_lod_edges *e, size_t k, double x[4],
                        double y[4])
{
    const float3 pa = m->positions[e->ends[k][0]], pb = m->positions[e->ends[k][1]];
    const float3 na = e->nrm[k][0], nb = e->nrm[k][1];
    const float3 q[4] = {pa, scale3(sub3(add3(scale3(pa, 2.0f), pb), scale3(na, dot3(sub3(pb, pa), na))), 1.0f / 3.0f),
                         scale3(sub3(add3(scale3(pb, 2.0f), pa), scale3(nb, dot3(sub3(pa, pb), nb))), 1.0f / 3.0f), pb};
    for (int i = 0; i < 4; i++) {
        float4 c = mul4(f4_of(q[i], 1.0f), &p->wvp);
        x[i] = (double)c.x / c.w * 0.5 * p->width, y[i] = (double)c.y / c.w * 0.5 * p->height;
    }
}

/* The cubic Bezier with control points x, y at t. */
static void bezier(const double x[4], const double y[4], double t, double *bx, double *by)
{
    const double s = 1.0 - t, w[4] = {s * s * s, 3 * s * s * t, 3 * s * t * t, t * t * t};
    *bx = w[0] * x[0] + w[1] * x[1] + w[2] * x[2] + w[3] * x[3];
    *by = w[0] * y[0] + w[1] * y[1] + w[2] * y[2] + w[3] * y[3];
}

/* The largest distance between the cubic and its polyline of L equal parameter steps, at 256 parameters. */
static double polyline_deviation(const double x[4], const double y[4], int L)
{
    double worst = 0.0;
    for (int s = 0; s <= 256; s++) {
        const double t = s / 256.0, u = t * L;
        int i = (int)floor(u);
        if (i >= L) i = L - 1;
        double x0, y0, x1, y1, bx, by;
        bezier(x, y, (double)i / L, &x0, &y0), bezier(x, y, (double)(i + 1) / L, &x1, &y1), bezier(x, y, t, &bx, &by);
        const double f = u - i;
        worst = fmax(worst, hypot(bx - (x0 + f * (x1 - x0)), by - (y0 + f * (y1 - y0))));
    }
    return worst;
}

/* An affine view of the sheet (tilted 0.7 rad about x, orthographic over 2 x 2 units). */
static tess_lod_params affine_params(tess_lod_mode mode, float target, int lo, int hi)
{
    float4x4 wv = mat_rotation_x(0.7f), proj = mat_ortho_lh(2.0f, 2.0f, -10.0f, 10.0f);
    return (tess_lod_params){.mode = mode, .target_px = target, .min_level = lo, .max_level = hi, .width = SIDE,
                             .height = SIDE, .world_view = wv, .wvp = mat_mul(&wv, &proj)};
}

/* Every edge below max_level lies within the target of its polyline; the levels are not all one value. */
static void test_deviation_within_target(void **state)
{
    (void)state;
    static const double bumps[] = {0.05, 0.2, 0.6};
    static const float targets[] = {0.1f, 0.3f, 1.0f, 4.0f};
    for (size_t b = 0; b < sizeof bumps / sizeof *bumps; b++) {
        is_mesh m;
        tess_lod_edges e;
        sheet(bumps[b], 11 + b, &m, &e);
        for (size_t t = 0; t < sizeof targets / sizeof *targets; t++) {
            tess_lod_params p = affine_params(TESS_LOD_DEVIATION, targets[t], 1, CORE_LOD_MAX_LEVEL);
            uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
            tess_lod_levels(&p, &m, &e, hist);
            int distinct = 0;
            for (int l = 0; l <= CORE_LOD_MAX_LEVEL; l++) distinct += hist[l] != 0;
            double worst = 0.0;
            for (size_t k = 0; k < e.n_edges; k++) {
                double x[4], y[4];
                edge_pixels(&p, &m, &e, k, x, y);
                if (e.level[k] < CORE_LOD_MAX_LEVEL) worst = fmax(worst, polyline_deviation(x, y, e.level[k]) / targets[t]);
            }
            fprintf(stderr, "bump %.2f target %.1f px: %d levels, worst deviation %.3f of the target\n", bumps[b],
                    (double)targets[t], distinct, worst);
            assert_true(worst <= 1.0 + 1e-4);
            if (bumps[b] >= 0.2 && targets[t] <= 1.0f) assert_true(distinct >= 3);
        }
        tess_lod_edges_free(&e);
        mesh_free(&m);
    }
}

/* A flat sheet: straight edges whose control points are evenly spaced, so every edge takes min_level. */
static void test_flat_takes_min_level(void **state)
{
    (void)state;
    is_mesh m;
    tess_lod_edges e;
    sheet(0.0, 3, &m, &e);
    tess_lod_params p = affine_params(TESS_LOD_DEVIATION, 0.01f, 3, 40);
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    tess_lod_levels(&p, &m, &e, hist);
    assert_int_equal(hist[3], e.n_edges);
    tess_lod_edges_free(&e);
    mesh_free(&m);
}

/* No target (0, negative, NaN), or an edge with a corner behind the eye: max_level. */
static void test_no_target_or_behind_takes_max(void **state)
{
    (void)state;
    is_mesh m;
    tess_lod_edges e;
    sheet(0.3, 5, &m, &e);
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    static const float none[] = {0.0f, -1.0f, NAN};
    for (size_t t = 0; t < 3; t++) {
        tess_lod_params p = affine_params(TESS_LOD_DEVIATION, none[t], 2, 9);
        tess_lod_levels(&p, &m, &e, hist);
        assert_int_equal(hist[9], e.n_edges);
    }
    float4x4 wv = mat_translation(0.0f, 0.0f, 0.2f), proj = mat_perspective_fov_lh(1.0f, 1.0f, 0.05f, 10.0f);
    tess_lod_params p = {.mode = TESS_LOD_DEVIATION, .target_px = 1000.0f, .min_level = 1, .max_level = 7,
                         .width = SIDE, .height = SIDE, .world_view = wv, .wvp = mat_mul(&wv, &proj)};
    for (size_t k = 0; k < m.n_vertices; k++) m.positions[k].z -= 1.0f;   /* the sheet straddles the eye plane */
    tess_lod_levels(&p, &m, &e, hist);
    assert_true(hist[7] > 0);   /* the edges behind */
    tess_lod_edges_free(&e);
    mesh_free(&m);
}

/* The screen mode's levels: the projected control polygon's length over the target, rounded up (tess.h), as a
 * copy of its rule computes them. */
static void test_screen_mode_unchanged(void **state)
{
    (void)state;
    is_mesh m;
    tess_lod_edges e;
    sheet(0.4, 7, &m, &e);
    tess_lod_params p = affine_params(TESS_LOD_SCREEN, 2.5f, 1, CORE_LOD_MAX_LEVEL);
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    tess_lod_levels(&p, &m, &e, hist);
    for (size_t k = 0; k < e.n_edges; k++) {
        double x[4], y[4], len = 0.0;
        edge_pixels(&p, &m, &e, k, x, y);
        for (int i = 1; i < 4; i++) len += hypot(x[i] - x[i - 1], y[i] - y[i - 1]);
        int want = (int)ceil(len / 2.5f);
        want = want < 1 ? 1 : want > CORE_LOD_MAX_LEVEL ? CORE_LOD_MAX_LEVEL : want;
        assert_int_equal(e.level[k], want);
    }
    tess_lod_edges_free(&e);
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_deviation_within_target),
        cmocka_unit_test(test_flat_takes_min_level),
        cmocka_unit_test(test_no_target_or_behind_takes_max),
        cmocka_unit_test(test_screen_mode_unchanged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
