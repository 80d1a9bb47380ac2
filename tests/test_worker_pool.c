/* The worker pool's helpers (common/worker_pool.h): every index of every job run once, whether
 * the helpers sleep between jobs or spin for the next; a job posted while they sleep says it
 * woke them, one posted while they spin does not; and a pool whose helpers spin is freed
 * without waiting out the spin. The usable CPUs follow the thread's affinity. */
#define _GNU_SOURCE /* sched_setaffinity */
#include <sched.h>
#include <stdatomic.h>
#include <time.h>

#include "harness.h"
#include "worker_pool.h"

#define N_IDX 64

typedef struct {
    atomic_int runs[N_IDX];
} job;

static void count(void *ctx, size_t i, int worker)
{
    (void)worker;
    atomic_fetch_add(&((job *)ctx)->runs[i], 1);
}

/* jobs jobs back to back through c5_pool_start and c5_pool_wait; the count of those after
 * the first that had to wake a helper, or -1 where an index did not run exactly once. */
static int back_to_back(c5_pool *p, int jobs)
{
    int woke = 0;
    for (int k = 0; k < jobs; k++) {
        job j;
        for (int i = 0; i < N_IDX; i++)
            atomic_init(&j.runs[i], 0);
        int w = c5_pool_start(p, N_IDX, 1, count, &j);
        woke += k > 0 && w;
        c5_pool_wait(p);
        for (int i = 0; i < N_IDX; i++)
            if (atomic_load(&j.runs[i]) != 1)
                return -1;
    }
    return woke;
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

TEST(worker_pool_sleeping_helpers_are_woken_at_every_job)
{
    /* without a spin a helper sleeps as it ends a job, before c5_pool_wait can return */
    c5_pool *p = c5_pool_new(3);
    CHECK(p != NULL);
    CHECK_INT(c5_pool_threads(p), 3);
    CHECK_INT(back_to_back(p, 50), 49);
    c5_pool_free(p);
}

TEST(worker_pool_spinning_helpers_need_no_wake)
{
    /* a spin far longer than the gap between two jobs: every helper is still spinning when
     * the next is posted */
    c5_pool *p = c5_pool_new(3);
    CHECK(p != NULL);
    c5_pool_set_spin(p, 30L * 1000000000L);
    CHECK_INT(back_to_back(p, 50), 0);
    /* c5_pool_run takes part itself: the same indices with the helpers spinning */
    job j;
    for (int i = 0; i < N_IDX; i++)
        atomic_init(&j.runs[i], 0);
    c5_pool_run(p, N_IDX, 3, count, &j);
    for (int i = 0; i < N_IDX; i++)
        CHECK_INT(atomic_load(&j.runs[i]), 1);
    /* freed at once: the helpers leave their spin (a 30 s spin waited out would take 30 s) */
    double t0 = now_s();
    c5_pool_free(p);
    CHECK_MSG(now_s() - t0 < 20, "c5_pool_free took %.1f s with spinning helpers", now_s() - t0);
}

TEST(worker_pool_spin_ends_in_sleep)
{
    /* a spin of 1 us: the helpers are asleep again long before the next job, 0.2 s later */
    c5_pool *p = c5_pool_new(2);
    CHECK(p != NULL);
    c5_pool_set_spin(p, 1000);
    job j;
    for (int i = 0; i < N_IDX; i++)
        atomic_init(&j.runs[i], 0);
    c5_pool_start(p, N_IDX, 1, count, &j);
    c5_pool_wait(p);
    struct timespec pause = {0, 200 * 1000000L};
    nanosleep(&pause, NULL);
    for (int i = 0; i < N_IDX; i++)
        atomic_init(&j.runs[i], 0);
    CHECK_INT(c5_pool_start(p, N_IDX, 1, count, &j), 1);
    c5_pool_wait(p);
    for (int i = 0; i < N_IDX; i++)
        CHECK_INT(atomic_load(&j.runs[i]), 1);
    c5_pool_free(p);
}

TEST(cpus_usable_follows_the_affinity_mask)
{
    cpu_set_t all, one;
    CHECK(sched_getaffinity(0, sizeof all, &all) == 0);
    CHECK_INT(c5_cpus_usable(), CPU_COUNT(&all));
    int first = 0;
    while (!CPU_ISSET(first, &all))
        first++;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    CHECK(sched_setaffinity(0, sizeof one, &one) == 0);
    int usable = c5_cpus_usable();
    CHECK(sched_setaffinity(0, sizeof all, &all) == 0);
    CHECK_INT(usable, 1); /* as under taskset -c 0, whatever the machine's count */
}
