/* cli/run/manpage.c -- the manual page instess.1, written by `instess --man` from the tables that also make the
 * program's usage texts: the render options (scene_options, cli/run/options.c, which --help prints), the
 * subcommands with their synopses, options and exit codes (cli/run/main.c), compare's options (cli/run/compare.c).
 * Nothing here lists an option: a new row of a table is in --help and in the page at once. */
#include "scene.h"

#include <string.h>

/* text into f as roff running text: backslashes and hyphens escaped, a leading '.' or '\'' made literal. */
static void roff(FILE *f, const char *text)
{
    bool line_start = true;
    for (const char *p = text; *p; p++) {
        if (line_start && (*p == '.' || *p == '\'')) fputs("\\&", f);
        if (*p == '\\') fputs("\\e", f);
        else if (*p == '-') fputs("\\-", f);
        else fputc(*p, f);
        line_start = *p == '\n';
    }
}

/* One option's tag line (.TP, then "-o, --output FILE" in bold with the value in italics) into f. */
static void option_tag(FILE *f, int short_name, const char *name, const char *metavar)
{
    fputs(".TP\n", f);
    if (short_name) fprintf(f, "\\fB\\-%c\\fR, ", short_name);
    fputs("\\fB\\-\\-", f);
    roff(f, name);
    fputs("\\fR", f);
    if (metavar) {
        fputs(" \\fI", f);
        roff(f, metavar);
        fputs("\\fR", f);
    }
    fputc('\n', f);
}

/* The render options of scene_options, with their choices and defaults as --help shows them, then --help,
 * --version and --man. */
static void man_options(FILE *f)
{
    fputs(".SH OPTIONS\nThe options of a render (the first form of the synopsis).\n", f);
    for (size_t k = 0; k < scene_option_count; k++) {
        const scene_option *o = &scene_options[k];
        char names[512] = "";
        option_tag(f, o->short_name, o->name, o->metavar);
        roff(f, o->help);
        fputs(".\n", f);
        if (o->choices) {
            o->choices(", ", names, sizeof names);
            fputs("One of: ", f);
            roff(f, names);
            fputs(".\n", f);
        }
        if (o->deflt) {
            fputs("Default: ", f);
            roff(f, o->deflt);
            fputs(".\n", f);
        }
    }
    option_tag(f, 'h', "help", NULL);
    fputs("The usage text, every option with its choices and default.\n", f);
    option_tag(f, 'V', "version", NULL);
    fputs("The version, the libraries it was built with and the rasterizer kernels this CPU runs (avx2 or avx512: the "
          "same bytes either way).\n", f);
    option_tag(f, 0, "man", NULL);
    fputs("This manual page, as roff, on standard output (the Makefile installs it as instess.1).\n", f);
}

/* Each subcommand: its synopsis, what it does, its options and its exit codes. */
static void man_subcommands(FILE *f, const scene_subcommand *subs, size_t n)
{
    fputs(".SH SUBCOMMANDS\n", f);
    for (size_t k = 0; k < n; k++) {
        fprintf(f, ".SS instess %s\n.B instess %s\n", subs[k].name, subs[k].name);
        roff(f, subs[k].synopsis);
        fputs("\n.PP\n", f);
        roff(f, subs[k].summary);
        fputc('\n', f);
        for (const scene_subopt *o = subs[k].options; o && o->name; o++) {
            option_tag(f, 0, o->name, o->metavar);
            roff(f, o->help);
            fputs(".\n", f);
        }
    }
}

/* The exit codes of a render, then of each subcommand that has its own. */
static void man_exit_status(FILE *f, const char *render_codes, const scene_subcommand *subs, size_t n)
{
    fputs(".SH EXIT STATUS\nA render: ", f);
    roff(f, render_codes);
    fputc('\n', f);
    for (size_t k = 0; k < n; k++)
        if (subs[k].exit_codes) {
            fprintf(f, ".PP\n\\fBinstess %s\\fR: ", subs[k].name);
            roff(f, subs[k].exit_codes);
            fputc('\n', f);
        }
}

/* Examples: commands that work as written with the built-in meshes. */
static void man_examples(FILE *f)
{
    static const char *const ex[][2] = {
        {"instess --mesh cube --patch npatch --level 6 -o cube.png", "The cube as an N-Patch (PN triangles)."},
        {"instess model.obj --patch smooth --size 1024x768 --stats json -o model.png",
         "A mesh file with Gruen's smoothed patch; the statistics as JSON on standard output."},
        {"instess icosahedron --grid pg-fractional-odd --level 3.4 --aov normal,bary -o ico.exr",
         "A fractional level on the primitive generator's grid, with normals and barycentrics as EXR channels."},
        {"instess compare actual.png golden.png --fail 0.004 --failpercent 0.1 --diff diff.png",
         "A pixel-diff test: passes when at most 0.1% of the pixels differ by more than 1/255."},
        {"instess figures --out out", "Every figure of the source documents, with out/index.html."},
    };
    fputs(".SH EXAMPLES\n", f);
    for (size_t k = 0; k < sizeof ex / sizeof ex[0]; k++) {
        fputs(".TP\n.B ", f);
        roff(f, ex[k][0]);
        fputc('\n', f);
        roff(f, ex[k][1]);
        fputc('\n', f);
    }
}

/* Files and environment. */
static void man_files(FILE *f)
{
    fputs(".SH FILES\n.TP\n", f);
    roff(f, image_codec_install_dir());
    fputs("/libinstess_codec.so\nThe image codec (OpenImageIO), loaded on the first EXR read or written or text; "
          "PNG is written and read through libpng, without it.  Also looked "
          "for beside the program and in ../lib/instess.\n"
          ".TP\n/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf\nThe font of the figures' labels.\n"
          ".SH ENVIRONMENT\n.TP\nINSTESS_CODEC_DIR\nA folder (an absolute path) to look for libinstess_codec.so in first.\n"
          ".TP\nSOURCE_DATE_EPOCH\nWhen set, the time stored in images; otherwise none is stored, so one render "
          "always writes the same bytes.\n.TP\nOMP_WAIT_POLICY\nSet it to passive on a machine where other "
          "processes need the cores.\n", f);
}

void scene_print_man(FILE *f, const char *render_codes, const scene_subcommand *subs, size_t n)
{
    fprintf(f, ".TH INSTESS 1 \"\" \"instess %s\" \"User Commands\"\n.SH NAME\n", INSTESS_VERSION);
    fputs("instess \\- tessellation through instancing, as Direct3D 9 did it, on the CPU\n.SH SYNOPSIS\n"
          ".B instess\n[\\fIOPTION\\fR]... [\\fIMESH\\fR] \\fB\\-o\\fR \\fIFILE\\fR.png|\\fIFILE\\fR.exr\n", f);
    for (size_t k = 0; k < n; k++) {
        fprintf(f, ".br\n.B instess %s\n", subs[k].name);
        roff(f, subs[k].synopsis);
        fputc('\n', f);
    }
    fputs(".SH DESCRIPTION\ninstess renders a mesh tessellated through instancing (Gruen's technique): the "
          "barycentric grid of one triangle is drawn once per mesh triangle with SetStreamSourceFreq on a software "
          "device modelled on IDirect3DDevice9, and a vertex shader turns each grid point into a point of a curved "
          "patch (N-Patch / PN triangles, Gruen's smoothed N-Patch, Phong tessellation, PN-AEN).  The image is "
          "written atomically: a failed run leaves no output.  The same renderer is the library libinstess "
          "(pkg-config instess).\n.PP\nA mesh file's own texture -- its material's diffuse texture when it lies in "
          "the mesh's folder, or for an MD2 model that names no skin the image beside it of the skin's size (the "
          "skins of assimp's test models faerie.md2 and sydney.md2) -- is drawn as \\fB\\-\\-texture\\fR would "
          "draw it, and a line on standard error (not with \\fB\\-q\\fR) names it; \\fB\\-\\-texture\\fR "
          "\\fIFILE\\fR draws another, \\fB\\-\\-texture none\\fR none.  A texture the file names that cannot "
          "be used (missing, outside the folder, embedded in the file) is a warning, and the mesh is drawn "
          "untextured.  A texture on a mesh without texture coordinates (every vertex's at (0, 0)) shows one "
          "texel's colour: a warning says so, also with \\fB\\-q\\fR.\n", f);
    man_options(f);
    man_subcommands(f, subs, n);
    man_exit_status(f, render_codes, subs, n);
    man_examples(f);
    man_files(f);
    fputs(".SH SEE ALSO\n.BR pkg-config (1),\n.BR oiiotool (1)\n", f);
}
