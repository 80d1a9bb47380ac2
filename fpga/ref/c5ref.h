/* Shared by the live references of fpga/ref/ (libc5ref.so, loaded by GHDL). */
#ifndef C5REF_H
#define C5REF_H

#include <stdlib.h>

/* C5REF_FAULT=N: the step (cycle, packet, sample) at which a reference answers wrong on
 * purpose, -1 when unset: tests/live_test.sh shows every live testbench failing there. */
static inline long c5ref_fault_step(void)
{
    const char *f = getenv("C5REF_FAULT");
    return f ? atol(f) : -1;
}

#endif
