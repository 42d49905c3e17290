/* examples/npatch_diff.c -- a pixel-diff test of a curved-patch rendering, as a user of the installed
 * library writes one in their own project.
 *
 *   npatch_diff REFERENCE.png            render, compare with the reference: exit 0 same, 1 different
 *   npatch_diff --write REFERENCE.png    render and (re)write the reference (review it, then commit it)
 *   (exit 2: bad arguments, or the render or a file failed)
 *
 * It builds an octahedron from arrays, draws it as an N-Patch (PN triangles) by tessellation through
 * instancing on the CPU device -- a barycentric grid in stream 0 drawn once per triangle, one record per
 * triangle in stream 1, exactly as Direct3D 9's SetStreamSourceFreq did -- into memory, and compares the
 * image with the reference by image_check, the same test as the project's goldens and `instess compare`.
 *
 * Build it against an installed instess (make install):
 *   cc -std=c17 npatch_diff.c $(pkg-config --cflags --libs instess) -o npatch_diff
 * The images are the same bytes on every x86-64 machine for the library's fixed build, whatever the thread
 * count, so a threshold of 0 works; a project may allow a little with FAIL_THRESH and FAIL_PERCENT. */
#include <instess/core/core.h>
#include <instess/image/image.h>
#include <instess/meshes/meshes.h>
#include <instess/tess/tess.h>
#include <instess/vs/vs.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { WIDTH = 128, HEIGHT = 128, SAMPLES = 4, LEVEL = 6 };
#define FAIL_THRESH 0.0f    /* a pixel fails when a channel differs by more than this (colour in 0..1) */
#define FAIL_PERCENT 0.0f   /* the test fails when more than this percentage of pixels fail */
#define PI_F 3.14159265f

/* The octahedron of unit radius into *m: six corners, eight triangles wound so that cross(v1 - v0, v2 - v0)
 * points outward (instess's convention, as D3D9's: clockwise seen from the front); the normals are left to
 * the library (angle-weighted).  0, or -1 with the reason in err. */
static int build_octahedron(is_mesh *m, char *err, size_t errlen)
{
    static const float3 p[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    uint32_t idx[24];
    int t = 0;
    for (int sx = 0; sx < 2; sx++)          /* one triangle per octant: corners x = +-1, y = +-1, z = +-1 */
        for (int sy = 0; sy < 2; sy++)
            for (int sz = 0; sz < 2; sz++) {
                uint32_t x = (uint32_t)sx, y = 2u + (uint32_t)sy, z = 4u + (uint32_t)sz;
                bool outward = (sx + sy + sz) % 2 == 0;   /* an even number of minus signs keeps (x, y, z) */
                idx[3 * t] = x, idx[3 * t + 1] = outward ? y : z, idx[3 * t + 2] = outward ? z : y;
                t++;
            }
    is_mesh_data d = {.n_vertices = 6, .n_triangles = 8, .positions = p, .indices = idx};
    return mesh_create(m, "octahedron", &d, NULL, err, errlen);
}

/* The N-Patch shader with its constants: World (yaw 30, pitch 20 degrees), a camera 3.2 units away, a 45
 * degree field of view, and a light grey g_vDiffuse.  IS_OK or the device's error. */
static is_result set_npatch_shader(is_device *dev)
{
    float4x4 ry = mat_rotation_y(30.0f * PI_F / 180.0f), rx = mat_rotation_x(20.0f * PI_F / 180.0f);
    float4x4 world = mat_mul(&ry, &rx);
    float4x4 view = mat_look_at_lh((float3){0, 0, -3.2f}, (float3){0, 0, 0}, (float3){0, 1, 0});
    float4x4 proj = mat_perspective_fov_lh(PI_F / 4.0f, (float)WIDTH / HEIGHT, 1.2f, 5.2f);
    float4x4 wv = mat_mul(&world, &view), wvp = mat_mul(&wv, &proj);
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    vs_set_constants(&c, &wvp, &world, (float4){0.85f, 0.85f, 0.8f, 1.0f}, NULL);   /* linear normals, as D3D9 */
    is_result e = dev_set_vertex_shader(dev, vs_patch_shader(VS_PATCH_NPATCH));
    return e == IS_OK ? dev_set_vertex_shader_constant_f(dev, 0, &c.c[0].x, VS_C_COUNT) : e;
}

/* Render the octahedron's N-Patch into img (R, G, B, A, allocated here).  0, or -1 with the reason in err. */
static int render(is_image *img, char *err, size_t errlen)
{
    is_mesh m = {0};
    core_grid g = {0};
    tess_resources r = {0};
    if (build_octahedron(&m, err, errlen) != 0) return -1;
    if (core_grid_make(CORE_GRID_REGULAR, LEVEL, &g) != 0) {   /* the barycentric grid of one triangle */
        snprintf(err, errlen, "out of memory");
        mesh_free(&m);
        return -1;
    }
    is_device *dev = dev_create(WIDTH, HEIGHT, SAMPLES, err, errlen);
    int rc = dev ? 0 : -1;
    is_result e = IS_OK;
    if (dev) e = dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0xff202830u, 1.0f);
    /* tessellation through instancing: the grid in stream 0 drawn once per triangle of m (INDEXEDDATA | n),
     * one is_patch_instance per triangle in stream 1 (INSTANCEDATA | 1), Listing 1.1.2's declaration */
    if (dev && e == IS_OK) e = tess_bind_instanced(dev, &m, &g, &r);
    if (dev && e == IS_OK) e = set_npatch_shader(dev);
    if (dev && e == IS_OK)   /* the grid's points and triangles, drawn m.n_triangles times */
        e = dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, (unsigned)g.n_points, 0,
                                       (unsigned)g.n_triangles);
    if (dev && e != IS_OK) rc = -1, snprintf(err, errlen, "draw failed: %s", dev_last_error(dev));
    uint32_t *rgba = rc == 0 ? malloc((size_t)WIDTH * HEIGHT * sizeof *rgba) : NULL;
    if (rc == 0 && !rgba) rc = -1, snprintf(err, errlen, "out of memory");
    if (rc == 0) rc = image_alloc(img, WIDTH, HEIGHT, "R,G,B,A", err, errlen);
    if (rc == 0) {   /* the multisampled target, resolved to one RGBA8 value per pixel */
        rs_target_resolve(dev_present(dev), rgba);   /* the present: the colour written */
        image_from_rgba8(img, rgba);
    }
    free(rgba);
    tess_resources_free(&r);
    dev_destroy(dev);
    core_grid_free(&g);
    mesh_free(&m);
    return rc;
}

int main(int argc, char **argv)
{
    bool write = argc == 3 && strcmp(argv[1], "--write") == 0;
    if (argc != 2 + write || argv[argc - 1][0] == '-') {
        fprintf(stderr, "usage: %s [--write] REFERENCE.png\n", argv[0]);
        return 2;
    }
    const char *ref = argv[argc - 1];
    char err[1024];
    is_image img = {0};
    if (render(&img, err, sizeof err) != 0) {
        fprintf(stderr, "npatch_diff: %s\n", err);
        return 2;
    }
    if (write) {
        is_image_meta meta = {"instess " INSTESS_VERSION, "examples/npatch_diff: octahedron, N-Patch, level 6"};
        int rc = image_write(&img, ref, &meta, err, sizeof err);
        image_free(&img);
        if (rc != 0) fprintf(stderr, "npatch_diff: %s\n", err);
        return rc == 0 ? 0 : 2;
    }
    /* The pixel-diff test.  On a difference, the amplified diff image goes beside the reference. */
    char diff[1100];
    snprintf(diff, sizeof diff, "%s.diff.png", ref);
    is_image ref_img = {0};
    is_image_diff d;
    is_image_verdict v = IS_IMAGE_IO_ERROR;
    if (image_read(&ref_img, ref, err, sizeof err) == 0)
        v = image_check(&img, &ref_img, FAIL_THRESH, FAIL_PERCENT, diff, &d, err, sizeof err);
    image_free(&img);
    image_free(&ref_img);
    if (v == IS_IMAGE_PASS) printf("npatch_diff: matches %s (largest difference %g)\n", ref, (double)d.max_error);
    else if (v == IS_IMAGE_DIFFERENT)
        printf("npatch_diff: DIFFERENT from %s: %ld of %ld pixels, largest difference %g; see %s\n", ref, d.n_fail,
               d.n_pixels, (double)d.max_error, diff);
    else fprintf(stderr, "npatch_diff: %s\n", err);
    return v == IS_IMAGE_PASS ? 0 : v == IS_IMAGE_DIFFERENT ? 1 : 2;
}
