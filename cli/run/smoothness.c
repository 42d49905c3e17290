/* cli/run/smoothness.c -- `instess smoothness`: for each patch on each built-in mesh (or the meshes given with
 * --mesh), the largest and mean angle between the surface normals on the two sides of shared edges (from the
 * derivatives), their mean at feature edges, the largest valley in a band beside the edges, and the largest
 * distance from the flat triangle (relative to the bounding-box diagonal).
 * Prints a Markdown table. */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "scene.h"

/* Warnings of the mesh loader on stderr. */
static void warn_stderr(void *user, const char *msg)
{
    (void)user;
    fprintf(stderr, "instess: warning: %s\n", msg);
}

/* One table row per patch for the mesh `spec` (a built-in or a file) into f; 0, 1 when the mesh cannot be
 * read (the message on stderr), or 1 when a measurement fails. */
static int print_mesh_rows(const char *spec, bool recompute, int samples, FILE *f)
{
    is_mesh m = {0};
    char err[1024];
    is_mesh_options mo = {.recompute_normals = recompute, .warn = warn_stderr};
    if (mesh_open(spec, &mo, &m, err, sizeof err) != 0) return fprintf(stderr, "instess: %s\n", err), 1;
    for (int p = 0; p < VS_PATCH_COUNT; p++) {
        vs_smoothness_result r;
        vs_options o = vs_default_options();
        o.normals = VS_NORMALS_REAL;
        if (tess_smoothness(&m, (vs_patch)p, &o, samples, &r) != 0) {
            fprintf(stderr, "instess: smoothness of %s on %s failed\n", vs_patch_name((vs_patch)p), spec);
            mesh_free(&m);
            return 1;
        }
        fprintf(f, "| %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.4f |\n", spec, vs_patch_name((vs_patch)p),
                r.max_angle_deg, r.mean_angle_deg, r.max_angle_coplanar_deg, r.max_angle_feature_deg,
                r.mean_angle_feature_deg, r.max_valley_deg, r.max_distance);
    }
    mesh_free(&m);
    return 0;
}

/* The table for the meshes specs[0..n-1] (every built-in when n is 0) into f; 0 or 1 on the first failure. */
static int print_table(const char *const *specs, int n, bool recompute, int samples, FILE *f)
{
    fprintf(f, "| mesh | patch | max angle (deg) | mean angle (deg) | max at coplanar edges | max at feature "
               "edges | mean at feature edges | max valley within 1/16 of an edge | max distance / diagonal |\n");
    fprintf(f, "|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    if (n == 0) {
        for (const char *const *name = mesh_builtin_names(); *name; name++)
            if (print_mesh_rows(*name, recompute, samples, f) != 0) return 1;
        return 0;
    }
    for (int k = 0; k < n; k++)
        if (print_mesh_rows(specs[k], recompute, samples, f) != 0) return 1;
    return 0;
}

#define SMOOTHNESS_USAGE "usage: instess smoothness [--samples N] [--mesh NAME|FILE]... [--recompute-normals]"
enum { SMOOTHNESS_MAX_MESHES = 64 };

int scene_cmd_smoothness(int argc, char **argv)
{
    int samples = 16, n = 0;
    const char *specs[SMOOTHNESS_MAX_MESHES];
    bool recompute = false;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            printf(SMOOTHNESS_USAGE "\n"
                   "For every built-in mesh, or each mesh given with --mesh (a built-in or a file assimp reads), and\n"
                   "every patch: the largest and mean angle between the real normals on the two sides of shared\n"
                   "edges (N samples per edge, 16 by default), split into coplanar and feature edges (where the\n"
                   "faces meet at an angle; their mean too); the largest valley beside the edges: at each sample,\n"
                   "the angle between the normals of the points 1/128 .. 8/128 of the way to the two opposite\n"
                   "corners where they lean towards each other (a concave fold; 0 where they lean apart); and the\n"
                   "largest distance from the flat triangle; a Markdown table.  --recompute-normals ignores the\n"
                   "files' normals.\n");
            return 0;
        }
        if (strcmp(argv[i], "--samples") == 0 && i + 1 < argc) {
            if (!scene_parse_int(argv[++i], 1, 1024, &samples)) {
                fprintf(stderr, "instess: --samples must be 1..1024\n");
                return 2;
            }
        } else if (strcmp(argv[i], "--mesh") == 0 && i + 1 < argc) {
            if (n == SMOOTHNESS_MAX_MESHES) return fprintf(stderr, "instess: at most 64 --mesh\n"), 2;
            specs[n++] = argv[++i];
        } else if (strcmp(argv[i], "--recompute-normals") == 0) {
            recompute = true;
        } else {
            fprintf(stderr, "instess: smoothness: unknown argument or missing value '%s' (" SMOOTHNESS_USAGE ")\n",
                    argv[i]);
            return 2;
        }
    }
    return print_table(specs, n, recompute, samples, stdout);
}
