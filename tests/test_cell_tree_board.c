/* The Cell Tree on the board: the tree a frame builds, the schedule the DSP makes from it,
 * and the board following that schedule (rtl_model/dsp/dsp_sched.h, docs/cell-tree.md). */
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "dsp_cost.h"
#include "dsp_sched.h"
#include "tree_analysis.h"
#include "harness.h"
#include "scene_load.h"
#include "sched_report.h"

static c5_scene scene;
static c5_supervol grid;

/* brain_mirrors (three mirrors: rays return into cells already processed) at a small size. */
static int load(const char *name, int size)
{
    c5_supervol_free(&grid);
    memset(&grid, 0, sizeof grid);
    return c5t_load_scene(name, size, &scene, &grid);
}

static int render(int frame, c5_board_opts o, c5_image *img, c5_board_stats *st)
{
    c5_err err;
    if (c5_board_render(&scene, &grid, frame, &o, img, st, &err) != 0) {
        fprintf(stderr, "render: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static int same_bits(const c5_image *a, const c5_image *b)
{
    return a->w == b->w && a->h == b->h && !memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * a->h);
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The tree as its sorted set of root-to-node cell paths: independent of node numbering. */
static char **paths(const c5_ctree *t)
{
    int n = (int)t->nodes;
    int *parent = malloc(sizeof(int) * (size_t)n), *cell = malloc(sizeof(int) * (size_t)n);
    uint32_t *id = malloc(sizeof(uint32_t) * (size_t)n);
    char **p = calloc((size_t)n + 1, sizeof *p);
    c5_ctree_export(t, parent, cell, id);
    for (int i = 0; i < n; i++) {
        int depth = 0;
        for (int k = i; k >= 0; k = parent[k])
            depth++;
        p[i] = malloc((size_t)depth + 1);
        p[i][depth] = 0;
        for (int k = i, d = depth - 1; k >= 0; k = parent[k], d--)
            p[i][d] = (char)('A' + cell[k]);
    }
    qsort(p, (size_t)n, sizeof *p, cmp_str);
    free(parent);
    free(cell);
    free(id);
    return p;
}

static void paths_free(char **p)
{
    for (char **q = p; *q; q++)
        free(*q);
    free(p);
}

static c5_ctree trees[3];

/* A frame builds the same tree whatever order its cells are processed in (the tree is the
 * union of the rays' dependency paths), and renders the same bits under every scheduler,
 * the Cell Tree's included. */
TEST(celltree_same_tree_and_bits_whatever_the_scheduler)
{
    CHECK(load("brain_mirrors", 40) == 0);
    c5_image a, b, c;
    c5_board_stats sa, sb, sc;
    c5_ctree_init(&trees[0], 0);
    c5_ctree_init(&trees[1], 0);
    c5_ctree_init(&trees[2], 0);
    CHECK(render(0, (c5_board_opts){.cells = {3, 3, 3}, .tree = &trees[0]}, &a, &sa) == 0);
    CHECK(render(0, (c5_board_opts){.cells = {3, 3, 3}, .sched = C5_SCHED_MINWORK, .tree = &trees[1]}, &b, &sb) == 0);
    c5_dsp_sched_result r;
    c5_err err;
    CHECK(c5_dsp_schedule(&trees[0], &(c5_dsp_sched_opts){.report = c5_dsp_sched_report}, &r, &err) == 0);
    CHECK(r.next.len > 0);
    CHECK(render(0, (c5_board_opts){.cells = {3, 3, 3}, .sched = C5_SCHED_EXTERNAL, .schedule = r.next.cells,
                                    .schedule_len = r.next.len, .tree = &trees[2]}, &c, &sc) == 0);
    CHECK(same_bits(&a, &b) && same_bits(&a, &c));
    CHECK(trees[0].nodes > 27 && !trees[0].overflow);
    CHECK_INT(trees[1].nodes, trees[0].nodes);
    CHECK_INT(trees[2].nodes, trees[0].nodes);
    char **pa = paths(&trees[0]), **pb = paths(&trees[1]), **pc = paths(&trees[2]);
    for (uint32_t i = 0; i < trees[0].nodes; i++)
        CHECK_MSG(!strcmp(pa[i], pb[i]) && !strcmp(pa[i], pc[i]), "path %u: %s / %s / %s", i, pa[i], pb[i], pc[i]);
    paths_free(pa);
    paths_free(pb);
    paths_free(pc);
    /* The orders really differed. */
    CHECK(sa.fetches != sb.fetches || sa.fetches != sc.fetches);
    c5_dsp_sched_free(&r);
    c5_image_free(&a);
    c5_image_free(&b);
    c5_image_free(&c);
}

/* The schedule made from a frame's own tree covers every ray of that frame: following it
 * the board never falls back to Max Work, fetches no more than the schedule is long, and
 * no scheduler beats the exact optimum, which is at least the lower bound. */
TEST(celltree_own_schedule_covers_the_frame)
{
    const char *scenes[3] = {"clouds_lake", "brain_mirrors", "brain_mirrors"};
    int splits[3][3] = {{2, 2, 2}, {2, 2, 2}, {3, 3, 3}};
    for (int k = 0; k < 3; k++) {
        CHECK(load(scenes[k], 32) == 0);
        c5_image a, b;
        c5_board_stats mw, ct;
        c5_ctree_init(&trees[0], 0);
        CHECK(render(0, (c5_board_opts){.cells = {splits[k][0], splits[k][1], splits[k][2]}, .tree = &trees[0]}, &a,
                     &mw) == 0);
        c5_dsp_sched_result r;
        c5_err err;
        /* The 27-cell tree without the local search and walk (tree_local_walk_random and
         * tree_bound_sandwich_random check those; here they cost a minute of CPU). */
        c5_dsp_sched_opts so = {.report = c5_dsp_sched_report, .rule = C5_SPLIT_MOST_LEAVES, .all_rules = 1, .exact_states = 200000,
                                .exact_nodes = 4096, .local_window = k == 2 ? -1 : 0};
        CHECK(c5_dsp_schedule(&trees[0], &so, &r, &err) == 0);
        CHECK(render(0, (c5_board_opts){.cells = {splits[k][0], splits[k][1], splits[k][2]},
                                        .sched = C5_SCHED_EXTERNAL, .schedule = r.next.cells,
                                        .schedule_len = r.next.len, .stale_check = -1}, &b, &ct) == 0);
        CHECK(same_bits(&a, &b));
        CHECK_INT(ct.sched_fallback, 0);
        CHECK(ct.fetches <= (uint64_t)r.next.len);
        CHECK_INT(ct.sched_loads + ct.sched_skipped, r.next.len);
        CHECK(r.sum_maxgen <= r.lower_bound);
        CHECK(r.lower_bound <= (int)ct.fetches && r.lower_bound <= (int)mw.fetches);
        CHECK(r.len_paper > 0 && r.len_lookahead > 0 && r.len_rollout > 0);
        /* The best known schedule lies between the proven bound and every rule. */
        CHECK(r.lower_bound <= r.best_known && r.best_known <= r.len_rollout && r.best_known <= r.len_paper);
        /* The small tree (clouds_lake, 8 cells) is within the exact search's budget. */
        CHECK_MSG(k > 0 || r.optimum >= 0, "exact optimum not found within the budget (%d nodes)", r.nodes);
        if (r.optimum >= 0) {
            CHECK(r.lower_bound <= r.optimum);
            CHECK(r.optimum <= (int)ct.fetches && r.optimum <= (int)mw.fetches);
            CHECK(r.optimum <= r.len_paper && r.optimum <= r.len_lookahead && r.optimum <= r.len_rollout);
        }
        /* The RAM now holds each node's generation and its ready flag. */
        int n = (int)trees[0].nodes;
        int *parent = malloc(sizeof(int) * (size_t)n), *cell = malloc(sizeof(int) * (size_t)n);
        int *gen = malloc(sizeof(int) * (size_t)n);
        uint32_t *id = malloc(sizeof(uint32_t) * (size_t)n);
        c5_ctree_export(&trees[0], parent, cell, id);
        c5_tree_generations(&(c5_dep_tree){n, parent, cell}, gen);
        int bad = 0;
        for (int i = 0; i < n; i++) {
            c5_cell_tree_node_t nd;
            c5_ctree_read(&trees[0], id[i], &nd);
            bad += (int)nd.generation != gen[i] || nd.ready != 1;
        }
        free(parent);
        free(cell);
        free(gen);
        free(id);
        CHECK_INT(bad, 0);
        c5_dsp_sched_free(&r);
        c5_image_free(&a);
        c5_image_free(&b);
    }
}

/* A tree that outgrows the RAM: the frame renders the same bits, the flag is up, the DSP
 * makes no schedule (the next frame runs Max Work), and the bounds are not claimed. */
TEST(celltree_overflow_keeps_the_frame_and_drops_the_schedule)
{
    CHECK(load("brain_mirrors", 32) == 0);
    c5_image a, b;
    c5_board_stats sa, sb;
    c5_ctree_init(&trees[0], 0);
    c5_ctree_init(&trees[1], 12);
    CHECK(render(0, (c5_board_opts){.cells = {3, 3, 3}, .tree = &trees[0]}, &a, &sa) == 0);
    CHECK(render(0, (c5_board_opts){.cells = {3, 3, 3}, .tree = &trees[1]}, &b, &sb) == 0);
    CHECK(same_bits(&a, &b));
    CHECK(!sa.tree_overflow && sb.tree_overflow);
    CHECK(sb.tree_slots <= 12);
    c5_dsp_sched_result r;
    c5_err err;
    CHECK(c5_dsp_schedule(&trees[1], &(c5_dsp_sched_opts){.report = c5_dsp_sched_report, .exact_states = 1000, .exact_nodes = 64}, &r, &err) == 0);
    CHECK(r.overflow && r.next.len == 0 && r.optimum == -1);
    /* Following an empty schedule is Max Work from the first fetch. */
    c5_board_stats sc;
    c5_image c;
    CHECK(render(0, (c5_board_opts){.cells = {3, 3, 3}, .sched = C5_SCHED_EXTERNAL, .schedule = r.next.cells,
                                    .schedule_len = 0}, &c, &sc) == 0);
    CHECK_INT(sc.fetches, sa.fetches);
    CHECK_INT(sc.sched_fallback, sc.fetches);
    c5_dsp_sched_free(&r);
    c5_image_free(&a);
    c5_image_free(&b);
    c5_image_free(&c);
}

/* A schedule naming a cell the split does not have is refused, not skipped. */
TEST(celltree_schedule_outside_the_split_refused)
{
    CHECK(load("default", 16) == 0);
    int sched[3] = {0, 8, 1};
    c5_image img;
    c5_board_stats st;
    c5_err err;
    c5_board_opts o = {.cells = {2, 2, 2}, .sched = C5_SCHED_EXTERNAL, .schedule = sched, .schedule_len = 3};
    CHECK(c5_board_render(&scene, &grid, 0, &o, &img, &st, &err) == -1);
    CHECK_HAS(err.msg, "cell 8 is outside the 8 cells");
}

/* The DSP's rule when trees overflow: groups double per axis after an overflow, up to the
 * split's largest axis, and stay where a tree fits. */
TEST(celltree_next_group_rule)
{
    const int c16[3] = {16, 16, 16}, c6[3] = {6, 2, 1};
    CHECK_INT(c5_dsp_next_group(1, 0, c16), 1);
    CHECK_INT(c5_dsp_next_group(1, 1, c16), 2);
    CHECK_INT(c5_dsp_next_group(8, 1, c16), 16);
    CHECK_INT(c5_dsp_next_group(16, 1, c16), 16);
    CHECK_INT(c5_dsp_next_group(4, 1, c6), 6);
    CHECK_INT(c5_dsp_next_group(0, 0, c6), 1);
}

/* A tree over groups of 2x2x2 cells: its nodes name groups, the schedule made from it is
 * followed group by group (every load is a scheduled group's cell, none falls back to Max
 * Work), and the image is the same bits. */
TEST(celltree_over_groups_is_followed_group_by_group)
{
    CHECK(load("brain_mirrors", 32) == 0);
    c5_image a, b;
    c5_board_stats sa, sb;
    c5_ctree_init(&trees[0], 0);
    c5_board_opts o = {.cells = {4, 4, 4}, .tree = &trees[0], .tree_group = {2, 2, 2}};
    CHECK(render(0, o, &a, &sa) == 0);
    CHECK(!sa.tree_overflow && sa.tree_nodes > 8);
    int n = (int)trees[0].nodes, *parent = malloc(sizeof(int) * (size_t)n), *cell = malloc(sizeof(int) * (size_t)n);
    uint32_t *id = malloc(sizeof(uint32_t) * (size_t)n);
    c5_ctree_export(&trees[0], parent, cell, id);
    int beyond = 0;
    for (int i = 0; i < n; i++)
        beyond += cell[i] >= 8;
    CHECK_INT(beyond, 0);
    free(parent);
    free(cell);
    free(id);
    c5_dsp_sched_result r;
    c5_err err;
    CHECK(c5_dsp_schedule(&trees[0], &(c5_dsp_sched_opts){.report = c5_dsp_sched_report}, &r, &err) == 0);
    CHECK(r.next.len > 0);
    c5_ctree_init(&trees[1], 0);
    c5_board_opts f = {.cells = {4, 4, 4}, .sched = C5_SCHED_EXTERNAL, .schedule = r.next.cells,
                       .schedule_len = r.next.len, .tree = &trees[1], .tree_group = {2, 2, 2},
                       .schedule_group = {2, 2, 2}};
    CHECK(render(0, f, &b, &sb) == 0);
    CHECK(same_bits(&a, &b));
    CHECK_INT(sb.sched_fallback, 0);
    CHECK_INT(sb.sched_loads, sb.fetches);
    CHECK(sb.fetches >= (uint64_t)r.next.len - sb.sched_skipped);
    /* A schedule entry beyond the groups is refused. */
    int bad[1] = {8};
    f.schedule = bad;
    f.schedule_len = 1;
    CHECK(c5_board_render(&scene, &grid, 0, &f, &b, &sb, &err) != 0);
    CHECK_HAS(err.msg, "group 8 is outside the 8 groups");
    c5_dsp_sched_free(&r);
    c5_image_free(&a);
    c5_image_free(&b);
}

/* --on-overflow partial: an overflowed tree still yields the schedule of what it holds, which
 * the next frame follows before Max Work takes over; the image is the same bits. */
TEST(celltree_partial_schedule_of_an_overflowed_tree)
{
    CHECK(load("brain_mirrors", 32) == 0);
    c5_image a, b;
    c5_board_stats sa, sb;
    c5_ctree_init(&trees[0], 60);
    CHECK(render(0, (c5_board_opts){.cells = {3, 3, 3}, .tree = &trees[0]}, &a, &sa) == 0);
    CHECK(sa.tree_overflow);
    c5_dsp_sched_result r;
    c5_err err;
    CHECK(c5_dsp_schedule(&trees[0], &(c5_dsp_sched_opts){.report = c5_dsp_sched_report, .partial = 1, .exact_states = 1000}, &r, &err) == 0);
    CHECK(r.overflow && r.next.len > 0);
    CHECK(r.optimum == -1 && r.len_lookahead == 0); /* no bounds or other rules for a partial tree */
    CHECK(render(0, (c5_board_opts){.cells = {3, 3, 3}, .sched = C5_SCHED_EXTERNAL, .schedule = r.next.cells,
                                    .schedule_len = r.next.len, .stale_check = -1}, &b, &sb) == 0);
    CHECK(same_bits(&a, &b));
    CHECK(sb.sched_loads > 0 && sb.sched_fallback > 0);
    c5_dsp_sched_free(&r);
    c5_image_free(&a);
    c5_image_free(&b);
}

/* A 512-cell split (8x8x8): the DSP schedules the frame's tree (cell ids up to 511), the
 * schedule is feasible for that tree, and the next frame (the same view) follows it to the
 * end (no fall back to Max Work) with the same image bits. The exact search and its bounds
 * work on 64-bit cell masks: not computed here (exact_skipped), the sum of maxGen is the
 * bound. */
TEST(celltree_512_cells_scheduled_and_followed)
{
    CHECK(load("clouds_lake", 48) == 0);
    c5_image a, b;
    c5_board_stats mw, ct;
    c5_board_opts o = {.cells = {8, 8, 8}, .tree = &trees[0]};
    c5_ctree_init(&trees[0], 0);
    CHECK(render(0, o, &a, &mw) == 0);
    CHECK(!trees[0].overflow && trees[0].nodes > 64);
    c5_dsp_sched_result r;
    c5_err err;
    c5_dsp_sched_opts so = {.report = c5_dsp_sched_report, .rule = C5_SPLIT_MOST_LEAVES, .all_rules = 1, .exact_states = 1000, .exact_nodes = 4096,
                            .split = {8, 8, 8}};
    CHECK_MSG(c5_dsp_schedule(&trees[0], &so, &r, &err) == 0, "%s", err.msg);
    CHECK(r.next.len > 0);
    int n = (int)trees[0].nodes, maxcell = 0;
    int *parent = malloc(sizeof(int) * (size_t)n), *cell = malloc(sizeof(int) * (size_t)n);
    uint32_t *id = malloc(sizeof(uint32_t) * (size_t)n);
    c5_ctree_export(&trees[0], parent, cell, id);
    for (int i = 0; i < n; i++)
        maxcell = cell[i] > maxcell ? cell[i] : maxcell;
    c5_dep_tree dt = {n, parent, cell};
    int feasible = c5_sched_feasible(&dt, r.next.cells, r.next.len), sum = c5_sched_sum_maxgen(&dt);
    int blocks = c5_sched_lower_bound_blocks(&dt, (const int[3]){8, 8, 8});
    free(parent);
    free(cell);
    free(id);
    CHECK(maxcell >= C5_BOUND_MAX_CELLS && maxcell < 512);
    CHECK_INT(feasible, 1);
    CHECK_INT(r.sum_maxgen, sum);
    CHECK(r.next.len >= sum);
    CHECK_INT(r.exact_skipped, 1);
    CHECK_INT(r.optimum, -1);
    /* above 64 cells the bound is the one over blocks of 4x4x4 cells */
    CHECK_INT(r.lower_bound, blocks);
    CHECK(sum <= blocks && blocks <= r.next.len);
    CHECK(r.len_paper == r.next.len && r.len_lookahead > 0 && r.len_lookahead <= r.len_paper && r.len_rollout > 0);
    o.sched = C5_SCHED_EXTERNAL;
    o.schedule = r.next.cells;
    o.schedule_len = r.next.len;
    o.stale_check = -1; /* the schedule's own frame: followed to its end */
    o.tree = &trees[1];
    c5_ctree_init(&trees[1], 0);
    CHECK(render(0, o, &b, &ct) == 0);
    CHECK(same_bits(&a, &b));
    CHECK_INT(ct.sched_fallback, 0);
    CHECK_INT(ct.sched_loads + ct.sched_skipped, r.next.len);
    CHECK(ct.fetches <= (uint64_t)r.next.len && (int)ct.fetches >= r.lower_bound);
    CHECK((int)mw.fetches >= r.lower_bound);
    c5_dsp_sched_free(&r);
    c5_image_free(&a);
    c5_image_free(&b);
}

/* The fetch log (c5_board_out.fetch_log): the cells the board loaded, in order, as many as it
 * fetched; a feasible schedule of the frame's own tree; and the window rule that starts from it
 * (c5_dsp_sched_opts.warm) makes a schedule no longer than it nor than the paper's, which the
 * next frame follows to the end with the same bits. */
TEST(celltree_fetch_log_warms_the_window_rule)
{
    CHECK(load("brain_mirrors", 40) == 0);
    c5_image a, b;
    c5_board_stats mw, ct;
    static int log[4096];
    c5_board_opts o = {.cells = {3, 3, 3}, .tree = &trees[0]};
    memset(log, 0xff, sizeof log);
    c5_ctree_init(&trees[0], 0);
    c5_err err;
    CHECK(c5_board_render_keep(&scene, &grid, 0, &o, &(c5_board_out){.fetch_log = log, .fetch_log_cap = 4096}, &a,
                               &mw, &err) == 0);
    CHECK(mw.fetches > 0 && mw.fetches < 4096);
    CHECK_INT(log[mw.fetches], -1); /* nothing past the fetches */
    for (uint64_t k = 0; k < mw.fetches; k++)
        CHECK(log[k] >= 0 && log[k] < 27);
    int n = (int)trees[0].nodes;
    int *parent = malloc(sizeof(int) * (size_t)n), *cell = malloc(sizeof(int) * (size_t)n);
    uint32_t *id = malloc(sizeof(uint32_t) * (size_t)n);
    c5_ctree_export(&trees[0], parent, cell, id);
    c5_dep_tree dt = {n, parent, cell};
    CHECK_INT(c5_sched_feasible(&dt, log, (int)mw.fetches), 1);
    free(parent);
    free(cell);
    free(id);
    c5_dsp_sched_result r;
    c5_dsp_sched_opts so = {.report = c5_dsp_sched_report, .rule = C5_SPLIT_WINDOW, .all_rules = 1, .warm = log, .warm_len = (int)mw.fetches};
    CHECK_MSG(c5_dsp_schedule(&trees[0], &so, &r, &err) == 0, "%s", err.msg);
    CHECK(r.next.len > 0 && r.next.len <= r.len_paper && r.next.len <= (int)mw.fetches);
    CHECK_INT(r.next.warm, (int)mw.fetches < r.len_paper);
    CHECK(r.dsp_ops_schedule <= C5_DSP_SCHED_BUDGET_OPS);
    o.sched = C5_SCHED_EXTERNAL;
    o.schedule = r.next.cells;
    o.schedule_len = r.next.len;
    o.tree = &trees[1];
    c5_ctree_init(&trees[1], 0);
    CHECK(render(0, o, &b, &ct) == 0);
    CHECK(same_bits(&a, &b));
    CHECK_INT(ct.sched_fallback, 0);
    c5_dsp_sched_free(&r);
    c5_image_free(&a);
    c5_image_free(&b);
}
