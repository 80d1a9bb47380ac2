/* The loopback transport (mb_loopback.h): every collective publishes this board's part, waits
 * at a barrier for all boards, reads the others' parts, and waits again before the parts may
 * change. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mb_loopback.h"

/* A barrier that a failing board can break: every board waiting in it, and every board that
 * comes to it later, returns -1 instead of waiting for a board that will not come. */
typedef struct {
    pthread_mutex_t m;
    pthread_cond_t c;
    int size, count, broken, first_failed;
    unsigned gen;
} barrier;

static int barrier_wait(barrier *b)
{
    pthread_mutex_lock(&b->m);
    unsigned gen = b->gen;
    if (!b->broken && ++b->count == b->size) {
        b->count = 0;
        b->gen++;
        pthread_cond_broadcast(&b->c);
    }
    while (!b->broken && gen == b->gen)
        pthread_cond_wait(&b->c, &b->m);
    int rc = b->broken ? -1 : 0;
    pthread_mutex_unlock(&b->m);
    return rc;
}

static void barrier_break(barrier *b, int rank)
{
    pthread_mutex_lock(&b->m);
    if (!b->broken)
        b->first_failed = rank;
    b->broken = 1;
    pthread_cond_broadcast(&b->c);
    pthread_mutex_unlock(&b->m);
}

typedef struct {
    int size;
    barrier bar;
    const void *part[C5_MB_MAX_BOARDS];      /* what each board published */
    const uint16_t *dest[C5_MB_MAX_BOARDS];
    size_t n[C5_MB_MAX_BOARDS];
} loop;

#define WAIT(L, err) \
    if (barrier_wait(&(L)->bar) != 0) \
        return c5_fail(err, "another board failed");

typedef struct {
    loop *L;
    int rank;
    uint8_t (*in)[C5_PACKET_BYTES];
    size_t cap;
    /* the thread's job and result */
    const c5_scene *s;
    const c5_supervol *sv;
    int frame;
    c5_board_opts base;
    const c5_board_out *keep;
    c5_mb_opts mo;
    c5_image img;
    c5_mb_stats *ms;
    c5_err err;
    int rc;
    long fail_at;   /* C5_LOOPBACK_TEST_FAIL: the exchange at which this board reports an error, -1: never */
    long exchanges;
} board_thread;

static int alltoall(void *ctx, const uint8_t (*out)[C5_PACKET_BYTES], const uint16_t *dest, size_t n_out,
                    const uint8_t (**in)[C5_PACKET_BYTES], size_t *n_in, c5_err *err)
{
    board_thread *t = ctx;
    loop *L = t->L;
    if (t->exchanges++ == t->fail_at) /* the error path, for the tests */
        return c5_fail(err, "a failure on purpose at exchange %ld (C5_LOOPBACK_TEST_FAIL)", t->fail_at);
    L->part[t->rank] = out;
    L->dest[t->rank] = dest;
    L->n[t->rank] = n_out;
    WAIT(L, err);
    size_t n = 0;
    for (int s = 0; s < L->size; s++) {
        const uint8_t (*pk)[C5_PACKET_BYTES] = L->part[s];
        for (size_t i = 0; i < L->n[s]; i++) {
            if (L->dest[s][i] != t->rank)
                continue;
            if (n == t->cap) {
                size_t cap = t->cap ? 2 * t->cap : 1024;
                void *p = realloc(t->in, cap * C5_PACKET_BYTES);
                if (!p)
                    return c5_fail(err, "loopback: out of memory");
                t->in = p;
                t->cap = cap;
            }
            memcpy(t->in[n++], pk[i], C5_PACKET_BYTES);
        }
    }
    WAIT(L, err);
    *in = (const uint8_t (*)[C5_PACKET_BYTES])t->in;
    *n_in = n;
    return 0;
}

static int allgather(void *ctx, const void *mine, size_t bytes, void *all, c5_err *err)
{
    board_thread *t = ctx;
    loop *L = t->L;
    L->part[t->rank] = mine;
    WAIT(L, err);
    for (int s = 0; s < L->size; s++)
        memcpy((char *)all + (size_t)s * bytes, L->part[s], bytes);
    WAIT(L, err);
    return 0;
}

static int sum_u64(void *ctx, uint64_t *v, size_t n, c5_err *err)
{
    board_thread *t = ctx;
    loop *L = t->L;
    uint64_t *tmp = calloc(n ? n : 1, sizeof *tmp);
    if (!tmp)
        return c5_fail(err, "loopback: out of memory");
    L->part[t->rank] = v;
    if (barrier_wait(&L->bar) != 0) {
        free(tmp);
        return c5_fail(err, "another board failed");
    }
    for (int s = 0; s < L->size; s++)
        for (size_t i = 0; i < n; i++)
            tmp[i] += ((const uint64_t *)L->part[s])[i];
    if (barrier_wait(&L->bar) != 0) {
        free(tmp);
        return c5_fail(err, "another board failed");
    }
    memcpy(v, tmp, n * sizeof *v);
    free(tmp);
    return 0;
}

static void *run(void *arg)
{
    board_thread *t = arg;
    c5_mb_transport tr = {t, t->rank, t->L->size, alltoall, allgather, sum_u64};
    t->rc = c5_mb_render(t->s, t->sv, t->frame, &t->base, t->keep, &t->mo, &tr, &t->img, t->ms, &t->err);
    if (t->rc != 0)
        barrier_break(&t->L->bar, t->rank);
    return NULL;
}

int c5_mb_render_loopback(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *base,
                          const c5_board_out *keep, const c5_mb_opts *mo, int boards, c5_mb_history *hist,
                          c5_image *out, c5_mb_stats *ms, c5_err *err)
{
    board_thread *t = calloc((size_t)(boards > 0 ? boards : 1), sizeof *t);
    c5_mb_stats *st = calloc((size_t)(boards > 0 ? boards : 1), sizeof *st);
    pthread_t *th = calloc((size_t)(boards > 0 ? boards : 1), sizeof *th);
    loop *L = calloc(1, sizeof *L);
    if (!t || !st || !th || !L || boards < 1 || boards > C5_MB_MAX_BOARDS) {
        free(t), free(st), free(th), free(L);
        return boards < 1 || boards > C5_MB_MAX_BOARDS
                   ? c5_fail(err, "boards: %d is outside 1..%d", boards, C5_MB_MAX_BOARDS)
                   : c5_fail(err, "out of memory for %d boards", boards);
    }
    L->size = boards;
    L->bar.size = boards;
    pthread_mutex_init(&L->bar.m, NULL);
    pthread_cond_init(&L->bar.c, NULL);
    const char *fail = getenv("C5_LOOPBACK_TEST_FAIL"); /* "BOARD:EXCHANGE" */
    int fail_board = -1;
    long fail_at = -1;
    if (!fail || sscanf(fail, "%d:%ld", &fail_board, &fail_at) != 2)
        fail_board = -1;
    for (int k = 0; k < boards; k++) {
        t[k] = (board_thread){.L = L, .rank = k, .s = s, .sv = sv, .frame = frame, .base = *base,
                              .keep = k ? NULL : keep, .mo = *mo, .ms = &st[k], .fail_at = k == fail_board ? fail_at : -1};
        t[k].mo.history = hist ? &hist[k] : NULL;
        if (k)
            t[k].base.progress = NULL;
    }
    int started = 0, rc = 0;
    for (; started < boards; started++)
        if (pthread_create(&th[started], NULL, run, &t[started]) != 0) {
            barrier_break(&L->bar, started); /* the boards started return from their next collective */
            rc = c5_fail(err, "could not start the thread of board %d of %d", started, boards);
            break;
        }
    for (int k = 0; k < started; k++)
        pthread_join(th[k], NULL);
    if (rc == 0 && L->bar.broken) {
        int k = L->bar.first_failed;
        rc = c5_fail(err, "board %d: %s", k, t[k].err.msg);
    }
    for (int k = 1; rc == 0 && k < boards; k++)
        if (memcmp(t[k].img.rgb, t[0].img.rgb, sizeof(float) * 3 * (size_t)t[0].img.w * t[0].img.h) ||
            st[k].frame_cycles != st[0].frame_cycles || st[k].rounds != st[0].rounds ||
            st[k].exchanges != st[0].exchanges)
            rc = c5_fail(err, "loopback: board %d ended with another image or figures than board 0", k);
    if (rc == 0) {
        *out = t[0].img;
        t[0].img.rgb = NULL;
        *ms = st[0];
    }
    for (int k = 0; k < started; k++) {
        if (t[k].rc == 0)
            c5_image_free(&t[k].img);
        free(t[k].in);
    }
    pthread_cond_destroy(&L->bar.c);
    pthread_mutex_destroy(&L->bar.m);
    free(t), free(st), free(th), free(L);
    return rc;
}
