/* cli/view/view_state.c -- `instess view` without SDL: its options (the render options of scene_parse_args, minus
 * the outputs, plus the scripting options), the key table and its actions, frames rendered through the scene
 * layer, the HUD's text, screenshots and captures.  The window is cli/view/view.c, loaded as a module (see
 * cli/view/view_internal.h). */
#define _GNU_SOURCE  /* RTLD_* */
#include "view_internal.h"

#include "../../core/hlsl.h"
#include <dlfcn.h>
#include <limits.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

/* ------------------------------------ state changes ------------------------------------ */

/* NULL if o (and, when split, o with the right half's patch) is a render the CLI accepts, else why not. */
static const char *state_error(const view_state *v, const scene_opts *o)
{
    const char *msg = scene_check_opts(o);
    if (msg || !v->split) return msg;
    scene_opts r = *o;
    r.patch = v->other;
    return scene_check_opts(&r);
}

/* Whether the render o stays within the limits of a render (vertex count, memory); else the message in err. */
static bool within_limits(const view_state *v, const scene_opts *o, char *err, size_t errlen)
{
    core_grid g;
    if (core_grid_make(o->grid, o->level, &g) != 0) return snprintf(err, errlen, "cannot build the grid"), false;
    int rc = scene_check_limits(o, v->draw, &g, err, errlen);
    core_grid_free(&g);
    return rc == 0;
}

/* Say msg on the HUD at once (the frame shown again with it, without rendering it again) and on stderr (also
 * with -q: it is a refusal or a change of what was asked). */
static void notice(view_state *v, const char *msg)
{
    snprintf(v->status, sizeof v->status, "%.479s", msg);
    v->overlay_dirty = true;
    fprintf(stderr, "instess view: %s\n", msg);
}

/* Add reason to the "; "-separated list in buf[len] unless it is there already (the refusals of a key's
 * candidates: often one reason for all). */
static void add_reason(char *buf, size_t len, const char *reason)
{
    size_t n = strlen(buf);
    if (!reason || strstr(buf, reason) || n + 1 >= len) return;
    snprintf(buf + n, len - n, "%s%s", n ? "; " : "", reason);
}

/* Say that the key changing `what` was refused, with the reasons the CLI gives for its candidates. */
static void refuse(view_state *v, const char *what, const char *reasons)
{
    char msg[480];
    snprintf(msg, sizeof msg, "%.60s refused: %.380s", what, reasons[0] ? reasons : "it has no other value");
    notice(v, msg);
}

/* Take the candidate render o if the CLI would accept it and it is within limits (a new frame follows), else
 * keep the state and say why (what names the change); true if taken. */
static bool commit(view_state *v, const scene_opts *o, const char *what)
{
    char err[400];
    const char *msg = state_error(v, o);
    if (msg) snprintf(err, sizeof err, "%s refused: %s", what, msg);
    else if (!within_limits(v, o, err, sizeof err)) msg = err;
    if (msg) return notice(v, err), false;
    v->o = *o;
    v->status[0] = 0;
    v->dirty = true;
    return true;
}

/* Cycle the field that next() advances through n values until the CLI accepts the render; what names it. */
static void cycle(view_state *v, void (*next)(scene_opts *o), int n, const char *what)
{
    scene_opts o = v->o;
    char reasons[380] = "";   /* why the other values were refused: the CLI's reasons, the student's answer */
    for (int k = 1; k < n; k++) {
        next(&o);
        const char *why = state_error(v, &o);
        if (!why) {
            commit(v, &o, what);
            return;
        }
        add_reason(reasons, sizeof reasons, why);
    }
    refuse(v, what, reasons);
}

/* A primitive-generator grid's level clamped as the CLI clamps it, said as the CLI says it. */
static void clamp_pg_level(view_state *v, scene_opts *o)
{
    if (o->grid == CORE_GRID_REGULAR) return;
    float used = core_grid_pg_clamp(o->grid, o->level);
    if (used == o->level) return;
    char msg[200];
    snprintf(msg, sizeof msg, "level %g is outside the range of grid %s; rendering level %g", (double)o->level,
             scene_grid_name(o->grid), (double)used);
    notice(v, msg);
    o->level = used;
}

/* ------------------------------------ the actions ------------------------------------ */

/* Level up / down by one (within 1..256 and the grid's range). */
static void level_by(view_state *v, float d)
{
    scene_opts o = v->o;
    o.level = fminf(SCENE_MAX_LEVEL, fmaxf(1.0f, o.level + d));
    clamp_pg_level(v, &o);
    if (o.level != v->o.level) commit(v, &o, "level");
}
static void act_level_up(view_state *v) { level_by(v, 1.0f); }
static void act_level_down(view_state *v) { level_by(v, -1.0f); }

static void next_patch(scene_opts *o) { o->patch = (vs_patch)((o->patch + 1) % VS_PATCH_COUNT); }
static void act_patch(view_state *v) { cycle(v, next_patch, VS_PATCH_COUNT, "patch"); }

static void next_normals(scene_opts *o) { o->normals = (vs_normals)((o->normals + 1) % 3); }
static void act_normals(view_state *v) { cycle(v, next_normals, 3, "normals"); }

static void next_lod(scene_opts *o) { o->lod = (tess_lod_mode)((o->lod + 1) % (TESS_LOD_DEVIATION + 1)); }
static void act_lod(view_state *v) { cycle(v, next_lod, TESS_LOD_DEVIATION + 1, "lod"); }

/* The next path; the N-patch mode and the CPU path evaluate linear or quadratic normals only, so real normals
 * become linear there (the CLI's default for those paths), said on the HUD. */
static void next_path(scene_opts *o)
{
    o->path = (scene_path)((o->path + 1) % 3);
    if (o->path != SCENE_PATH_INSTANCED && o->normals == VS_NORMALS_REAL) o->normals = VS_NORMALS_LINEAR;
}
static void act_path(view_state *v)
{
    vs_normals before = v->o.normals;
    cycle(v, next_path, 3, "path");
    if (v->o.normals != before) notice(v, "the N-patch mode and the CPU path shade linear or quadratic normals: "
                                          "normals linear");
}

/* The next grid; the regular grid takes the level rounded, a primitive-generator grid its clamped level. */
static void act_grid(view_state *v)
{
    scene_opts o = v->o;
    char reasons[380] = "";
    for (int k = 1; k < 4; k++) {
        o.grid = (core_grid_kind)((o.grid + 1) % 4);
        scene_opts t = o;
        if (t.grid == CORE_GRID_REGULAR) t.level = fmaxf(1.0f, roundf(t.level));
        else t.level = core_grid_pg_clamp(t.grid, t.level);
        const char *why = state_error(v, &t);
        if (why) {
            add_reason(reasons, sizeof reasons, why);
            continue;
        }
        if (t.level != v->o.level) {
            char msg[160];
            snprintf(msg, sizeof msg, "grid %s renders level %g", scene_grid_name(t.grid), (double)t.level);
            if (commit(v, &t, "grid")) notice(v, msg);
        } else {
            commit(v, &t, "grid");
        }
        return;
    }
    refuse(v, "grid", reasons);
}

/* Fill in the order solid, solid+wire, wire, point. */
static void act_fill(view_state *v)
{
    static const scene_fill next[] = {[SCENE_FILL_SOLID] = SCENE_FILL_SOLID_WIRE,
                                      [SCENE_FILL_SOLID_WIRE] = SCENE_FILL_WIRE,
                                      [SCENE_FILL_WIRE] = SCENE_FILL_POINT, [SCENE_FILL_POINT] = SCENE_FILL_SOLID};
    scene_opts o = v->o;
    o.fill = next[o.fill];
    commit(v, &o, "fill");
}

static void act_msaa(view_state *v)
{
    scene_opts o = v->o;
    o.msaa = o.msaa == 4 ? 1 : 4;
    commit(v, &o, "msaa");
}

/* Light per vertex (the listings) or per pixel (a pixel shader: --shading pixel), where the render allows it. */
static void act_shading(view_state *v)
{
    scene_opts o = v->o;
    o.shading = o.shading == SCENE_SHADING_PIXEL ? SCENE_SHADING_VERTEX : SCENE_SHADING_PIXEL;
    commit(v, &o, "shading");
}

/* --texture's image on or off (the file given on the command line, or the mesh's own). */
static void act_texture(view_state *v)
{
    if (!v->texture_path) {
        notice(v, "texture refused: no --texture FILE was given and the mesh has no texture of its own");
        return;
    }
    scene_opts o = v->o;
    o.texture = o.texture ? NULL : v->texture_path;
    commit(v, &o, "texture");
}

/* Split on: the right half's patch is the first one from v->other on that the state accepts. */
static void act_split(view_state *v)
{
    if (v->split) {
        v->split = false, v->dirty = true;
        return;
    }
    v->split = true;
    char reasons[380] = "";
    for (int k = 0; k < VS_PATCH_COUNT; k++, v->other = (vs_patch)((v->other + 1) % VS_PATCH_COUNT)) {
        const char *why = state_error(v, &v->o);
        if (!why) {
            v->dirty = true;
            return;
        }
        add_reason(reasons, sizeof reasons, why);
    }
    v->split = false;
    refuse(v, "split (a second patch)", reasons);
}

/* The right half's next patch that the state accepts. */
static void act_other(view_state *v)
{
    vs_patch was = v->other;
    char reasons[380] = "";
    for (int k = 1; k < VS_PATCH_COUNT; k++) {
        v->other = (vs_patch)((was + k) % VS_PATCH_COUNT);
        const char *why = state_error(v, &v->o);
        if (!why) {
            v->dirty = v->split;
            return;
        }
        add_reason(reasons, sizeof reasons, why);
    }
    v->other = was;
    if (v->split) refuse(v, "right half's patch", reasons);
}

static void act_show(view_state *v) { v->show = (view_show)((v->show + 1) % VIEW_SHOW_COUNT), v->dirty = true; }
static void act_hud(view_state *v) { v->hud = (view_hud)((v->hud + 1) % VIEW_HUD_COUNT), v->overlay_dirty = true; }
static void act_quit(view_state *v) { v->quit = true; }
static void act_left(view_state *v) { view_orbit(v, -60, 0); }
static void act_right(view_state *v) { view_orbit(v, 60, 0); }
static void act_up(view_state *v) { view_orbit(v, 0, -60); }
static void act_down(view_state *v) { view_orbit(v, 0, 60); }
static void act_closer(view_state *v) { view_zoom(v, 1); }
static void act_farther(view_state *v) { view_zoom(v, -1); }

/* The keys: one table for the actions, the `h` overlay and `instess view --help`. */
const view_key view_keys[] = {
    {"]", "]", "level up", act_level_up},
    {"[", "[", "level down", act_level_down},
    {"P", "p", "next patch (left half when split)", act_patch},
    {"O", "o", "next patch of the right half (split screen)", act_other},
    {"N", "n", "next normals: linear, quadratic, real", act_normals},
    {"G", "g", "next grid: regular, pg-equal, pg-fractional-odd, pg-fractional-even", act_grid},
    {"T", "t", "next path: instanced, npatch-mode, cpu (where the patch allows)", act_path},
    {"L", "l", "next level of detail: uniform, distance, screen, deviation (a level per mesh edge, --lod)", act_lod},
    {"W", "w", "next fill: solid, solid+wire, wire, point", act_fill},
    {"M", "m", "4x multisampling on / off", act_msaa},
    {"V", "v", "light per vertex (the listings) or per pixel (a pixel shader: --shading pixel)", act_shading},
    {"U", "u", "the texture on / off (--texture's, or the mesh's own)", act_texture},
    {"Tab", "Tab", "split screen: two patches side by side on one camera (labelled at the bottom)", act_split},
    {"C", "c", "next view: colour, normals, barycentrics, instance id, Gregory weights, cracks (odd counts red)",
     act_show},
    {"S", "s", "screenshot: instess-view-NNNN.png (the CLI's bytes for the colour view)", view_screenshot},
    {"H", "h", "HUD, HUD with these keys, nothing", act_hud},
    {"I", "i", "inspector: pin the centre pixel (or click one) and show its way through the pipeline; again: unpin",
     act_inspect},
    {"X", "x", "play the draw instance by instance (the grid stamped once per mesh triangle); again: stop",
     act_step},
    {". Period", ".", "playback faster (instances per frame x2)", act_step_faster},
    {", Comma", ",", "playback slower", act_step_slower},
    {"Left Right", "arrows", "orbit (also: drag with the mouse)", NULL},
    {"Up Down", "", "", NULL},
    {"PageUp PageDown PgUp PgDn", "PgUp PgDn", "zoom (also: the wheel)", NULL},
    {"Q Escape Esc", "q / Esc", "quit", act_quit},
};
const size_t view_key_count = sizeof view_keys / sizeof view_keys[0];

/* The actions of the rows that answer to two keys (arrows and page keys): the name says which. */
static void (*pair_action(const char *name))(view_state *)
{
    static const struct { const char *name; void (*fn)(view_state *); } pairs[] = {
        {"Left", act_left}, {"Right", act_right}, {"Up", act_up}, {"Down", act_down},
        {"PageUp", act_closer}, {"PageDown", act_farther}, {"PgUp", act_closer}, {"PgDn", act_farther}};
    for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++)
        if (strcasecmp(name, pairs[k].name) == 0) return pairs[k].fn;
    return NULL;
}

const view_key *view_find_key(const char *name)
{
    for (size_t k = 0; k < view_key_count; k++) {
        char buf[64];
        snprintf(buf, sizeof buf, "%s", view_keys[k].names);
        for (char *save = NULL, *t = strtok_r(buf, " ", &save); t; t = strtok_r(NULL, " ", &save))
            if (strcasecmp(t, name) == 0) return &view_keys[k];
    }
    return NULL;
}

bool view_press(view_state *v, const char *name)
{
    const view_key *k = view_find_key(name);
    if (!k) return false;
    void (*fn)(view_state *) = k->action ? k->action : pair_action(name);
    if (fn) fn(v);
    return true;
}

void view_orbit(view_state *v, int dx, int dy)
{
    if (!dx && !dy) return;
    v->o.yaw = fmodf(v->o.yaw - 0.25f * (float)dx, 360.0f);
    v->o.pitch = fmaxf(-89.0f, fminf(89.0f, v->o.pitch - 0.25f * (float)dy));
    v->dirty = true;
}

void view_zoom(view_state *v, int steps)
{
    float d = v->o.distance * powf(1.1f, (float)-steps);
    d = fmaxf(1.01f, fminf(1000.0f, d));
    if (d != v->o.distance) v->o.distance = d, v->dirty = true;
}

int view_resize(view_state *v, int width, int height, char *err, size_t errlen)
{
    if (width == v->o.width && height == v->o.height) return 0;
    scene_opts o = v->o;
    o.width = width < 1 ? 1 : width, o.height = height < 1 ? 1 : height;
    if ((unsigned long long)o.width * (unsigned long long)o.height > SCENE_MAX_PIXELS || !within_limits(v, &o, err, errlen))
        return snprintf(err, errlen, "window %dx%d: %s", width, height, SCENE_SIZE_MSG), -1;
    uint32_t *f = calloc((size_t)o.width * o.height, sizeof *f);
    if (!f) return snprintf(err, errlen, "out of memory for a %dx%d window", o.width, o.height), -1;
    free(v->frame);
    v->frame = f, v->o = o, v->dirty = true;
    return 0;
}

/* ------------------------------------ frames ------------------------------------ */

/* The crack view's shader: the path's shader, then colour 1/255 so that ONE + ONE blending counts layers.
 * c10.x selects the patch shader (instanced path) or, when negative, the fixed-function one. */
static void vs_count(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    const is_vertex_shader *s = c->c[10].x < 0 ? &vs_shader_fixed : vs_patch_shader((vs_patch)(int)c->c[10].x);
    s->main(c, in, out);
    out->attr[RS_ATTR_COLOR0] = f4(1.0f / 255.0f, 0, 0, 1.0f / 255.0f);
}
static const is_vertex_shader count_shader = {.name = "count", .main = vs_count, .outputs = IS_OUT_COLOR0};

/* The crack view of o on dev (cull none, no depth, ONE + ONE, one sample); 0 or -1 with a message. */
static int render_cracks(is_device *dev, const scene_opts *o, const is_mesh *m, const core_grid *g, char *err,
                         size_t errlen)
{
    dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE);
    dev_set_render_state(dev, IS_RS_ZENABLE, 0);
    dev_set_render_state(dev, IS_RS_ALPHABLENDENABLE, 1);
    dev_set_render_state(dev, IS_RS_SRCBLEND, IS_BLEND_ONE);
    dev_set_render_state(dev, IS_RS_DESTBLEND, IS_BLEND_ONE);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
    float sel[4] = {o->path == SCENE_PATH_INSTANCED ? (float)o->patch : -1.0f, 0, 0, 0};
    dev_set_vertex_shader_constant_f(dev, 10, sel, 1);
    if (scene_draw(dev, o, m, g, &count_shader) == 0) return 0;
    return snprintf(err, errlen, "%s: rendering the crack view failed: %s", m->name, dev_last_error(dev)), -1;
}

/* A channel value in [0, 1] as a byte. */
static uint32_t byte_of(float x)
{
    return (uint32_t)lrintf(255.0f * fmaxf(0.0f, fminf(1.0f, isfinite(x) ? x : 0.0f)));
}
static uint32_t rgba_of(float r, float g, float b) { return byte_of(r) | byte_of(g) << 8 | byte_of(b) << 16 | 0xff000000u; }

/* Pixel p of the AOV view `show` of target rt (the AOV plane, or the crack counts) as RGBA8. */
static uint32_t shown_pixel(view_show show, const rs_target *rt, size_t p)
{
    if (show == VIEW_SHOW_CRACKS) {
        unsigned n = rt->color[p] & 0xffu;
        if (n & 1) return rgba_of(1, 0, 0);
        return rgba_of(0.12f * (float)n, 0.12f * (float)n, 0.12f * (float)n);
    }
    const float *a = &rt->aov[0].data[p * (size_t)rt->aov[0].comps];
    switch (show) {
    case VIEW_SHOW_NORMAL: return a[0] == 0 && a[1] == 0 && a[2] == 0 ? rgba_of(0, 0, 0)
                                                                      : rgba_of(a[0] * 0.5f + 0.5f, a[1] * 0.5f + 0.5f, a[2] * 0.5f + 0.5f);
    case VIEW_SHOW_INSTANCE: {
        if (a[0] <= 0) return rgba_of(0, 0, 0);
        uint32_t h = (uint32_t)a[0] * 2654435761u;   /* instance ids as distinct colours */
        return rgba_of(0.3f + 0.7f * (float)(h >> 24) / 255.0f, 0.3f + 0.7f * (float)((h >> 16) & 0xff) / 255.0f,
                       0.3f + 0.7f * (float)((h >> 8) & 0xff) / 255.0f);
    }
    default: return rgba_of(a[0], a[1], a[2]);   /* barycentrics, Gregory weights */
    }
}

/* rs_target_resolve of rt into out (rt's size) in bands of rows on threads threads (0: all cores): each band is
 * the same target seen from its first row, so the bytes are rs_target_resolve's. */
static void resolve_parallel(const rs_target *rt, uint32_t *out, int threads)
{
    enum { BAND = 32 };
    const int n_bands = (rt->height + BAND - 1) / BAND;
#pragma omp parallel for schedule(dynamic) num_threads(threads > 0 ? threads : omp_get_num_procs())
    for (int b = 0; b < n_bands; b++) {
        rs_target band = *rt;
        band.height = rt->height - b * BAND < BAND ? rt->height - b * BAND : BAND;
        band.color = rt->color + (size_t)b * BAND * rt->width * rt->samples;
        band.depth = rt->depth + (size_t)b * BAND * rt->width * rt->samples;
        band.n_aov = 0;
        rs_target_resolve(&band, out + (size_t)b * BAND * rt->width);
    }
}

/* The device of part `part` for o and v->show: the one kept if it was made for the same, else a new one
 * (timing on); its state reset as a new device's; NULL with a message. */
static is_device *part_device(view_state *v, int part, const scene_opts *o, char *err, size_t errlen)
{
    static const unsigned aov_of[VIEW_SHOW_COUNT] = {[VIEW_SHOW_NORMAL] = SCENE_AOV_NORMAL,
                                                     [VIEW_SHOW_BARY] = SCENE_AOV_BARY,
                                                     [VIEW_SHOW_INSTANCE] = SCENE_AOV_INSTANCE,
                                                     [VIEW_SHOW_GREGORY] = SCENE_AOV_GREGORY};
    int samples = v->show == VIEW_SHOW_COLOR ? o->msaa : 1;
    int key[4] = {o->width, o->height, samples, (int)v->show};
    if (v->dev[part] && memcmp(key, v->dev_key[part], sizeof key) == 0) {
        dev_reset(v->dev[part]);
        return v->dev[part];
    }
    dev_destroy(v->dev[part]);
    v->dev[part] = scene_create_device(o, samples, aov_of[v->show], err, errlen);
    if (v->dev[part]) dev_set_timing(v->dev[part], true), memcpy(v->dev_key[part], key, sizeof key);
    return v->dev[part];
}

/* Render o (o->width wide) into columns x0.. of v->frame with part's device; its counters added to v's. */
static int render_part(view_state *v, int part, const scene_opts *o, int x0, char *err, size_t errlen)
{
    core_grid g;
    if (core_grid_make(o->grid, o->level, &g) != 0)
        return snprintf(err, errlen, "level %g: cannot build the grid", (double)o->level), -1;
    is_device *dev = scene_check_limits(o, v->draw, &g, err, errlen) == 0 ? part_device(v, part, o, err, errlen)
                                                                          : NULL;
    int rc = !dev ? -1
             : v->show == VIEW_SHOW_CRACKS ? render_cracks(dev, o, v->draw, &g, err, errlen)
                                           : scene_render_on(dev, o, v->draw, &g, NULL, err, errlen);
    core_grid_free(&g);
    if (rc != 0) return -1;
    const rs_target *rt = dev_present(dev);   /* colour and AOV planes: what the views show */
    if (v->show == VIEW_SHOW_COLOR && !v->split) {
        resolve_parallel(rt, v->frame, o->threads);
    } else if (v->show == VIEW_SHOW_COLOR) {
        uint32_t *px = malloc((size_t)o->width * o->height * sizeof *px);
        if (!px) return snprintf(err, errlen, "out of memory for a %dx%d frame", o->width, o->height), -1;
        resolve_parallel(rt, px, o->threads);
        for (int y = 0; y < o->height; y++)
            memcpy(&v->frame[(size_t)y * v->o.width + x0], &px[(size_t)y * o->width], (size_t)o->width * sizeof *px);
        free(px);
    } else {
        for (int y = 0; y < o->height; y++)
            for (int x = 0; x < o->width; x++)
                v->frame[(size_t)y * v->o.width + x0 + x] = shown_pixel(v->show, rt, (size_t)y * o->width + x);
    }
    const rs_stats *st = dev_stats(dev);
    v->triangles += st->prims_drawn;
    v->ms_setup += st->setup_ms, v->ms_tile += st->tile_ms;
    return 0;
}

int view_render(view_state *v, char *err, size_t errlen)
{
    double t0 = omp_get_wtime();
    view_step_frame(v);   /* the playback's instance count for this frame */
    v->triangles = 0, v->ms_setup = v->ms_tile = 0;
    int rc;
    if (!v->split) {
        rc = render_part(v, 0, &v->o, 0, err, errlen);
    } else {
        scene_opts l = v->o, r = v->o;
        l.width = v->o.width / 2 > 0 ? v->o.width / 2 : 1;
        r.width = v->o.width - l.width > 0 ? v->o.width - l.width : 1;
        r.patch = v->other;
        rc = render_part(v, 0, &l, 0, err, errlen);
        if (rc == 0 && v->o.width > 1) rc = render_part(v, 1, &r, l.width, err, errlen);
    }
    if (rc == 0) view_inspect_frame(v);   /* the pinned pixel's history and the picked instance over the frame */
    if (rc == 0 && v->stepping) v->dirty = true;   /* the playback goes on: another frame */
    v->ms_render = (omp_get_wtime() - t0) * 1e3;
    if (rc == 0 && v->n_times < (int)(sizeof v->times / sizeof v->times[0])) {
        float *t = v->times[v->n_times++];
        t[0] = (float)v->ms_render, t[1] = (float)v->ms_setup, t[2] = (float)v->ms_tile;
    }
    return rc;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The median of column c of the frame times after the first frame (the warm-up). */
static double median_time(const view_state *v, int c)
{
    float col[512];
    int n = 0;
    for (int k = 1; k < v->n_times; k++) col[n++] = v->times[k][c];
    if (!n) return 0;
    qsort(col, (size_t)n, sizeof col[0], cmp_float);
    return n % 2 ? col[n / 2] : 0.5 * (col[n / 2 - 1] + col[n / 2]);
}

/* The frame times on stderr (unless quiet): the count, the medians after the first frame. */
static void report_times(const view_state *v)
{
    if (v->o.quiet || v->n_times < 2) return;
    fprintf(stderr, "instess view: %d frames; after the first, median render %.2f ms (set-up regions %.2f, tile "
            "passes %.2f), %d thread(s)\n", v->n_times, median_time(v, 0), median_time(v, 1), median_time(v, 2),
            v->o.threads > 0 ? v->o.threads : omp_get_num_procs());
}

/* ------------------------------------ the HUD ------------------------------------ */

static const char *const show_names[VIEW_SHOW_COUNT] = {"colour", "normals", "barycentrics", "instance id",
                                                        "Gregory weights", "cracks (odd counts red)"};

/* The status (a refusal, a notice) as lines[n..] of at most HUD_WRAP characters, broken at spaces (whole: a
 * refusal's reason is the point of it); the new count of lines, at most max. */
static int status_lines(const char *status, char lines[][160], int n, int max)
{
    enum { HUD_WRAP = 96 };
    for (const char *s = status; *s && n < max;) {
        size_t len = strlen(s);
        if (len > HUD_WRAP) {
            len = HUD_WRAP;
            while (len > HUD_WRAP / 2 && s[len] != ' ') len--;
            if (s[len] != ' ') len = HUD_WRAP;
        }
        snprintf(lines[n++], 160, "%s%.*s", s == status ? "" : "  ", (int)len, s);
        s += len;
        while (*s == ' ') s++;
    }
    return n;
}

void view_split_label(const view_state *v, int half, char *buf, size_t len)
{
    snprintf(buf, len, "%s: %s", half ? "right" : "left", vs_patch_name(half ? v->other : v->o.patch));
}

int view_hud_lines(const view_state *v, double ms_frame, char lines[][160], int max)
{
    int n = 0;
    const scene_opts *o = &v->o;
    if (v->hud == VIEW_HUD_OFF || max < 6) return 0;
    char patch[40];
    if (v->split) snprintf(patch, sizeof patch, "%s | %s", vs_patch_name(o->patch), vs_patch_name(v->other));
    else snprintf(patch, sizeof patch, "%s", vs_patch_name(o->patch));
    const char *base = strrchr(v->mesh.name, '/') ? strrchr(v->mesh.name, '/') + 1 : v->mesh.name;
    snprintf(lines[n++], 160, "%.48s  patch %.39s  normals %s  level %g", base, patch, vs_normals_name(o->normals),
             (double)o->level);
    snprintf(lines[n++], 160, "grid %s  path %s  fill %s  msaa %dx  view %s  lod %s", scene_grid_name(o->grid),
             scene_path_names[o->path], scene_fill_names[o->fill], o->msaa, show_names[v->show],
             scene_lod_names[o->lod]);
    snprintf(lines[n++], 160, "%llu triangles drawn  %dx%d  shading %s%s", (unsigned long long)v->triangles, o->width,
             o->height, scene_shading_names[o->shading], o->texture ? "  textured" : "");
    double other = v->ms_render - v->ms_setup - v->ms_tile;
    snprintf(lines[n++], 160, "%.1f ms: shading+set-up %.1f  raster %.1f  other %.1f", v->ms_render, v->ms_setup,
             v->ms_tile, other > 0 ? other : 0.0);
    snprintf(lines[n++], 160, "%.1f ms per frame shown (%.0f fps)", ms_frame, ms_frame > 0 ? 1e3 / ms_frame : 0.0);
    n = status_lines(v->status, lines, n, max);
    if (v->stepping && n < max)
        snprintf(lines[n++], 160, "playback: instances 1..%u of %zu drawn (%u per frame; . faster, , slower, x stops)",
                 o->instances, v->draw ? v->draw->n_triangles : (size_t)0, v->step_speed);
    for (int k = 0; k < v->n_pin_lines && n < max; k++) snprintf(lines[n++], 160, "%s", v->pin_lines[k]);
    if (v->hud != VIEW_HUD_KEYS) {
        if (n < max) snprintf(lines[n++], 160, "h: keys");
        return n;
    }
    for (size_t k = 0; k < view_key_count && n < max; k++)
        if (view_keys[k].help[0]) snprintf(lines[n++], 160, "%-10s %s", view_keys[k].label, view_keys[k].help);
    return n;
}

/* ------------------------------------ files ------------------------------------ */

bool view_frame_is_cli(const view_state *v)
{
    return !v->split && v->show == VIEW_SHOW_COLOR && !v->pinned;   /* a pin draws its instance over the frame */
}

int view_write_png(const view_state *v, const uint32_t *pixels, bool cli_equal, const char *path, char *err,
                   size_t errlen)
{
    is_image img = {0};
    if (image_alloc(&img, v->o.width, v->o.height, cli_equal ? "R,G,B,A,Z" : "R,G,B,A", err, errlen) != 0) return -1;
    image_from_rgba8(&img, pixels);
    char *scene = scene_describe_file(&v->o, &v->mesh, &img, IS_IMAGE_PNG), *desc = NULL;
    if (scene && cli_equal) desc = scene, scene = NULL;
    else if (scene) {   /* what the frame shows, then the scene */
        size_t n = strlen(scene) + 160;
        if ((desc = malloc(n)))
            snprintf(desc, n, "instess view frame (%s%s%s%s): %s", show_names[v->show], v->split ? ", split with " : "",
                     v->split ? vs_patch_name(v->other) : "", v->hud != VIEW_HUD_OFF ? ", HUD" : "", scene);
    }
    is_image_meta meta = {"instess " INSTESS_VERSION, desc};
    int rc = desc ? outputs_write_image(&img, path, &meta, err, errlen)
                  : (snprintf(err, errlen, "out of memory for the image's description"), -1);
    free(scene);
    free(desc);
    image_free(&img);
    return rc;
}

void view_screenshot(view_state *v)
{
    char path[64], err[1024], msg[1200];
    struct stat s;
    if (v->dirty && view_render(v, err, sizeof err) != 0) {   /* keys pressed since the last frame shown */
        snprintf(msg, sizeof msg, "screenshot failed: %s", err);
        notice(v, msg);
        return;
    }
    int k = v->shots;
    do snprintf(path, sizeof path, "instess-view-%04d.png", ++k);
    while (lstat(path, &s) == 0 && k < 9999);
    if (lstat(path, &s) == 0) {   /* every name taken: never over an existing file (an input, say) */
        notice(v, "screenshot refused: instess-view-0001.png .. instess-view-9999.png all exist here");
        return;
    }
    if (view_write_png(v, v->frame, view_frame_is_cli(v), path, err, sizeof err) != 0) {
        snprintf(msg, sizeof msg, "screenshot failed: %s", err);
        notice(v, msg);
        return;
    }
    v->shots = k;
    snprintf(v->status, sizeof v->status, "wrote %s", path);
    if (!v->o.quiet) fprintf(stderr, "instess view: wrote %s\n", path);
    v->overlay_dirty = true;   /* the HUD shows the notice */
}

/* ------------------------------------ the command line ------------------------------------ */

/* The scripting options: one table for their parsing and their help. */
typedef struct view_option {
    const char *name, *metavar, *help;
} view_option;
static const view_option view_options[] = {
    {"keys", "LIST", "comma-separated key names (those of the key table: ], p, Tab, s, Left, ...)\n"
     "pressed one per frame after the first frame; `close` closes the window; a+b presses\n"
     "a and b before the next frame"},
    {"frames", "N", "stop after N frames (a frame is drawn only when something changed)"},
    {"capture", "FILE.png", "at the end, write the last frame shown (with the HUD unless --no-hud);\n"
     "with --no-hud and the colour view, the bytes of `instess -o FILE.png`"},
    {"no-hud", NULL, "start without the HUD (h shows it)"},
    {"pin", "X,Y", "pin pixel X,Y for the inspector from the first frame (as a click there)"},
};
enum { N_VIEW_OPTIONS = sizeof view_options / sizeof view_options[0] };
/* The render options `instess view` does not take: it writes no image but its screenshots and capture. */
static const char *const not_view_options[] = {"output", "export-obj", "aov", NULL};

/* The usage text of `instess view` into f. */
static void view_usage(FILE *f)
{
    fputs("usage: instess view [OPTION]... [MESH]\n"
          "Show the render `instess [OPTION]... -o FILE` writes in a window (SDL2) and change it live: the mouse\n"
          "orbits (drag) and zooms (wheel), resizing re-renders, and the keys below change every option.\n\n", f);
    scene_print_options_except(f, not_view_options);
    for (int k = 0; k < N_VIEW_OPTIONS; k++) {
        char label[64];
        snprintf(label, sizeof label, "  --%s%s%s", view_options[k].name, view_options[k].metavar ? " " : "",
                 view_options[k].metavar ? view_options[k].metavar : "");
        fprintf(f, "%-28s", label);
        for (const char *c = view_options[k].help; *c; c++)
            if (*c == '\n') fprintf(f, "\n%28s", "");
            else fputc(*c, f);
        fputc('\n', f);
    }
    fputs("\nKeys:\n", f);
    for (size_t k = 0; k < view_key_count; k++)
        if (view_keys[k].help[0]) fprintf(f, "  %-12s%s\n", view_keys[k].label, view_keys[k].help);
}

/* Print msg as a usage error of `instess view`; 2. */
static int view_usage_error(const char *msg, const char *arg)
{
    fprintf(stderr, "instess: %s%s%s\nTry 'instess view --help'.\n", msg, arg ? ": " : "", arg ? arg : "");
    return 2;
}

/* Whether name (one key, or keys joined by '+', pressed together) names keys of the table or `close`. */
static bool known_keys(const char *name)
{
    char buf[64];
    snprintf(buf, sizeof buf, "%s", name);
    int n = 0;
    for (char *save = NULL, *t = strtok_r(buf, "+", &save); t; t = strtok_r(NULL, "+", &save), n++)
        if (!view_find_key(t) && strcasecmp(t, "close") != 0) return false;
    return n > 0;
}

/* The LIST of --keys into s (each name must have a key row, or be `close`); NULL or the usage error. */
static const char *parse_keys(const char *list, view_script *s, char *err, size_t errlen)
{
    char buf[1024];
    const int max_keys = (int)(sizeof s->keys / sizeof s->keys[0]);
    size_t n = 1;
    for (const char *c = list; *c; c++) n += *c == ',';
    if (n > (size_t)max_keys || strlen(list) >= sizeof buf)   /* said without echoing the list back */
        return snprintf(err, errlen, "--keys: %zu key names in %zu characters; at most %d names in %zu characters",
                        n, strlen(list), max_keys, sizeof buf - 1), err;
    if (*list && (list[0] == ',' || list[strlen(list) - 1] == ',' || strstr(list, ",,")))   /* strtok skips them */
        return snprintf(err, errlen, "--keys: an empty key name in the list (names are separated by single commas)"),
               err;
    strcpy(buf, list);
    for (char *save = NULL, *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        if (strlen(t) >= sizeof s->keys[0] || !known_keys(t)) {
            for (char *c = t; *c; c++)   /* shown, never a control byte on the terminal (an escape sequence) */
                if ((unsigned char)*c < 0x20 || *c == 0x7f) *c = '?';
            return snprintf(err, errlen, "--keys: unknown key %.40s (see the keys of 'instess view --help')", t), err;
        }
        strcpy(s->keys[s->n_keys++], t);
    }
    return s->n_keys ? NULL : "--keys needs at least one key name";
}

/* Take the scripting options out of argv (they are applied to s), leaving the render options in rest; NULL or
 * the usage error (err may hold it). */
static const char *take_view_options(int argc, char **argv, view_script *s, bool *no_hud, int *n_rest, char **rest,
                                     char *err, size_t errlen)
{
    *n_rest = 0;
    rest[(*n_rest)++] = argv[0];
    for (int i = 1; i < argc; i++) {
        const view_option *opt = NULL;
        const char *val = NULL;
        for (int k = 0; k < N_VIEW_OPTIONS && strncmp(argv[i], "--", 2) == 0; k++) {
            size_t n = strlen(view_options[k].name);
            if (strncmp(argv[i] + 2, view_options[k].name, n) != 0) continue;
            if (argv[i][2 + n] == 0) opt = &view_options[k];
            else if (argv[i][2 + n] == '=' && view_options[k].metavar) opt = &view_options[k], val = argv[i] + 3 + n;
        }
        if (!opt) {
            rest[(*n_rest)++] = argv[i];
            if (strcmp(argv[i], "--") == 0)   /* the rest is positional */
                while (++i < argc) rest[(*n_rest)++] = argv[i];
            continue;
        }
        if (opt->metavar && !val) {
            if (i + 1 >= argc) return snprintf(err, errlen, "--%s needs a value", opt->name), err;
            val = argv[++i];
        }
        const char *msg = NULL;
        if (strcmp(opt->name, "keys") == 0) msg = parse_keys(val, s, err, errlen);
        else if (strcmp(opt->name, "frames") == 0)
            msg = scene_parse_int(val, 1, 1000000000, &s->frames) ? NULL : "--frames must be 1..1000000000";
        else if (strcmp(opt->name, "pin") == 0)
            msg = scene_parse_pixel(val, &s->pin_x, &s->pin_y) && (s->pin = true) ? NULL
                  : "--pin takes X,Y: two whole numbers, the pixel's column and row";
        else if (strcmp(opt->name, "capture") == 0)
            msg = image_format_of(val) == IS_IMAGE_PNG ? (s->capture = val, NULL) : "--capture must end in .png";
        else *no_hud = true;
        if (msg) return msg == err ? err : (snprintf(err, errlen, "%s%s%s", msg, val ? ": " : "", val ? val : ""), err);
    }
    rest[*n_rest] = NULL;
    return NULL;
}

/* The view's options checked as the CLI checks a render's; 0 with v->o and v->script set, 2 (usage error,
 * said), or -1 when --help or --version was answered. */
static int view_options_parse(int argc, char **argv, view_state *v)
{
    char err[1024];
    char **rest = calloc((size_t)argc + 1, sizeof *rest);
    if (!rest) return view_usage_error("out of memory", NULL);
    int n_rest;
    bool no_hud = false;
    const char *msg = take_view_options(argc, argv, &v->script, &no_hud, &n_rest, rest, err, sizeof err);
    scene_args_result res = SCENE_ARGS_RUN;
    v->o.width = v->o.height = 0;   /* still 0 after the options: no --size */
    if (!msg && scene_parse_args(n_rest, rest, &v->o, &res, err, sizeof err) != 0) msg = err;
    free(rest);
    if ((v->size_default = v->o.width == 0)) v->o.width = VIEW_DEFAULT_WIDTH, v->o.height = VIEW_DEFAULT_HEIGHT;
    if (msg) return view_usage_error(msg, NULL);
    if (res == SCENE_ARGS_HELP) return view_usage(stdout), -1;
    if (res == SCENE_ARGS_VERSION) return printf("instess %s\n", INSTESS_VERSION), -1;
    if (v->o.output || v->o.export_obj)
        return view_usage_error("instess view writes no -o / --export-obj: --capture FILE.png or the s key write "
                                "what it shows", NULL);
    if ((msg = scene_check_opts(&v->o))) return view_usage_error(msg, NULL);
    v->hud = no_hud ? VIEW_HUD_OFF : VIEW_HUD_ON;
    if (v->script.pin && (v->script.pin_x >= v->o.width || v->script.pin_y >= v->o.height))
        return view_usage_error("--pin is outside the window (its --size)", NULL);
    if (v->script.pin) view_pin(v, v->script.pin_x, v->script.pin_y);
    v->texture_path = v->o.texture;   /* u turns it off and on again */
    return 0;
}

/* Load the mesh and check the first render as the CLI would; 0 or 1 (input error, said). */
static int view_load(view_state *v)
{
    char err[1024];
    is_mesh_options mo = scene_mesh_options(&v->o, scene_warn_unless_quiet, (void *)&v->o.quiet);
    is_outputs outs;
    outputs_init(&outs);
    int rc = 0;
    const char *cap = v->script.capture;
    if (cap && v->o.mesh && outputs_same_target(cap, v->o.mesh))   /* as the CLI's -o: never over an input */
        rc = -1, snprintf(err, sizeof err, "%s: is the input mesh; instess will not replace its input", cap);
    else if (cap && v->o.displace && outputs_same_target(cap, v->o.displace))
        rc = -1, snprintf(err, sizeof err, "%s: is the height map of --displace; instess will not replace its input",
                          cap);
    if (rc == 0 && cap && outputs_add(&outs, cap, err, sizeof err) != 0) rc = -1;
    outputs_abort(&outs);
    if (rc == 0 && v->o.displace && (rc = scene_load_displacement(v->o.displace, &v->displace_map, err, sizeof err)) == 0)
        v->o.displace_map = &v->displace_map;
    if (rc == 0) rc = mesh_open(v->o.mesh, &mo, &v->mesh, err, sizeof err);
    if (rc == 0 && !v->texture_path && v->mesh.texture[0]) {   /* u: the mesh's own, also after --texture none */
        v->texture_path = v->mesh.texture;
        scene_use_mesh_texture(&v->o, &v->mesh, scene_note_stderr, NULL);
    }
    char misfit[1000];
    if (rc == 0 && scene_normals_misfit(&v->mesh, misfit, sizeof misfit))   /* also with -q, as the CLI */
        fprintf(stderr, "instess: warning: %s\n", misfit);
    scene_opts textured = v->o;   /* the texture u shows, on or off now */
    textured.texture = v->texture_path;
    if (rc == 0 && scene_texture_misfit(&textured, &v->mesh, misfit, sizeof misfit))
        fprintf(stderr, "instess: warning: %s\n", misfit);
    if (rc == 0) v->draw = scene_fit_mesh(&v->mesh, &v->fit_copy);
    if (rc == 0 && !within_limits(v, &v->o, err, sizeof err)) rc = -1;
    if (rc == 0 && !(v->frame = calloc((size_t)v->o.width * v->o.height, sizeof *v->frame)))
        rc = -1, snprintf(err, sizeof err, "out of memory for a %dx%d frame", v->o.width, v->o.height);
    if (rc != 0) fprintf(stderr, "instess: %s\n", err);
    return rc == 0 ? 0 : 1;
}

/* The folder of the running executable into dir ("." if unknown). */
static void exe_dir(char *dir, size_t len)
{
    ssize_t n = readlink("/proc/self/exe", dir, len - 1);
    if (n <= 0) {
        snprintf(dir, len, ".");
        return;
    }
    dir[n] = 0;
    char *slash = strrchr(dir, '/');
    if (slash) *slash = 0;
}

/* The window module's entry point, or NULL with the reason in err.  Looked for by absolute path beside the
 * executable (the build tree), in ../lib/instess beside it and in the folder compiled in (LIBDIR/instess, where
 * make install puts it) -- never in the current folder or the folder above the program.  The first folder that
 * holds the file decides, and the file gets the codec module's checks before it is loaded (image_module_open): a
 * module there that is refused is an error, not a reason to look further. */
static view_module_fn load_module(char *err, size_t errlen)
{
    char dir[PATH_MAX], path[PATH_MAX + 64];
    exe_dir(dir, sizeof dir);
    char dirs[3][PATH_MAX + 32];
    snprintf(dirs[0], sizeof dirs[0], "%.*s", PATH_MAX, dir);
    snprintf(dirs[1], sizeof dirs[1], "%.*s/../lib/instess", PATH_MAX, dir);
    snprintf(dirs[2], sizeof dirs[2], "%.*s", PATH_MAX, image_codec_install_dir());
    size_t n = (size_t)snprintf(err, errlen, "cannot load the window module " VIEW_MODULE);
    for (int k = 0; k < 3; k++) {
        snprintf(path, sizeof path, "%.*s/" VIEW_MODULE, PATH_MAX, dirs[k]);
        struct stat st;
        if (lstat(path, &st) != 0) continue;
        char why[1024];
        void *h = image_module_open(path, VIEW_MODULE_ENTRY, why, sizeof why);
        view_module_fn fn = NULL;
        if (h) *(void **)&fn = dlsym(h, VIEW_MODULE_ENTRY);
        if (fn) return fn;
        if (n < errlen) snprintf(err + n, errlen - n, ": %s", h ? dlerror() : why);
        if (h) dlclose(h);
        return NULL;
    }
    if (n < errlen)
        snprintf(err + n, errlen - n, " (looked in %.300s, %.300s and %.300s)", dirs[0], dirs[1], dirs[2]);
    return NULL;
}

void view_free(view_state *v)
{
    for (int k = 0; k < 2; k++) dev_destroy(v->dev[k]), v->dev[k] = NULL;
    free(v->frame);
    mesh_free(&v->fit_copy);
    mesh_free(&v->mesh);
    image_free(&v->displace_map);
    v->frame = NULL;
}

int scene_cmd_view(int argc, char **argv)
{
    view_state *v = calloc(1, sizeof *v);
    if (!v) return fputs("instess: out of memory\n", stderr), 1;
    scene_opts_default(&v->o);
    v->other = VS_PATCH_NPATCH;
    int rc = view_options_parse(argc, argv, v);
    if (rc == 0) {
        clamp_pg_level(v, &v->o);
        v->status[0] = 0;
        rc = view_load(v);
    }
    if (rc == 0) {
        char err[2048];
        view_module_fn run = load_module(err, sizeof err);
        if (!run) fprintf(stderr, "instess: %s\n", err), rc = 1;
        else v->dirty = true, rc = run(v);
        report_times(v);
    }
    view_free(v);
    free(v);
    return rc < 0 ? 0 : rc;
}
