/* The DSP's Cell Tree scheduling (Frank & Kaufman, Sections 3.3-3.4) on a plain array tree.
 *
 * A Cell Tree is a forest: node i has a cell cell[i] in 0..63 and a parent parent[i] (-1 for
 * a root). The DSP-RAM storage converts itself into this form; nothing here knows about it.
 * Guarantees (c5_tree_check): parent[i] < i, a child's cell differs from its parent's, and
 * siblings (roots included) have distinct cells.
 *
 * A schedule is a sequence of cell loads. It is feasible when every root-to-leaf path's
 * sequence of cells is a subsequence of it; the optimum is the shortest feasible one (a
 * shortest common supersequence of the paths, NP-hard in general).
 *
 * The algorithms work in reverse: a "peel" of cell c removes every current leaf of cell c
 * from the interim tree and appends c to the reverse schedule; the forward (load-order)
 * schedule is the reverse schedule reversed. Every function except c5_tree_check expects a
 * tree that passes c5_tree_check. */
#ifndef C5_TREE_SCHED_H
#define C5_TREE_SCHED_H

#include <stdint.h>

#include "err.h"

#define C5_SCHED_MAX_CELLS 64

typedef struct {
    int n;
    const int *parent;
    const int *cell;
} c5_dep_tree;

typedef enum {
    C5_SPLIT_MOST_LEAVES = 1, /* the paper's rule: the cell with most leaf nodes (ties: lowest id) */
    C5_SPLIT_LOOKAHEAD = 2,   /* ours: simulate each candidate's split plus the completion peels
                                 it unlocks; lowest (peels + remaining lower bound) wins
                                 (ties: most leaves, then lowest id). Since each completion
                                 lowers the sum of maxGen by exactly one, the score is
                                 1 + sum + (stuck again), so this is the paper's rule except
                                 when some split lets completions finish the tree: never
                                 longer than rule 1, rarely shorter. */
    C5_SPLIT_ROLLOUT = 3,     /* ours, best and dearest: at every peel (not only splits) a cell
                                 with only leaves left is peeled at once (provably optimal);
                                 otherwise each cell with a leaf, ready or not, is tried and the
                                 rest finished by the cheap policy (completions, full cells
                                 first, else most leaves); shortest total wins (same ties).
                                 Never longer than that cheap policy. Cost: one cheap run per
                                 candidate cell per peel (about 3000x rule 1's node visits on an
                                 8191-node, 64-cell tree). */
} c5_split_rule;

typedef struct {
    int len;                 /* schedule length */
    int *cells;              /* FORWARD schedule (load order), len entries, malloc'd (never NULL) */
    int peels_completion, peels_split;
    uint64_t nodes_examined; /* node visits by the algorithm (the paper's cost measure) */
    int max_gen;             /* largest generation */
} c5_schedule;

/* The guarantees above; 0, or -1 with a message naming the first offending node. */
int c5_tree_check(const c5_dep_tree *t, c5_err *err);

/* gen[i] = 1 + number of ancestors of i with cell[i] (gen has t->n entries); returns the
 * largest generation (0 for an empty tree), or -1 when out of memory. */
int c5_tree_generations(const c5_dep_tree *t, int *gen);

/* The Cell Tree algorithm: completion peels of the lowest ready cell while there is one,
 * otherwise a split peel chosen by `rule` (C5_SPLIT_ROLLOUT decides every peel itself).
 * A peel counts as a completion when its cell was ready. Fills *out (free with
 * c5_schedule_free). */
int c5_sched_celltree(const c5_dep_tree *t, c5_split_rule rule, c5_schedule *out, c5_err *err);
void c5_schedule_free(c5_schedule *s);

/* Section 3.4's "bound": sum over cells of the largest generation, + 1 when completion peels
 * alone (lowest ready id first), from the start, get stuck on a non-empty tree. -1 when out
 * of memory. NOT a valid lower bound: it rests on the paper's claim that a completion peel
 * is part of some optimal schedule, which is false (paths 0-1-2 and 1-0-1: bound 5, optimum
 * 4). It exceeds the optimum by at most 1, and only when the optimum equals the sum of
 * maxGen (all peels completions, in a better order). Kept to reproduce the paper's Figure 6;
 * c5_sched_sum_maxgen is the valid bound. */
int c5_sched_lower_bound(const c5_dep_tree *t);

/* Sum over cells of the largest generation: a lower bound that needs no claim (cell c must
 * be loaded at least maxGen(c) times). -1 when out of memory. */
int c5_sched_sum_maxgen(const c5_dep_tree *t);

/* 1 iff every root-to-leaf path is a subsequence of sched[0..len); 0 otherwise; -1 when out
 * of memory. Entries outside 0..63 are loads that serve no node. */
int c5_sched_feasible(const c5_dep_tree *t, const int *sched, int len);

/* Exact optimum by A* over interim trees (tree_exact.c).
 * 1: found, *len_out = optimum (and, if sched_out != NULL, a malloc'd optimal forward
 *    schedule, never NULL);
 * 0: gave up because the search would store more than max_states states or the tree has
 *    more than max_nodes nodes;
 * -1: error (bad tree, out of memory).
 * Memory budget: each stored state costs 8*ceil(n/64) bytes of node bitset plus about 50
 * bytes of bookkeeping (g, back pointer, action, hash, hash-table slots, heap entries), so
 * max_states = 200000 on a 200-node tree is about 16 MB. Deterministic: no pointer hashing,
 * no clock. */
int c5_sched_optimum(const c5_dep_tree *t, long max_states, int max_nodes, int *len_out, int **sched_out,
                     c5_err *err);
/* The same search without the rollout rule's schedule as an upper bound: slower, but its
 * answer does not depend on that rule (the tests check the search alone with it). */
int c5_sched_optimum_plain(const c5_dep_tree *t, long max_states, int max_nodes, int *len_out, int **sched_out,
                           c5_err *err);

#endif
