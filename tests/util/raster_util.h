/* tests/util/raster_util.h -- rasterizer states shared by the raster tests. */
#ifndef INSTESS_TEST_RASTER_UTIL_H
#define INSTESS_TEST_RASTER_UTIL_H

#include "../../raster/raster.h"

/* D3D9's defaults for a full w x h viewport: cull CCW, solid, Gouraud, z LESSEQUAL with write, no blending,
 * multisampling on, COLOR0 interpolated. */
rs_state test_rs_defaults(int w, int h);
/* Counting states: no culling, no depth, additive blending (ONE, ONE) of COLOR0. */
rs_state test_rs_additive(int w, int h);

/* Add the counters of a draw (prims in, culled, drawn, clipped away, degenerate; samples tested, written) to *sum. */
void test_rs_stats_add(rs_stats *sum, const rs_stats *s);

#endif
