/* raster/span_wide.c -- the fast path of triangle rasterization on 1-sample targets, larger triangles (span.c's
 * rs_tri_fast sends them here): 8 pixels at a time, the same per-pixel operations and bytes as span.c's walks and
 * tri.c's reference walk (span_lanes.h states how).
 *
 * One walk, the interval walk: per row the covered interval, exact, from each edge's crossing column (row_spans:
 * double arithmetic, 4 rows per vector, no per-pixel coverage at all), then groups of 8 columns over it with the
 * lanes outside masked off (none between a row's first and last group); the planes' x parts per column and y
 * parts per row come from tables made once per call, the colour coefficients are broadcast once (memory operands
 * of the lane arithmetic) and the shading is specialised for a constant alpha.  Medium triangles (box at most 32
 * wide, edge coefficients at most 2^13: rs_tri_fast's walks 1 and 2) take groups from each row's first covered
 * column, so a short row is one group, and two rows of at most 4 pixels one 4x2 group; the others
 * (walk 3) 8-aligned groups, no loads across cache lines, in bands of 64 x 64 pixels (BAND).  It replaced a span
 * walk (per row the coverage of a window of 2 or 4 groups, 32-bit edge values) and a block walk (8x8 blocks with
 * trivial accept / reject tests): scene A 25.2 -> 20.4 M and scene C 43.3 -> 34.1 M instructions per frame.  Then (issue
 * 29, wave 3) A 20.42 -> 19.56 M, C 34.30 -> 32.84 M: the packs do the channels' lower saturation (to8_8p), the
 * depth clamp in three instructions (zclamp8), the edges permuted into starts and ends for row_spans (no caps),
 * the medium walk's groups kept inside the box (x parts of its columns only), any two rows of at most 4 pixels
 * in one 4x2 group (each with its own 4 columns).  Wave 3, round 2 (main 897ac3f: A npatch 18.39 M, C npatch
 * 28.49 M per frame; span_le 9.84 M of A's, ~88k groups for 422k pixels): span8 and frag8 clamp depth with
 * the three-instruction zclamp8 too, the old two-blend one removed (A npatch -4k, A smooth -4k, C -0.3k;
 * B npatch +2.5k, B smooth +3k per frame against main's binary: 0.003%, cause not found).  Tried and dropped: pairing each row's tail (k % 8 in 1..4 after k / 8 full
 * groups) with the next row's in a 4x2 group, a superset of the short-row pairing: 7% fewer groups on A but the
 * row loop's bookkeeping grew more (span_le 9.84 -> 10.58 M, A 18.39 -> 19.13 M); n[nr] = 0 so that the short-row
 * test reads n[i + 1] without i + 1 < nr (A +16k); c->w in a local (A unchanged).
 * Wave 3, round 3 (main 615eb03: A npatch 18.36 M, span_le 9.84 M): a group's lane mask one load from a [lo][hi]
 * table instead of two loads and an andnot (A npatch 18.359 -> 18.315 M, A smooth 18.759 -> 18.713 M, C npatch
 * 28.485 -> 28.440 M, B npatch unchanged); frag_w's two blends by the pass mask as one vblendvps each (blend_sign,
 * inline asm: the intrinsic is folded into a compare with 0 and a blend, an extra instruction and register per
 * group; A npatch 18.315 -> 18.104 M, span_le 9.79 -> 9.58 M; A smooth 18.713 -> 18.500 M, C npatch 28.440 ->
 * 28.236 M, B unchanged); the aligned walk's rows that end inside the target (the last group at most gmax) go
 * straight to frag_w, the groups between the first and the last unmasked in a loop of their own (no span8 test, no
 * tail test per group; C npatch 28.236 -> 26.546 M, big_le 20.43 -> 18.74 M; A, B unchanged).  Tried and dropped: the group plan (every row's groups listed first as
 * 8-byte entries, offset, column, row, lanes; then one loop over the row groups and one over the 4x2 pairs): the
 * scalar list costs more than the row loop it replaces (~13 instructions to store an entry, ~10 to read one back:
 * span_le 9.84 -> 10.91 M, A 18.36 -> 19.43 M); it would pay only built with vectors, 8 rows at a time.  The
 * aligned walk's fast rows for the medium walk too (rows whose groups from the first column all start at most at
 * gmax: full groups unmasked, the last one lanes [0, k)): A npatch 18.1033 -> 18.1049 M, the row loop's registers.
 * Wave 3, round 4 (main a13220c: A npatch 18.095 M, A smooth 18.491 M, C npatch 26.513 M; span_le 9.58 M of A's,
 * per frame ~57k rows, ~57k single-row groups at ~65 instructions, ~10k 4x2 pairs at ~135): the medium walk's
 * plain groups take their lanes from the row's run (runs_tab's row k from entry 8 - l: one memory operand per
 * group instead of lanes_tab's index arithmetic; A npatch 18.095 -> 17.910 M); rows2 one vpermps with a memory
 * operand (17.910 -> 17.874 M); the medium plain rows one group site, the run pointer one constant step per group,
 * no out-of-line moved-left group (17.874 -> 17.304 M, span_le 9.58 -> 8.79 M); row_spans stores each row's run
 * offset (one load per row instead of ~6 instructions; 17.304 -> 17.237 M, but C npatch +41k while the aligned
 * walk stored it too) and, medium walk only, the pair's column and lanes per row (17.237 -> 17.121 M).  In all
 * A npatch 18.095 -> 17.121 M (-5.4%), A smooth 18.491 -> 17.514 M, C npatch 26.513 -> 26.387 M, B unchanged.
 * Tried and dropped, each against 17.304 M (gcc's register allocation of the row loop swings by 0.1 M on small
 * changes): the pair's lanes from the two rows' runs (_mm256_loadu2_m128i, index arithmetic per pair) instead of
 * two lanes_tab loads, 17.436 M (neutral, 17.874 M, before the one group site; it pays once row_spans gives the
 * offsets); the medium plain rows, pair and run loop, in one block ahead of the general row set-up, 17.365 M
 * (17.429 M with lanes_tab's pair lanes); the constant alpha's NaN test against a zero register instead of k[10],
 * k[11] (zeros) as memory operands, 17.401 M; a pair whose two rows fit the same 4 columns at one column (x parts
 * one 16-byte load each, tested first), 17.342 M; no 4x2 pairs at all, 17.447 M (a pair still saves ~14
 * instructions on two single-row groups and their row overhead).
 * The walk is instantiated per depth-state mode (span_lanes.h's INSTANCES). */
#include "span_lanes.h"

/* The interval walk's boxes are at most BAND x BAND pixels (row_spans' exactness argument and the x parts' table
 * are for 64 columns); larger boxes, in a tile of 128, go in bands of it (walk_big). */
#define BAND 64
_Static_assert(RS_TILE_MIN % BAND == 0, "a tile is whole bands: the 8-aligned groups never cross a band");

#ifdef __AVX2__

/* ---- the interval walk ---- */

/* a * X + b * Y per edge for |X|, |Y| < 2^31: |a|, |b| <= 2^23 fit int32 (setup.c), so the signed 32 x 32-bit
 * products are the exact int64 ones. */
static inline __m256i edge_xy(const edges4 *E, int64_t X, int64_t Y)
{
    RS_ASSERT(X >= INT32_MIN && X <= INT32_MAX && Y >= INT32_MIN && Y <= INT32_MAX);
    return _mm256_add_epi64(_mm256_mul_epi32(E->a, _mm256_set1_epi64x(X)),
                            _mm256_mul_epi32(E->b, _mm256_set1_epi64x(Y)));
}

typedef double v4d __attribute__((vector_size(32)));
typedef int64_t v4l __attribute__((vector_size(32)));

/* int64 lanes -> double, exactly for |v| < 2^51: v + 1.5 * 2^52 as an integer is the double 1.5 * 2^52 + v. */
static inline v4d exact_pd(__m256i v)
{
    const __m256i magic = _mm256_set1_epi64x(0x4338000000000000ll);
    return (v4d)_mm256_add_epi64(v, magic) - (v4d){0x1.8p52, 0x1.8p52, 0x1.8p52, 0x1.8p52};
}

#define CEIL (_MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC)
#define RUNW (8 + 8 * SPAN_GROUPS + 8) /* runs_tab's row length */
#define LANE(v, i) ((v4d)_mm256_permute4x64_pd((__m256d)(v), 0x55 * (i)))

/* row_spans' answer, per row i of the box (4 more: the last vector's rows past nr); r, u, p only for the medium
 * walk (n <= 32, w >= 9; row_spans_any, for degenerate triangles, stores them always). */
typedef struct spans {
    int32_t l[BAND + 4];  /* the first covered column, relative to x0 */
    int32_t n[BAND + 4];  /* how many from it (<= 0: none) */
    int32_t r[BAND + 4];  /* n * RUNW - l: the row's run in runs_tab (from its entry 8) */
    int32_t u[BAND + 4];  /* min(l, w - 4): the row's 4 columns in a 4x2 pair, inside the box */
    int32_t p[BAND + 4];  /* r + u: their lanes in the row's run */
} spans;

/* Store rows i .. i + 3 of row_spans' answer from their starts st and ends en (columns, exact integers): st in
 * [0, 2^41]: n = en - st <= 0 when st > 64 (the start's int32 then does not matter; an out-of-range conversion
 * gives INT32_MIN, as does n's below -2^31). */
static inline void spans_store(__m256d st, __m256d en, bool medium, spans *sp, int i, __m128i w4)
{
    const __m128i l = _mm256_cvttpd_epi32(st), n = _mm256_cvttpd_epi32(_mm256_sub_pd(en, st));
    _mm_storeu_si128((__m128i *)(sp->l + i), l);
    _mm_storeu_si128((__m128i *)(sp->n + i), n);
    if (medium) { /* (r wraps harmlessly where n <= 0: not read) */
        const __m128i r = _mm_sub_epi32(_mm_mullo_epi32(n, _mm_set1_epi32(RUNW)), l), u = _mm_min_epi32(l, w4);
        _mm_storeu_si128((__m128i *)(sp->r + i), r);
        _mm_storeu_si128((__m128i *)(sp->u + i), u);
        _mm_storeu_si128((__m128i *)(sp->p + i), _mm_add_epi32(r, u));
    }
}

/* row_spans for edges in role order (e0, A, B permuted: lanes 0 and 1 starts and 2 an end, or with two_ends lane
 * 0 a start and 1, 2 ends): each row's start the largest of its starts' u (and 0), its end the smallest of its
 * ends' u (and w) -- what the caps of row_spans_any select, without them. */
ALWAYS_INLINE void spans_by_role(v4d e0, v4d A, v4d B, bool two_ends, bool medium, int w, int nr, spans *sp)
{
    const v4d one = {1.0, 1.0, 1.0, 1.0}, zero = {0.0, 0.0, 0.0, 0.0}, rows = {0.0, 1.0, 2.0, 3.0};
    const v4l isz = (v4l)(A == zero);
    const v4d m = (v4d)_mm256_blendv_pd((__m256d)(-one / (v4d)_mm256_blendv_pd((__m256d)A, (__m256d)one, (__m256d)isz)),
                                        _mm256_set1_pd(-1024.0), (__m256d)isz);
    const v4d eps = {0x1p-33, 0x1p-33, 0x1p-33, 0x1p-33};
    v4d e_0 = LANE(e0, 0) + rows * LANE(B, 0), e_1 = LANE(e0, 1) + rows * LANE(B, 1),
        e_2 = LANE(e0, 2) + rows * LANE(B, 2);
    const v4d d_0 = LANE(B, 0) * 4.0, d_1 = LANE(B, 1) * 4.0, d_2 = LANE(B, 2) * 4.0;
    const v4d m_0 = LANE(m, 0), m_1 = LANE(m, 1), m_2 = LANE(m, 2);
    const v4d b_1 = two_ends ? eps : -eps; /* edge 0: a start (-eps), edge 2: an end (+eps) */
    const v4d wv = {w, w, w, w};
    const __m128i w4 = _mm_set1_epi32(w - 4);
    for (int i = 0; i < nr; i += 4) {
        const __m256d u0 = _mm256_round_pd((__m256d)(e_0 * m_0 - eps), CEIL);
        const __m256d u1 = _mm256_round_pd((__m256d)(e_1 * m_1 + b_1), CEIL);
        const __m256d u2 = _mm256_round_pd((__m256d)(e_2 * m_2 + eps), CEIL);
        e_0 += d_0, e_1 += d_1, e_2 += d_2;
        if (two_ends)
            spans_store(_mm256_max_pd(u0, (__m256d)zero), _mm256_min_pd(_mm256_min_pd(u1, u2), (__m256d)wv), medium,
                        sp, i, w4);
        else
            spans_store(_mm256_max_pd(_mm256_max_pd(u0, u1), (__m256d)zero), _mm256_min_pd(u2, (__m256d)wv), medium,
                        sp, i, w4);
    }
}

/* row_spans for any roles (every edge through caps: its u for a start, -huge for an end in the starts' maximum,
 * and the reverse in the ends' minimum); right: the ends' lanes (A < 0). */
static __attribute__((noinline)) void row_spans_any(v4d e0, v4d A, v4d B, int w, int nr, spans *sp)
{
    const v4d one = {1.0, 1.0, 1.0, 1.0}, zero = {0.0, 0.0, 0.0, 0.0};
    const v4l isz = (v4l)(A == zero), right = (v4l)(A < zero);
    const v4d m = (v4d)_mm256_blendv_pd((__m256d)(-one / (v4d)_mm256_blendv_pd((__m256d)A, (__m256d)one, (__m256d)isz)),
                                        _mm256_set1_pd(-1024.0), (__m256d)isz);
    const v4d eps = {0x1p-33, 0x1p-33, 0x1p-33, 0x1p-33}, huge = {0x1p60, 0x1p60, 0x1p60, 0x1p60};
    const v4d bias = (v4d)_mm256_blendv_pd((__m256d)-eps, (__m256d)eps, (__m256d)right);
    /* min(u, caps) is u for a start and -huge for an end, max(u, caps) huge for a start and u for an end */
    const v4d caps = (v4d)_mm256_blendv_pd((__m256d)huge, (__m256d)-huge, (__m256d)right);
    const v4d rows = {0.0, 1.0, 2.0, 3.0};
    v4d e_0 = LANE(e0, 0) + rows * LANE(B, 0), e_1 = LANE(e0, 1) + rows * LANE(B, 1),
        e_2 = LANE(e0, 2) + rows * LANE(B, 2);
    const v4d d_0 = LANE(B, 0) * 4.0, d_1 = LANE(B, 1) * 4.0, d_2 = LANE(B, 2) * 4.0;
    const v4d m_0 = LANE(m, 0), m_1 = LANE(m, 1), m_2 = LANE(m, 2);
    const v4d b_0 = LANE(bias, 0), b_1 = LANE(bias, 1), b_2 = LANE(bias, 2);
    const v4d c_0 = LANE(caps, 0), c_1 = LANE(caps, 1), c_2 = LANE(caps, 2);
    const v4d wv = {w, w, w, w};
    const __m128i w4 = _mm_set1_epi32(w - 4);
    for (int i = 0; i < nr; i += 4) {
        const __m256d u0 = _mm256_round_pd((__m256d)(e_0 * m_0 + b_0), CEIL);
        const __m256d u1 = _mm256_round_pd((__m256d)(e_1 * m_1 + b_1), CEIL);
        const __m256d u2 = _mm256_round_pd((__m256d)(e_2 * m_2 + b_2), CEIL);
        e_0 += d_0, e_1 += d_1, e_2 += d_2;
        __m256d st = _mm256_max_pd(_mm256_max_pd(_mm256_min_pd(u0, (__m256d)c_0), _mm256_min_pd(u1, (__m256d)c_1)),
                                   _mm256_max_pd(_mm256_min_pd(u2, (__m256d)c_2), (__m256d)zero));
        __m256d en = _mm256_min_pd(_mm256_min_pd(_mm256_max_pd(u0, (__m256d)c_0), _mm256_max_pd(u1, (__m256d)c_1)),
                                   _mm256_min_pd(_mm256_max_pd(u2, (__m256d)c_2), (__m256d)wv));
        spans_store(st, en, true, sp, i, w4);
    }
}

/* The permutation of row_spans' double lanes per pattern of ends (bit i: edge i has A < 0), as 32-bit indices:
 * the starts first, then the ends (lane 3 stays); patterns 0 and 7 (no start or no end: a degenerate triangle)
 * go to row_spans_any. */
static const int32_t role_perm[8][8] __attribute__((aligned(32))) = {
    {0, 1, 2, 3, 4, 5, 6, 7}, {2, 3, 4, 5, 0, 1, 6, 7}, {0, 1, 4, 5, 2, 3, 6, 7}, {4, 5, 0, 1, 2, 3, 6, 7},
    {0, 1, 2, 3, 4, 5, 6, 7}, {2, 3, 0, 1, 4, 5, 6, 7}, {0, 1, 2, 3, 4, 5, 6, 7}, {0, 1, 2, 3, 4, 5, 6, 7},
};

/* The covered interval of each row of triangle tr in columns x0 .. x0 + w - 1 (w <= 64), rows y0 .. y0 + nr - 1
 * (nr <= 64), from each edge's exact crossing column, 4 rows per vector, into sp: l[i] the first covered column of
 * row y0 + i relative to x0, n[i] how many follow it (<= 0: none); medium: r, u, p too (spans).
 *
 * Edge i is e + A * c at column x0 + c of a row (A = ea * 256, e its value at x0; inside iff >= 0), q = -e / A:
 * for A > 0 the row's pixels start at c = ceil(q), for A < 0 they end before c = floor(q) + 1, for A = 0 they are
 * all in or all out.  Each edge gives u = ceil(e * m + b): m = -1 / A and b = -eps (A > 0: the start), b = +eps
 * (A < 0: the end); m = -1024 and b = -eps for A = 0 (a start: u <= 0 when e >= 0, u >= 1024 when e < 0).  Why
 * exact: e, its row steps and e * 1024 are integers below 2^53 (exact doubles); p = fl(e * fl(-1 / A)) is within
 * |q| * 2^-52 of q, so within 2^-45 when |q| <= 128.  When q is an integer, p - eps lies in (q - 1, q) and p + eps
 * in (q, q + 1): u = q, resp. q + 1.  Otherwise q is at least 1 / |A| >= 2^-31 (|A| <= 2^31) away from the
 * integers around it, more than eps (2^-33) + 2^-45 + the rounding of the sum: u = ceil(q), resp. floor(q) + 1.
 * When |q| > 128, p is beyond the walked columns as q is, and the bounds are clamped to them.
 * A triangle's edges have both roles (their A sum to 0): the usual case permutes them into starts, then ends
 * (spans_by_role, no caps per edge and row); a degenerate one (no start or no end) takes row_spans_any. */
ALWAYS_INLINE void row_spans(const rs_job *j, const rs_tri *tr, bool medium, int x0, int y0, int w, int nr,
                             spans *sp)
{
    const edges4 E = edges4_of(tr);
    RS_ASSERT(rs_within((int64_t)x0 * RS_SUB - j->cx, 22) && rs_within((int64_t)y0 * RS_SUB - j->cy, 22));
    const __m256i ev = _mm256_add_epi64(edge_xy(&E, (int64_t)x0 * RS_SUB - j->cx, (int64_t)y0 * RS_SUB - j->cy),
                                        E.c); /* lanes 0..2: e at (x0, y0), |e| < 2^48 */
    RS_ASSERT(rs_within(((v4l)ev)[0], 48) && rs_within(((v4l)ev)[1], 48) && rs_within(((v4l)ev)[2], 48));
    const v4d e0 = exact_pd(ev);
    const v4d A = _mm256_cvtepi32_pd(_mm_loadu_si128((const __m128i *)tr->ea)) * 256.0; /* lane 3: eb[0]'s */
    const v4d B = _mm256_cvtepi32_pd(_mm_loadu_si128((const __m128i *)tr->eb)) * 256.0; /* lane 3: ec's */
    const unsigned ends = (unsigned)_mm256_movemask_pd((__m256d)(A < (v4d){0.0, 0.0, 0.0, 0.0})) & 7u;
    if (ends == 0 || ends == 7) {
        row_spans_any(e0, A, B, w, nr, sp);
        return;
    }
    const __m256i pi = _mm256_load_si256((const __m256i *)role_perm[ends]);
#define PERM(v) ((v4d)_mm256_permutevar8x32_ps((__m256)(v), pi))
    if (ends == 3 || ends == 5 || ends == 6) spans_by_role(PERM(e0), PERM(A), PERM(B), true, medium, w, nr, sp);
    else spans_by_role(PERM(e0), PERM(A), PERM(B), false, medium, w, nr, sp);
#undef PERM
}
#undef LANE
#undef CEIL

/* Is pixel x of the row at Y (1/256 px from the centre) inside triangle tr (every edge >= 0, int64)? */
static inline bool inside_at(const rs_job *j, const rs_tri *tr, int x, int64_t Y)
{
    bool in = true;
    for (int q = 0; q < 3; q++)
        in &= (int64_t)tr->ea[q] * ((int64_t)x * RS_SUB - j->cx) + (int64_t)tr->eb[q] * Y + tr->ec[q] >= 0;
    return in;
}

/* Are l, n row_spans' exact answer for the box [x0, x1] x [y0, y0 + nr - 1]: the first and last pixel of each
 * interval inside, the pixels just outside it (in the box) not, and no pixel of an empty row inside?  For
 * RS_ASSERT. */
static inline __attribute__((unused)) bool spans_exact(const rs_job *j, const rs_tri *tr, int x0, int y0, int x1,
                                                      int nr, const int32_t *l, const int32_t *n)
{
    for (int i = 0; i < nr; i++) {
        const int64_t Y = (int64_t)(y0 + i) * RS_SUB - j->cy;
        if (n[i] <= 0) { /* none covered: test them all */
            for (int x = x0; x <= x1; x++)
                if (inside_at(j, tr, x, Y)) return false;
            continue;
        }
        const int first = x0 + l[i], last = first + n[i] - 1;
        if (last > x1 || !inside_at(j, tr, first, Y) || !inside_at(j, tr, last, Y) ||
            (first > x0 && inside_at(j, tr, first - 1, Y)) || (last < x1 && inside_at(j, tr, last + 1, Y)))
            return false;
    }
    return true;
}

/* Lanes [lo, hi) of 8 as -1 / 0 lanes, at lanes_tab[lo][hi] (0 <= lo < 8, hi <= 8): one load per group. */
#define LB(lo, hi, i) ((i) >= (lo) && (i) < (hi) ? -1 : 0)
#define LROW(lo, hi) {LB(lo, hi, 0), LB(lo, hi, 1), LB(lo, hi, 2), LB(lo, hi, 3), LB(lo, hi, 4), LB(lo, hi, 5), \
                      LB(lo, hi, 6), LB(lo, hi, 7)}
#define LTAB(lo) {LROW(lo, 0), LROW(lo, 1), LROW(lo, 2), LROW(lo, 3), LROW(lo, 4), LROW(lo, 5), LROW(lo, 6), \
                  LROW(lo, 7), LROW(lo, 8)}
static const int32_t lanes_tab[8][9][8] __attribute__((aligned(32))) = {
    LTAB(0), LTAB(1), LTAB(2), LTAB(3), LTAB(4), LTAB(5), LTAB(6), LTAB(7),
};
#undef LTAB
#undef LROW
#undef LB
/* Lanes [lo, k) as -1 / 0 lanes (0 <= lo < k <= 8). */
static inline v8i lanes_between(int lo, int k)
{
    RS_ASSERT(lo >= 0 && lo < k && k <= 8);
    v8i a;
    memcpy(&a, lanes_tab[lo][k], 32);
    return a;
}

/* Runs of k lanes (0 <= k <= 8 * SPAN_GROUPS), row k of RUNW entries: runs_tab[k * RUNW + 8 + c] is -1 for
 * 0 <= c < k, else 0, so that from run = runs_tab + k * RUNW + 8 - l (per row: its k columns from l; row_spans
 * gives k * RUNW - l), the 8 entries at run + s are the lanes of the group at column s, masked to the row's
 * interval, for any s in [l - 7, l + k + 7]: one unaligned load, a memory operand of the lane arithmetic, no index
 * arithmetic per group. */
#define RB(k, c) ((c) >= 8 && (c) < 8 + (k) ? -1 : 0)
#define R8(k, c) RB(k, c), RB(k, c + 1), RB(k, c + 2), RB(k, c + 3), RB(k, c + 4), RB(k, c + 5), RB(k, c + 6), \
                 RB(k, c + 7)
#define RROW(k) R8(k, 0), R8(k, 8), R8(k, 16), R8(k, 24), R8(k, 32), R8(k, 40)
#define RROW4(k) RROW(k), RROW(k + 1), RROW(k + 2), RROW(k + 3)
_Static_assert(RUNW == 48, "runs_tab's rows are written out for SPAN_GROUPS 4");
static const int32_t runs_tab[(8 * SPAN_GROUPS + 1) * RUNW] __attribute__((aligned(32))) = { /* (one array:
                                                                   * the runs' pointers step across its rows) */
    RROW4(0), RROW4(4), RROW4(8), RROW4(12), RROW4(16), RROW4(20), RROW4(24), RROW4(28), RROW(32),
};
#undef RROW4
#undef RROW
#undef R8
#undef RB
/* The 8 lanes of run at entry s (runs_tab's comment). */
static inline v8i run_lanes(const int32_t *run, ptrdiff_t s)
{
    v8i a;
    memcpy(&a, run + s, 32);
    return a;
}

/* A walk's per-triangle constants as vectors: the colour slot's 12 coefficients (rs_fill_slot's layout) and the
 * constant alpha broadcast once, so the lanes' arithmetic takes them as memory operands (AVX2 has no broadcast
 * operand: shade8 broadcasts them per group). */
typedef struct wconst {
    v8f k[12];
    v8i a8;
} wconst;

/* shade8 with w's vectors: the same operations in the same order, but for the lower saturation, which the packs
 * do (to8_8p): the same bytes. */
ALWAYS_INLINE v8i shade8w(const wconst *w, int a8, v8f b1, v8f b2)
{
    const v8f *k = w->k;
    __m256i r = to8_8p(k[0] + b1 * k[1] + b2 * k[2]); /* (to8_8p: the packs below saturate) */
    __m256i g = to8_8p(k[3] + b1 * k[4] + b2 * k[5]);
    __m256i b = to8_8p(k[6] + b1 * k[7] + b2 * k[8]);
    __m256i al;
    if (a8 >= 0) { /* k[10], k[11] are zeros: b1 * k[10] + b2 * k[11] is NaN iff one of the products is */
        const __m256 t1 = (__m256)(b1 * k[10]), t2 = (__m256)(b2 * k[11]);
        al = _mm256_and_si256((__m256i)_mm256_cmp_ps(t1, t2, _CMP_ORD_Q), (__m256i)w->a8);
    } else {
        al = to8_8p(k[9] + b1 * k[10] + b2 * k[11]);
    }
    __m256i x = _mm256_packus_epi16(_mm256_packus_epi32(r, g), _mm256_packus_epi32(b, al));
    const __m256i order = _mm256_setr_epi8(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15,
                                           0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15);
    return (v8i)_mm256_shuffle_epi8(x, order);
}

/* Depth-test (mode m, plain), shade and write lanes `lanes` of the 8 pixels at dp (depth) and cp (colour) in c's
 * planes, whose x parts are at xz, xs, xq1, xq2 and y parts zy, sy, q1y, q2y: frag8's operations.  split: lanes
 * 0..3 are the 4 pixels at dp, cp and lanes 4..7 4 pixels of the next row, dx columns right of those (x parts
 * likewise).  a8c: c has a colour slot with a constant alpha (the common case, known at compile time: no tests per
 * group). */
ALWAYS_INLINE void frag_w(fctx *c, const wconst *w, zmode m, bool a8c, bool split, ptrdiff_t dx, v8i lanes, float *dp,
                          uint32_t *cp, const float *xz, const float *xs, const float *xq1, const float *xq2, v8f zy,
                          v8f sy, v8f q1y, v8f q2y)
{
#define XP(q) (split ? (v8f)_mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(q)), _mm_loadu_ps((q) + dx), 1) \
                     : (v8f)_mm256_loadu_ps(q))
    float *dp1 = split ? dp + c->w + dx : dp;
    uint32_t *cp1 = split ? cp + c->w + dx : cp;
    v8i pass = lanes;
    if (m.ze) {
        const v8f d = (v8f)load_lanes(dp, dp1, split);
        const v8f z = zclamp8(XP(xz) + zy, c->zlo, c->zhi);
        pass &= zpass8(m.zf, z, d);
        if (m.zw) store_lanes(dp, dp1, split, (__m256i)blend_sign(pass, z, d));
    }
    const unsigned pm = mask_of(pass);
    if (!pm) return;
    c->written += (uint64_t)__builtin_popcount(pm);
    const v8f rr = bf(1.0f) / (XP(xs) + sy);
    const v8f b1 = (XP(xq1) + q1y) * rr;
    const v8f b2 = (XP(xq2) + q2y) * rr;
#undef XP
    const v8i src = a8c ? shade8w(w, 0, b1, b2) : c->pc ? shade8w(w, c->a8, b1, b2) : bi(-1);
    store_lanes(cp, cp1, split, (__m256i)blend_sign(pass, (v8f)src, (v8f)load_lanes(cp, cp1, split)));
}

/* The x parts of the planes per column: column bx + i at index i, for up to 72 columns (a band's 64 and the 8
 * past a group that starts at its last one). */
#define XCOLS 72
typedef struct xcols {
    float zx[XCOLS], sx[XCOLS], q1x[XCOLS], q2x[XCOLS];
} xcols;

/* Fill the first 8n columns of xc from column bx: per column the values rows8_at gives it (its X is the same
 * integer whichever group holds it, so the same floats), without its sample offset: on a 1-sample target sox[0]
 * is 0 (draw.c) and fx + 0.0f is fx (fx is an integer times 1/256, never -0). */
static inline void xcols_fill(xcols *xc, const rs_job *j, const rs_tri *tr, int bx, int n)
{
    RS_ASSERT(8 * n <= XCOLS && j->sox[0] == 0);
    const float k = 1.0f / RS_SUB;
    const v8f z0 = bf(tr->z[0]), z2 = bf(tr->z[2]), s0 = bf(tr->s[0]), s2 = bf(tr->s[2]);
    const v8f a0 = bf(tr->q1[0]), a2 = bf(tr->q1[2]), c0 = bf(tr->q2[0]), c2 = bf(tr->q2[2]);
    v8i X = bi((int32_t)((int64_t)bx * RS_SUB - j->cx - tr->vx)) + lane_idx * RS_SUB;
    for (int v = 0; v < n; v++, X += bi(8 * RS_SUB)) {
        RS_ASSERT(lanes_exact(X));
        const v8f fx = __builtin_convertvector(X, v8f) * bf(k); /* |X| < 2^24: exact in float, as tri_pixel's */
        const v8f zx = z2 + z0 * fx, sx = s2 + s0 * fx, q1x = a2 + a0 * fx, q2x = c2 + c0 * fx;
        memcpy(xc->zx + 8 * v, &zx, 32);
        memcpy(xc->sx + 8 * v, &sx, 32);
        memcpy(xc->q1x + 8 * v, &q1x, 32);
        memcpy(xc->q2x + 8 * v, &q2x, 32);
    }
}

/* The y parts of the planes per row: row y0 + i at index i (a band's 64 rows and the rest of a vector of 8; 8 more
 * that rows2's load may read and then ignore). */
typedef struct yrows {
    float zy[BAND + 8], sy[BAND + 8], q1y[BAND + 8], q2y[BAND + 8];
} yrows;

/* Fill rows 0 .. nr - 1 of yr from row y0: per row the values ypart_at gives it, 8 rows per vector, without its
 * sample offset (0 on a 1-sample target: fy + 0.0f is fy, as in xcols_fill). */
static inline void yrows_fill(yrows *yr, const rs_job *j, const rs_tri *tr, int y0, int nr)
{
    RS_ASSERT(j->soy[0] == 0);
    const float k = 1.0f / RS_SUB;
    const v8f z1 = bf(tr->z[1]), s1 = bf(tr->s[1]), a1 = bf(tr->q1[1]), c1 = bf(tr->q2[1]);
    v8i Y = bi((int32_t)((int64_t)y0 * RS_SUB - j->cy - tr->vy)) + lane_idx * RS_SUB;
    for (int i = 0; i < nr; i += 8, Y += bi(8 * RS_SUB)) {
        RS_ASSERT(lanes_exact(Y));
        const v8f fy = __builtin_convertvector(Y, v8f) * bf(k);
        const v8f zy = z1 * fy, sy = s1 * fy, q1y = a1 * fy, q2y = c1 * fy;
        memcpy(yr->zy + i, &zy, 32);
        memcpy(yr->sy + i, &sy, 32);
        memcpy(yr->q1y + i, &q1y, 32);
        memcpy(yr->q2y + i, &q2y, 32);
    }
}

/* p[0] in lanes 0..3 and p[1] in lanes 4..7 (the y parts of two rows, for the 4x2 groups). */
static inline v8f rows2(const float *p)
{
    __m256 v; /* p[0 .. 7] (p[2 ..] ignored; yrows has room for them): the permute's memory operand */
    memcpy(&v, p, sizeof v);
    return (v8f)_mm256_permutevar8x32_ps(v, _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1));
}

/* One group of the interval walk: lanes [lo, hi) of the 8 pixels from column gx of row y (index xi in xc, in the
 * row's planes drow, crow), all 8 when full (known at compile time: no lane mask); through frag_w, or span8 when
 * not plain or the group passes the target's right end (aligned walks, gx > gmax). */
ALWAYS_INLINE void group_w(fctx *c, const wconst *w, zmode m, bool aligned, bool a8c, const rs_job *j, rs_tile *t,
                           const rs_prim *p, const float *a, const xcols *xc, float *drow, uint32_t *crow, int gmax,
                           int gx, ptrdiff_t xi, int y, int lo, int hi, bool full, const v8f *yv, uint64_t *tested)
{
    if (m.plain && (!aligned || gx <= gmax)) {
        const v8i lanes = full ? bi(-1) : lanes_between(lo, hi);
        frag_w(c, w, m, a8c, false, 0, lanes, drow + xi, crow + xi, xc->zx + xi, xc->sx + xi, xc->q1x + xi, xc->q2x + xi,
               yv[0], yv[1], yv[2], yv[3]);
    } else { /* (span8 counts its pixels as tested) */
        if (m.plain) *tested -= (uint64_t)(hi - lo);
        span8(j, t, p, a, gx, y, lane_range(lo, hi - 1));
    }
}

/* The interval walk of the box [x0, x1] x [y0, y1] (at most BAND x BAND, inside tile t): per row the covered
 * interval (row_spans), then groups of 8 columns over it, lanes masked to it (the full ones between without a mask):
 * aligned, 8-aligned groups (no loads across cache lines; groups past the target's right end through span8); else
 * groups from the interval's first column, moved left to stay in the tile (tile at least 8 wide), so that a short
 * row is one group.  a8c: c has a colour slot with a constant alpha (frag_w). */
ALWAYS_INLINE void walk_iv(fctx *c, zmode m, bool aligned, bool a8c, const rs_job *j, rs_tile *t, const rs_prim *p,
                           const float *a, int x0, int y0, int x1, int y1)
{
    const rs_tri *tr = c->tr;
    const int nr = y1 - y0 + 1;
    RS_ASSERT(nr <= BAND && x1 - x0 < BAND && x0 >= t->x0 && x1 < t->x1);
    spans sp;
    row_spans(j, tr, !aligned, x0, y0, x1 - x0 + 1, nr, &sp);
    const int32_t *const l = sp.l, *const n = sp.n;
    RS_ASSERT(spans_exact(j, tr, x0, y0, x1, nr, l, n));
    const int bx = aligned ? x0 & ~7 : x0; /* xcols' column 0 */
    /* aligned: the last group of 8 existing pixels; else: the last group start inside the box and the tile, so
     * that no group reads columns past x1 (then xcols holds the box's columns only) */
    const int gmax = aligned ? j->rt->width - 8 : t->x1 - 8 < x1 - 7 ? t->x1 - 8 : x1 - 7;
    RS_ASSERT(aligned || gmax >= x0);
    xcols xc;
    xcols_fill(&xc, j, tr, bx, aligned ? (x1 - bx) / 8 + 1 : (x1 - x0 + 8) / 8);
    yrows yr;
    yrows_fill(&yr, j, tr, y0, nr);
    wconst w;
    { /* (white without a colour slot, or not plain: then w is not read) */
        static const float none[12];
        const float *q = c->pc ? c->pc : none;
        w.k[0] = bf(q[0]), w.k[1] = bf(q[1]), w.k[2] = bf(q[2]), w.k[3] = bf(q[3]);
        w.k[4] = bf(q[4]), w.k[5] = bf(q[5]), w.k[6] = bf(q[6]), w.k[7] = bf(q[7]);
        w.k[8] = bf(q[8]), w.k[9] = bf(q[9]), w.k[10] = bf(q[10]), w.k[11] = bf(q[11]);
        w.a8 = bi(c->a8);
    }
    const size_t o0 = fidx(c, bx, y0);
    float *drow = c->depth + o0;
    uint32_t *crow = c->color + o0;
    uint64_t tested = 0;
#define GROUP(lo, hi, full) group_w(c, &w, m, aligned, a8c, j, t, p, a, &xc, drow, crow, gmax, gx, xi, y0 + i, lo, hi, \
                                    full, yv, &tested)
    for (int i = 0; i < nr; i++, drow += c->w, crow += c->w) {
        int k = n[i];
        if (k <= 0) continue;
        if (m.plain) tested += (uint64_t)k; /* (span8 counts its own) */
        const int g = x0 + l[i]; /* the first covered column */
        int gx = aligned ? g & ~7 : g < gmax ? g : gmax;
        const int lo = g - gx;
        ptrdiff_t xi = gx - bx;
        if (!aligned && m.plain && k <= 4 && i + 1 < nr && n[i + 1] > 0 && n[i + 1] <= 4) { /* two short rows */
            /* one group: 4 columns of each from its first covered one, moved left to end at x1 at most (so inside
             * the box, the tile and xcols) */
            const int k2 = n[i + 1], a0 = l[i], b0 = l[i + 1], wb = x1 - x0 + 1;
            const int ua = sp.u[i], ub = sp.u[i + 1];
            RS_ASSERT(ua == (a0 < wb - 4 ? a0 : wb - 4) && ub == (b0 < wb - 4 ? b0 : wb - 4));
            RS_ASSERT(ua >= 0 && x0 + ua + 4 <= t->x1 && x0 + ub + 4 <= t->x1);
            const v8i lanes = (v8i)_mm256_loadu2_m128i((const __m128i *)(runs_tab + 8 + sp.p[i + 1]),
                                                       (const __m128i *)(runs_tab + 8 + sp.p[i]));
            frag_w(c, &w, m, a8c, true, ub - ua, lanes, drow + ua, crow + ua, xc.zx + ua, xc.sx + ua, xc.q1x + ua,
                   xc.q2x + ua, rows2(yr.zy + i), rows2(yr.sy + i), rows2(yr.q1y + i), rows2(yr.q2y + i));
            tested += (uint64_t)k2;
            i++, drow += c->w, crow += c->w;
            continue;
        }
        const v8f yv[4] = {bf(yr.zy[i]), bf(yr.sy[i]), bf(yr.q1y[i]), bf(yr.q2y[i])};
#define FRAG(lanes, at) frag_w(c, &w, m, a8c, false, 0, lanes, drow + (at), crow + (at), xc.zx + (at), xc.sx + (at), \
                               xc.q1x + (at), xc.q2x + (at), yv[0], yv[1], yv[2], yv[3])
        if (!aligned && m.plain) { /* per group the row's next 8 columns from lr, the group moved left to end at
                                    * wr + 8 at most, its lanes masked to [lr, e) by the rest's run (which is
                                    * row k - 8's entry 8 - (lr + 8) after each group: one constant step) */
            RS_ASSERT(bx == x0 && k <= 8 * SPAN_GROUPS && sp.r[i] == k * RUNW - l[i]);
            const int32_t *run = runs_tab + 8 + sp.r[i]; /* row k's entry 8 - l[i] */
            const ptrdiff_t e = l[i] + k, wr = gmax - bx;
            for (ptrdiff_t lr = l[i];;) {
                const ptrdiff_t s = lr < wr ? lr : wr;
                FRAG(run_lanes(run, s), s);
                lr += 8;
                if (lr >= e) break;
                run -= 8 * (RUNW + 1);
            }
            continue;
        }
        if (!aligned) { /* groups of 8 from gx (<= gmax), the one past gmax moved left: one masked group site */
            const int end = g + k;
            for (int lw = lo;;) {
                GROUP(lw, end - gx < 8 ? end - gx : 8, false);
                gx += 8, xi += 8;
                if (gx >= end) break;
                lw = gx > gmax ? gx - gmax : 0;
                gx -= lw, xi -= lw;
            }
            continue;
        }
        const int last = (g + k - 1) & ~7; /* aligned: the row's last group */
        if (m.plain && last <= gmax) { /* all through frag_w: no span8 test per group, the middle ones unmasked */
            if (lo + k <= 8) {
                FRAG(lanes_between(lo, lo + k), xi);
                continue;
            }
            FRAG(lanes_between(lo, 8), xi);
            const ptrdiff_t xl = xi + (last - gx);
            for (xi += 8; xi < xl; xi += 8)
                FRAG(bi(-1), xi);
            FRAG(lanes_between(0, g + k - last), xi);
            continue;
        }
#undef FRAG
        if (lo + k <= 8) { /* one group */
            GROUP(lo, lo + k, false);
            continue;
        }
        GROUP(lo, 8, false);
        k -= 8 - lo;
        for (;;) { /* k > 0 pixels from column gx + 8 */
            gx += 8, xi += 8;
            if (!aligned && gx > gmax) { /* at the tile's end: the group moved left, lanes [s, s + k) */
                const int s = gx - gmax;
                gx -= s, xi -= s;
                GROUP(s, s + k, false);
                break;
            }
            if (k < 8) {
                GROUP(0, k, false);
                break;
            }
            GROUP(0, 8, true);
            if (!(k -= 8)) break;
        }
    }
#undef GROUP
    c->tested += tested;
}

/* ---- the instances ---- */

/* Triangle p's box [x0, x1] x [y0, y1] of tile t through the interval walk from each row's first column (box at
 * most 32 wide and, coef_small, at most 33 tall; tile at least 8 wide). */
ALWAYS_INLINE void walk_span(zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0,
                             int y0, int x1, int y1)
{
    fctx c;
    fctx_make(&c, j, t, p, a);
    if (c.pc && c.a8 >= 0) walk_iv(&c, m, false, true, j, t, p, a, x0, y0, x1, y1);
    else walk_iv(&c, m, false, false, j, t, p, a, x0, y0, x1, y1);
    t->tested += c.tested;
    t->written += c.written;
}

/* The same with 8-aligned groups, in bands of BAND x BAND aligned to the tile's grid (any box inside tile t). */
ALWAYS_INLINE void walk_big(zmode m, const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0,
                            int x1, int y1)
{
    fctx c;
    fctx_make(&c, j, t, p, a);
    for (int b = y0; b <= y1; b += BAND) { /* rows in bands, each in column bands of the tile's 64-grid */
        const int b1 = y1 - b < BAND ? y1 : b + BAND - 1;
        for (int u = x0; u <= x1; u = (u | (BAND - 1)) + 1) {
            const int u1 = (u | (BAND - 1)) < x1 ? (u | (BAND - 1)) : x1;
            if (c.pc && c.a8 >= 0) walk_iv(&c, m, true, true, j, t, p, a, u, b, u1, b1);
            else walk_iv(&c, m, true, false, j, t, p, a, u, b, u1, b1);
        }
    }
    t->tested += c.tested;
    t->written += c.written;
}

INSTANCES(span, walk_span)
INSTANCES(big, walk_big)

typedef void walk_fn(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1, int y1);
/* walks[walk - 1][mode]: rs_tri_fast's walk 1 and 2 (box at most 16, 32 wide) from each row's first column, 3
 * 8-aligned; mode: the job's span_mode (0 LESSEQUAL, 1 LESS, 2 any). */
static walk_fn *const walks[3][3] = {
    {span_le, span_less, span_any},
    {span_le, span_less, span_any},
    {big_le, big_less, big_any},
};

void RS_KERNEL(rs_tri_wide)(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                            int y1, int walk)
{
    RS_ASSERT(walk >= 1 && walk <= 3);
    walks[walk - 1][j->span_mode](j, t, p, a, x0, y0, x1, y1);
}

#else /* without AVX2 every draw takes the reference path (rs_span_ok is false) */

void RS_KERNEL(rs_tri_wide)(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                            int y1, int walk)
{
}

#endif
