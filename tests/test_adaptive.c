/* tests/test_adaptive.c -- the refinement patterns of core/grid_adaptive.c (per-edge levels): every pattern of
 * every sorted level triple is a valid tiling of the triangle (no fold, no zero area, areas summing to the
 * triangle, interior edges used twice in opposite directions, each edge cut into exactly its level's segments at
 * the points k / l), uniform levels give the regular grid, the pattern drawn as the regular grid of moved points
 * (core_grid_adaptive_points) is the pattern, core_lod_order's renumbering, and the bounded cache. */
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

/* Twice the signed area of (a, b, c) in the (b1, b2) plane, in double. */
static double area2(float3 a, float3 b, float3 c)
{
    return ((double)b.y - a.y) * ((double)c.z - a.z) - ((double)c.y - a.y) * ((double)b.z - a.z);
}

/* The edge (0, 1, 2) point p lies on, or -1 (a corner counts for none: it lies on two). */
static int on_edge(float3 p)
{
    int zeros = (p.x == 0.0f) + (p.y == 0.0f) + (p.z == 0.0f);
    if (zeros != 1) return -1;
    return p.z == 0.0f ? 0 : p.x == 0.0f ? 1 : 2;
}

/* Whether p is edge e's point k of l, with the weights computed from their own ends. */
static bool is_edge_point(float3 p, int e, int k, int l)
{
    const float *c = &p.x;
    return c[e] == (float)(l - k) / (float)l && c[(e + 1) % 3] == (float)k / (float)l && c[(e + 2) % 3] == 0.0f;
}

/* Directed edge (a, b) as a 64-bit key. */
static uint64_t dkey(uint32_t a, uint32_t b) { return (uint64_t)a << 32 | b; }
static int cmp_u64(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

/* Whether the sorted array holds v. */
static bool has(const uint64_t *s, size_t n, uint64_t v) { return bsearch(&v, s, n, sizeof v, cmp_u64) != NULL; }

/* All tiling checks on the pattern g of edge levels l; fails the test with the levels named. */
static void check_tiling(const core_grid *g, const int l[3])
{
    char what[64];
    snprintf(what, sizeof what, "pattern %d/%d/%d", l[0], l[1], l[2]);
    double sum = 0.0;
    uint64_t *de = malloc(3 * g->n_triangles * sizeof *de);
    assert_non_null(de);
    for (size_t t = 0; t < g->n_triangles; t++) {
        const uint32_t *q = &g->idx[3 * t];
        for (int c = 0; c < 3; c++) if (q[c] >= g->n_points) fail_msg("%s: index out of range", what);
        double a = area2(g->bary[q[0]], g->bary[q[1]], g->bary[q[2]]);
        if (!(a > 0.0)) fail_msg("%s: triangle %zu has signed area %g (fold or degenerate)", what, t, a);
        sum += a;
        for (int c = 0; c < 3; c++) de[3 * t + c] = dkey(q[c], q[(c + 1) % 3]);
    }
    /* the border points are floats (1/3 is not exact): the sum is 1 up to their rounding */
    if (fabs(sum - 1.0) > 1e-6) fail_msg("%s: areas sum to %.12g of the triangle", what, sum);
    const size_t nd = 3 * g->n_triangles;
    qsort(de, nd, sizeof *de, cmp_u64);
    size_t boundary[3] = {0, 0, 0};
    for (size_t k = 0; k < nd; k++) {
        if (k && de[k] == de[k - 1]) fail_msg("%s: a directed edge is used twice (fold)", what);
        uint32_t a = (uint32_t)(de[k] >> 32), b = (uint32_t)de[k];
        if (has(de, nd, dkey(b, a))) continue; /* interior: used once each way */
        /* a boundary edge: both ends on one edge of the triangle (corners on either of theirs) */
        float3 pa = g->bary[a], pb = g->bary[b];
        int e = on_edge(pa) >= 0 ? on_edge(pa) : on_edge(pb);
        if (e < 0) { /* corner to corner: the edge is one segment */
            e = (pa.x == 1.0f && pb.y == 1.0f) ? 0 : (pa.y == 1.0f && pb.z == 1.0f) ? 1 : 2;
        }
        const float *ca = &pa.x, *cb = &pb.x;
        if (ca[(e + 2) % 3] != 0.0f || cb[(e + 2) % 3] != 0.0f)
            fail_msg("%s: edge %u-%u used once but not on the triangle's border", what, a, b);
        boundary[e]++;
    }
    for (int e = 0; e < 3; e++) {
        if (boundary[e] != (size_t)l[e]) fail_msg("%s: edge %d has %zu segments", what, e, boundary[e]);
        for (int k = 0; k <= l[e]; k++) { /* each of the edge's points is there, with its exact floats */
            bool found = false;
            for (size_t p = 0; p < g->n_points && !found; p++) found = is_edge_point(g->bary[p], e, k, l[e]);
            if (!found) fail_msg("%s: edge %d lacks point %d of %d", what, e, k, l[e]);
        }
    }
    for (size_t p = 0; p < g->n_points; p++) { /* no other point on an edge */
        int e = on_edge(g->bary[p]);
        if (e < 0) continue;
        bool ok = false;
        for (int k = 1; k < l[e] && !ok; k++) ok = is_edge_point(g->bary[p], e, k, l[e]);
        if (!ok) fail_msg("%s: point %zu on edge %d is not one of its %d points", what, p, e, l[e]);
    }
    free(de);
}

/* fn on every sorted triple whose largest level is at most `all`, and on those with a larger largest level whose
 * others come from a spread (1, multiples of 7 or equal to the next, and 1, multiples of 5 or equal to the
 * largest); returns how many. */
static long each_sorted_triple(int all, void (*fn)(const int l[3]))
{
    long n = 0;
    for (int c = 1; c <= CORE_LOD_MAX_LEVEL; c++)
        for (int b = 1; b <= c; b++)
            for (int a = 1; a <= b; a++) {
                if (c > all && !((a == 1 || a % 7 == 0 || a == b) && (b == 1 || b % 5 == 0 || b == c))) continue;
                fn((const int[3]){a, b, c}), n++;
            }
    return n;
}

/* The pattern of levels l tiles its triangle (check_tiling). */
static void check_pattern_tiles(const int l[3])
{
    core_grid g;
    assert_int_equal(core_grid_adaptive(l, &g), 0);
    check_tiling(&g, l);
    core_grid_free(&g);
}

/* Every sorted triple up to 24, and every triple with its largest level in 25..64 and the others from a spread. */
static void test_patterns_tile(void **state)
{
    const long n = each_sorted_triple(24, check_pattern_tiles);
    print_message("%ld sorted patterns tile the triangle\n", n);
    assert_true(n > 2600);
}

/* Unsorted levels (as a caller without the cache may ask) tile too: every order of a few triples. */
static void test_unsorted_patterns_tile(void **state)
{
    static const int triples[][3] = {{1, 2, 3}, {2, 7, 64}, {5, 5, 9}, {1, 1, 64}, {13, 40, 33}};
    for (size_t t = 0; t < sizeof triples / sizeof triples[0]; t++)
        for (int r = 0; r < 6; r++) {
            static const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
            int l[3] = {triples[t][orders[r][0]], triples[t][orders[r][1]], triples[t][orders[r][2]]};
            core_grid g;
            assert_int_equal(core_grid_adaptive(l, &g), 0);
            check_tiling(&g, l);
            core_grid_free(&g);
        }
}

/* Uniform levels give core_grid_regular's points and triangles exactly. */
static void test_uniform_is_regular(void **state)
{
    for (int L = 1; L <= CORE_LOD_MAX_LEVEL; L++) {
        core_grid a, r;
        assert_int_equal(core_grid_adaptive((const int[3]){L, L, L}, &a), 0);
        assert_int_equal(core_grid_make(CORE_GRID_REGULAR, (float)L, &r), 0);
        assert_int_equal(a.n_points, r.n_points);
        assert_int_equal(a.n_triangles, r.n_triangles);
        assert_memory_equal(a.bary, r.bary, a.n_points * sizeof(float3));
        assert_memory_equal(a.idx, r.idx, 3 * a.n_triangles * sizeof(uint32_t));
        core_grid_free(&a), core_grid_free(&r);
    }
}

/* The pattern as the regular grid of moved points (core_grid_adaptive_points): over every triple of the tiling
 * test's set and every order of a few, the regular level-M list over the moved points gives, once the triangles
 * with two bit-equal points are left out, exactly the pattern's triangles in the pattern's order, point for point
 * (bit for bit); and every moved point is a pattern point. */
static void check_moved_points(const int l[3])
{
    core_grid g, r;
    assert_int_equal(core_grid_adaptive(l, &g), 0);
    const int M = l[0] > l[1] ? (l[0] > l[2] ? l[0] : l[2]) : (l[1] > l[2] ? l[1] : l[2]);
    assert_int_equal(core_grid_make(CORE_GRID_REGULAR, (float)M, &r), 0);
    float3 *p = malloc(r.n_points * sizeof *p);
    assert_non_null(p);
    assert_int_equal(core_grid_adaptive_points(l, p), M);
    for (size_t k = 0; k < r.n_points; k++) {
        bool found = false;
        for (size_t q = 0; q < g.n_points && !found; q++) found = memcmp(&p[k], &g.bary[q], sizeof p[k]) == 0;
        assert_true(found);
    }
    size_t t = 0;
    for (size_t q = 0; q < r.n_triangles; q++) {
        const float3 *a = &p[r.idx[3 * q]], *b = &p[r.idx[3 * q + 1]], *c = &p[r.idx[3 * q + 2]];
        if (!memcmp(a, b, sizeof *a) || !memcmp(b, c, sizeof *b) || !memcmp(c, a, sizeof *c)) continue;
        assert_true(t < g.n_triangles);
        assert_memory_equal(a, &g.bary[g.idx[3 * t]], sizeof *a);
        assert_memory_equal(b, &g.bary[g.idx[3 * t + 1]], sizeof *b);
        assert_memory_equal(c, &g.bary[g.idx[3 * t + 2]], sizeof *c);
        t++;
    }
    assert_int_equal(t, g.n_triangles);
    free(p);
    core_grid_free(&g), core_grid_free(&r);
}

static void test_pattern_as_regular_grid(void **state)
{
    long n = each_sorted_triple(12, check_moved_points);
    static const int unsorted[][3] = {{3, 2, 1}, {64, 2, 7}, {9, 5, 5}, {40, 13, 33}};
    for (size_t k = 0; k < sizeof unsorted / sizeof *unsorted; k++) check_moved_points(unsorted[k]), n++;
    float3 pt[3];
    assert_int_equal(core_grid_adaptive_points((const int[3]){1, 0, 1}, pt), -1);
    assert_int_equal(core_grid_adaptive_points((const int[3]){1, 65, 1}, pt), -1);
    assert_int_equal(core_grid_adaptive_points(NULL, pt), -1);
    assert_int_equal(core_grid_adaptive_points((const int[3]){1, 1, 1}, NULL), -1);
    print_message("%ld patterns drawn as the regular grid of moved points\n", n);
}

/* Bad levels are refused. */
static void test_bad_levels(void **state)
{
    core_grid g;
    assert_int_equal(core_grid_adaptive((const int[3]){0, 1, 1}, &g), -1);
    assert_int_equal(core_grid_adaptive((const int[3]){1, 65, 1}, &g), -1);
    assert_int_equal(core_grid_adaptive((const int[3]){1, 1, -3}, &g), -1);
    assert_int_equal(core_grid_adaptive(NULL, &g), -1);
    assert_int_equal(core_grid_adaptive((const int[3]){1, 1, 1}, NULL), -1);
}

/* core_lod_order: for every order of levels the renumbered triangle's edge k has level sorted[k], sorted is
 * ascending, and the parity is that of perm (counted by inversions). */
static void test_lod_order(void **state)
{
    const int vals[3] = {2, 5, 9};
    int seen_odd = 0, seen_even = 0;
    for (int x = 0; x < 27; x++) {
        int e[3] = {vals[x % 3], vals[x / 3 % 3], vals[x / 9]};
        int sorted[3], perm[3];
        bool odd = core_lod_order(e, sorted, perm);
        assert_true(sorted[0] <= sorted[1] && sorted[1] <= sorted[2]);
        for (int k = 0; k < 3; k++) {
            int a = perm[k], b = perm[(k + 1) % 3];
            int old_edge = (b == (a + 1) % 3) ? a : b; /* the triangle's edge joining a and b */
            assert_int_equal(e[old_edge], sorted[k]);
        }
        int inv = (perm[0] > perm[1]) + (perm[0] > perm[2]) + (perm[1] > perm[2]);
        assert_int_equal(odd, inv % 2 == 1);
        seen_odd += odd, seen_even += !odd;
    }
    assert_true(seen_odd > 0 && seen_even > 0);
}

/* The cache: patterns equal core_grid_adaptive's, hits return the same pattern, the byte bound holds and evicts
 * the least recently used pattern, unsorted keys are refused. */
static void test_cache(void **state)
{
    core_pattern_cache *c = core_pattern_cache_create(200u << 10); /* about two of the largest patterns */
    assert_non_null(c);
    const core_grid *p = core_pattern_get(c, 3, 4, 7);
    assert_non_null(p);
    core_grid ref;
    assert_int_equal(core_grid_adaptive((const int[3]){3, 4, 7}, &ref), 0);
    assert_int_equal(p->n_triangles, ref.n_triangles);
    assert_memory_equal(p->idx, ref.idx, 3 * ref.n_triangles * sizeof(uint32_t));
    assert_memory_equal(p->bary, ref.bary, ref.n_points * sizeof(float3));
    core_grid_free(&ref);
    assert_ptr_equal(core_pattern_get(c, 3, 4, 7), p);
    assert_int_equal(core_pattern_cache_built(c), 1);
    assert_null(core_pattern_get(c, 4, 3, 7));
    assert_null(core_pattern_get(c, 1, 1, 65));
    for (int k = 40; k <= 64; k++) {
        assert_non_null(core_pattern_get(c, k, k, k));
        assert_true(core_pattern_cache_bytes(c) <= 200u << 10);
        assert_non_null(core_pattern_get(c, 3, 4, 7)); /* kept in use: never the one evicted */
    }
    assert_true(core_pattern_cache_evicted(c) > 0);
    assert_int_equal(core_pattern_cache_built(c), 1 + 25); /* 3/4/7 was never rebuilt */
    core_pattern_cache_destroy(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_levels),
        cmocka_unit_test(test_uniform_is_regular),
        cmocka_unit_test(test_pattern_as_regular_grid),
        cmocka_unit_test(test_lod_order),
        cmocka_unit_test(test_cache),
        cmocka_unit_test(test_unsorted_patterns_tile),
        cmocka_unit_test(test_patterns_tile),
    };
    return cmocka_run_group_tests_name("adaptive", tests, NULL, NULL);
}
