/* cli/figures/figures.h -- the figures of the three source documents (docs/design.md, section 5): one table entry per figure,
 * rendered by `instess figures` (cli/figures/figures.c) into out/<id>.png (+ .exr for renderings) and out/index.html, and
 * by tests/test_figures.c at a small size against golden images.
 *
 * Conventions: a figure's render function fills an image (allocated by it with image_alloc: "R,G,B,A" for diagrams;
 * "R,G,B,A,Z,N.X,N.Y,N.Z" for renderings, where Z and N come from an AOV pass of the main view) and returns 0, or
 * -1 with a message in err.  The image is a picture (cli/run/scene.h): display values over the scene's default
 * background, A the coverage (0 on the background of a composite, 1 for diagrams); the files are written by
 * scene_write_picture, the writer of `instess -o`, so a figure's PNG and EXR hold what that command's do (the
 * golden images are the PNG's form).  It must be deterministic (same bytes for any thread count) and use only the
 * project's device for drawing (lines, points, triangles) and image_draw_text for labels (printable ASCII only:
 * write "b0", "alpha").  `small` asks for the test size: the same picture at about 1/4 of the pixels (goldens stay
 * small).  No globals except the const tables. */
#ifndef INSTESS_FIGURES_H
#define INSTESS_FIGURES_H

#include <stdbool.h>

#include "../run/scene.h"

typedef struct fig_ctx {
    bool small;   /* test size */
    int threads;  /* threads for each render (0: all cores) */
    /* Optional out (NULL: not asked): a single rendering sets these to what `instess -o` stores as the
     * description of its PNG and of its EXR with the normal AOV (scene_describe_file of the figure's view,
     * malloc'd: the caller frees them); composites and diagrams leave them as they are. */
    char **describe_png, **describe_exr;
} fig_ctx;

typedef int (*fig_fn)(const fig_ctx *ctx, is_image *out, char *err, size_t errlen);

/* One view of a figure: spec is render options as the command takes them ("--mesh cube --patch npatch ..."),
 * rendered at w x h through scene_render_view (as the command renders) into img (allocated: R, G, B, A, Z, N.X,
 * N.Y, N.Z); 0 or -1 with a message. */
int fig_render_spec(const fig_ctx *ctx, const char *spec, int w, int h, is_image *img, char *err, size_t errlen);

typedef struct figure {
    const char *id;        /* "fig-1.1.1a" (docs/design.md, section 5) */
    const char *group;     /* figures shown side by side share a group ("fig-1.1.1"); NULL: alone */
    const char *source;    /* "Gruen, Smoothed N-Patches (seed 000), Figure 1.1.1a" */
    const char *caption;   /* the document's caption, as printed (OCR fixed) */
    const char *shows;     /* what the image shows and how it was made (mesh, patch, level, view, samples) */
    const char *command;   /* how to reproduce it: a single rendering's `instess ...` command (the same pixels,
                              tests/test_figures.c runs it); for a composite `instess figures --only ID --out DIR`
                              and one line "panel K: instess ... -o panelK.png" per panel that has a command (its
                              pixels are in the figure unchanged); for a diagram `instess figures --only ID
                              --out DIR` alone */
    bool rendering;        /* a rendering of a surface: also written as .exr with Z and N.X, N.Y, N.Z */
    fig_fn render;
    int section;           /* the gallery section: the document it reproduces (0: seed 000, 1: 001, 2: 003), or 3:
                              beyond the documents (adaptive level of detail) */
} figure;
#define FIG_SECTIONS 4

/* The two tables, each ended by an entry with id == NULL.  A figure is one row: adding one is a row here and its
 * render function (README, "Extending instess"); the gallery orders them by section, then by id. */
extern const figure fig_renders[];   /* cli/figures/fig_renders.c: surfaces of meshes (Figs 1.1.1, 1.1.7, 1.1.8, ...) */
extern const figure fig_diagrams[];  /* cli/figures/fig_diagrams.c: the explanatory drawings (Figs 1.1.2-1.1.6, ...) */

/* Where to find the document's own figure that f reproduces (the documents' figures are not shown: their
 * copyright is not the project's): "Figure N of <the document's citation>" into buf (returned), or NULL when f
 * reproduces no figure of a document (a comparison, a companion, a figure the text describes but does not
 * have, or section 3).  A reproduction's source ends in ", Figure N". */
const char *fig_original(const figure *f, char *buf, size_t len);

/* ---- a small drawing kit for diagrams and labels (cli/figures/canvas.c) ---- */
typedef struct fig_canvas fig_canvas;
/* A w x h canvas with 4x MSAA, background colour bg (RGBA in [0,1]); a 2D coordinate frame maps
 * [x0, x1] x [y0, y1] (y up) onto the image with equal scale on both axes and a margin. */
fig_canvas *canvas_create(int w, int h, const float bg[4], float x0, float y0, float x1, float y1, char *err,
                          size_t errlen);
void canvas_destroy(fig_canvas *c);
/* Primitives in frame coordinates (z ignored: later draws are on top), colours RGBA in [0,1]. */
void canvas_line(fig_canvas *c, float2 a, float2 b, float width_px, const float rgba[4]);
void canvas_dashed_line(fig_canvas *c, float2 a, float2 b, float width_px, float dash_px, const float rgba[4]);
void canvas_arrow(fig_canvas *c, float2 a, float2 b, float width_px, const float rgba[4]);
void canvas_point(fig_canvas *c, float2 p, float radius_px, const float rgba[4]);
void canvas_triangle(fig_canvas *c, float2 a, float2 b, float2 d, const float rgba[4]);
/* Text with its baseline's left end at p shifted by (dx, dy) pixels (image_draw_text's font). */
void canvas_text(fig_canvas *c, float2 p, float dx, float dy, const char *text, float size_px, const float rgba[4]);
/* A 3D view: project a point through the canvas's matrix set by canvas_set_view (world*view*proj, as scene). */
void canvas_set_view(fig_canvas *c, const float4x4 *wvp);
float2 canvas_project(const fig_canvas *c, float3 p);
/* Resolve into img (allocated "R,G,B,A"); 0 or -1. */
int canvas_finish(fig_canvas *c, is_image *img, char *err, size_t errlen);

#endif
