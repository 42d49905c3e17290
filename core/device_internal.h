/* core/device_internal.h -- the device's private state, shared by core/device.c, resources.c, draw.c and
 * draw_fused.c: the device, buffers and declarations, and a draw's fetch plan.  Private to core/ (tests/ may look).
 *
 * Conventions: as core.h; D3D9's fetch address is spelled once, in fetch_offset. */
#ifndef INSTESS_DEVICE_INTERNAL_H
#define INSTESS_DEVICE_INTERNAL_H

#include "core.h"
#include "hlsl.h"

#include <omp.h>
#include <math.h>
#include <stdarg.h>
#include <string.h>

/* The device's registry of its live buffers and declarations: every one starts with a dev_res, linked into its
 * device's list from creation to release.  A handle given to the device is looked up in the list by its address
 * (never read before it is found there, of the right kind), so a buffer of another device, a released one or a
 * pointer that names no resource at all is refused without touching its memory.  The registry also counts the
 * resources' reference to their device (D3D9's): dev_destroy frees the device's memory and the memory of every
 * resource still listed (their data: lock returns NULL, size 0), and the small structs themselves stay until each
 * is released -- the device's last few bytes with its last -- so releasing after dev_destroy is safe. */
typedef enum { DEV_RES_VB = 1, DEV_RES_IB, DEV_RES_DECL, DEV_RES_SB, DEV_RES_SURF } dev_res_kind;
typedef struct dev_res {
    struct dev_res *prev, *next;
    is_device *dev;
    dev_res_kind kind;
} dev_res;
/* Link r (of kind, owned by dev) into dev's registry. */
void dev_res_add(is_device *dev, dev_res *r, dev_res_kind kind);
/* Unlink r from its device's registry; frees a destroyed device with its last resource. */
void dev_res_remove(dev_res *r);
/* Whether p is a live resource of dev of that kind (p compared, never read). */
bool dev_res_owns(const is_device *dev, const void *p, dev_res_kind kind);

/* printf into err (when err and errlen are given), always NUL-terminated: the message of a failed call. */
void core_set_err(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Threads when the caller asked for "all cores". */
static inline int omp_threads(void) { return omp_get_num_procs(); }

struct is_vertex_buffer {
    dev_res res;            /* first: the registry's link (res.dev: the device) */
    unsigned char *data;
    size_t size;
    uint64_t scene_gen;     /* a draw recorded in the device's scene generation scene_gen reads it (dev_scene) */
};

struct is_index_buffer {
    dev_res res;
    unsigned char *data;
    size_t size;
    is_format format;
};

/* One element, resolved at creation: where it reads and which input register it fills. */
typedef struct decl_element {
    is_vertex_element e;
    unsigned size;          /* bytes read */
    unsigned reg_offset;    /* byte offset of the float4 register inside is_vs_input */
} decl_element;

struct is_vertex_declaration {
    dev_res res;
    unsigned n;
    decl_element el[IS_MAX_ELEMENTS];
    uint32_t stream_mask;   /* streams the declaration reads */
    bool positiont;         /* an element of usage POSITIONT: pre-transformed vertices (core/raster_states.c) */
};

/* The viewport as the rasterizer gets it (dev_rs_state): the set viewport clipped to the target, and the affine map
 * of clip-space x and y that places a vertex through the clipped viewport where the set one would put it
 * (x' = ax x + bx w, y' = ay y + by w); `on` false when the set viewport lies inside the target (no map: the
 * shaded bytes are untouched).  dev_viewport_update computes it whenever the viewport changes. */
typedef struct vp_remap {
    bool on;
    float ax, bx, ay, by;
} vp_remap;

typedef struct stream_source {
    is_vertex_buffer *vb;
    unsigned offset, stride;
    uint32_t freq;          /* as given to SetStreamSourceFreq; 1 by default */
} stream_source;

/* One level of a texture: w x h texels at bits, rows tightly packed. */
typedef struct tex_level {
    unsigned w, h;
    unsigned char *bits;
} tex_level;

/* A texture (core/texture.c): every level in one allocation, in the device's list of live textures. */
struct is_texture {
    is_device *dev;
    is_texture *prev, *next;   /* the device's live textures (dev->textures) */
    is_format format;
    uint32_t usage;
    unsigned bpp;              /* bytes per texel */
    unsigned levels;           /* levels kept (the whole chain of an AUTOGENMIPMAP texture) */
    uint32_t locked;           /* bit l: level l is locked */
    bool lock0_readonly;       /* level 0 is locked with IS_LOCK_READONLY */
    tex_level lv[IS_MAX_TEXTURE_LEVELS];
    unsigned char *mem;
    is_surface *surf[IS_MAX_TEXTURE_LEVELS]; /* GetSurfaceLevel's surfaces, made on first use (core/surface.c) */
};

/* A surface (core/surface.c, rules in core/device.h "render targets and surfaces"): a render target (usage
 * IS_USAGE_RENDERTARGET: `color`, packed RGBA8 as rs_target's plane), a depth-stencil surface (IS_USAGE_DEPTHSTENCIL:
 * `depth` and `stencil`, as rs_target's), a system-memory surface (usage 0: `bits`, the format's D3D9 layout), or
 * level `level` of texture `tex` (its texels in tex->lv; a render-target texture's level gets a `color` plane while
 * it is the device's target, converted back into its texels when another target is set).  The device's back
 * buffer and automatic depth-stencil surface are embedded in the device (`implicit`: not in the registry, never
 * released); the others are in the registry (DEV_RES_SURF), texture levels until their texture is released. */
struct is_surface {
    dev_res res;               /* first: the registry's link (res.dev: the device, also for implicit ones) */
    uint32_t usage;            /* IS_USAGE_RENDERTARGET, IS_USAGE_DEPTHSTENCIL, or 0 (system memory) */
    is_format format;
    unsigned width, height;
    int samples;               /* 1 or 4 */
    bool implicit;             /* the back buffer or the automatic depth-stencil surface */
    bool locked;               /* a system-memory surface is locked */
    is_texture *tex;           /* a texture's level, or NULL */
    unsigned level;
    uint32_t *color;           /* 64-byte aligned planes (rs_target_init's) */
    float *depth;
    uint8_t *stencil;
    unsigned char *bits;       /* a system-memory surface's pixels, rows of width * 4 bytes */
    int n_aov;                 /* the back buffer's AOV planes while another target is set */
    rs_aov aov[RS_MAX_AOV];
};
/* (surface.c) Set dev's render target and depth-stencil surface (either may be the current one): flushes the
 * deferred clear, converts a render-target texture's level back into texels, and makes dev->rt describe rt's
 * colour plane and ds's depth and stencil (directly when ds has rt's size and samples, else a scratch plane with
 * ds's top-left copied in, or with depth off: dev->no_depth).  IS_ERR_OUTOFMEMORY with nothing changed. */
is_result dev_bind_targets(is_device *dev, is_surface *rt, is_surface *ds);
/* (surface.c) Free the planes of a surface (not the struct); dev_destroy and the releases. */
void surf_free_planes(is_surface *s);
/* (surface.c) Release texture t's level surfaces (t is being released): the device goes back to its back buffer
 * when one of them is its target. */
void surf_release_texture_levels(is_texture *t);

/* The samplers a device keeps besides the vertex shader's (which are dev->consts.s): pixel samplers 0..15 and
 * the displacement-map sampler. */
#define DEV_PS_SAMPLERS (IS_MAX_PS_SAMPLERS + 1)

/* Every sampler of a device, numbered for stateblocks: 0..15 the pixel samplers, 16 D3DDMAPSAMPLER, 17..20 the
 * vertex samplers (D3DVERTEXTEXTURESAMPLER0..3). */
#define DEV_ALL_SAMPLERS (DEV_PS_SAMPLERS + IS_MAX_VS_SAMPLERS)

/* A stateblock (core/stateblock.c): values of the device's state and which of them it holds (D3D9's lists for
 * ALL, PIXELSTATE and VERTEXSTATE, or what was set while it was recorded).  Its buffers, declaration and textures
 * are pointers the device forgets from every stateblock when they are released (sb_forget). */
typedef struct is_state_block {
    dev_res res;                               /* first: the registry's link (DEV_RES_SB) */
    uint32_t rs[IS_RS_COUNT];
    is_viewport viewport;
    stream_source streams[IS_MAX_STREAMS];
    is_index_buffer *ib;
    is_vertex_declaration *decl;
    const is_vertex_shader *vs;
    float4 c[IS_MAX_VS_CONSTANTS];
    const is_pixel_shader *ps;
    float4 pc[IS_MAX_PS_CONSTANTS];
    is_sampler samplers[DEV_ALL_SAMPLERS];
    /* what it holds */
    bool has_rs[IS_RS_COUNT];
    bool has_c[IS_MAX_VS_CONSTANTS];
    bool has_pc[IS_MAX_PS_CONSTANTS];
    bool has_ps;
    is_rect scissor;                           /* SetScissorRect, SetClipPlane (ALL blocks, as DXVK's) */
    float clip_plane[IS_MAX_USER_CLIP_PLANES][4];
    bool has_scissor;
    uint32_t has_clip_plane;                   /* bit k: plane k */
    uint32_t has_samp[DEV_ALL_SAMPLERS];       /* bit t: sampler state t */
    uint32_t has_tex;                          /* bit k: sampler k's texture */
    uint32_t has_source;                       /* bit s: stream s's buffer, offset and stride */
    uint32_t has_freq;                         /* bit s: stream s's frequency */
    bool has_viewport, has_ib, has_decl, has_vs;
} is_state_block;

/* Sampler k of dev in stateblock numbering (DEV_ALL_SAMPLERS), and the number of sampler s of dev. */
is_sampler *dev_sampler_at(is_device *dev, unsigned k);
unsigned dev_sampler_number(const is_device *dev, const is_sampler *s);
/* Drop a released buffer, declaration or texture p from every stateblock of dev (the recorded one included). */
void sb_forget(is_device *dev, const void *p);
/* Free the stateblock dev is recording, if any (dev_reset, dev_destroy). */
void sb_abort_recording(is_device *dev);

/* Every sampler of dev back to D3D9's defaults, without a texture (core/texture.c). */
void dev_samplers_default(is_device *dev);
/* Release every texture dev still owns (dev_destroy). */
void dev_release_textures(is_device *dev);

/* A buffer of a device's draw scratch: kept between draws and grown only (scratch_get). */
typedef struct scratch_buf {
    void *p;
    size_t bytes;
} scratch_buf;

/* The frame's recorded draws (draw_fused.c): each instanced draw on the fused path is recorded -- a snapshot of
 * its shader, constants, fetch plan, per-vertex inputs and index list -- and handed to the rasterizer, which runs
 * the frame's recorded draws in one set-up region and one tile pass at its next flush (raster.h rs_set_scene).
 * The records stay valid until dev_scene_flush (they are reused, never freed, between frames); the vertex
 * buffers they read are marked with the generation (a Lock or a release of a marked buffer flushes first). */
typedef struct fused_rec fused_rec;
typedef struct dev_scene {
    fused_rec **recs;       /* recs[0..n): this generation's records; recs[n..cap): free ones (or NULL) */
    size_t n, cap;
    uint64_t serial;        /* the last record's serial number (1, 2, ...: never reused) */
    uint64_t gen;           /* the generation: dev_scene_flush starts the next */
    is_result err;          /* the first error of a recorded draw at a flush, until dev_flush reports it */
} dev_scene;

/* How a recorded draw fills a slot's input registers (draw_fused.c): its shader's entries, its vertex count (a
 * slot's: the entries made with this shape), which registers its per-vertex elements fill (vreg[q] for the fetch
 * cache's element q) and which its per-instance elements fill.  Two draws of the same layout whose per-vertex
 * values are equal leave the same registers. */
typedef struct fused_layout {
    bool valid;                 /* false: the slot's registers are not known (fresh scratch) */
    bool per_call;              /* the shader is called per vertex (per-instance registers in every entry) */
    is_vs_grid_batch_fn grid_fn; /* the shader's grid_batch (its workspace's format) */
    uint32_t count, inst_regs, n_vert;
    uint8_t vreg[IS_MAX_ELEMENTS];
} fused_layout;

/* The per-thread scratch of the recorded draws' producers (draw_fused.c), sized when a draw is recorded and used
 * at the flush: per slot (rs_produce_fn's) v_slot shaded vertices, in_slot input registers and list_slot indices,
 * which record's inputs (tag) and index list (ltag, lcount instances of it) the slot holds, and the layout its
 * input registers were last made with (lay: a draw of the same layout and per-vertex values keeps them, and the
 * shader's grid workspace with them). */
typedef struct fused_scratch {
    int slots;
    size_t v_slot, in_slot, list_slot;
    rs_vertex *v;
    is_vs_input *in;
    uint32_t *list;
    uint64_t *tag, *ltag;
    uint32_t *lcount;
    fused_layout *lay;
    is_vs_grid *grid;          /* per slot: the shader's grid workspace (grid_batch), grid_room bytes each */
    unsigned char *grid_mem;
    size_t grid_room;
} fused_scratch;

struct is_device {
    /* The registry of live buffers and declarations (dev_res above): they hold a reference to their device, as
     * D3D9's do, so a destroyed device's struct is freed with its last resource. */
    dev_res *resources;
    bool destroyed;
    rs_context *rs;
    rs_target rt;
    int threads;
    bool reference;         /* dev_set_reference_path */
    bool timing;            /* dev_set_timing: phase times into stats (setup_ms, tile_ms) */
    bool patch_cull;        /* dev_set_patch_cull */
    unsigned present_flags; /* dev_set_present_flags */
    uint32_t rs_state[IS_RS_COUNT];
    is_viewport viewport;   /* as set (and read back by GetViewport) */
    rs_viewport rs_vp;      /* the rasterizer's: clipped to the target, MaxZ fixed (dev_viewport_update) */
    vp_remap remap;         /* the clip-space map that the clipping needs (vp_remap) */
    stream_source streams[IS_MAX_STREAMS];
    is_index_buffer *ib;
    is_vertex_buffer up_vb;    /* the caller's memory during a UP draw (not in the registry; never handed out) */
    is_index_buffer up_ib;
    is_vertex_declaration *decl;
    const is_vertex_shader *vs;
    is_vs_constants consts;    /* c0..c255 and the vertex samplers s0..s3 */
    is_sampler ps_samplers[DEV_PS_SAMPLERS]; /* pixel samplers 0..15, then D3DDMAPSAMPLER */
    is_texture *textures;      /* the live textures this device created (a list through next) */
    float npatch_segments;
    is_npatch_eval_fn npatch_eval;
    rs_stats stats;
    uint64_t shaded;
    uint64_t instances_culled; /* dev_instances_culled */
    is_state_block *recording; /* BeginStateBlock .. EndStateBlock: setters write here, not into the device */
    char err[512];
    char debug_log[2048];      /* dev_debug_log: the latest notes, one line each, oldest dropped first */
    /* scratch of draw calls, kept between draws and grown only, so that a frame like the last one allocates
     * nothing and touches no fresh pages (out_v, out_i: bounded by DRAW_CHUNK_VERTICES) */
    rs_vertex *out_v;
    size_t out_v_cap;
    uint32_t *out_i;
    size_t out_i_cap;
    scratch_buf idx;        /* uint32_t: the draw's index-stream entries (both draw calls) */
    scratch_buf list;       /* uint32_t: draw_fused's index list of instance 0 */
    scratch_buf fcache;     /* float4: fetch_cache */
    scratch_buf npatch_lv;  /* float[3]: the adaptive N-patch mode's edge levels per triangle of a draw */
    dev_scene scene;        /* the frame's recorded draws (draw_fused.c) */
    fused_scratch fz;       /* their producers' per-thread scratch */
    struct dev_inspector *inspector; /* the pipeline inspector while it records (core/inspect.c), else NULL */
    const is_pixel_shader *ps;  /* SetPixelShader (core/pixel.c), NULL: the fixed path */
    uint32_t fvf;               /* SetFVF's value (core/fvf.c), 0 after SetVertexDeclaration */
    is_vertex_declaration *fvf_decl; /* the declaration made for it, owned by the device */
    is_ps_constants ps_consts;  /* its c0..c223; s points at ps_samplers */
    /* core/raster_states.c: SetScissorRect, SetClipPlane */
    is_rect scissor;
    float clip_plane[IS_MAX_USER_CLIP_PLANES][4];
    /* core/surface.c: the render target and depth-stencil surface that dev->rt describes */
    is_surface backbuffer, auto_ds;   /* the implicit ones (dev_create's target) */
    is_surface *cur_rt, *cur_ds;      /* SetRenderTarget(0, ...), SetDepthStencilSurface (NULL: none) */
    bool ds_copied;                   /* dev->rt's depth is `scratch`'s, cur_ds's top-left copied in */
    bool no_depth;                    /* no usable depth-stencil surface: depth and stencil tests off */
    rs_target scratch;                /* depth and stencil planes of the target's size (ds_copied, no_depth) */
};

/* Whether dev may be used: not NULL, and not destroyed (a destroyed device's struct lives on while its resources
 * do; every public function treats it as a NULL device: IS_ERR_INVALIDCALL, NULL or 0). */
static inline bool dev_live(const is_device *dev) { return dev && !dev->destroyed; }

/* Wall-clock milliseconds now when dev times its draws (dev_set_timing), else 0. */
static inline double dev_clock(const is_device *dev) { return dev->timing ? omp_get_wtime() * 1e3 : 0.0; }

/* Record a message for dev_last_error and return code. */
is_result dev_fail(is_device *dev, is_result code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Append one line (printf-style, without its newline) to dev's debug log, dropping the oldest lines to make room. */
void dev_debug(is_device *dev, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* The rasterizer's copy of the device's render states and viewport. */
rs_state dev_rs_state(const is_device *dev);
/* dev->rs_vp and dev->remap from dev->viewport and the target's size (device.c). */
void dev_viewport_update(is_device *dev);

/* ---- core/raster_states.c: D3D9's scissor, colour write, alpha test, stencil, clipping and pre-transformed
 * vertices on the device's side ---- */
/* Whether render state `state` (one of that file's) takes value v: 1 yes, 0 a bad value, -1 not one of them
 * (device.c's state_check codes). */
int raster_state_check(is_rs state, uint32_t v);
/* Those states, the scissor rectangle (the whole target) and the clip planes (zero) to a new device's. */
void raster_states_default(is_device *dev);
/* Fill the fields of st (dev_rs_state) that those states drive. */
void raster_states_apply(const is_device *dev, rs_state *st);
/* Rectangle r narrowed to the scissor rectangle when the scissor test is on (Clear). */
is_rect raster_scissor_clip(const is_device *dev, is_rect r);
/* Whether the draw about to run is of pre-transformed vertices (no vertex shader, a declaration with POSITIONT):
 * then the device's pass-through shader is bound for it and the bound shader (NULL) returned in *saved for
 * raster_pretransformed_end; false (nothing changed) otherwise. */
bool raster_pretransformed_begin(is_device *dev, const is_vertex_shader **saved);
void raster_pretransformed_end(is_device *dev, const is_vertex_shader *saved);

/* Expand one element at src into a float4 register (D3D9 defaults fill missing components). */
float4 decl_fetch(uint8_t type, const unsigned char *src);
/* decl_fetch with the FLOAT1..FLOAT4 elements read here (the floats' bits, then the defaults (0, 0, 1)): the
 * per-instance fetch of the fused path, without a call and a switch per element. */
static inline float4 decl_fetch_inline(uint8_t type, const unsigned char *src)
{
    float f[4];
    switch (type) {
    case IS_DECLTYPE_FLOAT1: memcpy(f, src, 4); return (float4){f[0], 0, 0, 1};
    case IS_DECLTYPE_FLOAT2: memcpy(f, src, 8); return (float4){f[0], f[1], 0, 1};
    case IS_DECLTYPE_FLOAT3: memcpy(f, src, 12); return (float4){f[0], f[1], f[2], 1};
    case IS_DECLTYPE_FLOAT4: memcpy(f, src, 16); return (float4){f[0], f[1], f[2], f[3]};
    default: return decl_fetch(type, src);
    }
}

/* ---- a draw's vertex fetch (draw.c, draw_fused.c) ---- */

/* D3D9's fetch address, in bytes from an element's first byte in its stream: vertex (or instance) `index` of a
 * stream with frequency divider `divider` and stride `stride` is read at index / divider * stride (per-vertex data
 * has divider 1: index * stride; INSTANCEDATA | 0, divider 0: element 0 for all, as the runtime reads it).  A 32-bit
 * index takes a 32-bit division, as D3D9's DWORD indices do. */
static inline uint64_t fetch_offset(uint64_t index, uint32_t divider, uint64_t stride)
{
    if (divider == 1) return index * stride;   /* per-vertex data, and INSTANCEDATA | 1 */
    if (divider == 0) return 0;   /* INSTANCEDATA | 0: every instance reads the stream's first element */
    return (index <= UINT32_MAX ? (uint32_t)index / divider : index / divider) * stride;
}

/* D3D9 saturates the vertex colour outputs oD0 and oD1 per vertex, before they are interpolated: COLOR0 and
 * COLOR1 of out[0..n) clamped to [0, 1] (NaN becomes 0).  Every draw path calls it after the shader. */
static inline void saturate_colors(rs_vertex *out, size_t n)
{
    _Static_assert(RS_ATTR_COLOR1 == RS_ATTR_COLOR0 + 1, "COLOR0 and COLOR1 are adjacent");
    for (size_t v = 0; v < n; v++) saturate_color_outputs(&out[v].attr[RS_ATTR_COLOR0]);
}

/* post_shade's viewport part alone: oPos of out[0..n) mapped for the clipped viewport when m is on (the fused
 * path's grid_batch hands its colours over saturated already). */
static inline void post_remap(const vp_remap *m, rs_vertex *out, size_t n)
{
    if (!m->on) return;
    for (size_t v = 0; v < n; v++) {
        float4 *p = &out[v].pos;
        p->x = m->ax * p->x + m->bx * p->w;
        p->y = m->ay * p->y + m->by * p->w;
    }
}

/* What every draw path does to shaded vertices out[0..n) before the rasterizer sees them: the colours saturated
 * (saturate_colors) and, when the viewport reaches beyond the target, oPos mapped for the clipped viewport
 * (vp_remap; checked once per batch, so a viewport inside the target costs nothing per vertex). */
static inline void post_shade(const vp_remap *m, rs_vertex *out, size_t n)
{
    saturate_colors(out, n);
    post_remap(m, out, n);
}

/* How one declaration element is read during a draw.  Reads are robust (D3D10's robust buffer access, which a
 * software device needs: it must never read outside its buffers): an element whose bytes would lie past its
 * buffer's end, or on a stream without a buffer, reads as zero bytes.  max_off is the largest fetch offset whose
 * element lies inside the buffer; an unbound stream (or one too short for a single element) has base fetch_zeros,
 * stride 0 and max_off 0.  The bound is checked once per fetch of an element's address (fetch_at): once per vertex
 * per draw for per-vertex data (fetch_cache), once per instance for per-instance data. */
typedef struct fetch_elem {
    const unsigned char *base; /* buffer + stream offset + element offset */
    size_t stride;
    uint64_t max_off;
    uint32_t divider;
    bool per_instance;
    uint8_t type;
    unsigned reg_offset;
} fetch_elem;

/* What a read outside a buffer sees: zero bytes, as many as the largest element (FLOAT4) reads. */
static const unsigned char fetch_zeros[16] = {0};

/* The elements of a draw, checked against their buffers (draw.c's plan_fetch). */
typedef struct fetch_plan {
    unsigned n;
    fetch_elem el[IS_MAX_ELEMENTS];
    unsigned n_instances;
    unsigned n_vert;                 /* per-vertex elements: el[vert[0..n_vert)] (the fast path's fetch) */
    uint8_t vert[IS_MAX_ELEMENTS];
    uint32_t shared;                 /* registers no per-vertex element fills, the same for every vertex of an
                                        instance (the fused path's `shared` mask); 0 without per-instance
                                        elements */
} fetch_plan;

/* Where element e of vertex (per-vertex element) or instance (per-instance element) `index` is read. */
static inline const unsigned char *fetch_at(const fetch_elem *e, uint32_t index)
{
    const uint64_t off = fetch_offset(index, e->divider, e->stride);
    return off <= e->max_off ? e->base + off : fetch_zeros;   /* past the buffer's end: zeros (fetch_elem) */
}

/* The input registers before fetch: every register (0, 0, 0, 1). */
static inline void input_defaults(is_vs_input *in)
{
    float4 *r = (float4 *)in;
    for (size_t k = 0; k < sizeof *in / sizeof(float4); k++) r[k] = f4(0, 0, 0, 1);
}

/* fetch_vertices (draw.c) from a fetch_cache: vertices v0..v0+n-1 of the cache (relative to its first vertex)
 * into the per-vertex registers of in[0..n). */
static inline void fetch_cached(const fetch_plan *fp, const float4 *cache, uint32_t v0, uint32_t n, is_vs_input *in)
{
    const float4 *c = cache + (size_t)v0 * fp->n_vert;
    for (uint32_t v = 0; v < n; v++)
        for (unsigned q = 0; q < fp->n_vert; q++)
            *(float4 *)((unsigned char *)&in[v] + fp->el[fp->vert[q]].reg_offset) = *c++;
}

/* The outputs the rasterizer reads when drawing into dev's target: oD0 (the pixel colour) and the slots of the
 * target's AOV planes (raster.h).  A batch may skip the others, as a D3D9 driver links the vertex outputs to what
 * the pixel stage consumes (a pixel shader: every output). */
static inline uint32_t live_outputs(const is_device *dev)
{
    if (dev->ps) return ~0u;   /* a pixel shader may read every output */
    uint32_t live = IS_OUT_COLOR0;
    for (int k = 0; k < dev->rt.n_aov; k++) live |= 1u << dev->rt.aov[k].slot;
    return live;
}

/* The per-vertex elements of vertices first..first+count-1 fetched once into dev's scratch (dev->fcache, valid
 * until the next call): cache[v * n_vert + q] holds what fetch_vertices writes for vertex first + v, element q
 * (the same for every instance); NULL when out of memory. */
float4 *fetch_cache(is_device *dev, const fetch_plan *fp, uint32_t first, uint32_t count);
/* Scratch s with room for n elements of `size` bytes: grown only, without keeping its contents; NULL when out of
 * memory (s unchanged). */
void *scratch_get(scratch_buf *s, size_t n, size_t size);
/* Make sure the draw scratch (dev->out_v, dev->out_i) holds nv vertices and ni indices. */
is_result reserve_scratch(is_device *dev, size_t nv, size_t ni);
/* The device's result of a rasterizer call that returned r (RS_OK or RS_E*): IS_OK with its counters s added to
 * the device's, or the error with its message. */
is_result draw_result(is_device *dev, int r, const rs_stats *s);
/* (draw.c) Index-stream position of corner c of primitive p of a draw of `type`; fetch vertex `vertex` of
 * instance `instance` into in's registers; run dev's shader on in (outputs it does not write are zero, colours
 * saturated) -- the device's reference front end, which the fast paths match bit for bit. */
size_t prim_vertex(is_primtype type, size_t p, unsigned c);
void fetch_vertex(const fetch_plan *fp, uint32_t vertex, uint32_t instance, is_vs_input *in);
void shade(const is_device *dev, const is_vs_input *in, rs_vertex *out);
/* (inspect.c) The recording inspector's share of a draw (dev->inspector set): inspect_draw replays it for the
 * recorded pixel before the device draws and returns the record's mark; inspect_draw_done keeps the fragments
 * after the mark when the draw succeeded, else drops them and counts the draw skipped.  inspect_stop frees the
 * inspector (dev_destroy, dev_inspect_end). */
size_t inspect_draw(is_device *dev, const fetch_plan *fp, is_primtype type, size_t n_prims, uint32_t first,
                    uint32_t count, const uint32_t *stream_idx);
void inspect_draw_done(is_device *dev, size_t mark, bool drawn);
void inspect_stop(is_device *dev);
/* (pixel.c) rs_state.ps while a pixel shader is set: dev (ctx)'s shader with its constants and samplers. */
void dev_ps_run(const void *ctx, const rs_ps_quad *q, rs_ps_out *out);

/* ---- draw_fused.c: the fused path of instanced triangle draws ---- */

/* Whether the fused path takes a draw of rasterizer primitive `prim` with `count` vertices per instance. */
bool draw_fused_takes(const is_device *dev, int prim, uint32_t count);
/* The fused draw of n_prims triangles per instance of fp's instances, vertices first..first+count-1: list holds
 * instance 0's index list (3 per triangle, rebased to first).  The draw is recorded (dev_scene): what it reads is
 * copied, but for the vertex buffers, which are marked. */
is_result draw_fused(is_device *dev, const fetch_plan *fp, size_t n_prims, uint32_t first, uint32_t count,
                     const uint32_t *list);
/* Run the recorded draws (rs_flush), take their counters (instances culled) and any error of theirs (kept for
 * dev_flush, the message in dev_last_error), and start the next generation: the records are free again. */
void dev_scene_flush(is_device *dev);
/* Whether a draw recorded since the last dev_scene_flush reads vertex buffer vb (then a Lock or a release of vb
 * flushes first). */
bool dev_scene_reads(const is_device *dev, const is_vertex_buffer *vb);
/* Free the records and the producers' scratch (dev_destroy). */
void dev_scene_free(is_device *dev);

/* ---- the pre-tessellation cull of instanced draws (draw_cull.c) ---- */
typedef struct cull_view {
    bool on;                  /* the shader has a hull stage and the draw allows a cull */
    bool backface;            /* the grid is regular and the cull mode CW / CCW: the winding test applies */
    int winding;              /* +1 / -1: the grid triangles' winding in the domain */
    unsigned pairs;           /* bit p: some grid triangle has its edges along pair p (draw_cull.c) */
    double h;                 /* the grid's spacing (in b) */
    double grid_slack;        /* largest deviation of a grid triangle from its ideal one (ell-1, in b) */
    double sign;              /* +1: a triangle is culled when det3 > 0 of its (x, y, w) rows, -1 when < 0 */
    double sx, sy;            /* screen units (1/256 px) per unit of x/w, y/w */
    double gx, gy;            /* the guard band, as the rasterizer clips */
    double mux, muy;          /* a pixel beyond the viewport, in x/w, y/w */
} cull_view;
/* Prepare the cull of an instanced triangle draw whose instance triangles are list[0..3 n_prims) (into the fetch
 * cache of its vertices): cv->on is false when no instance can be culled. */
void cull_prepare(const is_device *dev, const fetch_plan *fp, const float4 *cache, const uint32_t *list,
                  size_t n_prims, cull_view *cv);
/* True when hull h proves that the rasterizer draws nothing of the instance. */
bool cull_instance(const cull_view *cv, const is_patch_hull *h);

#endif
