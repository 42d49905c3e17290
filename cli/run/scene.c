/* cli/run/scene.c -- render one scene through the device: options, camera, the three paths to a patch
 * (instanced, the device's N-patch mode, CPU tessellation), image assembly (RGBA, Z, AOVs) and output. */
#include "scene.h"

#include "../../core/hlsl.h"
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define PI_F 3.14159265358979f

/* ---------------------------------------- options ---------------------------------------- */

void scene_opts_default(scene_opts *o)
{
    *o = (scene_opts){
        .mesh = "cube", .patch = VS_PATCH_SMOOTH, .normals = VS_NORMALS_REAL, .level = 8.0f,
        .grid = CORE_GRID_REGULAR, .path = SCENE_PATH_INSTANCED, .width = 512, .height = 512, .yaw = 30.0f,
        .pitch = 20.0f, .distance = 3.2f, .fill = SCENE_FILL_SOLID, .msaa = 4, .threads = 0,
        .diffuse = {0.85f, 0.78f, 0.62f, 1.0f}, .wire_color = {0.0f, 0.0f, 0.0f, 1.0f},
        .background = IS_COLOR_ARGB(255, 46, 52, 64), .max_memory_mib = SCENE_DEFAULT_MAX_MEMORY_MIB,
        .lod = TESS_LOD_UNIFORM, .lod_target = SCENE_LOD_DEFAULT_TARGET, .lod_deviation = SCENE_LOD_DEFAULT_DEVIATION,
        .min_level = 1, .max_level = 0,
        .light = SCENE_LIGHT_HEADLIGHT, .fov = 45.0f,
        .cull = IS_CULL_CCW, .up = SCENE_UP_Y, .displace_scale = SCENE_DISPLACE_SCALE,
    };
    vs_options vo = vs_default_options();
    o->phong_alpha = vo.phong_alpha, o->n110_factor = vo.quad_factor;
}

/* Index of s in a NULL-terminated name table, or -1. */
static int lookup(const char *s, const char *const *names)
{
    for (int k = 0; s && names[k]; k++)
        if (strcmp(s, names[k]) == 0) return k;
    return -1;
}

bool scene_parse_patch(const char *s, vs_patch *out)
{
    return vs_patch_from_name(s, out) == 0;
}

bool scene_parse_normals(const char *s, vs_normals *out)
{
    return vs_normals_from_name(s, out) == 0;
}

/* The names of --grid, --path and --fill, in their enums' order (scene.h). */
const char *const scene_grid_names[] = {"regular", "pg-equal", "pg-fractional-odd", "pg-fractional-even", NULL};
const char *const scene_path_names[] = {"instanced", "npatch-mode", "cpu", NULL};
const char *const scene_fill_names[] = {"solid", "wire", "solid+wire", "point", NULL};
const char *const scene_cull_names[] = {"none", "cw", "ccw", NULL};
const char *const scene_up_names[] = {"x", "y", "z", "-x", "-y", "-z", NULL};
const char *const scene_fit_names[] = {"sphere", "box", NULL};

const char *scene_grid_name(core_grid_kind g)
{
    return (unsigned)g < sizeof scene_grid_names / sizeof scene_grid_names[0] - 1 ? scene_grid_names[g] : "?";
}

bool scene_parse_grid(const char *s, core_grid_kind *out)
{
    int k = lookup(s, scene_grid_names);
    if (k < 0) return false;
    *out = (core_grid_kind)k;
    return true;
}

bool scene_parse_path(const char *s, scene_path *out)
{
    int k = lookup(s, scene_path_names);
    if (k < 0) return false;
    *out = (scene_path)k;
    return true;
}

bool scene_parse_cull(const char *s, uint32_t *out)
{
    int k = lookup(s, scene_cull_names);
    if (k < 0) return false;
    *out = (uint32_t)(IS_CULL_NONE + k);
    return true;
}

/* Index of s in names into *out; false if it is not there. */
bool scene_parse_name(const char *s, const char *const *names, int *out)
{
    int k = lookup(s, names);
    if (k < 0) return false;
    *out = k;
    return true;
}

bool scene_parse_fill(const char *s, scene_fill *out)
{
    int k = lookup(s, scene_fill_names);
    if (k < 0) return false;
    *out = (scene_fill)k;
    return true;
}

char *scene_join_names(const char *const *names, const char *sep, char *buf, size_t len)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; names[i] && n < len; i++) n += (size_t)snprintf(buf + n, len - n, "%s%s", i ? sep : "", names[i]);
    return buf;
}

bool scene_plain_number(const char *s)
{
    if (!s) return false;
    const char *p = s + (*s == '+' || *s == '-');
    if (!((*p >= '0' && *p <= '9') || (*p == '.' && p[1] >= '0' && p[1] <= '9'))) return false;
    for (; *p && *p != ','; p++)   /* a number of a list ends at its comma */
        if (!((*p >= '0' && *p <= '9') || *p == '.' || *p == 'e' || *p == 'E' || *p == '+' || *p == '-'))
            return false;
    return true;
}

/* A whole decimal integer in [lo, hi], written plainly (scene_plain_number). */
bool scene_parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = scene_plain_number(s) ? strtol(s, &end, 10) : 0;
    if (!scene_plain_number(s) || end == s || *end || errno || v < lo || v > hi) return false;
    *out = (int)v;
    return true;
}

/* A finite number in [lo, hi], written plainly (scene_plain_number). */
bool scene_parse_float(const char *s, float lo, float hi, float *out)
{
    char *end;
    errno = 0;
    double v = scene_plain_number(s) ? strtod(s, &end) : 0;
    if (!scene_plain_number(s) || end == s || *end || errno || !isfinite(v) || v < lo || v > hi) return false;
    *out = (float)v;
    return true;
}

/* WxH with both sides in 1..SCENE_MAX_SIDE and at most SCENE_MAX_PIXELS pixels. */
bool scene_parse_pixel(const char *s, int *x, int *y)
{
    char buf[32];
    const char *comma = s ? strchr(s, ',') : NULL;
    if (!comma || (size_t)(comma - s) >= sizeof buf) return false;
    memcpy(buf, s, (size_t)(comma - s));
    buf[comma - s] = 0;
    int a, b;
    if (!scene_parse_int(buf, 0, RS_MAX_SIZE - 1, &a) || !scene_parse_int(comma + 1, 0, RS_MAX_SIZE - 1, &b)) return false;
    *x = a, *y = b;
    return true;
}

bool scene_parse_size(const char *s, int *w, int *h)
{
    char buf[64];
    if (!s || strlen(s) >= sizeof buf) return false;
    strcpy(buf, s);
    char *x = strchr(buf, 'x');
    if (!x) return false;
    *x = 0;
    int a, b;
    if (!scene_parse_int(buf, 1, SCENE_MAX_SIDE, &a) || !scene_parse_int(x + 1, 1, SCENE_MAX_SIDE, &b)) return false;
    if ((unsigned long long)a * (unsigned long long)b > SCENE_MAX_PIXELS) return false;
    *w = a, *h = b;
    return true;
}

bool scene_parse_msaa(const char *s, int *out)
{
    int v;
    if (!scene_parse_int(s, 1, 4, &v) || (v != 1 && v != 4)) return false;
    *out = v;
    return true;
}

const scene_aov scene_aov_table[SCENE_AOV_COUNT] = {
    {"normal", SCENE_AOV_NORMAL, VS_OUT_NORMAL, 3, "N.X,N.Y,N.Z"},
    {"bary", SCENE_AOV_BARY, VS_OUT_BARY, 3, "bary.X,bary.Y,bary.Z"},
    {"instance", SCENE_AOV_INSTANCE, VS_OUT_INSTANCE, 1, "instance"},
    {"gregory", SCENE_AOV_GREGORY, VS_OUT_GREGORY, 3, "gregory.X,gregory.Y,gregory.Z"},
    {"uv", SCENE_AOV_UV, VS_OUT_TEX, 2, "uv.U,uv.V"},
    {"depth", SCENE_AOV_DEPTH, -1, 1, "depth"},
};

/* Comma-separated AOV names (scene_aov_table's) into a SCENE_AOV_* mask. */
bool scene_parse_aovs(const char *s, unsigned *out)
{
    char buf[256];
    if (!s || !*s || strlen(s) >= sizeof buf) return false;
    strcpy(buf, s);
    unsigned m = 0;
    for (char *save = NULL, *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        int k = 0;
        while (k < SCENE_AOV_COUNT && strcmp(t, scene_aov_table[k].name) != 0) k++;
        if (k == SCENE_AOV_COUNT) return false;
        m |= scene_aov_table[k].bit;
    }
    *out = m;
    return m != 0;
}

/* True if path ends with ext (case-insensitive ASCII). */
static bool has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    if (n < e) return false;
    for (size_t k = 0; k < e; k++) {
        char a = path[n - e + k], b = ext[k];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (a != b) return false;
    }
    return true;
}

static const char *check_lod_opts(const scene_opts *o);

const char *scene_check_opts(const scene_opts *o)
{
    if (o->output && !has_ext(o->output, ".png") && !has_ext(o->output, ".exr"))
        return "the output must end in .png or .exr";
    if (o->aovs && (!o->output || !has_ext(o->output, ".exr"))) return "--aov needs an .exr output";
    if (o->export_obj && !has_ext(o->export_obj, ".obj")) return "--export-obj writes OBJ: its name must end in .obj";
    if (o->path != SCENE_PATH_INSTANCED && !vs_patches[o->patch].fixed_function)
        return "--path npatch-mode and cpu draw the N-Patch (or flat): use --patch npatch or flat";
    if (o->path != SCENE_PATH_INSTANCED && o->normals == VS_NORMALS_REAL)
        return "--path npatch-mode and cpu offer linear and quadratic normals (as D3D9's NORMALDEGREE)";
    if (o->path == SCENE_PATH_NPATCH_MODE && o->grid != CORE_GRID_REGULAR && o->grid != CORE_GRID_PG_FRACTIONAL_EVEN)
        return "--path npatch-mode tessellates with the regular grid (PATCHEDGESTYLE DISCRETE) or "
               "pg-fractional-even (CONTINUOUS)";
    if (o->d3d9_adaptive != SCENE_D3D9_OFF && o->path != SCENE_PATH_NPATCH_MODE)
        return "--d3d9-adaptive is D3D9's adaptive N-patch mode: it needs --path npatch-mode";
    if (o->d3d9_adaptive != SCENE_D3D9_OFF && o->level > CORE_PG_MAX_LEVEL)
        return "--d3d9-adaptive tessellates an edge into at most 64 segments (the primitive generator's bound): "
               "--level must be 1..64";
    if (o->d3d9_adaptive != SCENE_D3D9_OFF && o->export_obj)
        return "--export-obj writes the uniform tessellation: it cannot be combined with --d3d9-adaptive";
    if (o->d3d9_adaptive != SCENE_D3D9_OFF && o->lod != TESS_LOD_UNIFORM)
        return "--d3d9-adaptive (the device's N-patch mode) and --lod (instanced patterns) are two ways: choose one";
    if (o->grid == CORE_GRID_REGULAR && o->level != floorf(o->level) && o->lod == TESS_LOD_UNIFORM)
        return "a fractional --level needs a primitive-generator grid (--grid pg-fractional-odd or -even)";
    if (o->lod == TESS_LOD_UNIFORM && (o->max_level || o->min_level != 1 || o->silhouette || o->wire_by_level))
        return "--min-level, --max-level, --silhouette and --wire-levels need --lod distance, screen or deviation";
    if (o->lod != TESS_LOD_SCREEN && o->lod_target != SCENE_LOD_DEFAULT_TARGET) return "--lod-target needs --lod screen";
    if (o->lod != TESS_LOD_DEVIATION && o->lod_deviation != SCENE_LOD_DEFAULT_DEVIATION)
        return "--lod-deviation needs --lod deviation";
    if (!o->displace && o->displace_scale != SCENE_DISPLACE_SCALE) return "--displace-scale needs --displace FILE";
    if (o->displace && o->export_obj)
        return "--export-obj writes the patch without its displacement: it cannot be combined with --displace";
    if (o->instances && o->lod != TESS_LOD_UNIFORM)
        return "--instances counts the mesh triangles of one draw: it needs --lod uniform";
    if (o->shading == SCENE_SHADING_PIXEL && (o->path != SCENE_PATH_INSTANCED || o->lod != TESS_LOD_UNIFORM || o->displace))
        return "--shading pixel evaluates the patch of the instanced path's grid points: it needs --path instanced "
               "and --lod uniform, without --displace";
    return o->lod == TESS_LOD_UNIFORM ? NULL : check_lod_opts(o);
}

/* The adaptive options' consistency (scene_check_opts for --lod distance, screen and deviation). */
const char *const scene_lod_names[] = {"uniform", "distance", "screen", "deviation", NULL};
_Static_assert(TESS_LOD_DEVIATION == 3, "scene_lod_names follows tess_lod_mode");

bool scene_parse_lod(const char *s, tess_lod_mode *out)
{
    for (int k = 0; s && scene_lod_names[k]; k++)
        if (strcmp(s, scene_lod_names[k]) == 0) return *out = (tess_lod_mode)k, true;
    return false;
}

int scene_lod_max_level(const scene_opts *o)
{
    if (o->max_level > 0) return o->max_level;
    int l = (int)lroundf(o->level);
    return l < 1 ? 1 : l;
}

static const char *check_lod_opts(const scene_opts *o)
{
    if (o->path != SCENE_PATH_INSTANCED) return "--lod distance, screen and deviation draw through instancing (--path instanced)";
    if (o->grid != CORE_GRID_REGULAR) return "--lod distance, screen and deviation use their own patterns: --grid must be regular";
    if (o->max_level == 0 && o->level != floorf(o->level))
        return "--lod distance, screen and deviation take whole levels: give --max-level (or an integer --level)";
    if (o->max_level == 0 && o->level > (float)CORE_LOD_MAX_LEVEL)
        return "--lod distance, screen and deviation need levels up to 64: give --max-level 1..64 (or a --level up to 64)";
    if (o->min_level < 1 || o->min_level > scene_lod_max_level(o)) return "--min-level must be 1..--max-level";
    if (!(o->lod_target > 0.0f)) return "--lod-target must be a positive number of pixels";
    if (!(o->lod_deviation > 0.0f)) return "--lod-deviation must be a positive number of pixels";
    return NULL;
}

/* ---------------------------------------- camera and constants ---------------------------------------- */

/* The bounding box of m's vertices into lo, hi. */
static void mesh_box(const is_mesh *m, float3 *lo_out, float3 *hi_out)
{
    float3 lo = m->positions[0], hi = lo;
    for (size_t k = 1; k < m->n_vertices; k++) {
        float3 p = m->positions[k];
        lo = f3(fminf(lo.x, p.x), fminf(lo.y, p.y), fminf(lo.z, p.z));
        hi = f3(fmaxf(hi.x, p.x), fmaxf(hi.y, p.y), fmaxf(hi.z, p.z));
    }
    *lo_out = lo, *hi_out = hi;
}

/* Centre of the bounding box and the largest distance from it to a vertex.  lo / 2 + hi / 2 (the same bits as
 * (lo + hi) / 2 without its overflow near FLT_MAX), and a distance that overflows in float is redone in double. */
static void mesh_bounds(const is_mesh *m, float3 *centre, float *radius)
{
    float3 lo, hi;
    mesh_box(m, &lo, &hi);
    *centre = add3(scale3(lo, 0.5f), scale3(hi, 0.5f));
    double r2 = 0;
    for (size_t k = 0; k < m->n_vertices; k++) {
        float3 d = sub3(m->positions[k], *centre);
        double l = (double)d.x * d.x + (double)d.y * d.y + (double)d.z * d.z;
        if (!isfinite(l)) {
            double dx = (double)m->positions[k].x - centre->x, dy = (double)m->positions[k].y - centre->y,
                   dz = (double)m->positions[k].z - centre->z;
            l = dx * dx + dy * dy + dz * dz;
        }
        if (l > r2) r2 = l;
    }
    /* a denormal radius is kept: rescaled_copy divides by it in double (1 / radius would overflow in float) */
    *radius = r2 > 0 ? (float)sqrt(r2) : 1.0f;
}

/* The matrices of a scene: g_mWorld is the object's rotation (normals are rotated, never scaled, so the
 * listing's unnormalized mul(normal, (float3x3)g_mWorld) keeps unit length); positions are first centred and
 * scaled to a unit bounding radius. */
typedef struct scene_camera {
    float4x4 world, wvp, world_view;
    float4x4 view_proj;     /* View * Proj (the displacement's direction transform, cli/run/displace.c) */
    float ref_depth;        /* the nearest depth of the unit bounding sphere (the LOD rules' reference) */
    float zn, zf, radius;   /* the projection's near and far planes (bounding radii), the mesh's bounding radius */
} scene_camera;

/* The rotation that turns the --up axis o->up (scene_up_names; the file's axes, whose z the import negated)
 * into +y, as rows: x, y, z. */
static float4x4 up_rotation(int up)
{
    static const float rows[6][3][3] = {
        {{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}},  /* x  -> +y */
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},   /* y  (identity) */
        {{1, 0, 0}, {0, 0, 1}, {0, -1, 0}},  /* z: ours -z -> +y */
        {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},  /* -x -> +y */
        {{1, 0, 0}, {0, -1, 0}, {0, 0, -1}}, /* -y -> +y */
        {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},  /* -z: ours +z -> +y */
    };
    float4x4 u = mat_identity();
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) u.m[i][j] = rows[up][i][j];
    return u;
}

/* The camera distance (in bounding radii) at which the 8 corners of m's bounding box, centred at c, scaled by
 * 1 / r and rotated by world, fit in the vertical field of view fov_deg of an image of aspect `aspect`, with a
 * margin of 5% on each side; at least 1.2 (the mesh stays in front of the near plane). */
static float box_fit_distance(const is_mesh *m, float3 c, float r, const float4x4 *world, float aspect, float fov_deg)
{
    float3 lo, hi;
    mesh_box(m, &lo, &hi);
    double ty = tan(fov_deg * PI_F / 360.0) * 0.9, tx = ty * aspect, d = 1.2;
    for (int k = 0; k < 8; k++) {
        float3 corner = f3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
        float3 q = mul3x3(scale3(sub3(corner, c), 1.0f / r), world);
        double need = fmax(fabs(q.x) / tx, fabs(q.y) / ty) - q.z;
        if (need > d) d = need;
    }
    return (float)d;
}

static scene_camera make_camera(const scene_opts *o, const is_mesh *m)
{
    float3 c;
    float r;
    mesh_bounds(m, &c, &r);
    float4x4 fit = mat_translation(-c.x, -c.y, -c.z), s = mat_scaling(1.0f / r, 1.0f / r, 1.0f / r);
    fit = mat_mul(&fit, &s);
    float4x4 ry = mat_rotation_y(o->yaw * PI_F / 180.0f), rx = mat_rotation_x(o->pitch * PI_F / 180.0f);
    scene_camera cam;
    cam.world = mat_mul(&ry, &rx);
    if (o->up != SCENE_UP_Y) {   /* (y: no product with the identity, so the images stay the same bits) */
        float4x4 u = up_rotation(o->up);
        cam.world = mat_mul(&u, &cam.world);
    }
    float aspect = (float)o->width / (float)o->height;
    float dist = o->fit == SCENE_FIT_BOX ? box_fit_distance(m, c, r, &cam.world, aspect, o->fov) : o->distance;
    float4x4 view = mat_look_at_lh(f3(0, 0, -dist), f3(0, 0, 0), f3(0, 1, 0));
    float zn = dist - 2.0f > 0.05f ? dist - 2.0f : 0.05f;
    float4x4 proj = mat_perspective_fov_lh(o->fov / 180.0f * PI_F, aspect, zn, dist + 2.0f);   /* 45 / 180 * pi: the
                                                                                                 same bits as pi / 4 */
    cam.zn = zn, cam.zf = dist + 2.0f, cam.radius = r;
    float4x4 t = mat_mul(&fit, &cam.world);
    t = mat_mul(&t, &view);
    cam.wvp = mat_mul(&t, &proj);
    cam.world_view = t;
    cam.view_proj = mat_mul(&view, &proj);
    cam.ref_depth = dist - 1.0f; /* the nearest depth of the unit bounding sphere */
    return cam;
}

tess_lod_params scene_lod_params_of(const scene_opts *o, const is_mesh *m)
{
    scene_camera cam = make_camera(o, m);
    int hi = scene_lod_max_level(o);
    if (hi > CORE_LOD_MAX_LEVEL) hi = CORE_LOD_MAX_LEVEL;
    return (tess_lod_params){.mode = o->lod, .target_px = o->lod == TESS_LOD_DEVIATION ? o->lod_deviation : o->lod_target,
                              .ref_depth = cam.ref_depth,
                              .min_level = o->min_level < hi ? o->min_level : hi, .max_level = hi,
                              .width = o->width, .height = o->height, .silhouette = o->silhouette,
                              .world_view = cam.world_view, .wvp = cam.wvp};
}

/* The AOV outputs of the patch shaders (vs/vs.h): TEXCOORD1 normal, 2 barycentrics, 3 instance, 4 Gregory. */

/* The listing's constants for the scene's matrices, a diffuse colour and the patch options. */
static void fill_constants(is_vs_constants *c, const scene_opts *o, const float4x4 *wvp, const float4x4 *world,
                           const float diffuse[4])
{
    vs_options vo = vs_default_options();
    vo.normals = o->normals;
    vo.phong_alpha = o->phong_alpha, vo.quad_factor = o->n110_factor;
    vs_set_constants(c, wvp, world, f4(diffuse[0], diffuse[1], diffuse[2], diffuse[3]), &vo);
}

/* Upload the constants (SetVertexShaderConstantF c0..c9). */
static void set_constants(is_device *dev, const scene_opts *o, const scene_camera *cam, const float diffuse[4])
{
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    fill_constants(&c, o, &cam->wvp, &cam->world, diffuse);
    dev_set_vertex_shader_constant_f(dev, 0, &c.c[0].x, VS_C_COUNT);
}

/* ---------------------------------------- buffers ---------------------------------------- */

/* The vertex of the non-instanced paths: position, normal, texcoord (declaration vs_tnl_declaration). */
typedef struct tnl_vertex { float3 p, n; float2 t; } tnl_vertex;
static const is_vertex_element tnl_declaration[] = {
    {0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
    {0, 12, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_NORMAL, 0},
    {0, 24, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TEXCOORD, 0},
    IS_DECL_END};

/* Bind a non-instanced vertex buffer of tnl_vertex and an index buffer. */
static is_result bind_tnl(is_device *dev, tess_resources *r, const uint32_t *idx, size_t n_idx, size_t n_vtx)
{
    is_result e = tess_index_buffer(dev, idx, n_idx, n_vtx, &r->ib);
    if (e == IS_OK) e = dev_create_vertex_declaration(dev, tnl_declaration, &r->decl);
    if (e != IS_OK) return e;
    dev_set_vertex_declaration(dev, r->decl);
    dev_set_stream_source(dev, 0, r->vb0, 0, sizeof(tnl_vertex));
    dev_set_indices(dev, r->ib);
    r->n_vertices = (unsigned)n_vtx, r->n_prims = (unsigned)(n_idx / 3), r->n_instances = 1;
    return IS_OK;
}

/* The device's N-patch mode: the mesh itself in stream 0, SetNPatchMode(level) and the degrees. */
static is_result build_npatch_mode(is_device *dev, const scene_opts *o, const is_mesh *m, tess_resources *r)
{
    is_result e = dev_create_vertex_buffer(dev, m->n_vertices * sizeof(tnl_vertex), &r->vb0);
    if (e != IS_OK) return e;
    tnl_vertex *v = vb_lock(r->vb0);
    for (size_t k = 0; k < m->n_vertices; k++) v[k] = (tnl_vertex){m->positions[k], m->normals[k], m->texcoords[k]};
    e = bind_tnl(dev, r, m->indices, 3 * m->n_triangles, m->n_vertices);
    if (e != IS_OK) return e;
    dev_set_npatch_evaluator(dev, vs_npatch_evaluate);
    dev_set_npatch_mode(dev, o->level);
    dev_set_render_state(dev, IS_RS_PATCHEDGESTYLE,
                         o->grid == CORE_GRID_PG_FRACTIONAL_EVEN ? IS_PATCHEDGE_CONTINUOUS : IS_PATCHEDGE_DISCRETE);
    dev_set_render_state(dev, IS_RS_POSITIONDEGREE, o->patch == VS_PATCH_FLAT ? IS_DEGREE_LINEAR : IS_DEGREE_CUBIC);
    dev_set_render_state(dev, IS_RS_NORMALDEGREE,
                         o->normals == VS_NORMALS_QUADRATIC ? IS_DEGREE_QUADRATIC : IS_DEGREE_LINEAR);
    return IS_OK;
}

/* CPU tessellation (D3DXTessellateNPatches-style): every grid point of every triangle evaluated on all cores
 * into a dynamic vertex buffer, drawn without instancing. */
static is_result build_cpu(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g,
                           tess_resources *r)
{
    const size_t np = g->n_points, nt = g->n_triangles, T = m->n_triangles;
    is_result e = dev_create_vertex_buffer(dev, T * np * sizeof(tnl_vertex), &r->vb0);
    uint32_t *idx = e == IS_OK ? malloc(T * nt * 3 * sizeof *idx) : NULL;
    if (!idx) return e == IS_OK ? IS_ERR_OUTOFMEMORY : e;
    tnl_vertex *v = vb_lock(r->vb0);
    uint32_t pdeg = o->patch == VS_PATCH_FLAT ? IS_DEGREE_LINEAR : IS_DEGREE_CUBIC;
    uint32_t ndeg = o->normals == VS_NORMALS_QUADRATIC ? IS_DEGREE_QUADRATIC : IS_DEGREE_LINEAR;
#pragma omp parallel for schedule(static) num_threads(o->threads > 0 ? o->threads : omp_get_num_procs())
    for (long t = 0; t < (long)T; t++) {
        const uint32_t *tri = &m->indices[3 * t];
        float3 p[3] = {m->positions[tri[0]], m->positions[tri[1]], m->positions[tri[2]]};
        float3 n[3] = {m->normals[tri[0]], m->normals[tri[1]], m->normals[tri[2]]};
        for (size_t k = 0; k < np; k++) {
            float3 b = g->bary[k];
            tnl_vertex *out = &v[(size_t)t * np + k];
            vs_npatch_evaluate(p, n, b, pdeg, ndeg, &out->p, &out->n);
            for (int c = 0; c < 2; c++) {
                const float *t0 = &m->texcoords[tri[0]].x, *t1 = &m->texcoords[tri[1]].x, *t2 = &m->texcoords[tri[2]].x;
                (&out->t.x)[c] = b.x * t0[c] + b.y * t1[c] + b.z * t2[c];
            }
        }
        for (size_t k = 0; k < 3 * nt; k++) idx[(size_t)t * 3 * nt + k] = (uint32_t)((size_t)t * np) + g->idx[k];
    }
    e = bind_tnl(dev, r, idx, T * nt * 3, T * np);
    free(idx);
    return e;
}

/* ---------------------------------------- drawing ---------------------------------------- */

/* The shader of a path: the patch's own on the instanced path, fixed transform-and-light otherwise. */
static const is_vertex_shader *path_shader(const scene_opts *o)
{
    return o->path == SCENE_PATH_INSTANCED ? vs_patch_shader(o->patch) : &vs_shader_fixed;
}

/* The wireframe overlay's states: the same triangles' edges, pulled slightly towards the eye so they win the
 * depth test. */
static void set_overlay_states(is_device *dev)
{
    float bias = -2e-5f, slope = -1.0f;
    uint32_t bb, sb;
    memcpy(&bb, &bias, 4), memcpy(&sb, &slope, 4);
    dev_set_render_state(dev, IS_RS_FILLMODE, IS_FILL_WIREFRAME);
    dev_set_render_state(dev, IS_RS_DEPTHBIAS, bb);
    dev_set_render_state(dev, IS_RS_SLOPESCALEDEPTHBIAS, sb);
}

/* Issue the draw(s) of the fill mode on a device whose buffers are bound. */
static is_result draw_fill(is_device *dev, const scene_opts *o, const scene_camera *cam, const tess_resources *r)
{
    const int fills[4] = {IS_FILL_SOLID, IS_FILL_WIREFRAME, IS_FILL_SOLID, IS_FILL_POINT};
    static const float white[4] = {1, 1, 1, 1};   /* --light normals: the normal is the colour */
    dev_set_render_state(dev, IS_RS_FILLMODE, (uint32_t)fills[o->fill]);
    set_constants(dev, o, cam, o->light == SCENE_LIGHT_NORMALS ? white : o->diffuse);
    if (o->shading == SCENE_SHADING_PIXEL || o->texture) scene_shading_constants(dev, o);
    is_result e = dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, r->n_vertices, 0, r->n_prims);
    if (e != IS_OK || o->fill != SCENE_FILL_SOLID_WIRE) return e;
    dev_set_pixel_shader(dev, NULL);   /* the wire overlay keeps its colour */
    set_overlay_states(dev);
    set_constants(dev, o, cam, o->wire_color);
    return dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, r->n_vertices, 0, r->n_prims);
}

/* The colour of a level for wireframes coloured by level: blue (1) through green (8) to red (64), by log2. */
static void level_color(int level, float rgba[4])
{
    float x = log2f((float)level) / 6.0f; /* 0 at level 1, 1 at 64 */
    rgba[0] = saturate(2.0f * x - 0.6f), rgba[1] = saturate(1.2f - fabsf(2.4f * x - 1.2f)), rgba[2] = saturate(1.0f - 2.0f * x);
    rgba[3] = 1.0f;
}

/* One pass over every bucket of a; with by_level each bucket's colour is its finest level's, else `color`. */
static is_result draw_buckets(is_device *dev, const scene_opts *o, const scene_camera *cam, const tess_adaptive *a,
                              bool by_level, const float color[4])
{
    is_result e = IS_OK;
    if (!by_level) set_constants(dev, o, cam, color);
    if (!by_level && o->texture) scene_shading_constants(dev, o);
    for (size_t k = 0; k < a->n_buckets && e == IS_OK; k++) {
        float c[4];
        if (by_level) level_color(a->buckets[k].level[2], c), set_constants(dev, o, cam, c);
        if (by_level && o->texture) scene_shading_constants(dev, o);
        e = tess_draw_bucket(dev, a, k);
    }
    return e;
}

/* draw_fill for an adaptive draw: every bucket per pass, the wireframe coloured by level if o asks. */
static is_result draw_fill_adaptive(is_device *dev, const scene_opts *o, const scene_camera *cam,
                                    const tess_adaptive *a)
{
    const int fills[4] = {IS_FILL_SOLID, IS_FILL_WIREFRAME, IS_FILL_SOLID, IS_FILL_POINT};
    dev_set_render_state(dev, IS_RS_FILLMODE, (uint32_t)fills[o->fill]);
    static const float white[4] = {1, 1, 1, 1};   /* --light normals: the normal is the colour */
    is_result e = draw_buckets(dev, o, cam, a, o->fill == SCENE_FILL_WIRE && o->wire_by_level,
                               o->light == SCENE_LIGHT_NORMALS ? white : o->diffuse);
    if (e != IS_OK || o->fill != SCENE_FILL_SOLID_WIRE) return e;
    dev_set_pixel_shader(dev, NULL);   /* the wire overlay keeps its colour */
    set_overlay_states(dev);
    return draw_buckets(dev, o, cam, a, o->wire_by_level, o->wire_color);
}

/* Bind the buffers of o->path on dev. */
static is_result build_path(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g,
                            tess_resources *r)
{
    switch (o->path) {
    case SCENE_PATH_NPATCH_MODE: return build_npatch_mode(dev, o, m, r);
    case SCENE_PATH_CPU: return build_cpu(dev, o, m, g, r);
    default: {
        is_result e = tess_bind_instanced(dev, m, g, r);
        return e == IS_OK && o->patch == VS_PATCH_PN_AEN ? tess_bind_adjacent_normals(dev, m, r, NULL) : e;
    }
    }
}

/* --d3d9-adaptive's states on dev (scene.h); nothing when it is off. */
static void set_d3d9_adaptive(is_device *dev, const scene_opts *o, const scene_camera *cam)
{
    if (o->d3d9_adaptive == SCENE_D3D9_OFF) return;
    float mdm[4], lo = 1.0f;
    for (int i = 0; i < 4; i++) /* depth: the view-depth column of World * View over the nearest point's depth */
        mdm[i] = o->d3d9_adaptive == SCENE_D3D9_DEPTH ? cam->world_view.m[i][2] / cam->ref_depth : o->d3d9_mdm[i];
    uint32_t u;
    for (int i = 0; i < 4; i++) memcpy(&u, &mdm[i], 4), dev_set_render_state(dev, (is_rs)(IS_RS_ADAPTIVETESS_X + i), u);
    memcpy(&u, &lo, 4), dev_set_render_state(dev, IS_RS_MINTESSELLATIONLEVEL, u);
    memcpy(&u, &o->level, 4), dev_set_render_state(dev, IS_RS_MAXTESSELLATIONLEVEL, u);
    dev_set_render_state(dev, IS_RS_ENABLEADAPTIVETESSELLATION, 1);
}

/* Set the shader that draws o's scene (path: the path's shader; shader: the caller's, or NULL) with its
 * constants: the light's wrapper, and with --displace the displacement's wrapper and its map, bound in vertex
 * sampler 0 as *dmap (the caller releases it after the draw).  IS_OK or the device's error. */
static is_result set_scene_shader(is_device *dev, const scene_opts *o, const scene_camera *cam,
                                  const is_vertex_shader *path, const is_vertex_shader *shader, is_texture **dmap)
{
    const is_vertex_shader *s = shader ? shader : path;
    if (o->displace) {
        is_result e = scene_displace_bind(dev, o, &cam->view_proj, cam->radius, s, dmap);
        if (e != IS_OK) return e;
        if (!shader) s = scene_displace_shader(o, s);
    }
    if (!shader) {
        scene_light_constants(dev, o, s);
        s = scene_light_shader(o, s);
    }
    return dev_set_vertex_shader(dev, s);
}

/* The adaptive draw of scene_draw (o->lod distance or screen): per-edge levels, buckets of patterns, one instanced
 * draw per bucket and pass; the levels' histogram and counts into st if not NULL.  0 or -1. */
/* Bytes the patterns of the distinct sorted edge-level triples of m's triangles (levels in e) take at most -- the
 * pool on the host, then the device's vertex and index buffers (both windings): 24 bytes per point and 36 per
 * triangle of the regular grid of the triple's finest level, which a pattern never exceeds -- with the number of
 * triples in *n; ULLONG_MAX when out of memory for counting. */
static unsigned long long pattern_pool_bytes(const is_mesh *m, const tess_lod_edges *e, size_t *n)
{
    enum { L = CORE_LOD_MAX_LEVEL };
    uint8_t *seen = calloc((size_t)L * L * L / 8, 1);
    if (!seen) return ULLONG_MAX;
    unsigned long long bytes = 0;
    *n = 0;
    for (size_t t = 0; t < m->n_triangles; t++) {
        int v[3];
        for (int k = 0; k < 3; k++) v[k] = e->level[e->tri_edge[3 * t + k]];
        int lo = v[0] < v[1] ? v[0] : v[1], hi = v[0] < v[1] ? v[1] : v[0];
        int a = lo < v[2] ? lo : v[2], c = hi > v[2] ? hi : v[2], b = v[0] + v[1] + v[2] - a - c;
        size_t key = ((size_t)(a - 1) * L + (size_t)(b - 1)) * L + (size_t)(c - 1);
        if (seen[key / 8] & (1u << (key % 8))) continue;
        seen[key / 8] |= (uint8_t)(1u << (key % 8));
        (*n)++;
        bytes += 24ull * core_grid_points(c) + 36ull * core_grid_triangles(c);
    }
    free(seen);
    return bytes;
}

/* Whether the patterns of levels e fit in what --max-memory leaves after the render's estimate; else the message
 * in err (the pool grows with the distinct level triples, up to 45,760 patterns of up to 200 KB). */
static bool patterns_fit(const scene_opts *o, const is_mesh *m, const tess_lod_edges *e, char *err, size_t errlen)
{
    size_t n = 0;
    const unsigned long long pool = pattern_pool_bytes(m, e, &n), budget = (unsigned long long)o->max_memory_mib << 20;
    const unsigned long long used =
        scene_memory_estimate(o, m->n_triangles, core_grid_points(scene_lod_max_level(o)));
    if (pool != ULLONG_MAX && used <= budget && pool <= budget - used) return true;
    if (pool == ULLONG_MAX) snprintf(err, errlen, "%s: out of memory for counting the edge-level triples", m->name);
    else snprintf(err, errlen, "%s: --lod %s gives %zu distinct edge-level triples, whose patterns need about %llu "
                  "MiB besides the render's %llu MiB, more than the memory budget of %u MiB (--max-memory MIB raises "
                  "it; --max-level lowers the need)", m->name, scene_lod_names[o->lod], n, (pool + (1u << 20) - 1) >> 20,
                  (used + (1u << 20) - 1) >> 20, o->max_memory_mib);
    return false;
}

/* --instances N on the bound path r: the instanced draw's count (stream 0's INDEXEDDATA | N), or the first N
 * triangles' share of the N-patch mode's and the CPU path's primitives. */
static void limit_instances(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g,
                            tess_resources *r)
{
    unsigned n = o->instances < m->n_triangles ? o->instances : (unsigned)m->n_triangles;
    if (o->path == SCENE_PATH_INSTANCED) dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | n);
    else if (o->path == SCENE_PATH_NPATCH_MODE) r->n_prims = n;
    else r->n_prims = n * (unsigned)g->n_triangles;
}

/* The pixel shader and the textures of --shading pixel (itex) and --texture (ttex) off dev, and released. */
static void unbind_pixel_stage(is_device *dev, is_texture *itex, is_texture *ttex)
{
    if (!itex && !ttex) return;
    dev_set_pixel_shader(dev, NULL);
    dev_set_texture(dev, 0, NULL);
    dev_set_texture(dev, SCENE_TEXTURE_SAMPLER, NULL);
    tex_release(itex);
    tex_release(ttex);
}

/* The adaptive draw: 0, or -1 with the reason in err (or, when err is empty, in dev_last_error). */
static int draw_adaptive(is_device *dev, const scene_opts *o, const is_mesh *m, const is_vertex_shader *shader,
                         scene_stats *st, char *err, size_t errlen)
{
    scene_camera cam = make_camera(o, m);
    tess_lod_params p = scene_lod_params_of(o, m);
    tess_lod_edges e;
    tess_adaptive a = {0};
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    core_pattern_cache *cache = core_pattern_cache_create(0);
    if (!cache) return snprintf(err, errlen, "%s: out of memory for the pattern cache", m->name), -1;
    if (tess_lod_edges_build(m, &e, err, errlen) != 0) return core_pattern_cache_destroy(cache), -1;
    tess_lod_levels(&p, m, &e, hist);
    if (!patterns_fit(o, m, &e, err, errlen)) {
        tess_lod_edges_free(&e);
        core_pattern_cache_destroy(cache);
        return -1;
    }
    is_texture *dmap = NULL, *ttex = NULL;
    is_result r = set_scene_shader(dev, o, &cam, vs_patch_shader(o->patch), shader, &dmap);
    if (r == IS_OK) r = tess_bind_adaptive(dev, m, &e, cache, &a);
    if (r == IS_OK && o->patch == VS_PATCH_PN_AEN) r = tess_bind_adjacent_normals(dev, m, &a.r, &a);
    if (r == IS_OK && o->texture) r = scene_texture_bind(dev, o, &ttex);
    if (r == IS_OK) r = draw_fill_adaptive(dev, o, &cam, &a);
    unbind_pixel_stage(dev, NULL, ttex);
    if (st) {
        memcpy(st->level_hist, hist, sizeof hist);
        st->n_buckets = a.n_buckets, st->n_patterns = a.n_patterns, st->tessellated_triangles = a.n_triangles;
    }
    tess_adaptive_free(&a);
    tess_lod_edges_free(&e);
    core_pattern_cache_destroy(cache);
    tex_release(dmap);
    return r == IS_OK ? 0 : -1;
}

/* scene_draw with the adaptive draw's statistics into st (may be NULL); -1 with a message in err, or err left
 * empty when dev_last_error says why. */
static int draw_scene(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g,
                      const is_vertex_shader *shader, scene_stats *st, char *err, size_t errlen)
{
    if (o->lod != TESS_LOD_UNIFORM && o->path == SCENE_PATH_INSTANCED)
        return draw_adaptive(dev, o, m, shader, st, err, errlen);
    return scene_draw(dev, o, m, g, shader);
}

int scene_draw(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g,
               const is_vertex_shader *shader)
{
    char why[400] = "";
    if (o->lod != TESS_LOD_UNIFORM && o->path == SCENE_PATH_INSTANCED)
        return draw_adaptive(dev, o, m, shader, NULL, why, sizeof why);   /* the reason: dev_last_error's, or lost */
    scene_camera cam = make_camera(o, m);
    tess_resources r = {0};
    is_texture *dmap = NULL, *itex = NULL, *ttex = NULL;
    is_result e = set_scene_shader(dev, o, &cam, path_shader(o), shader, &dmap);
    if (e == IS_OK) e = build_path(dev, o, m, g, &r);
    if (e == IS_OK && o->instances) limit_instances(dev, o, m, g, &r);
    if (e == IS_OK && o->path == SCENE_PATH_NPATCH_MODE) set_d3d9_adaptive(dev, o, &cam);
    if (e == IS_OK && o->shading == SCENE_SHADING_PIXEL) e = scene_shading_bind(dev, o, m, &itex);
    if (e == IS_OK && o->texture) e = scene_texture_bind(dev, o, &ttex);
    if (e == IS_OK) e = draw_fill(dev, o, &cam, &r);
    unbind_pixel_stage(dev, itex, ttex);
    tess_resources_free(&r);
    tex_release(dmap);
    return e == IS_OK ? 0 : -1;
}

is_device *scene_create_device(const scene_opts *o, int samples, unsigned aovs, char *err, size_t errlen)
{
    is_device *dev = dev_create(o->width, o->height, samples, err, errlen);
    if (!dev) return NULL;
    dev_set_threads(dev, o->threads);
    for (size_t k = 0; k < SCENE_AOV_COUNT; k++) {   /* planes in the table's (the channels') order */
        const scene_aov *a = &scene_aov_table[k];
        if ((aovs & a->bit) && a->slot >= 0 &&
            rs_target_add_aov(dev_render_target(dev), RS_ATTR_TEXCOORD0 + a->slot, a->comps) != RS_OK) {
            /* a plane missing would leave its channels silently empty in the image */
            snprintf(err, errlen, "out of memory for the AOV planes of a %dx%d target", o->width, o->height);
            dev_destroy(dev);
            return NULL;
        }
    }
    return dev;
}

int scene_render_on(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g, scene_stats *st,
                    char *err, size_t errlen)
{
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, o->background, 1.0f);
    /* the cull mode is the render's, set on every draw: a device reset between frames (the viewer's) is back at
     * D3D9's ccw, so setting it only when the device is made drew the first frame alone as --cull says */
    dev_set_render_state(dev, IS_RS_CULLMODE, o->cull);
    char why[600] = "";
    /* dev_flush: the recorded draws run, and a failure found only then (the work bound) is reported */
    if (draw_scene(dev, o, m, g, NULL, st, why, sizeof why) != 0 || (!why[0] && dev_flush(dev) != IS_OK))
        return why[0] ? snprintf(err, errlen, "%s", why)
                      : snprintf(err, errlen, "%s: rendering failed: %s", m->name, dev_last_error(dev)), -1;
    if (st) {
        st->vertices_shaded += dev_vertices_shaded(dev);
        st->triangles_drawn += dev_stats(dev)->prims_drawn;
        st->raster = *dev_stats(dev);
    }
    return 0;
}

is_device *scene_render_view(const scene_opts *o, const is_mesh *m, const core_grid *g, int samples, unsigned aovs,
                             scene_stats *st, char *err, size_t errlen)
{
    is_device *dev = scene_create_device(o, samples, aovs, err, errlen);
    if (dev && scene_render_on(dev, o, m, g, st, err, errlen) != 0) {
        dev_destroy(dev);
        return NULL;
    }
    return dev;
}

/* Channel names of the image: R,G,B,A,Z then the AOVs in scene_aov_table's order. */
static void channel_list(unsigned aovs, char *buf, size_t len)
{
    size_t k = (size_t)snprintf(buf, len, "R,G,B,A,Z");
    for (int a = 0; a < SCENE_AOV_COUNT; a++)
        if (aovs & scene_aov_table[a].bit)
            k += (size_t)snprintf(buf + k, k < len ? len - k : 0, ",%s", scene_aov_table[a].channels);
}

unsigned scene_aovs_of(const scene_opts *o)
{
    return o->aovs | (o->texture && o->output && has_ext(o->output, ".exr") ? SCENE_AOV_UV : 0u);
}

int scene_copy_color_depth(const rs_target *rt, is_image *img, char *err, size_t errlen)
{
    size_t n = (size_t)rt->width * rt->height;
    uint32_t *rgba = malloc(n * sizeof *rgba);
    if (!rgba) return snprintf(err, errlen, "out of memory for a %dx%d image", rt->width, rt->height), -1;
    rs_target_resolve(rt, rgba);
    image_from_rgba8(img, rgba);
    free(rgba);
    for (size_t p = 0; p < n; p++) {
        const float *d = &rt->depth[p * rt->samples];
        float z = d[0];
        int covered = d[0] < 1.0f;
        for (int s = 1; s < rt->samples; s++) z = fminf(z, d[s]), covered += d[s] < 1.0f;
        img->data[p * img->channels + 3] = (float)covered / (float)rt->samples;
        img->data[p * img->channels + 4] = z;
    }
    return 0;
}

/* Copy the AOV planes of rt (one sample per pixel) into img's channels from `first` on; on the background
 * (depth still the clear value 1) `instance` becomes SCENE_INSTANCE_BACKGROUND; `depth` is the view-space depth
 * of the projection of cam, from the depth buffer. */
static void copy_aovs(const rs_target *rt, const scene_camera *cam, is_image *img, int first)
{
    size_t n = (size_t)rt->width * rt->height;
    int c = first;
    for (int a = 0; a < rt->n_aov; a++) {
        for (size_t p = 0; p < n; p++)
            for (int k = 0; k < rt->aov[a].comps; k++)
                img->data[p * img->channels + c + k] = rt->aov[a].data[p * rt->aov[a].comps + k];
        c += rt->aov[a].comps;
    }
    int inst = image_channel_index(img, "instance"), depth = image_channel_index(img, "depth");
    double zn = cam->zn, zf = cam->zf;
    for (size_t p = 0; p < n; p++) {
        float d = rt->depth[p];
        if (inst >= 0 && d >= 1.0f) img->data[p * img->channels + inst] = SCENE_INSTANCE_BACKGROUND;
        /* D3DXMatrixPerspectiveFovLH: d = zf / (zf - zn) - zn zf / ((zf - zn) z), solved for z */
        if (depth >= 0)
            img->data[p * img->channels + depth] =
                d >= 1.0f ? INFINITY : (float)(zn * zf / (zf - d * (zf - zn)) * cam->radius);
    }
}

/* The sRGB transfer function's inverse: a display value in [0, 1] as linear light. */
static float srgb_to_linear(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

void scene_picture_for_format(is_image *img, is_image_format fmt, uint32_t background)
{
    const float bg[3] = {(float)((background >> 16) & 0xffu) / 255.0f, (float)((background >> 8) & 0xffu) / 255.0f,
                         (float)(background & 0xffu) / 255.0f};
    size_t n = (size_t)img->width * img->height;
    for (size_t p = 0; p < n; p++) {
        float *px = &img->data[p * img->channels], a = px[3];
        if (fmt != IS_IMAGE_EXR) {
            px[3] = 1.0f;   /* PNG: the display values over the background, opaque */
            continue;
        }
        /* EXR: the resolved colour C = a F + (1 - a) B solved for F, decoded from sRGB, premultiplied by a */
        for (int k = 0; k < 3; k++) {
            float f = a > 0.0f ? (px[k] - (1.0f - a) * bg[k]) / a : 0.0f;
            px[k] = srgb_to_linear(saturate(f)) * a;
        }
    }
}

int scene_write_picture(is_outputs *outs, int k, const is_image *img, uint32_t background, const is_image_meta *meta,
                        char *err, size_t errlen)
{
    is_image file = {0};
    char names[IS_IMAGE_MAX_CHANNELS * 17] = "";
    for (int c = 0; c < img->channels; c++)
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", c ? "," : "", img->channel_names[c]);
    if (img->channels < 4 || strcmp(img->channel_names[3], "A") != 0)
        return snprintf(err, errlen, "%s: not a picture (R, G, B, A first)", outs->f[k].path), -1;
    if (image_alloc(&file, img->width, img->height, names, err, errlen) != 0) return -1;
    memcpy(file.data, img->data, (size_t)img->width * img->height * img->channels * sizeof *file.data);
    scene_picture_for_format(&file, image_format_of(outs->f[k].path), background);
    int rc = image_write_output(outs, k, &file, meta, err, errlen);
    image_free(&file);
    return rc;
}

/* Coordinates beyond 1e6 or a bounding radius below 1e-6: the shaders' float intermediates (squared edge
 * lengths, control points before their /3, and the real normals' cross products of derivatives, which are of
 * the order of the size squared and underflow at a size of 1e-12) would lose precision, overflow or underflow.
 * Such a mesh is drawn from a copy moved to the origin and scaled to unit radius (patches are affine-invariant,
 * and the camera frames the mesh by its bounds anyway).  Other meshes are drawn as they are. */
#define SCENE_EXTREME_COORD 1e6f

static int render_mesh(const scene_opts *o, const is_mesh *m, float unit, is_image *img, scene_stats *st,
                       char *err, size_t errlen);

/* The copy of m with positions (p - c) / r described above into out, r into *scale; 0, or -1 when m is not
 * extreme or the copy fails (m is then drawn as it is). */
static int rescaled_copy(const is_mesh *m, is_mesh *out, float *scale)
{
    float3 c;
    float r;
    mesh_bounds(m, &c, &r);
    float far = fmaxf(fmaxf(fabsf(c.x), fabsf(c.y)), fabsf(c.z)) + r;
    if (far <= SCENE_EXTREME_COORD && r >= 1.0f / SCENE_EXTREME_COORD) return -1;
    float3 *p = malloc(m->n_vertices * sizeof *p);
    if (!p) return -1;
    for (size_t k = 0; k < m->n_vertices; k++)
        p[k] = f3((float)(((double)m->positions[k].x - c.x) / r), (float)(((double)m->positions[k].y - c.y) / r),
                  (float)(((double)m->positions[k].z - c.z) / r));
    is_mesh_data d = {m->n_vertices, m->n_triangles, p, m->normals, m->texcoords, m->indices};
    int rc = mesh_create(out, m->name, &d, NULL, NULL, 0);
    free(p);
    *scale = r;
    return rc == 0 ? 0 : -1;
}

const is_mesh *scene_fit_mesh(const is_mesh *mesh, is_mesh *copy)
{
    float scale;
    *copy = (is_mesh){0};
    return rescaled_copy(mesh, copy, &scale) == 0 ? copy : mesh;
}

int scene_render_picture(const scene_opts *o, const is_mesh *mesh, is_image *img, scene_stats *st, char *err,
                         size_t errlen)
{
    is_mesh copy = {0};
    float scale = 1.0f;
    const is_mesh *m = rescaled_copy(mesh, &copy, &scale) == 0 ? &copy : mesh;
    int rc = render_mesh(o, m, m == &copy ? scale : 1.0f, img, st, err, errlen);
    mesh_free(&copy);
    return rc;
}

int scene_render_mesh(const scene_opts *o, const is_mesh *mesh, is_image *img, scene_stats *st, char *err,
                      size_t errlen)
{
    int rc = scene_render_picture(o, mesh, img, st, err, errlen);
    is_image_format fmt = o->output ? image_format_of(o->output) : IS_IMAGE_PNG;
    if (rc == 0) scene_picture_for_format(img, fmt, o->background);
    return rc;
}

unsigned long long scene_memory_estimate(const scene_opts *o, size_t mesh_triangles, size_t grid_points)
{
    unsigned long long px = (unsigned long long)o->width * (unsigned long long)o->height;
    unsigned long long bytes = px * ((unsigned long long)o->msaa * 8 + 4 + 5 * 4);   /* target, resolve, image */
    if (scene_aovs_of(o)) {   /* the AOV device's target and planes, the channels: every AOV's, at most */
        unsigned long long c = 0;
        for (int a = 0; a < SCENE_AOV_COUNT; a++) c += (unsigned long long)scene_aov_table[a].comps;
        bytes += px * (8 + 4 + c * 4 + (c + 1) * 4);
    }
    bytes += (unsigned long long)mesh_triangles * (sizeof(is_patch_instance) + 64);
    if (o->path == SCENE_PATH_CPU)
        bytes += SCENE_CPU_BYTES_PER_VERTEX * (unsigned long long)mesh_triangles * grid_points;
    if (o->lod != TESS_LOD_UNIFORM)   /* the pattern cache's bound and index, the renumbered instances and keys */
        bytes += CORE_PATTERN_CACHE_DEFAULT_BYTES + 4ull * CORE_LOD_MAX_LEVEL * CORE_LOD_MAX_LEVEL * CORE_LOD_MAX_LEVEL +
                 (unsigned long long)mesh_triangles * (sizeof(is_patch_instance) + 16);
    return bytes;
}

int scene_check_limits(const scene_opts *o, const is_mesh *m, const core_grid *g, char *err, size_t errlen)
{
    if ((unsigned long long)g->n_points * m->n_triangles > SCENE_MAX_VERTICES)
        return snprintf(err, errlen, "%s: %zu triangles at level %g need %llu vertices, more than the limit %llu",
                        m->name, m->n_triangles, (double)o->level, (unsigned long long)g->n_points * m->n_triangles,
                        (unsigned long long)SCENE_MAX_VERTICES), -1;
    unsigned long long need = scene_memory_estimate(o, m->n_triangles, g->n_points);
    if (need > (unsigned long long)o->max_memory_mib << 20)
        return snprintf(err, errlen, "%s: %zu triangles at level %g on this path need about %llu MiB, more than the "
                        "memory budget of %u MiB (--max-memory MIB raises it)", m->name, m->n_triangles,
                        (double)o->level, (need + (1u << 20) - 1) >> 20, o->max_memory_mib), -1;
    return 0;
}

/* scene_render_mesh on a mesh of ordinary coordinates, whose unit is `unit` of the mesh's own (for the depth
 * AOV). */
static int render_mesh(const scene_opts *o, const is_mesh *m, float unit, is_image *img, scene_stats *st,
                       char *err, size_t errlen)
{
    core_grid g;
    /* an adaptive render is checked against its finest level everywhere (its grid is not drawn) */
    const bool adaptive = o->lod != TESS_LOD_UNIFORM;
    if (core_grid_make(adaptive ? CORE_GRID_REGULAR : o->grid, adaptive ? (float)scene_lod_max_level(o) : o->level,
                       &g) != 0) {
        snprintf(err, errlen, "level %g: cannot build the grid", (double)o->level);
        return -1;
    }
    if (scene_check_limits(o, m, &g, err, errlen) != 0) {
        core_grid_free(&g);
        return -1;
    }
    if (st) memset(st, 0, sizeof *st), st->mesh_triangles = m->n_triangles, st->grid_points = g.n_points,
            st->grid_triangles = g.n_triangles;
    char names[256];
    const unsigned aovs = scene_aovs_of(o);
    channel_list(aovs, names, sizeof names);
    int rc = -1;
    is_device *dev = scene_render_view(o, m, &g, o->msaa, 0, st, err, errlen);
    if (dev && image_alloc(img, o->width, o->height, names, err, errlen) == 0) {
        rc = scene_copy_color_depth(dev_render_target(dev), img, err, errlen);
        if (rc != 0) image_free(img);
        if (rc == 0 && aovs) {
            is_device *adev = scene_render_view(o, m, &g, 1, aovs, NULL, err, errlen);
            scene_camera cam = make_camera(o, m);
            cam.radius *= unit;
            if (adev) copy_aovs(dev_render_target(adev), &cam, img, 5);
            else rc = -1, image_free(img);
            dev_destroy(adev);
        }
    }
    dev_destroy(dev);
    core_grid_free(&g);
    return rc;
}

/* ---------------------------------------- files ---------------------------------------- */

/* One tessellated vertex of the export in the OBJ file's frame: OBJ is right-handed with counter-clockwise
 * fronts and v up, and assimp's ConvertToLeftHanded (z -> -z, winding flipped, v -> 1 - v) turned the file into
 * this program's frame; the export undoes it, so that an OBJ input comes back in its own coordinates and any
 * export reads back (through assimp) as the mesh that was rendered. */
static void write_obj_vertex(FILE *f, const is_vs_output *out, float2 t)
{
    float4 n = out->attr[RS_ATTR_TEXCOORD0 + VS_OUT_NORMAL];
    fprintf(f, "v %.9g %.9g %.9g\nvt %.9g %.9g\nvn %.9g %.9g %.9g\n", out->pos.x, out->pos.y, -out->pos.z, t.x,
            1.0f - t.y, n.x, n.y, -n.z);
}

/* The texture coordinates of instance inst at barycentrics b (the corners' interpolated, as the CPU path). */
static float2 instance_texcoord(const is_patch_instance *inst, float3 b)
{
    return f2(b.x * inst->t[0].x + b.y * inst->t[1].x + b.z * inst->t[2].x,
              b.x * inst->t[0].y + b.y * inst->t[1].y + b.z * inst->t[2].y);
}

/* The export's frame, said in its header. */
#define OBJ_FRAME "# right-handed, counter-clockwise fronts, v up (the OBJ convention; the input's own frame)\n"

/* What the OBJ export evaluates with: the patch shader with identity matrices, as the renderer does. */
typedef struct obj_writer {
    FILE *f;
    is_vs_constants c;
    const is_vertex_shader *vs;
    size_t next;   /* the OBJ index of the next vertex */
} obj_writer;

/* Write grid g's points evaluated on instance inst (with PN-AEN's neighbour normals nadj, or NULL), then its
 * faces (indices 1 and 2 swapped when flip). */
static void obj_triangle(obj_writer *w, const is_patch_instance *inst, const float3 (*nadj)[2], const core_grid *g,
                         bool flip)
{
    for (size_t p = 0; p < g->n_points; p++) {
        is_vs_input in;
        is_vs_output out;
        tess_input_from_instance(inst, nadj, g->bary[p], &in);
        memset(&out, 0, sizeof out);
        w->vs->main(&w->c, &in, &out);
        write_obj_vertex(w->f, &out, instance_texcoord(inst, g->bary[p]));
    }
    for (size_t q = 0; q < g->n_triangles; q++) {   /* clockwise here (unless flip), so corners 0, 2, 1 in the file */
        size_t a = w->next + g->idx[3 * q], b = w->next + g->idx[3 * q + (flip ? 1 : 2)],
               c = w->next + g->idx[3 * q + (flip ? 2 : 1)];
        fprintf(w->f, "f %zu/%zu/%zu %zu/%zu/%zu %zu/%zu/%zu\n", a, a, a, b, b, b, c, c, c);
    }
    w->next += g->n_points;
}

/* The adaptive tessellation of the render (levels from its camera) into w; 0 or -1 with a message. */
static int obj_adaptive(obj_writer *w, const scene_opts *o, const is_mesh *m, const is_patch_instance *inst,
                        const float3 (*nadj)[3][2], char *err, size_t errlen)
{
    tess_lod_params p = scene_lod_params_of(o, m);
    tess_lod_edges e;
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    core_pattern_cache *cache = core_pattern_cache_create(0);
    if (!cache || tess_lod_edges_build(m, &e, err, errlen) != 0) {
        core_pattern_cache_destroy(cache);
        return snprintf(err, errlen, "%s: out of memory", o->export_obj), -1;
    }
    tess_lod_levels(&p, m, &e, hist);
    int rc = 0;
    for (size_t t = 0; t < m->n_triangles && !ferror(w->f) && rc == 0; t++) {
        int lv[3], sorted[3], perm[3];
        for (int k = 0; k < 3; k++) lv[k] = e.level[e.tri_edge[3 * t + k]];
        bool odd = core_lod_order(lv, sorted, perm);
        const core_grid *g = core_pattern_get(cache, sorted[0], sorted[1], sorted[2]);
        if (!g) snprintf(err, errlen, "%s: out of memory for a pattern", o->export_obj), rc = -1;
        is_patch_instance pi;
        const uint8_t p8[3] = {(uint8_t)perm[0], (uint8_t)perm[1], (uint8_t)perm[2]};
        tess_permute_instance(&inst[t], p8, &pi);
        float3 pn[3][2];
        if (nadj) tess_permute_adjacent_normals(nadj[t], p8, pn);
        if (g) obj_triangle(w, &pi, nadj ? (const float3(*)[2])pn : NULL, g, odd);
    }
    tess_lod_edges_free(&e);
    core_pattern_cache_destroy(cache);
    return rc;
}

/* Evaluate the patch shader at every grid (or pattern) point of every triangle with identity matrices, as the
 * renderer does, and write positions, normals and faces as OBJ into output k of outs; 0 or -1. */
static int export_obj(const scene_opts *o, const is_mesh *m, is_outputs *outs, int k, char *err, size_t errlen)
{
    core_grid g;
    if (core_grid_make(o->grid, o->lod == TESS_LOD_UNIFORM ? o->level : 1.0f, &g) != 0)
        return snprintf(err, errlen, "cannot build the grid"), -1;
    is_patch_instance *inst = malloc(m->n_triangles * sizeof *inst);
    obj_writer w = {.f = inst ? outputs_stream(outs, k, err, errlen) : NULL, .vs = vs_patch_shader(o->patch), .next = 1};
    if (!w.f) {
        if (!inst) snprintf(err, errlen, "%s: out of memory for %zu triangles", o->export_obj, m->n_triangles);
        free(inst);
        core_grid_free(&g);
        return -1;
    }
    float4x4 id = mat_identity();
    memset(&w.c, 0, sizeof w.c);
    fill_constants(&w.c, o, &id, &id, o->diffuse);
    mesh_build_instances(m, inst);
    float3 (*nadj)[3][2] = o->patch == VS_PATCH_PN_AEN ? malloc(m->n_triangles * sizeof *nadj) : NULL;
    int rc = 0;
    if (nadj && tess_adjacent_normals(m, nadj) != 0) free(nadj), nadj = NULL;
    if (o->patch == VS_PATCH_PN_AEN && !nadj) rc = -1, snprintf(err, errlen, "%s: out of memory", o->export_obj);
    if (rc != 0) {
    } else if (o->lod == TESS_LOD_UNIFORM) {
        fprintf(w.f, "# instess %s: %s, patch %s, normals %s, level %g, %zu triangles x %zu grid points\n" OBJ_FRAME,
                INSTESS_VERSION, m->name, w.vs->name, vs_normals_name(o->normals), (double)o->level, m->n_triangles,
                g.n_points);
        for (size_t t = 0; t < m->n_triangles && !ferror(w.f); t++)
            obj_triangle(&w, &inst[t], nadj ? (const float3(*)[2])nadj[t] : NULL, &g, false);
    } else {
        fprintf(w.f, "# instess %s: %s, patch %s, normals %s, --lod %s, levels %d..%d, %zu triangles\n" OBJ_FRAME,
                INSTESS_VERSION, m->name, w.vs->name, vs_normals_name(o->normals), scene_lod_names[o->lod],
                o->min_level, scene_lod_max_level(o), m->n_triangles);
        rc = obj_adaptive(&w, o, m, inst, (const float3(*)[3][2])nadj, err, errlen);
    }
    free(inst);
    free(nadj);
    core_grid_free(&g);
    if (rc != 0) {
        char scratch[16];
        outputs_close_stream(outs, k, w.f, scratch, sizeof scratch);
        return -1;
    }
    return outputs_close_stream(outs, k, w.f, err, errlen);
}

/* The article's per-edge shortcut on the smoothed patch: how many P_k evaluations it saves of how many, into
 * *saved and *total; false when it does not apply (another patch or grid) or memory is short. */
static bool shortcut_savings(const scene_opts *o, const is_mesh *m, uint64_t *saved, uint64_t *total)
{
    if (o->patch != VS_PATCH_SMOOTH || o->grid != CORE_GRID_REGULAR || o->lod != TESS_LOD_UNIFORM) return false;
    vs_triangle *t = malloc(m->n_triangles * sizeof *t);
    is_patch_instance *inst = malloc(m->n_triangles * sizeof *inst);
    bool ok = t && inst;
    if (ok) {
        mesh_build_instances(m, inst);
        for (size_t k = 0; k < m->n_triangles; k++) {
            t[k] = vs_triangle_make(inst[k].v, inst[k].n);
            for (int e = 0; e < 3; e++) t[k].opp[e] = inst[k].opp[e];
        }
        *total = 0;
        *saved = vs_smooth_shortcut_savings(t, m->n_triangles, (int)o->level, total);
    }
    free(t);
    free(inst);
    return ok;
}

/* What a finished render reports: the scene's statistics, its time and the shortcut's savings. */
typedef struct run_report {
    scene_stats st;
    double ms;
    bool shortcut;             /* the savings below apply */
    uint64_t saved, total;
} run_report;

/* The report as text on stderr (the default; -q: none). */
static void print_stats_text(const scene_opts *o, const is_mesh *m, const run_report *r)
{
    if (r->shortcut)
        fprintf(stderr, "instess: per-edge shortcut: %llu of %llu P_k evaluations skipped (%.1f%%)\n",
                (unsigned long long)r->saved, (unsigned long long)r->total,
                r->total ? 100.0 * (double)r->saved / (double)r->total : 0.0);
    fprintf(stderr, "instess: %s: %zu triangles x %zu grid points, %llu vertices shaded, %llu triangles drawn, "
                    "%.1f ms -> %s\n",
            m->name, r->st.mesh_triangles, r->st.grid_points, (unsigned long long)r->st.vertices_shaded,
            (unsigned long long)r->st.triangles_drawn, r->ms, o->output);
}

/* s as a JSON string (quoted; control characters, '"' and '\\' escaped, bytes that are not UTF-8 as U+FFFD)
 * into f. */
/* The length of the well-formed UTF-8 sequence at p (RFC 3629: no overlong forms, no surrogates, nothing above
 * U+10FFFF), or 0 when the bytes there are not one. */
static int utf8_len(const unsigned char *p)
{
    if (p[0] < 0x80) return 1;
    int len = p[0] >= 0xc2 && p[0] <= 0xdf ? 2 : p[0] >= 0xe0 && p[0] <= 0xef ? 3 : p[0] >= 0xf0 && p[0] <= 0xf4 ? 4 : 0;
    for (int k = 1; k < len; k++)
        if ((p[k] & 0xc0) != 0x80) return 0;
    if ((p[0] == 0xe0 && p[1] < 0xa0) || (p[0] == 0xed && p[1] > 0x9f) || (p[0] == 0xf0 && p[1] < 0x90) ||
        (p[0] == 0xf4 && p[1] > 0x8f))
        return 0;   /* overlong, a surrogate, or beyond U+10FFFF */
    return len;
}

void scene_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p;) {
        int len = utf8_len(p);
        if (len == 0) fputs("\\ufffd", f), p++;
        else if (*p == '"' || *p == '\\') fprintf(f, "\\%c", *p), p++;
        else if (*p < 0x20 || *p == 0x7f) fprintf(f, "\\u%04x", *p), p++;   /* control bytes and DEL */
        else fwrite(p, 1, (size_t)len, f), p += len;
    }
    fputc('"', f);
}

/* The report as one JSON object into f (--stats json; a memory stream): every figure of the text form. */
static void print_stats_json(FILE *f, const scene_opts *o, const is_mesh *m, const run_report *r)
{
    fputs("{\"mesh\": ", f);
    scene_json_string(f, m->name);
    fputs(", \"output\": ", f);
    scene_json_string(f, o->output);
    fprintf(f, ", \"triangles\": %zu, \"grid_points\": %zu, \"grid_triangles\": %zu, \"vertices_shaded\": %llu, "
               "\"triangles_drawn\": %llu, \"ms\": %.3f",
               r->st.mesh_triangles, r->st.grid_points, r->st.grid_triangles, (unsigned long long)r->st.vertices_shaded,
               (unsigned long long)r->st.triangles_drawn, r->ms);
    if (o->lod != TESS_LOD_UNIFORM) {   /* the edge level histogram: {"level": edges} */
        fprintf(f, ", \"lod\": \"%s\", \"patterns\": %zu, \"buckets\": %zu, \"triangles_tessellated\": %zu, "
                   "\"edge_levels\": {", scene_lod_names[o->lod], r->st.n_patterns, r->st.n_buckets,
                   r->st.tessellated_triangles);
        for (int l = 1, first = 1; l <= CORE_LOD_MAX_LEVEL; l++)
            if (r->st.level_hist[l])
                fprintf(f, "%s\"%d\": %llu", first ? "" : ", ", l, (unsigned long long)r->st.level_hist[l]), first = 0;
        fputc('}', f);
    }
    if (r->shortcut)
        fprintf(f, ", \"shortcut\": {\"skipped\": %llu, \"evaluations\": %llu, \"percent\": %.3f}",
               (unsigned long long)r->saved, (unsigned long long)r->total,
               r->total ? 100.0 * (double)r->saved / (double)r->total : 0.0);
    fputs("}\n", f);
}

/* The --stats json report written to the standard output with write(2), before the outputs are committed: 0,
 * or -1 with the reason in err when it cannot all be written (a full disk, a closed descriptor), so that the
 * run fails with nothing written rather than succeed with its statistics lost. */
static int write_stats_json(const scene_opts *o, const is_mesh *m, const run_report *r, char *err, size_t errlen)
{
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    if (!f) return snprintf(err, errlen, "out of memory for the statistics"), -1;
    print_stats_json(f, o, m, r);
    bool ok = fclose(f) == 0;
    errno = 0;
    ok = ok && fflush(stdout) == 0;
    for (size_t done = 0; ok && done < len;) {
        ssize_t n = write(STDOUT_FILENO, text + done, len - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) ok = false;
        else done += (size_t)n;
    }
    free(text);
    if (!ok)
        snprintf(err, errlen, "cannot write to standard output: %s (the statistics of --stats json); nothing written",
                 errno ? strerror(errno) : "write error");
    return ok ? 0 : -1;
}

/* The level histogram of an adaptive render: mesh edges per level, patterns, buckets, triangles. */
static void report_levels(const scene_opts *o, const scene_stats *st)
{
    fprintf(stderr, "instess: edge levels (--lod %s):", scene_lod_names[o->lod]);
    for (int l = 1; l <= CORE_LOD_MAX_LEVEL; l++)
        if (st->level_hist[l]) fprintf(stderr, " %d:%llu", l, (unsigned long long)st->level_hist[l]);
    fprintf(stderr, "\ninstess: %zu patterns, %zu buckets (one instanced draw each), %zu triangles tessellated "
                    "(uniform level %d: %zu)\n", st->n_patterns, st->n_buckets, st->tessellated_triangles,
            scene_lod_max_level(o), st->mesh_triangles * st->grid_triangles);
}

/* Warnings of the mesh loader go to stderr (the program's choice; the library never prints), also with -q:
 * -q hides statistics, never warnings.  user is the run's progress line, erased first. */
is_mesh_options scene_mesh_options(const scene_opts *o, void (*warn)(void *user, const char *msg), void *user)
{
    return (is_mesh_options){.recompute_normals = o->recompute_normals, .warn = warn, .warn_user = user,
                             .import_timeout_ms = o->import_timeout_s * 1000,
                             .max_file_bytes = (uint64_t)o->max_file_mib << 20,
                             .max_import_memory_bytes = (uint64_t)o->max_import_memory_mib << 20};
}

void scene_warn_unless_quiet(void *quiet, const char *msg)
{
    if (!*(const bool *)quiet) fprintf(stderr, "instess: warning: %s\n", msg);
}

static void warn_stderr(void *user, const char *msg)
{
    char line[1200];
    snprintf(line, sizeof line, "instess: warning: %s\n", msg);
    scene_progress_print(user, line);
}

/* A note of the run ("instess: MSG") on stderr through the progress line pr (user), erased first. */
static void note_stderr(void *user, const char *msg)
{
    char line[PATH_MAX + 1200];
    snprintf(line, sizeof line, "instess: %s\n", msg);
    scene_progress_print(user, line);
}

void scene_note_stderr(void *user, const char *msg)
{
    (void)user;
    fprintf(stderr, "instess: %s\n", msg);
}

bool scene_use_mesh_texture(scene_opts *o, const is_mesh *m, void (*note)(void *user, const char *msg), void *user)
{
    if (o->texture || o->texture_none || !m->texture[0]) return false;
    o->texture = m->texture;
    char line[PATH_MAX + 600];
    snprintf(line, sizeof line, "%s: textured with its own %s (--texture none: without)", m->name, m->texture);
    for (char *c = line; *c; c++)   /* a file's name from the mesh's folder: no escape sequence on the terminal */
        if ((unsigned char)*c < 0x20 || *c == 0x7f) *c = '?';
    if (!o->quiet && note) note(user, line);
    return true;
}

bool scene_texture_misfit(const scene_opts *o, const is_mesh *m, char *msg, size_t len)
{
    if (!o->texture || m->n_vertices == 0) return false;
    const float2 t0 = m->texcoords[0];
    for (size_t v = 1; v < m->n_vertices; v++)
        if (m->texcoords[v].x != t0.x || m->texcoords[v].y != t0.y) return false;
    snprintf(msg, len, "%s: has no texture coordinates (every vertex's (u, v) is (%g, %g)): %s draws one colour over it",
             m->name, (double)t0.x, (double)t0.y, o->texture);
    for (char *c = msg; *c; c++)   /* names from the command line or the mesh's folder: no escape sequences */
        if ((unsigned char)*c < 0x20 || *c == 0x7f) *c = '?';
    return true;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* FNV-1a, 64 bits, of n bytes continuing from h. */
static uint64_t fnv1a(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t k = 0; k < n; k++) h = (h ^ p[k]) * 0x100000001b3ull;
    return h;
}

/* The hash of the mesh as rendered: its vertices, normals, texture coordinates and triangles. */
static uint64_t mesh_hash(const is_mesh *m)
{
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv1a(h, m->positions, m->n_vertices * sizeof *m->positions);
    h = fnv1a(h, m->normals, m->n_vertices * sizeof *m->normals);
    h = fnv1a(h, m->texcoords, m->n_vertices * sizeof *m->texcoords);
    return fnv1a(h, m->indices, 3 * m->n_triangles * sizeof *m->indices);
}

/* printf at buf[*n], as much as fits in len; *n grows by the whole length (as snprintf counts it). */
static void append(char *buf, size_t len, size_t *n, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static void append(char *buf, size_t len, size_t *n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(*n < len ? buf + *n : NULL, *n < len ? len - *n : 0, fmt, ap);
    va_end(ap);
    if (k > 0) *n += (size_t)k;
}

size_t scene_describe(const scene_opts *o, const is_mesh *m, const char *channels, char *buf, size_t len)
{
    size_t n = 0;
    if (len) buf[0] = '\0';
    append(buf, len, &n, "instess %s render: mesh %s (%zu triangles, FNV-1a 0x%016llx)", INSTESS_VERSION, m->name,
           m->n_triangles, (unsigned long long)mesh_hash(m));
    char value[PATH_MAX + 128];   /* a value may hold a path (--displace) */
    for (size_t k = 0; k < scene_option_count; k++) {
        const scene_option *opt = &scene_options[k];
        const char *v = opt->value ? opt->value(o, value, sizeof value) : NULL;
        if (v) append(buf, len, &n, ", %s %s", opt->name, v);
    }
    if (channels) append(buf, len, &n, ", channels %s", channels);
    return n;
}

char *scene_describe_file(const scene_opts *o, const is_mesh *m, const is_image *img, is_image_format fmt)
{
    size_t nc = image_file_channels(img, fmt, NULL, 0);
    char *channels = malloc(nc + 1);
    if (!channels) return NULL;
    image_file_channels(img, fmt, channels, nc + 1);
    size_t n = scene_describe(o, m, channels, NULL, 0);
    char *desc = malloc(n + 1);
    if (desc) scene_describe(o, m, channels, desc, n + 1);
    free(channels);
    return desc;
}

/* Claim the run's outputs (the image, then the export) before any work; 0 or -1 with a message. */
static int claim_outputs(const scene_opts *o, is_outputs *outs, char *err, size_t errlen)
{
    outputs_init(outs);
    const char *const names[2] = {o->output, o->export_obj};
    for (int k = 0; k < 2; k++) {
        if (names[k] && o->mesh && outputs_same_target(names[k], o->mesh))
            return snprintf(err, errlen, "%s: is the input mesh; instess will not replace its input", names[k]), -1;
        if (names[k] && o->displace && outputs_same_target(names[k], o->displace))
            return snprintf(err, errlen, "%s: is the height map of --displace; instess will not replace its input",
                            names[k]), -1;
        if (names[k] && o->texture && outputs_same_target(names[k], o->texture))
            return snprintf(err, errlen, "%s: is the image of --texture; instess will not replace its input",
                            names[k]), -1;
    }
    if (image_check_path(o->output, err, errlen) != 0 || outputs_add(outs, o->output, err, errlen) != 0) return -1;
    if (o->export_obj && outputs_add(outs, o->export_obj, err, errlen) != 1) return -1;
    return 0;
}

/* Render the loaded mesh m and fill the claimed outputs, then commit them, showing the phases on pr (stopped
 * here, before the statistics); 0 or -1 (nothing left behind). */
static int render_outputs(const scene_opts *o, const is_mesh *m, is_outputs *outs, scene_progress *pr, char *err,
                          size_t errlen)
{
    double t0 = now_seconds();
    is_image img = {0};
    scene_stats st;
    scene_progress_phase(pr, "rendering");
    int rc = scene_render_picture(o, m, &img, &st, err, errlen);
    double t1 = now_seconds();
    scene_progress_phase(pr, "writing");
    if (rc == 0) {
        char *desc = scene_describe_file(o, m, &img, image_format_of(o->output));
        is_image_meta meta = {"instess " INSTESS_VERSION, desc};
        rc = desc ? scene_write_picture(outs, 0, &img, o->background, &meta, err, errlen)
                  : (snprintf(err, errlen, "out of memory for the image's description"), -1);
        free(desc);
    }
    image_free(&img);
    if (rc == 0 && o->export_obj) rc = export_obj(o, m, outs, 1, err, errlen);
    run_report r = {.st = st, .ms = (t1 - t0) * 1e3};
    if (rc == 0 && o->stats_json) {   /* before the commit: statistics that cannot be written fail the run */
        scene_progress_stop(pr);
        r.shortcut = shortcut_savings(o, m, &r.saved, &r.total);
        rc = write_stats_json(o, m, &r, err, errlen);
    }
    if (rc == 0) rc = outputs_commit(outs, err, errlen);
    scene_progress_stop(pr);
    if (rc != 0 || o->quiet || o->stats_json) return rc;
    r.shortcut = shortcut_savings(o, m, &r.saved, &r.total);
    {
        if (o->lod != TESS_LOD_UNIFORM) report_levels(o, &st);
        print_stats_text(o, m, &r);
    }
    return 0;
}

int scene_render_to_file(const scene_opts *o, char *err, size_t errlen)
{
    scene_progress pr;
    is_outputs outs;
    is_mesh m = {0};
    is_mesh_options mo = scene_mesh_options(o, warn_stderr, &pr);
    is_image map = {0};
    scene_opts od = *o;   /* with the displacement map read once, before the mesh */
    int rc = claim_outputs(o, &outs, err, errlen);
    if (rc == 0 && o->displace && (rc = scene_load_displacement(o->displace, &map, err, errlen)) == 0)
        od.displace_map = &map;
    scene_progress_start(&pr, o->mesh, o->quiet);
    scene_progress_phase(&pr, "reading the mesh");
    if (rc == 0) rc = mesh_open(o->mesh, &mo, &m, err, errlen);
    char misfit[1000];
    if (rc == 0 && scene_normals_misfit(&m, misfit, sizeof misfit)) warn_stderr(&pr, misfit);
    const bool own_texture = rc == 0 && scene_use_mesh_texture(&od, &m, note_stderr, &pr);
    if (rc == 0 && scene_texture_misfit(&od, &m, misfit, sizeof misfit)) warn_stderr(&pr, misfit);
    if (own_texture)
        for (int k = 0; k < 2 && rc == 0; k++) {   /* the outputs were claimed before the mesh named it */
            const char *out = k == 0 ? o->output : o->export_obj;
            if (out && outputs_same_target(out, od.texture))
                rc = -1, snprintf(err, errlen, "%s: is the mesh's own texture; instess will not replace its input", out);
        }
    if (rc == 0) rc = render_outputs(&od, &m, &outs, &pr, err, errlen);
    scene_progress_stop(&pr);
    outputs_abort(&outs);
    mesh_free(&m);
    image_free(&map);
    return rc;
}
