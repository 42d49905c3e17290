/* tests/test_reference_path.c -- the optimized draw path (batched shading, shared vertex projection, 8-pixel
 * spans) writes exactly the bytes of the scalar reference path (dev_set_reference_path(dev, true)): scenes
 * shaped like the benchmark's A (one cube, high level), B (many cubes, geometry-bound) and C (one cube, low level,
 * fill-bound), smaller, and D (adaptive levels: many draws a frame, one tile pass), with every patch, 1 and 2
 * threads, plus the cases that leave the fast paths: near-plane
 * clipping, a target width that is not a multiple of 8, 4 samples, AOV planes, the wireframe overlay, the
 * device's N-patch mode and CPU tessellation; the limits of the fused path (several rasterizer calls per draw,
 * instances larger than a piece); and every shader's batched entry against its per-vertex main, bit for bit.
 * Every comparison runs for each instruction set's copy of the rasterizer's kernels that this CPU runs (AVX2, and
 * AVX-512 where it has it: test_isa_avx512 says when that copy could not run). */
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
#include "../raster/raster_internal.h"

#include "../core/hlsl.h"
/* The cube, or side x side copies of it (tests/util/patch_util.h). */
static void make_cubes(int side, is_mesh *out)
{
    assert_int_equal(cubes_mesh(side, out), 0);
}

/* Render o (mesh m) on a fresh device with the reference path on or off (off: the fast paths of instruction set
 * isa, RS_ISA_*, or the device's own choice for -1); returns the device. */
static is_device *render_isa(const scene_opts *o, const is_mesh *m, unsigned aovs, bool reference, int isa)
{
    char err[256];
    is_device *dev = dev_create(o->width, o->height, aovs ? 1 : o->msaa, err, sizeof err);
    assert_non_null(dev);
    dev_set_threads(dev, o->threads);
    dev_set_reference_path(dev, reference);
    assert_true(dev_reference_path(dev) == reference);
    if (isa >= 0) {
        assert_int_equal(dev_set_isa(dev, isa), 0);
        assert_int_equal(dev_isa(dev), isa);
    }
    for (int k = 0; aovs && k < 4; k++)
        assert_int_equal(rs_target_add_aov(dev_render_target(dev), RS_ATTR_TEXCOORD0 + 1 + k, k == 2 ? 1 : 3), RS_OK);
    assert_int_equal(clear_and_draw(dev, o, m), 0);
    return dev;
}

/* render_isa with the device's own instruction set. */
static is_device *render(const scene_opts *o, const is_mesh *m, unsigned aovs, bool reference)
{
    return render_isa(o, m, aovs, reference, -1);
}

/* The reference path and the fast paths of instruction set isa give the same colour, depth and AOV bytes and the
 * same statistics; returns the samples written. */
static uint64_t check_same_isa(const scene_opts *o, const is_mesh *m, unsigned aovs, int isa)
{
    is_device *ref = render(o, m, aovs, true), *fast = render_isa(o, m, aovs, false, isa);
    const rs_target *a = dev_render_target(ref), *b = dev_render_target(fast);
    size_t n = (size_t)a->width * (size_t)a->height * (size_t)a->samples;
    assert_memory_equal(a->color, b->color, n * sizeof *a->color);
    assert_memory_equal(a->depth, b->depth, n * sizeof *a->depth);
    for (int k = 0; k < a->n_aov; k++)
        assert_memory_equal(a->aov[k].data, b->aov[k].data,
                            (size_t)a->width * (size_t)a->height * (size_t)a->aov[k].comps * sizeof(float));
    const rs_stats *sa = dev_stats(ref), *sb = dev_stats(fast);
    assert_memory_equal(sa, sb, sizeof *sa);
    assert_true(dev_vertices_shaded(ref) == dev_vertices_shaded(fast));
    uint64_t written = sa->samples_written;
    dev_destroy(ref);
    dev_destroy(fast);
    return written;
}

/* check_same_isa for every instruction set this CPU runs (AVX2 always, AVX-512 where it has it: test_isa_avx512
 * says when that half did not run); returns the samples written. */
static uint64_t check_same(const scene_opts *o, const is_mesh *m, unsigned aovs)
{
    uint64_t written = 0;
    for (int isa = 0; isa < RS_ISA_COUNT; isa++)
        if (rs_isa_supported(isa)) written = check_same_isa(o, m, aovs, isa);
    return written;
}

/* A scene: side x side cubes at `level` on a w x h target, 1 sample, camera distance d. */
static scene_opts scene(float level, int w, int h, float d)
{
    scene_opts o;
    scene_opts_default(&o);
    o.level = level, o.width = w, o.height = h, o.distance = d, o.msaa = 1;
    return o;
}

/* Every patch (and both thread counts) on one scene: same bytes, and something was drawn. */
static void all_patches(int side, float level, int w, int h, float d)
{
    is_mesh m;
    make_cubes(side, &m);
    for (int p = 0; p < VS_PATCH_COUNT; p++)
        for (int t = 1; t <= 2; t++) {
            scene_opts o = scene(level, w, h, d);
            o.patch = (vs_patch)p, o.threads = t;
            assert_true(check_same(&o, &m, 0) > 0);
        }
    mesh_free(&m);
}

/* A: one cube at a high level. */
static void test_scene_a(void **state) { (void)state; all_patches(1, 16, 160, 160, 3.2f); }
/* B: 16 cubes at a middle level (small triangles, most of the work in geometry). */
static void test_scene_b(void **state) { (void)state; all_patches(4, 6, 192, 192, 2.4f); }
/* C: one cube at a low level on a larger target (few large triangles). */
static void test_scene_c(void **state) { (void)state; all_patches(1, 2, 320, 320, 3.2f); }

/* D: adaptive levels (--lod screen), so a frame is one instanced draw per bucket of level triples -- the draws
 * the device queues for one tile pass (raster.h, rs_set_scene) -- with every patch and 1 and 2 threads. */
static void test_scene_d(void **state)
{
    (void)state;
    is_mesh m;
    make_cubes(3, &m);
    for (int p = 0; p < VS_PATCH_COUNT; p++)
        for (int t = 1; t <= 2; t++) {
            scene_opts o = scene(12, 200, 200, 2.4f);
            o.patch = (vs_patch)p, o.threads = t, o.lod = TESS_LOD_SCREEN, o.lod_target = 5.0f;
            assert_true(check_same(&o, &m, 0) > 0);
        }
    mesh_free(&m);
}

/* Targets whose planes take the tile pass's streaming copy-out (2048 x 1024 at 1 sample and 512 x 512 at 4
 * samples: 8 and 4 MB planes, rows of whole cache lines) and a large one whose rows are not whole cache lines
 * (2056 x 1024: plain stores), 2 threads; then a second draw without a clear, drawn in the target and
 * depth-tested against what the copy-out wrote.  (The reference path draws in the target: no copy-out.) */
_Static_assert(2048u * 1024u * 4u >= COPY_STREAM_BYTES && 512u * 512u * 4u * 4u >= COPY_STREAM_BYTES,
               "test_large_targets' first two targets must take the streaming copy-out");
static void test_large_targets(void **state)
{
    (void)state;
    is_mesh m;
    make_cubes(1, &m);
    const int sizes[3][3] = {{2048, 1024, 1}, {512, 512, 4}, {2056, 1024, 1}}; /* width, height, samples */
    for (int k = 0; k < 3; k++) {
        scene_opts o = scene(2, sizes[k][0], sizes[k][1], 3.2f);
        o.msaa = sizes[k][2], o.threads = 2, o.patch = VS_PATCH_NPATCH;
        is_device *dev[2];
        for (int r = 0; r < 2; r++) {
            dev[r] = render(&o, &m, 0, r == 0);
            core_grid g;
            assert_int_equal(core_grid_make(o.grid, o.level, &g), 0);
            o.yaw += 7.0f; /* a second, turned draw without a clear: depth-tested against the copied-out planes */
            assert_int_equal(scene_draw(dev[r], &o, &m, &g, NULL), 0);
            o.yaw -= 7.0f;
            core_grid_free(&g);
        }
        const rs_target *a = dev_render_target(dev[0]), *b = dev_render_target(dev[1]);
        assert_int_equal(a->samples, sizes[k][2]);
        size_t n = (size_t)a->width * (size_t)a->height * (size_t)a->samples;
        assert_memory_equal(a->color, b->color, n * sizeof *a->color);
        assert_memory_equal(a->depth, b->depth, n * sizeof *a->depth);
        assert_true(dev_stats(dev[0])->samples_written > 10000);
        dev_destroy(dev[0]), dev_destroy(dev[1]);
    }
    mesh_free(&m);
}

/* A draw larger than one fused rasterizer call (2^19 triangles): 15 x 15 cubes at level 16 (691 200 triangles,
 * two calls) on a small target, and a level whose instances exceed a fused piece (level 96: 4753 vertices). */
static void test_fused_limits(void **state)
{
    (void)state;
    is_mesh m;
    make_cubes(15, &m);
    scene_opts o = scene(16, 96, 96, 2.4f);
    o.threads = 2, o.patch = VS_PATCH_NPATCH;
    assert_true(check_same(&o, &m, 0) > 0);
    mesh_free(&m);
    make_cubes(1, &m);
    o = scene(96, 64, 64, 3.2f);
    o.threads = 2, o.patch = VS_PATCH_SMOOTH;
    assert_true(check_same(&o, &m, 0) > 0);
    mesh_free(&m);
}

/* An octahedron of radius 100 centred at (1e6, 1e6, 1e6) (float positions 1/16 apart: flat-ish coarse patches),
 * with every patch: the scene normalises it like any mesh, and both paths must agree on it. */
static void test_offset_mesh(void **state)
{
    (void)state;
    const float s = 100.0f, c = 1e6f;
    const float3 p[6] = {{s + c, c, c}, {c - s, c, c}, {c, s + c, c}, {c, c - s, c}, {c, c, s + c}, {c, c, c - s}};
    uint32_t idx[24];
    int n = 0;
    for (int x = 0; x < 2; x++)
        for (int y = 2; y < 4; y++)
            for (int z = 4; z < 6; z++) {
                bool ccw = ((x == 0) == (y == 2)) == (z == 4);
                idx[n++] = (uint32_t)x, idx[n++] = (uint32_t)(ccw ? y : z), idx[n++] = (uint32_t)(ccw ? z : y);
            }
    is_mesh_data md = {6, 8, p, NULL, NULL, idx};
    is_mesh m;
    char err[256];
    assert_int_equal(mesh_create(&m, "offset", &md, NULL, err, sizeof err), 0);
    for (int q = 0; q < VS_PATCH_COUNT; q++) {
        scene_opts o = scene(5, 64, 64, 3.2f);
        o.patch = (vs_patch)q;
        assert_true(check_same(&o, &m, 0) > 0);
    }
    mesh_free(&m);
}

/* A 4-sample frame on a fresh device (reference path or not, instruction set isa): o drawn with the default depth
 * state, then the same scene again with cull none (its front faces at the same depths, its back faces behind) with
 * depth function zf, depth test ze and depth write zw -- every depth state of the 4-sample walk (tri.c's tri_tile_msaa4)
 * against samples the first scene wrote. */
static is_device *render_msaa_states(const scene_opts *o, const is_mesh *m, bool reference, int isa, uint32_t zf,
                                     uint32_t ze, uint32_t zw)
{
    char err[256];
    is_device *dev = dev_create(o->width, o->height, 4, err, sizeof err);
    assert_non_null(dev);
    dev_set_threads(dev, o->threads);
    dev_set_reference_path(dev, reference);
    if (!reference) assert_int_equal(dev_set_isa(dev, isa), 0);
    assert_int_equal(clear_and_draw(dev, o, m), 0);
    scene_opts o2 = *o;
    o2.cull = IS_CULL_NONE;   /* (the same surface again: equal depths where it faces the camera) */
    core_grid g;
    assert_int_equal(core_grid_make(o2.grid, o2.level, &g), 0);
    dev_set_render_state(dev, IS_RS_ZFUNC, zf);
    dev_set_render_state(dev, IS_RS_ZENABLE, ze);
    dev_set_render_state(dev, IS_RS_ZWRITEENABLE, zw);
    assert_int_equal(scene_draw(dev, &o2, m, &g, NULL), 0);
    core_grid_free(&g);
    return dev;
}

/* 4 samples off the reference path (tri_tile_msaa4): the reference's colour, depth and statistics for every depth
 * function, with the depth test or its writes off, 1 and 2 threads, on each instruction set; a near camera
 * (clipping, pixels whose centre lies outside a triangle covered by samples); the written samples differ between
 * the functions (the state reaches the walk). */
static void test_msaa4_states(void **state)
{
    (void)state;
    is_mesh m;
    make_cubes(2, &m);
    for (int near = 0; near < 2; near++) {
        uint64_t written[IS_CMP_ALWAYS + 1] = {0};   /* per function, with the test and writes on */
        for (uint32_t zf = IS_CMP_NEVER; zf <= IS_CMP_ALWAYS; zf++)
            for (int zs = 0; zs < 3; zs++) {   /* test and writes, test alone, no test */
                scene_opts o = scene(6, 67, 53, near ? 1.2f : 3.0f);
                o.msaa = 4, o.threads = 1 + (int)(zf & 1), o.patch = VS_PATCH_SMOOTH;
                const uint32_t ze = zs < 2, zw = zs == 0;
                is_device *ref = render_msaa_states(&o, &m, true, 0, zf, ze, zw);
                const rs_stats *sa = dev_stats(ref);
                for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
                    if (!rs_isa_supported(isa)) continue;
                    is_device *fast = render_msaa_states(&o, &m, false, isa, zf, ze, zw);
                    const rs_target *a = dev_render_target(ref), *b = dev_render_target(fast);
                    const size_t n = (size_t)a->width * (size_t)a->height * 4;
                    assert_memory_equal(a->color, b->color, n * sizeof *a->color);
                    assert_memory_equal(a->depth, b->depth, n * sizeof *a->depth);
                    assert_memory_equal(sa, dev_stats(fast), sizeof *sa);
                    dev_destroy(fast);
                }
                if (zs == 0) written[zf] = sa->samples_written;
                dev_destroy(ref);
            }
        /* NEVER: the first scene's alone; LESS: nothing more (the front faces' depths are equal, the back faces'
         * greater); LESSEQUAL and EQUAL: the front faces again; ALWAYS: every covered sample of both */
        assert_true(written[IS_CMP_NEVER] > 0 && written[IS_CMP_LESS] == written[IS_CMP_NEVER]);
        assert_true(written[IS_CMP_EQUAL] > written[IS_CMP_LESS] && written[IS_CMP_LESSEQUAL] == written[IS_CMP_EQUAL]);
        assert_true(written[IS_CMP_ALWAYS] > written[IS_CMP_LESSEQUAL] && written[IS_CMP_GREATER] > written[IS_CMP_NEVER]);
    }
    mesh_free(&m);
}

/* The cases off the fast paths or at their edges, with the smoothed patch. */
static void test_edge_cases(void **state)
{
    (void)state;
    is_mesh m;
    make_cubes(1, &m);
    scene_opts o = scene(8, 131, 97, 1.1f); /* near-plane and guard-band clipping, width % 8 != 0 */
    o.threads = 2;
    check_same(&o, &m, 0);
    o = scene(8, 133, 101, 3.2f);
    o.msaa = 4; /* 4 samples: the 4-sample walk and batched shading on one */
    assert_true(check_same(&o, &m, 0) > 0);
    o.msaa = 1;
    o.normals = VS_NORMALS_QUADRATIC;
    assert_true(check_same(&o, &m, SCENE_AOV_NORMAL) > 0); /* AOV planes */
    o.normals = VS_NORMALS_REAL;
    o.fill = SCENE_FILL_SOLID_WIRE; /* lines with depth bias over the solid */
    assert_true(check_same(&o, &m, 0) > 0);
    o.fill = SCENE_FILL_SOLID;
    o.normals = VS_NORMALS_LINEAR;
    o.patch = VS_PATCH_NPATCH;
    o.path = SCENE_PATH_NPATCH_MODE;
    assert_true(check_same(&o, &m, 0) > 0);
    o.path = SCENE_PATH_CPU;
    assert_true(check_same(&o, &m, 0) > 0);
    mesh_free(&m);
}

/* Barycentrics of vertex v of a batch: grid points of level 7 (interior, edges, corners), some negative zeros and
 * slightly negative or tiny components. */
static float3 random_b(uint32_t *st, int v)
{
    int level = 7, i = v % 36, a = 0;
    while (i > level - a) i -= level - a + 1, a++;
    float3 b = f3((float)a / (float)level, (float)i / (float)level, 0.0f);
    b.z = 1.0f - b.x - b.y;
    if (v % 11 == 3) b.x = -0.0f;
    if (v % 13 == 5) b.y = -1e-7f;
    if (v % 17 == 7) b = f3(1e-30f, 1e-30f, 1.0f);
    if (v % 19 == 9) b = f3(lcg_float(st, 0, 1), lcg_float(st, 0, 1), lcg_float(st, 0, 1));
    return b;
}

/* Every shader's batched entry writes exactly the bytes of its per-vertex main, for every normal mode and with and
 * without the per-edge shortcut, on instances of several families and batches that mix instances. */
/* A clip-space coordinate: mostly ordinary values, sometimes huge, zero, tiny, infinite or NaN. */
static float pick_coord(unsigned r)
{
    static const float special[] = { 0.0f, -0.0f, 1.0f, -1.0f, 1e-30f, 1e30f, -1e30f, 3e38f, 1e-45f, NAN, INFINITY,
                                     -INFINITY };
    if (r % 7 == 0) return special[(r / 7) % 12];
    float u = (float)((r >> 4) % 65536u) / 65536.0f - 0.5f;
    return u * ((r / 3) % 3 == 0 ? 1e5f : 4.0f);
}

/* rs_project_vertices (four vertices at a time), in every instruction set's copy this CPU runs, gives exactly
 * rs_project_vertex's records. */
static void test_project_vertices(void **state)
{
    (void)state;
    rs_state st = {0};
    rs_job j = {0};
    j.st = &st;
    j.sx_scale = 1024 * 128.0, j.sy_scale = -768 * 128.0;
    j.gx = (16384.0 - 1.0) / 512.0, j.gy = (16384.0 - 1.0) / 384.0;
    j.zoff = 0.25f, j.zscale = 0.5f;
    enum { N = 1027 };
    rs_vertex *v = calloc(N, sizeof *v);
    size_t sz = rs_pvert_size();
    unsigned char *a = calloc(N, sz), *b = calloc(N, sz);
    assert_non_null(v), assert_non_null(a), assert_non_null(b);
    unsigned r = 12345u;
    for (int round = 0; round < 20; round++) {
        for (int i = 0; i < N; i++) {
            float *p = &v[i].pos.x;
            for (int c = 0; c < 4; c++) r = r * 1103515245u + 12345u, p[c] = pick_coord(r >> 1);
            if (r & 256u) v[i].pos.w = fabsf(v[i].pos.w) + 0.5f; /* half of them in front of the camera */
        }
        memset(b, 0, N * sz);
        for (int i = 0; i < N; i++) rs_kernels_of(RS_ISA_AVX2)->project_vertex(&j, &v[i], (rs_pvert *)(b + (size_t)i * sz));
        for (int isa = 0; isa < RS_ISA_COUNT; isa++) { /* each instruction set's copy this CPU runs */
            if (!rs_isa_supported(isa)) continue;
            memset(a, 0, N * sz);
            rs_kernels_of(isa)->project_vertices(&j, v, N, (rs_pvert *)a);
            assert_memory_equal(a, b, N * sz);
        }
    }
    free(v), free(a), free(b);
}

/* The instruction sets: AVX2 always runs; an unknown value is refused and changes nothing; on a CPU with AVX-512
 * a new device picks it and the same scene-B-like draw through both copies of the kernels gives the same bytes
 * (every check_same above compares both to the reference path too).  Skipped, and reported so, without AVX-512. */
static void test_isa_avx512(void **state)
{
    (void)state;
    char err[256];
    is_device *dev = dev_create(64, 64, 1, err, sizeof err);
    assert_non_null(dev);
    assert_true(rs_isa_supported(RS_ISA_AVX2));
    int own = dev_isa(dev);
    assert_int_equal(dev_set_isa(dev, RS_ISA_COUNT), -1);
    assert_int_equal(dev_set_isa(dev, -1), -1);
    assert_int_equal(dev_isa(dev), own);
    assert_string_equal(rs_isa_name(RS_ISA_AVX512), "avx512");
    assert_int_equal(rs_isa_parse("avx2"), RS_ISA_AVX2);
    assert_int_equal(rs_isa_parse("sse"), -1);
    dev_destroy(dev);
    if (!rs_isa_supported(RS_ISA_AVX512)) {
        print_message("this CPU has no AVX-512: its kernels were not compared\n");
        skip();
    }
    assert_int_equal(own, RS_ISA_AVX512);
    is_mesh m;
    make_cubes(6, &m);
    scene_opts o = scene(12, 256, 192, 2.4f);
    o.threads = 2, o.patch = VS_PATCH_SMOOTH;
    is_device *d[2] = { render_isa(&o, &m, 0, false, RS_ISA_AVX2), render_isa(&o, &m, 0, false, RS_ISA_AVX512) };
    const rs_target *a = dev_render_target(d[0]), *b = dev_render_target(d[1]);
    assert_memory_equal(a->color, b->color, (size_t)a->width * (size_t)a->height * sizeof *a->color);
    assert_memory_equal(a->depth, b->depth, (size_t)a->width * (size_t)a->height * sizeof *a->depth);
    assert_memory_equal(dev_stats(d[0]), dev_stats(d[1]), sizeof(rs_stats));
    assert_true(dev_stats(d[0])->samples_written > 10000);
    dev_destroy(d[0]), dev_destroy(d[1]);
    mesh_free(&m);
}

static void test_shader_batches(void **state)
{
    (void)state;
    enum { N = 100 }; /* not a multiple of 8 or 32: partial lane groups and a short last block */
    is_vs_input *in = calloc(N, sizeof *in), *sh = calloc(N, sizeof *sh), *full = calloc(N, sizeof *full);
    is_vs_output *a = calloc(N, sizeof *a), *b = calloc(N, sizeof *b);
    assert_non_null(in), assert_non_null(sh), assert_non_null(full), assert_non_null(a), assert_non_null(b);
    uint32_t st = 12345u;
    float4x4 wvp = mat_mul(&(float4x4){{{1, 0.2f, 0, 0}, {0, 1, 0.1f, 0}, {0.3f, 0, 1, 1}, {0, 0, 3, 4}}}, &(float4x4){{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}});
    float4x4 world = mat_rotation_y(0.5f);
    for (int s = 0; vs_shaders[s]; s++) {
        if (!vs_shaders[s]->batch) continue;
        for (int mode = 0; mode < 6; mode++) {
            vs_options o = vs_default_options();
            o.normals = (vs_normals)(mode % 3);
            o.flags = mode >= 3 ? VS_FLAG_NO_SHORTCUT : 0u;
            is_vs_constants c;
            memset(&c, 0, sizeof c);
            vs_set_constants(&c, &wvp, &world, f4(0.8f, 0.7f, 0.6f, 1), &o);
            for (int t = 0; t < 10; t++) {
                is_vs_input inst;
                random_instance_regs(&st, t, &inst);
                for (int v = 0; v < N; v++) {
                    in[v] = inst;
                    if (v >= 60 && t % 2) in[v].texcoord[0].x += 0.25f; /* a second instance in the batch */
                    in[v].position[0] = f4_of(random_b(&st, v), 1);
                }
                memset(a, 0, N * sizeof *a), memset(b, 0, N * sizeof *b);
                for (int v = 0; v < N; v++) vs_shaders[s]->main(&c, &in[v], &a[v]);
                vs_shaders[s]->batch(&c, in, N, ~0u, 0, b);
                for (int v = 0; v < N; v++)
                    if (memcmp(&a[v], &b[v], sizeof a[v]) != 0)
                        fail_msg("shader %s mode %d instance %d vertex %d: batch differs", vs_shaders[s]->name, mode, t, v);
                /* only oD0 live (the device's usual link): oPos and oD0 keep the bytes of main */
                memset(b, 0, N * sizeof *b);
                vs_shaders[s]->batch(&c, in, N, IS_OUT_COLOR0, 0, b);
                for (int v = 0; v < N; v++)
                    if (memcmp(&a[v].pos, &b[v].pos, sizeof a[v].pos) != 0 ||
                        memcmp(&a[v].attr[RS_ATTR_COLOR0], &b[v].attr[RS_ATTR_COLOR0], sizeof(rs_vec4)) != 0)
                        fail_msg("shader %s mode %d instance %d vertex %d: batch with oD0 live differs",
                                 vs_shaders[s]->name, mode, t, v);
                if (t % 2) continue;
                /* one instance with its shared registers stored in in[0] only (the device's fused path), the
                 * other vertices' copies poisoned: a shader that read them would differ.  The reference is main
                 * on complete inputs (the shared registers copied from in[0]); with POSITION0 shared every vertex
                 * is in[0]'s point. */
                const int color_reg = (int)(offsetof(is_vs_input, color) / sizeof(float4));
                const uint32_t masks[] = {((1u << (VS_IN_ID + 1)) - 1u) << IS_VS_REG_TEXCOORD,
                                          IS_VS_REGS_INSTANCE, 7u << IS_VS_REG_TEXCOORD,
                                          1u | 7u << IS_VS_REG_TEXCOORD, IS_VS_REGS_ALL,
                                          3u << color_reg};
                for (size_t q = 0; q < sizeof masks / sizeof masks[0]; q++) {
                    for (int v = 0; v < N; v++) {
                        full[v] = sh[v] = in[v];
                        for (int r = 0; r < IS_VS_INPUT_REGS; r++) {
                            if (!(masks[q] & (1u << r)) || v == 0) continue;
                            ((float4 *)&full[v])[r] = ((const float4 *)&in[0])[r];
                            ((float4 *)&sh[v])[r] = f4(NAN, -1e30f, NAN, 7);
                        }
                    }
                    memset(a, 0, N * sizeof *a);
                    for (int v = 0; v < N; v++) vs_shaders[s]->main(&c, &full[v], &a[v]);
                    for (int live = 0; live < 2; live++) {
                        memset(b, 0, N * sizeof *b);
                        vs_shaders[s]->batch(&c, sh, N, live ? IS_OUT_COLOR0 : ~0u, masks[q], b);
                        for (int v = 0; v < N; v++)
                            if (live ? memcmp(&a[v].pos, &b[v].pos, sizeof a[v].pos) != 0 ||
                                           memcmp(&a[v].attr[RS_ATTR_COLOR0], &b[v].attr[RS_ATTR_COLOR0],
                                                  sizeof(rs_vec4)) != 0
                                     : memcmp(&a[v], &b[v], sizeof a[v]) != 0)
                                fail_msg("shader %s mode %d instance %d vertex %d: batch with shared mask %#x "
                                         "(live %s) differs", vs_shaders[s]->name, mode, t, v, masks[q],
                                         live ? "oD0" : "all");
                    }
                }
            }
        }
    }
    free(in), free(sh), free(full), free(a), free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scene_a),
        cmocka_unit_test(test_scene_b),
        cmocka_unit_test(test_scene_c),
        cmocka_unit_test(test_scene_d),
        cmocka_unit_test(test_edge_cases),
        cmocka_unit_test(test_msaa4_states),
        cmocka_unit_test(test_fused_limits),
        cmocka_unit_test(test_large_targets),
        cmocka_unit_test(test_offset_mesh),
        cmocka_unit_test(test_shader_batches),
        cmocka_unit_test(test_project_vertices),
        cmocka_unit_test(test_isa_avx512),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
