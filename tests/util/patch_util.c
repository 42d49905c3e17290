/* tests/util/patch_util.c -- random triangles and small helpers shared by the patch tests. */
#include "patch_util.h"

#include <math.h>
#include <string.h>

float frand(uint64_t *s)
{
    *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
    return (float)((*s * 2685821657736338717ull) >> 40) / (float)(1u << 23) - 1.0f;
}

float3 rand3(uint64_t *s) { return f3(frand(s), frand(s), frand(s)); }

bool same3(float3 a, float3 b) { return memcmp(&a, &b, sizeof a) == 0; }

vs_triangle rand_tri(uint64_t *s)
{
    float3 v[3] = {rand3(s), rand3(s), rand3(s)}, n[3];
    float3 up = normalize3(cross3(sub3(v[1], v[0]), sub3(v[2], v[0])));
    for (int k = 0; k < 3; k++) n[k] = normalize3(add3(up, scale3(rand3(s), 0.5f)));
    vs_triangle t = vs_triangle_make(v, n);
    for (int k = 0; k < 3; k++) {
        float3 mid = scale3(add3(v[k], v[(k + 1) % 3]), 0.5f), third = v[(k + 2) % 3];
        t.opp[k] = add3(add3(mid, sub3(mid, third)), scale3(up, frand(s)));
    }
    return t;
}

void to_d(const vs_triangle *t, double v[3][3], double n[3][3], double opp[3][3])
{
    for (int k = 0; k < 3; k++) {
        v[k][0] = t->v[k].x, v[k][1] = t->v[k].y, v[k][2] = t->v[k].z;
        n[k][0] = t->n[k].x, n[k][1] = t->n[k].y, n[k][2] = t->n[k].z;
        opp[k][0] = t->opp[k].x, opp[k][1] = t->opp[k].y, opp[k][2] = t->opp[k].z;
    }
}

double dist_d(float3 a, const double b[3])
{
    double x = a.x - b[0], y = a.y - b[1], z = a.z - b[2];
    return sqrt(x * x + y * y + z * z);
}

vs_triangle rotate(const vs_triangle *t, int r)
{
    vs_triangle o = *t;
    for (int k = 0; k < 3; k++) {
        int j = (k + r) % 3;
        o.v[k] = t->v[j], o.n[k] = t->n[j], o.opp[k] = t->opp[j], o.t[k] = t->t[j];
        o.nadj[k][0] = t->nadj[j][0], o.nadj[k][1] = t->nadj[j][1];
    }
    return o;
}
