/* tests/test_watertight.c -- docs/design.md, erratum 6: positions on a shared edge are bitwise identical from both
 * triangles, for every patch, normal mode and level 1..16 (random pairs, the tetrahedron, the welded cube; PN-AEN
 * on the cube with split normals). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "../vs/vs.h"
#include "util/patch_util.h"

#include "../core/hlsl.h"
static const vs_normals modes[3] = {VS_NORMALS_LINEAR, VS_NORMALS_QUADRATIC, VS_NORMALS_REAL};

/* Triangles a and b share the edge (a.v[ka], a.v[ka+1]) = (b.v[kb+1], b.v[kb]): compare every edge grid point of
 * level L; returns the number of mismatching positions (and linear / quadratic normals when normals is set). */
static int compare_edge(vs_patch p, const vs_triangle *a, int ka, const vs_triangle *b, int kb, int L,
                        const vs_options *o, bool normals)
{
    int bad = 0;
    for (int i = 0; i <= L; i++) {
        float wa[3] = {0, 0, 0}, wb[3] = {0, 0, 0};
        float s = (float)(L - i) / (float)L, t = (float)i / (float)L; /* the grid's (integer) / L */
        wa[ka] = s, wa[(ka + 1) % 3] = t;
        wb[(kb + 1) % 3] = s, wb[kb] = t;
        float3 pa, pb, na, nb;
        vs_patch_eval(p, a, f3(wa[0], wa[1], wa[2]), o, &pa, &na, NULL);
        vs_patch_eval(p, b, f3(wb[0], wb[1], wb[2]), o, &pb, &nb, NULL);
        if (!same3(pa, pb)) bad++;
        if (normals && o->normals != VS_NORMALS_REAL && !same3(na, nb)) bad++;
    }
    return bad;
}

/* A random pair sharing edge P-Q: A = (P, Q, R), B = (Q, P, S), rotated randomly; split: B's normals at P, Q
 * differ from A's (PN-AEN's case). */
static void random_pair(uint64_t *s, bool split, vs_triangle *A, int *ka, vs_triangle *B, int *kb)
{
    float3 P = rand3(s), Q = rand3(s), R = rand3(s), S = rand3(s);
    float3 up = normalize3(cross3(sub3(Q, P), sub3(R, P)));
    float3 nP = normalize3(add3(up, scale3(rand3(s), 0.6f))), nQ = normalize3(add3(up, scale3(rand3(s), 0.6f)));
    float3 nR = normalize3(add3(up, scale3(rand3(s), 0.6f))), nS = normalize3(add3(up, scale3(rand3(s), 0.6f)));
    float3 nP2 = split ? normalize3(add3(up, scale3(rand3(s), 0.6f))) : nP;
    float3 nQ2 = split ? normalize3(add3(up, scale3(rand3(s), 0.6f))) : nQ;
    float3 va[3] = {P, Q, R}, na[3] = {nP, nQ, nR}, vb[3] = {Q, P, S}, nb[3] = {nQ2, nP2, nS};
    vs_triangle a = vs_triangle_make(va, na), b = vs_triangle_make(vb, nb);
    a.opp[0] = S, b.opp[0] = R;
    a.nadj[0][0] = nP2, a.nadj[0][1] = nQ2; /* B's normals at P, Q */
    b.nadj[0][0] = nQ, b.nadj[0][1] = nP;
    int ra = (int)((frand(s) + 1.0f) * 1.5f) % 3, rb = (int)((frand(s) + 1.0f) * 1.5f) % 3;
    *A = rotate(&a, ra), *B = rotate(&b, rb);
    *ka = (3 - ra) % 3, *kb = (3 - rb) % 3; /* edge 0 moved to edge (0 - r) mod 3 */
}

/* Random pairs: every patch, normal mode and level 1..16; the edge really is shared (sanity of the setup). */
static void test_random_pairs(void **state)
{
    (void)state;
    uint64_t s = 0x9E3779B97F4A7C15ull;
    long bad = 0, checked = 0;
    for (int trial = 0; trial < 200; trial++) {
        vs_triangle A, B;
        int ka, kb;
        random_pair(&s, false, &A, &ka, &B, &kb);
        assert_true(same3(A.v[ka], B.v[(kb + 1) % 3]) && same3(A.v[(ka + 1) % 3], B.v[kb]));
        for (int p = 0; p < VS_PATCH_COUNT; p++)
            for (int m = 0; m < 3; m++) {
                vs_options o = vs_default_options();
                o.normals = modes[m];
                for (int L = 1; L <= 16; L++, checked++)
                    bad += compare_edge((vs_patch)p, &A, ka, &B, kb, L, &o, true);
            }
    }
    print_message("random pairs: %ld edge evaluations, %ld mismatches\n", checked, bad);
    assert_int_equal(bad, 0);
}

/* van Overveld's factor and the no-shortcut flag keep edges watertight too. */
static void test_random_pairs_options(void **state)
{
    (void)state;
    uint64_t s = 77;
    long bad = 0;
    for (int trial = 0; trial < 50; trial++) {
        vs_triangle A, B;
        int ka, kb;
        random_pair(&s, false, &A, &ka, &B, &kb);
        vs_options o = vs_default_options();
        o.normals = VS_NORMALS_QUADRATIC, o.quad_factor = 1.5f, o.flags = VS_FLAG_NO_SHORTCUT, o.phong_alpha = 0.5f;
        for (int p = 0; p < VS_PATCH_COUNT; p++)
            for (int L = 1; L <= 16; L++) bad += compare_edge((vs_patch)p, &A, ka, &B, kb, L, &o, true);
    }
    assert_int_equal(bad, 0);
}

/* PN-AEN with split normals: watertight; the N-Patch cracks there (fig-001-5), by far more than rounding. */
static void test_split_normals_pn_aen(void **state)
{
    (void)state;
    uint64_t s = 4242;
    long bad_aen = 0, bad_pn = 0;
    double gap_pn = 0.0;
    for (int trial = 0; trial < 100; trial++) {
        vs_triangle A, B;
        int ka, kb;
        random_pair(&s, true, &A, &ka, &B, &kb);
        for (int m = 0; m < 3; m++) {
            vs_options o = vs_default_options();
            o.normals = modes[m];
            for (int L = 1; L <= 16; L++) {
                bad_aen += compare_edge(VS_PATCH_PN_AEN, &A, ka, &B, kb, L, &o, false);
                bad_pn += compare_edge(VS_PATCH_NPATCH, &A, ka, &B, kb, L, &o, false);
            }
        }
        float wa[3] = {0, 0, 0}, wb[3] = {0, 0, 0};
        wa[ka] = wa[(ka + 1) % 3] = 0.5f, wb[kb] = wb[(kb + 1) % 3] = 0.5f;
        float3 pa = vs_patch_position(VS_PATCH_NPATCH, &A, f3(wa[0], wa[1], wa[2]), NULL);
        float3 pb = vs_patch_position(VS_PATCH_NPATCH, &B, f3(wb[0], wb[1], wb[2]), NULL);
        gap_pn = fmax(gap_pn, length3(sub3(pa, pb)));
    }
    print_message("split normals: pn-aen mismatches %ld, npatch mismatches %ld (largest mid-edge gap %g)\n",
                  bad_aen, bad_pn, gap_pn);
    assert_int_equal(bad_aen, 0);
    assert_true(bad_pn > 0 && gap_pn > 1e-3);
}

/* A closed mesh: welded positions, per-vertex normals, opposite vertices and nadj from the index adjacency. */
typedef struct mesh { int nv, nt; float3 v[8], n[8]; int idx[12][3]; } mesh;

/* Build the instances of a mesh (opp and nadj from adjacency by index). */
static void instances(const mesh *m, vs_triangle *T)
{
    for (int t = 0; t < m->nt; t++) {
        float3 v[3], n[3];
        for (int k = 0; k < 3; k++) v[k] = m->v[m->idx[t][k]], n[k] = m->n[m->idx[t][k]];
        T[t] = vs_triangle_make(v, n);
        T[t].id = (float)t;
        for (int k = 0; k < 3; k++) {
            int a = m->idx[t][k], b = m->idx[t][(k + 1) % 3];
            for (int u = 0; u < m->nt; u++)
                for (int j = 0; j < 3; j++)
                    if (m->idx[u][j] == b && m->idx[u][(j + 1) % 3] == a) T[t].opp[k] = m->v[m->idx[u][(j + 2) % 3]];
        }
    }
}

/* Every shared edge of a closed mesh, every patch, normal mode and level 1..16. */
static long mesh_mismatches(const mesh *m, long *edges)
{
    vs_triangle T[12];
    instances(m, T);
    long bad = 0;
    *edges = 0;
    for (int t = 0; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            int a = m->idx[t][k], b = m->idx[t][(k + 1) % 3];
            for (int u = t + 1; u < m->nt; u++)
                for (int j = 0; j < 3; j++) {
                    if (!(m->idx[u][j] == b && m->idx[u][(j + 1) % 3] == a)) continue;
                    ++*edges;
                    for (int p = 0; p < VS_PATCH_COUNT; p++)
                        for (int md = 0; md < 3; md++) {
                            vs_options o = vs_default_options();
                            o.normals = modes[md];
                            for (int L = 1; L <= 16; L++)
                                bad += compare_edge((vs_patch)p, &T[t], k, &T[u], j, L, &o, true);
                        }
                }
        }
    return bad;
}

/* The regular tetrahedron, normals = directions of the vertices. */
static mesh tetrahedron(void)
{
    static const float3 v[4] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    static const int idx[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    mesh m;
    memset(&m, 0, sizeof m);
    m.nv = 4, m.nt = 4;
    memcpy(m.idx, idx, sizeof idx);
    for (int i = 0; i < 4; i++) m.v[i] = v[i], m.n[i] = normalize3(v[i]);
    return m;
}

/* The welded cube of side 2 centred at the origin, normals (+-1, +-1, +-1)/sqrt3, consistently wound. */
static mesh cube(void)
{
    mesh m;
    memset(&m, 0, sizeof m);
    m.nv = 8, m.nt = 12;
    for (int i = 0; i < 8; i++) {
        m.v[i] = f3(i & 4 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 1 ? 1.0f : -1.0f);
        m.n[i] = scale3(m.v[i], 1.0f / sqrtf(3.0f));
    }
    int t = 0;
    for (int a = 0; a < 3; a++)
        for (int sgn = 0; sgn < 2; sgn++) {
            int q[4], bit[3] = {4, 2, 1}, u = bit[(a + 1) % 3], w = bit[(a + 2) % 3], base = sgn ? bit[a] : 0;
            int ccw[4] = {base, base | u, base | u | w, base | w};
            for (int i = 0; i < 4; i++) q[i] = sgn ? ccw[i] : ccw[3 - i];
            m.idx[t][0] = q[0], m.idx[t][1] = q[1], m.idx[t][2] = q[2], t++;
            m.idx[t][0] = q[0], m.idx[t][1] = q[2], m.idx[t][2] = q[3], t++;
        }
    return m;
}

static void test_tetrahedron(void **state)
{
    (void)state;
    mesh m = tetrahedron();
    long edges, bad = mesh_mismatches(&m, &edges);
    assert_int_equal(edges, 6);
    assert_int_equal(bad, 0);
}

static void test_cube(void **state)
{
    (void)state;
    mesh m = cube();
    for (int t = 0; t < 12; t++) { /* outward winding: cross(v1 - v0, v2 - v0) points away from the centre */
        float3 a = m.v[m.idx[t][0]], b = m.v[m.idx[t][1]], c = m.v[m.idx[t][2]];
        assert_true(dot3(cross3(sub3(b, a), sub3(c, a)), add3(add3(a, b), c)) > 0.0f);
    }
    long edges, bad = mesh_mismatches(&m, &edges);
    assert_int_equal(edges, 18);
    assert_int_equal(bad, 0);
}

/* The cube with split normals (one normal per face at each corner) under PN-AEN: watertight. */
static void test_cube_split_pn_aen(void **state)
{
    (void)state;
    mesh m = cube();
    vs_triangle T[12];
    instances(&m, T);
    for (int t = 0; t < 12; t++) { /* face normals as vertex normals */
        float3 f = normalize3(cross3(sub3(T[t].v[1], T[t].v[0]), sub3(T[t].v[2], T[t].v[0])));
        for (int k = 0; k < 3; k++) T[t].n[k] = f;
    }
    for (int t = 0; t < 12; t++) /* neighbours' normals across each edge */
        for (int k = 0; k < 3; k++)
            for (int u = 0; u < 12; u++)
                for (int j = 0; j < 3; j++)
                    if (u != t && same3(T[u].v[j], T[t].v[(k + 1) % 3]) && same3(T[u].v[(j + 1) % 3], T[t].v[k]))
                        T[t].nadj[k][0] = T[u].n[(j + 1) % 3], T[t].nadj[k][1] = T[u].n[j];
    long bad = 0, edges = 0;
    for (int t = 0; t < 12; t++)
        for (int k = 0; k < 3; k++)
            for (int u = t + 1; u < 12; u++)
                for (int j = 0; j < 3; j++) {
                    if (!(same3(T[u].v[j], T[t].v[(k + 1) % 3]) && same3(T[u].v[(j + 1) % 3], T[t].v[k]))) continue;
                    edges++;
                    for (int md = 0; md < 3; md++) {
                        vs_options o = vs_default_options();
                        o.normals = modes[md];
                        for (int L = 1; L <= 16; L++) bad += compare_edge(VS_PATCH_PN_AEN, &T[t], k, &T[u], j, L, &o, false);
                    }
                }
    assert_int_equal(edges, 18);
    assert_int_equal(bad, 0);
}

/* Fill the input registers of an instance (Listing 1.1.2's declaration). */
static void fill_input(const vs_triangle *t, float3 b, is_vs_input *in)
{
    memset(in, 0, sizeof *in);
    in->position[0] = f4_of(b, 1.0f);
    for (int k = 0; k < 3; k++) {
        in->texcoord[VS_IN_V0 + k] = f4_of(t->v[k], 1.0f);
        in->texcoord[VS_IN_N0 + k] = f4_of(t->n[k], 1.0f);
        in->texcoord[VS_IN_OPP0 + k] = f4_of(t->opp[k], 1.0f);
        in->texcoord[VS_IN_T0 + k] = f4(t->t[k].x, t->t[k].y, 0.0f, 1.0f);
    }
    in->texcoord[VS_IN_ID] = f4(t->id, 0, 0, 1);
}

/* Through the shaders themselves (registers, constants, a perspective transform): oPos bitwise equal. */
static void test_shaders_oPos(void **state)
{
    (void)state;
    uint64_t s = 99;
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    float4x4 wvp = {{{1.2f, 0.1f, 0.0f, 0.0f}, {0.0f, 1.5f, 0.2f, 0.0f}, {0.3f, 0.0f, 1.001f, 1.0f}, {0.1f, -0.2f, 2.0f, 3.0f}}};
    float4x4 world = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
    long bad = 0;
    for (int trial = 0; trial < 30; trial++) {
        vs_triangle A, B;
        int ka, kb;
        random_pair(&s, false, &A, &ka, &B, &kb);
        for (int p = 0; p < VS_PATCH_COUNT; p++) {
            const is_vertex_shader *sh = vs_patch_shader((vs_patch)p);
            vs_set_constants(&c, &wvp, &world, f4(1, 1, 1, 1), NULL);
            for (int L = 1; L <= 16; L++)
                for (int i = 0; i <= L; i++) {
                    float wa[3] = {0, 0, 0}, wb[3] = {0, 0, 0};
                    wa[ka] = (float)(L - i) / L, wa[(ka + 1) % 3] = (float)i / L;
                    wb[(kb + 1) % 3] = (float)(L - i) / L, wb[kb] = (float)i / L;
                    is_vs_input ia, ib;
                    is_vs_output oa, ob;
                    fill_input(&A, f3(wa[0], wa[1], wa[2]), &ia);
                    fill_input(&B, f3(wb[0], wb[1], wb[2]), &ib);
                    sh->main(&c, &ia, &oa);
                    sh->main(&c, &ib, &ob);
                    if (memcmp(&oa.pos, &ob.pos, sizeof oa.pos) != 0) bad++;
                    if (memcmp(&oa.attr[RS_ATTR_COLOR0], &ob.attr[RS_ATTR_COLOR0], sizeof(float4)) != 0) bad++;
                }
        }
    }
    assert_int_equal(bad, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_pairs),
        cmocka_unit_test(test_random_pairs_options),
        cmocka_unit_test(test_split_normals_pn_aen),
        cmocka_unit_test(test_tetrahedron),
        cmocka_unit_test(test_cube),
        cmocka_unit_test(test_cube_split_pn_aen),
        cmocka_unit_test(test_shaders_oPos),
    };
    return cmocka_run_group_tests_name("watertight", tests, NULL, NULL);
}
