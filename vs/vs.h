/* vs/vs.h -- the patch vertex shaders of instess (the one public header of vs/).
 *
 * Conventions (read these before anything else):
 *  - Shaders are plain C functions with the is_vs_fn contract of core/core.h; each reads like the HLSL listing
 *    it reproduces (seed 000, Listings 1.1.1 and 1.1.2; variable names b, g, c, pos0..2, norm0..2, fn0..2, bl,
 *    posN kept).  vs_find_shader(name) gives them by name: "flat", "npatch", "smooth-initial", "smooth",
 *    "phong", "pn-aen", plus "fixed" (transform and light only, for the device's N-patch mode).
 *  - Constant registers (fill them with vs_set_constants, upload c0..c[VS_C_COUNT-1]):
 *      c0..c3  g_mWorldViewProjection (row vectors: oPos = mul(float4(pos, 1), M))
 *      c4..c7  g_mWorld (its upper 3x3 transforms the normal, as the listing: no re-normalisation)
 *      c8      g_vDiffuse
 *      c9      options: x = normal mode (0 linear, 1 quadratic, 2 real), y = Phong shape factor alpha,
 *              z = quadratic-normal factor of v_ij (2: reflection, the default; 1.5: van Overveld; 0 reads as 2),
 *              w = flags (bit 0 VS_FLAG_NO_SHORTCUT: the smooth shader evaluates every P_k).
 *  - Input registers of the patch shaders (Listing 1.1.2's per-instance declaration, built by meshes/):
 *      POSITION0 = b = (b0, b1, b2), the barycentrics of the grid point; b.x weights v0, b.y v1, b.z v2.
 *      TEXCOORD0..2 = v0, v1, v2;  TEXCOORD3..5 = n0, n1, n2;  TEXCOORD6..8 = opp0, opp1, opp2;
 *      TEXCOORD9..11 = t0, t1, t2 (xy);  TEXCOORD12.x = instance id.
 *      Edge k joins v_k and v_(k+1)%3 (edge 0 = v0-v1, edge 1 = v1-v2, edge 2 = v2-v0); opp_k is the vertex of
 *      the triangle across edge k that is not on the edge.  On a boundary edge (and on a non-manifold edge,
 *      docs/design.md, erratum 5) opp_k is this triangle's own third vertex v_(k+2)%3: fn_k is then exactly 1.
 *      PN-AEN only (optional; absent registers read (0, 0, 0, 1) and mean "same normals as mine"):
 *      n_adj[k][j] = the normal that the triangle across edge k has at v_(k+j)%3 (j = 0, 1), in the registers
 *      of vs_nadj_regs[k][j]: TEXCOORD13..15 for j = 0 and NORMAL0, NORMAL1, TANGENT0 for j = 1 (18 floats do
 *      not fit in TEXCOORD13..15).  A boundary edge gives its own normals (or zeros).
 *  - Outputs (every patch shader writes all of them):
 *      oPos = mul(float4(pos, 1), g_mWorldViewProjection), pos the object-space patch point;
 *      COLOR0 = Diffuse = saturate(dot(Normal, (0, 0, -1))) * g_vDiffuse, Diffuse.w = 1, where
 *               Normal = mul(normal, (float3x3)g_mWorld) and normal is the object-space unit normal of the
 *               normal mode (linear: normalize(b0 n0 + b1 n1 + b2 n2), normalised then transformed, as listed);
 *      TEXCOORD0 = oTex = (b0 t0 + b1 t1 + b2 t2, 0, 1);
 *      TEXCOORD1 = normalize(Normal), the world-space unit normal used for lighting (AOV), w = 0;
 *      TEXCOORD2 = (b, 1) (AOV);  TEXCOORD3 = (instance id, 0, 0, 1) (AOV);
 *      TEXCOORD4 = (g.x, g.y, g.z, 0), the Gregory weights of the smoothed patches (AOV; 0 for the others).
 *  - Normal modes: linear = normalised linear interpolation of n0..n2 (D3DDEGREE_LINEAR); quadratic = Vlachos'
 *    quadratic normal patch n200 b0^2 + ... + n110 b0 b1 + ... with n110 = normalize(n0 + n1 - v01 (P1 - P0)),
 *    v01 = f dot(P1 - P0, n0 + n1) / dot(P1 - P0, P1 - P0), f = 2 (reflection) or 3/2 (van Overveld);
 *    real = normalize(cross(dP/du, dP/dv)) of the patch (seed 001, 3.2.2), oriented to agree with the linear
 *    normal: analytic for flat, npatch, pn-aen and phong; a finite difference in barycentric space
 *    (h = 2^-7; central differences where every b >= h/2, else one-sided on the shrunken triangle
 *    (1 - h) b + h e_i, which stays inside the domain, Richardson-extrapolated to second order) for the two
 *    Gruen patches.  Note: min(1, fn + bl) of Eq. 1.1.10 makes the final patch only C0 along the curves where
 *    fn_k + bl = 1, so its real normal jumps there (the finite difference smears the jump over h).
 *  - Winding: a patch keeps the winding of its input triangle (v0, v1, v2); real normals are oriented like the
 *    linear normal, never by the winding.
 *  - Watertightness (docs/design.md, erratum 6): where one b component is 0 (<= 0) the point is on an edge and every
 *    patch returns the edge's curve evaluated in a canonical vertex order (endpoints ordered by the bits of
 *    position, then normal), with the two barycentrics of the endpoints as weights; where two are 0 it returns
 *    the vertex itself.  Two triangles sharing an edge (same vertex bits, same normal bits) therefore give
 *    bitwise identical positions, and bitwise identical linear / quadratic normals, whatever their vertex order.
 *    Real normals on an edge are the one-sided derivative normals of each side (a genuine crease for the
 *    N-Patch; tess_smoothness measures it); at a corner the curved patches return the vertex normal.
 *  - Errors: none at run time.  From finite input the shaders never produce NaN: every division is guarded
 *    (Gregory 0/0, curve parameters, zero-length edges), normalize of a zero vector stays zero and a zero
 *    normal falls back to the linear normal, then the face normal.  Non-finite results fall back to the flat
 *    position, then to the vertex with the largest weight.  Degenerate triangles give finite points.
 *    The functions below take NULL where a pointer is asked: a NULL triangle, vertex or normal array reads as
 *    zeros (results zero), a NULL output is not written, a NULL name or out pointer is "not found" (-1), and
 *    vs_patch_names writes nothing into a NULL or zero-byte buffer; a patch or normal mode out of range is "?" /
 *    NULL by name and evaluates as some patch, never out of a table (tests/test_api_vs.c walks them all).  The
 *    shaders' own entry points (main, batch, hull) are the device's to call, with its registers.
 *  - No globals except const tables; everything is reentrant.
 */
#ifndef INSTESS_VS_H
#define INSTESS_VS_H

#include "../core/api.h"
#include "../core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- constant registers ---- */
enum {
    VS_C_WORLDVIEWPROJ = 0, /* c0..c3 */
    VS_C_WORLD = 4,         /* c4..c7 */
    VS_C_DIFFUSE = 8,       /* c8     */
    VS_C_OPTIONS = 9,       /* c9     */
    VS_C_COUNT = 10         /* registers to upload */
};

/* ---- input registers (TEXCOORD usage indices) ---- */
enum {
    VS_IN_V0 = 0,    /* TEXCOORD0..2  v0, v1, v2 */
    VS_IN_N0 = 3,    /* TEXCOORD3..5  n0, n1, n2 */
    VS_IN_OPP0 = 6,  /* TEXCOORD6..8  opp0..2    */
    VS_IN_T0 = 9,    /* TEXCOORD9..11 t0..t2     */
    VS_IN_ID = 12    /* TEXCOORD12.x instance id */
};
/* ---- output registers (oT usage indices; oPos and oD0 = COLOR0, the lit colour, besides) ---- */
enum {
    VS_OUT_TEX = 0,      /* oT0.xy   the interpolated texture coordinate          */
    VS_OUT_NORMAL = 1,   /* oT1.xyz  the unit patch normal (object space, as lit)  */
    VS_OUT_BARY = 2,     /* oT2.xyz  the grid point's barycentrics b               */
    VS_OUT_INSTANCE = 3, /* oT3.x    the instance (mesh triangle) index            */
    VS_OUT_GREGORY = 4   /* oT4.xyz  the Gregory coordinates of b                  */
};
/* The per-instance record these registers are fetched from is meshes.h's is_patch_instance, declared by
 * mesh_patch_declaration: both are written in terms of VS_IN_* (meshes/mesh.c checks the layout at compile
 * time), so the three cannot disagree. */
typedef struct vs_reg { uint8_t usage, usage_index; } vs_reg;
/* Where PN-AEN reads n_adj[k][j] (is_declusage, usage index). */
extern INSTESS_API const vs_reg vs_nadj_regs[3][2];

/* ---- patches and options ---- */
typedef enum vs_patch {
    VS_PATCH_FLAT = 0,           /* linear positions (D3DDEGREE_LINEAR)                               */
    VS_PATCH_NPATCH = 1,         /* Eq. 1.1.1-1.1.2, the cubic Bezier triangle of Vlachos et al.       */
    VS_PATCH_SMOOTH_INITIAL = 2, /* Listing 1.1.1: Gregory blend of P0, P1, P2                         */
    VS_PATCH_SMOOTH = 3,         /* Listing 1.1.2, Eq. 1.1.9-1.1.11: blended towards the N-Patch       */
    VS_PATCH_PHONG = 4,          /* Boubekeur and Alexa 2008, shape factor alpha                      */
    VS_PATCH_PN_AEN = 5,         /* McDonald and Kilgard 2010: edge control points averaged over sides */
} vs_patch;
/* Not an enumerator, so that a switch over vs_patch without a default must name every patch (-Werror=switch). */
#define VS_PATCH_COUNT 6

typedef enum vs_normals { VS_NORMALS_LINEAR = 0, VS_NORMALS_QUADRATIC = 1, VS_NORMALS_REAL = 2 } vs_normals;

#define VS_FLAG_NO_SHORTCUT 1u /* smooth: evaluate P_k even where fn_k == 1 (same bits, slower) */

typedef struct vs_options {
    vs_normals normals;  /* default linear */
    float phong_alpha;   /* default 3/4 */
    float quad_factor;   /* factor of v_ij in n110: 2 (default) or 1.5 (van Overveld) */
    uint32_t flags;      /* VS_FLAG_* */
} vs_options;

/* Defaults: linear normals, alpha 3/4, factor 2, shortcut on. */
INSTESS_API vs_options vs_default_options(void);
/* Fill c0..c9 (the other registers are left alone); o NULL means defaults. */
INSTESS_API void vs_set_constants(is_vs_constants *c, const float4x4 *world_view_proj, const float4x4 *world, float4 diffuse,
                      const vs_options *o);
/* Read c9 back (what the shaders do). */
INSTESS_API vs_options vs_options_from_constants(const is_vs_constants *c);
/* The same from the register c9 itself (a pixel shader given the options in its own constants). */
INSTESS_API vs_options vs_options_from_register(float4 c9);
/* "linear" | "quadratic" | "real" -> 0 and *out, or -1. */
INSTESS_API int vs_normals_from_name(const char *name, vs_normals *out);
INSTESS_API const char *vs_normals_name(vs_normals n);
/* ---- the patch table: the one list of the patches (adding one: README, "Extending instess") ---- */
typedef struct vs_patch_info {
    const char *name;                /* --patch NAME, and the shader's name */
    const char *reference;           /* where the patch comes from */
    const is_vertex_shader *shader;  /* the instanced shader (its batch entry is shader->batch) */
    bool fixed_function;             /* also drawn by the device's N-patch mode and the CPU path (D3D9's
                                        POSITIONDEGREE: npatch is CUBIC, flat LINEAR), with linear and
                                        quadratic normals; every patch takes linear, quadratic and real
                                        normals on the instanced path */
    bool gregory;                    /* writes Gregory weights (TEXCOORD4): the two smoothed patches */
} vs_patch_info;
/* Row p describes patch p; vs_patch_eval (object space) and the shaders dispatch on p with switches that name
 * every patch.  tests/test_patches.c checks that every row is filled and consistent. */
extern INSTESS_API const vs_patch_info vs_patches[VS_PATCH_COUNT];
/* The table's name -> 0 and *out, or -1. */
INSTESS_API int vs_patch_from_name(const char *name, vs_patch *out);
/* The table's name of p ("?" out of range). */
INSTESS_API const char *vs_patch_name(vs_patch p);
/* The names of the table joined by sep into buf ("flat | npatch | ..."), for usage texts; buf. */
INSTESS_API char *vs_patch_names(const char *sep, char *buf, size_t len);

/* ---- shaders ---- */
/* The shader of a name ("flat", "npatch", "smooth-initial", "smooth", "phong", "pn-aen", "fixed"), or NULL. */
INSTESS_API const is_vertex_shader *vs_find_shader(const char *name);
/* The shader of a patch (vs_patches[p].shader), NULL out of range. */
INSTESS_API const is_vertex_shader *vs_patch_shader(vs_patch p);
/* All shaders, ended by a NULL entry. */
extern INSTESS_API const is_vertex_shader *const vs_shaders[];
/* "fixed": reads POSITION0 (object position), NORMAL0 (normal, used as is), TEXCOORD0 (uv) and writes the
 * outputs above (TEXCOORD2..4 zero).  The vertex shader for the device's N-patch mode: fed by
 * vs_npatch_evaluate it lights exactly as the instanced npatch shader does. */
extern INSTESS_API const is_vertex_shader vs_shader_fixed;
/* The patch shaders themselves (also in vs_shaders, in vs_patch order). */
extern INSTESS_API const is_vertex_shader vs_shader_flat, vs_shader_npatch, vs_shader_smooth_initial, vs_shader_smooth,
    vs_shader_phong, vs_shader_pn_aen;

/* ---- the patches in object space (the CPU path, the tests and the figures use these) ---- */
/* One instance's data (the input registers above). */
typedef struct vs_triangle {
    float3 v[3];       /* positions */
    float3 n[3];       /* vertex normals (assumed unit, as the listings do) */
    float3 opp[3];     /* vertex across edge k (own third vertex on a boundary edge) */
    float3 nadj[3][2]; /* PN-AEN: the neighbour's normals at v_k, v_k+1 of edge k (own normals if unknown) */
    float2 t[3];       /* texture coordinates */
    float id;          /* instance id */
} vs_triangle;

/* A triangle without neighbours: opp_k = own third vertex, nadj = own normals, t = 0, id = 0. */
INSTESS_API vs_triangle vs_triangle_make(const float3 v[3], const float3 n[3]);
/* One instance's triangle read from a patch shader's input registers (above; zero n_adj registers become the
 * triangle's own normals): what the shaders evaluate, for code that wraps them. */
INSTESS_API void vs_triangle_from_input(const is_vs_input *in, vs_triangle *tri);

/* Object-space position, unit normal (mode of o) and Gregory weights (0 for patches without) of patch p at b;
 * nrm and greg may be NULL.  Watertight on edges as described above.  o NULL means defaults. */
INSTESS_API void vs_patch_eval(vs_patch p, const vs_triangle *tri, float3 b, const vs_options *o, float3 *pos, float3 *nrm,
                   float3 *greg);
/* The position only. */
INSTESS_API float3 vs_patch_position(vs_patch p, const vs_triangle *tri, float3 b, const vs_options *o);

/* The N-Patch evaluator for the device's N-patch mode (is_npatch_eval_fn) and the CPU path: position_degree
 * IS_DEGREE_CUBIC (default) or IS_DEGREE_LINEAR; normal_degree IS_DEGREE_LINEAR (default), IS_DEGREE_QUADRATIC
 * or VS_DEGREE_REAL (an extension: derivative normals).  The npatch shader calls exactly this function, so the
 * three paths give the same bits. */
#define VS_DEGREE_REAL 0x100u
INSTESS_API void vs_npatch_evaluate(const float3 v[3], const float3 n[3], float3 b, uint32_t position_degree,
                        uint32_t normal_degree, float3 *pos, float3 *nrm);

/* Building blocks in the listings' form (errata resolved, see docs/errata.md), valid for any b; the patches
 * above add the watertight edge and corner handling on top of them. */
/* evaluateCurve (Listing 1.1.1): cubic border curve from v0 to v1 with end normals n0, n1 at parameter b,
 * control points without the /3, Bernstein weights without the 3 (same curve). */
INSTESS_API float3 vs_evaluate_curve(float3 v0, float3 v1, float3 n0, float3 n1, float b);
/* evaluateNPatch (Listing 1.1.2): the N-Patch of Eq. 1.1.1-1.1.2 in the listing's form. */
INSTESS_API float3 vs_evaluate_npatch(float3 v0, float3 v1, float3 v2, float3 n0, float3 n1, float3 n2, float3 b);
/* Listing 1.1.1 / 1.1.2 without the edge handling (interior formulas, for tests of the naive evaluation);
 * g gets the Gregory weights (may be NULL).  flags: VS_FLAG_NO_SHORTCUT; *p_evals (may be NULL) gets the
 * number of P_k evaluated (0..3). */
INSTESS_API float3 vs_smooth_initial_formula(const vs_triangle *tri, float3 b, float3 *g);
INSTESS_API float3 vs_smooth_formula(const vs_triangle *tri, float3 b, uint32_t flags, float3 *g, int *p_evals);
/* Gregory coordinates (Eq. 1.1.4, the listing's order): g.x = b0 b2 / sum (1 on edge v2-v0), g.y = b0 b1 / sum
 * (1 on edge v0-v1), g.z = b1 b2 / sum (1 on edge v1-v2).  At a corner (sum == 0, erratum 4) the two edges of
 * the corner get 1/2 each. */
INSTESS_API float3 vs_gregory(float3 b);
/* fn0..fn2 of Listing 1.1.2 (erratum 3): fn_k = |dot(own face normal, face normal across edge k)|, exactly 1 on
 * a boundary edge (opp_k = own third vertex), for degenerate faces and within 2^-20 of 1. */
INSTESS_API float3 vs_smooth_fn(const vs_triangle *tri);
/* The smooth shader's per-edge shortcut: for n triangles on the regular grid of `level`, the P_k evaluations
 * without the shortcut (*total, may be NULL) and the number saved (returned).  Edge and corner points evaluate
 * no P_k at all (they are the border curve), so only interior points count. */
INSTESS_API uint64_t vs_smooth_shortcut_savings(const vs_triangle *tris, size_t n, int level, uint64_t *total);



/* The output mask of the shaders: COLOR0 and the TEXCOORD outputs VS_OUT_* (see "output registers" above). */
#define VS_OUTPUTS (IS_OUT_COLOR0 | IS_OUT_TEXCOORD(VS_OUT_TEX) | IS_OUT_TEXCOORD(VS_OUT_NORMAL) | \
                    IS_OUT_TEXCOORD(VS_OUT_BARY) | IS_OUT_TEXCOORD(VS_OUT_INSTANCE) | IS_OUT_TEXCOORD(VS_OUT_GREGORY))

#ifdef __cplusplus
}
#endif
#endif
