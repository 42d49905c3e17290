/* core/inspect.c -- the pipeline inspector (core/inspect.h): while a device records, each draw of triangles is
 * replayed for one pixel before the device draws it.  The replay shades the draw's vertices with the device's
 * fetch and shader, keeps the primitives whose screen box may hold the pixel, and draws each of them alone with
 * the rasterizer's reference path into a scratch target of the device's size: once with the depth test forced to
 * ALWAYS (coverage, barycentrics, the fragment's depth), once with the device's states on the pixel as the target
 * holds it (the verdict and the colour after).  Nothing here changes what the device draws. */
#include "device_internal.h"
#include "inspect.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define INSPECT_BARY_SLOT (RS_MAX_ATTR - 1)   /* the slot the replay carries (1,0,0), (0,1,0), (0,0,1) in */

struct dev_inspector {
    is_inspect *rec;
    rs_context *rs;             /* one thread, reference path */
    rs_target t;                /* the device's size, one sample, an AOV plane of the barycentric slot */
    rs_vertex *verts;           /* one instance's shaded vertices */
    size_t verts_cap;
    bool skip;                  /* the current draw is not recorded (not triangles, or out of memory) */
};

static const char *const usage_names[IS_DECLUSAGE_COUNT] = {
    "POSITION", "BLENDWEIGHT", "BLENDINDICES", "NORMAL", "PSIZE", "TEXCOORD", "TANGENT",
    "BINORMAL", "TESSFACTOR", "POSITIONT", "COLOR", "FOG", "DEPTH", "SAMPLE"};

const char *is_decl_usage_name(unsigned usage)
{
    return usage < IS_DECLUSAGE_COUNT ? usage_names[usage] : "?";
}

/* Free the inspector of dev (if any) and stop recording. */
void inspect_stop(is_device *dev)
{
    struct dev_inspector *in = dev->inspector;
    if (!in) return;
    rs_target_free(&in->t);
    rs_destroy(in->rs);
    free(in->verts);
    free(in);
    dev->inspector = NULL;
}

is_result dev_inspect_begin(is_device *dev, int x, int y, is_inspect *rec)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!rec) return dev_fail(dev, IS_ERR_INVALIDCALL, "dev_inspect_begin: NULL record");
    if (x < 0 || y < 0 || x >= dev->rt.width || y >= dev->rt.height)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "dev_inspect_begin: pixel (%d, %d) outside the %dx%d target", x, y,
                        dev->rt.width, dev->rt.height);
    if (dev->rt.samples != 1)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "dev_inspect_begin: the target has %d samples per pixel; the "
                        "inspector records one-sample targets", dev->rt.samples);
    struct dev_inspector *in = calloc(1, sizeof *in);
    if (!in) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "dev_inspect_begin: out of memory");
    in->rs = rs_create(1);
    bool ok = in->rs && rs_target_init(&in->t, dev->rt.width, dev->rt.height, 1) == RS_OK;
    ok = ok && rs_target_add_aov(&in->t, INSPECT_BARY_SLOT, 3) == RS_OK;
    if (!ok) {
        if (in->rs) rs_destroy(in->rs);
        rs_target_free(&in->t);
        free(in);
        return dev_fail(dev, IS_ERR_OUTOFMEMORY, "dev_inspect_begin: out of memory for a %dx%d scratch target",
                        dev->rt.width, dev->rt.height);
    }
    rs_set_reference_path(in->rs, true);
    inspect_stop(dev);   /* a recording already on ends here */
    is_inspect_free(rec);
    rec->x = x, rec->y = y;
    in->rec = rec;
    dev->inspector = in;
    return IS_OK;
}

void dev_inspect_end(is_device *dev)
{
    if (dev_live(dev)) inspect_stop(dev);
}

void is_inspect_free(is_inspect *rec)
{
    if (!rec) return;
    free(rec->fragments);
    memset(rec, 0, sizeof *rec);
}

/* Could a triangle with clip-space positions p[0..2] (as the rasterizer gets them) cover pixel (x, y) of the
 * rasterizer's viewport vp?  False only when all
 * three vertices are in front of the eye and their screen box, grown by a pixel, misses the pixel. */
static bool may_cover(const rs_vertex *const p[3], const rs_viewport *vp, int x, int y)
{
    float lo_x = INFINITY, hi_x = -INFINITY, lo_y = INFINITY, hi_y = -INFINITY;
    for (int k = 0; k < 3; k++) {
        float w = p[k]->pos.w;
        if (!(w > 0.0f) || !isfinite(p[k]->pos.x) || !isfinite(p[k]->pos.y)) return true;   /* clipping: try it */
        float sx = (float)vp->x + (1.0f + p[k]->pos.x / w) * (float)vp->width * 0.5f;
        float sy = (float)vp->y + (1.0f - p[k]->pos.y / w) * (float)vp->height * 0.5f;
        lo_x = fminf(lo_x, sx), hi_x = fmaxf(hi_x, sx), lo_y = fminf(lo_y, sy), hi_y = fmaxf(hi_y, sy);
    }
    return !(hi_x < (float)x - 1.0f || lo_x > (float)x + 1.0f || hi_y < (float)y - 1.0f || lo_y > (float)y + 1.0f);
}

/* Draw triangle v[0..2] alone into the scratch target, whose pixel px holds (color, depth) first and a NaN in its
 * barycentric plane: whether the triangle wrote the pixel (its AOV planes are written exactly by the fragments that
 * pass the depth test, raster.h); the pixel's colour, depth and barycentrics are left in the target. */
static bool replay(struct dev_inspector *in, const rs_state *st, const rs_vertex v[3], size_t px, uint32_t color,
                   float depth)
{
    in->t.color[px] = color;
    in->t.depth[px] = depth;
    float *b = in->t.aov[0].data + px * 3;
    b[0] = b[1] = b[2] = NAN;
    rs_stats s = {0};
    if (rs_draw(in->rs, st, &in->t, RS_PRIM_TRIANGLES, v, 3, NULL, 1, &s) != RS_OK) return false;
    return !isnan(b[0]);
}

/* The inputs of vertex (vertex, instance) of plan fp into out->inputs, by the declaration's elements. */
static void record_inputs(const is_device *dev, const fetch_plan *fp, is_inspect_vertex *out)
{
    is_vs_input *regs = &out->regs;
    fetch_vertex(fp, out->vertex, out->instance, regs);
    out->n_inputs = fp->n;
    for (unsigned k = 0; k < fp->n; k++) {
        const decl_element *de = &dev->decl->el[k];
        out->inputs[k] = (is_inspect_input){de->e.usage, de->e.usage_index, (uint8_t)de->e.stream,
                                            fp->el[k].per_instance,
                                            *(const float4 *)((const unsigned char *)regs + de->reg_offset)};
    }
    out->n_values = dev->vs->explain ? dev->vs->explain(&dev->consts, regs, out->values, IS_INSPECT_MAX_VALUES) : 0;
    if (out->n_values > IS_INSPECT_MAX_VALUES) out->n_values = IS_INSPECT_MAX_VALUES;
}

/* Append fragment f to the record (or count it dropped); false when out of memory. */
static bool append(is_inspect *rec, const is_inspect_fragment *f)
{
    if (rec->n_fragments == IS_INSPECT_MAX_FRAGMENTS) return rec->fragments_dropped++, true;
    size_t n = rec->n_fragments;
    if ((n & (n - 1)) == 0) {   /* grow at powers of two */
        is_inspect_fragment *p = realloc(rec->fragments, (n ? 2 * n : 1) * sizeof *p);
        if (!p) return false;
        rec->fragments = p;
    }
    rec->fragments[rec->n_fragments++] = *f;
    return true;
}

/* The two states of a draw's replay: the device's (with the barycentric slot), and the probe's -- coverage and the
 * fragment's own depth: the depth test always passes and writes, no blending. */
typedef struct replay_states { rs_state st, probe; } replay_states;

/* The replay states of dev's current draw. */
static replay_states replay_states_of(const is_device *dev)
{
    replay_states r;
    r.st = dev_rs_state(dev);
    r.st.attr_mask |= 1u << INSPECT_BARY_SLOT;
    r.probe = r.st;
    r.probe.z_enable = r.probe.z_write = true, r.probe.z_func = RS_CMP_ALWAYS, r.probe.blend_enable = false;
    return r;
}

/* One primitive of the replay (states rs, made once per draw): if it covers the pixel, record the fragment and move
 * the pixel on. */
static bool replay_prim(is_device *dev, const replay_states *rs, const fetch_plan *fp, const rs_vertex *const p[3],
                        const uint32_t vid[3], uint32_t instance, uint32_t prim, uint32_t *color, float *depth)
{
    struct dev_inspector *in = dev->inspector;
    is_inspect *rec = in->rec;
    size_t px = (size_t)rec->y * (size_t)in->t.width + (size_t)rec->x;
    rs_vertex v[3];
    for (int k = 0; k < 3; k++) {
        v[k] = *p[k];
        v[k].attr[INSPECT_BARY_SLOT] = (rs_vec4){k == 0, k == 1, k == 2, 0};
    }
    if (!replay(in, &rs->probe, v, px, *color, *depth)) return true;   /* the primitive misses the pixel centre */
    is_inspect_fragment f;
    memset(&f, 0, sizeof f);
    f.draw = rec->draws, f.instance = instance, f.primitive = prim;
    const float *b = in->t.aov[0].data + px * 3;
    f.bary[0] = b[0], f.bary[1] = b[1], f.bary[2] = b[2];
    f.depth = in->t.depth[px];
    f.depth_before = *depth, f.color_before = *color;
    f.passed = replay(in, &rs->st, v, px, *color, *depth);
    *color = f.color_after = in->t.color[px];
    *depth = in->t.depth[px];
    for (int k = 0; k < 3; k++) {
        f.v[k].vertex = vid[k], f.v[k].instance = instance;
        f.v[k].out = *p[k], f.v[k].outputs = dev->vs->outputs;
        record_inputs(dev, fp, &f.v[k]);
    }
    return append(rec, &f);
}

/* Is a draw of `type` made of triangles (what the inspector records)? */
static bool triangles(is_primtype type)
{
    return type == IS_PT_TRIANGLELIST || type == IS_PT_TRIANGLESTRIP || type == IS_PT_TRIANGLEFAN;
}

size_t inspect_draw(is_device *dev, const fetch_plan *fp, is_primtype type, size_t n_prims, uint32_t first,
                    uint32_t count, const uint32_t *stream_idx)
{
    struct dev_inspector *in = dev->inspector;
    is_inspect *rec = in->rec;
    size_t mark = rec->n_fragments;
    /* a draw into a render target of another size or sample count than the one recording began on is not
     * recorded (the pixel and the scratch target are the first target's) */
    in->skip = !triangles(type) || rec->out_of_memory || dev->rt.width != in->t.width ||
               dev->rt.height != in->t.height || dev->rt.samples != 1;
    if (in->skip) return mark;
    if (count > in->verts_cap) {
        rs_vertex *p = realloc(in->verts, (size_t)count * sizeof *p);
        if (!p) return rec->out_of_memory = in->skip = true, mark;
        in->verts = p, in->verts_cap = count;
    }
    rs_target_flush(dev->rs, &dev->rt);   /* a deferred clear is the pixel's first state */
    size_t px = (size_t)rec->y * (size_t)dev->rt.width + (size_t)rec->x;
    uint32_t color = dev->rt.color[px];
    float depth = dev->rt.depth[px];
    const replay_states rs = replay_states_of(dev);
    const rs_viewport vp = rs.st.viewport;   /* the rasterizer's (a viewport beyond the target: clipped) */
    for (uint32_t i = 0; i < fp->n_instances && !rec->out_of_memory; i++) {
        for (uint32_t v = 0; v < count; v++) {
            is_vs_input regs;
            fetch_vertex(fp, first + v, i, &regs);
            shade(dev, &regs, &in->verts[v]);
        }
        for (size_t p = 0; p < n_prims && !rec->out_of_memory; p++) {
            uint32_t t[3];
            for (unsigned c = 0; c < 3; c++) t[c] = stream_idx[prim_vertex(type, p, c)];
            const rs_vertex *pv[3] = {&in->verts[t[0]], &in->verts[t[1]], &in->verts[t[2]]};
            if (!may_cover(pv, &vp, rec->x, rec->y)) continue;
            uint32_t vid[3] = {first + t[0], first + t[1], first + t[2]};
            if (!replay_prim(dev, &rs, fp, pv, vid, i, (uint32_t)p, &color, &depth)) rec->out_of_memory = true;
        }
    }
    return mark;
}

void inspect_draw_done(is_device *dev, size_t mark, bool drawn)
{
    struct dev_inspector *in = dev->inspector;
    is_inspect *rec = in->rec;
    if (drawn && !in->skip) {
        rec->draws++;
        return;
    }
    if (rec->n_fragments > mark) rec->n_fragments = mark;   /* a failed draw drew nothing */
    rec->draws_skipped++;
}
