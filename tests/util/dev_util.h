/* tests/util/dev_util.h -- a device set up to draw a few vertices with the fixed vertex shader, for the API tests
 * of the device's stages (inspector, pixel shaders).
 *
 * Conventions: asserts (cmocka) on any failure; the buffer and declaration it makes hold the device and are the
 * caller's to release after dev_destroy. */
#ifndef INSTESS_TEST_DEV_UTIL_H
#define INSTESS_TEST_DEV_UTIL_H

#include "../../core/core.h"

/* A w x h device of `samples` per pixel drawing the `bytes` of verts (vertices of `stride` bytes, declaration
 * el) with the fixed vertex shader under identity matrices and diffuse colour `diffuse`, culling off; its vertex
 * buffer and declaration into *vb and *decl. */
is_device *tu_fixed_device(int w, int h, int samples, const void *verts, unsigned bytes, unsigned stride,
                           const is_vertex_element *el, float4 diffuse, is_vertex_buffer **vb,
                           is_vertex_declaration **decl);

/* dev_destroy(dev), then release *vb and *decl (which hold the device's struct until then) and set them NULL. */
void tu_device_destroy(is_device *dev, is_vertex_buffer **vb, is_vertex_declaration **decl);

#endif
