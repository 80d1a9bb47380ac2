/* The largest-subtree rule (C5_SPLIT_SUBTREE, rtl_model/dsp/tree_subtree.c) and the window
 * rule's start from it (rtl_model/dsp/tree_window.c). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rng.h"
#include "tree_fixtures.h"
#include "tree_sched.h"

/* Cell 1 holds three ready leaves, cell 0 one root with a chain 0-1-0-1 below it: a count of
 * ready nodes (Max Work's measure) loads cell 1 first and needs 5 loads (1 0 1 0 1); the
 * subtree rule weighs the root 4^3 = 64 against 1 + 1 + 1 and needs 4 (0 1 0 1), the
 * optimum. Then a tie: two roots of one node each in cells 7 and 3 go lowest id first. */
TEST(tree_subtree_by_hand)
{
    int par[] = {-1, 0, 1, 2, -1, -1, -1};
    int cel[] = {0, 1, 0, 1, 1, 1, 1};
    c5_dep_tree t = {7, par, cel};
    c5_schedule s;
    c5_err err;
    CHECK_INT(c5_sched_subtree(&t, &s, &err), 0);
    int want[] = {0, 1, 0, 1};
    CHECK_INT(s.len, 4);
    for (int k = 0; k < s.len && k < 4; k++)
        CHECK_INT(s.cells[k], want[k]);
    CHECK_INT(c5t_brute_opt(&t), 4);
    CHECK(s.dsp_ops > 0);
    c5_schedule_free(&s);

    int par2[] = {-1, -1};
    int cel2[] = {7, 3};
    c5_dep_tree t2 = {2, par2, cel2};
    CHECK_INT(c5_sched_subtree(&t2, &s, &err), 0);
    CHECK_INT(s.len, 2);
    CHECK_INT(s.cells[0], 3);
    CHECK_INT(s.cells[1], 7);
    c5_schedule_free(&s);

    c5_dep_tree empty = {0, par, cel};
    CHECK_INT(c5_sched_subtree(&empty, &s, &err), 0);
    CHECK_INT(s.len, 0);
    c5_schedule_free(&s);
}

/* On random trees, narrow and wide (cell ids up to 4095): feasible, every load serves a
 * node (no more loads than nodes), deterministic, never below the lower bound, the optimum
 * on tiny trees; its count within the worst case the window rule checks before running it. */
TEST(tree_subtree_random)
{
    uint64_t rng = 0x5b7eeull;
    static int par[600], cel[600], pool[64];
    c5_err err;
    for (int it = 0; it < 2000; it++) {
        int n;
        if (it % 2) {
            n = c5t_random_tree(&rng, 2 + (int)(c5_splitmix64(&rng) % 300), 2 + (int)(c5_splitmix64(&rng) % 20),
                                2 + (int)(c5_splitmix64(&rng) % 10), par, cel);
        } else {
            int np = 2 + (int)(c5_splitmix64(&rng) % 60);
            int off = (int)(c5_splitmix64(&rng) % C5_SCHED_MAX_CELLS);
            for (int k = 0; k < np; k++) /* distinct: 4093 is prime to 4096 */
                pool[k] = (off + 4093 * k) % C5_SCHED_MAX_CELLS;
            n = c5t_random_tree_wide(&rng, 2 + (int)(c5_splitmix64(&rng) % 598), pool, np,
                                     2 + (int)(c5_splitmix64(&rng) % 12), par, cel);
        }
        c5_dep_tree t = {n, par, cel};
        if (c5_tree_check(&t, &err) != 0)
            continue;
        c5_schedule a, b;
        CHECK_INT(c5_sched_subtree(&t, &a, &err), 0);
        CHECK_INT(c5_sched_subtree(&t, &b, &err), 0);
        CHECK_MSG(c5_sched_feasible(&t, a.cells, a.len) == 1, "tree %d: not feasible", it);
        CHECK(a.len <= n && a.len >= c5_sched_sum_maxgen(&t));
        CHECK(a.len == b.len && memcmp(a.cells, b.cells, (size_t)a.len * sizeof *a.cells) == 0 &&
              a.dsp_ops == b.dsp_ops);
        int m = 0, seen[C5_SCHED_MAX_CELLS] = {0};
        for (int i = 0; i < n; i++)
            m += !seen[cel[i]]++;
        uint64_t worst = c5_sched_subtree_worst(n, m);
        CHECK_MSG(a.dsp_ops <= worst, "tree %d: %llu ops, worst %llu", it, (unsigned long long)a.dsp_ops,
                  (unsigned long long)worst);
        if (it % 2 && n <= 14 && m <= 6) /* brute force: narrow ids only */
            CHECK(a.len >= c5t_brute_opt(&t));
        c5_schedule_free(&a);
        c5_schedule_free(&b);
    }
}

/* The window rule without a budget is never longer than the subtree rule's schedule (it
 * starts from it when shorter than the paper's, and keeps the shorter of that search and one
 * from the paper's), and says which start it kept; with a budget below the subtree rule's
 * worst case it does not run it. Wide trees of a few hundred nodes, where the
 * subtree rule is often the shorter. */
TEST(tree_subtree_window_start)
{
    uint64_t rng = 0x7a11ull;
    static int par[800], cel[800], pool[200];
    int started = 0;
    c5_err err;
    for (int it = 0; it < 200; it++) {
        int np = 40 + (int)(c5_splitmix64(&rng) % 160);
        int off = (int)(c5_splitmix64(&rng) % C5_SCHED_MAX_CELLS);
        for (int k = 0; k < np; k++)
            pool[k] = (off + 4093 * k) % C5_SCHED_MAX_CELLS;
        int n = c5t_random_tree_wide(&rng, 200 + (int)(c5_splitmix64(&rng) % 600), pool, np,
                                     4 + (int)(c5_splitmix64(&rng) % 12), par, cel);
        c5_dep_tree t = {n, par, cel};
        if (c5_tree_check(&t, &err) != 0)
            continue;
        c5_schedule sub, paper, w;
        CHECK_INT(c5_sched_subtree(&t, &sub, &err), 0);
        CHECK_INT(c5_sched_celltree(&t, C5_SPLIT_MOST_LEAVES, &paper, &err), 0);
        CHECK_INT(c5_sched_window_from(&t, 0, NULL, 0, &w, &err), 0);
        CHECK(c5_sched_feasible(&t, w.cells, w.len) == 1 && w.len <= sub.len && w.len <= paper.len);
        /* from the subtree rule's schedule only when it is the shorter start; a second search
         * from the paper's may win (c5_sched_window_resume) */
        CHECK(!w.subtree || sub.len < paper.len);
        started += w.subtree;
        c5_schedule_free(&w);
        /* a budget the paper's rule and the set-up already spend: no room for it */
        CHECK_INT(c5_sched_window_from(&t, paper.dsp_ops + 1, NULL, 0, &w, &err), 0);
        CHECK_INT(w.subtree, 0);
        CHECK(c5_sched_feasible(&t, w.cells, w.len) == 1 && w.len <= paper.len);
        c5_schedule_free(&w);
        c5_schedule_free(&sub);
        c5_schedule_free(&paper);
    }
    CHECK_MSG(started > 5 && started < 195, "the window rule started from the subtree rule on %d trees", started);
}
