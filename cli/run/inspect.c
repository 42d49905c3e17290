/* cli/run/inspect.c -- `instess inspect [OPTION]... [MESH] --pixel X,Y [--json]`: render as `instess --msaa 1 -o`
 * would with the device recording pixel (X, Y) (core/inspect.h), then print the pixel's history:
 * every fragment that reached it -- draw, instance (the mesh triangle), grid triangle, each vertex's stream
 * registers, shader outputs and published values, the barycentrics, depth, depth test and colour -- as text for
 * people or as one JSON object (--json; README, "The pipeline inspector", documents its fields). */
#include "scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define INSPECT_USAGE "usage: instess inspect [OPTION]... [MESH] --pixel X,Y [--json]"

/* The inspect command's own options, taken out of argv before the render options are parsed. */
typedef struct inspect_args {
    int x, y;
    bool have_pixel, json;
} inspect_args;

/* Print a usage error (2). */
static int usage_error(const char *msg)
{
    fprintf(stderr, "instess inspect: %s\n" INSPECT_USAGE " (instess inspect --help)\n", msg);
    return 2;
}

/* Split argv into inspect's options (into a) and the rest (rest[0] = argv[0]); NULL or the usage error. */
static const char *take_args(int argc, char **argv, inspect_args *a, char **rest, int *n_rest)
{
    *n_rest = 0;
    rest[(*n_rest)++] = argv[0];
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--pixel") == 0) {
            if (i + 1 >= argc || !scene_parse_pixel(argv[i + 1], &a->x, &a->y))
                return "--pixel takes X,Y: two whole numbers, the pixel's column and row from the top left";
            a->have_pixel = true, i++;
        } else if (strcmp(argv[i], "--json") == 0) {
            a->json = true;
        } else {
            rest[(*n_rest)++] = argv[i];
        }
    }
    return NULL;
}

/* The help text on stdout. */
static void print_help(void)
{
    printf(INSPECT_USAGE "\n"
           "Render as instess -o would, with one sample per pixel, and print the history of pixel X,Y (from the top\n"
           "left): every fragment that reached it -- its draw, instance (the mesh triangle), grid triangle, the\n"
           "registers each vertex read from stream 0 (the grid) and stream 1 (the instance), what the vertex shader\n"
           "wrote and the values the patch shaders publish (for the smoothed patch: c, fn, bl, posN, P0..P2, g), the\n"
           "barycentrics at the pixel centre, the depth and the depth test's verdict, the colour after it -- then the\n"
           "pixel's final colour.  --json prints the same as one JSON object.  Every render option applies (instess\n"
           "--help lists them) except -o and --export-obj; the render has one sample per pixel (--msaa 1).\n\n"
           "Exit status: 0 success, 1 input error, 2 usage error.\n");
}

/* Colour packed RGBA8 (R in the low byte) as #rrggbbaa into buf. */
static const char *hex(uint32_t c, char buf[10])
{
    snprintf(buf, 10, "#%02x%02x%02x%02x", c & 0xffu, (c >> 8) & 0xffu, (c >> 16) & 0xffu, c >> 24);
    return buf;
}

/* The name of output slot k (oD0, oD1, oT0..oT7 as D3D9 names them in HLSL: COLOR0, COLOR1, TEXCOORD0..7). */
static const char *slot_name(int k, char buf[16])
{
    if (k < RS_ATTR_TEXCOORD0) snprintf(buf, 16, "COLOR%d", k);
    else snprintf(buf, 16, "TEXCOORD%d", k - RS_ATTR_TEXCOORD0);
    return buf;
}

/* One vertex of a fragment as text. */
static void print_vertex_text(FILE *f, const is_inspect_vertex *v, int k)
{
    char name[16];
    fprintf(f, "  vertex %d: stream-0 vertex %u, instance %u\n", k, v->vertex, v->instance);
    for (unsigned e = 0; e < v->n_inputs; e++) {
        const is_inspect_input *in = &v->inputs[e];
        char reg[24];
        snprintf(reg, sizeof reg, "%s%u", is_decl_usage_name(in->usage), in->usage_index);
        fprintf(f, "    in   stream %u %-13s (%.7g, %.7g, %.7g, %.7g)%s\n", in->stream, reg, in->value.x, in->value.y,
               in->value.z, in->value.w, in->per_instance ? "  per instance" : "");
    }
    for (unsigned n = 0; n < v->n_values; n++)
        fprintf(f, "    vs   %-20s (%.7g, %.7g, %.7g, %.7g)\n", v->values[n].name, v->values[n].v.x, v->values[n].v.y,
               v->values[n].v.z, v->values[n].v.w);
    fprintf(f, "    out  %-20s (%.7g, %.7g, %.7g, %.7g)\n", "POSITION (oPos)", v->out.pos.x, v->out.pos.y, v->out.pos.z,
           v->out.pos.w);
    for (int s = 0; s < RS_MAX_ATTR; s++) {
        if (!(v->outputs & (1u << s))) continue;
        const rs_vec4 *a = &v->out.attr[s];
        fprintf(f, "    out  %-20s (%.7g, %.7g, %.7g, %.7g)\n", slot_name(s, name), a->x, a->y, a->z, a->w);
    }
}

/* The record as text. */
static void print_text(FILE *f, const scene_opts *o, const is_mesh *m, const is_inspect *rec, uint32_t final_color,
                       float final_depth)
{
    char h1[10], h2[10];
    fprintf(f, "pixel (%d, %d) of a %dx%d render of %s (%s patch, level %g): %zu fragment%s in %u draw%s", rec->x,
           rec->y, o->width, o->height, m->name, vs_patch_name(o->patch), (double)o->level, rec->n_fragments,
           rec->n_fragments == 1 ? "" : "s", rec->draws, rec->draws == 1 ? "" : "s");
    if (rec->draws_skipped) fprintf(f, " (%u draw%s not recorded: N-patch mode, points or lines)", rec->draws_skipped,
                                   rec->draws_skipped == 1 ? "" : "s");
    fprintf(f, "\n");
    for (size_t k = 0; k < rec->n_fragments; k++) {
        const is_inspect_fragment *fr = &rec->fragments[k];
        fprintf(f, "\nfragment %zu: draw %u, instance %u (the mesh triangle), grid triangle %u\n", k + 1, fr->draw,
               fr->instance, fr->primitive);
        fprintf(f, "  barycentrics at the pixel centre: %.7g %.7g %.7g (of vertices 0, 1, 2)\n", fr->bary[0], fr->bary[1],
               fr->bary[2]);
        fprintf(f, "  depth %.9g against %.9g in the depth buffer: %s\n", fr->depth, fr->depth_before,
               fr->passed ? "passed" : "failed");
        fprintf(f, "  colour %s -> %s\n", hex(fr->color_before, h1), hex(fr->color_after, h2));
        for (int v = 0; v < 3; v++) print_vertex_text(f, &fr->v[v], v);
    }
    if (rec->fragments_dropped) fprintf(f, "\n(%zu more fragments not kept)\n", rec->fragments_dropped);
    fprintf(f, "\nfinal pixel: colour %s, depth %.9g\n", hex(final_color, h1), final_depth);
}

/* A float4 as a JSON array (%.9g: the float's exact value reads back). */
static void json_vec(FILE *f, const char *key, rs_vec4 v, bool comma)
{
    fprintf(f, "\"%s\": [%.9g, %.9g, %.9g, %.9g]%s", key, v.x, v.y, v.z, v.w, comma ? ", " : "");
}

/* One vertex as a JSON object. */
static void print_vertex_json(FILE *f, const is_inspect_vertex *v)
{
    char name[16];
    fprintf(f, "{\"vertex\": %u, \"instance\": %u, \"inputs\": [", v->vertex, v->instance);
    for (unsigned e = 0; e < v->n_inputs; e++) {
        const is_inspect_input *in = &v->inputs[e];
        fprintf(f, "%s{\"usage\": \"%s\", \"usage_index\": %u, \"stream\": %u, \"per_instance\": %s, ", e ? ", " : "",
               is_decl_usage_name(in->usage), in->usage_index, in->stream, in->per_instance ? "true" : "false");
        json_vec(f, "value", in->value, false);
        fprintf(f, "}");
    }
    fprintf(f, "], \"shader\": {");
    for (unsigned n = 0; n < v->n_values; n++) json_vec(f, v->values[n].name, v->values[n].v, n + 1 < v->n_values);
    fprintf(f, "}, \"outputs\": {");
    json_vec(f, "POSITION", v->out.pos, false);
    for (int s = 0; s < RS_MAX_ATTR; s++)
        if (v->outputs & (1u << s)) fprintf(f, ", "), json_vec(f, slot_name(s, name), v->out.attr[s], false);
    fprintf(f, "}}");
}

/* The record as one JSON object. */
static void print_json(FILE *f, const scene_opts *o, const is_mesh *m, const is_inspect *rec, uint32_t final_color,
                       float final_depth)
{
    char h[10];
    fprintf(f, "{\"pixel\": [%d, %d], \"size\": [%d, %d], \"mesh\": ", rec->x, rec->y, o->width, o->height);
    scene_json_string(f, m->name);
    fprintf(f, ", \"patch\": \"%s\", \"level\": %.9g, \"draws\": %u, \"draws_skipped\": %u, \"fragments_dropped\": %zu, "
           "\"fragments\": [", vs_patch_name(o->patch), (double)o->level, rec->draws, rec->draws_skipped,
           rec->fragments_dropped);
    for (size_t k = 0; k < rec->n_fragments; k++) {
        const is_inspect_fragment *fr = &rec->fragments[k];
        fprintf(f, "%s{\"draw\": %u, \"instance\": %u, \"primitive\": %u, \"bary\": [%.9g, %.9g, %.9g], "
               "\"depth\": %.9g, \"depth_before\": %.9g, \"passed\": %s, ", k ? ", " : "", fr->draw, fr->instance,
               fr->primitive, fr->bary[0], fr->bary[1], fr->bary[2], fr->depth, fr->depth_before,
               fr->passed ? "true" : "false");
        fprintf(f, "\"color_before\": \"%s\", ", hex(fr->color_before, h));
        fprintf(f, "\"color_after\": \"%s\", \"vertices\": [", hex(fr->color_after, h));
        for (int v = 0; v < 3; v++) fprintf(f, "%s", v ? ", " : ""), print_vertex_json(f, &fr->v[v]);
        fprintf(f, "]}");
    }
    fprintf(f, "], \"final\": {\"color\": \"%s\", \"depth\": %.9g}}\n", hex(final_color, h), final_depth);
}

void scene_inspect_print(FILE *f, const scene_opts *o, const is_mesh *m, const is_inspect *rec, uint32_t color,
                         float depth, bool json)
{
    if (json) print_json(f, o, m, rec, color, depth);
    else print_text(f, o, m, rec, color, depth);
}

int scene_inspect_pixel(const scene_opts *o, const is_mesh *m, int x, int y, is_inspect *rec, uint32_t *color,
                        float *depth, is_vs_constants *consts, char *err, size_t errlen)
{
    core_grid g = {0};
    const bool adaptive = o->lod != TESS_LOD_UNIFORM;   /* as the run: an adaptive render checks its finest grid */
    if (core_grid_make(adaptive ? CORE_GRID_REGULAR : o->grid, adaptive ? (float)scene_lod_max_level(o) : o->level,
                       &g) != 0)
        return snprintf(err, errlen, "level %g: cannot build the grid", (double)o->level), -1;
    int rc = scene_check_limits(o, m, &g, err, errlen);
    scene_opts one = *o;
    one.msaa = 1;
    is_device *dev = rc == 0 ? scene_create_device(&one, 1, 0, err, errlen) : NULL;
    if (rc == 0 && !dev) rc = -1;
    if (rc == 0 && dev_inspect_begin(dev, x, y, rec) != IS_OK) rc = -1, snprintf(err, errlen, "%s", dev_last_error(dev));
    if (rc == 0) rc = scene_render_on(dev, &one, m, &g, NULL, err, errlen);
    if (rc == 0 && rec->out_of_memory) rc = -1, snprintf(err, errlen, "out of memory while recording the pixel");
    if (rc == 0) {
        dev_inspect_end(dev);
        const rs_target *rt = dev_render_target(dev);
        size_t px = (size_t)y * (size_t)rt->width + (size_t)x;
        *color = rt->color[px], *depth = rt->depth[px];
        if (consts) memset(consts, 0, sizeof *consts),
                    dev_get_vertex_shader_constant_f(dev, 0, &consts->c[0].x, IS_MAX_VS_CONSTANTS);
    }
    dev_destroy(dev);
    core_grid_free(&g);
    return rc;
}

/* Load o's mesh, record pixel a and print the record on stdout; 0, or 1 with a message. */
static int inspect_scene(const scene_opts *o, const inspect_args *a)
{
    char err[1024] = "";
    is_mesh mesh = {0}, copy = {0};
    is_image map = {0};
    scene_opts od = *o;
    is_mesh_options mo = scene_mesh_options(o, scene_warn_unless_quiet, (void *)&o->quiet);
    int rc = 0;
    if (o->displace && (rc = scene_load_displacement(o->displace, &map, err, sizeof err)) == 0) od.displace_map = &map;
    if (rc == 0) rc = mesh_open(o->mesh, &mo, &mesh, err, sizeof err);
    if (rc == 0) scene_use_mesh_texture(&od, &mesh, scene_note_stderr, NULL);
    char misfit[1000];
    if (rc == 0 && scene_texture_misfit(&od, &mesh, misfit, sizeof misfit)) fprintf(stderr, "instess: warning: %s\n", misfit);
    is_inspect rec = {0};
    uint32_t color = 0;
    float depth = 0;
    const is_mesh *m = rc == 0 ? scene_fit_mesh(&mesh, &copy) : NULL;
    if (rc == 0) rc = scene_inspect_pixel(&od, m, a->x, a->y, &rec, &color, &depth, NULL, err, sizeof err);
    if (rc == 0) scene_inspect_print(stdout, o, m, &rec, color, depth, a->json);
    else fprintf(stderr, "instess inspect: %s\n", err);
    is_inspect_free(&rec);
    mesh_free(&copy);
    mesh_free(&mesh);
    image_free(&map);
    return rc == 0 ? 0 : 1;
}

int scene_cmd_inspect(int argc, char **argv)
{
    inspect_args a = {0};
    char **rest = calloc((size_t)argc + 1, sizeof *rest);
    if (!rest) return fprintf(stderr, "instess inspect: out of memory\n"), 1;
    int n_rest = 0;
    char err[1024];
    const char *msg = take_args(argc, argv, &a, rest, &n_rest);
    scene_opts o;
    scene_opts_default(&o);
    scene_args_result res = SCENE_ARGS_RUN;
    if (!msg && scene_parse_args(n_rest, rest, &o, &res, err, sizeof err) != 0) msg = err;
    free(rest);
    if (msg) return usage_error(msg);
    if (res == SCENE_ARGS_HELP) return print_help(), 0;
    if (res == SCENE_ARGS_VERSION) return printf("instess %s\n", INSTESS_VERSION), 0;
    if (o.output || o.export_obj) return usage_error("inspect writes no file: drop -o and --export-obj");
    if (o.msaa != 1 && !o.quiet)   /* the run's default is 4: say what is inspected instead */
        fprintf(stderr, "instess inspect: note: one sample per pixel, at its centre (the pixel of instess --msaa 1 "
                        "-o), not the %d samples of --msaa %d\n", o.msaa, o.msaa);
    o.msaa = 1;
    if (!a.have_pixel) return usage_error("--pixel X,Y is required");
    if ((msg = scene_check_opts(&o))) return usage_error(msg);
    if (a.x >= o.width || a.y >= o.height) {
        snprintf(err, sizeof err, "--pixel %d,%d is outside the %dx%d image", a.x, a.y, o.width, o.height);
        return usage_error(err);
    }
    return inspect_scene(&o, &a);
}
