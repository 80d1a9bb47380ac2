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

/* A reference's fault counter: c5ref_faulty is 1 in the call C5REF_FAULT names (counted from
 * 0 over the process's calls of that reference), else 0. */
typedef struct {
    long runs, step; /* step -2: C5REF_FAULT not read yet */
} c5ref_fault;
#define C5REF_FAULT_INIT {0, -2}

static inline int c5ref_faulty(c5ref_fault *f)
{
    if (f->step == -2)
        f->step = c5ref_fault_step();
    return f->runs++ == f->step;
}

#endif
