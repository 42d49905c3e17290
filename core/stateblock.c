/* core/stateblock.c -- stateblocks as IDirect3DStateBlock9: BeginStateBlock / EndStateBlock (record what is set),
 * CreateStateBlock with D3D9's ALL, PIXELSTATE and VERTEXSTATE lists, Capture and Apply.
 *
 * The rules, as Wine's d3d9 stateblock tests and DXVK's D3D9StateBlock record the runtime: while a block is recorded
 * the setters write into it, not into the device (the getters read the device); Begin while recording, End while
 * not, CreateStateBlock, Capture and Apply while recording are refused; Capture refreshes only what the block holds,
 * from the device; Apply sets the device to it.  The lists of which render states are pixel and which vertex
 * states are D3D9's (by number: the states this device implements are picked from them); the pixel shader and its
 * constants are PIXELSTATE's, the scissor rectangle and the clip planes ALL's alone (DXVK's D3D9StateBlock). */
#include "device_internal.h"

#include <stdlib.h>
#include <string.h>

/* D3D9's pixel render states (D3DRS_*: ZENABLE, FILLMODE, SHADEMODE, ZWRITEENABLE, ALPHATESTENABLE, LASTPIXEL,
 * SRCBLEND, DESTBLEND, ZFUNC, ALPHAREF, ALPHAFUNC, DITHERENABLE, FOGSTART, FOGEND, FOGDENSITY, ALPHABLENDENABLE,
 * STENCILENABLE .. STENCILWRITEMASK, TEXTUREFACTOR, WRAP0..7, COLORWRITEENABLE, BLENDOP, SCISSORTESTENABLE,
 * SLOPESCALEDEPTHBIAS, ANTIALIASEDLINEENABLE, TWOSIDEDSTENCILMODE, CCW_STENCILFAIL .. CCW_STENCILFUNC,
 * COLORWRITEENABLE1..3, BLENDFACTOR, SRGBWRITEENABLE, DEPTHBIAS, WRAP8..15, SEPARATEALPHABLENDENABLE,
 * SRCBLENDALPHA, DESTBLENDALPHA, BLENDOPALPHA), as numbers. */
static const uint8_t pixel_states[] = {
    7, 8, 9, 14, 15, 16, 19, 20, 23, 24, 25, 26, 36, 37, 38, 27, 52, 53, 54, 55, 56, 57, 58, 59, 60,
    128, 129, 130, 131, 132, 133, 134, 135, 168, 171, 174, 175, 176, 185, 186, 187, 188, 189, 190, 191, 192,
    193, 194, 195, 198, 199, 200, 201, 202, 203, 204, 205, 206, 207, 208, 209};
/* D3D9's vertex render states (CULLMODE, FOGENABLE, SPECULARENABLE, FOGCOLOR, FOGTABLEMODE, FOGSTART, FOGEND,
 * FOGDENSITY, RANGEFOGENABLE, CLIPPING, LIGHTING, AMBIENT, FOGVERTEXMODE, COLORVERTEX, LOCALVIEWER,
 * NORMALIZENORMALS, the four MATERIALSOURCEs, VERTEXBLEND, CLIPPLANEENABLE, POINTSIZE, POINTSIZE_MIN,
 * POINTSPRITEENABLE, POINTSCALEENABLE, POINTSCALE_A..C, MULTISAMPLEANTIALIAS, MULTISAMPLEMASK, PATCHEDGESTYLE,
 * POINTSIZE_MAX, INDEXEDVERTEXBLENDENABLE, TWEENFACTOR, POSITIONDEGREE, NORMALDEGREE, MIN/MAXTESSELLATIONLEVEL,
 * ADAPTIVETESS_X..W, ENABLEADAPTIVETESSELLATION, SHADEMODE), as numbers. */
static const uint8_t vertex_states[] = {
    22, 28, 29, 34, 35, 36, 37, 38, 48, 136, 137, 139, 140, 141, 142, 143, 145, 146, 147, 148, 151, 152, 154,
    155, 156, 157, 158, 159, 160, 161, 162, 163, 166, 167, 170, 172, 173, 178, 179, 180, 181, 182, 183, 184, 9};

/* The sampler states of PIXELSTATE (ADDRESSU .. ELEMENTINDEX, on the pixel samplers and D3DDMAPSAMPLER) and of VERTEXSTATE
 * (DMAPOFFSET, on the vertex samplers), as DXVK's D3D9StateBlock lists them. */
#define PIXEL_SAMP_BITS (((1u << (IS_SAMP_ELEMENTINDEX + 1)) - 1u) & ~1u)
#define VERTEX_SAMP_BITS (1u << IS_SAMP_DMAPOFFSET)

/* Sampler k (stateblock numbering) of dev in, its struct out. */
is_sampler *dev_sampler_at(is_device *dev, unsigned k)
{
    return k < DEV_PS_SAMPLERS ? &dev->ps_samplers[k] : &dev->consts.s[k - DEV_PS_SAMPLERS];
}

/* One of dev's samplers in, its stateblock number out. */
unsigned dev_sampler_number(const is_device *dev, const is_sampler *s)
{
    if (s >= dev->ps_samplers && s < dev->ps_samplers + DEV_PS_SAMPLERS) return (unsigned)(s - dev->ps_samplers);
    return DEV_PS_SAMPLERS + (unsigned)(s - dev->consts.s);
}

/* Whether render state r is one this device implements (GetRenderState answers for it). */
static bool implemented(const is_device *dev, unsigned r)
{
    uint32_t v;
    return dev_get_render_state(dev, (is_rs)r, &v) == IS_OK;
}

/* Mark in sb the states of D3D9's list for `type` (ALL is both lists and the rest of the device's state). */
static void mark_type(const is_device *dev, is_state_block *sb, is_state_block_type type)
{
    if (type == IS_SBT_ALL || type == IS_SBT_PIXELSTATE) {
        for (size_t k = 0; k < sizeof pixel_states; k++) sb->has_rs[pixel_states[k]] = implemented(dev, pixel_states[k]);
        for (unsigned k = 0; k < DEV_PS_SAMPLERS; k++) sb->has_samp[k] |= PIXEL_SAMP_BITS;   /* DMAP too */
        sb->has_ps = true;   /* the pixel shader and its constants (core/pixel.h), as DXVK's PIXELSTATE */
        for (unsigned k = 0; k < IS_MAX_PS_CONSTANTS; k++) sb->has_pc[k] = true;
    }
    if (type == IS_SBT_ALL || type == IS_SBT_VERTEXSTATE) {
        for (size_t k = 0; k < sizeof vertex_states; k++)
            sb->has_rs[vertex_states[k]] = implemented(dev, vertex_states[k]);
        for (unsigned k = DEV_PS_SAMPLERS; k < DEV_ALL_SAMPLERS; k++) sb->has_samp[k] |= VERTEX_SAMP_BITS;
        sb->has_vs = sb->has_decl = true;
        for (unsigned k = 0; k < IS_MAX_VS_CONSTANTS; k++) sb->has_c[k] = true;
        sb->has_freq = (1u << IS_MAX_STREAMS) - 1u;
    }
    if (type == IS_SBT_ALL) {
        sb->has_tex = (1u << DEV_ALL_SAMPLERS) - 1u;
        sb->has_source = (1u << IS_MAX_STREAMS) - 1u;
        sb->has_ib = sb->has_viewport = sb->has_scissor = true;
        sb->has_clip_plane = (1u << IS_MAX_USER_CLIP_PLANES) - 1u;
    }
}

/* Copy what sb holds from the device into sb (Capture). */
static void capture(const is_device *dev, is_state_block *sb)
{
    for (unsigned r = 0; r < IS_RS_COUNT; r++)
        if (sb->has_rs[r]) sb->rs[r] = dev->rs_state[r];
    for (unsigned k = 0; k < IS_MAX_VS_CONSTANTS; k++)
        if (sb->has_c[k]) sb->c[k] = dev->consts.c[k];
    for (unsigned k = 0; k < IS_MAX_PS_CONSTANTS; k++)
        if (sb->has_pc[k]) sb->pc[k] = dev->ps_consts.c[k];
    if (sb->has_ps) sb->ps = dev->ps;
    for (unsigned k = 0; k < DEV_ALL_SAMPLERS; k++) {
        const is_sampler *s = dev_sampler_at((is_device *)dev, k);
        for (unsigned t = 0; t < IS_SAMP_COUNT; t++)
            if (sb->has_samp[k] & (1u << t)) sb->samplers[k].state[t] = s->state[t];
        if (sb->has_tex & (1u << k)) sb->samplers[k].tex = s->tex;
    }
    for (unsigned s = 0; s < IS_MAX_STREAMS; s++) {
        if (sb->has_source & (1u << s)) {
            sb->streams[s].vb = dev->streams[s].vb;
            sb->streams[s].offset = dev->streams[s].offset, sb->streams[s].stride = dev->streams[s].stride;
        }
        if (sb->has_freq & (1u << s)) sb->streams[s].freq = dev->streams[s].freq;
    }
    if (sb->has_viewport) sb->viewport = dev->viewport;
    if (sb->has_scissor) sb->scissor = dev->scissor;
    for (unsigned k = 0; k < IS_MAX_USER_CLIP_PLANES; k++)
        if (sb->has_clip_plane & (1u << k)) memcpy(sb->clip_plane[k], dev->clip_plane[k], sizeof sb->clip_plane[k]);
    if (sb->has_ib) sb->ib = dev->ib;
    if (sb->has_decl) sb->decl = dev->decl;
    if (sb->has_vs) sb->vs = dev->vs;
}

/* Set the device to what sb holds (Apply). */
static void apply(is_device *dev, const is_state_block *sb)
{
    for (unsigned r = 0; r < IS_RS_COUNT; r++)
        if (sb->has_rs[r]) dev->rs_state[r] = sb->rs[r];
    for (unsigned k = 0; k < IS_MAX_VS_CONSTANTS; k++)
        if (sb->has_c[k]) dev->consts.c[k] = sb->c[k];
    for (unsigned k = 0; k < IS_MAX_PS_CONSTANTS; k++)
        if (sb->has_pc[k]) dev->ps_consts.c[k] = sb->pc[k];
    if (sb->has_ps) dev->ps = sb->ps;
    for (unsigned k = 0; k < DEV_ALL_SAMPLERS; k++) {
        is_sampler *s = dev_sampler_at(dev, k);
        for (unsigned t = 0; t < IS_SAMP_COUNT; t++)
            if (sb->has_samp[k] & (1u << t)) s->state[t] = sb->samplers[k].state[t];
        if (sb->has_tex & (1u << k)) s->tex = sb->samplers[k].tex;
    }
    for (unsigned s = 0; s < IS_MAX_STREAMS; s++) {
        if (sb->has_source & (1u << s)) {
            dev->streams[s].vb = sb->streams[s].vb;
            dev->streams[s].offset = sb->streams[s].offset, dev->streams[s].stride = sb->streams[s].stride;
        }
        if (sb->has_freq & (1u << s)) dev->streams[s].freq = sb->streams[s].freq;
    }
    if (sb->has_viewport) {
        dev->viewport = sb->viewport;
        dev_viewport_update(dev);
    }
    if (sb->has_ib) dev->ib = sb->ib;
    if (sb->has_decl) dev->decl = sb->decl;
    if (sb->has_vs) dev->vs = sb->vs;
    if (sb->has_scissor) dev->scissor = sb->scissor;
    for (unsigned k = 0; k < IS_MAX_USER_CLIP_PLANES; k++)
        if (sb->has_clip_plane & (1u << k)) memcpy(dev->clip_plane[k], sb->clip_plane[k], sizeof dev->clip_plane[k]);
}

/* A new, empty stateblock, or NULL when out of memory. */
static is_state_block *sb_new(void)
{
    return calloc(1, sizeof(is_state_block));
}

/* BeginStateBlock: a new, empty block that the setters fill from now on. */
is_result dev_begin_state_block(is_device *dev)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (dev->recording) return dev_fail(dev, IS_ERR_INVALIDCALL, "BeginStateBlock: a stateblock is already recorded");
    if (!(dev->recording = sb_new())) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "BeginStateBlock: out of memory");
    return IS_OK;
}

/* EndStateBlock: the recorded block out, registered with its device; the setters write the device again. */
is_result dev_end_state_block(is_device *dev, is_state_block **out)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!out) return dev_fail(dev, IS_ERR_INVALIDCALL, "EndStateBlock: NULL output pointer");
    if (!dev->recording) return dev_fail(dev, IS_ERR_INVALIDCALL, "EndStateBlock: no stateblock is recorded");
    dev_res_add(dev, &dev->recording->res, DEV_RES_SB);
    *out = dev->recording;
    dev->recording = NULL;
    return IS_OK;
}

/* CreateStateBlock: a block holding D3D9's list for type, captured from the device now. */
is_result dev_create_state_block(is_device *dev, is_state_block_type type, is_state_block **out)
{
    if (out) *out = NULL;
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!out) return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateStateBlock: NULL output pointer");
    if (dev->recording) return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateStateBlock: a stateblock is being recorded");
    if (type != IS_SBT_ALL && type != IS_SBT_PIXELSTATE && type != IS_SBT_VERTEXSTATE)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateStateBlock: type %d is not ALL (1), PIXELSTATE (2) or "
                        "VERTEXSTATE (3)", (int)type);
    is_state_block *sb = sb_new();
    if (!sb) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "CreateStateBlock: out of memory");
    mark_type(dev, sb, type);
    capture(dev, sb);
    dev_res_add(dev, &sb->res, DEV_RES_SB);
    *out = sb;
    return IS_OK;
}

/* The device of a stateblock that may be used (its device alive and recording nothing), or NULL with the error
 * left in the device when it is recording. */
static is_device *sb_device(is_state_block *sb, const char *call)
{
    if (!sb || !dev_live(sb->res.dev)) return NULL;
    if (sb->res.dev->recording) {
        dev_fail(sb->res.dev, IS_ERR_INVALIDCALL, "%s: a stateblock is being recorded", call);
        return NULL;
    }
    return sb->res.dev;
}

/* Capture: what sb holds, refreshed from its device. */
is_result sb_capture(is_state_block *sb)
{
    is_device *dev = sb_device(sb, "Capture");
    if (!dev) return IS_ERR_INVALIDCALL;
    capture(dev, sb);
    return IS_OK;
}

/* Apply: its device set to what sb holds. */
is_result sb_apply(is_state_block *sb)
{
    is_device *dev = sb_device(sb, "Apply");
    if (!dev) return IS_ERR_INVALIDCALL;
    apply(dev, sb);
    return IS_OK;
}

/* Release: sb unregistered and freed (after dev_destroy too). */
void sb_release(is_state_block *sb)
{
    if (!sb) return;
    dev_res_remove(&sb->res);   /* may free a destroyed device */
    free(sb);
}

/* Clear p from one stateblock's pointers. */
static void forget_in(is_state_block *sb, const void *p)
{
    for (unsigned s = 0; s < IS_MAX_STREAMS; s++)
        if ((const void *)sb->streams[s].vb == p) sb->streams[s].vb = NULL;
    if ((const void *)sb->ib == p) sb->ib = NULL;
    if ((const void *)sb->decl == p) sb->decl = NULL;
    for (unsigned k = 0; k < DEV_ALL_SAMPLERS; k++)
        if ((const void *)sb->samplers[k].tex == p) sb->samplers[k].tex = NULL;
}

/* A released resource p dropped from every block of dev (device_internal.h). */
void sb_forget(is_device *dev, const void *p)
{
    if (dev->recording) forget_in(dev->recording, p);
    for (dev_res *r = dev->resources; r; r = r->next)
        if (r->kind == DEV_RES_SB) forget_in((is_state_block *)r, p);
}

/* The block being recorded freed, recording over. */
void sb_abort_recording(is_device *dev)
{
    free(dev->recording);
    dev->recording = NULL;
}
