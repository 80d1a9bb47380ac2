/* The traversal step of the C model (c5_trav_step, rtl_model/proc/processor.c) as a live
 * reference for GHDL (tb/c5ref_pkg.vhd): inputs set one by one, one step, outputs read. */
#include <stdint.h>

#include "c5ref.h"
#include "processor.h"
#include "taps.h"

int32_t c5ref_tr_set(int32_t k, int32_t v);
int32_t c5ref_tr_run(void);
int32_t c5ref_tr_out(int32_t k);

static c5_trav_in tin;
static c5_trav_out tout;
static long runs, fault = -2; /* the model's lifetime_out is off by one in this step (c5ref.h) */

/* k: 0..2 pos (SQ10.15), 3..5 step (SQ3.15), 6 lifetime, 7..9 cell_lo, 10..12 cell_hi,
 * 13..15 dims, 16 block_empty. */
int32_t c5ref_tr_set(int32_t k, int32_t v)
{
    if (k >= 0 && k < 3)
        tin.pos[k] = v;
    else if (k < 6)
        tin.S[k - 3] = v;
    else if (k == 6)
        tin.lifetime = (uint32_t)v;
    else if (k < 10)
        tin.lo[k - 7] = v;
    else if (k < 13)
        tin.hi[k - 10] = v;
    else if (k < 16)
        tin.dims[k - 13] = v;
    else if (k == 16)
        tin.block_empty = v != 0;
    else
        return -1;
    return 0;
}

int32_t c5ref_tr_run(void)
{
    if (fault == -2)
        fault = c5ref_fault_step();
    c5_trav_step(&tin, &tout);
    if (runs++ == fault)
        tout.lifetime ^= 1u;
    return tout.action;
}

/* k: 0 action, 1 leaped, 2..4 pos_out, 5 lifetime_out. */
int32_t c5ref_tr_out(int32_t k)
{
    switch (k) {
    case 0: return tout.action;
    case 1: return (int32_t)tout.leaped;
    case 2: case 3: case 4: return (int32_t)tout.pos[k - 2];
    case 5: return (int32_t)tout.lifetime;
    default: return 0;
    }
}
