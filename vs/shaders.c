/* vs/shaders.c -- constants and options, the outputs every patch shader writes, the flat, Phong, PN-AEN and
 * fixed shaders, and the table of shaders by name. */
#include "vs_internal.h"

#include "../core/hlsl.h"
#include <stdio.h>
#include <string.h>

vs_options vs_default_options(void)
{
    return (vs_options){VS_NORMALS_LINEAR, 0.75f, 2.0f, 0u};
}

void vs_set_constants(is_vs_constants *c, const float4x4 *wvp, const float4x4 *world, float4 diffuse,
                      const vs_options *o)
{
    vs_options od = vs_default_options();
    if (!o) o = &od;
    if (!c) return;
    const float4x4 zero = {{{0}}};
    if (!wvp) wvp = &zero;   /* a NULL matrix is written as the zero matrix (math.h's rule) */
    if (!world) world = &zero;
    for (int i = 0; i < 4; i++) {
        c->c[VS_C_WORLDVIEWPROJ + i] = f4(wvp->m[i][0], wvp->m[i][1], wvp->m[i][2], wvp->m[i][3]);
        c->c[VS_C_WORLD + i] = f4(world->m[i][0], world->m[i][1], world->m[i][2], world->m[i][3]);
    }
    c->c[VS_C_DIFFUSE] = diffuse;
    c->c[VS_C_OPTIONS] = f4((float)o->normals, o->phong_alpha, o->quad_factor, (float)o->flags);
}

vs_options vs_options_from_constants(const is_vs_constants *c)
{
    return c ? vs_options_from_register(c->c[VS_C_OPTIONS]) : vs_default_options();
}

vs_options vs_options_from_register(float4 r)
{
    vs_options o = vs_default_options();
    o.normals = r.x >= 1.5f ? VS_NORMALS_REAL : r.x >= 0.5f ? VS_NORMALS_QUADRATIC : VS_NORMALS_LINEAR;
    o.phong_alpha = isfinite(r.y) ? r.y : 0.75f;
    o.quad_factor = isfinite(r.z) && r.z != 0.0f ? r.z : 2.0f;
    o.flags = r.w >= 1.0f && r.w < 65536.0f ? (uint32_t)r.w : 0u;
    return o;
}

static const char *const normals_names[] = {"linear", "quadratic", "real"};

int vs_normals_from_name(const char *name, vs_normals *out)
{
    for (int i = 0; name && out && i < 3; i++)
        if (strcmp(name, normals_names[i]) == 0) return *out = (vs_normals)i, 0;
    return -1;
}

const char *vs_normals_name(vs_normals n) { return (unsigned)n < 3 ? normals_names[n] : "?"; }

const vs_patch_info vs_patches[VS_PATCH_COUNT] = {
    [VS_PATCH_FLAT] = {"flat", "linear positions: D3DDEGREE_LINEAR; Akenine-Moller and Haines", &vs_shader_flat,
                       true, false},
    [VS_PATCH_NPATCH] = {"npatch", "the N-Patch (PN triangle): Vlachos et al. 2001; Gruen, Eq. 1.1.1-1.1.2",
                         &vs_shader_npatch, true, false},
    [VS_PATCH_SMOOTH_INITIAL] = {"smooth-initial", "Gruen, intermediate smoothed patch (Listing 1.1.1)",
                                 &vs_shader_smooth_initial, false, true},
    [VS_PATCH_SMOOTH] = {"smooth", "Gruen, final smoothed patch (Listing 1.1.2, Eq. 1.1.9-1.1.11)",
                         &vs_shader_smooth, false, true},
    [VS_PATCH_PHONG] = {"phong", "Phong tessellation: Boubekeur and Alexa 2008", &vs_shader_phong, false, false},
    [VS_PATCH_PN_AEN] = {"pn-aen", "PN triangles with adjacent edge normals: McDonald and Kilgard 2010",
                         &vs_shader_pn_aen, false, false},
};

int vs_patch_from_name(const char *name, vs_patch *out)
{
    for (int i = 0; name && out && i < VS_PATCH_COUNT; i++)
        if (strcmp(name, vs_patches[i].name) == 0) return *out = (vs_patch)i, 0;
    return -1;
}

const char *vs_patch_name(vs_patch p) { return (unsigned)p < VS_PATCH_COUNT ? vs_patches[p].name : "?"; }

char *vs_patch_names(const char *sep, char *buf, size_t len)
{
    size_t n = 0;
    if (!buf || len == 0) return buf;
    buf[0] = 0;
    for (int i = 0; i < VS_PATCH_COUNT && n < len; i++)
        n += (size_t)snprintf(buf + n, len - n, "%s%s", i && sep ? sep : "", vs_patches[i].name);
    return buf;
}

void vs_write_outputs(const is_vs_constants *c, float3 pos, float3 normal, float2 oTex, float3 b, float id,
                      float3 g, is_vs_output *out)
{
    vs_batch_consts k;
    k.wvp = vs_const_matrix(c, VS_C_WORLDVIEWPROJ);
    k.world = vs_const_matrix(c, VS_C_WORLD);
    k.diffuse = c->c[VS_C_DIFFUSE];
    vs_write_outputs_k(&k, pos, normal, oTex, b, id, g, out);
}

void vs_write_outputs_k(const vs_batch_consts *k, float3 pos, float3 normal, float2 oTex, float3 b, float id,
                        float3 g, is_vs_output *out)
{
    const float4x4 *g_mWorldViewProjection = &k->wvp, *g_mWorld = &k->world;
    // transform
    out->pos = mul4(f4_of(pos, 1.0f), g_mWorldViewProjection);
    float3 Normal = mul3x3(normal, g_mWorld);
    float d = dot3(Normal, f3(0.0f, 0.0f, -1.0f));
    float4 Diffuse = scale4(k->diffuse, saturate(isnan(d) ? 0.0f : d));
    Diffuse.w = 1.0f;
    out->attr[RS_ATTR_COLOR0] = Diffuse;
    out->attr[RS_ATTR_TEXCOORD0 + VS_OUT_TEX] = f4(oTex.x, oTex.y, 0.0f, 1.0f);
    out->attr[RS_ATTR_TEXCOORD0 + VS_OUT_NORMAL] = f4_of(normalize3(Normal), 0.0f);
    out->attr[RS_ATTR_TEXCOORD0 + VS_OUT_BARY] = f4_of(b, 1.0f);
    out->attr[RS_ATTR_TEXCOORD0 + VS_OUT_INSTANCE] = f4(id, 0.0f, 0.0f, 1.0f);
    out->attr[RS_ATTR_TEXCOORD0 + VS_OUT_GREGORY] = f4_of(g, 0.0f);
}

void vs_batch_consts_read(const is_vs_constants *c, vs_batch_consts *k)
{
    k->wvp = vs_const_matrix(c, VS_C_WORLDVIEWPROJ);
    k->world = vs_const_matrix(c, VS_C_WORLD);
    k->diffuse = c->c[VS_C_DIFFUSE];
    k->o = vs_options_from_constants(c);
    k->live = ~0u;
}

bool vs_same_instance(const is_vs_input *a, const is_vs_input *b)
{
    const size_t skip = sizeof(float4); /* position[0] comes first */
    return memcmp((const char *)a + skip, (const char *)b + skip, sizeof *a - skip) == 0;
}

/* run_patch over a batch: the triangle is read once per instance, the options and matrices once per batch. */
void vs_patch_batch(vs_patch p, const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t shared,
                    is_vs_output *out)
{
    vs_batch_consts k;
    vs_batch_consts_read(c, &k);
    vs_triangle tri;
    /* every register but POSITION0 shared (the device's fused path): one instance, read once from in[0] */
    const bool one = shared == IS_VS_REGS_INSTANCE;
    is_vs_input tmp[2]; /* vertex v's inputs for other shared masks (alternating: the previous one stays) */
    const is_vs_input *prev = NULL;
    for (size_t v = 0; v < n; v++) {
        const is_vs_input *r = one ? &in[v] : is_vs_input_at(in, v, shared, &tmp[v & 1]);
        if (!prev || (!one && !vs_same_instance(r, prev))) vs_triangle_from_input(r, &tri);
        prev = r;
        float3 b = f3_of(r->position[0]); // barycentric coords
        float3 pos, normal, g;
        vs_patch_eval(p, &tri, b, &k.o, &pos, &normal, &g);
        float2 oTex = add2(add2(scale2(tri.t[0], b.x), scale2(tri.t[1], b.y)), scale2(tri.t[2], b.z));
        vs_write_outputs_k(&k, pos, normal, oTex, b, tri.id, g, &out[v]);
    }
}

void vs_run_patch(vs_patch p, const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    float3 b = f3_of(in->position[0]); // barycentric coords
    vs_triangle tri;
    vs_triangle_from_input(in, &tri);
    vs_options o = vs_options_from_constants(c);
    float3 pos, normal, g;
    vs_patch_eval(p, &tri, b, &o, &pos, &normal, &g);
    float2 oTex = add2(add2(scale2(tri.t[0], b.x), scale2(tri.t[1], b.y)), scale2(tri.t[2], b.z));
    vs_write_outputs(c, pos, normal, oTex, b, tri.id, g, out);
}

/* D3DDEGREE_LINEAR positions: the flat triangle with the chosen normals. */
static void VSFlat(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    vs_run_patch(VS_PATCH_FLAT, c, in, out);
}

/* Phong tessellation (Boubekeur and Alexa 2008), alpha in c9.y. */
static void VSPhong(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    vs_run_patch(VS_PATCH_PHONG, c, in, out);
}

/* PN-AEN (McDonald and Kilgard 2010): edge control points averaged over both sides' normals. */
static void VSPnAen(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    vs_run_patch(VS_PATCH_PN_AEN, c, in, out);
}

/* Transform and light POSITION0 / NORMAL0 / TEXCOORD0 (the device's N-patch mode feeds evaluated points). */
static void VSFixed(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    vs_write_outputs(c, f3_of(in->position[0]), f3_of(in->normal[0]), f2_of(in->texcoord[0]), f3(0, 0, 0), 0.0f,
                     f3(0, 0, 0), out);
}

static void VSFlatBatch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live,
                        uint32_t shared, is_vs_output *out)
{
    vs_patch_batch(VS_PATCH_FLAT, c, in, n, shared, out);
}
static void VSPhongBatch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live,
                         uint32_t shared, is_vs_output *out)
{
    vs_patch_batch(VS_PATCH_PHONG, c, in, n, shared, out);
}
static void VSPnAenBatch(const is_vs_constants *c, const is_vs_input *in, size_t n, uint32_t live,
                         uint32_t shared, is_vs_output *out)
{
    vs_patch_batch(VS_PATCH_PN_AEN, c, in, n, shared, out);
}

const is_vertex_shader vs_shader_flat = {"flat", VSFlat, VS_OUTPUTS, VSFlatBatch, vs_flat_hull,
                                         vs_explain_flat, NULL, NULL};
const is_vertex_shader vs_shader_phong = {"phong", VSPhong, VS_OUTPUTS, VSPhongBatch, NULL, vs_explain_phong,
                                          NULL, NULL};
const is_vertex_shader vs_shader_pn_aen = {"pn-aen", VSPnAen, VS_OUTPUTS, VSPnAenBatch, NULL,
                                           vs_explain_pn_aen, NULL, NULL};
const is_vertex_shader vs_shader_fixed = {"fixed", VSFixed, VS_OUTPUTS, NULL, NULL, NULL, NULL, NULL};

const is_vertex_shader *const vs_shaders[] = {&vs_shader_flat, &vs_shader_npatch, &vs_shader_smooth_initial,
                                              &vs_shader_smooth, &vs_shader_phong, &vs_shader_pn_aen,
                                              &vs_shader_fixed, NULL};

const is_vertex_shader *vs_find_shader(const char *name)
{
    for (int i = 0; name && vs_shaders[i]; i++)
        if (strcmp(vs_shaders[i]->name, name) == 0) return vs_shaders[i];
    return NULL;
}

const is_vertex_shader *vs_patch_shader(vs_patch p)
{
    return (unsigned)p < VS_PATCH_COUNT ? vs_patches[p].shader : NULL;
}
