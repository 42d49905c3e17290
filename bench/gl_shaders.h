/* bench/gl_shaders.h -- the GLSL 330 ports of instess's patch shaders for the llvmpipe reference (bench-gl).
 *
 * The vertex shaders are Listing 1.1.2 of seed 000 with the errata of docs/design.md, section 4, resolved exactly as
 * vs/smooth.c and vs/npatch.c resolve them (same formulas, same guards), so that both sides do the same work:
 *  - evaluateNPatch / evaluateCurve keep the listing's form (control points without the /3, Bernstein weights
 *    without the 3: the same surface as Eq. 1.1.1-1.1.2);
 *  - Gregory coordinates guarded at the corners (the two edges of the corner get 1/2 each), curve parameters
 *    st = bj / (bi + bj) with 0.5 where both are 0;
 *  - fn_k = |dot(own face normal, face normal across edge k)|, edge 0 = v0-v1 -> pos0, edge 1 = v1-v2 -> pos1,
 *    edge 2 = v2-v0 -> pos2; 1 on a boundary (opp_k = own third vertex) and within 2^-20 of 1;
 *    bl = 27 b0 b1 b2; P_k is skipped where fn_k == 1 (the shortcut of vs/smooth.c: lerp(P_k, posN, 1) = posN).
 * Lighting: Diffuse = saturate(dot(Normal, (0, 0, -1))) * g_vDiffuse, Normal = mul(normalize(b0 n0 + b1 n1 +
 * b2 n2), (float3x3)g_mWorld).  Matrices are D3D's row-major arrays uploaded untransposed, so that
 * mul(v, M) (HLSL, row vector) is M * v in GLSL.  u_clip turns D3D's clip space into GL's: xy += w * (1/W, -1/H)
 * moves GL's pixel centres (+0.5) onto D3D9's (integers); z = 2 z - w when glClipControl is missing.
 * The fragment shader writes the interpolated diffuse colour.
 *
 * Scene P (the pixel stage, bench_scene_file.h's BENCH_SHADING_PIXEL_TEXTURE): compiled with "#define
 * BENCH_PIXEL" after the #version line (glsl_version, glsl_define_pixel), the vertex shaders output, instead of
 * Diffuse, what instess's patch shaders write to TEXCOORD1 and TEXCOORD0 (vs/vs.h): the world-space unit normal
 * normalize(Normal) and the texture coordinates b.x t0 + b.y t1 + b.z t2 (the instance's TEXCOORD9..11), and
 * glsl_fs_pixel_texture lights the normalised interpolated normal per fragment and multiplies by the texture, as
 * bench.c's pixel shader does.  Texel centres need no correction: D3D9 and GL both put texel i of a level of
 * width W at u = (i + 1/2) / W and read texture rows from the first one in memory at v = 0, so the same
 * coordinates at the same pixel centres (the half-pixel offset above) read the same texels. */
#ifndef INSTESS_BENCH_GL_SHADERS_H
#define INSTESS_BENCH_GL_SHADERS_H

/* The first source string of every stage, and the second one of scene P's vertex shader. */
static const char *const glsl_version = "#version 330 core\n";
static const char *const glsl_define_pixel = "#define BENCH_PIXEL 1\n";

/* Inputs, uniforms, the N-Patch and the transform-and-light tail shared by both vertex shaders (after
 * glsl_version). */
#define GLSL_VS_COMMON                                                                                        \
    "layout(location = 0) in vec3 b;    // POSITION: barycentric coords (stream 0, per vertex)\n"             \
    "layout(location = 1) in vec3 v0;   // TEXCOORD0..2: the triangle (stream 1, per instance)\n"             \
    "layout(location = 2) in vec3 v1;\n"                                                                      \
    "layout(location = 3) in vec3 v2;\n"                                                                      \
    "layout(location = 4) in vec3 n0;   // TEXCOORD3..5: its normals\n"                                       \
    "layout(location = 5) in vec3 n1;\n"                                                                      \
    "layout(location = 6) in vec3 n2;\n"                                                                      \
    "uniform mat4 g_mWorldViewProjection;\n"                                                                  \
    "uniform mat4 g_mWorld;\n"                                                                                \
    "uniform vec4 g_vDiffuse;\n"                                                                              \
    "uniform vec3 u_clip;\n"                                                                                  \
    "#ifdef BENCH_PIXEL\n"                                                                                    \
    "layout(location = 10) in vec2 t0;  // TEXCOORD9..11: texture coordinates\n"                              \
    "layout(location = 11) in vec2 t1;\n"                                                                     \
    "layout(location = 12) in vec2 t2;\n"                                                                     \
    "out vec3 Normal;                   // TEXCOORD1: the world-space unit normal\n"                          \
    "out vec2 Tex;                      // TEXCOORD0: the texture coordinates\n"                              \
    "#else\n"                                                                                                 \
    "out vec4 Diffuse;\n"                                                                                     \
    "#endif\n"                                                                                                \
    "vec3 evaluateNPatch(vec3 b) {\n"                                                                         \
    "  vec3 b102 = 2.0 * v2 + v0 - dot(v0 - v2, n2) * n2;\n"                                                  \
    "  vec3 b012 = 2.0 * v2 + v1 - dot(v1 - v2, n2) * n2;\n"                                                  \
    "  vec3 b201 = 2.0 * v0 + v2 - dot(v2 - v0, n0) * n0;\n"                                                  \
    "  vec3 b021 = 2.0 * v1 + v2 - dot(v2 - v1, n1) * n1;\n"                                                  \
    "  vec3 b210 = 2.0 * v0 + v1 - dot(v1 - v0, n0) * n0;\n"                                                  \
    "  vec3 b120 = 2.0 * v1 + v0 - dot(v0 - v1, n1) * n1;\n"                                                  \
    "  return b.x*b.x*b.x * v0 + b.y*b.y*b.y * v1 + b.z*b.z*b.z * v2 + b.x*b.z*b.z * b102\n"                  \
    "       + b.y*b.z*b.z * b012 + b.x*b.x*b.z * b201 + b.y*b.y*b.z * b021\n"                                 \
    "       + b.x*b.x*b.y * b210 + b.x*b.y*b.y * b120\n"                                                      \
    "       + b.x*b.y*b.z * (0.5 * (b210 + b120 + b021 + b012 + b102 + b201) - v0 - v1 - v2);\n"              \
    "}\n"                                                                                                     \
    "void transformAndLight(vec3 pos) {\n"                                                                    \
    "  vec4 p = g_mWorldViewProjection * vec4(pos, 1.0);\n"                                                   \
    "  p.xy += p.w * u_clip.xy;\n"                                                                            \
    "  if (u_clip.z != 0.0) p.z = 2.0 * p.z - p.w;\n"                                                         \
    "  gl_Position = p;\n"                                                                                    \
    "  vec3 N = mat3(g_mWorld) * normalize(b.x * n0 + b.y * n1 + b.z * n2);\n"                                \
    "#ifdef BENCH_PIXEL\n"                                                                                    \
    "  Normal = normalize(N);\n"                                                                              \
    "  Tex = b.x * t0 + b.y * t1 + b.z * t2;\n"                                                               \
    "#else\n"                                                                                                 \
    "  Diffuse = clamp(dot(N, vec3(0.0, 0.0, -1.0)), 0.0, 1.0) * g_vDiffuse;\n"                               \
    "  Diffuse.w = 1.0;\n"                                                                                    \
    "#endif\n"                                                                                                \
    "}\n"

/* The original N-Patch (Eq. 1.1.1-1.1.2 in Listing 1.1.2's form). */
static const char *const glsl_vs_npatch = GLSL_VS_COMMON
    "void main() { transformAndLight(evaluateNPatch(b)); }\n";

/* Gruen's final smoothed patch (Listing 1.1.2, Eq. 1.1.9-1.1.11), errata resolved as in vs/smooth.c. */
static const char *const glsl_vs_smooth = GLSL_VS_COMMON
    "layout(location = 7) in vec3 opp0; // TEXCOORD6..8: vertex opposite edge k\n"
    "layout(location = 8) in vec3 opp1;\n"
    "layout(location = 9) in vec3 opp2;\n"
    "vec3 safeNormalize(vec3 a) { float l = length(a); return l > 0.0 ? a / l : a; }\n"
    "vec3 lerpExact(vec3 a, vec3 c, float t) { return t == 1.0 ? c : a + (c - a) * t; }\n"
    "vec3 evaluateCurve(vec3 p0, vec3 p1, vec3 m0, vec3 m1, float t) {\n"
    "  float t_ = 1.0 - t;\n"
    "  vec3 b21 = 2.0 * p0 + p1 - dot(p1 - p0, m0) * m0;\n"
    "  vec3 b12 = 2.0 * p1 + p0 - dot(p0 - p1, m1) * m1;\n"
    "  return t_*t_*t_ * p0 + t*t*t * p1 + t_*t_*t * b21 + t_*t*t * b12;\n"
    "}\n"
    "float curveParam(float bi, float bj) { float d = bi + bj; return d > 0.0 ? bj / max(d, 1e-30) : 0.5; }\n"
    "vec3 gregory(vec3 c) {\n"
    "  float b0b2 = c.x * c.z, b0b1 = c.x * c.y, b1b2 = c.y * c.z;\n"
    "  float sum = b0b2 + b0b1 + b1b2;\n"
    "  if (sum > 0.0) return vec3(b0b2, b0b1, b1b2) / sum;\n"
    "  if (c.x >= c.y && c.x >= c.z) return vec3(0.5, 0.5, 0.0);\n"
    "  return c.y >= c.z ? vec3(0.0, 0.5, 0.5) : vec3(0.5, 0.0, 0.5);\n"
    "}\n"
    "float edgeFn(vec3 nf, vec3 a, vec3 e, vec3 o, vec3 third) {\n"
    "  if (o == third) return 1.0;\n"
    "  vec3 nn = safeNormalize(cross(e - a, o - a));\n"
    "  if (!(dot(nf, nf) > 0.0) || !(dot(nn, nn) > 0.0)) return 1.0;\n"
    "  float d = abs(dot(nf, nn));\n"
    "  return d >= 1.0 - 1.0 / 1048576.0 ? 1.0 : d;\n"
    "}\n"
    "vec3 edgePatch(vec3 va, vec3 vb, vec3 vc, vec3 na, vec3 nb, vec3 nc, float st, float ct) {\n"
    "  vec3 p = evaluateCurve(va, vb, na, nb, st);\n"
    "  vec3 m = safeNormalize(mix(na, nb, st));\n"
    "  return evaluateCurve(p, vc, m, nc, ct);\n"
    "}\n"
    "vec3 smoothPatch() {\n"
    "  vec3 g = gregory(b);\n"
    "  vec3 c = vec3(curveParam(b.x, b.y), curveParam(b.y, b.z), curveParam(b.z, b.x));\n"
    "  vec3 nf = safeNormalize(cross(v1 - v0, v2 - v0));\n"
    "  vec3 fn = vec3(edgeFn(nf, v1, v0, opp0, v2), edgeFn(nf, v2, v1, opp1, v0), edgeFn(nf, v0, v2, opp2, v1));\n"
    "  vec3 posN = evaluateNPatch(b);\n"
    "  float bl = 27.0 * b.x * b.y * b.z;\n"
    "  if (all(equal(fn, vec3(1.0)))) return posN;\n"
    "  vec3 pos0 = posN, pos1 = posN, pos2 = posN;\n"
    "  if (fn.x != 1.0) pos0 = lerpExact(edgePatch(v0, v1, v2, n0, n1, n2, c.x, b.z), posN, min(1.0, fn.x + bl));\n"
    "  if (fn.y != 1.0) pos1 = lerpExact(edgePatch(v1, v2, v0, n1, n2, n0, c.y, b.x), posN, min(1.0, fn.y + bl));\n"
    "  if (fn.z != 1.0) pos2 = lerpExact(edgePatch(v2, v0, v1, n2, n0, n1, c.z, b.y), posN, min(1.0, fn.z + bl));\n"
    "  return lerpExact(g.x * pos2 + g.y * pos0 + g.z * pos1, posN, bl);\n"
    "}\n"
    "void main() { transformAndLight(smoothPatch()); }\n";

/* The interpolated diffuse colour (after glsl_version). */
static const char *const glsl_fs_diffuse =
    "in vec4 Diffuse;\n"
    "layout(location = 0) out vec4 color;\n"
    "void main() { color = Diffuse; }\n";

/* Scene P: the interpolated normal normalised and lit per fragment, times the texture (after glsl_version). */
static const char *const glsl_fs_pixel_texture =
    "in vec3 Normal;\n"
    "in vec2 Tex;\n"
    "uniform vec4 g_vDiffuse;\n"
    "uniform sampler2D s0;\n"
    "layout(location = 0) out vec4 color;\n"
    "void main() {\n"
    "  vec3 n = normalize(Normal);\n"
    "  vec4 t = texture(s0, Tex);\n"
    "  color = vec4(clamp(dot(n, vec3(0.0, 0.0, -1.0)), 0.0, 1.0) * g_vDiffuse.rgb * t.rgb, 1.0);\n"
    "}\n";

#endif
