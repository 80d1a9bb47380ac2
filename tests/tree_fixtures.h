/* Fixtures of the Cell Tree scheduling tests (test_tree_sched.c, test_tree_bound.c). */
#ifndef C5_TREE_FIXTURES_H
#define C5_TREE_FIXTURES_H

#include <stdint.h>

#include "tree_sched.h"

/* A random forest honouring the tree guarantees, up to n (< 9000) nodes: returns the count. */
int c5t_random_tree(uint64_t *rng, int n, int ncells, int maxdepth, int *parent, int *cell);
/* The same with the cells drawn from pool[0..npool) (distinct ids up to C5_SCHED_MAX_CELLS-1). */
int c5t_random_tree_wide(uint64_t *rng, int n, const int *pool, int npool, int maxdepth, int *parent, int *cell);
/* The optimum by forward brute force over load sequences of growing length (tiny trees,
 * at most 64 nodes); needs none of the tree guarantees, so it also solves projections. */
int c5t_brute_opt(const c5_dep_tree *t);

#endif
