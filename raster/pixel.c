/* raster/pixel.c -- D3D9's per-pixel states beyond depth and blending, in the order of the D3D9 pipeline: alpha
 * test (ALPHATESTENABLE, ALPHAFUNC, ALPHAREF) on the pixel's 8-bit alpha, then per sample the stencil test and
 * the depth test with the stencil operations of their outcome (STENCIL*, two-sided with the CCW_ states), depth
 * write, blend, and the colour write mask (COLORWRITEENABLE).  The scissor test is not here: it narrows the
 * job's rectangle (draw.c's make_job), which every path honours.
 *
 * These states are implemented on the reference walk only: make_job turns a job with any of them on into a
 * reference job (rs_state_ext), so the fast paths never see them and cost nothing more when they are off.
 *
 * The alpha test compares the pixel's alpha as written to the target (COLOR0's alpha saturated and rounded to 8
 * bits) with ALPHAREF's low 8 bits: "alpha func ref" (GREATER passes when alpha > ref).  The stencil test is
 * "(ref & mask) func (stencil & mask)" on the 8 bits of the sample's stencil; an operation writes only the bits
 * of STENCILWRITEMASK.  A sample failing the stencil test runs the FAIL operation and nothing else; passing it
 * and failing depth runs ZFAIL; passing both runs PASS, writes depth (ZWRITEENABLE) and colour. */
#include "raster_internal.h"

#include <string.h>

bool rs_state_ext(const rs_state *st, const rs_target *rt)
{
    return st->ps || st->alpha_test || (st->stencil_enable && rt->stencil) || (st->color_write_disable & 0xfu) ||
           st->no_clipping || (st->clip_plane_enable & 0x3fu) || st->pretransformed;
}

unsigned rs_clip_mask(const rs_state *st)
{
    const unsigned guard = 0x3cu;   /* planes 2..5 */
    if (st->no_clipping) return guard;
    unsigned user = st->pretransformed ? 0u : (st->clip_plane_enable & 0x3fu);
    return 0x3fu | user << RS_CLIP_PLANES;
}

/* Does a pass RS_CMP_* f against b (unsigned 8-bit values)? */
static bool cmp8(int f, uint32_t a, uint32_t b)
{
    switch (f) {
    case RS_CMP_NEVER: return false;
    case RS_CMP_LESS: return a < b;
    case RS_CMP_EQUAL: return a == b;
    case RS_CMP_LESSEQUAL: return a <= b;
    case RS_CMP_GREATER: return a > b;
    case RS_CMP_NOTEQUAL: return a != b;
    case RS_CMP_GREATEREQUAL: return a >= b;
    default: return true;
    }
}

/* Stencil value s after operation op with reference ref (8 bits in, 8 bits out). */
static uint32_t stencil_op(int op, uint32_t s, uint32_t ref)
{
    switch (op) {
    case RS_STENCILOP_ZERO: return 0;
    case RS_STENCILOP_REPLACE: return ref & 0xffu;
    case RS_STENCILOP_INCRSAT: return s < 255u ? s + 1u : 255u;
    case RS_STENCILOP_DECRSAT: return s > 0u ? s - 1u : 0u;
    case RS_STENCILOP_INVERT: return ~s & 0xffu;
    case RS_STENCILOP_INCR: return (s + 1u) & 0xffu;
    case RS_STENCILOP_DECR: return (s - 1u) & 0xffu;
    default: return s;   /* KEEP */
    }
}

/* Colour new written over old through the mask: channels in `keep` (a byte mask) keep old. */
static inline uint32_t write_masked(uint32_t new, uint32_t old, uint32_t keep) { return (new & ~keep) | (old & keep); }

/* Bytes of the packed colour kept by a colour write mask that disables channels `disable` (bit c: byte c). */
static uint32_t keep_bytes(uint32_t disable)
{
    uint32_t k = 0;
    for (int c = 0; c < 4; c++)
        if (disable & (1u << c)) k |= 0xffu << (8 * c);
    return k;
}

void rs_ps_lane(const rs_job *j, const float *a, float b1, float b2, rs_vec4 *v)
{
    uint32_t read = j->st->ps_inputs ? j->st->ps_inputs : ~0u;   /* the slots the shader reads */
    for (int i = 0; i < j->n_slots; i++) {
        if (!((read >> j->slot[i]) & 1u)) continue;   /* not read: left 0 */
        const float *p = a + i * RS_ATTR_STRIDE;
        v[j->slot[i]] = (rs_vec4){p[0] + b1 * p[1] + b2 * p[2], p[3] + b1 * p[4] + b2 * p[5],
                                  p[6] + b1 * p[7] + b2 * p[8], p[9] + b1 * p[10] + b2 * p[11]};
    }
}

/* rs_frag_out's body, inline in rs_ps_write (the pixel shader's path) and rs_frag_out. */
static inline __attribute__((always_inline)) void frag_out(const rs_job *j, rs_tile *t, int x, int y, unsigned cov,
                                                           const float *zs, bool back, uint32_t src, const float *a,
                                                           float b1, float b2)
{
    const rs_state *st = j->st;
    t->tested += (uint64_t)__builtin_popcount(cov);
    if (st->alpha_test && !cmp8(st->alpha_func, src >> 24, st->alpha_ref & 0xffu)) return;
    size_t base = rs_tile_index(t, x, y) * (size_t)j->samples;
    float *dep = t->depth + base;
    /* the reference walk draws in the target (raster_tiles gives a job with ext no tile buffers) */
    RS_ASSERT(t->color == j->rt->color && t->ox == 0 && t->oy == 0);
    uint8_t *sten = st->stencil_enable && j->rt->stencil ? j->rt->stencil + base : NULL;
    const rs_stencil_ops *ops = back && st->stencil_two_sided ? &st->stencil_ccw : &st->stencil_cw;
    uint32_t ref = st->stencil_ref & 0xffu, mask = st->stencil_mask & 0xffu, wm = st->stencil_write_mask & 0xffu;
    unsigned pass = 0;
    for (int s = 0; s < j->samples; s++) {
        if (!(cov & (1u << s))) continue;
        bool zp = !st->z_enable || rs_zpass(st->z_func, zs[s], dep[s]);
        if (sten) {
            bool sp = cmp8(ops->func, ref & mask, sten[s] & mask);
            int op = !sp ? ops->fail : (!zp ? ops->zfail : ops->pass);
            sten[s] = (uint8_t)((sten[s] & ~wm) | (stencil_op(op, sten[s], ref) & wm));
            if (!sp) continue;
        }
        if (!zp) continue;
        if (st->z_enable && st->z_write) dep[s] = zs[s];
        pass |= 1u << s;
    }
    if (!pass) return;
    t->written += (uint64_t)__builtin_popcount(pass);
    uint32_t *col = t->color + base, keep = st->color_write_disable & 0xfu ? keep_bytes(st->color_write_disable) : 0;
    for (int s = 0; s < j->samples; s++) {
        if (!(pass & (1u << s))) continue;
        uint32_t v = st->blend_enable ? rs_blend(st->src_blend, st->dst_blend, src, col[s]) : src;
        col[s] = write_masked(v, col[s], keep);
    }
    if (j->rt->n_aov > 0) rs_write_aov(j, a, b1, b2, x, y);
}

/* rs_to8(c.x) | rs_to8(c.y) << 8 | rs_to8(c.z) << 16 | rs_to8(c.w) << 24, four channels at a time: each
 * saturated (NaN to 0), times 255, plus 0.5, truncated -- rs_to8's operations in its order. */
static inline uint32_t pack8(rs_vec4 c)
{
    typedef float v4f __attribute__((vector_size(16)));
    typedef int v4i __attribute__((vector_size(16)));
    const v4f zero = {0, 0, 0, 0}, one = {1, 1, 1, 1}, k255 = {255, 255, 255, 255}, half = {0.5f, 0.5f, 0.5f, 0.5f};
    v4f v = {c.x, c.y, c.z, c.w};
    v4i above = v > zero, below = v < one;   /* all ones where true; both false for NaN */
    v4f sat = (v4f)((((v4i)v & below) | ((v4i)one & ~below)) & above);   /* c > 0 ? (c < 1 ? c : 1) : 0 */
    v4i q = __builtin_convertvector(sat * k255 + half, v4i);
    return (uint32_t)q[0] | (uint32_t)q[1] << 8 | (uint32_t)q[2] << 16 | (uint32_t)q[3] << 24;
}

void rs_frag_ps(const rs_job *j, rs_tile *t, int x, int y, unsigned cov, float *zs, bool back, const rs_ps_quad *q,
                int lane, const float *a, float b1, float b2)
{
    rs_ps_out o;
    memset(&o, 0, sizeof o);
    j->st->ps(j->st->ps_ctx, q, &o);
    rs_ps_write(j, t, x, y, cov, zs, back, &o, lane, a, b1, b2);
}

void rs_ps_write(const rs_job *j, rs_tile *t, int x, int y, unsigned cov, float *zs, bool back, const rs_ps_out *o,
                 int lane, const float *a, float b1, float b2)
{
    if (o->kill & (1u << lane)) return;   /* texkill: the pixel ends here, before any test */
    if (o->depth_written)
        for (int s = 0; s < j->samples; s++) zs[s] = rs_zclamp(o->depth[lane], j->zlo, j->zhi);
    const rs_vec4 c = o->color[lane];
    frag_out(j, t, x, y, cov, zs, back, pack8(c), a, b1, b2);
}

void rs_frag_ext(const rs_job *j, rs_tile *t, int x, int y, unsigned cov, const float *zs, bool back,
                 const float *a, float b1, float b2)
{
    if (j->st->ps) {   /* a line or a point: a quad whose lanes all hold this pixel's inputs */
        rs_ps_quad q;
        memset(&q, 0, sizeof q);
        int lane = (x & 1) + 2 * (y & 1);
        for (int k = 0; k < 4; k++) {
            rs_ps_lane(j, a, b1, b2, q.v[k]);
            q.vpos[k][0] = (float)((x & ~1) + (k & 1)), q.vpos[k][1] = (float)((y & ~1) + (k >> 1));
        }
        q.front = true, q.live = q.need = 1u << lane;
        float z[4] = {zs[0], zs[1], zs[2], zs[3]};
        rs_frag_ps(j, t, x, y, cov, z, back, &q, lane, a, b1, b2);
        return;
    }
    rs_frag_out(j, t, x, y, cov, zs, back, rs_shade_color(j, a, b1, b2), a, b1, b2);
}

void rs_frag_out(const rs_job *j, rs_tile *t, int x, int y, unsigned cov, const float *zs, bool back, uint32_t src,
                 const float *a, float b1, float b2)
{
    frag_out(j, t, x, y, cov, zs, back, src, a, b1, b2);
}
