/* web/libm.c -- sinf, cosf, tanf and tan for the browser build: the native C library's results at the angles
 * the page's controls produce (tables made by web/trig_table.c at build time; it says why), the browser build's
 * own elsewhere.  These definitions take the place of the C library's in the page's static link.  Elsewhere:
 * sinf and cosf correctly rounded through double (musl's sin and cos), tan through long double. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "trig_table.h"

/* Index of key in the sorted keys[0..n), or -1. */
static long find32(const uint32_t *keys, size_t n, uint32_t key)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (keys[mid] < key) lo = mid + 1;
        else hi = mid;
    }
    return lo < n && keys[lo] == key ? (long)lo : -1;
}
static long find64(const uint64_t *keys, size_t n, uint64_t key)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (keys[mid] < key) lo = mid + 1;
        else hi = mid;
    }
    return lo < n && keys[lo] == key ? (long)lo : -1;
}

/* The table's value for float x, or NAN-free fallback when x is not a key. */
static float from_table(const uint32_t *keys, const uint32_t *values, size_t n, float x, float fallback)
{
    uint32_t u;
    memcpy(&u, &x, 4);
    long k = find32(keys, n, u);
    if (k < 0) return fallback;
    float r;
    memcpy(&r, &values[k], 4);
    return r;
}

float sinf(float x) { return from_table(web_sinf_key, web_sinf_value, web_sinf_N, x, (float)sin((double)x)); }
float cosf(float x) { return from_table(web_cosf_key, web_cosf_value, web_cosf_N, x, (float)cos((double)x)); }
float tanf(float x) { return from_table(web_tanf_key, web_tanf_value, web_tanf_N, x, (float)tan((double)x)); }

double tan(double x)
{
    uint64_t u;
    memcpy(&u, &x, 8);
    long k = find64(web_tan_key, web_tan_N, u);
    if (k < 0) return (double)tanl((long double)x);
    double r;
    memcpy(&r, &web_tan_value[k], 8);
    return r;
}
