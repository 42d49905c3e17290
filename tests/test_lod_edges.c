/* tests/test_lod_edges.c -- per-edge levels of detail and D3D9's adaptive mode at their edges (docs/robustness.md,
 * "Round 3: library API, viewer and numbers"): a mesh whose edges take thousands of distinct level triples (the
 * pattern pool, counted in --max-memory before it is built), the pattern cache at a bound of one byte (the same
 * buffers as the default bound), --silhouette on open meshes (edges of one face), and --d3d9-adaptive with a
 * depth of zero, negative or huge (every level MAX or MIN: the non-adaptive image of that level, byte for byte).
 * The usage errors of --lod (min above max, levels beyond 64, targets of 0) are test_adaptive_cracks's and
 * test_option_edges's; the closed --export-obj of an adaptive render is test_adaptive_cracks's. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/prog.h"
#include "../cli/run/scene.h"
#include "../tess/tess.h"

static char dir[256];

static int setup(void **state)
{
    (void)state;
    return prog_mkdtemp(dir, "lod-edges");
}

static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

/* A deterministic number in [0, 1) from *s (a 64-bit LCG). */
static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

enum { BUMPY_N = 60 };
/* The bumpy open sheet: an N x N grid in x, y jittered by 0.02 with heights 0..0.3, two triangles per cell
 * (OBJ's counter-clockwise fronts); its edges' projected lengths vary so much that --lod screen --lod-target 0.25
 * gives them every level and their triangles about 1,800 distinct level triples.  Written to dir/name. */
static void write_bumpy(const char *name)
{
    char p[600];
    FILE *f = fopen(prog_path(dir, name, p, sizeof p), "w");
    assert_non_null(f);
    uint64_t s = 7;
    for (int j = 0; j < BUMPY_N; j++)
        for (int i = 0; i < BUMPY_N; i++) {
            double x = i / (double)BUMPY_N + lcg(&s) * 0.02, y = j / (double)BUMPY_N + lcg(&s) * 0.02;
            fprintf(f, "v %.6f %.6f %.6f\n", x, y, lcg(&s) * 0.3);
        }
    for (int j = 0; j + 1 < BUMPY_N; j++)
        for (int i = 0; i + 1 < BUMPY_N; i++) {
            int a = j * BUMPY_N + i + 1, b = a + 1, c = a + BUMPY_N, d = c + 1;
            fprintf(f, "f %d %d %d\nf %d %d %d\n", a, b, d, a, d, c);
        }
    assert_int_equal(fclose(f), 0);
}

/* The pattern pool of thousands of distinct level triples is counted in --max-memory before anything of it is
 * built: refused at once in 100 MiB (it needs about 250), rendered when --max-level 8 keeps it small. */
static void test_pattern_pool_budget(void **state)
{
    (void)state;
    const char *err;
    write_bumpy("bumpy.obj");
    char args[1200], obj[600];
    prog_path(dir, "bumpy.obj", obj, sizeof obj);
    snprintf(args, sizeof args, "--mesh %s --lod screen --lod-target 0.25 --max-level 64 --size 512x512 -q "
             "--max-memory 100 -o %s/pool.png", obj, dir);
    assert_int_equal(prog_run(dir, &err, "", "%s", args), 1);
    if (!strstr(err, "distinct edge-level triples")) fprintf(stderr, "said: %s\n", err);
    assert_non_null(strstr(err, "distinct edge-level triples, whose patterns need about"));
    assert_non_null(strstr(err, "more than the memory budget of 100 MiB"));
    assert_false(prog_exists(dir, "pool.png"));
    snprintf(args, sizeof args, "--mesh %s --lod screen --lod-target 0.25 --max-level 8 --size 512x512 -q "
             "--max-memory 100 -o %s/pool.png", obj, dir);
    assert_int_equal(prog_run(dir, &err, "", "%s", args), 0);
    assert_true(prog_exists(dir, "pool.png"));
}

/* The pattern cache bounded to one byte (every pattern evicted by the next) builds the same buffers as the default
 * bound: the pool keeps a copy of each pattern before the cache is asked for another. */
static void test_cache_bound_changes_nothing(void **state)
{
    (void)state;
    char err[300];
    is_mesh m;
    write_bumpy("cache.obj");
    char obj[600];
    assert_int_equal(mesh_load_file(prog_path(dir, "cache.obj", obj, sizeof obj), NULL, &m, err, sizeof err), 0);
    tess_lod_edges e;
    assert_int_equal(tess_lod_edges_build(&m, &e, err, sizeof err), 0);
    float4x4 wv = mat_mul((const float4x4[]){mat_rotation_x(0.9f)}, (const float4x4[]){mat_translation(-0.5f, -0.3f, 1.2f)});
    float4x4 proj = mat_perspective_fov_lh(0.8f, 1.0f, 0.05f, 10.0f);
    tess_lod_params p = {.mode = TESS_LOD_SCREEN, .target_px = 0.5f, .min_level = 1, .max_level = 64, .width = 512,
                         .height = 512, .world_view = wv, .wvp = mat_mul(&wv, &proj)};
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    tess_lod_levels(&p, &m, &e, hist);
    core_pattern_cache *tiny = core_pattern_cache_create(1), *big = core_pattern_cache_create(0);
    is_device *d1 = dev_create(8, 8, 1, NULL, 0), *d2 = dev_create(8, 8, 1, NULL, 0);
    tess_adaptive a1, a2;
    assert_int_equal(tess_bind_adaptive(d1, &m, &e, tiny, &a1), IS_OK);
    assert_int_equal(tess_bind_adaptive(d2, &m, &e, big, &a2), IS_OK);
    fprintf(stderr, "%zu patterns, %zu evicted from the one-byte cache\n", a1.n_patterns,
            core_pattern_cache_evicted(tiny));
    assert_true(a1.n_patterns > 100);
    assert_true(core_pattern_cache_evicted(tiny) >= a1.n_patterns - 1);
    assert_int_equal(a1.n_patterns, a2.n_patterns);
    assert_int_equal(a1.n_buckets, a2.n_buckets);
    assert_int_equal(vb_size(a1.r.vb0), vb_size(a2.r.vb0));
    assert_memory_equal(vb_lock(a1.r.vb0), vb_lock(a2.r.vb0), vb_size(a1.r.vb0));
    assert_int_equal(ib_size(a1.r.ib), ib_size(a2.r.ib));
    assert_memory_equal(ib_lock(a1.r.ib), ib_lock(a2.r.ib), ib_size(a1.r.ib));
    assert_memory_equal(a1.buckets, a2.buckets, a1.n_buckets * sizeof *a1.buckets);
    tess_adaptive_free(&a1), tess_adaptive_free(&a2);
    dev_destroy(d1), dev_destroy(d2);
    core_pattern_cache_destroy(tiny), core_pattern_cache_destroy(big);
    tess_lod_edges_free(&e);
    mesh_free(&m);
}

/* Whether dir/name's every value is finite. */
static bool all_finite(const char *name)
{
    char p[600], err[400];
    is_image img = {0};
    if (image_read(&img, prog_path(dir, name, p, sizeof p), err, sizeof err) != 0) return false;
    size_t n = (size_t)img.width * img.height * img.channels, bad = 0;
    for (size_t k = 0; k < n; k++) bad += !isfinite(img.data[k]);
    image_free(&img);
    return bad == 0;
}

/* --silhouette on open meshes (a sheet with boundary edges of one face, one lone triangle): rendered, finite. */
static void test_silhouette_open_meshes(void **state)
{
    (void)state;
    const char *err;
    write_bumpy("open.obj");
    assert_true(prog_write_text(dir, "one.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    const char *const meshes[] = {"open.obj", "one.obj"};
    const char *const modes[] = {"screen", "distance"};
    for (int k = 0; k < 2; k++)
        for (int l = 0; l < 2; l++) {
            char p[600];
            int rc = prog_run(dir, &err, "", "--mesh %s --lod %s --silhouette --cull none --max-level 12 --size 64x64 "
                              "-q --aov normal,bary -o %s/sil.exr", prog_path(dir, meshes[k], p, sizeof p), modes[l],
                              dir);
            if (rc != 0) fprintf(stderr, "%s --lod %s: %s\n", meshes[k], modes[l], err);
            assert_int_equal(rc, 0);
            assert_true(all_finite("sil.exr"));
        }
}

/* D3D9's adaptive mode with an Mdm that makes every depth 0 (T = S / 0: +inf, then MAX), negative everywhere (T < 0: MAX) or
 * huge (T ~ 0: MIN): every edge at one level, so the image is the mode's without adaptivity at that level. */
static void test_d3d9_adaptive_values(void **state)
{
    (void)state;
    const char *err;
    const char *base = "--path npatch-mode --patch npatch --mesh icosahedron --size 96x96 -q";
    assert_int_equal(prog_run(dir, &err, "", "%s --level 8 -o %s/max.png", base, dir), 0);
    assert_int_equal(prog_run(dir, &err, "", "%s --level 1 -o %s/min.png", base, dir), 0);
    static const struct { const char *mdm, *same; } cases[] = {
        {"0,0,0,0", "max.png"}, {"0,0,0,-1", "max.png"}, {"0,0,0,-3e38", "max.png"}, {"0,0,0,1e38", "min.png"}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        assert_int_equal(prog_run(dir, &err, "", "%s --level 8 --d3d9-adaptive %s -o %s/ad.png", base, cases[k].mdm,
                                  dir), 0);
        char a[600], b[600];
        bool same = prog_same_pixels(prog_path(dir, "ad.png", a, sizeof a), prog_path(dir, cases[k].same, b, sizeof b));
        if (!same) fprintf(stderr, "--d3d9-adaptive %s: not the image of %s\n", cases[k].mdm, cases[k].same);
        assert_true(same);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pattern_pool_budget),
        cmocka_unit_test(test_cache_bound_changes_nothing),
        cmocka_unit_test(test_silhouette_open_meshes),
        cmocka_unit_test(test_d3d9_adaptive_values),
    };
    return cmocka_run_group_tests_name("lod_edges", tests, setup, teardown);
}
