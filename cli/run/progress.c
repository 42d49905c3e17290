/* cli/run/progress.c -- the progress line of a long run (pbrt's habit): when stderr is a terminal and the work
 * has taken more than SCENE_PROGRESS_DELAY_MS, a thread redraws one line "instess: MESH: PHASE, 2.4 s" on
 * stderr every 0.2 s until the work ends, then erases it, so that the statistics and messages that follow
 * start on a clean line.  Nothing is drawn when stderr is not a terminal (a file, a pipe) or with -q. */
#include "scene.h"

#include <errno.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* Seconds on the monotonic clock. */
static double mono_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* The absolute CLOCK_MONOTONIC time t (seconds) as a timespec. */
static struct timespec abs_time(double t)
{
    struct timespec ts;
    ts.tv_sec = (time_t)t;
    ts.tv_nsec = (long)((t - (double)ts.tv_sec) * 1e9);
    if (ts.tv_nsec >= 1000000000L) ts.tv_sec++, ts.tv_nsec -= 1000000000L;
    return ts;
}

/* The drawing thread: waits for the delay, then redraws the line every 0.2 s until stopped; erases it. */
static void *progress_thread(void *arg)
{
    scene_progress *p = arg;
    pthread_mutex_lock(&p->mu);
    double next = p->t0 + SCENE_PROGRESS_DELAY_MS / 1000.0;
    while (!p->stop) {
        struct timespec ts = abs_time(next);
        int rc = pthread_cond_timedwait(&p->cv, &p->mu, &ts);
        if (p->stop) break;
        if (rc != ETIMEDOUT) continue;
        double now = mono_now();
        fprintf(stderr, "\rinstess: %s: %s, %.1f s\033[K", p->label, p->phase, now - p->t0);
        fflush(stderr);
        p->drawn = true;
        next = now + 0.2;
    }
    if (p->drawn) fputs("\r\033[K", stderr), fflush(stderr);
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

void scene_progress_start(scene_progress *p, const char *label, bool quiet)
{
    memset(p, 0, sizeof *p);
    p->label = label, p->phase = "starting", p->t0 = mono_now();
    if (quiet || !isatty(STDERR_FILENO)) return;
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->cv, &ca);
    pthread_condattr_destroy(&ca);
    p->active = pthread_create(&p->thread, NULL, progress_thread, p) == 0;
    if (!p->active) pthread_cond_destroy(&p->cv), pthread_mutex_destroy(&p->mu);
}

void scene_progress_phase(scene_progress *p, const char *phase)
{
    if (!p || !p->active) return;
    pthread_mutex_lock(&p->mu);
    p->phase = phase;
    pthread_mutex_unlock(&p->mu);
}

void scene_progress_stop(scene_progress *p)
{
    if (!p || !p->active) return;
    pthread_mutex_lock(&p->mu);
    p->stop = true;
    pthread_cond_signal(&p->cv);
    pthread_mutex_unlock(&p->mu);
    pthread_join(p->thread, NULL);
    pthread_cond_destroy(&p->cv);
    pthread_mutex_destroy(&p->mu);
    p->active = false;
}

void scene_progress_print(scene_progress *p, const char *text)
{
    if (!p || !p->active) {
        fputs(text, stderr);
        return;
    }
    pthread_mutex_lock(&p->mu);
    if (p->drawn) fputs("\r\033[K", stderr), p->drawn = false;
    fputs(text, stderr);
    fflush(stderr);
    pthread_mutex_unlock(&p->mu);
}
