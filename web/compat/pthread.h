/* web/compat/pthread.h -- the types cli/run/scene.h names (scene_progress, the progress line of a long run
 * on a terminal) for the browser build with wasi-libc, which has no threads.  The page compiles scene.c and
 * never starts a progress line (cli/run/progress.c is not part of it), so no function is declared here. */
#ifndef INSTESS_WEB_PTHREAD_H
#define INSTESS_WEB_PTHREAD_H

typedef unsigned long pthread_t;
typedef struct { int unused; } pthread_mutex_t;
typedef struct { int unused; } pthread_cond_t;

#endif
