/* cli/figures/canvas.c -- the drawing kit of the diagrams (cli/figures/figures.h): primitives are recorded as coloured triangles
 * in frame coordinates, drawn in one call on a 4x MSAA device of this project (its own pass-through vertex
 * shader, no culling, no depth test, premultiplied "over" blending, so later draws lie on top), resolved, and then
 * labelled with image_draw_text so text stays crisp.
 *
 * Conventions: the frame [x0, x1] x [y0, y1] (y up) maps onto the image with equal scale on both axes, centred
 * inside a margin of 3% of the smaller side.  Widths, radii, dash lengths and text offsets are in pixels; text
 * offsets (dx, dy) are image pixels (dy > 0 moves down).  Opaque lines get round caps so that polylines join
 * without gaps; translucent lines get none (a cap would blend twice).  canvas_project maps the normalised device
 * coordinates of the view (x/w, y/w in [-1, 1]) onto the whole frame rectangle, so a projection whose aspect is
 * (x1 - x0) / (y1 - y0) keeps its proportions.  Out-of-memory while recording is reported by canvas_finish. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "figures.h"

#include "../../core/hlsl.h"
#define CANVAS_MARGIN 0.03f   /* of the smaller image side */
#define CANVAS_DISC_SEGS 20   /* polygon sides of a disc of radius >= 4 px */
#define CANVAS_ARROW_HEAD 4.0f /* head length in line widths (at least 5 px) */

/* One vertex as the device reads it: clip position (POSITION0) and premultiplied colour (COLOR0). */
typedef struct canvas_vertex { float pos[4]; float col[4]; } canvas_vertex;

/* A recorded label, drawn after the resolve. */
typedef struct canvas_label {
    int x, y;
    float size;
    float rgba[4];
    char *text;
} canvas_label;

struct fig_canvas {
    int w, h;
    float bg[4];
    float scale, ox, oy;        /* pixel = (ox + (x - x0) scale, oy - (y - y0) scale) */
    float x0, y0, x1, y1;
    float4x4 wvp;
    canvas_vertex *v;
    size_t nv, cap_v;
    canvas_label *t;
    size_t nt, cap_t;
    bool oom;
};

/* The canvas's vertex shader: oPos = POSITION0, oD0 = COLOR0. */
static void canvas_vs(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    (void)c;
    out->pos = in->position[0];
    out->attr[RS_ATTR_COLOR0] = in->color[0];
}

static const is_vertex_shader canvas_shader = {.name = "canvas", .main = canvas_vs, .outputs = IS_OUT_COLOR0};

static const is_vertex_element canvas_decl[] = {
    {0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITION, 0},
    {0, 16, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_COLOR, 0},
    IS_DECL_END,
};

/* Set up the frame mapping: equal scale, centred inside the margin. */
static void canvas_frame(fig_canvas *c, float x0, float y0, float x1, float y1)
{
    float m = CANVAS_MARGIN * (float)(c->w < c->h ? c->w : c->h);
    float fw = x1 - x0 > 0.0f ? x1 - x0 : 1.0f, fh = y1 - y0 > 0.0f ? y1 - y0 : 1.0f;
    float sx = ((float)c->w - 2.0f * m) / fw, sy = ((float)c->h - 2.0f * m) / fh;
    c->scale = sx < sy ? sx : sy;
    c->ox = 0.5f * ((float)c->w - fw * c->scale);
    c->oy = 0.5f * ((float)c->h + fh * c->scale);
    c->x0 = x0, c->y0 = y0, c->x1 = x0 + fw, c->y1 = y0 + fh;
}

/* A w x h canvas with background bg and the frame [x0, x1] x [y0, y1]. */
fig_canvas *canvas_create(int w, int h, const float bg[4], float x0, float y0, float x1, float y1, char *err,
                          size_t errlen)
{
    if (w < 1 || h < 1 || w > RS_MAX_SIZE || h > RS_MAX_SIZE) {
        if (err) snprintf(err, errlen, "canvas size %dx%d: each side must be 1..%d", w, h, RS_MAX_SIZE);
        return NULL;
    }
    if (!(isfinite(x0) && isfinite(y0) && isfinite(x1) && isfinite(y1))) {
        if (err) snprintf(err, errlen, "canvas frame is not finite");
        return NULL;
    }
    fig_canvas *c = calloc(1, sizeof *c);
    if (!c) {
        if (err) snprintf(err, errlen, "out of memory for a canvas");
        return NULL;
    }
    c->w = w, c->h = h;
    memcpy(c->bg, bg, sizeof c->bg);
    canvas_frame(c, x0, y0, x1, y1);
    c->wvp = mat_identity();
    return c;
}

/* Free the canvas and what it recorded. */
void canvas_destroy(fig_canvas *c)
{
    if (!c) return;
    for (size_t k = 0; k < c->nt; k++) free(c->t[k].text);
    free(c->t);
    free(c->v);
    free(c);
}

/* Frame coordinates -> image pixels. */
static float2 to_px(const fig_canvas *c, float2 p)
{
    return f2(c->ox + (p.x - c->x0) * c->scale, c->oy - (p.y - c->y0) * c->scale);
}

/* Grow the vertex array to hold n more vertices; false (and oom set) when out of memory. */
static bool reserve_vertices(fig_canvas *c, size_t n)
{
    if (c->oom) return false;
    if (c->nv + n <= c->cap_v) return true;
    size_t cap = c->cap_v ? c->cap_v : 1024;
    while (cap < c->nv + n) cap *= 2;
    canvas_vertex *v = realloc(c->v, cap * sizeof *v);
    if (!v) {
        c->oom = true;
        return false;
    }
    c->v = v, c->cap_v = cap;
    return true;
}

/* Append one vertex at pixel position q (clip space with D3D9's pixel centres) with colour rgba. */
static void push_px(fig_canvas *c, float2 q, const float rgba[4])
{
    canvas_vertex *v = &c->v[c->nv++];
    v->pos[0] = 2.0f * q.x / (float)c->w - 1.0f;
    v->pos[1] = 1.0f - 2.0f * q.y / (float)c->h;
    v->pos[2] = 0.5f, v->pos[3] = 1.0f;
    float a = saturate(rgba[3]);
    v->col[0] = saturate(rgba[0]) * a, v->col[1] = saturate(rgba[1]) * a, v->col[2] = saturate(rgba[2]) * a;
    v->col[3] = a;
}

/* A triangle given in pixels. */
static void tri_px(fig_canvas *c, float2 a, float2 b, float2 d, const float rgba[4])
{
    if (!reserve_vertices(c, 3)) return;
    push_px(c, a, rgba), push_px(c, b, rgba), push_px(c, d, rgba);
}

/* A disc of radius r pixels around pixel q (a triangle fan). */
static void disc_px(fig_canvas *c, float2 q, float r, const float rgba[4])
{
    int n = r < 4.0f ? 12 : CANVAS_DISC_SEGS;
    for (int k = 0; k < n; k++) {
        float a0 = 6.2831853f * (float)k / (float)n, a1 = 6.2831853f * (float)(k + 1) / (float)n;
        tri_px(c, q, f2(q.x + r * cosf(a0), q.y + r * sinf(a0)), f2(q.x + r * cosf(a1), q.y + r * sinf(a1)), rgba);
    }
}

/* A straight band of width wpx between pixels a and b (two triangles). */
static void band_px(fig_canvas *c, float2 a, float2 b, float wpx, const float rgba[4])
{
    float dx = b.x - a.x, dy = b.y - a.y, l = sqrtf(dx * dx + dy * dy);
    if (!(l > 0.0f)) return;
    float nx = -dy / l * 0.5f * wpx, ny = dx / l * 0.5f * wpx;
    float2 p0 = f2(a.x + nx, a.y + ny), p1 = f2(b.x + nx, b.y + ny), p2 = f2(b.x - nx, b.y - ny),
           p3 = f2(a.x - nx, a.y - ny);
    tri_px(c, p0, p1, p2, rgba);
    tri_px(c, p0, p2, p3, rgba);
}

/* A line in pixels with round caps when opaque. */
static void line_px(fig_canvas *c, float2 a, float2 b, float wpx, const float rgba[4])
{
    band_px(c, a, b, wpx, rgba);
    if (rgba[3] >= 1.0f && wpx > 1.5f) {
        disc_px(c, a, 0.5f * wpx, rgba);
        disc_px(c, b, 0.5f * wpx, rgba);
    }
}

/* A line of width_px pixels from a to b. */
void canvas_line(fig_canvas *c, float2 a, float2 b, float width_px, const float rgba[4])
{
    line_px(c, to_px(c, a), to_px(c, b), width_px, rgba);
}

/* A dashed line: dashes and gaps of dash_px pixels, starting and ending with a dash. */
void canvas_dashed_line(fig_canvas *c, float2 a, float2 b, float width_px, float dash_px, const float rgba[4])
{
    float2 pa = to_px(c, a), pb = to_px(c, b);
    float dx = pb.x - pa.x, dy = pb.y - pa.y, l = sqrtf(dx * dx + dy * dy);
    if (!(l > 0.0f) || !(dash_px > 0.0f)) return;
    int n = (int)floorf((l / dash_px - 1.0f) / 2.0f) + 1; /* dashes; period stretched to end on a dash */
    if (n < 1) n = 1;
    float period = n > 1 ? (l - dash_px) / (float)(n - 1) : 0.0f, dash = n > 1 ? dash_px : l;
    for (int k = 0; k < n && k < 100000; k++) {
        float s0 = (float)k * period / l, s1 = ((float)k * period + dash) / l;
        line_px(c, f2(pa.x + dx * s0, pa.y + dy * s0), f2(pa.x + dx * s1, pa.y + dy * s1), width_px, rgba);
    }
}

/* An arrow from a to b: a line ending at the base of a filled head whose tip is b. */
void canvas_arrow(fig_canvas *c, float2 a, float2 b, float width_px, const float rgba[4])
{
    float2 pa = to_px(c, a), pb = to_px(c, b);
    float dx = pb.x - pa.x, dy = pb.y - pa.y, l = sqrtf(dx * dx + dy * dy);
    if (!(l > 0.0f)) return;
    float hl = CANVAS_ARROW_HEAD * width_px < 5.0f ? 5.0f : CANVAS_ARROW_HEAD * width_px;
    if (hl > 0.6f * l) hl = 0.6f * l;
    float ux = dx / l, uy = dy / l, hw = 0.45f * hl;
    float2 base = f2(pb.x - ux * hl, pb.y - uy * hl);
    line_px(c, pa, f2(pb.x - ux * hl * 0.8f, pb.y - uy * hl * 0.8f), width_px, rgba);
    tri_px(c, pb, f2(base.x - uy * hw, base.y + ux * hw), f2(base.x + uy * hw, base.y - ux * hw), rgba);
}

/* A filled disc of radius_px pixels at p. */
void canvas_point(fig_canvas *c, float2 p, float radius_px, const float rgba[4])
{
    disc_px(c, to_px(c, p), radius_px, rgba);
}

/* A filled triangle (translucent when rgba[3] < 1). */
void canvas_triangle(fig_canvas *c, float2 a, float2 b, float2 d, const float rgba[4])
{
    tri_px(c, to_px(c, a), to_px(c, b), to_px(c, d), rgba);
}

/* Record a label at p + (dx, dy) pixels (baseline's left end). */
void canvas_text(fig_canvas *c, float2 p, float dx, float dy, const char *text, float size_px, const float rgba[4])
{
    if (c->oom || !text || !*text) return;
    if (c->nt == c->cap_t) {
        size_t cap = c->cap_t ? 2 * c->cap_t : 32;
        canvas_label *t = realloc(c->t, cap * sizeof *t);
        if (!t) {
            c->oom = true;
            return;
        }
        c->t = t, c->cap_t = cap;
    }
    char *s = strdup(text);
    if (!s) {
        c->oom = true;
        return;
    }
    float2 q = to_px(c, p);
    canvas_label *l = &c->t[c->nt++];
    l->x = (int)lroundf(q.x + dx), l->y = (int)lroundf(q.y + dy);
    l->size = size_px;
    memcpy(l->rgba, rgba, sizeof l->rgba);
    l->text = s;
}

/* Set the world*view*proj matrix of canvas_project. */
void canvas_set_view(fig_canvas *c, const float4x4 *wvp) { c->wvp = *wvp; }

/* Project p through the view: NDC [-1, 1]^2 onto the frame rectangle. */
float2 canvas_project(const fig_canvas *c, float3 p)
{
    float4 q = mul4(f4_of(p, 1.0f), &c->wvp);
    float iw = q.w != 0.0f ? 1.0f / q.w : 0.0f;
    float nx = q.x * iw, ny = q.y * iw;
    return f2(c->x0 + 0.5f * (nx + 1.0f) * (c->x1 - c->x0), c->y0 + 0.5f * (ny + 1.0f) * (c->y1 - c->y0));
}

/* D3DCOLOR (ARGB) of an RGBA colour in [0, 1]. */
static uint32_t argb_of(const float rgba[4])
{
    unsigned ch[4];
    for (int k = 0; k < 4; k++) ch[k] = (unsigned)lroundf(saturate(rgba[k]) * 255.0f);
    return IS_COLOR_ARGB(ch[3], ch[0], ch[1], ch[2]);
}

/* Device states of the canvas: no culling, no depth, premultiplied "over" blending. */
static is_result canvas_states(is_device *dev)
{
    is_result r = dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE);
    if (r == IS_OK) r = dev_set_render_state(dev, IS_RS_ZENABLE, IS_ZB_FALSE);
    if (r == IS_OK) r = dev_set_render_state(dev, IS_RS_ZWRITEENABLE, 0);
    if (r == IS_OK) r = dev_set_render_state(dev, IS_RS_ALPHABLENDENABLE, 1);
    if (r == IS_OK) r = dev_set_render_state(dev, IS_RS_SRCBLEND, IS_BLEND_ONE);
    if (r == IS_OK) r = dev_set_render_state(dev, IS_RS_DESTBLEND, IS_BLEND_INVSRCALPHA);
    if (r == IS_OK) r = dev_set_render_state(dev, IS_RS_FILLMODE, IS_FILL_SOLID);
    if (r == IS_OK) r = dev_set_vertex_shader(dev, &canvas_shader);
    return r;
}

/* Upload the recorded triangles and draw them in one call (nothing to draw is fine). */
static is_result canvas_draw(fig_canvas *c, is_device *dev)
{
    is_result r = canvas_states(dev);
    if (r != IS_OK || c->nv < 3) return r;
    is_vertex_buffer *vb = NULL;
    is_vertex_declaration *decl = NULL;
    r = dev_create_vertex_buffer(dev, c->nv * sizeof *c->v, &vb);
    if (r == IS_OK) {
        memcpy(vb_lock(vb), c->v, c->nv * sizeof *c->v);
        vb_unlock(vb);
        r = dev_create_vertex_declaration(dev, canvas_decl, &decl);
    }
    if (r == IS_OK) r = dev_set_vertex_declaration(dev, decl);
    if (r == IS_OK) r = dev_set_stream_source(dev, 0, vb, 0, sizeof *c->v);
    if (r == IS_OK) r = dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, (unsigned)(c->nv / 3));
    decl_release(decl);
    vb_release(vb);
    return r;
}

/* Resolve the device's samples into img (allocated here, "R,G,B,A"). */
static int canvas_resolve(fig_canvas *c, is_device *dev, is_image *img, char *err, size_t errlen)
{
    uint32_t *rgba = malloc((size_t)c->w * (size_t)c->h * sizeof *rgba);
    if (!rgba) {
        snprintf(err, errlen, "out of memory for a %dx%d canvas", c->w, c->h);
        return -1;
    }
    rs_target_resolve(dev_render_target(dev), rgba);
    int rc = image_alloc(img, c->w, c->h, "R,G,B,A", err, errlen);
    if (rc == 0) image_from_rgba8(img, rgba);
    free(rgba);
    return rc;
}

/* Draw the recorded labels over the resolved image. */
static int canvas_labels(const fig_canvas *c, is_image *img, char *err, size_t errlen)
{
    for (size_t k = 0; k < c->nt; k++) {
        const canvas_label *l = &c->t[k];
        if (image_draw_text(img, l->x, l->y, l->text, l->size, l->rgba, err, errlen) != 0) return -1;
    }
    return 0;
}

/* Render everything recorded into img ("R,G,B,A"); 0, or -1 with a message. */
int canvas_finish(fig_canvas *c, is_image *img, char *err, size_t errlen)
{
    if (c->oom) {
        snprintf(err, errlen, "out of memory while recording the canvas");
        return -1;
    }
    is_device *dev = dev_create(c->w, c->h, 4, err, errlen);
    if (!dev) return -1;
    is_result r = dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, argb_of(c->bg), 1.0f);
    if (r == IS_OK) r = canvas_draw(c, dev);
    if (r != IS_OK) {
        snprintf(err, errlen, "canvas: %s", dev_last_error(dev));
        dev_destroy(dev);
        return -1;
    }
    int rc = canvas_resolve(c, dev, img, err, errlen);
    dev_destroy(dev);
    if (rc == 0 && canvas_labels(c, img, err, errlen) != 0) {
        image_free(img);
        rc = -1;
    }
    return rc;
}
