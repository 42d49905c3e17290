/* vs/hull.c -- the hull stage (is_vs_hull_fn, core/core.h) of the patches that are polynomials in b: the flat
 * triangle (degree 1) and the N-Patch (degree 3, Eq. 1.1.1).  Each writes its Bernstein coefficients in clip
 * space, in double, and a bound of the rounding of the float shader against them.  The device culls with them (core/draw_cull.c); the smoothed patches are not
 * polynomials and have no hull stage. */
#include "vs_internal.h"

/* The shaders' rounding, relative to the magnitudes involved: about 1000 float ulps (a cubic evaluated in ~40
 * float operations loses at most a few tens; the transform a few more). */
#define HULL_REL_ERR 0x1p-20

/* Index of Bernstein coefficient (i, j, k) (exponents of b0, b1, b2; i + j + k = d) in the order k-major, then j. */
static int bern_index(int d, int j, int k)
{
    int base = 0;
    for (int q = 0; q < k; q++) base += d + 1 - q;
    return base + j;
}

/* Clip-space row vector (p, w) * M in double. */
static void to_clip(const float4x4 *M, const double p[3], double w, double out[4])
{
    for (int c = 0; c < 4; c++)
        out[c] = p[0] * M->m[0][c] + p[1] * M->m[1][c] + p[2] * M->m[2][c] + w * M->m[3][c];
}

/* Fill h from object-space Bernstein coefficients obj[(d+1)(d+2)/2] of degree d (1..3) and the magnitude `mag`
 * of every float value the shader computes on the way (inputs, control points, partial sums); false when
 * anything is not finite. */
static bool hull_from_bezier(const is_vs_constants *c, int d, const double (*obj)[3], double mag, is_patch_hull *h)
{
    const float4x4 M = vs_const_matrix(c, VS_C_WORLDVIEWPROJ);
    const int n = (d + 1) * (d + 2) / 2;
    h->n_pos = n, h->degree = d;
    for (int q = 0; q < n; q++) to_clip(&M, obj[q], 1.0, h->pos[q]);
    /* rounding: the object point (error ~ mag), times the matrix's column sums, plus the transform's own */
    double col = 0.0, big = 0.0;
    for (int k = 0; k < 4; k++) {
        double s = fabs(M.m[0][k]) + fabs(M.m[1][k]) + fabs(M.m[2][k]);
        col = fmax(col, s);
        big = fmax(big, s * mag + fabs(M.m[3][k]));
    }
    double rinf = 0.0;
    for (int q = 0; q < n; q++)
        for (int a = 0; a < 4; a++) rinf = fmax(rinf, fabs(h->pos[q][a]));
    /* the widened domain (IS_HULL_DOMAIN_SLACK = 2^-23): Bernstein weights off by at most ~4 d slack in all */
    h->err = HULL_REL_ERR * (mag * col + big) + 0x1p-20 * rinf;
    bool ok = isfinite(h->err);
    for (int q = 0; q < n; q++)
        for (int a = 0; a < 4; a++) ok &= isfinite(h->pos[q][a]);
    return ok;
}

/* Largest |component| of a float3. */
static double max_abs3(float3 a) { return fmax(fabs((double)a.x), fmax(fabs((double)a.y), fabs((double)a.z))); }

/* The N-Patch's ten control points (Eq. 1.1.1: b_ijk with the /3, b111 = E + (E - V) / 2) of triangle T. */
static void npatch_bezier(const vs_triangle *T, double obj[10][3])
{
    double v[3][3], n[3][3];
    for (int i = 0; i < 3; i++) {
        v[i][0] = T->v[i].x, v[i][1] = T->v[i].y, v[i][2] = T->v[i].z;
        n[i][0] = T->n[i].x, n[i][1] = T->n[i].y, n[i][2] = T->n[i].z;
    }
    /* exponent triple of the corner i as (b0, b1, b2) */
    static const int corner[3][3] = {{3, 0, 0}, {0, 3, 0}, {0, 0, 3}};
    double sum[3] = {0, 0, 0};
    for (int i = 0; i < 3; i++) {
        const int *e = corner[i];
        double *o = obj[bern_index(3, e[1], e[2])];
        for (int a = 0; a < 3; a++) o[a] = v[i][a];
        for (int j = 0; j < 3; j++) { /* b_(2 at i, 1 at j): (2 vi + vj - ni dot(vj - vi, ni)) / 3 */
            if (j == i) continue;
            int x[3] = {0, 0, 0};
            x[i] = 2, x[j] = 1;
            double w = 0.0;
            for (int a = 0; a < 3; a++) w += (v[j][a] - v[i][a]) * n[i][a];
            double *p = obj[bern_index(3, x[1], x[2])];
            for (int a = 0; a < 3; a++) {
                p[a] = (2.0 * v[i][a] + v[j][a] - w * n[i][a]) / 3.0;
                sum[a] += p[a];
            }
        }
    }
    double *c = obj[bern_index(3, 1, 1)];
    for (int a = 0; a < 3; a++) {
        double E = sum[a] / 6.0, V = (v[0][a] + v[1][a] + v[2][a]) / 3.0;
        c[a] = E + (E - V) / 2.0;
    }
}

/* is_vs_hull_fn of the npatch shader. */
bool vs_npatch_hull(const is_vs_constants *c, const is_vs_input *in, is_patch_hull *h)
{
    vs_triangle T;
    vs_triangle_from_input(in, &T);
    double obj[10][3];
    npatch_bezier(&T, obj);
    double vm = 0.0, nm = 0.0;
    for (int i = 0; i < 3; i++) vm = fmax(vm, max_abs3(T.v[i])), nm = fmax(nm, max_abs3(T.n[i]));
    /* 2 vi + vj - ni dot(vj - vi, ni): |dot| <= 3 (2 vm) nm, so up to 3 vm + 6 vm nm^2 per component; the
     * centre's sum of the six and its half: 3x that */
    double mag = 3.0 * (3.0 * vm + 6.0 * nm * nm * vm);
    return hull_from_bezier(c, 3, (const double(*)[3])obj, mag, h);
}

/* is_vs_hull_fn of the flat shader: the triangle itself. */
bool vs_flat_hull(const is_vs_constants *c, const is_vs_input *in, is_patch_hull *h)
{
    vs_triangle T;
    vs_triangle_from_input(in, &T);
    double obj[3][3];
    double vm = 0.0;
    for (int i = 0; i < 3; i++) {
        double *o = obj[i == 0 ? bern_index(1, 0, 0) : (i == 1 ? bern_index(1, 1, 0) : bern_index(1, 0, 1))];
        o[0] = T.v[i].x, o[1] = T.v[i].y, o[2] = T.v[i].z;
        vm = fmax(vm, max_abs3(T.v[i]));
    }
    return hull_from_bezier(c, 1, (const double(*)[3])obj, 3.0 * vm, h);
}
