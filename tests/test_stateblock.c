/* tests/test_stateblock.c -- stateblocks as the D3D9 runtime has them, after the behaviour Wine's d3d9 stateblock
 * tests record (dlls/d3d9/tests/stateblock.c: begin/end, recording that leaves the device alone, apply, capture and
 * re-apply) and D3D9's lists of pixel and vertex states (CreateStateBlock PIXELSTATE / VERTEXSTATE / ALL). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/core.h"

static void vs_a_main(const is_vs_constants *c, const is_vs_input *in, is_vs_output *out) { out->pos = in->position[0]; }
static const is_vertex_shader vs_a = {.name = "a", .main = vs_a_main, .outputs = 0};

/* The resources a test binds. */
typedef struct sb_fixture {
    is_device *dev;
    is_vertex_buffer *vb;
    is_index_buffer *ib;
    is_vertex_declaration *decl;
    is_texture *tex;
} sb_fixture;

static sb_fixture fixture(void)
{
    sb_fixture f;
    f.dev = dev_create(16, 16, 1, NULL, 0);
    assert_non_null(f.dev);
    assert_int_equal(dev_create_vertex_buffer(f.dev, 64, &f.vb), IS_OK);
    assert_int_equal(dev_create_index_buffer(f.dev, 64, IS_FMT_INDEX16, &f.ib), IS_OK);
    static const is_vertex_element el[] = {{0, 0, IS_DECLTYPE_FLOAT4, 0, IS_DECLUSAGE_POSITION, 0}, IS_DECL_END};
    assert_int_equal(dev_create_vertex_declaration(f.dev, el, &f.decl), IS_OK);
    assert_int_equal(dev_create_texture(f.dev, 4, 4, 1, 0, IS_FMT_A8R8G8B8, &f.tex), IS_OK);
    return f;
}

static void fixture_free(sb_fixture *f)
{
    tex_release(f->tex);
    decl_release(f->decl);
    ib_release(f->ib);
    vb_release(f->vb);
    dev_destroy(f->dev);
}

static const float test_c[4] = {5, 6, 7, 8};
static const is_viewport test_vp = {2, 3, 10, 11, 0.25f, 0.75f};

/* Set the "test data" of Wine's state tests: one value of each kind of state, none of them a default. */
static void set_test_data(const sb_fixture *f)
{
    is_device *dev = f->dev;
    assert_int_equal(dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE), IS_OK);      /* vertex */
    assert_int_equal(dev_set_render_state(dev, IS_RS_ZFUNC, IS_CMP_GREATER), IS_OK);       /* pixel */
    assert_int_equal(dev_set_render_state(dev, IS_RS_SHADEMODE, IS_SHADE_FLAT), IS_OK);    /* both */
    assert_int_equal(dev_set_viewport(dev, &test_vp), IS_OK);
    assert_int_equal(dev_set_stream_source(dev, 1, f->vb, 16, 16), IS_OK);
    assert_int_equal(dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 3), IS_OK);
    assert_int_equal(dev_set_indices(dev, f->ib), IS_OK);
    assert_int_equal(dev_set_vertex_declaration(dev, f->decl), IS_OK);
    assert_int_equal(dev_set_vertex_shader(dev, &vs_a), IS_OK);
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, 7, test_c, 1), IS_OK);
    assert_int_equal(dev_set_texture(dev, 3, f->tex), IS_OK);
    assert_int_equal(dev_set_sampler_state(dev, 3, IS_SAMP_ADDRESSU, IS_TADDRESS_CLAMP), IS_OK);   /* pixel */
    assert_int_equal(dev_set_sampler_state(dev, IS_VERTEXTEXTURESAMPLER(1), IS_SAMP_DMAPOFFSET, 9), IS_OK);
}

/* Which parts of the test data a check expects (else the defaults). */
enum { P_CULL = 1, P_ZFUNC = 2, P_SHADE = 4, P_VIEWPORT = 8, P_SOURCE = 16, P_FREQ = 32, P_IB = 64, P_DECL = 128,
       P_VS = 256, P_CONST = 512, P_TEX = 1024, P_PSAMP = 2048, P_VSAMP = 4096, P_ALL = 8191 };

/* The device holds the test data in the parts of `which`, the defaults in the others. */
static void check_state(const sb_fixture *f, unsigned which)
{
    const is_device *dev = f->dev;
    uint32_t v;
    assert_int_equal(dev_get_render_state(dev, IS_RS_CULLMODE, &v), IS_OK);
    assert_int_equal(v, which & P_CULL ? IS_CULL_NONE : IS_CULL_CCW);
    assert_int_equal(dev_get_render_state(dev, IS_RS_ZFUNC, &v), IS_OK);
    assert_int_equal(v, which & P_ZFUNC ? IS_CMP_GREATER : IS_CMP_LESSEQUAL);
    assert_int_equal(dev_get_render_state(dev, IS_RS_SHADEMODE, &v), IS_OK);
    assert_int_equal(v, which & P_SHADE ? IS_SHADE_FLAT : IS_SHADE_GOURAUD);
    is_viewport vp;
    assert_int_equal(dev_get_viewport(dev, &vp), IS_OK);
    const is_viewport full = {0, 0, 16, 16, 0, 1};
    assert_memory_equal(&vp, which & P_VIEWPORT ? &test_vp : &full, sizeof vp);
    is_vertex_buffer *vb;
    unsigned off, stride;
    assert_int_equal(dev_get_stream_source(dev, 1, &vb, &off, &stride), IS_OK);
    if (which & P_SOURCE) assert_true(vb == f->vb && off == 16 && stride == 16);
    else assert_true(vb == NULL && off == 0 && stride == 0);
    assert_int_equal(dev_get_stream_source_freq(dev, 1, &v), IS_OK);
    assert_int_equal(v, which & P_FREQ ? IS_STREAMSOURCE_INSTANCEDATA | 3 : 1u);
    is_index_buffer *ib;
    assert_int_equal(dev_get_indices(dev, &ib), IS_OK);
    assert_ptr_equal(ib, which & P_IB ? f->ib : NULL);
    is_vertex_declaration *decl;
    assert_int_equal(dev_get_vertex_declaration(dev, &decl), IS_OK);
    assert_ptr_equal(decl, which & P_DECL ? f->decl : NULL);
    const is_vertex_shader *vs;
    assert_int_equal(dev_get_vertex_shader(dev, &vs), IS_OK);
    assert_ptr_equal(vs, which & P_VS ? &vs_a : NULL);
    float c[4];
    const float zero[4] = {0};
    assert_int_equal(dev_get_vertex_shader_constant_f(dev, 7, c, 1), IS_OK);
    assert_memory_equal(c, which & P_CONST ? test_c : zero, sizeof c);
    is_texture *t;
    assert_int_equal(dev_get_texture(dev, 3, &t), IS_OK);
    assert_ptr_equal(t, which & P_TEX ? f->tex : NULL);
    assert_int_equal(dev_get_sampler_state(dev, 3, IS_SAMP_ADDRESSU, &v), IS_OK);
    assert_int_equal(v, which & P_PSAMP ? IS_TADDRESS_CLAMP : IS_TADDRESS_WRAP);
    assert_int_equal(dev_get_sampler_state(dev, IS_VERTEXTEXTURESAMPLER(1), IS_SAMP_DMAPOFFSET, &v), IS_OK);
    assert_int_equal(v, which & P_VSAMP ? 9u : 0u);
}

/* Wine's test_begin_end_state_block: Begin twice fails, End hands out a block, End again fails and leaves its
 * output alone. */
static void test_begin_end(void **state)
{
    (void)state;
    sb_fixture f = fixture();
    is_state_block *sb = (is_state_block *)0x1, *none = (is_state_block *)0xdeadbeef;
    assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
    assert_int_equal(dev_begin_state_block(f.dev), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_end_state_block(f.dev, NULL), IS_ERR_INVALIDCALL);   /* still recording */
    assert_int_equal(dev_end_state_block(f.dev, &sb), IS_OK);
    assert_true(sb != NULL && sb != (is_state_block *)0x1);
    assert_int_equal(dev_end_state_block(f.dev, &none), IS_ERR_INVALIDCALL);
    assert_ptr_equal(none, (is_state_block *)0xdeadbeef);
    sb_release(sb);
    fixture_free(&f);
}

/* Recording leaves the device alone (the getters read the device: defaults); a recorded block released unapplied
 * changes nothing (Wine's "abort" chain); applied, it sets everything that was recorded (the "apply" chain). */
static void test_record_apply(void **state)
{
    (void)state;
    sb_fixture f = fixture();
    is_state_block *sb;
    assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
    set_test_data(&f);
    check_state(&f, 0);
    assert_int_equal(dev_end_state_block(f.dev, &sb), IS_OK);
    check_state(&f, 0);
    sb_release(sb);
    check_state(&f, 0);
    assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
    set_test_data(&f);
    assert_int_equal(dev_end_state_block(f.dev, &sb), IS_OK);
    assert_int_equal(sb_apply(sb), IS_OK);
    check_state(&f, P_ALL);
    sb_release(sb);
    check_state(&f, P_ALL);   /* releasing a block leaves the device as it is */
    fixture_free(&f);
}

/* Wine's "capture / re-apply" chain: a recorded block captures the device's current values of what it holds (the
 * defaults here), the test data is then set, and applying the block brings the defaults back. */
static void test_capture_reapply(void **state)
{
    (void)state;
    sb_fixture f = fixture();
    is_state_block *sb;
    assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
    set_test_data(&f);
    assert_int_equal(dev_end_state_block(f.dev, &sb), IS_OK);
    assert_int_equal(sb_capture(sb), IS_OK);
    check_state(&f, 0);
    set_test_data(&f);
    check_state(&f, P_ALL);
    assert_int_equal(sb_apply(sb), IS_OK);
    check_state(&f, 0);
    sb_release(sb);
    fixture_free(&f);
}

/* A recorded block holds only what was set while recording: the rest of the device is left as it is. */
static void test_recorded_holds_only_what_was_set(void **state)
{
    (void)state;
    sb_fixture f = fixture();
    is_state_block *sb;
    assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_ZFUNC, IS_CMP_GREATER), IS_OK);
    assert_int_equal(dev_set_vertex_shader_constant_f(f.dev, 7, test_c, 1), IS_OK);
    assert_int_equal(dev_set_stream_source(f.dev, 1, f.vb, 16, 16), IS_OK);
    assert_int_equal(dev_end_state_block(f.dev, &sb), IS_OK);
    set_test_data(&f);
    const is_viewport vp = {0, 0, 16, 16, 0, 1};
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_ZFUNC, IS_CMP_ALWAYS), IS_OK);
    assert_int_equal(dev_set_stream_source(f.dev, 1, NULL, 0, 0), IS_OK);
    float zero[4] = {0};
    assert_int_equal(dev_set_vertex_shader_constant_f(f.dev, 7, zero, 1), IS_OK);
    assert_int_equal(dev_set_viewport(f.dev, &vp), IS_OK);
    assert_int_equal(sb_apply(sb), IS_OK);
    check_state(&f, P_ALL & ~P_VIEWPORT);   /* ZFUNC, the constant and stream 1 from the block, the rest as set */
    float c8[4];
    assert_int_equal(dev_get_vertex_shader_constant_f(f.dev, 8, c8, 1), IS_OK);
    assert_memory_equal(c8, zero, sizeof c8);   /* c8 was not recorded */
    sb_release(sb);
    fixture_free(&f);
}

/* CreateStateBlock captures D3D9's list for its type: applied over the test data, a PIXELSTATE block restores the
 * pixel states (ZFUNC, SHADEMODE, the pixel sampler's state), a VERTEXSTATE block the vertex states (CULLMODE,
 * SHADEMODE, the vertex sampler's DMAPOFFSET, declaration, shader, constants, frequencies), ALL everything. */
static void test_create_types(void **state)
{
    (void)state;
    const struct { is_state_block_type type; unsigned restores; } cases[] = {
        {IS_SBT_PIXELSTATE, P_ZFUNC | P_SHADE | P_PSAMP},
        {IS_SBT_VERTEXSTATE, P_CULL | P_SHADE | P_VSAMP | P_DECL | P_VS | P_CONST | P_FREQ},
        {IS_SBT_ALL, P_ALL},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        sb_fixture f = fixture();
        is_state_block *sb;
        assert_int_equal(dev_create_state_block(f.dev, cases[k].type, &sb), IS_OK);
        set_test_data(&f);
        assert_int_equal(sb_apply(sb), IS_OK);
        check_state(&f, P_ALL & ~cases[k].restores);
        /* Capture takes the device's values into the block: applying it again changes nothing */
        assert_int_equal(sb_capture(sb), IS_OK);
        set_test_data(&f);
        assert_int_equal(sb_apply(sb), IS_OK);
        check_state(&f, P_ALL & ~cases[k].restores);
        sb_release(sb);
        fixture_free(&f);
    }
}

static void ps_a_main(const is_ps_constants *c, const is_ps_input *in, is_ps_output *out) { (void)c, (void)in, (void)out; }
static const is_pixel_shader ps_a = {"a", ps_a_main, 0};

/* The pixel shader and its constants: recorded into a block (the device keeps its own), in PIXELSTATE and ALL
 * blocks, not in VERTEXSTATE ones. */
static void test_pixel_shader(void **state)
{
    (void)state;
    sb_fixture f = fixture();
    const float one[4] = {1, 2, 3, 4}, two[4] = {5, 6, 7, 8};
    const is_pixel_shader *got;
    float c[4];
    assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
    assert_int_equal(dev_set_pixel_shader(f.dev, &ps_a), IS_OK);
    assert_int_equal(dev_set_pixel_shader_constant_f(f.dev, 7, one, 1), IS_OK);
    is_state_block *rec;
    assert_int_equal(dev_end_state_block(f.dev, &rec), IS_OK);
    assert_int_equal(dev_get_pixel_shader(f.dev, &got), IS_OK);
    assert_null(got);   /* recording left the device alone */
    assert_int_equal(dev_get_pixel_shader_constant_f(f.dev, 7, c, 1), IS_OK);
    assert_true(c[0] == 0.0f);
    assert_int_equal(sb_apply(rec), IS_OK);
    assert_int_equal(dev_get_pixel_shader(f.dev, &got), IS_OK);
    assert_ptr_equal(got, &ps_a);
    assert_int_equal(dev_get_pixel_shader_constant_f(f.dev, 7, c, 1), IS_OK);
    assert_memory_equal(c, one, sizeof c);
    const struct { is_state_block_type type; bool holds; } cases[] = {
        {IS_SBT_PIXELSTATE, true}, {IS_SBT_ALL, true}, {IS_SBT_VERTEXSTATE, false}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        is_state_block *sb;
        assert_int_equal(dev_set_pixel_shader(f.dev, &ps_a), IS_OK);
        assert_int_equal(dev_set_pixel_shader_constant_f(f.dev, 7, one, 1), IS_OK);
        assert_int_equal(dev_create_state_block(f.dev, cases[k].type, &sb), IS_OK);
        assert_int_equal(dev_set_pixel_shader(f.dev, NULL), IS_OK);
        assert_int_equal(dev_set_pixel_shader_constant_f(f.dev, 7, two, 1), IS_OK);
        assert_int_equal(sb_apply(sb), IS_OK);
        assert_int_equal(dev_get_pixel_shader(f.dev, &got), IS_OK);
        assert_ptr_equal(got, cases[k].holds ? &ps_a : NULL);
        assert_int_equal(dev_get_pixel_shader_constant_f(f.dev, 7, c, 1), IS_OK);
        assert_memory_equal(c, cases[k].holds ? one : two, sizeof c);
        sb_release(sb);
    }
    sb_release(rec);
    fixture_free(&f);
}

/* The scissor rectangle and the clip planes: recorded into a block, held by ALL blocks only. */
static void test_scissor_and_clip_planes(void **state)
{
    (void)state;
    sb_fixture f = fixture();
    const is_rect a = {1, 2, 3, 4}, b = {5, 6, 7, 8};
    const float pa[4] = {1, 0, 0, 0.5f}, pb[4] = {0, 1, 0, -0.5f};
    is_rect r;
    float p[4];
    assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
    assert_int_equal(dev_set_scissor_rect(f.dev, &a), IS_OK);
    assert_int_equal(dev_set_clip_plane(f.dev, 2, pa), IS_OK);
    is_state_block *rec;
    assert_int_equal(dev_end_state_block(f.dev, &rec), IS_OK);
    assert_int_equal(dev_get_scissor_rect(f.dev, &r), IS_OK);
    assert_int_not_equal(r.left, a.left);   /* the device kept its own */
    assert_int_equal(sb_apply(rec), IS_OK);
    assert_int_equal(dev_get_scissor_rect(f.dev, &r), IS_OK);
    assert_memory_equal(&r, &a, sizeof r);
    assert_int_equal(dev_get_clip_plane(f.dev, 2, p), IS_OK);
    assert_memory_equal(p, pa, sizeof p);
    const struct { is_state_block_type type; bool holds; } cases[] = {
        {IS_SBT_ALL, true}, {IS_SBT_PIXELSTATE, false}, {IS_SBT_VERTEXSTATE, false}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        is_state_block *sb;
        assert_int_equal(dev_set_scissor_rect(f.dev, &a), IS_OK);
        assert_int_equal(dev_set_clip_plane(f.dev, 2, pa), IS_OK);
        assert_int_equal(dev_create_state_block(f.dev, cases[k].type, &sb), IS_OK);
        assert_int_equal(dev_set_scissor_rect(f.dev, &b), IS_OK);
        assert_int_equal(dev_set_clip_plane(f.dev, 2, pb), IS_OK);
        assert_int_equal(sb_apply(sb), IS_OK);
        assert_int_equal(dev_get_scissor_rect(f.dev, &r), IS_OK);
        assert_memory_equal(&r, cases[k].holds ? &a : &b, sizeof r);
        assert_int_equal(dev_get_clip_plane(f.dev, 2, p), IS_OK);
        assert_memory_equal(p, cases[k].holds ? pa : pb, sizeof p);
        sb_release(sb);
    }
    sb_release(rec);
    fixture_free(&f);
}

/* While a block is recorded, CreateStateBlock, Capture and Apply are refused; unknown types, NULL outputs and NULL
 * blocks too; dev_reset drops the recording. */
static void test_refusals(void **state)
{
    (void)state;
    sb_fixture f = fixture();
    is_state_block *sb, *other = (is_state_block *)0x1;
    assert_int_equal(dev_create_state_block(f.dev, IS_SBT_ALL, &sb), IS_OK);
    assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
    assert_int_equal(dev_create_state_block(f.dev, IS_SBT_ALL, &other), IS_ERR_INVALIDCALL);
    assert_null(other);
    assert_int_equal(sb_capture(sb), IS_ERR_INVALIDCALL);
    assert_int_equal(sb_apply(sb), IS_ERR_INVALIDCALL);
    assert_true(strlen(dev_last_error(f.dev)) > 0);
    dev_reset(f.dev);   /* the recording goes */
    assert_int_equal(dev_end_state_block(f.dev, &other), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_state_block(f.dev, (is_state_block_type)0, &other), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_state_block(f.dev, (is_state_block_type)4, &other), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_create_state_block(f.dev, IS_SBT_ALL, NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(sb_capture(NULL), IS_ERR_INVALIDCALL);
    assert_int_equal(sb_apply(NULL), IS_ERR_INVALIDCALL);
    sb_release(NULL);
    /* a refused setter records nothing */
    assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_CULLMODE, 42), IS_ERR_INVALIDCALL);
    assert_int_equal(dev_end_state_block(f.dev, &other), IS_OK);
    assert_int_equal(dev_set_render_state(f.dev, IS_RS_CULLMODE, IS_CULL_NONE), IS_OK);
    assert_int_equal(sb_apply(other), IS_OK);
    check_state(&f, P_CULL);
    sb_release(other);
    sb_release(sb);
    fixture_free(&f);
}

/* A buffer, declaration or texture released while a block holds it is dropped from the block (Apply binds nothing
 * there: no dangling pointer); a block released after its device is destroyed is safe (ASan checks both). */
static void test_release_order(void **state)
{
    (void)state;
    sb_fixture f = fixture();
    set_test_data(&f);
    is_state_block *sb, *rec;
    assert_int_equal(dev_create_state_block(f.dev, IS_SBT_ALL, &sb), IS_OK);
    assert_int_equal(dev_begin_state_block(f.dev), IS_OK);
    assert_int_equal(dev_set_stream_source(f.dev, 2, f.vb, 0, 16), IS_OK);
    vb_release(f.vb), f.vb = NULL;   /* while recording: dropped from the recorded block too */
    assert_int_equal(dev_end_state_block(f.dev, &rec), IS_OK);
    tex_release(f.tex), f.tex = NULL;
    decl_release(f.decl), f.decl = NULL;
    assert_int_equal(sb_apply(sb), IS_OK);
    assert_int_equal(sb_apply(rec), IS_OK);
    is_vertex_buffer *vb;
    unsigned off, stride;
    assert_int_equal(dev_get_stream_source(f.dev, 1, &vb, &off, &stride), IS_OK);
    assert_true(vb == NULL && off == 16 && stride == 16);
    assert_int_equal(dev_get_stream_source(f.dev, 2, &vb, &off, &stride), IS_OK);
    assert_null(vb);
    is_texture *t;
    assert_int_equal(dev_get_texture(f.dev, 3, &t), IS_OK);
    assert_null(t);
    is_vertex_declaration *d;
    assert_int_equal(dev_get_vertex_declaration(f.dev, &d), IS_OK);
    assert_null(d);
    is_device *dev = f.dev;
    ib_release(f.ib);
    dev_destroy(dev);
    assert_int_equal(sb_apply(sb), IS_ERR_INVALIDCALL);   /* its device is gone */
    sb_release(sb);
    sb_release(rec);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_begin_end),         cmocka_unit_test(test_record_apply),
        cmocka_unit_test(test_capture_reapply),   cmocka_unit_test(test_recorded_holds_only_what_was_set),
        cmocka_unit_test(test_create_types),      cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_release_order),     cmocka_unit_test(test_pixel_shader),
        cmocka_unit_test(test_scissor_and_clip_planes),
    };
    return cmocka_run_group_tests_name("stateblock", tests, NULL, NULL);
}
