/* bench/gl_ref.c -- build/bench-gl: the llvmpipe reference of `make bench`.
 *
 * Renders one benchmark scene (a scene file written by build/bench, see bench_scene_file.h) with Mesa's llvmpipe
 * through OpenGL instancing -- the grid in one buffer, the per-triangle data in a second with
 * glVertexAttribDivisor(1) (= SetStreamSourceFreq INSTANCEDATA | 1), one glDrawElementsInstanced per frame --
 * into an RGBA8 FBO with a 32-bit float depth buffer, on an EGL surfaceless (EGL_MESA_platform_surfaceless)
 * OpenGL 4.5 core context (3.3 core as a fallback).  Each frame is glClear + draw + glFinish, timed with
 * CLOCK_MONOTONIC; after the warm-up frames it prints the median and writes the last image as raw RGBA8, top
 * row first (the instess layout).  The environment (LP_NUM_THREADS, GLIBC_TUNABLES) is set by the parent.
 * A scene file with a texture block (scene P) is drawn with the per-pixel light times the texture: its mip levels
 * uploaded as they are in the file (instess's own chain), GL_LINEAR_MIPMAP_LINEAR / GL_LINEAR, GL_REPEAT.
 *
 * Usage: bench-gl SCENE_FILE [--frames N] [--warmup N] [--out FILE.rgba] [--ppm FILE.ppm] [--no-clip-control]
 * (--no-clip-control tests the GL 3.3 path: D3D's clip z in [0, w] mapped to GL's [-w, w] as z' = 2 z - w.)
 * Prints one line of key=value pairs on stdout (see print_result); errors on stderr, exit 1.
 */
#define _GNU_SOURCE
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "bench_scene_file.h"
#include "gl_shaders.h"

#ifndef EGL_PLATFORM_SURFACELESS_MESA
#define EGL_PLATFORM_SURFACELESS_MESA 0x31DD
#endif
#ifndef GL_VERTEX_SHADER_INVOCATIONS_ARB
#define GL_VERTEX_SHADER_INVOCATIONS_ARB 0x82F0
#define GL_PRIMITIVES_SUBMITTED_ARB 0x82EF
#define GL_CLIPPING_OUTPUT_PRIMITIVES_ARB 0x82F7
#define GL_FRAGMENT_SHADER_INVOCATIONS_ARB 0x82F4
#endif

/* ---------------------------------------- GL entry points ---------------------------------------- */

/* The GL functions used, loaded through eglGetProcAddress (no link-time dependency on libGL / libOpenGL). */
typedef struct gl_api {
    PFNGLGETSTRINGPROC GetString;
    PFNGLGETSTRINGIPROC GetStringi;
    PFNGLGETINTEGERVPROC GetIntegerv;
    PFNGLGETERRORPROC GetError;
    PFNGLCREATESHADERPROC CreateShader;
    PFNGLSHADERSOURCEPROC ShaderSource;
    PFNGLCOMPILESHADERPROC CompileShader;
    PFNGLGETSHADERIVPROC GetShaderiv;
    PFNGLGETSHADERINFOLOGPROC GetShaderInfoLog;
    PFNGLCREATEPROGRAMPROC CreateProgram;
    PFNGLATTACHSHADERPROC AttachShader;
    PFNGLLINKPROGRAMPROC LinkProgram;
    PFNGLGETPROGRAMIVPROC GetProgramiv;
    PFNGLGETPROGRAMINFOLOGPROC GetProgramInfoLog;
    PFNGLUSEPROGRAMPROC UseProgram;
    PFNGLGETUNIFORMLOCATIONPROC GetUniformLocation;
    PFNGLGETATTRIBLOCATIONPROC GetAttribLocation;
    PFNGLUNIFORMMATRIX4FVPROC UniformMatrix4fv;
    PFNGLUNIFORM4FVPROC Uniform4fv;
    PFNGLUNIFORM3FPROC Uniform3f;
    PFNGLGENVERTEXARRAYSPROC GenVertexArrays;
    PFNGLBINDVERTEXARRAYPROC BindVertexArray;
    PFNGLGENBUFFERSPROC GenBuffers;
    PFNGLBINDBUFFERPROC BindBuffer;
    PFNGLBUFFERDATAPROC BufferData;
    PFNGLVERTEXATTRIBPOINTERPROC VertexAttribPointer;
    PFNGLENABLEVERTEXATTRIBARRAYPROC EnableVertexAttribArray;
    PFNGLVERTEXATTRIBDIVISORPROC VertexAttribDivisor;
    PFNGLGENFRAMEBUFFERSPROC GenFramebuffers;
    PFNGLBINDFRAMEBUFFERPROC BindFramebuffer;
    PFNGLGENRENDERBUFFERSPROC GenRenderbuffers;
    PFNGLBINDRENDERBUFFERPROC BindRenderbuffer;
    PFNGLRENDERBUFFERSTORAGEPROC RenderbufferStorage;
    PFNGLFRAMEBUFFERRENDERBUFFERPROC FramebufferRenderbuffer;
    PFNGLCHECKFRAMEBUFFERSTATUSPROC CheckFramebufferStatus;
    PFNGLDRAWBUFFERSPROC DrawBuffers;
    PFNGLVIEWPORTPROC Viewport;
    PFNGLCLEARCOLORPROC ClearColor;
    PFNGLCLEARDEPTHPROC ClearDepth;
    PFNGLCLEARPROC Clear;
    PFNGLENABLEPROC Enable;
    PFNGLDISABLEPROC Disable;
    PFNGLDEPTHFUNCPROC DepthFunc;
    PFNGLDEPTHMASKPROC DepthMask;
    PFNGLCULLFACEPROC CullFace;
    PFNGLFRONTFACEPROC FrontFace;
    PFNGLDRAWELEMENTSINSTANCEDPROC DrawElementsInstanced;
    PFNGLFINISHPROC Finish;
    PFNGLPIXELSTOREIPROC PixelStorei;
    PFNGLREADPIXELSPROC ReadPixels;
    PFNGLCLIPCONTROLPROC ClipControl;            /* GL 4.5 / ARB_clip_control; may be NULL */
    PFNGLINVALIDATEFRAMEBUFFERPROC InvalidateFramebuffer;   /* GL 4.3; may be NULL */
    PFNGLGENQUERIESPROC GenQueries;
    PFNGLBEGINQUERYPROC BeginQuery;
    PFNGLENDQUERYPROC EndQuery;
    PFNGLGETQUERYOBJECTUI64VPROC GetQueryObjectui64v;
    PFNGLGENTEXTURESPROC GenTextures;
    PFNGLBINDTEXTUREPROC BindTexture;
    PFNGLACTIVETEXTUREPROC ActiveTexture;
    PFNGLTEXIMAGE2DPROC TexImage2D;
    PFNGLTEXPARAMETERIPROC TexParameteri;
    PFNGLUNIFORM1IPROC Uniform1i;
} gl_api;

/* Name and place of each entry point; `optional` ones may be missing. */
typedef struct gl_entry { const char *name; size_t offset; int optional; } gl_entry;
#define GL_ENTRY(f, opt) {"gl" #f, offsetof(gl_api, f), opt}
static const gl_entry gl_entries[] = {
    GL_ENTRY(GetString, 0), GL_ENTRY(GetStringi, 0), GL_ENTRY(GetIntegerv, 0), GL_ENTRY(GetError, 0),
    GL_ENTRY(CreateShader, 0), GL_ENTRY(ShaderSource, 0), GL_ENTRY(CompileShader, 0), GL_ENTRY(GetShaderiv, 0),
    GL_ENTRY(GetShaderInfoLog, 0), GL_ENTRY(CreateProgram, 0), GL_ENTRY(AttachShader, 0),
    GL_ENTRY(LinkProgram, 0), GL_ENTRY(GetProgramiv, 0), GL_ENTRY(GetProgramInfoLog, 0), GL_ENTRY(UseProgram, 0),
    GL_ENTRY(GetUniformLocation, 0), GL_ENTRY(GetAttribLocation, 0), GL_ENTRY(UniformMatrix4fv, 0),
    GL_ENTRY(Uniform4fv, 0), GL_ENTRY(Uniform3f, 0), GL_ENTRY(GenVertexArrays, 0), GL_ENTRY(BindVertexArray, 0),
    GL_ENTRY(GenBuffers, 0), GL_ENTRY(BindBuffer, 0), GL_ENTRY(BufferData, 0), GL_ENTRY(VertexAttribPointer, 0),
    GL_ENTRY(EnableVertexAttribArray, 0), GL_ENTRY(VertexAttribDivisor, 0), GL_ENTRY(GenFramebuffers, 0),
    GL_ENTRY(BindFramebuffer, 0), GL_ENTRY(GenRenderbuffers, 0), GL_ENTRY(BindRenderbuffer, 0),
    GL_ENTRY(RenderbufferStorage, 0), GL_ENTRY(FramebufferRenderbuffer, 0), GL_ENTRY(CheckFramebufferStatus, 0),
    GL_ENTRY(DrawBuffers, 0), GL_ENTRY(Viewport, 0), GL_ENTRY(ClearColor, 0), GL_ENTRY(ClearDepth, 0),
    GL_ENTRY(Clear, 0), GL_ENTRY(Enable, 0), GL_ENTRY(Disable, 0), GL_ENTRY(DepthFunc, 0), GL_ENTRY(DepthMask, 0),
    GL_ENTRY(CullFace, 0), GL_ENTRY(FrontFace, 0), GL_ENTRY(DrawElementsInstanced, 0), GL_ENTRY(Finish, 0),
    GL_ENTRY(PixelStorei, 0), GL_ENTRY(ReadPixels, 0), GL_ENTRY(ClipControl, 1), GL_ENTRY(GenQueries, 0),
    GL_ENTRY(BeginQuery, 0), GL_ENTRY(EndQuery, 0), GL_ENTRY(GetQueryObjectui64v, 0), GL_ENTRY(GenTextures, 0),
    GL_ENTRY(BindTexture, 0), GL_ENTRY(ActiveTexture, 0), GL_ENTRY(TexImage2D, 0), GL_ENTRY(TexParameteri, 0),
    GL_ENTRY(Uniform1i, 0), GL_ENTRY(InvalidateFramebuffer, 1),
};

/* Load every entry point; 0, or -1 naming the first required one missing. */
static int gl_load(gl_api *gl)
{
    memset(gl, 0, sizeof *gl);
    for (size_t k = 0; k < sizeof gl_entries / sizeof gl_entries[0]; k++) {
        void (*fn)(void) = eglGetProcAddress(gl_entries[k].name);
        if (!fn && !gl_entries[k].optional) {
            fprintf(stderr, "bench-gl: missing GL entry point %s\n", gl_entries[k].name);
            return -1;
        }
        memcpy((char *)gl + gl_entries[k].offset, &fn, sizeof fn);
    }
    return 0;
}

/* True if the context advertises extension `name`. */
static int gl_has_extension(const gl_api *gl, const char *name)
{
    GLint n = 0;
    gl->GetIntegerv(GL_NUM_EXTENSIONS, &n);
    for (GLint k = 0; k < n; k++)
        if (strcmp((const char *)gl->GetStringi(GL_EXTENSIONS, (GLuint)k), name) == 0) return 1;
    return 0;
}

/* ---------------------------------------- EGL ---------------------------------------- */

typedef struct egl_state { EGLDisplay dpy; EGLContext ctx; int major, minor; } egl_state;

/* Try a core context of version major.minor on dpy without a config (EGL_KHR_no_config_context). */
static EGLContext egl_try_context(EGLDisplay dpy, int major, int minor)
{
    const EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION, major, EGL_CONTEXT_MINOR_VERSION, minor,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    return eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attrs);
}

/* Surfaceless Mesa display, OpenGL 4.5 core context (3.3 core as a fallback), made current; 0 or -1. */
static int egl_init(egl_state *e)
{
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    if (!get_display) return fprintf(stderr, "bench-gl: no eglGetPlatformDisplayEXT\n"), -1;
    e->dpy = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    EGLint maj, min;
    if (e->dpy == EGL_NO_DISPLAY || !eglInitialize(e->dpy, &maj, &min))
        return fprintf(stderr, "bench-gl: cannot initialise the surfaceless EGL display (libegl-mesa0?)\n"), -1;
    if (!eglBindAPI(EGL_OPENGL_API)) return fprintf(stderr, "bench-gl: eglBindAPI(EGL_OPENGL_API) failed\n"), -1;
    e->major = 4, e->minor = 5;
    e->ctx = egl_try_context(e->dpy, 4, 5);
    if (e->ctx == EGL_NO_CONTEXT) e->major = 3, e->minor = 3, e->ctx = egl_try_context(e->dpy, 3, 3);
    if (e->ctx == EGL_NO_CONTEXT)
        return fprintf(stderr, "bench-gl: cannot create an OpenGL 3.3 core context (0x%x)\n", eglGetError()), -1;
    if (!eglMakeCurrent(e->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, e->ctx))
        return fprintf(stderr, "bench-gl: eglMakeCurrent failed (0x%x)\n", eglGetError()), -1;
    return 0;
}

/* Release the context and the display. */
static void egl_fini(egl_state *e)
{
    eglMakeCurrent(e->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(e->dpy, e->ctx);
    eglTerminate(e->dpy);
}

/* ---------------------------------------- the scene file ---------------------------------------- */

typedef struct gl_scene {
    bench_scene_header h;
    float *bary;        /* 3 * n_points */
    uint32_t *idx;      /* n_indices */
    unsigned char *inst; /* n_instances * stride */
    int textured;       /* a texture block follows (scene P): th and texels are set */
    bench_texture_header th;
    uint32_t *texels;   /* every level, level 0 first (bench_scene_file.h) */
} gl_scene;

/* Read exactly n bytes into a new buffer (NULL on a short read or no memory). */
static void *read_block(FILE *f, size_t n)
{
    void *p = malloc(n ? n : 1);
    if (p && fread(p, 1, n, f) != n) free(p), p = NULL;
    return p;
}

/* Texels of levels 0..levels-1 of a w x h chain. */
static size_t chain_texels(int w, int h, int levels)
{
    size_t n = 0;
    for (int l = 0; l < levels; l++) n += (size_t)(w >> l > 0 ? w >> l : 1) * (size_t)(h >> l > 0 ? h >> l : 1);
    return n;
}

/* The optional texture block after the instances: 1 when there is none (the file ends), 0 when it was read into
 * s, -1 when it is there but not valid (short, wrong magic, shading, size or level count, bytes after it). */
static int texture_load(FILE *f, gl_scene *s)
{
    bench_texture_header *t = &s->th;
    size_t got = fread(t, 1, sizeof *t, f);
    if (got == 0 && feof(f)) return 1;
    if (got != sizeof *t || memcmp(t->magic, BENCH_TEXTURE_MAGIC, 8) != 0 ||
        t->shading != BENCH_SHADING_PIXEL_TEXTURE || t->width < 1 || t->height < 1 || t->width > 16384 ||
        t->height > 16384 || t->levels < 1)
        return -1;
    int full = 1;
    while ((t->width >> full) > 0 || (t->height >> full) > 0) full++;
    if (t->levels > full) return -1;
    s->texels = read_block(f, chain_texels(t->width, t->height, t->levels) * sizeof(uint32_t));
    if (!s->texels || fgetc(f) != EOF) return -1;
    s->textured = 1;
    return 0;
}

/* Load and check a scene file; 0 or -1 with a message. */
static int scene_load(const char *path, gl_scene *s)
{
    memset(s, 0, sizeof *s);
    FILE *f = fopen(path, "rb");
    if (!f) return fprintf(stderr, "bench-gl: %s: cannot open\n", path), -1;
    int ok = fread(&s->h, sizeof s->h, 1, f) == 1 && memcmp(s->h.magic, BENCH_SCENE_MAGIC, 8) == 0 &&
             s->h.instance_stride == BENCH_INSTANCE_STRIDE && s->h.width > 0 && s->h.height > 0 &&
             s->h.width <= 16384 && s->h.height <= 16384 && s->h.n_indices % 3 == 0 &&
             (s->h.patch == BENCH_PATCH_NPATCH || s->h.patch == BENCH_PATCH_SMOOTH);
    if (ok) s->bary = read_block(f, (size_t)s->h.n_points * 3 * sizeof(float));
    if (ok && s->bary) s->idx = read_block(f, (size_t)s->h.n_indices * sizeof(uint32_t));
    if (ok && s->idx) s->inst = read_block(f, (size_t)s->h.n_instances * s->h.instance_stride);
    if (ok && s->inst) ok = texture_load(f, s) >= 0;
    fclose(f);
    for (uint32_t k = 0; ok && s->inst && k < s->h.n_indices; k++) ok = s->idx[k] < s->h.n_points;
    if (!ok || !s->inst) return fprintf(stderr, "bench-gl: %s: not a valid bench scene file\n", path), -1;
    return 0;
}

/* Free the arrays of a scene. */
static void scene_free(gl_scene *s)
{
    free(s->bary), free(s->idx), free(s->inst), free(s->texels);
}

/* ---------------------------------------- GL objects ---------------------------------------- */

/* Compile one shader stage from its n source strings; 0 on failure (the log goes to stderr). */
static GLuint compile_stage(const gl_api *gl, GLenum type, const char *const *src, int n)
{
    GLuint sh = gl->CreateShader(type);
    gl->ShaderSource(sh, n, src, NULL);
    gl->CompileShader(sh);
    GLint ok = 0;
    gl->GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096];
        gl->GetShaderInfoLog(sh, sizeof log, NULL, log);
        fprintf(stderr, "bench-gl: shader compile error:\n%s\n", log);
        return 0;
    }
    return sh;
}

/* Link the vertex shader of the patch with the diffuse fragment shader, or for a textured scene (pixel != 0) the
 * vertex shader's BENCH_PIXEL variant with the per-pixel light times the texture; 0 on failure. */
static GLuint make_program(const gl_api *gl, int patch, int pixel)
{
    const char *body = patch == BENCH_PATCH_SMOOTH ? glsl_vs_smooth : glsl_vs_npatch;
    const char *vsrc[3] = {glsl_version, pixel ? glsl_define_pixel : body, body};
    const char *fsrc[2] = {glsl_version, pixel ? glsl_fs_pixel_texture : glsl_fs_diffuse};
    GLuint vs = compile_stage(gl, GL_VERTEX_SHADER, vsrc, pixel ? 3 : 2);
    GLuint fs = compile_stage(gl, GL_FRAGMENT_SHADER, fsrc, 2);
    if (!vs || !fs) return 0;
    GLuint prog = gl->CreateProgram();
    gl->AttachShader(prog, vs);
    gl->AttachShader(prog, fs);
    gl->LinkProgram(prog);
    GLint ok = 0;
    gl->GetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096];
        gl->GetProgramInfoLog(prog, sizeof log, NULL, log);
        fprintf(stderr, "bench-gl: program link error:\n%s\n", log);
        return 0;
    }
    return prog;
}

/* The per-instance attributes: shader name, byte offset in is_patch_instance (Listing 1.1.2's order) and floats. */
static const struct { const char *name; unsigned offset; int size; } instance_attrs[] = {
    {"v0", 0, 3}, {"v1", 12, 3}, {"v2", 24, 3}, {"n0", 36, 3}, {"n1", 48, 3}, {"n2", 60, 3}, {"opp0", 72, 3},
    {"opp1", 84, 3}, {"opp2", 96, 3}, {"t0", 108, 2}, {"t1", 116, 2}, {"t2", 124, 2},
};

/* Upload a buffer object of `bytes` from data to `target`; returns its name. */
static GLuint upload(const gl_api *gl, GLenum target, const void *data, size_t bytes)
{
    GLuint buf;
    gl->GenBuffers(1, &buf);
    gl->BindBuffer(target, buf);
    gl->BufferData(target, (GLsizeiptr)bytes, data, GL_STATIC_DRAW);
    return buf;
}

/* VAO: stream 0 (grid, per vertex), stream 1 (instances, divisor 1) with only the attributes prog reads, and
 * the index buffer (16-bit when the grid allows, as instess does).  Returns the index type. */
static GLenum make_vao(const gl_api *gl, GLuint prog, const gl_scene *s)
{
    GLuint vao;
    gl->GenVertexArrays(1, &vao);
    gl->BindVertexArray(vao);
    upload(gl, GL_ARRAY_BUFFER, s->bary, (size_t)s->h.n_points * 3 * sizeof(float));
    gl->VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), (const void *)0);
    gl->EnableVertexAttribArray(0);
    upload(gl, GL_ARRAY_BUFFER, s->inst, (size_t)s->h.n_instances * s->h.instance_stride);
    for (size_t k = 0; k < sizeof instance_attrs / sizeof instance_attrs[0]; k++) {
        GLint loc = gl->GetAttribLocation(prog, instance_attrs[k].name);
        if (loc < 0) continue;
        gl->VertexAttribPointer((GLuint)loc, instance_attrs[k].size, GL_FLOAT, GL_FALSE, (GLsizei)s->h.instance_stride,
                                (const void *)(uintptr_t)instance_attrs[k].offset);
        gl->VertexAttribDivisor((GLuint)loc, 1); /* = SetStreamSourceFreq(1, INSTANCEDATA | 1) */
        gl->EnableVertexAttribArray((GLuint)loc);
    }
    if (s->h.n_points <= 65536) {
        uint16_t *i16 = malloc((size_t)s->h.n_indices * sizeof *i16 + 1);
        if (!i16) return 0;
        for (uint32_t k = 0; k < s->h.n_indices; k++) i16[k] = (uint16_t)s->idx[k];
        upload(gl, GL_ELEMENT_ARRAY_BUFFER, i16, (size_t)s->h.n_indices * sizeof *i16);
        free(i16);
        return GL_UNSIGNED_SHORT;
    }
    upload(gl, GL_ELEMENT_ARRAY_BUFFER, s->idx, (size_t)s->h.n_indices * sizeof(uint32_t));
    return GL_UNSIGNED_INT;
}

/* An FBO with an RGBA8 colour and a 32-bit float depth renderbuffer of w x h, bound; 0 or -1. */
static int make_fbo(const gl_api *gl, int w, int h)
{
    GLuint fbo, rb[2];
    gl->GenFramebuffers(1, &fbo);
    gl->BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl->GenRenderbuffers(2, rb);
    gl->BindRenderbuffer(GL_RENDERBUFFER, rb[0]);
    gl->RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
    gl->BindRenderbuffer(GL_RENDERBUFFER, rb[1]);
    gl->RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb[1]);
    const GLenum bufs[1] = {GL_COLOR_ATTACHMENT0};
    gl->DrawBuffers(1, bufs);
    if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return fprintf(stderr, "bench-gl: framebuffer incomplete\n"), -1;
    return 0;
}

/* Scene P's texture in unit 0: every level of the file's chain (A8R8G8B8's bytes B, G, R, A are GL_BGRA with
 * GL_UNSIGNED_BYTE), GL_TEXTURE_MAX_LEVEL the last one, trilinear (GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR) and
 * GL_REPEAT in s and t: D3D9's MIN/MAG/MIPFILTER LINEAR and ADDRESSU/V WRAP. */
static void make_texture(const gl_api *gl, GLuint prog, const gl_scene *s)
{
    GLuint tex;
    gl->ActiveTexture(GL_TEXTURE0);
    gl->GenTextures(1, &tex);
    gl->BindTexture(GL_TEXTURE_2D, tex);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    const uint32_t *p = s->texels;
    for (int l = 0; l < s->th.levels; l++) {
        int w = s->th.width >> l > 0 ? s->th.width >> l : 1, h = s->th.height >> l > 0 ? s->th.height >> l : 1;
        gl->TexImage2D(GL_TEXTURE_2D, l, GL_RGBA8, w, h, 0, GL_BGRA, GL_UNSIGNED_BYTE, p);
        p += (size_t)w * h;
    }
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, s->th.levels - 1);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    gl->UseProgram(prog);
    gl->Uniform1i(gl->GetUniformLocation(prog, "s0"), 0);
}

/* D3D9's fixed-function state in GL: depth LESSEQUAL with writes, clockwise front faces, cull the back
 * (D3DCULL_CCW), D3D's [0, w] clip depth via glClipControl when available, the half-pixel offset; the
 * uniforms.  Returns 1 if glClipControl is used. */
static int set_state(const gl_api *gl, GLuint prog, const gl_scene *s, int use_clip_control)
{
    gl->UseProgram(prog);
    gl->Viewport(0, 0, s->h.width, s->h.height);
    gl->Enable(GL_DEPTH_TEST);
    gl->DepthFunc(GL_LEQUAL);
    gl->DepthMask(GL_TRUE);
    gl->Enable(GL_CULL_FACE);
    gl->FrontFace(GL_CW);
    gl->CullFace(GL_BACK);
    if (use_clip_control) gl->ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    gl->UniformMatrix4fv(gl->GetUniformLocation(prog, "g_mWorldViewProjection"), 1, GL_FALSE, s->h.wvp);
    gl->UniformMatrix4fv(gl->GetUniformLocation(prog, "g_mWorld"), 1, GL_FALSE, s->h.world);
    gl->Uniform4fv(gl->GetUniformLocation(prog, "g_vDiffuse"), 1, s->h.diffuse);
    gl->Uniform3f(gl->GetUniformLocation(prog, "u_clip"), 1.0f / (float)s->h.width, -1.0f / (float)s->h.height,
                  use_clip_control ? 0.0f : 1.0f);
    gl->ClearColor(s->h.clear_rgba[0], s->h.clear_rgba[1], s->h.clear_rgba[2], s->h.clear_rgba[3]);
    gl->ClearDepth(1.0);
    return use_clip_control;
}

/* ---------------------------------------- frames ---------------------------------------- */

/* Monotonic time in milliseconds. */
static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* One frame: clear, one instanced draw, the depth invalidated (unless `keep`: the frame's depth is not needed
 * afterwards, as instess's present is told with DISCARD_DEPTHSTENCIL), glFinish. */
static void draw_frame(const gl_api *gl, const gl_scene *s, GLenum index_type, int keep)
{
    gl->Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl->DrawElementsInstanced(GL_TRIANGLES, (GLsizei)s->h.n_indices, index_type, (const void *)0,
                              (GLsizei)s->h.n_instances);
    if (!keep && gl->InvalidateFramebuffer) {
        const GLenum depth = GL_DEPTH_ATTACHMENT;
        gl->InvalidateFramebuffer(GL_FRAMEBUFFER, 1, &depth);
    }
    gl->Finish();
}

/* qsort comparator for doubles. */
static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Pipeline statistics of one extra (untimed) frame, when ARB_pipeline_statistics_query is there. */
typedef struct gl_counts { int have; uint64_t vs_invocations, prims_submitted, clip_prims, fs_invocations; } gl_counts;

/* Count one frame with pipeline-statistics queries (counts->have = 0 without the extension). */
static void count_frame(const gl_api *gl, const gl_scene *s, GLenum index_type, gl_counts *counts)
{
    static const GLenum targets[4] = {GL_VERTEX_SHADER_INVOCATIONS_ARB, GL_PRIMITIVES_SUBMITTED_ARB,
                                      GL_CLIPPING_OUTPUT_PRIMITIVES_ARB, GL_FRAGMENT_SHADER_INVOCATIONS_ARB};
    memset(counts, 0, sizeof *counts);
    if (!gl_has_extension(gl, "GL_ARB_pipeline_statistics_query")) return;
    GLuint q[4];
    GLuint64 v[4] = {0};
    gl->GenQueries(4, q);
    for (int k = 0; k < 4; k++) gl->BeginQuery(targets[k], q[k]);
    draw_frame(gl, s, index_type, 1);
    for (int k = 0; k < 4; k++) gl->EndQuery(targets[k]);
    for (int k = 0; k < 4; k++) gl->GetQueryObjectui64v(q[k], GL_QUERY_RESULT, &v[k]);
    *counts = (gl_counts){1, v[0], v[1], v[2], v[3]};
}

/* Read the FBO as RGBA8, top row first (flipping GL's bottom-up rows). NULL when out of memory. */
static unsigned char *read_image(const gl_api *gl, int w, int h)
{
    size_t row = (size_t)w * 4;
    unsigned char *up = malloc(row * (size_t)h), *img = malloc(row * (size_t)h);
    if (up && img) {
        gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
        gl->ReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, up);
        for (int y = 0; y < h; y++) memcpy(img + (size_t)y * row, up + (size_t)(h - 1 - y) * row, row);
    }
    free(up);
    if (!up) free(img), img = NULL;
    return img;
}

/* Write rgba (w x h, top row first) raw, or as a binary PPM when ppm; 0 or -1. */
static int write_image(const char *path, const unsigned char *rgba, int w, int h, int ppm)
{
    FILE *f = fopen(path, "wb");
    if (!f) return fprintf(stderr, "bench-gl: %s: cannot write\n", path), -1;
    if (ppm) {
        fprintf(f, "P6\n%d %d\n255\n", w, h);
        for (size_t p = 0; p < (size_t)w * h; p++) fwrite(rgba + 4 * p, 1, 3, f);
    } else {
        fwrite(rgba, 4, (size_t)w * h, f);
    }
    int bad = ferror(f);
    bad |= fclose(f) != 0;
    if (bad) return fprintf(stderr, "bench-gl: %s: write error\n", path), -1;
    return 0;
}

/* ---------------------------------------- main ---------------------------------------- */

typedef struct gl_args { const char *scene, *out, *ppm; int frames, warmup, no_clip_control, keep_depth; } gl_args;

/* Parse the command line; 0 or -1 (usage on stderr). */
static int parse_args(int argc, char **argv, gl_args *a)
{
    *a = (gl_args){NULL, NULL, NULL, 10, 3, 0, 0};
    for (int i = 1; i < argc; i++) {
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(argv[i], "--frames") == 0 && v) a->frames = atoi(v), i++;
        else if (strcmp(argv[i], "--warmup") == 0 && v) a->warmup = atoi(v), i++;
        else if (strcmp(argv[i], "--out") == 0 && v) a->out = v, i++;
        else if (strcmp(argv[i], "--ppm") == 0 && v) a->ppm = v, i++;
        else if (strcmp(argv[i], "--no-clip-control") == 0) a->no_clip_control = 1;
        else if (strcmp(argv[i], "--keep-depth") == 0) a->keep_depth = 1;
        else if (argv[i][0] != '-' && !a->scene) a->scene = argv[i];
        else a->scene = NULL, i = argc;
    }
    if (!a->scene || a->frames < 1 || a->frames > 100000 || a->warmup < 0) {
        fprintf(stderr, "usage: bench-gl SCENE_FILE [--frames N] [--warmup N] [--out FILE.rgba] [--ppm FILE.ppm] "
                        "[--no-clip-control] [--keep-depth]\n");
        return -1;
    }
    return 0;
}

/* The result line: key=value pairs parsed by build/bench. */
static void print_result(const gl_api *gl, const egl_state *e, int clip_control, int invalidate, const double *ms,
                         int n, const gl_counts *c)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    const char *lp = getenv("LP_NUM_THREADS");
    printf("bench-gl renderer=\"%s\" gl=%d.%d clip_control=%d lp_threads=%s frames=%d median_ms=%.4f "
           "min_ms=%.4f max_ms=%.4f maxrss_kb=%ld invalidate_depth=%d",
           (const char *)gl->GetString(GL_RENDERER), e->major, e->minor, clip_control, lp ? lp : "default", n,
           ms[n / 2], ms[0], ms[n - 1], ru.ru_maxrss, invalidate);
    if (c->have)
        printf(" vs_invocations=%llu prims_submitted=%llu clip_prims=%llu fs_invocations=%llu",
               (unsigned long long)c->vs_invocations, (unsigned long long)c->prims_submitted,
               (unsigned long long)c->clip_prims, (unsigned long long)c->fs_invocations);
    printf("\n");
}

/* Time the frames: warm-up, then a.frames frames; ms gets the sorted times. */
static void time_frames(const gl_api *gl, const gl_scene *s, GLenum index_type, const gl_args *a, double *ms)
{
    for (int k = 0; k < a->warmup; k++) draw_frame(gl, s, index_type, a->keep_depth);
    for (int k = 0; k < a->frames; k++) {
        double t0 = now_ms();
        draw_frame(gl, s, index_type, a->keep_depth);
        ms[k] = now_ms() - t0;
    }
    qsort(ms, (size_t)a->frames, sizeof *ms, cmp_double);
}

/* Render and time the scene on a current context; 0 or -1. */
static int run(const gl_api *gl, const egl_state *e, const gl_scene *s, const gl_args *a)
{
    GLuint prog = make_program(gl, s->h.patch, s->textured);
    if (!prog || make_fbo(gl, s->h.width, s->h.height) != 0) return -1;
    if (s->textured) make_texture(gl, prog, s);
    GLenum index_type = make_vao(gl, prog, s);
    if (!index_type) return fprintf(stderr, "bench-gl: out of memory\n"), -1;
    int cc = set_state(gl, prog, s, !a->no_clip_control && gl->ClipControl &&
                                        (e->major > 4 || (e->major == 4 && e->minor >= 5) ||
                                         gl_has_extension(gl, "GL_ARB_clip_control")));
    double *ms = malloc((size_t)a->frames * sizeof *ms);
    if (!ms) return fprintf(stderr, "bench-gl: out of memory\n"), -1;
    time_frames(gl, s, index_type, a, ms);
    unsigned char *img = read_image(gl, s->h.width, s->h.height);
    gl_counts counts;
    count_frame(gl, s, index_type, &counts);
    GLenum err = gl->GetError();
    int rc = img && err == GL_NO_ERROR ? 0 : -1;
    if (err != GL_NO_ERROR) fprintf(stderr, "bench-gl: GL error 0x%x\n", err);
    if (rc == 0 && a->out) rc = write_image(a->out, img, s->h.width, s->h.height, 0);
    if (rc == 0 && a->ppm) rc = write_image(a->ppm, img, s->h.width, s->h.height, 1);
    if (rc == 0) print_result(gl, e, cc, !a->keep_depth && gl->InvalidateFramebuffer, ms, a->frames, &counts);
    free(img);
    free(ms);
    return rc;
}

int main(int argc, char **argv)
{
    gl_args a;
    if (parse_args(argc, argv, &a) != 0) return 2;
    gl_scene s;
    if (scene_load(a.scene, &s) != 0) return 1;
    egl_state e = {EGL_NO_DISPLAY, EGL_NO_CONTEXT, 0, 0};
    gl_api gl;
    int rc = egl_init(&e) == 0 && gl_load(&gl) == 0 ? run(&gl, &e, &s, &a) : -1;
    if (e.ctx != EGL_NO_CONTEXT && e.dpy != EGL_NO_DISPLAY) egl_fini(&e);
    scene_free(&s);
    return rc == 0 ? 0 : 1;
}
