/* meshes/builtin.c -- the built-in meshes, closed and wound clockwise from outside (see meshes.h). */
#include "meshes.h"

#include "../core/hlsl.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

#define MAXV 256
#define MAXT 256
#define PI_D 3.14159265358979323846

/* A small mesh under construction (lives on the stack). */
typedef struct builder {
    size_t nv, nt;
    float3 p[MAXV], n[MAXV];
    float2 uv[MAXV];
    uint32_t idx[3 * MAXT];
} builder;

static const char *const builtin_names[] = {
    "tetrahedron", "cube", "cube-split", "octahedron", "icosahedron", "sphere", "cylinder", NULL
};

/* mesh_builtin_names: see meshes.h. */
const char *const *mesh_builtin_names(void) { return builtin_names; }

/* Append a vertex; returns its index. */
static uint32_t add_vertex(builder *b, float3 p, float3 n, float2 uv)
{
    b->p[b->nv] = p;
    b->n[b->nv] = n;
    b->uv[b->nv] = uv;
    return (uint32_t)b->nv++;
}

/* Append a triangle. */
static void add_tri(builder *b, uint32_t i0, uint32_t i1, uint32_t i2)
{
    b->idx[3 * b->nt + 0] = i0;
    b->idx[3 * b->nt + 1] = i1;
    b->idx[3 * b->nt + 2] = i2;
    b->nt++;
}

/* Planar texcoords from x and y (D3D: v down), for shapes without a natural unwrap. */
static float2 planar_uv(float3 p) { return f2(0.5f * (p.x + 1.0f), 0.5f * (1.0f - p.y)); }

/* Built-ins are convex and centred at the origin: make every face's outward normal cross(v1-v0, v2-v0)
 * point away from the origin by swapping two corners where it does not. */
static void orient_outward(builder *b)
{
    for (size_t t = 0; t < b->nt; t++) {
        uint32_t *tri = b->idx + 3 * t;
        float3 c = scale3(add3(add3(b->p[tri[0]], b->p[tri[1]]), b->p[tri[2]]), 1.0f / 3.0f);
        float3 fn = cross3(sub3(b->p[tri[1]], b->p[tri[0]]), sub3(b->p[tri[2]], b->p[tri[0]]));
        if (dot3(fn, c) < 0.0f) { uint32_t s = tri[1]; tri[1] = tri[2]; tri[2] = s; }
    }
}

/* Vertices on the unit-length directions of pts (normal = position normalized), planar texcoords. */
static void add_radial_vertices(builder *b, const float3 *pts, size_t n, float scale)
{
    for (size_t i = 0; i < n; i++) {
        float3 u = normalize3(pts[i]);
        float3 p = scale3(u, scale);
        add_vertex(b, p, u, planar_uv(p));
    }
}

/* Regular tetrahedron on alternate corners of the cube [-1, 1]^3. */
static void build_tetrahedron(builder *b)
{
    static const float3 c[4] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    for (int i = 0; i < 4; i++) add_vertex(b, c[i], normalize3(c[i]), planar_uv(c[i]));
    add_tri(b, 0, 1, 2); add_tri(b, 0, 3, 1); add_tri(b, 0, 2, 3); add_tri(b, 1, 3, 2);
    orient_outward(b);
}

/* Face frames of the cube: outward normal N and "up" V seen from outside; right U = cross(N, V). */
static const float3 cube_face_n[6] = {{0, 1, 0}, {0, -1, 0}, {-1, 0, 0}, {1, 0, 0}, {0, 0, -1}, {0, 0, 1}};
static const float3 cube_face_up[6] = {{0, 0, 1}, {0, 0, -1}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}};

/* Corner q (0 top-left, 1 top-right, 2 bottom-right, 3 bottom-left, as seen from outside) of cube face f.
 * Seen from outside on a left-handed screen, 0 -> 1 -> 2 is clockwise: the triangles (0,1,2), (0,2,3) face out. */
static float3 cube_corner(int f, int q)
{
    static const float su[4] = {-1, 1, 1, -1}, sv[4] = {1, 1, -1, -1};
    float3 n = cube_face_n[f], v = cube_face_up[f], u = cross3(n, v);
    return add3(n, add3(scale3(u, su[q]), scale3(v, sv[q])));
}

/* Index of the welded cube's vertex at corner c = (+-1, +-1, +-1). */
static uint32_t cube_vertex_index(float3 c)
{
    return (uint32_t)((c.x > 0) * 4 + (c.y > 0) * 2 + (c.z > 0));
}

/* The welded cube: 8 vertices, normals along the diagonals, 12 triangles (same order as cube-split). */
static void build_cube(builder *b)
{
    for (int i = 0; i < 8; i++) {
        float3 p = f3(i & 4 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 1 ? 1.0f : -1.0f);
        add_vertex(b, p, normalize3(p), planar_uv(p));
    }
    for (int f = 0; f < 6; f++) {
        uint32_t q[4];
        for (int k = 0; k < 4; k++) q[k] = cube_vertex_index(cube_corner(f, k));
        add_tri(b, q[0], q[1], q[2]);
        add_tri(b, q[0], q[2], q[3]);
    }
}

/* The DirectX SDK cube: 4 vertices per face with the face normal and the full texture. */
static void build_cube_split(builder *b)
{
    static const float2 uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int f = 0; f < 6; f++) {
        uint32_t base = (uint32_t)b->nv;
        for (int k = 0; k < 4; k++) add_vertex(b, cube_corner(f, k), cube_face_n[f], uv[k]);
        add_tri(b, base, base + 1, base + 2);
        add_tri(b, base, base + 2, base + 3);
    }
}

/* Octahedron: vertices on the axes, radius 1. */
static void build_octahedron(builder *b)
{
    static const float3 c[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    add_radial_vertices(b, c, 6, 1.0f);
    for (int ix = 0; ix < 2; ix++)
        for (int iy = 2; iy < 4; iy++)
            for (int iz = 4; iz < 6; iz++) add_tri(b, (uint32_t)ix, (uint32_t)iy, (uint32_t)iz);
    orient_outward(b);
}

static const uint8_t ico_faces[20][3] = {
    {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2},
    {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5},
    {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};

/* The 12 icosahedron directions (golden rectangles). */
static void ico_points(float3 *pts)
{
    const float g = (float)((1.0 + sqrt(5.0)) / 2.0);
    const float3 c[12] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                          {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    memcpy(pts, c, sizeof c);
}

/* Icosahedron, radius 1. */
static void build_icosahedron(builder *b)
{
    float3 pts[12];
    ico_points(pts);
    add_radial_vertices(b, pts, 12, 1.0f);
    for (int f = 0; f < 20; f++) add_tri(b, ico_faces[f][0], ico_faces[f][1], ico_faces[f][2]);
    orient_outward(b);
}

/* Index of the midpoint vertex of edge (i, j) on the unit sphere, created once per edge. */
static uint32_t midpoint(builder *b, uint32_t (*edges)[3], size_t *ne, uint32_t i, uint32_t j)
{
    uint32_t lo = i < j ? i : j, hi = i < j ? j : i;
    for (size_t e = 0; e < *ne; e++)
        if (edges[e][0] == lo && edges[e][1] == hi) return edges[e][2];
    float3 u = normalize3(add3(b->p[lo], b->p[hi]));
    uint32_t m = add_vertex(b, u, u, f2(0, 0));
    edges[*ne][0] = lo; edges[*ne][1] = hi; edges[*ne][2] = m;
    (*ne)++;
    return m;
}

/* Spherical texcoords: u around y from the seam at -x, v from the top (+y) down. */
static float2 sphere_uv(float3 p)
{
    double u = 0.5 + atan2((double)p.z, (double)-p.x) / (2.0 * PI_D);
    double v = acos(fmax(-1.0, fmin(1.0, (double)p.y))) / PI_D;
    return f2((float)u, (float)v);
}

/* Whether p is on the y axis (a pole, where u is undefined). */
static bool is_pole(float3 p) { return fabsf(p.x) < 1e-6f && fabsf(p.z) < 1e-6f; }

/* Copy of vertex v with texcoord uv (a split vertex: same position and normal). */
static uint32_t split_vertex(builder *b, uint32_t v, float2 uv) { return add_vertex(b, b->p[v], b->n[v], uv); }

/* Triangles crossing the u seam get copies of their low-u corners with u + 1 (one copy per vertex). */
static void fix_seam(builder *b, size_t nv0)
{
    uint32_t copy[MAXV];
    memset(copy, 0xff, sizeof copy);
    for (size_t t = 0; t < b->nt; t++) {
        uint32_t *tri = b->idx + 3 * t;
        float lo = 2.0f, hi = -1.0f;
        for (int k = 0; k < 3; k++)
            if (!is_pole(b->p[tri[k]])) { lo = fminf(lo, b->uv[tri[k]].x); hi = fmaxf(hi, b->uv[tri[k]].x); }
        if (hi - lo <= 0.5f) continue;
        for (int k = 0; k < 3; k++) {
            uint32_t v = tri[k];
            if (v >= nv0 || is_pole(b->p[v]) || b->uv[v].x >= 0.5f) continue;
            if (copy[v] == UINT32_MAX) copy[v] = split_vertex(b, v, f2(b->uv[v].x + 1.0f, b->uv[v].y));
            tri[k] = copy[v];
        }
    }
}

/* Pole corners get a copy per triangle with u = the mean of the triangle's other two corners. */
static void fix_poles(builder *b)
{
    for (size_t t = 0; t < b->nt; t++) {
        uint32_t *tri = b->idx + 3 * t;
        for (int k = 0; k < 3; k++) {
            if (!is_pole(b->p[tri[k]])) continue;
            float u = 0.5f * (b->uv[tri[(k + 1) % 3]].x + b->uv[tri[(k + 2) % 3]].x);
            tri[k] = split_vertex(b, tri[k], f2(u, b->uv[tri[k]].y));
        }
    }
}

/* Geodesic sphere: the icosahedron subdivided once (80 triangles), radius 1, normals = positions,
 * spherical texcoords with split vertices along the seam and at the poles. */
static void build_sphere(builder *b)
{
    build_icosahedron(b);
    uint32_t faces[20][3], edges[30][3];
    size_t ne = 0;
    memcpy(faces, b->idx, sizeof faces);
    b->nt = 0;
    for (int f = 0; f < 20; f++) {
        uint32_t a = faces[f][0], c = faces[f][1], d = faces[f][2];
        uint32_t ac = midpoint(b, edges, &ne, a, c), cd = midpoint(b, edges, &ne, c, d);
        uint32_t da = midpoint(b, edges, &ne, d, a);
        add_tri(b, a, ac, da); add_tri(b, ac, c, cd); add_tri(b, da, cd, d); add_tri(b, ac, cd, da);
    }
    for (size_t v = 0; v < b->nv; v++) b->uv[v] = sphere_uv(b->p[v]);
    orient_outward(b);
    fix_seam(b, b->nv);
    fix_poles(b);
}

/* Cylinder: 12 sides, radius 1, y in [-1, 1]; smooth sides, flat caps, split normals at the rims. */
static void build_cylinder(builder *b)
{
    enum { SIDES = 12 };
    uint32_t top[SIDES + 1], bot[SIDES + 1];
    for (int i = 0; i <= SIDES; i++) {          /* side rings, seam duplicated for u = 0 and 1 */
        double a = 2.0 * PI_D * (i % SIDES) / SIDES;
        float3 r = f3((float)cos(a), 0.0f, (float)sin(a));
        top[i] = add_vertex(b, f3(r.x, 1.0f, r.z), r, f2((float)i / SIDES, 0.0f));
        bot[i] = add_vertex(b, f3(r.x, -1.0f, r.z), r, f2((float)i / SIDES, 1.0f));
    }
    for (int i = 0; i < SIDES; i++) {
        add_tri(b, top[i], top[i + 1], bot[i + 1]);
        add_tri(b, top[i], bot[i + 1], bot[i]);
    }
    for (int s = 0; s < 2; s++) {               /* caps */
        float y = s ? -1.0f : 1.0f;
        uint32_t c = add_vertex(b, f3(0, y, 0), f3(0, y, 0), f2(0.5f, 0.5f)), rim[SIDES];
        for (int i = 0; i < SIDES; i++) {
            double a = 2.0 * PI_D * i / SIDES;
            float3 p = f3((float)cos(a), y, (float)sin(a));
            rim[i] = add_vertex(b, p, f3(0, y, 0), f2(0.5f + 0.5f * p.x, 0.5f - 0.5f * p.z));
        }
        for (int i = 0; i < SIDES; i++) add_tri(b, c, rim[i], rim[(i + 1) % SIDES]);
    }
    orient_outward(b);
}

typedef void (*build_fn)(builder *b);

/* The builder of a built-in name, or NULL. */
static build_fn find_builder(const char *name)
{
    static const build_fn fns[] = {build_tetrahedron, build_cube, build_cube_split, build_octahedron,
                                   build_icosahedron, build_sphere, build_cylinder};
    for (size_t i = 0; builtin_names[i]; i++)
        if (strcmp(name, builtin_names[i]) == 0) return fns[i];
    return NULL;
}

/* mesh_builtin_ex: see meshes.h. */
int mesh_builtin_ex(const char *name, const is_mesh_options *opt, is_mesh *out, char *err, size_t errlen)
{
    build_fn fn = name ? find_builder(name) : NULL;
    if (!fn) {
        if (err && errlen)
            snprintf(err, errlen, "unknown built-in mesh '%s' (built-ins: tetrahedron, cube, cube-split, "
                     "octahedron, icosahedron, sphere, cylinder)", name ? name : "(null)");
        if (out) memset(out, 0, sizeof *out);
        return IS_MESH_ERR_ARG;
    }
    builder b;
    memset(&b, 0, sizeof b);
    fn(&b);
    is_mesh_data d = {b.nv, b.nt, b.p, b.n, b.uv, b.idx};
    return mesh_create(out, name, &d, opt, err, errlen);
}

/* mesh_builtin: see meshes.h. */
int mesh_builtin(const char *name, is_mesh *out, char *err, size_t errlen)
{
    return mesh_builtin_ex(name, NULL, out, err, errlen);
}
