/* tests/test_inspect.c -- the pipeline inspector (core/inspect.h, `instess inspect`).  What is checked:
 *  - recording changes no pixel of the render, and every pixel's last fragment is the target's final colour and
 *    depth (a pixel without fragments keeps the clear);
 *  - the recorded values equal an independent evaluation: each vertex's outputs are the shader run again on the
 *    registers the record lists, the barycentrics and depth are those of the vertices' screen positions in double
 *    precision at the pixel centre, the smoothed patch's published point is the listing's formula
 *    (vs_smooth_formula) at b transformed by c0..c3, and exactly one front fragment covers an interior pixel;
 *  - `instess inspect`: text and JSON, the final colour equals instess --msaa 1 -o's PNG, and its usage errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cli/run/scene.h"
#include "util/prog.h"

#define W 96
#define H 96

/* A render of builtin mesh `name` with patch p at level 5 (one sample) on a new device; the device. */
static is_device *render(const char *name, vs_patch p, is_mesh *m, core_grid *g, scene_opts *o, is_inspect *rec,
                         int x, int y)
{
    char err[512];
    scene_opts_default(o);
    o->width = W, o->height = H, o->level = 5, o->patch = p, o->msaa = 1, o->threads = 2;
    assert_int_equal(mesh_builtin(name, m, err, sizeof err), 0);
    assert_int_equal(core_grid_make(o->grid, o->level, g), 0);
    is_device *dev = scene_create_device(o, 1, 0, err, sizeof err);
    assert_non_null(dev);
    if (rec) assert_int_equal(dev_inspect_begin(dev, x, y, rec), IS_OK);
    assert_int_equal(scene_render_on(dev, o, m, g, NULL, err, sizeof err), 0);
    if (rec) dev_inspect_end(dev);
    return dev;
}

/* Registers of is_vs_input rebuilt from a recorded vertex's inputs (POSITION0 and TEXCOORDn, as vs.h lists). */
static void rebuild_inputs(const is_inspect_vertex *v, is_vs_input *in)
{
    memset(in, 0, sizeof *in);
    float4 *r = (float4 *)in;
    for (size_t k = 0; k < sizeof *in / sizeof(float4); k++) r[k] = (float4){0, 0, 0, 1};
    for (unsigned e = 0; e < v->n_inputs; e++) {
        const is_inspect_input *i = &v->inputs[e];
        if (i->usage == IS_DECLUSAGE_POSITION) in->position[i->usage_index] = i->value;
        else if (i->usage == IS_DECLUSAGE_TEXCOORD) in->texcoord[i->usage_index] = i->value;
        else fail_msg("unexpected input usage %u", i->usage);
    }
}

/* The published value called name of v, or NULL. */
static const float4 *value_of(const is_inspect_vertex *v, const char *name)
{
    for (unsigned n = 0; n < v->n_values; n++)
        if (strcmp(v->values[n].name, name) == 0) return &v->values[n].v;
    return NULL;
}

/* Screen position (double) of clip-space p on a W x H viewport (raster.h's mapping). */
static void screen(rs_vec4 p, double *x, double *y, double *z)
{
    *x = (1.0 + (double)p.x / p.w) * W / 2;
    *y = (1.0 - (double)p.y / p.w) * H / 2;
    *z = (double)p.z / p.w;
}

/* Check fragment f's barycentrics and depth against the double-precision ones of its vertices at pixel (px, py). */
static void check_bary(const is_inspect_fragment *f, int px, int py)
{
    double X[3], Y[3], Z[3];
    for (int k = 0; k < 3; k++) screen(f->v[k].out.pos, &X[k], &Y[k], &Z[k]);
    double area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    double l1 = ((px - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (py - Y[0])) / area;
    double l2 = ((X[1] - X[0]) * (py - Y[0]) - (px - X[0]) * (Y[1] - Y[0])) / area;
    double l[3] = {1.0 - l1 - l2, l1, l2};
    for (int k = 0; k < 3; k++) assert_true(l[k] > -1e-3 && l[k] < 1.0 + 1e-3);   /* the centre is inside */
    double z = l[0] * Z[0] + l[1] * Z[1] + l[2] * Z[2];   /* z/w is linear in screen space */
    assert_true(fabs(z - f->depth) < 1e-4);
    double q[3], s = 0;   /* perspective-correct: l_k / w_k normalised */
    for (int k = 0; k < 3; k++) s += q[k] = l[k] / f->v[k].out.pos.w;
    for (int k = 0; k < 3; k++) assert_true(fabs(q[k] / s - f->bary[k]) < 1e-3);
}

/* Recording changes no pixel; each pixel's last fragment is the target's pixel; values match a re-evaluation. */
static void test_pixels(void **state)
{
    (void)state;
    is_mesh m;
    core_grid g;
    scene_opts o;
    is_device *plain = render("cube", VS_PATCH_SMOOTH, &m, &g, &o, NULL, 0, 0);
    const rs_target *want = dev_render_target(plain);
    int checked = 0, covered = 0;
    for (int y = 3; y < H; y += 11)
        for (int x = 5; x < W; x += 13) {
            is_mesh m2;
            core_grid g2;
            is_inspect rec = {0};
            is_device *dev = render("cube", VS_PATCH_SMOOTH, &m2, &g2, &o, &rec, x, y);
            const rs_target *rt = dev_render_target(dev);
            assert_memory_equal(rt->color, want->color, (size_t)W * H * 4);   /* recording changes nothing */
            assert_memory_equal(rt->depth, want->depth, (size_t)W * H * 4);
            size_t px = (size_t)y * W + x;
            assert_int_equal(rec.draws, 1);
            assert_false(rec.out_of_memory);
            if (rec.n_fragments == 0) {
                assert_int_equal(rt->depth[px], 1.0f);   /* the clear: nothing drawn here */
            } else {
                const is_inspect_fragment *last = &rec.fragments[rec.n_fragments - 1];
                assert_int_equal(last->color_after, rt->color[px]);
                assert_true(last->depth == rt->depth[px] || !last->passed);
                covered++;
            }
            is_vs_constants c;
            memset(&c, 0, sizeof c);
            assert_int_equal(dev_get_vertex_shader_constant_f(dev, 0, &c.c[0].x, IS_MAX_VS_CONSTANTS), IS_OK);
            int passed = 0;
            for (size_t k = 0; k < rec.n_fragments; k++) {
                const is_inspect_fragment *f = &rec.fragments[k];
                passed += f->passed;
                check_bary(f, x, y);
                for (int v = 0; v < 3; v++) {
                    is_vs_input in;
                    is_vs_output out;
                    rebuild_inputs(&f->v[v], &in);
                    assert_memory_equal(&in, &f->v[v].regs, sizeof in);   /* the element list says the registers */
                    memset(&out, 0, sizeof out);
                    vs_shader_smooth.main(&c, &in, &out);
                    assert_memory_equal(&out.pos, &f->v[v].out.pos, sizeof out.pos);
                    assert_memory_equal(&out.attr[RS_ATTR_COLOR0], &f->v[v].out.attr[RS_ATTR_COLOR0], sizeof(rs_vec4));
                    const float4 *b = value_of(&f->v[v], "b"), *where = value_of(&f->v[v], "where");
                    const float4 *pos = value_of(&f->v[v], "pos"), *posN = value_of(&f->v[v], "posN");
                    assert_non_null(b), assert_non_null(pos), assert_non_null(posN), assert_non_null(where);
                    assert_memory_equal(b, &in.position[0], 3 * sizeof(float));
                    if (where->x == 0.0f) {   /* inside: the point is Listing 1.1.2's formula, as published */
                        vs_triangle tri;
                        vs_triangle_from_input(&in, &tri);
                        float3 want_pos = vs_smooth_formula(&tri, (float3){b->x, b->y, b->z}, 0, NULL, NULL);
                        assert_memory_equal(&want_pos, pos, sizeof want_pos);
                        float3 want_n = vs_evaluate_npatch(tri.v[0], tri.v[1], tri.v[2], tri.n[0], tri.n[1],
                                                           tri.n[2], (float3){b->x, b->y, b->z});
                        assert_memory_equal(&want_n, posN, sizeof want_n);
                    }
                }
            }
            assert_true(passed <= 1 || rec.n_fragments > 1);
            /* a closed convex mesh drawn with culling: at most one front fragment per pixel centre */
            assert_true(rec.n_fragments <= 1);
            checked++;
            is_inspect_free(&rec);
            dev_destroy(dev);
            mesh_free(&m2);
            core_grid_free(&g2);
        }
    assert_true(checked > 40 && covered > 10);
    dev_destroy(plain);
    mesh_free(&m);
    core_grid_free(&g);
}

/* With culling off, a pixel of the cube's centre sees the back face first or second, and the depth test decides. */
static void test_depth_order(void **state)
{
    (void)state;
    char err[512];
    is_mesh m;
    core_grid g;
    scene_opts o;
    scene_opts_default(&o);
    o.width = W, o.height = H, o.level = 3, o.msaa = 1, o.cull = IS_CULL_NONE;
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);
    assert_int_equal(core_grid_make(o.grid, o.level, &g), 0);
    is_device *dev = scene_create_device(&o, 1, 0, err, sizeof err);
    is_inspect rec = {0};
    assert_int_equal(dev_inspect_begin(dev, W / 2, H / 2, &rec), IS_OK);
    assert_int_equal(scene_render_on(dev, &o, &m, &g, NULL, err, sizeof err), 0);
    assert_int_equal(rec.n_fragments, 2);   /* the front and the back of the cube */
    const is_inspect_fragment *a = &rec.fragments[0], *b = &rec.fragments[1];
    assert_int_equal(a->passed, a->depth <= a->depth_before);
    assert_int_equal(b->passed, b->depth <= b->depth_before);
    assert_true(a->passed != b->passed || a->depth > b->depth);   /* the nearer one wins */
    assert_true(b->depth_before == (a->passed ? a->depth : a->depth_before));
    is_inspect_free(&rec);
    dev_destroy(dev);
    mesh_free(&m);
    core_grid_free(&g);
}

/* Refusals: NULL device or record, a pixel outside, a multisampled target; end without begin does nothing. */
static void test_refusals(void **state)
{
    (void)state;
    char err[256];
    scene_opts o;
    scene_opts_default(&o);
    o.width = 8, o.height = 8;
    is_inspect rec = {0};
    assert_int_equal(dev_inspect_begin(NULL, 0, 0, &rec), IS_ERR_INVALIDCALL);
    is_device *dev = scene_create_device(&o, 1, 0, err, sizeof err);
    assert_int_equal(dev_inspect_begin(dev, 0, 0, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_inspect_begin(dev, 8, 0, &rec), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_inspect_begin(dev, 0, -1, &rec), IS_ERR_INVALIDCALL);
    dev_inspect_end(dev);
    dev_inspect_end(NULL);
    is_inspect_free(NULL);
    dev_destroy(dev);
    dev = scene_create_device(&o, 4, 0, err, sizeof err);
    assert_int_equal(dev_inspect_begin(dev, 0, 0, &rec), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(dev), "samples"));
    dev_destroy(dev);
    assert_string_equal(is_decl_usage_name(IS_DECLUSAGE_TEXCOORD), "TEXCOORD");
    assert_string_equal(is_decl_usage_name(99), "?");
}

/* The program: JSON whose final colour is the PNG's pixel, text, and usage errors. */
static void test_program(void **state)
{
    (void)state;
    char dir[256], path[512], cmd[1400];
    assert_int_equal(prog_mkdtemp(dir, "inspect"), 0);
    const char *err;
    assert_int_equal(prog_run(dir, &err, "", "cube --size 64x64 --level 4 --msaa 1 -q -o %s",
                              prog_path(dir, "a.png", path, sizeof path)), 0);
    is_image img;
    char e[256];
    assert_int_equal(image_read(&img, path, e, sizeof e), 0);
    snprintf(cmd, sizeof cmd, "%s inspect cube --size 64x64 --level 4 --pixel 30,33 --json -q > %s/out.json",
             prog_bin(), dir);
    assert_int_equal(system(cmd), 0);
    size_t n;
    char *json = (char *)prog_slurp(prog_path(dir, "out.json", path, sizeof path), &n);
    assert_non_null(json);
    const char *fin = strstr(json, "\"final\": {\"color\": \"#");
    assert_non_null(fin);
    unsigned r, gc, b;
    assert_int_equal(sscanf(fin + strlen("\"final\": {\"color\": \"#"), "%2x%2x%2x", &r, &gc, &b), 3);
    const float *p = img.data + ((size_t)33 * 64 + 30) * img.channels;
    assert_int_equal(r, (unsigned)lrintf(p[0] * 255.0f));
    assert_int_equal(gc, (unsigned)lrintf(p[1] * 255.0f));
    assert_int_equal(b, (unsigned)lrintf(p[2] * 255.0f));
    assert_non_null(strstr(json, "\"posN\": ["));   /* the smoothed patch publishes its intermediates */
    assert_non_null(strstr(json, "\"usage\": \"TEXCOORD\", \"usage_index\": 12"));
    image_free(&img);
    free(json);
    /* under another light the patch is wrapped (cli/run/lighting.c): the wrapper forwards what the patch publishes */
    snprintf(cmd, sizeof cmd, "%s inspect cube --light grazing --size 64x64 --level 4 --pixel 30,33 --json -q > %s/lit.json",
             prog_bin(), dir);
    assert_int_equal(system(cmd), 0);
    json = (char *)prog_slurp(prog_path(dir, "lit.json", path, sizeof path), &n);
    assert_non_null(json);
    assert_non_null(strstr(json, "\"posN\": ["));
    free(json);
    /* the note on stderr: the default --msaa 4 is not what is inspected */
    assert_int_equal(prog_run(dir, &err, "", "inspect cube --size 64x64 --level 4 --pixel 30,33"), 0);
    assert_non_null(strstr(err, "one sample per pixel"));
    assert_int_equal(prog_run(dir, &err, "", "inspect cube --size 64x64 --pixel 64,0"), 2);
    assert_non_null(strstr(err, "outside the 64x64 image"));
    assert_int_equal(prog_run(dir, &err, "", "inspect cube --size 64x64"), 2);
    assert_non_null(strstr(err, "--pixel X,Y is required"));
    assert_int_equal(prog_run(dir, &err, "", "inspect cube --pixel 1,x"), 2);
    assert_int_equal(prog_run(dir, &err, "", "inspect cube --pixel 1,1 -o %s", prog_path(dir, "b.png", path, sizeof path)), 2);
    assert_false(prog_exists(dir, "b.png"));
    assert_int_equal(prog_run(dir, &err, "", "inspect no-such-mesh.obj --pixel 1,1"), 1);
    assert_non_null(strstr(err, "no-such-mesh.obj"));
    prog_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pixels),
        cmocka_unit_test(test_depth_order),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_program),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
