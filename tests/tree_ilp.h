/* The optimum of a Cell Tree schedule as an integer program solved by GLPK: a formulation
 * that shares no code with the A* of rtl_model/analysis/tree_exact.c (nor with its bounds or the
 * feasibility test), so the tests can check one against the other (docs/cell-tree.md,
 * "Bounds (Section 3.4) and the exact optimum"). Test-only: the DSP never runs it. */
#ifndef C5_TREE_ILP_H
#define C5_TREE_ILP_H

#include "tree_sched.h"

/* Time-indexed program over positions 0..horizon-1 of the forward schedule:
 *   y[c][t] = 1: position t loads cell c;  at most one cell per position;
 *   x[v][t] = 1: node v is served by the load at position t;  every node exactly once, by
 *   a load of its own cell, at a position after its parent's;
 *   minimise the loads, sum of y.
 * A feasible x embeds every root-to-leaf path as a subsequence, and conversely (the
 * leftmost embedding of each path agrees on shared prefixes), so the minimum is the
 * shortest feasible schedule when one fits the horizon.
 * 1: *len_out = the optimum and, if sched != NULL, an optimal forward schedule in
 *    sched[0..*len_out) (sched has room for horizon entries);
 * 0: no schedule of at most `horizon` loads exists (GLPK proved the program infeasible);
 * -1: error (GLPK failed, out of memory, cell id outside 0..C5_SCHED_MAX_CELLS-1). */
int c5t_ilp_optimum(const c5_dep_tree *t, int horizon, int *len_out, int *sched);

#endif
