/* core/resources.c -- vertex buffers, index buffers and vertex declarations (CreateVertexBuffer & co.). */
#include "device_internal.h"

#include "hlsl.h"
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* CreateVertexBuffer: zeroed memory of `bytes` bytes. */
is_result dev_create_vertex_buffer(is_device *dev, size_t bytes, is_vertex_buffer **out)
{
    if (out) *out = NULL;
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!out) return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexBuffer: NULL output pointer");
    if (bytes == 0) return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexBuffer: size 0");
    is_vertex_buffer *vb = calloc(1, sizeof *vb);
    unsigned char *data = vb ? calloc(1, bytes) : NULL;
    if (!data) {
        free(vb);
        return dev_fail(dev, IS_ERR_OUTOFMEMORY, "CreateVertexBuffer: out of memory for %zu bytes", bytes);
    }
    *vb = (is_vertex_buffer){.data = data, .size = bytes};
    dev_res_add(dev, &vb->res, DEV_RES_VB);
    *out = vb;
    return IS_OK;
}

/* CreateIndexBuffer: 16- or 32-bit indices. */
is_result dev_create_index_buffer(is_device *dev, size_t bytes, is_format fmt, is_index_buffer **out)
{
    if (out) *out = NULL;
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!out) return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateIndexBuffer: NULL output pointer");
    if (fmt != IS_FMT_INDEX16 && fmt != IS_FMT_INDEX32)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateIndexBuffer: format %d is not INDEX16 or INDEX32", fmt);
    if (bytes == 0) return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateIndexBuffer: size 0");
    is_index_buffer *ib = calloc(1, sizeof *ib);
    unsigned char *data = ib ? calloc(1, bytes) : NULL;
    if (!data) {
        free(ib);
        return dev_fail(dev, IS_ERR_OUTOFMEMORY, "CreateIndexBuffer: out of memory for %zu bytes", bytes);
    }
    *ib = (is_index_buffer){.data = data, .size = bytes, .format = fmt};
    dev_res_add(dev, &ib->res, DEV_RES_IB);
    *out = ib;
    return IS_OK;
}

/* Lock: the buffer's memory (this device has no GPU copy, so Unlock has nothing to upload); NULL for a NULL
 * handle, or one whose device was destroyed (dev_destroy freed its memory). */
/* The draws recorded from vb run first (they read its bytes as they were at the draw). */
static void vb_flush_readers(is_vertex_buffer *vb)
{
    is_device *dev = vb->res.dev;
    if (dev_live(dev) && dev_scene_reads(dev, vb)) dev_scene_flush(dev);
}

void *vb_lock(is_vertex_buffer *vb)
{
    if (!vb) return NULL;
    vb_flush_readers(vb);
    return vb->data;
}
void vb_unlock(is_vertex_buffer *vb) { (void)vb; }
size_t vb_size(const is_vertex_buffer *vb) { return vb ? vb->size : 0; }
void *ib_lock(is_index_buffer *ib) { return ib ? ib->data : NULL; }
void ib_unlock(is_index_buffer *ib) { (void)ib; }
size_t ib_size(const is_index_buffer *ib) { return ib ? ib->size : 0; }

/* Release a vertex buffer; unbinds it from the device's streams. */
void vb_release(is_vertex_buffer *vb)
{
    if (!vb) return;
    vb_flush_readers(vb);
    is_device *dev = vb->res.dev;
    for (int s = 0; s < IS_MAX_STREAMS; s++)
        if (dev->streams[s].vb == vb) dev->streams[s].vb = NULL;
    sb_forget(dev, vb);
    dev_res_remove(&vb->res);   /* may free a destroyed device: dev is not read after it */
    free(vb->data);
    free(vb);
}

/* Release an index buffer; unbinds it. */
void ib_release(is_index_buffer *ib)
{
    if (!ib) return;
    if (ib->res.dev->ib == ib) ib->res.dev->ib = NULL;
    sb_forget(ib->res.dev, ib);
    dev_res_remove(&ib->res);
    free(ib->data);
    free(ib);
}

/* Bytes an element of `type` reads, or 0 for an unknown type. */
static unsigned decltype_size(uint8_t type)
{
    switch (type) {
    case IS_DECLTYPE_FLOAT1: return 4;
    case IS_DECLTYPE_FLOAT2: return 8;
    case IS_DECLTYPE_FLOAT3: return 12;
    case IS_DECLTYPE_FLOAT4: return 16;
    case IS_DECLTYPE_D3DCOLOR: case IS_DECLTYPE_UBYTE4: case IS_DECLTYPE_UBYTE4N: return 4;
    case IS_DECLTYPE_SHORT2: case IS_DECLTYPE_SHORT2N: case IS_DECLTYPE_USHORT2N: return 4;
    case IS_DECLTYPE_SHORT4: case IS_DECLTYPE_SHORT4N: case IS_DECLTYPE_USHORT4N: return 8;
    case IS_DECLTYPE_UDEC3: case IS_DECLTYPE_DEC3N: case IS_DECLTYPE_FLOAT16_2: return 4;
    case IS_DECLTYPE_FLOAT16_4: return 8;
    default: return 0;
    }
}

/* Byte offset in is_vs_input of the register for (usage, index); -1 if this device has no such register. */
static long usage_register(uint8_t usage, uint8_t index)
{
    size_t base, count;
    switch (usage) {
    case IS_DECLUSAGE_POSITION: base = offsetof(is_vs_input, position), count = 2; break;
    case IS_DECLUSAGE_BLENDWEIGHT: base = offsetof(is_vs_input, blendweight), count = 1; break;
    case IS_DECLUSAGE_BLENDINDICES: base = offsetof(is_vs_input, blendindices), count = 1; break;
    case IS_DECLUSAGE_NORMAL: base = offsetof(is_vs_input, normal), count = 2; break;
    case IS_DECLUSAGE_PSIZE: base = offsetof(is_vs_input, psize), count = 1; break;
    case IS_DECLUSAGE_TEXCOORD: base = offsetof(is_vs_input, texcoord), count = IS_USAGE_INDICES; break;
    case IS_DECLUSAGE_TANGENT: base = offsetof(is_vs_input, tangent), count = 1; break;
    case IS_DECLUSAGE_BINORMAL: base = offsetof(is_vs_input, binormal), count = 1; break;
    case IS_DECLUSAGE_COLOR: base = offsetof(is_vs_input, color), count = 2; break;
    case IS_DECLUSAGE_TESSFACTOR: base = offsetof(is_vs_input, tessfactor), count = 1; break;
    /* pre-transformed x, y, z, rhw (core/raster_states.c): the position register, which the pass-through reads */
    case IS_DECLUSAGE_POSITIONT: base = offsetof(is_vs_input, position), count = 1; break;
    default: return -1;
    }
    return index < count ? (long)(base + index * sizeof(float4)) : -1;
}

/* Validate one element e (number k) against the ones before it; message into dev on failure. */
static is_result check_element(is_device *dev, const is_vertex_declaration *d, unsigned k,
                               const is_vertex_element *e)
{
    if (e->stream >= IS_MAX_STREAMS)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: element %u: stream %u >= %d", k,
                        e->stream, IS_MAX_STREAMS);
    if (!decltype_size(e->type))
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: element %u: unknown type %u", k,
                        e->type);
    if (e->method != 0)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: element %u: method %u unsupported", k,
                        e->method);
    if (e->offset % 4)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: element %u: offset %u not DWORD-aligned",
                        k, e->offset);
    if (usage_register(e->usage, e->usage_index) < 0)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: element %u: usage %u index %u unsupported",
                        k, e->usage, e->usage_index);
    if (e->usage == IS_DECLUSAGE_TESSFACTOR && e->type != IS_DECLTYPE_FLOAT1) /* D3D9's rule for the factor */
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: element %u: TESSFACTOR must be FLOAT1 "
                        "(type %u)", k, e->type);
    for (unsigned j = 0; j < d->n; j++) {
        const is_vertex_element *o = &d->el[j].e;
        if (o->usage == e->usage && o->usage_index == e->usage_index)
            return dev_fail(dev, IS_ERR_INVALIDCALL,
                            "CreateVertexDeclaration: element %u repeats usage %u index %u of element %u", k,
                            e->usage, e->usage_index, j);
        if (usage_register(o->usage, o->usage_index) == usage_register(e->usage, e->usage_index)) /* POSITIONT */
            return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: element %u (usage %u) and element %u "
                            "(usage %u) fill the same register (POSITION0 and POSITIONT)", k, e->usage, j, o->usage);
        if (o->stream == e->stream && e->offset < o->offset + d->el[j].size &&
            o->offset < e->offset + decltype_size(e->type))
            return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: element %u overlaps element %u", k, j);
    }
    return IS_OK;
}

/* CreateVertexDeclaration: copy and validate the elements up to the end marker. */
is_result dev_create_vertex_declaration(is_device *dev, const is_vertex_element *elements,
                                        is_vertex_declaration **out)
{
    if (out) *out = NULL;
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!elements || !out) return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: NULL argument");
    is_vertex_declaration *d = calloc(1, sizeof *d);
    if (!d) return dev_fail(dev, IS_ERR_OUTOFMEMORY, "CreateVertexDeclaration: out of memory");
    for (unsigned k = 0;; k++) {
        const is_vertex_element *e = &elements[k];
        if (e->stream == 0xFF) break;
        is_result r = k >= IS_MAX_ELEMENTS
                          ? dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: more than %d elements",
                                     IS_MAX_ELEMENTS)
                          : check_element(dev, d, k, e);
        if (r != IS_OK) {
            free(d);
            return r;
        }
        d->el[d->n++] = (decl_element){*e, decltype_size(e->type), (unsigned)usage_register(e->usage, e->usage_index)};
        d->stream_mask |= 1u << e->stream;
        d->positiont |= e->usage == IS_DECLUSAGE_POSITIONT;
    }
    if (d->n == 0) {
        free(d);
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateVertexDeclaration: no elements before the end marker");
    }
    dev_res_add(dev, &d->res, DEV_RES_DECL);
    *out = d;
    return IS_OK;
}

/* Release a declaration; unbinds it. */
void decl_release(is_vertex_declaration *decl)
{
    if (!decl) return;
    if (decl->res.dev->decl == decl) decl->res.dev->decl = NULL;
    sb_forget(decl->res.dev, decl);
    dev_res_remove(&decl->res);
    free(decl);
}

/* Read a little-endian value of a type at p without alignment assumptions. */
static float rd_f32(const unsigned char *p) { float f; memcpy(&f, p, 4); return f; }
static int16_t rd_i16(const unsigned char *p) { int16_t v; memcpy(&v, p, 2); return v; }
static uint16_t rd_u16(const unsigned char *p) { uint16_t v; memcpy(&v, p, 2); return v; }
/* SHORTnN: -32768 and -32767 both map to -1 (D3D9's SNORM rule). */
static float snorm16(int16_t v) { return v <= -32767 ? -1.0f : (float)v / 32767.0f; }

/* An IEEE 754 half float's value, exactly (every half is a float): subnormals, infinities and NaN included. */
static float half_float(uint16_t h)
{
    const uint32_t sign = (uint32_t)(h >> 15) << 31, e = (h >> 10) & 31u, m = h & 1023u;
    if (e == 0) {   /* zero or subnormal: m * 2^-24, exact in float */
        float f = ldexpf((float)m, -24);
        return sign ? -f : f;
    }
    uint32_t bits = sign | (e == 31 ? (255u << 23) | (m << 13) : ((e + 112u) << 23) | (m << 13));
    float f;
    memcpy(&f, &bits, 4);
    return f;
}

/* DEC3N's field: a signed 10-bit value / 511, -512 and -511 both -1. */
static float snorm10(uint32_t field)
{
    int v = (int)(field & 1023u) - (field & 512u ? 1024 : 0);
    return v <= -511 ? -1.0f : (float)v / 511.0f;
}

/* Expand an element of `type` at src into a float4 register; missing components default to (0, 0, 0, 1). */
float4 decl_fetch(uint8_t type, const unsigned char *src)
{
    switch (type) {
    case IS_DECLTYPE_FLOAT1: return f4(rd_f32(src), 0, 0, 1);
    case IS_DECLTYPE_FLOAT2: return f4(rd_f32(src), rd_f32(src + 4), 0, 1);
    case IS_DECLTYPE_FLOAT3: return f4(rd_f32(src), rd_f32(src + 4), rd_f32(src + 8), 1);
    case IS_DECLTYPE_FLOAT4: return f4(rd_f32(src), rd_f32(src + 4), rd_f32(src + 8), rd_f32(src + 12));
    case IS_DECLTYPE_D3DCOLOR: /* bytes B, G, R, A in memory -> (R, G, B, A) */
        return f4(src[2] / 255.0f, src[1] / 255.0f, src[0] / 255.0f, src[3] / 255.0f);
    case IS_DECLTYPE_UBYTE4: return f4(src[0], src[1], src[2], src[3]);
    case IS_DECLTYPE_UBYTE4N: return f4(src[0] / 255.0f, src[1] / 255.0f, src[2] / 255.0f, src[3] / 255.0f);
    case IS_DECLTYPE_SHORT2: return f4(rd_i16(src), rd_i16(src + 2), 0, 1);
    case IS_DECLTYPE_SHORT4: return f4(rd_i16(src), rd_i16(src + 2), rd_i16(src + 4), rd_i16(src + 6));
    case IS_DECLTYPE_SHORT2N: return f4(snorm16(rd_i16(src)), snorm16(rd_i16(src + 2)), 0, 1);
    case IS_DECLTYPE_SHORT4N:
        return f4(snorm16(rd_i16(src)), snorm16(rd_i16(src + 2)), snorm16(rd_i16(src + 4)),
                  snorm16(rd_i16(src + 6)));
    case IS_DECLTYPE_USHORT2N: return f4(rd_u16(src) / 65535.0f, rd_u16(src + 2) / 65535.0f, 0, 1);
    case IS_DECLTYPE_USHORT4N:
        return f4(rd_u16(src) / 65535.0f, rd_u16(src + 2) / 65535.0f, rd_u16(src + 4) / 65535.0f,
                  rd_u16(src + 6) / 65535.0f);
    case IS_DECLTYPE_UDEC3: {
        uint32_t u;
        memcpy(&u, src, 4);
        return f4((float)(u & 1023u), (float)((u >> 10) & 1023u), (float)((u >> 20) & 1023u), 1);
    }
    case IS_DECLTYPE_DEC3N: {
        uint32_t u;
        memcpy(&u, src, 4);
        return f4(snorm10(u), snorm10(u >> 10), snorm10(u >> 20), 1);
    }
    case IS_DECLTYPE_FLOAT16_2: return f4(half_float(rd_u16(src)), half_float(rd_u16(src + 2)), 0, 1);
    case IS_DECLTYPE_FLOAT16_4:
        return f4(half_float(rd_u16(src)), half_float(rd_u16(src + 2)), half_float(rd_u16(src + 4)),
                  half_float(rd_u16(src + 6)));
    default: return f4(0, 0, 0, 1);
    }
}
