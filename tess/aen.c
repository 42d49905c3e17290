/* tess/aen.c -- PN-AEN's extra per-instance stream (tess/tess.h): the neighbour's normals at each edge's two
 * ends, from the mesh's welded edges. */
#include "tess_internal.h"

#include <stdlib.h>
#include <string.h>

/* The normal triangle u has at the vertex welded to w (fallback: `own`). */
static float3 normal_at(const is_mesh *m, uint32_t u, uint32_t w, float3 own)
{
    for (int c = 0; c < 3; c++)
        if (m->welded[3 * (size_t)u + c] == w) return m->normals[m->indices[3 * (size_t)u + c]];
    return own;
}

/* Fill nadj[t][k][j] = the normal that the triangle across edge k has at corner (k + j) % 3 of triangle t; an
 * edge without exactly one neighbour (boundary, non-manifold) gets t's own normals.  Returns 0 or -1. */
int tess_adjacent_normals(const is_mesh *m, float3 (*nadj)[3][2])
{
    if (!m || !nadj || (m->n_triangles && (!m->edges || !m->tri_edge))) return -1;
    for (size_t t = 0; t < m->n_triangles; t++)
        for (uint32_t k = 0; k < 3; k++) {
            const is_mesh_edge *E = &m->edges[m->tri_edge[3 * t + k]];
            uint32_t other = E->n_faces == 2 ? (E->faces[0] == t ? E->faces[1] : E->faces[0]) : (uint32_t)t;
            for (int c = 0; c < 2; c++) {
                size_t corner = 3 * t + (k + (uint32_t)c) % 3;
                float3 own = m->normals[m->indices[corner]];
                nadj[t][k][c] = other == t ? own : normal_at(m, other, m->welded[corner], own);
            }
        }
    return 0;
}

/* One triangle's neighbour normals in, those of its renumbering by p (tess_permute_instance) out. */
void tess_permute_adjacent_normals(const float3 in[3][2], const uint8_t p[3], float3 out[3][2])
{
    if (!in || !out) return;
    if (!tess_is_permutation(p)) {   /* as tess_permute_instance: the normals as they are */
        memcpy(out, in, sizeof(float3[3][2]));
        return;
    }
    for (int k = 0; k < 3; k++) {
        const int x = p[k], y = p[(k + 1) % 3], old = y == (x + 1) % 3 ? x : y; /* the edge joining x, y */
        for (int j = 0; j < 2; j++) /* the corner p[k + j] of the old edge is (old + c) % 3 */
            out[k][j] = in[old][(p[(k + j) % 3] - old + 3) % 3];
    }
}

/* adjacent_normals for the instances of an adaptive draw (a's order and renumbering); 0 or -1. */
static int permuted_adjacent_normals(const is_mesh *m, const tess_adaptive *a, float3 (*out)[3][2])
{
    float3 (*nadj)[3][2] = malloc(m->n_triangles * sizeof *nadj);
    if (!nadj || tess_adjacent_normals(m, nadj) != 0) return free(nadj), -1;
    for (size_t i = 0; i < m->n_triangles; i++)
        tess_permute_adjacent_normals((const float3(*)[2])nadj[a->tri[i]], a->perm[i], out[i]);
    free(nadj);
    return 0;
}

/* Bind stream 2 (INSTANCEDATA | 1) with the neighbour normals (a: in an adaptive draw's order) and a declaration that adds vs_nadj_regs to
 * Listing 1.1.2's; replaces the declaration of tess_bind_instanced. */
is_result tess_bind_adjacent_normals(is_device *dev, const is_mesh *m, tess_resources *r, const tess_adaptive *a)
{
    if (!dev || !m || !r || !m->n_triangles) return IS_ERR_INVALIDCALL;
    vb_release(r->vb2), r->vb2 = NULL;   /* (a second call: the first one's stream 2 replaced) */
    is_result e = dev_create_vertex_buffer(dev, m->n_triangles * sizeof(float3[3][2]), &r->vb2);
    if (e != IS_OK) return e;
    if (a ? permuted_adjacent_normals(m, a, vb_lock(r->vb2)) : tess_adjacent_normals(m, vb_lock(r->vb2))) return IS_ERR_OUTOFMEMORY;
    is_vertex_element el[MESH_PATCH_DECLARATION_COUNT + 6];
    size_t n = 0;
    while (mesh_patch_declaration[n].stream != 0xFF) el[n] = mesh_patch_declaration[n], n++;
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 2; j++)
            el[n++] = (is_vertex_element){2, (uint16_t)((k * 2 + j) * sizeof(float3)), IS_DECLTYPE_FLOAT3, 0,
                                          vs_nadj_regs[k][j].usage, vs_nadj_regs[k][j].usage_index};
    el[n] = (is_vertex_element)IS_DECL_END;
    decl_release(r->decl);
    r->decl = NULL;
    e = dev_create_vertex_declaration(dev, el, &r->decl);
    if (e != IS_OK) return e;
    dev_set_vertex_declaration(dev, r->decl);
    dev_set_stream_source(dev, 2, r->vb2, 0, sizeof(float3[3][2]));
    dev_set_stream_source_freq(dev, 2, IS_STREAMSOURCE_INSTANCEDATA | 1u);
    return IS_OK;
}

