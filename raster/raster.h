/* raster/raster.h -- the one interface between the device (front end, core/) and the rasterizer (back end).
 *
 * Conventions (read these before anything else):
 *  - Input vertices are post-vertex-shader: pos is clip space (x, y, z, w) with Direct3D's clip volume
 *    -w <= x <= w, -w <= y <= w, 0 <= z <= w.  Every other output is an attribute slot (float4).
 *  - Viewport (D3D9): screen X = vp.x + (1 + x/w) * vp.width / 2, screen Y = vp.y + (1 - y/w) * vp.height / 2,
 *    depth = vp.min_z + (z/w) * (vp.max_z - vp.min_z).  Screen y grows downwards.
 *  - Pixel centres are at integer screen coordinates (D3D9; D3D10 and OpenGL put them at +0.5).  Pixel (i, j)
 *    is sampled at (i, j); with 4x multisampling at (i, j) + {(-2,-6), (6,-2), (-6,2), (2,6)} / 16.
 *  - Fill rule: top-left.  A sample exactly on an edge belongs to the triangle only if the edge is a top edge
 *    (horizontal, interior below it) or a left edge.  Abutting triangles therefore cover every sample once.
 *  - Winding: screen-space clockwise triangles are front faces.  RS_CULL_CCW (the D3D9 default) drops
 *    counter-clockwise ones, RS_CULL_CW drops clockwise ones.
 *  - Fixed point: screen positions snap to 1/RS_SUB = 1/256 pixel (RS_SUB_BITS = 8 sub-pixel bits).  Primitives are clipped to the guard
 *    band |X - cx|, |Y - cy| < RS_GUARD_BAND pixels around the viewport centre (cx, cy) (so there is always at
 *    least 8192 px of band around a viewport); edge functions are evaluated in int64 (budget in
 *    raster/setup.c).  Triangles outside the guard band are clipped against it, never overflowed.  Rendering is
 *    scissored to the viewport rectangle (and to the scissor rectangle when scissor_enable is set).
 *  - Depth: float32 in [min_z, max_z] (normally [0, 1]), smaller is nearer with RS_CMP_LESS.  Depth bias is
 *    depth_bias + slope_scale_depth_bias * max(|dz/dx|, |dz/dy|) (per pixel), added before the test; the biased
 *    depth is clamped to the viewport's depth range.
 *  - Colour: attribute slot RS_ATTR_COLOR0 is the pixel colour (RGBA, saturated to [0, 1], stored as 8 bits per
 *    channel, rounded to nearest).  Interpolation is perspective-correct for every slot (SHADEMODE GOURAUD); with
 *    FLAT the colour of the triangle's first vertex is used (D3D9's rule) for slots COLOR0 and COLOR1.
 *    Only slots that are both in attr_mask and consumed (COLOR0, and the target's AOV slots) are interpolated;
 *    a consumed slot missing from attr_mask reads (0, 0, 0, 0), except COLOR0 which reads opaque white.
 *  - Multisampling (4 samples and MULTISAMPLEANTIALIAS): coverage and depth per sample, colour shaded once per
 *    pixel at the pixel centre (no centroid).  A 4-sample target without MULTISAMPLEANTIALIAS gives every
 *    sample the pixel centre's coverage and depth.  Lines and points cover all samples of their pixels.
 *  - Lines: one pixel per pixel centre crossed on the major axis (|dx| >= |dy|: x), from the first vertex up to
 *    but excluding the last (D3DRS_LASTPIXEL FALSE); the minor pixel is the nearest pixel centre (ties to +).
 *    Points and point fill: the pixel whose centre is nearest (ties to +x / +y).  Wireframe draws the edges of
 *    the clipped polygon that lie on the input triangle's edges (not edges made by clipping); point fill its
 *    input vertices that survive clipping.
 *  - Blending: 8-bit math, out = min(255, round(src*fs/255) + round(dst*fd/255)) per channel (raster/frag.c).
 *  - Errors: functions return 0 on success or a negative RS_E* code.  Degenerate, non-finite or fully clipped
 *    primitives are silently dropped (counted in rs_stats) -- they are not errors.  NULL contexts, states and
 *    targets, and targets whose fields do not describe planes (rs_target_init's are always good) are refused:
 *    RS_EINVAL, or nothing done by the void functions; rs_threads(NULL) is 1, rs_max_pieces of a bad target 0
 *    (tests/test_api_raster.c walks every function).
 *  - Determinism: the same draw gives the same bytes for any thread count (tiles are owned by one thread and
 *    walk primitives in submission order).
 *  - Paths: every draw has a scalar reference path (rs_set_reference_path) and fast paths (shared vertex
 *    projection, four-lane set-up, 8-lane spans) that write the same bytes; the tests compare the two.  The
 *    fast paths exist once per instruction set (rs_set_isa: AVX2, and AVX-512 where the CPU has it, chosen at
 *    run time), again with the same bytes.
 *  - Frames: rs_target_clear_deferred starts a frame on a context (its clear is written tile by tile when a draw
 *    first touches a tile); until rs_target_flush the target's planes must be read or written only through that
 *    context.  The work bound (RS_MAX_OVERDRAW) counts per frame (each draw alone on a context that never
 *    started one).  With rs_set_scene on, a frame's rs_draw_source draws are recorded and share one set-up
 *    region and one tile pass, run when the target is flushed or cleared (or at rs_flush): same bytes as
 *    drawing them one by one.
 *  - Draw sources: rs_draw_source draws triangles whose vertices a callback produces piece by piece on the
 *    set-up threads (the device's instanced draws); same bytes as rs_draw on the concatenated pieces.
 */
#ifndef INSTESS_RASTER_H
#define INSTESS_RASTER_H


#include "../core/api.h"
#include <stddef.h>
#include <stdint.h>
#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the vertex the front end hands over: exactly the vertex shader's outputs ---- */
enum {
    RS_ATTR_COLOR0 = 0,    /* oD0: diffuse, the pixel colour           */
    RS_ATTR_COLOR1 = 1,    /* oD1: specular (carried, not used in colour) */
    RS_ATTR_TEXCOORD0 = 2, /* oT0 .. oT7 are slots 2 .. 9                */
    RS_MAX_ATTR = 10
};

typedef struct rs_vec4 { float x, y, z, w; } rs_vec4;

typedef struct rs_vertex {
    rs_vec4 pos;               /* oPos, clip space */
    rs_vec4 attr[RS_MAX_ATTR]; /* oD0, oD1, oT0..oT7 */
} rs_vertex;

/* ---- render states the rasterizer needs (a copy of the device's, values as in D3D9) ---- */
enum { RS_CULL_NONE = 1, RS_CULL_CW = 2, RS_CULL_CCW = 3 };
enum { RS_FILL_POINT = 1, RS_FILL_WIREFRAME = 2, RS_FILL_SOLID = 3 };
enum { RS_SHADE_FLAT = 1, RS_SHADE_GOURAUD = 2 };
enum {
    RS_CMP_NEVER = 1, RS_CMP_LESS, RS_CMP_EQUAL, RS_CMP_LESSEQUAL,
    RS_CMP_GREATER, RS_CMP_NOTEQUAL, RS_CMP_GREATEREQUAL, RS_CMP_ALWAYS
};
enum {
    RS_BLEND_ZERO = 1, RS_BLEND_ONE = 2, RS_BLEND_SRCCOLOR = 3, RS_BLEND_INVSRCCOLOR = 4,
    RS_BLEND_SRCALPHA = 5, RS_BLEND_INVSRCALPHA = 6, RS_BLEND_DESTALPHA = 7, RS_BLEND_INVDESTALPHA = 8,
    RS_BLEND_DESTCOLOR = 9, RS_BLEND_INVDESTCOLOR = 10,
    RS_BLEND_SRCALPHASAT = 11   /* (f, f, f, 1) with f = min(As, 1 - Ad) */
};
enum { RS_PRIM_POINTS = 1, RS_PRIM_LINES = 2, RS_PRIM_TRIANGLES = 4 };

#define RS_SUB_BITS 8          /* the fixed point of snapped screen positions: sub-pixel bits ... */
#define RS_SUB (1 << RS_SUB_BITS) /* ... and steps per pixel (256); the device's culling snaps as the rasterizer */
#define RS_GUARD_BAND 16384.0f /* pixels from the viewport centre; see setup.c for the bit budget */
#define RS_MAX_SIZE 16384      /* largest render target side */
#define RS_TILE_SIZE 128       /* the tile pass's square tiles on 1-sample targets (multisampled: 64), from the
                                * target's origin: the deferred clear's unit */

typedef struct rs_viewport { int x, y, width, height; float min_z, max_z; } rs_viewport;
/* A rectangle of pixels x0 <= x < x1, y0 <= y < y1 (the scissor). */
typedef struct rs_rect { int x0, y0, x1, y1; } rs_rect;
/* D3DSTENCILOP: what a stencil test outcome writes. */
enum {
    RS_STENCILOP_KEEP = 1, RS_STENCILOP_ZERO, RS_STENCILOP_REPLACE, RS_STENCILOP_INCRSAT, RS_STENCILOP_DECRSAT,
    RS_STENCILOP_INVERT, RS_STENCILOP_INCR, RS_STENCILOP_DECR
};
/* One face's stencil states: the test (RS_CMP_*: (ref & mask) func (stencil & mask)) and the operations on
 * stencil failure, stencil pass with depth failure, and both passing (RS_STENCILOP_*). */
typedef struct rs_stencil_ops { int func, fail, zfail, pass; } rs_stencil_ops;
#define RS_MAX_CLIP_PLANES 6   /* D3D9's user clip planes */

/* ---- the pixel shader: a C function run on 2x2 quads of pixels (D3D9 ps_3_0's model) ----
 * Lane k of a quad is pixel (x0 + (k & 1), y0 + (k >> 1)), x0 and y0 even.  The inputs are every slot of attr_mask
 * interpolated as the fixed path interpolates COLOR0 (perspective-correct, FLAT for COLOR0/1 with SHADEMODE FLAT),
 * at each lane's pixel centre, also for helper lanes the primitive does not cover (extrapolated from its planes;
 * a lane where that is undefined -- behind the eye -- gets its quad's covered pixel's inputs), so ddx = lane 1 -
 * lane 0 and ddy = lane 2 - lane 0 exist everywhere (coarse derivatives, as D3D9 hardware).  Lines and points run
 * quads whose four lanes hold the same inputs (derivatives zero).  A shader that reads only some slots may say so in
 * rs_state.ps_inputs (bit k: slot k is read; 0, the default: every slot): the others are not interpolated and
 * read (0, 0, 0, 0). */
typedef struct rs_ps_quad {
    rs_vec4 v[4][RS_MAX_ATTR];  /* per lane: COLOR0, COLOR1, TEXCOORD0..7 (slots of attr_mask and of rs_state's
                                   ps_inputs when not 0; others 0) */
    float vpos[4][2];           /* vPos: the lane's pixel (integers: D3D9's pixel centres) */
    bool front;                 /* vFace > 0: a clockwise (front) triangle; lines and points are front */
    unsigned live;              /* lanes the primitive covers (bit k: lane k); the others are helpers */
    unsigned need;              /* lanes whose results are used: a shader that takes no derivatives may compute
                                   only these (the others' outputs are ignored) */
} rs_ps_quad;
typedef struct rs_ps_out {
    rs_vec4 color[4];           /* oC0 per lane (saturated and rounded to 8 bits when written) */
    float depth[4];             /* oDepth per lane, used when depth_written (then clamped to the viewport range) */
    bool depth_written;
    unsigned kill;              /* texkill / clip: bit k drops lane k (no depth, stencil-pass or colour write) */
} rs_ps_out;
/* The shader: ctx is rs_state.ps_ctx; out is zeroed before the call.  Called from several threads at once. */
typedef void (*rs_ps_fn)(const void *ctx, const rs_ps_quad *q, rs_ps_out *out);

typedef struct rs_state {
    int cull_mode;            /* RS_CULL_*  */
    int fill_mode;            /* RS_FILL_*  */
    int shade_mode;           /* RS_SHADE_* */
    bool z_enable, z_write;
    int z_func;               /* RS_CMP_*   */
    bool blend_enable;
    int src_blend, dst_blend; /* RS_BLEND_* */
    bool multisample;         /* MULTISAMPLEANTIALIAS: use all samples of a 4-sample target */
    float depth_bias;         /* added to depth before the test (D3DRS_DEPTHBIAS) */
    float slope_scale_depth_bias; /* times max |dz/dx|, |dz/dy| (D3DRS_SLOPESCALEDEPTHBIAS) */
    uint32_t attr_mask;       /* bit k set: slot k is written by the shader and is interpolated */
    rs_viewport viewport;
    /* ---- D3D9's per-pixel and clipping states beyond the above (raster/pixel.c): all zero is off, the
     * behaviour of a state without them.  A draw with any of them on but the scissor takes the reference path
     * (same bytes for any thread count and instruction set). ---- */
    bool scissor_enable;      /* SCISSORTESTENABLE: draw only inside `scissor` (besides the viewport) */
    rs_rect scissor;          /* SetScissorRect, pixels x0 <= x < x1, y0 <= y < y1 */
    uint32_t color_write_disable; /* bit c set: channel c (R, G, B, A = D3DCOLORWRITEENABLE's bits 1, 2, 4, 8) is
                                     not written (COLORWRITEENABLE = 0xF & ~color_write_disable) */
    bool alpha_test;          /* ALPHATESTENABLE: keep a pixel when its 8-bit alpha alpha_func alpha_ref */
    int alpha_func;           /* RS_CMP_* */
    uint32_t alpha_ref;       /* 0..255 (low 8 bits of ALPHAREF) */
    bool stencil_enable;      /* STENCILENABLE (needs rt->stencil; without a stencil plane nothing is tested) */
    bool stencil_two_sided;   /* TWOSIDEDSTENCILMODE: counter-clockwise triangles use stencil_ccw */
    rs_stencil_ops stencil_cw, stencil_ccw; /* the front (clockwise, lines and points too) and CCW states */
    uint32_t stencil_ref, stencil_mask, stencil_write_mask; /* STENCILREF, STENCILMASK, STENCILWRITEMASK (8 bits used) */
    bool no_clipping;         /* CLIPPING FALSE: no near, far or user-plane clipping (only the guard band);
                                 depth is clamped to the viewport's range instead */
    uint32_t clip_plane_enable; /* CLIPPLANEENABLE bits 0..5: keep the part where dot(clip_plane[i], pos) >= 0 */
    float clip_plane[RS_MAX_CLIP_PLANES][4]; /* SetClipPlane, in clip space (a, b, c, d) */
    rs_ps_fn ps;              /* the pixel shader, or NULL: the fixed path (the pixel colour is COLOR0) */
    const void *ps_ctx;       /* its context (the device's constants and samplers) */
    uint32_t ps_inputs;       /* slots the pixel shader reads (bit k: slot k; 0: every slot); the others read 0 */
    bool pretransformed;      /* POSITIONT / XYZRHW: pos is (X, Y, Z, RHW) in screen pixels, depth Z (no
                                 viewport mapping, no user planes), 1/w = RHW for perspective-correct attributes */
} rs_state;

/* ---- the render target: colour and depth per sample, optional float AOV planes per pixel ---- */
#define RS_MAX_AOV 8
typedef struct rs_aov {
    int slot;     /* attribute slot copied into this plane (e.g. RS_ATTR_TEXCOORD0 + 1) */
    int comps;    /* 1..4 components taken from x, y, z, w */
    float *data;  /* width * height * comps floats, row-major, top row first */
} rs_aov;

typedef struct rs_target {
    int width, height;
    int samples;        /* 1 or 4 */
    uint32_t *color;    /* width*height*samples, sample-major inside a pixel: [(y*w + x)*samples + s],
                           packed R | G<<8 | B<<16 | A<<24 (byte order R, G, B, A in memory) */
    float *depth;       /* same layout as color */
    int n_aov;          /* AOV planes, written only when samples == 1, by the fragment that passes depth */
    rs_aov aov[RS_MAX_AOV];
    uint8_t *stencil;   /* the 8 stencil bits of D3D24S8 per sample, same layout as color (rs_target_init
                           allocates it, zeroed; NULL in a hand-made target: no stencil test) */
} rs_target;

/* Counters of one rs_draw call (for tests and the benchmark).  prims_* count input primitives: culled by
 * winding, clipped away (entirely outside the clip volume), degenerate (zero area after snapping, zero-length
 * line, or a non-finite position), drawn (the rest).  samples_tested: covered samples that reached the depth
 * test (with raster/pixel.c's states: every covered sample, the alpha test's failures included);
 * samples_written: those that passed it (colour written).  Zeroed when rs_draw fails.
 * setup_ms, tile_ms: wall-clock milliseconds of the draw's two phases, measured only with rs_set_timing on
 * (else 0, so that the counters of two runs compare equal byte for byte): setup_ms the set-up (projection,
 * clipping, set-up and binning of every chunk; for rs_draw_source also the producer's shading), tile_ms the tile
 * pass (deferred clear into the tile buffers, rasterization, copy-out).  A draw run at once has one parallel
 * region for each, and everything else of it (validation, the checks between the regions, summing the counters)
 * is in neither; a flush of the frame's scene (rs_set_scene) runs both phases in one region, setup_ms from its
 * start to the end of the last piece, tile_ms the rest (the checks between the phases included).
 * setup_regions, tile_regions: the set-up regions and tile passes run (one each per draw, or per flush of the
 * frame's scene: rs_set_scene), counted only with rs_set_timing on (else 0), whatever the thread count. */
typedef struct rs_stats {
    uint64_t prims_in, prims_culled, prims_clipped_away, prims_degenerate, prims_drawn;
    uint64_t samples_tested, samples_written;
    double setup_ms, tile_ms;
    uint64_t setup_regions, tile_regions;
} rs_stats;

typedef struct rs_context rs_context;

enum { RS_OK = 0, RS_EINVAL = -1, RS_ENOMEM = -2, RS_EWORK = -3 };
/* Work is bounded by the output, not by the input: a frame -- the draws on a context since its last
 * rs_target_clear_deferred, or one draw on a context that never had one -- may cover the target's pixels at
 * most RS_MAX_OVERDRAW times on average.  Set-up counts each triangle as min(its area, its pixel box clipped
 * to the scissor), exactly in fixed point (about the pixels it covers, in integers, so the same for any thread
 * count); a draw that would pass the bound returns RS_EWORK and draws nothing (100,000 copies of one
 * screen-filling triangle, say).  Closed meshes cover a pixel a few times; lines and points are not counted. */
#define RS_MAX_OVERDRAW 1024
/* ... but never less than this many pixels of work (4 M: a few milliseconds), so small targets keep room. */
#define RS_MIN_WORK ((uint64_t)1 << 22)

/* Create a rasterizer that uses up to `threads` threads (0: all cores). NULL when out of memory. */
INSTESS_API rs_context *rs_create(int threads);
/* Free the rasterizer and its scratch memory. */
INSTESS_API void rs_destroy(rs_context *rs);
/* Change the thread count (0: all cores). */
INSTESS_API void rs_set_threads(rs_context *rs, int threads);
/* The threads a draw on rs uses (the count set, or the cores for 0); at least 1. */
INSTESS_API int rs_threads(const rs_context *rs);
/* The scalar reference path on (every draw takes the simplest per-sample loops: set-up per triangle, tri.c's
 * per-pixel walk, no tile buffers) or off (the default: the fast paths, which write the same bytes). */
INSTESS_API void rs_set_reference_path(rs_context *rs, bool on);
/* Instruction sets of the fast paths: each has its own copy of the fast kernels, and all of them write the same
 * bytes.  rs_create picks the widest one the CPU (and the build) supports. */
enum { RS_ISA_AVX2 = 0, RS_ISA_AVX512 = 1, RS_ISA_COUNT };
/* Does this CPU (and this build) run instruction set isa's kernels? */
INSTESS_API bool rs_isa_supported(int isa);
/* The widest instruction set this CPU runs (what rs_create picks). */
INSTESS_API int rs_isa_best(void);
/* The fast paths of rs use instruction set isa: RS_OK, or RS_EINVAL (nothing changed) when it is unsupported. */
INSTESS_API int rs_set_isa(rs_context *rs, int isa);
/* The instruction set rs's fast paths use. */
INSTESS_API int rs_isa(const rs_context *rs);
/* "avx2", "avx512", or NULL for an unknown value; rs_isa_parse is the inverse (-1: unknown name). */
INSTESS_API const char *rs_isa_name(int isa);
INSTESS_API int rs_isa_parse(const char *name);
/* The frame's scene on (sink non-NULL) or off (NULL, the default; the queue is flushed first).  With it on, a
 * rs_draw_source draw on the fast path into the target of the frame the last rs_target_clear_deferred started is
 * recorded, not run: its state and source are checked and copied (RS_EINVAL, RS_ENOMEM returned at once) and it
 * returns RS_OK with its rs_stats zero.  A flush -- rs_flush, rs_target_flush, rs_target_clear_deferred, rs_draw,
 * rs_set_threads, a draw on another target, or the queue's set-up memory passing its budget -- then runs ONE
 * set-up region in which the threads take pieces across all recorded draws (shading, projection, set-up,
 * binning), checks each draw in submission order (a draw whose pieces break their promise, that runs out of
 * memory or that would pass the frame's work bound is dropped whole, its error kept for rs_scene_error), and
 * runs ONE tile pass in which each tile walks the draws in submission order: the same bytes as drawing them one
 * by one.  The recorded draws' counters (prims_* and samples_*, setup_ms, tile_ms) are added to *sink.  Until the
 * flush the source's ctx and what its producer reads must stay valid and unchanged, the target's planes must not
 * be read or written (as a deferred clear's), and *sink must stay valid. */
INSTESS_API void rs_set_scene(rs_context *rs, rs_stats *sink);
/* Run the recorded draws of rs_set_scene now (nothing when none is recorded). */
INSTESS_API void rs_flush(rs_context *rs);
/* The first error (RS_EINVAL, RS_ENOMEM, RS_EWORK) of a recorded draw that a flush dropped since the last call,
 * or RS_OK; the call forgets it.  RS_OK for NULL. */
INSTESS_API int rs_scene_error(rs_context *rs);
/* Measure each draw's phase times into rs_stats.setup_ms / tile_ms (on) or leave them 0 (off, the default).
 * Timing changes no image byte and no counter; it costs two clock reads per region. */
INSTESS_API void rs_set_timing(rs_context *rs, bool on);

/* Allocate a target of w x h pixels with `samples` (1 or 4) samples; RS_EINVAL for bad sizes. */
INSTESS_API int rs_target_init(rs_target *rt, int width, int height, int samples);
/* Free a target's planes (also its AOV planes). */
INSTESS_API void rs_target_free(rs_target *rt);
/* Add an AOV plane copying `comps` components of attribute `slot`; RS_EINVAL if samples != 1 or full. */
INSTESS_API int rs_target_add_aov(rs_target *rt, int slot, int comps);
/* What a clear writes (D3DCLEAR_TARGET and D3DCLEAR_ZBUFFER have these values). */
enum { RS_CLEAR_COLOR = 1 /* colour and AOV planes */, RS_CLEAR_DEPTH = 2, RS_CLEAR_STENCIL = 4 /* see rs_target_clear_stencil */,
       RS_DISCARD_DEPTH = 8 /* rs_target_flush_planes: the drawn depth is not kept (below) */,
       RS_PRESENT = 16 /* rs_target_flush_planes: a present, the planes only read until the next frame (below) */ };
/* Clear colour (packed RGBA8) and depth of every sample, and AOV planes to 0 (flags: RS_CLEAR_*). */
INSTESS_API void rs_target_clear(rs_target *rt, unsigned flags, uint32_t rgba, float z);
/* The same for the pixels x0 <= x < x1, y0 <= y < y1 only (clipped to the target); no deferred clear of rt may be
 * pending (rs_target_flush first). */
INSTESS_API void rs_target_clear_rect(rs_target *rt, int x0, int y0, int x1, int y1, unsigned flags, uint32_t rgba,
                                      float z);
/* rs_target_clear deferred, and a new frame on rs (its work count restarts): each tile of rt (RS_TILE_SIZE, 64 when
 * multisampled) is written (in cache) when a draw on rs first touches it, or by rs_target_flush.  Until
 * rs_target_flush, rt's planes must only be drawn into through rs.  Nothing happens without flags (or without rs, rt
 * or its planes). */
INSTESS_API void rs_target_clear_deferred(rs_context *rs, rs_target *rt, unsigned flags, uint32_t rgba, float z);
/* Write every tile of rt whose clear is still deferred on rs (call before anything else reads or writes rt's
 * planes). */
INSTESS_API void rs_target_flush(rs_context *rs, rs_target *rt);
/* rs_target_flush for the planes in `planes` alone (RS_CLEAR_COLOR: colour and AOV planes; RS_CLEAR_DEPTH): those
 * may then be read; the others' deferred clear stays deferred (a present reads only the colour: the depth of the
 * tiles no draw touched is then written only if something reads it -- rs_target_flush -- before the next
 * rs_target_clear_deferred replaces it).  The queued draws run first, as for rs_target_flush.  With
 * RS_DISCARD_DEPTH in `planes` (D3DPRESENTFLAG_DISCARD_DEPTHSTENCIL: the depth is not needed after the present)
 * the depth the queued draws write is dropped too in every tile whose depth clear was deferred: that clear stays
 * deferred, so the depth plane then reads as the cleared value there (the tile pass skips the depth's copy-out);
 * tiles whose depth was not cleared keep the drawn depth.  With RS_PRESENT in `planes` the caller promises that
 * nothing writes rt's planes but through rs until the next rs_target_clear_deferred: the tiles no draw touched,
 * whose colour this flush fills with the clear's, are remembered, and when the next frame's deferred clear has
 * the same colour and leaves them untouched too they are not written again (they hold those bytes already).  Any
 * flush without RS_PRESENT forgets them (its caller may write the planes), as does a clear of another colour. */
INSTESS_API void rs_target_flush_planes(rs_context *rs, rs_target *rt, unsigned planes);
/* Set the stencil of every sample of pixels x0 <= x < x1, y0 <= y < y1 (clipped to the target) to the low 8 bits
 * of value (D3DCLEAR_STENCIL; never deferred: the stencil plane is only written by stencil draws and this). */
INSTESS_API void rs_target_clear_stencil(rs_target *rt, int x0, int y0, int x1, int y1, uint32_t value);
/* Average the samples of each pixel into out (width*height packed RGBA8), per channel, rounding to nearest
 * (halves up: (sum + 2) / 4). */
INSTESS_API void rs_target_resolve(const rs_target *rt, uint32_t *out);

/* Draw n_prims primitives of `prim` (points, lines or triangles) whose vertices are verts[idx[k]]
 * (idx == NULL: consecutive).  Triangles obey fill_mode (wireframe draws each triangle's three edges as
 * lines, point fill its three vertices).  Returns RS_OK, or RS_EINVAL / RS_ENOMEM / RS_EWORK with nothing
 * drawn. */
INSTESS_API int rs_draw(rs_context *rs, const rs_state *st, rs_target *rt, int prim,
            const rs_vertex *verts, size_t n_verts, const uint32_t *idx, size_t n_prims,
            rs_stats *stats);

/* ---- draw sources: triangles whose vertices are produced piece by piece on the set-up threads ----
 * The device's fast path for instanced draws: each piece (a few instances) is shaded, projected, set up and
 * binned by one thread while its vertices are still in the cache, so one draw costs one set-up region and one
 * tile region (with rs_set_scene: a frame's recorded draws share one region for both), and the shaded vertices
 * never go through memory.  Each piece is one set-up chunk, in order, so the bytes are those of rs_draw on
 * the concatenated pieces. */
/* Produce piece `piece`: vertices into *verts (n_verts of them, at most the source's max_verts), its triangles'
 * indices (into *verts, 3 per triangle) into *idx; returns the triangle count.  `slot` (below rs_threads) is the
 * calling thread's: pieces produced at the same time have different slots, so a producer may keep one scratch
 * per slot.  Called from several threads at once. */
typedef size_t (*rs_produce_fn)(void *ctx, size_t piece, int slot, rs_vertex **verts, size_t *n_verts,
                                const uint32_t **idx);
typedef struct rs_source {
    size_t n_pieces;      /* at most rs_max_pieces */
    size_t n_prims;       /* triangles of all pieces at most (a producer may drop instances it culls) */
    size_t max_verts;     /* vertices of the largest piece */
    rs_produce_fn produce;
    void *ctx;            /* passed to produce */
    size_t group_prims;   /* 0, or the triangles of one instance: each piece's triangles in runs of this many
                             (the last may be shorter) are binned to tiles as one entry and set up inside the
                             tile pass, when the piece allows it (raster_internal.h: grouped pieces); the same
                             bytes and counters either way */
    size_t grid_level;    /* 0, or L in 1..RS_GRID_MAX_LEVEL with group_prims = L*L (else RS_EINVAL): the producer
                             promises that group g of each piece is the regular barycentric grid of level L
                             (core_grid_regular) over its own P = (L+1)(L+2)/2 vertices g*P .. g*P+P-1: vertex
                             rows k = 0..L of L+1-k vertices, row k starting at g*P + k*(L+1) - k*(k-1)/2; row k's
                             triangles, in this order, (r_k[i], r_k[i+1], r_k+1[i]) and, for i < L-k-1,
                             (r_k[i+1], r_k+1[i+1], r_k+1[i]) for i = 0..L-k-1.  The rasterizer may then set such
                             groups up from the vertex rows without reading their indices (the same bytes; a
                             piece that breaks the promise draws something else, never out of its vertices) */
    bool grid_mirrored;   /* with grid_level: the promise is of that list mirrored, each triangle's second and third
                             index swapped (core_grid_regular_level_mirrored): the same triangles wound the other
                             way, so the row set-up culls the other sign (a triangle's vertices end up in the same
                             clockwise order either way) */
} rs_source;
/* The largest rs_source.grid_level (core_grid_regular's limit). */
#define RS_GRID_MAX_LEVEL 16384
/* The most pieces one rs_draw_source may have on target rt (its tile bins must stay bounded). */
INSTESS_API size_t rs_max_pieces(const rs_target *rt);
/* Set-up work of fewer triangles than this (a draw, or a flush of queued draws) runs on one thread: waking a
 * second one costs more (scene C, 192 triangles: 0.03 ms on 1 thread, 0.11-0.14 ms on 2; ~20-30 ns a triangle).
 * A producer may size its pieces by it (core/draw_fused.c: a small draw in few, large pieces). */
#define RS_PARALLEL_SETUP_MIN 8192u
/* Draw the triangles of src (rs_stats.prims_in counts those the pieces gave): RS_OK, or RS_EINVAL (bad state,
 * target or source: too many pieces, pieces whose triangles add up to more than n_prims, or a piece without
 * vertices or indices, with more than max_verts vertices or an index past its vertices), RS_ENOMEM or RS_EWORK with nothing drawn. */
INSTESS_API int rs_draw_source(rs_context *rs, const rs_state *st, rs_target *rt, const rs_source *src, rs_stats *stats);

#ifdef __cplusplus
}
#endif
#endif
