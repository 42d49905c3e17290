/* bench/bench_scene_file.h -- the scene file the benchmark driver (build/bench) writes and the llvmpipe
 * reference (build/bench-gl) reads, so that both sides draw exactly the same data.
 *
 * Layout (native little-endian, no padding between parts):
 *   bench_scene_header
 *   float    bary[n_points][3]            stream 0: the regular barycentric grid (core_grid_regular)
 *   uint32_t idx[n_indices]               its triangles (3 per triangle)
 *   uint8_t  inst[n_instances][stride]    stream 1: is_patch_instance (136 bytes, Listing 1.1.2's order)
 * Matrices are D3D's: row vectors, m[row][col] stored row by row, clip z in [0, w], pixel centres at integers.
 * bench-gl applies the OpenGL corrections itself (half-pixel offset, depth range, y flip on readback). */
#ifndef INSTESS_BENCH_SCENE_FILE_H
#define INSTESS_BENCH_SCENE_FILE_H

#include <stdint.h>

#define BENCH_SCENE_MAGIC "ISBENCH1"
#define BENCH_INSTANCE_STRIDE 136u

enum { BENCH_PATCH_NPATCH = 0, BENCH_PATCH_SMOOTH = 1 };

typedef struct bench_scene_header {
    char magic[8];            /* BENCH_SCENE_MAGIC, no terminator */
    int32_t width, height;    /* render target in pixels */
    int32_t level;            /* grid level L (for messages) */
    int32_t patch;            /* BENCH_PATCH_* */
    uint32_t n_points;        /* (L+1)(L+2)/2 */
    uint32_t n_indices;       /* 3 L^2 */
    uint32_t n_instances;     /* mesh triangles */
    uint32_t instance_stride; /* BENCH_INSTANCE_STRIDE */
    float wvp[16];            /* g_mWorldViewProjection, row-major, row vectors */
    float world[16];          /* g_mWorld (its 3x3 rotates the normal) */
    float diffuse[4];         /* g_vDiffuse */
    float clear_rgba[4];      /* background colour in [0, 1] */
} bench_scene_header;

#endif
