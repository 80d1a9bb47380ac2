/* The unbounded Cell Tree instrument (rtl_model/analysis/tree_demand.h): the DSP's rule on its own
 * ids, node for node and slot for slot where the 96 KB tree fits, and still counting where
 * it overflows. */
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "builtin_scenes.h"
#include "cell_tree.h"
#include "dsp_sched.h"
#include "harness.h"
#include "rng.h"
#include "tree_demand.h"
#include "sched_report.h"

/* The same tag sequence through the DSP's tree and the instrument: the same answers (up to
 * numbering: the same node for the same (node, cell) question), nodes and slots, for five
 * and for any children a slot the slot formula follows cell_tree.c's chaining. */
TEST(demand_follows_the_dsp_tree_tag_for_tag)
{
    static c5_ctree t;
    c5_tree_demand d;
    CHECK(c5_demand_init(&d) == 0);
    c5_ctree_init(&t, 0);
    uint32_t tn[64], dn[64]; /* 64 rays' current nodes in both numberings */
    for (int i = 0; i < 64; i++)
        tn[i] = C5_NODE_NONE, dn[i] = C5_DEMAND_NONE;
    uint64_t s = 12345;
    for (int k = 0; k < 6000 && !t.overflow; k++) {
        int i = (int)(c5_splitmix64(&s) % 64), cell = (int)(c5_splitmix64(&s) % 40) * 97 % C5_MAX_CELLS;
        if (c5_splitmix64(&s) % 16 == 0)
            tn[i] = C5_NODE_NONE, dn[i] = C5_DEMAND_NONE; /* a new eye ray */
        tn[i] = c5_ctree_tag(&t, tn[i], cell);
        dn[i] = c5_demand_tag(&d, dn[i], cell);
    }
    CHECK(!t.overflow);
    CHECK(t.nodes > 500);
    CHECK_INT(d.n, t.nodes);
    CHECK_INT(c5_demand_slots(&d, C5_TREE_CHILDREN), t.used);
    CHECK(c5_demand_slots(&d, 6) <= c5_demand_slots(&d, C5_TREE_CHILDREN));
    CHECK(c5_demand_slots(&d, 2) > c5_demand_slots(&d, C5_TREE_CHILDREN));
    c5_demand_free(&d);
}

/* Slots by hand: 5 children fit one slot, the 6th takes an extension (4 + link, then 2),
 * 10 take three slots (4 + link, 4 + link, 2). */
TEST(demand_slots_by_hand)
{
    c5_tree_demand d;
    CHECK(c5_demand_init(&d) == 0);
    uint32_t r = c5_demand_tag(&d, C5_DEMAND_NONE, 0);
    for (int c = 1; c <= 5; c++)
        c5_demand_tag(&d, r, c);
    CHECK_INT(c5_demand_slots(&d, 5), 6);
    c5_demand_tag(&d, r, 6);
    CHECK_INT(c5_demand_slots(&d, 5), 8);
    CHECK_INT(c5_demand_slots(&d, 6), 7);
    for (int c = 7; c <= 10; c++)
        c5_demand_tag(&d, r, c);
    CHECK_INT(d.n, 11);
    CHECK_INT(c5_demand_slots(&d, 5), 11 + 2);
    CHECK_INT(c5_demand_tag(&d, r, 3), 3); /* found again, nothing new */
    CHECK_INT(d.n, 11);
    /* maxGen: one node of each of 11 cells; then the path 0 -> 1 -> 0 -> 1 gives cells 0 and
     * 1 two generations each */
    CHECK_INT(c5_demand_sum_maxgen(&d), 11);
    uint32_t back = c5_demand_tag(&d, 1, 0);
    CHECK_INT(c5_demand_sum_maxgen(&d), 12);
    c5_demand_tag(&d, back, 1);
    CHECK_INT(c5_demand_sum_maxgen(&d), 13);
    c5_demand_free(&d);
}

/* On the board: where the tree fits, the instrument counts what the DSP's RAM holds; where
 * a small RAM overflows, it keeps counting to the full tree's size and gives the frame's
 * bound, and the frame is the same bits. */
TEST(demand_on_the_board)
{
    c5_scene s;
    c5_supervol sv;
    c5_err err;
    CHECK(c5_scene_parse(c5_builtin_scene_json("brain_mirrors"), NULL, "test", &s, &err) == 0);
    CHECK(c5_supervol_build(&s, &sv, &err) == 0);
    s.render.width = s.render.height = 40;
    static c5_ctree big, small;
    c5_ctree_init(&big, 0);
    c5_ctree_init(&small, 300);
    c5_image a, b;
    c5_board_stats sa, sb;
    CHECK(c5_board_render(&s, &sv, 0, &(c5_board_opts){.cells = {3, 3, 3}, .tree = &big}, &a, &sa, &err) == 0);
    CHECK(c5_board_render(&s, &sv, 0, &(c5_board_opts){.cells = {3, 3, 3}, .tree = &small}, &b, &sb, &err) == 0);
    CHECK(!sa.tree_overflow && sb.tree_overflow);
    CHECK(sa.tree_nodes > 300);
    CHECK_INT(sa.tree_demand_nodes, sa.tree_nodes);
    CHECK_INT(sa.tree_demand_slots, sa.tree_slots);
    CHECK_INT(sb.tree_demand_nodes, sa.tree_nodes);
    CHECK_INT(sb.tree_demand_slots, sa.tree_slots);
    CHECK(sb.tree_slots <= 300);
    CHECK(!memcmp(a.rgb, b.rgb, sizeof(float) * 3 * 40 * 40));
    /* The instrument's sum of maxGen: the scheduler's where the tree fits, the same where it
     * does not, and at most any order of loads of the frame (Max Work's fetches). */
    c5_dsp_sched_result r;
    CHECK(c5_dsp_schedule(&big, &(c5_dsp_sched_opts){.report = c5_dsp_sched_report, .rule = C5_SPLIT_MOST_LEAVES}, &r, &err) == 0);
    CHECK(r.sum_maxgen > 0);
    CHECK_INT(sa.tree_demand_sum_maxgen, r.sum_maxgen);
    CHECK_INT(sb.tree_demand_sum_maxgen, r.sum_maxgen);
    CHECK(sb.tree_demand_sum_maxgen <= sb.fetches && sb.tree_demand_sum_maxgen <= (uint64_t)r.next.len);
    c5_dsp_sched_free(&r);
    c5_image_free(&a);
    c5_image_free(&b);
    c5_supervol_free(&sv);
}
