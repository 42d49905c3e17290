/* cli/instancing.c -- the scene layer's buffers of tessellation through instancing (cli/scene.h): the grid in
 * stream 0, one instance per mesh triangle in stream 1.  A file of its own, with no image code, so that a
 * program that only draws (build/bench) does not link the image library. */
#include "scene.h"

#include <string.h>

void scene_resources_free(scene_resources *r)
{
    vb_release(r->vb0);
    vb_release(r->vb1);
    vb_release(r->vb2);
    ib_release(r->ib);
    decl_release(r->decl);
    memset(r, 0, sizeof *r);
}

is_result scene_index_buffer(is_device *dev, const uint32_t *idx, size_t n, size_t max_index, is_index_buffer **out)
{
    bool small = max_index < 65536;
    is_result r = dev_create_index_buffer(dev, n * (small ? 2 : 4), small ? IS_FMT_INDEX16 : IS_FMT_INDEX32, out);
    if (r != IS_OK) return r;
    void *p = ib_lock(*out);
    for (size_t k = 0; k < n; k++) {
        if (small) ((uint16_t *)p)[k] = (uint16_t)idx[k];
        else ((uint32_t *)p)[k] = idx[k];
    }
    ib_unlock(*out);
    return IS_OK;
}

is_result scene_bind_instanced(is_device *dev, const is_mesh *m, const core_grid *g, scene_resources *r)
{
    is_result e = dev_create_vertex_buffer(dev, g->n_points * sizeof(float3), &r->vb0);
    if (e == IS_OK) e = dev_create_vertex_buffer(dev, m->n_triangles * sizeof(is_patch_instance), &r->vb1);
    if (e == IS_OK) e = scene_index_buffer(dev, g->idx, 3 * g->n_triangles, g->n_points, &r->ib);
    if (e == IS_OK) e = dev_create_vertex_declaration(dev, mesh_patch_declaration, &r->decl);
    if (e != IS_OK) return e;
    memcpy(vb_lock(r->vb0), g->bary, g->n_points * sizeof(float3));
    mesh_build_instances(m, vb_lock(r->vb1));
    dev_set_vertex_declaration(dev, r->decl);
    dev_set_stream_source(dev, 0, r->vb0, 0, sizeof(float3));
    dev_set_stream_source(dev, 1, r->vb1, 0, sizeof(is_patch_instance));
    dev_set_indices(dev, r->ib);
    dev_set_stream_source_freq(dev, 0, IS_STREAMSOURCE_INDEXEDDATA | (uint32_t)m->n_triangles);
    dev_set_stream_source_freq(dev, 1, IS_STREAMSOURCE_INSTANCEDATA | 1u);
    r->n_vertices = (unsigned)g->n_points, r->n_prims = (unsigned)g->n_triangles;
    r->n_instances = (unsigned)m->n_triangles;
    return IS_OK;
}

