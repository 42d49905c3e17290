/* bench/bench_lod.h -- scene D of the benchmark (bench/bench_lod.c): adaptive level of detail against one uniform
 * level, instess alone.  bench.c calls it for `--scenes D`. */
#ifndef INSTESS_BENCH_LOD_H
#define INSTESS_BENCH_LOD_H

typedef struct bench_lod_args {
    int frames, warmup, threads;
    unsigned patches;   /* bit 0: npatch, bit 1: smooth */
} bench_lod_args;

/* Measure and print scene D; 0, or 1 when a case failed (with a message on stderr). */
int bench_scene_d(const bench_lod_args *a);

#endif
