/* tests/util/pn_ref.h -- double-precision references of the patches, written from the equations (seed 000
 * Eq. 1.1.1-1.1.11, seed 001 Eq. 1-4, seed 003), independently of vs/ and of the listings' form.
 * Conventions: points and normals are double[3]; b = (b0, b1, b2) weights v0, v1, v2; edge k joins v_k and
 * v_(k+1)%3 and opp[k] is the vertex across it (own third vertex on a boundary). */
#ifndef INSTESS_TESTS_PN_REF_H
#define INSTESS_TESTS_PN_REF_H

/* The ten control points of Eq. 1.1.1 in canonical form (with the /3, b111 = E + (E - V) / 2 over all six
 * tangent points), c[i][j] = b_{i j (3-i-j)}. */
void pn_ref_control_points(const double v[3][3], const double n[3][3], double c[4][4][3]);
/* Eq. 1.1.2: sum of the Bernstein terms with the weights 1, 3 and 6. */
void pn_ref_npatch(const double v[3][3], const double n[3][3], const double b[3], double out[3]);
/* Eq. 1.1.5: the cubic border curve from p0 to p1 with end normals n0, n1 at t, canonical Bernstein form. */
void pn_ref_curve(const double p0[3], const double p1[3], const double n0[3], const double n1[3], double t,
                  double out[3]);
/* The intermediate patch (Eq. 1.1.4-1.1.8, Fig. 1.1.5): P = g_e01 P01 + g_e12 P12 + g_e20 P20 where P_e starts on
 * edge e at st = (weight of the edge's second vertex) / (sum of the edge's weights) and runs to the opposite
 * vertex at ct = its barycentric; the vertex itself at a corner. */
void pn_ref_smooth_initial(const double v[3][3], const double n[3][3], const double b[3], double out[3]);
/* |dot| of the face normals of (v0, v1, v2) and of the triangle across edge k; 1 on a boundary. */
void pn_ref_fn(const double v[3][3], const double opp[3][3], double fn[3]);
/* The final patch (Eq. 1.1.9-1.1.11): each P_e lerped towards the N-Patch by min(1, fn_e + bl), bl = 27 b0 b1 b2,
 * Gregory-blended, lerped towards the N-Patch by bl. */
void pn_ref_smooth(const double v[3][3], const double n[3][3], const double opp[3][3], const double b[3],
                   double out[3]);
/* Vlachos' quadratic normal (unit), mid-edge normals reflected with factor f (2 or 1.5). */
void pn_ref_quadratic_normal(const double v[3][3], const double n[3][3], const double b[3], double f,
                             double out[3]);

#endif
