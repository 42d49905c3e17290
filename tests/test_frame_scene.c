/* tests/test_frame_scene.c -- the device's recorded draws (core/draw_fused.c, raster.h rs_set_scene): a frame's
 * instanced draws are recorded (shader, constants, fetch plan, indices copied; vertex buffers marked) and run at
 * the next flush in one set-up region and one tile pass.  A frame of many draws with varied states, constants,
 * instance buffers and counts -- a vertex buffer locked and changed between draws, the constants changed between
 * draws, line draws (not recorded) in between, a buffer released while a draw that reads it is recorded, a vertex
 * texture locked and rewritten between draws that sample it -- must
 * give the bytes of the reference path (each draw drawn at once) and the same bytes and counters on 1 and 2
 * threads; a frame without interruptions runs one set-up region and one tile pass; an error found at the flush
 * (the work bound) drops that draw and is reported by dev_flush.  Deterministic: fixed seeds. */
#include <omp.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/core.h"
#include "../core/hlsl.h"
#include "../core/texture.h"

enum { W = 160, H = 120, N = 5 /* grid points per side */, DRAWS = 60, MAX_INST = 40 };

/* xorshift64 random numbers. */
static uint32_t rnd(uint64_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return (uint32_t)(*s >> 11);
}
static float frnd(uint64_t *s, float lo, float hi) { return lo + (hi - lo) * (float)(rnd(s) & 0xffffff) / 16777216.0f; }

/* The grid point (u, v) = position.xy placed by the instance (texcoord0: x, y, size, depth) through c0 (x scale,
 * x offset, y scale, y offset) and c1 (depth scale, perspective); colour = instance colour * c2 + (u, v) * c3. */
static void vs_grid(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    const float4 p = in->position[0], t = in->texcoord[0], k = in->color[0];
    const float x = (t.x + p.x * t.z) * c->c[0].x + c->c[0].y, y = (t.y + p.y * t.z) * c->c[0].z + c->c[0].w;
    const float w = 1.0f + p.x * c->c[1].y;
    out->pos = f4(x * w, y * w, t.w * c->c[1].x * w, w);
    out->attr[RS_ATTR_COLOR0] = f4(k.x * c->c[2].x + p.x * c->c[3].x, k.y * c->c[2].y + p.y * c->c[3].y,
                                   k.z * c->c[2].z, k.w * c->c[2].w);
}
static const is_vertex_shader vs = {.name = "grid", .main = vs_grid, .outputs = IS_OUT_COLOR0};

/* vs_grid with the blue channel from vertex texture s0 at (u, v) (vertex texture fetch). */
static void vs_grid_tex(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    vs_grid(c, in, out);
    out->attr[RS_ATTR_COLOR0].z = tex2Dlod(&c->s[0], f4(in->position[0].x, in->position[0].y, 0, 0)).x;
}
static const is_vertex_shader vs_tex = {.name = "grid_tex", .main = vs_grid_tex, .outputs = IS_OUT_COLOR0};

/* What a frame drew: colour, depth, counters. */
typedef struct result {
    uint32_t color[W * H];
    float depth[W * H];
    rs_stats stats;
    uint64_t shaded;
} result;

/* The device's buffers: the grid (stream 0) and its indices, two instance buffers (texcoord0 and colour, 32 bytes
 * per instance), a line's two vertices. */
typedef struct scene {
    is_device *dev;
    is_vertex_buffer *grid, *inst[2], *line;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
} scene;

/* Fill instance buffer vb with random instances (seeded). */
static void fill_instances(is_vertex_buffer *vb, uint64_t seed)
{
    float (*q)[8] = vb_lock(vb);
    uint64_t s = seed;
    for (int i = 0; i < MAX_INST; i++) {
        float size = frnd(&s, 0.05f, 0.5f);
        float t[8] = {frnd(&s, -1.2f, 1.0f), frnd(&s, -1.2f, 1.0f), size, frnd(&s, 0.0f, 1.0f),
                      frnd(&s, 0, 1), frnd(&s, 0, 1), frnd(&s, 0, 1), frnd(&s, 0.2f, 1)};
        memcpy(q[i], t, sizeof t);
    }
    vb_unlock(vb);
}

/* A device with the buffers made and bound (threads, reference path as asked). */
static scene make_scene(int threads, bool reference)
{
    scene sc;
    sc.dev = dev_create(W, H, 1, NULL, 0);
    assert_non_null(sc.dev);
    dev_set_threads(sc.dev, threads);
    dev_set_reference_path(sc.dev, reference);
    assert_int_equal(dev_create_vertex_buffer(sc.dev, N * N * 8, &sc.grid), IS_OK);
    float (*g)[2] = vb_lock(sc.grid);
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) g[j * N + i][0] = (float)i / (N - 1), g[j * N + i][1] = (float)j / (N - 1);
    assert_int_equal(dev_create_index_buffer(sc.dev, 6 * (N - 1) * (N - 1) * 2, IS_FMT_INDEX16, &sc.ib), IS_OK);
    uint16_t *ix = ib_lock(sc.ib);
    for (int j = 0, k = 0; j + 1 < N; j++)
        for (int i = 0; i + 1 < N; i++) {
            const uint16_t a = (uint16_t)(j * N + i), b = (uint16_t)(a + 1), c = (uint16_t)(a + N);
            const uint16_t d = (uint16_t)(c + 1);
            const uint16_t t[6] = {a, b, c, b, d, c};
            memcpy(ix + k, t, sizeof t), k += 6;
        }
    for (int k = 0; k < 2; k++) {
        assert_int_equal(dev_create_vertex_buffer(sc.dev, MAX_INST * 32, &sc.inst[k]), IS_OK);
        fill_instances(sc.inst[k], 1234 + (uint64_t)k);
    }
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0},
                                    {1, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, 0},
                                    {1, 16, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_COLOR, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(sc.dev, el, &sc.decl), IS_OK);
    dev_set_vertex_declaration(sc.dev, sc.decl);
    dev_set_vertex_shader(sc.dev, &vs);
    dev_set_stream_source(sc.dev, 0, sc.grid, 0, 8);
    dev_set_stream_source_freq(sc.dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1u);
    dev_set_indices(sc.dev, sc.ib);
    assert_int_equal(dev_create_vertex_buffer(sc.dev, 2 * 8, &sc.line), IS_OK);
    return sc;
}

/* Release the scene's buffers and its device. */
static void scene_free(scene *sc)
{
    decl_release(sc->decl);
    vb_release(sc->grid), vb_release(sc->inst[0]), vb_release(sc->inst[1]), vb_release(sc->line);
    ib_release(sc->ib);
    dev_destroy(sc->dev);
}

/* Random states and constants for draw d (cull, depth function and writes, blending, scissor, viewport). */
static void random_states(is_device *dev, uint64_t *s)
{
    dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE + rnd(s) % 3);
    dev_set_render_state(dev, IS_RS_ZFUNC, rnd(s) % 2 ? IS_CMP_LESSEQUAL : IS_CMP_GREATER);
    dev_set_render_state(dev, IS_RS_ZWRITEENABLE, rnd(s) % 4 != 0);
    const bool blend = rnd(s) % 4 == 0;
    dev_set_render_state(dev, IS_RS_ALPHABLENDENABLE, blend);
    dev_set_render_state(dev, IS_RS_SRCBLEND, blend ? IS_BLEND_SRCALPHA : IS_BLEND_ONE);
    dev_set_render_state(dev, IS_RS_DESTBLEND, blend ? IS_BLEND_INVSRCALPHA : IS_BLEND_ZERO);
    const bool scissor = rnd(s) % 5 == 0;
    dev_set_render_state(dev, IS_RS_SCISSORTESTENABLE, scissor);
    int x0 = (int)(rnd(s) % 100), y0 = (int)(rnd(s) % 70);
    is_rect r = {x0, y0, x0 + 60, y0 + 50};
    dev_set_scissor_rect(dev, &r);
    is_viewport vp = {0, 0, W, H, 0.0f, 1.0f};
    if (rnd(s) % 4 == 0) vp = (is_viewport){rnd(s) % 40, rnd(s) % 30, 100, 80, 0.0f, 1.0f};
    dev_set_viewport(dev, &vp);
    const float c[16] = {frnd(s, 0.6f, 1.2f), frnd(s, -0.2f, 0.2f), frnd(s, 0.6f, 1.2f), frnd(s, -0.2f, 0.2f),
                         frnd(s, 0.5f, 1.0f), frnd(s, 0.0f, 0.5f), 0, 0,
                         frnd(s, 0.3f, 1.0f), frnd(s, 0.3f, 1.0f), frnd(s, 0.3f, 1.0f), 1.0f,
                         frnd(s, 0.0f, 0.5f), frnd(s, 0.0f, 0.5f), 0, 0};
    dev_set_vertex_shader_constant_f(dev, 0, c, 4);   /* changed between the draws of the frame */
}

/* A line across the target (DrawPrimitive LINELIST: not recorded, so the recorded draws run first). */
static void draw_line(scene *sc, uint64_t *s)
{
    float (*p)[2] = vb_lock(sc->line);
    p[0][0] = frnd(s, 0, 1), p[0][1] = frnd(s, 0, 1), p[1][0] = frnd(s, 0, 1), p[1][1] = frnd(s, 0, 1);
    vb_unlock(sc->line);
    dev_set_stream_source(sc->dev, 0, sc->line, 0, 8);
    dev_set_stream_source_freq(sc->dev, 0, 1);
    assert_int_equal(dev_draw_primitive(sc->dev, IS_PT_LINELIST, 0, 1), IS_OK);
    dev_set_stream_source(sc->dev, 0, sc->grid, 0, 8);
}

/* Draw the frame of `seed` on sc: DRAWS instanced draws, each with its own states, constants, instance buffer,
 * offset and count; every 9th draw an instance buffer is locked and changed, every 13th a line is drawn, and
 * draw 30 releases instance buffer 1 (a new one, of other data, takes its place). */
static void draw_frame(scene *sc, uint64_t seed)
{
    uint64_t s = seed;
    is_device *dev = sc->dev;
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0xff203040u, 1.0f), IS_OK);
    for (int d = 0; d < DRAWS; d++) {
        random_states(dev, &s);
        const int k = (int)(rnd(&s) % 2);
        const unsigned first = rnd(&s) % 20, count = 1 + rnd(&s) % (MAX_INST - first);
        dev_set_stream_source(dev, 1, sc->inst[k], first * 32, 32);
        dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | count);
        assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, N * N, 0, 2 * (N - 1) * (N - 1)),
                         IS_OK);
        if (d % 9 == 4) fill_instances(sc->inst[rnd(&s) % 2], s);   /* Lock + change: the draws before read the old */
        if (d % 13 == 12) draw_line(sc, &s);
        if (d == 30) {
            vb_release(sc->inst[1]);
            assert_int_equal(dev_create_vertex_buffer(dev, MAX_INST * 32, &sc->inst[1]), IS_OK);
            fill_instances(sc->inst[1], 999);
        }
    }
}

/* Render frames seed and seed + 1 with the given threads and path into *out (the second frame's). */
static void render(uint64_t seed, int threads, bool reference, result *out)
{
    scene sc = make_scene(threads, reference);
    draw_frame(&sc, seed);
    draw_frame(&sc, seed + 1);   /* a second frame on the same device: the records reused */
    assert_int_equal(dev_flush(sc.dev), IS_OK);
    out->shaded = dev_vertices_shaded(sc.dev);
    out->stats = *dev_stats(sc.dev);
    assert_int_equal(dev_get_render_target_data(sc.dev, out->color, W * H), IS_OK);
    memcpy(out->depth, dev_render_target(sc.dev)->depth, sizeof out->depth);
    scene_free(&sc);
}

/* The recorded frame against the reference path (images) and 1 against 2 threads (images and counters). */
static void test_frame_same_bytes(void **state)
{
    (void)state;
    result *ref = malloc(sizeof *ref), *one = malloc(sizeof *one), *two = malloc(sizeof *two);
    assert_true(ref && one && two);
    for (uint64_t seed = 1; seed <= 3; seed++) {
        render(seed * 0x9e3779b97f4a7c15ull, 1, true, ref);
        render(seed * 0x9e3779b97f4a7c15ull, 1, false, one);
        render(seed * 0x9e3779b97f4a7c15ull, 2, false, two);
        assert_true(ref->stats.samples_written > 1000);
        assert_memory_equal(ref->color, one->color, sizeof ref->color);
        assert_memory_equal(ref->depth, one->depth, sizeof ref->depth);
        assert_int_equal(ref->stats.prims_drawn, one->stats.prims_drawn);
        assert_int_equal(ref->stats.samples_written, one->stats.samples_written);
        assert_int_equal(ref->shaded, one->shaded);
        assert_memory_equal(one->color, two->color, sizeof one->color);
        assert_memory_equal(one->depth, two->depth, sizeof one->depth);
        assert_memory_equal(&one->stats, &two->stats, sizeof one->stats);
    }
    free(ref), free(one), free(two);
}

/* Thread counts other than 1 and 2 give the 1-thread frame's bytes and counters: the tile pass's ranges (raster/
 * draw.c, one per thread, taken from the back once a thread's own is done) split the frame's 6 tiles unevenly for 4
 * threads, 7 and 9 threads have more threads than tiles (the extra ones only take from the others' backs), and a
 * team of one thread for a plan of 4 ranges takes them all. */
static void test_thread_counts(void **state)
{
    (void)state;
    result *one = malloc(sizeof *one), *many = malloc(sizeof *many);
    assert_true(one && many);
    const uint64_t seed = 5 * 0x9e3779b97f4a7c15ull;
    render(seed, 1, false, one);
    assert_true(one->stats.samples_written > 1000);
    const int counts[] = {3, 4, 7, 9};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
        render(seed, counts[k], false, many);
        assert_memory_equal(one->color, many->color, sizeof one->color);
        assert_memory_equal(one->depth, many->depth, sizeof one->depth);
        assert_memory_equal(&one->stats, &many->stats, sizeof one->stats);
    }
    /* a team smaller than the plan: the frame drawn inside a parallel region with nested regions off, where the
     * draw's own region has one thread, which then takes all 4 ranges */
    omp_set_max_active_levels(1);
#pragma omp parallel num_threads(2)
#pragma omp single
    render(seed, 4, false, many);
    assert_memory_equal(one->color, many->color, sizeof one->color);
    assert_memory_equal(one->depth, many->depth, sizeof one->depth);
    assert_memory_equal(&one->stats, &many->stats, sizeof one->stats);
    free(one), free(many);
}

/* A frame of recorded draws without interruptions runs one set-up region and one tile pass (counted with timing
 * on), on 1 and 2 threads; the draws are recorded until the read. */
static void test_one_region_per_frame(void **state)
{
    (void)state;
    for (int threads = 1; threads <= 2; threads++) {
        scene sc = make_scene(threads, false);
        dev_set_timing(sc.dev, true);
        uint64_t s = 5;
        assert_int_equal(dev_clear(sc.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
        for (int d = 0; d < 40; d++) {
            random_states(sc.dev, &s);
            dev_set_stream_source(sc.dev, 1, sc.inst[d % 2], 0, 32);
            dev_set_stream_source_freq(sc.dev, 0, IS_STREAMSOURCE_INDEXEDDATA | (unsigned)(1 + d % MAX_INST));
            assert_int_equal(dev_draw_indexed_primitive(sc.dev, IS_PT_TRIANGLELIST, 0, 0, N * N, 0,
                                                        2 * (N - 1) * (N - 1)), IS_OK);
        }
        const rs_stats *st = dev_stats(sc.dev);
        print_message("  %d thread(s): %llu set-up region(s), %llu tile pass(es) for 40 draws\n", threads,
                      (unsigned long long)st->setup_regions, (unsigned long long)st->tile_regions);
        assert_int_equal(st->setup_regions, 1u);
        assert_int_equal(st->tile_regions, 1u);
        assert_true(st->samples_written > 0);
        scene_free(&sc);
    }
}

/* Texture t's 4x4 texels rewritten (locked), their red byte from seed k. */
static void fill_texture(is_texture *t, unsigned k)
{
    is_locked_rect lr;
    assert_int_equal(tex_lock_rect(t, 0, &lr, NULL, 0), IS_OK);
    for (unsigned j = 0; j < 4; j++)
        for (unsigned i = 0; i < 4; i++)
            ((uint32_t *)((char *)lr.bits + j * (unsigned)lr.pitch))[i] =
                IS_COLOR_ARGB(255, (37 * k + 61 * i + 17 * j) & 255, 0, 0);
    assert_int_equal(tex_unlock_rect(t, 0), IS_OK);
}

/* A frame of 12 draws that sample a vertex texture, the texture locked and rewritten after each draw, into color. */
static void render_texture_frame(int threads, bool reference, uint32_t *color)
{
    scene sc = make_scene(threads, reference);
    is_texture *t;
    assert_int_equal(dev_create_texture(sc.dev, 4, 4, 1, 0, IS_FMT_A8R8G8B8, &t), IS_OK);
    fill_texture(t, 0);
    assert_int_equal(dev_set_texture(sc.dev, IS_VERTEXTEXTURESAMPLER(0), t), IS_OK);
    dev_set_vertex_shader(sc.dev, &vs_tex);
    uint64_t s = 11;
    assert_int_equal(dev_clear(sc.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
    for (unsigned d = 0; d < 12; d++) {
        random_states(sc.dev, &s);
        dev_set_stream_source(sc.dev, 1, sc.inst[d % 2], 0, 32);
        dev_set_stream_source_freq(sc.dev, 0, IS_STREAMSOURCE_INDEXEDDATA | (1 + 3 * d));
        assert_int_equal(dev_draw_indexed_primitive(sc.dev, IS_PT_TRIANGLELIST, 0, 0, N * N, 0, 2 * (N - 1) * (N - 1)),
                         IS_OK);
        fill_texture(t, d + 1);   /* the draws recorded so far sampled the old texels */
    }
    assert_int_equal(dev_get_render_target_data(sc.dev, color, W * H), IS_OK);
    tex_release(t);
    scene_free(&sc);
}

/* A texture locked between recorded draws: the reference path's bytes, 1 and 2 threads. */
static void test_texture_lock_between_draws(void **state)
{
    (void)state;
    uint32_t *ref = malloc(W * H * sizeof *ref), *fast = malloc(W * H * sizeof *fast);
    assert_true(ref && fast);
    render_texture_frame(1, true, ref);
    for (int threads = 1; threads <= 2; threads++) {
        render_texture_frame(threads, false, fast);
        assert_memory_equal(ref, fast, W * H * sizeof *ref);
    }
    free(ref), free(fast);
}

/* A recorded draw that passes the frame's work bound at the flush: dropped whole, the draw call itself OK, the
 * error from dev_flush (once) with dev_last_error naming the bound; the draws before it are drawn. */
static void test_error_at_flush(void **state)
{
    (void)state;
    scene sc = make_scene(2, false);
    float (*q)[8] = vb_lock(sc.inst[0]);
    for (int i = 0; i < MAX_INST; i++) {   /* instances covering the whole target */
        const float t[8] = {-1.5f, -1.5f, 3.0f, 0.5f, 1, 1, 1, 1};
        memcpy(q[i], t, sizeof t);
    }
    const float c[16] = {1, 0, 1, 0, 1, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0};
    dev_set_vertex_shader_constant_f(sc.dev, 0, c, 4);
    dev_set_render_state(sc.dev, IS_RS_CULLMODE, IS_CULL_NONE);
    dev_set_render_state(sc.dev, IS_RS_ZFUNC, IS_CMP_ALWAYS);
    assert_int_equal(dev_clear(sc.dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f), IS_OK);
    dev_set_stream_source(sc.dev, 1, sc.inst[0], 0, 32);
    dev_set_stream_source_freq(sc.dev, 0, IS_STREAMSOURCE_INDEXEDDATA | 1u);
    assert_int_equal(dev_draw_indexed_primitive(sc.dev, IS_PT_TRIANGLELIST, 0, 0, N * N, 0, 2 * (N - 1) * (N - 1)),
                     IS_OK);
    /* 20000 instances of the whole target: about 20000 x 19200 pixels, more than RS_MAX_OVERDRAW (1024) times
     * the target (the instances past the buffer read zeros: size 0, nothing; 40 of them cover it) */
    dev_set_stream_source(sc.dev, 1, sc.inst[0], 0, 0);   /* stride 0: every instance reads the first */
    dev_set_stream_source_freq(sc.dev, 0, IS_STREAMSOURCE_INDEXEDDATA | 20000u);
    assert_int_equal(dev_draw_indexed_primitive(sc.dev, IS_PT_TRIANGLELIST, 0, 0, N * N, 0, 2 * (N - 1) * (N - 1)),
                     IS_OK);
    assert_int_equal(dev_flush(sc.dev), IS_ERR_OUTOFMEMORY);
    assert_non_null(strstr(dev_last_error(sc.dev), "times on average"));
    assert_int_equal(dev_flush(sc.dev), IS_OK);   /* reported once */
    assert_int_equal(dev_stats(sc.dev)->prims_drawn, 2u * (N - 1) * (N - 1));   /* the first draw only */
    scene_free(&sc);
}

/* vs_grid with the colour made of every component of three per-vertex elements (FLOAT1 texcoord1, FLOAT3
 * texcoord2, FLOAT4 texcoord3), each with its own weight: a component read wrong, or a default other than D3D9's
 * (0, 0, 1), changes it. */
static void vs_floats(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    vs_grid(c, in, out);
    const float4 a = in->texcoord[1], b = in->texcoord[2], d = in->texcoord[3];
    out->attr[RS_ATTR_COLOR0] = f4(0.1f * a.x + 0.2f * a.y + 0.3f * a.z + 0.4f * a.w,
                                   0.1f * b.x + 0.2f * b.y + 0.3f * b.z + 0.4f * b.w,
                                   0.1f * d.x + 0.2f * d.y + 0.3f * d.z + 0.4f * d.w, 1.0f);
}
static const is_vertex_shader vs_fl = {.name = "floats", .main = vs_floats, .outputs = IS_OUT_COLOR0};

/* Two instanced draws (25 instances) of a grid whose vertices hold FLOAT2, FLOAT1, FLOAT3 and FLOAT4 elements (40
 * bytes): the whole grid inside its buffer, then stream 0 moved by 8 bytes so that the last vertex's FLOAT4 lies
 * past the buffer's end (it reads zeros); with per_instance the FLOAT1, FLOAT3 and FLOAT4 elements are read per
 * instance instead (stream 2, INSTANCEDATA | 1, the same buffer: the last instance's FLOAT4 past the end); with
 * drop the second draw's declaration has no FLOAT4 element (its register must read D3D9's default, not what the
 * first draw left in the slot's registers); the image into color. */
static void render_floats(int threads, bool reference, bool per_instance, bool drop, uint32_t *color)
{
    scene sc = make_scene(threads, reference);
    is_device *dev = sc.dev;
    is_vertex_buffer *vb;
    assert_int_equal(dev_create_vertex_buffer(dev, N * N * 40, &vb), IS_OK);
    float (*v)[10] = vb_lock(vb);
    uint64_t s = 77;
    for (int k = 0; k < N * N; k++) {
        v[k][0] = (float)(k % N) / (N - 1), v[k][1] = (float)(k / N) / (N - 1);
        for (int q = 2; q < 10; q++) v[k][q] = frnd(&s, 0, 1);
    }
    vb_unlock(vb);
    const uint16_t st = per_instance ? 2 : 0;
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_POSITION, 0},
                                    {st, 8, IS_DECLTYPE_FLOAT1, 0, IS_DECLUSAGE_TEXCOORD, 1},
                                    {st, 12, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_TEXCOORD, 2},
                                    {st, 24, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, 3},
                                    {1, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_TEXCOORD, 0},
                                    {1, 16, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_COLOR, 0}, IS_DECL_END};
    is_vertex_element el3[7];   /* el without its FLOAT4 element */
    memcpy(el3, el, 3 * sizeof *el), memcpy(el3 + 3, el + 4, 3 * sizeof *el);
    is_vertex_declaration *decl, *decl3;
    assert_int_equal(dev_create_vertex_declaration(dev, el, &decl), IS_OK);
    assert_int_equal(dev_create_vertex_declaration(dev, el3, &decl3), IS_OK);
    dev_set_vertex_shader(dev, &vs_fl);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0xff203040u, 1.0f), IS_OK);
    for (int d = 0; d < 2; d++) {
        dev_set_vertex_declaration(dev, drop && d == 1 ? decl3 : decl);
        random_states(dev, &s);
        dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE);
        dev_set_render_state(dev, IS_RS_ALPHABLENDENABLE, 0);
        if (per_instance) {
            dev_set_stream_source(dev, 0, sc.grid, 0, 8);
            dev_set_stream_source(dev, 2, vb, 8u * (unsigned)d, 40);
            dev_set_stream_source_freq(dev, 2, IS_STREAMSOURCE_INSTANCEDATA | 1u);
        } else
            dev_set_stream_source(dev, 0, vb, 8u * (unsigned)d, 40);
        dev_set_stream_source(dev, 1, sc.inst[d], 0, 32);
        dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | 25u);
        assert_int_equal(dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, N * N, 0, 2 * (N - 1) * (N - 1)),
                         IS_OK);
    }
    assert_int_equal(dev_get_render_target_data(dev, color, W * H), IS_OK);
    decl_release(decl), decl_release(decl3), decl_release(sc.decl);
    vb_release(vb), vb_release(sc.grid), vb_release(sc.inst[0]), vb_release(sc.inst[1]), vb_release(sc.line);
    ib_release(sc.ib);
    dev_destroy(dev);
}

/* The fused path's fetch of FLOAT1..FLOAT4 elements, per vertex (draw.c's fetch_floats, and the element read past
 * its buffer's end, which takes decl_fetch) and per instance (decl_fetch_inline), and a draw whose declaration
 * drops an element after one that had it (the slot's registers made again: draw_fused.c's slot_inputs), give the
 * reference path's image on 1 and 2 threads. */
static void test_per_vertex_floats(void **state)
{
    (void)state;
    uint32_t *ref = malloc(W * H * sizeof *ref), *img = malloc(W * H * sizeof *img);
    assert_true(ref && img);
    for (int mode = 0; mode < 3; mode++) {
        const bool inst = mode == 1, drop = mode == 2;
        render_floats(1, true, inst, drop, ref);
        size_t lit = 0;
        for (size_t k = 0; k < W * H; k++) lit += ref[k] != 0xff203040u;
        assert_true(lit > 1000);
        for (int threads = 1; threads <= 2; threads++) {
            render_floats(threads, false, inst, drop, img);
            assert_memory_equal(ref, img, W * H * sizeof *ref);
        }
    }
    free(ref), free(img);
}

/* Frame seed shown by dev_present on a device with present flags `flags`: its colour as dev_present returns it and
 * the depth dev_render_target reads afterwards, into *out.  (One frame: the next frame's Clear is not the whole
 * target -- draw_frame's last viewport -- so it would draw over the discarded depth.) */
static void render_present(uint64_t seed, int threads, bool reference, unsigned flags, result *out)
{
    scene sc = make_scene(threads, reference);
    assert_int_equal(dev_set_present_flags(sc.dev, flags), IS_OK);
    draw_frame(&sc, seed);
    memcpy(out->color, dev_present(sc.dev)->color, sizeof out->color);
    memcpy(out->depth, dev_render_target(sc.dev)->depth, sizeof out->depth);
    scene_free(&sc);
}

/* D3DPRESENTFLAG_DISCARD_DEPTHSTENCIL: the presented colour is the frame's, on the reference and the fast path,
 * 1 and 2 threads; the depth afterwards is the frame's Clear value (the drawn depth dropped) -- and without the
 * flag the drawn depth; GetRenderTargetData is not a present (the depth kept); other flags refused. */
static void test_present_discard_depth(void **state)
{
    (void)state;
    result *keep = malloc(sizeof *keep), *drop = malloc(sizeof *drop);
    assert_true(keep && drop);
    for (int path = 0; path < 3; path++) {   /* reference, 1 thread, 2 threads */
        render_present(77, path == 2 ? 2 : 1, path == 0, 0, keep);
        render_present(77, path == 2 ? 2 : 1, path == 0, IS_PRESENTFLAG_DISCARD_DEPTHSTENCIL, drop);
        assert_memory_equal(keep->color, drop->color, sizeof keep->color);
        size_t drawn = 0;
        for (size_t p = 0; p < W * H; p++) {
            drawn += keep->depth[p] != 1.0f;
            if (drop->depth[p] != 1.0f) fail_msg("path %d: depth %g at (%zu, %zu)", path, drop->depth[p], p % W, p / W);
        }
        assert_true(drawn > 1000);
    }
    scene sc = make_scene(2, false);
    assert_int_equal(dev_set_present_flags(sc.dev, IS_PRESENTFLAG_DISCARD_DEPTHSTENCIL), IS_OK);
    draw_frame(&sc, 77);
    assert_int_equal(dev_get_render_target_data(sc.dev, drop->color, W * H), IS_OK);
    assert_memory_equal(keep->color, drop->color, sizeof keep->color);
    assert_memory_equal(keep->depth, dev_render_target(sc.dev)->depth, sizeof keep->depth);
    assert_int_equal(dev_set_present_flags(sc.dev, 0x1u), IS_ERR_INVALIDCALL);   /* LOCKABLE_BACKBUFFER: not known */
    assert_non_null(strstr(dev_last_error(sc.dev), "0x1"));
    scene_free(&sc);
    free(keep), free(drop);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frame_same_bytes),
        cmocka_unit_test(test_thread_counts),
        cmocka_unit_test(test_one_region_per_frame),
        cmocka_unit_test(test_texture_lock_between_draws),
        cmocka_unit_test(test_error_at_flush),
        cmocka_unit_test(test_per_vertex_floats),
        cmocka_unit_test(test_present_discard_depth),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
