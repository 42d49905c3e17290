/* tests/test_adaptive_cracks.c -- adaptive tessellation is crack-free across level transitions, and its OBJ export
 * is closed.
 *
 * The detector is tests/test_cracks.c's (see its top): culling and the depth test off, additive blending of 1/255,
 * so a closed surface covers every pixel an even number of times; each vertex is moved by up to half a pixel by a
 * hash of its clip position's bits, so that a shared edge point computed with one differing ulp by its two
 * triangles opens a visible sliver.  Here the triangles of one mesh are drawn with different patterns: every edge
 * gets an arbitrary level 1..MAX_TEST_LEVEL (a hash of its index and a seed), so every combination of neighbouring
 * levels and renumberings (even and odd) occurs, on every built-in mesh and every patch (split-normal meshes with
 * the patches that are crack-free there: flat and pn-aen, as in test_cracks.c), through the shaders' batched
 * entries and their per-vertex main.  Then the same through scene_draw with --lod distance and screen, and the
 * program's --export-obj of an adaptive render, welded by exact coordinates, has every edge used twice in opposite
 * directions. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cli/run/scene.h"
#include "util/crack.h"
#include "util/prog.h"

#include "../core/hlsl.h"
enum { SIZE = 96, MAX_TEST_LEVEL = 12 };

/* Colour 1/255 and, unless c10.y is 0, the bit-keyed jitter of oPos (a function of its bits alone). */
static void count_finish(const is_vs_constants *c, is_vs_output *out)
{
    out->attr[RS_ATTR_COLOR0] = f4(1.0f / 255.0f, 0, 0, 1.0f / 255.0f);
    if (c->c[10].y == 0.0f) return;
    crack_jitter(&out->pos, SIZE);
}

/* The patch selected by c10.x, through main. */
static void vs_count(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    vs_patch_shader((vs_patch)(int)c->c[10].x)->main(c, in, out);
    count_finish(c, out);
}
/* The same through its batched entry. */
static void vs_count_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                           is_vs_output *out)
{
    vs_patch_shader((vs_patch)(int)c->c[10].x)->batch(c, in, n, live, shared, out);
    for (size_t v = 0; v < n; v++) count_finish(c, &out[v]);
}
static const is_vertex_shader count_main = {.name = "count", .main = vs_count, .outputs = IS_OUT_COLOR0};
static const is_vertex_shader count_batch = {
    .name = "count-batch", .main = vs_count, .outputs = IS_OUT_COLOR0, .batch = vs_count_batch};

/* A counting device: culling and depth test off, additive blending, cleared; patch p selected in c10. */
static is_device *count_device(vs_patch p)
{
    is_device *dev = dev_create(SIZE, SIZE, 1, NULL, 0);
    assert_non_null(dev);
    crack_counting_states(dev);
    float sel[4] = {(float)p, 1.0f, 0, 0};
    dev_set_vertex_shader_constant_f(dev, 10, sel, 1);
    return dev;
}

/* Pixels with an odd count on dev (and the covered ones into *covered); dev destroyed. */
static long odd_and_destroy(is_device *dev, long *covered)
{
    const rs_target *rt = dev_render_target(dev);
    long odd = 0;
    *covered = 0;
    for (int k = 0; k < SIZE * SIZE; k++) {
        unsigned n = rt->color[k] & 0xff;
        odd += n & 1, *covered += n != 0;
    }
    dev_destroy(dev);
    return odd;
}

/* The scene options of these tests: SIZE x SIZE, one sample, close enough for curvature to show. */
static scene_opts test_opts(vs_patch p)
{
    scene_opts o;
    scene_opts_default(&o);
    o.patch = p, o.width = o.height = SIZE, o.msaa = 1, o.distance = 2.6f, o.yaw = -115.0f, o.pitch = -47.0f;
    return o;
}

/* Draw m with patch p and per-edge levels hashed from seed (edges of e; `break_tri` >= 0 makes that triangle
 * read a wrong edge's level: a planted disagreement) through the adaptive buffers with cull mode `cull`; the
 * counting device returned. */
static is_device *levels_device(const is_mesh *m, vs_patch p, uint32_t seed, bool batch, long break_tri, uint32_t cull)
{
    scene_opts o = test_opts(p);
    tess_lod_edges e;
    char err[256];
    assert_int_equal(tess_lod_edges_build(m, &e, err, sizeof err), 0);
    for (size_t k = 0; k < e.n_edges; k++) e.level[k] = (uint8_t)(1 + crack_mix32((uint32_t)k * 2654435761u ^ seed) % MAX_TEST_LEVEL);
    if (break_tri >= 0) { /* point its edge 0 at an edge of another level */
        uint32_t *te = &e.tri_edge[3 * (size_t)break_tri];
        for (size_t k = 0; k < e.n_edges; k++)
            if (e.level[k] != e.level[te[0]]) { te[0] = (uint32_t)k; break; }
    }
    core_pattern_cache *cache = core_pattern_cache_create(0);
    is_device *dev = count_device(p);
    dev_set_render_state(dev, IS_RS_CULLMODE, cull);
    if (cull != IS_CULL_NONE) dev_set_vertex_shader_constant_f(dev, 10, (const float[4]){(float)p, 0, 0, 0}, 1);
    dev_set_vertex_shader(dev, batch ? &count_batch : &count_main);
    tess_lod_params lp = scene_lod_params_of(&o, m);
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    float4x4 id = mat_identity();
    vs_options vo = vs_default_options();
    vs_set_constants(&c, &lp.wvp, &id, f4(1, 1, 1, 1), &vo);
    dev_set_vertex_shader_constant_f(dev, 0, &c.c[0].x, VS_C_COUNT);
    tess_adaptive a;
    assert_int_equal(tess_bind_adaptive(dev, m, &e, cache, &a), IS_OK);
    if (p == VS_PATCH_PN_AEN) assert_int_equal(tess_bind_adjacent_normals(dev, m, &a.r, &a), IS_OK);
    assert_true(a.n_buckets > 1);
    for (size_t k = 0; k < a.n_buckets; k++) assert_int_equal(tess_draw_bucket(dev, &a, k), IS_OK);
    tess_adaptive_free(&a);
    tess_lod_edges_free(&e);
    core_pattern_cache_destroy(cache);
    return dev;
}

/* levels_device without culling: its odd pixels (and the covered ones into *covered). */
static long odd_pixels_levels(const is_mesh *m, vs_patch p, uint32_t seed, bool batch, long break_tri, long *covered)
{
    return odd_and_destroy(levels_device(m, p, seed, batch, break_tri, IS_CULL_NONE), covered);
}

/* Winding: a convex closed mesh drawn flat with D3D9's default culling (CCW) covers every pixel inside its
 * silhouette exactly once (pixels next to the silhouette are left out: there triangles are seen edge-on and the
 * sign of their projected area is rounding noise) (without the jitter, which folds silhouettes) -- so the odd renumberings' flipped index ranges wind like the mesh (drawn unflipped,
 * their triangles would be culled in front, leaving holes, and drawn at the back). */
static void test_winding_of_renumbered_triangles(void **state)
{
    static const char *const meshes[] = {"sphere", "icosahedron", "cube"};
    for (size_t mi = 0; mi < 3; mi++) {
        is_mesh m = {0};
        char err[256];
        assert_int_equal(mesh_builtin(meshes[mi], &m, err, sizeof err), 0);
        is_device *all = levels_device(&m, VS_PATCH_FLAT, 3, true, -1, IS_CULL_NONE);
        is_device *front = levels_device(&m, VS_PATCH_FLAT, 3, true, -1, IS_CULL_CCW);
        const rs_target *ra = dev_render_target(all), *rf = dev_render_target(front);
        long wrong = 0, covered = 0;
        for (int y = 1; y < SIZE - 1; y++)
            for (int x = 1; x < SIZE - 1; x++) {
                bool inside = true; /* the pixel and its 8 neighbours are covered: away from the silhouette */
                for (int d = 0; d < 9; d++) inside &= (ra->color[(y + d / 3 - 1) * SIZE + x + d % 3 - 1] & 0xff) != 0;
                covered += inside;
                wrong += inside && (rf->color[y * SIZE + x] & 0xff) != 1;
            }
        if (wrong) fprintf(stderr, "winding: %s: %ld pixels not covered exactly once by front faces\n", meshes[mi], wrong);
        assert_int_equal(wrong, 0);
        assert_true(covered > SIZE * SIZE / 10);
        dev_destroy(all), dev_destroy(front);
        mesh_free(&m);
    }
}

/* Every built-in mesh and patch with hashed per-edge levels, two seeds, batched and per-vertex: no odd pixel. */
static void test_no_cracks_across_levels(void **state)
{
    long renders = 0;
    for (const char *const *name = mesh_builtin_names(); *name; name++) {
        is_mesh m = {0};
        char err[256];
        assert_int_equal(mesh_builtin(*name, &m, err, sizeof err), 0);
        bool split = crack_split_normals(&m);
        for (int p = 0; p < VS_PATCH_COUNT; p++) {
            if (split && p != VS_PATCH_FLAT && p != VS_PATCH_PN_AEN) continue;
            for (uint32_t seed = 1; seed <= 2; seed++)
                for (int batch = 0; batch < 2; batch++) {
                    long covered, odd = odd_pixels_levels(&m, (vs_patch)p, seed, batch, -1, &covered);
                    if (odd) fprintf(stderr, "cracks: %s %s seed %u %s: %ld odd pixels\n", *name,
                                     vs_patch_name((vs_patch)p), seed, batch ? "batched" : "main", odd);
                    assert_int_equal(odd, 0);
                    assert_true(covered > SIZE * SIZE / 10);
                    renders++;
                }
        }
        mesh_free(&m);
    }
    assert_true(renders > 50);
}

/* The detector sees a disagreement: one triangle reading another edge's level opens the surface. */
static void test_detector_sees_a_level_mismatch(void **state)
{
    is_mesh m = {0};
    char err[256];
    assert_int_equal(mesh_builtin("sphere", &m, err, sizeof err), 0);
    long covered;
    assert_int_equal(odd_pixels_levels(&m, VS_PATCH_NPATCH, 1, true, -1, &covered), 0);
    long odd = 0;
    for (long t = 0; t < 8 && odd == 0; t++) odd = odd_pixels_levels(&m, VS_PATCH_NPATCH, 1, true, t, &covered);
    assert_true(odd > 0);
    mesh_free(&m);
}

/* The distinct levels tess_lod_levels gives m's edges under o. */
static int lod_levels_used(const scene_opts *o, const is_mesh *m)
{
    tess_lod_edges e;
    char err[256];
    assert_int_equal(tess_lod_edges_build(m, &e, err, sizeof err), 0);
    tess_lod_params lp = scene_lod_params_of(o, m);
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    tess_lod_levels(&lp, m, &e, hist);
    int used = 0;
    for (int l = 0; l <= CORE_LOD_MAX_LEVEL; l++) used += hist[l] != 0;
    tess_lod_edges_free(&e);
    return used;
}

/* Through scene_draw: --lod distance and screen (with and without silhouettes), and tess_lod_levels' deviation
 * mode (which the program's --lod does not offer yet), on the welded meshes, every patch. */
static void test_no_cracks_lod_modes(void **state)
{
    static const char *const meshes[] = {"cube", "sphere", "icosahedron"};
    for (size_t mi = 0; mi < 3; mi++) {
        is_mesh m = {0};
        char err[256];
        assert_int_equal(mesh_builtin(meshes[mi], &m, err, sizeof err), 0);
        for (int p = 0; p < VS_PATCH_COUNT; p++)
            for (int mode = 0; mode < 4; mode++) {   /* distance, screen, screen with silhouettes, deviation */
                scene_opts o = test_opts((vs_patch)p);
                o.lod = mode == 0 ? TESS_LOD_DISTANCE : mode == 3 ? TESS_LOD_DEVIATION : TESS_LOD_SCREEN;
                o.max_level = 12, o.lod_target = mode == 3 ? 0.5f : 3.0f;
                o.distance = 1.6f, o.silhouette = mode == 2;
                if (mode == 3) assert_true(lod_levels_used(&o, &m) >= 5);   /* levels that can crack */
                is_device *dev = count_device((vs_patch)p);
                assert_int_equal(scene_draw(dev, &o, &m, NULL, &count_batch), 0);
                long covered, odd = odd_and_destroy(dev, &covered);
                if (odd) fprintf(stderr, "cracks: %s %s lod mode %d: %ld odd pixels\n", meshes[mi],
                                 vs_patch_name((vs_patch)p), mode, odd);
                assert_int_equal(odd, 0);
                assert_true(covered > SIZE * SIZE / 10);
            }
        mesh_free(&m);
    }
}

/* One OBJ vertex: its coordinates' text (the export prints %.9g, so equal text is equal floats) and its index. */
typedef struct vkey { char s[80]; uint32_t idx; } vkey;
static int vkey_cmp(const void *a, const void *b) { return strcmp(((const vkey *)a)->s, ((const vkey *)b)->s); }

static int u64_cmp(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

/* Each vertex's welded id (the group of equal coordinates it belongs to) from the vertices' texts. */
static uint32_t *weld_ids(vkey *v, size_t nv)
{
    uint32_t *id = malloc(nv * sizeof *id);
    assert_non_null(id);
    qsort(v, nv, sizeof *v, vkey_cmp);
    uint32_t g = 0;
    for (size_t k = 0; k < nv; k++) {
        if (k && strcmp(v[k].s, v[k - 1].s) != 0) g++;
        id[v[k].idx] = g;
    }
    return id;
}

/* Parse the OBJ at path, weld its vertices by exact coordinates and count the directed edges that have no
 * opposite twin or are used twice (*bad), and the faces (*faces). */
static void obj_closed(const char *path, long *bad, long *faces)
{
    size_t n;
    unsigned char *bytes = prog_slurp(path, &n);
    assert_non_null(bytes);
    char *text = malloc(n + 1); /* NUL-terminated for strtok_r */
    assert_non_null(text);
    memcpy(text, bytes, n), text[n] = 0, free(bytes);
    size_t nv = 0, nf = 0;
    for (size_t k = 0; k + 2 < n; k++)
        if (k == 0 || text[k - 1] == '\n') nv += text[k] == 'v' && text[k + 1] == ' ', nf += text[k] == 'f';
    vkey *v = malloc(nv * sizeof *v);
    uint64_t *de = malloc(3 * nf * sizeof *de);
    assert_true(v && de);
    size_t iv = 0, id = 0;
    for (char *save = NULL, *l = strtok_r(text, "\n", &save); l; l = strtok_r(NULL, "\n", &save)) {
        if (l[0] == 'v' && l[1] == ' ') snprintf(v[iv].s, sizeof v->s, "%s", l + 2), v[iv].idx = (uint32_t)iv, iv++;
        if (l[0] != 'f') continue;
        size_t q[3];
        assert_int_equal(sscanf(l, "f %zu/%*u/%*u %zu/%*u/%*u %zu/%*u/%*u", &q[0], &q[1], &q[2]), 3);
        for (int j = 0; j < 3; j++) de[id++] = (uint64_t)(q[j] - 1) << 32 | (q[(j + 1) % 3] - 1);
    }
    assert_int_equal(iv, nv);
    uint32_t *w = weld_ids(v, nv);
    for (size_t k = 0; k < id; k++) de[k] = (uint64_t)w[de[k] >> 32] << 32 | w[(uint32_t)de[k]];
    qsort(de, id, sizeof *de, u64_cmp);
    *bad = 0;
    for (size_t k = 0; k < id; k++) {
        uint64_t rev = de[k] << 32 | de[k] >> 32;
        if ((k && de[k] == de[k - 1]) || !bsearch(&rev, de, id, sizeof *de, u64_cmp)) (*bad)++;
    }
    *faces = (long)nf;
    free(v), free(w), free(de), free(text);
}

/* instess --lod screen --export-obj: the OBJ, welded by exact coordinates, is closed (welded meshes, the patches
 * that are watertight there); the level histogram is printed; with -q it is not. */
static void test_export_obj_closed(void **state)
{
    char dir[256], obj[512], png[512];
    assert_int_equal(prog_mkdtemp(dir, "adaptive"), 0);
    prog_path(dir, "a.png", png, sizeof png), prog_path(dir, "a.obj", obj, sizeof obj);
    static const struct { const char *mesh, *patch, *lod; } cases[] = {
        {"sphere", "smooth", "screen"}, {"cube", "npatch", "distance"}, {"icosahedron", "pn-aen", "screen"},
        {"cylinder", "pn-aen", "screen"}, {"tetrahedron", "phong", "distance"}, {"sphere", "npatch", "deviation"},
        {"icosahedron", "smooth", "deviation"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const char *err;
        int rc = prog_run(dir, &err, "", "--mesh %s --patch %s --lod %s --max-level 12 %s --distance 2 "
                          "--size 128x128 -o %s --export-obj %s", cases[k].mesh, cases[k].patch, cases[k].lod,
                          strcmp(cases[k].lod, "screen") == 0      ? "--lod-target 4"
                          : strcmp(cases[k].lod, "deviation") == 0 ? "--lod-deviation 0.2"
                                                                   : "",
                          png, obj);
        if (rc != 0) fprintf(stderr, "%s\n", err);
        assert_int_equal(rc, 0);
        assert_non_null(strstr(err, "edge levels (--lod "));
        long bad, faces;
        obj_closed(obj, &bad, &faces);
        if (bad) fprintf(stderr, "%s %s: %ld directed edges without a twin\n", cases[k].mesh, cases[k].patch, bad);
        assert_int_equal(bad, 0);
        assert_true(faces > 100);
    }
    /* the detector: the N-Patch on the cylinder's split normals (rim) is open (seed 001's Fig. 5) */
    const char *err;
    assert_int_equal(prog_run(dir, &err, "", "--mesh cylinder --patch npatch --lod screen --max-level 8 -q "
                              "--size 64x64 -o %s --export-obj %s", png, obj), 0);
    assert_null(strstr(err, "edge levels"));
    long bad, faces;
    obj_closed(obj, &bad, &faces);
    assert_true(bad > 0);
    prog_rmdir(dir);
}

/* --lod deviation follows --lod-deviation: an eighth of a pixel tessellates finer than the default half pixel,
 * which tessellates finer than two pixels (the triangle counts of the run's summary line), and the default is
 * the run with --lod-deviation 0.5, byte for byte. */
static void test_deviation_target(void **state)
{
    (void)state;
    char dir[256], a[512], b[512];
    assert_int_equal(prog_mkdtemp(dir, "deviation"), 0);
    const char *targets[] = {"2", "0.5", "0.125"};
    long tris[3];
    for (int k = 0; k < 3; k++) {
        const char *err;
        assert_int_equal(prog_run(dir, &err, "", "--mesh sphere --lod deviation --lod-deviation %s --max-level 16 "
                                  "--size 256x256 --distance 2 -o %s", targets[k], prog_path(dir, "a.png", a, sizeof a)), 0);
        const char *t = strstr(err, " buckets (one instanced draw each), ");
        assert_non_null(t);
        tris[k] = strtol(t + strlen(" buckets (one instanced draw each), "), NULL, 10);
    }
    fprintf(stderr, "triangles at 2, 0.5, 0.125 px: %ld %ld %ld\n", tris[0], tris[1], tris[2]);
    assert_true(tris[0] < tris[1] && tris[1] < tris[2]);
    const char *err;
    assert_int_equal(prog_run(dir, &err, "", "--mesh sphere --lod deviation --max-level 16 --size 256x256 "
                              "--distance 2 -q -o %s", prog_path(dir, "b.png", b, sizeof b)), 0);
    assert_true(prog_same_bytes(a, b) == false);   /* a holds the 0.125 px run */
    assert_int_equal(prog_run(dir, &err, "", "--mesh sphere --lod deviation --lod-deviation 0.5 --max-level 16 "
                              "--size 256x256 --distance 2 -q -o %s", a), 0);
    assert_true(prog_same_bytes(a, b));
    prog_rmdir(dir);
}

/* The renumbered instance is the same patch: every patch shader evaluated on tess_permute_instance's record at
 * the renumbered barycentrics gives the original's point (up to rounding), for all six renumberings, on the
 * welded cube (curved; its edges are feature edges or coplanar diagonals, so a wrong opp changes the smoothed
 * patches). */
static void test_permuted_instance_same_surface(void **state)
{
    static const uint8_t perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
    is_mesh m = {0};
    char err[256];
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);
    is_patch_instance *inst = malloc(m.n_triangles * sizeof *inst);
    assert_non_null(inst);
    mesh_build_instances(&m, inst);
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    float4x4 id = mat_identity();
    vs_options vo = vs_default_options();
    vs_set_constants(&c, &id, &id, f4(1, 1, 1, 1), &vo);
    double worst = 0.0;
    for (int p = 0; p < VS_PATCH_COUNT; p++) {
        if (p == VS_PATCH_PN_AEN) continue; /* its neighbour normals are a stream of their own (scene.c) */
        const is_vertex_shader *vs = vs_patch_shader((vs_patch)p);
        for (size_t t = 0; t < m.n_triangles; t++)
            for (int q = 0; q < 6; q++) {
                is_patch_instance pi;
                tess_permute_instance(&inst[t], perms[q], &pi);
                const float b[3] = {0.2f, 0.5f, 0.3f};
                is_vs_input in0, in1;
                is_vs_output o0, o1;
                tess_input_from_instance(&inst[t], NULL, f3(b[0], b[1], b[2]), &in0);
                tess_input_from_instance(&pi, NULL, f3(b[perms[q][0]], b[perms[q][1]], b[perms[q][2]]), &in1);
                vs->main(&c, &in0, &o0), vs->main(&c, &in1, &o1);
                double d = fabs((double)o0.pos.x - o1.pos.x) + fabs((double)o0.pos.y - o1.pos.y) +
                           fabs((double)o0.pos.z - o1.pos.z);
                if (d > 1e-5) fail_msg("%s: triangle %zu renumbered by %d%d%d moves by %g", vs_patch_name((vs_patch)p),
                                       t, perms[q][0], perms[q][1], perms[q][2], d);
                if (d > worst) worst = d;
            }
    }
    print_message("largest move under renumbering: %g\n", worst);
    free(inst);
    mesh_free(&m);
}

/* Usage errors of the adaptive options: exit 2 with the option named. */
static void test_lod_usage_errors(void **state)
{
    char dir[256], png[512];
    assert_int_equal(prog_mkdtemp(dir, "adaptive-usage"), 0);
    prog_path(dir, "x.png", png, sizeof png);
    static const struct { const char *args, *msg; } cases[] = {
        {"--lod sometimes", "unknown --lod"},
        {"--lod screen --max-level 65", "--max-level must be 1..64"},
        {"--lod screen --min-level 0", "--min-level must be 1..64"},
        {"--lod screen --level 100", "--max-level"},
        {"--lod screen --min-level 9 --max-level 4", "--min-level must be 1..--max-level"},
        {"--lod distance --grid pg-equal", "--grid must be regular"},
        {"--lod distance --path cpu --patch npatch", "--path instanced"},
        {"--lod screen --lod-target 0", "--lod-target"},
        {"--max-level 8", "need --lod distance, screen or deviation"},
        {"--silhouette", "need --lod distance, screen or deviation"},
        {"--lod distance --lod-target 4", "--lod-target needs --lod screen"},
        {"--lod screen --lod-deviation 0.3", "--lod-deviation needs --lod deviation"},
        {"--lod deviation --lod-deviation 0.1", "--lod-deviation takes pixels, 0.125..64"},
        {"--lod deviation --lod-target 4", "--lod-target needs --lod screen"},
        {"--lod screen --level 7.5", "whole levels"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const char *err;
        assert_int_equal(prog_run(dir, &err, "", "%s -o %s", cases[k].args, png), 2);
        if (!strstr(err, cases[k].msg)) fprintf(stderr, "%s: %s\n", cases[k].args, err);
        assert_non_null(strstr(err, cases[k].msg));
        assert_false(prog_exists(dir, "x.png"));
    }
    prog_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lod_usage_errors),
        cmocka_unit_test(test_winding_of_renumbered_triangles),
        cmocka_unit_test(test_permuted_instance_same_surface),
        cmocka_unit_test(test_detector_sees_a_level_mismatch),
        cmocka_unit_test(test_export_obj_closed),
        cmocka_unit_test(test_deviation_target),
        cmocka_unit_test(test_no_cracks_lod_modes),
        cmocka_unit_test(test_no_cracks_across_levels),
    };
    return cmocka_run_group_tests_name("adaptive_cracks", tests, NULL, NULL);
}
