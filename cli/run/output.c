/* cli/run/output.c -- the files one run writes, all or none (the API and its rules are in cli/run/outputs.h).
 *
 * Each output is checked when it is claimed, before any work: a regular file or nothing at the path (never a
 * symbolic link, a directory, a device, a FIFO or a socket), a name within the filesystem's limit, no second
 * claim of the same file (same path or same inode), and an existing folder the process may write.  The first
 * write creates the output's temporary file there with mkstemp (O_CREAT | O_EXCL, a random name, so a link
 * planted at a predictable name is never followed).  Every write is checked (EFBIG from `ulimit -f` and ENOSPC
 * are errors, not signals: the program ignores SIGXFSZ).  outputs_commit fsyncs every temporary and only then
 * renames each onto its target; outputs_abort unlinks them.
 *
 * The temporaries' names also sit in a fixed table of slots from before each file exists, so that a signal
 * handler can unlink them (outputs_remove_temp_files).  That table is the one accepted exception to "no
 * mutable globals": a signal handler reaches nothing else. */
#define _GNU_SOURCE  /* mkostemps */
#include "outputs.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define TEMP_SLOTS 16
#define TEMP_PATH_MAX 4096

/* A slot's state: 0 free, 1 claimed, 2 path valid (the file may exist; the handler unlinks it). */
typedef struct temp_slot {
    atomic_int state;
    char path[TEMP_PATH_MAX];
} temp_slot;
_Static_assert(ATOMIC_INT_LOCK_FREE == 2, "the signal handler needs lock-free atomics");
static temp_slot g_temp_slots[TEMP_SLOTS];  /* zero-initialised: all free */

/* printf into err (when given), always NUL-terminated. */
static void __attribute__((format(printf, 3, 4))) set_err(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

/* Claim a slot holding path (state 2); its index, or -1 when all are busy or the path is too long. */
static int temp_claim(const char *path)
{
    size_t n = strlen(path);
    if (n >= TEMP_PATH_MAX) return -1;
    for (int s = 0; s < TEMP_SLOTS; s++) {
        int expected = 0;
        if (atomic_compare_exchange_strong(&g_temp_slots[s].state, &expected, 1)) {
            memcpy(g_temp_slots[s].path, path, n + 1);
            atomic_store(&g_temp_slots[s].state, 2);
            return s;
        }
    }
    return -1;
}

/* Free slot s (after the rename or the unlink of its file); -1 is ignored. */
static void temp_release(int s)
{
    if (s >= 0 && s < TEMP_SLOTS) atomic_store(&g_temp_slots[s].state, 0);
}

void outputs_remove_temp_files(void)
{
    for (int s = 0; s < TEMP_SLOTS; s++)
        if (atomic_load(&g_temp_slots[s].state) == 2) unlink(g_temp_slots[s].path);
}

/* The folder part of path into dir ("." when there is none); false if it does not fit. */
static bool dir_of(const char *path, char *dir, size_t len)
{
    const char *slash = strrchr(path, '/');
    if (!slash) return snprintf(dir, len, ".") < (int)len;
    size_t n = slash == path ? 1 : (size_t)(slash - path);
    if (n >= len) return false;
    memcpy(dir, path, n);
    dir[n] = 0;
    return true;
}

/* The file name part of path. */
static const char *base_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* What kind of file st is, in words (for refusals). */
static const char *kind_of(const struct stat *st)
{
    if (S_ISDIR(st->st_mode)) return "a directory";
    if (S_ISLNK(st->st_mode)) return "a symbolic link";
    if (S_ISCHR(st->st_mode) || S_ISBLK(st->st_mode)) return "a device";
    if (S_ISFIFO(st->st_mode)) return "a FIFO";
    if (S_ISSOCK(st->st_mode)) return "a socket";
    return "not a regular file";
}

/* Check path as a target: a name, within NAME_MAX, and a regular file or nothing there; *st / *exists out. */
static int check_target(const char *path, struct stat *st, bool *exists, char *err, size_t errlen)
{
    const char *base = base_of(path);
    if (!*base || !strcmp(base, ".") || !strcmp(base, "..")) {
        set_err(err, errlen, "%s: not a file name", *path ? path : "(empty output path)");
        return -1;
    }
    char dir[TEMP_PATH_MAX];
    if (!dir_of(path, dir, sizeof dir)) return set_err(err, errlen, "%s: path too long", path), -1;
    long name_max = pathconf(dir, _PC_NAME_MAX);
    if (name_max <= 0) name_max = NAME_MAX;
    if ((long)strlen(base) > name_max) {
        set_err(err, errlen, "%s: the file name is %zu bytes, longer than the folder's limit of %ld", path,
                strlen(base), name_max);
        return -1;
    }
    struct stat ds;
    errno = 0;
    if (stat(dir, &ds) != 0 || !S_ISDIR(ds.st_mode) || access(dir, W_OK | X_OK) != 0) {
        set_err(err, errlen, "%s: cannot create a file in the folder %s: %s", path, dir,
                errno ? strerror(errno) : "not a directory");
        return -1;
    }
    *exists = lstat(path, st) == 0;
    if (!*exists && errno != ENOENT) return set_err(err, errlen, "%s: %s", path, strerror(errno)), -1;
    if (*exists && !S_ISREG(st->st_mode)) {
        set_err(err, errlen, "%s: is %s; instess writes only regular files and will not replace it", path,
                kind_of(st));
        return -1;
    }
    return 0;
}


bool outputs_same_target(const char *a, const char *b)
{
    if (!strcmp(a, b)) return true;
    struct stat sa, sb;
    if (stat(a, &sa) == 0 && stat(b, &sb) == 0) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    char da[TEMP_PATH_MAX], db[TEMP_PATH_MAX], ra[PATH_MAX], rb[PATH_MAX];
    if (strcmp(base_of(a), base_of(b)) || !dir_of(a, da, sizeof da) || !dir_of(b, db, sizeof db)) return false;
    return realpath(da, ra) && realpath(db, rb) && !strcmp(ra, rb);
}

/* Create f's temporary file ".instess-XXXXXX.tmp" in the target's folder (its name claimed in a signal slot
 * first); 0 or -1 with a message. */
static int make_temp(is_output_file *f, char *err, size_t errlen)
{
    char dir[TEMP_PATH_MAX];
    dir_of(f->path, dir, sizeof dir);
    int n = snprintf(f->tmp, sizeof f->tmp, "%s/.instess-XXXXXX.tmp", dir);
    if (n < 0 || (size_t)n >= sizeof f->tmp) return set_err(err, errlen, "%s: path too long", f->path), -1;
    f->slot = temp_claim(f->tmp);
    char *name = f->slot >= 0 ? g_temp_slots[f->slot].path : f->tmp;
    int fd = mkostemps(name, 4, O_CLOEXEC);
    if (fd < 0) {
        set_err(err, errlen, "%s: cannot create a file in the folder %s: %s", f->path, dir, strerror(errno));
        temp_release(f->slot);
        f->slot = -1;
        return -1;
    }
    if (name != f->tmp) memcpy(f->tmp, name, strlen(name) + 1);
    (void)fchmod(fd, 0644);  /* mkstemp makes 0600; images are for everyone to read */
    f->fd = fd;
    return 0;
}

void outputs_init(is_outputs *o)
{
    memset(o, 0, sizeof *o);
}

int outputs_add(is_outputs *o, const char *path, char *err, size_t errlen)
{
    if (!path) return set_err(err, errlen, "outputs_add: NULL path"), -1;
    if (o->n >= IS_OUTPUTS_MAX) return set_err(err, errlen, "%s: more than %d outputs", path, IS_OUTPUTS_MAX), -1;
    if (strlen(path) >= TEMP_PATH_MAX - 32) return set_err(err, errlen, "%s: path too long", path), -1;
    struct stat st;
    bool exists;
    if (check_target(path, &st, &exists, err, errlen) != 0) return -1;
    for (int k = 0; k < o->n; k++)
        if (outputs_same_target(o->f[k].path, path)) {
            set_err(err, errlen, "%s: named as two outputs of one run (%s and %s)", path, o->f[k].path, path);
            return -1;
        }
    is_output_file *f = &o->f[o->n];
    memset(f, 0, sizeof *f);
    f->path = path;
    f->fd = -1;
    f->slot = -1;
    return o->n++;
}

/* Create f's temporary file on its first write; 0 or -1. */
static int open_temp(is_output_file *f, char *err, size_t errlen)
{
    return f->fd >= 0 ? 0 : make_temp(f, err, errlen);
}

int outputs_write(is_outputs *o, int k, const void *buf, size_t n, char *err, size_t errlen)
{
    is_output_file *f = &o->f[k];
    if (open_temp(f, err, errlen) != 0) return -1;
    size_t done = 0;
    while (done < n) {
        ssize_t w = write(f->fd, (const char *)buf + done, n - done);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            const char *why = w < 0 ? (errno == EFBIG ? "the file size limit (ulimit -f) was reached" : strerror(errno))
                                    : "no progress";
            set_err(err, errlen, "%s: write failed after %zu of %zu bytes: %s", f->path, done, n, why);
            return -1;
        }
        done += (size_t)w;
    }
    return 0;
}

FILE *outputs_stream(is_outputs *o, int k, char *err, size_t errlen)
{
    is_output_file *f = &o->f[k];
    if (open_temp(f, err, errlen) != 0) return NULL;
    int fd = dup(f->fd);
    FILE *s = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!s) {
        set_err(err, errlen, "%s: cannot open a stream: %s", f->path, strerror(errno));
        if (fd >= 0) close(fd);
    }
    return s;
}

int outputs_close_stream(is_outputs *o, int k, FILE *s, char *err, size_t errlen)
{
    errno = 0;
    bool ok = fflush(s) == 0 && !ferror(s);
    int e = errno;
    ok = fclose(s) == 0 && ok;
    if (!e) e = errno;
    if (!ok)
        set_err(err, errlen, "%s: write failed: %s", o->f[k].path,
                e == EFBIG ? "the file size limit (ulimit -f) was reached" : e ? strerror(e) : "stream error");
    return ok ? 0 : -1;
}

/* The test build's hook (build/tests/instess-hooks, compiled with INSTESS_TEST_HOOKS; the program proper has
 * none): INSTESS_TEST_WRITE_DELAY_MS=N sleeps N ms (at most 60000) with every temporary complete and none
 * renamed, so that tests can signal the program in that window. */
static void test_write_delay(void)
{
#ifdef INSTESS_TEST_HOOKS
    const char *d = getenv("INSTESS_TEST_WRITE_DELAY_MS");
    long ms = d ? strtol(d, NULL, 10) : 0;
    if (ms <= 0 || ms > 60000) return;
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
#endif
}

/* fsync a folder (makes the renames durable; some filesystems cannot, which is harmless here). */
static void fsync_dir(const char *path)
{
    char dir[TEMP_PATH_MAX];
    if (!dir_of(path, dir, sizeof dir)) return;
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        (void)fsync(fd);
        close(fd);
    }
}

/* Re-check f's target just before the rename: still a regular file or nothing (a link or folder planted
 * meanwhile is not replaced). */
static int recheck_target(const is_output_file *f, char *err, size_t errlen)
{
    struct stat st;
    bool exists;
    return check_target(f->path, &st, &exists, err, errlen);
}

int outputs_commit(is_outputs *o, char *err, size_t errlen)
{
    for (int k = 0; k < o->n; k++) {
        is_output_file *f = &o->f[k];
        if (open_temp(f, err, errlen) != 0) return outputs_abort(o), -1;
        if (fsync(f->fd) != 0 || close(f->fd) != 0) {
            f->fd = -1;
            set_err(err, errlen, "%s: fsync / close failed: %s", f->path, strerror(errno));
            outputs_abort(o);
            return -1;
        }
        f->fd = -1;
        if (recheck_target(f, err, errlen) != 0) return outputs_abort(o), -1;
    }
    test_write_delay();
    for (int k = 0; k < o->n; k++) {
        is_output_file *f = &o->f[k];
        if (rename(f->tmp, f->path) != 0) {
            set_err(err, errlen, "%s: cannot rename the temporary file into place: %s", f->path, strerror(errno));
            outputs_abort(o);
            return -1;
        }
        f->renamed = true;
        temp_release(f->slot);
        f->slot = -1;
        fsync_dir(f->path);
    }
    return 0;
}

void outputs_abort(is_outputs *o)
{
    for (int k = 0; k < o->n; k++) {
        is_output_file *f = &o->f[k];
        if (f->fd >= 0) close(f->fd);
        f->fd = -1;
        if (!f->renamed && f->tmp[0]) unlink(f->tmp);
        f->tmp[0] = 0;
        temp_release(f->slot);
        f->slot = -1;
    }
}

/* Whether s is a time SOURCE_DATE_EPOCH may give: digits only, 0..253402300799 (9999-12-31 23:59:59) -- the
 * rule image/image_oiio.cpp's set_date_time applies when it stores the time in an OpenEXR file. */
static bool source_date_ok(const char *s)
{
    size_t n = strspn(s, "0123456789");
    return n > 0 && n <= 12 && !s[n] && strtoull(s, NULL, 10) <= 253402300799ull;
}

/* Say on stderr (a warning naming the value, control bytes as '?') that SOURCE_DATE_EPOCH, set and not empty, is
 * no time, so that the OpenEXR file path stores none -- the codec ignores it without a word. */
static void warn_source_date(const char *path)
{
    const char *e = getenv("SOURCE_DATE_EPOCH");
    if (!e || !*e || source_date_ok(e)) return;
    char shown[64];
    size_t n = 0;
    for (; e[n] && n < sizeof shown - 1; n++) shown[n] = (unsigned char)e[n] < 0x20 || e[n] == 0x7f ? '?' : e[n];
    shown[n] = 0;
    fprintf(stderr, "instess: warning: SOURCE_DATE_EPOCH='%s'%s is not a whole number of seconds in "
            "0..253402300799: the OpenEXR files store no time (%s)\n", shown, e[n] ? "..." : "", path);
}

int image_write_output(is_outputs *o, int k, const is_image *img, const is_image_meta *meta, char *err,
                       size_t errlen)
{
    const char *path = o->f[k].path;
    if (image_check_path(path, err, errlen) != 0) return -1;
    if (image_format_of(path) == IS_IMAGE_EXR) warn_source_date(path);
    unsigned char *bytes = NULL;
    size_t len = 0;
    if (image_encode(img, image_format_of(path), meta, path, &bytes, &len, err, errlen) != 0) return -1;
    int rc = outputs_write(o, k, bytes, len, err, errlen);
    free(bytes);
    return rc;
}

int outputs_write_image(const is_image *img, const char *path, const is_image_meta *meta, char *err, size_t errlen)
{
    if (image_check_path(path, err, errlen) != 0) return -1;
    is_outputs o;
    outputs_init(&o);
    int k = outputs_add(&o, path, err, errlen);
    int rc = k < 0 ? -1 : image_write_output(&o, k, img, meta, err, errlen);
    if (rc == 0) return outputs_commit(&o, err, errlen);
    outputs_abort(&o);
    return -1;
}
