/* tests/util/patch_util.h -- random triangles and small helpers shared by the patch tests. */
#ifndef INSTESS_TEST_PATCH_UTIL_H
#define INSTESS_TEST_PATCH_UTIL_H

#include <stdbool.h>
#include <stdint.h>

#include "../../meshes/meshes.h"
#include "../../vs/vs.h"
#include "../../cli/run/scene.h"

/* xorshift64* in [-1, 1). */
float frand(uint64_t *s);
float3 rand3(uint64_t *s);
/* Bitwise equality. */
bool same3(float3 a, float3 b);
/* A random curved triangle: normals = face normal tilted by up to ~30 degrees, neighbours across every edge
 * folded randomly (opp below or above the edge's outside). */
vs_triangle rand_tri(uint64_t *s);
/* The triangle's positions, normals and opposite vertices in double. */
void to_d(const vs_triangle *t, double v[3][3], double n[3][3], double opp[3][3]);
/* |a - b| in double. */
double dist_d(float3 a, const double b[3]);
/* Rotate labels by r: v_k <- v_(k+r)%3 with its normal, opposite vertex, texcoord and nadj. */
vs_triangle rotate(const vs_triangle *t, int r);
/* The built-in cube, or side x side copies of it 3 apart in the z = 0 plane (the benchmark's scene B layout),
 * into out; 0 or -1. */
int cubes_mesh(int side, is_mesh *out);
/* Clear dev (target and depth, o's background) and draw scene o of mesh m with o's grid: scene_draw's result (the
 * device's error printed to stderr when it fails). */
int clear_and_draw(is_device *dev, const scene_opts *o, const is_mesh *m);

/* An LCG step of *st into a float in [lo, hi). */
float lcg_float(uint32_t *st, float lo, float hi);
/* Instance registers (Listing 1.1.2's per-instance data in is_vs_input) of triangle t of family t % 5: ordinary,
 * shared position and normal bits on edge 0 (degenerate edge, no canonical order), a zero normal, huge coordinates
 * (non-finite intermediate results), a boundary edge (fn = 1); the rest of *in is D3D9's default (0, 0, 0, 1). */
void random_instance_regs(uint32_t *st, int t, is_vs_input *in);

#endif
