/* tests/test_shading.c -- --shading pixel (cli/run/shading.c): each pixel's colour is the patch's own normal at
 * the pixel's barycentrics, lit.  The pipeline inspector gives, for every fragment, the barycentrics at the pixel
 * centre and each grid vertex's b and registers; the test interpolates b itself, evaluates the patch normal with
 * vs_patch_eval from the recorded registers, lights it with the listing's headlight written out here, and compares
 * with the pixel (within one 8-bit step: the rasterizer interpolates in its own float order).  Also: the per-vertex
 * path is what the listings draw (the pixel path differs from it where the normal bends inside a grid triangle),
 * and the combinations --shading pixel refuses. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../cli/run/scene.h"
#include "util/prog.h"

#define W 128
#define H 128

/* Render builtin `name` with patch p, normals nm, --shading s at level 3, recording pixel (x, y) (rec may be NULL). */
static is_device *render(const char *name, vs_patch p, vs_normals nm, scene_shading s, is_inspect *rec, int x, int y)
{
    char err[512];
    scene_opts o;
    scene_opts_default(&o);
    o.width = W, o.height = H, o.level = 3, o.patch = p, o.normals = nm, o.msaa = 1, o.shading = s;
    is_mesh m;
    core_grid g;
    assert_int_equal(mesh_builtin(name, &m, err, sizeof err), 0);
    assert_int_equal(core_grid_make(o.grid, o.level, &g), 0);
    is_device *dev = scene_create_device(&o, 1, 0, err, sizeof err);
    assert_non_null(dev);
    if (rec) assert_int_equal(dev_inspect_begin(dev, x, y, rec), IS_OK);
    assert_int_equal(scene_render_on(dev, &o, &m, &g, NULL, err, sizeof err), 0);
    if (rec) dev_inspect_end(dev);
    mesh_free(&m);
    core_grid_free(&g);
    return dev;
}

/* 8-bit channel of c, as the target rounds it. */
static int to8(float c) { return (int)(fminf(fmaxf(c, 0.0f), 1.0f) * 255.0f + 0.5f); }

/* Every covered pixel of a grid of pixels is the patch normal at its barycentrics, lit by the headlight. */
static void check_patch(const char *name, vs_patch p, vs_normals nm)
{
    int checked = 0;
    for (int y = 8; y < H; y += 9)
        for (int x = 6; x < W; x += 9) {
            is_inspect rec = {0};
            is_device *dev = render(name, p, nm, SCENE_SHADING_PIXEL, &rec, x, y);
            float c[4 * 12];
            assert_int_equal(dev_get_vertex_shader_constant_f(dev, 0, c, 12), IS_OK);
            for (size_t f = 0; f < rec.n_fragments; f++) {
                const is_inspect_fragment *fr = &rec.fragments[f];
                if (!fr->passed) continue;
                float3 b = {0, 0, 0};
                for (int k = 0; k < 3; k++) {
                    rs_vec4 bk = fr->v[k].out.attr[RS_ATTR_TEXCOORD0 + VS_OUT_BARY];
                    b.x += fr->bary[k] * bk.x, b.y += fr->bary[k] * bk.y, b.z += fr->bary[k] * bk.z;
                }
                float s = b.x + b.y + b.z;
                b = (float3){b.x / s, b.y / s, b.z / s};
                const is_vs_input in = fr->v[0].regs;
                vs_triangle tri;
                vs_triangle_from_input(&in, &tri);
                vs_options o = vs_options_from_register((float4){c[36], c[37], c[38], c[39]});
                float3 n;
                vs_patch_eval(p, &tri, b, &o, NULL, &n, NULL);
                /* Normal = mul(n, (float3x3)World), rows c4..c6; headlight saturate(dot(Normal, (0, 0, -1))) * c8 */
                float nz = n.x * c[4 * 4 + 2] + n.y * c[5 * 4 + 2] + n.z * c[6 * 4 + 2];
                float l = fminf(fmaxf(-nz, 0.0f), 1.0f);
                uint32_t px = fr->color_after;
                for (int ch = 0; ch < 3; ch++) {
                    int want = to8(c[8 * 4 + ch] * l), got = (int)((px >> (8 * ch)) & 0xffu);
                    if (abs(want - got) > 1)
                        fail_msg("%s pixel (%d, %d) channel %d: %d, the patch normal lit gives %d", name, x, y, ch,
                                 got, want);
                }
                checked++;
            }
            is_inspect_free(&rec);
            dev_destroy(dev);
        }
    assert_true(checked > 40);
}

static void test_npatch_real(void **state)
{
    (void)state;
    check_patch("cube", VS_PATCH_NPATCH, VS_NORMALS_REAL);
}

static void test_smooth_linear(void **state)
{
    (void)state;
    check_patch("sphere", VS_PATCH_SMOOTH, VS_NORMALS_LINEAR);
}

/* Per pixel differs from per vertex (the normal bends inside the grid triangles at level 3), and per vertex is the
 * default: the listings' image. */
static void test_differs_from_vertex(void **state)
{
    (void)state;
    is_device *v = render("cube", VS_PATCH_NPATCH, VS_NORMALS_REAL, SCENE_SHADING_VERTEX, NULL, 0, 0);
    is_device *p = render("cube", VS_PATCH_NPATCH, VS_NORMALS_REAL, SCENE_SHADING_PIXEL, NULL, 0, 0);
    const rs_target *a = dev_render_target(v), *b = dev_render_target(p);
    int differ = 0;
    for (int k = 0; k < W * H; k++) differ += a->color[k] != b->color[k];
    assert_true(differ > W * H / 20);
    assert_memory_equal(a->depth, b->depth, (size_t)W * H * 4);   /* the same surface: only the light moved */
    dev_destroy(v);
    dev_destroy(p);
}

/* The combinations it refuses, with the reason. */
static void test_refused(void **state)
{
    (void)state;
    char dir[256], path[512];
    assert_int_equal(prog_mkdtemp(dir, "shading"), 0);
    const char *err;
    const char *bad[] = {"--path cpu --patch npatch", "--lod screen", "--displace tests/data/textures/bumps.png",
                         "--shading texel"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        assert_int_equal(prog_run(dir, &err, "", "cube --shading pixel %s -o %s", bad[k],
                                  prog_path(dir, "x.png", path, sizeof path)), 2);
        assert_non_null(strstr(err, "--shading"));
        assert_false(prog_exists(dir, "x.png"));
    }
    prog_rmdir(dir);
}

/* --texture: a texture of one colour t multiplies every pixel by t (within an 8-bit step), per vertex and per
 * pixel; a missing file is refused by name before anything is written. */
static void test_texture(void **state)
{
    (void)state;
    char dir[256], tpath[512], a[512], b[512];
    assert_int_equal(prog_mkdtemp(dir, "texture"), 0);
    is_image t;
    char err[256];
    assert_int_equal(image_alloc(&t, 4, 4, "R,G,B,A", err, sizeof err), 0);
    for (int p = 0; p < 16; p++) t.data[4 * p] = 0.4f, t.data[4 * p + 1] = 1.0f, t.data[4 * p + 2] = 0.2f, t.data[4 * p + 3] = 1;
    assert_int_equal(image_write(&t, prog_path(dir, "t.png", tpath, sizeof tpath), NULL, err, sizeof err), 0);
    image_free(&t);
    const float k[3] = {102.0f / 255, 1.0f, 51.0f / 255};   /* the PNG's 8-bit values */
    const char *shadings[] = {"vertex", "pixel"};
    for (int s = 0; s < 2; s++) {
        const char *e;
        assert_int_equal(prog_run(dir, &e, "", "sphere --level 3 --size 64x64 --msaa 1 --shading %s -q -o %s",
                                  shadings[s], prog_path(dir, "a.png", a, sizeof a)), 0);
        assert_int_equal(prog_run(dir, &e, "", "sphere --level 3 --size 64x64 --msaa 1 --shading %s --texture %s -q -o %s",
                                  shadings[s], tpath, prog_path(dir, "b.png", b, sizeof b)), 0);
        is_image ia, ib;
        assert_int_equal(image_read(&ia, a, err, sizeof err), 0);
        assert_int_equal(image_read(&ib, b, err, sizeof err), 0);
        int lit = 0;
        for (int p = 0; p < 64 * 64; p++) {
            const float *pa = ia.data + p * ia.channels, *pb = ib.data + p * ib.channels;
            if (lrintf(pa[0] * 255) == 0x2e && lrintf(pa[1] * 255) == 0x34 && lrintf(pa[2] * 255) == 0x40)
                continue;   /* the background (--msaa 1: no edge pixel mixes it in) */
            for (int c = 0; c < 3; c++)
                if (fabsf(pa[c] * k[c] - pb[c]) > 1.5f / 255)
                    fail_msg("pixel %d channel %d: %g * %g != %g", p, c, pa[c], k[c], pb[c]);
            lit++;
        }
        assert_true(lit > 1000);
        image_free(&ia);
        image_free(&ib);
    }
    const char *e;
    assert_int_equal(prog_run(dir, &e, "", "cube --texture %s/none.png -q -o %s", dir, prog_path(dir, "c.png", a, sizeof a)), 1);
    assert_non_null(strstr(e, "none.png"));
    assert_false(prog_exists(dir, "c.png"));
    prog_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_npatch_real),
        cmocka_unit_test(test_smooth_linear),
        cmocka_unit_test(test_differs_from_vertex),
        cmocka_unit_test(test_refused),
        cmocka_unit_test(test_texture),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
