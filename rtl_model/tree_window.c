/* The window rule (C5_SPLIT_WINDOW): the paper's schedule shortened window by window within
 * the DSP's budget of counted operations. docs/cell-tree.md, "The window rule".
 *
 * A forward schedule S is feasible when every root-to-leaf path embeds in it as a
 * subsequence. E[v], the earliest load that can serve node v (the first load of v's cell
 * after E[parent]), and Lt[v], the latest (the last load of v's cell before the Lt of each
 * child), say what any window [lo, hi) of S must do: a path's nodes with E < lo are served
 * by S[0, lo), its nodes with Lt >= hi by S[hi, L) (both embeddings are S's own, and E, Lt
 * grow along a path), and the rest, the nodes with E >= lo and Lt < hi, a segment of the
 * path, must be served by the window. So any schedule W of the window's forest (those
 * nodes, each under its parent when the parent is one of them, merged into a trie: paths
 * are what counts) gives a feasible S[0, lo) W S[hi, L). The forest of a window holds only
 * the nodes without slack around it, a few dozen to a few hundred on the board's trees; the
 * bounded rollout (c5_sched_bounded_core) looks there for a schedule shorter than the
 * window, and a shorter one replaces it. Windows of 8, then 16, 24 and 32 loads, half
 * overlapping, are swept until a sweep changes nothing or the budget is spent. */
#include "dsp_cost.h"
#include "tree_sched.h"

#include <stdlib.h>
#include <string.h>

/* Window widths, in the order they are swept (docs/cell-tree.md: measured on the Figure 6
 * trees). */
static const int widths[] = {8, 16, 24, 32};

typedef struct {
    const c5_dep_tree *t;
    int n, m, L;
    int *loc;              /* [max id + 1] local cell of a cell id */
    int *gid;              /* [m] cell id of a local cell */
    int *lc;               /* [n] local cell of a node */
    int *S;                /* [cap] the schedule, local cells */
    int *occstart, *occ;   /* the loads of each cell, ascending: occ[occstart[c] .. occstart[c+1]) */
    int *E, *Lt, *lim;     /* [n] earliest and latest load serving a node; lim: the children's bound */
    int *bstart, *order;   /* nodes by E (counting sort, stable in node order) */
    int *tp, *stamp;       /* [n] a node's trie node in the window of stamp */
    int *fpar, *fcell, *ffirst, *fnext; /* the window's forest (a trie), cell ids */
    uint64_t *sig;         /* [cap] signature of the window that started at a load and failed */
    int *S2;               /* [cap] */
    uint64_t ops;
} win;

static int ceil_log2(int x)
{
    int k = 0;
    while ((1 << k) < x)
        k++;
    return k;
}

/* The most embed() costs. */
static uint64_t embed_worst(const win *w)
{
    return (uint64_t)w->n * (C5_OPS_EMBED + C5_OPS_WIN_NODE + 2 * C5_OPS_SEARCH * (1 + ceil_log2(w->L + 1))) +
           (2 * (uint64_t)w->L + (uint64_t)w->m + 4) * C5_OPS_WIN_NODE;
}

/* The first load of cell c at or after `from` (binary search in its loads); L: none. */
static int first_at(win *w, int c, int from)
{
    int a = w->occstart[c], b = w->occstart[c + 1];
    while (a < b) {
        int mid = (a + b) / 2;
        w->ops += C5_OPS_SEARCH;
        if (w->occ[mid] < from)
            a = mid + 1;
        else
            b = mid;
    }
    return a < w->occstart[c + 1] ? w->occ[a] : w->L;
}

/* The last load of cell c at or before `to`; -1: none. */
static int last_at(win *w, int c, int to)
{
    int a = w->occstart[c], b = w->occstart[c + 1];
    while (a < b) {
        int mid = (a + b) / 2;
        w->ops += C5_OPS_SEARCH;
        if (w->occ[mid] <= to)
            a = mid + 1;
        else
            b = mid;
    }
    return a > w->occstart[c] ? w->occ[a - 1] : -1;
}

/* E, Lt and the nodes by E for the schedule S[0, L). */
static void embed(win *w)
{
    int n = w->n, m = w->m, L = w->L;
    const int *P = w->t->parent;
    memset(w->occstart, 0, ((size_t)m + 1) * sizeof *w->occstart);
    for (int k = 0; k < L; k++)
        w->occstart[w->S[k] + 1]++;
    for (int c = 0; c < m; c++)
        w->occstart[c + 1] += w->occstart[c];
    for (int c = 0; c < m; c++)
        w->lim[c] = w->occstart[c];
    for (int k = 0; k < L; k++)
        w->occ[w->lim[w->S[k]]++] = k;
    w->ops += (2 * (uint64_t)L + (uint64_t)m) * C5_OPS_WIN_NODE;
    for (int i = 0; i < n; i++)
        w->E[i] = first_at(w, w->lc[i], P[i] < 0 ? 0 : w->E[P[i]] + 1);
    for (int i = 0; i < n; i++)
        w->lim[i] = L;
    for (int i = n - 1; i >= 0; i--) {
        int k = last_at(w, w->lc[i], w->lim[i] - 1);
        w->Lt[i] = k;
        if (P[i] >= 0 && k < w->lim[P[i]])
            w->lim[P[i]] = k;
    }
    w->ops += (uint64_t)n * C5_OPS_EMBED;
    memset(w->bstart, 0, ((size_t)L + 2) * sizeof *w->bstart);
    for (int i = 0; i < n; i++)
        w->bstart[w->E[i] + 1]++;
    for (int k = 0; k <= L; k++)
        w->bstart[k + 1] += w->bstart[k];
    for (int k = 0; k <= L; k++)
        w->lim[k] = w->bstart[k];
    for (int i = 0; i < n; i++)
        w->order[w->lim[w->E[i]]++] = i;
    w->ops += (uint64_t)n * C5_OPS_WIN_NODE + 4;
}

/* The most extract() costs on a window whose nodes by E are order[a, b). */
static uint64_t extract_worst(const win *w, int a, int b)
{
    return (uint64_t)(b - a) * (C5_OPS_WIN_EXTRACT + C5_OPS_TRIE_STEP * (uint64_t)w->m) + 2;
}

/* The forest of the window [lo, hi) as a trie in fpar/fcell (node order: a parent before
 * its children, as the nodes are taken by E); returns its size, *h its signature with the
 * window's loads. */
static int extract(win *w, int lo, int hi, int stamp_id, uint64_t *h)
{
    const int *P = w->t->parent;
    int M = 0, roots = -1;
    uint64_t x = 1469598103934665603ull; /* FNV-1a */
    for (int k = w->bstart[lo]; k < w->bstart[hi]; k++) {
        int i = w->order[k];
        w->ops += C5_OPS_WIN_EXTRACT;
        if (w->Lt[i] >= hi)
            continue;
        int par = P[i] >= 0 && w->stamp[P[i]] == stamp_id ? w->tp[P[i]] : -1;
        int c = w->t->cell[i], f = par >= 0 ? w->ffirst[par] : roots;
        while (f >= 0 && w->fcell[f] != c) {
            w->ops += C5_OPS_TRIE_STEP;
            f = w->fnext[f];
        }
        if (f < 0) {
            f = M++;
            w->fpar[f] = par;
            w->fcell[f] = c;
            w->ffirst[f] = -1;
            if (par >= 0) {
                w->fnext[f] = w->ffirst[par];
                w->ffirst[par] = f;
            } else {
                w->fnext[f] = roots;
                roots = f;
            }
            x = (x ^ (uint64_t)(par + 1)) * 1099511628211ull;
            x = (x ^ (uint64_t)c) * 1099511628211ull;
        }
        w->tp[i] = f;
        w->stamp[i] = stamp_id;
    }
    for (int k = lo; k < hi; k++)
        x = (x ^ (uint64_t)(w->S[k] + 0x10000)) * 1099511628211ull;
    w->ops += (uint64_t)(hi - lo);
    *h = x;
    return M;
}

static void win_free(win *w)
{
    free(w->loc);
    free(w->gid);
    free(w->lc);
    free(w->S);
    free(w->occstart);
    free(w->occ);
    free(w->E);
    free(w->Lt);
    free(w->lim);
    free(w->bstart);
    free(w->order);
    free(w->tp);
    free(w->stamp);
    free(w->fpar);
    free(w->fcell);
    free(w->ffirst);
    free(w->fnext);
    free(w->sig);
    free(w->S2);
}

int c5_sched_window(const c5_dep_tree *t, uint64_t budget_ops, c5_schedule *out, c5_err *err)
{
    memset(out, 0, sizeof *out);
    c5_schedule paper;
    if (c5_sched_celltree(t, C5_SPLIT_MOST_LEAVES, &paper, err) != 0)
        return -1;
    win w;
    memset(&w, 0, sizeof w);
    int n = t->n, L = paper.len, maxc = 0, rc = -1;
    for (int i = 0; i < n; i++)
        if (t->cell[i] > maxc)
            maxc = t->cell[i];
    size_t sn = (size_t)n + 2, sl = (size_t)L + 2;
    w.t = t;
    w.n = n;
    w.L = L;
    w.loc = malloc(((size_t)maxc + 1) * sizeof *w.loc);
    w.gid = malloc(sn * sizeof *w.gid);
    w.lc = malloc(sn * sizeof *w.lc);
    w.S = malloc(sl * sizeof *w.S);
    w.occstart = malloc(sn * sizeof *w.occstart);
    w.occ = malloc(sl * sizeof *w.occ);
    w.E = malloc(sn * sizeof *w.E);
    w.Lt = malloc(sn * sizeof *w.Lt);
    w.lim = malloc(sn * sizeof *w.lim);
    w.bstart = malloc((sl + 1) * sizeof *w.bstart);
    w.order = malloc(sn * sizeof *w.order);
    w.tp = malloc(sn * sizeof *w.tp);
    w.stamp = calloc(sn, sizeof *w.stamp);
    w.fpar = malloc(sn * sizeof *w.fpar);
    w.fcell = malloc(sn * sizeof *w.fcell);
    w.ffirst = malloc(sn * sizeof *w.ffirst);
    w.fnext = malloc(sn * sizeof *w.fnext);
    w.sig = malloc(sl * sizeof *w.sig);
    w.S2 = malloc(sl * sizeof *w.S2);
    if (!w.loc || !w.gid || !w.lc || !w.S || !w.occstart || !w.occ || !w.E || !w.Lt || !w.lim || !w.bstart ||
        !w.order || !w.tp || !w.stamp || !w.fpar || !w.fcell || !w.ffirst || !w.fnext || !w.sig || !w.S2) {
        c5_fail(err, "cell tree schedule: out of memory for %d nodes", n);
        goto done;
    }
    w.ops = paper.dsp_ops - (uint64_t)L; /* the paper's rule without writing its schedule out */
    /* Local cells 0..m-1 in id order, as the peeler numbers them. */
    for (int c = 0; c <= maxc; c++)
        w.loc[c] = -1;
    for (int i = 0; i < n; i++)
        w.loc[t->cell[i]] = 0;
    for (int c = 0; c <= maxc; c++)
        if (w.loc[c] == 0) {
            w.gid[w.m] = c;
            w.loc[c] = w.m++;
        }
    for (int i = 0; i < n; i++)
        w.lc[i] = w.loc[t->cell[i]];
    for (int k = 0; k < L; k++)
        w.S[k] = w.loc[paper.cells[k]];
    w.ops += (uint64_t)(n + L) * C5_OPS_WIN_NODE + (uint64_t)(maxc + 1) * 2;
    uint64_t reserve = 2 * (uint64_t)L; /* writing the schedule out */
    int dirty = 1, stamp_id = 0, stopped = 0;
    for (size_t wi = 0; wi < sizeof widths / sizeof *widths && !stopped; wi++) {
        int W = widths[wi], improved = 1;
        memset(w.sig, 0, sl * sizeof *w.sig);
        w.ops += (uint64_t)w.L;
        while (improved && !stopped) {
            improved = 0;
            for (int lo = 0; lo + 1 < w.L && !stopped; lo += W / 2) {
                int hi = lo + W < w.L ? lo + W : w.L;
                if (dirty) {
                    if (budget_ops && w.ops + embed_worst(&w) + reserve > budget_ops) {
                        stopped = 1;
                        break;
                    }
                    embed(&w);
                    dirty = 0;
                }
                if (budget_ops && w.ops + extract_worst(&w, w.bstart[lo], w.bstart[hi]) + reserve > budget_ops) {
                    stopped = 1;
                    break;
                }
                uint64_t h;
                int M = extract(&w, lo, hi, ++stamp_id, &h);
                if (M == 0 || w.sig[lo] == h) /* nothing to serve, or failed as it is */
                    continue;
                w.sig[lo] = h;
                /* The search's set-up must fit (it holds the budget from there on). */
                int mc = M < w.m ? M : w.m;
                uint64_t init = (uint64_t)M * C5_OPS_INIT_NODE + (uint64_t)mc * (C5_OPS_INIT_CELL + C5_OPS_MARK) +
                                2 * C5_OPS_WORD * (uint64_t)(1 + mc / 64) + 2 * (uint64_t)M;
                if (budget_ops && w.ops + init + reserve >= budget_ops)
                    continue; /* a smaller window may still fit */
                c5_dep_tree ft = {M, w.fpar, w.fcell};
                c5_schedule ws;
                if (c5_sched_bounded_core(&ft, budget_ops ? budget_ops - w.ops - reserve : 0, hi - lo, 0, &ws, err) !=
                    0)
                    goto done;
                w.ops += ws.dsp_ops;
                out->nodes_examined += ws.nodes_examined;
                if (ws.gave_up)
                    out->gave_up = 1;
                if (ws.len > 0 && ws.len < hi - lo) {
                    int k = 0;
                    for (int j = 0; j < lo; j++)
                        w.S2[k++] = w.S[j];
                    for (int j = 0; j < ws.len; j++)
                        w.S2[k++] = w.loc[ws.cells[j]];
                    for (int j = hi; j < w.L; j++)
                        w.S2[k++] = w.S[j];
                    w.ops += (uint64_t)(ws.len + w.L - hi) * C5_OPS_COPY;
                    int *tmp = w.S;
                    w.S = w.S2;
                    w.S2 = tmp;
                    w.L = k;
                    dirty = improved = 1;
                }
                c5_schedule_free(&ws);
            }
        }
    }
    if (stopped)
        out->gave_up = 1;
    /* The result: the forward schedule in cell ids. */
    for (int k = 0; k < w.L; k++)
        paper.cells[k] = w.gid[w.S[k]];
    out->len = w.L;
    out->cells = paper.cells;
    paper.cells = NULL;
    out->fell_back = w.L == paper.len;
    out->peels_completion = paper.peels_completion; /* the paper's run (the windows do not peel the tree) */
    out->peels_split = paper.peels_split;
    out->nodes_examined += paper.nodes_examined;
    out->max_gen = paper.max_gen;
    out->dsp_ops = w.ops + reserve;
    rc = 0;
done:
    win_free(&w);
    c5_schedule_free(&paper);
    return rc;
}
