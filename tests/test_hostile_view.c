/* tests/test_hostile_view.c -- hostile input, round 3, family 2: `instess view` scripting fed what a script or a
 * careless user would: unknown key names of every kind (control bytes, escape sequences, non-ASCII, one name of
 * thousands of characters), the limits of --keys at and past their ends, --frames junk and its largest value on a
 * scene that stands still, and displays that are missing, unknown or unreachable.  Each case is in
 * docs/robustness.md ("Round 3: `instess view` scripting") with its message.  Runs build/instess or $INSTESS_BIN
 * with SDL's dummy video driver unless a case says otherwise; tests/test_view.c has the viewer's own behaviour. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

char *realpath(const char *path, char *resolved);   /* POSIX; glibc declares it only with _DEFAULT_SOURCE */

#include "util/prog.h"

static char dir[256], bin[4096];
static char err_buf[16384];

static int setup(void **state)
{
    (void)state;
    if (prog_mkdtemp(dir, "hview") != 0 || !realpath(prog_bin(), bin)) return -1;
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    prog_rmdir(dir);
    return 0;
}

/* Run "cd dir && ENV instess view ARGS" (env: NULL for SDL's dummy drivers), stderr into err_buf, bounded by 120 s
 * (a bound, not a measurement); the exit code (128 + signal when killed). */
static int run_view(const char *env, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int run_view(const char *env, const char *fmt, ...)
{
    char args[12000], cmd[16384 + 4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    snprintf(cmd, sizeof cmd, "cd '%s' && %s timeout -s KILL 120 '%s' view %s >/dev/null 2>err.txt", dir,
             env ? env : "SDL_VIDEODRIVER=dummy SDL_AUDIODRIVER=dummy", bin, args);
    int st = system(cmd);
    prog_read_text(dir, "err.txt", err_buf, sizeof err_buf);
    return prog_exit_code(st);
}

/* Whether err_buf holds a control byte other than the newline (an escape sequence would reach the terminal). */
static bool control_bytes_in_err(void)
{
    for (const unsigned char *c = (const unsigned char *)err_buf; *c; c++)
        if ((*c < 0x20 && *c != '\n') || *c == 0x7f) return true;
    return false;
}

/* Assert exit `code`, `what` in stderr, no control byte there, and nothing left in dir but err.txt. */
static void expect(int rc, int code, const char *what)
{
    if (rc != code || !strstr(err_buf, what) || control_bytes_in_err())
        fail_msg("expected exit %d with \"%s\" and no control byte, got %d:\n%s", code, what, rc, err_buf);
    assert_int_equal(prog_entries_with(dir, ".png") + prog_entries_with(dir, ".instess-"), 0);
}

/* Unknown key names: not in the table, empty between commas, joined by '+' with an unknown one, with control
 * bytes or an escape sequence (shown as '?'), non-ASCII, of thousands of characters (said by size, not echoed):
 * exit 2 at once, before any window opens. */
static void test_unknown_keys(void **state)
{
    (void)state;
    static const struct { const char *keys, *what; } cases[] = {
        {"F13", "--keys: unknown key F13"},
        {"p,,p", "--keys: an empty key name in the list"},
        {"p,", "--keys: an empty key name in the list"},
        {",p", "--keys: an empty key name in the list"},
        {"p+F13", "--keys: unknown key p+F13"},
        {"ctrl+alt+Delete", "--keys: unknown key"},
        {"\"$(printf 'a\\001b')\"", "--keys: unknown key a?b"},
        {"\"$(printf '\\033[2J\\033]0;pwned\\007')\"", "--keys: unknown key ?[2J?]0;pwned?"},
        {"\"$(printf 'p\\177')\"", "--keys: unknown key p?"},
        {"\xc3\xa9", "--keys: unknown key \xc3\xa9"},
        {"''", "--keys needs at least one key name"},
        {",", "--keys: an empty key name in the list"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++)
        expect(run_view(NULL, "-q --size 32x32 --keys %s --capture k.png", cases[k].keys), 2, cases[k].what);
    /* one name of 5000 characters, and 2000 names: the sizes and the limits, never the list */
    char big[5100] = "";
    memset(big, 'x', 5000);
    expect(run_view(NULL, "-q --size 32x32 --keys %s", big), 2, "--keys: 1 key names in 5000 characters; at most 64 "
                                                                 "names in 1023 characters");
    assert_true(strlen(err_buf) < 400);
    char many[2000 * 2 + 8] = "p";
    for (int k = 1; k < 2000; k++) strcat(many, ",p");
    expect(run_view(NULL, "-q --size 32x32 --keys %s", many), 2, "--keys: 2000 key names in 3999 characters");
    assert_true(strlen(err_buf) < 400);
}

/* --keys at its limits: 64 names run (and end: the run stops when the script is done), 65 are refused; a 1023-
 * character list of known names is taken by length, one more character refused. */
static void test_key_limits(void **state)
{
    (void)state;
    char list[1100] = "p";
    for (int k = 1; k < 64; k++) strcat(list, ",p");
    assert_int_equal(run_view(NULL, "-q --no-hud --size 32x32 --keys %s", list), 0);
    strcat(list, ",p");
    expect(run_view(NULL, "-q --size 32x32 --keys %s", list), 2, "--keys: 65 key names in 129 characters");
    /* 64 names of 15 characters and one of 62: 1023 characters (Right+Left+Up+ pressed together is one name) */
    char longest[1100] = "";
    for (int k = 0; k < 63; k++) strcat(longest, k ? ",Right+Left+Up+p" : "Right+Left+Up+p");
    size_t n = strlen(longest);   /* 63 * 15 + 62 = 1007 */
    assert_int_equal(n, 1007);
    strcat(longest, ",Right+Left+Up+p");   /* 64 names, 1023 characters */
    assert_int_equal(strlen(longest), 1023);
    assert_int_equal(run_view(NULL, "-q --no-hud --size 32x32 --keys %s", longest), 0);
    strcat(longest, "p");   /* the last name now unknown; the list past the limit */
    expect(run_view(NULL, "-q --size 32x32 --keys %s", longest), 2, "--keys: 64 key names in 1024 characters");
}

/* --frames: junk and values past its range are usage errors naming the range; its largest value on a scene
 * that stands still ends after the one frame drawn (a frame is drawn only when something changed), and with
 * keys that change the scene after the frames they draw. */
static void test_frames(void **state)
{
    (void)state;
    static const char *const bad[] = {"0", "-1", "1000000001", "99999999999", "1.5", "1e999", "nan", "inf", "' 3'",
                                      "0x10", "''", "3abc"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        expect(run_view(NULL, "-q --size 32x32 --frames %s --capture f.png", bad[k]), 2, "--frames must be "
                                                                                          "1..1000000000");
    assert_int_equal(run_view(NULL, "-q --no-hud --size 32x32 --frames 1000000000"), 0);
    assert_non_null(strstr(err_buf, "--frames 1000000000: the scene stood still after 1 frame(s)"));
    assert_int_equal(run_view(NULL, "-q --no-hud --size 32x32 --keys p,p,p --frames 1000000000"), 0);
    assert_non_null(strstr(err_buf, "the scene stood still after 4 frame(s)"));
}

/* Displays: an unknown SDL video driver, X11 with no server at $DISPLAY, Wayland with no compositor: exit 1 with a
 * message that names the driver and says how to run without a display; nothing captured.  Without a script, the
 * dummy driver (which shows nothing) is refused: the run could not end.  (With no display variables at all SDL
 * may find an off-screen driver and a scripted run captures; test_view covers the unscripted case.) */
static void test_displays(void **state)
{
    (void)state;
    static const struct { const char *env, *what; } cases[] = {
        {"SDL_VIDEODRIVER=bogus", "cannot open the window: bogus not available"},
        {"SDL_VIDEODRIVER=x11 DISPLAY=:97", "cannot open the window: x11 not available"},
        {"SDL_VIDEODRIVER=wayland WAYLAND_DISPLAY=nowhere XDG_RUNTIME_DIR=/nonexistent",
         "cannot open the window: wayland not available"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        int rc = run_view(cases[k].env, "-q --size 32x32 --frames 1 --capture d.png");
        if (rc != 1 || !strstr(err_buf, cases[k].what) || !strstr(err_buf, "SDL_VIDEODRIVER=dummy"))
            fail_msg("%s: exit %d (want 1 with \"%s\"):\n%s", cases[k].env, rc, cases[k].what, err_buf);
        assert_false(prog_exists(dir, "d.png"));
    }
    assert_int_equal(run_view(NULL, "-q --size 32x32"), 1);
    assert_non_null(strstr(err_buf, "dummy"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_unknown_keys),
        cmocka_unit_test(test_key_limits),
        cmocka_unit_test(test_frames),
        cmocka_unit_test(test_displays),
    };
    return cmocka_run_group_tests_name("hostile_view", tests, setup, teardown);
}
