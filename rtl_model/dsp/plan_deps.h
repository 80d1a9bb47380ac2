/* The plan across boards (docs/multi-board.md, "Scheduling across boards"): the schedule of
 * the boards' pooled Cell Tree, which every board follows for its own cells, and what each
 * entry waits for on the other boards. */
#ifndef C5_PLAN_DEPS_H
#define C5_PLAN_DEPS_H

#include <stdint.h>

/* The tree: n nodes, parent[i] < i or -1, cell[i]; sched: the forward schedule of len
 * entries; owner[cell]: the board of each cell, of `boards`. dep[i * boards + k] is set to
 * the last entry of board k whose load hands rays on to a node entry i works off (-1: none):
 * a node is worked off at the first entry of its cell after its parent's (a root: the first
 * of its cell), as the replay follows a schedule. Only other boards' entries count; every
 * dependency is on an earlier entry. */
void c5_plan_deps(const int *parent, const int *cell, int n, const int *sched, int len, const uint16_t *owner,
                  int boards, int *dep);

#endif
