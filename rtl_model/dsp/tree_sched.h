/* The DSP's Cell Tree scheduling (Frank & Kaufman, Sections 3.3-3.4) on a plain array tree.
 *
 * A Cell Tree is a forest: node i has a cell cell[i] in 0..C5_SCHED_MAX_CELLS-1 (the board's
 * 12-bit cell ids) and a parent parent[i] (-1 for a root). The DSP-RAM storage converts itself into this form; nothing here knows about it.
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

/* Cell ids the DSP's algorithms take (c5_tree_check .. c5_sched_feasible): the packet's and
 * the node's 12 bits (C5_MAX_CELLS in ray.h). Their per-cell arrays have one entry per cell
 * present in the tree, not per id. */
#define C5_SCHED_MAX_CELLS 4096

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
    C5_SPLIT_BOUNDED = 4,     /* ours, for the DSP: the rollout under a budget of counted DSP
                                 operations (dsp_cost.h). The cheap policy's schedule is the
                                 incumbent; at each peel without a full cell the other cells
                                 with a leaf are tried by rollout, pruned as soon as they
                                 cannot beat the incumbent (peels so far + sum of maxGen), and
                                 a shorter one replaces it. At the budget it stops and returns
                                 the incumbent (a complete schedule); the paper's rule runs
                                 first, and its schedule is returned when it is no longer.
                                 Never longer than rule 1 nor than the cheap policy (c5_sched_bounded). */
    C5_SPLIT_WINDOW = 5,      /* ours, for the DSP (cube5 schedule's default): the shortest of
                                 the paper's schedule, C5_SPLIT_SUBTREE's and a known one
                                 (c5_sched_window_from), then
                                 window after window of it (8, 16, 24, 32 loads) replaced by a
                                 shorter schedule of the nodes only that window can serve, found
                                 by the bounded rollout, within the DSP's budget
                                 (c5_sched_window). Never longer than rule 1. */
    C5_SPLIT_SUBTREE = 6,     /* ours: forward, the cell whose ready nodes head the largest
                                 subtrees (the sum of their node counts cubed) first
                                 (c5_sched_subtree); the window rule starts from it when it is
                                 shorter than the paper's. */
} c5_split_rule;

/* Where the window rule's sweeps stopped: round, width index, first load of the window. */
typedef struct {
    int round, width, lo;
} c5_window_cursor;

typedef struct {
    int len;                 /* schedule length */
    int *cells;              /* FORWARD schedule (load order), len entries, malloc'd (never NULL) */
    int peels_completion, peels_split;
    uint64_t nodes_examined; /* node visits by the algorithm (the paper's cost measure) */
    int max_gen;             /* largest generation */
    uint64_t dsp_ops;        /* the DSP's operations for it (dsp_cost.h): preparation, peels and
                                simulations, writing the schedule out */
    int gave_up;             /* C5_SPLIT_BOUNDED: 1 when the budget stopped the search */
    int fell_back;           /* C5_SPLIT_BOUNDED, C5_SPLIT_WINDOW: 1 when the paper's rule's schedule
                                was returned (the search found nothing shorter) */
    int warm;                /* c5_sched_window_from: 1 when it started from the warm schedule */
    int subtree;             /* the window rule: 1 when it started from C5_SPLIT_SUBTREE's schedule */
    c5_window_cursor cursor; /* the window rule: where a search that starts from this schedule
                                goes on (c5_sched_window_resume) */
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
/* The same, giving up once more than max_examined nodes were examined (0: no cap; checked
 * before each simulated candidate, so it overshoots by at most one simulation): 1 when it
 * gave up (*out then has len 0), 0 with the schedule, -1 on error. The lookahead and rollout
 * rules' cost grows with the cells and the peels (docs/cell-tree.md); the report caps them. */
int c5_sched_celltree_capped(const c5_dep_tree *t, c5_split_rule rule, uint64_t max_examined, c5_schedule *out,
                             c5_err *err);

/* C5_SPLIT_BOUNDED with a budget of budget_ops DSP operations (dsp_cost.h) for the rule
 * itself, preparation included. Deterministic: the budget is counted operations, checked
 * before each peel against the peel's worst case and the undo it would need, so out->dsp_ops
 * never exceeds the budget, except that the paper's rule always runs (it is the fallback):
 * a budget below its cost gives its schedule at its cost (out->gave_up 1, fell_back 1).
 * budget_ops 0: no budget. Properties (tests/test_tree_bounded.c): feasible, never longer
 * than C5_SPLIT_MOST_LEAVES (ties: its schedule is returned), never longer than the cheap
 * policy (full cells first, lowest ready, else most leaves) once that policy's first run
 * fits the budget; a budget that does not bind gives the unbounded run's schedule; the same
 * tree and budget give the same schedule and count. */
int c5_sched_bounded(const c5_dep_tree *t, uint64_t budget_ops, c5_schedule *out, c5_err *err);

/* C5_SPLIT_SUBTREE (tree_subtree.c): feasible for any checked tree, deterministic (ties: the
 * lowest cell id), out->dsp_ops its counted cost, O((n + loads) log cells). */
int c5_sched_subtree(const c5_dep_tree *t, c5_schedule *out, c5_err *err);
/* The most c5_sched_subtree counts on a tree of n nodes over m cells (checked before it runs). */
uint64_t c5_sched_subtree_worst(int n, int m);

/* C5_SPLIT_WINDOW (tree_window.c) with a budget of budget_ops DSP operations (dsp_cost.h)
 * for the rule, the paper's rule included (0: no budget). The paper's rule always runs; each
 * step after it (the loads' positions of every node, a window's forest, the search in it)
 * runs only when its worst case fits what is left, and the search holds its share, so
 * out->dsp_ops <= budget_ops unless the paper's rule alone costs more. out->gave_up: the
 * budget ended the sweeps; fell_back: the paper's schedule was returned (nothing shorter
 * found); peels: the paper's run's. Feasible, never longer than C5_SPLIT_MOST_LEAVES,
 * deterministic (tests/test_tree_bounded.c). */
int c5_sched_window(const c5_dep_tree *t, uint64_t budget_ops, c5_schedule *out, c5_err *err);
/* The same starting from `warm` (cell ids, warm_len loads) instead of the paper's schedule when
 * it is shorter and every node embeds in it (loads of cells absent from the tree dropped):
 * the cells the frame that built the tree fetched are such a schedule. out->warm: it was
 * taken. The same guarantees. */
/* The same, its sweeps starting where a search stopped (from: a c5_schedule's cursor, NULL: the
 * start), for a search that goes on with more budget over several calls: with the previous
 * call's schedule as the warm start, the windows it already tried are not tried again first.
 * Any cursor gives a feasible schedule with the guarantees above. */
int c5_sched_window_resume(const c5_dep_tree *t, uint64_t budget_ops, const int *warm, int warm_len,
                           const c5_window_cursor *from, c5_schedule *out, c5_err *err);
int c5_sched_window_from(const c5_dep_tree *t, uint64_t budget_ops, const int *warm, int warm_len, c5_schedule *out,
                         c5_err *err);

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
 * of memory. Entries that are no node's cell are loads that serve no node. */
int c5_sched_feasible(const c5_dep_tree *t, const int *sched, int len);

/* ---- internal: the bounded search, for c5_sched_window (tree_window.c) -------------------- */

/* c5_sched_bounded with a target and without the paper's fallback, for c5_sched_window
 * (tree_sched.c says how). */
int c5_sched_bounded_core(const c5_dep_tree *t, uint64_t budget_ops, int stop, int with_paper, c5_schedule *out,
                          c5_err *err);

#endif
