/* raster/raster_internal.h -- private types of the rasterizer: the per-draw job, set-up primitives, chunks of
 * set-up primitives with their tile bins, and the small inline helpers of the per-sample path.
 *
 * Pipeline of one rs_draw (draw.c):
 *   1. validate, build the job (per-draw constants);
 *   2. in parallel over chunks of input primitives (clip.c, setup.c, setup_simd.c): clip, project, snap, cull,
 *      set up triangles / lines / points into the chunk's own arrays (submission order inside the chunk), then
 *      bin them to the target's tiles (rs_tile_bits; bin.c; per chunk, so no locks);
 *   3. in parallel over tiles (tri.c, span.c, line.c): walk the chunks in order and each chunk's bin in order, so
 *      every sample sees the primitives in submission order whatever the thread count.
 * rs_draw_source (raster.h; the device's fused path) is the same with step 2 fed piece by piece: each chunk's
 * vertices are produced (shaded) by the thread that sets the chunk up.  A grouped piece (rs_source.group_prims,
 * rs_group_ok) is binned per instance instead of per triangle (RS_K_GROUP entries) and its triangles are set up in
 * step 3, per tile, into an L1 scratch (setup_simd.c's rs_setup_groups / rs_group_tile).
 *
 * Every fast path sits in its own file beside its definition: setup.c (reference set-up) / setup_simd.c (shared
 * pass, four-lane finish); tri.c (reference walk) / span.c (8-lane walks).  setup_internal.h is what the two
 * set-ups share.  Preconditions of the fast paths ("|x| < 2^N", "fits int32") are RS_ASSERTs, live in the
 * INSTESS_CHECKS build (the sanitizer build) and nothing otherwise.
 */
#ifndef INSTESS_RASTER_INTERNAL_H
#define INSTESS_RASTER_INTERNAL_H

#include <math.h>
#include <stdint.h>
#include <stdbool.h>
#include <stddef.h>

#include "raster.h"

/* The fast-path kernels (span.c, setup_simd.c) are compiled twice: for AVX2 (the build's -march=x86-64-v3) and,
 * with RS_KERNEL_AVX512 defined, for AVX-512 (-march=x86-64-v4: the same source, with 32 vector registers and
 * AVX-512's encodings).  RS_KERNEL(name) gives each copy's entry points their own names; the job's kernel table
 * (rs_kernels, draw.c) picks the copy the context chose (rs_set_isa).  Both copies perform the same IEEE
 * operations per lane, so they write the same bytes (tests/test_reference_path.c compares each with the
 * reference path and, in test_isa_avx512, with each other). */
#ifdef RS_KERNEL_AVX512
#define RS_KERNEL(name) name##_avx512
#else
#define RS_KERNEL(name) name##_avx2
#endif

/* RS_NO_KERNELS (the browser build, `make web`: WebAssembly has neither instruction set): span.c and setup_simd.c
 * are not compiled, the kernel table has no functions (draw.c), and every draw takes the reference path, which
 * writes the same bytes (make_job), but for tri.c's 4-sample walk, which needs no kernels (rs_job.walk4).
 * RS_ONLY_REFERENCE says so at compile time. */
#ifdef RS_NO_KERNELS
#define RS_ONLY_REFERENCE true
#else
#define RS_ONLY_REFERENCE false
#endif

/* RS_ASSERT(cond): assert(cond) when INSTESS_CHECKS is defined; otherwise no code at all (cond is not evaluated,
 * only type-checked, so it may name variables that exist for the check alone). */
#ifdef INSTESS_CHECKS
#include <assert.h>
#define RS_ASSERT(cond) assert(cond)
#else
#define RS_ASSERT(cond) ((void)sizeof(!(cond)))
#endif

/* |v| <= 2^n: the bit budgets' claims (setup.c), for RS_ASSERT. */
static inline bool rs_within(int64_t v, int n) { return v >= -((int64_t)1 << n) && v <= (int64_t)1 << n; }

/* Tile sides by the target's samples (raster.h's RS_TILE_SIZE): 128 pixels on 1-sample targets (fewer tiles per
 * grid instance: fewer step set-ups repeated on tile borders), 64 on multisampled ones (a 4-sample tile of 128
 * would take 512 KB a thread: the viewer's frame was 4 % slower).  docs/performance-history.md, tenth round. */
#define RS_TILE_MIN 64
static inline int rs_tile_bits(const rs_target *rt) { return rt->samples > 1 ? 6 : 7; }
/* Tiles of side 1 << bits across n pixels. */
static inline int rs_tiles_across(int n, int bits) { return (n + (1 << bits) - 1) >> bits; }
_Static_assert(RS_TILE_SIZE == 128, "raster.h's tile side of 1-sample targets: rs_tile_bits");
/* Planes of at least this many bytes (rows of whole cache lines) get the tile copy-out's streaming stores (a
 * 1024x1024 target's two planes, 8 MB, do not stay in a core's L2 cache; measured on scenes A and B, 2 threads:
 * the tile pass 5-8% faster). */
#define COPY_STREAM_BYTES (4u << 20)
#define RS_WORK_UNIT ((uint64_t)2 * RS_SUB * RS_SUB)   /* work units per pixel: doubled areas in 1/256 px */
#define RS_BLOCK 8                    /* block side of the trivial reject / accept test */
#define RS_MAX_POLY 16                /* 3 vertices + one per clip plane (6 + 6 user planes), with room */
#define RS_ATTR_STRIDE 12             /* floats per interpolated slot: 4 components x (v0, d1, d2) */

enum { RS_K_TRI = 0, RS_K_LINE = 1, RS_K_POINT = 2, RS_K_GROUP = 3 };

typedef struct rs_pvert rs_pvert;
typedef struct rs_kernels rs_kernels;

/* Constants of one draw, shared read-only by every thread. */
typedef struct rs_job {
    const rs_state *st;
    rs_target *rt;
    int prim;                   /* RS_PRIM_* */
    const rs_vertex *verts;
    const uint32_t *idx;
    const rs_pvert *pv;         /* the shared pass's projected vertices (fast path, indexed triangles), or NULL */
    int samples;                /* samples per pixel in the target (1 or 4) */
    int32_t sox[4], soy[4];     /* sample offsets from the pixel centre, 1/256 px (0 when not multisampling) */
    int32_t omax;               /* max |offset| over the samples, 1/256 px */
    int sx0, sy0, sx1, sy1;     /* scissor = viewport ∩ target, pixels, half-open */
    int64_t cx, cy;             /* viewport centre, 1/256 px (absolute) */
    double sx_scale, sy_scale;  /* NDC -> fixed point relative to the centre: width*128, -height*128 */
    double gx, gy;              /* guard band in NDC units: |x| <= gx*w, |y| <= gy*w */
    float zscale, zoff;         /* depth = zoff + zscale * z/w */
    float zlo, zhi;             /* depth clamp (the viewport's depth range) */
    int n_slots;                /* interpolated slots (attr_mask ∩ slots that are consumed) */
    int slot[RS_MAX_ATTR];
    int color_idx;              /* index of RS_ATTR_COLOR0 in slot[], -1: constant white */
    int aov_idx[RS_MAX_AOV];    /* index of each AOV plane's slot in slot[], -1: zeros */
    int stride;                 /* floats per primitive in the attribute pool */
    bool flat;
    bool reference;             /* the scalar reference path (rs_set_reference_path): no fast paths */
    const rs_kernels *kern;     /* the fast-path kernels of the context's instruction set (rs_set_isa) */
    int span_mode;              /* span.c's walk instance for the depth state (rs_span_mode) */
    bool ext;                   /* a state of pixel.c is on (rs_state_ext): the reference walk's rs_frag_ext */
    bool walk4;                 /* tri.c's 4-sample walk (tri_tile_msaa4): 4 samples, plain states (no blending, no
                                   pixel.c state), the reference path not asked for -- no kernels needed, so the
                                   browser build, always on the reference path otherwise, takes it too */
    unsigned clip_mask;         /* the clip planes that clip (rs_outcode's bits): near, far, guard band and the
                                   enabled user planes; the guard band alone with CLIPPING FALSE */
    bool grid_mirrored;         /* rs_source.grid_mirrored of a grid source: the row set-up culls the other sign */
    int tile_bits;              /* the target's tiles: side 1 << tile_bits (rs_tile_bits) */
    int tiles_x, tiles_y, n_tiles;
} rs_job;

/* A triangle after setup: integer edge functions and float planes, all relative to vertex 0. */
typedef struct rs_tri {
    int32_t ea[3], eb[3];        /* E = ea*X + eb*Y + ec in int64 (X, Y: sample, 1/256 px, relative to the viewport */
    int64_t ec[3];               /* centre); inside iff E >= 0 (top-left bias folded into ec).  ea, eb are vertex
                                    differences, |.| <= 2^23 (setup.c's bit budget): in int32, rs_prim takes 128
                                    bytes instead of 152 for the set-up to write and the tile pass to read */
    int32_t vx, vy;              /* vertex 0, 1/256 px relative to the centre: origin of the float planes */
    float z[3];                  /* depth plane: dz/dx, dz/dy per pixel, z at vertex 0 (bias included) */
    float q1[3], q2[3], s[3];    /* planes of lambda1/w1, lambda2/w2, sum lambda_i/w_i (1/w normalised) */
} rs_tri;

/* A line after setup: the major axis walk of line.c. */
typedef struct rs_line {
    int64_t m0, n0;              /* start on the major / minor axis, 1/256 px, absolute */
    int64_t dm, dn;              /* end - start, dm > 0 */
    float z0, dz;                /* depth at the start (bias included) and its change to the end */
    float w0, w1;                /* normalised 1/w at the start and the end */
    bool xmajor;
} rs_line;

typedef struct rs_point {
    float z;
} rs_point;

/* A group of a grouped piece (RS_K_GROUP), binned as one entry with the union of its drawn triangles' pixel boxes
 * and set up inside the tile pass (rs_group_tile): level 0, drawn triangles [first, first + count) of its chunk's
 * gtri; or a grid group (rs_source.grid_level): the regular grid of level `level` over the chunk's vertices from
 * vbase on, its row and step boxes at grow[first .. first + count) (setup_simd.c's grid_boxes). */
typedef struct rs_group {
    uint32_t first, count;
    uint32_t level, vbase;
} rs_group;

typedef struct rs_prim {
    int32_t x0, y0, x1, y1;      /* pixel bounding box clamped to the scissor, inclusive */
    int kind;                    /* RS_K_* */
    int back;                    /* 1: a triangle counter-clockwise on screen (two-sided stencil); set by the
                                    reference set-up only, read only by rs_frag_ext (in what was padding) */
    union { rs_tri t; rs_line l; rs_point p; rs_group g; } u;
} rs_prim;

/* A drawn triangle of a grouped piece, as the set-up region leaves it for the tile pass: its vertices (indices into
 * the chunk's gpv and gattr) in clockwise order, and its pixel box (x0, y0, x1, y1, inside the scissor: below
 * RS_MAX_SIZE = 2^14, so int16) -- 20 bytes where today's path writes a 128-byte rs_prim and its attribute block. */
typedef struct rs_gtri {
    uint32_t v[3];
    int16_t box[4];
} rs_gtri;
_Static_assert(sizeof(rs_prim) == 128, "rs_prim's size as rs_tri's comment states it");

/* ptile value of a primitive whose box touches more than one tile. */
#define RS_MULTI_TILE UINT32_MAX

/* The set-up output of one chunk of input primitives, with its tile bins (CSR: bin_off[tile]..[tile+1]). */
typedef struct rs_chunk {
    _Alignas(64) size_t first, count; /* input primitives [first, first+count) (a chunk starts a cache line: two
                                    set-up threads writing neighbouring chunks' counters share none) */
    rs_prim *prims;
    uint32_t *ptile;             /* per primitive: its tile when its box lies in one, else RS_MULTI_TILE */
    float *attr;                 /* stride floats per primitive */
    size_t attr_cap;             /* floats attr holds (cap times the stride of the draw that last grew it) */
    size_t n, cap;
    uint32_t *bin_off;           /* n_tiles + 1 */
    size_t bin_off_cap;
    uint32_t *bin_idx;
    size_t n_idx, idx_cap;
    uint64_t culled, clipped, degenerate, drawn;
    uint64_t work;               /* triangles' min(area, box) in RS_WORK_UNIT, saturating (RS_MAX_OVERDRAW) */
    bool oom;
    bool bad_piece;              /* rs_draw_source: the producer broke the piece's promise (RS_EINVAL) */
    /* a grouped piece (rs_draw_source with group_prims; rs_setup_groups): its projected vertices, their
     * interpolated slots (n_slots rs_vec4 per vertex) and its drawn triangles, kept for the tile pass; prims then
     * holds RS_K_GROUP entries only */
    void *gpv;
    size_t gpv_cap;              /* rs_pvert records */
    rs_vec4 *gattr;
    size_t gattr_cap;
    rs_gtri *gtri;
    size_t gtri_cap;
    /* a grid piece (rs_source.grid_level): its projected vertices again as rows of x, y (int32), z (float) and
     * 1/w (double), each array gsoa_cap entries long (RS_GRID_PAD zeros past the piece's vertices: the row loads
     * read past a row's end), and per grid group per row the pixel box of its drawn triangles, then one per step
     * of eight triangles of the row (x0, x1, y0, y1; x0 > x1 when none) */
    void *gsoa;
    size_t gsoa_cap;
    int16_t (*grow)[4];
    size_t grow_cap;
    uint64_t grid_groups;        /* grid group entries pushed (the row path's; tests look) */
    uint64_t grid_direct;        /* the tile pass: the row path's triangles that rs_tri_run took straight to the
                                    small-triangle walks (tests look; added atomically once per group and tile, as tiles of
                                    one chunk run on several threads; zeroed by the set-up region) */
    uint32_t draw;               /* a recorded draw's chunk: its draw in rs->q ... */
    size_t piece;                /* ... and its piece of that draw's source */
    int setup_thread;            /* the thread of the flush's region that set it up (the tile ranges follow: draw.c) */
} rs_chunk;

/* Is rt well formed: planes present, sizes and samples in range, AOV planes (at most RS_MAX_AOV, on one sample)
 * with data, slots and components in range?  Every public function that reads or writes a target's planes asks
 * first (a hand-made target may say anything). */
bool rs_target_valid(const rs_target *rt);

/* A draw recorded for the frame's scene (rs_set_scene): its job (j.st points at st once the flush runs: the queue
 * may move), its source (set up at the flush, piece k into chunk c0 + k) and its chunks rs->chunks[c0 .. c0 + nc)
 * (nc 0 once the flush has dropped it for an error). */
typedef struct rs_scene_draw {
    rs_job j;
    rs_state st;
    rs_source src;
    size_t c0, nc;
} rs_scene_draw;

struct rs_context {
    int threads;
    uint64_t work;               /* RS_WORK_UNIT covered by the draws since the last deferred clear (RS_MAX_OVERDRAW) */
    bool frame;                  /* a deferred clear started a frame (else each draw's work counts alone) */
    bool reference;              /* rs_set_reference_path's argument (a job is on the reference path also without
                                    kernels: RS_ONLY_REFERENCE, make_job) */
    bool timing;                 /* rs_set_timing: phase times into rs_stats */
    int isa;                     /* RS_ISA_*: the fast paths' instruction set (rs_set_isa) */
    rs_chunk *chunks;
    size_t n_chunks_cap;
    uint64_t *tile_stats;        /* 2 per tile: samples tested, written */
    size_t tile_stats_cap;
    struct rs_range *ranges;     /* a flush's work split per thread (draw.c): ranges of tiles, ranges of pieces ... */
    int *range_own;              /* ... and per thread the range of tiles it owns (-1: none) */
    size_t ranges_cap;           /* threads both have room for */
    void *pv;                    /* rs_pvert scratch of the shared pass */
    size_t pv_cap;
    uint8_t *pend;               /* per tile of pend_rt: the planes (RS_CLEAR_COLOR, _DEPTH) whose deferred clear is
                                    not yet written there; 0: none */
    size_t pend_cap;
    int pend_tiles;              /* tiles of pend_rt with a deferred clear; 0: none */
    rs_target *pend_rt;          /* the target of the deferred clear (rs_target_clear_deferred) */
    uint32_t *pend_color;        /* pend_rt->color when deferred (detects a reallocated target) */
    unsigned pend_flags;         /* the deferred clear's flags, colour and depth */
    uint32_t pend_rgba;
    float pend_z;
    /* the tiles whose colour plane holds clean_rgba as fill_tile wrote it, nothing written there since (clean[tile]
     * 1), valid while clean_on for clean_rt with colour plane clean_color and clean_tiles tiles: from the deferred
     * clear through the frame's present to the next deferred clear (rs_target_flush_planes' RS_PRESENT), whose
     * fill those tiles then skip; any other flush of a target drops them all (the caller may write the planes) */
    uint8_t *clean;
    size_t clean_cap;
    bool clean_on;
    const rs_target *clean_rt;
    const uint32_t *clean_color;
    int clean_tiles;
    uint32_t clean_rgba;
    void *tbuf;                  /* tile buffers of the tile pass, one per thread (rs_tile_buffer_size bytes each) */
    size_t tbuf_cap;             /* bytes */
    rs_stats *sink;              /* rs_set_scene: the queued draws' tile counters go here; NULL: no queue */
    rs_scene_draw *q;            /* the queued draws, in submission order */
    size_t q_n, q_cap;
    size_t q_chunks, q_prims;    /* chunks they use (rs->chunks[0 .. q_chunks)), the triangles their sources promise */
    size_t q_max_verts;          /* their sources' largest max_verts: each set-up slot's share of rs->pv at the flush */
    rs_target *q_rt;             /* their target and its colour plane when queued */
    uint32_t *q_color;
    int scene_err;               /* the first error of a recorded draw at a flush (rs_scene_error), else RS_OK */
};

/* A tile being rasterized by one thread: its pixel rectangle (inside the scissor), where its samples live and its
 * counters.  Sample s of pixel (x, y) is color / depth [rs_tile_index(t, x, y) * samples + s]: the target's planes
 * themselves (origin (0, 0), pitch = the target's width), or the thread's tile buffer (origin = the tile's
 * corner, pitch the tile's side) that the tile pass fills with a deferred clear and writes back when the tile is
 * done. */
typedef struct rs_tile {
    int x0, y0, x1, y1;          /* half-open */
    uint64_t tested, written;
    uint32_t *color;
    float *depth;
    int ox, oy;                  /* the pixel at index 0 */
    size_t pitch;                /* pixels per row */
} rs_tile;

/* Index (in pixels) of pixel (x, y) of tile t in t->color / t->depth (times the samples per pixel). */
static inline size_t rs_tile_index(const rs_tile *t, int x, int y)
{
    return (size_t)(y - t->oy) * t->pitch + (size_t)(x - t->ox);
}

/* ---- clip.c: homogeneous clipping of polygons and segments ---- */
#define RS_CLIP_PLANES 6   /* near, far, left, right, top, bottom (guard band) */
#define RS_ALL_PLANES (RS_CLIP_PLANES + RS_MAX_CLIP_PLANES) /* and the user planes, bits 6..11 */

/* A vertex being clipped: homogeneous position in double, attribute slots by pointer. */
typedef struct rs_cvert {
    double p[4];
    const rs_vec4 *a;      /* RS_MAX_ATTR slots (only the job's slots are valid for clip-made vertices) */
    double line[3];        /* guard-band stage: projective line (x, y, w) through this vertex and the next */
    bool edge;             /* the edge from this vertex to the next is (part of) an input edge */
    bool orig;             /* an input vertex, not made by clipping */
} rs_cvert;

/* Storage for the attributes of vertices made by clipping one primitive. */
typedef struct rs_clipbuf {
    rs_vec4 pool[2 * RS_ALL_PLANES + 4][RS_MAX_ATTR];
    int n_pool;
} rs_clipbuf;

/* Bit k set when homogeneous point p is outside clip plane k. */
unsigned rs_outcode(const rs_job *j, const double *p);
/* Clip polygon poly[0..n) (room for RS_MAX_POLY) against the planes in mask; returns the new count. */
int rs_clip_poly(const rs_job *j, rs_cvert *poly, int n, unsigned planes, rs_clipbuf *cb);
/* Clip segment v[0]-v[1] in place; false when it is entirely outside. */
bool rs_clip_line(const rs_job *j, rs_cvert *v, unsigned planes, rs_clipbuf *cb);

/* ---- setup.c: set-up of a chunk (the shared pass's triangles go to setup_simd.c) ---- */
/* Set up input primitives [c->first, c->first+c->count) of the job into chunk c (prims, attr, counters). */
void rs_setup_chunk(const rs_job *j, rs_chunk *c);

/* ---- setup_simd.c: the shared pass (one copy per instruction set: RS_KERNEL) ---- */
/* Outcode and projection of vertex v into its record (once per vertex, not once per triangle). */
void rs_project_vertex_avx2(const rs_job *j, const rs_vertex *v, rs_pvert *out);
void rs_project_vertex_avx512(const rs_job *j, const rs_vertex *v, rs_pvert *out);
/* Bytes of one rs_pvert record (the type is opaque outside setup_simd.c). */
size_t rs_pvert_size(void);
/* rs_project_vertex for v[0..n) into out[0..n) (four at a time where AVX2 is available, same results). */
void rs_project_vertices_avx2(const rs_job *j, const rs_vertex *v, size_t n, rs_pvert *out);
void rs_project_vertices_avx512(const rs_job *j, const rs_vertex *v, size_t n, rs_pvert *out);
/* Set up chunk c's triangles from the shared pass's records (j->pv, indices j->idx): per triangle what
 * setup.c's rs_setup_triangle gives, the front-facing unclipped ones finished four at a time. */
void rs_setup_shared_avx2(const rs_job *j, rs_chunk *c);
void rs_setup_shared_avx512(const rs_job *j, rs_chunk *c);

/* Grouped pieces (rs_source.group_prims; the fast path only, see rs_group_ok): the set-up region projects the
 * piece's vertices into c->gpv, keeps their slots in c->gattr, culls each triangle as rs_setup_shared does (the
 * same counters and work) and keeps each drawn one with a pixel as a 20-byte rs_gtri (oriented vertices, box), and
 * pushes one RS_K_GROUP entry per run of group triangles with the union of their boxes; the tile pass sets up, per
 * group entry of a tile's bin, the group's triangles whose box meets the tile -- rs_setup_shared's edges and planes
 * (finish4), into an L1 scratch -- and rasterizes each at once with rs_tri_tile, in the group's order (grid groups:
 * with rs_tri_run, below).
 * rs_setup_groups projects the piece itself (a grid piece's vertices straight into its rows, the records only when
 * a path reading them comes up) and returns false (the chunk left for rs_setup_chunk with j->pv = c->gpv, the
 * records made) when a vertex of the piece is not PV_READY (clipping needed).
 * Grid groups (level = rs_source.grid_level > 0; setup_simd.c, "grid rows"): a full group of a grid piece whose
 * vertices span less than 2^15 (1/256 px, 128 px) in x and in y keeps no rs_gtri: the set-up region counts and
 * boxes its triangles from contiguous loads of vertex rows r and r+1 (eight consecutive triangles of a row -- up,
 * down, up, ... -- per step; no index list) and keeps its rows' and steps' pixel boxes; the tile pass does the same
 * per step meeting the tile and sets up the triangles that meet it from those loads with finish4's operations, into
 * the L1 scratch.  Other groups (larger, over more than 4 tiles, partial, a piece without the promise) take the paths
 * above: the same bytes and counters either way. */
#define RS_GRID_PAD 16
bool rs_setup_groups_avx2(const rs_job *j, rs_chunk *c, const rs_vertex *v, size_t nv, const uint32_t *idx,
                          size_t np, size_t group, size_t level);
bool rs_setup_groups_avx512(const rs_job *j, rs_chunk *c, const rs_vertex *v, size_t nv, const uint32_t *idx,
                            size_t np, size_t group, size_t level);
/* Rasterize group entry p of chunk c inside tile t (set-up of its triangles that meet the tile, then rs_tri_tile). */
void rs_group_tile_avx2(const rs_job *j, rs_tile *t, const rs_chunk *c, const rs_prim *p);
void rs_group_tile_avx512(const rs_job *j, rs_tile *t, const rs_chunk *c, const rs_prim *p);
/* May draw j's pieces be grouped: the fast path's walk (1-sample target, off the reference path, so none of pixel.c's
 * states), solid fill, Gouraud shading, no pixel shader, no AOV planes? */
static inline bool rs_group_ok(const rs_job *j)
{
    return !RS_ONLY_REFERENCE && !j->reference && !j->ext && j->samples == 1 && j->prim == RS_PRIM_TRIANGLES &&
           j->st->fill_mode == RS_FILL_SOLID && !j->flat && !j->st->ps && j->rt->n_aov == 0;
}

/* ---- bin.c ---- */
/* Grow *buf (elements of `size` bytes, capacity *cap, doubling) to hold n; false (*buf kept) when out of memory:
 * the chunks' growing arrays (bins, grouped pieces' records and rows). */
bool rs_reserve(void **buf, size_t *cap, size_t n, size_t size);
/* Bin chunk c's primitives to tiles (bin_off / bin_idx); sets c->oom on allocation failure. */
void rs_bin_chunk(const rs_job *j, rs_chunk *c);
/* rs_flush, and when the queued draws go into rt, the tiles none of them touches get the deferred clear of the
 * planes `planes` in the same tile pass (rs_target_flush_planes: one parallel region instead of two). */
void rs_flush_fill(rs_context *rs, const rs_target *rt, unsigned planes);

/* ---- target.c ---- */
/* rs_target_clear on `threads` threads (0: all cores), split by rows (rs_target_clear_deferred's fallback). */
void rs_target_clear_threads(rs_target *rt, unsigned flags, uint32_t rgba, float z, int threads);
/* The tile pass: write the planes `planes` (RS_CLEAR_*) of tile `tile` of the job's target whose clear is deferred
 * on rs (and mark them written). */
void rs_tile_flush(const rs_context *rs, const rs_job *j, int tile, unsigned planes);
/* Bytes of one tile buffer for the job's target (a tile's pixels of colour and depth samples). */
size_t rs_tile_buffer_size(const rs_job *j);
/* The tile pass, when tile `tile`'s clear is deferred: fill buffer `buf` (rs_tile_buffer_size bytes, 32-byte
 * aligned) with the clear (planes the clear keeps are copied from the target), clear its AOV pixels in the target,
 * and point t at the buffer; false (nothing done) when the clear is not deferred. */
bool rs_tile_buffer_begin(const rs_context *rs, const rs_job *j, int tile, rs_tile *t, void *buf);
/* Copy tile buffer t back into the job's target but for the planes `keep` (RS_CLEAR_*), and mark the tile's clear
 * done but for those (their deferred clear stays: rs_target_flush_planes' RS_DISCARD_DEPTH). */
void rs_tile_buffer_end(const rs_context *rs, const rs_job *j, int tile, const rs_tile *t, unsigned keep);
/* The planes (RS_CLEAR_*) of tile `tile` of the job's target whose clear is deferred on rs (0: none). */
unsigned rs_tile_pending(const rs_context *rs, const rs_job *j, int tile);
/* The tile pass draws into tile `tile` of the job's target: its colour no longer holds a fill (rs->clean). */
void rs_tile_drawn(const rs_context *rs, const rs_job *j, int tile);

/* ---- span.c, span_wide.c: the 8-lane fast path of triangles on 1-sample targets ---- */
/* True when the job may take the fast path: 1-sample targets off the reference path, with AVX2. */
static inline bool rs_span_ok(const rs_job *j)
{
#ifdef __AVX2__
    return j->samples == 1 && !j->reference;
#else
    return false;
#endif
}
/* The walk instance (rs_job.span_mode) for depth state st drawing into rt: 0 LESSEQUAL with writes, 1 LESS with
 * writes (both without blending or AOV planes), 2 any other state. */
static inline int rs_span_mode(const rs_state *st, const rs_target *rt)
{
    const bool zw = st->z_enable && st->z_write && !st->blend_enable && rt->n_aov == 0;
    return zw && st->z_func == RS_CMP_LESSEQUAL ? 0 : zw && st->z_func == RS_CMP_LESS ? 1 : 2;
}
/* Rasterize triangle p's pixels [x0, x1] x [y0, y1] (its box clipped to tile t) on the fast path (rs_span_ok):
 * the same bytes and counters as tri.c's reference walk.  One copy per instruction set (RS_KERNEL). */
void rs_tri_fast_avx2(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                      int y1);
void rs_tri_fast_avx512(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                        int y1);

/* span_wide.c: rs_tri_fast's walks of larger triangles, the interval walk -- walk 1 or 2 (box at most 16 or 32
 * wide, coef_small, tile at least 8 wide): groups from each row's first covered column, 3 (any): 8-aligned groups
 * -- in the job's span_mode.  One copy per instruction set (RS_KERNEL). */
void rs_tri_wide_avx2(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1, int y1,
                      int walk);
void rs_tri_wide_avx512(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                        int y1, int walk);

/* The grid rows' tile pass (setup_simd.c's grid_tile) rasterizes the triangles of a step (up to 8, in the L1
 * scratch: triangle sp[l], attribute block sa + l * stride, pixel box already clipped to tile t in cb[0..4)[l] as
 * x0, y0, x1, y1) for the lanes l of live (cb, live, small, stamp, covm: rs_run_step's fields), in lane order, with
 * the walk picked once per call from the job's span_mode and the lanes' box sizes: a lane of `small` (the set-up
 * lanes' coef_small: vertex spans of at most 2^13 in x and in y) whose box rs_tri_fast would give the
 * small-triangle walks goes straight to them, any other through rs_tri_fast -- the same bytes and counters.  The
 * lanes of `stamp` (a part of those: the caller's test of rs_tri_fast's and walk_small's conditions for the stamp
 * walk, plain modes only) go to the stamp walk at once, and
 * their attribute blocks hold the colour slot alone, as v0, d1, d2 of four channels each (rs_fill_slot's values,
 * not interleaved), and covm[l] is their coverage (the stamp walk's mask: bit row * 4 + column of the clipped box
 * set for a covered pixel; the caller computes it for the whole step, with the box corner's offsets from vertex 0
 * and in the tile's planes); the others' blocks are rs_fill_slot's.  (The step's arrays in one struct: one pointer
 * instead of four arguments.)
 * Returns the triangles that went straight (the test's counter). */
typedef struct rs_run_step {
    int32_t cb[4][8];               /* the lanes' boxes clipped to the tile: x0, y0, x1, y1 */
    uint32_t covm[8];               /* the stamp lanes: coverage (bit row * 4 + column of the clipped box) */
    int32_t xs[8], ys[8], off[8];   /* the stamp lanes: the box corner from vertex 0 (1/256 px, modulo 2^32) and its
                                       rs_tile_index */
    int32_t pitch;                  /* the tile's pitch (the stamp lanes broadcast it from here) */
    unsigned live, small, stamp;
} rs_run_step;
unsigned rs_tri_run_avx2(const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa, size_t stride,
                         const rs_run_step *s);
unsigned rs_tri_run_avx512(const rs_job *j, rs_tile *t, const rs_prim *sp, const float *sa, size_t stride,
                           const rs_run_step *s);

/* ---- the kernel table: one row per instruction set (draw.c) ---- */
struct rs_kernels {
    const char *name;                                   /* rs_isa_name */
    void (*tri_fast)(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a, int x0, int y0, int x1,
                     int y1);                           /* rs_tri_fast_* */
    void (*project_vertices)(const rs_job *j, const rs_vertex *v, size_t n, rs_pvert *out);
    void (*project_vertex)(const rs_job *j, const rs_vertex *v, rs_pvert *out);
    void (*setup_shared)(const rs_job *j, rs_chunk *c); /* rs_setup_shared_* */
    bool (*setup_groups)(const rs_job *j, rs_chunk *c, const rs_vertex *v, size_t nv, const uint32_t *idx,
                         size_t np, size_t group, size_t level);   /* rs_setup_groups_* */
    void (*group_tile)(const rs_job *j, rs_tile *t, const rs_chunk *c, const rs_prim *p); /* rs_group_tile_* */
};
/* The kernels of instruction set isa (RS_ISA_*; any value the CPU may lack: check rs_isa_supported first). */
const rs_kernels *rs_kernels_of(int isa);

/* ---- tri.c, line.c ---- */
/* Rasterize triangle p (attributes a) inside tile t. */
void rs_tri_tile(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a);
/* Rasterize line p (attributes a) inside tile t. */
void rs_line_tile(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a);
/* Rasterize point p (attributes a) inside tile t. */
void rs_point_tile(const rs_job *j, rs_tile *t, const rs_prim *p, const float *a);
/* Depth-test pixel (x, y)'s samples in cov at the one depth z, then shade with barycentrics (b1, b2) and write. */
void rs_frag_const_z(const rs_job *j, rs_tile *t, int x, int y, unsigned cov, float z, const float *a,
                     float b1, float b2);

/* ---- pixel.c: D3D9's per-pixel states beyond depth and blending (the reference walk only) ---- */
/* Whether st has a state on that only the reference path implements (rs_job.ext): alpha test, stencil (with a
 * stencil plane in rt), colour write mask, CLIPPING FALSE, user clip planes, pre-transformed vertices.  The
 * scissor is not one: it narrows the job's rectangle, which every path honours. */
bool rs_state_ext(const rs_state *st, const rs_target *rt);
/* The job's clip planes (rs_job.clip_mask) for st. */
unsigned rs_clip_mask(const rs_state *st);
/* The pixel of a job with ext: shade colour at (b1, b2) of attribute block a, alpha test, then per covered sample
 * s of cov the stencil and depth tests (zs[s]: its clamped depth) with their stencil operations (the CCW states
 * when `back` and two-sided), depth write, blend and colour write mask, and the AOV planes. */
void rs_frag_ext(const rs_job *j, rs_tile *t, int x, int y, unsigned cov, const float *zs, bool back,
                 const float *a, float b1, float b2);
/* rs_frag_ext after the colour: the pixel's colour src (packed RGBA8) through the alpha test, stencil, depth,
 * blend, colour mask, and the AOV planes from (b1, b2) of a. */
void rs_frag_out(const rs_job *j, rs_tile *t, int x, int y, unsigned cov, const float *zs, bool back, uint32_t src,
                 const float *a, float b1, float b2);
/* The pixel shader's inputs at barycentrics (b1, b2) of attribute block a: every interpolated slot into v[slot]. */
void rs_ps_lane(const rs_job *j, const float *a, float b1, float b2, rs_vec4 *v);
/* Run the pixel shader on quad q and take lane `lane` (pixel (x, y), coverage cov, sample depths zs -- replaced
 * by oDepth when the shader writes it) through rs_frag_out, unless the shader killed it. */
void rs_frag_ps(const rs_job *j, rs_tile *t, int x, int y, unsigned cov, float *zs, bool back, const rs_ps_quad *q,
                int lane, const float *a, float b1, float b2);
/* rs_frag_ps after the shader: lane `lane` of its outputs o (pixel (x, y), ...) through rs_frag_out. */
void rs_ps_write(const rs_job *j, rs_tile *t, int x, int y, unsigned cov, float *zs, bool back, const rs_ps_out *o,
                 int lane, const float *a, float b1, float b2);

/* ---- small helpers ---- */
/* floor(a / b) for b > 0. */
static inline int64_t rs_floor_div(int64_t a, int64_t b)
{
    int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}
/* ceil(a / b) for b > 0. */
static inline int64_t rs_ceil_div(int64_t a, int64_t b) { return -rs_floor_div(-a, b); }

/* Minor-axis pixel of line l at major pixel i (nearest pixel centre, ties towards +minor); exact in int64. */
static inline int64_t rs_line_minor(const rs_line *l, int64_t i)
{
    return rs_floor_div((l->n0 + RS_SUB / 2) * l->dm + (i * RS_SUB - l->m0) * l->dn, (int64_t)RS_SUB * l->dm);
}

/* Saturate to [0, 1]; NaN becomes 0. */
static inline float rs_sat(float c) { return c > 0.0f ? (c < 1.0f ? c : 1.0f) : 0.0f; }

/* float colour channel -> 8 bits, rounded to nearest. */
static inline uint32_t rs_to8(float c) { return (uint32_t)(int)(rs_sat(c) * 255.0f + 0.5f); }

/* Depth test: does new depth z pass against stored d with RS_CMP_* f? */
static inline bool rs_zpass(int f, float z, float d)
{
    switch (f) {
    case RS_CMP_NEVER: return false;
    case RS_CMP_LESS: return z < d;
    case RS_CMP_EQUAL: return z == d;
    case RS_CMP_LESSEQUAL: return z <= d;
    case RS_CMP_GREATER: return z > d;
    case RS_CMP_NOTEQUAL: return z != d;
    case RS_CMP_GREATEREQUAL: return z >= d;
    default: return true;
    }
}

/* rs_zpass per lane of vectors z, d of any width (GCC's vector extensions: a comparison gives -1 / 0 per lane
 * with C's semantics, NaN false but for !=), as mask type T (span_lanes.h's 8 lanes, tri.c's 4). */
#define RS_ZPASS_LANES(T, f, z, d)                                  \
    __extension__({                                                 \
        T m_;                                                       \
        switch (f) {                                                \
        case RS_CMP_NEVER: m_ = (T){0}; break;                      \
        case RS_CMP_LESS: m_ = (z) < (d); break;                    \
        case RS_CMP_EQUAL: m_ = (z) == (d); break;                  \
        case RS_CMP_LESSEQUAL: m_ = (z) <= (d); break;              \
        case RS_CMP_GREATER: m_ = (z) > (d); break;                 \
        case RS_CMP_NOTEQUAL: m_ = (z) != (d); break;               \
        case RS_CMP_GREATEREQUAL: m_ = (z) >= (d); break;           \
        default: m_ = ((z) == (z)) | ((z) != (z)); break;           \
        }                                                           \
        m_;                                                         \
    })

/* Clamp depth z to the viewport's range [lo, hi] (NaN -> lo). */
static inline float rs_zclamp(float z, float lo, float hi) { return z >= lo ? (z <= hi ? z : hi) : lo; }

/* Blend packed RGBA8 src over dst with the job's factors (8-bit math, see frag.c). */
uint32_t rs_blend(int sf, int df, uint32_t src, uint32_t dst);
/* Write the target's AOV planes at pixel (x, y) from attribute block a at barycentrics (b1, b2). */
void rs_write_aov(const rs_job *j, const float *a, float b1, float b2, int x, int y);

/* Colour (packed RGBA8) at perspective barycentrics (b1, b2) of attribute block a (white without COLOR0). */
static inline uint32_t rs_shade_color(const rs_job *j, const float *a, float b1, float b2)
{
    if (j->color_idx < 0) return 0xffffffffu;
    const float *p = a + j->color_idx * RS_ATTR_STRIDE;
    uint32_t r = rs_to8(p[0] + b1 * p[1] + b2 * p[2]);
    uint32_t g = rs_to8(p[3] + b1 * p[4] + b2 * p[5]);
    uint32_t b = rs_to8(p[6] + b1 * p[7] + b2 * p[8]);
    uint32_t al = rs_to8(p[9] + b1 * p[10] + b2 * p[11]);
    return r | g << 8 | b << 16 | al << 24;
}

/* Store colour src (blended when enabled) into the samples in mask `pass` of the pixel whose samples start at col. */
static inline void rs_write_color(const rs_job *j, uint32_t *col, unsigned pass, uint32_t src)
{
    const rs_state *st = j->st;
    for (int s = 0; s < j->samples; s++) {
        if (!(pass & (1u << s))) continue;
        col[s] = st->blend_enable ? rs_blend(st->src_blend, st->dst_blend, src, col[s]) : src;
    }
}

#endif
