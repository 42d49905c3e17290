/* tests/test_render_options.c -- the options that came out of the figures (cli/run/options.c, cli/run/lighting.c):
 * --light, --fov, --color, --background, --phong-alpha, --n110-factor.  Each changes the pixels it should and
 * only those; its default, given explicitly, changes nothing (the default image keeps its bytes); the names the
 * figures use equal the values they stand for; a bad value is a usage error (exit 2) naming the option, with
 * nothing written.  Runs build/instess (or $INSTESS_BIN). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "util/prog.h"

static char dir[256];

/* Render a small image of `args` into dir/name; asserts success. */
static void render(const char *name, const char *args)
{
    char out[512];
    const char *err;
    int rc = prog_run(dir, &err, "", "--size 64x64 --level 4 -q %s -o '%s'", args,
                      prog_path(dir, name, out, sizeof out));
    if (rc != 0) fprintf(stderr, "render %s: exit %d: %s\n", args, rc, err);
    assert_int_equal(rc, 0);
}

/* Whether dir/a and dir/b hold the same pixels. */
static bool same(const char *a, const char *b)
{
    char pa[512], pb[512];
    return prog_same_pixels(prog_path(dir, a, pa, sizeof pa), prog_path(dir, b, pb, sizeof pb));
}

/* Every option at its default, spelled out, gives the default image; the figures' names equal their values. */
static void test_defaults_and_names(void **state)
{
    (void)state;
    render("default.png", "--mesh tetrahedron --patch phong --normals quadratic");
    render("explicit.png", "--mesh tetrahedron --patch phong --normals quadratic --light headlight --fov 45 "
                           "--color 0.85,0.78,0.62 --background '#2e3440' --phong-alpha 0.75 --n110-factor 2");
    assert_true(same("default.png", "explicit.png"));
    render("grazing.png", "--mesh cube --normals real --light grazing");
    render("direction.png", "--mesh cube --normals real --light 0.62,0.62,-0.48");
    assert_true(same("grazing.png", "direction.png"));
    render("hex.png", "--color '#ff8000' --background '#000000'");
    render("rgb.png", "--color 1,0.50196078,0 --background 0,0,0");
    assert_true(same("hex.png", "rgb.png"));
}

/* Each option changes the image. */
static void test_each_option_changes_pixels(void **state)
{
    (void)state;
    static const char *const changed[] = {"--light grazing", "--light 1,0,0", "--light normals", "--fov 30",
                                          "--color 0.2,0.4,0.9", "--background 1,1,1"};
    render("base.png", "--mesh cube --normals real");
    for (size_t k = 0; k < sizeof changed / sizeof changed[0]; k++) {
        char args[128];
        snprintf(args, sizeof args, "--mesh cube --normals real %s", changed[k]);
        render("changed.png", args);
        if (same("base.png", "changed.png")) fprintf(stderr, "%s did not change the image\n", changed[k]);
        assert_false(same("base.png", "changed.png"));
    }
}

/* --phong-alpha moves Phong tessellation only; --n110-factor moves quadratic normals only. */
static void test_patch_factors(void **state)
{
    (void)state;
    render("phong.png", "--mesh octahedron --patch phong");
    render("phong-a.png", "--mesh octahedron --patch phong --phong-alpha 0.3");
    assert_false(same("phong.png", "phong-a.png"));
    render("np.png", "--mesh octahedron --patch npatch");
    render("np-a.png", "--mesh octahedron --patch npatch --phong-alpha 0.3");
    assert_true(same("np.png", "np-a.png"));
    /* the built-ins' normals are symmetric about every edge (n0 + n1 perpendicular to it), so v_ij = 0 whatever
     * the factor: a quad whose normals all lean the same way (an inflection along each edge) instead */
    assert_true(prog_write_text(dir, "lean.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0.4 0.3 1\n"
                                                 "f 1//1 2//1 3//1\nf 1//1 3//1 4//1\n"));
    char mesh[512], args[700];
    prog_path(dir, "lean.obj", mesh, sizeof mesh);
    snprintf(args, sizeof args, "--mesh '%s' --yaw 0 --pitch 0 --patch npatch --normals quadratic", mesh);
    render("quad.png", args);
    strcat(args, " --n110-factor 1.5");
    render("quad-f.png", args);
    assert_false(same("quad.png", "quad-f.png"));
    snprintf(args, sizeof args, "--mesh '%s' --yaw 0 --pitch 0 --patch npatch", mesh);
    render("lin.png", args);
    strcat(args, " --n110-factor 1.5");
    render("lin-f.png", args);
    assert_true(same("lin.png", "lin-f.png"));
}

/* A bad value: exit 2, the option named, no file. */
static void test_bad_values(void **state)
{
    (void)state;
    static const struct { const char *args, *name; } bad[] = {
        {"--light 0,0,0", "--light"},        {"--light sideways", "--light"}, {"--light 1,2", "--light"},
        {"--color 2,0,0", "--color"},        {"--color '#12345'", "--color"}, {"--background red", "--background"},
        {"--fov 0", "--fov"},                {"--fov 180", "--fov"},          {"--phong-alpha -1", "--phong-alpha"},
        {"--n110-factor 3", "--n110-factor"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char out[512];
        const char *err;
        int rc = prog_run(dir, &err, "", "--size 16x16 %s -o '%s'", bad[k].args,
                          prog_path(dir, "bad.png", out, sizeof out));
        if (rc != 2 || !strstr(err, bad[k].name)) fprintf(stderr, "%s: exit %d: %s\n", bad[k].args, rc, err);
        assert_int_equal(rc, 2);
        assert_non_null(strstr(err, bad[k].name));
        assert_false(prog_exists(dir, "bad.png"));
    }
}

static int setup(void **state)
{
    (void)state;
    return prog_mkdtemp(dir, "options");
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
        cmocka_unit_test(test_defaults_and_names),
        cmocka_unit_test(test_each_option_changes_pixels),
        cmocka_unit_test(test_patch_factors),
        cmocka_unit_test(test_bad_values),
    };
    return cmocka_run_group_tests_name("render_options", tests, setup, teardown);
}
