/* tests/test_mesh_texture.c -- a mesh file's own texture (meshes.h, mesh_load_file: "The file's texture";
 * is_mesh.texture) and how instess uses it (cli/run/scene.c, scene_use_mesh_texture): the skins of assimp's MD2
 * test models (they name none; the image their header's skin size identifies), a named skin found by its path or
 * its last component, one that is missing or outside the folder (a warning, untextured), an embedded one
 * (refused with a warning); the program draws the mesh's own texture as if --texture named it, --texture none
 * draws none.  The MD2 models come with assimp-testmodels (scripts/setup.sh installs it): the tests that need
 * them are skipped, saying so, when it is absent. */
#define _DEFAULT_SOURCE
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util/prog.h"
#include "../meshes/meshes.h"

#define MD2_DIR "/usr/share/assimp/models/MD2/"
#define FAERIE MD2_DIR "faerie.md2"
#define EMBEDDED "/usr/share/assimp/models/glTF/BoxTextured-glTF-Embedded/BoxTextured.gltf"

/* Skip the test (saying why) when the assimp test model path is absent. */
#define NEED(path)                                                                                 \
    do {                                                                                           \
        if (access(path, R_OK) != 0) {                                                             \
            print_message("SKIP: %s is absent (scripts/setup.sh installs assimp-testmodels)\n", path); \
            skip();                                                                                \
        }                                                                                          \
    } while (0)

/* The warnings of one load, joined by newlines. */
typedef struct warnings { char text[8192]; } warnings;

/* is_mesh_warn_fn: append the message. */
static void collect(void *user, const char *msg)
{
    warnings *w = user;
    size_t n = strlen(w->text);
    snprintf(w->text + n, sizeof w->text - n, "%s\n", msg);
}

/* Load path into m (or fail the test) with its warnings into w; m->texture is what the test looks at. */
static void load(const char *path, is_mesh *m, warnings *w)
{
    char err[512] = "";
    w->text[0] = '\0';
    is_mesh_options opt = {.warn = collect, .warn_user = w};
    if (mesh_load_file(path, &opt, m, err, sizeof err) != 0) fail_msg("%s: %s", path, err);
}

/* faerie.md2 with one skin named `skin` (MD2 header: numSkins at byte 20, ofs_skins at 44; the other offsets,
 * 48..64, move by the 64 bytes inserted at ofs_skins) as dir/name. */
static void write_md2_with_skin(const char *dir, const char *name, const char *skin)
{
    size_t n;
    unsigned char *d = prog_slurp(FAERIE, &n);
    assert_non_null(d);
    unsigned char *o = calloc(1, n + 64);
    assert_non_null(o);
    uint32_t ofs;
    memcpy(&ofs, d + 44, 4);
    memcpy(o, d, ofs);
    memcpy(o + ofs + 64, d + ofs, n - ofs);
    strncpy((char *)o + ofs, skin, 63);
    uint32_t one = 1;
    memcpy(o + 20, &one, 4);
    for (int at = 48; at <= 64; at += 4) {
        uint32_t v;
        memcpy(&v, o + at, 4);
        v += 64;
        memcpy(o + at, &v, 4);
    }
    assert_true(prog_write_bytes(dir, name, o, n + 64));
    free(o);
    free(d);
}

/* Copy the file at src to dir/name. */
static void copy_file(const char *src, const char *dir, const char *name)
{
    size_t n;
    unsigned char *d = prog_slurp(src, &n);
    assert_non_null(d);
    assert_true(prog_write_bytes(dir, name, d, n));
    free(d);
}

/* A BMP header of w x h (enough for the size the skin guess reads) as dir/name. */
static void write_bmp_header(const char *dir, const char *name, int w, int h)
{
    unsigned char b[54] = {'B', 'M'};
    memcpy(b + 18, &w, 4), memcpy(b + 22, &h, 4);
    assert_true(prog_write_bytes(dir, name, b, sizeof b));
}

/* assimp's MD2 test models name no skin (assimp reports its placeholder "$texture_dummy.bmp"); the image beside
 * each whose size is the header's skin size is theirs: faerie2.bmp (220x193), sydney.bmp (308x193).  Silently. */
static void test_md2_skins(void **state)
{
    (void)state;
    NEED(FAERIE);
    is_mesh m;
    warnings w;
    load(FAERIE, &m, &w);
    assert_string_equal(m.texture, MD2_DIR "faerie2.bmp");
    assert_null(strstr(w.text, "untextured"));
    mesh_free(&m);
    load(MD2_DIR "sydney.md2", &m, &w);
    assert_string_equal(m.texture, MD2_DIR "sydney.bmp");
    assert_null(strstr(w.text, "untextured"));
    mesh_free(&m);
}

/* The skin guess of an MD2 that names none: only images whose name starts with the model's and whose size is the
 * skin's; none: no texture and no word; two: a warning naming both, no texture. */
static void test_md2_skin_guess(void **state)
{
    (void)state;
    NEED(FAERIE);
    char dir[256], p[512];
    assert_int_equal(prog_mkdtemp(dir, "skin-guess"), 0);
    copy_file(FAERIE, dir, "faerie.md2");
    write_bmp_header(dir, "faerie_small.bmp", 64, 64);     /* the model's name, not its skin's size */
    write_bmp_header(dir, "other.bmp", 220, 193);          /* the size, not the model's name */
    is_mesh m;
    warnings w;
    load(prog_path(dir, "faerie.md2", p, sizeof p), &m, &w);
    assert_string_equal(m.texture, "");
    assert_null(strstr(w.text, "untextured"));
    mesh_free(&m);
    copy_file(MD2_DIR "faerie2.bmp", dir, "faerie2.bmp");
    load(prog_path(dir, "faerie.md2", p, sizeof p), &m, &w);
    char want[600];
    assert_string_equal(m.texture, prog_path(dir, "faerie2.bmp", want, sizeof want));
    mesh_free(&m);
    write_bmp_header(dir, "faerie-red.bmp", 220, -193);    /* a top-down BMP of the same size */
    load(prog_path(dir, "faerie.md2", p, sizeof p), &m, &w);
    assert_string_equal(m.texture, "");
    assert_non_null(strstr(w.text, "names no skin, and 2 images in its folder have its skin's size 220x193 "
                                   "('faerie-red.bmp', 'faerie2.bmp'): rendered untextured"));
    mesh_free(&m);
    prog_rmdir(dir);
}

/* An MD2 that names its skin (as Quake 2's do, by a path from the game's folder): found by that path relative
 * to the mesh's folder, or by its last component beside the mesh, or by that in another case; missing: a
 * warning naming it and no texture. */
static void test_named_skin(void **state)
{
    (void)state;
    NEED(FAERIE);
    char dir[256], p[512], want[600];
    assert_int_equal(prog_mkdtemp(dir, "named-skin"), 0);
    write_md2_with_skin(dir, "q2.md2", "models/monsters/faerie/skin.bmp");
    is_mesh m;
    warnings w;
    load(prog_path(dir, "q2.md2", p, sizeof p), &m, &w);
    assert_string_equal(m.texture, "");
    assert_non_null(strstr(w.text, "q2.md2: its material names the texture 'models/monsters/faerie/skin.bmp', which "
                                   "is not in the mesh's folder: rendered untextured (--texture FILE gives one)"));
    mesh_free(&m);
    copy_file(MD2_DIR "faerie2.bmp", dir, "SKIN.BMP");      /* another case */
    load(prog_path(dir, "q2.md2", p, sizeof p), &m, &w);
    assert_string_equal(m.texture, prog_path(dir, "SKIN.BMP", want, sizeof want));
    assert_null(strstr(w.text, "untextured"));
    mesh_free(&m);
    copy_file(MD2_DIR "faerie2.bmp", dir, "skin.bmp");      /* the last component: now two in another case */
    load(prog_path(dir, "q2.md2", p, sizeof p), &m, &w);
    assert_string_equal(m.texture, prog_path(dir, "skin.bmp", want, sizeof want));
    mesh_free(&m);
    write_md2_with_skin(dir, "rel.md2", "sub\\skin.bmp");   /* a relative path, written on Windows */
    assert_int_equal(mkdir(prog_path(dir, "sub", want, sizeof want), 0700), 0);
    copy_file(MD2_DIR "faerie2.bmp", dir, "sub/skin.bmp");
    load(prog_path(dir, "rel.md2", p, sizeof p), &m, &w);
    assert_string_equal(m.texture, prog_path(dir, "sub/skin.bmp", want, sizeof want));
    mesh_free(&m);
    prog_rmdir(dir);
}

/* A skin outside the mesh's folder, or a folder by that name: not used, with a warning saying why. */
static void test_skin_outside(void **state)
{
    (void)state;
    NEED(FAERIE);
    char dir[256], p[512];
    assert_int_equal(prog_mkdtemp(dir, "skin-outside"), 0);
    assert_int_equal(mkdir(prog_path(dir, "m", p, sizeof p), 0700), 0);
    copy_file(MD2_DIR "faerie2.bmp", dir, "outside.bmp");
    write_md2_with_skin(dir, "m/up.md2", "../outside.bmp");
    is_mesh m;
    warnings w;
    load(prog_path(dir, "m/up.md2", p, sizeof p), &m, &w);
    assert_string_equal(m.texture, "");
    assert_non_null(strstr(w.text, "'../outside.bmp', which is outside the mesh's folder: rendered untextured"));
    mesh_free(&m);
    assert_int_equal(mkdir(prog_path(dir, "m/d.bmp", p, sizeof p), 0700), 0);
    write_md2_with_skin(dir, "m/dir.md2", "d.bmp");
    load(prog_path(dir, "m/dir.md2", p, sizeof p), &m, &w);
    assert_string_equal(m.texture, "");
    assert_non_null(strstr(w.text, "'d.bmp', which is a directory: rendered untextured"));
    mesh_free(&m);
    prog_rmdir(dir);
}

/* A texture embedded in the file ("*0") is not read: a warning, no texture. */
static void test_embedded(void **state)
{
    (void)state;
    NEED(EMBEDDED);
    is_mesh m;
    warnings w;
    load(EMBEDDED, &m, &w);
    assert_string_equal(m.texture, "");
    assert_non_null(strstr(w.text, "its texture '*0' is embedded in the file, which instess does not read: rendered "
                                   "untextured"));
    mesh_free(&m);
}

/* Built-ins and memory imports have no texture: a memory import that names one says it is not used. */
static void test_no_folder(void **state)
{
    (void)state;
    is_mesh m;
    char err[256];
    assert_int_equal(mesh_builtin("cube", &m, err, sizeof err), 0);
    assert_string_equal(m.texture, "");
    mesh_free(&m);
    NEED(FAERIE);
    char dir[256], p[512];
    assert_int_equal(prog_mkdtemp(dir, "skin-memory"), 0);
    write_md2_with_skin(dir, "q2.md2", "skin.bmp");
    copy_file(MD2_DIR "faerie2.bmp", dir, "skin.bmp");
    size_t n;
    unsigned char *d = prog_slurp(prog_path(dir, "q2.md2", p, sizeof p), &n);
    warnings w = {""};
    is_mesh_options opt = {.warn = collect, .warn_user = &w};
    assert_int_equal(mesh_load_memory(d, n, "md2", "buf", &opt, &m, err, sizeof err), 0);
    assert_string_equal(m.texture, "");
    assert_non_null(strstr(w.text, "buf: its texture 'skin.bmp' is not used: a mesh read from memory has no folder"));
    mesh_free(&m);
    free(d);
    prog_rmdir(dir);
}

/* The program: faerie.md2 without --texture is the file of --texture faerie2.bmp, byte for byte (the same
 * description: the texture's path is the same), and says so on stderr (not with -q); --texture none is the
 * untextured render (the same mesh beside no skin); a mesh whose skin is missing warns and renders untextured. */
static void test_cli_own_texture(void **state)
{
    (void)state;
    NEED(FAERIE);
    char dir[256], a[512], b[512], mesh[512];
    assert_int_equal(prog_mkdtemp(dir, "own-texture"), 0);
    const char *view = "--size 48x80 --yaw 90 --pitch 0 --level 2 --msaa 1";
    const char *e;
    assert_int_equal(prog_run(dir, &e, "", FAERIE " %s -o %s", view, prog_path(dir, "own.png", a, sizeof a)), 0);
    assert_non_null(strstr(e, "instess: " FAERIE ": textured with its own " MD2_DIR "faerie2.bmp (--texture none: "
                              "without)"));
    assert_int_equal(prog_run(dir, &e, "", FAERIE " %s --texture " MD2_DIR "faerie2.bmp -q -o %s", view,
                              prog_path(dir, "given.png", b, sizeof b)), 0);
    assert_true(prog_same_bytes(a, b));
    assert_int_equal(prog_run(dir, &e, "", FAERIE " %s -q -o %s", view, prog_path(dir, "own.png", a, sizeof a)), 0);
    assert_null(strstr(e, "textured with"));
    /* --texture none: the untextured picture, as of the same mesh with no skin beside it */
    assert_int_equal(prog_run(dir, &e, "", FAERIE " %s --texture none -q -o %s", view,
                              prog_path(dir, "none.png", a, sizeof a)), 0);
    assert_false(prog_same_pixels(a, b));
    copy_file(FAERIE, dir, "faerie.md2");
    assert_int_equal(prog_run(dir, &e, "", "%s %s -o %s", prog_path(dir, "faerie.md2", mesh, sizeof mesh), view,
                              prog_path(dir, "bare.png", b, sizeof b)), 0);
    assert_null(strstr(e, "textured with"));
    assert_null(strstr(e, "untextured"));
    assert_true(prog_same_pixels(a, b));
    /* a named skin that is missing: a warning, and the untextured picture */
    write_md2_with_skin(dir, "q2.md2", "skin.bmp");
    assert_int_equal(prog_run(dir, &e, "", "%s %s -q -o %s", prog_path(dir, "q2.md2", mesh, sizeof mesh), view,
                              prog_path(dir, "q2.png", b, sizeof b)), 0);
    assert_non_null(strstr(e, "/q2.md2: its material names the texture 'skin.bmp', which is not in "
                              "the mesh's folder: rendered untextured"));
    assert_true(prog_same_pixels(a, b));
    /* --texture none on a mesh without a texture: the same file as without it */
    assert_int_equal(prog_run(dir, &e, "", "cube --size 32x32 --texture none -q -o %s",
                              prog_path(dir, "c1.png", a, sizeof a)), 0);
    assert_int_equal(prog_run(dir, &e, "", "cube --size 32x32 -q -o %s", prog_path(dir, "c2.png", b, sizeof b)), 0);
    assert_true(prog_same_bytes(a, b));
    prog_rmdir(dir);
}

/* The mesh's own texture is an input: -o never replaces it (as the mesh and --texture's file), nothing written. */
static void test_cli_texture_not_replaced(void **state)
{
    (void)state;
    NEED(FAERIE);
    char dir[256], p[512], mesh[512];
    assert_int_equal(prog_mkdtemp(dir, "own-texture-out"), 0);
    copy_file(FAERIE, dir, "faerie.md2");
    const char *e;
    assert_int_equal(prog_run(dir, &e, "", "cube --size 220x193 -q -o %s", prog_path(dir, "faerie2.png", p, sizeof p)), 0);
    size_t n0, n1;
    unsigned char *before = prog_slurp(p, &n0);
    assert_int_equal(prog_run(dir, &e, "", "%s --size 32x32 -q -o %s", prog_path(dir, "faerie.md2", mesh, sizeof mesh),
                              p), 1);
    assert_non_null(strstr(e, "faerie2.png: is the mesh's own texture; instess will not replace its input"));
    assert_int_equal(prog_run(dir, &e, "", "cube --size 32x32 --texture %s -q -o %s", p, p), 1);
    assert_non_null(strstr(e, "faerie2.png: is the image of --texture; instess will not replace its input"));
    unsigned char *after = prog_slurp(p, &n1);
    assert_true(n0 == n1 && memcmp(before, after, n0) == 0);
    free(before);
    free(after);
    prog_rmdir(dir);
}

/* A texture on a mesh whose file has no texture coordinates (every (u, v) is (0, 0)) shows one texel's colour:
 * the program warns, also with -q, naming the mesh and the texture; a mesh with texture coordinates (the
 * built-in cube) draws the same texture without the warning, and the OBJ without --texture without it too. */
static void test_cli_texture_without_texcoords(void **state)
{
    (void)state;
    char dir[256], tex[512], mesh[512], out[512];
    assert_int_equal(prog_mkdtemp(dir, "no-texcoords"), 0);
    assert_true(prog_write_text(dir, "tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                                "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"));
    const char *e;
    assert_int_equal(prog_run(dir, &e, "", "sphere --size 16x16 -q -o %s", prog_path(dir, "tex.png", tex, sizeof tex)), 0);
    prog_path(dir, "tet.obj", mesh, sizeof mesh);
    assert_int_equal(prog_run(dir, &e, "", "%s --size 24x24 --level 2 --texture %s -q -o %s", mesh, tex,
                              prog_path(dir, "a.png", out, sizeof out)), 0);
    char want[2048];
    snprintf(want, sizeof want, "instess: warning: %s: has no texture coordinates (every vertex's (u, v) is (0, 0)): "
                                "%s draws one colour over it", mesh, tex);
    if (!strstr(e, want)) print_message("stderr: %s\nwant: %s\n", e, want);
    assert_non_null(strstr(e, want));
    assert_int_equal(prog_run(dir, &e, "", "%s --size 24x24 --level 2 -q -o %s", mesh, out), 0);
    assert_null(strstr(e, "no texture coordinates"));
    assert_int_equal(prog_run(dir, &e, "", "cube --size 24x24 --level 2 --texture %s -q -o %s", tex, out), 0);
    assert_null(strstr(e, "no texture coordinates"));
    prog_rmdir(dir);
}

/* The note names a file of the mesh's folder: a control byte in its name reaches the terminal as '?'. */
static void test_cli_note_sanitized(void **state)
{
    (void)state;
    NEED(FAERIE);
    char dir[256], p[512], out[512];
    assert_int_equal(prog_mkdtemp(dir, "own-texture-note"), 0);
    write_md2_with_skin(dir, "q2.md2", "a\x1b[2Jb.bmp");
    copy_file(MD2_DIR "faerie2.bmp", dir, "a\x1b[2Jb.bmp");
    const char *e;
    assert_int_equal(prog_run(dir, &e, "", "%s --size 16x16 --level 1 -o %s", prog_path(dir, "q2.md2", p, sizeof p),
                              prog_path(dir, "q.png", out, sizeof out)), 0);
    assert_non_null(strstr(e, "a?[2Jb.bmp (--texture none: without)"));
    assert_null(strchr(e, '\x1b'));
    prog_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_md2_skins),
        cmocka_unit_test(test_md2_skin_guess),
        cmocka_unit_test(test_named_skin),
        cmocka_unit_test(test_skin_outside),
        cmocka_unit_test(test_embedded),
        cmocka_unit_test(test_no_folder),
        cmocka_unit_test(test_cli_own_texture),
        cmocka_unit_test(test_cli_texture_not_replaced),
        cmocka_unit_test(test_cli_note_sanitized),
        cmocka_unit_test(test_cli_texture_without_texcoords),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
