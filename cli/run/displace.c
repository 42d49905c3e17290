/* cli/run/displace.c -- --displace FILE --displace-scale S: every patch moved along its normal by a height that
 * the vertex shader fetches from a texture at its texture coordinates (Shader Model 3's vertex texture fetch:
 * core/texture.h, sampler D3DVERTEXTEXTURESAMPLER0), as a wrapper around the shader that draws the patch (the
 * patch's own, or the fixed shader of the N-patch-mode and CPU paths), inside the light's wrapper, so the patch
 * shaders stay as listed and a render without --displace keeps its bytes.
 *
 * Position: the inner shader's outputs, then h = tex2Dlod(s0, float4(oTex.u, oTex.v, 0, 0)).r (TEXCOORD0) and
 * oPos += S h mul(float4(n, 0), View * Proj), n the unit world-space normal the inner shader wrote to TEXCOORD1.
 * The scene's world matrix turns the object scaled to a unit bounding radius, so this is the object-space point
 * moved by S h bounding radii along its normal: S is in bounding radii, h the map's red channel (a grey image:
 * its value; PNG 0..1).
 * The map: an R32F texture of one level, LINEAR minification and magnification, WRAP in u and v (a tiling map
 * joins at u = 0 and 1), so the height is continuous in the texture coordinates.
 * Shading: on the instanced path (a patch shader inside) the normal is the displaced surface's own: the patch
 * displaced as above (vs_patch_eval, the same texture coordinates and fetch) at the three points (1 - d) b + d e_k
 * around the vertex's barycentrics b (d = 2^-10; inside the triangle also on its edges), the unit normal of the
 * small triangle they span, turned by g_mWorld and oriented like the patch normal; COLOR0 is then the listing's
 * headlight term of it (saturate(dot(N, (0, 0, -1))) * g_vDiffuse) and TEXCOORD1 (the normal AOV, the light's
 * wrapper) is it.  On the N-patch-mode and CPU paths the fixed shader has no patch to evaluate: the surface moves,
 * the shading stays the undisplaced patch's.  The shading normal never moves a vertex.
 * Cracks: two triangles sharing an edge give its points the same oPos, TEXCOORD0 and TEXCOORD1 bits when their
 * texture coordinates and normals agree there (vs/vs.h: positions always; linear and quadratic normals; texture
 * coordinates b0 t0 + b1 t1 + b2 t2 from the grid's mirrored barycentrics), so the displaced points agree too and
 * the surface stays closed.  Where a texture seam gives an edge two sets of texture coordinates, or where real
 * normals differ on the two sides, the two sides move apart (docs/design.md counts those cracks).
 * Constant registers: c12 = (the inner shader (scene_shader_index), S, the mesh's bounding radius in its own
 * units, 0), c13..c16 = View * Proj. */
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

#define NORMAL_STEP 0x1p-10f

/* Patch p of T at b displaced as the wrapper displaces it, in object space (vo: the normal mode). */
static float3 displaced_point(const is_vs_constants *c, vs_patch p, const vs_triangle *T, const vs_options *vo,
                              float3 b)
{
    float3 pos, n;
    vs_patch_eval(p, T, b, vo, &pos, &n, NULL);
    float2 t = add2(add2(scale2(T->t[0], b.x), scale2(T->t[1], b.y)), scale2(T->t[2], b.z));
    float h = tex2Dlod(&c->s[0], f4(t.x, t.y, 0.0f, 0.0f)).x;
    return add3(pos, scale3(n, c->c[C_DISPLACE].y * c->c[C_DISPLACE].z * h));
}

/* The unit world-space normal of the displaced patch p at the vertex of `in` (see the top), oriented like n; n
 * itself where the small triangle is degenerate. */
static float3 displaced_normal(const is_vs_constants *c, vs_patch p, const is_vs_input *in, float3 n)
{
    vs_triangle T;
    vs_triangle_from_input(in, &T);
    vs_options vo = vs_options_from_constants(c);
    float3 b = f3_of(in->position[0]), q[3];
    for (int k = 0; k < 3; k++) {
        float3 bk = scale3(b, 1.0f - NORMAL_STEP);
        (&bk.x)[k] += NORMAL_STEP;
        q[k] = displaced_point(c, p, &T, &vo, bk);
    }
    float4x4 world = vs_const_matrix(c, VS_C_WORLD);
    float3 w = normalize3(mul3x3(cross3(sub3(q[1], q[0]), sub3(q[2], q[0])), &world));
    if (!(dot3(w, w) > 0.5f)) return n;
    return dot3(w, n) < 0.0f ? neg3(w) : w;
}

/* The inner shader of c12.x, then the displacement, then (inside a patch) the displaced surface's shading. */
static void vs_displaced(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    int k = (int)c->c[C_DISPLACE].x;
    scene_shader_at(k)->main(c, in, out);
    scene_displace_apply(c, out);
    if (k >= VS_PATCH_COUNT) return;
    float3 n = displaced_normal(c, (vs_patch)k, in, f3_of(out->attr[RS_ATTR_TEXCOORD0 + 1]));
    float d = dot3(n, f3(0.0f, 0.0f, -1.0f));
    float4 diffuse = scale4(c->c[VS_C_DIFFUSE], saturate(d));
    diffuse.w = 1.0f;
    out->attr[RS_ATTR_COLOR0] = diffuse;
    out->attr[RS_ATTR_TEXCOORD0 + 1] = f4_of(n, 0.0f);
}
/* The inner shader's published values, then the displaced point (object space) as "displaced". */
static unsigned vs_displaced_explain(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals,
                                     unsigned max)
{
    int k = (int)c->c[C_DISPLACE].x;
    const is_vertex_shader *inner = scene_shader_at(k);
    unsigned n = inner->explain ? inner->explain(c, in, vals, max) : 0;
    if (k >= VS_PATCH_COUNT || n >= max) return n;
    vs_triangle T;
    vs_triangle_from_input(in, &T);
    vs_options vo = vs_options_from_constants(c);
    vals[n] = (is_vs_value){"displaced", f4_of(displaced_point(c, (vs_patch)k, &T, &vo, f3_of(in->position[0])), 1.0f)};
    return n + 1;
}
const is_vertex_shader scene_displaced_shader = {.name = "displaced", .main = vs_displaced, .outputs = VS_OUTPUTS,
                                                 .explain = vs_displaced_explain};

const is_vertex_shader *scene_displace_shader(const scene_opts *o, const is_vertex_shader *inner)
{
    return o->displace && scene_shader_index(inner) >= 0 ? &scene_displaced_shader : inner;
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

is_result scene_displace_bind(is_device *dev, const scene_opts *o, const float4x4 *view_proj, float radius,
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
    float c[20] = {(float)scene_shader_index(inner), o->displace_scale, radius, 0};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) c[4 + 4 * i + j] = view_proj->m[i][j];
    return dev_set_vertex_shader_constant_f(dev, C_DISPLACE, c, 5);
}
