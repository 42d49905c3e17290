/* tests/util/raster_util.c -- rasterizer states shared by the raster tests. */
#include "raster_util.h"

#include <string.h>

rs_state test_rs_defaults(int w, int h)
{
    rs_state st;
    memset(&st, 0, sizeof st);
    st.cull_mode = RS_CULL_CCW;
    st.fill_mode = RS_FILL_SOLID;
    st.shade_mode = RS_SHADE_GOURAUD;
    st.z_enable = true;
    st.z_write = true;
    st.z_func = RS_CMP_LESSEQUAL;
    st.src_blend = RS_BLEND_ONE;
    st.dst_blend = RS_BLEND_ZERO;
    st.multisample = true;
    st.attr_mask = 1u << RS_ATTR_COLOR0;
    st.viewport = (rs_viewport){0, 0, w, h, 0.0f, 1.0f};
    return st;
}

rs_state test_rs_additive(int w, int h)
{
    rs_state st = test_rs_defaults(w, h);
    st.cull_mode = RS_CULL_NONE;
    st.z_enable = false;
    st.z_write = false;
    st.blend_enable = true;
    st.dst_blend = RS_BLEND_ONE;
    return st;
}

void test_rs_stats_add(rs_stats *sum, const rs_stats *s)
{
    sum->prims_in += s->prims_in, sum->prims_culled += s->prims_culled, sum->prims_drawn += s->prims_drawn;
    sum->prims_clipped_away += s->prims_clipped_away, sum->prims_degenerate += s->prims_degenerate;
    sum->samples_tested += s->samples_tested, sum->samples_written += s->samples_written;
}
