/* core/grid.h -- the barycentric grids drawn once per instance: the regular grid of one triangle (Gruen's
 * stream 0), the OpenGL 4 / Direct3D 11 primitive generator's pattern, per-edge refinement patterns for
 * adaptive LOD and their cache.
 *
 * Conventions: a grid point holds barycentrics b = (b0, b1, b2) weighting the triangle's v0, v1, v2; edge k runs
 * from v_k to v_(k+1 mod 3); triangles wind like (v0, v1, v2).  Functions that allocate return 0 / -1 (or NULL)
 * and free with core_grid_free; no globals.
 */
#ifndef INSTESS_CORE_GRID_H
#define INSTESS_CORE_GRID_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "api.h"
#include "math.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The regular barycentric grid of a triangle at level L >= 1 (seed 000, Fig. 1.1.6): (L+1)(L+2)/2 points and
 * L*L triangles.  Point (i, j) with i + j <= L has b = ((L-i-j)/L, i/L, j/L) stored at index
 * core_grid_index(L, i, j) (rows of constant j); triangles wind like the input triangle (v0, v1, v2).
 * Each coordinate is computed as (integer)/L, so mirrored points of an edge hold the same floats swapped.
 * bary gets the points, idx gets 3*L*L indices.  Returns the number of points. */
INSTESS_API size_t core_grid_regular(int level, float3 *bary, uint32_t *idx);
/* The largest level core_grid_regular takes (core_grid_index's int arithmetic); beyond it, below 1 or with a NULL
 * array it writes nothing and returns 0, and the two sizes below are 0 for a level below 1. */
#define CORE_GRID_REGULAR_MAX_LEVEL 16384
static inline size_t core_grid_points(int level)
{
    return level < 1 ? 0 : (size_t)(level + 1) * (size_t)(level + 2) / 2;
}
static inline size_t core_grid_triangles(int level) { return level < 1 ? 0 : (size_t)level * (size_t)level; }
static inline uint32_t core_grid_index(int level, int i, int j)
{
    /* rows j = 0..L hold L+1-j points each */
    return (uint32_t)(j * (level + 1) - j * (j - 1) / 2 + i);
}
/* The level L when idx[0 .. 3 n_triangles) is exactly core_grid_regular(L)'s index list and n_points its point
 * count core_grid_points(L); else (another list, a NULL list, no triangles) 0.  A draw's instance list is
 * compared once (core/draw_fused.c tells the rasterizer, rs_source.grid_level), never assumed. */
INSTESS_API int core_grid_regular_level(const uint32_t *idx, size_t n_triangles, size_t n_points);
/* The same for core_grid_regular(L)'s list mirrored: each triangle's second and third index swapped (the winding
 * an odd renumbering of the corners needs, as the adaptive buckets' flipped ranges); 0 for any other list. */
INSTESS_API int core_grid_regular_level_mirrored(const uint32_t *idx, size_t n_triangles, size_t n_points);

/* The pattern of the OpenGL 4 / Direct3D 11 primitive generator for triangles (seed 001, Figs. 10-11):
 * concentric rings from the inner level, outer edges subdivided by the three outer levels (outer[k] belongs to
 * edge k: 0 = v0-v1, 1 = v1-v2, 2 = v2-v0 in instess's edge order), with equal, fractional_odd or
 * fractional_even spacing (core/grid_pg.c has the rules).  Points are barycentric like core_grid_regular's and
 * wind the same way; a point on an edge has exactly one coordinate 0, and its two others are each computed
 * from the count of segments from its own end, so a neighbour with the same outer level holds the same floats
 * swapped (watertight).  Levels are clamped to [1, 64] (fractional_odd: [1, 63], fractional_even: [2, 64]); non-finite levels are
 * an error.  Memory is allocated here: free with core_grid_free. */
typedef enum core_grid_kind {
    CORE_GRID_REGULAR = 0, CORE_GRID_PG_EQUAL, CORE_GRID_PG_FRACTIONAL_ODD, CORE_GRID_PG_FRACTIONAL_EVEN
} core_grid_kind;
typedef struct core_grid {
    size_t n_points, n_triangles;
    float3 *bary;   /* n_points */
    uint32_t *idx;  /* 3 * n_triangles */
} core_grid;
#define CORE_PG_MAX_LEVEL 64.0f
/* The level a primitive-generator grid of this spacing uses for `level`: clamped to [1, 63] (fractional_odd),
 * [2, 64] (fractional_even) or [1, 64] (equal), as the D3D11 / GL 4 primitive generator does. */
INSTESS_API float core_grid_pg_clamp(core_grid_kind kind, float level);
/* Primitive-generator grid with an inner level and three outer levels; 0 or -1 (bad level, no memory). */
INSTESS_API int core_grid_pg(core_grid_kind spacing, float inner, const float outer[3], core_grid *out);
/* Any grid at one level: regular (level rounded to the nearest integer >= 1) or pg with inner = outer = level. */
INSTESS_API int core_grid_make(core_grid_kind kind, float level, core_grid *out);
INSTESS_API void core_grid_free(core_grid *g);

/* --- adaptive tessellation patterns (core/grid_adaptive.c) --- */

/* Refinement patterns for per-edge levels (semi-uniform tessellation: Dyken, Reimers, Seland, "Semi-uniform
 * adaptive patch tessellation", Computer Graphics Forum 28(8), 2009).  The pattern of edge levels (l0, l1, l2)
 * (edge k: v_k - v_(k+1), as core_grid_regular; each level 1..CORE_LOD_MAX_LEVEL) is the regular grid of level
 * M = max(l0, l1, l2) whose points on edge k are snapped to the nearest of that edge's l_k + 1 points (round
 * half up in integer arithmetic, a monotone map, so no triangle folds over), merged, and whose triangles that
 * lost an index to the merge (zero area) are dropped.  An edge point k segments of l from v_e holds the weight
 * (float)k / (float)l for the far corner and (float)(l - k) / (float)l for v_e, the same floats (swapped) for
 * the neighbour whatever its other levels: neighbours agree bit for bit on every edge point.  With
 * l0 = l1 = l2 = L the pattern is core_grid_regular(L), point for point and triangle for triangle.
 * Triangles wind like (v0, v1, v2); points are in the regular grid's order with the merged ones left out. */
#define CORE_LOD_MAX_LEVEL 64
/* The pattern of edge levels l[0..2] (any order); 0, or -1 for a level outside 1..CORE_LOD_MAX_LEVEL or no memory.
 * Free with core_grid_free. */
INSTESS_API int core_grid_adaptive(const int levels[3], core_grid *out);
/* The same pattern drawn as the regular grid: the core_grid_points(M) points of core_grid_regular(M), M the
 * largest of the levels, at their core_grid_index places, each moved as core_grid_adaptive moves it (the pattern's
 * points, bit for bit, the merged ones repeated).  core_grid_regular(M)'s triangle list over these points draws
 * the pattern's triangles in the pattern's order, plus the merged ones, which have zero area and draw nothing --
 * how Dyken et al. draw it, and what lets a renderer treat every pattern as a regular grid (instess's rasterizer
 * sets such draws up from the grid's rows).  Returns M, or -1 (nothing written) for a level outside
 * 1..CORE_LOD_MAX_LEVEL or a NULL array. */
INSTESS_API int core_grid_adaptive_points(const int levels[3], float3 *bary);

/* Patterns are kept for sorted triples a <= b <= c only: a triangle with edge levels e[0..2] is drawn with the
 * pattern of sort(e) after renumbering its vertices.  core_lod_order gives that renumbering: perm[i] is the
 * triangle's vertex that becomes the pattern's vertex i, so that the triangle's edge (perm[k], perm[k+1]) has
 * level sorted[k]; returns true when perm is odd (a reflection: the pattern's triangles must then be drawn with
 * two indices swapped to keep the mesh's winding).  Ties keep the lower edge first (deterministic).  A NULL
 * array: false, nothing written. */
INSTESS_API bool core_lod_order(const int edge_levels[3], int sorted[3], int perm[3]);

/* A lazily filled cache of the patterns of sorted triples, bounded in memory: the patterns held take at most
 * max_bytes (counted as 12 bytes per point, 12 per triangle and 64 per entry; CORE_PATTERN_CACHE_DEFAULT_BYTES by
 * default), plus a fixed index of CORE_LOD_MAX_LEVEL^3 int32 (1 MiB).  When a new pattern does not fit, the
 * least recently used ones are evicted (the largest pattern, 64/64/64, takes about 75 KB, so a bound under that
 * still keeps the one pattern asked for).  Single-threaded: one cache per user. */
#define CORE_PATTERN_CACHE_DEFAULT_BYTES (16u << 20)
typedef struct core_pattern_cache core_pattern_cache;
/* A new empty cache (max_bytes 0: the default); NULL when out of memory. */
INSTESS_API core_pattern_cache *core_pattern_cache_create(size_t max_bytes);
INSTESS_API void core_pattern_cache_destroy(core_pattern_cache *c);
/* The pattern of sorted levels a <= b <= c (built on first use), valid until the next call on this cache; NULL
 * for unsorted or out-of-range levels or when out of memory. */
INSTESS_API const core_grid *core_pattern_get(core_pattern_cache *c, int a, int b, int cl);
/* Bytes held now (by the bound's count), patterns built so far, patterns evicted so far (0 for a NULL cache). */
INSTESS_API size_t core_pattern_cache_bytes(const core_pattern_cache *c);
INSTESS_API size_t core_pattern_cache_built(const core_pattern_cache *c);
INSTESS_API size_t core_pattern_cache_evicted(const core_pattern_cache *c);

#ifdef __cplusplus
}
#endif
#endif
