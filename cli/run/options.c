/* cli/run/options.c -- the render options of the command line: one table (scene_options) from which getopt's
 * long options, `--help` and the parsing of every program that renders a scene (instess, instess view, the
 * figures' "Reproduce" lines) are made, so that no list of options is repeated anywhere else. */
#include "scene.h"

#include <stdarg.h>

#include "../../core/hlsl.h"
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------ choices ------------------------------------ */

/* The names --patch takes, joined by sep into buf; buf. */
static const char *patch_choices(const char *sep, char *buf, size_t len)
{
    return vs_patch_names(sep, buf, len);
}

/* The names --normals takes, joined by sep into buf; buf. */
static const char *normals_choices(const char *sep, char *buf, size_t len)
{
    snprintf(buf, len, "%s%s%s%s%s", vs_normals_name(VS_NORMALS_LINEAR), sep, vs_normals_name(VS_NORMALS_QUADRATIC),
             sep, vs_normals_name(VS_NORMALS_REAL));
    return buf;
}

/* The names --grid, --path and --fill take, joined by sep into buf; buf. */
static const char *grid_choices(const char *sep, char *buf, size_t len)
{
    return scene_join_names(scene_grid_names, sep, buf, len);
}
static const char *path_choices(const char *sep, char *buf, size_t len)
{
    return scene_join_names(scene_path_names, sep, buf, len);
}
static const char *fill_choices(const char *sep, char *buf, size_t len)
{
    return scene_join_names(scene_fill_names, sep, buf, len);
}

/* The names --stats takes, joined by sep into buf; buf. */
static const char *const stats_names[] = {"text", "json", NULL};
static const char *stats_choices(const char *sep, char *buf, size_t len)
{
    return scene_join_names(stats_names, sep, buf, len);
}
static const char *shading_choices(const char *sep, char *buf, size_t len)
{
    return scene_join_names(scene_shading_names, sep, buf, len);
}
static const char *cull_choices(const char *sep, char *buf, size_t len)
{
    return scene_join_names(scene_cull_names, sep, buf, len);
}

static const char *up_choices(const char *sep, char *buf, size_t len)
{
    return scene_join_names(scene_up_names, sep, buf, len);
}
static const char *fit_choices(const char *sep, char *buf, size_t len)
{
    return scene_join_names(scene_fit_names, sep, buf, len);
}

/* "unknown --NAME (one of: ...)" for option opt into buf; buf. */
static const char *unknown_choice(const scene_option *opt, char *buf, size_t len)
{
    char names[512];
    snprintf(buf, len, "unknown --%s (one of: %s)", opt->name, opt->choices(" | ", names, sizeof names));
    return buf;
}

/* ------------------------------------ appliers ------------------------------------ */
/* Each takes the option's value and returns NULL, or the usage error (CHOICE_ERROR: "unknown --x (one of ...)"). */

static const char CHOICE_ERROR[] = "";

static const char *opt_mesh(scene_opts *o, const char *a) { return o->mesh = a, NULL; }
static const char *opt_patch(scene_opts *o, const char *a)
{
    return scene_parse_patch(a, &o->patch) ? NULL : CHOICE_ERROR;
}
static const char *opt_normals(scene_opts *o, const char *a)
{
    return scene_parse_normals(a, &o->normals) ? NULL : CHOICE_ERROR;
}
static const char *opt_level(scene_opts *o, const char *a)
{
    return scene_parse_float(a, 1.0f, SCENE_MAX_LEVEL, &o->level) ? NULL : SCENE_LEVEL_MSG;
}
static const char *opt_instances(scene_opts *o, const char *a)
{
    int n;
    if (!scene_parse_int(a, 0, INT32_MAX, &n)) return "--instances must be a whole number, 0..2147483647 (0: all)";
    o->instances = (unsigned)n;
    return NULL;
}
static const char *opt_grid(scene_opts *o, const char *a)
{
    return scene_parse_grid(a, &o->grid) ? NULL : CHOICE_ERROR;
}
static const char *opt_path(scene_opts *o, const char *a)
{
    return scene_parse_path(a, &o->path) ? NULL : CHOICE_ERROR;
}
static const char *opt_size(scene_opts *o, const char *a)
{
    return scene_parse_size(a, &o->width, &o->height) ? NULL : SCENE_SIZE_MSG;
}
static const char *opt_yaw(scene_opts *o, const char *a)
{
    return scene_parse_float(a, -1e6f, 1e6f, &o->yaw) ? NULL : "--yaw takes degrees, -1000000..1000000";
}
static const char *opt_pitch(scene_opts *o, const char *a)
{
    return scene_parse_float(a, -1e6f, 1e6f, &o->pitch) ? NULL : "--pitch takes degrees, -1000000..1000000";
}
static const char *opt_distance(scene_opts *o, const char *a)
{
    return scene_parse_float(a, 1.01f, 1000.0f, &o->distance) ? NULL : "--distance must be 1.01..1000";
}
static const char *opt_fill(scene_opts *o, const char *a)
{
    return scene_parse_fill(a, &o->fill) ? NULL : CHOICE_ERROR;
}
static const char *opt_msaa(scene_opts *o, const char *a)
{
    return scene_parse_msaa(a, &o->msaa) ? NULL : "--msaa must be 1 or 4";
}
static const char *opt_threads(scene_opts *o, const char *a)
{
    return scene_parse_int(a, 0, 256, &o->threads) ? NULL : "--threads must be 0..256";
}
static const char *opt_fov(scene_opts *o, const char *a)
{
    return scene_parse_float(a, 1.0f, 170.0f, &o->fov) ? NULL : "--fov must be 1..170 degrees";
}
static const char *opt_light(scene_opts *o, const char *a)
{
    static const char msg[] = "--light takes headlight, grazing, normals or a direction X,Y,Z of finite numbers, not "
                              "all zero";
    return scene_parse_light(a, o) ? NULL : msg;
}
static const char *opt_shading(scene_opts *o, const char *a)
{
    int k;
    if (!scene_parse_name(a, scene_shading_names, &k)) return CHOICE_ERROR;
    o->shading = (scene_shading)k;
    return NULL;
}
static const char *opt_texture(scene_opts *o, const char *a)
{
    o->texture_none = strcmp(a, "none") == 0;   /* a file named none: ./none */
    o->texture = o->texture_none ? NULL : a;
    return NULL;
}
static const char *opt_color(scene_opts *o, const char *a)
{
    return scene_parse_color(a, o->diffuse) ? NULL : "--color takes R,G,B (each 0..1) or #rrggbb";
}
static const char *opt_background(scene_opts *o, const char *a)
{
    float c[3];
    if (!scene_parse_color(a, c)) return "--background takes R,G,B (each 0..1) or #rrggbb";
    unsigned ch[3];
    for (int k = 0; k < 3; k++) ch[k] = (unsigned)lroundf(c[k] * 255.0f);
    o->background = IS_COLOR_ARGB(255, ch[0], ch[1], ch[2]);
    return NULL;
}
static const char *opt_phong_alpha(scene_opts *o, const char *a)
{
    return scene_parse_float(a, 0.0f, 1.0f, &o->phong_alpha) ? NULL : "--phong-alpha must be 0..1";
}
static const char *opt_n110_factor(scene_opts *o, const char *a)
{
    static const char msg[] = "--n110-factor must be 1..2 (2: reflection, 1.5: van Overveld)";
    return scene_parse_float(a, 1.0f, 2.0f, &o->n110_factor) ? NULL : msg;
}
static const char *opt_cull(scene_opts *o, const char *a)
{
    return scene_parse_cull(a, &o->cull) ? NULL : CHOICE_ERROR;
}
static const char *opt_import_timeout(scene_opts *o, const char *a)
{
    return scene_parse_int(a, 1, 86400, &o->import_timeout_s) ? NULL : "--import-timeout takes seconds, 1..86400";
}
static const char *opt_up(scene_opts *o, const char *a)
{
    return scene_parse_name(a, scene_up_names, &o->up) ? NULL : CHOICE_ERROR;
}
static const char *opt_fit(scene_opts *o, const char *a)
{
    return scene_parse_name(a, scene_fit_names, &o->fit) ? NULL : CHOICE_ERROR;
}
static const char *opt_recompute(scene_opts *o, const char *a) { return o->recompute_normals = true, NULL; }

/* A size in MiB in [lo, 2^20] into *out; NULL or msg. */
static const char *parse_mib(const char *a, int lo, unsigned *out, const char *msg)
{
    int mib;
    if (!scene_parse_int(a, lo, 1 << 20, &mib)) return msg;
    *out = (unsigned)mib;
    return NULL;
}
static const char *opt_max_memory(scene_opts *o, const char *a)
{
    return parse_mib(a, 16, &o->max_memory_mib, "--max-memory takes MiB, 16..1048576");
}
static const char *opt_max_file_size(scene_opts *o, const char *a)
{
    return parse_mib(a, 1, &o->max_file_mib, "--max-file-size takes MiB, 1..1048576");
}
static const char *opt_max_import_memory(scene_opts *o, const char *a)
{
    return parse_mib(a, 16, &o->max_import_memory_mib, "--max-import-memory takes MiB, 16..1048576");
}
static const char *opt_aov(scene_opts *o, const char *a)
{
    return scene_parse_aovs(a, &o->aovs) ? NULL : "--aov takes normal,bary,instance,gregory,uv,depth";
}
/* --d3d9-adaptive: "depth" or four finite numbers "X,Y,Z,W" (scene.h). */
static const char *opt_d3d9_adaptive(scene_opts *o, const char *a)
{
    static const char msg[] = "--d3d9-adaptive takes depth or X,Y,Z,W (four finite numbers)";
    if (strcmp(a, "depth") == 0) return o->d3d9_adaptive = SCENE_D3D9_DEPTH, NULL;
    char *end;
    const char *p = a;
    for (int i = 0; i < 4; i++) {
        if (!scene_plain_number(p)) return msg;
        o->d3d9_mdm[i] = strtof(p, &end);
        if (end == p || !isfinite(o->d3d9_mdm[i]) || *end != (i < 3 ? ',' : '\0')) return msg;
        p = end + 1;
    }
    o->d3d9_adaptive = SCENE_D3D9_MDM;
    return NULL;
}
static const char *lod_choices(const char *sep, char *buf, size_t len)
{
    return scene_join_names(scene_lod_names, sep, buf, len);
}
static const char *opt_lod(scene_opts *o, const char *a)
{
    return scene_parse_lod(a, &o->lod) ? NULL : CHOICE_ERROR;
}
static const char *opt_lod_target(scene_opts *o, const char *a)
{
    return scene_parse_float(a, 0.25f, 4096.0f, &o->lod_target) ? NULL : "--lod-target takes pixels, 0.25..4096";
}
static const char *opt_lod_deviation(scene_opts *o, const char *a)
{
    return scene_parse_float(a, 0.125f, 64.0f, &o->lod_deviation) ? NULL : "--lod-deviation takes pixels, 0.125..64";
}
static const char *opt_min_level(scene_opts *o, const char *a)
{
    return scene_parse_int(a, 1, CORE_LOD_MAX_LEVEL, &o->min_level) ? NULL : "--min-level must be 1..64";
}
static const char *opt_max_level(scene_opts *o, const char *a)
{
    return scene_parse_int(a, 1, CORE_LOD_MAX_LEVEL, &o->max_level) ? NULL : "--max-level must be 1..64";
}
static const char *opt_silhouette(scene_opts *o, const char *a) { return o->silhouette = true, NULL; }
static const char *opt_wire_levels(scene_opts *o, const char *a)
{
    if (strcmp(a, "on") != 0 && strcmp(a, "off") != 0) return "--wire-levels takes on or off";
    return o->wire_by_level = strcmp(a, "on") == 0, NULL;
}
static const char *opt_displace(scene_opts *o, const char *a) { return o->displace = a, NULL; }
static const char *opt_displace_scale(scene_opts *o, const char *a)
{
    return scene_parse_float(a, -10.0f, 10.0f, &o->displace_scale) ? NULL : SCENE_DISPLACE_SCALE_MSG;
}
static const char *opt_export_obj(scene_opts *o, const char *a) { return o->export_obj = a, NULL; }
static const char *opt_output(scene_opts *o, const char *a) { return o->output = a, NULL; }
static const char *opt_quiet(scene_opts *o, const char *a) { return o->quiet = true, NULL; }
static const char *opt_stats(scene_opts *o, const char *a)
{
    if (strcmp(a, "text") != 0 && strcmp(a, "json") != 0) return CHOICE_ERROR;
    return o->stats_json = strcmp(a, "json") == 0, NULL;
}

/* ------------------------------------ values (the description) ------------------------------------ */

/* printf into buf; buf. */
static const char *val_printf(char *buf, size_t len, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static const char *val_printf(char *buf, size_t len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, len, fmt, ap);
    va_end(ap);
    return buf;
}
/* A value printer of a float field, a name from a table, or a flag (on / off). */
#define VALUE_FLOAT(fn, field) \
    static const char *fn(const scene_opts *o, char *b, size_t n) { return val_printf(b, n, "%g", (double)o->field); }
#define VALUE_NAME(fn, expr) \
    static const char *fn(const scene_opts *o, char *b, size_t n) { return val_printf(b, n, "%s", (expr)); }
#define VALUE_FLAG(fn, field) \
    static const char *fn(const scene_opts *o, char *b, size_t n) { return val_printf(b, n, "%s", o->field ? "on" : "off"); }
VALUE_NAME(val_patch, vs_patch_name(o->patch))
VALUE_NAME(val_normals, vs_normals_name(o->normals))
VALUE_FLOAT(val_phong_alpha, phong_alpha)
VALUE_FLOAT(val_n110, n110_factor)
VALUE_FLOAT(val_level, level)
VALUE_NAME(val_grid, scene_grid_name(o->grid))
VALUE_NAME(val_path, scene_path_names[o->path])
VALUE_NAME(val_up, scene_up_names[o->up])
VALUE_FLOAT(val_yaw, yaw)
VALUE_FLOAT(val_pitch, pitch)
VALUE_FLOAT(val_distance, distance)
VALUE_FLOAT(val_fov, fov)
VALUE_NAME(val_fill, scene_fill_names[o->fill])
VALUE_NAME(val_fit, scene_fit_names[o->fit])
VALUE_NAME(val_cull, scene_cull_names[o->cull - IS_CULL_NONE])
VALUE_NAME(val_lod, scene_lod_names[o->lod])
VALUE_FLOAT(val_lod_target, lod_target)
VALUE_FLOAT(val_lod_deviation, lod_deviation)
VALUE_FLAG(val_silhouette, silhouette)
VALUE_FLAG(val_wire_levels, wire_by_level)
VALUE_FLAG(val_recompute, recompute_normals)
static const char *val_size(const scene_opts *o, char *b, size_t n) { return val_printf(b, n, "%dx%d", o->width, o->height); }
static const char *val_msaa(const scene_opts *o, char *b, size_t n) { return val_printf(b, n, "%d", o->msaa); }
static const char *val_min_level(const scene_opts *o, char *b, size_t n) { return val_printf(b, n, "%d", o->min_level); }
static const char *val_max_level(const scene_opts *o, char *b, size_t n)
{
    return val_printf(b, n, "%d", scene_lod_max_level(o));
}
static const char *val_light(const scene_opts *o, char *b, size_t n) { return scene_light_name(o, b, n); }
static const char *val_shading(const scene_opts *o, char *b, size_t n)
{
    return val_printf(b, n, "%s", scene_shading_names[o->shading]);
}
static const char *val_texture(const scene_opts *o, char *b, size_t n)
{
    return o->texture ? val_printf(b, n, "%s", o->texture) : NULL;
}
static const char *val_instances(const scene_opts *o, char *b, size_t n)
{
    return o->instances ? val_printf(b, n, "%u", o->instances) : NULL;
}
static const char *val_color(const scene_opts *o, char *b, size_t n)
{
    return val_printf(b, n, "%g,%g,%g", (double)o->diffuse[0], (double)o->diffuse[1], (double)o->diffuse[2]);
}
static const char *val_background(const scene_opts *o, char *b, size_t n)
{
    return val_printf(b, n, "#%06x", (unsigned)(o->background & 0xffffffu));
}
static const char *val_aov(const scene_opts *o, char *b, size_t n)
{
    size_t k = 0;
    b[0] = '\0';
    for (int i = 0; i < SCENE_AOV_COUNT; i++)
        if (o->aovs & scene_aov_table[i].bit)
            k += (size_t)snprintf(b + k, k < n ? n - k : 0, "%s%s", k ? "," : "", scene_aov_table[i].name);
    return k ? b : val_printf(b, n, "none");
}
static const char *val_d3d9_adaptive(const scene_opts *o, char *b, size_t n)
{
    if (o->d3d9_adaptive == SCENE_D3D9_DEPTH) return val_printf(b, n, "depth");
    if (o->d3d9_adaptive == SCENE_D3D9_OFF) return val_printf(b, n, "off");
    return val_printf(b, n, "%g,%g,%g,%g", (double)o->d3d9_mdm[0], (double)o->d3d9_mdm[1], (double)o->d3d9_mdm[2],
                      (double)o->d3d9_mdm[3]);
}
/* --displace: the map's name and, once read, the FNV-1a hash of its pixels (the pixels depend on them); NULL
 * (not in the description) without a map, as --displace-scale then. */
static const char *val_displace(const scene_opts *o, char *b, size_t n)
{
    if (!o->displace) return NULL;
    if (!o->displace_map) return val_printf(b, n, "%s", o->displace);
    uint64_t h = 0xcbf29ce484222325ull;
    const is_image *m = o->displace_map;
    const unsigned char *p = (const unsigned char *)m->data;
    for (size_t k = 0; k < (size_t)m->width * m->height * m->channels * sizeof(float); k++)
        h = (h ^ p[k]) * 0x100000001b3ull;
    return val_printf(b, n, "%s (%dx%d, FNV-1a 0x%016llx)", o->displace, m->width, m->height, (unsigned long long)h);
}
static const char *val_displace_scale(const scene_opts *o, char *b, size_t n)
{
    return o->displace ? val_printf(b, n, "%g", (double)o->displace_scale) : NULL;
}

/* ------------------------------------ the table ------------------------------------ */

const scene_option scene_options[] = {
    {"mesh", 0, "NAME|FILE", "the mesh: a built-in (tetrahedron, cube, cube-split, octahedron, icosahedron, sphere, "
     "cylinder) or a file assimp reads (OBJ, PLY, OFF, STL, MD2, glTF...); also the positional MESH", "cube",
     opt_mesh, NULL, NULL},
    {"patch", 0, "P", "the curved patch", "smooth", opt_patch, patch_choices, val_patch},
    {"normals", 0, "N", "the normals the patch shades with: real (the patch's own, from its derivatives) shows how "
     "the patches differ; D3D9 and the listings used linear (D3DRS_NORMALDEGREE's default), under which every curved "
     "patch shades alike", "real; linear on --path npatch-mode and cpu", opt_normals, normals_choices, val_normals},
    {"phong-alpha", 0, "A", "Phong tessellation's shape factor: 0 flat, 1 the full projection (Boubekeur and Alexa "
     "2008)", "0.75", opt_phong_alpha, NULL, val_phong_alpha},
    {"n110-factor", 0, "F", "the quadratic normals' mid-edge normal n110 = normalize(n0 + n1 - v (p1 - p0)), v = F "
     "dot(p1 - p0, n0 + n1) / |p1 - p0|^2: 2 reflects the average normal (Vlachos et al.), 1.5 is van Overveld and "
     "Wyvill's factor (Real-Time Rendering)", "2", opt_n110_factor, NULL, val_n110},
    {"level", 0, "N", "tessellation level, 1..256 (fractional with the pg-* grids)", "8", opt_level, NULL, val_level},
    {"grid", 0, "G", "the barycentric grid drawn per triangle", "regular", opt_grid, grid_choices, val_grid},
    {"instances", 0, "N", "draw only the patches of the first N mesh triangles: the instanced draw's count "
     "(SetStreamSourceFreq(0, INDEXEDDATA | N)), the technique one instance at a time (--lod uniform)", "0: all",
     opt_instances, NULL, val_instances},
    {"path", 0, "P", "how the patch is drawn (npatch-mode and cpu: N-Patch or flat only)", "instanced", opt_path,
     path_choices, val_path},
    {"size", 0, "WxH", "image size in pixels", "512x512", opt_size, NULL, val_size},
    {"up", 0, "AXIS", "the mesh's axis drawn upwards, in the file's own frame (Blender and many CAD files: z)", "y",
     opt_up, up_choices, val_up},
    {"yaw", 0, "DEG", "rotation of the object about the vertical axis", "30", opt_yaw, NULL, val_yaw},
    {"pitch", 0, "DEG", "rotation of the object about the horizontal axis", "20", opt_pitch, NULL, val_pitch},
    {"distance", 0, "D", "camera distance in units of the mesh's bounding radius", "3.2", opt_distance, NULL, val_distance},
    {"fov", 0, "DEG", "vertical field of view", "45", opt_fov, NULL, val_fov},
    {"fill", 0, "F", "what is drawn", "solid", opt_fill, fill_choices, val_fill},
    {"light", 0, "L", "headlight: the listing's saturate(dot(N, (0,0,-1))); X,Y,Z: a light from that world-space "
     "direction (x right, y up, -z towards the camera) with 0.08 ambient; grazing: 0.62,0.62,-0.48 (valleys show); "
     "normals: colour by the unit normal", "headlight", opt_light, NULL, val_light},
    {"shading", 0, "S", "where the light is computed: vertex (the listings: per grid vertex, Gouraud in between) or "
     "pixel (a pixel shader evaluates the patch's --normals normal at each pixel's barycentrics and lights it; "
     "--path instanced, --lod uniform, no --displace)", "vertex", opt_shading, shading_choices, val_shading},
    {"texture", 0, "FILE", "multiply the colour by this image (PNG, BMP, TGA, EXR) at the mesh's texture "
     "coordinates, in a pixel shader: mip-mapped, trilinear, wrapping (an MD2 model's skin, say); without it a mesh "
     "file's own texture (its material's, or an MD2's skin beside it) is used, said on stderr; none: untextured",
     "the mesh's own, if any", opt_texture, NULL, val_texture},
    {"color", 0, "R,G,B", "the surface colour (g_vDiffuse), each 0..1, or #rrggbb", "0.85,0.78,0.62", opt_color, NULL, val_color},
    {"background", 0, "R,G,B", "the background colour, each 0..1, or #rrggbb", "#2e3440", opt_background, NULL, val_background},
    {"fit", 0, "F", "framing: sphere puts the camera --distance bounding radii away; box computes the distance at "
     "which the turned bounding box fills the image (for long or flat models; --distance is then not used)", "sphere", opt_fit, fit_choices, val_fit},
    {"cull", 0, "C", "the faces not drawn (D3DRS_CULLMODE): ccw culls the back faces (fronts run clockwise), cw "
     "culls the fronts (shows a mesh wound the other way), none draws both sides (inside-out or open meshes)",
     "ccw, D3D9's default", opt_cull, cull_choices, val_cull},
    {"msaa", 0, "1|4", "samples per pixel", "4", opt_msaa, NULL, val_msaa},
    {"threads", 0, "N", "threads (0: all cores; the image does not depend on it)", "0", opt_threads, NULL, NULL},
    {"lod", 0, "MODE", "level of detail: one --level for all (uniform), or a level per mesh edge from its "
     "midpoint's view depth (distance), its projected length (screen) or how far its projected curve lies from "
     "its segments (deviation), drawn with one instanced call per pattern", "uniform", opt_lod, lod_choices, val_lod},
    {"lod-target", 0, "PIXELS", "--lod screen: pixels per segment of an edge's projected control polygon", "8",
     opt_lod_target, NULL, val_lod_target},
    {"lod-deviation", 0, "PIXELS", "--lod deviation: the screen-space distance allowed between an edge's curve and "
     "its segments", "0.5", opt_lod_deviation, NULL, val_lod_deviation},
    {"min-level", 0, "N", "--lod distance|screen|deviation: the coarsest edge level, 1..64", "1", opt_min_level, NULL, val_min_level},
    {"max-level", 0, "N", "--lod distance|screen|deviation: the finest edge level, 1..64", "--level", opt_max_level, NULL, val_max_level},
    {"silhouette", 0, NULL, "--lod distance|screen|deviation: edges between a front and a back face get --max-level", NULL,
     opt_silhouette, NULL, val_silhouette},
    {"wire-levels", 0, "on|off", "--lod with a wireframe: each pattern's wire in the colour of its finest level "
     "(blue 1, green 8, red 64)", "off", opt_wire_levels, NULL, val_wire_levels},
    {"recompute-normals", 0, NULL, "ignore the file's normals and recompute them (angle-weighted)", NULL,
     opt_recompute, NULL, val_recompute},
    {"import-timeout", 0, "S", "seconds the mesh import (assimp, run in a child process) may take before it is "
     "stopped and reported", "60", opt_import_timeout, NULL, NULL},
    {"max-memory", 0, "MIB", "the memory a render may take, checked before it starts", "4096", opt_max_memory, NULL, NULL},
    {"max-file-size", 0, "MIB", "the largest mesh file (with the files it refers to) read", "256",
     opt_max_file_size, NULL, NULL},
    {"max-import-memory", 0, "MIB", "memory for the mesh import", "by the files' size", opt_max_import_memory, NULL, NULL},
    {"aov", 0, "LIST", "EXR only: extra float channels (one sample per pixel), comma-separated: normal (N.X,N.Y,N.Z, "
     "the patch's unit normal), bary (bary.X,Y,Z), instance (the triangle's index; -1 on the background, which no "
     "triangle has), gregory (gregory.X,Y,Z), uv (uv.U,uv.V: the texture coordinates TEXCOORD0; added by itself with "
     "--texture), depth (view-space depth in the mesh's units; +inf on the background); the others are 0 on the "
     "background", NULL, opt_aov, NULL, val_aov},
    {"d3d9-adaptive", 0, "MDM", "npatch-mode: D3D9's adaptive tessellation, per vertex level * ref / depth, per edge "
     "the mean, clamped to 1..--level; MDM is depth (the view depth over the nearest point's) or X,Y,Z,W (D3DRS_"
     "ADAPTIVETESS_*, dotted with the mesh's vertices)", NULL, opt_d3d9_adaptive, NULL, val_d3d9_adaptive},
    {"displace", 0, "FILE", "move every patch along its normal (--normals) by --displace-scale times the height "
     "that the vertex shader fetches from this image (PNG, BMP, TGA, EXR; its red channel, or grey) at the patch's "
     "texture coordinates, linear filtered, wrapping (vertex texture fetch)", NULL, opt_displace, NULL, val_displace},
    {"displace-scale", 0, "S", "--displace: bounding radii per unit of height, -10..10 (negative: inwards)", "0.1",
     opt_displace_scale, NULL, val_displace_scale},
    {"export-obj", 0, "FILE.obj", "also write the tessellated surface as OBJ (positions, texture coordinates, normals) "
     "in the input's own frame: right-handed, counter-clockwise fronts, as assimp reads it", NULL, opt_export_obj,
     NULL, NULL},
    {"output", 'o', "FILE", "the image: .png (8-bit sRGB over the background colour, A = 1) or .exr (R, G, B linear "
     "and premultiplied by A = the pixel's coverage, the background transparent; half floats; Z = D3D9's depth z/w "
     "in [MinZ, MaxZ] = [0, 1], 1 on the background, float; then the AOVs)", NULL, opt_output, NULL, NULL},
    {"quiet", 'q', NULL, "no statistics and no progress line on stderr (warnings are still printed); the progress "
     "line is drawn only on a terminal, for runs longer than a second", NULL, opt_quiet, NULL, NULL},
    {"stats", 0, "FORMAT", "the statistics of a render: text on stderr, or json, one object on stdout for scripts "
     "(with the same figures, printed also with -q)", "text", opt_stats, stats_choices, NULL},
};
const size_t scene_option_count = sizeof scene_options / sizeof scene_options[0];

const scene_option *scene_find_option(const char *name)
{
    for (size_t k = 0; k < scene_option_count; k++)
        if (strcmp(scene_options[k].name, name) == 0) return &scene_options[k];
    return NULL;
}

const char *scene_apply_option(scene_opts *o, const scene_option *opt, const char *arg, char *buf, size_t len)
{
    const char *msg = opt->apply(o, arg);
    return msg == CHOICE_ERROR ? unknown_choice(opt, buf, len) : msg;
}

/* ------------------------------------ usage ------------------------------------ */

/* The left column of opt's help line ("  -o, --output FILE") into buf; buf. */
static const char *option_label(const scene_option *opt, char *buf, size_t len)
{
    char shortname[8] = "";
    if (opt->short_name) snprintf(shortname, sizeof shortname, "-%c, ", opt->short_name);
    snprintf(buf, len, "  %s--%s%s%s", shortname, opt->name, opt->metavar ? " " : "", opt->metavar ? opt->metavar : "");
    return buf;
}

enum { HELP_INDENT = 28, HELP_WIDTH = 110 };

/* text into f, wrapped at spaces to HELP_WIDTH columns, continuation lines indented HELP_INDENT; col is the
 * column the text starts at. */
static void print_wrapped(FILE *f, const char *text, int col)
{
    while (*text) {
        int room = HELP_WIDTH - col, n = (int)strlen(text);
        if (n > room) {   /* break at the last space that fits (or the first one, for a long word) */
            int cut = room;
            while (cut > 0 && text[cut] != ' ') cut--;
            if (cut == 0) cut = (int)(strchr(text, ' ') ? strchr(text, ' ') - text : n);
            n = cut;
        }
        while (n > 0 && text[n - 1] == ' ') n--;
        fprintf(f, "%.*s\n", n, text);
        text += n;
        while (*text == ' ') text++;
        if (*text) fprintf(f, "%*s", HELP_INDENT, ""), col = HELP_INDENT;
    }
}

/* One option's lines of --help into f: label, text, the choices and the default. */
static void print_option(FILE *f, const scene_option *opt)
{
    char label[96], names[512] = "", text[1400];
    option_label(opt, label, sizeof label);
    if (opt->choices) opt->choices(" | ", names, sizeof names);
    snprintf(text, sizeof text, "%s%s%s%s%s%s", opt->help, *names ? ": " : "", names, opt->deflt ? "  [" : "",
             opt->deflt ? opt->deflt : "", opt->deflt ? "]" : "");
    fprintf(f, "%-*s", HELP_INDENT, label);
    print_wrapped(f, text, HELP_INDENT > (int)strlen(label) ? HELP_INDENT : (int)strlen(label));
}

void scene_print_options(FILE *f)
{
    scene_print_options_except(f, NULL);
}

void scene_print_options_except(FILE *f, const char *const *skip)
{
    for (size_t k = 0; k < scene_option_count; k++) {
        bool skipped = false;
        for (size_t s = 0; skip && skip[s]; s++) skipped |= strcmp(skip[s], scene_options[k].name) == 0;
        if (!skipped) print_option(f, &scene_options[k]);
    }
    fprintf(f, "%-*s%s\n%-*s%s\n", HELP_INDENT, "  -h, --help", "this text", HELP_INDENT, "  -V, --version",
            "the version, the libraries it was built with and the rasterizer kernels this CPU runs");
}

/* ------------------------------------ parsing ------------------------------------ */

/* getopt_long's table of scene_options (plus --help, --version) into lo (scene_option_count + 3 entries). */
static void long_options(struct option *lo)
{
    size_t k = 0;
    for (; k < scene_option_count; k++)
        lo[k] = (struct option){scene_options[k].name, scene_options[k].metavar ? required_argument : no_argument, 0,
                                (int)(256 + k)};
    lo[k++] = (struct option){"help", no_argument, 0, 'h'};
    lo[k++] = (struct option){"version", no_argument, 0, 'V'};
    lo[k] = (struct option){0, 0, 0, 0};
}

/* The option of getopt's return value c, or NULL. */
static const scene_option *option_of(int c)
{
    if (c >= 256 && (size_t)(c - 256) < scene_option_count) return &scene_options[c - 256];
    for (size_t k = 0; k < scene_option_count; k++)
        if (scene_options[k].short_name && scene_options[k].short_name == c) return &scene_options[k];
    return NULL;
}

int scene_parse_args(int argc, char **argv, scene_opts *o, scene_args_result *res, char *err, size_t errlen)
{
    struct option lo[sizeof scene_options / sizeof scene_options[0] + 3];
    long_options(lo);
    bool mesh_given = false, normals_given = false;
    int c;
    opterr = 0;
    optind = 1;
    *res = SCENE_ARGS_RUN;
    while ((c = getopt_long(argc, argv, "o:qhV", lo, NULL)) != -1) {
        if (c == 'h' || c == 'V') return *res = c == 'h' ? SCENE_ARGS_HELP : SCENE_ARGS_VERSION, 0;
        const scene_option *opt = option_of(c);
        if (!opt) return snprintf(err, errlen, "unknown option or missing value: %s", argv[optind - 1]), -1;
        char buf[600];
        const char *msg = scene_apply_option(o, opt, optarg, buf, sizeof buf);
        if (msg) return snprintf(err, errlen, "%s%s%s", msg, optarg ? ": " : "", optarg ? optarg : ""), -1;
        mesh_given |= opt->apply == opt_mesh;
        normals_given |= opt->apply == opt_normals;
    }
    /* the default normals are the patch's own (real), which only the instanced path evaluates: the fixed-function
     * paths default to D3D9's linear normals (--help says so) */
    if (!normals_given && o->path != SCENE_PATH_INSTANCED && o->normals == VS_NORMALS_REAL)
        o->normals = VS_NORMALS_LINEAR;
    if (optind < argc && !mesh_given) o->mesh = argv[optind++];   /* instess MESH -o OUT (getopt moved it last) */
    if (optind < argc)
        return snprintf(err, errlen, "%s: %s", mesh_given ? "unexpected argument (the mesh is given by --mesh)"
                                                          : "unexpected argument", argv[optind]), -1;
    return 0;
}
