/* cli/run/render_call.c -- the program's render as one call: scene_render_args, the entry point of the module
 * libinstess_run.so that the Python package (python/instess) opens.  Same options, same pixels as
 * `instess ARGS -o FILE`, without the file: the image comes back in memory. */
#include "scene.h"

#include <stdlib.h>
#include <string.h>

/* The notes of one call: the mesh loader's warnings and the changes made to what was asked, one per line. */
typedef struct notes {
    char *buf;
    size_t len, used;
} notes;

/* Append msg and a newline to the notes (as much as fits). */
static void note(void *user, const char *msg)
{
    notes *n = user;
    if (!n->buf || n->len == 0 || n->used + 1 >= n->len) return;
    int k = snprintf(n->buf + n->used, n->len - n->used, "%s\n", msg);
    if (k > 0) n->used = n->used + (size_t)k < n->len ? n->used + (size_t)k : n->len - 1;
}

/* The options of argv (without the program's name) into o, checked as the program checks them, for a file of
 * format fmt that is not written; 0 or -1 with the usage error.  args (argc + 1 entries) holds the copy getopt
 * reorders and o points into. */
static int parse(int argc, const char *const argv[], is_image_format fmt, char **args, scene_opts *o, notes *n,
                 char *err, size_t errlen)
{
    args[0] = (char *)"instess";
    for (int k = 0; k < argc; k++) args[k + 1] = (char *)argv[k];
    scene_opts_default(o);
    scene_args_result res;
    if (scene_parse_args(argc + 1, args, o, &res, err, errlen) != 0) return -1;
    if (res != SCENE_ARGS_RUN) return snprintf(err, errlen, "--help and --version are not renders"), -1;
    if (o->output || o->export_obj || o->stats_json)
        return snprintf(err, errlen, "-o, --export-obj and --stats: this call writes no file and prints nothing (the "
                        "image is returned)"), -1;
    o->output = fmt == IS_IMAGE_EXR ? "(memory).exr" : "(memory).png";   /* that format's colour; not written */
    const char *msg = scene_check_opts(o);
    if (msg) return snprintf(err, errlen, "%s", msg), -1;
    if (o->grid != CORE_GRID_REGULAR && core_grid_pg_clamp(o->grid, o->level) != o->level) {   /* as the program */
        char line[200];
        float used = core_grid_pg_clamp(o->grid, o->level);
        snprintf(line, sizeof line, "--level %g is outside the range of --grid %s; rendering level %g",
                 (double)o->level, scene_grid_name(o->grid), (double)used);
        note(n, line);
        o->level = used;
    }
    return 0;
}

int scene_render_args(int argc, const char *const argv[], is_image_format fmt, is_image *img, char *notes_buf,
                      size_t notes_len, char *err, size_t errlen)
{
    notes n = {notes_buf, notes_len, 0};
    if (notes_buf && notes_len) notes_buf[0] = '\0';
    if (!img || argc < 0 || (argc > 0 && !argv) || (fmt != IS_IMAGE_PNG && fmt != IS_IMAGE_EXR))
        return snprintf(err, errlen, "scene_render_args: bad arguments"), -1;
    memset(img, 0, sizeof *img);
    char **args = calloc((size_t)argc + 2, sizeof *args);
    if (!args) return snprintf(err, errlen, "out of memory"), -1;
    scene_opts o;
    int rc = parse(argc, argv, fmt, args, &o, &n, err, errlen);
    is_mesh m = {0};
    is_image map = {0};
    if (rc == 0 && o.displace && (rc = scene_load_displacement(o.displace, &map, err, errlen)) == 0)
        o.displace_map = &map;
    is_mesh_options mo = scene_mesh_options(&o, note, &n);
    if (rc == 0) rc = mesh_open(o.mesh, &mo, &m, err, errlen);
    if (rc == 0) scene_use_mesh_texture(&o, &m, note, &n);
    char misfit[1000];
    if (rc == 0 && scene_texture_misfit(&o, &m, misfit, sizeof misfit)) note(&n, misfit);
    if (rc == 0) rc = scene_render_mesh(&o, &m, img, NULL, err, errlen);
    mesh_free(&m);
    image_free(&map);
    free(args);
    return rc;
}
