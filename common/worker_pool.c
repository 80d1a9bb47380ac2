/* A fixed set of host threads that run one indexed job at a time (worker_pool.h). */
#define _GNU_SOURCE /* sched_getaffinity */
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "worker_pool.h"

struct c5_pool {
    int threads;                /* workers, the caller included */
    pthread_t *th;
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    unsigned long job;          /* incremented for every job; a helper runs each once */
    atomic_ulong posted;        /* job, for the helpers that spin (read without mu) */
    long spin_ns;               /* how long a helper spins for the next job before it sleeps */
    int sleeping;               /* helpers in pthread_cond_wait on go */
    int busy;                   /* helpers still in the current job */
    int quit;
    size_t n, chunk;
    atomic_size_t next;         /* the next index handed out */
    void (*fn)(void *ctx, size_t i, int worker);
    void *ctx;
};

typedef struct {
    c5_pool *p;
    int worker;
} helper_arg;

static void take_share(c5_pool *p, int worker)
{
    for (;;) {
        size_t i0 = atomic_fetch_add(&p->next, p->chunk);
        if (i0 >= p->n)
            return;
        size_t i1 = i0 + p->chunk < p->n ? i0 + p->chunk : p->n;
        for (size_t i = i0; i < i1; i++)
            p->fn(p->ctx, i, worker);
    }
}

static long now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (long)t.tv_sec * 1000000000L + t.tv_nsec;
}

/* Until a job after `seen` is posted, or for ns at most (the clock read every 64 pauses). */
static void spin_for_job(c5_pool *p, unsigned long seen, long ns)
{
    long until = now_ns() + ns;
    for (;;) {
        for (int k = 0; k < 64; k++) {
            if (atomic_load_explicit(&p->posted, memory_order_relaxed) != seen)
                return;
            c5_cpu_relax();
        }
        if (now_ns() >= until)
            return;
    }
}

static void *helper(void *arg)
{
    helper_arg *h = arg;
    c5_pool *p = h->p;
    int worker = h->worker;
    free(h);
    unsigned long seen = 0;
    pthread_mutex_lock(&p->mu);
    for (;;) {
        if (p->spin_ns > 0 && !p->quit && p->job == seen) {
            long ns = p->spin_ns;
            pthread_mutex_unlock(&p->mu);
            spin_for_job(p, seen, ns);
            pthread_mutex_lock(&p->mu);
        }
        while (!p->quit && p->job == seen) {
            p->sleeping++;
            pthread_cond_wait(&p->go, &p->mu);
            p->sleeping--;
        }
        if (p->quit)
            break;
        seen = p->job;
        pthread_mutex_unlock(&p->mu);
        take_share(p, worker);
        pthread_mutex_lock(&p->mu);
        if (--p->busy == 0)
            pthread_cond_signal(&p->done);
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

c5_pool *c5_pool_new(int threads)
{
    c5_pool *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->threads = 1;
    atomic_init(&p->posted, 0);
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->go, NULL);
    pthread_cond_init(&p->done, NULL);
    if (threads > 1 && (p->th = calloc((size_t)threads - 1, sizeof *p->th)) != NULL)
        for (int w = 1; w < threads; w++) {
            helper_arg *h = malloc(sizeof *h);
            if (!h)
                break;
            *h = (helper_arg){p, w};
            if (pthread_create(&p->th[w - 1], NULL, helper, h) != 0) {
                free(h);
                break;
            }
            p->threads = w + 1;
        }
    return p;
}

void c5_pool_free(c5_pool *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->mu);
    p->quit = 1;
    atomic_store_explicit(&p->posted, p->job + 1, memory_order_relaxed); /* ends a spin */
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    for (int w = 1; w < p->threads; w++)
        pthread_join(p->th[w - 1], NULL);
    pthread_cond_destroy(&p->go);
    pthread_cond_destroy(&p->done);
    pthread_mutex_destroy(&p->mu);
    free(p->th);
    free(p);
}

int c5_pool_threads(const c5_pool *p) { return p ? p->threads : 1; }

void c5_pool_set_spin(c5_pool *p, long ns)
{
    pthread_mutex_lock(&p->mu);
    p->spin_ns = ns > 0 ? ns : 0;
    pthread_mutex_unlock(&p->mu);
}

int c5_pool_start(c5_pool *p, size_t n, size_t chunk, void (*fn)(void *ctx, size_t i, int worker), void *ctx)
{
    pthread_mutex_lock(&p->mu);
    p->n = n;
    p->chunk = chunk < 1 ? 1 : chunk;
    p->fn = fn;
    p->ctx = ctx;
    atomic_store(&p->next, 0);
    p->busy = p->threads - 1;
    p->job++;
    atomic_store_explicit(&p->posted, p->job, memory_order_relaxed);
    int woke = p->sleeping > 0;
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    return woke;
}

void c5_pool_wait(c5_pool *p)
{
    pthread_mutex_lock(&p->mu);
    while (p->busy > 0)
        pthread_cond_wait(&p->done, &p->mu);
    pthread_mutex_unlock(&p->mu);
}

void c5_pool_run(c5_pool *p, size_t n, size_t chunk, void (*fn)(void *ctx, size_t i, int worker), void *ctx)
{
    if (n == 0)
        return;
    if (chunk < 1)
        chunk = 1;
    if (!p || p->threads == 1 || n <= chunk) {
        for (size_t i = 0; i < n; i++)
            fn(ctx, i, 0);
        return;
    }
    (void)c5_pool_start(p, n, chunk, fn, ctx);
    take_share(p, 0);
    c5_pool_wait(p);
}

int c5_cpus_usable(void)
{
    cpu_set_t set;
    long n = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > 256 ? 256 : (int)n;
}

/* C5_THREADS as a count 1..256, or 0 when unset, -1 when not such a count. */
static long env_threads(void)
{
    const char *e = getenv("C5_THREADS");
    if (!e)
        return 0;
    char *end;
    long n = strtol(e, &end, 10);
    return *e && !*end && n >= 1 && n <= 256 ? n : -1;
}

int c5_pool_threads_env(c5_err *err)
{
    if (env_threads() < 0)
        return c5_fail(err, "C5_THREADS: expected a thread count 1..256, got '%.40s'", getenv("C5_THREADS"));
    return 0;
}

int c5_pool_cpus(void)
{
    long n = env_threads();
    return n >= 1 ? (int)n : c5_cpus_usable();
}
