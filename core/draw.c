/* core/draw.c -- DrawPrimitive / DrawIndexedPrimitive: validation, vertex fetch with D3D9 stream frequencies
 * (instancing), vertex shading through a post-transform cache, primitive assembly, N-patch mode, and the hand-off
 * to the rasterizer (raster/raster.h).
 *
 * Instancing as D3D9 fetched it: with stream 0 set to INDEXEDDATA | n the draw is repeated for instances
 * 0..n-1; for instance i and index k, a per-vertex stream (frequency 1 or a plain divider d) is read at vertex
 * (ib[k] + BaseVertexIndex) / d and an INSTANCEDATA | d stream at vertex i / d.
 *
 * Post-transform cache: each instance's vertices MinVertexIndex .. MinVertexIndex + NumVertices - 1 are shaded
 * once, then the instance's primitives index them.  Instances are processed in chunks of at most
 * DRAW_CHUNK_VERTICES shaded vertices, so memory stays bounded whatever the instance count; chunks are drawn in
 * order, so the result is the same as one big draw.  This is the definition (and the reference path's only
 * route); off the reference path, triangle draws with few vertices per instance take the fused path instead
 * (draw_fused.c: pieces of a few instances shaded and set up by one thread each), which writes the same bytes.
 *
 * D3D9's fetch address (index / divider * stride) is device_internal.h's fetch_offset. */
#include "device_internal.h"

#include "hlsl.h"
#include <stdlib.h>
#include <string.h>

#define DRAW_CHUNK_VERTICES (1u << 16)
/* The device's word for RS_EWORK (raster.h: work bounded by the output). */
#define DEV_EWORK_STR2(x) #x
#define DEV_EWORK_STR(x) DEV_EWORK_STR2(x)
#define DEV_EWORK_MSG "draw: the frame would cover each pixel more than " DEV_EWORK_STR(RS_MAX_OVERDRAW) \
                      " times on average (work is bounded by the output's size); nothing drawn"
#define DRAW_MAX_VERTICES (1u << 26) /* NumVertices of one draw (one instance must fit in scratch memory) */

_Static_assert(sizeof(is_vs_input) % sizeof(float4) == 0 && IS_VS_INPUT_REGS < 32,
               "register masks are 32 bits (and 1u << IS_VS_INPUT_REGS is defined)");

/* Indices a primitive list of `count` primitives of `type` uses; 0 for an unknown type. */
static size_t prim_index_count(is_primtype type, unsigned count)
{
    switch (type) {
    case IS_PT_POINTLIST: return count;
    case IS_PT_LINELIST: return 2 * (size_t)count;
    case IS_PT_LINESTRIP: return (size_t)count + 1;
    case IS_PT_TRIANGLELIST: return 3 * (size_t)count;
    case IS_PT_TRIANGLESTRIP: case IS_PT_TRIANGLEFAN: return (size_t)count + 2;
    default: return 0;
    }
}

/* The rasterizer primitive and vertices per primitive of a D3D9 primitive type. */
static int prim_raster_type(is_primtype type, unsigned *per_prim)
{
    if (type == IS_PT_POINTLIST) return *per_prim = 1, RS_PRIM_POINTS;
    if (type == IS_PT_LINELIST || type == IS_PT_LINESTRIP) return *per_prim = 2, RS_PRIM_LINES;
    return *per_prim = 3, RS_PRIM_TRIANGLES;
}

/* Position in the index stream of vertex c (0..per-1) of primitive p: lists, strips (triangle p is
 * (p, p+1, p+2) when even and (p, p+2, p+1) when odd, keeping the winding, as D3D9 does) and fans (0, p+1, p+2). */
size_t prim_vertex(is_primtype type, size_t p, unsigned c)
{
    switch (type) {
    case IS_PT_LINESTRIP: return p + c;
    case IS_PT_TRIANGLESTRIP: return (p & 1) && c ? p + 3 - c : p + c;
    case IS_PT_TRIANGLEFAN: return c == 0 ? 0 : p + c;
    case IS_PT_POINTLIST: return p;
    case IS_PT_LINELIST: return 2 * p + c;
    default: return 3 * p + c;
    }
}

/* Element k of declaration element de on stream s, read robustly (fetch_elem): the buffer's bounds for its reads.
 * Returns the number of the first vertex (or instance, after the divider) that lies past the buffer's end, or
 * UINT64_MAX when every read up to `last` (the last index the draw reads) is inside it. */
static uint64_t plan_element(const stream_source *s, const decl_element *de, uint64_t last, uint32_t div,
                             fetch_elem *fe)
{
    const uint64_t start = (uint64_t)s->offset + de->e.offset, need = start + de->size;
    const size_t size = s->vb ? s->vb->size : 0;
    if (!s->vb || need > size) {   /* no buffer, or not even one element in it: every read is zeros */
        fe->base = fetch_zeros, fe->stride = 0, fe->max_off = 0;
        return 0;
    }
    fe->base = s->vb->data + start, fe->stride = s->stride, fe->max_off = size - need;
    if (fetch_offset(last, div, s->stride) <= fe->max_off) return UINT64_MAX;
    return s->stride ? fe->max_off / s->stride + 1 : UINT64_MAX;
}

/* Check that the shader and declaration allow a draw; fill the fetch plan. max_vertex is the largest per-vertex
 * index the draw reads.  Elements past their buffer's end or on streams without one read zeros (fetch_elem); the
 * draw goes on, and the debug log gets one line for the draw (dev_debug_log). */
static is_result plan_fetch(is_device *dev, const char *call, uint64_t max_vertex, unsigned n_instances,
                            fetch_plan *fp)
{
    const is_vertex_declaration *d = dev->decl;
    if (!dev->vs) return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: no vertex shader set", call);
    if (!d) return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: no vertex declaration set", call);
    fp->n = d->n;
    fp->n_instances = n_instances;
    fp->n_vert = 0;
    uint32_t vert_regs = 0;
    bool any_inst = false;
    int outside = -1;            /* the first element that reads past its buffer (for the log) */
    uint64_t outside_from = 0;
    for (unsigned k = 0; k < d->n; k++) {
        const decl_element *de = &d->el[k];
        const stream_source *s = &dev->streams[de->e.stream];
        bool inst = (s->freq & IS_STREAMSOURCE_INSTANCEDATA) != 0;
        uint32_t div = inst ? (s->freq & ~IS_STREAMSOURCE_INSTANCEDATA)
                            : ((s->freq & IS_STREAMSOURCE_INDEXEDDATA) ? 1 : s->freq);
        if (inst && n_instances <= 1 && !(dev->streams[0].freq & IS_STREAMSOURCE_INDEXEDDATA))
            inst = false, div = 1; /* INSTANCEDATA without an instanced draw: D3D9 reads it per vertex */
        fetch_elem *fe = &fp->el[k];
        uint64_t from = plan_element(s, de, inst ? n_instances - 1 : max_vertex, div, fe);
        if (from != UINT64_MAX && outside < 0) outside = (int)k, outside_from = from;
        fe->divider = div, fe->per_instance = inst, fe->type = de->e.type, fe->reg_offset = de->reg_offset;
        if (!inst) {
            fp->vert[fp->n_vert++] = (uint8_t)k;
            vert_regs |= 1u << (de->reg_offset / sizeof(float4));
        }
        any_inst |= inst;
    }
    if (outside >= 0) {
        const decl_element *de = &d->el[outside];
        if (!dev->streams[de->e.stream].vb)
            dev_debug(dev, "%s: element %d reads stream %u, which has no vertex buffer: it reads zeros", call,
                      outside, de->e.stream);
        else
            dev_debug(dev, "%s: element %d reads stream %u past its %zu-byte buffer from %s %llu on: zeros", call,
                      outside, de->e.stream, dev->streams[de->e.stream].vb->size,
                      fp->el[outside].per_instance ? "instance element" : "vertex",
                      (unsigned long long)outside_from);
    }
    /* without per-instance elements every entry of a batch is complete: nothing to share */
    fp->shared = any_inst ? IS_VS_REGS_ALL & ~vert_regs : 0u;
    return IS_OK;
}

/* Fetch vertex `vertex` of instance `instance` into the input registers. */
void fetch_vertex(const fetch_plan *fp, uint32_t vertex, uint32_t instance, is_vs_input *in)
{
    input_defaults(in);
    for (unsigned k = 0; k < fp->n; k++) {
        const fetch_elem *e = &fp->el[k];
        *(float4 *)((unsigned char *)in + e->reg_offset) =
            decl_fetch(e->type, fetch_at(e, e->per_instance ? instance : vertex));
    }
}

/* Run the shader on one input; outputs it does not write are zero, as the rasterizer expects. */
void shade(const is_device *dev, const is_vs_input *in, rs_vertex *out)
{
    memset(out, 0, sizeof *out);
    dev->vs->main(&dev->consts, in, out);
    post_shade(&dev->remap, out, 1);
}

/* Scratch s with room for n elements of `size` bytes (device_internal.h): a larger block replaces a smaller one
 * without copying (scratch contents are not kept), and nothing is freed between draws, so a frame like the last
 * one allocates nothing and touches no fresh pages. */
void *scratch_get(scratch_buf *s, size_t n, size_t size)
{
    if (size && n > SIZE_MAX / size) return NULL;
    if (n * size <= s->bytes) return s->p;
    void *p = malloc(n * size);
    if (!p) return NULL;
    free(s->p);
    s->p = p, s->bytes = n * size;
    return p;
}

/* Make sure the scratch holds nv vertices and ni indices. */
is_result reserve_scratch(is_device *dev, size_t nv, size_t ni)
{
    if (nv > dev->out_v_cap) {
        rs_vertex *v = realloc(dev->out_v, nv * sizeof *v);
        if (!v) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "draw: out of memory for %zu shaded vertices", nv);
        dev->out_v = v, dev->out_v_cap = nv;
    }
    if (ni > dev->out_i_cap) {
        uint32_t *i = realloc(dev->out_i, ni * sizeof *i);
        if (!i) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "draw: out of memory for %zu indices", ni);
        dev->out_i = i, dev->out_i_cap = ni;
    }
    return IS_OK;
}

/* Add a draw's rasterizer counters to the device's. */
static void add_stats(is_device *dev, const rs_stats *s)
{
    dev->stats.prims_in += s->prims_in, dev->stats.prims_culled += s->prims_culled;
    dev->stats.prims_clipped_away += s->prims_clipped_away, dev->stats.prims_degenerate += s->prims_degenerate;
    dev->stats.prims_drawn += s->prims_drawn, dev->stats.samples_tested += s->samples_tested;
    dev->stats.samples_written += s->samples_written;
    dev->stats.setup_ms += s->setup_ms, dev->stats.tile_ms += s->tile_ms;
}

/* IS_OK with the call's counters added, or the rasterizer's error r as the device's. */
is_result draw_result(is_device *dev, int r, const rs_stats *s)
{
    if (r == RS_ENOMEM) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "draw: the rasterizer ran out of memory");
    if (r == RS_EWORK) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "%s", DEV_EWORK_MSG);
    if (r != RS_OK) return dev_fail(dev, IS_ERR_INVALIDCALL, "draw: the rasterizer refused the primitives");
    add_stats(dev, s);
    return IS_OK;
}

/* Hand n_prims primitives over to the rasterizer and add its counters to the device's. */
static is_result rasterize(is_device *dev, int prim, size_t n_verts, size_t n_prims)
{
    rs_state st = dev_rs_state(dev);
    rs_stats s = {0};
    return draw_result(dev, rs_draw(dev->rs, &st, &dev->rt, prim, dev->out_v, n_verts, dev->out_i, n_prims, &s),
                       &s);
}

/* Read index k of the bound index buffer. */
static uint32_t read_index(const is_index_buffer *ib, size_t k)
{
    if (ib->format == IS_FMT_INDEX16) {
        uint16_t v;
        memcpy(&v, ib->data + 2 * k, 2);
        return v;
    }
    uint32_t v;
    memcpy(&v, ib->data + 4 * k, 4);
    return v;
}

/* Shade vertices first..first+count-1 of instances i0..i0+ni-1 into out_v (instance-major), in parallel:
 * the reference path, one fetch and one call of main per vertex. */
static void shade_range_reference(is_device *dev, const fetch_plan *fp, uint32_t first, uint32_t count, uint32_t i0,
                                  uint32_t ni)
{
    const long n = (long)count * (long)ni;
#pragma omp parallel for schedule(static) num_threads(dev->threads > 0 ? dev->threads : omp_threads())
    for (long v = 0; v < n; v++) {
        is_vs_input in;
        fetch_vertex(fp, first + (uint32_t)(v % count), i0 + (uint32_t)(v / count), &in);
        shade(dev, &in, &dev->out_v[v]);
    }
}

/* Fewer vertices than this are shaded by one thread: a parallel region costs more than it saves (and much more
 * on a loaded machine, where a waiting thread may not get a core for milliseconds). */
#define PARALLEL_MIN_VERTICES 2048

/* Vertices of one instance shaded together by the fast path (fetched into a stack array), and batches per
 * parallel work item (one fetch of the per-instance registers serves them all). */
#define SHADE_BATCH 32
#define SHADE_PIECE 8

/* Fetch vertices first..first+n-1 of `instance` into in[0..n) as fetch_vertex does: the per-instance elements once,
 * copied to every entry, then the per-vertex elements. */
static void fetch_batch(const fetch_plan *fp, uint32_t first, uint32_t n, uint32_t instance, is_vs_input *in)
{
    input_defaults(&in[0]);
    for (unsigned k = 0; k < fp->n; k++) {
        const fetch_elem *e = &fp->el[k];
        if (e->per_instance)
            *(float4 *)((unsigned char *)&in[0] + e->reg_offset) =
                decl_fetch(e->type, fetch_at(e, instance));
    }
    for (uint32_t v = 1; v < n; v++) in[v] = in[0];
}

/* Refill the per-vertex elements of in[0..n) for vertices first..first+n-1 (the other registers of a batch of the
 * same instance are already right). */
static void fetch_vertices(const fetch_plan *fp, uint32_t first, uint32_t n, is_vs_input *in)
{
    for (uint32_t v = 0; v < n; v++)
        for (unsigned q = 0; q < fp->n_vert; q++) {
            const fetch_elem *e = &fp->el[fp->vert[q]];
            *(float4 *)((unsigned char *)&in[v] + e->reg_offset) = decl_fetch(e->type, fetch_at(e, first + v));
        }
}

/* Element e (per-vertex, divider 1) of vertices first..first+count-1 into out[0], out[step], ... when it is a
 * FLOAT1..FLOAT4 element whose every read lies inside its buffer: decl_fetch_inline with the type a constant in
 * each loop (its switch folded away, no call per vertex).  False (nothing written) for other elements. */
static bool fetch_floats(const fetch_elem *e, uint32_t first, uint32_t count, float4 *out, size_t step)
{
    const uint8_t t = e->type;
    if ((t != IS_DECLTYPE_FLOAT1 && t != IS_DECLTYPE_FLOAT2 && t != IS_DECLTYPE_FLOAT3 && t != IS_DECLTYPE_FLOAT4) ||
        e->divider != 1 || !count || fetch_offset((uint64_t)first + count - 1, 1, e->stride) > e->max_off)
        return false;
    const unsigned char *src = e->base + (uint64_t)first * e->stride;
#define FETCH_FLOATS(type) \
    for (uint32_t v = 0; v < count; v++, src += e->stride, out += step) *out = decl_fetch_inline(type, src)
    switch (t) {
    case IS_DECLTYPE_FLOAT1: FETCH_FLOATS(IS_DECLTYPE_FLOAT1); break;
    case IS_DECLTYPE_FLOAT2: FETCH_FLOATS(IS_DECLTYPE_FLOAT2); break;
    case IS_DECLTYPE_FLOAT3: FETCH_FLOATS(IS_DECLTYPE_FLOAT3); break;
    default: FETCH_FLOATS(IS_DECLTYPE_FLOAT4); break;
    }
#undef FETCH_FLOATS
    return true;
}

/* The per-vertex elements of vertices first..first+count-1 fetched once into dev->fcache: cache[v * n_vert + q]
 * holds what fetch_vertices writes for vertex first + v, element q (the same for every instance); NULL when out of
 * memory. */
float4 *fetch_cache(is_device *dev, const fetch_plan *fp, uint32_t first, uint32_t count)
{
    float4 *c = scratch_get(&dev->fcache, (size_t)count * fp->n_vert + 1, sizeof *c);
    if (!c) return NULL;
    for (unsigned q = 0; q < fp->n_vert; q++) {
        const fetch_elem *e = &fp->el[fp->vert[q]];
        if (fetch_floats(e, first, count, c + q, fp->n_vert)) continue;
        for (uint32_t v = 0; v < count; v++)
            c[(size_t)v * fp->n_vert + q] = decl_fetch(e->type, fetch_at(e, first + v));
    }
    return c;
}

/* Shade vertices v0..v0+n-1 of `instance` into out[0..n), in batches of SHADE_BATCH; cache: the draw's
 * fetch_cache (vertex 0 = first) or NULL. */
static void shade_piece(const is_device *dev, const fetch_plan *fp, uint32_t first, uint32_t instance, uint32_t v0,
                        uint32_t n, rs_vertex *out_v, const float4 *cache)
{
    is_vs_input in[SHADE_BATCH];
    const is_vertex_shader *vs = dev->vs;
    const uint32_t live = live_outputs(dev);
    fetch_batch(fp, first + v0, n < SHADE_BATCH ? n : SHADE_BATCH, instance, in);
    for (uint32_t b = 0; b < n; b += SHADE_BATCH) {
        uint32_t m = n - b < SHADE_BATCH ? n - b : SHADE_BATCH;
        rs_vertex *out = out_v + b;
        if (cache) fetch_cached(fp, cache, v0 + b, m, in);
        else fetch_vertices(fp, first + v0 + b, m, in);
        memset(out, 0, m * sizeof *out);
        if (vs->batch) vs->batch(&dev->consts, in, m, live, 0, out);
        else
            for (uint32_t k = 0; k < m; k++) vs->main(&dev->consts, &in[k], &out[k]);
        post_shade(&dev->remap, out, m);
    }
}

/* The fast path of shade_range: pieces of up to SHADE_PIECE batches of one instance, shaded through the shader's
 * batch entry when it has one. */
static void shade_range_fast(is_device *dev, const fetch_plan *fp, uint32_t first, uint32_t count, uint32_t i0,
                             uint32_t ni)
{
    const uint32_t piece = SHADE_BATCH * SHADE_PIECE;
    const long per = (long)((count + piece - 1) / piece), np = per * (long)ni;
    /* dynamic: a thread the OS takes away for a while (a loaded machine) delays the draw by a few pieces only */
#pragma omp parallel for schedule(dynamic, 1) num_threads(dev->threads > 0 ? dev->threads : omp_threads()) \
    if (count * ni >= PARALLEL_MIN_VERTICES)
    for (long q = 0; q < np; q++) {
        uint32_t i = (uint32_t)(q / per), v0 = (uint32_t)(q % per) * piece;
        shade_piece(dev, fp, first, i0 + i, v0, count - v0 < piece ? count - v0 : piece,
                    &dev->out_v[(size_t)i * count + v0], NULL);
    }
}

/* Shade vertices first..first+count-1 of instances i0..i0+ni-1 into out_v (instance-major). */
static void shade_range(is_device *dev, const fetch_plan *fp, uint32_t first, uint32_t count, uint32_t i0,
                        uint32_t ni)
{
    if (dev->reference) shade_range_reference(dev, fp, first, count, i0, ni);
    else shade_range_fast(dev, fp, first, count, i0, ni);
    dev->shaded += (uint64_t)count * ni;
}

/* Build the rasterizer's index list for ni instances: prims of `type` whose index-stream positions are read
 * by idx_at(k) and rebased to first, repeated per instance with a stride of `count` vertices. */
static size_t assemble(is_device *dev, is_primtype type, size_t n_prims, uint32_t ni, uint32_t count,
                       const uint32_t *stream_idx)
{
    unsigned per;
    prim_raster_type(type, &per);
    const size_t n = n_prims * per;
    uint32_t *first = dev->out_i;
    for (size_t p = 0; p < n_prims; p++)
        for (unsigned c = 0; c < per; c++) first[p * per + c] = stream_idx[prim_vertex(type, p, c)];
    const long nl = (long)ni;
#pragma omp parallel for schedule(dynamic, 16) num_threads(dev->threads > 0 ? dev->threads : omp_threads()) if (nl > 64)
    for (long i = 1; i < nl; i++) /* instance i: instance 0's list moved by i * count */
        for (size_t k = 0; k < n; k++) dev->out_i[(size_t)i * n + k] = (uint32_t)i * count + first[k];
    return (size_t)ni * n_prims;
}

/* The draw after validation: stream_idx[k] are index-stream entries already rebased to `first`. */
static is_result draw_shaded_run(is_device *dev, const fetch_plan *fp, is_primtype type, size_t n_prims,
                                 uint32_t first, uint32_t count, const uint32_t *stream_idx)
{
    unsigned per;
    int prim = prim_raster_type(type, &per);
    if (draw_fused_takes(dev, prim, count)) { /* the fast path: draw_fused.c */
        if (type == IS_PT_TRIANGLELIST) /* a list's index stream is its triangles' list: nothing to assemble */
            return draw_fused(dev, fp, n_prims, first, count, stream_idx);
        uint32_t *list = scratch_get(&dev->list, 3 * n_prims, sizeof *list);
        if (!list) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "draw: out of memory for %zu indices", n_prims * 3);
        for (size_t p = 0; p < n_prims; p++)
            for (unsigned c = 0; c < 3; c++) list[3 * p + c] = stream_idx[prim_vertex(type, p, c)];
        return draw_fused(dev, fp, n_prims, first, count, list);
    }
    uint32_t chunk = count >= DRAW_CHUNK_VERTICES ? 1 : DRAW_CHUNK_VERTICES / count;
    if (chunk > fp->n_instances) chunk = fp->n_instances;
    is_result r = reserve_scratch(dev, (size_t)chunk * count, (size_t)chunk * n_prims * per);
    for (uint32_t i0 = 0; r == IS_OK && i0 < fp->n_instances; i0 += chunk) {
        uint32_t ni = fp->n_instances - i0 < chunk ? fp->n_instances - i0 : chunk;
        const double t0 = dev_clock(dev);
        shade_range(dev, fp, first, count, i0, ni);
        dev->stats.setup_ms += dev_clock(dev) - t0;
        size_t np = assemble(dev, type, n_prims, ni, count, stream_idx);
        r = rasterize(dev, prim, (size_t)ni * count, np);
    }
    return r;
}

/* draw_shaded_run, replayed first for the pixel the inspector records (core/inspect.c) when the device records. */
static is_result draw_shaded(is_device *dev, const fetch_plan *fp, is_primtype type, size_t n_prims,
                             uint32_t first, uint32_t count, const uint32_t *stream_idx)
{
    if (!dev->inspector) return draw_shaded_run(dev, fp, type, n_prims, first, count, stream_idx);
    size_t mark = inspect_draw(dev, fp, type, n_prims, first, count, stream_idx);
    is_result r = draw_shaded_run(dev, fp, type, n_prims, first, count, stream_idx);
    inspect_draw_done(dev, mark, r == IS_OK);
    return r;
}

/* Common checks of both draw calls: primitive type and count. */
static is_result check_prims(is_device *dev, const char *call, is_primtype type, unsigned prim_count)
{
    if (!prim_index_count(type, 1))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: unknown primitive type %d", call, type);
    return IS_OK;
}

static is_result draw_npatch(is_device *dev, const fetch_plan *fp, size_t n_tris, const uint32_t *stream_idx,
                             uint32_t first);

/* The instances of an indexed draw, as the runtime counts them: stream 0's count (its setting without the flags,
 * at least 1) when a stream the declaration reads has INSTANCEDATA, else 1 (INDEXEDDATA | n alone, or | 0, draws
 * once). */
static unsigned instance_count(const is_device *dev)
{
    const uint32_t flags = IS_STREAMSOURCE_INDEXEDDATA | IS_STREAMSOURCE_INSTANCEDATA;
    bool instanced = false;
    for (unsigned k = 0; dev->decl && k < dev->decl->n; k++)
        instanced |= (dev->streams[dev->decl->el[k].e.stream].freq & IS_STREAMSOURCE_INSTANCEDATA) != 0;
    uint32_t n = dev->streams[0].freq & ~flags;
    return instanced && n > 1 ? n : 1;
}

static is_result draw_primitive(is_device *dev, const char *call, is_primtype type, unsigned start_vertex,
                                unsigned prim_count);
static is_result draw_indexed(is_device *dev, const char *call, is_primtype type, int base_vertex_index,
                              unsigned min_vertex_index, unsigned num_vertices, unsigned start_index,
                              unsigned prim_count);

/* DrawPrimitive under the name `call` (for its messages), on a live device: non-indexed, one instance whatever the
 * stream frequencies say (the runtime does not instance non-indexed draws; it draws the one instance and
 * succeeds).  dev_draw_primitive binds the pass-through of pre-transformed vertices around it. */
static is_result draw_primitive(is_device *dev, const char *call, is_primtype type, unsigned start_vertex,
                                unsigned prim_count)
{
    if (!dev->decl) return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: no vertex declaration set", call);
    if (prim_count == 0) return IS_OK;   /* the runtime: nothing drawn, no error */
    is_result r = check_prims(dev, call, type, prim_count);
    if (r != IS_OK) return r;
    size_t n_idx = prim_index_count(type, prim_count);
    if (n_idx > DRAW_MAX_VERTICES)   /* the device's MaxPrimitiveCount: D3D9 refuses a draw beyond its caps */
        return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: %zu vertices, more than the %u one draw may read", call,
                        n_idx, DRAW_MAX_VERTICES);
    if ((uint64_t)start_vertex + n_idx - 1 > UINT32_MAX)   /* vertex numbers are 32-bit, as D3D9's */
        return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: StartVertex %u + %zu vertices pass vertex 2^32 - 1", call,
                        start_vertex, n_idx);
    fetch_plan fp;
    r = plan_fetch(dev, call, (uint64_t)start_vertex + n_idx - 1, 1, &fp);
    if (r != IS_OK) return r;
    uint32_t *seq = scratch_get(&dev->idx, n_idx, sizeof *seq);
    if (!seq) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "%s: out of memory", call);
    for (size_t k = 0; k < n_idx; k++) seq[k] = (uint32_t)k;
    if (dev->npatch_segments >= 1.0f && dev->npatch_eval && type == IS_PT_TRIANGLELIST)
        return draw_npatch(dev, &fp, prim_count, seq, start_vertex);
    return draw_shaded(dev, &fp, type, prim_count, start_vertex, (uint32_t)n_idx, seq);
}

/* Whether indices start..start+n_idx-1 lie in the bound index buffer; else the error (checked before the draw
 * allocates room for them: a count beyond the buffer never sizes an allocation). */
static is_result check_index_range(is_device *dev, const char *call, unsigned start, size_t n_idx)
{
    const is_index_buffer *ib = dev->ib;
    size_t isz = ib->format == IS_FMT_INDEX16 ? 2 : 4;
    if (start > ib->size / isz || n_idx > ib->size / isz - start)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: indices %u..%zu beyond the %zu-index buffer", call,
                        start, start + n_idx - 1, ib->size / isz);
    return IS_OK;
}

/* Indices start..start+n_idx-1 of ib (in the buffer) rebased to min into out; true when every one lies in
 * [min, min + num) (out is then the draw's list), false when one does not.  Eight indices per vector (GCC's -O2
 * does not vectorize the loop by itself), the rest one by one. */
static bool rebase_indices(const is_index_buffer *ib, unsigned start, size_t n_idx, unsigned min, unsigned num,
                           uint32_t *restrict out)
{
    typedef uint32_t u32x8 __attribute__((vector_size(32)));
    typedef uint16_t u16x8 __attribute__((vector_size(16)));
    const bool i16 = ib->format == IS_FMT_INDEX16;
    const unsigned char *src = ib->data + (i16 ? 2 : 4) * (size_t)start;
    u32x8 bad8 = {0};
    size_t k = 0;
    for (; k + 8 <= n_idx; k += 8) {
        u32x8 v;
        if (i16) {
            u16x8 h;
            memcpy(&h, src + 2 * k, sizeof h);
            v = __builtin_convertvector(h, u32x8);
        } else
            memcpy(&v, src + 4 * k, sizeof v);
        const u32x8 r = v - min;
        bad8 |= (u32x8)((v < min) | (r >= num));
        memcpy(out + k, &r, sizeof r);
    }
    uint32_t bad = 0;
    for (int q = 0; q < 8; q++) bad |= bad8[q];
    for (; k < n_idx; k++) {
        const uint32_t v = read_index(ib, start + k), r = v - min;
        bad |= (v < min) | (r >= num);
        out[k] = r;
    }
    return !bad;
}

/* Read the draw's indices (in the buffer: check_index_range), check them against [min, min + num) and rebase
 * them to min. */
static is_result read_indices(is_device *dev, const char *call, unsigned start, size_t n_idx, unsigned min,
                              unsigned num, uint32_t *out)
{
    const is_index_buffer *ib = dev->ib;
    if (rebase_indices(ib, start, n_idx, min, num, out)) return IS_OK;
    for (size_t k = 0; k < n_idx; k++) {   /* the first index outside, for the message */
        uint32_t v = read_index(ib, start + k);
        if (v < min || v - min >= num)
            return dev_fail(dev, IS_ERR_INVALIDCALL,
                            "%s: index %u at position %zu outside MinVertexIndex %u + NumVertices %u", call,
                            v, start + k, min, num);
    }
    return IS_OK;
}

/* DrawIndexedPrimitive under the name `call`, on a live device, with D3D9 instancing: see the top of this file.
 * dev_draw_indexed_primitive binds the pass-through of pre-transformed vertices around it. */
static is_result draw_indexed(is_device *dev, const char *call, is_primtype type, int base_vertex_index,
                              unsigned min_vertex_index, unsigned num_vertices, unsigned start_index,
                              unsigned prim_count)
{
    if (!dev->decl) return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: no vertex declaration set", call);
    if (prim_count == 0 || num_vertices == 0) return IS_OK;   /* the runtime: nothing drawn, no error */
    is_result r = check_prims(dev, call, type, prim_count);
    if (r != IS_OK) return r;
    if (!dev->ib) return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: no index buffer set", call);
    if (num_vertices == 0 || num_vertices > DRAW_MAX_VERTICES)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: NumVertices %u not in 1..%u", call, num_vertices,
                        DRAW_MAX_VERTICES);
    int64_t first = (int64_t)base_vertex_index + min_vertex_index;
    if (first < 0 || first + num_vertices - 1 > UINT32_MAX)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: BaseVertexIndex %d + MinVertexIndex %u out of range", call,
                        base_vertex_index, min_vertex_index);
    unsigned n_inst = instance_count(dev);
    size_t n_idx = prim_index_count(type, prim_count);
    if ((r = check_index_range(dev, call, start_index, n_idx)) != IS_OK) return r;
    uint32_t *idx = scratch_get(&dev->idx, n_idx, sizeof *idx);
    if (!idx) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "%s: out of memory for %zu indices", call, n_idx);
    fetch_plan fp;
    r = read_indices(dev, call, start_index, n_idx, min_vertex_index, num_vertices, idx);
    if (r == IS_OK) r = plan_fetch(dev, call, (uint64_t)first + num_vertices - 1, n_inst, &fp);
    if (r == IS_OK) {
        if (dev->npatch_segments >= 1.0f && dev->npatch_eval && type == IS_PT_TRIANGLELIST)
            r = n_inst > 1 ? dev_fail(dev, IS_ERR_INVALIDCALL, "%s: N-patch mode with instancing", call)
                           : draw_npatch(dev, &fp, prim_count, idx, (uint32_t)first);
        else
            r = draw_shaded(dev, &fp, type, prim_count, (uint32_t)first, num_vertices, idx);
    }
    return r;
}

/* ---------------------------------------- UP draws ---------------------------------------- */

/* Stream 0 unset (no buffer, offset and stride 0), as a UP draw leaves it. */
static void unset_stream0(is_device *dev)
{
    dev->streams[0].vb = NULL, dev->streams[0].offset = 0, dev->streams[0].stride = 0;
}

/* DrawPrimitiveUP: the vertices from the caller's memory (prim_count primitives' worth, stride bytes apart) as
 * stream 0; afterwards stream 0 is unset, as the runtime leaves it (DXVK's DrawPrimitiveUP; a count of 0 draws
 * nothing and changes nothing). */
is_result dev_draw_primitive_up(is_device *dev, is_primtype type, unsigned prim_count, const void *vertices,
                                unsigned stride)
{
    const char *call = "DrawPrimitiveUP";
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!vertices || stride == 0)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: %s", call, vertices ? "a stride of 0" : "NULL vertex data");
    if (!dev->decl) return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: no vertex declaration set", call);
    if (prim_count == 0) return IS_OK;
    is_result r = check_prims(dev, call, type, prim_count);
    if (r != IS_OK) return r;
    dev->up_vb.data = (unsigned char *)(uintptr_t)vertices;   /* read only */
    dev->up_vb.size = prim_index_count(type, prim_count) * (size_t)stride;
    dev->streams[0].vb = &dev->up_vb, dev->streams[0].offset = 0, dev->streams[0].stride = stride;
    const is_vertex_shader *saved = NULL;
    bool pre = raster_pretransformed_begin(dev, &saved);   /* POSITIONT, as the buffer draws */
    r = draw_primitive(dev, call, type, 0, prim_count);
    if (pre) raster_pretransformed_end(dev, saved);
    dev_scene_flush(dev);   /* a recorded draw reads the caller's vertices: only during the call */
    unset_stream0(dev);
    dev->up_vb.data = NULL, dev->up_vb.size = 0;
    return r;
}

/* DrawIndexedPrimitiveUP: the indices (prim_count primitives' worth, INDEX16 or INDEX32) and the vertices
 * (MinVertexIndex + NumVertices of them, stride bytes apart) from the caller's memory; afterwards stream 0 and the
 * indices are unset, as the runtime leaves them (DXVK's DrawIndexedPrimitiveUP).  Instancing as
 * DrawIndexedPrimitive. */
is_result dev_draw_indexed_primitive_up(is_device *dev, is_primtype type, unsigned min_vertex_index,
                                        unsigned num_vertices, unsigned prim_count, const void *indices,
                                        is_format index_format, const void *vertices, unsigned stride)
{
    const char *call = "DrawIndexedPrimitiveUP";
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!vertices || !indices || stride == 0)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: %s", call, stride ? "NULL index or vertex data" : "a stride of 0");
    if (index_format != IS_FMT_INDEX16 && index_format != IS_FMT_INDEX32)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: index format %d is not INDEX16 or INDEX32", call, index_format);
    if (!dev->decl) return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: no vertex declaration set", call);
    if (prim_count == 0 || num_vertices == 0) return IS_OK;
    is_result r = check_prims(dev, call, type, prim_count);
    if (r != IS_OK) return r;
    dev->up_vb.data = (unsigned char *)(uintptr_t)vertices;
    dev->up_vb.size = ((size_t)min_vertex_index + num_vertices) * stride;
    dev->up_ib.data = (unsigned char *)(uintptr_t)indices;
    dev->up_ib.size = prim_index_count(type, prim_count) * (index_format == IS_FMT_INDEX16 ? 2u : 4u);
    dev->up_ib.format = index_format;
    dev->streams[0].vb = &dev->up_vb, dev->streams[0].offset = 0, dev->streams[0].stride = stride;
    dev->ib = &dev->up_ib;
    const is_vertex_shader *saved = NULL;
    bool pre = raster_pretransformed_begin(dev, &saved);   /* POSITIONT, as the buffer draws */
    r = draw_indexed(dev, call, type, 0, min_vertex_index, num_vertices, 0, prim_count);
    if (pre) raster_pretransformed_end(dev, saved);
    dev_scene_flush(dev);   /* a recorded draw reads the caller's vertices: only during the call */
    unset_stream0(dev);
    dev->ib = NULL;
    dev->up_vb.data = NULL, dev->up_vb.size = 0, dev->up_ib.data = NULL, dev->up_ib.size = 0;
    return r;
}

/* ---------------------------------------- N-patch mode ---------------------------------------- */

/* in = b0 * a + b1 * b + b2 * c for every register (the tessellator's linear interpolation). */
static void lerp_inputs(const is_vs_input *a, const is_vs_input *b, const is_vs_input *c, float3 w,
                        is_vs_input *in)
{
    const float *pa = (const float *)a, *pb = (const float *)b, *pc = (const float *)c;
    float *po = (float *)in;
    for (size_t k = 0; k < sizeof *in / sizeof(float); k++) po[k] = w.x * pa[k] + w.y * pb[k] + w.z * pc[k];
}

/* NORMALDEGREE as the evaluator takes it: CUBIC (which the runtime accepts) as QUADRATIC (device.h). */
static uint32_t normal_degree(const is_device *dev)
{
    const uint32_t d = dev->rs_state[IS_RS_NORMALDEGREE];
    return d == IS_DEGREE_CUBIC ? IS_DEGREE_QUADRATIC : d;
}

/* N-patch segments as draws take them: at most IS_NPATCH_MAX_SEGMENTS (NaN stays NaN: the mode is off). */
static float npatch_segments(const is_device *dev)
{
    return dev->npatch_segments > IS_NPATCH_MAX_SEGMENTS ? IS_NPATCH_MAX_SEGMENTS : dev->npatch_segments;
}

/* Shade the grid points of triangle t: the evaluator gives POSITION0 / NORMAL0, the rest is interpolated. */
static void npatch_triangle(const is_device *dev, const fetch_plan *fp, const uint32_t *tri, const float3 *bary,
                            size_t n_pts, rs_vertex *out)
{
    is_vs_input v[3];
    float3 p[3], n[3];
    for (int c = 0; c < 3; c++) {
        fetch_vertex(fp, tri[c], 0, &v[c]);
        p[c] = f3_of(v[c].position[0]), n[c] = f3_of(v[c].normal[0]);
    }
    for (size_t g = 0; g < n_pts; g++) {
        is_vs_input in;
        float3 pos, nrm;
        lerp_inputs(&v[0], &v[1], &v[2], bary[g], &in);
        dev->npatch_eval(p, n, bary[g], dev->rs_state[IS_RS_POSITIONDEGREE], normal_degree(dev), &pos, &nrm);
        in.position[0] = f4_of(pos, 1.0f), in.normal[0] = f4_of(nrm, 0.0f);
        shade(dev, &in, &out[g]);
    }
}

/* ------------------------------ adaptive N-patch mode (core.h) ------------------------------ */

/* The adaptive mode's inputs, read from the device's states once per draw. */
typedef struct adaptive_params {
    float segments, min_level, max_level;
    float4 mdm;         /* (ADAPTIVETESS_X, _Y, _Z, _W) */
    bool factor;        /* the declaration has a TESSFACTOR element (else every factor is 1) */
    bool continuous;    /* PATCHEDGESTYLE CONTINUOUS */
} adaptive_params;

/* A float render state's value. */
static float state_float(const is_device *dev, is_rs state)
{
    float f;
    memcpy(&f, &dev->rs_state[state], sizeof f);
    return f;
}

/* The device's states in, the draw's adaptive parameters out. */
static adaptive_params adaptive_params_of(const is_device *dev)
{
    adaptive_params a = {npatch_segments(dev), state_float(dev, IS_RS_MINTESSELLATIONLEVEL),
                         state_float(dev, IS_RS_MAXTESSELLATIONLEVEL),
                         f4(state_float(dev, IS_RS_ADAPTIVETESS_X), state_float(dev, IS_RS_ADAPTIVETESS_Y),
                            state_float(dev, IS_RS_ADAPTIVETESS_Z), state_float(dev, IS_RS_ADAPTIVETESS_W)),
                         false, dev->rs_state[IS_RS_PATCHEDGESTYLE] == IS_PATCHEDGE_CONTINUOUS};
    for (unsigned k = 0; k < dev->decl->n; k++) a.factor |= dev->decl->el[k].e.usage == IS_DECLUSAGE_TESSFACTOR;
    return a;
}

/* Triangle tri (absolute vertex numbers) in; its edge levels lv[k] (edge k from tri[k] to tri[k+1 mod 3]) as its
 * pattern takes them out: D3D9's rule, at most CORE_PG_MAX_LEVEL, truncated to an integer for DISCRETE. */
static void adaptive_edge_levels(const adaptive_params *a, const fetch_plan *fp, const uint32_t tri[3], float lv[3])
{
    float t[3];
    for (int c = 0; c < 3; c++) {
        is_vs_input in;
        fetch_vertex(fp, tri[c], 0, &in);
        t[c] = core_adaptive_vertex_level(a->segments, a->factor ? in.tessfactor[0].x : 1.0f, in.position[0],
                                          a->mdm);
    }
    for (int k = 0; k < 3; k++) {
        /* MIN / MAX below 1 (which the runtime takes) can give an edge less than one segment: the grids take it as
         * one (core_grid_make, core_grid_pg) */
        float e = fminf(core_adaptive_edge_level(t[k], t[(k + 1) % 3], a->min_level, a->max_level), CORE_PG_MAX_LEVEL);
        lv[k] = a->continuous ? e : floorf(e);
    }
}

/* Edge levels in; the triangle's pattern out (allocated; 0 or -1): the non-adaptive grid when all three are equal,
 * else the primitive generator's with inner = the largest outer (core.h says why). */
static int adaptive_grid(bool continuous, const float lv[3], core_grid *g)
{
    if (lv[0] == lv[1] && lv[1] == lv[2])
        return core_grid_make(continuous ? CORE_GRID_PG_FRACTIONAL_EVEN : CORE_GRID_REGULAR, lv[0], g);
    const float inner = fmaxf(lv[0], fmaxf(lv[1], lv[2]));
    return core_grid_pg(continuous ? CORE_GRID_PG_FRACTIONAL_EVEN : CORE_GRID_PG_EQUAL, inner, lv, g);
}

/* Edge levels in; at least the points adaptive_grid makes of them out: with n >= the segments of any of its
 * edges and rings, a pattern has at most 3n + 3(n^2/4 - n/2) + 1 <= (n + 2)^2 points. */
static size_t adaptive_points_bound(const float lv[3])
{
    const float m = fmaxf(lv[0], fmaxf(lv[1], lv[2]));
    const size_t n = (size_t)fminf(ceilf(m) + 1.0f, CORE_PG_MAX_LEVEL);
    return (n + 2) * (n + 2);
}

/* Triangles stream_idx[0..3 nt) with their edge levels lv in: each tessellated with its pattern, shaded and
 * rasterized in order (one rasterizer call). */
static is_result adaptive_chunk(is_device *dev, const fetch_plan *fp, bool continuous, const uint32_t *stream_idx,
                                uint32_t first, const float (*lv)[3], size_t nt)
{
    core_grid *g = calloc(nt, sizeof *g);
    size_t *pts = malloc((nt + 1) * sizeof *pts), *tris = malloc((nt + 1) * sizeof *tris);
    int bad = !g || !pts || !tris;
    const double c0 = dev_clock(dev);
    if (!bad) {
#pragma omp parallel for schedule(dynamic, 16) reduction(| : bad) \
    num_threads(dev->threads > 0 ? dev->threads : omp_threads())
        for (long t = 0; t < (long)nt; t++) bad |= adaptive_grid(continuous, lv[t], &g[t]) != 0;
    }
    is_result r = bad ? dev_fail(dev, IS_ERR_OUTOFMEMORY, "N-patch draw: out of memory for the adaptive patterns")
                      : IS_OK;
    if (r == IS_OK) {
        pts[0] = tris[0] = 0;
        for (size_t t = 0; t < nt; t++) pts[t + 1] = pts[t] + g[t].n_points, tris[t + 1] = tris[t] + g[t].n_triangles;
        r = reserve_scratch(dev, pts[nt], 3 * tris[nt]);
    }
    if (r == IS_OK) {
#pragma omp parallel for schedule(dynamic, 16) num_threads(dev->threads > 0 ? dev->threads : omp_threads())
        for (long t = 0; t < (long)nt; t++) {
            uint32_t tri[3];
            for (int c = 0; c < 3; c++) tri[c] = first + stream_idx[3 * (size_t)t + (size_t)c];
            npatch_triangle(dev, fp, tri, g[t].bary, g[t].n_points, &dev->out_v[pts[t]]);
            for (size_t k = 0; k < 3 * g[t].n_triangles; k++)
                dev->out_i[3 * tris[t] + k] = (uint32_t)pts[t] + g[t].idx[k];
        }
        dev->stats.setup_ms += dev_clock(dev) - c0;
        dev->shaded += pts[nt];
        r = rasterize(dev, RS_PRIM_TRIANGLES, pts[nt], tris[nt]);
    }
    for (size_t t = 0; g && t < nt; t++) core_grid_free(&g[t]);
    free(g), free(pts), free(tris);
    return r;
}

/* Adaptive N-patch mode: every triangle's edge levels by D3D9's rule (core.h), then the triangles in chunks of
 * about DRAW_CHUNK_VERTICES tessellated vertices, each with its own pattern. */
static is_result draw_npatch_adaptive(is_device *dev, const fetch_plan *fp, size_t n_tris, const uint32_t *stream_idx,
                                      uint32_t first)
{
    const adaptive_params a = adaptive_params_of(dev);
    float (*lv)[3] = scratch_get(&dev->npatch_lv, n_tris, sizeof *lv);
    if (!lv) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "N-patch draw: out of memory for %zu edge levels", 3 * n_tris);
#pragma omp parallel for schedule(static) num_threads(dev->threads > 0 ? dev->threads : omp_threads())
    for (long t = 0; t < (long)n_tris; t++) {
        uint32_t tri[3];
        for (int c = 0; c < 3; c++) tri[c] = first + stream_idx[3 * (size_t)t + (size_t)c];
        adaptive_edge_levels(&a, fp, tri, lv[t]);
    }
    is_result r = IS_OK;
    for (size_t t0 = 0, t1; r == IS_OK && t0 < n_tris; t0 = t1) {
        size_t budget = adaptive_points_bound(lv[t0]);
        for (t1 = t0 + 1; t1 < n_tris && budget + adaptive_points_bound(lv[t1]) <= DRAW_CHUNK_VERTICES; t1++)
            budget += adaptive_points_bound(lv[t1]);
        r = adaptive_chunk(dev, fp, a.continuous, stream_idx + 3 * t0, first, (const float (*)[3])(lv + t0), t1 - t0);
    }
    return r;
}

/* N-patch mode: every triangle becomes a grid shaded point by point.  PATCHEDGESTYLE DISCRETE truncates the
 * segments to an integer and uses the regular grid (D3D9: "float tessellation ... truncated to integers");
 * CONTINUOUS uses the segments as they are, with the primitive generator's fractional_even pattern -- the
 * D3D11 spacing that descends from D3D9's continuous tessellation, which varies smoothly with the level.
 * With ENABLEADAPTIVETESSELLATION each triangle gets its own pattern instead (draw_npatch_adaptive). */
static is_result draw_npatch(is_device *dev, const fetch_plan *fp, size_t n_tris, const uint32_t *stream_idx,
                             uint32_t first)
{
    if (dev->inspector) inspect_draw_done(dev, SIZE_MAX, false);   /* the N-patch mode is not recorded */
    if (dev->rs_state[IS_RS_ENABLEADAPTIVETESSELLATION])
        return draw_npatch_adaptive(dev, fp, n_tris, stream_idx, first);
    core_grid grid;
    bool continuous = dev->rs_state[IS_RS_PATCHEDGESTYLE] == IS_PATCHEDGE_CONTINUOUS;
    const float seg = npatch_segments(dev);
    float level = continuous ? seg : (float)(int)seg;
    if (core_grid_make(continuous ? CORE_GRID_PG_FRACTIONAL_EVEN : CORE_GRID_REGULAR, level, &grid) != 0)
        return dev_fail(dev, IS_ERR_OUTOFMEMORY, "N-patch draw: out of memory for the grid");
    const size_t n_pts = grid.n_points, n_grid = grid.n_triangles;
    const float3 *bary = grid.bary;
    const uint32_t *gidx = grid.idx;
    size_t chunk = n_pts >= DRAW_CHUNK_VERTICES ? 1 : DRAW_CHUNK_VERTICES / n_pts;
    is_result r = reserve_scratch(dev, chunk * n_pts, chunk * 3 * n_grid);
    for (size_t t0 = 0; r == IS_OK && t0 < n_tris; t0 += chunk) {
        long nt = (long)(n_tris - t0 < chunk ? n_tris - t0 : chunk);
        const double c0 = dev_clock(dev);
#pragma omp parallel for schedule(static) num_threads(dev->threads > 0 ? dev->threads : omp_threads())
        for (long t = 0; t < nt; t++) {
            uint32_t tri[3];
            for (int c = 0; c < 3; c++) tri[c] = first + stream_idx[3 * (t0 + (size_t)t) + (size_t)c];
            npatch_triangle(dev, fp, tri, bary, n_pts, &dev->out_v[(size_t)t * n_pts]);
        }
        dev->stats.setup_ms += dev_clock(dev) - c0;
        dev->shaded += (uint64_t)nt * n_pts;
        for (long t = 0; t < nt; t++)
            for (size_t k = 0; k < 3 * n_grid; k++) dev->out_i[(size_t)t * 3 * n_grid + k] = (uint32_t)(t * n_pts) + gidx[k];
        r = rasterize(dev, RS_PRIM_TRIANGLES, (size_t)nt * n_pts, (size_t)nt * n_grid);
    }
    core_grid_free(&grid);
    return r;
}

/* The public draws: with no vertex shader and a POSITIONT declaration, the pass-through of pre-transformed
 * vertices is bound for the draw (core/raster_states.c). */
is_result dev_draw_primitive(is_device *dev, is_primtype type, unsigned start_vertex, unsigned prim_count)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    const is_vertex_shader *saved = NULL;
    bool pre = raster_pretransformed_begin(dev, &saved);
    is_result r = draw_primitive(dev, "DrawPrimitive", type, start_vertex, prim_count);
    if (pre) raster_pretransformed_end(dev, saved);
    return r;
}

is_result dev_draw_indexed_primitive(is_device *dev, is_primtype type, int base_vertex_index,
                                     unsigned min_vertex_index, unsigned num_vertices, unsigned start_index,
                                     unsigned prim_count)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    const is_vertex_shader *saved = NULL;
    bool pre = raster_pretransformed_begin(dev, &saved);
    is_result r = draw_indexed(dev, "DrawIndexedPrimitive", type, base_vertex_index, min_vertex_index, num_vertices,
                               start_index, prim_count);
    if (pre) raster_pretransformed_end(dev, saved);
    return r;
}
