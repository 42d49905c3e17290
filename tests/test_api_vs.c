/* tests/test_api_vs.c -- every public function and table of vs/vs.h with NULL pointers, patches and normal modes
 * that do not exist, names that are not names, buffers of zero bytes, and triangles and barycentrics of
 * non-finite, huge and tiny values; every shader of vs_shaders called through main, batch and hull with such
 * registers.  Each returns (a value, "?", -1, or nothing written), never writes past a buffer it was given and
 * never converts a float out of an integer's range (UBSan's float-cast-overflow in the sanitizer stage).
 * tests/check_api_walkers.sh checks that every INSTESS_API name of vs/vs.h is named in this file. */
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

#include "../vs/vs.h"

static const float edge[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 1e-45f, 1e-30f, 1e30f, FLT_MAX, -FLT_MAX, INFINITY,
                             -INFINITY, NAN};
enum { N_EDGE = sizeof edge / sizeof edge[0] };

/* Names, tables and options with NULL and out-of-range arguments. */
static void test_names_and_options(void **state)
{
    (void)state;
    vs_normals nm = VS_NORMALS_REAL;
    vs_patch p = VS_PATCH_PHONG;
    assert_int_equal(vs_normals_from_name(NULL, &nm), -1);
    assert_int_equal(vs_normals_from_name("linear", NULL), -1);
    assert_int_equal(vs_normals_from_name("", &nm), -1);
    assert_int_equal(nm, VS_NORMALS_REAL);
    assert_string_equal(vs_normals_name((vs_normals)-1), "?");
    assert_string_equal(vs_normals_name((vs_normals)3), "?");
    assert_string_equal(vs_normals_name((vs_normals)INT_MAX), "?");
    assert_int_equal(vs_patch_from_name(NULL, &p), -1);
    assert_int_equal(vs_patch_from_name("flat", NULL), -1);
    assert_int_equal(vs_patch_from_name("FLAT", &p), -1);
    assert_int_equal(p, VS_PATCH_PHONG);
    assert_string_equal(vs_patch_name((vs_patch)-1), "?");
    assert_string_equal(vs_patch_name((vs_patch)VS_PATCH_COUNT), "?");
    assert_null(vs_patch_shader((vs_patch)-1));
    assert_null(vs_patch_shader((vs_patch)VS_PATCH_COUNT));
    assert_null(vs_find_shader(NULL));
    assert_null(vs_find_shader("no such shader"));
    assert_ptr_equal(vs_find_shader("fixed"), &vs_shader_fixed);
    /* vs_patch_names into no buffer, a buffer of 0 and 1 bytes, a NULL separator */
    char buf[8] = "xxxxxxx";
    assert_null(vs_patch_names(" | ", NULL, 10));
    assert_ptr_equal(vs_patch_names(" | ", buf, 0), buf);
    assert_int_equal(buf[0], 'x');   /* nothing written into 0 bytes */
    vs_patch_names(" | ", buf, 1);
    assert_int_equal(buf[0], 0);
    vs_patch_names(NULL, buf, sizeof buf);
    assert_int_equal(buf[sizeof buf - 1], 0);
    char all[400];
    vs_patch_names(", ", all, sizeof all);
    for (int k = 0; k < VS_PATCH_COUNT; k++) {
        assert_non_null(strstr(all, vs_patches[k].name));
        assert_ptr_equal(vs_patches[k].shader, vs_patch_shader((vs_patch)k));
    }
    int n = 0;
    for (; vs_shaders[n]; n++) assert_non_null(vs_shaders[n]->main);
    assert_true(n >= VS_PATCH_COUNT);
    const is_vertex_shader *named[] = {&vs_shader_flat, &vs_shader_npatch, &vs_shader_smooth_initial, &vs_shader_smooth,
                                       &vs_shader_phong, &vs_shader_pn_aen, &vs_shader_fixed};
    for (size_t k = 0; k < sizeof named / sizeof named[0]; k++) assert_ptr_equal(vs_find_shader(named[k]->name), named[k]);
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 2; j++) assert_true(vs_nadj_regs[k][j].usage < IS_DECLUSAGE_COUNT);
    /* constants: NULL registers, matrices, options; options read back from registers of any value */
    float4x4 id = mat_identity();
    vs_set_constants(NULL, &id, &id, (float4){1, 1, 1, 1}, NULL);
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    vs_set_constants(&c, NULL, &id, (float4){1, 1, 1, 1}, NULL);
    vs_set_constants(&c, &id, NULL, (float4){1, 1, 1, 1}, NULL);
    vs_options o = vs_options_from_constants(NULL);
    vs_options d = vs_default_options();
    assert_memory_equal(&o, &d, sizeof o);
    for (int a = 0; a < N_EDGE; a++)
        for (int b = 0; b < N_EDGE; b++) {
            c.c[VS_C_OPTIONS] = (float4){edge[a], edge[b], edge[(a + b) % N_EDGE], edge[(a * b + 1) % N_EDGE]};
            o = vs_options_from_constants(&c);
            vs_options r = vs_options_from_register(c.c[VS_C_OPTIONS]);
            assert_memory_equal(&o, &r, sizeof o);   /* the register read alone decodes the same */
            assert_true((unsigned)o.normals < 3);
            assert_true(isfinite(o.phong_alpha) && isfinite(o.quad_factor) && o.quad_factor != 0.0f);
            vs_options odd = {(vs_normals)(a - 3), edge[a], edge[b], (uint32_t)-1};
            vs_set_constants(&c, &id, &id, (float4){edge[a], 0, 0, 1}, &odd);   /* any option values are stored */
        }
}

/* A triangle of corner values v (normals n) with the given texcoords and id. */
static vs_triangle tri_of(float v, float n)
{
    const float3 vs3[3] = {{v, 0, 0}, {0, v, 0}, {0, 0, v}}, ns3[3] = {{n, 0, 0}, {0, n, 0}, {0, 0, n}};
    return vs_triangle_make(vs3, ns3);
}

/* The patch functions with NULL triangles and outputs, patches that do not exist, and every edge value. */
static void test_patch_functions(void **state)
{
    (void)state;
    vs_triangle z = vs_triangle_make(NULL, NULL);   /* a triangle of zeros */
    const float3 v3[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    vs_triangle t1 = vs_triangle_make(v3, NULL), t2 = vs_triangle_make(NULL, v3);
    (void)z, (void)t1, (void)t2;
    vs_triangle_from_input(NULL, &z);
    is_vs_input in;
    memset(&in, 0, sizeof in);
    vs_triangle_from_input(&in, NULL);
    float3 pos = {7, 7, 7}, nrm = {7, 7, 7}, g = {7, 7, 7};
    const float3 b = {0.2f, 0.3f, 0.5f};
    for (int p = -2; p < VS_PATCH_COUNT + 2; p++) {
        vs_patch_eval((vs_patch)p, NULL, b, NULL, &pos, &nrm, &g);
        vs_patch_eval((vs_patch)p, &t1, b, NULL, NULL, NULL, NULL);
        vs_patch_eval((vs_patch)p, &t1, b, NULL, &pos, &nrm, &g);
        (void)vs_patch_position((vs_patch)p, NULL, b, NULL);
        (void)vs_patch_position((vs_patch)p, &t1, b, NULL);
    }
    (void)vs_smooth_fn(NULL);
    (void)vs_smooth_formula(NULL, b, 0, &g, NULL);
    (void)vs_smooth_initial_formula(NULL, b, &g);
    vs_npatch_evaluate(NULL, NULL, b, IS_DEGREE_CUBIC, IS_DEGREE_LINEAR, &pos, &nrm);
    vs_npatch_evaluate(v3, v3, b, 0, 0xffffffffu, NULL, NULL);
    uint64_t total = 0;
    assert_int_equal(vs_smooth_shortcut_savings(NULL, 5, 4, &total), 0);
    assert_int_equal(vs_smooth_shortcut_savings(&t1, 1, 0, &total), 0);
    assert_int_equal(vs_smooth_shortcut_savings(&t1, 1, -7, &total), 0);
    assert_int_equal(vs_smooth_shortcut_savings(&t1, 1, INT_MIN, NULL), 0);
    assert_int_equal(vs_smooth_shortcut_savings(&t1, 0, 8, &total), 0);
    (void)vs_smooth_shortcut_savings(&t1, 1, 300, &total);   /* a large level: counts, no overflow of int */
    /* every value in every slot: positions, normals, barycentrics */
    for (int a = 0; a < N_EDGE; a++)
        for (int k = 0; k < N_EDGE; k++) {
            vs_triangle t = tri_of(edge[a], edge[k]);
            t.opp[1] = (float3){edge[k], edge[a], 0};
            t.id = edge[a];
            const float3 bs[] = {{edge[k], edge[a], 0}, {1, 0, 0}, {edge[k], 0.5f, 0.5f}, b};
            for (size_t q = 0; q < sizeof bs / sizeof bs[0]; q++) {
                vs_options o = vs_default_options();
                for (int nm = 0; nm < 3; nm++) {
                    o.normals = (vs_normals)nm;
                    o.phong_alpha = edge[a], o.quad_factor = edge[k];
                    for (int p = 0; p < VS_PATCH_COUNT; p++) vs_patch_eval((vs_patch)p, &t, bs[q], &o, &pos, &nrm, &g);
                }
                (void)vs_smooth_formula(&t, bs[q], VS_FLAG_NO_SHORTCUT, &g, NULL);
                (void)vs_smooth_initial_formula(&t, bs[q], NULL);
                (void)vs_gregory(bs[q]);
                (void)vs_evaluate_curve(t.v[0], t.v[1], t.n[0], t.n[1], bs[q].x);
                (void)vs_evaluate_npatch(t.v[0], t.v[1], t.v[2], t.n[0], t.n[1], t.n[2], bs[q]);
                vs_npatch_evaluate(t.v, t.n, bs[q], IS_DEGREE_CUBIC, VS_DEGREE_REAL, &pos, &nrm);
            }
            (void)vs_smooth_fn(&t);
        }
}

/* Every shader through main, its batch (if any) with every live mask, and its hull, on registers of every edge
 * value (the instance id too, which a shader might turn into an integer). */
static void test_shaders(void **state)
{
    (void)state;
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    float4x4 id = mat_identity();
    vs_set_constants(&c, &id, &id, (float4){1, 1, 1, 1}, NULL);
    enum { N = 4 };
    is_vs_input in[N];
    is_vs_output out[N];
    for (int s = 0; vs_shaders[s]; s++) {
        const is_vertex_shader *sh = vs_shaders[s];
        for (int a = 0; a < N_EDGE; a++) {
            memset(in, 0, sizeof in);
            for (int v = 0; v < N; v++) {
                float x = edge[(a + v) % N_EDGE];
                float *r = (float *)&in[v];
                for (size_t k = 0; k < sizeof in[v] / sizeof(float); k++) r[k] = k % 5 == 0 ? x : (float)(k % 3);
                in[v].position[0] = (float4){x, 0.25f, 0.5f, 1};
                in[v].texcoord[VS_IN_ID] = (float4){x, 0, 0, 1};
            }
            c.c[VS_C_OPTIONS] = (float4){edge[a], edge[a], edge[a], edge[a]};
            for (int v = 0; v < N; v++) sh->main(&c, &in[v], &out[v]);
            if (sh->batch)
                for (uint32_t live = 0; live < 4; live++)
                    sh->batch(&c, in, N, live ? VS_OUTPUTS >> (live - 1) : 0u, live == 3 ? IS_VS_REGS_INSTANCE : 0u,
                              out);
            if (sh->hull) {
                is_patch_hull h;
                (void)sh->hull(&c, &in[0], &h);
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names_and_options),
        cmocka_unit_test(test_patch_functions),
        cmocka_unit_test(test_shaders),
    };
    return cmocka_run_group_tests_name("api_vs", tests, NULL, NULL);
}
