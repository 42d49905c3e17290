/* tests/test_robustness.c -- the catalogue of bad input (docs/robustness.md), run through the real
 * program (build/instess, or $INSTESS_BIN as tests/test_cli.c does) on files written into a temporary folder:
 *  - input errors: exit 1, a message naming the input and what is wrong, and no file written;
 *  - usage errors (the ones tests/test_cli.c does not already try): exit 2, nothing written;
 *  - valid but odd meshes (huge and tiny coordinates, boundary edges, isolated vertices, inconsistent winding,
 *    non-manifold edges, degenerate triangles among good ones, zero and NaN normals): exit 0, the warning, and
 *    an EXR whose every value is finite with a sane number of covered pixels;
 *  - determinism: the same PNG bytes for --threads 1, 2, 4 and across runs; EXR pixels equal, and EXR bytes equal
 *    with SOURCE_DATE_EPOCH (OpenEXR files carry a DateTime);
 *  - atomic outputs: SIGTERM / SIGINT while rendering or while the temporary file is complete leave the previous
 *    image byte-identical and no temporary file; SIGKILL leaves the previous image intact (a stale temporary
 *    file may remain: nothing can clean up after SIGKILL);
 *  - killing instess while assimp hangs in the import child leaves no child running on. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <fcntl.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "../core/core.h"
#include "../image/image.h"
#include "util/prog.h"

int putenv(char *string);   /* POSIX (XSI), not declared under _POSIX_C_SOURCE alone */

static char dir[256];

/* The helpers of tests/util/prog.h on this file's work folder. */
static const char *program(void) { return prog_bin(); }
static const char *path_of(const char *name, char *buf, size_t len) { return prog_path(dir, name, buf, len); }
static void write_bytes(const char *name, const void *data, size_t n) { assert_true(prog_write_bytes(dir, name, data, n)); }
static void write_text(const char *name, const char *text) { assert_true(prog_write_text(dir, name, text)); }
static bool exists(const char *name) { return prog_exists(dir, name); }
static unsigned char *slurp(const char *path, size_t *n) { return prog_slurp(path, n); }

/* Run `instess ARGS` (fmt expanded; a shell command line) with stderr captured into *err_out (a static
 * buffer); returns the exit code (128 + signal when killed). */
static int run(const char **err_out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int run(const char **err_out, const char *fmt, ...)
{
    char args[3000];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    return prog_run(dir, err_out, "", "%s", args);
}

/* Number of entries of the work folder whose name contains `part` (NULL: all but stderr.txt). */
static int entries_with(const char *part)
{
    int n = prog_entries_with(dir, part);
    assert_true(n >= 0);
    return n;
}

/* Remove every file of the work folder (not folders). */
static void clear_dir(void)
{
    char cmd[400];
    snprintf(cmd, sizeof cmd, "find '%s' -mindepth 1 -maxdepth 1 ! -type d -delete", dir);
    assert_int_equal(system(cmd), 0);
}

static int setup(void **state)
{
    (void)state;
    return prog_mkdtemp(dir, "robust");
}

/* Work is bounded by the output (raster.h RS_MAX_OVERDRAW): 20000 copies of one triangle, which the camera
 * fits to the whole image, are refused within seconds (exit 1, the mesh and the bound named, nothing written);
 * 100 copies (overdraw about 50) still render. */
static void test_overdraw_bomb(void **state)
{
    (void)state;
    for (int copies = 100; copies <= 20000; copies += 19900) {
        size_t cap = 64 + (size_t)copies * 12, n = 0;
        char *obj = malloc(cap);
        assert_non_null(obj);
        n += (size_t)sprintf(obj, "v -1 -1 0\nv 1 -1 0\nv 0 1 0\n");
        for (int k = 0; k < copies; k++) n += (size_t)sprintf(obj + n, "f 1 2 3\n");
        write_text("bomb.obj", obj);
        free(obj);
        const char *err;
        char p[512];
        time_t t0 = time(NULL);
        int rc = run(&err, "--mesh '%s' --patch flat --level 4 --size 64x64 -o '%s/out.png'",
                     path_of("bomb.obj", p, sizeof p), dir);
        print_message("  %d copies: exit %d in %lds: %s", copies, rc, (long)(time(NULL) - t0), err);
        if (copies == 100) {
            assert_int_equal(rc, 0);
            assert_true(exists("out.png"));
        } else {
            assert_int_equal(rc, 1);
            assert_non_null(strstr(err, "bomb.obj"));
            assert_non_null(strstr(err, "more than 1024 times on average"));
            assert_false(exists("out.png"));
        }
        clear_dir();
    }
}

/* The memory budget (cli/run/scene.h SCENE_DEFAULT_MAX_MEMORY_MIB, --max-memory) is checked before anything is
 * allocated: the CPU path at level 128 (about 270 MiB by the estimate) is refused under a 100 MiB budget with
 * the estimate and the option named, and renders under the default; the instanced path needs no per-vertex
 * memory and renders under the smallest budget; a budget below 16 MiB is a usage error. */
static void test_memory_budget(void **state)
{
    (void)state;
    const char *err;
    int rc = run(&err, "--mesh sphere --patch npatch --path cpu --level 128 --size 32x32 --max-memory 100 -o '%s/a.png'",
                 dir);
    print_message("  cpu, 100 MiB: exit %d: %s", rc, err);
    assert_int_equal(rc, 1);
    assert_non_null(strstr(err, "more than the memory budget of 100 MiB (--max-memory MIB raises it)"));
    assert_false(exists("a.png"));
    assert_int_equal(run(&err, "--mesh sphere --patch npatch --path cpu --level 128 --size 32x32 -q -o '%s/a.png'", dir), 0);
    assert_int_equal(run(&err, "--mesh sphere --patch npatch --level 128 --size 32x32 --max-memory 16 -q -o '%s/b.png'",
                         dir), 0);
    assert_int_equal(run(&err, "--max-memory 8 -o '%s/c.png'", dir), 2);
    assert_false(exists("c.png"));
    clear_dir();
}

static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

/* ------------------------------------------------ mesh files ------------------------------------------------ */

/* An octahedron of radius s centred at (c, c, c) as OBJ text (counter-clockwise from outside, OBJ's
 * convention), followed by `extra` lines. */
static void octahedron_obj(char *buf, size_t len, double s, double c, const char *extra)
{
    const double v[6][3] = {{s, 0, 0}, {-s, 0, 0}, {0, s, 0}, {0, -s, 0}, {0, 0, s}, {0, 0, -s}};
    size_t n = 0;
    for (int k = 0; k < 6; k++)
        n += (size_t)snprintf(buf + n, len - n, "v %.9g %.9g %.9g\n", v[k][0] + c, v[k][1] + c, v[k][2] + c);
    for (int x = 0; x < 2; x++)
        for (int y = 2; y < 4; y++)
            for (int z = 4; z < 6; z++) {
                bool ccw = ((x == 0) == (y == 2)) == (z == 4);
                n += (size_t)snprintf(buf + n, len - n, "f %d %d %d\n", x + 1, (ccw ? y : z) + 1, (ccw ? z : y) + 1);
            }
    snprintf(buf + n, len - n, "%s", extra);
}

/* Deterministic garbage bytes (xorshift). */
static void garbage(unsigned char *buf, size_t n, uint32_t seed)
{
    for (size_t k = 0; k < n; k++) {
        seed ^= seed << 13, seed ^= seed >> 17, seed ^= seed << 5;
        buf[k] = (unsigned char)seed;
    }
}

/* A binary little-endian PLY tetrahedron cut after `keep` bytes of its body. */
static size_t truncated_ply(unsigned char *buf, size_t keep)
{
    const char *hdr = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
    size_t n = strlen(hdr);
    memcpy(buf, hdr, n);
    const float p[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    memcpy(buf + n, p, sizeof p);
    size_t body = sizeof p;
    const int f[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    for (int t = 0; t < 4; t++) {
        buf[n + body++] = 3;
        memcpy(buf + n + body, f[t], 12);
        body += 12;
    }
    return n + (keep < body ? keep : body);
}

/* A binary STL whose header announces `announced` triangles but holds `present`. */
static size_t truncated_stl(unsigned char *buf, uint32_t announced, uint32_t present)
{
    memset(buf, ' ', 80);
    memcpy(buf, "binary stl", 10);
    memcpy(buf + 80, &announced, 4);
    size_t n = 84;
    for (uint32_t t = 0; t < present; t++) {
        const float tri[12] = {0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0};
        memcpy(buf + n, tri, sizeof tri);
        buf[n + 48] = buf[n + 49] = 0;
        n += 50;
    }
    return n;
}

/* ------------------------------------------------ the catalogue: input errors ------------------------------------------------ */

/* Run the program on mesh file dir/name and expect exit code rc, a message naming the file and containing
 * `what`, and no output written. */
static void expect_input_error(const char *name, int rc, const char *what)
{
    const char *err;
    char p[512];
    int got = run(&err, "--mesh '%s' --level 2 --size 32x32 -o '%s/out.png'", path_of(name, p, sizeof p), dir);
    print_message("  %-22s exit %d: %s", name, got, err);
    if (got != rc || !strstr(err, name) || !strstr(err, what))
        fail_msg("%s: wanted exit %d and a message with '%s', got exit %d: %s", name, rc, what, got, err);
    assert_false(exists("out.png"));
    assert_int_equal(entries_with(".instess-"), 0);
}

/* Missing pieces of files, and files that are not meshes. */
static void test_bad_files(void **state)
{
    (void)state;
    unsigned char buf[4096];
    write_text("empty.obj", "");
    expect_input_error("empty.obj", 1, "empty file");
    write_text("blank.obj", "\n   \n# only a comment\n");
    expect_input_error("blank.obj", 1, "cannot read the mesh");
    write_text("truncated.obj", "v 0 0 0\nv 1 0 0\nv 0 1");
    expect_input_error("truncated.obj", 1, "cannot read the mesh");
    write_bytes("truncated.ply", buf, truncated_ply(buf, 30));
    expect_input_error("truncated.ply", 1, "truncated.ply: ");
    write_bytes("truncated_faces.ply", buf, truncated_ply(buf, 60));
    expect_input_error("truncated_faces.ply", 1, "truncated_faces.ply: ");
    write_bytes("truncated.stl", buf, truncated_stl(buf, 12, 2));
    expect_input_error("truncated.stl", 1, "cannot read the mesh");
    const char *exts[] = {"garbage.obj", "garbage.ply", "garbage.stl", "garbage.off", "garbage.md2", "garbage.glb"};
    for (size_t k = 0; k < sizeof exts / sizeof exts[0]; k++) {
        garbage(buf, sizeof buf, 12345u + (uint32_t)k);
        write_bytes(exts[k], buf, sizeof buf);
        expect_input_error(exts[k], 1, "cannot read the mesh");
    }
    write_text("mesh.xyz", "v 0 0 0\n");
    expect_input_error("mesh.xyz", 1, "unknown mesh format '.xyz'");
    write_text("noextension", "v 0 0 0\n");
    expect_input_error("noextension", 1, "no file extension");
    char p[512];
    assert_int_equal(mkdir(path_of("folder.obj", p, sizeof p), 0755), 0);
    expect_input_error("folder.obj", 1, "is a directory");
    rmdir(p);
    /* assimp 5.2.5 aborts on this PLY (tests/test_meshes.c): the child process turns it into an error */
    size_t n;
    unsigned char *abort_ply = slurp("tests/data/meshes/assimp_abort.ply", &n);
    assert_non_null(abort_ply);
    write_bytes("assimp_abort.ply", abort_ply, n);
    free(abort_ply);
    expect_input_error("assimp_abort.ply", 1, "assimp crashed on it (signal 6");
    /* and segfaults on this binary PLY, found by the import fuzzer (tests/fuzz/regressions/import-assimp/) */
    unsigned char *segv_ply = slurp("tests/fuzz/regressions/import-assimp/assimp_segv_ply_binary.ply", &n);
    assert_non_null(segv_ply);
    write_bytes("assimp_segv.ply", segv_ply, n);
    free(segv_ply);
    expect_input_error("assimp_segv.ply", 1, "assimp crashed on it (signal 11");
    clear_dir();
}

/* Files that parse but hold no usable triangles, or invalid numbers. */
static void test_bad_contents(void **state)
{
    (void)state;
    write_text("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n");
    expect_input_error("points.obj", 1, "no triangles");
    write_text("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n");
    expect_input_error("lines.obj", 1, "no triangles");
    write_text("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_input_error("nan.obj", 1, "vertex 1 has a non-finite position (nan, 0, 0)");
    write_text("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n");
    expect_input_error("inf.obj", 1, "vertex 2 has a non-finite position (0, -inf, 0)");
    write_text("overflow.obj", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n");   /* beyond float: inf */
    expect_input_error("overflow.obj", 1, "non-finite position");
    write_text("degenerate.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 0 0\nf 1 2 3\nf 1 4 2\nf 1 1 2\n");
    expect_input_error("degenerate.obj", 1, "no triangles left: all 3 are degenerate");
    char text[2048];
    octahedron_obj(text, sizeof text, 1e-30, 1.0, "");   /* 1 + 1e-30 rounds to 1: every vertex coincides */
    write_text("collapsed.obj", text);
    expect_input_error("collapsed.obj", 1, "all 8 are degenerate");
    write_text("badindex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    expect_input_error("badindex.obj", 1, "badindex.obj: ");
    clear_dir();
}

/* Built-in names, tessellation budget and output paths: exit 1 naming the input. */
static void test_bad_inputs_other(void **state)
{
    (void)state;
    const char *err;
    assert_int_equal(run(&err, "--mesh dodecahedron -o '%s/out.png'", dir), 1);
    assert_non_null(strstr(err, "dodecahedron: neither a built-in mesh"));
    /* 4096 triangles at level 256 = 135 M vertices, over the 64 M budget: refused before anything is allocated */
    char *obj = malloc(1 << 20);
    assert_non_null(obj);
    size_t n = 0;
    for (int j = 0; j <= 32; j++)
        for (int i = 0; i <= 64; i++) n += (size_t)sprintf(obj + n, "v %d %d 0\n", i, j);
    for (int j = 0; j < 32; j++)
        for (int i = 0; i < 64; i++) {
            int a = j * 65 + i + 1;
            n += (size_t)sprintf(obj + n, "f %d %d %d\nf %d %d %d\n", a, a + 1, a + 66, a, a + 66, a + 65);
        }
    write_text("grid.obj", obj);
    free(obj);
    char p[512];
    assert_int_equal(run(&err, "--mesh %s --level 256 -o '%s/out.png'", path_of("grid.obj", p, sizeof p), dir), 1);
    assert_non_null(strstr(err, "grid.obj: 4096 triangles at level 256 need"));
    assert_non_null(strstr(err, "more than the limit"));
    assert_false(exists("out.png"));
    /* an output folder that does not exist */
    assert_int_equal(run(&err, "--mesh cube --level 1 --size 16x16 -o '%s/no/such/out.png'", dir), 1);
    assert_non_null(strstr(err, "no/such/out.png"));
    assert_non_null(strstr(err, "cannot create a file in the folder"));
    clear_dir();
}

/* Usage errors beyond tests/test_cli.c's: exit 2 and nothing written. */
static void test_bad_arguments(void **state)
{
    (void)state;
    const char *bad[] = {
        "--level nan", "--level inf", "--level 257", "--level 0.5", "--level 1e-30", "--level ''", "--level 4x",
        "--size 10x", "--size x10", "--size -5x5", "--size 16385x1", "--size 16384x16384", "--size 10x10x10",
        "--size 0x0", "--size 0x7", "--size 99999999999999999999x1", "--distance 0",
        "--distance nan", "--distance 1", "--threads 1000", "--threads 1.5", "--msaa 2", "--msaa 0", "--msaa",
        "--mesh", "--grid hex", "--path gpu", "--normals cubic", "--yaw 1e40", "--pitch nan", "--export-obj",
        "--fill", "--grid pg-fractional-odd --level 2.5 --path npatch-mode --patch npatch", "-x", "--level=3 --level=abc"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        const char *err;
        int rc = run(&err, "%s -o '%s/out.png'", bad[k], dir);
        if (rc != 2 || !strstr(err, "instess: ")) fail_msg("'%s' gave exit %d: %s", bad[k], rc, err);
        assert_int_equal(entries_with(NULL), 0);
    }
    const char *err;
    assert_int_equal(run(&err, "--aov bogus -o '%s/out.exr'", dir), 2);
    assert_non_null(strstr(err, "--aov"));
    assert_int_equal(run(&err, "--aov '' -o '%s/out.exr'", dir), 2);
    assert_int_equal(run(&err, "--mesh cube -o"), 2);
    assert_int_equal(run(&err, "--mesh cube -o '%s/out.tiff'", dir), 2);
    assert_int_equal(entries_with(NULL), 0);
}

/* ------------------------------------------------ valid but odd ------------------------------------------------ */

/* Index of channel `name` in img, or fail. */
static int channel(const is_image *img, const char *name)
{
    for (int c = 0; c < img->channels; c++)
        if (!strcmp(img->channel_names[c], name)) return c;
    fail_msg("no channel %s", name);
    return -1;
}

/* Render dir/name with extra options into an EXR with AOVs: exit 0, every value finite, colour and depth in
 * [0, 1]; returns the covered pixels (depth below 1); *warnings gets stderr. */
static long render_odd(const char *name, const char *opts, const char **warnings)
{
    char p[512], out[512];
    unlink(path_of("odd.exr", out, sizeof out));
    int rc = run(warnings, "--mesh '%s' %s --size 64x64 --msaa 1 --aov normal,bary,gregory -o '%s'",
                 path_of(name, p, sizeof p), opts, out);
    if (rc != 0) fail_msg("%s %s: exit %d: %s", name, opts, rc, *warnings);
    is_image img = {0};
    char err[512];
    assert_int_equal(image_read(&img, out, err, sizeof err), 0);
    int z = channel(&img, "Z");
    long covered = 0;
    for (long k = 0; k < (long)img.width * img.height; k++)
        for (int c = 0; c < img.channels; c++) {
            float v = img.data[k * img.channels + c];
            bool rgbaz = strlen(img.channel_names[c]) == 1;
            if (!isfinite(v) || (rgbaz && (v < 0.0f || v > 1.0f)))
                fail_msg("%s %s: pixel %ld channel %s = %g", name, opts, k, img.channel_names[c], (double)v);
            if (c == z) covered += v < 1.0f;
        }
    image_free(&img);
    return covered;
}

/* The patches and normal modes every odd mesh is drawn with. */
static const char *const odd_opts[] = {
    "--patch smooth --level 5", "--patch npatch --normals quadratic --level 4", "--patch pn-aen --normals real",
    "--patch phong --normals real --fill solid+wire", "--patch smooth-initial --grid pg-fractional-odd --level 3.3",
    "--patch npatch --path cpu --level 3", "--patch npatch --path npatch-mode --normals quadratic --level 3"};
#define N_ODD (sizeof odd_opts / sizeof odd_opts[0])

/* Huge, tiny and far-away octahedra render like the unit one (the scene scales by the bounding radius). */
static void test_huge_and_tiny_coordinates(void **state)
{
    (void)state;
    char text[4096];
    const struct { const char *name; double s, c; } meshes[] = {
        {"unit.obj", 1, 0}, {"huge.obj", 1e30, 0}, {"tiny.obj", 1e-30, 0}, {"far.obj", 1e37, 2e38},
        {"max.obj", 3.4e38, 0}, {"offset.obj", 100, 1e6}};
    long unit[N_ODD];
    for (size_t m = 0; m < sizeof meshes / sizeof meshes[0]; m++) {
        octahedron_obj(text, sizeof text, meshes[m].s, meshes[m].c, "");
        write_text(meshes[m].name, text);
        for (size_t k = 0; k < N_ODD; k++) {
            const char *w;
            long cov = render_odd(meshes[m].name, odd_opts[k], &w);
            if (m == 0) unit[k] = cov;
            print_message("  %-10s %-62s %4ld px (unit %ld)\n", meshes[m].name, odd_opts[k], cov, unit[k]);
            assert_true(cov > 64 * 64 / 20 && cov < 64 * 64 * 3 / 4);
            assert_true(labs(cov - unit[k]) <= 64 * 64 / 50);
        }
    }
    clear_dir();
}

/* Open, non-manifold, isolated, inconsistent, degenerate and bad-normal meshes: exit 0 with the warning. */
static void test_odd_topology(void **state)
{
    (void)state;
    char text[4096];
    const struct { const char *name, *extra, *warning; double s; } cases[] = {
        /* boundary edges: the octahedron without its last two faces (4 boundary edges) */
        {"open.obj", NULL, NULL, 1},
        /* isolated vertices: not used by any triangle, dropped without changing the framing */
        {"isolated.obj", "v 1000 1000 1000\nv -7 3 2\nv nan 0 0\n", NULL, 1},
        /* a fin on edge 1-3: that edge has three triangles */
        {"fin.obj", "v 2 2 0\nf 1 3 7\n", "non-manifold edge", 1},
        /* inconsistent winding: two faces reversed */
        {"flipped.obj", NULL, "inconsistently wound", 1},
        /* degenerate triangles among good ones: repeated vertex, zero area, collinear */
        {"degenerates.obj", "v 0.5 0 0\nf 1 1 3\nf 1 2 1\nf 1 7 2\n", "dropped 3 degenerate", 1},
        /* zero and NaN normals: replaced by recomputed ones */
        {"normals.obj", NULL, "replaced", 1},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        octahedron_obj(text, sizeof text, cases[k].s, 0, cases[k].extra ? cases[k].extra : "");
        if (!strcmp(cases[k].name, "open.obj")) *strstr(text, "f 2 4 5") = 0;   /* drop the last faces */
        if (!strcmp(cases[k].name, "flipped.obj")) {
            char *f = strstr(text, "f 1 3 5"), *g = strstr(text, "f 2 3 6");
            assert_true(f && g);
            memcpy(f, "f 1 5 3", 7), memcpy(g, "f 2 6 3", 7);
        }
        if (!strcmp(cases[k].name, "normals.obj")) {
            char with[4096] = "vn 0 0 0\nvn nan 0 0\nvn 0.5 0.5 0.5\n";
            for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
                size_t n = strlen(with);
                int a, b, c;
                if (sscanf(line, "f %d %d %d", &a, &b, &c) == 3)
                    snprintf(with + n, sizeof with - n, "f %d//1 %d//2 %d//3\n", a, b, c);
                else snprintf(with + n, sizeof with - n, "%s\n", line);
            }
            snprintf(text, sizeof text, "%s", with);
        }
        write_text(cases[k].name, text);
        for (size_t o = 0; o < N_ODD; o++) {
            const char *w;
            long cov = render_odd(cases[k].name, odd_opts[o], &w);
            print_message("  %-16s %-62s %4ld px\n", cases[k].name, odd_opts[o], cov);
            assert_true(cov > 64 * 64 / 40 && cov < 64 * 64 * 3 / 4);
            if (cases[k].warning && (!strstr(w, cases[k].warning) || !strstr(w, cases[k].name)))
                fail_msg("%s: no warning '%s' in: %s", cases[k].name, cases[k].warning, w);
        }
    }
    clear_dir();
}

/* ------------------------------------------------ determinism ------------------------------------------------ */

/* Whether two files hold the same bytes. */
static bool same_bytes(const char *a, const char *b) { return prog_same_bytes(a, b); }


/* Render `scene` with --threads t into dir/out.EXT and move it to dir/NAME. */
static void render_as(const char *scene, int t, const char *ext, const char *name)
{
    char out[512], to[512];
    path_of("out.", out, sizeof out);
    strncat(out, ext, sizeof out - strlen(out) - 1);
    assert_int_equal(run(NULL, "%s --threads %d -q -o '%s'", scene, t, out), 0);
    assert_int_equal(rename(out, path_of(name, to, sizeof to)), 0);
}

/* Same render, same bytes: PNG and EXR files are byte-identical across runs, output names and --threads 1, 2,
 * 4, with no SOURCE_DATE_EPOCH (the file stores a canonical description of the render, scene_describe, and no
 * time); SOURCE_DATE_EPOCH, when given, stamps that time (the same bytes a second later). */
static void test_determinism(void **state)
{
    (void)state;
    const char *scenes[] = {"--mesh sphere --patch smooth --level 6 --size 160x120 --fill solid+wire",
                            "--mesh cylinder --patch pn-aen --normals real --level 5 --size 128x128",
                            "--mesh icosahedron --patch npatch --path cpu --level 5 --size 128x96 --msaa 1"};
    char a[512], b[512];
    for (size_t s = 0; s < 3; s++) {
        render_as(scenes[s], 1, "png", "t1.png");
        render_as(scenes[s], 2, "png", "t2.png");
        render_as(scenes[s], 4, "png", "t4.png");
        render_as(scenes[s], 4, "png", "t4b.png");
        render_as(scenes[s], 1, "png", "t1b.png");
        const char *others[] = {"t2.png", "t4.png", "t4b.png", "t1b.png"};
        for (int k = 0; k < 4; k++)
            assert_true(same_bytes(path_of("t1.png", a, sizeof a), path_of(others[k], b, sizeof b)));
    }
    const char *exr = "--mesh tetrahedron --patch smooth --level 5 --size 96x96 --msaa 1 --aov normal,bary,instance,gregory";
    render_as(exr, 1, "exr", "e1.exr");
    sleep(1);                                   /* a different second: no time may be stored */
    render_as(exr, 4, "exr", "e4.exr");
    assert_true(same_bytes(path_of("e1.exr", a, sizeof a), path_of("e4.exr", b, sizeof b)));
    setenv("SOURCE_DATE_EPOCH", "1700000000", 1);
    render_as(exr, 2, "exr", "s1.exr");
    sleep(1);                                   /* a different second: only the fixed DateTime makes them equal */
    render_as(exr, 2, "exr", "s2.exr");
    unsetenv("SOURCE_DATE_EPOCH");
    assert_true(same_bytes(path_of("s1.exr", a, sizeof a), path_of("s2.exr", b, sizeof b)));
    assert_true(prog_same_pixels(a, path_of("e1.exr", b, sizeof b)));
    clear_dir();
}

/* ------------------------------------------------ atomic outputs ------------------------------------------------ */

/* Start `instess ARGS...` (NULL-terminated) with the environment variable env (NAME=VALUE, may be NULL: a test
 * hook, so then the test build with the hooks runs). */
static pid_t spawn(const char *env, const char *const *args)
{
    pid_t pid = fork();
    if (pid == 0) {
        if (env) putenv((char *)env);
        int fd = open("/dev/null", O_WRONLY);
        if (fd >= 0) dup2(fd, STDERR_FILENO);
        const char *bin = env ? prog_hooks_bin() : program();
        const char *argv[32] = {bin};
        for (int k = 0; args[k] && k < 30; k++) argv[k + 1] = args[k];
        execv(bin, (char *const *)argv);
        _exit(127);
    }
    return pid;
}

/* Sleep ms milliseconds. */
static void sleep_ms(long ms)
{
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

/* Wait up to ms for a file whose name contains part to appear in the work folder; whether it did. */
static bool wait_for_entry(const char *part, long ms)
{
    for (long t = 0; t < ms; t += 10) {
        if (entries_with(part) > 0) return true;
        sleep_ms(10);
    }
    return false;
}

/* Kill a render of keep.png with sig, either while it renders (delay_ms after the start) or while its
 * temporary file is complete (INSTESS_TEST_WRITE_DELAY_MS); keep.png must be byte-identical afterwards and,
 * for catchable signals, no temporary file may remain. */
static void kill_render(int sig, bool in_write, long delay_ms)
{
    char keep[512], saved[512];
    path_of("keep.png", keep, sizeof keep);
    path_of("saved.png", saved, sizeof saved);
    const char *const args[] = {"--mesh", "sphere", "--patch", "smooth", "--level", "48", "--size", "4096x4096",
                                "--threads", "1", "-q", "-o", keep, NULL};
    const char *const small[] = {"--mesh", "sphere", "--patch", "smooth", "--level", "2", "--size", "300x300",
                                 "--threads", "1", "-q", "-o", keep, NULL};
    pid_t pid = spawn(in_write ? "INSTESS_TEST_WRITE_DELAY_MS=20000" : NULL, in_write ? small : args);
    assert_true(pid > 0);
    if (in_write) assert_true(wait_for_entry(".instess-", 20000));
    else sleep_ms(delay_ms);
    assert_int_equal(kill(pid, sig), 0);
    int st;
    assert_int_equal(waitpid(pid, &st, 0), pid);
    if (!WIFSIGNALED(st) || WTERMSIG(st) != sig)
        fail_msg("signal %d (%s): the program ended with status 0x%x", sig, in_write ? "writing" : "rendering", st);
    assert_true(same_bytes(keep, saved));
    int stale = entries_with(".instess-");
    print_message("  signal %2d while %-9s: previous image intact, %d temporary file(s) left\n", sig,
                  in_write ? "writing" : "rendering", stale);
    if (sig != SIGKILL) assert_int_equal(stale, 0);
    else if (in_write) assert_int_equal(stale, 1);   /* documented: nothing can remove it after SIGKILL */
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -f %s/.instess-*", dir);
    assert_int_equal(system(cmd), 0);
}

/* SIGTERM, SIGINT and SIGKILL during a big render and during the write leave the previous image intact. */
static void test_atomic_output(void **state)
{
    (void)state;
    char keep[512], saved[512];
    assert_int_equal(run(NULL, "--mesh cube --level 2 --size 64x64 -q -o '%s'", path_of("keep.png", keep, sizeof keep)), 0);
    size_t n;
    unsigned char *bytes = slurp(keep, &n);
    assert_non_null(bytes);
    write_bytes("saved.png", bytes, n);
    free(bytes);
    path_of("saved.png", saved, sizeof saved);
    const int sigs[] = {SIGTERM, SIGINT, SIGKILL};
    for (int k = 0; k < 3; k++) {
        kill_render(sigs[k], false, 300);
        kill_render(sigs[k], true, 0);
    }
    /* a failed render keeps the previous image too (an input error after a good image) */
    assert_int_equal(run(NULL, "--mesh '%s/missing.obj' -q -o '%s'", dir, keep), 1);
    assert_true(same_bytes(keep, saved));
    clear_dir();
}

/* The first child process of pid (from /proc), or 0. */
static pid_t first_child(pid_t pid)
{
    char p[128];
    snprintf(p, sizeof p, "/proc/%d/task/%d/children", (int)pid, (int)pid);
    FILE *f = fopen(p, "r");
    int c = 0;
    if (f) {
        if (fscanf(f, "%d", &c) != 1) c = 0;
        fclose(f);
    }
    return (pid_t)c;
}

/* Whether process pid exists, is not a zombie, and has `part` in its command line. */
static bool runs_with(pid_t pid, const char *part)
{
    char p[64], buf[4097], st[512];
    snprintf(p, sizeof p, "/proc/%d/stat", (int)pid);
    FILE *f = fopen(p, "r");
    if (!f) return false;
    size_t n = fread(st, 1, sizeof st - 1, f);
    fclose(f);
    st[n] = 0;
    const char *close_paren = strrchr(st, ')');
    if (!close_paren || close_paren[1] == 0 || close_paren[2] == 'Z') return false;
    snprintf(p, sizeof p, "/proc/%d/cmdline", (int)pid);
    if (!(f = fopen(p, "r"))) return false;
    n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    for (size_t k = 0; k < n; k++) if (buf[k] == 0) buf[k] = ' ';
    buf[n] = 0;
    return strstr(buf, part) != NULL;
}

/* Killing instess (SIGTERM or SIGKILL) while assimp hangs in its import child leaves no child running on. */
static void test_no_orphan_import(void **state)
{
    (void)state;
    char out[512];
    const char *const args[] = {"--mesh", "tests/fuzz/regressions/import-assimp/assimp_hang_ply_binary.ply", "-q",
                                "-o", path_of("out.png", out, sizeof out), NULL};
    const int sigs[] = {SIGTERM, SIGKILL};
    for (int k = 0; k < 2; k++) {
        pid_t pid = spawn(NULL, args), child = 0;
        for (int t = 0; t < 500 && !child; t++) child = first_child(pid), sleep_ms(10);
        assert_true(child > 0);
        assert_int_equal(kill(pid, sigs[k]), 0);
        int st;
        assert_int_equal(waitpid(pid, &st, 0), pid);
        bool gone = false;
        for (int t = 0; t < 300 && !gone; t++) {
            gone = !runs_with(child, "assimp_hang_ply_binary");   /* exited (or its pid was reused) */
            if (!gone) sleep_ms(10);
        }
        print_message("  signal %d to instess during a hung import: child %d %s\n", sigs[k], (int)child,
                      gone ? "gone" : "STILL RUNNING");
        if (!gone) kill(child, SIGKILL);
        assert_true(gone);
        assert_false(exists("out.png"));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_files),
        cmocka_unit_test(test_bad_contents),
        cmocka_unit_test(test_bad_inputs_other),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_huge_and_tiny_coordinates),
        cmocka_unit_test(test_odd_topology),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_atomic_output),
        cmocka_unit_test(test_no_orphan_import),
        cmocka_unit_test(test_overdraw_bomb),
        cmocka_unit_test(test_memory_budget),
    };
    return cmocka_run_group_tests_name("robustness", tests, setup, teardown);
}
