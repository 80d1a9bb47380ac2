/* The report beside the DSP's schedule (sched_report.h). */
#include <stdlib.h>

#include "clock.h"
#include "sched_report.h"
#include "tree_analysis.h"

/* Slabs of the cell grid along each axis as groups; the best axis's bound. */
static int slab_bound(const c5_dep_tree *dt, const c5_dsp_sched_opts *o)
{
    const int *n = o->split;
    if (n[0] < 1 || n[1] < 1 || n[2] < 1 || n[0] * n[1] * n[2] > C5_BOUND_MAX_CELLS)
        return -1;
    int best = -1;
    for (int a = 0; a < 3; a++) {
        if (n[a] < 2)
            continue;
        uint64_t groups[C5_BOUND_MAX_CELLS] = {0};
        for (int z = 0; z < n[2]; z++)
            for (int y = 0; y < n[1]; y++)
                for (int x = 0; x < n[0]; x++) {
                    int coord[3] = {x, y, z};
                    groups[coord[a]] |= 1ull << (x + n[0] * (y + n[1] * z));
                }
        int b = c5_sched_lower_bound_split(dt, groups, n[a], o->exact_states, NULL);
        best = b > best ? b : best;
    }
    return best;
}

static int report_bounds(const c5_dep_tree *dt, const c5_dsp_sched_opts *o, c5_dsp_sched_result *r, c5_err *err)
{
    double t1 = c5_now_s();
    c5_exact_opts eo = {.max_states = o->exact_states, .max_nodes = o->exact_nodes, .use_rollout_ub = 1,
                        .group_max = C5_EXACT_GROUPS_DEFAULT};
    c5_exact_stats es;
    int len, found = c5_sched_optimum_ex(dt, &eo, &len, NULL, &es, err);
    if (found < 0)
        return -1;
    if (es.lower > r->lower_bound)
        r->lower_bound = es.lower;
    if (found) {
        r->optimum = r->best_known = len;
    } else {
        int slabs = slab_bound(dt, o);
        if (slabs > r->lower_bound)
            r->lower_bound = slabs;
        int *best = NULL;
        if (c5_sched_beam(dt, o->beam_width > 0 ? o->beam_width : 200, &r->best_known, &best, err) != 0)
            return -1;
        /* The window rule without a budget often finds shorter schedules than the beam; the
         * local search (tree_local.c: windows of a schedule solved exactly, never longer)
         * improves each, and which start ends shorter varies from tree to tree. */
        c5_schedule ws;
        if (c5_sched_window(dt, 0, &ws, err) != 0) {
            free(best);
            return -1;
        }
        int w = o->local_window ? o->local_window : C5_DSP_LOCAL_WINDOW;
        int lens[2] = {r->best_known, ws.len}, *starts[2] = {best, ws.cells};
        for (int k = 0; k < 2 && w >= 3; k++)
            if (c5_sched_local_search(dt, starts[k], &lens[k], 2 * w / 3, C5_DSP_LOCAL_STATES, err) < 0 ||
                c5_sched_local_search(dt, starts[k], &lens[k], w, C5_DSP_LOCAL_STATES, err) < 0) {
                free(best);
                c5_schedule_free(&ws);
                return -1;
            }
        /* The local walk from the shorter: it leaves the local search's fixed point by moves
         * between equally long schedules and finds shorter ones the windows alone do not. */
        int k = lens[1] < lens[0];
        if (w >= 3 && o->walk_steps > 0 &&
            c5_sched_local_walk(dt, starts[k], &lens[k], C5_DSP_WALK_MIN, C5_DSP_WALK_MAX, o->walk_steps,
                                C5_DSP_WALK_STATES, C5_DSP_WALK_SEED, err) < 0) {
            free(best);
            c5_schedule_free(&ws);
            return -1;
        }
        r->best_known = lens[0] < lens[1] ? lens[0] : lens[1];
        c5_schedule_free(&ws);
        free(best);
    }
    r->exact_wall_s = c5_now_s() - t1;
    return 0;
}

int c5_dsp_sched_report(const c5_dep_tree *dt, c5_split_rule rule, const c5_dsp_sched_opts *o,
                        c5_dsp_sched_result *r, c5_err *err)
{
    int *len_of[7] = {NULL,           &r->len_paper,   &r->len_lookahead, &r->len_rollout,
                      &r->len_bounded, &r->len_window, &r->len_subtree};
    c5_schedule other = {0};
    /* Above 64 cells the other rules run under a cap on nodes examined (the rollout rule's
     * cost grows with cells times peels squared); over it, their length is -1. */
    uint64_t cap = c5_tree_bound_cells(dt) ? 0 : C5_DSP_REPORT_MAX_EXAMINED;
    for (int k = C5_SPLIT_MOST_LEAVES; o->all_rules && k <= C5_SPLIT_SUBTREE; k++) {
        if (k == (int)rule)
            continue;
        int got = c5_dsp_run_rule(dt, (c5_split_rule)k, cap, o, &other, err);
        if (got < 0) {
            c5_schedule_free(&other);
            return -1;
        }
        *len_of[k] = got == 0 ? other.len : -1;
        c5_schedule_free(&other);
    }
    r->paper_bound = c5_sched_lower_bound(dt);
    r->sum_maxgen = c5_sched_sum_maxgen(dt);
    r->lower_bound = r->sum_maxgen;
    if (o->exact_states > 0) {
        if (!c5_tree_bound_cells(dt)) {
            /* 64-bit cell masks: no exact search; the bound over blocks of 64 cells */
            r->exact_skipped = 1;
            double t0 = c5_now_s();
            int blocks = o->split[0] > 0 ? c5_sched_lower_bound_blocks(dt, o->split) : -1;
            r->exact_wall_s = c5_now_s() - t0;
            if (blocks > r->lower_bound)
                r->lower_bound = blocks;
        } else if (report_bounds(dt, o, r, err) != 0)
            return -1;
    }
    return 0;
}
