/* tests/test_hostile_files.c -- hostile input, round 3: the program's files.  `figures --out` into odd places and
 * `--only` with odd ids (family 5); several processes writing one output at once, and a mesh rewritten while it
 * is read (family 8); failed writes to stdout, --stats json on file names that are not UTF-8, and outputs that
 * name the input mesh.  Each case is in docs/robustness.md ("Round 3: images, files and environment").  Runs
 * build/instess or $INSTESS_BIN. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

char *realpath(const char *path, char *resolved);   /* POSIX; glibc declares them only with _DEFAULT_SOURCE */
int symlink(const char *target, const char *linkpath);
int link(const char *target, const char *linkpath);
int mkfifo(const char *path, mode_t mode);

#include "util/prog.h"
#include "../core/core.h"
#include "../image/image.h"

static char dir[256];
static char out_buf[16384], err_buf[16384];

/* Run `instess ARGS` in dir (cd there) with stdout into `out` (a file name, or "&-" to close it, or NULL for
 * dir/out.txt, read into out_buf) and stderr into err_buf; the exit code, 128 + N for a death by signal N. */
static int run_to(const char *out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int run_to(const char *out, const char *fmt, ...)
{
    char redirect[600];
    snprintf(redirect, sizeof redirect, ">%s 2>err.txt", out ? out : "out.txt");
    va_list ap;
    va_start(ap, fmt);
    int rc = prog_vrun_in(dir, "rm -f out.txt &&", NULL, redirect, fmt, ap);
    va_end(ap);
    prog_read_text(dir, "out.txt", out_buf, sizeof out_buf);
    prog_read_text(dir, "err.txt", err_buf, sizeof err_buf);
    return rc;
}
#define run(...) run_to(NULL, __VA_ARGS__)

/* Assert exit `code` and `what` in the last run's stderr. */
static void expect(int rc, int code, const char *what)
{
    if (rc != code || !strstr(err_buf, what))
        fail_msg("expected exit %d with \"%s\", got %d:\n%s", code, what, rc, err_buf);
}

/* dir/name into buf. */
static const char *at(const char *name, char *buf, size_t len)
{
    return prog_path(dir, name, buf, len);
}

/* The number of times needle occurs in the file dir/name (-1 when it cannot be read). */
static int count_in(const char *name, const char *needle)
{
    char p[512];
    size_t n;
    char *t = (char *)prog_slurp(at(name, p, sizeof p), &n);
    if (!t) return -1;
    char *z = realloc(t, n + 1);
    if (!z) return free(t), -1;
    z[n] = 0;
    int c = 0;
    for (const char *q = z; (q = strstr(q, needle)); q += strlen(needle)) c++;
    free(z);
    return c;
}

/* Whether dir/name is a complete gallery: one <html> that ends with </html> and a newline. */
static bool complete_gallery(const char *name)
{
    char p[512];
    size_t n;
    unsigned char *t = prog_slurp(at(name, p, sizeof p), &n);
    bool ok = t && n > 100 && memcmp(t, "<!DOCTYPE html>", 15) == 0 && memcmp(t + n - 8, "</html>\n", 8) == 0;
    free(t);
    return ok && count_in(name, "<html") == 1;
}

/* Whether dir/name holds exactly text. */
static bool holds(const char *name, const char *text)
{
    char p[512];
    size_t n;
    unsigned char *t = prog_slurp(at(name, p, sizeof p), &n);
    bool ok = t && n == strlen(text) && memcmp(t, text, n) == 0;
    free(t);
    return ok;
}

/* The kind of dir/name by lstat ('f' file, 'd' folder, 'l' link, 'p' FIFO, 0 none). */
static char kind(const char *name)
{
    char p[512];
    struct stat st;
    if (lstat(at(name, p, sizeof p), &st) != 0) return 0;
    return S_ISLNK(st.st_mode) ? 'l' : S_ISDIR(st.st_mode) ? 'd' : S_ISFIFO(st.st_mode) ? 'p' : S_ISREG(st.st_mode) ? 'f' : '?';
}

static int setup(void **state)
{
    (void)state;
    if (prog_mkdtemp(dir, "hfiles") != 0) return -1;
    return run("--size 32x32 --level 2 -q -o a.png") || run("--size 32x32 --level 3 -q -o b.png");
}

static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

/* A cheap figure (a diagram) for the figures cases. */
#define FIG "fig-003-4"

/* ------------------------------------------------------------ figures --out and --only */

/* --out a regular file, a dangling link, a path through a file: exit 1 before any work, nothing created or
 * changed; a link to a folder is followed like any path (the files land in that folder). */
static void test_figures_out_not_a_folder(void **state)
{
    (void)state;
    char p[512];
    assert_true(prog_write_text(dir, "plain", "a file\n"));
    expect(run("figures --only " FIG " --out plain"), 1, "plain: not a directory");
    assert_true(holds("plain", "a file\n"));
    expect(run("figures --only " FIG " --out plain/sub"), 1, "plain/sub: cannot create the directory: Not a directory");
    assert_int_equal(mkdir(at("real", p, sizeof p), 0755), 0);
    assert_int_equal(symlink("real", at("to-real", p, sizeof p)), 0);
    assert_int_equal(run("figures --only " FIG " --out to-real"), 0);
    assert_int_equal(kind("real/" FIG ".png"), 'f');
    assert_true(complete_gallery("real/index.html"));
    assert_int_equal(kind("to-real"), 'l');
    assert_int_equal(symlink("nowhere", at("dangling", p, sizeof p)), 0);
    expect(run("figures --only " FIG " --out dangling"), 1, "dangling: not a directory");
    assert_int_equal(kind("nowhere"), 0);
    assert_null(strstr(err_buf, "[ 1/1]"));   /* refused before rendering */
}

/* --out on a read-only filesystem (a tmpfs mounted read-only in a private mount namespace): exit 1 before any
 * rendering, naming the folder. */
static void test_figures_out_read_only(void **state)
{
    (void)state;
    char cmd[9000], mnt[512], bin[4096];
    at("ro", mnt, sizeof mnt);
    mkdir(mnt, 0755);
    assert_non_null(realpath(prog_bin(), bin));
    snprintf(cmd, sizeof cmd,
             "unshare -r -m sh -c 'mount -t tmpfs -o size=64k tmpfs %s && mount -o remount,ro %s || exit 97; "
             "%s figures --only " FIG " --out %s/gallery 2>%s/err.txt; echo $? >%s/rc.txt; ls -A %s >%s/left.txt'",
             mnt, mnt, bin, mnt, dir, dir, mnt, dir);
    int st = system(cmd);
    if (st != 0) {   /* no user namespaces here (a container that forbids them): the case cannot be set up */
        print_message("  could not mount a read-only tmpfs in a private namespace (unshare -r -m; status %d): "
                      "skipped\n", st);
        rmdir(mnt);
        skip();
    }
    assert_true(holds("rc.txt", "1\n"));
    assert_true(holds("left.txt", ""));
    assert_int_equal(count_in("err.txt", "ro/gallery: cannot create the directory: Read-only file system"), 1);
    /* the folder exists and is read-only: the write check, before any work */
    snprintf(cmd, sizeof cmd,
             "unshare -r -m sh -c 'mount -t tmpfs -o size=64k tmpfs %s && mkdir %s/gallery && mount -o remount,ro %s "
             "|| exit 97; %s figures --only " FIG " --out %s/gallery 2>%s/err.txt; echo $? >%s/rc.txt'",
             mnt, mnt, mnt, bin, mnt, dir, dir);
    st = system(cmd);
    if (st != 0) fail_msg("could not mount a read-only tmpfs (status %d)", st);
    assert_true(holds("rc.txt", "1\n"));
    assert_int_equal(count_in("err.txt", "ro/gallery/index.html: cannot create a file in the folder "), 1);
    assert_int_equal(count_in("err.txt", "ro/gallery: Read-only file system"), 1);
    assert_int_equal(count_in("err.txt", "[ 1/1]"), 0);
    rmdir(mnt);
}

/* A folder that holds other files: they are left as they were, index.html is replaced whole; a FIFO, a link
 * or a folder at index.html is refused before any rendering and left as it was; a link at a figure's name
 * fails that figure (named), and is left as it was.  No temporary is left, and none has a predictable name. */
static void test_figures_out_busy_folder(void **state)
{
    (void)state;
    char p[512];
    assert_int_equal(mkdir(at("gal", p, sizeof p), 0755), 0);
    assert_true(prog_write_text(dir, "gal/keep.txt", "keep\n"));
    assert_true(prog_write_text(dir, "gal/index.html", "old gallery\n"));
    assert_int_equal(run("figures --only " FIG " --out gal"), 0);
    assert_true(holds("gal/keep.txt", "keep\n"));
    assert_true(complete_gallery("gal/index.html"));
    assert_int_equal(prog_entries_with(at("gal", p, sizeof p), ".tmp"), 0);

    assert_int_equal(mkdir(at("g2", p, sizeof p), 0755), 0);
    assert_int_equal(mkfifo(at("g2/index.html", p, sizeof p), 0600), 0);
    expect(run("figures --only " FIG " --out g2"), 1, "g2/index.html: is a FIFO; instess writes only regular files");
    assert_int_equal(kind("g2/index.html"), 'p');
    assert_int_equal(kind("g2/" FIG ".png"), 0);   /* claimed before any work */
    unlink(at("g2/index.html", p, sizeof p));
    assert_true(prog_write_text(dir, "outside.html", "outside\n"));
    assert_int_equal(symlink("../outside.html", at("g2/index.html", p, sizeof p)), 0);
    expect(run("figures --only " FIG " --out g2"), 1, "g2/index.html: is a symbolic link");
    assert_true(holds("outside.html", "outside\n"));
    unlink(at("g2/index.html", p, sizeof p));
    assert_int_equal(mkdir(at("g2/index.html", p, sizeof p), 0755), 0);
    expect(run("figures --only " FIG " --out g2"), 1, "g2/index.html: is a directory");
    rmdir(at("g2/index.html", p, sizeof p));

    assert_int_equal(symlink("../outside.html", at("g2/" FIG ".png", p, sizeof p)), 0);
    expect(run("figures --only " FIG ",fig-1.1.3 --out g2"), 1, FIG ": ");
    assert_non_null(strstr(err_buf, "is a symbolic link"));
    assert_true(holds("outside.html", "outside\n"));
    assert_int_equal(kind("g2/" FIG ".png"), 'l');
    assert_int_equal(kind("g2/fig-1.1.3.png"), 'f');   /* the other figure is written */
    assert_true(complete_gallery("g2/index.html"));
    assert_int_equal(prog_entries_with(at("g2", p, sizeof p), ".tmp"), 0);
}

/* --only: an unknown id and empty ids are usage errors (exit 2); an id named twice is rendered once. */
static void test_figures_only_ids(void **state)
{
    (void)state;
    expect(run("figures --only nope --out o1"), 2, "unknown figure id 'nope'");
    expect(run("figures --only " FIG ",nope --out o1"), 2, "unknown figure id 'nope'");
    const char *empty[] = {"," FIG, FIG ",", FIG ",,fig-1.1.3", ","};
    for (size_t k = 0; k < sizeof empty / sizeof empty[0]; k++)
        expect(run("figures --only '%s' --out o1", empty[k]), 2, "--only has an empty id in '");
    expect(run("figures --only '' --out o1"), 2, "--only needs figure ids");
    assert_int_equal(kind("o1"), 0);
    assert_int_equal(run("figures --only " FIG "," FIG " --out o2"), 0);
    assert_int_equal(count_in("o2/index.html", "<figure id=\"" FIG "\""), 1);
    assert_int_equal(count_in("err.txt", "[ 1/1]"), 1);   /* one figure rendered */
}

/* Whether err_buf holds a control byte other than the newline. */
static bool control_bytes_in_err(void)
{
    for (const unsigned char *c = (const unsigned char *)err_buf; *c; c++)
        if ((*c < 0x20 && *c != '\n') || *c == 0x7f) return true;
    return false;
}

/* Values and file names with control bytes or an escape sequence, echoed in a message: shown with '?' in their
 * place, so that no option value or file name puts an escape sequence on the user's terminal (an option's value
 * and compare's file names went out raw). */
static void test_messages_without_control_bytes(void **state)
{
    (void)state;
    static const struct { const char *args, *what; int code; } cases[] = {
        {"--level \"$(printf '\\033[2J')\" -o x.png", "--level must be a number in 1..256: ?[2J", 2},
        {"--size \"$(printf '8x8\\007')\" -o x.png", "?", 2},
        {"\"$(printf 'm\\033]0;t\\007.obj')\" -o x.png", "m?]0;t?.obj", 1},
        {"--bogus-\"$(printf '\\033')\" -o x.png", "--bogus-?", 2},
        {"compare \"$(printf 'a\\033[1m.png')\" b.png", "a?[1m.png", 4},
        {"compare a.png b.png --diff \"$(printf 'd\\033.png')\" --fail \"$(printf '\\033')\"", "?", 2},
        {"compare a.png b.png --diff \"$(printf 'no\\033/d.png')\"", "no?/d.png", 4},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        int rc = run("%s", cases[k].args);
        if (rc != cases[k].code || !strstr(err_buf, cases[k].what) || control_bytes_in_err())
            fail_msg("%s: exit %d (want %d, \"%s\", no control byte):\n%s", cases[k].args, rc, cases[k].code,
                     cases[k].what, err_buf);
    }
    assert_int_equal(kind("x.png"), 0);
}

/* ------------------------------------------------------------ stdout, --stats json, the input mesh */

/* A failed write to stdout -- /dev/full, a closed descriptor -- is an error with a message, for every command
 * that prints there (compare: exit 4); --stats json that cannot be written fails the run with nothing written. */
static void test_stdout_failures(void **state)
{
    (void)state;
    const char *cmds[] = {"--help", "--version", "--man", "figures --list", "figures --help", "compare --help",
                          "view --help", "compare a.png a.png", "smoothness --samples 2 --mesh tetrahedron"};
    const char *sinks[] = {"/dev/full", "&-"};
    for (size_t s = 0; s < 2; s++)
        for (size_t k = 0; k < sizeof cmds / sizeof cmds[0]; k++) {
            int rc = run_to(sinks[s], "%s", cmds[k]);
            int want = strncmp(cmds[k], "compare", 7) == 0 ? 4 : 1;   /* compare's code for what cannot be written */
            if (rc != want || !strstr(err_buf, "cannot write to standard output: "))
                fail_msg("%s >%s: exit %d (want %d): %s", cmds[k], sinks[s], rc, want, err_buf);
        }
    assert_int_equal(run_to("/dev/full", "compare a.png b.png"), 1);   /* its verdict stands */
    assert_non_null(strstr(err_buf, "cannot write to standard output: No space left on device"));
    for (size_t s = 0; s < 2; s++) {
        int rc = run_to(sinks[s], "--size 16x16 -q --stats json -o s.png");
        expect(rc, 1, " (the statistics of --stats json); nothing written");
        assert_non_null(strstr(err_buf, "instess: cannot write to standard output: "));
        assert_int_equal(kind("s.png"), 0);
        assert_int_equal(prog_entries_with(dir, ".instess-"), 0);
    }
    assert_int_equal(run("--size 16x16 -q --stats json -o s.png"), 0);
    assert_int_equal(kind("s.png"), 'f');
}

/* Whether the n bytes at s are well-formed UTF-8: each sequence decoded to its code point, which must need
 * exactly that many bytes (no overlong form), not be a UTF-16 surrogate, and be at most U+10FFFF. */
static bool valid_utf8(const unsigned char *s, size_t n)
{
    for (size_t k = 0; k < n;) {
        int len = s[k] < 0x80 ? 1 : (s[k] >> 5) == 6 ? 2 : (s[k] >> 4) == 14 ? 3 : (s[k] >> 3) == 30 ? 4 : 0;
        if (!len || k + (size_t)len > n) return false;
        uint32_t cp = len == 1 ? s[k] : s[k] & (0x7fu >> len);
        for (int j = 1; j < len; j++) {
            if ((s[k + j] & 0xc0) != 0x80) return false;
            cp = (cp << 6) | (s[k + j] & 0x3fu);
        }
        static const uint32_t least[5] = {0, 0, 0x80, 0x800, 0x10000};
        if (cp < least[len] || (cp >= 0xd800 && cp <= 0xdfff) || cp > 0x10ffff) return false;
        k += (size_t)len;
    }
    return true;
}

/* --stats json on mesh and image names that are not UTF-8 (overlong forms, a surrogate, a code point beyond
 * U+10FFFF, stray bytes) or hold DEL: the output is well-formed UTF-8 with no raw control byte, each bad byte as
 * \ufffd; a good name (é) is kept as it is. */
static void test_stats_json_utf8(void **state)
{
    (void)state;
    static const char cube[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
    const char *names[] = {"\xc0\xaf", "\xe0\x80\x80", "\xed\xa0\x80", "\xf4\x90\x80\x80", "\xff\xfe", "\x7f",
                           "\xc3\xa9", "\xe2\x82", "\xf0\x9f\x98"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
        char mesh[64], png[64];
        snprintf(mesh, sizeof mesh, "m%s.obj", names[k]);
        snprintf(png, sizeof png, "o%s.png", names[k]);
        assert_true(prog_write_text(dir, mesh, cube));
        int rc = run("--mesh '%s' --size 16x16 -q --stats json -o '%s'", mesh, png);
        if (rc != 0) fail_msg("name %zu: exit %d: %s", k, rc, err_buf);
        size_t n = strlen(out_buf);
        if (!valid_utf8((const unsigned char *)out_buf, n)) fail_msg("name %zu: not UTF-8: %s", k, out_buf);
        for (size_t i = 0; i + 1 < n; i++)
            if ((unsigned char)out_buf[i] < 0x20 || out_buf[i] == 0x7f) fail_msg("name %zu: raw byte 0x%02x", k, out_buf[i]);
        assert_true(out_buf[0] == '{' && out_buf[n - 2] == '}' && out_buf[n - 1] == '\n');
        bool good = k == 6;
        assert_true(good == (strstr(out_buf, "\\ufffd") == NULL && strstr(out_buf, "\\u007f") == NULL));
        if (good) assert_non_null(strstr(out_buf, "\"o\xc3\xa9.png\""));
    }
}

/* -o or --export-obj naming the input mesh -- the same name, another spelling, a hard link, a symbolic link to
 * it -- is a usage error (exit 2) and the mesh keeps its bytes. */
static void test_output_names_the_mesh(void **state)
{
    (void)state;
    static const char tet[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
    char p[512], q[512];
    assert_true(prog_write_text(dir, "tet.obj", tet));
    assert_int_equal(mkdir(at("sub", p, sizeof p), 0755), 0);
    assert_int_equal(link(at("tet.obj", p, sizeof p), at("hard.obj", q, sizeof q)), 0);
    assert_int_equal(symlink("tet.obj", at("soft.obj", p, sizeof p)), 0);
    const char *exports[] = {"tet.obj", "./tet.obj", "sub/../tet.obj", "hard.obj", "soft.obj"};
    for (size_t k = 0; k < sizeof exports / sizeof exports[0]; k++) {
        expect(run("--mesh tet.obj --size 16x16 -q -o t.png --export-obj %s", exports[k]), 1,
               ": is the input mesh; instess will not replace its input");
        assert_true(holds("tet.obj", tet));
    }
    expect(run("--mesh soft.obj --size 16x16 -q -o t.png --export-obj tet.obj"), 1, "tet.obj: is the input mesh");
    assert_true(prog_write_text(dir, "mesh.png", "not a mesh\n"));
    expect(run("--mesh mesh.png --size 16x16 -q -o ./mesh.png"), 1, "./mesh.png: is the input mesh");
    assert_true(holds("mesh.png", "not a mesh\n"));
    assert_int_equal(kind("t.png"), 0);
    assert_int_equal(run("--mesh tet.obj --size 16x16 -q -o t.png --export-obj out.obj"), 0);
    assert_true(holds("tet.obj", tet));
}

/* ------------------------------------------------------------ concurrency */

/* Start `instess` with args in dir (stdout and stderr discarded); its pid. */
static pid_t spawn(const char *const *args)
{
    pid_t pid = fork();
    if (pid != 0) return pid;
    char bin[4096];
    if (!realpath(prog_bin(), bin) || chdir(dir) != 0) _exit(126);
    if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) _exit(126);
    const char *argv[40] = {bin};
    for (int k = 0; args[k] && k < 38; k++) argv[k + 1] = args[k];
    execv(bin, (char *const *)argv);
    _exit(127);
}

/* Wait for n processes; assert each exited with `code`. */
static void wait_all(const pid_t *pids, int n, int code)
{
    for (int k = 0; k < n; k++) {
        int st;
        assert_int_equal(waitpid(pids[k], &st, 0), pids[k]);
        if (!WIFEXITED(st) || WEXITSTATUS(st) != code) fail_msg("process %d: status 0x%x, want exit %d", k, st, code);
    }
}

/* Four processes rendering into one image and one export at once, three rounds: each target ends as one whole
 * file of the four (the same bytes as that run alone), no temporary is left. */
static void test_concurrent_render_and_export(void **state)
{
    (void)state;
    const char *levels[] = {"1", "2", "3", "4"};
    for (int k = 0; k < 4; k++)
        assert_int_equal(run("--mesh tetrahedron --level %s --size 32x32 -q -o ref%d.png --export-obj ref%d.obj",
                             levels[k], k, k), 0);
    for (int round = 0; round < 3; round++) {
        pid_t pids[4];
        for (int k = 0; k < 4; k++) {
            const char *const args[] = {"--mesh", "tetrahedron", "--level", levels[k], "--size", "32x32", "-q", "-o",
                                        "same.png", "--export-obj", "same.obj", NULL};
            pids[k] = spawn(args);
        }
        wait_all(pids, 4, 0);
        int png = 0, obj = 0;
        char a[512], b[512];
        for (int k = 0; k < 4; k++) {
            char r[32];
            snprintf(r, sizeof r, "ref%d.png", k);
            png += prog_same_bytes(at("same.png", a, sizeof a), at(r, b, sizeof b));
            snprintf(r, sizeof r, "ref%d.obj", k);
            obj += prog_same_bytes(at("same.obj", a, sizeof a), at(r, b, sizeof b));
        }
        assert_int_equal(png, 1);
        assert_int_equal(obj, 1);
        assert_int_equal(prog_entries_with(dir, ".instess-"), 0);
    }
}

/* Four `figures` runs into one folder and four `compare --diff` runs onto one diff image at once: the gallery
 * and the figure are whole files, the diff image is the one a single run writes; no temporary is left. */
static void test_concurrent_figures_and_diffs(void **state)
{
    (void)state;
    char p[512], q[512];
    assert_int_equal(run("compare a.png b.png --diff ref-diff.png"), 1);
    for (int round = 0; round < 3; round++) {
        pid_t pids[8];
        for (int k = 0; k < 4; k++) {
            const char *const fig[] = {"figures", "--only", FIG, "--out", "shared", "--threads", "1", NULL};
            const char *const cmp[] = {"compare", "a.png", "b.png", "--diff", "diff.png", NULL};
            pids[2 * k] = spawn(fig);
            pids[2 * k + 1] = spawn(cmp);
        }
        for (int k = 0; k < 8; k++) wait_all(&pids[k], 1, k % 2 ? 1 : 0);
        assert_true(complete_gallery("shared/index.html"));
        assert_int_equal(count_in("shared/index.html", "<figure id="), 1);
        is_image img;
        char err[512];
        assert_int_equal(image_read(&img, at("shared/" FIG ".png", p, sizeof p), err, sizeof err), 0);
        image_free(&img);
        assert_true(prog_same_bytes(at("diff.png", p, sizeof p), at("ref-diff.png", q, sizeof q)));
        assert_int_equal(prog_entries_with(dir, ".instess-"), 0);
        assert_int_equal(prog_entries_with(at("shared", p, sizeof p), ".instess-"), 0);
    }
}

/* The OBJ text of a sphere-like mesh of n x n quads (2 n^2 triangles) into a malloc'ed string. */
static char *grid_obj(int n, size_t *len)
{
    size_t cap = (size_t)(n + 1) * (n + 1) * 48 + (size_t)n * n * 64 + 64, k = 0;
    char *t = malloc(cap);
    for (int i = 0; i <= n; i++)
        for (int j = 0; j <= n; j++)
            k += (size_t)snprintf(t + k, cap - k, "v %g %g %g\n", (double)i / n, (double)j / n,
                                  0.1 * ((i * 7 + j * 3) % 5));
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            int a = i * (n + 1) + j + 1, b = a + 1, c = a + n + 1, d = c + 1;
            k += (size_t)snprintf(t + k, cap - k, "f %d %d %d\nf %d %d %d\n", a, c, b, b, c, d);
        }
    *len = k;
    return t;
}

/* A mesh rewritten in place (truncated, then written in pieces) by another process, over and over, while the
 * program reads it 16 times: every run ends with an image (exit 0, a whole file) or an error naming the mesh
 * (exit 1) -- never a crash, a hang, another exit code or a partial image. */
static void test_mesh_rewritten_while_read(void **state)
{
    (void)state;
    size_t n_small, n_big;
    char *small = grid_obj(2, &n_small), *big = grid_obj(60, &n_big);
    char path[512], stop[512], out[512];
    at("moving.obj", path, sizeof path);
    at("stop", stop, sizeof stop);
    assert_true(prog_write_bytes(dir, "moving.obj", big, n_big));
    pid_t parent = getpid(), writer = fork();
    assert_true(writer >= 0);
    if (writer == 0) {   /* until told to stop, or the test is gone (an assertion left it) */
        for (long it = 0; it < 2000000 && access(stop, F_OK) != 0 && getppid() == parent; it++) {
            const char *t = it % 2 ? small : big;
            size_t n = it % 2 ? n_small : n_big;
            FILE *f = fopen(path, "w");   /* truncates: a reader may see 0 bytes, a part, or the whole */
            if (!f) continue;
            for (size_t k = 0; k < n; k += n / 3 + 1) fwrite(t + k, 1, n - k < n / 3 + 1 ? n - k : n / 3 + 1, f), fflush(f);
            fclose(f);
            if (it % 2) nanosleep(&(struct timespec){0, 5000000}, NULL);   /* the small mesh stays whole a while */
        }
        _exit(0);
    }
    int images = 0, errors = 0;
    for (int r = 0; r < 16; r++) {
        int rc = run("--mesh moving.obj --size 32x32 -q -o out.png");
        if (rc == 0) {
            images++;
            is_image img;
            char err[512];
            assert_int_equal(image_read(&img, at("out.png", out, sizeof out), err, sizeof err), 0);
            image_free(&img);
        } else if (rc == 1 && strstr(err_buf, "moving.obj")) {
            errors++;
        } else {
            prog_write_text(dir, "stop", "");
            fail_msg("run %d: exit %d: %s", r, rc, err_buf);
        }
    }
    assert_true(prog_write_text(dir, "stop", ""));
    int st;
    assert_int_equal(waitpid(writer, &st, 0), writer);
    print_message("  mesh rewritten while read: %d images, %d errors naming the mesh\n", images, errors);
    assert_int_equal(images + errors, 16);
    assert_int_equal(prog_entries_with(dir, ".instess-"), 0);
    free(small);
    free(big);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_figures_out_not_a_folder),
        cmocka_unit_test(test_figures_out_read_only),
        cmocka_unit_test(test_figures_out_busy_folder),
        cmocka_unit_test(test_figures_only_ids),
        cmocka_unit_test(test_messages_without_control_bytes),
        cmocka_unit_test(test_stdout_failures),
        cmocka_unit_test(test_stats_json_utf8),
        cmocka_unit_test(test_output_names_the_mesh),
        cmocka_unit_test(test_concurrent_render_and_export),
        cmocka_unit_test(test_concurrent_figures_and_diffs),
        cmocka_unit_test(test_mesh_rewritten_while_read),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
