/* tests/fuzz/fuzz_targets.c -- the code paths of the fuzzers (see fuzz_targets.h).
 *
 * Raw-array layout of fuzz_mesh_input (missing bytes read as 0):
 *   byte 0  vertices  = 1 + b % 64          byte 5  level fraction b / 256 (pg grids only)
 *   byte 1  triangles = 1 + b % 64          byte 6  path b % 3, fill (b / 3) % 4
 *   byte 2  flags: 1 normals given, 2 texcoords given, 4 raw float32 (else int8 / 8, which makes shared and
 *           coincident vertices likely), 8 recompute normals, 16 4x MSAA, 32 AOVs (with 1 sample)
 *   byte 3  patch b % 6, normal mode (b / 6) % 3
 *   byte 4  grid b % 4, level 1 + (b / 4) % 8
 *   byte 7  yaw b * 360 / 256     byte 8 pitch (b - 128) * 180 / 256     byte 9 distance 1.01 + b / 16
 *   then positions (3 per vertex), normals (3 per vertex, if given), texcoords (2 per vertex, if given), each a
 *   float32 (4 bytes) or an int8 / 8 (1 byte); then 3 index bytes per triangle: 255 is the out-of-range index
 *   `vertices`, anything else b % vertices. */
#include "fuzz_targets.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../cli/run/scene.h"
#include "../../meshes/meshes.h"

#include "../../core/hlsl.h"
#define FUZZ_SIDE 32

/* printf into why; returns -1 (the "invariant broken" result). */
static int broken(char *why, size_t whylen, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, whylen, fmt, ap);
    va_end(ap);
    return -1;
}

/* Whether |n| is within 1e-3 of 1 and n is finite. */
static bool unit3(float3 n)
{
    float l = sqrtf(n.x * n.x + n.y * n.y + n.z * n.z);
    return isfinite(l) && fabsf(l - 1.0f) < 1e-3f;
}

/* The invariants of a mesh that mesh_create (or an import) accepted. */
static int check_mesh(const is_mesh *m, char *why, size_t whylen)
{
    if (m->n_triangles == 0 || m->n_vertices == 0 || m->stats.triangles != m->n_triangles)
        return broken(why, whylen, "accepted mesh with %zu triangles, %zu vertices", m->n_triangles, m->n_vertices);
    for (size_t v = 0; v < m->n_vertices; v++) {
        float3 p = m->positions[v];
        if (!(isfinite(p.x) && isfinite(p.y) && isfinite(p.z))) return broken(why, whylen, "vertex %zu not finite", v);
        if (!unit3(m->normals[v]))
            return broken(why, whylen, "normal %zu is (%g, %g, %g), not unit", v, m->normals[v].x, m->normals[v].y,
                          m->normals[v].z);
    }
    for (size_t i = 0; i < 3 * m->n_triangles; i++)
        if (m->indices[i] >= m->n_vertices || m->welded[i] >= m->n_vertices || m->opposite[i] >= m->n_vertices)
            return broken(why, whylen, "index %zu out of range", i);
    return 0;
}

/* Every channel finite; colour and depth in [0, 1]. */
static int check_image(const is_image *img, char *why, size_t whylen)
{
    size_t n = (size_t)img->width * img->height;
    for (size_t p = 0; p < n; p++)
        for (int c = 0; c < img->channels; c++) {
            float v = img->data[p * img->channels + c];
            if (!isfinite(v) || (c < 5 && (v < 0.0f || v > 1.0f)))
                return broken(why, whylen, "pixel (%zu, %zu) channel %s = %g", p % (size_t)img->width,
                              p / (size_t)img->width, img->channel_names[c], (double)v);
        }
    return 0;
}

/* Instances of m must be finite (they feed the shaders). */
static int check_instances(const is_mesh *m, char *why, size_t whylen)
{
    is_patch_instance *inst = malloc(m->n_triangles * sizeof *inst);
    if (!inst) return 0;
    int rc = mesh_build_instances(m, inst) == m->n_triangles ? 0 : broken(why, whylen, "instance count");
    const float *f = (const float *)inst;
    for (size_t k = 0; rc == 0 && k < m->n_triangles * sizeof *inst / sizeof(float); k++)
        if (!isfinite(f[k])) rc = broken(why, whylen, "instance float %zu is %g", k, (double)f[k]);
    free(inst);
    return rc;
}

/* Render m with o and check the image. */
static int render_and_check(const scene_opts *o, const is_mesh *m, char *why, size_t whylen)
{
    is_image img = {0};
    char err[1024] = "";
    if (scene_render_mesh(o, m, &img, NULL, err, sizeof err) != 0)
        return broken(why, whylen, "render of a valid mesh failed: %s", err);
    int rc = check_image(&img, why, whylen);
    image_free(&img);
    return rc;
}

/* An error result: a known code, a message naming the input, nothing allocated. */
static int check_error(int rc, const char *err, const char *label, const is_mesh *m, char *why, size_t whylen)
{
    if (rc < IS_MESH_ERR_NOMEM) return broken(why, whylen, "unknown error code %d", rc);
    if (!strstr(err, label)) return broken(why, whylen, "message does not name the input: '%s'", err);
    if (m->positions || m->indices || m->n_triangles) return broken(why, whylen, "failed import left a mesh");
    return 0;
}

/* ---------------------------------------- import ---------------------------------------- */

const char *fuzz_sniff_format(const uint8_t *d, size_t n)
{
    if (n >= 3 && memcmp(d, "ply", 3) == 0) return "ply";
    if ((n >= 3 && memcmp(d, "OFF", 3) == 0) || (n >= 4 && memcmp(d + 1, "OFF", 3) == 0)) return "off";
    if (n >= 5 && memcmp(d, "solid", 5) == 0) return "stl";
    if (n >= 84) {
        uint32_t count;
        memcpy(&count, d + 80, 4);
        if (84 + 50 * (uint64_t)count == n) return "stl";
    }
    if (n >= 4 && memcmp(d, "IDP2", 4) == 0) return "md2";
    if (n >= 4 && memcmp(d, "glTF", 4) == 0) return "glb";
    if (n >= 1 && d[0] == '{') return "gltf";
    return "obj";
}

int fuzz_import_input(const uint8_t *data, size_t size, bool sandboxed, int timeout_ms, char *why, size_t whylen)
{
    const char *hint = fuzz_sniff_format(data, size);
    char label[64], err[1024] = "";
    snprintf(label, sizeof label, "fuzz-input.%s", hint);
    is_mesh_options mo = {.in_process = !sandboxed, .import_timeout_ms = timeout_ms > 0 ? timeout_ms : 10000};
    is_mesh m;
    int rc = mesh_load_memory(size ? data : NULL, size, hint, label, &mo, &m, err, sizeof err);
    if (rc != 0) return check_error(rc, err, label, &m, why, whylen);
    int bad = check_mesh(&m, why, whylen);
    if (!bad) bad = check_instances(&m, why, whylen);
    scene_opts o;
    scene_opts_default(&o);
    o.width = o.height = FUZZ_SIDE, o.level = 3, o.msaa = 1, o.threads = 1, o.quiet = true;
    o.aovs = SCENE_AOV_NORMAL | SCENE_AOV_BARY | SCENE_AOV_GREGORY;
    if (!bad && m.n_triangles <= 200000) bad = render_and_check(&o, &m, why, whylen);
    mesh_free(&m);
    return bad;
}

/* ---------------------------------------- raw arrays ---------------------------------------- */

/* A cursor over the fuzzer's bytes; reads past the end give 0. */
typedef struct cursor { const uint8_t *d; size_t n, at; } cursor;

/* The next byte (0 past the end). */
static uint8_t next_byte(cursor *c) { return c->at < c->n ? c->d[c->at++] : 0; }

/* The next float: raw float32 bits, or a signed byte / 8. */
static float next_float(cursor *c, bool raw)
{
    if (!raw) return (float)(int8_t)next_byte(c) / 8.0f;
    uint8_t b[4] = {next_byte(c), next_byte(c), next_byte(c), next_byte(c)};
    float f;
    memcpy(&f, b, 4);
    return f;
}

/* The scene options of the header bytes h[0..9], made consistent (scene_check_opts) where they are not. */
static void mesh_scene_opts(const uint8_t h[10], scene_opts *o)
{
    scene_opts_default(o);
    o->width = o->height = FUZZ_SIDE, o->threads = 1, o->quiet = true;
    o->patch = (vs_patch)(h[3] % 6);
    o->normals = (vs_normals)((h[3] / 6) % 3);
    o->grid = (core_grid_kind)(h[4] % 4);
    o->level = (float)(1 + (h[4] / 4) % 8) + (o->grid == CORE_GRID_REGULAR ? 0.0f : (float)h[5] / 256.0f);
    o->path = (scene_path)(h[6] % 3);
    o->fill = (scene_fill)((h[6] / 3) % 4);
    o->yaw = (float)h[7] * 360.0f / 256.0f;
    o->pitch = ((float)h[8] - 128.0f) * 180.0f / 256.0f;
    o->distance = 1.01f + (float)h[9] / 16.0f;
    o->msaa = (h[2] & 16) ? 4 : 1;
    o->aovs = (h[2] & 32) && o->msaa == 1 ? SCENE_AOV_NORMAL | SCENE_AOV_BARY | SCENE_AOV_INSTANCE | SCENE_AOV_GREGORY
                                          : 0;
    if (o->aovs) o->output = "fuzz.exr";
    if (scene_check_opts(o)) o->path = SCENE_PATH_INSTANCED;
}

int fuzz_mesh_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    cursor c = {data, size, 0};
    uint8_t h[10];
    for (int k = 0; k < 10; k++) h[k] = next_byte(&c);
    size_t nv = 1 + h[0] % 64, nt = 1 + h[1] % 64;
    bool raw = h[2] & 4;
    float3 p[64], n[64];
    float2 t[64];
    uint32_t idx[3 * 64];
    for (size_t v = 0; v < nv; v++) p[v] = f3(next_float(&c, raw), next_float(&c, raw), next_float(&c, raw));
    if (h[2] & 1)
        for (size_t v = 0; v < nv; v++) n[v] = f3(next_float(&c, raw), next_float(&c, raw), next_float(&c, raw));
    if (h[2] & 2)
        for (size_t v = 0; v < nv; v++) t[v] = f2(next_float(&c, raw), next_float(&c, raw));
    for (size_t i = 0; i < 3 * nt; i++) {
        uint8_t b = next_byte(&c);
        idx[i] = b == 255 ? (uint32_t)nv : b % (uint32_t)nv;
    }
    is_mesh_data d = {nv, nt, p, (h[2] & 1) ? n : NULL, (h[2] & 2) ? t : NULL, idx};
    is_mesh_options mo = {.recompute_normals = (h[2] & 8) != 0};
    is_mesh m;
    char err[1024] = "";
    int rc = mesh_create(&m, "fuzz-mesh", &d, &mo, err, sizeof err);
    if (rc != 0) return check_error(rc, err, "fuzz-mesh", &m, why, whylen);
    int bad = check_mesh(&m, why, whylen);
    if (!bad) bad = check_instances(&m, why, whylen);
    scene_opts o;
    mesh_scene_opts(h, &o);
    if (!bad && !scene_check_opts(&o)) bad = render_and_check(&o, &m, why, whylen);
    mesh_free(&m);
    return bad;
}
