/* The Cell Tree in the DSP's SDRAM (rtl_model/dsp/cell_tree_sdram.h): the paper's rule with
 * per-cell node indices in the packet, the region's limits, and the board and the DSP working
 * on it as on the on-chip tree (docs/cell-tree.md, "Where the tree lives"). */
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "cell_tree_sdram.h"
#include "dsp_cost.h"
#include "dsp_sched.h"
#include "harness.h"
#include "scene_load.h"
#include "sched_report.h"

/* Figure 3's trace (test_cell_tree.c) on the SDRAM tree: the same nodes, and the index a packet
 * carries names its node within the cell it is queued for. */
TEST(sdram_tree_figure3_indices)
{
    static c5_sdram_tree s;
    CHECK_INT(c5_sdram_tree_init(&s, 0), 0);
    uint32_t id1, id2, id;
    uint32_t r1 = c5_sdram_tree_tag(&s, -1, C5_NODE_NONE, 1, &id1);
    uint32_t r2 = c5_sdram_tree_tag(&s, -1, C5_NODE_NONE, 2, &id2);
    CHECK_INT(r1, 0); /* the first node of cell 1, and of cell 2 */
    CHECK_INT(r2, 0);
    CHECK(id1 != id2);
    CHECK_INT(c5_sdram_tree_tag(&s, 1, r1, 1, &id), r1); /* a ray spawned in cell 1 stays in it */
    CHECK_INT(id, id1);
    uint32_t n12 = c5_sdram_tree_tag(&s, 1, r1, 2, &id);
    CHECK_INT(n12, 1); /* cell 2's second node */
    CHECK_INT(c5_sdram_tree_id(&s, 2, n12), id);
    CHECK_INT(s.t.parent[id], id1);
    CHECK_INT(c5_sdram_tree_tag(&s, 1, r1, 2, &id), n12); /* the same dependency again */
    uint32_t n21 = c5_sdram_tree_tag(&s, 2, r2, 1, &id);
    uint32_t n25 = c5_sdram_tree_tag(&s, 2, r2, 5, &id);
    uint32_t n121 = c5_sdram_tree_tag(&s, 2, n12, 1, &id);
    uint32_t n212 = c5_sdram_tree_tag(&s, 1, n21, 2, &id);
    uint32_t n252 = c5_sdram_tree_tag(&s, 5, n25, 2, &id);
    CHECK_INT(n21, 1);
    CHECK_INT(n25, 0);
    CHECK_INT(n121, 2);
    CHECK_INT(n212, 2);
    CHECK_INT(n252, 3);
    CHECK_INT(s.t.n, 8);
    CHECK_INT(s.max_index, 4); /* cell 2: its root, 12, 212, 252 */
    CHECK_INT(s.overflow, 0);
    /* Eight nodes, none with more than four children: eight 16-byte slots and 8 bytes a node. */
    CHECK_INT(s.slots, 8);
    CHECK_INT(c5_sdram_tree_bytes_used(&s), 8 * 16 + 8 * 8);
    c5_sdram_tree_free(&s);
}

/* A node with more than four children chains extension slots (as cell_tree.c with five): one
 * for the 5th..7th child, another from the 8th. */
TEST(sdram_tree_extension_slots)
{
    static c5_sdram_tree s;
    CHECK_INT(c5_sdram_tree_init(&s, 0), 0);
    uint32_t id, root = c5_sdram_tree_tag(&s, -1, C5_NODE_NONE, 0, &id);
    uint64_t want[9] = {1, 2, 3, 4, 5, 7, 8, 9, 11}; /* slots after 0..8 children */
    CHECK_INT(s.slots, want[0]);
    for (int k = 1; k <= 8; k++) {
        c5_sdram_tree_tag(&s, 0, root, k, &id);
        CHECK_INT(s.slots, want[k]);
    }
    c5_sdram_tree_free(&s);
}

/* The region and the packet's field bound the tree: a node past either freezes it, and every
 * later packet carries none, as the on-chip tree does when its 96 KB fill. */
TEST(sdram_tree_freezes_at_its_limits)
{
    static c5_sdram_tree s;
    /* room for three nodes of one slot: 3 x 24 bytes */
    CHECK_INT(c5_sdram_tree_init(&s, 3 * (C5_SDRAM_NODE_BYTES + C5_SDRAM_DIR_BYTES + C5_SDRAM_COUNT_BYTES)), 0);
    CHECK_INT(c5_sdram_tree_max_nodes(&s), 3);
    uint32_t id;
    uint32_t a = c5_sdram_tree_tag(&s, -1, C5_NODE_NONE, 0, &id);
    uint32_t b = c5_sdram_tree_tag(&s, 0, a, 1, &id);
    CHECK(c5_sdram_tree_tag(&s, 1, b, 2, &id) != C5_NODE_NONE);
    CHECK_INT(s.overflow, 0);
    CHECK_INT(c5_sdram_tree_tag(&s, 1, b, 3, &id), C5_NODE_NONE);
    CHECK_INT(id, C5_DEMAND_NONE);
    CHECK_INT(s.overflow, 1);
    CHECK_INT(c5_sdram_tree_tag(&s, -1, C5_NODE_NONE, 0, &id), C5_NODE_NONE); /* frozen */
    c5_sdram_tree_free(&s);

    /* One cell with 8,191 nodes (indices 0..8190) fills the packet's 13 bits: the next one
     * freezes the tree however large the region. */
    CHECK_INT(c5_sdram_tree_init(&s, 0), 0);
    uint32_t from = c5_sdram_tree_tag(&s, -1, C5_NODE_NONE, 0, &id), last = 0;
    CHECK_INT(c5_sdram_tree_tag(&s, -1, C5_NODE_NONE, 1, &id), 0); /* cell 1's root, index 0 */
    for (int k = 1; k < (int)C5_NODE_NONE && !s.overflow; k++) {
        /* a chain 0 -> 1 -> 0 -> 1 ...: every second node is cell 1's */
        uint32_t n1 = c5_sdram_tree_tag(&s, 0, from, 1, &id);
        last = n1;
        from = c5_sdram_tree_tag(&s, 1, n1, 0, &id);
    }
    CHECK_INT(last, C5_NODE_NONE - 1);
    CHECK_INT(s.overflow, 0);
    CHECK_INT(c5_sdram_tree_tag(&s, 0, from, 1, &id), C5_NODE_NONE);
    CHECK_INT(s.overflow, 1);
    c5_sdram_tree_free(&s);
}

static c5_scene scene;
static c5_supervol grid;

static int load(void)
{
    c5_supervol_free(&grid);
    memset(&grid, 0, sizeof grid);
    return c5t_load_scene("brain_mirrors", 32, &scene, &grid);
}

/* node_rays: the packets tagged with each node, or NULL. */
static int render_rays(c5_board_opts o, uint32_t *node_rays, c5_image *img, c5_board_stats *st)
{
    c5_err err;
    c5_board_out keep = {.node_rays = node_rays};
    if (c5_board_render_keep(&scene, &grid, 0, &o, &keep, img, st, &err) != 0) {
        fprintf(stderr, "render: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static int render(c5_board_opts o, c5_image *img, c5_board_stats *st)
{
    return render_rays(o, NULL, img, st);
}

/* On the board: a frame whose tree fits the 96 KB builds the same tree in SDRAM (node for
 * node in creation order, so the DSP's schedule is the same), the image and the fetches do not
 * depend on where the tree is, and the SDRAM tree is the unbounded instrument's. */
TEST(sdram_tree_on_the_board_is_the_onchip_tree)
{
    CHECK_INT(load(), 0);
    static c5_ctree onchip, unused;
    static c5_sdram_tree s;
    c5_ctree_init(&onchip, 0);
    c5_ctree_init(&unused, 0);
    CHECK_INT(c5_sdram_tree_init(&s, 0), 0);
    c5_image a = {0}, b = {0};
    c5_board_stats sa, sb;
    static uint32_t node_rays[C5_TREE_SLOTS], asked[C5_TREE_SLOTS]; /* asked: the SDRAM run's, unused */
    c5_board_opts o = {.cells = {3, 3, 3}, .tree = &onchip};
    CHECK_INT(render_rays(o, node_rays, &a, &sa), 0);
    o.tree = &unused;
    o.sdram_tree = &s;
    CHECK_INT(render_rays(o, asked, &b, &sb), 0);
    CHECK(a.w == b.w && !memcmp(a.rgb, b.rgb, sizeof(float) * 3 * (size_t)a.w * (size_t)a.h));
    CHECK_INT(sa.fetches, sb.fetches);
    CHECK_INT(sa.tree_overflow, 0);
    CHECK_INT(sb.tree_sdram, 1);
    CHECK_INT(sb.tree_nodes, sa.tree_nodes);
    CHECK_INT(sb.tree_nodes, sb.tree_demand_nodes);
    CHECK_INT(unused.nodes, 0); /* the on-chip RAM is not used */
    CHECK(s.max_index < C5_NODE_NONE);
    /* The same nodes in the same order: the export of the on-chip tree is the SDRAM tree's. */
    int n = (int)onchip.nodes;
    int *parent = malloc(sizeof(int) * (size_t)n), *cell = malloc(sizeof(int) * (size_t)n);
    uint32_t *id = malloc(sizeof(uint32_t) * (size_t)n);
    c5_ctree_export(&onchip, parent, cell, id);
    int same = 1;
    uint64_t rays_onchip = 0, rays_sdram = 0;
    for (int v = 0; v < n; v++) {
        same &= cell[v] == (int)s.t.cell[v] && parent[v] == (s.t.parent[v] == C5_DEMAND_NONE ? -1 : (int)s.t.parent[v]);
        same &= node_rays[id[v]] == s.rays[v];
        rays_onchip += node_rays[id[v]];
        rays_sdram += s.rays[v];
    }
    CHECK(same);
    CHECK(rays_sdram > 0 && rays_sdram == rays_onchip);
    /* The DSP's schedule by the paper's rule is the same from either RAM. */
    c5_dsp_sched_opts so = {.report = c5_dsp_sched_report, .rule = C5_SPLIT_MOST_LEAVES};
    c5_dsp_sched_result ra, rb;
    c5_err err;
    CHECK_INT(c5_dsp_schedule(&onchip, &so, &ra, &err), 0);
    CHECK_INT(c5_dsp_schedule_sdram(&s, &so, &rb, &err), 0);
    CHECK(ra.next.len > 0 && ra.next.len == rb.next.len &&
          !memcmp(ra.next.cells, rb.next.cells, sizeof(int) * (size_t)ra.next.len));
    CHECK(rb.dsp_ops_export > ra.dsp_ops_export); /* SDRAM accesses cost more */
    /* The replay of stale_plan.h agrees too. */
    c5_stale_plan pa, pb;
    CHECK_INT(c5_stale_plan_make(&onchip, node_rays, ra.next.cells, ra.next.len, NULL, 0, &pa, &err), 0);
    CHECK_INT(c5_stale_plan_make_sdram(&s, rb.next.cells, rb.next.len, NULL, 0, &pb, &err), 0);
    CHECK(pa.valid && pb.valid);
    CHECK_INT(pa.maxwork_loads, pb.maxwork_loads);
    CHECK_INT(pa.sched_loads, pb.sched_loads);
    CHECK_INT(pa.maxwork_loads, (int)sa.fetches); /* the replay of Max Work is the frame's */
    c5_stale_plan_free(&pa);
    c5_stale_plan_free(&pb);
    c5_dsp_sched_free(&ra);
    c5_dsp_sched_free(&rb);
    free(parent), free(cell), free(id);
    c5_image_free(&a);
    c5_image_free(&b);
    c5_sdram_tree_free(&s);
    c5_supervol_free(&grid);
}

/* A region too small for the frame's tree freezes it: the frame renders the same, the tree
 * reports its overflow, and the DSP makes no schedule from it. */
TEST(sdram_tree_overflow_on_the_board)
{
    CHECK_INT(load(), 0);
    static c5_ctree unused;
    static c5_sdram_tree s;
    c5_ctree_init(&unused, 0);
    CHECK_INT(c5_sdram_tree_init(&s, 50 * 24), 0); /* 50 nodes */
    c5_image a = {0}, b = {0};
    c5_board_stats sa, sb;
    c5_board_opts o = {.cells = {3, 3, 3}};
    CHECK_INT(render(o, &a, &sa), 0);
    o.tree = &unused;
    o.sdram_tree = &s;
    CHECK_INT(render(o, &b, &sb), 0);
    CHECK(!memcmp(a.rgb, b.rgb, sizeof(float) * 3 * (size_t)a.w * (size_t)a.h));
    CHECK_INT(sb.tree_overflow, 1);
    CHECK(sb.tree_nodes <= 51);
    c5_dsp_sched_opts so = {.report = c5_dsp_sched_report, .rule = C5_SPLIT_WINDOW};
    c5_dsp_sched_result r;
    c5_err err;
    CHECK_INT(c5_dsp_schedule_sdram(&s, &so, &r, &err), 0);
    CHECK_INT(r.next.len, 0);
    CHECK_INT(r.overflow, 1);
    c5_image_free(&a);
    c5_image_free(&b);
    c5_sdram_tree_free(&s);
    c5_supervol_free(&grid);
}

/* The DSP's rules around the SDRAM tree: where the tree lives, and its budget. */
TEST(sdram_tree_dsp_rules)
{
    CHECK_INT(c5_dsp_tree_in_sdram(27, 0, 0, 0), 0);
    CHECK_INT(c5_dsp_tree_in_sdram(64, 0, 0, 0), 0);
    CHECK_INT(c5_dsp_tree_in_sdram(512, 0, 0, 0), 1);
    CHECK_INT(c5_dsp_tree_in_sdram(27, 1, 0, 0), 0);
    CHECK_INT(c5_dsp_tree_in_sdram(27, 1, 0, 1), 1); /* after an on-chip overflow */
    CHECK_INT(c5_dsp_tree_in_sdram(27, 2, 1, 0), 1); /* and there it stays */
    /* 10 % of the frame's board time, less the tree's reading and writing, never below the
     * on-chip budget */
    CHECK_INT(c5_dsp_sdram_budget(0.0, 0), C5_DSP_SCHED_BUDGET_OPS);
    CHECK_INT(c5_dsp_sdram_budget(1.0, 0), (uint64_t)(0.1 * 255e6));
    CHECK_INT(c5_dsp_sdram_budget(1.0, 5000000), (uint64_t)(0.1 * 255e6) - 5000000);
    CHECK_INT(c5_dsp_sdram_budget(0.05, 0), C5_DSP_SCHED_BUDGET_OPS);
}
