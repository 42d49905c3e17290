/* core/surface.c -- surfaces (CreateRenderTarget, CreateDepthStencilSurface, CreateOffscreenPlainSurface,
 * GetSurfaceLevel), SetRenderTarget / SetDepthStencilSurface (which planes dev->rt describes) and
 * GetRenderTargetData.  Rules: core/device.h, "render targets and surfaces"; the struct: device_internal.h. */
#include "device_internal.h"

#include <stdlib.h>
#include <string.h>

/* Whether f is a colour format of surfaces and render-target textures (A8R8G8B8, X8R8G8B8). */
static bool color_format(is_format f) { return f == IS_FMT_A8R8G8B8 || f == IS_FMT_X8R8G8B8; }
/* Whether f is a depth-stencil format (D24S8, D24X8, D16). */
static bool depth_format(is_format f) { return f == IS_FMT_D24S8 || f == IS_FMT_D24X8 || f == IS_FMT_D16; }

/* Whether p is a surface of dev: its back buffer, its automatic depth surface, or one in its registry (compared,
 * never read). */
static bool surf_known(const is_device *dev, const void *p)
{
    return p == &dev->backbuffer || p == &dev->auto_ds || dev_res_owns(dev, p, DEV_RES_SURF);
}

/* The planes of a w x h target of `samples` samples (rs_target_init's, 64-byte aligned) into s: the colour plane
 * when color, else depth (1.0) and stencil (0).  IS_OK or IS_ERR_OUTOFMEMORY (s unchanged). */
static is_result alloc_planes(is_surface *s, unsigned w, unsigned h, int samples, bool color)
{
    rs_target t;
    if (rs_target_init(&t, (int)w, (int)h, samples) != RS_OK) return IS_ERR_OUTOFMEMORY;
    if (color) {
        s->color = t.color, t.color = NULL;
    } else {
        rs_target_clear(&t, RS_CLEAR_DEPTH, 0, 1.0f);
        s->depth = t.depth, s->stencil = t.stencil, t.depth = NULL, t.stencil = NULL;
    }
    rs_target_free(&t);
    return IS_OK;
}

void surf_free_planes(is_surface *s)
{
    free(s->color), free(s->depth), free(s->stencil), free(s->bits);
    s->color = NULL, s->depth = NULL, s->stencil = NULL, s->bits = NULL;
}

/* The checks shared by the Create* calls: IS_OK, or the failure with its message. */
static is_result check_create(is_device *dev, const char *what, unsigned w, unsigned h, unsigned ms, is_surface **out)
{
    if (!out) return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: NULL output pointer", what);
    if (w < 1 || h < 1 || w > RS_MAX_SIZE || h > RS_MAX_SIZE)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "%s: size %ux%u: each side must be 1..%d", what, w, h, RS_MAX_SIZE);
    if (ms != IS_MULTISAMPLE_NONE && ms != IS_MULTISAMPLE_4_SAMPLES)
        return dev_fail(dev, IS_ERR_NOTAVAILABLE, "%s: multisample type %u: this device has NONE (0) and 4_SAMPLES "
                        "(4)", what, ms);
    return IS_OK;
}

/* A new surface of dev in the registry with the given description and planes (kind: usage), into *out. */
static is_result make_surface(is_device *dev, const char *what, unsigned w, unsigned h, is_format f, uint32_t usage,
                              unsigned ms, is_surface **out)
{
    is_surface *s = calloc(1, sizeof *s);
    is_result r = s ? IS_OK : IS_ERR_OUTOFMEMORY;
    if (s) *s = (is_surface){.usage = usage, .format = f, .width = w, .height = h, .samples = ms ? 4 : 1};
    if (r == IS_OK && usage) r = alloc_planes(s, w, h, s->samples, usage == IS_USAGE_RENDERTARGET);
    if (r == IS_OK && !usage && !(s->bits = calloc((size_t)w * h, 4))) r = IS_ERR_OUTOFMEMORY;
    if (r != IS_OK) {
        free(s);
        return dev_fail(dev, r, "%s: out of memory for %ux%u pixels", what, w, h);
    }
    dev_res_add(dev, &s->res, DEV_RES_SURF);
    *out = s;
    return IS_OK;
}

is_result dev_create_render_target(is_device *dev, unsigned width, unsigned height, is_format format,
                                   unsigned multisample, is_surface **out)
{
    if (out) *out = NULL;
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    is_result r = check_create(dev, "CreateRenderTarget", width, height, multisample, out);
    if (r != IS_OK) return r;
    if (!color_format(format))
        return dev_fail(dev, IS_ERR_NOTAVAILABLE, "CreateRenderTarget: format %d is not a target format of this "
                        "device (A8R8G8B8 21, X8R8G8B8 22)", (int)format);
    return make_surface(dev, "CreateRenderTarget", width, height, format, IS_USAGE_RENDERTARGET, multisample, out);
}

is_result dev_create_depth_stencil_surface(is_device *dev, unsigned width, unsigned height, is_format format,
                                           unsigned multisample, is_surface **out)
{
    if (out) *out = NULL;
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    is_result r = check_create(dev, "CreateDepthStencilSurface", width, height, multisample, out);
    if (r != IS_OK) return r;
    if (!depth_format(format))
        return dev_fail(dev, IS_ERR_NOTAVAILABLE, "CreateDepthStencilSurface: format %d is not a depth format of this "
                        "device (D24S8 75, D24X8 77, D16 80)", (int)format);
    return make_surface(dev, "CreateDepthStencilSurface", width, height, format, IS_USAGE_DEPTHSTENCIL, multisample,
                        out);
}

is_result dev_create_offscreen_plain_surface(is_device *dev, unsigned width, unsigned height, is_format format,
                                             is_surface **out)
{
    if (out) *out = NULL;
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    is_result r = check_create(dev, "CreateOffscreenPlainSurface", width, height, 0, out);
    if (r != IS_OK) return r;
    if (!color_format(format))
        return dev_fail(dev, IS_ERR_NOTAVAILABLE, "CreateOffscreenPlainSurface: format %d (this device has A8R8G8B8 "
                        "21, X8R8G8B8 22)", (int)format);
    return make_surface(dev, "CreateOffscreenPlainSurface", width, height, format, 0, 0, out);
}

is_result tex_get_surface_level(is_texture *tex, unsigned level, is_surface **out)
{
    if (out) *out = NULL;
    if (!tex || !dev_live(tex->dev)) return IS_ERR_INVALIDCALL;
    if (!out || level >= tex_get_level_count(tex))
        return dev_fail(tex->dev, IS_ERR_INVALIDCALL, "GetSurfaceLevel: level %u of a texture of %u levels (or NULL "
                        "output)", level, tex_get_level_count(tex));
    if (!tex->surf[level]) {
        is_surface *s = calloc(1, sizeof *s);
        if (!s) return dev_fail(tex->dev, IS_ERR_OUTOFMEMORY, "GetSurfaceLevel: out of memory");
        *s = (is_surface){.usage = tex->usage & IS_USAGE_RENDERTARGET, .format = tex->format, .width = tex->lv[level].w,
                          .height = tex->lv[level].h, .samples = 1, .tex = tex, .level = level};
        dev_res_add(tex->dev, &s->res, DEV_RES_SURF);
        tex->surf[level] = s;
    }
    *out = tex->surf[level];
    return IS_OK;
}

/* Unlink and free surface s (a created one, or a texture's level): the device goes back to its back buffer when s
 * is its target, and to no depth-stencil surface when s is that. */
static void surf_drop(is_surface *s)
{
    is_device *dev = s->res.dev;
    if (dev_live(dev) && dev->cur_rt == s) {
        dev_bind_targets(dev, &dev->backbuffer, dev->cur_ds);   /* the back buffer's planes need no memory */
        dev->viewport = (is_viewport){0, 0, dev->backbuffer.width, dev->backbuffer.height, 0.0f, 1.0f};
        dev->scissor = (is_rect){0, 0, (int32_t)dev->backbuffer.width, (int32_t)dev->backbuffer.height};
        dev_viewport_update(dev);
    }
    if (dev_live(dev) && dev->cur_ds == s) dev_bind_targets(dev, dev->cur_rt, NULL);
    surf_free_planes(s);
    dev_res_remove(&s->res);   /* may free a destroyed device: dev is not read after it */
    free(s);
}

void surf_release(is_surface *s)
{
    if (!s || s->implicit || s->tex) return;   /* the device's or a texture's: theirs to free */
    surf_drop(s);
}

void surf_release_texture_levels(is_texture *t)
{
    for (unsigned l = 0; l < IS_MAX_TEXTURE_LEVELS; l++)
        if (t->surf[l]) surf_drop(t->surf[l]), t->surf[l] = NULL;
}

is_result surf_get_desc(const is_surface *s, is_surface_desc *out)
{
    if (!s || !dev_live(s->res.dev) || !out) return IS_ERR_INVALIDCALL;
    *out = (is_surface_desc){s->format, s->usage, s->width, s->height,
                             s->samples > 1 ? IS_MULTISAMPLE_4_SAMPLES : IS_MULTISAMPLE_NONE};
    return IS_OK;
}

is_result surf_lock_rect(is_surface *s, const is_rect *r, int *pitch, void **bits)
{
    if (!s || !dev_live(s->res.dev)) return IS_ERR_INVALIDCALL;
    if (!pitch || !bits) return dev_fail(s->res.dev, IS_ERR_INVALIDCALL, "LockRect: NULL output pointer");
    if (!s->bits) return dev_fail(s->res.dev, IS_ERR_INVALIDCALL, "LockRect: only system-memory surfaces lock here "
                                  "(render targets are not lockable, nor texture levels through their surface)");
    if (s->locked) return dev_fail(s->res.dev, IS_ERR_INVALIDCALL, "LockRect: the surface is locked already");
    size_t off = 0;
    if (r) {
        if (r->left < 0 || r->top < 0 || r->left >= r->right || r->top >= r->bottom || (uint32_t)r->right > s->width ||
            (uint32_t)r->bottom > s->height)
            return dev_fail(s->res.dev, IS_ERR_INVALIDCALL, "LockRect: rect (%d, %d)-(%d, %d) is empty or outside the "
                            "%ux%u surface", r->left, r->top, r->right, r->bottom, s->width, s->height);
        off = ((size_t)r->top * s->width + (size_t)r->left) * 4;
    }
    s->locked = true;
    *pitch = (int)(s->width * 4), *bits = s->bits + off;
    return IS_OK;
}

is_result surf_unlock_rect(is_surface *s)
{
    if (!s || !dev_live(s->res.dev)) return IS_ERR_INVALIDCALL;
    if (!s->locked) return dev_fail(s->res.dev, IS_ERR_INVALIDCALL, "UnlockRect: the surface is not locked");
    s->locked = false;
    return IS_OK;
}

/* ---------------------------------------- binding ---------------------------------------- */

/* Packed RGBA8 (R in the low byte) to a D3D9 A8R8G8B8 DWORD (0xAARRGGBB) and back: R and B swap. */
static uint32_t swap_rb(uint32_t v) { return (v & 0xff00ff00u) | (v >> 16 & 0xffu) | (v & 0xffu) << 16; }

/* Copy n pixels between a colour plane and a level's texels (A8R8G8B8 / X8R8G8B8 DWORDs), either way. */
static void convert_pixels(const uint32_t *src, uint32_t *dst, size_t n)
{
    for (size_t k = 0; k < n; k++) dst[k] = swap_rb(src[k]);
}

/* A render-target texture's level s into its colour plane (bind: allocated on first use), or the plane back into
 * the level's texels (unbind; an AUTOGENMIPMAP texture's sublevels generated). */
static is_result level_sync(is_surface *s, bool bind)
{
    const tex_level *l = &s->tex->lv[s->level];
    const size_t n = (size_t)l->w * l->h;
    if (bind) {
        if (!s->color && alloc_planes(s, l->w, l->h, 1, true) != IS_OK) return IS_ERR_OUTOFMEMORY;
        convert_pixels((const uint32_t *)(const void *)l->bits, s->color, n);
        return IS_OK;
    }
    convert_pixels(s->color, (uint32_t *)(void *)l->bits, n);
    if (s->level == 0 && (s->tex->usage & IS_USAGE_AUTOGENMIPMAP)) tex_filter_texture(s->tex);
    return IS_OK;
}

/* Copy the top-left w x h pixels (samples each) of ds's planes into t's (into: true) or back. */
static void copy_depth(is_surface *ds, rs_target *t, bool into)
{
    const size_t row = (size_t)t->width * (size_t)t->samples, drow = (size_t)ds->width * (size_t)t->samples;
    for (size_t y = 0; y < (size_t)t->height; y++) {
        float *a = t->depth + y * row, *b = ds->depth + y * drow;
        uint8_t *sa = t->stencil + y * row, *sb = ds->stencil + y * drow;
        memcpy(into ? a : b, into ? b : a, row * sizeof *a);
        memcpy(into ? sa : sb, into ? sb : sa, row);
    }
}

/* dev->scratch with room for a w x h target of `samples` (kept when its size is right). */
static is_result scratch_for(is_device *dev, unsigned w, unsigned h, int samples)
{
    rs_target *t = &dev->scratch;
    if (t->depth && t->width == (int)w && t->height == (int)h && t->samples == samples) return IS_OK;
    rs_target n;
    if (rs_target_init(&n, (int)w, (int)h, samples) != RS_OK) return IS_ERR_OUTOFMEMORY;
    free(n.color), n.color = NULL;
    rs_target_free(t);
    *t = n;
    return IS_OK;
}

/* Leave the current targets: the back buffer's AOV planes saved, a level's plane written back, a copied depth
 * written back. */
static void unbind_current(is_device *dev)
{
    is_surface *rt = dev->cur_rt, *ds = dev->cur_ds;
    if (rt == &dev->backbuffer) {
        rt->n_aov = dev->rt.n_aov;
        memcpy(rt->aov, dev->rt.aov, sizeof rt->aov);
    }
    if (rt && rt->tex) level_sync(rt, false);
    if (ds && dev->ds_copied) copy_depth(ds, &dev->rt, false);
}

is_result dev_bind_targets(is_device *dev, is_surface *rt, is_surface *ds)
{
    rs_target_flush(dev->rs, &dev->rt);
    const bool fits = ds && ds->width >= rt->width && ds->height >= rt->height && ds->samples == rt->samples;
    const bool exact = fits && ds->width == rt->width && ds->height == rt->height;
    if ((!exact && scratch_for(dev, rt->width, rt->height, rt->samples) != IS_OK) ||
        (rt->tex && rt != dev->cur_rt && !rt->color && alloc_planes(rt, rt->width, rt->height, 1, true) != IS_OK))
        return dev_fail(dev, IS_ERR_OUTOFMEMORY, "SetRenderTarget: out of memory for a %ux%u target", rt->width,
                        rt->height);
    unbind_current(dev);
    if (rt->tex) level_sync(rt, true);
    dev->cur_rt = rt, dev->cur_ds = ds;
    dev->rt.width = (int)rt->width, dev->rt.height = (int)rt->height, dev->rt.samples = rt->samples;
    dev->rt.color = rt->color;
    dev->rt.n_aov = rt == &dev->backbuffer ? rt->n_aov : 0;
    memcpy(dev->rt.aov, rt->aov, sizeof dev->rt.aov);
    dev->ds_copied = fits && !exact, dev->no_depth = !fits;
    dev->rt.depth = exact ? ds->depth : dev->scratch.depth;
    dev->rt.stencil = exact ? ds->stencil : dev->scratch.stencil;
    if (dev->ds_copied) copy_depth(ds, &dev->rt, true);
    return IS_OK;
}

is_result dev_set_render_target(is_device *dev, unsigned index, is_surface *s)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (index != 0)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetRenderTarget: index %u: this device has one render target (0)",
                        index);
    if (!s || !surf_known(dev, s))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetRenderTarget: %s", !s ? "NULL surface (index 0 needs one)" :
                        "not a live surface of this device (another device's, or released)");
    if (s->usage != IS_USAGE_RENDERTARGET)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetRenderTarget: the surface is not a render target (usage %#x)",
                        s->usage);
    is_result r = dev_bind_targets(dev, s, dev->cur_ds);
    if (r != IS_OK) return r;
    dev->viewport = (is_viewport){0, 0, s->width, s->height, 0.0f, 1.0f};
    dev->scissor = (is_rect){0, 0, (int32_t)s->width, (int32_t)s->height};
    dev_viewport_update(dev);
    return IS_OK;
}

is_result dev_get_render_target(const is_device *dev, unsigned index, is_surface **out)
{
    if (!dev_live(dev) || !out || index != 0) return IS_ERR_INVALIDCALL;
    *out = dev->cur_rt;
    return IS_OK;
}

is_result dev_set_depth_stencil_surface(is_device *dev, is_surface *s)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (s && !surf_known(dev, s))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetDepthStencilSurface: not a live surface of this device "
                        "(another device's, or released)");
    if (s && s->usage != IS_USAGE_DEPTHSTENCIL)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetDepthStencilSurface: the surface is not a depth-stencil surface "
                        "(usage %#x)", s->usage);
    return dev_bind_targets(dev, dev->cur_rt, s);
}

is_result dev_get_depth_stencil_surface(const is_device *dev, is_surface **out)
{
    if (!dev_live(dev) || !out) return IS_ERR_INVALIDCALL;
    *out = dev->cur_ds;
    return dev->cur_ds ? IS_OK : IS_ERR_NOTFOUND;
}

is_result dev_get_render_target_surface_data(is_device *dev, is_surface *src, is_surface *dst)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!src || !dst || !surf_known(dev, src) || !surf_known(dev, dst))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "GetRenderTargetData: a NULL surface or not a live surface of this "
                        "device");
    if (src->usage != IS_USAGE_RENDERTARGET || src->samples != 1 || !dst->bits || dst->locked ||
        src->width != dst->width || src->height != dst->height || src->format != dst->format)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "GetRenderTargetData: needs a one-sample render target and an "
                        "unlocked system-memory surface of its size and format (%ux%u %d into %ux%u %d)", src->width,
                        src->height, (int)src->format, dst->width, dst->height, (int)dst->format);
    const size_t n = (size_t)src->width * src->height;
    if (src == dev->cur_rt) rs_target_flush(dev->rs, &dev->rt);
    if (src->tex && src != dev->cur_rt) memcpy(dst->bits, src->tex->lv[src->level].bits, n * 4);
    else convert_pixels(src->color, (uint32_t *)(void *)dst->bits, n);
    return IS_OK;
}
