/* The ray queue's equivalent model: see rq_heap.h and docs/ray-queue.md. The prelude of
 * c5_rqh_step (masking, pop, full, accepted, the outputs, the statistics) is that of
 * c5_rq_step line for line; only the storage differs. */
#include "rq_heap.h"

#include <stdlib.h>
#include <string.h>

/* Does a leave before b? Smaller key first, equal keys in acceptance order. */
static inline int before(const c5_rqh_el *a, const c5_rqh_el *b)
{
    /* (key, seq) as one number: one comparison, no branch (which child is smaller is data) */
    return ((unsigned __int128)a->key << 64 | a->seq) < ((unsigned __int128)b->key << 64 | b->seq);
}

int c5_rqh_init(c5_rqh *q, const c5_rq_cfg *cfg)
{
    memset(q, 0, sizeof *q);
    if (!cfg || cfg->capacity < 1 || cfg->capacity > C5_RQ_MAX_CAPACITY || cfg->key_bits < 1 || cfg->key_bits > 32)
        return -1;
    q->a = calloc(cfg->capacity, sizeof *q->a);
    if (!q->a)
        return -1;
    q->cfg = *cfg;
    q->key_mask = cfg->key_bits == 32 ? 0xFFFFFFFFu : ((1u << cfg->key_bits) - 1u);
    c5_rqh_reset(q);
    return 0;
}

void c5_rqh_reset(c5_rqh *q)
{
    if (!q->a)
        return;
    q->count = 0;
    q->next_seq = 0;
    memset(&q->stats, 0, sizeof q->stats);
}

void c5_rqh_free(c5_rqh *q)
{
    free(q->a);
    memset(q, 0, sizeof *q);
}

/* Places x in the hole at the root of a[0..n-1] (n >= 1), moving the hole down. */
static void sift_down(c5_rqh_el *a, uint32_t n, c5_rqh_el x)
{
    uint32_t i = 0;
    for (;;) {
        uint32_t c = 2 * i + 1;
        if (c >= n)
            break;
        if (c + 1 < n)
            c += (uint32_t)before(&a[c + 1], &a[c]);
        if (!before(&a[c], &x))
            break;
        a[i] = a[c];
        i = c;
    }
    a[i] = x;
}

/* Places x in the hole at a[i], moving the hole up. */
static void sift_up(c5_rqh_el *a, uint32_t i, c5_rqh_el x)
{
    while (i > 0) {
        uint32_t p = (i - 1) / 2;
        if (!before(&x, &a[p]))
            break;
        a[i] = a[p];
        i = p;
    }
    a[i] = x;
}

void c5_rqh_step(c5_rqh *q, const c5_rq_in *in, c5_rq_out *out)
{
    uint32_t count = q->count;
    c5_rq_cycle c = c5_rq_ports(count, q->cfg.capacity, q->key_mask, &q->stats, in, q->a[0].key, q->a[0].payload,
                                out);
    uint32_t key = c.key;
    int pop = c.pop, accepted = c.accepted;

    /* Pop first (only elements of earlier cycles can leave), then insert. */
    if (accepted) {
        c5_rqh_el x = {key, in->insert_payload, q->next_seq++};
        if (pop)
            sift_down(q->a, count, x); /* the insert takes the popped root's place */
        else
            sift_up(q->a, count, x);
    } else if (pop && count > 1) {
        sift_down(q->a, count - 1, q->a[count - 1]);
    }

    c5_rq_account(&q->count, &q->stats, &c);
}
