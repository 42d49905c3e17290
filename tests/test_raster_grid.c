/* tests/test_raster_grid.c -- grid groups (rs_source.grid_level): a grouped piece whose instances are the regular
 * barycentric grid of level L (core_grid_regular) is set up from its vertex rows in the tile pass, without its
 * index list.  Frames of grid instances of levels 1, 2, 5, 16 and 40 -- small and large (past the row path's
 * 128-pixel budget and past four tiles: those take the rs_gtri / per-triangle paths), straddling tile borders,
 * partly off screen, with a column folded over its neighbour (rows partly back-facing: partly culled under a cull
 * mode) or a row collapsed onto the one below (degenerate triangles), a few pieces needing clipping -- under random
 * states must give the reference path's bytes and counters with the grid level told, untold and on the reference
 * path, 1 and 2 threads, scene on and off, every instruction set the CPU has; and the row path must be taken (the
 * chunks' grid_groups count).  The same frames with every index list mirrored (each triangle's second and third
 * index swapped, rs_source.grid_mirrored: the adaptive buckets' odd ranges) too.  core_grid_regular_level and
 * core_grid_regular_level_mirrored, which the device asks once per draw, must tell the regular list and its mirror
 * from others.  Deterministic: fixed seeds. */
#include <fenv.h>
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

enum { W = 320, H = 240, DRAWS = 10, PIECES = 3, INST = 5, MAXL = 40 };
enum { MAXP = (MAXL + 1) * (MAXL + 2) / 2 };

/* One draw: its state, grid level and pieces of INST instances (vertices, and the piece's index list). */
typedef struct draw_def {
    rs_state st;
    int level, inst;                /* level, instances per piece */
    size_t cut;                     /* triangles the pieces leave off their end (the last group partial) */
    size_t points, prims;           /* per instance */
    rs_vertex *v[PIECES];           /* INST * points each */
    uint32_t *idx;                  /* INST instances: core_grid_regular's list moved by k * points */
    uint32_t *idx_m;                /* the same mirrored: each triangle's second and third index swapped */
} draw_def;
typedef struct frame { draw_def d[DRAWS]; } frame;

/* rs_produce_fn: piece p of draw d as it is. */
static size_t produce(void *ctx, size_t piece, int slot, rs_vertex **verts, size_t *n_verts, const uint32_t **idx)
{
    const draw_def *d = ctx;
    (void)slot;
    *verts = d->v[piece], *n_verts = (size_t)d->inst * d->points, *idx = d->idx;
    return (size_t)d->inst * d->prims - d->cut;
}

/* rs_produce_fn: piece p of draw d with its mirrored list. */
static size_t produce_mirrored(void *ctx, size_t piece, int slot, rs_vertex **verts, size_t *n_verts,
                               const uint32_t **idx)
{
    const size_t n = produce(ctx, piece, slot, verts, n_verts, idx);
    *idx = ((const draw_def *)ctx)->idx_m;
    return n;
}

/* Random states on the fast path: cull, depth function and writes, depth bias, blending, scissor, viewport
 * offsets. */
static rs_state random_state(uint64_t *s)
{
    rs_state st = {.cull_mode = RS_CULL_NONE + (int)(test_rnd(s) % 3), .fill_mode = RS_FILL_SOLID,
                   .shade_mode = RS_SHADE_GOURAUD, .z_enable = true, .z_write = test_rnd(s) % 4 != 0,
                   .z_func = test_rnd(s) % 3 == 0 ? RS_CMP_LESS : (test_rnd(s) % 2 ? RS_CMP_LESSEQUAL : RS_CMP_GREATER),
                   .src_blend = RS_BLEND_ONE, .dst_blend = RS_BLEND_ZERO, .attr_mask = 1u << RS_ATTR_COLOR0,
                   .viewport = {0, 0, W, H, 0.0f, 1.0f}};
    if (test_rnd(s) % 4 == 0)
        st.blend_enable = true, st.src_blend = RS_BLEND_SRCALPHA, st.dst_blend = RS_BLEND_INVSRCALPHA;
    if (test_rnd(s) % 3 == 0)
        st.depth_bias = test_frnd(s, -0.01f, 0.01f), st.slope_scale_depth_bias = test_frnd(s, 0.0f, 2.0f);
    if (test_rnd(s) % 5 == 0)
        st.viewport = (rs_viewport){(int)(test_rnd(s) % 90), (int)(test_rnd(s) % 60), 210, 150, 0.0f, 1.0f};
    if (test_rnd(s) % 5 == 0) {
        int x0 = (int)(test_rnd(s) % 200), y0 = (int)(test_rnd(s) % 120);
        st.scissor_enable = true, st.scissor = (rs_rect){x0, y0, x0 + 100, y0 + 80};
    }
    return st;
}

/* One level-L grid instance into v[0..points): the triangle p0, p0 + e1, p0 + e2 of size r (NDC) around a random
 * centre, its points at core_grid_index(L, i, k) jittered; now and then column `fold` moved past its neighbour
 * (triangles of each row turn round) or row `flat` put onto the row below (zero-area triangles); `far`: one vertex
 * behind the near plane or past the guard band. */
static void make_instance(uint64_t *s, int L, float r, rs_vertex *v, bool far)
{
    const float w = test_frnd(s, 0.7f, 1.6f), cx = test_frnd(s, -1.1f, 1.1f), cy = test_frnd(s, -1.1f, 1.1f);
    const float z = test_frnd(s, 0.05f, 0.95f), ang = test_frnd(s, 0.0f, 6.28f);
    const float e1x = r * cosf(ang), e1y = r * sinf(ang);
    const float e2x = r * cosf(ang + test_frnd(s, 0.8f, 2.2f)), e2y = r * sinf(ang + test_frnd(s, 0.8f, 2.2f));
    const int fold = L > 1 && test_rnd(s) % 3 == 0 ? 1 + (int)(test_rnd(s) % (unsigned)(L - 1)) : -1;
    const int flat = L > 1 && test_rnd(s) % 4 == 0 ? 1 + (int)(test_rnd(s) % (unsigned)(L - 1)) : -1;
    for (int k = 0; k <= L; k++)
        for (int i = 0; i + k <= L; i++) {
            rs_vertex *o = &v[core_grid_index(L, i, k)];
            memset(o, 0, sizeof *o);
            float a = (float)i / (float)L, b = (float)k / (float)L;
            if (i == fold) a -= 1.7f / (float)L;   /* past column i - 1: the row's triangles there turn round */
            const float j = 0.15f * r / (float)L;
            const float x = cx + a * e1x + b * e2x + test_frnd(s, -j, j),
                        y = cy + a * e1y + b * e2y + test_frnd(s, -j, j);
            o->pos = (rs_vec4){x * w, y * w, (z + test_frnd(s, -0.04f, 0.04f)) * w, w};
            o->attr[RS_ATTR_COLOR0] =
                (rs_vec4){test_frnd(s, 0, 1), test_frnd(s, 0, 1), test_frnd(s, 0, 1), test_frnd(s, 0.3f, 1)};
            if (k == flat && i + k < L) o->pos = v[core_grid_index(L, i, k - 1)].pos;   /* onto row k - 1 */
        }
    if (far) {
        rs_vertex *o = &v[test_rnd(s) % core_grid_points(L)];
        if (test_rnd(s) % 2) o->pos.z = -0.5f * o->pos.w;        /* behind the near plane */
        else o->pos.x = 400.0f * o->pos.w;                   /* past the guard band */
    }
}

/* Draw d of level L with instances of size around r: its index list and pieces (one in six with a far vertex). */
static void make_draw(uint64_t *s, draw_def *d, int L, float rlo, float rhi)
{
    d->st = random_state(s);
    d->level = L, d->inst = INST, d->cut = 0, d->points = core_grid_points(L), d->prims = core_grid_triangles(L);
    d->idx = test_grid_instances(L, INST);
    d->idx_m = malloc(3 * INST * d->prims * sizeof *d->idx_m);
    assert_non_null(d->idx_m);
    for (size_t t = 0; t < INST * d->prims; t++)
        d->idx_m[3 * t] = d->idx[3 * t], d->idx_m[3 * t + 1] = d->idx[3 * t + 2], d->idx_m[3 * t + 2] = d->idx[3 * t + 1];
    for (int p = 0; p < PIECES; p++) {
        d->v[p] = malloc(INST * d->points * sizeof *d->v[p]);
        assert_non_null(d->v[p]);
        const int far = test_rnd(s) % 6 == 0 ? (int)(test_rnd(s) % INST) : -1;
        for (int k = 0; k < INST; k++) make_instance(s, L, test_frnd(s, rlo, rhi), d->v[p] + k * d->points, k == far);
    }
}

static void free_frame(frame *f)
{
    for (int d = 0; d < DRAWS; d++) {
        free(f->d[d].idx), free(f->d[d].idx_m);
        for (int p = 0; p < PIECES; p++) free(f->d[d].v[p]);
    }
}

/* A frame: levels 1, 2, 5, 16 and 40, sizes from a few pixels to past the row path's budget; two draws whose
 * pieces end in a partial group. */
static void make_frame(frame *f, uint64_t seed)
{
    static const int levels[DRAWS] = { 1, 2, 5, 16, 5, 16, 40, 1, 16, 40 };
    static const float rlo[DRAWS] = { 0.02f, 0.02f, 0.05f, 0.1f, 0.3f, 0.2f, 0.3f, 0.1f, 0.5f, 0.9f };
    static const float rhi[DRAWS] = { 0.1f, 0.2f, 0.4f, 0.6f, 1.2f, 0.7f, 0.7f, 0.5f, 1.0f, 1.4f };
    uint64_t s = seed;
    for (int d = 0; d < DRAWS; d++) make_draw(&s, &f->d[d], levels[d], rlo[d], rhi[d]);
    f->d[3].cut = 5, f->d[5].cut = 1;   /* a piece's last group short: the rs_gtri path for it */
}

/* What a frame drew: the planes, the summed counters and the grid groups the row path took (scene off only). */
typedef struct result {
    uint32_t color[W * H];
    float depth[W * H];
    rs_stats sum;
    uint64_t grid_groups;
    uint64_t grid_direct;           /* the row path's triangles rs_tri_run took straight to span.c's small walks */
} result;

/* How a frame is drawn: scene on, reference path, threads, instruction set, grid level told, lists mirrored. */
typedef struct how { bool scene, reference; int threads, isa; bool tell, mirror; } how;

/* The row path's grid groups of the last draw's chunks on rs (rs_draw_source without the scene). */
static uint64_t grid_groups(const rs_context *rs, size_t n_pieces)
{
    uint64_t n = 0;
    for (size_t c = 0; c < n_pieces; c++) n += rs->chunks[c].grid_groups;
    return n;
}

/* The row path's triangles that the tile pass took straight to the small-triangle walks (rs_tri_run), over the
 * last draw's chunks on rs. */
static uint64_t grid_direct(const rs_context *rs, size_t n_pieces)
{
    uint64_t n = 0;
    for (size_t c = 0; c < n_pieces; c++) n += rs->chunks[c].grid_direct;
    return n;
}

/* Draw frame f on a fresh context as h says. */
static void draw_frame(const frame *f, how h, result *out)
{
    rs_context *rs = rs_create(h.threads);
    rs_target rt;
    assert_non_null(rs);
    assert_int_equal(rs_set_isa(rs, h.isa), RS_OK);
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_stats sink = {0}, s;
    memset(&out->sum, 0, sizeof out->sum);
    out->grid_groups = out->grid_direct = 0;
    rs_set_reference_path(rs, h.reference);
    rs_set_scene(rs, h.scene ? &sink : NULL);
    rs_target_clear_deferred(rs, &rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0xff402010u, 1.0f);
    for (int d = 0; d < DRAWS; d++) {
        const draw_def *dd = &f->d[d];
        rs_source src = {.n_pieces = PIECES, .n_prims = PIECES * INST * dd->prims, .max_verts = INST * dd->points,
                         .produce = h.mirror ? produce_mirrored : produce, .ctx = (void *)dd,
                         .group_prims = dd->prims, .grid_level = h.tell ? (size_t)dd->level : 0,
                         .grid_mirrored = h.tell && h.mirror};
        assert_int_equal(rs_draw_source(rs, &dd->st, &rt, &src, &s), RS_OK);
        test_rs_stats_add(&out->sum, &s);
        if (!h.scene) out->grid_groups += grid_groups(rs, PIECES), out->grid_direct += grid_direct(rs, PIECES);
    }
    test_rs_frame_end(rs, &rt, &sink, &out->sum, out->color, out->depth, W * H);
}

/* Compare two results byte for byte (planes and counters). */
static void same(const result *a, const result *b)
{
    test_rs_same_frame(a->color, a->depth, &a->sum, b->color, b->depth, &b->sum, W * H);
}

/* The grid level told, untold and on the reference path give the same bytes and counters, scene on and off, 1 and
 * 2 threads, every instruction set; told, the row path takes most groups, untold none. */
static void test_grid_same_bytes(void **state)
{
    (void)state;
    frame *f = calloc(1, sizeof *f);
    result *ref = malloc(sizeof *ref), *r = malloc(sizeof *r);
    assert_true(f && ref && r);
    for (uint64_t seed = 1; seed <= 3; seed++) {
        make_frame(f, 0x2545f4914f6cdd1dull * seed);
        draw_frame(f, (how){ false, true, 1, RS_ISA_AVX2, false, false }, ref);
        assert_true(ref->sum.samples_written > 0 && ref->sum.prims_culled > 0 && ref->sum.prims_degenerate > 0);
        for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
            if (!rs_isa_supported(isa)) continue;
            for (int threads = 1; threads <= 2; threads++) {
                draw_frame(f, (how){ false, false, threads, isa, true, false }, r);
                same(ref, r);
                assert_true(r->grid_groups >= 20);   /* many instances: the row path */
                assert_true(r->grid_groups < DRAWS * PIECES * INST);        /* the large ones: not */
                /* most of the row path's triangles go straight to the small walks, not all (boxes over 8 wide) */
                assert_true(r->grid_direct >= 1000 && r->grid_direct < r->sum.prims_drawn);
                draw_frame(f, (how){ true, false, threads, isa, true, false }, r);
                same(ref, r);
                draw_frame(f, (how){ false, false, threads, isa, false, false }, r);
                same(ref, r);
                assert_int_equal(r->grid_groups, 0);
                assert_int_equal(r->grid_direct, 0);
            }
        }
        free_frame(f);
    }
    free(f), free(ref), free(r);
}

/* The same with every list mirrored (rs_source.grid_mirrored): the reference path's bytes and counters of the
 * mirrored lists -- under the random cull modes the other triangles are culled -- with the row path taken. */
static void test_grid_mirrored_same_bytes(void **state)
{
    (void)state;
    frame *f = calloc(1, sizeof *f);
    result *ref = malloc(sizeof *ref), *r = malloc(sizeof *r), *plain = malloc(sizeof *plain);
    assert_true(f && ref && r && plain);
    for (uint64_t seed = 4; seed <= 5; seed++) {
        make_frame(f, 0x2545f4914f6cdd1dull * seed);
        draw_frame(f, (how){ false, true, 1, RS_ISA_AVX2, false, true }, ref);
        draw_frame(f, (how){ false, true, 1, RS_ISA_AVX2, false, false }, plain);
        assert_true(ref->sum.samples_written > 0 && ref->sum.prims_culled > 0);
        assert_true(ref->sum.prims_culled != plain->sum.prims_culled);   /* the cull modes see the other winding */
        for (int isa = 0; isa < RS_ISA_COUNT; isa++) {
            if (!rs_isa_supported(isa)) continue;
            for (int threads = 1; threads <= 2; threads++) {
                draw_frame(f, (how){ false, false, threads, isa, true, true }, r);
                same(ref, r);
                assert_true(r->grid_groups >= 20);
                draw_frame(f, (how){ true, false, threads, isa, true, true }, r);
                same(ref, r);
            }
        }
        free_frame(f);
    }
    free(f), free(ref), free(r), free(plain);
}

/* Draw d (one group of level d->level, its points in d->v[0]) into a fresh W x H target on pass `pass` of the
 * one-group tests -- 0 the reference path, 1 the row path on 1 thread, 2 on 2 threads, 3 with AVX-512 -- into *o
 * (planes, counters, grid groups).  fe: fail when pass 1 raises a divide-by-zero, invalid or overflow flag (the
 * tile pass runs on this thread then: its lanes that are not live must not divide by zero or make a NaN --
 * grid_finish_half -- nor any lane overflow). */
static void one_group_pass(draw_def *d, int pass, bool fe, result *o)
{
    const size_t L = d->level;
    rs_context *rs = rs_create(pass == 2 ? 2 : 1);
    assert_non_null(rs);
    assert_int_equal(rs_set_isa(rs, pass == 3 ? RS_ISA_AVX512 : RS_ISA_AVX2), RS_OK);
    rs_set_reference_path(rs, pass == 0);
    rs_target rt;
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_target_clear(&rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0, 1.0f);
    rs_source src = {.n_pieces = 1, .n_prims = L * L, .max_verts = d->points, .produce = produce, .ctx = d,
                     .group_prims = L * L, .grid_level = L};
    feclearexcept(FE_ALL_EXCEPT);
    assert_int_equal(rs_draw_source(rs, &d->st, &rt, &src, &o->sum), RS_OK);
    if (fe && pass == 1) assert_int_equal(fetestexcept(FE_DIVBYZERO | FE_INVALID | FE_OVERFLOW), 0);
    o->grid_groups = grid_groups(rs, 1);
    memcpy(o->color, rt.color, sizeof o->color);
    memcpy(o->depth, rt.depth, sizeof o->depth);
    rs_target_free(&rt);
    rs_destroy(rs);
}

/* One level-40 instance of ~70 x 70 pixels over the four tiles around (T, T) (T = RS_TILE_SIZE) -- 1,600
 * triangles, many on the tile borders -- then the same at 120 pixels from (40, 40) (with 64-pixel tiles over nine
 * tiles: the per-triangle path; with 128-pixel ones over four: the row path) and at 150 pixels (past the row path's
 * budget of 128 pixels: per triangle): the reference path's bytes and counters on each, the row path taken where
 * said.  Cull CCW with every tenth column folded: rows partly culled. */
static void test_grid_over_tiles(void **state)
{
    (void)state;
    enum { L = 40, P = (L + 1) * (L + 2) / 2 };
    static const struct { float x0, y0, size; uint64_t grid; } cases[] = {
        { RS_TILE_SIZE - 34.0f, RS_TILE_SIZE - 36.0f, 70.0f, 1 }, { 40.0f, 40.0f, 120.0f, RS_TILE_SIZE >= 128 },
        { 10.0f, 20.0f, 150.0f, 0 } };
    _Static_assert(RS_TILE_SIZE + 36 < W && RS_TILE_SIZE + 36 < H, "the first instance inside the target");
    rs_vertex *v = malloc(P * sizeof *v);
    uint32_t *idx = malloc(3 * L * L * sizeof *idx);
    float3 *bary = malloc(P * sizeof *bary);
    result *ref = malloc(sizeof *ref), *r = malloc(sizeof *r);
    assert_true(v && idx && bary && ref && r);
    assert_int_equal(core_grid_regular(L, bary, idx), P);
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        uint64_t s = 777 + c;
        for (int k = 0; k <= L; k++)
            for (int i = 0; i + k <= L; i++) {
                rs_vertex *o = &v[core_grid_index(L, i, k)];
                memset(o, 0, sizeof *o);
                float a = (float)i / L - (i % 10 == 5 ? 1.5f / L : 0.0f), b = (float)k / L;
                float px = cases[c].x0 + cases[c].size * (a + 0.5f * b), py = cases[c].y0 + cases[c].size * b;
                o->pos =
                    (rs_vec4){px / (W / 2.0f) - 1.0f + test_frnd(&s, -0.002f, 0.002f),
                              1.0f - py / (H / 2.0f) + test_frnd(&s, -0.002f, 0.002f), test_frnd(&s, 0.1f, 0.9f), 1.0f};
                o->attr[RS_ATTR_COLOR0] =
                    (rs_vec4){test_frnd(&s, 0, 1), test_frnd(&s, 0, 1), test_frnd(&s, 0, 1), 1.0f};
            }
        draw_def d = { .level = L, .inst = 1, .points = P, .prims = L * L, .v = { v }, .idx = idx };
        d.st = (rs_state){.cull_mode = RS_CULL_CCW, .fill_mode = RS_FILL_SOLID, .shade_mode = RS_SHADE_GOURAUD,
                          .z_enable = true, .z_write = true, .z_func = RS_CMP_LESSEQUAL, .src_blend = RS_BLEND_ONE,
                          .dst_blend = RS_BLEND_ZERO, .attr_mask = 1u << RS_ATTR_COLOR0,
                          .viewport = {0, 0, W, H, 0.0f, 1.0f}};
        for (int pass = 0; pass < 4; pass++) {   /* reference; the row path on 1 thread, 2 threads, AVX-512 */
            if (pass == 3 && !rs_isa_supported(RS_ISA_AVX512)) continue;
            result *o = pass == 0 ? ref : r;
            one_group_pass(&d, pass, false, o);
            if (pass == 0) {
                assert_true(ref->sum.samples_written > 1000 && ref->sum.prims_culled > 0);
                continue;
            }
            same(ref, r);
            assert_int_equal(r->grid_groups, cases[c].grid);
        }
    }
    free(v), free(idx), free(bary), free(ref), free(r);
}

/* A level-16 instance placed in pixels by case c: 0 inside the tile (64..127)^2; 1 over the four tiles around
 * (64, 64); 2 and 3 with rows that wave across x = 64 three times (leave the tile and come back; the waves' back
 * slopes turn their triangles round) and cross y = 128. */
static void place_instance(int c, int L, uint64_t *s, rs_vertex *v)
{
    for (int k = 0; k <= L; k++)
        for (int i = 0; i + k <= L; i++) {
            rs_vertex *o = &v[core_grid_index(L, i, k)];
            memset(o, 0, sizeof *o);
            const float a = (float)i / L, b = (float)k / L;
            float px, py;
            if (c == 0) px = 70.0f + 40.0f * (a + 0.5f * b), py = 70.0f + 40.0f * b;
            else if (c == 1) px = 40.0f + 50.0f * (a + 0.5f * b), py = 44.0f + 50.0f * b;
            else px = 64.0f + 12.0f * sinf(6.0f * 3.14159265f * a) + 20.0f * b, py = 100.0f + 50.0f * b + 8.0f * a;
            o->pos = (rs_vec4){px / (W / 2.0f) - 1.0f + test_frnd(s, -0.002f, 0.002f),
                               1.0f - py / (H / 2.0f) + test_frnd(s, -0.002f, 0.002f), test_frnd(s, 0.1f, 0.9f), 1.0f};
            o->attr[RS_ATTR_COLOR0] = (rs_vec4){ test_frnd(s, 0, 1), test_frnd(s, 0, 1), test_frnd(s, 0, 1), 1.0f };
        }
}

/* The row and step boxes (the tile pass skips a row or a step of eight triangles whose box misses the tile): a
 * level-16 instance inside one tile, one over four tiles, and two whose rows leave a tile and come back (cull none,
 * then CCW: steps of only culled triangles); the reference path's bytes and counters with the row path taken, on
 * 1 and 2 threads and AVX-512. */
static void test_grid_step_boxes(void **state)
{
    (void)state;
    enum { L = 16, P = (L + 1) * (L + 2) / 2 };
    rs_vertex *v = malloc(P * sizeof *v);
    uint32_t *idx = malloc(3 * L * L * sizeof *idx);
    float3 *bary = malloc(P * sizeof *bary);
    result *ref = malloc(sizeof *ref), *r = malloc(sizeof *r);
    assert_true(v && idx && bary && ref && r);
    assert_int_equal(core_grid_regular(L, bary, idx), P);
    for (int c = 0; c < 4; c++) {
        uint64_t s = 4242 + (uint64_t)c;
        place_instance(c, L, &s, v);
        draw_def d = { .level = L, .inst = 1, .points = P, .prims = L * L, .v = { v }, .idx = idx };
        d.st = (rs_state){.cull_mode = c == 3 ? RS_CULL_CCW : RS_CULL_NONE, .fill_mode = RS_FILL_SOLID,
                          .shade_mode = RS_SHADE_GOURAUD, .z_enable = true, .z_write = true,
                          .z_func = RS_CMP_LESSEQUAL, .src_blend = RS_BLEND_ONE, .dst_blend = RS_BLEND_ZERO,
                          .attr_mask = 1u << RS_ATTR_COLOR0, .viewport = {0, 0, W, H, 0.0f, 1.0f}};
        for (int pass = 0; pass < 4; pass++) {   /* reference; the row path on 1 thread, 2 threads, AVX-512 */
            if (pass == 3 && !rs_isa_supported(RS_ISA_AVX512)) continue;
            result *o = pass == 0 ? ref : r;
            one_group_pass(&d, pass, true, o);
            if (pass == 0) {
                assert_true(ref->sum.samples_written > 500);
                if (c == 3) assert_true(ref->sum.prims_culled > 0);
                continue;
            }
            same(ref, r);
            assert_int_equal(r->grid_groups, 1);
        }
    }
    free(v), free(idx), free(bary), free(ref), free(r);
}

/* A grid level the source cannot hold is RS_EINVAL (group_prims not its square, past RS_GRID_MAX_LEVEL);
 * core_grid_regular_level_mirrored tells the mirrored list (and only it, with its point count, every triangle
 * mirrored); and core_grid_regular_level tells the regular list from lists that are not it: one triangle's vertices rotated (the
 * same triangle), two triangles swapped, an adaptive pattern of unequal levels, a primitive-generator grid --
 * while the adaptive pattern of equal levels is the regular grid. */
static void test_grid_level_checks(void **state)
{
    (void)state;
    enum { L = 5, P = (L + 1) * (L + 2) / 2 };
    rs_vertex v[P];
    memset(v, 0, sizeof v);
    uint32_t idx[3 * L * L], t0;
    float3 bary[P];
    assert_int_equal(core_grid_regular(L, bary, idx), P);
    assert_int_equal(core_grid_regular_level(idx, L * L, P), L);
    assert_int_equal(core_grid_regular_level_mirrored(idx, L * L, P), 0);
    uint32_t mir[3 * L * L];
    for (int k = 0; k < L * L; k++) mir[3 * k] = idx[3 * k], mir[3 * k + 1] = idx[3 * k + 2], mir[3 * k + 2] = idx[3 * k + 1];
    assert_int_equal(core_grid_regular_level_mirrored(mir, L * L, P), L);
    assert_int_equal(core_grid_regular_level(mir, L * L, P), 0);
    assert_int_equal(core_grid_regular_level_mirrored(mir, L * L, P + 1), 0);   /* not its point count */
    t0 = mir[3 * (L * L - 1) + 1], mir[3 * (L * L - 1) + 1] = mir[3 * (L * L - 1) + 2], mir[3 * (L * L - 1) + 2] = t0;
    assert_int_equal(core_grid_regular_level_mirrored(mir, L * L, P), 0);      /* its last triangle unmirrored */
    draw_def d = { .level = L, .inst = 1, .points = P, .prims = L * L, .v = { v }, .idx = idx };
    d.st = (rs_state){.cull_mode = RS_CULL_NONE, .fill_mode = RS_FILL_SOLID, .shade_mode = RS_SHADE_GOURAUD,
                      .z_enable = true, .z_write = true, .z_func = RS_CMP_LESSEQUAL, .src_blend = RS_BLEND_ONE,
                      .dst_blend = RS_BLEND_ZERO, .attr_mask = 1u << RS_ATTR_COLOR0, .viewport = {0, 0, W, H, 0, 1}};
    rs_context *rs = rs_create(1);
    rs_target rt;
    assert_non_null(rs);
    assert_int_equal(rs_target_init(&rt, W, H, 1), RS_OK);
    rs_source src = {.n_pieces = 1, .n_prims = L * L, .max_verts = P, .produce = produce, .ctx = &d,
                     .group_prims = L * L + 1, .grid_level = L};
    assert_int_equal(rs_draw_source(rs, &d.st, &rt, &src, NULL), RS_EINVAL);
    src.grid_level = RS_GRID_MAX_LEVEL + 1, src.group_prims = src.grid_level * src.grid_level;
    assert_int_equal(rs_draw_source(rs, &d.st, &rt, &src, NULL), RS_EINVAL);
    src.grid_level = SIZE_MAX, src.group_prims = 1;
    assert_int_equal(rs_draw_source(rs, &d.st, &rt, &src, NULL), RS_EINVAL);
    src.grid_level = L, src.group_prims = L * L;
    assert_int_equal(rs_draw_source(rs, &d.st, &rt, &src, NULL), RS_OK);
    rs_target_free(&rt);
    rs_destroy(rs);
    /* lists that are not the regular grid */
    uint32_t t = idx[3];   /* triangle 1's vertices rotated */
    idx[3] = idx[4], idx[4] = idx[5], idx[5] = t;
    assert_int_equal(core_grid_regular_level(idx, L * L, P), 0);
    assert_int_equal(core_grid_regular(L, bary, idx), P);
    for (int c = 0; c < 3; c++) t = idx[3 * 7 + c], idx[3 * 7 + c] = idx[3 * 8 + c], idx[3 * 8 + c] = t;
    assert_int_equal(core_grid_regular_level(idx, L * L, P), 0);
    core_grid g;
    assert_int_equal(core_grid_adaptive((const int[3]){ 3, 4, 5 }, &g), 0);
    assert_int_equal(core_grid_regular_level(g.idx, g.n_triangles, g.n_points), 0);
    core_grid_free(&g);
    assert_int_equal(core_grid_adaptive((const int[3]){ 4, 4, 4 }, &g), 0);
    assert_int_equal(core_grid_regular_level(g.idx, g.n_triangles, g.n_points), 4);
    core_grid_free(&g);
    assert_int_equal(core_grid_pg(CORE_GRID_PG_EQUAL, 4.0f, (const float[3]){ 4.0f, 4.0f, 4.0f }, &g), 0);
    assert_int_equal(core_grid_regular_level(g.idx, g.n_triangles, g.n_points), 0);
    core_grid_free(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_same_bytes),
        cmocka_unit_test(test_grid_mirrored_same_bytes),
        cmocka_unit_test(test_grid_over_tiles),
        cmocka_unit_test(test_grid_step_boxes),
        cmocka_unit_test(test_grid_level_checks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
