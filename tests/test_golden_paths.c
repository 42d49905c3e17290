/* tests/test_golden_paths.c -- golden images of the batched shading paths: the cube, the icosahedron and the
 * sphere with the N-Patch, both Gruen patches, Phong tessellation and PN-AEN, with linear and quadratic normals,
 * rendered through the scene layer (scene_render_mesh, the instanced path) and compared with
 * tests/golden/batch-<mesh>-<patch>-<normals>.png.
 *
 * Why: every shaded figure golden lights derivative ("real") normals, which the patch shaders evaluate one vertex
 * at a time, and tests/test_paths.c's goldens (which do take the 8 lanes) show two meshes, two patches, one level
 * and no AOV.  vs/batch8.c's 8-lane groups run only where all of these hold: the device is off the reference path
 * (scene_render_mesh's devices are), the shader's batched entry is vs_npatch_batch or vs_smooth_batch (the npatch
 * and smooth patches on the instanced path; the device's fused path hands it whole instances), the normal mode is
 * linear, and the vertex is inside its triangle (interior lanes: npatch8 / smooth8) or on an edge whose two ends
 * differ in position or normal bits (edge lanes: the canonical border curve); corners, quadratic and real normals
 * and the fallbacks go through the per-vertex evaluation.  So the npatch and smooth images with linear normals
 * are the ones drawn by the 8 lanes (test_batch8_route checks those conditions); the other patches
 * (vs_patch_batch) and quadratic normals (batch8's per-vertex route) are drawn by the scalar evaluation under the
 * same batched entries, and pin down the rest of the table.
 *
 * Each image is four 96x96 tiles side by side, one camera (the scene's default view):
 *   1. level 4, solid + wireframe overlay (the overlay puts every tessellated vertex's position on screen),
 *   2. level 9, solid, 4x MSAA (the lit colour: COLOR0 of the linear or quadratic normal; the silhouette),
 *   3. level 9, the normal AOV (TEXCOORD1) as colour 0.5 + 0.5 n,
 *   4. level 9, the Gregory-weight AOV (TEXCOORD4) as colour (zero but for the Gruen patches).
 * Tiles 3 and 4 come from the scene's AOV pass, where the shader must also compute TEXCOORD1..4 (the 8-lane
 * groups compute only the outputs the draw reads).
 *
 * Thresholds: none.  The images must be the same bytes: the build configuration fixes the arithmetic (-O2
 * -march=x86-64-v3 -ffp-contract=off: no FMA contraction, no instruction beyond AVX2, so an AVX-512 machine runs
 * the same instructions as an AVX2 one); the device gives the same bytes for any thread count; the tiles are 8-bit
 * values.  The only inputs from outside the build are libm's sinf / cosf / tanf of the camera, the same on every
 * x86-64-v3 CPU for one glibc.  (Checked: the same bytes with 1, 2 and 3 threads, and from the clang -O1
 * ASan + UBSan build of `make sanitize`.)
 *
 * INSTESS_REGENERATE_GOLDENS=1 rewrites the goldens (INSTESS_GOLDENS_ONLY=batch-cube-smooth-linear,... only
 * those); tests/failures/ gets the actual image and a diff of a failing one. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "../cli/run/scene.h"
#include "../vs/vs_internal.h" /* vs_npatch_batch, vs_smooth_batch */
#include "util/golden.h"

enum { TILE = 96, TILES = 4 };

static const char *const meshes[] = {"cube", "icosahedron", "sphere"};
static const vs_patch patches[] = {VS_PATCH_NPATCH, VS_PATCH_SMOOTH_INITIAL, VS_PATCH_SMOOTH, VS_PATCH_PHONG,
                                   VS_PATCH_PN_AEN};
static const vs_normals normal_modes[] = {VS_NORMALS_LINEAR, VS_NORMALS_QUADRATIC};

/* Render mesh m with patch p, normals nm at `level` (fill, AOVs) into img (RGBA, Z, AOVs), asserting success. */
static void render(const is_mesh *m, vs_patch p, vs_normals nm, int level, scene_fill fill, unsigned aovs,
                   is_image *img)
{
    scene_opts o;
    scene_opts_default(&o);
    o.width = o.height = TILE, o.patch = p, o.normals = nm, o.level = (float)level, o.fill = fill, o.aovs = aovs;
    char err[512] = "";
    memset(img, 0, sizeof *img);
    int rc = scene_render_mesh(&o, m, img, NULL, err, sizeof err);
    if (rc) fprintf(stderr, "golden paths: %s: render failed: %s\n", m->name, err);
    assert_int_equal(rc, 0);
}

/* Copy channels ch[0..3) of src (a TILE x TILE render; -1: 0) through v -> a * v + b, and alpha 1, into tile t
 * of dst. */
static void put_tile(is_image *dst, int t, const is_image *src, const int ch[3], float a, float b)
{
    assert_int_equal(src->width, TILE);
    assert_int_equal(src->height, TILE);
    for (int y = 0; y < TILE; y++)
        for (int x = 0; x < TILE; x++) {
            const float *s = &src->data[((size_t)y * TILE + x) * src->channels];
            float *d = &dst->data[((size_t)y * dst->width + (size_t)t * TILE + x) * dst->channels];
            for (int c = 0; c < 3; c++) d[c] = ch[c] < 0 ? 0.0f : a * s[ch[c]] + b;
            d[3] = 1.0f;
        }
}

/* The channel indices of three named channels of img (asserting they exist). */
static void channels(const is_image *img, const char *a, const char *b, const char *c, int ch[3])
{
    const char *names[3] = {a, b, c};
    for (int k = 0; k < 3; k++) {
        ch[k] = image_channel_index(img, names[k]);
        assert_true(ch[k] >= 0);
    }
}

/* The four tiles of (mesh, patch, normals) into img. */
static void compose(const is_mesh *m, vs_patch p, vs_normals nm, is_image *img)
{
    char err[256];
    assert_int_equal(image_alloc(img, TILES * TILE, TILE, "R,G,B,A", err, sizeof err), 0);
    is_image a, b;
    int rgb[3] = {0, 1, 2}, n[3], g[3];
    render(m, p, nm, 4, SCENE_FILL_SOLID_WIRE, 0, &a);
    put_tile(img, 0, &a, rgb, 1.0f, 0.0f);
    render(m, p, nm, 9, SCENE_FILL_SOLID, SCENE_AOV_NORMAL | SCENE_AOV_GREGORY, &b);
    put_tile(img, 1, &b, rgb, 1.0f, 0.0f);
    channels(&b, "N.X", "N.Y", "N.Z", n);
    put_tile(img, 2, &b, n, 0.5f, 0.5f);
    channels(&b, "gregory.X", "gregory.Y", "gregory.Z", g);
    put_tile(img, 3, &b, g, 1.0f, 0.0f);
    image_free(&a), image_free(&b);
}

/* Pixels of tile t of img that differ from its top-left pixel (the background): the object is on screen. */
static long object_pixels(const is_image *img, int t)
{
    long n = 0;
    const float *bg = &img->data[(size_t)t * TILE * img->channels];
    for (int y = 0; y < TILE; y++)
        for (int x = 0; x < TILE; x++)
            n += memcmp(&img->data[((size_t)y * img->width + (size_t)t * TILE + x) * img->channels], bg,
                        3 * sizeof(float)) != 0;
    return n;
}

/* Every (mesh, patch, normals) against its golden; the failures are listed, then asserted. */
static void check_mesh(const char *mesh)
{
    is_mesh m = {0};
    char err[256];
    assert_int_equal(mesh_builtin(mesh, &m, err, sizeof err), 0);
    int failures = 0, checked = 0;
    for (size_t p = 0; p < sizeof patches / sizeof patches[0]; p++)
        for (size_t k = 0; k < sizeof normal_modes / sizeof normal_modes[0]; k++) {
            char name[128];
            snprintf(name, sizeof name, "batch-%s-%s-%s", mesh, vs_patch_name(patches[p]),
                     vs_normals_name(normal_modes[k]));
            is_image img;
            compose(&m, patches[p], normal_modes[k], &img);
            for (int t = 0; t < 3; t++) assert_true(object_pixels(&img, t) > TILE * TILE / 5);
            if (golden_check(&img, name, 0.0f, 0.0f) != 0) {
                fprintf(stderr, "golden paths: %s differs from tests/golden/%s.png\n", name, name);
                failures++;
            }
            checked++;
            image_free(&img);
        }
    mesh_free(&m);
    fprintf(stderr, "golden paths: %s: %d checked, %d failed\n", mesh, checked, failures);
    assert_int_equal(failures, 0);
}

static void test_golden_cube(void **state) { (void)state; check_mesh(meshes[0]); }
static void test_golden_icosahedron(void **state) { (void)state; check_mesh(meshes[1]); }
static void test_golden_sphere(void **state) { (void)state; check_mesh(meshes[2]); }

/* The goldens of npatch and smooth with linear normals are drawn by vs/batch8.c's lanes: the instanced path uses
 * the patch's own shader, whose batched entry is batch8's, and a new device is off the reference path. */
static void test_batch8_route(void **state)
{
    (void)state;
    assert_true(vs_patch_shader(VS_PATCH_NPATCH)->batch == vs_npatch_batch);
    assert_true(vs_patch_shader(VS_PATCH_SMOOTH)->batch == vs_smooth_batch);
    scene_opts o;
    scene_opts_default(&o);
    assert_int_equal(o.path, SCENE_PATH_INSTANCED);
    is_device *dev = dev_create(TILE, TILE, 4, NULL, 0);
    assert_non_null(dev);
    assert_false(dev_reference_path(dev));
    dev_destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_batch8_route),
        cmocka_unit_test(test_golden_cube),
        cmocka_unit_test(test_golden_icosahedron),
        cmocka_unit_test(test_golden_sphere),
    };
    return cmocka_run_group_tests_name("golden_paths", tests, NULL, NULL);
}
