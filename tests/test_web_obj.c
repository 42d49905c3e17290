/* tests/test_web_obj.c -- the page's OBJ reader (web/obj.c, compiled here natively) against the program's import
 * through assimp (meshes/import.c): the same mesh, bit for bit, for every OBJ the reader claims to read as
 * assimp does; a clear error where assimp fails too; the warnings it promises. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../meshes/meshes.h"
#include "../web/obj.h"

/* Path of tests/data/meshes/<name>, found next to this source file. */
static const char *data_path(const char *name, char *buf, size_t len)
{
    const char *file = __FILE__, *slash = strrchr(file, '/');
    int dir = slash ? (int)(slash - file) : 1;
    snprintf(buf, len, "%.*s/data/meshes/%s", dir, slash ? file : ".", name);
    return buf;
}

/* The bytes of a file (malloc'd, *len) or fail the test. */
static char *read_bytes(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("cannot open %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    assert_non_null(buf);
    assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    *len = (size_t)n;
    return buf;
}

/* The warnings of one read, joined. */
typedef struct warnings { char text[2048]; int n; } warnings;
static void collect(void *user, const char *msg)
{
    warnings *w = user;
    size_t at = strlen(w->text);
    snprintf(w->text + at, sizeof w->text - at, "%s\n", msg);
    w->n++;
}

/* Read name with the page's reader: its return code, the mesh in *m, the message in err. */
static int web_read(const char *name, bool recompute, warnings *w, is_mesh *m, char *err, size_t errlen)
{
    char path[1024];
    size_t len;
    char *data = read_bytes(data_path(name, path, sizeof path), &len);
    is_mesh_options opt = {.recompute_normals = recompute, .warn = w ? collect : NULL, .warn_user = w};
    int rc = web_obj_read(path, data, len, &opt, m, err, errlen);
    free(data);
    return rc;
}

/* The page's mesh of name equals the program's, array by array and count by count. */
static void same_as_import(const char *name, bool recompute)
{
    char path[1024], err[512] = "", werr[512] = "";
    is_mesh_options opt = {.recompute_normals = recompute};
    is_mesh a, b;
    if (mesh_load_file(data_path(name, path, sizeof path), &opt, &a, err, sizeof err) != 0)
        fail_msg("%s: the program's import failed: %s", name, err);
    if (web_read(name, recompute, NULL, &b, werr, sizeof werr) != 0) fail_msg("%s: the page's reader failed: %s", name, werr);
    assert_int_equal(a.n_vertices, b.n_vertices);
    assert_int_equal(a.n_triangles, b.n_triangles);
    assert_memory_equal(a.positions, b.positions, a.n_vertices * sizeof *a.positions);
    assert_memory_equal(a.normals, b.normals, a.n_vertices * sizeof *a.normals);
    assert_memory_equal(a.texcoords, b.texcoords, a.n_vertices * sizeof *a.texcoords);
    assert_memory_equal(a.indices, b.indices, 3 * a.n_triangles * sizeof *a.indices);
    assert_memory_equal(a.welded, b.welded, 3 * a.n_triangles * sizeof *a.welded);
    assert_memory_equal(a.opposite, b.opposite, 3 * a.n_triangles * sizeof *a.opposite);
    assert_int_equal(a.stats.welded_vertices, b.stats.welded_vertices);
    assert_int_equal(a.stats.edges, b.stats.edges);
    assert_int_equal(a.stats.boundary_edges, b.stats.boundary_edges);
    assert_int_equal(a.stats.degenerates_dropped, b.stats.degenerates_dropped);
    assert_int_equal(a.stats.normals_replaced, b.stats.normals_replaced);
    assert_int_equal(a.stats.primitives_skipped, b.stats.primitives_skipped);
    assert_int_equal(a.stats.normals_computed, b.stats.normals_computed);
    mesh_free(&a);
    mesh_free(&b);
}

/* Quads, normals, texture coordinates, decimals of 6 to 17 digits, -0, relative indices, ignored statements. */
static void test_torus(void **state)
{
    (void)state;
    same_as_import("web_torus.obj", false);
    same_as_import("web_torus.obj", true);
}

/* Quads without normals (box), degenerate triangles dropped, zero and NaN file normals replaced. */
static void test_box_and_bad_normals(void **state)
{
    (void)state;
    same_as_import("box.obj", false);
    same_as_import("box_degenerate.obj", false);
    same_as_import("normals_bad.obj", false);
}

/* A concave quad split from its concave corner, v//vn corners, a continued line, a face without normals. */
static void test_concave_quad(void **state)
{
    (void)state;
    same_as_import("web_concave.obj", false);
}

/* Exponents, a decimal comma, a leading dot, signs, w and colour components: assimp's number reading. */
static void test_numbers(void **state)
{
    (void)state;
    same_as_import("web_numbers.obj", false);
}

/* Files assimp refuses are refused with a message naming the file (and the line where there is one). */
static void test_errors(void **state)
{
    (void)state;
    static const struct { const char *name, *says; } cases[] = {
        {"badindex.obj", "line 5: the face names vertex 99, but the file defines 3"},
        {"empty.obj", "empty file"},
        {"garbage.obj", "no faces"},
        {"lines.obj", "no faces (2 point/line primitives)"},
        {"nan.obj", "vertex"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char path[1024], err[512] = "", werr[512] = "";
        is_mesh a, b;
        assert_int_not_equal(mesh_load_file(data_path(cases[k].name, path, sizeof path), NULL, &a, err, sizeof err), 0);
        assert_int_not_equal(web_read(cases[k].name, false, NULL, &b, werr, sizeof werr), 0);
        if (!strstr(werr, cases[k].name) || !strstr(werr, cases[k].says))
            fail_msg("%s: the message \"%s\" does not name the file and say \"%s\"", cases[k].name, werr, cases[k].says);
        assert_int_equal(b.n_triangles, 0);   /* left empty */
    }
}

/* A token that is not a number, a vertex of two coordinates, index 0: the line named. */
static void test_syntax_errors(void **state)
{
    (void)state;
    static const struct { const char *text, *says; } cases[] = {
        {"v 0 0 0\nv 1 0 0\nv 0 1 x\nf 1 2 3\n", "line 3: 'x' is not a number"},
        {"v 0 0 0\nv 1 0\n", "line 2: a vertex has 3 coordinates"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 0 1 2\n", "line 5: vertex index 0"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -2 -1\n", "line 4: vertex index -4, but only 3 are defined before this line"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/a 2 3\n", "line 4: 'a' is not a texture coordinate index"},
        {"v 0 0 0\nv .5 0 0\n", "line 2: '.5': the program's import (assimp) does not read a number that starts"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char err[512] = "";
        is_mesh m;
        assert_int_not_equal(web_obj_read("x.obj", cases[k].text, strlen(cases[k].text), NULL, &m, err, sizeof err), 0);
        if (!strstr(err, cases[k].says)) fail_msg("case %zu: \"%s\" does not say \"%s\"", k, err, cases[k].says);
    }
}

/* The promised warnings: a polygon of five corners cut into a fan (the line named), skipped lines, dropped
 * normals. */
static void test_warnings(void **state)
{
    (void)state;
    warnings w = {"", 0};
    char err[512] = "";
    is_mesh m;
    assert_int_equal(web_read("web_pentagon.obj", false, &w, &m, err, sizeof err), 0);
    assert_int_equal(m.n_triangles, 4);
    if (!strstr(w.text, "five or more corners (the first on line 8) cut into a fan")) fail_msg("warnings: %s", w.text);
    mesh_free(&m);
    static const char with_line[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//9\nl 1 2 3\n";
    w = (warnings){"", 0};
    is_mesh_options opt = {.warn = collect, .warn_user = &w};
    assert_int_equal(web_obj_read("x.obj", with_line, sizeof with_line - 1, &opt, &m, err, sizeof err), 0);
    if (!strstr(w.text, "skipped 2 point/line primitive(s)") || !strstr(w.text, "normal 9, but the file defines 1"))
        fail_msg("warnings: %s", w.text);
    assert_true(m.stats.normals_computed);
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_torus),         cmocka_unit_test(test_box_and_bad_normals),
        cmocka_unit_test(test_concave_quad),  cmocka_unit_test(test_numbers),
        cmocka_unit_test(test_errors),        cmocka_unit_test(test_syntax_errors),
        cmocka_unit_test(test_warnings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
