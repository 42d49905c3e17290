/* core/texture.h -- textures and samplers of the device (IDirect3DTexture9, SetTexture, SetSamplerState) and the
 * sampling functions a C shader calls (HLSL's tex2Dlod, tex2Dgrad, tex2Dbias).
 *
 * Conventions:
 *  - Names as core/device.h: CreateTexture -> dev_create_texture, IDirect3DTexture9::LockRect -> tex_lock_rect,
 *    D3DSAMP_MINFILTER -> IS_SAMP_MINFILTER, D3DTADDRESS_WRAP -> IS_TADDRESS_WRAP, D3DTEXF_LINEAR ->
 *    IS_TEXF_LINEAR, D3DFMT_A8R8G8B8 -> IS_FMT_A8R8G8B8 (core/device.h's is_format); every value equals D3D9's.
 *  - Ownership: a texture belongs to the device that created it.  dev_set_texture refuses a texture that is not
 *    one of the device's live textures (created by another device, or released); tex_release unbinds it from
 *    every sampler of its device; dev_destroy releases the textures still alive (do not release them after).
 *  - Levels: level l of a W x H texture is max(1, W >> l) x max(1, H >> l) texels, top row first, rows tightly
 *    packed (pitch = width * bytes per texel), in the format's D3D9 memory layout: A8R8G8B8 and X8R8G8B8 one
 *    little-endian DWORD 0xAARRGGBB per texel (bytes B, G, R, A), R32F one float, A32B32G32R32F four floats in
 *    the order R, G, B, A.
 *  - What a sample returns, float4 (r, g, b, a): A8R8G8B8 each byte / 255; X8R8G8B8 the same with a = 1; R32F
 *    (r, 1, 1, 1) (D3D9's rule for missing channels: Wine's d3d9 float_texture_test reads R32F 0.0 as 0x00ffff);
 *    A32B32G32R32F as stored.  An empty sampler (no texture) returns (0, 0, 0, 1).
 *  - Texel centres (D3D9, "Directly Mapping Texels to Pixels"): in texel units x = u * width, y = v * height of
 *    the level, texel (i, j) covers [i, i + 1) x [j, j + 1) and its centre is (i + 1/2, j + 1/2).  POINT takes
 *    texel (floor(x), floor(y)); LINEAR takes x' = x - 1/2, y' = y - 1/2 and blends texels floor(x')..floor(x')+1
 *    (and in y) with weights frac(x'), frac(y').  The address modes act on those integer texel indices: WRAP
 *    i mod width, MIRROR reflects every width texels, CLAMP clamps to 0..width-1, BORDER gives BORDERCOLOR for a
 *    texel outside 0..width-1 (before blending), MIRRORONCE mirrors once about 0 and then clamps; an unknown
 *    value wraps (as DXVK decodes it).  Coordinates beyond +-2^30 texels act as +-2^30 and NaN as 0.
 *  - Level of detail: lambda = lod + MIPMAPLODBIAS (tex2Dlod: lod = t.w; tex2Dgrad: lod = log2 of the longer of
 *    the two screen-axis footprints (du/dx width, dv/dx height) and (du/dy width, dv/dy height) of level 0;
 *    tex2Dbias adds t.w to that).  The filter within a level is MINFILTER when lambda > 0, else MAGFILTER
 *    (NONE and POINT are point sampling, every other value LINEAR, as DXVK decodes them).  MIPFILTER NONE
 *    samples level 0 (MAXMIPLEVEL is then ignored: Wine's d3d9 maxmip_test).  Otherwise lambda is clamped to
 *    [MAXMIPLEVEL, last level] (a MAXMIPLEVEL past the chain samples the last level: maxmip_test): POINT takes
 *    level ceil(lambda + 1/2) - 1 (the nearest, halves down, as Vulkan and OpenGL select it), LINEAR (and any
 *    other value) blends levels floor(lambda) and floor(lambda) + 1 by frac(lambda).  A NaN lambda reads as 0.
 *    MIPMAPLODBIAS applies to tex2Dlod too (texldl; DXVK passes it to the Vulkan sampler, which adds it to an
 *    explicit LOD).
 *  - Exactness: scalar float code in a fixed order (no FMA: the library is built with -ffp-contract=off, and the
 *    LOD's logarithm is computed here, not by libm), so a sample is the same bits for any thread count and ISA.
 *    Weights are the exact float fractions (hardware rounds them to 8 or more bits).
 *  - Errors: functions that take a device or texture return IS_OK or a negative IS_ERR_* with a message in
 *    dev_last_error of the (texture's) device, and an invalid call changes nothing.  As the D3D9 runtime does,
 *    SetTexture and SetSamplerState on a sampler index that does not exist return IS_OK and do nothing, and
 *    SetSamplerState stores any value (sampling decodes unknown ones as said above).  A NULL device, texture or
 *    output is IS_ERR_INVALIDCALL (tex_get_level_count: 0), a NULL sampler samples as an empty one
 *    (tests/test_api_texture.c walks every function).
 */
#ifndef INSTESS_CORE_TEXTURE_H
#define INSTESS_CORE_TEXTURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "api.h"
#include "device.h"
#include "math.h"

#ifdef __cplusplus
extern "C" {
#endif

/* --- sampler indices (SetTexture / SetSamplerState's first argument) --- */
#define IS_MAX_PS_SAMPLERS 16                  /* pixel samplers 0..15 */
#define IS_DMAPSAMPLER 256u                    /* D3DDMAPSAMPLER */
#define IS_VERTEXTEXTURESAMPLER0 257u          /* D3DVERTEXTEXTURESAMPLER0..3 = D3DDMAPSAMPLER + 1..4 */
#define IS_VERTEXTEXTURESAMPLER(k) (IS_VERTEXTEXTURESAMPLER0 + (unsigned)(k))
/* (IS_MAX_VS_SAMPLERS, the sampler states is_samp and is_sampler, which the vertex shader reads, are in
 * core/device.h.) */

/* --- sampler state values --- */
enum { IS_TADDRESS_WRAP = 1, IS_TADDRESS_MIRROR = 2, IS_TADDRESS_CLAMP = 3, IS_TADDRESS_BORDER = 4,
       IS_TADDRESS_MIRRORONCE = 5 };
enum { IS_TEXF_NONE = 0, IS_TEXF_POINT = 1, IS_TEXF_LINEAR = 2, IS_TEXF_ANISOTROPIC = 3 };
/* Defaults (D3D9's): ADDRESSU/V/W WRAP, BORDERCOLOR 0x00000000, MAG/MINFILTER POINT, MIPFILTER NONE,
 * MIPMAPLODBIAS 0.0f (as its bits), MAXMIPLEVEL 0, MAXANISOTROPY 1, SRGBTEXTURE 0, ELEMENTINDEX 0,
 * DMAPOFFSET 0.  SRGBTEXTURE, MAXANISOTROPY, ELEMENTINDEX, DMAPOFFSET and ADDRESSW are stored, not used. */

/* --- usage and locking --- */
#define IS_USAGE_DYNAMIC 0x200u          /* D3DUSAGE_DYNAMIC: accepted (all memory here is the CPU's) */
#define IS_USAGE_AUTOGENMIPMAP 0x400u    /* D3DUSAGE_AUTOGENMIPMAP: one level shown, sublevels generated */
#define IS_LOCK_READONLY 0x10u           /* D3DLOCK_READONLY: the unlock regenerates nothing */
#define IS_MAX_TEXTURE_SIZE 16384        /* width and height 1..16384 */
#define IS_MAX_TEXTURE_LEVELS 15         /* a 16384-texel side has 15 levels */

typedef struct is_locked_rect { int pitch; void *bits; } is_locked_rect; /* D3DLOCKED_RECT */
typedef struct is_texture_desc {                                         /* D3DSURFACE_DESC, the fields kept */
    is_format format;
    uint32_t usage;
    unsigned width, height;
} is_texture_desc;

/* CreateTexture: a width x height texture of `levels` levels (0: the whole chain down to 1 x 1) in one of the
 * formats A8R8G8B8, X8R8G8B8, R32F, A32B32G32R32F (IS_ERR_NOTAVAILABLE for others), usage 0, DYNAMIC and / or
 * AUTOGENMIPMAP (levels 0 or 1: the whole chain is kept, one level shown), and RENDERTARGET (A8R8G8B8 or X8R8G8B8
 * only; not lockable; core/device.h, "render targets and surfaces").  Texels start zero. */
INSTESS_API is_result dev_create_texture(is_device *dev, unsigned width, unsigned height, unsigned levels,
                                         uint32_t usage, is_format format, is_texture **out);
/* Release a texture (NULL: nothing): unbound from its device's samplers, its memory freed. */
INSTESS_API void tex_release(is_texture *tex);
/* GetLevelCount (1 for an AUTOGENMIPMAP texture), GetLevelDesc. */
INSTESS_API unsigned tex_get_level_count(const is_texture *tex);
INSTESS_API is_result tex_get_level_desc(const is_texture *tex, unsigned level, is_texture_desc *out);
/* LockRect(level, rect or NULL for the whole level, flags): the level's memory at the rect's first texel; a
 * level is locked once at a time.  UnlockRect: of an AUTOGENMIPMAP texture's level 0 (not locked READONLY), the
 * sublevels are generated again (GenerateMipSubLevels). */
INSTESS_API is_result tex_lock_rect(is_texture *tex, unsigned level, is_locked_rect *out, const is_rect *rect,
                                    uint32_t flags);
INSTESS_API is_result tex_unlock_rect(is_texture *tex, unsigned level);
/* GenerateMipSubLevels: an AUTOGENMIPMAP texture's levels 1.. from level 0 by the box filter below; nothing for
 * other textures (as D3D9). */
INSTESS_API void tex_generate_mip_sub_levels(is_texture *tex);
/* D3DXFilterTexture with D3DX_FILTER_BOX: levels 1.. of any texture from level 0.  Texel (i, j) of level l + 1
 * is the mean of texels (2i + a, 2j + b), a, b in {0, 1}, of level l, indices clamped to level l (a side of 1
 * repeats its texel; an odd side drops its last texel); 8-bit channels as (sum + 2) / 4 in integers, floats as
 * ((t00 + t10) + (t01 + t11)) * 0.25.  IS_ERR_INVALIDCALL while a level is locked. */
INSTESS_API is_result tex_filter_texture(is_texture *tex);

/* SetTexture(sampler, tex or NULL) and GetTexture; sampler 0..15, IS_DMAPSAMPLER, IS_VERTEXTEXTURESAMPLER0..3. */
INSTESS_API is_result dev_set_texture(is_device *dev, unsigned sampler, is_texture *tex);
INSTESS_API is_result dev_get_texture(const is_device *dev, unsigned sampler, is_texture **out);
/* SetSamplerState / GetSamplerState (an unknown sampler reads 0, as the runtime). */
INSTESS_API is_result dev_set_sampler_state(is_device *dev, unsigned sampler, is_samp type, uint32_t value);
INSTESS_API is_result dev_get_sampler_state(const is_device *dev, unsigned sampler, is_samp type, uint32_t *value);
/* A sampler with D3D9's default states and texture tex (for tests and for shaders called outside a device). */
INSTESS_API is_sampler tex_sampler_default(const is_texture *tex);

/* --- sampling (the rules of the conventions above) --- */
/* tex2Dlod(s, t): t.xy the coordinates, t.w the level of detail. */
INSTESS_API float4 tex_sample_lod(const is_sampler *s, float4 t);
/* tex2Dgrad(s, uv, ddx, ddy): the level of detail from the coordinates' screen derivatives. */
INSTESS_API float4 tex_sample_grad(const is_sampler *s, float2 uv, float2 ddx, float2 ddy);
/* tex2Dbias(s, t) with the derivatives of t.xy: tex2Dgrad's level of detail plus t.w. */
INSTESS_API float4 tex_sample_bias(const is_sampler *s, float4 t, float2 ddx, float2 ddy);
/* The level of detail tex_sample_grad uses for a texture of level-0 size width x height (before the bias and
 * the clamps): log2 of the longer footprint, -infinity for a zero footprint. */
INSTESS_API float tex_lod_from_gradients(unsigned width, unsigned height, float2 ddx, float2 ddy);
/* log2(x) as this module computes it (exact at powers of two, within 2 ulp elsewhere, the same bits on every
 * CPU): -infinity for 0, NaN for negative or NaN x. */
INSTESS_API float tex_log2(float x);

/* --- images (D3DXCreateTextureFromFileEx) --- */
struct is_image; /* image/image.h */
/* A texture of `format` with `levels` levels (0: the whole chain) made from an image file that OpenImageIO reads
 * (PNG, BMP, TGA, EXR, ...), its level 0 the image (top row first), the other levels by tex_filter_texture.
 * Channels: R, G, B, A by name; an image of one channel is grey (r = g = b = that channel); missing alpha is 1.
 * 8-bit formats store round(clamp(value, 0, 1) * 255) (PNG, BMP and TGA values come back exactly); the float
 * formats store the values as read (EXR's linear values).  A failure's message names the file. */
INSTESS_API is_result dev_create_texture_from_file(is_device *dev, const char *path, is_format format, unsigned levels,
                                                   is_texture **out);
/* The same from an image in memory (image/image.h's is_image, as image_read gives it). */
INSTESS_API is_result dev_create_texture_from_image(is_device *dev, const struct is_image *img, is_format format,
                                                    unsigned levels, is_texture **out);

#ifdef __cplusplus
}
#endif
#endif
