/* The replay of Max Work and of a schedule on a Cell Tree with per-node ray counts
 * (stale_plan.h). A node's rays all reach its cell's queue in the load that works off its
 * parent (the eye rays: the set-up), so a load of cell c takes every waiting node of c and
 * makes their children wait: the queue counts the board would see, load by load. */
#include <stdlib.h>
#include <string.h>

#include "stale_plan.h"

typedef struct {
    int n, ncell;
    const int *cell;
    int *first, *next_child, *sibling; /* children lists */
    int *head, *link;                  /* per cell: the waiting nodes */
    uint64_t *wait;                    /* per cell: their rays */
    const uint32_t *rays;              /* per node */
    uint64_t ops;
} replay;

static void make_wait(replay *r, int v)
{
    int c = r->cell[v];
    r->link[v] = r->head[c];
    r->head[c] = v;
    r->wait[c] += r->rays[v];
}

/* Loads cell c: its waiting nodes are worked off, their children wait in their cells. */
static void load(replay *r, int c)
{
    while (r->head[c] >= 0) {
        int v = r->head[c];
        r->head[c] = r->link[v];
        for (int k = r->first[v]; k >= 0; k = r->sibling[k])
            make_wait(r, k);
    }
    r->wait[c] = 0;
}

/* Max Work's choice: most waiting rays, ties to the lowest id; -1 when none waits. */
static int busiest(replay *r)
{
    int best = -1;
    uint64_t most = 0;
    for (int c = 0; c < r->ncell; c++)
        if (r->head[c] >= 0 && (best < 0 || r->wait[c] > most))
            best = c, most = r->wait[c];
    r->ops += (uint64_t)r->ncell * C5_OPS_PLAN_CELL;
    return best;
}

static void start(replay *r, const int *parent)
{
    for (int c = 0; c < r->ncell; c++)
        r->head[c] = -1, r->wait[c] = 0;
    for (int v = 0; v < r->n; v++)
        if (parent[v] < 0)
            make_wait(r, v);
}

/* Loads following sched[0..len) on the tree (entries whose cell holds rays), then Max Work;
 * pred (or NULL): the rays each entry's cell holds when it is reached. */
static int follow(replay *r, const int *parent, const int *sched, int len, uint32_t *pred)
{
    int loads = 0;
    start(r, parent);
    for (int i = 0; i < len; i++) {
        int c = sched[i];
        if (c >= r->ncell)
            continue; /* a cell without nodes */
        if (pred)
            pred[i] = (uint32_t)(r->wait[c] > UINT32_MAX ? UINT32_MAX : r->wait[c]);
        if (r->head[c] >= 0) {
            loads++;
            load(r, c);
        }
    }
    r->ops += (uint64_t)len * C5_OPS_PLAN_ENTRY;
    for (int c; (c = busiest(r)) >= 0; loads++)
        load(r, c);
    return loads;
}

/* The replay on a tree read out of the DSP's RAM: n nodes in id order (parents first), the
 * packets tagged with each. */
static int plan_tree(int n, const int *parent, const int *cell, const uint32_t *rays, const int *sched, int len,
                     const int *lag_sched, int lag_len, c5_stale_plan *p, c5_err *err)
{
    int ncell = 0;
    replay r = {.n = n, .cell = cell, .rays = rays};
    r.first = malloc(sizeof(int) * (size_t)(n ? n : 1));
    r.sibling = malloc(sizeof(int) * (size_t)(n ? n : 1));
    r.link = malloc(sizeof(int) * (size_t)(n ? n : 1));
    p->pred = calloc((size_t)(len ? len : 1), sizeof *p->pred);
    int rc = -1;
    if (!r.first || !r.sibling || !r.link || !p->pred) {
        c5_fail(err, "out of memory for the stale-schedule replay");
        goto done;
    }
    for (int v = 0; v < n; v++) {
        p->rays += rays[v];
        if (cell[v] + 1 > ncell)
            ncell = cell[v] + 1;
        r.first[v] = -1;
    }
    for (int v = n - 1; v >= 0; v--) /* parents come first: children lists in id order */
        if (parent[v] >= 0) {
            r.sibling[v] = r.first[parent[v]];
            r.first[parent[v]] = v;
        }
    r.ncell = ncell;
    r.head = malloc(sizeof(int) * (size_t)(ncell ? ncell : 1));
    r.wait = malloc(sizeof(uint64_t) * (size_t)(ncell ? ncell : 1));
    if (!r.head || !r.wait) {
        c5_fail(err, "out of memory for the stale-schedule replay");
        goto done;
    }
    r.ops = 4 * (uint64_t)n * C5_OPS_PLAN_NODE; /* each node made waiting and worked off, per replay */
    start(&r, parent);
    for (int c; (c = busiest(&r)) >= 0; p->maxwork_loads++)
        load(&r, c);
    p->sched_loads = follow(&r, parent, sched, len, p->pred);
    if (lag_sched) {
        r.ops += 2 * (uint64_t)n * C5_OPS_PLAN_NODE;
        p->lag_loads = follow(&r, parent, lag_sched, lag_len, NULL);
    }
    p->ops = r.ops;
    p->valid = 1;
    rc = 0;
done:
    free(r.first), free(r.sibling), free(r.link), free(r.head), free(r.wait);
    return rc;
}

int c5_stale_plan_make(const c5_ctree *t, const uint32_t *node_rays, const int *sched, int len, const int *lag_sched,
                       int lag_len, c5_stale_plan *p, c5_err *err)
{
    memset(p, 0, sizeof *p);
    p->len = len;
    p->lag_loads = -1;
    if (!t || !node_rays || t->overflow)
        return 0;
    int n = (int)t->nodes, rc = -1;
    int *parent = malloc(sizeof(int) * (size_t)(n ? n : 1)), *cell = malloc(sizeof(int) * (size_t)(n ? n : 1));
    uint32_t *id = malloc(sizeof(uint32_t) * (size_t)(n ? n : 1)), *rays = malloc(sizeof(uint32_t) * (size_t)(n ? n : 1));
    if (!parent || !cell || !id || !rays) {
        c5_fail(err, "out of memory for the stale-schedule replay");
    } else {
        c5_ctree_export(t, parent, cell, id); /* the DSP's read of the tree is the scheduler's */
        for (int v = 0; v < n; v++)
            rays[v] = node_rays[id[v]];
        rc = plan_tree(n, parent, cell, rays, sched, len, lag_sched, lag_len, p, err);
    }
    free(parent), free(cell), free(id), free(rays);
    if (rc)
        c5_stale_plan_free(p);
    return rc;
}

int c5_stale_plan_make_sdram(const c5_sdram_tree *t, const int *sched, int len, const int *lag_sched, int lag_len,
                             c5_stale_plan *p, c5_err *err)
{
    memset(p, 0, sizeof *p);
    p->len = len;
    p->lag_loads = -1;
    if (!t || t->overflow || t->t.oom)
        return 0;
    int n = (int)t->t.n, rc = -1;
    int *parent = malloc(sizeof(int) * (size_t)(n ? n : 1)), *cell = malloc(sizeof(int) * (size_t)(n ? n : 1));
    if (!parent || !cell) {
        c5_fail(err, "out of memory for the stale-schedule replay");
    } else {
        c5_sdram_tree_export(t, parent, cell);
        rc = plan_tree(n, parent, cell, t->rays, sched, len, lag_sched, lag_len, p, err);
    }
    free(parent), free(cell);
    if (rc)
        c5_stale_plan_free(p);
    return rc;
}

void c5_stale_plan_free(c5_stale_plan *p)
{
    free(p->pred);
    memset(p, 0, sizeof *p);
}

void c5_stale_plan_settle(c5_stale_plan *p, const c5_stale_plan *prev, uint64_t fetches, uint64_t frame_key)
{
    p->frame_key = frame_key;
    p->bank = (prev ? prev->bank : 0) + (p->valid ? (int64_t)p->maxwork_loads - (int64_t)fetches : 0);
}
