/* core/core.h -- a device modelled on IDirect3DDevice9, D3DX-style math, and image files.
 *
 * Conventions:
 *  - Spaces: left-handed, as D3D9.  Object -> world -> view -> clip with row vectors: v' = mul(v, M), so a
 *    matrix's translation is its 4th row and M = World * View * Proj transforms in that order.
 *  - Clip volume -w <= x, y <= w, 0 <= z <= w; the viewport maps z/w to [MinZ, MaxZ].
 *  - Pixel centres at integer coordinates, top-left fill rule, clockwise front faces, default cull CCW:
 *    see raster/raster.h, which is the interface between this device and the rasterizer.
 *  - Names: a D3D9 method becomes dev_<snake_case>(dev, ...) (SetStreamSourceFreq -> dev_set_stream_source_freq);
 *    a D3D9 constant D3DXXX_YYY becomes IS_XXX_YYY (D3DCULL_CCW -> IS_CULL_CCW, D3DRS_CULLMODE -> IS_RS_CULLMODE).
 *    Values of render states equal D3D9's.
 *  - Errors: every dev_* call returns IS_OK (0) or a negative IS_ERR_* code; an invalid call changes nothing and
 *    leaves a message in dev_last_error(dev).  Image functions return 0 or -1 with a message in err.
 *  - No globals: all state lives in the device (the context passed first).  Threads: dev_set_threads.
 */
#ifndef INSTESS_CORE_H
#define INSTESS_CORE_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "../raster/raster.h"

#ifdef __cplusplus
extern "C" {
#endif

#define INSTESS_VERSION "0.1.0"

/* ================================ HLSL-like math (D3DX conventions) ================================ */

typedef struct float2 { float x, y; } float2;
typedef struct float3 { float x, y, z; } float3;
typedef rs_vec4 float4;                       /* { x, y, z, w } */
typedef struct float4x4 { float m[4][4]; } float4x4; /* m[row][col], row vectors */

static inline float2 f2(float x, float y) { return (float2){x, y}; }
static inline float3 f3(float x, float y, float z) { return (float3){x, y, z}; }
static inline float4 f4(float x, float y, float z, float w) { return (float4){x, y, z, w}; }
static inline float3 f3_of(float4 v) { return (float3){v.x, v.y, v.z}; }   /* v.xyz */
static inline float2 f2_of(float4 v) { return (float2){v.x, v.y}; }        /* v.xy  */
static inline float4 f4_of(float3 v, float w) { return (float4){v.x, v.y, v.z, w}; }

static inline float3 add3(float3 a, float3 b) { return f3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline float3 sub3(float3 a, float3 b) { return f3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline float3 scale3(float3 a, float s) { return f3(a.x * s, a.y * s, a.z * s); }
static inline float3 neg3(float3 a) { return f3(-a.x, -a.y, -a.z); }
static inline float dot3(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline float3 cross3(float3 a, float3 b)
{
    return f3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float length3(float3 a) { return sqrtf(dot3(a, a)); }
/* HLSL normalize(); a zero vector stays zero instead of becoming NaN. */
static inline float3 normalize3(float3 a)
{
    float l = length3(a);
    return l > 0.0f ? scale3(a, 1.0f / l) : a;
}
static inline float3 lerp3(float3 a, float3 b, float t) { return add3(a, scale3(sub3(b, a), t)); }
static inline float saturate(float x) { return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x); }
static inline float2 add2(float2 a, float2 b) { return f2(a.x + b.x, a.y + b.y); }
static inline float2 scale2(float2 a, float s) { return f2(a.x * s, a.y * s); }
static inline float4 scale4(float4 a, float s) { return f4(a.x * s, a.y * s, a.z * s, a.w * s); }

/* mul(v, M) for a row vector v. */
static inline float4 mul4(float4 v, const float4x4 *M)
{
    float4 r;
    r.x = v.x * M->m[0][0] + v.y * M->m[1][0] + v.z * M->m[2][0] + v.w * M->m[3][0];
    r.y = v.x * M->m[0][1] + v.y * M->m[1][1] + v.z * M->m[2][1] + v.w * M->m[3][1];
    r.z = v.x * M->m[0][2] + v.y * M->m[1][2] + v.z * M->m[2][2] + v.w * M->m[3][2];
    r.w = v.x * M->m[0][3] + v.y * M->m[1][3] + v.z * M->m[2][3] + v.w * M->m[3][3];
    return r;
}
/* mul(v, (float3x3)M): direction transform by the upper 3x3. */
static inline float3 mul3x3(float3 v, const float4x4 *M)
{
    return f3(v.x * M->m[0][0] + v.y * M->m[1][0] + v.z * M->m[2][0],
              v.x * M->m[0][1] + v.y * M->m[1][1] + v.z * M->m[2][1],
              v.x * M->m[0][2] + v.y * M->m[1][2] + v.z * M->m[2][2]);
}

float4x4 mat_identity(void);
/* A * B (apply A first, then B, for row vectors). */
float4x4 mat_mul(const float4x4 *a, const float4x4 *b);
float4x4 mat_translation(float x, float y, float z);
float4x4 mat_scaling(float x, float y, float z);
/* D3DXMatrixRotationX/Y/Z: angle in radians, left-handed (clockwise looking down the axis to the origin). */
float4x4 mat_rotation_x(float a);
float4x4 mat_rotation_y(float a);
float4x4 mat_rotation_z(float a);
/* D3DXMatrixLookAtLH. */
float4x4 mat_look_at_lh(float3 eye, float3 at, float3 up);
/* D3DXMatrixPerspectiveFovLH: fovy in radians, aspect = width / height, z in [zn, zf] -> [0, 1]. */
float4x4 mat_perspective_fov_lh(float fovy, float aspect, float zn, float zf);
/* D3DXMatrixOrthoLH. */
float4x4 mat_ortho_lh(float w, float h, float zn, float zf);
/* Transpose; inverse (returns false, and identity, when singular). */
float4x4 mat_transpose(const float4x4 *a);
bool mat_inverse(const float4x4 *a, float4x4 *out);

/* ================================ the device ================================ */

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

typedef enum is_format { IS_FMT_INDEX16 = 101, IS_FMT_INDEX32 = 102 } is_format;

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
    IS_RS_ENABLEADAPTIVETESSELLATION = 184
} is_rs;

enum { IS_CULL_NONE = 1, IS_CULL_CW = 2, IS_CULL_CCW = 3 };
enum { IS_FILL_POINT = 1, IS_FILL_WIREFRAME = 2, IS_FILL_SOLID = 3 };
enum { IS_SHADE_FLAT = 1, IS_SHADE_GOURAUD = 2 };
enum { IS_ZB_FALSE = 0, IS_ZB_TRUE = 1 };
enum {
    IS_CMP_NEVER = 1, IS_CMP_LESS, IS_CMP_EQUAL, IS_CMP_LESSEQUAL,
    IS_CMP_GREATER, IS_CMP_NOTEQUAL, IS_CMP_GREATEREQUAL, IS_CMP_ALWAYS
};
enum {
    IS_BLEND_ZERO = 1, IS_BLEND_ONE = 2, IS_BLEND_SRCCOLOR = 3, IS_BLEND_INVSRCCOLOR = 4,
    IS_BLEND_SRCALPHA = 5, IS_BLEND_INVSRCALPHA = 6, IS_BLEND_DESTALPHA = 7, IS_BLEND_INVDESTALPHA = 8,
    IS_BLEND_DESTCOLOR = 9, IS_BLEND_INVDESTCOLOR = 10
};
enum { IS_DEGREE_LINEAR = 1, IS_DEGREE_QUADRATIC = 2, IS_DEGREE_CUBIC = 3 };
enum { IS_PATCHEDGE_DISCRETE = 0, IS_PATCHEDGE_CONTINUOUS = 1 };
enum { IS_CLEAR_TARGET = 1, IS_CLEAR_ZBUFFER = 2 };
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

/* Shader constants c0..c255 (SetVertexShaderConstantF). */
typedef struct is_vs_constants { float4 c[IS_MAX_VS_CONSTANTS]; } is_vs_constants;

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

typedef struct is_vertex_shader {
    const char *name;
    is_vs_fn main;
    uint32_t outputs;   /* IS_OUT_* mask of written outputs (what the rasterizer interpolates) */
    is_vs_batch_fn batch; /* NULL: the device calls main per vertex */
    is_vs_hull_fn hull;   /* NULL: no bound, every instance is shaded */
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
is_device *dev_create(int width, int height, int samples, char *err, size_t errlen);
void dev_destroy(is_device *dev);
/* The device's state back to a new device's (render states, stream sources and frequencies, indices,
 * declaration, shader, constants, viewport, N-patch mode and evaluator); the target, its contents, the thread
 * count, timing, reference path and scratch memory are kept.  For programs that draw frame after frame on one
 * device (instess view): the next frame is drawn as on a new device, without allocating its target again. */
void dev_reset(is_device *dev);
/* The message of the last failed call ("" if none). */
const char *dev_last_error(const is_device *dev);
/* Threads used by draws (0: all cores).  Output bytes do not depend on it. */
void dev_set_threads(is_device *dev, int threads);
/* Phase times on or off (default off): dev_stats' setup_ms and tile_ms then sum the frame's set-up regions
 * (vertex shading included) and tile passes; off, both stay 0 so that the statistics of two renders compare
 * equal. */
void dev_set_timing(is_device *dev, bool on);
/* Pre-tessellation culling on or off (default off; the reference path never culls): an instanced triangle draw
 * whose shader has a hull stage skips, before shading any of its vertices, every instance that the hull proves
 * invisible -- outside one plane of the view, or (on a regular barycentric grid in stream 0's POSITION0, cull mode
 * CW or CCW, solid fill) with every grid triangle culled by its snapped winding.  The image bytes are those of the
 * draw without it; the statistics count fewer triangles and vertices (dev_instances_culled counts the skips). */
void dev_set_patch_cull(is_device *dev, bool on);

/* Buffers: CreateVertexBuffer / CreateIndexBuffer, Lock (returns the memory), Unlock. */
is_result dev_create_vertex_buffer(is_device *dev, size_t bytes, is_vertex_buffer **out);
is_result dev_create_index_buffer(is_device *dev, size_t bytes, is_format fmt, is_index_buffer **out);
void *vb_lock(is_vertex_buffer *vb);
void vb_unlock(is_vertex_buffer *vb);
size_t vb_size(const is_vertex_buffer *vb);
void vb_release(is_vertex_buffer *vb);
void *ib_lock(is_index_buffer *ib);
void ib_unlock(is_index_buffer *ib);
size_t ib_size(const is_index_buffer *ib);
void ib_release(is_index_buffer *ib);

/* CreateVertexDeclaration: elements ended by IS_DECL_END; validates types, usages and overlaps. */
is_result dev_create_vertex_declaration(is_device *dev, const is_vertex_element *elements,
                                        is_vertex_declaration **out);
void decl_release(is_vertex_declaration *decl);

/* State setters, as IDirect3DDevice9. */
is_result dev_set_vertex_declaration(is_device *dev, is_vertex_declaration *decl);
is_result dev_set_stream_source(is_device *dev, unsigned stream, is_vertex_buffer *vb, unsigned offset,
                                unsigned stride);
is_result dev_set_stream_source_freq(is_device *dev, unsigned stream, uint32_t setting);
is_result dev_get_stream_source_freq(const is_device *dev, unsigned stream, uint32_t *setting);
is_result dev_set_indices(is_device *dev, is_index_buffer *ib);
is_result dev_set_vertex_shader(is_device *dev, const is_vertex_shader *vs);
is_result dev_set_vertex_shader_constant_f(is_device *dev, unsigned start, const float *data, unsigned count4);
is_result dev_set_render_state(is_device *dev, is_rs state, uint32_t value);
is_result dev_get_render_state(const is_device *dev, is_rs state, uint32_t *value);
is_result dev_set_viewport(is_device *dev, const is_viewport *vp);
is_result dev_get_viewport(const is_device *dev, is_viewport *vp);
/* SetNPatchMode(segments): below 1 disables N-patches (see vs/ for the patch the device evaluates). */
is_result dev_set_npatch_mode(is_device *dev, float segments);
float dev_get_npatch_mode(const is_device *dev);

/* Clear(flags, color (D3DCOLOR ARGB), z). */
is_result dev_clear(is_device *dev, unsigned flags, uint32_t argb, float z);
/* DrawPrimitive / DrawIndexedPrimitive, with D3D9 instancing (stream frequencies) on indexed draws. */
is_result dev_draw_primitive(is_device *dev, is_primtype type, unsigned start_vertex, unsigned prim_count);
is_result dev_draw_indexed_primitive(is_device *dev, is_primtype type, int base_vertex_index,
                                     unsigned min_vertex_index, unsigned num_vertices, unsigned start_index,
                                     unsigned prim_count);

/* The render target (for output and tests) and statistics accumulated since the last dev_clear.  dev_clear is
 * deferred per tile (tiles are filled when first drawn to); dev_render_target writes out the tiles still pending,
 * so call it again after clearing and drawing before reading the planes -- a pointer kept across a dev_clear
 * may see tiles that were never drawn to with their old contents. */
rs_target *dev_render_target(is_device *dev);
const rs_stats *dev_stats(const is_device *dev);
/* Vertices shaded since the last dev_clear (a post-transform cache shades each one once per instance). */
uint64_t dev_vertices_shaded(const is_device *dev);
/* Instances skipped by the pre-tessellation cull since the last dev_clear (dev_set_patch_cull). */
uint64_t dev_instances_culled(const is_device *dev);

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
is_result dev_set_npatch_evaluator(is_device *dev, is_npatch_eval_fn fn);

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
 * MAX must be finite and >= 1 ("cannot be less than 1"), X..W finite.  Disabled, the mode draws as above, bit
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
float core_adaptive_vertex_level(float segments, float factor, float4 v, float4 mdm);
/* T_e of an edge from its ends' T_1, T_2 and the MIN / MAX states, as above. */
float core_adaptive_edge_level(float t1, float t2, float min_level, float max_level);

/* The scalar reference path (for tests and teaching): with on, draws shade vertex by vertex through the
 * shader's `main` and the rasterizer walks its simplest per-sample loops; off (the default) takes the fast
 * paths (batched shaders, shared vertex projection, 8-pixel spans), which produce the same bytes. */
void dev_set_reference_path(is_device *dev, bool on);
bool dev_reference_path(const is_device *dev);
/* The instruction set of the rasterizer's fast paths (raster.h's RS_ISA_*: AVX2, or AVX-512 where the CPU has
 * it, which a new device picks): 0, or -1 (nothing changed) when this CPU lacks it.  Every one writes the same
 * bytes; this exists to compare them and to measure each. */
int dev_set_isa(is_device *dev, int isa);
int dev_isa(const is_device *dev);

/* ================================ tessellation grids (core/grid.c) ================================ */

/* The regular barycentric grid of a triangle at level L >= 1 (seed 000, Fig. 1.1.6): (L+1)(L+2)/2 points and
 * L*L triangles.  Point (i, j) with i + j <= L has b = ((L-i-j)/L, i/L, j/L) stored at index
 * core_grid_index(L, i, j) (rows of constant j); triangles wind like the input triangle (v0, v1, v2).
 * Each coordinate is computed as (integer)/L, so mirrored points of an edge hold the same floats swapped.
 * bary gets the points, idx gets 3*L*L indices.  Returns the number of points. */
size_t core_grid_regular(int level, float3 *bary, uint32_t *idx);
static inline size_t core_grid_points(int level) { return (size_t)(level + 1) * (size_t)(level + 2) / 2; }
static inline size_t core_grid_triangles(int level) { return (size_t)level * (size_t)level; }
static inline uint32_t core_grid_index(int level, int i, int j)
{
    /* rows j = 0..L hold L+1-j points each */
    return (uint32_t)(j * (level + 1) - j * (j - 1) / 2 + i);
}

/* The pattern of the OpenGL 4 / Direct3D 11 primitive generator for triangles (seed 001, Figs. 10-11):
 * concentric rings from the inner level, outer edges subdivided by the three outer levels (outer[k] belongs to
 * edge k: 0 = v0-v1, 1 = v1-v2, 2 = v2-v0 in instess's edge order), with equal, fractional_odd or
 * fractional_even spacing (core/grid_pg.c has the rules).  Points are barycentric like core_grid_regular's and
 * wind the same way; a point on an edge has exactly one coordinate 0, and its two others are each computed
 * from the count of segments from its own end, so a neighbour with the same outer level holds the same floats
 * swapped (watertight).  Levels are clamped to [1, 64] (fractional_odd: [1, 63], fractional_even: [2, 64]); non-finite levels are
 * an error.  Memory is allocated here: free with core_grid_free. */
typedef enum core_grid_kind {
    CORE_GRID_REGULAR = 0, CORE_GRID_PG_EQUAL, CORE_GRID_PG_FRACTIONAL_ODD, CORE_GRID_PG_FRACTIONAL_EVEN
} core_grid_kind;
typedef struct core_grid {
    size_t n_points, n_triangles;
    float3 *bary;   /* n_points */
    uint32_t *idx;  /* 3 * n_triangles */
} core_grid;
#define CORE_PG_MAX_LEVEL 64.0f
/* The level a primitive-generator grid of this spacing uses for `level`: clamped to [1, 63] (fractional_odd),
 * [2, 64] (fractional_even) or [1, 64] (equal), as the D3D11 / GL 4 primitive generator does. */
float core_grid_pg_clamp(core_grid_kind kind, float level);
/* Primitive-generator grid with an inner level and three outer levels; 0 or -1 (bad level, no memory). */
int core_grid_pg(core_grid_kind spacing, float inner, const float outer[3], core_grid *out);
/* Any grid at one level: regular (level rounded to the nearest integer >= 1) or pg with inner = outer = level. */
int core_grid_make(core_grid_kind kind, float level, core_grid *out);
void core_grid_free(core_grid *g);

/* ================================ adaptive tessellation patterns (core/grid_adaptive.c) ================================ */

/* Refinement patterns for per-edge levels (semi-uniform tessellation: Dyken, Reimers, Seland, "Semi-uniform
 * adaptive patch tessellation", Computer Graphics Forum 28(8), 2009).  The pattern of edge levels (l0, l1, l2)
 * (edge k: v_k - v_(k+1), as core_grid_regular; each level 1..CORE_LOD_MAX_LEVEL) is the regular grid of level
 * M = max(l0, l1, l2) whose points on edge k are snapped to the nearest of that edge's l_k + 1 points (round
 * half up in integer arithmetic, a monotone map, so no triangle folds over), merged, and whose triangles that
 * lost an index to the merge (zero area) are dropped.  An edge point k segments of l from v_e holds the weight
 * (float)k / (float)l for the far corner and (float)(l - k) / (float)l for v_e, the same floats (swapped) for
 * the neighbour whatever its other levels: neighbours agree bit for bit on every edge point.  With
 * l0 = l1 = l2 = L the pattern is core_grid_regular(L), point for point and triangle for triangle.
 * Triangles wind like (v0, v1, v2); points are in the regular grid's order with the merged ones left out. */
#define CORE_LOD_MAX_LEVEL 64
/* The pattern of edge levels l[0..2] (any order); 0, or -1 for a level outside 1..CORE_LOD_MAX_LEVEL or no memory.
 * Free with core_grid_free. */
int core_grid_adaptive(const int levels[3], core_grid *out);

/* Patterns are kept for sorted triples a <= b <= c only: a triangle with edge levels e[0..2] is drawn with the
 * pattern of sort(e) after renumbering its vertices.  core_lod_order gives that renumbering: perm[i] is the
 * triangle's vertex that becomes the pattern's vertex i, so that the triangle's edge (perm[k], perm[k+1]) has
 * level sorted[k]; returns true when perm is odd (a reflection: the pattern's triangles must then be drawn with
 * two indices swapped to keep the mesh's winding).  Ties keep the lower edge first (deterministic). */
bool core_lod_order(const int edge_levels[3], int sorted[3], int perm[3]);

/* A lazily filled cache of the patterns of sorted triples, bounded in memory: the patterns held take at most
 * max_bytes (counted as 12 bytes per point, 12 per triangle and 64 per entry; CORE_PATTERN_CACHE_DEFAULT_BYTES by
 * default), plus a fixed index of CORE_LOD_MAX_LEVEL^3 int32 (1 MiB).  When a new pattern does not fit, the
 * least recently used ones are evicted (the largest pattern, 64/64/64, takes about 75 KB, so a bound under that
 * still keeps the one pattern asked for).  Single-threaded: one cache per user. */
#define CORE_PATTERN_CACHE_DEFAULT_BYTES (16u << 20)
typedef struct core_pattern_cache core_pattern_cache;
/* A new empty cache (max_bytes 0: the default); NULL when out of memory. */
core_pattern_cache *core_pattern_cache_create(size_t max_bytes);
void core_pattern_cache_destroy(core_pattern_cache *c);
/* The pattern of sorted levels a <= b <= c (built on first use), valid until the next call on this cache; NULL
 * for unsorted or out-of-range levels or when out of memory. */
const core_grid *core_pattern_get(core_pattern_cache *c, int a, int b, int cl);
/* Bytes held now (by the bound's count), patterns built so far, patterns evicted so far. */
size_t core_pattern_cache_bytes(const core_pattern_cache *c);
size_t core_pattern_cache_built(const core_pattern_cache *c);
size_t core_pattern_cache_evicted(const core_pattern_cache *c);

/* ================================ outputs: the files of one run (core/output.c) ================================ */

/* The files one run writes succeed together or none is left.  outputs_add claims each target before any work:
 * it must be a regular file or absent (a symbolic link, a directory, a device, a FIFO or a socket is refused,
 * never replaced), its name within the folder's limit (NAME_MAX, 255 bytes on Linux), not the same file as an
 * earlier output of the run (same path or same inode), in an existing folder the process may write.  The first
 * write creates the output's temporary ".instess-XXXXXX.tmp" in that folder with mkstemp (O_EXCL, a random
 * name: a link planted at a predictable name is never followed).  Writers fill the temporaries
 * (outputs_write, or outputs_stream for stdio); every write is checked, EFBIG (`ulimit -f`, when
 * SIGXFSZ is ignored, as the program does) and ENOSPC included.  outputs_commit fsyncs every temporary, checks
 * each target again, and only then renames them onto their targets one by one; on any failure it calls
 * outputs_abort, which unlinks every temporary not yet renamed.  A target changes only by rename(2), so after
 * any signal, also SIGKILL, it holds the previous file or the complete new one; two processes writing the
 * same target leave one of the two complete files.  (After a failed rename of a second output the first one
 * has already been replaced: only a failure of rename(2) itself, after all writing succeeded, can do that.)
 * A run holds no file and no descriptor for its outputs until it writes them (after the import and the render).
 *
 * Signals: the temporaries' names sit in a fixed table from before each file exists;
 * outputs_remove_temp_files() unlinks them and is async-signal-safe (lock-free atomics and unlink(2)), for a
 * program's handlers of SIGTERM, SIGINT, SIGHUP, SIGQUIT, SIGXCPU (cli/main.c), which then die of the signal.
 * SIGKILL cannot be caught: a stale ".instess-*.tmp" may then remain.  At most 16 temporaries are tracked at
 * once (beyond that a file is written but not removed by a signal).
 * INSTESS_TEST_WRITE_DELAY_MS=N (at most 60000) makes outputs_commit wait N ms with every temporary complete
 * and none renamed, so that a test can signal the program in that window. */
#define IS_OUTPUTS_MAX 4
typedef struct is_output_file {
    const char *path;                      /* the target, as given (not copied: keep it alive) */
    char tmp[4096];                        /* its temporary file, "" when none */
    int fd, slot;                          /* open descriptor or -1; signal slot or -1 */
    bool renamed;                          /* the temporary is in place */
} is_output_file;
typedef struct is_outputs {
    int n;
    is_output_file f[IS_OUTPUTS_MAX];
} is_outputs;

void outputs_init(is_outputs *o);
/* Claim path as the next output (checks above; nothing is created yet); its index k >= 0, or -1 with a
 * message naming path.  Nothing else of o changes on failure (the caller still calls outputs_abort). */
int outputs_add(is_outputs *o, const char *path, char *err, size_t errlen);
/* Append n bytes to output k's temporary; 0 or -1 with a message naming the target. */
int outputs_write(is_outputs *o, int k, const void *buf, size_t n, char *err, size_t errlen);
/* A stdio stream appending to output k's temporary, or NULL; finish it with outputs_close_stream (0 or -1:
 * the first write error of the stream, named). */
FILE *outputs_stream(is_outputs *o, int k, char *err, size_t errlen);
int outputs_close_stream(is_outputs *o, int k, FILE *s, char *err, size_t errlen);
/* fsync every temporary, then rename each onto its target; 0, or -1 with a message (all temporaries gone). */
int outputs_commit(is_outputs *o, char *err, size_t errlen);
/* Remove every temporary not yet renamed and release its slot; safe to call twice or after a commit. */
void outputs_abort(is_outputs *o);
/* True if paths a and b name the same file: the same string, the same existing inode, or the same name in the
 * same folder after resolving the folders' links (for a usage check before any output is claimed). */
bool outputs_same_target(const char *a, const char *b);
/* Unlink every temporary of this process that exists now: async-signal-safe. */
void outputs_remove_temp_files(void);

/* ================================ images (core/image.c; files through OpenImageIO, core/image.cpp) ============ */

/* Two halves: core/image.c holds the pixels and writes files through the outputs above; the codec (encode into
 * memory, read, compare, text) is core/image_oiio.cpp, the only code that touches OpenImageIO, built as the
 * module libinstess_codec.so that core/image_codec.c opens on the first codec call (so a program that never
 * reads or writes an image never loads OpenImageIO's libraries).  The valgrind stage's build
 * (tests/valgrind/) links another codec with the same five functions in place of core/image_codec.c. */
#define IS_IMAGE_MAX_CHANNELS 32
#define IS_IMAGE_MAX_DIM 65536
typedef struct is_image {
    int width, height, channels;
    char channel_names[IS_IMAGE_MAX_CHANNELS][16];  /* "R", "G", "B", "A", "Z", "N.X", ... */
    float *data;  /* width*height*channels floats, row-major, top row first, colour in [0, 1] */
} is_image;

typedef struct is_image_meta {
    const char *software;     /* "instess 0.1.0" */
    const char *description;  /* what was rendered (the program stores scene_describe's canonical text) */
} is_image_meta;

/* The file formats image files are written in, chosen by the extension (case-insensitive). */
typedef enum is_image_format { IS_IMAGE_NONE, IS_IMAGE_PNG, IS_IMAGE_EXR } is_image_format;
/* The format of path's extension (.png, .exr), or IS_IMAGE_NONE. */
is_image_format image_format_of(const char *path);
/* 0 if path can name an image file (a known extension after a non-empty stem), else -1 with a message. */
int image_check_path(const char *path, char *err, size_t errlen);

/* The OpenImageIO version the codec module was built against (from the build; "unknown" if it was not told),
 * without loading the module. */
const char *image_codec_build_version(void);

/* Allocate an image with the given channel names (comma-separated, e.g. "R,G,B,A,Z"); 0 or -1. */
int image_alloc(is_image *img, int width, int height, const char *channel_names, char *err, size_t errlen);
void image_free(is_image *img);
/* Index of the channel called name, or -1. */
int image_channel_index(const is_image *img, const char *name);
/* Fill RGBA of img from packed RGBA8 pixels (alpha forced to 1 where opaque is asked). */
void image_from_rgba8(is_image *img, const uint32_t *rgba);
/* Encode img as fmt into a malloc'd buffer (*bytes, *len; free it): .png 8-bit RGBA (other channels dropped),
 * .exr RGBA half and other channels float; label names the file in messages.  0 or -1. */
int image_encode(const is_image *img, is_image_format fmt, const is_image_meta *meta, const char *label,
                 unsigned char **bytes, size_t *len, char *err, size_t errlen);
/* Encode img in the format of output k's path and write it into that output's temporary; 0 or -1. */
int image_write_output(is_outputs *o, int k, const is_image *img, const is_image_meta *meta, char *err,
                       size_t errlen);
/* Write one image file as a run of its own (outputs above): nothing is left at path on failure; 0 or -1. */
int image_write(const is_image *img, const char *path, const is_image_meta *meta, char *err, size_t errlen);
/* Read any file OpenImageIO reads into floats; 0 or -1. */
int image_read(is_image *img, const char *path, char *err, size_t errlen);

typedef struct is_image_diff {
    float max_error;        /* largest per-channel absolute difference */
    double mean_error;
    long n_fail, n_warn;    /* values above the fail / warn thresholds */
    long n_pixels;
    int max_x, max_y, max_channel;  /* where max_error is (the first such value) */
} is_image_diff;
/* Compare a and b (same size and channel count) through OpenImageIO; if diff_path is not NULL, also write a
 * visual diff image there.  Returns 0 when compared (see *res), -1 when they cannot be compared. */
int image_compare(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, is_image_diff *res,
                  const char *diff_path, char *err, size_t errlen);
/* Notes on the above (core/image.cpp): n_fail / n_warn count PIXELS (a pixel counts once however many of its
 * channels exceed the threshold); mean_error is over all values.  The diff image shows the dimmed first image
 * plus |a - b| scaled so the largest difference is full brightness; failing pixels red, warning yellow, from
 * 35% to full brightness by their largest difference over the image's largest (amplified).
 * image_read overwrites *img without freeing it (image_free an earlier image first).  PNG colour is stored as
 * given (unassociated alpha: no premultiplication either way), channels 8-bit k/255. */

/* The verdicts of image_check, which are also the exit codes of `instess compare` (2 is its usage error). */
typedef enum is_image_verdict {
    IS_IMAGE_PASS = 0,          /* identical, or within the thresholds */
    IS_IMAGE_DIFFERENT = 1,     /* more than fail_percent % of the pixels differ by more than fail_thresh */
    IS_IMAGE_SHAPE_DIFFERS = 3, /* width, height or channels (count or names) differ: not compared */
    IS_IMAGE_IO_ERROR = 4       /* an image cannot be read, or the diff image cannot be written */
} is_image_verdict;
/* The pixel-diff test of actual against reference, as the golden tests and `instess compare` run it: through
 * image_compare, a pixel fails when one of its channels differs by more than fail_thresh, and the test passes
 * when at most fail_percent percent of the pixels fail (0 and 0: any difference fails).  *res gets the counts
 * and the largest difference (zeroed when not compared).  On IS_IMAGE_DIFFERENT, if diff_path is not NULL,
 * the amplified diff image (see the notes above) is written there as a run of its own (image_write); nothing
 * is written otherwise.  Anything but IS_IMAGE_PASS / IS_IMAGE_DIFFERENT leaves the reason in err. */
is_image_verdict image_check(const is_image *actual, const is_image *reference, float fail_thresh,
                             float fail_percent, const char *diff_path, is_image_diff *res, char *err, size_t errlen);
/* The folder the codec module is installed in, as the Makefile compiled it in (LIBDIR/instess; see
 * core/image_codec.c for where the module is looked for). */
const char *image_codec_install_dir(void);
/* image_check of the image files a and b (read with image_read); IS_IMAGE_IO_ERROR names the unreadable one. */
is_image_verdict image_check_files(const char *a, const char *b, float fail_thresh, float fail_percent,
                                   const char *diff_path, is_image_diff *res, char *err, size_t errlen);

/* Text for diagrams, in DejaVu Sans (/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf), rendered by
 * OpenImageIO's render_text and composited "over" the channels R, G, B (and A if present) with colour rgba
 * (not premultiplied; rgba[3] is the opacity); other channels (Z, AOVs) are untouched.  (x, y) is the left end
 * of the first line's baseline; '\n' starts a new line size_px lower; size_px is rounded to whole pixels
 * (1..4096).  Text must be printable ASCII (OpenImageIO 2.4 draws other characters wrongly: write "alpha",
 * "b0").  Pixels outside the image are clipped.  Returns 0, or -1 with a message in err. */
int image_draw_text(is_image *img, int x, int y, const char *text, float size_px, const float rgba[4], char *err,
                    size_t errlen);
/* Width and height in pixels of the box that image_draw_text(text, size_px) covers (0 x 0 for ""); 0 or -1. */
int image_text_size(const char *text, float size_px, int *w, int *h);

#ifdef __cplusplus
}
#endif
#endif
