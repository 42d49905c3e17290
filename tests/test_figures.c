/* tests/test_figures.c -- pixel-diff tests of every figure (cli/figures.h): both tables, fig_renders and
 * fig_diagrams, rendered at the test size (fig_ctx.small) and compared with tests/golden/<id>.png.
 *
 * Thresholds: the renders are deterministic under the fixed build configuration (Makefile: -O2
 * -march=x86-64-v3 -ffp-contract=off; the device gives the same bytes for any thread count), so a regenerated
 * golden matches exactly on this machine.  The allowance is for what may still move between machines of this
 * kind: 1/255 per channel (one step of 8-bit rounding of a resolved 4x MSAA pixel), and on at most 0.25% of the
 * pixels more than that (glyph edges of OpenImageIO / FreeType text and libm's last bits in acosf, sqrtf, ... that
 * can flip one anti-aliased edge sample).  A missing golden fails (golden_check).
 *
 * INSTESS_REGENERATE_GOLDENS=1 (make goldens) rewrites the goldens; INSTESS_FIGURES_ONLY=ID[,ID...] restricts the
 * test to those figures (to regenerate only one's own goldens). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cli/figures.h"
#include "util/golden.h"

#define FAIL_THRESH (1.0f / 255.0f)  /* per channel: one 8-bit step */
#define FAIL_PERCENT 0.25f           /* of the pixels: text glyph edges, libm last bits */

/* Whether id is selected by INSTESS_FIGURES_ONLY (all when unset). */
static bool selected(const char *id)
{
    const char *only = getenv("INSTESS_FIGURES_ONLY");
    if (!only || !*only) return true;
    size_t n = strlen(id);
    for (const char *p = only; *p;) {
        size_t len = strcspn(p, ",");
        if (len == n && strncmp(p, id, n) == 0) return true;
        p += len + (p[len] == ',');
    }
    return false;
}

/* Render every figure of table t small and compare with its golden; the failures are listed, then asserted. */
static void check_table(const figure *t)
{
    fig_ctx ctx = {.small = true, .threads = 0};
    int failures = 0, checked = 0;
    for (const figure *f = t; f->id; f++) {
        if (!selected(f->id)) continue;
        is_image img = {0};
        char err[1024] = "";
        int rc = f->render(&ctx, &img, err, sizeof err);
        if (rc != 0) fprintf(stderr, "figures: %s: render failed: %s\n", f->id, err);
        else if (img.width > 1024 || img.height > 1200)
            fprintf(stderr, "figures: %s: the small size is %dx%d, too large\n", f->id, img.width, img.height), rc = -1;
        else if (golden_check(&img, f->id, FAIL_THRESH, FAIL_PERCENT) != 0)
            fprintf(stderr, "figures: %s: golden check failed (tests/golden/%s.png missing or different)\n", f->id,
                    f->id), rc = -1;
        failures += rc != 0;
        checked++;
        image_free(&img);
    }
    fprintf(stderr, "figures: %d checked, %d failed\n", checked, failures);
    assert_int_equal(failures, 0);
}

/* The renderings (cli/fig_renders.c). */
static void test_render_figures(void **state)
{
    (void)state;
    check_table(fig_renders);
}

/* The diagrams (cli/fig_diagrams.c). */
static void test_diagram_figures(void **state)
{
    (void)state;
    check_table(fig_diagrams);
}

/* The table entries are complete: id, source, caption, shows, command, a render function, a gallery section;
 * ids are unique. */
static void test_tables_complete(void **state)
{
    (void)state;
    const figure *const tables[2] = {fig_renders, fig_diagrams};
    for (int a = 0; a < 2; a++)
        for (const figure *f = tables[a]; f->id; f++) {
            assert_non_null(f->source), assert_non_null(f->caption), assert_non_null(f->shows);
            assert_non_null(f->command), assert_non_null(f->render);
            assert_true(strncmp(f->command, "instess ", 8) == 0);
            assert_true(f->section >= 0 && f->section < FIG_SECTIONS);
            for (int b = 0; b < 2; b++)
                for (const figure *g = tables[b]; g->id; g++)
                    if (g != f) assert_true(strcmp(f->id, g->id) != 0);
        }
}

/* A figure's bytes do not depend on the thread count (fig_ctx.threads 1 vs 3). */
static void test_deterministic(void **state)
{
    (void)state;
    const figure *f = &fig_renders[0];
    is_image a = {0}, b = {0};
    char err[512];
    fig_ctx c1 = {.small = true, .threads = 1}, c3 = {.small = true, .threads = 3};
    assert_int_equal(f->render(&c1, &a, err, sizeof err), 0);
    assert_int_equal(f->render(&c3, &b, err, sizeof err), 0);
    assert_int_equal(a.width, b.width);
    assert_int_equal(a.channels, b.channels);
    assert_memory_equal(a.data, b.data, (size_t)a.width * a.height * a.channels * sizeof(float));
    image_free(&a);
    image_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tables_complete),
        cmocka_unit_test(test_deterministic),
        cmocka_unit_test(test_render_figures),
        cmocka_unit_test(test_diagram_figures),
    };
    return cmocka_run_group_tests_name("figures", tests, NULL, NULL);
}
