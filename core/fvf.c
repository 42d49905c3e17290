/* core/fvf.c -- SetFVF / GetFVF: a flexible vertex format turned into the vertex declaration D3D9's runtime
 * builds for it (DXVK's D3D9 FVF conversion, the D3DFVF documentation's order): position (XYZ: float3 POSITION0,
 * XYZRHW: float4 POSITIONT), NORMAL float3, PSIZE float1, DIFFUSE D3DCOLOR COLOR0, SPECULAR D3DCOLOR COLOR1, then
 * TEXCOUNT texture coordinate sets TEXCOORD0.. with the sizes of D3DFVF_TEXCOORDSIZEn (2 floats by default), packed
 * in that order in one stream (stream 0).  The device owns the declaration it makes (released with it, or when
 * another FVF replaces it); SetVertexDeclaration makes GetFVF 0.  Refused (IS_ERR_INVALIDCALL, nothing changed):
 * FVFs with blend weights (XYZB1..5, XYZW), no position, more than 8 texture sets, or unknown bits. */
#include "device_internal.h"

enum {
    FVF_POSITION_MASK = 0x400e, FVF_XYZ = 0x002, FVF_XYZRHW = 0x004, FVF_NORMAL = 0x010, FVF_PSIZE = 0x020,
    FVF_DIFFUSE = 0x040, FVF_SPECULAR = 0x080, FVF_TEXCOUNT_MASK = 0xf00, FVF_TEXCOUNT_SHIFT = 8
};
#define FVF_KNOWN (FVF_POSITION_MASK | FVF_NORMAL | FVF_PSIZE | FVF_DIFFUSE | FVF_SPECULAR | FVF_TEXCOUNT_MASK | \
                   0xffff0000u)

/* The declaration elements of fvf into el (ended by IS_DECL_END); the element count, or -1 with why. */
static int fvf_elements(uint32_t fvf, is_vertex_element el[16], const char **why)
{
    int n = 0;
    uint16_t off = 0;
    uint32_t pos = fvf & FVF_POSITION_MASK;
    if (fvf & ~FVF_KNOWN) return *why = "unknown bits", -1;
    if (pos != FVF_XYZ && pos != FVF_XYZRHW) return *why = "only XYZ or XYZRHW positions (no blend weights)", -1;
    unsigned tex = (fvf & FVF_TEXCOUNT_MASK) >> FVF_TEXCOUNT_SHIFT;
    if (tex > 8) return *why = "more than 8 texture coordinate sets", -1;
    bool rhw = pos == FVF_XYZRHW;
    el[n++] = (is_vertex_element){0, off, rhw ? IS_DECLTYPE_FLOAT4 : IS_DECLTYPE_FLOAT3, 0,
                                  rhw ? IS_DECLUSAGE_POSITIONT : IS_DECLUSAGE_POSITION, 0};
    off += rhw ? 16 : 12;
    if (fvf & FVF_NORMAL) el[n++] = (is_vertex_element){0, off, IS_DECLTYPE_FLOAT3, 0, IS_DECLUSAGE_NORMAL, 0}, off += 12;
    if (fvf & FVF_PSIZE) el[n++] = (is_vertex_element){0, off, IS_DECLTYPE_FLOAT1, 0, IS_DECLUSAGE_PSIZE, 0}, off += 4;
    if (fvf & FVF_DIFFUSE) el[n++] = (is_vertex_element){0, off, IS_DECLTYPE_D3DCOLOR, 0, IS_DECLUSAGE_COLOR, 0}, off += 4;
    if (fvf & FVF_SPECULAR) el[n++] = (is_vertex_element){0, off, IS_DECLTYPE_D3DCOLOR, 0, IS_DECLUSAGE_COLOR, 1}, off += 4;
    static const uint8_t type_of[4] = {IS_DECLTYPE_FLOAT2, IS_DECLTYPE_FLOAT3, IS_DECLTYPE_FLOAT4, IS_DECLTYPE_FLOAT1};
    static const uint8_t bytes_of[4] = {8, 12, 16, 4};
    for (unsigned k = 0; k < tex; k++) {   /* D3DFVF_TEXCOORDSIZEn: 2 bits per set from bit 16 (0: 2 floats) */
        unsigned code = (fvf >> (16 + 2 * k)) & 3u;
        el[n++] = (is_vertex_element){0, off, type_of[code], 0, IS_DECLUSAGE_TEXCOORD, (uint8_t)k};
        off += bytes_of[code];
    }
    el[n] = (is_vertex_element)IS_DECL_END;
    return n;
}

is_result dev_set_fvf(is_device *dev, uint32_t fvf)
{
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    is_vertex_element el[16];
    const char *why = "";
    if (fvf_elements(fvf, el, &why) < 0) return dev_fail(dev, IS_ERR_INVALIDCALL, "SetFVF: 0x%x: %s", fvf, why);
    is_vertex_declaration *decl = NULL;
    is_result r = IS_OK;
    if (fvf == dev->fvf && dev->fvf_decl) decl = dev->fvf_decl;
    else if ((r = dev_create_vertex_declaration(dev, el, &decl)) != IS_OK) return r;
    r = dev_set_vertex_declaration(dev, decl);   /* a stateblock being recorded takes it */
    if (r != IS_OK) return r;
    if (decl != dev->fvf_decl) {
        is_vertex_declaration *old = dev->fvf_decl;
        dev->fvf_decl = decl;
        if (old) decl_release(old);   /* a stateblock that held it drops it (resources.c) */
    }
    dev->fvf = fvf;   /* after dev_set_vertex_declaration, which sets it to 0 */
    return IS_OK;
}

is_result dev_get_fvf(const is_device *dev, uint32_t *fvf)
{
    if (!dev_live(dev) || !fvf) return IS_ERR_INVALIDCALL;
    *fvf = dev->fvf;
    return IS_OK;
}
