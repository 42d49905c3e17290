/* raster/draw.c -- the rasterizer context and rs_draw: validation, the per-draw job, parallel setup and
 * binning over chunks of primitives, then parallel rasterization over tiles (128 or 64 pixels square:
 * rs_tile_bits; a flush of the frame's recorded draws does both in one parallel region: rs_flush_fill).
 *
 * Determinism: chunk boundaries depend only on the primitive count and the target size, each chunk keeps its
 * primitives in submission order, and each tile (owned by one thread) walks the chunks in order and each bin
 * in order; so every sample sees the same operations in the same order for any thread count.
 */
#include <omp.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "raster_internal.h"

#define CHUNK_MIN 1024            /* input primitives per chunk, at least */
#define CHUNK_MAX_COUNT 256       /* chunks per draw, at most */
#define BIN_OFFSETS_BUDGET (1u << 22) /* chunks * (tiles + 1) bin offsets per draw, at most */

/* The kernel table: one row per instruction set (RS_ISA_*), each a copy of span.c and setup_simd.c compiled for
 * it (raster_internal.h, RS_KERNEL). */
#ifndef RS_NO_KERNELS
static const rs_kernels kernels[RS_ISA_COUNT] = {
    [RS_ISA_AVX2] = { "avx2", rs_tri_fast_avx2, rs_project_vertices_avx2, rs_project_vertex_avx2,
                      rs_setup_shared_avx2, rs_setup_groups_avx2, rs_group_tile_avx2 },
    [RS_ISA_AVX512] = { "avx512", rs_tri_fast_avx512, rs_project_vertices_avx512, rs_project_vertex_avx512,
                        rs_setup_shared_avx512, rs_setup_groups_avx512, rs_group_tile_avx512 },
};
#else /* the browser build: no kernels, the reference path only (raster_internal.h) */
static const rs_kernels kernels[RS_ISA_COUNT] = {[RS_ISA_AVX2] = {"none", NULL, NULL, NULL, NULL, NULL, NULL},
                                                 [RS_ISA_AVX512] = {"avx512", NULL, NULL, NULL, NULL, NULL, NULL}};
/* setup_simd.c's definition (sizeof(rs_pvert), asserted 24 there), for the scratch rs_draw_source reserves */
size_t rs_pvert_size(void) { return 24; }
#endif

const rs_kernels *rs_kernels_of(int isa) { return &kernels[isa >= 0 && isa < RS_ISA_COUNT ? isa : RS_ISA_AVX2]; }

bool rs_isa_supported(int isa)
{
    if (isa == RS_ISA_AVX2) return true; /* the build's own level: rs_span_ok decides what it can do */
#if defined(__x86_64__) && defined(__GNUC__)
    /* what -march=x86-64-v4 lets the compiler use (and the OS saves: __builtin_cpu_supports checks XCR0 too) */
    if (isa == RS_ISA_AVX512)
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
               __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
               __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx2") &&
               __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2");
#endif
    return false;
}

int rs_isa_best(void)
{
    for (int isa = RS_ISA_COUNT - 1; isa > RS_ISA_AVX2; isa--)
        if (rs_isa_supported(isa)) return isa;
    return RS_ISA_AVX2;
}

int rs_set_isa(rs_context *rs, int isa)
{
    if (!rs || !rs_isa_supported(isa)) return RS_EINVAL;
    rs->isa = isa;
    return RS_OK;
}

int rs_isa(const rs_context *rs) { return rs ? rs->isa : RS_ISA_AVX2; }

const char *rs_isa_name(int isa) { return isa >= 0 && isa < RS_ISA_COUNT ? kernels[isa].name : NULL; }

int rs_isa_parse(const char *name)
{
    for (int i = 0; name && i < RS_ISA_COUNT; i++)
        if (strcmp(name, kernels[i].name) == 0) return i;
    return -1;
}

rs_context *rs_create(int threads)
{
    rs_context *rs = calloc(1, sizeof *rs);
    if (!rs) return NULL;
    rs->threads = threads > 0 ? threads : 0;
    rs->isa = rs_isa_best();
    return rs;
}

void rs_destroy(rs_context *rs)
{
    if (!rs) return;
    for (size_t i = 0; i < rs->n_chunks_cap; i++) {
        rs_chunk *c = &rs->chunks[i];
        free(c->prims);
        free(c->ptile);
        free(c->attr);
        free(c->bin_off);
        free(c->bin_idx);
        free(c->gpv);
        free(c->gattr);
        free(c->gtri);
        free(c->gsoa);
        free(c->grow);
    }
    free(rs->chunks);
    free(rs->q);
    free(rs->tile_stats);
    free(rs->ranges);
    free(rs->range_own);
    free(rs->pv);
    free(rs->pend);
    free(rs->clean);
    free(rs->tbuf);
    free(rs);
}

void rs_set_reference_path(rs_context *rs, bool on)
{
    if (rs) rs->reference = on;
}

void rs_set_timing(rs_context *rs, bool on)
{
    if (rs) rs->timing = on;
}

/* Wall-clock milliseconds now when rs times its draws (rs_set_timing), else 0. */
static double phase_clock(const rs_context *rs)
{
    return rs->timing ? omp_get_wtime() * 1e3 : 0.0;
}

void rs_set_threads(rs_context *rs, int threads)
{
    if (!rs) return;
    rs_flush(rs);   /* the recorded draws' scratch is sized for the thread count they were recorded with */
    rs->threads = threads > 0 ? threads : 0;
}

/* Threads to use for a draw (0 in the context: all cores). */
static int thread_count(const rs_context *rs)
{
    int n = rs->threads > 0 ? rs->threads : omp_get_num_procs();
    return n > 0 ? n : 1;
}

/* Is f a comparison function (RS_CMP_*) and o a stencil operation (RS_STENCILOP_*)? */
static bool valid_cmp(int f) { return f >= RS_CMP_NEVER && f <= RS_CMP_ALWAYS; }
static bool valid_sop(int o) { return o >= RS_STENCILOP_KEEP && o <= RS_STENCILOP_DECR; }
static bool valid_face(const rs_stencil_ops *f)
{
    return valid_cmp(f->func) && valid_sop(f->fail) && valid_sop(f->zfail) && valid_sop(f->pass);
}

/* Are pixel.c's states (those on) valid: functions, operations, finite clip planes? */
static bool valid_ext_state(const rs_state *st)
{
    if (st->alpha_test && !valid_cmp(st->alpha_func)) return false;
    if (st->stencil_enable && (!valid_face(&st->stencil_cw) || (st->stencil_two_sided && !valid_face(&st->stencil_ccw))))
        return false;
    for (int i = 0; i < RS_MAX_CLIP_PLANES; i++)
        if ((st->clip_plane_enable >> i) & 1u)
            for (int c = 0; c < 4; c++)
                if (!isfinite(st->clip_plane[i][c])) return false;
    return true;
}

/* Are the render states and the viewport valid for target rt? */
static bool valid_state(const rs_state *st, const rs_target *rt)
{
    if (st->cull_mode < RS_CULL_NONE || st->cull_mode > RS_CULL_CCW) return false;
    if (st->fill_mode < RS_FILL_POINT || st->fill_mode > RS_FILL_SOLID) return false;
    if (st->shade_mode != RS_SHADE_FLAT && st->shade_mode != RS_SHADE_GOURAUD) return false;
    if (st->z_enable && (st->z_func < RS_CMP_NEVER || st->z_func > RS_CMP_ALWAYS)) return false;
    if (st->blend_enable && (st->src_blend < RS_BLEND_ZERO || st->src_blend > RS_BLEND_SRCALPHASAT ||
                             st->dst_blend < RS_BLEND_ZERO || st->dst_blend > RS_BLEND_SRCALPHASAT))
        return false;
    if (!isfinite(st->depth_bias) || !isfinite(st->slope_scale_depth_bias)) return false;
    if (!valid_ext_state(st)) return false;
    const rs_viewport *vp = &st->viewport;
    if (vp->x < 0 || vp->y < 0 || vp->width < 1 || vp->height < 1) return false;
    if (vp->width > rt->width - vp->x || vp->height > rt->height - vp->y) return false;
    return isfinite(vp->min_z) && isfinite(vp->max_z);
}

/* Do the primitive type, counts and indices describe vertices that exist? */
static bool valid_input(int prim, const rs_vertex *verts, size_t n_verts, const uint32_t *idx, size_t n_prims)
{
    if (prim != RS_PRIM_POINTS && prim != RS_PRIM_LINES && prim != RS_PRIM_TRIANGLES) return false;
    if (n_prims == 0) return true;
    size_t vpp = prim == RS_PRIM_TRIANGLES ? 3 : (prim == RS_PRIM_LINES ? 2 : 1);
    if (!verts || n_prims > SIZE_MAX / vpp / sizeof(rs_vertex)) return false;
    size_t n = n_prims * vpp;
    if (!idx) return n <= n_verts;
    for (size_t k = 0; k < n; k++)
        if (idx[k] >= n_verts) return false;
    return true;
}

/* Interpolated slots: those of attr_mask that are consumed (COLOR0 and the AOV planes' slots). */
static void job_slots(rs_job *j)
{
    const rs_state *st = j->st;
    uint32_t need = st->ps ? ~0u : 1u << RS_ATTR_COLOR0;   /* a pixel shader reads every slot written */
    for (int k = 0; k < j->rt->n_aov; k++) need |= 1u << j->rt->aov[k].slot;
    need &= st->attr_mask;
    j->n_slots = 0;
    int where[RS_MAX_ATTR];
    for (int k = 0; k < RS_MAX_ATTR; k++) {
        where[k] = -1;
        if (need & (1u << k)) { where[k] = j->n_slots; j->slot[j->n_slots++] = k; }
    }
    j->color_idx = where[RS_ATTR_COLOR0];
    for (int k = 0; k < RS_MAX_AOV; k++) j->aov_idx[k] = k < j->rt->n_aov ? where[j->rt->aov[k].slot] : -1;
    j->stride = j->n_slots * RS_ATTR_STRIDE;
}

/* Narrow the job's rectangle [sx0, sx1) x [sy0, sy1) to the scissor rectangle r (empty: sx1 = sx0, sy1 = sy0). */
static void job_scissor(rs_job *j, const rs_rect *r)
{
    j->sx0 = r->x0 > j->sx0 ? r->x0 : j->sx0, j->sy0 = r->y0 > j->sy0 ? r->y0 : j->sy0;
    j->sx1 = r->x1 < j->sx1 ? r->x1 : j->sx1, j->sy1 = r->y1 < j->sy1 ? r->y1 : j->sy1;
    if (j->sx1 < j->sx0 || j->sy1 < j->sy0) j->sx1 = j->sx0, j->sy1 = j->sy0;
}

/* Fill the per-draw constants of a draw on rs (its path and kernels too). */
static void make_job(rs_job *j, const rs_context *rs, const rs_state *st, rs_target *rt, int prim,
                     const rs_vertex *verts, const uint32_t *idx)
{
    static const int32_t pat[4][2] = { { -2, -6 }, { 6, -2 }, { -6, 2 }, { 2, 6 } }; /* 1/16 px */
    memset(j, 0, sizeof *j);
    j->reference = rs->reference || RS_ONLY_REFERENCE;   /* (without kernels, always) */
    j->kern = rs_kernels_of(rs->isa);
    j->st = st;
    j->rt = rt;
    j->prim = prim;
    j->verts = verts;
    j->idx = idx;
    j->samples = rt->samples;
    bool ms = rt->samples == 4 && st->multisample;
    for (int s = 0; s < 4; s++) {
        j->sox[s] = ms ? pat[s][0] * (RS_SUB / 16) : 0;
        j->soy[s] = ms ? pat[s][1] * (RS_SUB / 16) : 0;
    }
    j->omax = ms ? 6 * (RS_SUB / 16) : 0;
    const rs_viewport *vp = &st->viewport;
    j->sx0 = vp->x; j->sy0 = vp->y; j->sx1 = vp->x + vp->width; j->sy1 = vp->y + vp->height;
    if (st->scissor_enable) job_scissor(j, &st->scissor);
    j->cx = (int64_t)vp->x * RS_SUB + (int64_t)vp->width * (RS_SUB / 2);
    j->cy = (int64_t)vp->y * RS_SUB + (int64_t)vp->height * (RS_SUB / 2);
    j->sx_scale = (double)vp->width * (RS_SUB / 2);
    j->sy_scale = -(double)vp->height * (RS_SUB / 2);
    j->gx = ((double)RS_GUARD_BAND - 1.0) / (vp->width * 0.5);
    j->gy = ((double)RS_GUARD_BAND - 1.0) / (vp->height * 0.5);
    j->zoff = vp->min_z;
    j->zscale = vp->max_z - vp->min_z;
    j->zlo = vp->min_z < vp->max_z ? vp->min_z : vp->max_z;
    j->zhi = vp->min_z < vp->max_z ? vp->max_z : vp->min_z;
    j->ext = rs_state_ext(st, rt);
    j->reference |= j->ext;   /* pixel.c's states live on the reference path only */
    j->walk4 = !rs->reference && !j->ext && rt->samples == 4 && !st->blend_enable && rt->n_aov == 0;
    j->clip_mask = rs_clip_mask(st);
    if (st->pretransformed) { /* screen pixels: x/w and y/w are pixels from the centre, depth is z/w itself */
        j->sx_scale = j->sy_scale = RS_SUB;
        j->gx = j->gy = (double)RS_GUARD_BAND - 1.0;
        j->zoff = 0.0f, j->zscale = 1.0f, j->zlo = 0.0f, j->zhi = 1.0f;
    }
    j->flat = st->shade_mode == RS_SHADE_FLAT;
    j->span_mode = rs_span_mode(st, rt);
    j->tile_bits = rs_tile_bits(rt);
    j->tiles_x = rs_tiles_across(rt->width, j->tile_bits);
    j->tiles_y = rs_tiles_across(rt->height, j->tile_bits);
    j->n_tiles = j->tiles_x * j->tiles_y;
    job_slots(j);
}

/* Make room for n chunks (growing at least twofold: the frame's scene adds a draw's chunks at a time) and the
 * tile counters; false when out of memory. */
static bool reserve_context(rs_context *rs, size_t n, size_t n_tiles)
{
    if (n > rs->n_chunks_cap) {
        if (n < 2 * rs->n_chunks_cap) n = 2 * rs->n_chunks_cap;
        rs_chunk *c = aligned_alloc(_Alignof(rs_chunk), n * sizeof *c);
        if (!c) return false;
        if (rs->n_chunks_cap) memcpy(c, rs->chunks, rs->n_chunks_cap * sizeof *c);
        memset(c + rs->n_chunks_cap, 0, (n - rs->n_chunks_cap) * sizeof *c);
        free(rs->chunks);
        rs->chunks = c;
        rs->n_chunks_cap = n;
    }
    if (2 * n_tiles > rs->tile_stats_cap) {
        uint64_t *s = realloc(rs->tile_stats, 2 * n_tiles * sizeof *s);
        if (!s) return false;
        rs->tile_stats = s;
        rs->tile_stats_cap = 2 * n_tiles;
    }
    return true;
}

int rs_threads(const rs_context *rs) { return rs ? thread_count(rs) : 1; }

size_t rs_max_pieces(const rs_target *rt)
{
    if (!rs_target_valid(rt)) return 0;
    const int b = rs_tile_bits(rt);
    size_t tiles = (size_t)rs_tiles_across(rt->width, b) * (size_t)rs_tiles_across(rt->height, b);
    size_t cap = BIN_OFFSETS_BUDGET / (tiles + 1);
    return cap < 1 ? 1 : (cap > CHUNK_MAX_COUNT ? CHUNK_MAX_COUNT : cap);
}

/* Number of chunks for n primitives on a target of n_tiles tiles. */
static size_t chunk_count(size_t n, size_t n_tiles)
{
    size_t c = (n + CHUNK_MIN - 1) / CHUNK_MIN;
    size_t cap = BIN_OFFSETS_BUDGET / (n_tiles + 1);
    cap = cap < 1 ? 1 : (cap > CHUNK_MAX_COUNT ? CHUNK_MAX_COUNT : cap);
    return c < 1 ? 1 : (c > cap ? cap : c);
}

/* Largest vertex count of the shared projection pass (bounds its scratch memory). */
#define SHARED_PASS_MAX_VERTICES (1u << 22)

/* The shared pass of indexed triangle draws on the fast path: project every vertex once (in parallel) into the
 * context's scratch and point the job at it.  Left off (j->pv NULL) on the reference path, when a vertex is used
 * about once, when the scratch would be large, or when out of memory (the per-triangle setup gives the same). */
static void shared_pass(rs_context *rs, rs_job *j, size_t n_verts, size_t n_prims, int nt)
{
    if (j->reference || j->prim != RS_PRIM_TRIANGLES || !j->idx || n_verts > 3 * n_prims ||
        n_verts > SHARED_PASS_MAX_VERTICES)
        return;
    if (n_verts > rs->pv_cap) {
        void *p = realloc(rs->pv, n_verts * rs_pvert_size());
        if (!p) return;
        rs->pv = p, rs->pv_cap = n_verts;
    }
    rs_pvert *pv = rs->pv;
    const size_t block = 4096;
    long nb = (long)((n_verts + block - 1) / block);
#pragma omp parallel for schedule(dynamic, 1) num_threads(nt) if (nb >= 2)
    for (long b = 0; b < nb; b++) {
        size_t v0 = (size_t)b * block, n = n_verts - v0 < block ? n_verts - v0 : block;
        j->kern->project_vertices(j, j->verts + v0, n, (rs_pvert *)((char *)pv + v0 * rs_pvert_size()));
    }
    j->pv = pv;
}

/* Make room for `slots` projection scratches of n vertices each; false when out of memory. */
static bool reserve_pv(rs_context *rs, size_t slots, size_t n)
{
    if (n && slots > SIZE_MAX / rs_pvert_size() / n) return false;
    if (slots * n <= rs->pv_cap) return true;
    void *p = realloc(rs->pv, slots * n * rs_pvert_size());
    if (!p) return false;
    rs->pv = p, rs->pv_cap = slots * n;
    return true;
}

/* The largest of idx[0..n), n > 0: eight running maxima without an early exit, which the compiler turns into
 * vector instructions (every piece's indices are checked: a branch per index cost 3 % of scene B's frame). */
static uint32_t max_index(const uint32_t *idx, size_t n)
{
    uint32_t m[8] = {0};
    size_t k = 0;
    for (; k + 8 <= n; k += 8)
        for (int l = 0; l < 8; l++) m[l] = idx[k + l] > m[l] ? idx[k + l] : m[l];
    for (; k < n; k++) m[0] = idx[k] > m[0] ? idx[k] : m[0];
    for (int l = 1; l < 8; l++) m[0] = m[l] > m[0] ? m[l] : m[0];
    return m[0];
}

/* Whether a produced piece keeps the source's promise: vertices (at most max_verts) and 3 * np indices, each
 * naming one of them. */
static bool piece_ok(const rs_source *src, const rs_vertex *v, size_t nv, const uint32_t *idx, size_t np)
{
    if (!v || !idx || nv > src->max_verts || np > SIZE_MAX / 3) return false;
    return np == 0 || max_index(idx, 3 * np) < nv;
}

/* Chunk ch's projected vertices of a grouped piece made to hold n records; false when out of memory. */
static bool reserve_gpv(rs_chunk *ch, size_t n) { return rs_reserve(&ch->gpv, &ch->gpv_cap, n, rs_pvert_size()); }

/* Produce piece c of src on the calling thread and set it up into chunk ch: shade (the producer), project each
 * vertex once (as the shared pass, into the slot's pv_slot vertices of rs->pv), set up and bin.  A piece of a
 * source with group_prims that may be grouped (rs_group_ok; every vertex inside the clip volume) is projected by
 * rs_setup_groups into the chunk's own records (or a grid piece's rows) instead and binned by groups. */
static void source_chunk(const rs_job *j, rs_context *rs, const rs_source *src, size_t c, rs_chunk *ch, int slot,
                         size_t pv_slot)
{
    rs_vertex *v = NULL;
    size_t nv = 0;
    const uint32_t *idx = NULL;
    size_t np = src->produce(src->ctx, c, slot, &v, &nv, &idx);
    ch->bad_piece = np && !piece_ok(src, v, nv, idx, np);
    if (ch->bad_piece) np = 0;   /* set up nothing of it: the draw fails (RS_EINVAL) */
    rs_job jl = *j;
    jl.verts = v, jl.idx = idx, jl.pv = NULL;
    ch->first = 0, ch->count = np, ch->grid_groups = ch->grid_direct = 0;
    if (np && nv <= src->max_verts && !j->reference) {
        const bool grouped = src->group_prims && rs_group_ok(j) && reserve_gpv(ch, nv);
        if (grouped || nv <= 3 * np) {
            rs_pvert *pv = grouped ? ch->gpv : (rs_pvert *)((char *)rs->pv + (size_t)slot * pv_slot * rs_pvert_size());
            if (!grouped) jl.kern->project_vertices(&jl, v, nv, pv);   /* (a grouped piece's: setup_groups') */
            jl.pv = pv;
        }
        if (grouped && jl.kern->setup_groups(&jl, ch, v, nv, idx, np, src->group_prims, src->grid_level)) {
            rs_bin_chunk(&jl, ch);
            return;
        }
    }
    rs_setup_chunk(&jl, ch);
    rs_bin_chunk(&jl, ch);
}

/* Does any of draws d[0..nd) bin a primitive to tile `tile`? */
static bool tile_has_prims(const rs_context *rs, const rs_scene_draw *d, size_t nd, int tile)
{
    for (size_t k = 0; k < nd; k++)
        for (size_t c = d[k].c0; c < d[k].c0 + d[k].nc; c++)
            if (rs->chunks[c].bin_off[tile + 1] > rs->chunks[c].bin_off[tile]) return true;
    return false;
}

/* Bin entries between a primitive's prefetch and its rasterization. */
#define PREFETCH_AHEAD 4

/* Start loading primitive i of chunk ch and its attribute block into the cache (the tile pass reads primitives
 * that were set up long before, in bin order: a gather the hardware prefetcher does not foresee). */
static inline void prefetch_prim(const rs_job *j, const rs_chunk *ch, uint32_t i)
{
    const char *p = (const char *)&ch->prims[i];
    __builtin_prefetch(p);
    __builtin_prefetch(p + 64);
    __builtin_prefetch(p + sizeof(rs_prim) - 1);
    __builtin_prefetch(ch->attr + (size_t)i * (size_t)j->stride);
}

/* Rasterize draw d's bins of the tile t is set up for (its rectangle narrowed to d's viewport and scissor). */
static void raster_tile_draw(const rs_context *rs, const rs_scene_draw *d, int tile, rs_tile *t)
{
    const rs_job *j = &d->j;
    const int ts = 1 << j->tile_bits, tx = tile % j->tiles_x * ts, ty = tile / j->tiles_x * ts;
    t->x0 = tx > j->sx0 ? tx : j->sx0;
    t->y0 = ty > j->sy0 ? ty : j->sy0;
    t->x1 = tx + ts < j->sx1 ? tx + ts : j->sx1;
    t->y1 = ty + ts < j->sy1 ? ty + ts : j->sy1;
    for (size_t c = d->c0; c < d->c0 + d->nc && t->x0 < t->x1 && t->y0 < t->y1; c++) {
        const rs_chunk *ch = &rs->chunks[c];
        for (uint32_t k = ch->bin_off[tile], end = ch->bin_off[tile + 1]; k < end; k++) {
            if (k + PREFETCH_AHEAD < end) prefetch_prim(j, ch, ch->bin_idx[k + PREFETCH_AHEAD]);
            uint32_t i = ch->bin_idx[k];
            const rs_prim *p = &ch->prims[i];
            const float *a = ch->attr + (size_t)i * (size_t)j->stride;
            if (p->kind == RS_K_TRI) rs_tri_tile(j, t, p, a);
            else if (p->kind == RS_K_GROUP) j->kern->group_tile(j, t, ch, p);
            else if (p->kind == RS_K_LINE) rs_line_tile(j, t, p, a);
            else rs_point_tile(j, t, p, a);
        }
    }
}

/* Rasterize tile `tile`: draws d[0..nd) (one target) one after the other, each chunk's bin of it in submission
 * order; counters into ts[0..2).  buf: the thread's tile buffer (used when the tile's clear is deferred: every
 * draw of the tile then draws in it) or NULL (the tile is drawn in the target).  A tile no draw touches gets the
 * deferred clear of the planes `fill` (RS_CLEAR_*; 0: none); with RS_DISCARD_DEPTH in `fill` a drawn tile whose
 * depth clear is deferred keeps it deferred (rs_target_flush_planes). */
static void raster_tile(const rs_context *rs, const rs_scene_draw *d, size_t nd, int tile, uint64_t *ts, void *buf,
                        unsigned fill)
{
    const rs_job *j = &d[0].j;
    rs_tile t;
    t.tested = t.written = 0;
    t.color = j->rt->color, t.depth = j->rt->depth;
    t.ox = t.oy = 0, t.pitch = (size_t)j->rt->width;
    bool has = tile_has_prims(rs, d, nd, tile);
    /* RS_DISCARD_DEPTH: the depth is not copied out where its clear is deferred (rs_target_flush_planes then defers
     * it again: tiles drawn in the target too) */
    const unsigned keep = has && (fill & RS_DISCARD_DEPTH) ? rs_tile_pending(rs, j, tile) & RS_CLEAR_DEPTH : 0u;
    bool buffered = has && rs_tile_buffer_begin(rs, j, tile, &t, buf);
    if (has && !buffered) rs_tile_flush(rs, j, tile, RS_CLEAR_COLOR | RS_CLEAR_DEPTH);
    if (has) rs_tile_drawn(rs, j, tile);   /* (after the tile's fill in the target, which marks it) */
    const unsigned fp = fill & (RS_CLEAR_COLOR | RS_CLEAR_DEPTH);
    if (!has && fp) rs_tile_flush(rs, j, tile, fp);
    for (size_t k = 0; has && k < nd; k++) raster_tile_draw(rs, &d[k], tile, &t);
    if (buffered) rs_tile_buffer_end(rs, j, tile, &t, keep);
    ts[0] = t.tested;
    ts[1] = t.written;
}

/* One tile buffer per thread (32-byte aligned) in rs->tbuf; NULL when out of memory (the tiles are then drawn in
 * the target directly, the same bytes). */
static void *tile_buffers(rs_context *rs, const rs_job *j, int nt)
{
    size_t need = (size_t)nt * rs_tile_buffer_size(j);
    if (need > rs->tbuf_cap) {
        free(rs->tbuf);
        rs->tbuf = aligned_alloc(64, need);
        rs->tbuf_cap = rs->tbuf ? need : 0;
    }
    return rs->tbuf;
}

/* The counters of chunks c0..c0+n_chunks-1 (prims_*) into *stats, the rest zero. */
static void gather_chunk_stats(const rs_context *rs, size_t c0, size_t n_chunks, size_t n_prims, rs_stats *stats)
{
    memset(stats, 0, sizeof *stats);
    stats->prims_in = n_prims;
    for (size_t c = c0; c < c0 + n_chunks; c++) {
        const rs_chunk *ch = &rs->chunks[c];
        stats->prims_culled += ch->culled;
        stats->prims_clipped_away += ch->clipped;
        stats->prims_degenerate += ch->degenerate;
        stats->prims_drawn += ch->drawn;
    }
}

/* Sum the counters of chunks c0..c0+n_chunks-1 and of the tiles into *stats. */
static void gather_stats(const rs_job *j, const rs_context *rs, size_t c0, size_t n_chunks, size_t n_prims,
                         rs_stats *stats)
{
    gather_chunk_stats(rs, c0, n_chunks, n_prims, stats);
    for (int t = 0; t < j->n_tiles; t++) {
        stats->samples_tested += rs->tile_stats[2 * (size_t)t];
        stats->samples_written += rs->tile_stats[2 * (size_t)t + 1];
    }
}

/* Add the work of set-up chunks c0..c0+n_chunks-1 to the frame's; false (and the frame's work unchanged) when it
 * would pass RS_MAX_OVERDRAW times the scissor's pixels. */
static bool add_work(rs_context *rs, const rs_job *j, size_t c0, size_t n_chunks)
{
    uint64_t w = 0;
    for (size_t c = c0; c < c0 + n_chunks; c++) w = w + rs->chunks[c].work < w ? UINT64_MAX : w + rs->chunks[c].work;
    uint64_t px = (uint64_t)RS_MAX_OVERDRAW * (uint64_t)(j->sx1 - j->sx0) * (uint64_t)(j->sy1 - j->sy0);
    uint64_t limit = (px > RS_MIN_WORK ? px : RS_MIN_WORK) * RS_WORK_UNIT;
    if (!rs->frame) rs->work = 0;   /* no frame started: each draw counts alone */
    if (w > limit || rs->work > limit - w) return false;
    rs->work += w;
    return true;
}

/* A thread's range of a flush's work (pieces to set up, or tiles): items lo..lo+n-1, taken from the front by their
 * owner and from the back by a thread done with its own (fb: the front's count in the low 32 bits, the back's in the
 * high 32: one atomic add takes an item from either end and sees both counts, so none is taken twice or missed).
 * Each range in its own cache line.  Why ranges and not one counter: the per-tile bytes a tile's thread reads and
 * writes (pend, clean, tile_stats) then lie in lines only that thread touches until the threads meet, where with
 * one counter the two threads drew neighbouring tiles and passed those lines and the counter back and forth (~150 ns
 * a round trip between this VM's two vCPUs); and a thread's pieces are neighbours in the draw, often on screen too,
 * so that plan_assign can give it the tiles they fall in. */
typedef struct rs_range {
    _Alignas(64) atomic_ullong fb;
    int lo, n;
} rs_range;

/* The next item of range r, from its front (the owner) or its back (another thread); -1 when none is left. */
static int range_take(rs_range *r, bool back)
{
    const unsigned long long old = atomic_fetch_add_explicit(&r->fb, back ? 1ull << 32 : 1ull, memory_order_relaxed);
    const unsigned long long f = old & 0xffffffffull, b = old >> 32;
    if (f + b >= (unsigned long long)r->n) return -1;
    return back ? r->lo + r->n - 1 - (int)b : r->lo + (int)f;
}

/* n items split over nt threads: ranges rg[0..nr), and own[0..nt), the range each thread owns (-1: none; NULL:
 * thread i owns range i below nr); one range holds every item when the ranges could not be allocated. */
typedef struct range_plan {
    rs_range *rg;
    int nr, nt;
    int *own;
    rs_range one;
} range_plan;

/* Room in rs for two plans of nt threads (ranges: tiles at 0, pieces at nt; owners of the tiles); false when out of
 * memory (the plans then take one range each). */
static bool plan_room(rs_context *rs, int nt)
{
    if ((size_t)nt > rs->ranges_cap) {
        free(rs->ranges), free(rs->range_own);
        rs->ranges = aligned_alloc(64, 2 * (size_t)nt * sizeof *rs->ranges);
        rs->range_own = malloc((size_t)nt * sizeof *rs->range_own);
        rs->ranges_cap = rs->ranges && rs->range_own ? (size_t)nt : 0;
    }
    return rs->ranges_cap >= (size_t)nt;
}

/* Plan p of n items on nt threads in the ranges at store (room for nt; NULL: one range), thread i owning range i;
 * own: room for nt owners (NULL: thread i owns range i, never reassigned). */
static void plan_make(range_plan *p, rs_range *store, int *own, int n, int nt)
{
    const int nr = nt < n ? nt : n;
    p->rg = nr > 1 && store ? store : &p->one;
    p->nr = p->rg == &p->one ? 1 : nr;
    p->nt = nt;
    p->own = p->rg == &p->one ? NULL : own;
    for (int i = 0; p->own && i < nt; i++) p->own[i] = i < p->nr ? i : -1;
    for (int r = 0; r < p->nr; r++) {
        atomic_init(&p->rg[r].fb, 0);
        p->rg[r].lo = (int)((int64_t)n * r / p->nr);
        p->rg[r].n = (int)((int64_t)n * (r + 1) / p->nr) - p->rg[r].lo;
    }
}

/* The next item of plan p for thread me: from its own range's front, then from the others' backs (*k: where it is
 * in that order, 0 at the start); -1 when none is left anywhere. */
static int plan_next(range_plan *p, int me, int *k)
{
    const int own = p->own ? (me < p->nt ? p->own[me] : -1) : (me < p->nr ? me : -1);
    for (; *k < p->nr; ++*k) {   /* (a team larger than the ranges: the others only take from the backs) */
        const int t = range_take(&p->rg[((own >= 0 ? own : me) + *k) % p->nr], own < 0 || *k > 0);
        if (t >= 0) return t;
    }
    return -1;
}

/* Largest team plan_assign weighs (larger ones keep thread i on range i). */
#define PLAN_ASSIGN_MAX 16

/* After the set-up of the recorded draws d[0..nd): the tile plan p's ranges to the threads whose chunks put the most
 * bin entries in them (greedy, the largest weight first), so that a thread rasterizes first what its own set-up
 * wrote, still in its caches.  Only which thread draws a tile changes, never the bytes. */
static void plan_assign(const rs_context *rs, range_plan *p, const rs_scene_draw *d, size_t nd)
{
    if (p->nr < 2 || !p->own || p->nt > PLAN_ASSIGN_MAX) return;
    uint64_t w[PLAN_ASSIGN_MAX][PLAN_ASSIGN_MAX] = {{0}};   /* [thread][range]: bin entries */
    for (size_t k = 0; k < nd; k++)
        for (size_t c = d[k].c0; c < d[k].c0 + d[k].nc; c++) {
            const rs_chunk *ch = &rs->chunks[c];
            if (ch->setup_thread < 0 || ch->setup_thread >= p->nt) continue;
            for (int r = 0; r < p->nr; r++)
                w[ch->setup_thread][r] += ch->bin_off[p->rg[r].lo + p->rg[r].n] - ch->bin_off[p->rg[r].lo];
        }
    unsigned taken_t = 0, taken_r = 0;
    for (int i = 0; i < p->nt; i++) p->own[i] = -1;
    for (int a = 0; a < p->nr; a++) {   /* nr <= nt: every range gets an owner */
        int bt = -1, br = -1;
        for (int t = 0; t < p->nt; t++)
            for (int r = 0; r < p->nr; r++)
                if (!(taken_t >> t & 1u) && !(taken_r >> r & 1u) && (bt < 0 || w[t][r] > w[bt][br])) bt = t, br = r;
        p->own[bt] = br, taken_t |= 1u << bt, taken_r |= 1u << br;
    }
}

/* Thread me's part of a tile pass of plan p over draws d[0..nd): each tile it takes rasterized (raster_tile, with
 * tile buffer buf). */
static void plan_tiles(const rs_context *rs, range_plan *p, int me, const rs_scene_draw *d, size_t nd, void *buf,
                       unsigned fill)
{
    for (int k = 0, t; (t = plan_next(p, me, &k)) >= 0;)
        raster_tile(rs, d, nd, t, rs->tile_stats + 2 * (size_t)t, buf, fill);
}

/* Rasterize every tile in parallel for draws d[0..nd) (one target, the same tiles), the tiles they do not touch
 * filled with the deferred clear of planes `fill`; the tiles' counters in rs->tile_stats; returns the region's ms
 * (rs_set_timing). */
static double raster_scene(rs_context *rs, const rs_scene_draw *d, size_t nd, int nt, unsigned fill)
{
    const rs_job *j = &d[0].j;
    int ntl = j->n_tiles;
    /* the reference path draws in the target, so that the tests compare the tile buffers and their copy-out
     * against it */
    char *bufs = j->reference ? NULL : tile_buffers(rs, j, nt);
    const size_t bsz = rs_tile_buffer_size(j);
    range_plan p;
    const bool room = plan_room(rs, nt);
    plan_make(&p, room ? rs->ranges : NULL, NULL, ntl, nt);
    const double t0 = phase_clock(rs);
#pragma omp parallel num_threads(nt)
    {
        const int me = omp_get_thread_num();
        plan_tiles(rs, &p, me, d, nd, bufs ? bufs + (size_t)me * bsz : NULL, fill);
    }
    return phase_clock(rs) - t0;
}

/* Rasterize every tile for the draw j of chunks rs->chunks[0..n_chunks) now, then sum the counters and the phase
 * times (setup_ms: the first half's) into *stats (the second half of a draw). */
static void raster_tiles(const rs_job *j, rs_context *rs, size_t n_chunks, size_t n_prims, int nt, double setup_ms,
                         rs_stats *stats)
{
    rs_scene_draw d;
    d.j = *j, d.c0 = 0, d.nc = n_chunks;
    const double tile_ms = raster_scene(rs, &d, 1, nt, 0);
    if (!stats) return;
    gather_stats(j, rs, 0, n_chunks, n_prims, stats);
    stats->setup_ms = setup_ms, stats->tile_ms = tile_ms;
    stats->setup_regions = stats->tile_regions = rs->timing;   /* counted with timing on */
}

/* ------------------------------ the frame's scene (rs_set_scene) ------------------------------ */

/* Set-up triangles the queue holds at most before a draw flushes it (each costs ~150 bytes of set-up records
 * written by the set-up and read back by the tile pass: 2^18 is ~40 MB). */
#define SCENE_MAX_PRIMS (1u << 18)

/* Check recorded draw d after the set-up (its pieces' promises, memory, the frame's work, in submission order)
 * and add its prims_* to the sink; a failing draw is dropped (nc = 0: the tile pass skips it) and the context
 * keeps the first error. */
static void scene_check(rs_context *rs, rs_scene_draw *d)
{
    int e = RS_OK;
    size_t n_prims = 0;
    for (size_t c = d->c0; c < d->c0 + d->nc; c++) {
        if (rs->chunks[c].bad_piece && e == RS_OK) e = RS_EINVAL;
        if (rs->chunks[c].oom && e == RS_OK) e = RS_ENOMEM;
        n_prims += rs->chunks[c].count;
    }
    if (e == RS_OK && n_prims > d->src.n_prims) e = RS_EINVAL;
    if (e == RS_OK && !add_work(rs, &d->j, d->c0, d->nc)) e = RS_EWORK;
    if (e != RS_OK) {
        if (rs->scene_err == RS_OK) rs->scene_err = e;
        d->nc = 0;
        return;
    }
    rs_stats s;
    gather_chunk_stats(rs, d->c0, d->nc, n_prims, &s);
    rs_stats *k = rs->sink;
    k->prims_in += s.prims_in, k->prims_culled += s.prims_culled, k->prims_clipped_away += s.prims_clipped_away;
    k->prims_degenerate += s.prims_degenerate, k->prims_drawn += s.prims_drawn;
}

void rs_flush(rs_context *rs) { rs_flush_fill(rs, NULL, 0); }

/* Return once *flag is set (acquire): a short busy wait with pause, then yielding the core.  A thread of the
 * flush's region waits so for another's last piece or tile without sleeping in the kernel -- where libgomp's
 * passive waiting puts it at a region's end, and waking it costs tens of microseconds on a virtual machine (an
 * empty region after 0.5 ms of serial work: ~74 us passive, ~12 us active, 2-core AMD EPYC VM) -- and without
 * holding for long a core another process wants. */
static void wait_flag(atomic_int *flag)
{
    for (unsigned i = 0; !atomic_load_explicit(flag, memory_order_acquire); i++) {
#ifdef _OPENMP
        if (i < 4096) {
#if defined(__x86_64__) || defined(__i386__)
            __builtin_ia32_pause();
#endif
        } else
            sched_yield();
#endif
    }
}

/* The shared state of a flush's region: the next piece to set up and the pieces done, the tile pass's start
 * (released: set after the serial middle by the thread that finished the last piece), the tile pass's plan, and the
 * threads done with the tiles (all_done: set by the last of them). */
typedef struct flush_sync {
    atomic_long chunks_done;
    atomic_int released, done, all_done;
    range_plan pieces;     /* the set-up's ranges of pieces (chunks) */
    range_plan tiles;      /* the tile pass's ranges (their owners set by flush_middle: plan_assign) */
    char *bufs;            /* the threads' tile buffers (NULL: the target) */
    double t_mid;          /* when the set-up ended (phase_clock) */
} flush_sync;

/* The serial middle of a flush, run by the thread that finished the last piece: the set-up's end time noted, each
 * recorded draw checked in submission order (scene_check), the tile buffers of nt threads made, then the tile pass
 * released. */
static void flush_middle(rs_context *rs, int nt, flush_sync *f)
{
    f->t_mid = phase_clock(rs);
    for (size_t k = 0; k < rs->q_n; k++) scene_check(rs, &rs->q[k]);
    plan_assign(rs, &f->tiles, rs->q, rs->q_n);
    f->bufs = rs->q[0].j.reference ? NULL : tile_buffers(rs, &rs->q[0].j, nt);
    atomic_store_explicit(&f->released, 1, memory_order_release);
}

/* One thread's part of a flush (nt: the team's size): pieces of the recorded draws set up, each into its own
 * chunk, from the thread's range of pieces, then from the others' backs (all threads when par, else thread 0
 * alone); once the last piece is done and flush_middle has run, tiles taken one at a time the same way from the
 * tile ranges and rasterized for every recorded draw (raster_tile); then a wait for the others' last tiles, so
 * that the region's own end finds every thread there and none sleeps.  A thread that wakes late finds its pieces
 * taken by the others and goes to the tiles: nobody waits for it. */
static void flush_thread(rs_context *rs, flush_sync *f, int nt, bool par, unsigned fill)
{
    const int me = omp_get_thread_num();
    const long nc = (long)rs->q_chunks;
    if (par || me == 0)
        for (int k = 0, c; (c = plan_next(&f->pieces, par ? me : 0, &k)) >= 0;) {
            rs_chunk *ch = &rs->chunks[c];
            const rs_scene_draw *d = &rs->q[ch->draw];
            ch->setup_thread = me;
            source_chunk(&d->j, rs, &d->src, ch->piece, ch, me, rs->q_max_verts);
            if (atomic_fetch_add_explicit(&f->chunks_done, 1, memory_order_acq_rel) == nc - 1)
                flush_middle(rs, nt, f);   /* the last piece done: the middle, by whoever did it */
        }
    if (nc == 0 && me == 0) flush_middle(rs, nt, f);
    wait_flag(&f->released);
    const size_t bsz = rs_tile_buffer_size(&rs->q[0].j);
    char *buf = f->bufs ? f->bufs + (size_t)me * bsz : NULL;
    plan_tiles(rs, &f->tiles, me, rs->q, rs->q_n, buf, fill);
    if (atomic_fetch_add_explicit(&f->done, 1, memory_order_acq_rel) == nt - 1)
        atomic_store_explicit(&f->all_done, 1, memory_order_release);
    else
        wait_flag(&f->all_done);
}

/* One parallel region for the whole flush (the set-up of every recorded draw, then the tile pass), the threads
 * passing from one to the other by flush_thread's own barrier rather than by two regions' ends and starts. */
void rs_flush_fill(rs_context *rs, const rs_target *rt, unsigned planes)
{
    if (!rs || rs->q_n == 0) return;
    for (size_t k = 0; k < rs->q_n; k++) rs->q[k].j.st = &rs->q[k].st;   /* the queue may have moved */
    const int nt = thread_count(rs);
    rs_stats *s = rs->sink;   /* set while draws are recorded (rs_set_scene flushes before it changes) */
    const unsigned fill = rt == rs->q_rt && rt->color == rs->q_color ? planes : 0;
    const bool par = rs->q_chunks > 1 && rs->q_prims >= RS_PARALLEL_SETUP_MIN;
    flush_sync f;
    atomic_init(&f.chunks_done, 0);
    atomic_init(&f.released, 0), atomic_init(&f.done, 0), atomic_init(&f.all_done, 0);
    const bool room = plan_room(rs, nt);
    plan_make(&f.pieces, room ? rs->ranges + nt : NULL, NULL, (int)rs->q_chunks, nt);
    plan_make(&f.tiles, room ? rs->ranges : NULL, rs->range_own, rs->q[0].j.n_tiles, nt);
    f.bufs = NULL, f.t_mid = 0.0;
    const double t0 = phase_clock(rs);
#pragma omp parallel num_threads(nt)
    flush_thread(rs, &f, omp_get_num_threads(), par, fill);
    const double t1 = phase_clock(rs);
    const int ntl = rs->q[0].j.n_tiles;
    for (int t = 0; t < ntl; t++) {
        s->samples_tested += rs->tile_stats[2 * (size_t)t];
        s->samples_written += rs->tile_stats[2 * (size_t)t + 1];
    }
    s->setup_ms += f.t_mid - t0, s->tile_ms += t1 - f.t_mid;
    s->setup_regions += rs->timing, s->tile_regions += rs->timing;   /* counted with timing on */
    rs->q_n = rs->q_chunks = rs->q_prims = rs->q_max_verts = 0;
}

int rs_scene_error(rs_context *rs)
{
    if (!rs) return RS_OK;
    const int e = rs->scene_err;
    rs->scene_err = RS_OK;
    return e;
}

void rs_set_scene(rs_context *rs, rs_stats *sink)
{
    if (!rs) return;
    rs_flush(rs);
    rs->sink = sink;
}

/* Whether draw j of n_pieces pieces and at most n_prims triangles is queued (rs_set_scene on, the fast path, the
 * target of the frame the last deferred clear started); the queue flushed first when j cannot join it (another
 * target, or the budget) or when j is not queued (it draws now, after them).  Room for one more entry made. */
static bool scene_takes(rs_context *rs, const rs_job *j, size_t n_pieces, size_t n_prims)
{
    rs_target *rt = j->rt;
    bool take = rs->sink && !j->reference && rs->frame && rt == rs->pend_rt && rt->color == rs->pend_color;
    size_t tiles = (size_t)j->n_tiles, max_chunks = BIN_OFFSETS_BUDGET / (tiles + 1); /* bin offsets: 16 MB */
    if (rs->q_n && (!take || rt != rs->q_rt || rt->color != rs->q_color || rs->q_prims + n_prims > SCENE_MAX_PRIMS ||
                    rs->q_chunks + n_pieces > max_chunks))
        rs_flush(rs);
    if (take && rs->q_n == rs->q_cap) {
        size_t cap = rs->q_cap ? 2 * rs->q_cap : 64;
        rs_scene_draw *q = realloc(rs->q, cap * sizeof *q);
        if (!q) {   /* drawn now, after the queued draws: the same bytes */
            rs_flush(rs);
            return false;
        }
        rs->q = q, rs->q_cap = cap;
    }
    return take;
}

/* Record draw j of source src: its pieces to be set up into rs->chunks[q_chunks .. + n_pieces) at the flush
 * (scene_takes made room in the queue, the caller in the chunks and the projection scratch). */
static void scene_push(rs_context *rs, const rs_job *j, const rs_source *src)
{
    rs_scene_draw *d = &rs->q[rs->q_n];
    d->j = *j, d->st = *j->st, d->j.st = &d->st, d->src = *src;
    d->c0 = rs->q_chunks, d->nc = src->n_pieces;
    for (size_t c = 0; c < src->n_pieces; c++) {
        rs->chunks[d->c0 + c].draw = (uint32_t)rs->q_n;
        rs->chunks[d->c0 + c].piece = c;
    }
    rs->q_n++;
    rs->q_chunks += src->n_pieces, rs->q_prims += src->n_prims;
    if (src->max_verts > rs->q_max_verts) rs->q_max_verts = src->max_verts;   /* the slots' projection scratch */
    rs->q_rt = j->rt, rs->q_color = j->rt->color;
}

/* rs_draw_source without the scene: set up every piece of src now (one parallel region) and rasterize them (one
 * tile pass), draw j. */
static int draw_source_now(rs_context *rs, const rs_job *j, const rs_source *src, int nt, rs_stats *stats)
{
    long nc = (long)src->n_pieces;
    rs_chunk *ch = rs->chunks;
    const double t0 = phase_clock(rs);
#pragma omp parallel for schedule(dynamic, 1) num_threads(nt) if (nc > 1 && src->n_prims >= RS_PARALLEL_SETUP_MIN)
    for (long c = 0; c < nc; c++) source_chunk(j, rs, src, (size_t)c, &ch[c], omp_get_thread_num(), src->max_verts);
    const double setup_ms = phase_clock(rs) - t0;
    size_t n_prims = 0;
    for (size_t c = 0; c < src->n_pieces; c++) {
        if (ch[c].bad_piece) return RS_EINVAL;
        if (ch[c].oom) return RS_ENOMEM;
        n_prims += ch[c].count;
    }
    if (n_prims > src->n_prims) return RS_EINVAL;
    if (!add_work(rs, j, 0, src->n_pieces)) return RS_EWORK;
    raster_tiles(j, rs, src->n_pieces, n_prims, nt, setup_ms, stats);
    return RS_OK;
}

/* Is src's grid_level 0, or a level up to RS_GRID_MAX_LEVEL whose grid has group_prims triangles? */
static bool grid_level_ok(const rs_source *src)
{
    const size_t l = src->grid_level;
    return l == 0 || (l <= RS_GRID_MAX_LEVEL && src->group_prims == l * l);
}

int rs_draw_source(rs_context *rs, const rs_state *st, rs_target *rt, const rs_source *src, rs_stats *stats)
{
    if (stats) memset(stats, 0, sizeof *stats);
    if (!rs || !st || !rt || !src || !src->produce || !rs_target_valid(rt) || !valid_state(st, rt) ||
        src->n_pieces > rs_max_pieces(rt) || !grid_level_ok(src))
        return RS_EINVAL;
    if (stats) stats->prims_in = src->n_prims;
    if (src->n_pieces == 0 || src->n_prims == 0) return RS_OK;
    rs_job j;
    make_job(&j, rs, st, rt, RS_PRIM_TRIANGLES, NULL, NULL);
    j.grid_mirrored = src->grid_level && src->grid_mirrored;
    int nt = thread_count(rs);
    const bool queued = scene_takes(rs, &j, src->n_pieces, src->n_prims);
    const size_t c0 = queued ? rs->q_chunks : 0;   /* not queued: the queue is empty */
    if (!reserve_context(rs, c0 + src->n_pieces, (size_t)j.n_tiles) || !reserve_pv(rs, (size_t)nt, src->max_verts))
        return RS_ENOMEM;
    if (queued) {   /* set up and rasterized at the flush; its counters then go to the sink */
        if (stats) stats->prims_in = 0;
        scene_push(rs, &j, src);
        return RS_OK;
    }
    return draw_source_now(rs, &j, src, nt, stats);
}

int rs_draw(rs_context *rs, const rs_state *st, rs_target *rt, int prim, const rs_vertex *verts, size_t n_verts,
            const uint32_t *idx, size_t n_prims, rs_stats *stats)
{
    if (stats) memset(stats, 0, sizeof *stats);
    if (!rs || !st || !rt || !rs_target_valid(rt) || !valid_state(st, rt) ||
        !valid_input(prim, verts, n_verts, idx, n_prims))
        return RS_EINVAL;
    if (stats) stats->prims_in = n_prims;
    if (n_prims == 0) return RS_OK;
    rs_flush(rs);   /* the queued draws come first */
    rs_job j;
    make_job(&j, rs, st, rt, prim, verts, idx);
    size_t n_chunks = chunk_count(n_prims, (size_t)j.n_tiles);
    if (!reserve_context(rs, n_chunks, (size_t)j.n_tiles)) return RS_ENOMEM;
    size_t per = (n_prims + n_chunks - 1) / n_chunks;
    for (size_t c = 0; c < n_chunks; c++) {
        rs->chunks[c].first = c * per < n_prims ? c * per : n_prims;
        rs->chunks[c].count = c * per < n_prims ? (n_prims - c * per < per ? n_prims - c * per : per) : 0;
    }
    int nt = thread_count(rs);
    const double t0 = phase_clock(rs);
    shared_pass(rs, &j, n_verts, n_prims, nt);
    long nc = (long)n_chunks;
#pragma omp parallel for schedule(dynamic, 1) num_threads(nt) if (nc > 1 && n_prims >= RS_PARALLEL_SETUP_MIN)
    for (long c = 0; c < nc; c++) {
        rs_setup_chunk(&j, &rs->chunks[c]);
        rs_bin_chunk(&j, &rs->chunks[c]);
    }
    const double setup_ms = phase_clock(rs) - t0;
    for (size_t c = 0; c < n_chunks; c++)
        if (rs->chunks[c].oom) return RS_ENOMEM;
    if (!add_work(rs, &j, 0, n_chunks)) return RS_EWORK;
    raster_tiles(&j, rs, n_chunks, n_prims, nt, setup_ms, stats);
    return RS_OK;
}
