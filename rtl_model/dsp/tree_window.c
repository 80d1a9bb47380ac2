/* The window rule (C5_SPLIT_WINDOW): the shortest of the paper's schedule, the largest-subtree
 * rule's (tree_subtree.c) and one known (the fetches of the frame that built the tree),
 * shortened window by window within the DSP's budget of counted operations. docs/cell-tree.md,
 * "The window rule".
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
 * window, and a shorter one replaces it (or one as long that is lexicographically lower: a
 * move along a plateau, which opens other windows). Windows of 8, then 16, 24 and 32 loads,
 * half overlapping, are swept until two rounds shorten nothing (without a budget: change
 * nothing), the schedule reaches the sum of maxGen, or the budget is spent. */
#include "dsp_cost.h"
#include "tree_sched.h"

#include <stdlib.h>
#include <string.h>

/* Window widths, in the order they are swept: short windows are cheap and find the loose
 * loads, long ones let the search reorder more (docs/cell-tree.md: measured against other
 * sets on the Figure 6 trees). */
static const int widths[] = {8, 16, 24, 32};
#define NWIDTHS ((int)(sizeof widths / sizeof *widths))

typedef struct {
    const c5_dep_tree *t;
    int n, m, L;
    int *loc;              /* [max id + 1] local cell of a cell id */
    int *gid;              /* [m] cell id of a local cell */
    int *lc;               /* [n] local cell of a node */
    int *ncell;            /* [m] nodes of a cell */
    int *kstart, *kids;    /* children of node i: kids[kstart[i] .. kstart[i+1]) */
    int *S;                /* [cap] the schedule, local cells */
    int *occstart, *occ;   /* the loads of each cell, ascending: occ[occstart[c] .. occstart[c+1]) */
    int *E, *R;            /* [n] earliest load serving a node; L - the latest */
    int *order, *bstart;   /* nodes by E: those with E = k are order[bstart[k] .. bstart[k+1]) */
    int *tmp, *tmpn;       /* scratch: [cap + n], [n] */
    int *tp, *stamp;       /* [n] a node's trie node in the window of stamp */
    int *fpar, *fcell, *ffirst, *fnext; /* the window's forest (a trie), cell ids */
    uint64_t *sig;         /* signature of a window (width, first load) when it last failed */
    size_t sig_row;        /* entries of sig per width */
    int *S2;               /* [cap] */
    uint64_t ops;
    /* The search's course (c5_sched_window_resume): */
    uint64_t budget, reserve; /* budget_ops (0: none); operations kept for the ending */
    int maxc;                 /* the largest cell id */
    int stopped, stale;       /* the budget ended the search; E is not the schedule's */
    c5_window_cursor at;      /* where a stopped search resumes */
} win;

static int ceil_log2(int x)
{
    int k = 0;
    while ((1 << k) < x)
        k++;
    return k;
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

/* The loads of each cell, ascending. */
static void occ_build(win *w)
{
    int m = w->m, L = w->L;
    memset(w->occstart, 0, ((size_t)m + 1) * sizeof *w->occstart);
    for (int k = 0; k < L; k++)
        w->occstart[w->S[k] + 1]++;
    for (int c = 0; c < m; c++)
        w->occstart[c + 1] += w->occstart[c];
    for (int c = 0; c < m; c++)
        w->tmp[c] = w->occstart[c];
    for (int k = 0; k < L; k++)
        w->occ[w->tmp[w->S[k]]++] = k;
    w->ops += (2 * (uint64_t)L + 2 * (uint64_t)m) * C5_OPS_WIN_NODE;
}

/* The most embed_full costs on the schedule as it is: every node's two searches in its
 * cell's loads, its children, the sort; and the lists of loads. (The caller counts this
 * check: 2 a cell.) */
static uint64_t embed_worst(const win *w)
{
    uint64_t x = 0;
    for (int c = 0; c < w->m; c++)
        x += (uint64_t)w->ncell[c] * (uint64_t)(1 + ceil_log2(w->occstart[c + 1] - w->occstart[c] + 1));
    return 2 * C5_OPS_SEARCH * x + (uint64_t)w->n * (C5_OPS_EMBED + 4 * C5_OPS_WIN_NODE) +
           (6 * (uint64_t)w->L + 2 * (uint64_t)w->m + 8) * C5_OPS_WIN_NODE;
}

/* The most embed_tail costs for the nodes order[e0, n) (a search in at most L loads). */
static uint64_t tail_worst(const win *w, int e0)
{
    uint64_t k = (uint64_t)(w->n - e0);
    return k * (C5_OPS_EMBED + C5_OPS_SEARCH * (uint64_t)(1 + ceil_log2(w->L + 1)) + 3 * C5_OPS_WIN_NODE) +
           (6 * (uint64_t)w->L + 2 * (uint64_t)w->m + 8) * C5_OPS_WIN_NODE;
}

/* Counting sort of the nodes src[0, k) by E in [base, base + span) into order[off ...],
 * stable; bstart[base + v] = off + the number of them with E below base + v. */
static void sort_by_e(win *w, const int *src, int k, int base, int span, int off)
{
    int *cnt = w->tmp;
    memset(cnt, 0, ((size_t)span + 1) * sizeof *cnt);
    for (int j = 0; j < k; j++)
        cnt[w->E[src[j]] - base + 1]++;
    cnt[0] = off;
    for (int v = 0; v < span; v++)
        cnt[v + 1] += cnt[v];
    memcpy(w->bstart + base, cnt, ((size_t)span + 1) * sizeof *cnt);
    for (int j = 0; j < k; j++)
        w->order[cnt[w->E[src[j]] - base]++] = src[j];
    w->ops += (2 * (uint64_t)k + 2 * (uint64_t)span) * C5_OPS_WIN_NODE;
}

/* E, the latest loads (as R = L - Lt, which a change before them leaves as it is) and the
 * nodes by E, for the schedule S[0, L). Lt is bounded by the children's, so nodes are taken
 * last to first (a child's index is above its parent's). */
static void embed_full(win *w)
{
    int n = w->n, L = w->L;
    const int *P = w->t->parent;
    occ_build(w);
    for (int i = 0; i < n; i++)
        w->E[i] = first_at(w, w->lc[i], P[i] < 0 ? 0 : w->E[P[i]] + 1);
    for (int i = n - 1; i >= 0; i--) {
        int lim = L;
        for (int k = w->kstart[i]; k < w->kstart[i + 1]; k++)
            if (L - w->R[w->kids[k]] < lim)
                lim = L - w->R[w->kids[k]];
        w->ops += (uint64_t)(w->kstart[i + 1] - w->kstart[i]) * C5_OPS_WIN_NODE;
        w->R[i] = L - last_at(w, w->lc[i], lim - 1);
    }
    w->ops += (uint64_t)n * C5_OPS_EMBED;
    for (int i = 0; i < n; i++)
        w->tmpn[i] = i;
    sort_by_e(w, w->tmpn, n, 0, L + 1, 0);
}

/* Drops the loads that no node's earliest load is (embed_full's E, by bstart): the board would
 * pass them with an empty queue. Every node keeps its load, so the schedule stays feasible.
 * Returns the loads dropped; the caller embeds again. */
static int compact(win *w)
{
    int k = 0;
    for (int j = 0; j < w->L; j++)
        if (w->bstart[j + 1] > w->bstart[j])
            w->S[k++] = w->S[j];
    int dropped = w->L - k;
    w->ops += (uint64_t)w->L * C5_OPS_WIN_NODE;
    w->L = k;
    return dropped;
}

/* After the old schedule's S[lo, hi) became S[lo, lo + len) (w->L already the new length),
 * within a sweep that goes on at lo + len or later: a node with E < lo keeps E (it embeds in
 * the unchanged head); the others' E are recomputed, parents first (old E order), and
 * sorted. R stays right for every node whose latest load was in the unchanged tail; the
 * others now have Lt < lo + len, hence E < lo + len: no later window of the sweep looks at
 * them (embed_full sets them right for the next sweep). */
static void embed_tail(win *w, int lo)
{
    int n = w->n, e0 = w->bstart[lo];
    const int *P = w->t->parent;
    occ_build(w);
    for (int k = e0; k < n; k++) {
        int i = w->order[k];
        w->E[i] = first_at(w, w->lc[i], P[i] < 0 ? 0 : w->E[P[i]] + 1);
    }
    w->ops += (uint64_t)(n - e0) * C5_OPS_EMBED;
    memcpy(w->tmpn, w->order + e0, (size_t)(n - e0) * sizeof *w->tmpn);
    sort_by_e(w, w->tmpn, n - e0, lo, w->L + 1 - lo, e0);
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
        if (w->L - w->R[i] >= hi) /* the tail serves it */
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
    int **arrays[] = {&w->loc, &w->gid,  &w->lc,   &w->ncell, &w->kstart, &w->kids,  &w->S,     &w->occstart,
                      &w->occ, &w->E,    &w->R,    &w->order, &w->bstart, &w->tmp,   &w->tmpn,  &w->tp,
                      &w->stamp, &w->fpar, &w->fcell, &w->ffirst, &w->fnext, &w->S2};
    for (size_t k = 0; k < sizeof arrays / sizeof *arrays; k++)
        free(*arrays[k]);
    free(w->sig);
}

/* Replaces S[lo, hi) by the window schedule ws (cell ids). */
static void replace(win *w, int lo, int hi, const c5_schedule *ws)
{
    int k = lo;
    memcpy(w->S2, w->S, (size_t)lo * sizeof *w->S2);
    for (int j = 0; j < ws->len; j++)
        w->S2[k++] = w->loc[ws->cells[j]];
    for (int j = hi; j < w->L; j++)
        w->S2[k++] = w->S[j];
    w->ops += (uint64_t)(ws->len + w->L - hi) * C5_OPS_COPY;
    int *x = w->S;
    w->S = w->S2;
    w->S2 = x;
    w->L = k;
}

/* 1 when the window schedule ws is taken for S[lo, hi): shorter, or as long and first
 * differing by a lower cell (a move along a plateau that opens other windows; the order
 * makes the sweeps terminate). */
static int takes(win *w, int lo, int hi, const c5_schedule *ws)
{
    if (ws->len == 0 || ws->len > hi - lo)
        return 0;
    if (ws->len < hi - lo)
        return 1;
    int j = 0;
    while (j < ws->len && w->loc[ws->cells[j]] == w->S[lo + j])
        j++;
    w->ops += (uint64_t)(j + 1) * C5_OPS_COPY;
    return j < ws->len && w->loc[ws->cells[j]] < w->S[lo + j];
}

int c5_sched_window(const c5_dep_tree *t, uint64_t budget_ops, c5_schedule *out, c5_err *err)
{
    return c5_sched_window_from(t, budget_ops, NULL, 0, out, err);
}

int c5_sched_window_from(const c5_dep_tree *t, uint64_t budget_ops, const int *warm, int warm_len, c5_schedule *out,
                         c5_err *err)
{
    return c5_sched_window_resume(t, budget_ops, warm, warm_len, NULL, out, err);
}

/* Whether spending `cost` more operations (and the reserve) stays within the budget. */
static int affords(const win *w, uint64_t cost)
{
    return !(w->budget && w->ops + cost + w->reserve > w->budget);
}

/* The search's arrays for the tree and the paper's schedule of L loads. 0, or -1. */
static int win_alloc(win *w, const c5_dep_tree *t, int L)
{
    int n = t->n;
    w->t = t;
    w->n = n;
    w->L = L;
    for (int i = 0; i < n; i++)
        if (t->cell[i] > w->maxc)
            w->maxc = t->cell[i];
    size_t sn = (size_t)n + 2, sl = (size_t)L + 3;
    w->loc = malloc(((size_t)w->maxc + 1) * sizeof *w->loc);
    int **arrays[] = {&w->gid, &w->lc, &w->ncell, &w->kstart, &w->kids, &w->E, &w->R, &w->order, &w->tmpn,
                      &w->tp, &w->fpar, &w->fcell, &w->ffirst, &w->fnext};
    int ok = w->loc != NULL;
    for (size_t k = 0; k < sizeof arrays / sizeof *arrays; k++)
        ok &= (*arrays[k] = malloc(sn * sizeof **arrays[k])) != NULL;
    int **sarrays[] = {&w->S, &w->S2, &w->occ, &w->bstart};
    for (size_t k = 0; k < sizeof sarrays / sizeof *sarrays; k++)
        ok &= (*sarrays[k] = malloc(sl * sizeof **sarrays[k])) != NULL;
    ok &= (w->occstart = malloc(sn * sizeof *w->occstart)) != NULL;
    ok &= (w->tmp = malloc((sn + sl) * sizeof *w->tmp)) != NULL;
    ok &= (w->stamp = calloc(sn, sizeof *w->stamp)) != NULL;
    ok &= (w->sig = calloc((size_t)NWIDTHS * sl, sizeof *w->sig)) != NULL;
    w->sig_row = sl;
    return ok ? 0 : -1;
}

/* The worst case of the set-up and the first embedding (bounded with at most n cells and L
 * loads a cell): when it does not fit, the paper's schedule is the answer at its cost. */
static uint64_t setup_worst(const win *w)
{
    uint64_t n = (uint64_t)w->n, L = (uint64_t)w->L;
    return (6 * n + 3 * L + 4) * C5_OPS_WIN_NODE + (uint64_t)(w->maxc + 1) * 2 + n * 2 +
           2 * C5_OPS_SEARCH * n * (uint64_t)(1 + ceil_log2(w->L + 1)) + n * (C5_OPS_EMBED + 4 * C5_OPS_WIN_NODE) +
           (8 * L + 2 * n + 8) * C5_OPS_WIN_NODE;
}

/* Local cells 0..m-1 in id order, as the peeler numbers them; the children lists; the paper's
 * schedule in local cells and its loads per cell. */
static void win_setup(win *w, const int *paper)
{
    const c5_dep_tree *t = w->t;
    int n = w->n, L = w->L;
    size_t sn = (size_t)n + 2;
    for (int c = 0; c <= w->maxc; c++)
        w->loc[c] = -1;
    for (int i = 0; i < n; i++)
        w->loc[t->cell[i]] = 0;
    for (int c = 0; c <= w->maxc; c++)
        if (w->loc[c] == 0) {
            w->gid[w->m] = c;
            w->loc[c] = w->m++;
        }
    memset(w->ncell, 0, (size_t)w->m * sizeof *w->ncell);
    memset(w->kstart, 0, sn * sizeof *w->kstart);
    for (int i = 0; i < n; i++) {
        w->lc[i] = w->loc[t->cell[i]];
        w->ncell[w->lc[i]]++;
        if (t->parent[i] >= 0)
            w->kstart[t->parent[i] + 1]++;
    }
    for (int i = 0; i < n; i++)
        w->kstart[i + 1] += w->kstart[i];
    memcpy(w->tmpn, w->kstart, (size_t)n * sizeof *w->tmpn);
    for (int i = 0; i < n; i++)
        if (t->parent[i] >= 0)
            w->kids[w->tmpn[t->parent[i]]++] = i;
    for (int k = 0; k < L; k++)
        w->S[k] = w->loc[paper[k]];
    w->ops += (uint64_t)(4 * n + L + w->m) * C5_OPS_WIN_NODE + (uint64_t)(w->maxc + 1) * 2;
    occ_build(w);
}

static void swap_schedules(win *w)
{
    int *x = w->S;
    w->S = w->S2;
    w->S2 = x;
}

/* The warm start, when shorter than the paper's: loads of cells absent from the tree serve
 * nothing and are dropped; it is taken when every node embeds in it. 1: taken. */
static int try_warm(win *w, const int *warm, int warm_len)
{
    int k = 0, L = w->L, n = w->n;
    if (warm && warm_len > 0 && affords(w, (uint64_t)warm_len * C5_OPS_WIN_NODE)) {
        for (int j = 0; j < warm_len && k < L; j++)
            if (warm[j] >= 0 && warm[j] <= w->maxc && w->loc[warm[j]] >= 0)
                w->S2[k++] = w->loc[warm[j]];
        w->ops += (uint64_t)warm_len * C5_OPS_WIN_NODE;
    }
    if (k == 0 || k >= L)
        return 0;
    swap_schedules(w);
    w->L = k;
    occ_build(w);
    uint64_t ew = embed_worst(w);
    w->ops += 2 * (uint64_t)w->m + (uint64_t)n; /* the check, and each node's E tested below */
    int feasible = affords(w, ew);
    if (feasible) {
        embed_full(w);
        for (int i = 0; i < n && feasible; i++)
            feasible = w->E[i] < w->L;
    }
    if (feasible) {
        w->stale = 0;
        return 1;
    }
    swap_schedules(w); /* back to the one before */
    w->L = L;
    w->stale = 1;
    occ_build(w);
    return 0;
}

/* The largest-subtree rule's schedule (c5_sched_subtree) in place of the paper's when it is
 * shorter and its worst case fits the budget: on trees of hundreds of cells and more it is
 * the shorter by a fifth to a third, and the windows start closer to where they end. 1: taken,
 * 0: not, -1 with err. */
static int try_subtree(win *w, c5_err *err)
{
    if (!affords(w, c5_sched_subtree_worst(w->n, w->m)))
        return 0;
    c5_schedule s;
    if (c5_sched_subtree(w->t, &s, err) != 0)
        return -1;
    w->ops += s.dsp_ops - (uint64_t)s.len; /* not written out: the window rule writes its own */
    int took = s.len < w->L && try_warm(w, s.cells, s.len);
    c5_schedule_free(&s);
    return took;
}

/* The loads that serve nothing go first (the paper's schedule holds many on large trees), for
 * one embedding. */
static void drop_idle(win *w)
{
    uint64_t ew = w->stale ? embed_worst(w) + 2 * (uint64_t)w->m : 0;
    if (!affords(w, ew + (uint64_t)w->L * C5_OPS_WIN_NODE)) {
        w->stopped = 1;
        return;
    }
    if (w->stale)
        embed_full(w);
    w->ops += w->stale ? 2 * (uint64_t)w->m : 0;
    w->stale = compact(w) > 0;
}

/* One sweep of windows of width widths[wi] from load lo, each solved exactly by the bounded
 * rule and taken when shorter (or as long and better placed, takes()); after a window is
 * replaced the sweep goes on past it, so only the E of the nodes after it need recomputing
 * (embed_tail). Stops (w->at) where the budget cannot pay for the next step. 1: a window was
 * taken, 0: none, -1 with err. */
static int sweep_width(win *w, int round, int wi, int lo, int lb, int *stamp_id, c5_schedule *out, c5_err *err)
{
    int W = widths[wi], changed = 0;
    if (w->stale) {
        uint64_t ew = embed_worst(w);
        w->ops += 2 * (uint64_t)w->m;
        if (!affords(w, ew)) {
            w->stopped = 1;
            w->at = (c5_window_cursor){round, wi, lo};
            return 0;
        }
        embed_full(w);
        w->stale = 0;
    }
    while (lo + 1 < w->L && !w->stopped && w->L > lb) {
        int hi = lo + W < w->L ? lo + W : w->L, next = lo + W / 2;
        uint64_t *sig = &w->sig[(size_t)wi * w->sig_row + (size_t)lo], h;
        if (!affords(w, extract_worst(w, w->bstart[lo], w->bstart[hi]))) {
            w->stopped = 1;
            w->at = (c5_window_cursor){round, wi, lo};
            break;
        }
        int M = extract(w, lo, hi, ++*stamp_id, &h);
        /* The search's set-up must fit; from there on it holds its share. */
        int mc = M < w->m ? M : w->m;
        uint64_t init = (uint64_t)M * (C5_OPS_INIT_NODE + 2) + (uint64_t)mc * (C5_OPS_INIT_CELL + C5_OPS_MARK) +
                        4 * C5_OPS_WORD * (uint64_t)(1 + mc / 64) + 64;
        /* (nothing to serve; tried as it is; or too dear for what is left, where a window with
         * a smaller forest may still fit) */
        if (M > 0 && *sig != h && !(w->budget && w->ops + init + w->reserve >= w->budget)) {
            *sig = h;
            c5_dep_tree ft = {M, w->fpar, w->fcell};
            c5_schedule ws;
            /* stop hi - lo + 1: a schedule as long as the window is of use too (takes) */
            if (c5_sched_bounded_core(&ft, w->budget ? w->budget - w->ops - w->reserve : 0, hi - lo + 1, 0, &ws,
                                      err) != 0)
                return -1;
            w->ops += ws.dsp_ops;
            out->nodes_examined += ws.nodes_examined;
            if (takes(w, lo, hi, &ws)) {
                replace(w, lo, hi, &ws);
                changed = w->stale = 1;
                next = lo + ws.len;
                if (!affords(w, tail_worst(w, w->bstart[lo]))) {
                    w->stopped = 1; /* the schedule stands; no window can be tried on it */
                    w->at = (c5_window_cursor){round, wi, next};
                } else
                    embed_tail(w, lo);
            }
            c5_schedule_free(&ws);
        }
        lo = next;
    }
    return changed;
}

/* Sweeps left to right over each width, windows half overlapping and shifted by a quarter
 * width every other round, until two rounds change nothing or the budget is spent; a search
 * resumed (from) starts at the round, width and first load where the last one stopped. A
 * schedule as long as the sum of maxGen (lb, the paper's completion peels) is optimal:
 * nothing to look for. 0, or -1 with err. */
static int sweep(win *w, int lb, const c5_window_cursor *from, c5_schedule *out, c5_err *err)
{
    int r0 = from ? from->round : 0, wi0 = from && from->width < NWIDTHS ? from->width : 0;
    int stamp_id = 0, quiet = 0;
    for (int round = r0; !w->stopped && quiet < 2 && w->L > lb; round++) {
        int changed = 0, len0 = w->L;
        for (int wi = round == r0 ? wi0 : 0; wi < NWIDTHS && !w->stopped; wi++) {
            int lo = (round & 1) ? widths[wi] / 4 : 0;
            if (from && round == r0 && wi == wi0 && from->lo > lo && from->lo < w->L)
                lo = from->lo;
            int c = sweep_width(w, round, wi, lo, lb, &stamp_id, out, err);
            if (c < 0)
                return -1;
            changed |= c;
        }
        /* Under a budget only a shorter schedule counts as progress: plateau moves alone for
         * two rounds end the search (they rarely pay for the DSP's time, and where the start
         * is already optimal they would spend the whole budget); offline (no budget) they go
         * on until two rounds change nothing. */
        int progress = w->budget ? w->L < len0 : changed;
        quiet = progress ? 0 : quiet + 1;
    }
    return 0;
}

/* One search: from the shortest of the paper's schedule, the subtree rule's (with_subtree) and
 * warm. `paid`: the paper's rule is already counted (a second search on the same tree). */
static int window_run(const c5_dep_tree *t, uint64_t budget_ops, const c5_schedule *paper, int paid, int with_subtree,
                      const int *warm, int warm_len, const c5_window_cursor *from, c5_schedule *out, c5_err *err)
{
    memset(out, 0, sizeof *out);
    win w;
    memset(&w, 0, sizeof w);
    int n = t->n, rc = -1;
    out->cells = malloc((size_t)(paper->len > 0 ? paper->len : 1) * sizeof *out->cells);
    if (!out->cells || win_alloc(&w, t, paper->len) != 0) {
        c5_fail(err, "cell tree schedule: out of memory for %d nodes", n);
        goto done;
    }
    w.budget = budget_ops;
    /* the paper's rule, its schedule not yet written out */
    w.ops = paid ? 0 : paper->dsp_ops - (uint64_t)paper->len;
    w.reserve = 2 * (uint64_t)paper->len; /* writing the schedule out */
    int set_up = n > 0 && affords(&w, setup_worst(&w));
    w.stopped = !set_up;
    if (set_up)
        win_setup(&w, paper->cells);
    w.reserve += 2 * (uint64_t)w.m; /* and the last check of an embedding's cost */
    w.stale = 1;
    if (!w.stopped && with_subtree)
        out->subtree = try_subtree(&w, err);
    if (out->subtree < 0)
        goto done;
    if (!w.stopped)
        out->warm = try_warm(&w, warm, warm_len);
    if (!w.stopped && w.L > 0)
        drop_idle(&w);
    if (sweep(&w, paper->peels_completion, from, out, err) != 0)
        goto done;
    out->gave_up = w.stopped && n > 0;
    /* Where a search resumed with this schedule as its warm start goes on: where this one
     * stopped (the window it could not pay for), or from the start when it ended. */
    out->cursor = w.at;
    /* The result: the forward schedule in cell ids. */
    for (int k = 0; k < paper->len; k++)
        out->cells[k] = set_up && k < w.L ? w.gid[w.S[k]] : paper->cells[k];
    out->len = set_up ? w.L : paper->len;
    out->fell_back = out->len == paper->len && !out->warm && !out->subtree;
    out->peels_completion = paper->peels_completion; /* the paper's run (the windows do not peel the tree) */
    out->peels_split = paper->peels_split;
    out->nodes_examined += paid ? 0 : paper->nodes_examined;
    out->max_gen = paper->max_gen;
    out->dsp_ops = w.ops + w.reserve;
    rc = 0;
done:
    win_free(&w);
    if (rc != 0)
        c5_schedule_free(out);
    return rc;
}

/* The search from the subtree rule's schedule can end in a local optimum the windows do not
 * leave, with budget to spare, where the one from the paper's goes further (the 1024^3 hall
 * at 1/4096: 3,590 loads from the subtree start, 3,431 from the paper's). So when the first
 * search started from the subtree rule's schedule and ended on its own (two quiet rounds, not
 * the budget), a second starts from the paper's (or warm) with what is left; the shorter
 * schedule wins (ties: the first), and the count is both searches'. */
int c5_sched_window_resume(const c5_dep_tree *t, uint64_t budget_ops, const int *warm, int warm_len,
                           const c5_window_cursor *from, c5_schedule *out, c5_err *err)
{
    memset(out, 0, sizeof *out);
    c5_schedule paper, alt;
    if (c5_sched_celltree(t, C5_SPLIT_MOST_LEAVES, &paper, err) != 0)
        return -1;
    int rc = window_run(t, budget_ops, &paper, 0, 1, warm, warm_len, from, out, err);
    if (rc != 0 || !out->subtree || out->warm || out->gave_up || (budget_ops && out->dsp_ops >= budget_ops))
        goto done;
    rc = window_run(t, budget_ops ? budget_ops - out->dsp_ops : 0, &paper, 1, 0, warm, warm_len, NULL, &alt, err);
    if (rc != 0) {
        c5_schedule_free(out);
        goto done;
    }
    uint64_t ops = out->dsp_ops + alt.dsp_ops, examined = out->nodes_examined + alt.nodes_examined;
    if (alt.len < out->len) {
        c5_schedule_free(out);
        *out = alt;
    } else
        c5_schedule_free(&alt);
    out->dsp_ops = ops;
    out->nodes_examined = examined;
done:
    c5_schedule_free(&paper);
    return rc;
}
