/* tests/util/crack.h -- the crack detector the crack tests share (tests/test_cracks.c explains it): additive
 * coverage without culling or depth test, where a closed surface covers every pixel an even number of times,
 * and a jitter of each clip-space position that depends on its bits alone, so that two vertices on the two sides
 * of an edge move together only if their bits are equal (one ulp apart moves them about a pixel apart).
 *
 * Conventions: images are square, `size` pixels a side; counts are in the red channel, 1/255 per cover. */
#ifndef INSTESS_TESTS_CRACK_H
#define INSTESS_TESTS_CRACK_H

#include <stdbool.h>
#include <stdint.h>

#include "../../core/core.h"
#include "../../core/hlsl.h"
#include "../../image/image.h"
#include "../../meshes/meshes.h"

/* One round of a 32-bit integer hash (lowbias32). */
uint32_t crack_mix32(uint32_t h);
/* The bits of f with -0 read as +0. */
uint32_t crack_bits(float f);
/* Move clip-space *pos by (jx, jy) pixels of a size x size image, each in [-1/2, 1/2), hashed from its bits. */
void crack_jitter(float4 *pos, int size);
/* dev's states for counting: culling and depth test off, additive blending (ONE, ONE), target and depth cleared. */
void crack_counting_states(is_device *dev);
/* Whether two vertices of m at the same position carry different normals (N-Patches crack there by design). */
bool crack_split_normals(const is_mesh *m);

#endif
