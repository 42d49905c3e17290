/* tests/test_figures.c -- pixel-diff tests of every figure (cli/figures/figures.h): both tables, fig_renders and
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
#define _DEFAULT_SOURCE  /* realpath */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>

#include "../cli/figures/figures.h"
#include "util/golden.h"
#include "util/prog.h"

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

/* A figure's picture in the form its PNG holds (scene_write_picture's): what the goldens are. */
static void png_form(is_image *img)
{
    scene_opts o;
    scene_opts_default(&o);
    scene_picture_for_format(img, IS_IMAGE_PNG, o.background);
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
        if (rc == 0) png_form(&img);
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

/* The renderings (cli/figures/fig_renders.c). */
static void test_render_figures(void **state)
{
    (void)state;
    check_table(fig_renders);
}

/* The diagrams (cli/figures/fig_diagrams.c). */
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

/* A figure's view renders as the command does, --cull included (the figures once drew with D3D9's default cull
 * mode whatever the view said): the cube seen with CW culling shows its inside, other pixels than CCW's. */
static void test_views_honour_cull(void **state)
{
    (void)state;
    fig_ctx ctx = {.small = true, .threads = 0};
    const char *specs[] = {"--mesh cube --cull ccw", "--mesh cube --cull cw", "--mesh cube --cull none"};
    is_image img[3];
    char err[512];
    for (int k = 0; k < 3; k++) assert_int_equal(fig_render_spec(&ctx, specs[k], 64, 64, &img[k], err, sizeof err), 0);
    size_t n = (size_t)64 * 64 * img[0].channels * sizeof(float);
    assert_true(memcmp(img[0].data, img[1].data, n) != 0);   /* CW culls the faces CCW keeps */
    assert_true(memcmp(img[0].data, img[2].data, n) == 0);   /* a closed mesh: no culling looks like CCW's */
    for (int k = 0; k < 3; k++) image_free(&img[k]);
}

/* Whether figure f is a single rendering: its Reproduce line is one `instess` render (not `instess figures`). */
static bool single_rendering(const figure *f)
{
    return f->rendering && strncmp(f->command, "instess --", 10) == 0 && !strchr(f->command, '\n');
}

/* Every single rendering's Reproduce line, run through the program as printed (only the output moved into a
 * temporary folder), gives the figure's pixels exactly: the gallery's commands are the figures. */
static void test_reproduce_lines(void **state)
{
    (void)state;
    char dir[256];
    assert_int_equal(prog_mkdtemp(dir, "reproduce"), 0);
    fig_ctx ctx = {.small = false, .threads = 0};
    int checked = 0, failed = 0;
    for (const figure *f = fig_renders; f->id; f++) {
        if (!single_rendering(f) || !selected(f->id)) continue;
        const char *o = strstr(f->command, " -o ");
        assert_non_null(o);
        char fig_png[512], cli_png[512], name[128], err[1024];
        snprintf(name, sizeof name, "%s-cli.png", f->id);
        prog_path(dir, name, cli_png, sizeof cli_png);
        snprintf(name, sizeof name, "%s-figure.png", f->id);
        prog_path(dir, name, fig_png, sizeof fig_png);
        const char *perr;
        int rc = prog_run(dir, &perr, "", "%.*s -q -o '%s'", (int)(o - f->command - 8), f->command + 8, cli_png);
        if (rc != 0) fprintf(stderr, "figures: %s: the Reproduce line failed (%d): %s\n", f->id, rc, perr);
        is_image img = {0};
        if (rc == 0 && (rc = f->render(&ctx, &img, err, sizeof err)) == 0)
            png_form(&img), rc = image_write(&img, fig_png, NULL, err, sizeof err);
        image_free(&img);
        if (rc == 0 && !prog_same_pixels(fig_png, cli_png)) {
            fprintf(stderr, "figures: %s: the Reproduce line gives other pixels than the figure\n", f->id);
            rc = -1;
        }
        failed += rc != 0;
        checked++;
    }
    prog_rmdir(dir);
    fprintf(stderr, "figures: %d Reproduce lines run, %d differ\n", checked, failed);
    if (!getenv("INSTESS_FIGURES_ONLY")) assert_true(checked >= 10);   /* every single rendering of the table */
    assert_int_equal(failed, 0);
}

/* The sRGB transfer function's inverse (what an EXR's linear colour is of the PNG's display value). */
static float linear_of(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

/* The gallery's files are written by `instess -o`'s writer: a single rendering's ID.png and ID.exr are the bytes
 * its Reproduce line writes to a .png, and with --aov normal (the figure's N channels) to an .exr -- channels,
 * formats, colour space and description; the EXR holds linear colour premultiplied by the coverage (0 and
 * transparent on the background, the PNG's display values decoded from sRGB where the mesh covers the pixel),
 * and a composite's background is transparent too. */
static void test_files_like_cli(void **state)
{
    (void)state;
    char dir[256], out[512], a[600], b[600], name[160];
    assert_int_equal(prog_mkdtemp(dir, "files"), 0);
    prog_path(dir, "gallery", out, sizeof out);
    const char *perr;
    static const char *const ids[] = {"fig-1.1.8b", "fig-1.1.10b"};
    int rc = prog_run(dir, &perr, "", "figures --only %s,%s,fig-001-5 --out '%s'", ids[0], ids[1], out);
    if (rc != 0) fprintf(stderr, "figures: exit %d: %s\n", rc, perr);
    assert_int_equal(rc, 0);
    for (size_t k = 0; k < sizeof ids / sizeof ids[0]; k++) {
        const figure *f = fig_renders;
        while (f->id && strcmp(f->id, ids[k])) f++;
        assert_non_null(f->id);
        const char *args = f->command + strlen("instess "), *o = strstr(args, " -o ");
        assert_non_null(o);
        char cli_png[600], cli_exr[600];
        prog_path(dir, "cli.png", cli_png, sizeof cli_png);
        prog_path(dir, "cli.exr", cli_exr, sizeof cli_exr);
        assert_int_equal(prog_run(dir, &perr, "", "%.*s -q -o '%s'", (int)(o - args), args, cli_png), 0);
        assert_int_equal(prog_run(dir, &perr, "", "%.*s -q --aov normal -o '%s'", (int)(o - args), args, cli_exr), 0);
        for (int e = 0; e < 2; e++) {
            snprintf(name, sizeof name, "gallery/%s.%s", ids[k], e ? "exr" : "png");
            prog_path(dir, name, a, sizeof a);
            prog_path(dir, e ? "cli.exr" : "cli.png", b, sizeof b);
            if (!prog_same_bytes(a, b)) fprintf(stderr, "figures: %s differs from the Reproduce line's file\n", name);
            assert_true(prog_same_bytes(a, b));
        }
        is_image exr = {0}, png = {0};
        char err[512];
        assert_int_equal(image_read(&exr, b, err, sizeof err), 0);
        prog_path(dir, "cli.png", a, sizeof a);
        assert_int_equal(image_read(&png, a, err, sizeof err), 0);
        assert_int_equal(exr.channels, 8);
        assert_string_equal(exr.channel_names[5], "N.X");
        long covered = 0;
        for (size_t p = 0; p < (size_t)exr.width * exr.height; p++) {
            const float *x = &exr.data[p * exr.channels], *g = &png.data[p * png.channels];
            assert_true(g[3] == 1.0f);                          /* the PNG: opaque, over the background */
            if (x[3] == 0.0f) assert_true(x[0] == 0.0f && x[1] == 0.0f && x[2] == 0.0f && x[4] == 1.0f);
            if (x[3] != 1.0f) continue;
            covered++;
            for (int c = 0; c < 3; c++) assert_true(fabsf(x[c] - linear_of(g[c])) <= 1e-3f + 1e-3f * x[c]);
        }
        assert_true(covered > 10000);
        assert_true(exr.data[3] == 0.0f);                       /* the corner: background */
        image_free(&exr), image_free(&png);
    }
    is_image comp = {0};
    char err[512];
    assert_int_equal(image_read(&comp, prog_path(dir, "gallery/fig-001-5.exr", a, sizeof a), err, sizeof err), 0);
    assert_true(comp.data[3] == 0.0f && comp.data[0] == 0.0f);  /* a composite's background: transparent */
    image_free(&comp);
    prog_rmdir(dir);
}

/* ---------------------------------------- the smoothness numbers the documents quote ---------------------------------------- */

/* tess_smoothness of patch p on the built-in (welded) cube, as instess smoothness measures it (16 samples). */
static vs_smoothness_result cube_smoothness(vs_patch p)
{
    is_mesh m;
    char err[256];
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);
    vs_options o = vs_default_options();
    o.normals = VS_NORMALS_REAL;
    vs_smoothness_result r;
    assert_int_equal(tess_smoothness(&m, p, &o, 16, &r), 0);
    mesh_free(&m);
    return r;
}

/* The cube's numbers the captions of fig-1.1.1d, fig-1.1.8b and fig-1.1.10b, the README and docs/smoothness.md
 * state: the final patch across the cube's 12 edges (not the 18 shared edges, which count the 6 face diagonals
 * too), and the valley the final patch leaves beside the face diagonals (the N-Patch's faces lean apart: none). */
static void test_smoothness_cube(void **state)
{
    (void)state;
    vs_smoothness_result sm = cube_smoothness(VS_PATCH_SMOOTH), si = cube_smoothness(VS_PATCH_SMOOTH_INITIAL);
    vs_smoothness_result np = cube_smoothness(VS_PATCH_NPATCH), fl = cube_smoothness(VS_PATCH_FLAT);
    assert_true(fabs(sm.max_angle_feature_deg - 9.20) < 0.005);
    assert_true(fabs(sm.mean_angle_feature_deg - 2.10) < 0.005);
    assert_true(fabs(sm.mean_angle_deg - 1.44) < 0.005);
    assert_true(fabs(sm.max_angle_coplanar_deg - 0.28) < 0.005);
    assert_true(fabs(sm.max_valley_deg - 5.30) < 0.005);
    assert_true(fabs(si.max_valley_deg - 21.82) < 0.005);
    assert_true(np.max_valley_deg == 0.0 && fl.max_valley_deg == 0.0);
}

/* The caption ("shows") of the figure called id. */
static const char *shows_of(const char *id)
{
    for (const figure *f = fig_renders; f->id; f++)
        if (!strcmp(f->id, id)) return f->shows;
    fail_msg("no figure %s", id);
    return NULL;
}

/* Whether caption `shows` of figure id states the measurement (formatted as it is written there). */
static bool states(const char *id, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static bool states(const char *id, const char *fmt, ...)
{
    char phrase[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(phrase, sizeof phrase, fmt, ap);
    va_end(ap);
    bool ok = strstr(shows_of(id), phrase) != NULL;
    if (!ok) fprintf(stderr, "figures: %s does not say \"%s\" (measured now)\n", id, phrase);
    return ok;
}

/* The numbers the cube's captions quote are those tess_smoothness measures (instess smoothness,
 * docs/smoothness.md): fig-1.1.1d across the cube's 12 edges (their mean, not the mean over all 18 shared edges)
 * and across the face diagonals; fig-1.1.10b the diagonals and the valley beside them; fig-1.1.8b the
 * intermediate patch's. */
static void test_caption_numbers(void **state)
{
    (void)state;
    vs_smoothness_result sm = cube_smoothness(VS_PATCH_SMOOTH), si = cube_smoothness(VS_PATCH_SMOOTH_INITIAL);
    assert_true(states("fig-1.1.1d", "%.1f degrees at worst and %.1f on average across the cube's 12 edges",
                       sm.max_angle_feature_deg, sm.mean_angle_feature_deg));
    assert_true(states("fig-1.1.1d", "%.2f across the 6 face diagonals", sm.max_angle_coplanar_deg));
    assert_true(states("fig-1.1.1d", "its mean over all 18 shared edges, %.2f,", sm.mean_angle_deg));
    assert_true(states("fig-1.1.10b", "differ by only %.2f degrees", sm.max_angle_coplanar_deg));
    assert_true(states("fig-1.1.10b", "lean towards each other by up to %.1f degrees", sm.max_valley_deg));
    assert_true(states("fig-1.1.8b", "differ by %.1f degrees", si.max_angle_coplanar_deg));
    assert_true(states("fig-1.1.8b", "by up to %.1f degrees apart", si.max_valley_deg));
}

/* One face of the welded cube: its two triangles (edge ka of A is edge kb of B, the face's diagonal). */
static void cube_face(vs_triangle *A, vs_triangle *B, int *ka, int *kb)
{
    is_mesh m;
    char err[256];
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);   /* the built-in: welded, as rendered */
    vs_triangle T[2];
    for (int t = 0; t < 2; t++) {
        const uint32_t *i = &m.indices[3 * t];
        float3 v[3] = {m.positions[i[0]], m.positions[i[1]], m.positions[i[2]]};
        float3 n[3] = {m.normals[i[0]], m.normals[i[1]], m.normals[i[2]]};
        T[t] = vs_triangle_make(v, n);
    }
    mesh_free(&m);
    *A = T[0], *B = T[1], *ka = *kb = -1;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (!memcmp(&A->v[i], &B->v[(j + 1) % 3], sizeof(float3)) &&
                !memcmp(&A->v[(i + 1) % 3], &B->v[j], sizeof(float3)))
                *ka = i, *kb = j;
    assert_true(*ka >= 0);
}

/* Ridge or valley (docs/smoothness.md): the intermediate patch across the diagonal of a cube face, a quarter of
 * the way along it, on the diagonal and 1/64 of the way to each side's opposite corner (0.022 off the diagonal on
 * the cube of side 2).  Both sides' normals lean 9.53 degrees towards the diagonal and the surface there stands
 * 0.0054 higher than on the diagonal (0.2554 against 0.2500 above the face's plane): a concave fold, a valley --
 * the word the README, the captions and --help use.  The N-Patch's normals at the same points lean 0.42 degrees
 * apart (its face bulges). */
static void test_diagonal_valley(void **state)
{
    (void)state;
    vs_triangle A, B;
    int ka, kb;
    cube_face(&A, &B, &ka, &kb);
    vs_options o = vs_default_options();
    o.normals = VS_NORMALS_REAL;
    float3 face = normalize3(cross3(sub3(A.v[1], A.v[0]), sub3(A.v[2], A.v[0])));
    if (dot3(face, A.v[0]) < 0) face = scale3(face, -1.0f);              /* outward */
    const float t = 0.25f, s = 1.0f / 64.0f;
    float ba[3] = {0, 0, 0}, bb[3] = {0, 0, 0}, be[3] = {0, 0, 0};
    ba[ka] = (1 - s) * (1 - t), ba[(ka + 1) % 3] = (1 - s) * t, ba[(ka + 2) % 3] = s;
    bb[kb] = (1 - s) * t, bb[(kb + 1) % 3] = (1 - s) * (1 - t), bb[(kb + 2) % 3] = s;   /* B runs the other way */
    be[ka] = 1 - t, be[(ka + 1) % 3] = t;
    float3 pa, pb, pe, na, nb;
    vs_patch_eval(VS_PATCH_SMOOTH_INITIAL, &A, f3(ba[0], ba[1], ba[2]), &o, &pa, &na, NULL);
    vs_patch_eval(VS_PATCH_SMOOTH_INITIAL, &B, f3(bb[0], bb[1], bb[2]), &o, &pb, &nb, NULL);
    vs_patch_eval(VS_PATCH_SMOOTH_INITIAL, &A, f3(be[0], be[1], be[2]), &o, &pe, NULL, NULL);
    float3 d = sub3(pb, pa);                                            /* across the diagonal, from A to B */
    d = normalize3(sub3(d, scale3(face, dot3(d, face))));
    double lean_a = asin(dot3(na, d)) * 57.29577951308232, lean_b = -asin(dot3(nb, d)) * 57.29577951308232;
    double ha = dot3(sub3(pa, A.v[0]), face), hb = dot3(sub3(pb, A.v[0]), face), he = dot3(sub3(pe, A.v[0]), face);
    print_message("diagonal of a cube face: normals lean %.3f and %.3f deg towards it; height %.4f on it, %.4f and "
                  "%.4f beside it\n", lean_a, lean_b, he, ha, hb);
    assert_true(fabs(lean_a - 9.53) < 0.01 && fabs(lean_b - 9.53) < 0.01);   /* towards each other: concave */
    assert_true(fabs(he - 0.2500) < 1e-4 && fabs(ha - 0.2554) < 1e-4 && fabs(hb - 0.2554) < 1e-4);
    vs_patch_eval(VS_PATCH_NPATCH, &A, f3(ba[0], ba[1], ba[2]), &o, NULL, &na, NULL);
    vs_patch_eval(VS_PATCH_NPATCH, &B, f3(bb[0], bb[1], bb[2]), &o, NULL, &nb, NULL);
    lean_a = asin(dot3(na, d)) * 57.29577951308232, lean_b = -asin(dot3(nb, d)) * 57.29577951308232;
    assert_true(fabs(lean_a + 0.42) < 0.01 && fabs(lean_b + 0.42) < 0.01);
}

/* The smoothness tables of docs/smoothness.md (every row) and of the README (the cube's rows, without the mesh
 * column) are what `instess smoothness` prints: the numbers the documents state are the command's. */
static void test_smoothness_tables(void **state)
{
    (void)state;
    char dir[256], cmd[2400];
    assert_int_equal(prog_mkdtemp(dir, "smooth"), 0);
    snprintf(cmd, sizeof cmd, "'%s' smoothness > %s/t.md && grep '^|' docs/smoothness.md | cmp -s - %s/t.md",
             prog_bin(), dir, dir);
    if (system(cmd) != 0) fprintf(stderr, "docs/smoothness.md's table is not what instess smoothness prints\n");
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "grep '^| cube |' %s/t.md | sed 's/^| cube |/|/' > %s/cube.md && test $(wc -l < "
                              "%s/cube.md) -eq 6 && test $(grep -c -x -F -f %s/cube.md README.md) -eq 6", dir, dir,
             dir, dir);
    if (system(cmd) != 0) fprintf(stderr, "README's cube table is not what instess smoothness prints\n");
    assert_int_equal(system(cmd), 0);
    prog_rmdir(dir);
}

/* The README's "render both and compare" example shows what it says: its three lines (two renders of assimp's
 * Cube.off and their comparison) run in a fresh folder, compare exits 1 (they differ), and the two lines it
 * prints are the ones the README quotes, number for number.  (The example was the MD2 faerie, whose two
 * images differ by 0.0002 on average: nothing to see.) */
static void test_readme_compare(void **state)
{
    (void)state;
    char dir[256], cmd[2400 + PATH_MAX], bin[PATH_MAX];
    assert_non_null(realpath(prog_bin(), bin));   /* the commands run in dir */
    assert_int_equal(prog_mkdtemp(dir, "readme"), 0);
    snprintf(cmd, sizeof cmd, "mkdir %s/out && grep -E '^build/instess (/usr/share/assimp/models/OFF/Cube.off "
             "|compare out/cube-)' README.md | sed \"s|^build/instess|'%s' -q|; s|-q compare|compare|\" > %s/run.sh && "
             "test $(wc -l < %s/run.sh) -eq 3", dir, bin, dir, dir);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "cd %s && sh run.sh > said.txt 2>&1; test $? -eq 1", dir);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "grep -e '^largest difference' -e '^failing pixels' %s/said.txt | sed 's/^/  /' > "
             "%s/lines.txt && test $(wc -l < %s/lines.txt) -eq 2 && test $(grep -c -x -F -f %s/lines.txt README.md) "
             "-eq 2", dir, dir, dir, dir);
    if (system(cmd) != 0) fprintf(stderr, "figures: the README does not quote what its compare example prints\n");
    assert_int_equal(system(cmd), 0);
    prog_rmdir(dir);
}

/* One word for the fold along the cube's face diagonals, the one the measured normals justify (a valley,
 * test_diagonal_valley): --help says valley, and every line of the README and of the documents this part of the
 * project writes (docs/smoothness.md, docs/errata.md) that says ridge quotes Gruen or sets it against the valley;
 * so do the captions. */
static void test_valley_word(void **state)
{
    (void)state;
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "'%s' --help | grep -q 'valleys show' && ! '%s' --help | grep -qiw 'ridges\\?'",
             prog_bin(), prog_bin());
    assert_int_equal(system(cmd), 0);
    assert_int_equal(system("! grep -iw 'ridges\\?' README.md docs/smoothness.md docs/errata.md | "
                            "grep -v -e Gruen -e valley"), 0);
    for (const figure *f = fig_renders; f->id; f++)
        if (f->shows && strstr(f->shows, "ridge") && !strstr(f->shows, "valley"))
            fail_msg("%s's caption says ridge without the valley", f->id);
}

/* Whether the pixels of p appear unchanged somewhere in big (same channels): the first pixel of p that is not its
 * top-left pixel picks the candidates, then the whole panel is compared. */
static bool contains_panel(const is_image *big, const is_image *p)
{
    const int c = p->channels;
    if (big->channels != c || p->width > big->width || p->height > big->height) return false;
    size_t key = 0, np = (size_t)p->width * p->height;
    while (key < np && !memcmp(&p->data[key * c], &p->data[0], c * sizeof(float))) key++;
    if (key == np) key = 0;
    int kx = (int)(key % p->width), ky = (int)(key / p->width);
    for (int y = 0; y + p->height <= big->height; y++)
        for (int x = 0; x + p->width <= big->width; x++) {
            const float *b = &big->data[((size_t)(y + ky) * big->width + x + kx) * c];
            if (memcmp(b, &p->data[key * c], c * sizeof(float))) continue;
            bool same = true;
            for (int r = 0; same && r < p->height; r++)
                same = !memcmp(&big->data[((size_t)(y + r) * big->width + x) * c], &p->data[(size_t)r * p->width * c],
                               (size_t)p->width * c * sizeof(float));
            if (same) return true;
        }
    return false;
}

/* Run every "panel K: instess ARGS -o panelK.png" line of composite f and look for its pixels in the composite
 * (written to png and read back: the same 8-bit rounding as the command's PNG); returns the failures. */
static int check_panels(const figure *f, const char *dir, int *checked)
{
    fig_ctx ctx = {.small = false, .threads = 0};
    char err[1024], path[512], name[160];
    is_image img = {0}, big = {0};
    snprintf(name, sizeof name, "%s-figure.png", f->id);
    prog_path(dir, name, path, sizeof path);
    int made = f->render(&ctx, &img, err, sizeof err);
    if (made == 0) png_form(&img);
    if (made != 0 || image_write(&img, path, NULL, err, sizeof err) != 0 ||
        image_read(&big, path, err, sizeof err) != 0) {
        fprintf(stderr, "figures: %s: %s\n", f->id, err);
        image_free(&img);
        return 1;
    }
    image_free(&img);
    int failed = 0;
    for (const char *line = strstr(f->command, "\npanel "); line; line = strstr(line + 1, "\npanel ")) {
        const char *args = strstr(line, ": instess "), *o = args ? strstr(args, " -o ") : NULL;
        const char *eol = strchr(line + 1, '\n');
        if (!args || !o || (eol && o > eol)) continue;   /* a panel without a command line (said so in the text) */
        args += 10;
        snprintf(name, sizeof name, "%s-panel.png", f->id);
        prog_path(dir, name, path, sizeof path);
        const char *perr;
        is_image p = {0};
        int rc = prog_run(dir, &perr, "", "%.*s -q -o '%s'", (int)(o - args), args, path);
        if (rc != 0) fprintf(stderr, "figures: %s: a panel's line failed (%d): %s\n", f->id, rc, perr);
        else if (image_read(&p, path, err, sizeof err) != 0 || !contains_panel(&big, &p)) {
            fprintf(stderr, "figures: %s: the pixels of '%.*s' are not in the figure\n", f->id, (int)(o - args), args);
            rc = -1;
        }
        image_free(&p);
        failed += rc != 0;
        ++*checked;
    }
    image_free(&big);
    return failed;
}

/* Every panel command listed under a composite gives pixels that are in the composite as they are. */
static void test_panel_lines(void **state)
{
    (void)state;
    char dir[256];
    assert_int_equal(prog_mkdtemp(dir, "panels"), 0);
    int checked = 0, failed = 0;
    for (const figure *f = fig_renders; f->id; f++)
        if (f->rendering && strstr(f->command, "\npanel ") && selected(f->id)) failed += check_panels(f, dir, &checked);
    prog_rmdir(dir);
    fprintf(stderr, "figures: %d panel lines run, %d not found in their figure\n", checked, failed);
    if (!getenv("INSTESS_FIGURES_ONLY")) assert_true(checked >= 20);
    assert_int_equal(failed, 0);
}

/* Every reproduction of a document's figure says where to find the original (fig_original, shown in the gallery
 * beside it): the figure number and the document's citation; the others (comparisons, companions, figures the
 * text only describes, adaptive LOD) claim none. */
static void test_originals(void **state)
{
    (void)state;
    static const char *const docs[3] = {"Smoothed N-Patches", "A Discussion of Curved Point-Normal Triangles",
                                        "Bezier Triangles and N-Patches"};
    const figure *const tables[2] = {fig_renders, fig_diagrams};
    int cited = 0;
    for (int t = 0; t < 2; t++)
        for (const figure *f = tables[t]; f->id; f++) {
            char buf[600];
            const char *o = fig_original(f, buf, sizeof buf), *num = strstr(f->source, ", Figure ");
            if (!num || f->section > 2) {
                assert_null(o);
                continue;
            }
            assert_non_null(o);
            char want[64];
            snprintf(want, sizeof want, "Figure %s of ", num + 9);
            if (strncmp(o, want, strlen(want)) != 0 || !strstr(o, docs[f->section]))
                fail_msg("%s: '%s' does not cite %s%s", f->id, o, want, docs[f->section]);
            assert_null(strchr(o, '/'));   /* a citation, never a path */
            cited++;
        }
    print_message("%d reproductions cite their original\n", cited);
    assert_true(cited >= 27);   /* 14 renderings and 13 diagrams */
}

/* Sentence k of text (split after ". "), copied into buf; false when there is none. */
static bool sentence(const char *text, int k, char *buf, size_t len)
{
    const char *p = text;
    for (int i = 0; i < k && p; i++) {
        p = strstr(p, ". ");
        if (p) p += 2;
    }
    if (!p || !*p) return false;
    const char *e = strstr(p, ". ");
    size_t n = e ? (size_t)(e - p) : strlen(p);
    snprintf(buf, len, "%.*s", (int)n, p);
    return true;
}

/* No sentence of 30 characters or more is said in the captions ("shows") of two figures: what holds for many
 * is said once, in the gallery's section introductions. */
static void test_no_repeated_sentences(void **state)
{
    (void)state;
    const figure *const tables[2] = {fig_renders, fig_diagrams};
    int repeats = 0;
    for (int a = 0; a < 2; a++)
        for (const figure *f = tables[a]; f->id; f++) {
            char sent[1024];
            for (int k = 0; sentence(f->shows, k, sent, sizeof sent); k++) {
                if (strlen(sent) < 30) continue;
                for (int b = 0; b < 2; b++)
                    for (const figure *g = tables[b]; g->id; g++)
                        if (g != f && strstr(g->shows, sent) && f < g) {
                            fprintf(stderr, "figures: %s and %s both say \"%s\"\n", f->id, g->id, sent);
                            repeats++;
                        }
            }
        }
    assert_int_equal(repeats, 0);
}

/* Occurrences of needle in the file at path (-1 when unreadable). */
static int count_in_file(const char *path, const char *needle)
{
    size_t n;
    unsigned char *data = prog_slurp(path, &n);
    if (!data) return -1;
    char *text = realloc(data, n + 1);
    if (!text) return free(data), -1;
    text[n] = 0;
    int c = 0;
    for (const char *p = text; (p = strstr(p, needle)); p += strlen(needle)) c++;
    free(text);
    return c;
}

/* `instess figures --only ID --out NEWDIR` writes an index of what is in NEWDIR: that figure alone (no image
 * links, ids or contents entries of figures not rendered there); a second run into the same folder adds its
 * figure to the first.  Its Reproduce lines say build/instess, the program a clone has. */
static void test_only_index(void **state)
{
    (void)state;
    char dir[256], sub[512], index[600];
    assert_int_equal(prog_mkdtemp(dir, "only"), 0);
    snprintf(sub, sizeof sub, "%s/new/gallery", dir);
    snprintf(index, sizeof index, "%s/index.html", sub);
    const char *err;
    int rc = prog_run(dir, &err, "", "figures --only fig-1.1.3 --out '%s'", sub);
    if (rc != 0) fprintf(stderr, "figures --only: exit %d: %s\n", rc, err);
    assert_int_equal(rc, 0);
    assert_int_equal(count_in_file(index, "<figure id=\"fig-1.1.3\""), 1);
    assert_int_equal(count_in_file(index, "<figure id="), 1);
    assert_int_equal(count_in_file(index, "<img src="), 1);
    assert_int_equal(count_in_file(index, "href=\"#fig-"), 1);
    assert_int_equal(count_in_file(index, "<h2 id=\"section-"), 1);
    /* the link to the tutorial in the browser (make web), with its contents entry; not built in this folder */
    assert_int_equal(count_in_file(index, "<a href=\"web/index.html\">"), 1);
    assert_int_equal(count_in_file(index, "href=\"#browser\""), 1);
    assert_int_equal(count_in_file(index, "Not built in this folder yet"), 1);
    assert_int_equal(count_in_file(index, "The original (not shown here): Figure 1.1.3 of H. Gruen, &quot;Smoothed "
                                          "N-Patches&quot;, article 1.1 of ShaderX5"), 1);
    rc = prog_run(dir, &err, "", "figures --only fig-003-4 --out '%s'", sub);
    assert_int_equal(rc, 0);
    assert_int_equal(count_in_file(index, "<figure id="), 2);
    assert_int_equal(count_in_file(index, "<figure id=\"fig-003-4\""), 1);
    assert_int_equal(count_in_file(index, "<h2 id=\"section-"), 2);
    /* the Reproduce lines name the program as a clone has it (build/instess), never a bare instess */
    assert_int_equal(count_in_file(index, "<code>build/instess figures --only fig-1.1.3 --out DIR</code>"), 1);
    assert_true(count_in_file(index, "build/instess ") >= 2);
    assert_int_equal(count_in_file(index, "<code>instess "), 0);
    assert_int_equal(count_in_file(index, ": instess "), 0);
    prog_rmdir(dir);
}

/* index.html is an output of the run: a FIFO or a symbolic link at its place is refused before anything is
 * rendered (exit 1, the reason named), and left as it was; the old writer renamed a predictable temporary over
 * whatever was there. */
static void test_index_odd_targets(void **state)
{
    (void)state;
    char dir[256], out[512], index[600], target[600];
    assert_int_equal(prog_mkdtemp(dir, "index"), 0);
    const char *err;
    for (int k = 0; k < 2; k++) {
        snprintf(out, sizeof out, "%s/g%d", dir, k);
        assert_int_equal(mkdir(out, 0755), 0);
        snprintf(index, sizeof index, "%s/index.html", out);
        snprintf(target, sizeof target, "%s/keep.txt", dir);
        assert_true(prog_write_text(dir, "keep.txt", "keep\n"));
        if (k == 0) assert_int_equal(mkfifo(index, 0644), 0);
        else assert_int_equal(symlink(target, index), 0);
        int rc = prog_run(dir, &err, "", "figures --only fig-1.1.3 --out '%s'", out);
        assert_int_equal(rc, 1);
        assert_non_null(strstr(err, k == 0 ? "is a FIFO" : "is a symbolic link"));
        assert_int_equal(prog_entries_with(out, NULL), 1);   /* index.html alone: no figure rendered */
        size_t n = 0;
        unsigned char *bytes = prog_slurp(target, &n);
        assert_true(bytes && n == 5 && memcmp(bytes, "keep\n", 5) == 0);
        free(bytes);
    }
    prog_rmdir(dir);
}

/* The viewer's frame (made on every whole run, and with --only viewer), made by `instess view` headless into
 * viewer.png, is in the gallery with its contents entry; a gallery of --only figures has no viewer section.
 * (One figure and the viewer rather than the whole gallery: the whole run takes minutes under the sanitizers.) */
static void test_gallery_viewer(void **state)
{
    (void)state;
    char dir[256], all[512], one[512], index[600], png[600];
    assert_int_equal(prog_mkdtemp(dir, "viewer"), 0);
    snprintf(all, sizeof all, "%s/all", dir);
    snprintf(one, sizeof one, "%s/one", dir);
    const char *err;
    int rc = prog_run(dir, &err, "", "figures --small --only fig-1.1.3,viewer --out '%s'", all);
    if (rc != 0) fprintf(stderr, "figures --only fig-1.1.3,viewer: exit %d: %s\n", rc, err);
    assert_int_equal(rc, 0);
    snprintf(index, sizeof index, "%s/index.html", all);
    snprintf(png, sizeof png, "%s/viewer.png", all);
    size_t n = 0;
    unsigned char *bytes = prog_slurp(png, &n);
    assert_non_null(bytes);
    assert_true(n > 1000 && memcmp(bytes, "\x89PNG", 4) == 0);
    free(bytes);
    assert_int_equal(count_in_file(index, "<img src=\"viewer.png\""), 1);
    assert_int_equal(count_in_file(index, "href=\"#live\""), 1);
    assert_int_equal(prog_run(dir, &err, "", "figures --only fig-1.1.3 --out '%s'", one), 0);
    snprintf(index, sizeof index, "%s/index.html", one);
    assert_int_equal(count_in_file(index, "viewer.png"), 0);
    prog_rmdir(dir);
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
    /* The codec module (OpenImageIO and its ~260 libraries) loaded before any OpenMP thread exists: loaded later, its
     * thread-local storage grows the worker threads' TLS vectors, which clang 14's LeakSanitizer then misreads at
     * exit ("Tracer caught signal 11", the sanitizer stage), once enough threads and modules come together. */
    int tw = 0, th = 0;
    (void)image_text_size("x", 12.0f, &tw, &th);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tables_complete),
        cmocka_unit_test(test_deterministic),
        cmocka_unit_test(test_no_repeated_sentences),
        cmocka_unit_test(test_originals),
        cmocka_unit_test(test_only_index),
        cmocka_unit_test(test_gallery_viewer),
        cmocka_unit_test(test_reproduce_lines),
        cmocka_unit_test(test_views_honour_cull),
        cmocka_unit_test(test_index_odd_targets),
        cmocka_unit_test(test_files_like_cli),
        cmocka_unit_test(test_smoothness_cube),
        cmocka_unit_test(test_caption_numbers),
        cmocka_unit_test(test_diagonal_valley),
        cmocka_unit_test(test_smoothness_tables),
        cmocka_unit_test(test_valley_word),
        cmocka_unit_test(test_readme_compare),
        cmocka_unit_test(test_panel_lines),
        cmocka_unit_test(test_render_figures),
        cmocka_unit_test(test_diagram_figures),
    };
    return cmocka_run_group_tests_name("figures", tests, NULL, NULL);
}
