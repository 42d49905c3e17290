/* tests/test_api_tess.c -- every public function of tess/tess.h with NULL devices, meshes, grids, caches and
 * outputs, permutations that are not permutations, LOD parameters out of range (levels 0, negative, above 64,
 * min above max, targets 0, negative and NaN), bucket numbers past the last, and smoothness sample counts of 0
 * and INT_MAX.  Each returns its error or clamps as tess.h says, never indexes past an array (ASan in the
 * sanitizer stage) and never loops for ever.
 * tests/check_api_walkers.sh checks that every INSTESS_API function of tess/tess.h is named in this file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../tess/tess.h"

/* NULL everywhere. */
static void test_null(void **state)
{
    (void)state;
    char err[200];
    tess_resources_free(NULL);
    tess_adaptive_free(NULL);
    tess_lod_edges_free(NULL);
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_mesh m;
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);
    core_grid g;
    assert_int_equal(core_grid_make(CORE_GRID_REGULAR, 2, &g), 0);
    tess_resources r = {0};
    is_index_buffer *ib = NULL;
    const uint32_t idx[3] = {0, 1, 2};
    assert_int_equal(tess_index_buffer(NULL, idx, 3, 3, &ib), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_index_buffer(dev, NULL, 3, 3, &ib), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_index_buffer(dev, idx, 3, 3, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_index_buffer(dev, idx, 0, 3, &ib), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_index_buffer(dev, idx, SIZE_MAX / 2, 3, &ib), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_instanced(NULL, &m, &g, &r), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_instanced(dev, NULL, &g, &r), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_instanced(dev, &m, NULL, &r), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_instanced(dev, &m, &g, NULL), IS_ERR_INVALIDCALL);
    core_grid empty = {0};
    assert_int_equal(tess_bind_instanced(dev, &m, &empty, &r), IS_ERR_INVALIDCALL);
    tess_resources_free(&r);
    is_vs_input in;
    tess_input_from_instance(NULL, NULL, (float3){1, 0, 0}, &in);
    is_patch_instance inst[12];
    assert_int_equal(mesh_build_instances(&m, inst), 12);
    tess_input_from_instance(&inst[0], NULL, (float3){1, 0, 0}, NULL);
    float3 (*nadj)[3][2] = malloc(m.n_triangles * sizeof *nadj);
    assert_int_equal(tess_adjacent_normals(NULL, nadj), -1);
    assert_int_equal(tess_adjacent_normals(&m, NULL), -1);
    assert_int_equal(tess_adjacent_normals(&m, nadj), 0);
    float3 out[3][2];
    tess_permute_adjacent_normals(NULL, (const uint8_t[3]){0, 1, 2}, out);
    tess_permute_adjacent_normals(nadj[0], NULL, out);
    tess_permute_adjacent_normals(nadj[0], (const uint8_t[3]){0, 1, 2}, NULL);
    is_patch_instance pi;
    tess_permute_instance(NULL, (const uint8_t[3]){0, 1, 2}, &pi);
    tess_permute_instance(&inst[0], NULL, &pi);
    tess_permute_instance(&inst[0], (const uint8_t[3]){0, 1, 2}, NULL);
    tess_lod_edges e;
    assert_int_equal(tess_lod_edges_build(NULL, &e, err, sizeof err), -1);
    assert_int_equal(tess_lod_edges_build(&m, NULL, err, sizeof err), -1);
    assert_int_equal(tess_lod_edges_build(&m, &e, err, sizeof err), 0);
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    tess_lod_params p = {.mode = TESS_LOD_UNIFORM, .min_level = 1, .max_level = 4, .width = 8, .height = 8};
    tess_lod_levels(NULL, &m, &e, hist);
    tess_lod_levels(&p, NULL, &e, hist);
    tess_lod_levels(&p, &m, NULL, hist);
    tess_lod_levels(&p, &m, &e, NULL);
    core_pattern_cache *cache = core_pattern_cache_create(0);
    tess_adaptive a = {0};
    tess_lod_levels(&p, &m, &e, hist);
    assert_int_equal(tess_bind_adaptive(NULL, &m, &e, cache, &a), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_adaptive(dev, NULL, &e, cache, &a), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_adaptive(dev, &m, NULL, cache, &a), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_adaptive(dev, &m, &e, NULL, &a), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_adaptive(dev, &m, &e, cache, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_rebind_adaptive(NULL, &m, &e, cache, &a), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_rebind_adaptive(dev, NULL, &e, cache, &a), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_rebind_adaptive(dev, &m, NULL, cache, &a), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_rebind_adaptive(dev, &m, &e, NULL, &a), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_rebind_adaptive(dev, &m, &e, cache, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(a.n_buckets, 0);
    assert_int_equal(tess_bind_adjacent_normals(NULL, &m, &r, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_adjacent_normals(dev, NULL, &r, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_adjacent_normals(dev, &m, NULL, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_draw_bucket(NULL, &a, 0), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_draw_bucket(dev, NULL, 0), IS_ERR_INVALIDCALL);
    vs_smoothness_result res;
    assert_int_equal(tess_smoothness(NULL, VS_PATCH_SMOOTH, NULL, 4, &res), -1);
    assert_int_equal(tess_smoothness(&m, VS_PATCH_SMOOTH, NULL, 4, NULL), -1);
    tess_adaptive_free(&a);
    core_pattern_cache_destroy(cache);
    tess_lod_edges_free(&e);
    free(nadj);
    core_grid_free(&g);
    mesh_free(&m);
    dev_destroy(dev);
}

/* Permutations that are not permutations (values past 2, repeated): read as the identity, nothing past the
 * instance read. */
static void test_permutations(void **state)
{
    (void)state;
    is_patch_instance in, out;
    memset(&in, 0, sizeof in);
    for (int k = 0; k < 3; k++) in.v[k] = (float3){(float)k, 0, 0};
    float3 nin[3][2], nout[3][2];
    memset(nin, 0, sizeof nin);
    const uint8_t bad[][3] = {{3, 0, 1}, {255, 254, 253}, {0, 0, 0}, {1, 1, 2}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        tess_permute_instance(&in, bad[k], &out);
        for (int i = 0; i < 3; i++) assert_true(out.v[i].x == (float)i);
        tess_permute_adjacent_normals(nin, bad[k], nout);
    }
    tess_permute_instance(&in, (const uint8_t[3]){2, 0, 1}, &out);
    assert_true(out.v[0].x == 2.0f);
}

/* LOD parameters out of range: the levels stay in 1..64 and the histogram's bounds (a min_level of 1000 wrote
 * hist[1000]); bucket numbers past the last are refused; smoothness sample counts are bounded. */
static void test_lod_params(void **state)
{
    (void)state;
    char err[200];
    is_mesh m;
    assert_int_equal(mesh_builtin("sphere", &m, err, sizeof err), 0);
    tess_lod_edges e;
    assert_int_equal(tess_lod_edges_build(&m, &e, err, sizeof err), 0);
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    const int levels[][2] = {{1, 64}, {0, 0}, {-5, -1}, {1000, 2000}, {64, 1}, {INT_MIN, INT_MAX}, {30, 20}};
    const float targets[] = {8.0f, 0.0f, -1.0f, NAN, INFINITY, 1e-45f};
    float4x4 wv = mat_translation(0, 0, 3), proj = mat_perspective_fov_lh(1.0f, 1.0f, 0.1f, 10.0f);
    for (int mode = TESS_LOD_UNIFORM; mode <= TESS_LOD_DEVIATION; mode++)
        for (size_t l = 0; l < sizeof levels / sizeof levels[0]; l++)
            for (size_t t = 0; t < sizeof targets / sizeof targets[0]; t++) {
                tess_lod_params p = {.mode = (tess_lod_mode)mode, .target_px = targets[t], .ref_depth = targets[t],
                                     .min_level = levels[l][0], .max_level = levels[l][1], .width = 64, .height = 64,
                                     .silhouette = t % 2, .world_view = wv, .wvp = mat_mul(&wv, &proj)};
                tess_lod_levels(&p, &m, &e, hist);
                uint64_t sum = 0;
                for (int k = 0; k <= CORE_LOD_MAX_LEVEL; k++) sum += hist[k];
                assert_int_equal(sum, e.n_edges);
                assert_int_equal(hist[0], 0);
                for (size_t k = 0; k < e.n_edges; k++) assert_true(e.level[k] >= 1 && e.level[k] <= CORE_LOD_MAX_LEVEL);
            }
    /* the buckets of the last levels, drawn; a bucket past the last refused */
    is_device *dev = dev_create(16, 16, 1, NULL, 0);
    core_pattern_cache *cache = core_pattern_cache_create(0);
    tess_adaptive a;
    assert_int_equal(tess_bind_adaptive(dev, &m, &e, cache, &a), IS_OK);
    assert_int_equal(dev_set_vertex_shader(dev, vs_patch_shader(VS_PATCH_FLAT)), IS_OK);
    assert_int_equal(tess_draw_bucket(dev, &a, a.n_buckets), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_draw_bucket(dev, &a, SIZE_MAX), IS_ERR_INVALIDCALL);
    assert_int_equal(tess_bind_adjacent_normals(dev, &m, &a.r, &a), IS_OK);
    tess_adaptive_free(&a);
    core_pattern_cache_destroy(cache);
    dev_destroy(dev);
    vs_smoothness_result res;
    assert_int_equal(tess_smoothness(&m, VS_PATCH_SMOOTH, NULL, 0, &res), -1);
    assert_int_equal(tess_smoothness(&m, VS_PATCH_SMOOTH, NULL, -3, &res), -1);
    assert_int_equal(tess_smoothness(&m, VS_PATCH_SMOOTH, NULL, INT_MAX, &res), -1);   /* would not end */
    assert_int_equal(tess_smoothness(&m, (vs_patch)VS_PATCH_COUNT, NULL, 4, &res), -1);
    assert_int_equal(tess_smoothness(&m, VS_PATCH_NPATCH, NULL, 2, &res), 0);
    tess_lod_edges_free(&e);
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_null),
        cmocka_unit_test(test_permutations),
        cmocka_unit_test(test_lod_params),
    };
    return cmocka_run_group_tests_name("api_tess", tests, NULL, NULL);
}
