/* cli/main.c -- the `instess` program: option parsing and exit codes.  The rendering is in cli/scene.c.
 *
 * Exit codes: 0 success (image written atomically), 1 input error (names the input, nothing written),
 * 2 usage error (message on stderr). */
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"

/* The usage text; the patch names come from the patch table (vs/vs.h). */
static const char usage_fmt[] =
    "usage: instess [OPTION]... [MESH] -o FILE.png|FILE.exr\n"
    "       instess figures [--out DIR] [--only ID[,ID...]] [--small] [--threads N] [--list]\n"
    "       instess smoothness [--samples N]\n"
    "Render one mesh tessellated through instancing, as Direct3D 9 did, on the CPU.\n"
    "\n"
    "  MESH, --mesh NAME|FILE  the mesh: a built-in (tetrahedron, cube, cube-split, octahedron, icosahedron,\n"
    "                       sphere, cylinder) or a file assimp reads (OBJ, PLY, OFF, STL, MD2, glTF...)  [cube]\n"
    "  --patch P            %-68s[smooth]\n"
    "  --normals N          linear | quadratic | real                                           [linear]\n"
    "  --level N            tessellation level (fractional with the pg-* grids)                 [8]\n"
    "  --grid G             regular | pg-equal | pg-fractional-odd | pg-fractional-even          [regular]\n"
    "  --path P             instanced | npatch-mode | cpu (the last two: N-Patch or flat only)   [instanced]\n"
    "  --size WxH           image size in pixels                                                 [512x512]\n"
    "  --yaw DEG --pitch DEG  rotation of the object                                            [30, 20]\n"
    "  --distance D         camera distance in units of the mesh's bounding radius              [3.2]\n"
    "  --fill F             solid | wire | solid+wire | point                                   [solid]\n"
    "  --msaa 1|4           samples per pixel                                                    [4]\n"
    "  --threads N          threads (0: all cores; the image does not depend on it)              [0]\n"
    "  --recompute-normals  ignore the file's normals and recompute them (angle-weighted)\n"
    "  --max-memory MIB     the memory a render may take, checked before it starts           [4096]\n"
    "  --max-file-size MIB  the largest mesh file (with the files it refers to) read          [256]\n"
    "  --max-import-memory MIB  memory for the mesh import (default: by the files' size)\n"
    "  --aov LIST           EXR only: extra channels, comma-separated: normal,bary,instance,gregory\n"
    "  --export-obj FILE    also write the tessellated surface as OBJ (object space)\n"
    "  -o, --output FILE    the image: .png (8-bit RGBA) or .exr (RGBA half + Z float + AOVs)\n"
    "  -q, --quiet          no statistics on stderr\n"
    "  -h, --help           this text       -V, --version   the version\n";

/* Print the usage text to f. */
static void print_usage(FILE *f)
{
    char names[256];
    fprintf(f, usage_fmt, vs_patch_names(" | ", names, sizeof names));
}

/* Print msg and the usage hint; exit code 2. */
static int usage_error(const char *msg, const char *arg)
{
    fprintf(stderr, "instess: %s%s%s\nTry 'instess --help'.\n", msg, arg ? ": " : "", arg ? arg : "");
    return 2;
}

enum {
    OPT_MESH = 256, OPT_PATCH, OPT_NORMALS, OPT_LEVEL, OPT_GRID, OPT_PATH, OPT_SIZE, OPT_YAW, OPT_PITCH,
    OPT_DISTANCE, OPT_FILL, OPT_MSAA, OPT_THREADS, OPT_AOV, OPT_EXPORT_OBJ, OPT_RECOMPUTE, OPT_MAX_MEMORY,
    OPT_MAX_FILE_SIZE, OPT_MAX_IMPORT_MEMORY
};

static const struct option long_opts[] = {
    {"mesh", required_argument, 0, OPT_MESH},       {"patch", required_argument, 0, OPT_PATCH},
    {"normals", required_argument, 0, OPT_NORMALS}, {"level", required_argument, 0, OPT_LEVEL},
    {"grid", required_argument, 0, OPT_GRID},       {"path", required_argument, 0, OPT_PATH},
    {"size", required_argument, 0, OPT_SIZE},       {"yaw", required_argument, 0, OPT_YAW},
    {"pitch", required_argument, 0, OPT_PITCH},     {"distance", required_argument, 0, OPT_DISTANCE},
    {"fill", required_argument, 0, OPT_FILL},       {"msaa", required_argument, 0, OPT_MSAA},
    {"threads", required_argument, 0, OPT_THREADS}, {"aov", required_argument, 0, OPT_AOV},
    {"export-obj", required_argument, 0, OPT_EXPORT_OBJ},
    {"recompute-normals", no_argument, 0, OPT_RECOMPUTE},
    {"max-memory", required_argument, 0, OPT_MAX_MEMORY},
    {"max-file-size", required_argument, 0, OPT_MAX_FILE_SIZE},
    {"max-import-memory", required_argument, 0, OPT_MAX_IMPORT_MEMORY},
    {"output", required_argument, 0, 'o'},          {"quiet", no_argument, 0, 'q'},
    {"help", no_argument, 0, 'h'},                  {"version", no_argument, 0, 'V'},
    {0, 0, 0, 0}};

/* The usage error of a choice option whose value is unknown, naming the valid ones, into buf; buf. */
static const char *unknown_choice(int c, char *buf, size_t len)
{
    char names[256];
    const char *opt = c == OPT_PATCH ? "--patch" : c == OPT_NORMALS ? "--normals" : c == OPT_GRID ? "--grid"
                      : c == OPT_PATH ? "--path" : "--fill";
    if (c == OPT_PATCH) vs_patch_names(" | ", names, sizeof names);
    else if (c == OPT_NORMALS) snprintf(names, sizeof names, "%s | %s | %s", vs_normals_name(VS_NORMALS_LINEAR),
                                        vs_normals_name(VS_NORMALS_QUADRATIC), vs_normals_name(VS_NORMALS_REAL));
    else scene_join_names(c == OPT_GRID ? scene_grid_names : c == OPT_PATH ? scene_path_names : scene_fill_names,
                          " | ", names, sizeof names);
    snprintf(buf, len, "unknown %s (one of: %s)", opt, names);
    return buf;
}

/* Apply one option to opts; returns NULL or the text of a usage error (in buf when it is built). */
static const char *apply_option(scene_opts *o, int c, const char *arg, char *buf, size_t len)
{
    switch (c) {
    case OPT_MESH: o->mesh = arg; return NULL;
    case OPT_PATCH: return scene_parse_patch(arg, &o->patch) ? NULL : unknown_choice(c, buf, len);
    case OPT_NORMALS: return scene_parse_normals(arg, &o->normals) ? NULL : unknown_choice(c, buf, len);
    case OPT_LEVEL: return scene_parse_float(arg, 1.0f, SCENE_MAX_LEVEL, &o->level) ? NULL : SCENE_LEVEL_MSG;
    case OPT_GRID: return scene_parse_grid(arg, &o->grid) ? NULL : unknown_choice(c, buf, len);
    case OPT_PATH: return scene_parse_path(arg, &o->path) ? NULL : unknown_choice(c, buf, len);
    case OPT_SIZE: return scene_parse_size(arg, &o->width, &o->height) ? NULL : SCENE_SIZE_MSG;
    case OPT_YAW: return scene_parse_float(arg, -1e6f, 1e6f, &o->yaw) ? NULL : "--yaw needs a number of degrees";
    case OPT_PITCH: return scene_parse_float(arg, -1e6f, 1e6f, &o->pitch) ? NULL : "--pitch needs a number of degrees";
    case OPT_DISTANCE:
        return scene_parse_float(arg, 1.01f, 1000.0f, &o->distance) ? NULL : "--distance must be 1.01..1000";
    case OPT_FILL: return scene_parse_fill(arg, &o->fill) ? NULL : unknown_choice(c, buf, len);
    case OPT_MSAA: return scene_parse_msaa(arg, &o->msaa) ? NULL : "--msaa must be 1 or 4";
    case OPT_THREADS: return scene_parse_int(arg, 0, 256, &o->threads) ? NULL : "--threads must be 0..256";
    case OPT_AOV: return scene_parse_aovs(arg, &o->aovs) ? NULL : "--aov takes normal,bary,instance,gregory";
    case OPT_EXPORT_OBJ: o->export_obj = arg; return NULL;
    case OPT_RECOMPUTE: o->recompute_normals = true; return NULL;
    case OPT_MAX_MEMORY: {
        int mib;
        if (!scene_parse_int(arg, 16, 1 << 20, &mib)) return "--max-memory takes MiB, 16..1048576";
        o->max_memory_mib = (unsigned)mib;
        return NULL;
    }
    case OPT_MAX_FILE_SIZE: {
        int mib;
        if (!scene_parse_int(arg, 1, 1 << 20, &mib)) return "--max-file-size takes MiB, 1..1048576";
        o->max_file_mib = (unsigned)mib;
        return NULL;
    }
    case OPT_MAX_IMPORT_MEMORY: {
        int mib;
        if (!scene_parse_int(arg, 16, 1 << 20, &mib)) return "--max-import-memory takes MiB, 16..1048576";
        o->max_import_memory_mib = (unsigned)mib;
        return NULL;
    }
    case 'o': o->output = arg; return NULL;
    case 'q': o->quiet = true; return NULL;
    default: return "unknown option";
    }
}


/* A primitive-generator grid takes levels in a narrower range than --level: say so on stderr (also with -q)
 * and render the level it will use. */
static void warn_level_clamp(scene_opts *o)
{
    if (o->grid == CORE_GRID_REGULAR) return;
    float used = core_grid_pg_clamp(o->grid, o->level);
    if (used == o->level) return;
    fprintf(stderr, "instess: warning: --level %g is outside the range of --grid %s; rendering level %g\n",
            (double)o->level, scene_grid_name(o->grid), (double)used);
    o->level = used;
}

/* Render one image from the options. */
static int cmd_render(int argc, char **argv)
{
    scene_opts o;
    scene_opts_default(&o);
    int c;
    bool mesh_given = false;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "o:qhV", long_opts, NULL)) != -1) {
        if (c == 'h') return print_usage(stdout), 0;
        if (c == 'V') return printf("instess %s\n", INSTESS_VERSION), 0;
        if (c == '?') return usage_error("unknown option or missing value", argv[optind - 1]);
        char buf[400];
        const char *msg = apply_option(&o, c, optarg, buf, sizeof buf);
        if (msg) return usage_error(msg, optarg);
        mesh_given |= c == OPT_MESH;
    }
    if (optind < argc && !mesh_given) o.mesh = argv[optind++];   /* instess MESH -o OUT */
    if (optind < argc) return usage_error(mesh_given ? "unexpected argument (the mesh is given by --mesh)"
                                                     : "unexpected argument", argv[optind]);
    if (!o.output) return usage_error("no output file (-o FILE.png or FILE.exr)", NULL);
    const char *msg = scene_check_opts(&o);
    if (msg) return usage_error(msg, NULL);
    if (o.export_obj && outputs_same_target(o.output, o.export_obj))
        return usage_error("-o and --export-obj name the same file", o.output);
    warn_level_clamp(&o);
    char err[1024];
    if (scene_render_to_file(&o, err, sizeof err) != 0) {
        fprintf(stderr, "instess: %s\n", err);
        return 1;
    }
    return 0;
}

/* SIGTERM, SIGINT, SIGHUP, SIGQUIT, SIGXCPU: remove the temporary files of the outputs being written
 * (outputs_remove_temp_files is async-signal-safe; the names live in core/output.c's static slots, the one
 * accepted exception to "no globals"), then die of the same signal with its default action, so the caller sees
 * how the program ended.  The targets are never partial in any case (rename). */
static void on_signal(int sig)
{
    outputs_remove_temp_files();
    signal(sig, SIG_DFL);
    raise(sig);
}

/* Install on_signal for the termination signals that are not ignored (nohup keeps SIGHUP ignored), and ignore
 * SIGXFSZ so that a file size limit (`ulimit -f`) makes write(2) fail with EFBIG: an error with a message and
 * the temporaries removed, instead of a death that leaves them behind. */
static void install_signal_handlers(void)
{
    static const int sigs[] = {SIGTERM, SIGINT, SIGHUP, SIGQUIT, SIGXCPU};
    for (size_t k = 0; k < sizeof sigs / sizeof sigs[0]; k++) {
        struct sigaction old, sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sigemptyset(&sa.sa_mask);
        if (sigaction(sigs[k], NULL, &old) == 0 && old.sa_handler != SIG_IGN) sigaction(sigs[k], &sa, NULL);
    }
    signal(SIGXFSZ, SIG_IGN);
}

int main(int argc, char **argv)
{
    install_signal_handlers();
    if (argc < 2) {   /* no arguments: the usage, as a usage error */
        print_usage(stderr);
        fputs("\ninstess: no arguments: `instess MESH -o FILE.png` renders a mesh\n", stderr);
        return 2;
    }
    if (argc > 1 && strcmp(argv[1], "figures") == 0) return scene_cmd_figures(argc - 1, argv + 1);
    if (argc > 1 && strcmp(argv[1], "smoothness") == 0) return scene_cmd_smoothness(argc - 1, argv + 1);
    return cmd_render(argc, argv);
}
