/* tests/test_hostile_env.c -- hostile input, round 3, family 6: the environment.  Where the codec and window
 * modules are loaded from (never the folder above the program or the current directory; a wrong or hostile
 * module refused with a message), SOURCE_DATE_EPOCH that is not a time, OMP_NUM_THREADS 0 or huge, a
 * decimal-comma locale, no HOME, an unwritable TMPDIR.  Each case is in docs/robustness.md ("Round 3: images,
 * files and environment").  Runs build/instess or $INSTESS_BIN; the planted modules are compiled here with cc. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

char *realpath(const char *path, char *resolved);   /* POSIX; glibc declares them only with _DEFAULT_SOURCE */
int symlink(const char *target, const char *linkpath);
int mkfifo(const char *path, mode_t mode);

#include "util/prog.h"

static char dir[256], bin[4096];
static char out_buf[16384], err_buf[16384];

/* Run the shell line "cd dir && ENV PROGRAM ARGS" (PROGRAM: the program under test, or `program` when not
 * NULL) with stdout into out_buf and stderr into err_buf; the exit code. */
static int run_env(const char *env, const char *program, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int run_env(const char *env, const char *program, const char *fmt, ...)
{
    char redirect[600];   /* absolute: env may change the folder (cd cwd &&) */
    snprintf(redirect, sizeof redirect, ">'%s/out.txt' 2>'%s/err.txt'", dir, dir);
    va_list ap;
    va_start(ap, fmt);
    int rc = prog_vrun_in(dir, env, program ? program : bin, redirect, fmt, ap);
    va_end(ap);
    prog_read_text(dir, "out.txt", out_buf, sizeof out_buf);
    prog_read_text(dir, "err.txt", err_buf, sizeof err_buf);
    return rc;
}

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

/* Whether dir/a and dir/b hold the same bytes. */
static bool same_file(const char *a, const char *b)
{
    char pa[512], pb[512];
    return prog_same_bytes(at(a, pa, sizeof pa), at(b, pb, sizeof pb));
}

/* Run a shell command line in dir; its exit status. */
static int sh(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static int sh(const char *fmt, ...)
{
    char line[6000], cmd[7000];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    snprintf(cmd, sizeof cmd, "cd '%s' && %s", dir, line);
    return system(cmd);
}

/* LeakSanitizer's suppressions file named relative to the tree (the sanitizer stage's LSAN_OPTIONS), made
 * absolute: the program runs in the test's folder, where a relative name is not found. */
static void absolute_lsan_suppressions(void)
{
    const char *l = getenv("LSAN_OPTIONS"), *at_rel = l ? strstr(l, "suppressions=tests/") : NULL;
    char cwd[2048], opts[4096];
    if (!at_rel || !getcwd(cwd, sizeof cwd)) return;
    snprintf(opts, sizeof opts, "%.*ssuppressions=%s/%s", (int)(at_rel - l), l, cwd, at_rel + strlen("suppressions="));
    setenv("LSAN_OPTIONS", opts, 1);
}

static int setup(void **state)
{
    (void)state;
    absolute_lsan_suppressions();
    if (prog_mkdtemp(dir, "henv") != 0 || !realpath(prog_bin(), bin)) return -1;
    return run_env(NULL, NULL, "--size 32x32 -q -o a.png") != 0 || run_env(NULL, NULL, "--size 32x32 -q -o a.exr") != 0;
}

static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

/* ------------------------------------------------------------ modules */

/* Compile a module into dir/out whose constructor creates dir/PWNED (so that running it shows), defining the
 * symbols of `defs` (C source, may be ""). */
static void make_module(const char *out, const char *defs)
{
    char src[600];
    snprintf(src, sizeof src, "%s.c", out);
    char text[1400];
    snprintf(text, sizeof text, "#include <stdio.h>\n__attribute__((constructor)) static void planted(void)\n"
             "{ FILE *f = fopen(\"%s/PWNED\", \"w\"); if (f) fclose(f); }\n%s\n", dir, defs);
    assert_true(prog_write_text(dir, src, text));
    if (sh("cc -shared -fPIC -o '%s' '%s' 2>cc.txt", out, src) != 0) fail_msg("cannot compile %s with cc", out);
}

/* Whether a planted module's constructor ran (and forget it). */
static bool pwned(void)
{
    char p[512];
    bool yes = access(at("PWNED", p, sizeof p), F_OK) == 0;
    unlink(p);
    return yes;
}

/* A codec module and a window module planted in the folder above a copy of the program (which has neither
 * beside it) are never loaded: their constructors do not run, and the program says where it looked; with the
 * real codec beside the copy, that one is used.  (OpenEXR files: PNG files never load the codec.) */
static void test_modules_not_from_the_folder_above(void **state)
{
    (void)state;
    char p[512];
    assert_int_equal(sh("mkdir -p inst/bin && cp '%s' inst/bin/instess", bin), 0);
    make_module("inst/libinstess_codec.so", "int codec_abi = 2; int codec_encode, codec_read_fd, codec_draw_text, "
                                            "codec_text_size;");
    make_module("inst/libinstess_view.so", "int view_module_run(void *v) { return 0; }");
    char copy[512];
    at("inst/bin/instess", copy, sizeof copy);
    expect(run_env(NULL, copy, "compare a.exr a.exr"), 4, "cannot load libinstess_codec.so (looked in ");
    assert_non_null(strstr(err_buf, "inst/bin, "));
    assert_null(strstr(err_buf, "inst/bin/.., "));
    assert_false(pwned());
    expect(run_env(NULL, copy, "--size 16x16 -q -o b.exr"), 1, "cannot load libinstess_codec.so");
    assert_false(pwned());
    expect(run_env("SDL_VIDEODRIVER=dummy", copy, "view --frames 1 --size 16x16 -q"), 1,
           "cannot load the window module libinstess_view.so");
    assert_null(strstr(err_buf, "inst/bin/.., "));
    assert_false(pwned());
    /* the real codec beside the copy (through a link, as in build/tests) */
    char real[4096], codec[4200];
    assert_non_null(realpath(bin, real));
    *strrchr(real, '/') = 0;
    snprintf(codec, sizeof codec, "%s/libinstess_codec.so", real);
    assert_int_equal(symlink(codec, at("inst/bin/libinstess_codec.so", p, sizeof p)), 0);
    assert_int_equal(run_env(NULL, copy, "compare a.exr a.exr"), 0);
    assert_false(pwned());
}

/* A window module beside a copy of the program gets the codec module's checks before it is loaded: a file that
 * is not an ELF shared object, a library that does not define view_module_run (its constructor never runs) and a
 * module or folder writable by every user are refused with a message naming the file (the folder); the first folder holding the file
 * decides (the real module in the compiled-in folder is not tried after a refusal). */
static void test_wrong_and_hostile_window_modules(void **state)
{
    (void)state;
    char p[512], copy[512], real[4096], view[4200];
    assert_non_null(realpath(bin, real));
    *strrchr(real, '/') = 0;
    snprintf(view, sizeof view, "%s/libinstess_view.so", real);
    const struct { const char *folder, *what; } cases[] = {
        {"w-garbage", "not a 64-bit ELF shared object: refused (not loaded)"},
        {"w-other", "does not define view_module_run, so it is not the module it is named after: refused"},
        {"w-o+w", "the module is writable by every user: refused"},
        {"w-open", "the folder of the module is writable by every user: refused"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const char *f = cases[k].folder;
        assert_int_equal(sh("mkdir -p '%s' && cp '%s' '%s/instess'", f, bin, f), 0);
        char so[300];
        snprintf(so, sizeof so, "%s/libinstess_view.so", f);
        if (k == 0) assert_int_equal(sh("echo 'not a library' > '%s'", so), 0);
        else if (k == 1) make_module(so, "int unrelated = 1;");
        else if (k == 2) assert_int_equal(sh("cp '%s' '%s' && chmod 0666 '%s'", view, so, so), 0);
        else assert_int_equal(sh("cp '%s' '%s' && chmod 0777 '%s'", view, so, f), 0);
        snprintf(p, sizeof p, "%s/instess", f);
        at(p, copy, sizeof copy);
        expect(run_env("SDL_VIDEODRIVER=dummy", copy, "view --frames 1 --size 16x16 -q"), 1, cases[k].what);
        if (!strstr(err_buf, k == 3 ? f : so)) fail_msg("the message does not name %s:\n%s", k == 3 ? f : so, err_buf);
        assert_false(pwned());
    }
}

/* A module in the current directory is never loaded: INSTESS_CODEC_DIR must be absolute ('.', 'sub', './' are
 * refused with a message); unset or empty, the program's own module is used. */
static void test_modules_not_from_the_current_directory(void **state)
{
    (void)state;
    assert_int_equal(sh("mkdir -p cwd/sub"), 0);
    make_module("cwd/libinstess_codec.so", "int codec_abi = 2;");
    make_module("cwd/sub/libinstess_codec.so", "int codec_abi = 2;");
    const char *rel[] = {".", "sub", "./", "../cwd"};
    for (size_t k = 0; k < sizeof rel / sizeof rel[0]; k++) {
        char env[64];
        snprintf(env, sizeof env, "cd cwd && INSTESS_CODEC_DIR='%s'", rel[k]);
        expect(run_env(env, NULL, "compare ../a.exr ../a.exr"), 4, "is not an absolute path: refused (a module is "
                                                                   "never loaded from the current directory)");
        assert_false(pwned());
    }
    assert_int_equal(run_env("cd cwd &&", NULL, "compare ../a.exr ../a.exr"), 0);
    assert_int_equal(run_env("cd cwd && INSTESS_CODEC_DIR=", NULL, "compare ../a.exr ../a.exr"), 0);
    assert_false(pwned());
}

/* INSTESS_CODEC_DIR naming a wrong or untrusted module: refused with a message naming it (compare exit 4, a
 * render exit 1); a file that is not the module is never loaded (its constructor does not run); a module of
 * another version is refused before any of its functions is called.  A folder without the module is passed
 * over. */
static void test_wrong_and_hostile_modules(void **state)
{
    (void)state;
    char p[512], env[4400], real[4096], codec[4200];
    assert_non_null(realpath(bin, real));
    *strrchr(real, '/') = 0;
    snprintf(codec, sizeof codec, "%s/libinstess_codec.so", real);
    const struct { const char *folder, *make, *what; bool runs; } cases[] = {
        {"m-garbage", "echo 'not a library' > m-garbage/libinstess_codec.so", "not a 64-bit ELF shared object: refused "
         "(not loaded)", false},
        {"m-other", NULL, "does not define codec_abi, so it is not the module it is named after: refused (not loaded)",
         false},
        {"m-old", NULL, "not an image codec module of this version (codec_abi 1, this library needs 2): refused", true},
        {"m-fifo", "mkfifo m-fifo/libinstess_codec.so", "not a regular file: refused", false},
        {"m-folder", "mkdir m-folder/libinstess_codec.so", "not a regular file: refused", false},
        {"m-open", "cp \"$CODEC\" m-open/ && chmod 0777 m-open", "the folder of the module is writable by every "
         "user: refused", false},
        {"m-o+w", "cp \"$CODEC\" m-o+w/ && chmod 0666 m-o+w/libinstess_codec.so", "the module is writable by every "
         "user: refused", false},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        assert_int_equal(sh("mkdir -p '%s'", cases[k].folder), 0);
        char so[300];
        snprintf(so, sizeof so, "%s/libinstess_codec.so", cases[k].folder);
        if (!strcmp(cases[k].folder, "m-other")) make_module(so, "int unrelated = 1;");
        else if (!strcmp(cases[k].folder, "m-old")) make_module(so, "int codec_abi = 1;");
        else assert_int_equal(sh("CODEC='%s'; %s", codec, cases[k].make), 0);
        snprintf(env, sizeof env, "INSTESS_CODEC_DIR='%s'", at(cases[k].folder, p, sizeof p));
        expect(run_env(env, NULL, "compare a.exr a.exr"), 4, cases[k].what);
        assert_non_null(strstr(err_buf, cases[k].folder));
        assert_int_equal(pwned(), cases[k].runs);
        expect(run_env(env, NULL, "--size 16x16 -q -o b.exr"), 1, cases[k].what);
        pwned();
    }
    /* owned by another user: only root can make one */
    if (geteuid() == 0) {
        assert_int_equal(sh("mkdir -p m-theirs && cp '%s' m-theirs/ && chown 65534 m-theirs/libinstess_codec.so",
                            codec), 0);
        snprintf(env, sizeof env, "INSTESS_CODEC_DIR='%s'", at("m-theirs", p, sizeof p));
        expect(run_env(env, NULL, "compare a.exr a.exr"), 4, "the module is owned by user 65534, neither root nor "
                                                             "this user (0): refused");
    } else {
        print_message("  (a module owned by another user: not tried, the test does not run as root)\n");
    }
    /* a folder without the module: passed over */
    snprintf(env, sizeof env, "INSTESS_CODEC_DIR='%s'", at("no-such-folder", p, sizeof p));
    assert_int_equal(run_env(env, NULL, "compare a.exr a.exr"), 0);
    /* the real module through INSTESS_CODEC_DIR: used */
    snprintf(env, sizeof env, "INSTESS_CODEC_DIR='%s'", real);
    assert_int_equal(run_env(env, NULL, "compare a.exr a.exr"), 0);
}

/* ------------------------------------------------------------ other variables */

/* SOURCE_DATE_EPOCH that is not a whole number of seconds in 0..253402300799: exit 0, a warning naming the
 * value (control bytes as '?'), an OpenEXR file without a time (the bytes of a run without the variable); a PNG
 * carries no time and gets no warning.  Valid values are stored. */
static void test_source_date_epoch(void **state)
{
    (void)state;
    assert_int_equal(run_env("env -u SOURCE_DATE_EPOCH", NULL, "--size 16x16 -q -o plain.exr"), 0);
    const char *bad[] = {"garbage", "-1", "1e9", "' 1'", "'1 '", "+5", "253402300800", "99999999999999999999",
                         "0x10", "$(printf '\\033[2J')"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char env[128];
        snprintf(env, sizeof env, "SOURCE_DATE_EPOCH=%s", bad[k]);
        expect(run_env(env, NULL, "--size 16x16 -q -o bad.exr"), 0, "is not a whole number of seconds in "
                                                                    "0..253402300799: the OpenEXR files store no time");
        assert_null(strchr(err_buf, '\033'));
        assert_true(same_file("bad.exr", "plain.exr"));
        assert_int_equal(run_env(env, NULL, "--size 16x16 -q -o bad.png"), 0);
        assert_string_equal(err_buf, "");
    }
    assert_int_equal(run_env("SOURCE_DATE_EPOCH=", NULL, "--size 16x16 -q -o empty.exr"), 0);
    assert_string_equal(err_buf, "");
    assert_true(same_file("empty.exr", "plain.exr"));
    const char *good[][2] = {{"0", "1970:01:01 00:00:00"}, {"253402300799", "9999:12:31 23:59:59"}};
    for (int k = 0; k < 2; k++) {
        char env[64];
        snprintf(env, sizeof env, "SOURCE_DATE_EPOCH=%s", good[k][0]);
        assert_int_equal(run_env(env, NULL, "--size 16x16 -q -o dated.exr"), 0);
        assert_string_equal(err_buf, "");
        assert_int_equal(sh("grep -q '%s' dated.exr", good[k][1]), 0);
    }
}

/* OMP_NUM_THREADS and friends at their edges (0, negative, not a number, huge, a list) change nothing: exit 0
 * and the bytes of the default run (libgomp's own note about an invalid value aside). */
static void test_openmp_variables(void **state)
{
    (void)state;
    const char *envs[] = {"OMP_NUM_THREADS=0", "OMP_NUM_THREADS=-1", "OMP_NUM_THREADS=abc", "OMP_NUM_THREADS=100000",
                          "OMP_NUM_THREADS=99999999999", "OMP_NUM_THREADS=4,2", "OMP_NUM_THREADS=",
                          "OMP_THREAD_LIMIT=1", "OMP_DYNAMIC=true OMP_NUM_THREADS=1000", "OMP_THREAD_LIMIT=0"};
    assert_int_equal(run_env(NULL, NULL, "--mesh sphere --size 64x64 -q -o ref.png"), 0);
    for (size_t k = 0; k < sizeof envs / sizeof envs[0]; k++) {
        int rc = run_env(envs[k], NULL, "--mesh sphere --size 64x64 -q -o omp.png");
        if (rc != 0 || !same_file("omp.png", "ref.png")) fail_msg("%s: exit %d: %s", envs[k], rc, err_buf);
        rc = run_env(envs[k], NULL, "compare omp.png ref.png");
        if (rc != 0) fail_msg("%s: compare exit %d: %s", envs[k], rc, err_buf);
    }
}

/* Under a decimal-comma locale (de_DE.UTF-8, generated here with localedef into the test's folder and found
 * through LOCPATH) numbers parse and print as in C: a render with fractional options gives the same image, export
 * and OpenEXR description bytes, --stats json keeps '.', compare and smoothness print the same text. */
static void test_decimal_comma_locale(void **state)
{
    (void)state;
    if (sh("mkdir -p loc && localedef -i de_DE -f UTF-8 loc/de_DE.UTF-8 >/dev/null 2>&1") != 0) {
        print_message("  localedef could not make de_DE.UTF-8 (the locales package's sources are missing)\n");
        skip();
    }
    char env[700], p[512];
    snprintf(env, sizeof env, "LOCPATH='%s' LC_ALL=de_DE.UTF-8", at("loc", p, sizeof p));
    /* the locale works: printf(1) reads and writes a decimal comma in it */
    char check[1600];
    snprintf(check, sizeof check, "test \"$(%s /usr/bin/printf %%.1f 1,5)\" = 1,5", env);
    assert_int_equal(sh("%s", check), 0);
    const char *args = "--mesh sphere --yaw 12.5 --pitch -7.25 --distance 3.5 --fov 40.5 --light 0.5,1,-0.25 "
                       "--color 0.8,0.7,0.6 --size 48x48 -q";
    assert_int_equal(run_env("LC_ALL=C", NULL, "%s -o c.png --export-obj c.obj", args), 0);
    assert_int_equal(run_env("LC_ALL=C", NULL, "%s --aov depth -o c.exr", args), 0);
    int rc = run_env(env, NULL, "%s --stats json -o de.png --export-obj de.obj", args);
    if (rc != 0) fail_msg("exit %d under de_DE.UTF-8: %s", rc, err_buf);
    assert_true(same_file("de.png", "c.png"));
    assert_true(same_file("de.obj", "c.obj"));
    char *ms = strstr(out_buf, "\"ms\": ");
    assert_non_null(ms);
    ms += 6;
    while (*ms >= '0' && *ms <= '9') ms++;
    assert_true(ms[0] == '.' && ms[1] >= '0' && ms[1] <= '9');
    rc = run_env(env, NULL, "%s --aov depth -o de.exr", args);
    if (rc != 0) fail_msg("exit %d under de_DE.UTF-8: %s", rc, err_buf);
    assert_true(same_file("de.exr", "c.exr"));
    assert_int_equal(run_env("LC_ALL=C", NULL, "%s --yaw 14 -o c2.png", args), 0);
    int c_rc = run_env("LC_ALL=C", NULL, "compare c.png c2.png --fail 0.5 --failpercent 2.5");
    static char c_out[16384];
    snprintf(c_out, sizeof c_out, "%s", out_buf);
    assert_non_null(strstr(c_out, "allowed: 2.5%"));
    assert_int_equal(run_env(env, NULL, "compare c.png c2.png --fail 0.5 --failpercent 2.5"), c_rc);
    assert_string_equal(out_buf, c_out);
    assert_int_equal(run_env("LC_ALL=C", NULL, "smoothness --samples 3 --mesh tetrahedron"), 0);
    snprintf(c_out, sizeof c_out, "%s", out_buf);
    assert_int_equal(run_env(env, NULL, "smoothness --samples 3 --mesh tetrahedron"), 0);
    assert_string_equal(out_buf, c_out);
}

/* No HOME (unset, or a folder that does not exist) and a TMPDIR that cannot be written (missing, /proc): a
 * render with an export and an OpenEXR file, a mesh through the import process, compare and figures work and
 * write the same bytes. */
static void test_home_and_tmpdir(void **state)
{
    (void)state;
    static const char tet[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
    assert_true(prog_write_text(dir, "tet.obj", tet));
    assert_int_equal(run_env(NULL, NULL, "--mesh tet.obj --size 32x32 -q -o ref.exr --export-obj ref.obj"), 0);
    assert_int_equal(run_env(NULL, NULL, "figures --only fig-1.1.3 --out ref-fig"), 0);
    const char *envs[] = {"env -u HOME", "HOME=/nonexistent", "TMPDIR=/nonexistent", "TMPDIR=/proc",
                          "env -u HOME TMPDIR=/proc"};
    for (size_t k = 0; k < sizeof envs / sizeof envs[0]; k++) {
        int rc = run_env(envs[k], NULL, "--mesh tet.obj --size 32x32 -q -o e.exr --export-obj e.obj");
        if (rc != 0) fail_msg("%s: exit %d: %s", envs[k], rc, err_buf);
        assert_true(same_file("e.exr", "ref.exr") && same_file("e.obj", "ref.obj"));
        assert_int_equal(run_env(envs[k], NULL, "compare e.exr ref.exr"), 0);
        assert_int_equal(run_env(envs[k], NULL, "figures --only fig-1.1.3 --out fig%zu", k), 0);
        char a[64];
        snprintf(a, sizeof a, "fig%zu/fig-1.1.3.png", k);
        assert_true(same_file(a, "ref-fig/fig-1.1.3.png"));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_modules_not_from_the_folder_above),
        cmocka_unit_test(test_modules_not_from_the_current_directory),
        cmocka_unit_test(test_wrong_and_hostile_modules),
        cmocka_unit_test(test_wrong_and_hostile_window_modules),
        cmocka_unit_test(test_source_date_epoch),
        cmocka_unit_test(test_openmp_variables),
        cmocka_unit_test(test_decimal_comma_locale),
        cmocka_unit_test(test_home_and_tmpdir),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
