/* The bounded rollout (C5_SPLIT_BOUNDED, rtl_model/dsp/tree_sched.c), the window rule
 * (C5_SPLIT_WINDOW, rtl_model/dsp/tree_window.c) and the DSP's operation count
 * (rtl_model/dsp/dsp_cost.h): feasible, never longer than the paper's rule, deterministic, within
 * their budget, and the paper's schedule when the budget is too small. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "dsp_cost.h"
#include "harness.h"
#include "rng.h"
#include "tree_fixtures.h"
#include "tree_sched.h"

/* What the bounded rule may spend beyond its budget: only the paper's rule, which always
 * runs (preparation and peels: its own dsp_ops), the undo of its peels, one pick of the
 * cheap policy (trees of at most 64 cells: one bitset word) and the schedule written out. */
static uint64_t fallback_cost(const c5_dep_tree *t, const c5_schedule *paper)
{
    return paper->dsp_ops + (uint64_t)t->n * (C5_OPS_RESTORE + 2 * C5_OPS_MARK) + 4 * C5_OPS_WORD +
           66 * C5_OPS_CANDIDATE + 2 * (uint64_t)paper->len;
}

TEST(tree_bounded_random)
{
    uint64_t rng = 0xb0dedull;
    static int par[400], cel[400];
    int shorter = 0, trees = 0;
    c5_err err;
    for (int it = 0; it < 3000; it++) {
        int n = c5t_random_tree(&rng, 1 + (int)(c5_splitmix64(&rng) % 120), 2 + (int)(c5_splitmix64(&rng) % 6),
                                3 + (int)(c5_splitmix64(&rng) % 6), par, cel);
        c5_dep_tree t = {n, par, cel};
        c5_schedule paper, free_run;
        CHECK_INT(c5_sched_celltree(&t, C5_SPLIT_MOST_LEAVES, &paper, &err), 0);
        CHECK_INT(c5_sched_bounded(&t, 0, &free_run, &err), 0);
        CHECK(!free_run.gave_up);
        CHECK_MSG(c5_sched_feasible(&t, free_run.cells, free_run.len) == 1, "tree %d: infeasible", it);
        CHECK_MSG(free_run.len <= paper.len, "tree %d: %d loads, the paper's rule %d", it, free_run.len, paper.len);
        CHECK_INT(free_run.peels_completion + free_run.peels_split, free_run.len);
        shorter += free_run.len < paper.len;
        trees++;
        /* Budgets from nothing to the unbounded run's cost: feasible, no longer than the
         * paper's rule, within the budget or only what the fallback costs. */
        for (int k = 0; k < 3; k++) {
            uint64_t b = 1 + c5_splitmix64(&rng) % (free_run.dsp_ops + 1);
            c5_schedule s;
            CHECK_INT(c5_sched_bounded(&t, b, &s, &err), 0);
            CHECK_MSG(c5_sched_feasible(&t, s.cells, s.len) == 1, "tree %d budget %llu: infeasible", it,
                      (unsigned long long)b);
            CHECK(s.len <= paper.len);
            CHECK_MSG(s.dsp_ops <= b || (s.gave_up && s.fell_back && s.dsp_ops <= fallback_cost(&t, &paper)),
                      "tree %d (%d nodes): %llu ops against a budget of %llu (gave up %d, fell back %d, paper %llu)",
                      it, n, (unsigned long long)s.dsp_ops, (unsigned long long)b, s.gave_up, s.fell_back,
                      (unsigned long long)paper.dsp_ops);
            if (!s.gave_up) /* the budget did not bind: the unbounded run */
                CHECK(s.len == free_run.len && !memcmp(s.cells, free_run.cells, sizeof *s.cells * (size_t)s.len));
            c5_schedule_free(&s);
        }
        c5_schedule_free(&paper);
        c5_schedule_free(&free_run);
    }
    /* the rule does something: shorter than the paper's on some trees */
    CHECK_MSG(shorter > trees / 50, "shorter than the paper's rule on %d of %d trees", shorter, trees);
}

TEST(tree_bounded_tiny_budget_is_the_paper)
{
    uint64_t rng = 0x7e57ull;
    static int par[300], cel[300];
    c5_err err;
    for (int it = 0; it < 200; it++) {
        int n = c5t_random_tree(&rng, 50 + (int)(c5_splitmix64(&rng) % 200), 4, 6, par, cel);
        c5_dep_tree t = {n, par, cel};
        c5_schedule paper, s;
        CHECK_INT(c5_sched_celltree(&t, C5_SPLIT_MOST_LEAVES, &paper, &err), 0);
        CHECK_INT(c5_sched_bounded(&t, 1, &s, &err), 0);
        CHECK(s.gave_up && s.fell_back);
        CHECK_INT(s.len, paper.len);
        CHECK(!memcmp(s.cells, paper.cells, sizeof *s.cells * (size_t)s.len));
        CHECK_INT(s.peels_completion, paper.peels_completion);
        c5_schedule_free(&paper);
        c5_schedule_free(&s);
    }
}

TEST(tree_bounded_deterministic)
{
    uint64_t rng = 0xde7ull;
    static int par[2000], cel[2000];
    c5_err err;
    int n = c5t_random_tree(&rng, 1500, 27, 8, par, cel);
    c5_dep_tree t = {n, par, cel};
    uint64_t budgets[3] = {0, C5_DSP_SCHED_BUDGET_OPS, 400000};
    for (int k = 0; k < 3; k++) {
        c5_schedule a, b;
        CHECK_INT(c5_sched_bounded(&t, budgets[k], &a, &err), 0);
        CHECK_INT(c5_sched_bounded(&t, budgets[k], &b, &err), 0);
        CHECK_INT(a.len, b.len);
        CHECK(a.dsp_ops == b.dsp_ops && a.nodes_examined == b.nodes_examined);
        CHECK(a.gave_up == b.gave_up && a.fell_back == b.fell_back);
        CHECK(!memcmp(a.cells, b.cells, sizeof *a.cells * (size_t)a.len));
        c5_schedule_free(&a);
        c5_schedule_free(&b);
    }
}

/* A rule as the DSP runs it on 8,191-node random trees over each of the cell counts:
 * export, rule and write-back within C5_DSP_SCHED_BUDGET_OPS (and the paper's rule too,
 * with paper_too), feasible, no longer than the paper's rule. pool: the cell ids drawn. */
static void check_within_budget_big(uint64_t rng, c5_split_rule rule, const int *pool, const int *sizes, int nsizes,
                                    int paper_too)
{
    static int par[8191], cel[8191];
    c5_err err;
    for (int k = 0; k < nsizes; k++) {
        int n = c5t_random_tree_wide(&rng, 8191, pool, sizes[k], 8, par, cel);
        c5_dep_tree t = {n, par, cel};
        uint64_t io = (uint64_t)n * (C5_OPS_NODE_READ + C5_OPS_NODE_WRITE);
        c5_schedule s, paper;
        CHECK_INT(c5_sched_celltree(&t, rule, &s, &err), 0);
        CHECK_INT(c5_sched_celltree(&t, C5_SPLIT_MOST_LEAVES, &paper, &err), 0);
        if (paper_too)
            CHECK_MSG(io + paper.dsp_ops <= C5_DSP_SCHED_BUDGET_OPS, "%d cells: the paper's rule %llu ops", sizes[k],
                      (unsigned long long)(io + paper.dsp_ops));
        CHECK_MSG(io + s.dsp_ops <= C5_DSP_SCHED_BUDGET_OPS, "%d cells: %llu ops", sizes[k],
                  (unsigned long long)(io + s.dsp_ops));
        CHECK(s.len <= paper.len && c5_sched_feasible(&t, s.cells, s.len) == 1);
        c5_schedule_free(&s);
        c5_schedule_free(&paper);
    }
}

/* The rule as the DSP runs it (c5_sched_celltree): its share of the budget on the largest
 * trees the RAM holds, 8191 nodes over 27 and 64 cells; and the paper's rule fits the same
 * budget with export and write-back. (Over 4096 cell ids the paper's rule alone costs more:
 * its bitset scans grow with the cells; docs/cell-tree.md.) */
TEST(tree_bounded_within_budget_big)
{
    static int pool[4096];
    for (int i = 0; i < 4096; i++)
        pool[i] = i;
    check_within_budget_big(0xb16ull, C5_SPLIT_BOUNDED, pool, (const int[]){27, 64}, 2, 1);
}

/* The window rule (C5_SPLIT_WINDOW, rtl_model/dsp/tree_window.c): feasible, never longer than the
 * paper's rule, within its budget (but for the paper's rule, which always runs), the same
 * schedule and count for the same tree and budget. Budgets from nothing to the unbounded
 * run's cost. */
TEST(tree_window_random)
{
    uint64_t rng = 0x3a7d0ull;
    static int par[400], cel[400];
    int shorter = 0, trees = 0;
    c5_err err;
    for (int it = 0; it < 800; it++) {
        int n = c5t_random_tree(&rng, 1 + (int)(c5_splitmix64(&rng) % 160), 2 + (int)(c5_splitmix64(&rng) % 10),
                                3 + (int)(c5_splitmix64(&rng) % 8), par, cel);
        c5_dep_tree t = {n, par, cel};
        c5_schedule paper, free_run, again;
        CHECK_INT(c5_sched_celltree(&t, C5_SPLIT_MOST_LEAVES, &paper, &err), 0);
        CHECK_INT(c5_sched_window(&t, 0, &free_run, &err), 0);
        CHECK(!free_run.gave_up);
        CHECK_MSG(c5_sched_feasible(&t, free_run.cells, free_run.len) == 1, "tree %d: infeasible", it);
        CHECK_MSG(free_run.len <= paper.len, "tree %d: %d loads, the paper's rule %d", it, free_run.len, paper.len);
        CHECK_INT(free_run.fell_back, free_run.len == paper.len);
        CHECK_INT(c5_sched_window(&t, 0, &again, &err), 0);
        CHECK(again.len == free_run.len && again.dsp_ops == free_run.dsp_ops &&
              !memcmp(again.cells, free_run.cells, sizeof *again.cells * (size_t)again.len));
        c5_schedule_free(&again);
        shorter += free_run.len < paper.len;
        trees++;
        for (int k = 0; k < 3; k++) {
            uint64_t b = 1 + c5_splitmix64(&rng) % (free_run.dsp_ops + 1);
            c5_schedule s, s2;
            CHECK_INT(c5_sched_window(&t, b, &s, &err), 0);
            CHECK_MSG(c5_sched_feasible(&t, s.cells, s.len) == 1, "tree %d budget %llu: infeasible", it,
                      (unsigned long long)b);
            CHECK(s.len <= paper.len);
            /* over the budget only when the paper's rule alone (its peels, its schedule
             * written out) costs more */
            CHECK_MSG(s.dsp_ops <= b || (s.gave_up && s.fell_back && s.dsp_ops <= paper.dsp_ops + (uint64_t)paper.len),
                      "tree %d (%d nodes): %llu ops against a budget of %llu (paper %llu)", it, n,
                      (unsigned long long)s.dsp_ops, (unsigned long long)b, (unsigned long long)paper.dsp_ops);
            CHECK_INT(c5_sched_window(&t, b, &s2, &err), 0);
            CHECK(s2.len == s.len && s2.dsp_ops == s.dsp_ops && s2.gave_up == s.gave_up &&
                  !memcmp(s2.cells, s.cells, sizeof *s.cells * (size_t)s.len));
            c5_schedule_free(&s);
            c5_schedule_free(&s2);
        }
        c5_schedule_free(&paper);
        c5_schedule_free(&free_run);
    }
    CHECK_MSG(shorter > trees / 10, "shorter than the paper's rule on %d of %d trees", shorter, trees);
}

/* As the DSP runs it (c5_sched_celltree: its share of the budget) on the largest trees the
 * RAM holds, 8191 nodes over 27 and 64 cells, and over cell ids up to 4095: export, rule and
 * write-back within C5_DSP_SCHED_BUDGET_OPS, feasible, no longer than the paper's. */
TEST(tree_window_within_budget_big)
{
    static int pool[4096];
    for (int i = 0; i < 4096; i++)
        pool[i] = (i * 2654435761u) % 4096; /* distinct ids, not in order */
    check_within_budget_big(0xb17ull, C5_SPLIT_WINDOW, pool, (const int[]){27, 64, 200}, 3, 0);
}

/* The window rule's warm start (c5_sched_window_from): a shorter schedule that serves every
 * node is taken (the result no longer than it), loads of cells absent from the tree are
 * dropped, and one that misses a node is refused for the paper's. */
TEST(tree_window_warm_start)
{
    uint64_t rng = 0x3a53ull;
    static int par[300], cel[300], warm[700];
    int taken = 0, refused = 0;
    c5_err err;
    for (int it = 0; it < 300; it++) {
        int n = c5t_random_tree(&rng, 20 + (int)(c5_splitmix64(&rng) % 150), 3 + (int)(c5_splitmix64(&rng) % 8),
                                4 + (int)(c5_splitmix64(&rng) % 6), par, cel);
        c5_dep_tree t = {n, par, cel};
        c5_schedule paper, roll, sub, s;
        CHECK_INT(c5_sched_celltree(&t, C5_SPLIT_MOST_LEAVES, &paper, &err), 0);
        CHECK_INT(c5_sched_celltree(&t, C5_SPLIT_ROLLOUT, &roll, &err), 0);
        CHECK_INT(c5_sched_subtree(&t, &sub, &err), 0);
        /* the window rule starts from the shortest of the paper's, the largest-subtree and
         * the warm schedule (no budget: each is tried) */
        int start = sub.len < paper.len ? sub.len : paper.len;
        c5_schedule_free(&sub);
        /* the rollout's schedule with loads of a cell no node has (id 4000) between its loads */
        int k = 0;
        for (int j = 0; j < roll.len; j++) {
            if (c5_splitmix64(&rng) % 4 == 0)
                warm[k++] = 4000;
            warm[k++] = roll.cells[j];
        }
        CHECK_INT(c5_sched_window_from(&t, 0, warm, k, &s, &err), 0);
        CHECK(c5_sched_feasible(&t, s.cells, s.len) == 1 && s.len <= start && s.len <= roll.len);
        if (roll.len < start) {
            CHECK_MSG(s.warm && s.len <= roll.len, "tree %d: warm %d, %d loads, the warm schedule %d", it, s.warm,
                      s.len, roll.len);
            taken++;
        }
        c5_schedule_free(&s);
        /* without its first load the first root's cell misses a node, unless it is loaded
         * again later: then either way the result must be feasible */
        if (roll.len > 1 && roll.len - 1 < start) {
            CHECK_INT(c5_sched_window_from(&t, 0, roll.cells + 1, roll.len - 1, &s, &err), 0);
            int ok = c5_sched_feasible(&t, roll.cells + 1, roll.len - 1);
            CHECK(c5_sched_feasible(&t, s.cells, s.len) == 1 && s.len <= start);
            CHECK_INT(s.warm, ok);
            refused += !ok;
            c5_schedule_free(&s);
        }
        c5_schedule_free(&paper);
        c5_schedule_free(&roll);
    }
    CHECK_MSG(taken > 20 && refused > 20, "taken %d, refused %d", taken, refused);
}
