/* cli/run/scene.h -- one rendered scene: a mesh, a patch, a grid, a path, a camera; the programs' shared layer
 * (the instess command, figures, bench and the golden tests all render through it).
 *
 * Conventions: the object is centred on its bounding box and scaled by 1 / bounding radius, then turned so that
 * the --up axis points up (+y), rotated by yaw (about y) and pitch (about x) -- the world matrix -- and seen by a
 * left-handed camera at (0, 0, -distance) looking at the origin with a vertical field of view of 45 degrees
 * (--fov; with --fit box the distance is the one at which the rotated bounding box fills the image).  The
 * listing's light direction (0, 0, -1) is in world space, so the lit side faces the camera (a headlight; --light
 * changes it).  Errors: functions return 0 or -1 with a message in err naming the input and what is wrong. */
#ifndef INSTESS_SCENE_H
#define INSTESS_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <pthread.h>
#include <stdio.h>

#include "../../core/core.h"
#include "../../core/hlsl.h"
#include "../../image/image.h"
#include "outputs.h"
#include "../../meshes/meshes.h"
#include "../../vs/vs.h"
#include "../../tess/tess.h"

#define SCENE_MAX_LEVEL 256.0f
#define SCENE_LEVEL_MSG "--level must be a number in 1..256"
#define SCENE_MAX_SIDE 16384
#define SCENE_MAX_PIXELS (64u * 1024u * 1024u)
#define SCENE_SIZE_MSG "--size must be WxH with each side 1..16384 and at most 64 Mpixels"
/* Largest number of tessellated vertices one render may evaluate (triangles x grid points). */
#define SCENE_MAX_VERTICES (64ull * 1024 * 1024)
/* The memory a render may take, checked before anything is allocated (--max-memory MIB raises it): the
 * estimate of scene_memory_estimate, which counts the target (samples x 8 bytes per pixel, plus the image's
 * floats), the instances, and on the CPU path SCENE_CPU_BYTES_PER_VERTEX per tessellated vertex (its vertex
 * buffer, indices and the device's shaded vertices: measured 397-400 bytes as peak RSS over the instanced path
 * on the sphere at levels 128 and 256), and with --lod the pattern cache's bound (CORE_PATTERN_CACHE_DEFAULT_BYTES
 * plus its 1 MiB index) and the renumbered instances.  The instanced and N-patch-mode paths shade in bounded chunks.
 * An adaptive render checks its pattern pool too, once its edges' levels are known and before the pool is built:
 * 24 bytes per point and 36 per triangle of the finest level's regular grid, per distinct level triple (up to
 * 45,760 of them at up to 200 KB each), must fit in what the estimate leaves of the budget. */
#define SCENE_DEFAULT_MAX_MEMORY_MIB 4096
#define SCENE_CPU_BYTES_PER_VERTEX 400ull

typedef enum { SCENE_FILL_SOLID, SCENE_FILL_WIRE, SCENE_FILL_SOLID_WIRE, SCENE_FILL_POINT } scene_fill;
typedef enum { SCENE_PATH_INSTANCED, SCENE_PATH_NPATCH_MODE, SCENE_PATH_CPU } scene_path;
/* The light (--light): the listing's headlight, a direction (with a little ambient), or colour by normal. */
typedef enum { SCENE_LIGHT_HEADLIGHT = 0, SCENE_LIGHT_DIRECTION = 1, SCENE_LIGHT_NORMALS = 2 } scene_light;
/* --shading: where the light is computed -- per vertex by the patch shader (the listings, Gouraud in between) or
 * per pixel by a pixel shader evaluating the patch's normal at the pixel's barycentrics (cli/run/shading.c). */
typedef enum { SCENE_SHADING_VERTEX = 0, SCENE_SHADING_PIXEL = 1 } scene_shading;
extern const char *const scene_shading_names[];   /* "vertex", "pixel", NULL */
/* --d3d9-adaptive: D3D9's adaptive N-patch mode (core.h) on the npatch-mode path.  "depth": Mdm = the view-depth
 * column of World * View divided by the depth of the object's nearest point (distance - 1 bounding radii), so
 * T = level * ref_depth / depth per vertex: --level at the nearest point, less farther away; "X,Y,Z,W": Mdm as
 * given (T = level * 1 / dot(V, Mdm), V the mesh's own vertex).  MINTESSELLATIONLEVEL 1, MAXTESSELLATIONLEVEL
 * --level. */
typedef enum { SCENE_D3D9_OFF, SCENE_D3D9_DEPTH, SCENE_D3D9_MDM } scene_d3d9_adaptive;
/* Level of detail (--lod): one --level for all (uniform), or a level per mesh edge (tess/lod.c). */
#define SCENE_LOD_DEFAULT_TARGET 8.0f   /* --lod-target: pixels per segment of an edge's control polygon */
#define SCENE_LOD_DEFAULT_DEVIATION 0.5f /* --lod-deviation: pixels an edge's polyline may lie from its curve */
/* The AOV channels of an EXR (--aov; README.md lists them with their background values): the patch's
 * unit normal N.X,N.Y,N.Z (0 on the background), barycentrics bary.* (0), the triangle's index `instance`
 * (SCENE_INSTANCE_BACKGROUND on the background: no triangle has it), Gregory coordinates gregory.* (0), and the
 * view-space depth `depth` (the distance from the camera's plane along the view direction, in the mesh's
 * units; +infinity on the background).  One sample per pixel. */
enum { SCENE_AOV_NORMAL = 1, SCENE_AOV_BARY = 2, SCENE_AOV_INSTANCE = 4, SCENE_AOV_GREGORY = 8, SCENE_AOV_DEPTH = 16,
       SCENE_AOV_UV = 32 };
/* ... and uv.U,uv.V: the interpolated texture coordinates TEXCOORD0.xy that --texture samples at (0 on the
 * background), added by itself to an .exr output of a render with --texture (scene_aovs_of).
 * The one table of the AOVs, in the order of the image's channels (after R,G,B,A,Z): its --aov name, SCENE_AOV_*
 * bit, the vertex shader output its plane copies (VS_OUT_*; -1: computed from the depth buffer, after the planes)
 * and its channels. */
typedef struct scene_aov { const char *name; unsigned bit; int slot, comps; const char *channels; } scene_aov;
#define SCENE_AOV_COUNT 6
extern const scene_aov scene_aov_table[SCENE_AOV_COUNT];
/* The AOVs a render of o writes: o->aovs, with SCENE_AOV_UV when o has a texture and an .exr output. */
struct scene_opts;
unsigned scene_aovs_of(const struct scene_opts *o);
#define SCENE_INSTANCE_BACKGROUND (-1.0f)

typedef struct scene_opts {
    const char *mesh;           /* built-in name or file */
    vs_patch patch;
    vs_normals normals;
    float level;
    core_grid_kind grid;
    scene_path path;
    int width, height;
    int up;                     /* the axis drawn upwards: SCENE_UP_* (scene_up_names) */
    float yaw, pitch, distance; /* degrees, degrees, bounding radii */
    int fit;                    /* SCENE_FIT_SPHERE (distance as given) or SCENE_FIT_BOX (distance computed) */
    scene_fill fill;
    int msaa;
    int threads;
    bool recompute_normals;
    unsigned aovs;              /* SCENE_AOV_* */
    float diffuse[4];           /* g_vDiffuse (--color) */
    float wire_color[4];        /* g_vDiffuse of the wireframe overlay */
    uint32_t background;        /* D3DCOLOR (ARGB) (--background) */
    scene_light light;          /* SCENE_LIGHT_HEADLIGHT: the listing's (0, 0, -1) (cli/run/lighting.c) */
    float light_dir[3];         /* towards the light, world space (SCENE_LIGHT_DIRECTION; normalised when used) */
    float fov;                  /* vertical field of view, degrees */
    float phong_alpha;          /* Phong tessellation's shape factor (vs_options.phong_alpha) */
    float n110_factor;          /* factor of v_ij in the quadratic normal's n110 (vs_options.quad_factor) */
    const char *output, *export_obj;
    uint32_t cull;              /* D3DRS_CULLMODE: IS_CULL_NONE, IS_CULL_CW or IS_CULL_CCW (D3D9's default) */
    bool quiet;
    bool stats_json;            /* --stats json: the statistics as one JSON object on stdout */
    int import_timeout_s;       /* the import child's time limit in seconds (0: meshes.h's default, 60) */
    unsigned max_memory_mib;    /* the memory budget (SCENE_DEFAULT_MAX_MEMORY_MIB) */
    unsigned max_file_mib;      /* a mesh file with its side files (0: meshes.h's default, 256 MiB) */
    unsigned max_import_memory_mib; /* the import child's memory (0: meshes.h's rule by the files' size) */
    scene_d3d9_adaptive d3d9_adaptive; /* --d3d9-adaptive (npatch-mode only): off, depth, or d3d9_mdm */
    float d3d9_mdm[4];          /* SCENE_D3D9_MDM: (ADAPTIVETESS_X, _Y, _Z, _W) as given */
    tess_lod_mode lod;              /* TESS_LOD_UNIFORM: o->level everywhere; else per-edge levels (tess/lod.c) */
    float lod_target;           /* screen: pixels per segment (SCENE_LOD_DEFAULT_TARGET) */
    float lod_deviation;        /* deviation: pixels from the curve (SCENE_LOD_DEFAULT_DEVIATION) */
    int min_level, max_level;   /* per-edge levels are clamped to these (1..CORE_LOD_MAX_LEVEL); max 0: --level */
    bool silhouette;            /* edges whose two faces face opposite ways get max_level */
    bool wire_by_level;         /* the wireframe of an adaptive draw coloured by each bucket's finest level */
    scene_shading shading;      /* --shading: vertex (the listings') or pixel (cli/run/shading.c) */
    unsigned instances;         /* --instances: draw only the first N mesh triangles' patches (0: all) */
    const char *texture;        /* --texture: the image multiplied in at TEXCOORD0 (cli/run/shading.c), or NULL */
    const is_image *texture_map; /* the image already read, or NULL: read per draw */
    bool texture_none;          /* --texture none: untextured, also a mesh with its own (scene_use_mesh_texture) */
    const char *displace;       /* --displace: the height map (cli/run/displace.c), or NULL */
    float displace_scale;       /* --displace-scale: bounding radii per unit of height (SCENE_DISPLACE_SCALE) */
    const is_image *displace_map; /* the map already read (scene_load_displacement), or NULL: read per draw */
} scene_opts;
#define SCENE_DISPLACE_SCALE 0.1f
#define SCENE_DISPLACE_SCALE_MSG "--displace-scale must be a number of bounding radii, -10..10"

/* Bytes a render of mesh_triangles triangles with grid_points points per triangle takes at most, by the
 * estimate stated at SCENE_DEFAULT_MAX_MEMORY_MIB. */
unsigned long long scene_memory_estimate(const scene_opts *o, size_t mesh_triangles, size_t grid_points);


/* The canonical description of a render of mesh m, stored in its image (ImageDescription): the mesh's name,
 * size and hash, then every option of the table (cli/run/options.c) that changes pixels with its value ("patch
 * smooth, level 8, ..."): not the thread count, the output's name or the time, so that two runs of one render
 * write the same bytes, and two renders with the same description have the same pixels; then, when channels is
 * not NULL, "channels " and that list (what the file holds).  As much as fits in buf[len] (NUL-terminated when
 * len > 0); the length of the whole description, as snprintf. */
size_t scene_describe(const scene_opts *o, const is_mesh *m, const char *channels, char *buf, size_t len);
/* The whole description of a render of m written as img into a file of format fmt: scene_describe with the
 * channels that file holds (image_file_channels: a PNG's first four, an EXR's all).  malloc'd (free it), or
 * NULL when out of memory. */
char *scene_describe_file(const scene_opts *o, const is_mesh *m, const is_image *img, is_image_format fmt);

/* What a render did (for statistics and the benchmark).  Adaptive renders also count their edges per level
 * (level_hist[l]: mesh edges at level l), buckets (draw calls per pass) and patterns. */
typedef struct scene_stats {
    size_t mesh_triangles, grid_points, grid_triangles;
    uint64_t vertices_shaded, triangles_drawn;
    rs_stats raster;
    uint64_t level_hist[CORE_LOD_MAX_LEVEL + 1];
    size_t n_buckets, n_patterns, tessellated_triangles;
} scene_stats;

/* Defaults: the welded cube, smoothed patch, real normals (the patch's own: the patches look as different as they
 * are; D3D9's were linear), level 8, 512x512, 4x MSAA, solid. */
void scene_opts_default(scene_opts *o);
/* NULL if the options are consistent, else the usage error (e.g. --aov without an .exr output). */
const char *scene_check_opts(const scene_opts *o);

/* Option parsers: true on success. */
bool scene_parse_patch(const char *s, vs_patch *out);
bool scene_parse_normals(const char *s, vs_normals *out);
bool scene_parse_grid(const char *s, core_grid_kind *out);
/* The --grid name of g. */
const char *scene_grid_name(core_grid_kind g);
/* The names --grid, --path and --fill take, NULL-terminated, in their enums' order (the patches' are vs/vs.h's
 * table, the normals' vs_normals_name). */
extern const char *const scene_grid_names[], *const scene_path_names[], *const scene_fill_names[];
/* --up's axes, in the input file's frame (its z is the import's -z), and --fit's framings, NULL-terminated. */
enum { SCENE_UP_X, SCENE_UP_Y, SCENE_UP_Z, SCENE_UP_NEG_X, SCENE_UP_NEG_Y, SCENE_UP_NEG_Z };
enum { SCENE_FIT_SPHERE, SCENE_FIT_BOX };
extern const char *const scene_up_names[], *const scene_fit_names[];
/* Index of s in the NULL-terminated names into *out; false if it is not there. */
bool scene_parse_name(const char *s, const char *const *names, int *out);
/* The names --cull takes, NULL-terminated: D3DCULL_NONE, _CW, _CCW (value = index + 1). */
extern const char *const scene_cull_names[];
bool scene_parse_cull(const char *s, uint32_t *out);
/* names joined by sep into buf (for messages and usage texts); buf. */
char *scene_join_names(const char *const *names, const char *sep, char *buf, size_t len);
bool scene_parse_path(const char *s, scene_path *out);
bool scene_parse_fill(const char *s, scene_fill *out);
bool scene_parse_size(const char *s, int *w, int *h);
/* "X,Y": a pixel's column and row from the top left, plain whole numbers 0..RS_MAX_SIZE-1 (--pixel, --pin). */
bool scene_parse_pixel(const char *s, int *x, int *y);
bool scene_parse_msaa(const char *s, int *out);
/* Whether s starts a number written plainly, up to its end or the next comma: an optional sign, then digits (or a
 * point and a digit), then only digits, '.', exponents and their signs -- never spaces, hexadecimal, "inf" or
 * "nan", which strtod would take.  Every numeric option is parsed through it (docs/robustness.md, "Round 3:
 * library API, viewer and numbers"). */
bool scene_plain_number(const char *s);
bool scene_parse_int(const char *s, int lo, int hi, int *out);
bool scene_parse_float(const char *s, float lo, float hi, float *out);
bool scene_parse_aovs(const char *s, unsigned *out);

/* ------------- light and colours (cli/run/lighting.c) ------------- */
/* "headlight" | "grazing" | "normals" | "X,Y,Z" (towards the light, world space, not zero) into o; true on success. */
bool scene_parse_light(const char *s, scene_opts *o);
/* The --light value of o (a name, or the direction written into buf). */
const char *scene_light_name(const scene_opts *o, char *buf, size_t len);
/* "R,G,B" (each 0..1) or "#rrggbb" into rgb; true on success. */
bool scene_parse_color(const char *s, float rgb[3]);
/* The shader that draws with o's light: path_shader itself for the headlight, else a wrapper that relights
 * its output (a shader of vs_shaders only; others are returned as they are).  Its constants c10, c11 are set by
 * scene_light_constants (nothing for the headlight). */
const is_vertex_shader *scene_light_shader(const scene_opts *o, const is_vertex_shader *path_shader);
void scene_light_constants(is_device *dev, const scene_opts *o, const is_vertex_shader *path_shader);
/* The shaders a wrapper (the light's, the displacement's) may wrap, by number: vs_shaders, then the light's
 * wrapper, then the displacement's (scene_displaced_shader).  scene_shader_index: s's number, or -1;
 * scene_shader_at: the shader of a number scene_shader_index gave. */
int scene_shader_index(const is_vertex_shader *s);
const is_vertex_shader *scene_shader_at(int k);

/* ------------- displacement by a vertex texture fetch (cli/run/displace.c) ------------- */
/* Read the height map of --displace into img: 0, or -1 with a message naming the file. */
int scene_load_displacement(const char *path, is_image *img, char *err, size_t errlen);
/* (cli/run/shading.c) --shading pixel on dev for o's patch of mesh m: the instances' registers in a float texture
 * bound to pixel sampler 0 (*tex: the caller releases it after the draw) and the pixel shader set; IS_OK or the
 * device's error.  scene_shading_constants copies the vertex shader's c0..c11 (matrices, colour, options, light)
 * into the pixel shader's, with the patch in c12.x: call it after each change of the vertex constants. */
is_result scene_shading_bind(is_device *dev, const scene_opts *o, const is_mesh *m, is_texture **tex);
void scene_shading_constants(is_device *dev, const scene_opts *o);
/* Without --texture (and not --texture none), a mesh file's own texture (is_mesh.texture, meshes.h: "The file's
 * texture") is drawn: o->texture becomes m->texture (m must outlive o's use), and unless o->quiet, note(user,
 * "MESH: textured with its own FILE (--texture none: without)").  Whether o now draws m's texture.  The run, the
 * Python call, inspect and the viewer call it after loading the mesh; the figures do not (their views say
 * --texture when they are textured). */
bool scene_use_mesh_texture(scene_opts *o, const is_mesh *m, void (*note)(void *user, const char *msg), void *user);
/* Does o draw a texture (o->texture, after scene_use_mesh_texture) on a mesh m whose vertices all have the same
 * texture coordinates (a file without them: (0, 0) everywhere), so that the whole mesh shows one texel's colour?
 * Then msg holds "MESH: has no texture coordinates (every vertex's (u, v) is (U, V)): TEXTURE draws one colour
 * over it" for a warning.  The run, the Python call, inspect and the viewer warn with it, also with -q. */
bool scene_texture_misfit(const scene_opts *o, const is_mesh *m, char *msg, size_t len);
/* --texture on dev: o's image (texture_map, or the file) as a mip-mapped texture on pixel sampler
 * SCENE_TEXTURE_SAMPLER (trilinear, wrapping; *tex: the caller releases it after the draw), and with --shading
 * vertex the pixel shader that multiplies COLOR0 by it.  IS_OK or the device's error. */
#define SCENE_TEXTURE_SAMPLER 1
is_result scene_texture_bind(is_device *dev, const scene_opts *o, is_texture **tex);
/* (cli/run/lighting.c) The colour of o's light as the registers c hold it (c8 the diffuse colour, c10.y the light,
 * c11 its direction) for the world-space normal Normal (the listing's headlight takes it as it is, the others
 * normalise it): what the patch shaders and the light's wrapper write to COLOR0. */
float4 scene_light_color(const float4 *c, float3 Normal);
/* The shader that draws o's scene displaced: the wrapper scene_displaced_shader around inner (the path's shader,
 * a shader of scene_shader_index) when o->displace, else inner itself; the light's wrapper goes around it. */
extern const is_vertex_shader scene_displaced_shader;
const is_vertex_shader *scene_displace_shader(const scene_opts *o, const is_vertex_shader *inner);
/* The map of o (o->displace_map, or the file o->displace) as a texture of dev in vertex sampler 0 with its states,
 * and the wrapper's constants c12..c16 (inner, the scale, radius = the mesh's bounding radius, view_proj = View *
 * Proj); *tex is the caller's to release.  IS_OK, or the device's error (its message names the file). */
is_result scene_displace_bind(is_device *dev, const scene_opts *o, const float4x4 *view_proj, float radius,
                              const is_vertex_shader *inner, is_texture **tex);
/* The displacement itself, applied to outputs a patch shader wrote (oPos, from TEXCOORD0 and TEXCOORD1): what the
 * wrapper does after its inner shader, for shaders of the caller's (the crack tests) that wrap a patch shader. */
void scene_displace_apply(const is_vs_constants *c, is_vs_output *out);

/* Draw mesh m with grid g on dev as o says (path, fill, camera, constants c0..c9), with o's shader or, if
 * shader is not NULL, that one (tests wrap the patch shaders; with --displace the map and its constants are bound
 * for it, and it calls scene_displace_apply itself).  The device's other states are left as the
 * caller set them, apart from FILLMODE, DEPTHBIAS, SLOPESCALEDEPTHBIAS and the N-patch states.  0 or -1
 * (dev_last_error tells why). */
int scene_draw(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g,
               const is_vertex_shader *shader);
/* A picture: what `instess -o` and `instess figures` hold before they write a file.  R, G, B are display (sRGB)
 * values over the background colour, A the coverage: the fraction of the pixel's samples the mesh covers (0 on
 * the background; text drawn over a picture with image_draw_text adds its opacity), then Z -- D3D9's depth z/w
 * in [MinZ, MaxZ] = [0, 1] of the nearest sample, 1 on the background -- and the AOV channels.
 * scene_render_picture: render a loaded mesh into img (allocated here: R, G, B, A, Z, then the AOVs asked for).
 * scene_picture_for_format: in place, what a file of format fmt holds of picture img (background the colour the
 * picture was rendered over): a PNG the display values with A = 1 (opaque over the background); an EXR
 * R, G, B = the colour without the background (C = a F + (1 - a) B solved for F), decoded from sRGB to linear
 * and premultiplied by A, so the background is transparent black (OpenEXR's associated alpha, tagged linear),
 * the other channels as they are.  scene_write_picture: the one writer of image files -- that form of img for
 * the format of output k's path, encoded into output k of outs (a copy: img is unchanged); 0 or -1.
 * scene_render_mesh: scene_render_picture, then the form of o->output's format (a PNG's when o->output is
 * NULL). */
int scene_render_picture(const scene_opts *o, const is_mesh *mesh, is_image *img, scene_stats *st, char *err,
                         size_t errlen);
void scene_picture_for_format(is_image *img, is_image_format fmt, uint32_t background);
int scene_write_picture(is_outputs *outs, int k, const is_image *img, uint32_t background, const is_image_meta *meta,
                        char *err, size_t errlen);
int scene_render_mesh(const scene_opts *o, const is_mesh *mesh, is_image *img, scene_stats *st, char *err,
                      size_t errlen);
/* The pieces of scene_render_mesh for programs that render frame after frame (instess view, cli/view/view_state.c).
 * scene_fit_mesh: the mesh to draw for mesh -- mesh itself, or a copy moved to the origin and scaled to unit
 * radius in *copy when its coordinates are extreme (mesh_free(copy) afterwards in both cases).
 * scene_check_limits: the limits a render of m with g must respect (the vertex limit and the memory budget): 0,
 * or -1 with the CLI's message.  scene_create_device: a device of o's size and threads with `samples` samples
 * and the AOV planes `aovs` (SCENE_AOV_*, samples 1 only), or NULL with a message.  scene_render_on: clear dev
 * and draw, setting o's cull mode (dev's other states as a new device's: dev_reset a device that drew before);
 * 0, or -1 with a message; st gets the counters added. */
const is_mesh *scene_fit_mesh(const is_mesh *mesh, is_mesh *copy);
int scene_check_limits(const scene_opts *o, const is_mesh *m, const core_grid *g, char *err, size_t errlen);
is_device *scene_create_device(const scene_opts *o, int samples, unsigned aovs, char *err, size_t errlen);
int scene_render_on(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g, scene_stats *st,
                    char *err, size_t errlen);
/* The one way a view is rendered (the run, the figures, the viewer's first frame and the tests go through it;
 * the viewer then redraws its devices with scene_render_on): a new device of o's size with `samples` samples and
 * the AOV planes `aovs` (samples 1 only), cleared and drawn as o says (cull mode, path, LOD, light).  The device,
 * or NULL with a message; st gets the counters added. */
is_device *scene_render_view(const scene_opts *o, const is_mesh *m, const core_grid *g, int samples, unsigned aovs,
                             scene_stats *st, char *err, size_t errlen);
/* The picture's first channels from rt: the resolved colour, the coverage and the nearest sample's depth of
 * each pixel into img's channels 0..4 (R, G, B, A, Z; img has rt's size and at least 5 channels).  0, or -1
 * when out of memory. */
int scene_copy_color_depth(const rs_target *rt, is_image *img, char *err, size_t errlen);
/* Whether the file's normals of m do not fit its surface (cli/run/normals_fit.c: across the edges where the
 * file's normals are shared, the N-Patch creases more than twice, and 1 degree more, than over normals computed
 * from the triangles -- the shading looks quilted); then the warning, naming --recompute-normals, into msg.
 * False for computed normals (and when out of memory: it is only a warning). */
bool scene_normals_misfit(const is_mesh *m, char *msg, size_t len);
/* The mesh loader's options of o (--recompute-normals, the file and import limits, the import timeout) with its
 * warnings to warn(user, msg). */
is_mesh_options scene_mesh_options(const scene_opts *o, void (*warn)(void *user, const char *msg), void *user);
/* A warn for scene_mesh_options: "instess: warning: MSG" on stderr unless *(const bool *)quiet (o->quiet). */
void scene_warn_unless_quiet(void *quiet, const char *msg);
/* A note for scene_use_mesh_texture: "instess: MSG" on stderr (user is not used). */
void scene_note_stderr(void *user, const char *msg);
/* Load o->mesh, render, write o->output atomically (and o->export_obj); print statistics unless quiet; warn
 * (scene_normals_misfit) when the file's normals do not fit its surface. */
int scene_render_to_file(const scene_opts *o, char *err, size_t errlen);
/* (cli/run/render_call.c) What `instess ARGV -o FILE` writes into a file of format fmt (IS_IMAGE_PNG or
 * IS_IMAGE_EXR: the colour of that format), rendered into img (allocated: image_free it) and not written: the
 * render options of argv[0..argc-1] (no program name; -o, --export-obj and --stats are refused), checked as the
 * program checks them.  img holds the program's channels (R, G, B, A, Z and the AOVs); a PNG file holds the
 * first four of them, an EXR all (image_file_channels).  The mesh loader's warnings and what was changed from
 * what was asked (a level outside a primitive-generator grid's range) go to notes, one per line; nothing is
 * printed.  0, or -1 with the usage or input error in err.  Exported by libinstess_run.so (the Python package);
 * one call at a time (the options are parsed with getopt). */
INSTESS_API int scene_render_args(int argc, const char *const argv[], is_image_format fmt, is_image *img,
                                  char *notes, size_t notes_len, char *err, size_t errlen);

/* ------------- the command line (cli/run/options.c): one table for getopt, --help, the man page ------------- */

/* One render option: `--name METAVAR` (or a flag when metavar is NULL), its help line, its default as shown,
 * the function that applies a value to scene_opts, and for options that take one of a set of names, the names. */
typedef struct scene_option {
    const char *name;        /* the long name, without "--" */
    int short_name;          /* 'o', 'q', or 0 */
    const char *metavar;     /* the value's name in --help, or NULL for a flag */
    const char *help;        /* what it does, one line */
    const char *deflt;       /* the default as --help shows it, or NULL */
    /* Apply the value (NULL for a flag) to o: NULL, or the usage error. */
    const char *(*apply)(scene_opts *o, const char *arg);
    /* The names the option takes joined by sep into buf (buf), or NULL for options without a set of names. */
    const char *(*choices)(const char *sep, char *buf, size_t len);
    /* For an option that changes pixels: o's value written as the option takes it into buf (buf); the image's
     * embedded description (scene_describe) is made of these, so two renders with the same description have
     * the same pixels.  NULL for the options that do not change pixels (threads, limits, file names, quiet); a
     * printer returns NULL for a setting it leaves out of the description (--displace without a map). */
    const char *(*value)(const scene_opts *o, char *buf, size_t len);
} scene_option;
extern const scene_option scene_options[];
extern const size_t scene_option_count;

/* The option called name (without "--"), or NULL. */
const scene_option *scene_find_option(const char *name);
/* Apply arg to o by opt: NULL, or the usage error (an unknown name lists the valid ones, built in buf). */
const char *scene_apply_option(scene_opts *o, const scene_option *opt, const char *arg, char *buf, size_t len);
/* Every option's help lines into f (the table's order, then --help and --version). */
void scene_print_options(FILE *f);
/* The same without the options named in skip (NULL-terminated names without "--"; `instess view` has no -o). */
void scene_print_options_except(FILE *f, const char *const *skip);

typedef enum { SCENE_ARGS_RUN, SCENE_ARGS_HELP, SCENE_ARGS_VERSION } scene_args_result;
/* The render options of argv[1..argc-1] applied to o (which holds the defaults), with at most one positional
 * argument, the mesh.  0 with *res saying whether to render or that --help / --version was asked; -1 with the
 * usage error in err. */
int scene_parse_args(int argc, char **argv, scene_opts *o, scene_args_result *res, char *err, size_t errlen);

/* ---------------------------------------- adaptive level of detail (tess/tess.h has the rules) ------------- */
/* The parameters of o's scene for mesh m (camera as scene_draw's; ref_depth the bounding sphere's nearest). */
tess_lod_params scene_lod_params_of(const scene_opts *o, const is_mesh *m);
/* The largest level a render of o may use (max_level, or --level rounded). */
int scene_lod_max_level(const scene_opts *o);
/* The names --lod takes, in tess_lod_mode's order; parse one. */
extern const char *const scene_lod_names[];
bool scene_parse_lod(const char *s, tess_lod_mode *out);

/* ------------- the progress line of a long run (cli/run/progress.c) ------------- */

/* After this many milliseconds of work a terminal gets a progress line. */
#define SCENE_PROGRESS_DELAY_MS 1000
/* One run's progress line: label (the mesh) and phase (a string constant) are shown with the elapsed time. */
typedef struct scene_progress {
    const char *label, *phase;
    double t0;                  /* start, seconds on CLOCK_MONOTONIC */
    bool active, stop, drawn;   /* the thread runs; asked to stop; a line is on the screen */
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
} scene_progress;
/* Start p's clock, and its drawing thread when stderr is a terminal and not quiet. */
void scene_progress_start(scene_progress *p, const char *label, bool quiet);
/* The phase shown from now on ("reading the mesh", "rendering", "writing"). */
void scene_progress_phase(scene_progress *p, const char *phase);
/* Print text on stderr while p may be drawing: the line is erased first (and redrawn at the next tick). */
void scene_progress_print(scene_progress *p, const char *text);
/* Stop the thread and erase the line (before anything else is printed on stderr). */
void scene_progress_stop(scene_progress *p);

/* Subcommands: `instess figures` (cli/figures/figures.c), `instess smoothness` (cli/run/smoothness.c), `instess compare`
 * (cli/run/compare.c) and `instess view` (cli/view/view_state.c, which loads the SDL2 window of cli/view/view.c as the module
 * libinstess_view.so).  argv[0] is the subcommand's name; each returns the exit code. */
int scene_cmd_figures(int argc, char **argv);
int scene_cmd_smoothness(int argc, char **argv);
int scene_cmd_compare(int argc, char **argv);
int scene_cmd_view(int argc, char **argv);
/* `instess inspect` (cli/run/inspect.c): one pixel's history through the device's draws (core/inspect.h). */
int scene_cmd_inspect(int argc, char **argv);
/* The pieces of `instess inspect` for other front ends (the page of make web): scene_inspect_pixel renders o's
 * scene of mesh m (as scene_fit_mesh gives it; displacement map read) with one sample per pixel, recording pixel
 * (x, y) into rec (is_inspect_free it), the target's final colour and depth into *color, *depth, and the vertex
 * shader's constants after the draw into *consts (when not NULL): 0, or -1 with a message; scene_inspect_print
 * prints the record as text or JSON into f. */
int scene_inspect_pixel(const scene_opts *o, const is_mesh *m, int x, int y, is_inspect *rec, uint32_t *color,
                        float *depth, is_vs_constants *consts, char *err, size_t errlen);
void scene_inspect_print(FILE *f, const scene_opts *o, const is_mesh *m, const is_inspect *rec, uint32_t color,
                         float depth, bool json);
/* s as a JSON string (quoted; invalid UTF-8 as U+FFFD, control characters escaped) into f. */
void scene_json_string(FILE *f, const char *s);

/* An option of a subcommand, for its usage text and the man page: `--name METAVAR`, what it does. */
typedef struct scene_subopt {
    const char *name, *metavar, *help;
} scene_subopt;
/* compare's options, ended by a NULL name (its getopt table and usage are made from them). */
extern const scene_subopt scene_compare_options[];

/* One subcommand: its name, entry point, synopsis, what it does (a sentence or two), its options (NULL-name
 * terminated, or NULL when the synopsis says all) and its exit codes (NULL: those of a render). */
typedef struct scene_subcommand {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *synopsis, *summary;
    const scene_subopt *options;
    const char *exit_codes;
} scene_subcommand;

/* The manual page instess.1 (roff) into f, from the option table above, the exit codes of a render (a
 * sentence) and the subcommands subs[0..n-1]: `instess --man`, which the Makefile runs to write the installed
 * page. */
void scene_print_man(FILE *f, const char *render_codes, const scene_subcommand *subs, size_t n);

#endif
