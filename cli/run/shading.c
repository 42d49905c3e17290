/* cli/run/shading.c -- --shading pixel and --texture: the pixel shaders of a render (core/pixel.h).
 *
 * The listings light each grid vertex and let the rasterizer interpolate the colour (Gouraud): between grid
 * points the N-Patch's creases and ripples blur.  With --shading pixel the patch shader runs as before (positions,
 * and the outputs the pixel shader reads: TEXCOORD2 = the grid point's barycentrics b, TEXCOORD3 = the instance,
 * the mesh triangle's index), and a pixel shader evaluates, at every pixel, the patch's own normal of --normals at
 * the pixel's barycentrics (b interpolated perspective-correct across the grid triangle) and lights it with the
 * scene's light -- for real normals the derivative normal of the patch at that point, not an interpolated vertex
 * normal.  The pixel shader reads the mesh triangle's registers (Listing 1.1.2's per-instance data, as the vertex
 * shader fetches them from stream 1) from a float texture, the D3D9 way of giving a pixel shader per-instance
 * data: texel (instance % PER_ROW) * REGS + r, row instance / PER_ROW holds register r (A32B32G32R32F, point
 * sampling at texel centres, so the floats come back exactly).
 *
 * --texture FILE multiplies the colour (the vertex shader's, or the per-pixel light) by the image at the patch's
 * texture coordinates (TEXCOORD0, the mesh's own, D3D's origin at the top left), sampled from pixel sampler 1
 * with a mip chain, trilinear filtering and wrapping, the level of detail from the quad's derivatives.
 *
 * Constants of the pixel shader: c0..c11 as the vertex shader's (vs.h and lighting.c: matrices, diffuse colour,
 * options, light), c12.x the patch, c12.y 1 when a texture is bound. */
#include "scene.h"

#include "../../core/hlsl.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define REGS IS_VS_INPUT_REGS          /* registers per instance: all of is_vs_input */
#define PER_ROW (4096 / REGS)          /* instances per texture row */
#define C_PATCH 12                     /* c12.x: the patch (vs_patch) */

const char *const scene_shading_names[] = {"vertex", "pixel", NULL};

/* Centre of the texel of register r of instance id in a w x h texture, in texture coordinates (tex2Dlod's). */
static float4 texel_of(uint32_t id, int r, unsigned w, unsigned h)
{
    unsigned x = (id % PER_ROW) * REGS + (unsigned)r, y = id / PER_ROW;
    return f4(((float)x + 0.5f) / (float)w, ((float)y + 0.5f) / (float)h, 0.0f, 0.0f);
}

/* The mesh triangle whose registers a quad's lanes fetched last: a quad is one grid triangle's, so all its lanes
 * (helpers too: the instance id is constant over the triangle) name one instance and it is fetched once per call;
 * the id check keeps a caller that mixed instances correct. */
typedef struct lit_cache {
    bool valid;
    uint32_t id;
    vs_triangle tri;
} lit_cache;

/* Lane k's colour: the patch normal at the lane's barycentrics, in the world, lit; the instance's triangle from
 * *cache when it holds the lane's instance (the same registers, fetched once per quad). */
static float4 lit_lane(const is_ps_constants *c, const is_ps_input *in, int k, vs_patch p, const vs_options *o,
                       const float4x4 *world, lit_cache *cache)
{
    const is_sampler *s = &c->s[0];
    float4 bb = in->v[k][RS_ATTR_TEXCOORD0 + VS_OUT_BARY];
    float sum = bb.x + bb.y + bb.z;
    float3 b = sum > 0.0f ? f3(bb.x / sum, bb.y / sum, bb.z / sum) : f3(1.0f / 3, 1.0f / 3, 1.0f / 3);
    float id = in->v[k][RS_ATTR_TEXCOORD0 + VS_OUT_INSTANCE].x;
    uint32_t i = id > 0.0f ? (uint32_t)(id + 0.5f) : 0u;   /* the same at all three vertices: rounding is exact */
    if (!cache->valid || cache->id != i) {
        is_texture_desc d = {0};
        if (!s->tex || tex_get_level_desc(s->tex, 0, &d) != IS_OK) return f4(0, 0, 0, 1);
        is_vs_input regs;
        float4 *r = (float4 *)&regs;
        for (int q = 0; q < REGS; q++) r[q] = tex_sample_lod(s, texel_of(i, q, d.width, d.height));
        vs_triangle_from_input(&regs, &cache->tri);
        cache->valid = true, cache->id = i;
    }
    float3 normal;
    vs_patch_eval(p, &cache->tri, b, o, NULL, &normal, NULL);
    return scene_light_color(c->c, mul3x3(normal, world));
}

/* oC0 *= tex2D(s1, TEXCOORD0) in the lanes used (D3DTOP_MODULATE), when c12.y says a texture is bound; the
 * coordinates of all four lanes give the level of detail. */
static void modulate(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out)
{
    if (c->c[C_PATCH].y == 0.0f) return;
    float2 uv[4];
    for (int k = 0; k < 4; k++) uv[k] = f2(in->v[k][RS_ATTR_TEXCOORD0].x, in->v[k][RS_ATTR_TEXCOORD0].y);
    for (int k = 0; k < 4; k++) {
        if (!(in->need & (1u << k))) continue;
        float4 t = ps_tex2D(&c->s[SCENE_TEXTURE_SAMPLER], uv, k);
        out->color[k] = f4(out->color[k].x * t.x, out->color[k].y * t.y, out->color[k].z * t.z, out->color[k].w);
    }
}

/* The pixel shader of --shading pixel: the lanes the rasterizer uses, lit per pixel (times the texture). */
static void ps_patch_lit(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out)
{
    vs_patch p = (vs_patch)(int)c->c[C_PATCH].x;
    vs_options o = vs_options_from_register(c->c[VS_C_OPTIONS]);
    float4x4 world;
    for (int i = 0; i < 4; i++) world.m[i][0] = c->c[VS_C_WORLD + i].x, world.m[i][1] = c->c[VS_C_WORLD + i].y,
                                world.m[i][2] = c->c[VS_C_WORLD + i].z, world.m[i][3] = c->c[VS_C_WORLD + i].w;
    lit_cache cache;
    cache.valid = false;
    for (int k = 0; k < 4; k++)
        if (in->need & (1u << k)) out->color[k] = lit_lane(c, in, k, p, &o, &world, &cache);
    modulate(c, in, out);
}
/* Its inputs: the barycentrics and the instance (lit_lane), the texture coordinates (modulate). */
static const is_pixel_shader patch_lit = {"patch-lit", ps_patch_lit,
                                          (1u << RS_ATTR_TEXCOORD0) | (1u << (RS_ATTR_TEXCOORD0 + VS_OUT_BARY)) |
                                              (1u << (RS_ATTR_TEXCOORD0 + VS_OUT_INSTANCE))};

/* The pixel shader of --texture with --shading vertex: COLOR0 (the vertex shader's light) times the texture. */
static void ps_textured(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out)
{
    for (int k = 0; k < 4; k++) out->color[k] = in->v[k][RS_ATTR_COLOR0];
    modulate(c, in, out);
}
/* Its inputs: COLOR0 and the texture coordinates. */
static const is_pixel_shader textured = {"textured", ps_textured, (1u << RS_ATTR_COLOR0) | (1u << RS_ATTR_TEXCOORD0)};

void scene_shading_constants(is_device *dev, const scene_opts *o)
{
    float c[4 * (C_PATCH + 1)];
    if (dev_get_vertex_shader_constant_f(dev, 0, c, C_PATCH) != IS_OK) return;
    c[4 * C_PATCH] = (float)o->patch, c[4 * C_PATCH + 1] = o->texture ? 1.0f : 0.0f;
    c[4 * C_PATCH + 2] = c[4 * C_PATCH + 3] = 0.0f;
    dev_set_pixel_shader_constant_f(dev, 0, c, C_PATCH + 1);
}

is_result scene_texture_bind(is_device *dev, const scene_opts *o, is_texture **tex)
{
    *tex = NULL;   /* with its mip chain; read here when the caller did not read it first (the device says why not) */
    is_result e = o->texture_map ? dev_create_texture_from_image(dev, o->texture_map, IS_FMT_A8R8G8B8, 0, tex)
                                 : dev_create_texture_from_file(dev, o->texture, IS_FMT_A8R8G8B8, 0, tex);
    if (e == IS_OK) e = dev_set_texture(dev, SCENE_TEXTURE_SAMPLER, *tex);
    static const struct { is_samp state; uint32_t value; } states[] = {
        {IS_SAMP_MINFILTER, IS_TEXF_LINEAR}, {IS_SAMP_MAGFILTER, IS_TEXF_LINEAR}, {IS_SAMP_MIPFILTER, IS_TEXF_LINEAR},
        {IS_SAMP_ADDRESSU, IS_TADDRESS_WRAP}, {IS_SAMP_ADDRESSV, IS_TADDRESS_WRAP}};
    for (size_t k = 0; e == IS_OK && k < sizeof states / sizeof states[0]; k++)
        e = dev_set_sampler_state(dev, SCENE_TEXTURE_SAMPLER, states[k].state, states[k].value);
    if (e == IS_OK && o->shading == SCENE_SHADING_VERTEX) e = dev_set_pixel_shader(dev, &textured);
    if (e != IS_OK) tex_release(*tex), *tex = NULL;
    return e;
}

is_result scene_shading_bind(is_device *dev, const scene_opts *o, const is_mesh *m, is_texture **tex)
{
    *tex = NULL;
    size_t n = m->n_triangles;
    unsigned w = PER_ROW * REGS, h = (unsigned)((n + PER_ROW - 1) / PER_ROW);
    if (h == 0) h = 1;
    if (h > IS_MAX_TEXTURE_SIZE) return IS_ERR_INVALIDCALL;
    is_patch_instance *inst = malloc(n * sizeof *inst);
    float3 (*nadj)[3][2] = o->patch == VS_PATCH_PN_AEN ? malloc(n * sizeof *nadj) : NULL;
    is_result e = inst && (o->patch != VS_PATCH_PN_AEN || nadj) ? IS_OK : IS_ERR_OUTOFMEMORY;
    if (e == IS_OK) mesh_build_instances(m, inst);
    if (e == IS_OK && nadj && tess_adjacent_normals(m, nadj) != 0) e = IS_ERR_OUTOFMEMORY;
    if (e == IS_OK) e = dev_create_texture(dev, w, h, 1, 0, IS_FMT_A32B32G32R32F, tex);
    is_locked_rect lr;
    if (e == IS_OK) e = tex_lock_rect(*tex, 0, &lr, NULL, 0);
    if (e == IS_OK) {
        for (size_t i = 0; i < n; i++) {
            is_vs_input in;
            tess_input_from_instance(&inst[i], nadj ? (const float3 (*)[2])nadj[i] : NULL, f3(0, 0, 0), &in);
            unsigned char *row = (unsigned char *)lr.bits + (size_t)(i / PER_ROW) * (size_t)lr.pitch;
            memcpy(row + (i % PER_ROW) * REGS * sizeof(float4), &in, REGS * sizeof(float4));
        }
        e = tex_unlock_rect(*tex, 0);
    }
    free(inst);
    free(nadj);
    if (e == IS_OK) e = dev_set_texture(dev, 0, *tex);
    for (int k = 0; e == IS_OK && k < 3; k++)   /* point sampling of level 0: the registers' floats exactly */
        e = dev_set_sampler_state(dev, 0, k == 0 ? IS_SAMP_MINFILTER : k == 1 ? IS_SAMP_MAGFILTER : IS_SAMP_MIPFILTER,
                                  k == 2 ? IS_TEXF_NONE : IS_TEXF_POINT);
    if (e == IS_OK) e = dev_set_pixel_shader(dev, &patch_lit);
    if (e != IS_OK) tex_release(*tex), *tex = NULL;
    return e;
}
