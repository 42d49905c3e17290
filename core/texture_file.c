/* core/texture_file.c -- a texture from an image file (D3DXCreateTextureFromFileEx): read through image/'s
 * OpenImageIO codec, converted to the texture's format, levels filtered.  Rules: core/texture.h. */
#include "device_internal.h"

#include "../image/image.h"
#include <stdio.h>
#include <string.h>

/* The channels of img that give r, g, b, a (-1: none): by name; without R the image is grey (Y, or channel 0). */
static void pick_channels(const is_image *img, int ch[4])
{
    static const char *const names[4] = {"R", "G", "B", "A"};
    for (int k = 0; k < 4; k++) ch[k] = image_channel_index(img, names[k]);
    if (ch[0] >= 0) return;
    int y = image_channel_index(img, "Y");
    ch[0] = y >= 0 ? y : 0;
    if (ch[1] < 0) ch[1] = ch[0];
    if (ch[2] < 0) ch[2] = ch[0];
}

/* A value in [0, 1] as a byte, rounded (NaN as 0). */
static unsigned char unorm8(float v)
{
    if (!(v > 0.0f)) return 0;
    return v >= 1.0f ? 255 : (unsigned char)(v * 255.0f + 0.5f);
}

/* Level 0 of t (img's size) from img's pixels. */
static void fill_level0(is_texture *t, const is_image *img)
{
    int ch[4];
    pick_channels(img, ch);
    const tex_level *l = &t->lv[0];
    for (size_t p = 0; p < (size_t)l->w * l->h; p++) {
        const float *px = img->data + p * (size_t)img->channels;
        float v[4];
        for (int k = 0; k < 4; k++) v[k] = ch[k] >= 0 ? px[ch[k]] : k == 3 ? 1.0f : 0.0f;
        unsigned char *q = l->bits + p * t->bpp;
        if (t->format == IS_FMT_R32F) memcpy(q, &v[0], 4);
        else if (t->format == IS_FMT_A32B32G32R32F) memcpy(q, v, 16);
        else q[0] = unorm8(v[2]), q[1] = unorm8(v[1]), q[2] = unorm8(v[0]), q[3] = unorm8(v[3]); /* B, G, R, A */
    }
}

is_result dev_create_texture_from_image(is_device *dev, const is_image *img, is_format format, unsigned levels,
                                        is_texture **out)
{
    if (out) *out = NULL;
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!img || !img->data || !out) return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateTextureFromImage: NULL argument");
    if (img->channels < 1 || img->channels > IS_IMAGE_MAX_CHANNELS || img->width < 1 || img->height < 1)
        return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateTextureFromImage: an image of %dx%d pixels and %d channels",
                        img->width, img->height, img->channels);
    is_texture *t = NULL;
    is_result r = dev_create_texture(dev, (unsigned)img->width, (unsigned)img->height, levels, 0, format, &t);
    if (r != IS_OK) return r;
    fill_level0(t, img);
    tex_filter_texture(t);
    *out = t;
    return IS_OK;
}

is_result dev_create_texture_from_file(is_device *dev, const char *path, is_format format, unsigned levels,
                                       is_texture **out)
{
    if (out) *out = NULL;
    if (!dev_live(dev)) return IS_ERR_INVALIDCALL;
    if (!path || !out) return dev_fail(dev, IS_ERR_INVALIDCALL, "CreateTextureFromFile: NULL %s",
                                       path ? "output pointer" : "path");
    is_image img = {0};
    char err[512];
    if (image_read(&img, path, err, sizeof err) != 0) return dev_fail(dev, IS_ERR_NOTAVAILABLE, "%s", err);
    is_result r = dev_create_texture_from_image(dev, &img, format, levels, out);
    image_free(&img);
    if (r != IS_OK) {
        char why[sizeof dev->err];
        snprintf(why, sizeof why, "%s", dev->err);
        return dev_fail(dev, r, "%s: %s", path, why);
    }
    return IS_OK;
}
