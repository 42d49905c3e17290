/* tests/util/pn_ref.c -- double-precision references of the patches from the equations (see pn_ref.h). */
#include "pn_ref.h"

#include <math.h>
#include <string.h>

/* out = a*x + b*y (3 components). */
static void ax_by(double a, const double x[3], double b, const double y[3], double out[3])
{
    for (int i = 0; i < 3; i++) out[i] = a * x[i] + b * y[i];
}

static double ddot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Tangent control point (2 pi + pj - dot(pj - pi, ni) ni) / 3 (Eq. 1.1.1 / 1.1.5). */
static void tangent_point(const double pi[3], const double pj[3], const double ni[3], double out[3])
{
    double d[3] = {pj[0] - pi[0], pj[1] - pi[1], pj[2] - pi[2]};
    double w = ddot(d, ni);
    for (int k = 0; k < 3; k++) out[k] = (2.0 * pi[k] + pj[k] - w * ni[k]) / 3.0;
}

void pn_ref_control_points(const double v[3][3], const double n[3][3], double c[4][4][3])
{
    memset(c, 0, sizeof(double) * 4 * 4 * 3);
    memcpy(c[3][0], v[0], sizeof(double) * 3);
    memcpy(c[0][3], v[1], sizeof(double) * 3);
    memcpy(c[0][0], v[2], sizeof(double) * 3);
    tangent_point(v[0], v[1], n[0], c[2][1]); /* b210 */
    tangent_point(v[1], v[0], n[1], c[1][2]); /* b120 */
    tangent_point(v[1], v[2], n[1], c[0][2]); /* b021 */
    tangent_point(v[2], v[1], n[2], c[0][1]); /* b012 */
    tangent_point(v[2], v[0], n[2], c[1][0]); /* b102 */
    tangent_point(v[0], v[2], n[0], c[2][0]); /* b201 */
    for (int k = 0; k < 3; k++) {
        double E = (c[2][1][k] + c[1][2][k] + c[0][2][k] + c[0][1][k] + c[1][0][k] + c[2][0][k]) / 6.0;
        double V = (v[0][k] + v[1][k] + v[2][k]) / 3.0;
        c[1][1][k] = E + (E - V) / 2.0;
    }
}

void pn_ref_npatch(const double v[3][3], const double n[3][3], const double b[3], double out[3])
{
    double c[4][4][3];
    pn_ref_control_points(v, n, c);
    double b0 = b[0], b1 = b[1], b2 = b[2];
    for (int k = 0; k < 3; k++)
        out[k] = c[3][0][k] * b0 * b0 * b0 + c[0][3][k] * b1 * b1 * b1 + c[0][0][k] * b2 * b2 * b2 +
                 3.0 * c[1][0][k] * b0 * b2 * b2 + 3.0 * c[0][1][k] * b1 * b2 * b2 +
                 3.0 * c[2][0][k] * b0 * b0 * b2 + 3.0 * c[0][2][k] * b1 * b1 * b2 +
                 3.0 * c[2][1][k] * b0 * b0 * b1 + 3.0 * c[1][2][k] * b0 * b1 * b1 +
                 6.0 * c[1][1][k] * b0 * b1 * b2;
}

void pn_ref_curve(const double p0[3], const double p1[3], const double n0[3], const double n1[3], double t,
                  double out[3])
{
    double b21[3], b12[3], s = 1.0 - t;
    tangent_point(p0, p1, n0, b21);
    tangent_point(p1, p0, n1, b12);
    for (int k = 0; k < 3; k++)
        out[k] = s * s * s * p0[k] + 3.0 * s * s * t * b21[k] + 3.0 * s * t * t * b12[k] + t * t * t * p1[k];
}

/* P_e of edge e = (v_e, v_e+1) towards the opposite vertex (Fig. 1.1.5, Eq. 1.1.7-1.1.8). */
static void edge_patch(const double v[3][3], const double n[3][3], const double b[3], int e, double out[3])
{
    int a = e, bb = (e + 1) % 3, o = (e + 2) % 3;
    double den = b[a] + b[bb]; /* = 1 - b[o] */
    double st = den > 0.0 ? b[bb] / den : 0.5;
    double p[3], nb[3];
    pn_ref_curve(v[a], v[bb], n[a], n[bb], st, p);
    ax_by(1.0 - st, n[a], st, n[bb], nb);
    double l = sqrt(ddot(nb, nb));
    for (int k = 0; k < 3; k++) nb[k] = l > 0.0 ? nb[k] / l : 0.0;
    pn_ref_curve(p, v[o], nb, n[o], b[o], out);
}

/* Gregory weight of edge e: product of its two barycentrics over the sum of all products; -1 at a corner. */
static int gregory(const double b[3], double g[3])
{
    double sum = b[0] * b[1] + b[1] * b[2] + b[2] * b[0];
    if (!(sum > 0.0)) return -1;
    for (int e = 0; e < 3; e++) g[e] = b[e] * b[(e + 1) % 3] / sum;
    return 0;
}

/* The vertex where b is 1 (corners). */
static void corner(const double v[3][3], const double b[3], double out[3])
{
    int m = b[0] >= b[1] ? (b[0] >= b[2] ? 0 : 2) : (b[1] >= b[2] ? 1 : 2);
    memcpy(out, v[m], sizeof(double) * 3);
}

void pn_ref_smooth_initial(const double v[3][3], const double n[3][3], const double b[3], double out[3])
{
    double g[3], P[3][3];
    if (gregory(b, g) < 0) {
        corner(v, b, out);
        return;
    }
    for (int e = 0; e < 3; e++) edge_patch(v, n, b, e, P[e]);
    for (int k = 0; k < 3; k++) out[k] = g[0] * P[0][k] + g[1] * P[1][k] + g[2] * P[2][k];
}

/* Unit normal of the triangle (a, b, c): cross(b - a, c - a) / |...|; 0 if degenerate. */
static void face_normal(const double a[3], const double b[3], const double c[3], double out[3])
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    out[0] = u[1] * w[2] - u[2] * w[1];
    out[1] = u[2] * w[0] - u[0] * w[2];
    out[2] = u[0] * w[1] - u[1] * w[0];
    double l = sqrt(ddot(out, out));
    for (int k = 0; k < 3; k++) out[k] = l > 0.0 ? out[k] / l : 0.0;
}

void pn_ref_fn(const double v[3][3], const double opp[3][3], double fn[3])
{
    double nf[3];
    face_normal(v[0], v[1], v[2], nf);
    for (int e = 0; e < 3; e++) {
        const double *third = v[(e + 2) % 3];
        if (opp[e][0] == third[0] && opp[e][1] == third[1] && opp[e][2] == third[2]) {
            fn[e] = 1.0;
            continue;
        }
        double nn[3];
        face_normal(v[(e + 1) % 3], v[e], opp[e], nn);
        fn[e] = (ddot(nf, nf) > 0.0 && ddot(nn, nn) > 0.0) ? fabs(ddot(nf, nn)) : 1.0;
        if (fn[e] > 1.0) fn[e] = 1.0;
    }
}

void pn_ref_smooth(const double v[3][3], const double n[3][3], const double opp[3][3], const double b[3],
                   double out[3])
{
    double g[3], P[3][3], np[3], fn[3];
    if (gregory(b, g) < 0) {
        corner(v, b, out);
        return;
    }
    pn_ref_npatch(v, n, b, np);
    pn_ref_fn(v, opp, fn);
    double bl = 27.0 * b[0] * b[1] * b[2];
    for (int e = 0; e < 3; e++) {
        edge_patch(v, n, b, e, P[e]);
        double bf = fmin(1.0, fn[e] + bl);
        ax_by(1.0 - bf, P[e], bf, np, P[e]);
    }
    for (int k = 0; k < 3; k++) {
        double p = g[0] * P[0][k] + g[1] * P[1][k] + g[2] * P[2][k];
        out[k] = (1.0 - bl) * p + bl * np[k];
    }
}

void pn_ref_quadratic_normal(const double v[3][3], const double n[3][3], const double b[3], double f,
                             double out[3])
{
    double m[3][3]; /* mid-edge normal of edge e */
    for (int e = 0; e < 3; e++) {
        const double *pi = v[e], *pj = v[(e + 1) % 3], *ni = n[e], *nj = n[(e + 1) % 3];
        double d[3] = {pj[0] - pi[0], pj[1] - pi[1], pj[2] - pi[2]}, s[3] = {ni[0] + nj[0], ni[1] + nj[1], ni[2] + nj[2]};
        double dd = ddot(d, d), w = dd > 0.0 ? f * ddot(d, s) / dd : 0.0;
        for (int k = 0; k < 3; k++) m[e][k] = s[k] - w * d[k];
        double l = sqrt(ddot(m[e], m[e]));
        for (int k = 0; k < 3; k++) m[e][k] = l > 0.0 ? m[e][k] / l : 0.0;
    }
    for (int k = 0; k < 3; k++)
        out[k] = n[0][k] * b[0] * b[0] + n[1][k] * b[1] * b[1] + n[2][k] * b[2] * b[2] + m[0][k] * b[0] * b[1] +
                 m[1][k] * b[1] * b[2] + m[2][k] * b[2] * b[0];
    double l = sqrt(ddot(out, out));
    for (int k = 0; k < 3; k++) out[k] = l > 0.0 ? out[k] / l : 0.0;
}
