/* tests/util/raster_util.h -- rasterizer states shared by the raster tests. */
#ifndef INSTESS_TEST_RASTER_UTIL_H
#define INSTESS_TEST_RASTER_UTIL_H

#include "../../raster/raster.h"

#include <stdint.h>

/* xorshift64 random numbers, the raster tests' only state (*s, never 0), passed by pointer: 21 bits. */
uint32_t test_rnd(uint64_t *s);
/* A uniform float in [lo, hi) from test_rnd. */
float test_frnd(uint64_t *s, float lo, float hi);
/* A pixel coordinate near a place the walks must get right -- a tile border or a border of the interval walk's
 * 64-pixel bands (multiples of 64; RS_TILE_SIZE is a multiple), the last pixels of a target of size n, or anywhere
 * in it -- moved by a uniform offset in [lo, hi). */
float test_near_edge(uint64_t *s, int n, float lo, float hi);

/* The index list of `inst` instances of the level-L regular grid (core_grid_regular), instance k's indices offset by
 * k times the grid's points: 3 * inst * L^2 indices, malloc'd (the caller frees them); a failed allocation fails
 * the test. */
uint32_t *test_grid_instances(int L, size_t inst);

/* D3D9's defaults for a full w x h viewport: cull CCW, solid, Gouraud, z LESSEQUAL with write, no blending,
 * multisampling on, COLOR0 interpolated. */
rs_state test_rs_defaults(int w, int h);
/* Counting states: no culling, no depth, additive blending (ONE, ONE) of COLOR0. */
rs_state test_rs_additive(int w, int h);

/* Add the counters of a draw (prims in, culled, drawn, clipped away, degenerate; samples tested, written) to *sum. */
void test_rs_stats_add(rs_stats *sum, const rs_stats *s);

/* The end of a test frame of n pixels: flush rs's recorded draws, add the flush's counters (*sink, filled by the
 * flush when the scene was on) to *sum, flush rt's deferred clear, copy its planes into color and depth, free rt and
 * destroy rs. */
void test_rs_frame_end(rs_context *rs, rs_target *rt, const rs_stats *sink, rs_stats *sum, uint32_t *color,
                       float *depth, size_t n);
/* Fail the test unless two frames of n pixels have the same colour and depth bytes and the same counters. */
void test_rs_same_frame(const uint32_t *color_a, const float *depth_a, const rs_stats *sum_a, const uint32_t *color_b,
                        const float *depth_b, const rs_stats *sum_b, size_t n);

/* Draw v (n triangles, twice: stats[0], stats[1]) into rt with st on a new context of `threads` threads, after a
 * first clear of both planes to other values and then a clear of the planes in flags (RS_CLEAR_*): on the
 * reference path (reference), else the fast path with instruction set isa; deferred: the second clear through
 * rs_target_clear_deferred (the tile buffers), else rs_target_clear.  Ends with rs_target_flush. */
void test_rs_draw_twice(rs_target *rt, const rs_state *st, const rs_vertex *v, int n, bool reference, int isa,
                        int threads, bool deferred, unsigned flags, float clear_z, rs_stats stats[2]);
/* Fail the test unless the fast path (each instruction set the CPU has, deferred and immediate clear, 1 and 2
 * threads) draws v (n triangles, twice, test_rs_draw_twice with both planes cleared) into a w x h target with st
 * to the reference path's colour and depth bytes and samples tested and written, and the reference tested more
 * than min_tested samples; `what` names the case in the failure message. */
void test_rs_paths_agree(int w, int h, const rs_state *st, const rs_vertex *v, int n, float clear_z,
                         uint64_t min_tested, const char *what);

#endif
