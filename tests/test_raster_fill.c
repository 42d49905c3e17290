/* tests/test_raster_fill.c -- the fill rule: tilings of the screen at several rotations and sub-pixel offsets
 * drawn with additive blending cover every sample exactly once, and a brute-force double-precision coverage
 * oracle (same 1/256 snapping, same top-left rule, written here independently) agrees sample for sample with the
 * rasterizer on thousands of random triangles, at 1 and 4 samples. */
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

enum { W = 128, H = 128 };

/* Default states for a full-target viewport: no culling, additive blending of colour, no depth. */
static rs_state add_state(int w, int h) { return test_rs_additive(w, h); }

/* A vertex at screen position (X, Y) in pixels (w = 1) whose colour adds 1 to the red channel. */
static rs_vertex screen_vertex(double X, double Y, int w, int h)
{
    rs_vertex v;
    memset(&v, 0, sizeof v);
    v.pos = (rs_vec4){ (float)(X / (w * 0.5) - 1.0), (float)(1.0 - Y / (h * 0.5)), 0.5f, 1.0f };
    v.attr[RS_ATTR_COLOR0] = (rs_vec4){ 1.0f / 255.0f, 0.0f, 0.0f, 0.0f };
    return v;
}

/* Red channel (the count) of sample s of pixel (x, y). */
static int count_at(const rs_target *rt, int x, int y, int s)
{
    return (int)(rt->color[((size_t)y * rt->width + x) * rt->samples + s] & 0xffu);
}

/* Draw triangles (3 vertices each) additively on a cleared target; returns rs_draw's result. */
static int draw_add(rs_context *rs, rs_target *rt, const rs_vertex *v, size_t n_tris)
{
    rs_state st = add_state(rt->width, rt->height);
    rs_target_clear(rt, 3, 0, 1.0f);
    rs_stats stats;
    return rs_draw(rs, &st, rt, RS_PRIM_TRIANGLES, v, n_tris * 3, NULL, n_tris, &stats);
}

/* Number of samples whose count differs from 1. */
static long not_once(const rs_target *rt)
{
    long bad = 0;
    for (int y = 0; y < rt->height; y++)
        for (int x = 0; x < rt->width; x++)
            for (int s = 0; s < rt->samples; s++) bad += count_at(rt, x, y, s) != 1;
    return bad;
}

/* Small deterministic generator (xorshift64*), uniform in [0, 1). */
static double rnd(uint64_t *s)
{
    *s ^= *s >> 12; *s ^= *s << 25; *s ^= *s >> 27;
    return (double)((*s * 0x2545F4914F6CDD1DULL) >> 11) * (1.0 / 9007199254740992.0);
}

/* A jittered, rotated grid of quads (two triangles each) covering the screen and beyond: each vertex is
 * shared exactly, so the tiling must cover every sample once. */
static void grid_tiling(int samples)
{
    const double angles[] = { 0.0, 7.3, 15.0, 30.0, 45.0, 60.0, 90.0, 123.4 };
    const double offs[][2] = { { 0, 0 }, { 0.5, 0.5 }, { 0.25, -0.75 }, { 1.0 / 256, 3.0 / 256 }, { 0.37, 0.61 } };
    const double spacing[] = { 8.0, 5.25, 13.0 };
    enum { N = 24 };
    rs_context *rs = rs_create(2);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, samples), RS_OK);
    static rs_vertex grid[(2 * N + 1) * (2 * N + 1)];
    static rs_vertex tris[(2 * N) * (2 * N) * 6];
    uint64_t seed = 12345;
    for (size_t a = 0; a < sizeof angles / sizeof *angles; a++)
        for (size_t o = 0; o < sizeof offs / sizeof *offs; o++)
            for (size_t sp = 0; sp < sizeof spacing / sizeof *spacing; sp++) {
                double th = angles[a] * 3.14159265358979 / 180.0, c = cos(th), s = sin(th), d = spacing[sp];
                bool jitter = (a + o + sp) % 2 == 1;
                for (int i = 0; i <= 2 * N; i++)
                    for (int k = 0; k <= 2 * N; k++) {
                        double u = (i - N) * d + (jitter ? (rnd(&seed) - 0.5) * d * 0.4 : 0);
                        double v = (k - N) * d + (jitter ? (rnd(&seed) - 0.5) * d * 0.4 : 0);
                        double X = 64 + offs[o][0] + c * u - s * v, Y = 64 + offs[o][1] + s * u + c * v;
                        if (o % 2 == 0) { /* on the snapping grid for some offsets, arbitrary for the others */
                            X = round(X * 256) / 256;
                            Y = round(Y * 256) / 256;
                        }
                        grid[i * (2 * N + 1) + k] = screen_vertex(X, Y, W, H);
                    }
                size_t n = 0;
                for (int i = 0; i < 2 * N; i++)
                    for (int k = 0; k < 2 * N; k++) {
                        const rs_vertex *p00 = &grid[i * (2 * N + 1) + k], *p10 = &grid[(i + 1) * (2 * N + 1) + k];
                        const rs_vertex *p01 = &grid[i * (2 * N + 1) + k + 1], *p11 = &grid[(i + 1) * (2 * N + 1) + k + 1];
                        bool flip = (i + k) % 3 == 0; /* both diagonals occur */
                        if (!flip) {
                            tris[n++] = *p00; tris[n++] = *p10; tris[n++] = *p11;
                            tris[n++] = *p00; tris[n++] = *p11; tris[n++] = *p01;
                        } else {
                            tris[n++] = *p00; tris[n++] = *p10; tris[n++] = *p01;
                            tris[n++] = *p10; tris[n++] = *p11; tris[n++] = *p01;
                        }
                    }
                assert_int_equal(draw_add(rs, &rt, tris, n / 3), RS_OK);
                long bad = not_once(&rt);
                if (bad) fprintf(stderr, "grid angle %g offset %zu spacing %g samples %d: %ld bad samples\n",
                                 angles[a], o, d, samples, bad);
                assert_int_equal(bad, 0);
            }
    rs_target_free(&rt);
    rs_destroy(rs);
}

static void test_grid_tiling_1x(void **state) { (void)state; grid_tiling(1); }
static void test_grid_tiling_4x(void **state) { (void)state; grid_tiling(4); }

/* Fans around a centre (on a pixel centre, on a sample, arbitrary) with spokes reaching far off screen (also
 * beyond the guard band, so the shared spokes are clipped by it): every
 * sample is covered once, including the centre where all triangles meet. */
static void test_fans(void **state)
{
    (void)state;
    const double centres[][2] = { { 64, 64 }, { 64.5, 63.25 }, { 10 - 2.0 / 16, 20 - 6.0 / 16 }, { 0, 0 }, { 100.3, 7.7 } };
    const int spokes[] = { 3, 4, 7, 8, 16, 33, 64 };
    rs_context *rs = rs_create(0);
    for (int samples = 1; samples <= 4; samples += 3) {
        rs_target rt;
        assert_int_equal(rs_target_init(&rt, W, H, samples), RS_OK);
        for (size_t c = 0; c < sizeof centres / sizeof *centres; c++)
            for (size_t k = 0; k < sizeof spokes / sizeof *spokes; k++) {
                int n = spokes[k];
                double R = k % 2 ? 1000.0 : 3.0e6; /* within the guard band, or clipped by it */
                rs_vertex v[64 * 3];
                for (int i = 0; i < n; i++) {
                    double a0 = 2 * 3.14159265358979 * i / n + 0.1 * (double)c;
                    double a1 = 2 * 3.14159265358979 * (i + 1) / n + 0.1 * (double)c;
                    v[3 * i] = screen_vertex(centres[c][0], centres[c][1], W, H);
                    v[3 * i + 1] = screen_vertex(centres[c][0] + R * cos(a0), centres[c][1] + R * sin(a0), W, H);
                    v[3 * i + 2] = screen_vertex(centres[c][0] + R * cos(a1), centres[c][1] + R * sin(a1), W, H);
                }
                /* the spoke ends must be bitwise shared: copy the previous triangle's end */
                for (int i = 1; i < n; i++) v[3 * i + 1] = v[3 * (i - 1) + 2];
                v[3 * (n - 1) + 2] = v[1];
                assert_int_equal(draw_add(rs, &rt, v, (size_t)n), RS_OK);
                long bad = not_once(&rt);
                if (bad) fprintf(stderr, "fan centre %zu spokes %d samples %d: %ld bad\n", c, n, samples, bad);
                assert_int_equal(bad, 0);
            }
        rs_target_free(&rt);
    }
    rs_destroy(rs);
}

/* ---- the oracle ---- */

/* Snapped fixed-point coordinate (1/256 px) of screen coordinate X, as the rasterizer snaps it: the test
 * only uses coordinates already on the 1/256 grid, so this is exact. */
static double snap(double X) { return nearbyint(X * 256.0); }

/* Is sample (px, py) (1/256 px units) inside the snapped triangle t[3][2] by the top-left rule? */
static bool oracle_inside(const double t[3][2], double px, double py)
{
    double area = (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[1][1] - t[0][1]) * (t[2][0] - t[0][0]);
    if (area == 0) return false;
    int o1 = area > 0 ? 1 : 2, o2 = area > 0 ? 2 : 1; /* make the order clockwise on screen (y down) */
    const double *v[3] = { t[0], t[o1], t[o2] };
    for (int e = 0; e < 3; e++) {
        const double *a = v[e], *b = v[(e + 1) % 3];
        double dx = b[0] - a[0], dy = b[1] - a[1];
        double E = dx * (py - a[1]) - dy * (px - a[0]); /* > 0 inside */
        bool top = dy == 0 && dx > 0, left = dy < 0;
        if (E < 0 || (E == 0 && !(top || left))) return false;
    }
    return true;
}

/* A random screen coordinate in [lo, hi], quantised to 1/256, 1/16, 1/2 or 1 px. */
static double rcoord(uint64_t *s, double lo, double hi)
{
    static const double q[] = { 256, 16, 2, 1, 256, 256 };
    double g = q[(int)(rnd(s) * 6)];
    return round((lo + rnd(s) * (hi - lo)) * g) / g;
}

static void oracle_run(int samples)
{
    enum { OW = 64, OH = 64, BATCH = 100, BATCHES = 40 };
    static const double so[4][2] = { { -2, -6 }, { 6, -2 }, { -6, 2 }, { 2, 6 } };
    rs_context *rs = rs_create(2);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, OW, OH, samples), RS_OK);
    static int expect[OW * OH * 4];
    rs_vertex v[BATCH * 3];
    uint64_t seed = 0x9E3779B97F4A7C15ULL;
    long compared = 0, covered = 0;
    for (int b = 0; b < BATCHES; b++) {
        memset(expect, 0, sizeof expect);
        for (int i = 0; i < BATCH; i++) {
            double t[3][2];
            int kind = (int)(rnd(&seed) * 4);
            double cx = rcoord(&seed, -8, OW + 8), cy = rcoord(&seed, -8, OH + 8);
            double r = kind == 0 ? 3 : (kind == 1 ? 12 : (kind == 2 ? 40 : 200));
            for (int k = 0; k < 3; k++) {
                t[k][0] = rcoord(&seed, cx - r, cx + r);
                t[k][1] = rcoord(&seed, cy - r, cy + r);
                v[3 * i + k] = screen_vertex(t[k][0], t[k][1], OW, OH);
                t[k][0] = snap(t[k][0]);
                t[k][1] = snap(t[k][1]);
            }
            if (i % 17 == 0) { t[2][0] = t[1][0]; t[2][1] = t[1][1]; v[3 * i + 2] = v[3 * i + 1]; } /* degenerate */
            for (int y = 0; y < OH; y++)
                for (int x = 0; x < OW; x++)
                    for (int s = 0; s < samples; s++) {
                        double px = x * 256.0 + (samples == 4 ? so[s][0] * 16 : 0);
                        double py = y * 256.0 + (samples == 4 ? so[s][1] * 16 : 0);
                        expect[(y * OW + x) * samples + s] += oracle_inside((const double(*)[2])t, px, py);
                    }
        }
        assert_int_equal(draw_add(rs, &rt, v, BATCH), RS_OK);
        for (int k = 0; k < OW * OH * samples; k++) {
            int got = (int)(rt.color[k] & 0xffu);
            if (got != expect[k])
                fprintf(stderr, "batch %d sample %d (pixel %d,%d): got %d expected %d\n", b, k, (k / samples) % OW,
                        (k / samples) / OW, got, expect[k]);
            assert_int_equal(got, expect[k]);
            compared++;
            covered += expect[k];
        }
    }
    assert_true(covered > compared / 4); /* the batches do cover a lot */
    rs_target_free(&rt);
    rs_destroy(rs);
}

static void test_oracle_1x(void **state) { (void)state; oracle_run(1); }
static void test_oracle_4x(void **state) { (void)state; oracle_run(4); }

/* Two triangles sharing an edge exactly through sample positions: horizontal, vertical and diagonal edges
 * through pixel centres give each sample to exactly one side. */
static void test_edges_through_centres(void **state)
{
    (void)state;
    rs_context *rs = rs_create(1);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, 32, 32, 1), RS_OK);
    const double quads[][4][2] = {
        { { 4, 4 }, { 20, 4 }, { 20, 20 }, { 4, 20 } },          /* axis-aligned, edges on pixel centres */
        { { 16, 2 }, { 30, 16 }, { 16, 30 }, { 2, 16 } },        /* diamond, 45-degree edges through centres */
        { { 3, 3 }, { 29, 5 }, { 27, 29 }, { 5, 27 } },
    };
    for (size_t q = 0; q < 3; q++) {
        const double(*p)[2] = quads[q];
        rs_vertex v[6] = { screen_vertex(p[0][0], p[0][1], 32, 32), screen_vertex(p[1][0], p[1][1], 32, 32),
                           screen_vertex(p[2][0], p[2][1], 32, 32), screen_vertex(p[0][0], p[0][1], 32, 32),
                           screen_vertex(p[2][0], p[2][1], 32, 32), screen_vertex(p[3][0], p[3][1], 32, 32) };
        assert_int_equal(draw_add(rs, &rt, v, 2), RS_OK);
        long n = 0;
        for (int y = 0; y < 32; y++)
            for (int x = 0; x < 32; x++) {
                assert_true(count_at(&rt, x, y, 0) <= 1);
                n += count_at(&rt, x, y, 0);
            }
        if (q == 0) {
            assert_int_equal(n, 16 * 16); /* [4, 20) x [4, 20): top and left edges in, bottom and right out */
            assert_int_equal(count_at(&rt, 4, 4, 0), 1);
            assert_int_equal(count_at(&rt, 20, 10, 0), 0);
            assert_int_equal(count_at(&rt, 10, 20, 0), 0);
        }
        if (q == 1) assert_int_equal(n, 14 * 14 * 2); /* a diamond of half-diagonal 14 holds 2*14*14 centres */
    }
    rs_target_free(&rt);
    rs_destroy(rs);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_edges_through_centres),
        cmocka_unit_test(test_grid_tiling_1x),
        cmocka_unit_test(test_grid_tiling_4x),
        cmocka_unit_test(test_fans),
        cmocka_unit_test(test_oracle_1x),
        cmocka_unit_test(test_oracle_4x),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
