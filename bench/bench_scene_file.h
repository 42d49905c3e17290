/* bench/bench_scene_file.h -- the scene file the benchmark driver (build/bench) writes and the llvmpipe
 * reference (build/bench-gl) reads, so that both sides draw exactly the same data.
 *
 * Layout (native little-endian, no padding between parts):
 *   bench_scene_header
 *   float    bary[n_points][3]            stream 0: the regular barycentric grid (core_grid_regular)
 *   uint32_t idx[n_indices]               its triangles (3 per triangle)
 *   uint8_t  inst[n_instances][stride]    stream 1: is_patch_instance (136 bytes, Listing 1.1.2's order)
 *   optional, to the end of the file (scene P; a file that ends after inst draws the interpolated diffuse colour):
 *   bench_texture_header                 the pixel stage: per-pixel light times a texture (BENCH_SHADING_*)
 *   uint32_t texels[levels][...]          level l: max(1, width >> l) x max(1, height >> l) texels, top row first,
 *                                         D3DFMT_A8R8G8B8 (one little-endian DWORD 0xAARRGGBB: bytes B, G, R, A),
 *                                         instess's own mip chain (tex_filter_texture), levels 0..levels-1
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

#define BENCH_TEXTURE_MAGIC "ISBTEX01"

/* What the pixel stage draws when a texture block follows the instances. */
enum {
    /* oC0 = saturate(dot(normalize(TEXCOORD1), (0, 0, -1))) * g_vDiffuse * tex2D(s0, TEXCOORD0.xy), alpha 1: the
     * patch shader's world normal lit per pixel, times the texture sampled with the mip chain, trilinear
     * filtering and WRAP in u and v (GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR, GL_REPEAT) */
    BENCH_SHADING_PIXEL_TEXTURE = 1
};

typedef struct bench_texture_header {
    char magic[8];            /* BENCH_TEXTURE_MAGIC, no terminator */
    int32_t shading;          /* BENCH_SHADING_* */
    int32_t width, height;    /* level 0, texels (1..16384) */
    int32_t levels;           /* levels that follow (1..the full chain) */
} bench_texture_header;

#endif
