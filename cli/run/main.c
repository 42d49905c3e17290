/* cli/run/main.c -- the `instess` program: option parsing and exit codes.  The rendering is in cli/run/scene.c.
 *
 * Exit codes: render_exit_codes below (0 success, 1 input error, 2 usage error); compare's are its own. */
#include <omp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene.h"

#include <errno.h>
#include <fcntl.h>

/* The exit codes of a render (--help and the man page print this sentence; '\n' breaks the usage's line). */
static const char render_exit_codes[] =
    "0 success (the image written atomically),\n1 input error (the message names the input; nothing is written), "
    "2 usage error.";

/* The subcommands (one table: the dispatch, the usage text and the man page). */
static const scene_subcommand subcommands[] = {
    {"figures", scene_cmd_figures, "[--out DIR] [--only ID[,ID...]] [--small] [--threads N] [--list]",
     "Render every figure of the source documents into DIR (default out) with an index.html gallery; --only "
     "renders some, --small the test size, --list prints the ids.", NULL, NULL},
    {"smoothness", scene_cmd_smoothness, "[--samples N] [--mesh NAME|FILE]... [--recompute-normals]",
     "For every built-in mesh and patch, the angle between the surface normals on the two sides of each shared "
     "edge and the largest bulge, as a Markdown table.", NULL, NULL},
    {"compare", scene_cmd_compare, "A B [--diff FILE] [--fail T] [--failpercent P]",
     "Compare two image files as the golden tests do (OpenImageIO 2.4's comparison, computed without loading it): "
     "print the number of pixels, "
     "the largest difference with its pixel and channel, the mean difference and the count of failing pixels.",
     scene_compare_options,
     "0 identical or within the thresholds, 1 different, 2 usage error, 3 the sizes or channels differ, 4 an "
     "image cannot be read (or the diff image cannot be written)."},
    {"inspect", scene_cmd_inspect, "[OPTION]... [MESH] --pixel X,Y [--json]",
     "Render as -o would (one sample per pixel) and print the history of pixel X,Y through the draws: each fragment's "
     "draw, instance, grid triangle, stream registers, vertex shader values, barycentrics, depth test and colour "
     "(--json: as JSON).", NULL, NULL},
    {"view", scene_cmd_view, "[OPTION]... [MESH] [--keys LIST] [--frames N] [--capture FILE.png] [--no-hud]",
     "Open a window showing exactly what the same render options write with -o, re-rendered as keys and the mouse "
     "change them (instess view --help lists the keys); --keys, --frames and --capture script it without a "
     "display.", NULL, NULL},
};
enum { N_SUBCOMMANDS = sizeof subcommands / sizeof subcommands[0] };

/* Print the usage text to f: the synopses, then every render option from the option table (cli/run/options.c). */
static void print_usage(FILE *f)
{
    fputs("usage: instess [OPTION]... [MESH] -o FILE.png|FILE.exr\n", f);
    for (int k = 0; k < N_SUBCOMMANDS; k++) fprintf(f, "       instess %s %s\n", subcommands[k].name, subcommands[k].synopsis);
    fputs("Render one mesh tessellated through instancing, as Direct3D 9 did, on the CPU.\n\n", f);
    scene_print_options(f);
    fprintf(f, "%-28s%s\n\nExit status: %s\n", "  --man", "the manual page (roff) on stdout", render_exit_codes);
    fputs("instess compare has its own: see instess compare --help.\n", f);
}

/* The version, the libraries the program was built with (the image codec's by its build: --version does not
 * load OpenImageIO) and the rasterizer kernels this CPU runs into f. */
static void print_version(FILE *f)
{
    char mesh_libs[128];
    mesh_library_versions(mesh_libs, sizeof mesh_libs);
    fprintf(f, "instess %s\nbuilt with gcc %s, OpenMP %d, %s, OpenImageIO %s (in the module libinstess_codec.so, "
               "loaded on the first EXR or text; PNG through libpng)\n", INSTESS_VERSION, __VERSION__, _OPENMP, mesh_libs,
            image_codec_build_version());
    fprintf(f, "rasterizer kernels on this CPU: %s (the same bytes as every other)\n", rs_isa_name(rs_isa_best()));
}

/* s as shown in a message into buf (len bytes): control bytes and DEL as '?', so that a value or file name
 * never puts an escape sequence on the terminal; buf. */
static const char *shown(const char *s, char *buf, size_t len)
{
    size_t n = 0;
    for (; s && s[n] && n + 1 < len; n++) buf[n] = (unsigned char)s[n] < 0x20 || s[n] == 0x7f ? '?' : s[n];
    if (len) buf[n] = 0;
    return buf;
}

/* Print msg and the usage hint; exit code 2. */
static int usage_error(const char *msg, const char *arg)
{
    char m[2048], a[1024];
    fprintf(stderr, "instess: %s%s%s\nTry 'instess --help'.\n", shown(msg, m, sizeof m), arg ? ": " : "",
            arg ? shown(arg, a, sizeof a) : "");
    return 2;
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
    scene_args_result res;
    char err[1024];
    if (scene_parse_args(argc, argv, &o, &res, err, sizeof err) != 0) return usage_error(err, NULL);
    if (res == SCENE_ARGS_HELP) return print_usage(stdout), 0;
    if (res == SCENE_ARGS_VERSION) return print_version(stdout), 0;
    if (!o.output) return usage_error("no output file (-o FILE.png or FILE.exr)", NULL);
    const char *msg = scene_check_opts(&o);
    if (msg) return usage_error(msg, NULL);
    if (o.export_obj && outputs_same_target(o.output, o.export_obj))
        return usage_error("-o and --export-obj name the same file", o.output);
    warn_level_clamp(&o);
    if (scene_render_to_file(&o, err, sizeof err) != 0) {
        char m[sizeof err];
        fprintf(stderr, "instess: %s\n", shown(err, m, sizeof m));
        return 1;
    }
    return 0;
}

/* SIGTERM, SIGINT, SIGHUP, SIGQUIT, SIGXCPU: remove the temporary files of the outputs being written
 * (outputs_remove_temp_files is async-signal-safe; the names live in cli/run/output.c's static slots, the one
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

/* rc, or code (said on stderr) when what was written to stdout did not all reach it (a full disk, a closed pipe):
 * output lost is a failure, not a success. */
static int stdout_checked(int rc, int code)
{
    errno = 0;
    if (fflush(stdout) == 0 && !ferror(stdout)) return rc;
    fprintf(stderr, "instess: cannot write to standard output: %s\n", errno ? strerror(errno) : "write error");
    return rc ? rc : code;
}

static int run_command(int argc, char **argv);

/* Descriptors 0, 1 and 2 that were closed when the program started get /dev/null opened read-only: otherwise the
 * next file the program opens (an output's temporary, the mesh) would be descriptor 1, and what is printed for
 * stdout -- --stats json -- would go into it.  Writes to a read-only descriptor fail, so a closed stdout is still
 * reported (stdout_checked, --stats json) rather than silently lost. */
static void hold_standard_descriptors(void)
{
    for (int fd = 0; fd <= 2; fd++) {
        if (fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
        int got = open("/dev/null", O_RDONLY);
        if (got >= 0 && got != fd) close(got);
    }
}

/* Whether s is a thread count the OpenMP runtimes take: a comma-separated list of whole numbers 1..65536. */
static bool thread_list_ok(const char *s)
{
    for (;;) {
        size_t n = strspn(s, "0123456789");
        if (n == 0 || n > 5 || strtoul(s, NULL, 10) < 1 || strtoul(s, NULL, 10) > 65536) return false;
        s += n;
        if (!*s) return true;
        if (*s++ != ',') return false;
    }
}

/* OMP_NUM_THREADS and OMP_THREAD_LIMIT that are no thread count are removed (said on stderr), before the OpenMP
 * runtime reads them on its first call: LLVM's libomp (the sanitizer build's) aborts on 99999999999 (an
 * assertion in kmp_runtime.cpp), and the program sets its threads itself (--threads) in any case. */
static void drop_bad_openmp_variables(void)
{
    static const char *const names[] = {"OMP_NUM_THREADS", "OMP_THREAD_LIMIT"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
        const char *v = getenv(names[k]);
        if (!v || thread_list_ok(v)) continue;   /* empty too: libomp asserts on it */
        char m[64];
        fprintf(stderr, "instess: warning: %s='%s' is not a thread count (1..65536, or a list of them): ignored\n",
                names[k], shown(v, m, sizeof m));
        unsetenv(names[k]);
    }
}

int main(int argc, char **argv)
{
    hold_standard_descriptors();
    drop_bad_openmp_variables();
    /* compare's exit 1 means "the images differ": output it could not write is its I/O error, 4 */
    bool compare = argc > 1 && strcmp(argv[1], "compare") == 0;
    return stdout_checked(run_command(argc, argv), compare ? 4 : 1);
}

/* The program: the subcommands, or a render. */
static int run_command(int argc, char **argv)
{
    install_signal_handlers();
    if (argc < 2) {   /* no arguments: the usage, as a usage error */
        print_usage(stderr);
        fputs("\ninstess: no arguments: `instess MESH -o FILE.png` renders a mesh\n", stderr);
        return 2;
    }
    if (argc == 2 && strcmp(argv[1], "--man") == 0)
        return scene_print_man(stdout, render_exit_codes, subcommands, N_SUBCOMMANDS), 0;
    for (int k = 0; k < N_SUBCOMMANDS; k++)
        if (strcmp(argv[1], subcommands[k].name) == 0) return subcommands[k].run(argc - 1, argv + 1);
    return cmd_render(argc, argv);
}
