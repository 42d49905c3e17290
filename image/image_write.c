/* image/image_write.c -- image files written whole or not at all (image_write): the encoded bytes go to a
 * temporary file beside the target (created exclusively), are synced, and the temporary is renamed over the
 * target; on any failure the temporary is removed and the target is as it was.  Apart from image/image.c (images
 * in memory), which also builds where there are no files to write (the browser build, web/web.mk). */
#define _GNU_SOURCE /* mkostemps */
#include "image_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Write n bytes to fd, retrying short writes; 0 or an errno value. */
static int write_all(int fd, const unsigned char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return w < 0 ? errno : EIO;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

/* bytes[0..len) onto path through a temporary ".instess-XXXXXX.tmp" beside it, renamed when complete;
 * path must be a regular file or absent.  0 or -1 with a message naming path; nothing left on failure. */
static int write_file_atomic(const char *path, const unsigned char *bytes, size_t len, char *err, size_t errlen)
{
    struct stat st;
    if (lstat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return image_set_err(err, errlen, "%s: is %s; instess writes only regular files and will not replace it", path,
                             S_ISDIR(st.st_mode) ? "a directory" : S_ISLNK(st.st_mode) ? "a symbolic link"
                             : S_ISFIFO(st.st_mode) ? "a FIFO" : "not a regular file"), -1;
    char tmp[4096];
    const char *slash = strrchr(path, '/');
    int dlen = slash ? (int)(slash - path) : 1;
    int n = snprintf(tmp, sizeof tmp, "%.*s/.instess-XXXXXX.tmp", dlen, slash ? (slash == path ? "/" : path) : ".");
    if (n < 0 || (size_t)n >= sizeof tmp) return image_set_err(err, errlen, "%s: path too long", path), -1;
    int fd = mkostemps(tmp, 4, O_CLOEXEC);
    if (fd < 0) return image_set_err(err, errlen, "%s: cannot create a file beside it: %s", path, strerror(errno)), -1;
    (void)fchmod(fd, 0644);
    int e = write_all(fd, bytes, len);
    if (!e && fsync(fd) != 0) e = errno;
    if (close(fd) != 0 && !e) e = errno;
    if (!e && rename(tmp, path) != 0) e = errno;
    if (e) {
        unlink(tmp);
        return image_set_err(err, errlen, "%s: %s", path, strerror(e)), -1;
    }
    return 0;
}

int image_write(const is_image *img, const char *path, const is_image_meta *meta, char *err, size_t errlen)
{
    if (image_check_path(path, err, errlen) != 0) return -1;
    unsigned char *bytes = NULL;
    size_t len = 0;
    if (image_encode(img, image_format_of(path), meta, path, &bytes, &len, err, errlen) != 0) return -1;
    int rc = write_file_atomic(path, bytes, len, err, errlen);
    free(bytes);
    return rc;
}
