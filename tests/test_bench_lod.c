/* tests/test_bench_lod.c -- scene D's options and target line (bench/bench_lod.c, compiled into this test): the
 * --lod-modes list (uniform / u and pixels per segment; empty items, a trailing comma, zero, negative, too many
 * and junk refused), and the pick behind the target line: the fastest adaptive mode within 0.5 px of the uniform
 * surface, never one beyond it, against the uniform mode; the colour comparison with the uniform frame. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "../bench/bench_lod.c"

/* Lists that parse, with their modes. */
static void test_modes_parse(void **state)
{
    (void)state;
    bench_lod_args a = {0};
    assert_int_equal(bench_lod_parse_modes(&a, "uniform,8,4,3,2"), 0);
    assert_int_equal(a.n_modes, 5);
    const float want[] = {0.0f, 8.0f, 4.0f, 3.0f, 2.0f};
    for (int k = 0; k < 5; k++) assert_true(a.modes[k] == want[k]);
    assert_int_equal(bench_lod_parse_modes(&a, "u,2.5"), 0);
    assert_int_equal(a.n_modes, 2);
    assert_true(a.modes[0] == 0.0f && a.modes[1] == 2.5f);
    assert_int_equal(bench_lod_parse_modes(&a, "3"), 0);
    assert_true(a.n_modes == 1 && a.modes[0] == 3.0f);
    assert_int_equal(bench_lod_parse_modes(&a, "d0.3,u,d2"), 0);   /* the deviation mode, as a negative value */
    assert_true(a.n_modes == 3 && a.modes[0] == -0.3f && a.modes[1] == 0.0f && a.modes[2] == -2.0f);
}

/* Lists that do not parse leave a usage error. */
static void test_modes_refused(void **state)
{
    (void)state;
    static const char *bad[] = {"", ",", "u,", ",u", "u,,2", "0", "-2", "1001", "nan", "2x", "un", "uniformx",
                                "1,2,3,4,5,6,7,8,9", "u 2", "d", "d0", "d-1", "d-0.5", "dd1", "d1x", "dnan", "d 1"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        bench_lod_args a = {0};
        if (bench_lod_parse_modes(&a, bad[k]) == 0) fail_msg("\"%s\" parsed", bad[k]);
    }
    assert_int_equal(bench_lod_parse_modes(NULL, "u"), -1);
    assert_int_equal(bench_lod_parse_modes(&(bench_lod_args){0}, NULL), -1);
}

/* The target's pick: the fastest adaptive mode within 0.5 px, the uniform mode, failed modes skipped. */
static void test_target_pick(void **state)
{
    (void)state;
    const float modes[] = {0.0f, 8.0f, 3.0f, 2.0f, 0.0f, -0.3f};
    d_result r[6] = {{.ms = 60}, {.ms = 20, .deviation = 2.4}, {.ms = 35, .deviation = 0.47},
                     {.ms = 50, .deviation = 0.32}, {.ms = 10}, {.ms = 30, .deviation = 0.6}};
    bool ok[6] = {true, true, true, true, false, true};
    assert_int_equal(d_pick(modes, r, ok, 6, false), 0);   /* the failed uniform run is not taken */
    assert_int_equal(d_pick(modes, r, ok, 6, true), 2);    /* 8 px is faster, but 2.4 px off */
    r[2].deviation = 0.5;
    assert_int_equal(d_pick(modes, r, ok, 6, true), 2);    /* 0.5 px is within */
    r[2].deviation = 0.5001;
    assert_int_equal(d_pick(modes, r, ok, 6, true), 3);
    ok[3] = false;
    assert_int_equal(d_pick(modes, r, ok, 6, true), -1);
    r[5].deviation = 0.41;   /* the deviation mode (a negative value) is adaptive too */
    assert_int_equal(d_pick(modes, r, ok, 6, true), 5);
    r[5].deviation = 0.6, r[2].deviation = NAN;
    assert_int_equal(d_pick(modes, r, ok, 6, true), -1);
}

/* The colour comparison: the first call keeps the frame, later ones count pixels over 8/255 and the mean. */
static void test_colour_against_uniform(void **state)
{
    (void)state;
    is_device *dev = dev_create(4, 4, 1, NULL, 0);
    assert_non_null(dev);
    uint32_t *ref = NULL;
    d_result r;
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET, IS_COLOR_ARGB(255, 100, 100, 100), 1.0f), IS_OK);
    d_colour(dev, &ref, &r);
    assert_non_null(ref);
    assert_int_equal(r.colour_over, -1);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET, IS_COLOR_ARGB(255, 100, 109, 100), 1.0f), IS_OK);
    d_colour(dev, &ref, &r);
    assert_int_equal(r.colour_over, 16);   /* 9 > 8 on every pixel */
    assert_true(fabs(r.colour_mean - 3.0) < 1e-9);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET, IS_COLOR_ARGB(0, 92, 100, 108), 1.0f), IS_OK);
    d_colour(dev, &ref, &r);
    assert_int_equal(r.colour_over, 0);    /* 8 is not over; alpha is not compared */
    assert_true(fabs(r.colour_mean - 16.0 / 3.0) < 1e-9);
    d_colour(dev, NULL, &r);
    assert_int_equal(r.colour_over, -1);
    free(ref);
    dev_destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_modes_parse),
        cmocka_unit_test(test_modes_refused),
        cmocka_unit_test(test_target_pick),
        cmocka_unit_test(test_colour_against_uniform),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
