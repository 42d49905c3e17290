/* meshes/import_io.c -- every file assimp reads goes through here (assimp/cfileio.h's aiFileIO, handed to
 * aiImportFileEx).  The rule (docs/robustness.md, "Threat model: inputs"):
 *  - the mesh file itself is read;
 *  - a side file (a glTF buffer, an MD3 skin, ...) is read only when, after resolving symlinks, it lies inside
 *    the mesh file's folder and is a regular file: never a device, a FIFO or a socket (a FIFO would block the
 *    import until the time limit), never a file outside the folder (`../../etc/passwd`, an absolute path);
 *  - material libraries are never read (an OBJ's mtllib, any *.mtl): materials are not used for rendering;
 *  - all files of one mesh together hold at most max_bytes;
 *  - a memory import reads its buffer and nothing else.
 * A refused file is not opened (assimp sees a missing file) and the first refusal is kept in io->refusal
 * for the error message.  Nothing is ever written. */
#define _XOPEN_SOURCE 700   /* realpath */
#include "mesh_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

/* One open file: the aiFile assimp holds (first member), and where its bytes come from. */
typedef struct io_file {
    struct aiFile f;
    int fd;                          /* -1 for the memory buffer */
    const unsigned char *mem;
    uint64_t size, pos;
} io_file;

/* mesh_sanitize: see mesh_internal.h. */
void mesh_sanitize(char *dst, size_t len, const char *src, size_t max_chars)
{
    if (!dst || len == 0) return;
    size_t n = 0;
    for (; src && src[n] && n < max_chars && n + 1 < len; n++) {
        unsigned char c = (unsigned char)src[n];
        dst[n] = c < 0x20 || c == 0x7f ? '?' : (char)c;
    }
    dst[n] = '\0';
    if (src && src[n] && n + 4 < len) memcpy(dst + n, "...", 4);
}

/* What kind of file mode is, for messages ("a FIFO"). */
static const char *kind_of(mode_t mode)
{
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    return "not a regular file";
}

/* Keep the first refusal, "LABEL: refers to 'NAME', WHY: not read" (the mesh file itself: "LABEL: WHY");
 * returns NULL (assimp sees no file). */
static struct aiFile *refuse(mesh_io *io, const char *name, bool main, const char *why)
{
    if (io->refusal[0]) return NULL;
    char safe[256];
    const char *slash = io->path ? strrchr(io->path, '/') : NULL;
    size_t prefix = slash ? (size_t)(slash - io->path) + 1 : 0;   /* assimp asks for "FOLDER/" + the reference */
    if (!main && prefix && strncmp(name, io->path, prefix) == 0) name += prefix;
    mesh_sanitize(safe, sizeof safe, name, 200);
    if (main) snprintf(io->refusal, sizeof io->refusal, "%s: %s", io->label, why);
    else snprintf(io->refusal, sizeof io->refusal, "%s: refers to '%s', which %s: not read", io->label, safe, why);
    return NULL;
}

/* refuse() with "cannot be opened (strerror(e))". */
static struct aiFile *refuse_errno(mesh_io *io, const char *name, bool main, int e)
{
    char why[160];
    snprintf(why, sizeof why, "%s (%s)", main ? "cannot open" : "cannot be opened", strerror(e));
    return refuse(io, name, main, why);
}

/* Read up to size * count bytes at the file's position (fread's contract: returns whole items read). */
static size_t io_read(struct aiFile *af, char *buf, size_t size, size_t count)
{
    io_file *f = (io_file *)af;
    if (size == 0 || count == 0 || count > SIZE_MAX / size || f->pos >= f->size) return 0;
    uint64_t want = (uint64_t)size * count, left = f->size - f->pos;
    size_t n = (size_t)(want < left ? want : left), got = 0;
    if (f->fd < 0) {
        memcpy(buf, f->mem + f->pos, n);
        got = n;
    }
    while (f->fd >= 0 && got < n) {
        ssize_t r = pread(f->fd, buf + got, n - got, (off_t)(f->pos + got));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) break;
        got += (size_t)r;
    }
    f->pos += got;
    return got / size;
}

/* assimp never writes through this IO: refused. */
static size_t io_write(struct aiFile *af, const char *buf, size_t size, size_t count)
{
    (void)af, (void)buf, (void)size, (void)count;
    return 0;
}

/* The position. */
static size_t io_tell(struct aiFile *af) { return (size_t)((io_file *)af)->pos; }

/* The size at the time of opening. */
static size_t io_size(struct aiFile *af) { return (size_t)((io_file *)af)->size; }

/* Nothing to flush. */
static void io_flush(struct aiFile *af) { (void)af; }

/* Move the position (offsets wrap as size_t, so SEEK_CUR / SEEK_END take negative ones); not past the end. */
static enum aiReturn io_seek(struct aiFile *af, size_t offset, enum aiOrigin origin)
{
    io_file *f = (io_file *)af;
    uint64_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? f->pos : f->size;
    uint64_t to = base + (uint64_t)offset;
    if (origin != aiOrigin_SET && origin != aiOrigin_CUR && origin != aiOrigin_END) return aiReturn_FAILURE;
    if (to > f->size) return aiReturn_FAILURE;
    f->pos = to;
    return aiReturn_SUCCESS;
}

/* A new aiFile over fd (or the memory buffer when fd < 0). */
static struct aiFile *new_file(int fd, const void *mem, uint64_t size)
{
    io_file *f = calloc(1, sizeof *f);
    if (!f) return NULL;
    f->f.ReadProc = io_read;
    f->f.WriteProc = io_write;
    f->f.TellProc = io_tell;
    f->f.FileSizeProc = io_size;
    f->f.SeekProc = io_seek;
    f->f.FlushProc = io_flush;
    f->fd = fd;
    f->mem = mem;
    f->size = size;
    return &f->f;
}

/* Count a newly opened file's bytes once per distinct file; false when the total would pass the limit. */
static bool count_file(mesh_io *io, const struct stat *st)
{
    for (size_t k = 0; k < io->n_files; k++)
        if (io->dev[k] == st->st_dev && io->ino[k] == st->st_ino) return true;
    if (io->n_files == MESH_IO_MAX_FILES || (uint64_t)st->st_size > io->max_bytes - io->total_bytes) return false;
    io->dev[io->n_files] = st->st_dev;
    io->ino[io->n_files++] = st->st_ino;
    io->total_bytes += (uint64_t)st->st_size;
    if (io->on_file) io->on_file(io->on_file_user, (uint64_t)st->st_size);
    return true;
}

/* Open the resolved path `real` (asked for as `name`; `main`: the mesh file itself) when it is a regular file
 * within the byte budget. */
static struct aiFile *open_checked(mesh_io *io, const char *name, const char *real, bool main)
{
    char why[160];
    struct stat st;
    if (stat(real, &st) != 0) return refuse_errno(io, name, main, errno);
    if (!S_ISREG(st.st_mode)) {   /* decided before open(): opening a device or a FIFO can have effects */
        snprintf(why, sizeof why, "is %s, not a regular file", kind_of(st.st_mode));
        return refuse(io, name, main, why);
    }
    int fd = open(real, O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return refuse_errno(io, name, main, errno);
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {   /* replaced since the stat */
        close(fd);
        return refuse(io, name, main, "is not a regular file");
    }
    if (!count_file(io, &st)) {
        close(fd);
        snprintf(why, sizeof why, "would bring the mesh's files over the limit of %llu bytes",
                 (unsigned long long)io->max_bytes);
        return refuse(io, name, main, why);
    }
    struct aiFile *f = new_file(fd, NULL, (uint64_t)st.st_size);
    if (!f) close(fd);
    return f;
}

/* Whether name ends in ".mtl" (any case). */
static bool is_material_library(const char *name)
{
    size_t n = strlen(name);
    return n >= 4 && strcasecmp(name + n - 4, ".mtl") == 0;
}

/* mesh_path_inside: see mesh_internal.h. */
bool mesh_path_inside(const char *folder, const char *real)
{
    size_t n = strlen(folder);
    if (n == 1 && folder[0] == '/') return true;
    return strncmp(real, folder, n) == 0 && real[n] == '/';
}

/* aiFileIO.OpenProc: the rule at the top of this file. */
static struct aiFile *io_open(struct aiFileIO *fio, const char *name, const char *mode)
{
    mesh_io *io = (mesh_io *)fio;
    if (!name || !mode || strpbrk(mode, "wa+")) return NULL;
    if (!io->path) {
        if (strcmp(name, io->mem_name) == 0) return new_file(-1, io->data, io->size);
        if (is_material_library(name)) return NULL;   /* materials: never read, no error */
        return refuse(io, name, false, "cannot be read: a mesh read from memory has no folder");
    }
    bool named = strcmp(name, io->path) == 0;
    if (!named && (io->obj || is_material_library(name))) return NULL;   /* materials: never read, no error */
    char real[PATH_MAX], why[PATH_MAX + 64];
    if (!realpath(name, real)) return refuse_errno(io, name, named, errno);
    if (named || strcmp(real, io->real) == 0) return open_checked(io, name, real, true);
    if (!mesh_path_inside(io->folder, real)) {
        snprintf(why, sizeof why, "is outside the mesh's folder %s", io->folder);
        return refuse(io, name, false, why);
    }
    return open_checked(io, name, real, false);
}

/* aiFileIO.CloseProc. */
static void io_close(struct aiFileIO *fio, struct aiFile *af)
{
    (void)fio;
    io_file *f = (io_file *)af;
    if (!f) return;
    if (f->fd >= 0) close(f->fd);
    free(f);
}

/* mesh_folder_of: see mesh_internal.h. */
void mesh_folder_of(const char *path, char *dir, size_t len)
{
    const char *slash = strrchr(path, '/');
    if (!slash) { snprintf(dir, len, "."); return; }
    size_t n = (size_t)(slash - path);
    snprintf(dir, len, "%.*s", (int)(n ? n : 1), path);
}

/* A cleared io whose aiFileIO opens and closes through this file, reporting as label. */
static void io_init(mesh_io *io, const char *label)
{
    memset(io, 0, sizeof *io);
    io->fio.OpenProc = io_open;
    io->fio.CloseProc = io_close;
    io->label = label;
}

/* mesh_io_init_file: see mesh_internal.h. */
int mesh_io_init_file(mesh_io *io, const char *path, const char *label, uint64_t max_bytes, char *err,
                      size_t errlen)
{
    io_init(io, label);
    io->path = path;
    io->max_bytes = max_bytes;
    size_t n = strlen(path);
    io->obj = n >= 4 && strcasecmp(path + n - 4, ".obj") == 0;
    char dir[PATH_MAX];
    mesh_folder_of(path, dir, sizeof dir);
    if (!realpath(path, io->real) || !realpath(dir, io->folder)) {
        mesh_set_err(err, errlen, "%s: cannot open: %s", label, strerror(errno));
        return IS_MESH_ERR_IO;
    }
    return IS_MESH_OK;
}

/* mesh_io_init_memory: see mesh_internal.h. */
void mesh_io_init_memory(mesh_io *io, const void *data, size_t size, const char *hint, const char *label)
{
    io_init(io, label);
    io->data = data;
    io->size = size;
    char ext[32];
    mesh_sanitize(ext, sizeof ext, hint ? hint : "", 16);
    snprintf(io->mem_name, sizeof io->mem_name, "$$instess-memory$$%s%s", ext[0] ? "." : "", ext);
}

/* mesh_io_name: see mesh_internal.h. */
const char *mesh_io_name(const mesh_io *io) { return io->path ? io->path : io->mem_name; }
