/* web/trig_table.c -- run natively by `make web`: the native C library's sinf, cosf, tanf and tan at the angles
 * the page's controls produce, as C tables for web/libm.c.
 *
 * Why: the C libraries disagree in the last bit of these functions (glibc 2.36 on x86-64-v3 runs its FMA
 * variants of sinf and cosf and Sun's tanf kernel; wasi-libc and emscripten run musl's): of the 7201 angles
 * -360..360 degrees in tenths, glibc's sinf differs from musl's at 94, cosf at 92, tanf at 952.  The
 * camera's matrices (cli/run/scene.c's make_camera, core/math.c) take those bits, and a last-bit change moves an
 * edge across a sample now and then.  The page's controls give whole degrees (yaw, pitch -360..360, field of
 * view 1..170), so the page can take the native values for exactly those arguments: the keys below are the
 * expressions make_camera, mat_perspective_fov_lh and box_fit_distance evaluate (PI_F as cli/run/scene.c has it).
 * Other arguments fall back to the browser build's own functions (web/libm.c).
 *
 * Output (stdout): for each function a sorted array of argument bits and an array of result bits. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI_F 3.14159265358979f   /* cli/run/scene.c */

typedef struct entry { uint64_t key, value; } entry;

static int by_key(const void *a, const void *b)
{
    uint64_t x = ((const entry *)a)->key, y = ((const entry *)b)->key;
    return (x > y) - (x < y);
}

static uint64_t fbits(float f) { uint32_t u; memcpy(&u, &f, 4); return u; }
static uint64_t dbits(double d) { uint64_t u; memcpy(&u, &d, 8); return u; }

/* Sort e[0..n), drop repeated keys, print as NAME_key[] and NAME_value[] of type T. */
static void emit(const char *name, const char *type, entry *e, size_t n)
{
    qsort(e, n, sizeof *e, by_key);
    size_t m = 0;
    for (size_t k = 0; k < n; k++)
        if (m == 0 || e[k].key != e[m - 1].key) e[m++] = e[k];
    printf("#define %s_N %zu\nstatic const %s %s_key[%zu] = {", name, m, type, name, m);
    for (size_t k = 0; k < m; k++) printf("%s0x%llx", k % 6 ? ", " : ",\n    " + (k == 0), (unsigned long long)e[k].key);
    printf("};\nstatic const %s %s_value[%zu] = {", type, name, m);
    for (size_t k = 0; k < m; k++) printf("%s0x%llx", k % 6 ? ", " : ",\n    " + (k == 0), (unsigned long long)e[k].value);
    printf("};\n");
}

int main(void)
{
    enum { DEG = 721, FOV = 170 };
    entry s[DEG], c[DEG], tf[FOV], td[FOV];
    for (int d = -360; d <= 360; d++) {   /* make_camera: mat_rotation_y(yaw * PI_F / 180), mat_rotation_x(pitch ...) */
        float a = (float)d * PI_F / 180.0f;
        s[d + 360] = (entry){fbits(a), fbits(sinf(a))};
        c[d + 360] = (entry){fbits(a), fbits(cosf(a))};
    }
    for (int f = 1; f <= FOV; f++) {
        float fovy = (float)f / 180.0f * PI_F, half = fovy * 0.5f;   /* mat_perspective_fov_lh's tanf(fovy * 0.5f) */
        double box = (float)f * PI_F / 360.0;                       /* box_fit_distance's tan(fov_deg * PI_F / 360.0) */
        tf[f - 1] = (entry){fbits(half), fbits(tanf(half))};
        td[f - 1] = (entry){dbits(box), dbits(tan(box))};
    }
    printf("/* made by web/trig_table.c with the native C library: do not edit */\n");
    emit("web_sinf", "uint32_t", s, DEG);
    emit("web_cosf", "uint32_t", c, DEG);
    emit("web_tanf", "uint32_t", tf, FOV);
    emit("web_tan", "uint64_t", td, FOV);
    return 0;
}
