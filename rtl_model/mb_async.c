/* The asynchronous link between boards (mb_async.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mb_async.h"

int c5_mb_async_init(c5_mb_async *a, const c5_mb_transport *t, const c5_mb_stats *ms, c5_err *err)
{
    memset(a, 0, sizeof *a);
    a->t = t;
    double ser = (double)C5_PACKET_BYTES / ms->link_bw * C5_MB_CLOCK_HZ * C5_MB_TICKS;
    a->ser = (uint64_t)ceil(ser);
    if (a->ser < 1)
        a->ser = 1;
    double lat_cycles = ms->link_latency_s * C5_MB_CLOCK_HZ;
    a->lat = (uint64_t)llround(lat_cycles * C5_MB_TICKS);
    a->lookahead = (uint64_t)floor(lat_cycles);
    if (a->lookahead < 1)
        a->lookahead = 1;
    if (!(a->all = malloc((size_t)t->size * sizeof *a->all)))
        return c5_fail(err, "out of memory for %d boards", t->size);
    return 0;
}

void c5_mb_async_free(c5_mb_async *a)
{
    free(a->all);
    free(a->rec);
    free(a->in);
    free(a->t_in);
    free(a->order);
    free(a->wait);
    free(a->spare);
    memset(a, 0, sizeof *a);
}

static int grow(c5_mb_async *a, size_t n_rec, size_t n_in, c5_err *err)
{
    if (n_rec > a->cap_rec) {
        size_t cap = n_rec + n_rec / 2 + 64;
        void *p = realloc(a->rec, cap * C5_PACKET_BYTES);
        if (!p)
            return c5_fail(err, "out of memory for the link");
        a->rec = p;
        a->cap_rec = cap;
    }
    if (n_in > a->cap_in) {
        size_t cap = n_in + n_in / 2 + 64;
        void *p = realloc(a->in, cap * C5_PACKET_BYTES);
        if (p)
            a->in = p;
        void *q = p ? realloc(a->t_in, cap * sizeof *a->t_in) : NULL;
        if (q)
            a->t_in = q;
        void *r = q ? realloc(a->order, cap * sizeof *a->order) : NULL;
        if (r)
            a->order = r;
        void *w = r ? realloc(a->wait, cap * C5_PACKET_BYTES) : NULL;
        if (w)
            a->wait = w;
        void *sp = w ? realloc(a->spare, cap * C5_PACKET_BYTES) : NULL;
        if (!sp)
            return c5_fail(err, "out of memory for the link");
        a->spare = sp;
        a->cap_in = cap;
    }
    return 0;
}

/* By the time at the switch, ties in the order received. */
static int by_switch(const void *x, const void *y)
{
    const c5_mb_arrival *p = x, *q = y;
    return p->at_switch < q->at_switch ? -1 : p->at_switch > q->at_switch ? 1 : p->i < q->i ? -1 : p->i > q->i;
}

/* The packets handed on so far leave through this board's port, in the order handed on. */
static int send_all(c5_mb_async *a, const uint8_t (*out)[C5_PACKET_BYTES], const uint16_t *dest,
                    const uint64_t *t_out, size_t n_out, c5_err *err)
{
    const c5_mb_transport *t = a->t;
    if (grow(a, n_out, 0, err) != 0)
        return -1;
    for (size_t i = 0; i < n_out; i++) {
        uint64_t ready = t_out[i] * C5_MB_TICKS;
        a->tx_free = (a->tx_free > ready ? a->tx_free : ready) + a->ser;
        a->tx_busy += a->ser;
        c5_mb_wire m = {a->tx_free + a->lat, t_out[i]};
        memset(a->rec[i], 0, C5_PACKET_BYTES);
        memcpy(a->rec[i], &m, sizeof m);
    }
    const uint8_t (*pk)[C5_PACKET_BYTES] = NULL, (*rec)[C5_PACKET_BYTES] = NULL;
    size_t n_pk = 0, n_rec = 0;
    if (t->alltoall(t->ctx, out, dest, n_out, &pk, &n_pk, err) != 0 || grow(a, 0, a->n_wait + n_pk, err) != 0)
        return -1;
    if (n_pk) /* the transport's memory is reused below */
        memcpy(a->wait + a->n_wait, pk, n_pk * C5_PACKET_BYTES);
    if (t->alltoall(t->ctx, (const uint8_t (*)[C5_PACKET_BYTES])a->rec, dest, n_out, &rec, &n_rec, err) != 0)
        return -1;
    if (n_rec != n_pk)
        return c5_fail(err, "link: %zu packets arrived with %zu times", n_pk, n_rec);
    for (size_t i = 0; i < n_pk; i++) {
        c5_mb_wire m;
        memcpy(&m, rec[i], sizeof m);
        a->order[a->n_wait + i] = (c5_mb_arrival){m.at_switch, m.sent, a->received++, a->n_wait + i};
    }
    a->n_wait += n_pk;
    if (n_pk)
        qsort(a->order, a->n_wait, sizeof *a->order, by_switch);
    return 0;
}

/* The receiver's port takes the waiting packets that reach the switch by `to` (ticks), in
 * that order, into the in-box handed to the board; the rest wait. */
static void take(c5_mb_async *a, uint64_t to)
{
    size_t k = 0;
    while (k < a->n_wait && a->order[k].at_switch <= to)
        k++;
    for (size_t i = 0; i < k; i++) {
        const c5_mb_arrival *m = &a->order[i];
        a->rx_free = (a->rx_free > m->at_switch ? a->rx_free : m->at_switch) + a->ser;
        a->rx_busy += a->ser;
        uint64_t arrive = (a->rx_free + C5_MB_TICKS - 1) / C5_MB_TICKS;
        if (arrive < m->sent + a->lookahead)
            arrive = m->sent + a->lookahead;
        if (arrive < a->last_arrival)
            arrive = a->last_arrival;
        a->last_arrival = arrive;
        a->t_in[i] = arrive;
        memcpy(a->in[i], a->wait[m->slot], C5_PACKET_BYTES);
    }
    a->n_in = k;
    /* the rest move to the front, their slots renumbered */
    for (size_t i = k; i < a->n_wait; i++) {
        memcpy(a->spare[i - k], a->wait[a->order[i].slot], C5_PACKET_BYTES);
        a->order[i - k] = a->order[i];
        a->order[i - k].slot = i - k;
    }
    a->n_wait -= k;
    if (a->n_wait)
        memcpy(a->wait, a->spare, a->n_wait * C5_PACKET_BYTES);
}

int c5_mb_async_exchange(void *ctx, const c5_link_report *me, const uint8_t (*out)[C5_PACKET_BYTES],
                         const uint16_t *dest, const uint64_t *t_out, size_t n_out,
                         const uint8_t (**in)[C5_PACKET_BYTES], const uint64_t **t_in, size_t *n_in,
                         uint64_t *bound, c5_err *err)
{
    c5_mb_async *a = ctx;
    const c5_mb_transport *t = a->t;
    *n_in = 0;
    *in = NULL;
    *t_in = NULL;
    if (send_all(a, out, dest, t_out, n_out, err) != 0)
        return -1;
    c5_link_report r = *me; /* a packet still at the switch wakes this board no sooner */
    if (a->n_wait && a->order[0].at_switch / C5_MB_TICKS < r.next)
        r.next = a->order[0].at_switch / C5_MB_TICKS;
    if (t->allgather(t->ctx, &r, sizeof r, a->all, err) != 0)
        return -1;
    a->exchanges++;
    uint64_t b = UINT64_MAX;
    for (int k = 0; k < t->size; k++)
        b = a->all[k].next < b ? a->all[k].next : b;
    *bound = b;
    if (b == UINT64_MAX) /* no board has a ray, an arrival to come or a packet on its way */
        return 0;
    /* any packet not yet at the switch is handed on after b: it reaches the switch after
     * b + latency, so none can pass those that reach it by then */
    uint64_t to = (b + a->lookahead) > UINT64_MAX / C5_MB_TICKS ? UINT64_MAX : (b + a->lookahead) * C5_MB_TICKS;
    take(a, to);
    *in = (const uint8_t (*)[C5_PACKET_BYTES])a->in;
    *t_in = a->t_in;
    *n_in = a->n_in;
    return 1;
}

const c5_link_report *c5_mb_async_reports(void *ctx) { return ((c5_mb_async *)ctx)->all; }
