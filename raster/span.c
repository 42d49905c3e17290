/* raster/span.c -- the fast path of triangle rasterization on 1-sample targets, small triangles: 8 pixels at a
 * time (8 lanes of AVX2), coverage from the edge functions, then depth test, depth write, perspective-correct
 * colour and colour write for the 8 pixels at once -- the same bytes as tri.c's reference walk (span_lanes.h states
 * how).  rs_tri_fast picks the walk per triangle; larger triangles take span_wide.c's interval walk.
 *
 * The walks here:
 *  - small triangles (box at most 8 wide, edge coefficients at most 2^13): no block tests, 32-bit edge values;
 *    boxes of at most 4x8 or 8x2 pixels in the plain modes take the stamp walk: the coverage of the whole box
 *    first, then only its covered pixels packed into the lanes (one pass of 8 for almost every triangle of a
 *    tessellated grid, where the 4x2 walk below drew about a third of its lanes), depth read by a gather and the
 *    passing pixels written by a masked scatter (AVX-512) or by stores of every lane (AVX2); larger boxes go
 *    4x2 pixels at a time (two rows in the 8 lanes) when at most 4 wide, the others one row of 8 lanes;
 *  - rs_tri_run, the grid rows' entry (setup_simd.c's grid_tile): a step's up to 8 triangles, the mode picked once
 *    and each triangle's walk from the set-up lanes (coef_small) and its clipped box, rs_tri_fast only for the rest;
 *    the stamp lanes come with their coverage masks, which grid_tile computes for the whole step at once (grid_cov8:
 *    lanes = triangles, per box position the 8 lanes' edge values stepped by adds, ~7 instructions per position for
 *    8 triangles, over the union of the lanes' boxes), and go straight to the stamp walk's drawing (band_draw);
 *    grid_tile drops the stamp lanes that cover no pixel (~40% of them on scene B) before their planes and
 *    attribute slots.  Measured (per frame, 1 thread, AVX2): B npatch 107.59 -> 98.70 M instructions (run_le
 *    54.02 -> 41.40 M, rs_group_tile 23.72 -> 27.47 M), B smooth 116.77 -> 107.95 M; the per-triangle coverage in
 *    walk_band cost ~100 instructions per stamp triangle, the step's ~170 per step of ~4.4 stamp lanes (the first
 *    version, columns in a loop and the box masks by shifts: 101.08 M).  Then (issue 29 wave 3) the step's arrays in
 *    one struct (rs_run_step) with the stamp lanes' box corners from vertex 0 and in the tile (grid_tile computes
 *    them for the step) and the pitch, broadcast from memory (bcast); instances per colour (white or slot 0); the
 *    steps whose live lanes are all stamp lanes (~74% on scene B) through a loop of band_draw alone (run_stamps);
 *    stamp_pass's plane coefficients broadcast from memory for these lanes (bcf: gcc loaded them early and
 *    broadcast them after the depth test); their masks known non-zero.  B npatch 98.70 -> 93.26 M instructions per
 *    frame (struct and offsets 96.52, stamp-only loop 95.77, colour slot 95.49, out of line 95.31, bcast 94.85,
 *    pitch 94.80, bcf 93.79 (93.63 with bcf in walk_band's instances too, but A npatch +0.04%), masks 93.26),
 *    B smooth 107.95 -> 102.56 M, A and C unchanged (18.36, 28.48 M).  Then a band of more than 8 covered pixels
 *    wholly out of line (band_draw_rt, its first pass included; LESSEQUAL with writes a constant there), so that the
 *    one-pass band keeps no value across its pass (gcc spilled the pitch, Xs and Ys for the later passes, and reloaded
 *    sp), and stamp_pass's lanes below nl by bzhi of the depth test's mask (one instruction; lane_idx < nl took four):
 *    B npatch 93.32 -> 91.86 M (stamps_le 21.02 -> 19.72, run_le 14.51 -> 13.49), B smooth 102.56 -> 101.16 M,
 *    A npatch 18.360 -> 18.369 M (+0.05%: its ~30 bands per frame of 9..16 pixels pay both passes out of line), C
 *    28.485 -> 28.487 M.  (Dropped: the first pass of walk_band's bands kept inline, B 92.78 M (A 18.349); the
 *    8-wide ones' only, B 92.39, A 18.347.)  Then stamp_pass's s, q1, q2 planes after the depth test (gcc broadcast
 *    their coefficients before the gather and spilled two): B npatch 91.86 -> 91.63 M, B smooth
 *    101.16 -> 100.94 M, A npatch 18.369 -> 18.361 M, C npatch 28.485 M.  Then pack16's constants set once
 *    before run_stamps' loop (pk16_loop; gcc rebuilt them by three movabs per triangle): B npatch 91.63 ->
 *    91.39 M (stamps_le 19.59 -> 19.35), B smooth 100.94 -> 100.70 M, A and C unchanged (18.362, 28.485 M); in
 *    run_lanes' loop too: run_le 13.41 -> 13.43, dropped.  Then the store loop's lane index by low_bit (tzcnt
 *    in an asm, 64-bit: gcc put an xor before its own tzcnt and, for a 32-bit index, a zero extension): 9 -> 8
 *    instructions per written pixel, B npatch 91.39 -> 91.08 M (stamps_le 19.35 -> 19.12, run_le 13.41 -> 13.36),
 *    B smooth 100.70 -> 100.38 M, A npatch 18.361, A smooth 18.758, C npatch 28.485 M (that loop is gone since:
 *    stamp_pass writes without a branch per pixel).
 * Each walk is instantiated with the depth state as compile-time constants for the common states (depth test
 * LESSEQUAL or LESS with writes, no blending, no AOV planes) and once with the job's values for the rest;
 * blending and AOV planes go through span8 (per-pixel write-out, as the reference).
 * (Measured on scene B npatch and dropped in wave 3: the tested / written counters kept in locals across a run and
 * added once (96.52 -> 97.25 M: spilled); the barycentrics computed before the test of the pass mask (no change);
 * a counted store loop when every lane passed (95.77 -> 97.39 M); pack32, the 4x8 stamps' positions of more than 4
 * rows without take8 (95.49 -> 95.51 M); col = id - (row << W) (+0.003 M); Xs, Ys and the pitch passed by pointer
 * to stamp_pass (93.79 -> 94.51 M); in the AVX-512 kernel, the stamps whose positions are below 16 read and written
 * by rows -- a masked load per row and a compress for the depth, an expand and a masked store per row for the
 * writes -- instead of the gather and the two scatters (a microbenchmark on AMD EPYC: 6.3 -> 3.4 ns a pass), B npatch
 * 1 thread 8.04 -> 8.21 ms (ten alternated pairs, 1 faster), rows for the read alone 8.37, for the writes alone
 * 8.57: the gather and scatters overlap with the rest of the pass, the rows' masked stores forward worse.)
 * (Measured on scene B and dropped: the job's and tile's constants read once per step into locals or a struct --
 * the run's loop has no registers left for them, the compiler spills them and it costs more than the reloads.
 * Also dropped: passes shared by the stamp lanes of several triangles of a step, issue 29 step 6 -- with ~4 stamp
 * triangles per rs_tri_run call a pass holds 1.9 of them, and the per-triangle overlap test and lane packing cost
 * more than the passes saved: B npatch 120.76 -> 128.9 M instructions per frame; a second version, the coefficients
 * gathered from per-step tables and passes only in steps of 4 or more stamp lanes, gave 120.76 -> 119.82 M and no
 * wall-time gain in three alternated runs, so it was not kept either.  A third, the step's region walked in 4x2
 * blocks -- per block the covering triangle per lane from the edges, per-lane coefficients by permutes --, gave
 * 113.88 -> 135.98 M: a step's covered pixels (15.2 in a union box of 53) fill region blocks no better than each
 * triangle's own stamp, 4.86 block passes per step against 4.37 stamp passes, and each block pays the coverage
 * of several triangles and the permutes; only packing the step's pixels (2.36 passes) would cut the passes.) */
#include "span_lanes.h"

#ifdef __AVX2__

/* ---- the small-triangle walks ---- */

/* The 4x2 walk of a box at most 4 pixels wide (columns gx..gx+3 inside tile t), two rows per step. */
ALWAYS_INLINE void walk_quads(fctx *c, zmode m, const rs_job *j, const rs_tile *t, int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = c->tr;
    const int gx = x0 + 4 <= t->x1 ? x0 : t->x1 - 4;
    const uint32_t X = (uint32_t)((int64_t)gx * RS_SUB - j->cx), Y = (uint32_t)((int64_t)y0 * RS_SUB - j->cy);
    v8u e[3], dy[3];
    edges32(tr, X, Y, quad_col, quad_row, 2, e, dy);
    const unsigned row = ((1u << (x1 - x0 + 1)) - 1u) << (x0 - gx);
    const rows8 r = rows8_at(j, tr, bi((int32_t)((int64_t)gx * RS_SUB - j->cx - tr->vx)) + quad_col * RS_SUB);
    v8i Yl = bi((int32_t)((int64_t)y0 * RS_SUB - j->cy - tr->vy)) + quad_row * RS_SUB;
    size_t o = fidx(c, gx, y0);
    for (int y = y0; y <= y1; y += 2) {
        unsigned box = y + 1 <= y1 ? row | row << 4 : row;
        unsigned cov = box & ~mask_of((v8i)(e[0] | e[1] | e[2])); /* sign bit: some edge < 0 */
        if (cov) {
            ypart yp = ypart_at(j, tr, Yl);
            frag8(c, m, true, cov, o, y + 1 < t->y1 ? o + c->w : o, &r, &yp);
        }
        for (int i = 0; i < 3; i++) e[i] += dy[i];
        Yl += bi(2 * RS_SUB);
        o += 2 * c->w;
    }
}

/* The row walk of a box at most 8 pixels wide: lanes gx..gx+7 inside tile t, one row per step. */
ALWAYS_INLINE void walk_rows(fctx *c, zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a,
                             int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = c->tr;
    const int gx = x0 + 8 <= t->x1 ? x0 : t->x1 - 8;
    const uint32_t X = (uint32_t)((int64_t)gx * RS_SUB - j->cx), Y = (uint32_t)((int64_t)y0 * RS_SUB - j->cy);
    v8u e[3], dy[3];
    edges32(tr, X, Y, lane_idx, bi(0), 1, e, dy);
    const unsigned box = ((1u << (x1 - x0 + 1)) - 1u) << (x0 - gx);
    const rows8 r = rows8_at(j, tr, bi((int32_t)((int64_t)gx * RS_SUB - j->cx - tr->vx)) + lane_idx * RS_SUB);
    int32_t Yr = (int32_t)((int64_t)y0 * RS_SUB - j->cy - tr->vy);
    size_t o = fidx(c, gx, y0);
    for (int y = y0; y <= y1; y++) {
        unsigned cov = box & ~mask_of((v8i)(e[0] | e[1] | e[2])); /* sign bit: some edge < 0 */
        if (cov && m.plain) {
            ypart yp = ypart_at(j, tr, bi(Yr));
            frag8(c, m, false, cov, o, 0, &r, &yp);
        } else if (cov) {
            span8(j, t, p, a, gx, y, cov);
        }
        for (int i = 0; i < 3; i++) e[i] += dy[i];
        Yr += RS_SUB;
        o += c->w;
    }
}

/* ---- the stamp walk: boxes at most 8 wide, plain modes ---- */

/* The positions of the first (at most 8) set bits of *cov, one byte each from the low byte; they are cleared from
 * *cov and their count goes to *n. */
static inline uint64_t take8(uint64_t *cov, int *n)
{
    uint64_t ids = 0, c = *cov;
    int k = 0;
    do {
        ids |= (uint64_t)__builtin_ctzll(c) << (8 * k++);
        c &= c - 1;
    } while (c && k < 8);
    *cov = c, *n = k;
    return ids;
}

/* pack16's constants: the nibbles' low bits, the nibbles' positions, the bytes' low nibbles. */
typedef struct pk16c {
    uint64_t one, idx, low;
} pk16c;
#define PK16C ((pk16c){0x1111111111111111ull, 0xfedcba9876543210ull, 0x0f0f0f0f0f0f0f0full})

/* PK16C for a loop of band_draw: opaque to gcc (an empty asm), so that they are set once before the loop and
 * kept in registers or read by pdep / pext from the stack, not rebuilt by three movabs per triangle. */
static inline pk16c pk16_loop(void)
{
    pk16c k = PK16C;
    __asm__("" : "+r"(k.one), "+r"(k.idx), "+r"(k.low));
    return k;
}

/* The positions of the set bits of the 16-bit mask m (at most 8 of them), one byte each from the low byte, as
 * take8 gives them (k: PK16C or pk16_loop's): _pdep_u64 spreads each bit of m over its nibble (times 0xf),
 * _pext_u64 keeps those nibbles of 0xfedcba9876543210 (each nibble its own position), and the last _pdep_u64
 * widens the 8 low nibbles to bytes.
 * (BMI2's pdep / pext take one instruction each: fast on Intel since Haswell and on AMD since Zen 3, microcoded
 * and slow on Zen 1 and 2.  Measured and not kept: a 256-entry table of byte positions, low byte's then high
 * byte's (+ 8) shifted past them -- B npatch 120.76 -> 121.03 M instructions per frame, +0.2%.) */
static inline uint64_t pack16(unsigned m, pk16c k)
{
    const uint64_t nib = _pext_u64(k.idx, _pdep_u64(m, k.one) * 0xfu);
    return _pdep_u64(nib, k.low);
}

/* *p in every lane, broadcast from memory (one vbroadcastss). */
static inline v8f bcf(const float *p) { return (v8f)_mm256_broadcast_ss(p); }

/* Depth-test (mode m), shade and write nl (1..8) covered pixels of a stamp W = 1 << wbits pixels wide whose
 * corner pixel is at index o of tile t's planes (pitch w) and at Xs, Ys from vertex 0 of triangle tr (1/256 px;
 * w, Xs, Ys in every lane):
 * lane l holds stamp position ids byte l (column id % W, row id / W).  Per lane the x and y parts of the planes as
 * rows8_at and ypart_at give them for that pixel (the same integer offsets, so the same floats: see below) and
 * frag8's operations (pc: the colour slot, NULL: white; alpha always interpolated); the depth is read by a gather,
 * the passing lanes written by a scatter or by stores of every lane (a triangle's pixels are distinct: their order
 * does not matter). */
ALWAYS_INLINE void stamp_pass(zmode m, const rs_job *j, rs_tile *t, const rs_tri *tr, const float *pc, bool vl,
                              int wbits, uint64_t ids, int nl, size_t o, v8i w, v8i Xs, v8i Ys)
{
    const v8i id = (v8i)_mm256_cvtepu8_epi32(_mm_cvtsi64_si128((long long)ids));
    const v8i col = id & bi((1 << wbits) - 1), row = id >> wbits;
    const v8i off = row * w + col;
    /* rows8_at and ypart_at without their sample offsets: on a 1-sample target sox[0] = soy[0] = 0 (draw.c), and
     * fx + 0.0f is fx (fx is an integer times 1/256, never -0) */
    RS_ASSERT(j->sox[0] == 0 && j->soy[0] == 0);
    const float k = 1.0f / RS_SUB;
    const v8f fx = __builtin_convertvector(Xs + (col << RS_SUB_BITS), v8f) * bf(k);
    const v8f fy = __builtin_convertvector(Ys + (row << RS_SUB_BITS), v8f) * bf(k);
    /* (the grid rows' stamp lanes (vl) broadcast the coefficients from memory, bcf: gcc otherwise loads most of
     * them early and broadcasts them later, two instructions each; walk_band's instances keep bf, A npatch +0.04%
     * with bcf) */
#define C(x) (vl ? bcf(&(x)) : bf(x))
    float *dep = t->depth + o;
    unsigned zm = 0xffu;
    v8f z = bf(0.0f);
    if (m.ze) { /* lanes past nl read the stamp's position 0 (id 0): a pixel of the box, so inside the planes */
        const v8f d = (v8f)_mm256_i32gather_ps(dep, (__m256i)off, 4);
        z = zclamp8((C(tr->z[2]) + C(tr->z[0]) * fx) + C(tr->z[1]) * fy, bf(j->zlo), bf(j->zhi));
        zm = mask_of(zpass8(m.zf, z, d));
    }
    t->tested += (uint64_t)nl;
    uint64_t pm = _bzhi_u32(zm, (unsigned)nl); /* lanes below nl (one instruction; lane_idx < nl took four) */
    if (!pm) return;
    t->written += (uint64_t)__builtin_popcountll(pm);
    /* the other planes after the test (their coefficients were broadcast before the gather and spilled) */
    const v8f rr = bf(1.0f) / ((C(tr->s[2]) + C(tr->s[0]) * fx) + C(tr->s[1]) * fy);
    const v8f b1 = ((C(tr->q1[2]) + C(tr->q1[0]) * fx) + C(tr->q1[1]) * fy) * rr;
    const v8f b2 = ((C(tr->q2[2]) + C(tr->q2[0]) * fx) + C(tr->q2[1]) * fy) * rr;
#undef C
    const v8i src = pc ? shade8_l(pc, -1, b1, b2, vl) : bi(-1);
    /* the passing lanes written without a branch per pixel: the loop over pm's bits (~3.5 pixels a triangle on scene
     * B) mispredicted its exit about once a triangle (callgrind's branch model: ~140k mispredictions a frame, a
     * quarter of the frame's).  AVX-512: a masked scatter each (B npatch 10.08 -> 8.76 ms on 1 thread, eight
     * alternated pairs, AMD EPYC); AVX2: the lanes that fail take the last passing lane's offset and values, so
     * that storing every lane writes that pixel again with the same bytes -- lanes 0-3 always, 4-7 when one of
     * them passes (--isa avx2: 10.11 -> 9.63 ms; all 8 always: 9.71 ms). */
#if defined(__AVX512F__) && defined(__AVX512VL__)
    if (m.ze && m.zw) _mm256_mask_i32scatter_ps(dep, (__mmask8)pm, (__m256i)off, (__m256)z, 4);
    _mm256_mask_i32scatter_epi32(t->color + o, (__mmask8)pm, (__m256i)off, (__m256i)src, 4);
#else
    const v8i pass = ((bi((int32_t)pm) >> lane_idx) & bi(1)) != bi(0);
    const v8i hv = bi((int32_t)(63 - __builtin_clzll(pm)));   /* the last passing lane */
    const v8i offw = (v8i)_mm256_blendv_epi8(_mm256_permutevar8x32_epi32((__m256i)off, (__m256i)hv), (__m256i)off,
                                             (__m256i)pass);
    const v8i srcw = (v8i)_mm256_blendv_epi8(_mm256_permutevar8x32_epi32((__m256i)src, (__m256i)hv), (__m256i)src,
                                             (__m256i)pass);
    int32_t ov[8]; /* unaligned: no realignment of the stack for them */
    uint32_t cv[8];
    _mm256_storeu_si256((__m256i *)ov, (__m256i)offw);
    _mm256_storeu_si256((__m256i *)cv, (__m256i)srcw);
    uint32_t *col0 = t->color + o;
    if (m.ze && m.zw) {
        const v8f zw =
            (v8f)_mm256_blendv_ps(_mm256_permutevar8x32_ps((__m256)z, (__m256i)hv), (__m256)z, (__m256)pass);
        float zv[8];
        _mm256_storeu_ps(zv, (__m256)zw);
#pragma GCC unroll 4
        for (int l = 0; l < 4; l++) dep[ov[l]] = zv[l], col0[ov[l]] = cv[l];
        if (pm > 15u)
#pragma GCC unroll 4
            for (int l = 4; l < 8; l++) dep[ov[l]] = zv[l], col0[ov[l]] = cv[l];
    } else {
#pragma GCC unroll 4
        for (int l = 0; l < 4; l++) col0[ov[l]] = cv[l];
        if (pm > 15u)
#pragma GCC unroll 4
            for (int l = 4; l < 8; l++) col0[ov[l]] = cv[l];
    }
#endif
}

/* band_draw_rt's passes in mode m: take8's positions of cov (not 0), 8 per pass. */
ALWAYS_INLINE void band_passes(zmode m, const rs_job *j, rs_tile *t, const rs_tri *tr, const float *pc, bool vl,
                               int wbits, uint64_t cov, size_t o, v8i w, v8i Xs, v8i Ys)
{
    int n;
    do {
        const uint64_t ids = take8(&cov, &n);
        if (vl) stamp_pass(m, j, t, tr, pc, true, 2, ids, n, o, w, Xs, Ys); /* (the grid rows' stamp lanes: 4 wide) */
        else if (wbits == 2) stamp_pass(m, j, t, tr, pc, false, 2, ids, n, o, w, Xs, Ys);
        else stamp_pass(m, j, t, tr, pc, false, 3, ids, n, o, w, Xs, Ys);
    } while (cov);
}

/* The stamp walk's drawing of the covered positions cov (not 0) of a band of more than 8, out of line, the mode m
 * as a value (LESSEQUAL with writes, the grids' mode, as a constant: A npatch +0.05% without): take8's positions,
 * 8 per pass.  The whole band here, its first pass included, so that band_draw's common one-pass band keeps no
 * value across its pass (gcc spilled the pitch, Xs and Ys there for the later passes). */
static __attribute__((noinline)) void band_draw_rt(zmode m, const rs_job *j, rs_tile *t, const rs_tri *tr,
                                                   const float *pc, bool vl, int wbits, uint64_t cov, size_t o,
                                                   v8i w, v8i Xs, v8i Ys)
{
    if (m.ze && m.zw && m.zf == RS_CMP_LESSEQUAL) band_passes(MODE_LE, j, t, tr, pc, vl, wbits, cov, o, w, Xs, Ys);
    else band_passes(m, j, t, tr, pc, vl, wbits, cov, o, w, Xs, Ys);
}

/* The stamp walk's drawing: triangle tr's covered positions cov (bit row * W + column, W = 1 << wbits, of its box
 * whose corner pixel is at index o of tile t's planes and at Xs, Ys from vertex 0 (1/256 px, modulo 2^32), mode m
 * plain; pc: its colour slot, NULL: white) packed into the lanes (pack16, take8) and drawn 8 per pass (stamp_pass,
 * the bands of more than one pass out of line: band_draw_rt); nothing when cov is 0. */
ALWAYS_INLINE void band_draw(zmode m, const rs_job *j, rs_tile *t, const rs_tri *tr, const float *pc, bool vl,
                             int wbits, uint64_t cov, size_t o, v8i w, v8i Xs, v8i Ys, pk16c kc)
{
    if (!cov) return;
    const int n = __builtin_popcountll(cov);
    if (n > 8) { /* more than one pass: out of line */
        band_draw_rt(m, j, t, tr, pc, vl, wbits, cov, o, w, Xs, Ys);
        return;
    }
    int k = n;
    /* the common case, 16 positions: at once (pack16) */
    const uint64_t ids = cov <= 0xffffu ? pack16((unsigned)cov, kc) : take8(&cov, &k);
    stamp_pass(m, j, t, tr, pc, vl, wbits, ids, n, o, w, Xs, Ys);
}

/* The stamp walk of the box [x0, x1] x [y0, y1] of triangle p (in tile t, mode m plain), at most W = 1 << wbits
 * (4 or 8) columns by 64 / W rows (positions row * W + column, below 64; walk_small gives it boxes of at most 4x8
 * or 8x2 pixels).  Coverage first, 8 positions per vector (two rows of 4, or one of 8) with 32-bit edge values
 * (modulo 2^32 as edges32: exact by coef_small), into one 64-bit mask; then band_draw: the covered pixels packed
 * into the lanes, 8 per pass: one pass for almost every small triangle, where the 4x2 walk drew a third of its
 * lanes.  (The grid rows' stamp lanes skip the first half: setup_simd.c's grid_tile computes their masks for a
 * whole step at once.) */
ALWAYS_INLINE void walk_band(zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int wbits,
                             int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = &p->u.t;
    const int vr = wbits == 2 ? 2 : 1; /* rows per vector */
    const v8u Xl = bu((uint32_t)((int64_t)x0 * RS_SUB - j->cx)) +
                   ((wbits == 2 ? (v8u)quad_col : (v8u)lane_idx) << RS_SUB_BITS);
    const v8u Yl = bu((uint32_t)((int64_t)y0 * RS_SUB - j->cy)) + ((wbits == 2 ? (v8u)quad_row : bu(0)) << RS_SUB_BITS);
    const v8u eb0 = bu((uint32_t)tr->eb[0]), eb1 = bu((uint32_t)tr->eb[1]), eb2 = bu((uint32_t)tr->eb[2]);
    v8u e0 = Xl * bu((uint32_t)tr->ea[0]) + Yl * eb0 + bu((uint32_t)tr->ec[0]);
    v8u e1 = Xl * bu((uint32_t)tr->ea[1]) + Yl * eb1 + bu((uint32_t)tr->ec[1]);
    v8u e2 = Xl * bu((uint32_t)tr->ea[2]) + Yl * eb2 + bu((uint32_t)tr->ec[2]);
    const int ds = RS_SUB_BITS + vr - 1; /* vr rows in 1/256 px, as a shift */
    const v8u d0 = eb0 << ds, d1 = eb1 << ds, d2 = eb2 << ds;
    const unsigned cols = (1u << (x1 - x0 + 1)) - 1u, vbox = wbits == 2 ? cols * 0x11u : cols;
    const int nv = (y1 - y0) / vr + 1; /* vectors, at most 8 */
    RS_ASSERT(x1 - x0 < (1 << wbits) && nv <= 8);
    uint64_t cov = 0;
    for (int v = 0; v < nv; v++) {
        const unsigned bx = vr == 2 && 2 * v == y1 - y0 ? vbox & 0x0fu : vbox; /* the last row alone */
        cov |= (uint64_t)(bx & ~mask_of((v8i)(e0 | e1 | e2))) << (8 * v); /* sign bit: some edge < 0 */
        e0 += d0, e1 += d1, e2 += d2;
    }
    const float *pc = j->color_idx < 0 ? NULL : a + j->color_idx * RS_ATTR_STRIDE;
    band_draw(m, j, t, tr, pc, false, wbits, cov, rs_tile_index(t, x0, y0), bi((int32_t)t->pitch),
              bi((int32_t)((int64_t)x0 * RS_SUB - j->cx - tr->vx)), bi((int32_t)((int64_t)y0 * RS_SUB - j->cy - tr->vy)),
              PK16C);
}

/* ---- the instances ---- */

/* Triangle p's pixels [x0, x1] x [y0, y1] of tile t through the small-triangle walks (box at most 8 wide,
 * coef_small), in mode m. */
ALWAYS_INLINE void walk_small(zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0,
                              int y0, int x1, int y1)
{
    RS_ASSERT(x1 - x0 < 8 && box_fits32(j, &p->u.t, x0, y0, x1, y1)); /* coef_small's claim */
    if (m.plain && x1 - x0 < 4 && y1 - y0 < 8) { /* at most 32 pixels: the stamp walk */
        walk_band(m, j, t, p, a, 2, x0, y0, x1, y1);
    } else if (m.plain && y1 - y0 < 2) {
        walk_band(m, j, t, p, a, 3, x0, y0, x1, y1);
    } else { /* larger boxes, whose lanes the 4x2 and row walks fill better; blending or AOV planes */
        fctx c;
        fctx_make(&c, j, t, p, a);
        if (m.plain && x1 - x0 < 4) walk_quads(&c, m, j, t, x0, y0, x1, y1);
        else walk_rows(&c, m, j, t, p, a, x0, y0, x1, y1);
        t->tested += c.tested;
        t->written += c.written;
    }
}

INSTANCE(small_less, walk_small, MODE_LESS)
INSTANCE(small_any, walk_small, MODE_JOB(j))

void RS_KERNEL(rs_tri_fast)(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                            int y1)
{
    const int wbox = x1 - x0 + 1; /* small: the small-triangle and span walks' conditions */
    const bool small = t->x1 - t->x0 >= 8 && wbox <= 8 * SPAN_GROUPS && coef_small(&p->u.t);
    const int walk = !small ? 3 : wbox <= 8 ? 0 : wbox <= 16 ? 1 : 2;
    if (walk > 0) RS_KERNEL(rs_tri_wide)(j, t, p, a, x0, y0, x1, y1, walk);
    else if (j->span_mode == 0) walk_small(MODE_LE, j, t, p, a, x0, y0, x1, y1); /* the tessellated grids' case */
    else if (j->span_mode == 1) small_less(j, t, p, a, x0, y0, x1, y1);
    else small_any(j, t, p, a, x0, y0, x1, y1);
}

/* ---- the grid rows' run (setup_simd.c's grid_tile): a step's triangles from the L1 scratch ---- */

/* *p in every lane, broadcast from memory (one vpbroadcastd: gcc otherwise loads the scalar early and broadcasts it
 * from a register later). */
static inline v8i bcast(const int32_t *p) { return (v8i)_mm256_broadcastd_epi32(_mm_loadu_si32(p)); }

/* rs_tri_run's steps whose live lanes are all stamp lanes (most of scene B's), in mode m, white as run_lanes: a
 * loop of band_draw alone, out of line apart from run_lanes (no dispatch in the loop, fewer values kept across it:
 * the stamp lanes are a part of the direct ones, so here all are).  Returns their count. */
ALWAYS_INLINE unsigned run_stamps(zmode m, bool white, const rs_job *j, rs_tile *t, const rs_prim *sp,
                                  const float *sa, size_t stride, const rs_run_step *s)
{
    RS_ASSERT(m.plain && j->color_idx == (white ? -1 : 0) && stride == RS_ATTR_STRIDE); /* one slot: stamp_ok */
    const pk16c kc = pk16_loop();
    for (unsigned live = s->live; live; live &= live - 1) {
        const int l = __builtin_ctz(live);
        const float *pc = white ? NULL : sa + (size_t)l * RS_ATTR_STRIDE;
        if (!white && !pc) __builtin_unreachable(); /* (no test of pc in stamp_pass) */
        RS_ASSERT(s->covm[l] != 0);
        if (!s->covm[l]) __builtin_unreachable(); /* (grid_tile drops the empty lanes: no test in band_draw) */
        band_draw(m, j, t, &sp[l].u.t, pc, true, 2, s->covm[l], (size_t)(uint32_t)s->off[l], bcast(&s->pitch),
                  bcast(&s->xs[l]), bcast(&s->ys[l]), kc);
    }
    return (unsigned)__builtin_popcount(s->live);
}

/* rs_tri_run in mode m, white: the job's colour_idx < 0 (the stamp lanes' colour slot, when there is one, is slot
 * 0: grid_tile gives stamp lanes only for one slot): the lanes of s->stamp straight to band_draw with their coverage
 * masks and offsets (the stamp walk after its coverage; their attribute blocks in shade8_l's vector layout); the
 * others of s->live whose triangle is coef_small (s->small, from the set-up lanes) with a box at most 8 pixels wide
 * in a tile at least 8 wide -- rs_tri_fast's conditions for walk_small -- straight to walk_small; the rest through
 * rs_tri_fast.  Returns the count of the first two. */
ALWAYS_INLINE unsigned run_lanes(zmode m, bool white, const rs_job *j, rs_tile *t, const rs_prim *sp,
                                 const float *sa, size_t stride, const rs_run_step *s)
{
    unsigned live = s->live;
    const unsigned stamp = s->stamp;
    RS_ASSERT(stamp == 0 || (m.plain && j->color_idx == (white ? -1 : 0)));
    const int32_t (*cb)[8] = s->cb;
    unsigned direct = 0;
    if (t->x1 - t->x0 >= 8) { /* the boxes' widths in lanes: rs_tri_fast's test */
        const v8i x0 = (v8i)_mm256_loadu_si256((const __m256i *)cb[0]);
        const v8i x1 = (v8i)_mm256_loadu_si256((const __m256i *)cb[2]);
        direct = live & s->small & mask_of(x1 - x0 < bi(8));
    }
    RS_ASSERT((stamp & ~direct) == 0);
    for (; live; live &= live - 1) {
        const int l = __builtin_ctz(live);
        const float *a = sa + (size_t)l * stride;
        if (stamp >> l & 1u) {
            if (!white && !a) __builtin_unreachable();
            band_draw(m, j, t, &sp[l].u.t, white ? NULL : a, true, 2, s->covm[l], (size_t)(uint32_t)s->off[l],
                      bcast(&s->pitch), bcast(&s->xs[l]), bcast(&s->ys[l]), PK16C);
        }
        else if (direct >> l & 1u) walk_small(m, j, t, &sp[l], a, cb[0][l], cb[1][l], cb[2][l], cb[3][l]);
        else RS_KERNEL(rs_tri_fast)(j, t, &sp[l], a, cb[0][l], cb[1][l], cb[2][l], cb[3][l]);
    }
    return (unsigned)__builtin_popcount(direct);
}

/* run_lanes per mode (the job's span_mode) and colour, out of line: one dispatch per step instead of one per
 * triangle. */
typedef unsigned run_fn(const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa, size_t stride,
                        const rs_run_step *s);
#define STEP_INSTANCE(name, body, mode, white)                                                                  \
    static unsigned name(const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa, size_t stride,       \
                         const rs_run_step *s)                                                                  \
    {                                                                                                           \
        return body(mode, white, j, t, sp, sa, stride, s);                                                      \
    }
STEP_INSTANCE(run_le, run_lanes, MODE_LE, false)
STEP_INSTANCE(run_less, run_lanes, MODE_LESS, false)
STEP_INSTANCE(run_any, run_lanes, MODE_JOB(j), false)
STEP_INSTANCE(run_le_w, run_lanes, MODE_LE, true)
STEP_INSTANCE(run_less_w, run_lanes, MODE_LESS, true)
STEP_INSTANCE(run_any_w, run_lanes, MODE_JOB(j), true)
static run_fn *const runs[2][3] = {{run_le, run_less, run_any}, {run_le_w, run_less_w, run_any_w}};
STEP_INSTANCE(stamps_le, run_stamps, MODE_LE, false)
STEP_INSTANCE(stamps_less, run_stamps, MODE_LESS, false)
STEP_INSTANCE(stamps_any, run_stamps, MODE_JOB(j), false)
STEP_INSTANCE(stamps_le_w, run_stamps, MODE_LE, true)
STEP_INSTANCE(stamps_less_w, run_stamps, MODE_LESS, true)
STEP_INSTANCE(stamps_any_w, run_stamps, MODE_JOB(j), true)
static run_fn *const stamps[2][3] = {{stamps_le, stamps_less, stamps_any},
                                     {stamps_le_w, stamps_less_w, stamps_any_w}};

unsigned RS_KERNEL(rs_tri_run)(const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa, size_t stride,
                               const rs_run_step *s)
{
    return (s->live == s->stamp ? stamps : runs)[j->color_idx < 0][j->span_mode](j, t, sp, sa, stride, s);
}

#else /* without AVX2 every draw takes the reference path (rs_span_ok is false) */

unsigned RS_KERNEL(rs_tri_run)(const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa, size_t stride,
                               const rs_run_step *s)
{
    return 0;
}

void RS_KERNEL(rs_tri_fast)(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                            int y1)
{
}

#endif
