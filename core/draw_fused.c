/* core/draw_fused.c -- the fused path of instanced triangle draws: the fast path of draw.c's D3D9 draw (which is
 * the definition, and the reference path's only route), writing the same bytes.
 *
 * Instanced triangle draws with few vertices per instance (the tessellation grids; off the reference path, at most
 * FUSED_PIECE_VERTICES vertices per instance): the rasterizer's setup threads ask for pieces of a few instances
 * (rs_draw_source), which are fetched, shaded, projected and set up by one thread while they are in the cache, into
 * per-thread scratch, at most FUSED_MAX_PRIMS triangles per rasterizer call.  Same bytes as shading everything
 * first (each instance's vertices and triangles are the same, in the same order).  A draw is then one parallel
 * region (set-up) plus its share of the frame's tile pass (the rasterizer queues a frame's draws: rs_set_scene,
 * which the device turns on): on a machine whose cores are busy with other processes, each region's
 * end can wait for a descheduled thread while libgomp's default busy-waiting keeps the core -- run with
 * OMP_WAIT_POLICY=passive there. */
#include "device_internal.h"

#include <stdlib.h>
#include <string.h>

/* Vertices per piece at most (about 700 KB of shaded vertices: the piece stays in the cache), and pieces per draw
 * aimed at (enough for load balance, few enough that the per-tile walk over pieces stays cheap). */
#define FUSED_PIECE_VERTICES 4096u
#define FUSED_PIECES 64u
#define FUSED_PIECE_PRIMS 16384u
/* Draws of fewer triangles than this are set up by one thread (raster/draw.c's PARALLEL_SETUP_MIN): their pieces
 * are made as large as the limits above allow, since more pieces buy no balance there and each costs the
 * rasterizer a pass over the tiles (binning, and the tile pass's walk over the pieces: scene D's adaptive frames
 * draw ~650 such draws, one instance per piece before). */
#define FUSED_SMALL_DRAW 8192u
/* Triangles per rs_draw_source call at most: bounds the set-up triangles held before the tile pass. */
#define FUSED_MAX_PRIMS (1u << 19)

/* A fused draw pass: instances i0..i0+ni-1 in pieces of per_piece instances. */
typedef struct fused_ctx {
    const is_device *dev;
    const fetch_plan *fp;
    uint32_t first, count, i0, ni, per_piece;
    size_t n_idx;              /* indices of one instance (3 per triangle) */
    const uint32_t *list;      /* the index list of a full piece (instance i's vertices at i * count) */
    size_t slot_verts;         /* scratch per slot in out_v */
    rs_vertex *out_v;
    const float4 *cache;       /* fetch_cache of first..first+count-1 (the draw has one) */
    is_vs_input *in;           /* count input registers per slot (see shade_instance) */
    bool *in_ready;            /* per slot: its inputs hold the defaults and the per-vertex registers */
    uint32_t live;             /* live_outputs(dev) */
    is_vs_grid *grid;          /* per slot: the shader's grid workspace (NULL: none; see fetch_instance) */
    cull_view cull;            /* the pre-tessellation cull (draw_cull.c) */
    uint64_t *culled;          /* per slot: instances culled */
} fused_ctx;

/* Make the inputs of `instance` ready for shade_instance, which shades all `count` vertices into out[0..count)
 * with one batch call (so the shader's 8-lane groups are full but for the instance's last ones).  in[0..count)
 * is the slot's input scratch, made ready once per draw
 * (*ready): D3D9's defaults, then the per-vertex registers from the draw's fetch_cache (the same for every
 * instance; no element shares a register with another).  Per instance only the per-instance registers are
 * fetched: into in[0] alone for a batch shader, into every entry for a shader called per vertex.  A batch shader
 * is told that every register but the per-vertex ones (fp->shared: the per-instance registers and the defaults)
 * is the same for all vertices and stored in in[0] only.  The outputs are not zeroed first: the rasterizer reads
 * oPos and the live outputs the shader writes (its `outputs` mask), nothing else of this scratch. */
static void fetch_instance(const fused_ctx *f, uint32_t instance, is_vs_input *in, bool *ready, is_vs_grid *grid)
{
    const fetch_plan *fp = f->fp;
    const uint32_t n = f->count;
    const is_vertex_shader *vs = f->dev->vs;
    if (!*ready) {
        for (uint32_t v = 0; v < n; v++) input_defaults(&in[v]);
        fetch_cached(fp, f->cache, 0, n, in);
        *ready = true;
        if (grid) grid->ready = false; /* the shader's grid workspace follows the per-vertex registers */
    }
    const uint32_t copies = vs->batch ? 1 : n;
    for (unsigned k = 0; k < fp->n; k++) {
        const fetch_elem *e = &fp->el[k];
        if (!e->per_instance) continue;
        float4 r = decl_fetch(e->type, fetch_at(e, instance));
        for (uint32_t v = 0; v < copies; v++) *(float4 *)((unsigned char *)&in[v] + e->reg_offset) = r;
    }
}

/* Shade the instance whose inputs fetch_instance made ready: its `count` vertices into out[0..count) (with the
 * slot's grid workspace when the shader takes one). */
static void shade_instance(const fused_ctx *f, const is_vs_input *in, is_vs_grid *grid, rs_vertex *out)
{
    const fetch_plan *fp = f->fp;
    const uint32_t n = f->count;
    const is_vertex_shader *vs = f->dev->vs;
    if (grid) vs->grid_batch(&f->dev->consts, in, n, f->live, fp->shared, grid, out);
    else if (vs->batch) vs->batch(&f->dev->consts, in, n, f->live, fp->shared, out);
    else
        for (uint32_t v = 0; v < n; v++) vs->main(&f->dev->consts, &in[v], &out[v]);
    post_shade(&f->dev->remap, out, n);
}

/* rs_produce_fn: shade the piece's instances that the cull keeps into the slot's scratch, one after the other,
 * and hand over the prefix of the index list that covers them. */
static size_t fused_produce(void *ctx, size_t piece, int slot, rs_vertex **verts, size_t *n_verts,
                            const uint32_t **idx)
{
    const fused_ctx *f = ctx;
    uint32_t a = (uint32_t)piece * f->per_piece, n = f->ni - a < f->per_piece ? f->ni - a : f->per_piece;
    rs_vertex *out = f->out_v + (size_t)slot * f->slot_verts;
    is_vs_input *in = f->in + (size_t)slot * f->count;
    is_vs_grid *grid = f->grid ? &f->grid[slot] : NULL;
    uint32_t kept = 0;
    for (uint32_t i = 0; i < n; i++) {
        fetch_instance(f, f->i0 + a + i, in, &f->in_ready[slot], grid);
        is_patch_hull h;
        if (f->cull.on && f->dev->vs->hull(&f->dev->consts, in, &h) && cull_instance(&f->cull, &h)) {
            f->culled[slot]++;
            continue;
        }
        shade_instance(f, in, grid, out + (size_t)kept++ * f->count);
    }
    *verts = out, *n_verts = (size_t)kept * f->count, *idx = f->list; /* a short piece uses a prefix */
    return (size_t)kept * (f->n_idx / 3);
}

/* Instances per piece: about 1/FUSED_PIECES of the draw (all of a small one), at most FUSED_PIECE_VERTICES
 * vertices and FUSED_PIECE_PRIMS triangles (the piece's index list), at least one instance. */
static uint32_t fused_per_piece(uint32_t n_inst, uint32_t count, size_t n_prims)
{
    uint64_t want = (uint64_t)n_inst * count / FUSED_PIECES;
    if ((uint64_t)n_inst * n_prims < FUSED_SMALL_DRAW) want = (uint64_t)n_inst * count;
    uint64_t per = want <= count ? 1u : want / count;
    if (per * count > FUSED_PIECE_VERTICES) per = FUSED_PIECE_VERTICES / count;
    if (per * n_prims > FUSED_PIECE_PRIMS) per = FUSED_PIECE_PRIMS / n_prims;
    return per < 1 ? 1u : (uint32_t)per;
}

/* The slots' grid workspaces of the shader for instances of count vertices (device scratch, not ready), or NULL
 * when the shader takes none or memory is short (the shader's plain batch then: the same bytes). */
static is_vs_grid *fused_grids(is_device *dev, int slots, uint32_t count)
{
    const is_vertex_shader *vs = dev->vs;
    size_t room = vs->grid_batch && vs->grid_room ? vs->grid_room(count) : 0;
    is_vs_grid *g = room ? scratch_get(&dev->vs_grid, (size_t)slots, sizeof *g) : NULL;
    unsigned char *mem = g ? scratch_get(&dev->vs_grid_mem, (size_t)slots, room) : NULL;
    if (!mem) return NULL;
    for (int k = 0; k < slots; k++) g[k] = (is_vs_grid){mem + (size_t)k * room, room, false};
    return g;
}

/* Triangles off the reference path, at most FUSED_PIECE_VERTICES vertices per instance. */
bool draw_fused_takes(const is_device *dev, int prim, uint32_t count)
{
    return !dev->reference && prim == RS_PRIM_TRIANGLES && count <= FUSED_PIECE_VERTICES;
}

/* The index list of fused_per_piece instances. */
size_t draw_fused_list_room(const fetch_plan *fp, uint32_t count, size_t n_prims)
{
    return (size_t)fused_per_piece(fp->n_instances, count, n_prims) * n_prims * 3;
}

/* The fused draw of n_prims triangles per instance (see above); list = instance 0's index list, with room for
 * the index list of a full piece (fused_per_piece instances). */
is_result draw_fused(is_device *dev, const fetch_plan *fp, size_t n_prims, uint32_t first, uint32_t count,
                     uint32_t *list)
{
    const uint32_t n_inst = fp->n_instances, per_piece = fused_per_piece(n_inst, count, n_prims);
    const uint64_t total = (uint64_t)n_inst * count;
    size_t max_pieces = rs_max_pieces(&dev->rt), per_pass = FUSED_MAX_PRIMS / n_prims;
    if (per_pass < per_piece) per_pass = per_piece;
    if (per_pass / per_piece > max_pieces) per_pass = max_pieces * per_piece;
    int slots = rs_threads(dev->rs);
    for (uint32_t i = 1; i < per_piece; i++) /* instance i of a piece: instance 0's list moved by i * count */
        for (size_t k = 0; k < 3 * n_prims; k++) list[(size_t)i * 3 * n_prims + k] = i * count + list[k];
    /* the device's scratch, kept between draws: in_ready is cleared, the inputs are made ready again per draw */
    const float4 *cache = fetch_cache(dev, fp, first, count);
    is_vs_input *in = scratch_get(&dev->in, (size_t)slots * count, sizeof *in);
    bool *in_ready = scratch_get(&dev->in_ready, (size_t)slots, sizeof *in_ready);
    uint64_t *culled = scratch_get(&dev->culled, (size_t)slots, sizeof *culled);
    if (in_ready) memset(in_ready, 0, (size_t)slots * sizeof *in_ready);
    if (culled) memset(culled, 0, (size_t)slots * sizeof *culled);
    fused_ctx f = {dev, fp, first, count, 0, 0, per_piece, 3 * n_prims, list, (size_t)per_piece * count, NULL, cache,
                   in, in_ready, live_outputs(dev), fused_grids(dev, slots, count), {0}, culled};
    cull_prepare(dev, fp, cache, list, n_prims, &f.cull);
    is_result r = cache && in && in_ready && culled
                      ? reserve_scratch(dev, (size_t)slots * f.slot_verts, 0)
                      : dev_fail(dev, IS_ERR_OUTOFMEMORY, "draw: out of memory for the inputs");
    f.out_v = dev->out_v;
    for (uint32_t i0 = 0; r == IS_OK && i0 < n_inst; i0 += (uint32_t)per_pass) {
        f.i0 = i0;
        f.ni = n_inst - i0 < per_pass ? n_inst - i0 : (uint32_t)per_pass;
        rs_source src = {(f.ni + per_piece - 1) / per_piece, (size_t)f.ni * n_prims, f.slot_verts, fused_produce, &f};
        rs_state st = dev_rs_state(dev);
        rs_stats s = {0};
        r = draw_result(dev, rs_draw_source(dev->rs, &st, &dev->rt, &src, &s), &s);
    }
    uint64_t skipped = 0;
    for (int k = 0; culled && k < slots; k++) skipped += culled[k];
    dev->instances_culled += skipped;
    dev->shaded += total - skipped * count;
    return r;
}
