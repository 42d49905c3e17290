/* core/draw_fused.c -- the fused path of instanced triangle draws: the fast path of draw.c's D3D9 draw (which is
 * the definition, and the reference path's only route), writing the same bytes.
 *
 * Instanced triangle draws with few vertices per instance (the tessellation grids; off the reference path, at most
 * FUSED_PIECE_VERTICES vertices per instance): the rasterizer's setup threads ask for pieces of a few instances
 * (rs_draw_source), which are fetched, shaded, projected and set up by one thread while they are in the cache, into
 * per-thread scratch, at most FUSED_MAX_PRIMS triangles per rasterizer call.  Same bytes as shading everything
 * first (each instance's vertices and triangles are the same, in the same order).
 *
 * Draws are recorded, not run (device_internal.h's dev_scene): a draw copies what its pieces read -- the shader,
 * the constants and vertex samplers, the viewport map, the fetch plan, the per-vertex inputs, instance 0's index
 * list, the cull -- into a record, marks the vertex buffers it reads (its streams), and hands the record to
 * the rasterizer (rs_draw_source with the scene on, which the device turns on).  At the rasterizer's next flush
 * the threads take pieces across all recorded draws, then ONE tile pass walks each tile's draws in submission
 * order, both in ONE parallel region: a frame of many small draws (scene D: ~650) pays one region per flush, not
 * two per draw.  Each slot's scratch (dev->fz) says which record its inputs and index list were made for, and a record
 * whose per-vertex registers are those the slot holds, bit for bit (scene D: the two parities of a pattern), keeps
 * them and the shader's grid plan.  On a machine
 * whose cores are busy with other processes, each region's end can wait for a descheduled thread while libgomp's
 * default busy-waiting keeps the core -- run with OMP_WAIT_POLICY=passive there (the flush's region passes from
 * the set-up to the tile pass by its own short wait, which yields the core after ~4096 spins). */
#include "device_internal.h"

#include <stdlib.h>
#include <string.h>

/* Vertices per piece at most (about 700 KB of shaded vertices: the piece stays in the cache), and pieces per draw
 * aimed at (enough for load balance, few enough that the per-tile walk over pieces stays cheap). */
#define FUSED_PIECE_VERTICES 4096u
#define FUSED_PIECES 64u
#define FUSED_PIECE_PRIMS 16384u
/* Triangles per rs_draw_source call at most: bounds the set-up triangles held before the tile pass. */
#define FUSED_MAX_PRIMS (1u << 19)

/* Records per generation at most: a device drawing without frames (no deferred clear: nothing is queued) flushes
 * its records at this many. */
#define FUSED_MAX_RECORDS 1024u

/* A recorded fused draw pass: instances i0..i0+ni-1 in pieces of per_piece instances, with the snapshot of what
 * its pieces read at the flush (the pointers lead into its fused_rec). */
typedef struct fused_ctx {
    const is_device *dev;      /* its producers' scratch (dev->fz), read at the flush */
    const fetch_plan *fp;      /* the draw's fetch plan (a copy) */
    const is_vertex_shader *vs; /* the draw's shader (a copy) */
    is_vs_constants consts;    /* the draw's constants and vertex samplers */
    vp_remap remap;            /* the draw's viewport map */
    uint32_t first, count, i0, ni, per_piece;
    size_t n_idx;              /* indices of one instance (3 per triangle) */
    const uint32_t *list0;     /* instance 0's index list (rebased to first) */
    size_t slot_verts;         /* shaded vertices of a full piece */
    const float4 *cache;       /* fetch_cache of first..first+count-1 (a copy) */
    uint32_t live;             /* live_outputs(dev) */
    size_t grid_room;          /* bytes of the shader's grid workspace per slot (0: it takes none) */
    cull_view cull;            /* the pre-tessellation cull (draw_cull.c) */
    fused_layout lay;          /* how its pieces fill a slot's input registers */
    uint64_t serial;           /* the record's number (the slots' tags) */
    uint64_t culled;           /* instances culled at the flush (atomic) */
} fused_ctx;

/* A record: the pass, the copies it points at, then its fetch cache and index list in data[]. */
struct fused_rec {
    fused_ctx f;
    is_vertex_shader vs;
    fetch_plan fp;
    size_t bytes;              /* of data[] */
    float4 data[];
};

/* Whether a slot's registers made with layout *have are laid out as record f's would be: the same shader kind,
 * the same per-instance registers and the same per-vertex registers in the same order (then only the per-vertex
 * values of the entries may differ; have->count entries were made). */
static bool same_shape(const fused_layout *have, const fused_layout *want)
{
    return have->valid && have->per_call == want->per_call && have->inst_regs == want->inst_regs &&
           have->n_vert == want->n_vert && !memcmp(have->vreg, want->vreg, want->n_vert);
}

/* Whether the per-vertex registers of in[0..count) hold, bit for bit, record f's fetch cache (a vertex buffer
 * rewritten between two draws gives other values, whatever its pointer and size). */
static bool same_values(const fused_ctx *f, const is_vs_input *in)
{
    const fused_layout *want = &f->lay;
    const float4 *c = f->cache;
    for (uint32_t v = 0; v < want->count; v++) {
        const float4 *r = (const float4 *)&in[v];
        for (uint32_t q = 0; q < want->n_vert; q++, c++)
            if (memcmp(&r[want->vreg[q]], c, sizeof *c)) return false;
    }
    return true;
}

/* Make the slot's input registers in[0..count) ready for record f (once per record and slot), made with layout
 * *lay before: kept as they are when they already hold f's (same_shape, enough entries, same_values); else the
 * per-vertex registers from the draw's fetch_cache (the same for every instance; no element shares a register with
 * another) over D3D9's defaults, which are written only to the entries not made with f's shape before (the other
 * registers of those hold the defaults, or per-instance registers fetch_instance rewrites).  The slot's grid
 * workspace ws (NULL: none) follows the registers: kept with them (and the same grid_batch), else made anew. */
static void slot_inputs(const fused_ctx *f, is_vs_input *in, fused_layout *lay, is_vs_grid *ws)
{
    const bool shape = same_shape(lay, &f->lay);
    if (shape && lay->count >= f->count && same_values(f, in)) {
        if (lay->grid_fn != f->lay.grid_fn && ws) ws->ready = false;
        lay->grid_fn = f->lay.grid_fn;
        return;
    }
    const uint32_t made = shape ? lay->count : 0;
    for (uint32_t v = made; v < f->count; v++) input_defaults(&in[v]);
    fetch_cached(f->fp, f->cache, 0, f->count, in);
    *lay = f->lay;
    lay->count = made > f->count ? made : f->count;
    if (ws) ws->ready = false;
}

/* Make the inputs of `instance` ready for shade_instance, which shades all `count` vertices into out[0..count)
 * with one batch call (so the shader's 8-lane groups are full but for the instance's last ones): the slot's
 * registers for the record (slot_inputs, once per record and slot: *ready), then per instance only the
 * per-instance registers, fetched into in[0] alone for a batch shader, into every entry for a shader called per
 * vertex.  A batch shader is told that every register but the per-vertex ones (fp->shared: the per-instance
 * registers and the defaults) is the same for all vertices and stored in in[0] only.  The outputs are not zeroed
 * first: the rasterizer reads oPos and the live outputs the shader writes (its `outputs` mask), nothing else of
 * this scratch. */
static void fetch_instance(const fused_ctx *f, uint32_t instance, is_vs_input *in, bool *ready, fused_layout *lay,
                           is_vs_grid *ws)
{
    const fetch_plan *fp = f->fp;
    const uint32_t n = f->count;
    const is_vertex_shader *vs = f->vs;
    if (!*ready) {
        slot_inputs(f, in, lay, ws);
        *ready = true;
    }
    const uint32_t copies = vs->batch ? 1 : n;
    for (unsigned k = 0; k < fp->n; k++) {
        const fetch_elem *e = &fp->el[k];
        if (!e->per_instance) continue;
        float4 r = decl_fetch_inline(e->type, fetch_at(e, instance));
        for (uint32_t v = 0; v < copies; v++) *(float4 *)((unsigned char *)&in[v] + e->reg_offset) = r;
    }
}

/* Shade the instance whose inputs fetch_instance made ready: its `count` vertices into out[0..count) (with the
 * slot's grid workspace when the shader takes one), then post_shade's work (the colours' part only when the shader
 * did not saturate them). */
static void shade_instance(const fused_ctx *f, const is_vs_input *in, is_vs_grid *grid, rs_vertex *out)
{
    const fetch_plan *fp = f->fp;
    const uint32_t n = f->count;
    const is_vertex_shader *vs = f->vs;
    if (grid) {   /* its colours come saturated (is_vs_grid_batch_fn) */
        vs->grid_batch(&f->consts, in, n, f->live, fp->shared, grid, out);
        post_remap(&f->remap, out, n);
        return;
    }
    if (vs->batch) vs->batch(&f->consts, in, n, f->live, fp->shared, out);
    else
        for (uint32_t v = 0; v < n; v++) vs->main(&f->consts, &in[v], &out[v]);
    post_shade(&f->remap, out, n);
}

/* out[0..n) = l0[0..n) + base, 8 indices per vector (GCC's -O2 does not vectorize the loop by itself). */
static void list_moved(uint32_t *restrict out, const uint32_t *restrict l0, size_t n, uint32_t base)
{
    typedef uint32_t u32x8 __attribute__((vector_size(32)));
    size_t k = 0;
    for (; k + 8 <= n; k += 8) {
        u32x8 v;
        memcpy(&v, l0 + k, sizeof v);
        v += base;
        memcpy(out + k, &v, sizeof v);
    }
    for (; k < n; k++) out[k] = l0[k] + base;
}

/* The index list of `kept` instances of record f in the slot's scratch (instance i: instance 0's list moved by
 * i * count), extended when the slot's list of f is shorter. */
static const uint32_t *slot_list(const fused_ctx *f, const fused_scratch *z, int slot, uint32_t kept)
{
    uint32_t *l = z->list + (size_t)slot * z->list_slot;
    const uint32_t done = z->ltag[slot] == f->serial ? z->lcount[slot] : 0;
    for (uint32_t i = done; i < kept; i++) list_moved(l + (size_t)i * f->n_idx, f->list0, f->n_idx, i * f->count);
    z->ltag[slot] = f->serial, z->lcount[slot] = kept > done ? kept : done;
    return l;
}

/* rs_produce_fn: shade the piece's instances that the cull keeps into the slot's scratch, one after the other,
 * and hand over the index list that covers them. */
static size_t fused_produce(void *ctx, size_t piece, int slot, rs_vertex **verts, size_t *n_verts,
                            const uint32_t **idx)
{
    fused_ctx *f = ctx;
    const fused_scratch *z = &f->dev->fz;
    uint32_t a = (uint32_t)piece * f->per_piece, n = f->ni - a < f->per_piece ? f->ni - a : f->per_piece;
    rs_vertex *out = z->v + (size_t)slot * z->v_slot;
    is_vs_input *in = z->in + (size_t)slot * z->in_slot;
    is_vs_grid *ws = z->grid ? &z->grid[slot] : NULL;
    is_vs_grid *grid = f->grid_room && z->grid_room >= f->grid_room ? ws : NULL;
    bool ready = z->tag[slot] == f->serial;   /* the slot's inputs were made for this record */
    uint32_t kept = 0;
    for (uint32_t i = 0; i < n; i++) {
        fetch_instance(f, f->i0 + a + i, in, &ready, &z->lay[slot], ws);
        is_patch_hull h;
        if (f->cull.on && f->vs->hull(&f->consts, in, &h) && cull_instance(&f->cull, &h)) {
#pragma omp atomic
            f->culled++;
            continue;
        }
        shade_instance(f, in, grid, out + (size_t)kept++ * f->count);
    }
    if (ready) z->tag[slot] = f->serial;
    *verts = out, *n_verts = (size_t)kept * f->count, *idx = slot_list(f, z, slot, kept);
    return (size_t)kept * (f->n_idx / 3);
}

/* Instances per piece: about 1/FUSED_PIECES of the draw (all of a small one), at most FUSED_PIECE_VERTICES
 * vertices and FUSED_PIECE_PRIMS triangles (the piece's index list), at least one instance.  A small draw (fewer
 * triangles than RS_PARALLEL_SETUP_MIN, raster.h) is set up by one thread, so its pieces are as large as those
 * limits allow: more pieces buy no balance there and each costs the rasterizer a pass over the tiles (binning,
 * and the tile pass's walk over the pieces: scene D's adaptive frames draw ~650 such draws). */
static uint32_t fused_per_piece(uint32_t n_inst, uint32_t count, size_t n_prims)
{
    uint64_t want = (uint64_t)n_inst * count / FUSED_PIECES;
    if ((uint64_t)n_inst * n_prims < RS_PARALLEL_SETUP_MIN) want = (uint64_t)n_inst * count;
    uint64_t per = want <= count ? 1u : want / count;
    if (per * count > FUSED_PIECE_VERTICES) per = FUSED_PIECE_VERTICES / count;
    if (per * n_prims > FUSED_PIECE_PRIMS) per = FUSED_PIECE_PRIMS / n_prims;
    return per < 1 ? 1u : (uint32_t)per;
}

/* Triangles off the reference path, at most FUSED_PIECE_VERTICES vertices per instance. */
bool draw_fused_takes(const is_device *dev, int prim, uint32_t count)
{
    return !dev->reference && prim == RS_PRIM_TRIANGLES && count <= FUSED_PIECE_VERTICES;
}

/* A free record of dev's scene with room for `bytes` of data (grown when smaller), counted in; NULL when out of
 * memory. */
static fused_rec *rec_take(dev_scene *sc, size_t bytes)
{
    if (sc->n == sc->cap) {
        size_t cap = sc->cap ? 2 * sc->cap : 64;
        fused_rec **r = realloc(sc->recs, cap * sizeof *r);
        if (!r) return NULL;
        memset(r + sc->cap, 0, (cap - sc->cap) * sizeof *r);
        sc->recs = r, sc->cap = cap;
    }
    fused_rec *r = sc->recs[sc->n];
    if (!r || r->bytes < bytes) {
        fused_rec *q = realloc(r, sizeof *q + bytes);
        if (!q) return NULL;
        q->bytes = bytes, sc->recs[sc->n] = r = q;
    }
    sc->n++;
    return r;
}

/* The layout (fused_layout) record f's pieces fill a slot's input registers with. */
static void layout_of(const fused_ctx *f, fused_layout *lay)
{
    const fetch_plan *fp = f->fp;
    memset(lay, 0, sizeof *lay);
    lay->valid = true, lay->per_call = f->vs->batch == NULL, lay->count = f->count, lay->n_vert = fp->n_vert;
    lay->grid_fn = f->vs->grid_batch;
    for (unsigned q = 0; q < fp->n_vert; q++) lay->vreg[q] = (uint8_t)(fp->el[fp->vert[q]].reg_offset / sizeof(float4));
    for (unsigned k = 0; k < fp->n; k++)
        if (fp->el[k].per_instance) lay->inst_regs |= 1u << (fp->el[k].reg_offset / sizeof(float4));
}

/* Record a pass of the draw (instances set by the caller): copies of the shader, constants, viewport map, fetch
 * plan, fetch cache (nc float4), instance 0's index list (3 n_prims) and cull; NULL when out of memory. */
static fused_ctx *fused_record(is_device *dev, const fetch_plan *fp, const float4 *cache, size_t nc,
                               const uint32_t *list, size_t n_prims, uint32_t first, uint32_t count,
                               uint32_t per_piece, const cull_view *cull)
{
    fused_rec *r = rec_take(&dev->scene, nc * sizeof(float4) + 3 * n_prims * sizeof(uint32_t));
    if (!r) return NULL;
    r->vs = *dev->vs, r->fp = *fp;
    memcpy(r->data, cache, nc * sizeof(float4));
    uint32_t *l0 = (uint32_t *)(r->data + nc);
    memcpy(l0, list, 3 * n_prims * sizeof *l0);
    fused_ctx *f = &r->f;
    f->dev = dev, f->fp = &r->fp, f->vs = &r->vs, f->consts = dev->consts, f->remap = dev->remap;
    f->first = first, f->count = count, f->i0 = 0, f->ni = 0, f->per_piece = per_piece;
    f->n_idx = 3 * n_prims, f->list0 = l0, f->slot_verts = (size_t)per_piece * count, f->cache = r->data;
    f->live = live_outputs(dev), f->cull = *cull, f->serial = ++dev->scene.serial, f->culled = 0;
    f->grid_room = r->vs.grid_batch && r->vs.grid_room ? r->vs.grid_room(count) : 0;
    layout_of(f, &f->lay);
    return f;
}

/* Grow dev's producer scratch to `slots` slots of what record f needs (a grown scratch forgets what its slots
 * held); IS_OK or IS_ERR_OUTOFMEMORY with nothing changed. */
static is_result fused_reserve(is_device *dev, int slots, const fused_ctx *f)
{
    fused_scratch *z = &dev->fz, n = *z;
    if (slots > n.slots) n.slots = slots;
    if (f->slot_verts > n.v_slot) n.v_slot = f->slot_verts;
    if (f->count > n.in_slot) n.in_slot = f->count;
    if ((size_t)f->per_piece * f->n_idx > n.list_slot) n.list_slot = (size_t)f->per_piece * f->n_idx;
    if (n.slots == z->slots && n.v_slot == z->v_slot && n.in_slot == z->in_slot && n.list_slot == z->list_slot)
        return IS_OK;
    const size_t ns = (size_t)n.slots;
    n.v = malloc(ns * n.v_slot * sizeof *n.v), n.in = malloc(ns * n.in_slot * sizeof *n.in);
    n.list = malloc(ns * n.list_slot * sizeof *n.list), n.lcount = calloc(ns, sizeof *n.lcount);
    n.tag = calloc(ns, sizeof *n.tag), n.ltag = calloc(ns, sizeof *n.ltag), n.lay = calloc(ns, sizeof *n.lay);
    if (!n.v || !n.in || !n.list || !n.lcount || !n.tag || !n.ltag || !n.lay) {
        free(n.v), free(n.in), free(n.list), free(n.lcount), free(n.tag), free(n.ltag), free(n.lay);
        return dev_fail(dev, IS_ERR_OUTOFMEMORY, "draw: out of memory for the shading scratch");
    }
    free(z->v), free(z->in), free(z->list), free(z->lcount), free(z->tag), free(z->ltag), free(z->lay);
    if (n.slots != z->slots) {   /* the grid workspaces are per slot: fused_reserve_grids makes them again */
        free(z->grid), free(z->grid_mem);
        n.grid = NULL, n.grid_mem = NULL, n.grid_room = 0;
    }
    *z = n;
    return IS_OK;
}

/* Grow dev's per-slot grid workspaces to what record f's shader asks (fused_reserve's slots); when memory is
 * short they stay as they were and f's pieces take the shader's plain batch (the same bytes). */
static void fused_reserve_grids(is_device *dev, const fused_ctx *f)
{
    fused_scratch *z = &dev->fz;
    if (!f->grid_room || (z->grid && f->grid_room <= z->grid_room)) return;
    const size_t ns = (size_t)z->slots, room = f->grid_room > z->grid_room ? f->grid_room : z->grid_room;
    is_vs_grid *g = malloc(ns * sizeof *g);
    unsigned char *mem = room && ns <= SIZE_MAX / room ? malloc(ns * room) : NULL;
    if (!g || !mem) {
        free(g), free(mem);
        return;
    }
    for (size_t k = 0; k < ns; k++) g[k] = (is_vs_grid){mem + k * room, room, false};
    free(z->grid), free(z->grid_mem);
    z->grid = g, z->grid_mem = mem, z->grid_room = room;
}

/* Mark the vertex buffers the draw about to be recorded reads (its declaration's streams) with the generation. */
static void mark_buffers(is_device *dev)
{
    for (unsigned k = 0; k < dev->decl->n; k++) {
        is_vertex_buffer *vb = dev->streams[dev->decl->el[k].e.stream].vb;
        if (vb) vb->scene_gen = dev->scene.gen;
    }
}

/* Record pass i0..i0+ni-1 of the draw and hand it to the rasterizer (which runs it at its next flush, or now when
 * the scene does not take it). */
static is_result fused_pass(is_device *dev, const fetch_plan *fp, const float4 *cache, const uint32_t *list,
                            size_t n_prims, uint32_t first, uint32_t count, uint32_t per_piece, const cull_view *cv,
                            uint32_t i0, uint32_t ni, int level, bool mirrored)
{
    fused_ctx *f = fused_record(dev, fp, cache, (size_t)count * fp->n_vert + 1, list, n_prims, first, count,
                                per_piece, cv);
    if (!f) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "draw: out of memory for the draw's record");
    f->i0 = i0, f->ni = ni;
    is_result r = fused_reserve(dev, rs_threads(dev->rs), f);
    if (r != IS_OK) return r;
    fused_reserve_grids(dev, f);
    /* each piece's triangles come in runs of n_prims, one per kept instance: the rasterizer bins them by instance;
     * when the instance list is the regular grid of `level` over the instance's `count` vertices (fused_produce
     * puts kept instance k's vertices at k * count), it may set them up from the grid's rows */
    rs_source src = {(ni + per_piece - 1) / per_piece, (size_t)ni * n_prims, f->slot_verts, fused_produce, f, n_prims,
                     (size_t)level, mirrored};
    rs_state st = dev_rs_state(dev);
    rs_stats s = {0};
    dev->shaded += (uint64_t)ni * count;   /* the instances culled are taken off at the flush */
    return draw_result(dev, rs_draw_source(dev->rs, &st, &dev->rt, &src, &s), &s);
}

/* The fused draw of n_prims triangles per instance (see above); list = instance 0's index list, compared once
 * per draw with the regular grid's, as it is or mirrored (core_grid_regular_level and _mirrored: 0 when it is
 * another list). */
is_result draw_fused(is_device *dev, const fetch_plan *fp, size_t n_prims, uint32_t first, uint32_t count,
                     const uint32_t *list)
{
    const uint32_t n_inst = fp->n_instances, per_piece = fused_per_piece(n_inst, count, n_prims);
    size_t max_pieces = rs_max_pieces(&dev->rt), per_pass = FUSED_MAX_PRIMS / n_prims;
    if (per_pass < per_piece) per_pass = per_piece;
    if (per_pass / per_piece > max_pieces) per_pass = max_pieces * per_piece;
    if (dev->scene.n >= FUSED_MAX_RECORDS) dev_scene_flush(dev);
    const float4 *cache = fetch_cache(dev, fp, first, count);
    if (!cache) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "draw: out of memory for the inputs");
    cull_view cv = {0};
    cull_prepare(dev, fp, cache, list, n_prims, &cv);
    mark_buffers(dev);
    int level = core_grid_regular_level(list, n_prims, count);
    const bool mirrored = !level && (level = core_grid_regular_level_mirrored(list, n_prims, count)) > 0;
    is_result r = IS_OK;
    for (uint32_t i0 = 0; r == IS_OK && i0 < n_inst; i0 += (uint32_t)per_pass)
        r = fused_pass(dev, fp, cache, list, n_prims, first, count, per_piece, &cv, i0,
                       n_inst - i0 < per_pass ? n_inst - i0 : (uint32_t)per_pass, level, mirrored);
    return r;
}

void dev_scene_flush(is_device *dev)
{
    dev_scene *sc = &dev->scene;
    rs_flush(dev->rs);
    const int e = rs_scene_error(dev->rs);
    if (e != RS_OK) {
        const rs_stats none = {0};
        is_result r = draw_result(dev, e, &none);
        dev_debug(dev, "a recorded draw was dropped when the frame's draws ran: %s", dev->err);
        if (sc->err == IS_OK) sc->err = r;
    }
    for (size_t k = 0; k < sc->n; k++) {
        const fused_ctx *f = &sc->recs[k]->f;
        dev->instances_culled += f->culled;
        dev->shaded -= f->culled * f->count;
    }
    sc->n = 0;
    sc->gen++;
}

bool dev_scene_reads(const is_device *dev, const is_vertex_buffer *vb)
{
    return dev->scene.n > 0 && vb->scene_gen == dev->scene.gen;
}

void dev_scene_free(is_device *dev)
{
    for (size_t k = 0; k < dev->scene.cap; k++) free(dev->scene.recs[k]);
    free(dev->scene.recs);
    fused_scratch *z = &dev->fz;
    free(z->v), free(z->in), free(z->list), free(z->lcount), free(z->tag), free(z->ltag), free(z->lay);
    free(z->grid), free(z->grid_mem);
    memset(&dev->scene, 0, sizeof dev->scene), memset(z, 0, sizeof *z);
}
