/* The host's helper threads for one board's frame (c5_board_opts.threads; docs/board-model.md,
 * "Host threads").
 *
 * Each cell's visit hands them its items: the rays that waited in the cell's SDRAM queue when
 * the cell was loaded (and the frame's set-up, the pixels' eye rays). The board's thread
 * goes through them in the board's order, the sorter's. The helpers run the items ahead of
 * it, each on a recording copy of the processor into a log (proc/ray_log.h), and leave it
 * the items it is about to reach. When the board's thread pops an item a helper ran, it
 * replays the log: the same effects, in the same place of the board's order; an item no
 * helper has taken it runs itself. So the image, every counter and every cycle count are
 * the same for any number of threads; the helpers' counters are added to the processor's
 * at the end of the visit (sums). The board's thread, which also runs the sorter, the DSP
 * and the replays, runs more items itself the more the helpers fall behind, and a helper
 * with nothing left ahead takes the items the board's thread has not reached yet, so neither
 * side waits for the other but for an item in hand.
 *
 * An item is the ray's position in the cell's SDRAM queue when the cell was loaded: the
 * queue is moved into the sorter in order (refill), so the k-th ray moved is item k, and the
 * item goes with the ray's sorter slot until it is popped. Rays queued during the visit are
 * not items: the board's thread runs them. */
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "board_internal.h"
#include "ray_log.h"
#include "worker_pool.h"

enum { TODO, MINE, CLAIMED, DONE, FAILED }; /* an item: to run, the board's, a helper's, logged, not logged */
/* Fewer items than this: the board's thread alone (waking the helpers costs more). */
#define MIN_ITEMS 256
/* How long a helper spins after a visit, watching for the next, before it sleeps: waking a
 * sleeping helper took some 50 us a visit on the 2-vCPU VM (a frame of brain_mirrors at 1/27
 * has 112 visits with helpers), and the next visit began 40 us later on average
 * (docs/board-model.md, "Host threads"). */
#define SPIN_NS 250000L
#define CHUNK_BYTES ((size_t)1 << 18)

/* A chunk is free again when every log written into it has been replayed: two counts that
 * only grow, each written by one thread on a line of its own, so that a log costs no
 * read-modify-write of a line both cores write. */
typedef struct chunk {
    struct chunk *next;
    size_t used, cap;
    size_t logs;                          /* the helper's: logs written into it */
    _Alignas(64) _Atomic size_t replayed; /* the board's thread's: logs of it replayed */
    _Alignas(64) uint64_t data[];
} chunk;

typedef struct {
    _Atomic uint32_t state;
    const void *log; /* DONE: the helper's log, in chunk c */
    chunk *c;
} item;

typedef struct {
    c5_proc w;       /* the recording copy of the board's processor, made at each visit's start */
    c5_ray_rec rec;
    chunk *chunks, *cur; /* the visit's logs, in chunks that never move */
} helper;

struct c5_bd_threads {
    c5_pool *pool;       /* the board's thread and the helpers (worker k > 0 is helper k - 1) */
    int n_helpers;
    int replay_all;      /* the board's thread takes no item: opts.threads_replay_all */
    helper *h;
    pthread_mutex_t mu;  /* with ran: the board's thread sleeping on an item */
    pthread_cond_t ran;
    atomic_long waiting; /* the item the board's thread sleeps on until it is run, -1: none */
    /* The visit: what the helpers only read */
    size_t n;
    item *it;
    size_t cap;
    uint8_t (*pk)[C5_PACKET_BYTES]; /* the rays' packets and instrument nodes */
    uint32_t *shadow;
    size_t cap_pk;
    int eye;             /* the items are the pixels' eye rays (c5_bd_threads_eye_rays) */
    c5_camera_basis basis;
    int64_t eye_o[3];
    c5_bray proto;
    const c5_cells *cells;
    /* What is written as the visit goes, each on lines of its own (the struct is 64-aligned) */
    _Alignas(64) atomic_long next; /* the helpers' next item, unless the board's thread is near it */
    _Alignas(64) _Atomic size_t mark; /* where the board's thread is: the items refilled */
    size_t refilled;     /* rays moved into the sorter so far: item refilled if < n */
};

/* Room for a log of `bytes` in the helper's chunks: the current one, else a free one (every
 * log in it replayed), else a new one. The chunk is counted as holding one more log. */
static void *log_room(helper *h, size_t bytes, chunk **in)
{
    size_t words = (bytes + 7) / 8;
    chunk *c = h->cur;
    if (!c || c->used + words > c->cap) {
        for (c = h->chunks; c; c = c->next)
            if (c != h->cur && c->cap >= words && atomic_load_explicit(&c->replayed, memory_order_acquire) == c->logs)
                break;
        if (!c) {
            size_t cap = words > CHUNK_BYTES / 8 ? (words + 7) / 8 * 8 : CHUNK_BYTES / 8;
            if (!(c = aligned_alloc(64, sizeof *c + cap * 8))) /* sizeof *c and cap * 8: multiples of 64 */
                return NULL;
            c->cap = cap;
            c->logs = 0;
            atomic_init(&c->replayed, 0);
            c->next = h->chunks;
            h->chunks = c;
        }
        c->used = 0;
        h->cur = c;
    }
    void *p = c->data + c->used;
    c->used += words;
    c->logs++;
    *in = c;
    return p;
}

/* Item j is run: wakes the board's thread if it sleeps on it. */
static void wake(struct c5_bd_threads *t, size_t j)
{
    if (atomic_load(&t->waiting) != (long)j)
        return;
    pthread_mutex_lock(&t->mu);
    pthread_cond_signal(&t->ran);
    pthread_mutex_unlock(&t->mu);
}

/* Item j on the helper's recording processor, into a log. */
static void run_item(struct c5_bd_threads *t, helper *h, size_t j)
{
    item *x = &t->it[j];
    c5_proc_stats before = h->w.st;
    c5_rlog_begin(&h->rec);
    if (t->eye) {
        c5_bd_eye_ray(&h->w, &t->basis, t->eye_o, &t->proto, (int)(j % (size_t)t->basis.w), (int)(j / (size_t)t->basis.w));
    } else {
        c5_bray r;
        c5_bray_unpack(t->pk[j], t->cells, &r);
        r.shadow = t->shadow[j];
        c5_proc_run(&h->w, &r);
    }
    void *log = h->rec.oom ? NULL : log_room(h, c5_rlog_size(&h->rec), &x->c);
    if (!log) { /* out of memory: the board's thread runs it, the counters as if not run */
        h->w.st = before;
        atomic_store(&x->state, FAILED);
        wake(t, j);
        return;
    }
    c5_rlog_write(&h->rec, log);
    x->log = log;
    atomic_store(&x->state, DONE);
    wake(t, j);
}

/* Items the helpers leave to the board's thread ahead of where it is (beyond the rays in the
 * sorter, which it may pop in any order): what it is about to take is not worth waiting for.
 * And how far ahead of it they run at most: the logs between stay in a few chunks, which are
 * used again, and in the caches. */
#define LEAD 32
#define AHEAD 4096

/* Item k taken for a helper, if no one has it yet. */
static int claim(struct c5_bd_threads *t, long k)
{
    uint32_t s = TODO;
    return atomic_compare_exchange_strong_explicit(&t->it[k].state, &s, CLAIMED, memory_order_acq_rel,
                                                   memory_order_acquire);
}

/* The helper's share of a visit: the next item not taken, LEAD to AHEAD beyond the board's
 * thread, until none is left; then any the board's thread has not reached. */
static void run_visit(struct c5_bd_threads *t, helper *h)
{
    h->cur = NULL;
    long j, cur = atomic_load_explicit(&t->next, memory_order_relaxed);
    for (;;) {
        long mark = (long)atomic_load_explicit(&t->mark, memory_order_relaxed), lo = t->replay_all ? 0 : mark + LEAD;
        j = cur > lo ? cur : lo;
        if (j >= (long)t->n)
            break;
        if (j > mark + AHEAD) {
            sched_yield();
            cur = atomic_load_explicit(&t->next, memory_order_relaxed);
            continue;
        }
        if (!atomic_compare_exchange_weak_explicit(&t->next, &cur, j + 1, memory_order_relaxed, memory_order_relaxed))
            continue; /* another helper moved it: cur is where it is now */
        cur = j + 1;
        if (claim(t, j))
            run_item(t, h, (size_t)j);
    }
    /* None is left beyond LEAD of the board's thread, which reaches the rest in the sorter's
     * order, whatever their place: the helper takes those not yet taken, from the last one
     * down, rather than sit idle while the board's thread runs the visit's end alone. */
    for (long k = (long)t->n - 1; k >= 0; k--)
        if (atomic_load_explicit(&t->it[k].state, memory_order_relaxed) == TODO && claim(t, k))
            run_item(t, h, (size_t)k);
}

/* The pool's job at a visit: each helper's share. */
static void visit_job(void *ctx, size_t i, int worker)
{
    struct c5_bd_threads *t = ctx;
    (void)i;
    run_visit(t, &t->h[worker - 1]);
}

int c5_bd_threads_init(c5_bd *b, int threads)
{
    if (threads < 2)
        return 0;
    struct c5_bd_threads *t = aligned_alloc(64, sizeof *t); /* sizeof: a multiple of its alignment */
    if (t)
        memset(t, 0, sizeof *t);
    if (!t || !(t->h = calloc((size_t)threads - 1, sizeof *t->h)) || !(t->pool = c5_pool_new(threads)) ||
        !(b->slot_item = malloc((size_t)b->o->queue_capacity * sizeof *b->slot_item))) {
        if (t) {
            c5_pool_free(t->pool);
            free(t->h);
        }
        free(t);
        return -1;
    }
    pthread_mutex_init(&t->mu, NULL);
    pthread_cond_init(&t->ran, NULL);
    atomic_init(&t->waiting, -1);
    t->n_helpers = c5_pool_threads(t->pool) - 1; /* fewer if the system refused threads */
    /* not with more threads than CPUs to run on, where a spinning helper holds a CPU another
     * needs */
    if (c5_pool_threads(t->pool) <= c5_cpus_usable())
        c5_pool_set_spin(t->pool, SPIN_NS);
    t->cells = &b->cells;
    t->replay_all = b->o->threads_replay_all;
    b->threads = t;
    return 0;
}

void c5_bd_threads_free(c5_bd *b)
{
    struct c5_bd_threads *t = b->threads;
    free(b->slot_item);
    b->slot_item = NULL;
    if (!t)
        return;
    c5_pool_free(t->pool);
    for (int k = 0; k < t->n_helpers; k++) {
        c5_rlog_free(&t->h[k].rec);
        for (chunk *c = t->h[k].chunks, *n; c; c = n)
            n = c->next, free(c);
    }
    pthread_cond_destroy(&t->ran);
    pthread_mutex_destroy(&t->mu);
    free(t->it);
    free(t->pk);
    free(t->shadow);
    free(t->h);
    free(t);
    b->threads = NULL;
}

/* Room for n items and their packets: 0, or -1 (the visit runs without helpers). */
static int reserve(struct c5_bd_threads *t, size_t n)
{
    if (n > t->cap) {
        item *it = realloc(t->it, n * sizeof *it);
        if (!it)
            return -1;
        t->it = it;
        t->cap = n;
    }
    if (n > t->cap_pk) {
        if (c5_bd_grow_packets(&t->pk, &t->shadow, n))
            return -1;
        t->cap_pk = n;
    }
    return 0;
}

/* The helpers start on the visit's n items, each with a recording copy of the processor. */
static void start(c5_bd *b, size_t n)
{
    struct c5_bd_threads *t = b->threads;
    for (size_t i = 0; i < n; i++)
        atomic_init(&t->it[i].state, TODO);
    t->n = n;
    atomic_store_explicit(&t->next, 0, memory_order_relaxed);
    atomic_store_explicit(&t->mark, 0, memory_order_relaxed);
    for (int k = 0; k < t->n_helpers; k++)
        c5_rlog_recorder(&t->h[k].w, &b->proc, &t->h[k].rec);
    b->st->helper_wakes += (uint64_t)c5_pool_start(t->pool, (size_t)t->n_helpers, 1, visit_job, t);
}

/* After the board's thread has taken every item: waits for the helpers, adds their counters. */
static void finish(c5_bd *b)
{
    struct c5_bd_threads *t = b->threads;
    c5_pool_wait(t->pool);
    _Static_assert(sizeof(c5_proc_stats) % sizeof(uint64_t) == 0, "c5_proc_stats: uint64_t counters only");
    uint64_t *dst = (uint64_t *)&b->proc.st;
    for (int k = 0; k < t->n_helpers; k++) {
        const uint64_t *src = (const uint64_t *)&t->h[k].w.st;
        for (size_t i = 0; i < sizeof(c5_proc_stats) / sizeof(uint64_t); i++)
            dst[i] += src[i];
    }
    t->n = 0;
}

/* Whether the board's thread waits for an item in state s: a helper runs it, or (replay_all)
 * will. */
static int waits(const struct c5_bd_threads *t, uint32_t s) { return s == CLAIMED || (s == TODO && t->replay_all); }

/* Item i reached in the board's order: 1 if a helper ran it and its log is replayed, 0 if the
 * board's thread is to run it. */
int c5_bd_threads_take(c5_bd *b, size_t i)
{
    struct c5_bd_threads *t = b->threads;
    item *x = &t->it[i];
    uint32_t s = TODO;
    if (!t->replay_all &&
        atomic_compare_exchange_strong_explicit(&x->state, &s, MINE, memory_order_acq_rel, memory_order_acquire))
        return 0;
    /* A helper runs it (or will: replay_all): a run takes microseconds, but the helper may
     * have lost its core, to this thread among others, so after a short spin the thread
     * sleeps until it is run. */
    for (int spin = 0; spin < 2000 && waits(t, s = atomic_load_explicit(&x->state, memory_order_acquire)); spin++)
        c5_cpu_relax();
    if (waits(t, s)) {
        atomic_store(&t->waiting, (long)i);
        pthread_mutex_lock(&t->mu);
        while (waits(t, s = atomic_load(&x->state)))
            pthread_cond_wait(&t->ran, &t->mu);
        pthread_mutex_unlock(&t->mu);
        atomic_store(&t->waiting, -1);
    }
    if (s != DONE)
        return 0;
    c5_rlog_replay(&b->proc, x->log);
    /* the board's thread is the only writer: a plain store, released after the log's reads */
    atomic_store_explicit(&x->c->replayed, atomic_load_explicit(&x->c->replayed, memory_order_relaxed) + 1,
                          memory_order_release);
    b->st->helper_runs++;
    return 1;
}

void c5_bd_threads_cell_begin(c5_bd *b, int cell)
{
    struct c5_bd_threads *t = b->threads;
    const c5_sdram_queue *q = &b->q[cell];
    size_t n = q->n - q->head;
    t->refilled = 0;
    t->n = 0;
    if (t->n_helpers == 0 || n < MIN_ITEMS || reserve(t, n) != 0)
        return;
    memcpy(t->pk, q->pk + q->head, n * C5_PACKET_BYTES);
    memcpy(t->shadow, q->shadow + q->head, n * sizeof *t->shadow);
    t->eye = 0;
    start(b, n);
}

uint32_t c5_bd_threads_refill_item(c5_bd *b)
{
    struct c5_bd_threads *t = b->threads;
    return t->refilled < t->n ? (uint32_t)t->refilled : C5_BD_NO_ITEM;
}

void c5_bd_threads_refilled(c5_bd *b)
{
    struct c5_bd_threads *t = b->threads;
    if (t->refilled >= t->n) /* not an item (a ray queued during the visit), or no items */
        return;
    item *x = &t->it[t->refilled];
    atomic_store_explicit(&t->mark, ++t->refilled, memory_order_relaxed);
    /* It is popped some hundred pops later: its log is fetched from the helper's core by then. */
    if (atomic_load_explicit(&x->state, memory_order_acquire) == DONE) {
        const char *log = x->log;
        for (int line = 0; line < 4; line++)
            __builtin_prefetch(log + 64 * line);
    }
}


void c5_bd_threads_cell_end(c5_bd *b)
{
    if (b->threads->n)
        finish(b);
}

int c5_bd_threads_eye_rays(c5_bd *b, const c5_camera_basis *basis, const int64_t O[3], const c5_bray *proto)
{
    struct c5_bd_threads *t = b->threads;
    size_t n = (size_t)basis->w * (size_t)basis->h;
    if (t->n_helpers == 0 || n < MIN_ITEMS || reserve(t, n) != 0)
        return 0;
    t->eye = 1;
    t->basis = *basis;
    memcpy(t->eye_o, O, sizeof t->eye_o);
    t->proto = *proto;
    start(b, n);
    for (size_t i = 0; i < n; i++) {
        atomic_store_explicit(&t->mark, i, memory_order_relaxed);
        if (!c5_bd_threads_take(b, i))
            c5_bd_eye_ray(&b->proc, basis, O, proto, (int)(i % (size_t)basis->w), (int)(i / (size_t)basis->w));
    }
    finish(b);
    return 1;
}
