/* core/device.c -- device creation and state: streams, frequencies, render states, constants, viewport, clear. */
#include "device_internal.h"

#include <stdarg.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void core_set_err(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}


/* Record a printf-style message for dev_last_error; returns code so callers can `return dev_fail(...)`. */
is_result dev_fail(is_device *dev, is_result code, const char *fmt, ...)
{
    if (dev) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(dev->err, sizeof dev->err, fmt, ap);
        va_end(ap);
    }
    return code;
}

/* Append a line to the debug log (device_internal.h), dropping the oldest lines when it is full. */
void dev_debug(is_device *dev, const char *fmt, ...)
{
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line, sizeof line - 1, fmt, ap);
    va_end(ap);
    if (n < 0) return;
    size_t len = strlen(line);
    line[len++] = '\n', line[len] = 0;
    char *log = dev->debug_log;
    size_t have = strlen(log);
    while (have + len >= sizeof dev->debug_log) {   /* drop the oldest line */
        char *nl = strchr(log, '\n');
        size_t drop = nl ? (size_t)(nl - log) + 1 : have;
        memmove(log, log + drop, have - drop + 1);
        have -= drop;
    }
    memcpy(log + have, line, len + 1);
}

/* The debug log's text ("" for a NULL or destroyed device). */
const char *dev_debug_log(const is_device *dev) { return dev_live(dev) ? dev->debug_log : ""; }

/* Bits of a float, as D3D9 passes float render states through a DWORD. */
static uint32_t float_bits(float f) { uint32_t u; memcpy(&u, &f, 4); return u; }
static float bits_float(uint32_t u) { float f; memcpy(&f, &u, 4); return f; }

/* D3D9's defaults for the render states this device knows (an auto depth buffer exists, so ZENABLE is TRUE). */
static void set_default_states(is_device *dev)
{
    uint32_t *s = dev->rs_state;
    s[IS_RS_ZENABLE] = IS_ZB_TRUE;
    s[IS_RS_FILLMODE] = IS_FILL_SOLID;
    s[IS_RS_SHADEMODE] = IS_SHADE_GOURAUD;
    s[IS_RS_ZWRITEENABLE] = 1;
    s[IS_RS_SRCBLEND] = IS_BLEND_ONE;
    s[IS_RS_DESTBLEND] = IS_BLEND_ZERO;
    s[IS_RS_CULLMODE] = IS_CULL_CCW;
    s[IS_RS_ZFUNC] = IS_CMP_LESSEQUAL;
    s[IS_RS_ALPHABLENDENABLE] = 0;
    s[IS_RS_MULTISAMPLEANTIALIAS] = 1;
    s[IS_RS_POSITIONDEGREE] = IS_DEGREE_CUBIC;
    s[IS_RS_NORMALDEGREE] = IS_DEGREE_LINEAR;
    s[IS_RS_PATCHEDGESTYLE] = IS_PATCHEDGE_DISCRETE;
    s[IS_RS_DEPTHBIAS] = float_bits(0.0f);
    s[IS_RS_SLOPESCALEDEPTHBIAS] = float_bits(0.0f);
    /* adaptive tessellation: the documented defaults (core/device.h) */
    s[IS_RS_ENABLEADAPTIVETESSELLATION] = 0;
    s[IS_RS_MINTESSELLATIONLEVEL] = float_bits(1.0f);
    s[IS_RS_MAXTESSELLATIONLEVEL] = float_bits(1.0f);
    s[IS_RS_ADAPTIVETESS_X] = float_bits(0.0f);
    s[IS_RS_ADAPTIVETESS_Y] = float_bits(0.0f);
    s[IS_RS_ADAPTIVETESS_Z] = float_bits(1.0f);
    s[IS_RS_ADAPTIVETESS_W] = float_bits(0.0f);
    raster_states_default(dev);   /* scissor, colour write, alpha test, stencil, clipping (and the rectangles) */
}

/* Create a device with a w x h target of `samples` samples, cleared to black and depth 1. */
is_device *dev_create(int width, int height, int samples, char *err, size_t errlen)
{
    is_device *dev = calloc(1, sizeof *dev);
    if (!dev) {
        if (err) snprintf(err, errlen, "out of memory for the device");
        return NULL;
    }
    if (samples != 1 && samples != 4) {
        if (err) snprintf(err, errlen, "%d samples per pixel: this device supports 1 or 4", samples);
        free(dev);
        return NULL;
    }
    if (width < 1 || height < 1 || width > RS_MAX_SIZE || height > RS_MAX_SIZE) {
        if (err) snprintf(err, errlen, "target size %dx%d: each side must be 1..%d", width, height, RS_MAX_SIZE);
        free(dev);
        return NULL;
    }
    dev->rs = rs_create(0);
    if (!dev->rs || rs_target_init(&dev->rt, width, height, samples) != RS_OK) {
        if (err) snprintf(err, errlen, "out of memory for a %dx%d target with %d samples", width, height, samples);
        rs_destroy(dev->rs);
        free(dev);
        return NULL;
    }
    dev->backbuffer = (is_surface){.res = {.dev = dev}, .usage = IS_USAGE_RENDERTARGET, .format = IS_FMT_A8R8G8B8,
                                   .width = (unsigned)width, .height = (unsigned)height, .samples = samples,
                                   .implicit = true, .color = dev->rt.color};
    dev->auto_ds = (is_surface){.res = {.dev = dev}, .usage = IS_USAGE_DEPTHSTENCIL, .format = IS_FMT_D24S8,
                                .width = (unsigned)width, .height = (unsigned)height, .samples = samples,
                                .implicit = true, .depth = dev->rt.depth, .stencil = dev->rt.stencil};
    dev->cur_rt = &dev->backbuffer, dev->cur_ds = &dev->auto_ds;
    set_default_states(dev);
    dev_samplers_default(dev);
    dev->ps_consts.s = dev->ps_samplers;
    for (int s = 0; s < IS_MAX_STREAMS; s++) dev->streams[s].freq = 1;
    dev->viewport = (is_viewport){0, 0, (uint32_t)width, (uint32_t)height, 0.0f, 1.0f};
    dev_viewport_update(dev);
    rs_target_clear(&dev->rt, RS_CLEAR_COLOR | RS_CLEAR_DEPTH, 0xff000000u, 1.0f);
    rs_set_scene(dev->rs, &dev->stats);   /* a frame's instanced draws share one tile pass (raster.h) */
    dev->scene.gen = 1;   /* a new buffer's generation (0) is none of the scene's */
    return dev;
}

void dev_reset(is_device *dev)
{
    if (!dev_live(dev)) return;
    dev_scene_flush(dev);
    sb_abort_recording(dev);
    if (dev->cur_rt != &dev->backbuffer || dev->cur_ds != &dev->auto_ds)   /* D3D9's Reset: the implicit ones */
        dev_bind_targets(dev, &dev->backbuffer, &dev->auto_ds);   /* (no memory needed: cannot fail) */
    memset(dev->rs_state, 0, sizeof dev->rs_state);
    set_default_states(dev);
    memset(dev->streams, 0, sizeof dev->streams);
    for (int s = 0; s < IS_MAX_STREAMS; s++) dev->streams[s].freq = 1;
    dev->ib = NULL, dev->decl = NULL, dev->vs = NULL, dev->fvf = 0;
    memset(&dev->consts, 0, sizeof dev->consts);
    dev->ps = NULL;
    memset(dev->ps_consts.c, 0, sizeof dev->ps_consts.c);
    dev_samplers_default(dev); /* no texture bound; the textures themselves stay the device's */
    dev->npatch_segments = 0, dev->npatch_eval = NULL;
    dev->viewport = (is_viewport){0, 0, (uint32_t)dev->rt.width, (uint32_t)dev->rt.height, 0.0f, 1.0f};
    dev_viewport_update(dev);
}

void dev_res_add(is_device *dev, dev_res *r, dev_res_kind kind)
{
    *r = (dev_res){NULL, dev->resources, dev, kind};
    if (dev->resources) dev->resources->prev = r;
    dev->resources = r;
}

void dev_res_remove(dev_res *r)
{
    is_device *dev = r->dev;
    if (r->prev) r->prev->next = r->next;
    else dev->resources = r->next;
    if (r->next) r->next->prev = r->prev;
    r->prev = r->next = NULL;
    if (!dev->resources && dev->destroyed) free(dev);
}

bool dev_res_owns(const is_device *dev, const void *p, dev_res_kind kind)
{
    for (const dev_res *r = dev->resources; r; r = r->next)
        if ((const void *)r == p) return r->kind == kind;
    return false;
}

/* Free the memory of a resource still listed when its device is destroyed (its handle stays for its release). */
static void res_free_contents(dev_res *r)
{
    if (r->kind == DEV_RES_VB) {
        is_vertex_buffer *vb = (is_vertex_buffer *)r;
        free(vb->data), vb->data = NULL, vb->size = 0;
    } else if (r->kind == DEV_RES_IB) {
        is_index_buffer *ib = (is_index_buffer *)r;
        free(ib->data), ib->data = NULL, ib->size = 0;
    } else if (r->kind == DEV_RES_SURF) {
        surf_free_planes((is_surface *)r);
    }
}

/* Destroy the device and the textures it still owns.  Its memory and its buffers' memory go at once; the small
 * struct itself stays until its last buffer or declaration is released (the resources' reference,
 * device_internal.h), so a buffer released after dev_destroy finds it. */
void dev_destroy(is_device *dev)
{
    if (!dev || dev->destroyed) return;
    inspect_stop(dev);
    sb_abort_recording(dev);
    if (dev->fvf_decl) {   /* the declaration SetFVF made is the device's own */
        is_vertex_declaration *d = dev->fvf_decl;
        dev->fvf_decl = NULL, dev->fvf = 0;
        if (dev->decl == d) dev->decl = NULL;
        decl_release(d);
    }
    dev_bind_targets(dev, &dev->backbuffer, &dev->auto_ds);   /* dev->rt describes the device's own planes again */
    dev_release_textures(dev);
    for (dev_res *r = dev->resources; r; r = r->next) res_free_contents(r);
    for (int s = 0; s < IS_MAX_STREAMS; s++) dev->streams[s].vb = NULL;
    dev->ib = NULL;
    dev->decl = NULL;
    rs_target_free(&dev->rt);
    rs_target_free(&dev->scratch);
    rs_destroy(dev->rs);
    free(dev->out_v);
    free(dev->out_i);
    free(dev->idx.p);
    free(dev->list.p);
    free(dev->fcache.p);
    free(dev->npatch_lv.p);
    dev_scene_free(dev);
    dev->destroyed = true;
    if (!dev->resources) free(dev);
}

const char *dev_last_error(const is_device *dev) { return dev_live(dev) ? dev->err : "no device"; }

/* Threads for shading and rasterization (0: all cores). */
void dev_set_threads(is_device *dev, int threads)
{
    if (!dev_live(dev)) return;
    dev_scene_flush(dev);   /* the records' scratch has a slot per thread */
    dev->threads = threads < 0 ? 0 : threads;
    rs_set_threads(dev->rs, dev->threads);
}

/* The scalar reference path on or off (same bytes either way). */
void dev_set_reference_path(is_device *dev, bool on)
{
    if (!dev_live(dev)) return;
    dev->reference = on;
    rs_set_reference_path(dev->rs, on);
}

bool dev_reference_path(const is_device *dev) { return dev_live(dev) && dev->reference; }

/* The rasterizer's instruction set (core.h). */
int dev_set_isa(is_device *dev, int isa) { return dev_live(dev) && rs_set_isa(dev->rs, isa) == RS_OK ? 0 : -1; }

int dev_isa(const is_device *dev) { return dev_live(dev) ? rs_isa(dev->rs) : -1; }

/* Phase times in dev_stats on or off (device_internal.h). */
void dev_set_timing(is_device *dev, bool on)
{
    if (!dev_live(dev)) return;
    dev->timing = on;
    rs_set_timing(dev->rs, on);
}

/* D3DPRESENT_PARAMETERS.Flags (device.h): IS_PRESENTFLAG_DISCARD_DEPTHSTENCIL alone, or none. */
is_result dev_set_present_flags(is_device *dev, unsigned flags)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (flags & ~IS_PRESENTFLAG_DISCARD_DEPTHSTENCIL) {
        snprintf(dev->err, sizeof dev->err, "SetPresentFlags: flags 0x%x: only DISCARD_DEPTHSTENCIL (0x2) is known",
                 flags);
        return IS_ERR_INVALIDCALL;
    }
    dev->present_flags = flags;
    return IS_OK;
}

/* Pre-tessellation culling on or off (draw_cull.c). */
void dev_set_patch_cull(is_device *dev, bool on)
{
    if (dev_live(dev)) dev->patch_cull = on;
}

is_result dev_set_vertex_declaration(is_device *dev, is_vertex_declaration *decl)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (decl && !dev_res_owns(dev, decl, DEV_RES_DECL))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetVertexDeclaration: not a live declaration of this device (another "
                        "device's, or released)");
    if (dev->recording) dev->recording->decl = decl, dev->recording->has_decl = true;
    else dev->decl = decl, dev->fvf = 0;   /* GetFVF: no FVF now (dev_set_fvf sets it after) */
    return IS_OK;
}

/* SetStreamSource: stride 0 is allowed (every vertex reads the same data), as in D3D9. */
is_result dev_set_stream_source(is_device *dev, unsigned stream, is_vertex_buffer *vb, unsigned offset,
                                unsigned stride)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (stream >= IS_MAX_STREAMS)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetStreamSource: stream %u >= %d", stream, IS_MAX_STREAMS);
    if (offset % 4)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetStreamSource: offset %u not DWORD-aligned", offset);
    if (vb && !dev_res_owns(dev, vb, DEV_RES_VB))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetStreamSource: not a live vertex buffer of this device (another "
                        "device's, or released)");
    stream_source *d = dev->recording ? &dev->recording->streams[stream] : &dev->streams[stream];
    d->vb = vb, d->offset = offset, d->stride = stride;
    if (dev->recording) dev->recording->has_source |= 1u << stream;
    return IS_OK;
}

/* SetStreamSourceFreq with D3D9's rules: INDEXEDDATA|n (n >= 1) only on stream 0, INSTANCEDATA|d (d >= 1) only
 * on other streams, never both flags, a plain divider >= 1 anywhere.  An invalid call changes nothing. */
/* SetStreamSourceFreq as the runtime answers it (docs/design.md: the documentation refuses more): a stream beyond
 * the last, INSTANCEDATA on stream 0, both flags, and a setting of 0 are refused; everything else is stored
 * (INDEXEDDATA | n on any stream, INDEXEDDATA | 0, INSTANCEDATA | 0), and the draw interprets it. */
is_result dev_set_stream_source_freq(is_device *dev, unsigned stream, uint32_t setting)
{
    const uint32_t flags = setting & (IS_STREAMSOURCE_INDEXEDDATA | IS_STREAMSOURCE_INSTANCEDATA);
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (stream >= IS_MAX_STREAMS)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetStreamSourceFreq: stream %u >= %d", stream, IS_MAX_STREAMS);
    if (flags == (IS_STREAMSOURCE_INDEXEDDATA | IS_STREAMSOURCE_INSTANCEDATA))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetStreamSourceFreq: stream %u: INDEXEDDATA and INSTANCEDATA together",
                        stream);
    if ((flags & IS_STREAMSOURCE_INSTANCEDATA) && stream == 0)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetStreamSourceFreq: INSTANCEDATA on stream 0");
    if (setting == 0) return dev_fail(dev, IS_ERR_INVALIDCALL, "SetStreamSourceFreq: stream %u: a setting of 0", stream);
    if (dev->recording) {
        dev->recording->streams[stream].freq = setting, dev->recording->has_freq |= 1u << stream;
        return IS_OK;
    }
    dev->streams[stream].freq = setting;
    return IS_OK;
}

is_result dev_get_stream_source_freq(const is_device *dev, unsigned stream, uint32_t *setting)
{
    if (!dev_live(dev) || stream >= IS_MAX_STREAMS || !setting) return IS_ERR_INVALIDCALL;
    *setting = dev->streams[stream].freq;
    return IS_OK;
}

is_result dev_set_indices(is_device *dev, is_index_buffer *ib)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (ib && !dev_res_owns(dev, ib, DEV_RES_IB))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetIndices: not a live index buffer of this device (another "
                        "device's, or released)");
    if (dev->recording) dev->recording->ib = ib, dev->recording->has_ib = true;
    else dev->ib = ib;
    return IS_OK;
}

is_result dev_set_vertex_shader(is_device *dev, const is_vertex_shader *vs)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (vs && !vs->main) return dev_fail(dev, IS_ERR_INVALIDCALL, "SetVertexShader: shader '%s' has no function",
                                         vs->name ? vs->name : "?");
    if (dev->recording) dev->recording->vs = vs, dev->recording->has_vs = true;
    else dev->vs = vs;
    return IS_OK;
}

/* SetVertexShaderConstantF: count4 float4 registers starting at c[start]. */
is_result dev_set_vertex_shader_constant_f(is_device *dev, unsigned start, const float *data, unsigned count4)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!data || start >= IS_MAX_VS_CONSTANTS || count4 > IS_MAX_VS_CONSTANTS - start)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetVertexShaderConstantF: registers c%u..c%u out of c0..c%d", start,
                        start + count4 - 1, IS_MAX_VS_CONSTANTS - 1);
    if (dev->recording) {
        memcpy(&dev->recording->c[start], data, count4 * sizeof(float4));
        for (unsigned k = 0; k < count4; k++) dev->recording->has_c[start + k] = true;
        return IS_OK;
    }
    memcpy(&dev->consts.c[start], data, count4 * sizeof(float4));
    return IS_OK;
}

is_result dev_get_vertex_declaration(const is_device *dev, is_vertex_declaration **decl)
{
    if (!dev_live(dev) || !decl) return IS_ERR_INVALIDCALL;
    *decl = dev->decl;
    return IS_OK;
}

is_result dev_get_stream_source(const is_device *dev, unsigned stream, is_vertex_buffer **vb, unsigned *offset,
                                unsigned *stride)
{
    if (!dev_live(dev) || !vb || !offset || !stride || stream >= IS_MAX_STREAMS) return IS_ERR_INVALIDCALL;
    *vb = dev->streams[stream].vb;
    *offset = dev->streams[stream].offset;
    *stride = dev->streams[stream].stride;
    return IS_OK;
}

is_result dev_get_indices(const is_device *dev, is_index_buffer **ib)
{
    if (!dev_live(dev) || !ib) return IS_ERR_INVALIDCALL;
    *ib = dev->ib;
    return IS_OK;
}

is_result dev_get_vertex_shader(const is_device *dev, const is_vertex_shader **vs)
{
    if (!dev_live(dev) || !vs) return IS_ERR_INVALIDCALL;
    *vs = dev->vs;
    return IS_OK;
}

is_result dev_get_vertex_shader_constant_f(const is_device *dev, unsigned start, float *data, unsigned count4)
{
    if (!dev_live(dev) || !data || start >= IS_MAX_VS_CONSTANTS || count4 > IS_MAX_VS_CONSTANTS - start)
        return IS_ERR_INVALIDCALL;
    memcpy(data, &dev->consts.c[start], count4 * sizeof(float4));
    return IS_OK;
}

/* Whether render state `state` takes `value`: STATE_OK, STATE_BAD_VALUE, or STATE_UNKNOWN for a state this
 * device does not implement. */
enum { STATE_UNKNOWN = -1, STATE_BAD_VALUE = 0, STATE_OK = 1 };
static int state_check(is_rs state, uint32_t v)
{
    bool ok;
    switch (state) {
    case IS_RS_ZENABLE: ok = v <= IS_ZB_USEW; break;
    case IS_RS_FILLMODE: ok = v >= IS_FILL_POINT && v <= IS_FILL_SOLID; break;
    case IS_RS_SHADEMODE: ok = v >= IS_SHADE_FLAT && v <= IS_SHADE_PHONG; break;
    case IS_RS_ZWRITEENABLE: case IS_RS_ALPHABLENDENABLE: case IS_RS_MULTISAMPLEANTIALIAS: ok = v <= 1; break;
    case IS_RS_SRCBLEND: case IS_RS_DESTBLEND: ok = v >= IS_BLEND_ZERO && v <= IS_BLEND_BOTHINVSRCALPHA; break;
    case IS_RS_CULLMODE: ok = v >= IS_CULL_NONE && v <= IS_CULL_CCW; break;
    case IS_RS_ZFUNC: ok = v >= IS_CMP_NEVER && v <= IS_CMP_ALWAYS; break;
    case IS_RS_POSITIONDEGREE: ok = v == IS_DEGREE_LINEAR || v == IS_DEGREE_CUBIC; break;
    case IS_RS_NORMALDEGREE: ok = v >= IS_DEGREE_LINEAR && v <= IS_DEGREE_CUBIC; break;   /* CUBIC: the runtime's */
    case IS_RS_PATCHEDGESTYLE: ok = v <= 1; break;
    case IS_RS_DEPTHBIAS: case IS_RS_SLOPESCALEDEPTHBIAS: ok = isfinite(bits_float(v)); break;
    case IS_RS_ENABLEADAPTIVETESSELLATION: ok = v <= 1; break;
    case IS_RS_MINTESSELLATIONLEVEL: case IS_RS_MAXTESSELLATIONLEVEL: /* finite; below 1 as the runtime takes it */
    case IS_RS_ADAPTIVETESS_X: case IS_RS_ADAPTIVETESS_Y: case IS_RS_ADAPTIVETESS_Z: case IS_RS_ADAPTIVETESS_W:
        ok = isfinite(bits_float(v));
        break;
    default: return raster_state_check(state, v);   /* core/raster_states.c's, or STATE_UNKNOWN */
    }
    return ok ? STATE_OK : STATE_BAD_VALUE;
}

/* SetRenderState: D3D9 values; float states (DEPTHBIAS, SLOPESCALEDEPTHBIAS, the tessellation levels and
 * ADAPTIVETESS_X..W) as their bits. */
is_result dev_set_render_state(is_device *dev, is_rs state, uint32_t value)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    int r = (unsigned)state < IS_RS_COUNT ? state_check(state, value) : STATE_UNKNOWN;
    if (r == STATE_UNKNOWN)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetRenderState: unknown render state %d (this device implements "
                        "the states listed in core.h)", (int)state);
    if (r == STATE_BAD_VALUE)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetRenderState: state %d does not take value %u", state, value);
    if (dev->recording) dev->recording->rs[state] = value, dev->recording->has_rs[state] = true;
    else dev->rs_state[state] = value;
    return IS_OK;
}

is_result dev_get_render_state(const is_device *dev, is_rs state, uint32_t *value)
{
    if (!dev_live(dev) || (unsigned)state >= IS_RS_COUNT || !value || state_check(state, dev->rs_state[state]) != STATE_OK)
        return IS_ERR_INVALIDCALL;
    *value = dev->rs_state[state];
    return IS_OK;
}

/* SetViewport as the runtime takes it: any position and size of at least one pixel (a viewport reaching beyond
 * the target is clipped to it when drawing and clearing), MinZ and MaxZ in [0, 1] in either order; stored as given
 * (GetViewport reads it back), with MinZ >= MaxZ drawn as [MinZ, MinZ + 0.001] (dev_viewport_update). */
is_result dev_set_viewport(is_device *dev, const is_viewport *vp)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!vp || vp->width == 0 || vp->height == 0 || !(vp->min_z >= 0.0f && vp->min_z <= 1.0f) ||
        !(vp->max_z >= 0.0f && vp->max_z <= 1.0f))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetViewport: %s", !vp ? "NULL viewport" :
                        (vp->width == 0 || vp->height == 0) ? "a width or height of 0" :
                        "MinZ or MaxZ outside [0, 1]");
    if (dev->recording) {
        dev->recording->viewport = *vp, dev->recording->has_viewport = true;
        return IS_OK;
    }
    dev->viewport = *vp;
    dev_viewport_update(dev);
    return IS_OK;
}

/* The rasterizer's viewport of dev (dev->rs_vp) and the clip-space map (dev->remap) from the set viewport: the
 * viewport clipped to the target (one that misses the target entirely becomes a 1x1 viewport that every vertex
 * is mapped outside of: nothing is drawn), and MaxZ = MinZ + 0.001 when MinZ >= MaxZ, as the runtime draws it
 * (DXVK's D3D9DeviceEx::SetViewport). */
void dev_viewport_update(is_device *dev)
{
    const is_viewport *v = &dev->viewport;
    const double X = v->x, Y = v->y, W = v->width, H = v->height, tw = dev->rt.width, th = dev->rt.height;
    const double x0 = X < tw ? X : tw, x1 = X + W < tw ? X + W : tw, y0 = Y < th ? Y : th, y1 = Y + H < th ? Y + H : th;
    float max_z = v->min_z < v->max_z ? v->max_z : v->min_z + 0.001f;
    dev->remap = (vp_remap){false, 1.0f, 0.0f, 1.0f, 0.0f};
    if (x0 >= x1 || y0 >= y1) {   /* outside the target: x' = 4w lies outside -w..w for every w > 0 */
        dev->rs_vp = (rs_viewport){0, 0, 1, 1, v->min_z, max_z};
        dev->remap = (vp_remap){true, 0.0f, 4.0f, 0.0f, 4.0f};
        return;
    }
    dev->rs_vp = (rs_viewport){(int)x0, (int)y0, (int)(x1 - x0), (int)(y1 - y0), v->min_z, max_z};
    if (x0 == X && x1 == X + W && y0 == Y && y1 == Y + H) return;
    const double w = x1 - x0, h = y1 - y0;
    dev->remap = (vp_remap){true, (float)(W / w), (float)((2.0 * (X - x0) + W) / w - 1.0), (float)(H / h),
                            (float)(1.0 - (2.0 * (Y - y0) + H) / h)};
}

is_result dev_get_viewport(const is_device *dev, is_viewport *vp)
{
    if (!dev_live(dev) || !vp) return IS_ERR_INVALIDCALL;
    *vp = dev->viewport;
    return IS_OK;
}

/* SetNPatchMode: every value stored as the runtime stores it (below 1 or NaN disables; draws cap it, device.h). */
is_result dev_set_npatch_mode(is_device *dev, float segments)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    dev->npatch_segments = segments;
    return IS_OK;
}

float dev_get_npatch_mode(const is_device *dev) { return dev_live(dev) ? dev->npatch_segments : 0.0f; }

is_result dev_set_npatch_evaluator(is_device *dev, is_npatch_eval_fn fn)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    dev->npatch_eval = fn;
    return IS_OK;
}

/* Clear: D3DCOLOR (ARGB) into packed RGBA8; z must be in [0, 1].  Resets the statistics. */
/* Clear the pixels of rectangle r (already within the target) with the packed colour, z and stencil as flags say. */
static void clear_rect(is_device *dev, is_rect r, unsigned flags, uint32_t rgba, float z, uint32_t stencil)
{
    if (r.left < r.right && r.top < r.bottom) {
        rs_target_clear_rect(&dev->rt, r.left, r.top, r.right, r.bottom, flags, rgba, z);
        if (flags & IS_CLEAR_STENCIL) rs_target_clear_stencil(&dev->rt, r.left, r.top, r.right, r.bottom, stencil);
    }
}

is_result dev_clear_rects(is_device *dev, unsigned count, const is_rect *rects, unsigned flags, uint32_t argb, float z)
{
    return dev_clear_rects_stencil(dev, count, rects, flags, argb, z, 0);
}

is_result dev_clear_rects_stencil(is_device *dev, unsigned count, const is_rect *rects, unsigned flags,
                                  uint32_t argb, float z, uint32_t stencil)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if ((flags & ~(unsigned)(IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER | IS_CLEAR_STENCIL)) || !(z >= 0.0f && z <= 1.0f))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "Clear: flags %#x or z %g invalid", flags, (double)z);
    if ((flags & (IS_CLEAR_ZBUFFER | IS_CLEAR_STENCIL)) && !dev->cur_ds)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "Clear: ZBUFFER or STENCIL without a depth-stencil surface");
    if ((flags & IS_CLEAR_STENCIL) && dev->cur_ds->format != IS_FMT_D24S8)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "Clear: STENCIL on a depth-stencil surface without stencil bits");
    if (count == 0 && rects) return IS_OK;   /* the runtime: nothing cleared */
    dev_scene_flush(dev);   /* the recorded draws first (their counters, then zeroed below) */
    uint32_t a = argb >> 24, r = (argb >> 16) & 0xff, g = (argb >> 8) & 0xff, b = argb & 0xff;
    uint32_t rgba = r | g << 8 | b << 16 | a << 24;
    const is_viewport *vp = &dev->viewport;   /* the area: the viewport, within the target */
    const int64_t vx1 = (int64_t)vp->x + vp->width, vy1 = (int64_t)vp->y + vp->height;
    is_rect area = {vp->x < (uint32_t)dev->rt.width ? (int32_t)vp->x : dev->rt.width,
                    vp->y < (uint32_t)dev->rt.height ? (int32_t)vp->y : dev->rt.height,
                    vx1 < dev->rt.width ? (int32_t)vx1 : dev->rt.width, vy1 < dev->rt.height ? (int32_t)vy1 : dev->rt.height};
    area = raster_scissor_clip(dev, area);   /* and the scissor rectangle, when the test is on */
    bool whole = area.left == 0 && area.top == 0 && area.right == dev->rt.width && area.bottom == dev->rt.height;
    if (!rects) count = 0;
    if (whole && count == 0) {   /* the whole target: deferred per tile, and a new frame (the stencil at once) */
        rs_target_clear_deferred(dev->rs, &dev->rt, flags & (IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER), rgba, z);
        if (flags & IS_CLEAR_STENCIL) rs_target_clear_stencil(&dev->rt, 0, 0, dev->rt.width, dev->rt.height, stencil);
    } else {
        rs_target_flush(dev->rs, &dev->rt);
        if (count == 0) clear_rect(dev, area, flags, rgba, z, stencil);
        for (unsigned k = 0; k < count; k++) {
            const is_rect *q = &rects[k];   /* its part of the area */
            is_rect c = {q->left > area.left ? q->left : area.left, q->top > area.top ? q->top : area.top,
                         q->right < area.right ? q->right : area.right, q->bottom < area.bottom ? q->bottom : area.bottom};
            clear_rect(dev, c, flags, rgba, z, stencil);
        }
    }
    memset(&dev->stats, 0, sizeof dev->stats);
    dev->shaded = 0;
    dev->instances_culled = 0;
    return IS_OK;
}

is_result dev_clear(is_device *dev, unsigned flags, uint32_t argb, float z)
{
    return dev_clear_rects(dev, 0, NULL, flags, argb, z);
}

/* The target with the recorded draws run and the planes `planes` (RS_CLEAR_*) of any deferred clear written;
 * NULL for a dead device. */
static rs_target *target_flushed(is_device *dev, unsigned planes)
{
    if (!dev_live(dev)) return NULL;
    rs_target_flush_planes(dev->rs, &dev->rt, planes);   /* the recorded draws, untouched tiles filled in their pass */
    dev_scene_flush(dev);                                /* (their counters and errors) */
    return &dev->rt;
}

/* The target, with any deferred clear written (so its planes may be read directly). */
rs_target *dev_render_target(is_device *dev) { return target_flushed(dev, RS_CLEAR_COLOR | RS_CLEAR_DEPTH); }

/* The target with its colour and AOV planes written (its depth's deferred clear may stay deferred; with
 * DISCARD_DEPTHSTENCIL the frame's drawn depth may be dropped too). */
const rs_target *dev_present(is_device *dev)
{
    const bool discard = dev_live(dev) && (dev->present_flags & IS_PRESENTFLAG_DISCARD_DEPTHSTENCIL);
    return target_flushed(dev, RS_CLEAR_COLOR | RS_PRESENT | (discard ? RS_DISCARD_DEPTH : 0u));
}

/* The recorded draws run now; the first error of one since the last call (device.h). */
is_result dev_flush(is_device *dev)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    dev_scene_flush(dev);
    const is_result r = dev->scene.err;
    dev->scene.err = IS_OK;
    return r;
}
is_result dev_get_render_target_data(is_device *dev, uint32_t *rgba, size_t count)
{
    if (!dev_live(dev) || !rgba) return IS_ERR_INVALIDCALL;
    const rs_target *rt = target_flushed(dev, RS_CLEAR_COLOR);   /* the colour alone is read (not a present) */
    if (count < (size_t)rt->width * (size_t)rt->height) {
        snprintf(dev->err, sizeof dev->err, "GetRenderTargetData: a buffer of %zu pixels for a %dx%d target", count,
                 rt->width, rt->height);
        return IS_ERR_INVALIDCALL;
    }
    rs_target_resolve(rt, rgba);
    return IS_OK;
}

/* The recorded draws run (their counters), on a device a const getter was given: every device is dev_create's
 * (never a const object), so the cast is sound. */
static void flush_for_read(const is_device *dev) { dev_scene_flush((is_device *)(uintptr_t)dev); }

/* The counters (the recorded draws run first: their counters); a NULL (or destroyed) device has none: zeros. */
const rs_stats *dev_stats(const is_device *dev)
{
    static const rs_stats none = {0};
    if (!dev_live(dev)) return &none;
    flush_for_read(dev);
    return &dev->stats;
}
uint64_t dev_vertices_shaded(const is_device *dev)
{
    if (!dev_live(dev)) return 0;
    flush_for_read(dev);
    return dev->shaded;
}
uint64_t dev_instances_culled(const is_device *dev)
{
    if (!dev_live(dev)) return 0;
    flush_for_read(dev);
    return dev->instances_culled;
}

/* The render-state values dev_rs_state and dev_clear pass to the rasterizer unchanged: D3D9's values on both
 * sides (core.h's IS_*, raster.h's RS_*), tied here so that a change to one side that breaks the other does not
 * compile.  (Compared as int: they are constants of different enums.) */
#define SAME(a, b) ((int)(a) == (int)(b))
_Static_assert(SAME(IS_CULL_NONE, RS_CULL_NONE) && SAME(IS_CULL_CW, RS_CULL_CW) && SAME(IS_CULL_CCW, RS_CULL_CCW),
               "cull modes: IS_CULL_* == RS_CULL_*");
_Static_assert(SAME(IS_FILL_POINT, RS_FILL_POINT) && SAME(IS_FILL_WIREFRAME, RS_FILL_WIREFRAME) &&
               SAME(IS_FILL_SOLID, RS_FILL_SOLID), "fill modes: IS_FILL_* == RS_FILL_*");
_Static_assert(SAME(IS_SHADE_FLAT, RS_SHADE_FLAT) && SAME(IS_SHADE_GOURAUD, RS_SHADE_GOURAUD),
               "shade modes: IS_SHADE_* == RS_SHADE_*");
_Static_assert(SAME(IS_CMP_NEVER, RS_CMP_NEVER) && SAME(IS_CMP_LESS, RS_CMP_LESS) &&
               SAME(IS_CMP_EQUAL, RS_CMP_EQUAL) && SAME(IS_CMP_LESSEQUAL, RS_CMP_LESSEQUAL) &&
               SAME(IS_CMP_GREATER, RS_CMP_GREATER) && SAME(IS_CMP_NOTEQUAL, RS_CMP_NOTEQUAL) &&
               SAME(IS_CMP_GREATEREQUAL, RS_CMP_GREATEREQUAL) && SAME(IS_CMP_ALWAYS, RS_CMP_ALWAYS),
               "compare functions: IS_CMP_* == RS_CMP_*");
_Static_assert(SAME(IS_BLEND_ZERO, RS_BLEND_ZERO) && SAME(IS_BLEND_ONE, RS_BLEND_ONE) &&
               SAME(IS_BLEND_SRCCOLOR, RS_BLEND_SRCCOLOR) && SAME(IS_BLEND_INVSRCCOLOR, RS_BLEND_INVSRCCOLOR) &&
               SAME(IS_BLEND_SRCALPHA, RS_BLEND_SRCALPHA) && SAME(IS_BLEND_INVSRCALPHA, RS_BLEND_INVSRCALPHA) &&
               SAME(IS_BLEND_DESTALPHA, RS_BLEND_DESTALPHA) && SAME(IS_BLEND_INVDESTALPHA, RS_BLEND_INVDESTALPHA) &&
               SAME(IS_BLEND_DESTCOLOR, RS_BLEND_DESTCOLOR) && SAME(IS_BLEND_INVDESTCOLOR, RS_BLEND_INVDESTCOLOR) &&
               SAME(IS_BLEND_SRCALPHASAT, RS_BLEND_SRCALPHASAT),
               "blend factors: IS_BLEND_* == RS_BLEND_*");
_Static_assert(SAME(IS_STENCILOP_KEEP, RS_STENCILOP_KEEP) && SAME(IS_STENCILOP_ZERO, RS_STENCILOP_ZERO) &&
               SAME(IS_STENCILOP_REPLACE, RS_STENCILOP_REPLACE) && SAME(IS_STENCILOP_INCRSAT, RS_STENCILOP_INCRSAT) &&
               SAME(IS_STENCILOP_DECRSAT, RS_STENCILOP_DECRSAT) && SAME(IS_STENCILOP_INVERT, RS_STENCILOP_INVERT) &&
               SAME(IS_STENCILOP_INCR, RS_STENCILOP_INCR) && SAME(IS_STENCILOP_DECR, RS_STENCILOP_DECR) &&
               SAME(IS_MAX_USER_CLIP_PLANES, RS_MAX_CLIP_PLANES), "stencil operations: IS_STENCILOP_* == RS_*");
_Static_assert(SAME(IS_CLEAR_TARGET, RS_CLEAR_COLOR) && SAME(IS_CLEAR_ZBUFFER, RS_CLEAR_DEPTH) &&
               SAME(IS_CLEAR_STENCIL, RS_CLEAR_STENCIL),
               "clear flags: IS_CLEAR_* == RS_CLEAR_*");
#undef SAME

/* A blend factor as the rasterizer has it: BOTH(INV)SRCALPHA as (INV)SRCALPHA (device.h), the rest as they are. */
static int blend_factor(uint32_t f)
{
    if (f == IS_BLEND_BOTHSRCALPHA) return RS_BLEND_SRCALPHA;
    if (f == IS_BLEND_BOTHINVSRCALPHA) return RS_BLEND_INVSRCALPHA;
    return (int)f;
}

/* The rasterizer's copy of the current states. */
rs_state dev_rs_state(const is_device *dev)
{
    const uint32_t *s = dev->rs_state;
    const uint32_t src = s[IS_RS_SRCBLEND];   /* BOTH(INV)SRCALPHA as SRCBLEND sets both factors */
    const bool both = src == IS_BLEND_BOTHSRCALPHA || src == IS_BLEND_BOTHINVSRCALPHA;
    rs_state st = {
        .cull_mode = (int)s[IS_RS_CULLMODE],
        .fill_mode = (int)s[IS_RS_FILLMODE],
        .shade_mode = s[IS_RS_SHADEMODE] == IS_SHADE_FLAT ? RS_SHADE_FLAT : RS_SHADE_GOURAUD,   /* PHONG too */
        .z_enable = s[IS_RS_ZENABLE] != 0,
        .z_write = s[IS_RS_ZWRITEENABLE] != 0,
        .z_func = (int)s[IS_RS_ZFUNC],
        .blend_enable = s[IS_RS_ALPHABLENDENABLE] != 0,
        .src_blend = blend_factor(src),
        .dst_blend = both ? (src == IS_BLEND_BOTHSRCALPHA ? RS_BLEND_INVSRCALPHA : RS_BLEND_SRCALPHA)
                          : blend_factor(s[IS_RS_DESTBLEND]),
        .multisample = s[IS_RS_MULTISAMPLEANTIALIAS] != 0 && dev->rt.samples > 1,
        .depth_bias = bits_float(s[IS_RS_DEPTHBIAS]),
        .slope_scale_depth_bias = bits_float(s[IS_RS_SLOPESCALEDEPTHBIAS]),
        .attr_mask = dev->vs ? dev->vs->outputs : 0,
        .ps = dev->ps ? dev_ps_run : NULL,
        .ps_ctx = dev,
        .ps_inputs = dev->ps ? dev->ps->inputs : 0,
        .viewport = dev->rs_vp,
    };
    raster_states_apply(dev, &st);   /* core/raster_states.c */
    if (dev->no_depth) st.z_enable = st.z_write = false;   /* no usable depth-stencil surface (core/surface.c) */
    if (dev->no_depth || dev->cur_ds->format != IS_FMT_D24S8) st.stencil_enable = false;
    return st;
}
