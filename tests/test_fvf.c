/* tests/test_fvf.c -- SetFVF / GetFVF (core/fvf.c): a pre-transformed, coloured triangle drawn through
 * D3DFVF_XYZRHW | D3DFVF_DIFFUSE gives the bytes of the same draw through the explicit declaration the runtime
 * builds for it (POSITIONT float4, COLOR0 D3DCOLOR); GetFVF reads back what was set and 0 after
 * SetVertexDeclaration; refused FVFs change nothing; the device's own declaration goes with it (the sanitizer
 * stage finds no leak). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "../core/core.h"

#define W 16
#define FVF_XYZRHW 0x004u
#define FVF_DIFFUSE 0x040u
#define FVF_TEX2 0x200u
#define FVF_TEXCOORDSIZE3_0 (1u << 16)   /* D3DFVF_TEXCOORDSIZE3(0) */

typedef struct tl_vertex { float x, y, z, rhw; uint32_t argb; } tl_vertex;

static const tl_vertex tri[3] = {{1, 1, 0.5f, 1, 0xffff0000u}, {15, 2, 0.5f, 0.25f, 0xff00ff00u}, {2, 14, 0.5f, 2, 0xff0000ffu}};

/* Draw tri with DrawPrimitiveUP on a new W x W device after `bind` set its input layout; its pixels into px. */
static void draw(is_result (*bind)(is_device *dev), uint32_t *px)
{
    char err[200];
    is_device *dev = dev_create(W, W, 1, err, sizeof err);
    assert_non_null(dev);
    assert_int_equal(dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE), IS_OK);
    assert_int_equal(bind(dev), IS_OK);
    assert_int_equal(dev_clear(dev, IS_CLEAR_TARGET | IS_CLEAR_ZBUFFER, 0xff000000u, 1.0f), IS_OK);
    assert_int_equal(dev_draw_primitive_up(dev, IS_PT_TRIANGLELIST, 1, tri, sizeof tri[0]), IS_OK);
    assert_int_equal(dev_get_render_target_data(dev, px, W * W), IS_OK);
    dev_destroy(dev);
}

static is_vertex_declaration *made;   /* the explicit declaration of bind_decl (released after the draw) */
static is_result bind_fvf(is_device *dev) { return dev_set_fvf(dev, FVF_XYZRHW | FVF_DIFFUSE); }
static is_result bind_decl(is_device *dev)
{
    const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITIONT, 0},
                                    {0, 16, IS_DECLTYPE_D3DCOLOR, 0, IS_DECLUSAGE_COLOR, 0}, IS_DECL_END};
    is_result r = dev_create_vertex_declaration(dev, el, &made);
    return r == IS_OK ? dev_set_vertex_declaration(dev, made) : r;
}

static void test_same_as_declaration(void **state)
{
    (void)state;
    uint32_t a[W * W], b[W * W];
    draw(bind_fvf, a);
    draw(bind_decl, b);
    decl_release(made);
    assert_memory_equal(a, b, sizeof a);
    int coloured = 0;
    for (int k = 0; k < W * W; k++) coloured += a[k] != 0xff000000u;
    assert_true(coloured > 40);
}

static void test_get_and_refusals(void **state)
{
    (void)state;
    char err[200];
    is_device *dev = dev_create(W, W, 1, err, sizeof err);
    uint32_t fvf = 7;
    assert_int_equal(dev_get_fvf(dev, &fvf), IS_OK);
    assert_int_equal(fvf, 0u);
    const uint32_t good = FVF_XYZRHW | FVF_DIFFUSE | FVF_TEX2 | FVF_TEXCOORDSIZE3_0;
    assert_int_equal(dev_set_fvf(dev, good), IS_OK);
    assert_int_equal(dev_get_fvf(dev, &fvf), IS_OK);
    assert_int_equal(fvf, good);
    is_vertex_declaration *d1, *d2;
    assert_int_equal(dev_get_vertex_declaration(dev, &d1), IS_OK);
    assert_non_null(d1);
    assert_int_equal(dev_set_fvf(dev, good), IS_OK);   /* the same FVF: the same declaration */
    assert_int_equal(dev_get_vertex_declaration(dev, &d2), IS_OK);
    assert_ptr_equal(d1, d2);
    const uint32_t bad[] = {0x006u /* XYZB1 */, 0u /* no position */, FVF_XYZRHW | 0x900u /* 9 sets */,
                            FVF_XYZRHW | 0x1000u /* unknown */, 0x4002u /* XYZW */};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        assert_int_equal(dev_set_fvf(dev, bad[k]), IS_ERR_INVALIDCALL);
        assert_int_equal(dev_get_fvf(dev, &fvf), IS_OK);
        assert_int_equal(fvf, good);   /* nothing changed */
    }
    assert_int_equal(dev_set_vertex_declaration(dev, NULL), IS_OK);
    assert_int_equal(dev_get_fvf(dev, &fvf), IS_OK);
    assert_int_equal(fvf, 0u);
    assert_int_equal(dev_set_fvf(NULL, good), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_get_fvf(dev, NULL), IS_ERR_INVALIDCALL);
    dev_destroy(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_as_declaration),
        cmocka_unit_test(test_get_and_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
