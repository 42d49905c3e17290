/* examples/adaptive_lod.c -- adaptive level of detail drawn the instancing way, as a user of the installed
 * library writes it: a level per mesh edge from its projected size, the triangles bucketed by their edges' level
 * triple, one refinement pattern per bucket in stream 0 and one instanced draw per bucket.
 *
 *   adaptive_lod OUT.png     render the built-in sphere with screen-space levels (8 pixels a segment), write
 *                            OUT.png and print the levels used and the draws made; exit 0, or 1 on failure
 *
 * Build it against an installed instess (make install):
 *   cc -std=c17 adaptive_lod.c $(pkg-config --cflags --libs instess) -o adaptive_lod
 * Every edge's level depends on its two welded end points alone, so the two triangles of an edge agree and the
 * surface has no cracks whatever the levels (tess/tess.h). */
#include <instess/core/core.h>
#include <instess/image/image.h>
#include <instess/meshes/meshes.h>
#include <instess/tess/tess.h>
#include <instess/vs/vs.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { WIDTH = 256, HEIGHT = 256, MAX_LEVEL = 16 };
#define PI_F 3.14159265f

/* The camera: the unit sphere 2.6 units in front of the eye, 45 degrees of field of view. */
static void camera(float4x4 *world, float4x4 *world_view, float4x4 *wvp)
{
    *world = mat_identity();
    float4x4 view = mat_look_at_lh((float3){0, 0, -2.6f}, (float3){0, 0, 0}, (float3){0, 1, 0});
    float4x4 proj = mat_perspective_fov_lh(PI_F / 4.0f, (float)WIDTH / HEIGHT, 0.5f, 10.0f);
    *world_view = mat_mul(world, &view);
    *wvp = mat_mul(world_view, &proj);
}

/* The smoothed patch's shader and its constants on dev; IS_OK or the device's error. */
static is_result set_shader(is_device *dev, const float4x4 *wvp, const float4x4 *world)
{
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    vs_set_constants(&c, wvp, world, (float4){0.8f, 0.82f, 0.9f, 1.0f}, NULL);
    is_result e = dev_set_vertex_shader(dev, vs_patch_shader(VS_PATCH_SMOOTH));
    return e == IS_OK ? dev_set_vertex_shader_constant_f(dev, 0, &c.c[0].x, VS_C_COUNT) : e;
}

/* Per-edge levels of m on screen into e (built here), the draws bucketed in a, drawn on dev; prints what it did.
 * 0, or -1 with the reason in err. */
static int draw_adaptive(is_device *dev, const is_mesh *m, tess_lod_edges *e, tess_adaptive *a, char *err,
                         size_t errlen)
{
    tess_lod_params p = {.mode = TESS_LOD_SCREEN, .target_px = 8.0f, .ref_depth = 1.6f, .min_level = 1,
                         .max_level = MAX_LEVEL, .width = WIDTH, .height = HEIGHT};
    float4x4 world;
    camera(&world, &p.world_view, &p.wvp);
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    if (tess_lod_edges_build(m, e, err, errlen) != 0) return -1;
    tess_lod_levels(&p, m, e, hist);
    core_pattern_cache *cache = core_pattern_cache_create(0);
    if (!cache) return snprintf(err, errlen, "out of memory"), -1;
    is_result r = tess_bind_adaptive(dev, m, e, cache, a);
    if (r == IS_OK) r = set_shader(dev, &p.wvp, &world);
    for (size_t k = 0; k < a->n_buckets && r == IS_OK; k++) r = tess_draw_bucket(dev, a, k);
    core_pattern_cache_destroy(cache);
    if (r != IS_OK) return snprintf(err, errlen, "draw failed: %s", dev_last_error(dev)), -1;
    int lo = 0, hi = 0;
    for (int l = 1; l <= CORE_LOD_MAX_LEVEL; l++)
        if (hist[l]) hi = l, lo = lo ? lo : l;
    printf("edges: %zu, levels %d..%d; draws: %zu buckets of %zu patterns, %zu triangles\n", e->n_edges, lo, hi,
           a->n_buckets, a->n_patterns, a->n_triangles);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2 || argv[1][0] == '-') return fprintf(stderr, "usage: %s OUT.png\n", argv[0]), 1;
    char err[512] = "";
    is_mesh m = {0};
    tess_lod_edges e = {0};
    tess_adaptive a = {0};
    is_image img = {0};
    is_device *dev = NULL;
    int rc = mesh_builtin("sphere", &m, err, sizeof err);
    if (rc == 0) rc = (dev = dev_create(WIDTH, HEIGHT, 4, err, sizeof err)) ? 0 : -1;
    if (rc == 0) rc = dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0xff202830u, 1.0f) == IS_OK ? 0 : -1;
    if (rc == 0) rc = draw_adaptive(dev, &m, &e, &a, err, sizeof err);
    if (rc == 0) rc = image_alloc(&img, WIDTH, HEIGHT, "R,G,B,A", err, sizeof err);
    uint32_t *rgba = rc == 0 ? malloc((size_t)WIDTH * HEIGHT * sizeof *rgba) : NULL;
    if (rc == 0 && !rgba) rc = -1, snprintf(err, sizeof err, "out of memory");
    if (rc == 0) {   /* the multisampled target, resolved to one RGBA8 value per pixel */
        rs_target_resolve(dev_present(dev), rgba);   /* the present: the colour written */
        image_from_rgba8(&img, rgba);
        is_image_meta meta = {"instess " INSTESS_VERSION, "examples/adaptive_lod: sphere, smoothed patch, screen 8 px"};
        rc = image_write(&img, argv[1], &meta, err, sizeof err);
    }
    free(rgba);
    image_free(&img);
    tess_adaptive_free(&a);
    tess_lod_edges_free(&e);
    dev_destroy(dev);
    mesh_free(&m);
    if (rc != 0) fprintf(stderr, "adaptive_lod: %s\n", err);
    return rc == 0 ? 0 : 1;
}
