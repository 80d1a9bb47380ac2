/* The ray queue: see ray_queue.h and docs/ray-queue.md.
 *
 * Per stage, with empty slots counting as larger than any key:
 *   level 1 (every cycle): the carry meets the held element of its stage;
 *       lo = the smaller, hi = the larger.
 *   no pop: held'[i] = lo[i], carry'[i+1] = hi[i].
 *   pop (level 2, between neighbours): held[0] leaves, the insert of this cycle takes the
 *       place of hi[0], and hi[i] meets lo[i+1]:
 *       held'[i] = the smaller, carry'[i+1] = the larger.
 * Ties: a fresh element (inserted, never settled) loses, anything else wins. With that rule
 * every comparison orders by (key, acceptance cycle), which makes the queue stable. */
#include "ray_queue.h"

#include <stdlib.h>
#include <string.h>

static const c5_rq_slot EMPTY = {0, 0, 0, 0};

/* Does a go before b? a and b from different sources; a fresh a loses ties. */
static inline int goes_first(const c5_rq_slot *a, const c5_rq_slot *b)
{
    if (!a->valid)
        return 0;
    if (!b->valid)
        return 1;
    return a->key < b->key || (a->key == b->key && !a->fresh);
}

int c5_rq_init(c5_rq *q, const c5_rq_cfg *cfg)
{
    memset(q, 0, sizeof *q);
    if (!cfg || cfg->capacity < 1 || cfg->capacity > C5_RQ_MAX_CAPACITY || cfg->key_bits < 1 || cfg->key_bits > 32)
        return -1;
    q->held = calloc(cfg->capacity, sizeof *q->held);
    q->carry = calloc((size_t)cfg->capacity + 1, sizeof *q->carry);
    if (!q->held || !q->carry) {
        free(q->held);
        free(q->carry);
        memset(q, 0, sizeof *q);
        return -1;
    }
    q->cfg = *cfg;
    q->key_mask = cfg->key_bits == 32 ? 0xFFFFFFFFu : ((1u << cfg->key_bits) - 1u);
    c5_rq_reset(q);
    return 0;
}

void c5_rq_reset(c5_rq *q)
{
    if (!q->held)
        return;
    memset(q->held, 0, q->cfg.capacity * sizeof *q->held);
    memset(q->carry, 0, ((size_t)q->cfg.capacity + 1) * sizeof *q->carry);
    q->count = 0;
    q->len = 0;
    memset(&q->stats, 0, sizeof q->stats);
}

void c5_rq_free(c5_rq *q)
{
    free(q->held);
    free(q->carry);
    memset(q, 0, sizeof *q);
}

/* Level 1 at stage i: carry c meets held p. */
static inline void level1(const c5_rq_slot *c, const c5_rq_slot *p, c5_rq_slot *lo, c5_rq_slot *hi)
{
    if (goes_first(c, p)) {
        *lo = *c;
        *hi = *p; /* a settled element displaced into the carry line */
    } else {
        *lo = *p;
        *hi = *c;
    }
    lo->fresh = 0;
    hi->fresh = hi->valid && hi->fresh; /* p is never fresh; c keeps its tag */
}

/* No pop: every carry meets its stage, the larger moves one stage on. Stages with neither
 * a carry arriving nor one leaving keep their registers and are skipped. The registers are
 * read into locals once (the pointers may alias for the compiler), stage 0 (the insert
 * port) is peeled, and a run of stages without a carry is skipped in one scan: the model's
 * hottest loop, the result register for register that of one stage at a time. */
static void edge_hold(c5_rq *q, const c5_rq_slot *ins, uint32_t in_flight)
{
    uint32_t n = q->cfg.capacity;
    uint32_t last = q->len < n ? q->len : n - 1; /* carries exist at stages <= len only */
    c5_rq_slot *held = q->held, *carry = q->carry;
    c5_rq_slot moving = EMPTY;                   /* carry'[i], produced by stage i-1 */
    if (ins->valid) {
        c5_rq_slot c = *ins, p = held[0], lo, hi;
        level1(&c, &p, &lo, &hi);
        held[0] = lo;
        moving = hi;
    }
    for (uint32_t i = 1; i <= last; i++) {
        if (!moving.valid) {
            if (in_flight == 0)
                break; /* nothing further down moves */
            while (i <= last && !carry[i].valid)
                i++;
            if (i > last)
                break;
        }
        c5_rq_slot c = carry[i], p = held[i], lo, hi;
        in_flight -= c.valid;
        level1(&c, &p, &lo, &hi);
        held[i] = lo;
        carry[i] = moving;
        moving = hi;
    }
    /* moving is now empty: the last visited stage was either stage len, which has no held
     * element, or the end of a full line (count <= capacity: nothing falls off the end). */
    if (q->len < n && held[q->len].valid)
        q->len++;
}

/* Pop: held[0] leaves, the line shifts up while every carry still meets one element. Past
 * the last carry the line only shifts. Locals as in edge_hold. */
static void edge_pop(c5_rq *q, const c5_rq_slot *ins, uint32_t in_flight)
{
    uint32_t n = q->cfg.capacity, len = q->len; /* len >= 1 */
    c5_rq_slot *held = q->held, *carry = q->carry;
    c5_rq_slot hi = *ins;                        /* hi[0]: the insert of this cycle */
    for (uint32_t i = 0; i < len; i++) {
        if (in_flight == 0 && !hi.valid) { /* held'[j] = held[j+1] from here on */
            memmove(held + i, held + i + 1, (len - 1 - i) * sizeof *held);
            held[len - 1] = EMPTY;
            break;
        }
        c5_rq_slot lo1 = EMPTY, hi1 = EMPTY; /* level 1 at stage i+1 */
        if (i + 1 < n) {
            c5_rq_slot c = carry[i + 1], p = held[i + 1];
            in_flight -= c.valid;
            level1(&c, &p, &lo1, &hi1);
        }
        if (goes_first(&hi, &lo1)) {
            hi.fresh = 0;
            held[i] = hi;
            carry[i + 1] = lo1; /* lo1 is never fresh */
        } else {
            held[i] = lo1;
            carry[i + 1] = hi;
        }
        hi = hi1;
    }
    /* held[len] (if any) and carry[len+1] stay empty: stage len had no held element. */
    if (!held[len - 1].valid)
        q->len--;
}

void c5_rq_step(c5_rq *q, const c5_rq_in *in, c5_rq_out *out)
{
    uint32_t count = q->count;
    c5_rq_cycle c = c5_rq_ports(count, q->cfg.capacity, q->key_mask, &q->stats, in, q->held[0].key,
                                q->held[0].payload, out);
    uint32_t key = c.key;
    int pop = c.pop, accepted = c.accepted;

    /* the clock edge */
    c5_rq_slot ins = EMPTY;
    if (accepted) {
        ins.valid = 1;
        ins.fresh = 1;
        ins.key = key;
        ins.payload = in->insert_payload;
    }
    uint32_t in_flight = count - q->len;
    if (pop)
        edge_pop(q, &ins, in_flight);
    else if (accepted || in_flight > 0)
        edge_hold(q, &ins, in_flight);

    c5_rq_account(&q->count, &q->stats, &c);
}
