/* The report beside the DSP's schedule (`cube5 schedule`, docs/cell-tree.md): the other
 * split rules' lengths and the bounds on the optimum. Offline analysis: the DSP computes
 * none of it on the board; c5_dsp_schedule fills it in for a whole tree when asked. */
#ifndef C5_SCHED_REPORT_H
#define C5_SCHED_REPORT_H

#include "dsp_sched.h"

/* The other rules (o->all_rules), the paper's bound, the sum of maxGen and, with
 * o->exact_states, the exact optimum or the best schedule known and the best bound proved,
 * into r. rule: the one the DSP ran, already in r. 0, or -1 with a message. */
int c5_dsp_sched_report(const c5_dep_tree *dt, c5_split_rule rule, const c5_dsp_sched_opts *o,
                        c5_dsp_sched_result *r, c5_err *err);

#endif
