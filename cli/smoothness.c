/* cli/smoothness.c -- `instess smoothness`: for each patch on each built-in mesh, the largest and mean angle
 * between the surface normals on the two sides of shared edges (from the derivatives) and the largest
 * distance from the flat triangle (relative to the bounding-box diagonal).  Prints a Markdown table. */
#include <stdio.h>
#include <string.h>

#include "scene.h"

/* Print one table row per (mesh, patch); returns 0 or 1 on the first failure. */
static int print_table(int samples, FILE *f)
{
    fprintf(f, "| mesh | patch | max angle (deg) | mean angle (deg) | max at coplanar edges | max at feature "
               "edges | max distance / diagonal |\n");
    fprintf(f, "|---|---|---:|---:|---:|---:|---:|\n");
    for (const char *const *name = mesh_builtin_names(); *name; name++) {
        is_mesh m = {0};
        char err[512];
        if (mesh_builtin(*name, &m, err, sizeof err) != 0) return fprintf(stderr, "instess: %s\n", err), 1;
        for (int p = 0; p < VS_PATCH_COUNT; p++) {
            vs_smoothness_result r;
            vs_options o = vs_default_options();
            o.normals = VS_NORMALS_REAL;
            if (vs_smoothness((vs_patch)p, &o, m.positions, m.normals, m.n_vertices, m.indices, m.n_triangles, NULL,
                              samples, &r) != 0) {
                fprintf(stderr, "instess: smoothness of %s on %s failed\n", vs_patch_name((vs_patch)p), *name);
                mesh_free(&m);
                return 1;
            }
            fprintf(f, "| %s | %s | %.2f | %.2f | %.2f | %.2f | %.4f |\n", *name, vs_patch_name((vs_patch)p),
                    r.max_angle_deg, r.mean_angle_deg, r.max_angle_coplanar_deg, r.max_angle_feature_deg,
                    r.max_distance);
        }
        mesh_free(&m);
    }
    return 0;
}

int scene_cmd_smoothness(int argc, char **argv)
{
    int samples = 16;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            printf("usage: instess smoothness [--samples N]\n"
                   "For every built-in mesh and patch: the largest and mean angle between the real normals on the\n"
                   "two sides of shared edges (N samples per edge, 16 by default), split into coplanar and\n"
                   "feature edges, and the largest distance from the flat triangle; a Markdown table.\n");
            return 0;
        }
        if (strcmp(argv[i], "--samples") == 0 && i + 1 < argc) {
            if (!scene_parse_int(argv[++i], 1, 1024, &samples)) {
                fprintf(stderr, "instess: --samples must be 1..1024\n");
                return 2;
            }
        } else {
            fprintf(stderr, "instess: smoothness: unknown argument '%s' (usage: instess smoothness [--samples N])\n",
                    argv[i]);
            return 2;
        }
    }
    return print_table(samples, stdout);
}
