/* meshes/mesh_internal.h -- helpers shared by the files of meshes/ (not part of the public header). */
#ifndef INSTESS_MESH_INTERNAL_H
#define INSTESS_MESH_INTERNAL_H

#include <limits.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#include <assimp/cfileio.h>

struct aiScene;
struct aiMesh;

#include "meshes.h"
#include "../core/hlsl.h"

/* Write a formatted message into err (if any). */
void mesh_set_err(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Send a formatted warning to opt's callback (if any). */
void mesh_warn(const is_mesh_options *opt, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Copy src into dst[len] with every control byte (below 0x20, and 0x7f) replaced by '?', so a name or message
 * taken from a hostile file cannot move the terminal's cursor or fake a line of its own; at most max_chars
 * bytes of src (then "..."). */
void mesh_sanitize(char *dst, size_t len, const char *src, size_t max_chars);

/* ------------------------------ limits (docs/robustness.md, "Limits") ------------------------------ */

/* Triangles after instancing the scene's nodes: more can never be drawn (at level 1 a triangle is 3 shaded
 * vertices, and the scene's budget is 64 M; instance_id is exact below 2^24). */
#define MESH_MAX_IMPORT_TRIANGLES ((size_t)1 << 24)
/* Vertices after instancing, before unused and identical ones are dropped (3 per triangle for OBJ / STL). */
#define MESH_MAX_IMPORT_VERTICES ((size_t)1 << 26)
/* Mesh references made by the scene's nodes (a node graph that shares children is expanded as a tree). */
#define MESH_MAX_NODE_INSTANCES ((size_t)1 << 20)
/* Default of is_mesh_options.max_file_bytes: all files of one mesh together. */
#define MESH_DEFAULT_MAX_FILE_BYTES ((uint64_t)256 << 20)
/* Without is_mesh_options.max_import_memory_bytes, the address space the import child may add: this floor,
 * plus this much for every byte of the files assimp opens (assimp 5.2.5 needs about 5-10 bytes per byte of
 * OBJ and binary STL; compressed formats more).  A node graph that shares children (glTF), which assimp
 * expands as a tree, stops at the floor within about 2 s instead of filling gigabytes. */
#define MESH_IMPORT_MEMORY_FLOOR ((uint64_t)256 << 20)
#define MESH_IMPORT_MEMORY_PER_BYTE 32
/* The most of a file read to check a PLY or OFF header before the import. */
#define MESH_HEADER_BYTES 65536

/* ------------------------------ the files assimp may read (import_io.c) ------------------------------ */

/* Distinct files one import may read (the mesh and its side files). */
#define MESH_IO_MAX_FILES 64

/* The file system assimp sees: the mesh file itself, and side files (glTF buffers, ...) only when they are
 * regular files inside the mesh's folder after resolving symlinks; material libraries are never read; all
 * files together at most max_bytes.  For a memory import, only the buffer under the name mem_name. */
typedef struct mesh_io {
    struct aiFileIO fio;           /* handed to assimp; first member, so the callbacks find the rest */
    const char *label;             /* names the mesh in messages */
    const char *path;              /* the mesh file as given, or NULL for a memory import */
    bool obj;                      /* an OBJ mesh: its side files are only material libraries */
    char real[PATH_MAX];           /* the mesh file, resolved */
    char folder[PATH_MAX];         /* the folder side files must lie in, resolved */
    const void *data;              /* memory import: the bytes served as mem_name */
    size_t size;
    char mem_name[64];
    uint64_t max_bytes, total_bytes;
    dev_t dev[MESH_IO_MAX_FILES];  /* the distinct files opened so far (total_bytes counts each once) */
    ino_t ino[MESH_IO_MAX_FILES];
    size_t n_files;
    char refusal[512];             /* the first file refused and why ("" when none) */
    void (*on_file)(void *user, uint64_t bytes);   /* optional: called with the size of each new file opened */
    void *on_file_user;
} mesh_io;

/* Set up io for the mesh file `path` (checked by the caller); 0, or IS_MESH_ERR_IO with a message. */
int mesh_io_init_file(mesh_io *io, const char *path, const char *label, uint64_t max_bytes, char *err,
                      size_t errlen);
/* Set up io for a buffer; `hint` is the format's extension (may be NULL or ""). */
void mesh_io_init_memory(mesh_io *io, const void *data, size_t size, const char *hint, const char *label);
/* The name to hand to aiImportFileEx with &io->fio. */
const char *mesh_io_name(const mesh_io *io);
/* The folder of path (everything before the last '/', "." when none, "/" for "/x") into dir[len]. */
void mesh_folder_of(const char *path, char *dir, size_t len);
/* Whether the resolved path `real` lies inside the resolved folder (at any depth). */
bool mesh_path_inside(const char *folder, const char *real);

/* ------------------------------ the file's texture (import_texture.c) ------------------------------ */

/* assimp's MD2 loader names this diffuse texture when the file names no skin: a placeholder, never a file. */
#define MESH_MD2_PLACEHOLDER "$texture_dummy.bmp"

/* The diffuse textures of the meshes a scene draws, as the import child found them (and sends them). */
typedef struct mesh_texture_use {
    char name[1024];             /* the first texture named (assimp's aiString: at most 1023 bytes), or "" */
    uint32_t names;              /* distinct texture names (counting stops at 2) */
    uint32_t untextured;         /* drawn meshes without one (no texture, no texture coordinates, the placeholder) */
    uint32_t placeholder;        /* drawn meshes with MESH_MD2_PLACEHOLDER */
} mesh_texture_use;

/* Record the diffuse texture of one drawn scene mesh (its material's, when it has texture coordinates). */
void mesh_texture_note(mesh_texture_use *use, const struct aiScene *sc, const struct aiMesh *am);

/* The texture of the imported mesh m into m->texture (meshes.h, mesh_load_file: "The file's texture") from what
 * the import found: resolved in the folder of the mesh file `path` (NULL for a memory import: never), warnings
 * naming label through opt.  Nothing is returned: a texture that cannot be used is a warning, not an error. */
void mesh_texture_resolve(is_mesh *m, const char *path, const char *label, const mesh_texture_use *use,
                          const is_mesh_options *opt);

/* ------------------------------ checks before the import (import_check.c) ------------------------------ */

/* Check a PLY or OFF header in head[0..n) (the first bytes of a file of file_size bytes) against the file's
 * size and the limits above: every declared element needs some bytes in the body (binary PLY: exactly known
 * sizes, lists at least their count; ASCII: at least 2 bytes per number).  Other formats, and headers this
 * check cannot parse, pass (assimp then reads them under the import's time and memory limits).  0 or
 * IS_MESH_ERR_INVALID with a message naming label. */
int mesh_check_header(const unsigned char *head, size_t n, uint64_t file_size, const char *label, char *err,
                      size_t errlen);

/* The face indices of a text OFF or OBJ file or a binary MD2 file (data[0..n), ext its extension without the
 * dot, or NULL): every corner names a vertex of the file (assimp 5.2 clamps an OFF or MD2 index past the end
 * without a word).  Other formats pass (assimp's validation refuses their out-of-range indices, and an import
 * whose loader logs a clamped index fails: meshes/import.c).  0 or IS_MESH_ERR_INVALID with a message naming
 * label, the line (text) or triangle, the face and the index. */
int mesh_check_face_indices(const unsigned char *data, size_t n, const char *ext, const char *label, char *err,
                            size_t errlen);

/* ------------------------------ normals (normals_check.c) ------------------------------ */

/* After the normals of m are set: count the corners whose file normal equals its face's normal (facet
 * normals) and those whose normal points against its face (wrong winding); fills the stats and warns
 * through opt.  Nothing when the normals were all computed. */
void mesh_check_normals(is_mesh *m, const char *label, const is_mesh_options *opt);

#endif
