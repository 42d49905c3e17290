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

#include "util/prog.h"
#include "../meshes/meshes.h"

#include "../core/hlsl.h"
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

/* An import during which assimp logs that it clamped an index it found out of range fails with that message:
 * faerie.md2 with a vertex index past the end, from memory without a format hint (so the named check of
 * meshes/import_check.c, chosen by extension, does not run first), in the import child and in this process. */
static void test_import_clamped_index_refused(void **state)
{
    (void)state;
    size_t n;
    char *d = (char *)prog_slurp(FAERIE, &n), err[512] = "";
    assert_non_null(d);
    unsigned ofs = (unsigned char)d[52] | (unsigned char)d[53] << 8 | (unsigned)(unsigned char)d[54] << 16;
    d[ofs + 2] = (char)0xff, d[ofs + 3] = 0x7f;   /* triangle 0, corner 1: vertex 32767 of 366 */
    is_mesh m;
    for (int in_process = 0; in_process < 2; in_process++) {
        is_mesh_options opt = {.in_process = in_process};
        int rc = mesh_load_memory(d, n, NULL, "bad-faerie", &opt, &m, err, sizeof err);
        print_message("  %s\n", err);
        assert_int_equal(rc, IS_MESH_ERR_INVALID);
        assert_non_null(strstr(err, "bad-faerie: a face names a vertex"));
        assert_non_null(strstr(err, "MD2: Vertex index is outside the allowed range"));
        assert_null(m.positions);
    }
    d[ofs + 2] = 1, d[ofs + 3] = 0;   /* in range again: loads */
    assert_int_equal(mesh_load_memory(d, n, NULL, "faerie", NULL, &m, err, sizeof err), 0);
    mesh_free(&m);
    free(d);
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
    snprintf(p, sizeof p, "%s", data_path("garbage.ply"));   /* declares 999999999 vertices: refused at once */
    expect_load_error(p, IS_MESH_ERR_INVALID, "declares 999999999 'vertex' elements, more than the limit");
    snprintf(p, sizeof p, "%s", data_path("box.xyz"));
    expect_load_error(p, IS_MESH_ERR_FORMAT, "unknown");
    snprintf(p, sizeof p, "%s", data_path("nan.obj"));
    expect_load_error(p, IS_MESH_ERR_INVALID, "vertex 1");
    snprintf(p, sizeof p, "%s", data_path("badindex.obj"));
    expect_load_error(p, IS_MESH_ERR_INVALID, "line 5: face 0, corner 2 names vertex 99");
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
    int rc = mesh_load_file(p, &opt, &m, err, sizeof err);
    print_message("  %s\n", err);
    assert_true(rc == IS_MESH_ERR_FORMAT || (UNDER_ASAN && rc == IS_MESH_ERR_NOMEM));
    assert_non_null(strstr(err, p));
    /* (under AddressSanitizer, whose quarantine keeps freed memory, the hanging reader reaches the import's
     * memory limit first) */
    assert_true(strstr(err, "did not finish within the import time limit of 1.5 s") ||
                (UNDER_ASAN && strstr(err, "ran out of the import memory limit")));
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

/* Zero, NaN, infinite and denormal normals are replaced by recomputed ones; others (even 1e-30 long) are
 * normalized: a normal is a direction, whatever the unit of the mesh. */
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
    n[0] = f3(1e-40f, 0, 0);                     /* denormal: float cannot hold its direction, replaced */
    n[1] = n[2] = n[3] = f3(0, 3, 0);            /* normalized, kept */
    assert_int_equal(mesh_create(&m, "tet", &d, NULL, err, sizeof err), 0);
    assert_int_equal(m.stats.normals_replaced, 1);
    assert_true(m.normals[1].y == 1.0f && m.normals[3].y == 1.0f);
    mesh_free(&m);
    n[0] = f3(0, 0, -1e-30f);                    /* tiny but normal floats: a direction, normalized in double */
    n[1] = f3(3e-38f, 0, 0);                     /* (a file's area-weighted normals of a mesh in nanometres) */
    assert_int_equal(mesh_create(&m, "tet", &d, NULL, err, sizeof err), 0);
    assert_int_equal(m.stats.normals_replaced, 0);
    assert_true(m.normals[0].z == -1.0f && m.normals[1].x == 1.0f);
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

/* ------------------------------------------ hostile input, library level ------------------------------------------ */

/* A temporary folder for generated files (removed by the caller with remove_tmp). */
static void make_tmp(char *dir, size_t len)
{
    snprintf(dir, len, "/tmp/instess-meshes-XXXXXX");
    assert_non_null(mkdtemp(dir));
}

/* Remove the temporary folder. */
static void remove_tmp(const char *dir)
{
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

/* Write text into dir/name; the full path into path[len]. */
static void write_tmp(const char *dir, const char *name, const void *data, size_t n, char *path, size_t len)
{
    snprintf(path, len, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
}


/* A glTF tetrahedron with NORMAL (outward unit normals) in a data: URI, its one node scaled by `scale`. */
static void gltf_scaled_tet(char *text, size_t len, double scale)
{
    const float p[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    const float r = 0.57735027f;
    const float n[12] = {r, r, r, r, -r, -r, -r, r, -r, -r, -r, r};
    const uint16_t idx[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    unsigned char buf[120];
    char b64[200];
    memcpy(buf, p, 48), memcpy(buf + 48, n, 48), memcpy(buf + 96, idx, 24);
    prog_base64(buf, sizeof buf, b64);
    snprintf(text, len,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"data:application/octet-stream;base64,%s\","
             "\"byteLength\":120}],\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":96,\"byteLength\":24}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[-1,-1,-1],"
             "\"max\":[1,1,1]},{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
             "{\"bufferView\":2,\"componentType\":5123,\"count\":12,\"type\":\"SCALAR\"}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1},\"indices\":2}]}],"
             "\"nodes\":[{\"mesh\":0,\"scale\":[%g,%g,%g]}],\"scenes\":[{\"nodes\":[0]}],\"scene\":0}",
             b64, scale, scale, scale);
}

/* A UV sphere (8 x 12) as OBJ whose coordinates all carry the exponent e (the same mantissas at every scale). */
static void sphere_obj_e(char *buf, size_t len, int e)
{
    const int rings = 8, segs = 12;
    size_t n = (size_t)snprintf(buf, len, "v 0 1e%d 0\n", e);
    for (int i = 1; i < rings; i++)
        for (int j = 0; j < segs; j++) {
            double th = 3.14159265358979323846 * i / rings, ph = 6.28318530717958647692 * j / segs;
            n += (size_t)snprintf(buf + n, len - n, "v %.7fe%d %.7fe%d %.7fe%d\n", sin(th) * cos(ph) * 1.3, e,
                                  cos(th), e, sin(th) * sin(ph) * 0.8, e);
        }
    n += (size_t)snprintf(buf + n, len - n, "v 0 -1e%d 0\n", e);
    for (int j = 0; j < segs; j++) n += (size_t)snprintf(buf + n, len - n, "f 1 %d %d\n", 2 + (j + 1) % segs, 2 + j);
    for (int i = 0; i < rings - 2; i++)
        for (int j = 0; j < segs; j++) {
            int a = 2 + i * segs + j, b = 2 + i * segs + (j + 1) % segs;
            n += (size_t)snprintf(buf + n, len - n, "f %d %d %d\nf %d %d %d\n", a, b, b + segs, a, b + segs, a + segs);
        }
    int last = 2 + (rings - 1) * segs, base = 2 + (rings - 2) * segs;
    for (int j = 0; j < segs; j++)
        n += (size_t)snprintf(buf + n, len - n, "f %d %d %d\n", last, base + j, base + (j + 1) % segs);
}

/* The same OBJ in units 1e-30 .. 1e20 gives the same mesh: counts, topology and (recomputed) normals.  (assimp's
 * JoinIdenticalVertices, with its absolute tolerance, used to join distinct vertices of the small ones.)  And
 * a glTF node that scales by 1e-20 keeps the file's normals (normalized after the node's transform). */
static void test_import_scale_invariant(void **state)
{
    (void)state;
    char dir[64], path[256], err[512] = "";
    static char text[32768];
    make_tmp(dir, sizeof dir);
    const int exps[] = {0, -6, -12, -30, 6, 20};
    is_mesh ref = {0};
    for (size_t k = 0; k < sizeof exps / sizeof exps[0]; k++) {
        sphere_obj_e(text, sizeof text, exps[k]);
        write_tmp(dir, "s.obj", text, strlen(text), path, sizeof path);
        is_mesh m;
        if (mesh_load_file(path, NULL, &m, err, sizeof err) != 0) fail_msg("1e%d: %s", exps[k], err);
        print_message("  1e%-3d %zu vertices (%zu welded), %zu triangles, %zu edges, %zu non-manifold, %zu dropped\n",
                      exps[k], m.n_vertices, m.stats.welded_vertices, m.n_triangles, m.stats.edges,
                      m.stats.nonmanifold_edges, m.stats.degenerates_dropped);
        if (k == 0) { ref = m; assert_closed_consistent(&ref); continue; }
        assert_int_equal(m.n_vertices, ref.n_vertices);
        assert_int_equal(m.stats.welded_vertices, ref.stats.welded_vertices);
        assert_int_equal(m.n_triangles, ref.n_triangles);
        assert_int_equal(m.stats.edges, ref.stats.edges);
        assert_int_equal(m.stats.nonmanifold_edges, 0);
        assert_int_equal(m.stats.degenerates_dropped, 0);
        assert_memory_equal(m.indices, ref.indices, 3 * m.n_triangles * sizeof(uint32_t));
        assert_memory_equal(m.opposite, ref.opposite, 3 * m.n_triangles * sizeof(uint32_t));
        for (size_t v = 0; v < m.n_vertices; v++) assert_true(dot3(m.normals[v], ref.normals[v]) > 0.999999f);
        mesh_free(&m);
    }
    mesh_free(&ref);
    gltf_scaled_tet(text, sizeof text, 1e-20);
    write_tmp(dir, "tiny.gltf", text, strlen(text), path, sizeof path);
    is_mesh m;
    if (mesh_load_file(path, NULL, &m, err, sizeof err) != 0) fail_msg("tiny.gltf: %s", err);
    assert_int_equal(m.stats.normals_replaced, 0);
    assert_false(m.stats.normals_computed);
    for (size_t v = 0; v < m.n_vertices; v++) assert_true(dot3(m.normals[v], normalize3(m.positions[v])) > 0.99999f);
    mesh_free(&m);
    remove_tmp(dir);
}

/* Warnings into a buffer. */
static void collect(void *user, const char *msg)
{
    char *buf = user;
    strncat(buf, msg, 4095 - strlen(buf));
    strncat(buf, "\n", 4095 - strlen(buf));
}

/* Facet normals (tetra.stl, cube_normals.ply) are detected and warned about, with --recompute-normals as the
 * fix; smooth normals and computed normals are not; inward normals are counted and warned about. */
static void test_import_normal_hints(void **state)
{
    (void)state;
    char warnings[4096] = "";
    is_mesh_options opt = {.warn = collect, .warn_user = warnings};
    is_mesh m = load_data("tetra.stl", &opt);
    assert_true(m.stats.facet_normals);
    assert_int_equal(m.stats.normals_against_faces, 0);
    assert_non_null(strstr(warnings, "tetra.stl: the file's normals are facet normals"));
    assert_non_null(strstr(warnings, "--recompute-normals"));
    assert_null(strstr(warnings, "against"));
    mesh_free(&m);
    warnings[0] = 0;
    m = load_data("cube_normals.ply", &opt);
    assert_true(m.stats.facet_normals);
    mesh_free(&m);
    warnings[0] = 0;
    opt.recompute_normals = true;
    m = load_data("tetra.stl", &opt);
    assert_false(m.stats.facet_normals);
    assert_string_equal(warnings, "");
    mesh_free(&m);
    opt.recompute_normals = false;
    m = load_data("normals_bad.obj", &opt);   /* smooth normals (two of them recomputed): no hint */
    assert_false(m.stats.facet_normals);
    assert_int_equal(m.stats.normals_against_faces, 0);
    assert_null(strstr(warnings, "facet"));
    mesh_free(&m);
    /* the tetrahedron with its vertex normals reversed: every corner against its face */
    char dir[64], path[256], err[512];
    make_tmp(dir, sizeof dir);
    const char *inward = "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\nvn -1 -1 -1\nvn -1 1 1\nvn 1 -1 1\nvn 1 1 -1\n"
                         "f 1//1 2//2 3//3\nf 1//1 4//4 2//2\nf 1//1 3//3 4//4\nf 2//2 4//4 3//3\n";
    write_tmp(dir, "inward.obj", inward, strlen(inward), path, sizeof path);
    warnings[0] = 0;
    assert_int_equal(mesh_load_file(path, &opt, &m, err, sizeof err), 0);
    assert_int_equal(m.stats.normals_against_faces, 12);
    assert_false(m.stats.facet_normals);
    assert_non_null(strstr(warnings, "12 of 12 corner normals point against their face's winding"));
    /* and it offers both fixes: normals from the winding, or the other winding */
    assert_non_null(strstr(warnings, "--recompute-normals"));
    assert_non_null(strstr(warnings, "--cull cw"));
    mesh_free(&m);
    remove_tmp(dir);
}

/* Declared sizes (mesh_check_header through mesh_load_memory, so no file and no assimp): binary PLY sizes are
 * exact (a body one byte short is refused, the exact body passes), lists count at least their count, ASCII at
 * least 2 bytes per number; counts over the limits are refused; a header the check cannot parse passes. */
static void test_import_declared_sizes(void **state)
{
    (void)state;
    static unsigned char buf[16384];
    char err[512];
    is_mesh m;
    const char *hdr = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
    size_t h = strlen(hdr), body = 4 * 12 + 4 * 13;   /* the tetrahedron: 4 vertices, 4 faces of 3 */
    memcpy(buf, hdr, h);
    const float p[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    memcpy(buf + h, p, sizeof p);
    const int f[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    for (int t = 0; t < 4; t++) buf[h + 48 + 13 * t] = 3, memcpy(buf + h + 49 + 13 * t, f[t], 12);
    assert_int_equal(mesh_load_memory(buf, h + body, "ply", "tet.ply", NULL, &m, err, sizeof err), 0);
    mesh_free(&m);
    /* 4 vertices need 48 bytes, 4 faces at least 4: 51 bytes of body are one short */
    assert_int_equal(mesh_load_memory(buf, h + 51, "ply", "cut.ply", NULL, &m, err, sizeof err), IS_MESH_ERR_INVALID);
    assert_non_null(strstr(err, "cut.ply: the PLY header declares 4 'vertex' elements (with the others at least 52 "
                                "bytes), but the file holds only 51 bytes after its header"));
    const char *ascii = "ply\r\nformat ascii 1.0\r\ncomment a comment\r\nelement vertex 3\r\nproperty double x\r\n"
                        "property double y\r\nproperty double z\r\nelement face 1\r\n"
                        "property list uchar uint vertex_indices\r\n"
                        "end_header\r\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2";   /* 3 x 3 + 1 numbers: at least 19 bytes */
    if (mesh_load_memory(ascii, strlen(ascii), "ply", "a.ply", NULL, &m, err, sizeof err) != 0) fail_msg("%s", err);
    mesh_free(&m);
    const char *big = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 70000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n";
    assert_int_equal(mesh_load_memory(big, strlen(big), "ply", "big.ply", NULL, &m, err, sizeof err),
                     IS_MESH_ERR_INVALID);
    assert_non_null(strstr(err, "big.ply: the PLY header declares 70000000 'face' elements, more than the limit of "
                                "16777216"));
    const char *huge = "ply\nformat binary_big_endian 1.0\nelement vertex 99999999999999999999999\n"
                       "property float x\nend_header\n\x01";
    assert_int_equal(mesh_load_memory(huge, strlen(huge), "ply", "huge.ply", NULL, &m, err, sizeof err),
                     IS_MESH_ERR_INVALID);
    assert_non_null(strstr(err, "huge.ply: the PLY header declares 18446744073709551615 'vertex' elements"));
    const char *off = "COFF\n3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n";
    assert_int_equal(mesh_load_memory(off, strlen(off), "off", "c.off", NULL, &m, err, sizeof err), 0);
    mesh_free(&m);
    assert_int_equal(mesh_load_memory(off, 20, "off", "cut.off", NULL, &m, err, sizeof err), IS_MESH_ERR_INVALID);
    assert_non_null(strstr(err, "cut.off: the OFF header declares 3 'vertex' elements"));
    /* an unknown property type: no verdict, assimp decides (and refuses it) */
    const char *odd = "ply\nformat ascii 1.0\nelement vertex 1000000\nproperty quaternion q\nend_header\n";
    int rc = mesh_load_memory(odd, strlen(odd), "ply", "odd.ply", NULL, &m, err, sizeof err);
    print_message("  odd.ply -> %d: %s\n", rc, err);
    assert_true(rc < 0 && !strstr(err, "header declares"));
}

/* Limits of the options: the file's size (max_file_bytes), the mesh's files together (a glTF whose buffer
 * passes the rest of the budget), the import child's memory (max_import_memory_bytes), and a buffer imported
 * from memory, which may refer to no file at all. */
static void test_import_limits(void **state)
{
    (void)state;
    char err[512], dir[64], path[256];
    is_mesh m;
    is_mesh_options small = {.max_file_bytes = 100};
    assert_int_equal(mesh_load_file(data_path("box.obj"), &small, &m, err, sizeof err), IS_MESH_ERR_INVALID);
    assert_non_null(strstr(err, "box.obj: the file has 229 bytes, more than the limit of 100"));
    make_tmp(dir, sizeof dir);
    unsigned char bin[72];
    const float p[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    const uint16_t idx[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    memcpy(bin, p, 48), memcpy(bin + 48, idx, 24);
    write_tmp(dir, "tet.bin", bin, sizeof bin, path, sizeof path);
    char text[2048];
    int n = snprintf(text, sizeof text,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"tet.bin\",\"byteLength\":72}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":24}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[-1,-1,-1],"
             "\"max\":[1,1,1]},{\"bufferView\":1,\"componentType\":5123,\"count\":12,\"type\":\"SCALAR\"}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
             "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}],\"scene\":0}");
    write_tmp(dir, "tet.gltf", text, (size_t)n, path, sizeof path);
    assert_int_equal(mesh_load_file(path, NULL, &m, err, sizeof err), 0);
    mesh_free(&m);
    is_mesh_options tight = {.max_file_bytes = (uint64_t)n + 71};   /* the glTF fits, the buffer does not */
    assert_true(mesh_load_file(path, &tight, &m, err, sizeof err) < 0);
    print_message("  %s\n", err);
    assert_non_null(strstr(err, "tet.gltf: refers to 'tet.bin', which would bring the mesh's files over the limit"));
    /* from memory, the same glTF may not read tet.bin (no folder), in the child or in this process */
    for (int in_process = 0; in_process < 2; in_process++) {
        is_mesh_options o = {.in_process = in_process};
        assert_true(mesh_load_memory(text, (size_t)n, "gltf", "mem.gltf", &o, &m, err, sizeof err) < 0);
        assert_non_null(strstr(err, "mem.gltf: refers to 'tet.bin', which cannot be read: a mesh read from memory "
                                    "has no folder"));
    }
    /* a grid of 20000 triangles needs more than 1 MiB in assimp: a clear message, not a killed process */
    static char grid[1 << 20];
    size_t k = 0;
    for (int j = 0; j <= 100; j++)
        for (int i = 0; i <= 100; i++) k += (size_t)snprintf(grid + k, sizeof grid - k, "v %d %d 0\n", i, j);
    for (int j = 0; j < 100; j++)
        for (int i = 0; i < 100; i++) {
            int a = j * 101 + i + 1;
            k += (size_t)snprintf(grid + k, sizeof grid - k, "f %d %d %d\nf %d %d %d\n", a, a + 1, a + 102, a,
                                  a + 102, a + 101);
        }
    write_tmp(dir, "grid.obj", grid, k, path, sizeof path);
    is_mesh_options mem = {.max_import_memory_bytes = 1 << 20};
    assert_int_equal(mesh_load_file(path, &mem, &m, err, sizeof err), IS_MESH_ERR_NOMEM);
    print_message("  %s\n", err);
    assert_non_null(strstr(err, "grid.obj: cannot read the mesh: assimp ran out of the import memory limit of 1 MiB"));
    assert_int_equal(mesh_load_file(path, NULL, &m, err, sizeof err), 0);   /* the default rule: 256 MiB + 32/byte */
    assert_int_equal(m.n_triangles, 20000);
    mesh_free(&m);
    remove_tmp(dir);
}

/* A glTF whose one mesh (a 64 x 32 grid, 4096 triangles, in a data: URI) is used 2^depth times by a node graph
 * that shares children: node k uses node k + 1 twice. */
static char *gltf_grid_graph(int depth)
{
    enum { W = 64, H = 32, NV = (W + 1) * (H + 1), NT = 2 * W * H };
    size_t bytes = NV * 12 + NT * 12;
    unsigned char *buf = malloc(bytes);
    char *b64 = malloc(bytes * 4 / 3 + 8), *text = malloc(bytes * 4 / 3 + 4096);
    assert_true(buf && b64 && text);
    for (int j = 0, v = 0; j <= H; j++)
        for (int i = 0; i <= W; i++, v++) {
            const float p[3] = {(float)i, (float)j, 0.0f};
            memcpy(buf + 12 * v, p, 12);
        }
    for (int j = 0, t = 0; j < H; j++)
        for (int i = 0; i < W; i++, t += 2) {
            uint32_t a = (uint32_t)(j * (W + 1) + i), q[6] = {a, a + 1, a + W + 2, a, a + W + 2, a + W + 1};
            memcpy(buf + NV * 12 + 12 * t, q, sizeof q);
        }
    prog_base64(buf, bytes, b64);
    size_t n = (size_t)sprintf(text,
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"data:application/octet-stream;base64,%s\","
        "\"byteLength\":%zu}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":%d},{\"buffer\":0,\"byteOffset\":%d,"
        "\"byteLength\":%d}],\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%d,\"type\":\"VEC3\","
        "\"min\":[0,0,0],\"max\":[%d,%d,0]},"
        "{\"bufferView\":1,\"componentType\":5125,\"count\":%d,\"type\":\"SCALAR\"}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],\"nodes\":[",
        b64, bytes, NV * 12, NV * 12, NT * 12, NV, W, H, 3 * NT);
    for (int k = 0; k < depth; k++) n += (size_t)sprintf(text + n, "{\"children\":[%d,%d]},", k + 1, k + 1);
    sprintf(text + n, "{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}],\"scene\":0}");
    free(buf), free(b64);
    return text;
}

/* The instanced expansion is counted before anything is merged, and the count stops at the limit: 2^13 uses of
 * a 4096-triangle mesh (2^25 triangles, from a 100 KB file) are refused at once; 2^3 uses load. */
static void test_import_instancing_cap(void **state)
{
    (void)state;
    char dir[64], path[256], err[512];
    make_tmp(dir, sizeof dir);
    is_mesh m;
    for (int depth = 3; depth <= 13; depth += 10) {
        char *text = gltf_grid_graph(depth);
        write_tmp(dir, "graph.gltf", text, strlen(text), path, sizeof path);
        free(text);
        int rc = mesh_load_file(path, NULL, &m, err, sizeof err);
        print_message("  depth %d: %s\n", depth, rc ? err : "loaded");
        if (depth == 3) {
            if (rc != 0) fail_msg("%s", err);
            assert_int_equal(m.n_triangles, 8 * 4096);
            mesh_free(&m);
            continue;
        }
        assert_int_equal(rc, IS_MESH_ERR_INVALID);
        assert_non_null(strstr(err, "graph.gltf: too large after instancing the scene's nodes: more than 16777216 "
                                    "triangles"));
    }
    remove_tmp(dir);
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
        cmocka_unit_test(test_import_clamped_index_refused),
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
        cmocka_unit_test(test_import_scale_invariant),
        cmocka_unit_test(test_import_normal_hints),
        cmocka_unit_test(test_import_declared_sizes),
        cmocka_unit_test(test_import_limits),
        cmocka_unit_test(test_import_instancing_cap),
    };
    return cmocka_run_group_tests_name("meshes", tests, NULL, NULL);
}
