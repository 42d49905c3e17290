/* tests/test_cracks.c -- zero crack pixels, for every patch, level and built-in mesh (docs/design.md, section 6).
 *
 * The detector: every ray through a closed surface crosses it an even number of times.  Each tessellated
 * triangle is drawn with culling off, no depth test and additive blending of 1/255, so a pixel's red channel
 * counts the triangles covering its centre.  With bitwise-identical shared edges and the top-left fill rule every
 * count is even; a crack (a hole between two patches) or a doubly drawn edge pixel makes some count odd.  The
 * assertion is therefore "every count is even", which fails on a single cracked pixel (see
 * test_detector_finds_a_crack, which opens one on purpose).
 *
 * Last-bit differences.  The rasterizer snaps positions to 1/256 pixel, and a shared edge point computed with different
 * last bits by its two triangles (about 1e-6 px apart on this 96x96 target) almost never lands on the other side of a
 * snapping boundary, let alone of a sample: a plain rendering is blind to them.  So every case of test_no_cracks is
 * also drawn, and the primitive-generator grids are drawn only, with a *bit-keyed jitter*: after the patch shader, each
 * vertex's clip position is moved by up to half a pixel in x and y, by an amount hashed from the bits of its oPos (-0
 * counted as +0).  A vertex computed with the same bits by both of its triangles moves the same way on both sides, so
 * the jittered surface is still closed and every count still even (the parity argument holds for any map of the
 * vertices, folds included); a vertex whose bits differ by one ulp gets two unrelated moves, its two copies land about
 * a pixel apart, and the sliver between them covers a sample or two.  So one jittered rendering sees what the plain
 * ones cannot, and test_jitter_sees_one_ulp proves it on a one-ulp disagreement planted in the counting shader.
 *
 * Both shading routes of the device are drawn: the plain view through the shaders' per-vertex entry (`main`, the
 * scalar evaluation of vs/patch.c), the jittered view through their batched entry (the device's fused path hands
 * whole instances to it: vs/batch8.c's 8-lane groups for npatch and smooth with linear normals, including the
 * canonical edge lanes; vs_patch_batch for the others), and a jittered view through `main` too for npatch and
 * smooth, whose per-vertex and batched edge evaluations are different code.
 *
 * Meshes whose vertices have different normals per face at one position (cube-split, cylinder: sharp edges) are
 * crack-free with the patches that need only positions there (flat) or that average the two sides (pn-aen).  The
 * N-Patch, Phong tessellation and Gruen's patches do crack there -- that is seed 001's Fig. 5 and the reason
 * PN-AEN exists -- and test_split_normals_crack_the_npatch asserts it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../cli/run/scene.h"
#include "util/crack.h"

#include "../core/hlsl.h"
enum { SIZE = 96 };

/* How a counting image is drawn. */
typedef enum {
    PLAIN = 0,        /* the patch shader's main, positions as computed */
    JITTER = 1,       /* bit-keyed jitter (see the top of the file) */
    BATCH = 2,        /* through the batched entry (is_vertex_shader.batch) instead of main */
    NUDGE_ONE_ULP = 4 /* (main only) instance 0's edge points one ulp further in clip x: a planted disagreement */
} draw_mode;

/* Vertices shaded through the counting shader's batched entry (so a test can check that it was used). */
static unsigned long long batched_vertices;

/* What every counting vertex gets after the patch shader: colour 1/255, and with c10.y set the jitter: oPos
 * moved by (jx, jy) pixels, each in [-1/2, 1/2), hashed from the bits of oPos.  A function of oPos's bits alone,
 * so equal bits give equal results on both sides of an edge. */
static void count_finish(const is_vs_constants *c, is_vs_output *out)
{
    out->attr[RS_ATTR_COLOR0] = f4(1.0f / 255.0f, 0, 0, 1.0f / 255.0f);
    if (c->c[10].y == 0.0f) return;
    crack_jitter(&out->pos, SIZE);
}

/* The wrapped patch: c10.x selects it, c10.y the jitter, c10.z the one-ulp nudge of instance 0's edge points. */
static void vs_count(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    vs_patch_shader((vs_patch)(int)c->c[10].x)->main(c, in, out);
    if (c->c[10].z != 0.0f && in->texcoord[12].x == 0.0f) {
        float4 b = in->position[0];
        int zeros = (b.x <= 0.0f) + (b.y <= 0.0f) + (b.z <= 0.0f);
        if (zeros == 1) out->pos.x = nextafterf(out->pos.x, INFINITY);
    }
    count_finish(c, out);
}
/* The same through the patch shader's batched entry (every patch shader has one). */
static void vs_count_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                           is_vs_output *out)
{
    const is_vertex_shader *s = vs_patch_shader((vs_patch)(int)c->c[10].x);
    s->batch(c, in, n, live, shared, out);
    for (size_t v = 0; v < n; v++) count_finish(c, &out[v]);
    __atomic_fetch_add(&batched_vertices, (unsigned long long)n, __ATOMIC_RELAXED);
}
static const is_vertex_shader count_shader = {.name = "count", .main = vs_count, .outputs = IS_OUT_COLOR0};
static const is_vertex_shader count_shader_batch = {
    .name = "count-batch", .main = vs_count, .outputs = IS_OUT_COLOR0, .batch = vs_count_batch};

/* Draw the counting image of mesh m with patch p at `level` from (yaw, pitch) as `mode` says; returns the number
 * of pixels with an odd count and fills *covered with the pixels covered at all. */
static long odd_pixels_grid(const is_mesh *m, vs_patch p, core_grid_kind kind, float level, float yaw, float pitch,
                            unsigned mode, long *covered)
{
    scene_opts o;
    scene_opts_default(&o);
    o.patch = p, o.level = level, o.grid = kind, o.yaw = yaw, o.pitch = pitch, o.width = o.height = SIZE, o.msaa = 1;
    o.distance = 2.6f;
    core_grid g;
    assert_int_equal(core_grid_make(kind, o.level, &g), 0);
    is_device *dev = dev_create(SIZE, SIZE, 1, NULL, 0);
    assert_non_null(dev);
    crack_counting_states(dev);
    assert_false((mode & BATCH) && (mode & NUDGE_ONE_ULP)); /* the nudge reads the instance id per vertex */
    float sel[4] = {(float)p, (mode & JITTER) ? 1.0f : 0.0f, (mode & NUDGE_ONE_ULP) ? 1.0f : 0.0f, 0};
    dev_set_vertex_shader_constant_f(dev, 10, sel, 1);
    assert_int_equal(scene_draw(dev, &o, m, &g, (mode & BATCH) ? &count_shader_batch : &count_shader), 0);
    const rs_target *rt = dev_render_target(dev);
    long odd = 0;
    *covered = 0;
    for (int k = 0; k < SIZE * SIZE; k++) {
        unsigned n = rt->color[k] & 0xff;
        odd += n & 1;
        *covered += n != 0;
    }
    dev_destroy(dev);
    core_grid_free(&g);
    return odd;
}

/* The same on the regular grid of an integer level. */
static long odd_pixels(const is_mesh *m, vs_patch p, int level, float yaw, float pitch, unsigned mode, long *covered)
{
    return odd_pixels_grid(m, p, CORE_GRID_REGULAR, (float)level, yaw, pitch, mode, covered);
}

/* Every built-in mesh, every patch (see above for split normals), levels 1..16: no odd count in the plain view
 * (main), the jittered view through the batched entry and, for the two patches whose batched entry is
 * vs/batch8.c's, the jittered view through main. */
static void test_no_cracks(void **state)
{
    static const struct { float yaw, pitch; unsigned mode; bool batch8_only; } views[] = {
        {30.0f, 20.0f, PLAIN, false},
        {-115.0f, -47.0f, JITTER | BATCH, false},
        {-115.0f, -47.0f, JITTER, true},
    };
    const size_t n_views = sizeof views / sizeof views[0];
    long renders = 0, total_covered = 0;
    batched_vertices = 0;
    for (const char *const *name = mesh_builtin_names(); *name; name++) {
        is_mesh m = {0};
        char err[256];
        assert_int_equal(mesh_builtin(*name, &m, err, sizeof err), 0);
        bool split = crack_split_normals(&m);
        for (int p = 0; p < VS_PATCH_COUNT; p++) {
            if (split && p != VS_PATCH_FLAT && p != VS_PATCH_PN_AEN) continue;
            bool b8 = p == VS_PATCH_NPATCH || p == VS_PATCH_SMOOTH;
            for (int level = 1; level <= 16; level++)
                for (size_t v = 0; v < n_views; v++) {
                    if (views[v].batch8_only && !b8) continue;
                    long covered;
                    long odd =
                        odd_pixels(&m, (vs_patch)p, level, views[v].yaw, views[v].pitch, views[v].mode, &covered);
                    if (odd) fprintf(stderr, "cracks: %s %s level %d view %zu (%s%s): %ld odd pixels\n", *name,
                                     vs_patch_name((vs_patch)p), level, v, views[v].mode & JITTER ? "jittered, " : "",
                                     views[v].mode & BATCH ? "batched entry" : "main", odd);
                    assert_int_equal(odd, 0);
                    assert_true(covered > SIZE * SIZE / 10); /* the mesh is really on screen */
                    renders++, total_covered += covered;
                }
        }
        mesh_free(&m);
    }
    assert_true(renders > 0);
    assert_true(batched_vertices > 0); /* the batched entry really ran */
}

/* The jitter sees a one-ulp disagreement on shared edges, which the plain view misses (its count is printed, not
 * asserted: whether one ulp crosses a snapping boundary is luck): instance 0's edge points are moved one ulp in
 * clip x by the counting shader, its neighbours' copies of them are not.  The flat patch, whose edge points do not
 * depend on the canonical order (a*x + b*y is commutative), so that this checks the detector alone. */
static void test_jitter_sees_one_ulp(void **state)
{
    is_mesh m = {0};
    char err[256];
    assert_int_equal(mesh_builtin("sphere", &m, err, sizeof err), 0);
    long covered;
    /* the setting without the nudge is clean */
    assert_int_equal(odd_pixels(&m, VS_PATCH_FLAT, 8, -115.0f, -47.0f, JITTER, &covered), 0);
    long plain = odd_pixels(&m, VS_PATCH_FLAT, 8, -115.0f, -47.0f, PLAIN | NUDGE_ONE_ULP, &covered);
    long jittered = odd_pixels(&m, VS_PATCH_FLAT, 8, -115.0f, -47.0f, JITTER | NUDGE_ONE_ULP, &covered);
    print_message("one ulp on instance 0's edges: %ld odd pixels plain, %ld jittered\n", plain, jittered);
    assert_true(jittered > 0);
    mesh_free(&m);
}

/* The detector can fail: move one vertex of one triangle of the cube off the shared position -> odd pixels. */
static void test_detector_finds_a_crack(void **state)
{
    is_mesh m = {0};
    char err[256];
    assert_int_equal(mesh_builtin("cube-split", &m, err, sizeof err), 0);
    /* cube-split has separate vertices per face: nudging one of them opens the seam along its two edges */
    m.positions[0] = add3(m.positions[0], f3(0.04f, 0.05f, 0.03f));
    long covered;
    long odd = odd_pixels(&m, VS_PATCH_FLAT, 4, 30.0f, 20.0f, PLAIN, &covered);
    assert_true(odd > 0);
    mesh_free(&m);
}

/* Seed 001, Fig. 5: where the cylinder's side (radial normals) meets a cap (axial normals) the two sides of
 * the rim evaluate different edge curves and the N-Patch surface opens; PN-AEN closes it. */
static void test_split_normals_crack_the_npatch(void **state)
{
    is_mesh m = {0};
    char err[256];
    assert_int_equal(mesh_builtin("cylinder", &m, err, sizeof err), 0);
    assert_true(crack_split_normals(&m));
    long covered;
    assert_true(odd_pixels(&m, VS_PATCH_NPATCH, 4, 30.0f, 20.0f, PLAIN, &covered) > 0);
    assert_int_equal(odd_pixels(&m, VS_PATCH_FLAT, 4, 30.0f, 20.0f, PLAIN, &covered), 0);
    assert_int_equal(odd_pixels(&m, VS_PATCH_PN_AEN, 4, 30.0f, 20.0f, PLAIN, &covered), 0);
    mesh_free(&m);
}

/* The primitive-generator grids at fractional levels: no cracks either (welded meshes, every patch), jittered,
 * through the batched entry and main at alternate levels. */
static void test_no_cracks_pg_grids(void **state)
{
    const core_grid_kind kinds[] = {CORE_GRID_PG_EQUAL, CORE_GRID_PG_FRACTIONAL_ODD, CORE_GRID_PG_FRACTIONAL_EVEN};
    const float levels[] = {1.0f, 2.5f, 3.3f, 4.7f, 7.9f};
    const char *meshes[] = {"tetrahedron", "cube", "sphere"};
    for (size_t mi = 0; mi < 3; mi++) {
        is_mesh m = {0};
        char err[256];
        assert_int_equal(mesh_builtin(meshes[mi], &m, err, sizeof err), 0);
        for (int p = 0; p < VS_PATCH_COUNT; p++)
            for (size_t k = 0; k < 3; k++)
                for (size_t l = 0; l < 5; l++) {
                    long covered;
                    long odd = odd_pixels_grid(&m, (vs_patch)p, kinds[k], levels[l], 30.0f, 20.0f,
                                               l % 2 ? JITTER : JITTER | BATCH, &covered);
                    if (odd) fprintf(stderr, "cracks: %s %s grid %d level %g: %ld odd pixels\n", meshes[mi],
                                     vs_patch_name((vs_patch)p), (int)kinds[k], (double)levels[l], odd);
                    assert_int_equal(odd, 0);
                    assert_true(covered > SIZE * SIZE / 10);
                }
        mesh_free(&m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_detector_finds_a_crack),
        cmocka_unit_test(test_split_normals_crack_the_npatch),
        cmocka_unit_test(test_jitter_sees_one_ulp),
        cmocka_unit_test(test_no_cracks),
        cmocka_unit_test(test_no_cracks_pg_grids),
    };
    return cmocka_run_group_tests_name("cracks", tests, NULL, NULL);
}
