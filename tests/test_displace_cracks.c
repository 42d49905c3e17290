/* tests/test_displace_cracks.c -- cracks of --displace (cli/run/displace.c), counted with the crack detector of
 * tests/test_cracks.c (tests/util/crack.h: additive coverage, odd counts are cracks, and the bit-keyed jitter that
 * turns a one-ulp disagreement into a visible one).  The counting shader is the patch shader, then
 * scene_displace_apply (the displacement wrapper's own step), then the count and the jitter.
 *
 * Proven here:
 *  - where texture coordinates are continuous across every edge (the built-ins with one vertex per position:
 *    tetrahedron, cube, octahedron, icosahedron) and the normals agree bitwise on shared edges (linear and
 *    quadratic normals), the displaced surface has no crack: every patch, levels 1..12, plain and jittered,
 *    through the shaders' main and batched entries, on the regular and primitive-generator grids, on the N-patch
 *    mode and CPU paths and with per-edge LOD;
 *  - the detector sees a texture seam: the sphere's texture coordinates are split along its u seam (u and u + 1)
 *    and at its poles, and there the displaced sides part (counted and printed; docs/design.md has the numbers);
 *    with a map that does not vary in u the same sphere has no crack, so the seam's texture coordinates are the
 *    cause;
 *  - real normals differ on the two sides of an edge (the N-Patch's crease), so displacing along them opens the
 *    surface (counted and printed). */
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
enum { PLAIN = 0, JITTER = 1, BATCH = 2 };
#define PI_D 3.14159265358979323846

/* The shader under the displacement: patch c10.x (VS_PATCH_COUNT: the fixed shader of the other paths). */
static const is_vertex_shader *inner(const is_vs_constants *c)
{
    int k = (int)c->c[10].x;
    return k == VS_PATCH_COUNT ? &vs_shader_fixed : vs_patch_shader((vs_patch)k);
}

/* After the displacement: colour 1/255 (the count) and, with c10.y, the jitter. */
static void finish(const is_vs_constants *c, is_vs_output *out)
{
    scene_displace_apply(c, out);
    out->attr[RS_ATTR_COLOR0] = f4(1.0f / 255.0f, 0, 0, 1.0f / 255.0f);
    if (c->c[10].y != 0.0f) crack_jitter(&out->pos, SIZE);
}
static void vs_count(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    inner(c)->main(c, in, out);
    finish(c, out);
}
static void vs_count_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                           is_vs_output *out)
{
    /* the displacement reads TEXCOORD0 and TEXCOORD1: ask the batch for them */
    inner(c)->batch(c, in, n, live | IS_OUT_TEXCOORD(0) | IS_OUT_TEXCOORD(1), shared, out);
    for (size_t v = 0; v < n; v++) finish(c, &out[v]);
}
static const is_vertex_shader count_shader = {.name = "dcount", .main = vs_count, .outputs = IS_OUT_COLOR0};
static const is_vertex_shader count_shader_batch = {
    .name = "dcount-batch", .main = vs_count, .outputs = IS_OUT_COLOR0, .batch = vs_count_batch};

/* A 32x32 grey height map: bumps varying in u and v, or (u_free) in v only. */
static void make_map(is_image *img, bool u_free)
{
    char err[128];
    assert_int_equal(image_alloc(img, 32, 32, "Y", err, sizeof err), 0);
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++)
            img->data[y * 32 + x] = 0.5f + 0.5f * (float)(sin(2.0 * PI_D * y / 8.0) *
                                                         (u_free ? 1.0 : sin(2.0 * PI_D * x / 8.0 + 0.4)));
}

typedef struct view {
    const is_mesh *m;
    vs_patch patch;
    vs_normals normals;
    scene_path path;
    core_grid_kind grid;
    float level;
    tess_lod_mode lod;
    float yaw, pitch;
    unsigned mode;
    float scale;
    const is_image *map;
} view;

/* The counting image of v: the number of pixels with an odd count; *covered gets those covered at all, and
 * *sum (may be NULL) a checksum of the counts (to tell two images apart). */
static long odd_pixels(const view *v, long *covered, uint64_t *sum)
{
    scene_opts o;
    scene_opts_default(&o);
    o.patch = v->patch, o.normals = v->normals, o.path = v->path, o.grid = v->grid, o.level = v->level;
    o.lod = v->lod, o.yaw = v->yaw, o.pitch = v->pitch, o.width = o.height = SIZE, o.msaa = 1, o.distance = 2.6f;
    o.displace = "the test's map", o.displace_map = v->map, o.displace_scale = v->scale;
    if (o.lod != TESS_LOD_UNIFORM) o.max_level = (int)v->level;
    assert_null(scene_check_opts(&o));
    core_grid g;
    assert_int_equal(core_grid_make(v->grid, v->level, &g), 0);
    is_device *dev = dev_create(SIZE, SIZE, 1, NULL, 0);
    crack_counting_states(dev);
    int k = v->path == SCENE_PATH_INSTANCED ? (int)v->patch : VS_PATCH_COUNT;
    float sel[4] = {(float)k, (v->mode & JITTER) ? 1.0f : 0.0f, 0, 0};
    dev_set_vertex_shader_constant_f(dev, 10, sel, 1);
    if (scene_draw(dev, &o, v->m, &g, (v->mode & BATCH) ? &count_shader_batch : &count_shader) != 0)
        fail_msg("%s", dev_last_error(dev));
    const rs_target *rt = dev_render_target(dev);
    long odd = 0;
    uint64_t h = 0;
    *covered = 0;
    for (int p = 0; p < SIZE * SIZE; p++) {
        unsigned n = rt->color[p] & 0xff;
        odd += n & 1, *covered += n != 0, h = h * 31 + n;
    }
    if (sum) *sum = h;
    dev_destroy(dev);
    core_grid_free(&g);
    return odd;
}

/* odd_pixels of v, asserted 0, with a message naming the case; the mesh must be on screen. */
static void expect_closed(const view *v, const char *mesh)
{
    long covered;
    long odd = odd_pixels(v, &covered, NULL);
    if (odd) fail_msg("%s %s normals %s path %d grid %d level %g lod %d mode %u: %ld odd pixels", mesh,
                      vs_patch_name(v->patch), vs_normals_name(v->normals), (int)v->path, (int)v->grid,
                      (double)v->level, (int)v->lod, v->mode, odd);
    assert_true(covered > SIZE * SIZE / 10);
}

static const char *const continuous[] = {"tetrahedron", "cube", "octahedron", "icosahedron"};

/* The displacement really moves the surface (so that "no crack" is not the undisplaced surface's). */
static void test_displacement_moves(void **state)
{
    is_image map = {0};
    make_map(&map, false);
    is_mesh m = {0};
    char err[256];
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);
    view v = {&m, VS_PATCH_SMOOTH, VS_NORMALS_LINEAR, SCENE_PATH_INSTANCED, CORE_GRID_REGULAR, 8, TESS_LOD_UNIFORM,
              30, 20, PLAIN, 0.0f, &map};
    long c0, c1;
    uint64_t s0, s1;
    odd_pixels(&v, &c0, &s0);
    v.scale = 0.15f;
    odd_pixels(&v, &c1, &s1);
    assert_true(s0 != s1);
    assert_true(c1 > c0); /* displaced outwards (heights >= 0): a larger silhouette */
    mesh_free(&m);
    image_free(&map);
}

/* Continuous texture coordinates, linear and quadratic normals: no crack on any patch, level, route. */
static void test_no_cracks_continuous_texcoords(void **state)
{
    is_image map = {0};
    make_map(&map, false);
    static const struct { float yaw, pitch; unsigned mode; } views[] = {
        {30, 20, PLAIN}, {-115, -47, JITTER | BATCH}, {-115, -47, JITTER}};
    const int levels[] = {1, 2, 3, 5, 8, 12};
    for (size_t mi = 0; mi < sizeof continuous / sizeof continuous[0]; mi++) {
        is_mesh m = {0};
        char err[256];
        assert_int_equal(mesh_builtin(continuous[mi], &m, err, sizeof err), 0);
        assert_false(crack_split_normals(&m));
        for (int p = 0; p < VS_PATCH_COUNT; p++)
            for (int nm = VS_NORMALS_LINEAR; nm <= VS_NORMALS_QUADRATIC; nm++)
                for (size_t l = 0; l < sizeof levels / sizeof levels[0]; l++)
                    for (size_t k = 0; k < 3; k++) {
                        view v = {&m, (vs_patch)p, (vs_normals)nm, SCENE_PATH_INSTANCED, CORE_GRID_REGULAR,
                                  (float)levels[l], TESS_LOD_UNIFORM, views[k].yaw, views[k].pitch, views[k].mode,
                                  0.12f, &map};
                        expect_closed(&v, continuous[mi]);
                    }
        mesh_free(&m);
    }
    image_free(&map);
}

/* The same on the other routes: primitive-generator grids at fractional levels, the N-patch mode and CPU paths
 * (npatch and flat: D3D9's fixed-function patches), per-edge LOD. */
static void test_no_cracks_other_routes(void **state)
{
    is_image map = {0};
    make_map(&map, false);
    const core_grid_kind kinds[] = {CORE_GRID_PG_EQUAL, CORE_GRID_PG_FRACTIONAL_ODD, CORE_GRID_PG_FRACTIONAL_EVEN};
    const float levels[] = {2.5f, 4.7f, 7.9f};
    for (size_t mi = 0; mi < sizeof continuous / sizeof continuous[0]; mi++) {
        is_mesh m = {0};
        char err[256];
        assert_int_equal(mesh_builtin(continuous[mi], &m, err, sizeof err), 0);
        for (int p = 0; p < VS_PATCH_COUNT; p++) {
            for (size_t k = 0; k < 3; k++)
                for (size_t l = 0; l < 3; l++) {
                    view v = {&m, (vs_patch)p, VS_NORMALS_LINEAR, SCENE_PATH_INSTANCED, kinds[k], levels[l],
                              TESS_LOD_UNIFORM, -115, -47, l % 2 ? JITTER : JITTER | BATCH, 0.12f, &map};
                    expect_closed(&v, continuous[mi]);
                }
            for (tess_lod_mode lod = TESS_LOD_DISTANCE; lod <= TESS_LOD_SCREEN; lod++) {
                view v = {&m, (vs_patch)p, VS_NORMALS_QUADRATIC, SCENE_PATH_INSTANCED, CORE_GRID_REGULAR, 12, lod,
                          -115, -47, JITTER, 0.12f, &map};
                expect_closed(&v, continuous[mi]);
            }
        }
        const vs_patch fixed[2] = {VS_PATCH_NPATCH, VS_PATCH_FLAT};
        const scene_path paths[2] = {SCENE_PATH_NPATCH_MODE, SCENE_PATH_CPU};
        for (int f = 0; f < 2; f++)
            for (int pa = 0; pa < 2; pa++)
                for (int nm = VS_NORMALS_LINEAR; nm <= VS_NORMALS_QUADRATIC; nm++)
                    for (int level = 1; level <= 9; level += 4) {
                        view v = {&m, fixed[f], (vs_normals)nm, paths[pa], CORE_GRID_REGULAR, (float)level,
                                  TESS_LOD_UNIFORM, -115, -47, JITTER, 0.12f, &map};
                        expect_closed(&v, continuous[mi]);
                    }
        mesh_free(&m);
    }
    image_free(&map);
}

/* The sphere's texture seam: odd pixels where its texture coordinates split, none with a map constant in u. */
static void test_texture_seam_cracks(void **state)
{
    is_image map = {0}, vmap = {0};
    make_map(&map, false);
    make_map(&vmap, true);
    is_mesh m = {0};
    char err[256];
    assert_int_equal(mesh_builtin("sphere", &m, err, sizeof err), 0);
    assert_false(crack_split_normals(&m)); /* its split vertices differ in texture coordinates only */
    long total_plain = 0, total_jitter = 0;
    for (int p = 0; p < VS_PATCH_COUNT; p++) {
        long counts[2][2];
        for (int j = 0; j < 2; j++) {
            long covered;
            view v = {&m, (vs_patch)p, VS_NORMALS_LINEAR, SCENE_PATH_INSTANCED, CORE_GRID_REGULAR, 8,
                      TESS_LOD_UNIFORM, 0, 80, j ? JITTER : PLAIN, 0.12f, &map};
            counts[j][0] = odd_pixels(&v, &covered, NULL);   /* looking down at the north pole and the seam */
            v.pitch = -80;
            counts[j][1] = odd_pixels(&v, &covered, NULL);   /* the south pole */
            v.map = &vmap, v.pitch = 80;
            expect_closed(&v, "sphere, a map constant in u,");
            v.pitch = -80;
            expect_closed(&v, "sphere, a map constant in u,");
        }
        print_message("sphere seam, %-14s level 8, scale 0.12, %dx%d: odd pixels plain %ld + %ld, jittered "
                      "%ld + %ld (north + south)\n", vs_patch_name((vs_patch)p), SIZE, SIZE, counts[0][0],
                      counts[0][1], counts[1][0], counts[1][1]);
        total_plain += counts[0][0] + counts[0][1], total_jitter += counts[1][0] + counts[1][1];
    }
    assert_true(total_plain > 0);   /* the seam opens, visibly */
    assert_true(total_jitter > 0);
    mesh_free(&m);
    image_free(&map);
    image_free(&vmap);
}

/* Real normals: the two sides of an edge have their own derivative normals, so the displaced sides part. */
static void test_real_normals_crack(void **state)
{
    is_image map = {0};
    make_map(&map, false);
    is_mesh m = {0};
    char err[256];
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);
    long npatch = 0;
    for (int p = 0; p < VS_PATCH_COUNT; p++) {
        long covered, c[2];
        for (int j = 0; j < 2; j++) {
            view v = {&m, (vs_patch)p, VS_NORMALS_REAL, SCENE_PATH_INSTANCED, CORE_GRID_REGULAR, 8,
                      TESS_LOD_UNIFORM, 30, 20, j ? JITTER : PLAIN, 0.12f, &map};
            c[j] = odd_pixels(&v, &covered, NULL);
        }
        print_message("cube, real normals, %-14s level 8, scale 0.12, %dx%d: odd pixels plain %ld, jittered %ld\n",
                      vs_patch_name((vs_patch)p), SIZE, SIZE, c[0], c[1]);
        if (p == VS_PATCH_NPATCH) npatch = c[0];
    }
    assert_true(npatch > 0); /* the N-Patch's crease opens */
    mesh_free(&m);
    image_free(&map);
}

/* The wrapper by hand: the flat patch of the triangle (0,0,0), (1,0,0), (0,1,0) with normals (0, 0, -1) and texture
 * coordinates (x, y), a height ramp h(u) = 2u - 1/2 (a 2x1 R32F texture 0, 1, linear, clamped), S = 0.5, a
 * bounding radius r = 2 (the scene's WVP scales by 1 / r; World and View * Proj are identities): at b = (0.4, 0.4,
 * 0.2), the point (0.4, 0.2, 0), h = 0.3, so oPos = P / r + S h (0, 0, -1) = (0.2, 0.1, -0.15, 1); in object space
 * the displaced surface is z = -S r h = -(2x - 1/2), whose normal (-2 S r, 0, -1) / |.| = (-2, 0, -1) / sqrt 5,
 * and the headlight term saturate(dot(N, (0, 0, -1))) = 1 / sqrt 5 scales g_vDiffuse. */
static void test_displaced_wrapper_by_hand(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_texture *t;
    is_locked_rect lr;
    assert_int_equal(dev_create_texture(dev, 2, 1, 1, 0, IS_FMT_R32F, &t), IS_OK);
    assert_int_equal(tex_lock_rect(t, 0, &lr, NULL, 0), IS_OK);
    ((float *)lr.bits)[0] = 0.0f, ((float *)lr.bits)[1] = 1.0f;
    tex_unlock_rect(t, 0);
    static is_vs_constants c;
    memset(&c, 0, sizeof c);
    float4x4 id = mat_identity();
    vs_options vo = vs_default_options();
    float4x4 wvp = mat_scaling(0.5f, 0.5f, 0.5f);
    vs_set_constants(&c, &wvp, &id, f4(0.8f, 0.6f, 0.4f, 1.0f), &vo);
    c.c[12] = f4((float)scene_shader_index(vs_patch_shader(VS_PATCH_FLAT)), 0.5f, 2.0f, 0.0f);
    for (int i = 0; i < 4; i++) c.c[13 + i] = f4(id.m[i][0], id.m[i][1], id.m[i][2], id.m[i][3]);
    c.s[0] = tex_sampler_default(t);
    c.s[0].state[IS_SAMP_MAGFILTER] = c.s[0].state[IS_SAMP_MINFILTER] = IS_TEXF_LINEAR;
    c.s[0].state[IS_SAMP_ADDRESSU] = IS_TADDRESS_CLAMP;
    is_vs_input in;
    for (size_t r = 0; r < sizeof in / sizeof(float4); r++) ((float4 *)&in)[r] = f4(0, 0, 0, 1);
    const float3 v[3] = {f3(0, 0, 0), f3(1, 0, 0), f3(0, 1, 0)};
    in.position[0] = f4(0.4f, 0.4f, 0.2f, 1.0f);
    for (int k = 0; k < 3; k++) {
        in.texcoord[VS_IN_V0 + k] = f4_of(v[k], 1.0f);
        in.texcoord[VS_IN_N0 + k] = f4(0, 0, -1, 1);
        in.texcoord[VS_IN_OPP0 + k] = f4_of(v[(k + 2) % 3], 1.0f);
        in.texcoord[VS_IN_T0 + k] = f4(v[k].x, v[k].y, 0, 1);
    }
    in.texcoord[VS_IN_ID] = f4(0, 0, 0, 1);
    is_vs_output out;
    memset(&out, 0, sizeof out);
    scene_displaced_shader.main(&c, &in, &out);
    const float r5 = 0.4472136f; /* 1 / sqrt 5 */
    assert_true(fabsf(out.pos.x - 0.2f) < 1e-6f && fabsf(out.pos.y - 0.1f) < 1e-6f);
    assert_true(fabsf(out.pos.z + 0.15f) < 1e-6f && out.pos.w == 1.0f);
    float4 n = out.attr[RS_ATTR_TEXCOORD0 + 1];
    if (!(fabsf(n.x + 2 * r5) < 1e-3f && fabsf(n.y) < 1e-3f && fabsf(n.z + r5) < 1e-3f))
        fail_msg("displaced normal (%g, %g, %g), want (-0.8944, 0, -0.4472)", n.x, n.y, n.z);
    float4 col = out.attr[RS_ATTR_COLOR0];
    assert_true(fabsf(col.x - 0.8f * r5) < 1e-3f && fabsf(col.y - 0.6f * r5) < 1e-3f && col.w == 1.0f);
    dev_destroy(dev);
}

/* The angle in degrees between two (interpolated, so not quite unit) normals. */
static double angle_deg(const float *a, const float *b)
{
    double d = (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
    double la = sqrt((double)a[0] * a[0] + (double)a[1] * a[1] + (double)a[2] * a[2]);
    double lb = sqrt((double)b[0] * b[0] + (double)b[1] * b[1] + (double)b[2] * b[2]);
    d /= la * lb;
    return acos(d > 1 ? 1 : d < -1 ? -1 : d) * 180.0 / PI_D;
}

/* The shading normal of a displaced patch (the displaced surface's own, cli/run/displace.c) is, with no height,
 * the patch's real normal: the normal AOVs of the two renders agree within a degree wherever both cover a pixel
 * (two different finite differences for the Gruen patches), and the displaced one differs once the map moves the
 * surface. */
static void test_displaced_normal(void **state)
{
    is_image flat = {0}, map = {0};
    char err[256];
    assert_int_equal(image_alloc(&flat, 4, 4, "Y", err, sizeof err), 0);   /* zero everywhere */
    make_map(&map, false);
    is_mesh m = {0};
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);
    for (int p = VS_PATCH_NPATCH; p <= VS_PATCH_SMOOTH; p++) {
        rs_target *rt[3];
        is_device *dev[3];
        for (int k = 0; k < 3; k++) {
            scene_opts o;
            scene_opts_default(&o);
            o.patch = (vs_patch)p, o.level = 16, o.width = o.height = 64, o.msaa = 1;
            o.normals = k == 0 ? VS_NORMALS_REAL : VS_NORMALS_LINEAR;
            if (k > 0) o.displace = "map", o.displace_map = k == 1 ? &flat : &map;
            core_grid g;
            assert_int_equal(core_grid_make(o.grid, o.level, &g), 0);
            dev[k] = scene_render_view(&o, &m, &g, 1, SCENE_AOV_NORMAL, NULL, err, sizeof err);
            assert_non_null(dev[k]);
            rt[k] = dev_render_target(dev[k]);
            core_grid_free(&g);
        }
        double worst = 0, moved = 0;
        int both = 0, off = 0, off2 = 0;
        for (int q = 0; q < 64 * 64; q++) {
            const float *a = &rt[0]->aov[0].data[3 * q], *b = &rt[1]->aov[0].data[3 * q], *c = &rt[2]->aov[0].data[3 * q];
            if (rt[0]->depth[q] >= 1.0f || rt[1]->depth[q] >= 1.0f) continue;
            double deg = angle_deg(a, b);
            worst = deg > worst ? deg : worst, both++, off += deg > 1.0, off2 += deg > 2.0;
            if (rt[2]->depth[q] < 1.0f) {
                double dm = angle_deg(a, c);
                moved = dm > moved ? dm : moved;
            }
        }
        print_message("%s: displaced-surface normal at height 0 against the real normal: %d of %d pixels more than "
                      "1 degree off, %d more than 2, at most %.2f; with the bumps up to %.1f degrees off\n",
                      vs_patch_name((vs_patch)p), off, both, off2, worst, moved);
        assert_true(both > 1000);
        assert_true(worst < 1.0);
        assert_true(moved > 20.0);
        for (int k = 0; k < 3; k++) dev_destroy(dev[k]);
    }
    mesh_free(&m);
    image_free(&flat);
    image_free(&map);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_displacement_moves),
        cmocka_unit_test(test_displaced_normal),
        cmocka_unit_test(test_displaced_wrapper_by_hand),
        cmocka_unit_test(test_texture_seam_cracks),
        cmocka_unit_test(test_real_normals_crack),
        cmocka_unit_test(test_no_cracks_continuous_texcoords),
        cmocka_unit_test(test_no_cracks_other_routes),
    };
    return cmocka_run_group_tests_name("displace-cracks", tests, NULL, NULL);
}
