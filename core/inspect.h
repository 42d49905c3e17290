/* core/inspect.h -- the pipeline inspector: one pixel's whole way through the device's draws, recorded while the
 * device draws (what PIX did for Direct3D 9 on a GPU, for the draws of instess).
 *
 * Conventions:
 *  - Recording is a mode of the device, off by default and free when off (one pointer test per draw).
 *    dev_inspect_begin(dev, x, y, rec) starts it for pixel (x, y) of the render target; every draw after it
 *    appends to rec the fragments that reached the pixel, in the order the device's rules apply them (draws in
 *    call order, instances in order, primitives in index order); dev_inspect_end stops it.
 *  - A fragment is one primitive covering the pixel centre (D3D9's rules: top-left fill, pixel centres at
 *    integer coordinates): its draw (counted from 0 since dev_inspect_begin), instance (in the technique: the mesh
 *    triangle), primitive within the instance (the grid triangle), and for each of its three vertices the
 *    per-vertex and per-instance indices, the input registers the declaration filled (with their usage and usage
 *    index), the vertex shader's outputs, and the values the shader publishes (is_vertex_shader.explain: the
 *    patch shaders give the barycentrics b, the patch point and normal, and the smoothed patch its Listing 1.1.2
 *    intermediates); then the barycentrics at the pixel centre (perspective-correct, of vertices 0, 1, 2), the
 *    fragment's depth (bias and clamp applied), the depth buffer's value before it, the depth test's verdict, and
 *    the colour in the pixel after it (blending applied).
 *  - The values are exact: each candidate primitive is drawn again by the rasterizer (rs_draw, reference path)
 *    into a one-pixel target placed at (x, y) with the viewport moved by whole pixels, which leaves every
 *    snapped position relative to the viewport centre unchanged; the pixel holds what the render target held
 *    before the draw.  So the last fragment's colour and depth are the target's (tests/test_inspect.c checks it).
 *  - Limits: the device's draws of triangles (lists, strips, fans) with one sample per pixel are recorded; the
 *    device's own N-patch mode, points and lines, and draws into a render target of another size than the one
 *    recording began on (SetRenderTarget), are counted in draws_skipped.  At most IS_INSPECT_MAX_FRAGMENTS
 *    fragments are kept (the rest counted in fragments_dropped).
 *  - Errors: dev_inspect_begin returns IS_ERR_INVALIDCALL for a NULL device or record, a pixel outside the target,
 *    or a multisampled target (nothing changes).  Recording that runs out of memory stops recording and sets
 *    rec->out_of_memory; the draws themselves are never affected.
 */
#ifndef INSTESS_INSPECT_H
#define INSTESS_INSPECT_H

#include "api.h"
#include "device.h"

#ifdef __cplusplus
extern "C" {
#endif

#define IS_INSPECT_MAX_FRAGMENTS 1024
#define IS_INSPECT_MAX_VALUES 24   /* values one vertex's shader may publish */

/* One input register the declaration filled: its usage (IS_DECLUSAGE_*), usage index, stream and value. */
typedef struct is_inspect_input {
    uint8_t usage, usage_index, stream;
    bool per_instance;          /* read by instance (INSTANCEDATA) rather than by vertex */
    float4 value;
} is_inspect_input;

typedef struct is_inspect_vertex {
    uint32_t vertex;            /* index into the per-vertex streams (after BaseVertexIndex) */
    uint32_t instance;          /* index into the per-instance streams */
    unsigned n_inputs;
    is_inspect_input inputs[IS_MAX_ELEMENTS];   /* the declaration's elements, in its order */
    is_vs_input regs;           /* the input registers as the shader read them (those no element fills (0,0,0,1)) */
    is_vs_output out;           /* oPos, COLOR0/1 (saturated), TEXCOORD0..7 */
    uint32_t outputs;           /* the shader's IS_OUT_* mask */
    unsigned n_values;
    is_vs_value values[IS_INSPECT_MAX_VALUES]; /* what the shader published (explain), in its order */
} is_inspect_vertex;

typedef struct is_inspect_fragment {
    unsigned draw;              /* draw number since dev_inspect_begin */
    uint32_t instance;          /* instance of the draw (the mesh triangle) */
    uint32_t primitive;         /* primitive within the instance (the grid triangle) */
    is_inspect_vertex v[3];
    float bary[3];              /* perspective-correct weights of v[0], v[1], v[2] at the pixel centre */
    float depth;                /* the fragment's depth */
    float depth_before;         /* the depth buffer before the fragment */
    bool passed;                /* the depth test's verdict (true when ZENABLE is off) */
    uint32_t color_before, color_after; /* the pixel, packed RGBA8 (R in the low byte) */
} is_inspect_fragment;

typedef struct is_inspect {
    int x, y;                   /* the pixel */
    unsigned draws;             /* draws recorded */
    unsigned draws_skipped;     /* draws not recorded (N-patch mode, points, lines) */
    size_t n_fragments;
    is_inspect_fragment *fragments;
    size_t fragments_dropped;   /* beyond IS_INSPECT_MAX_FRAGMENTS */
    bool out_of_memory;
} is_inspect;

/* Start recording pixel (x, y) of dev's render target into rec (emptied first): IS_OK or IS_ERR_INVALIDCALL. */
INSTESS_API is_result dev_inspect_begin(is_device *dev, int x, int y, is_inspect *rec);
/* Stop recording (rec keeps what was recorded); nothing for a device that does not record. */
INSTESS_API void dev_inspect_end(is_device *dev);
/* Free what rec holds (rec may be NULL or empty). */
INSTESS_API void is_inspect_free(is_inspect *rec);
/* The name of a declaration usage ("POSITION", "TEXCOORD", ...), "?" for an unknown value. */
INSTESS_API const char *is_decl_usage_name(unsigned usage);

#ifdef __cplusplus
}
#endif
#endif
