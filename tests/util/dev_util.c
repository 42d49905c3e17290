/* tests/util/dev_util.c -- see dev_util.h. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "dev_util.h"
#include "../../vs/vs.h"

is_device *tu_fixed_device(int w, int h, int samples, const void *verts, unsigned bytes, unsigned stride,
                           const is_vertex_element *el, float4 diffuse, is_vertex_buffer **vb,
                           is_vertex_declaration **decl)
{
    char err[256];
    is_device *dev = dev_create(w, h, samples, err, sizeof err);
    assert_non_null(dev);
    assert_int_equal(dev_create_vertex_buffer(dev, bytes, vb), IS_OK);
    memcpy(vb_lock(*vb), verts, bytes);
    vb_unlock(*vb);
    assert_int_equal(dev_create_vertex_declaration(dev, el, decl), IS_OK);
    assert_int_equal(dev_set_vertex_declaration(dev, *decl), IS_OK);
    assert_int_equal(dev_set_stream_source(dev, 0, *vb, 0, stride), IS_OK);
    float4x4 id = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
    is_vs_constants c;
    memset(&c, 0, sizeof c);
    vs_set_constants(&c, &id, &id, diffuse, NULL);
    assert_int_equal(dev_set_vertex_shader_constant_f(dev, 0, &c.c[0].x, 10), IS_OK);
    assert_int_equal(dev_set_vertex_shader(dev, &vs_shader_fixed), IS_OK);
    assert_int_equal(dev_set_render_state(dev, IS_RS_CULLMODE, IS_CULL_NONE), IS_OK);
    return dev;
}

void tu_device_destroy(is_device *dev, is_vertex_buffer **vb, is_vertex_declaration **decl)
{
    dev_destroy(dev);
    vb_release(*vb);
    decl_release(*decl);
    *vb = NULL, *decl = NULL;
}
