/* The ray queue's equivalent model: the same ports, outputs and statistics as the clock-level
 * insertion sorter (ray_queue.h) every cycle, computed by a stable binary heap instead of
 * 256 stages of registers.
 *
 * Why it is equal (docs/ray-queue.md, "The equivalent model"): every output of the sorter
 * in cycle t is a function of its occupancy at the start of t and of its smallest element by
 * (key, acceptance cycle): pop_valid, full, insert_accepted, count and empty of the count,
 * pop_key and pop_payload of held[0], which the sorter keeps as that minimum while inserts
 * still ripple. A heap ordered by (key, acceptance number) has the same minimum and the same
 * count after every cycle, so it produces the same outputs and statistics bit for bit. It
 * holds no stage registers: the clock-level model stays the reference for the registers
 * themselves (its tests, the ray queue's golden vectors). tests/test_rq_heap.c runs both
 * side by side on random and adversarial traffic and on whole frames of every built-in scene.
 *
 * O(log capacity) a cycle instead of O(elements in flight): the board uses it unless asked
 * for the clock-level sorter (board.h, queue_model). */
#ifndef C5_RQ_HEAP_H
#define C5_RQ_HEAP_H

#include <stdint.h>

#include "ray_queue.h"

/* One element: its key, payload and acceptance number (what breaks ties: equal keys leave
 * in acceptance order, as in the sorter). 64 bits never wrap. */
typedef struct {
    uint32_t key, payload;
    uint64_t seq;
} c5_rqh_el;

typedef struct {
    c5_rq_cfg cfg;
    uint32_t key_mask;
    c5_rqh_el *a;      /* [capacity]: a binary heap on (key, seq), a[0] the smallest */
    uint32_t count;    /* elements in the queue, as c5_rq.count */
    uint64_t next_seq; /* acceptance number of the next accepted insert */
    c5_rq_stats stats; /* as c5_rq.stats */
} c5_rqh;

/* As c5_rq_init, c5_rq_reset, c5_rq_step and c5_rq_free, with the same arguments, results
 * and refusals (capacity 1..4096, key_bits 1..32). */
int c5_rqh_init(c5_rqh *q, const c5_rq_cfg *cfg);
void c5_rqh_reset(c5_rqh *q);
void c5_rqh_step(c5_rqh *q, const c5_rq_in *in, c5_rq_out *out);
void c5_rqh_free(c5_rqh *q);

#endif
