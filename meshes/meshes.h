/* meshes/meshes.h -- triangle meshes for instess: built-in shapes, import through assimp, validation, welding,
 * normals, adjacency (opposite vertices) and the per-instance buffer of tessellation through instancing.
 *
 * Conventions (all of meshes/ follows them; tests/test_meshes.c and tests/test_adjacency.c check them):
 *  - Object space is left-handed, as D3D9: +x right, +y up, +z away from a default viewer.
 *  - Winding: a front face runs clockwise when seen from outside (D3D9's default cull mode CCW culls the back).
 *    In numbers, for a triangle (v0, v1, v2) the OUTWARD face normal is normalize(cross(v1 - v0, v2 - v0)),
 *    cross as in core.h (cross3).  Check: v0 = (0,0,0), v1 = (0,1,0), v2 = (1,0,0) gives (0,0,-1); a camera at
 *    -z looking along +z sees v0 -> v1 (up) -> v2 (right): clockwise, front, facing it.
 *    (The formula is the same as OpenGL's outward normal for counter-clockwise right-handed data: the two
 *    conventions differ by a mirror, see mesh_load_file.)
 *  - Units: whatever the file uses; no rescaling.  Built-ins fit in [-1, 1]^3 and are centred at the origin
 *    (cube: side 2; tetrahedron: 4 corners of that cube; octahedron, icosahedron, sphere: radius 1; cylinder:
 *    radius 1, y in [-1, 1]).  Texcoords: D3D's, origin at the top-left of the texture, v down.
 *  - Edges: edge k of triangle t runs from corner k to corner (k+1) % 3: edge 0 = v0-v1, edge 1 = v1-v2,
 *    edge 2 = v2-v0.  The corner not on edge k is (k+2) % 3.
 *  - Welding: vertices are welded for adjacency (and for recomputed normals) when their positions are bitwise
 *    equal, after turning -0.0 into +0.0.  No epsilon: the patches need bitwise-identical shared edges anyway
 *    (docs/design.md, erratum 6), and vertices an ulp apart do not make a watertight edge.  No tolerance in meshes/
 *    depends on the mesh's size or unit: welding and joining are exact, the degenerate test is a ratio
 *    (height / longest edge), normals are normalized in double, so a mesh scaled by 1e-30 or 1e20 becomes the
 *    same mesh up to float rounding.  The mesh's own vertices (with
 *    split normals / texcoords) are kept; `welded` is a second index buffer (meshopt_generateShadowIndexBuffer).
 *  - Opposite vertex: for edge k of triangle t, the vertex of the neighbouring triangle (the other triangle
 *    containing the same welded edge) that is not on the edge, as an index into the vertex arrays.
 *      boundary edge (one triangle):      the triangle's own third vertex (corner (k+2) % 3), so the shader's
 *                                         fn = |dot(face normal, neighbour's face normal)| = 1 and the smoothed
 *                                         patch falls back to the N-Patch along that edge.
 *      non-manifold edge (3+ triangles):  also the own third vertex, for every triangle on the edge: there is no
 *                                         single neighbour, and any per-triangle pick would give the two sides
 *                                         of a face pair different fn, hence different edge curves and a crack;
 *                                         with fn = 1 everywhere the edge is the N-Patch curve, which depends
 *                                         on the edge alone.  Counted in is_mesh_stats.nonmanifold_edges.
 *      two triangles using the edge in the same direction (inconsistent winding): they are neighbours anyway
 *                                         (fn uses |dot|); counted in inconsistent_edges.
 *  - Errors: functions return 0 or a negative IS_MESH_ERR_* code and write a message into the caller's
 *    buffer err[errlen] (may be NULL) that names the file (or built-in), the element (vertex 12, triangle 7)
 *    and what is wrong.  Warnings (dropped degenerate triangles, replaced normals, non-manifold edges) go to
 *    the optional callback in is_mesh_options and are counted in is_mesh_stats; library code never prints.
 *    A NULL mesh, output, name or array is IS_MESH_ERR_ARG (mesh_stats and mesh_build_instances: zeros, 0);
 *    counts beyond the limits are refused before the arrays are read (tests/test_api_meshes.c walks them all).
 *  - No globals except const tables (mesh_patch_declaration, the built-in name list).  Thread-safe apart
 *    from assimp's own last-error string.
 */
#ifndef INSTESS_MESHES_H
#define INSTESS_MESHES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/api.h"
#include "../core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    IS_MESH_OK = 0,
    IS_MESH_ERR_ARG = -1,       /* bad argument, unknown built-in name                          */
    IS_MESH_ERR_IO = -2,        /* missing / unreadable file, a directory, empty file             */
    IS_MESH_ERR_FORMAT = -3,    /* unknown extension, assimp could not parse it                   */
    IS_MESH_ERR_INVALID = -4,   /* non-finite position / texcoord, index out of range, too large  */
    IS_MESH_ERR_EMPTY = -5,     /* no triangles (none in the file, or all degenerate)             */
    IS_MESH_ERR_NOMEM = -6
};

/* Counts of one mesh, filled when it is created (mesh_stats returns them). */
typedef struct is_mesh_stats {
    size_t vertices;             /* vertices kept (each used by at least one triangle) */
    size_t welded_vertices;      /* distinct positions */
    size_t triangles;            /* triangles kept */
    size_t edges;                /* distinct welded edges */
    size_t boundary_edges;       /* edges of one triangle */
    size_t nonmanifold_edges;    /* edges of 3+ triangles */
    size_t inconsistent_edges;   /* edges of 2 triangles that both run the same direction */
    size_t degenerates_dropped;  /* repeated index, zero area, collinear (height < 1e-7 x longest edge) */
    size_t normals_replaced;     /* file normals that were zero, non-finite or missing: recomputed */
    size_t primitives_skipped;   /* points and lines in an imported file */
    bool normals_computed;       /* all normals computed (file had none, or options.recompute_normals) */
    /* Imported files only (see mesh_load_file): */
    bool facet_normals;          /* every corner's normal is its face's normal (within ~0.8 degrees) */
    size_t normals_against_faces;/* corners whose normal points against their face's outward normal */
} is_mesh_stats;

/* One welded edge: the welded vertices it joins (ends[0] < ends[1]) and the triangles that hold it: faces[0] <
 * faces[1] are the first two by index (UINT32_MAX when there are fewer), n_faces all of them (1: a boundary edge,
 * 2: shared, 3+: non-manifold).  The one table of the mesh's edges: adjacency (opposite), PN-AEN's neighbour
 * normals, the per-edge levels of detail and the smoothness measurement all read it. */
typedef struct is_mesh_edge {
    uint32_t ends[2];
    uint32_t faces[2];
    uint32_t n_faces;
} is_mesh_edge;

/* The longest path is_mesh.texture holds, with its NUL (a longer one is not reported: a warning says so). */
#define IS_MESH_TEXTURE_MAX 4096

typedef struct is_mesh {
    char name[256];              /* built-in name or the file's path (truncated) */
    size_t n_vertices;
    size_t n_triangles;
    float3 *positions;           /* n_vertices */
    float3 *normals;             /* n_vertices, unit length, pointing outward */
    float2 *texcoords;           /* n_vertices; (0, 0) when the file has none */
    uint32_t *indices;           /* 3 * n_triangles, clockwise from outside */
    uint32_t *welded;            /* 3 * n_triangles: indices[i] -> the first vertex (in index order) at its position */
    uint32_t *opposite;          /* 3 * n_triangles: [3t+k] = opposite vertex of edge k of triangle t */
    size_t n_edges;              /* the welded edges (= stats.edges), ordered by (ends[0], ends[1]) */
    is_mesh_edge *edges;         /* n_edges */
    uint32_t *tri_edge;          /* 3 * n_triangles: [3t+k] = the edge (index into edges) of edge k of triangle t */
    is_mesh_stats stats;
    /* The mesh's own diffuse texture (mesh_load_file, "The file's texture"): the path of an image file inside the
     * mesh's folder, for the texture coordinates above; "" when there is none (always for built-ins, mesh_create
     * and mesh_load_memory).  Reported, never read: the caller decides whether to use it. */
    char texture[IS_MESH_TEXTURE_MAX];
} is_mesh;

typedef void (*is_mesh_warn_fn)(void *user, const char *message);

typedef struct is_mesh_options {
    bool recompute_normals;      /* ignore the file's normals, compute all (angle-weighted, per welded vertex) */
    is_mesh_warn_fn warn;        /* optional: receives each warning ("FILE: dropped 3 degenerate triangles") */
    void *warn_user;
    /* Imports run assimp in a forked child process by default: assimp 5.2.5 hangs on some truncated files and
     * crashes on some corrupted ones, and those must become errors.  in_process = true runs it here instead
     * (for fuzzers that need in-process coverage).  import_timeout_ms: the child's limit (0: 60000). */
    bool in_process;
    int import_timeout_ms;
    /* Limits against resource bombs (docs/robustness.md, "Limits"); 0 means the default.
     * max_file_bytes: the mesh file and the side files it refers to, together (default 256 MiB); the mesh
     * file is checked before the import, side files when assimp opens them.
     * max_import_memory_bytes: address space and data the import child may add to what it had when it was
     * forked (setrlimit RLIMIT_AS and RLIMIT_DATA).  Default: 256 MiB plus 32 bytes per byte of the files
     * assimp opens.  An import that needs more fails with "assimp ran out of the import memory limit of N
     * MiB".  Not with in_process. */
    uint64_t max_file_bytes;
    uint64_t max_import_memory_bytes;
} is_mesh_options;

/* Raw arrays for mesh_create.  normals and texcoords may be NULL (computed / zero). */
typedef struct is_mesh_data {
    size_t n_vertices, n_triangles;
    const float3 *positions;
    const float3 *normals;
    const float2 *texcoords;
    const uint32_t *indices;     /* 3 * n_triangles */
} is_mesh_data;

/* ---------------------------------------------------------------------------------------------------------- */

/* Build a mesh from arrays (copied): validate (finite positions and texcoords, indices in range; the first bad
 * element is reported), drop degenerate triangles (warning with the count), drop unused vertices, weld by
 * position, normals (the given ones, normalized; zero / non-finite ones replaced by recomputed ones and
 * counted; all computed if normals is NULL or opt->recompute_normals), adjacency.  `label` names the mesh in
 * messages and becomes out->name.  opt may be NULL.  On error *out is left empty (mesh_free-safe). */
INSTESS_API int mesh_create(is_mesh *out, const char *label, const is_mesh_data *in, const is_mesh_options *opt,
                char *err, size_t errlen);
INSTESS_API void mesh_free(is_mesh *m);

/* Built-ins: "tetrahedron", "cube", "cube-split", "octahedron", "icosahedron", "sphere", "cylinder". */
INSTESS_API int mesh_builtin(const char *name, is_mesh *out, char *err, size_t errlen);
/* Same, with options (recompute_normals, warnings). */
INSTESS_API int mesh_builtin_ex(const char *name, const is_mesh_options *opt, is_mesh *out, char *err, size_t errlen);
/* The built-in names, NULL-terminated (a const table). */
INSTESS_API const char *const *mesh_builtin_names(void);

/* Import any format assimp 5.2 reads, by extension.  Post-processing: Triangulate, ValidateDataStructure and
 * ConvertToLeftHanded (= MakeLeftHanded: z -> -z, FlipWindingOrder, FlipUVs), which turns assimp's
 * right-handed counter-clockwise data into this file's convention without changing how the model looks (the
 * file's +z towards the viewer becomes our -z towards the viewer).  Vertices that are bitwise identical in
 * position, normal and texcoord are joined (meshoptimizer's vertex remap; assimp's JoinIdenticalVertices is
 * not used: its absolute 1e-5 tolerance joins distinct vertices of a small mesh), each in the place of its
 * first copy (as JoinIdenticalVertices numbered them).  Normals are never generated or smoothed by assimp;
 * ours are computed only where the file has none.  All meshes of the scene are merged with their node
 * transforms (normals by the inverse transpose, then normalized; a mirroring node flips winding).  Points and
 * lines are skipped (counted).  Hostile input (docs/robustness.md, "Threat model: inputs"): only regular files
 * are read, side files only from the mesh's folder and never material libraries (meshes/import_io.c), PLY and
 * OFF headers are checked against the file's size, and the files' size, the instanced triangles and the
 * import's time and memory are limited (is_mesh_options).  Facet normals and normals against the winding are
 * warned about.  Errors name the path: missing, not a regular file, empty, too large, unknown extension, a
 * refused side file, assimp's message, assimp crashed / timed out / ran out of memory, no triangles, invalid
 * data.
 *
 * The file's texture (out->texture): the diffuse texture of the material (assimp's AI_MATKEY_TEXTURE(
 * aiTextureType_DIFFUSE, 0)) when every mesh the scene draws names the same one -- one texture is bound per
 * draw -- as a regular file inside the mesh's folder, by the rules of side files above (its name read
 * with '\' as '/'; tried as a path relative to the folder, then by its last component in the folder itself, as
 * tools that copy a model's textures beside it leave them -- absolute names, "C:\..." too, only so -- then by
 * that component in another case when the folder holds just one such file: "TEST.PNG" finds test.png).  Warned
 * about, and then "" (the render goes on untextured): a named file that is not in the folder
 * (missing, outside it, not a regular file, or a path longer than IS_MESH_TEXTURE_MAX), a texture embedded in the
 * file ("*0": not read), meshes that name different textures or some none.  MD2: Quake 2's models name their skins
 * in the file; one that names none (numSkins 0, as assimp's test models faerie.md2 and sydney.md2: assimp then
 * reports its placeholder "$texture_dummy.bmp", which is never a file) gets the image in its folder that the
 * skin's size recorded in the MD2 header identifies: a BMP, PNG or TGA whose name starts with the model's
 * (faerie*, sydney*) and whose width and height are the header's (faerie2.bmp, 220x193; sydney.bmp, 308x193);
 * none found: "" without a warning, several: a warning and "".  A material texture on a mesh without texture
 * coordinates (a projection mapping) is no texture. */
INSTESS_API int mesh_load_file(const char *path, const is_mesh_options *opt, is_mesh *out, char *err, size_t errlen);
/* The same from memory (for fuzzers): hint is the format's extension ("obj", may be NULL or "" to let assimp
 * guess), label names the buffer in messages (NULL: "<memory>"). */
INSTESS_API int mesh_load_memory(const void *data, size_t size, const char *hint, const char *label,
                     const is_mesh_options *opt, is_mesh *out, char *err, size_t errlen);
/* --mesh NAME|FILE: a built-in when `spec` is one of the names, a file otherwise. */
INSTESS_API int mesh_open(const char *spec, const is_mesh_options *opt, is_mesh *out, char *err, size_t errlen);

/* Recompute welded indices, opposite vertices and the edge counts of stats from positions and indices (after
 * a caller changed positions).  0, IS_MESH_ERR_NOMEM, IS_MESH_ERR_ARG (NULL, or not a mesh of mesh_create), or
 * IS_MESH_ERR_INVALID for an index the caller set past the vertices (checked first: nothing is read past them). */
INSTESS_API int mesh_update_topology(is_mesh *m, char *err, size_t errlen);

/* The outward face normal of (v0, v1, v2) under the convention above: normalize(cross(v1 - v0, v2 - v0)),
 * computed in double; (0, 0, 0) for a degenerate triangle. */
INSTESS_API float3 mesh_compute_face_normal(float3 v0, float3 v1, float3 v2);

/* The libraries meshes/ runs with, "assimp 5.2.4, meshoptimizer 0.18" (assimp's as the loaded library says,
 * meshoptimizer's from its header: it is linked statically) into buf. */
INSTESS_API void mesh_library_versions(char *buf, size_t len);

/* The counts (a copy of m->stats). */
INSTESS_API is_mesh_stats mesh_stats(const is_mesh *m);

/* ---------------------------------------- tessellation through instancing ---------------------------------------- */

/* One instance = one mesh triangle (stream 1, Listing 1.1.2 order).  136 bytes, no padding. */
typedef struct is_patch_instance {
    float3 v[3];         /* TEXCOORD0..2: corner positions                                      */
    float3 n[3];         /* TEXCOORD3..5: corner normals                                        */
    float3 opp[3];       /* TEXCOORD6..8: position of the vertex opposite edge k (see above)    */
    float2 t[3];         /* TEXCOORD9..11: corner texcoords                                     */
    float instance_id;   /* TEXCOORD12: the triangle's index (exact below 2^24 triangles)       */
} is_patch_instance;

/* Fill out[0 .. m->n_triangles-1]; returns the number written. */
INSTESS_API size_t mesh_build_instances(const is_mesh *m, is_patch_instance *out);

/* The vertex declaration of Listing 1.1.2: stream 0 offset 0 FLOAT3 POSITION0 (the barycentric grid point);
 * stream 1: v0..v2 TEXCOORD0..2, n0..n2 TEXCOORD3..5, opp0..2 TEXCOORD6..8 (FLOAT3), t0..t2 TEXCOORD9..11
 * (FLOAT2), instance_id TEXCOORD12 (FLOAT1); then IS_DECL_END.  MESH_PATCH_DECLARATION_COUNT entries with END. */
#define MESH_PATCH_DECLARATION_COUNT 15
extern INSTESS_API const is_vertex_element mesh_patch_declaration[MESH_PATCH_DECLARATION_COUNT];

#ifdef __cplusplus
}
#endif
#endif
