/* tess/tess.h -- tessellation through instancing, the host side [Gruen05]: a mesh's triangles as per-instance
 * data in stream 1, a barycentric grid of one triangle in stream 0, drawn once per triangle with
 * SetStreamSourceFreq; per-edge levels of detail drawn the same way with refinement patterns bucketed by level
 * triple; PN-AEN's extra stream of neighbour normals; and the device's fetch done on the CPU.
 *
 * Conventions:
 *  - The device is core/device.h's; the per-instance record is meshes.h's is_patch_instance laid out by
 *    mesh_patch_declaration (Listing 1.1.2's registers, vs/vs.h's VS_IN_*); grids are core/grid.h's.
 *  - tess_bind_* create the buffers and the declaration in a tess_resources (or tess_adaptive) and bind them
 *    (stream sources, frequencies, indices, declaration); the shader and its constants are the caller's.  They
 *    return IS_OK or an IS_ERR_* code; free what they made with tess_resources_free / tess_adaptive_free, also
 *    after a failure.  Nothing is global: a pattern cache (core_pattern_cache) belongs to its caller.
 *  - Edge k of a triangle runs from v_k to v_(k+1 mod 3); an edge's level depends on its two welded end points
 *    alone, so both triangles of an edge agree and the surface stays watertight.
 *  - NULL arguments: IS_ERR_INVALIDCALL / -1, or nothing done; a perm that is not a permutation of 0, 1, 2 is
 *    the identity; tess_lod_levels clamps its levels into 1..CORE_LOD_MAX_LEVEL with min_level <= max_level
 *    (tests/test_api_tess.c walks every function).
 */
#ifndef INSTESS_TESS_H
#define INSTESS_TESS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/api.h"
#include "../core/core.h"
#include "../meshes/meshes.h"
#include "../vs/vs.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------- uniform draws (tess/instancing.c) ---------------------------------------- */

/* The device resources of one instanced draw (released by tess_resources_free). */
typedef struct tess_resources {
    is_vertex_buffer *vb0, *vb1, *vb2;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
    unsigned n_vertices, n_prims, n_instances;   /* the draw's NumVertices, PrimitiveCount, instances */
} tess_resources;
INSTESS_API void tess_resources_free(tess_resources *r);
/* An index buffer of n indices copied from idx: 16-bit when max_index < 65536, else 32-bit; IS_OK or an error. */
INSTESS_API is_result tess_index_buffer(is_device *dev, const uint32_t *idx, size_t n, size_t max_index, is_index_buffer **out);
/* Tessellation through instancing on dev: the grid g in stream 0 (INDEXEDDATA | n_triangles; 16-bit indices
 * when they fit), one is_patch_instance per triangle of m in stream 1 (INSTANCEDATA | 1), Listing 1.1.2's
 * declaration; created in r and bound.  The shader and constants are the caller's.  IS_OK or an error. */
INSTESS_API is_result tess_bind_instanced(is_device *dev, const is_mesh *m, const core_grid *g, tess_resources *r);

/* ---------------------------------------- the fetch on the CPU (tess/fetch.c) ---------------------------------------- */

/* The input registers the device fetches for grid point b of instance inst (Listing 1.1.2's declaration, as
 * mesh_patch_declaration lays it out; with nadj, not NULL, also PN-AEN's neighbour normals as
 * tess_bind_adjacent_normals binds them, nadj[k][j] as tess_adjacent_normals gives them): for evaluating a patch
 * shader outside a draw (OBJ export, tests).  Registers the declaration does not fill read (0, 0, 0, 1). */
INSTESS_API void tess_input_from_instance(const is_patch_instance *inst, const float3 (*nadj)[2], float3 b, is_vs_input *in);

/* ---------------------------------------- PN-AEN's stream (tess/aen.c) ---------------------------------------- */

/* nadj[t][k][j] = the normal that the triangle across edge k of triangle t has at corner (k + j) % 3 of t; an
 * edge without exactly one neighbour (boundary, non-manifold) gets t's own normals.  nadj has m->n_triangles
 * entries.  0, or -1 when out of memory. */
INSTESS_API int tess_adjacent_normals(const is_mesh *m, float3 (*nadj)[3][2]);
/* One triangle's neighbour normals in, those of its renumbering by perm (tess_permute_instance) out. */
INSTESS_API void tess_permute_adjacent_normals(const float3 in[3][2], const uint8_t perm[3], float3 out[3][2]);

/* ---------------------------------------- adaptive level of detail (tess/lod.c, tess/instancing.c) -------------
 *
 * Per-edge levels: each mesh edge (a pair of welded vertices a < b) gets one level, computed once per edge from
 * its two end points in that canonical order (and, for --lod screen, the normals at its ends of the first
 * triangle holding it), so both triangles of an edge use the same level whatever their vertex order.
 * The modes (tess_lod_mode): uniform (one level everywhere: tess_bind_instanced), or
 *  - distance: L = max_level * ref_depth / z, z the view depth of the edge's midpoint (ref_depth: the depth at
 *    which max_level is reached; the scene uses the nearest depth of the object's bounding sphere);
 *  - screen: L = length in pixels of the projected N-Patch control polygon of the edge (b300 b210 b120 b030, the
 *    border curve's hull: a bound of the curve's projected length) / target (NVIDIA's GDC 2011 rule);
 *  - deviation: L = sqrt(3/4 D / target), D the larger length in pixels of the projected control polygon's two
 *    second differences (b300 - 2 b210 + b120, b210 - 2 b120 + b030): a cubic Bezier with those control points
 *    lies within 3/4 D / L^2 of its polyline of L equal parameter steps, so target is the screen-space deviation
 *    allowed to an edge.  An estimate, not a bound, for the surface: the projection is not affine and the
 *    patch's interior is not its edges (bench/README.md, scene D, measures the whole surface);
 *  - then rounded up and clamped to [min_level, max_level]; an edge with a corner behind the eye gets max_level;
 *    with silhouette, an edge whose two faces face opposite ways (view space) gets max_level. */
typedef enum { TESS_LOD_UNIFORM, TESS_LOD_DISTANCE, TESS_LOD_SCREEN, TESS_LOD_DEVIATION } tess_lod_mode;
typedef struct tess_lod_params {
    tess_lod_mode mode;
    float target_px, ref_depth;
    int min_level, max_level, width, height;
    bool silhouette;
    float4x4 world_view, wvp;   /* object -> view, object -> clip */
} tess_lod_params;

/* A mesh's edges (topology only, built once) and their current levels. */
typedef struct tess_lod_edges {
    size_t n_edges;
    uint32_t (*ends)[2];        /* welded vertices a < b */
    float3 (*nrm)[2];           /* the normals at a and b of the first triangle holding the edge */
    uint32_t (*faces)[2];       /* its first two triangles (UINT32_MAX: none) */
    uint32_t *n_faces;
    uint32_t *tri_edge;         /* 3 per triangle: the edge index of its edge k */
    uint8_t *level;             /* per edge, after tess_lod_levels */
} tess_lod_edges;
INSTESS_API int tess_lod_edges_build(const is_mesh *m, tess_lod_edges *e, char *err, size_t errlen);
INSTESS_API void tess_lod_edges_free(tess_lod_edges *e);
/* Compute every edge's level as p says into e->level; hist[l] (CORE_LOD_MAX_LEVEL + 1 entries, zeroed here)
 * counts edges per level. */
INSTESS_API void tess_lod_levels(const tess_lod_params *p, const is_mesh *m, tess_lod_edges *e, uint64_t *hist);


/* One bucket: the triangles drawn with one pattern and one winding, in one instanced draw. */
typedef struct tess_bucket {
    int level[3];               /* the pattern's sorted edge levels */
    bool odd;                   /* instances renumbered by an odd permutation: the flipped index range */
    unsigned first, count;      /* its instances in stream 1 (and 2) */
    int base_vertex;            /* the pattern's points in stream 0 (BaseVertexIndex) */
    unsigned n_points, start_index, n_prims;   /* the regular grid of level[2] drawn: its points and triangles */
    unsigned n_tessellated;     /* the pattern's own triangles: n_prims less the merged ones (zero area) */
} tess_bucket;
/* The buffers of an adaptive draw: every pattern in use in stream 0 as the regular grid of its largest level whose
 * edge points are moved where the pattern puts them (core_grid_adaptive_points: 16-bit indices local to the
 * pattern, core_grid_regular's triangles then the same with two indices swapped; the triangles the pattern merges
 * have zero area and draw nothing), the instances renumbered (core_lod_order) and sorted by bucket in stream 1.
 * Every bucket's draw is then a regular grid (mirrored for the odd ones), which the device's rasterizer sets up from
 * the grid's rows. */
typedef struct tess_adaptive {
    tess_resources r;
    tess_bucket *buckets;
    size_t n_buckets, n_patterns, n_triangles;  /* n_triangles: tessellated (n_tessellated), over all buckets */
    uint32_t *tri;              /* per instance: the mesh triangle */
    uint8_t (*perm)[3];         /* per instance: the renumbering */
    struct tess_adaptive_keep *keep;   /* private: what a rebind reuses (host scratch, the buffers' device) */
} tess_adaptive;
typedef struct tess_adaptive_keep tess_adaptive_keep;
INSTESS_API void tess_adaptive_free(tess_adaptive *a);
/* Bucket m's triangles by the patterns of the levels in e, fill and bind the buffers (stream 0, 1, the index
 * buffer, Listing 1.1.2's declaration) in a (whatever a held: it is overwritten, not freed); patterns from cache.
 * IS_OK or an error; free a with tess_adaptive_free either way. */
INSTESS_API is_result tess_bind_adaptive(is_device *dev, const is_mesh *m, const tess_lod_edges *e, core_pattern_cache *cache,
                              tess_adaptive *a);
/* The same for a bound before (by tess_bind_adaptive or tess_rebind_adaptive, or zeroed), as a view-dependent LOD
 * does every frame: the new levels' buckets, written into a's buffers and host scratch when they are large enough
 * (a's buffers grow when they are not; a frame of settled levels allocates nothing), and bound.  The same buckets
 * and buffer contents as tess_bind_adaptive; buffers of another device than a's are made again on dev.  PN-AEN's
 * stream 2 is dropped (the instances' order changed): call tess_bind_adjacent_normals again.  IS_OK or an error;
 * after an error a draws nothing (n_buckets 0) and is still freed with tess_adaptive_free. */
INSTESS_API is_result tess_rebind_adaptive(is_device *dev, const is_mesh *m, const tess_lod_edges *e,
                                           core_pattern_cache *cache, tess_adaptive *a);
/* PN-AEN's third stream: the neighbours' normals at each edge's ends (INSTANCEDATA | 1) and the declaration with
 * them, replacing r's; with a (an adaptive draw) in a's order and renumbering.  IS_OK or an error. */
INSTESS_API is_result tess_bind_adjacent_normals(is_device *dev, const is_mesh *m, tess_resources *r, const tess_adaptive *a);
/* Set stream 1 (and 2, if bound) to bucket k's instances with INDEXEDDATA | count on stream 0, and draw it. */
INSTESS_API is_result tess_draw_bucket(is_device *dev, const tess_adaptive *a, size_t k);
/* The renumbered instance: perm[i] of in becomes vertex i (positions, normals, texcoords, opposite vertices). */
INSTESS_API void tess_permute_instance(const is_patch_instance *in, const uint8_t perm[3], is_patch_instance *out);

/* ---------------------------------------- smoothness in numbers (tess/smoothness.c) ---------------------------------------- */
typedef struct vs_smoothness_result {
    double max_angle_deg;   /* largest angle between the real normals of the two sides of a shared edge */
    double mean_angle_deg;  /* mean of those angles over all samples */
    double max_angle_coplanar_deg; /* the largest angle on edges between coplanar faces (|dot of face normals|
                                      within 1e-6 of 1, e.g. the cube's face diagonals): ripples show here */
    double max_angle_feature_deg;  /* the largest angle on the other shared edges (where the faces meet at an
                                      angle): creases show here */
    double max_distance;    /* largest distance of a patch point from its flat triangle's plane, relative to
                               the bounding-box diagonal of the mesh */
    size_t shared_edges;    /* edges with exactly two triangles (sampled) */
    size_t boundary_edges;  /* edges with one triangle */
    size_t nonmanifold_edges; /* edges with more than two triangles (not sampled) */
    size_t samples;         /* edge samples taken */
    double mean_angle_feature_deg; /* mean of the angles at feature edges alone (max_angle_feature_deg's edges) */
    double max_valley_deg;  /* the largest valley in a band across the shared edges: at each edge sample, the
                               points 1/128, 2/128, ..., 8/128 (up to 1/16) of the way from the edge to each
                               side's opposite corner are paired, and where their real normals lean towards each
                               other (dot(nA - nB, PB - PA) > 0, a concave fold) the angle between them counts;
                               normals leaning apart (a convex surface, a ridge) count 0.  It sees the valleys
                               that lie beside an edge rather than on it (the final patch's soft band along the
                               cube's face diagonals), and on a mesh with concave regions their curvature too */
} vs_smoothness_result;

/* The most samples per edge tess_smoothness takes (more would not end in reasonable time on a large mesh). */
#define TESS_SMOOTHNESS_MAX_SAMPLES 4096
/* Sample every shared edge of m (the mesh's welded-edge table: edges with exactly two triangles) at
 * `samples_per_edge` points (i + 1/2) / samples_per_edge and compare the derivative normals of the two sides
 * (patch p with options o, real normals), on the edge and in the band of max_valley_deg; sample each triangle at
 * the interior points of the level-8 grid for the distance.  The neighbours (opposite vertices, PN-AEN's normals) come from the same table.  Returns 0, or
 * -1 for bad arguments (samples_per_edge outside 1..TESS_SMOOTHNESS_MAX_SAMPLES) or when out of memory. */
INSTESS_API int tess_smoothness(const is_mesh *m, vs_patch p, const vs_options *o, int samples_per_edge,
                                vs_smoothness_result *res);


#ifdef __cplusplus
}
#endif
#endif
