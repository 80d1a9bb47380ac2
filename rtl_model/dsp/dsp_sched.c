/* The DSP's work between frames (dsp_sched.h). */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dsp_sched.h"
#include "clock.h"
#include "dsp_cost.h"

void c5_dsp_sched_free(c5_dsp_sched_result *r)
{
    c5_schedule_free(&r->next);
}

int c5_dsp_next_group(int group, int overflowed, const int cells[3])
{
    int most = cells[0] > cells[1] ? cells[0] : cells[1];
    most = most > cells[2] ? most : cells[2];
    if (group < 1)
        group = 1;
    if (!overflowed || group >= most)
        return group;
    return 2 * group < most ? 2 * group : most;
}

int c5_dsp_refine(const c5_dep_tree *dt, uint64_t budget, const c5_schedule *from, c5_schedule *out, c5_err *err)
{
    return c5_sched_window_resume(dt, budget ? budget : 1, from->cells, from->len, &from->cursor, out, err);
}

int c5_dsp_tree_in_sdram(int cells, int frame, int prev_sdram, int prev_overflow)
{
    if (frame == 0)
        return cells > C5_DSP_ONCHIP_MAX_CELLS;
    return prev_sdram || prev_overflow;
}

int c5_dsp_run_rule(const c5_dep_tree *dt, c5_split_rule rule, uint64_t cap, const c5_dsp_sched_opts *o,
                    c5_schedule *out, c5_err *err)
{
    if (rule == C5_SPLIT_WINDOW)
        return c5_sched_window_resume(dt, o->rule_budget ? o->rule_budget : c5_dsp_rule_budget(dt->n), o->warm,
                                      o->warm_len, o->resume, out, err);
    if (rule == C5_SPLIT_SUBTREE)
        return c5_sched_subtree(dt, out, err);
    return c5_sched_celltree_capped(dt, rule, cap, out, err);
}

/* The DSP's work on a tree read out of its RAM (dt: nodes in id order, parents first): the
 * chosen rule, the generations checked against the node's field and written back (counted by
 * the caller's weights). */
static int schedule_tree(const c5_dep_tree *dt, const c5_dsp_sched_opts *o, int *gen,
                         c5_dsp_sched_result *r, c5_err *err)
{
    int *len_of[7] = {NULL,           &r->len_paper,   &r->len_lookahead, &r->len_rollout,
                      &r->len_bounded, &r->len_window, &r->len_subtree};
    c5_split_rule rule = o->rule ? o->rule : C5_SPLIT_MOST_LEAVES;
    if (c5_tree_check(dt, err) != 0 || c5_dsp_run_rule(dt, rule, 0, o, &r->next, err) != 0 ||
        c5_tree_generations(dt, gen) < 0)
        return -1;
    r->peels_completion = r->next.peels_completion;
    r->peels_split = r->next.peels_split;
    r->nodes_examined = r->next.nodes_examined;
    r->max_gen = r->next.max_gen;
    r->dsp_ops_rule = r->next.dsp_ops;
    r->bounded_gave_up = r->next.gave_up;
    r->bounded_fell_back = r->next.fell_back;
    *len_of[rule] = r->next.len;
    return 0;
}

int c5_dsp_schedule(c5_ctree *t, const c5_dsp_sched_opts *o, c5_dsp_sched_result *r, c5_err *err)
{
    memset(r, 0, sizeof *r);
    r->nodes = (int)t->nodes;
    r->slots = (int)t->used;
    r->overflow = t->overflow;
    r->optimum = -1;
    if (t->overflow && !o->partial)
        return 0;
    int report = !t->overflow; /* the other rules and the bounds: for a whole tree only */
    double t0 = c5_now_s();
    int n = r->nodes, rc = -1;
    int *parent = malloc(sizeof *parent * (size_t)(n + 1)), *cell = malloc(sizeof *cell * (size_t)(n + 1));
    int *gen = malloc(sizeof *gen * (size_t)(n + 1));
    uint32_t *id = malloc(sizeof *id * (size_t)(n + 1));
    if (!parent || !cell || !gen || !id) {
        c5_fail(err, "out of memory for the Cell Tree scheduler (%d nodes)", n);
        goto done;
    }
    /* The DSP's own work, timed: read the tree, schedule by the chosen rule, write back. */
    c5_ctree_export(t, parent, cell, id);
    c5_dep_tree dt = {n, parent, cell};
    if (schedule_tree(&dt, o, gen, r, err) != 0 || c5_ctree_annotate(t, id, gen, n, err) != 0)
        goto done;
    r->sched_wall_s = c5_now_s() - t0;
    r->dsp_ops_export = (uint64_t)n * C5_OPS_NODE_READ;
    r->dsp_ops_writeback = (uint64_t)n * C5_OPS_NODE_WRITE;
    r->dsp_ops_schedule = r->dsp_ops_export + r->dsp_ops_rule + r->dsp_ops_writeback;
    /* The report's: the other rules and the bounds (offline analysis, when handed in). */
    rc = report && o->report ? o->report(&dt, o->rule ? o->rule : C5_SPLIT_MOST_LEAVES, o, r, err) : 0;
done:
    free(parent);
    free(cell);
    free(gen);
    free(id);
    if (rc != 0)
        c5_schedule_free(&r->next);
    return rc;
}

int c5_dsp_schedule_sdram(const c5_sdram_tree *t, const c5_dsp_sched_opts *o, c5_dsp_sched_result *r, c5_err *err)
{
    memset(r, 0, sizeof *r);
    r->nodes = (int)t->t.n;
    r->slots = (int)t->slots;
    r->overflow = t->overflow || t->t.oom;
    r->optimum = -1;
    if (r->overflow)
        return 0; /* a frozen SDRAM tree: the next frame runs Max Work (or groups, c5_dsp_next_group) */
    double t0 = c5_now_s();
    int n = r->nodes, rc = -1;
    int *parent = malloc(sizeof *parent * (size_t)(n + 1)), *cell = malloc(sizeof *cell * (size_t)(n + 1));
    int *gen = malloc(sizeof *gen * (size_t)(n + 1));
    if (!parent || !cell || !gen) {
        c5_fail(err, "out of memory for the Cell Tree scheduler (%d nodes)", n);
        goto done;
    }
    c5_sdram_tree_export(t, parent, cell);
    c5_dep_tree dt = {n, parent, cell};
    if (schedule_tree(&dt, o, gen, r, err) != 0)
        goto done;
    for (int v = 0; v < n; v++)
        if (gen[v] >= 1 << C5_CELL_TREE_NODE_GENERATION_WIDTH) {
            c5_fail(err, "Cell Tree node %d: generation %d does not fit the node's %d-bit field", v, gen[v],
                    C5_CELL_TREE_NODE_GENERATION_WIDTH);
            goto done;
        }
    r->sched_wall_s = c5_now_s() - t0;
    r->dsp_ops_export = (uint64_t)t->slots * C5_OPS_SDRAM_NODE;
    r->dsp_ops_writeback = (uint64_t)n * C5_OPS_SDRAM_NODE;
    r->dsp_ops_schedule = r->dsp_ops_export + r->dsp_ops_rule + r->dsp_ops_writeback;
    rc = o->report ? o->report(&dt, o->rule ? o->rule : C5_SPLIT_MOST_LEAVES, o, r, err) : 0;
done:
    free(parent);
    free(cell);
    free(gen);
    if (rc != 0)
        c5_schedule_free(&r->next);
    return rc;
}
