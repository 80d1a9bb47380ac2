/* The largest-subtree rule (C5_SPLIT_SUBTREE): a forward list schedule. A node is ready once
 * its parent has been served; the next load is the cell whose ready nodes carry the most work
 * below them, each weighed by the cube of its subtree's node count, ties to the lowest cell
 * id. A load serves the cell's ready nodes (a child never shares its parent's cell:
 * c5_tree_check), and their children become ready for later loads.
 *
 * Why the subtree: on the board's trees at 512 and 4,096 cells the loads that cost are those
 * of a node with a long, bushy future that waits while its cell is put off; Max Work and a
 * count of ready nodes weigh such a node like a leaf. Why the cube: it leans towards the
 * single largest subtree (a soft maximum) and is the highest power whose sums stay exact in
 * 64 bits: a cell's ready nodes head disjoint subtrees, so its score is at most n^3, and
 * n^3 < 2^63 for the SDRAM region's 699,050 nodes and any tree under 2^21 nodes (larger
 * trees saturate). docs/results/cell-tree-studies.md, "The largest-subtree rule", measures
 * powers 0 to 6.
 *
 * Cost: O((n + loads) log cells) with an indexed binary heap of the cells by score, counted
 * in DSP operations (dsp_cost.h). */
#include "tree_sched.h"

#include "dsp_cost.h"

#include <stdlib.h>
#include <string.h>

#define SUBTREE_MAX ((int64_t)2097151) /* 2^21 - 1: its cube is below 2^63 */

typedef struct {
    int m;            /* cells present, local ids 0..m-1 in ascending id */
    int *gid;         /* [m] cell id of a local cell */
    uint64_t *score;  /* [m] sum of the ready nodes' weights */
    int *heap, *hpos; /* heap of local cells; hpos[c]: index in heap, -1: not in it */
    int hn;
    uint64_t ops;
} cell_heap;

/* a before b: higher score, then lower cell id */
static int above(const cell_heap *h, int a, int b)
{
    return h->score[a] != h->score[b] ? h->score[a] > h->score[b] : a < b;
}

static void heap_set(cell_heap *h, int i, int c)
{
    h->heap[i] = c;
    h->hpos[c] = i;
}

static void sift_up(cell_heap *h, int i)
{
    int c = h->heap[i];
    while (i > 0 && above(h, c, h->heap[(i - 1) / 2])) {
        h->ops += C5_OPS_HEAP_STEP;
        heap_set(h, i, h->heap[(i - 1) / 2]);
        i = (i - 1) / 2;
    }
    heap_set(h, i, c);
}

static void sift_down(cell_heap *h, int i)
{
    int c = h->heap[i];
    for (;;) {
        int k = 2 * i + 1;
        if (k >= h->hn)
            break;
        if (k + 1 < h->hn && above(h, h->heap[k + 1], h->heap[k]))
            k++;
        h->ops += C5_OPS_HEAP_STEP;
        if (!above(h, h->heap[k], c))
            break;
        heap_set(h, i, h->heap[k]);
        i = k;
    }
    heap_set(h, i, c);
}

/* Adds weight w to cell c's score (the heap holds cells with a ready node). */
static void add_score(cell_heap *h, int c, uint64_t w)
{
    uint64_t s = h->score[c] + w;
    h->score[c] = s < h->score[c] ? UINT64_MAX : s;
    if (h->hpos[c] < 0)
        heap_set(h, h->hn++, c);
    sift_up(h, h->hpos[c]);
}

/* Node i (of local cell c, subtree of `size` nodes) onto its cell's ready list. */
static void make_ready(cell_heap *h, int i, int c, int64_t size, int *rhead, int *rnext)
{
    int64_t s = size < SUBTREE_MAX ? size : SUBTREE_MAX;
    rnext[i] = rhead[c];
    rhead[c] = i;
    add_score(h, c, (uint64_t)(s * s * s));
}

static int pop(cell_heap *h)
{
    int c = h->heap[0];
    h->hpos[c] = -1;
    h->score[c] = 0;
    if (--h->hn > 0) {
        heap_set(h, 0, h->heap[h->hn]);
        sift_down(h, 0);
    }
    return c;
}

/* Per node: its preparation, one examination, at most one load (a peel and the entry written),
 * a sift up when made ready and its share of a sift down when its cell is loaded. */
uint64_t c5_sched_subtree_worst(int n, int m)
{
    int lg = 0;
    while ((1 << lg) < m + 1)
        lg++;
    uint64_t per_node = C5_OPS_SUBTREE_NODE + C5_OPS_EXAMINE + C5_OPS_PEEL + 1 + 2 * (uint64_t)lg * C5_OPS_HEAP_STEP;
    return (uint64_t)(n > 0 ? n : 0) * per_node + (uint64_t)(m > 0 ? m : 0) * C5_OPS_INIT_CELL;
}

int c5_sched_subtree(const c5_dep_tree *t, c5_schedule *out, c5_err *err)
{
    memset(out, 0, sizeof *out);
    int n = t->n, rc = -1;
    size_t nn = (size_t)(n > 0 ? n : 1);
    int *loc = malloc(C5_SCHED_MAX_CELLS * sizeof *loc);
    int64_t *size = malloc(nn * sizeof *size);
    int *first = malloc(nn * sizeof *first), *next = malloc(nn * sizeof *next);
    int *lc = malloc(nn * sizeof *lc), *rhead = NULL, *rnext = malloc(nn * sizeof *rnext);
    cell_heap h = {0};
    out->cells = malloc(nn * sizeof *out->cells); /* a schedule never needs more loads than nodes */
    if (!loc || !size || !first || !next || !lc || !rnext || !out->cells) {
        c5_fail(err, "cell tree schedule: out of memory for %d nodes", n);
        goto done;
    }
    /* Cells present, numbered in ascending id. */
    for (int c = 0; c < C5_SCHED_MAX_CELLS; c++)
        loc[c] = -1;
    for (int i = 0; i < n; i++)
        loc[t->cell[i]] = 0;
    for (int c = 0; c < C5_SCHED_MAX_CELLS; c++)
        if (loc[c] == 0)
            loc[c] = h.m++;
    size_t mm = (size_t)(h.m > 0 ? h.m : 1);
    h.gid = malloc(mm * sizeof *h.gid);
    h.score = calloc(mm, sizeof *h.score);
    h.heap = malloc(mm * sizeof *h.heap);
    h.hpos = malloc(mm * sizeof *h.hpos);
    rhead = malloc(mm * sizeof *rhead);
    if (!h.gid || !h.score || !h.heap || !h.hpos || !rhead) {
        c5_fail(err, "cell tree schedule: out of memory for %d cells", h.m);
        goto done;
    }
    for (int c = 0; c < C5_SCHED_MAX_CELLS; c++)
        if (loc[c] >= 0)
            h.gid[loc[c]] = c;
    for (int c = 0; c < h.m; c++) {
        h.hpos[c] = -1;
        rhead[c] = -1;
    }
    h.ops += (uint64_t)h.m * C5_OPS_INIT_CELL;
    /* Subtree sizes and child lists, children after parents (parent < i). */
    for (int i = 0; i < n; i++) {
        size[i] = 1;
        first[i] = -1;
        lc[i] = loc[t->cell[i]];
    }
    for (int i = n - 1; i >= 0; i--) {
        int p = t->parent[i];
        if (p >= 0) {
            size[p] += size[i];
            next[i] = first[p];
            first[p] = i;
        }
    }
    h.ops += (uint64_t)n * C5_OPS_SUBTREE_NODE;
    /* Ready nodes: the roots. Each node is made ready once and served once. */
    for (int i = 0; i < n; i++)
        if (t->parent[i] < 0)
            make_ready(&h, i, lc[i], size[i], rhead, rnext);
    while (h.hn > 0) {
        int c = pop(&h);
        out->cells[out->len++] = h.gid[c];
        h.ops += C5_OPS_PEEL;
        int i = rhead[c];
        rhead[c] = -1;
        for (; i >= 0; i = rnext[i]) {
            h.ops += C5_OPS_EXAMINE;
            out->nodes_examined++;
            for (int k = first[i]; k >= 0; k = next[k])
                make_ready(&h, k, lc[k], size[k], rhead, rnext);
        }
    }
    h.ops += (uint64_t)out->len; /* writing the schedule out */
    out->dsp_ops = h.ops;
    rc = 0;
done:
    free(loc);
    free(size);
    free(first);
    free(next);
    free(lc);
    free(rnext);
    free(rhead);
    free(h.gid);
    free(h.score);
    free(h.heap);
    free(h.hpos);
    if (rc != 0)
        c5_schedule_free(out);
    return rc;
}
