/* tests/test_outputs.c -- the files a run writes (cli/run/output.c, docs/robustness.md "Outputs"), through the real
 * program: all outputs of a run succeed together or none is left; only regular files are replaced; names up
 * to the filesystem's limit; a full or read-only filesystem, `ulimit -f`, `ulimit -v` and signals in the write
 * window give an error or a clean death, never a partial file or a damaged earlier one; concurrent writers of
 * one target leave one complete image. */
#define _GNU_SOURCE /* memmem */
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
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "../core/core.h"
#include "util/prog.h"

int setenv(const char *name, const char *value, int overwrite);  /* POSIX; hidden by glibc's strict modes */
int symlink(const char *target, const char *linkpath);
int mkfifo(const char *path, mode_t mode);

static char dir[256];

/* A small render into dir/name; asserts success. */
static void render_ok(const char *name, const char *extra)
{
    char p[512];
    const char *err;
    int rc = prog_run(dir, &err, "", "--mesh cube --level 2 --size 48x48 --msaa 1 -q %s -o '%s'", extra,
                      prog_path(dir, name, p, sizeof p));
    if (rc != 0) fail_msg("render of %s failed (exit %d): %s", name, rc, err);
}

/* Copy dir/from to dir/to byte for byte. */
static void copy_file(const char *from, const char *to)
{
    char p[512];
    size_t n;
    unsigned char *b = prog_slurp(prog_path(dir, from, p, sizeof p), &n);
    assert_non_null(b);
    assert_true(prog_write_bytes(dir, to, b, n));
    free(b);
}

/* Whether dir/a and dir/b hold the same bytes. */
static bool same(const char *a, const char *b)
{
    char pa[512], pb[512];
    return prog_same_bytes(prog_path(dir, a, pa, sizeof pa), prog_path(dir, b, pb, sizeof pb));
}

/* Expect exit rc, a message holding `what`, and no temporary file left. */
static void expect(int got, int rc, const char *err, const char *what)
{
    print_message("  exit %d: %s", got, err);
    if (got != rc || !strstr(err, what)) fail_msg("wanted exit %d and '%s', got exit %d: %s", rc, what, got, err);
    assert_int_equal(prog_entries_with(dir, ".instess-"), 0);
}

/* An export that cannot be written fails the run before any work: the image is not written either, and an
 * earlier image at that path keeps its bytes (issue: `--export-obj no-such-dir/a.obj -o y.png` left y.png). */
static void test_failed_export_leaves_no_image(void **state)
{
    (void)state;
    const char *err;
    char y[512], keep[512], e[512];
    prog_path(dir, "y.png", y, sizeof y);
    int rc = prog_run(dir, &err, "", "--mesh cube -q --size 32x32 --export-obj '%s/no-such-dir/a.obj' -o '%s'", dir, y);
    expect(rc, 1, err, "no-such-dir/a.obj");
    assert_false(prog_exists(dir, "y.png"));
    render_ok("keep.png", "");
    copy_file("keep.png", "saved.png");
    /* the export's target is a directory: refused, the earlier image untouched */
    mkdir(prog_path(dir, "adir.obj", e, sizeof e), 0755);
    rc = prog_run(dir, &err, "", "--mesh cube -q --size 40x40 --yaw 10 --export-obj '%s' -o '%s'", e,
                  prog_path(dir, "keep.png", keep, sizeof keep));
    expect(rc, 1, err, "is a directory");
    assert_true(same("keep.png", "saved.png"));
    rmdir(e);
}

/* The image and the export naming one file is a usage error and writes nothing: the export must end in .obj
 * and the image in .png or .exr, so one name cannot be both; an existing file can (a hard link a.obj of a.png,
 * or a.obj reached through a linked folder), and that is found before any output is claimed. */
static void test_same_file_twice_is_usage_error(void **state)
{
    (void)state;
    const char *err;
    char sub[512], alias[512], a[512], b[512];
    mkdir(prog_path(dir, "sub", sub, sizeof sub), 0755);
    assert_int_equal(symlink(sub, prog_path(dir, "alias", alias, sizeof alias)), 0);
    int rc = prog_run(dir, &err, "", "--mesh cube -q --size 16x16 -o '%s/a.png' --export-obj '%s/a.png'", dir, dir);
    expect(rc, 2, err, "its name must end in .obj");
    assert_true(prog_write_text(dir, "sub/b.png", "earlier\n"));
    const char *spellings[][2] = {{"sub/b.png", "sub/c.obj"}, {"sub/b.png", "alias/c.obj"}};
    assert_int_equal(link(prog_path(dir, "sub/b.png", a, sizeof a), prog_path(dir, "sub/c.obj", b, sizeof b)), 0);
    for (int k = 0; k < 2; k++) {
        rc = prog_run(dir, &err, "", "--mesh cube -q --size 16x16 -o '%s/%s' --export-obj '%s/%s'", dir,
                      spellings[k][0], dir, spellings[k][1]);
        expect(rc, 2, err, "name the same file");
        assert_false(prog_exists(dir, "a.png"));
        assert_int_equal(prog_entries_with(sub, NULL), 2);
        size_t n;
        unsigned char *bytes = prog_slurp(a, &n);
        assert_true(bytes && n == 8 && !memcmp(bytes, "earlier\n", 8));
        free(bytes);
    }
    unlink(a), unlink(b);
    unlink(alias);
    rmdir(sub);
}

/* Targets that are not regular files are refused and left as they were: a link to a file, a dangling link,
 * a link loop, a directory, a FIFO (without blocking), a device. */
static void test_only_regular_files_replaced(void **state)
{
    (void)state;
    const char *err;
    char p[512], q[512];
    render_ok("victim.png", "");
    copy_file("victim.png", "victim-saved.png");
    assert_int_equal(symlink(prog_path(dir, "victim.png", q, sizeof q), prog_path(dir, "link.png", p, sizeof p)), 0);
    assert_int_equal(symlink(prog_path(dir, "nowhere.png", q, sizeof q), prog_path(dir, "dangling.png", p, sizeof p)), 0);
    assert_int_equal(symlink("loop.png", prog_path(dir, "loop.png", p, sizeof p)), 0);
    assert_int_equal(mkfifo(prog_path(dir, "fifo.png", p, sizeof p), 0644), 0);
    mkdir(prog_path(dir, "folder.png", p, sizeof p), 0755);
    const struct { const char *name, *why; } cases[] = {
        {"link.png", "is a symbolic link"}, {"dangling.png", "is a symbolic link"}, {"loop.png", "is a symbolic link"},
        {"fifo.png", "is a FIFO"}, {"folder.png", "is a directory"}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        int rc = prog_run(dir, &err, "timeout 20", "--mesh cube -q --size 16x16 -o '%s'",
                          prog_path(dir, cases[k].name, p, sizeof p));
        expect(rc, 1, err, cases[k].why);
        assert_non_null(strstr(err, cases[k].name));
    }
    assert_true(same("victim.png", "victim-saved.png"));
    assert_false(prog_exists(dir, "nowhere.png"));
    struct stat st;
    assert_int_equal(lstat(prog_path(dir, "link.png", p, sizeof p), &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    /* an export that is not named .obj is a usage error before any output is looked at */
    int rc = prog_run(dir, &err, "", "--mesh cube -q --size 16x16 -o /dev/null.png --export-obj /dev/null");
    expect(rc, 2, err, "--export-obj writes OBJ: its name must end in .obj");
    const char *names[] = {"link.png", "dangling.png", "loop.png", "fifo.png"};
    for (int k = 0; k < 4; k++) unlink(prog_path(dir, names[k], p, sizeof p));
    rmdir(prog_path(dir, "folder.png", p, sizeof p));
}

/* A file name of 255 bytes (Linux's NAME_MAX) is written; one of 256 is refused before any work. */
static void test_long_names(void **state)
{
    (void)state;
    char name[300];
    const char *err;
    memset(name, 'n', 251);
    strcpy(name + 251, ".png");
    render_ok(name, "");
    assert_true(prog_exists(dir, name));
    char p[600];
    unlink(prog_path(dir, name, p, sizeof p));
    memset(name, 'n', 252);
    strcpy(name + 252, ".png");
    int rc = prog_run(dir, &err, "", "--mesh cube -q --size 16x16 -o '%s'", prog_path(dir, name, p, sizeof p));
    expect(rc, 1, err, "longer than the folder's limit of 255");
    assert_false(prog_exists(dir, name));
}

/* `ulimit -f` below the image's size: exit 1 naming the limit (SIGXFSZ is ignored, EFBIG is an error), no
 * temporary file, the earlier image intact.  sh's ulimit -f counts 512-byte blocks: 4 KiB here. */
static void test_file_size_limit(void **state)
{
    (void)state;
    const char *err;
    char keep[512];
    render_ok("keep.png", "");
    copy_file("keep.png", "saved.png");
    int rc = prog_run(dir, &err, "ulimit -f 8;", "--mesh sphere --patch smooth -q --size 256x256 -o '%s'",
                      prog_path(dir, "keep.png", keep, sizeof keep));
    expect(rc, 1, err, "the file size limit (ulimit -f) was reached");
    assert_true(same("keep.png", "saved.png"));
}

/* Run `instess ARGS` inside a private mount namespace (unshare: no root needed where user namespaces are
 * allowed) with a tmpfs of `kib` KiB at dir/mnt, mounted read-only when ro; `seed` is written into it first.
 * Leaves the exit code in dir/rc.txt and the tmpfs's listing afterwards in dir/left.txt; returns the shell's
 * status (0 when the mount worked). */
static int run_in_tmpfs(int kib, bool ro, const char *seed, const char *args, const char **err)
{
    char cmd[3000], mnt[512];
    prog_path(dir, "mnt", mnt, sizeof mnt);
    mkdir(mnt, 0755);
    snprintf(cmd, sizeof cmd,
             "unshare -r -m sh -c 'mount -t tmpfs -o size=%dk tmpfs %s || exit 97; %s %s mount -o remount,ro %s || exit 98; "
             "%s %s 2>%s/stderr2.txt >/dev/null; echo $? >%s/rc.txt; ls -A %s >%s/left.txt'",
             kib, mnt, seed, ro ? "" : "true ||", mnt, prog_bin(), args, dir, dir, mnt, dir);
    int st = system(cmd);
    char p[512];
    size_t n = 0;
    static char buf[4096];
    unsigned char *b = prog_slurp(prog_path(dir, "stderr2.txt", p, sizeof p), &n);
    n = b ? (n < sizeof buf - 1 ? n : sizeof buf - 1) : 0;
    if (b) memcpy(buf, b, n);
    buf[n] = 0;
    free(b);
    *err = buf;
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* The contents of dir/name as an integer (the exit code a tmpfs run left), or -1. */
static int read_int(const char *name)
{
    char p[512];
    size_t n;
    char *b = (char *)prog_slurp(prog_path(dir, name, p, sizeof p), &n);
    int v = b && n ? atoi(b) : -1;
    free(b);
    return v;
}

/* A full filesystem (ENOSPC) and a read-only one (EROFS): exit 1 naming the reason, nothing left in them. */
static void test_full_and_read_only_filesystems(void **state)
{
    (void)state;
    const char *err;
    char args[1200];
    snprintf(args, sizeof args, "--mesh sphere --patch smooth -q --size 512x512 -o %s/mnt/a.png --export-obj %s/mnt/a.obj",
             dir, dir);
    int st = run_in_tmpfs(16, false, "", args, &err);
    if (st != 0) fail_msg("could not mount a tmpfs in a private namespace (unshare -r -m; status %d)", st);
    print_message("  full: exit %d: %s", read_int("rc.txt"), err);
    assert_int_equal(read_int("rc.txt"), 1);
    assert_non_null(strstr(err, "No space left on device"));
    char p[512];
    size_t n = 1;
    free(prog_slurp(prog_path(dir, "left.txt", p, sizeof p), &n));
    assert_int_equal(n, 0);  /* nothing left in the full filesystem */
    snprintf(args, sizeof args, "--mesh cube -q --size 16x16 -o %s/mnt/b.png", dir);
    st = run_in_tmpfs(64, true, "", args, &err);
    if (st != 0) fail_msg("could not mount a read-only tmpfs (status %d)", st);
    print_message("  read-only: exit %d: %s", read_int("rc.txt"), err);
    assert_int_equal(read_int("rc.txt"), 1);
    assert_non_null(strstr(err, "Read-only file system"));
    n = 1;
    free(prog_slurp(prog_path(dir, "left.txt", p, sizeof p), &n));
    assert_int_equal(n, 0);
    rmdir(prog_path(dir, "mnt", p, sizeof p));
}

/* Start `instess ARGS...` with env (NAME=VALUE or NULL) set and core dumps off; its pid. */
/* True if the file at path holds the bytes of s (a string constant compiled into a program). */
static bool file_holds(const char *path, const char *s)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    size_t n = strlen(s), have = 0, cap = 1 << 20;
    char *buf = malloc(cap);
    assert_non_null(buf);
    bool found = false;
    for (size_t r; !found && (r = fread(buf + have, 1, cap - have, f)) > 0;) {
        have += r;
        found = memmem(buf, have, s, n) != NULL;
        if (have > n) memmove(buf, buf + have - n, n), have = n;   /* keep a tail that may start a match */
    }
    fclose(f);
    free(buf);
    return found;
}

/* The test hook is in the test build only: the program proper does not even hold the variable's name. */
static void test_hook_only_in_test_build(void **state)
{
    (void)state;
    assert_false(file_holds(prog_bin(), "INSTESS_TEST_WRITE_DELAY_MS"));
    assert_true(file_holds(prog_hooks_bin(), "INSTESS_TEST_WRITE_DELAY_MS"));
}

/* Run the program (with env "NAME=VALUE" set, the test build with the hooks) on args, without waiting. */
static pid_t spawn(const char *env, const char *const *args)
{
    pid_t pid = fork();
    if (pid != 0) return pid;
    struct rlimit no_core = {0, 0};
    setrlimit(RLIMIT_CORE, &no_core);
    if (env) {
        char name[64];
        const char *eq = strchr(env, '=');
        snprintf(name, sizeof name, "%.*s", (int)(eq - env), env);
        setenv(name, eq + 1, 1);
    }
    const char *bin = env ? prog_hooks_bin() : prog_bin();
    const char *argv[32] = {bin};
    for (int k = 0; args[k] && k < 30; k++) argv[k + 1] = args[k];
    execv(bin, (char *const *)argv);
    _exit(127);
}

/* Sleep ms milliseconds. */
static void sleep_ms(long ms)
{
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}

/* SIGQUIT and SIGXCPU (besides SIGTERM, SIGINT, SIGHUP, tested in test_robustness) while every temporary is
 * complete and none renamed: the program dies of the signal, no temporary remains, the earlier image and
 * export keep their bytes. */
static void test_signals_in_write_window(void **state)
{
    (void)state;
    char keep[512], obj[512];
    render_ok("keep.png", "");
    copy_file("keep.png", "saved.png");
    assert_true(prog_write_text(dir, "keep.obj", "# earlier export\n"));
    const int sigs[] = {SIGQUIT, SIGXCPU};
    for (int k = 0; k < 2; k++) {
        const char *const args[] = {"--mesh", "cube", "--size", "64x64", "-q", "-o", prog_path(dir, "keep.png", keep, sizeof keep),
                                    "--export-obj", prog_path(dir, "keep.obj", obj, sizeof obj), NULL};
        pid_t pid = spawn("INSTESS_TEST_WRITE_DELAY_MS=20000", args);
        assert_true(pid > 0);
        int seen = 0;
        for (int t = 0; t < 2000 && seen < 2; t++, sleep_ms(10)) seen = prog_entries_with(dir, ".instess-");
        assert_int_equal(seen, 2);  /* both temporaries complete, none renamed */
        sleep_ms(50);
        assert_int_equal(kill(pid, sigs[k]), 0);
        int st;
        assert_int_equal(waitpid(pid, &st, 0), pid);
        print_message("  signal %d in the write window: status 0x%x, %d temporaries left\n", sigs[k], st,
                      prog_entries_with(dir, ".instess-"));
        assert_true(WIFSIGNALED(st) && WTERMSIG(st) == sigs[k]);
        assert_int_equal(prog_entries_with(dir, ".instess-"), 0);
        assert_true(same("keep.png", "saved.png"));
        size_t n;
        char *b = (char *)prog_slurp(obj, &n);
        assert_true(b && n == 17 && !memcmp(b, "# earlier export\n", 17));
        free(b);
    }
}


/* Whether dir/a and dir/b decode to the same pixels. */
static bool same_pixels(const char *a, const char *b)
{
    char pa[512], pb[512];
    snprintf(pa, sizeof pa, "%s/%s", dir, a);
    snprintf(pb, sizeof pb, "%s/%s", dir, b);
    return prog_same_pixels(pa, pb);
}

/* Four processes writing one target at once: it ends as one complete image of the four, no temporary left. */
static void test_concurrent_writers(void **state)
{
    (void)state;
    const char *yaws[] = {"0", "30", "60", "90"};
    char refs[4][32], out[512];
    for (int k = 0; k < 4; k++) {
        snprintf(refs[k], sizeof refs[k], "ref%d.png", k);
        char extra[64];
        snprintf(extra, sizeof extra, "--yaw %s", yaws[k]);
        render_ok(refs[k], extra);
    }
    for (int round = 0; round < 3; round++) {
        pid_t pids[4];
        for (int k = 0; k < 4; k++) {
            const char *const args[] = {"--mesh", "cube", "--level", "2", "--size", "48x48", "--msaa", "1", "--yaw",
                                        yaws[k], "-q", "-o", prog_path(dir, "out.png", out, sizeof out), NULL};
            pids[k] = spawn(NULL, args);
        }
        for (int k = 0; k < 4; k++) {
            int st;
            assert_int_equal(waitpid(pids[k], &st, 0), pids[k]);
            assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
        }
        int matches = 0;
        for (int k = 0; k < 4; k++) matches += same_pixels("out.png", refs[k]);
        assert_int_equal(matches, 1);
        assert_int_equal(prog_entries_with(dir, ".instess-"), 0);
    }
}

/* `ulimit -v` too small for the requested image: exit 1 saying so, nothing written.  AddressSanitizer cannot
 * run under an address-space limit (its shadow memory alone exceeds it), so the sanitizer stage runs the
 * plain build/instess for this one case. */
static void test_address_space_limit(void **state)
{
    (void)state;
    const char *err;
    char p[512];
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
    setenv("INSTESS_BIN", "build/instess", 1);
#endif
#endif
    int rc = prog_run(dir, &err, "ulimit -v 2000000;", "--mesh cube -q --size 8192x8192 -o '%s'",
                      prog_path(dir, "huge.png", p, sizeof p));
    expect(rc, 1, err, "out of memory");
    assert_false(prog_exists(dir, "huge.png"));
}

static int setup(void **state)
{
    (void)state;
    return prog_mkdtemp(dir, "outputs");
}

static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_failed_export_leaves_no_image),
        cmocka_unit_test(test_same_file_twice_is_usage_error),
        cmocka_unit_test(test_only_regular_files_replaced),
        cmocka_unit_test(test_long_names),
        cmocka_unit_test(test_file_size_limit),
        cmocka_unit_test(test_full_and_read_only_filesystems),
        cmocka_unit_test(test_hook_only_in_test_build),
        cmocka_unit_test(test_signals_in_write_window),
        cmocka_unit_test(test_concurrent_writers),
        cmocka_unit_test(test_address_space_limit),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
