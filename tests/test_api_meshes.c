/* tests/test_api_meshes.c -- every public function of meshes/meshes.h with NULL pointers (outputs, labels,
 * arrays, message buffers of 0 and 1 bytes), counts of zero and beyond the limits (refused before anything is
 * read or allocated), meshes emptied or changed by their caller, memory buffers of 0 bytes and of one byte, and
 * paths that are not files.  Each returns its IS_MESH_ERR_* with a message (NUL-terminated in any buffer), leaves
 * the output mesh_free-safe, and never reads past the arrays it was given (ASan in the sanitizer stage).
 * tests/check_api_walkers.sh checks that every INSTESS_API name of meshes/meshes.h is named in this file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../meshes/meshes.h"

static const float3 tet_p[4] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
static const uint32_t tet_i[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};

/* NULL outputs, inputs, labels and message buffers of every size. */
static void test_null_arguments(void **state)
{
    (void)state;
    is_mesh m;
    char err[200], one[1] = {'x'};
    is_mesh_data in = {4, 4, tet_p, NULL, NULL, tet_i};
    assert_int_equal(mesh_create(NULL, "x", &in, NULL, err, sizeof err), IS_MESH_ERR_ARG);
    assert_int_equal(mesh_create(&m, "x", NULL, NULL, err, sizeof err), IS_MESH_ERR_ARG);
    assert_int_equal(mesh_create(&m, NULL, &in, NULL, NULL, 0), IS_MESH_OK);   /* no label, no buffer */
    mesh_free(&m);
    assert_int_equal(mesh_create(&m, "x", &in, NULL, one, sizeof one), IS_MESH_OK);
    mesh_free(&m);
    is_mesh_data no_pos = {4, 4, NULL, NULL, NULL, tet_i}, no_idx = {4, 4, tet_p, NULL, NULL, NULL};
    assert_int_equal(mesh_create(&m, "x", &no_pos, NULL, one, sizeof one), IS_MESH_ERR_ARG);
    assert_int_equal(one[0], 0);
    assert_int_equal(mesh_create(&m, "x", &no_idx, NULL, NULL, 10), IS_MESH_ERR_ARG);
    mesh_free(&m);
    mesh_free(NULL);
    assert_int_equal(mesh_builtin(NULL, &m, err, sizeof err), IS_MESH_ERR_ARG);
    assert_int_equal(mesh_builtin("cube", NULL, err, sizeof err), IS_MESH_ERR_ARG);
    assert_int_equal(mesh_builtin("no such", &m, one, sizeof one), IS_MESH_ERR_ARG);
    assert_int_equal(mesh_builtin_ex(NULL, NULL, NULL, NULL, 0), IS_MESH_ERR_ARG);
    memset(m.texture, 'x', sizeof m.texture);   /* is_mesh.texture: "" after a failed load, never a stale path */
    assert_int_equal(mesh_load_file(NULL, NULL, &m, err, sizeof err), IS_MESH_ERR_ARG);
    assert_string_equal(m.texture, "");
    assert_int_equal(mesh_load_file("x.obj", NULL, NULL, err, sizeof err), IS_MESH_ERR_ARG);
    assert_int_equal(mesh_load_memory(NULL, 10, "obj", NULL, NULL, &m, err, sizeof err), IS_MESH_ERR_ARG);
    assert_int_equal(mesh_load_memory("v 0 0 0", 7, "obj", NULL, NULL, NULL, err, sizeof err), IS_MESH_ERR_ARG);
    assert_int_equal(mesh_open(NULL, NULL, &m, err, sizeof err), IS_MESH_ERR_ARG);
    assert_int_equal(mesh_open("cube", NULL, NULL, err, sizeof err), IS_MESH_ERR_ARG);
    assert_int_equal(mesh_update_topology(NULL, err, sizeof err), IS_MESH_ERR_ARG);
    is_mesh_stats st = mesh_stats(NULL);
    assert_int_equal(st.triangles, 0);
    is_patch_instance inst[4];
    assert_int_equal(mesh_build_instances(NULL, inst), 0);
    assert_int_equal(mesh_builtin("tetrahedron", &m, err, sizeof err), IS_MESH_OK);
    assert_int_equal(mesh_build_instances(&m, NULL), 0);
    assert_int_equal(mesh_build_instances(&m, inst), 4);
    mesh_free(&m);
    mesh_library_versions(NULL, 100);
    mesh_library_versions(one, 0);
    mesh_library_versions(one, 1);
    assert_int_equal(one[0], 0);
    const char *const *names = mesh_builtin_names();
    for (size_t k = 0; names[k]; k++) {
        assert_int_equal(mesh_builtin(names[k], &m, err, sizeof err), IS_MESH_OK);
        mesh_free(&m);
    }
    assert_int_equal(mesh_patch_declaration[MESH_PATCH_DECLARATION_COUNT - 1].stream, 0xFF);
}

/* Counts of zero and beyond the limits: refused before the arrays are read (the arrays here hold 4 vertices and
 * 4 triangles: reading further is an ASan error). */
static void test_counts(void **state)
{
    (void)state;
    is_mesh m;
    char err[200];
    const size_t bad_v[] = {0, UINT32_MAX, (size_t)UINT32_MAX + 5, SIZE_MAX};
    for (size_t k = 0; k < sizeof bad_v / sizeof bad_v[0]; k++) {
        is_mesh_data in = {bad_v[k], 4, tet_p, NULL, NULL, tet_i};
        int rc = mesh_create(&m, "big", &in, NULL, err, sizeof err);
        assert_true(rc == IS_MESH_ERR_INVALID || rc == IS_MESH_ERR_EMPTY);
        assert_null(m.positions);
        mesh_free(&m);
    }
    const size_t bad_t[] = {0, SIZE_MAX, SIZE_MAX / 3, SIZE_MAX / 48 + 1};
    for (size_t k = 0; k < sizeof bad_t / sizeof bad_t[0]; k++) {
        is_mesh_data in = {4, bad_t[k], tet_p, NULL, NULL, tet_i};
        int rc = mesh_create(&m, "big", &in, NULL, err, sizeof err);
        assert_true(rc == IS_MESH_ERR_INVALID || rc == IS_MESH_ERR_EMPTY);
        mesh_free(&m);
    }
    /* an index past the vertices, non-finite positions and texcoords, NaN and zero normals */
    uint32_t idx[12];
    memcpy(idx, tet_i, sizeof idx);
    idx[7] = UINT32_MAX;
    is_mesh_data bad_idx = {4, 4, tet_p, NULL, NULL, idx};
    assert_int_equal(mesh_create(&m, "x", &bad_idx, NULL, err, sizeof err), IS_MESH_ERR_INVALID);
    assert_non_null(strstr(err, "out of range"));
    float3 p[4], n[4] = {{NAN, 0, 0}, {0, 0, 0}, {INFINITY, 1, 0}, {1e-45f, 0, 0}};
    float2 t[4] = {{0, 0}, {1, 1}, {NAN, 0}, {0, 0}};
    memcpy(p, tet_p, sizeof p);
    is_mesh_data with_t = {4, 4, p, n, t, tet_i};
    assert_int_equal(mesh_create(&m, "x", &with_t, NULL, err, sizeof err), IS_MESH_ERR_INVALID);
    t[2].x = 0;
    assert_int_equal(mesh_create(&m, "x", &with_t, NULL, err, sizeof err), IS_MESH_OK);   /* normals replaced */
    assert_true(m.stats.normals_replaced >= 3);
    mesh_free(&m);
    p[2].y = NAN;
    assert_int_equal(mesh_create(&m, "x", &with_t, NULL, err, sizeof err), IS_MESH_ERR_INVALID);
    p[2] = (float3){FLT_MAX, -FLT_MAX, FLT_MAX};
    int rc = mesh_create(&m, "x", &with_t, NULL, err, sizeof err);
    assert_true(rc == IS_MESH_OK || rc == IS_MESH_ERR_EMPTY);
    mesh_free(&m);
}

/* Meshes emptied or changed by their caller: mesh_update_topology refuses indices past the vertices, takes an
 * empty mesh; mesh_build_instances and mesh_stats read only what the mesh holds. */
static void test_changed_meshes(void **state)
{
    (void)state;
    is_mesh m;
    char err[200];
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), IS_MESH_OK);
    m.indices[5] = (uint32_t)m.n_vertices;   /* one past the last */
    assert_int_equal(mesh_update_topology(&m, err, sizeof err), IS_MESH_ERR_INVALID);
    assert_non_null(strstr(err, "out of range"));
    m.indices[5] = 0;
    m.positions[3] = (float3){NAN, 0, 0};
    assert_true(mesh_update_topology(&m, err, sizeof err) == IS_MESH_OK);   /* positions are the caller's */
    mesh_free(&m);
    is_mesh empty;
    memset(&empty, 0, sizeof empty);
    assert_int_equal(mesh_update_topology(&empty, err, sizeof err), IS_MESH_OK);
    is_patch_instance inst;
    assert_int_equal(mesh_build_instances(&empty, &inst), 0);
    assert_int_equal(mesh_stats(&empty).triangles, 0);
    mesh_free(&empty);
    (void)mesh_compute_face_normal((float3){0, 0, 0}, (float3){0, 0, 0}, (float3){0, 0, 0});
    (void)mesh_compute_face_normal((float3){NAN, 0, 0}, (float3){INFINITY, 1, 0}, (float3){FLT_MAX, -FLT_MAX, 0});
    float3 f = mesh_compute_face_normal((float3){0, 0, 0}, (float3){0, 1e-30f, 0}, (float3){1e-30f, 0, 0});
    assert_true(f.z == -1.0f);   /* tiny triangles have a unit normal too (double) */
}

/* Memory buffers of 0 bytes, one byte, and bytes that are no mesh; paths that are not files. */
static void test_inputs(void **state)
{
    (void)state;
    is_mesh m;
    char err[300];
    is_mesh_options opt = {.in_process = true};
    assert_int_equal(mesh_load_memory("", 0, "obj", "empty", &opt, &m, err, sizeof err), IS_MESH_ERR_IO);
    int rc = mesh_load_memory("v", 1, "obj", "one", &opt, &m, err, sizeof err);
    assert_true(rc < 0);
    mesh_free(&m);
    rc = mesh_load_memory("\x00\x01\x02\x03", 4, NULL, NULL, &opt, &m, err, sizeof err);
    assert_true(rc < 0);
    mesh_free(&m);
    rc = mesh_load_memory("v 0 0 0\n", 8, "no-such-format", "x", &opt, &m, err, sizeof err);
    assert_true(rc < 0);
    mesh_free(&m);
    const char *paths[] = {"", "/", "/dev/null", "/nonexistent/dir/x.obj", ".", "no-extension"};
    for (size_t k = 0; k < sizeof paths / sizeof paths[0]; k++) {
        assert_true(mesh_load_file(paths[k], NULL, &m, err, sizeof err) < 0);
        assert_true(strlen(err) > 0);
        assert_string_equal(m.texture, "");
        mesh_free(&m);
        assert_true(mesh_open(paths[k], NULL, &m, err, sizeof err) < 0);
        mesh_free(&m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_null_arguments),
        cmocka_unit_test(test_counts),
        cmocka_unit_test(test_changed_meshes),
        cmocka_unit_test(test_inputs),
    };
    return cmocka_run_group_tests_name("api_meshes", tests, NULL, NULL);
}
