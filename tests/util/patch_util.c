/* tests/util/patch_util.c -- random triangles and small helpers shared by the patch tests. */
#include "patch_util.h"

#include "../../core/hlsl.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

float frand(uint64_t *s)
{
    *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
    return (float)((*s * 2685821657736338717ull) >> 40) / (float)(1u << 23) - 1.0f;
}

float3 rand3(uint64_t *s) { return f3(frand(s), frand(s), frand(s)); }

bool same3(float3 a, float3 b) { return memcmp(&a, &b, sizeof a) == 0; }

vs_triangle rand_tri(uint64_t *s)
{
    float3 v[3] = {rand3(s), rand3(s), rand3(s)}, n[3];
    float3 up = normalize3(cross3(sub3(v[1], v[0]), sub3(v[2], v[0])));
    for (int k = 0; k < 3; k++) n[k] = normalize3(add3(up, scale3(rand3(s), 0.5f)));
    vs_triangle t = vs_triangle_make(v, n);
    for (int k = 0; k < 3; k++) {
        float3 mid = scale3(add3(v[k], v[(k + 1) % 3]), 0.5f), third = v[(k + 2) % 3];
        t.opp[k] = add3(add3(mid, sub3(mid, third)), scale3(up, frand(s)));
    }
    return t;
}

void to_d(const vs_triangle *t, double v[3][3], double n[3][3], double opp[3][3])
{
    for (int k = 0; k < 3; k++) {
        v[k][0] = t->v[k].x, v[k][1] = t->v[k].y, v[k][2] = t->v[k].z;
        n[k][0] = t->n[k].x, n[k][1] = t->n[k].y, n[k][2] = t->n[k].z;
        opp[k][0] = t->opp[k].x, opp[k][1] = t->opp[k].y, opp[k][2] = t->opp[k].z;
    }
}

double dist_d(float3 a, const double b[3])
{
    double x = a.x - b[0], y = a.y - b[1], z = a.z - b[2];
    return sqrt(x * x + y * y + z * z);
}

vs_triangle rotate(const vs_triangle *t, int r)
{
    vs_triangle o = *t;
    for (int k = 0; k < 3; k++) {
        int j = (k + r) % 3;
        o.v[k] = t->v[j], o.n[k] = t->n[j], o.opp[k] = t->opp[j], o.t[k] = t->t[j];
        o.nadj[k][0] = t->nadj[j][0], o.nadj[k][1] = t->nadj[j][1];
    }
    return o;
}

int cubes_mesh(int side, is_mesh *out)
{
    char err[256];
    is_mesh cube = {0};
    if (mesh_builtin("cube", &cube, err, sizeof err) != 0) return -1;
    if (side == 1) return *out = cube, 0;
    size_t copies = (size_t)side * (size_t)side, nv = cube.n_vertices, nt = cube.n_triangles;
    float3 *p = malloc(copies * nv * sizeof *p), *n = malloc(copies * nv * sizeof *n);
    uint32_t *idx = malloc(copies * nt * 3 * sizeof *idx);
    int rc = p && n && idx ? 0 : -1;
    for (size_t c = 0; rc == 0 && c < copies; c++) {
        float ox = ((float)(c % (size_t)side) - 0.5f * (float)(side - 1)) * 3.0f;
        float oy = ((float)(c / (size_t)side) - 0.5f * (float)(side - 1)) * 3.0f;
        for (size_t k = 0; k < nv; k++) p[c * nv + k] = add3(cube.positions[k], f3(ox, oy, 0.0f)), n[c * nv + k] = cube.normals[k];
        for (size_t k = 0; k < 3 * nt; k++) idx[c * 3 * nt + k] = (uint32_t)(c * nv) + cube.indices[k];
    }
    is_mesh_data md = {copies * nv, copies * nt, p, n, NULL, idx};
    if (rc == 0) rc = mesh_create(out, "cubes", &md, NULL, err, sizeof err) == 0 ? 0 : -1;
    free(p), free(n), free(idx);
    mesh_free(&cube);
    return rc;
}

int clear_and_draw(is_device *dev, const scene_opts *o, const is_mesh *m)
{
    core_grid g;
    if (core_grid_make(o->grid, o->level, &g) != 0) return -1;
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, o->background, 1.0f);
    int rc = scene_draw(dev, o, m, &g, NULL);
    if (rc) fprintf(stderr, "draw failed: %s\n", dev_last_error(dev));
    core_grid_free(&g);
    return rc;
}

float lcg_float(uint32_t *st, float lo, float hi)
{
    *st = *st * 1664525u + 1013904223u;
    return lo + (hi - lo) * (float)(*st >> 8) * (1.0f / 16777216.0f);
}

void random_instance_regs(uint32_t *st, int t, is_vs_input *in)
{
    for (size_t k = 0; k < sizeof *in / sizeof(float4); k++) ((float4 *)in)[k] = f4(0, 0, 0, 1);
    for (int r = 0; r < 13; r++)
        in->texcoord[r] = f4(lcg_float(st, -1, 1), lcg_float(st, -1, 1), lcg_float(st, -1, 1), 1);
    for (int k = 0; k < 3; k++) in->texcoord[VS_IN_N0 + k] = f4_of(normalize3(f3_of(in->texcoord[VS_IN_N0 + k])), 1);
    int family = t % 5;
    if (family == 1) in->texcoord[1] = in->texcoord[0], in->texcoord[4] = in->texcoord[3];
    if (family == 2) in->texcoord[VS_IN_N0 + 1] = f4(0, 0, 0, 1);
    if (family == 3) in->texcoord[2] = f4(3e38f, -3e38f, 3e38f, 1);
    if (family == 4) in->texcoord[VS_IN_OPP0 + 1] = in->texcoord[0]; /* boundary edge: fn = 1 */
}
