/* raster/target.c -- render targets: allocation, AOV planes, clear and multisample resolve. */
#include <stdlib.h>
#include <string.h>

#include "raster_internal.h"

/* Allocate a w x h target with 1 or 4 samples: RS_OK, RS_EINVAL (bad arguments) or RS_ENOMEM. */
int rs_target_init(rs_target *rt, int width, int height, int samples)
{
    if (!rt) return RS_EINVAL;
    memset(rt, 0, sizeof *rt);
    if (width < 1 || height < 1 || width > RS_MAX_SIZE || height > RS_MAX_SIZE) return RS_EINVAL;
    if (samples != 1 && samples != 4) return RS_EINVAL;
    size_t n = (size_t)width * (size_t)height * (size_t)samples;
    rt->color = calloc(n, sizeof *rt->color);
    rt->depth = calloc(n, sizeof *rt->depth);
    if (!rt->color || !rt->depth) {
        rs_target_free(rt);
        return RS_ENOMEM;
    }
    rt->width = width;
    rt->height = height;
    rt->samples = samples;
    return RS_OK;
}

/* Free every plane of rt and zero it (safe on a zeroed or already freed target). */
void rs_target_free(rs_target *rt)
{
    if (!rt) return;
    free(rt->color);
    free(rt->depth);
    for (int k = 0; k < rt->n_aov && k < RS_MAX_AOV; k++) free(rt->aov[k].data);
    memset(rt, 0, sizeof *rt);
}

/* Add a zeroed AOV plane of `comps` components of `slot`: RS_OK, RS_EINVAL or RS_ENOMEM. */
int rs_target_add_aov(rs_target *rt, int slot, int comps)
{
    if (!rt || !rt->color || rt->samples != 1 || rt->n_aov < 0 || rt->n_aov >= RS_MAX_AOV) return RS_EINVAL;
    if (slot < 0 || slot >= RS_MAX_ATTR || comps < 1 || comps > 4) return RS_EINVAL;
    float *d = calloc((size_t)rt->width * (size_t)rt->height * (size_t)comps, sizeof *d);
    if (!d) return RS_ENOMEM;
    rt->aov[rt->n_aov] = (rs_aov){ slot, comps, d };
    rt->n_aov++;
    return RS_OK;
}

/* Clear colour (flags & 1, also the AOV planes to 0) and depth (flags & 2) of every sample. */
void rs_target_clear(rs_target *rt, unsigned flags, uint32_t rgba, float z)
{
    if (!rt || !rt->color) return;
    size_t n = (size_t)rt->width * (size_t)rt->height * (size_t)rt->samples;
    if (flags & 1u) {
        for (size_t i = 0; i < n; i++) rt->color[i] = rgba;
        for (int k = 0; k < rt->n_aov; k++)
            memset(rt->aov[k].data, 0,
                   (size_t)rt->width * (size_t)rt->height * (size_t)rt->aov[k].comps * sizeof(float));
    }
    if (flags & 2u)
        for (size_t i = 0; i < n; i++) rt->depth[i] = z;
}

/* Average the samples of each pixel, per channel, rounding half up: (sum + n/2) / n. */
void rs_target_resolve(const rs_target *rt, uint32_t *out)
{
    if (!rt || !rt->color || !out) return;
    size_t np = (size_t)rt->width * (size_t)rt->height;
    int ns = rt->samples;
    if (ns == 1) {
        memcpy(out, rt->color, np * sizeof *out);
        return;
    }
    for (size_t p = 0; p < np; p++) {
        const uint32_t *s = rt->color + p * (size_t)ns;
        uint32_t r = 0;
        for (int c = 0; c < 32; c += 8) {
            uint32_t sum = 0;
            for (int k = 0; k < ns; k++) sum += (s[k] >> c) & 0xffu;
            r |= ((sum + (uint32_t)ns / 2) / (uint32_t)ns) << c;
        }
        out[p] = r;
    }
}
