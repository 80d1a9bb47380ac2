/* The exact optimum (rtl_model/analysis/tree_exact.c, A*) against an independent formulation: the
 * time-indexed integer program of tests/tree_ilp.c solved by GLPK, which shares no code with
 * the A*, its bounds or the feasibility test. An answer is confirmed when the program finds
 * a schedule of that length and proves that none is one shorter. */
#include <stdint.h>
#include <stdlib.h>

#include "harness.h"
#include "rng.h"
#include "tree_fixtures.h"
#include "tree_ilp.h"
#include "tree_analysis.h"

/* 1 iff the program confirms `claimed` as the optimum: a schedule of `claimed` loads exists
 * (the minimum over a horizon of `claimed` is exactly that) and none of claimed - 1 does. */
static int ilp_confirms(const c5_dep_tree *t, int claimed)
{
    int len = -1;
    if (claimed < 0 || c5t_ilp_optimum(t, claimed, &len, NULL) != 1 || len != claimed)
        return 0;
    return claimed == 0 || c5t_ilp_optimum(t, claimed - 1, &len, NULL) == 0;
}

/* The program's own optimum (horizon: the paper's rule, a feasible schedule), its schedule
 * feasible, and both A* searches agreeing. */
static void against_astar(const c5_dep_tree *t, const char *what, int trial)
{
    c5_err err;
    c5_schedule paper;
    CHECK_INT(c5_sched_celltree(t, C5_SPLIT_MOST_LEAVES, &paper, &err), 0);
    int ilp = -1, *s = malloc(sizeof *s * (size_t)(paper.len + 1));
    int rc = c5t_ilp_optimum(t, paper.len, &ilp, s);
    c5_schedule_free(&paper);
    CHECK_MSG(rc == 1, "%s %d: GLPK rc %d", what, trial, rc);
    CHECK_MSG(c5_sched_feasible(t, s, ilp) == 1, "%s %d: the program's schedule is infeasible", what, trial);
    free(s);
    int astar = -1, plain = -1;
    CHECK_INT(c5_sched_optimum(t, 1000000, 64, &astar, NULL, &err), 1);
    CHECK_INT(c5_sched_optimum_plain(t, 1000000, 64, &plain, NULL, &err), 1);
    CHECK_MSG(ilp == astar && ilp == plain, "%s %d (n=%d): program %d, A* %d, plain A* %d", what, trial, t->n, ilp,
              astar, plain);
    CHECK_MSG(ilp_confirms(t, astar), "%s %d: the program does not confirm %d", what, trial, astar);
}

TEST(tree_ilp_matches_astar_random)
{
    uint64_t rng = 0x11B;
    int par[16], cel[16];
    for (int trial = 0; trial < 300 && !c5t_failed_now(); trial++) {
        int n = c5t_random_tree(&rng, 1 + (int)(c5_splitmix64(&rng) % 12), 2 + (int)(c5_splitmix64(&rng) % 4),
                                1 + (int)(c5_splitmix64(&rng) % 8), par, cel);
        c5_dep_tree t = {n, par, cel};
        against_astar(&t, "random", trial);
    }
    /* cell ids spread over the packet's 12 bits (the wide fixtures) */
    static const int pool[] = {7, 63, 64, 1000, 4095};
    for (int trial = 0; trial < 100 && !c5t_failed_now(); trial++) {
        int n = c5t_random_tree_wide(&rng, 1 + (int)(c5_splitmix64(&rng) % 10), pool, 3 + trial % 3, 6, par, cel);
        c5_dep_tree t = {n, par, cel};
        CHECK_INT(c5_tree_check(&t, NULL), 0);
        int len = -1;
        c5_schedule paper;
        c5_err err;
        CHECK_INT(c5_sched_celltree(&t, C5_SPLIT_MOST_LEAVES, &paper, &err), 0);
        int s[64];
        CHECK_INT(c5t_ilp_optimum(&t, paper.len, &len, s), 1);
        CHECK_INT(c5_sched_feasible(&t, s, len), 1);
        CHECK_MSG(len <= paper.len, "wide %d: %d > %d", trial, len, paper.len);
        c5_schedule_free(&paper);
        /* A* works below 64 cells: the same tree with its ids renumbered by rank */
        int rank[16];
        for (int i = 0; i < n; i++) {
            rank[i] = 0;
            for (int k = 0; k < (int)(sizeof pool / sizeof *pool); k++)
                rank[i] += pool[k] < cel[i];
        }
        c5_dep_tree r = {n, par, rank};
        int astar = -1;
        CHECK_INT(c5_sched_optimum(&r, 1000000, 64, &astar, NULL, &err), 1);
        CHECK_MSG(astar == len, "wide %d: program %d, A* on the renumbered tree %d", trial, len, astar);
        CHECK(ilp_confirms(&t, len));
    }
}

/* Larger trees than the brute force takes, where the A*'s heuristics and reductions do work. */
TEST(tree_ilp_matches_astar_larger)
{
    uint64_t rng = 0x1A26E;
    int par[32], cel[32];
    for (int trial = 0; trial < 40 && !c5t_failed_now(); trial++) {
        int n = c5t_random_tree(&rng, 14 + (int)(c5_splitmix64(&rng) % 9), 3 + (int)(c5_splitmix64(&rng) % 3), 6,
                                par, cel);
        c5_dep_tree t = {n, par, cel};
        against_astar(&t, "larger", trial);
    }
}

/* The hand-made trees of the scheduling tests, with the optima worked out there. */
TEST(tree_ilp_hand_trees)
{
    /* paths 0-1-2 and 1-0-1: the paper's completion claim fails; optimum 4 (1 0 1 2) */
    static const int par1[] = {-1, 0, -1, 1, 2, 4}, cel1[] = {0, 1, 1, 2, 0, 1};
    /* three ping-pong pairs: 0 1 0 2 3 2 4 5 4 */
    static const int par2[] = {-1, 0, -1, 2, -1, 4, -1, 6, -1, 8, -1, 10}, cel2[] = {0, 1, 1, 0, 2, 3, 3, 2, 4, 5, 5, 4};
    /* where the rollout rule is one above the optimum, 5 */
    static const int par3[] = {-1, -1, 1, 0, -1, 0, 2, 5, 7, 6}, cel3[] = {0, 2, 1, 1, 1, 2, 0, 1, 2, 2};
    struct {
        c5_dep_tree t;
        int opt;
    } cases[] = {{{6, par1, cel1}, 4}, {{12, par2, cel2}, 9}, {{10, par3, cel3}, 5}};
    for (int k = 0; k < 3; k++) {
        CHECK_INT(c5_tree_check(&cases[k].t, NULL), 0);
        CHECK_MSG(ilp_confirms(&cases[k].t, cases[k].opt), "case %d", k);
        against_astar(&cases[k].t, "hand", k);
    }
    c5_dep_tree empty = {0, NULL, NULL};
    int len = -1;
    CHECK_INT(c5t_ilp_optimum(&empty, 3, &len, NULL), 1);
    CHECK_INT(len, 0);
    CHECK_INT(c5t_ilp_optimum(&cases[0].t, 0, &len, NULL), 0);
}

/* The check can fail: a claimed optimum one too long (a shorter schedule exists) or one too
 * short (the program proves no schedule of that length) is refused on every tree. */
TEST(tree_ilp_catches_wrong_answers)
{
    uint64_t rng = 0xBAD;
    int par[16], cel[16];
    c5_err err;
    for (int trial = 0; trial < 100 && !c5t_failed_now(); trial++) {
        int n = c5t_random_tree(&rng, 2 + (int)(c5_splitmix64(&rng) % 10), 2 + (int)(c5_splitmix64(&rng) % 3), 6, par,
                                cel);
        c5_dep_tree t = {n, par, cel};
        int opt = -1, *s = NULL;
        CHECK_INT(c5_sched_optimum(&t, 1000000, 64, &opt, &s, &err), 1);
        CHECK_MSG(!ilp_confirms(&t, opt + 1), "trial %d: %d + 1 confirmed", trial, opt);
        CHECK_MSG(!ilp_confirms(&t, opt - 1), "trial %d: %d - 1 confirmed", trial, opt);
        /* the A*'s optimal schedule with one load dropped: no schedule that short exists */
        int len = -1;
        CHECK_INT(c5t_ilp_optimum(&t, opt - 1, &len, NULL), 0);
        CHECK_INT(c5_sched_feasible(&t, s + 1, opt - 1), 0);
        free(s);
    }
}
