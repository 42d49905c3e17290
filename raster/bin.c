/* raster/bin.c -- binning: a chunk's set-up primitives into the lists of the tiles their boxes touch
 * (CSR: rs_chunk.bin_off / bin_idx), in primitive order, so the tile pass walks each tile's primitives in
 * submission order.
 *
 *  The set-ups record each primitive's tile (or RS_MULTI_TILE) in the chunk's ptile array when they push it, so
 *  rs_bin_chunk's two passes (count, fill) read 4 bytes per primitive and the box only of primitives over several
 *  tiles.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "raster_internal.h"

bool rs_reserve(void **buf, size_t *cap, size_t n, size_t size)
{
    if (n <= *cap) return true;
    size_t nc = *cap ? *cap : 64;
    while (nc < n) nc *= 2;
    void *p = nc <= SIZE_MAX / size ? realloc(*buf, nc * size) : NULL;
    if (!p) return false;
    *buf = p;
    *cap = nc;
    return true;
}

/* Add 1 to cnt[t] for every tile t that primitive p's box touches (a primitive over several tiles). */
static void count_tiles(const rs_job *j, const rs_prim *p, uint32_t *cnt)
{
    const int b = j->tile_bits;
    for (int ty = p->y0 >> b; ty <= p->y1 >> b; ty++)
        for (int tx = p->x0 >> b; tx <= p->x1 >> b; tx++)
            cnt[(size_t)ty * (size_t)j->tiles_x + (size_t)tx]++;
}

/* Append primitive k (box of p) to the bin of every tile it touches; cur[t]: tile t's fill cursor. */
static void fill_tiles(const rs_job *j, const rs_prim *p, uint32_t k, uint32_t *cur, uint32_t *idx)
{
    const int b = j->tile_bits;
    for (int ty = p->y0 >> b; ty <= p->y1 >> b; ty++)
        for (int tx = p->x0 >> b; tx <= p->x1 >> b; tx++)
            idx[cur[(size_t)ty * (size_t)j->tiles_x + (size_t)tx]++] = k;
}

/* The number of job j's tiles primitive p's box touches. */
static size_t tiles_of(const rs_job *j, const rs_prim *p)
{
    const int b = j->tile_bits;
    return (size_t)((p->x1 >> b) - (p->x0 >> b) + 1) * (size_t)((p->y1 >> b) - (p->y0 >> b) + 1);
}

/* Count chunk c's bin entries into cnt[t + 1] (zeroed by the caller); returns their total, or more than
 * UINT32_MAX when they do not fit (the counts are then partial). */
static size_t count_bins(const rs_job *j, const rs_chunk *c, uint32_t *cnt)
{
    size_t total = c->n;
    for (size_t k = 0; k < c->n; k++) {
        uint32_t t = c->ptile[k];
        if (t != RS_MULTI_TILE) { cnt[t + 1]++; continue; }
        total += tiles_of(j, &c->prims[k]) - 1;
        if (total > UINT32_MAX) return total;
        count_tiles(j, &c->prims[k], cnt + 1);
    }
    return total;
}

/* Fill chunk c's bin_idx from the bins' starts off[t] (which end as the bins' ends), in primitive order. */
static void fill_bins(const rs_job *j, const rs_chunk *c, uint32_t *off)
{
    for (size_t k = 0; k < c->n; k++) {
        uint32_t t = c->ptile[k];
        if (t != RS_MULTI_TILE) c->bin_idx[off[t]++] = (uint32_t)k;
        else fill_tiles(j, &c->prims[k], (uint32_t)k, off, c->bin_idx);
    }
}

void rs_bin_chunk(const rs_job *j, rs_chunk *c)
{
    size_t nt = (size_t)j->n_tiles;
    if (c->oom || !rs_reserve((void **)&c->bin_off, &c->bin_off_cap, nt + 1, sizeof *c->bin_off)) {
        c->oom = true;
        return;
    }
    uint32_t *off = c->bin_off;
    memset(off, 0, (nt + 1) * sizeof *off);
    size_t total = count_bins(j, c, off);
    if (total > UINT32_MAX || !rs_reserve((void **)&c->bin_idx, &c->idx_cap, total ? total : 1, sizeof *c->bin_idx)) {
        c->oom = true;
        return;
    }
    for (size_t t = 1; t <= nt; t++) off[t] += off[t - 1];   /* off[t]: start of bin t */
    fill_bins(j, c, off);                                    /* off[t]: end of bin t */
    memmove(off + 1, off, nt * sizeof *off);
    off[0] = 0;
    c->n_idx = total;
}
