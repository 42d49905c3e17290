/* core/image_codec.c -- the image codec, loaded on the first image call: image_encode, image_read,
 * image_compare, image_draw_text and image_text_size (core/core.h) forward to libinstess_codec.so
 * (core/image_oiio.cpp and OpenImageIO), opened with dlopen.
 *
 * Why: OpenImageIO brings in about 260 shared libraries, and loading them took 0.5 s of every start of the
 * program, also of `--help`, of usage and input errors and of renders that fail before they write.  Now a
 * process loads them only when it encodes, reads, compares or draws text.
 *
 * Where the module is looked for, first found wins: beside the executable (build/instess), one folder up
 * (build/tests/...), and ../lib/instess beside it (an installed program).  The executable exports its own
 * symbols (-rdynamic) for the module's calls of image_alloc, image_write and the like.  When no module can be
 * loaded, every call fails with a message naming the places tried and dlerror's reason.
 *
 * The function table is filled once (pthread_once) and read-only afterwards: with the signal handler's slots
 * (core/output.c), one of the two process-wide states the project allows. */
#define _GNU_SOURCE  /* dladdr-free /proc/self/exe handling, RTLD_* */
#include "device_internal.h"

#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define CODEC_MODULE "libinstess_codec.so"

/* The module's entry points (the image_* signatures of core.h). */
typedef struct codec_table {
    int (*encode)(const is_image *, is_image_format, const is_image_meta *, const char *, unsigned char **, size_t *,
                  char *, size_t);
    int (*read)(is_image *, const char *, char *, size_t);
    int (*compare)(const is_image *, const is_image *, float, float, is_image_diff *, const char *, char *, size_t);
    int (*draw_text)(is_image *, int, int, const char *, float, const float[4], char *, size_t);
    int (*text_size)(const char *, float, int *, int *);
    char why[1536];  /* why loading failed, when it did */
} codec_table;

static codec_table g_codec;
static pthread_once_t g_codec_once = PTHREAD_ONCE_INIT;

/* The folder of the running executable into dir ("." if unknown). */
static void exe_dir(char *dir, size_t len)
{
    ssize_t n = readlink("/proc/self/exe", dir, len - 1);
    if (n <= 0) {
        snprintf(dir, len, ".");
        return;
    }
    dir[n] = 0;
    char *slash = strrchr(dir, '/');
    if (slash) *slash = 0;
}

/* Open the module from the places above; its handle or NULL with g_codec.why filled. */
static void *open_module(void)
{
    char dir[PATH_MAX], path[PATH_MAX + 64];
    exe_dir(dir, sizeof dir);
    const char *const rel[] = {"", "/..", "/../lib/instess"};
    size_t n = (size_t)snprintf(g_codec.why, sizeof g_codec.why, "image codec: cannot load " CODEC_MODULE);
    for (int k = 0; k < 3; k++) {
        snprintf(path, sizeof path, "%s%s/" CODEC_MODULE, dir, rel[k]);
        if (access(path, R_OK) != 0) continue;
        void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
        if (h) return h;
        if (n < sizeof g_codec.why) n += (size_t)snprintf(g_codec.why + n, sizeof g_codec.why - n, "; %s", dlerror());
    }
    if (n < sizeof g_codec.why)
        snprintf(g_codec.why + n, sizeof g_codec.why - n, " (looked beside %.900s, in .. and ../lib/instess)", dir);
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
    *(void **)&t.compare = dlsym(h, "codec_compare");
    *(void **)&t.draw_text = dlsym(h, "codec_draw_text");
    *(void **)&t.text_size = dlsym(h, "codec_text_size");
    if (!t.encode || !t.read || !t.compare || !t.draw_text || !t.text_size) {
        snprintf(g_codec.why, sizeof g_codec.why, "image codec: " CODEC_MODULE " lacks an entry point");
        return;
    }
    memcpy(&g_codec, &t, offsetof(codec_table, why));
}

/* The loaded codec, or NULL with the reason in err. */
static const codec_table *codec(char *err, size_t errlen)
{
    pthread_once(&g_codec_once, load_codec);
    if (g_codec.encode) return &g_codec;
    core_set_err(err, errlen, "%s", g_codec.why);
    return NULL;
}

int image_encode(const is_image *img, is_image_format fmt, const is_image_meta *meta, const char *label,
                 unsigned char **bytes, size_t *len, char *err, size_t errlen)
{
    const codec_table *c = codec(err, errlen);
    return c ? c->encode(img, fmt, meta, label, bytes, len, err, errlen) : -1;
}

int image_read(is_image *img, const char *path, char *err, size_t errlen)
{
    const codec_table *c = codec(err, errlen);
    return c ? c->read(img, path, err, errlen) : -1;
}

int image_compare(const is_image *a, const is_image *b, float fail_thresh, float warn_thresh, is_image_diff *res,
                  const char *diff_path, char *err, size_t errlen)
{
    const codec_table *c = codec(err, errlen);
    return c ? c->compare(a, b, fail_thresh, warn_thresh, res, diff_path, err, errlen) : -1;
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
