/* cli/scene.c -- render one scene through the device: options, camera, the three paths to a patch
 * (instanced, the device's N-patch mode, CPU tessellation), image assembly (RGBA, Z, AOVs) and output. */
#include "scene.h"

#include <errno.h>
#include <math.h>
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
        .background = IS_COLOR_ARGB(255, 46, 52, 64), .cull = IS_CULL_CCW, .up = SCENE_UP_Y,
        .max_memory_mib = SCENE_DEFAULT_MAX_MEMORY_MIB,
    };
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

/* A whole decimal integer in [lo, hi]. */
bool scene_parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = s ? strtol(s, &end, 10) : 0;
    if (!s || end == s || *end || errno || v < lo || v > hi) return false;
    *out = (int)v;
    return true;
}

/* A finite number in [lo, hi]. */
bool scene_parse_float(const char *s, float lo, float hi, float *out)
{
    char *end;
    errno = 0;
    double v = s ? strtod(s, &end) : 0;
    if (!s || end == s || *end || errno || !isfinite(v) || v < lo || v > hi) return false;
    *out = (float)v;
    return true;
}

/* WxH with both sides in 1..SCENE_MAX_SIDE and at most SCENE_MAX_PIXELS pixels. */
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

/* Comma-separated AOV names into a SCENE_AOV_* mask. */
bool scene_parse_aovs(const char *s, unsigned *out)
{
    static const char *const names[] = {"normal", "bary", "instance", "gregory", "depth", NULL};
    char buf[256];
    if (!s || !*s || strlen(s) >= sizeof buf) return false;
    strcpy(buf, s);
    unsigned m = 0;
    for (char *save = NULL, *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        int k = lookup(t, names);
        if (k < 0) return false;
        m |= 1u << k;
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
    if (o->grid == CORE_GRID_REGULAR && o->level != floorf(o->level))
        return "a fractional --level needs a primitive-generator grid (--grid pg-fractional-odd or -even)";
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
    float4x4 world, wvp;
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
 * 1 / r and rotated by world, fit in the 45 degree field of view of an image of aspect `aspect`, with a margin
 * of 5% on each side; at least 1.2 (the mesh stays in front of the near plane). */
static float box_fit_distance(const is_mesh *m, float3 c, float r, const float4x4 *world, float aspect)
{
    float3 lo, hi;
    mesh_box(m, &lo, &hi);
    double ty = tan(PI_F / 8.0) * 0.9, tx = ty * aspect, d = 1.2;
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
    float dist = o->fit == SCENE_FIT_BOX ? box_fit_distance(m, c, r, &cam.world, aspect) : o->distance;
    float4x4 view = mat_look_at_lh(f3(0, 0, -dist), f3(0, 0, 0), f3(0, 1, 0));
    float zn = dist - 2.0f > 0.05f ? dist - 2.0f : 0.05f;
    float4x4 proj = mat_perspective_fov_lh(PI_F / 4.0f, aspect, zn, dist + 2.0f);
    cam.zn = zn, cam.zf = dist + 2.0f, cam.radius = r;
    float4x4 t = mat_mul(&fit, &cam.world);
    t = mat_mul(&t, &view);
    cam.wvp = mat_mul(&t, &proj);
    return cam;
}

/* The AOV outputs of the patch shaders (vs/vs.h): TEXCOORD1 normal, 2 barycentrics, 3 instance, 4 Gregory. */
enum { VS_OUT_NORMAL = 1, VS_OUT_BARY = 2, VS_OUT_INSTANCE = 3, VS_OUT_GREGORY = 4 };

/* The listing's constants for the scene's matrices, a diffuse colour and the patch options. */
static void fill_constants(is_vs_constants *c, const scene_opts *o, const float4x4 *wvp, const float4x4 *world,
                           const float diffuse[4])
{
    vs_options vo = vs_default_options();
    vo.normals = o->normals;
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

/* ---- PN-AEN's extra per-instance stream: the neighbour's normals at each edge's two ends ---- */

/* One triangle edge keyed by its welded end points (a < b). */
typedef struct edge_rec { uint32_t a, b, tri, k; } edge_rec;

static int edge_cmp(const void *x, const void *y)
{
    const edge_rec *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    return p->tri < q->tri ? -1 : (p->tri > q->tri);
}

/* The normal triangle u has at the vertex welded to w (fallback: `own`). */
static float3 normal_at(const is_mesh *m, uint32_t u, uint32_t w, float3 own)
{
    for (int c = 0; c < 3; c++)
        if (m->welded[3 * (size_t)u + c] == w) return m->normals[m->indices[3 * (size_t)u + c]];
    return own;
}

/* Fill nadj[t][k][j] = the normal that the triangle across edge k has at corner (k + j) % 3 of triangle t; an
 * edge without exactly one neighbour (boundary, non-manifold) gets t's own normals.  Returns 0 or -1. */
static int adjacent_normals(const is_mesh *m, float3 (*nadj)[3][2])
{
    const size_t ne = 3 * m->n_triangles;
    edge_rec *e = malloc(ne * sizeof *e);
    if (!e) return -1;
    for (size_t i = 0; i < ne; i++) {
        uint32_t t = (uint32_t)(i / 3), k = (uint32_t)(i % 3);
        uint32_t a = m->welded[i], b = m->welded[3 * (size_t)t + (k + 1) % 3];
        e[i] = (edge_rec){a < b ? a : b, a < b ? b : a, t, k};
    }
    qsort(e, ne, sizeof *e, edge_cmp);
    for (size_t i = 0; i < ne;) {
        size_t j = i;
        while (j < ne && e[j].a == e[i].a && e[j].b == e[i].b) j++;
        for (size_t r = i; r < j; r++) {
            uint32_t t = e[r].tri, k = e[r].k;
            for (int c = 0; c < 2; c++) {
                size_t corner = 3 * (size_t)t + (k + (uint32_t)c) % 3;
                float3 own = m->normals[m->indices[corner]];
                uint32_t other = j - i == 2 ? e[r == i ? i + 1 : i].tri : t;
                nadj[t][k][c] = other == t ? own : normal_at(m, other, m->welded[corner], own);
            }
        }
        i = j;
    }
    free(e);
    return 0;
}

/* Bind stream 2 (INSTANCEDATA | 1) with the neighbour normals and a declaration that adds vs_nadj_regs to
 * Listing 1.1.2's; replaces the declaration of scene_bind_instanced. */
static is_result bind_adjacent_normals(is_device *dev, const is_mesh *m, scene_resources *r)
{
    is_result e = dev_create_vertex_buffer(dev, m->n_triangles * sizeof(float3[3][2]), &r->vb2);
    if (e != IS_OK) return e;
    if (adjacent_normals(m, vb_lock(r->vb2)) != 0) return IS_ERR_OUTOFMEMORY;
    is_vertex_element el[MESH_PATCH_DECLARATION_COUNT + 6];
    size_t n = 0;
    while (mesh_patch_declaration[n].stream != 0xFF) el[n] = mesh_patch_declaration[n], n++;
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 2; j++)
            el[n++] = (is_vertex_element){2, (uint16_t)((k * 2 + j) * sizeof(float3)), IS_DECLTYPE_FLOAT3, 0,
                                          vs_nadj_regs[k][j].usage, vs_nadj_regs[k][j].usage_index};
    el[n] = (is_vertex_element)IS_DECL_END;
    decl_release(r->decl);
    r->decl = NULL;
    e = dev_create_vertex_declaration(dev, el, &r->decl);
    if (e != IS_OK) return e;
    dev_set_vertex_declaration(dev, r->decl);
    dev_set_stream_source(dev, 2, r->vb2, 0, sizeof(float3[3][2]));
    dev_set_stream_source_freq(dev, 2, IS_STREAMSOURCE_INSTANCEDATA | 1u);
    return IS_OK;
}

/* The vertex of the non-instanced paths: position, normal, texcoord (declaration vs_tnl_declaration). */
typedef struct tnl_vertex { float3 p, n; float2 t; } tnl_vertex;
static const is_vertex_element tnl_declaration[] = {
    {0, 0, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_POSITION, 0},
    {0, 12, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_NORMAL, 0},
    {0, 24, IS_DECLTYPE_FLOAT2, 0, IS_DECLUSAGE_TEXCOORD, 0},
    IS_DECL_END};

/* Bind a non-instanced vertex buffer of tnl_vertex and an index buffer. */
static is_result bind_tnl(is_device *dev, scene_resources *r, const uint32_t *idx, size_t n_idx, size_t n_vtx)
{
    is_result e = scene_index_buffer(dev, idx, n_idx, n_vtx, &r->ib);
    if (e == IS_OK) e = dev_create_vertex_declaration(dev, tnl_declaration, &r->decl);
    if (e != IS_OK) return e;
    dev_set_vertex_declaration(dev, r->decl);
    dev_set_stream_source(dev, 0, r->vb0, 0, sizeof(tnl_vertex));
    dev_set_indices(dev, r->ib);
    r->n_vertices = (unsigned)n_vtx, r->n_prims = (unsigned)(n_idx / 3), r->n_instances = 1;
    return IS_OK;
}

/* The device's N-patch mode: the mesh itself in stream 0, SetNPatchMode(level) and the degrees. */
static is_result build_npatch_mode(is_device *dev, const scene_opts *o, const is_mesh *m, scene_resources *r)
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
                           scene_resources *r)
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

/* Issue the draw(s) of the fill mode on a device whose buffers are bound. */
static is_result draw_fill(is_device *dev, const scene_opts *o, const scene_camera *cam, const scene_resources *r)
{
    const int fills[4] = {IS_FILL_SOLID, IS_FILL_WIREFRAME, IS_FILL_SOLID, IS_FILL_POINT};
    dev_set_render_state(dev, IS_RS_FILLMODE, (uint32_t)fills[o->fill]);
    set_constants(dev, o, cam, o->diffuse);
    is_result e = dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, r->n_vertices, 0, r->n_prims);
    if (e != IS_OK || o->fill != SCENE_FILL_SOLID_WIRE) return e;
    /* the overlay: the same triangles' edges, pulled slightly towards the eye so they win the depth test */
    float bias = -2e-5f, slope = -1.0f;
    uint32_t bb, sb;
    memcpy(&bb, &bias, 4), memcpy(&sb, &slope, 4);
    dev_set_render_state(dev, IS_RS_FILLMODE, IS_FILL_WIREFRAME);
    dev_set_render_state(dev, IS_RS_DEPTHBIAS, bb);
    dev_set_render_state(dev, IS_RS_SLOPESCALEDEPTHBIAS, sb);
    set_constants(dev, o, cam, o->wire_color);
    return dev_draw_indexed_primitive(dev, IS_PT_TRIANGLELIST, 0, 0, r->n_vertices, 0, r->n_prims);
}

/* Bind the buffers of o->path on dev. */
static is_result build_path(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g,
                            scene_resources *r)
{
    switch (o->path) {
    case SCENE_PATH_NPATCH_MODE: return build_npatch_mode(dev, o, m, r);
    case SCENE_PATH_CPU: return build_cpu(dev, o, m, g, r);
    default: {
        is_result e = scene_bind_instanced(dev, m, g, r);
        return e == IS_OK && o->patch == VS_PATCH_PN_AEN ? bind_adjacent_normals(dev, m, r) : e;
    }
    }
}

int scene_draw(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g,
               const is_vertex_shader *shader)
{
    scene_camera cam = make_camera(o, m);
    scene_resources r = {0};
    dev_set_vertex_shader(dev, shader ? shader : path_shader(o));
    is_result e = build_path(dev, o, m, g, &r);
    if (e == IS_OK) e = draw_fill(dev, o, &cam, &r);
    scene_resources_free(&r);
    return e == IS_OK ? 0 : -1;
}

/* Render into a new device of `samples` samples with `aov` planes (samples 1 only); the device is returned. */
static is_device *render_device(const scene_opts *o, const is_mesh *m, const core_grid *g, int samples,
                                unsigned aovs, scene_stats *st, char *err, size_t errlen)
{
    is_device *dev = dev_create(o->width, o->height, samples, err, errlen);
    if (!dev) return NULL;
    dev_set_threads(dev, o->threads);
    dev_set_render_state(dev, IS_RS_CULLMODE, o->cull);
    static const struct { unsigned bit; int slot, comps; } aov_slots[] = {
        {SCENE_AOV_NORMAL, VS_OUT_NORMAL, 3}, {SCENE_AOV_BARY, VS_OUT_BARY, 3},
        {SCENE_AOV_INSTANCE, VS_OUT_INSTANCE, 1}, {SCENE_AOV_GREGORY, VS_OUT_GREGORY, 3}};
    for (size_t k = 0; k < 4; k++)
        if (aovs & aov_slots[k].bit) rs_target_add_aov(dev_render_target(dev), RS_ATTR_TEXCOORD0 + aov_slots[k].slot,
                                                       aov_slots[k].comps);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, o->background, 1.0f);
    if (scene_draw(dev, o, m, g, NULL) != 0) {
        snprintf(err, errlen, "%s: rendering failed: %s", m->name, dev_last_error(dev));
        dev_destroy(dev);
        return NULL;
    }
    if (st) {
        st->vertices_shaded += dev_vertices_shaded(dev);
        st->triangles_drawn += dev_stats(dev)->prims_drawn;
        st->raster = *dev_stats(dev);
    }
    return dev;
}

/* Channel names of the image: R,G,B,A,Z then the AOVs in SCENE_AOV_* order. */
static void channel_list(unsigned aovs, char *buf, size_t len)
{
    snprintf(buf, len, "R,G,B,A,Z%s%s%s%s%s", aovs & SCENE_AOV_NORMAL ? ",N.X,N.Y,N.Z" : "",
             aovs & SCENE_AOV_BARY ? ",bary.X,bary.Y,bary.Z" : "", aovs & SCENE_AOV_INSTANCE ? ",instance" : "",
             aovs & SCENE_AOV_GREGORY ? ",gregory.X,gregory.Y,gregory.Z" : "", aovs & SCENE_AOV_DEPTH ? ",depth" : "");
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
        float z = rt->depth[p * rt->samples];
        for (int s = 1; s < rt->samples; s++) z = fminf(z, rt->depth[p * rt->samples + s]);
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

/* An EXR's colour (see scene_render_mesh): A = the fraction of each pixel's samples of rt that the mesh covers
 * (depth below the clear value 1), R, G, B = the mesh's colour without the background (the resolved colour C =
 * a F + (1 - a) B solved for F), decoded from sRGB to linear and premultiplied by A. */
static void exr_colour(const rs_target *rt, uint32_t background, is_image *img)
{
    const float bg[3] = {(float)((background >> 16) & 0xffu) / 255.0f, (float)((background >> 8) & 0xffu) / 255.0f,
                         (float)(background & 0xffu) / 255.0f};
    size_t n = (size_t)rt->width * rt->height;
    for (size_t p = 0; p < n; p++) {
        int covered = 0;
        for (int s = 0; s < rt->samples; s++) covered += rt->depth[p * rt->samples + s] < 1.0f;
        float a = (float)covered / (float)rt->samples, *px = &img->data[p * img->channels];
        for (int k = 0; k < 3; k++) {
            float f = a > 0.0f ? (px[k] - (1.0f - a) * bg[k]) / a : 0.0f;
            px[k] = srgb_to_linear(saturate(f)) * a;
        }
        px[3] = a;
    }
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

int scene_render_mesh(const scene_opts *o, const is_mesh *mesh, is_image *img, scene_stats *st, char *err,
                      size_t errlen)
{
    is_mesh copy = {0};
    float scale = 1.0f;
    const is_mesh *m = rescaled_copy(mesh, &copy, &scale) == 0 ? &copy : mesh;
    int rc = render_mesh(o, m, m == &copy ? scale : 1.0f, img, st, err, errlen);
    mesh_free(&copy);
    return rc;
}

unsigned long long scene_memory_estimate(const scene_opts *o, size_t mesh_triangles, size_t grid_points)
{
    unsigned long long px = (unsigned long long)o->width * (unsigned long long)o->height;
    unsigned long long bytes = px * ((unsigned long long)o->msaa * 8 + 4 + 5 * 4);   /* target, resolve, image */
    if (o->aovs) bytes += px * (8 + 4 + 11 * 4 + 12 * 4);   /* the AOV device's target and planes, the channels */
    bytes += (unsigned long long)mesh_triangles * (sizeof(is_patch_instance) + 64);
    if (o->path == SCENE_PATH_CPU)
        bytes += SCENE_CPU_BYTES_PER_VERTEX * (unsigned long long)mesh_triangles * grid_points;
    return bytes;
}

/* scene_render_mesh on a mesh of ordinary coordinates, whose unit is `unit` of the mesh's own (for the depth
 * AOV). */
static int render_mesh(const scene_opts *o, const is_mesh *m, float unit, is_image *img, scene_stats *st,
                       char *err, size_t errlen)
{
    core_grid g;
    if (core_grid_make(o->grid, o->level, &g) != 0) {
        snprintf(err, errlen, "level %g: cannot build the grid", (double)o->level);
        return -1;
    }
    if ((unsigned long long)g.n_points * m->n_triangles > SCENE_MAX_VERTICES) {
        snprintf(err, errlen, "%s: %zu triangles at level %g need %llu vertices, more than the limit %llu", m->name,
                 m->n_triangles, (double)o->level, (unsigned long long)g.n_points * m->n_triangles,
                 (unsigned long long)SCENE_MAX_VERTICES);
        core_grid_free(&g);
        return -1;
    }
    unsigned long long need = scene_memory_estimate(o, m->n_triangles, g.n_points);
    if (need > (unsigned long long)o->max_memory_mib << 20) {
        snprintf(err, errlen, "%s: %zu triangles at level %g on this path need about %llu MiB, more than the memory "
                 "budget of %u MiB (--max-memory MIB raises it)", m->name, m->n_triangles, (double)o->level,
                 (need + (1u << 20) - 1) >> 20, o->max_memory_mib);
        core_grid_free(&g);
        return -1;
    }
    if (st) *st = (scene_stats){m->n_triangles, g.n_points, g.n_triangles, 0, 0, {0}};
    char names[256];
    channel_list(o->aovs, names, sizeof names);
    int rc = -1;
    is_device *dev = render_device(o, m, &g, o->msaa, 0, st, err, errlen);
    if (dev && image_alloc(img, o->width, o->height, names, err, errlen) == 0) {
        rc = scene_copy_color_depth(dev_render_target(dev), img, err, errlen);
        if (rc != 0) image_free(img);
        if (rc == 0 && o->output && image_format_of(o->output) == IS_IMAGE_EXR)
            exr_colour(dev_render_target(dev), o->background, img);
        if (rc == 0 && o->aovs) {
            is_device *adev = render_device(o, m, &g, 1, o->aovs, NULL, err, errlen);
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

/* The input registers the device would fetch for grid point b of instance inst (Listing 1.1.2's layout). */
void scene_input_from_instance(const is_patch_instance *inst, float3 b, is_vs_input *in)
{
    float4 *r = (float4 *)in;
    for (size_t k = 0; k < sizeof *in / sizeof(float4); k++) r[k] = f4(0, 0, 0, 1);
    in->position[0] = f4_of(b, 1.0f);
    for (int k = 0; k < 3; k++) {
        in->texcoord[VS_IN_V0 + k] = f4_of(inst->v[k], 1.0f);
        in->texcoord[VS_IN_N0 + k] = f4_of(inst->n[k], 1.0f);
        in->texcoord[VS_IN_OPP0 + k] = f4_of(inst->opp[k], 1.0f);
        in->texcoord[VS_IN_T0 + k] = f4(inst->t[k].x, inst->t[k].y, 0.0f, 1.0f);
    }
    in->texcoord[VS_IN_ID] = f4(inst->instance_id, 0.0f, 0.0f, 1.0f);
}

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

/* Evaluate the patch shader at every grid point of every triangle with identity matrices, as the renderer
 * does, and write positions, texture coordinates, normals and faces as OBJ (in the file's frame, see
 * write_obj_vertex) into output k of outs; 0 or -1. */
static int export_obj(const scene_opts *o, const is_mesh *m, is_outputs *outs, int k, char *err, size_t errlen)
{
    core_grid g;
    if (core_grid_make(o->grid, o->level, &g) != 0) return snprintf(err, errlen, "cannot build the grid"), -1;
    is_patch_instance *inst = malloc(m->n_triangles * sizeof *inst);
    FILE *f = inst ? outputs_stream(outs, k, err, errlen) : NULL;
    if (!f) {
        if (!inst) snprintf(err, errlen, "%s: out of memory for %zu triangles", o->export_obj, m->n_triangles);
        free(inst);
        core_grid_free(&g);
        return -1;
    }
    is_vs_constants c;
    float4x4 id = mat_identity();
    memset(&c, 0, sizeof c);
    fill_constants(&c, o, &id, &id, o->diffuse);
    const is_vertex_shader *vs = vs_patch_shader(o->patch);
    mesh_build_instances(m, inst);
    fprintf(f, "# instess %s: %s, patch %s, normals %s, level %g, %zu triangles x %zu grid points\n"
               "# right-handed, counter-clockwise fronts, v up (the OBJ convention; the input's own frame)\n",
            INSTESS_VERSION, m->name, vs->name, vs_normals_name(o->normals), (double)o->level, m->n_triangles,
            g.n_points);
    for (size_t t = 0; t < m->n_triangles && !ferror(f); t++) {
        for (size_t p = 0; p < g.n_points; p++) {
            is_vs_input in;
            is_vs_output out;
            scene_input_from_instance(&inst[t], g.bary[p], &in);
            memset(&out, 0, sizeof out);
            vs->main(&c, &in, &out);
            write_obj_vertex(f, &out, instance_texcoord(&inst[t], g.bary[p]));
        }
        size_t base = t * g.n_points + 1;
        for (size_t q = 0; q < g.n_triangles; q++) {   /* clockwise here, so corners 0, 2, 1 in the file */
            size_t a = base + g.idx[3 * q], b = base + g.idx[3 * q + 2], d = base + g.idx[3 * q + 1];
            fprintf(f, "f %zu/%zu/%zu %zu/%zu/%zu %zu/%zu/%zu\n", a, a, a, b, b, b, d, d, d);
        }
    }
    free(inst);
    core_grid_free(&g);
    return outputs_close_stream(outs, k, f, err, errlen);
}

/* The article's per-edge shortcut on the smoothed patch: print how many P_k evaluations it saved. */
static void report_shortcut(const scene_opts *o, const is_mesh *m)
{
    if (o->patch != VS_PATCH_SMOOTH || o->grid != CORE_GRID_REGULAR || o->quiet) return;
    vs_triangle *t = malloc(m->n_triangles * sizeof *t);
    is_patch_instance *inst = malloc(m->n_triangles * sizeof *inst);
    if (t && inst) {
        mesh_build_instances(m, inst);
        for (size_t k = 0; k < m->n_triangles; k++) {
            t[k] = vs_triangle_make(inst[k].v, inst[k].n);
            for (int e = 0; e < 3; e++) t[k].opp[e] = inst[k].opp[e];
        }
        uint64_t total = 0, saved = vs_smooth_shortcut_savings(t, m->n_triangles, (int)o->level, &total);
        fprintf(stderr, "instess: per-edge shortcut: %llu of %llu P_k evaluations skipped (%.1f%%)\n",
                (unsigned long long)saved, (unsigned long long)total, total ? 100.0 * (double)saved / (double)total : 0.0);
    }
    free(t);
    free(inst);
}

/* Warnings of the mesh loader go to stderr (the program's choice; the library never prints), also with -q:
 * -q hides statistics, never warnings.  user is the run's progress line, erased first. */
static void warn_stderr(void *user, const char *msg)
{
    char line[1200];
    snprintf(line, sizeof line, "instess: warning: %s\n", msg);
    scene_progress_print(user, line);
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

void scene_describe(const scene_opts *o, const is_mesh *m, char *buf, size_t len)
{
    char names[64] = "none";
    channel_list(o->aovs, names, sizeof names);
    snprintf(buf, len, "instess %s render: mesh %s (%zu triangles, FNV-1a 0x%016llx), patch %s, normals %s, level %g, "
             "grid %s, path %s, size %dx%d, up %s, yaw %g, pitch %g, distance %g, fit %s, fill %s, cull %s, msaa %d, "
             "channels %s",
             INSTESS_VERSION, m->name, m->n_triangles, (unsigned long long)mesh_hash(m), vs_patch_name(o->patch),
             vs_normals_name(o->normals), (double)o->level, scene_grid_name(o->grid), scene_path_names[o->path],
             o->width, o->height, scene_up_names[o->up], (double)o->yaw, (double)o->pitch, (double)o->distance,
             scene_fit_names[o->fit], scene_fill_names[o->fill],
             scene_cull_names[o->cull - IS_CULL_NONE], o->msaa, names);
}

/* Claim the run's outputs (the image, then the export) before any work; 0 or -1 with a message. */
static int claim_outputs(const scene_opts *o, is_outputs *outs, char *err, size_t errlen)
{
    outputs_init(outs);
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
    int rc = scene_render_mesh(o, m, &img, &st, err, errlen);
    double t1 = now_seconds();
    scene_progress_phase(pr, "writing");
    if (rc == 0) {
        char desc[1024];
        scene_describe(o, m, desc, sizeof desc);
        is_image_meta meta = {"instess " INSTESS_VERSION, desc};
        rc = image_write_output(outs, 0, &img, &meta, err, errlen);
    }
    image_free(&img);
    if (rc == 0 && o->export_obj) rc = export_obj(o, m, outs, 1, err, errlen);
    if (rc == 0) rc = outputs_commit(outs, err, errlen);
    scene_progress_stop(pr);
    if (rc == 0) report_shortcut(o, m);
    if (rc == 0 && !o->quiet)
        fprintf(stderr, "instess: %s: %zu triangles x %zu grid points, %llu vertices shaded, %llu triangles drawn, "
                        "%.1f ms -> %s\n",
                m->name, st.mesh_triangles, st.grid_points, (unsigned long long)st.vertices_shaded,
                (unsigned long long)st.triangles_drawn, (t1 - t0) * 1e3, o->output);
    return rc;
}

int scene_render_to_file(const scene_opts *o, char *err, size_t errlen)
{
    scene_progress pr;
    is_outputs outs;
    is_mesh m = {0};
    is_mesh_options mo = {.recompute_normals = o->recompute_normals, .warn = warn_stderr, .warn_user = &pr,
                          .import_timeout_ms = o->import_timeout_s * 1000,
                          .max_file_bytes = (uint64_t)o->max_file_mib << 20,
                          .max_import_memory_bytes = (uint64_t)o->max_import_memory_mib << 20};
    int rc = claim_outputs(o, &outs, err, errlen);
    scene_progress_start(&pr, o->mesh, o->quiet);
    scene_progress_phase(&pr, "reading the mesh");
    if (rc == 0) rc = mesh_open(o->mesh, &mo, &m, err, errlen);
    if (rc == 0) rc = render_outputs(o, &m, &outs, &pr, err, errlen);
    scene_progress_stop(&pr);
    outputs_abort(&outs);
    mesh_free(&m);
    return rc;
}
