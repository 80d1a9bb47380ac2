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
/* The offline bounds and the exact and beam searches (tree_bound.c, tree_exact.c) work on
 * 64-bit cell masks: they take trees whose cell ids are all below 64 and refuse others
 * (c5_tree_bound_cells). */
#define C5_BOUND_MAX_CELLS 64
#define C5_GROUP_MAX 8 /* largest group of cells c5_sched_lower_bound_groups projects onto */

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
    C5_SPLIT_WINDOW = 5,      /* ours, for the DSP (cube5 schedule's default): the paper's
                                 schedule (or a shorter known one, c5_sched_window_from), then
                                 window after window of it (8, 16, 24, 32 loads) replaced by a
                                 shorter schedule of the nodes only that window can serve, found
                                 by the bounded rollout, within the DSP's budget
                                 (c5_sched_window). Never longer than rule 1. */
} c5_split_rule;

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

/* ---- internal: tree_bound.c for tree_exact.c ---------------------------------------------- */

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

/* c5_sched_bounded with a target and without the paper's fallback, for c5_sched_window
 * (tree_sched.c says how). */
int c5_sched_bounded_core(const c5_dep_tree *t, uint64_t budget_ops, int stop, int with_paper, c5_schedule *out,
                          c5_err *err);

int c5_group_opt(c5_group *g, const uint64_t *downset, int *exact);
int c5_sched_bound_partition(const c5_dep_tree *t, int max_group, long budget, uint64_t *groups_out,
                             int *ngroups_out);

#endif
