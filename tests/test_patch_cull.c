/* tests/test_patch_cull.c -- pre-tessellation culling (dev_set_patch_cull, core/draw_cull.c) never changes a
 * byte: random meshes (the built-ins with their positions and normals jittered, so that patches bulge and twist),
 * random views (close cameras that clip and leave patches off-screen, far ones), levels, patches (the ones with a
 * hull stage and one without), cull modes, sample counts and thread counts, each rendered with the cull on and
 * off and compared plane by plane; and the cull does skip instances in these scenes and, by its winding test
 * alone (every cube in view), in the benchmark's scene B layout, whose image is also the reference path's (which
 * never culls). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cli/run/scene.h"
#include "util/patch_util.h"

#include "../core/hlsl.h"
/* A small deterministic generator (xorshift64*), so that a failure replays. */
static uint64_t rnd_next(uint64_t *s)
{
    *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
    return *s * 2685821657736338717ull;
}
/* Uniform in [lo, hi). */
static float rnd_in(uint64_t *s, float lo, float hi) { return lo + (hi - lo) * (float)(rnd_next(s) >> 40) / 16777216.0f; }

/* Built-in `name` with every position moved by up to `jp` and every normal by up to `jn` (then normalised). */
static void jittered_mesh(const char *name, float jp, float jn, uint64_t *s, is_mesh *out)
{
    char err[256];
    is_mesh b = {0};
    assert_int_equal(mesh_builtin(name, &b, err, sizeof err), 0);
    float3 *p = malloc(b.n_vertices * sizeof *p), *n = malloc(b.n_vertices * sizeof *n);
    assert_non_null(p), assert_non_null(n);
    for (size_t k = 0; k < b.n_vertices; k++) {
        p[k] = add3(b.positions[k], f3(rnd_in(s, -jp, jp), rnd_in(s, -jp, jp), rnd_in(s, -jp, jp)));
        n[k] = normalize3(add3(b.normals[k], f3(rnd_in(s, -jn, jn), rnd_in(s, -jn, jn), rnd_in(s, -jn, jn))));
    }
    is_mesh_data md = {b.n_vertices, b.n_triangles, p, n, NULL, b.indices};
    assert_int_equal(mesh_create(out, name, &md, NULL, err, sizeof err), 0);
    free(p), free(n);
    mesh_free(&b);
}

/* Render o (mesh m) with cull mode `cull`, the patch cull on or off, on the fast or the reference path; returns
 * the device. */
static is_device *render_path(const scene_opts *o, const is_mesh *m, uint32_t cull, bool patch_cull, bool reference)
{
    char err[256];
    is_device *dev = dev_create(o->width, o->height, o->msaa, err, sizeof err);
    assert_non_null(dev);
    dev_set_threads(dev, o->threads);
    dev_set_reference_path(dev, reference);
    dev_set_patch_cull(dev, patch_cull);
    assert_int_equal(dev_set_render_state(dev, IS_RS_CULLMODE, cull), IS_OK);
    assert_int_equal(clear_and_draw(dev, o, m), 0);
    return dev;
}

/* render_path on the fast path. */
static is_device *render(const scene_opts *o, const is_mesh *m, uint32_t cull, bool patch_cull)
{
    return render_path(o, m, cull, patch_cull, false);
}

/* Totals over the comparisons. */
typedef struct cull_counts { uint64_t instances, culled, renders; } cull_counts;

/* o rendered with and without the cull: the same colour and depth bytes; counts the instances culled. */
static void check_same(const scene_opts *o, const is_mesh *m, uint32_t cull, cull_counts *c)
{
    is_device *off = render(o, m, cull, false), *on = render(o, m, cull, true);
    const rs_target *a = dev_render_target(off), *b = dev_render_target(on);
    size_t n = (size_t)a->width * (size_t)a->height * (size_t)a->samples;
    if (memcmp(a->color, b->color, n * sizeof *a->color) || memcmp(a->depth, b->depth, n * sizeof *a->depth))
        fprintf(stderr, "differs: mesh %s patch %d level %g %dx%d msaa %d yaw %g pitch %g distance %g cull %u\n", m->name,
                (int)o->patch, (double)o->level, o->width, o->height, o->msaa, (double)o->yaw, (double)o->pitch,
                (double)o->distance, cull);
    assert_memory_equal(a->color, b->color, n * sizeof *a->color);
    assert_memory_equal(a->depth, b->depth, n * sizeof *a->depth);
    assert_int_equal(dev_instances_culled(off), 0);
    uint64_t k = dev_instances_culled(on);
    /* a culled instance shades none of its vertices: the counts differ by exactly that */
    uint64_t per = dev_vertices_shaded(off) / m->n_triangles;
    assert_true(dev_vertices_shaded(off) - dev_vertices_shaded(on) == k * per);
    c->instances += m->n_triangles, c->culled += k, c->renders++;
    dev_destroy(off), dev_destroy(on);
}

/* Random scenes: every one the same bytes with the cull; the cull skipped instances in many of them. */
static void test_random_scenes(void **state)
{
    (void)state;
    uint64_t seed = 0x9e3779b97f4a7c15ull;
    const char *const *names = mesh_builtin_names();
    size_t n_names = 0;
    while (names[n_names]) n_names++;
    static const vs_patch patches[] = {VS_PATCH_NPATCH, VS_PATCH_NPATCH, VS_PATCH_FLAT, VS_PATCH_SMOOTH};
    static const uint32_t culls[] = {IS_CULL_CCW, IS_CULL_CCW, IS_CULL_CW, IS_CULL_NONE};
    cull_counts c = {0};
    for (int t = 0; t < 500; t++) {
        is_mesh m;
        jittered_mesh(names[rnd_next(&seed) % n_names], rnd_in(&seed, 0.0f, 0.15f), rnd_in(&seed, 0.0f, 0.6f), &seed,
                      &m);
        scene_opts o;
        scene_opts_default(&o);
        o.patch = patches[rnd_next(&seed) % 4];
        o.level = (float)(1 + rnd_next(&seed) % 12);
        o.width = 40 + (int)(rnd_next(&seed) % 120), o.height = 40 + (int)(rnd_next(&seed) % 120);
        o.msaa = rnd_next(&seed) % 4 == 0 ? 4 : 1;
        o.threads = 1 + (int)(rnd_next(&seed) % 2);
        o.yaw = rnd_in(&seed, -180.0f, 180.0f), o.pitch = rnd_in(&seed, -89.0f, 89.0f);
        o.distance = t % 3 == 0 ? rnd_in(&seed, 0.3f, 1.5f) : rnd_in(&seed, 2.5f, 6.0f);
        check_same(&o, &m, culls[rnd_next(&seed) % 4], &c);
        mesh_free(&m);
    }
    fprintf(stderr, "test_random_scenes: %llu renders, %llu of %llu instances culled\n",
            (unsigned long long)c.renders, (unsigned long long)c.culled, (unsigned long long)c.instances);
    assert_true(c.culled > c.instances / 20); /* the test is not vacuous: the cull did work */
}

/* The benchmark's scene B layout, smaller: 6 x 6 jitter-free cubes at level 8; the winding test skips instances
 * (about a sixth of the patches face away entirely), same bytes. */
static void test_cubes(void **state)
{
    (void)state;
    is_mesh m;
    assert_int_equal(cubes_mesh(6, &m), 0);
    scene_opts o;
    scene_opts_default(&o);
    o.patch = VS_PATCH_NPATCH, o.level = 8, o.width = o.height = 256, o.distance = 2.4f, o.msaa = 1, o.threads = 2;
    cull_counts c = {0};
    check_same(&o, &m, IS_CULL_CCW, &c);
    assert_true(c.culled > c.instances / 12);
    /* the reference path is the definition: it never culls, and the fast path with the cull gives its bytes */
    is_device *ref = render_path(&o, &m, IS_CULL_CCW, true, true), *fast = render(&o, &m, IS_CULL_CCW, true);
    assert_int_equal(dev_instances_culled(ref), 0);
    assert_true(dev_instances_culled(fast) > 0);
    const rs_target *a = dev_render_target(ref), *b = dev_render_target(fast);
    size_t np = (size_t)a->width * (size_t)a->height * (size_t)a->samples;
    assert_memory_equal(a->color, b->color, np * sizeof *a->color);
    assert_memory_equal(a->depth, b->depth, np * sizeof *a->depth);
    dev_destroy(ref), dev_destroy(fast);
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_scenes),
        cmocka_unit_test(test_cubes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
