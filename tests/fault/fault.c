/* tests/fault/fault.c -- allocation failure on demand, for the fault-injection build of the program
 * (build-asan/tests/instess-faults, `make faults`; tests/faults.sh drives it).  Linked with
 * -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc,--wrap=aligned_alloc,--wrap=strdup, so that every call the
 * library's and the program's own objects make to these goes through the wrappers below (the shared libraries
 * they use -- libc, libstdc++, OpenImageIO, assimp -- keep their own allocator: their failures are theirs).
 *
 * INSTESS_FAULT_AT=N makes the N-th of those calls (counting from 1, in this process; a forked child goes on
 * counting from where its parent was) return NULL, once, as SQLite's transient malloc test does; unset or 0, no
 * call fails.  INSTESS_FAULT_REPORT=FILE: at exit the process that started the program writes "CALLS FIRED"
 * there (the number of calls it made, and 1 if the N-th failed), so that the driver knows when N has passed the
 * last allocation; any process whose N-th call failed creates FILE.fired (see note_fired).  Test code only: the library and the program never contain it (the one mutable global here
 * is the counter the wrappers share). */
#define _GNU_SOURCE
#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <unistd.h>

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t size);
void *__real_realloc(void *p, size_t n);
void *__real_aligned_alloc(size_t align, size_t n);
char *__real_strdup(const char *s);
void *__wrap_malloc(size_t n);
void *__wrap_calloc(size_t n, size_t size);
void *__wrap_realloc(void *p, size_t n);
void *__wrap_aligned_alloc(size_t align, size_t n);
char *__wrap_strdup(const char *s);

static atomic_ulong calls;       /* allocations so far */
static unsigned long fail_at;    /* INSTESS_FAULT_AT */
static atomic_int fired;         /* the fault happened */
static pid_t main_pid;

/* Read the environment once, before main. */
__attribute__((constructor)) static void fault_init(void)
{
    const char *s = getenv("INSTESS_FAULT_AT");
    fail_at = s ? strtoul(s, NULL, 10) : 0;
    main_pid = getpid();
}

/* Write the report (the first process only: a forked child that exits normally must not overwrite it). */
__attribute__((destructor)) static void fault_report(void)
{
    const char *path = getenv("INSTESS_FAULT_REPORT");
    if (!path || getpid() != main_pid) return;
    FILE *f = fopen(path, "w");
    if (!f) return;
    fprintf(f, "%lu %d\n", (unsigned long)atomic_load(&calls), atomic_load(&fired));
    fclose(f);
}

/* The sanitizers' stack printer (in the sanitizer build; weak: absent elsewhere). */
void __sanitizer_print_stack_trace(void) __attribute__((weak));

/* Note that the fault fired, in whichever process (a forked import child's is not in the report): the file
 * INSTESS_FAULT_REPORT.fired is created; with INSTESS_FAULT_TRACE set, the stack of the failing call goes to
 * stderr (tests/faults.sh prints it for a run that went wrong). */
static void note_fired(void)
{
    atomic_store(&fired, 1);
    const char *path = getenv("INSTESS_FAULT_REPORT");
    if (path) {
        char name[4096];
        snprintf(name, sizeof name, "%s.fired", path);
        int fd = open(name, O_WRONLY | O_CREAT | O_CLOEXEC, 0600);
        if (fd >= 0) close(fd);
    }
    if (getenv("INSTESS_FAULT_TRACE") && __sanitizer_print_stack_trace) {
        static const char msg[] = "fault: this allocation fails:\n";
        if (write(2, msg, sizeof msg - 1) < 0) return;
        __sanitizer_print_stack_trace();
    }
}

/* Whether this call is the one to fail. */
static int fail_now(void)
{
    unsigned long k = atomic_fetch_add(&calls, 1) + 1;
    if (fail_at && k == fail_at) {
        note_fired();
        return 1;
    }
    return 0;
}

void *__wrap_malloc(size_t n) { return fail_now() ? NULL : __real_malloc(n); }
void *__wrap_calloc(size_t n, size_t size) { return fail_now() ? NULL : __real_calloc(n, size); }
void *__wrap_realloc(void *p, size_t n) { return fail_now() ? NULL : __real_realloc(p, n); }
void *__wrap_aligned_alloc(size_t align, size_t n) { return fail_now() ? NULL : __real_aligned_alloc(align, n); }
char *__wrap_strdup(const char *s) { return fail_now() ? NULL : __real_strdup(s); }
