/* tests/test_raster_multi_grid.c -- the grid rows' stamp lanes (span.c's rs_tri_run with `stamp` lanes): the small
 * triangles of a step (up to 8 consecutive triangles of a grid row, boxes at most 4 x 8) in plain modes.  Frames of
 * small grid instances (triangles of ~1 to ~6 pixels, so that a step's triangles can share a group of 8 lanes),
 * each instance folded -- a column moved past its neighbour, so that triangles of one step cover the same pixels
 * -- with the fold in front and behind, with equal depths (flat instances: LESSEQUAL lets the later triangle win,
 * LESS the earlier), tall thin instances (boxes of 4 x 8 pixels with more than 8 covered pixels), centred on the tile
 * borders, depth LESSEQUAL and LESS with writes: every byte of colour and depth and every counter must equal the
 * reference path's, on 1 and 2 threads, scene on and off, every instruction set the CPU has, and the stamp lanes must
 * be taken (the chunks' grid_direct count).  Deterministic: fixed seeds. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../core/core.h"
#include "../raster/raster_internal.h"
#include "util/raster_util.h"

enum { W = 200, H = 136, INST = 24, PIECES = 2 };

/* One draw: its state, grid level, and PIECES pieces of INST instances (vertices; the pieces' index list). */
typedef struct draw_def {
    rs_state st;
    int level;
    size_t points, prims;           /* per instance */
    rs_vertex *v[PIECES];
    uint32_t *idx;
} draw_def;

/* rs_produce_fn: piece p of draw d as it is. */
static size_t produce(void *ctx, size_t piece, int slot, rs_vertex **verts, size_t *n_verts, const uint32_t **idx)
{
    const draw_def *d = ctx;
    (void)slot;
    *verts = d->v[piece], *n_verts = (size_t)INST * d->points, *idx = d->idx;
    return (size_t)INST * d->prims;
}

/* A pixel coordinate near a tile border (a multiple of RS_TILE_SIZE inside the target of size n) or anywhere. */
static float near_border(uint64_t *s, int n)
{
    return test_rnd(s) % 2 ? (float)(RS_TILE_SIZE * (1 + (int)(test_rnd(s) % (unsigned)(n / RS_TILE_SIZE)))) +
                                 test_frnd(s, -6.0f, 6.0f)
                           : test_frnd(s, 4.0f, (float)n - 4.0f);
}
_Static_assert(W >= RS_TILE_SIZE && H >= RS_TILE_SIZE, "a tile border inside the target");

/* One level-L instance into v: edges e1, e2 of ~size pixels (tall: e1 short, e2 long and near vertical: boxes of
 * 4 x 8 pixels) around a pixel near a tile border; column `fold` moved past its neighbours by `by` columns (its row
 * triangles turn round and cover their neighbours' pixels), its depth moved by dz (in front, behind); flat: one
 * depth for the whole instance (ties). */
static void make_instance(uint64_t *s, int L, rs_vertex *v, bool tall, bool flat)
{
    const float size = tall ? test_frnd(s, 1.5f, 3.5f) * (float)L : test_frnd(s, 1.2f, 3.2f) * (float)L;
    const float px = near_border(s, W), py = near_border(s, H), ang = test_frnd(s, 0.0f, 6.28f);
    float e1x = size * cosf(ang), e1y = size * sinf(ang);
    float e2x = size * cosf(ang + test_frnd(s, 0.9f, 2.2f)), e2y = size * sinf(ang + test_frnd(s, 0.9f, 2.2f));
    if (tall) e1x = test_frnd(s, 0.8f, 1.6f) * (float)L, e1y = 0.0f, e2x = test_frnd(s, -0.5f, 0.5f) * (float)L,
              e2y = test_frnd(s, 5.0f, 7.0f) * (float)L;
    const int fold = 1 + (int)(test_rnd(s) % (unsigned)(L - 1));
    const float by = test_frnd(s, 1.2f, 2.8f), dz = test_rnd(s) % 2 ? 0.05f : -0.05f;
    const float z0 = test_frnd(s, 0.2f, 0.8f);
    for (int k = 0; k <= L; k++)
        for (int i = 0; i + k <= L; i++) {
            rs_vertex *o = &v[core_grid_index(L, i, k)];
            memset(o, 0, sizeof *o);
            float a = (float)i / (float)L, b = (float)k / (float)L, z = flat ? z0 : z0 + test_frnd(s, -0.03f, 0.03f);
            if (i == fold) a -= by / (float)L, z += flat ? 0.0f : dz;
            const float x = px + a * e1x + b * e2x - 0.3f * e1x, y = py + a * e1y + b * e2y - 0.3f * e2y;
            o->pos = (rs_vec4){x / (W / 2.0f) - 1.0f, 1.0f - y / (H / 2.0f), z, 1.0f};
            o->attr[RS_ATTR_COLOR0] =
                (rs_vec4){test_frnd(s, 0, 1), test_frnd(s, 0, 1), test_frnd(s, 0, 1), test_frnd(s, 0.3f, 1)};
        }
}

/* Draw d of level L, depth function f (writes on), instances tall or not, flat or not. */
static void make_draw(uint64_t *s, draw_def *d, int L, int f, bool tall, bool flat)
{
    d->st = (rs_state){.cull_mode = RS_CULL_NONE, .fill_mode = RS_FILL_SOLID, .shade_mode = RS_SHADE_GOURAUD,
                       .z_enable = true, .z_write = true, .z_func = f, .src_blend = RS_BLEND_ONE,
                       .dst_blend = RS_BLEND_ZERO, .attr_mask = 1u << RS_ATTR_COLOR0,
                       .viewport = {0, 0, W, H, 0.0f, 1.0f}};
    d->level = L, d->points = core_grid_points(L), d->prims = core_grid_triangles(L);
    d->idx = test_grid_instances(L, INST);
    for (int p = 0; p < PIECES; p++) {
        d->v[p] = malloc(INST * d->points * sizeof *d->v[p]);
        assert_non_null(d->v[p]);
        for (int k = 0; k < INST; k++) make_instance(s, L, d->v[p] + k * d->points, tall, flat);
    }
}

static void free_draw(draw_def *d)
{
    free(d->idx);
    for (int p = 0; p < PIECES; p++) free(d->v[p]);
}

/* What a frame drew: planes, summed counters, the triangles rs_tri_run took straight to the small walks. */
typedef struct result {
    uint32_t color[W * H];
    float depth[W * H];
    rs_stats sum;
    uint64_t grid_direct;
} result;

/* Draw the n draws d on a fresh context: reference path or not, threads, instruction set, scene on or off. */
static void draw_all(const draw_def *d, int n, bool reference, int threads, int isa, bool scene, result *out)
{
    rs_context *rs = rs_create(threads);
    rs_target rt;
    assert_non_null(rs);
    assert_int_equal(rs_set_isa(rs, isa), RS_OK);
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_stats sink = {0}, st;
    memset(&out->sum, 0, sizeof out->sum);
    out->grid_direct = 0;
    rs_set_reference_path(rs, reference);
    rs_set_scene(rs, scene ? &sink : NULL);
    rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0xff402010u, 1.0f);
    for (int k = 0; k < n; k++) {
        rs_source src = {.n_pieces = PIECES, .n_prims = PIECES * INST * d[k].prims,
                         .max_verts = INST * d[k].points, .produce = produce, .ctx = (void *)&d[k],
                         .group_prims = d[k].prims, .grid_level = (size_t)d[k].level};
        assert_int_equal(rs_draw_source(rs, &d[k].st, &rt, &src, &st), RS_OK);
        test_rs_stats_add(&out->sum, &st);
        if (!scene)
            for (size_t c = 0; c < PIECES; c++) out->grid_direct += rs->chunks[c].grid_direct;
    }
    test_rs_frame_end(rs, &rt, &sink, &out->sum, out->color, out->depth, W * H);
}

/* Draws of one kind (tall or not, flat or not) in LESSEQUAL and LESS, levels 5, 8 and 16: the fast path's bytes
 * and counters against the reference's on every combination. */
static void one_kind(bool tall, bool flat, uint64_t seed)
{
    enum { N = 6 };
    static const int levels[N] = {16, 8, 5, 16, 8, 5};
    draw_def d[N];
    uint64_t s = seed;
    for (int k = 0; k < N; k++)
        make_draw(&s, &d[k], levels[k], k % 2 ? RS_CMP_LESS : RS_CMP_LESSEQUAL, tall, flat);
    result *ref = malloc(sizeof *ref), *r = malloc(sizeof *r);
    assert_true(ref && r);
    draw_all(d, N, true, 1, RS_ISA_AVX2, false, ref);
    assert_true(ref->sum.samples_written > 2000);
    for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
        if (!rs_isa_supported(isa)) continue;
        for (int threads = 1; threads <= 2; threads++)
            for (int scene = 0; scene < 2; scene++) {
                draw_all(d, N, false, threads, isa, scene, r);
                test_rs_same_frame(ref->color, ref->depth, &ref->sum, r->color, r->depth, &r->sum, W * H);
                if (!scene) assert_true(r->grid_direct > ref->sum.prims_drawn / 2); /* the small walks */
            }
    }
    for (int k = 0; k < N; k++) free_draw(&d[k]);
    free(ref), free(r);
}

/* Folded instances of small triangles, fold in front or behind. */
static void test_multi_folds(void **state)
{
    (void)state;
    for (uint64_t seed = 1; seed <= 3; seed++) one_kind(false, false, 0x9e3779b97f4a7c15ull * seed);
}

/* Folded flat instances: equal depths where the fold covers its neighbours (LESSEQUAL: the later triangle's
 * colour, LESS: the earlier's). */
static void test_multi_ties(void **state)
{
    (void)state;
    for (uint64_t seed = 1; seed <= 3; seed++) one_kind(false, true, 0x2545f4914f6cdd1dull * seed);
}

/* Tall thin folded instances: boxes up to 4 x 8 pixels, triangles of more than 8 covered pixels. */
static void test_multi_tall(void **state)
{
    (void)state;
    for (uint64_t seed = 1; seed <= 2; seed++) {
        one_kind(true, false, 0xd1b54a32d192ed03ull * seed);
        one_kind(true, true, 0xabcdef12345ull * seed);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_multi_folds),
        cmocka_unit_test(test_multi_ties),
        cmocka_unit_test(test_multi_tall),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
