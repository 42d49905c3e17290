/* meshes/import_check.c -- declared sizes checked against the file before assimp sees it.  A PLY or OFF header
 * states how many vertices and faces follow, and assimp 5.2.5 allocates for them before reading: a 226-byte
 * PLY that declares 10^9 vertices makes it allocate gigabytes.  Every declared element needs some bytes in
 * the body, so the counts are checked against the body's size (and the import limits) first.  A header this
 * file cannot parse passes: assimp reads it under the import's time and memory limits. */
#include "mesh_internal.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* One parsed header: the body's least size, and the first element over a limit. */
typedef struct header_sum {
    uint64_t min_body;               /* saturating */
    bool binary;
    char over_name[32];              /* an element whose count passes its limit ("" none) */
    uint64_t over_count, over_limit;
    char big_name[32];               /* the element that needs the most bytes, for the message */
    uint64_t big_count, big_bytes;
} header_sum;

/* a + b, saturating at UINT64_MAX. */
static uint64_t sat_add(uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; }

/* a * b, saturating at UINT64_MAX. */
static uint64_t sat_mul(uint64_t a, uint64_t b) { return b && a > UINT64_MAX / b ? UINT64_MAX : a * b; }

/* The next line of text[*pos..n) into line[len] (without its \r\n); false at the end or for an overlong line. */
static bool next_line(const unsigned char *text, size_t n, size_t *pos, char *line, size_t len)
{
    size_t k = 0;
    if (*pos >= n) return false;
    while (*pos < n && text[*pos] != '\n') {
        if (k + 1 >= len) return false;
        line[k++] = (char)text[(*pos)++];
    }
    if (*pos >= n) return false;   /* no line end: the header is cut, no verdict */
    (*pos)++;
    if (k && line[k - 1] == '\r') k--;
    line[k] = '\0';
    return true;
}

/* An unsigned decimal count (all digits, saturating at UINT64_MAX); false when tok is not one. */
static bool parse_count(const char *tok, uint64_t *out)
{
    if (!tok || !*tok) return false;
    uint64_t v = 0;
    for (const char *c = tok; *c; c++) {
        if (!isdigit((unsigned char)*c)) return false;
        v = sat_add(sat_mul(v, 10), (uint64_t)(*c - '0'));
    }
    *out = v;
    return true;
}

/* Size in bytes of a PLY scalar type, 0 when unknown. */
static unsigned ply_type_size(const char *t)
{
    static const struct { const char *name; unsigned size; } types[] = {
        {"char", 1}, {"uchar", 1}, {"int8", 1}, {"uint8", 1}, {"short", 2}, {"ushort", 2}, {"int16", 2},
        {"uint16", 2}, {"int", 4}, {"uint", 4}, {"int32", 4}, {"uint32", 4}, {"float", 4}, {"float32", 4},
        {"double", 8}, {"float64", 8}};
    for (size_t k = 0; t && k < sizeof types / sizeof types[0]; k++)
        if (strcmp(t, types[k].name) == 0) return types[k].size;
    return 0;
}

/* The limit of an element by name: vertices, faces (each gives at least one triangle), anything else. */
static uint64_t element_limit(const char *name)
{
    if (strcmp(name, "vertex") == 0) return MESH_MAX_IMPORT_VERTICES;
    if (strcmp(name, "face") == 0) return MESH_MAX_IMPORT_TRIANGLES;
    return MESH_MAX_IMPORT_VERTICES;
}

/* The element being declared: its name, count and least bytes per item. */
typedef struct ply_element { char name[32]; uint64_t count, item; bool open; } ply_element;

/* Close the element e into s (its count against its limit, its bytes into the body's least size). */
static void close_element(header_sum *s, ply_element *e)
{
    if (!e->open) return;
    uint64_t limit = element_limit(e->name);
    if (e->count > limit && !s->over_name[0]) {
        snprintf(s->over_name, sizeof s->over_name, "%s", e->name);
        s->over_count = e->count;
        s->over_limit = limit;
    }
    uint64_t bytes = sat_mul(e->count, e->item);
    if (bytes >= s->big_bytes) {
        snprintf(s->big_name, sizeof s->big_name, "%s", e->name);
        s->big_count = e->count;
        s->big_bytes = bytes;
    }
    s->min_body = sat_add(s->min_body, bytes);
    e->open = false;
}

/* One "property ..." line of element e (tokens after "property"); false when it cannot be parsed. */
static bool ply_property(ply_element *e, bool binary, char *rest)
{
    char *save = NULL, *t = strtok_r(rest, " \t", &save);
    if (!e->open || !t) return false;
    if (strcmp(t, "list") == 0) {
        unsigned count_size = ply_type_size(strtok_r(NULL, " \t", &save));
        unsigned item_size = ply_type_size(strtok_r(NULL, " \t", &save));
        if (!count_size || !item_size) return false;
        e->item += binary ? count_size : 2;   /* a list holds at least its count */
        return true;
    }
    unsigned size = ply_type_size(t);
    if (!size) return false;
    e->item += binary ? size : 2;            /* ASCII: a digit and a separator at least */
    return true;
}

/* One header line after "ply"; 1 on end_header, 0 to go on, -1 when it cannot be parsed. */
static int ply_line(header_sum *s, ply_element *e, char *line)
{
    char *save = NULL, *key = strtok_r(line, " \t", &save);
    if (!key) return 0;
    if (!strcmp(key, "comment") || !strcmp(key, "obj_info")) return 0;
    if (!strcmp(key, "end_header")) return 1;
    if (!strcmp(key, "format")) {
        const char *f = strtok_r(NULL, " \t", &save);
        if (!f) return -1;
        s->binary = strcmp(f, "ascii") != 0;
        return !strcmp(f, "ascii") || !strcmp(f, "binary_little_endian") || !strcmp(f, "binary_big_endian") ? 0 : -1;
    }
    if (!strcmp(key, "element")) {
        close_element(s, e);
        const char *name = strtok_r(NULL, " \t", &save);
        if (!name || !parse_count(strtok_r(NULL, " \t", &save), &e->count)) return -1;
        snprintf(e->name, sizeof e->name, "%s", name);
        e->item = 0;
        e->open = true;
        return 0;
    }
    if (!strcmp(key, "property")) return ply_property(e, s->binary, save) ? 0 : -1;
    return -1;
}

/* Parse a PLY header; the header's length into *hlen.  false: no verdict (not parsed to its end). */
static bool parse_ply(const unsigned char *head, size_t n, header_sum *s, size_t *hlen)
{
    char line[1024];
    size_t pos = 0;
    ply_element e = {{0}, 0, 0, false};
    if (!next_line(head, n, &pos, line, sizeof line) || strcmp(line, "ply") != 0) return false;
    while (next_line(head, n, &pos, line, sizeof line)) {
        int r = ply_line(s, &e, line);
        if (r < 0) return false;
        if (r == 1) {
            close_element(s, &e);
            if (!s->binary && s->min_body) s->min_body--;   /* the last number needs no separator */
            *hlen = pos;
            return true;
        }
    }
    return false;
}

/* The OFF header "[ST][C][N][4]OFF" then the vertex, face and edge counts; false: no verdict (other forms,
 * such as nOFF's dimension or a missing keyword, are left to assimp). */
static bool parse_off(const unsigned char *head, size_t n, header_sum *s, size_t *hlen)
{
    char text[512], key[16];
    size_t k = 0;
    for (; k < n && k + 1 < sizeof text; k++) text[k] = (char)head[k];
    text[k] = '\0';
    unsigned long long nv, nf, ne;
    int used = 0;
    if (sscanf(text, "%15s %llu %llu %llu%n", key, &nv, &nf, &ne, &used) != 4) return false;
    size_t kl = strlen(key);
    if (kl < 3 || strcmp(key + kl - 3, "OFF") != 0 || strspn(key, "STCN4") != kl - 3 ||
        memchr(text, '-', (size_t)used))   /* %llu would take "-1" as a huge count */
        return false;
    bool texcoords = strstr(key, "ST") == key, colours = strchr(key, 'C'), normals = strchr(key, 'N');
    uint64_t per_vertex = 2 * (3 + (strchr(key, '4') ? 1 : 0) + (normals ? 3 : 0) + (texcoords ? 2 : 0) +
                               (colours ? 1 : 0));
    s->min_body = sat_add(sat_mul(nv, per_vertex), sat_mul(nf, 2));   /* a face: at least its count */
    bool v_big = sat_mul(nv, per_vertex) >= sat_mul(nf, 2);
    snprintf(s->big_name, sizeof s->big_name, "%s", v_big ? "vertex" : "face");
    s->big_count = v_big ? nv : nf;
    if (nv > MESH_MAX_IMPORT_VERTICES || nf > MESH_MAX_IMPORT_TRIANGLES) {
        snprintf(s->over_name, sizeof s->over_name, "%s", nv > MESH_MAX_IMPORT_VERTICES ? "vertex" : "face");
        s->over_count = nv > MESH_MAX_IMPORT_VERTICES ? nv : nf;
        s->over_limit = nv > MESH_MAX_IMPORT_VERTICES ? MESH_MAX_IMPORT_VERTICES : MESH_MAX_IMPORT_TRIANGLES;
    }
    *hlen = (size_t)used;
    return true;
}

/* mesh_check_header: see mesh_internal.h. */
int mesh_check_header(const unsigned char *head, size_t n, uint64_t file_size, const char *label, char *err,
                      size_t errlen)
{
    header_sum s;
    memset(&s, 0, sizeof s);
    size_t hlen = 0;
    const char *format = "PLY";
    if (!parse_ply(head, n, &s, &hlen)) {
        memset(&s, 0, sizeof s);
        format = "OFF";
        if (!parse_off(head, n, &s, &hlen)) return IS_MESH_OK;
    }
    if (s.over_name[0]) {
        mesh_set_err(err, errlen, "%s: the %s header declares %llu '%s' elements, more than the limit of %llu", label,
                     format, (unsigned long long)s.over_count, s.over_name, (unsigned long long)s.over_limit);
        return IS_MESH_ERR_INVALID;
    }
    uint64_t body = file_size > hlen ? file_size - hlen : 0;
    if (s.min_body > body) {
        mesh_set_err(err, errlen, "%s: the %s header declares %llu '%s' elements (with the others at least %llu "
                     "bytes), but the file holds only %llu bytes after its header", label, format,
                     (unsigned long long)s.big_count, s.big_name, (unsigned long long)s.min_body,
                     (unsigned long long)body);
        return IS_MESH_ERR_INVALID;
    }
    return IS_MESH_OK;
}

/* ------------------------------ face indices of text formats ------------------------------ */

/* The next line of data[*pos..n) as [*b, *e) (without its \r\n); false at the end. */
static bool line_span(const unsigned char *data, size_t n, size_t *pos, const char **b, const char **e)
{
    if (*pos >= n) return false;
    const unsigned char *s = data + *pos, *nl = memchr(s, '\n', n - *pos);
    size_t len = nl ? (size_t)(nl - s) : n - *pos;
    *pos += len + (nl != NULL);
    *b = (const char *)s;
    *e = (const char *)s + len;
    if (*e > *b && (*e)[-1] == '\r') (*e)--;
    return true;
}

/* The integer at *p (before e), advancing past it and the spaces around; false when none is there. */
static bool read_int(const char **p, const char *e, long long *out)
{
    while (*p < e && isspace((unsigned char)**p)) (*p)++;
    char buf[32];
    size_t k = 0;
    while (*p + k < e && k + 1 < sizeof buf && (isdigit((unsigned char)(*p)[k]) || ((*p)[k] == '-' && k == 0)))
        buf[k] = (*p)[k], k++;
    if (k == 0 || (k == 1 && buf[0] == '-')) return false;
    buf[k] = '\0';
    *out = strtoll(buf, NULL, 10);
    *p += k;
    return true;
}

/* OFF (text): every face's vertex indices in 0..nv-1; assimp 5.2 clamps an index past the end to the last
 * vertex without a word.  The keyword ("OFF", "COFF", ...), then the vertex and face counts (on its line or
 * the next), nv vertex lines and nf face lines "k i1 .. ik [colour]"; blank and '#' lines are skipped, lines are
 * counted from 1.  A file this cannot follow passes (assimp reads it and says what is wrong). */
static int check_off_faces(const unsigned char *data, size_t n, const char *label, char *err, size_t errlen)
{
    size_t pos = 0;
    const char *b, *e;
    long long counts[2] = {-1, -1}, v = 0, f = 0;
    int stage = 0;   /* 0: keyword, 1: counts, 2: vertices and faces */
    for (long line_no = 1; line_span(data, n, &pos, &b, &e); line_no++) {
        const char *p = b;
        while (p < e && isspace((unsigned char)*p)) p++;
        if (p == e || *p == '#') continue;
        if (stage == 0) {
            const char *k = p;
            while (p < e && !isspace((unsigned char)*p)) p++;
            if (p - k < 3 || memcmp(p - 3, "OFF", 3) != 0) return IS_MESH_OK;
            stage = 1;
        }
        if (stage == 1) {
            for (int c = 0; c < 2 && counts[c] < 0;)
                if (!read_int(&p, e, &counts[c++])) break;
            if (counts[1] >= 0) stage = 2;   /* (sizes were checked by mesh_check_header) */
            continue;
        }
        if (v < counts[0]) { v++; continue; }
        if (f >= counts[1]) break;
        long long k, idx;
        if (!read_int(&p, e, &k) || k < 0) return IS_MESH_OK;   /* a malformed face: assimp says so */
        for (long long c = 0; c < k && read_int(&p, e, &idx); c++)
            if (idx < 0 || idx >= counts[0]) {
                mesh_set_err(err, errlen, "%s: line %ld: face %lld names vertex %lld, but the file has %lld vertices "
                             "(0..%lld)", label, line_no, f, idx, counts[0], counts[0] ? counts[0] - 1 : 0);
                return IS_MESH_ERR_INVALID;
            }
        f++;
    }
    return IS_MESH_OK;
}

/* OBJ: every 'f' corner's vertex index names a vertex ('v' line) of the file: 1..count, or -1..-(count so far) as
 * a reference back.  Lines are counted from 1. */
static int check_obj_faces(const unsigned char *data, size_t n, const char *label, char *err, size_t errlen)
{
    uint64_t total = 0, so_far = 0, f = 0;
    size_t pos = 0;
    const char *b, *e;
    while (line_span(data, n, &pos, &b, &e)) total += e - b > 1 && b[0] == 'v' && isspace((unsigned char)b[1]);
    pos = 0;
    for (long line_no = 1; line_span(data, n, &pos, &b, &e); line_no++) {
        if (e - b < 2 || !isspace((unsigned char)b[1])) continue;
        if (b[0] == 'v') so_far++;
        if (b[0] != 'f') continue;
        const char *p = b + 1;
        long long idx;
        for (int c = 0; read_int(&p, e, &idx); c++) {
            bool ok = idx > 0 ? (uint64_t)idx <= total : idx < 0 && (uint64_t)(-idx) <= so_far;
            if (!ok) {
                mesh_set_err(err, errlen, "%s: line %ld: face %llu, corner %d names vertex %lld, but the file has %llu "
                             "vertices (1..%llu, or -1..-%llu back from that line)", label, line_no,
                             (unsigned long long)f, c, idx, (unsigned long long)total, (unsigned long long)total,
                             (unsigned long long)so_far);
                return IS_MESH_ERR_INVALID;
            }
            while (p < e && !isspace((unsigned char)*p)) p++;   /* the corner's /texcoord/normal */
        }
        f++;
    }
    return IS_MESH_OK;
}

/* A little-endian 32-bit integer at p. */
static int32_t le32(const unsigned char *p)
{
    return (int32_t)((uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24);
}

/* MD2 (Quake II, binary): every triangle's three vertex indices and three texture coordinate indices name one
 * of the file's; assimp 5.2 clamps one past the end to the last without a word.  The header (magic "IDP2",
 * counts and offsets as little-endian ints: num_vertices at byte 24, num_st 28, num_tris 32, ofs_tris 52), then
 * num_tris triangles of six unsigned 16-bit indices (vertices, then texture coordinates).  A file whose
 * triangles lie outside it passes (assimp refuses it). */
static int check_md2_faces(const unsigned char *data, size_t n, const char *label, char *err, size_t errlen)
{
    if (n < 68 || memcmp(data, "IDP2", 4) != 0) return IS_MESH_OK;
    int32_t nv = le32(data + 24), nst = le32(data + 28), nt = le32(data + 32), ofs = le32(data + 52);
    if (nv < 0 || nst < 0 || nt < 0 || ofs < 0 || (uint64_t)ofs + 12u * (uint64_t)nt > n) return IS_MESH_OK;
    for (int32_t t = 0; t < nt; t++)
        for (int k = 0; k < 6; k++) {
            const unsigned char *p = data + ofs + 12 * (size_t)t + 2 * (size_t)k;
            int32_t idx = p[0] | p[1] << 8, count = k < 3 ? nv : nst;
            if (idx < count) continue;
            mesh_set_err(err, errlen, "%s: triangle %ld, corner %d names %s %ld, but the file has %ld (0..%ld)", label,
                         (long)t, k % 3, k < 3 ? "vertex" : "texture coordinate", (long)idx, (long)count,
                         (long)(count ? count - 1 : 0));
            return IS_MESH_ERR_INVALID;
        }
    return IS_MESH_OK;
}

/* mesh_check_face_indices: see mesh_internal.h. */
int mesh_check_face_indices(const unsigned char *data, size_t n, const char *ext, const char *label, char *err,
                            size_t errlen)
{
    if (ext && strcasecmp(ext, "obj") == 0) return check_obj_faces(data, n, label, err, errlen);
    if (ext && strcasecmp(ext, "md2") == 0) return check_md2_faces(data, n, label, err, errlen);
    return check_off_faces(data, n, label, err, errlen);
}
