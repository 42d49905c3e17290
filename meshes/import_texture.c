/* meshes/import_texture.c -- the file's own diffuse texture (meshes.h, mesh_load_file: "The file's texture"): what
 * the import child found in the scene's materials (mesh_texture_note), resolved in the parent against the mesh's
 * folder by the rules of side files (meshes/import_io.c: regular files inside the folder only), and for an MD2
 * that names no skin, the image its header's skin size identifies.  Nothing here reads an image's pixels: the
 * path is reported, the caller reads it (or not). */
#define _XOPEN_SOURCE 700   /* realpath */
#define _DEFAULT_SOURCE 1   /* O_NOFOLLOW, pread */
#include "mesh_internal.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <assimp/material.h>
#include <assimp/scene.h>

/* mesh_texture_note: see mesh_internal.h. */
void mesh_texture_note(mesh_texture_use *use, const struct aiScene *sc, const struct aiMesh *am)
{
    struct aiString s;
    const struct aiMaterial *mat = am->mMaterialIndex < sc->mNumMaterials ? sc->mMaterials[am->mMaterialIndex] : NULL;
    bool named = mat && am->mTextureCoords[0] &&
                 aiGetMaterialTexture(mat, aiTextureType_DIFFUSE, 0, &s, NULL, NULL, NULL, NULL, NULL, NULL) ==
                     aiReturn_SUCCESS && s.length > 0 && s.length < sizeof s.data;
    if (named) s.data[s.length] = '\0';
    if (named && strcmp(s.data, MESH_MD2_PLACEHOLDER) == 0) use->placeholder++, named = false;
    if (!named) {
        use->untextured++;
        return;
    }
    if (use->names == 0) snprintf(use->name, sizeof use->name, "%s", s.data), use->names = 1;
    else if (use->names == 1 && strcmp(use->name, s.data) != 0) use->names = 2;
}

/* The name as it is shown in messages (control bytes as '?', at most 200 bytes) into buf. */
static const char *shown(const char *name, char *buf, size_t len)
{
    mesh_sanitize(buf, len, name, 200);
    return buf;
}

/* Whether the name is absolute: "/x", or a drive letter's "C:/x" (with '\\' read as '/'). */
static bool absolute(const char *name)
{
    return name[0] == '/' || (((name[0] | 0x20) >= 'a' && (name[0] | 0x20) <= 'z') && name[1] == ':');
}

/* The checks of one candidate path (the folder's prefix + rel) into out[IS_MESH_TEXTURE_MAX]: NULL when it is a
 * regular file inside the resolved folder `real_folder`, else why not (for the warning). */
static const char *check_candidate(const char *prefix, const char *rel, const char *real_folder, char *out)
{
    if ((size_t)snprintf(out, IS_MESH_TEXTURE_MAX, "%s%s", prefix, rel) >= IS_MESH_TEXTURE_MAX)
        return "makes a path longer than the limit";
    char real[PATH_MAX];
    struct stat st;
    if (!realpath(out, real)) return errno == ENOENT || errno == ENOTDIR ? "is not in the mesh's folder" : strerror(errno);
    if (!mesh_path_inside(real_folder, real)) return "is outside the mesh's folder";
    if (stat(real, &st) != 0) return strerror(errno);
    if (!S_ISREG(st.st_mode)) return S_ISDIR(st.st_mode) ? "is a directory" : "is not a regular file";
    return NULL;
}

/* The one entry of the folder whose name is `file` but for case (a file made on Windows names "TEST.PNG" for
 * test.png), checked, into out; false when there is none, or more than one. */
static bool case_match(const char *folder, const char *prefix, const char *real_folder, const char *file, char *out)
{
    DIR *d = opendir(folder);
    char hit[256] = "";
    unsigned n = 0;
    for (struct dirent *e = d ? readdir(d) : NULL; e; e = readdir(d))
        if (strcasecmp(e->d_name, file) == 0 && strlen(e->d_name) < sizeof hit) n++, snprintf(hit, sizeof hit, "%s", e->d_name);
    if (d) closedir(d);
    return n == 1 && !check_candidate(prefix, hit, real_folder, out);
}

/* The named texture name (not embedded, not the placeholder) in the folder of path into m->texture, or a
 * warning: as a path relative to the folder, then by its last component in the folder, then by that component
 * in another case (the one file of the folder that differs only in case). */
static void resolve_named(is_mesh *m, const char *path, const char *label, const char *name,
                          const is_mesh_options *opt)
{
    char norm[1024], prefix[PATH_MAX], folder[PATH_MAX], real_folder[PATH_MAX], safe[256];
    snprintf(norm, sizeof norm, "%s", name);
    for (char *c = norm; *c; c++) if (*c == '\\') *c = '/';
    const char *slash = strrchr(path, '/'), *base = strrchr(norm, '/');
    snprintf(prefix, sizeof prefix, "%.*s", slash ? (int)(slash - path + 1) : 0, path);
    mesh_folder_of(path, folder, sizeof folder);
    if (!realpath(folder, real_folder)) {
        mesh_warn(opt, "%s: its texture '%s' is not used: the mesh's folder cannot be resolved (%s)", label,
                  shown(name, safe, sizeof safe), strerror(errno));
        return;
    }
    const char *rel = strncmp(norm, "./", 2) == 0 ? norm + 2 : norm;
    const char *why = absolute(norm) ? "is not in the mesh's folder" : check_candidate(prefix, rel, real_folder, m->texture);
    const char *file = base ? base + 1 : rel;
    if (why && base && base[1] && (absolute(norm) || strcmp(file, rel) != 0))
        why = check_candidate(prefix, file, real_folder, m->texture) ? why : NULL;
    if (why && file[0] && case_match(folder, prefix, real_folder, file, m->texture)) why = NULL;
    if (!why) return;
    m->texture[0] = '\0';
    mesh_warn(opt, "%s: its material names the texture '%s', which %s: rendered untextured (--texture FILE gives one)",
              label, shown(name, safe, sizeof safe), why);
}

/* Width and height of the BMP, PNG or TGA image at path (by its header; false when it is none of them, or
 * unreadable).  The file is opened without following a link, read only when regular, 32 bytes at most. */
static bool image_size(const char *path, const char *ext, int *w, int *h)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC);
    struct stat st;
    unsigned char b[32] = {0};
    ssize_t n = fd >= 0 && fstat(fd, &st) == 0 && S_ISREG(st.st_mode) ? pread(fd, b, sizeof b, 0) : -1;
    if (fd >= 0) close(fd);
    if (n < 26) return false;
    uint32_t le16_12 = b[12] | b[13] << 8, le16_14 = b[14] | b[15] << 8;
    if (strcasecmp(ext, "bmp") == 0 && b[0] == 'B' && b[1] == 'M') {
        int32_t bw = (int32_t)(b[18] | b[19] << 8 | b[20] << 16 | (uint32_t)b[21] << 24);
        int32_t bh = (int32_t)(b[22] | b[23] << 8 | b[24] << 16 | (uint32_t)b[25] << 24);
        *w = bw, *h = bh < 0 ? -bh : bh;
        return true;
    }
    if (strcasecmp(ext, "png") == 0 && memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0 && memcmp(b + 12, "IHDR", 4) == 0) {
        *w = (int)((uint32_t)b[16] << 24 | b[17] << 16 | b[18] << 8 | b[19]);
        *h = (int)((uint32_t)b[20] << 24 | b[21] << 16 | b[22] << 8 | b[23]);
        return true;
    }
    if (strcasecmp(ext, "tga") == 0 && (b[2] & ~8u) >= 1 && (b[2] & ~8u) <= 3) {
        *w = (int)le16_12, *h = (int)le16_14;
        return true;
    }
    return false;
}

/* The skin size of the MD2 file at path when it names no skin and has texture coordinates (its header: "IDP2",
 * skin width and height at bytes 8 and 12, the skin count at 20, the texture coordinates' at 28); false else. */
static bool md2_unnamed_skin(const char *path, int *w, int *h)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    unsigned char b[32];
    ssize_t n = fd >= 0 ? pread(fd, b, sizeof b, 0) : -1;
    if (fd >= 0) close(fd);
    if (n != (ssize_t)sizeof b || memcmp(b, "IDP2", 4) != 0) return false;
    int32_t v[8];
    for (int k = 0; k < 8; k++) v[k] = (int32_t)(b[4 * k] | b[4 * k + 1] << 8 | b[4 * k + 2] << 16 | (uint32_t)b[4 * k + 3] << 24);
    *w = v[2], *h = v[3];
    return v[5] == 0 && v[7] > 0 && *w > 0 && *h > 0;
}

/* Whether the directory entry e of the folder (prefix: its path with '/') is a skin of the MD2 model named
 * `model` (its file name without the extension): a BMP, PNG or TGA whose name starts with model's, a regular file
 * inside the folder, of size w x h. */
static bool is_skin(const char *e, const char *model, const char *prefix, const char *real_folder, int w, int h)
{
    size_t n = strlen(model);
    const char *dot = strrchr(e, '.');
    if (strncmp(e, model, n) != 0 || !dot || dot < e + n ||
        (strcasecmp(dot + 1, "bmp") != 0 && strcasecmp(dot + 1, "png") != 0 && strcasecmp(dot + 1, "tga") != 0))
        return false;
    char path[IS_MESH_TEXTURE_MAX], real[PATH_MAX];
    int iw = 0, ih = 0;
    return !check_candidate(prefix, e, real_folder, path) && realpath(path, real) &&
           image_size(real, dot + 1, &iw, &ih) && iw == w && ih == h;
}

/* An MD2 that names no skin: the one image of its folder that is its skin (is_skin) into m->texture; several:
 * a warning; none: nothing. */
static void md2_skin(is_mesh *m, const char *path, const char *label, const is_mesh_options *opt)
{
    int w, h;
    char folder[PATH_MAX], real_folder[PATH_MAX], prefix[PATH_MAX], model[256], first[256] = "", second[256] = "";
    if (!md2_unnamed_skin(path, &w, &h)) return;
    mesh_folder_of(path, folder, sizeof folder);
    const char *slash = strrchr(path, '/'), *file = slash ? slash + 1 : path, *dot = strrchr(file, '.');
    snprintf(prefix, sizeof prefix, "%.*s", slash ? (int)(slash - path + 1) : 0, path);
    snprintf(model, sizeof model, "%.*s", dot ? (int)(dot - file) : (int)strlen(file), file);
    DIR *d = realpath(folder, real_folder) ? opendir(folder) : NULL;
    unsigned found = 0;
    for (struct dirent *e = d ? readdir(d) : NULL; e; e = readdir(d)) {
        if (strlen(e->d_name) >= sizeof first || !is_skin(e->d_name, model, prefix, real_folder, w, h)) continue;
        found++;   /* the first two by name: the same answer in any directory order */
        if (!first[0] || strcmp(e->d_name, first) < 0) snprintf(second, sizeof second, "%s", first),
                                                      snprintf(first, sizeof first, "%s", e->d_name);
        else if (!second[0] || strcmp(e->d_name, second) < 0) snprintf(second, sizeof second, "%s", e->d_name);
    }
    if (d) closedir(d);
    if (found == 1) snprintf(m->texture, sizeof m->texture, "%s%s", prefix, first);
    char s1[256], s2[256];
    if (found > 1)
        mesh_warn(opt, "%s: names no skin, and %u images in its folder have its skin's size %dx%d ('%s', '%s'%s): "
                  "rendered untextured (--texture FILE chooses one)", label, found, w, h, shown(first, s1, sizeof s1),
                  shown(second, s2, sizeof s2), found > 2 ? ", ..." : "");
}

/* mesh_texture_resolve: see mesh_internal.h. */
void mesh_texture_resolve(is_mesh *m, const char *path, const char *label, const mesh_texture_use *use,
                          const is_mesh_options *opt)
{
    char safe[256];
    m->texture[0] = '\0';
    const char *ext = path ? strrchr(path, '.') : NULL;
    if (use->names == 0 && use->placeholder && path && ext && strcasecmp(ext, ".md2") == 0) md2_skin(m, path, label, opt);
    if (use->names == 0) return;
    const char *name = shown(use->name, safe, sizeof safe);
    if (use->names > 1)
        mesh_warn(opt, "%s: its meshes name different diffuse textures ('%s', ...) and instess draws with one: rendered "
                  "untextured (--texture FILE gives one)", label, name);
    else if (use->untextured)
        mesh_warn(opt, "%s: some of its meshes have no diffuse texture or no texture coordinates, others name '%s': "
                  "rendered untextured (--texture FILE gives one)", label, name);
    else if (use->name[0] == '*')
        mesh_warn(opt, "%s: its texture '%s' is embedded in the file, which instess does not read: rendered "
                  "untextured (--texture FILE gives one)", label, name);
    else if (!path)
        mesh_warn(opt, "%s: its texture '%s' is not used: a mesh read from memory has no folder", label, name);
    else
        resolve_named(m, path, label, use->name, opt);
}
