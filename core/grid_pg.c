/* core/grid_pg.c -- the triangle pattern of the OpenGL 4 / Direct3D 11 tessellation primitive generator
 * (seed 001, section 4.3 and Figs. 10-11; OpenGL 4.x core specification, "Triangle Tessellation" and the
 * tessellation spacing rules before it -- the Vulkan specification's "Triangle Tessellation" is the same text).
 *
 * Spacing: a level f is clamped and rounded up to n segments: equal -> the next integer, fractional_odd -> the
 * next odd, fractional_even -> the next even.  Fractional levels give n-2 segments of length 1 and two of
 * length (f-(n-2))/2 (in level units; the total is f), placed symmetrically next to the middle of the edge
 * (meeting at the midpoint for even n, flanking the middle segment for odd n), so points move continuously
 * with f and new points split off old ones.
 * Rings: the inner level gives n segments.  Ring r = 1..n/2 is the concentric triangle whose corners lie on the
 * lines from the patch corners to the centre, where the perpendiculars through point r of the two adjacent
 * edges meet; its edges carry segments r..n-r-1 projected onto them (each ring drops the first and last
 * segment of the ring outside it).  n-2r = 0 is the centre point; n-2r = 1 the innermost triangle, emitted as is.
 * Ring 0, the patch's edges, is subdivided by the three outer levels instead.
 * Bands: between two neighbouring rings each edge bounds a trapezoid (outer edge, inner edge, two pieces of the
 * medians).  It is zipped from end to end: each triangle takes two adjacent points of one side and one point of
 * the other, advancing the side whose next segment's midpoint (projected onto the edge) comes first.
 *
 * Choices the spec leaves to the implementation (or that keep every triangle non-degenerate):
 *  - inner level 1 with an outer level above 1: the spec's "1 + epsilon" would give a centre point (equal) or,
 *    for fractional_odd, an inner triangle on the patch's edges and zero-area triangles around it; instess
 *    uses the centre point for every spacing.
 *  - a fractional level within 1/1024 above n-2 (short segments under 1/2048 level units) is taken as n-2.
 *  - fractional_odd is clamped to [1, 63] (the spec's maxLevel - 1), so no edge has more than 64 segments.
 * Watertightness: a point of edge k has exactly 0.0f in its third coordinate and its two others computed each
 * from the count of segments from its own end; with equal spacing that is (float)k / (float)n, bit for bit
 * core_grid_regular's edge points. */
#include <stdlib.h>
#include <string.h>

#include "core.h"
#include "hlsl.h"

/* A fractional level less than this above n-2 (the two short segments together, in level units) is taken as n-2. */
#define PG_SNAP (1.0 / 1024.0)
/* A regular grid's level beyond this is an error (core_grid_index's int arithmetic, and memory). */
#define PG_REGULAR_MAX_LEVEL ((float)CORE_GRID_REGULAR_MAX_LEVEL)
/* The most segments on an edge: CORE_PG_MAX_LEVEL as an integer. */
enum { PG_MAX_SEGMENTS = 64 };
_Static_assert(PG_MAX_SEGMENTS == (int)CORE_PG_MAX_LEVEL, "PG_MAX_SEGMENTS follows CORE_PG_MAX_LEVEL");

/* One edge's subdivision: n segments at the clamped level f. */
typedef struct pg_spacing {
    int n;
    double f;
    bool equal;
} pg_spacing;

/* A ring's points: base index and segments per edge (edge e runs from corner e to corner e+1). */
typedef struct pg_ring {
    uint32_t base;
    int m[3];
} pg_ring;

/* Spacing in, the range of levels it takes out ([lo, hi]: the spec's clamps). */
static void pg_range(core_grid_kind kind, double *lo, double *hi)
{
    *lo = kind == CORE_GRID_PG_FRACTIONAL_EVEN ? 2.0 : 1.0;
    *hi = kind == CORE_GRID_PG_FRACTIONAL_ODD ? (double)CORE_PG_MAX_LEVEL - 1.0 : (double)CORE_PG_MAX_LEVEL;
}

float core_grid_pg_clamp(core_grid_kind kind, float level)
{
    double lo, hi;
    pg_range(kind, &lo, &hi);
    return (float)fmin(fmax((double)level, lo), hi);
}

/* Level and spacing in, n segments and clamped level out; false for a non-finite level. */
static bool pg_spacing_of(core_grid_kind kind, float level, pg_spacing *s)
{
    if (!isfinite(level)) return false;
    const bool odd = kind == CORE_GRID_PG_FRACTIONAL_ODD;
    double lo, hi;
    pg_range(kind, &lo, &hi);
    double f = fmin(fmax((double)level, lo), hi);
    int n = (int)ceil(f);
    s->equal = kind == CORE_GRID_PG_EQUAL;
    if (!s->equal) {
        if ((n % 2 == 1) != odd) n++;
        if (n - 2 >= lo && f - (double)(n - 2) < PG_SNAP) n -= 2, f = (double)n;
    } else {
        f = (double)n;
    }
    s->n = n;
    s->f = f;
    return true;
}

/* Spacing and k in 0..n in, the fraction of the edge covered by its first k segments out (double). */
static double pg_x(const pg_spacing *s, int k)
{
    if (s->equal || s->n < 3) return (double)k / (double)s->n; /* n = 1, 2: f = n, all segments equal */
    const double h = 0.5 * (s->f - (double)(s->n - 2));         /* each short segment; the others are 1 */
    const int a = s->n % 2 ? (s->n - 3) / 2 : s->n / 2 - 1;     /* the first short segment ... */
    const int b = s->n - 1 - a;                                 /* ... and its mirror */
    const int shorts = (k > a) + (k > b);
    return ((double)k - shorts * (1.0 - h)) / s->f;
}

/* Spacing and k in, the float weight of the far corner at k segments from the near one (edge points). */
static float pg_edge_coord(const pg_spacing *s, int k)
{
    if (s->equal) return (float)k / (float)s->n; /* exactly core_grid_regular's k/L */
    return (float)pg_x(s, k);
}

/* Ring, edge and i in 0..m[e] in, the point's index out (i = m[e] is the next edge's first point). */
static uint32_t pg_ring_index(const pg_ring *R, int e, int i)
{
    if (i == R->m[e]) e = (e + 1) % 3, i = 0;
    uint32_t off = 0;
    for (int q = 0; q < e; q++) off += (uint32_t)R->m[q];
    return R->base + off + (uint32_t)i;
}

/* Band on edge e between rings O (outside) and I (inside) with their points' projected positions po[0..m],
 * pi[0..m] in; its triangles appended at idx[t..], the new t out. */
static size_t pg_zip(const pg_ring *O, const pg_ring *I, int e, const double *po, const double *pi,
                     uint32_t *idx, size_t t)
{
    const int a = O->m[e], b = I->m[e];
    int i = 0, j = 0;
    while (i < a || j < b) {
        bool outer = j == b;
        if (i < a && j < b) {
            /* compare the next segments' midpoints (doubled); ties go outside in the first half, so the
             * pattern is mirror-symmetric */
            const double mo = po[i] + po[i + 1], mi = pi[j] + pi[j + 1];
            outer = mo < mi || (mo == mi && mo < 1.0);
        }
        if (outer) {
            idx[t++] = pg_ring_index(O, e, i);
            idx[t++] = pg_ring_index(O, e, i + 1);
            idx[t++] = pg_ring_index(I, e, j);
            i++;
        } else {
            idx[t++] = pg_ring_index(O, e, i);
            idx[t++] = pg_ring_index(I, e, j + 1);
            idx[t++] = pg_ring_index(I, e, j);
            j++;
        }
    }
    return t;
}

/* Inner positions X[0..n] and ring r >= 1 in, the ring's points written at bary[base..]. */
static void pg_ring_points(const double *X, int n, int r, float3 *bary)
{
    const int m = n - 2 * r;
    if (m == 0) {
        bary[0] = f3(1.0f / 3.0f, 1.0f / 3.0f, 1.0f / 3.0f);
        return;
    }
    const double sigma = 1.0 - 2.0 * X[r]; /* the ring's scale about the centre */
    for (int e = 0; e < 3; e++) {
        for (int i = 0; i < m; i++) {
            const double tau = X[r + i] - X[r]; /* distance along the edge from the ring's corner */
            float c[3];
            c[e] = (float)(1.0 / 3.0 + 2.0 * sigma / 3.0 - tau);
            c[(e + 1) % 3] = (float)(1.0 / 3.0 - sigma / 3.0 + tau);
            c[(e + 2) % 3] = (float)(1.0 / 3.0 - sigma / 3.0);
            bary[e * m + i] = f3(c[0], c[1], c[2]);
        }
    }
}

/* Outer spacings in, the patch's edge points (ring 0) written at bary[0..]. */
static void pg_outer_points(const pg_spacing s[3], float3 *bary)
{
    size_t p = 0;
    for (int e = 0; e < 3; e++) {
        for (int i = 0; i < s[e].n; i++) {
            float c[3] = {0.0f, 0.0f, 0.0f};
            if (i == 0) {
                c[e] = 1.0f;
            } else {
                c[e] = pg_edge_coord(&s[e], s[e].n - i);   /* from corner e+1's end */
                c[(e + 1) % 3] = pg_edge_coord(&s[e], i);  /* from corner e's end */
            }
            bary[p++] = f3(c[0], c[1], c[2]);
        }
    }
}

/* Inner and outer spacings in; rings[0..n/2] laid out, the point count returned and the triangle count in
 * *n_tris. */
static size_t pg_layout(const pg_spacing *in, const pg_spacing os[3], pg_ring *rings, size_t *n_tris)
{
    const int n = in->n;
    size_t n_points = 0, tris = (size_t)(n % 2); /* the innermost triangle for odd n */
    for (int r = 0; r <= n / 2; r++) {
        pg_ring *g = &rings[r];
        g->base = (uint32_t)n_points;
        for (int e = 0; e < 3; e++) g->m[e] = r == 0 ? os[e].n : n - 2 * r;
        const int per_ring = g->m[0] + g->m[1] + g->m[2];
        n_points += per_ring ? (size_t)per_ring : 1;
        if (r > 0) tris += (size_t)(rings[r - 1].m[0] + rings[r - 1].m[1] + rings[r - 1].m[2] + per_ring);
    }
    *n_tris = tris;
    return n_points;
}

/* Spacings and the rings' layout in; the points and triangles written to bary and idx; the index count out. */
static size_t pg_fill(const pg_spacing *in, const pg_spacing os[3], const pg_ring *rings, float3 *bary,
                      uint32_t *idx)
{
    const int n = in->n, R = n / 2;
    double X[PG_MAX_SEGMENTS + 1], po[PG_MAX_SEGMENTS + 1]; /* inner positions; one edge's outside positions */
    for (int k = 0; k <= n; k++) X[k] = pg_x(in, k);
    pg_outer_points(os, bary);
    for (int r = 1; r <= R; r++) pg_ring_points(X, n, r, bary + rings[r].base);
    size_t t = 0;
    for (int r = 0; r < R; r++) {
        for (int e = 0; e < 3; e++) {
            for (int i = 0; i <= rings[r].m[e]; i++) po[i] = r == 0 ? pg_x(&os[e], i) : X[r + i];
            t = pg_zip(&rings[r], &rings[r + 1], e, po, X + r + 1, idx, t);
        }
    }
    if (n % 2) /* the innermost triangle, one segment per edge */
        for (int e = 0; e < 3; e++) idx[t++] = pg_ring_index(&rings[R], e, 0);
    return t;
}

/* Spacing, inner and outer levels in; the grid out (allocated).  0, or -1 for a bad level or no memory. */
int core_grid_pg(core_grid_kind spacing, float inner, const float outer[3], core_grid *out)
{
    if (!out) return -1;
    memset(out, 0, sizeof *out);
    if (!outer || (spacing != CORE_GRID_PG_EQUAL && spacing != CORE_GRID_PG_FRACTIONAL_ODD &&
                   spacing != CORE_GRID_PG_FRACTIONAL_EVEN))
        return -1;
    pg_spacing in, os[3];
    if (!pg_spacing_of(spacing, inner, &in)) return -1;
    for (int e = 0; e < 3; e++)
        if (!pg_spacing_of(spacing, outer[e], &os[e])) return -1;

    const bool single = in.n == 1 && os[0].n == 1 && os[1].n == 1 && os[2].n == 1;
    if (in.n == 1) in = (pg_spacing){.n = 2, .f = 2.0, .equal = true}; /* see the top: the centre point */
    pg_ring rings[PG_MAX_SEGMENTS / 2 + 1];
    size_t n_tris = 1, n_points = single ? 3 : pg_layout(&in, os, rings, &n_tris);
    out->bary = malloc(n_points * sizeof *out->bary);
    out->idx = malloc(3 * n_tris * sizeof *out->idx);
    if (!out->bary || !out->idx) return core_grid_free(out), -1;
    if (single) { /* all levels 1: the triangle itself */
        out->bary[0] = f3(1.0f, 0.0f, 0.0f), out->bary[1] = f3(0.0f, 1.0f, 0.0f), out->bary[2] = f3(0.0f, 0.0f, 1.0f);
        out->idx[0] = 0, out->idx[1] = 1, out->idx[2] = 2;
    } else if (pg_fill(&in, os, rings, out->bary, out->idx) != 3 * n_tris) {
        return core_grid_free(out), -1; /* cannot happen: pg_layout counts what the zips emit */
    }
    out->n_points = n_points;
    out->n_triangles = n_tris;
    return 0;
}

/* Kind and one level in; the grid out (allocated).  0, or -1 for a bad level or no memory. */
int core_grid_make(core_grid_kind kind, float level, core_grid *out)
{
    if (!out) return -1;
    memset(out, 0, sizeof *out);
    if (!isfinite(level)) return -1;
    if (kind != CORE_GRID_REGULAR) {
        const float outer[3] = {level, level, level};
        return core_grid_pg(kind, level, outer, out);
    }
    const float l = roundf(level);
    if (l > PG_REGULAR_MAX_LEVEL) return -1;
    const int L = l < 1.0f ? 1 : (int)l;
    out->bary = malloc(core_grid_points(L) * sizeof *out->bary);
    out->idx = malloc(3 * core_grid_triangles(L) * sizeof *out->idx);
    if (!out->bary || !out->idx) return core_grid_free(out), -1;
    out->n_points = core_grid_regular(L, out->bary, out->idx);
    out->n_triangles = core_grid_triangles(L);
    return 0;
}

/* Grid in; its memory freed and the struct zeroed (NULL or an empty grid is fine). */
void core_grid_free(core_grid *g)
{
    if (!g) return;
    free(g->bary);
    free(g->idx);
    memset(g, 0, sizeof *g);
}
