/* core/grid.c -- the regular barycentric grid of one triangle (seed 000, Fig. 1.1.6). */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "core.h"
#include "hlsl.h"

/* The triangles of the level-L regular grid in order, 3 indices each (the second and third swapped when mirrored):
 * into idx when it is not NULL, and compared with cmp when it is not NULL (stopping at the first difference).
 * Returns whether cmp matched (true without cmp). */
static bool regular_triangles(int L, bool mirrored, uint32_t *idx, const uint32_t *cmp)
{
    size_t t = 0;
    const int b = mirrored ? 2 : 1, c = mirrored ? 1 : 2;   /* where a triangle's second and third index go */
    for (int j = 0; j < L; j++) {
        for (int i = 0; i + j < L; i++) {
            /* the "upright" triangle of cell (i, j): same winding as (v0, v1, v2), then (when i + j + 1 < L) the
             * "inverted" triangle between it and the next cell */
            uint32_t tri[6];
            tri[0] = core_grid_index(L, i, j), tri[b] = core_grid_index(L, i + 1, j), tri[c] = core_grid_index(L, i, j + 1);
            tri[3] = core_grid_index(L, i + 1, j), tri[3 + b] = core_grid_index(L, i + 1, j + 1);
            tri[3 + c] = core_grid_index(L, i, j + 1);
            const size_t n = i + j + 1 < L ? 6 : 3;
            if (cmp && memcmp(cmp + t, tri, n * sizeof *tri) != 0) return false;
            if (idx) memcpy(idx + t, tri, n * sizeof *tri);
            t += n;
        }
    }
    return true;
}

/* Fill bary with the (L+1)(L+2)/2 grid points and idx with L*L triangles (3 indices each); returns the
 * point count (0, nothing written, for a level outside 1..CORE_GRID_REGULAR_MAX_LEVEL or a NULL array).  Point (i, j) is b = ((L-i-j)/L, i/L, j/L): each coordinate is an exact integer over L, so the
 * point mirrored along an edge holds the same three floats in swapped positions. */
size_t core_grid_regular(int level, float3 *bary, uint32_t *idx)
{
    if (level < 1 || level > CORE_GRID_REGULAR_MAX_LEVEL || !bary || !idx) return 0;
    const int L = level;
    const float fl = (float)L;
    for (int j = 0; j <= L; j++)
        for (int i = 0; i + j <= L; i++)
            bary[core_grid_index(L, i, j)] = f3((float)(L - i - j) / fl, (float)i / fl, (float)j / fl);
    regular_triangles(L, false, idx, NULL);
    return core_grid_points(L);
}

/* core_grid_regular_level, of the list as it is or mirrored. */
static int regular_level(const uint32_t *idx, size_t n_triangles, size_t n_points, bool mirrored)
{
    if (!idx || n_triangles == 0 || n_triangles > core_grid_triangles(CORE_GRID_REGULAR_MAX_LEVEL)) return 0;
    const int L = (int)lrint(sqrt((double)n_triangles));   /* exact: n_triangles <= 2^28 */
    if (core_grid_triangles(L) != n_triangles || core_grid_points(L) != n_points) return 0;
    return regular_triangles(L, mirrored, NULL, idx) ? L : 0;
}

int core_grid_regular_level(const uint32_t *idx, size_t n_triangles, size_t n_points)
{
    return regular_level(idx, n_triangles, n_points, false);
}

int core_grid_regular_level_mirrored(const uint32_t *idx, size_t n_triangles, size_t n_points)
{
    return regular_level(idx, n_triangles, n_points, true);
}
