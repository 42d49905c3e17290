/* tests/test_patches.c -- the patches of vs/: corners, planarity, border curves, relabelling, the listing form
 * against the double-precision reference, the smooth patch's shortcut, NaN-freedom, normals, shaders and the
 * smoothness numbers. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "../vs/vs.h"
#include "../tess/tess.h"
#include "util/patch_util.h"
#include "util/pn_ref.h"

#include "../core/hlsl.h"
static bool finite3(float3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
static float3 grid_b(int L, int i, int j) { return f3((float)(L - i - j) / (float)L, (float)i / (float)L, (float)j / (float)L); }
static double angle_deg(float3 a, float3 b)
{
    double ax = a.x, ay = a.y, az = a.z, bx = b.x, by = b.y, bz = b.z; /* atan2(|a x b|, a.b): exact near 0 */
    double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), ax * bx + ay * by + az * bz) * 57.29577951308232;
}

static const vs_normals modes[3] = {VS_NORMALS_LINEAR, VS_NORMALS_QUADRATIC, VS_NORMALS_REAL};

static float tri_size(const vs_triangle *t)
{
    return fmaxf(length3(sub3(t->v[1], t->v[0])), fmaxf(length3(sub3(t->v[2], t->v[1])), length3(sub3(t->v[0], t->v[2]))));
}

/* Corners: exactly the vertices; linear / quadratic (and the curved patches' real) normals: the vertex normal. */
static void test_corners_exact(void **state)
{
    (void)state;
    uint64_t s = 1;
    for (int trial = 0; trial < 200; trial++) {
        vs_triangle t = rand_tri(&s);
        for (int p = 0; p < VS_PATCH_COUNT; p++)
            for (int m = 0; m < 3; m++) {
                vs_options o = vs_default_options();
                o.normals = modes[m];
                for (int k = 0; k < 3; k++) {
                    float w[3] = {0, 0, 0};
                    w[k] = 1.0f;
                    float3 pos, nrm;
                    vs_patch_eval((vs_patch)p, &t, f3(w[0], w[1], w[2]), &o, &pos, &nrm, NULL);
                    assert_true(same3(pos, t.v[k]));
                    if (modes[m] != VS_NORMALS_REAL || (p != VS_PATCH_FLAT && p != VS_PATCH_PN_AEN))
                        assert_true(same3(nrm, normalize3(t.n[k])));
                }
            }
    }
}

/* Flat input (every normal = the face normal) stays planar; real normals are the face normal. */
static void test_flat_input_planar(void **state)
{
    (void)state;
    uint64_t s = 2;
    for (int trial = 0; trial < 100; trial++) {
        vs_triangle t = rand_tri(&s);
        float3 f = normalize3(cross3(sub3(t.v[1], t.v[0]), sub3(t.v[2], t.v[0])));
        for (int k = 0; k < 3; k++) t.n[k] = t.nadj[k][0] = t.nadj[k][1] = f;
        float size = tri_size(&t);
        vs_options o = vs_default_options();
        o.normals = VS_NORMALS_REAL;
        for (int p = 0; p < VS_PATCH_COUNT; p++)
            for (int j = 0; j <= 8; j++)
                for (int i = 0; i + j <= 8; i++) {
                    float3 pos, nrm;
                    vs_patch_eval((vs_patch)p, &t, grid_b(8, i, j), &o, &pos, &nrm, NULL);
                    assert_true(fabsf(dot3(sub3(pos, t.v[0]), f)) < 1e-6f * size);
                    if (!(angle_deg(nrm, f) < 0.05)) fail_msg("patch %d b %d %d angle %g trial %d", p, i, j, angle_deg(nrm, f), trial);
                }
    }
}

/* Level 1 reproduces the input triangle, also through the shaders (identity transforms: oPos = (v, 1)). */
static void test_level1(void **state)
{
    (void)state;
    uint64_t s = 3;
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    float4x4 I = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
    vs_set_constants(&c, &I, &I, f4(1, 1, 1, 1), NULL);
    for (int trial = 0; trial < 50; trial++) {
        vs_triangle t = rand_tri(&s);
        for (int p = 0; p < VS_PATCH_COUNT; p++)
            for (int j = 0; j <= 1; j++)
                for (int i = 0; i + j <= 1; i++) {
                    float3 b = grid_b(1, i, j);
                    int k = i ? 1 : j ? 2 : 0;
                    assert_true(same3(vs_patch_position((vs_patch)p, &t, b, NULL), t.v[k]));
                    is_vs_input in;
                    memset(&in, 0, sizeof in);
                    in.position[0] = f4_of(b, 1);
                    for (int q = 0; q < 3; q++) {
                        in.texcoord[q] = f4_of(t.v[q], 1), in.texcoord[3 + q] = f4_of(t.n[q], 1);
                        in.texcoord[6 + q] = f4_of(t.opp[q], 1);
                    }
                    is_vs_output out;
                    vs_patch_shader((vs_patch)p)->main(&c, &in, &out);
                    assert_true(out.pos.x == t.v[k].x && out.pos.y == t.v[k].y && out.pos.z == t.v[k].z && out.pos.w == 1.0f);
                }
    }
}

/* On an edge the N-Patch and both Gruen patches are the same border curve (bitwise), and that curve is Eq. 1.1.5. */
static void test_edge_border_curve(void **state)
{
    (void)state;
    uint64_t s = 4;
    for (int trial = 0; trial < 200; trial++) {
        vs_triangle t = rand_tri(&s);
        double v[3][3], n[3][3], opp[3][3];
        to_d(&t, v, n, opp);
        float size = tri_size(&t);
        for (int k = 0; k < 3; k++)
            for (int i = 0; i <= 16; i++) {
                float w[3] = {0, 0, 0};
                w[k] = (float)(16 - i) / 16.0f, w[(k + 1) % 3] = (float)i / 16.0f;
                float3 b = f3(w[0], w[1], w[2]);
                for (int m = 0; m < 2; m++) {
                    vs_options o = vs_default_options();
                    o.normals = modes[m];
                    float3 pn, ps, pi, nn, ns, ni;
                    vs_patch_eval(VS_PATCH_NPATCH, &t, b, &o, &pn, &nn, NULL);
                    vs_patch_eval(VS_PATCH_SMOOTH, &t, b, &o, &ps, &ns, NULL);
                    vs_patch_eval(VS_PATCH_SMOOTH_INITIAL, &t, b, &o, &pi, &ni, NULL);
                    assert_true(same3(pn, ps) && same3(pn, pi));
                    assert_true(same3(nn, ns) && same3(nn, ni));
                }
                double ref[3];
                pn_ref_curve(v[k], v[(k + 1) % 3], n[k], n[(k + 1) % 3], (double)i / 16.0, ref);
                assert_true(dist_d(vs_patch_position(VS_PATCH_NPATCH, &t, b, NULL), ref) < 1e-5 * size);
            }
    }
}

/* Cyclic relabelling gives the same surface: within 1e-5 of the size inside, bitwise on edges. */
static void test_cyclic_relabel(void **state)
{
    (void)state;
    uint64_t s = 5;
    double worst = 0;
    for (int trial = 0; trial < 100; trial++) {
        vs_triangle t = rand_tri(&s);
        float size = tri_size(&t);
        for (int r = 1; r < 3; r++) {
            vs_triangle u = rotate(&t, r);
            for (int p = 0; p < VS_PATCH_COUNT; p++)
                for (int m = 0; m < 3; m++) {
                    vs_options o = vs_default_options();
                    o.normals = modes[m];
                    for (int j = 0; j <= 12; j++)
                        for (int i = 0; i + j <= 12; i++) {
                            float3 b = grid_b(12, i, j), bw = {0, 0, 0};
                            float w[3] = {b.x, b.y, b.z}, wr[3];
                            for (int k = 0; k < 3; k++) wr[k] = w[(k + r) % 3];
                            bw = f3(wr[0], wr[1], wr[2]);
                            float3 pa, pb, na, nb;
                            vs_patch_eval((vs_patch)p, &t, b, &o, &pa, &na, NULL);
                            vs_patch_eval((vs_patch)p, &u, bw, &o, &pb, &nb, NULL);
                            bool edge = b.x == 0 || b.y == 0 || b.z == 0;
                            if (edge) {
                                assert_true(same3(pa, pb));
                                if (modes[m] != VS_NORMALS_REAL) assert_true(same3(na, nb));
                            } else {
                                double d = length3(sub3(pa, pb)) / size;
                                if (d > worst) worst = d;
                                assert_true(d < 1e-5);
                                /* real: analytic 0.01 deg; finite differences of the Gruen patches 1 deg (they straddle
                                 * the crease of min(1, fn + bl) in different directions) */
                                bool fd = p == VS_PATCH_SMOOTH || p == VS_PATCH_SMOOTH_INITIAL;
                                double tol = modes[m] != VS_NORMALS_REAL ? 1e-3 : fd ? 1.0 : 0.01;
                                if (!(angle_deg(na, nb) < tol)) fail_msg("patch %d mode %d b %d %d angle %g na %g %g %g nb %g %g %g n0 %g %g %g n1 %g %g %g n2 %g %g %g", p, m, i, j, angle_deg(na, nb), na.x, na.y, na.z, nb.x, nb.y, nb.z, t.n[0].x, t.n[0].y, t.n[0].z, t.n[1].x, t.n[1].y, t.n[1].z, t.n[2].x, t.n[2].y, t.n[2].z);
                            }
                        }
                }
        }
    }
    print_message("relabelling: largest interior difference %.3g of the size\n", worst);
}

/* The listing form (float) equals the canonical Bernstein form / the equations (double) within 1e-5 of the size. */
static void test_listing_vs_reference(void **state)
{
    (void)state;
    uint64_t s = 6;
    double worst[4] = {0, 0, 0, 0};
    for (int trial = 0; trial < 500; trial++) {
        vs_triangle t = rand_tri(&s);
        double v[3][3], n[3][3], opp[3][3];
        to_d(&t, v, n, opp);
        double size = tri_size(&t);
        for (int j = 0; j <= 16; j++)
            for (int i = 0; i + j <= 16; i++) {
                float3 b = grid_b(16, i, j);
                double bd[3] = {b.x, b.y, b.z}, r[3];
                pn_ref_npatch(v, n, bd, r);
                double d0 = dist_d(vs_evaluate_npatch(t.v[0], t.v[1], t.v[2], t.n[0], t.n[1], t.n[2], b), r) / size;
                double d1 = dist_d(vs_patch_position(VS_PATCH_NPATCH, &t, b, NULL), r) / size;
                pn_ref_smooth_initial(v, n, bd, r);
                double d2 = dist_d(vs_patch_position(VS_PATCH_SMOOTH_INITIAL, &t, b, NULL), r) / size;
                pn_ref_smooth(v, n, opp, bd, r);
                double d3 = dist_d(vs_patch_position(VS_PATCH_SMOOTH, &t, b, NULL), r) / size;
                double dd[4] = {d0, d1, d2, d3};
                for (int q = 0; q < 4; q++) {
                    if (dd[q] > worst[q]) worst[q] = dd[q];
                    assert_true(dd[q] < 1e-5);
                }
                /* quadratic normals, both factors */
                for (int f = 0; f < 2; f++) {
                    vs_options o = vs_default_options();
                    o.normals = VS_NORMALS_QUADRATIC, o.quad_factor = f ? 1.5f : 2.0f;
                    float3 nrm;
                    vs_patch_eval(VS_PATCH_NPATCH, &t, b, &o, NULL, &nrm, NULL);
                    pn_ref_quadratic_normal(v, n, bd, f ? 1.5 : 2.0, r);
                    assert_true(dist_d(nrm, r) < 1e-5);
                }
            }
    }
    print_message("listing vs reference (relative): evaluateNPatch %.2g, npatch %.2g, smooth-initial %.2g, smooth %.2g\n",
                  worst[0], worst[1], worst[2], worst[3]);
}

/* Where every fn is 1 the smoothed patch is the N-Patch, bitwise (boundary triangle; coplanar neighbours). */
static void test_smooth_equals_npatch(void **state)
{
    (void)state;
    uint64_t s = 7;
    for (int trial = 0; trial < 100; trial++) {
        vs_triangle t = rand_tri(&s);
        if (trial % 2 == 0) {
            for (int k = 0; k < 3; k++) t.opp[k] = t.v[(k + 2) % 3]; /* boundary everywhere */
        } else { /* flat in z = 0 with coplanar neighbours: exact face normals (0, 0, +-1) */
            for (int k = 0; k < 3; k++) t.v[k].z = 0.0f;
            for (int k = 0; k < 3; k++) {
                float3 mid = scale3(add3(t.v[k], t.v[(k + 1) % 3]), 0.5f);
                t.opp[k] = sub3(scale3(mid, 2.0f), t.v[(k + 2) % 3]);
            }
        }
        float3 fn = vs_smooth_fn(&t);
        assert_true(fn.x == 1.0f && fn.y == 1.0f && fn.z == 1.0f);
        for (int f = 0; f < 2; f++) {
            vs_options o = vs_default_options();
            o.flags = f ? VS_FLAG_NO_SHORTCUT : 0;
            for (int L = 1; L <= 16; L++)
                for (int j = 0; j <= L; j++)
                    for (int i = 0; i + j <= L; i++) {
                        float3 b = grid_b(L, i, j);
                        assert_true(same3(vs_patch_position(VS_PATCH_SMOOTH, &t, b, &o),
                                          vs_patch_position(VS_PATCH_NPATCH, &t, b, &o)));
                    }
        }
    }
}

/* The per-edge shortcut gives the same bits as evaluating every P_k; the savings count matches. */
static void test_shortcut_same_bits(void **state)
{
    (void)state;
    uint64_t s = 8;
    vs_triangle tris[64];
    long partial = 0;
    for (int trial = 0; trial < 64; trial++) {
        vs_triangle t = rand_tri(&s);
        for (int k = 0; k < 3; k++)
            if ((trial >> k) & 1) t.opp[k] = t.v[(k + 2) % 3]; /* a boundary edge: fn_k = 1 */
        tris[trial] = t;
        float3 fn = vs_smooth_fn(&t);
        int ones = (fn.x == 1.0f) + (fn.y == 1.0f) + (fn.z == 1.0f);
        if (ones > 0 && ones < 3) partial++;
        vs_options on = vs_default_options(), off = on;
        off.flags = VS_FLAG_NO_SHORTCUT;
        for (int L = 1; L <= 16; L++)
            for (int j = 0; j <= L; j++)
                for (int i = 0; i + j <= L; i++) {
                    float3 b = grid_b(L, i, j);
                    assert_true(same3(vs_patch_position(VS_PATCH_SMOOTH, &t, b, &on),
                                      vs_patch_position(VS_PATCH_SMOOTH, &t, b, &off)));
                    int e_on, e_off;
                    float3 a = vs_smooth_formula(&t, b, 0, NULL, &e_on), c = vs_smooth_formula(&t, b, VS_FLAG_NO_SHORTCUT, NULL, &e_off);
                    assert_true(same3(a, c));
                    assert_int_equal(e_off, 3);
                    assert_int_equal(e_on, 3 - ones);
                }
    }
    assert_true(partial > 20);
    /* the count: interior points of level 10 times the edges with fn == 1 */
    uint64_t total, saved = vs_smooth_shortcut_savings(tris, 64, 10, &total), expect = 0;
    for (int i = 0; i < 64; i++) {
        float3 fn = vs_smooth_fn(&tris[i]);
        expect += 36u * (uint64_t)((fn.x == 1.0f) + (fn.y == 1.0f) + (fn.z == 1.0f));
    }
    assert_int_equal(total, 64u * 36u * 3u);
    assert_int_equal(saved, expect);
    print_message("shortcut at level 10 on 64 triangles: %llu of %llu P_k evaluations saved\n",
                  (unsigned long long)saved, (unsigned long long)total);
}

/* No NaN at corners, edges, near corners, for exactly opposite normals, zero normals, degenerate triangles. */
static void test_no_nan(void **state)
{
    (void)state;
    uint64_t s = 9;
    vs_triangle cases[9];
    for (int i = 0; i < 9; i++) cases[i] = rand_tri(&s);
    cases[0].n[1] = neg3(cases[0].n[0]);                              /* exactly opposite normals */
    cases[1].n[0] = cases[1].n[1] = cases[1].n[2] = f3(0, 0, 0);      /* zero normals */
    cases[2].v[1] = cases[2].v[0];                                    /* two vertices equal */
    cases[3].v[1] = cases[3].v[2] = cases[3].v[0];                    /* a point */
    cases[4].v[2] = lerp3(cases[4].v[0], cases[4].v[1], 0.25f);       /* collinear */
    cases[5].opp[0] = lerp3(cases[5].v[0], cases[5].v[1], 0.5f);      /* degenerate neighbour */
    for (int k = 0; k < 3; k++) cases[6].v[k] = scale3(cases[6].v[k], 1e15f); /* huge */
    for (int k = 0; k < 3; k++) cases[7].v[k] = scale3(cases[7].v[k], 1e-30f); /* tiny */
    cases[8].n[2] = neg3(cases[8].n[1]), cases[8].n[0] = neg3(cases[8].n[1]);
    float3 special[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5f, 0.5f, 0}, {1 - 1e-7f, 1e-7f, 0}, {1, 1e-30f, 1e-30f},
                        {1 - 2e-7f, 1e-7f, 1e-7f}, {1e-38f, 1e-38f, 1}, {0.999f, 0.0005f, 0.0005f}, {0, 0, 0},
                        {-0.0f, 0.5f, 0.5f}, {1.0f / 3, 1.0f / 3, 1.0f / 3}};
    for (int c = 0; c < 9; c++)
        for (int p = 0; p < VS_PATCH_COUNT; p++)
            for (int m = 0; m < 3; m++) {
                vs_options o = vs_default_options();
                o.normals = modes[m];
                for (int q = 0; q < (int)(sizeof special / sizeof special[0]) + 45; q++) {
                    float3 b = q < (int)(sizeof special / sizeof special[0]) ? special[q] : grid_b(8, q % 9, (q / 9) % 9);
                    float3 pos, nrm, g;
                    vs_patch_eval((vs_patch)p, &cases[c], b, &o, &pos, &nrm, &g);
                    if (!finite3(pos) || !finite3(nrm) || !finite3(g))
                        fail_msg("NaN: case %d patch %s normals %d b (%g %g %g)", c, vs_patch_name((vs_patch)p), m, b.x, b.y, b.z);
                }
            }
}

/* The shaders by name and their outputs (the listing's Diffuse, oTex, AOVs). */
static void test_shader_outputs(void **state)
{
    (void)state;
    const char *names[] = {"flat", "npatch", "smooth-initial", "smooth", "phong", "pn-aen", "fixed"};
    for (int i = 0; i < 7; i++) {
        const is_vertex_shader *sh = vs_find_shader(names[i]);
        assert_non_null(sh);
        assert_string_equal(sh->name, names[i]);
        assert_int_equal(sh->outputs, VS_OUTPUTS);
        if (i < 6) {
            vs_patch p;
            assert_int_equal(vs_patch_from_name(names[i], &p), 0);
            assert_ptr_equal(vs_patch_shader(p), sh);
        }
    }
    assert_null(vs_find_shader("nope"));
    vs_normals nm;
    assert_int_equal(vs_normals_from_name("quadratic", &nm), 0);
    assert_int_equal(nm, VS_NORMALS_QUADRATIC);
    assert_int_equal(vs_normals_from_name("cubic", &nm), -1);

    uint64_t s = 10;
    vs_triangle t = rand_tri(&s);
    t.t[0] = f2(0, 0), t.t[1] = f2(1, 0), t.t[2] = f2(0, 1), t.id = 42;
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    float4x4 I = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
    vs_options o = vs_default_options();
    o.normals = VS_NORMALS_QUADRATIC;
    vs_set_constants(&c, &I, &I, f4(0.5f, 0.25f, 1.0f, 0.0f), &o);
    vs_options back = vs_options_from_constants(&c);
    assert_int_equal(back.normals, VS_NORMALS_QUADRATIC);
    assert_true(back.phong_alpha == 0.75f && back.quad_factor == 2.0f && back.flags == 0);
    float3 b = f3(0.2f, 0.3f, 0.5f);
    is_vs_input in;
    memset(&in, 0, sizeof in);
    in.position[0] = f4_of(b, 1);
    for (int q = 0; q < 3; q++) {
        in.texcoord[q] = f4_of(t.v[q], 1), in.texcoord[3 + q] = f4_of(t.n[q], 1), in.texcoord[6 + q] = f4_of(t.opp[q], 1);
        in.texcoord[9 + q] = f4(t.t[q].x, t.t[q].y, 0, 1);
    }
    in.texcoord[12] = f4(42, 0, 0, 1);
    is_vs_output out;
    vs_shader_smooth.main(&c, &in, &out);
    float3 pos, nrm, g;
    vs_patch_eval(VS_PATCH_SMOOTH, &t, b, &o, &pos, &nrm, &g);
    assert_true(out.pos.x == pos.x && out.pos.y == pos.y && out.pos.z == pos.z && out.pos.w == 1.0f);
    float d = saturate(-nrm.z);
    float4 col = out.attr[RS_ATTR_COLOR0];
    assert_true(col.x == 0.5f * d && col.y == 0.25f * d && col.z == d && col.w == 1.0f);
    float4 tex = out.attr[RS_ATTR_TEXCOORD0];
    assert_true(fabsf(tex.x - 0.3f) < 1e-7f && fabsf(tex.y - 0.5f) < 1e-7f);
    assert_true(same3(f3_of(out.attr[RS_ATTR_TEXCOORD0 + 1]), normalize3(nrm)));
    assert_true(same3(f3_of(out.attr[RS_ATTR_TEXCOORD0 + 2]), b));
    assert_true(out.attr[RS_ATTR_TEXCOORD0 + 3].x == 42.0f);
    assert_true(same3(f3_of(out.attr[RS_ATTR_TEXCOORD0 + 4]), g));
    assert_true(fabsf(g.x + g.y + g.z - 1.0f) < 1e-6f);
    /* the device's N-patch mode: vs_npatch_evaluate + "fixed" lights exactly like the instanced npatch shader */
    o.normals = VS_NORMALS_LINEAR;
    vs_set_constants(&c, &I, &I, f4(1, 1, 1, 1), &o);
    for (int j = 0; j <= 8; j++)
        for (int i = 0; i + j <= 8; i++) {
            float3 bb = grid_b(8, i, j), dp, dn, cp, cn;
            in.position[0] = f4_of(bb, 1);
            vs_npatch_evaluate(t.v, t.n, bb, IS_DEGREE_CUBIC, IS_DEGREE_LINEAR, &dp, &dn);
            vs_patch_eval(VS_PATCH_NPATCH, &t, bb, &o, &cp, &cn, NULL);
            assert_true(same3(dp, cp) && same3(dn, cn));
            is_vs_output oi, of;
            vs_shader_npatch.main(&c, &in, &oi);
            is_vs_input fi;
            memset(&fi, 0, sizeof fi);
            fi.position[0] = f4_of(dp, 1), fi.normal[0] = f4_of(dn, 0);
            vs_shader_fixed.main(&c, &fi, &of);
            assert_memory_equal(&oi.pos, &of.pos, sizeof oi.pos);
            assert_memory_equal(&oi.attr[RS_ATTR_COLOR0], &of.attr[RS_ATTR_COLOR0], sizeof(float4));
        }
}

/* Real normals: analytic derivatives agree with finite differences of the positions; orientation follows the
 * linear normal; the Gruen patches' finite differences are close to the N-Patch's normal where they coincide. */
static void test_real_normals(void **state)
{
    (void)state;
    uint64_t s = 11;
    vs_options o = vs_default_options();
    o.normals = VS_NORMALS_REAL;
    double worst = 0;
    for (int trial = 0; trial < 100; trial++) {
        vs_triangle t = rand_tri(&s);
        for (int j = 1; j < 10; j++)
            for (int i = 1; i + j < 10; i++) {
                float3 b = grid_b(10, i, j);
                for (int p = 0; p < VS_PATCH_COUNT; p++) {
                    float3 pos, nrm, du, dv;
                    vs_patch_eval((vs_patch)p, &t, b, &o, &pos, &nrm, NULL);
                    float3 lin = add3(add3(scale3(t.n[0], b.x), scale3(t.n[1], b.y)), scale3(t.n[2], b.z));
                    assert_true(dot3(nrm, lin) >= 0.0f);
                    assert_true(fabsf(length3(nrm) - 1.0f) < 1e-5f);
                    /* numerical derivative in double steps of the float positions */
                    const float h = 1.0f / 256;
                    float3 e = f3(-h, h, 0), f = f3(-h, 0, h);
                    vs_options lo = vs_default_options();
                    du = sub3(vs_patch_position((vs_patch)p, &t, add3(b, e), &lo), vs_patch_position((vs_patch)p, &t, sub3(b, e), &lo));
                    dv = sub3(vs_patch_position((vs_patch)p, &t, add3(b, f), &lo), vs_patch_position((vs_patch)p, &t, sub3(b, f), &lo));
                    float3 fd = cross3(du, dv);
                    if (dot3(fd, lin) < 0) fd = neg3(fd);
                    double a = angle_deg(nrm, fd);
                    if (a > worst) worst = a;
                    assert_true(a < 0.5);
                }
            }
    }
    print_message("real normals vs finite differences: largest angle %.3g deg\n", worst);
}

/* The quadratic normal: the reflection (factor 2) and van Overveld's 3/2 differ where an edge has an inflection;
 * equal normals perpendicular to the edge stay unchanged. */
static void test_quadratic_normals(void **state)
{
    (void)state;
    float3 v[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    float3 up = f3(0, 0, 1), tilt = normalize3(f3(0.4f, 0, 1));
    float3 n[3] = {tilt, tilt, up}; /* same normal at both ends of edge v0-v1, tilted: an inflection */
    vs_triangle t = vs_triangle_make(v, n);
    vs_options o2 = vs_default_options(), o15 = o2;
    o2.normals = o15.normals = VS_NORMALS_QUADRATIC;
    o15.quad_factor = 1.5f;
    float3 a, b, l;
    vs_patch_eval(VS_PATCH_NPATCH, &t, f3(0.5f, 0.5f, 0), &o2, NULL, &a, NULL);
    vs_patch_eval(VS_PATCH_NPATCH, &t, f3(0.5f, 0.5f, 0), &o15, NULL, &b, NULL);
    o2.normals = VS_NORMALS_LINEAR;
    vs_patch_eval(VS_PATCH_NPATCH, &t, f3(0.5f, 0.5f, 0), &o2, NULL, &l, NULL);
    /* the reflected mid normal leans the other way (x < 0): the quadratic normal leans less than the linear one
     * (the mixed terms carry no factor 2, as in seeds 001 and 003), the more so with factor 2 than with 3/2 */
    assert_true(angle_deg(l, tilt) < 1e-4);
    assert_true(a.x < b.x && b.x < l.x && angle_deg(a, b) > 1.0);
    float3 m[3] = {up, up, up};
    vs_triangle flat = vs_triangle_make(v, m);
    o2.normals = VS_NORMALS_QUADRATIC;
    vs_patch_eval(VS_PATCH_NPATCH, &flat, f3(0.3f, 0.3f, 0.4f), &o2, NULL, &a, NULL);
    assert_true(angle_deg(a, up) < 1e-4);
}

/* The welded cube as arrays (for tess_smoothness, through mesh_create). */
static void cube_arrays(float3 pos[8], float3 nrm[8], uint32_t idx[36])
{
    for (int i = 0; i < 8; i++) {
        pos[i] = f3(i & 4 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 1 ? 1.0f : -1.0f);
        nrm[i] = scale3(pos[i], 1.0f / sqrtf(3.0f));
    }
    int t = 0, bit[3] = {4, 2, 1};
    for (int a = 0; a < 3; a++)
        for (int sg = 0; sg < 2; sg++) {
            int u = bit[(a + 1) % 3], w = bit[(a + 2) % 3], base = sg ? bit[a] : 0, q[4];
            int ccw[4] = {base, base | u, base | u | w, base | w};
            for (int i = 0; i < 4; i++) q[i] = sg ? ccw[i] : ccw[3 - i];
            int tri[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
            for (int i = 0; i < 6; i++) idx[t++] = (uint32_t)tri[i];
        }
}

/* Smoothness numbers on the cube: the final patch is smoother across edges than the N-Patch (Gruen's claim). */
static void test_smoothness_cube(void **state)
{
    (void)state;
    float3 pos[8], nrm[8];
    uint32_t idx[36];
    cube_arrays(pos, nrm, idx);
    is_mesh m;
    char err[256];
    is_mesh_data d = {.n_vertices = 8, .n_triangles = 12, .positions = pos, .normals = nrm, .indices = idx};
    assert_int_equal(mesh_create(&m, "cube arrays", &d, NULL, err, sizeof err), 0);
    vs_smoothness_result r[VS_PATCH_COUNT];
    for (int p = 0; p < VS_PATCH_COUNT; p++) {
        assert_int_equal(tess_smoothness(&m, (vs_patch)p, NULL, 16, &r[p]), 0);
        assert_int_equal(r[p].shared_edges, 18);
        assert_int_equal(r[p].boundary_edges, 0);
        assert_int_equal(r[p].samples, 18 * 16);
        assert_true(isfinite(r[p].max_angle_deg) && isfinite(r[p].mean_angle_deg) && isfinite(r[p].max_distance));
        print_message("cube %-14s max %7.3f deg  mean %7.3f deg  distance %.4f\n", vs_patch_name((vs_patch)p),
                      r[p].max_angle_deg, r[p].mean_angle_deg, r[p].max_distance);
    }
    assert_true(fabs(r[VS_PATCH_FLAT].max_angle_deg - 90.0) < 1e-3);
    assert_true(r[VS_PATCH_FLAT].max_distance == 0.0);
    assert_true(r[VS_PATCH_NPATCH].max_distance > 0.01);
    assert_true(r[VS_PATCH_SMOOTH].mean_angle_deg < r[VS_PATCH_NPATCH].mean_angle_deg);
    assert_true(r[VS_PATCH_SMOOTH_INITIAL].mean_angle_deg < r[VS_PATCH_NPATCH].mean_angle_deg);
    /* bad arguments */
    vs_smoothness_result bad;
    is_mesh empty = {0};
    assert_int_equal(tess_smoothness(&empty, VS_PATCH_NPATCH, NULL, 16, &bad), -1);
    assert_int_equal(tess_smoothness(&m, VS_PATCH_NPATCH, NULL, 0, &bad), -1);
    assert_int_equal(tess_smoothness(NULL, VS_PATCH_NPATCH, NULL, 16, &bad), -1);
    mesh_free(&m);
}

/* The patch table (vs/vs.h) is complete and agrees with what the patches do: every row has a name, a source and
 * a shader of the same name that vs_find_shader finds; names round-trip (`gregory` is checked against the
 * shaders' outputs by test_shader_outputs); where `fixed_function` is set, the device's evaluator
 * (vs_npatch_evaluate, POSITIONDEGREE CUBIC for npatch, LINEAR for flat) gives the patch's own points. */
static void test_patch_table(void **state)
{
    (void)state;
    float3 v[3] = {f3(0, 0, 0), f3(1, 0, 0.1f), f3(0.2f, 1, 0)};
    float3 n[3] = {normalize3(f3(-0.3f, -0.2f, 1)), normalize3(f3(0.4f, 0.1f, 1)), normalize3(f3(0, 0.5f, 1))};
    vs_triangle t = vs_triangle_make(v, n);
    float3 b = f3(0.2f, 0.3f, 0.5f);
    char names[256];
    vs_patch_names(",", names, sizeof names);
    for (int p = 0; p < VS_PATCH_COUNT; p++) {
        const vs_patch_info *r = &vs_patches[p];
        assert_non_null(r->name);
        assert_non_null(r->reference);
        assert_non_null(r->shader);
        assert_string_equal(r->shader->name, r->name);
        assert_ptr_equal(vs_find_shader(r->name), r->shader);
        assert_ptr_equal(vs_patch_shader((vs_patch)p), r->shader);
        vs_patch back;
        assert_int_equal(vs_patch_from_name(r->name, &back), 0);
        assert_int_equal(back, p);
        assert_non_null(strstr(names, r->name));
        float3 pos;
        vs_patch_eval((vs_patch)p, &t, b, NULL, &pos, NULL, NULL);
        float3 q, qn;
        vs_npatch_evaluate(v, n, b, p == VS_PATCH_FLAT ? IS_DEGREE_LINEAR : IS_DEGREE_CUBIC, IS_DEGREE_LINEAR, &q, &qn);
        bool same = fabsf(q.x - pos.x) < 1e-6f && fabsf(q.y - pos.y) < 1e-6f && fabsf(q.z - pos.z) < 1e-6f;
        if (r->fixed_function) assert_true(same);
    }
    vs_patch none;
    assert_int_equal(vs_patch_from_name("fixed", &none), -1);
    assert_string_equal(vs_patch_name((vs_patch)VS_PATCH_COUNT), "?");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_patch_table),
        cmocka_unit_test(test_corners_exact),
        cmocka_unit_test(test_flat_input_planar),
        cmocka_unit_test(test_level1),
        cmocka_unit_test(test_edge_border_curve),
        cmocka_unit_test(test_cyclic_relabel),
        cmocka_unit_test(test_listing_vs_reference),
        cmocka_unit_test(test_smooth_equals_npatch),
        cmocka_unit_test(test_shortcut_same_bits),
        cmocka_unit_test(test_no_nan),
        cmocka_unit_test(test_shader_outputs),
        cmocka_unit_test(test_real_normals),
        cmocka_unit_test(test_quadratic_normals),
        cmocka_unit_test(test_smoothness_cube),
    };
    return cmocka_run_group_tests_name("patches", tests, NULL, NULL);
}
