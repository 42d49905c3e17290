/* tests/test_cli.c -- the `instess` program as a user runs it: exit codes (0 / 1 input error / 2 usage error),
 * messages naming the input, nothing written on failure, PNG and EXR (channels R, G, B, A, Z and AOVs), OBJ
 * export.  Runs build/instess, or $INSTESS_BIN (the sanitizer build's), which make test builds first. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "util/prog.h"
#include "../core/core.h"
#include "../image/image.h"
#include "../meshes/meshes.h"

static char dir[256];

/* Run `build/instess ARGS` with stderr captured into *err_out (static buffer); returns the exit code. */
static int run(const char *args, const char **err_out)
{
    static char errbuf[32768];
    char cmd[2400], errfile[300];
    snprintf(errfile, sizeof errfile, "%s/stderr.txt", dir);
    const char *bin = getenv("INSTESS_BIN") ? getenv("INSTESS_BIN") : "build/instess";
    snprintf(cmd, sizeof cmd, "%s %s 2>%s >/dev/null", bin, args, errfile);
    int st = system(cmd);
    prog_read_text(dir, "stderr.txt", errbuf, sizeof errbuf);
    if (err_out) *err_out = errbuf;
    return prog_exit_code(st);
}

static bool exists(const char *name)
{
    char p[512];
    struct stat s;
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return stat(p, &s) == 0;
}

/* Number of entries in the work directory besides stderr.txt. */
static int entries(void)
{
    char cmd[400];
    snprintf(cmd, sizeof cmd, "test $(ls -A %s | grep -v '^stderr.txt$' | wc -l) -eq 0", dir);
    return system(cmd) == 0 ? 0 : 1;
}

static int setup(void **state)
{
    snprintf(dir, sizeof dir, "/tmp/instess-cli-XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static void test_usage_errors(void **state)
{
    const char *err;
    const char *bad[] = {"--bogus -o X.png", "--level", "--level 0 -o X.png", "--level -3 -o X.png",
                         "--level 1000000 -o X.png", "--size 0x10 -o X.png", "--size 1000000x1000000 -o X.png",
                         "--size 12 -o X.png", "--msaa 3 -o X.png", "--patch curvy -o X.png", "--fill dots -o X.png",
                         "--threads -1 -o X.png", "", "-o X.tiff", "--aov normal -o X.png", "--level 2.5 -o X.png",
                         "--path cpu --patch smooth -o X.png", "--yaw abc -o X.png",
                         "--mesh cube extra -o X.png", "cube extra -o X.png"};
    char args[1024];
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char *x = strstr(bad[k], "X.");
        if (x) snprintf(args, sizeof args, "%.*s%s/%s", (int)(x - bad[k]), bad[k], dir, x);
        else snprintf(args, sizeof args, "%s", bad[k]);
        int rc = run(args, &err);
        if (rc != 2) fprintf(stderr, "args '%s' gave %d: %s\n", args, rc, err);
        assert_int_equal(rc, 2);
        assert_non_null(strstr(err, "instess:"));
        assert_int_equal(entries(), 0);
    }
    assert_int_equal(run("--help", NULL), 0);
    assert_int_equal(run("--version", &err), 0);
    /* --version names the rasterizer kernels this CPU runs (what a new device picks) */
    char cmd[600], out[2048], want[128];
    snprintf(cmd, sizeof cmd, "%s --version", getenv("INSTESS_BIN") ? getenv("INSTESS_BIN") : "build/instess");
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = 0;
    assert_int_equal(pclose(p), 0);
    snprintf(want, sizeof want, "rasterizer kernels on this CPU: %s ", rs_isa_name(rs_isa_best()));
    assert_non_null(strstr(out, want));
}

static void test_input_errors(void **state)
{
    const char *err;
    char args[1024];
    snprintf(args, sizeof args, "--mesh %s/missing.obj -o %s/a.png", dir, dir);
    assert_int_equal(run(args, &err), 1);
    assert_non_null(strstr(err, "missing.obj"));
    assert_false(exists("a.png"));
    /* an unwritable output: a directory in the way */
    snprintf(args, sizeof args, "mkdir -p %s/b.png", dir);
    assert_int_equal(system(args), 0);
    snprintf(args, sizeof args, "--mesh cube --level 2 --size 64x64 -o %s/b.png", dir);
    assert_int_equal(run(args, &err), 1);
    assert_non_null(strstr(err, "b.png"));
    snprintf(args, sizeof args, "rmdir %s/b.png", dir);
    assert_int_equal(system(args), 0);
    /* a previous image survives a failed render */
    snprintf(args, sizeof args, "--mesh cube --level 2 --size 64x64 -q -o %s/keep.png", dir);
    assert_int_equal(run(args, NULL), 0);
    is_image before = {0}, after = {0};
    char p[512], e[256];
    snprintf(p, sizeof p, "%s/keep.png", dir);
    assert_int_equal(image_read(&before, p, e, sizeof e), 0);
    snprintf(args, sizeof args, "--mesh %s/missing.obj -o %s/keep.png", dir, dir);
    assert_int_equal(run(args, NULL), 1);
    assert_int_equal(image_read(&after, p, e, sizeof e), 0);
    assert_memory_equal(before.data, after.data, sizeof(float) * 64 * 64 * 4);
    image_free(&before), image_free(&after);
    snprintf(args, sizeof args, "rm -f %s/keep.png", dir);
    assert_int_equal(system(args), 0);
}

/* --displace: a height map moves the surface (the same bytes on 1 and 2 threads); a missing or unreadable map is an
 * input error naming the file, a bad --displace-scale, --displace-scale alone and --displace with --export-obj are
 * usage errors; nothing is written on failure. */
static void test_displace(void **state)
{
    const char *err;
    char args[2048], map[300], a[300], b[300];
    is_image img = {0};
    char e[256];
    assert_int_equal(image_alloc(&img, 16, 16, "Y", e, sizeof e), 0);
    for (int k = 0; k < 256; k++) img.data[k] = (float)((k * 37) % 16) / 15.0f;
    snprintf(map, sizeof map, "%s/map.png", dir);
    assert_int_equal(image_write(&img, map, NULL, e, sizeof e), 0);
    image_free(&img);
    const char *base = "--mesh sphere --level 6 --size 96x96 --normals linear -q";
    snprintf(args, sizeof args, "%s --displace %s --displace-scale 0.2 --threads 2 -o %s/d2.png", base, map, dir);
    assert_int_equal(run(args, &err), 0);
    snprintf(args, sizeof args, "%s --displace %s --displace-scale 0.2 --threads 1 -o %s/d1.png", base, map, dir);
    assert_int_equal(run(args, &err), 0);
    snprintf(args, sizeof args, "%s -o %s/u.png", base, dir);
    assert_int_equal(run(args, &err), 0);
    assert_true(prog_same_bytes(prog_path(dir, "d1.png", a, sizeof a), prog_path(dir, "d2.png", b, sizeof b)));
    assert_false(prog_same_pixels(prog_path(dir, "d1.png", a, sizeof a), prog_path(dir, "u.png", b, sizeof b)));
    snprintf(args, sizeof args, "rm -f %s/d1.png %s/d2.png %s/u.png", dir, dir, dir);
    assert_int_equal(system(args), 0);
    /* input errors: the map's name in the message, no image */
    snprintf(args, sizeof args, "%s --displace %s/no-such-map.png -o %s/x.png", base, dir, dir);
    assert_int_equal(run(args, &err), 1);
    assert_non_null(strstr(err, "no-such-map.png"));
    assert_non_null(strstr(err, "--displace"));
    /* -o naming the map: refused, the map kept */
    snprintf(args, sizeof args, "%s --displace %s -o %s", base, map, map);
    assert_int_equal(run(args, &err), 1);
    assert_non_null(strstr(err, "height map"));
    is_image back = {0};
    assert_int_equal(image_read(&back, map, e, sizeof e), 0);
    assert_int_equal(back.width, 16);
    image_free(&back);
    assert_true(prog_write_text(dir, "junk.png", "this is not a PNG"));
    snprintf(args, sizeof args, "%s --displace %s/junk.png -o %s/x.png", base, dir, dir);
    assert_int_equal(run(args, &err), 1);
    assert_non_null(strstr(err, "junk.png"));
    assert_false(exists("x.png"));
    snprintf(args, sizeof args, "rm -f %s/junk.png", dir);
    assert_int_equal(system(args), 0);
    /* usage errors */
    const char *bad[] = {"--displace-scale abc", "--displace-scale nan", "--displace-scale inf", "--displace-scale 11",
                         "--displace-scale -10.5", "--displace-scale ''", "--displace-scale"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        snprintf(args, sizeof args, "%s --displace %s -o %s/x.png %s", base, map, dir, bad[k]);
        assert_int_equal(run(args, &err), 2);
        assert_non_null(strstr(err, "--displace-scale"));
    }
    snprintf(args, sizeof args, "%s --displace-scale 0.3 -o %s/x.png", base, dir);
    assert_int_equal(run(args, &err), 2);
    assert_non_null(strstr(err, "--displace-scale needs --displace"));
    snprintf(args, sizeof args, "%s --displace %s --export-obj %s/x.obj -o %s/x.png", base, map, dir, dir);
    assert_int_equal(run(args, &err), 2);
    assert_non_null(strstr(err, "--export-obj"));
    snprintf(args, sizeof args, "rm -f %s", map);
    assert_int_equal(system(args), 0);
    assert_int_equal(prog_entries_with(dir, "x."), 0);         /* no x.png, x.obj */
    assert_int_equal(prog_entries_with(dir, ".instess-"), 0);  /* nor a temporary of them */
}

static void test_png_and_exr(void **state)
{
    char args[1400], p[512], e[256];
    snprintf(args, sizeof args, "--mesh cube --patch flat --level 2 --size 80x60 -q -o %s/cube.png", dir);
    assert_int_equal(run(args, NULL), 0);
    snprintf(args, sizeof args,
             "--mesh tetrahedron --patch smooth --level 5 --size 80x60 --msaa 1 --aov normal,bary,instance,gregory "
             "-q -o %s/tet.exr --export-obj %s/tet.obj",
             dir, dir);
    assert_int_equal(run(args, NULL), 0);
    is_image img = {0};
    snprintf(p, sizeof p, "%s/cube.png", dir);
    assert_int_equal(image_read(&img, p, e, sizeof e), 0);
    assert_int_equal(img.width, 80);
    assert_int_equal(img.height, 60);
    assert_int_equal(img.channels, 4);
    image_free(&img);
    snprintf(p, sizeof p, "%s/tet.exr", dir);
    assert_int_equal(image_read(&img, p, e, sizeof e), 0);
    const char *names[] = {"R", "G", "B", "A", "Z", "N.X", "N.Y", "N.Z", "bary.X", "bary.Y", "bary.Z", "instance",
                           "gregory.X", "gregory.Y", "gregory.Z"};
    assert_int_equal(img.channels, 15);
    int at[15]; /* OpenEXR stores channels by name, so find each one (the reader groups layers) */
    for (int c = 0; c < 15; c++) {
        at[c] = -1;
        for (int k = 0; k < img.channels; k++)
            if (strcmp(img.channel_names[k], names[c]) == 0) at[c] = k;
        assert_true(at[c] >= 0);
    }
    /* the centre pixel is on the tetrahedron: depth inside (0, 1), barycentrics sum to 1, a normal */
    const float *px = &img.data[(30 * 80 + 40) * img.channels];
    assert_true(px[at[4]] > 0.0f && px[at[4]] < 1.0f);
    assert_float_equal(px[at[8]] + px[at[9]] + px[at[10]], 1.0f, 1e-3);
    /* unit normals at the vertices, interpolated across each small triangle: length slightly below 1 */
    float len2 = px[at[5]] * px[at[5]] + px[at[6]] * px[at[6]] + px[at[7]] * px[at[7]];
    assert_true(len2 > 0.8f && len2 < 1.001f);
    assert_true(px[at[11]] >= 0.0f && px[at[11]] <= 3.0f && px[at[11]] == (float)(int)px[at[11]]);
    image_free(&img);
    /* OBJ: 4 triangles x 21 grid points, 4 x 25 faces */
    snprintf(args, sizeof args, "test $(grep -c '^v ' %s/tet.obj) -eq 84 && test $(grep -c '^vn ' %s/tet.obj) -eq 84 "
                                "&& test $(grep -c '^f ' %s/tet.obj) -eq 100", dir, dir, dir);
    assert_int_equal(system(args), 0);
}

/* A primitive-generator grid renders its clamped level and says so on stderr, even with -q; a level inside
 * the range says nothing. */
static void test_clamped_level_is_said(void **state)
{
    (void)state;
    const char *err;
    char args[600];
    const struct { const char *grid, *level, *said; } cases[] = {
        {"pg-fractional-odd", "100", "--level 100 is outside the range of --grid pg-fractional-odd; rendering level 63"},
        {"pg-fractional-even", "1", "--level 1 is outside the range of --grid pg-fractional-even; rendering level 2"},
        {"pg-equal", "64.5", "rendering level 64"}};
    for (int k = 0; k < 3; k++) {
        snprintf(args, sizeof args, "--grid %s --level %s --size 16x16 -q -o %s/a.png", cases[k].grid, cases[k].level,
                 dir);
        assert_int_equal(run(args, &err), 0);
        if (!strstr(err, cases[k].said)) fail_msg("%s: stderr was: %s", cases[k].grid, err);
    }
    snprintf(args, sizeof args, "--grid pg-fractional-odd --level 7.5 --size 16x16 -q -o %s/a.png", dir);
    assert_int_equal(run(args, &err), 0);
    assert_string_equal(err, "");
    char p[512];
    snprintf(p, sizeof p, "%s/a.png", dir);
    unlink(p);
}


/* Whether dir/a and dir/b decode to the same pixels. */
static bool same_pixels(const char *a, const char *b)
{
    char pa[512], pb[512];
    snprintf(pa, sizeof pa, "%s/%s", dir, a);
    snprintf(pb, sizeof pb, "%s/%s", dir, b);
    return prog_same_pixels(pa, pb);
}

/* What people expect of a command line: no arguments print the usage (exit 2); the mesh may be positional
 * (the same image as --mesh), but not both; an unknown value lists the valid ones; every subcommand takes
 * --help. */
static void test_command_line_conventions(void **state)
{
    (void)state;
    const char *err;
    assert_int_equal(run("", &err), 2);
    assert_non_null(strstr(err, "usage: instess"));
    char args[600];
    snprintf(args, sizeof args, "tests/data/meshes/box.obj --size 24x24 -q -o %s/pos.png", dir);
    assert_int_equal(run(args, &err), 0);
    snprintf(args, sizeof args, "--mesh tests/data/meshes/box.obj --size 24x24 -q -o %s/opt.png", dir);
    assert_int_equal(run(args, &err), 0);
    assert_true(same_pixels("pos.png", "opt.png"));
    snprintf(args, sizeof args, "--mesh cube tests/data/meshes/box.obj -o %s/two.png", dir);
    assert_int_equal(run(args, &err), 2);
    assert_non_null(strstr(err, "the mesh is given by --mesh"));
    snprintf(args, sizeof args, "--patch curvy -o %s/x.png", dir);
    assert_int_equal(run(args, &err), 2);
    assert_non_null(strstr(err, "one of: flat | npatch | smooth-initial | smooth | phong | pn-aen"));
    snprintf(args, sizeof args, "--normals bent -o %s/x.png", dir);
    assert_int_equal(run(args, &err), 2);
    assert_non_null(strstr(err, "one of: linear | quadratic | real"));
    assert_int_equal(run("smoothness --help", &err), 0);
    assert_int_equal(run("figures --help", &err), 0);
    assert_int_equal(run("--help", &err), 0);
    char p[512];
    const char *names[] = {"pos.png", "opt.png"};
    for (int k = 0; k < 2; k++) snprintf(p, sizeof p, "%s/%s", dir, names[k]), unlink(p);
    assert_false(exists("two.png"));
    assert_false(exists("x.png"));
}

/* The image codec (OpenImageIO) is a module loaded on the first call that needs it: a copy of the program
 * without the module beside it still answers --help and --version (which names the libraries), reports usage
 * errors, renders and compares PNGs (libpng, in the program), and an EXR render fails with exit 1 naming the
 * module, writing nothing. */
static void test_codec_loaded_on_demand(void **state)
{
    (void)state;
    const char *bin = getenv("INSTESS_BIN") ? getenv("INSTESS_BIN") : "build/instess";
    char cmd[4096], copy[512], err_path[512];
    snprintf(copy, sizeof copy, "%s/lonely/instess", dir);
    snprintf(cmd, sizeof cmd, "mkdir -p %s/lonely && cp %s %s", dir, bin, copy);
    assert_int_equal(system(cmd), 0);
    snprintf(err_path, sizeof err_path, "%s/lonely/err.txt", dir);
    snprintf(cmd, sizeof cmd, "%s --help >/dev/null 2>%s", copy, err_path);
    assert_int_equal(system(cmd), 0);
    /* --version names the libraries, OpenImageIO's version from the build, without the module */
    snprintf(cmd, sizeof cmd, "%s --version 2>%s | grep -q 'OpenImageIO [0-9]' && %s --version | grep -q 'assimp [0-9]' "
                              "&& %s --version | grep -q 'meshoptimizer 0' && %s --version | grep -q 'gcc'",
             copy, err_path, copy, copy, copy);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s --patch curvy -o %s/x.png 2>%s", copy, dir, err_path);
    int st = system(cmd);
    assert_int_equal(WEXITSTATUS(st), 2);
    snprintf(cmd, sizeof cmd, "%s --size 16x16 -q -o %s/x.png 2>%s && %s compare %s/x.png %s/x.png >/dev/null 2>>%s",
             copy, dir, err_path, copy, dir, dir, err_path);
    assert_int_equal(system(cmd), 0);
    assert_true(exists("x.png"));
    snprintf(cmd, sizeof cmd, "%s/x.png", dir);
    unlink(cmd);
    snprintf(cmd, sizeof cmd, "%s --size 16x16 -q -o %s/x.exr 2>%s", copy, dir, err_path);
    st = system(cmd);
    assert_int_equal(WEXITSTATUS(st), 1);
    FILE *f = fopen(err_path, "r");
    char msg[2048] = "";
    size_t n = f ? fread(msg, 1, sizeof msg - 1, f) : 0;
    if (f) fclose(f);
    msg[n] = 0;
    print_message("  without the module: %s", msg);
    assert_non_null(strstr(msg, "cannot load libinstess_codec.so"));
    assert_false(exists("x.exr"));
    snprintf(cmd, sizeof cmd, "rm -rf %s/lonely", dir);
    assert_int_equal(system(cmd), 0);
}

/* Channel name of img, asserted present. */
static int channel(const is_image *img, const char *name)
{
    int c = image_channel_index(img, name);
    if (c < 0) fail_msg("no channel %s", name);
    return c;
}

/* The EXR's channels mean what they say: A is coverage (0 on the background, 1 inside, between at the
 * antialiased edges), R, G, B are linear (the PNG's sRGB values decoded) and premultiplied, the background
 * transparent; `instance` is -1 where no triangle is (and a triangle's index elsewhere), `depth` the view-space
 * depth (+inf on the background; the cube's front face seen head-on lies at 5.5426 - 1 = 4.5426 mesh units,
 * the camera being 3.2 bounding radii of sqrt(3) away), Z is z/w in [0, 1] and 1 on the background. */
static void test_exr_channels(void **state)
{
    (void)state;
    char args[1200], p[512], e[256];
    const char *common = "--mesh cube --patch flat --yaw 0 --pitch 0 --size 64x64 -q";
    snprintf(args, sizeof args, "%s -o %s/c.png", common, dir);
    assert_int_equal(run(args, NULL), 0);
    snprintf(args, sizeof args, "%s --aov instance,depth -o %s/c.exr", common, dir);
    assert_int_equal(run(args, NULL), 0);
    is_image png = {0}, exr = {0};
    assert_int_equal(image_read(&png, prog_path(dir, "c.png", p, sizeof p), e, sizeof e), 0);
    assert_int_equal(image_read(&exr, prog_path(dir, "c.exr", p, sizeof p), e, sizeof e), 0);
    int A = channel(&exr, "A"), Z = channel(&exr, "Z"), I = channel(&exr, "instance"), D = channel(&exr, "depth");
    int rgb[3] = {channel(&exr, "R"), channel(&exr, "G"), channel(&exr, "B")};
    const float *bg = &exr.data[0], *mid = &exr.data[(32 * 64 + 32) * exr.channels];
    assert_true(bg[A] == 0.0f && bg[rgb[0]] == 0.0f && bg[rgb[1]] == 0.0f && bg[rgb[2]] == 0.0f);
    assert_true(bg[Z] == 1.0f && bg[I] == -1.0f && isinf(bg[D]) && bg[D] > 0);
    assert_true(mid[A] == 1.0f);
    assert_true(mid[Z] > 0.0f && mid[Z] < 1.0f);
    assert_float_equal(mid[D], 3.2 * sqrt(3.0) - 1.0, 1e-3);
    assert_true(mid[I] >= 0.0f && mid[I] <= 11.0f && mid[I] == floorf(mid[I]));
    for (int k = 0; k < 3; k++) {   /* sRGB decoded: the PNG's value c as ((c + 0.055) / 1.055)^2.4 */
        float c = png.data[(32 * 64 + 32) * png.channels + k];
        double lin = c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
        assert_float_equal(mid[rgb[k]], lin, 2e-3 * lin + 1e-4);
        assert_true(c > 0.05f && mid[rgb[k]] < c - 0.01f);   /* really decoded, not the display value */
    }
    long partial = 0, background = 0;
    for (long q = 0; q < 64 * 64; q++) {
        const float *px = &exr.data[q * exr.channels];
        partial += px[A] > 0.0f && px[A] < 1.0f;
        for (int k = 0; k < 3; k++) assert_true(px[rgb[k]] <= px[A] + 1e-3f);   /* premultiplied */
        assert_true(isinf(px[D]) == (px[I] == -1.0f));   /* no triangle exactly where no depth */
        background += px[I] == -1.0f;
    }
    print_message("  %ld edge pixels with partial coverage, %ld background pixels\n", partial, background);
    assert_true(partial > 20);
    assert_true(background > 1000);
    image_free(&png), image_free(&exr);
    unlink(prog_path(dir, "c.png", p, sizeof p));
    unlink(prog_path(dir, "c.exr", p, sizeof p));
}

/* The run of `ARGS` with stderr (and stdout) on a terminal, through util-linux's script(1); what the terminal
 * showed into *out (static buffer). */
static void run_on_terminal(const char *args, const char **out)
{
    static char buf[16384];
    const char *bin = getenv("INSTESS_BIN") ? getenv("INSTESS_BIN") : "build/instess";
    char cmd[2400], path[512];
    snprintf(path, sizeof path, "%s/typescript", dir);
    snprintf(cmd, sizeof cmd, "script -qec '%s %s' %s >/dev/null 2>&1 </dev/null", bin, args, path);
    assert_true(system(cmd) != -1);
    size_t n = 0;
    unsigned char *b = prog_slurp(path, &n);
    n = n < sizeof buf - 1 ? n : sizeof buf - 1;
    if (b) memcpy(buf, b, n);
    buf[b ? n : 0] = 0;
    free(b);
    unlink(path);
    *out = buf;
}

/* A run that takes more than a second draws a progress line on a terminal (here the import of a PLY header
 * that hangs assimp, stopped after 3 s: certainly longer than a second), erased before the error message;
 * with -q, or with stderr in a file, no progress line at all. */
static void test_progress_line(void **state)
{
    (void)state;
    const char *out;
    char args[1200];
    snprintf(args, sizeof args, "tests/data/meshes/truncated_header.ply --import-timeout 3 -o %s/p.png", dir);
    run_on_terminal(args, &out);
    if (strstr(out, "ran out of the import memory")) {   /* AddressSanitizer's quarantine: the limit comes first */
        print_message("  the import ran out of memory before the time limit: no long run to show\n");
        return;
    }
    assert_non_null(strstr(out, "truncated_header.ply: reading the mesh, 1."));
    assert_non_null(strstr(out, "\r\033[Kinstess: tests/data/meshes/truncated_header.ply: cannot read the mesh"));
    assert_non_null(strstr(out, "import time limit of 3 s"));
    snprintf(args, sizeof args, "tests/data/meshes/truncated_header.ply --import-timeout 2 -q -o %s/p.png", dir);
    run_on_terminal(args, &out);
    if (!strstr(out, "ran out of the import memory"))   /* as above: under ASan either limit may come first */
        assert_non_null(strstr(out, "import time limit of 2 s"));
    assert_null(strstr(out, "reading the mesh"));
    const char *err;
    snprintf(args, sizeof args, "tests/data/meshes/truncated_header.ply --import-timeout 2 -o %s/p.png", dir);
    assert_int_equal(run(args, &err), 1);
    assert_null(strchr(err, '\r'));
    assert_null(strstr(err, "reading the mesh"));
    assert_false(exists("p.png"));
}

/* `instess smoothness --mesh FILE` measures the user's mesh: one row per patch named by the file, and --mesh
 * cube gives the very rows of the built-in table; a missing file is an input error naming it. */
static void test_smoothness_mesh(void **state)
{
    (void)state;
    const char *bin = getenv("INSTESS_BIN") ? getenv("INSTESS_BIN") : "build/instess";
    char cmd[2400];
    snprintf(cmd, sizeof cmd, "%s smoothness --mesh tests/data/meshes/box.obj --samples 4 > %s/box.md && "
                              "test $(grep -c '^| tests/data/meshes/box.obj | ' %s/box.md) -eq 6 && "
                              "grep -q '^| tests/data/meshes/box.obj | npatch | ' %s/box.md", bin, dir, dir, dir);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s smoothness --samples 4 | grep '^| cube |' > %s/all.md && %s smoothness --samples 4 "
                              "--mesh cube | grep '^| cube |' > %s/one.md && test -s %s/one.md && cmp -s %s/all.md "
                              "%s/one.md", bin, dir, bin, dir, dir, dir, dir);
    assert_int_equal(system(cmd), 0);
    const char *err;
    assert_int_equal(run("smoothness --mesh tests/data/meshes/missing.obj", &err), 1);
    assert_non_null(strstr(err, "missing.obj"));
    assert_int_equal(run("smoothness --mesh", &err), 2);
    snprintf(cmd, sizeof cmd, "rm -f %s/box.md %s/all.md %s/one.md", dir, dir, dir);
    assert_int_equal(system(cmd), 0);
}

/* The box of the pixels of PNG dir/name that differ from the background: x0, y0, x1, y1 (inclusive), and the
 * covered widths of its top and bottom fifths in w_top, w_bottom; false if nothing is covered. */
static bool covered_box(const char *name, int box[4], long *w_top, long *w_bottom)
{
    char p[512], e[256];
    is_image img = {0};
    if (image_read(&img, prog_path(dir, name, p, sizeof p), e, sizeof e) != 0) return false;
    const float bg[3] = {46 / 255.0f, 52 / 255.0f, 64 / 255.0f};
    int W = img.width, H = img.height;
    unsigned char *cov = calloc((size_t)W * H, 1);
    box[0] = W, box[1] = H, box[2] = -1, box[3] = -1;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const float *px = &img.data[((size_t)y * W + x) * img.channels];
            for (int c = 0; c < 3; c++) cov[y * W + x] |= fabsf(px[c] - bg[c]) > 0.5f / 255.0f;
            if (!cov[y * W + x]) continue;
            if (x < box[0]) box[0] = x;
            if (y < box[1]) box[1] = y;
            if (x > box[2]) box[2] = x;
            if (y > box[3]) box[3] = y;
        }
    int h5 = (box[3] - box[1] + 1) / 5;
    *w_top = *w_bottom = 0;
    for (int y = 0; box[2] >= 0 && y < h5; y++)
        for (int x = 0; x < W; x++) *w_top += cov[(box[1] + y) * W + x], *w_bottom += cov[(box[3] - y) * W + x];
    free(cov);
    image_free(&img);
    unlink(p);
    return box[2] >= 0;
}

/* --up z stands a pyramid whose apex is at the file's +z on its base (apex up: the top of the picture is
 * narrower than its bottom, the picture taller than wide); -z turns it upside down; the default (y) leaves it
 * lying.  --fit box makes the long model fill the image (at least 85% of its height, where the sphere fit
 * leaves more) without touching the border. */
static void test_up_and_fit(void **state)
{
    (void)state;
    assert_true(prog_write_text(dir, "pyr.obj", "v -0.25 -0.25 0\nv 0.25 -0.25 0\nv 0.25 0.25 0\nv -0.25 0.25 0\n"
                                                "v 0 0 3\nf 1 4 3\nf 1 3 2\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n"));
    char args[1200];
    int box[4] = {0}, sphere_h = 0;
    long top = 0, bottom = 0;
    const char *views[] = {"--up z", "--up -z", "", "--up z --fit box"};
    for (int k = 0; k < 4; k++) {
        snprintf(args, sizeof args, "%s/pyr.obj %s --yaw 20 --pitch 0 --size 96x96 -q -o %s/up.png", dir, views[k],
                 dir);
        assert_int_equal(run(args, NULL), 0);
        assert_true(covered_box("up.png", box, &top, &bottom));
        int w = box[2] - box[0] + 1, h = box[3] - box[1] + 1;
        print_message("  '%s': %dx%d at (%d, %d), top fifth %ld px, bottom fifth %ld px\n", views[k], w, h, box[0],
                      box[1], top, bottom);
        if (k == 0) assert_true(h > 2 * w && top * 2 < bottom), sphere_h = h;
        if (k == 1) assert_true(h > 2 * w && bottom * 2 < top);
        if (k == 2) assert_true(w > 2 * h);
        if (k == 3) {
            assert_true(h >= 82 && sphere_h < 82 && top * 2 < bottom);   /* 90% of 96 rows asked, 85% at least */
            assert_true(box[0] > 0 && box[1] > 0 && box[2] < 95 && box[3] < 95);
        }
    }
    char p[512];
    unlink(prog_path(dir, "pyr.obj", p, sizeof p));
}

/* Index of the triangle of m with the corners of triangle t of e at the same positions (bitwise) and texcoords,
 * in the same cyclic order (the same winding), or -1. */
static long same_triangle(const is_mesh *m, const is_mesh *e, size_t t)
{
    for (size_t u = 0; u < m->n_triangles; u++)
        for (int r = 0; r < 3; r++) {
            bool same = true;
            for (int c = 0; c < 3 && same; c++) {
                uint32_t a = m->indices[3 * u + (c + r) % 3], b = e->indices[3 * t + c];
                same = !memcmp(&m->positions[a], &e->positions[b], sizeof(float3)) &&
                       !memcmp(&m->texcoords[a], &e->texcoords[b], sizeof(float2));
            }
            if (same) return (long)u;
        }
    return -1;
}

/* --export-obj writes the surface in the input's own frame: the flat patch at level 1 is the input, so the
 * export read back through assimp has the input's triangles -- the same positions (not mirrored), texture
 * coordinates and winding -- and its vertex lines are the input's; a curved export keeps the
 * winding too (its faces' normals agree with its vertex normals).  An export not named .obj is refused. */
static void test_export_obj_frame(void **state)
{
    (void)state;
    /* an asymmetric tetrahedron, counter-clockwise seen from outside (OBJ), with texture coordinates */
    assert_true(prog_write_text(dir, "in.obj", "v 0.25 -0.5 2\nv 2 0 0.5\nv 0 1.5 1.25\nv 0.5 0.25 -1\n"
                                               "vt 0.1 0.2\nvt 0.9 0.3\nvt 0.4 0.8\nvt 0.7 0.6\n"
                                               "f 1/1 3/3 2/2\nf 1/1 2/2 4/4\nf 2/2 3/3 4/4\nf 3/3 1/1 4/4\n"));
    char args[1200], in[512], ex[512], err[512];
    snprintf(args, sizeof args, "%s/in.obj --patch flat --level 1 --size 16x16 -q -o %s/a.png --export-obj %s/ex.obj",
             dir, dir, dir);
    assert_int_equal(run(args, NULL), 0);
    is_mesh a = {0}, b = {0};
    assert_int_equal(mesh_load_file(prog_path(dir, "in.obj", in, sizeof in), NULL, &a, err, sizeof err), 0);
    assert_int_equal(mesh_load_file(prog_path(dir, "ex.obj", ex, sizeof ex), NULL, &b, err, sizeof err), 0);
    assert_int_equal(b.n_triangles, a.n_triangles);
    for (size_t t = 0; t < b.n_triangles; t++) assert_true(same_triangle(&a, &b, t) >= 0);
    mesh_free(&b);
    snprintf(args, sizeof args, "grep -qx 'v 0.25 -0.5 2' %s/ex.obj && grep -qx 'v 0.5 0.25 -1' %s/ex.obj", dir, dir);
    assert_int_equal(system(args), 0);
    /* the smoothed patch at level 4: every face's winding agrees with the normals (outward, as the input's) */
    snprintf(args, sizeof args, "%s/in.obj --patch smooth --level 4 --size 16x16 -q -o %s/a.png --export-obj %s/ex.obj",
             dir, dir, dir);
    assert_int_equal(run(args, NULL), 0);
    assert_int_equal(mesh_load_file(ex, NULL, &b, err, sizeof err), 0);
    assert_int_equal(b.n_triangles, 4 * 16);
    assert_int_equal(b.stats.normals_against_faces, 0);
    mesh_free(&b);
    mesh_free(&a);
    const char *e;
    snprintf(args, sizeof args, "--mesh cube -q -o %s/a.png --export-obj %s/ex.ply", dir, dir);
    assert_int_equal(run(args, &e), 2);
    assert_non_null(strstr(e, "--export-obj writes OBJ: its name must end in .obj"));
    assert_false(exists("ex.ply"));
    const char *names[] = {"in.obj", "ex.obj", "a.png"};
    for (int k = 0; k < 3; k++) unlink(prog_path(dir, names[k], in, sizeof in));
}

/* Pixels of the PNG dir/name that differ from the default background (46, 52, 64); -1 if unreadable. */
static long covered_pixels(const char *name)
{
    char p[512], e[256];
    is_image img = {0};
    snprintf(p, sizeof p, "%s/%s", dir, name);
    if (image_read(&img, p, e, sizeof e) != 0) return -1;
    long n = 0;
    const float bg[3] = {46 / 255.0f, 52 / 255.0f, 64 / 255.0f};
    for (long k = 0; k < (long)img.width * img.height; k++)
        for (int c = 0; c < 3; c++)
            if (fabsf(img.data[k * img.channels + c] - bg[c]) > 0.5f / 255.0f) {
                n++;
                break;
            }
    image_free(&img);
    unlink(p);
    return n;
}

/* --cull is D3DRS_CULLMODE: a triangle facing the camera (clockwise on screen after the import's change of
 * handedness) is drawn under ccw (the default) and none, culled under cw; the same triangle wound the other way
 * the opposite. */
static void test_cull(void **state)
{
    (void)state;
    const char *files[2] = {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 3 2\n"};
    const char *culls[3] = {"", "--cull none", "--cull cw"};
    const bool drawn[2][3] = {{true, true, false}, {false, true, true}};
    char args[1200];
    for (int f = 0; f < 2; f++) {
        assert_true(prog_write_text(dir, "tri.obj", files[f]));
        for (int c = 0; c < 3; c++) {
            snprintf(args, sizeof args, "%s/tri.obj %s --yaw 0 --pitch 0 --size 64x64 -q -o %s/cull.png", dir,
                     culls[c], dir);
            assert_int_equal(run(args, NULL), 0);
            long n = covered_pixels("cull.png");
            print_message("  file %d, '%s': %ld pixels\n", f, culls[c], n);
            assert_true(drawn[f][c] ? n > 200 : n == 0);
        }
    }
    snprintf(args, sizeof args, "--cull both -o %s/x.png", dir);
    const char *err;
    assert_int_equal(run(args, &err), 2);
    assert_non_null(strstr(err, "one of: none | cw | ccw"));
    char p[512];
    unlink(prog_path(dir, "tri.obj", p, sizeof p));
}

/* -q hides statistics, never warnings; --import-timeout sets the import child's time limit (a PLY header that
 * hangs assimp is stopped after 1 s and the message says so). */
static void test_quiet_and_import_timeout(void **state)
{
    (void)state;
    const char *err;
    char args[1200];
    snprintf(args, sizeof args, "tests/data/meshes/normals_bad.obj --size 16x16 -q -o %s/w.png", dir);
    assert_int_equal(run(args, &err), 0);
    assert_non_null(strstr(err, "instess: warning:"));
    assert_null(strstr(err, "triangles drawn"));
    snprintf(args, sizeof args, "tests/data/meshes/normals_bad.obj --size 16x16 -o %s/w.png", dir);
    assert_int_equal(run(args, &err), 0);
    assert_non_null(strstr(err, "triangles drawn"));
    snprintf(args, sizeof args, "tests/data/meshes/truncated_header.ply --import-timeout 1 -q -o %s/t.png", dir);
    assert_int_equal(run(args, &err), 1);
    print_message("  %s", err);
    assert_true(strstr(err, "within the import time limit of 1 s") || strstr(err, "ran out of the import memory"));
    assert_false(exists("t.png"));
    snprintf(args, sizeof args, "--import-timeout 0 -o %s/t.png", dir);
    assert_int_equal(run(args, &err), 2);
    char p[512];
    unlink(prog_path(dir, "w.png", p, sizeof p));
}

/* Output lost is a failure: --help, --version and --stats json into a full device exit 1 and say so. */
static void test_stdout_write_failure(void **state)
{
    (void)state;
    const char *bin = getenv("INSTESS_BIN") ? getenv("INSTESS_BIN") : "build/instess";
    char render[600];
    snprintf(render, sizeof render, "--mesh octahedron --size 16x16 --level 1 --stats json -o %s/full.png", dir);
    const char *const cmds[] = {"--help", "--version", render};
    for (int k = 0; k < 3; k++) {
        char cmd[1200], errfile[300];
        snprintf(errfile, sizeof errfile, "%s/stderr.txt", dir);
        snprintf(cmd, sizeof cmd, "%s %s >/dev/full 2>%s", bin, cmds[k], errfile);
        int st = system(cmd);
        assert_true(WIFEXITED(st));
        char err[1024] = "";
        FILE *f = fopen(errfile, "r");
        size_t n = f ? fread(err, 1, sizeof err - 1, f) : 0;
        if (f) fclose(f);
        err[n] = 0;
        if (WEXITSTATUS(st) != 1 || !strstr(err, "cannot write to standard output"))
            fail_msg("%s > /dev/full: exit %d: %s", cmds[k], WEXITSTATUS(st), err);
    }
}

/* -o or --export-obj naming the input mesh is refused: the mesh is never replaced. */
static void test_output_names_input(void **state)
{
    (void)state;
    char mesh[400], args[1200];
    snprintf(mesh, sizeof mesh, "%s/in.obj", dir);
    FILE *f = fopen(mesh, "w");
    assert_non_null(f);
    fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", f);
    fclose(f);
    const char *err;
    snprintf(args, sizeof args, "'%s' -q -o '%s/a.png' --export-obj '%s/./in.obj'", mesh, dir, dir);
    assert_int_equal(run(args, &err), 1);
    assert_non_null(strstr(err, "is the input mesh; instess will not replace its input"));
    struct stat st;
    assert_int_equal(stat(mesh, &st), 0);
    assert_int_equal((int)st.st_size, 32);   /* unchanged */
    assert_false(exists("a.png"));
}

/* --stats json is valid UTF-8 JSON whatever the mesh file's name: bytes that are not well-formed UTF-8
 * (an overlong form, a surrogate, a lone continuation byte) become U+FFFD. */
static void test_stats_json_utf8(void **state)
{
    (void)state;
    const char *bad[] = {"\xed\xa0\x80", "\xe0\x80\xaf", "\x80x", "\xf4\x90\x80\x80"};
    const char *bin = getenv("INSTESS_BIN") ? getenv("INSTESS_BIN") : "build/instess";
    for (int k = 0; k < 4; k++) {
        char mesh[400], cmd[1400], out[400];
        snprintf(mesh, sizeof mesh, "%s/%s.obj", dir, bad[k]);
        FILE *f = fopen(mesh, "w");
        assert_non_null(f);
        fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", f);
        fclose(f);
        snprintf(out, sizeof out, "%s/stats.json", dir);
        snprintf(cmd, sizeof cmd, "%s '%s' --size 16x16 --level 1 --stats json -o '%s/s.png' >'%s' 2>/dev/null", bin,
                 mesh, dir, out);
        assert_int_equal(system(cmd), 0);
        char text[8192];
        f = fopen(out, "rb");
        assert_non_null(f);
        size_t n = fread(text, 1, sizeof text - 1, f);
        fclose(f);
        text[n] = 0;
        assert_null(strstr(text, bad[k]));          /* the malformed bytes are not passed through */
        assert_non_null(strstr(text, "\\ufffd"));   /* they are replaced, escaped */
        unlink(mesh);
    }
}

/* --light X,Y,Z is a direction at every scale: 1e30,1e30,0 and 1e-30,1e-30,0 light as 1,1,0 does (the squares
 * once overflowed to a zero light, or fell under the "not 0,0,0" test); 0,0,0 and values beyond float are usage
 * errors naming what --light takes. */
static void test_light_any_scale(void **state)
{
    (void)state;
    const char *err;
    const char *const dirs[] = {"1,1,0", "1e30,1e30,0", "1e-30,1e-30,0"};
    for (int k = 0; k < 3; k++) {
        char args[600];
        snprintf(args, sizeof args, "--light %s --size 48x48 --level 3 -q -o %s/light%d.png", dirs[k], dir, k);
        assert_int_equal(run(args, &err), 0);
    }
    assert_true(same_pixels("light0.png", "light1.png"));
    assert_true(same_pixels("light0.png", "light2.png"));
    const char *const bad[] = {"0,0,0", "0,0,1e-50", "1e39,0,0", "nan,1,0"};
    for (int k = 0; k < 4; k++) {
        char args[600];
        snprintf(args, sizeof args, "--light %s -q -o %s/bad.png", bad[k], dir);
        assert_int_equal(run(args, &err), 2);
        assert_non_null(strstr(err, "a direction X,Y,Z of finite numbers, not all zero"));
    }
}

/* --lod's pattern cache is inside --max-memory: a budget the uniform render fits in refuses the adaptive one
 * (its cache may take 16 MiB and an index of 1 MiB), before anything is allocated or written. */
static void test_lod_memory_budget(void **state)
{
    (void)state;
    const char *err;
    char args[600];
    snprintf(args, sizeof args, "--max-memory 20 -q -o %s/uniform.png", dir);
    assert_int_equal(run(args, &err), 0);
    snprintf(args, sizeof args, "--lod screen --max-memory 20 -q -o %s/lod.png", dir);
    assert_int_equal(run(args, &err), 1);
    assert_non_null(strstr(err, "more than the memory budget of 20 MiB"));
    assert_false(exists("lod.png"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_usage_errors),
        cmocka_unit_test(test_input_errors),
        cmocka_unit_test(test_png_and_exr),
        cmocka_unit_test(test_displace),
        cmocka_unit_test(test_clamped_level_is_said),
        cmocka_unit_test(test_command_line_conventions),
        cmocka_unit_test(test_codec_loaded_on_demand),
        cmocka_unit_test(test_cull),
        cmocka_unit_test(test_progress_line),
        cmocka_unit_test(test_smoothness_mesh),
        cmocka_unit_test(test_up_and_fit),
        cmocka_unit_test(test_exr_channels),
        cmocka_unit_test(test_export_obj_frame),
        cmocka_unit_test(test_quiet_and_import_timeout),
        cmocka_unit_test(test_stdout_write_failure),
        cmocka_unit_test(test_output_names_input),
        cmocka_unit_test(test_stats_json_utf8),
        cmocka_unit_test(test_light_any_scale),
        cmocka_unit_test(test_lod_memory_budget),
    };
    return cmocka_run_group_tests_name("cli", tests, setup, teardown);
}
