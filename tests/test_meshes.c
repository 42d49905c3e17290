/* tests/test_meshes.c -- built-in meshes, import through assimp, validation, normals, instances (meshes/). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../meshes/meshes.h"

#define FAERIE "/usr/share/assimp/models/MD2/faerie.md2"

/* Path of a test data file: tests/data/meshes/<name>, found next to this source file. */
static const char *data_path(const char *name)
{
    static char buf[1024];   /* test-only scratch */
    const char *file = __FILE__, *slash = strrchr(file, '/');
    int dir = slash ? (int)(slash - file) : 1;
    snprintf(buf, sizeof buf, "%.*s/data/meshes/%s", dir, slash ? file : ".", name);
    return buf;
}

/* Load a built-in or fail the test. */
static is_mesh load_builtin(const char *name)
{
    is_mesh m;
    char err[512] = "";
    int rc = mesh_builtin(name, &m, err, sizeof err);
    if (rc != 0) fail_msg("%s: %s", name, err);
    return m;
}

/* Load a data file or fail the test. */
static is_mesh load_data(const char *name, const is_mesh_options *opt)
{
    is_mesh m;
    char err[512] = "";
    int rc = mesh_load_file(data_path(name), opt, &m, err, sizeof err);
    if (rc != 0) fail_msg("%s: %s", name, err);
    return m;
}

/* Bitwise equality of positions (the weld criterion, without -0). */
static bool same_pos(float3 a, float3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/* The first vertex with the same position as v (an independent O(n^2) weld). */
static size_t weld_of(const is_mesh *m, size_t v)
{
    for (size_t u = 0; u < v; u++)
        if (same_pos(m->positions[u], m->positions[v])) return u;
    return v;
}

/* Count triangles using the directed welded edge a -> b. */
static int count_directed(const is_mesh *m, size_t a, size_t b)
{
    int n = 0;
    for (size_t t = 0; t < m->n_triangles; t++)
        for (int k = 0; k < 3; k++)
            if (weld_of(m, m->indices[3 * t + k]) == a && weld_of(m, m->indices[3 * t + (k + 1) % 3]) == b) n++;
    return n;
}

/* Closed and consistently wound: every directed edge once, and its reverse once. */
static void assert_closed_consistent(const is_mesh *m)
{
    for (size_t t = 0; t < m->n_triangles; t++)
        for (int k = 0; k < 3; k++) {
            size_t a = weld_of(m, m->indices[3 * t + k]), b = weld_of(m, m->indices[3 * t + (k + 1) % 3]);
            if (count_directed(m, a, b) != 1 || count_directed(m, b, a) != 1)
                fail_msg("%s: triangle %zu edge %d: used %d times forward, %d backward", m->name, t, k,
                         count_directed(m, a, b), count_directed(m, b, a));
        }
    assert_int_equal(m->stats.boundary_edges, 0);
    assert_int_equal(m->stats.nonmanifold_edges, 0);
    assert_int_equal(m->stats.inconsistent_edges, 0);
}

/* cross(v1 - v0, v2 - v0) of triangle t, computed here (not by the library). */
static float3 raw_face_normal(const is_mesh *m, size_t t)
{
    const uint32_t *x = m->indices + 3 * t;
    return cross3(sub3(m->positions[x[1]], m->positions[x[0]]), sub3(m->positions[x[2]], m->positions[x[0]]));
}

/* Centroid of triangle t. */
static float3 tri_centroid(const is_mesh *m, size_t t)
{
    const uint32_t *x = m->indices + 3 * t;
    return scale3(add3(add3(m->positions[x[0]], m->positions[x[1]]), m->positions[x[2]]), 1.0f / 3.0f);
}

/* Every face normal points away from `centre` (for convex meshes). */
static void assert_outward(const is_mesh *m, float3 centre)
{
    for (size_t t = 0; t < m->n_triangles; t++)
        if (!(dot3(raw_face_normal(m, t), sub3(tri_centroid(m, t), centre)) > 0.0f))
            fail_msg("%s: triangle %zu faces inward", m->name, t);
}

/* Vertex normals unit length, texcoords finite. */
static void assert_unit_normals(const is_mesh *m)
{
    for (size_t v = 0; v < m->n_vertices; v++) {
        assert_true(fabsf(length3(m->normals[v]) - 1.0f) < 1e-5f);
        assert_true(isfinite(m->texcoords[v].x) && isfinite(m->texcoords[v].y));
    }
}

/* ------------------------------------------------ built-ins ------------------------------------------------ */

/* Every built-in: closed, consistent, outward faces and normals, unit normals, sane texcoords. */
static void test_builtins_closed_outward(void **state)
{
    (void)state;
    size_t count = 0;
    for (const char *const *n = mesh_builtin_names(); *n; n++, count++) {
        is_mesh m = load_builtin(*n);
        assert_string_equal(m.name, *n);
        assert_closed_consistent(&m);
        assert_outward(&m, f3(0, 0, 0));
        assert_unit_normals(&m);
        for (size_t v = 0; v < m.n_vertices; v++) {
            if (!(dot3(m.normals[v], m.positions[v]) > 0.0f)) fail_msg("%s: vertex %zu normal inward", *n, v);
            assert_true(m.texcoords[v].x >= 0.0f && m.texcoords[v].x <= 2.0f);
            assert_true(m.texcoords[v].y >= 0.0f && m.texcoords[v].y <= 1.0f);
            for (int c = 0; c < 3; c++) assert_true(fabsf((&m.positions[v].x)[c]) <= 1.0f);
        }
        assert_int_equal(m.stats.degenerates_dropped, 0);
        assert_int_equal(m.stats.normals_replaced, 0);
        assert_false(m.stats.normals_computed);
        mesh_free(&m);
    }
    assert_int_equal(count, 7);
}

/* Expected vertex / welded / triangle counts. */
static void test_builtin_counts(void **state)
{
    (void)state;
    static const struct { const char *name; size_t v, w, t; } want[] = {
        {"tetrahedron", 4, 4, 4}, {"cube", 8, 8, 12}, {"cube-split", 24, 8, 12}, {"octahedron", 6, 6, 8},
        {"icosahedron", 12, 12, 20}, {"sphere", 0, 42, 80}, {"cylinder", 0, 26, 48}};
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        is_mesh m = load_builtin(want[i].name);
        if (want[i].v) assert_int_equal(m.n_vertices, want[i].v);
        assert_int_equal(m.stats.welded_vertices, want[i].w);
        assert_int_equal(m.n_triangles, want[i].t);
        assert_int_equal(m.stats.triangles, want[i].t);
        assert_int_equal(m.stats.edges, 3 * want[i].t / 2);
        mesh_free(&m);
    }
}

/* Tetrahedron: regular (all 6 edges equal), normals = directions from the centre. */
static void test_tetrahedron_regular(void **state)
{
    (void)state;
    is_mesh m = load_builtin("tetrahedron");
    float l0 = length3(sub3(m.positions[0], m.positions[1]));
    for (size_t a = 0; a < 4; a++)
        for (size_t b = a + 1; b < 4; b++) assert_float_equal(length3(sub3(m.positions[a], m.positions[b])), l0, 1e-6);
    for (size_t v = 0; v < 4; v++)
        assert_true(dot3(m.normals[v], normalize3(m.positions[v])) > 0.999999f);
    mesh_free(&m);
}

/* Cube: side 2 at the origin, normals along the diagonals. */
static void test_cube_diagonal_normals(void **state)
{
    (void)state;
    is_mesh m = load_builtin("cube");
    const float s = 1.0f / sqrtf(3.0f);
    for (size_t v = 0; v < 8; v++) {
        float3 p = m.positions[v], n = m.normals[v];
        assert_true(fabsf(p.x) == 1.0f && fabsf(p.y) == 1.0f && fabsf(p.z) == 1.0f);
        assert_float_equal(n.x, p.x * s, 1e-6);
        assert_float_equal(n.y, p.y * s, 1e-6);
        assert_float_equal(n.z, p.z * s, 1e-6);
    }
    mesh_free(&m);
}

/* Whether n is a unit axis vector. */
static bool axis_aligned(float3 n)
{
    int ones = (fabsf(n.x) == 1.0f) + (fabsf(n.y) == 1.0f) + (fabsf(n.z) == 1.0f);
    int zeros = (n.x == 0.0f) + (n.y == 0.0f) + (n.z == 0.0f);
    return ones == 1 && zeros == 2;
}

/* Every vertex normal axis-aligned and equal to the face normal of each of its triangles. */
static void assert_face_normals_axis(const is_mesh *m)
{
    for (size_t t = 0; t < m->n_triangles; t++) {
        float3 fn = normalize3(raw_face_normal(m, t));
        for (int k = 0; k < 3; k++) {
            float3 n = m->normals[m->indices[3 * t + k]];
            assert_true(axis_aligned(n));
            assert_true(dot3(n, fn) > 0.999999f);
        }
    }
}

/* cube-split: 24 vertices, face normals, full texture per face. */
static void test_cube_split_face_normals(void **state)
{
    (void)state;
    is_mesh m = load_builtin("cube-split");
    assert_face_normals_axis(&m);
    for (size_t v = 0; v < m.n_vertices; v++) {
        float2 t = m.texcoords[v];
        assert_true((t.x == 0.0f || t.x == 1.0f) && (t.y == 0.0f || t.y == 1.0f));
    }
    mesh_free(&m);
}

/* Sphere: radius 1, normals = positions. */
static void test_sphere_normals(void **state)
{
    (void)state;
    is_mesh m = load_builtin("sphere");
    for (size_t v = 0; v < m.n_vertices; v++) {
        assert_float_equal(length3(m.positions[v]), 1.0f, 1e-6);
        assert_true(dot3(m.normals[v], m.positions[v]) > 0.999999f);
    }
    mesh_free(&m);
}

/* Cylinder: every rim position carries two normals (flat cap, smooth side): a sharp edge. */
static void test_cylinder_sharp_rim(void **state)
{
    (void)state;
    is_mesh m = load_builtin("cylinder");
    size_t rim = 0;
    for (size_t v = 0; v < m.n_vertices; v++) {
        float3 p = m.positions[v];
        if (fabsf(p.y) != 1.0f || (p.x == 0.0f && p.z == 0.0f)) continue;
        bool cap = false, side = false;
        for (size_t u = 0; u < m.n_vertices; u++) {
            if (!same_pos(m.positions[u], p)) continue;
            float3 n = m.normals[u];
            cap |= n.x == 0.0f && n.z == 0.0f && n.y == p.y;
            side |= n.y == 0.0f && dot3(n, p) > 0.99f;
        }
        assert_true(cap && side);
        rim++;
    }
    assert_true(rim >= 48);   /* 2 rims x 12, each position at least twice */
    mesh_free(&m);
}

/* Unknown names fail with a message naming them; mesh_open chooses built-ins by name. */
static void test_builtin_unknown_and_open(void **state)
{
    (void)state;
    is_mesh m;
    char err[512] = "";
    assert_int_equal(mesh_builtin("dodecahedron", &m, err, sizeof err), IS_MESH_ERR_ARG);
    assert_non_null(strstr(err, "dodecahedron"));
    assert_null(m.positions);
    mesh_free(&m);
    assert_int_equal(mesh_open("cube-split", NULL, &m, err, sizeof err), 0);
    assert_int_equal(m.n_vertices, 24);
    mesh_free(&m);
    assert_int_equal(mesh_open("nosuchmesh", NULL, &m, err, sizeof err), IS_MESH_ERR_ARG);
    assert_non_null(strstr(err, "nosuchmesh"));
}

/* The convention's worked example: clockwise seen from a camera at -z looking +z faces that camera. */
static void test_face_normal_convention(void **state)
{
    (void)state;
    float3 n = mesh_compute_face_normal(f3(0, 0, 0), f3(0, 1, 0), f3(1, 0, 0));
    assert_true(n.x == 0.0f && n.y == 0.0f && n.z == -1.0f);
    n = mesh_compute_face_normal(f3(0, 0, 0), f3(1, 0, 0), f3(0, 1, 0));
    assert_true(n.z == 1.0f);
    n = mesh_compute_face_normal(f3(0, 0, 0), f3(1, 1, 1), f3(2, 2, 2));
    assert_true(n.x == 0.0f && n.y == 0.0f && n.z == 0.0f);
    n = mesh_compute_face_normal(f3(0, 0, 0), f3(3e38f, 0, 0), f3(0, 3e38f, 0));   /* no overflow */
    assert_true(n.z == 1.0f);
}

/* ------------------------------------------------ import ------------------------------------------------ */

/* box.obj (counter-clockwise, right-handed): 8 / 12, mirrored z, outward under our convention. */
static void test_import_obj(void **state)
{
    (void)state;
    is_mesh m = load_data("box.obj", NULL);
    assert_int_equal(m.n_vertices, 8);
    assert_int_equal(m.n_triangles, 12);
    assert_true(m.stats.normals_computed);
    assert_closed_consistent(&m);
    for (size_t v = 0; v < 8; v++) {                   /* x in [0,1], y in [0,2], z in [-3,0]: z mirrored */
        float3 p = m.positions[v];
        assert_true(p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 2 && p.z >= -3 && p.z <= 0);
    }
    assert_outward(&m, f3(0.5f, 1.0f, -1.5f));
    assert_unit_normals(&m);
    for (size_t v = 0; v < 8; v++)
        assert_true(dot3(m.normals[v], sub3(m.positions[v], f3(0.5f, 1.0f, -1.5f))) > 0.0f);
    mesh_free(&m);
}

/* tetra.off: 4 / 4, outward. */
static void test_import_off(void **state)
{
    (void)state;
    is_mesh m = load_data("tetra.off", NULL);
    assert_int_equal(m.n_vertices, 4);
    assert_int_equal(m.n_triangles, 4);
    assert_closed_consistent(&m);
    assert_outward(&m, f3(0, 0, 0));
    mesh_free(&m);
}

/* cube_normals.ply: 24 / 12 with the file's face normals kept. */
static void test_import_ply(void **state)
{
    (void)state;
    is_mesh m = load_data("cube_normals.ply", NULL);
    assert_int_equal(m.n_vertices, 24);
    assert_int_equal(m.n_triangles, 12);
    assert_int_equal(m.stats.welded_vertices, 8);
    assert_false(m.stats.normals_computed);
    assert_int_equal(m.stats.normals_replaced, 0);
    assert_closed_consistent(&m);
    assert_outward(&m, f3(0, 0, 0));
    assert_face_normals_axis(&m);
    mesh_free(&m);
}

/* tetra.stl: facet normals split the 4 positions into 12 vertices. */
static void test_import_stl(void **state)
{
    (void)state;
    is_mesh m = load_data("tetra.stl", NULL);
    assert_int_equal(m.n_vertices, 12);
    assert_int_equal(m.n_triangles, 4);
    assert_int_equal(m.stats.welded_vertices, 4);
    assert_closed_consistent(&m);
    assert_outward(&m, f3(0, 0, 0));
    for (size_t t = 0; t < 4; t++)
        for (int k = 0; k < 3; k++)
            assert_true(dot3(m.normals[m.indices[3 * t + k]], normalize3(raw_face_normal(&m, t))) > 0.99999f);
    mesh_free(&m);
}

/* Read a whole file into memory (test helper). */
static char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    char *buf = malloc(65536);
    *size = fread(buf, 1, 65536, f);
    fclose(f);
    return buf;
}

/* Import from memory: same result as the file; empty and garbage buffers fail naming the label. */
static void test_import_memory(void **state)
{
    (void)state;
    size_t size;
    char *buf = read_all(data_path("box.obj"), &size), err[512] = "";
    is_mesh m;
    assert_int_equal(mesh_load_memory(buf, size, "obj", "box-in-memory", NULL, &m, err, sizeof err), 0);
    assert_int_equal(m.n_vertices, 8);
    assert_int_equal(m.n_triangles, 12);
    assert_string_equal(m.name, "box-in-memory");
    mesh_free(&m);
    assert_true(mesh_load_memory(buf, 0, "obj", "empty-buf", NULL, &m, err, sizeof err) < 0);
    assert_non_null(strstr(err, "empty-buf"));
    static const char junk[] = "\x01\x02garbage \xff\xfe not a mesh";
    assert_true(mesh_load_memory(junk, sizeof junk, "ply", "junk-buf", NULL, &m, err, sizeof err) < 0);
    assert_non_null(strstr(err, "junk-buf"));
    assert_null(m.positions);
    free(buf);
}

/* Fraction of triangles whose face normal agrees with the sum of their vertex normals. */
static double winding_agreement(const is_mesh *m)
{
    size_t agree = 0;
    for (size_t t = 0; t < m->n_triangles; t++) {
        const uint32_t *x = m->indices + 3 * t;
        float3 vn = add3(add3(m->normals[x[0]], m->normals[x[1]]), m->normals[x[2]]);
        agree += dot3(raw_face_normal(m, t), vn) > 0.0f;
    }
    return (double)agree / (double)m->n_triangles;
}

/* The MD2 faerie of assimp-testmodels loads; its winding agrees with its own normals after conversion. */
static void test_import_md2_faerie(void **state)
{
    (void)state;
    if (access(FAERIE, R_OK) != 0) {
        print_message("SKIP: %s is absent (install assimp-testmodels)\n", FAERIE);
        skip();
    }
    is_mesh m;
    char err[512] = "";
    assert_int_equal(mesh_load_file(FAERIE, NULL, &m, err, sizeof err), 0);
    print_message("faerie: %zu vertices (%zu welded), %zu triangles, %zu boundary / %zu non-manifold edges\n",
                  m.n_vertices, m.stats.welded_vertices, m.n_triangles, m.stats.boundary_edges,
                  m.stats.nonmanifold_edges);
    assert_true(m.n_triangles > 500);
    assert_true(m.stats.welded_vertices < m.n_vertices);
    assert_false(m.stats.normals_computed);
    assert_unit_normals(&m);
    for (size_t i = 0; i < 3 * m.n_triangles; i++) {
        assert_true(m.indices[i] < m.n_vertices);
        assert_true(m.opposite[i] < m.n_vertices);
    }
    assert_true(winding_agreement(&m) > 0.95);
    mesh_free(&m);
}

/* Load a data file expecting failure code rc with the path and `what` in the message. */
static void expect_load_error(const char *path, int rc, const char *what)
{
    is_mesh m;
    char err[512] = "";
    int got = mesh_load_file(path, NULL, &m, err, sizeof err);
    print_message("  %s -> %d: %s\n", path, got, err);
    if (got >= 0) fail_msg("%s loaded", path);
    if (rc) assert_int_equal(got, rc);
    assert_non_null(strstr(err, path));
    if (what) assert_non_null(strstr(err, what));
    assert_null(m.positions);
    mesh_free(&m);
}

/* Missing / directory / empty / garbage / unknown extension / NaN / bad index / no triangles. */
static void test_import_errors(void **state)
{
    (void)state;
    char p[1024];
    snprintf(p, sizeof p, "%s", data_path("does-not-exist.obj"));
    expect_load_error(p, IS_MESH_ERR_IO, "cannot open");
    snprintf(p, sizeof p, "%s", data_path(""));
    expect_load_error(p, IS_MESH_ERR_IO, "directory");
    snprintf(p, sizeof p, "%s", data_path("empty.obj"));
    expect_load_error(p, IS_MESH_ERR_IO, "empty");
    snprintf(p, sizeof p, "%s", data_path("garbage.obj"));
    expect_load_error(p, 0, NULL);
    snprintf(p, sizeof p, "%s", data_path("garbage.ply"));
    expect_load_error(p, IS_MESH_ERR_FORMAT, NULL);
    snprintf(p, sizeof p, "%s", data_path("box.xyz"));
    expect_load_error(p, IS_MESH_ERR_FORMAT, "unknown");
    snprintf(p, sizeof p, "%s", data_path("nan.obj"));
    expect_load_error(p, IS_MESH_ERR_INVALID, "vertex 1");
    snprintf(p, sizeof p, "%s", data_path("badindex.obj"));
    expect_load_error(p, 0, "out of range");
    snprintf(p, sizeof p, "%s", data_path("lines.obj"));
    expect_load_error(p, IS_MESH_ERR_EMPTY, "no triangles");
}

/* assimp 5.2.5 hangs on a truncated PLY header and aborts (ai_assert in its Triangulate step) on a corrupted
 * PLY: the import runs in a child process, so both become errors naming the file, within the time limit. */
static void test_import_hostile(void **state)
{
    (void)state;
    is_mesh m;
    char err[512] = "", p[1024];
    is_mesh_options opt = {.import_timeout_ms = 1500};
    snprintf(p, sizeof p, "%s", data_path("truncated_header.ply"));
    assert_int_equal(mesh_load_file(p, &opt, &m, err, sizeof err), IS_MESH_ERR_FORMAT);
    print_message("  %s\n", err);
    assert_non_null(strstr(err, p));
    assert_non_null(strstr(err, "did not finish within 1500 ms"));
    assert_null(m.positions);
    snprintf(p, sizeof p, "%s", data_path("assimp_abort.ply"));
    assert_int_equal(mesh_load_file(p, &opt, &m, err, sizeof err), IS_MESH_ERR_FORMAT);
    print_message("  %s\n", err);
    assert_non_null(strstr(err, p));
    assert_non_null(strstr(err, "crashed"));
    assert_null(m.positions);
    is_mesh ok = load_data("box.obj", &opt);          /* the same child path succeeds on a good file */
    assert_int_equal(ok.n_triangles, 12);
    mesh_free(&ok);
}

/* in_process (for fuzzers) gives the same mesh as the child process. */
static void test_import_in_process(void **state)
{
    (void)state;
    is_mesh_options opt = {.in_process = true};
    is_mesh a = load_data("cube_normals.ply", &opt), b = load_data("cube_normals.ply", NULL);
    assert_int_equal(a.n_vertices, b.n_vertices);
    assert_int_equal(a.n_triangles, b.n_triangles);
    assert_memory_equal(a.positions, b.positions, a.n_vertices * sizeof(float3));
    assert_memory_equal(a.normals, b.normals, a.n_vertices * sizeof(float3));
    assert_memory_equal(a.texcoords, b.texcoords, a.n_vertices * sizeof(float2));
    assert_memory_equal(a.indices, b.indices, 3 * a.n_triangles * sizeof(uint32_t));
    assert_memory_equal(a.opposite, b.opposite, 3 * a.n_triangles * sizeof(uint32_t));
    mesh_free(&a);
    mesh_free(&b);
}

/* Warning callback: remembers the messages. */
static void collect_warning(void *user, const char *msg)
{
    char *buf = user;
    strncat(buf, msg, 2047 - strlen(buf));
    strncat(buf, "\n", 2047 - strlen(buf));
}

/* box_degenerate.obj: the repeated-vertex and the collinear triangles are dropped, counted and reported. */
static void test_import_degenerates(void **state)
{
    (void)state;
    char warnings[2048] = "";
    is_mesh_options opt = {.warn = collect_warning, .warn_user = warnings};
    is_mesh m = load_data("box_degenerate.obj", &opt);
    assert_int_equal(m.stats.degenerates_dropped, 2);
    assert_int_equal(m.n_triangles, 12);
    assert_int_equal(m.n_vertices, 8);             /* the collinear points were used by nothing else */
    assert_closed_consistent(&m);
    assert_non_null(strstr(warnings, "dropped 2 degenerate"));
    assert_non_null(strstr(warnings, "box_degenerate.obj"));
    mesh_free(&m);
}

/* normals_bad.obj: the zero and the NaN normal are replaced by recomputed (outward) ones and counted. */
static void test_import_bad_normals(void **state)
{
    (void)state;
    char warnings[2048] = "";
    is_mesh_options opt = {.warn = collect_warning, .warn_user = warnings};
    is_mesh m = load_data("normals_bad.obj", &opt);
    assert_int_equal(m.stats.normals_replaced, 2);
    assert_false(m.stats.normals_computed);
    assert_unit_normals(&m);
    for (size_t v = 0; v < m.n_vertices; v++)
        assert_true(dot3(m.normals[v], normalize3(m.positions[v])) > 0.9999f);
    assert_non_null(strstr(warnings, "replaced 2"));
    mesh_free(&m);
}

/* ------------------------------------------------ mesh_create ------------------------------------------------ */

/* The regular tetrahedron's arrays (outward, clockwise under our convention). */
static const float3 tet_p[4] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
static const uint32_t tet_i[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};

/* Zero, NaN, infinite and tiny normals are replaced by recomputed ones; others are normalized. */
static void test_create_bad_normals(void **state)
{
    (void)state;
    float3 n[4] = {{0, 0, 0}, {NAN, 0, 0}, {-INFINITY, 1, -1}, {-2, -2, 2}};
    is_mesh_data d = {4, 4, tet_p, n, NULL, tet_i};
    is_mesh m;
    char err[512] = "";
    assert_int_equal(mesh_create(&m, "tet", &d, NULL, err, sizeof err), 0);
    assert_closed_consistent(&m);
    assert_outward(&m, f3(0, 0, 0));
    assert_int_equal(m.stats.normals_replaced, 3);
    for (size_t v = 0; v < 4; v++) assert_true(dot3(m.normals[v], normalize3(m.positions[v])) > 0.99999f);
    mesh_free(&m);
    n[0] = f3(1e-30f, 0, 0);                     /* too short to normalize in float: replaced */
    n[1] = n[2] = n[3] = f3(0, 3, 0);            /* normalized, kept */
    assert_int_equal(mesh_create(&m, "tet", &d, NULL, err, sizeof err), 0);
    assert_int_equal(m.stats.normals_replaced, 1);
    assert_true(m.normals[1].y == 1.0f && m.normals[3].y == 1.0f);
    mesh_free(&m);
}

/* recompute_normals ignores split normals: cube-split becomes smooth (diagonal normals). */
static void test_create_recompute_option(void **state)
{
    (void)state;
    is_mesh m;
    char err[512] = "";
    is_mesh_options opt = {.recompute_normals = true};
    assert_int_equal(mesh_builtin_ex("cube-split", &opt, &m, err, sizeof err), 0);
    assert_true(m.stats.normals_computed);
    const float s = 1.0f / sqrtf(3.0f);
    for (size_t v = 0; v < m.n_vertices; v++) {
        assert_float_equal(m.normals[v].x, m.positions[v].x * s, 1e-6);
        assert_float_equal(m.normals[v].y, m.positions[v].y * s, 1e-6);
        assert_float_equal(m.normals[v].z, m.positions[v].z * s, 1e-6);
    }
    mesh_free(&m);
}

/* Degenerates in arrays: repeated index, coincident positions, collinear, sliver below 1e-7; a thin but
 * valid triangle is kept.  Unused vertices are dropped. */
static void test_create_degenerates(void **state)
{
    (void)state;
    const float3 p[9] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 0}, {2, 2, 2}, {3, 3, 3}, {4, 4, 4},
                         {0.5f, 1e-9f, 0}, {0.5f, 1e-4f, 0}};
    const uint32_t idx[] = {0, 1, 2, 0, 0, 1, 0, 3, 2, 4, 5, 6, 0, 7, 2, 0, 8, 2};
    is_mesh_data d = {9, 6, p, NULL, NULL, idx};
    is_mesh m;
    char err[512] = "", warnings[2048] = "";
    is_mesh_options opt = {.warn = collect_warning, .warn_user = warnings};
    assert_int_equal(mesh_create(&m, "degen", &d, &opt, err, sizeof err), 0);
    assert_int_equal(m.stats.degenerates_dropped, 4);
    assert_int_equal(m.n_triangles, 2);
    assert_int_equal(m.n_vertices, 4);            /* 0, 1, 2, 8 */
    assert_true(m.positions[3].y == 1e-4f);
    assert_non_null(strstr(warnings, "degen: dropped 4 degenerate"));
    mesh_free(&m);
    is_mesh_data all_bad = {9, 2, p, NULL, NULL, idx + 3};
    assert_int_equal(mesh_create(&m, "degen", &all_bad, NULL, err, sizeof err), IS_MESH_ERR_EMPTY);
    assert_non_null(strstr(err, "degenerate"));
}

/* Validation reports the first bad element. */
static void test_create_validation(void **state)
{
    (void)state;
    float3 p[4] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}};
    float2 uv[4] = {{0, 0}, {0, 1}, {1, 0}, {1, 1}};
    uint32_t idx[6] = {0, 1, 2, 2, 1, 7};
    is_mesh m;
    char err[512] = "";
    is_mesh_data d = {4, 2, p, NULL, uv, idx};
    assert_int_equal(mesh_create(&m, "quad", &d, NULL, err, sizeof err), IS_MESH_ERR_INVALID);
    assert_non_null(strstr(err, "quad: triangle 1, corner 2: vertex index 7"));
    idx[5] = 3;
    p[2].y = INFINITY;
    assert_int_equal(mesh_create(&m, "quad", &d, NULL, err, sizeof err), IS_MESH_ERR_INVALID);
    assert_non_null(strstr(err, "vertex 2 has a non-finite position"));
    p[2].y = 0;
    uv[3].x = NAN;
    assert_int_equal(mesh_create(&m, "quad", &d, NULL, err, sizeof err), IS_MESH_ERR_INVALID);
    assert_non_null(strstr(err, "vertex 3 has a non-finite texcoord"));
    uv[3].x = 1;
    d.n_triangles = 0;
    assert_int_equal(mesh_create(&m, "quad", &d, NULL, err, sizeof err), IS_MESH_ERR_EMPTY);
    d.n_triangles = 2;
    assert_int_equal(mesh_create(&m, "quad", &d, NULL, err, sizeof err), 0);
    assert_int_equal(m.stats.boundary_edges, 4);
    mesh_free(&m);
    mesh_free(&m);                                /* idempotent on a freed mesh */
}

/* ------------------------------------------------ instances ------------------------------------------------ */

/* Instances copy corners, normals, opposite positions, texcoords and the index, for every built-in. */
static void test_instances_match_triangles(void **state)
{
    (void)state;
    assert_int_equal(sizeof(is_patch_instance), 136);
    for (const char *const *n = mesh_builtin_names(); *n; n++) {
        is_mesh m = load_builtin(*n);
        is_patch_instance *inst = calloc(m.n_triangles, sizeof *inst);
        assert_int_equal(mesh_build_instances(&m, inst), m.n_triangles);
        for (size_t t = 0; t < m.n_triangles; t++) {
            for (int k = 0; k < 3; k++) {
                uint32_t v = m.indices[3 * t + k];
                assert_true(same_pos(inst[t].v[k], m.positions[v]));
                assert_true(same_pos(inst[t].n[k], m.normals[v]));
                assert_true(same_pos(inst[t].opp[k], m.positions[m.opposite[3 * t + k]]));
                assert_true(inst[t].t[k].x == m.texcoords[v].x && inst[t].t[k].y == m.texcoords[v].y);
            }
            assert_true(inst[t].instance_id == (float)t);
        }
        free(inst);
        mesh_free(&m);
    }
}

/* The declaration of Listing 1.1.2: POSITION0 on stream 0, TEXCOORD0..12 on stream 1 at the struct's offsets. */
static void test_patch_declaration(void **state)
{
    (void)state;
    const is_vertex_element *e = mesh_patch_declaration;
    assert_true(e[0].stream == 0 && e[0].offset == 0 && e[0].type == IS_DECLTYPE_FLOAT3 &&
                e[0].usage == IS_DECLUSAGE_POSITION && e[0].usage_index == 0);
    const size_t off[13] = {offsetof(is_patch_instance, v[0]), offsetof(is_patch_instance, v[1]),
                            offsetof(is_patch_instance, v[2]), offsetof(is_patch_instance, n[0]),
                            offsetof(is_patch_instance, n[1]), offsetof(is_patch_instance, n[2]),
                            offsetof(is_patch_instance, opp[0]), offsetof(is_patch_instance, opp[1]),
                            offsetof(is_patch_instance, opp[2]), offsetof(is_patch_instance, t[0]),
                            offsetof(is_patch_instance, t[1]), offsetof(is_patch_instance, t[2]),
                            offsetof(is_patch_instance, instance_id)};
    for (int i = 0; i < 13; i++) {
        const is_vertex_element *x = &e[1 + i];
        int type = i < 9 ? IS_DECLTYPE_FLOAT3 : i < 12 ? IS_DECLTYPE_FLOAT2 : IS_DECLTYPE_FLOAT1;
        assert_int_equal(x->stream, 1);
        assert_int_equal(x->offset, off[i]);
        assert_int_equal(x->type, type);
        assert_int_equal(x->method, 0);
        assert_int_equal(x->usage, IS_DECLUSAGE_TEXCOORD);
        assert_int_equal(x->usage_index, i);
    }
    const is_vertex_element end = IS_DECL_END;
    assert_memory_equal(&e[14], &end, sizeof end);
    assert_int_equal(MESH_PATCH_DECLARATION_COUNT, 15);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_builtins_closed_outward),
        cmocka_unit_test(test_builtin_counts),
        cmocka_unit_test(test_tetrahedron_regular),
        cmocka_unit_test(test_cube_diagonal_normals),
        cmocka_unit_test(test_cube_split_face_normals),
        cmocka_unit_test(test_sphere_normals),
        cmocka_unit_test(test_cylinder_sharp_rim),
        cmocka_unit_test(test_builtin_unknown_and_open),
        cmocka_unit_test(test_face_normal_convention),
        cmocka_unit_test(test_import_obj),
        cmocka_unit_test(test_import_off),
        cmocka_unit_test(test_import_ply),
        cmocka_unit_test(test_import_stl),
        cmocka_unit_test(test_import_memory),
        cmocka_unit_test(test_import_md2_faerie),
        cmocka_unit_test(test_import_errors),
        cmocka_unit_test(test_import_hostile),
        cmocka_unit_test(test_import_in_process),
        cmocka_unit_test(test_import_degenerates),
        cmocka_unit_test(test_import_bad_normals),
        cmocka_unit_test(test_create_bad_normals),
        cmocka_unit_test(test_create_recompute_option),
        cmocka_unit_test(test_create_degenerates),
        cmocka_unit_test(test_create_validation),
        cmocka_unit_test(test_instances_match_triangles),
        cmocka_unit_test(test_patch_declaration),
    };
    return cmocka_run_group_tests_name("meshes", tests, NULL, NULL);
}
