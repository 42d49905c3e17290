/* cli/run/lighting.c -- the light and the colours of a scene (--light, --color, --background): parsing, and the
 * wrapper shader that relights a patch when the light is not the listing's headlight.
 *
 * The listing's shaders light with saturate(dot(Normal, (0, 0, -1))) * g_vDiffuse (a headlight: the camera looks
 * along +z).  Any other light is applied by a wrapper around the path's own shader, so the patch shaders stay
 * exactly as listed and the default image keeps its bytes:
 *   --light X,Y,Z   (0.08 + 0.92 saturate(dot(n, normalize(X, Y, Z)))) * g_vDiffuse, n the world-space unit
 *                   normal the shader wrote to TEXCOORD1 (a little ambient so faces turned away stay visible);
 *   --light grazing the direction (0.62, 0.62, -0.48): from the upper right, grazing a face turned to the camera,
 *                   so creases and valleys show in the shading (fig-1.1.8b);
 *   --light normals colour = 0.5 + 0.5 (n.x, n.y, -n.z) (facing the camera is blue; fig-001-1), times
 *                   g_vDiffuse, which the scene sets to white for the surface (the wireframe keeps its colour).
 * Constant registers of the wrapper, after the listing's c0..c9: c10.x = index of the wrapped shader in
 * vs_shaders, c10.y = SCENE_LIGHT_*, c11 = the unit direction towards the light. */
#include "scene.h"

#include "../../core/hlsl.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { C_LIGHT_MODE = VS_C_COUNT, C_LIGHT_DIR = VS_C_COUNT + 1 };

/* The colour of light c10.y (not the headlight) for the world-space unit normal n (c8 the diffuse colour). */
static float4 lit_unit(const float4 *c, float3 n)
{
    float4 d = c[VS_C_DIFFUSE];
    float3 k;
    if ((int)c[C_LIGHT_MODE].y == SCENE_LIGHT_NORMALS) k = f3(0.5f + 0.5f * n.x, 0.5f + 0.5f * n.y, 0.5f - 0.5f * n.z);
    else {
        float l = 0.08f + 0.92f * saturate(dot3(n, f3_of(c[C_LIGHT_DIR])));
        k = f3(l, l, l);
    }
    return f4(k.x * d.x, k.y * d.y, k.z * d.z, 1.0f);
}

float4 scene_light_color(const float4 *c, float3 Normal)
{
    if ((int)c[C_LIGHT_MODE].y != SCENE_LIGHT_HEADLIGHT) return lit_unit(c, normalize3(Normal));
    float d = dot3(Normal, f3(0.0f, 0.0f, -1.0f));   /* the listing's headlight, as vs_write_outputs lights */
    float4 diffuse = scale4(c[VS_C_DIFFUSE], saturate(isnan(d) ? 0.0f : d));
    diffuse.w = 1.0f;
    return diffuse;
}

/* The wrapped shader (c10.x), then the light of c10.y applied to COLOR0. */
static void vs_relit(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    scene_shader_at((int)c->c[C_LIGHT_MODE].x)->main(c, in, out);
    if ((int)c->c[C_LIGHT_MODE].y == SCENE_LIGHT_HEADLIGHT) return;
    out->attr[RS_ATTR_COLOR0] = lit_unit(c->c, f3_of(out->attr[RS_ATTR_TEXCOORD0 + VS_OUT_NORMAL]));
}
/* The wrapped shader's published values (the inspector's view of the patch under the light). */
static unsigned vs_relit_explain(const is_vs_constants *c, const is_vs_input *in, is_vs_value *vals, unsigned max)
{
    const is_vertex_shader *inner = scene_shader_at((int)c->c[C_LIGHT_MODE].x);
    return inner->explain ? inner->explain(c, in, vals, max) : 0;
}
static const is_vertex_shader relit_shader = {.name = "relit", .main = vs_relit, .outputs = VS_OUTPUTS,
                                              .explain = vs_relit_explain};

/* Index of s in vs_shaders, or -1. */
static int shader_index(const is_vertex_shader *s)
{
    for (int k = 0; vs_shaders[k]; k++)
        if (vs_shaders[k] == s) return k;
    return -1;
}

/* The shaders a wrapper may wrap: vs_shaders, then the light's wrapper and the displacement's (scene.h). */
int scene_shader_index(const is_vertex_shader *s)
{
    int k = shader_index(s), n = 0;
    if (k >= 0 || (s != &relit_shader && s != &scene_displaced_shader)) return k;
    while (vs_shaders[n]) n++;
    return s == &relit_shader ? n : n + 1;
}

const is_vertex_shader *scene_shader_at(int k)
{
    int n = 0;
    while (vs_shaders[n]) n++;
    return k < n ? vs_shaders[k] : k == n ? &relit_shader : &scene_displaced_shader;
}

const is_vertex_shader *scene_light_shader(const scene_opts *o, const is_vertex_shader *path_shader)
{
    return o->light == SCENE_LIGHT_HEADLIGHT || scene_shader_index(path_shader) < 0 ? path_shader : &relit_shader;
}

void scene_light_constants(is_device *dev, const scene_opts *o, const is_vertex_shader *path_shader)
{
    if (o->light == SCENE_LIGHT_HEADLIGHT) return;
    float3 l = normalize3(f3(o->light_dir[0], o->light_dir[1], o->light_dir[2]));
    float c[8] = {(float)scene_shader_index(path_shader), (float)o->light, 0, 0, l.x, l.y, l.z, 0};
    dev_set_vertex_shader_constant_f(dev, C_LIGHT_MODE, c, 2);
}

/* Three comma-separated finite numbers into v; true on success. */
static bool parse_triple(const char *s, float v[3])
{
    char *end;
    for (int k = 0; k < 3; k++) {
        if (!scene_plain_number(s)) return false;
        double x = strtod(s, &end);
        if (end == s || !isfinite(x) || !isfinite((float)x)) return false;
        v[k] = (float)x;
        if (k < 2 && *end != ',') return false;
        s = end + 1;
    }
    return *end == 0;
}

bool scene_parse_light(const char *s, scene_opts *o)
{
    static const float grazing[3] = {0.62f, 0.62f, -0.48f};
    float v[3];
    if (!s) return false;
    if (!strcmp(s, "headlight")) return o->light = SCENE_LIGHT_HEADLIGHT, true;
    if (!strcmp(s, "normals")) return o->light = SCENE_LIGHT_NORMALS, true;
    if (!strcmp(s, "grazing")) memcpy(v, grazing, sizeof v);
    else if (!parse_triple(s, v)) return false;
    float m = fmaxf(fabsf(v[0]), fmaxf(fabsf(v[1]), fabsf(v[2])));
    if (!(m > 0.0f)) return false;   /* 0,0,0 (also after rounding to float) */
    /* A direction at any scale: scaled by the power of two that brings its largest component to [1, 2), which is
     * exact, so that its square sums neither overflow (1e30,0,0) nor vanish (1e-30,0,0) and a direction already of
     * ordinary size keeps its bits (and the image its pixels). */
    if (m < 0x1p-20f || m > 0x1p20f)
        for (int k = 0; k < 3; k++) v[k] = ldexpf(v[k], -ilogbf(m));
    o->light = SCENE_LIGHT_DIRECTION;
    memcpy(o->light_dir, v, sizeof v);
    return true;
}

const char *scene_light_name(const scene_opts *o, char *buf, size_t len)
{
    if (o->light == SCENE_LIGHT_HEADLIGHT) return "headlight";
    if (o->light == SCENE_LIGHT_NORMALS) return "normals";
    snprintf(buf, len, "%g,%g,%g", (double)o->light_dir[0], (double)o->light_dir[1], (double)o->light_dir[2]);
    return buf;
}

/* Two hexadecimal digits at s into *out; true on success. */
static bool hex_byte(const char *s, float *out)
{
    unsigned v = 0;
    for (int k = 0; k < 2; k++) {
        char c = s[k];
        unsigned d = c >= '0' && c <= '9' ? (unsigned)(c - '0')
                     : c >= 'a' && c <= 'f' ? (unsigned)(c - 'a' + 10)
                     : c >= 'A' && c <= 'F' ? (unsigned)(c - 'A' + 10) : 16u;
        if (d > 15) return false;
        v = v * 16 + d;
    }
    *out = (float)v / 255.0f;
    return true;
}

bool scene_parse_color(const char *s, float rgb[3])
{
    float v[3];
    if (!s) return false;
    if (s[0] == '#') {
        if (strlen(s) != 7) return false;
        for (int k = 0; k < 3; k++)
            if (!hex_byte(s + 1 + 2 * k, &v[k])) return false;
    } else if (!parse_triple(s, v)) {
        return false;
    }
    for (int k = 0; k < 3; k++)
        if (!(v[k] >= 0.0f && v[k] <= 1.0f)) return false;
    memcpy(rgb, v, sizeof v);
    return true;
}
