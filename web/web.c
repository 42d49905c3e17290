/* web/web.c -- the front end of the tutorial in the browser (make web): what the page's JavaScript calls.
 *
 * The page renders through the program's own scene layer (cli/run/scene.c, lighting.c and options.c, compiled
 * into the page without the rest of cli/): a frame is given as the command line of `instess` ("cube --patch
 * npatch --level 4 --size 512x512"), parsed by the option table of the program (scene_parse_args), checked as
 * the program checks it (scene_check_opts, the level clamp of a primitive-generator grid, scene_check_limits)
 * and drawn by scene_render_on on a new device, then resolved (rs_target_resolve) into RGBA8: the bytes of the
 * PNG that `instess ARGS -o FILE.png` writes, which tests/web_test.mjs checks in a browser.  The split view is
 * two such frames, side by side (the left half width / 2 wide, as `instess view`'s split screen).
 *
 * Conventions: a context (web_create) holds everything; nothing is global.  Calls return 0, or -1 with the
 * message in web_message (the program's message for the same input); notices and warnings of the last call
 * (a clamped level, a dropped OBJ's warnings) are in web_notes.  Strings are UTF-8, NUL-terminated, in the
 * module's memory (web_alloc / web_free for the page's).  One thread (web/compat/omp.h says why). */
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "../cli/run/scene.h"
#include "obj.h"

#define WEB_EXPORT(name) __attribute__((export_name(#name)))
#define WEB_MAX_ARGS 96

/* The mesh of the frames: loaded once per name (and --recompute-normals), kept while they use it. */
typedef struct web_mesh {
    char spec[256];
    bool recompute, loaded;
    is_mesh mesh, fit;          /* as loaded; scene_fit_mesh's copy when it made one */
    const is_mesh *draw;        /* the one drawn: &mesh or &fit */
} web_mesh;

/* One part of the canvas (the whole, or a half of the split view): its last frame and statistics. */
typedef struct web_part {
    uint32_t *frame;            /* width x height RGBA8 (R first in memory) */
    size_t cap;
    int width, height;
    char stats[2048];
} web_part;

typedef struct web_ctx {
    web_mesh mesh;
    char *obj_name, *obj_data;  /* the OBJ dropped on the page (its bytes are kept: --recompute-normals reads it again) */
    size_t obj_len;
    web_part part[2];
    char message[1024];
    char notes[2048];
    char tables[8192];
    char *inspected;            /* web_inspect's last text (open_memstream's buffer) */
    size_t inspected_len;
} web_ctx;

/* printf into w->message; -1. */
static int fail(web_ctx *w, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(web_ctx *w, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->message, sizeof w->message, fmt, ap);
    va_end(ap);
    return -1;
}

/* Append a line to w->notes (mesh warnings: the callback of is_mesh_options). */
static void note(void *user, const char *msg)
{
    web_ctx *w = user;
    size_t n = strlen(w->notes);
    snprintf(w->notes + n, sizeof w->notes - n, "%s%s", n ? "\n" : "", msg);
}

WEB_EXPORT(web_create) web_ctx *web_create(void) { return calloc(1, sizeof(web_ctx)); }
WEB_EXPORT(web_alloc) void *web_alloc(size_t n) { return malloc(n ? n : 1); }
WEB_EXPORT(web_free) void web_free(void *p) { free(p); }
WEB_EXPORT(web_message) const char *web_message(const web_ctx *w) { return w->message; }
WEB_EXPORT(web_notes) const char *web_notes(const web_ctx *w) { return w->notes; }

/* Forget the mesh (and its fitted copy). */
static void mesh_drop(web_mesh *m)
{
    mesh_free(&m->mesh);
    mesh_free(&m->fit);
    *m = (web_mesh){0};
}

/* Is spec the dropped OBJ's name? */
static bool is_dropped(const web_ctx *w, const char *spec) { return w->obj_name && !strcmp(spec, w->obj_name); }

/* Load mesh spec (a built-in, or the dropped OBJ) as the program does for --recompute-normals `recompute`,
 * unless it is the one loaded; 0 or -1. */
static int mesh_load(web_ctx *w, const char *spec, bool recompute)
{
    web_mesh *m = &w->mesh;
    if (m->loaded && !strcmp(m->spec, spec) && m->recompute == recompute) return 0;
    mesh_drop(m);
    is_mesh_options mo = {.recompute_normals = recompute, .warn = note, .warn_user = w};
    bool builtin = false;
    for (const char *const *n = mesh_builtin_names(); *n; n++) builtin |= !strcmp(*n, spec);
    int rc;
    if (is_dropped(w, spec)) rc = web_obj_read(spec, w->obj_data, w->obj_len, &mo, &m->mesh, w->message, sizeof w->message);
    else if (builtin) rc = mesh_builtin_ex(spec, &mo, &m->mesh, w->message, sizeof w->message);
    else {
        char names[256] = "";
        for (const char *const *n = mesh_builtin_names(); *n; n++)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", *names ? ", " : "", *n);
        return fail(w, "%.200s: neither a built-in mesh (%s) nor the OBJ file dropped on the page", spec, names);
    }
    if (rc != 0) return mesh_drop(m), -1;
    snprintf(m->spec, sizeof m->spec, "%s", spec);
    m->recompute = recompute, m->loaded = true;
    m->draw = scene_fit_mesh(&m->mesh, &m->fit);
    return 0;
}

WEB_EXPORT(web_drop_obj) int web_drop_obj(web_ctx *w, const char *name, const char *data, size_t len)
{
    w->message[0] = w->notes[0] = 0;
    is_mesh test;
    is_mesh_options mo = {.warn = note, .warn_user = w};
    if (web_obj_read(name, data, len, &mo, &test, w->message, sizeof w->message) != 0) return -1;
    mesh_free(&test);
    char *n = strdup(name), *d = malloc(len ? len : 1);
    if (!n || !d) return free(n), free(d), fail(w, "%s: out of memory", name);
    memcpy(d, data, len);
    if (w->mesh.loaded && is_dropped(w, w->mesh.spec)) mesh_drop(&w->mesh);   /* a new file of the same name */
    free(w->obj_name), free(w->obj_data);
    w->obj_name = n, w->obj_data = d, w->obj_len = len;
    return 0;
}

/* args split at spaces (a token may be quoted with '...', as a shell does) into argv[1..], argv[0] "instess";
 * the count, or -1 when there are too many or a quote is not closed.  buf is modified. */
static int split_args(char *buf, char **argv, int max)
{
    int n = 0;
    argv[n++] = "instess";
    char *p = buf;
    for (;;) {
        while (*p == ' ') p++;
        if (!*p) return n;
        if (n == max) return -1;
        char *out = p;
        argv[n++] = out;
        while (*p && *p != ' ') {
            if (*p == '\'') {
                char *q = strchr(p + 1, '\'');
                if (!q) return -1;
                memmove(out, p + 1, (size_t)(q - p - 1));
                out += q - p - 1, p = q + 1;
            } else {
                *out++ = *p++;
            }
        }
        if (*p) p++;
        *out = 0;
    }
}

/* The options of args into *o, checked as the program checks a render; 0 or -1. */
static int parse_render(web_ctx *w, char *args, char **argv, scene_opts *o)
{
    int argc = split_args(args, argv, WEB_MAX_ARGS);
    if (argc < 0) return fail(w, "the command line has more than %d words or an unclosed quote", WEB_MAX_ARGS - 1);
    scene_opts_default(o);
    scene_args_result res;
    if (scene_parse_args(argc, argv, o, &res, w->message, sizeof w->message) != 0) return -1;
    if (res != SCENE_ARGS_RUN) return fail(w, "--help and --version are the program's: the page lists its controls");
    if (o->output || o->export_obj || o->aovs || o->stats_json)
        return fail(w, "-o, --export-obj, --aov and --stats write files: the page draws into its canvas");
    const char *msg = scene_check_opts(o);
    if (msg) return fail(w, "%s", msg);
    float used = o->grid == CORE_GRID_REGULAR ? o->level : core_grid_pg_clamp(o->grid, o->level);
    if (used != o->level) {   /* the program's warn_level_clamp */
        char line[200];
        snprintf(line, sizeof line, "--level %g is outside the range of --grid %s; rendering level %g",
                 (double)o->level, scene_grid_name(o->grid), (double)used);
        note(w, line);
        o->level = used;
    }
    return 0;
}

/* The statistics of a frame as JSON into p->stats. */
static void write_stats(web_part *p, const scene_opts *o, const is_mesh *m, const scene_stats *st, double ms_render,
                        double ms_resolve)
{
    int n = snprintf(p->stats, sizeof p->stats,
                     "{\"mesh_triangles\":%zu,\"grid_points\":%zu,\"grid_triangles\":%zu,\"vertices_shaded\":%llu,"
                     "\"triangles_drawn\":%llu,\"samples\":%d,\"setup_ms\":%.3f,\"tile_ms\":%.3f,\"render_ms\":%.3f,"
                     "\"resolve_ms\":%.3f,\"vertices\":%zu,\"welded_vertices\":%zu,\"boundary_edges\":%zu",
                     m->n_triangles, st->grid_points, st->grid_triangles, (unsigned long long)st->vertices_shaded,
                     (unsigned long long)st->triangles_drawn, o->msaa, st->raster.setup_ms, st->raster.tile_ms,
                     ms_render, ms_resolve, m->stats.vertices, m->stats.welded_vertices, m->stats.boundary_edges);
    if (o->lod != TESS_LOD_UNIFORM && n > 0 && (size_t)n < sizeof p->stats) {
        n += snprintf(p->stats + n, sizeof p->stats - (size_t)n, ",\"buckets\":%zu,\"patterns\":%zu,"
                      "\"tessellated_triangles\":%zu,\"edges_per_level\":[", st->n_buckets, st->n_patterns,
                      st->tessellated_triangles);
        for (int l = 1; l <= CORE_LOD_MAX_LEVEL && n > 0 && (size_t)n < sizeof p->stats; l++)
            n += snprintf(p->stats + n, sizeof p->stats - (size_t)n, "%s%llu", l > 1 ? "," : "",
                          (unsigned long long)st->level_hist[l]);
        if (n > 0 && (size_t)n < sizeof p->stats) n += snprintf(p->stats + n, sizeof p->stats - (size_t)n, "]");
    }
    if (n > 0 && (size_t)n < sizeof p->stats) snprintf(p->stats + n, sizeof p->stats - (size_t)n, "}");
}

/* Milliseconds on the monotonic clock. */
static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

/* Draw o's scene into part k's frame (as scene_render_view and the program's PNG: a new device of o's size, its
 * samples, cleared and drawn, resolved); 0 or -1. */
static int draw_part(web_ctx *w, int k, const scene_opts *o)
{
    web_part *p = &w->part[k];
    const is_mesh *m = w->mesh.draw;
    const bool adaptive = o->lod != TESS_LOD_UNIFORM;   /* as the program: its grid is only checked */
    core_grid g;
    if (core_grid_make(adaptive ? CORE_GRID_REGULAR : o->grid, adaptive ? (float)scene_lod_max_level(o) : o->level,
                       &g) != 0)
        return fail(w, "level %g: cannot build the grid", (double)o->level);
    if (scene_check_limits(o, m, &g, w->message, sizeof w->message) != 0) return core_grid_free(&g), -1;
    size_t px = (size_t)o->width * (size_t)o->height;
    if (px > p->cap) {
        uint32_t *f = realloc(p->frame, px * sizeof *f);
        if (!f) return core_grid_free(&g), fail(w, "out of memory for a %dx%d frame", o->width, o->height);
        p->frame = f, p->cap = px;
    }
    scene_stats st = {.mesh_triangles = m->n_triangles, .grid_points = g.n_points, .grid_triangles = g.n_triangles};
    double t0 = now_ms();
    is_device *dev = scene_create_device(o, o->msaa, 0, w->message, sizeof w->message);
    if (dev) dev_set_timing(dev, true);
    int rc = dev ? scene_render_on(dev, o, m, &g, &st, w->message, sizeof w->message) : -1;
    double t1 = now_ms();
    if (rc == 0) {
        rs_target_resolve(dev_present(dev), p->frame);
        p->width = o->width, p->height = o->height;
        write_stats(p, o, m, &st, t1 - t0, now_ms() - t1);
    }
    dev_destroy(dev);
    core_grid_free(&g);
    return rc;
}

WEB_EXPORT(web_render) int web_render(web_ctx *w, int part, const char *args)
{
    w->message[0] = w->notes[0] = 0;
    if (part < 0 || part > 1) return fail(w, "part %d: the canvas has parts 0 and 1", part);
    char *buf = strdup(args ? args : ""), *argv[WEB_MAX_ARGS];
    if (!buf) return fail(w, "out of memory");
    scene_opts o;
    int rc = parse_render(w, buf, argv, &o);
    if (rc == 0) rc = mesh_load(w, o.mesh, o.recompute_normals);
    if (rc == 0) rc = draw_part(w, part, &o);
    free(buf);
    return rc;
}

/* The pipeline inspector (README, "The pipeline inspector"): the history of pixel (x, y) of args's render (one
 * sample per pixel), as `instess inspect ARGS --pixel X,Y` prints it (JSON when json is not 0), or NULL with the
 * message. */
WEB_EXPORT(web_inspect) const char *web_inspect(web_ctx *w, const char *args, int x, int y, int json)
{
    w->message[0] = w->notes[0] = 0;
    free(w->inspected);
    w->inspected = NULL;
    char *buf = strdup(args ? args : ""), *argv[WEB_MAX_ARGS];
    if (!buf) return fail(w, "out of memory"), NULL;
    scene_opts o;
    int rc = parse_render(w, buf, argv, &o);
    if (rc == 0) rc = mesh_load(w, o.mesh, o.recompute_normals);
    if (rc == 0 && (x < 0 || y < 0 || x >= o.width || y >= o.height))
        rc = fail(w, "pixel (%d, %d) is outside the %dx%d image", x, y, o.width, o.height);
    is_inspect rec = {0};
    uint32_t color = 0;
    float depth = 0;
    if (rc == 0) rc = scene_inspect_pixel(&o, w->mesh.draw, x, y, &rec, &color, &depth, NULL, w->message, sizeof w->message);
    FILE *f = rc == 0 ? open_memstream(&w->inspected, &w->inspected_len) : NULL;
    if (rc == 0 && !f) rc = fail(w, "out of memory");
    if (f) {
        scene_inspect_print(f, &o, w->mesh.draw, &rec, color, depth, json != 0);
        if (fclose(f) != 0) rc = fail(w, "out of memory");
    }
    is_inspect_free(&rec);
    free(buf);
    return rc == 0 ? w->inspected : NULL;
}

WEB_EXPORT(web_frame) const uint32_t *web_frame(const web_ctx *w, int part) { return w->part[part & 1].frame; }
WEB_EXPORT(web_frame_width) int web_frame_width(const web_ctx *w, int part) { return w->part[part & 1].width; }
WEB_EXPORT(web_frame_height) int web_frame_height(const web_ctx *w, int part) { return w->part[part & 1].height; }
WEB_EXPORT(web_stats) const char *web_stats(const web_ctx *w, int part) { return w->part[part & 1].stats; }

/* names as a JSON array appended at buf + *n. */
static void json_names(char *buf, size_t len, size_t *n, const char *key, const char *const *names, int count)
{
    *n += (size_t)snprintf(buf + *n, *n < len ? len - *n : 0, "%s\"%s\":[", *n > 1 ? "," : "", key);
    for (int k = 0; (count < 0 ? names[k] != NULL : k < count) && *n < len; k++)
        *n += (size_t)snprintf(buf + *n, len - *n, "%s\"%s\"", k ? "," : "", names[k]);
    if (*n < len) *n += (size_t)snprintf(buf + *n, len - *n, "]");
}

/* s as a JSON string (quotes and backslashes escaped) appended at buf + *n. */
static void json_string(char *buf, size_t len, size_t *n, const char *s)
{
    if (*n < len) buf[(*n)++] = '"';
    for (; *s && *n + 2 < len; s++) {
        if (*s == '"' || *s == '\\') buf[(*n)++] = '\\';
        buf[(*n)++] = *s;
    }
    if (*n + 1 < len) buf[(*n)++] = '"', buf[*n] = 0;
}

WEB_EXPORT(web_tables) const char *web_tables(web_ctx *w)
{
    /* The names the program's options take, from the program's tables, and the help line of each option the page
     * offers: the page builds its controls from them. */
    const char *patches[VS_PATCH_COUNT], *normals[3];
    for (int k = 0; k < VS_PATCH_COUNT; k++) patches[k] = vs_patch_name((vs_patch)k);
    for (int k = 0; k < 3; k++) normals[k] = vs_normals_name((vs_normals)k);
    char *b = w->tables;
    size_t len = sizeof w->tables, n = (size_t)snprintf(b, len, "{");
    json_names(b, len, &n, "mesh", mesh_builtin_names(), -1);
    json_names(b, len, &n, "patch", patches, VS_PATCH_COUNT);
    json_names(b, len, &n, "normals", normals, 3);
    json_names(b, len, &n, "grid", scene_grid_names, -1);
    json_names(b, len, &n, "path", scene_path_names, -1);
    json_names(b, len, &n, "fill", scene_fill_names, -1);
    json_names(b, len, &n, "lod", scene_lod_names, -1);
    json_names(b, len, &n, "cull", scene_cull_names, -1);
    /* the program's defaults (scene_opts_default), as the options write them */
    scene_opts d;
    scene_opts_default(&d);
    char light[96];
    if (n < len)
        n += (size_t)snprintf(b + n, len - n, ",\"defaults\":{\"mesh\":\"%s\",\"patch\":\"%s\",\"normals\":\"%s\","
                              "\"level\":\"%g\",\"grid\":\"%s\",\"path\":\"%s\",\"fill\":\"%s\",\"light\":\"%s\","
                              "\"msaa\":\"%d\",\"yaw\":\"%g\",\"pitch\":\"%g\",\"distance\":\"%g\",\"fov\":\"%g\","
                              "\"size\":\"%dx%d\",\"lod\":\"%s\",\"lod-target\":\"%g\",\"lod-deviation\":\"%g\",\"cull\":\"%s\",\"up\":\"%s\","
                              "\"fit\":\"%s\",\"instances\":\"%u\"}", d.mesh, vs_patch_name(d.patch), vs_normals_name(d.normals),
                              (double)d.level, scene_grid_name(d.grid), scene_path_names[d.path],
                              scene_fill_names[d.fill], scene_light_name(&d, light, sizeof light), d.msaa, (double)d.yaw,
                              (double)d.pitch, (double)d.distance, (double)d.fov, d.width, d.height,
                              scene_lod_names[d.lod], (double)d.lod_target, (double)d.lod_deviation,
                              scene_cull_names[d.cull - IS_CULL_NONE],
                              scene_up_names[d.up], scene_fit_names[d.fit], d.instances);
    json_names(b, len, &n, "up", scene_up_names, -1);
    json_names(b, len, &n, "fit", scene_fit_names, -1);
    if (n < len) n += (size_t)snprintf(b + n, len - n, ",\"version\":\"%s\",\"threads\":%d,\"help\":{", INSTESS_VERSION,
                                       omp_get_num_procs());
    for (size_t k = 0; k < scene_option_count && n < len; k++) {
        if (n < len) n += (size_t)snprintf(b + n, len - n, "%s\"%s\":", k ? "," : "", scene_options[k].name);
        json_string(b, len, &n, scene_options[k].help);
    }
    if (n + 2 < len) snprintf(b + n, len - n, "}}");
    return w->tables;
}
