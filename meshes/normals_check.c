/* meshes/normals_check.c -- hints about a file's normals that make every curved patch look wrong:
 *  - facet normals (STL, or any file that stores one normal per face): every corner's normal is its face's
 *    normal, so the N-Patch and the smoothed patches degenerate into the flat triangles;
 *  - normals against the winding (an STL whose facet normals point inward, a file with flipped faces): most
 *    corners' normals point away from their face's outward normal, so the patches bulge inward.
 * Both are warnings suggesting --recompute-normals; the normals are left as the file has them. */
#include "mesh_internal.h"

#include <math.h>
#include <stdio.h>

/* A corner's normal counts as its face's normal when |cos(angle)| >= 1 - FACET_TOLERANCE (about 0.8 degrees:
 * float normals written with 6 digits are well within it, a smooth normal of a 200-triangle sphere is not). */
#define FACET_TOLERANCE 1e-4

/* cos of the angle between the unit normal n and the unit face normal fn, in double. */
static double cos_to_face(float3 n, float3 fn)
{
    return (double)n.x * fn.x + (double)n.y * fn.y + (double)n.z * fn.z;
}

/* mesh_check_normals: see mesh_internal.h. */
void mesh_check_normals(is_mesh *m, const char *label, const is_mesh_options *opt)
{
    if (m->stats.normals_computed || m->n_triangles == 0) return;
    size_t facet = 0, against = 0, corners = 3 * m->n_triangles;
    for (size_t t = 0; t < m->n_triangles; t++) {
        const uint32_t *tri = m->indices + 3 * t;
        float3 fn = mesh_compute_face_normal(m->positions[tri[0]], m->positions[tri[1]], m->positions[tri[2]]);
        for (int c = 0; c < 3; c++) {
            double d = cos_to_face(m->normals[tri[c]], fn);
            facet += fabs(d) >= 1.0 - FACET_TOLERANCE;
            against += d < 0.0;
        }
    }
    m->stats.facet_normals = facet == corners;
    m->stats.normals_against_faces = against;
    if (m->stats.facet_normals)
        mesh_warn(opt, "%s: the file's normals are facet normals (each corner has its face's normal), so every patch "
             "renders as flat facets; --recompute-normals computes smooth vertex normals", label);
    if (2 * against > corners)
        mesh_warn(opt, "%s: %zu of %zu corner normals point against their face's winding (inward normals or "
             "reversed faces), so the patches bulge the wrong way and the lit side renders black; --recompute-normals "
             "computes them from the winding, or if the normals are right and the faces wound the other way, "
             "--cull cw draws their fronts", label, against, corners);
}
