/* The ray queue of the C model (rtl_model/proc/ray_queue.c) as a live reference inside a VHDL
 * simulator: foreign functions that GHDL calls through VHPIDIRECT (tb/c5ref_pkg.vhd),
 * built with the model's source into build/libc5ref.so (docs/vectors.md, "The model inside
 * the simulator"). Integers cross as VHDL `integer` (32-bit signed): keys and payloads are
 * their bit patterns. One queue per process, as one testbench drives one DUT. */
#include <stdint.h>

#include "c5ref.h"
#include "ray_queue.h"

int32_t c5ref_rq_reset(int32_t capacity, int32_t key_bits);
int32_t c5ref_rq_step(int32_t insert_valid, int32_t insert_key, int32_t insert_payload, int32_t pop_ready);
int32_t c5ref_rq_out(int32_t k);

static c5_rq q;
static int ready;
static c5_rq_out out;
static long cycle, fault = -1; /* the model's pop_key is wrong in this cycle (c5ref.h) */

/* Empties the queue (the DUT's reset); 0, or -1 for a configuration the model refuses. */
int32_t c5ref_rq_reset(int32_t capacity, int32_t key_bits)
{
    if (ready)
        c5_rq_free(&q);
    c5_rq_cfg cfg = {(uint32_t)capacity, (uint32_t)key_bits};
    ready = c5_rq_init(&q, &cfg) == 0;
    cycle = 0;
    fault = c5ref_fault_step();
    return ready ? 0 : -1;
}

/* One clock cycle: the inputs of the cycle; its outputs are read with c5ref_rq_out. */
int32_t c5ref_rq_step(int32_t insert_valid, int32_t insert_key, int32_t insert_payload, int32_t pop_ready)
{
    if (!ready)
        return -1;
    c5_rq_in in = {insert_valid != 0, (uint32_t)insert_key, (uint32_t)insert_payload, pop_ready != 0};
    c5_rq_step(&q, &in, &out);
    if (cycle++ == fault)
        out.pop_key ^= 1u;
    return 0;
}

/* Output k of the last cycle: 0 pop_valid, 1 pop_key, 2 pop_payload, 3 insert_accepted,
 * 4 full, 5 count, 6 empty (the entity's port order). */
int32_t c5ref_rq_out(int32_t k)
{
    switch (k) {
    case 0: return out.pop_valid;
    case 1: return (int32_t)out.pop_key;
    case 2: return (int32_t)out.pop_payload;
    case 3: return out.insert_accepted;
    case 4: return out.full;
    case 5: return (int32_t)out.count;
    case 6: return out.empty;
    default: return 0;
    }
}
