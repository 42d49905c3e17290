/* cli/run/compare.c -- `instess compare A B [--diff FILE] [--fail T] [--failpercent P]`: the pixel-diff test of
 * the golden tests (image_check, image/image.h) on two image files, for scripts and for a user's own goldens.
 *
 * Prints the shape, the largest difference with its pixel and channel, the mean, and the count of failing
 * pixels on stdout; exit codes are image_check's verdicts: 0 identical or within the thresholds, 1 different,
 * 3 the sizes (or channels) differ, 4 an image cannot be read (or the diff cannot be written), and 2 for a
 * usage error.  Its options are the table below, from which its usage text and the man page are printed. */
#include "scene.h"

#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* What the command line asked for. */
typedef struct compare_args {
    const char *a, *b, *diff;
    float fail, failpercent;
} compare_args;

const scene_subopt scene_compare_options[] = {
    {"diff", "FILE", "when the images differ (exit 1), write the amplified diff image there (.png or .exr): the "
     "first image dimmed plus |A - B| scaled so that the largest difference is full brightness, failing pixels "
     "red; nothing is written when they pass"},
    {"fail", "T", "a pixel fails when one of its channels differs by more than T (colour in 0..1)  [0]"},
    {"failpercent", "P", "pass when at most P percent of the pixels fail  [0]"},
    {NULL, NULL, NULL},
};

/* Print the usage of compare, from the table, to f. */
static void compare_usage(FILE *f)
{
    fputs("usage: instess compare A B [--diff FILE] [--fail T] [--failpercent P]\n"
          "Compare two images as the golden tests do; exit 0 identical or within the thresholds, 1 different,\n"
          "2 usage error, 3 sizes or channels differ, 4 an image cannot be read.\n\n", f);
    for (const scene_subopt *o = scene_compare_options; o->name; o++) {
        char label[64];
        snprintf(label, sizeof label, "  --%s %s", o->name, o->metavar);
        fprintf(f, "%-22s%s\n", label, o->help);
    }
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

/* A usage error: the message and the hint on stderr; 2. */
static int compare_usage_error(const char *msg, const char *arg)
{
    char m[2048], v[1024];
    fprintf(stderr, "instess compare: %s%s%s\nTry 'instess compare --help'.\n", shown(msg, m, sizeof m),
            arg ? ": " : "", arg ? shown(arg, v, sizeof v) : "");
    return 2;
}

/* A threshold in [0, hi] from s into *out; true on success. */
static bool parse_threshold(const char *s, float hi, float *out)
{
    return scene_parse_float(s, 0.0f, hi, out);
}

/* argv into a; 0, -1 for a usage error (printed), 1 when --help was asked (usage printed). */
static int parse_compare_args(int argc, char **argv, compare_args *a, int *code)
{
    struct option lo[sizeof scene_compare_options / sizeof scene_compare_options[0] + 1];
    size_t n = 0;
    for (; scene_compare_options[n].name; n++)
        lo[n] = (struct option){scene_compare_options[n].name, required_argument, 0, (int)(256 + n)};
    lo[n++] = (struct option){"help", no_argument, 0, 'h'};
    lo[n] = (struct option){0, 0, 0, 0};
    *a = (compare_args){0};
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, "h", lo, NULL)) != -1) {
        const char *name = c >= 256 ? scene_compare_options[c - 256].name : "";
        if (c == 'h') return compare_usage(stdout), *code = 0, 1;
        if (c == '?') return *code = compare_usage_error("unknown option or missing value", argv[optind - 1]), -1;
        if (!strcmp(name, "diff")) a->diff = optarg;
        else if (!strcmp(name, "fail") && !parse_threshold(optarg, 1e30f, &a->fail))
            return *code = compare_usage_error("--fail needs a number >= 0", optarg), -1;
        else if (!strcmp(name, "failpercent") && !parse_threshold(optarg, 100.0f, &a->failpercent))
            return *code = compare_usage_error("--failpercent needs a number in 0..100", optarg), -1;
    }
    if (argc - optind != 2) return *code = compare_usage_error("compare takes two images, A and B", NULL), -1;
    a->a = argv[optind], a->b = argv[optind + 1];
    char err[512];
    if (a->diff && image_check_path(a->diff, err, sizeof err) != 0)
        return *code = compare_usage_error("--diff", err), -1;
    if (a->diff && (outputs_same_target(a->diff, a->a) || outputs_same_target(a->diff, a->b)))
        return *code = compare_usage_error("--diff names one of the images compared", a->diff), -1;
    return 0;
}

/* Whether the --diff path can be written (checked before any image is read, so that a run that cannot write its
 * diff image fails at once): absent or a regular file, in a folder that exists and the process can write into;
 * else false with the reason printed.  image_write checks again when it writes (the path may change meanwhile). */
static bool diff_target_ok(const char *path)
{
    char p[1024];
    struct stat st;
    const char *what = NULL;
    if (lstat(path, &st) == 0)
        what = S_ISLNK(st.st_mode) ? "is a symbolic link (instess does not write through links)"
               : S_ISDIR(st.st_mode) ? "is a directory" : S_ISFIFO(st.st_mode) ? "is a FIFO"
               : !S_ISREG(st.st_mode) ? "is not a regular file" : NULL;
    char folder[4096];
    const char *slash = strrchr(path, '/');
    snprintf(folder, sizeof folder, "%.*s", slash ? (int)(slash - path) + (slash == path) : 1, slash ? path : ".");
    if (!what && access(folder, W_OK | X_OK) != 0) {
        char f[1024];
        fprintf(stderr, "instess compare: --diff %s: cannot create a file in the folder %s: %s\n",
                shown(path, p, sizeof p), shown(folder, f, sizeof f), strerror(errno));
        return false;
    }
    if (what) fprintf(stderr, "instess compare: --diff %s: %s\n", shown(path, p, sizeof p), what);
    return !what;
}

/* The report of a comparison that ran (verdict pass or different) on stdout. */
static void print_report(const compare_args *a, const is_image_diff *d, is_image_verdict v)
{
    double pct = d->n_pixels ? 100.0 * (double)d->n_fail / (double)d->n_pixels : 0.0;
    char na[1024], nb[1024], nd[1024];
    printf("%s vs %s: %ld pixels\n", shown(a->a, na, sizeof na), shown(a->b, nb, sizeof nb), d->n_pixels);
    printf("largest difference: %g (pixel %d,%d, channel %d); mean difference: %g\n", (double)d->max_error, d->max_x,
           d->max_y, d->max_channel, d->mean_error);
    printf("failing pixels: %ld (%.4f%%) differ by more than %g; allowed: %g%%\n", d->n_fail, pct, (double)a->fail,
           (double)a->failpercent);
    if (d->n_nonfinite)
        printf("non-finite mismatches: %ld pixels (NaN in one image only, or an infinity the other does not hold)\n",
               d->n_nonfinite);
    if (v == IS_IMAGE_DIFFERENT)
        printf("DIFFERENT%s%s\n", a->diff ? "; diff image: " : "", a->diff ? shown(a->diff, nd, sizeof nd) : "");
    else printf("%s\n", d->max_error == 0.0f ? "identical" : "within the thresholds");
}

/* The exit code of a verdict: 0 pass, 1 different, 3 shapes differ, 4 unreadable (2 is the usage error). */
static int compare_exit_code(is_image_verdict v)
{
    switch (v) {
    case IS_IMAGE_PASS: return 0;
    case IS_IMAGE_DIFFERENT: return 1;
    case IS_IMAGE_SHAPE_DIFFERS: return 3;
    case IS_IMAGE_IO_ERROR: return 4;
    case IS_IMAGE_BAD_ARGUMENT: return 2;   /* the options are checked before: not reached */
    }
    return 4;
}

int scene_cmd_compare(int argc, char **argv)
{
    compare_args a;
    int code = 0;
    if (parse_compare_args(argc, argv, &a, &code) != 0) return code;
    if (a.diff && !diff_target_ok(a.diff)) return 4;
    is_image_diff d;
    char err[2048];
    is_image_verdict v = image_check_files(a.a, a.b, a.fail, a.failpercent, a.diff, &d, err, sizeof err);
    if (v == IS_IMAGE_PASS || v == IS_IMAGE_DIFFERENT) print_report(&a, &d, v);
    else {
        char m[sizeof err];
        fprintf(stderr, "instess compare: %s\n", shown(err, m, sizeof m));
    }
    return compare_exit_code(v);
}
