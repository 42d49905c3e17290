/* web/obj.h -- the OBJ reader of the browser build (make web): the page has no assimp, so a mesh dropped onto it
 * is read here, into the same is_mesh that `instess FILE.obj` builds through assimp (meshes/import.c).
 *
 * Conventions:
 *  - What is read: `v x y z` (also `v x y z w`, divided by w, and `v x y z r g b`, the colour ignored), `vt u v
 *    [w]`, `vn x y z`, `f` with corners `v`, `v/vt`, `v//vn`, `v/vt/vn` (1-based; negative: relative to the
 *    elements defined so far), lines continued by a trailing backslash.  `p` and `l` statements and faces of one
 *    or two corners are skipped (counted in stats.primitives_skipped, with a warning).  Objects, groups,
 *    smoothing groups and materials are ignored (material libraries are never read, as in the program); faces
 *    are taken in the file's order.
 *  - The same mesh as assimp 5.2 makes with instess's import flags, bit for bit (tests/test_web_obj.c compares
 *    them): numbers parsed as assimp's fast_atof parses them (float, not strtod's rounding), one vertex per face
 *    corner, ConvertToLeftHanded (z -> -z, v -> 1 - v, each face's corners reversed), quads split as assimp's
 *    Triangulate splits them (from the concave corner, if any), the two identity node transforms of assimp's
 *    OBJ scene applied as meshes/import.c applies them (file normals normalised in double), then vertices with
 *    bitwise equal position, normal and texture coordinate joined, numbered in vertex order.  Normals come from
 *    the file when a face names one (corners without get zero normals, which mesh_create replaces and counts);
 *    a normal or texture index out of range drops all of them, as assimp does (with a warning here).
 *  - Not the same: polygons of five or more corners are cut into a fan from their first (reversed) corner, where
 *    assimp cuts ears; the surface is the same for a convex planar polygon but the triangles, and so the last
 *    bits of the pixels, may differ: a warning says so.  Files that re-open an object by name, and numbers with
 *    an exponent (assimp multiplies by powf(10, e), whose last bit may differ between C libraries), are read in
 *    the file's order and with this C library's powf.
 *  - Errors: 0, or a negative IS_MESH_ERR_* with a message naming the label, the line and what is wrong (a token
 *    that is not a number, a vertex of the wrong number of coordinates, a face index 0 or out of range, no
 *    faces); mesh_create's own errors (non-finite coordinates, ...) name the vertex.  *out is left empty on
 *    error (mesh_free-safe).  Warnings go to opt->warn. */
#ifndef INSTESS_WEB_OBJ_H
#define INSTESS_WEB_OBJ_H

#include <stddef.h>

#include "../meshes/meshes.h"

/* Read the OBJ text data[0..len) named label into *out, with opt's options (recompute_normals, warn). */
int web_obj_read(const char *label, const char *data, size_t len, const is_mesh_options *opt, is_mesh *out,
                 char *err, size_t errlen);

#endif
