/* raster/line.c -- lines and points inside one tile.  A line lights one pixel per pixel centre crossed on its
 * major axis (|dx| >= |dy|: x-major), the minor pixel being the nearest pixel centre of the exact line (see
 * rs_line_minor); the end pixel is left out (half-open, like D3DRS_LASTPIXEL = FALSE), so a closed loop of
 * edges lights each vertex once.  Lines and points cover every sample of their pixels, with one depth per
 * pixel; attributes and depth are interpolated along the line (perspective-correct, at the pixel's major
 * coordinate). */
#include "raster_internal.h"

void rs_line_tile(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a)
{
    const rs_line *l = &p->u.l;
    int x0 = p->x0 > t->x0 ? p->x0 : t->x0, x1 = p->x1 < t->x1 - 1 ? p->x1 : t->x1 - 1;
    int y0 = p->y0 > t->y0 ? p->y0 : t->y0, y1 = p->y1 < t->y1 - 1 ? p->y1 : t->y1 - 1;
    if (x0 > x1 || y0 > y1) return;
    int i0 = l->xmajor ? x0 : y0, i1 = l->xmajor ? x1 : y1;
    int n0 = l->xmajor ? y0 : x0, n1 = l->xmajor ? y1 : x1;
    unsigned full = (1u << j->samples) - 1u;
    for (int i = i0; i <= i1; i++) {
        int64_t n = rs_line_minor(l, i);
        if (n < n0 || n > n1) continue;
        float tt = (float)((int64_t)i * RS_SUB - l->m0) / (float)l->dm;
        tt = tt > 0.0f ? (tt < 1.0f ? tt : 1.0f) : 0.0f;
        float z = l->z0 + tt * l->dz;
        float b1 = tt * l->w1 / ((1.0f - tt) * l->w0 + tt * l->w1);
        int x = l->xmajor ? i : (int)n, y = l->xmajor ? (int)n : i;
        rs_frag_const_z(j, t, x, y, full, z, a, b1, 0.0f);
    }
}

void rs_point_tile(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a)
{
    if (p->x0 < t->x0 || p->x0 >= t->x1 || p->y0 < t->y0 || p->y0 >= t->y1) return;
    rs_frag_const_z(j, t, p->x0, p->y0, (1u << j->samples) - 1u, p->u.p.z, a, 0.0f, 0.0f);
}
