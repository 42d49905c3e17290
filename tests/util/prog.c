/* tests/util/prog.c -- running the instess program from a test (see prog.h). */
#include "prog.h"

#include "../../core/core.h"
#include "../../image/image.h"

#include <dirent.h>
#include <stdint.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

char *mkdtemp(char *tmpl);  /* POSIX 2008, declared only with _DEFAULT_SOURCE by glibc's headers */

const char *prog_hooks_bin(void)
{
    const char *b = getenv("INSTESS_HOOKS_BIN");
    return b && *b ? b : "build/tests/instess-hooks";
}

const char *prog_bin(void)
{
    const char *b = getenv("INSTESS_BIN");
    return b && *b ? b : "build/instess";
}

int prog_mkdtemp(char *dir, const char *tag)
{
    snprintf(dir, 256, "/tmp/instess-%s-XXXXXX", tag);
    return mkdtemp(dir) ? 0 : -1;
}

void prog_rmdir(const char *dir)
{
    char cmd[600];
    snprintf(cmd, sizeof cmd, "chmod -R u+rwx '%s' 2>/dev/null; rm -rf '%s'", dir, dir);
    if (system(cmd) != 0) fprintf(stderr, "prog_rmdir: could not remove %s\n", dir);
}

int prog_run(const char *dir, const char **err, const char *prefix, const char *fmt, ...)
{
    static char errbuf[16384];
    char args[6000], cmd[8192], errfile[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    snprintf(errfile, sizeof errfile, "%s/stderr.txt", dir);
    snprintf(cmd, sizeof cmd, "%s %s %s 2>'%s' >/dev/null", prefix ? prefix : "", prog_bin(), args, errfile);
    int st = system(cmd);
    FILE *f = fopen(errfile, "r");
    size_t n = f ? fread(errbuf, 1, sizeof errbuf - 1, f) : 0;
    if (f) fclose(f);
    unlink(errfile);
    errbuf[n] = 0;
    if (err) *err = errbuf;
    return prog_exit_code(st);
}

const char *prog_path(const char *dir, const char *name, char *buf, size_t len)
{
    snprintf(buf, len, "%s/%s", dir, name);
    return buf;
}

bool prog_write_bytes(const char *dir, const char *name, const void *data, size_t n)
{
    char p[4400];
    FILE *f = fopen(prog_path(dir, name, p, sizeof p), "wb");
    if (!f) return false;
    bool ok = fwrite(data, 1, n, f) == n;
    return (fclose(f) == 0) && ok;
}

bool prog_write_text(const char *dir, const char *name, const char *text)
{
    return prog_write_bytes(dir, name, text, strlen(text));
}

bool prog_exists(const char *dir, const char *name)
{
    char p[4400];
    struct stat s;
    return lstat(prog_path(dir, name, p, sizeof p), &s) == 0;
}

int prog_entries_with(const char *dir, const char *part)
{
    DIR *d = opendir(dir);
    if (!d) return -1;
    int n = 0;
    for (struct dirent *e; (e = readdir(d));) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..") || !strcmp(e->d_name, "stderr.txt")) continue;
        if (!part || strstr(e->d_name, part)) n++;
    }
    closedir(d);
    return n;
}

char *realpath(const char *path, char *resolved);   /* POSIX; glibc declares it only with _DEFAULT_SOURCE */

int prog_vrun_in(const char *dir, const char *prefix, const char *program, const char *redirect, const char *fmt,
                 va_list ap)
{
    char args[12000], cmd[16384 + 4096], bin[4096];
    if (!program) {
        if (!realpath(prog_bin(), bin)) return fprintf(stderr, "no program %s\n", prog_bin()), 127;
        program = bin;
    }
    vsnprintf(args, sizeof args, fmt, ap);
    snprintf(cmd, sizeof cmd, "cd '%s' && %s '%s' %s %s", dir, prefix ? prefix : "", program, args,
             redirect ? redirect : "");
    return prog_exit_code(system(cmd));
}

void prog_read_text(const char *dir, const char *name, char *buf, size_t len)
{
    char p[1024];
    size_t n = 0;
    unsigned char *t = prog_slurp(prog_path(dir, name, p, sizeof p), &n);
    snprintf(buf, len, "%.*s", t ? (int)n : 0, t ? (char *)t : "");
    free(t);
}

int prog_exit_code(int status)
{
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

unsigned char *prog_slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *buf = malloc(len > 0 ? (size_t)len : 1);
    *n = buf && len > 0 ? fread(buf, 1, (size_t)len, f) : 0;
    fclose(f);
    return buf;
}

bool prog_same_bytes(const char *a, const char *b)
{
    size_t na = 0, nb = 0;
    unsigned char *x = prog_slurp(a, &na), *y = prog_slurp(b, &nb);
    bool same = x && y && na == nb && memcmp(x, y, na) == 0;
    free(x);
    free(y);
    return same;
}

void prog_base64(const unsigned char *in, size_t n, char *out)
{
    static const char a[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t k = 0; k < n; k += 3) {
        uint32_t v = (uint32_t)in[k] << 16 | (k + 1 < n ? (uint32_t)in[k + 1] << 8 : 0) | (k + 2 < n ? in[k + 2] : 0);
        out[o++] = a[v >> 18 & 63];
        out[o++] = a[v >> 12 & 63];
        out[o++] = k + 1 < n ? a[v >> 6 & 63] : '=';
        out[o++] = k + 2 < n ? a[v & 63] : '=';
    }
    out[o] = 0;
}

bool prog_same_pixels(const char *a, const char *b)
{
    is_image x = {0}, y = {0};
    char err[512];
    bool read = image_read(&x, a, err, sizeof err) == 0 && image_read(&y, b, err, sizeof err) == 0;
    if (!read) fprintf(stderr, "prog_same_pixels: %s\n", err);
    bool same = read && x.width == y.width && x.height == y.height && x.channels == y.channels &&
                memcmp(x.data, y.data, sizeof(float) * (size_t)x.width * x.height * x.channels) == 0;
    image_free(&x), image_free(&y);
    return same;
}
