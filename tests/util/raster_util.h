/* tests/util/raster_util.h -- rasterizer states shared by the raster tests. */
#ifndef INSTESS_TEST_RASTER_UTIL_H
#define INSTESS_TEST_RASTER_UTIL_H

#include "../../raster/raster.h"

#include <stdint.h>

/* xorshift64 random numbers, the raster tests' only state (*s, never 0), passed by pointer: 21 bits. */
uint32_t test_rnd(uint64_t *s);
/* A uniform float in [lo, hi) from test_rnd. */
float test_frnd(uint64_t *s, float lo, float hi);
/* A pixel coordinate near a place the walks must get right -- a tile border (multiples of 64), the last pixels of a
 * target of size n, or anywhere in it -- moved by a uniform offset in [lo, hi). */
float test_near_edge(uint64_t *s, int n, float lo, float hi);

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

#endif
