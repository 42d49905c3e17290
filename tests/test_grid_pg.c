/* tests/test_grid_pg.c -- the primitive-generator grids of core/grid_pg.c (OpenGL 4 / D3D11 triangle
 * tessellation, seed 001 Figs. 10-11): every spacing over a range of equal and mixed levels gives valid,
 * non-overlapping triangles covering the unit triangle once, the spec's segment counts on the outer edges,
 * bitwise-mirrored (watertight) edge points, the counts the spec implies (Fig. 11's fractional_odd 4.0 among
 * them), equal spacing's edge points equal to core_grid_regular's, clamping, bad levels, and core_grid_make. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/core.h"

#include "../core/hlsl.h"
static const core_grid_kind SPACINGS[3] = {CORE_GRID_PG_EQUAL, CORE_GRID_PG_FRACTIONAL_ODD,
                                           CORE_GRID_PG_FRACTIONAL_EVEN};
static const char *const SPACING_NAME[4] = {"regular", "equal", "fractional_odd", "fractional_even"};
static const float LEVELS[] = {1.0f, 1.5f, 2.0f, 2.3f, 3.0f, 4.0f, 4.7f, 7.0f, 16.0f, 64.0f};
/* mixed levels: inner, outer[0], outer[1], outer[2] */
static const float MIXED[][4] = {
    {1.0f, 4.0f, 2.0f, 7.0f}, {1.0f, 1.0f, 1.0f, 2.0f}, {7.0f, 1.0f, 1.0f, 1.0f},  {2.3f, 16.0f, 1.5f, 64.0f},
    {64.0f, 1.0f, 2.0f, 3.0f}, {4.7f, 4.7f, 3.0f, 1.0f}, {3.0f, 64.0f, 64.0f, 64.0f}, {16.0f, 5.5f, 9.25f, 2.0f},
    {1.5f, 33.3f, 1.0f, 12.6f},
};

static float coord(float3 p, int k) { return k == 0 ? p.x : (k == 1 ? p.y : p.z); }
static uint32_t bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* Twice the signed area of (a, b, c) in the (b1, b2) plane, in double. */
static double area2(float3 a, float3 b, float3 c)
{
    return ((double)b.y - a.y) * ((double)c.z - a.z) - ((double)b.z - a.z) * ((double)c.y - a.y);
}

/* ---------------- the spec's numbers, written independently of core/grid_pg.c ---------------- */

/* Segments of an edge at a level: clamp ([1, 64]; fractional_even [2, 64]; fractional_odd [1, 63], the spec's
 * maxLevel - 1) and round up to an integer / the next odd / the next even. */
static int spec_segments(core_grid_kind k, float level)
{
    const double lo = k == CORE_GRID_PG_FRACTIONAL_EVEN ? 2.0 : 1.0;
    const double hi = k == CORE_GRID_PG_FRACTIONAL_ODD ? 63.0 : 64.0;
    const double f = level < lo ? lo : (level > hi ? hi : level);
    int n = (int)ceil(f);
    if (k == CORE_GRID_PG_FRACTIONAL_ODD && n % 2 == 0) n++;
    if (k == CORE_GRID_PG_FRACTIONAL_EVEN && n % 2 == 1) n++;
    return n;
}

/* Points and triangles the spec implies for inner n and outer n0..n2 segments: one triangle if all are 1;
 * otherwise the outer edges' points, then rings of 3(n-2r) points (r = 1..n/2; a centre point when n-2r = 0);
 * each band between rings with a and b segments on an edge has a + b triangles, plus the innermost triangle for
 * odd n.  Inner 1 with an outer above 1 is taken as 2 (the centre point; see core/grid_pg.c). */
static void spec_counts(int n, const int o[3], size_t *points, size_t *tris)
{
    if (n == 1 && o[0] == 1 && o[1] == 1 && o[2] == 1) {
        *points = 3, *tris = 1;
        return;
    }
    if (n == 1) n = 2;
    size_t p = (size_t)(o[0] + o[1] + o[2]), t = (size_t)(o[0] + o[1] + o[2]) + (size_t)(n % 2);
    for (int r = 1; r <= n / 2; r++) {
        const int m = n - 2 * r;
        p += m ? (size_t)(3 * m) : 1;
        t += (size_t)(3 * m) * (r < n / 2 ? 2 : 1); /* once as a band's inside, once as the next band's outside */
    }
    *points = p, *tris = t;
}

/* ---------------- checks on one grid ---------------- */

/* The edge k points' (b_k, b_{k+1}) pairs (third coordinate exactly 0), in traversal-independent order. */
typedef struct pair { uint32_t a, b; } pair;
static int cmp_pair(const void *x, const void *y)
{
    const pair *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    return p->b < q->b ? -1 : (p->b > q->b);
}
static size_t edge_pairs(const core_grid *g, int e, pair *out, bool swapped)
{
    size_t n = 0;
    for (size_t i = 0; i < g->n_points; i++) {
        const float3 p = g->bary[i];
        if (bits(coord(p, (e + 2) % 3)) != 0u) continue; /* +0.0f exactly */
        const uint32_t a = bits(coord(p, e)), b = bits(coord(p, (e + 1) % 3));
        out[n++] = swapped ? (pair){b, a} : (pair){a, b};
    }
    qsort(out, n, sizeof *out, cmp_pair);
    return n;
}

/* Valid points, positive triangles, total area 1/2, exact corners, no duplicate or unused point. */
static void check_basic(const core_grid *g, const char *what)
{
    if (g->n_points == 0 || g->n_triangles == 0 || !g->bary || !g->idx) fail_msg("%s: empty grid", what);
    unsigned char *used = calloc(g->n_points, 1);
    double total = 0.0;
    for (size_t t = 0; t < g->n_triangles; t++) {
        for (int v = 0; v < 3; v++) {
            if (g->idx[3 * t + v] >= g->n_points) fail_msg("%s: triangle %zu index out of range", what, t);
            used[g->idx[3 * t + v]] = 1;
        }
        const double a = 0.5 * area2(g->bary[g->idx[3 * t]], g->bary[g->idx[3 * t + 1]], g->bary[g->idx[3 * t + 2]]);
        if (!(a > 0.0)) fail_msg("%s: triangle %zu has signed area %g", what, t, a);
        total += a;
    }
    if (fabs(total - 0.5) > 1e-6) fail_msg("%s: total area %.9f", what, total);
    int corners[3] = {0, 0, 0};
    for (size_t i = 0; i < g->n_points; i++) {
        const float3 p = g->bary[i];
        if (!used[i]) fail_msg("%s: point %zu is in no triangle", what, i);
        for (int k = 0; k < 3; k++)
            if (!(coord(p, k) >= 0.0f && coord(p, k) <= 1.0f)) fail_msg("%s: point %zu outside [0,1]", what, i);
        if (fabs((double)p.x + p.y + p.z - 1.0) > 1e-6) fail_msg("%s: point %zu does not sum to 1", what, i);
        for (int k = 0; k < 3; k++)
            if (coord(p, k) == 1.0f) {
                if (bits(coord(p, (k + 1) % 3)) || bits(coord(p, (k + 2) % 3)))
                    fail_msg("%s: corner %d is not an exact unit vector", what, k);
                corners[k]++;
            }
        for (size_t j = 0; j < i; j++)
            if (bits(p.x) == bits(g->bary[j].x) && bits(p.y) == bits(g->bary[j].y) && bits(p.z) == bits(g->bary[j].z))
                fail_msg("%s: points %zu and %zu are the same", what, j, i);
    }
    free(used);
    if (corners[0] != 1 || corners[1] != 1 || corners[2] != 1)
        fail_msg("%s: corners %d %d %d", what, corners[0], corners[1], corners[2]);
}

/* Samples on a fine lattice (off the grid's lines) are each inside one triangle: covered by at least one
 * (edges included) and strictly inside at most one. */
static void check_coverage(const core_grid *g, const char *what)
{
    enum { N = 73 };
    const double tol = 1e-12;
    for (int i = 0; i < N; i++) {
        for (int j = 0; i + j < N; j++) {
            const double s1 = (i + 0.3137) / N, s2 = (j + 0.2718) / N;
            if (s1 + s2 >= 1.0) continue;
            int loose = 0, strict = 0;
            for (size_t t = 0; t < g->n_triangles; t++) {
                const uint32_t *tri = &g->idx[3 * t];
                const float3 *v[3] = {&g->bary[tri[0]], &g->bary[tri[1]], &g->bary[tri[2]]};
                double emin = INFINITY;
                for (int k = 0; k < 3; k++) {
                    const float3 *a = v[k], *b = v[(k + 1) % 3];
                    const double e = ((double)b->y - a->y) * (s2 - a->z) - ((double)b->z - a->z) * (s1 - a->y);
                    if (e < emin) emin = e;
                }
                loose += emin >= -tol;
                strict += emin > tol;
            }
            if (loose < 1 || strict > 1)
                fail_msg("%s: sample (%g, %g) in %d triangles (%d strictly)", what, s1, s2, loose, strict);
        }
    }
}

/* Edge e has the spec's number of segments, and its points mirror bit for bit (a neighbour traversing the
 * edge the other way with the same outer level computes the same floats swapped). */
static void check_edge(const core_grid *g, int e, int segments, const char *what)
{
    pair *p = malloc(g->n_points * sizeof *p), *q = malloc(g->n_points * sizeof *q);
    const size_t n = edge_pairs(g, e, p, false), m = edge_pairs(g, e, q, true);
    if (n != (size_t)segments + 1) fail_msg("%s: edge %d has %zu points, expected %d", what, e, n, segments + 1);
    assert_int_equal(n, m);
    if (memcmp(p, q, n * sizeof *p) != 0) fail_msg("%s: edge %d points are not mirror images", what, e);
    free(p);
    free(q);
}

/* All checks on core_grid_pg(spacing, inner, outer). */
static void check_case(core_grid_kind k, float inner, const float outer[3])
{
    char what[160];
    snprintf(what, sizeof what, "%s inner %g outer %g %g %g", SPACING_NAME[k], (double)inner, (double)outer[0],
             (double)outer[1], (double)outer[2]);
    core_grid g;
    if (core_grid_pg(k, inner, outer, &g) != 0) fail_msg("%s: core_grid_pg failed", what);
    check_basic(&g, what);
    check_coverage(&g, what);
    int o[3];
    for (int e = 0; e < 3; e++) check_edge(&g, e, o[e] = spec_segments(k, outer[e]), what);
    size_t np, nt;
    spec_counts(spec_segments(k, inner), o, &np, &nt);
    if (g.n_points != np || g.n_triangles != nt)
        fail_msg("%s: %zu points %zu triangles, expected %zu %zu", what, g.n_points, g.n_triangles, np, nt);
    core_grid_free(&g);
    assert_null(g.bary);
}

/* ---------------- tests ---------------- */

/* Every spacing at each level of LEVELS (inner = outer) and at the mixed levels of MIXED. */
static void test_pg_all_levels(void **state)
{
    (void)state;
    for (int s = 0; s < 3; s++) {
        for (size_t i = 0; i < sizeof LEVELS / sizeof LEVELS[0]; i++) {
            const float o[3] = {LEVELS[i], LEVELS[i], LEVELS[i]};
            check_case(SPACINGS[s], LEVELS[i], o);
        }
        for (size_t i = 0; i < sizeof MIXED / sizeof MIXED[0]; i++) check_case(SPACINGS[s], MIXED[i][0], &MIXED[i][1]);
    }
}

/* Points and triangles for each spacing at levels 1, 2, 3, 4, 4.7 (inner = outer).  Rounded levels n:
 *   equal 1 2 3 4 5, fractional_odd 1 3 3 5 5, fractional_even 2 2 4 4 6.
 * From spec_counts: n = 1 -> 3 points, 1 triangle; even n = 2k -> 3k(k+1)+1 points, 3n^2/2 triangles;
 * odd n = 2k+1 > 1 -> 3(k+1)^2 points, (3n^2-1)/2 triangles. */
static void test_pg_counts(void **state)
{
    (void)state;
    static const struct { core_grid_kind k; float level; size_t points, tris; } want[] = {
        {CORE_GRID_PG_EQUAL, 1.0f, 3, 1},          {CORE_GRID_PG_EQUAL, 2.0f, 7, 6},
        {CORE_GRID_PG_EQUAL, 3.0f, 12, 13},        {CORE_GRID_PG_EQUAL, 4.0f, 19, 24},
        {CORE_GRID_PG_EQUAL, 4.7f, 27, 37},        {CORE_GRID_PG_FRACTIONAL_ODD, 1.0f, 3, 1},
        {CORE_GRID_PG_FRACTIONAL_ODD, 2.0f, 12, 13}, {CORE_GRID_PG_FRACTIONAL_ODD, 3.0f, 12, 13},
        {CORE_GRID_PG_FRACTIONAL_ODD, 4.0f, 27, 37}, {CORE_GRID_PG_FRACTIONAL_ODD, 4.7f, 27, 37},
        {CORE_GRID_PG_FRACTIONAL_EVEN, 1.0f, 7, 6}, {CORE_GRID_PG_FRACTIONAL_EVEN, 2.0f, 7, 6},
        {CORE_GRID_PG_FRACTIONAL_EVEN, 3.0f, 19, 24}, {CORE_GRID_PG_FRACTIONAL_EVEN, 4.0f, 19, 24},
        {CORE_GRID_PG_FRACTIONAL_EVEN, 4.7f, 37, 54},
    };
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        core_grid g;
        assert_int_equal(core_grid_make(want[i].k, want[i].level, &g), 0);
        if (g.n_points != want[i].points || g.n_triangles != want[i].tris)
            fail_msg("%s %g: %zu points %zu triangles, expected %zu %zu", SPACING_NAME[want[i].k],
                     (double)want[i].level, g.n_points, g.n_triangles, want[i].points, want[i].tris);
        core_grid_free(&g);
    }
}

/* Seed 001, Fig. 11: fractional_odd with inner = outer = 4.0.  f = 4 rounds up to the odd n = 5: n-2 = 3
 * segments of length 1 and two of (f-(n-2))/2 = 0.5, total 4; placed symmetrically beside the middle segment,
 * an edge reads 1, .5, 1, .5, 1, i.e. points at 0, 1/4, 3/8, 5/8, 3/4, 1.  Rings: the outer edges (3 x 5 = 15
 * points), ring 1 with n-2 = 3 segments per edge (9 points), ring 2 with 1 segment = the innermost triangle
 * (3 points): 27 points.  Triangles: band 0 has 3 x (5 + 3) = 24, band 1 3 x (3 + 1) = 12, plus the innermost
 * triangle: 37. */
static void test_pg_fig11_fractional_odd_4(void **state)
{
    (void)state;
    core_grid g;
    assert_int_equal(core_grid_make(CORE_GRID_PG_FRACTIONAL_ODD, 4.0f, &g), 0);
    assert_int_equal(g.n_points, 27);
    assert_int_equal(g.n_triangles, 37);
    int on_edge = 0;
    for (size_t i = 0; i < g.n_points; i++)
        on_edge += g.bary[i].x == 0.0f || g.bary[i].y == 0.0f || g.bary[i].z == 0.0f;
    assert_int_equal(on_edge, 15);
    static const float want[6] = {0.0f, 0.25f, 0.375f, 0.625f, 0.75f, 1.0f};
    pair p[32];
    for (int e = 0; e < 3; e++) {
        assert_int_equal(edge_pairs(&g, e, p, false), 6);
        for (int k = 0; k < 6; k++) { /* sorted by the first coordinate: b_{e+1} = 1 - b_e runs down */
            float a, b;
            memcpy(&a, &p[k].a, sizeof a);
            memcpy(&b, &p[k].b, sizeof b);
            assert_true(a == want[k] && b == want[5 - k]);
        }
    }
    /* the segments of ring 1: 0.5, 1, 0.5 over its edge's 2 level units, and the innermost triangle's corners
     * on the medians at the perpendiculars through 3/8 of the outer edge: b = (1 - 4d/3, 2d/3, 2d/3), d = 3/8 */
    bool inner_corner = false;
    for (size_t i = 0; i < g.n_points; i++)
        inner_corner |= fabsf(g.bary[i].x - 0.5f) < 1e-6f && fabsf(g.bary[i].y - 0.25f) < 1e-6f;
    assert_true(inner_corner);
    core_grid_free(&g);
}

/* Equal spacing at an integer n: the edge points are core_grid_regular(n)'s, bit for bit. */
static void test_pg_equal_edges_match_regular(void **state)
{
    (void)state;
    static const int ns[] = {1, 2, 3, 4, 5, 7, 8, 13, 16, 31, 64};
    for (size_t c = 0; c < sizeof ns / sizeof ns[0]; c++) {
        const int n = ns[c];
        float3 *rb = malloc(core_grid_points(n) * sizeof *rb);
        uint32_t *ri = malloc(3 * core_grid_triangles(n) * sizeof *ri);
        core_grid r = {core_grid_regular(n, rb, ri), core_grid_triangles(n), rb, ri}, g;
        assert_int_equal(core_grid_make(CORE_GRID_PG_EQUAL, (float)n, &g), 0);
        pair *p = malloc(r.n_points * sizeof *p), *q = malloc(g.n_points * sizeof *q);
        for (int e = 0; e < 3; e++) {
            const size_t np = edge_pairs(&r, e, p, false), nq = edge_pairs(&g, e, q, false);
            assert_int_equal(np, (size_t)n + 1);
            assert_int_equal(nq, np);
            assert_memory_equal(p, q, np * sizeof *p);
        }
        free(p), free(q), free(rb), free(ri);
        core_grid_free(&g);
    }
}

/* Two patches sharing an edge with the same outer level but different inner and other outer levels, the
 * second traversing it the other way (its v1 -> v2 is the first's v1 -> v0): the same floats, swapped. */
static void test_pg_neighbours_watertight(void **state)
{
    (void)state;
    for (int s = 0; s < 3; s++) {
        const float a_outer[3] = {4.7f, 3.0f, 7.0f}, b_outer[3] = {1.0f, 4.7f, 2.0f};
        core_grid a, b;
        assert_int_equal(core_grid_pg(SPACINGS[s], 2.3f, a_outer, &a), 0);
        assert_int_equal(core_grid_pg(SPACINGS[s], 16.0f, b_outer, &b), 0);
        pair p[128], q[128];
        const size_t np = edge_pairs(&a, 0, p, false); /* (b0, b1) of a's edge v0 -> v1 */
        const size_t nq = edge_pairs(&b, 1, q, true);  /* (b2, b1) of b's edge v1 -> v2 */
        assert_int_equal(np, (size_t)spec_segments(SPACINGS[s], 4.7f) + 1);
        assert_int_equal(nq, np);
        assert_memory_equal(p, q, np * sizeof *p);
        core_grid_free(&a);
        core_grid_free(&b);
    }
}

/* Levels are clamped: 0.5 and -3 -> 1 (fractional_even: 2), 1000 -> 64 (fractional_odd: 63); the grids are the
 * clamped level's, bit for bit. */
static void test_pg_clamping(void **state)
{
    (void)state;
    static const struct { core_grid_kind k; float level, as; int segments; } c[] = {
        {CORE_GRID_PG_EQUAL, 0.5f, 1.0f, 1},           {CORE_GRID_PG_EQUAL, -3.0f, 1.0f, 1},
        {CORE_GRID_PG_EQUAL, 1000.0f, 64.0f, 64},      {CORE_GRID_PG_FRACTIONAL_ODD, 0.5f, 1.0f, 1},
        {CORE_GRID_PG_FRACTIONAL_ODD, 1000.0f, 63.0f, 63}, {CORE_GRID_PG_FRACTIONAL_ODD, 64.0f, 63.0f, 63},
        {CORE_GRID_PG_FRACTIONAL_EVEN, 0.5f, 2.0f, 2}, {CORE_GRID_PG_FRACTIONAL_EVEN, 1.0f, 2.0f, 2},
        {CORE_GRID_PG_FRACTIONAL_EVEN, 1.7f, 2.0f, 2}, {CORE_GRID_PG_FRACTIONAL_EVEN, 1000.0f, 64.0f, 64},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        core_grid g, h;
        assert_int_equal(core_grid_make(c[i].k, c[i].level, &g), 0);
        assert_int_equal(core_grid_make(c[i].k, c[i].as, &h), 0);
        assert_int_equal(g.n_points, h.n_points);
        assert_int_equal(g.n_triangles, h.n_triangles);
        assert_memory_equal(g.bary, h.bary, g.n_points * sizeof *g.bary);
        assert_memory_equal(g.idx, h.idx, 3 * g.n_triangles * sizeof *g.idx);
        char what[64];
        snprintf(what, sizeof what, "%s clamp %g", SPACING_NAME[c[i].k], (double)c[i].level);
        for (int e = 0; e < 3; e++) check_edge(&g, e, c[i].segments, what);
        core_grid_free(&g);
        core_grid_free(&h);
    }
    /* mixed: inner 0.5 with outer 1000 on one edge */
    const float o[3] = {1000.0f, 0.5f, 1.0f};
    core_grid g;
    assert_int_equal(core_grid_pg(CORE_GRID_PG_EQUAL, 0.5f, o, &g), 0);
    check_basic(&g, "equal inner 0.5 outer 1000 0.5 1");
    check_edge(&g, 0, 64, "equal inner 0.5 outer 1000 0.5 1");
    check_edge(&g, 1, 1, "equal inner 0.5 outer 1000 0.5 1");
    core_grid_free(&g);
}

/* NaN and infinite levels (inner or any outer), a regular kind in core_grid_pg, and a NULL outer are -1, with
 * the output left empty. */
static void test_pg_bad_levels(void **state)
{
    (void)state;
    const float bad[3] = {NAN, INFINITY, -INFINITY};
    for (int s = 0; s < 3; s++) {
        for (int b = 0; b < 3; b++) {
            for (int where = 0; where < 4; where++) {
                float inner = 3.0f, outer[3] = {3.0f, 3.0f, 3.0f};
                if (where == 0) inner = bad[b];
                else outer[where - 1] = bad[b];
                core_grid g = {99, 99, (float3 *)&g, (uint32_t *)&g};
                assert_int_equal(core_grid_pg(SPACINGS[s], inner, outer, &g), -1);
                assert_true(g.n_points == 0 && g.n_triangles == 0 && !g.bary && !g.idx);
                core_grid_free(&g);
            }
            core_grid g;
            assert_int_equal(core_grid_make(SPACINGS[s], bad[b], &g), -1);
            assert_int_equal(core_grid_make(CORE_GRID_REGULAR, bad[b], &g), -1);
        }
    }
    const float o[3] = {2.0f, 2.0f, 2.0f};
    core_grid g;
    assert_int_equal(core_grid_pg(CORE_GRID_REGULAR, 2.0f, o, &g), -1);
    assert_int_equal(core_grid_pg(CORE_GRID_PG_EQUAL, 2.0f, NULL, &g), -1);
    assert_int_equal(core_grid_pg((core_grid_kind)17, 2.0f, o, &g), -1);
    core_grid_free(NULL);
}

/* core_grid_make: regular rounds to the nearest integer >= 1 (4.4 -> core_grid_regular(4), 0.3 -> 1, 2.5 -> 3);
 * the pg kinds are core_grid_pg with inner = outer = level. */
static void test_make(void **state)
{
    (void)state;
    static const struct { float level; int L; } reg[] = {{4.4f, 4}, {0.3f, 1}, {2.5f, 3}, {7.0f, 7}, {-2.0f, 1}};
    for (size_t i = 0; i < sizeof reg / sizeof reg[0]; i++) {
        const int L = reg[i].L;
        float3 *rb = malloc(core_grid_points(L) * sizeof *rb);
        uint32_t *ri = malloc(3 * core_grid_triangles(L) * sizeof *ri);
        assert_int_equal(core_grid_regular(L, rb, ri), core_grid_points(L));
        core_grid g;
        assert_int_equal(core_grid_make(CORE_GRID_REGULAR, reg[i].level, &g), 0);
        assert_int_equal(g.n_points, core_grid_points(L));
        assert_int_equal(g.n_triangles, core_grid_triangles(L));
        assert_memory_equal(g.bary, rb, g.n_points * sizeof *rb);
        assert_memory_equal(g.idx, ri, 3 * g.n_triangles * sizeof *ri);
        core_grid_free(&g);
        free(rb), free(ri);
    }
    for (int s = 0; s < 3; s++) {
        for (size_t i = 0; i < sizeof LEVELS / sizeof LEVELS[0]; i++) {
            const float l = LEVELS[i], o[3] = {l, l, l};
            core_grid g, h;
            assert_int_equal(core_grid_make(SPACINGS[s], l, &g), 0);
            assert_int_equal(core_grid_pg(SPACINGS[s], l, o, &h), 0);
            assert_int_equal(g.n_points, h.n_points);
            assert_int_equal(g.n_triangles, h.n_triangles);
            assert_memory_equal(g.bary, h.bary, g.n_points * sizeof *g.bary);
            assert_memory_equal(g.idx, h.idx, 3 * g.n_triangles * sizeof *g.idx);
            core_grid_free(&g);
            core_grid_free(&h);
        }
    }
}

/* Fractional levels move points continuously: a small change of level moves every point a little (same
 * counts), while equal spacing keeps the points until the rounded level changes. */
static void test_pg_fractional_continuity(void **state)
{
    (void)state;
    static const float pairs[][2] = {{4.2f, 4.21f}, {2.6f, 2.61f}, {9.5f, 9.51f}, {29.5f, 29.51f}};
    for (int s = 1; s < 3; s++) {
        for (size_t i = 0; i < sizeof pairs / sizeof pairs[0]; i++) {
            core_grid g, h;
            assert_int_equal(core_grid_make(SPACINGS[s], pairs[i][0], &g), 0);
            assert_int_equal(core_grid_make(SPACINGS[s], pairs[i][1], &h), 0);
            assert_int_equal(g.n_points, h.n_points);
            assert_memory_equal(g.idx, h.idx, 3 * g.n_triangles * sizeof *g.idx);
            for (size_t p = 0; p < g.n_points; p++) {
                const float3 d = sub3(g.bary[p], h.bary[p]);
                assert_true(fabsf(d.x) < 0.01f && fabsf(d.y) < 0.01f && fabsf(d.z) < 0.01f);
            }
            core_grid_free(&g);
            core_grid_free(&h);
        }
    }
}

/* The smallest angle of the grid's triangles, in degrees, drawn on an equilateral triangle (the spec's picture). */
static double min_angle(const core_grid *g)
{
    double best = 180.0;
    for (size_t t = 0; t < g->n_triangles; t++) {
        double P[3][2];
        for (int v = 0; v < 3; v++) {
            const float3 b = g->bary[g->idx[3 * t + v]];
            P[v][0] = b.y + 0.5 * b.z, P[v][1] = 0.8660254037844386 * b.z;
        }
        for (int v = 0; v < 3; v++) {
            const double ax = P[(v + 1) % 3][0] - P[v][0], ay = P[(v + 1) % 3][1] - P[v][1];
            const double bx = P[(v + 2) % 3][0] - P[v][0], by = P[(v + 2) % 3][1] - P[v][1];
            const double a = atan2(fabs(ax * by - ay * bx), ax * bx + ay * by) * (180.0 / 3.14159265358979323846);
            if (a < best) best = a;
        }
    }
    return best;
}

/* Shape: with equal spacing and inner = outer, each band is zipped so that every triangle pairs a segment with
 * the nearest point of the other ring -- no angle below 30 degrees on the equilateral triangle (a zipper that
 * advanced the wrong side would still cover the triangle, with slivers). */
static void test_pg_equal_shape(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof LEVELS / sizeof LEVELS[0]; i++) {
        core_grid g;
        assert_int_equal(core_grid_make(CORE_GRID_PG_EQUAL, LEVELS[i], &g), 0);
        const double a = min_angle(&g);
        if (a < 30.0 - 1e-3) fail_msg("equal %g: smallest angle %.3f degrees", (double)LEVELS[i], a);
        core_grid_free(&g);
    }
}

/* A sweep of levels 0.5..64.5 in steps of 1/8, plus each integer +- 2^-12, +- 2^-9 and its next float up
 * (beside core/grid_pg.c's fold of short segments under 2^-11), as inner = outer and against other outer
 * levels: every triangle positive, total area 1/2, points in [0,1] summing to 1, edges mirrored bit for bit. */
static void test_pg_level_sweep(void **state)
{
    (void)state;
    for (int s = 0; s < 3; s++) {
        for (int step = 4; step <= 8 * 64 + 4; step++) {
            float ls[6] = {step / 8.0f, 0, 0, 0, 0, 0};
            int nl = 1;
            if (step % 8 == 0) {
                for (int d = 0; d < 4; d++)
                    ls[nl++] = step / 8.0f + (d % 2 ? -1.0f : 1.0f) * ldexpf(1.0f, d < 2 ? -12 : -9);
                ls[nl++] = nextafterf(step / 8.0f, INFINITY);
            }
            for (int i = 0; i < nl; i++) {
                const float l = ls[i];
                const float cases[3][4] = {{l, l, l, l}, {l, 2.5f, l, 1.0f}, {1.0f + (float)(step % 5), l, 9.0f, l}};
                for (int c = 0; c < 3; c++) {
                    char what[96];
                    snprintf(what, sizeof what, "%s sweep %.9g case %d", SPACING_NAME[SPACINGS[s]], (double)l, c);
                    core_grid g;
                    if (core_grid_pg(SPACINGS[s], cases[c][0], &cases[c][1], &g) != 0) fail_msg("%s: failed", what);
                    double total = 0.0;
                    for (size_t t = 0; t < g.n_triangles; t++) {
                        const uint32_t *tri = &g.idx[3 * t];
                        const double a = 0.5 * area2(g.bary[tri[0]], g.bary[tri[1]], g.bary[tri[2]]);
                        if (!(a > 0.0)) fail_msg("%s: triangle %zu has area %g", what, t, a);
                        total += a;
                    }
                    if (fabs(total - 0.5) > 1e-6) fail_msg("%s: total area %.9f", what, total);
                    for (size_t p = 0; p < g.n_points; p++) {
                        const float3 q = g.bary[p];
                        if (!(q.x >= 0.0f && q.y >= 0.0f && q.z >= 0.0f && q.x <= 1.0f && q.y <= 1.0f && q.z <= 1.0f) ||
                            fabs((double)q.x + q.y + q.z - 1.0) > 1e-6)
                            fail_msg("%s: point %zu is not barycentric", what, p);
                    }
                    pair *pp = malloc(g.n_points * sizeof *pp), *qq = malloc(g.n_points * sizeof *qq);
                    for (int e = 0; e < 3; e++) {
                        const size_t np = edge_pairs(&g, e, pp, false), nq = edge_pairs(&g, e, qq, true);
                        if (np != nq || np < 2 || memcmp(pp, qq, np * sizeof *pp) != 0)
                            fail_msg("%s: edge %d not mirrored", what, e);
                    }
                    free(pp), free(qq);
                    core_grid_free(&g);
                }
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pg_all_levels),
        cmocka_unit_test(test_pg_counts),
        cmocka_unit_test(test_pg_fig11_fractional_odd_4),
        cmocka_unit_test(test_pg_equal_edges_match_regular),
        cmocka_unit_test(test_pg_neighbours_watertight),
        cmocka_unit_test(test_pg_clamping),
        cmocka_unit_test(test_pg_bad_levels),
        cmocka_unit_test(test_make),
        cmocka_unit_test(test_pg_fractional_continuity),
        cmocka_unit_test(test_pg_equal_shape),
        cmocka_unit_test(test_pg_level_sweep),
    };
    return cmocka_run_group_tests_name("grid_pg", tests, NULL, NULL);
}
