/* tests/test_numerics.c -- numerical edge cases of the patch shaders, rendered through the device:
 * barycentrics exactly at corners and on edges (and -0.0, denormals, a hair outside the triangle),
 * Gregory 0/0, nearly parallel and exactly opposite normals, zero / NaN / in-plane normals handed straight to
 * the shader, degenerate and folded triangles, neighbours folded back onto the triangle, and vertices behind the
 * eye, on the eye plane (w = 0) and on the near plane (z = 0).  For every patch, normal mode and a few grids:
 * each vertex the shader writes is finite (or its triangle is dropped by the rasterizer, which drops
 * non-finite positions), and every depth, colour and AOV value of the render is finite and in range. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../cli/run/scene.h"
#include "../core/hlsl.h"
#include "../vs/vs_internal.h"  /* vs_finite3 */

#define SIDE 64

/* A camera at (0, 0, -3) looking at the origin, 45 degrees, near 0.5, far 10. */
static float4x4 camera(void)
{
    float4x4 view = mat_look_at_lh(f3(0, 0, -3), f3(0, 0, 0), f3(0, 1, 0));
    float4x4 proj = mat_perspective_fov_lh(3.14159265f / 4.0f, 1.0f, 0.5f, 10.0f);
    return mat_mul(&view, &proj);
}

/* One instance: corners v, normals n (used as given: no normalisation), opposite vertices opp (NULL: own
 * third vertices, i.e. boundary edges). */
static is_patch_instance instance(const float3 v[3], const float3 n[3], const float3 *opp)
{
    is_patch_instance t;
    memset(&t, 0, sizeof t);
    for (int k = 0; k < 3; k++) {
        t.v[k] = v[k], t.n[k] = n[k];
        t.opp[k] = opp ? opp[k] : v[(k + 2) % 3];
        t.t[k] = f2((float)k, 1.0f - (float)k);
    }
    return t;
}

/* Whether every component of a float4 is finite. */
static bool finite4(float4 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z) && isfinite(v.w); }

/* Evaluate shader vs at each point b[0..n) of inst: a vertex must be all finite, or have a non-finite position
 * (then the rasterizer drops its triangles); its colour and AOVs are finite whenever its position is.  Returns
 * the number of vertices with a non-finite position. */
static int check_vertices(const is_vertex_shader *vs, const is_vs_constants *c, const is_patch_instance *inst,
                          const float3 *b, size_t n, const char *what)
{
    int dropped = 0;
    for (size_t k = 0; k < n; k++) {
        is_vs_input in;
        is_vs_output out;
        tess_input_from_instance(inst, NULL, b[k], &in);
        memset(&out, 0, sizeof out);
        vs->main(c, &in, &out);
        if (!finite4(out.pos)) { dropped++; continue; }
        for (int a = 0; a < RS_MAX_ATTR; a++)
            if (!finite4(out.attr[a]))
                fail_msg("%s, %s: b = (%g, %g, %g): output %d is (%g, %g, %g, %g)", what, vs->name, (double)b[k].x,
                         (double)b[k].y, (double)b[k].z, a, (double)out.attr[a].x, (double)out.attr[a].y,
                         (double)out.attr[a].z, (double)out.attr[a].w);
    }
    return dropped;
}

/* Draw n instances with patch p, normals nm and grid (kind, level) through the device (cull none, 1 sample, AOVs
 * normal, bary, gregory) and check every depth and AOV value; returns the triangles drawn. */
static uint64_t draw_checked(const is_patch_instance *inst, size_t n, vs_patch p, vs_normals nm, core_grid_kind kind,
                             float level, const float4x4 *wvp, const char *what)
{
    core_grid g;
    assert_int_equal(core_grid_make(kind, level, &g), 0);
    is_device *dev = dev_create(SIDE, SIDE, 1, NULL, 0);
    assert_non_null(dev);
    dev_set_threads(dev, 1);
    rs_target *rt = dev_render_target(dev);
    const int slots[3] = {1, 2, 4}, comps[3] = {3, 3, 3};
    for (int a = 0; a < 3; a++) assert_int_equal(rs_target_add_aov(rt, RS_ATTR_TEXCOORD0 + slots[a], comps[a]), 0);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
    dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE);
    is_vertex_buffer *vb0, *vb1;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
    assert_int_equal(dev_create_vertex_buffer(dev, g.n_points * sizeof(float3), &vb0), IS_OK);
    assert_int_equal(dev_create_vertex_buffer(dev, n * sizeof(is_patch_instance), &vb1), IS_OK);
    assert_int_equal(dev_create_index_buffer(dev, 3 * g.n_triangles * 4, IS_FMT_INDEX32, &ib), IS_OK);
    assert_int_equal(dev_create_vertex_declaration(dev, mesh_patch_declaration, &decl), IS_OK);
    memcpy(vb_lock(vb0), g.bary, g.n_points * sizeof(float3));
    memcpy(vb_lock(vb1), inst, n * sizeof(is_patch_instance));
    memcpy(ib_lock(ib), g.idx, 3 * g.n_triangles * 4);
    dev_set_vertex_declaration(dev, decl);
    dev_set_stream_source(dev, 0, vb0, 0, sizeof(float3));
    dev_set_stream_source(dev, 1, vb1, 0, sizeof(is_patch_instance));
    dev_set_indices(dev, ib);
    dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | (uint32_t)n);
    dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1u);
    const is_vertex_shader *vs = vs_patch_shader(p);
    dev_set_vertex_shader(dev, vs);
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    vs_options o = vs_default_options();
    o.normals = nm;
    float4x4 world = mat_identity();
    vs_set_constants(&c, wvp, &world, f4(0.8f, 0.7f, 0.6f, 1.0f), &o);
    dev_set_vertex_shader_constant_f(dev, 0, &c.c[0].x, VS_C_COUNT);
    for (size_t t = 0; t < n; t++) check_vertices(vs, &c, &inst[t], g.bary, g.n_points, what);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, (unsigned)g.n_points, 0,
                                                (unsigned)g.n_triangles), IS_OK);
    rt = dev_render_target(dev); /* again after the draw: it flushes the deferred clear of untouched tiles */
    for (size_t k = 0; k < (size_t)SIDE * SIDE; k++) {
        float z = rt->depth[k];
        if (!(z >= 0.0f && z <= 1.0f)) fail_msg("%s, %s: depth %g at pixel %zu", what, vs->name, (double)z, k);
        for (int a = 0; a < rt->n_aov; a++)
            for (int j = 0; j < rt->aov[a].comps; j++)
                if (!isfinite(rt->aov[a].data[k * rt->aov[a].comps + j]))
                    fail_msg("%s, %s: AOV %d not finite at pixel %zu", what, vs->name, a, k);
    }
    uint64_t drawn = dev_stats(dev)->prims_drawn;
    vb_release(vb0), vb_release(vb1), ib_release(ib), decl_release(decl);
    dev_destroy(dev);
    core_grid_free(&g);
    return drawn;
}

/* Every patch, normal mode and grid on the instances; returns the fewest triangles any of them drew. */
static uint64_t draw_all(const is_patch_instance *inst, size_t n, const float4x4 *wvp, const char *what)
{
    const struct { core_grid_kind kind; float level; } grids[] = {
        {CORE_GRID_REGULAR, 1}, {CORE_GRID_REGULAR, 4}, {CORE_GRID_PG_FRACTIONAL_ODD, 2.7f},
        {CORE_GRID_PG_FRACTIONAL_EVEN, 5.3f}};
    uint64_t least = UINT64_MAX;
    for (int p = 0; p < VS_PATCH_COUNT; p++)
        for (int nm = 0; nm < 3; nm++)
            for (size_t gi = 0; gi < sizeof grids / sizeof grids[0]; gi++) {
                uint64_t d = draw_checked(inst, n, (vs_patch)p, (vs_normals)nm, grids[gi].kind, grids[gi].level, wvp,
                                          what);
                if (d < least) least = d;
            }
    return least;
}

static const float3 tri_v[3] = {{-1, -0.8f, 0}, {0, 1, 0.2f}, {1, -0.8f, 0}};

/* Barycentrics exactly at corners, on edges, -0.0, denormal and a hair outside: finite outputs, and the
 * Gregory weights at a corner (0/0 in the listing) are finite and sum to 1. */
static void test_exact_barycentrics(void **state)
{
    (void)state;
    const float3 n[3] = {{-0.6f, -0.3f, -0.74f}, {0, 0.6f, -0.8f}, {0.6f, -0.3f, -0.74f}};
    is_patch_instance t = instance(tri_v, n, NULL);
    const float d = 1e-45f, h = 1e-8f;
    const float3 b[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5f, 0.5f, 0}, {0, 0.5f, 0.5f}, {0.5f, 0, 0.5f},
                        {-0.0f, 1, 0}, {1, -0.0f, -0.0f}, {0.5f, -0.0f, 0.5f}, {1 - d, d, 0}, {d, d, 1}, {d, 1, d},
                        {1.0f / 3, 1.0f / 3, 1.0f / 3}, {-h, 0.5f, 0.5f + h}, {1 + h, -h, 0}, {0.25f, 0.75f, -0.0f}};
    float4x4 wvp = camera();
    for (int p = 0; p < VS_PATCH_COUNT; p++)
        for (int nm = 0; nm < 3; nm++) {
            is_vs_constants c;
            memset(&c, 0, sizeof c);
            vs_options o = vs_default_options();
            o.normals = (vs_normals)nm;
            float4x4 world = mat_identity();
            vs_set_constants(&c, &wvp, &world, f4(1, 1, 1, 1), &o);
            assert_int_equal(check_vertices(vs_patch_shader((vs_patch)p), &c, &t, b, sizeof b / sizeof b[0],
                                            "exact barycentrics"), 0);
        }
    for (size_t k = 0; k < sizeof b / sizeof b[0]; k++) {
        float3 g = vs_gregory(b[k]);
        assert_true(vs_finite3(g));
        if (b[k].x >= 0 && b[k].y >= 0 && b[k].z >= 0) assert_float_equal(g.x + g.y + g.z, 1.0f, 1e-5);
    }
    assert_true(draw_all(&t, 1, &wvp, "exact barycentrics") > 0);
}

/* Normals nearly parallel, exactly opposite, in the triangle's plane, zero and NaN, handed to the shader as
 * they are (mesh_create would have replaced the last two). */
static void test_normals(void **state)
{
    (void)state;
    const float e = 1e-7f;
    const struct { const char *what; float3 n[3]; bool must_draw; } cases[] = {
        {"nearly parallel", {{0, 0, -1}, {e, 0, -1}, {0, e, -1}}, true},
        {"exactly opposite", {{0, 0, -1}, {0, 0, 1}, {0, 0, -1}}, true},
        {"all opposite pairs", {{0.6f, 0, -0.8f}, {-0.6f, 0, 0.8f}, {0, 1, 0}}, true},
        {"in the plane", {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}}, true},
        {"zero", {{0, 0, 0}, {0, 0, 0}, {0, 0, -1}}, true},
        {"all zero", {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, true},
        {"NaN", {{NAN, 0, 0}, {0, 0, -1}, {0, 0, -1}}, false},
        {"infinite", {{INFINITY, 0, 0}, {0, 0, -1}, {0, -INFINITY, 0}}, false},
        {"huge", {{1e30f, 0, -1e30f}, {0, 0, -1e38f}, {0, 3e38f, 0}}, true},
        {"tiny", {{1e-30f, 0, -1e-30f}, {0, 0, -1e-38f}, {0, 1e-45f, 0}}, true},
    };
    float4x4 wvp = camera();
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        is_patch_instance t = instance(tri_v, cases[k].n, NULL);
        uint64_t drawn = draw_all(&t, 1, &wvp, cases[k].what);
        print_message("  normals %-20s: at least %llu triangles drawn\n", cases[k].what, (unsigned long long)drawn);
        if (cases[k].must_draw) assert_true(drawn > 0);
    }
}

/* Degenerate triangles (a point, collinear, two equal corners), a folded pair and neighbours folded back onto
 * the triangle (fn = |dot| = 1), a needle and a very flat sliver. */
static void test_degenerate_and_folded(void **state)
{
    (void)state;
    const float3 n[3] = {{0, 0, -1}, {0, 0.6f, -0.8f}, {0.6f, 0, -0.8f}};
    const float3 point[3] = {{0.1f, 0.1f, 0}, {0.1f, 0.1f, 0}, {0.1f, 0.1f, 0}};
    const float3 line[3] = {{-1, 0, 0}, {0, 0, 0}, {1, 0, 0}};
    const float3 twice[3] = {{-1, 0, 0}, {-1, 0, 0}, {1, 1, 0}};
    const float3 needle[3] = {{-1, 0, 0}, {1, 1e-6f, 0}, {1, -1e-6f, 0}};
    const float3 sliver[3] = {{-1, 0, 0}, {0, 1e-7f, 0}, {1, 0, 0}};
    const float3 *tris[] = {point, line, twice, needle, sliver};
    const char *names[] = {"point", "collinear", "repeated corner", "needle", "sliver"};
    float4x4 wvp = camera();
    for (size_t k = 0; k < 5; k++) {
        is_patch_instance t = instance(tris[k], n, NULL);
        draw_all(&t, 1, &wvp, names[k]);
    }
    /* folded: the neighbour across each edge is the own third vertex mirrored through the edge's plane, i.e. the
     * neighbour lies folded back onto this triangle */
    float3 opp[3];
    for (int e = 0; e < 3; e++) opp[e] = tri_v[(e + 2) % 3];
    opp[0] = add3(tri_v[2], f3(0, 0, 1e-6f));
    is_patch_instance folded[2] = {instance(tri_v, n, opp), instance(tri_v, n, opp)};
    const float3 back[3] = {tri_v[1], tri_v[0], tri_v[2]};
    const float3 nb[3] = {n[1], n[0], n[2]};
    folded[1] = instance(back, nb, NULL);
    assert_true(draw_all(folded, 2, &wvp, "folded pair") > 0);
    /* the same through mesh_create and the scene: a two-sided sheet (two triangles on the same corners) */
    const float3 p[3] = {{-1, -1, 0}, {0, 1, 0}, {1, -1, 0}};
    const uint32_t idx[6] = {0, 1, 2, 1, 0, 2};
    is_mesh_data d = {3, 2, p, NULL, NULL, idx};
    is_mesh m;
    char err[512];
    assert_int_equal(mesh_create(&m, "sheet", &d, NULL, err, sizeof err), 0);
    for (int pt = 0; pt < VS_PATCH_COUNT; pt++) {
        scene_opts o;
        scene_opts_default(&o);
        o.width = o.height = SIDE, o.patch = (vs_patch)pt, o.level = 4, o.msaa = 1, o.threads = 1;
        o.aovs = SCENE_AOV_NORMAL | SCENE_AOV_BARY | SCENE_AOV_GREGORY;
        is_image img = {0};
        assert_int_equal(scene_render_mesh(&o, &m, &img, NULL, err, sizeof err), 0);
        long covered = 0;
        for (long k = 0; k < (long)SIDE * SIDE; k++) {
            for (int ch = 0; ch < img.channels; ch++) assert_true(isfinite(img.data[k * img.channels + ch]));
            covered += img.data[k * img.channels + 4] < 1.0f;
        }
        assert_true(covered > 100);
        image_free(&img);
    }
    mesh_free(&m);
}

/* Vertices behind the eye (w < 0), on the eye plane (w = 0 exactly) and on the near plane (z = 0 exactly):
 * clipped, finite depth in [0, 1], never a NaN pixel. */
static void test_behind_the_eye(void **state)
{
    (void)state;
    /* the camera at z = -3, near plane at z = -2.5: */
    const float3 cases[][3] = {
        {{-1, -1, 0}, {0, 1, -5}, {1, -1, 0}},            /* one corner behind the eye */
        {{-1, -1, -6}, {0, 1, -5}, {1, -1, 0}},           /* two behind */
        {{-1, -1, -6}, {0, 1, -5}, {1, -1, -7}},          /* all behind */
        {{-1, -1, -3}, {0, 1, 0}, {1, -1, 0}},            /* one on the eye plane: w = 0 */
        {{-1, -1, -3}, {0, 1, -3}, {1, -1, -3}},          /* all on the eye plane */
        {{-1, -1, -2.5f}, {0, 1, 0}, {1, -1, -2.5f}},     /* two on the near plane: z = 0 */
        {{0, 0, -3}, {0.5f, 1, 1}, {1, -1, 1}},           /* a corner at the eye itself */
    };
    const float3 n[3] = {{0, 0, -1}, {0, 0.6f, -0.8f}, {0.6f, 0, -0.8f}};
    float4x4 wvp = camera();
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        is_patch_instance t = instance(cases[k], n, NULL);
        char what[64];
        snprintf(what, sizeof what, "eye case %zu", k);
        uint64_t drawn = draw_all(&t, 1, &wvp, what);
        print_message("  %s: at least %llu triangles drawn\n", what, (unsigned long long)drawn);
    }
    /* the whole scene with the camera inside the mesh's bounding sphere is not possible (--distance > 1); the
     * closest camera still draws a finite image */
    is_mesh m;
    char err[512];
    assert_int_equal(mesh_builtin("sphere", &m, err, sizeof err), 0);
    scene_opts o;
    scene_opts_default(&o);
    o.width = o.height = SIDE, o.distance = 1.01f, o.level = 6, o.msaa = 1, o.threads = 1;
    o.aovs = SCENE_AOV_NORMAL | SCENE_AOV_BARY | SCENE_AOV_GREGORY;
    is_image img = {0};
    assert_int_equal(scene_render_mesh(&o, &m, &img, NULL, err, sizeof err), 0);
    for (long k = 0; k < (long)SIDE * SIDE * img.channels; k++) assert_true(isfinite(img.data[k]));
    image_free(&img);
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact_barycentrics),
        cmocka_unit_test(test_normals),
        cmocka_unit_test(test_degenerate_and_folded),
        cmocka_unit_test(test_behind_the_eye),
    };
    return cmocka_run_group_tests_name("numerics", tests, NULL, NULL);
}
