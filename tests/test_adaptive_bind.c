/* tests/test_adaptive_bind.c -- tess_bind_adaptive's buckets and buffers against their definition, written out
 * here the plain way: each triangle's key (core_lod_order's sorted levels and parity), the triangles sorted by
 * (key, triangle) with qsort, one bucket per key, each distinct pattern as the regular grid of its largest level M
 * -- each grid point moved to the pattern's point it snaps to (an edge point to the nearest of its edge's points,
 * ties to the farther one, found among the pattern's points), then the regular grid's triangles, then the same
 * with indices 1 and 2 swapped, 16-bit -- and the instances renumbered in bucket order.  The bind sorts by radix
 * passes and sizes its pool from upper bounds (tess/instancing.c); the buckets, the renumbering, stream 0, the
 * index buffer and stream 1 must be the same bytes, for edge levels drawn at random from narrow and wide ranges
 * (up to CORE_LOD_MAX_LEVEL, so keys use every radix digit), a single level, and one triangle. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/core.h"
#include "../meshes/meshes.h"
#include "../tess/tess.h"

/* A deterministic integer in [lo, hi] from *s (a 64-bit LCG). */
static int lcg_int(uint64_t *s, int lo, int hi)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (int)((*s >> 33) % (uint64_t)(hi - lo + 1));
}

/* The definition's buffers and buckets. */
typedef struct ref_bind {
    tess_bucket *b;
    size_t n_buckets, n_patterns, n_triangles, n_pts, n_idx;
    uint32_t *tri;
    uint8_t (*perm)[3];
    float3 *pts;
    uint16_t *idx;
    is_patch_instance *inst;
} ref_bind;

static int cmp_u64(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

/* Where grid point (i, j) of level M goes in pattern g of edge levels l: an interior point stays (it is one of g's
 * points); a point on edge e (from v_e to v_(e+1)), s of M segments from v_e, goes to the point of g on that edge
 * whose k of l[e] segments is nearest s / M, the farther one on a tie. */
static float3 ref_moved(const core_grid *g, const int l[3], int M, int i, int j)
{
    const int e = j == 0 && i < M ? 0 : i + j == M && j < M ? 1 : i == 0 ? 2 : -1;
    const int s = e == 0 ? i : e == 1 ? j : M - j;
    const float3 r = {(float)(M - i - j) / (float)M, (float)i / (float)M, (float)j / (float)M};
    long best = -1, bd = 0, bk = 0;
    for (size_t q = 0; q < g->n_points; q++) {
        const float *c = &g->bary[q].x;
        if (e < 0) {
            if (!memcmp(&g->bary[q], &r, sizeof r)) return g->bary[q];
            continue;
        }
        if (c[(e + 2) % 3] != 0.0f) continue;   /* not on edge e */
        const long k = lrintf(c[(e + 1) % 3] * (float)l[e]), d = labs(k * M - (long)s * l[e]);
        if (best < 0 || d < bd || (d == bd && k > bk)) best = (long)q, bd = d, bk = k;
    }
    assert_true(best >= 0);
    return g->bary[best];
}

/* Append pattern g of levels l (sorted) as the regular grid of level l[2] -- its points moved (ref_moved), its
 * triangles straight, then with indices 1 and 2 swapped -- to r; its bucket fields into b. */
static void ref_pattern(ref_bind *r, const core_grid *g, const int l[3], tess_bucket *b)
{
    const int M = l[2];
    const size_t np = (size_t)(M + 1) * (size_t)(M + 2) / 2, nt = (size_t)M * (size_t)M;
    r->pts = realloc(r->pts, (r->n_pts + np) * sizeof *r->pts);
    r->idx = realloc(r->idx, (r->n_idx + 6 * nt) * sizeof *r->idx);
    assert_true(r->pts && r->idx);
    b->base_vertex = (int)r->n_pts, b->n_points = (unsigned)np;
    b->start_index = (unsigned)r->n_idx, b->n_prims = (unsigned)nt, b->n_tessellated = (unsigned)g->n_triangles;
    for (int j = 0; j <= M; j++)
        for (int i = 0; i + j <= M; i++) r->pts[r->n_pts + core_grid_index(M, i, j)] = ref_moved(g, l, M, i, j);
    uint16_t *d = &r->idx[r->n_idx], *f = d + 3 * nt;
    size_t t = 0;
    for (int j = 0; j < M; j++)   /* row j's cells: the upright triangle, then the inverted one before the next */
        for (int i = 0; i + j < M; i++) {
            const uint16_t up[3] = {(uint16_t)core_grid_index(M, i, j), (uint16_t)core_grid_index(M, i + 1, j),
                                    (uint16_t)core_grid_index(M, i, j + 1)};
            const uint16_t dn[3] = {(uint16_t)core_grid_index(M, i + 1, j), (uint16_t)core_grid_index(M, i + 1, j + 1),
                                    (uint16_t)core_grid_index(M, i, j + 1)};
            for (int h = 0; h < (i + j + 1 < M ? 2 : 1); h++, t++) {
                const uint16_t *v = h ? dn : up;
                d[3 * t] = v[0], d[3 * t + 1] = v[1], d[3 * t + 2] = v[2];
                f[3 * t] = v[0], f[3 * t + 1] = v[2], f[3 * t + 2] = v[1];
            }
        }
    assert_int_equal(t, nt);
    r->n_pts += np, r->n_idx += 6 * nt;
}

/* The definition for mesh m with levels e, patterns from cache. */
static void ref_build(const is_mesh *m, const tess_lod_edges *e, core_pattern_cache *cache, ref_bind *r)
{
    const size_t n = m->n_triangles;
    memset(r, 0, sizeof *r);
    uint64_t *keys = malloc(n * sizeof *keys);
    uint8_t (*tp)[3] = malloc(n * sizeof *tp);
    r->b = calloc(n, sizeof *r->b), r->tri = malloc(n * sizeof *r->tri), r->perm = malloc(n * sizeof *r->perm);
    r->inst = malloc(n * sizeof *r->inst);
    is_patch_instance *plain = malloc(n * sizeof *plain);
    assert_true(keys && tp && r->b && r->tri && r->perm && r->inst && plain);
    for (size_t t = 0; t < n; t++) {
        int lv[3], s[3], p[3];
        for (int k = 0; k < 3; k++) lv[k] = e->level[e->tri_edge[3 * t + k]];
        const bool odd = core_lod_order(lv, s, p);
        const uint64_t L = CORE_LOD_MAX_LEVEL, key = ((uint64_t)(s[0] - 1) * L + (uint64_t)(s[1] - 1)) * L + (uint64_t)(s[2] - 1);
        keys[t] = (key * 2 + odd) << 32 | t;
        for (int k = 0; k < 3; k++) tp[t][k] = (uint8_t)p[k];
    }
    qsort(keys, n, sizeof *keys, cmp_u64);
    mesh_build_instances(m, plain);
    for (size_t i = 0; i < n; i++) {
        const uint32_t t = (uint32_t)keys[i];
        r->tri[i] = t;
        memcpy(r->perm[i], tp[t], 3);
        tess_permute_instance(&plain[t], tp[t], &r->inst[i]);
        if (i > 0 && keys[i] >> 32 == keys[i - 1] >> 32) { r->b[r->n_buckets - 1].count++; continue; }
        tess_bucket *b = &r->b[r->n_buckets++];
        const uint64_t pk = keys[i] >> 33;
        const uint64_t L = CORE_LOD_MAX_LEVEL;
        *b = (tess_bucket){.level = {(int)(pk / (L * L)) + 1, (int)(pk / L % L) + 1, (int)(pk % L) + 1},
                           .odd = keys[i] >> 32 & 1, .first = (unsigned)i, .count = 1};
        if (i > 0 && pk == keys[i - 1] >> 33) {   /* the same pattern in the other parity */
            b->base_vertex = b[-1].base_vertex, b->n_points = b[-1].n_points;
            b->start_index = b[-1].start_index, b->n_prims = b[-1].n_prims, b->n_tessellated = b[-1].n_tessellated;
            continue;
        }
        const core_grid *g = core_pattern_get(cache, b->level[0], b->level[1], b->level[2]);
        assert_non_null(g);
        ref_pattern(r, g, b->level, b);
        r->n_patterns++;
    }
    for (size_t k = 0; k < r->n_buckets; k++) {
        r->n_triangles += (size_t)r->b[k].count * r->b[k].n_tessellated;
        if (r->b[k].odd) r->b[k].start_index += 3 * r->b[k].n_prims;
    }
    free(keys), free(tp), free(plain);
}

static void ref_free(ref_bind *r)
{
    free(r->b), free(r->tri), free(r->perm), free(r->pts), free(r->idx), free(r->inst);
}

/* Bucket a is b, field by field (not by memcmp: the bytes after `odd` are padding, whatever a copy leaves there). */
static void same_bucket(const tess_bucket *a, const tess_bucket *b)
{
    assert_memory_equal(a->level, b->level, sizeof a->level);
    assert_int_equal(a->odd, b->odd);
    assert_int_equal(a->first, b->first);
    assert_int_equal(a->count, b->count);
    assert_int_equal(a->base_vertex, b->base_vertex);
    assert_int_equal(a->n_points, b->n_points);
    assert_int_equal(a->start_index, b->start_index);
    assert_int_equal(a->n_prims, b->n_prims);
    assert_int_equal(a->n_tessellated, b->n_tessellated);
}

/* a (bound for m) holds the definition r: buckets, renumbering, and the buffers' used bytes (exact: the buffers
 * no larger; else at least as large, as a rebind keeps them). */
static void same_bind(const tess_adaptive *a, const ref_bind *r, const is_mesh *m, bool exact)
{
    assert_int_equal(a->n_buckets, r->n_buckets);
    assert_int_equal(a->n_patterns, r->n_patterns);
    assert_int_equal(a->n_triangles, r->n_triangles);
    for (size_t k = 0; k < r->n_buckets; k++) same_bucket(&a->buckets[k], &r->b[k]);
    assert_memory_equal(a->tri, r->tri, m->n_triangles * sizeof *r->tri);
    assert_memory_equal(a->perm, r->perm, m->n_triangles * sizeof *r->perm);
    const size_t pts = r->n_pts * sizeof *r->pts, idx = r->n_idx * sizeof *r->idx, inst = m->n_triangles * sizeof *r->inst;
    assert_true(exact ? vb_size(a->r.vb0) == pts : vb_size(a->r.vb0) >= pts);
    assert_memory_equal(vb_lock(a->r.vb0), r->pts, pts);
    assert_true(exact ? ib_size(a->r.ib) == idx : ib_size(a->r.ib) >= idx);
    assert_memory_equal(ib_lock(a->r.ib), r->idx, idx);
    assert_true(exact ? vb_size(a->r.vb1) == inst : vb_size(a->r.vb1) >= inst);
    assert_memory_equal(vb_lock(a->r.vb1), r->inst, inst);
}

/* Bind m with e's levels and compare everything with the definition. */
static void check_bind(const is_mesh *m, tess_lod_edges *e)
{
    core_pattern_cache *cache = core_pattern_cache_create(0);
    is_device *dev = dev_create(8, 8, 1, NULL, 0);
    assert_true(cache && dev);
    ref_bind r;
    ref_build(m, e, cache, &r);
    tess_adaptive a;
    assert_int_equal(tess_bind_adaptive(dev, m, e, cache, &a), IS_OK);
    same_bind(&a, &r, m, true);
    tess_adaptive_free(&a);
    ref_free(&r);
    dev_destroy(dev);
    core_pattern_cache_destroy(cache);
}

/* The built-in sphere (or its first triangle alone) with its edge table. */
static void sphere(is_mesh *m, tess_lod_edges *e, bool one)
{
    char err[256];
    assert_int_equal(mesh_builtin("sphere", m, err, sizeof err), 0);
    if (one) {
        float3 p[3], n[3];
        for (int k = 0; k < 3; k++) p[k] = m->positions[m->indices[k]], n[k] = m->normals[m->indices[k]];
        is_mesh_data md = {3, 1, p, n, NULL, (const uint32_t[]){0, 1, 2}};
        is_mesh t;
        assert_int_equal(mesh_create(&t, "one", &md, NULL, err, sizeof err), 0);
        mesh_free(m);
        *m = t;
    }
    assert_int_equal(tess_lod_edges_build(m, e, err, sizeof err), 0);
}

/* Random levels from narrow and wide ranges, and every edge at one level. */
static void test_bind_random_levels(void **state)
{
    (void)state;
    is_mesh m;
    tess_lod_edges e;
    sphere(&m, &e, false);
    static const int ranges[][2] = {{1, 3}, {1, 16}, {5, 9}, {1, CORE_LOD_MAX_LEVEL}, {60, CORE_LOD_MAX_LEVEL}, {7, 7}};
    uint64_t s = 29;
    for (size_t r = 0; r < sizeof ranges / sizeof *ranges; r++) {
        for (size_t k = 0; k < e.n_edges; k++) e.level[k] = (uint8_t)lcg_int(&s, ranges[r][0], ranges[r][1]);
        check_bind(&m, &e);
    }
    tess_lod_edges_free(&e);
    mesh_free(&m);
}

/* One triangle, its three levels in every order of a few triples (both parities). */
static void test_bind_one_triangle(void **state)
{
    (void)state;
    is_mesh m;
    tess_lod_edges e;
    sphere(&m, &e, true);
    assert_int_equal(e.n_edges, 3);
    static const int triples[][3] = {{1, 2, 3}, {3, 2, 1}, {2, 3, 1}, {64, 1, 64}, {64, 64, 64}, {1, 1, 1}};
    for (size_t k = 0; k < sizeof triples / sizeof *triples; k++) {
        for (int j = 0; j < 3; j++) e.level[j] = (uint8_t)triples[k][j];
        check_bind(&m, &e);
    }
    tess_lod_edges_free(&e);
    mesh_free(&m);
}

/* A view-dependent LOD's frames: one tess_adaptive rebound (tess_rebind_adaptive) with levels that grow, shrink
 * and repeat -- each rebind the definition's bytes; a rebind whose buffers are large enough keeps them (the same
 * handles: nothing allocated); one onto another device makes them there; one after PN-AEN's stream 2 drops it. */
static void test_rebind_frames(void **state)
{
    (void)state;
    is_mesh m;
    tess_lod_edges e;
    sphere(&m, &e, false);
    core_pattern_cache *cache = core_pattern_cache_create(0);
    is_device *dev = dev_create(8, 8, 1, NULL, 0), *other = dev_create(8, 8, 1, NULL, 0);
    assert_true(cache && dev && other);
    static const int ranges[][2] = {{1, 3}, {1, 16}, {5, 9}, {1, 3}, {1, CORE_LOD_MAX_LEVEL}, {7, 7}, {1, 16}};
    tess_adaptive a = {0};
    uint64_t s = 31;
    for (size_t f = 0; f < 2 * sizeof ranges / sizeof *ranges; f++) {
        const size_t k = f % (sizeof ranges / sizeof *ranges);
        if (f == sizeof ranges / sizeof *ranges) s = 31;   /* the second round: the same levels again */
        for (size_t q = 0; q < e.n_edges; q++) e.level[q] = (uint8_t)lcg_int(&s, ranges[k][0], ranges[k][1]);
        ref_bind r;
        ref_build(&m, &e, cache, &r);
        const is_vertex_buffer *vb0 = a.r.vb0, *vb1 = a.r.vb1;
        const is_index_buffer *ib = a.r.ib;
        const bool fits = vb0 && vb_size(vb0) >= r.n_pts * sizeof *r.pts && ib_size(ib) >= r.n_idx * sizeof *r.idx;
        assert_int_equal(tess_rebind_adaptive(dev, &m, &e, cache, &a), IS_OK);
        same_bind(&a, &r, &m, f == 0);
        if (fits) assert_true(a.r.vb0 == vb0 && a.r.ib == ib && a.r.vb1 == vb1);   /* kept */
        if (k == 4) {   /* the largest levels: from now on every rebind fits */
            assert_int_equal(tess_bind_adjacent_normals(dev, &m, &a.r, &a), IS_OK);
            assert_non_null(a.r.vb2);
        }
        if (k == 5) assert_null(a.r.vb2);   /* dropped by the rebind after it */
        ref_free(&r);
    }
    /* another device: its own buffers, the same bytes */
    ref_bind r;
    ref_build(&m, &e, cache, &r);
    const is_vertex_buffer *vb0 = a.r.vb0;
    assert_int_equal(tess_rebind_adaptive(other, &m, &e, cache, &a), IS_OK);
    assert_true(a.r.vb0 != vb0);
    same_bind(&a, &r, &m, true);
    /* a failed rebind draws nothing and is still freed */
    assert_int_equal(tess_rebind_adaptive(other, &m, NULL, cache, &a), IS_ERR_INVALIDCALL);
    assert_int_equal(a.n_buckets, 0);
    assert_int_equal(tess_draw_bucket(other, &a, 0), IS_ERR_INVALIDCALL);
    ref_free(&r);
    tess_adaptive_free(&a);
    dev_destroy(other), dev_destroy(dev);
    core_pattern_cache_destroy(cache);
    tess_lod_edges_free(&e);
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bind_random_levels),
        cmocka_unit_test(test_bind_one_triangle),
        cmocka_unit_test(test_rebind_frames),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
