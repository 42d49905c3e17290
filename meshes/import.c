/* meshes/import.c -- users' meshes through assimp's C API, merged into one is_mesh (see meshes.h).  assimp
 * reads files only through meshes/import_io.c's file system, runs in a forked child with time and memory
 * limits, and sees a PLY or OFF file only after meshes/import_check.c has checked its header's counts. */
#define _DEFAULT_SOURCE 1   /* MAP_ANONYMOUS */
#include "meshes.h"
#include "mesh_internal.h"

#include "../core/hlsl.h"
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif
#include <time.h>
#include <unistd.h>

#include <assimp/cimport.h>
#include <assimp/version.h>
#include <meshoptimizer.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <meshoptimizer.h>

/* Triangulate polygons; ValidateDataStructure rejects inconsistent scenes (bad indices) from hostile files;
 * ConvertToLeftHanded = MakeLeftHanded (z -> -z on positions, normals and node transforms) + FlipWindingOrder
 * + FlipUVs: assimp's right-handed counter-clockwise data becomes left-handed clockwise (outward normal still
 * cross(v1 - v0, v2 - v0)) with D3D texcoords.  No JoinIdenticalVertices: its absolute tolerance (1e-5) joins
 * distinct vertices of a small mesh, so the image would depend on the unit; join_identical joins bitwise-equal
 * vertices instead.  No GenNormals / GenSmoothNormals / FindDegenerates: normals and degenerate triangles are
 * ours (counted, see mesh_create). */
#define IMPORT_FLAGS (aiProcess_Triangulate | aiProcess_ValidateDataStructure | aiProcess_ConvertToLeftHanded)
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

/* Destination arrays of the merge (NULL pointers in the counting pass), and the counting pass's bounds. */
typedef struct merged {
    size_t nv, nt, skipped;
    float3 *p, *n;
    float2 *uv;
    uint32_t *idx;
    bool any_normals;
    const size_t *mesh_tris;     /* counting pass: triangles of each scene mesh (counted once, not per use) */
    size_t instances;            /* counting pass: mesh references made by the nodes so far */
    mesh_texture_use tex;        /* filling pass: the diffuse textures of the meshes drawn (import_texture.c) */
} merged;

/* Why the counting walk stopped. */
enum { WALK_OK = 0, WALK_DEEP = -1, WALK_LARGE = -2 };

/* Append the triangles of mesh `am` (vertex base `base`); flip winding under a mirroring transform. */
static void append_faces(merged *o, const struct aiMesh *am, size_t base, bool flip)
{
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        const struct aiFace *face = &am->mFaces[f];
        if (face->mNumIndices != 3) { o->skipped++; continue; }
        uint32_t *t = o->idx + 3 * o->nt;
        t[0] = (uint32_t)(base + face->mIndices[0]);
        t[1] = (uint32_t)(base + face->mIndices[flip ? 2 : 1]);
        t[2] = (uint32_t)(base + face->mIndices[flip ? 1 : 2]);
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

/* The file normal q through the cofactor matrix c (sign s), normalized in double: a node that scales by
 * 1e-20 must not shrink normals below float's range (they would count as zero and be replaced).  Zero and
 * non-finite normals stay as they are (mesh_create replaces and counts them). */
static float3 transform_normal(const double c[3][3], double s, const struct aiVector3D *q)
{
    double x = s * (c[0][0] * q->x + c[0][1] * q->y + c[0][2] * q->z);
    double y = s * (c[1][0] * q->x + c[1][1] * q->y + c[1][2] * q->z);
    double z = s * (c[2][0] * q->x + c[2][1] * q->y + c[2][2] * q->z);
    double l = sqrt(x * x + y * y + z * z);
    if (l > 0.0 && isfinite(l)) x /= l, y /= l, z /= l;
    return f3((float)x, (float)y, (float)z);
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
        /* missing normals: zero, replaced (and counted) by mesh_create */
        o->n[o->nv + v] = am->mNormals ? transform_normal(c, s, &am->mNormals[v]) : f3(0.0f, 0.0f, 0.0f);
        const struct aiVector3D *t = am->mTextureCoords[0] ? &am->mTextureCoords[0][v] : NULL;
        o->uv[o->nv + v] = t ? f2(t->x, t->y) : f2(0.0f, 0.0f);
    }
}

/* Add one use of scene mesh k: counted (o->p NULL, with per-mesh triangle counts), or appended. */
static void append_mesh(merged *o, const struct aiScene *sc, unsigned k, const xform *x)
{
    const struct aiMesh *am = sc->mMeshes[k];
    if (!am || !am->mVertices || am->mNumVertices == 0) return;
    if (am->mNormals) o->any_normals = true;
    if (!o->p) {
        o->instances++;
        o->nt += o->mesh_tris[k];
        o->skipped += am->mNumFaces - o->mesh_tris[k];
    } else {
        append_vertices(o, am, x);
        append_faces(o, am, o->nv, det3(x) < 0.0);
        mesh_texture_note(&o->tex, sc, am);
    }
    o->nv += am->mNumVertices;
}

/* Whether the counting pass has passed a limit (then it stops: a node graph that shares its children
 * expands as a tree, 2^depth uses of one mesh, and must not be walked to its end). */
static bool over_limits(const merged *o)
{
    return !o->p && (o->instances > MESH_MAX_NODE_INSTANCES || o->nt > MESH_MAX_IMPORT_TRIANGLES ||
                     o->nv > MESH_MAX_IMPORT_VERTICES);
}

/* Walk the node tree, merging (or counting) every referenced mesh with its global transform.  WALK_OK,
 * WALK_DEEP (nested deeper than MAX_NODE_DEPTH) or WALK_LARGE (over_limits). */
static int walk(merged *o, const struct aiScene *sc, const struct aiNode *node, const xform *parent, int depth)
{
    if (depth > MAX_NODE_DEPTH) return WALK_DEEP;
    xform local = xform_of(&node->mTransformation), g = xform_mul(parent, &local);
    for (unsigned i = 0; i < node->mNumMeshes; i++) {
        if (node->mMeshes[i] < sc->mNumMeshes) append_mesh(o, sc, node->mMeshes[i], &g);
        if (over_limits(o)) return WALK_LARGE;
    }
    for (unsigned i = 0; i < node->mNumChildren; i++) {
        int r = node->mChildren[i] ? walk(o, sc, node->mChildren[i], &g, depth + 1) : WALK_OK;
        if (r != WALK_OK) return r;
    }
    return WALK_OK;
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

/* Triangles of each scene mesh into a new array (NULL when out of memory). */
static size_t *count_mesh_triangles(const struct aiScene *sc)
{
    size_t *n = calloc(sc->mNumMeshes ? sc->mNumMeshes : 1, sizeof *n);
    for (unsigned k = 0; n && k < sc->mNumMeshes; k++) {
        const struct aiMesh *am = sc->mMeshes[k];
        for (unsigned f = 0; am && f < am->mNumFaces; f++) n[k] += am->mFaces[f].mNumIndices == 3;
    }
    return n;
}

/* The counting pass over sc into o (counts only); an error message for a scene too deep or too large. */
static int count_scene(merged *o, const struct aiScene *sc, const char *label, char *err, size_t errlen)
{
    static const xform identity = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
    size_t *tris = count_mesh_triangles(sc);
    if (!tris) {
        mesh_set_err(err, errlen, "%s: out of memory", label);
        return IS_MESH_ERR_NOMEM;
    }
    memset(o, 0, sizeof *o);
    o->mesh_tris = tris;
    int r = sc->mRootNode ? walk(o, sc, sc->mRootNode, &identity, 0) : WALK_DEEP;
    free(tris);
    o->mesh_tris = NULL;
    if (r == WALK_DEEP)
        mesh_set_err(err, errlen, "%s: invalid scene (no root node, or nodes nested deeper than %d)", label,
                MAX_NODE_DEPTH);
    else if (r == WALK_LARGE && o->instances > MESH_MAX_NODE_INSTANCES)
        mesh_set_err(err, errlen, "%s: too large: the scene's nodes use meshes more than %zu times (nodes that "
                "share children expand as a tree)", label, MESH_MAX_NODE_INSTANCES);
    else if (r == WALK_LARGE)
        mesh_set_err(err, errlen, "%s: too large after instancing the scene's nodes: more than %zu %s", label,
                o->nt > MESH_MAX_IMPORT_TRIANGLES ? MESH_MAX_IMPORT_TRIANGLES : MESH_MAX_IMPORT_VERTICES,
                o->nt > MESH_MAX_IMPORT_TRIANGLES ? "triangles" : "vertices");
    return r == WALK_OK ? IS_MESH_OK : IS_MESH_ERR_INVALID;
}

/* Renumber a remap table (old vertex -> class) so that classes are numbered in the order of their first
 * vertex, as assimp's JoinIdenticalVertices did: vertex numbers in messages follow the file's order. */
static bool renumber_in_vertex_order(unsigned *remap, size_t nv, size_t unique)
{
    unsigned *rank = malloc((unique ? unique : 1) * sizeof *rank), next = 0;
    if (!rank) return false;
    memset(rank, 0xff, (unique ? unique : 1) * sizeof *rank);
    for (size_t v = 0; v < nv; v++) {
        if (remap[v] == ~0u) continue;   /* unused: dropped */
        if (rank[remap[v]] == ~0u) rank[remap[v]] = next++;
        remap[v] = rank[remap[v]];
    }
    free(rank);
    return true;
}

/* Join vertices whose position, normal and texcoord are bitwise equal (meshoptimizer's vertex remap); unused
 * vertices go.  Exact, so it does not depend on the mesh's unit (formats that store one vertex per corner,
 * OBJ and STL, become indexed).  false when out of memory. */
static bool join_identical(merged *o)
{
    unsigned *remap = malloc((o->nv ? o->nv : 1) * sizeof *remap);
    if (!remap) return false;
    const struct meshopt_Stream streams[3] = {{o->p, sizeof(float3), sizeof(float3)},
                                              {o->n, sizeof(float3), sizeof(float3)},
                                              {o->uv, sizeof(float2), sizeof(float2)}};
    size_t unique = meshopt_generateVertexRemapMulti(remap, o->idx, 3 * o->nt, o->nv, streams, 3);
    if (!renumber_in_vertex_order(remap, o->nv, unique)) { free(remap); return false; }
    meshopt_remapVertexBuffer(o->p, o->p, o->nv, sizeof(float3), remap);
    meshopt_remapVertexBuffer(o->n, o->n, o->nv, sizeof(float3), remap);
    meshopt_remapVertexBuffer(o->uv, o->uv, o->nv, sizeof(float2), remap);
    meshopt_remapIndexBuffer(o->idx, o->idx, 3 * o->nt, remap);
    free(remap);
    o->nv = unique;
    return true;
}

/* Count, check sizes, allocate, fill and join the merged arrays of scene sc. */
static int merge_scene(merged *o, const struct aiScene *sc, const char *label, char *err, size_t errlen)
{
    static const xform identity = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
    int rc = count_scene(o, sc, label, err, errlen);
    if (rc != IS_MESH_OK) return rc;
    if (o->nt == 0) {
        mesh_set_err(err, errlen, "%s: no triangles (%zu point/line primitives, %u meshes)", label, o->skipped,
                sc->mNumMeshes);
        return IS_MESH_ERR_EMPTY;
    }
    size_t nv = o->nv, nt = o->nt;
    bool ok = merged_alloc(o);
    o->nv = o->nt = o->skipped = 0;
    if (ok) walk(o, sc, sc->mRootNode, &identity, 0);
    if (!ok || !join_identical(o)) {
        mesh_set_err(err, errlen, "%s: out of memory (%zu vertices, %zu triangles)", label, nv, nt);
        return IS_MESH_ERR_NOMEM;
    }
    return IS_MESH_OK;
}

/* The limits of one import (is_mesh_options, 0 meaning the default). */
typedef struct import_limits {
    int timeout_ms;
    uint64_t max_file_bytes;
    uint64_t max_memory;         /* address space the child may add (RLIMIT_AS); 0: the size rule (mem_guard) */
} import_limits;

/* The import child's memory limit: the address space (RLIMIT_AS) and the private writable memory
 * (RLIMIT_DATA) it had when it was forked, each plus `allowed`.  RLIMIT_AS is the limit of a normal build;
 * under AddressSanitizer, whose allocator maps its chunks inside a region reserved at start-up, only
 * RLIMIT_DATA grows.  With the size rule, allowed starts at MESH_IMPORT_MEMORY_FLOOR and grows by
 * MESH_IMPORT_MEMORY_PER_BYTE for every byte of the files assimp opens (import_io.c calls mem_grow); a fixed
 * limit does not grow.  `shared` is a page shared with the parent, which reads the limit in force (MiB) when
 * the child died of it. */
typedef struct mem_guard {
    uint64_t base_as, base_data, allowed, per_byte;
    volatile uint64_t *shared;
    bool active;
} mem_guard;

/* Where to import from: a file (path) or a buffer (data, size, hint); its limits; the child's memory guard
 * (NULL in the parent and in_process). */
typedef struct import_src {
    const char *path;
    const void *data;
    size_t size;
    const char *hint;
    import_limits lim;
    mem_guard *guard;
} import_src;

/* Set the soft limit `res` to base + allowed (never above the hard limit; never raised past a lower limit the
 * process had before the guard: then nothing is set).  Whether it is in force. */
static bool set_limit(int res, uint64_t base, uint64_t allowed, bool active)
{
    struct rlimit rl;
    if (base == 0 || getrlimit(res, &rl) != 0) return false;
    uint64_t want = base > UINT64_MAX - allowed ? UINT64_MAX : base + allowed;
    if (!active && rl.rlim_cur != RLIM_INFINITY && (uint64_t)rl.rlim_cur <= want) return false;
    rl.rlim_cur = rl.rlim_max != RLIM_INFINITY && (uint64_t)rl.rlim_max < want ? rl.rlim_max : (rlim_t)want;
    return setrlimit(res, &rl) == 0;
}

/* Put the guard's limits in force; whether one is. */
static bool mem_apply(mem_guard *g)
{
    bool as = set_limit(RLIMIT_AS, g->base_as, g->allowed, g->active);
    bool data = set_limit(RLIMIT_DATA, g->base_data, g->allowed, g->active);
    g->active = g->active || as || data;
    if (g->active && g->shared) *g->shared = g->allowed >> 20;
    return g->active;
}

/* mesh_io's hook: a file of `bytes` was opened; the size rule lets the import use more memory for it. */
static void mem_grow(void *user, uint64_t bytes)
{
    mem_guard *g = user;
    if (!g->active || !g->per_byte) return;
    g->allowed = bytes > (UINT64_MAX - g->allowed) / g->per_byte ? UINT64_MAX : g->allowed + bytes * g->per_byte;
    mem_apply(g);
}

/* The message of an import that ran out of the child's memory limit of `mib` MiB. */
static int out_of_memory(uint64_t mib, const char *label, char *err, size_t errlen)
{
    mesh_set_err(err, errlen, "%s: cannot read the mesh: assimp ran out of the import memory limit of %llu MiB",
                 label, (unsigned long long)mib);
    return IS_MESH_ERR_NOMEM;
}

/* The message of a failed import: the memory limit, a refused file, or assimp's reason (sanitized). */
static int import_error(const import_src *src, const mesh_io *io, const char *label, char *err, size_t errlen)
{
    const char *msg = aiGetErrorString();
    char safe[400];
    mesh_sanitize(safe, sizeof safe, msg && *msg ? msg : "assimp failed", 300);
    if (src->guard && src->guard->active && (strstr(safe, "bad_alloc") || !(msg && *msg)))
        return out_of_memory(src->guard->allowed >> 20, label, err, errlen);
    if (io->refusal[0]) mesh_set_err(err, errlen, "%s (assimp: %s)", io->refusal, safe);
    else mesh_set_err(err, errlen, "%s: cannot read the mesh: %s", label, safe);
    return io->refusal[0] ? IS_MESH_ERR_IO : IS_MESH_ERR_FORMAT;
}

/* assimp's loaders that meet a face index past the end of their vertices clamp it, log an error and go on (OFF
 * and MD2 among them; meshes/import_check.c names the face for those before the import): an import during which
 * such an error is logged fails with it.  The first message is kept. */
typedef struct index_log { char msg[300]; } index_log;

/* assimp's log callback (user: the index_log): keep the first error about an index out of range. */
static void on_assimp_log(const char *message, char *user)
{
    index_log *l = (index_log *)(void *)user;
    if (l->msg[0] || strncmp(message, "Error", 5) != 0 || (!strstr(message, "index") && !strstr(message, "Index")) ||
        (!strstr(message, "out of range") && !strstr(message, "outside the allowed range")))
        return;
    const char *m = strstr(message, ": ");   /* "Error, T0: MD2: Vertex index is outside the allowed range\n" */
    char text[300];
    snprintf(text, sizeof text, "%s", m ? m + 2 : message);
    text[strcspn(text, "\r\n")] = '\0';
    mesh_sanitize(l->msg, sizeof l->msg, text, 250);
}

/* Import with assimp in this process through meshes/import_io.c's file system and merge the scene into o
 * (arrays owned by o); a file refused by an import that still succeeded goes to note[notelen]. */
static int import_merged(const import_src *src, const char *label, merged *o, char *note, size_t notelen,
                         char *err, size_t errlen)
{
    memset(o, 0, sizeof *o);
    mesh_io io;
    if (src->path) {
        int rc = mesh_io_init_file(&io, src->path, label, src->lim.max_file_bytes, err, errlen);
        if (rc != IS_MESH_OK) return rc;
    } else {
        mesh_io_init_memory(&io, src->data, src->size, src->hint, label);
        if (src->guard) mem_grow(src->guard, src->size);
    }
    if (src->guard) io.on_file = mem_grow, io.on_file_user = src->guard;
    index_log ilog = {""};
    struct aiLogStream stream = {on_assimp_log, (char *)&ilog};
    aiAttachLogStream(&stream);
    const struct aiScene *sc = aiImportFileEx(mesh_io_name(&io), IMPORT_FLAGS, &io.fio);
    aiDetachLogStream(&stream);
    if (!sc) return import_error(src, &io, label, err, errlen);
    if (ilog.msg[0]) {
        aiReleaseImport(sc);
        mesh_set_err(err, errlen, "%s: a face names a vertex (or texture coordinate) the file does not have; assimp "
                     "would have used another in its place (assimp: %s)", label, ilog.msg);
        return IS_MESH_ERR_INVALID;
    }
    int rc = merge_scene(o, sc, label, err, errlen);
    aiReleaseImport(sc);
    if (rc == IS_MESH_ERR_NOMEM && src->guard && src->guard->active)
        return out_of_memory(src->guard->allowed >> 20, label, err, errlen);
    if (rc == IS_MESH_OK && note && notelen) snprintf(note, notelen, "%s", io.refusal);
    return rc;
}

/* ---------------- the child process (a crash or hang inside assimp becomes an error) ---------------- */

/* What the child sends first; the arrays follow when rc == 0. */
typedef struct child_header {
    int32_t rc;
    int32_t any_normals;
    uint64_t nv, nt, skipped;
    char err[512];
    char note[512];              /* a refused side file the import did without */
    mesh_texture_use tex;        /* the diffuse textures of the meshes drawn */
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
    h.rc = import_merged(src, label, &o, h.note, sizeof h.note, h.err, sizeof h.err);
    h.any_normals = o.any_normals;
    h.nv = o.nv; h.nt = o.nt; h.skipped = o.skipped;
    h.tex = o.tex;
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

/* How receiving from the child can fail, apart from the child's own error codes (IS_MESH_ERR_*). */
enum { RECV_DIED = -100, RECV_TIMEOUT = -101 };

/* Read len bytes before the deadline: 0, RECV_DIED at end of data / error, RECV_TIMEOUT. */
static int read_all(int fd, void *buf, size_t len, int64_t deadline)
{
    char *p = buf;
    while (len) {
        int64_t left = deadline - now_ms();
        if (left <= 0) return RECV_TIMEOUT;
        struct pollfd pfd = {fd, POLLIN, 0};
        int r = poll(&pfd, 1, left > INT_MAX ? INT_MAX : (int)left);
        if (r < 0 && errno == EINTR) continue;
        if (r == 0) return RECV_TIMEOUT;
        if (r < 0) return RECV_DIED;
        ssize_t got = read(fd, p, len);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) return RECV_DIED;
        p += got;
        len -= (size_t)got;
    }
    return 0;
}

/* Parent: receive the header and arrays into o (and the child's note).  0, RECV_DIED (child died / bad
 * data), RECV_TIMEOUT, or the child's own error code (message in err). */
static int receive(int fd, int64_t deadline, const char *label, merged *o, char *note, size_t notelen, char *err,
                   size_t errlen)
{
    child_header h;
    int r = read_all(fd, &h, sizeof h, deadline);
    if (r != 0) return r;
    h.err[sizeof h.err - 1] = '\0';
    h.note[sizeof h.note - 1] = '\0';
    if (h.rc != IS_MESH_OK) {
        mesh_set_err(err, errlen, "%s", h.err);
        return h.rc < 0 ? h.rc : IS_MESH_ERR_FORMAT;
    }
    snprintf(note, notelen, "%s", h.note);
    if (h.nv == 0 || h.nt == 0 || h.nv > MESH_MAX_IMPORT_VERTICES || h.nt > MESH_MAX_IMPORT_TRIANGLES)
        return RECV_DIED;
    o->nv = (size_t)h.nv; o->nt = (size_t)h.nt; o->skipped = (size_t)h.skipped; o->any_normals = h.any_normals;
    h.tex.name[sizeof h.tex.name - 1] = '\0';
    o->tex = h.tex;
    if (!merged_alloc(o)) {
        mesh_set_err(err, errlen, "%s: out of memory (%zu vertices, %zu triangles)", label, o->nv, o->nt);
        return IS_MESH_ERR_NOMEM;
    }
    if ((r = read_all(fd, o->p, o->nv * sizeof(float3), deadline)) != 0) return r;
    if ((r = read_all(fd, o->n, o->nv * sizeof(float3), deadline)) != 0) return r;
    if ((r = read_all(fd, o->uv, o->nv * sizeof(float2), deadline)) != 0) return r;
    return read_all(fd, o->idx, 3 * o->nt * sizeof(uint32_t), deadline);
}

/* The first line the child wrote to its stderr (assimp's assertion message), sanitized, into buf[len]; lines
 * of '=' only (AddressSanitizer's report frame) are skipped.  "" when there is no error pipe (fd < 0). */
static void child_stderr(int fd, char *buf, size_t len)
{
    buf[0] = '\0';
    struct pollfd pfd = {fd, POLLIN, 0};
    if (fd < 0 || poll(&pfd, 1, 0) <= 0) return;
    char raw[1024];
    ssize_t got = read(fd, raw, sizeof raw - 1);
    raw[got > 0 ? got : 0] = '\0';
    char *line = raw + strspn(raw, "=\r\n");
    line[strcspn(line, "\r\n")] = '\0';
    mesh_sanitize(buf, len, line, len - 1);
}

/* Whether the child's stderr says it ran out of memory: an uncaught std::bad_alloc (std::terminate), or the
 * allocator of an AddressSanitizer build (which reports and exits instead of returning NULL). */
static bool says_out_of_memory(const char *what)
{
    return strstr(what, "bad_alloc") || strstr(what, "Failed to mmap") ||
           (strstr(what, "AddressSanitizer") && (strstr(what, "out of memory") || strstr(what, "failed to allocate")));
}

/* Explain how the child ended when it sent no (complete) result. */
static int child_failure(int r, int status, const import_src *src, uint64_t limit_mib, const char *label,
                         const char *what, char *err, size_t errlen)
{
    const char *sep = *what ? ": " : "";
    if (r == RECV_TIMEOUT)
        mesh_set_err(err, errlen, "%s: cannot read the mesh: assimp did not finish within the import time limit of "
                "%g s (stopped)", label, src->lim.timeout_ms / 1000.0);
    else if (limit_mib && says_out_of_memory(what))
        return out_of_memory(limit_mib, label, err, errlen);
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

/* The process's address space and its data + stack memory in bytes (/proc/self/statm's size and data
 * fields); false when unknown. */
static bool memory_now(uint64_t *as, uint64_t *data)
{
    int fd = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    char buf[256];
    ssize_t got = read(fd, buf, sizeof buf - 1);
    close(fd);
    if (got <= 0) return false;
    buf[got] = '\0';
    unsigned long long f[6];
    long page = sysconf(_SC_PAGESIZE);
    if (page <= 0 || sscanf(buf, "%llu %llu %llu %llu %llu %llu", &f[0], &f[1], &f[2], &f[3], &f[4], &f[5]) != 6)
        return false;
    *as = f[0] * (uint64_t)page;
    *data = f[5] * (uint64_t)page;
    return true;
}

/* Child side of the fork: default signals; dies with its parent (a killed instess leaves no assimp running on,
 * hung or not) and at the time limit plus two seconds even if nobody reads it; stderr into the (non-blocking)
 * error pipe when there is one (efd[0] < 0: none, stderr stays); the memory limit; then import and exit.
 * Needs no descriptor beyond the pipes it was given, except one at a time for /proc/self/statm and the files
 * assimp reads. */
static _Noreturn void child_main(const import_src *src, const char *label, const int fd[2], const int efd[2],
                                 pid_t parent, volatile uint64_t *shared)
{
#ifdef __linux__
    prctl(PR_SET_PDEATHSIG, SIGKILL);
#endif
    if (getppid() != parent) _exit(4);           /* the parent died before prctl */
    child_default_signals();
    alarm((unsigned)(src->lim.timeout_ms / 1000 + 2));
    close(fd[0]);
    if (efd[0] >= 0) {
        close(efd[0]);
        dup2(efd[1], STDERR_FILENO);
        close(efd[1]);
        fcntl(STDERR_FILENO, F_SETFL, O_NONBLOCK);   /* never block on a full pipe: drop the excess */
    }
    mem_guard guard = {0, 0, src->lim.max_memory ? src->lim.max_memory : MESH_IMPORT_MEMORY_FLOOR,
                       src->lim.max_memory ? 0 : MESH_IMPORT_MEMORY_PER_BYTE, shared, false};
    if (memory_now(&guard.base_as, &guard.base_data)) mem_apply(&guard);
    import_src limited = *src;
    limited.guard = &guard;
    child_import(&limited, label, fd[1]);
}

/* The message of an import that could not start (no pipe, no process): errno e of step `what`. */
static int start_failure(const char *label, const char *what, int e, char *err, size_t errlen)
{
    mesh_set_err(err, errlen, "%s: cannot start the import process (%s: %s)", label, what, strerror(e));
    return IS_MESH_ERR_IO;
}

/* Import in a forked child with time and memory limits; merged arrays into o, the child's note into note.
 * Without a descriptor for the data pipe (ulimit -n), or without a process, this is an error, never an
 * import in this process: the file may be one that crashes assimp.  Without a second pipe for the child's
 * stderr, the import goes on without its assertion text. */
static int import_sandboxed(const import_src *src, const char *label, merged *o, char *note, size_t notelen,
                            char *err, size_t errlen)
{
    memset(o, 0, sizeof *o);
    int fd[2], efd[2] = {-1, -1};
    if (pipe(fd) != 0) return start_failure(label, "pipe", errno, err, errlen);
    if (pipe(efd) != 0) efd[0] = efd[1] = -1;
    volatile uint64_t *shared = mmap(NULL, sizeof *shared, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (shared == MAP_FAILED) shared = NULL;
    else *shared = 0;
    pid_t parent = getpid(), pid = fork();
    if (pid == 0) child_main(src, label, fd, efd, parent, shared);
    int fork_errno = errno;
    close(fd[1]);
    if (efd[1] >= 0) close(efd[1]);
    if (pid < 0) {
        close(fd[0]);
        if (efd[0] >= 0) close(efd[0]);
        if (shared) munmap((void *)shared, sizeof *shared);
        return start_failure(label, "fork", fork_errno, err, errlen);
    }
    int r = receive(fd[0], now_ms() + src->lim.timeout_ms, label, o, note, notelen, err, errlen);
    close(fd[0]);
    if (r == RECV_TIMEOUT) kill(pid, SIGKILL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    char what[256];
    child_stderr(efd[0], what, sizeof what);
    if (efd[0] >= 0) close(efd[0]);
    uint64_t limit_mib = shared ? *shared : 0;
    if (shared) munmap((void *)shared, sizeof *shared);
    if (r == RECV_DIED || r == RECV_TIMEOUT) {
        merged_free(o);
        memset(o, 0, sizeof *o);
        return child_failure(r, status, src, limit_mib, label, what, err, errlen);
    }
    return r;
}

/* Warn about a side file the import did without, and about the file's normals; the file's texture (path: the
 * mesh file, NULL for a memory import). */
static void import_warnings(is_mesh *m, const char *path, const char *label, const char *note,
                            const mesh_texture_use *tex, const is_mesh_options *opt)
{
    if (m->stats.primitives_skipped)
        mesh_warn(opt, "%s: skipped %zu point/line primitive(s)", label, m->stats.primitives_skipped);
    if (note[0]) mesh_warn(opt, "%s", note);
    mesh_check_normals(m, label, opt);
    mesh_texture_resolve(m, path, label, tex, opt);
}

/* Import (in a child unless opt->in_process), then build *out from the merged arrays. */
static int import_mesh(const import_src *src, const char *label, const is_mesh_options *opt, is_mesh *out,
                       char *err, size_t errlen)
{
    merged o;
    char note[512] = "";
    int rc = opt && opt->in_process ? import_merged(src, label, &o, note, sizeof note, err, errlen)
                                    : import_sandboxed(src, label, &o, note, sizeof note, err, errlen);
    if (rc == IS_MESH_OK) {
        is_mesh_data d = {o.nv, o.nt, o.p, o.any_normals ? o.n : NULL, o.uv, o.idx};
        rc = mesh_create(out, label, &d, opt, err, errlen);
        if (rc == IS_MESH_OK) {
            out->stats.primitives_skipped = o.skipped;
            import_warnings(out, src->path, label, note, &o.tex, opt);
        }
    }
    merged_free(&o);
    return rc;
}

/* The limits of opt, with the defaults for its zeros. */
static import_limits limits_of(const is_mesh_options *opt)
{
    import_limits l = {DEFAULT_TIMEOUT_MS, MESH_DEFAULT_MAX_FILE_BYTES, 0};
    if (opt && opt->import_timeout_ms > 0) l.timeout_ms = opt->import_timeout_ms;
    if (opt && opt->max_file_bytes > 0) l.max_file_bytes = opt->max_file_bytes;
    if (opt && opt->max_import_memory_bytes > 0) l.max_memory = opt->max_import_memory_bytes;
    return l;
}

/* The extension of path including the dot (".obj"), or NULL. */
static const char *extension_of(const char *path)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash) || dot[1] == '\0') return NULL;
    return dot;
}

/* The kind of a file that is not regular, for messages. */
static const char *file_kind(mode_t mode)
{
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    return "not a regular file";
}

/* Checks of the file itself before assimp sees it: exists, a regular file (not a directory, device, FIFO or
 * socket), not empty, within the size limit, a known extension.  Its size into *size. */
static int check_file(const char *path, const char *label, uint64_t max_bytes, uint64_t *size, char *err,
                      size_t errlen)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        mesh_set_err(err, errlen, "%s: cannot open: %s", label, strerror(errno));
        return IS_MESH_ERR_IO;
    }
    if (S_ISDIR(st.st_mode)) {
        mesh_set_err(err, errlen, "%s: is a directory, not a mesh file", label);
        return IS_MESH_ERR_IO;
    }
    if (!S_ISREG(st.st_mode)) {
        mesh_set_err(err, errlen, "%s: is %s, not a mesh file", label, file_kind(st.st_mode));
        return IS_MESH_ERR_IO;
    }
    if (st.st_size == 0) {
        mesh_set_err(err, errlen, "%s: empty file", label);
        return IS_MESH_ERR_IO;
    }
    if ((uint64_t)st.st_size > max_bytes) {
        mesh_set_err(err, errlen, "%s: the file has %llu bytes, more than the limit of %llu (%llu MiB)", label,
                (unsigned long long)st.st_size, (unsigned long long)max_bytes, (unsigned long long)(max_bytes >> 20));
        return IS_MESH_ERR_INVALID;
    }
    *size = (uint64_t)st.st_size;
    const char *ext = extension_of(path);
    if (!ext) {
        mesh_set_err(err, errlen, "%s: no file extension: cannot tell the mesh format", label);
        return IS_MESH_ERR_FORMAT;
    }
    if (!aiIsExtensionSupported(ext)) {
        char safe[40];
        mesh_sanitize(safe, sizeof safe, ext, 24);
        mesh_set_err(err, errlen, "%s: unknown mesh format '%s' (not an extension assimp reads)", label, safe);
        return IS_MESH_ERR_FORMAT;
    }
    return IS_MESH_OK;
}

/* The first `max` bytes of the file at path (fewer when it is shorter) into a malloc'd buffer (*n bytes), or NULL
 * with a message naming label (*rc the error). */
static unsigned char *read_prefix(const char *path, const char *label, size_t max, size_t *n, int *rc, char *err,
                                  size_t errlen)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        mesh_set_err(err, errlen, "%s: cannot open: %s", label, strerror(errno));
        return *rc = IS_MESH_ERR_IO, NULL;
    }
    unsigned char *data = malloc(max ? max : 1);
    *n = 0;
    while (data && *n < max) {
        ssize_t got = read(fd, data + *n, max - *n);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) break;
        *n += (size_t)got;
    }
    close(fd);
    if (!data) mesh_set_err(err, errlen, "%s: out of memory", label), *rc = IS_MESH_ERR_NOMEM;
    return data;
}

/* Check the PLY / OFF header at the start of the file (mesh_check_header). */
static int check_file_header(const char *path, const char *label, uint64_t size, char *err, size_t errlen)
{
    size_t n;
    int rc = IS_MESH_OK;
    unsigned char *head = read_prefix(path, label, MESH_HEADER_BYTES, &n, &rc, err, errlen);
    if (head) rc = mesh_check_header(head, n, size, label, err, errlen);
    free(head);
    return rc;
}

/* path's extension without the dot ("" when none). */
static const char *ext_of(const char *path)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    return dot && (!slash || dot > slash) ? dot + 1 : "";
}

/* The face indices of a text OFF or OBJ file or an MD2 file of `size` bytes (mesh_check_face_indices); other
 * formats pass unread. */
static int check_file_indices(const char *path, const char *label, uint64_t size, char *err, size_t errlen)
{
    const char *ext = ext_of(path);
    if (strcasecmp(ext, "off") != 0 && strcasecmp(ext, "obj") != 0 && strcasecmp(ext, "md2") != 0) return IS_MESH_OK;
    size_t n;
    int rc = IS_MESH_OK;
    unsigned char *data = read_prefix(path, label, (size_t)size, &n, &rc, err, errlen);
    if (data) rc = mesh_check_face_indices(data, n, ext, label, err, errlen);
    free(data);
    return rc;
}

/* mesh_load_file: see meshes.h. */
int mesh_load_file(const char *path, const is_mesh_options *opt, is_mesh *out, char *err, size_t errlen)
{
    if (out) memset(out, 0, sizeof *out);
    if (!path || !out) {
        mesh_set_err(err, errlen, "mesh_load_file: NULL argument");
        return IS_MESH_ERR_ARG;
    }
    char label[256];
    mesh_sanitize(label, sizeof label, path, 240);
    import_src src = {path, NULL, 0, NULL, limits_of(opt), NULL};
    uint64_t size = 0;
    int rc = check_file(path, label, src.lim.max_file_bytes, &size, err, errlen);
    if (rc == IS_MESH_OK) rc = check_file_header(path, label, size, err, errlen);
    if (rc == IS_MESH_OK) rc = check_file_indices(path, label, size, err, errlen);
    if (rc != IS_MESH_OK) return rc;
    return import_mesh(&src, label, opt, out, err, errlen);
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
    import_src src = {NULL, data, size, hint, limits_of(opt), NULL};
    if ((uint64_t)size > src.lim.max_file_bytes) {
        mesh_set_err(err, errlen, "%s: buffer too large (%zu bytes, more than the limit of %llu)", label, size,
                (unsigned long long)src.lim.max_file_bytes);
        return IS_MESH_ERR_INVALID;
    }
    int rc = mesh_check_header(data, size < MESH_HEADER_BYTES ? size : MESH_HEADER_BYTES, size, label, err, errlen);
    if (rc == IS_MESH_OK) rc = mesh_check_face_indices(data, size, hint, label, err, errlen);
    if (rc != IS_MESH_OK) return rc;
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
        char safe[256];
        mesh_sanitize(safe, sizeof safe, spec, 200);
        mesh_set_err(err, errlen, "%s: neither a built-in mesh (tetrahedron, cube, cube-split, octahedron, "
                "icosahedron, sphere, cylinder) nor a file", safe);
        return IS_MESH_ERR_ARG;
    }
    return mesh_load_file(spec, opt, out, err, errlen);
}

/* mesh_library_versions: see meshes.h. */
void mesh_library_versions(char *buf, size_t len)
{
    if (!buf || len == 0) return;
    snprintf(buf, len, "assimp %u.%u.%u, meshoptimizer %d.%d", aiGetVersionMajor(), aiGetVersionMinor(),
             aiGetVersionPatch(), MESHOPTIMIZER_VERSION / 1000, MESHOPTIMIZER_VERSION % 1000 / 10);
}
