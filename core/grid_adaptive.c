/* core/grid_adaptive.c -- refinement patterns for per-edge tessellation levels (semi-uniform: Dyken, Reimers,
 * Seland 2009) and their bounded cache; core/grid.h states the rules.
 *
 * Why no fold: a grid triangle keeps its corners on the lines they lie on (an edge point moves along its edge,
 * a corner and an interior point stay), and the snap is monotone along each edge.  A triangle with two points on
 * one edge keeps their order or collapses; one with a single point on an edge has its other two on the parallel
 * row next to it, so moving the first along the edge keeps the area; the triangles at a corner have their points
 * on the two edges of a convex corner.  tests/test_adaptive.c checks the tiling of every sorted triple. */
#include <stdlib.h>
#include <string.h>

#include "core.h"
#include "hlsl.h"

/* Snap position s of 0..M on an edge of level l <= M to the nearest of 0..l (ties up). */
static int snap(int s, int M, int l)
{
    return (2 * s * l + M) / (2 * M);
}

/* Grid point (i, j) of level M in; its edge (0, 1, 2) and position from that edge's first corner out, or -1 for
 * an interior point.  Corners report the edge that starts at them. */
static int point_edge(int M, int i, int j, int *s)
{
    if (j == 0 && i < M) return *s = i, 0;        /* v0 -> v1 */
    if (i + j == M && j < M) return *s = j, 1;    /* v1 -> v2 */
    if (i == 0) return *s = M - j, 2;             /* v2 -> v0 */
    return -1;
}

/* Edge e's point k of l in; its barycentrics (k / l towards v_(e+1), (l - k) / l at v_e, each from its own end). */
static float3 edge_point(int e, int k, int l)
{
    float c[3] = {0.0f, 0.0f, 0.0f};
    c[e] = (float)(l - k) / (float)l;
    c[(e + 1) % 3] = (float)k / (float)l;
    return f3(c[0], c[1], c[2]);
}

/* Where the snap puts grid point (i, j) of level M under edge levels l: -1 for an interior point (it stays), else
 * the edge e and the position k of 0..l[e] it moves to, a far corner given as point 0 of the next edge. */
static int snapped_edge(const int l[3], int M, int i, int j, int *k)
{
    int s, e = point_edge(M, i, j, &s);
    if (e < 0) return -1;
    *k = snap(s, M, l[e]);
    if (*k == l[e]) e = (e + 1) % 3, *k = 0; /* the far corner: point 0 of the next edge */
    return e;
}

/* The barycentrics of grid point (i, j) of level M (interior) or of edge e's point k of l[e] (e >= 0). */
static float3 point_bary(const int l[3], int M, int i, int j, int e, int k)
{
    if (e < 0) return f3((float)(M - i - j) / (float)M, (float)i / (float)M, (float)j / (float)M);
    return edge_point(e, k, l[e]);
}

/* The levels and M in; for each grid point its pattern index written to map[], the points to out->bary; the point
 * count out.  ids[e][k] holds the index given to edge e's point k (corners are point 0 of their edge). */
static size_t adaptive_points(const int l[3], int M, uint32_t *map, float3 *bary)
{
    int32_t ids[3][CORE_LOD_MAX_LEVEL + 1];
    memset(ids, 0xff, sizeof ids);
    size_t n = 0;
    for (int j = 0; j <= M; j++)
        for (int i = 0; i + j <= M; i++) {
            int k = 0, e = snapped_edge(l, M, i, j, &k);
            uint32_t *slot = &map[core_grid_index(M, i, j)];
            if (e < 0) {
                bary[n] = point_bary(l, M, i, j, e, k);
                *slot = (uint32_t)n++;
                continue;
            }
            if (ids[e][k] < 0) ids[e][k] = (int32_t)n, bary[n++] = point_bary(l, M, i, j, e, k);
            *slot = (uint32_t)ids[e][k];
        }
    return n;
}

/* Is every level in 1..CORE_LOD_MAX_LEVEL?  Their largest into *M. */
static bool levels_ok(const int levels[3], int *M)
{
    *M = 0;
    for (int e = 0; e < 3; e++) {
        if (!levels || levels[e] < 1 || levels[e] > CORE_LOD_MAX_LEVEL) return false;
        if (levels[e] > *M) *M = levels[e];
    }
    return true;
}

int core_grid_adaptive_points(const int levels[3], float3 *bary)
{
    int M;
    if (!bary || !levels_ok(levels, &M)) return -1;
    for (int j = 0; j <= M; j++)
        for (int i = 0; i + j <= M; i++) {
            int k = 0, e = snapped_edge(levels, M, i, j, &k);
            bary[core_grid_index(M, i, j)] = point_bary(levels, M, i, j, e, k);
        }
    return M;
}

int core_grid_adaptive(const int levels[3], core_grid *out)
{
    if (!out) return -1;
    memset(out, 0, sizeof *out);
    int M;
    if (!levels_ok(levels, &M)) return -1;
    const size_t np = core_grid_points(M), nt = core_grid_triangles(M);
    uint32_t *grid_idx = malloc(3 * nt * sizeof *grid_idx), *map = malloc(np * sizeof *map);
    out->bary = malloc(np * sizeof *out->bary);
    out->idx = malloc(3 * nt * sizeof *out->idx);
    if (!grid_idx || !map || !out->bary || !out->idx) {
        free(grid_idx), free(map);
        return core_grid_free(out), -1;
    }
    core_grid_regular(M, out->bary, grid_idx); /* the regular grid's triangles (its points are rebuilt below) */
    out->n_points = adaptive_points(levels, M, map, out->bary);
    size_t t = 0;
    for (size_t q = 0; q < nt; q++) {
        uint32_t a = map[grid_idx[3 * q]], b = map[grid_idx[3 * q + 1]], c = map[grid_idx[3 * q + 2]];
        if (a == b || b == c || c == a) continue; /* collapsed by the snap */
        out->idx[3 * t] = a, out->idx[3 * t + 1] = b, out->idx[3 * t + 2] = c, t++;
    }
    out->n_triangles = t;
    free(grid_idx), free(map);
    return 0;
}

bool core_lod_order(const int edge_levels[3], int sorted[3], int perm[3])
{
    if (!edge_levels || !sorted || !perm) return false;
    int o[3] = {0, 1, 2}; /* the triangle's edges by level, ties by index (insertion sort: stable) */
    for (int i = 1; i < 3; i++)
        for (int k = i; k > 0 && edge_levels[o[k]] < edge_levels[o[k - 1]]; k--) {
            int t = o[k];
            o[k] = o[k - 1], o[k - 1] = t;
        }
    /* pattern edge k is opposite pattern vertex k+2; the triangle's edge o[k] is opposite its vertex o[k]+2 */
    for (int k = 0; k < 3; k++) sorted[k] = edge_levels[o[k]], perm[(k + 2) % 3] = (o[k] + 2) % 3;
    /* a permutation of three is odd when it is a transposition: one fixed point */
    return (perm[0] == 0) + (perm[1] == 1) + (perm[2] == 2) == 1;
}

/* ---------------------------------------- the cache ---------------------------------------- */

enum { CACHE_ENTRY_BYTES = 64, CACHE_KEYS = CORE_LOD_MAX_LEVEL * CORE_LOD_MAX_LEVEL * CORE_LOD_MAX_LEVEL };

typedef struct cache_entry {
    core_grid g;
    int key;             /* -1: free */
    uint64_t last_use;
    size_t bytes;
} cache_entry;

struct core_pattern_cache {
    size_t max_bytes, bytes, built, evicted;
    uint64_t clock;
    int32_t *index;      /* key -> entry, or -1 */
    cache_entry *e;
    size_t n, cap;
};

core_pattern_cache *core_pattern_cache_create(size_t max_bytes)
{
    core_pattern_cache *c = calloc(1, sizeof *c);
    if (!c) return NULL;
    c->index = malloc(CACHE_KEYS * sizeof *c->index);
    if (!c->index) return free(c), NULL;
    memset(c->index, 0xff, CACHE_KEYS * sizeof *c->index);
    c->max_bytes = max_bytes ? max_bytes : CORE_PATTERN_CACHE_DEFAULT_BYTES;
    return c;
}

void core_pattern_cache_destroy(core_pattern_cache *c)
{
    if (!c) return;
    for (size_t k = 0; k < c->n; k++) core_grid_free(&c->e[k].g);
    free(c->e);
    free(c->index);
    free(c);
}

/* Entry k in; its pattern freed and the slot marked free. */
static void cache_evict(core_pattern_cache *c, size_t k)
{
    c->index[c->e[k].key] = -1;
    c->bytes -= c->e[k].bytes;
    core_grid_free(&c->e[k].g);
    c->e[k].key = -1;
    c->evicted++;
}

/* Evict least recently used entries until `need` more bytes fit (or nothing is left). */
static void cache_make_room(core_pattern_cache *c, size_t need)
{
    while (c->bytes + need > c->max_bytes) {
        size_t best = c->n;
        for (size_t k = 0; k < c->n; k++)
            if (c->e[k].key >= 0 && (best == c->n || c->e[k].last_use < c->e[best].last_use)) best = k;
        if (best == c->n) return;
        cache_evict(c, best);
    }
}

/* A free entry's index (growing the array when none), or -1 when out of memory. */
static long cache_slot(core_pattern_cache *c)
{
    for (size_t k = 0; k < c->n; k++)
        if (c->e[k].key < 0) return (long)k;
    if (c->n == c->cap) {
        size_t cap = c->cap ? 2 * c->cap : 64;
        cache_entry *e = realloc(c->e, cap * sizeof *e);
        if (!e) return -1;
        c->e = e, c->cap = cap;
    }
    c->e[c->n].key = -1;
    return (long)c->n++;
}

const core_grid *core_pattern_get(core_pattern_cache *c, int a, int b, int cl)
{
    if (!c || a < 1 || a > b || b > cl || cl > CORE_LOD_MAX_LEVEL) return NULL;
    const int key = ((a - 1) * CORE_LOD_MAX_LEVEL + (b - 1)) * CORE_LOD_MAX_LEVEL + (cl - 1);
    if (c->index[key] >= 0) {
        cache_entry *hit = &c->e[c->index[key]];
        hit->last_use = ++c->clock;
        return &hit->g;
    }
    core_grid g;
    if (core_grid_adaptive((const int[3]){a, b, cl}, &g) != 0) return NULL;
    const size_t bytes = 12 * g.n_points + 12 * g.n_triangles + CACHE_ENTRY_BYTES;
    cache_make_room(c, bytes);
    long k = cache_slot(c);
    if (k < 0) return core_grid_free(&g), NULL;
    c->e[k] = (cache_entry){g, key, ++c->clock, bytes};
    c->index[key] = (int32_t)k;
    c->bytes += bytes;
    c->built++;
    return &c->e[k].g;
}

size_t core_pattern_cache_bytes(const core_pattern_cache *c) { return c ? c->bytes : 0; }
size_t core_pattern_cache_built(const core_pattern_cache *c) { return c ? c->built : 0; }
size_t core_pattern_cache_evicted(const core_pattern_cache *c) { return c ? c->evicted : 0; }
