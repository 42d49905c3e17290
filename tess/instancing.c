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

void tess_adaptive_free(tess_adaptive *a)
{
    if (!a) return;
    tess_resources_free(&a->r);
    free(a->buckets), free(a->tri), free(a->perm);
    memset(a, 0, sizeof *a);
}

/* Patterns' points and indices gathered on the host before the buffers are created. */
typedef struct pattern_pool {
    float3 *pts;
    uint32_t *idx;
    size_t n_pts, n_idx, cap_pts, cap_idx, max_points;
} pattern_pool;

/* Grow *p (elements of size sz) to hold need; false when out of memory. */
static bool grow(void **p, size_t *cap, size_t need, size_t sz)
{
    if (need <= *cap) return true;
    size_t c = *cap ? *cap : 1024;
    while (c < need) c *= 2;
    void *q = realloc(*p, c * sz);
    if (!q) return false;
    *p = q, *cap = c;
    return true;
}

/* Append pattern g (its triangles, then the same with indices 1 and 2 swapped) to the pool; bucket b gets its
 * base vertex, point count, start index (of the unflipped range) and triangle count.  False when out of memory. */
static bool pool_add(pattern_pool *pool, const core_grid *g, tess_bucket *b)
{
    if (!grow((void **)&pool->pts, &pool->cap_pts, pool->n_pts + g->n_points, sizeof(float3)) ||
        !grow((void **)&pool->idx, &pool->cap_idx, pool->n_idx + 6 * g->n_triangles, sizeof(uint32_t)))
        return false;
    b->base_vertex = (int)pool->n_pts, b->n_points = (unsigned)g->n_points;
    b->start_index = (unsigned)pool->n_idx, b->n_prims = (unsigned)g->n_triangles;
    memcpy(pool->pts + pool->n_pts, g->bary, g->n_points * sizeof(float3));
    uint32_t *d = pool->idx + pool->n_idx;
    for (size_t t = 0; t < g->n_triangles; t++) {
        const uint32_t *s = &g->idx[3 * t];
        d[3 * t] = s[0], d[3 * t + 1] = s[1], d[3 * t + 2] = s[2];
        uint32_t *f = d + 3 * g->n_triangles + 3 * t;
        f[0] = s[0], f[1] = s[2], f[2] = s[1];
    }
    pool->n_pts += g->n_points, pool->n_idx += 6 * g->n_triangles;
    if (g->n_points > pool->max_points) pool->max_points = g->n_points;
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

static int cmp_u64(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

/* Sorted keys in; a->buckets, a->tri, a->perm (reordered from by-triangle tperm) and the pool filled.  IS_OK or
 * IS_ERR_OUTOFMEMORY. */
static is_result make_buckets(const uint64_t *keys, size_t n, const uint8_t (*tperm)[3], core_pattern_cache *cache,
                              tess_adaptive *a, pattern_pool *pool)
{
    size_t cap = 0;
    uint64_t pattern_key = UINT64_MAX;
    tess_bucket last = {0};
    for (size_t i = 0; i < n; i++) {
        const uint32_t t = (uint32_t)keys[i];
        a->tri[i] = t;
        memcpy(a->perm[i], tperm[t], 3);
        const uint64_t key = keys[i] >> 32;
        if (i > 0 && key == keys[i - 1] >> 32) { a->buckets[a->n_buckets - 1].count++; continue; }
        if (!grow((void **)&a->buckets, &cap, a->n_buckets + 1, sizeof *a->buckets)) return IS_ERR_OUTOFMEMORY;
        tess_bucket *b = &a->buckets[a->n_buckets++];
        *b = (tess_bucket){.odd = key & 1, .first = (unsigned)i, .count = 1};
        const uint64_t pk = key >> 1;
        b->level[0] = (int)(pk / (CORE_LOD_MAX_LEVEL * CORE_LOD_MAX_LEVEL)) + 1;
        b->level[1] = (int)(pk / CORE_LOD_MAX_LEVEL % CORE_LOD_MAX_LEVEL) + 1;
        b->level[2] = (int)(pk % CORE_LOD_MAX_LEVEL) + 1;
        if (pk != pattern_key) {
            const core_grid *g = core_pattern_get(cache, b->level[0], b->level[1], b->level[2]);
            if (!g || !pool_add(pool, g, b)) return IS_ERR_OUTOFMEMORY;
            pattern_key = pk, a->n_patterns++;
        } else {
            b->base_vertex = last.base_vertex, b->n_points = last.n_points;
            b->start_index = last.start_index, b->n_prims = last.n_prims;
        }
        last = *b;
    }
    for (size_t k = 0; k < a->n_buckets; k++) {
        a->n_triangles += (size_t)a->buckets[k].count * a->buckets[k].n_prims;
        if (a->buckets[k].odd) a->buckets[k].start_index += 3 * a->buckets[k].n_prims;
    }
    return IS_OK;
}

/* The pool and the sorted instances into device buffers, bound with Listing 1.1.2's declaration. */
static is_result upload_adaptive(is_device *dev, const is_mesh *m, const pattern_pool *pool, tess_adaptive *a)
{
    tess_resources *r = &a->r;
    is_patch_instance *inst = malloc(m->n_triangles * sizeof *inst);
    if (!inst) return IS_ERR_OUTOFMEMORY;
    is_result e = dev_create_vertex_buffer(dev, pool->n_pts * sizeof(float3), &r->vb0);
    if (e == IS_OK) e = dev_create_vertex_buffer(dev, m->n_triangles * sizeof(is_patch_instance), &r->vb1);
    if (e == IS_OK) e = tess_index_buffer(dev, pool->idx, pool->n_idx, pool->max_points, &r->ib);
    if (e == IS_OK) e = dev_create_vertex_declaration(dev, mesh_patch_declaration, &r->decl);
    if (e == IS_OK) {
        memcpy(vb_lock(r->vb0), pool->pts, pool->n_pts * sizeof(float3));
        mesh_build_instances(m, inst);
        is_patch_instance *out = vb_lock(r->vb1);
        for (size_t i = 0; i < m->n_triangles; i++) tess_permute_instance(&inst[a->tri[i]], a->perm[i], &out[i]);
        dev_set_vertex_declaration(dev, r->decl);
        dev_set_stream_source(dev, 0, r->vb0, 0, sizeof(float3));
        dev_set_indices(dev, r->ib);
        dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1u);
    }
    free(inst);
    return e;
}

is_result tess_bind_adaptive(is_device *dev, const is_mesh *m, const tess_lod_edges *e, core_pattern_cache *cache,
                              tess_adaptive *a)
{
    if (!a) return IS_ERR_INVALIDCALL;
    memset(a, 0, sizeof *a);
    if (!dev || !m || !e || !cache || !m->n_triangles || e->n_edges == 0) return IS_ERR_INVALIDCALL;
    const size_t n = m->n_triangles;
    uint64_t *keys = malloc(n * sizeof *keys);
    uint8_t (*tperm)[3] = malloc(n * sizeof *tperm);
    a->tri = malloc(n * sizeof *a->tri), a->perm = malloc(n * sizeof *a->perm);
    pattern_pool pool = {0};
    is_result r = keys && tperm && a->tri && a->perm ? IS_OK : IS_ERR_OUTOFMEMORY;
    if (r == IS_OK) {
        triangle_keys(m, e, keys, tperm);
        qsort(keys, n, sizeof *keys, cmp_u64);
        r = make_buckets(keys, n, (const uint8_t (*)[3])tperm, cache, a, &pool);
    }
    if (r == IS_OK) r = upload_adaptive(dev, m, &pool, a);
    free(keys), free(tperm), free(pool.pts), free(pool.idx);
    return r;
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
