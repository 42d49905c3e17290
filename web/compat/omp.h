/* web/compat/omp.h -- OpenMP's run-time functions for the browser build (make web), which compiles without
 * -fopenmp: one thread.  A page's WebAssembly runs on one thread unless the page is served with the
 * cross-origin isolation headers that SharedArrayBuffer needs, which a file opened from the disk never has; the
 * `#pragma omp` lines are then ignored and every parallel loop runs its iterations in order on the caller's
 * thread (the same bytes: images do not depend on the thread count).  omp_get_wtime reads the monotonic clock
 * (the page's performance.now through WASI's clock_time_get). */
#ifndef INSTESS_WEB_OMP_H
#define INSTESS_WEB_OMP_H

#include <time.h>

static inline int omp_get_num_procs(void) { return 1; }
static inline int omp_get_max_threads(void) { return 1; }
static inline int omp_get_num_threads(void) { return 1; }
static inline int omp_get_thread_num(void) { return 0; }
static inline double omp_get_wtime(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

#endif
