/* tests/util/prog.h -- running the instess program from a test, on files in a work folder.
 *
 * Conventions: `dir` is the test's own temporary folder (made with prog_mkdtemp, removed with prog_rmdir);
 * names are relative to it.  The program is $INSTESS_BIN (the sanitizer stage points it at the ASan build) or
 * build/instess.  Exit codes come back as the program's, or 128 + N when it died of signal N. */
#ifndef INSTESS_TESTS_PROG_H
#define INSTESS_TESTS_PROG_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>

/* The program under test. */
const char *prog_bin(void);
/* The program built with the test hooks (INSTESS_TEST_HOOKS, e.g. INSTESS_TEST_WRITE_DELAY_MS): $INSTESS_HOOKS_BIN,
 * or build/tests/instess-hooks.  The program proper has no hooks. */
const char *prog_hooks_bin(void);
/* Make a fresh folder /tmp/instess-<tag>-XXXXXX into dir (at least 256 bytes); 0 or -1. */
int prog_mkdtemp(char *dir, const char *tag);
/* Remove dir and everything in it. */
void prog_rmdir(const char *dir);
/* Run the shell command line "prefix program ARGS" (ARGS printf-expanded; prefix may be "" or e.g.
 * "ulimit -f 8;") with stderr captured into *err (a static buffer, overwritten by the next run) and stdout
 * discarded; returns the exit code. */
int prog_run(const char *dir, const char **err, const char *prefix, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* dir/name into buf. */
const char *prog_path(const char *dir, const char *name, char *buf, size_t len);
/* Run the shell line "cd DIR && PREFIX PROGRAM ARGS REDIRECT": PREFIX (NULL: none) e.g. "timeout -s KILL 120" or
 * environment assignments, PROGRAM the program under test by its absolute path when NULL, ARGS fmt expanded with
 * ap, REDIRECT e.g. ">out.txt 2>err.txt"; the exit code (128 + N for a death by signal N), 127 with a message on
 * stderr when the program under test is not found. */
int prog_vrun_in(const char *dir, const char *prefix, const char *program, const char *redirect, const char *fmt,
                 va_list ap);
/* The text of dir/name into buf (len bytes, NUL-terminated, cut to fit; "" when it cannot be read). */
void prog_read_text(const char *dir, const char *name, char *buf, size_t len);
/* The exit code of a system() status: the program's, or 128 + N for a death by signal N. */
int prog_exit_code(int status);
/* Write n bytes (or a string) into dir/name; false on failure. */
bool prog_write_bytes(const char *dir, const char *name, const void *data, size_t n);
bool prog_write_text(const char *dir, const char *name, const char *text);
/* Whether dir/name exists (links are not followed). */
bool prog_exists(const char *dir, const char *name);
/* Number of entries of dir whose name contains part (NULL: all), not counting stderr.txt. */
int prog_entries_with(const char *dir, const char *part);
/* The whole content of path (malloc'ed, *n bytes), or NULL. */
unsigned char *prog_slurp(const char *path, size_t *n);
/* Whether image files a and b decode to the same size, channels and pixel values (false, with the reason on
 * stderr, when either cannot be read). */
bool prog_same_pixels(const char *a, const char *b);
/* Base64 (RFC 4648, with padding) of n bytes into out, which holds 4 * ((n + 2) / 3) + 1 bytes. */
void prog_base64(const unsigned char *in, size_t n, char *out);
/* Whether two files hold the same bytes (false if either is missing). */
bool prog_same_bytes(const char *a, const char *b);

/* Whether this is the AddressSanitizer build (make sanitize): clang's __has_feature, gcc's macro. */
#if defined(__SANITIZE_ADDRESS__)
#define UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UNDER_ASAN 1
#endif
#endif
#ifndef UNDER_ASAN
#define UNDER_ASAN 0
#endif

#endif
