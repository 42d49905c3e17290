/* core/draw_cull.c -- pre-tessellation culling (dev_set_patch_cull): an instance of an instanced triangle draw is
 * skipped before any of its vertices is shaded when its shader's hull stage (is_vs_hull_fn) proves that the
 * rasterizer would draw none of its triangles [Hasselgren, Munkberg and Akenine-Moller 2009].  Two tests:
 *
 *  - Outside one plane: every oPos of the patch lies within err of the convex hull of the position coefficients,
 *    so when every coefficient is beyond the near plane (z < 0), the far plane (z > w) or, with w > 0, a side of
 *    the viewport by more than a pixel (x/w > 1 + mu: every pixel box of every triangle is empty, whatever the
 *    sample offsets), by more than the error, every triangle is clipped away or covers no pixel of the viewport.
 *  - Facing away: with the grid's triangles in stream 0 a regular barycentric grid (edges h u, h v, h (v - u),
 *    one winding; checked once per draw from the grid's POSITION0) and the hull a polynomial Q of degree d, a
 *    grid triangle (a, a + h X, a + h Y) at domain point b has det3(Q(a), Q(b) - Q(a), Q(c) - Q(a)) (rows x, y, w)
 *    = h^2 F(b) with F = det3(Q, Xh, Yh), Xh = (Q(b + h X) - Q(b)) / h exactly (Taylor): F is a polynomial of
 *    degree 3 d - 2 over the triangle where such corners lie, and its Bernstein coefficients (sums of the
 *    coefficient triples' determinants), refined by bisection, bound it from below.  The rasterizer culls by
 *    the sign of the doubled screen area after snapping to 1/256 px, A = sx sy det3 / (wa wb wc), and snapping
 *    moves A by at most |b - a|_1 + |c - a|_1 + 2 (screen units); the shader's rounding moves each vertex by at
 *    most err.  When the patch is inside the clip volume (no triangle is clipped), w > 0 on it and the bound on
 *    |A| beats both, every triangle is culled (or degenerate).
 *
 * All bounds are evaluated in double with slack for its own rounding; tests/test_patch_cull.c renders random
 * views with and without the cull and compares the bytes. */
#include "device_internal.h"

#include <stddef.h>
#include <string.h>

/* Largest deviation of a grid triangle from the ideal (a, a + h X, a + h Y), relative to h, for a grid to be
 * regular (float grids are off by a few ulps). */
#define CULL_GRID_TOL 0x1p-16
/* Slack of the position hull over the widened domain, relative to its largest coordinate. */
#define CULL_POS_SLACK 0x1p-20
/* Slack of F (degree 3 d - 2) over the widened domain, relative to its largest coefficient, and the bisections
 * of its triangle tried before giving up. */
#define CULL_F_SLACK 0x1p-16
#define CULL_SUBDIVISIONS 6
/* Slack of the difference quotients Xh over the widened domain (IS_HULL_DOMAIN_SLACK), relative to their size. */
#define CULL_DER_SLACK 0x1p-14

/* fmax / fmin without the libm call (a NaN in b comes out, one in a gives b: the callers check the results with isfinite or comparisons that a NaN fails). */
static inline double dmax(double a, double b) { return a > b ? a : b; }
static inline double dmin(double a, double b) { return a < b ? a : b; }

/* Edge directions in (b0, b1, b2): u, v, v - u, -u; pair p of the regular grid's winding uses (X, Y) =
 * pair_dir[p] (0: (u, v), 1: (v, v - u), 2: (v - u, -u)); the reversed winding the same pairs swapped. */
static const double dir3[4][3] = {{-1, 1, 0}, {-1, 0, 1}, {0, -1, 1}, {1, -1, 0}};
static const int pair_dir[3][2] = {{0, 1}, {1, 2}, {2, 3}};

/* |d - h e|_1 for 3-vectors. */
static double dev1(const double d[3], double h, const double e[3])
{
    return fabs(d[0] - h * e[0]) + fabs(d[1] - h * e[1]) + fabs(d[2] - h * e[2]);
}

/* Slack of domain point b: how far it is outside the simplex (|sum - 1| plus its negative components). */
static double domain_slack(const double b[3])
{
    double s = fabs(b[0] + b[1] + b[2] - 1.0);
    for (int k = 0; k < 3; k++) s += b[k] < 0.0 ? -b[k] : 0.0;
    return s;
}

/* Match grid triangle b[0..3) (domain points) to an ideal triangle (a, a + h e1, a + h e2) of a pair and winding
 * (+1 / -1), with spacing h_fixed (> 0) or its own (0): *h_out, the deviation (ell-1, max over the vertices) in
 * *dev_out; false when no rotation and pair fits within CULL_GRID_TOL. */
static bool match_triangle(const double b[3][3], double h_fixed, double *h_out, double *dev_out, int *pair,
                           int *wind)
{
    for (int r = 0; r < 3; r++) {
        const double *a = b[r], *p = b[(r + 1) % 3], *c = b[(r + 2) % 3];
        double d1[3], d2[3];
        for (int k = 0; k < 3; k++) d1[k] = p[k] - a[k], d2[k] = c[k] - a[k];
        for (int q = 0; q < 6; q++) {
            const double *e1 = dir3[pair_dir[q % 3][q < 3 ? 0 : 1]], *e2 = dir3[pair_dir[q % 3][q < 3 ? 1 : 0]];
            double ee = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
            double h = h_fixed > 0.0 ? h_fixed : (d1[0] * e1[0] + d1[1] * e1[1] + d1[2] * e1[2]) / ee;
            if (!(h > 0.0)) continue;
            double dv = dmax(dev1(d1, h, e1), dev1(d2, h, e2));
            if (dv > CULL_GRID_TOL * h) continue;
            /* the ideal vertices a, a + h e1, a + h e2 must lie in the widened domain too */
            double i1[3], i2[3];
            for (int k = 0; k < 3; k++) i1[k] = a[k] + h * e1[k], i2[k] = a[k] + h * e2[k];
            double sl = dmax(domain_slack(a), dmax(domain_slack(i1), domain_slack(i2)));
            if (sl > IS_HULL_DOMAIN_SLACK) return false;
            *h_out = h, *dev_out = dv, *pair = q % 3, *wind = q < 3 ? 1 : -1;
            return true;
        }
    }
    return false;
}

/* The grid part of *cv: whether the draw's triangles (list, 3 * n_prims entries into the fetch cache) form a
 * regular grid over POSITION0, with its spacing, winding and slack. */
static void analyse_grid(const fetch_plan *fp, const float4 *cache, const uint32_t *list, size_t n_prims,
                         cull_view *cv)
{
    int q = -1;
    for (unsigned k = 0; k < fp->n_vert; k++)
        if (fp->el[fp->vert[k]].reg_offset == offsetof(is_vs_input, position[0])) q = (int)k;
    cv->on = q >= 0; /* the hull's domain is POSITION0: it must be a per-vertex element */
    if (!cv->on) return;
    bool regular = true;
    int winding = 0;
    double h0 = 0.0, slack = 0.0;
    unsigned pairs = 0;
    for (size_t t = 0; t < n_prims && regular; t++) {
        double b[3][3];
        for (int c = 0; c < 3; c++) {
            const float4 r = cache[(size_t)list[3 * t + c] * fp->n_vert + (unsigned)q];
            b[c][0] = r.x, b[c][1] = r.y, b[c][2] = r.z;
            if (!(domain_slack(b[c]) <= IS_HULL_DOMAIN_SLACK)) cv->on = false, regular = false;
        }
        double h, dv;
        int pair, w;
        if (!regular || !match_triangle(b, h0, &h, &dv, &pair, &w) || (winding && w != winding)) {
            regular = false;
            break;
        }
        winding = w, pairs |= 1u << pair;
        h0 = h, slack = dmax(slack, dv); /* every triangle measured against the first one's spacing */
    }
    cv->backface = regular && n_prims > 0;
    cv->winding = winding, cv->pairs = pairs, cv->h = h0, cv->grid_slack = slack;
}

/* Prepare the cull of an instanced triangle draw: *cv->on false when no instance can be culled. */
void cull_prepare(const is_device *dev, const fetch_plan *fp, const float4 *cache, const uint32_t *list,
                  size_t n_prims, cull_view *cv)
{
    memset(cv, 0, sizeof *cv);
    const rs_state st = dev_rs_state(dev);
    if (!dev->patch_cull || dev->reference || dev->remap.on || !dev->vs || !dev->vs->hull || st.fill_mode != RS_FILL_SOLID || !cache)
        return;
    if (st.no_clipping || st.pretransformed) return;   /* CLIPPING FALSE draws what lies beyond near and far */
    analyse_grid(fp, cache, list, n_prims, cv);
    const rs_viewport *vp = &st.viewport;
    cv->sx = (double)vp->width * ((double)RS_SUB / 2), cv->sy = (double)vp->height * ((double)RS_SUB / 2);
    cv->gx = ((double)RS_GUARD_BAND - 1.0) / (vp->width * 0.5), cv->gy = ((double)RS_GUARD_BAND - 1.0) / (vp->height * 0.5);
    cv->mux = (double)RS_SUB / cv->sx, cv->muy = (double)RS_SUB / cv->sy; /* one pixel beyond the viewport's edge */
    /* A = sx sy det3 / (wa wb wc) with sy < 0: CULL_CCW drops A < 0, i.e. det3 > 0 */
    int cm = st.cull_mode;
    if (cm != RS_CULL_CCW && cm != RS_CULL_CW) cv->backface = false;
    cv->sign = (cm == RS_CULL_CCW ? 1.0 : -1.0) * cv->winding;
}

/* The hull against the view's planes, in one pass: out[0..6) the largest distance of a coefficient beyond the
 * near, far, and the four sides one pixel out of the viewport (> 0 inside), scaled by the plane's error factor
 * (the distance's error is that times E); in_[0..6) the same for the near, far and guard-band planes. */
static void plane_extremes(const cull_view *cv, const is_patch_hull *h, double out[6], double in_[6])
{
    const double ax = 1.0 + cv->mux, ay = 1.0 + cv->muy, gx = cv->gx, gy = cv->gy;
    for (int k = 0; k < 6; k++) out[k] = in_[k] = -INFINITY;
    for (int i = 0; i < h->n_pos; i++) {
        const double x = h->pos[i][0], y = h->pos[i][1], z = h->pos[i][2], w = h->pos[i][3];
        out[0] = dmax(out[0], z), out[1] = dmax(out[1], (w - z) / 2.0);
        out[2] = dmax(out[2], (ax * w - x) / (1.0 + ax)), out[3] = dmax(out[3], (ax * w + x) / (1.0 + ax));
        out[4] = dmax(out[4], (ay * w - y) / (1.0 + ay)), out[5] = dmax(out[5], (ay * w + y) / (1.0 + ay));
        in_[0] = dmax(in_[0], -z), in_[1] = dmax(in_[1], (z - w) / 2.0);
        in_[2] = dmax(in_[2], (x - gx * w) / (1.0 + gx)), in_[3] = dmax(in_[3], (-x - gx * w) / (1.0 + gx));
        in_[4] = dmax(in_[4], (y - gy * w) / (1.0 + gy)), in_[5] = dmax(in_[5], (-y - gy * w) / (1.0 + gy));
    }
}

/* True when the hull lies beyond one plane of the view by more than its error (E per coordinate): beyond the near
 * plane (z < 0), the far plane (w - z < 0), or, with w > 0, a side (|x| > (1 + mu) w, |y| likewise). */
static bool outside_a_plane(const double out[6], double E, double wmin)
{
    if (out[0] < -E || out[1] < -E) return true;
    if (!(wmin > 0.0)) return false;
    return out[2] < -E || out[3] < -E || out[4] < -E || out[5] < -E;
}

/* True when the hull lies inside the clip volume (near, far, guard band) by more than its error: no triangle of
 * it is clipped or clamped. */
static bool inside_clip_volume(const double in_[6], double E)
{
    for (int k = 0; k < 6; k++)
        if (!(in_[k] < -E)) return false;
    return true;
}

/* The (x, y, w) of 4-vector a into o. */
static void xyw(const double *a, double o[3]) { o[0] = a[0], o[1] = a[1], o[2] = a[3]; }

static double norm3(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* Index of Bernstein coefficient (i, j, k) of degree n (exponents of b0, b1, b2) in the hull's order (k-major,
 * then j; vs/hull.c). */
static inline int bern_at(int n, int j, int k) { return k * (n + 1) - (int)((unsigned)(k * (k - 1)) >> 1) + j; }

/* Factorials up to 7 (multinomials n! / (i! j! k!) of the Bernstein products below). */
static const double fact[8] = {1, 1, 2, 6, 24, 120, 720, 5040};

/* Coefficients of degree n - 1 of the derivative along direction dir (a b-vector summing to 0) of the degree n
 * coefficients c (x, y, w) into o; the count. */
static int derive(const double (*c)[3], int n, const double dir[3], double (*o)[3])
{
    int m = 0;
    for (int k = 0; k < n; k++)
        for (int j = 0; j + k < n; j++, m++) {
            const double *c0 = c[bern_at(n, j, k)], *c1 = c[bern_at(n, j + 1, k)], *c2 = c[bern_at(n, j, k + 1)];
            double *q = o[bern_at(n - 1, j, k)];
            for (int a = 0; a < 3; a++) q[a] = n * (dir[0] * c0[a] + dir[1] * c1[a] + dir[2] * c2[a]);
        }
    return m;
}

/* Largest norm of c[0..n). */
static double max_norm(const double (*c)[3], int n)
{
    double g = 0.0;
    for (int i = 0; i < n; i++) g = dmax(g, norm3(c[i]));
    return g;
}

/* The blossom of the degree n polynomial with coefficients c (x, y, w) at the domain points args[0..n): o. */
static void blossom(const double (*c)[3], int n, const double *const *args, double o[3])
{
    double lv[IS_HULL_MAX_POS][3];
    for (int q = 0; q < (n + 1) * (n + 2) / 2; q++)
        for (int a = 0; a < 3; a++) lv[q][a] = c[q][a];
    for (int r = 0; r < n; r++) {
        const int d = n - r;
        const double *t = args[r];
        for (int k = 0; k < d; k++)
            for (int j = 0; j + k < d; j++)
                for (int a = 0; a < 3; a++) /* in place: entry (j, k) of degree d - 1 reads entries at or after it */
                    lv[bern_at(d - 1, j, k)][a] = t[0] * lv[bern_at(d, j, k)][a] + t[1] * lv[bern_at(d, j + 1, k)][a] +
                                                  t[2] * lv[bern_at(d, j, k + 1)][a];
    }
    for (int a = 0; a < 3; a++) o[a] = lv[0][a];
}

/* dg! / (i! j! k!) for dg <= 3, in the coefficients' order. */
static const double multinomial[4][10] = {{1}, {1, 1, 1}, {1, 2, 1, 2, 2, 1}, {1, 3, 3, 1, 3, 6, 3, 3, 3, 1}};

/* The degree dg (<= 3) polynomial with coefficients c at domain point b: o (the Bernstein sum). */
static void eval_q(const double (*c)[3], int dg, const double b[3], double o[3])
{
    double p0[4] = {1, b[0], b[0] * b[0], b[0] * b[0] * b[0]}, p1[4] = {1, b[1], b[1] * b[1], b[1] * b[1] * b[1]},
           p2[4] = {1, b[2], b[2] * b[2], b[2] * b[2] * b[2]};
    o[0] = o[1] = o[2] = 0.0;
    for (int k = 0; k <= dg; k++)
        for (int j = 0; j + k <= dg; j++) {
            const int i = dg - j - k;
            const double w = multinomial[dg][bern_at(dg, j, k)] * p0[i] * p1[j] * p2[k];
            const double *q = c[bern_at(dg, j, k)];
            o[0] += w * q[0], o[1] += w * q[1], o[2] += w * q[2];
        }
}

/* det3 of the ideal triangle (Q(a), Q(a + h e1), Q(a + h e2)) of the degree dg polynomial with coefficients c. */
static double ideal_det(const double (*c)[3], int dg, const double a[3], double h, const double e1[3],
                        const double e2[3])
{
    double b[3], d[3], qa[3], qb[3], qc[3];
    for (int k = 0; k < 3; k++) b[k] = a[k] + h * e1[k], d[k] = a[k] + h * e2[k];
    eval_q(c, dg, a, qa), eval_q(c, dg, b, qb), eval_q(c, dg, d, qc);
    return qa[0] * (qb[1] * qc[2] - qb[2] * qc[1]) - qa[1] * (qb[0] * qc[2] - qb[2] * qc[0]) +
           qa[2] * (qb[0] * qc[1] - qb[1] * qc[0]);
}

/* Degree elevation: the degree n + 1 coefficients of the polynomial whose degree n coefficients are c. */
static void elevate(const double (*c)[3], int n, double (*o)[3])
{
    for (int k = 0; k <= n + 1; k++)
        for (int j = 0; j + k <= n + 1; j++) {
            const int i = n + 1 - j - k;
            double *q = o[bern_at(n + 1, j, k)];
            for (int a = 0; a < 3; a++) {
                double v = 0.0;
                if (i > 0) v += i * c[bern_at(n, j, k)][a];
                if (j > 0) v += j * c[bern_at(n, j - 1, k)][a];
                if (k > 0) v += k * c[bern_at(n, j, k - 1)][a];
                q[a] = v / (n + 1);
            }
        }
}

/* The coefficients (degree dg - 1, count returned) of the divided difference (Q(b + h dir) - Q(b)) / h of the
 * degree dg polynomial with coefficients P: D Q + h/2 D^2 Q + h^2/6 D^3 Q (exact, Taylor), each elevated to
 * degree dg - 1. */
static int difference(const double (*P)[3], int dg, const double dir[3], double h, double (*o)[3])
{
    double d1[6][3], d2[6][3], d3[6][3], t[6][3];
    const int n = derive(P, dg, dir, d1);
    for (int q = 0; q < n; q++)
        for (int a = 0; a < 3; a++) o[q][a] = d1[q][a];
    if (dg >= 2) {
        derive((const double(*)[3])d1, dg - 1, dir, d2);
        if (dg >= 3) {
            derive((const double(*)[3])d2, dg - 2, dir, d3); /* degree dg - 3 = 0: one coefficient */
            double e3[6][3];
            elevate((const double(*)[3])d3, dg - 3, e3); /* to dg - 2 */
            for (int q = 0; q < (dg - 1) * dg / 2; q++)
                for (int a = 0; a < 3; a++) t[q][a] = d2[q][a] / 2.0 + h / 6.0 * e3[q][a];
        } else {
            for (int a = 0; a < 3; a++) t[0][a] = d2[0][a] / 2.0;
        }
        double e2[6][3];
        elevate((const double(*)[3])t, dg - 2, e2); /* to dg - 1 */
        for (int q = 0; q < n; q++)
            for (int a = 0; a < 3; a++) o[q][a] += h * e2[q][a];
    }
    return n;
}

/* Split the triangular Bernstein coefficients c (degree n) at the midpoint of the edge between vertices 1 and 2
 * (de Casteljau) into those of the halves (vertex order (P, V0, V1) and (P, V2, V0), P the midpoint: each half's
 * next split is then of an edge of the input triangle). */
static void bernstein_split(const double *c, int n, double *a, double *b)
{
    double lv[36];
    const int m = (n + 1) * (n + 2) / 2;
    for (int q = 0; q < m; q++) lv[q] = c[q];
    for (int r = 0; r <= n; r++) {
        /* level r: coefficients of degree n - r in lv (index bern_at(n - r, j, k)); record the faces */
        const int d = n - r;
        for (int i = 0; i <= d; i++) {
            a[bern_at(n, i, d - i)] = lv[bern_at(d, d - i, 0)];  /* (P, V0, V1) exponents (r, i, d - i) of V0^i V1^(d-i) */
            b[bern_at(n, d - i, i)] = lv[bern_at(d, 0, d - i)];  /* (P, V2, V0) exponents (r, d - i, i): V2^(d-i) V0^i */
        }
        if (d == 0) break;
        double nx[36];
        for (int k = 0; k < d; k++)
            for (int j = 0; j + k < d; j++)
                nx[bern_at(d - 1, j, k)] = 0.5 * (lv[bern_at(d, j + 1, k)] + lv[bern_at(d, j, k + 1)]);
        for (int q = 0; q < d * (d + 1) / 2; q++) lv[q] = nx[q];
    }
}

/* A lower bound of the polynomial with Bernstein coefficients c (degree n) on its triangle: the smallest
 * coefficient, refined by up to `depth` bisections while it is below `want` (then the smallest over the pieces). */
static double bernstein_min(const double *c, int n, int depth, double want)
{
    const int m = (n + 1) * (n + 2) / 2;
    double lo = INFINITY;
    for (int q = 0; q < m; q++) lo = c[q] < lo ? c[q] : lo;
    if (lo > want || depth == 0) return lo;
    /* the corner coefficients are the polynomial's values there: no bisection raises them */
    const double corner = dmin(c[bern_at(n, 0, 0)], dmin(c[bern_at(n, n, 0)], c[bern_at(n, 0, n)]));
    if (!(corner > want)) return corner;
    double hi = -INFINITY;
    for (int q = 0; q < m; q++) hi = dmax(hi, c[q]);
    if (!(hi > want)) return lo; /* every coefficient at or below: no piece can do better than... give up */
    double a[36], b[36];
    bernstein_split(c, n, a, b);
    double la = bernstein_min(a, n, depth - 1, want);
    if (!(la > want)) return la;
    return dmin(la, bernstein_min(b, n, depth - 1, want));
}

/* The corners a of pair p's ideal triangles (a, a + h X, a + h Y) lie where b_k >= h for every k that an edge
 * direction decreases: the triangle V_i = m + s e_i; s into *s (<= 0: no such triangle). */
static void pair_region(const cull_view *cv, int p, double V[3][3], double *s)
{
    const double *ed1 = dir3[pair_dir[p][0]], *ed2 = dir3[pair_dir[p][1]];
    double mk[3];
    *s = 1.0;
    for (int k = 0; k < 3; k++) mk[k] = ed1[k] < 0.0 || ed2[k] < 0.0 ? cv->h : 0.0, *s -= mk[k];
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) V[i][k] = mk[k] + (i == k ? *s : 0.0);
}

/* A quick necessary condition for pair_faces_away (most instances fail it): the ideal triangles at the centre
 * and the corners of the pair's region face away (exactly, without margins). */
static bool pair_may_face_away(const cull_view *cv, int p, const double (*P0)[3], int dg)
{
    double V[3][3], s;
    pair_region(cv, p, V, &s);
    if (!(s > 0.0)) return false;
    for (int i = 0; i < 4; i++) {
        double a[3];
        for (int k = 0; k < 3; k++) a[k] = i > 0 ? V[i - 1][k] : (V[0][k] + V[1][k] + V[2][k]) / 3.0;
        if (!(cv->sign * ideal_det(P0, dg, a, cv->h, dir3[pair_dir[p][0]], dir3[pair_dir[p][1]]) > 0.0)) return false;
    }
    return true;
}

/* True when every grid triangle whose edges follow pair p is back-facing (for the cull mode) with a margin that
 * beats snapping and the error E.  The ideal triangle (a, a + h X, a + h Y) at domain point b (Q the hull's
 * polynomial) has det3(a, b - a, c - a) = h^2 F(b), F = det3(Q, Xh, Yh) with Xh = (Q(b + h X) - Q(b)) / h (exact,
 * a polynomial of degree d - 1), so F is a polynomial of degree 3 d - 2 whose smallest Bernstein coefficient
 * bounds it on the domain (the coefficients of a product: sums of the coefficient triples' determinants).
 * P0 (x, y, w) are Q's coefficients (degree dg); wmin / wmax bound w over the shaded vertices. */
static bool pair_faces_away(const cull_view *cv, int p, const double (*P0)[3], int dg, double E, double wmin,
                            double wmax)
{
    /* Q on the region of the pair's corners (pair_region): the coefficients of its blossom, spacing h / s */
    double P[IS_HULL_MAX_POS][3], V[3][3], R = 0.0, s;
    pair_region(cv, p, V, &s);
    if (!(s > 0.0)) return false;
    for (int k = 0; k <= dg; k++)
        for (int j = 0; j + k <= dg; j++) {
            const double *args[3];
            int q = 0;
            for (int t = 0; t < dg - j - k; t++) args[q++] = V[0];
            for (int t = 0; t < j; t++) args[q++] = V[1];
            for (int t = 0; t < k; t++) args[q++] = V[2];
            double *o = P[bern_at(dg, j, k)];
            blossom(P0, dg, args, o);
            R = dmax(R, norm3(o));
        }
    const double hh = cv->h / s;
    double X[6][3], Y[6][3];
    const int nd = difference(P, dg, dir3[pair_dir[p][0]], hh, X);
    difference(P, dg, dir3[pair_dir[p][1]], hh, Y);
    const double gx = max_norm((const double(*)[3])X, nd) * (1.0 + CULL_DER_SLACK),
                 gy = max_norm((const double(*)[3])Y, nd) * (1.0 + CULL_DER_SLACK);
    /* F's Bernstein coefficients: c_g += M(a) M(b) M(c) / M(g) det3(P_a, X_b, Y_c) over a + b + c = g, with
     * M(a) = n! / (a0! a1! a2!): the factorials of g go to the end, those of a, b, c into the factors */
    const int nf = 3 * dg - 2, n_f = (nf + 1) * (nf + 2) / 2;
    double F[36], Pw[IS_HULL_MAX_POS][3], Xw[6][3];
    for (int q = 0; q < n_f; q++) F[q] = 0.0;
    for (int k = 0; k <= dg; k++)
        for (int j = 0; j + k <= dg; j++) {
            double w = 1.0 / (fact[dg - j - k] * fact[j] * fact[k]);
            for (int a = 0; a < 3; a++) Pw[bern_at(dg, j, k)][a] = w * P[bern_at(dg, j, k)][a];
        }
    for (int k = 0; k < dg; k++)
        for (int j = 0; j + k < dg; j++) {
            double w = 1.0 / (fact[dg - 1 - j - k] * fact[j] * fact[k]);
            for (int a = 0; a < 3; a++) Xw[bern_at(dg - 1, j, k)][a] = w * X[bern_at(dg - 1, j, k)][a];
        }
    for (int kc = 0; kc < dg; kc++)
        for (int jc = 0; jc + kc < dg; jc++) {
            const double *y = Y[bern_at(dg - 1, jc, kc)];
            const double wc = 1.0 / (fact[dg - 1 - jc - kc] * fact[jc] * fact[kc]);
            for (int kb = 0; kb < dg; kb++)
                for (int jb = 0; jb + kb < dg; jb++) {
                    const double *x = Xw[bern_at(dg - 1, jb, kb)];
                    double cr[3] = {wc * (x[1] * y[2] - x[2] * y[1]), wc * (x[2] * y[0] - x[0] * y[2]),
                                    wc * (x[0] * y[1] - x[1] * y[0])};
                    for (int ka = 0; ka <= dg; ka++)
                        for (int ja = 0; ja + ka <= dg; ja++) {
                            const double *a = Pw[bern_at(dg, ja, ka)];
                            F[bern_at(nf, ja + jb + jc, ka + kb + kc)] += a[0] * cr[0] + a[1] * cr[1] + a[2] * cr[2];
                        }
                }
        }
    const double mf = fact[dg] * fact[dg - 1] * fact[dg - 1] / fact[nf];
    for (int k = 0; k <= nf; k++)
        for (int j = 0; j + k <= nf; j++) F[bern_at(nf, j, k)] *= mf * fact[nf - j - k] * fact[j] * fact[k];
    double fabs_ = 0.0;
    for (int q = 0; q < n_f; q++) F[q] *= cv->sign, fabs_ = dmax(fabs_, fabs(F[q]));
    /* F on the widened domain (IS_HULL_DOMAIN_SLACK), and the double rounding of the sums and subdivisions */
    const double margin = CULL_F_SLACK * fabs_ + 0x1p-40 * R * gx * gy;
    double fmin_ = bernstein_min(F, nf, CULL_SUBDIVISIONS, margin) - margin;
    if (!(fmin_ > 0.0)) return false;
    /* the shaded triangle (a', b', c'): each vertex within eta of the ideal one (ell-2 over x, y, w) */
    const double eta = sqrt(3.0) * E, xi = 2.0 * eta, Rp = R * (1.0 + CULL_POS_SLACK) + eta;
    const double e1 = hh * gx + xi, e2 = hh * gy + xi; /* |b' - a'|, |c' - a'| */
    const double low = hh * hh * fmin_ - (eta * e1 * e2 + Rp * xi * e2 + Rp * hh * gx * xi);
    if (!(low > 0.0)) return false;
    /* screen: |A| >= sx sy low / wmax^3 against |b - a|_1 + |c - a|_1 + 2 (+ 2 for the projection's rounding) */
    const double area = cv->sx * cv->sy * low / (wmax * wmax * wmax);
    const double perim = (cv->sx + cv->sy) * (wmax + Rp) / (wmin * wmin) * (e1 + e2) + 4.0;
    return area > perim * (1.0 + 0x1p-20);
}

/* True when the hull proves that the rasterizer draws nothing of the instance (see the top of the file). */
bool cull_instance(const cull_view *cv, const is_patch_hull *h)
{
    const int n = h->n_pos;
    const int d = h->degree;
    if (n < 1 || n > IS_HULL_MAX_POS || d < 0 || d > 3 || (d > 0 && n != (d + 1) * (d + 2) / 2) ||
        !(h->err >= 0.0))
        return false;
    double rinf = 0.0, P[IS_HULL_MAX_POS][3], wlo = INFINITY, whi = -INFINITY;
    for (int i = 0; i < n; i++) {
        for (int a = 0; a < 4; a++) rinf = dmax(rinf, fabs(h->pos[i][a]));
        xyw(h->pos[i], P[i]);
        wlo = dmin(wlo, h->pos[i][3]), whi = dmax(whi, h->pos[i][3]);
    }
    if (!isfinite(rinf)) return false;
    /* E: the shader's error, plus moving each vertex to its ideal grid point (gradient <= d |coefficients|) */
    const double E = (h->err + 1.01 * (d > 0 ? d : 1) * rinf * cv->grid_slack + CULL_POS_SLACK * rinf) * (1.0 + 0x1p-20);
    const double wmin = wlo - E, wmax = whi + E;
    double out[6], in_[6];
    plane_extremes(cv, h, out, in_);
    if (outside_a_plane(out, E, wmin)) return true;
    if (!cv->backface || d < 1 || !(wmin > 0.0) || !inside_clip_volume(in_, E)) return false;
    for (int p = 0; p < 3; p++) /* the quick rejections of every pair first: most instances end here */
        if ((cv->pairs & (1u << p)) && !pair_may_face_away(cv, p, (const double(*)[3])P, d)) return false;
    for (int p = 0; p < 3; p++)
        if ((cv->pairs & (1u << p)) && !pair_faces_away(cv, p, (const double(*)[3])P, d, E, wmin, wmax))
            return false;
    return true;
}
