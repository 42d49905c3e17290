/* tests/test_adaptive_d3d9.c -- D3D9's adaptive tessellation in the device's N-patch mode (core/device.h, "Adaptive
 * N-patch mode"): the render states with their documented defaults and their invalid values, TESSFACTOR in
 * declarations, the level rule against hand-computed levels, the edge levels a draw really tessellates with
 * (counted at the evaluator), renders with adaptivity off or uniform equal to the plain mode byte for byte, and
 * zero cracks on every built-in mesh with levels that differ from edge to edge (the parity detector of
 * tests/test_cracks.c, with its bit-keyed jitter). */
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
#include "../core/device_internal.h" /* the draw's edge levels (dev->npatch_lv) */
#include "util/golden.h"
#include "util/crack.h"
#include "util/prog.h"

#include "../core/hlsl.h"
/* Bits of a float, as float render states take them. */
static uint32_t fbits(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}
static float state_f(const is_device *dev, is_rs s)
{
    uint32_t v = 0;
    assert_int_equal(dev_get_render_state(dev, s, &v), IS_OK);
    float f;
    memcpy(&f, &v, 4);
    return f;
}

/* ---------------- states ---------------- */

/* The documented defaults: FALSE, MIN = MAX = 1.0f, (X, Y, Z, W) = (0, 0, 1, 0). */
static void test_state_defaults(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    uint32_t v = 7;
    assert_int_equal(dev_get_render_state(dev, IS_RS_ENABLEADAPTIVETESSELLATION, &v), IS_OK);
    assert_int_equal(v, 0);
    assert_true(state_f(dev, IS_RS_MINTESSELLATIONLEVEL) == 1.0f);
    assert_true(state_f(dev, IS_RS_MAXTESSELLATIONLEVEL) == 1.0f);
    assert_true(state_f(dev, IS_RS_ADAPTIVETESS_X) == 0.0f);
    assert_true(state_f(dev, IS_RS_ADAPTIVETESS_Y) == 0.0f);
    assert_true(state_f(dev, IS_RS_ADAPTIVETESS_Z) == 1.0f);
    assert_true(state_f(dev, IS_RS_ADAPTIVETESS_W) == 0.0f);
    /* D3D9's numbers */
    assert_int_equal(IS_RS_MINTESSELLATIONLEVEL, 178);
    assert_int_equal(IS_RS_ADAPTIVETESS_X, 180);
    assert_int_equal(IS_RS_ENABLEADAPTIVETESSELLATION, 184);
    dev_destroy(dev);
}

/* Valid values are kept; invalid ones fail with a message naming the value and change nothing. */
static void test_state_validation(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    assert_int_equal(dev_set_render_state(dev, IS_RS_ENABLEADAPTIVETESSELLATION, 1), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_MAXTESSELLATIONLEVEL, fbits(12.5f)), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_MINTESSELLATIONLEVEL, fbits(2.0f)), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_ADAPTIVETESS_W, fbits(-3.0f)), IS_OK);
    const struct { is_rs s; uint32_t v; } bad[] = {
        {IS_RS_ENABLEADAPTIVETESSELLATION, 2},
        /* (below 1 -- "cannot be less than 1" -- the runtime takes: tests/test_d3d9_api.c) */
        {IS_RS_MAXTESSELLATIONLEVEL, fbits(INFINITY)},
        {IS_RS_MINTESSELLATIONLEVEL, fbits(NAN)},
        {IS_RS_ADAPTIVETESS_X, fbits(NAN)},
        {IS_RS_ADAPTIVETESS_Z, fbits(-INFINITY)},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        uint32_t before, after;
        assert_int_equal(dev_get_render_state(dev, bad[k].s, &before), IS_OK);
        assert_int_equal(dev_set_render_state(dev, bad[k].s, bad[k].v), IS_ERR_INVALIDCALL);
        assert_non_null(strstr(dev_last_error(dev), "does not take value"));
        assert_int_equal(dev_get_render_state(dev, bad[k].s, &after), IS_OK);
        assert_int_equal(before, after);
    }
    assert_true(state_f(dev, IS_RS_MAXTESSELLATIONLEVEL) == 12.5f);
    assert_true(state_f(dev, IS_RS_MINTESSELLATIONLEVEL) == 2.0f);
    assert_true(state_f(dev, IS_RS_ADAPTIVETESS_W) == -3.0f);
    /* the states next to them stay unknown */
    assert_int_equal(dev_set_render_state(dev, (is_rs)177, 0), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(dev), "unknown render state 177"));
    assert_int_equal(dev_set_render_state(dev, (is_rs)190, 0), IS_ERR_INVALIDCALL);   /* 185: TWOSIDEDSTENCILMODE */
    dev_destroy(dev);
}

/* TESSFACTOR: FLOAT1 with usage index 0 only, as D3D9 requires; it fills in->tessfactor[0]. */
static void test_tessfactor_declaration(void **state)
{
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    is_vertex_declaration *d = NULL;
    const is_vertex_element ok[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
                                    {0, 12, IS_DECLTYPE_FLOAT1, 0, IS_DECLUSAGE_TESSFACTOR, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(dev, ok, &d), IS_OK);
    assert_int_equal(d->el[1].reg_offset, offsetof(is_vs_input, tessfactor));
    decl_release(d);
    const is_vertex_element wide[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
                                      {0, 12, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TESSFACTOR, 0}, IS_DECL_END};
    d = NULL;
    assert_int_equal(dev_create_vertex_declaration(dev, wide, &d), IS_ERR_INVALIDCALL);
    assert_null(d);
    assert_non_null(strstr(dev_last_error(dev), "TESSFACTOR must be FLOAT1"));
    const is_vertex_element index1[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
                                        {0, 12, IS_DECLTYPE_FLOAT1, 0, IS_DECLUSAGE_TESSFACTOR, 1}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(dev, index1, &d), IS_ERR_INVALIDCALL);
    assert_non_null(strstr(dev_last_error(dev), "usage 8 index 1 unsupported"));
    dev_destroy(dev);
}

/* ---------------- the rule ---------------- */

/* Per vertex T = S * F / dot(V, Mdm), levels worked out by hand. */
static void test_vertex_levels(void **state)
{
    const float4 z_axis = f4(0, 0, 1, 0); /* the default Mdm: the vertex's own z */
    /* S = 8 at z = 4: 2; at z = 1: 8; at z = 0.5: 16 */
    assert_true(core_adaptive_vertex_level(8.0f, 1.0f, f4(3, -2, 4, 1), z_axis) == 2.0f);
    assert_true(core_adaptive_vertex_level(8.0f, 1.0f, f4(0, 0, 1, 1), z_axis) == 8.0f);
    assert_true(core_adaptive_vertex_level(8.0f, 1.0f, f4(7, 7, 0.5f, 1), z_axis) == 16.0f);
    /* TESSFACTOR multiplies: F = 3 at z = 4 gives 6; F = 0.25 gives 0.5 */
    assert_true(core_adaptive_vertex_level(8.0f, 3.0f, f4(3, -2, 4, 1), z_axis) == 6.0f);
    assert_true(core_adaptive_vertex_level(8.0f, 0.25f, f4(3, -2, 4, 1), z_axis) == 0.5f);
    /* every component of Mdm counts, W against the vertex's w: (1, 2, 3, 1).(0.5, 0.25, 1, 2) = 0.5+0.5+3+2 = 6 */
    assert_true(core_adaptive_vertex_level(12.0f, 1.0f, f4(1, 2, 3, 1), f4(0.5f, 0.25f, 1, 2)) == 2.0f);
    /* behind the eye: negative; at depth 0: infinite (sign of the numerator) */
    assert_true(core_adaptive_vertex_level(8.0f, 1.0f, f4(0, 0, -2, 1), z_axis) == -4.0f);
    assert_true(core_adaptive_vertex_level(8.0f, 1.0f, f4(1, 1, 0, 1), z_axis) == INFINITY);
    assert_true(core_adaptive_vertex_level(8.0f, 1.0f, f4(-1, -1, -0.0f, -1), z_axis) == -INFINITY);
    assert_true(core_adaptive_vertex_level(-8.0f, 1.0f, f4(1, 1, 0, 1), z_axis) == -INFINITY);
    assert_true(isnan(core_adaptive_vertex_level(8.0f, 0.0f, f4(1, 1, 0, 1), z_axis)));
}

/* Per edge: the mean; above MAX, below 0 or NaN -> MAX; then below MIN -> MIN. */
static void test_edge_levels(void **state)
{
    assert_true(core_adaptive_edge_level(2.0f, 4.0f, 1.0f, 16.0f) == 3.0f);     /* mean */
    assert_true(core_adaptive_edge_level(4.0f, 2.0f, 1.0f, 16.0f) == 3.0f);     /* symmetric */
    assert_true(core_adaptive_edge_level(5.0f, 6.0f, 1.0f, 16.0f) == 5.5f);     /* not rounded */
    assert_true(core_adaptive_edge_level(20.0f, 14.0f, 1.0f, 16.0f) == 16.0f);  /* 17 > MAX -> MAX */
    assert_true(core_adaptive_edge_level(20.0f, 12.0f, 1.0f, 16.0f) == 16.0f);  /* 16 == MAX: kept */
    assert_true(core_adaptive_edge_level(30.0f, -4.0f, 1.0f, 16.0f) == 13.0f);  /* one end negative, mean 13 */
    assert_true(core_adaptive_edge_level(2.0f, -4.0f, 1.0f, 16.0f) == 16.0f);   /* mean -1 < 0 -> MAX, not MIN */
    assert_true(core_adaptive_edge_level(NAN, 2.0f, 1.0f, 16.0f) == 16.0f);     /* NaN -> MAX */
    assert_true(core_adaptive_edge_level(INFINITY, 2.0f, 1.0f, 16.0f) == 16.0f);
    assert_true(core_adaptive_edge_level(INFINITY, -INFINITY, 1.0f, 16.0f) == 16.0f); /* inf - inf: NaN */
    assert_true(core_adaptive_edge_level(0.5f, 1.0f, 1.0f, 16.0f) == 1.0f);     /* 0.75 < MIN -> MIN */
    assert_true(core_adaptive_edge_level(0.5f, 1.0f, 2.5f, 16.0f) == 2.5f);
    assert_true(core_adaptive_edge_level(0.0f, 0.0f, 3.0f, 16.0f) == 3.0f);     /* 0 is in range: MIN */
    assert_true(core_adaptive_edge_level(-1.0f, -1.0f, 3.0f, 8.0f) == 8.0f);    /* negative: MAX (above MIN) */
    assert_true(core_adaptive_edge_level(40.0f, 40.0f, 8.0f, 4.0f) == 8.0f);    /* MIN > MAX: MIN wins */
    /* the defaults MIN = MAX = 1: every edge 1 */
    const float t[] = {0.1f, 1.0f, 7.0f, 300.0f, -2.0f, NAN};
    for (size_t a = 0; a < 6; a++)
        for (size_t b = 0; b < 6; b++) assert_true(core_adaptive_edge_level(t[a], t[b], 1.0f, 1.0f) == 1.0f);
}

/* ---------------- the draw's levels, counted at the evaluator ---------------- */

/* Points the evaluator saw on each edge of the triangle (b with one zero coordinate; corners count on both
 * edges): edge k from v[k] to v[k+1] has a zero weight for the third vertex.  The device runs with one thread. */
static unsigned long edge_points[3], all_points;
static void eval_count(const float3 v[3], const float3 n[3], float3 b, uint32_t pd, uint32_t nd, float3 *pos,
                       float3 *nrm)
{
    const float w[3] = {b.x, b.y, b.z};
    for (int k = 0; k < 3; k++) edge_points[k] += w[(k + 2) % 3] == 0.0f;
    all_points++;
    *pos = add3(add3(scale3(v[0], b.x), scale3(v[1], b.y)), scale3(v[2], b.z));
    *nrm = n[0];
}
static void vs_pass(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    out->pos = f4(in->position[0].x * 0.1f, in->position[0].y * 0.1f, 0.5f, 1.0f);
    out->attr[RS_ATTR_COLOR0] = f4(1, 1, 1, 1);
}
static const is_vertex_shader pass_shader = {.name = "pass", .main = vs_pass, .outputs = IS_OUT_COLOR0};

typedef struct { float p[3], n[3], tf; } tf_vertex;

/* Draw one triangle with vertices at depths z[] and factors tf[] (tf NULL: no TESSFACTOR element) in adaptive
 * N-patch mode with S segments, MIN, MAX and edge style; the evaluator's counts are left in edge_points. */
static void draw_one(const float z[3], const float *tf, float S, float min, float max, uint32_t style)
{
    is_device *dev = dev_create(32, 32, 1, NULL, 0);
    dev_set_threads(dev, 1);
    is_vertex_buffer *vb;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
    assert_int_equal(dev_create_vertex_buffer(dev, 3 * sizeof(tf_vertex), &vb), IS_OK);
    assert_int_equal(dev_create_index_buffer(dev, 3 * 2, IS_FMT_INDEX16, &ib), IS_OK);
    tf_vertex *v = vb_lock(vb);
    const float xy[3][2] = {{0, 0}, {5, 0}, {0, 5}};
    for (int c = 0; c < 3; c++)
        v[c] = (tf_vertex){{xy[c][0], xy[c][1], z[c]}, {0, 0, -1}, tf ? tf[c] : 99.0f};
    uint16_t *idx = ib_lock(ib);
    idx[0] = 0, idx[1] = 1, idx[2] = 2;
    const is_vertex_element with[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
                                      {0, 12, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_NORMAL, 0},
                                      {0, 24, IS_DECLTYPE_FLOAT1, 0, IS_DECLUSAGE_TESSFACTOR, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(dev, tf ? with : (const is_vertex_element[]){with[0], with[1],
                                                                                                  with[3]},
                                                   &decl),
                     IS_OK);
    dev_set_vertex_declaration(dev, decl);
    dev_set_stream_source(dev, 0, vb, 0, sizeof(tf_vertex));
    dev_set_indices(dev, ib);
    dev_set_vertex_shader(dev, &pass_shader);
    dev_set_npatch_evaluator(dev, eval_count);
    assert_int_equal(dev_set_npatch_mode(dev, S), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_PATCHEDGESTYLE, style), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_ENABLEADAPTIVETESSELLATION, 1), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_MINTESSELLATIONLEVEL, fbits(min)), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_MAXTESSELLATIONLEVEL, fbits(max)), IS_OK);
    dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE);
    memset(edge_points, 0, sizeof edge_points), all_points = 0;
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, 3, 0, 1), IS_OK);
    assert_int_equal(dev_vertices_shaded(dev), all_points);
    decl_release(decl), vb_release(vb), ib_release(ib);
    dev_destroy(dev);
}

/* Segments per edge = points on it - 1. */
static void expect_segments(unsigned e0, unsigned e1, unsigned e2)
{
    assert_int_equal(edge_points[0], e0 + 1);
    assert_int_equal(edge_points[1], e1 + 1);
    assert_int_equal(edge_points[2], e2 + 1);
}

static void test_draw_edge_levels(void **state)
{
    /* S = 8, Mdm = (0, 0, 1, 0) (default): T = 8/1, 8/2, 8/4 = 8, 4, 2; edges (8+4)/2, (4+2)/2, (2+8)/2 = 6, 3, 5 */
    const float z[3] = {1, 2, 4};
    draw_one(z, NULL, 8.0f, 1.0f, 16.0f, IS_PATCHEDGE_DISCRETE);
    expect_segments(6, 3, 5);
    /* MAX = 4: 6 and 5 -> 4; MIN = 3.5 then lifts 3 (DISCRETE truncates 3.5 to 3) */
    draw_one(z, NULL, 8.0f, 1.0f, 4.0f, IS_PATCHEDGE_DISCRETE);
    expect_segments(4, 3, 4);
    draw_one(z, NULL, 8.0f, 4.0f, 16.0f, IS_PATCHEDGE_DISCRETE);
    expect_segments(6, 4, 5);
    /* TESSFACTOR (1, 2, 0.5): T = 8, 8, 1; edges 8, 4.5, 4.5 -> DISCRETE 8, 4, 4 */
    const float tf[3] = {1.0f, 2.0f, 0.5f};
    draw_one(z, tf, 8.0f, 1.0f, 16.0f, IS_PATCHEDGE_DISCRETE);
    expect_segments(8, 4, 4);
    /* the defaults MIN = MAX = 1: one segment per edge, the triangle itself */
    draw_one(z, NULL, 8.0f, 1.0f, 1.0f, IS_PATCHEDGE_DISCRETE);
    expect_segments(1, 1, 1);
    assert_int_equal(all_points, 3);
    /* a vertex behind the eye (z = -2: T = -4): edges (8-4)/2 = 2 and (-4+2)/2 = -1 -> MAX = 10 */
    const float zb[3] = {1, -2, 4};
    draw_one(zb, NULL, 8.0f, 1.0f, 10.0f, IS_PATCHEDGE_DISCRETE);
    expect_segments(2, 10, 5);
    /* CONTINUOUS: fractional_even segments: levels 6, 3, 5 -> 6, 4, 6 segments (the next even count) */
    draw_one(z, NULL, 8.0f, 1.0f, 16.0f, IS_PATCHEDGE_CONTINUOUS);
    expect_segments(6, 4, 6);
    /* levels above 64 are taken as 64 */
    const float zn[3] = {0.01f, 0.01f, 0.01f};
    draw_one(zn, NULL, 8.0f, 1.0f, 100.0f, IS_PATCHEDGE_DISCRETE);
    expect_segments(64, 64, 64);
}

/* ---------------- renders: off and uniform are the plain mode ---------------- */

/* Render mesh m in N-patch mode at `level` (scene_draw) with `setup` applied to the device first; the target's
 * bytes are copied into *pixels (malloc'd). */
typedef void (*dev_setup_fn)(is_device *dev, float level);
static void render_npatch(const is_mesh *m, float level, bool continuous, int threads, dev_setup_fn setup,
                          uint32_t **pixels, size_t *n)
{
    scene_opts o;
    scene_opts_default(&o);
    o.width = o.height = 96, o.msaa = 1, o.level = level, o.patch = VS_PATCH_NPATCH, o.path = SCENE_PATH_NPATCH_MODE;
    o.grid = continuous ? CORE_GRID_PG_FRACTIONAL_EVEN : CORE_GRID_REGULAR, o.yaw = 30.0f, o.pitch = 20.0f;
    o.fill = SCENE_FILL_SOLID_WIRE;
    is_device *dev = dev_create(o.width, o.height, 1, NULL, 0);
    dev_set_threads(dev, threads);
    if (setup) setup(dev, level);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0xff202020u, 1.0f);
    assert_int_equal(scene_draw(dev, &o, m, NULL, NULL), 0);
    const rs_target *rt = dev_render_target(dev);
    *n = (size_t)rt->width * rt->height;
    *pixels = malloc(*n * sizeof **pixels);
    memcpy(*pixels, rt->color, *n * sizeof **pixels);
    dev_destroy(dev);
}

/* Every adaptive state set to something else, adaptivity off. */
static void setup_off_but_set(is_device *dev, float level)
{
    dev_set_render_state(dev, IS_RS_MINTESSELLATIONLEVEL, fbits(2.0f));
    dev_set_render_state(dev, IS_RS_MAXTESSELLATIONLEVEL, fbits(7.0f));
    dev_set_render_state(dev, IS_RS_ADAPTIVETESS_X, fbits(0.3f));
    dev_set_render_state(dev, IS_RS_ADAPTIVETESS_Z, fbits(-2.0f));
    dev_set_render_state(dev, IS_RS_ADAPTIVETESS_W, fbits(5.0f));
}
/* Adaptivity on with MIN = MAX = the level: every edge at the level, whatever the depths. */
static void setup_uniform(is_device *dev, float level)
{
    setup_off_but_set(dev, level);
    dev_set_render_state(dev, IS_RS_ENABLEADAPTIVETESSELLATION, 1);
    dev_set_render_state(dev, IS_RS_MINTESSELLATIONLEVEL, fbits(level));
    dev_set_render_state(dev, IS_RS_MAXTESSELLATIONLEVEL, fbits(level));
}
/* Adaptivity on with levels from the mesh's own z: Mdm = (0, 0, 1, 2) puts the "depths" in [1, 3] for these
 * built-ins (within the unit ball), so the levels run from level / 3 to level. */
static void setup_varying(is_device *dev, float level)
{
    dev_set_render_state(dev, IS_RS_ENABLEADAPTIVETESSELLATION, 1);
    dev_set_render_state(dev, IS_RS_MAXTESSELLATIONLEVEL, fbits(3.0f * level));
    dev_set_render_state(dev, IS_RS_ADAPTIVETESS_W, fbits(2.0f));
}

/* Adaptivity off renders the plain N-patch mode whatever the other states; on with MIN = MAX = level it renders
 * the same bytes too (each triangle gets the plain grid); on with varying levels it differs (not vacuous); the
 * bytes do not depend on the thread count. */
static void test_off_and_uniform_are_plain(void **state)
{
    const char *meshes[] = {"sphere", "cube", "tetrahedron"};
    const struct { float level; bool continuous; } cases[] = {{1, false}, {5, false}, {8, false}, {4.6f, true},
                                                                {7.0f, true}};
    for (size_t mi = 0; mi < 3; mi++) {
        is_mesh m = {0};
        char err[256];
        assert_int_equal(mesh_builtin(meshes[mi], &m, err, sizeof err), 0);
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
            uint32_t *plain, *off, *uni, *var, *var1;
            size_t n;
            render_npatch(&m, cases[c].level, cases[c].continuous, 2, NULL, &plain, &n);
            render_npatch(&m, cases[c].level, cases[c].continuous, 2, setup_off_but_set, &off, &n);
            render_npatch(&m, cases[c].level, cases[c].continuous, 2, setup_uniform, &uni, &n);
            render_npatch(&m, cases[c].level, cases[c].continuous, 2, setup_varying, &var, &n);
            render_npatch(&m, cases[c].level, cases[c].continuous, 1, setup_varying, &var1, &n);
            assert_memory_equal(plain, off, n * sizeof *plain);
            assert_memory_equal(plain, uni, n * sizeof *plain);
            assert_memory_equal(var, var1, n * sizeof *var);
            if (cases[c].level > 1.0f && strcmp(meshes[mi], "tetrahedron") != 0)
                assert_memory_not_equal(plain, var, n * sizeof *plain);
            free(plain), free(off), free(uni), free(var), free(var1);
        }
        mesh_free(&m);
    }
}

/* The committed goldens of the N-Patch cube and tetrahedron (made before these states existed, on the instanced
 * path, which the N-patch mode matches byte for byte: tests/test_paths.c), drawn in N-patch mode with adaptivity
 * off, and on with Mdm = (0, 0, 0, 1) (every depth 1: every level 8); test_paths' golden thresholds. */
static void test_goldens_from_before(void **state)
{
    const char *names[2][2] = {{"npatch-cube", "cube"}, {"npatch-tetrahedron", "tetrahedron"}};
    for (int k = 0; k < 2; k++)
        for (int on = 0; on < 2; on++) {
            scene_opts o;
            scene_opts_default(&o);
            o.width = o.height = 160, o.level = 8, o.patch = VS_PATCH_NPATCH, o.path = SCENE_PATH_NPATCH_MODE;
            if (on) o.d3d9_adaptive = SCENE_D3D9_MDM, o.d3d9_mdm[3] = 1.0f;
            is_mesh m = {0};
            char err[256];
            assert_int_equal(mesh_builtin(names[k][1], &m, err, sizeof err), 0);
            is_image img = {0};
            assert_int_equal(scene_render_mesh(&o, &m, &img, NULL, err, sizeof err), 0);
            assert_int_equal(golden_check(&img, names[k][0], 1.0f / 255.0f, 0.1f), 0);
            image_free(&img);
            mesh_free(&m);
        }
}

/* ---------------- cracks ---------------- */

enum { SIZE = 96 };


/* The counting shader: oPos = POSITION0 * c0..c3, moved by up to half a pixel in x and y by a hash of its bits
 * (the jitter of tests/test_cracks.c: equal bits move equally, one ulp apart moves about a pixel apart); colour
 * 1/255, added up by the blend. */
static void vs_count(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    const float4x4 wvp = vs_const_matrix(c, 0);
    float4 P = mul4(f4_of(f3_of(in->position[0]), 1.0f), &wvp);
    crack_jitter(&P, SIZE);
    out->pos = P;
    out->attr[RS_ATTR_COLOR0] = f4(1.0f / 255.0f, 0, 0, 1.0f / 255.0f);
}
static const is_vertex_shader count_shader = {.name = "count", .main = vs_count, .outputs = IS_OUT_COLOR0};

/* A factor in [0.5, 2) from the bits of a position (the same for every vertex at that position), or from the
 * vertex's number when by_index (different across a seam of split vertices: a planted disagreement). */
static float factor_of(float3 p, uint32_t vertex, bool by_index)
{
    uint32_t h = by_index ? crack_mix32(vertex * 2654435761u) : crack_mix32(crack_bits(p.x) ^ crack_mix32(crack_bits(p.y) ^ crack_mix32(crack_bits(p.z))));
    return 0.5f + 1.5f * (float)(h & 0xffffu) / 65536.0f;
}

/* How a crack case draws. */
typedef struct crack_case {
    uint32_t pdeg, style;
    float segments;
    bool factors, factors_by_index;
} crack_case;

/* Draw m in adaptive N-patch mode as cc says, seen from (yaw, pitch) at distance 2.6 (scene.h's framing: centred,
 * unit radius) with Mdm = the view-depth column of World * View; count odd pixels and covered pixels, and the
 * distinct edge levels of the draw. */
static long adaptive_odd_pixels(const is_mesh *m, const crack_case *cc, float yaw, float pitch, long *covered,
                                int *distinct, bool *mixed)
{
    float3 lo = m->positions[0], hi = lo;
    for (size_t k = 1; k < m->n_vertices; k++) {
        float3 p = m->positions[k];
        lo = f3(fminf(lo.x, p.x), fminf(lo.y, p.y), fminf(lo.z, p.z));
        hi = f3(fmaxf(hi.x, p.x), fmaxf(hi.y, p.y), fmaxf(hi.z, p.z));
    }
    const float3 ctr = scale3(add3(lo, hi), 0.5f);
    float r = 0.0f;
    for (size_t k = 0; k < m->n_vertices; k++) r = fmaxf(r, length3(sub3(m->positions[k], ctr)));
    float4x4 tr = mat_translation(-ctr.x, -ctr.y, -ctr.z), s = mat_scaling(1.0f / r, 1.0f / r, 1.0f / r);
    float4x4 ry = mat_rotation_y(yaw * 3.14159265f / 180.0f), rx = mat_rotation_x(pitch * 3.14159265f / 180.0f);
    float4x4 w = mat_mul(&tr, &s);
    w = mat_mul(&w, &ry), w = mat_mul(&w, &rx);
    float4x4 view = mat_look_at_lh(f3(0, 0, -2.6f), f3(0, 0, 0), f3(0, 1, 0));
    float4x4 proj = mat_perspective_fov_lh(3.14159265f / 4.0f, 1.0f, 0.1f, 10.0f);
    float4x4 wv = mat_mul(&w, &view), wvp = mat_mul(&wv, &proj);

    is_device *dev = dev_create(SIZE, SIZE, 1, NULL, 0);
    dev_set_threads(dev, 2);
    is_vertex_buffer *vb;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
    assert_int_equal(dev_create_vertex_buffer(dev, m->n_vertices * sizeof(tf_vertex), &vb), IS_OK);
    assert_int_equal(dev_create_index_buffer(dev, 3 * m->n_triangles * 4, IS_FMT_INDEX32, &ib), IS_OK);
    tf_vertex *v = vb_lock(vb);
    for (size_t k = 0; k < m->n_vertices; k++) {
        float3 p = m->positions[k], nn = m->normals[k];
        v[k] = (tf_vertex){{p.x, p.y, p.z}, {nn.x, nn.y, nn.z}, factor_of(p, (uint32_t)k, cc->factors_by_index)};
    }
    memcpy(ib_lock(ib), m->indices, 3 * m->n_triangles * 4);
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
                                    {0, 12, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_NORMAL, 0},
                                    {0, 24, IS_DECLTYPE_FLOAT1, 0, IS_DECLUSAGE_TESSFACTOR, 0}, IS_DECL_END};
    const is_vertex_element el_nf[] = {el[0], el[1], el[3]};
    assert_int_equal(dev_create_vertex_declaration(dev, cc->factors ? el : el_nf, &decl), IS_OK);
    dev_set_vertex_declaration(dev, decl);
    dev_set_stream_source(dev, 0, vb, 0, sizeof(tf_vertex));
    dev_set_indices(dev, ib);
    dev_set_vertex_shader(dev, &count_shader);
    float rows[16];
    memcpy(rows, wvp.m, sizeof rows);
    dev_set_vertex_shader_constant_f(dev, 0, rows, 4);
    dev_set_npatch_evaluator(dev, vs_npatch_evaluate);
    dev_set_npatch_mode(dev, cc->segments);
    dev_set_render_state(dev, IS_RS_POSITIONDEGREE, cc->pdeg);
    dev_set_render_state(dev, IS_RS_PATCHEDGESTYLE, cc->style);
    dev_set_render_state(dev, IS_RS_ENABLEADAPTIVETESSELLATION, 1);
    dev_set_render_state(dev, IS_RS_MAXTESSELLATIONLEVEL, fbits(14.0f));
    /* Mdm: the third column of World * View, so dot(V, Mdm) is the view depth (2.6 +- 1) */
    for (int i = 0; i < 4; i++) dev_set_render_state(dev, (is_rs)(IS_RS_ADAPTIVETESS_X + i), fbits(wv.m[i][2]));
    crack_counting_states(dev);
    assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, (unsigned)m->n_vertices, 0,
                                                (unsigned)m->n_triangles),
                     IS_OK);
    /* the draw's edge levels: how many distinct ones, and whether some triangle has unequal edges */
    const float (*lv)[3] = dev->npatch_lv.p;
    float seen[65];
    *distinct = 0, *mixed = false;
    for (size_t t = 0; t < m->n_triangles; t++)
        for (int k = 0; k < 3; k++) {
            *mixed |= lv[t][k] != lv[t][0];
            int j = 0;
            while (j < *distinct && seen[j] != lv[t][k]) j++;
            if (j == *distinct && *distinct < 65) seen[(*distinct)++] = lv[t][k];
        }
    const rs_target *rt = dev_render_target(dev);
    long odd = 0;
    *covered = 0;
    for (int k = 0; k < SIZE * SIZE; k++) {
        unsigned c = rt->color[k] & 0xff;
        odd += c & 1;
        *covered += c != 0;
    }
    decl_release(decl), vb_release(vb), ib_release(ib);
    dev_destroy(dev);
    return odd;
}

/* Every built-in mesh, DISCRETE and CONTINUOUS, levels from the depth alone and from depth and TESSFACTOR, cubic
 * positions (linear where the normals split) and linear: no odd pixel, with levels that really differ per edge. */
static void test_no_cracks_adaptive(void **state)
{
    const float views[2][2] = {{30.0f, 20.0f}, {-115.0f, -47.0f}};
    long renders = 0;
    for (const char *const *name = mesh_builtin_names(); *name; name++) {
        is_mesh m = {0};
        char err[256];
        assert_int_equal(mesh_builtin(*name, &m, err, sizeof err), 0);
        const bool split = crack_split_normals(&m);
        for (int deg = 0; deg < 2; deg++) {
            if (deg == 0 && split) continue;
            for (int style = 0; style < 2; style++)
                for (int f = 0; f < 2; f++)
                    for (int vw = 0; vw < 2; vw++) {
                        crack_case cc = {deg ? IS_DEGREE_LINEAR : IS_DEGREE_CUBIC,
                                         style ? IS_PATCHEDGE_CONTINUOUS : IS_PATCHEDGE_DISCRETE, 16.0f, f == 1, false};
                        long covered;
                        int distinct;
                        bool mixed;
                        long odd =
                            adaptive_odd_pixels(&m, &cc, views[vw][0], views[vw][1], &covered, &distinct, &mixed);
                        if (odd)
                            fprintf(stderr, "cracks: %s degree %u style %u factors %d view %d: %ld odd pixels\n", *name,
                                    cc.pdeg, cc.style, f, vw, odd);
                        assert_int_equal(odd, 0);
                        assert_true(covered > SIZE * SIZE / 10);
                        assert_true(distinct >= 2); /* levels differ across the mesh */
                        if (m.n_triangles > 12 || f) assert_true(mixed); /* and within triangles */
                        renders++;
                    }
        }
        mesh_free(&m);
    }
    print_message("%ld adaptive renders without a crack\n", renders);
}

/* The detector sees a real disagreement: factors by vertex number split the levels of cube-split's seams (its
 * faces have their own vertices), and the flat patch then opens there. */
static void test_detector_finds_a_level_mismatch(void **state)
{
    is_mesh m = {0};
    char err[256];
    assert_int_equal(mesh_builtin("cube-split", &m, err, sizeof err), 0);
    crack_case cc = {IS_DEGREE_LINEAR, IS_PATCHEDGE_DISCRETE, 16.0f, true, false};
    long covered;
    int distinct;
    bool mixed;
    assert_int_equal(adaptive_odd_pixels(&m, &cc, 30.0f, 20.0f, &covered, &distinct, &mixed), 0);
    cc.factors_by_index = true;
    assert_true(adaptive_odd_pixels(&m, &cc, 30.0f, 20.0f, &covered, &distinct, &mixed) > 0);
    mesh_free(&m);
}

/* ---------------- the command line ---------------- */

/* --d3d9-adaptive: usage errors (exit 2, nothing written), Mdm = (0, 0, 0, 1) renders the plain mode's pixels
 * (every depth 1: every level --level), depth renders something else, the same at 1 and 2 threads. */
static void test_cli(void **state)
{
    char dir[256], a[512], b[512];
    const char *err;
    assert_int_equal(prog_mkdtemp(dir, "adaptive"), 0);
    const char *base = "sphere --patch npatch --path npatch-mode --level 12 --size 96x96 --fill solid+wire -q";
    assert_int_equal(prog_run(dir, &err, "", "%s --d3d9-adaptive depth --path instanced -o %s/x.png", base, dir), 2);
    assert_non_null(strstr(err, "--d3d9-adaptive is D3D9's adaptive N-patch mode: it needs --path npatch-mode"));
    assert_int_equal(prog_run(dir, &err, "", "%s --d3d9-adaptive 1,2,3 -o %s/x.png", base, dir), 2);
    assert_non_null(strstr(err, "--d3d9-adaptive takes depth or X,Y,Z,W (four finite numbers): 1,2,3"));
    assert_int_equal(prog_run(dir, &err, "", "%s --d3d9-adaptive 0,0,1,inf -o %s/x.png", base, dir), 2);
    assert_int_equal(prog_run(dir, &err, "", "%s --d3d9-adaptive depth --level 65 -o %s/x.png", base, dir), 2);
    assert_non_null(strstr(err, "--level must be 1..64"));
    assert_int_equal(prog_run(dir, &err, "", "%s --d3d9-adaptive 0,0,1,0,5 -o %s/x.png", base, dir), 2);
    assert_int_equal(
        prog_run(dir, &err, "", "%s --d3d9-adaptive depth --export-obj %s/x.obj -o %s/x.png", base, dir, dir), 2);
    assert_non_null(strstr(err, "cannot be combined with --d3d9-adaptive"));
    assert_int_equal(prog_entries_with(dir, NULL), 0);
    assert_int_equal(prog_run(dir, &err, "", "%s -o %s/plain.png", base, dir), 0);
    assert_int_equal(prog_run(dir, &err, "", "%s --d3d9-adaptive 0,0,0,1 -o %s/one.png", base, dir), 0);
    assert_int_equal(prog_run(dir, &err, "", "%s --d3d9-adaptive depth --threads 1 -o %s/depth1.png", base, dir), 0);
    assert_int_equal(prog_run(dir, &err, "", "%s --d3d9-adaptive depth --threads 2 -o %s/depth2.png", base, dir), 0);
    assert_true(prog_same_pixels(prog_path(dir, "plain.png", a, sizeof a), prog_path(dir, "one.png", b, sizeof b)));
    assert_false(prog_same_pixels(a, prog_path(dir, "depth1.png", b, sizeof b)));
    assert_true(prog_same_bytes(b, prog_path(dir, "depth2.png", a, sizeof a)));
    prog_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_state_defaults),
        cmocka_unit_test(test_state_validation),
        cmocka_unit_test(test_tessfactor_declaration),
        cmocka_unit_test(test_vertex_levels),
        cmocka_unit_test(test_edge_levels),
        cmocka_unit_test(test_draw_edge_levels),
        cmocka_unit_test(test_off_and_uniform_are_plain),
        cmocka_unit_test(test_goldens_from_before),
        cmocka_unit_test(test_detector_finds_a_level_mismatch),
        cmocka_unit_test(test_no_cracks_adaptive),
        cmocka_unit_test(test_cli),
    };
    return cmocka_run_group_tests_name("adaptive_d3d9", tests, NULL, NULL);
}
