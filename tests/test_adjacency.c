/* tests/test_adjacency.c -- welding and opposite vertices (meshes/): closed, open, non-manifold meshes. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../meshes/meshes.h"

#include "../core/hlsl.h"
/* Load a built-in or fail the test. */
static is_mesh load_builtin(const char *name)
{
    is_mesh m;
    char err[512] = "";
    if (mesh_builtin(name, &m, err, sizeof err) != 0) fail_msg("%s: %s", name, err);
    return m;
}

/* Build a mesh from arrays or fail the test. */
static is_mesh make(const char *label, size_t nv, const float3 *p, size_t nt, const uint32_t *idx)
{
    is_mesh_data d = {nv, nt, p, NULL, NULL, idx};
    is_mesh m;
    char err[512] = "";
    if (mesh_create(&m, label, &d, NULL, err, sizeof err) != 0) fail_msg("%s: %s", label, err);
    return m;
}

/* Bitwise-equal positions. */
static bool same_pos(float3 a, float3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/* Opposite vertex of edge k of triangle t. */
static uint32_t opp(const is_mesh *m, size_t t, int k) { return m->opposite[3 * t + k]; }

/* Corner c of triangle t. */
static uint32_t corner(const is_mesh *m, size_t t, int c) { return m->indices[3 * t + c]; }

/* Whether triangle t has a corner at position p. */
static bool tri_has_pos(const is_mesh *m, size_t t, float3 p)
{
    for (int c = 0; c < 3; c++)
        if (same_pos(m->positions[corner(m, t, c)], p)) return true;
    return false;
}

/* ------------------------------------------------ closed meshes ------------------------------------------------ */

/* Tetrahedron: the opposite vertex of every edge is the vertex not in the triangle. */
static void test_tetrahedron_fourth_vertex(void **state)
{
    (void)state;
    is_mesh m = load_builtin("tetrahedron");
    for (size_t t = 0; t < 4; t++) {
        uint32_t fourth = 0 + 1 + 2 + 3 - corner(&m, t, 0) - corner(&m, t, 1) - corner(&m, t, 2);
        for (int k = 0; k < 3; k++) assert_int_equal(opp(&m, t, k), fourth);
    }
    mesh_free(&m);
}

/* Every closed built-in: the opposite vertex belongs to another triangle on the same edge, is off the edge,
 * and the answer is symmetric (that triangle's opposite vertex for the edge is our third corner). */
static void test_closed_builtins_neighbours(void **state)
{
    (void)state;
    for (const char *const *n = mesh_builtin_names(); *n; n++) {
        is_mesh m = load_builtin(*n);
        for (size_t t = 0; t < m.n_triangles; t++)
            for (int k = 0; k < 3; k++) {
                float3 a = m.positions[corner(&m, t, k)], b = m.positions[corner(&m, t, (k + 1) % 3)];
                float3 o = m.positions[opp(&m, t, k)], own = m.positions[corner(&m, t, (k + 2) % 3)];
                assert_false(same_pos(o, a) || same_pos(o, b) || same_pos(o, own));
                size_t found = 0;
                for (size_t u = 0; u < m.n_triangles; u++) {
                    if (u == t || !tri_has_pos(&m, u, a) || !tri_has_pos(&m, u, b) || !tri_has_pos(&m, u, o)) continue;
                    found++;
                    for (int j = 0; j < 3; j++) {       /* u's edge b -> a points back at our third corner */
                        if (same_pos(m.positions[corner(&m, u, j)], b) &&
                            same_pos(m.positions[corner(&m, u, (j + 1) % 3)], a))
                            assert_true(same_pos(m.positions[opp(&m, u, j)], own));
                    }
                }
                if (found != 1) fail_msg("%s: triangle %zu edge %d: %zu neighbours", *n, t, k, found);
            }
        mesh_free(&m);
    }
}

/* cube-split welds to the cube's 8 positions and gets the welded cube's adjacency, triangle by triangle. */
static void test_cube_split_welds_like_cube(void **state)
{
    (void)state;
    is_mesh c = load_builtin("cube"), s = load_builtin("cube-split");
    assert_int_equal(s.stats.welded_vertices, 8);
    assert_int_equal(s.stats.boundary_edges, 0);
    assert_int_equal(c.n_triangles, s.n_triangles);
    for (size_t t = 0; t < c.n_triangles; t++)
        for (int k = 0; k < 3; k++) {
            assert_true(same_pos(c.positions[corner(&c, t, k)], s.positions[corner(&s, t, k)]));
            assert_true(same_pos(c.positions[opp(&c, t, k)], s.positions[opp(&s, t, k)]));
        }
    for (size_t i = 0; i < 3 * s.n_triangles; i++)          /* welded ids point at equal positions */
        assert_true(same_pos(s.positions[s.welded[i]], s.positions[s.indices[i]]));
    mesh_free(&c);
    mesh_free(&s);
}

/* -0.0 and +0.0 weld; positions an ulp apart do not. */
static void test_weld_signed_zero_and_ulp(void **state)
{
    (void)state;
    const float3 p[6] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {-0.0f, -0.0f, 0}, {1, 0, -0.0f}, {1, 1, 0}};
    const uint32_t idx[6] = {0, 1, 2, 4, 3, 5};  /* second triangle uses the same edge through -0 copies */
    is_mesh m = make("zeros", 6, p, 2, idx);
    assert_int_equal(m.stats.welded_vertices, 4);
    assert_int_equal(m.stats.boundary_edges, 4);
    assert_int_equal(opp(&m, 0, 2), 5);          /* edge v2-v0 of triangle 0 -> (1,1,0) */
    assert_int_equal(opp(&m, 1, 0), 1);
    mesh_free(&m);
    float3 q[6];
    memcpy(q, p, sizeof q);
    q[3] = f3(nextafterf(0.0f, 1.0f), 0, 0);
    m = make("ulp", 6, q, 2, idx);
    assert_int_equal(m.stats.welded_vertices, 5);
    assert_int_equal(m.stats.boundary_edges, 6);
    mesh_free(&m);
}

/* ------------------------------------------------ open meshes ------------------------------------------------ */

/* A single triangle: every edge is a boundary; the answer is the own third vertex. */
static void test_single_triangle_boundary(void **state)
{
    (void)state;
    const float3 p[3] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}};
    const uint32_t idx[3] = {0, 1, 2};
    is_mesh m = make("tri", 3, p, 1, idx);
    assert_int_equal(opp(&m, 0, 0), 2);
    assert_int_equal(opp(&m, 0, 1), 0);
    assert_int_equal(opp(&m, 0, 2), 1);
    assert_int_equal(m.stats.boundary_edges, 3);
    assert_int_equal(m.stats.edges, 3);
    /* the shader's fn = |dot(own face normal, neighbour face normal)| is 1 on a boundary */
    is_patch_instance inst;
    mesh_build_instances(&m, &inst);
    float3 fn = mesh_compute_face_normal(inst.v[0], inst.v[1], inst.v[2]);
    for (int k = 0; k < 3; k++) {
        float3 nn = mesh_compute_face_normal(inst.v[(k + 1) % 3], inst.v[k], inst.opp[k]);
        assert_float_equal(fabsf(dot3(fn, nn)), 1.0f, 1e-6);
    }
    mesh_free(&m);
}

/* A quad of two triangles: the diagonal is shared, the four sides are boundaries. */
static void test_quad_two_triangles(void **state)
{
    (void)state;
    const float3 p[4] = {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
    const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    is_mesh m = make("quad", 4, p, 2, idx);
    assert_int_equal(opp(&m, 0, 2), 3);          /* tri 0 edge v2-v0 = 2-0, across it: vertex 3 */
    assert_int_equal(opp(&m, 1, 0), 1);          /* tri 1 edge v0-v1 = 0-2, across it: vertex 1 */
    assert_int_equal(opp(&m, 0, 0), 2);          /* boundaries: own third vertex */
    assert_int_equal(opp(&m, 0, 1), 0);
    assert_int_equal(opp(&m, 1, 1), 0);
    assert_int_equal(opp(&m, 1, 2), 2);
    assert_int_equal(m.stats.edges, 5);
    assert_int_equal(m.stats.boundary_edges, 4);
    assert_int_equal(m.stats.nonmanifold_edges, 0);
    assert_int_equal(m.stats.inconsistent_edges, 0);
    mesh_free(&m);
}

/* ------------------------------------------------ non-manifold, inconsistent ------------------------------------------------ */

/* Three triangles on edge 0-1: the edge is counted once as non-manifold and every triangle's answer on it is
 * its own third vertex, whatever the triangle order. */
static void test_nonmanifold_fin(void **state)
{
    (void)state;
    const float3 p[5] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}};
    const uint32_t idx[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    is_mesh m = make("fin", 5, p, 3, idx);
    assert_int_equal(m.stats.nonmanifold_edges, 1);
    assert_int_equal(m.stats.boundary_edges, 6);
    assert_int_equal(m.stats.edges, 7);
    assert_int_equal(opp(&m, 0, 0), 2);
    assert_int_equal(opp(&m, 1, 0), 3);
    assert_int_equal(opp(&m, 2, 0), 4);
    mesh_free(&m);
    const uint32_t rev[9] = {0, 1, 4, 1, 0, 3, 0, 1, 2};   /* reordered: same per-triangle answers */
    m = make("fin2", 5, p, 3, rev);
    assert_int_equal(opp(&m, 0, 0), 4);
    assert_int_equal(opp(&m, 1, 0), 3);
    assert_int_equal(opp(&m, 2, 0), 2);
    mesh_free(&m);
}

/* The non-manifold edge is reported through the warning callback. */
static void collect_warning(void *user, const char *msg) { strncat(user, msg, 511 - strlen(user)); }

/* Warnings name the mesh and count non-manifold and inconsistent edges. */
static void test_nonmanifold_warning(void **state)
{
    (void)state;
    const float3 p[5] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}};
    const uint32_t idx[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    char warnings[512] = "", err[256] = "";
    is_mesh_options opt = {.warn = collect_warning, .warn_user = warnings};
    is_mesh_data d = {5, 3, p, NULL, NULL, idx};
    is_mesh m;
    assert_int_equal(mesh_create(&m, "fin", &d, &opt, err, sizeof err), 0);
    assert_non_null(strstr(warnings, "fin: 1 non-manifold edge"));
    mesh_free(&m);
}

/* Two triangles using an edge in the same direction are still neighbours, counted as inconsistent. */
static void test_inconsistent_winding(void **state)
{
    (void)state;
    const float3 p[4] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {-1, 0, 0}};
    const uint32_t idx[6] = {0, 1, 2, 0, 1, 3};
    is_mesh m = make("flip", 4, p, 2, idx);
    assert_int_equal(m.stats.inconsistent_edges, 1);
    assert_int_equal(m.stats.boundary_edges, 4);
    assert_int_equal(opp(&m, 0, 0), 3);
    assert_int_equal(opp(&m, 1, 0), 2);
    mesh_free(&m);
}

/* mesh_update_topology after moving a corner of cube-split's first face outward: that face's two outer
 * edges at the corner lose their neighbours (so do the two faces they met), the face's diagonal does not. */
static void test_update_topology(void **state)
{
    (void)state;
    is_mesh m = load_builtin("cube-split");
    char err[256] = "";
    assert_int_equal(corner(&m, 0, 0), 0);
    assert_int_equal(corner(&m, 1, 0), 0);
    m.positions[0] = scale3(m.positions[0], 1.5f);
    assert_int_equal(mesh_update_topology(&m, err, sizeof err), 0);
    assert_int_equal(m.stats.welded_vertices, 9);
    assert_int_equal(m.stats.boundary_edges, 4);
    assert_int_equal(opp(&m, 0, 0), corner(&m, 0, 2));   /* edge 0-1: boundary now */
    assert_int_equal(opp(&m, 1, 2), corner(&m, 1, 1));   /* edge 3-0: boundary now */
    assert_int_equal(opp(&m, 0, 2), corner(&m, 1, 2));   /* diagonal still shared */
    assert_int_equal(opp(&m, 1, 0), corner(&m, 0, 1));
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tetrahedron_fourth_vertex),
        cmocka_unit_test(test_closed_builtins_neighbours),
        cmocka_unit_test(test_cube_split_welds_like_cube),
        cmocka_unit_test(test_weld_signed_zero_and_ulp),
        cmocka_unit_test(test_single_triangle_boundary),
        cmocka_unit_test(test_quad_two_triangles),
        cmocka_unit_test(test_nonmanifold_fin),
        cmocka_unit_test(test_nonmanifold_warning),
        cmocka_unit_test(test_inconsistent_winding),
        cmocka_unit_test(test_update_topology),
    };
    return cmocka_run_group_tests_name("adjacency", tests, NULL, NULL);
}
