/* cli/view/view_inspect.c -- what the viewer shows that a GPU cannot: the pipeline inspector on a pinned pixel
 * and the draw played instance by instance.
 *
 * Pinning (a click without a drag, the I key for the window's centre, --pin X,Y in a script): after each frame
 * the part of the frame holding the pixel is rendered again with the device recording it (scene_inspect_pixel,
 * core/inspect.h: one sample per pixel), the whole history goes to the terminal as instess inspect prints it
 * (registers, shader values and outputs of every vertex), the HUD lists its fragments -- draw, instance (the mesh triangle), grid
 * triangle, barycentrics, depth test, colour -- and the patch shader's values at the winning fragment's first
 * vertex, and the picked instance is drawn over the frame: its grid (the patch shader run on every grid point
 * with the render's constants) in yellow, the grid triangle that covers the pixel in red, the mesh triangle's
 * corners (the patch's corner control points) in cyan, the vertices opposite its edges (what the smoothed patch
 * reads of its neighbours) in magenta, and the pixel itself in white.
 *
 * Playback (X): the draw's instance count (--instances, the INDEXEDDATA count of stream 0) starts at 1 and grows by
 * the speed (. faster, , slower: 1, 2, 4, ... per frame) every frame until the whole mesh is drawn: the grid stamped
 * once per mesh triangle, the technique's one idea, watched.  The count moves on when the next frame starts, so a
 * frame and its state (a screenshot's description, --capture) always agree: frame k of the playback is the file of
 * instess --instances k. */
#include "view_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The frame's part holding window column x (the split screen's halves): its options and first column. */
static scene_opts part_of(const view_state *v, int x, int *x0)
{
    scene_opts o = v->o;
    *x0 = 0;
    if (!v->split) return o;
    int lw = v->o.width / 2 > 0 ? v->o.width / 2 : 1;
    if (x < lw) return o.width = lw, o;
    o.width = v->o.width - lw, o.patch = v->other, *x0 = lw;
    return o;
}

void view_pin(view_state *v, int x, int y)
{
    v->pinned = x >= 0 && y >= 0 && x < v->o.width && y < v->o.height;
    v->pin_x = x, v->pin_y = y;
    v->n_pin_lines = 0;
    v->dirty = true;
}

void act_inspect(view_state *v)
{
    if (v->pinned) view_pin(v, -1, -1);
    else view_pin(v, v->o.width / 2, v->o.height / 2);
}

/* One pixel (x, y) of v->frame in colour c (RGBA8), if inside [x0, x1). */
static void plot(view_state *v, int x, int y, int x0, int x1, uint32_t c)
{
    if (x >= x0 && x < x1 && y >= 0 && y < v->o.height) v->frame[(size_t)y * v->o.width + x] = c;
}

/* A line from (ax, ay) to (bx, by) (pixels) into v->frame's columns [x0, x1), at most 4096 steps. */
static void line(view_state *v, double ax, double ay, double bx, double by, int x0, int x1, uint32_t c)
{
    double dx = bx - ax, dy = by - ay, len = fmax(fabs(dx), fabs(dy));
    if (!(len < 4096.0)) return;   /* off screen far, or not a number */
    int n = (int)len + 1;
    for (int k = 0; k <= n; k++) plot(v, (int)lround(ax + dx * k / n), (int)lround(ay + dy * k / n), x0, x1, c);
}

/* A 5x5 square around (x, y). */
static void mark(view_state *v, double x, double y, int x0, int x1, uint32_t c)
{
    if (!(fabs(x) < 1e6 && fabs(y) < 1e6)) return;
    for (int j = -2; j <= 2; j++)
        for (int i = -2; i <= 2; i++) plot(v, (int)lround(x) + i, (int)lround(y) + j, x0, x1, c);
}

/* Clip-space p on a part of width w from column x0: screen (*x, *y); false behind the eye. */
static bool screen_of(const view_state *v, rs_vec4 p, int x0, int w, double *x, double *y)
{
    if (!(p.w > 0.0f)) return false;
    *x = x0 + (1.0 + (double)p.x / p.w) * w * 0.5;
    *y = (1.0 - (double)p.y / p.w) * v->o.height * 0.5;
    return true;
}

/* Object-space point q through c0..c3 (row vectors, as the listings: mul(float4(q, 1), WVP)). */
static rs_vec4 project(const is_vs_constants *c, float4 q)
{
    float r[4];
    for (int k = 0; k < 4; k++)
        r[k] = q.x * (&c->c[0].x)[k] + q.y * (&c->c[1].x)[k] + q.z * (&c->c[2].x)[k] + (&c->c[3].x)[k];
    return (rs_vec4){r[0], r[1], r[2], r[3]};
}

/* The picked instance over the frame: its grid through the patch shader, the covering grid triangle, the mesh
 * triangle's corners and opposite vertices, the pixel (see the top of the file). */
static void draw_instance(view_state *v, const scene_opts *o, const is_inspect_fragment *f,
                          const is_vs_constants *c, int x0)
{
    const uint32_t yellow = 0xff40e0f0u, red = 0xff3030ffu, cyan = 0xfff0e040u, magenta = 0xfff040f0u;
    const int x1 = x0 + o->width;
    core_grid g;
    const is_vertex_shader *vs = vs_patch_shader(o->patch);
    if (vs && core_grid_make(o->grid, o->level, &g) == 0) {
        is_vs_input in = f->v[0].regs;   /* the instance's registers; POSITION0 set per grid point below */
        double (*p)[2] = malloc(g.n_points * sizeof *p);
        bool *ok = malloc(g.n_points * sizeof *ok);
        for (size_t k = 0; p && ok && k < g.n_points; k++) {
            is_vs_output out;
            memset(&out, 0, sizeof out);
            in.position[0] = (float4){g.bary[k].x, g.bary[k].y, g.bary[k].z, 1.0f};
            vs->main(c, &in, &out);
            ok[k] = screen_of(v, out.pos, x0, o->width, &p[k][0], &p[k][1]);
        }
        for (size_t t = 0; p && ok && t < g.n_triangles; t++)
            for (int e = 0; e < 3; e++) {
                uint32_t a = g.idx[3 * t + e], b = g.idx[3 * t + (e + 1) % 3];
                if (ok[a] && ok[b]) line(v, p[a][0], p[a][1], p[b][0], p[b][1], x0, x1, yellow);
            }
        free(p);
        free(ok);
        core_grid_free(&g);
    }
    double sx[3], sy[3];
    bool on[3];
    for (int k = 0; k < 3; k++) on[k] = screen_of(v, f->v[k].out.pos, x0, o->width, &sx[k], &sy[k]);
    for (int k = 0; k < 3; k++)
        if (on[k] && on[(k + 1) % 3]) line(v, sx[k], sy[k], sx[(k + 1) % 3], sy[(k + 1) % 3], x0, x1, red);
    const is_vs_input *in = &f->v[0].regs;
    for (int k = 0; k < 3; k++) {   /* Listing 1.1.2's registers: v0..v2 in TEXCOORD0..2, opp0..2 in TEXCOORD6..8 */
        double x, y;
        if (screen_of(v, project(c, in->texcoord[VS_IN_V0 + k]), x0, o->width, &x, &y)) mark(v, x, y, x0, x1, cyan);
        if (screen_of(v, project(c, in->texcoord[VS_IN_OPP0 + k]), x0, o->width, &x, &y)) mark(v, x, y, x0, x1, magenta);
    }
    plot(v, v->pin_x, v->pin_y, x0, x1, 0xffffffffu);
}

/* A float4's first n components as "(a, b, c)" into buf. */
static const char *vec(float4 q, int n, char *buf, size_t len)
{
    if (n == 1) snprintf(buf, len, "%.4g", q.x);
    else snprintf(buf, len, n == 3 ? "(%.4g, %.4g, %.4g)" : "(%.4g, %.4g, %.4g, %.4g)", q.x, q.y, q.z, q.w);
    return buf;
}

/* The record as HUD lines (at most VIEW_PIN_LINES). */
static void pin_lines(view_state *v, const is_inspect *rec, uint32_t color, float depth)
{
    int n = 0;
    snprintf(v->pin_lines[n++], 160, "inspector: pixel (%d, %d), %zu fragment(s), final #%02x%02x%02x depth %.6g "
             "(I unpins)", v->pin_x, v->pin_y, rec->n_fragments, color & 0xffu, (color >> 8) & 0xffu,
             (color >> 16) & 0xffu, depth);
    const is_inspect_fragment *win = NULL;
    for (size_t k = 0; k < rec->n_fragments && n < VIEW_PIN_LINES - 3; k++) {
        const is_inspect_fragment *f = &rec->fragments[k];
        if (f->passed) win = f;
        snprintf(v->pin_lines[n++], 160, " draw %u instance %u grid tri %u  bary (%.3f, %.3f, %.3f)  depth %.5f vs %.5f "
                 "%s", f->draw, f->instance, f->primitive, f->bary[0], f->bary[1], f->bary[2], f->depth,
                 f->depth_before, f->passed ? "passed" : "failed");
    }
    if (win) {   /* the winning fragment's first vertex: what the patch shader published */
        const is_inspect_vertex *iv = &win->v[0];
        char line[160] = " vs at vertex 0:", b[64];
        for (unsigned k = 0; k < iv->n_values; k++) {
            const char *name = iv->values[k].name;
            int comps = !strcmp(name, "bl") ? 1 : 3;
            if (!strcmp(name, "where") || !strcmp(name, "pos") || !strcmp(name, "posN") || name[0] == 'P') continue;
            size_t len = strlen(line);
            if (len + 40 > 112 && n < VIEW_PIN_LINES) snprintf(v->pin_lines[n++], 160, "%s", line), line[0] = 0;
            len = strlen(line);
            snprintf(line + len, sizeof line - len, " %s %s", name, vec(iv->values[k].v, comps, b, sizeof b));
        }
        if (n < VIEW_PIN_LINES) snprintf(v->pin_lines[n++], 160, "%s", line);
    }
    v->n_pin_lines = n;
}

void view_inspect_frame(view_state *v)
{
    v->n_pin_lines = 0;
    if (!v->pinned) return;
    int x0;
    scene_opts o = part_of(v, v->pin_x, &x0);
    is_inspect rec = {0};
    uint32_t color = 0;
    float depth = 0;
    char err[512];
    is_vs_constants *c = calloc(1, sizeof *c);
    if (!c || scene_inspect_pixel(&o, v->draw, v->pin_x - x0, v->pin_y, &rec, &color, &depth, c, err, sizeof err) != 0) {
        snprintf(v->pin_lines[0], 160, "inspector: %.140s", c ? err : "out of memory");
        v->n_pin_lines = 1;
    } else {
        pin_lines(v, &rec, color, depth);
        if (!v->o.quiet) {   /* the whole history, as instess inspect prints it, on the terminal */
            fprintf(stderr, "instess view: the pinned pixel's history (instess inspect --pixel %d,%d):\n", v->pin_x - x0,
                    v->pin_y);
            scene_inspect_print(stderr, &o, v->draw, &rec, color, depth, false);
        }
        const is_inspect_fragment *win = NULL;
        for (size_t k = 0; k < rec.n_fragments; k++)
            if (rec.fragments[k].passed) win = &rec.fragments[k];
        if (win && o.path == SCENE_PATH_INSTANCED) draw_instance(v, &o, win, c, x0);
        else plot(v, v->pin_x, v->pin_y, x0, x0 + o.width, 0xffffffffu);
    }
    is_inspect_free(&rec);
    free(c);
}

void act_step(view_state *v)
{
    v->stepping = !v->stepping;
    v->step_drawn = false;
    v->o.instances = v->stepping ? 1 : 0;
    if (!v->step_speed) v->step_speed = 1;
    v->dirty = true;
}

void act_step_faster(view_state *v)
{
    v->step_speed = v->step_speed ? (v->step_speed < 4096 ? v->step_speed * 2 : 4096) : 2;
    v->overlay_dirty = true;
}

void act_step_slower(view_state *v)
{
    v->step_speed = v->step_speed > 1 ? v->step_speed / 2 : 1;
    v->overlay_dirty = true;
}

void view_step_frame(view_state *v)
{
    if (!v->stepping) return;
    if (!v->step_drawn) {   /* the playback's first frame: one instance */
        v->step_drawn = true;
        return;
    }
    size_t n = v->draw ? v->draw->n_triangles : 0;
    if (!v->step_speed) v->step_speed = 1;
    if ((size_t)v->o.instances + v->step_speed >= n) v->stepping = false, v->o.instances = 0;   /* the last: all */
    else v->o.instances += v->step_speed;
}
