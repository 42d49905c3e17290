/* image/image_codec.c -- the image codec, loaded on the first call that needs it: image_encode (EXR), image_read
 * (every file but the PNGs image/image_png.c decodes), image_draw_text and image_text_size (image/image.h)
 * forward to libinstess_codec.so (image/image_oiio.cpp and OpenImageIO), opened with dlopen.  PNG files are
 * written and read through libpng (image/image_png.c), and image_compare is C (image/image_diff.c):
 * neither loads the module.
 *
 * Why: OpenImageIO brings in about 260 shared libraries, and loading them takes about 0.4 s (the dynamic
 * loader binding their symbols).  It was paid by every start of the program, then (with the module) by every
 * process that touched an image; now only by one that writes or reads an EXR (or another format) or draws text.
 *
 * Where the module is looked for, by absolute path only; the first folder that holds the file decides (a module
 * there that is refused is an error, not a reason to look further):
 *  1. $INSTESS_CODEC_DIR, when set (a relocated install, or a test of the staged install); it must be an
 *     absolute path (a relative one is refused: a module is never loaded from the current directory);
 *  2. instess/ beside the shared library that holds this code (libinstess.so in LIBDIR finds
 *     LIBDIR/instess/libinstess_codec.so, wherever the library was installed or staged: found with dladdr);
 *  3. beside the executable (build/instess; the build puts a link to the module beside the test programs in
 *     build/tests/ too), and ../lib/instess beside it (the installed program, BINDIR = PREFIX/bin) -- never the
 *     current folder nor the folder above the program, where anyone might plant a module whose constructor
 *     would run inside instess;
 *  4. INSTESS_CODEC_DIR as compiled in by the Makefile (LIBDIR/instess of the PREFIX the library was built
 *     for): a program linked with the static archive libinstess.a finds the installed module there.
 * Before dlopen runs any of its code, the file is checked: a regular file, it and its folder owned by root or
 * this user and not writable by every user, a 64-bit ELF shared object whose dynamic symbols define codec_abi;
 * then codec_abi must be CODEC_ABI before any entry point is called.
 * The module calls image_alloc, image_write and the like of the code that opened it through the table it is
 * handed when loaded (codec_set_host, image_internal.h): it has no undefined symbol of the library, so it loads
 * in a static program, and beside a libinstess.so opened with RTLD_LOCAL (Python's ctypes) alike.  When no module can be loaded, every call fails with a message naming
 * the places tried and dlerror's reason.
 *
 * The function table is filled once (pthread_once) and read-only afterwards: with the signal handler's slots
 * (cli/run/output.c), one of the two process-wide states the project allows. */
#define _GNU_SOURCE  /* dladdr-free /proc/self/exe handling, RTLD_* */
#include "image_internal.h"

#include <dlfcn.h>
#include <elf.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define CODEC_MODULE "libinstess_codec.so"
/* The module's interface version, its exported int codec_abi (image/image_oiio.cpp): a module of another version
 * is refused before any of its functions is called.  2: the host table (codec_set_host), PNG reading left the
 * module. */
#define CODEC_ABI 2

/* The module's entry points (the image_* signatures of image/image.h). */
typedef struct codec_table {
    int (*encode)(const is_image *, is_image_format, const is_image_meta *, const char *, unsigned char **, size_t *,
                  char *, size_t);
    int (*read)(is_image *, const char *, char *, size_t);
    int (*draw_text)(is_image *, int, int, const char *, float, const float[4], char *, size_t);
    int (*text_size)(const char *, float, int *, int *);
    char why[4096];  /* why loading failed, when it did */
} codec_table;

static codec_table g_codec;
static pthread_once_t g_codec_once = PTHREAD_ONCE_INIT;

#ifndef INSTESS_CODEC_DIR
#define INSTESS_CODEC_DIR "/usr/local/lib/instess"
#endif

/* The folder of the running executable into dir; false when unknown (then nothing is looked for beside it:
 * "." would be the current directory). */
static bool exe_dir(char *dir, size_t len)
{
    char exe[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0 || exe[0] != '/') return false;
    exe[n] = 0;
    image_dir_of(exe, dir, len);
    return true;
}

/* The folder of the shared object that holds this code into dir; false when it is the executable itself
 * (linked with libinstess.a) or unknown. */
static bool library_dir(char *dir, size_t len)
{
    Dl_info info;
    char exe[PATH_MAX], lib[PATH_MAX];
    if (!dladdr((void *)library_dir, &info) || !info.dli_fname || !realpath(info.dli_fname, lib)) return false;
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    exe[n > 0 ? n : 0] = 0;
    if (strcmp(lib, exe) == 0) return false;
    image_dir_of(lib, dir, len);
    return true;
}

/* The folders to look in, in order (see the top of this file), into dirs[]; their number, or -1 with the reason
 * in why when $INSTESS_CODEC_DIR is not an absolute path. */
static int candidate_dirs(char dirs[][PATH_MAX + 32], char *why, size_t whylen)
{
    int n = 0;
    const char *env = getenv("INSTESS_CODEC_DIR");
    char d[PATH_MAX];
    if (env && *env) {
        if (env[0] != '/') {
            snprintf(why, whylen, "image codec: INSTESS_CODEC_DIR=%.300s is not an absolute path: refused (a module "
                     "is never loaded from the current directory)", env);
            return -1;
        }
        snprintf(dirs[n++], PATH_MAX + 32, "%.*s", PATH_MAX, env);
    }
    if (library_dir(d, sizeof d)) snprintf(dirs[n++], PATH_MAX + 32, "%s/instess", d);
    if (exe_dir(d, sizeof d)) {
        snprintf(dirs[n++], PATH_MAX + 32, "%s", d);
        snprintf(dirs[n++], PATH_MAX + 32, "%s/../lib/instess", d);
    }
    snprintf(dirs[n++], PATH_MAX + 32, "%s", INSTESS_CODEC_DIR);
    return n;
}

const char *image_codec_install_dir(void)
{
    return INSTESS_CODEC_DIR;
}

/* Open the module from the places above (the first folder holding the file decides: a module there that is
 * refused is an error, not a reason to look further) and check its version; its handle or NULL with
 * g_codec.why filled. */
static void *open_module(void)
{
    char dirs[5][PATH_MAX + 32], path[PATH_MAX + 64];
    int nd = candidate_dirs(dirs, g_codec.why, sizeof g_codec.why);
    if (nd < 0) return NULL;
    for (int k = 0; k < nd; k++) {
        snprintf(path, sizeof path, "%.*s/" CODEC_MODULE, PATH_MAX, dirs[k]);
        struct stat st;
        if (lstat(path, &st) != 0) continue;
        char why[1024];
        void *h = image_module_open(path, "codec_abi", why, sizeof why);
        if (!h) {
            snprintf(g_codec.why, sizeof g_codec.why, "image codec: %s", why);
            return NULL;
        }
        const int *abi = dlsym(h, "codec_abi");
        if (!abi || *abi != CODEC_ABI) {
            snprintf(g_codec.why, sizeof g_codec.why, "image codec: %.2000s: not an image codec module of this "
                     "version (codec_abi %d, this library needs %d): refused", path, abi ? *abi : 0, CODEC_ABI);
            dlclose(h);
            return NULL;
        }
        return h;
    }
    size_t n = (size_t)snprintf(g_codec.why, sizeof g_codec.why, "image codec: cannot load " CODEC_MODULE);
    for (int k = 0; k < nd && n < sizeof g_codec.why; k++)
        n += (size_t)snprintf(g_codec.why + n, sizeof g_codec.why - n, "%s%.300s", k ? ", " : " (looked in ", dirs[k]);
    if (n < sizeof g_codec.why) snprintf(g_codec.why + n, sizeof g_codec.why - n, ")");
    return NULL;
}

/* Fill g_codec (once): the module's five entry points, or none and the reason. */
static void load_codec(void)
{
    void *h = open_module();
    if (!h) return;
    codec_table t = {0};
    *(void **)&t.encode = dlsym(h, "codec_encode");
    *(void **)&t.read = dlsym(h, "codec_read");
    *(void **)&t.draw_text = dlsym(h, "codec_draw_text");
    *(void **)&t.text_size = dlsym(h, "codec_text_size");
    void (*set_host)(const image_codec_host *);
    *(void **)&set_host = dlsym(h, "codec_set_host");
    if (!t.encode || !t.read || !t.draw_text || !t.text_size || !set_host) {
        snprintf(g_codec.why, sizeof g_codec.why, "image codec: " CODEC_MODULE " lacks an entry point: refused");
        dlclose(h);
        return;
    }
    static const image_codec_host host = {image_alloc, image_channel_index, image_free, image_write};
    set_host(&host);
    memcpy(&g_codec, &t, offsetof(codec_table, why));
}

/* The loaded codec, or NULL with the reason in err. */
static const codec_table *codec(char *err, size_t errlen)
{
    pthread_once(&g_codec_once, load_codec);
    if (g_codec.encode) return &g_codec;
    image_set_err(err, errlen, "%s", g_codec.why);
    return NULL;
}

int image_encode(const is_image *img, is_image_format fmt, const is_image_meta *meta, const char *label,
                 unsigned char **bytes, size_t *len, char *err, size_t errlen)
{
    if (fmt != IS_IMAGE_PNG && fmt != IS_IMAGE_EXR)   /* before the C++ side, where another value is no enum's */
        return image_set_err(err, errlen, "%s: image_encode: format %d is neither PNG nor EXR", label ? label : "image",
                             (int)fmt), -1;
    if (fmt == IS_IMAGE_PNG && bytes && len) {   /* PNG: libpng, without loading the module */
        label = label ? label : "image";
        *bytes = NULL, *len = 0;
        return image_valid(img, label, err, errlen) ? image_png_encode(img, meta, label, bytes, len, err, errlen) : -1;
    }
    const codec_table *c = codec(err, errlen);
    return c ? c->encode(img, fmt, meta, label, bytes, len, err, errlen) : -1;
}

/* What a file that is not regular is, in words. */
static const char *kind_of(mode_t m)
{
    return S_ISDIR(m) ? "a directory" : S_ISFIFO(m) ? "a FIFO" : S_ISCHR(m) || S_ISBLK(m) ? "a device"
           : S_ISSOCK(m) ? "a socket" : "not a regular file";
}

/* Whether path names a file image_read may open: a regular file (a FIFO would block the reader, /dev/zero never
 * ends), not empty, at most IS_IMAGE_MAX_FILE_BYTES; else false with why in err.  Decided by stat, before any
 * open, so that OpenImageIO never reads a file it would scan for minutes. */
static bool readable_image_file(const char *path, char *err, size_t errlen)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return image_set_err(err, errlen, "%s: cannot open: %s", path, strerror(errno)), false;
    if (!S_ISREG(st.st_mode))
        return image_set_err(err, errlen, "%s: is %s, not an image file", path, kind_of(st.st_mode)), false;
    if (st.st_size == 0) return image_set_err(err, errlen, "%s: empty file, not an image", path), false;
    if ((unsigned long long)st.st_size > IS_IMAGE_MAX_FILE_BYTES)
        return image_set_err(err, errlen, "%s: the file has %lld bytes, more than the limit of %llu for an image "
                             "file; not opened", path, (long long)st.st_size, IS_IMAGE_MAX_FILE_BYTES), false;
    return true;
}

int image_read(is_image *img, const char *path, char *err, size_t errlen)
{
    if (img) memset(img, 0, sizeof *img);
    if (!img || !path || !*path) return image_set_err(err, errlen, "image_read: NULL image or empty path"), -1;
    if (!readable_image_file(path, err, errlen)) return -1;
    int png = image_png_read(img, path, err, errlen);   /* every PNG (by its signature): libpng */
    if (png != 1) return png;
    const codec_table *c = codec(err, errlen);
    return c ? c->read(img, path, err, errlen) : -1;
}

int image_draw_text(is_image *img, int x, int y, const char *text, float size_px, const float rgba[4], char *err,
                    size_t errlen)
{
    const codec_table *c = codec(err, errlen);
    return c ? c->draw_text(img, x, y, text, size_px, rgba, err, errlen) : -1;
}

int image_text_size(const char *text, float size_px, int *w, int *h)
{
    const codec_table *c = codec(NULL, 0);
    return c ? c->text_size(text, size_px, w, h) : -1;
}
