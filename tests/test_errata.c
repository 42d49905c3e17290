/* tests/test_errata.c -- one test per erratum of docs/design.md, section 4 (see docs/errata.md): each shows what the
 * printed text would do and that vs/ does what the equations say. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "../vs/vs.h"
#include "util/patch_util.h"
#include "util/pn_ref.h"

#include "../core/hlsl.h"
#include <stdio.h>
#include <stdlib.h>

/* x as docs/errata.md writes a measurement: two significant digits, "1.4e-7". */
static const char *sci(double x, char buf[24])
{
    char e[24];
    snprintf(e, sizeof e, "%.1e", x);                      /* "1.4e-07" */
    char *p = strchr(e, 'e');
    if (!p) return strcpy(buf, e);
    int exp = atoi(p + 1);
    *p = 0;
    snprintf(buf, 24, "%.4se%d", e, exp);   /* "-1.4" at most, then the exponent */
    return buf;
}

#if defined(__clang__)
/* Every number of s (a run of digits, '.', 'e' and signs holding a digit) replaced by '#', in place. */
static void mask_numbers(char *s)
{
    size_t w = 0;
    for (size_t r = 0; s[r];) {
        size_t e = r;
        bool digit = false;
        while (s[e] && (strchr("0123456789.", s[e]) || ((s[e] == 'e' || s[e] == '-' || s[e] == '+') && e > r)))
            digit |= s[e] >= '0' && s[e] <= '9', e++;
        if (digit) s[w++] = '#', r = e;
        else s[w++] = s[r++];
    }
    s[w] = 0;
}
#endif

/* Whether docs/errata.md states the phrase (printf-formatted), line breaks read as spaces: the numbers the
 * document quotes are the ones these tests measure (README, docs/errata.md: "can be checked"). */
static bool doc_says(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static bool doc_says(const char *fmt, ...)
{
    char phrase[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(phrase, sizeof phrase, fmt, ap);
    va_end(ap);
    FILE *f = fopen("docs/errata.md", "r");
    if (!f) return fprintf(stderr, "docs/errata.md: cannot read it (run from the repository's root)\n"), false;
    static char text[65536];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    size_t w = 0;
    for (size_t r = 0; r < n; r++) {
        char c = text[r] == '\n' ? ' ' : text[r];
        if (c == ' ' && w > 0 && text[w - 1] == ' ') continue;
        text[w++] = c;
    }
    text[w] = 0;
    bool ok = strstr(text, phrase) != NULL;
#if defined(__clang__)
    /* The document's numbers are the goldens' build's (gcc, README "The build configuration"): clang (the sanitizer
     * stage) rounds some float expressions differently, so here the phrase must be there with its numbers masked. */
    if (!ok) {
        mask_numbers(text);
        mask_numbers(phrase);
        ok = strstr(text, phrase) != NULL;
        if (ok) fprintf(stderr, "docs/errata.md: \"%s\" found with other numbers (they are gcc's)\n", phrase);
    }
#endif
    if (!ok) fprintf(stderr, "docs/errata.md does not say \"%s\" (measured now)\n", phrase);
    return ok;
}

/* Erratum 1: evaluateCurve / evaluateNPatch drop the /3 of the control points and the 3 of the weights: the same
 * surface as the canonical Bernstein form (double); Eq. 1.1.1's printed b111 (five tangent points) is not. */
static void test_erratum1_missing_thirds(void **state)
{
    (void)state;
    uint64_t s = 101;
    double worst_curve = 0, worst_patch = 0, printed_min = 1e30;
    for (int trial = 0; trial < 300; trial++) {
        vs_triangle t = rand_tri(&s);
        double v[3][3], n[3][3], opp[3][3], r[3];
        to_d(&t, v, n, opp);
        for (int i = 0; i <= 16; i++) {
            double u = i / 16.0;
            pn_ref_curve(v[0], v[1], n[0], n[1], u, r);
            double d = dist_d(vs_evaluate_curve(t.v[0], t.v[1], t.n[0], t.n[1], (float)u), r);
            if (d > worst_curve) worst_curve = d;
        }
        for (int j = 1; j < 12; j++)
            for (int i = 1; i + j < 12; i++) {
                double b[3] = {(12.0 - i - j) / 12, i / 12.0, j / 12.0};
                pn_ref_npatch(v, n, b, r);
                float3 p = vs_evaluate_npatch(t.v[0], t.v[1], t.v[2], t.n[0], t.n[1], t.n[2], f3((float)b[0], (float)b[1], (float)b[2]));
                double d = dist_d(p, r);
                if (d > worst_patch) worst_patch = d;
                /* Eq. 1.1.1 as printed: b111 = 3 (b210 + b120 + b021 + b102 + b201) / 12 - (v0 + v1 + v2) / 6 */
                double c[4][4][3], pr[3];
                pn_ref_control_points(v, n, c);
                for (int k = 0; k < 3; k++) {
                    double printed = 3.0 * (c[2][1][k] + c[1][2][k] + c[0][2][k] + c[1][0][k] + c[2][0][k]) / 12.0 -
                                     (v[0][k] + v[1][k] + v[2][k]) / 6.0;
                    pr[k] = r[k] + 6.0 * (printed - c[1][1][k]) * b[0] * b[1] * b[2];
                }
                if (i == 4 && j == 4) printed_min = fmin(printed_min, dist_d(p, pr)); /* at the centre */
            }
    }
    print_message("erratum 1: curve %.2g, N-Patch %.2g from the canonical form; printed b111 off at the centre by >= %.2g\n",
                  worst_curve, worst_patch, printed_min);
    assert_true(worst_curve < 1e-5 && worst_patch < 1e-5);
    assert_true(printed_min > 1e-3);
    char a[24], b[24], c[24];
    assert_true(doc_says("measured %s for the curve, %s for the N-Patch", sci(worst_curve, a), sci(worst_patch, b)));
    assert_true(doc_says("off by at least %s at the centre", sci(printed_min, c)));
}

/* The intermediate patch as printed in Listing 1.1.1 with a chosen reading of the typos: norm1's parameter
 * (c.v: c.y or, wrongly, c.x) and norm2's (c2.z: c.z or, wrongly, c.y). */
static float3 listing_initial(const vs_triangle *t, float3 b, int norm1_param, int norm2_param)
{
    float3 v0 = t->v[0], v1 = t->v[1], v2 = t->v[2], n0 = t->n[0], n1 = t->n[1], n2 = t->n[2];
    float sum = b.x * b.z + b.x * b.y + b.y * b.z;
    float3 g = f3(b.x * b.z / sum, b.x * b.y / sum, b.y * b.z / sum);
    float c[3] = {b.y / (1.0f - b.z), b.z / (1.0f - b.x), b.x / (1.0f - b.y)};
    float3 pos0 = vs_evaluate_curve(v0, v1, n0, n1, c[0]);
    float3 pos1 = vs_evaluate_curve(v1, v2, n1, n2, c[1]);
    float3 pos2 = vs_evaluate_curve(v2, v0, n2, n0, c[2]);
    float3 norm0 = normalize3(lerp3(n0, n1, c[0]));
    float3 norm1 = normalize3(lerp3(n1, n2, c[norm1_param]));
    float3 norm2 = normalize3(lerp3(n2, n0, c[norm2_param]));
    pos0 = vs_evaluate_curve(pos0, v2, norm0, n2, b.z);
    pos1 = vs_evaluate_curve(pos1, v0, norm1, n0, b.x);
    pos2 = vs_evaluate_curve(pos2, v1, norm2, n1, b.y);
    return add3(add3(scale3(pos2, g.x), scale3(pos0, g.y)), scale3(pos1, g.z));
}

/* Erratum 2: c.v is c.y and c2.z is c.z (the readings that match Eq. 1.1.7 and the reference); `float b1 =
 * 3*3*3*...` is bl = 27 b0 b1 b2, which is 1 at the centre, where the final patch is the N-Patch. */
static void test_erratum2_typos(void **state)
{
    (void)state;
    uint64_t s = 202;
    double ours = 0, wrong_y = 1e30, wrong_z = 1e30, centre = 0;
    for (int trial = 0; trial < 200; trial++) {
        vs_triangle t = rand_tri(&s);
        double v[3][3], n[3][3], opp[3][3], r[3];
        to_d(&t, v, n, opp);
        float3 b = f3(0.2f, 0.3f, 0.5f);
        double bd[3] = {b.x, b.y, b.z};
        pn_ref_smooth_initial(v, n, bd, r);
        ours = fmax(ours, dist_d(vs_smooth_initial_formula(&t, b, NULL), r));
        ours = fmax(ours, dist_d(listing_initial(&t, b, 1, 2), r));
        wrong_y = fmin(wrong_y, dist_d(listing_initial(&t, b, 0, 2), r));
        wrong_z = fmin(wrong_z, dist_d(listing_initial(&t, b, 1, 1), r));
        float3 c3 = f3(1.0f / 3, 1.0f / 3, 1.0f / 3);
        float3 pn = vs_evaluate_npatch(t.v[0], t.v[1], t.v[2], t.n[0], t.n[1], t.n[2], c3);
        centre = fmax(centre, length3(sub3(vs_smooth_formula(&t, c3, 0, NULL, NULL), pn)));
    }
    print_message("erratum 2: ours %.2g; reading c.v as c.x off by >= %.2g, c2.z as c.y by >= %.2g; centre %.2g\n",
                  ours, wrong_y, wrong_z, centre);
    assert_true(ours < 1e-5 && centre < 1e-5);
    char a[24], b[24], c[24];
    assert_true(doc_says("within 1e-5 (measured %s)", sci(ours, a)));
    assert_true(doc_says("by at least %s and %s", sci(wrong_y, b), sci(wrong_z, c)));
    assert_true(centre == 0 && doc_says("(measured difference 0)"));
    assert_true(wrong_y > 1e-6 && wrong_z > 1e-6); /* (some triangles barely notice; the minimum is still > 0) */
}

/* Erratum 3: fn_k = |dot(own face normal, face normal across edge k)|, pos0 / edge v0-v1 (g.y), pos1 / v1-v2
 * (g.z), pos2 / v2-v0 (g.x); a garbled pairing gives another surface. */
static void test_erratum3_fn_pairing(void **state)
{
    (void)state;
    float3 v[3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
    float3 up = f3(0, 0, 1);
    float3 n[3] = {normalize3(f3(-1, -1, 1)), normalize3(f3(1, -0.2f, 1)), normalize3(f3(-0.2f, 1, 1))};
    vs_triangle t = vs_triangle_make(v, n);
    t.opp[0] = f3(1, -2, 0);              /* across v0-v1: coplanar -> fn0 = 1  */
    t.opp[1] = f3(1, 1, -2);              /* across v1-v2: folded 90 deg -> 0 */
    t.opp[2] = f3(-1, 1, 1);              /* across v2-v0: folded 45 deg -> 0.7071 */
    (void)up;
    float3 fn = vs_smooth_fn(&t);
    assert_true(fn.x == 1.0f);
    assert_true(fabsf(fn.y) < 1e-6f);
    assert_true(fabsf(fn.z - sqrtf(0.5f)) < 1e-6f);
    /* Gregory: g.y is 1 on edge v0-v1, g.z on v1-v2, g.x on v2-v0 */
    assert_true(same3(vs_gregory(f3(0.25f, 0.75f, 0)), f3(0, 1, 0)));
    assert_true(same3(vs_gregory(f3(0, 0.25f, 0.75f)), f3(0, 0, 1)));
    assert_true(same3(vs_gregory(f3(0.75f, 0, 0.25f)), f3(1, 0, 0)));
    /* the patch follows the correct pairing; shifting the pairing (opp_k -> edge k+1) changes it */
    double vd[3][3], nd[3][3], od[3][3], shifted[3][3], r[3], rs[3];
    to_d(&t, vd, nd, od);
    for (int k = 0; k < 3; k++) memcpy(shifted[k], od[(k + 2) % 3], sizeof shifted[k]);
    double ours = 0, garbled = 0;
    for (int j = 1; j < 8; j++)
        for (int i = 1; i + j < 8; i++) {
            double b[3] = {(8.0 - i - j) / 8, i / 8.0, j / 8.0};
            pn_ref_smooth(vd, nd, od, b, r);
            pn_ref_smooth(vd, nd, shifted, b, rs);
            float3 p = vs_patch_position(VS_PATCH_SMOOTH, &t, f3((float)b[0], (float)b[1], (float)b[2]), NULL);
            ours = fmax(ours, dist_d(p, r));
            garbled = fmax(garbled, dist_d(p, rs));
        }
    print_message("erratum 3: ours %.2g from the reference, garbled pairing %.2g\n", ours, garbled);
    assert_true(ours < 1e-5 && garbled > 1e-3);
    char a[24], b[24];
    assert_true(doc_says("matches the reference (%s) and a shifted pairing gives a different surface (%s)",
                         sci(ours, a), sci(garbled, b)));
}

/* The listing's unguarded Gregory weight at a corner, as C computes it: 0/0 = NaN.  Computing that NaN is the
 * point, so UBSan's float-divide-by-zero check (on in make sanitize) is off for this one function. */
#ifdef __clang__
__attribute__((no_sanitize("float-divide-by-zero")))
#endif
static float unguarded_gregory(float z)
{
    return z * z / (z * z + z * z);
}

/* Erratum 4: Gregory 0/0 at corners and the curve parameters' division by zero give NaN in C; the guards give
 * finite values converging to the vertex, continuous across the listing's 0.999 threshold. */
static void test_erratum4_division_guards(void **state)
{
    (void)state;
    volatile float zero = 0.0f;
    assert_true(isnan(unguarded_gregory(zero))); /* what the unguarded listing computes in C */
    uint64_t s = 404;
    vs_triangle t = rand_tri(&s);
    float3 corners[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int k = 0; k < 3; k++) {
        float3 g = vs_gregory(corners[k]);
        assert_true(isfinite(g.x) && isfinite(g.y) && isfinite(g.z) && g.x + g.y + g.z == 1.0f);
        float3 g0, p0 = vs_smooth_initial_formula(&t, corners[k], &g0), p1 = vs_smooth_formula(&t, corners[k], 0, NULL, NULL);
        assert_true(length3(sub3(p0, t.v[k])) < 1e-6f && length3(sub3(p1, t.v[k])) < 1e-6f);
    }
    /* approaching a corner: finite and converging */
    for (int e = 3; e <= 40; e++) {
        float eps = powf(10.0f, -(float)e);
        float3 b = f3(1.0f - eps, 0.5f * eps, 0.5f * eps);
        if (b.x == 1.0f) b.x = nextafterf(1.0f, 0.0f);
        for (int p = 0; p < VS_PATCH_COUNT; p++) {
            float3 pos = vs_patch_position((vs_patch)p, &t, b, NULL);
            assert_true(isfinite(pos.x) && isfinite(pos.y) && isfinite(pos.z));
            assert_true(length3(sub3(pos, t.v[0])) < 20.0f * fmaxf(eps, 1e-7f));
        }
    }
    /* the listing snaps g to (1, 0, 0) where b.x > 0.999; ours needs no threshold and is continuous there (the
     * snap itself is harmless: P0, P1, P2 agree to ~1e-7 that close to a corner) */
    float xb = nextafterf(0.999f, 0.0f), xa = nextafterf(0.999f, 1.0f); /* one float step on each side */
    float3 below = f3(xb, 0.0009f, 1.0f - xb - 0.0009f), above = f3(xa, 0.0009f, 1.0f - xa - 0.0009f);
    float3 pb = vs_smooth_initial_formula(&t, below, NULL), pa = vs_smooth_initial_formula(&t, above, NULL);
    /* the snapped value is pos2 alone (g.x = 1) */
    float cz = above.x / (1.0f - above.y);
    float3 pos2 = vs_evaluate_curve(t.v[2], t.v[0], t.n[2], t.n[0], cz);
    pos2 = vs_evaluate_curve(pos2, t.v[1], normalize3(lerp3(t.n[2], t.n[0], cz)), t.n[1], above.y);
    float ours = length3(sub3(pa, pb)), listing = length3(sub3(pos2, pb));
    print_message("erratum 4: step across b0 = 0.999: ours %.2g, listing's snap %.2g\n", ours, listing);
    assert_true(ours < 1e-6f && listing < 1e-5f);
    char a[24], b[24];
    assert_true(doc_says("moves the surface by %s (continuous; the listing's snap to the vertex there moves it by %s)",
                         sci(ours, a), sci(listing, b)));
}

/* Erratum 5: a boundary (or non-manifold) edge gives opp_k = own third vertex, and then fn_k is exactly 1 (the
 * naive face normal of (v1, v0, v2) is not always exactly parallel in float); the patch is the N-Patch there. */
static void test_erratum5_boundary(void **state)
{
    (void)state;
    uint64_t s = 505;
    int naive_not_one = 0;
    for (int trial = 0; trial < 500; trial++) {
        vs_triangle t = rand_tri(&s);
        for (int k = 0; k < 3; k++) t.opp[k] = t.v[(k + 2) % 3];
        float3 fn = vs_smooth_fn(&t);
        assert_true(fn.x == 1.0f && fn.y == 1.0f && fn.z == 1.0f);
        float3 nf = normalize3(cross3(sub3(t.v[1], t.v[0]), sub3(t.v[2], t.v[0])));
        float3 nn = normalize3(cross3(sub3(t.v[0], t.v[1]), sub3(t.v[2], t.v[1])));
        if (fabsf(dot3(nf, nn)) != 1.0f) naive_not_one++;
        for (int j = 0; j <= 6; j++)
            for (int i = 0; i + j <= 6; i++) {
                float3 b = f3((6.0f - i - j) / 6, i / 6.0f, j / 6.0f);
                assert_true(same3(vs_patch_position(VS_PATCH_SMOOTH, &t, b, NULL), vs_patch_position(VS_PATCH_NPATCH, &t, b, NULL)));
            }
    }
    /* a degenerate neighbour (opp on the edge's line) carries no information: fn = 1 as well */
    vs_triangle t = rand_tri(&s);
    t.opp[1] = lerp3(t.v[1], t.v[2], 2.0f);
    assert_true(vs_smooth_fn(&t).y == 1.0f);
    print_message("erratum 5: naive |dot| of a triangle with itself is not exactly 1 in %d of 500\n", naive_not_one);
    assert_true(naive_not_one > 0);
    assert_true(doc_says("not exactly 1 for %d of 500 random triangles", naive_not_one));
}

/* Erratum 6: the naive evaluation of the same edge point from the two triangles differs in the last bits; the
 * canonical edge evaluation never does. */
static void test_erratum6_watertight(void **state)
{
    (void)state;
    uint64_t s = 606;
    long naive_np = 0, naive_sm = 0, ours = 0, points = 0;
    for (int trial = 0; trial < 300; trial++) {
        float3 P = rand3(&s), Q = rand3(&s), R = rand3(&s), S = rand3(&s);
        float3 up = normalize3(cross3(sub3(Q, P), sub3(R, P)));
        float3 nP = normalize3(add3(up, scale3(rand3(&s), 0.5f))), nQ = normalize3(add3(up, scale3(rand3(&s), 0.5f)));
        float3 nR = normalize3(add3(up, scale3(rand3(&s), 0.5f))), nS = normalize3(add3(up, scale3(rand3(&s), 0.5f)));
        float3 va[3] = {P, Q, R}, na[3] = {nP, nQ, nR}, vb[3] = {S, Q, P}, nb[3] = {nS, nQ, nP};
        vs_triangle A = vs_triangle_make(va, na), B = vs_triangle_make(vb, nb);
        A.opp[0] = S, B.opp[1] = R; /* A's edge 0 (P, Q) is B's edge 1 (Q, P) */
        for (int L = 2; L <= 16; L++)
            for (int i = 1; i < L; i++, points++) {
                float s0 = (float)(L - i) / L, s1 = (float)i / L;
                float3 ba = f3(s0, s1, 0), bb = f3(0, s1, s0);
                naive_np += !same3(vs_evaluate_npatch(A.v[0], A.v[1], A.v[2], A.n[0], A.n[1], A.n[2], ba),
                                   vs_evaluate_npatch(B.v[0], B.v[1], B.v[2], B.n[0], B.n[1], B.n[2], bb));
                naive_sm += !same3(vs_smooth_formula(&A, ba, 0, NULL, NULL), vs_smooth_formula(&B, bb, 0, NULL, NULL));
                for (int p = 0; p < VS_PATCH_COUNT; p++)
                    ours += !same3(vs_patch_position((vs_patch)p, &A, ba, NULL), vs_patch_position((vs_patch)p, &B, bb, NULL));
            }
    }
    print_message("erratum 6: %ld edge points; naive N-Patch differs at %ld, naive smooth at %ld, ours at %ld\n",
                  points, naive_np, naive_sm, ours);
    assert_true(naive_np > points / 10 && naive_sm > points / 10);
    assert_int_equal(ours, 0);
    assert_true(doc_says("over %ld shared-edge points", points));
    assert_true(doc_says("differs in the bits at %ld and %ld points; ours at 0", naive_np, naive_sm));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_erratum1_missing_thirds),
        cmocka_unit_test(test_erratum2_typos),
        cmocka_unit_test(test_erratum3_fn_pairing),
        cmocka_unit_test(test_erratum4_division_guards),
        cmocka_unit_test(test_erratum5_boundary),
        cmocka_unit_test(test_erratum6_watertight),
    };
    return cmocka_run_group_tests_name("errata", tests, NULL, NULL);
}
