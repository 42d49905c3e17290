/* tests/test_describe.c -- the image's embedded description (scene_describe) is made from the option table
 * (cli/run/options.c): every option that changes pixels (rendered, to find out) is described and changes the
 * description, and the others do not, so
 * "same description, same pixels" holds.  (`--wire-levels on` and `off` once gave different pixels and the same
 * description: the description was a hand-written list that missed the option.)  The description is stored
 * whole, however long its names, and ends with the channels the file holds: a PNG's four, an EXR's all (an EXR
 * with every AOV once had its description cut mid-name, and a PNG's listed a Z channel it did not hold). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

char *strtok_r(char *str, const char *delim, char **saveptr);   /* POSIX */

#include "../cli/run/scene.h"
#include "../image/image.h"
#include "util/prog.h"

#define ALL_AOVS "R,G,B,A,Z,N.X,N.Y,N.Z,bary.X,bary.Y,bary.Z,instance,gregory.X,gregory.Y,gregory.Z,depth"

/* A value for each option that differs from the default (NULL for a flag); every option of the table must have
 * a row here, so a new option is described (or declared pixel-neutral) on purpose. */
static const struct { const char *name, *arg, *context; } samples[] = {
    {"mesh", "sphere", ""}, {"patch", "npatch", ""}, {"normals", "linear", ""},
    {"phong-alpha", "0.5", "patch=phong"}, {"n110-factor", "1.5", "normals=quadratic"}, {"level", "5", ""},
    {"grid", "pg-fractional-odd", ""}, {"path", "cpu", ""}, {"size", "64x32", ""}, {"up", "z", ""}, {"yaw", "10", ""},
    {"pitch", "-5", ""}, {"distance", "4", ""}, {"fov", "30", ""}, {"fill", "wire", ""}, {"light", "grazing", ""},
    {"shading", "pixel", ""}, {"texture", "tests/data/textures/bumps.png", ""}, {"instances", "5", ""},
    {"color", "1,0,0", ""}, {"background", "#102030", ""}, {"fit", "box", ""}, {"cull", "cw", ""},
    {"msaa", "1", ""}, {"threads", "3", ""}, {"lod", "screen", ""}, {"lod-target", "2", "lod=screen"},
    {"lod-deviation", "0.2", "lod=deviation"},
    {"min-level", "6", "lod=screen"}, {"max-level", "3", "lod=screen"}, {"silhouette", NULL, "lod=distance"},
    {"wire-levels", "on", "lod=screen,fill=solid+wire"}, {"recompute-normals", NULL, ""},
    {"import-timeout", "5", ""}, {"max-memory", "100", ""}, {"max-file-size", "10", ""},
    {"max-import-memory", "300", ""}, {"aov", "normal,depth", "output=x.exr"},
    {"d3d9-adaptive", "depth", "path=npatch-mode"}, {"displace", "tests/data/textures/bumps.png", ""},
    {"displace-scale", "0.3", "displace=tests/data/textures/bumps.png"}, {"export-obj", "x.obj", ""},
    {"output", "x.exr", ""},
    {"quiet", NULL, ""}, {"stats", "json", ""},
};

/* Apply "name=value,name=value" (render options without their dashes) to o.  Options keep pointers to their
 * values (file names), so the values are cut in `copy` (len bytes), which must live as long as o is used. */
static void apply_context(scene_opts *o, const char *context, char *copy, size_t len)
{
    char buf[512];
    snprintf(copy, len, "%s", context);
    for (char *save = NULL, *kv = strtok_r(copy, ",", &save); kv; kv = strtok_r(NULL, ",", &save)) {
        char *eq = strchr(kv, '=');
        assert_non_null(eq);
        *eq = '\0';
        const scene_option *opt = scene_find_option(kv);
        assert_non_null(opt);
        assert_null(scene_apply_option(o, opt, eq + 1, buf, sizeof buf));
    }
}


/* True if o renders other pixels than base (or another size) on m. */
static bool other_pixels(const scene_opts *base, const scene_opts *o, const is_mesh *m)
{
    is_image a = {0}, b = {0};
    char err[512];
    if (scene_render_mesh(base, m, &a, NULL, err, sizeof err) != 0) fail_msg("render: %s", err);
    if (scene_render_mesh(o, m, &b, NULL, err, sizeof err) != 0) fail_msg("render: %s", err);
    bool differ = a.width != b.width || a.height != b.height || a.channels != b.channels ||
                  memcmp(a.data, b.data, (size_t)a.width * a.height * a.channels * sizeof(float)) != 0;
    image_free(&a);
    image_free(&b);
    return differ;
}

/* The description of o for the octahedron. */
static void describe(const scene_opts *o, const is_mesh *m, char *buf, size_t len) { scene_describe(o, m, NULL, buf, len); }

static void test_every_pixel_option_is_described(void **state)
{
    (void)state;
    is_mesh m;
    char err[256], base[2048], desc[2048], errbuf[512];
    assert_int_equal(mesh_builtin("octahedron", &m, err, sizeof err), 0);
    scene_opts def;
    scene_opts_default(&def);
    def.width = def.height = 40;
    int described = 0;
    for (size_t k = 0; k < scene_option_count; k++) {
        const scene_option *opt = &scene_options[k];
        const char *arg = NULL, *context = "";
        bool found = false;
        for (size_t i = 0; i < sizeof samples / sizeof samples[0]; i++)
            if (!strcmp(samples[i].name, opt->name)) arg = samples[i].arg, context = samples[i].context, found = true;
        if (!found) fail_msg("--%s: no sample value in tests/test_describe.c (add one)", opt->name);
        scene_opts ctx = def;   /* the options this one acts with (e.g. --lod for --lod-target) */
        char ctxbuf[256];
        apply_context(&ctx, context, ctxbuf, sizeof ctxbuf);
        describe(&ctx, &m, base, sizeof base);
        scene_opts o = ctx;
        const char *msg = scene_apply_option(&o, opt, arg, errbuf, sizeof errbuf);
        if (msg) fail_msg("--%s %s: %s", opt->name, arg ? arg : "", msg);
        describe(&o, &m, desc, sizeof desc);
        bool changed = strcmp(desc, base) != 0;
        /* the file names are not pixels (an .exr output stores the same render in linear, premultiplied form) */
        bool file_name = !strcmp(opt->name, "output") || !strcmp(opt->name, "export-obj") || !strcmp(opt->name, "mesh");
        if (!file_name && !opt->value && other_pixels(&ctx, &o, &m))
            fail_msg("--%s %s changes the pixels, but the table says it does not (no value printer)", opt->name,
                     arg ? arg : "");
        if (opt->value && !changed) fail_msg("--%s changes pixels, but not the description: %s", opt->name, desc);
        if (!opt->value && changed) fail_msg("--%s does not change pixels, but changes the description", opt->name);
        if (opt->value) {   /* named as the option, with the value as it was given (where it reads back) */
            char want[128];
            snprintf(want, sizeof want, ", %s ", opt->name);
            assert_non_null(strstr(desc, want));
            described++;
        }
    }
    print_message("  %d options described, %zu in the table\n", described, scene_option_count);
    assert_true(described >= 25);
    mesh_free(&m);
}

/* --wire-levels on and off, the drift that was found: different pixels, different descriptions. */
static void test_wire_levels_described(void **state)
{
    (void)state;
    is_mesh m;
    char err[256], a[2048], b[2048];
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);
    scene_opts o;
    scene_opts_default(&o);
    o.lod = TESS_LOD_SCREEN, o.fill = SCENE_FILL_SOLID_WIRE;
    describe(&o, &m, a, sizeof a);
    o.wire_by_level = true;
    describe(&o, &m, b, sizeof b);
    assert_string_not_equal(a, b);
    assert_non_null(strstr(b, ", wire-levels on"));
    mesh_free(&m);
}

/* The description of a file: whole with a 3000-character --displace path, its length what scene_describe says,
 * ending with the channels the file holds (PNG: R,G,B,A of an image that has Z and AOVs too; EXR: all). */
static void test_description_whole(void **state)
{
    (void)state;
    is_mesh m;
    is_image img;
    char err[256], path[3001];
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);
    assert_int_equal(image_alloc(&img, 4, 4, ALL_AOVS, err, sizeof err), 0);
    memset(path, 'd', sizeof path - 5);
    memcpy(path + sizeof path - 5, ".png", 5);
    scene_opts o;
    scene_opts_default(&o);
    o.displace = path;
    char *exr = scene_describe_file(&o, &m, &img, IS_IMAGE_EXR), *png = scene_describe_file(&o, &m, &img, IS_IMAGE_PNG);
    assert_true(exr && png);
    assert_int_equal(strlen(exr), scene_describe(&o, &m, ALL_AOVS, NULL, 0));
    assert_non_null(strstr(exr, path));
    size_t ne = strlen(exr), np = strlen(png), tail = strlen(", channels " ALL_AOVS);
    assert_true(ne > tail && !strcmp(exr + ne - tail, ", channels " ALL_AOVS));
    assert_true(np > 20 && !strcmp(png + np - strlen(", channels R,G,B,A"), ", channels R,G,B,A"));
    assert_null(strstr(png, "R,G,B,A,Z"));
    char small[64];   /* a short buffer: cut, NUL-terminated, and the whole length still returned */
    assert_int_equal(scene_describe(&o, &m, "R", small, sizeof small), scene_describe(&o, &m, "R", NULL, 0));
    assert_int_equal(strlen(small), sizeof small - 1);
    free(exr);
    free(png);
    image_free(&img);
    mesh_free(&m);
}

/* The ImageDescription OpenImageIO's iinfo reads from path (malloc'd), or NULL. */
static char *stored_description(const char *path)
{
    char cmd[1024], line[16384];
    snprintf(cmd, sizeof cmd, "iinfo -v '%s' 2>&1", path);
    FILE *p = popen(cmd, "r");
    char *desc = NULL;
    while (p && fgets(line, sizeof line, p))
        if (!desc && strstr(line, "ImageDescription: \"")) {
            char *s = strchr(line, '"') + 1, *e = strrchr(line, '"');
            if (e > s) desc = strndup(s, (size_t)(e - s));
        }
    if (p) pclose(p);
    return desc;
}

/* The program's files: an EXR with every AOV, rendered from a mesh in a folder with a 200-character name, stores
 * the mesh's path and the whole channel list; the PNG of the same render lists R,G,B,A. */
static void test_file_descriptions(void **state)
{
    (void)state;
    char dir[256], sub[256], cmd[2400], mesh[800], p[512];
    const char *err;
    assert_int_equal(prog_mkdtemp(dir, "describe"), 0);
    memset(sub, 'm', 200);
    sub[200] = 0;
    snprintf(mesh, sizeof mesh, "%s/%s/box.obj", dir, sub);
    snprintf(cmd, sizeof cmd, "mkdir -p '%s/%s' && cp tests/data/meshes/box.obj '%s'", dir, sub, mesh);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(prog_run(dir, &err, "", "-q --size 24x24 --aov normal,bary,instance,gregory,depth '%s' -o %s/a.exr",
                              mesh, dir), 0);
    assert_int_equal(prog_run(dir, &err, "", "-q --size 24x24 '%s' -o %s/a.png", mesh, dir), 0);
    char *exr = stored_description(prog_path(dir, "a.exr", p, sizeof p));
    char *png = stored_description(prog_path(dir, "a.png", p, sizeof p));
    if (!exr || !png) fail_msg("no description read back (is iinfo installed? scripts/setup.sh installs it)");
    print_message("  EXR: ...%s\n", exr + strlen(exr) - 80);
    size_t tail = strlen(", channels " ALL_AOVS);
    assert_true(strlen(exr) > tail && !strcmp(exr + strlen(exr) - tail, ", channels " ALL_AOVS));
    assert_non_null(strstr(exr, sub));
    assert_true(!strcmp(png + strlen(png) - strlen(", channels R,G,B,A"), ", channels R,G,B,A"));
    assert_null(strstr(png, ",Z"));
    free(exr);
    free(png);
    prog_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_description_whole),
        cmocka_unit_test(test_file_descriptions),
        cmocka_unit_test(test_every_pixel_option_is_described),
        cmocka_unit_test(test_wire_levels_described),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
