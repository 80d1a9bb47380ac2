/* Offline analysis of Cell Tree schedules, not the DSP's work: lower bounds from projections
 * onto small groups of cells (tree_bound.c), the exact optimum and a beam search over interim
 * trees (tree_exact.c), and local search on a feasible schedule (tree_local.c). They measure
 * the DSP's schedules (`cube5 schedule`'s report, sched_report.c; docs/cell-tree.md); the board
 * never runs them. Trees as in tree_sched.h. */
#ifndef C5_TREE_ANALYSIS_H
#define C5_TREE_ANALYSIS_H

#include <stdint.h>

#include "err.h"
#include "tree_sched.h"

/* The offline bounds and the exact and beam searches work on 64-bit cell masks: they take
 * trees whose cell ids are all below 64 and refuse others (c5_tree_bound_cells). */
#define C5_BOUND_MAX_CELLS 64
#define C5_GROUP_MAX 8 /* largest group of cells c5_sched_lower_bound_groups projects onto */

/* ---- offline analysis (tree_bound.c, tree_exact.c): trees whose cell ids are all below
 * C5_BOUND_MAX_CELLS. The bounds below return -1 for any other tree; the searches fail with a
 * message naming the limit. */

/* 1 iff every cell id of t is in 0..C5_BOUND_MAX_CELLS-1. */
int c5_tree_bound_cells(const c5_dep_tree *t);

/* A lower bound on the optimum that rests on no unproven claim: the sum of maxGen improved
 * by the exact optima of two-cell projections, matched over disjoint pairs (tree_bound.c,
 * proofs there). At least c5_sched_sum_maxgen (hence at least the longest root-to-leaf
 * path: a path holds each cell c at most maxGen(c) times). Each pair's optimum is searched
 * within 100,000 memoized states; a pair over that budget is left out (never seen on the
 * board model's trees). -1 when out of memory. */
int c5_sched_lower_bound_pairs(const c5_dep_tree *t);

/* The same with groups of 2..max_group cells (at most C5_GROUP_MAX), each group's
 * optimum searched within `budget` memoized states. Packing the groups is exact up to 16
 * cells and a branch and bound with a node budget beyond (any packing is a valid bound).
 * Cost on the board's 27-cell trees (up to 3946 nodes): pairs 0.02 s, up to 3 cells 0.05-0.08
 * s, up to 4 0.1-0.4 s, up to 5 1-5 s. -1 when out of memory. */
int c5_sched_lower_bound_groups(const c5_dep_tree *t, int max_group, long budget);

/* The same claims with groups chosen by the caller, who may know which cells interact (the
 * board's cells are a grid: its slabs of 9 cells give the best bounds seen on 27-cell trees):
 * the sum over the disjoint groups (cell masks) of each projection's optimum, found by the
 * exact search (groups heuristic, at most max_states states per group) or, when the search
 * gives up, the bound it proved (c5_exact_stats.lower); cells in no group count their
 * maxGen. *all_exact (if not NULL): 1 when every group was solved. -1 when the groups
 * overlap or on error (out of memory). */
int c5_sched_lower_bound_split(const c5_dep_tree *t, const uint64_t *groups, int ngroups, long max_states,
                               int *all_exact);

/* A lower bound at any split (tree_block_bound.c, proof there): the grid of cells cut into
 * blocks of 4x4x4 cells, the sum over the blocks of a proven bound on the tree's restriction
 * to each block (matched pairs of cells, or the block's slabs: seconds at 4,096 cells). Cell ids are x + split[0] (y + split[1] z), below 4,096. At least
 * the sum of maxGen. -1 when a cell is outside the split or out of memory. */
int c5_sched_lower_bound_blocks(const c5_dep_tree *t, const int split[3]);
/* Exact optimum by A* over interim trees (tree_exact.c).
 * 1: found, *len_out = optimum (and, if sched_out != NULL, a malloc'd optimal forward
 *    schedule, never NULL);
 * 0: gave up because the search would store more than max_states states or the tree has
 *    more than max_nodes nodes;
 * -1: error (bad tree, out of memory).
 * Heuristic: the larger of the sum of maxGen (+1 when no cell is ready) and the sum, over
 * the groups of cells c5_sched_lower_bound_groups packs at the root (groups of up to 4
 * cells, fewer when C(cells, 4) * n exceeds about 1e8), of the state's projection's exact
 * optimum, memoized per group. Consistent; proofs in tree_exact.c and tree_bound.c. On the
 * board model's 8-cell trees it starts within 3 of the optimum and needs a few thousand
 * states (the sum of maxGen alone needed up to 450,000).
 * Memory budget: each stored state costs 8*ceil(n/64) bytes of node bitset plus about 50
 * bytes of bookkeeping (g, back pointer, action, hash, hash-table slots, heap entries), so
 * max_states = 200000 on a 200-node tree is about 16 MB; each group's memo stores at most
 * about max_states projected states of 8*ceil(trie/64) + 20 bytes (a few thousand on the
 * board's trees). Deterministic: no pointer hashing, no clock. */
int c5_sched_optimum(const c5_dep_tree *t, long max_states, int max_nodes, int *len_out, int **sched_out,
                     c5_err *err);
/* The same search without the rollout rule's schedule as an upper bound and with the sum of
 * maxGen as its only heuristic (the search as it was first written): slower, but its answer
 * depends on neither (the tests check the search alone with it). */
int c5_sched_optimum_plain(const c5_dep_tree *t, long max_states, int max_nodes, int *len_out, int **sched_out,
                           c5_err *err);

/* A short schedule, not a proof: beam search over interim trees (tree_exact.c), level by
 * level keeping the `width` states with the least heuristic (that of c5_sched_optimum), and
 * the rollout rule's schedule when that is shorter: never longer than C5_SPLIT_ROLLOUT.
 * Fills *len_out and a malloc'd forward schedule (if sched_out != NULL); 0, or -1 on error.
 * Stores at most width states per load; time about width * cells heuristic evaluations per
 * load. On the board model's 27-cell trees, width 1000 takes 0.1-3 s and is 0-10 loads
 * shorter than the rollout rule (on one tree the beam alone was 3 longer, hence the
 * minimum). */
int c5_sched_beam(const c5_dep_tree *t, int width, int *len_out, int **sched_out, c5_err *err);

/* The exact search with its knobs exposed (c5_sched_optimum: rollout bound on, default
 * groups; c5_sched_optimum_plain: both off). */
#define C5_EXACT_GROUPS_DEFAULT 4
typedef struct {
    long max_states;    /* as c5_sched_optimum */
    int max_nodes;      /* as c5_sched_optimum */
    int use_rollout_ub; /* the rollout rule's schedule as the initial upper bound */
    int group_max;      /* heuristic: projections onto groups of up to this many cells (the
                           packing of c5_sched_lower_bound_groups); < 2: sum of maxGen only */
    long group_budget;  /* memoized states per group (a group over it counts its sum of
                           maxGen from then on); 0: max_states */
    const uint64_t *groups; /* ngroups > 0: the heuristic's groups instead of the packing:
                               cell masks, up to C5_EXACT_MAX_PARTS partitions separated by
                               a 0 entry, each partition's groups disjoint (a partition
                               should cover every cell: one left out counts nothing); h is
                               the largest partition's sum, consistent as each is
                               (tree_exact.c) */
    int ngroups;
} c5_exact_opts;
#define C5_EXACT_MAX_PARTS 4
typedef struct {
    long states;   /* states stored */
    long expanded; /* states expanded */
    long memo;     /* projected states memoized by the heuristic */
    int root_h;    /* the heuristic at the root (a lower bound on the optimum) */
    int lower;     /* proven lower bound: the optimum when found; on giving up, the least f
                      still open (at least root_h) */
} c5_exact_stats;
int c5_sched_optimum_ex(const c5_dep_tree *t, const c5_exact_opts *o, int *len_out, int **sched_out,
                        c5_exact_stats *stats, c5_err *err);

/* c5_sched_beam with the search's knobs (max_states, max_nodes and use_rollout_ub unused:
 * the rollout rule's schedule is always the fallback). */
int c5_sched_beam_ex(const c5_dep_tree *t, const c5_exact_opts *o, int width, int *len_out, int **sched_out,
                     c5_err *err);

/* Local search (tree_local.c): shortens the feasible forward schedule sched[0..*len) in
 * place by solving windows of `window` consecutive loads exactly (the exact search within
 * max_states states a window; a window over budget is kept), the rest fixed, until no
 * window improves. Never longer than the start; every accepted schedule passes
 * c5_sched_feasible. Returns the loads saved (>= 0), or -1 with a message (infeasible start,
 * window < 2, a cell id >= C5_BOUND_MAX_CELLS, out of memory). */
int c5_sched_local_search(const c5_dep_tree *t, int *sched, int *len, int window, long max_states, c5_err *err);
/* Local walk (tree_local.c): `steps` windows of wmin..wmax loads at positions drawn from a
 * generator seeded with `seed`, each solved exactly (within max_states states) with the
 * cells renamed by a drawn permutation, and replaced when the answer is no longer than the
 * window: equally long answers move the schedule along a plateau of schedules of one length,
 * from which later windows find shorter ones that the local search, which takes only
 * shorter windows from a fixed start, does not reach. Never longer than the start; every
 * accepted schedule passes c5_sched_feasible; the same tree, start, knobs and seed give the
 * same schedule. Returns the loads saved (>= 0), or -1 with a message (infeasible start,
 * wmin < 2, wmax < wmin, steps < 0, a cell id >= C5_BOUND_MAX_CELLS, out of memory). */
int c5_sched_local_walk(const c5_dep_tree *t, int *sched, int *len, int wmin, int wmax, int steps, long max_states,
                        uint64_t seed, c5_err *err);

/* ---- internal: tree_bound.c for tree_exact.c and tree_local.c --------------------------- */

/* The projection of a tree onto a group of cells (a trie) and its memoized exact optimum. */
typedef struct c5_group c5_group;
c5_group *c5_group_new(const c5_dep_tree *t, uint64_t cells, long budget, int *map);
void c5_group_free(c5_group *g);
int c5_group_size(const c5_group *g);
int c5_group_words(const c5_group *g);
long c5_group_memo(const c5_group *g);
/* The trie as a tree (c5_group_size entries each; parent < index; a child may have its
 * parent's cell). */
void c5_group_tree(const c5_group *g, int *parent, int *cell);
/* The exact search on the projection of t onto `cells` (tree_exact.c); as
 * c5_sched_optimum_ex, without the rollout bound and without a schedule. */
int c5_sched_projection_optimum(const c5_dep_tree *t, uint64_t cells, const c5_exact_opts *o, int *len_out,
                                c5_exact_stats *stats, c5_err *err);


int c5_group_opt(c5_group *g, const uint64_t *downset, int *exact);
int c5_sched_bound_partition(const c5_dep_tree *t, int max_group, long budget, uint64_t *groups_out,
                             int *ngroups_out);

#endif
