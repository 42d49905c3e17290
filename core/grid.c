/* core/grid.c -- the regular barycentric grid of one triangle (seed 000, Fig. 1.1.6). */
#include "core.h"
#include "hlsl.h"

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
    size_t t = 0;
    for (int j = 0; j < L; j++) {
        for (int i = 0; i + j < L; i++) {
            /* the "upright" triangle of cell (i, j): same winding as (v0, v1, v2) */
            idx[t++] = core_grid_index(L, i, j);
            idx[t++] = core_grid_index(L, i + 1, j);
            idx[t++] = core_grid_index(L, i, j + 1);
            if (i + j + 1 < L) { /* the "inverted" triangle between it and the next cell */
                idx[t++] = core_grid_index(L, i + 1, j);
                idx[t++] = core_grid_index(L, i + 1, j + 1);
                idx[t++] = core_grid_index(L, i, j + 1);
            }
        }
    }
    return core_grid_points(L);
}
