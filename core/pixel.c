/* core/pixel.c -- the device's pixel stage (core/pixel.h): SetPixelShader, its constants, and the rasterizer's
 * call of the shader (dev_ps_run, which rs_state.ps points at while a pixel shader is set). */
#include "device_internal.h"

#include <string.h>

void dev_ps_run(const void *ctx, const rs_ps_quad *q, rs_ps_out *out)
{
    const is_device *dev = ctx;
    dev->ps->main(&dev->ps_consts, q, out);
}

is_result dev_set_pixel_shader(is_device *dev, const is_pixel_shader *ps)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (ps && !ps->main) return dev_fail(dev, IS_ERR_INVALIDCALL, "SetPixelShader: a shader without a main function");
    if (dev->recording) dev->recording->ps = ps, dev->recording->has_ps = true;   /* into the stateblock recorded */
    else dev->ps = ps;
    return IS_OK;
}

is_result dev_get_pixel_shader(const is_device *dev, const is_pixel_shader **ps)
{
    if (!dev_live(dev) || !ps) return IS_ERR_INVALIDCALL;
    *ps = dev->ps;
    return IS_OK;
}

/* Whether registers c[start .. start + count4) exist (and data is there when count4 > 0). */
static bool registers_ok(unsigned start, const void *data, unsigned count4)
{
    return (data || count4 == 0) && start <= IS_MAX_PS_CONSTANTS && count4 <= IS_MAX_PS_CONSTANTS - start;
}

is_result dev_set_pixel_shader_constant_f(is_device *dev, unsigned start, const float *data, unsigned count4)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!registers_ok(start, data, count4))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetPixelShaderConstantF: %u registers from c%u: out of c0..c%d%s",
                        count4, start, IS_MAX_PS_CONSTANTS - 1, data ? "" : " (or no data)");
    if (!count4) return IS_OK;
    if (dev->recording) {   /* into the stateblock recorded */
        memcpy(&dev->recording->pc[start], data, count4 * sizeof(float4));
        for (unsigned k = 0; k < count4; k++) dev->recording->has_pc[start + k] = true;
    } else {
        memcpy(&dev->ps_consts.c[start], data, count4 * sizeof(float4));
    }
    return IS_OK;
}

is_result dev_get_pixel_shader_constant_f(const is_device *dev, unsigned start, float *data, unsigned count4)
{
    if (!dev_live(dev) || !registers_ok(start, data, count4)) return IS_ERR_INVALIDCALL;
    if (count4) memcpy(data, &dev->ps_consts.c[start], count4 * sizeof(float4));
    return IS_OK;
}

float4 ps_tex2D(const is_sampler *s, const float2 uv[4], int k)
{
    return ps_tex2Dbias(s, uv, 0.0f, k);
}

float4 ps_tex2Dbias(const is_sampler *s, const float2 uv[4], float bias, int k)
{
    if (!uv || k < 0 || k > 3) return (float4){0, 0, 0, 1};
    float2 ddx = {uv[1].x - uv[0].x, uv[1].y - uv[0].y}, ddy = {uv[2].x - uv[0].x, uv[2].y - uv[0].y};
    return tex_sample_bias(s, (float4){uv[k].x, uv[k].y, 0.0f, bias}, ddx, ddy);
}

void ps_tex2D_quad(const is_sampler *s, const float2 uv[4], unsigned lanes, float4 out[4])
{
    if (!out) return;
    if (!uv || !s || !s->tex) {   /* as ps_tex2D: (0, 0, 0, 1) */
        for (int k = 0; k < 4; k++)
            if (lanes & (1u << k)) out[k] = (float4){0, 0, 0, 1};
        return;
    }
    float2 ddx = {uv[1].x - uv[0].x, uv[1].y - uv[0].y}, ddy = {uv[2].x - uv[0].x, uv[2].y - uv[0].y};
    /* tex_sample_bias's level of detail with bias 0 (ps_tex2D's), the same float operations */
    float lod = tex_lod_from_gradients(s->tex->lv[0].w, s->tex->lv[0].h, ddx, ddy) + 0.0f;
    for (int k = 0; k < 4; k++)
        if (lanes & (1u << k)) out[k] = tex_sample_lod(s, (float4){uv[k].x, uv[k].y, 0.0f, lod});
}
