/* tests/test_api_texture.c -- every public function of core/texture.h with NULL devices, textures, samplers and
 * outputs, sizes of zero and beyond IS_MAX_TEXTURE_SIZE, level counts beyond the chain, formats and usages that do
 * not exist, rectangles outside their level, locks twice and unlocks without a lock, textures of another device
 * or released, sampler indices that do not exist, and coordinates, levels of detail and gradients that are NaN,
 * infinite or huge.  Each returns its error (or IS_OK where the runtime ignores the call), never reads a texel
 * outside its level (ASan in the sanitizer stage) and never converts a float out of an integer's range (UBSan's
 * float-cast-overflow).  tests/check_api_walkers.sh checks that every INSTESS_API function of core/texture.h is
 * named in this file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../core/core.h"
#include "../core/texture.h"
#include "../image/image.h"

static const float edge[] = {0.0f, -0.0f, 0.5f, -1.0f, 1e-45f, 1e30f, -1e30f, FLT_MAX, INFINITY, -INFINITY, NAN,
                             1073741824.0f, 3e9f};
enum { N_EDGE = sizeof edge / sizeof edge[0] };

/* NULL devices, textures and outputs. */
static void test_null(void **state)
{
    (void)state;
    is_texture *t = (is_texture *)1;
    assert_int_equal(dev_create_texture(NULL, 4, 4, 1, 0, IS_FMT_A8R8G8B8, &t), IS_ERR_INVALIDCALL);
    assert_null(t);
    tex_release(NULL);
    assert_int_equal(tex_get_level_count(NULL), 0);
    is_texture_desc d;
    assert_int_equal(tex_get_level_desc(NULL, 0, &d), IS_ERR_INVALIDCALL);
    is_locked_rect lr;
    assert_int_equal(tex_lock_rect(NULL, 0, &lr, NULL, 0), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_unlock_rect(NULL, 0), IS_ERR_INVALIDCALL);
    tex_generate_mip_sub_levels(NULL);
    assert_int_equal(tex_filter_texture(NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_texture(NULL, 0, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_texture(NULL, 0, &t), IS_ERR_INVALIDCALL);
    uint32_t u;
    assert_int_equal(dev_set_sampler_state(NULL, 0, IS_SAMP_MINFILTER, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_sampler_state(NULL, 0, IS_SAMP_MINFILTER, &u), IS_ERR_INVALIDCALL);
    is_sampler s = tex_sampler_default(NULL);   /* an empty sampler: (0, 0, 0, 1) */
    float4 r = tex_sample_lod(&s, (float4){0.5f, 0.5f, 0, 0});
    assert_true(r.x == 0 && r.w == 1);
    r = tex_sample_lod(NULL, (float4){0.5f, 0.5f, 0, 0});
    assert_true(r.x == 0 && r.w == 1);
    r = tex_sample_grad(NULL, (float2){0, 0}, (float2){0, 0}, (float2){0, 0});
    assert_true(r.w == 1);
    r = tex_sample_bias(NULL, (float4){0, 0, 0, 0}, (float2){0, 0}, (float2){0, 0});
    assert_true(r.w == 1);
    assert_int_equal(dev_create_texture_from_file(NULL, "x.png", IS_FMT_A8R8G8B8, 1, &t), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_texture_from_image(NULL, NULL, IS_FMT_A8R8G8B8, 1, &t), IS_ERR_INVALIDCALL);
    is_device *dev = dev_create(4, 4, 1, NULL, 0);
    assert_int_equal(dev_create_texture(dev, 4, 4, 1, 0, IS_FMT_A8R8G8B8, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_texture_from_file(dev, NULL, IS_FMT_A8R8G8B8, 1, &t), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_texture_from_file(dev, "no-such-file.png", IS_FMT_A8R8G8B8, 1, &t) < 0, true);
    assert_int_equal(dev_create_texture_from_image(dev, NULL, IS_FMT_A8R8G8B8, 1, &t), IS_ERR_INVALIDCALL);
    float px[4] = {0};
    is_image lie = {.width = 1 << 20, .height = 1 << 20, .channels = 1, .data = px};
    assert_true(dev_create_texture_from_image(dev, &lie, IS_FMT_A8R8G8B8, 1, &t) < 0);
    lie = (is_image){.width = 2, .height = 2, .channels = 0, .data = px};
    assert_true(dev_create_texture_from_image(dev, &lie, IS_FMT_A8R8G8B8, 1, &t) < 0);
    lie = (is_image){.width = 2, .height = 2, .channels = 1, .data = NULL};
    assert_true(dev_create_texture_from_image(dev, &lie, IS_FMT_A8R8G8B8, 1, &t) < 0);
    dev_destroy(dev);
}

/* Creation at its edges, locks and levels. */
static void test_create_and_lock(void **state)
{
    (void)state;
    is_device *dev = dev_create(4, 4, 1, NULL, 0);
    is_texture *t;
    const unsigned bad[][3] = {{0, 4, 1}, {4, 0, 1}, {IS_MAX_TEXTURE_SIZE + 1, 1, 1}, {UINT_MAX, UINT_MAX, 0},
                               {4, 4, 4}, {4, 4, UINT_MAX}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        assert_true(dev_create_texture(dev, bad[k][0], bad[k][1], bad[k][2], 0, IS_FMT_A8R8G8B8, &t) < 0);
    assert_true(dev_create_texture(dev, 4, 4, 1, 0, (is_format)0, &t) < 0);
    assert_true(dev_create_texture(dev, 4, 4, 1, 0, IS_FMT_INDEX16, &t) < 0);
    assert_true(dev_create_texture(dev, 4, 4, 1, 0xffffffffu, IS_FMT_A8R8G8B8, &t) < 0);
    assert_true(dev_create_texture(dev, 4, 4, 3, IS_USAGE_AUTOGENMIPMAP, IS_FMT_A8R8G8B8, &t) < 0);
    assert_int_equal(dev_create_texture(dev, 5, 3, 0, 0, IS_FMT_R32F, &t), IS_OK);
    unsigned levels = tex_get_level_count(t);
    assert_int_equal(levels, 3);
    is_texture_desc d;
    assert_int_equal(tex_get_level_desc(t, levels, &d), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_get_level_desc(t, UINT_MAX, &d), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_get_level_desc(t, 0, NULL), IS_ERR_INVALIDCALL);
    is_locked_rect lr;
    assert_int_equal(tex_lock_rect(t, levels, &lr, NULL, 0), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_lock_rect(t, 32, &lr, NULL, 0), IS_ERR_INVALIDCALL);   /* past the lock mask's bits too */
    assert_int_equal(tex_lock_rect(t, 0, NULL, NULL, 0), IS_ERR_INVALIDCALL);
    const is_rect rects[] = {{0, 0, 0, 0}, {3, 1, 1, 2}, {-1, 0, 1, 1}, {0, 0, 6, 1}, {0, 0, 5, 4},
                             {INT32_MIN, INT32_MIN, INT32_MAX, INT32_MAX}, {4, 2, 5, 3}};
    for (size_t k = 0; k + 1 < sizeof rects / sizeof rects[0]; k++)
        assert_int_equal(tex_lock_rect(t, 0, &lr, &rects[k], 0), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_lock_rect(t, 0, &lr, &rects[6], 0), IS_OK);   /* the last texel */
    assert_int_equal(tex_lock_rect(t, 0, &lr, NULL, 0), IS_ERR_INVALIDCALL);   /* locked already */
    assert_int_equal(tex_filter_texture(t), IS_ERR_INVALIDCALL);              /* a level is locked */
    assert_int_equal(tex_unlock_rect(t, 0), IS_OK);
    assert_int_equal(tex_unlock_rect(t, 0), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_unlock_rect(t, UINT_MAX), IS_ERR_INVALIDCALL);
    assert_int_equal(tex_filter_texture(t), IS_OK);
    tex_generate_mip_sub_levels(t);
    /* samplers that do not exist: ignored as the runtime does; a NULL output refused */
    assert_int_equal(dev_set_texture(dev, 16, t), IS_OK);
    assert_int_equal(dev_set_texture(dev, UINT_MAX, t), IS_OK);
    is_texture *got = (is_texture *)1;
    assert_true(dev_get_texture(dev, 5000, &got) == IS_OK || dev_get_texture(dev, 5000, &got) == IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_texture(dev, 0, NULL), IS_ERR_INVALIDCALL);
    uint32_t u;
    assert_int_equal(dev_set_sampler_state(dev, UINT_MAX, IS_SAMP_MINFILTER, 1), IS_OK);
    assert_int_equal(dev_set_sampler_state(dev, 0, (is_samp)0, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_set_sampler_state(dev, 0, (is_samp)INT_MAX, 1), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_sampler_state(dev, 0, IS_SAMP_MINFILTER, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_sampler_state(dev, 0, (is_samp)-1, &u), IS_ERR_INVALIDCALL);
    /* another device's texture and a released one: refused */
    is_device *other = dev_create(4, 4, 1, NULL, 0);
    assert_int_equal(dev_set_texture(other, 0, t), IS_ERR_INVALIDCALL);
    is_texture *gone;
    assert_int_equal(dev_create_texture(dev, 2, 2, 1, 0, IS_FMT_A8R8G8B8, &gone), IS_OK);
    tex_release(gone);
    assert_int_equal(dev_set_texture(dev, 0, gone), IS_ERR_INVALIDCALL);
    char junk[512] = {0};
    assert_int_equal(dev_set_texture(dev, 0, (is_texture *)junk), IS_ERR_INVALIDCALL);
    dev_destroy(other);
    dev_destroy(dev);   /* releases t */
}

/* Sampling with every address, filter and odd value, at NaN, infinite and huge coordinates and levels. */
static void test_sampling(void **state)
{
    (void)state;
    is_device *dev = dev_create(4, 4, 1, NULL, 0);
    is_texture *t;
    assert_int_equal(dev_create_texture(dev, 3, 5, 0, 0, IS_FMT_A8R8G8B8, &t), IS_OK);
    is_sampler s = tex_sampler_default(t);
    const uint32_t odd[] = {0, 1, 2, 3, 4, 5, 6, 99, UINT32_MAX};
    for (size_t m = 0; m < sizeof odd / sizeof odd[0]; m++) {
        s.state[IS_SAMP_ADDRESSU] = s.state[IS_SAMP_ADDRESSV] = odd[m];
        s.state[IS_SAMP_MINFILTER] = s.state[IS_SAMP_MAGFILTER] = s.state[IS_SAMP_MIPFILTER] = odd[m];
        s.state[IS_SAMP_MAXMIPLEVEL] = odd[m];
        float bias = edge[m % N_EDGE];
        memcpy(&s.state[IS_SAMP_MIPMAPLODBIAS], &bias, 4);
        for (int a = 0; a < N_EDGE; a++)
            for (int b = 0; b < N_EDGE; b++) {
                float4 r = tex_sample_lod(&s, (float4){edge[a], edge[b], 0, edge[(a + b) % N_EDGE]});
                r = tex_sample_grad(&s, (float2){edge[a], edge[b]}, (float2){edge[b], 0}, (float2){0, edge[a]});
                r = tex_sample_bias(&s, (float4){edge[b], edge[a], 0, edge[a]}, (float2){edge[a], edge[b]},
                                    (float2){edge[b], edge[a]});
                (void)r;
            }
    }
    for (int a = 0; a < N_EDGE; a++) {
        (void)tex_log2(edge[a]);
        (void)tex_lod_from_gradients(0, 0, (float2){edge[a], edge[a]}, (float2){0, 0});
        (void)tex_lod_from_gradients(UINT_MAX, UINT_MAX, (float2){edge[a], 1}, (float2){1, edge[a]});
    }
    assert_true(tex_log2(8.0f) == 3.0f);
    assert_true(isinf(tex_log2(0.0f)) && tex_log2(0.0f) < 0);
    assert_true(isnan(tex_log2(-1.0f)));
    dev_destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_null),
        cmocka_unit_test(test_create_and_lock),
        cmocka_unit_test(test_sampling),
    };
    return cmocka_run_group_tests_name("api_texture", tests, NULL, NULL);
}
