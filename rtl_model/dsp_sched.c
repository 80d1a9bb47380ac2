/* The DSP's work between frames (dsp_sched.h). */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dsp_sched.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void c5_dsp_sched_free(c5_dsp_sched_result *r)
{
    c5_schedule_free(&r->next);
}

int c5_dsp_schedule(c5_ctree *t, const c5_dsp_sched_opts *o, c5_dsp_sched_result *r, c5_err *err)
{
    memset(r, 0, sizeof *r);
    r->nodes = (int)t->nodes;
    r->slots = (int)t->used;
    r->overflow = t->overflow;
    r->optimum = -1;
    if (t->overflow)
        return 0;
    double t0 = now_s();
    int n = r->nodes, rc = -1;
    int *parent = malloc(sizeof *parent * (size_t)(n + 1)), *cell = malloc(sizeof *cell * (size_t)(n + 1));
    int *gen = malloc(sizeof *gen * (size_t)(n + 1));
    uint32_t *id = malloc(sizeof *id * (size_t)(n + 1));
    c5_schedule other = {0};
    int *len_of[4] = {NULL, &r->len_paper, &r->len_lookahead, &r->len_rollout};
    if (!parent || !cell || !gen || !id) {
        c5_fail(err, "out of memory for the Cell Tree scheduler (%d nodes)", n);
        goto done;
    }
    /* The DSP's own work, timed: read the tree, schedule by the chosen rule, write back. */
    c5_ctree_export(t, parent, cell, id);
    c5_dep_tree dt = {n, parent, cell};
    c5_split_rule rule = o->rule ? o->rule : C5_SPLIT_MOST_LEAVES;
    if (c5_tree_check(&dt, err) != 0 || c5_sched_celltree(&dt, rule, &r->next, err) != 0 ||
        c5_tree_generations(&dt, gen) < 0 || c5_ctree_annotate(t, id, gen, n, err) != 0)
        goto done;
    r->sched_wall_s = now_s() - t0;
    r->peels_completion = r->next.peels_completion;
    r->peels_split = r->next.peels_split;
    r->nodes_examined = r->next.nodes_examined;
    r->max_gen = r->next.max_gen;
    /* The report's: the other rules and the bounds. */
    *len_of[rule] = r->next.len;
    for (int k = C5_SPLIT_MOST_LEAVES; o->all_rules && k <= C5_SPLIT_ROLLOUT; k++) {
        if (k == (int)rule)
            continue;
        if (c5_sched_celltree(&dt, (c5_split_rule)k, &other, err) != 0)
            goto done;
        *len_of[k] = other.len;
        c5_schedule_free(&other);
    }
    r->paper_bound = c5_sched_lower_bound(&dt);
    r->sum_maxgen = c5_sched_sum_maxgen(&dt);
    r->lower_bound = r->sum_maxgen;
    if (o->exact_states > 0) {
        double t1 = now_s();
        int len, found = c5_sched_optimum(&dt, o->exact_states, o->exact_nodes, &len, NULL, err);
        if (found < 0)
            goto done;
        r->optimum = found ? len : -1;
        r->exact_wall_s = now_s() - t1;
    }
    rc = 0;
done:
    c5_schedule_free(&other);
    free(parent);
    free(cell);
    free(gen);
    free(id);
    if (rc != 0)
        c5_schedule_free(&r->next);
    return rc;
}
