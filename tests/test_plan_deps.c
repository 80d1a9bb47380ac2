/* What each entry of the plan across boards waits for (rtl_model/dsp/plan_deps.h), on a tree
 * worked by hand: cells 0 and 2 on board 0, cell 1 on board 1. */
#include "harness.h"
#include "plan_deps.h"

TEST(plan_deps_waits_for_the_other_boards_parents_only)
{
    /* node:      0   1   2   3   4   5 */
    int parent[] = {-1, 0, 1, -1, 2, 1};
    int cell[] = {0, 1, 0, 1, 2, 2};
    int sched[] = {0, 1, 0, 1, 2};
    uint16_t owner[] = {0, 1, 0};
    int dep[5 * 2];
    c5_plan_deps(parent, cell, 6, sched, 5, owner, 2, dep);
    /* node 0: entry 0; node 1 (board 1): entry 1, after its parent's entry 0 on board 0;
     * node 2: entry 2, after node 1's entry 1 on board 1; node 3, a root: entry 1; node 4:
     * entry 4, its parent on the same board; node 5: entry 4, its parent node 1 on board 1 */
    int want[5 * 2] = {-1, -1, /* entry 0 */ 0, -1, /* 1 */ -1, 1, /* 2 */ -1, -1, /* 3 */ -1, 1 /* 4 */};
    for (int i = 0; i < 10; i++)
        CHECK_MSG(dep[i] == want[i], "entry %d board %d: %d, want %d", i / 2, i % 2, dep[i], want[i]);
}

/* A node its schedule never reaches (a stale schedule missing its cell) adds no wait, nor do
 * its children; every dependency is on an earlier entry. */
TEST(plan_deps_unserved_nodes_and_earlier_entries)
{
    int parent[] = {-1, 0, 1, -1};
    int cell[] = {0, 3, 1, 1};
    int sched[] = {0, 1, 0, 1};
    uint16_t owner[] = {0, 1, 0, 1};
    int dep[4 * 2];
    c5_plan_deps(parent, cell, 4, sched, 4, owner, 2, dep);
    for (int i = 0; i < 8; i++)
        CHECK_MSG(dep[i] == -1, "entry %d board %d waits for %d", i / 2, i % 2, dep[i]);
    int parent2[] = {-1, 0, 1, 2, 3};
    int cell2[] = {0, 1, 0, 1, 0};
    int sched2[] = {0, 1, 0, 1, 0};
    uint16_t owner2[] = {0, 1};
    int dep2[5 * 2];
    c5_plan_deps(parent2, cell2, 5, sched2, 5, owner2, 2, dep2);
    for (int i = 0; i < 10; i++)
        CHECK(dep2[i] < i / 2);
    CHECK_INT(dep2[4 * 2 + 1], 3);
}
