/* raster/target.c -- render targets: allocation, AOV planes, clear (immediate, or deferred per tile), the
 * tile pass's tile buffers, and multisample resolve.
 *
 * Deferred clear: dev_clear records the clear; the tile pass writes each tile's clear when a draw first touches the
 * tile -- into the thread's tile buffer (32 KB for 1 sample: it stays in the L1/L2 cache), which the tile's
 * primitives are drawn into and which is then copied to the target; rs_target_flush writes the tiles no draw
 * touched (rs_target_flush_planes only some planes: the present writes the colour, and the depth plane's clear stays
 * deferred per tile until something reads the depth or the next frame's clear replaces it -- on scene C 577 of
 * 1024 tiles are never drawn, and their 9.4 MB of depth are then never written); a present that discards the depth
 * (RS_DISCARD_DEPTH: D3DPRESENTFLAG_DISCARD_DEPTHSTENCIL) skips the drawn tiles' depth copy-out too and defers the
 * frame's depth clear again (C: 7.3 MB per frame, 15 % of its frame time).  (Measured on 2 cores: the
 * copy-out costs 1 thread ~2%, and saves 2 threads 6-12% on scenes A and C, which no longer share the L2/L3
 * traffic of drawing in the target.)  The copy-out uses streaming stores on planes of COPY_STREAM_BYTES or more
 * whose rows are whole cache lines (planes are 64-byte aligned): they skip reading the target's lines before
 * writing them (scene C: 1 thread 4.3 -> 3.3 ms, 2 threads 2.6 -> 1.9 ms).  Streaming stores into planes 16 bytes
 * off a cache line, as calloc gave, write partial lines and were 3x slower.  A present (RS_PRESENT) leaves marks on
 * the tiles whose colour it filled with the clear's (rs->clean); the next frame's deferred clear of the same colour
 * keeps them and its fill skips the tiles still marked -- they hold those bytes -- while a draw into a tile, another
 * colour, or any flush without RS_PRESENT (after which the caller may write the planes) drops them (scene C: 577 of
 * 1024 tiles, 9.4 MB of colour a frame not written again; 1 thread 2.39 -> 1.93 ms, A 1.55 -> 1.43 ms). */
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#ifdef __SSE2__
#include <immintrin.h>
#endif

#include "raster_internal.h"

/* n zeroed 32-bit words, 64-byte aligned: a tile row of a target whose rows are whole cache lines then is whole
 * cache lines too, which the tile copy-out's streaming stores need (a partial line costs the memory a read).
 * NULL when out of memory. */
static void *plane_alloc(size_t n)
{
    if (n > (SIZE_MAX - 63u) / 4u) return NULL;
    size_t bytes = (n * 4u + 63u) & ~(size_t)63u;
    void *p = aligned_alloc(64, bytes);
    if (p) memset(p, 0, bytes);
    return p;
}

bool rs_target_valid(const rs_target *rt)
{
    if (!rt || !rt->color || !rt->depth || rt->width < 1 || rt->height < 1 || rt->width > RS_MAX_SIZE ||
        rt->height > RS_MAX_SIZE || (rt->samples != 1 && rt->samples != 4))
        return false;
    if (rt->n_aov < 0 || rt->n_aov > RS_MAX_AOV || (rt->n_aov > 0 && rt->samples != 1)) return false;
    for (int k = 0; k < rt->n_aov; k++) {
        const rs_aov *a = &rt->aov[k];
        if (!a->data || a->slot < 0 || a->slot >= RS_MAX_ATTR || a->comps < 1 || a->comps > 4) return false;
    }
    return true;
}

/* Allocate a w x h target with 1 or 4 samples: RS_OK, RS_EINVAL (bad arguments) or RS_ENOMEM. */
int rs_target_init(rs_target *rt, int width, int height, int samples)
{
    if (!rt) return RS_EINVAL;
    memset(rt, 0, sizeof *rt);
    if (width < 1 || height < 1 || width > RS_MAX_SIZE || height > RS_MAX_SIZE) return RS_EINVAL;
    if (samples != 1 && samples != 4) return RS_EINVAL;
    size_t n = (size_t)width * (size_t)height * (size_t)samples;
    rt->color = plane_alloc(n);
    rt->depth = plane_alloc(n);
    rt->stencil = calloc(n, 1); /* one byte per sample (calloc: fresh pages cost no stores until used) */
    if (!rt->color || !rt->depth || !rt->stencil) {
        rs_target_free(rt);
        return RS_ENOMEM;
    }
    rt->width = width;
    rt->height = height;
    rt->samples = samples;
    return RS_OK;
}

/* Free every plane of rt and zero it (safe on a zeroed or already freed target). */
void rs_target_free(rs_target *rt)
{
    if (!rt) return;
    free(rt->color);
    free(rt->depth);
    free(rt->stencil);
    for (int k = 0; k < rt->n_aov && k < RS_MAX_AOV; k++) free(rt->aov[k].data);
    memset(rt, 0, sizeof *rt);
}

/* Add a zeroed AOV plane of `comps` components of `slot`: RS_OK, RS_EINVAL or RS_ENOMEM. */
int rs_target_add_aov(rs_target *rt, int slot, int comps)
{
    if (!rs_target_valid(rt) || rt->samples != 1 || rt->n_aov >= RS_MAX_AOV) return RS_EINVAL;
    if (slot < 0 || slot >= RS_MAX_ATTR || comps < 1 || comps > 4) return RS_EINVAL;
    float *d = calloc((size_t)rt->width * (size_t)rt->height * (size_t)comps, sizeof *d);
    if (!d) return RS_ENOMEM;
    rt->aov[rt->n_aov] = (rs_aov){ slot, comps, d };
    rt->n_aov++;
    return RS_OK;
}

/* Clear colour (flags & 1, also the AOV planes to 0) and depth (flags & 2) of every sample. */
/* Planes larger than this are cleared with streaming stores (they would not stay in the caches anyway). */
#define CLEAR_STREAM_BYTES (8u << 20)

/* A 32-bit word that may alias the float depth plane (fill32 and copy32 move depth bits as words). */
typedef uint32_t word32 __attribute__((may_alias));

/* After streaming stores (when `stream`): the fence that orders them before what follows. */
static inline void stream_fence(bool stream)
{
#ifdef __AVX2__
    if (stream) _mm_sfence();
#else
    (void)stream;
#endif
}

/* Fill n 32-bit words at dst with `bits`, 8 at a time; streaming (non-temporal) stores when `stream` (the caller
 * fences: stream_fence). */
static void fill32(word32 *dst, uint32_t bits, size_t n, bool stream)
{
    size_t i = 0;
#ifdef __AVX2__
    __m256i v = _mm256_set1_epi32((int)bits);
    for (; i < n && ((uintptr_t)(dst + i) & 31u); i++) dst[i] = bits;
    if (stream) {
        for (; i + 8 <= n; i += 8) _mm256_stream_si256((__m256i *)(dst + i), v);
    } else {
        for (; i + 32 <= n; i += 32) { /* a tile buffer's planes: 4 stores per step (a third of the instructions) */
            _mm256_store_si256((__m256i *)(dst + i), v);
            _mm256_store_si256((__m256i *)(dst + i + 8), v);
            _mm256_store_si256((__m256i *)(dst + i + 16), v);
            _mm256_store_si256((__m256i *)(dst + i + 24), v);
        }
        for (; i + 8 <= n; i += 8) _mm256_store_si256((__m256i *)(dst + i), v);
    }
#endif
    for (; i < n; i++) dst[i] = bits;
}

/* Copy n 32-bit words from src to dst, 8 at a time once dst is 32-byte aligned; streaming (non-temporal) stores
 * when `stream` (the caller fences). */
static void copy32(word32 *restrict dst, const word32 *restrict src, size_t n, bool stream)
{
    size_t i = 0;
#ifdef __AVX2__
    for (; i < n && ((uintptr_t)(dst + i) & 31u); i++) dst[i] = src[i];
    if (stream) {
        for (; i + 8 <= n; i += 8)
            _mm256_stream_si256((__m256i *)(dst + i), _mm256_loadu_si256((const __m256i *)(src + i)));
    } else {
        for (; i + 16 <= n; i += 16) { /* a tile row's copy-out: 2 vectors per step */
            const __m256i a = _mm256_loadu_si256((const __m256i *)(src + i));
            const __m256i b = _mm256_loadu_si256((const __m256i *)(src + i + 8));
            _mm256_store_si256((__m256i *)(dst + i), a);
            _mm256_store_si256((__m256i *)(dst + i + 8), b);
        }
        for (; i + 8 <= n; i += 8)
            _mm256_store_si256((__m256i *)(dst + i), _mm256_loadu_si256((const __m256i *)(src + i)));
    }
#else
    (void)stream;
#endif
    for (; i < n; i++) dst[i] = src[i];
}

/* Clear rows [y0, y1) of the target as rs_target_clear does. */
static void clear_rows(rs_target *rt, unsigned flags, uint32_t rgba, float z, int y0, int y1)
{
    size_t row = (size_t)rt->width * (size_t)rt->samples, n = row * (size_t)(y1 - y0), at = row * (size_t)y0;
    bool stream = row * (size_t)rt->height * 4u >= CLEAR_STREAM_BYTES;
    uint32_t zb;
    memcpy(&zb, &z, 4);
    if (flags & RS_CLEAR_COLOR) {
        fill32(rt->color + at, rgba, n, stream);
        for (int k = 0; k < rt->n_aov; k++) {
            size_t w = (size_t)rt->width * (size_t)rt->aov[k].comps;
            memset(rt->aov[k].data + w * (size_t)y0, 0, w * (size_t)(y1 - y0) * sizeof(float));
        }
    }
    if (flags & RS_CLEAR_DEPTH) fill32((word32 *)rt->depth + at, zb, n, stream);
    stream_fence(stream);
}

void rs_target_clear_threads(rs_target *rt, unsigned flags, uint32_t rgba, float z, int threads)
{
    if (!rs_target_valid(rt)) return;
    int nt = threads > 0 ? threads : omp_get_num_procs();
    nt = nt < 1 ? 1 : (nt > rt->height ? rt->height : nt);
#pragma omp parallel for schedule(static) num_threads(nt)
    for (int k = 0; k < nt; k++)
        clear_rows(rt, flags, rgba, z, (int)((int64_t)rt->height * k / nt), (int)((int64_t)rt->height * (k + 1) / nt));
}

void rs_target_clear_rect(rs_target *rt, int x0, int y0, int x1, int y1, unsigned flags, uint32_t rgba, float z)
{
    if (!rs_target_valid(rt)) return;
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > rt->width ? rt->width : x1, y1 = y1 > rt->height ? rt->height : y1;
    size_t ns = (size_t)rt->samples;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            size_t p = (size_t)y * (size_t)rt->width + (size_t)x;
            for (size_t s = 0; s < ns; s++) {
                if (flags & RS_CLEAR_COLOR) rt->color[p * ns + s] = rgba;
                if (flags & RS_CLEAR_DEPTH) rt->depth[p * ns + s] = z;
            }
            for (int k = 0; (flags & RS_CLEAR_COLOR) && k < rt->n_aov; k++)
                memset(rt->aov[k].data + p * (size_t)rt->aov[k].comps, 0, (size_t)rt->aov[k].comps * sizeof(float));
        }
}

void rs_target_clear(rs_target *rt, unsigned flags, uint32_t rgba, float z)
{
    if (!rs_target_valid(rt)) return;
    clear_rows(rt, flags, rgba, z, 0, rt->height);
}

/* The resolve of 4-sample pixels c[4 p .. 4 p + 3] into out[p], p < np: per channel (sum + 2) / 4, the general
 * loop's value, two channels at a time in 16-bit halves (channels 0 and 2, then 1 and 3: sums up to 1020 fit; the
 * high half's bits shifted into the low half land above its 8 bits and are masked off). */
static void resolve4(const uint32_t *c, uint32_t *out, size_t np)
{
    for (size_t p = 0; p < np; p++, c += 4) {
        const uint32_t m = 0x00ff00ffu;
        uint32_t even = (c[0] & m) + (c[1] & m) + (c[2] & m) + (c[3] & m);
        uint32_t odd = (c[0] >> 8 & m) + (c[1] >> 8 & m) + (c[2] >> 8 & m) + (c[3] >> 8 & m);
        out[p] = ((even + 0x00020002u) >> 2 & m) | ((odd + 0x00020002u) >> 2 & m) << 8;
    }
}

/* Average the samples of each pixel, per channel, rounding half up: (sum + n/2) / n. */
void rs_target_resolve(const rs_target *rt, uint32_t *out)
{
    if (!rs_target_valid(rt) || !out) return;
    size_t np = (size_t)rt->width * (size_t)rt->height;
    int ns = rt->samples;
    if (ns == 1) {
        memcpy(out, rt->color, np * sizeof *out);
        return;
    }
    if (ns == 4) {
        resolve4(rt->color, out, np);
        return;
    }
    for (size_t p = 0; p < np; p++) {
        const uint32_t *s = rt->color + p * (size_t)ns;
        uint32_t r = 0;
        for (int c = 0; c < 32; c += 8) {
            uint32_t sum = 0;
            for (int k = 0; k < ns; k++) sum += (s[k] >> c) & 0xffu;
            r |= ((sum + (uint32_t)ns / 2) / (uint32_t)ns) << c;
        }
        out[p] = r;
    }
}

/* The AOV planes' pixels [x0, x1) of row y of rt cleared to 0 (a clear of the colour clears them). */
static void clear_aov_row(rs_target *rt, int x0, int x1, int y)
{
    for (int k = 0; k < rt->n_aov; k++) {
        size_t c = (size_t)rt->aov[k].comps;
        memset(rt->aov[k].data + ((size_t)y * (size_t)rt->width + (size_t)x0) * c, 0,
               (size_t)(x1 - x0) * c * sizeof(float));
    }
}

/* Tiles of rt (squares of 1 << rs_tile_bits(rt) pixels, the tile pass's grid). */
static int tile_count(const rs_target *rt)
{
    const int b = rs_tile_bits(rt);
    return rs_tiles_across(rt->width, b) * rs_tiles_across(rt->height, b);
}

/* Do rs's clean marks (rs->clean) hold for rt now: armed by the deferred clear, rt the same target with the same
 * colour plane and tile count, no AOV planes (a fill clears them too, and nothing tracks them), the fill's colour
 * theirs? */
static bool clean_for(const rs_context *rs, const rs_target *rt)
{
    return rs->clean_on && rs->clean_rt == rt && rs->clean_color == rt->color && rt->n_aov == 0 &&
           rs->clean_rgba == rs->pend_rgba && rs->clean_tiles == tile_count(rt);
}

/* Write the planes `planes` (RS_CLEAR_COLOR: colour and AOV planes, RS_CLEAR_DEPTH) of rt's deferred clear (as
 * rs_target_clear with rs's pending values) into tile (tx, ty); streaming stores on the planes the tile
 * copy-out streams into (the present's tiles no draw touched: on a 2048x2048 target most of its 32 MB, which
 * plain stores would first read). */
static void fill_tile(const rs_context *rs, rs_target *rt, int tx, int ty, unsigned planes)
{
    const int b = rs_tile_bits(rt), ts = 1 << b;
    if ((planes & RS_CLEAR_COLOR) && clean_for(rs, rt)) {   /* the colour: not again where the last fill holds */
        uint8_t *c = &rs->clean[(size_t)ty * (size_t)rs_tiles_across(rt->width, b) + (size_t)tx];
        if (*c) planes &= ~(unsigned)RS_CLEAR_COLOR;
        *c = 1;
        if (!planes) return;
    }
    int x0 = tx * ts, y0 = ty * ts;
    int x1 = x0 + ts < rt->width ? x0 + ts : rt->width;
    int y1 = y0 + ts < rt->height ? y0 + ts : rt->height;
    size_t ns = (size_t)rt->samples, n = (size_t)(x1 - x0) * ns;
    const size_t row_bytes = (size_t)rt->width * ns * 4u;
    const bool stream = row_bytes % 64u == 0 && row_bytes * (size_t)rt->height >= COPY_STREAM_BYTES;
    uint32_t zb;
    memcpy(&zb, &rs->pend_z, 4);
    for (int y = y0; y < y1; y++) {
        size_t at = ((size_t)y * (size_t)rt->width + (size_t)x0) * ns;
        if (planes & RS_CLEAR_COLOR) fill32(rt->color + at, rs->pend_rgba, n, stream);
        if (planes & RS_CLEAR_DEPTH) fill32((word32 *)rt->depth + at, zb, n, stream);
        if (planes & RS_CLEAR_COLOR) clear_aov_row(rt, x0, x1, y);
    }
    stream_fence(stream);
}

/* rs->pend[tile]'s bits: the planes whose clear is deferred (RS_CLEAR_COLOR, RS_CLEAR_DEPTH), and PEND_FRAME_DEPTH
 * when the deferred clear covered the tile's depth -- kept when the tile is written, so that a discarding present
 * (RS_DISCARD_DEPTH) can defer it again whatever the frame drew there. */
#define PEND_PLANES (RS_CLEAR_COLOR | RS_CLEAR_DEPTH)
#define PEND_FRAME_DEPTH 16u

/* Is rs's deferred clear for rt (the same target, not reallocated since)? */
static bool pending_on(const rs_context *rs, const rs_target *rt)
{
    return rs->pend_tiles > 0 && rs->pend_rt == rt && rt->color == rs->pend_color && tile_count(rt) == rs->pend_tiles;
}

void rs_target_flush_planes(rs_context *rs, rs_target *rt, unsigned planes)
{
    if (rs && !(planes & RS_PRESENT)) rs->clean_on = false;   /* the caller may write the planes next */
    planes &= RS_CLEAR_COLOR | RS_CLEAR_DEPTH | (planes & RS_CLEAR_DEPTH ? 0u : RS_DISCARD_DEPTH);
    rs_flush_fill(rs, rt, planes);   /* the queued draws (rs_set_scene) first, the tiles they leave filled too */
    if (!rs || !rt || !pending_on(rs, rt)) {
        if (rs && rs->pend_rt == rt) rs->pend_tiles = 0;
        return;
    }
    int n = rs->pend_tiles, tx = rs_tiles_across(rt->width, rs_tile_bits(rt)), left = 0;
    if (planes & RS_DISCARD_DEPTH)   /* the frame's depth dropped: the clear deferred again, however it was drawn */
        for (int t = 0; t < n; t++) rs->pend[t] |= (uint8_t)(rs->pend[t] & PEND_FRAME_DEPTH ? RS_CLEAR_DEPTH : 0);
    planes &= PEND_PLANES;
    for (int t = 0; t < n && !left; t++) left = rs->pend[t] & planes;
    int nt = rs->threads > 0 ? rs->threads : omp_get_num_procs();
    nt = nt < 1 ? 1 : nt;
#pragma omp parallel for schedule(dynamic, 8) num_threads(nt) if (left)
    for (int t = 0; t < n; t++)
        if (rs->pend[t] & planes) {
            fill_tile(rs, rt, t % tx, t / tx, rs->pend[t] & planes);
            rs->pend[t] &= (uint8_t)~planes;
        }
    if ((rs->pend_flags & ~planes) == 0) rs->pend_tiles = 0;   /* nothing left deferred */
}

void rs_target_flush(rs_context *rs, rs_target *rt) { rs_target_flush_planes(rs, rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH); }

/* The clean marks for the frame rs_target_clear_deferred starts on rt (flags, colour rgba, n tiles): kept when they
 * hold for the same target, colour plane, tile count and colour since the last present (clean_for), else all
 * cleared -- or off when the colour is not cleared or the marks cannot be allocated. */
static void clean_arm(rs_context *rs, const rs_target *rt, unsigned flags, uint32_t rgba, size_t n)
{
    const bool keep = (flags & RS_CLEAR_COLOR) && clean_for(rs, rt);   /* (pend_rgba is rgba already) */
    rs->clean_on = false;
    if (!(flags & RS_CLEAR_COLOR) || rt->n_aov > 0) return;
    if (!keep) {
        if (!rs_reserve((void **)&rs->clean, &rs->clean_cap, n, 1)) return;
        memset(rs->clean, 0, n);
    }
    rs->clean_on = true, rs->clean_rt = rt, rs->clean_color = rt->color, rs->clean_tiles = (int)n;
    rs->clean_rgba = rgba;
}

void rs_target_clear_deferred(rs_context *rs, rs_target *rt, unsigned flags, uint32_t rgba, float z)
{
    if (!rs || !rs_target_valid(rt) || !(flags & (RS_CLEAR_COLOR | RS_CLEAR_DEPTH))) return;
    rs_flush(rs);   /* the queued draws (rs_set_scene) before the clear */
    rs->work = 0;   /* a new frame: RS_MAX_OVERDRAW counts from here */
    rs->frame = true;
    if (rs->pend_tiles > 0 && (!pending_on(rs, rt) || (flags & rs->pend_flags) != rs->pend_flags))
        rs_target_flush(rs, rs->pend_rt); /* another target, or a clear that keeps part of the pending one */
    size_t n = (size_t)tile_count(rt);
    if (n > rs->pend_cap) {
        uint8_t *p = realloc(rs->pend, n);
        if (!p) {
            rs->clean_on = false;   /* (the marks do not know this clear) */
            rs_target_clear_threads(rt, flags, rgba, z, rs->threads);
            return;
        }
        rs->pend = p, rs->pend_cap = n;
    }
    const unsigned frame = flags & RS_CLEAR_DEPTH ? PEND_FRAME_DEPTH : 0u;   /* per tile: the planes deferred */
    memset(rs->pend, (int)((flags & PEND_PLANES) | frame), n);
    rs->pend_tiles = (int)n, rs->pend_rt = rt, rs->pend_color = rt->color;
    rs->pend_flags = flags, rs->pend_rgba = rgba, rs->pend_z = z;
    clean_arm(rs, rt, flags, rgba, n);
}

void rs_tile_flush(const rs_context *rs, const rs_job *j, int tile, unsigned planes)
{
    if (!pending_on(rs, j->rt) || !(rs->pend[tile] & planes)) return;
    fill_tile(rs, j->rt, tile % j->tiles_x, tile / j->tiles_x, rs->pend[tile] & planes);
    rs->pend[tile] &= (uint8_t)~planes;
}

size_t rs_tile_buffer_size(const rs_job *j)
{
    return ((size_t)1 << 2 * j->tile_bits) * (size_t)j->samples * (sizeof(uint32_t) + sizeof(float));
}

bool rs_tile_buffer_begin(const rs_context *rs, const rs_job *j, int tile, rs_tile *t, void *buf)
{
    rs_target *rt = j->rt;
    if (!buf || !pending_on(rs, rt) || !(rs->pend[tile] & PEND_PLANES)) return false;
    const int ts = 1 << j->tile_bits, x0 = tile % j->tiles_x * ts, y0 = tile / j->tiles_x * ts;
    const int x1 = x0 + ts < rt->width ? x0 + ts : rt->width;
    const int y1 = y0 + ts < rt->height ? y0 + ts : rt->height;
    const size_t ns = (size_t)rt->samples, n = (size_t)(x1 - x0) * ns, row = (size_t)ts * ns;
    uint32_t *col = buf, *dep = col + row * (size_t)ts, zb;
    const unsigned pf = rs->pend[tile] & PEND_PLANES;   /* the planes still deferred here; the others from the target */
    memcpy(&zb, &rs->pend_z, 4);
    /* a cleared plane is filled whole, its rows at once (the columns past the target's right edge too, which
     * nothing copies out): one call per plane where one per row cost the fill's set-up 64 times */
    const size_t rows = (size_t)(y1 - y0) * row;
    if (pf & RS_CLEAR_COLOR) fill32(col, rs->pend_rgba, rows, false);
    if (pf & RS_CLEAR_DEPTH) fill32(dep, zb, rows, false);
    const bool keeps = (~pf & (RS_CLEAR_COLOR | RS_CLEAR_DEPTH)) != 0; /* a plane from the target */
    const bool aov = (pf & RS_CLEAR_COLOR) && rt->n_aov > 0;
    for (int y = y0; y < y1 && (keeps || aov); y++) {
        size_t at = ((size_t)y * (size_t)rt->width + (size_t)x0) * ns, bt = (size_t)(y - y0) * row;
        if (!(pf & RS_CLEAR_COLOR)) memcpy(col + bt, rt->color + at, n * sizeof *col);
        if (!(pf & RS_CLEAR_DEPTH)) memcpy(dep + bt, rt->depth + at, n * sizeof *dep);
        if (pf & RS_CLEAR_COLOR) clear_aov_row(rt, x0, x1, y);
    }
    t->color = col, t->depth = (float *)dep;
    t->ox = x0, t->oy = y0, t->pitch = ts;
    return true;
}


void rs_tile_buffer_end(const rs_context *rs, const rs_job *j, int tile, const rs_tile *t, unsigned keep)
{
    rs_target *rt = j->rt;
    const int ts = 1 << j->tile_bits;
    const int x1 = t->ox + ts < rt->width ? t->ox + ts : rt->width;
    const int y1 = t->oy + ts < rt->height ? t->oy + ts : rt->height;
    const size_t ns = (size_t)rt->samples, n = (size_t)(x1 - t->ox) * ns;
    const size_t row_bytes = (size_t)rt->width * ns * 4u;
    const bool stream = row_bytes % 64u == 0 && row_bytes * (size_t)rt->height >= COPY_STREAM_BYTES;
    for (int y = t->oy; y < y1; y++) {
        size_t at = ((size_t)y * (size_t)rt->width + (size_t)t->ox) * ns, bt = rs_tile_index(t, t->ox, y) * ns;
        copy32(rt->color + at, t->color + bt, n, stream);
        if (!(keep & RS_CLEAR_DEPTH)) copy32((word32 *)rt->depth + at, (const word32 *)t->depth + bt, n, stream);
    }
    stream_fence(stream);
    rs->pend[tile] = (uint8_t)(rs->pend[tile] & (PEND_FRAME_DEPTH | (keep & RS_CLEAR_DEPTH)));
}

unsigned rs_tile_pending(const rs_context *rs, const rs_job *j, int tile)
{
    return pending_on(rs, j->rt) ? rs->pend[tile] & PEND_PLANES : 0u;
}

void rs_tile_drawn(const rs_context *rs, const rs_job *j, int tile)
{
    if (rs->clean_on && rs->clean_rt == j->rt) rs->clean[tile] = 0;
}

/* rs_target_clear_stencil: the stencil bytes of the pixels of [x0, x1) x [y0, y1) inside the target. */
void rs_target_clear_stencil(rs_target *rt, int x0, int y0, int x1, int y1, uint32_t value)
{
    if (!rs_target_valid(rt) || !rt->stencil) return;
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > rt->width ? rt->width : x1, y1 = y1 > rt->height ? rt->height : y1;
    if (x0 >= x1 || y0 >= y1) return;
    size_t ns = (size_t)rt->samples;
    for (int y = y0; y < y1; y++)
        memset(rt->stencil + ((size_t)y * (size_t)rt->width + (size_t)x0) * ns, (int)(value & 0xffu),
               (size_t)(x1 - x0) * ns);
}
