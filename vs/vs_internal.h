/* vs/vs_internal.h -- what the files of vs/ share and nothing outside vs/ (tests aside) may include: the
 * per-vertex and batched bodies of the shaders, the decoded constants, the derivatives, the watertight edge
 * order.  The conventions are vs/vs.h's. */
#ifndef INSTESS_VS_INTERNAL_H
#define INSTESS_VS_INTERNAL_H

#include "vs.h"
#include "../core/hlsl.h"

/* Partial derivatives of P along the parameter directions (-1, 1, 0) (du) and (-1, 0, 1) (dv), analytic or by
 * finite differences (see "real" above); cross(du, dv) is the unoriented real normal. */
void vs_patch_derivatives(vs_patch p, const vs_triangle *tri, float3 b, const vs_options *o, float3 *du,
                          float3 *dv);

/* The body of a patch shader: read the instance and b from the input registers, evaluate patch p (options from
 * c9), write the outputs.  The smooth, smooth-initial, flat, phong and pn-aen shaders are this call. */
void vs_run_patch(vs_patch p, const is_vs_constants *c, const is_vs_input *in, is_vs_output *out);
/* Write the outputs (see the conventions) from an object-space position and unit normal. */
void vs_write_outputs(const is_vs_constants *c, float3 pos, float3 normal, float2 oTex, float3 b, float id,
                      float3 g, is_vs_output *out);

/* ---- batched entries (is_vs_batch_fn of every patch shader): the same bytes as per-vertex calls ----
 * Consecutive inputs of one instance (equal registers apart from POSITION0) share the work that depends only
 * on the instance (the triangle's registers, the options, the matrices); each vertex then runs exactly the
 * per-vertex operations of its listing.  `shared` as in is_vs_batch_fn (core.h): registers stored in in[0] only. */
/* The constants a shader decodes per call, decoded once per batch. */
typedef struct vs_batch_consts {
    float4x4 wvp, world;
    float4 diffuse;
    vs_options o;
    uint32_t live;  /* IS_OUT_* outputs the caller reads (the batch's `live`; ~0u from vs_batch_consts_read) */
} vs_batch_consts;
void vs_batch_consts_read(const is_vs_constants *c, vs_batch_consts *k);
/* Compare n floats by their bit patterns, in order: -1, 0 or 1 (a total order; equal bits compare equal).  The
 * watertight edge evaluation orders an edge's ends with it (patch.c, batch8.c). */
int vs_cmp_bits(const float *a, const float *b, int n);
/* True when a and b hold the same registers apart from POSITION0 (so a shader may reuse a's instance work). */
bool vs_same_instance(const is_vs_input *a, const is_vs_input *b);
/* vs_write_outputs with decoded constants. */
void vs_write_outputs_k(const vs_batch_consts *k, float3 pos, float3 normal, float2 oTex, float3 b, float id,
                        float3 g, is_vs_output *out);
/* The batched body of the comparison shaders (flat, smooth-initial, smooth, phong, pn-aen): patch p. */
void vs_patch_batch(vs_patch p, const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t shared,
                    is_vs_output *out);

/* The batched entries of the npatch and smooth shaders (vs/batch8.c): interior vertices with linear normals 8 at a
 * time, the rest through the per-vertex evaluation; the same bytes as the per-vertex shaders in oPos and the live
 * outputs (the 8-lane groups compute and store only those; vertices on the per-vertex path write every output). */
void vs_npatch_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                     is_vs_output *out);
void vs_smooth_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                     is_vs_output *out);

/* The same with a grid workspace (is_vs_grid_batch_fn): the grid's b-only work (which vertices are interior, on an
 * edge or corners; the Bernstein products, the Gregory weights, the curve parameters) once per grid, the same bytes;
 * vs_batch8_grid_room is their is_vs_grid_room_fn. */
void vs_npatch_grid_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                          is_vs_grid *grid, is_vs_output *out);
void vs_smooth_grid_batch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live, uint32_t shared,
                          is_vs_grid *grid, is_vs_output *out);
size_t vs_batch8_grid_room(size_t n);

/* The smoothed patch's Listing 1.1.2 intermediates at one b (the pipeline inspector's view): the curve
 * parameters c, the face-normal factors fn, the N-Patch point posN, the centre blend bl, the blended P0..P2 (posN
 * where the shortcut skips one) and the Gregory weights g.  vs_smooth_formula is vs_smooth_traced without a
 * trace: the same operations, so the numbers are those of the render. */
typedef struct vs_smooth_trace {
    float3 c, fn, posN, g, pos[3];
    float bl;
} vs_smooth_trace;
float3 vs_smooth_traced(const vs_triangle *T, float3 b, uint32_t flags, float3 *gout, int *p_evals,
                        vs_smooth_trace *tr);

/* The explain stages (is_vs_explain_fn, vs/explain.c) of the patch shaders: b, the patch point and normal in
 * object space, where b lies (interior, edge, corner) and, for the smoothed patches, their intermediates. */
unsigned vs_explain_flat(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max);
unsigned vs_explain_npatch(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max);
unsigned vs_explain_smooth_initial(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max);
unsigned vs_explain_smooth(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max);
unsigned vs_explain_phong(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max);
unsigned vs_explain_pn_aen(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max);

/* The hull stages (vs/hull.c; is_vs_hull_fn of core/core.h) of the npatch and flat shaders. */
bool vs_npatch_hull(const is_vs_constants *c, const is_vs_input *in, is_patch_hull *h);
bool vs_flat_hull(const is_vs_constants *c, const is_vs_input *in, is_patch_hull *h);

/* HLSL lerp(a, b, t) = a + (b - a) t, except that t == 1 gives b exactly (Eq. 1.1.11 with bf = 1 is the N-Patch
 * term itself; a + (b - a) need not round to b). */
static inline float3 vs_lerp3(float3 a, float3 b, float t) { return t == 1.0f ? b : lerp3(a, b, t); }
static inline bool vs_finite3(float3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

#endif
