/* core/texture.c -- textures (CreateTexture, LockRect / UnlockRect, GenerateMipSubLevels, D3DXFilterTexture), the
 * device's list of its live textures, and the samplers' textures and states (SetTexture, SetSamplerState).
 * Sampling is core/sample.c; images into textures core/texture_file.c.  Rules: core/texture.h. */
#include "device_internal.h"

#include <stdlib.h>
#include <string.h>

/* Bytes per texel of a texture format; 0 for a format textures do not take. */
static unsigned format_bpp(is_format f)
{
    switch (f) {
    case IS_FMT_A8R8G8B8: case IS_FMT_X8R8G8B8: case IS_FMT_R32F: return 4;
    case IS_FMT_A32B32G32R32F: return 16;
    default: return 0;
    }
}

/* The number of levels of a whole chain down to 1 x 1 for a w x h texture. */
static unsigned chain_length(unsigned w, unsigned h)
{
    unsigned m = w > h ? w : h, n = 1;
    while (m > 1) m >>= 1, n++;
    return n;
}

/* The checks of CreateTexture's arguments: IS_OK with the levels to keep in *kept, or the failure. */
static is_result check_create(is_device *dev, unsigned width, unsigned height, unsigned levels, uint32_t usage,
                              is_format format, unsigned *kept)
{
    if (width < 1 || height < 1 || width > IS_MAX_TEXTURE_SIZE || height > IS_MAX_TEXTURE_SIZE)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateTexture: size %ux%u: each side must be 1..%d", width, height,
                        IS_MAX_TEXTURE_SIZE);
    if (usage & ~(IS_USAGE_DYNAMIC | IS_USAGE_AUTOGENMIPMAP | IS_USAGE_RENDERTARGET))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateTexture: usage %#x: this device takes 0, RENDERTARGET (0x1), "
                        "DYNAMIC (0x200) and AUTOGENMIPMAP (0x400)", usage);
    if ((usage & IS_USAGE_RENDERTARGET) && format != IS_FMT_A8R8G8B8 && format != IS_FMT_X8R8G8B8)
        return dev_fail(dev, IS_ERR_NOTAVAILABLE, "CreateTexture: a RENDERTARGET texture of format %d: this device's "
                        "targets are A8R8G8B8 (21) and X8R8G8B8 (22)", (int)format);
    if (!format_bpp(format))
        return dev_fail(dev, IS_ERR_NOTAVAILABLE, "CreateTexture: format %d is not a texture format of this device "
                        "(A8R8G8B8 21, X8R8G8B8 22, R32F 114, A32B32G32R32F 116)", (int)format);
    unsigned full = chain_length(width, height);
    if ((usage & IS_USAGE_AUTOGENMIPMAP) && levels > 1)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateTexture: an AUTOGENMIPMAP texture takes levels 0 or 1 (%u)",
                        levels);
    if (levels > full)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateTexture: %u levels: a %ux%u texture has at most %u", levels,
                        width, height, full);
    *kept = levels == 0 || (usage & IS_USAGE_AUTOGENMIPMAP) ? full : levels;
    return IS_OK;
}

is_result dev_create_texture(is_device *dev, unsigned width, unsigned height, unsigned levels, uint32_t usage,
                             is_format format, is_texture **out)
{
    unsigned kept = 0;
    if (out) *out = NULL;
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!out) return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateTexture: NULL output pointer");
    is_result r = check_create(dev, width, height, levels, usage, format, &kept);
    if (r != IS_OK) return r;
    size_t bpp = format_bpp(format), bytes = 0;
    for (unsigned l = 0; l < kept; l++) {
        size_t w = width >> l ? width >> l : 1, h = height >> l ? height >> l : 1;
        bytes += w * h * bpp;
    }
    is_texture *t = calloc(1, sizeof *t);
    unsigned char *mem = t ? calloc(1, bytes) : NULL;
    if (!mem) {
        free(t);
        return dev_fail(dev, IS_ERR_OUTOFMEMORY, "CreateTexture: out of memory for %zu bytes (%ux%u, %u levels)", bytes,
                        width, height, kept);
    }
    *t = (is_texture){.dev = dev, .format = format, .usage = usage, .bpp = (unsigned)bpp, .levels = kept, .mem = mem};
    size_t off = 0;
    for (unsigned l = 0; l < kept; l++) {
        unsigned w = width >> l ? width >> l : 1, h = height >> l ? height >> l : 1;
        t->lv[l] = (tex_level){w, h, mem + off};
        off += (size_t)w * h * bpp;
    }
    t->next = dev->textures;
    if (dev->textures) dev->textures->prev = t;
    dev->textures = t;
    *out = t;
    return IS_OK;
}

/* Empty every sampler of dev that holds t. */
static void unbind(is_device *dev, const is_texture *t)
{
    for (int k = 0; k < IS_MAX_VS_SAMPLERS; k++)
        if (dev->consts.s[k].tex == t) dev->consts.s[k].tex = NULL;
    for (int k = 0; k < DEV_PS_SAMPLERS; k++)
        if (dev->ps_samplers[k].tex == t) dev->ps_samplers[k].tex = NULL;
    sb_forget(dev, t);   /* and from the stateblocks */
}

/* The recorded draws of t's device run first (a vertex shader may sample t; the samplers are recorded, not the
 * texels). */
static void tex_flush_readers(const is_texture *t)
{
    if (dev_live(t->dev) && t->dev->scene.n) dev_scene_flush(t->dev);
}

void tex_release(is_texture *t)
{
    if (!t) return;
    tex_flush_readers(t);
    is_device *dev = t->dev;
    surf_release_texture_levels(t);   /* its surfaces (the device's target goes back to the back buffer) */
    unbind(dev, t);
    if (t->prev) t->prev->next = t->next;
    else dev->textures = t->next;
    if (t->next) t->next->prev = t->prev;
    free(t->mem);
    free(t);
}

void dev_release_textures(is_device *dev)
{
    while (dev->textures) tex_release(dev->textures);
}

unsigned tex_get_level_count(const is_texture *t)
{
    return !t ? 0 : (t->usage & IS_USAGE_AUTOGENMIPMAP) ? 1 : t->levels;
}

is_result tex_get_level_desc(const is_texture *t, unsigned level, is_texture_desc *out)
{
    if (!t) return IS_ERR_INVALIDCALL;
    if (!out || level >= tex_get_level_count(t))
        return dev_fail(t->dev, IS_ERR_INVALIDCALL, "GetLevelDesc: level %u of a texture of %u levels (or NULL "
                        "output)", level, tex_get_level_count(t));
    *out = (is_texture_desc){t->format, t->usage, t->lv[level].w, t->lv[level].h};
    return IS_OK;
}

is_result tex_lock_rect(is_texture *t, unsigned level, is_locked_rect *out, const is_rect *r, uint32_t flags)
{
    if (!t) return IS_ERR_INVALIDCALL;
    if (!out) return dev_fail(t->dev, IS_ERR_INVALIDCALL, "LockRect: NULL output pointer");
    if (level >= tex_get_level_count(t))
        return dev_fail(t->dev, IS_ERR_INVALIDCALL, "LockRect: level %u of a texture of %u levels", level,
                        tex_get_level_count(t));
    if (t->locked & (1u << level))
        return dev_fail(t->dev, IS_ERR_INVALIDCALL, "LockRect: level %u is locked already", level);
    if (t->usage & IS_USAGE_RENDERTARGET)   /* D3DPOOL_DEFAULT, as render-target textures are: not lockable */
        return dev_fail(t->dev, IS_ERR_INVALIDCALL, "LockRect: a RENDERTARGET texture cannot be locked (read it "
                        "with GetRenderTargetData)");
    const tex_level *l = &t->lv[level];
    size_t off = 0;
    if (r) {
        if (r->left < 0 || r->top < 0 || r->left >= r->right || r->top >= r->bottom || (uint32_t)r->right > l->w ||
            (uint32_t)r->bottom > l->h)
            return dev_fail(t->dev, IS_ERR_INVALIDCALL, "LockRect: rect (%d, %d)-(%d, %d) is empty or outside level "
                            "%u's %ux%u texels", r->left, r->top, r->right, r->bottom, level, l->w, l->h);
        off = ((size_t)r->top * l->w + (size_t)r->left) * t->bpp;
    }
    tex_flush_readers(t);
    t->locked |= 1u << level;
    if (level == 0) t->lock0_readonly = (flags & IS_LOCK_READONLY) != 0;
    *out = (is_locked_rect){(int)(l->w * t->bpp), l->bits + off};
    return IS_OK;
}

/* Texel (x, y) of level l (its bytes). */
static const unsigned char *texel_at(const tex_level *l, unsigned x, unsigned y, unsigned bpp)
{
    return l->bits + ((size_t)y * l->w + x) * bpp;
}

/* One destination texel q from the four source texels p[0..3] by the box filter (bytes or floats). */
static void box_texel(const unsigned char *const p[4], unsigned char *q, unsigned bpp, bool bytes)
{
    if (bytes) {
        for (unsigned c = 0; c < bpp; c++) q[c] = (unsigned char)((p[0][c] + p[1][c] + p[2][c] + p[3][c] + 2u) / 4u);
        return;
    }
    for (unsigned c = 0; c < bpp / 4; c++) {
        float v[4], m;
        for (int k = 0; k < 4; k++) memcpy(&v[k], p[k] + 4 * c, 4);
        m = ((v[0] + v[1]) + (v[2] + v[3])) * 0.25f;
        memcpy(q + 4 * c, &m, 4);
    }
}

/* Level l + 1 of t from level l by the box filter of tex_filter_texture (texture.h). */
static void box_level(const is_texture *t, unsigned l)
{
    const tex_level *s = &t->lv[l], *d = &t->lv[l + 1];
    const bool bytes = t->format == IS_FMT_A8R8G8B8 || t->format == IS_FMT_X8R8G8B8;
    for (unsigned j = 0; j < d->h; j++)
        for (unsigned i = 0; i < d->w; i++) {
            unsigned x0 = 2 * i < s->w ? 2 * i : s->w - 1, x1 = 2 * i + 1 < s->w ? 2 * i + 1 : s->w - 1;
            unsigned y0 = 2 * j < s->h ? 2 * j : s->h - 1, y1 = 2 * j + 1 < s->h ? 2 * j + 1 : s->h - 1;
            const unsigned char *p[4] = {texel_at(s, x0, y0, t->bpp), texel_at(s, x1, y0, t->bpp),
                                         texel_at(s, x0, y1, t->bpp), texel_at(s, x1, y1, t->bpp)};
            box_texel(p, d->bits + ((size_t)j * d->w + i) * t->bpp, t->bpp, bytes);
        }
}

/* Levels 1.. of t from level 0. */
static void filter_levels(const is_texture *t)
{
    for (unsigned l = 0; l + 1 < t->levels; l++) box_level(t, l);
}

is_result tex_unlock_rect(is_texture *t, unsigned level)
{
    if (!t) return IS_ERR_INVALIDCALL;
    if (level >= IS_MAX_TEXTURE_LEVELS || !(t->locked & (1u << level)))
        return dev_fail(t->dev, IS_ERR_INVALIDCALL, "UnlockRect: level %u is not locked", level);
    t->locked &= ~(1u << level);
    if (level == 0 && (t->usage & IS_USAGE_AUTOGENMIPMAP) && !t->lock0_readonly) filter_levels(t);
    return IS_OK;
}

void tex_generate_mip_sub_levels(is_texture *t)
{
    if (!t || !(t->usage & IS_USAGE_AUTOGENMIPMAP) || (t->locked & 1u)) return;
    tex_flush_readers(t);
    filter_levels(t);
}

is_result tex_filter_texture(is_texture *t)
{
    if (!t) return IS_ERR_INVALIDCALL;
    if (t->locked) return dev_fail(t->dev, IS_ERR_INVALIDCALL, "D3DXFilterTexture: a level is locked (mask %#x)",
                                   t->locked);
    tex_flush_readers(t);
    filter_levels(t);
    return IS_OK;
}

/* ---------------------------------------- samplers ---------------------------------------- */

is_sampler tex_sampler_default(const is_texture *tex)
{
    is_sampler s;
    memset(&s, 0, sizeof s);
    s.tex = tex;
    s.state[IS_SAMP_ADDRESSU] = s.state[IS_SAMP_ADDRESSV] = s.state[IS_SAMP_ADDRESSW] = IS_TADDRESS_WRAP;
    s.state[IS_SAMP_MAGFILTER] = s.state[IS_SAMP_MINFILTER] = IS_TEXF_POINT;
    s.state[IS_SAMP_MIPFILTER] = IS_TEXF_NONE;
    s.state[IS_SAMP_MAXANISOTROPY] = 1;
    return s;  /* BORDERCOLOR 0, MIPMAPLODBIAS 0.0f (bits 0), MAXMIPLEVEL 0, the others 0 */
}

void dev_samplers_default(is_device *dev)
{
    for (int k = 0; k < IS_MAX_VS_SAMPLERS; k++) dev->consts.s[k] = tex_sampler_default(NULL);
    for (int k = 0; k < DEV_PS_SAMPLERS; k++) dev->ps_samplers[k] = tex_sampler_default(NULL);
}

/* The sampler of D3D9's index `sampler` on dev, or NULL for an index D3D9 does not have. */
static is_sampler *sampler_slot(const is_device *dev, unsigned sampler)
{
    is_device *d = (is_device *)dev; /* the getters pass a const device and only read */
    if (sampler < IS_MAX_PS_SAMPLERS) return &d->ps_samplers[sampler];
    if (sampler == IS_DMAPSAMPLER) return &d->ps_samplers[IS_MAX_PS_SAMPLERS];
    if (sampler >= IS_VERTEXTEXTURESAMPLER0 && sampler - IS_VERTEXTEXTURESAMPLER0 < IS_MAX_VS_SAMPLERS)
        return &d->consts.s[sampler - IS_VERTEXTEXTURESAMPLER0];
    return NULL;
}

/* Whether t is one of dev's live textures (compared as pointers: a released one is never read). */
static bool owns(const is_device *dev, const is_texture *t)
{
    for (const is_texture *k = dev->textures; k; k = k->next)
        if (k == t) return true;
    return false;
}

is_result dev_set_texture(is_device *dev, unsigned sampler, is_texture *tex)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    is_sampler *s = sampler_slot(dev, sampler);
    if (!s) return IS_OK; /* as the runtime: an index D3D9 does not have is ignored */
    if (tex && !owns(dev, tex))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetTexture: sampler %u: the texture is not a live texture of this "
                        "device (created by another device, or released)", sampler);
    if (dev->recording) {
        unsigned k = dev_sampler_number(dev, s);
        dev->recording->samplers[k].tex = tex, dev->recording->has_tex |= 1u << k;
        return IS_OK;
    }
    s->tex = tex;
    return IS_OK;
}

is_result dev_get_texture(const is_device *dev, unsigned sampler, is_texture **out)
{
    if (!dev_live(dev) || !out) return IS_ERR_INVALIDCALL;
    const is_sampler *s = sampler_slot(dev, sampler);
    *out = s ? (is_texture *)s->tex : NULL;
    return IS_OK;
}

is_result dev_set_sampler_state(is_device *dev, unsigned sampler, is_samp type, uint32_t value)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if ((unsigned)type < IS_SAMP_ADDRESSU || (unsigned)type >= IS_SAMP_COUNT)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "SetSamplerState: sampler %u: unknown state %d (D3DSAMP_ADDRESSU 1 .. "
                        "D3DSAMP_DMAPOFFSET 13)", sampler, (int)type);
    is_sampler *s = sampler_slot(dev, sampler);
    if (s && dev->recording) {
        unsigned k = dev_sampler_number(dev, s);
        dev->recording->samplers[k].state[type] = value, dev->recording->has_samp[k] |= 1u << type;
    } else if (s) {
        s->state[type] = value; /* any value, as the runtime stores it */
    }
    return IS_OK;
}

is_result dev_get_sampler_state(const is_device *dev, unsigned sampler, is_samp type, uint32_t *value)
{
    if (!dev_live(dev) || !value || (unsigned)type < IS_SAMP_ADDRESSU || (unsigned)type >= IS_SAMP_COUNT) return IS_ERR_INVALIDCALL;
    const is_sampler *s = sampler_slot(dev, sampler);
    *value = s ? s->state[type] : 0;
    return IS_OK;
}
