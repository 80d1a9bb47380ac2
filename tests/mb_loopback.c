/* The loopback transport: every collective publishes this board's part, waits at a barrier
 * for all boards, reads the others' parts, and waits again before the parts may change. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mb_loopback.h"

typedef struct {
    int size;
    pthread_barrier_t bar;
    const void *part[C5_MB_MAX_BOARDS];      /* what each board published */
    const uint16_t *dest[C5_MB_MAX_BOARDS];
    size_t n[C5_MB_MAX_BOARDS];
} loop;

typedef struct {
    loop *L;
    int rank;
    uint8_t (*in)[C5_PACKET_BYTES];
    size_t cap;
    /* the thread's job and result */
    const c5_scene *s;
    const c5_supervol *sv;
    int frame;
    const c5_board_opts *base;
    c5_mb_opts mo;
    c5_image img;
    c5_mb_stats *ms;
    c5_err err;
    int rc;
} board_thread;

static int alltoall(void *ctx, const uint8_t (*out)[C5_PACKET_BYTES], const uint16_t *dest, size_t n_out,
                    const uint8_t (**in)[C5_PACKET_BYTES], size_t *n_in, c5_err *err)
{
    board_thread *t = ctx;
    loop *L = t->L;
    L->part[t->rank] = out;
    L->dest[t->rank] = dest;
    L->n[t->rank] = n_out;
    pthread_barrier_wait(&L->bar);
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
    pthread_barrier_wait(&L->bar);
    *in = (const uint8_t (*)[C5_PACKET_BYTES])t->in;
    *n_in = n;
    return 0;
}

static int allgather(void *ctx, const void *mine, size_t bytes, void *all, c5_err *err)
{
    (void)err;
    board_thread *t = ctx;
    loop *L = t->L;
    L->part[t->rank] = mine;
    pthread_barrier_wait(&L->bar);
    for (int s = 0; s < L->size; s++)
        memcpy((char *)all + (size_t)s * bytes, L->part[s], bytes);
    pthread_barrier_wait(&L->bar);
    return 0;
}

static int sum_u64(void *ctx, uint64_t *v, size_t n, c5_err *err)
{
    board_thread *t = ctx;
    loop *L = t->L;
    uint64_t *tmp = calloc(n ? n : 1, sizeof *tmp);
    L->part[t->rank] = v;
    pthread_barrier_wait(&L->bar);
    for (int s = 0; tmp && s < L->size; s++)
        for (size_t i = 0; i < n; i++)
            tmp[i] += ((const uint64_t *)L->part[s])[i];
    pthread_barrier_wait(&L->bar);
    if (!tmp)
        return c5_fail(err, "loopback: out of memory");
    memcpy(v, tmp, n * sizeof *v);
    free(tmp);
    return 0;
}

static void *run(void *arg)
{
    board_thread *t = arg;
    c5_mb_transport tr = {t, t->rank, t->L->size, alltoall, allgather, sum_u64};
    t->rc = c5_mb_render(t->s, t->sv, t->frame, t->base, NULL, &t->mo, &tr, &t->img, t->ms, &t->err);
    return NULL;
}

int c5t_mb_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *base,
                  const c5_mb_opts *mo, int boards, c5_image *out, c5_mb_stats *ms)
{
    return c5t_mb_render_hist(s, sv, frame, base, mo, boards, NULL, out, ms);
}

int c5t_mb_render_hist(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *base,
                       const c5_mb_opts *mo, int boards, c5_mb_history *hist, c5_image *out, c5_mb_stats *ms)
{
    static loop L;
    board_thread *t = calloc((size_t)boards, sizeof *t);
    c5_mb_stats *st = calloc((size_t)boards, sizeof *st);
    pthread_t *th = calloc((size_t)boards, sizeof *th);
    if (!t || !st || !th || boards < 1 || boards > C5_MB_MAX_BOARDS) {
        fprintf(stderr, "loopback: %d boards\n", boards);
        free(t), free(st), free(th);
        return -1;
    }
    memset(&L, 0, sizeof L);
    L.size = boards;
    pthread_barrier_init(&L.bar, NULL, (unsigned)boards);
    for (int k = 0; k < boards; k++) {
        t[k] = (board_thread){.L = &L, .rank = k, .s = s, .sv = sv, .frame = frame, .base = base, .mo = *mo, .ms = &st[k]};
        t[k].mo.history = hist ? &hist[k] : NULL;
        pthread_create(&th[k], NULL, run, &t[k]);
    }
    int rc = 0;
    for (int k = 0; k < boards; k++) {
        pthread_join(th[k], NULL);
        if (t[k].rc != 0) {
            fprintf(stderr, "loopback board %d: %s\n", k, t[k].err.msg);
            rc = -1;
        }
    }
    for (int k = 1; rc == 0 && k < boards; k++)
        if (memcmp(t[k].img.rgb, t[0].img.rgb, sizeof(float) * 3 * (size_t)t[0].img.w * t[0].img.h) ||
            st[k].frame_cycles != st[0].frame_cycles || st[k].rounds != st[0].rounds) {
            fprintf(stderr, "loopback: board %d ended with another image or figures than board 0\n", k);
            rc = -1;
        }
    if (rc == 0) {
        *out = t[0].img;
        t[0].img.rgb = NULL;
        *ms = st[0];
    }
    for (int k = 0; k < boards; k++) {
        if (t[k].rc == 0)
            c5_image_free(&t[k].img);
        free(t[k].in);
    }
    pthread_barrier_destroy(&L.bar);
    free(t), free(st), free(th);
    return rc;
}
