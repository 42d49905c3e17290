/* web/obj.c -- the page's OBJ reader (web/obj.h states what it reads and how it matches the program's import). */
#include "obj.h"

#include "../core/hlsl.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One face corner: indices into the file's v, vt, vn lists (0-based; -1: none). */
typedef struct corner { long v, t, n; } corner;

/* What the parse collects. */
typedef struct obj_file {
    float3 *v, *vn;
    float2 *vt;
    size_t nv, nvt, nvn, cap_v, cap_vt, cap_vn;
    corner *c;                  /* the corners of every polygon, face after face */
    size_t nc, cap_c;
    size_t *face;               /* first corner of each polygon (and one past the last) */
    size_t *face_line;          /* each polygon's line */
    size_t nf, cap_f, cap_fl;
    size_t skipped;             /* point and line primitives, faces of one or two corners */
    size_t first_big_line, n_big; /* polygons of five or more corners (the first one's line) */
    bool any_t, any_n;          /* some polygon names a texture coordinate / a normal */
} obj_file;

/* Message into err (if any). */
static int fail(char *err, size_t errlen, int code, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static int fail(char *err, size_t errlen, int code, const char *fmt, ...)
{
    if (err && errlen) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, errlen, fmt, ap);
        va_end(ap);
    }
    return code;
}

/* Warning through opt's callback. */
static void warn(const is_mesh_options *opt, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void warn(const is_mesh_options *opt, const char *fmt, ...)
{
    if (!opt || !opt->warn) return;
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    opt->warn(opt->warn_user, msg);
}

/* Make room for one more element of size elem in *p (count n, capacity *cap); false when out of memory. */
static bool grow(void **p, size_t n, size_t *cap, size_t elem)
{
    if (n < *cap) return true;
    size_t c = *cap ? 2 * *cap : 64;
    void *q = realloc(*p, c * elem);
    if (!q) return false;
    *p = q, *cap = c;
    return true;
}

static void obj_free(obj_file *f)
{
    free(f->v), free(f->vn), free(f->vt), free(f->c), free(f->face), free(f->face_line);
}

/* ------------------------------------------------ numbers ------------------------------------------------ */

static bool is_digit(char c) { return c >= '0' && c <= '9'; }

/* Decimal digits at *s into *out (at most max_digits read when max_digits is not NULL: further digits are
 * skipped and *max_digits becomes the count read); false on overflow of 64 bits (assimp's strtoul10_64). */
static bool digits64(const char **s, uint64_t *out, unsigned *max_digits)
{
    uint64_t v = 0;
    unsigned n = 0;
    const char *c = *s;
    while (is_digit(*c)) {
        uint64_t w = v * 10u + (uint64_t)(*c - '0');
        if (w < v) return false;
        v = w, c++, n++;
        if (max_digits && n == *max_digits) {
            while (is_digit(*c)) c++;
            break;
        }
    }
    if (max_digits) *max_digits = n;
    *s = c, *out = v;
    return true;
}

/* The number at the start of token s as assimp's fast_atoreal_move<float> reads it (the integer part and up to
 * 15 fraction digits as integers, the fraction scaled in double, added in float, then times powf(10, e)); false
 * when s does not start like a number. */
static bool parse_real(const char *s, float *out)
{
    static const double scale[16] = {0.0, 0.1, 0.01, 0.001, 0.0001, 0.00001, 0.000001, 0.0000001, 0.00000001,
                                     0.000000001, 0.0000000001, 0.00000000001, 0.000000000001, 0.0000000000001,
                                     0.00000000000001, 0.000000000000001};
    const char *c = s;
    bool inv = *c == '-';
    if (inv || *c == '+') c++;
    if ((c[0] | 0x20) == 'n' && (c[1] | 0x20) == 'a' && (c[2] | 0x20) == 'n') return *out = NAN, true;
    if ((c[0] | 0x20) == 'i' && (c[1] | 0x20) == 'n' && (c[2] | 0x20) == 'f') return *out = inv ? -INFINITY : INFINITY, true;
    bool sep = *c == '.' || *c == ',';
    if (!is_digit(*c) && !(sep && is_digit(c[1]))) return false;
    float f = 0.0f;
    uint64_t u;
    if (!sep) {
        if (!digits64(&c, &u, NULL)) return false;
        f = (float)u;
    }
    if ((*c == '.' || *c == ',') && is_digit(c[1])) {
        c++;
        unsigned diff = 15;
        if (!digits64(&c, &u, &diff)) return false;
        double pl = (double)u * scale[diff];
        f += (float)pl;
    } else if (*c == '.') {
        c++;
    }
    if (*c == 'e' || *c == 'E') {
        c++;
        bool einv = *c == '-';
        if (einv || *c == '+') c++;
        if (!is_digit(*c) || !digits64(&c, &u, NULL)) return false;
        float e = (float)u;
        f *= powf(10.0f, einv ? -e : e);
    }
    *out = inv ? -f : f;
    return true;
}

/* ------------------------------------------------ lines ------------------------------------------------ */

static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/* Split line (modified) into at most max tokens, stopping at '#'; the count. */
static int tokens(char *line, char **tok, int max)
{
    int n = 0;
    char *p = line;
    for (;;) {
        while (is_space(*p)) p++;
        if (!*p || *p == '#') return n;
        if (n == max) return n + 1;
        tok[n++] = p;
        while (*p && !is_space(*p) && *p != '#') p++;
        if (*p == '#') { *p = 0; return n; }
        if (*p) *p++ = 0;
    }
}

/* The reader's state while it parses: the file, its label and line, where errors go. */
typedef struct parse {
    obj_file *f;
    const char *label;
    size_t line;
    char *err;
    size_t errlen;
} parse;

/* `v`, `vt`, `vn` with its n_tok numbers tok[1..]. */
static int read_vector(parse *ps, char **tok, int n_tok)
{
    obj_file *f = ps->f;
    int n = n_tok - 1;
    float x[6] = {0};
    for (int k = 0; k < n && k < 6; k++) {
        if (!parse_real(tok[1 + k], &x[k]))
            return fail(ps->err, ps->errlen, IS_MESH_ERR_FORMAT, "%s line %zu: '%.40s' is not a number", ps->label,
                        ps->line, tok[1 + k]);
        if (tok[1 + k][0] == '.' || tok[1 + k][0] == ',')   /* assimp does not count it: the vertex would vanish */
            return fail(ps->err, ps->errlen, IS_MESH_ERR_FORMAT, "%s line %zu: '%.40s': the program's import (assimp) "
                        "does not read a number that starts with '%c' and drops the line: write 0%s", ps->label,
                        ps->line, tok[1 + k], tok[1 + k][0], tok[1 + k]);
    }
    if (!strcmp(tok[0], "v")) {
        if (n != 3 && n != 4 && n != 6)
            return fail(ps->err, ps->errlen, IS_MESH_ERR_FORMAT, "%s line %zu: a vertex has 3 coordinates (4 with w, "
                        "6 with a colour), not %d", ps->label, ps->line, n);
        if (n == 4 && x[3] == 0.0f)
            return fail(ps->err, ps->errlen, IS_MESH_ERR_INVALID, "%s line %zu: a vertex with w = 0", ps->label, ps->line);
        if (!grow((void **)&f->v, f->nv, &f->cap_v, sizeof *f->v)) return IS_MESH_ERR_NOMEM;
        f->v[f->nv++] = n == 4 ? f3(x[0] / x[3], x[1] / x[3], x[2] / x[3]) : f3(x[0], x[1], x[2]);
    } else if (!strcmp(tok[0], "vt")) {
        if (n != 2 && n != 3)
            return fail(ps->err, ps->errlen, IS_MESH_ERR_FORMAT, "%s line %zu: a texture coordinate has 2 or 3 "
                        "numbers, not %d", ps->label, ps->line, n);
        if (!grow((void **)&f->vt, f->nvt, &f->cap_vt, sizeof *f->vt)) return IS_MESH_ERR_NOMEM;
        f->vt[f->nvt++] = f2(x[0], x[1]);
    } else {
        if (n < 3)
            return fail(ps->err, ps->errlen, IS_MESH_ERR_FORMAT, "%s line %zu: a normal has 3 numbers, not %d",
                        ps->label, ps->line, n);
        if (!grow((void **)&f->vn, f->nvn, &f->cap_vn, sizeof *f->vn)) return IS_MESH_ERR_NOMEM;
        f->vn[f->nvn++] = f3(x[0], x[1], x[2]);
    }
    return IS_MESH_OK;
}

/* One index of a corner (s up to end): 1-based, or negative relative to `count` defined so far, into *out. */
static int read_index(parse *ps, const char *s, const char *end, size_t count, const char *what, long *out)
{
    const char *p = s;
    bool neg = *p == '-';
    if (neg || *p == '+') p++;
    long v = 0;
    if (p == end) goto bad;
    for (; p < end; p++) {
        if (!is_digit(*p) || v > 100000000L) goto bad;
        v = v * 10 + (*p - '0');
    }
    if (v == 0)
        return fail(ps->err, ps->errlen, IS_MESH_ERR_INVALID, "%s line %zu: %s index 0 (OBJ counts from 1)",
                    ps->label, ps->line, what);
    *out = neg ? (long)count - v : v - 1;
    if (*out < 0)
        return fail(ps->err, ps->errlen, IS_MESH_ERR_INVALID, "%s line %zu: %s index -%ld, but only %zu are defined "
                    "before this line", ps->label, ps->line, what, v, count);
    return IS_MESH_OK;
bad:
    return fail(ps->err, ps->errlen, IS_MESH_ERR_FORMAT, "%s line %zu: '%.*s' is not a %s index", ps->label, ps->line,
                (int)(end - s > 40 ? 40 : end - s), s, what);
}

/* `f`, `l` or `p` with its corners tok[1..n_tok). */
static int read_face(parse *ps, char **tok, int n_tok)
{
    obj_file *f = ps->f;
    int n = n_tok - 1;
    if (tok[0][0] != 'f' || n < 3) {   /* points, lines, faces of one or two corners: what assimp gives as such */
        f->skipped += tok[0][0] == 'p' ? (size_t)n : tok[0][0] == 'l' && n > 1 ? (size_t)n - 1 : n > 0;
        return IS_MESH_OK;
    }
    for (int k = 1; k <= n; k++) {
        corner c = {-1, -1, -1};
        const char *s = tok[k], *a = strchr(s, '/'), *b = a ? strchr(a + 1, '/') : NULL;
        const char *e = s + strlen(s);
        int rc = read_index(ps, s, a ? a : e, f->nv, "vertex", &c.v);
        /* assimp: with normals but no texture coordinates defined so far, `v/x` names a normal */
        bool second_is_normal = !b && f->nvt == 0 && f->nvn > 0;
        if (rc == 0 && a && (b ? b > a + 1 : a + 1 < e))
            rc = second_is_normal ? read_index(ps, a + 1, e, f->nvn, "normal", &c.n)
                                  : read_index(ps, a + 1, b ? b : e, f->nvt, "texture coordinate", &c.t);
        if (rc == 0 && b && b + 1 < e) rc = read_index(ps, b + 1, e, f->nvn, "normal", &c.n);
        if (rc != 0) return rc;
        if (!grow((void **)&f->c, f->nc, &f->cap_c, sizeof *f->c)) return IS_MESH_ERR_NOMEM;
        f->c[f->nc++] = c;
        f->any_t |= c.t >= 0, f->any_n |= c.n >= 0;
    }
    if (!grow((void **)&f->face, f->nf + 1, &f->cap_f, sizeof *f->face) ||
        !grow((void **)&f->face_line, f->nf, &f->cap_fl, sizeof *f->face_line))
        return IS_MESH_ERR_NOMEM;
    f->face[f->nf] = f->nc - (size_t)n, f->face[f->nf + 1] = f->nc;
    f->face_line[f->nf++] = ps->line;
    if (n > 4 && f->n_big++ == 0) f->first_big_line = ps->line;
    return IS_MESH_OK;
}

/* One logical line (continuations joined). */
static int read_line(parse *ps, char *line)
{
    char *tok[64];
    int n = tokens(line, tok, 64);
    if (n == 0) return IS_MESH_OK;
    if (n > 64 && (tok[0][0] == 'f' || tok[0][0] == 'v'))
        return fail(ps->err, ps->errlen, IS_MESH_ERR_FORMAT, "%s line %zu: more than 63 corners or numbers",
                    ps->label, ps->line);
    if (!strcmp(tok[0], "v") || !strcmp(tok[0], "vt") || !strcmp(tok[0], "vn")) return read_vector(ps, tok, n);
    if (!strcmp(tok[0], "f") || !strcmp(tok[0], "l") || !strcmp(tok[0], "p")) return read_face(ps, tok, n);
    return IS_MESH_OK;   /* o, g, s, usemtl, mtllib, vp, free-form geometry: ignored */
}

/* Parse the whole text into f. */
static int parse_text(parse *ps, const char *data, size_t len)
{
    char *buf = malloc(len + 1);
    if (!buf) return fail(ps->err, ps->errlen, IS_MESH_ERR_NOMEM, "%s: out of memory", ps->label);
    size_t at = len >= 3 && !memcmp(data, "\xEF\xBB\xBF", 3) ? 3 : 0, next_line = 1;
    int rc = IS_MESH_OK;
    while (rc == IS_MESH_OK && at < len) {
        size_t n = 0;
        ps->line = next_line;
        while (at < len) {   /* one logical line into buf: a backslash before the end of a line continues it */
            char ch = data[at++];
            if (ch == '\n') {
                next_line++;
                if (n > 0 && buf[n - 1] == '\\') { buf[n - 1] = ' '; continue; }
                if (n > 1 && buf[n - 1] == '\r' && buf[n - 2] == '\\') { buf[n - 2] = ' ', n--; continue; }
                break;
            }
            if (ch == 0) ch = ' ';
            buf[n++] = ch;
        }
        buf[n] = 0;
        rc = read_line(ps, buf);
    }
    free(buf);
    return rc;
}

/* ------------------------------------------------ the mesh ------------------------------------------------ */

/* The affine node transforms of meshes/import.c (3x4, column vectors), and its arithmetic on them. */
typedef struct xform { double m[3][4]; } xform;
static xform xform_mul(const xform *p, const xform *q)
{
    xform r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            r.m[i][j] = p->m[i][0] * q->m[0][j] + p->m[i][1] * q->m[1][j] + p->m[i][2] * q->m[2][j] +
                        (j == 3 ? p->m[i][3] : 0.0);
    return r;
}
static void cofactor3(const xform *x, double c[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            c[i][j] = x->m[i1][j1] * x->m[i2][j2] - x->m[i1][j2] * x->m[i2][j1];
        }
}
static double row(const xform *x, int i, float3 p)
{
    double r = 0.0;
    if (x->m[i][0] != 0.0) r += x->m[i][0] * p.x;
    if (x->m[i][1] != 0.0) r += x->m[i][1] * p.y;
    if (x->m[i][2] != 0.0) r += x->m[i][2] * p.z;
    return r + x->m[i][3];
}
static float3 normal_through(const double c[3][3], double s, float3 q)
{
    double x = s * (c[0][0] * q.x + c[0][1] * q.y + c[0][2] * q.z);
    double y = s * (c[1][0] * q.x + c[1][1] * q.y + c[1][2] * q.z);
    double z = s * (c[2][0] * q.x + c[2][1] * q.y + c[2][2] * q.z);
    double l = sqrt(x * x + y * y + z * z);
    if (l > 0.0 && isfinite(l)) x /= l, y /= l, z /= l;
    return f3((float)x, (float)y, (float)z);
}

/* The global transform of assimp's OBJ scene as import.c's walk makes it: the root node and the object's node,
 * each an identity that MakeLeftHanded mirrored at z twice (its a3, b3, c1, c2, c4 negated: zeros become -0). */
static xform obj_node_transform(void)
{
    const xform id = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
    const xform node = {{{1, 0, -0.0, 0}, {0, 1, -0.0, 0}, {-0.0, -0.0, 1, -0.0}}};
    xform g = xform_mul(&id, &node);
    return xform_mul(&g, &node);
}

/* |a| as assimp's aiVector3D::Normalize leaves it (times 1 / length in float; zero stays). */
static float3 ai_normalize(float3 a)
{
    float l = sqrtf(a.x * a.x + a.y * a.y + a.z * a.z);
    if (l == 0.0f) return a;
    float inv = 1.0f / l;
    return f3(a.x * inv, a.y * inv, a.z * inv);
}

/* The corner assimp's Triangulate starts a quad's two triangles from: its concave corner, if any (q: the
 * quad's corner positions in the reversed order). */
static int quad_start(const float3 q[4])
{
    for (int i = 0; i < 4; i++) {
        float3 v = q[i];
        float3 left = ai_normalize(sub3(q[(i + 3) % 4], v)), diag = ai_normalize(sub3(q[(i + 2) % 4], v)),
               right = ai_normalize(sub3(q[(i + 1) % 4], v));
        float angle = acosf(dot3(left, diag)) + acosf(dot3(right, diag));
        if (angle > 3.1415926538f) return i;
    }
    return 0;
}

/* One vertex of the mesh: position, normal, texture coordinate (the bytes that join vertices). */
typedef struct obj_vertex { float3 p, n; float2 t; } obj_vertex;

/* The corners of f as vertices (assimp's per-corner vertices through ConvertToLeftHanded and the node
 * transform) into v[0..f->nc); has_n / has_t: the file's normals / texture coordinates are used. */
static void corner_vertices(const obj_file *f, bool has_n, bool has_t, obj_vertex *v)
{
    xform g = obj_node_transform();
    double c[3][3];
    cofactor3(&g, c);
    double det = g.m[0][0] * c[0][0] + g.m[0][1] * c[0][1] + g.m[0][2] * c[0][2], s = det < 0.0 ? -1.0 : 1.0;
    for (size_t k = 0; k < f->nc; k++) {
        const corner *cn = &f->c[k];
        float3 p = f->v[cn->v];
        p.z = -p.z;
        v[k].p = f3((float)row(&g, 0, p), (float)row(&g, 1, p), (float)row(&g, 2, p));
        float3 n = has_n && cn->n >= 0 ? f->vn[cn->n] : f3(0.0f, 0.0f, 0.0f);
        n.z = -n.z;
        v[k].n = has_n ? normal_through(c, s, n) : f3(0.0f, 0.0f, 0.0f);
        float2 t = has_t && cn->t >= 0 ? f->vt[cn->t] : f2(0.0f, 0.0f);
        v[k].t = has_t ? f2(t.x, 1.0f - t.y) : f2(0.0f, 0.0f);
    }
}

/* The triangles of polygon k of f (corners reversed, then split as assimp's Triangulate splits them) appended
 * to idx at *nt. */
static void triangulate(const obj_file *f, size_t k, uint32_t *idx, size_t *nt)
{
    size_t first = f->face[k], n = f->face[k + 1] - first;
    uint32_t r[64];
    for (size_t i = 0; i < n; i++) r[i] = (uint32_t)(first + n - 1 - i);
    int s = 0;
    if (n == 4) {
        float3 q[4];
        for (int i = 0; i < 4; i++) q[i] = f->v[f->c[r[i]].v], q[i].z = -q[i].z;
        s = quad_start(q);
    }
    for (size_t i = 1; i + 1 < n; i++) {
        uint32_t *t = idx + 3 * (*nt)++;
        t[0] = r[s], t[1] = r[(s + i) % n], t[2] = r[(s + i + 1) % n];
    }
}

/* Join the vertices whose bytes are equal, numbered in vertex order: v shrinks to *nv, idx is renumbered. */
static bool join(obj_vertex *v, size_t *nv, uint32_t *idx, size_t n_idx)
{
    size_t n = *nv, size = 16;
    while (size < 2 * n) size *= 2;
    uint32_t *table = malloc(size * sizeof *table), *remap = malloc((n ? n : 1) * sizeof *remap);
    if (!table || !remap) return free(table), free(remap), false;
    memset(table, 0xff, size * sizeof *table);
    size_t unique = 0;
    for (size_t k = 0; k < n; k++) {
        uint32_t h = 2166136261u;
        const unsigned char *b = (const unsigned char *)&v[k];
        for (size_t i = 0; i < sizeof v[k]; i++) h = (h ^ b[i]) * 16777619u;
        size_t slot = h & (size - 1);
        while (table[slot] != UINT32_MAX && memcmp(&v[table[slot]], &v[k], sizeof v[k]) != 0) slot = (slot + 1) & (size - 1);
        if (table[slot] == UINT32_MAX) {
            v[unique] = v[k];
            table[slot] = (uint32_t)unique++;
        }
        remap[k] = table[slot];
    }
    for (size_t i = 0; i < n_idx; i++) idx[i] = remap[idx[i]];
    free(table), free(remap);
    *nv = unique;
    return true;
}

/* Check the parsed file (indices in range; what to drop), warn, build the mesh. */
static int build_mesh(const obj_file *f, const char *label, const is_mesh_options *opt, is_mesh *out, char *err,
                      size_t errlen)
{
    for (size_t k = 0; k < f->nf; k++)
        for (size_t i = f->face[k]; i < f->face[k + 1]; i++)
            if ((size_t)f->c[i].v >= f->nv)
                return fail(err, errlen, IS_MESH_ERR_INVALID, "%s line %zu: the face names vertex %ld, but the file "
                            "defines %zu", label, f->face_line[k], f->c[i].v + 1, f->nv);
    if (f->nf == 0)
        return fail(err, errlen, IS_MESH_ERR_EMPTY, "%s: no faces (%zu point/line primitives)", label, f->skipped);
    bool has_n = f->nvn > 0 && f->any_n, has_t = f->nvt > 0 && f->any_t;
    for (size_t i = 0; has_n && i < f->nc; i++)
        if (f->c[i].n >= (long)f->nvn) {
            warn(opt, "%s: a face names normal %ld, but the file defines %zu: its normals are ignored and computed "
                 "(as the program's import does)", label, f->c[i].n + 1, f->nvn);
            has_n = false;
        }
    for (size_t i = 0; has_t && i < f->nc; i++)
        if (f->c[i].t >= (long)f->nvt) {
            warn(opt, "%s: a face names texture coordinate %ld, but the file defines %zu: they are ignored", label,
                 f->c[i].t + 1, f->nvt);
            has_t = false;
        }
    if (f->skipped) warn(opt, "%s: skipped %zu point/line primitive(s)", label, f->skipped);
    if (f->n_big)
        warn(opt, "%s: %zu polygon(s) of five or more corners (the first on line %zu) cut into a fan: the program's "
             "import (assimp) cuts them otherwise, so its triangles and the last bits of its pixels may differ",
             label, f->n_big, f->first_big_line);
    size_t n_tri = f->nc - 2 * f->nf, nv = f->nc, nt = 0;
    obj_vertex *v = malloc((nv ? nv : 1) * sizeof *v);
    uint32_t *idx = malloc(3 * n_tri * sizeof *idx);
    float3 *p = NULL, *n = NULL;
    float2 *t = NULL;
    int rc = IS_MESH_ERR_NOMEM;
    if (v && idx) {
        corner_vertices(f, has_n, has_t, v);
        for (size_t k = 0; k < f->nf; k++) triangulate(f, k, idx, &nt);
        if (join(v, &nv, idx, 3 * nt)) {
            p = malloc(nv * sizeof *p), n = malloc(nv * sizeof *n), t = malloc(nv * sizeof *t);
            if (p && n && t) {
                for (size_t k = 0; k < nv; k++) p[k] = v[k].p, n[k] = v[k].n, t[k] = v[k].t;
                is_mesh_data d = {nv, nt, p, has_n ? n : NULL, t, idx};
                rc = mesh_create(out, label, &d, opt, err, errlen);
                if (rc == IS_MESH_OK) out->stats.primitives_skipped = f->skipped;
            }
        }
    }
    if (rc == IS_MESH_ERR_NOMEM && (!v || !idx || !p || !n || !t)) fail(err, errlen, rc, "%s: out of memory", label);
    free(v), free(idx), free(p), free(n), free(t);
    return rc;
}

int web_obj_read(const char *label, const char *data, size_t len, const is_mesh_options *opt, is_mesh *out,
                 char *err, size_t errlen)
{
    if (out) memset(out, 0, sizeof *out);
    if (!label) label = "<dropped OBJ>";
    if (!out || (!data && len)) return fail(err, errlen, IS_MESH_ERR_ARG, "%s: web_obj_read: NULL argument", label);
    if (len == 0) return fail(err, errlen, IS_MESH_ERR_IO, "%s: empty file", label);
    obj_file f = {0};
    parse ps = {&f, label, 0, err, errlen};
    int rc = parse_text(&ps, data, len);
    if (rc == IS_MESH_ERR_NOMEM) fail(err, errlen, rc, "%s line %zu: out of memory", label, ps.line);
    if (rc == IS_MESH_OK) rc = build_mesh(&f, label, opt, out, err, errlen);
    obj_free(&f);
    return rc;
}
