/* core/pixel.h -- the pixel stage of the device: pixel shaders as C functions (IDirect3DDevice9::SetPixelShader,
 * SetPixelShaderConstantF) and the texture reads they make (tex2D, tex2Dbias, tex2Dlod of ps_3_0).
 *
 * Conventions:
 *  - A pixel shader runs on a 2x2 quad of pixels (raster/raster.h, rs_ps_quad): its input holds, per lane, the
 *    vertex shader's outputs COLOR0, COLOR1 and TEXCOORD0..7 interpolated as D3D9 interpolates them (perspective-
 *    correct; COLOR0/1 constant with SHADEMODE FLAT), vPos (the pixel: D3D9's centres are integers) and vFace
 *    (front: clockwise on screen); it writes oC0 per lane (saturated to 8 bits in the target), may write oDepth,
 *    and may kill lanes (texkill / clip).  Derivatives are the quad's lane differences: ddx = lane 1 - lane 0,
 *    ddy = lane 2 - lane 0 (coarse, as D3D9 hardware), defined on edge pixels too (helper lanes).
 *  - Inputs read: a D3D9 pixel shader declares its inputs (dcl_texcoord0 ...); a C function cannot, so every slot
 *    the vertex shader writes is interpolated for every lane.  is_pixel_shader.inputs may list the slots main reads
 *    (bit k: slot k, as rs_ps_quad.v's index); the others are then not interpolated and read (0, 0, 0, 0), which
 *    saves the interpolation's work.  0 (the default, e.g. an initializer that leaves it out) reads every slot.
 *  - After the shader: alpha test, stencil, depth test and write, blending, colour write mask, as without one.
 *    Without a pixel shader (NULL, the default) the pixel colour is COLOR0: the fixed path, byte for byte.
 *  - Constants: c0..c223 (ps_3_0's float constants), zero after dev_create and dev_reset.  Samplers s0..s15 are
 *    the device's pixel samplers (dev_set_texture / dev_set_sampler_state with sampler 0..15, core/texture.h).
 *  - Sampling: ps_tex2D(s, uv, k) is lane k's tex2D: the level of detail from the quad's derivatives of uv
 *    (tex_sample_grad), so a quad's lanes agree on it.  Same bytes for any thread count and ISA.  ps_tex2D_quad
 *    samples several lanes of a quad at once with the same values, computing that level of detail once.
 *  - Errors: IS_OK or IS_ERR_INVALIDCALL (NULL device, constants out of c0..c223, NULL data with a count), with a
 *    message in dev_last_error; a refused call changes nothing.
 */
#ifndef INSTESS_PIXEL_H
#define INSTESS_PIXEL_H

#include "api.h"
#include "device.h"
#include "texture.h"

#ifdef __cplusplus
extern "C" {
#endif

#define IS_MAX_PS_CONSTANTS 224

typedef rs_ps_quad is_ps_input;
typedef rs_ps_out is_ps_output;
typedef struct is_ps_constants {
    float4 c[IS_MAX_PS_CONSTANTS];
    const is_sampler *s;        /* s0..s15: the device's pixel samplers */
} is_ps_constants;
/* A pixel shader's body: out is zeroed before the call; called from several threads at once. */
typedef void (*is_ps_fn)(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out);
typedef struct is_pixel_shader {
    const char *name;
    is_ps_fn main;
    uint32_t inputs;   /* the input slots main reads, bit k: slot k (1u << (RS_ATTR_TEXCOORD0 + n): TEXCOORDn);
                          0 (the default): every slot.  An extension of instess: the others read (0, 0, 0, 0) */
} is_pixel_shader;

/* SetPixelShader (NULL: the fixed path) and GetPixelShader. */
INSTESS_API is_result dev_set_pixel_shader(is_device *dev, const is_pixel_shader *ps);
INSTESS_API is_result dev_get_pixel_shader(const is_device *dev, const is_pixel_shader **ps);
/* SetPixelShaderConstantF / GetPixelShaderConstantF: count4 float4 registers from c[start]. */
INSTESS_API is_result dev_set_pixel_shader_constant_f(is_device *dev, unsigned start, const float *data, unsigned count4);
INSTESS_API is_result dev_get_pixel_shader_constant_f(const is_device *dev, unsigned start, float *data,
                                                      unsigned count4);
/* tex2D(s, uv[k]) in lane k of a quad whose lanes read uv[0..3]; tex2Dbias adds bias to the level of detail. */
INSTESS_API float4 ps_tex2D(const is_sampler *s, const float2 uv[4], int k);
INSTESS_API float4 ps_tex2Dbias(const is_sampler *s, const float2 uv[4], float bias, int k);
/* tex2D(s, uv[k]) into out[k] for every lane k of the mask `lanes` (bit k; the other out[k] untouched): the
 * values of ps_tex2D(s, uv, k), with the level of detail -- the same for the quad's four lanes -- computed once.
 * NULL out: nothing; NULL uv, sampler or texture: (0, 0, 0, 1) per lane. */
INSTESS_API void ps_tex2D_quad(const is_sampler *s, const float2 uv[4], unsigned lanes, float4 out[4]);

#ifdef __cplusplus
}
#endif
#endif
