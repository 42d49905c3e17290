/* cli/figures/figures.c -- `instess figures`: every figure of the three source documents (docs/design.md, section 5) into
 * DIR/<id>.png (+ DIR/<id>.exr with Z and N for renderings) and the gallery DIR/index.html (a table of contents and
 * the figures whose images are in DIR: those of this run and of earlier runs into the same folder).
 *
 * One process renders all figures (OpenImageIO's start-up is paid once), in parallel over figures with OpenMP
 * (each figure's own renders then run on one thread; a lone figure gets all of them -- the bytes are the same
 * either way, the device is deterministic).  A progress line per figure goes to stderr.  A failing figure is
 * reported by id with its message, the others are still rendered, and the command exits 1.  Usage errors
 * (unknown option or id) exit 2.  Every file is written atomically. */
#include <errno.h>
#include <omp.h>
#include <ctype.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "figures.h"

#include "../../core/hlsl.h"
static const char figures_usage[] =
    "usage: instess figures [--out DIR] [--only ID[,ID...]] [--small] [--threads N]\n"
    "Render every figure of the source documents into DIR (default out): ID.png, ID.exr (renderings: RGBA, Z,\n"
    "N.X, N.Y, N.Z) and the gallery DIR/index.html, which lists the figures whose images are in DIR.\n"
    "\n"
    "  --out DIR      output directory (created if missing)                       [out]\n"
    "  --only IDS     only these figures (comma-separated ids, e.g. fig-1.1.1a,fig-003-3; `viewer`: the\n"
    "                 frame of instess view the whole gallery shows, viewer.png)\n"
    "  --small        the test size (about 1/4 of the pixels)\n"
    "  --threads N    threads (0: all cores; the images do not depend on it)       [0]\n"
    "  --list         print the figure ids and exit\n"
    "  -h, --help     this text\n";

/* The gallery's sections, indexed by figure.section: the document, and what holds for all its figures (said
 * once here, not in every caption). */
static const char *const section_titles[FIG_SECTIONS] = {
    "H. Gruen, Smoothed N-Patches",
    "R. van Veen and L. Baakman, A Discussion of Curved Point-Normal Triangles",
    "T. Akenine-Moller and E. Haines, Bezier Triangles and N-Patches (Real-Time Rendering)",
    "Beyond the documents: adaptive level of detail through instancing"};
static const char *const section_intros[FIG_SECTIONS] = {
    "Gruen compares the N-Patch with his smoothed patches on a tetrahedron and a cube. The renderings are 512x512 "
    "with 4x MSAA and light the derivative ('real') normals of each patch with the listing's diffuse term "
    "saturate(dot(N, L)), L = (0, 0, -1), a headlight, unless a caption names another light. With the listing's "
    "own interpolated normals every curved patch shades alike and the creases and valleys the article discusses "
    "do not show (fig-listing-shading puts those images side by side). The angles quoted are the largest angles "
    "between the surface normals on the two sides of a shared edge, as instess smoothness measures them.",
    "The draft discusses PN triangles, their normals and the OpenGL 4 tessellator. Renderings use the listing's "
    "headlight on the normals the caption names. The MD2 characters are the Irrlicht models of Debian's "
    "assimp-testmodels package, standing in for the models of the draft, which are not available.",
    "The book's section explains the N-Patch's control points and its quadratic normals.",
    "What none of the documents shows: a level per mesh edge, drawn the instancing way with one instanced draw "
    "per refinement pattern, crack-free by construction."};

/* Where each document's own figures are found (fig_original), by section; NULL: no document. */
static const char *const section_originals[FIG_SECTIONS] = {
    "H. Gruen, \"Smoothed N-Patches\", article 1.1 of ShaderX5: Advanced Rendering Techniques, W. Engel (ed.), "
    "Charles River Media, 2006",
    "R. van Veen and L. E. N. Baakman, \"A Discussion of Curved Point-Normal Triangles\", a draft of the "
    "Computing Science Department, University of Groningen (not published; the figure numbers are the draft's)",
    "T. Akenine-Moller and E. Haines, \"Bezier Triangles and N-Patches\", Gamasutra, 15 July 2002, an excerpt of "
    "Real-Time Rendering, 2nd edition, A K Peters, 2002 (the figure numbers are the excerpt's)",
    NULL};

const char *fig_original(const figure *f, char *buf, size_t len)
{
    const char *fig = strstr(f->source, ", Figure ");
    if (!fig || f->section < 0 || f->section >= FIG_SECTIONS || !section_originals[f->section]) return NULL;
    snprintf(buf, len, "Figure %s of %s", fig + strlen(", Figure "), section_originals[f->section]);
    return buf;
}

#define MAX_FIGURES 128

/* The options of the command. */
typedef struct figures_opts {
    const char *out;
    const char *only;  /* NULL: all */
    bool small, list;
    int threads;
} figures_opts;

/* What happened to one figure. */
typedef struct fig_result {
    int rc;            /* 0 written, -1 failed */
    double seconds;
    char err[768];
} fig_result;

/* ---------------------------------------- the figure list ---------------------------------------- */

/* Both tables, in table order, into list; returns the count. */
static size_t all_figures(const figure **list, size_t cap)
{
    size_t n = 0;
    const figure *const tables[2] = {fig_renders, fig_diagrams};
    for (int t = 0; t < 2; t++)
        for (const figure *f = tables[t]; f->id && n < cap; f++) list[n++] = f;
    return n;
}

/* The figure with this id among list[0..n-1], or NULL. */
static const figure *find_figure(const figure *const *list, size_t n, const char *id, size_t len)
{
    for (size_t k = 0; k < n; k++)
        if (strlen(list[k]->id) == len && strncmp(list[k]->id, id, len) == 0) return list[k];
    return NULL;
}

/* The pseudo-id of --only that asks for the viewer's frame (viewer.png; every whole run makes it). */
#define VIEWER_ID "viewer"

/* Keep the figures named in `only` (comma-separated; VIEWER_ID is not a figure) in table order; returns the
 * count or -1 (unknown id, printed). */
static long select_figures(const figure **list, size_t n, const char *only)
{
    if (!only) return (long)n;
    bool keep[MAX_FIGURES] = {0};
    for (const char *p = only;; p++) {   /* every item, an empty one before, between or after commas too */
        size_t len = strcspn(p, ",");
        if (len == 0) {
            fprintf(stderr, "instess: figures: --only has an empty id in '%s' (ids are separated by single commas)\n",
                    only);
            return -1;
        }
        bool viewer = len == strlen(VIEWER_ID) && strncmp(p, VIEWER_ID, len) == 0;
        const figure *f = viewer ? NULL : find_figure(list, n, p, len);
        if (!f && !viewer) {
            fprintf(stderr, "instess: figures: unknown figure id '%.*s' (instess figures --list shows them)\n",
                    (int)len, p);
            return -1;
        }
        for (size_t k = 0; f && k < n; k++) keep[k] |= list[k] == f;
        p += len;
        if (!*p) break;
    }
    size_t m = 0;
    for (size_t k = 0; k < n; k++)
        if (keep[k]) list[m++] = list[k];
    return (long)m;
}

/* ---------------------------------------- options ---------------------------------------- */

/* Print msg and the usage hint; 2. */
static int figures_usage_error(const char *msg, const char *arg)
{
    fprintf(stderr, "instess: figures: %s%s%s\nTry 'instess figures --help'.\n", msg, arg ? ": " : "",
            arg ? arg : "");
    return 2;
}

/* The value of option `name` at argv[*i] ("--name V" or "--name=V"), advancing *i; NULL if not this option. */
static const char *option_value(int argc, char **argv, int *i, const char *name, bool *missing)
{
    size_t n = strlen(name);
    if (strncmp(argv[*i], name, n) != 0) return NULL;
    if (argv[*i][n] == '=') return argv[*i] + n + 1;
    if (argv[*i][n] != 0) return NULL;
    if (*i + 1 >= argc) return *missing = true, NULL;
    return argv[++*i];
}

/* Parse argv (argv[0] = "figures"); -1 to go on, else the exit code. */
static int parse_figures_args(int argc, char **argv, figures_opts *o)
{
    *o = (figures_opts){.out = "out"};
    for (int i = 1; i < argc; i++) {
        bool missing = false;
        const char *v;
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) return fputs(figures_usage, stdout), 0;
        if (!strcmp(argv[i], "--small")) o->small = true;
        else if (!strcmp(argv[i], "--list")) o->list = true;
        else if ((v = option_value(argc, argv, &i, "--out", &missing))) o->out = v;
        else if ((v = option_value(argc, argv, &i, "--only", &missing))) o->only = v;
        else if ((v = option_value(argc, argv, &i, "--threads", &missing))) {
            if (!scene_parse_int(v, 0, 256, &o->threads)) return figures_usage_error("--threads must be 0..256", v);
        } else return figures_usage_error(missing ? "missing value" : "unknown option or argument", argv[i]);
        if (missing) return figures_usage_error("missing value", argv[i]);
    }
    if (!*o->out) return figures_usage_error("--out needs a directory", NULL);
    if (o->only && !*o->only) return figures_usage_error("--only needs figure ids", NULL);
    return -1;
}

/* mkdir -p dir; 0 or -1 with a message on stderr. */
static int make_dirs(const char *dir)
{
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", dir);
    for (char *p = buf + 1;; p++) {
        char c = *p;
        if (c != '/' && c != 0) continue;
        *p = 0;
        if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
            fprintf(stderr, "instess: figures: %s: cannot create the directory: %s\n", buf, strerror(errno));
            return -1;
        }
        *p = c;
        if (!c) break;
    }
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        fprintf(stderr, "instess: figures: %s: not a directory\n", dir);
        return -1;
    }
    return 0;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* ---------------------------------------- rendering ---------------------------------------- */

/* The scene's default background, which every figure's picture is rendered over. */
static uint32_t default_background(void)
{
    scene_opts o;
    scene_opts_default(&o);
    return o.background;
}

/* Write picture img of figure f as DIR/<id>.png (and .exr for renderings) through scene_write_picture, both or
 * neither; the descriptions are those `instess -o` stores for a single rendering (ctx's), else the command. */
static int write_figure(const figure *f, const fig_ctx *ctx, const is_image *img, const char *dir, char *err,
                        size_t errlen)
{
    char png[4096], exr[4096];
    snprintf(png, sizeof png, "%s/%s.png", dir, f->id);
    snprintf(exr, sizeof exr, "%s/%s.exr", dir, f->id);
    is_image_meta mp = {"instess " INSTESS_VERSION, *ctx->describe_png ? *ctx->describe_png : f->command};
    is_image_meta me = {"instess " INSTESS_VERSION, *ctx->describe_exr ? *ctx->describe_exr : f->command};
    is_outputs outs;
    outputs_init(&outs);
    uint32_t bg = default_background();
    int rc = outputs_add(&outs, png, err, errlen) == 0 ? 0 : -1;
    if (rc == 0 && f->rendering && outputs_add(&outs, exr, err, errlen) != 1) rc = -1;
    if (rc == 0) rc = scene_write_picture(&outs, 0, img, bg, &mp, err, errlen);
    if (rc == 0 && f->rendering) rc = scene_write_picture(&outs, 1, img, bg, &me, err, errlen);
    if (rc == 0) rc = outputs_commit(&outs, err, errlen);
    outputs_abort(&outs);
    return rc;
}

/* Render figure f and write its files into DIR atomically; the outcome into *res. */
static void render_figure(const figure *f, const fig_ctx *shared, const char *dir, fig_result *res)
{
    double t0 = now_s();
    is_image img = {0};
    char *png_desc = NULL, *exr_desc = NULL;
    fig_ctx ctx = *shared;
    ctx.describe_png = &png_desc, ctx.describe_exr = &exr_desc;
    res->rc = f->render(&ctx, &img, res->err, sizeof res->err);
    if (res->rc == 0) res->rc = write_figure(f, &ctx, &img, dir, res->err, sizeof res->err);
    free(png_desc);
    free(exr_desc);
    if (res->rc != 0 && !res->err[0]) snprintf(res->err, sizeof res->err, "failed without a message");
    image_free(&img);
    res->seconds = now_s() - t0;
}

/* Render list[0..n-1] in parallel over figures on `threads` threads, a progress line per figure; returns the
 * number of failures. */
static int render_all(const figure *const *list, size_t n, const figures_opts *o, int threads, fig_result *res)
{
    fig_ctx ctx = {.small = o->small, .threads = n == 1 ? threads : 1};
    size_t done = 0;
    int failed = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (long k = 0; k < (long)n; k++) {
        render_figure(list[k], &ctx, o->out, &res[k]);
#pragma omp critical(figures_progress)
        {
            done++;
            if (res[k].rc == 0)
                fprintf(stderr, "instess: figures: [%2zu/%zu] %-22s %6.2f s -> %s/%s.png%s\n", done, n, list[k]->id,
                        res[k].seconds, o->out, list[k]->id, list[k]->rendering ? " + .exr" : "");
            else {
                failed++;
                fprintf(stderr, "instess: figures: [%2zu/%zu] %-22s FAILED: %s\n", done, n, list[k]->id, res[k].err);
            }
        }
    }
    return failed;
}

/* ---------------------------------------- the gallery ---------------------------------------- */

/* Write s with &, <, >, " escaped. */
static void html_text(FILE *f, const char *s)
{
    for (; s && *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f);
        }
    }
}

/* A Reproduce command as HTML text, each "instess " that starts a command (at the start, or after "panel K: ")
 * written as "build/instess ": the program as a clone has it after make (installed, it is plain instess). */
static void html_command(FILE *f, const char *cmd)
{
    for (const char *s = cmd; s && *s;) {
        const char *line_end = strchr(s, '\n'), *colon = strstr(s, ": instess ");
        const char *start = strncmp(s, "instess ", 8) == 0 ? s
                            : strncmp(s, "panel ", 6) == 0 && colon && (!line_end || colon < line_end) ? colon + 2
                            : NULL;
        size_t len = line_end ? (size_t)(line_end - s) + 1 : strlen(s);
        char line[2048];
        snprintf(line, sizeof line, "%.*s%s%.*s", start ? (int)(start - s) : 0, s, start ? "build/" : "",
                 (int)(len - (start ? (size_t)(start - s) : 0)), start ? start : s);
        html_text(f, line);
        s += len;
    }
}

static const char gallery_css[] =
    "body{margin:0;padding:24px 32px;font:15px/1.45 system-ui,-apple-system,'Segoe UI',sans-serif;"
    "background:#f4f4f1;color:#222}\n"
    "h1{font-size:26px;margin:0 0 4px}h2{font-size:20px;margin:36px 0 12px;padding-bottom:4px;"
    "border-bottom:2px solid #cfcfc8}\n"
    "p.lead{max-width:72em;color:#444}\n"
    ".group{display:flex;flex-wrap:wrap;gap:16px;align-items:flex-start;margin:0 0 20px}\n"
    "figure{margin:0;flex:1 1 0;min-width:260px;max-width:100%;background:#fff;border:1px solid #d6d6d0;"
    "border-radius:6px;padding:10px;box-sizing:border-box}\n"
    "figure.wide{flex:1 1 100%}\n"
    "figure.wide img{max-width:min(100%,1000px)}\n"
    "figure img{display:block;max-width:100%;height:auto;margin:0 auto 8px}\n"
    "nav.toc{background:#fff;border:1px solid #d6d6d0;border-radius:6px;padding:8px 16px;max-width:72em}\n"
    "nav.toc ol{margin:4px 0;padding-left:1.4em}nav.toc li{margin:3px 0}\n"
    "nav.toc a.fig{font-family:ui-monospace,monospace;font-size:13px;margin-right:8px;white-space:nowrap}\n"
    ".kind{color:#666;font-size:12px;border:1px solid #ccc;border-radius:3px;padding:0 4px;margin-left:4px}\n"
    "p.intro{max-width:72em;color:#333}\n"
    "figcaption .id{font-weight:700;font-family:ui-monospace,monospace}\n"
    "figcaption .src{color:#666;font-size:13px}\n"
    "figcaption blockquote{margin:6px 0;padding:2px 0 2px 10px;border-left:3px solid #b9b9ae;font-style:italic}\n"
    "figcaption p{margin:6px 0}\n"
    "code{display:block;white-space:pre-wrap;word-break:break-all;background:#f0f0ea;padding:4px 6px;"
    "border-radius:3px;font:12px/1.4 ui-monospace,monospace}\n"
    ".fail{color:#a00;font-weight:700}\n";

/* strcmp, except that runs of digits compare by their value ("fig-1.1.9" < "fig-1.1.10"), digits before other
 * characters. */
static int natural_cmp(const char *a, const char *b)
{
    while (*a && *b) {
        bool da = isdigit((unsigned char)*a), db = isdigit((unsigned char)*b);
        if (da && db) {
            char *ea, *eb;
            unsigned long x = strtoul(a, &ea, 10), y = strtoul(b, &eb, 10);
            if (x != y) return x < y ? -1 : 1;
            a = ea, b = eb;
        } else if (da != db) {
            return da ? -1 : 1;
        } else {
            if (*a != *b) return (unsigned char)*a < (unsigned char)*b ? -1 : 1;
            a++, b++;
        }
    }
    return (unsigned char)*a - (unsigned char)*b;
}

/* The result of figure f in this run, or NULL if it was not rendered now. */
static const fig_result *result_of(const figure *f, const figure *const *sel, size_t n_sel, const fig_result *res)
{
    for (size_t k = 0; k < n_sel; k++)
        if (sel[k] == f) return &res[k];
    return NULL;
}

/* Whether DIR/<id><ext> exists. */
static bool file_there(const char *dir, const char *id, const char *ext)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s%s", dir, id, ext);
    return access(path, F_OK) == 0;
}

/* Whether the gallery shows figure f: its image is in the directory, or it failed in this run (then the page
 * says so).  A figure neither rendered now nor left by an earlier run is not mentioned. */
static bool shown(const char *dir, const figure *f, const fig_result *r)
{
    return file_there(dir, f->id, ".png") || (r && r->rc != 0);
}

/* What kind of entry f is, for its badge: a single rendering, a composite of renderings, or a diagram. */
static const char *kind_of(const figure *f)
{
    if (!f->rendering) return "diagram";
    return strncmp(f->command, "instess figures", 15) == 0 ? "composite" : "rendering";
}

/* One <figure> of the gallery (the image only when its file is there). */
static void html_figure(FILE *f, const char *dir, const figure *fg, const fig_result *r)
{
    fprintf(f, "<figure id=\"%s\"%s>\n", fg->id, fg->group ? "" : " class=\"wide\"");
    if (file_there(dir, fg->id, ".png")) {
        fprintf(f, "<a href=\"%s.png\"><img src=\"%s.png\" alt=\"", fg->id, fg->id);
        html_text(f, fg->id);
        fputs("\" loading=\"lazy\"></a>\n", f);
    }
    fputs("<figcaption>\n<span class=\"id\">", f);
    html_text(f, fg->id);
    fprintf(f, "</span><span class=\"kind\">%s</span>", kind_of(fg));
    if (fg->rendering && file_there(dir, fg->id, ".exr"))
        fprintf(f, "<span class=\"kind\"><a href=\"%s.exr\">EXR</a></span>", fg->id);
    fputs("<br><span class=\"src\">", f);
    html_text(f, fg->source);
    fputs("</span>\n", f);
    char orig[600];
    if (fig_original(fg, orig, sizeof orig)) {
        fputs("<br><span class=\"src\">The original (not shown here): ", f);
        html_text(f, orig);
        fputs("</span>\n", f);
    }
    fputs("<blockquote>", f);
    html_text(f, fg->caption);
    fputs("</blockquote>\n<p>", f);
    html_text(f, fg->shows);
    fputs("</p>\n<p><b>Reproduce</b> (in the repository after <code>make</code>):</p><code>", f);
    html_command(f, fg->command);
    fputs("</code>\n", f);
    if (r && r->rc != 0) {
        fputs("<p class=\"fail\">Rendering failed in the last run: ", f);
        html_text(f, r->err);
        fputs("</p>\n", f);
    }
    fputs("</figcaption>\n</figure>\n", f);
}

/* Sort all[0..n-1] into gallery order: by section, then by id with numbers in order (insertion sort). */
static void gallery_sort(const figure **all, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        const figure *x = all[i];
        size_t j = i;
        for (; j > 0; j--) {
            const figure *y = all[j - 1];
            if (y->section < x->section || (y->section == x->section && natural_cmp(y->id, x->id) <= 0)) break;
            all[j] = y;
        }
        all[j] = x;
    }
}

/* The table of contents: each section with links to its figures (all[0..n-1], the shown ones, in order), then
 * the viewer's section when live. */
static void html_toc(FILE *f, const figure **all, size_t n, bool live)
{
    fputs("<nav class=\"toc\"><b>Contents</b>\n<ol>\n", f);
    for (size_t k = 0; k < n; k++) {
        int s = all[k]->section;
        if (k == 0 || all[k - 1]->section != s) fprintf(f, "<li><a href=\"#section-%d\">%s</a><br>\n", s,
                                                        section_titles[s]);
        fprintf(f, "<a class=\"fig\" href=\"#%s\">%s</a>\n", all[k]->id, all[k]->id);
        if (k + 1 == n || all[k + 1]->section != s) fputs("</li>\n", f);
    }
    if (live) fputs("<li><a href=\"#live\">Explore it live: instess view</a></li>\n", f);
    fputs("<li><a href=\"#browser\">The tutorial in the browser</a></li>\n", f);
    fputs("</ol>\n</nav>\n", f);
}

/* The body of the gallery: sections with their introductions, figures of one group side by side. */
static void html_body(FILE *f, const char *dir, const figure **all, size_t n, const figure *const *sel,
                      size_t n_sel, const fig_result *res)
{
    int section = -1;
    for (size_t k = 0; k < n;) {
        int s = all[k]->section;
        if (s != section) {
            fprintf(f, "<h2 id=\"section-%d\">%s</h2>\n<p class=\"intro\">", s, section_titles[s]);
            html_text(f, section_intros[s]);
            fputs("</p>\n", f);
            section = s;
        }
        size_t end = k + 1;
        while (all[k]->group && end < n && all[end]->group && !strcmp(all[end]->group, all[k]->group)) end++;
        fputs("<div class=\"group\">\n", f);
        for (; k < end; k++) html_figure(f, dir, all[k], result_of(all[k], sel, n_sel, res));
        fputs("</div>\n", f);
    }
}

/* The viewer's section of the gallery, when DIR/viewer.png is there (capture_viewer). */
static void html_viewer(FILE *f, const char *dir)
{
    if (!file_there(dir, "viewer", ".png")) return;
    fputs("<h2 id=\"live\">Explore it live: instess view</h2>\n<p class=\"intro\">The same renders in an SDL2 "
          "window: the mouse orbits and zooms, keys change the level, patch, normals, grid, path, fill, "
          "multisampling and level of detail, Tab splits the screen between two patches. This frame was made "
          "headless by <code>SDL_VIDEODRIVER=dummy instess view --normals real --size 960x540 --keys "
          "Tab,Left,Right --capture viewer.png</code>: the smoothed patch (left) beside the N-Patch (right) on "
          "the cube, with the HUD.</p>\n<div class=\"group\"><figure><img src=\"viewer.png\" "
          "alt=\"instess view, split screen with the HUD\" width=\"960\" height=\"540\"></figure></div>\n", f);
}

/* The link to the tutorial in the browser (make web writes it beside the gallery, out/web/index.html: its own
 * target, so that make figures stays as fast), saying whether it is there yet. */
static void html_browser(FILE *f, const char *dir)
{
    fputs("<h2 id=\"browser\">The tutorial in the browser</h2>\n<p class=\"intro\"><a href=\"web/index.html\">"
          "web/index.html</a>: the README's tutorial with live controls (mesh, an OBJ file of your own, patch, level, "
          "normals, level of detail, split view), rendered by instess compiled to WebAssembly, in any browser, "
          "without a server: the same pixels as the program, and the command line that reproduces each frame.", f);
    if (!file_there(dir, "web/index", ".html"))
        fputs(" Not built in this folder yet: <code>make web</code> writes it to out/web/index.html.", f);
    fputs("</p>\n", f);
}

/* Whether the comma-separated list only names VIEWER_ID. */
static bool wants_viewer(const char *only)
{
    for (const char *p = only; *p;) {
        size_t len = strcspn(p, ",");
        if (len == strlen(VIEWER_ID) && strncmp(p, VIEWER_ID, len) == 0) return true;
        p += len + (p[len] == ',');
    }
    return false;
}

extern char **environ;

/* The viewer's frame for the gallery into DIR/viewer.png: this program's own executable run as `instess view`
 * headless (SDL's dummy driver), as the README's picture is made.  0, or -1 with the reason on stderr (the
 * gallery then has no viewer section). */
static int capture_viewer(const char *dir)
{
    char out[4096];
    snprintf(out, sizeof out, "%s/viewer.png", dir);
    char *args[] = {"instess", "view", "-q", "--normals", "real", "--size", "960x540", "--keys", "Tab,Left,Right",
                    "--capture", out, NULL};
    size_t n_env = 0;
    while (environ[n_env]) n_env++;
    char **env = calloc(n_env + 2, sizeof *env);
    if (!env) return -1;
    size_t k = 0;
    for (size_t i = 0; i < n_env; i++)
        if (strncmp(environ[i], "SDL_VIDEODRIVER=", 16) != 0) env[k++] = environ[i];
    env[k++] = "SDL_VIDEODRIVER=dummy";
    pid_t pid;
    int st = 0, rc = posix_spawn(&pid, "/proc/self/exe", NULL, NULL, args, env);
    free(env);
    if (rc == 0 && waitpid(pid, &st, 0) < 0) rc = errno;
    if (rc != 0 || !WIFEXITED(st) || WEXITSTATUS(st) != 0) {
        fprintf(stderr, "instess: figures: warning: the viewer's frame (instess view) could not be made%s%s; the "
                        "gallery has no viewer section\n", rc ? ": " : "", rc ? strerror(rc) : "");
        return -1;
    }
    return 0;
}

static const char gallery_lead[] =
    "The figures of three documents on curved triangle patches, rendered on the CPU by instess %s: tessellation "
    "through instancing on a device modelled on Direct3D 9. Each entry names its document and figure number, "
    "says where to find the document's own figure (not shown here: every image is instess's), "
    "quotes the document's caption, says what the image shows and gives the command that reproduces it: a "
    "rendering's command gives the same pixels; a composite lists the command of each panel (the labels are "
    "added by instess figures); a diagram is drawn by instess figures from the project's own formulas and has no "
    "render command of its own. Renderings also come as OpenEXR files with depth (Z) and normal (N.X, N.Y, N.Z) "
    "channels, written as instess -o writes an EXR: linear colour premultiplied by the coverage A, the background "
    "transparent (a single rendering's EXR is the file its Reproduce line writes with --aov normal and an .exr "
    "name). The commands are written as run in a clone of the repository after make (build/instess); after "
    "make install the program is instess. This page lists the figures whose images are in its folder; "
    "build/instess figures --out DIR writes them all (make figures in the repository).";

/* Write DIR/index.html as an output of the run (cli/run/outputs.h: never through a link or onto a FIFO, a random
 * temporary renamed when complete); 0 or -1 with a message on stderr. */
static int write_gallery(const char *dir, const figure *const *sel, size_t n_sel, const fig_result *res)
{
    const figure *all[MAX_FIGURES];
    size_t n_all = all_figures(all, MAX_FIGURES), n = 0;
    for (size_t k = 0; k < n_all; k++)
        if (shown(dir, all[k], result_of(all[k], sel, n_sel, res))) all[n++] = all[k];
    gallery_sort(all, n);
    char path[4096], err[1024];
    snprintf(path, sizeof path, "%s/index.html", dir);
    is_outputs outs;   /* the run's output rules: a regular file or nothing there, a random temporary, rename */
    outputs_init(&outs);
    int k = outputs_add(&outs, path, err, sizeof err);
    FILE *f = k < 0 ? NULL : outputs_stream(&outs, k, err, sizeof err);
    if (!f) {
        outputs_abort(&outs);
        return fprintf(stderr, "instess: figures: %s\n", err), -1;
    }
    fprintf(f, "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
               "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
               "<title>instess: the figures of the source documents</title>\n<style>\n%s</style>\n</head>\n<body>\n"
               "<h1>instess: the figures of the source documents</h1>\n<p class=\"lead\">", gallery_css);
    fprintf(f, gallery_lead, INSTESS_VERSION);
    fputs("</p>\n", f);
    html_toc(f, all, n, file_there(dir, "viewer", ".png"));
    html_body(f, dir, all, n, sel, n_sel, res);
    html_viewer(f, dir);
    html_browser(f, dir);
    fputs("</body>\n</html>\n", f);
    if (outputs_close_stream(&outs, k, f, err, sizeof err) != 0 || outputs_commit(&outs, err, sizeof err) != 0) {
        outputs_abort(&outs);
        return fprintf(stderr, "instess: figures: %s\n", err), -1;
    }
    return 0;
}

/* ---------------------------------------- the command ---------------------------------------- */

/* DIR/index.html can be written by the run's rules (a regular file or nothing there); 0, or -1 said on stderr. */
static int check_index(const char *dir)
{
    char path[4096], err[1024];
    snprintf(path, sizeof path, "%s/index.html", dir);
    is_outputs outs;
    outputs_init(&outs);
    int k = outputs_add(&outs, path, err, sizeof err);
    outputs_abort(&outs);
    if (k < 0) fprintf(stderr, "instess: figures: %s\n", err);
    return k < 0 ? -1 : 0;
}

int scene_cmd_figures(int argc, char **argv)
{
    figures_opts o;
    int rc = parse_figures_args(argc, argv, &o);
    if (rc >= 0) return rc;
    const figure *list[MAX_FIGURES];
    size_t n_all = all_figures(list, MAX_FIGURES);
    if (o.list) {
        for (size_t k = 0; k < n_all; k++) printf("%s\n", list[k]->id);
        return 0;
    }
    long n = select_figures(list, n_all, o.only);
    if (n < 0) return 2;
    if (make_dirs(o.out) != 0) return 1;
    if (check_index(o.out) != 0) return 1;   /* before any figure is rendered */
    int threads = o.threads > 0 ? o.threads : omp_get_num_procs();
    fig_result *res = calloc((size_t)n + 1, sizeof *res);
    if (!res) return fprintf(stderr, "instess: figures: out of memory\n"), 1;
    double t0 = now_s();
    int failed = render_all(list, (size_t)n, &o, threads, res);
    if (!o.only || wants_viewer(o.only)) capture_viewer(o.out);   /* the whole gallery shows the viewer too */
    int html = write_gallery(o.out, list, (size_t)n, res);
    fprintf(stderr, "instess: figures: %ld figure(s) in %.2f s on %d thread(s), %d failed -> %s/%s\n", n,
            now_s() - t0, threads, failed, o.out, html ? "(no index.html)" : "index.html");
    for (long k = 0; k < n; k++)
        if (res[k].rc != 0) fprintf(stderr, "instess: figures: %s: %s\n", list[k]->id, res[k].err);
    free(res);
    return failed || html ? 1 : 0;
}
