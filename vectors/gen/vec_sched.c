/* Block "sched": the DSP's scheduler between frames (rtl_model/dsp/dsp_sched.h) with the paper's
 * split rule. Input: the Cell Tree as the frame left it in the DSP RAM (images ram_in,
 * roots_in). Output: the schedule, one vector per load (its position and cell), and the RAM
 * with the generations and ready flags the scheduler writes back (image ram_out). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "dsp_sched.h"
#include "rng.h"
#include "tree_image.h"
#include "sched_report.h"

static const c5_vfield fields[] = {
    {"step", 16, 1, "uint"},
    {"cell", C5_CELL_TREE_NODE_CELL_ID_WIDTH, 1, "uint"},
};

static const c5_vblock block = {"sched",
                                "Cell Tree schedule (paper's split rule): the tree in the images ram_in and "
                                "roots_in; out: the cells in load order, one a vector, and the RAM written back "
                                "(ram_out: generation, ready)",
                                fields, 2};

/* Schedules t and writes the case's files. partial: an overflowed tree is scheduled as far as
 * it holds (the DSP's --on-overflow partial), not left to Max Work. */
static int write_case(c5_vset *s, const char *source, const char *scene, c5_ctree *t, int partial)
{
    c5_vec_tree_image(s, block.name, source, scene, "in", t, 1);
    c5_dsp_sched_opts o = {.report = c5_dsp_sched_report, .rule = C5_SPLIT_MOST_LEAVES, .partial = partial};
    c5_dsp_sched_result r;
    if (c5_dsp_schedule(t, &o, &r, s->err) != 0)
        return -1;
    c5_vfile *f = c5_vfile_open(s, &block, source, scene, NULL);
    if (f) {
        for (int i = 0; i < r.next.len; i++) {
            c5_vfile_u(f, (uint64_t)i);
            c5_vfile_u(f, (uint64_t)r.next.cells[i]);
            c5_vfile_end(f);
        }
        c5_vfile_set(f, "config", json_pack("{s:s, s:i, s:i, s:i, s:b, s:s}", "rule", "paper", "nodes", r.nodes,
                                            "peels_completion", r.peels_completion, "peels_split", r.peels_split,
                                            "overflow", r.overflow, "on_overflow", partial ? "partial" : "maxwork"));
        c5_vfile_close(f);
    }
    c5_dsp_sched_free(&r);
    c5_vec_tree_image(s, block.name, source, scene, "out", t, 0);
    return 0;
}

/* Builds the DSP's tree of a parent/cell array (parents first) by the DSP's own rule: a
 * packet whose node is the parent's, bound for the node's cell. */
static void build(c5_ctree *t, int n, const int *parent, const int *cell)
{
    uint32_t id[64];
    c5_ctree_init(t, 0);
    for (int i = 0; i < n; i++)
        id[i] = c5_ctree_tag(t, parent[i] < 0 ? C5_NODE_NONE : id[parent[i]], cell[i]);
}

/* The paper's Figure 4 (as read in tests/test_tree_sched.c); the counterexample to its
 * completion claim (paths 0-1-2 and 1-0-1, docs/cell-tree.md); random trees; a tree with
 * cell id 4095; an overflowed tree. */
static int directed(c5_vset *s)
{
    static const int fig4_parent[] = {-1, -1, 1, 1, 2, 3, 5, 0, 0, 7, 8, 0, 0, 9, 10, 11, 12};
    static const int fig4_cell[] = {1, 2, 0, 3, 2, 2, 0, 0, 3, 4, 5, 6, 7, 1, 1, 1, 1};
    static const int ce_parent[] = {-1, 0, 1, -1, 3, 4};
    static const int ce_cell[] = {0, 1, 2, 1, 0, 1};
    c5_ctree *t = malloc(sizeof *t);
    if (!t)
        return c5_fail(s->err, "out of memory for the Cell Tree");
    int rc = 0;
    build(t, 17, fig4_parent, fig4_cell);
    rc |= write_case(s, "fig4", NULL, t, 0);
    build(t, 6, ce_parent, ce_cell);
    rc |= write_case(s, "counterexample", NULL, t, 0);
    /* Random: chains of packets over 8 cells, as rays bouncing between cells make them. */
    uint64_t rng = s->seed ^ 0x7363686564ull; /* "sched" */
    c5_ctree_init(t, 0);
    for (long i = 0; i < s->count && !t->overflow; i++) {
        uint32_t node = C5_NODE_NONE;
        int len = 1 + (int)(c5_splitmix64(&rng) % 5);
        for (int k = 0; k < len; k++)
            node = c5_ctree_tag(t, node, (int)(c5_splitmix64(&rng) % 8));
    }
    rc |= write_case(s, "random", NULL, t, 0);
    /* "max_cell": cell id 4095, the last of a 4,096-cell split, in a small tree: rays from
     * cell 4095 to 0 and back, and from cell 1 through 4095 (loads of 4095 in two
     * generations). */
    static const int mc_parent[] = {-1, 0, 1, -1, 3, 4};
    static const int mc_cell[] = {4095, 0, 4095, 1, 4095, 0};
    build(t, 6, mc_parent, mc_cell);
    rc |= write_case(s, "max_cell", NULL, t, 0);
    /* "overflow": chains over 8 cells until the 8,191 slots are full, the tree frozen there,
     * scheduled as far as it holds (on_overflow partial; the default leaves such a frame to
     * Max Work and has no schedule to write). */
    c5_ctree_init(t, 0);
    while (!t->overflow) {
        uint32_t node = C5_NODE_NONE;
        for (int k = 0; k < 12 && !t->overflow; k++)
            node = c5_ctree_tag(t, node, (int)(c5_splitmix64(&rng) % 8));
    }
    rc |= write_case(s, "overflow", NULL, t, 1);
    free(t);
    return rc ? -1 : 0;
}

/* Scene taps: the tree the frame built, scheduled after the frame. */
static int tap_begin(c5_vscene *v, c5_taps *t)
{
    (void)v;
    (void)t;
    return 0;
}

static void tap_end(c5_vscene *v) { write_case(v->set, v->scene, v->scene, v->tree, 0); }

const c5_vblock_gen c5_vgen_sched = {"sched", directed, tap_begin, tap_end};
