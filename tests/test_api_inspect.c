/* tests/test_api_inspect.c -- every public function of core/inspect.h with NULL devices and records, pixels at
 * and beyond the target's edges (INT_MIN, INT_MAX), a multisampled target, recording begun twice, ended twice or
 * never, a device destroyed while it records (its inspector freed: the sanitizer stage checks for leaks), draws the
 * inspector does not record (points, lines) and draws that fail (nothing recorded for them).  Usage names out of
 * range are "?".  tests/check_api_walkers.sh checks that every INSTESS_API function of core/inspect.h is named
 * here. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <limits.h>
#include <string.h>

#include "../core/core.h"
#include "../vs/vs.h"
#include "util/dev_util.h"


/* The buffer and declaration of the last device made (they hold their device: released with it by destroy). */
static is_vertex_buffer *held_vb;
static is_vertex_declaration *held_decl;

/* dev_destroy, then the resources the device helper made (the device's struct goes with the last of them). */
static void destroy(is_device *dev) { tu_device_destroy(dev, &held_vb, &held_decl); }

/* A 16x16 device drawing one screen-filling triangle with the fixed shader (identity transform): positions in a
 * vertex buffer of float4s (stream 0, POSITION0). */
static is_device *device_with_triangle(int samples)
{
    const float verts[4][4] = {{-1, 1, 0.5f, 1}, {3, 1, 0.5f, 1}, {-1, -3, 0.5f, 1}, {0, 0, 0.5f, 1}};
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    return tu_fixed_device(16, 16, samples, verts, sizeof verts, sizeof verts[0], el, (float4){1, 1, 1, 1}, &held_vb,
                           &held_decl);
}

/* NULL arguments, pixels outside, multisampled targets; begin twice, end twice. */
static void test_arguments(void **state)
{
    (void)state;
    is_inspect rec, other;
    memset(&rec, 0x5a, sizeof rec);   /* untouched by refused calls */
    assert_int_equal(dev_inspect_begin(NULL, 0, 0, &rec), IS_ERR_INVALIDCALL);
    is_device *dev = device_with_triangle(1);
    assert_int_equal(dev_inspect_begin(dev, 0, 0, NULL), IS_ERR_INVALIDCALL);
    const int bad[][2] = {{-1, 0}, {0, -1}, {16, 0}, {0, 16}, {INT_MIN, 0}, {0, INT_MAX}, {INT_MAX, INT_MIN}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        assert_int_equal(dev_inspect_begin(dev, bad[k][0], bad[k][1], &rec), IS_ERR_INVALIDCALL);
    assert_int_equal(rec.x, 0x5a5a5a5a);
    memset(&rec, 0, sizeof rec);
    memset(&other, 0, sizeof other);
    assert_int_equal(dev_inspect_begin(dev, 15, 15, &rec), IS_OK);
    assert_int_equal(dev_inspect_begin(dev, 3, 4, &other), IS_OK);   /* the second replaces the first */
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
    assert_int_equal(rec.n_fragments, 0);
    assert_int_equal(other.n_fragments, 1);
    assert_int_equal(other.x, 3);
    dev_inspect_end(dev);
    dev_inspect_end(dev);
    dev_inspect_end(NULL);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
    assert_int_equal(other.n_fragments, 1);   /* nothing recorded after the end */
    is_inspect_free(&other);
    is_inspect_free(&other);
    is_inspect_free(NULL);
    assert_null(other.fragments);
    destroy(dev);
    dev = device_with_triangle(4);
    assert_int_equal(dev_inspect_begin(dev, 0, 0, &rec), IS_ERR_INVALIDCALL);
    destroy(dev);
    assert_string_equal(is_decl_usage_name(IS_DECLUSAGE_POSITION), "POSITION");
    assert_string_equal(is_decl_usage_name(IS_DECLUSAGE_COUNT), "?");
    assert_string_equal(is_decl_usage_name(UINT_MAX), "?");
}

/* Draws not recorded (points, lines), draws that fail, and a device destroyed while it records. */
static void test_draws(void **state)
{
    (void)state;
    is_device *dev = device_with_triangle(1);
    is_inspect rec = {0};
    assert_int_equal(dev_inspect_begin(dev, 2, 2, &rec), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_POINTLIST, 0, 3), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_LINELIST, 0, 1), IS_OK);
    assert_int_equal(rec.draws, 0);
    assert_int_equal(rec.draws_skipped, 2);
    assert_int_equal(dev_set_vertex_shader(dev, NULL), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_ERR_INVALIDCALL);   /* no shader */
    assert_int_equal(rec.n_fragments, 0);
    assert_int_equal(dev_set_vertex_shader(dev, &vs_shader_fixed), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
    assert_int_equal(rec.draws, 1);
    assert_int_equal(rec.n_fragments, 1);
    const is_inspect_fragment *f = &rec.fragments[0];
    assert_int_equal(f->v[0].n_inputs, 1);
    assert_int_equal(f->v[0].inputs[0].usage, IS_DECLUSAGE_POSITION);
    assert_int_equal(f->v[0].n_values, 0);   /* the fixed shader publishes nothing */
    assert_true(f->passed);
    destroy(dev);   /* while recording: the inspector goes with the device, rec keeps its fragments */
    assert_int_equal(rec.n_fragments, 1);
    is_inspect_free(&rec);
}

/* A viewport larger than the target (accepted and drawn clipped to it, as the runtime does): the record still
 * finds the fragment, and its colour is the target's. */
static void test_viewport_beyond_target(void **state)
{
    (void)state;
    is_device *dev = device_with_triangle(1);
    const float small[4][4] = {{-0.5f, 0.5f, 0.5f, 1}, {0.5f, 0.5f, 0.5f, 1}, {-0.5f, -0.5f, 0.5f, 1}, {0, 0, 0.5f, 1}};
    is_vertex_buffer *vb;
    assert_int_equal(dev_get_stream_source(dev, 0, &vb, &(unsigned){0}, &(unsigned){0}), IS_OK);
    memcpy(vb_lock(vb), small, sizeof small);
    vb_unlock(vb);
    const is_viewport vp = {0, 0, 40, 40, 0.0f, 1.0f};   /* the triangle's pixels: 10..30 of 40, the target 16 */
    assert_int_equal(dev_set_viewport(dev, &vp), IS_OK);
    for (int y = 11; y < 16; y += 2)
        for (int x = 11; x < 16; x += 2) {
            is_inspect rec = {0};
            assert_int_equal(dev_inspect_begin(dev, x, y, &rec), IS_OK);
            assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0xff102030u, 1.0f), IS_OK);
            assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
            dev_inspect_end(dev);
            uint32_t px[16 * 16];
            assert_int_equal(dev_get_render_target_data(dev, px, 16 * 16), IS_OK);
            bool drawn = px[y * 16 + x] != 0xff302010u;   /* the clear colour, RGBA8 in memory */
            assert_int_equal(rec.n_fragments, drawn ? 1 : 0);
            if (drawn) assert_int_equal(rec.fragments[0].color_after, px[y * 16 + x]);
            is_inspect_free(&rec);
        }
    destroy(dev);
}

/* A draw into a render target of another size is not recorded (counted skipped); back on the first target, it is. */
static void test_other_render_target(void **state)
{
    (void)state;
    is_device *dev = device_with_triangle(1);
    is_surface *back, *small;
    assert_int_equal(dev_get_render_target(dev, 0, &back), IS_OK);
    assert_int_equal(dev_create_render_target(dev, 8, 8, IS_FMT_A8R8G8B8, 0, &small), IS_OK);
    is_inspect rec = {0};
    assert_int_equal(dev_inspect_begin(dev, 12, 12, &rec), IS_OK);   /* outside the small target */
    assert_int_equal(dev_set_render_target(dev, 0, small), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
    assert_int_equal(rec.draws_skipped, 1);
    assert_int_equal(rec.n_fragments, 0);
    assert_int_equal(dev_set_render_target(dev, 0, back), IS_OK);
    assert_int_equal(dev_draw_primitive(dev, IS_PT_TRIANGLELIST, 0, 1), IS_OK);
    assert_int_equal(rec.draws, 1);
    assert_int_equal(rec.n_fragments, 1);
    dev_inspect_end(dev);
    is_inspect_free(&rec);
    surf_release(small);
    destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_arguments),
        cmocka_unit_test(test_draws),
        cmocka_unit_test(test_viewport_beyond_target),
        cmocka_unit_test(test_other_render_target),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
