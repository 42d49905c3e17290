/* raster/clip.c -- homogeneous clipping in double precision against the near plane z >= 0, the far plane
 * z <= w and the guard band |x| <= gx*w, |y| <= gy*w (which together imply w >= 0).
 *
 * The user clip planes (SetClipPlane, CLIPPLANEENABLE: dot(plane, p) >= 0 inside, in clip space) come after near
 * and far and before the guard band, with the same parametric intersection; CLIPPING FALSE leaves the guard band
 * alone (rs_job.clip_mask).
 *
 * Near and far planes: parametric intersection in 4D.  The guard band: with coordinates like 1e30 the
 * parametric point loses every digit that matters on screen (t = 0.5 - 1e-27 rounds to 0.5), so the screen
 * position of a guard-band intersection comes from projective lines in (x, y, w) instead: the edge's line
 * L = A x B (products of floats are exact in double, so L is accurate to a few ulps relative) crossed with
 * the guard line G gives the point accurately; depth, w and the attributes still come from the parametric t.
 * Each edge keeps the line of its input edge, so later planes reuse it rather than a rounded sub-edge.
 *
 * Watertightness: an intersection is always computed from the inside vertex towards the outside one, and
 * B x A = -(A x B) exactly, so the two triangles sharing an edge produce bitwise the same new vertex whatever
 * their edge directions.  Planes are visited in a fixed order, and a triangle is clipped only against planes
 * one of its vertices violates (an edge with both ends inside a plane is unchanged by it).
 */
#include "raster_internal.h"

/* Guard-band planes 2..5 as projective lines (a, b, c): inside when a*x + b*y + c*w >= 0. */
static void guard_line(const rs_job *j, int k, double g[3])
{
    g[0] = k == 2 ? 1.0 : (k == 3 ? -1.0 : 0.0);
    g[1] = k == 4 ? 1.0 : (k == 5 ? -1.0 : 0.0);
    g[2] = k <= 3 ? j->gx : j->gy;
}

/* Signed distance of homogeneous point p to clip plane k (>= 0 inside); planes 6.. are the user planes. */
static double plane_dist(const rs_job *j, const double *p, int k)
{
    if (k >= RS_CLIP_PLANES) {
        const float *u = j->st->clip_plane[k - RS_CLIP_PLANES];
        return (double)u[0] * p[0] + (double)u[1] * p[1] + (double)u[2] * p[2] + (double)u[3] * p[3];
    }
    switch (k) {
    case 0: return p[2];
    case 1: return p[3] - p[2];
    case 2: return p[0] + j->gx * p[3];
    case 3: return j->gx * p[3] - p[0];
    case 4: return p[1] + j->gy * p[3];
    default: return j->gy * p[3] - p[1];
    }
}

/* Bit k set when p is outside plane k (the user planes only when the job clips against one). */
unsigned rs_outcode(const rs_job *j, const double *p)
{
    unsigned c = 0;
    int n = j->clip_mask >> RS_CLIP_PLANES ? RS_ALL_PLANES : RS_CLIP_PLANES;
    for (int k = 0; k < n; k++)
        if (!(plane_dist(j, p, k) >= 0.0)) c |= 1u << k;
    return c;
}

/* The k-th plane in clipping order: near, far, the user planes, then the guard band (whose projective lines are
 * computed from the polygon the linear planes leave). */
static int plane_at(int k) { return k < 2 ? k : (k < 2 + RS_MAX_CLIP_PLANES ? k + 4 : k - RS_MAX_CLIP_PLANES); }

/* r = a x b (3-vectors). */
static void cross(const double *a, const double *b, double *r)
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

/* Projective line through the (x, y, w) of a and b. */
static void edge_line(const rs_cvert *a, const rs_cvert *b, double *l)
{
    double pa[3] = { a->p[0], a->p[1], a->p[3] }, pb[3] = { b->p[0], b->p[1], b->p[3] };
    cross(pa, pb, l);
}

/* New vertex on segment in -> out where plane k (distances di >= 0 > dout) crosses it; attributes of the
 * job's slots are interpolated into the buffer's pool.  line: the segment's projective line for guard planes
 * (k >= 2), NULL otherwise. */
static rs_cvert intersect(const rs_job *j, const rs_cvert *in, const rs_cvert *out, double di, double dout,
                          int k, const double *line, rs_clipbuf *cb)
{
    rs_cvert v;
    double t = di / (di - dout);
    for (int c = 0; c < 4; c++) v.p[c] = in->p[c] + t * (out->p[c] - in->p[c]);
    if (k == 0) v.p[2] = 0.0;
    if (k == 1) v.p[2] = v.p[3];
    if (line) {
        double g[3], q[3];
        guard_line(j, k, g);
        cross(line, g, q);
        double X = q[0] / q[2], Y = q[1] / q[2];
        if (isfinite(X) && isfinite(Y) && v.p[3] > 0.0) {
            v.p[0] = X * v.p[3];
            v.p[1] = Y * v.p[3];
        }
    }
    rs_vec4 *a = cb->pool[cb->n_pool++];
    float tf = (float)t;
    for (int s = 0; s < j->n_slots; s++) {
        int q = j->slot[s];
        const rs_vec4 *x = &in->a[q], *y = &out->a[q];
        a[q] = (rs_vec4){ x->x + tf * (y->x - x->x), x->y + tf * (y->y - x->y),
                          x->z + tf * (y->z - x->z), x->w + tf * (y->w - x->w) };
    }
    v.a = a;
    v.edge = false;
    v.orig = false;
    return v;
}

/* Clip polygon src[0..n) against plane k into dst; returns the new vertex count (Sutherland-Hodgman, with
 * edge flags: an edge along the clip plane is not an edge of the input triangle; and edge lines for the guard
 * planes). */
static int clip_plane(const rs_job *j, const rs_cvert *src, int n, rs_cvert *dst, int k, rs_clipbuf *cb)
{
    int m = 0;
    bool guard = k >= 2 && k < RS_CLIP_PLANES;
    for (int i = 0; i < n; i++) {
        const rs_cvert *a = &src[i], *b = &src[(i + 1) % n];
        double da = plane_dist(j, a->p, k), db = plane_dist(j, b->p, k);
        bool ina = da >= 0.0, inb = db >= 0.0;
        if (ina) {
            dst[m++] = *a;
            if (!inb) {
                dst[m] = intersect(j, a, b, da, db, k, guard ? a->line : NULL, cb);
                if (guard) guard_line(j, k, dst[m].line);
                dst[m++].edge = false;
            }
        } else if (inb) {
            dst[m] = intersect(j, b, a, db, da, k, guard ? a->line : NULL, cb);
            for (int c = 0; c < 3; c++) dst[m].line[c] = a->line[c];
            dst[m++].edge = a->edge;
        }
    }
    return m;
}

/* Clip polygon poly[0..n) against the planes in mask `planes`; returns the vertex count (< 3: nothing left). */
int rs_clip_poly(const rs_job *j, rs_cvert *poly, int n, unsigned planes, rs_clipbuf *cb)
{
    rs_cvert tmp[RS_MAX_POLY];
    for (int q = 0; q < RS_ALL_PLANES && n >= 3; q++) {
        int k = plane_at(q);
        if (!(planes & (1u << k))) continue;
        if (k >= 2 && k < RS_CLIP_PLANES && !(planes & (((1u << k) - 1u) & ~3u))) /* first guard plane: edge lines */
            for (int i = 0; i < n; i++) edge_line(&poly[i], &poly[(i + 1) % n], poly[i].line);
        int m = clip_plane(j, poly, n, tmp, k, cb);
        for (int i = 0; i < m; i++) poly[i] = tmp[i];
        n = m;
    }
    return n;
}

/* Clip segment v[0]-v[1] against the planes in `planes` in place; false when nothing is left. */
bool rs_clip_line(const rs_job *j, rs_cvert *v, unsigned planes, rs_clipbuf *cb)
{
    double line[3];
    bool have_line = false;
    for (int i = 0; i < RS_ALL_PLANES; i++) {
        int k = plane_at(i);
        bool guard = k >= 2 && k < RS_CLIP_PLANES;
        if (!(planes & (1u << k))) continue;
        if (guard && !have_line) { edge_line(&v[0], &v[1], line); have_line = true; }
        double d0 = plane_dist(j, v[0].p, k), d1 = plane_dist(j, v[1].p, k);
        bool in0 = d0 >= 0.0, in1 = d1 >= 0.0;
        if (!in0 && !in1) return false;
        if (in0 && !in1) v[1] = intersect(j, &v[0], &v[1], d0, d1, k, guard ? line : NULL, cb);
        else if (!in0 && in1) v[0] = intersect(j, &v[1], &v[0], d1, d0, k, guard ? line : NULL, cb);
    }
    return true;
}
