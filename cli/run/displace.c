/* cli/run/displace.c -- --displace FILE --displace-scale S: every patch moved along its normal by a height that
 * the vertex shader fetches from a texture at its texture coordinates (Shader Model 3's vertex texture fetch:
 * core/texture.h, sampler D3DVERTEXTEXTURESAMPLER0), as a wrapper around the shader that draws the scene (the
 * patch's own, the fixed shader of the N-patch-mode and CPU paths, or the light's wrapper), so the patch shaders
 * stay as listed and a render without --displace keeps its bytes.
 *
 * The wrapper: the inner shader's outputs, then h = tex2Dlod(s0, float4(oTex.u, oTex.v, 0, 0)).r (TEXCOORD0) and
 * oPos += S h mul(float4(n, 0), View * Proj), n the unit world-space normal the inner shader wrote to TEXCOORD1.
 * The scene's world matrix turns the object scaled to a unit bounding radius, so this is the object-space point
 * moved by S h bounding radii along its normal: S is in bounding radii, h the map's red channel (a grey image:
 * its value; PNG 0..1).  Normals and lighting stay the undisplaced patch's.
 * The map: an R32F texture of one level, LINEAR minification and magnification, WRAP in u and v (a tiling map
 * joins at u = 0 and 1), so the height is continuous in the texture coordinates.
 * Cracks: two triangles sharing an edge give its points the same oPos, TEXCOORD0 and TEXCOORD1 bits when their
 * texture coordinates and normals agree there (vs/vs.h: positions always; linear and quadratic normals; texture
 * coordinates b0 t0 + b1 t1 + b2 t2 from the grid's mirrored barycentrics), so the displaced points agree too and
 * the surface stays closed.  Where a texture seam gives an edge two sets of texture coordinates, or where real
 * normals differ on the two sides, the two sides move apart (docs/design.md counts those cracks).
 * Constant registers: c12.x = the inner shader (scene_shader_index), c12.y = S, c13..c16 = View * Proj. */
#include "scene.h"

#include "../../core/hlsl.h"
#include <stdio.h>
#include <string.h>

enum { C_DISPLACE = 12, C_VIEWPROJ = 13 };

void scene_displace_apply(const is_vs_constants *c, is_vs_output *out)
{
    float4 t = out->attr[RS_ATTR_TEXCOORD0];
    float h = tex2Dlod(&c->s[0], f4(t.x, t.y, 0.0f, 0.0f)).x;
    float4x4 vp = vs_const_matrix(c, C_VIEWPROJ);
    float4 d = mul4(f4_of(f3_of(out->attr[RS_ATTR_TEXCOORD0 + 1]), 0.0f), &vp);
    float s = c->c[C_DISPLACE].y * h;
    out->pos = f4(out->pos.x + s * d.x, out->pos.y + s * d.y, out->pos.z + s * d.z, out->pos.w + s * d.w);
}

/* The inner shader of c12.x, then the displacement. */
static void vs_displaced(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    scene_shader_at((int)c->c[C_DISPLACE].x)->main(c, in, out);
    scene_displace_apply(c, out);
}
static const is_vertex_shader displaced_shader = {.name = "displaced", .main = vs_displaced, .outputs = VS_OUTPUTS};

const is_vertex_shader *scene_displace_shader(const scene_opts *o, const is_vertex_shader *inner)
{
    return o->displace && scene_shader_index(inner) >= 0 ? &displaced_shader : inner;
}

int scene_load_displacement(const char *path, is_image *img, char *err, size_t errlen)
{
    char why[512];
    if (image_read(img, path, why, sizeof why) != 0)
        return snprintf(err, errlen, "--displace: %s", why), -1;
    if (img->width > IS_MAX_TEXTURE_SIZE || img->height > IS_MAX_TEXTURE_SIZE) {
        snprintf(err, errlen, "--displace: %s: %dx%d texels: a texture's sides are 1..%d", path, img->width,
                 img->height, IS_MAX_TEXTURE_SIZE);
        image_free(img);
        return -1;
    }
    return 0;
}

is_result scene_displace_bind(is_device *dev, const scene_opts *o, const float4x4 *view_proj,
                              const is_vertex_shader *inner, is_texture **tex)
{
    is_result e;
    if (o->displace_map) e = dev_create_texture_from_image(dev, o->displace_map, IS_FMT_R32F, 1, tex);
    else e = dev_create_texture_from_file(dev, o->displace, IS_FMT_R32F, 1, tex);
    if (e != IS_OK) return e;
    const unsigned s0 = IS_VERTEXTEXTURESAMPLER(0);
    dev_set_texture(dev, s0, *tex);
    dev_set_sampler_state(dev, s0, IS_SAMP_MINFILTER, IS_TEXF_LINEAR);
    dev_set_sampler_state(dev, s0, IS_SAMP_MAGFILTER, IS_TEXF_LINEAR);
    dev_set_sampler_state(dev, s0, IS_SAMP_ADDRESSU, IS_TADDRESS_WRAP);
    dev_set_sampler_state(dev, s0, IS_SAMP_ADDRESSV, IS_TADDRESS_WRAP);
    float c[20] = {(float)scene_shader_index(inner), o->displace_scale, 0, 0};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) c[4 + 4 * i + j] = view_proj->m[i][j];
    return dev_set_vertex_shader_constant_f(dev, C_DISPLACE, c, 5);
}
