/* tests/test_api_grid.c -- every public function of core/grid.h with NULL pointers, levels of zero, negative,
 * huge and not finite, unknown grid kinds, unsorted and out-of-range level triples, and the pattern cache at
 * bounds of 0 and SIZE_MAX: each returns its error (-1, 0, NULL, false) or a grid, never writes through a NULL
 * pointer or past the arrays it was given (ASan in the sanitizer stage).
 * tests/check_api_walkers.sh checks that every INSTESS_API function of core/grid.h is named in this file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../core/core.h"

/* core_grid_regular and its sizes: levels below 1 (and above the grid's limit) give nothing, NULL arrays too. */
static void test_regular(void **state)
{
    (void)state;
    assert_int_equal(core_grid_points(0), 0);
    assert_int_equal(core_grid_points(-5), 0);
    assert_int_equal(core_grid_triangles(-5), 0);
    assert_int_equal(core_grid_points(INT_MIN), 0);
    float3 bary[6];
    uint32_t idx[12];
    assert_int_equal(core_grid_regular(0, bary, idx), 0);
    assert_int_equal(core_grid_regular(-3, bary, idx), 0);
    assert_int_equal(core_grid_regular(INT_MIN, bary, idx), 0);
    assert_int_equal(core_grid_regular(2, NULL, idx), 0);
    assert_int_equal(core_grid_regular(2, bary, NULL), 0);
    assert_int_equal(core_grid_regular(INT_MAX, NULL, NULL), 0);   /* beyond the limit: before any write */
    assert_int_equal(core_grid_regular(2, bary, idx), 6);
    assert_int_equal(core_grid_points(2), 6);
    assert_int_equal(core_grid_triangles(2), 4);
    /* core_grid_regular_level: the list just made is level 2; NULL, no triangles, huge counts, the wrong point
     * count, a changed index, a count that is not a square: 0 */
    assert_int_equal(core_grid_regular_level(idx, 4, 6), 2);
    assert_int_equal(core_grid_regular_level(NULL, 4, 6), 0);
    assert_int_equal(core_grid_regular_level(idx, 0, 6), 0);
    assert_int_equal(core_grid_regular_level(idx, SIZE_MAX, 6), 0);
    assert_int_equal(core_grid_regular_level(idx, 4, SIZE_MAX), 0);
    assert_int_equal(core_grid_regular_level(idx, 4, 7), 0);
    assert_int_equal(core_grid_regular_level(idx, 3, 6), 0);
    /* core_grid_regular_level_mirrored: the same inputs give 0; the list mirrored is level 2 for it alone */
    assert_int_equal(core_grid_regular_level_mirrored(idx, 4, 6), 0);
    assert_int_equal(core_grid_regular_level_mirrored(NULL, 4, 6), 0);
    assert_int_equal(core_grid_regular_level_mirrored(idx, SIZE_MAX, 6), 0);
    assert_int_equal(core_grid_regular_level_mirrored(idx, 4, SIZE_MAX), 0);
    for (int t = 0; t < 4; t++) {
        const uint32_t k = idx[3 * t + 1];
        idx[3 * t + 1] = idx[3 * t + 2], idx[3 * t + 2] = k;
    }
    assert_int_equal(core_grid_regular_level_mirrored(idx, 4, 6), 2);
    assert_int_equal(core_grid_regular_level_mirrored(idx, 0, 6), 0);
    assert_int_equal(core_grid_regular_level(idx, 4, 6), 0);
    idx[11] ^= 1;
    assert_int_equal(core_grid_regular_level_mirrored(idx, 4, 6), 0);
    assert_int_equal(core_grid_regular(2, bary, idx), 6);
    idx[11] ^= 1;
    assert_int_equal(core_grid_regular_level(idx, 4, 6), 0);
}

/* core_grid_make / core_grid_pg / core_grid_pg_clamp: kinds that do not exist, levels not finite, negative,
 * huge; NULL outputs and outer levels.  An error leaves an empty grid that core_grid_free takes. */
static void test_make_and_pg(void **state)
{
    (void)state;
    const float levels[] = {0.0f, -0.0f, -1.0f, 0.5f, 1.0f, 63.5f, 64.0f, 65.0f, 1e6f, 16384.0f, 16385.0f, 1e30f,
                            FLT_MAX, INFINITY, -INFINITY, NAN, 1e-45f};
    const int kinds[] = {CORE_GRID_REGULAR, CORE_GRID_PG_EQUAL, CORE_GRID_PG_FRACTIONAL_ODD,
                         CORE_GRID_PG_FRACTIONAL_EVEN, -1, 4, 99, INT_MAX};
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++)
        for (size_t l = 0; l < sizeof levels / sizeof levels[0]; l++) {
            core_grid g;
            memset(&g, 0xAB, sizeof g);
            int rc = core_grid_make((core_grid_kind)kinds[k], levels[l], &g);
            if (rc == 0) {
                assert_true(g.n_points > 0 && g.n_triangles > 0 && g.bary && g.idx);
                for (size_t i = 0; i < 3 * g.n_triangles; i++) assert_true(g.idx[i] < g.n_points);
            } else {
                assert_int_equal(rc, -1);
                assert_null(g.bary);
                assert_int_equal(g.n_points, 0);
            }
            core_grid_free(&g);
            float c = core_grid_pg_clamp((core_grid_kind)kinds[k], levels[l]);
            if (!isnan(levels[l])) assert_true(c >= 1.0f && c <= CORE_PG_MAX_LEVEL);
            const float outer[3] = {levels[l], 2.0f, levels[(l + 3) % (sizeof levels / sizeof levels[0])]};
            rc = core_grid_pg((core_grid_kind)kinds[k], levels[l], outer, &g);
            assert_true(rc == 0 || rc == -1);
            core_grid_free(&g);
        }
    assert_int_equal(core_grid_make(CORE_GRID_REGULAR, 4.0f, NULL), -1);
    core_grid g;
    assert_int_equal(core_grid_pg(CORE_GRID_PG_EQUAL, 4.0f, NULL, &g), -1);
    assert_int_equal(g.n_points, 0);
    const float outer[3] = {1, 2, 3};
    assert_int_equal(core_grid_pg(CORE_GRID_PG_EQUAL, 4.0f, outer, NULL), -1);
    core_grid_free(NULL);
    core_grid_free(&g);
}

/* core_grid_adaptive and core_lod_order: NULL, levels 0, negative, above 64, INT_MIN / INT_MAX. */
static void test_adaptive(void **state)
{
    (void)state;
    const int bad[][3] = {{0, 1, 1}, {1, 1, 65}, {-1, 2, 3}, {INT_MIN, 1, 1}, {INT_MAX, 1, 1}, {64, 64, 100}};
    core_grid g;
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        assert_int_equal(core_grid_adaptive(bad[k], &g), -1);
        assert_int_equal(g.n_points, 0);
        int sorted[3], perm[3];
        (void)core_lod_order(bad[k], sorted, perm);   /* any ints sort */
        for (int i = 0; i < 3; i++) assert_true(perm[i] >= 0 && perm[i] < 3);
    }
    assert_int_equal(core_grid_adaptive(NULL, &g), -1);
    assert_int_equal(core_grid_adaptive((const int[3]){1, 2, 3}, NULL), -1);
    /* core_grid_adaptive_points: the same bad levels and NULLs give -1 and write nothing */
    float3 pts[10], canary = {-7.0f, -7.0f, -7.0f};   /* core_grid_points(3) */
    for (size_t k = 0; k < sizeof pts / sizeof *pts; k++) pts[k] = canary;
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) assert_int_equal(core_grid_adaptive_points(bad[k], pts), -1);
    assert_int_equal(core_grid_adaptive_points(NULL, pts), -1);
    assert_int_equal(core_grid_adaptive_points((const int[3]){1, 2, 3}, NULL), -1);
    for (size_t k = 0; k < sizeof pts / sizeof *pts; k++) assert_memory_equal(&pts[k], &canary, sizeof canary);
    assert_int_equal(core_grid_adaptive_points((const int[3]){3, 1, 2}, pts), 3);
    int sorted[3] = {7, 7, 7}, perm[3] = {7, 7, 7};
    assert_false(core_lod_order(NULL, sorted, perm));
    assert_false(core_lod_order((const int[3]){3, 2, 1}, NULL, perm));
    assert_false(core_lod_order((const int[3]){3, 2, 1}, sorted, NULL));
    assert_int_equal(core_grid_adaptive((const int[3]){64, 1, 64}, &g), 0);
    core_grid_free(&g);
}

/* The pattern cache: NULL, bounds 0 (the default) and 1 byte and SIZE_MAX, triples unsorted, out of range. */
static void test_pattern_cache(void **state)
{
    (void)state;
    assert_null(core_pattern_get(NULL, 1, 1, 1));
    assert_int_equal(core_pattern_cache_bytes(NULL), 0);
    assert_int_equal(core_pattern_cache_built(NULL), 0);
    assert_int_equal(core_pattern_cache_evicted(NULL), 0);
    core_pattern_cache_destroy(NULL);
    const size_t bounds[] = {0, 1, 4096, SIZE_MAX};
    for (size_t b = 0; b < sizeof bounds / sizeof bounds[0]; b++) {
        core_pattern_cache *c = core_pattern_cache_create(bounds[b]);
        assert_non_null(c);
        const int triples[][3] = {{0, 0, 0}, {1, 1, 1}, {3, 2, 1}, {1, 1, 65}, {-5, 1, 2}, {INT_MIN, INT_MAX, INT_MAX},
                                  {64, 64, 64}, {1, 64, 64}, {2, 2, 3}};
        for (size_t k = 0; k < sizeof triples / sizeof triples[0]; k++) {
            const int *t = triples[k];
            const core_grid *g = core_pattern_get(c, t[0], t[1], t[2]);
            bool valid = t[0] >= 1 && t[0] <= t[1] && t[1] <= t[2] && t[2] <= CORE_LOD_MAX_LEVEL;
            assert_true(valid ? g != NULL : g == NULL);
        }
        /* a bound of one byte keeps the one pattern asked for, evicting the others */
        if (bounds[b] == 1) assert_true(core_pattern_cache_evicted(c) > 0);
        assert_true(core_pattern_cache_built(c) >= 4);
        (void)core_pattern_cache_bytes(c);
        core_pattern_cache_destroy(c);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_regular),
        cmocka_unit_test(test_make_and_pg),
        cmocka_unit_test(test_adaptive),
        cmocka_unit_test(test_pattern_cache),
    };
    return cmocka_run_group_tests_name("api_grid", tests, NULL, NULL);
}
