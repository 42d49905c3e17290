/* cli/figures/fig_diagrams.c -- the explanatory drawings of the three source documents (docs/design.md, section 5), drawn with
 * the canvas of cli/figures/canvas.c from the project's own formulas (vs/: vs_evaluate_curve, vs_patch_eval,
 * vs_npatch_evaluate; core/: core_grid_regular, core_grid_pg), so every diagram shows what the code computes.
 *
 * Conventions: every diagram is 900x600 (360x240 when ctx->small: geometry and text scaled by 0.4) on a white
 * background, in a frame of 9 x 6 units (y up).  One palette for all: dark ink for geometry and labels, blue /
 * orange / green for the three things a diagram tells apart (edges, patches, sub-triangles), green for normals,
 * orange for derivatives, red for the constructed result, purple for planes.  3D diagrams use one curved triangle
 * (demo_triangle) seen from above by a perspective camera. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "figures.h"

#include "../../core/hlsl.h"
/* ------------------------------------------------------------------ style */

static const float BG[4] = {1.0f, 1.0f, 1.0f, 1.0f};
static const float INK[4] = {0.10f, 0.10f, 0.13f, 1.0f};
static const float GREY[4] = {0.55f, 0.55f, 0.58f, 1.0f};
static const float LIGHT[4] = {0.80f, 0.80f, 0.83f, 1.0f};
static const float BLUE[4] = {0.12f, 0.38f, 0.78f, 1.0f};
static const float ORANGE[4] = {0.90f, 0.45f, 0.05f, 1.0f};
static const float GREEN[4] = {0.10f, 0.58f, 0.25f, 1.0f};
static const float RED[4] = {0.82f, 0.12f, 0.15f, 1.0f};
static const float PURPLE[4] = {0.55f, 0.25f, 0.70f, 1.0f};
static const float FILL_BLUE[4] = {0.12f, 0.38f, 0.78f, 0.30f};
static const float FILL_ORANGE[4] = {0.90f, 0.45f, 0.05f, 0.30f};
static const float FILL_GREEN[4] = {0.10f, 0.58f, 0.25f, 0.30f};
static const float FILL_RED[4] = {0.82f, 0.12f, 0.15f, 0.35f};
static const float FILL_TRI[4] = {0.70f, 0.80f, 0.95f, 0.45f};

#define FW 9.0f  /* frame width in units */
#define FH 6.0f  /* frame height */
#define PI_F 3.14159265f

/* A diagram being drawn: the canvas, the scales of the size asked for, and the panel of 3D projections. */
typedef struct dg {
    fig_canvas *c;
    float k;        /* geometry scale: line widths, radii, dashes in pixels are multiplied by it */
    float kt;       /* text scale: sizes and pixel offsets of labels */
    float2 plo, phi; /* panel (frame rectangle) onto which dg_proj maps the view's [-1, 1]^2 */
} dg;

/* Start a 9 x 6 diagram of the size ctx asks for; 0 or -1. */
static int dg_begin(dg *d, const fig_ctx *ctx, char *err, size_t errlen)
{
    bool small = ctx && ctx->small;
    d->k = small ? 0.4f : 1.0f;
    d->kt = small ? 0.4f : 1.0f;
    d->plo = f2(0, 0), d->phi = f2(FW, FH);
    d->c = canvas_create(small ? 360 : 900, small ? 240 : 600, BG, 0.0f, 0.0f, FW, FH, err, errlen);
    return d->c ? 0 : -1;
}

/* Resolve into out and free the canvas; 0 or -1. */
static int dg_end(dg *d, is_image *out, char *err, size_t errlen)
{
    int rc = canvas_finish(d->c, out, err, errlen);
    canvas_destroy(d->c);
    return rc;
}

/* Line, dashed line, arrow and point with widths given at full size. */
static void ln(dg *d, float2 a, float2 b, float w, const float *col) { canvas_line(d->c, a, b, w * d->k, col); }
static void dash(dg *d, float2 a, float2 b, float w, const float *col)
{
    canvas_dashed_line(d->c, a, b, w * d->k, 7.0f * d->k, col);
}
static void arrow(dg *d, float2 a, float2 b, float w, const float *col) { canvas_arrow(d->c, a, b, w * d->k, col); }
static void dot_at(dg *d, float2 p, float r, const float *col) { canvas_point(d->c, p, r * d->k, col); }

/* A hollow point: a ring (dark disc with a white centre). */
static void ring_at(dg *d, float2 p, float r, const float *col)
{
    canvas_point(d->c, p, r * d->k, col);
    canvas_point(d->c, p, (r - 2.0f) * d->k, BG);
}

/* Text of full-size size px whose anchor (p + (dx, dy) px) is at its left (ha 0), centre (0.5) or right (1),
 * vertically centred on the anchor. */
static void text(dg *d, float2 p, float dx, float dy, float ha, const char *s, float size, const float *col)
{
    int w = 0, h = 0;
    float sz = size * d->kt;
    if (ha != 0.0f) image_text_size(s, sz, &w, &h);
    canvas_text(d->c, p, dx * d->kt - ha * (float)w, dy * d->kt + 0.36f * sz, s, sz, col);
}

/* Left-aligned lines of text from p downwards, line spacing 1.45 size. */
static void text_lines(dg *d, float2 p, const char *const *lines, int n, float size, const float *col)
{
    for (int i = 0; i < n; i++) text(d, p, 0.0f, (float)i * 1.45f * size, 0.0f, lines[i], size, col);
}

/* The heading at the top left of the frame. */
static void heading(dg *d, const char *s) { text(d, f2(0.05f, FH - 0.1f), 0.0f, 0.0f, 0.0f, s, 20.0f, INK); }

/* A legend entry: a short sample line (or an arrow when arrow_ is set) and its text. */
static void legend(dg *d, float2 p, const float *col, bool dashed, bool arrow_, const char *s)
{
    float2 q = f2(p.x + 0.45f, p.y);
    if (arrow_) arrow(d, p, q, 2.5f, col);
    else if (dashed) dash(d, p, q, 2.0f, col);
    else ln(d, p, q, 3.0f, col);
    text(d, q, 10.0f, 0.0f, 0.0f, s, 15.0f, INK);
}

/* A legend entry for a filled area: a small square and its text. */
static void legend_fill(dg *d, float2 p, const float *col, const char *s)
{
    float2 a = f2(p.x + 0.07f, p.y - 0.1f), b = f2(p.x + 0.37f, p.y - 0.1f), c = f2(p.x + 0.37f, p.y + 0.1f),
           e = f2(p.x + 0.07f, p.y + 0.1f);
    canvas_triangle(d->c, a, b, c, col);
    canvas_triangle(d->c, a, c, e, col);
    text(d, f2(p.x + 0.45f, p.y), 10.0f, 0.0f, 0.0f, s, 15.0f, INK);
}

/* A polyline through n points. */
static void polyline(dg *d, const float2 *p, int n, float w, const float *col)
{
    for (int i = 0; i + 1 < n; i++) ln(d, p[i], p[i + 1], w, col);
}

/* A dashed polyline: dashes of len frame units measured along the curve. */
static void dashed_polyline(dg *d, const float2 *p, int n, float w, float len, const float *col)
{
    float s = 0.0f;
    for (int i = 0; i + 1 < n; i++) {
        float dx = p[i + 1].x - p[i].x, dy = p[i + 1].y - p[i].y, l = sqrtf(dx * dx + dy * dy);
        if ((int)floorf(s / len) % 2 == 0) ln(d, p[i], p[i + 1], w, col);
        s += l;
    }
}

/* A right-angle marker at corner o between directions u and v (unit, frame units), size r. */
static void right_angle(dg *d, float2 o, float2 u, float2 v, float r, const float *col)
{
    float2 a = add2(o, scale2(u, r)), b = add2(add2(o, scale2(u, r)), scale2(v, r)), c = add2(o, scale2(v, r));
    ln(d, a, b, 1.5f, col);
    ln(d, b, c, 1.5f, col);
}

/* 2D vector helpers. */
static float2 sub2(float2 a, float2 b) { return f2(a.x - b.x, a.y - b.y); }
static float dot2(float2 a, float2 b) { return a.x * b.x + a.y * b.y; }
static float len2(float2 a) { return sqrtf(dot2(a, a)); }
static float2 norm2(float2 a)
{
    float l = len2(a);
    return l > 0.0f ? scale2(a, 1.0f / l) : a;
}
static float2 lerp2(float2 a, float2 b, float t) { return f2(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t); }
static float2 xy(float3 a) { return f2(a.x, a.y); }
static float3 xy0(float2 a) { return f3(a.x, a.y, 0.0f); }

/* ------------------------------------------------------------------ 3D views */

/* The curved triangle of the 3D diagrams: in the plane y = 0, normals from a centre below (a piece of a
 * sphere-like surface that bulges up). */
static void demo_triangle(float3 v[3], float3 n[3])
{
    v[0] = f3(-1.0f, 0.0f, -0.6f);
    v[1] = f3(1.0f, 0.0f, -0.6f);
    v[2] = f3(0.0f, 0.0f, 1.1f);
    const float3 c = f3(0.1f, -1.5f, 0.05f);
    for (int k = 0; k < 3; k++) n[k] = normalize3(sub3(v[k], c));
}

/* Set the camera (eye, at, vertical field of view) and the panel [lo, hi] the view is shown in. */
static void dg_view(dg *d, float2 lo, float2 hi, float3 eye, float3 at, float fov_deg)
{
    float4x4 view = mat_look_at_lh(eye, at, f3(0, 1, 0));
    float4x4 proj = mat_perspective_fov_lh(fov_deg * PI_F / 180.0f, (hi.x - lo.x) / (hi.y - lo.y), 0.1f, 20.0f);
    float4x4 wvp = mat_mul(&view, &proj);
    canvas_set_view(d->c, &wvp);
    d->plo = lo, d->phi = hi;
}

/* Project a 3D point into the current panel (canvas_project maps onto the whole 9 x 6 frame). */
static float2 pj(const dg *d, float3 p)
{
    float2 q = canvas_project(d->c, p);
    return f2(d->plo.x + q.x / FW * (d->phi.x - d->plo.x), d->plo.y + q.y / FH * (d->phi.y - d->plo.y));
}

/* The shaded N-Patch (vs_patch_eval, level 16) of triangle v, n: light blue, lit from above. */
static void draw_patch_surface(dg *d, const float3 v[3], const float3 n[3], float alpha)
{
    enum { L = 16 };
    float3 bary[(L + 1) * (L + 2) / 2];
    uint32_t idx[3 * L * L];
    size_t np = core_grid_regular(L, bary, idx);
    vs_triangle tri = vs_triangle_make(v, n);
    float2 q[(L + 1) * (L + 2) / 2];
    float shade[(L + 1) * (L + 2) / 2];
    const float3 light = normalize3(f3(-0.3f, 1.0f, -0.6f));
    for (size_t i = 0; i < np; i++) {
        float3 pos, nrm;
        vs_patch_eval(VS_PATCH_NPATCH, &tri, bary[i], NULL, &pos, &nrm, NULL);
        q[i] = pj(d, pos);
        shade[i] = 0.55f + 0.45f * saturate(dot3(nrm, light));
    }
    for (size_t t = 0; t < (size_t)L * L; t++) {
        float s = (shade[idx[3 * t]] + shade[idx[3 * t + 1]] + shade[idx[3 * t + 2]]) / 3.0f;
        float col[4] = {0.62f * s, 0.74f * s, 0.95f * s, alpha};
        canvas_triangle(d->c, q[idx[3 * t]], q[idx[3 * t + 1]], q[idx[3 * t + 2]], col);
    }
}

/* The border curve of edge a-b (vs_evaluate_curve), projected, as n + 1 points. */
static void border_curve(const dg *d, float3 va, float3 vb, float3 na, float3 nb, float2 *out, int n)
{
    for (int i = 0; i <= n; i++) out[i] = pj(d, vs_evaluate_curve(va, vb, na, nb, (float)i / (float)n));
}

/* The PN control points b_ijk (Eq. 1.1.1, with the /3) as c[i][j], k = 3 - i - j. */
static void pn_control_points(const float3 v[3], const float3 n[3], float3 c[4][4])
{
    memset(c, 0, sizeof(float3) * 16);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            if (i == j) continue;
            float3 t = sub3(add3(scale3(v[i], 2.0f), v[j]), scale3(n[i], dot3(sub3(v[j], v[i]), n[i])));
            int e[3] = {0, 0, 0};
            e[i] = 2, e[j] = 1;
            c[e[0]][e[1]] = scale3(t, 1.0f / 3.0f);
        }
    c[3][0] = v[0], c[0][3] = v[1], c[0][0] = v[2];
    float3 E = f3(0, 0, 0);
    for (int i = 0; i < 4; i++)
        for (int j = 0; i + j <= 3; j++)
            if (i != 3 && j != 3 && i + j != 0 && !(i == 1 && j == 1)) E = add3(E, scale3(c[i][j], 1.0f / 6.0f));
    float3 V = scale3(add3(add3(v[0], v[1]), v[2]), 1.0f / 3.0f);
    c[1][1] = add3(E, scale3(sub3(E, V), 0.5f));
}

/* The reflected mid-edge normal n_ij = normalize(ni + nj - v (Pj - Pi)), v = 2 dot(Pj - Pi, ni + nj) /
 * dot(Pj - Pi, Pj - Pi) (seed 003; vs/patch.c's quadratic normals). */
static float3 mid_edge_normal(float3 pi, float3 pj_, float3 ni, float3 nj)
{
    float3 e = sub3(pj_, pi), s = add3(ni, nj);
    float ee = dot3(e, e);
    float v = ee > 0.0f ? 2.0f * dot3(e, s) / ee : 0.0f;
    return normalize3(sub3(s, scale3(e, v)));
}

/* ------------------------------------------------------------------ fig-1.1.2: control net */

/* Label of control point (i, j, 3-i-j) placed away from the net's centre. */
static void net_label(dg *d, float2 p, float2 centre, int i, int j)
{
    char s[24];
    const char *corner = i == 3 ? " = v0" : (j == 3 ? " = v1" : (i + j == 0 ? " = v2" : ""));
    snprintf(s, sizeof s, "b%d%d%d%s", i, j, 3 - i - j, corner);
    float2 u = sub2(p, centre);
    u = len2(u) > 1e-3f ? norm2(u) : f2(0.0f, 1.0f);
    if (i == 1 && j == 1) u = f2(1.0f, -0.55f); /* b111: in the gap between the lines to b021 and b120 */
    if (i == 3 || j == 3) u = f2(0.0f, -1.0f); /* v0, v1: below; v2: left of its normal */
    if (i + j == 0) u = f2(1.0f, 1.2f);
    if (i + j == 3 && i != 3 && j != 3) u = f2(0.0f, -1.0f); /* b210, b120: below the edge, clear of the curve */
    float ha = u.x > 0.35f ? 0.0f : (u.x < -0.35f ? 1.0f : 0.5f);
    text(d, p, u.x * 14.0f, -u.y * 16.0f, ha, s, 17.0f, RED);
}

/* The net's edges: neighbours (i, j, k) - (i-1, j+1, k), (i-1, j, k+1), (i, j-1, k+1). */
static void net_edges(dg *d, const float2 q[4][4])
{
    for (int i = 0; i <= 3; i++)
        for (int j = 0; i + j <= 3; j++) {
            if (i > 0) ln(d, q[i][j], q[i - 1][j + 1], 2.0f, INK);
            if (i > 0) ln(d, q[i][j], q[i - 1][j], 2.0f, INK);
            if (j > 0) ln(d, q[i][j], q[i][j - 1], 2.0f, INK);
        }
}

/* fig-1.1.2: the N-Patch of one curved triangle under its labelled control net of 10 points. */
static int fig_1_1_2(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) return -1;
    float3 v[3], n[3], c[4][4];
    demo_triangle(v, n);
    pn_control_points(v, n, c);
    dg_view(&d, f2(0.75f, 0.25f), f2(5.6f, 5.45f), f3(0.0f, 5.6f, -3.9f), f3(0.0f, 0.15f, 0.1f), 20.5f);
    draw_patch_surface(&d, v, n, 1.0f);
    for (int k = 0; k < 3; k++) dash(&d, pj(&d, v[k]), pj(&d, v[(k + 1) % 3]), 1.5f, GREY);
    float2 q[4][4], centre = f2(0, 0);
    for (int i = 0; i <= 3; i++)
        for (int j = 0; i + j <= 3; j++) q[i][j] = pj(&d, c[i][j]), centre = add2(centre, scale2(q[i][j], 0.1f));
    float2 cv[3][41];
    for (int e = 0; e < 3; e++) {
        border_curve(&d, v[e], v[(e + 1) % 3], n[e], n[(e + 1) % 3], cv[e], 40);
        polyline(&d, cv[e], 41, 2.0f, BLUE);
    }
    for (int k = 0; k < 3; k++) arrow(&d, pj(&d, v[k]), pj(&d, add3(v[k], scale3(n[k], 0.35f))), 2.5f, GREEN);
    net_edges(&d, (const float2(*)[4])q);
    for (int i = 0; i <= 3; i++)
        for (int j = 0; i + j <= 3; j++) dot_at(&d, q[i][j], 5.5f, RED), net_label(&d, q[i][j], centre, i, j);
    heading(&d, "The 10 control points of the cubic Bezier triangle (N-Patch)");
    float x = 6.15f;
    legend(&d, f2(x, 5.0f), INK, false, false, "control net");
    dot_at(&d, f2(x + 0.22f, 4.55f), 5.5f, RED);
    text(&d, f2(x + 0.45f, 4.55f), 10.0f, 0.0f, 0.0f, "control points b_ijk", 15.0f, INK);
    legend(&d, f2(x, 4.1f), BLUE, false, false, "border curves (edges)");
    legend(&d, f2(x, 3.65f), GREEN, false, true, "vertex normals n0 n1 n2");
    legend_fill(&d, f2(x, 3.2f), FILL_TRI, "the patch P(b0, b1, b2)");
    legend(&d, f2(x, 2.8f), GREY, true, false, "the flat triangle");
    static const char *const eq[] = {
        "b_ijk (i + j + k = 3) is weighted by",
        "  3!/(i! j! k!) b0^i b1^j b2^k   (Eq. 1.1.2)",
        "corners: the vertices themselves",
        "edges: b210 = (2 v0 + v1",
        "          - dot(v1 - v0, n0) n0) / 3:",
        "  the edge's 1/3 point moved into the",
        "  tangent plane of the nearest corner",
        "centre: b111 = E + (E - V) / 2, E = mean",
        "  of the 6 edge points, V = (v0+v1+v2)/3",
    };
    text_lines(&d, f2(x - 0.1f, 2.3f), eq, 9, 13.5f, INK);
    return dg_end(&d, out, err, errlen);
}

/* ------------------------------------------------------------------ fig-1.1.3: barycentric areas */

/* Signed area of triangle a b c. */
static float area2(float2 a, float2 b, float2 c) { return 0.5f * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)); }

/* Centroid of three points. */
static float2 centroid(float2 a, float2 b, float2 c) { return f2((a.x + b.x + c.x) / 3.0f, (a.y + b.y + c.y) / 3.0f); }

/* fig-1.1.3: the three sub-triangles at p and b_i = A_i / A with their values. */
static int fig_1_1_3(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) return -1;
    const float2 v0 = f2(0.4f, 0.7f), v1 = f2(5.2f, 0.7f), v2 = f2(1.8f, 5.0f);
    const float3 bp = f3(0.5f, 0.3f, 0.2f);
    float2 p = add2(add2(scale2(v0, bp.x), scale2(v1, bp.y)), scale2(v2, bp.z));
    float A = area2(v0, v1, v2), A0 = area2(p, v1, v2), A1 = area2(v0, p, v2), A2 = area2(v0, v1, p);
    canvas_triangle(d.c, p, v1, v2, FILL_BLUE);
    canvas_triangle(d.c, v0, p, v2, FILL_ORANGE);
    canvas_triangle(d.c, v0, v1, p, FILL_GREEN);
    for (int k = 0; k < 3; k++) ln(&d, p, k == 0 ? v0 : (k == 1 ? v1 : v2), 1.5f, GREY);
    ln(&d, v0, v1, 3.0f, INK), ln(&d, v1, v2, 3.0f, INK), ln(&d, v2, v0, 3.0f, INK);
    dot_at(&d, v0, 5.0f, INK), dot_at(&d, v1, 5.0f, INK), dot_at(&d, v2, 5.0f, INK), dot_at(&d, p, 6.0f, RED);
    text(&d, v0, -8.0f, 16.0f, 1.0f, "v0", 20.0f, INK);
    text(&d, v1, 8.0f, 16.0f, 0.0f, "v1", 20.0f, INK);
    text(&d, v2, 0.0f, -22.0f, 0.5f, "v2", 20.0f, INK);
    text(&d, p, 10.0f, 14.0f, 0.0f, "p", 20.0f, RED);
    text(&d, centroid(p, v1, v2), 0.0f, 0.0f, 0.5f, "A0", 22.0f, BLUE);
    text(&d, centroid(v0, p, v2), 0.0f, 0.0f, 0.5f, "A1", 22.0f, ORANGE);
    text(&d, centroid(v0, v1, p), 0.0f, 0.0f, 0.5f, "A2", 22.0f, GREEN);
    heading(&d, "Barycentric coordinates are area ratios");
    float x = 5.75f;
    legend_fill(&d, f2(x, 4.9f), FILL_BLUE, "A0 = area(p, v1, v2): opposite v0");
    legend_fill(&d, f2(x, 4.5f), FILL_ORANGE, "A1 = area(v0, p, v2): opposite v1");
    legend_fill(&d, f2(x, 4.1f), FILL_GREEN, "A2 = area(v0, v1, p): opposite v2");
    char l[6][64];
    snprintf(l[0], sizeof l[0], "A = area(v0, v1, v2) = %.2f", (double)A);
    snprintf(l[1], sizeof l[1], "b0 = A0 / A = %.2f / %.2f = %.3f", (double)A0, (double)A, (double)(A0 / A));
    snprintf(l[2], sizeof l[2], "b1 = A1 / A = %.2f / %.2f = %.3f", (double)A1, (double)A, (double)(A1 / A));
    snprintf(l[3], sizeof l[3], "b2 = A2 / A = %.2f / %.2f = %.3f", (double)A2, (double)A, (double)(A2 / A));
    snprintf(l[4], sizeof l[4], "b0 + b1 + b2 = %.3f", (double)((A0 + A1 + A2) / A));
    snprintf(l[5], sizeof l[5], "p = b0 v0 + b1 v1 + b2 v2");
    const char *lines[6] = {l[0], l[1], l[2], l[3], l[4], l[5]};
    text_lines(&d, f2(x - 0.05f, 3.4f), lines, 6, 15.0f, INK);
    static const char *const note[] = {"b_i grows as p moves towards v_i:", "b0 = 1 at v0, b1 = 1 at v1, b2 = 1 at v2."};
    text_lines(&d, f2(x - 0.05f, 1.0f), note, 2, 14.0f, GREY);
    return dg_end(&d, out, err, errlen);
}

/* ------------------------------------------------------------------ fig-1.1.4: border curve */

/* Unit 2D normal tilted by tx (x component before normalising, y = 1). */
static float3 tilt(float tx) { return normalize3(f3(tx, 1.0f, 0.0f)); }

/* The curve vs_evaluate_curve(a, b, na, nb, t) at n + 1 parameters, as 2D points. */
static void curve2(float2 a, float2 b, float3 na, float3 nb, float2 *out, int n)
{
    for (int i = 0; i <= n; i++) out[i] = xy(vs_evaluate_curve(xy0(a), xy0(b), na, nb, (float)i / (float)n));
}

/* Inner control point of Eq. 1.1.5 near a towards b with the normal na at a. */
static float2 inner_cp(float2 a, float2 b, float3 na)
{
    float3 A = xy0(a), B = xy0(b);
    return xy(scale3(sub3(add3(scale3(A, 2.0f), B), scale3(na, dot3(sub3(B, A), na))), 1.0f / 3.0f));
}

/* fig-1.1.4: a cubic border curve, its control polygon, end normals and end derivatives. */
static int fig_1_1_4(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) return -1;
    const float2 b30 = f2(1.0f, 2.5f), b03 = f2(7.7f, 3.0f);
    const float3 n0 = tilt(-1.0f), n1 = tilt(0.65f);
    float2 b21 = inner_cp(b30, b03, n0), b12 = inner_cp(b03, b30, n1), cv[61];
    curve2(b30, b03, n0, n1, cv, 60);
    dash(&d, b30, b03, 1.5f, LIGHT);
    dash(&d, b30, b21, 2.0f, GREY), dash(&d, b21, b12, 2.0f, GREY), dash(&d, b12, b03, 2.0f, GREY);
    polyline(&d, cv, 61, 4.0f, BLUE);
    float2 d0 = sub2(b21, b30), d1 = sub2(b12, b03);
    arrow(&d, b30, add2(b30, scale2(d0, 0.75f)), 3.0f, ORANGE);
    arrow(&d, b03, add2(b03, scale2(d1, 0.75f)), 3.0f, ORANGE);
    arrow(&d, b30, add2(b30, scale2(xy(n0), 1.3f)), 3.0f, GREEN);
    arrow(&d, b03, add2(b03, scale2(xy(n1), 1.3f)), 3.0f, GREEN);
    right_angle(&d, b30, norm2(d0), xy(n0), 0.22f, INK);
    right_angle(&d, b03, norm2(d1), xy(n1), 0.22f, INK);
    float2 pts[4] = {b30, b21, b12, b03};
    const char *names[4] = {"b30", "b21", "b12", "b03"};
    const float lx[4] = {-10.0f, 0.0f, 0.0f, 12.0f}, ly[4] = {20.0f, -20.0f, -20.0f, 20.0f}, ha[4] = {1, 0.5f, 0.5f, 0};
    for (int i = 0; i < 4; i++) dot_at(&d, pts[i], 6.0f, RED), text(&d, pts[i], lx[i], ly[i], ha[i], names[i], 19.0f, RED);
    text(&d, add2(b30, scale2(xy(n0), 1.3f)), 0.0f, -16.0f, 0.5f, "n0", 19.0f, GREEN);
    text(&d, add2(b03, scale2(xy(n1), 1.3f)), 0.0f, -16.0f, 0.5f, "n1", 19.0f, GREEN);
    text(&d, add2(b30, scale2(d0, 0.5f)), 4.0f, 20.0f, 0.0f, "d0", 19.0f, ORANGE);
    text(&d, add2(b03, scale2(d1, 0.5f)), -4.0f, 20.0f, 1.0f, "d1", 19.0f, ORANGE);
    text(&d, cv[30], 0.0f, 22.0f, 0.5f, "border curve", 16.0f, BLUE);
    heading(&d, "A border curve of the N-Patch: a cubic Bezier curve (Eq. 1.1.5)");
    char l[5][96];
    snprintf(l[0], sizeof l[0], "b21 = (2 b30 + b03 - dot(b03 - b30, n0) n0) / 3");
    snprintf(l[1], sizeof l[1], "b12 = (2 b03 + b30 - dot(b30 - b03, n1) n1) / 3");
    snprintf(l[2], sizeof l[2], "d0 points from b30 to b21, d1 from b03 to b12 (the curve's end tangents)");
    snprintf(l[3], sizeof l[3], "d0 is perpendicular to n0, d1 to n1 (measured, unit vectors): %.4f and %.4f",
             (double)fabsf(dot2(norm2(d0), xy(n0))), (double)fabsf(dot2(norm2(d1), xy(n1))));
    snprintf(l[4], sizeof l[4], "The curve passes through b30 and b03 only; b21 and b12 pull it along d0, d1.");
    const char *lines[5] = {l[0], l[1], l[2], l[3], l[4]};
    text_lines(&d, f2(0.3f, 1.4f), lines, 5, 15.0f, INK);
    return dg_end(&d, out, err, errlen);
}

/* ------------------------------------------------------------------ fig-1.1.5: P0, P1, P2 */

/* One panel: patch P_e of edge e (v_e to v_e+1), its curves from the border curve to the opposite vertex. */
static void patch_family(dg *d, const float3 v[3], const float3 n[3], int e, const float *col)
{
    int a = e, b = (e + 1) % 3, o = (e + 2) % 3;
    float2 cv[41];
    for (int k = 0; k < 3; k++) {
        border_curve(d, v[k], v[(k + 1) % 3], n[k], n[(k + 1) % 3], cv, 40);
        polyline(d, cv, 41, k == e ? 4.0f : 1.5f, k == e ? col : GREY);
    }
    enum { NC = 8 };
    for (int s = 0; s <= NC; s++) {
        float st = (float)s / NC;
        float3 p = vs_evaluate_curve(v[a], v[b], n[a], n[b], st);
        float3 np = normalize3(lerp3(n[a], n[b], st));
        for (int i = 0; i <= 40; i++) cv[i] = pj(d, vs_evaluate_curve(p, v[o], np, n[o], (float)i / 40.0f));
        if (s > 0 && s < NC) polyline(d, cv, 41, 1.8f, col);
        arrow(d, pj(d, p), pj(d, add3(p, scale3(np, 0.35f))), 1.5f, GREEN);
    }
    arrow(d, pj(d, v[o]), pj(d, add3(v[o], scale3(n[o], 0.35f))), 1.5f, GREEN);
    const char *vn[3] = {"v0", "v1", "v2"};
    /* v2 left of its normal, except in P2's panel, where the arrows of edge v2-v0 rise on the left */
    const float dx[3] = {0.0f, 0.0f, e == 2 ? 10.0f : -10.0f}, dy[3] = {22.0f, 22.0f, -8.0f},
                ha[3] = {0.5f, 0.5f, e == 2 ? 0.0f : 1.0f};
    for (int k = 0; k < 3; k++) dot_at(d, pj(d, v[k]), 4.0f, INK), text(d, pj(d, v[k]), dx[k], dy[k], ha[k], vn[k], 15.0f, INK);
}

/* fig-1.1.5: the three patches, one per edge, as families of curves in three panels. */
static int fig_1_1_5(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) return -1;
    float3 v[3], n[3];
    demo_triangle(v, n);
    const float *cols[3] = {BLUE, ORANGE, GREEN};
    static const char *const titles[3] = {"P0: edge v0-v1, curves to v2", "P1: edge v1-v2, curves to v0",
                                           "P2: edge v2-v0, curves to v1"};
    for (int e = 0; e < 3; e++) {
        float x0 = 3.0f * (float)e;
        dg_view(&d, f2(x0 + 0.05f, 1.0f), f2(x0 + 2.95f, 5.0f), f3(0.0f, 4.3f, -4.1f), f3(0.0f, 0.1f, 0.2f), 35.0f);
        patch_family(&d, v, n, e, cols[e]);
        text(&d, f2(x0 + 1.5f, 4.75f), 0.0f, 0.0f, 0.5f, titles[e], 16.0f, cols[e]);
    }
    heading(&d, "One patch per edge (Listing 1.1.1), drawn as its family of curves");
    static const char *const txt[] = {
        "Each curve starts at a point p = curve(v_i, v_j, n_i, n_j, s) of the thick border curve, with the blended normal",
        "normalize(lerp(n_i, n_j, s)) (short green arrows), and ends at the opposite vertex with its normal (Eq. 1.1.5).",
        "Along the edge every curve leaves perpendicular to the blended normal, so a neighbour's patch agrees on the normal.",
        "The three patches are blended with Gregory weights, each 1 on its own edge: P = g.y P0 + g.z P1 + g.x P2.",
    };
    text_lines(&d, f2(0.1f, 1.05f), txt, 4, 13.5f, INK);
    return dg_end(&d, out, err, errlen);
}

/* ------------------------------------------------------------------ grids: fig-1.1.6, fig-001-11 */

/* The 2D triangle of the grid diagrams. */
static void grid_triangle(float2 t[3])
{
    t[0] = f2(0.4f, 0.6f), t[1] = f2(5.6f, 0.6f), t[2] = f2(3.0f, 0.6f + 5.2f * 0.8660254f);
}

/* The point of barycentrics b on triangle t. */
static float2 bary_point(const float2 t[3], float3 b)
{
    return add2(add2(scale2(t[0], b.x), scale2(t[1], b.y)), scale2(t[2], b.z));
}

/* Fill and wireframe of a grid of barycentric points on triangle t. */
static void draw_grid(dg *d, const float2 t[3], const float3 *bary, size_t np, const uint32_t *idx, size_t nt)
{
    canvas_triangle(d->c, t[0], t[1], t[2], FILL_TRI);
    for (size_t k = 0; k < nt; k++)
        for (int e = 0; e < 3; e++)
            ln(d, bary_point(t, bary[idx[3 * k + e]]), bary_point(t, bary[idx[3 * k + (e + 1) % 3]]), 1.5f, INK);
    for (size_t i = 0; i < np; i++) dot_at(d, bary_point(t, bary[i]), 3.0f, INK);
}

/* Corner labels v0 v1 v2 of a grid triangle. */
static void grid_corners(dg *d, const float2 t[3])
{
    text(d, t[0], -10.0f, 10.0f, 1.0f, "v0", 20.0f, INK);
    text(d, t[1], 10.0f, 10.0f, 0.0f, "v1", 20.0f, INK);
    text(d, t[2], 0.0f, -18.0f, 0.5f, "v2", 20.0f, INK);
}

/* A labelled grid point: a red dot and its (b0, b1, b2) at label position l with a leader line that ends at the
 * label's side (ha 0: left end, 1: right end) or, for a centred label, just above or below it. */
static void grid_label(dg *d, float2 p, float2 l, float ha, const char *s)
{
    if (len2(sub2(l, p)) > 0.3f) ln(d, p, l, 1.2f, RED);
    dot_at(d, p, 6.0f, RED);
    float dy = ha == 0.5f ? (l.y < p.y ? 12.0f : -12.0f) : 0.0f;
    text(d, l, ha == 0.0f ? 6.0f : (ha == 1.0f ? -6.0f : 0.0f), dy, ha, s, 15.0f, RED);
}

/* fig-1.1.6: the regular barycentric grid of level 8 with a few points' barycentrics and the counts. */
static int fig_1_1_6(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    enum { L = 8 };
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) return -1;
    float3 bary[(L + 1) * (L + 2) / 2];
    uint32_t idx[3 * L * L];
    size_t np = core_grid_regular(L, bary, idx);
    float2 t[3];
    grid_triangle(t);
    draw_grid(&d, t, bary, np, idx, (size_t)L * L);
    grid_corners(&d, t);
    grid_label(&d, t[0], f2(t[0].x + 0.2f, 0.25f), 0.0f, "(1, 0, 0)");
    grid_label(&d, t[1], f2(t[1].x - 0.2f, 0.25f), 1.0f, "(0, 1, 0)");
    grid_label(&d, t[2], f2(t[2].x + 0.35f, t[2].y), 0.0f, "(0, 0, 1)");
    grid_label(&d, bary_point(t, bary[core_grid_index(L, 4, 0)]), f2(3.0f, 0.33f), 0.5f, "(4/8, 4/8, 0)");
    grid_label(&d, bary_point(t, bary[core_grid_index(L, 2, 3)]), f2(1.95f, 4.5f), 1.0f, "(3/8, 2/8, 3/8)");
    grid_label(&d, bary_point(t, bary[core_grid_index(L, 5, 1)]), f2(5.9f, 2.0f), 0.0f, "(2/8, 5/8, 1/8)");
    heading(&d, "Tessellation through instancing: one flat barycentric grid, level L = 8");
    char l[7][80];
    snprintf(l[0], sizeof l[0], "level L = %d", L);
    snprintf(l[1], sizeof l[1], "point (i, j): b = ((L-i-j)/L, i/L, j/L)");
    snprintf(l[2], sizeof l[2], "points: (L+1)(L+2)/2 = %zu", np);
    snprintf(l[3], sizeof l[3], "triangles: L*L = %zu", core_grid_triangles(L));
    snprintf(l[4], sizeof l[4], "labels: (b0, b1, b2) of red points");
    snprintf(l[5], sizeof l[5], "The grid is one vertex buffer, drawn");
    snprintf(l[6], sizeof l[6], "once per mesh triangle (an instance).");
    const char *lines[7] = {l[0], l[1], l[2], l[3], l[4], l[5], l[6]};
    text_lines(&d, f2(6.0f, 4.6f), lines, 7, 15.0f, INK);
    return dg_end(&d, out, err, errlen);
}

/* Lengths, in level units, of the segments on edge v0-v1 (points with b2 == 0 sorted by b1); returns count. */
static int edge_segments(const core_grid *g, float level, float *len, int max)
{
    float b1[130];
    int n = 0;
    for (size_t i = 0; i < g->n_points && n < 130; i++)
        if (g->bary[i].z == 0.0f) b1[n++] = g->bary[i].y;
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && b1[j] < b1[j - 1]; j--) {
            float s = b1[j];
            b1[j] = b1[j - 1], b1[j - 1] = s;
        }
    int m = 0;
    for (int i = 0; i + 1 < n && m < max; i++) len[m++] = (b1[i + 1] - b1[i]) * level;
    return m;
}

/* Highlight the short (fractional) segments of the three outer edges. */
static void short_segments(dg *d, const float2 t[3], const core_grid *g, float level)
{
    for (size_t k = 0; k < g->n_triangles; k++)
        for (int e = 0; e < 3; e++) {
            float3 a = g->bary[g->idx[3 * k + e]], b = g->bary[g->idx[3 * k + (e + 1) % 3]];
            bool edge = (a.x == 0.0f && b.x == 0.0f) || (a.y == 0.0f && b.y == 0.0f) || (a.z == 0.0f && b.z == 0.0f);
            float l = length3(sub3(a, b)) / 1.41421356f * level;
            if (edge && l < 0.99f) ln(d, bary_point(t, a), bary_point(t, b), 5.0f, ORANGE);
        }
}

/* fig-001-11: the primitive generator's triangle with inner = outer = 4.0, fractional_odd spacing. */
static int fig_001_11(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    const float level = 4.0f, outer[3] = {4.0f, 4.0f, 4.0f};
    core_grid g;
    if (core_grid_pg(CORE_GRID_PG_FRACTIONAL_ODD, level, outer, &g) != 0) {
        snprintf(err, errlen, "fig-001-11: core_grid_pg failed");
        return -1;
    }
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) {
        core_grid_free(&g);
        return -1;
    }
    float2 t[3];
    grid_triangle(t);
    draw_grid(&d, t, g.bary, g.n_points, g.idx, g.n_triangles);
    short_segments(&d, t, &g, level);
    for (size_t i = 0; i < g.n_points; i++) dot_at(&d, bary_point(t, g.bary[i]), 3.5f, INK);
    grid_corners(&d, t);
    float seg[64];
    int ns = edge_segments(&g, level, seg, 64);
    char segs[200] = "", l[8][120];
    for (int i = 0; i < ns && strlen(segs) < 180; i++)
        snprintf(segs + strlen(segs), sizeof segs - strlen(segs), "%s%.2f", i ? " + " : "", (double)seg[i]);
    heading(&d, "OpenGL 4 primitive generator: inner = outer = 4.0, fractional_odd_spacing");
    snprintf(l[0], sizeof l[0], "inner level = %.1f", (double)level);
    snprintf(l[1], sizeof l[1], "outer levels = %.1f, %.1f, %.1f", (double)outer[0], (double)outer[1], (double)outer[2]);
    snprintf(l[2], sizeof l[2], "fractional_odd: %.1f rounds up to", (double)level);
    snprintf(l[3], sizeof l[3], "the next odd count, %d segments:", ns);
    snprintf(l[4], sizeof l[4], "  %s", segs);
    snprintf(l[5], sizeof l[5], "  (in level units, sum %.1f)", (double)level);
    snprintf(l[6], sizeof l[6], "points: %zu, triangles: %zu", g.n_points, g.n_triangles);
    snprintf(l[7], sizeof l[7], "inside: concentric rings, each with");
    const char *lines[9] = {l[0], l[1], l[2], l[3], l[4], l[5], l[6], l[7], "two segments fewer per edge (Fig. 10)"};
    text_lines(&d, f2(5.9f, 4.9f), lines, 9, 15.0f, INK);
    legend(&d, f2(5.95f, 1.6f), ORANGE, false, false, "short (fractional) segments");
    core_grid_free(&g);
    return dg_end(&d, out, err, errlen);
}

/* ------------------------------------------------------------------ fig-1.1.9: the wedge */

/* The wedge at q between T0's line from B continued across the edge and T1's line towards D. */
static void wedge(dg *d, float2 q, float2 B, float2 D)
{
    float2 uB = norm2(sub2(q, B)), uD = norm2(sub2(D, q));
    const float r = 0.8f;
    canvas_triangle(d->c, q, add2(q, scale2(uB, r)), add2(q, scale2(uD, r)), FILL_RED);
    dash(d, q, add2(q, scale2(uB, r)), 2.0f, BLUE);
    ln(d, q, add2(q, scale2(uD, r)), 2.5f, ORANGE);
    dot_at(d, q, 6.0f, RED);
    text(d, add2(q, scale2(add2(uB, uD), 0.5f * r)), -14.0f, 0.0f, 1.0f, "wedge", 17.0f, RED);
    text(d, q, 12.0f, 10.0f, 0.0f, "q", 18.0f, RED);
}

/* fig-1.1.9: two coplanar triangles sharing an edge; each patch's parameter lines meet the edge at the same
 * points but in different directions, and the little wedge between them. */
static int fig_1_1_9(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) return -1;
    const float2 A = f2(0.5f, 0.5f), B = f2(5.0f, 0.5f), C = f2(5.0f, 5.0f), D = f2(0.5f, 5.0f);
    canvas_triangle(d.c, A, B, C, FILL_BLUE);
    canvas_triangle(d.c, A, C, D, FILL_ORANGE);
    for (int s = 1; s < 8; s++) {
        float2 q = lerp2(A, C, (float)s / 8.0f);
        dash(&d, q, B, 1.8f, BLUE);
        dash(&d, q, D, 1.8f, ORANGE);
    }
    ln(&d, A, B, 2.5f, INK), ln(&d, B, C, 2.5f, INK), ln(&d, C, D, 2.5f, INK), ln(&d, D, A, 2.5f, INK);
    ln(&d, A, C, 4.0f, INK);
    wedge(&d, lerp2(A, C, 0.25f), B, D);
    text(&d, centroid(A, B, C), 20.0f, 10.0f, 0.5f, "T0", 28.0f, BLUE);
    text(&d, centroid(A, C, D), -20.0f, -10.0f, 0.5f, "T1", 28.0f, ORANGE);
    text(&d, lerp2(A, C, 0.62f), 14.0f, 0.0f, 0.0f, "shared edge", 15.0f, INK);
    heading(&d, "Why the intermediate patch shows valleys on flat faces");
    legend(&d, f2(5.6f, 4.9f), BLUE, true, false, "parameter lines of T0's patch");
    legend(&d, f2(5.6f, 4.5f), ORANGE, true, false, "parameter lines of T1's patch");
    legend_fill(&d, f2(5.6f, 4.1f), FILL_RED, "wedge at q: T0's line continued");
    text(&d, f2(6.05f, 3.85f), 10.0f, 0.0f, 0.0f, "across the edge vs T1's line", 15.0f, INK);
    static const char *const txt[] = {
        "The patch of the shared edge sweeps curves",
        "from a point q of the edge to the opposite",
        "vertex: in T0 towards its far corner, in T1",
        "towards the other one.",
        "Both reach q with the same normal but in",
        "different directions (only the midpoint",
        "lines up): the curves leave a little wedge",
        "between them, and sweeping it makes the",
        "valley of Fig. 1.1.8b on coplanar triangles.",
    };
    text_lines(&d, f2(5.55f, 3.3f), txt, 9, 14.0f, INK);
    return dg_end(&d, out, err, errlen);
}

/* ------------------------------------------------------------------ tangent-plane projection: 001-4, 003-4 */

/* Names of the projection diagram: corners, normal, the 1/3 point, the result, the plane. */
typedef struct proj_names {
    const char *p0, *p1, *n0, *n1, *q, *b, *b_other, *plane, *head, *eq[4];
    bool both;  /* also construct the coefficient at the other end */
} proj_names;

/* One end's construction: the tangent plane at a (as a line), the 1/3 point q, its projection along na. */
static float2 project_end(dg *d, float2 a, float2 b, float3 na, const char *qn, const char *bn, const char *pn)
{
    float2 n = xy(na), t = f2(n.y, -n.x);
    if (dot2(t, sub2(b, a)) < 0.0f) t = scale2(t, -1.0f);
    ln(d, sub2(a, scale2(t, 1.0f)), add2(a, scale2(t, 3.3f)), 2.5f, PURPLE);
    text(d, add2(a, scale2(t, 3.3f)), t.x > 0.0f ? 8.0f : -8.0f, 0.0f, t.x > 0.0f ? 0.0f : 1.0f, pn, 14.0f, PURPLE);
    float2 q = lerp2(a, b, 1.0f / 3.0f);
    float w = dot2(sub2(q, a), n);
    float2 p = sub2(q, scale2(n, w));
    arrow(d, q, p, 2.2f, RED);
    right_angle(d, p, scale2(t, -1.0f), w > 0.0f ? n : scale2(n, -1.0f), 0.16f, INK);
    ring_at(d, q, 6.0f, INK);
    dot_at(d, p, 6.5f, RED);
    text(d, q, 0.0f, w > 0.0f ? -18.0f : 20.0f, 0.5f, qn, 15.0f, INK);
    text(d, p, 0.0f, w > 0.0f ? 22.0f : -20.0f, 0.5f, bn, 19.0f, RED);
    return p;
}

/* The projection diagram with the labels of one document. */
static int draw_projection(const fig_ctx *ctx, const proj_names *nm, is_image *out, char *err, size_t errlen)
{
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) return -1;
    const float2 P1 = f2(0.9f, 2.9f), P2 = f2(7.9f, 3.3f);
    const float3 N1 = tilt(-0.6f), N2 = tilt(0.7f);
    float2 cv[61];
    curve2(P1, P2, N1, N2, cv, 60);
    dashed_polyline(&d, cv, 61, 2.0f, 0.12f, BLUE);
    ln(&d, P1, P2, 2.5f, INK);
    project_end(&d, P1, P2, N1, nm->q, nm->b, nm->plane);
    if (nm->both) project_end(&d, P2, P1, N2, "(2 P2 + P1) / 3", nm->b_other, "tangent plane of P2");
    arrow(&d, P1, add2(P1, scale2(xy(N1), 1.4f)), 3.0f, GREEN);
    text(&d, add2(P1, scale2(xy(N1), 1.4f)), 0.0f, -16.0f, 0.5f, nm->n0, 18.0f, GREEN);
    arrow(&d, P2, add2(P2, scale2(xy(N2), 1.4f)), 3.0f, GREEN);
    text(&d, add2(P2, scale2(xy(N2), 1.4f)), 0.0f, -16.0f, 0.5f, nm->n1, 18.0f, GREEN);
    dot_at(&d, P1, 6.0f, INK), dot_at(&d, P2, 6.0f, INK);
    text(&d, P1, 8.0f, 20.0f, 0.0f, nm->p0, 19.0f, INK);
    text(&d, P2, -8.0f, 20.0f, 1.0f, nm->p1, 19.0f, INK);
    heading(&d, nm->head);
    legend(&d, f2(0.3f, 1.35f), BLUE, true, false, "the resulting cubic edge curve (tangent to the plane at the corner)");
    text_lines(&d, f2(0.3f, 0.95f), nm->eq, 4, 15.0f, INK);
    return dg_end(&d, out, err, errlen);
}

/* fig-001-4: seed 001's construction of b210 (and b120) with P1, P2, N1, N2 and w12. */
static int fig_001_4(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const proj_names nm = {
        "P1", "P2", "N1", "N2", "Q = (2 P1 + P2) / 3", "b210", "b120", "tangent plane of P1",
        "Side view: b210 is projected into the tangent plane of its closest corner P1",
        {"w12 = (P2 - P1) . N1,   b210 = (2 P1 + P2 - w12 N1) / 3  (seed 001, Eq. 3):",
         "the 1/3 point Q = (2 P1 + P2) / 3 projected along N1: Q' = Q - ((Q - P1) . N1) N1 = Q - (w12 / 3) N1.",
         "Likewise b120 = (2 P2 + P1 - w21 N2) / 3 in the tangent plane of P2.",
         "The corners keep their normals: the patch is tangent to each corner's plane."},
        true,
    };
    return draw_projection(ctx, &nm, out, err, errlen);
}

/* fig-003-4: RTR's construction of p210 from p300, p030 and n200. */
static int fig_003_4(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const proj_names nm = {
        "p300", "p030", "n200", "n020", "2/3 p300 + 1/3 p030", "p210", "p120", "tangent plane at p300",
        "Side view: the Bezier point p210 from p300, p030 and the normal n200",
        {"p210 = (2 p300 + p030 - (n200 . (p030 - p300)) n200) / 3",
         "Take the point 2/3 p300 + 1/3 p030 on the edge and project it along n200",
         "onto the tangent plane defined by p300 and n200 (normals of unit length).",
         "The other five border points are computed the same way from their corner."},
        false,
    };
    return draw_projection(ctx, &nm, out, err, errlen);
}

/* ------------------------------------------------------------------ fig-001-6: normal field */

/* The quadratic normals (vs_npatch_evaluate) at the points of a level-6 grid, and the dashed boundary curves. */
static void quadratic_field(dg *d, const float3 v[3], const float3 n[3])
{
    enum { L = 6 };
    float3 bary[(L + 1) * (L + 2) / 2];
    uint32_t idx[3 * L * L];
    size_t np = core_grid_regular(L, bary, idx);
    for (size_t i = 0; i < np; i++) {
        float3 pos, nrm;
        vs_npatch_evaluate(v, n, bary[i], IS_DEGREE_CUBIC, IS_DEGREE_QUADRATIC, &pos, &nrm);
        arrow(d, pj(d, pos), pj(d, add3(pos, scale3(nrm, 0.28f))), 1.3f, GREY);
    }
    float2 cv[201];
    for (int k = 0; k < 3; k++) {
        border_curve(d, v[k], v[(k + 1) % 3], n[k], n[(k + 1) % 3], cv, 200);
        dashed_polyline(d, cv, 201, 2.5f, 0.07f, INK);
    }
}

/* The six normal control points: vertex normals at the corners, reflected mid-edge normals at the middle of
 * each edge curve, labelled. */
static void normal_controls(dg *d, const float3 v[3], const float3 n[3])
{
    static const char *const vn[3] = {"n200", "n020", "n002"}, *const en[3] = {"n110", "n011", "n101"};
    for (int k = 0; k < 3; k++) {
        int j = (k + 1) % 3;
        float3 tip = add3(v[k], scale3(n[k], 0.6f));
        arrow(d, pj(d, v[k]), pj(d, tip), 3.0f, GREEN);
        text(d, pj(d, tip), 0.0f, -14.0f, 0.5f, vn[k], 18.0f, GREEN);
        float3 m = vs_evaluate_curve(v[k], v[j], n[k], n[j], 0.5f), nm = mid_edge_normal(v[k], v[j], n[k], n[j]);
        arrow(d, pj(d, m), pj(d, add3(m, scale3(nm, 0.6f))), 3.0f, RED);
        text(d, pj(d, add3(m, scale3(nm, 0.6f))), 0.0f, -14.0f, 0.5f, en[k], 18.0f, RED);
    }
}

/* fig-001-6: the six normal control points of the quadratic normal patch over the cubic patch. */
static int fig_001_6(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) return -1;
    float3 v[3], n[3];
    demo_triangle(v, n);
    dg_view(&d, f2(0.2f, 0.1f), f2(5.6f, 5.6f), f3(0.0f, 3.2f, -4.4f), f3(0.0f, 0.3f, 0.15f), 37.0f);
    draw_patch_surface(&d, v, n, 0.55f);
    for (int k = 0; k < 3; k++) ln(&d, pj(&d, v[k]), pj(&d, v[(k + 1) % 3]), 1.5f, GREY);
    quadratic_field(&d, v, n);
    normal_controls(&d, v, n);
    heading(&d, "The normal field of a PN triangle: a quadratic patch of normals");
    float x = 5.85f;
    legend(&d, f2(x, 5.0f), GREEN, false, true, "vertex normals (given)");
    legend(&d, f2(x, 4.6f), RED, false, true, "mid-edge normals");
    legend(&d, f2(x, 4.2f), GREY, false, true, "interpolated n(b)");
    legend(&d, f2(x, 3.8f), INK, true, false, "boundary curves");
    text(&d, f2(x + 0.45f, 3.55f), 10.0f, 0.0f, 0.0f, "of the cubic patch", 15.0f, INK);
    legend(&d, f2(x, 3.2f), GREY, false, false, "the flat triangle");
    static const char *const eq[] = {
        "n(b) = n200 b0^2 + n020 b1^2",
        "   + n002 b2^2 + n110 b0 b1",
        "   + n011 b1 b2 + n101 b2 b0,",
        "normalised (seed 001, Eq. 5).",
        "n110 = normalize(n200 + n020",
        "          - v (P1 - P0)),",
        "v = 2 dot(P1 - P0, n200 + n020)",
        "      / dot(P1 - P0, P1 - P0):",
        "the average normal reflected in",
        "the plane perpendicular to the",
        "edge (fig-003-6); drawn at the",
        "middle of each edge curve.",
    };
    text_lines(&d, f2(x - 0.05f, 2.75f), eq, 12, 13.5f, INK);
    return dg_end(&d, out, err, errlen);
}

/* ------------------------------------------------------------------ linear vs quadratic normals */

/* The true unit normal of the 2D curve a-b at t (perpendicular to the derivative, pointing up). */
static float2 true_normal(float2 a, float2 b, float3 na, float3 nb, float t)
{
    const float h = 1.0f / 1024.0f;
    float t0 = t - h < 0.0f ? 0.0f : t - h, t1 = t + h > 1.0f ? 1.0f : t + h;
    float3 d = sub3(vs_evaluate_curve(xy0(a), xy0(b), na, nb, t1), vs_evaluate_curve(xy0(a), xy0(b), na, nb, t0));
    float2 n = norm2(f2(-d.y, d.x));
    return n.y < 0.0f ? scale2(n, -1.0f) : n;
}

/* The three interpolations compared: linear, the articles' literal quadratic form (n110 w t) and the Bernstein
 * form of a quadratic (2 n110 w t). */
enum { INTERP_LINEAR, INTERP_LITERAL, INTERP_BERNSTEIN, INTERP_COUNT };
static const float *const interp_colour[INTERP_COUNT] = {BLUE, RED, PURPLE};

/* Interpolated normal at t: linear normalize(lerp(na, nb, t)), or quadratic normalize(na w^2 + k n110 w t +
 * nb t^2), w = 1 - t, k = 1 (literal, seed 001 Eq. 5, seed 003, vs/patch.c) or 2 (Bernstein). */
static float2 interp_normal(float2 a, float2 b, float3 na, float3 nb, float t, int mode)
{
    if (mode == INTERP_LINEAR) return xy(normalize3(lerp3(na, nb, t)));
    float3 m = mid_edge_normal(xy0(a), xy0(b), na, nb);
    float w = 1.0f - t, k = mode == INTERP_BERNSTEIN ? 2.0f : 1.0f;
    return xy(normalize3(add3(add3(scale3(na, w * w), scale3(nb, t * t)), scale3(m, k * w * t))));
}

/* Signed tilt in degrees of a unit 2D normal from the vertical (positive: leaning right). */
static float tilt_deg(float2 n) { return atan2f(n.x, n.y) * 180.0f / PI_F; }

/* The largest angle in degrees between the true and the interpolated normal over 65 points of the curve. */
static float largest_error(float2 a, float2 b, float3 na, float3 nb, int mode)
{
    float worst = 0.0f;
    for (int i = 0; i <= 64; i++) {
        float t = (float)i / 64.0f;
        float ang = acosf(saturate(dot2(true_normal(a, b, na, nb, t), interp_normal(a, b, na, nb, t, mode))));
        if (ang * 180.0f / PI_F > worst) worst = ang * 180.0f / PI_F;
    }
    return worst;
}

/* One panel: the curve (chord `chord` from o) with end normals na, nb, the true normals (grey) and the
 * interpolated ones of `mode`, and the largest angle between them, measured. */
static void normal_panel(dg *d, float2 o, float chord, float3 na, float3 nb, int mode)
{
    const float2 a = o, b = f2(o.x + chord, o.y);
    const float len = 0.3f * chord;
    float2 cv[61];
    curve2(a, b, na, nb, cv, 60);
    polyline(d, cv, 61, 3.5f, INK);
    for (int i = 0; i <= 6; i++) {
        float t = (float)i / 6.0f;
        float2 p = cv[i * 10], tn = true_normal(a, b, na, nb, t), in = interp_normal(a, b, na, nb, t, mode);
        ln(d, p, add2(p, scale2(tn, len * 1.15f)), 4.5f, LIGHT);
        arrow(d, p, add2(p, scale2(in, len)), 2.2f, interp_colour[mode]);
    }
    char s[48];
    snprintf(s, sizeof s, "largest error %.1f deg", (double)largest_error(a, b, na, nb, mode));
    text(d, f2(o.x + 0.5f * chord, o.y), 0.0f, 24.0f, 0.5f, s, 14.0f, INK);
}

/* The tilt of the normals along t in [0, 1] (box at o, size w x h, +-50 degrees): true and each interpolation. */
static void angle_plot(dg *d, float2 o, float w, float h, float3 na, float3 nb)
{
    const float2 a = f2(0, 0), b = f2(2.4f, 0);
    ln(d, o, f2(o.x + w, o.y), 1.2f, GREY), ln(d, o, f2(o.x, o.y + h), 1.2f, GREY);
    dash(d, f2(o.x, o.y + 0.5f * h), f2(o.x + w, o.y + 0.5f * h), 1.0f, LIGHT);
    float2 pt[INTERP_COUNT + 1][65];
    for (int i = 0; i <= 64; i++) {
        float t = (float)i / 64.0f, x = o.x + t * w;
        pt[0][i] = f2(x, o.y + h * (0.5f + tilt_deg(true_normal(a, b, na, nb, t)) / 100.0f));
        for (int k = 0; k < INTERP_COUNT; k++)
            pt[k + 1][i] = f2(x, o.y + h * (0.5f + tilt_deg(interp_normal(a, b, na, nb, t, k)) / 100.0f));
    }
    polyline(d, pt[0], 65, 5.0f, LIGHT);
    for (int k = 0; k < INTERP_COUNT; k++) polyline(d, pt[k + 1], 65, 2.0f, interp_colour[k]);
    text(d, f2(o.x + w, o.y), 0.0f, 14.0f, 1.0f, "t", 13.0f, GREY);
    text(d, f2(o.x, o.y + h), 4.0f, -4.0f, 0.0f, "tilt (deg)", 13.0f, GREY);
    text(d, f2(o.x, o.y + 0.5f * h), -4.0f, 0.0f, 1.0f, "0", 12.0f, GREY);
    text(d, f2(o.x, o.y + h), -4.0f, 0.0f, 1.0f, "50", 12.0f, GREY);
    text(d, o, -4.0f, 0.0f, 1.0f, "-50", 12.0f, GREY);
}

/* Labels of the comparison: heading, row names, end-normal tilts of each row. */
typedef struct cmp_names { const char *head, *row0, *row1; float top[2], bottom[2]; } cmp_names;

/* Linear, literal quadratic and Bernstein quadratic normals (columns) on two curves (rows), and their tilt
 * along t (right). */
static int draw_normal_comparison(const fig_ctx *ctx, const cmp_names *nm, is_image *out, char *err, size_t errlen)
{
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) return -1;
    const float tilts[2][2] = {{nm->top[0], nm->top[1]}, {nm->bottom[0], nm->bottom[1]}};
    const float ys[2] = {3.6f, 1.3f}, xs[INTERP_COUNT] = {0.3f, 2.55f, 4.8f}, chord = 1.8f;
    static const char *const heads[INTERP_COUNT] = {"linear", "quadratic, literal", "quadratic, Bernstein"};
    for (int r = 0; r < 2; r++) {
        float3 na = tilt(tilts[r][0]), nb = tilt(tilts[r][1]);
        for (int q = 0; q < INTERP_COUNT; q++) normal_panel(&d, f2(xs[q], ys[r]), chord, na, nb, q);
        angle_plot(&d, f2(7.25f, ys[r] - 0.3f), 1.6f, 1.5f, na, nb);
    }
    for (int q = 0; q < INTERP_COUNT; q++)
        text(&d, f2(xs[q] + 0.5f * chord, 5.3f), 0.0f, 0.0f, 0.5f, heads[q], 17.0f, interp_colour[q]);
    text(&d, f2(8.05f, 5.3f), 0.0f, 0.0f, 0.5f, "tilt along t", 15.0f, INK);
    text(&d, f2(0.05f, ys[0] + 1.15f), 0.0f, 0.0f, 0.0f, nm->row0, 16.0f, INK);
    text(&d, f2(0.05f, ys[1] + 1.15f), 0.0f, 0.0f, 0.0f, nm->row1, 16.0f, INK);
    ln(&d, f2(0.0f, 2.75f), f2(FW, 2.75f), 1.0f, LIGHT);
    heading(&d, nm->head);
    legend(&d, f2(0.1f, 0.55f), LIGHT, false, false, "true normal");
    static const char *const eq[] = {
        "linear: normalize(lerp(n0, n1, t));  literal: normalize(n0 w^2 + n110 w t + n1 t^2), w = 1 - t",
        "Bernstein: normalize(n0 w^2 + 2 n110 w t + n1 t^2);  n110: n0 + n1 reflected (fig-003-6)",
        "The articles print the literal form, as instess's --normals quadratic evaluates it."};
    text_lines(&d, f2(1.75f, 0.55f), eq, 3, 13.0f, INK);
    return dg_end(&d, out, err, errlen);
}

/* fig-001-7: a parabolic and a cubic curve (seed 001, after van Overveld and Wyvill). */
static int fig_001_7(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const cmp_names nm = {"Linear vs quadratic normal variation along a curve (van Overveld and Wyvill)",
                                 "parabolic", "cubic", {-0.5f, 0.5f}, {0.6f, 0.6f}};
    return draw_normal_comparison(ctx, &nm, out, err, errlen);
}

/* fig-003-5: a convex curve and one with an inflection (seed 003). */
static int fig_003_5(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    static const cmp_names nm = {"Why normals are interpolated quadratically: convex surface vs inflection",
                                 "convex", "inflection", {-0.4f, 0.7f}, {0.3f, 0.8f}};
    return draw_normal_comparison(ctx, &nm, out, err, errlen);
}

/* ------------------------------------------------------------------ fig-003-6: n110 by reflection */

/* fig-003-6: the average of n200 and n020 reflected in the plane perpendicular to p030 - p300. */
static int fig_003_6(const fig_ctx *ctx, is_image *out, char *err, size_t errlen)
{
    dg d;
    if (dg_begin(&d, ctx, err, errlen)) return -1;
    const float2 p0 = f2(0.9f, 2.5f), p1 = f2(7.3f, 2.5f), M = lerp2(p0, p1, 0.5f);
    const float3 n0 = tilt(0.25f), n1 = tilt(0.95f);
    const float L = 2.0f;
    float2 cv[61];
    curve2(p0, p1, n0, n1, cv, 60);
    dashed_polyline(&d, cv, 61, 2.0f, 0.12f, GREY);
    ln(&d, p0, p1, 2.5f, INK);
    dash(&d, f2(M.x, 1.4f), f2(M.x, 5.3f), 2.5f, PURPLE);
    text(&d, f2(M.x, 5.3f), 8.0f, 4.0f, 0.0f, "plane pi, normal parallel to p030 - p300", 15.0f, PURPLE);
    float2 avg = scale2(add2(xy(n0), xy(n1)), 0.5f);
    float2 n110 = xy(mid_edge_normal(xy0(p0), xy0(p1), n0, n1));
    float2 refl = f2(-avg.x, avg.y);
    canvas_dashed_line(d.c, add2(M, scale2(avg, L)), add2(M, scale2(refl, L)), 1.5f * d.k, 4.0f * d.k, GREY);
    dash(&d, M, add2(M, scale2(avg, L)), 3.0f, INK);
    canvas_arrow(d.c, add2(M, scale2(avg, L * 0.93f)), add2(M, scale2(avg, L)), 3.0f * d.k, INK);
    arrow(&d, M, add2(M, scale2(n110, L)), 3.5f, RED);
    arrow(&d, p0, add2(p0, scale2(xy(n0), L)), 3.0f, GREEN);
    arrow(&d, p1, add2(p1, scale2(xy(n1), L)), 3.0f, GREEN);
    float2 tn = true_normal(p0, p1, n0, n1, 0.5f);
    arrow(&d, cv[30], add2(cv[30], scale2(tn, 1.0f)), 1.5f, BLUE);
    text(&d, cv[30], 4.0f, 40.0f, 0.0f, "blue: true normal at t = 1/2", 13.0f, BLUE);
    text(&d, add2(M, scale2(avg, L)), 8.0f, 0.0f, 0.0f, "(n200 + n020) / 2", 16.0f, INK);
    text(&d, add2(M, scale2(n110, L)), -8.0f, -6.0f, 1.0f, "n110", 19.0f, RED);
    text(&d, add2(p0, scale2(xy(n0), L)), 0.0f, -14.0f, 0.5f, "n200", 18.0f, GREEN);
    text(&d, add2(p1, scale2(xy(n1), L)), 0.0f, -14.0f, 0.5f, "n020", 18.0f, GREEN);
    dot_at(&d, p0, 6.0f, INK), dot_at(&d, p1, 6.0f, INK);
    text(&d, p0, 0.0f, 22.0f, 0.5f, "p300", 18.0f, INK);
    text(&d, p1, 0.0f, 22.0f, 0.5f, "p030", 18.0f, INK);
    heading(&d, "The mid-edge normal n110: the average normal reflected in the plane pi");
    static const char *const eq[] = {
        "n110 = normalize(n200 + n020 - v110 (p030 - p300)),",
        "v110 = 2 ((p030 - p300) . (n200 + n020)) / ((p030 - p300) . (p030 - p300))",
        "A plain average fails where the curve has an inflection (n200 = n020 would give the same normal everywhere);",
        "the reflection tilts n110 the other way, so the quadratic normals can turn back where the curve does.",
        "Dashed grey: the cubic edge curve of p300, p030, n200, n020; blue: its true normal in the middle.",
    };
    text_lines(&d, f2(0.1f, 1.15f), eq, 5, 14.0f, INK);
    return dg_end(&d, out, err, errlen);
}

/* ------------------------------------------------------------------ the table */

#define SRC000 "H. Gruen, Smoothed N-Patches, "
#define SRC001 "R. van Veen and L. Baakman, A Discussion of Curved Point-Normal Triangles, "
#define SRC003 "T. Akenine-Moller and E. Haines, Real-Time Rendering, section Bezier Triangles and N-Patches, "
/* Said in both normal comparisons (fig-001-7, fig-003-5): which quadratic form is whose. */
#define QUAD_FORMS "Direct3D 9 documents D3DDEGREE_QUADRATIC normals (D3DRS_NORMALDEGREE, D3DXTessellateNPatches) " \
    "without a formula; Vlachos et al., the draft (Eq. 5) and Real-Time Rendering all print the literal form " \
    "n110 b0 b1 without the factor 2 of a Bernstein quadratic, and instess's --normals quadratic evaluates it."

const figure fig_diagrams[] = {
    {"fig-1.1.2", NULL, SRC000 "Figure 1.1.2", "The control points of a bicubic triangular Bezier patch.",
     "A perspective view of one curved triangle (vertices (-1,0,-0.6), (1,0,-0.6), (0,0,1.1), normals pointing "
     "away from (0.1,-1.5,0.05)): its N-Patch shaded (vs_patch_eval, npatch, level 16), the three border curves, "
     "the vertex normals and the control net of the 10 control points b300 ... b111 of Eq. 1.1.1, each labelled.",
     "instess figures --only fig-1.1.2 --out DIR", false, fig_1_1_2, 0},
    {"fig-1.1.3", NULL, SRC000 "Figure 1.1.3",
     "If A is the area of a triangle, barycentric coordinates of a point p are defined by the ratios of A0/A, "
     "A1/A, and A2/A.",
     "A triangle v0 v1 v2 split at p = 0.5 v0 + 0.3 v1 + 0.2 v2 into the sub-triangles A0 (opposite v0), A1, A2 "
     "in three colours, with the areas measured and b_i = A_i / A printed (0.500, 0.300, 0.200).",
     "instess figures --only fig-1.1.3 --out DIR", false, fig_1_1_3, 0},
    {"fig-1.1.4", NULL, SRC000 "Figure 1.1.4",
     "The start and end derivatives of a cubic Bezier curve point toward the inner control points.",
     "A border curve evaluated with vs_evaluate_curve from b30, b03 and the normals n0, n1; its control polygon "
     "b30 b21 b12 b03 (Eq. 1.1.5), the end derivatives d0, d1 as arrows with right-angle marks to n0, n1, and "
     "the measured dot(d0, n0), dot(d1, n1).",
     "instess figures --only fig-1.1.4 --out DIR", false, fig_1_1_4, 0},
    {"fig-1.1.5", NULL, SRC000 "Figure 1.1.5", "One creates one patch for every edge e0, e1, and e2.",
     "Three panels, one per edge of the curved triangle of fig-1.1.2: the edge's border curve (thick) and seven "
     "curves of Listing 1.1.1 from points on it (s = 1/8 ... 7/8) to the opposite vertex, with the blended start "
     "normals normalize(lerp(n_i, n_j, s)); P0 (edge v0-v1) blue, P1 (v1-v2) orange, P2 (v2-v0) green.",
     "instess figures --only fig-1.1.5 --out DIR", false, fig_1_1_5, 0},
    {"fig-1.1.6", NULL, SRC000 "Figure 1.1.6", "A regular barycentric tessellation of a triangle.",
     "The grid of core_grid_regular at level 8 (45 points, 64 triangles) in wireframe, with the barycentrics "
     "(b0, b1, b2) of six points and the counts (L+1)(L+2)/2 and L*L.",
     "instess figures --only fig-1.1.6 --out DIR", false, fig_1_1_6, 0},
    {"fig-1.1.9", NULL, SRC000 "Figure 1.1.9",
     "Parameter space lines take off into different directions from the shared position on a shared triangle "
     "edge.",
     "Two coplanar triangles T0, T1 (a cube face split along its diagonal) with the dashed parameter lines of the "
     "patch of the shared edge in each (from points on the edge to the opposite vertex); at one point q the "
     "two directions and the wedge between them are marked.",
     "instess figures --only fig-1.1.9 --out DIR", false, fig_1_1_9, 0},
    {"fig-001-4", NULL, SRC001 "Figure 4",
     "Projection of a tangent coefficient b210 to the tangent plane of the closest corner P1.",
     "Side view of an edge P1-P2 with normals N1, N2: the tangent planes (as lines), the 1/3 points "
     "(2 P1 + P2)/3 and (2 P2 + P1)/3, their projections b210 and b120 along the normals (Eq. 3), and the "
     "resulting cubic edge curve (vs_evaluate_curve).",
     "instess figures --only fig-001-4 --out DIR", false, fig_001_4, 1},
    {"fig-001-6", NULL, SRC001 "Figure 6", "The normal field of the point-normal triangle.",
     "The curved triangle of fig-1.1.2 with the dashed boundary curves of its cubic patch, the vertex normals "
     "n200, n020, n002, the reflected mid-edge normals n110, n011, n101 at the middle of each edge curve, and "
     "the quadratic normals (vs_npatch_evaluate, quadratic) at the points of a level-6 grid.",
     "instess figures --only fig-001-6 --out DIR", false, fig_001_6, 1},
    {"fig-001-7", NULL, SRC001 "Figure 7",
     "The upper row shows a parabolic curve with linearly varying normals, on the left, and quadratically varying "
     "normals on the right. The lower row compares the normals of a cubic curve using linearly varying normals on "
     "the left and quadratically varying normals on the right. The illustration was taken from Overveld and "
     "Wyvill [OW97].",
     "A parabolic edge curve (end normals tilted apart) and a cubic S-curve (equal end normals), both from "
     "vs_evaluate_curve, each with its true normals (grey) against three interpolations: linear (blue), the "
     "quadratic normal as the articles print it (red) and the same with the Bernstein weight 2 on the mixed term "
     "(purple); under each panel the largest angle to the true normal over 65 points. On the S-curve the true "
     "normal swings past the vertical; the literal form stays on one side (22.3 degrees off at worst) and the "
     "Bernstein form comes twice as close (11.6). " QUAD_FORMS,
     "instess figures --only fig-001-7 --out DIR", false, fig_001_7, 1},
    {"fig-001-11", NULL, SRC001 "Figure 11",
     "A single triangle tessellated with both outer and inner tessellation level set to 4.0, and edge "
     "tessellation spacing set to fractional_odd_spacing.",
     "The primitive-generator grid core_grid_pg(CORE_GRID_PG_FRACTIONAL_ODD, inner 4.0, outer 4.0, 4.0, 4.0) "
     "in wireframe: 5 segments per edge (three of length 1, two short ones of 0.5, highlighted), the levels, "
     "the segment lengths and the point and triangle counts.",
     "instess figures --only fig-001-11 --out DIR", false, fig_001_11, 1},
    {"fig-003-4", NULL, SRC003 "Figure 4",
     "How the Bezier point p210 is computed using the normal n200 at p300, and the two corner points p300 and "
     "p030.",
     "Side view of the edge p300-p030 with n200: the tangent plane at p300 (as a line), the point "
     "2/3 p300 + 1/3 p030, its projection along n200 onto the plane (p210), the formula, and the cubic edge "
     "curve it produces.",
     "instess figures --only fig-003-4 --out DIR", false, fig_003_4, 2},
    {"fig-003-5", NULL, SRC003 "Figure 5",
     "This figure illustrates why quadratic interpolation of normals is needed, and why linear interpolation is "
     "not sufficient. The left column shows what happens when linear interpolation of normals are used. This "
     "works fine when the normals describe a convex surface (top), but breaks down when the surface has an "
     "inflection (bottom). The right column illustrates quadratic interpolation. (Illustration after van "
     "Overveld and Wyvill.)",
     "The book's two cases, a convex edge curve and one with an inflection, with the three interpolations of "
     "fig-001-7. The book says the quadratic normal captures the inflection; with its own (literal) weights the "
     "normal turns back only part of the way and stays on one side (22.9 degrees off at worst), while the "
     "Bernstein form crosses over as the true normal does (12.9).",
     "instess figures --only fig-003-5 --out DIR", false, fig_003_5, 2},
    {"fig-003-6", NULL, SRC003 "Figure 6",
     "Construction of n110 for N-patches. The dashed normal is the average of n200 and n020, and n110 is this "
     "normal reflected in the plane pi. The plane pi has a normal that is parallel to p030 - p300.",
     "Side view of an edge p300-p030 whose normals n200, n020 lean the same way (an inflection): the average "
     "(dashed), the plane pi through the edge's middle, perpendicular to p030 - p300, and n110 = the reflected "
     "average (the formula of vs/patch.c), next to the true normal of the cubic edge curve at its middle.",
     "instess figures --only fig-003-6 --out DIR", false, fig_003_6, 2},
    {NULL, NULL, NULL, NULL, NULL, NULL, false, NULL, 0},
};
