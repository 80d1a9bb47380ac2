/* The ray queue: a systolic (pipelined) insertion sorter, one per cell, on its own eDRAM,
 * holding up to `capacity` rays (256 on the board) ordered by key, smallest first.
 * Bit-accurate, cycle-counting: c5_rq_step() is exactly one clock edge.
 *
 * Structure (docs/ray-queue.md): `capacity` stages in a line. Stage i holds one settled
 * element held[i] and has one carry register carry[i], the element that travels into stage
 * i at the next edge (carry[0] is the insert port itself). The held elements form a sorted,
 * gap-free prefix. An inserted element moves exactly one stage per cycle, compare-and-swap
 * at each stage (the smaller stays, the larger travels on); a pop takes held[0] and shifts
 * the held line up by one stage in the same edge.
 *
 * Latency rule (cycle t, every output computed from the registers at the start of t and
 * the inputs of t; the registers change at the edge that ends t):
 *   - pop_valid = pop_ready && count > 0. The popped element is the smallest key among the
 *     elements accepted in cycles < t and not yet popped; among equal keys the one accepted
 *     first. The insert of cycle t is never popped in cycle t; it can be popped in t+1.
 *     Inserts still rippling down the line never delay or falsify a pop: held[0] is always
 *     the minimum of everything in the queue.
 *   - full = (count == capacity) && !pop_valid; insert_accepted = insert_valid && !full.
 *     A full queue that pops in the same cycle accepts the insert. A refused insert is lost
 *     to the queue: the caller must keep (spill) that ray.
 *   - count, empty: the occupancy at the start of cycle t (held + in flight), i.e. the
 *     elements accepted before t and not popped before t. q->count after the step is the
 *     occupancy of cycle t+1.
 * The popped sequence is therefore exactly that of an ideal stable priority queue that,
 * every cycle, first pops (if asked and non-empty) and then inserts (if not full).
 *
 * Keys wider than cfg.key_bits are a caller error: the key is masked to key_bits and the
 * event counted in stats.masked_keys (no assert). */
#ifndef C5_RAY_QUEUE_H
#define C5_RAY_QUEUE_H

#include <stdint.h>

#define C5_RQ_DEFAULT_CAPACITY 256u
#define C5_RQ_MAX_CAPACITY 4096u
#define C5_RQ_DEFAULT_KEY_BITS 32u
/* The board's configuration: 256 entries, 32-bit keys. */
#define C5_RQ_CFG_DEFAULT {C5_RQ_DEFAULT_CAPACITY, C5_RQ_DEFAULT_KEY_BITS}

/* Static parameters. */
typedef struct {
    uint32_t capacity; /* stages = elements held, 1..4096 */
    uint32_t key_bits; /* key width, 1..32 */
} c5_rq_cfg;

/* Input signals of one clock cycle (flags: 0 or non-zero). */
typedef struct {
    int insert_valid;
    uint32_t insert_key;     /* smaller = higher priority; must fit key_bits */
    uint32_t insert_payload; /* eDRAM address or ray index, carried unchanged */
    int pop_ready;           /* the consumer takes the head element this cycle if there is one */
} c5_rq_in;

/* Output signals of that cycle (flags 0 or 1; pop_key/pop_payload are 0 when !pop_valid). */
typedef struct {
    int pop_valid; /* an element leaves the queue this cycle */
    uint32_t pop_key;
    uint32_t pop_payload;
    int insert_accepted;
    int full;       /* an insert this cycle is (or would be) refused: spill the ray */
    uint32_t count; /* occupancy at the start of the cycle */
    int empty;      /* count == 0 */
} c5_rq_out;

/* One register slot. `fresh` only means something in a carry register: 1 for an element
 * that has not settled since it was inserted (it loses ties), 0 for a settled element
 * displaced back into the carry line (it wins ties). It is what keeps equal keys FIFO
 * without sequence numbers. */
typedef struct {
    uint8_t valid;
    uint8_t fresh;
    uint32_t key;
    uint32_t payload;
} c5_rq_slot;

/* What the queue counts since reset; the same for the equivalent model (rq_heap.h). */
typedef struct {
    uint64_t cycles;      /* steps since reset */
    uint64_t inserts;     /* accepted inserts */
    uint64_t pops;        /* elements popped */
    uint64_t refused;     /* inserts refused because the queue was full (spilled) */
    uint64_t masked_keys; /* insert_valid cycles whose key did not fit key_bits */
    uint32_t max_count;   /* largest occupancy reached */
} c5_rq_stats;

/* The ports of one cycle, the same for the sorter and its equivalent model (rq_heap.h): the
 * key as masked to key_bits, and whether the cycle pops, refuses and accepts. */
typedef struct {
    uint32_t key;
    int ins_valid, pop, full, accepted;
} c5_rq_cycle;

/* The cycle's outputs from the occupancy and the smallest element (min_key, min_payload:
 * read only when the cycle pops). */
static inline c5_rq_cycle c5_rq_ports(uint32_t count, uint32_t capacity, uint32_t key_mask, c5_rq_stats *st,
                                      const c5_rq_in *in, uint32_t min_key, uint32_t min_payload, c5_rq_out *out)
{
    c5_rq_cycle c = {in->insert_key, in->insert_valid != 0, 0, 0, 0};
    if (c.ins_valid && (c.key & ~key_mask)) {
        st->masked_keys++;
        c.key &= key_mask;
    }
    c.pop = in->pop_ready && count > 0;
    c.full = count == capacity && !c.pop;
    c.accepted = c.ins_valid && !c.full;
    out->pop_valid = c.pop;
    out->pop_key = c.pop ? min_key : 0;
    out->pop_payload = c.pop ? min_payload : 0;
    out->insert_accepted = c.accepted;
    out->full = c.full;
    out->count = count;
    out->empty = count == 0;
    return c;
}

/* The occupancy and statistics after the cycle's edge. */
static inline void c5_rq_account(uint32_t *count, c5_rq_stats *st, const c5_rq_cycle *c)
{
    *count += (uint32_t)c->accepted - (uint32_t)c->pop;
    st->cycles++;
    st->inserts += (uint64_t)c->accepted;
    st->pops += (uint64_t)c->pop;
    st->refused += (uint64_t)(c->ins_valid && c->full);
    if (*count > st->max_count)
        st->max_count = *count;
}

/* Registers and statistics. Read freely; write only through the functions. */
typedef struct {
    c5_rq_cfg cfg;
    uint32_t key_mask;
    c5_rq_slot *held;  /* [capacity]: the settled element of each stage, sorted, gap-free */
    c5_rq_slot *carry; /* [capacity + 1]: carry[i] enters stage i at the next edge; [0] and
                          [capacity] stay empty (the insert port and the end of the line) */
    uint32_t count;    /* elements held + in flight */
    uint32_t len;      /* held elements (held[0..len-1] valid); model bookkeeping, not a
                          hardware register: the step never touches stages beyond it */
    c5_rq_stats stats;
} c5_rq;

/* Allocates and resets. 0, or -1 (q zeroed) for a capacity outside 1..4096, key_bits
 * outside 1..32, or no memory. */
int c5_rq_init(c5_rq *q, const c5_rq_cfg *cfg);
/* Power-on state: every register empty, statistics zero. */
void c5_rq_reset(c5_rq *q);
/* Exactly one clock edge: fills *out with the signals of this cycle, then updates the
 * registers. */
void c5_rq_step(c5_rq *q, const c5_rq_in *in, c5_rq_out *out);
void c5_rq_free(c5_rq *q);

#endif
