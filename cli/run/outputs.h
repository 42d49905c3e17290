/* cli/run/outputs.h -- the files of one run of the program: all are written or none is left.
 *
 * Conventions: functions return 0 / index >= 0, or -1 with a message naming the file in err.  The signal table
 * (outputs_remove_temp_files) is the program's: the library never installs handlers nor reads test hooks.
 */
#ifndef INSTESS_CLI_OUTPUTS_H
#define INSTESS_CLI_OUTPUTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "../../image/image.h"

/* The files one run writes succeed together or none is left.  outputs_add claims each target before any work:
 * it must be a regular file or absent (a symbolic link, a directory, a device, a FIFO or a socket is refused,
 * never replaced), its name within the folder's limit (NAME_MAX, 255 bytes on Linux), not the same file as an
 * earlier output of the run (same path or same inode), in an existing folder the process may write.  The first
 * write creates the output's temporary ".instess-XXXXXX.tmp" in that folder with mkstemp (O_EXCL, a random
 * name: a link planted at a predictable name is never followed).  Writers fill the temporaries
 * (outputs_write, or outputs_stream for stdio); every write is checked, EFBIG (`ulimit -f`, when
 * SIGXFSZ is ignored, as the program does) and ENOSPC included.  outputs_commit fsyncs every temporary, checks
 * each target again, and only then renames them onto their targets one by one; on any failure it calls
 * outputs_abort, which unlinks every temporary not yet renamed.  A target changes only by rename(2), so after
 * any signal, also SIGKILL, it holds the previous file or the complete new one; two processes writing the
 * same target leave one of the two complete files.  (After a failed rename of a second output the first one
 * has already been replaced: only a failure of rename(2) itself, after all writing succeeded, can do that.)
 * A run holds no file and no descriptor for its outputs until it writes them (after the import and the render).
 *
 * Signals: the temporaries' names sit in a fixed table from before each file exists;
 * outputs_remove_temp_files() unlinks them and is async-signal-safe (lock-free atomics and unlink(2)), for a
 * program's handlers of SIGTERM, SIGINT, SIGHUP, SIGQUIT, SIGXCPU (cli/run/main.c), which then die of the signal.
 * SIGKILL cannot be caught: a stale ".instess-*.tmp" may then remain.  At most 16 temporaries are tracked at
 * once (beyond that a file is written but not removed by a signal).
 * In the test build only (INSTESS_TEST_HOOKS: build/tests/instess-hooks), INSTESS_TEST_WRITE_DELAY_MS=N (at
 * most 60000) makes outputs_commit wait N ms with every temporary complete and none renamed, so that a test can
 * signal the program in that window; the program proper reads no such variable. */
#define IS_OUTPUTS_MAX 4
typedef struct is_output_file {
    const char *path;                      /* the target, as given (not copied: keep it alive) */
    char tmp[4096];                        /* its temporary file, "" when none */
    int fd, slot;                          /* open descriptor or -1; signal slot or -1 */
    bool renamed;                          /* the temporary is in place */
} is_output_file;
typedef struct is_outputs {
    int n;
    is_output_file f[IS_OUTPUTS_MAX];
} is_outputs;

void outputs_init(is_outputs *o);
/* Claim path as the next output (checks above; nothing is created yet); its index k >= 0, or -1 with a
 * message naming path.  Nothing else of o changes on failure (the caller still calls outputs_abort). */
int outputs_add(is_outputs *o, const char *path, char *err, size_t errlen);
/* Append n bytes to output k's temporary; 0 or -1 with a message naming the target. */
int outputs_write(is_outputs *o, int k, const void *buf, size_t n, char *err, size_t errlen);
/* A stdio stream appending to output k's temporary, or NULL; finish it with outputs_close_stream (0 or -1:
 * the first write error of the stream, named). */
FILE *outputs_stream(is_outputs *o, int k, char *err, size_t errlen);
int outputs_close_stream(is_outputs *o, int k, FILE *s, char *err, size_t errlen);
/* fsync every temporary, then rename each onto its target; 0, or -1 with a message (all temporaries gone). */
int outputs_commit(is_outputs *o, char *err, size_t errlen);
/* Remove every temporary not yet renamed and release its slot; safe to call twice or after a commit. */
void outputs_abort(is_outputs *o);
/* True if paths a and b name the same file: the same string, the same existing inode, or the same name in the
 * same folder after resolving the folders' links (for a usage check before any output is claimed). */
bool outputs_same_target(const char *a, const char *b);
/* Unlink every temporary of this process that exists now: async-signal-safe. */
void outputs_remove_temp_files(void);

/* Write one image file as a run of its own (the program's screenshots and figures): through the outputs above, so
 * a signal leaves no temporary and the target holds its old or its complete new bytes; 0 or -1. */
int outputs_write_image(const is_image *img, const char *path, const is_image_meta *meta, char *err, size_t errlen);
/* Encode img in the format of output k's path and write it into that output's temporary; 0 or -1. */
int image_write_output(is_outputs *o, int k, const is_image *img, const is_image_meta *meta, char *err,
                       size_t errlen);

#endif
