/* The DSP between two frames: the Cell Tree of frame i, as left in its RAM, turned into the
 * cell schedule that frame i+1 follows (Section 3.3), with the bounds that say how good
 * that schedule is (Section 3.4) and what it cost to make. docs/cell-tree.md. */
#ifndef C5_DSP_SCHED_H
#define C5_DSP_SCHED_H

#include "cell_tree.h"
#include "cell_tree_sdram.h"
#include "err.h"
#include "tree_sched.h"

/* The report's cap on the other rules' work above 64 cells (nodes examined; a few seconds of
 * host time, docs/cell-tree.md). */
#define C5_DSP_REPORT_MAX_EXAMINED 50000000ull

/* The report's local search (docs/cell-tree.md, "Bounds": about 10-40 s a 27-cell tree). */
#define C5_DSP_LOCAL_WINDOW 45
#define C5_DSP_LOCAL_STATES 50000
/* Then the local walk (c5_sched_local_walk) from the shorter of the two: windows of 20..40
 * loads, 20,000 states each, 500 steps from a fixed seed (docs/cell-tree.md, "Bounds": the
 * walk shortens default 1/27 and lobster_tunnel 1/27 where the local search stops). */
#define C5_DSP_WALK_MIN 20
#define C5_DSP_WALK_MAX 40
#define C5_DSP_WALK_STATES 20000
#define C5_DSP_WALK_STEPS 500 /* the steps scripts/optimum-study.sh and sched-rules.sh ask for */
#define C5_DSP_WALK_SEED 1

struct c5_dsp_sched_result;
typedef struct c5_dsp_sched_opts {
    c5_split_rule rule; /* whose schedule the next frame follows; 0: C5_SPLIT_MOST_LEAVES */
    int all_rules;      /* also run the other rules, for their lengths (len_*); on trees with a
                           cell id >= C5_BOUND_MAX_CELLS (more than 64 cells) each under a cap of
                           C5_DSP_REPORT_MAX_EXAMINED nodes examined */
    /* The report's bounds (not the DSP's work): with exact_states > 0, the exact search,
     * and when it gives up, the best proven bound (its own, and the grid's slabs of cells
     * when split[] is given) and the best known schedule (beam search). Only on trees whose
     * cell ids are all below C5_BOUND_MAX_CELLS (64): otherwise r->exact_skipped. */
    long exact_states;  /* state budget of the exact optimum; 0: not computed */
    int exact_nodes;    /* largest tree the exact search is tried on */
    int split[3];       /* cells per axis (cell id = x + nx (y + ny z)); 0: no slab bound */
    int beam_width;     /* beam of the best known schedule; 0: 200 */
    int local_window;   /* the local search on the beam's schedule (c5_sched_local_search):
                           windows of 2/3 of this many loads, then of this many, each solved
                           within C5_DSP_LOCAL_STATES states, then the local walk from the
                           shorter result (walk_steps); 0: C5_DSP_LOCAL_WINDOW; < 0: both
                           off */
    int walk_steps;     /* steps of the local walk (C5_DSP_WALK_*; minutes on 27-cell trees);
                           0: none */
    /* An overflowed (frozen) tree: 0, no schedule (the next frame runs Max Work); 1, the
     * schedule of what it holds, the dependencies of the rays tagged before the RAM filled
     * (the next frame follows it, then Max Work). No other rules or bounds are computed for
     * a partial tree: they would describe a part of the frame. docs/cell-tree.md, "Overflow". */
    int partial;
    /* A schedule of this tree known beside the paper's, for the window rule to start from
     * when shorter: the cells the frame that built the tree fetched (NULL: none). Checked
     * before use (c5_sched_window_from). */
    const int *warm;
    int warm_len;
    /* The window rule's budget of DSP operations (0: c5_dsp_rule_budget, the on-chip tree's
     * between-frame budget); the SDRAM tree's is c5_dsp_sdram_budget. */
    uint64_t rule_budget;
    /* The window rule resumes its sweeps there (c5_sched_window_resume; NULL: from the start):
     * where the DSP's refinement of the same tree stopped (c5_dsp_refine). */
    const c5_window_cursor *resume;
    /* The offline report beside the schedule (analysis/sched_report.h, c5_dsp_sched_report:
     * the other rules and the bounds above), run on the exported tree; NULL: none. The DSP
     * computes none of it on the board, so the DSP's code does not depend on the analysis:
     * the caller that wants the report hands it in. */
    int (*report)(const c5_dep_tree *dt, c5_split_rule rule, const struct c5_dsp_sched_opts *o,
                  struct c5_dsp_sched_result *r, c5_err *err);
} c5_dsp_sched_opts;

typedef struct c5_dsp_sched_result {
    int nodes, slots, overflow; /* the tree as found in the RAM */
    int lower_bound;            /* the best proven bound on the optimum (tree_sched.h) */
    int best_known;             /* the shortest schedule known: the optimum when found, else the
                                 * shorter of the beam search and the window rule without a
                                 * budget (offline); 0: not computed */
    int sum_maxgen;             /* the simplest proven bound: every cell maxGen times */
    int paper_bound;            /* Section 3.4's formula: NOT a bound (docs/cell-tree.md) */
    int optimum;                /* shortest feasible schedule; -1: not computed (budget, overflow,
                                 * or exact_skipped) */
    int exact_skipped;          /* 1: exact_states > 0, but the tree has a cell id >= C5_BOUND_MAX_CELLS
                                 * (more than 64 cells), so the exact search, the bounds beyond the
                                 * sum of maxGen and the beam search were not run: lower_bound is
                                 * the sum of maxGen, optimum -1, best_known 0 */
    int len_paper, len_lookahead, len_rollout; /* schedule length under each rule; 0: not run;
                                                * -1: gave up at the cap (all_rules) */
    int len_bounded;            /* the same for C5_SPLIT_BOUNDED (never capped: its own budget) */
    int len_window;             /* the same for C5_SPLIT_WINDOW (never capped: its own budget) */
    int len_subtree;            /* the same for C5_SPLIT_SUBTREE (never capped: O(n log cells)) */
    /* The DSP's operations between frames for the chosen rule (dsp_cost.h): reading the tree
     * out of the RAM, the rule, writing generations and ready flags back; their sum against
     * C5_DSP_SCHED_BUDGET_OPS. bounded_gave_up / bounded_fell_back: the chosen rule
     * (C5_SPLIT_BOUNDED or C5_SPLIT_WINDOW) stopped at its budget / returned the paper's
     * rule's schedule. */
    uint64_t dsp_ops_export, dsp_ops_rule, dsp_ops_writeback, dsp_ops_schedule;
    int bounded_gave_up, bounded_fell_back;
    int peels_completion, peels_split; /* of the chosen rule */
    uint64_t nodes_examined;    /* of the chosen rule */
    int max_gen;
    double sched_wall_s;        /* host time of the DSP's work: read the tree, the chosen rule, write back */
    double exact_wall_s;        /* host time of the exact search */
    c5_schedule next;           /* the chosen rule's schedule; empty when the tree overflowed
                                 * (unless opts.partial) */
} c5_dsp_sched_result;

/* Schedules from tree t (and writes the generations and ready flags into its RAM). An
 * overflowed tree is scheduled only with o->partial; otherwise r->next is empty, so the next
 * frame runs Max Work. */
int c5_dsp_schedule(c5_ctree *t, const c5_dsp_sched_opts *o, c5_dsp_sched_result *r, c5_err *err);
/* The same for the tree in the DSP's SDRAM: read in slots, written back per node, at the SDRAM
 * weights (cell_tree_sdram.h); a frozen tree gives no schedule. The generations the write-back
 * stores are checked against the node's field. */
int c5_dsp_schedule_sdram(const c5_sdram_tree *t, const c5_dsp_sched_opts *o, c5_dsp_sched_result *r, c5_err *err);

/* One rule as the DSP runs it (the window rule from o->warm when there is one), or under a
 * cap of nodes examined (0: none) for the report; 0, 1 when over the cap, -1 on error. */
int c5_dsp_run_rule(const c5_dep_tree *dt, c5_split_rule rule, uint64_t cap, const c5_dsp_sched_opts *o,
                    c5_schedule *out, c5_err *err);
void c5_dsp_sched_free(c5_dsp_sched_result *r);

/* The DSP's rule for the unit of the next frame's tree when a tree outgrows its RAM: the
 * cells a group holds per axis, doubled after a frame whose tree (over groups of `group`)
 * overflowed, up to the largest axis of the split; unchanged otherwise. Coarser groups
 * make a tree of fewer nodes that still orders the groups; the next frame works off each
 * group Max Work among its cells (docs/results/cell-tree-studies.md, "Overflow policies": measured
 * against a frozen tree's partial schedule and against Max Work). */
int c5_dsp_next_group(int group, int overflowed, const int cells[3]);

/* The DSP's work during a frame, between its tags (the tree in SDRAM; docs/cell-tree.md, "Where
 * the tree lives"): the window rule goes on shortening `from`, the schedule the frame follows,
 * on the tree `from` was made from, where from's search stopped, within `budget` operations
 * (the DSP's idle time in the frame). The next schedule starts from the result when the next
 * tree is the same (the same camera registers). 0, or -1 with a message. */
int c5_dsp_refine(const c5_dep_tree *dt, uint64_t budget, const c5_schedule *from, c5_schedule *out, c5_err *err);

/* Where the DSP keeps the tree of frame `frame` of a split of `cells` cells (the default,
 * --tree-ram auto; docs/cell-tree.md, "Where the tree lives"): the first frame's tree on chip
 * up to C5_DSP_ONCHIP_MAX_CELLS cells, in SDRAM beyond; a later frame's in SDRAM once the
 * previous frame's was there or overflowed the on-chip RAM. 1: SDRAM. */
#define C5_DSP_ONCHIP_MAX_CELLS 64
int c5_dsp_tree_in_sdram(int cells, int frame, int prev_sdram, int prev_overflow);

#endif
