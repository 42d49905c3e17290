/* tests/test_hostile_meshes.c -- hostile mesh input, round 2 (docs/robustness.md, "Threat model: inputs"), run
 * through the real program (build/instess, or $INSTESS_BIN, which `make sanitize` points at the ASan build) on
 * files written into a temporary folder:
 *  - side files stay inside the mesh's folder: glTF buffers outside it (../, through a symlink, at /dev/zero,
 *    /dev/stdin), at a FIFO or a socket, or missing are clear errors; an OBJ's mtllib is never read (not
 *    outside the folder, not at a FIFO, whose open would block the import), and no byte of a foreign file
 *    reaches the messages;
 *  - resource bombs are refused by size before anything large happens: PLY and OFF headers that declare more
 *    than the body can hold or than the limits, a sparse 4 GiB file, a glTF node graph that assimp expands to
 *    millions of nodes (the import child's memory limit);
 *  - with `ulimit -n 5` (and 4) a file that crashes assimp is still a clear error, not a SIGSEGV;
 *  - the same OBJ at scale 1, 1e-6, 1e-12, 1e-30, 1e6 and 1e20 renders the same image (npatch and smooth);
 *  - facet normals and normals against the winding are warned about, with --recompute-normals as the fix;
 *  - odd OBJ files (negative indices, n-gons, normals on some faces, coordinates near FLT_MAX and denormal,
 *    duplicated and flipped faces, a 10,000-triangle fan, a Moebius strip, two cones touching at their tips)
 *    give a finite, non-empty image; odd paths (a directory, a FIFO, /dev/zero, a symlink loop, a name that
 *    starts with '-') a clear error or the image.
 * Every error case checks: exit 1, a message naming the file, no output file and no temporary file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "util/prog.h"
#include "../core/core.h"
#include "../image/image.h"

char *realpath(const char *restrict path, char *restrict resolved);   /* POSIX (XSI) */

static char dir[256];    /* the work folder: dir/m holds the meshes, dir itself the "foreign" files */
static char bin[PATH_MAX];

/* The program under test, as an absolute path (some cases run it from another folder). */
static const char *program(void)
{
    if (!bin[0]) {
        const char *p = getenv("INSTESS_BIN") ? getenv("INSTESS_BIN") : "build/instess";
        if (!realpath(p, bin)) snprintf(bin, sizeof bin, "%s", p);
    }
    return bin;
}

/* Seconds on the monotonic clock. */
static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Run the shell command (printf-style) with stderr captured into *err_out (a static buffer) and stdin from
 * /dev/null; returns the exit code (128 + signal when killed); *seconds (may be NULL) gets the wall time. */
static int shell(const char **err_out, double *seconds, const char *fmt, ...)
{
    static char errbuf[16384];
    char cmd[6000], line[6400], errfile[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    snprintf(errfile, sizeof errfile, "%s/stderr.txt", dir);
    snprintf(line, sizeof line, "%s 2>'%s' >/dev/null </dev/null", cmd, errfile);
    double t0 = now_s();
    int st = system(line);
    if (seconds) *seconds = now_s() - t0;
    prog_read_text(dir, "stderr.txt", errbuf, sizeof errbuf);
    if (err_out) *err_out = errbuf;
    return prog_exit_code(st);
}

/* The helpers of tests/util/prog.h on this file's work folder. */
static const char *path_of(const char *name, char *buf, size_t len) { return prog_path(dir, name, buf, len); }
static void write_bytes(const char *name, const void *data, size_t n) { assert_true(prog_write_bytes(dir, name, data, n)); }
static void write_text(const char *name, const char *text) { assert_true(prog_write_text(dir, name, text)); }
static bool exists(const char *name) { return prog_exists(dir, name); }

/* Number of entries of folder dir/sub whose name contains `part`. */
static int entries_with(const char *sub, const char *part)
{
    char p[512];
    DIR *d = opendir(path_of(sub, p, sizeof p));
    assert_non_null(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d));) n += strstr(e->d_name, part) != NULL;
    closedir(d);
    return n;
}

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/instess-hostile-XXXXXX");
    if (!mkdtemp(dir)) return -1;
    char p[512];
    return mkdir(path_of("m", p, sizeof p), 0755);
}

static int teardown(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

/* ------------------------ expectations ------------------------ */

/* The program on mesh `mesh` (a path, or a name under dir) with `opts`, PNG output dir/m/out.png: exit 1, a
 * message that names `mesh`, contains `what` and no byte of `never` (may be NULL), no output and no temporary
 * file; returns the wall time. */
static double expect_error(const char *mesh, const char *opts, const char *what, const char *never)
{
    const char *err;
    char p[512], out[512];
    const char *m = mesh[0] == '/' ? mesh : path_of(mesh, p, sizeof p);
    double s;
    int rc = shell(&err, &s, "'%s' --mesh '%s' %s --level 2 --size 32x32 --msaa 1 -o '%s'", program(), m, opts,
                   path_of("m/out.png", out, sizeof out));
    print_message("  %-22s exit %d, %.2f s: %s", mesh, rc, s, err);
    if (rc != 1 || !strstr(err, mesh) || !strstr(err, what))
        fail_msg("%s: wanted exit 1 and a message naming it with '%s', got exit %d: %s", mesh, what, rc, err);
    if (never && strstr(err, never)) fail_msg("%s: the message shows a foreign file's content: %s", mesh, err);
    assert_false(exists("m/out.png"));
    assert_int_equal(entries_with("m", ".tmp-"), 0);
    return s;
}

/* Index of channel `name` in img, or fail. */
static int channel(const is_image *img, const char *name)
{
    for (int c = 0; c < img->channels; c++)
        if (!strcmp(img->channel_names[c], name)) return c;
    fail_msg("no channel %s", name);
    return -1;
}

/* Read an EXR rendered with depth: every value finite, colour and depth in [0, 1]; the covered pixels. */
static long covered_pixels(const char *path, const char *what)
{
    is_image img = {0};
    char err[512];
    if (image_read(&img, path, err, sizeof err) != 0) fail_msg("%s: %s", what, err);
    int z = channel(&img, "Z");
    long covered = 0;
    for (long k = 0; k < (long)img.width * img.height; k++)
        for (int c = 0; c < img.channels; c++) {
            float v = img.data[k * img.channels + c];
            bool rgbaz = strlen(img.channel_names[c]) == 1;
            if (!isfinite(v) || (rgbaz && (v < 0.0f || v > 1.0f)))
                fail_msg("%s: pixel %ld channel %s = %g", what, k, img.channel_names[c], (double)v);
            if (c == z) covered += v < 1.0f;
        }
    image_free(&img);
    return covered;
}

/* The program on dir/`mesh` with `opts` into an EXR with AOVs: exit 0, a finite image with covered pixels;
 * *warnings gets stderr.  Returns the covered pixels. */
static long expect_image(const char *mesh, const char *opts, const char **warnings)
{
    char p[512], out[512];
    unlink(path_of("m/odd.exr", out, sizeof out));
    int rc = shell(warnings, NULL, "'%s' --mesh '%s' %s --size 48x48 --msaa 1 --aov normal,bary -o '%s'", program(),
                   path_of(mesh, p, sizeof p), opts, out);
    if (rc != 0) fail_msg("%s %s: exit %d: %s", mesh, opts, rc, *warnings);
    long cov = covered_pixels(out, mesh);
    print_message("  %-24s %-40s %4ld px covered\n", mesh, opts, cov);
    if (cov <= 0) fail_msg("%s %s: empty image", mesh, opts);
    return cov;
}

/* ------------------------ glTF files ------------------------ */

/* The tetrahedron's buffer: 4 float3 positions, then 12 uint16 indices (counter-clockwise from outside). */
static size_t tet_buffer(unsigned char *buf)
{
    const float p[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    const uint16_t idx[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    memcpy(buf, p, sizeof p);
    memcpy(buf + sizeof p, idx, sizeof idx);
    return sizeof p + sizeof idx;
}


/* A glTF 2.0 tetrahedron whose buffer is `uri` (NULL: a buffer without one), with `nodes` (a JSON array;
 * NULL: one node with the mesh). */
static void write_gltf(const char *name, const char *uri, const char *nodes)
{
    char text[8192], buffer[512];
    if (uri) snprintf(buffer, sizeof buffer, "\"uri\":\"%s\",", uri);
    else buffer[0] = 0;
    snprintf(text, sizeof text,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{%s\"byteLength\":72}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":24}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
             "\"min\":[-1,-1,-1],\"max\":[1,1,1]},{\"bufferView\":1,\"componentType\":5123,\"count\":12,"
             "\"type\":\"SCALAR\"}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
             "\"nodes\":%s,\"scenes\":[{\"nodes\":[0]}],\"scene\":0}",
             buffer, nodes ? nodes : "[{\"mesh\":0}]");
    write_text(name, text);
}

/* A UNIX socket bound at dir/name (left open until the test ends: it is only a name in the folder). */
static int make_socket(const char *name)
{
    struct sockaddr_un a = {.sun_family = AF_UNIX};
    char p[512];
    path_of(name, p, sizeof p);
    assert_true(strlen(p) < sizeof a.sun_path);
    memcpy(a.sun_path, p, strlen(p) + 1);
    int s = socket(AF_UNIX, SOCK_STREAM, 0);
    assert_true(s >= 0);
    assert_int_equal(bind(s, (struct sockaddr *)&a, sizeof a), 0);
    return s;
}

/* ------------------------ A: side files ------------------------ */

#define SECRET "SECRET-7f3a9c-CONTENT"

/* glTF buffers: inside the folder (also through a symlink that stays inside) and data: URIs render; outside
 * it (../, a symlink out, /dev/zero through a symlink, /dev/stdin reached by ../), at a FIFO, a socket, or
 * missing: a clear error naming the mesh and the buffer, at once (a FIFO must not block), and nothing of the
 * foreign file in the message.  A buffer without a URI: assimp's error. */
static void test_gltf_buffers(void **state)
{
    (void)state;
    unsigned char buf[128];
    size_t n = tet_buffer(buf);
    char p[512], q[512], b64[256], uri[400];
    write_bytes("m/tet.bin", buf, n);
    memcpy(buf + n, SECRET "\n", strlen(SECRET) + 1);   /* a valid buffer, then someone's secret */
    write_bytes("outside.bin", buf, n + strlen(SECRET) + 1);
    const char *w;
    write_gltf("m/inside.gltf", "tet.bin", NULL);
    expect_image("m/inside.gltf", "--patch smooth --level 3", &w);
    prog_base64(buf, n, b64);
    snprintf(uri, sizeof uri, "data:application/octet-stream;base64,%s", b64);
    write_gltf("m/data.gltf", uri, NULL);
    expect_image("m/data.gltf", "--patch npatch --level 3", &w);
    assert_int_equal(symlink("tet.bin", path_of("m/inlink.bin", p, sizeof p)), 0);   /* stays inside */
    write_gltf("m/inlink.gltf", "inlink.bin", NULL);
    expect_image("m/inlink.gltf", "--level 2", &w);

    write_gltf("m/outside.gltf", "../outside.bin", NULL);
    expect_error("m/outside.gltf", "", "refers to '../outside.bin', which is outside the mesh's folder", SECRET);
    assert_int_equal(symlink(path_of("outside.bin", q, sizeof q), path_of("m/outlink.bin", p, sizeof p)), 0);
    write_gltf("m/outlink.gltf", "outlink.bin", NULL);
    expect_error("m/outlink.gltf", "", "refers to 'outlink.bin', which is outside the mesh's folder", NULL);
    write_gltf("m/stdin.gltf", "../../../../../../../../../../dev/stdin", NULL);
    expect_error("m/stdin.gltf", "", "refers to", NULL);
    assert_int_equal(symlink("/dev/zero", path_of("m/devlink.bin", p, sizeof p)), 0);
    write_gltf("m/devlink.gltf", "devlink.bin", NULL);
    expect_error("m/devlink.gltf", "", "outside the mesh's folder", NULL);
    assert_int_equal(mkfifo(path_of("m/fifo.bin", p, sizeof p), 0644), 0);
    write_gltf("m/fifo.gltf", "fifo.bin", NULL);
    double s = expect_error("m/fifo.gltf", "", "refers to 'fifo.bin', which is a FIFO, not a regular file", NULL);
    assert_true(s < 20);
    int sock = make_socket("m/sock.bin");
    write_gltf("m/sock.gltf", "sock.bin", NULL);
    expect_error("m/sock.gltf", "", "which is a socket, not a regular file", NULL);
    close(sock);
    write_gltf("m/missing.gltf", "nothere.bin", NULL);
    expect_error("m/missing.gltf", "", "refers to 'nothere.bin', which cannot be opened (No such file or directory)",
                 NULL);
    write_gltf("m/nouri.gltf", NULL, NULL);
    expect_error("m/nouri.gltf", "", "cannot read the mesh: GLTF: buffer with non-zero length missing the \"uri\"",
                 NULL);
}

/* An OBJ's material library is never read: outside the folder, at a FIFO (whose open would block the import
 * until the time limit), at /dev/zero, or a malformed one beside the mesh: the mesh renders at once, and no
 * byte of the library reaches stderr. */
static void test_obj_material_libraries(void **state)
{
    (void)state;
    const char *tet = "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";
    char text[1024], p[512];
    write_text("secret.mtl", "newmtl " SECRET "\nKd 1 0 0\nmap_Kd " SECRET ".png\n");
    write_text("m/bad.mtl", SECRET " \x01\x02 garbage newmtl\nKd nan x\n");
    assert_int_equal(mkfifo(path_of("m/fifo.mtl", p, sizeof p), 0644), 0);
    const char *libs[] = {"../secret.mtl", "fifo.mtl", "/dev/zero", "bad.mtl"};
    for (size_t k = 0; k < sizeof libs / sizeof libs[0]; k++) {
        snprintf(text, sizeof text, "mtllib %s\nusemtl red\n%s", libs[k], tet);
        write_text("m/mtl.obj", text);
        const char *w;
        double t0 = now_s();
        expect_image("m/mtl.obj", "--level 2", &w);
        double s = now_s() - t0;
        print_message("    mtllib %-36s %.2f s\n", libs[k], s);
        if (strstr(w, SECRET)) fail_msg("mtllib %s: stderr shows the library's content: %s", libs[k], w);
        assert_true(s < 20);   /* the import's time limit is 60 s: a blocked open would reach it */
    }
}

/* ------------------------ B: resource bombs ------------------------ */

/* A PLY header (binary little-endian or ASCII) with `nv` vertices of x, y, z and `nf` faces, then `body`. */
static size_t ply_with(unsigned char *buf, size_t len, bool binary, unsigned long long nv, unsigned long long nf,
                       const void *body, size_t body_len)
{
    int n = snprintf((char *)buf, len,
                     "ply\nformat %s 1.0\nelement vertex %llu\nproperty float x\nproperty float y\nproperty float z\n"
                     "element face %llu\nproperty list uchar int vertex_indices\nend_header\n",
                     binary ? "binary_little_endian" : "ascii", nv, nf);
    assert_true(n > 0 && (size_t)n + body_len <= len);
    memcpy(buf + n, body, body_len);
    return (size_t)n + body_len;
}

/* Declared counts against the body and the limits (PLY binary and ASCII, OFF), a sparse 4 GiB file: refused
 * by size, at once, before assimp allocates anything. */
static void test_declared_sizes(void **state)
{
    (void)state;
    unsigned char buf[1024], zeros[64] = {0};
    write_bytes("m/bomb.ply", buf, ply_with(buf, sizeof buf, true, 1000000000ull, 1, zeros, 60));
    double s = expect_error("m/bomb.ply", "", "declares 1000000000 'vertex' elements, more than the limit", NULL);
    assert_true(s < 20);
    write_bytes("m/short.ply", buf, ply_with(buf, sizeof buf, true, 1000, 1, zeros, 60));
    expect_error("m/short.ply", "", "declares 1000 'vertex' elements (with the others at least 12001 bytes), but the "
                 "file holds only 60 bytes after its header", NULL);
    const char *ascii = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n";
    write_bytes("m/short_ascii.ply", buf, ply_with(buf, sizeof buf, false, 4, 2000000, ascii, strlen(ascii)));
    expect_error("m/short_ascii.ply", "", "declares 2000000 'face' elements", NULL);
    write_text("m/bomb.off", "OFF\n1000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    expect_error("m/bomb.off", "", "the OFF header declares 1000000000 'vertex' elements", NULL);
    char p[512];
    FILE *f = fopen(path_of("m/sparse.obj", p, sizeof p), "wb");
    assert_non_null(f);
    assert_int_equal(ftruncate(fileno(f), (off_t)4 << 30), 0);   /* 4 GiB of zeros, no disk used */
    fclose(f);
    assert_true(expect_error("m/sparse.obj", "", "the file has 4294967296 bytes, more than the limit of 268435456",
                             NULL) < 20);
    unlink(p);
}

/* faerie.md2 (the assimp test model) with triangle t's corner k index (k 0..2 vertex, 3..5 texture coordinate)
 * set to v, written as dir/name. */
static void write_md2_with(const char *name, int t, int k, unsigned v)
{
    size_t n;
    unsigned char *d = prog_slurp("/usr/share/assimp/models/MD2/faerie.md2", &n);
    assert_true(d && n > 68);
    unsigned ofs = d[52] | d[53] << 8 | (unsigned)d[54] << 16 | (unsigned)d[55] << 24;
    d[ofs + 12 * t + 2 * k] = (unsigned char)v, d[ofs + 12 * t + 2 * k + 1] = (unsigned char)(v >> 8);
    write_bytes(name, d, n);
    free(d);
}

/* A face naming a vertex the file does not have: refused with the file, line, face and index (assimp 5.2 clamps
 * an OFF or MD2 index past the end to the last vertex and renders without a word; its OBJ message names
 * neither). */
static void test_face_indices(void **state)
{
    (void)state;
    write_text("m/far.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 9\n3 0 2 3\n");
    expect_error("m/far.off", "", "line 7: face 0 names vertex 9, but the file has 4 vertices (0..3)", NULL);
    write_text("m/neg.off", "OFF\n# a comment\n4 2 0\n0 0 0\n1 0 0\n\n0 1 0\n0 0 1\n3 0 1 2\n3 0 2 -1\n");
    expect_error("m/neg.off", "", "line 10: face 1 names vertex -1", NULL);
    write_text("m/far.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1/1/1 3//2 9\n");
    expect_error("m/far.obj", "", "line 6: face 1, corner 2 names vertex 9, but the file has 4 vertices", NULL);
    write_text("m/back.obj", "v 0 0 0\nv 1 0 0\nf 1 2 -3\nv 0 1 0\n");
    expect_error("m/back.obj", "", "line 3: face 0, corner 2 names vertex -3", NULL);
    write_text("m/zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    expect_error("m/zero.obj", "", "line 4: face 0, corner 0 names vertex 0", NULL);
    write_md2_with("m/far.md2", 5, 1, 416);   /* faerie.md2 has 366 vertices and 487 texture coordinates */
    expect_error("m/far.md2", "", "triangle 5, corner 1 names vertex 416, but the file has 366 (0..365)", NULL);
    write_md2_with("m/far_uv.md2", 653, 5, 60000);
    expect_error("m/far_uv.md2", "", "triangle 653, corner 2 names texture coordinate 60000, but the file has 487", NULL);
    /* in range, relative and absolute: renders */
    write_text("m/fine.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf -4 -3 -1\nf 1 2 4\nf 2 3 4\n");
    write_text("m/fine.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n");
    const char *err;
    char p[512];
    assert_int_equal(shell(&err, NULL, "'%s' '%s' -q -o '%s/fine.png'", program(), path_of("m/fine.obj", p, sizeof p), dir), 0);
    assert_int_equal(shell(&err, NULL, "'%s' '%s' -q -o '%s/fine2.png'", program(), path_of("m/fine.off", p, sizeof p), dir), 0);
}

/* A 2 KB glTF whose 23 nodes each use the next one twice: assimp expands the graph into 2^23 nodes (several
 * GB).  The import child's memory limit (256 MiB + 32 bytes per byte of the files) stops it within seconds,
 * with a clear message.  The same graph 12 deep (2^12 uses of the mesh, 16384 triangles) renders. */
static void test_node_graph_bomb(void **state)
{
    (void)state;
    unsigned char buf[128];
    write_bytes("m/tet.bin", buf, tet_buffer(buf));
    char nodes[4096];
    for (int depth = 12; depth <= 22; depth += 10) {
        size_t n = (size_t)snprintf(nodes, sizeof nodes, "[");
        for (int k = 0; k < depth; k++)
            n += (size_t)snprintf(nodes + n, sizeof nodes - n, "{\"children\":[%d,%d]},", k + 1, k + 1);
        snprintf(nodes + n, sizeof nodes - n, "{\"mesh\":0}]");
        write_gltf(depth == 12 ? "m/dag12.gltf" : "m/dag22.gltf", "tet.bin", nodes);
    }
    const char *w;
    expect_image("m/dag12.gltf", "--level 1 --patch npatch", &w);
    double s = expect_error("m/dag22.gltf", "", "assimp ran out of the import memory limit of 256 MiB", NULL);
    assert_true(s < 30);
}

/* ------------------------ C: few descriptors ------------------------ */

/* With ulimit -n 5 a file that crashes assimp (a fuzzer-found binary PLY) is a clear error, and a good mesh
 * renders; with ulimit -n 4 there is no descriptor for the import's pipe: a clear error too.  Never a
 * signal, never an output file. */
static void test_few_descriptors(void **state)
{
    (void)state;
    FILE *in = fopen("tests/fuzz/regressions/import-assimp/assimp_segv_ply_binary.ply", "rb");
    assert_non_null(in);
    unsigned char buf[4096];
    size_t n = fread(buf, 1, sizeof buf, in);
    fclose(in);
    write_bytes("m/segv.ply", buf, n);
    write_text("m/tet.obj", "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n");
    char p[512], out[512];
    path_of("m/out.png", out, sizeof out);
    const struct { int fds; const char *mesh, *what; } cases[] = {
        {5, "m/segv.ply", "assimp crashed on it (signal 11"}, {4, "m/segv.ply", "cannot start the import process"},
        {4, "m/tet.obj", "cannot start the import process (pipe: Too many open files)"}, {5, "m/tet.obj", NULL}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const char *err;
        int rc = shell(&err, NULL, "sh -c \"ulimit -n %d; exec '%s' --mesh '%s' --level 2 --size 32x32 -o '%s'\"",
                       cases[k].fds, program(), path_of(cases[k].mesh, p, sizeof p), out);
        print_message("  ulimit -n %d %-12s exit %d: %s", cases[k].fds, cases[k].mesh, rc, err);
        if (!cases[k].what) {   /* the good mesh renders with 5 descriptors */
            if (rc != 0) fail_msg("ulimit -n %d %s: exit %d: %s", cases[k].fds, cases[k].mesh, rc, err);
            assert_true(exists("m/out.png"));
            unlink(out);
            continue;
        }
        if (rc != 1 || !strstr(err, cases[k].mesh) || !strstr(err, cases[k].what))
            fail_msg("ulimit -n %d %s: wanted exit 1 with '%s', got exit %d: %s", cases[k].fds, cases[k].mesh,
                     cases[k].what, rc, err);
        assert_false(exists("m/out.png"));
    }
}

/* ------------------------ D: scale invariance ------------------------ */

/* An ellipsoid (a UV sphere scaled 1.3 x 1 x 0.8, 8 x 12 segments, counter-clockwise from outside) as OBJ
 * text whose every coordinate is the same decimal mantissa with exponent `e` ("0.9238795e-12"), so the files
 * differ only in the unit. */
static void ellipsoid_obj(char *buf, size_t len, int e)
{
    const int rings = 8, segs = 12;
    const double pi = 3.14159265358979323846;
    size_t n = (size_t)snprintf(buf, len, "v 0 1e%d 0\n", e);
    for (int i = 1; i < rings; i++)
        for (int j = 0; j < segs; j++) {
            double th = pi * i / rings, ph = 2 * pi * j / segs;
            double x = round(sin(th) * cos(ph) * 1.3e7) / 1e7, y = round(cos(th) * 1e7) / 1e7,
                   z = round(sin(th) * sin(ph) * 0.8e7) / 1e7;
            n += (size_t)snprintf(buf + n, len - n, "v %.7fe%d %.7fe%d %.7fe%d\n", x, e, y, e, z, e);
        }
    n += (size_t)snprintf(buf + n, len - n, "v 0 -1e%d 0\n", e);
    for (int j = 0; j < segs; j++) n += (size_t)snprintf(buf + n, len - n, "f 1 %d %d\n", 2 + (j + 1) % segs, 2 + j);
    for (int i = 0; i < rings - 2; i++)
        for (int j = 0; j < segs; j++) {
            int a = 2 + i * segs + j, b = 2 + i * segs + (j + 1) % segs;
            n += (size_t)snprintf(buf + n, len - n, "f %d %d %d\nf %d %d %d\n", a, b, b + segs, a, b + segs, a + segs);
        }
    int last = 2 + (rings - 1) * segs, base = 2 + (rings - 2) * segs;
    for (int j = 0; j < segs; j++)
        n += (size_t)snprintf(buf + n, len - n, "f %d %d %d\n", last, base + j, base + (j + 1) % segs);
}

/* Pixels of two PNGs (same size) that differ in any channel. */
static long differing_pixels(const char *a, const char *b)
{
    is_image x = {0}, y = {0};
    char err[512];
    if (image_read(&x, a, err, sizeof err) != 0 || image_read(&y, b, err, sizeof err) != 0) fail_msg("%s", err);
    assert_true(x.width == y.width && x.height == y.height && x.channels == y.channels);
    long n = 0;
    for (long k = 0; k < (long)x.width * x.height; k++)
        n += memcmp(x.data + k * x.channels, y.data + k * y.channels, sizeof(float) * (size_t)x.channels) != 0;
    image_free(&x), image_free(&y);
    return n;
}

/* The same OBJ in six units renders alike.  Threshold: at most 0.5 % of the pixels may differ.  The files hold
 * the same decimal mantissas, but a float of 0.9238795e-12 is not exactly 1e-12 times the float of 0.9238795:
 * each coordinate may differ from the scaled unit one by an ulp, and after the scene maps the mesh to its unit
 * bounding sphere a sample exactly on an edge can fall on either side (a few edge pixels, 1/255 of shading).
 * Anything that depends on the unit -- a vertex joined or not, a triangle dropped as degenerate, a normal
 * replaced -- changes whole patches: before the fix 3 % to 30 % of the pixels differed. */
static void test_scale_invariance(void **state)
{
    (void)state;
    static char text[65536];
    const int exps[] = {0, -6, -12, -30, 6, 20};
    const char *patches[] = {"--patch npatch", "--patch smooth"};
    char p[512], out[512], ref[512], name[64];
    for (size_t e = 0; e < sizeof exps / sizeof exps[0]; e++) {
        ellipsoid_obj(text, sizeof text, exps[e]);
        snprintf(name, sizeof name, "m/scale%d.obj", exps[e]);
        write_text(name, text);
        for (size_t k = 0; k < 2; k++) {
            snprintf(out, sizeof out, "%s/m/scale%d_%zu.png", dir, exps[e], k);
            const char *err;
            int rc = shell(&err, NULL, "'%s' --mesh '%s' %s --level 4 --size 96x96 -q -o '%s'", program(),
                           path_of(name, p, sizeof p), patches[k], out);
            if (rc != 0) fail_msg("%s %s: exit %d: %s", name, patches[k], rc, err);
            if (e == 0) continue;
            snprintf(ref, sizeof ref, "%s/m/scale0_%zu.png", dir, k);
            long d = differing_pixels(ref, out);
            print_message("  1e%-4d %-16s %4ld of %d pixels differ from scale 1\n", exps[e], patches[k], d, 96 * 96);
            if (d > 96 * 96 / 200) fail_msg("scale 1e%d, %s: %ld pixels differ from scale 1", exps[e], patches[k], d);
        }
    }
}

/* ------------------------ E: normals ------------------------ */

/* The octahedron as ASCII STL with its facet normals (or their opposites, `inward`), counter-clockwise. */
static void octahedron_stl(char *buf, size_t len, bool inward)
{
    const double v[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    size_t n = (size_t)snprintf(buf, len, "solid octa\n");
    for (int x = 0; x < 2; x++)
        for (int y = 2; y < 4; y++)
            for (int z = 4; z < 6; z++) {
                bool ccw = ((x == 0) == (y == 2)) == (z == 4);
                int c[3] = {x, ccw ? y : z, ccw ? z : y};
                double s = (inward ? -1 : 1) / sqrt(3.0);
                n += (size_t)snprintf(buf + n, len - n, "facet normal %g %g %g\nouter loop\n",
                                      s * (v[x][0] + v[y][0] + v[z][0]), s * (v[x][1] + v[y][1] + v[z][1]),
                                      s * (v[x][2] + v[y][2] + v[z][2]));
                for (int k = 0; k < 3; k++)
                    n += (size_t)snprintf(buf + n, len - n, "vertex %g %g %g\n", v[c[k]][0], v[c[k]][1], v[c[k]][2]);
                n += (size_t)snprintf(buf + n, len - n, "endloop\nendfacet\n");
            }
    snprintf(buf + n, len - n, "endsolid octa\n");
}

/* An STL with facet normals warns that every patch renders flat, with --recompute-normals as the fix (and
 * with that option, no warning); one whose normals point inward also warns about the winding; an OBJ with
 * smooth vertex normals pointing inward warns about the winding only; smooth outward normals warn nothing. */
static void test_normal_warnings(void **state)
{
    (void)state;
    char text[8192];
    const char *w;
    const char *facet = "the file's normals are facet normals", *against = "point against their face's winding";
    octahedron_stl(text, sizeof text, false);
    write_text("m/facets.stl", text);
    expect_image("m/facets.stl", "--level 3", &w);
    if (!strstr(w, facet) || !strstr(w, "m/facets.stl") || !strstr(w, "--recompute-normals") || strstr(w, against))
        fail_msg("facets.stl: wanted the facet-normal warning only: %s", w);
    expect_image("m/facets.stl", "--level 3 --recompute-normals", &w);
    if (strstr(w, facet) || strstr(w, against)) fail_msg("facets.stl --recompute-normals warned: %s", w);
    octahedron_stl(text, sizeof text, true);
    write_text("m/inward.stl", text);
    expect_image("m/inward.stl", "--level 3", &w);
    if (!strstr(w, against) || !strstr(w, "24 of 24 corner normals") || !strstr(w, facet))
        fail_msg("inward.stl: wanted both warnings: %s", w);
    const char *faces = "f 1//1 3//3 5//5\nf 1//1 6//6 3//3\nf 1//1 5//5 4//4\nf 1//1 4//4 6//6\n"
                        "f 2//2 5//5 3//3\nf 2//2 3//3 6//6\nf 2//2 4//4 5//5\nf 2//2 6//6 4//4\n";
    const int axes[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int inward = 0; inward < 2; inward++) {
        char name[32];
        size_t n = 0;
        for (int k = 0; k < 6; k++)
            n += (size_t)snprintf(text + n, sizeof text - n, "v %d %d %d\n", axes[k][0], axes[k][1], axes[k][2]);
        for (int k = 0; k < 6; k++)   /* the vertex normals of a sphere: smooth, outward or inward */
            n += (size_t)snprintf(text + n, sizeof text - n, "vn %d %d %d\n", (inward ? -1 : 1) * axes[k][0],
                                  (inward ? -1 : 1) * axes[k][1], (inward ? -1 : 1) * axes[k][2]);
        snprintf(text + n, sizeof text - n, "%s", faces);
        snprintf(name, sizeof name, "m/smooth%d.obj", inward);
        write_text(name, text);
        expect_image(name, "--level 3", &w);
        if (strstr(w, facet) || (inward != (strstr(w, against) != NULL)))
            fail_msg("%s: wanted %s: %s", name, inward ? "the winding warning only" : "no warning", w);
    }
}

/* ------------------------ F: odd meshes and paths ------------------------ */

/* Two fans of n triangles each around the tips of a flat double cone (valence n at both tips), as OBJ,
 * counter-clockwise from outside.  Returns malloc'ed text. */
static char *fan_obj(int n)
{
    size_t len = (size_t)n * 80 + 256, k = 0;
    char *t = malloc(len);
    assert_non_null(t);
    k += (size_t)snprintf(t + k, len - k, "v 0 0 0.3\nv 0 0 -0.3\n");
    for (int i = 0; i < n; i++) {
        double a = 2 * 3.14159265358979323846 * i / n;
        k += (size_t)snprintf(t + k, len - k, "v %.9f %.9f 0\n", cos(a), sin(a));
    }
    for (int i = 0; i < n; i++)
        k += (size_t)snprintf(t + k, len - k, "f 1 %d %d\nf 2 %d %d\n", 3 + i, 3 + (i + 1) % n, 3 + (i + 1) % n,
                              3 + i);
    return t;
}

/* A Moebius strip of `segs` quads (non-orientable: no consistent winding exists) as OBJ. */
static void moebius_obj(char *buf, size_t len, int segs)
{
    size_t n = 0;
    for (int i = 0; i < segs; i++) {
        double u = 2 * 3.14159265358979323846 * i / segs;
        for (int s = -1; s <= 1; s += 2) {
            double r = 1 + 0.3 * s * cos(u / 2);
            n += (size_t)snprintf(buf + n, len - n, "v %.7f %.7f %.7f\n", r * cos(u), r * sin(u), 0.3 * s * sin(u / 2));
        }
    }
    for (int i = 0; i < segs; i++) {
        int a = 1 + 2 * i, b = 2 + 2 * i, c = 1 + 2 * ((i + 1) % segs), d = 2 + 2 * ((i + 1) % segs);
        if (i == segs - 1) { int t = c; c = d; d = t; }   /* the half twist closes the strip */
        n += (size_t)snprintf(buf + n, len - n, "f %d %d %d %d\n", a, c, d, b);
    }
}

/* Odd but valid OBJ files: each renders a finite, non-empty image (the smooth patch or the N-Patch with
 * quadratic normals, alternately). */
static void test_odd_obj(void **state)
{
    (void)state;
    const char *oct = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n";
    const char *faces = "f 1 3 5\nf 1 6 3\nf 1 5 4\nf 1 4 6\nf 2 5 3\nf 2 3 6\nf 2 4 5\nf 2 6 4\n";
    static char text[65536];
    const struct { const char *name, *body; } cases[] = {
        /* relative (negative) indices: -1 is the last vertex so far */
        {"m/negative.obj", "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
                           "f -6 -4 -2\nf -6 -1 -4\nf -6 -2 -3\nf -6 -3 -1\nf -5 -2 -4\nf -5 -4 -1\nf -5 -3 -2\n"
                           "f -5 -1 -3\n"},
        /* n-gons: a hexagonal prism with hexagon caps and quad sides */
        {"m/ngons.obj", "v 1 0 1\nv 0.5 0.866 1\nv -0.5 0.866 1\nv -1 0 1\nv -0.5 -0.866 1\nv 0.5 -0.866 1\n"
                        "v 1 0 -1\nv 0.5 0.866 -1\nv -0.5 0.866 -1\nv -1 0 -1\nv -0.5 -0.866 -1\nv 0.5 -0.866 -1\n"
                        "f 1 2 3 4 5 6\nf 12 11 10 9 8 7\nf 1 7 8 2\nf 2 8 9 3\nf 3 9 10 4\nf 4 10 11 5\n"
                        "f 5 11 12 6\nf 6 12 7 1\n"},
        /* normals on some faces only */
        {"m/somenormals.obj", "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\nvn 0.577 0.577 0.577\n"
                              "f 1//1 3//1 5//1\nf 1 6 3\nf 1 5 4\nf 1 4 6\nf 2 5 3\nf 2 3 6\nf 2 4 5\nf 2 6 4\n"},
        /* coordinates near FLT_MAX */
        {"m/fltmax.obj", "v 3.4e38 0 0\nv -3.4e38 0 0\nv 0 3.4e38 0\nv 0 -3.4e38 0\nv 0 0 3.4e38\nv 0 0 -3.4e38\n"},
        /* denormal coordinates (drawn unscaled: a dot, but finite) */
        {"m/denormal.obj", "v 1e-40 0 0\nv -1e-40 0 0\nv 0 1e-40 0\nv 0 -1e-40 0\nv 0 0 1e-40\nv 0 0 -1e-40\n"},
        /* every face twice, and twice more flipped */
        {"m/duplicated.obj", NULL},
        /* two cones touching at their tips: a non-manifold vertex */
        {"m/cones.obj", "v 0 0 0\nv 1 1 0\nv -1 1 0.5\nv -1 1 -0.5\nv 1 -1 0\nv -1 -1 0.5\nv -1 -1 -0.5\nv 0 1 0\n"
                        "v 0 -1 0\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 8 3 2\nf 8 4 3\nf 8 2 4\nf 1 6 5\nf 1 7 6\nf 1 5 7\n"
                        "f 9 5 6\nf 9 6 7\nf 9 7 5\n"},
        {"m/moebius.obj", NULL},
        {"m/fan.obj", NULL},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char *heap = NULL;
        const char *body = cases[k].body;
        if (!strcmp(cases[k].name, "m/fltmax.obj") || !strcmp(cases[k].name, "m/denormal.obj")) {
            snprintf(text, sizeof text, "%s%s", body, faces);
            body = text;
        } else if (!strcmp(cases[k].name, "m/duplicated.obj")) {
            snprintf(text, sizeof text, "%s%s%sf 3 1 5\nf 6 1 3\nf 5 1 4\nf 4 1 6\nf 5 2 3\nf 3 2 6\nf 4 2 5\n"
                     "f 6 2 4\n", oct, faces, faces);
            body = text;
        } else if (!strcmp(cases[k].name, "m/moebius.obj")) {
            moebius_obj(text, sizeof text, 24);
            body = text;
        } else if (!strcmp(cases[k].name, "m/fan.obj")) {
            body = heap = fan_obj(10000);
        }
        write_text(cases[k].name, body);
        free(heap);
        const char *w;
        if (!strcmp(cases[k].name, "m/denormal.obj")) continue;   /* below: finite, but may be empty */
        expect_image(cases[k].name, k % 2 ? "--patch npatch --normals quadratic --level 2" : "--patch smooth --level 3",
                     &w);
    }
    /* Denormal coordinates: a finite image.  cli/run/scene.c draws a mesh whose bounding radius is below 1e-37
     * unscaled (docs/robustness.md, "Limits"), so it covers no pixel until the scene rescales it too. */
    char p[512], out[512];
    const char *err;
    int rc = shell(&err, NULL, "'%s' --mesh '%s' --patch smooth --size 48x48 --msaa 1 --aov normal -o '%s'", program(),
                   path_of("m/denormal.obj", p, sizeof p), path_of("m/denormal.exr", out, sizeof out));
    if (rc != 0) fail_msg("denormal.obj: exit %d: %s", rc, err);
    long cov = covered_pixels(out, "denormal");
    print_message("  %-24s %-40s %4ld px covered\n", "m/denormal.obj", "--patch smooth", cov);
    /* all vertices identical: every triangle degenerate, a clear error */
    snprintf(text, sizeof text, "v 0.5 0.5 0.5\nv 0.5 0.5 0.5\nv 0.5 0.5 0.5\nv 0.5 0.5 0.5\nf 1 2 3\nf 1 3 4\n"
             "f 2 4 3\n");
    write_text("m/identical.obj", text);
    expect_error("m/identical.obj", "", "no triangles left: all 3 are degenerate", NULL);
}

/* Mesh paths that are not mesh files: a directory, a FIFO (must not block), /dev/zero, a symlink loop, a
 * socket: clear errors.  Names starting with '-': `--mesh -x.obj` and `--mesh ./-x.obj` both render. */
static void test_odd_paths(void **state)
{
    (void)state;
    char p[512], q[512], out[512];
    assert_int_equal(mkdir(path_of("m/folder.obj", p, sizeof p), 0755), 0);
    expect_error("m/folder.obj", "", "is a directory, not a mesh file", NULL);
    assert_int_equal(mkfifo(path_of("m/fifo.obj", p, sizeof p), 0644), 0);
    assert_true(expect_error("m/fifo.obj", "", "is a FIFO, not a mesh file", NULL) < 20);
    expect_error("/dev/zero", "", "is a character device, not a mesh file", NULL);
    assert_int_equal(symlink("loop2.obj", path_of("m/loop1.obj", p, sizeof p)), 0);
    assert_int_equal(symlink("loop1.obj", path_of("m/loop2.obj", q, sizeof q)), 0);
    expect_error("m/loop1.obj", "", "cannot open: Too many levels of symbolic links", NULL);
    int s = make_socket("m/sock.obj");
    expect_error("m/sock.obj", "", "is a socket, not a mesh file", NULL);
    close(s);
    write_text("m/-x.obj", "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n");
    const char *mesh[] = {"-x.obj", "./-x.obj"};
    for (int k = 0; k < 2; k++) {
        const char *err;
        int rc = shell(&err, NULL, "cd '%s' && '%s' --mesh %s --level 2 --size 32x32 -o '%s'",
                       path_of("m", p, sizeof p), program(), mesh[k], path_of("m/out.png", out, sizeof out));
        print_message("  --mesh %-10s exit %d: %s", mesh[k], rc, err);
        if (rc != 0) fail_msg("--mesh %s: exit %d: %s", mesh[k], rc, err);
        assert_true(exists("m/out.png"));
        unlink(out);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gltf_buffers),
        cmocka_unit_test(test_obj_material_libraries),
        cmocka_unit_test(test_declared_sizes),
        cmocka_unit_test(test_face_indices),
        cmocka_unit_test(test_node_graph_bomb),
        cmocka_unit_test(test_few_descriptors),
        cmocka_unit_test(test_scale_invariance),
        cmocka_unit_test(test_normal_warnings),
        cmocka_unit_test(test_odd_obj),
        cmocka_unit_test(test_odd_paths),
    };
    return cmocka_run_group_tests_name("hostile meshes", tests, setup, teardown);
}
