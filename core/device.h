/* core/device.h -- a device modelled on IDirect3DDevice9: resources, vertex declarations, stream sources and
 * frequencies (instancing), vertex shaders as C functions, render states, draws, N-patch mode.
 *
 * Conventions:
 *  - Spaces and matrices: core/math.h.  Clip volume -w <= x, y <= w, 0 <= z <= w; the viewport maps z/w to
 *    [MinZ, MaxZ].
 *  - Pixel centres at integer coordinates, top-left fill rule, clockwise front faces, default cull CCW:
 *    see raster/raster.h, which is the interface between this device and the rasterizer.
 *  - Names: a D3D9 method becomes dev_<snake_case>(dev, ...) (SetStreamSourceFreq -> dev_set_stream_source_freq);
 *    a D3D9 constant D3DXXX_YYY becomes IS_XXX_YYY (D3DCULL_CCW -> IS_CULL_CCW, D3DRS_CULLMODE -> IS_RS_CULLMODE).
 *    Values of render states equal D3D9's.
 *  - Errors: every dev_* call returns IS_OK (0) or a negative IS_ERR_* code; an invalid call changes nothing and
 *    leaves a message in dev_last_error(dev).  A NULL (or destroyed) device gets IS_ERR_INVALIDCALL, NULL or 0
 *    from every function, NULL pointers and out-of-range values an error; nothing prints, nothing exits
 *    (tests/test_api_device.c walks every function).
 *  - Ownership: buffers and declarations belong to the device that created them, which keeps a registry of the
 *    live ones; a setter given a handle that is not in it (another device's, released, or no handle at all) refuses
 *    it without reading it.  A released handle is gone: passing it to its own functions (lock, release) again is
 *    a use of freed memory, as in D3D9.
 *  - No globals: all state lives in the device (the context passed first).  Threads: dev_set_threads.
 */
#ifndef INSTESS_CORE_DEVICE_H
#define INSTESS_CORE_DEVICE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "api.h"
#include "math.h"
#include "../raster/raster.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum is_result {
    IS_OK = 0,
    IS_ERR_INVALIDCALL = -1,        /* D3DERR_INVALIDCALL                          */
    IS_ERR_OUTOFMEMORY = -2,        /* E_OUTOFMEMORY / D3DERR_OUTOFVIDEOMEMORY     */
    IS_ERR_NOTAVAILABLE = -3        /* D3DERR_NOTAVAILABLE (unsupported format...) */
} is_result;

/* --- vertex declarations (D3DVERTEXELEMENT9) --- */
typedef enum is_decltype {
    IS_DECLTYPE_FLOAT1 = 0, IS_DECLTYPE_FLOAT2 = 1, IS_DECLTYPE_FLOAT3 = 2, IS_DECLTYPE_FLOAT4 = 3,
    IS_DECLTYPE_D3DCOLOR = 4, IS_DECLTYPE_UBYTE4 = 5, IS_DECLTYPE_SHORT2 = 6, IS_DECLTYPE_SHORT4 = 7,
    IS_DECLTYPE_UBYTE4N = 8, IS_DECLTYPE_SHORT2N = 9, IS_DECLTYPE_SHORT4N = 10,
    IS_DECLTYPE_USHORT2N = 11, IS_DECLTYPE_USHORT4N = 12,
    /* UDEC3: three unsigned 10-bit fields (x in bits 0..9) -> (x, y, z, 1); DEC3N: three signed 10-bit fields / 511
     * -> (x, y, z, 1), -512 read as -1 (the SNORM rule of SHORTnN); FLOAT16_2/4: IEEE half floats, exactly */
    IS_DECLTYPE_UDEC3 = 13, IS_DECLTYPE_DEC3N = 14, IS_DECLTYPE_FLOAT16_2 = 15, IS_DECLTYPE_FLOAT16_4 = 16,
    IS_DECLTYPE_UNUSED = 17
} is_decltype;

typedef enum is_declusage {
    IS_DECLUSAGE_POSITION = 0, IS_DECLUSAGE_BLENDWEIGHT = 1, IS_DECLUSAGE_BLENDINDICES = 2,
    IS_DECLUSAGE_NORMAL = 3, IS_DECLUSAGE_PSIZE = 4, IS_DECLUSAGE_TEXCOORD = 5, IS_DECLUSAGE_TANGENT = 6,
    IS_DECLUSAGE_BINORMAL = 7, IS_DECLUSAGE_TESSFACTOR = 8, IS_DECLUSAGE_POSITIONT = 9,
    IS_DECLUSAGE_COLOR = 10, IS_DECLUSAGE_FOG = 11, IS_DECLUSAGE_DEPTH = 12, IS_DECLUSAGE_SAMPLE = 13,
    IS_DECLUSAGE_COUNT = 14
} is_declusage;

typedef struct is_vertex_element {
    uint16_t stream;   /* 0..IS_MAX_STREAMS-1, or 0xFF in the end marker */
    uint16_t offset;   /* bytes from the start of the vertex */
    uint8_t type;      /* is_decltype */
    uint8_t method;    /* D3DDECLMETHOD_DEFAULT (0) only */
    uint8_t usage;     /* is_declusage */
    uint8_t usage_index;
} is_vertex_element;
#define IS_DECL_END { 0xFF, 0, IS_DECLTYPE_UNUSED, 0, 0, 0 } /* D3DDECL_END() */

#define IS_MAX_STREAMS 16
#define IS_MAX_ELEMENTS 64
#define IS_USAGE_INDICES 16        /* usage indices 0..15 per usage */
#define IS_MAX_VS_CONSTANTS 256    /* float4 registers c0..c255 (vs_3_0) */

/* --- stream frequencies (D3DSTREAMSOURCE_*) --- */
#define IS_STREAMSOURCE_INDEXEDDATA (1u << 30)
#define IS_STREAMSOURCE_INSTANCEDATA (2u << 30)

/* --- primitives, formats, render states --- */
typedef enum is_primtype {
    IS_PT_POINTLIST = 1, IS_PT_LINELIST = 2, IS_PT_LINESTRIP = 3,
    IS_PT_TRIANGLELIST = 4, IS_PT_TRIANGLESTRIP = 5, IS_PT_TRIANGLEFAN = 6
} is_primtype;

/* D3DFORMAT: index formats, and the texture formats of core/texture.h. */
typedef enum is_format {
    IS_FMT_A8R8G8B8 = 21, IS_FMT_X8R8G8B8 = 22, IS_FMT_INDEX16 = 101, IS_FMT_INDEX32 = 102, IS_FMT_R32F = 114,
    IS_FMT_A32B32G32R32F = 116
} is_format;

typedef enum is_rs {
    IS_RS_ZENABLE = 7, IS_RS_FILLMODE = 8, IS_RS_SHADEMODE = 9, IS_RS_ZWRITEENABLE = 14,
    IS_RS_SRCBLEND = 19, IS_RS_DESTBLEND = 20, IS_RS_CULLMODE = 22, IS_RS_ZFUNC = 23,
    IS_RS_ALPHABLENDENABLE = 27, IS_RS_MULTISAMPLEANTIALIAS = 161, IS_RS_POSITIONDEGREE = 172,
    IS_RS_NORMALDEGREE = 173, IS_RS_SLOPESCALEDEPTHBIAS = 175, IS_RS_DEPTHBIAS = 195,
    IS_RS_PATCHEDGESTYLE = 163,
    /* D3D9's adaptive tessellation of N-patches (see "adaptive N-patch mode" below): floats passed as their
     * bits, but ENABLEADAPTIVETESSELLATION, a BOOL */
    IS_RS_MINTESSELLATIONLEVEL = 178, IS_RS_MAXTESSELLATIONLEVEL = 179, IS_RS_ADAPTIVETESS_X = 180,
    IS_RS_ADAPTIVETESS_Y = 181, IS_RS_ADAPTIVETESS_Z = 182, IS_RS_ADAPTIVETESS_W = 183,
    IS_RS_ENABLEADAPTIVETESSELLATION = 184,
    /* D3D9's scissor, colour write mask, alpha test, stencil and clipping states (core/raster_states.c; see
     * "per-pixel and clipping states" below) */
    IS_RS_ALPHATESTENABLE = 15, IS_RS_ALPHAREF = 24, IS_RS_ALPHAFUNC = 25, IS_RS_STENCILENABLE = 52,
    IS_RS_STENCILFAIL = 53, IS_RS_STENCILZFAIL = 54, IS_RS_STENCILPASS = 55, IS_RS_STENCILFUNC = 56,
    IS_RS_STENCILREF = 57, IS_RS_STENCILMASK = 58, IS_RS_STENCILWRITEMASK = 59, IS_RS_CLIPPING = 136,
    IS_RS_CLIPPLANEENABLE = 152, IS_RS_COLORWRITEENABLE = 168, IS_RS_SCISSORTESTENABLE = 174,
    IS_RS_TWOSIDEDSTENCILMODE = 185, IS_RS_CCW_STENCILFAIL = 186, IS_RS_CCW_STENCILZFAIL = 187,
    IS_RS_CCW_STENCILPASS = 188, IS_RS_CCW_STENCILFUNC = 189
} is_rs;

enum { IS_CULL_NONE = 1, IS_CULL_CW = 2, IS_CULL_CCW = 3 };
enum { IS_FILL_POINT = 1, IS_FILL_WIREFRAME = 2, IS_FILL_SOLID = 3 };
/* SHADEMODE PHONG and ZENABLE USEW are accepted as the runtime accepts them, with fallbacks: PHONG shades as
 * GOURAUD (no D3D9 driver implemented it), USEW uses the z-buffer as TRUE does (no w-buffer here). */
enum { IS_SHADE_FLAT = 1, IS_SHADE_GOURAUD = 2, IS_SHADE_PHONG = 3 };
enum { IS_ZB_FALSE = 0, IS_ZB_TRUE = 1, IS_ZB_USEW = 2 };
enum {
    IS_CMP_NEVER = 1, IS_CMP_LESS, IS_CMP_EQUAL, IS_CMP_LESSEQUAL,
    IS_CMP_GREATER, IS_CMP_NOTEQUAL, IS_CMP_GREATEREQUAL, IS_CMP_ALWAYS
};
enum {
    IS_BLEND_ZERO = 1, IS_BLEND_ONE = 2, IS_BLEND_SRCCOLOR = 3, IS_BLEND_INVSRCCOLOR = 4,
    IS_BLEND_SRCALPHA = 5, IS_BLEND_INVSRCALPHA = 6, IS_BLEND_DESTALPHA = 7, IS_BLEND_INVDESTALPHA = 8,
    IS_BLEND_DESTCOLOR = 9, IS_BLEND_INVDESTCOLOR = 10,
    /* values the runtime takes beyond those ten: SRCALPHASAT, the factor (f, f, f, 1) with f = min(As, 1 - Ad)
     * (as SRCBLEND or DESTBLEND); BOTHSRCALPHA as SRCBLEND means SRCBLEND SRCALPHA and
     * DESTBLEND INVSRCALPHA, BOTHINVSRCALPHA the reverse (DESTBLEND overridden, as D3D9 documents and DXVK does),
     * and as DESTBLEND they read as SRCALPHA and INVSRCALPHA.  GetRenderState reads back what was set. */
    IS_BLEND_SRCALPHASAT = 11, IS_BLEND_BOTHSRCALPHA = 12, IS_BLEND_BOTHINVSRCALPHA = 13
};
/* NORMALDEGREE takes LINEAR, QUADRATIC and (as the runtime does) CUBIC, which the N-patch evaluator gets as
 * QUADRATIC (the highest degree of normals it has); POSITIONDEGREE takes LINEAR and CUBIC. */
enum { IS_DEGREE_LINEAR = 1, IS_DEGREE_QUADRATIC = 2, IS_DEGREE_CUBIC = 3 };
enum { IS_PATCHEDGE_DISCRETE = 0, IS_PATCHEDGE_CONTINUOUS = 1 };
enum { IS_CLEAR_TARGET = 1, IS_CLEAR_ZBUFFER = 2, IS_CLEAR_STENCIL = 4 };
/* D3DSTENCILOP and D3DCOLORWRITEENABLE_* */
enum {
    IS_STENCILOP_KEEP = 1, IS_STENCILOP_ZERO = 2, IS_STENCILOP_REPLACE = 3, IS_STENCILOP_INCRSAT = 4,
    IS_STENCILOP_DECRSAT = 5, IS_STENCILOP_INVERT = 6, IS_STENCILOP_INCR = 7, IS_STENCILOP_DECR = 8
};
enum { IS_COLORWRITEENABLE_RED = 1, IS_COLORWRITEENABLE_GREEN = 2, IS_COLORWRITEENABLE_BLUE = 4,
       IS_COLORWRITEENABLE_ALPHA = 8 };
#define IS_MAX_USER_CLIP_PLANES 6   /* D3DCAPS9.MaxUserClipPlanes of this device */
#define IS_RS_COUNT 256

/* D3DCOLOR_ARGB -> is stored as packed RGBA8 in the target; these helpers build a D3DCOLOR (ARGB). */
#define IS_COLOR_ARGB(a, r, g, b) \
    ((uint32_t)((((a) & 0xffu) << 24) | (((r) & 0xffu) << 16) | (((g) & 0xffu) << 8) | ((b) & 0xffu)))

typedef struct is_viewport { uint32_t x, y, width, height; float min_z, max_z; } is_viewport;

/* --- vertex shaders: plain C functions --- */

/* The input registers of one vertex, filled by the device from the vertex declaration: an element with
 * usage U and index i lands in the register of (U, i), expanded to float4 with D3D9's defaults (0, 0, 0, 1).
 * A shader reads in->texcoord[3], not byte offsets.  Registers not in the declaration read (0, 0, 0, 1). */
typedef struct is_vs_input {
    float4 position[2];
    float4 blendweight[1];
    float4 blendindices[1];
    float4 normal[2];
    float4 psize[1];
    float4 texcoord[IS_USAGE_INDICES];
    float4 tangent[1];
    float4 binormal[1];
    float4 color[2];
    float4 tessfactor[1]; /* D3DDECLUSAGE_TESSFACTOR index 0 (FLOAT1 only): the adaptive N-patch mode's factor */
} is_vs_input;

/* The outputs: oPos, oD0/oD1, oT0..oT7 (the rasterizer's vertex). */
typedef rs_vertex is_vs_output;
#define IS_OUT_COLOR0 (1u << RS_ATTR_COLOR0)
#define IS_OUT_COLOR1 (1u << RS_ATTR_COLOR1)
#define IS_OUT_TEXCOORD(k) (1u << (RS_ATTR_TEXCOORD0 + (k)))

/* Samplers (core/texture.h has textures, the states' values and the sampling functions): a bound sampler is
 * its texture and its states, indexed by IS_SAMP_* (D3DSAMPLERSTATETYPE; MIPMAPLODBIAS holds a float's bits). */
typedef struct is_texture is_texture;
typedef enum is_samp {
    IS_SAMP_ADDRESSU = 1, IS_SAMP_ADDRESSV = 2, IS_SAMP_ADDRESSW = 3, IS_SAMP_BORDERCOLOR = 4,
    IS_SAMP_MAGFILTER = 5, IS_SAMP_MINFILTER = 6, IS_SAMP_MIPFILTER = 7, IS_SAMP_MIPMAPLODBIAS = 8,
    IS_SAMP_MAXMIPLEVEL = 9, IS_SAMP_MAXANISOTROPY = 10, IS_SAMP_SRGBTEXTURE = 11, IS_SAMP_ELEMENTINDEX = 12,
    IS_SAMP_DMAPOFFSET = 13
} is_samp;
#define IS_SAMP_COUNT 14
#define IS_MAX_VS_SAMPLERS 4 /* the vertex shader's s0..s3: D3DVERTEXTEXTURESAMPLER0..3 */
typedef struct is_sampler {
    const is_texture *tex;          /* NULL: sampling returns (0, 0, 0, 1) */
    uint32_t state[IS_SAMP_COUNT];
} is_sampler;

/* What a vertex shader reads besides its inputs: the constants c0..c255 (SetVertexShaderConstantF) and the
 * vertex texture samplers s0..s3 (SetTexture / SetSamplerState on IS_VERTEXTEXTURESAMPLER0..3), for
 * tex2Dlod(&c->s[k], t) (tex_sample_lod in core/texture.h): vertex texture fetch.  A shader that samples
 * nothing ignores s; a caller that fills is_vs_constants itself to call a shader outside a device leaves s zero
 * (empty samplers) or fills it with tex_sampler_default. */
typedef struct is_vs_constants {
    float4 c[IS_MAX_VS_CONSTANTS];
    is_sampler s[IS_MAX_VS_SAMPLERS];
} is_vs_constants;

/* A shader's function: reads constants and one vertex's inputs, writes its outputs.  The shader must write
 * oPos and every output named in its `outputs` mask; the others read zero in the rasterizer (the device zeroes
 * them, or never reads them). */
typedef void (*is_vs_fn)(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out);

/* The registers of is_vs_input as an array: register r is the r-th float4 (position[0] is 0, texcoord[k] is
 * IS_VS_REG_TEXCOORD + k); a mask of registers has bit r for register r. */
#define IS_VS_INPUT_REGS ((int)(sizeof(is_vs_input) / sizeof(float4)))
#define IS_VS_REG_TEXCOORD ((int)(offsetof(is_vs_input, texcoord) / sizeof(float4)))
#define IS_VS_REGS_ALL ((1u << IS_VS_INPUT_REGS) - 1u) /* every register */
#define IS_VS_REGS_INSTANCE (IS_VS_REGS_ALL & ~1u)      /* every register but POSITION0 (a patch's instance data) */

/* Vertex v of a batch whose `shared` registers are stored in in[0] only: in + v itself when nothing is shared
 * or v is 0, else *tmp filled with in[v]'s registers and in[0]'s shared ones (what `main` is given). */
static inline const is_vs_input *is_vs_input_at(const is_vs_input *in, size_t v, uint32_t shared, is_vs_input *tmp)
{
    if (!shared || v == 0) return in + v;
    *tmp = in[v];
    for (int r = 0; r < IS_VS_INPUT_REGS; r++)
        if (shared & (1u << r)) ((float4 *)tmp)[r] = ((const float4 *)in)[r];
    return tmp;
}

/* Optional batched entry: shade in[0..n) into out[0..n) (not necessarily zeroed first), producing exactly the
 * bytes of n calls of `main` in oPos and in the outputs of `live` (an IS_OUT_* mask: what the caller will read);
 * lets a shader share the work of consecutive vertices of one instance, and skip outputs nobody reads (as a D3D9
 * driver drops vertex outputs the pixel stage does not consume).  Outputs outside `live` may be left unwritten.
 * `shared` (a register mask, 0: none): registers that hold the same value for every vertex of the batch (an
 * instance's per-instance registers, the ones no element fills) and are stored in in[0] only -- in in[1..n) they
 * are unspecified; vertex v's inputs are those of is_vs_input_at.  The device's fused path uses it so that one
 * instance's data is neither copied to every vertex nor compared vertex by vertex. */
typedef void (*is_vs_batch_fn)(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live,
                               uint32_t shared, is_vs_output *out);

/* A batch shader's per-grid workspace (is_vertex_shader.grid_batch), the caller's memory: what the shader derives
 * from the per-vertex registers alone -- the grid's points: their weights, which lie on an edge -- kept between
 * batches over the same points (the device's fused path shades every instance of a draw over one grid).  mem
 * holds room bytes (any alignment; room from grid_room); ready false tells the shader to derive it again from the
 * batch's inputs (it sets ready then).  The caller clears ready whenever the per-vertex registers of in[0..n) may
 * have changed -- the device does when a draw's per-vertex registers differ in a bit from those its slot holds
 * (so it keeps the workspace across draws of the same grid points). */
typedef struct is_vs_grid {
    void *mem;
    size_t room;
    bool ready;
} is_vs_grid;
/* is_vs_batch_fn with a grid workspace (NULL: none): the same bytes as `batch`, cheaper per batch while the
 * workspace stays ready -- but for the colour outputs, which it hands over saturated as the device does after
 * any shader (x >= 0 ? x : 0, then x <= 1 ? x : 1 per component): the device does not saturate them again. */
typedef void (*is_vs_grid_batch_fn)(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live,
                                    uint32_t shared, is_vs_grid *grid, is_vs_output *out);
/* The workspace bytes grid_batch wants for batches of n vertices (0: it uses none). */
typedef size_t (*is_vs_grid_room_fn)(size_t n);

/* The hull stage (an extension of the D3D9 shader object, in the spirit of D3D11's hull shader and of
 * Hasselgren, Munkberg and Akenine-Moller's pre-tessellation culling): a conservative bound of what `main` writes
 * to oPos for one instance, over the barycentric domain b = POSITION0.xyz (b >= 0, b0 + b1 + b2 = 1, widened by
 * IS_HULL_DOMAIN_SLACK: b_k >= -slack, |b0 + b1 + b2 - 1| <= slack, as float grids give).  oPos(b) lies within
 * `err` (per coordinate, absolute) of the convex hull of pos[0..n_pos) (clip space x, y, z, w).  When degree
 * d > 0, oPos is moreover within err of the polynomial Q(b) = sum of B_ijk(b) pos[k-major index of (i, j, k)]
 * (Bernstein polynomials of degree d, i + j + k = d the exponents of b0, b1, b2; index = sum over q < k of
 * (d + 1 - q), plus j), so n_pos = (d + 1)(d + 2) / 2.  The device uses it to skip whole instances that the
 * rasterizer would draw nothing of (dev_set_patch_cull). */
#define IS_HULL_MAX_POS 10 /* degree 3 at most */
#define IS_HULL_DOMAIN_SLACK 0x1p-23
typedef struct is_patch_hull {
    int n_pos, degree;
    double pos[IS_HULL_MAX_POS][4];
    double err;
} is_patch_hull;
/* Fill *h for the instance whose per-instance registers are in `in` (POSITION0 is not read); false when the
 * instance has no bound (non-finite data, say): it is then drawn. */
typedef bool (*is_vs_hull_fn)(const is_vs_constants *c, const is_vs_input *in, is_patch_hull *h);

/* A named value a shader publishes for the pipeline inspector (core/inspect.h): name is a static string. */
typedef struct is_vs_value { const char *name; float4 v; } is_vs_value;
/* The explain stage (optional): for the inputs in, the shader's named intermediate values -- the same numbers
 * `main` computes for them -- into vals (at most max); returns how many it wrote. */
typedef unsigned (*is_vs_explain_fn)(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals,
                                     unsigned max);

typedef struct is_vertex_shader {
    const char *name;
    is_vs_fn main;
    uint32_t outputs;   /* IS_OUT_* mask of written outputs (what the rasterizer interpolates) */
    is_vs_batch_fn batch; /* NULL: the device calls main per vertex */
    is_vs_hull_fn hull;   /* NULL: no bound, every instance is shaded */
    is_vs_explain_fn explain; /* NULL: the shader publishes nothing to the inspector */
    is_vs_grid_batch_fn grid_batch; /* NULL: the device calls batch (with batch only) */
    is_vs_grid_room_fn grid_room;   /* with grid_batch */
} is_vertex_shader;

/* Read four constant registers starting at c[r] as a float4x4 (rows = registers, as with row_major). */
static inline float4x4 vs_const_matrix(const is_vs_constants *c, int r)
{
    float4x4 m;
    for (int i = 0; i < 4; i++) {
        m.m[i][0] = c->c[r + i].x; m.m[i][1] = c->c[r + i].y;
        m.m[i][2] = c->c[r + i].z; m.m[i][3] = c->c[r + i].w;
    }
    return m;
}

/* --- resources --- */
typedef struct is_device is_device;
typedef struct is_vertex_buffer is_vertex_buffer;
typedef struct is_index_buffer is_index_buffer;
typedef struct is_vertex_declaration is_vertex_declaration;

/* Create a device with a w x h back buffer with `samples` (1 or 4) samples and a float depth buffer.
 * Returns NULL (and a message in err if given) for bad sizes or when out of memory. */
INSTESS_API is_device *dev_create(int width, int height, int samples, char *err, size_t errlen);
/* Release the device and the textures it still owns (core/texture.h).  Buffers and declarations belong to their
 * device and hold a reference to it, as in D3D9: dev_destroy frees the device's memory and the memory of its
 * buffers still alive at once (their lock then returns NULL, their size 0), and releasing them after dev_destroy
 * is safe (the small handles go with their release, the device's last few bytes with its last resource).  A
 * resource of another device, or one released, is refused by the setters (IS_ERR_INVALIDCALL). */
INSTESS_API void dev_destroy(is_device *dev);
/* The device's state back to a new device's (render states, stream sources and frequencies, indices,
 * declaration, shader, constants, samplers (states and bound textures), viewport, N-patch mode and evaluator;
 * the back buffer and the automatic depth-stencil surface are the target again, as after D3D9's Reset); their
 * contents, the surfaces and textures it created, the thread count, timing, reference path and scratch memory
 * are kept.  For programs that draw frame after frame on one
 * device (instess view): the next frame is drawn as on a new device, without allocating its target again. */
INSTESS_API void dev_reset(is_device *dev);
/* The message of the last failed call ("" if none). */
INSTESS_API const char *dev_last_error(const is_device *dev);
/* The device's debug log (D3D9's debug runtime output, for this device): notes about calls that succeeded but did
 * something a program may not expect, one line each, the latest ~2 KB (older lines dropped); "" for a NULL
 * device.  A draw that reads past a vertex buffer's end or from a stream without a buffer (those reads return
 * zeros: D3D10's robust buffer access) adds one line per draw. */
INSTESS_API const char *dev_debug_log(const is_device *dev);
/* Threads used by draws (0: all cores).  Output bytes do not depend on it. */
INSTESS_API void dev_set_threads(is_device *dev, int threads);
/* Phase times on or off (default off): dev_stats' setup_ms and tile_ms then sum the frame's set-up regions
 * (vertex shading included) and tile passes; off, both stay 0 so that the statistics of two renders compare
 * equal. */
INSTESS_API void dev_set_timing(is_device *dev, bool on);
/* Pre-tessellation culling on or off (default off; the reference path never culls): an instanced triangle draw
 * whose shader has a hull stage skips, before shading any of its vertices, every instance that the hull proves
 * invisible -- outside one plane of the view, or (on a regular barycentric grid in stream 0's POSITION0, cull mode
 * CW or CCW, solid fill) with every grid triangle culled by its snapped winding.  The image bytes are those of the
 * draw without it; the statistics count fewer triangles and vertices (dev_instances_culled counts the skips). */
INSTESS_API void dev_set_patch_cull(is_device *dev, bool on);
/* D3DPRESENT_PARAMETERS.Flags, of which instess acts on one: IS_PRESENTFLAG_DISCARD_DEPTHSTENCIL (D3D9's
 * D3DPRESENTFLAG_DISCARD_DEPTHSTENCIL, 0x2; default off, dev_reset keeps it): the program does not need the depth
 * buffer's contents after a Present, so dev_present may drop the depth the frame drew.  Where the frame's Clear of
 * the depth is still deferred (the tiles a draw touched, after a whole-target Clear) the depth then reads as that
 * cleared value -- the Windows debug runtime clears it to a constant, drivers leave it undefined --, elsewhere as
 * drawn; stencil is kept.  Saves writing each drawn tile's depth to memory.  IS_ERR_INVALIDCALL for other bits
 * (dev_last_error says which) or a NULL or destroyed device. */
#define IS_PRESENTFLAG_DISCARD_DEPTHSTENCIL 0x2u
INSTESS_API is_result dev_set_present_flags(is_device *dev, unsigned flags);

/* Buffers: CreateVertexBuffer / CreateIndexBuffer, Lock (returns the memory), Unlock. */
INSTESS_API is_result dev_create_vertex_buffer(is_device *dev, size_t bytes, is_vertex_buffer **out);
INSTESS_API is_result dev_create_index_buffer(is_device *dev, size_t bytes, is_format fmt, is_index_buffer **out);
INSTESS_API void *vb_lock(is_vertex_buffer *vb);
INSTESS_API void vb_unlock(is_vertex_buffer *vb);
INSTESS_API size_t vb_size(const is_vertex_buffer *vb);
INSTESS_API void vb_release(is_vertex_buffer *vb);
INSTESS_API void *ib_lock(is_index_buffer *ib);
INSTESS_API void ib_unlock(is_index_buffer *ib);
INSTESS_API size_t ib_size(const is_index_buffer *ib);
INSTESS_API void ib_release(is_index_buffer *ib);

/* CreateVertexDeclaration: elements ended by IS_DECL_END; validates types, usages and overlaps. */
INSTESS_API is_result dev_create_vertex_declaration(is_device *dev, const is_vertex_element *elements,
                                        is_vertex_declaration **out);
INSTESS_API void decl_release(is_vertex_declaration *decl);

/* State setters, as IDirect3DDevice9. */
INSTESS_API is_result dev_set_vertex_declaration(is_device *dev, is_vertex_declaration *decl);
INSTESS_API is_result dev_set_stream_source(is_device *dev, unsigned stream, is_vertex_buffer *vb, unsigned offset,
                                unsigned stride);
INSTESS_API is_result dev_set_stream_source_freq(is_device *dev, unsigned stream, uint32_t setting);
INSTESS_API is_result dev_get_stream_source_freq(const is_device *dev, unsigned stream, uint32_t *setting);
INSTESS_API is_result dev_set_indices(is_device *dev, is_index_buffer *ib);
INSTESS_API is_result dev_set_vertex_shader(is_device *dev, const is_vertex_shader *vs);
INSTESS_API is_result dev_set_vertex_shader_constant_f(is_device *dev, unsigned start, const float *data, unsigned count4);
/* The getters of the setters above (GetVertexDeclaration, GetStreamSource, GetIndices, GetVertexShader,
 * GetVertexShaderConstantF): what was set, or NULL / zeros where nothing is; IS_ERR_INVALIDCALL for a NULL output,
 * a stream beyond the last or registers beyond c255, changing nothing.  (D3D9's getters add a reference to the
 * objects they return; these hand out the device's own pointers, which stay the caller's to release.) */
INSTESS_API is_result dev_get_vertex_declaration(const is_device *dev, is_vertex_declaration **decl);
INSTESS_API is_result dev_get_stream_source(const is_device *dev, unsigned stream, is_vertex_buffer **vb,
                                            unsigned *offset, unsigned *stride);
INSTESS_API is_result dev_get_indices(const is_device *dev, is_index_buffer **ib);
INSTESS_API is_result dev_get_vertex_shader(const is_device *dev, const is_vertex_shader **vs);
INSTESS_API is_result dev_get_vertex_shader_constant_f(const is_device *dev, unsigned start, float *data,
                                                       unsigned count4);
INSTESS_API is_result dev_set_render_state(is_device *dev, is_rs state, uint32_t value);
INSTESS_API is_result dev_get_render_state(const is_device *dev, is_rs state, uint32_t *value);
/* The render states' defaults, as D3D9 sets them on a new device (with an automatic depth buffer) and as
 * dev_create and dev_reset set them (tests/test_device.c reads this table and checks a new device against it):
 *
 *   | state                            | default                  |
 *   |----------------------------------|--------------------------|
 *   | IS_RS_ZENABLE                    | IS_ZB_TRUE               |
 *   | IS_RS_FILLMODE                   | IS_FILL_SOLID            |
 *   | IS_RS_SHADEMODE                  | IS_SHADE_GOURAUD         |
 *   | IS_RS_ZWRITEENABLE               | 1                        |
 *   | IS_RS_SRCBLEND                   | IS_BLEND_ONE             |
 *   | IS_RS_DESTBLEND                  | IS_BLEND_ZERO            |
 *   | IS_RS_CULLMODE                   | IS_CULL_CCW              |
 *   | IS_RS_ZFUNC                      | IS_CMP_LESSEQUAL         |
 *   | IS_RS_ALPHABLENDENABLE           | 0                        |
 *   | IS_RS_MULTISAMPLEANTIALIAS       | 1                        |
 *   | IS_RS_POSITIONDEGREE             | IS_DEGREE_CUBIC          |
 *   | IS_RS_NORMALDEGREE               | IS_DEGREE_LINEAR         |
 *   | IS_RS_PATCHEDGESTYLE             | IS_PATCHEDGE_DISCRETE    |
 *   | IS_RS_DEPTHBIAS                  | 0.0f (as its bits)       |
 *   | IS_RS_SLOPESCALEDEPTHBIAS        | 0.0f (as its bits)       |
 *   | IS_RS_ENABLEADAPTIVETESSELLATION | 0                        |
 *   | IS_RS_MINTESSELLATIONLEVEL       | 1.0f (as its bits)       |
 *   | IS_RS_MAXTESSELLATIONLEVEL       | 1.0f (as its bits)       |
 *   | IS_RS_ADAPTIVETESS_X             | 0.0f (as its bits)       |
 *   | IS_RS_ADAPTIVETESS_Y             | 0.0f (as its bits)       |
 *   | IS_RS_ADAPTIVETESS_Z             | 1.0f (as its bits)       |
 *   | IS_RS_ADAPTIVETESS_W             | 0.0f (as its bits)       |
 *   | IS_RS_ALPHATESTENABLE            | 0                        |
 *   | IS_RS_ALPHAREF                   | 0                        |
 *   | IS_RS_ALPHAFUNC                  | IS_CMP_ALWAYS            |
 *   | IS_RS_STENCILENABLE              | 0                        |
 *   | IS_RS_STENCILFAIL                | IS_STENCILOP_KEEP        |
 *   | IS_RS_STENCILZFAIL               | IS_STENCILOP_KEEP        |
 *   | IS_RS_STENCILPASS                | IS_STENCILOP_KEEP        |
 *   | IS_RS_STENCILFUNC                | IS_CMP_ALWAYS            |
 *   | IS_RS_STENCILREF                 | 0                        |
 *   | IS_RS_STENCILMASK                | 0xFFFFFFFF               |
 *   | IS_RS_STENCILWRITEMASK           | 0xFFFFFFFF               |
 *   | IS_RS_CLIPPING                   | 1                        |
 *   | IS_RS_CLIPPLANEENABLE            | 0                        |
 *   | IS_RS_COLORWRITEENABLE           | 0xF                      |
 *   | IS_RS_SCISSORTESTENABLE          | 0                        |
 *   | IS_RS_TWOSIDEDSTENCILMODE        | 0                        |
 *   | IS_RS_CCW_STENCILFAIL            | IS_STENCILOP_KEEP        |
 *   | IS_RS_CCW_STENCILZFAIL           | IS_STENCILOP_KEEP        |
 *   | IS_RS_CCW_STENCILPASS            | IS_STENCILOP_KEEP        |
 *   | IS_RS_CCW_STENCILFUNC            | IS_CMP_ALWAYS            |
 */
/* SetViewport, as the runtime takes it: any x, y and any width and height of at least 1 (a viewport reaching beyond
 * the target is drawn and cleared clipped to the target, each vertex where the whole viewport puts it; one wholly
 * outside draws nothing), MinZ and MaxZ in [0, 1] in either order.  GetViewport reads it back as given; draws use
 * MaxZ = MinZ + 0.001 when MinZ >= MaxZ (the runtime's rule, as DXVK's SetViewport records it).  Refused: NULL, a
 * width or height of 0, a depth outside [0, 1] or NaN. */
INSTESS_API is_result dev_set_viewport(is_device *dev, const is_viewport *vp);
INSTESS_API is_result dev_get_viewport(const is_device *dev, is_viewport *vp);
/* SetNPatchMode(segments): below 1 (or NaN) disables N-patches (see vs/ for the patch the device evaluates).  Every
 * float is stored and read back, as the runtime stores it; draws take more than IS_NPATCH_MAX_SEGMENTS (infinity
 * too) as that many, as a driver caps the level at its D3DCAPS9.MaxNpatchTessellationLevel. */
#define IS_NPATCH_MAX_SEGMENTS 256.0f
INSTESS_API is_result dev_set_npatch_mode(is_device *dev, float segments);
INSTESS_API float dev_get_npatch_mode(const is_device *dev);

/* --- stateblocks (IDirect3DStateBlock9) --- */
typedef struct is_state_block is_state_block;
typedef enum is_state_block_type { IS_SBT_ALL = 1, IS_SBT_PIXELSTATE = 2, IS_SBT_VERTEXSTATE = 3 } is_state_block_type;
/* BeginStateBlock / EndStateBlock: between them the setters (render states, viewport, stream sources and
 * frequencies, indices, declaration, shader, constants, textures and sampler states) write into the block being
 * recorded, not into the device (the getters still read the device); End hands out the block, which holds what was
 * set.  CreateStateBlock: a block holding D3D9's list for `type` (PIXELSTATE: the pixel render states and the pixel
 * samplers' states; VERTEXSTATE: the vertex render states, the vertex samplers' DMAPOFFSET, the declaration, the
 * shader, its constants and the stream frequencies; ALL: both, and the textures, stream buffers, indices and the
 * viewport), captured from the device now.  sb_capture refreshes what a block holds from the device, sb_apply
 * sets the device to it.  Refused (IS_ERR_INVALIDCALL, nothing changed): Begin while recording, End while not (its
 * output untouched), CreateStateBlock, Capture and Apply while recording, an unknown type, NULL outputs, a NULL
 * block or one whose device is destroyed -- as the runtime does (Wine's stateblock tests, DXVK).  A block belongs to
 * its device like a buffer (sb_release; safe after dev_destroy).  Unlike D3D9 a block holds no reference: a buffer,
 * declaration or texture released while a block holds it is dropped from the block (Apply binds nothing there).
 * SetNPatchMode and the evaluator are not stateblock state (nor in D3D9). */
INSTESS_API is_result dev_begin_state_block(is_device *dev);
INSTESS_API is_result dev_end_state_block(is_device *dev, is_state_block **out);
INSTESS_API is_result dev_create_state_block(is_device *dev, is_state_block_type type, is_state_block **out);
INSTESS_API is_result sb_capture(is_state_block *sb);
INSTESS_API is_result sb_apply(is_state_block *sb);
INSTESS_API void sb_release(is_state_block *sb);

/* RECT (and D3DRECT, the same four numbers): the pixels left <= x < right, top <= y < bottom. */
typedef struct is_rect { int32_t left, top, right, bottom; } is_rect;
/* Clear(Count, pRects, Flags, Color (D3DCOLOR ARGB), Z), as the runtime does it: the viewport is cleared, not the
 * whole target (the two are the same after dev_create or a full-target viewport), and with count rects (and
 * rects not NULL) only each rect's part of the viewport; count 0 with rects not NULL clears nothing and succeeds;
 * count > 0 with NULL rects clears the viewport.  Flags IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER | IS_CLEAR_STENCIL (to 0:
 * dev_clear_rects_stencil takes the value); z in [0, 1].  With SCISSORTESTENABLE the scissor rectangle bounds it too. */
INSTESS_API is_result dev_clear_rects(is_device *dev, unsigned count, const is_rect *rects, unsigned flags,
                                      uint32_t argb, float z);
/* dev_clear_rects(dev, 0, NULL, flags, argb, z): the viewport. */
INSTESS_API is_result dev_clear(is_device *dev, unsigned flags, uint32_t argb, float z);
/* DrawPrimitive / DrawIndexedPrimitive, with D3D9 instancing (stream frequencies) on indexed draws. */
INSTESS_API is_result dev_draw_primitive(is_device *dev, is_primtype type, unsigned start_vertex, unsigned prim_count);
INSTESS_API is_result dev_draw_indexed_primitive(is_device *dev, is_primtype type, int base_vertex_index,
                                     unsigned min_vertex_index, unsigned num_vertices, unsigned start_index,
                                     unsigned prim_count);
/* DrawPrimitiveUP / DrawIndexedPrimitiveUP: the vertices (and indices) from the caller's memory instead of buffers,
 * read during the call only.  The vertices are stream 0 (stride bytes apart: prim_count primitives' worth, or
 * MinVertexIndex + NumVertices of them; an element reaching past that reads zeros, as past a buffer's end), the
 * other streams as bound.  Afterwards stream 0 is unset (no buffer, offset 0, stride 0) and, for the indexed call,
 * the indices too (NULL), as the runtime leaves them; a count of 0 draws nothing, changes nothing and succeeds.
 * Refused: NULL data, a stride of 0, an index format other than INDEX16 / INDEX32, no declaration, and what
 * DrawPrimitive / DrawIndexedPrimitive refuse. */
INSTESS_API is_result dev_draw_primitive_up(is_device *dev, is_primtype type, unsigned prim_count,
                                            const void *vertices, unsigned stride);
INSTESS_API is_result dev_draw_indexed_primitive_up(is_device *dev, is_primtype type, unsigned min_vertex_index,
                                                    unsigned num_vertices, unsigned prim_count, const void *indices,
                                                    is_format index_format, const void *vertices, unsigned stride);

/* The render target (for output and tests) and statistics accumulated since the last dev_clear.  dev_clear is
 * deferred per tile (tiles are filled when first drawn to), and a frame's instanced draws are recorded and run
 * together (their set-up and one tile pass in one parallel region: dev_flush below, raster.h's rs_set_scene) when
 * the target is next read; dev_render_target does both, so call it again after clearing and drawing before reading the planes -- a
 * pointer kept across draws may see a target they have not been drawn into yet -- and before writing them after a
 * dev_present (the device remembers which tiles a present filled with the clear colour and does not fill them
 * again while they hold it; this call makes it forget).  dev_stats runs the recorded draws too (their counters). */
INSTESS_API rs_target *dev_render_target(is_device *dev);
/* The frame as a Present shows it: the recorded draws run and the colour (and AOV) planes written, as
 * dev_render_target, but a deferred dev_clear of the depth buffer stays deferred in the tiles no draw touched
 * (written when something reads the depth -- dev_render_target, binding other targets -- or dropped when the next
 * frame's clear replaces it; with dev_set_present_flags' DISCARD_DEPTHSTENCIL in the tiles drawn too).  So read
 * only the colour and AOV planes of the target it returns, and do not write them (a tile no draw touched keeps the
 * clear colour the present wrote there, and the next frame's dev_clear of that colour does not write it again:
 * rs_target_flush_planes' RS_PRESENT); NULL for a NULL or destroyed device. */
INSTESS_API const rs_target *dev_present(is_device *dev);
/* Run the draws recorded so far now and report how they went.  Instanced triangle draws on the fast path are
 * recorded, not run (a snapshot of the shader, constants, samplers, fetch plan and indices; the vertex buffers
 * they read stay the application's): the device runs them together -- one parallel set-up region and one tile
 * pass for all of them -- at the next read of the target (dev_render_target, dev_get_render_target_data, the
 * inspector), dev_clear, dev_stats, dev_vertices_shaded, dev_instances_culled, dev_set_threads, a draw that is not
 * recorded, a Lock or release of a vertex buffer one of them reads, a Lock, mip generation or release of any
 * texture, the end of a UP draw, dev_reset, or this call.  A draw's errors found only then -- the work bound
 * (the frame would cover each pixel more than RS_MAX_OVERDRAW times: IS_ERR_OUTOFMEMORY), out of memory -- drop
 * that draw whole (the others are drawn) and are kept: dev_flush returns the first one since its last call
 * (IS_OK: none), dev_last_error says what it was.  IS_ERR_INVALIDCALL for a NULL or destroyed device. */
INSTESS_API is_result dev_flush(is_device *dev);
/* The image the device has drawn, in one call (D3D9's GetRenderTargetData): the target resolved to one packed
 * RGBA8 value per pixel (R in the low byte, rows top to bottom) into rgba, which holds `count` values (at least
 * width x height of the target).  IS_OK, or IS_ERR_INVALIDCALL for a NULL pointer or a buffer too small. */
INSTESS_API is_result dev_get_render_target_data(is_device *dev, uint32_t *rgba, size_t count);
INSTESS_API const rs_stats *dev_stats(const is_device *dev);
/* Vertices shaded since the last dev_clear (a post-transform cache shades each one once per instance). */
INSTESS_API uint64_t dev_vertices_shaded(const is_device *dev);
/* Instances skipped by the pre-tessellation cull since the last dev_clear (dev_set_patch_cull). */
INSTESS_API uint64_t dev_instances_culled(const is_device *dev);

/* N-patch mode (SetNPatchMode, POSITIONDEGREE, NORMALDEGREE, PATCHEDGESTYLE).  With segments >= 1, indexed
 * triangle-list draws are tessellated by the device before the vertex shader, as D3D9's tessellator did: each
 * input triangle becomes a grid with the same vertex and triangle order as the instanced path: with
 * PATCHEDGESTYLE DISCRETE (the default) the regular grid of level (int)segments, with CONTINUOUS the
 * primitive generator's fractional_even grid of level segments (core_grid_make); at each grid point the evaluator below computes the object-space
 * position and normal from the triangle's POSITION0 / NORMAL0; every other input register is interpolated
 * linearly in the barycentrics.  The evaluator is the patch code of vs/ (vs_npatch_evaluate), plugged in by the
 * application so that core does not depend on vs/.  b = (b0, b1, b2) weights v[0], v[1], v[2]. */
typedef void (*is_npatch_eval_fn)(const float3 v[3], const float3 n[3], float3 b, uint32_t position_degree,
                                  uint32_t normal_degree, float3 *pos, float3 *nrm);
INSTESS_API is_result dev_set_npatch_evaluator(is_device *dev, is_npatch_eval_fn fn);

/* Adaptive N-patch mode (D3DRS_ENABLEADAPTIVETESSELLATION TRUE, with N-patch mode on as above).  The rule, as the
 * DirectX 9 documentation states it (Microsoft, "Tessellation (Direct3D 9)", section "Adaptive Tessellation",
 * and its "Math" part; the D3DX counterpart is ID3DXPatchMesh::TessellateAdaptive):
 *  - each vertex i of a triangle gets T_i = S * F_i / dot(V_i, Mdm), where S is the N-patch segments
 *    (SetNPatchMode: the documentation's "MaxTessellationLevel ... set by SetNPatchMode for N-patches", the level
 *    at eye depth 1), F_i the vertex's D3DDECLUSAGE_TESSFACTOR (FLOAT1, usage index 0; 1.0 when the declaration
 *    has none), V_i its POSITION0 register as fetched (x, y, z, w; w = 1 for FLOAT3: the control vertex before any
 *    transform) and Mdm = (ADAPTIVETESS_X, _Y, _Z, _W), which maps V to its eye-space depth: e.g. the third column
 *    of World * View, so that dot(V, Mdm) is the vertex's view z;
 *  - each edge gets the mean of its two ends, T_e = (T_1 + T_2) / 2; a T_e above MAXTESSELLATIONLEVEL, below 0,
 *    or not a number becomes MAXTESSELLATIONLEVEL (the documentation's "> MAX || < 0"; NaN, which it does not
 *    name -- 0/0, or +inf and -inf averaged -- is taken as out of range too), and then a T_e below
 *    MINTESSELLATIONLEVEL becomes MINTESSELLATIONLEVEL (so MIN wins when MIN > MAX).
 * An edge's level depends on its two vertices alone (the mean is symmetric), so both triangles of an edge agree.
 * Defaults (the documentation's): ENABLEADAPTIVETESSELLATION FALSE, MIN = MAX = 1.0f, Mdm = (0, 0, 1, 0); MIN and
 * MAX must be finite (the documentation adds "cannot be less than 1"; the runtime takes less, and so does this
 * device: an edge level below 1 draws as 1, one segment), X..W finite.  Disabled, the mode draws as above, bit
 * for bit as before these states existed.
 * The tessellation of a triangle with edge levels (e0, e1, e2) (edge k from v[k] to v[k+1 mod 3]): DISCRETE
 * truncates each to an integer, CONTINUOUS keeps them; levels above CORE_PG_MAX_LEVEL (64) are taken as 64 (the
 * primitive generator's bound).  Equal levels give exactly the non-adaptive grid of that level (so MIN = MAX = S
 * renders the same bytes as the mode without adaptivity); otherwise the primitive generator's grid
 * (core_grid_pg: equal spacing for DISCRETE, fractional_even for CONTINUOUS) with outer = (e0, e1, e2) and inner =
 * max(e0, e1, e2) -- D3D11's ProcessTriTessFactorsMax rule: the interior is never coarser than the triangle's
 * finest edge, so a triangle refined for one near vertex keeps that detail inside.  Edge points depend only on
 * the edge's level and ends (core_grid_pg's watertightness), so neighbours at different levels share them bit
 * for bit.  (The documentation's sentence that adaptive tessellation also draws triangles as N-patches when
 * SetNPatchMode is below 1 is not followed: below 1, S is below 1 and the mode is off.) */
/* T_i of one vertex: S * factor / dot(v, mdm) in float, as above (not clamped: that is per edge). */
INSTESS_API float core_adaptive_vertex_level(float segments, float factor, float4 v, float4 mdm);
/* T_e of an edge from its ends' T_1, T_2 and the MIN / MAX states, as above. */
INSTESS_API float core_adaptive_edge_level(float t1, float t2, float min_level, float max_level);

/* --- per-pixel and clipping states: scissor, colour write mask, alpha test, stencil, clip planes, CLIPPING,
 * pre-transformed vertices (core/raster_states.c; the rasterizer's side is raster/pixel.c) ---
 * As D3D9 with a D3DFMT_D24S8 depth-stencil buffer (8 stencil bits per sample beside the depth, which stays a
 * float here), in D3D9's order: scissor, alpha test, stencil test, depth test, blend, colour write mask.
 *  - Scissor: with SCISSORTESTENABLE only pixels inside the scissor rectangle (and the viewport) are drawn, and
 *    Clear clears only inside it.  The rectangle is the whole target on a new device and after dev_reset (as the
 *    runtime sets it); any rectangle is accepted (the part inside the target counts; an empty or inverted one
 *    draws nothing).
 *  - COLORWRITEENABLE: IS_COLORWRITEENABLE_* bits; channels not in it keep the target's value (after blending).
 *    Bits above 0xF are stored and ignored.  Clear is not masked (D3D9 clears ignore it too).
 *  - Alpha test (ALPHATESTENABLE, ALPHAFUNC, ALPHAREF): the pixel is kept when "alpha ALPHAFUNC ref", alpha being
 *    COLOR0's alpha saturated and rounded to 8 bits (what the target stores) and ref ALPHAREF's low 8 bits; a
 *    pixel that fails writes nothing (colour, depth or stencil).
 *  - Stencil (STENCILENABLE ...): "(ref & STENCILMASK) STENCILFUNC (stencil & STENCILMASK)" per sample, ref
 *    STENCILREF's low 8 bits; STENCILFAIL runs when it fails, STENCILZFAIL when it passes and depth fails,
 *    STENCILPASS when both pass, each writing only the bits of STENCILWRITEMASK; depth and colour are written
 *    only when both pass.  TWOSIDEDSTENCILMODE: triangles counter-clockwise on screen (the back faces of D3D9's
 *    clockwise front) use the CCW_* states; lines and points always the clockwise ones.  Clear's
 *    IS_CLEAR_STENCIL sets the stencil (dev_clear_rects_stencil).
 *  - Clip planes (SetClipPlane, CLIPPLANEENABLE bits 0..5): a vertex shader's oPos is kept where
 *    a x + b y + c z + d w >= 0, in clip space (as D3D9 with a vertex shader); the part outside is clipped
 *    exactly as the near plane clips.  Not applied to pre-transformed vertices.
 *  - CLIPPING FALSE: nothing is clipped but against the guard band (no near, far or user planes); depth outside
 *    the viewport's range is clamped to it, as the runtime with software vertex processing (Wine's
 *    depth_clamp_test).  The guard band stays (it keeps the fixed point exact).
 *  - Pre-transformed vertices: with no vertex shader set and a declaration with IS_DECLUSAGE_POSITIONT (index 0,
 *    FLOAT4: D3DFVF_XYZRHW's x, y, z, rhw), a draw takes the position as screen pixels x, y (pixel centres at
 *    integers, as every D3D9 coordinate here), depth z as is (the viewport's MinZ / MaxZ do not map it; it is
 *    clipped to [0, 1], or clamped with CLIPPING FALSE), and 1/w = rhw for perspective-correct interpolation of
 *    COLOR0, COLOR1 and TEXCOORD0..7 (which it passes through; COLOR0 absent from the declaration is opaque
 *    white, D3D9's default diffuse).  The viewport still bounds the pixels drawn.  A declaration may not hold
 *    both POSITION0 and POSITIONT (they share the register).
 * Each state is off by default (the defaults table above), and off it changes nothing: draws take the fast paths
 * as before.  With any of alpha test, stencil, colour write mask, user planes, CLIPPING FALSE or pre-transformed
 * vertices on, a draw takes the rasterizer's reference path (the same bytes for any thread count and ISA). */
/* SetScissorRect / GetScissorRect: NULL is IS_ERR_INVALIDCALL. */
INSTESS_API is_result dev_set_scissor_rect(is_device *dev, const is_rect *rect);
INSTESS_API is_result dev_get_scissor_rect(const is_device *dev, is_rect *rect);
/* SetClipPlane / GetClipPlane: plane (a, b, c, d); an index beyond the last plane names the last one (the
 * runtime clamps it so; Wine's d3d9 does the same); NULL, or (Set) a plane not finite, is IS_ERR_INVALIDCALL
 * (the runtime stores any floats; what it then draws is undefined). */
INSTESS_API is_result dev_set_clip_plane(is_device *dev, unsigned index, const float plane[4]);
INSTESS_API is_result dev_get_clip_plane(const is_device *dev, unsigned index, float plane[4]);
/* D3D9's Clear(Count, pRects, Flags, Color, Z, Stencil): dev_clear_rects with the stencil value, which
 * IS_CLEAR_STENCIL in flags writes (its low 8 bits) to the same pixels (dev_clear_rects clears it to 0). */
INSTESS_API is_result dev_clear_rects_stencil(is_device *dev, unsigned count, const is_rect *rects, unsigned flags,
                                              uint32_t argb, float z, uint32_t stencil);

/* The scalar reference path (for tests and teaching): with on, draws shade vertex by vertex through the
 * shader's `main` and the rasterizer walks its simplest per-sample loops; off (the default) takes the fast
 * paths (batched shaders, shared vertex projection, 8-pixel spans), which produce the same bytes. */
INSTESS_API void dev_set_reference_path(is_device *dev, bool on);
INSTESS_API bool dev_reference_path(const is_device *dev);
/* The instruction set of the rasterizer's fast paths (raster.h's RS_ISA_*: AVX2, or AVX-512 where the CPU has
 * it, which a new device picks): 0, or -1 (nothing changed) when this CPU lacks it.  Every one writes the same
 * bytes; this exists to compare them and to measure each. */
INSTESS_API int dev_set_isa(is_device *dev, int isa);
INSTESS_API int dev_isa(const is_device *dev);

/* --- render targets and surfaces (IDirect3DSurface9; core/surface.c) ---
 * A surface is a render target (CreateRenderTarget, or a level of a texture created with IS_USAGE_RENDERTARGET:
 * tex_get_surface_level), a depth-stencil surface (CreateDepthStencilSurface) or a system-memory surface
 * (CreateOffscreenPlainSurface, D3DPOOL_SYSTEMMEM: what GetRenderTargetData copies into and LockRect reads).
 *  - The device draws into dev_render_target's rs_target; SetRenderTarget and SetDepthStencilSurface change which
 *    surface's planes it describes.  A new device's target is its back buffer (A8R8G8B8, dev_create's size and
 *    samples) and its depth-stencil surface the automatic one (D24S8); dev_get_render_target(dev, 0) and
 *    dev_get_depth_stencil_surface hand them out, and dev_reset sets them again.  The back buffer keeps its AOV
 *    planes (raster.h) while another target is set; other targets have none.
 *  - SetRenderTarget(0, surface) (index 0 only: this device has one, D3DCAPS9.NumSimultaneousRTs 1) sets the
 *    viewport to the whole new target (MinZ 0, MaxZ 1) and the scissor rectangle to the whole target, also when it
 *    is the target already and also while a stateblock is recorded (the device's own state: Wine's d3d9
 *    test_set_rt_vp_scissor; DXVK's SetRenderTarget).  Render targets are not stateblock state.  Refused: a NULL
 *    surface, an index other than 0, a surface that is not a render target (a depth-stencil or system-memory
 *    surface, a level of a texture without RENDERTARGET), one of another device or released.
 *  - SetDepthStencilSurface(NULL or a depth-stencil surface): any size, as the runtime takes it.  Drawing needs
 *    it to be at least the target's size with the target's samples (D3D9: "must be at least as large as the render
 *    target"; the runtime draws something undefined otherwise -- Wine's d3d9 test_depth_stencil_size -- and
 *    ValidateDevice reports the conflict); here, as DXVK does, a smaller (or differently sampled) surface, like no
 *    surface, is not bound: depth and stencil tests are off and it keeps its contents.  A larger one is used by
 *    its top-left part.  Clear with IS_CLEAR_ZBUFFER or IS_CLEAR_STENCIL without a depth-stencil surface, or with
 *    IS_CLEAR_STENCIL on one without stencil bits (D24X8, D16), is refused, as the runtime (wined3d's clear).
 *  - Render-target textures: A8R8G8B8 or X8R8G8B8 (IS_ERR_NOTAVAILABLE for the float formats: this device's
 *    targets are 8-bit), any levels, AUTOGENMIPMAP allowed; they cannot be locked (D3DPOOL_DEFAULT: LockRect is
 *    refused).  While a level is the target, the device draws into a colour plane of its own; when another target
 *    is set (or the texture's device is reset or destroyed) the plane is written back into the level's texels
 *    (and an AUTOGENMIPMAP texture's sublevels generated), so a texture is sampled as rendered once the device
 *    draws elsewhere.  Sampling a texture while it is the target reads its texels from before (D3D9: undefined).
 *  - GetRenderTargetData (dev_get_render_target_surface_data): a one-sample render target (a surface or a
 *    level, the current target or not) into a system-memory surface of the same size and format, converted to the
 *    format's layout (bytes B, G, R, A per pixel).  Refused: multisampled sources, other sizes or formats, a
 *    destination that is not a system-memory surface, as the runtime.
 *  - Ownership: created surfaces belong to their device as buffers do (registry; surf_release, safe after
 *    dev_destroy); the back buffer, the automatic depth-stencil surface and texture levels belong to the device or
 *    the texture, and surf_release does nothing to them.  Releasing the current target sets the back buffer again
 *    (as SetRenderTarget does), releasing the current depth-stencil surface leaves none.  As the other getters,
 *    GetRenderTarget and GetDepthStencilSurface add no reference. */
typedef struct is_surface is_surface;
#define IS_FMT_D24S8 ((is_format)75)        /* depth-stencil formats: depth stays a float here, 8 stencil bits */
#define IS_FMT_D24X8 ((is_format)77)        /* no stencil bits */
#define IS_FMT_D16 ((is_format)80)          /* no stencil bits */
#define IS_USAGE_RENDERTARGET 0x1u          /* D3DUSAGE_RENDERTARGET */
#define IS_USAGE_DEPTHSTENCIL 0x2u          /* D3DUSAGE_DEPTHSTENCIL */
#define IS_MULTISAMPLE_NONE 0u              /* D3DMULTISAMPLE_TYPE */
#define IS_MULTISAMPLE_4_SAMPLES 4u
#define IS_ERR_NOTFOUND ((is_result)-4)     /* D3DERR_NOTFOUND */
typedef struct is_surface_desc {            /* D3DSURFACE_DESC, the fields kept */
    is_format format;
    uint32_t usage;                          /* IS_USAGE_RENDERTARGET, IS_USAGE_DEPTHSTENCIL or 0 */
    unsigned width, height;
    unsigned multisample;                    /* IS_MULTISAMPLE_NONE or IS_MULTISAMPLE_4_SAMPLES */
} is_surface_desc;

/* CreateRenderTarget: A8R8G8B8 or X8R8G8B8 (IS_ERR_NOTAVAILABLE otherwise), 1..16384 per side, multisample NONE
 * or 4_SAMPLES; pixels start zero. */
INSTESS_API is_result dev_create_render_target(is_device *dev, unsigned width, unsigned height, is_format format,
                                               unsigned multisample, is_surface **out);
/* CreateDepthStencilSurface: D24S8, D24X8 or D16, sizes and multisample as above; depth starts 1, stencil 0. */
INSTESS_API is_result dev_create_depth_stencil_surface(is_device *dev, unsigned width, unsigned height,
                                                       is_format format, unsigned multisample, is_surface **out);
/* CreateOffscreenPlainSurface in D3DPOOL_SYSTEMMEM: A8R8G8B8 or X8R8G8B8; pixels start zero. */
INSTESS_API is_result dev_create_offscreen_plain_surface(is_device *dev, unsigned width, unsigned height,
                                                         is_format format, is_surface **out);
/* IDirect3DTexture9::GetSurfaceLevel: the texture's level as a surface (the same surface every call). */
INSTESS_API is_result tex_get_surface_level(is_texture *tex, unsigned level, is_surface **out);
/* Release a created surface (NULL, or an implicit or texture-level one: nothing). */
INSTESS_API void surf_release(is_surface *surf);
/* GetDesc. */
INSTESS_API is_result surf_get_desc(const is_surface *surf, is_surface_desc *out);
/* LockRect / UnlockRect of a system-memory surface (others are refused, as non-lockable targets): the pixels of
 * rect (NULL: all) at *bits, rows *pitch bytes apart; locked once at a time. */
INSTESS_API is_result surf_lock_rect(is_surface *surf, const is_rect *rect, int *pitch, void **bits);
INSTESS_API is_result surf_unlock_rect(is_surface *surf);
/* SetRenderTarget / GetRenderTarget, SetDepthStencilSurface / GetDepthStencilSurface (IS_ERR_NOTFOUND and NULL
 * when none is set), GetRenderTargetData: the rules above. */
INSTESS_API is_result dev_set_render_target(is_device *dev, unsigned index, is_surface *surf);
INSTESS_API is_result dev_get_render_target(const is_device *dev, unsigned index, is_surface **out);
INSTESS_API is_result dev_set_depth_stencil_surface(is_device *dev, is_surface *surf);
INSTESS_API is_result dev_get_depth_stencil_surface(const is_device *dev, is_surface **out);
INSTESS_API is_result dev_get_render_target_surface_data(is_device *dev, is_surface *src, is_surface *dst);

/* SetFVF / GetFVF (core/fvf.c): the declaration the runtime makes for a flexible vertex format (XYZ or XYZRHW,
 * NORMAL, PSIZE, DIFFUSE, SPECULAR, TEXCOUNT with D3DFVF_TEXCOORDSIZEn), in one stream, set as the vertex
 * declaration; the FVF values are D3D9's (D3DFVF_XYZRHW = 0x004, D3DFVF_DIFFUSE = 0x040, D3DFVF_TEX1 = 0x100...).
 * Blend weights and unknown bits are refused; SetVertexDeclaration makes GetFVF 0. */
INSTESS_API is_result dev_set_fvf(is_device *dev, uint32_t fvf);
INSTESS_API is_result dev_get_fvf(const is_device *dev, uint32_t *fvf);

#ifdef __cplusplus
}
#endif
#endif
