/* core/raster_states.c -- the device's side of D3D9's scissor test, colour write mask, alpha test, stencil
 * buffer, user clip planes, CLIPPING and pre-transformed vertices (core/device.h, "per-pixel and clipping
 * states"): their render states' values and defaults, SetScissorRect, SetClipPlane, Clear's stencil, the
 * rasterizer's copy of the states (raster/pixel.c does the work) and the pass-through shader of POSITIONT draws. */
#include "device_internal.h"

#include <string.h>

/* Is v a D3DCMPFUNC, a D3DSTENCILOP, a BOOL (as the device's other BOOL states: 0 or 1)? */
static bool is_cmp(uint32_t v) { return v >= IS_CMP_NEVER && v <= IS_CMP_ALWAYS; }
static bool is_sop(uint32_t v) { return v >= IS_STENCILOP_KEEP && v <= IS_STENCILOP_DECR; }

int raster_state_check(is_rs state, uint32_t v)
{
    switch (state) {
    case IS_RS_ALPHATESTENABLE: case IS_RS_STENCILENABLE: case IS_RS_CLIPPING: case IS_RS_SCISSORTESTENABLE:
    case IS_RS_TWOSIDEDSTENCILMODE:
        return v <= 1;
    case IS_RS_ALPHAFUNC: case IS_RS_STENCILFUNC: case IS_RS_CCW_STENCILFUNC: return is_cmp(v);
    case IS_RS_STENCILFAIL: case IS_RS_STENCILZFAIL: case IS_RS_STENCILPASS: case IS_RS_CCW_STENCILFAIL:
    case IS_RS_CCW_STENCILZFAIL: case IS_RS_CCW_STENCILPASS:
        return is_sop(v);
    /* any DWORD, as the runtime stores them: ALPHAREF and STENCILREF use their low 8 bits, the masks their low 8,
     * CLIPPLANEENABLE its low 6, COLORWRITEENABLE its low 4 */
    case IS_RS_ALPHAREF: case IS_RS_STENCILREF: case IS_RS_STENCILMASK: case IS_RS_STENCILWRITEMASK:
    case IS_RS_CLIPPLANEENABLE: case IS_RS_COLORWRITEENABLE:
        return 1;
    default: return -1;
    }
}

void raster_states_default(is_device *dev)
{
    uint32_t *s = dev->rs_state;
    s[IS_RS_ALPHATESTENABLE] = 0, s[IS_RS_ALPHAREF] = 0, s[IS_RS_ALPHAFUNC] = IS_CMP_ALWAYS;
    s[IS_RS_STENCILENABLE] = 0, s[IS_RS_STENCILFUNC] = IS_CMP_ALWAYS, s[IS_RS_STENCILREF] = 0;
    s[IS_RS_STENCILFAIL] = s[IS_RS_STENCILZFAIL] = s[IS_RS_STENCILPASS] = IS_STENCILOP_KEEP;
    s[IS_RS_STENCILMASK] = s[IS_RS_STENCILWRITEMASK] = 0xFFFFFFFFu;
    s[IS_RS_TWOSIDEDSTENCILMODE] = 0, s[IS_RS_CCW_STENCILFUNC] = IS_CMP_ALWAYS;
    s[IS_RS_CCW_STENCILFAIL] = s[IS_RS_CCW_STENCILZFAIL] = s[IS_RS_CCW_STENCILPASS] = IS_STENCILOP_KEEP;
    s[IS_RS_CLIPPING] = 1, s[IS_RS_CLIPPLANEENABLE] = 0;
    s[IS_RS_COLORWRITEENABLE] = 0xFu, s[IS_RS_SCISSORTESTENABLE] = 0;
    dev->scissor = (is_rect){0, 0, dev->rt.width, dev->rt.height};
    memset(dev->clip_plane, 0, sizeof dev->clip_plane);
}

/* The stencil states of one face: the clockwise ones (ccw false) or the CCW_ ones. */
static rs_stencil_ops face_ops(const uint32_t *s, bool ccw)
{
    if (ccw)
        return (rs_stencil_ops){(int)s[IS_RS_CCW_STENCILFUNC], (int)s[IS_RS_CCW_STENCILFAIL],
                                (int)s[IS_RS_CCW_STENCILZFAIL], (int)s[IS_RS_CCW_STENCILPASS]};
    return (rs_stencil_ops){(int)s[IS_RS_STENCILFUNC], (int)s[IS_RS_STENCILFAIL], (int)s[IS_RS_STENCILZFAIL],
                            (int)s[IS_RS_STENCILPASS]};
}

/* The attribute slots a POSITIONT declaration gives (COLOR0/1, TEXCOORD0..7): what the pass-through writes. */
static uint32_t pretransformed_slots(const is_vertex_declaration *d)
{
    uint32_t m = 0;
    for (unsigned k = 0; k < d->n; k++) {
        const is_vertex_element *e = &d->el[k].e;
        if (e->usage == IS_DECLUSAGE_COLOR && e->usage_index < 2) m |= 1u << (RS_ATTR_COLOR0 + e->usage_index);
        if (e->usage == IS_DECLUSAGE_TEXCOORD && e->usage_index < 8) m |= 1u << (RS_ATTR_TEXCOORD0 + e->usage_index);
    }
    return m;
}

/* The pass-through "shader" of pre-transformed vertices: POSITIONT (in the position register) to oPos as
 * (x, y, z, rhw), which the rasterizer reads as screen coordinates (rs_state.pretransformed); colours and texture
 * coordinates unchanged. */
static void pretransformed_main(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out)
{
    (void)c;
    out->pos = (rs_vec4){in->position[0].x, in->position[0].y, in->position[0].z, in->position[0].w};
    for (int k = 0; k < 2; k++)
        out->attr[RS_ATTR_COLOR0 + k] = (rs_vec4){in->color[k].x, in->color[k].y, in->color[k].z, in->color[k].w};
    for (int k = 0; k < 8; k++)
        out->attr[RS_ATTR_TEXCOORD0 + k] =
            (rs_vec4){in->texcoord[k].x, in->texcoord[k].y, in->texcoord[k].z, in->texcoord[k].w};
}

static const is_vertex_shader pretransformed_vs = {
    "pre-transformed (POSITIONT)", pretransformed_main, 0x3ffu, NULL, NULL, NULL, NULL, NULL,
};

void raster_states_apply(const is_device *dev, rs_state *st)
{
    const uint32_t *s = dev->rs_state;
    st->scissor_enable = s[IS_RS_SCISSORTESTENABLE] != 0;
    st->scissor = (rs_rect){dev->scissor.left, dev->scissor.top, dev->scissor.right, dev->scissor.bottom};
    st->color_write_disable = ~s[IS_RS_COLORWRITEENABLE] & 0xFu;
    st->alpha_test = s[IS_RS_ALPHATESTENABLE] != 0;
    st->alpha_func = (int)s[IS_RS_ALPHAFUNC];
    st->alpha_ref = s[IS_RS_ALPHAREF] & 0xFFu;
    st->stencil_enable = s[IS_RS_STENCILENABLE] != 0;
    st->stencil_two_sided = s[IS_RS_TWOSIDEDSTENCILMODE] != 0;
    st->stencil_cw = face_ops(s, false);
    st->stencil_ccw = face_ops(s, true);
    st->stencil_ref = s[IS_RS_STENCILREF] & 0xFFu;
    st->stencil_mask = s[IS_RS_STENCILMASK] & 0xFFu;
    st->stencil_write_mask = s[IS_RS_STENCILWRITEMASK] & 0xFFu;
    st->no_clipping = s[IS_RS_CLIPPING] == 0;
    st->clip_plane_enable = s[IS_RS_CLIPPLANEENABLE] & 0x3Fu;
    memcpy(st->clip_plane, dev->clip_plane, sizeof st->clip_plane);
    st->pretransformed = dev->vs == &pretransformed_vs;
    if (st->pretransformed) st->attr_mask = pretransformed_slots(dev->decl);
}

bool raster_pretransformed_begin(is_device *dev, const is_vertex_shader **saved)
{
    if (dev->vs || !dev->decl || !dev->decl->positiont) return false;
    *saved = dev->vs;
    dev->vs = &pretransformed_vs;
    return true;
}

void raster_pretransformed_end(is_device *dev, const is_vertex_shader *saved) { dev->vs = saved; }

is_rect raster_scissor_clip(const is_device *dev, is_rect r)
{
    if (!dev->rs_state[IS_RS_SCISSORTESTENABLE]) return r;
    const is_rect *s = &dev->scissor;
    return (is_rect){r.left > s->left ? r.left : s->left, r.top > s->top ? r.top : s->top,
                     r.right < s->right ? r.right : s->right, r.bottom < s->bottom ? r.bottom : s->bottom};
}

is_result dev_set_scissor_rect(is_device *dev, const is_rect *rect)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!rect) return dev_fail(dev, IS_ERR_INVALIDCALL, "SetScissorRect: NULL rectangle");
    if (dev->recording) dev->recording->scissor = *rect, dev->recording->has_scissor = true;   /* a stateblock's */
    else dev->scissor = *rect;
    return IS_OK;
}

is_result dev_get_scissor_rect(const is_device *dev, is_rect *rect)
{
    if (!dev_live(dev) || !rect) return IS_ERR_INVALIDCALL;
    *rect = dev->scissor;
    return IS_OK;
}

is_result dev_set_clip_plane(is_device *dev, unsigned index, const float plane[4])
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!plane) return dev_fail(dev, IS_ERR_INVALIDCALL, "SetClipPlane: NULL plane");
    for (int c = 0; c < 4; c++)
        if (!isfinite(plane[c]))
            return dev_fail(dev, IS_ERR_INVALIDCALL, "SetClipPlane: plane %u is not finite", index);
    index = index < IS_MAX_USER_CLIP_PLANES ? index : IS_MAX_USER_CLIP_PLANES - 1;   /* the runtime's clamp */
    if (dev->recording) {   /* into the stateblock recorded */
        memcpy(dev->recording->clip_plane[index], plane, sizeof dev->clip_plane[index]);
        dev->recording->has_clip_plane |= 1u << index;
    } else {
        memcpy(dev->clip_plane[index], plane, sizeof dev->clip_plane[index]);
    }
    return IS_OK;
}

is_result dev_get_clip_plane(const is_device *dev, unsigned index, float plane[4])
{
    if (!dev_live(dev) || !plane) return IS_ERR_INVALIDCALL;
    index = index < IS_MAX_USER_CLIP_PLANES ? index : IS_MAX_USER_CLIP_PLANES - 1;
    memcpy(plane, dev->clip_plane[index], sizeof dev->clip_plane[index]);
    return IS_OK;
}
