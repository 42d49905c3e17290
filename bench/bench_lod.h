/* bench/bench_lod.h -- scene D of the benchmark (bench/bench_lod.c): adaptive level of detail against one uniform
 * level, instess alone.  bench.c calls it for `--scenes D`. */
#ifndef INSTESS_BENCH_LOD_H
#define INSTESS_BENCH_LOD_H

enum { BENCH_LOD_MAX_MODES = 8 };

typedef struct bench_lod_args {
    int frames, warmup, threads;
    unsigned patches;   /* bit 0: npatch, bit 1: smooth */
    int n_modes;        /* 0: the default modes (uniform, screen 8, 4, 3 and 2 px per segment, deviation 0.3 px) */
    float modes[BENCH_LOD_MAX_MODES];   /* 0: uniform level 16; > 0: TESS_LOD_SCREEN at that many pixels per
                                           segment; < 0: TESS_LOD_DEVIATION allowing -value pixels */
    const char *keep;   /* a directory for each mode's last frame as a PPM, or NULL */
} bench_lod_args;

/* "uniform,8,4,2,d0.3" (uniform or u; pixels per segment in (0, 1000]; d and a deviation in pixels, (0, 1000])
 * into a->modes; 0, or -1 when malformed. */
int bench_lod_parse_modes(bench_lod_args *a, const char *list);

/* Measure and print scene D; 0, or 1 when a case failed (with a message on stderr). */
int bench_scene_d(const bench_lod_args *a);

#endif
