/* tess/fetch.c -- the device's fetch done on the CPU (tess/tess.h): the input registers a patch shader gets for
 * one grid point of one instance, for evaluating a patch outside a draw (OBJ export, tests, the inspector). */
#include "tess_internal.h"

/* PN-AEN's neighbour normals into the registers of vs_nadj_regs (for evaluating outside a draw). */
static void set_nadj_regs(is_vs_input *in, const float3 nadj[3][2])
{
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 2; j++) {
            const vs_reg r = vs_nadj_regs[k][j];
            float4 *reg = r.usage == IS_DECLUSAGE_TEXCOORD ? &in->texcoord[r.usage_index]
                          : r.usage == IS_DECLUSAGE_NORMAL ? &in->normal[r.usage_index] : &in->tangent[r.usage_index];
            *reg = f4_of(nadj[k][j], 1.0f);
        }
}

/* The input registers the device would fetch for grid point b of instance inst (Listing 1.1.2's layout). */
void tess_input_from_instance(const is_patch_instance *inst, const float3 (*nadj)[2], float3 b, is_vs_input *in)
{
    if (!inst || !in) {   /* nothing to fetch: the defaults */
        if (in) for (size_t k = 0; k < sizeof *in / sizeof(float4); k++) ((float4 *)in)[k] = f4(0, 0, 0, 1);
        return;
    }
    float4 *r = (float4 *)in;
    for (size_t k = 0; k < sizeof *in / sizeof(float4); k++) r[k] = f4(0, 0, 0, 1);
    in->position[0] = f4_of(b, 1.0f);
    for (int k = 0; k < 3; k++) {
        in->texcoord[VS_IN_V0 + k] = f4_of(inst->v[k], 1.0f);
        in->texcoord[VS_IN_N0 + k] = f4_of(inst->n[k], 1.0f);
        in->texcoord[VS_IN_OPP0 + k] = f4_of(inst->opp[k], 1.0f);
        in->texcoord[VS_IN_T0 + k] = f4(inst->t[k].x, inst->t[k].y, 0.0f, 1.0f);
    }
    in->texcoord[VS_IN_ID] = f4(inst->instance_id, 0.0f, 0.0f, 1.0f);
    if (nadj) set_nadj_regs(in, nadj);
}
