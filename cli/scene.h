/* cli/scene.h -- one rendered scene: a mesh, a patch, a grid, a path, a camera; the programs' shared layer
 * (the instess command, figures, bench and the golden tests all render through it).
 *
 * Conventions: the object is centred on its bounding box and scaled by 1 / bounding radius, then turned so that
 * the --up axis points up (+y), rotated by yaw (about y) and pitch (about x) -- the world matrix -- and seen by a
 * left-handed camera at (0, 0, -distance) looking at the origin with a 45 degree vertical field of view (with
 * --fit box the distance is the one at which the rotated bounding box fills the image).  The listing's light direction (0, 0, -1) is in
 * world space, so the lit side faces the camera (a headlight).  Errors: functions return 0 or -1 with a message
 * in err naming the input and what is wrong. */
#ifndef INSTESS_SCENE_H
#define INSTESS_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <pthread.h>
#include <stdio.h>

#include "../core/core.h"
#include "../meshes/meshes.h"
#include "../vs/vs.h"

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
 * on the sphere at levels 128 and 256).  The instanced and N-patch-mode paths shade in bounded chunks. */
#define SCENE_DEFAULT_MAX_MEMORY_MIB 4096
#define SCENE_CPU_BYTES_PER_VERTEX 400ull

typedef enum { SCENE_FILL_SOLID, SCENE_FILL_WIRE, SCENE_FILL_SOLID_WIRE, SCENE_FILL_POINT } scene_fill;
typedef enum { SCENE_PATH_INSTANCED, SCENE_PATH_NPATCH_MODE, SCENE_PATH_CPU } scene_path;
/* The AOV channels of an EXR (--aov; README.md lists them with their background values): the patch's
 * unit normal N.X,N.Y,N.Z (0 on the background), barycentrics bary.* (0), the triangle's index `instance`
 * (SCENE_INSTANCE_BACKGROUND on the background: no triangle has it), Gregory coordinates gregory.* (0), and the
 * view-space depth `depth` (the distance from the camera's plane along the view direction, in the mesh's
 * units; +infinity on the background).  One sample per pixel. */
enum { SCENE_AOV_NORMAL = 1, SCENE_AOV_BARY = 2, SCENE_AOV_INSTANCE = 4, SCENE_AOV_GREGORY = 8, SCENE_AOV_DEPTH = 16 };
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
    float diffuse[4];           /* g_vDiffuse */
    float wire_color[4];        /* g_vDiffuse of the wireframe overlay */
    uint32_t background;        /* D3DCOLOR (ARGB) */
    const char *output, *export_obj;
    uint32_t cull;              /* D3DRS_CULLMODE: IS_CULL_NONE, IS_CULL_CW or IS_CULL_CCW (D3D9's default) */
    bool quiet;
    int import_timeout_s;       /* the import child's time limit in seconds (0: meshes.h's default, 60) */
    unsigned max_memory_mib;    /* the memory budget (SCENE_DEFAULT_MAX_MEMORY_MIB) */
    unsigned max_file_mib;      /* a mesh file with its side files (0: meshes.h's default, 256 MiB) */
    unsigned max_import_memory_mib; /* the import child's memory (0: meshes.h's rule by the files' size) */
} scene_opts;

/* Bytes a render of mesh_triangles triangles with grid_points points per triangle takes at most, by the
 * estimate stated at SCENE_DEFAULT_MAX_MEMORY_MIB. */
unsigned long long scene_memory_estimate(const scene_opts *o, size_t mesh_triangles, size_t grid_points);

/* The device resources of one scene draw (released by scene_resources_free). */
typedef struct scene_resources {
    is_vertex_buffer *vb0, *vb1, *vb2;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
    unsigned n_vertices, n_prims, n_instances;   /* the draw's NumVertices, PrimitiveCount, instances */
} scene_resources;
void scene_resources_free(scene_resources *r);
/* An index buffer of n indices copied from idx: 16-bit when max_index < 65536, else 32-bit; IS_OK or an error. */
is_result scene_index_buffer(is_device *dev, const uint32_t *idx, size_t n, size_t max_index, is_index_buffer **out);
/* (cli/instancing.c) Tessellation through instancing on dev: the grid g in stream 0 (INDEXEDDATA | n_triangles; 16-bit indices
 * when they fit), one is_patch_instance per triangle of m in stream 1 (INSTANCEDATA | 1), Listing 1.1.2's
 * declaration; created in r and bound.  The shader and constants are the caller's.  IS_OK or an error. */
is_result scene_bind_instanced(is_device *dev, const is_mesh *m, const core_grid *g, scene_resources *r);

/* The canonical description of a render of mesh m, stored in its image (ImageDescription): the mesh's name,
 * size and hash, and every option that changes pixels -- not the thread count, the output's name or the time,
 * so that two runs of one render write the same bytes. */
void scene_describe(const scene_opts *o, const is_mesh *m, char *buf, size_t len);

/* What a render did (for statistics and the benchmark). */
typedef struct scene_stats {
    size_t mesh_triangles, grid_points, grid_triangles;
    uint64_t vertices_shaded, triangles_drawn;
    rs_stats raster;
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
bool scene_parse_msaa(const char *s, int *out);
bool scene_parse_int(const char *s, int lo, int hi, int *out);
bool scene_parse_float(const char *s, float lo, float hi, float *out);
bool scene_parse_aovs(const char *s, unsigned *out);

/* Draw mesh m with grid g on dev as o says (path, fill, camera, constants c0..c9), with o's shader or, if
 * shader is not NULL, that one (tests wrap the patch shaders).  The device's other states are left as the
 * caller set them, apart from FILLMODE, DEPTHBIAS, SLOPESCALEDEPTHBIAS and the N-patch states.  0 or -1
 * (dev_last_error tells why). */
int scene_draw(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g,
               const is_vertex_shader *shader);
/* Render a loaded mesh into img (allocated here: R, G, B, A, Z, then the AOV channels asked for).  R, G, B are
 * the display (sRGB) values of the PNG and A = 1, unless o->output names an .exr: then A is the pixel's
 * coverage (the fraction of its samples the mesh covers) and R, G, B the linear colour premultiplied by it, the
 * background transparent black (OpenEXR's associated alpha).  Z is D3D9's depth z/w in [MinZ, MaxZ] = [0, 1] of
 * the nearest sample (1 on the background). */
int scene_render_mesh(const scene_opts *o, const is_mesh *mesh, is_image *img, scene_stats *st, char *err,
                      size_t errlen);
/* The resolved colour of rt and the nearest sample's depth of each pixel into img's channels 0..4 (R, G, B, A,
 * Z; img has rt's size and at least 5 channels).  0, or -1 when out of memory. */
int scene_copy_color_depth(const rs_target *rt, is_image *img, char *err, size_t errlen);
/* The input registers the device fetches for grid point b of instance inst (Listing 1.1.2's declaration, as
 * mesh_patch_declaration lays it out): for evaluating a patch shader outside a draw (OBJ export, tests). */
void scene_input_from_instance(const is_patch_instance *inst, float3 b, is_vs_input *in);
/* Load o->mesh, render, write o->output atomically (and o->export_obj); print statistics unless quiet. */
int scene_render_to_file(const scene_opts *o, char *err, size_t errlen);

/* ------------- the command line (cli/options.c): one table for getopt, --help, the man page ------------- */

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
} scene_option;
extern const scene_option scene_options[];
extern const size_t scene_option_count;

/* The option called name (without "--"), or NULL. */
const scene_option *scene_find_option(const char *name);
/* Apply arg to o by opt: NULL, or the usage error (an unknown name lists the valid ones, built in buf). */
const char *scene_apply_option(scene_opts *o, const scene_option *opt, const char *arg, char *buf, size_t len);
/* Every option's help lines into f (the table's order, then --help and --version). */
void scene_print_options(FILE *f);

typedef enum { SCENE_ARGS_RUN, SCENE_ARGS_HELP, SCENE_ARGS_VERSION } scene_args_result;
/* The render options of argv[1..argc-1] applied to o (which holds the defaults), with at most one positional
 * argument, the mesh.  0 with *res saying whether to render or that --help / --version was asked; -1 with the
 * usage error in err. */
int scene_parse_args(int argc, char **argv, scene_opts *o, scene_args_result *res, char *err, size_t errlen);

/* ------------- the progress line of a long run (cli/progress.c) ------------- */

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

/* Subcommands: `instess figures` (cli/figures.c) and `instess smoothness` (cli/smoothness.c). */
int scene_cmd_figures(int argc, char **argv);
int scene_cmd_smoothness(int argc, char **argv);

#endif
