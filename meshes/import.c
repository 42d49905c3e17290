/* meshes/import.c -- users' meshes through assimp's C API, merged into one is_mesh (see meshes.h). */
#include "meshes.h"
#include "mesh_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif
#include <time.h>
#include <unistd.h>

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

/* Triangulate polygons; JoinIdenticalVertices indexes formats that store one vertex per corner (OBJ, STL);
 * ValidateDataStructure rejects inconsistent scenes (bad indices) from hostile files; ConvertToLeftHanded =
 * MakeLeftHanded (z -> -z on positions, normals and node transforms) + FlipWindingOrder + FlipUVs: assimp's
 * right-handed counter-clockwise data becomes left-handed clockwise (outward normal still
 * cross(v1 - v0, v2 - v0)) with D3D texcoords.  No GenNormals / GenSmoothNormals / FindDegenerates: normals
 * and degenerate triangles are ours (counted, see mesh_create). */
#define IMPORT_FLAGS (aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_ValidateDataStructure | \
                      aiProcess_ConvertToLeftHanded)
/* Limits against hostile scenes (a big mesh instanced by many nodes). */
#define MAX_IMPORT_ELEMENTS ((size_t)1 << 27)
#define MAX_NODE_DEPTH 256
#define DEFAULT_TIMEOUT_MS 60000

/* A 3x4 affine transform in double (column vectors, as assimp: p' = M p). */
typedef struct xform { double m[3][4]; } xform;

/* aiMatrix4x4 -> xform (the last row of an affine node transform is 0 0 0 1). */
static xform xform_of(const struct aiMatrix4x4 *a)
{
    xform x = {{{a->a1, a->a2, a->a3, a->a4}, {a->b1, a->b2, a->b3, a->b4}, {a->c1, a->c2, a->c3, a->c4}}};
    return x;
}

/* p * q (apply q first). */
static xform xform_mul(const xform *p, const xform *q)
{
    xform r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            r.m[i][j] = p->m[i][0] * q->m[0][j] + p->m[i][1] * q->m[1][j] + p->m[i][2] * q->m[2][j] +
                        (j == 3 ? p->m[i][3] : 0.0);
    return r;
}

/* Cofactor matrix of the upper 3x3 (= det * inverse transpose), for normals. */
static void cofactor3(const xform *x, double c[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            c[i][j] = x->m[i1][j1] * x->m[i2][j2] - x->m[i1][j2] * x->m[i2][j1];
        }
}

/* Determinant of the upper 3x3. */
static double det3(const xform *x)
{
    double c[3][3];
    cofactor3(x, c);
    return x->m[0][0] * c[0][0] + x->m[0][1] * c[0][1] + x->m[0][2] * c[0][2];
}

/* Destination arrays of the merge (NULL pointers in the counting pass). */
typedef struct merged {
    size_t nv, nt, skipped;
    float3 *p, *n;
    float2 *uv;
    uint32_t *idx;
    bool any_normals;
} merged;

/* Append the triangles of mesh `am` (vertex base `base`); flip winding under a mirroring transform. */
static void append_faces(merged *o, const struct aiMesh *am, size_t base, bool flip)
{
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        const struct aiFace *face = &am->mFaces[f];
        if (face->mNumIndices != 3) { o->skipped++; continue; }
        if (o->idx) {
            uint32_t *t = o->idx + 3 * o->nt;
            t[0] = (uint32_t)(base + face->mIndices[0]);
            t[1] = (uint32_t)(base + face->mIndices[flip ? 2 : 1]);
            t[2] = (uint32_t)(base + face->mIndices[flip ? 1 : 2]);
        }
        o->nt++;
    }
}

/* Row i of the affine x applied to p: a zero coefficient contributes exactly 0, so a non-finite coordinate
 * stays in its own component (0 * inf would be NaN) and error messages show the file's values. */
static double xform_row(const xform *x, int i, const struct aiVector3D *p)
{
    double r = 0.0;   /* the same sums, in the same order, as the plain m0 x + m1 y + m2 z + m3 */
    if (x->m[i][0] != 0.0) r += x->m[i][0] * p->x;
    if (x->m[i][1] != 0.0) r += x->m[i][1] * p->y;
    if (x->m[i][2] != 0.0) r += x->m[i][2] * p->z;
    return r + x->m[i][3];
}

/* Append the vertices of `am` transformed by x (normals by the cofactor matrix, sign-corrected). */
static void append_vertices(merged *o, const struct aiMesh *am, const xform *x)
{
    double c[3][3], s = det3(x) < 0.0 ? -1.0 : 1.0;
    cofactor3(x, c);
    for (unsigned v = 0; v < am->mNumVertices; v++) {
        const struct aiVector3D *p = &am->mVertices[v];
        float3 *dp = &o->p[o->nv + v];
        *dp = f3((float)xform_row(x, 0, p), (float)xform_row(x, 1, p), (float)xform_row(x, 2, p));
        float3 n = f3(0.0f, 0.0f, 0.0f);   /* missing normals: replaced (and counted) by mesh_create */
        if (am->mNormals) {
            const struct aiVector3D *q = &am->mNormals[v];
            n = f3((float)(s * (c[0][0] * q->x + c[0][1] * q->y + c[0][2] * q->z)),
                   (float)(s * (c[1][0] * q->x + c[1][1] * q->y + c[1][2] * q->z)),
                   (float)(s * (c[2][0] * q->x + c[2][1] * q->y + c[2][2] * q->z)));
        }
        o->n[o->nv + v] = n;
        const struct aiVector3D *t = am->mTextureCoords[0] ? &am->mTextureCoords[0][v] : NULL;
        o->uv[o->nv + v] = t ? f2(t->x, t->y) : f2(0.0f, 0.0f);
    }
}

/* Add one mesh instance (counting pass when o->p is NULL). */
static void append_mesh(merged *o, const struct aiMesh *am, const xform *x)
{
    if (!am || !am->mVertices || am->mNumVertices == 0) return;
    if (am->mNormals) o->any_normals = true;
    if (o->p) append_vertices(o, am, x);
    append_faces(o, am, o->nv, det3(x) < 0.0);
    o->nv += am->mNumVertices;
}

/* Walk the node tree, merging every referenced mesh with its global transform.  -1 when too deep. */
static int walk(merged *o, const struct aiScene *sc, const struct aiNode *node, const xform *parent, int depth)
{
    if (depth > MAX_NODE_DEPTH) return -1;
    xform local = xform_of(&node->mTransformation), g = xform_mul(parent, &local);
    for (unsigned i = 0; i < node->mNumMeshes; i++)
        if (node->mMeshes[i] < sc->mNumMeshes) append_mesh(o, sc->mMeshes[node->mMeshes[i]], &g);
    for (unsigned i = 0; i < node->mNumChildren; i++)
        if (node->mChildren[i] && walk(o, sc, node->mChildren[i], &g, depth + 1) != 0) return -1;
    return 0;
}

/* Allocate the arrays of o for its counts; false when out of memory. */
static bool merged_alloc(merged *o)
{
    o->p = malloc((o->nv ? o->nv : 1) * sizeof(float3));
    o->n = malloc((o->nv ? o->nv : 1) * sizeof(float3));
    o->uv = malloc((o->nv ? o->nv : 1) * sizeof(float2));
    o->idx = malloc((o->nt ? o->nt : 1) * 3 * sizeof(uint32_t));
    return o->p && o->n && o->uv && o->idx;
}

/* Free the arrays of o. */
static void merged_free(merged *o)
{
    free(o->p); free(o->n); free(o->uv); free(o->idx);
}

/* Count, check sizes, allocate and fill the merged arrays of scene sc. */
static int merge_scene(merged *o, const struct aiScene *sc, const char *label, char *err, size_t errlen)
{
    static const xform identity = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
    memset(o, 0, sizeof *o);
    if (!sc->mRootNode || walk(o, sc, sc->mRootNode, &identity, 0) != 0) {
        mesh_set_err(err, errlen, "%s: invalid scene (no root node, or nodes nested deeper than %d)", label,
                MAX_NODE_DEPTH);
        return IS_MESH_ERR_INVALID;
    }
    if (o->nt == 0) {
        mesh_set_err(err, errlen, "%s: no triangles (%zu point/line primitives, %u meshes)", label, o->skipped,
                sc->mNumMeshes);
        return IS_MESH_ERR_EMPTY;
    }
    if (o->nv > MAX_IMPORT_ELEMENTS || o->nt > MAX_IMPORT_ELEMENTS) {
        mesh_set_err(err, errlen, "%s: too large after instancing the nodes (%zu vertices, %zu triangles)", label,
                o->nv, o->nt);
        return IS_MESH_ERR_INVALID;
    }
    size_t nv = o->nv, nt = o->nt;
    bool ok = merged_alloc(o);
    o->nv = o->nt = o->skipped = 0;
    if (!ok) {
        mesh_set_err(err, errlen, "%s: out of memory (%zu vertices, %zu triangles)", label, nv, nt);
        return IS_MESH_ERR_NOMEM;
    }
    walk(o, sc, sc->mRootNode, &identity, 0);
    return IS_MESH_OK;
}

/* Where to import from: a file (path) or a buffer (data, size, hint). */
typedef struct import_src {
    const char *path;
    const void *data;
    size_t size;
    const char *hint;
} import_src;

/* Import with assimp in this process and merge the scene into o (arrays owned by o). */
static int import_merged(const import_src *src, const char *label, merged *o, char *err, size_t errlen)
{
    memset(o, 0, sizeof *o);
    const struct aiScene *sc = src->path ? aiImportFile(src->path, IMPORT_FLAGS)
                                         : aiImportFileFromMemory(src->data, (unsigned)src->size, IMPORT_FLAGS,
                                                                  src->hint ? src->hint : "");
    if (!sc) {
        const char *msg = aiGetErrorString();
        mesh_set_err(err, errlen, "%s: cannot read the mesh: %s", label, msg && *msg ? msg : "assimp failed");
        return IS_MESH_ERR_FORMAT;
    }
    int rc = merge_scene(o, sc, label, err, errlen);
    aiReleaseImport(sc);
    return rc;
}

/* ---------------- the child process (a crash or hang inside assimp becomes an error) ---------------- */

/* What the child sends first; the arrays follow when rc == 0. */
typedef struct child_header {
    int32_t rc;
    int32_t any_normals;
    uint64_t nv, nt, skipped;
    char err[512];
} child_header;

/* Write all of buf; false when the pipe broke. */
static bool write_all(int fd, const void *buf, size_t len)
{
    const char *p = buf;
    while (len) {
        ssize_t w = write(fd, p, len);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        len -= (size_t)w;
    }
    return true;
}

/* Child: import, send the header and the merged arrays, exit without running atexit handlers. */
static _Noreturn void child_import(const import_src *src, const char *label, int fd)
{
    merged o;
    child_header h;
    memset(&h, 0, sizeof h);
    h.rc = import_merged(src, label, &o, h.err, sizeof h.err);
    h.any_normals = o.any_normals;
    h.nv = o.nv; h.nt = o.nt; h.skipped = o.skipped;
    bool ok = write_all(fd, &h, sizeof h);
    if (ok && h.rc == IS_MESH_OK)
        ok = write_all(fd, o.p, o.nv * sizeof(float3)) && write_all(fd, o.n, o.nv * sizeof(float3)) &&
             write_all(fd, o.uv, o.nv * sizeof(float2)) && write_all(fd, o.idx, 3 * o.nt * sizeof(uint32_t));
    _exit(ok ? 0 : 3);
}

/* Milliseconds on the monotonic clock. */
static int64_t now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* Read len bytes before the deadline: 0, -1 at end of data / error, -2 on timeout. */
static int read_all(int fd, void *buf, size_t len, int64_t deadline)
{
    char *p = buf;
    while (len) {
        int64_t left = deadline - now_ms();
        if (left <= 0) return -2;
        struct pollfd pfd = {fd, POLLIN, 0};
        int r = poll(&pfd, 1, left > INT_MAX ? INT_MAX : (int)left);
        if (r < 0 && errno == EINTR) continue;
        if (r == 0) return -2;
        if (r < 0) return -1;
        ssize_t got = read(fd, p, len);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) return -1;
        p += got;
        len -= (size_t)got;
    }
    return 0;
}

/* Parent: receive the header and arrays into o.  0, -1 (child died / bad data), -2 (timeout), or the
 * child's own error code (message in err). */
static int receive(int fd, int64_t deadline, const char *label, merged *o, char *err, size_t errlen)
{
    child_header h;
    int r = read_all(fd, &h, sizeof h, deadline);
    if (r != 0) return r;
    if (h.rc != IS_MESH_OK) {
        h.err[sizeof h.err - 1] = '\0';
        mesh_set_err(err, errlen, "%s", h.err);
        return h.rc < 0 ? h.rc : IS_MESH_ERR_FORMAT;
    }
    if (h.nv == 0 || h.nt == 0 || h.nv > MAX_IMPORT_ELEMENTS || h.nt > MAX_IMPORT_ELEMENTS) return -1;
    o->nv = (size_t)h.nv; o->nt = (size_t)h.nt; o->skipped = (size_t)h.skipped; o->any_normals = h.any_normals;
    if (!merged_alloc(o)) {
        mesh_set_err(err, errlen, "%s: out of memory (%zu vertices, %zu triangles)", label, o->nv, o->nt);
        return IS_MESH_ERR_NOMEM;
    }
    if ((r = read_all(fd, o->p, o->nv * sizeof(float3), deadline)) != 0) return r;
    if ((r = read_all(fd, o->n, o->nv * sizeof(float3), deadline)) != 0) return r;
    if ((r = read_all(fd, o->uv, o->nv * sizeof(float2), deadline)) != 0) return r;
    return read_all(fd, o->idx, 3 * o->nt * sizeof(uint32_t), deadline);
}

/* Up to len-1 bytes the child wrote to its stderr (assimp's assertion messages), first line only. */
static void child_stderr(int fd, char *buf, size_t len)
{
    buf[0] = '\0';
    struct pollfd pfd = {fd, POLLIN, 0};
    if (poll(&pfd, 1, 0) <= 0) return;
    ssize_t got = read(fd, buf, len - 1);
    buf[got > 0 ? got : 0] = '\0';
    buf[strcspn(buf, "\r\n")] = '\0';
}

/* Explain how the child ended when it sent no (complete) result. */
static int child_failure(int r, int status, const char *label, int timeout_ms, const char *what, char *err,
                         size_t errlen)
{
    const char *sep = *what ? ": " : "";
    if (r == -2)
        mesh_set_err(err, errlen, "%s: cannot read the mesh: assimp did not finish within %d ms (stopped)", label,
                timeout_ms);
    else if (WIFSIGNALED(status))
        mesh_set_err(err, errlen, "%s: cannot read the mesh: assimp crashed on it (signal %d, %s)%s%s", label,
                WTERMSIG(status), strsignal(WTERMSIG(status)), sep, what);
    else
        mesh_set_err(err, errlen, "%s: cannot read the mesh: the import process failed (status %d)%s%s", label,
                WIFEXITED(status) ? WEXITSTATUS(status) : -1, sep, what);
    return IS_MESH_ERR_FORMAT;
}

/* Every signal back to its default action and unblocked: a crash inside assimp must kill the child, not run
 * a handler the application installed (a crash reporter, a test framework's longjmp back into its runner, the
 * program's SIGTERM clean-up) in a copy of the application. */
static void child_default_signals(void)
{
    for (int sig = 1; sig <= SIGRTMAX; sig++)
        if (sig != SIGKILL && sig != SIGSTOP) signal(sig, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, NULL);
}

/* Child side of the fork: default signals; dies with its parent (a killed instess leaves no assimp running on,
 * hung or not) and at the time limit plus two seconds even if nobody reads it; stderr into the (non-blocking)
 * error pipe; then import and exit. */
static _Noreturn void child_main(const import_src *src, const char *label, const int fd[2], const int efd[2],
                                 pid_t parent, int timeout_ms)
{
#ifdef __linux__
    prctl(PR_SET_PDEATHSIG, SIGKILL);
#endif
    if (getppid() != parent) _exit(4);           /* the parent died before prctl */
    child_default_signals();
    alarm((unsigned)(timeout_ms / 1000 + 2));
    close(fd[0]);
    close(efd[0]);
    dup2(efd[1], STDERR_FILENO);
    fcntl(STDERR_FILENO, F_SETFL, O_NONBLOCK);   /* never block on a full pipe: drop the excess */
    child_import(src, label, fd[1]);
}

/* Import in a forked child with a time limit; merged arrays into o. */
static int import_sandboxed(const import_src *src, const char *label, int timeout_ms, merged *o, char *err,
                            size_t errlen)
{
    memset(o, 0, sizeof *o);
    int fd[2], efd[2];
    if (pipe(fd) != 0) return import_merged(src, label, o, err, errlen);
    if (pipe(efd) != 0) { close(fd[0]); close(fd[1]); return import_merged(src, label, o, err, errlen); }
    pid_t parent = getpid(), pid = fork();
    if (pid == 0) child_main(src, label, fd, efd, parent, timeout_ms);
    close(fd[1]);
    close(efd[1]);
    if (pid < 0) {
        close(fd[0]); close(efd[0]);
        return import_merged(src, label, o, err, errlen);
    }
    int r = receive(fd[0], now_ms() + timeout_ms, label, o, err, errlen);
    close(fd[0]);
    if (r == -2) kill(pid, SIGKILL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    char what[256];
    child_stderr(efd[0], what, sizeof what);
    close(efd[0]);
    if (r == -1 || r == -2) {
        merged_free(o);
        memset(o, 0, sizeof *o);
        return child_failure(r, status, label, timeout_ms, what, err, errlen);
    }
    return r;
}

/* Import (in a child unless opt->in_process), then build *out from the merged arrays. */
static int import_mesh(const import_src *src, const char *label, const is_mesh_options *opt, is_mesh *out,
                       char *err, size_t errlen)
{
    merged o;
    int timeout = opt && opt->import_timeout_ms > 0 ? opt->import_timeout_ms : DEFAULT_TIMEOUT_MS;
    int rc = opt && opt->in_process ? import_merged(src, label, &o, err, errlen)
                                    : import_sandboxed(src, label, timeout, &o, err, errlen);
    if (rc == IS_MESH_OK) {
        is_mesh_data d = {o.nv, o.nt, o.p, o.any_normals ? o.n : NULL, o.uv, o.idx};
        rc = mesh_create(out, label, &d, opt, err, errlen);
        if (rc == IS_MESH_OK) {
            out->stats.primitives_skipped = o.skipped;
            if (o.skipped && opt && opt->warn) {
                char msg[512];
                snprintf(msg, sizeof msg, "%s: skipped %zu point/line primitive(s)", label, o.skipped);
                opt->warn(opt->warn_user, msg);
            }
        }
    }
    merged_free(&o);
    return rc;
}

/* The extension of path including the dot (".obj"), or NULL. */
static const char *extension_of(const char *path)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash) || dot[1] == '\0') return NULL;
    return dot;
}

/* Checks before assimp sees the file: exists, regular, not empty, a known extension. */
static int check_file(const char *path, char *err, size_t errlen)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        mesh_set_err(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return IS_MESH_ERR_IO;
    }
    if (S_ISDIR(st.st_mode)) {
        mesh_set_err(err, errlen, "%s: is a directory, not a mesh file", path);
        return IS_MESH_ERR_IO;
    }
    if (st.st_size == 0) {
        mesh_set_err(err, errlen, "%s: empty file", path);
        return IS_MESH_ERR_IO;
    }
    const char *ext = extension_of(path);
    if (!ext) {
        mesh_set_err(err, errlen, "%s: no file extension: cannot tell the mesh format", path);
        return IS_MESH_ERR_FORMAT;
    }
    if (!aiIsExtensionSupported(ext)) {
        mesh_set_err(err, errlen, "%s: unknown mesh format '%s' (not an extension assimp reads)", path, ext);
        return IS_MESH_ERR_FORMAT;
    }
    return IS_MESH_OK;
}

/* mesh_load_file: see meshes.h. */
int mesh_load_file(const char *path, const is_mesh_options *opt, is_mesh *out, char *err, size_t errlen)
{
    if (out) memset(out, 0, sizeof *out);
    if (!path || !out) {
        mesh_set_err(err, errlen, "mesh_load_file: NULL argument");
        return IS_MESH_ERR_ARG;
    }
    int rc = check_file(path, err, errlen);
    if (rc != IS_MESH_OK) return rc;
    import_src src = {path, NULL, 0, NULL};
    return import_mesh(&src, path, opt, out, err, errlen);
}

/* mesh_load_memory: see meshes.h. */
int mesh_load_memory(const void *data, size_t size, const char *hint, const char *label,
                     const is_mesh_options *opt, is_mesh *out, char *err, size_t errlen)
{
    if (!label) label = "<memory>";
    if (out) memset(out, 0, sizeof *out);
    if (!out || (!data && size)) {
        mesh_set_err(err, errlen, "%s: mesh_load_memory: NULL argument", label);
        return IS_MESH_ERR_ARG;
    }
    if (size == 0) {
        mesh_set_err(err, errlen, "%s: empty buffer", label);
        return IS_MESH_ERR_IO;
    }
    if (size > UINT_MAX) {
        mesh_set_err(err, errlen, "%s: buffer too large (%zu bytes)", label, size);
        return IS_MESH_ERR_INVALID;
    }
    import_src src = {NULL, data, size, hint};
    return import_mesh(&src, label, opt, out, err, errlen);
}

/* mesh_open: see meshes.h. */
int mesh_open(const char *spec, const is_mesh_options *opt, is_mesh *out, char *err, size_t errlen)
{
    if (!spec) return mesh_load_file(spec, opt, out, err, errlen);
    for (const char *const *n = mesh_builtin_names(); *n; n++)
        if (strcmp(*n, spec) == 0) return mesh_builtin_ex(spec, opt, out, err, errlen);
    struct stat st;
    if (!strchr(spec, '/') && !strchr(spec, '.') && stat(spec, &st) != 0) {
        if (out) memset(out, 0, sizeof *out);
        mesh_set_err(err, errlen, "%s: neither a built-in mesh (tetrahedron, cube, cube-split, octahedron, "
                "icosahedron, sphere, cylinder) nor a file", spec);
        return IS_MESH_ERR_ARG;
    }
    return mesh_load_file(spec, opt, out, err, errlen);
}
