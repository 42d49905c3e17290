/* cli/figures/fig_renders.c -- the figures of the source documents that are renderings of surfaces (table fig_renders,
 * cli/figures/figures.h): Gruen's Figs. 1.1.1, 1.1.7, 1.1.8, 1.1.10; van Veen and Baakman's Figs. 1, 5, 12 and the
 * 'fake' vs 'real' normals of their section 5.1; Real-Time Rendering's Fig. 3; and the MD2 texture-seam cracks.
 *
 * Every view is written once, as the options of the `instess` command (V_* macros below): the render parses
 * that string with the option table of cli/run/options.c and draws it through scene_draw, exactly as the command
 * does, and the table's `command` field is built from the same string, so a single rendering is reproduced
 * pixel for pixel by its command (tests/test_figures.c runs each one).  Composites list their panels' commands.
 * A rendering is "R,G,B,A,Z,N.X,N.Y,N.Z": colour with 4x MSAA, then Z (nearest sample) and the unit normal of a
 * 1-sample pass of the same view (zero on the background). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "figures.h"

#include "../../core/hlsl.h"
#define FIG_CHANNELS "R,G,B,A,Z,N.X,N.Y,N.Z"
#define FIG_NCH 8
#define MD2_DIR "/usr/share/assimp/models/MD2/"
#define SYDNEY MD2_DIR "sydney.md2"
#define FAERIE MD2_DIR "faerie.md2"

/* One parsed view: the scene options and the mesh spec they point to. */
typedef struct fig_view {
    scene_opts o;
    char mesh[512];
    char displace[512]; /* --displace's file (the view keeps its own copy, as of the mesh's name) */
    char texture[512];  /* --texture's file (likewise) */
    bool recompute;  /* --recompute-normals: angle-weighted normals per welded position */
} fig_view;

/* ---------------------------------------- views ---------------------------------------- */

/* Apply one option of a view string (--mesh, --displace and --texture here: the view keeps its own copy of the name; the
 * rest by the option table); NULL or the problem (in buf when it is built). */
static const char *view_option(fig_view *v, const char *key, const char *val, char *buf, size_t len)
{
    scene_opts *o = &v->o;
    if (!strcmp(key, "--mesh")) return snprintf(v->mesh, sizeof v->mesh, "%s", val), NULL;
    if (!strcmp(key, "--displace"))
        return snprintf(v->displace, sizeof v->displace, "%s", val), o->displace = v->displace, NULL;
    if (!strcmp(key, "--texture") && strcmp(val, "none") != 0)   /* none: by the option table */
        return snprintf(v->texture, sizeof v->texture, "%s", val), o->texture = v->texture, NULL;
    const scene_option *opt = strncmp(key, "--", 2) == 0 ? scene_find_option(key + 2) : NULL;
    return opt ? scene_apply_option(o, opt, val, buf, len) : "unknown option";
}

/* Parse a view string ("--mesh cube --patch npatch ...") over the scene defaults; 0 or -1. */
static int view_parse(fig_view *v, const char *spec, char *err, size_t errlen)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", spec);
    memset(v, 0, sizeof *v);
    scene_opts_default(&v->o);
    snprintf(v->mesh, sizeof v->mesh, "cube");
    for (char *save = NULL, *k = strtok_r(buf, " ", &save); k; k = strtok_r(NULL, " ", &save)) {
        if (!strcmp(k, "--recompute-normals")) {
            v->recompute = true;
            continue;
        }
        char *val = strtok_r(NULL, " ", &save);
        char why[600];
        const char *msg = val ? view_option(v, k, val, why, sizeof why) : "missing value";
        if (msg) return snprintf(err, errlen, "view \"%s\": %s: %s", spec, k, msg), -1;
    }
    return 0;
}

/* Load a built-in or a mesh file (warnings dropped: the figures are quiet); 0 or -1. */
static int load_mesh(const char *spec, bool recompute, is_mesh *m, char *err, size_t errlen)
{
    is_mesh_options mo = {.recompute_normals = recompute};
    return mesh_open(spec, &mo, m, err, errlen) == 0 ? 0 : -1;
}

/* ---------------------------------------- rendering ---------------------------------------- */

/* The normal AOV plane of rt into img's N.X, N.Y, N.Z. */
static void copy_normals(const rs_target *rt, is_image *img)
{
    size_t n = (size_t)rt->width * rt->height;
    for (size_t p = 0; p < n; p++)
        for (int k = 0; k < 3; k++) img->data[p * FIG_NCH + 5 + k] = rt->aov[0].data[p * 3 + k];
}

/* Render view v of mesh m at w x h into img (allocated, FIG_CHANNELS); 0 or -1. */
static int render_mesh_view(const fig_ctx *ctx, fig_view *v, const is_mesh *m, int w, int h, is_image *img,
                            char *err, size_t errlen)
{
    v->o.width = w, v->o.height = h, v->o.threads = ctx->threads, v->o.mesh = v->mesh;
    core_grid g;
    if (core_grid_make(v->o.grid, v->o.level, &g) != 0)
        return snprintf(err, errlen, "level %g: cannot build the grid", (double)v->o.level), -1;
    int rc = -1;
    /* the colour with the view's samples, then the patch normal's AOV plane with one sample, as the command
     * renders them (scene_render_view: also --cull, the light and the LOD of the view) */
    is_device *dev = scene_render_view(&v->o, m, &g, v->o.msaa, 0, NULL, err, errlen);
    is_device *adev = dev ? scene_render_view(&v->o, m, &g, 1, SCENE_AOV_NORMAL, NULL, err, errlen) : NULL;
    if (adev && image_alloc(img, w, h, FIG_CHANNELS, err, errlen) == 0) {
        rc = scene_copy_color_depth(dev_render_target(dev), img, err, errlen);
        if (rc == 0) copy_normals(dev_render_target(adev), img);
        else image_free(img);
    }
    dev_destroy(adev);
    dev_destroy(dev);
    core_grid_free(&g);
    return rc;
}

int fig_render_spec(const fig_ctx *ctx, const char *spec, int w, int h, is_image *img, char *err, size_t errlen)
{
    fig_view v;
    is_mesh m = {0};
    if (view_parse(&v, spec, err, errlen) != 0 || load_mesh(v.mesh, v.recompute, &m, err, errlen) != 0) return -1;
    int rc = render_mesh_view(ctx, &v, &m, w, h, img, err, errlen);
    mesh_free(&m);
    return rc;
}

/* ---------------------------------------- composites ---------------------------------------- */

/* Sizes of composite figures: panel side, font sizes and the title band, halved for the test size. */
typedef struct fig_sizes { int single, panel, tall, lod_w, lod_h, title_h; float title_px, label_px; } fig_sizes;

static fig_sizes sizes_of(const fig_ctx *ctx)
{
    fig_sizes s = {512, 320, 400, 300, 520, 30, 18.0f, 14.0f};
    if (ctx->small) s = (fig_sizes){256, 160, 200, 150, 260, 16, 10.0f, 8.0f};
    return s;
}

/* The scene's default background colour as floats (what a rendering holds there). */
static void background_rgb(float rgb[3])
{
    scene_opts o;
    scene_opts_default(&o);
    for (int k = 0; k < 3; k++) rgb[k] = (float)((o.background >> (16 - 8 * k)) & 0xffu) / 255.0f;
}

/* A composite picture w x h filled with the background: its colour, A = 0 (no mesh: transparent in the EXR),
 * Z = 1 (far), N = 0; 0 or -1. */
static int composite_alloc(is_image *img, int w, int h, char *err, size_t errlen)
{
    if (image_alloc(img, w, h, FIG_CHANNELS, err, errlen) != 0) return -1;
    float bg[3];
    background_rgb(bg);
    for (size_t p = 0; p < (size_t)w * h; p++) {
        float *px = &img->data[p * FIG_NCH];
        memset(px, 0, FIG_NCH * sizeof *px);
        px[0] = bg[0], px[1] = bg[1], px[2] = bg[2], px[3] = 0.0f, px[4] = 1.0f;
    }
    return 0;
}

/* Copy every channel of src into dst with src's top-left corner at (x, y) (clipped). */
static void blit(is_image *dst, const is_image *src, int x, int y)
{
    for (int r = 0; r < src->height; r++)
        for (int c = 0; c < src->width; c++) {
            if (x + c < 0 || x + c >= dst->width || y + r < 0 || y + r >= dst->height) continue;
            memcpy(&dst->data[((size_t)(y + r) * dst->width + x + c) * FIG_NCH],
                   &src->data[((size_t)r * src->width + c) * FIG_NCH], FIG_NCH * sizeof(float));
        }
}

/* Light text at (x, baseline y); 0 or -1. */
static int label(is_image *img, int x, int y, const char *text, float px, char *err, size_t errlen)
{
    static const float ink[4] = {0.93f, 0.93f, 0.90f, 1.0f};
    return image_draw_text(img, x, y, text, px, ink, err, errlen);
}

/* Text centred horizontally on cx; 0 or -1. */
static int label_centred(is_image *img, int cx, int y, const char *text, float px, char *err, size_t errlen)
{
    int w = 0, h = 0;
    image_text_size(text, px, &w, &h);
    return label(img, cx - w / 2, y, text, px, err, errlen);
}

/* The frame of a composite: rows x cols panels of pw x ph, each under a band for its label, all under a band for
 * the title. */
typedef struct fig_layout { int rows, cols, pw, ph, label_h; fig_sizes s; } fig_layout;

static fig_layout layout_of(const fig_ctx *ctx, int rows, int cols, int pw, int ph)
{
    fig_sizes s = sizes_of(ctx);
    return (fig_layout){rows, cols, pw, ph, (int)(s.label_px * 1.8f), s};
}

/* Allocate the composite of L with its title; 0 or -1. */
static int layout_begin(const fig_layout *L, const char *title, is_image *out, char *err, size_t errlen)
{
    int w = L->cols * L->pw, h = L->s.title_h + L->rows * (L->label_h + L->ph);
    if (composite_alloc(out, w, h, err, errlen) != 0) return -1;
    if (label_centred(out, w / 2, (int)(L->s.title_h * 0.72f), title, L->s.title_px, err, errlen) == 0) return 0;
    image_free(out);
    return -1;
}

/* The top-left corner of panel k's image (row-major). */
static void layout_cell(const fig_layout *L, int k, int *x, int *y)
{
    *x = (k % L->cols) * L->pw;
    *y = L->s.title_h + (k / L->cols) * (L->label_h + L->ph) + L->label_h;
}

/* Put panel image p at cell k with its label above it; 0 or -1. */
static int layout_place(const fig_layout *L, is_image *out, int k, const is_image *p, const char *text, char *err,
                        size_t errlen)
{
    int x, y;
    layout_cell(L, k, &x, &y);
    blit(out, p, x, y);
    return label_centred(out, x + L->pw / 2, y - (int)(L->label_h * 0.3f), text, L->s.label_px, err, errlen);
}

/* One panel of a composite: its view string and its label. */
typedef struct fig_panel { const char *view; const char *label; } fig_panel;

/* A composite of rows x cols panels of pw x ph, each rendered from its view, labelled, under a title; 0 or -1. */
static int render_grid(const fig_ctx *ctx, const char *title, const fig_panel *panels, int rows, int cols, int pw,
                       int ph, is_image *out, char *err, size_t errlen)
{
    fig_layout L = layout_of(ctx, rows, cols, pw, ph);
    int rc = layout_begin(&L, title, out, err, errlen);
    for (int k = 0; rc == 0 && k < rows * cols; k++) {
        is_image p = {0};
        rc = fig_render_spec(ctx, panels[k].view, pw, ph, &p, err, errlen);
        if (rc == 0) rc = layout_place(&L, out, k, &p, panels[k].label, err, errlen);
        image_free(&p);
        if (rc != 0) image_free(out);
    }
    return rc;
}

/* ---------------------------------------- single renderings ---------------------------------------- */

/* What `instess -o` stores as the descriptions of view v's PNG and of its EXR with the normal AOV (the
 * channels of a rendering, img), into ctx's pointers when it asks; 0, or -1 when out of memory. */
static int describe_view(const fig_ctx *ctx, const fig_view *v, const is_mesh *m, const is_image *img, char *err,
                         size_t errlen)
{
    if (!ctx->describe_png || !ctx->describe_exr) return 0;
    scene_opts o = v->o;
    o.output = "figure.png", o.aovs = 0;
    *ctx->describe_png = scene_describe_file(&o, m, img, IS_IMAGE_PNG);
    o.output = "figure.exr", o.aovs = SCENE_AOV_NORMAL;
    *ctx->describe_exr = scene_describe_file(&o, m, img, IS_IMAGE_EXR);
    if (*ctx->describe_png && *ctx->describe_exr) return 0;
    return snprintf(err, errlen, "out of memory for the figure's descriptions"), -1;
}

/* One view at the single size (512x512; 256x256 small), its descriptions into ctx's buffers. */
static int render_single(const fig_ctx *ctx, const char *spec, is_image *out, char *err, size_t errlen)
{
    fig_sizes s = sizes_of(ctx);
    fig_view v;
    is_mesh m = {0};
    if (view_parse(&v, spec, err, errlen) != 0 || load_mesh(v.mesh, v.recompute, &m, err, errlen) != 0) return -1;
    int rc = render_mesh_view(ctx, &v, &m, s.single, s.single, out, err, errlen);
    if (rc == 0 && (rc = describe_view(ctx, &v, &m, out, err, errlen)) != 0) image_free(out);
    mesh_free(&m);
    return rc;
}

/* The views of the single renderings.  Real normals (seed 001, 3.2.2: the normal of the surface itself) under the
 * listing's diffuse term: Listing 1.1.2's linear normal would shade every patch alike and hide the shape the
 * figures are about (creases of the N-Patch across edges, the smoother new patch, the valleys). */
#define V_TETRA "--mesh tetrahedron --normals real --level 16 --yaw 60 --pitch 35 --distance 2.7"
#define V_TETRA_EDGE "--mesh tetrahedron --normals real --level 16 --yaw 0 --pitch 0 --distance 2.7"
#define V_CUBE "--mesh cube --normals real --level 16 --yaw 30 --pitch 20"
#define V_CUBE_10 "--mesh cube --normals real --level 16 --yaw -35 --pitch 30"
#define V_1_1_1A V_TETRA " --patch npatch"
#define V_1_1_1B V_TETRA " --patch smooth"
#define V_1_1_1C V_CUBE " --patch npatch"
#define V_1_1_1D V_CUBE " --patch smooth"
#define V_1_1_7A V_TETRA_EDGE " --patch npatch --light 0.3,0.3,-1"
#define V_1_1_7B V_TETRA_EDGE " --patch smooth-initial --light 0.3,0.3,-1"
#define V_1_1_8A "--mesh cube --patch smooth-initial --normals real --level 12 --yaw 45 --pitch 0 --fill solid+wire"
#define V_1_1_8B "--mesh cube --patch smooth-initial --normals real --level 32 --yaw 0 --pitch 0 --light grazing"
#define V_1_1_10A V_CUBE_10 " --patch npatch"
#define V_1_1_10B V_CUBE_10 " --patch smooth"
#define CMD_SINGLE(view, id) "instess " view " --size 512x512 -o " id ".png"

/* A render function per single figure (fig_fn has no argument naming the figure). */
#define SINGLE_FN(name, view) \
    static int name(const fig_ctx *ctx, is_image *out, char *err, size_t errlen) \
    { return render_single(ctx, view, out, err, errlen); }
SINGLE_FN(fig_1_1_1a, V_1_1_1A)
SINGLE_FN(fig_1_1_1b, V_1_1_1B)
SINGLE_FN(fig_1_1_1c, V_1_1_1C)
SINGLE_FN(fig_1_1_1d, V_1_1_1D)
SINGLE_FN(fig_1_1_7a, V_1_1_7A)
SINGLE_FN(fig_1_1_7b, V_1_1_7B)
SINGLE_FN(fig_1_1_8a, V_1_1_8A)
SINGLE_FN(fig_1_1_8b, V_1_1_8B)
SINGLE_FN(fig_1_1_10a, V_1_1_10A)
SINGLE_FN(fig_1_1_10b, V_1_1_10B)

/* The patches side by side on the cube of fig-1.1.1c/d, each labelled with its largest crease across an edge
 * as tess_smoothness measures it (16 samples per edge, as instess smoothness). */
#define V_PATCHES V_CUBE
static const char *const patch_panel_views[6] = {
    V_PATCHES " --patch flat", V_PATCHES " --patch npatch", V_PATCHES " --patch smooth-initial",
    V_PATCHES " --patch smooth", V_PATCHES " --patch phong", V_PATCHES " --patch pn-aen"};
static int fig_patches(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    fig_sizes s = sizes_of(ctx);
    fig_layout L = layout_of(ctx, 2, 3, s.panel, s.panel);
    int rc = layout_begin(&L, "The patches on one mesh: the welded cube, real normals, level 16", out, err, errlen);
    for (int k = 0; rc == 0 && k < 6; k++) {
        fig_view v;
        is_mesh m = {0};
        is_image p = {0};
        vs_smoothness_result r = {0};
        rc = view_parse(&v, patch_panel_views[k], err, errlen);
        if (rc == 0) rc = load_mesh(v.mesh, false, &m, err, errlen);
        vs_options vo = vs_default_options();
        if (rc == 0 && tess_smoothness(&m, v.o.patch, &vo, 16, &r) != 0)
            rc = -1, snprintf(err, errlen, "tess_smoothness failed");
        if (rc == 0) rc = render_mesh_view(ctx, &v, &m, s.panel, s.panel, &p, err, errlen);
        char text[96];
        snprintf(text, sizeof text, "%s: crease %.1f deg", vs_patch_name(v.o.patch), r.max_angle_deg);
        if (rc == 0) rc = layout_place(&L, out, k, &p, text, err, errlen);
        image_free(&p);
        mesh_free(&m);
        if (rc != 0) image_free(out);
    }
    return rc;
}

/* The renderings of seed 000 with the listing's own shading: its linear (interpolated) normals. */
#define LINEAR " --normals linear"
static int fig_000_listing(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const fig_panel p[] = {
        {V_1_1_1A LINEAR, "1.1.1a npatch"}, {V_1_1_1B LINEAR, "1.1.1b smooth"}, {V_1_1_1C LINEAR, "1.1.1c npatch"},
        {V_1_1_1D LINEAR, "1.1.1d smooth"}, {V_1_1_7A LINEAR, "1.1.7a npatch"}, {V_1_1_7B LINEAR, "1.1.7b initial"},
        {V_1_1_8A LINEAR, "1.1.8a initial"}, {V_1_1_8B LINEAR, "1.1.8b initial"}, {V_1_1_10A LINEAR, "1.1.10a npatch"},
        {V_1_1_10B LINEAR, "1.1.10b smooth"}};
    fig_sizes s = sizes_of(ctx);
    return render_grid(ctx, "Gruen's views shaded as his listing shades them: linear normals", p, 2, 5,
                       s.panel * 5 / 8, s.panel * 5 / 8, out, err, errlen);
}

/* ---------------------------------------- seed 001 ---------------------------------------- */

#define V_001_1 "--mesh icosahedron --yaw 20 --pitch 15"
/* Fig. 1: the input triangulation (flat, wireframe), the PN model, the PN model coloured by its normals. */
static int fig_001_1(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const fig_panel p[] = {
        {V_001_1 " --patch flat --normals linear --level 1 --fill solid+wire", "input triangulation"},
        {V_001_1 " --patch npatch --normals quadratic --level 12", "the model (PN triangles)"},
        {V_001_1 " --patch npatch --normals quadratic --level 12 --light normals", "PN model coloured by normals"}};
    fig_sizes s = sizes_of(ctx);
    return render_grid(ctx, "Input triangulation, the model, the PN model coloured by its normals", p, 1, 3,
                       s.panel, s.panel, out, err, errlen);
}

#define V_001_5 "--mesh cylinder --normals linear --level 8 --yaw 20 --pitch -35 --distance 2.8"
/* Fig. 5: PN triangles over split normals open cracks (the background shows through); PN-AEN and welded normals
 * do not. */
static int fig_001_5(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const fig_panel p[] = {{V_001_5 " --patch npatch", "N-Patch, split rim normals: crack"},
                                  {V_001_5 " --patch pn-aen", "PN-AEN, same normals: closed"},
                                  {V_001_5 " --patch npatch --recompute-normals", "N-Patch, welded normals"}};
    fig_sizes s = sizes_of(ctx);
    return render_grid(ctx, "PN triangles where vertices have different normals per face", p, 1, 3, s.panel,
                       s.panel, out, err, errlen);
}

#define V_MD2_CAMERA "--yaw 90 --pitch 0 --distance 2.7"
/* --texture none: the MD2 characters have skins beside them, which instess draws unless told not to */
#define V_MD2 V_MD2_CAMERA " --texture none"
/* Fig. 12: a family of game characters: input (Gouraud-shaded triangles), PN triangles, Gruen's smoothed patch. */
static int fig_001_12(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const fig_panel p[] = {
        {"--mesh " FAERIE " --patch flat --normals linear --level 1 " V_MD2, "faerie: input"},
        {"--mesh " SYDNEY " --patch flat --normals linear --level 1 " V_MD2, "sydney: input"},
        {"--mesh " FAERIE " --patch npatch --normals quadratic --level 4 " V_MD2, "faerie: PN triangles"},
        {"--mesh " SYDNEY " --patch npatch --normals quadratic --level 4 " V_MD2, "sydney: PN triangles"},
        {"--mesh " FAERIE " --patch smooth --normals quadratic --level 4 " V_MD2, "faerie: smoothed N-Patch"},
        {"--mesh " SYDNEY " --patch smooth --normals quadratic --level 4 " V_MD2, "sydney: smoothed N-Patch"}};
    fig_sizes s = sizes_of(ctx);
    return render_grid(ctx, "MD2 characters: input, PN, smoothed", p, 3, 2, s.panel * 3 / 4,
                       s.tall, out, err, errlen);
}

/* ---------------------------------------- adaptive level of detail ---------------------------------------- */

/* The same sphere near and far, uniform level 16 and --lod screen (levels 1..16, 8 pixels per segment at the full
 * size), solid with the wireframe coloured by level (--wire-levels on: each bucket's finest level,
 * blue 1 .. green 8 .. red 64).  The uniform panels go through the same adaptive path with every edge at 16 (the
 * pattern 16/16/16 is the regular grid). */
#define V_LOD "--mesh sphere --patch smooth --normals real --yaw 30 --pitch 20 --fill solid+wire --wire-levels on"
#define V_LOD_UNIFORM " --lod distance --min-level 16 --max-level 16"
#define V_LOD_SCREEN " --lod screen --max-level 16 --lod-target 8"
#define V_LOD_NEAR " --distance 3"
#define V_LOD_FAR " --distance 8"

/* Triangles the adaptive draw of view v on m tessellates (the levels as scene_draw computes them); 0 on failure. */
static size_t lod_triangles(const fig_view *v, const is_mesh *m)
{
    tess_lod_params p = scene_lod_params_of(&v->o, m);
    tess_lod_edges e;
    char err[64];
    uint64_t hist[CORE_LOD_MAX_LEVEL + 1];
    core_pattern_cache *cache = core_pattern_cache_create(0);
    size_t n = 0;
    if (cache && tess_lod_edges_build(m, &e, err, sizeof err) == 0) {
        tess_lod_levels(&p, m, &e, hist);
        for (size_t t = 0; t < m->n_triangles; t++) {
            int lv[3], s[3], q[3];
            for (int k = 0; k < 3; k++) lv[k] = e.level[e.tri_edge[3 * t + k]];
            core_lod_order(lv, s, q);
            const core_grid *g = core_pattern_get(cache, s[0], s[1], s[2]);
            n += g ? g->n_triangles : 0;
        }
        tess_lod_edges_free(&e);
    }
    core_pattern_cache_destroy(cache);
    return n;
}

/* Uniform vs adaptive at two distances, each panel labelled with its triangle count. */
static int fig_lod(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const struct { const char *view, *what; } p[] = {
        {V_LOD V_LOD_NEAR V_LOD_UNIFORM, "near, uniform 16"}, {V_LOD V_LOD_NEAR V_LOD_SCREEN, "near, --lod screen"},
        {V_LOD V_LOD_FAR V_LOD_UNIFORM, "far, uniform 16"}, {V_LOD V_LOD_FAR V_LOD_SCREEN, "far, --lod screen"}};
    fig_sizes s = sizes_of(ctx);
    fig_layout L = layout_of(ctx, 2, 2, s.panel, s.panel);
    int rc = layout_begin(&L, "Uniform 16 vs --lod screen; wire colour = level", out, err,
                          errlen);
    for (int k = 0; rc == 0 && k < 4; k++) {
        fig_view v;
        is_mesh m = {0};
        is_image img = {0};
        char text[96];
        rc = view_parse(&v, p[k].view, err, errlen);
        if (rc == 0) rc = load_mesh(v.mesh, v.recompute, &m, err, errlen);
        if (rc == 0) rc = render_mesh_view(ctx, &v, &m, s.panel, s.panel, &img, err, errlen);
        if (rc == 0) snprintf(text, sizeof text, "%s: %zu triangles", p[k].what, lod_triangles(&v, &m));
        if (rc == 0) rc = layout_place(&L, out, k, &img, text, err, errlen);
        image_free(&img);
        mesh_free(&m);
        if (rc != 0) image_free(out);
    }
    return rc;
}

/* ---------------------------------------- fake vs real normals ---------------------------------------- */

#define HEAT_MAX_DEG 45.0f
/* The heat-map colour of t in [0, 1]: black, purple, orange, pale yellow. */
static float3 heat_colour(float t)
{
    static const float stops[4][3] = {{0.02f, 0.02f, 0.08f}, {0.45f, 0.05f, 0.55f}, {0.95f, 0.40f, 0.08f},
                                      {1.0f, 0.98f, 0.65f}};
    t = saturate(t) * 3.0f;
    int k = t >= 3.0f ? 2 : (int)t;
    float f = t - (float)k;
    return f3(stops[k][0] + (stops[k + 1][0] - stops[k][0]) * f, stops[k][1] + (stops[k + 1][1] - stops[k][1]) * f,
              stops[k][2] + (stops[k + 1][2] - stops[k][2]) * f);
}

/* Replace the colour of `real` with the angle between its normals and those of `fake` (where both cover the
 * pixel; the background stays), mapped 0..HEAT_MAX_DEG to the heat colours. */
static void heat_map(is_image *real, const is_image *fake)
{
    for (size_t p = 0; p < (size_t)real->width * real->height; p++) {
        float *a = &real->data[p * FIG_NCH];
        const float *b = &fake->data[p * FIG_NCH];
        float3 na = f3(a[5], a[6], a[7]), nb = f3(b[5], b[6], b[7]);
        if (dot3(na, na) == 0.0f || dot3(nb, nb) == 0.0f) continue;
        float deg = acosf(fmaxf(-1.0f, fminf(1.0f, dot3(na, nb)))) * (180.0f / 3.14159265f);
        float3 c = heat_colour(deg / HEAT_MAX_DEG);
        a[0] = c.x, a[1] = c.y, a[2] = c.z;
    }
}

/* The colour scale under the heat map: a bar of the heat colours from 0 to HEAT_MAX_DEG degrees. */
static int heat_legend(is_image *img, int x, int y, int w, float px, char *err, size_t errlen)
{
    int h = (int)px;
    for (int r = 0; r < h; r++)
        for (int c = 0; c < w; c++) {
            float3 col = heat_colour((float)c / (float)(w - 1));
            float *d = &img->data[((size_t)(y + r) * img->width + x + c) * FIG_NCH];
            d[0] = col.x, d[1] = col.y, d[2] = col.z, d[3] = 1.0f;
        }
    char txt[64];
    snprintf(txt, sizeof txt, "%g deg", (double)HEAT_MAX_DEG);
    int tw = 0, th = 0;
    image_text_size(txt, px, &tw, &th);
    if (label(img, x - (int)(px * 1.0f), y + h + (int)(px * 1.2f), "0", px, err, errlen) != 0) return -1;
    return label(img, x + w - tw / 2, y + h + (int)(px * 1.2f), txt, px, err, errlen);
}

#define V_FAKE_REAL "--mesh cube --patch npatch --level 16 --yaw 30 --pitch 20"
/* A copy of src (allocated); 0 or -1. */
static int image_copy(is_image *dst, const is_image *src, char *err, size_t errlen)
{
    if (image_alloc(dst, src->width, src->height, FIG_CHANNELS, err, errlen) != 0) return -1;
    memcpy(dst->data, src->data, (size_t)src->width * src->height * FIG_NCH * sizeof(float));
    return 0;
}

/* 'Fake' (quadratic) vs 'real' (derivative) normals of the N-Patch on the cube, and the angle between them. */
static int fig_001_fake_vs_real(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    fig_sizes s = sizes_of(ctx);
    fig_layout L = layout_of(ctx, 1, 3, s.panel, s.panel);
    is_image fake = {0}, real = {0}, diff = {0};
    int rc = fig_render_spec(ctx, V_FAKE_REAL " --normals quadratic", s.panel, s.panel, &fake, err, errlen);
    if (rc == 0) rc = fig_render_spec(ctx, V_FAKE_REAL " --normals real", s.panel, s.panel, &real, err, errlen);
    if (rc == 0) rc = image_copy(&diff, &real, err, errlen);
    if (rc == 0) heat_map(&diff, &fake);
    if (rc == 0) rc = layout_begin(&L, "'Fake' vs 'real' normals of PN triangles", out, err, errlen);
    if (rc == 0) rc = layout_place(&L, out, 0, &fake, "'fake' (quadratic) normals", err, errlen);
    if (rc == 0) rc = layout_place(&L, out, 1, &real, "'real' (derivative) normals", err, errlen);
    if (rc == 0) rc = layout_place(&L, out, 2, &diff, "angle between them", err, errlen);
    int x, y;
    layout_cell(&L, 2, &x, &y);
    if (rc == 0) rc = heat_legend(out, x + s.panel / 4, y + s.panel - (int)(s.label_px * 2.6f), s.panel / 2,
                                  s.label_px, err, errlen);
    image_free(&fake);
    image_free(&real);
    image_free(&diff);
    if (rc != 0) image_free(out);
    return rc;
}

/* ---------------------------------------- seed 003 ---------------------------------------- */

#define V_003_3 "--mesh " SYDNEY " --patch npatch --normals quadratic " V_MD2
/* Fig. 3: LOD 0, 2, 6 (levels 1, 3, 7: x1, x9, x49 triangles) of a game character, shaded and wireframe. */
static int fig_003_3(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const fig_panel p[] = {
        {V_003_3 " --level 1", "LOD 0: 679 triangles"},   {V_003_3 " --level 3", "LOD 2: 6111 triangles"},
        {V_003_3 " --level 7", "LOD 6: 33271 triangles"}, {V_003_3 " --level 1 --fill wire", "LOD 0 wireframe"},
        {V_003_3 " --level 3 --fill wire", "LOD 2 wireframe"}, {V_003_3 " --level 7 --fill wire", "LOD 6 wireframe"}};
    fig_sizes s = sizes_of(ctx);
    return render_grid(ctx, "Levels of detail of the same model, shaded and wireframe", p, 2, 3, s.lod_w, s.lod_h,
                       out, err, errlen);
}

/* ---------------------------------------- MD2 texture seams ---------------------------------------- */

/* Angle-weighted normals per vertex INDEX (not per position): a vertex split at a texture seam gets only the
 * triangles that use that copy, so the copies on the two sides of a seam get different normals. */
static void normals_per_index(const is_mesh *m, float3 *n)
{
    memset(n, 0, m->n_vertices * sizeof *n);
    for (size_t t = 0; t < m->n_triangles; t++) {
        const uint32_t *i = &m->indices[3 * t];
        float3 fn = mesh_compute_face_normal(m->positions[i[0]], m->positions[i[1]], m->positions[i[2]]);
        for (int k = 0; k < 3; k++) {
            float3 a = normalize3(sub3(m->positions[i[(k + 1) % 3]], m->positions[i[k]]));
            float3 b = normalize3(sub3(m->positions[i[(k + 2) % 3]], m->positions[i[k]]));
            float ang = acosf(fmaxf(-1.0f, fminf(1.0f, dot3(a, b))));
            n[i[k]] = add3(n[i[k]], scale3(fn, ang));
        }
    }
    for (size_t v = 0; v < m->n_vertices; v++) n[v] = normalize3(n[v]);
}

/* The mesh at spec with normals per unwelded vertex (see above); 0 or -1. */
static int load_split_normals(const char *spec, is_mesh *out, char *err, size_t errlen)
{
    is_mesh m = {0};
    if (load_mesh(spec, true, &m, err, errlen) != 0) return -1;
    float3 *n = malloc(m.n_vertices * sizeof *n);
    int rc = -1;
    if (!n) snprintf(err, errlen, "out of memory");
    else {
        normals_per_index(&m, n);
        is_mesh_data d = {m.n_vertices, m.n_triangles, m.positions, n, m.texcoords, m.indices};
        rc = mesh_create(out, spec, &d, NULL, err, errlen) == 0 ? 0 : -1;
    }
    free(n);
    mesh_free(&m);
    return rc;
}

#define V_SEAMS "--mesh " SYDNEY " --patch npatch --normals linear --level 4 --yaw 180 --pitch 0 --distance 2.9 --texture none"
/* Split normals at the texture seams of an MD2 character crack the PN triangles; welded normals do not. */
static int fig_md2_seams(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    fig_sizes s = sizes_of(ctx);
    fig_layout L = layout_of(ctx, 1, 2, s.panel, s.lod_h);
    static const char *const labels[2] = {"normals per seam vertex: cracks", "welded normals: closed"};
    int rc = layout_begin(&L, "Normals split at texture seams vs welded", out, err, errlen);
    for (int k = 0; rc == 0 && k < 2; k++) {
        fig_view v;
        is_mesh m = {0};
        is_image p = {0};
        rc = view_parse(&v, V_SEAMS, err, errlen);
        if (rc == 0) rc = k == 0 ? load_split_normals(v.mesh, &m, err, errlen) : load_mesh(v.mesh, true, &m, err, errlen);
        if (rc == 0) rc = render_mesh_view(ctx, &v, &m, s.panel, s.lod_h, &p, err, errlen);
        if (rc == 0) rc = layout_place(&L, out, k, &p, labels[k], err, errlen);
        image_free(&p);
        mesh_free(&m);
        if (rc != 0) image_free(out);
    }
    return rc;
}

/* ---------------------------------------- displacement by vertex texture fetch ---------------------------------------- */

/* The height map, a file of the repository (tests/data/textures/make_bumps.py writes it): the figures run in the
 * repository's root, as `make figures` and the tests do. */
#define BUMPS "tests/data/textures/bumps.png"
#define V_DISPLACE "--mesh cube --level 32 --yaw 35 --pitch 25 --light grazing"
#define V_UNDISPLACED " --normals real"
#define V_DISPLACE_MAP " --normals linear --displace " BUMPS " --displace-scale 0.1"
/* The N-Patch and the smoothed patch, as they are and displaced by the same map. */
static int fig_displace(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const fig_panel p[] = {
        {V_DISPLACE " --patch npatch" V_UNDISPLACED, "N-Patch"},
        {V_DISPLACE " --patch smooth" V_UNDISPLACED, "smoothed patch"},
        {V_DISPLACE " --patch npatch" V_DISPLACE_MAP, "N-Patch, displaced"},
        {V_DISPLACE " --patch smooth" V_DISPLACE_MAP, "smoothed patch, displaced"}};
    fig_sizes s = sizes_of(ctx);
    return render_grid(ctx, "Displacement by a vertex texture fetch", p, 2, 2, s.panel,
                       s.panel, out, err, errlen);
}

/* The pixel stage (issue 28): light per vertex and per pixel, textures, and the technique one instance at a time. */
#define V_SHADE "--mesh cube --level 4 --yaw 35 --pitch 25 --light grazing --normals real"
/* Per-vertex (the listings: Gouraud between grid points) against per-pixel light (a pixel shader evaluating the
 * patch normal at each pixel's barycentrics) for the N-Patch and the smoothed patch. */
static int fig_shading(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const fig_panel p[] = {
        {V_SHADE " --patch npatch --shading vertex", "N-Patch, per vertex"},
        {V_SHADE " --patch smooth --shading vertex", "smoothed, per vertex"},
        {V_SHADE " --patch npatch --shading pixel", "N-Patch, per pixel"},
        {V_SHADE " --patch smooth --shading pixel", "smoothed, per pixel"}};
    fig_sizes s = sizes_of(ctx);
    return render_grid(ctx, "Light per vertex and per pixel at level 4", p, 2, 2, s.panel, s.panel, out, err, errlen);
}

#define V_SKIN " --color 1,1,1 --normals quadratic " V_MD2_CAMERA
/* The MD2 characters with their skins, through a pixel shader: input, PN triangles, Gruen's smoothed patch. */
static int fig_textured(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const fig_panel p[] = {
        {"--mesh " FAERIE " --texture " MD2_DIR "faerie2.bmp --patch flat --level 1" V_SKIN, "faerie: input"},
        {"--mesh " SYDNEY " --texture " MD2_DIR "sydney.bmp --patch flat --level 1" V_SKIN, "sydney: input"},
        {"--mesh " FAERIE " --texture " MD2_DIR "faerie2.bmp --patch npatch --level 4" V_SKIN, "faerie: PN"},
        {"--mesh " SYDNEY " --texture " MD2_DIR "sydney.bmp --patch npatch --level 4" V_SKIN, "sydney: PN"},
        {"--mesh " FAERIE " --texture " MD2_DIR "faerie2.bmp --patch smooth --level 4" V_SKIN, "faerie: smoothed"},
        {"--mesh " SYDNEY " --texture " MD2_DIR "sydney.bmp --patch smooth --level 4" V_SKIN, "sydney: smoothed"}};
    fig_sizes s = sizes_of(ctx);
    return render_grid(ctx, "MD2 characters with their skins", p, 3, 2, s.panel * 3 / 4, s.tall, out, err, errlen);
}

#define V_STEP "--mesh cube --patch smooth --level 4 --cull none --fill solid+wire --yaw 35 --pitch 25"
/* The instanced draw with 1, 2, 4, 6, 9 and 12 instances: one mesh triangle's grid per instance. */
static int fig_step(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const fig_panel p[] = {
        {V_STEP " --instances 1", "1 instance"}, {V_STEP " --instances 2", "2 instances"},
        {V_STEP " --instances 4", "4 instances"}, {V_STEP " --instances 6", "6 instances"},
        {V_STEP " --instances 9", "9 instances"}, {V_STEP " --instances 12", "12: the cube"}};
    fig_sizes s = sizes_of(ctx);
    return render_grid(ctx, "The instanced draw, one mesh triangle per instance", p, 1, 6, s.panel / 2, s.panel / 2,
                       out, err, errlen);
}

/* ---------------------------------------- the table ---------------------------------------- */

#define GRUEN "H. Gruen, Smoothed N-Patches, Figure "
#define VVB "R. van Veen and L. Baakman, A Discussion of Curved Point-Normal Triangles, "
#define RTR "T. Akenine-Moller and E. Haines, Real-Time Rendering, section Bezier Triangles and N-Patches, "
/* A composite's reproduction: the figure itself, then each panel's own command (its pixels, before labels). */
#define CMD_COMPOSITE(id, panels) "instess figures --only " id " --out DIR\n" panels
#define PANEL(k, view, size) "panel " #k ": instess " view " --size " size " -o panel" #k ".png\n"

const figure fig_renders[] = {
    {"fig-1.1.1a", "fig-1.1.1", GRUEN "1.1.1a", "A tetrahedron refined using the original N-Patch.",
     "The built-in tetrahedron (4 triangles, one averaged normal per corner) as N-Patches at level 16 (256 "
     "triangles per face), seen towards a corner. Every edge is a crease: instess smoothness measures 93.3 "
     "degrees between the normals on its two sides at worst, 78.0 on average.",
     CMD_SINGLE(V_1_1_1A, "fig-1.1.1a"), true, fig_1_1_1a, 0},
    {"fig-1.1.1b", "fig-1.1.1", GRUEN "1.1.1b", "A tetrahedron refined using the new patch.",
     "The same view with the final smoothed patch (Listing 1.1.2). The crease softens but stays: 50.2 degrees at "
     "worst, 42.9 on average. Each edge's patch P_k is blended towards the N-Patch by fn_k = |dot| of the two "
     "faces' normals, and a tetrahedron's faces meet at |dot| = 1/3, so a third of the N-Patch's fold is kept. "
     "That is why the final patch is rougher here than the intermediate one, which ignores fn (22.3 degrees, "
     "fig-1.1.7b), and likewise on the octahedron (|dot| = 1/3: 18.6 against 0.04 degrees) and the icosahedron "
     "(|dot| = 0.75: 12.2 against 2.4). The blend is made for meshes like the cube, whose neighbours meet at "
     "|dot| = 0 (fully smoothed) or 1 (coplanar: the N-Patch, no valley).",
     CMD_SINGLE(V_1_1_1B, "fig-1.1.1b"), true, fig_1_1_1b, 0},
    {"fig-1.1.1c", "fig-1.1.1", GRUEN "1.1.1c", "A cube refined using the original N-Patch.",
     "The welded built-in cube (12 triangles, averaged corner normals) as N-Patches at level 16: creases along "
     "the cube's edges, 50.2 degrees at worst.",
     CMD_SINGLE(V_1_1_1C, "fig-1.1.1c"), true, fig_1_1_1c, 0},
    {"fig-1.1.1d", "fig-1.1.1", GRUEN "1.1.1d", "A cube refined using the new N-Patch.",
     "The cube of fig-1.1.1c with the final smoothed patch: 9.2 degrees at worst and 2.1 on average across the "
     "cube's 12 edges, 0.28 across the 6 face diagonals (instess smoothness; its mean over all 18 shared edges, "
     "1.44, counts the diagonals too).",
     CMD_SINGLE(V_1_1_1D, "fig-1.1.1d"), true, fig_1_1_1d, 0},
    {"fig-1.1.7a", "fig-1.1.7", GRUEN "1.1.7a", "A tetrahedron refined using the original N-Patch.",
     "The tetrahedron as N-Patches at level 16, looking straight at one edge (yaw 0, pitch 0) and lit from the "
     "upper right (--light 0.3,0.3,-1), so the two faces differ in brightness: the crease is the sharp diagonal "
     "step between them. (Under the headlight both sides turn away from the camera alike and the step vanishes.)",
     CMD_SINGLE(V_1_1_7A, "fig-1.1.7a"), true, fig_1_1_7a, 0},
    {"fig-1.1.7b", "fig-1.1.7", GRUEN "1.1.7b", "A tetrahedron refined using the new intermediate patch.",
     "Same edge, same light, with the intermediate patch of Listing 1.1.1 (smooth-initial: the Gregory blend of "
     "P0, P1, P2): the step becomes a gradient, 22.3 degrees at worst where the N-Patch had 93.3.",
     CMD_SINGLE(V_1_1_7B, "fig-1.1.7b"), true, fig_1_1_7b, 0},
    {"fig-1.1.8a", "fig-1.1.8", GRUEN "1.1.8a", "Refined cube showing smooth edges where cube faces meet.",
     "The welded cube with the intermediate patch at level 12 and its wireframe, looking at the vertical edge "
     "between two faces (yaw 45, pitch 0): smooth where the faces meet, while the wireframe already bends along "
     "the face diagonals.",
     CMD_SINGLE(V_1_1_8A, "fig-1.1.8a"), true, fig_1_1_8a, 0},
    {"fig-1.1.8b", "fig-1.1.8", GRUEN "1.1.8b",
     "Refined cube showing ridges along the coplanar triangles that form the faces of the cube.",
     "The intermediate patch at level 32, straight at a face, under a light grazing it from the upper right "
     "(--light grazing: towards (0.62, 0.62, -0.48), ambient 0.08): the valley along the diagonal shared by the "
     "face's two coplanar triangles, where the normals of the two sides differ by 22.3 degrees. Gruen's caption "
     "calls them ridges, his text a valley; the normals settle it: on both sides of the diagonal they lean towards "
     "it (by up to 21.8 degrees apart within 1/16 of the way to the opposite corners), and the diagonal lies below "
     "its sides -- a concave fold, a valley (docs/smoothness.md).",
     CMD_SINGLE(V_1_1_8B, "fig-1.1.8b"), true, fig_1_1_8b, 0},
    {"fig-1.1.10a", "fig-1.1.10", GRUEN "1.1.10a", "A cube refined using the original N-Patch.",
     "The welded cube as N-Patches at level 16, seen from above left (yaw -35, pitch 30): no valleys on the faces "
     "(coplanar neighbours share their border curve), creases along the edges.",
     CMD_SINGLE(V_1_1_10A, "fig-1.1.10a"), true, fig_1_1_10a, 0},
    {"fig-1.1.10b", "fig-1.1.10", GRUEN "1.1.10b", "A cube refined using the final new patch.",
     "The final patch in that view: the cube's edges are smooth, and coplanar neighbours (fn = 1) keep the "
     "N-Patch along their shared diagonal, where the normals of the two sides differ by only 0.28 degrees. But "
     "the faces are not quite free of valleys: beside each diagonal the other two edges' patches P_k still bend "
     "the surface, and within a few pixels of it the normals of the two sides lean towards each other by up to "
     "5.3 degrees (instess smoothness, 'max valley'). The soft band this leaves along the diagonal is faint under "
     "the headlight and plain under a grazing light (the view of fig-1.1.8b with --patch smooth).",
     CMD_SINGLE(V_1_1_10B, "fig-1.1.10b"), true, fig_1_1_10b, 0},
    {"fig-patches", NULL, "Comparison added by instess (no figure of the documents): every patch on one mesh",
     "Flat, N-Patch, intermediate and final smoothed patch, Phong tessellation and PN-AEN on the same cube.",
     "Six panels of 320x320 on the view of fig-1.1.1c, each labelled with its largest crease across an edge as "
     "tess_smoothness measures it. Phong tessellation (Boubekeur and Alexa 2008, alpha 0.75) bulges most and "
     "creases like the N-Patch across the cube's edges, and it is the only patch besides the intermediate one "
     "that also folds across the face diagonals (19.6 degrees). PN-AEN equals the N-Patch here: the welded "
     "cube's neighbours already agree on their normals.",
     CMD_COMPOSITE("fig-patches", PANEL(1, V_PATCHES " --patch flat", "320x320")
                   PANEL(2, V_PATCHES " --patch npatch", "320x320") PANEL(3, V_PATCHES " --patch smooth-initial",
                   "320x320") PANEL(4, V_PATCHES " --patch smooth", "320x320")
                   PANEL(5, V_PATCHES " --patch phong", "320x320") PANEL(6, V_PATCHES " --patch pn-aen", "320x320")),
     true, fig_patches, 0},
    {"fig-listing-shading", NULL, "Companion of Gruen's Figures 1.1.1, 1.1.7, 1.1.8 and 1.1.10 (added by instess)",
     "The renderings above as Gruen's listing shades them.",
     "Each panel is the view of its figure at 200x200, shaded by the listing's own normal: normalize(b0 n0 + b1 "
     "n1 + b2 n2) interpolated from the corners (--normals linear, D3D9's default). The shape changes the "
     "silhouette only: the creases of the N-Patch and the valleys of the intermediate patch do not show in the "
     "shading, which is why the figures above light the derivative normals.",
     "instess figures --only fig-listing-shading --out DIR\n"
     "each panel: its figure's Reproduce line with --normals linear --size 200x200", true, fig_000_listing, 0},
    {"fig-001-1", NULL, VVB "Figure 1",
     "From left to right, the input triangulation, the model, and the curved point-normal model, colored according "
     "to its normals. The model was taken from Vlachos et al. [Vla+01].",
     "The built-in icosahedron (20 triangles; a stand-in for Vlachos' model), yaw 20, pitch 15: the input "
     "triangles (flat patch, level 1, wireframe overlay); PN triangles (npatch, quadratic normals, level 12) "
     "under the listing's headlight; the same PN model coloured by its world-space unit normal, RGB = 0.5 + 0.5 "
     "(x, y, -z) (--light normals).",
     CMD_COMPOSITE("fig-001-1", PANEL(1, V_001_1 " --patch flat --normals linear --level 1 --fill solid+wire", "320x320")
                   PANEL(2, V_001_1 " --patch npatch --normals quadratic --level 12", "320x320")
                   PANEL(3, V_001_1 " --patch npatch --normals quadratic --level 12 --light normals", "320x320")),
     true, fig_001_1, 1},
    {"fig-001-5", NULL, VVB "Figure 5",
     "Illustration of what would happen if one renders a model using point-normal triangles where vertices have "
     "different normals, depending on the associated faces. Image taken from [MK10].",
     "The built-in cylinder (12 sides; its rim vertices are split: radial normals for the side, axial ones for "
     "the caps), level 8, linear normals, seen from above. Left: the N-Patch; the side's rim curve bulges along "
     "the arc while the cap's stays the chord, so the surface opens along the top rim and the background shows "
     "through (back faces are culled). Middle: PN-AEN (McDonald and Kilgard, the fix [MK10] proposes) on the same "
     "mesh: closed. Right: one angle-weighted normal per welded position (--recompute-normals): closed but "
     "rounded into a blob. (cube-split is no example: its per-face normals are the face normals, so every "
     "N-Patch stays flat and nothing opens.)",
     CMD_COMPOSITE("fig-001-5", PANEL(1, V_001_5 " --patch npatch", "320x320")
                   PANEL(2, V_001_5 " --patch pn-aen", "320x320")
                   PANEL(3, V_001_5 " --patch npatch --recompute-normals", "320x320")),
     true, fig_001_5, 1},
    {"fig-md2-seams", NULL, RTR "the text under Figure 6 (it has no figure)",
     "Also worth knowing is that cracks will appear if two adjacent triangles do not share the same normals.",
     "sydney.md2 (679 triangles, 482 vertices at 342 positions), N-Patches at level 4, linear normals, seen from "
     "her left side (yaw 180). Left: normals computed per unwelded vertex (angle-weighted over the triangles "
     "using that exact vertex index), so the copies of a vertex on the two sides of a texture seam get different "
     "normals and the surface cracks along the seams (the dark lines). Right: the same normals per welded "
     "position: closed.",
     CMD_COMPOSITE("fig-md2-seams", "panel 1: no command line equivalent (normals per unwelded vertex)\n"
                   PANEL(2, V_SEAMS " --recompute-normals", "320x520")),
     true, fig_md2_seams, 1},
    {"fig-001-12", NULL, VVB "Figure 12",
     "A family of game characters from the game Quake 1. (a), (b) and (c) are rendered on a CPU by Vlachos et al. "
     "(d), (e), (f) are rendered by our implementation.",
     "Stand-ins: the MD2 characters faerie.md2 (654 triangles) and sydney.md2 (679), with the files' normals, "
     "seen from the front (yaw 90, pitch 0). Top: the input triangles (flat patch, Gouraud-shaded). Middle: PN "
     "triangles (npatch, quadratic normals, level 4 = 16 triangles each). Bottom: Gruen's final smoothed patch "
     "at the same level (its boundary and non-manifold edges fall back to the N-Patch).",
     CMD_COMPOSITE("fig-001-12", PANEL(1, "--mesh " FAERIE " --patch flat --normals linear --level 1 " V_MD2, "240x400")
                   PANEL(2, "--mesh " SYDNEY " --patch flat --normals linear --level 1 " V_MD2, "240x400")
                   PANEL(3, "--mesh " FAERIE " --patch npatch --normals quadratic --level 4 " V_MD2, "240x400")
                   PANEL(4, "--mesh " SYDNEY " --patch npatch --normals quadratic --level 4 " V_MD2, "240x400")
                   PANEL(5, "--mesh " FAERIE " --patch smooth --normals quadratic --level 4 " V_MD2, "240x400")
                   PANEL(6, "--mesh " SYDNEY " --patch smooth --normals quadratic --level 4 " V_MD2, "240x400")),
     true, fig_001_12, 1},
    {"fig-001-fake-vs-real", NULL, VVB "sections 3.2 and 5.1 (the draft has no figure: 'Show results of PN "
                                       "triangles with fake and real normals, and discuss differences')",
     "'Fake' normals (quadratic normal patch) versus 'real' normals (cross product of the partial derivatives of "
     "the geometric component).",
     "The welded cube as N-Patches at level 16: shaded with Vlachos' quadratic ('fake') normals, with the "
     "derivative ('real') normals, and the angle between the two per pixel as a heat map from 0 (black) to 45 "
     "degrees (pale yellow). The real normals crease along the cube's edges, where the N-Patch is only C0; the "
     "fake ones stay smooth.",
     CMD_COMPOSITE("fig-001-fake-vs-real", PANEL(1, V_FAKE_REAL " --normals quadratic", "320x320")
                   PANEL(2, V_FAKE_REAL " --normals real", "320x320")
                   "panel 3: computed from the normal AOVs of panels 1 and 2 (instess --aov normal, EXR)\n"),
     true, fig_001_fake_vs_real, 1},
    {"fig-003-3", NULL, RTR "Figure 3",
     "The columns show different levels of detail of the same model. The original triangle data, consisting of "
     "414 triangles, is shown on the left. The middle model has 3,726 triangles, while the right has 20,286 "
     "triangles, all generated with the presented algorithm. Note how the silhouette and the shading improves. "
     "The bottom rows show the models in wireframe, which reveals that each original triangle generates the same "
     "amount of subtriangles. (Model courtesy of id Software. Image from ATI Technologies Inc. demo.)",
     "sydney.md2 (679 triangles; stand-in for the id Software model) as N-Patches with quadratic normals at "
     "LOD 0, 2, 6 = levels 1, 3, 7 = x1, x9, x49 triangles (679, 6111, 33271); top row shaded, bottom row "
     "wireframe (--fill wire).",
     CMD_COMPOSITE("fig-003-3", PANEL(1, V_003_3 " --level 1", "300x520") PANEL(2, V_003_3 " --level 3", "300x520")
                   PANEL(3, V_003_3 " --level 7", "300x520") PANEL(4, V_003_3 " --level 1 --fill wire", "300x520")
                   PANEL(5, V_003_3 " --level 3 --fill wire", "300x520")
                   PANEL(6, V_003_3 " --level 7 --fill wire", "300x520")),
     true, fig_003_3, 2},
    {"fig-lod", NULL, "instess: adaptive level of detail through instancing (after Dyken, Reimers and Seland, "
     "Semi-uniform adaptive patch tessellation, 2009, and NVIDIA's screen-space rule, GDC 2011)",
     "The same mesh near and far: one tessellation level for every triangle, and a level per mesh edge from its "
     "projected length, drawn as D3D9 would -- one instanced DrawIndexedPrimitive per refinement pattern.",
     "The built-in sphere (80 triangles) with Gruen's final smoothed patch and real normals, yaw 30, pitch 20, at "
     "distance 3 (top) and 8 (bottom), 2x2 panels of 320x320 with 4x MSAA, solid with the wireframe coloured by "
     "level (blue 1, green 8, red 64; per bucket, its finest level). Left: uniform level 16 (every edge at 16: "
     "--lod distance --min-level 16 --max-level 16, the regular grid). Right: --lod screen --max-level 16 "
     "--lod-target 8 (8 pixels per segment of each edge's projected control polygon; patterns of the sorted "
     "edge levels, semi-uniform). Each label gives the triangles tessellated. Options: " V_LOD ".",
     CMD_COMPOSITE("fig-lod", PANEL(1, V_LOD V_LOD_NEAR V_LOD_UNIFORM, "320x320")
                   PANEL(2, V_LOD V_LOD_NEAR V_LOD_SCREEN, "320x320") PANEL(3, V_LOD V_LOD_FAR V_LOD_UNIFORM, "320x320")
                   PANEL(4, V_LOD V_LOD_FAR V_LOD_SCREEN, "320x320")),
     true, fig_lod, 3},
    {"fig-displace", NULL, "instess: displacement mapping on the patches by vertex texture fetch (Shader Model 3's "
     "tex2Dlod in the vertex shader, D3DVERTEXTEXTURESAMPLER0)",
     "The N-Patch and Gruen's smoothed patch on the same mesh, each displaced along its normal by a height that the "
     "vertex shader fetches from a texture at the patch's texture coordinates.",
     "The welded cube (planar texture coordinates u = (x + 1) / 2, v = (1 - y) / 2: one per vertex, continuous "
     "across every edge) at level 32, yaw 35, pitch 25, lit from the upper right (--light grazing). Top: the "
     "patches as they are, shaded with their real normals: the N-Patch's creases along the cube's edges, the "
     "smoothed patch's soft ones. Bottom: displaced by " BUMPS " (64x64 grey, a 4x4 lattice of round bumps; "
     "tests/data/textures/make_bumps.py writes it) with --displace-scale 0.1: every vertex moves 0.1 bounding "
     "radii times the fetched height (0..1, linear filtered, wrapping) along its linear normal, and the panel is "
     "shaded with the normal of the displaced surface (the displaced patch at three nearby points of the "
     "triangle, cli/run/displace.c; with no height it is the real normal of the top row). The front face (z = "
     "-1) holds the whole map; the side faces see one row or column of it, stretched. Texture coordinates and "
     "linear normals agree bitwise on every shared edge, so the displaced surface has no crack "
     "(tests/test_displace_cracks.c).",
     CMD_COMPOSITE("fig-displace", PANEL(1, V_DISPLACE " --patch npatch" V_UNDISPLACED, "320x320")
                   PANEL(2, V_DISPLACE " --patch smooth" V_UNDISPLACED, "320x320")
                   PANEL(3, V_DISPLACE " --patch npatch" V_DISPLACE_MAP, "320x320")
                   PANEL(4, V_DISPLACE " --patch smooth" V_DISPLACE_MAP, "320x320")),
     true, fig_displace, 3},
    {"fig-shading", NULL, "instess: the N-Patch's creases and the smoothed patch, lit per vertex and per pixel",
     "The same patches lit where the listings light them (each grid vertex, the colour interpolated) and at every "
     "pixel by a pixel shader.",
     "The welded cube at level 4 (16 triangles per face: the light's interpolation is visible), yaw 35, pitch 25, "
     "real normals, lit from the upper right (--light grazing). Top: --shading vertex, the listings' Gouraud "
     "shading: between grid points the colour is interpolated and the N-Patch's creases along the cube's edges "
     "blur into bands. Bottom: --shading pixel: a pixel shader evaluates the patch's own derivative normal at "
     "each pixel's barycentrics (the grid point's interpolated perspective-correct) and lights it, so the "
     "N-Patch's crease is a sharp line and the smoothed patch's surface reads as it is: its valley along the face "
     "diagonal shows, and along the cube's edges a dotted line where pixels whose barycentrics round onto the edge "
     "take the edge's one-sided normal (vs.h: real normals on an edge are each side's own) "
     "(cli/run/shading.c; tests/test_shading.c checks pixels against the normal evaluated at the inspector's "
     "barycentrics).",
     CMD_COMPOSITE("fig-shading", PANEL(1, V_SHADE " --patch npatch --shading vertex", "320x320")
                   PANEL(2, V_SHADE " --patch smooth --shading vertex", "320x320")
                   PANEL(3, V_SHADE " --patch npatch --shading pixel", "320x320")
                   PANEL(4, V_SHADE " --patch smooth --shading pixel", "320x320")),
     true, fig_shading, 3},
    {"fig-textured", NULL, "instess: the characters of fig-001-12 with their skins (a texture read in a pixel shader)",
     "The MD2 characters of assimp's test models, each with its skin: input, PN triangles, smoothed N-Patch.",
     "faerie.md2 and sydney.md2 (assimp's test models) with faerie2.bmp and sydney.bmp, --texture: a pixel "
     "shader multiplies the light by the skin at the mesh's texture coordinates (mip-mapped, trilinear, the level "
     "of detail from each 2x2 quad's derivatives), white surface colour, quadratic normals, level 4 for the "
     "patches, seen from the side as fig-001-12. The skins are continuous where the texture coordinates are: "
     "along the MD2 texture seams the patches of the two sides take different texels (fig-md2-seams counts "
     "the cracks the seams open in the surface itself).",
     CMD_COMPOSITE("fig-textured", PANEL(1, "--mesh " FAERIE " --texture " MD2_DIR "faerie2.bmp --patch flat --level 1"
                                            V_SKIN, "240x400")
                   PANEL(3, "--mesh " FAERIE " --texture " MD2_DIR "faerie2.bmp --patch npatch --level 4" V_SKIN,
                         "240x400")
                   PANEL(5, "--mesh " FAERIE " --texture " MD2_DIR "faerie2.bmp --patch smooth --level 4" V_SKIN,
                         "240x400")),
     true, fig_textured, 3},
    {"fig-step", NULL, "instess: tessellation through instancing, one instance at a time",
     "The smoothed patch's draw cut after 1, 2, 4, 6, 9 and 12 instances: each instance is one mesh triangle, "
     "the same grid stamped over it.",
     "The cube (12 triangles) at level 4, culling off (the dark faces are the patches' insides, turned away from "
     "the light), solid with its wireframe; --instances N sets the instanced draw's count (SetStreamSourceFreq(0, INDEXEDDATA | N)), so only the first N mesh triangles' "
     "patches are drawn: stream 0's grid (15 points, 16 triangles) is the same for every instance, stream 1 "
     "moves it onto the next mesh triangle. instess view plays this live (the X key), and the inspector (the I "
     "key, instess inspect) shows for any pixel which instance and grid triangle drew it.",
     CMD_COMPOSITE("fig-step", PANEL(1, V_STEP " --instances 1", "160x160") PANEL(6, V_STEP " --instances 12",
                                                                                 "160x160")),
     true, fig_step, 3},
    {NULL, NULL, NULL, NULL, NULL, NULL, false, NULL, 0}};
