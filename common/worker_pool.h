/* A fixed set of host threads that run one indexed job at a time: c5_pool_run calls
 * fn(ctx, i, worker) once for every i in [0, n), the calling thread taking part as worker 0,
 * and returns when every call has returned. Which worker runs which i is not fixed: a job
 * whose results depend on it is not deterministic, so callers write each i's result into
 * its own place. Made once for a pass and reused for its jobs, so that a short job does not
 * pay for creating threads. */
#ifndef C5_WORKER_POOL_H
#define C5_WORKER_POOL_H

#include <stddef.h>

#include "err.h"

typedef struct c5_pool c5_pool;

/* A pool of `threads` workers (the caller and threads - 1 started here; fewer if the system
 * refuses more: the results are the same, only slower). NULL: out of memory. */
c5_pool *c5_pool_new(int threads);
void c5_pool_free(c5_pool *p);
/* The workers it has, the caller included (>= 1). */
int c5_pool_threads(const c5_pool *p);
/* fn for every i in [0, n), handed out `chunk` consecutive indices at a time. */
void c5_pool_run(c5_pool *p, size_t n, size_t chunk, void (*fn)(void *ctx, size_t i, int worker), void *ctx);
/* The same job on the workers other than the caller (a pool of at least 2), which goes on
 * with its own work: c5_pool_start returns at once (1 if it had to wake a helper that slept,
 * 0 if they were all spinning or busy: see c5_pool_set_spin), c5_pool_wait when every call
 * has returned. One job at a time. */
int c5_pool_start(c5_pool *p, size_t n, size_t chunk, void (*fn)(void *ctx, size_t i, int worker), void *ctx);
void c5_pool_wait(c5_pool *p);
/* After each job a helper spins for up to ns nanoseconds, watching for the next, before it
 * sleeps (0, the default: it sleeps at once). Waking a sleeping thread takes tens of
 * microseconds on a virtual machine; a caller that posts short jobs in quick succession
 * (c5_pool_start, c5_pool_wait, a little work of its own, again) spends that at every job
 * unless its helpers spin. Only for pools with no more threads than usable CPUs
 * (c5_cpus_usable): a spinning helper holds its CPU. */
void c5_pool_set_spin(c5_pool *p, long ns);
/* One wait of a spin loop (x86's pause: the core runs its other thread, and leaves the loop
 * without a misspeculated exit). */
static inline void c5_cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}
/* The CPUs the calling thread may run on (its affinity mask: taskset), else the online CPUs;
 * 1..256. */
int c5_cpus_usable(void);
/* The default thread count: C5_THREADS when set (1..256), else c5_cpus_usable(). */
int c5_pool_cpus(void);
/* C5_THREADS checked: 0, or -1 with "C5_THREADS: ..." when set but not a count 1..256. */
int c5_pool_threads_env(c5_err *err);

#endif
