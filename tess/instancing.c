/* tess/instancing.c -- the buffers of tessellation through instancing (tess/tess.h): the grid in stream 0, one
 * instance per mesh triangle in stream 1; for per-edge levels, the patterns in use in stream 0 and the instances
 * renumbered and sorted by bucket. */
#include "tess_internal.h"

#include <stdlib.h>
#include <string.h>

void tess_resources_free(tess_resources *r)
{
    if (!r) return;
    vb_release(r->vb0);
    vb_release(r->vb1);
    vb_release(r->vb2);
    ib_release(r->ib);
    decl_release(r->decl);
    memset(r, 0, sizeof *r);
}

is_result tess_index_buffer(is_device *dev, const uint32_t *idx, size_t n, size_t max_index, is_index_buffer **out)
{
    if (out) *out = NULL;
    if (!dev || !idx || !out || n == 0 || n > SIZE_MAX / 4) return IS_ERR_INVALIDCALL;
    bool small = max_index < 65536;
    is_result r = dev_create_index_buffer(dev, n * (small ? 2 : 4), small ? IS_FMT_INDEX16 : IS_FMT_INDEX32, out);
    if (r != IS_OK) return r;
    void *p = ib_lock(*out);
    for (size_t k = 0; k < n; k++) {
        if (small) ((uint16_t *)p)[k] = (uint16_t)idx[k];
        else ((uint32_t *)p)[k] = idx[k];
    }
    ib_unlock(*out);
    return IS_OK;
}

is_result tess_bind_instanced(is_device *dev, const is_mesh *m, const core_grid *g, tess_resources *r)
{
    if (!dev || !m || !g || !r || !g->bary || !g->idx || !g->n_points || !g->n_triangles || !m->n_triangles)
        return IS_ERR_INVALIDCALL;
    is_result e = dev_create_vertex_buffer(dev, g->n_points * sizeof(float3), &r->vb0);
    if (e == IS_OK) e = dev_create_vertex_buffer(dev, m->n_triangles * sizeof(is_patch_instance), &r->vb1);
    if (e == IS_OK) e = tess_index_buffer(dev, g->idx, 3 * g->n_triangles, g->n_points, &r->ib);
    if (e == IS_OK) e = dev_create_vertex_declaration(dev, mesh_patch_declaration, &r->decl);
    if (e != IS_OK) return e;
    memcpy(vb_lock(r->vb0), g->bary, g->n_points * sizeof(float3));
    mesh_build_instances(m, vb_lock(r->vb1));
    dev_set_vertex_declaration(dev, r->decl);
    dev_set_stream_source(dev, 0, r->vb0, 0, sizeof(float3));
    dev_set_stream_source(dev, 1, r->vb1, 0, sizeof(is_patch_instance));
    dev_set_indices(dev, r->ib);
    dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | (uint32_t)m->n_triangles);
    dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1u);
    r->n_vertices = (unsigned)g->n_points, r->n_prims = (unsigned)g->n_triangles;
    r->n_instances = (unsigned)m->n_triangles;
    return IS_OK;
}


/* ---------------------------------------- adaptive: buckets of patterns ---------------------------------------- */

void tess_permute_instance(const is_patch_instance *in, const uint8_t perm[3], is_patch_instance *out)
{
    if (!in || !out) return;
    if (!tess_is_permutation(perm)) {   /* not a renumbering of three corners: the instance as it is */
        *out = *in;
        return;
    }
    for (int i = 0; i < 3; i++) {
        out->v[i] = in->v[perm[i]], out->n[i] = in->n[perm[i]], out->t[i] = in->t[perm[i]];
        const int a = perm[i], b = perm[(i + 1) % 3];
        out->opp[i] = in->opp[b == (a + 1) % 3 ? a : b]; /* the edge joining a and b, in either direction */
    }
    out->instance_id = in->instance_id;
}

/* What an adaptive bind keeps for the next (tess_rebind_adaptive): its host scratch and the device its buffers
 * belong to, each array at the largest size a bind asked of it, so that a frame's rebind allocates nothing once the
 * levels have settled (a fresh allocation per frame cost scene D's 8 px mode ~9 ms of a 27 ms frame in page faults
 * of new memory, bench/README.md). */
struct tess_adaptive_keep {
    const is_device *dev;       /* a->r's buffers' device */
    size_t n_tri;               /* room of keys (2 n_tri), tperm, inst, a->tri and a->perm */
    uint64_t *keys;
    uint8_t (*tperm)[3];
    is_patch_instance *inst;
    size_t n_buckets;           /* room of a->buckets */
    float3 *pts, *grid_pts;     /* the pattern pool (room cap_pts) and core_grid_regular's scratch (the largest */
    uint16_t *idx;              /* level's grid); (room cap_idx) */
    uint32_t *grid_idx;
    size_t cap_pts, cap_idx;
};

void tess_adaptive_free(tess_adaptive *a)
{
    if (!a) return;
    tess_resources_free(&a->r);
    free(a->buckets), free(a->tri), free(a->perm);
    tess_adaptive_keep *k = a->keep;
    if (k) free(k->keys), free(k->tperm), free(k->inst), free(k->pts), free(k->grid_pts), free(k->idx), free(k->grid_idx);
    free(k);
    memset(a, 0, sizeof *a);
}

/* *p with room for at least n elements of `size` bytes (*cap: its room, grown to n); false when out of memory (*p
 * and *cap as they were).  The old contents are not kept. */
static bool room(void **p, size_t *cap, size_t n, size_t size)
{
    if (n <= *cap && *p) return true;
    if (n > SIZE_MAX / size) return false;
    void *q = malloc(n * size);
    if (!q) return false;
    free(*p), *p = q, *cap = n;
    return true;
}

/* Every pattern's points fit 16-bit indices (level 64: 2,145 points), so the pool holds them as the index buffer
 * will (INDEX16, as tess_index_buffer chooses for them). */
_Static_assert((CORE_LOD_MAX_LEVEL + 1) * (CORE_LOD_MAX_LEVEL + 2) / 2 <= 65536, "pattern indices beyond 16 bits");

/* Patterns' points and indices gathered on the host before the buffers are created, sized once per bind from an
 * upper bound (a pattern of largest level M takes the regular level-M grid's points and triangles); a scratch for
 * core_grid_regular's output at the largest level. */
typedef struct pattern_pool {
    float3 *pts;
    uint16_t *idx;
    size_t n_pts, n_idx, cap_pts, cap_idx;
    float3 *grid_pts;
    uint32_t *grid_idx;
} pattern_pool;

/* Bucket keys: ((s0 - 1) * L + s1 - 1) * L + s2 - 1, then the parity, below 2^KEY_BITS (L = CORE_LOD_MAX_LEVEL). */
enum { KEY_BITS = 19, RADIX_BITS = 10 };
_Static_assert((uint64_t)CORE_LOD_MAX_LEVEL * CORE_LOD_MAX_LEVEL * CORE_LOD_MAX_LEVEL * 2 <= (1u << KEY_BITS) &&
               KEY_BITS <= 2 * RADIX_BITS, "bucket keys beyond two radix passes");

/* Append the pattern of bucket b's levels as the regular grid of its largest level M (core_grid_adaptive_points'
 * points; core_grid_regular(M)'s triangles, then the same with indices 1 and 2 swapped) to the pool; b gets its
 * base vertex, point count, start index (of the unflipped range) and triangle count.  False (nothing written)
 * when the pool's room, reserved from pool_bounds, would not hold it. */
static bool pool_add(pattern_pool *pool, tess_bucket *b)
{
    const int M = b->level[2];   /* the largest: the levels are sorted */
    const size_t np = core_grid_points(M), nt = core_grid_triangles(M);
    if (np > pool->cap_pts - pool->n_pts || nt > (pool->cap_idx - pool->n_idx) / 6) return false;
    if (core_grid_adaptive_points(b->level, pool->pts + pool->n_pts) != M ||
        core_grid_regular(M, pool->grid_pts, pool->grid_idx) != np)
        return false;
    b->base_vertex = (int)pool->n_pts, b->n_points = (unsigned)np;
    b->start_index = (unsigned)pool->n_idx, b->n_prims = (unsigned)nt;
    uint16_t *d = pool->idx + pool->n_idx, *f = d + 3 * nt;
    const uint32_t *s = pool->grid_idx;
    for (size_t t = 0; t < 3 * nt; t += 3) {
        d[t] = (uint16_t)s[t], d[t + 1] = (uint16_t)s[t + 1], d[t + 2] = (uint16_t)s[t + 2];
        f[t] = (uint16_t)s[t], f[t + 1] = (uint16_t)s[t + 2], f[t + 2] = (uint16_t)s[t + 1];
    }
    pool->n_pts += np, pool->n_idx += 6 * nt;
    return true;
}

/* Each triangle's bucket key ((a, b, c) sorted levels and parity) in the high 32 bits, the triangle below; its
 * renumbering into a->perm[t] (by triangle here; reordered by the caller). */
static void triangle_keys(const is_mesh *m, const tess_lod_edges *e, uint64_t *keys, uint8_t (*perm)[3])
{
    for (size_t t = 0; t < m->n_triangles; t++) {
        int lv[3], s[3], p[3];
        for (int k = 0; k < 3; k++) lv[k] = e->level[e->tri_edge[3 * t + k]];
        bool odd = core_lod_order(lv, s, p);
        uint64_t key = ((uint64_t)((s[0] - 1) * CORE_LOD_MAX_LEVEL + (s[1] - 1)) * CORE_LOD_MAX_LEVEL + (uint64_t)(s[2] - 1)) * 2 + odd;
        keys[t] = key << 32 | t;
        for (int k = 0; k < 3; k++) perm[t][k] = (uint8_t)p[k];
    }
}

/* keys[0..n) (bucket key << 32 | triangle, the triangles ascending) sorted by bucket key, ties in their order --
 * the order of sorting the whole 64-bit values, since the triangles are distinct -- by two stable counting passes
 * of RADIX_BITS over the key, through tmp[0..n). */
static void sort_keys(uint64_t *keys, uint64_t *tmp, size_t n)
{
    uint32_t count[1u << RADIX_BITS];
    for (int pass = 0; pass < 2; pass++) {
        const unsigned shift = 32u + (unsigned)pass * RADIX_BITS, mask = (1u << RADIX_BITS) - 1u;
        memset(count, 0, sizeof count);
        for (size_t i = 0; i < n; i++) count[keys[i] >> shift & mask]++;
        uint32_t at = 0;
        for (unsigned d = 0; d <= mask; d++) { uint32_t c = count[d]; count[d] = at, at += c; }
        for (size_t i = 0; i < n; i++) tmp[count[keys[i] >> shift & mask]++] = keys[i];
        memcpy(keys, tmp, n * sizeof *keys);
    }
}

/* The sorted keys' patterns: the number of buckets (*n_buckets) and the pool's room for their points and indices
 * (upper bounds from each distinct pattern's largest level). */
static void pool_bounds(const uint64_t *keys, size_t n, size_t *n_buckets, size_t *pts, size_t *idx)
{
    *n_buckets = *pts = *idx = 0;
    for (size_t i = 0; i < n; i++) {
        const uint64_t key = keys[i] >> 32;
        if (i > 0 && key == keys[i - 1] >> 32) continue;
        ++*n_buckets;
        if (i > 0 && key >> 1 == keys[i - 1] >> 33) continue;   /* the other parity of the same pattern */
        const int top = (int)(key >> 1) % CORE_LOD_MAX_LEVEL + 1;   /* s2, the largest level */
        *pts += core_grid_points(top), *idx += 6 * core_grid_triangles(top);
    }
}

/* Sorted keys in; a->buckets (room for n_buckets), a->tri, a->perm (reordered from by-triangle tperm) and the
 * pool (with room) filled.  IS_OK, IS_ERR_OUTOFMEMORY (a pattern the cache could not make) or IS_ERR_INVALIDCALL
 * (a pattern larger than pool_bounds allowed for). */
static is_result make_buckets(const uint64_t *keys, size_t n, const uint8_t (*tperm)[3], core_pattern_cache *cache,
                              tess_adaptive *a, pattern_pool *pool)
{
    uint64_t pattern_key = UINT64_MAX;
    tess_bucket last = {0};
    for (size_t i = 0; i < n; i++) {
        const uint32_t t = (uint32_t)keys[i];
        a->tri[i] = t;
        memcpy(a->perm[i], tperm[t], 3);
        const uint64_t key = keys[i] >> 32;
        if (i > 0 && key == keys[i - 1] >> 32) { a->buckets[a->n_buckets - 1].count++; continue; }
        tess_bucket *b = &a->buckets[a->n_buckets++];
        memset(b, 0, sizeof *b);   /* (padding too: two binds of the same levels are the same bytes) */
        b->odd = key & 1, b->first = (unsigned)i, b->count = 1;
        const uint64_t pk = key >> 1;
        b->level[0] = (int)(pk / (CORE_LOD_MAX_LEVEL * CORE_LOD_MAX_LEVEL)) + 1;
        b->level[1] = (int)(pk / CORE_LOD_MAX_LEVEL % CORE_LOD_MAX_LEVEL) + 1;
        b->level[2] = (int)(pk % CORE_LOD_MAX_LEVEL) + 1;
        if (pk != pattern_key) {
            const core_grid *g = core_pattern_get(cache, b->level[0], b->level[1], b->level[2]);
            if (!g) return IS_ERR_OUTOFMEMORY;
            if (!pool_add(pool, b)) return IS_ERR_INVALIDCALL;   /* a pattern beyond its bound: never */
            b->n_tessellated = (unsigned)g->n_triangles;
            pattern_key = pk, a->n_patterns++;
        } else {
            b->base_vertex = last.base_vertex, b->n_points = last.n_points;
            b->start_index = last.start_index, b->n_prims = last.n_prims, b->n_tessellated = last.n_tessellated;
        }
        last = *b;
    }
    for (size_t k = 0; k < a->n_buckets; k++) {
        a->n_triangles += (size_t)a->buckets[k].count * a->buckets[k].n_tessellated;
        if (a->buckets[k].odd) a->buckets[k].start_index += 3 * a->buckets[k].n_prims;
    }
    return IS_OK;
}

/* *vb holding at least `bytes` (created, or kept when large enough: its old bytes are rewritten by the caller) on
 * dev.  IS_OK or dev_create_vertex_buffer's error (*vb then NULL). */
static is_result vb_room(is_device *dev, size_t bytes, is_vertex_buffer **vb)
{
    if (*vb && vb_size(*vb) >= bytes) return IS_OK;
    vb_release(*vb), *vb = NULL;
    return dev_create_vertex_buffer(dev, bytes, vb);
}

/* The same for a 16-bit index buffer. */
static is_result ib_room(is_device *dev, size_t bytes, is_index_buffer **ib)
{
    if (*ib && ib_size(*ib) >= bytes) return IS_OK;
    ib_release(*ib), *ib = NULL;
    return dev_create_index_buffer(dev, bytes, IS_FMT_INDEX16, ib);
}

/* The pool and the sorted instances into device buffers (a's, kept when large enough), bound with Listing 1.1.2's
 * declaration (made again when PN-AEN's stream 2 replaced it: a rebind's instances are in a new order, so
 * tess_bind_adjacent_normals must come again). */
static is_result upload_adaptive(is_device *dev, const is_mesh *m, const pattern_pool *pool, tess_adaptive *a)
{
    tess_resources *r = &a->r;
    if (r->vb2) vb_release(r->vb2), decl_release(r->decl), r->vb2 = NULL, r->decl = NULL;
    is_result e = vb_room(dev, pool->n_pts * sizeof(float3), &r->vb0);
    if (e == IS_OK) e = vb_room(dev, m->n_triangles * sizeof(is_patch_instance), &r->vb1);
    if (e == IS_OK) e = ib_room(dev, pool->n_idx * sizeof *pool->idx, &r->ib);
    if (e == IS_OK && !r->decl) e = dev_create_vertex_declaration(dev, mesh_patch_declaration, &r->decl);
    if (e != IS_OK) return e;
    memcpy(vb_lock(r->vb0), pool->pts, pool->n_pts * sizeof(float3));
    memcpy(ib_lock(r->ib), pool->idx, pool->n_idx * sizeof *pool->idx);
    ib_unlock(r->ib);
    is_patch_instance *inst = a->keep->inst;
    mesh_build_instances(m, inst);
    is_patch_instance *out = vb_lock(r->vb1);
    for (size_t i = 0; i < m->n_triangles; i++) tess_permute_instance(&inst[a->tri[i]], a->perm[i], &out[i]);
    dev_set_vertex_declaration(dev, r->decl);
    dev_set_stream_source(dev, 0, r->vb0, 0, sizeof(float3));
    dev_set_indices(dev, r->ib);
    dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1u);
    return IS_OK;
}

/* Keys sorted in: the buckets, the pool (a->keep's arrays, grown to its bounds) and the buffers.  IS_OK or an
 * error. */
static is_result bind_sorted(is_device *dev, const is_mesh *m, const uint64_t *keys, const uint8_t (*tperm)[3],
                             core_pattern_cache *cache, tess_adaptive *a)
{
    tess_adaptive_keep *k = a->keep;
    const size_t n = m->n_triangles;
    size_t nb, np, ni;
    pool_bounds(keys, n, &nb, &np, &ni);
    if (!room((void **)&a->buckets, &k->n_buckets, nb, sizeof *a->buckets) ||
        !room((void **)&k->pts, &k->cap_pts, np, sizeof *k->pts) || !room((void **)&k->idx, &k->cap_idx, ni, sizeof *k->idx))
        return IS_ERR_OUTOFMEMORY;
    pattern_pool pool = {k->pts, k->idx, 0, 0, k->cap_pts, k->cap_idx, k->grid_pts, k->grid_idx};
    is_result r = make_buckets(keys, n, tperm, cache, a, &pool);
    if (r == IS_OK) r = upload_adaptive(dev, m, &pool, a);
    return r;
}

is_result tess_bind_adaptive(is_device *dev, const is_mesh *m, const tess_lod_edges *e, core_pattern_cache *cache,
                              tess_adaptive *a)
{
    if (!a) return IS_ERR_INVALIDCALL;
    memset(a, 0, sizeof *a);
    return tess_rebind_adaptive(dev, m, e, cache, a);
}

is_result tess_rebind_adaptive(is_device *dev, const is_mesh *m, const tess_lod_edges *e, core_pattern_cache *cache,
                               tess_adaptive *a)
{
    if (!a) return IS_ERR_INVALIDCALL;
    a->n_buckets = a->n_patterns = a->n_triangles = 0;   /* (no draw of a failed rebind draws anything) */
    if (!dev || !m || !e || !cache || !m->n_triangles || e->n_edges == 0) return IS_ERR_INVALIDCALL;
    const size_t n = m->n_triangles;
    if (n > UINT32_MAX) return IS_ERR_INVALIDCALL;   /* triangles are 32-bit in the keys and in stream 1's counts */
    if (!a->keep && !(a->keep = calloc(1, sizeof *a->keep))) return IS_ERR_OUTOFMEMORY;
    tess_adaptive_keep *k = a->keep;
    if (!k->grid_pts) k->grid_pts = malloc(core_grid_points(CORE_LOD_MAX_LEVEL) * sizeof *k->grid_pts);
    if (!k->grid_idx) k->grid_idx = malloc(3 * core_grid_triangles(CORE_LOD_MAX_LEVEL) * sizeof *k->grid_idx);
    if (!k->grid_pts || !k->grid_idx) return IS_ERR_OUTOFMEMORY;
    if (k->dev != dev) tess_resources_free(&a->r), k->dev = dev;   /* another device's buffers: made again */
    if (n > k->n_tri) {   /* (all five arrays at once: n_tri is the room of each) */
        free(k->keys), free(k->tperm), free(k->inst), free(a->tri), free(a->perm);
        k->keys = malloc(2 * n * sizeof *k->keys), k->tperm = malloc(n * sizeof *k->tperm);
        k->inst = malloc(n * sizeof *k->inst);
        a->tri = malloc(n * sizeof *a->tri), a->perm = malloc(n * sizeof *a->perm);
        k->n_tri = k->keys && k->tperm && k->inst && a->tri && a->perm ? n : 0;
        if (!k->n_tri) return IS_ERR_OUTOFMEMORY;
    }
    triangle_keys(m, e, k->keys, k->tperm);
    sort_keys(k->keys, k->keys + n, n);
    return bind_sorted(dev, m, k->keys, (const uint8_t (*)[3])k->tperm, cache, a);
}

is_result tess_draw_bucket(is_device *dev, const tess_adaptive *a, size_t k)
{
    if (!dev || !a || k >= a->n_buckets || !a->buckets) return IS_ERR_INVALIDCALL;
    const tess_bucket *b = &a->buckets[k];
    is_result e = dev_set_stream_source(dev, 1, a->r.vb1, b->first * (unsigned)sizeof(is_patch_instance),
                                        sizeof(is_patch_instance));
    if (e == IS_OK && a->r.vb2)
        e = dev_set_stream_source(dev, 2, a->r.vb2, b->first * (unsigned)sizeof(float3[3][2]), sizeof(float3[3][2]));
    if (e == IS_OK) e = dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | b->count);
    if (e == IS_OK)
        e = dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, b->base_vertex, 0, b->n_points, b->start_index,
                                       b->n_prims);
    return e;
}
