/* tests/util/crack.c -- the crack detector the crack tests share (crack.h). */
#include "crack.h"

#include <string.h>

uint32_t crack_mix32(uint32_t h)
{
    h ^= h >> 16, h *= 0x7feb352du, h ^= h >> 15, h *= 0x846ca68bu, h ^= h >> 16;
    return h;
}

uint32_t crack_bits(float f)
{
    f = f + 0.0f;   /* x + 0 is +0 for x = -0 and x otherwise */
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}

void crack_jitter(float4 *P, int size)
{
    uint32_t h = crack_mix32(crack_bits(P->w) ^ 0x5bd1e995u);
    h = crack_mix32(crack_bits(P->x) ^ crack_mix32(crack_bits(P->y) ^ crack_mix32(crack_bits(P->z) ^ h)));
    float jx = (float)(h & 0xffffu) / 65536.0f - 0.5f, jy = (float)(h >> 16) / 65536.0f - 0.5f;
    P->x += jx * (2.0f / (float)size) * P->w;   /* NDC x = x / w spans size pixels over 2 */
    P->y += jy * (2.0f / (float)size) * P->w;
}

void crack_counting_states(is_device *dev)
{
    dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE);
    dev_set_render_state(dev, IS_RS_ZENABLE, 0);
    dev_set_render_state(dev, IS_RS_ALPHABLENDENABLE, 1);
    dev_set_render_state(dev, IS_RS_SRCBLEND, IS_BLEND_ONE);
    dev_set_render_state(dev, IS_RS_DESTBLEND, IS_BLEND_ONE);
    dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0, 1.0f);
}

bool crack_split_normals(const is_mesh *m)
{
    for (size_t t = 0; t < 3 * m->n_triangles; t++) {
        uint32_t a = m->indices[t], w = m->welded[t];
        if (a != w && memcmp(&m->normals[a], &m->normals[w], sizeof(float3)) != 0) return true;
    }
    return false;
}
