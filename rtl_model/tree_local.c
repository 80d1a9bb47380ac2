/* Local search on a feasible schedule (offline analysis, not the DSP's work): large
 * neighbourhood search by windows solved exactly.
 *
 * Fix a forward schedule s = P W S (prefix, window, suffix). The nodes the prefix serves,
 * by the leftmost embedding of every path (a node is served at the first load of its cell
 * after its parent's), form an ancestor-closed set A; the nodes the suffix serves, by the
 * rightmost embedding (a node at the last load of its cell before all of its children's,
 * taken only when every child is served), form a descendant-closed set Z. The other nodes M
 * hang under A and above Z: a node of M has its parent in A or M and its children in M or
 * Z (a child of a node of Z is in Z). Any schedule W' that serves the forest M (as a set of
 * root-to-leaf sequences) makes P W' S feasible: every path of the tree is an A part
 * embedded in P, an M part in W', a Z part in S, in that order. W itself serves M, so the
 * optimum of M is at most |W|, and replacing W by an optimal W' never lengthens s.
 * The leftmost and rightmost embeddings serve the most nodes any embedding can, so nothing
 * better is lost by fixing them.
 *
 * M's roots may share cells; its trie (siblings of one cell merged, tree_bound.c's
 * c5_group_new over all cells) has the same sequences, hence the same optimum, and passes
 * c5_tree_check (a child's cell differs from its parent's in the tree, so in the trie). The
 * window's optimum comes from the exact search (c5_sched_optimum_ex) within a state
 * budget; a window over budget is left as it is. Every accepted schedule is checked with
 * c5_sched_feasible. Deterministic: windows in a fixed order, no clock. */
#include "tree_sched.h"

#include <stdlib.h>
#include <string.h>

typedef struct {
    const c5_dep_tree *t;
    int *pos, *mid, *mcell, *kids, *kstart, *kfill;
} local_ctx;

/* Marks M for the window [i, i + w) of s (length len) in ctx->mid; returns |M|. */
static int middle(local_ctx *x, const int *s, int len, int i, int w)
{
    const c5_dep_tree *t = x->t;
    int n = t->n;
    /* leftmost: pos[v] = index of the load serving v in the prefix, or -1 */
    for (int v = 0; v < n; v++) {
        int from = t->parent[v] < 0 ? 0 : x->pos[t->parent[v]] + 1;
        x->pos[v] = -1;
        if (t->parent[v] >= 0 && x->pos[t->parent[v]] < 0)
            continue;
        for (int k = from; k < i; k++)
            if (s[k] == t->cell[v]) {
                x->pos[v] = k;
                break;
            }
    }
    /* rightmost over the suffix, children before parents (children have larger ids):
     * rpos[v] = the last load of cell[v] in the suffix before every child's, len + 1 if a
     * child is not served by the suffix */
    int *rpos = x->mcell; /* scratch */
    int count = 0;
    for (int v = n - 1; v >= 0; v--) {
        int lim = len;
        for (int q = x->kstart[v]; q < x->kstart[v + 1]; q++) {
            int u = x->kids[q];
            if (rpos[u] > len) {
                lim = -1;
                break;
            }
            if (rpos[u] < lim)
                lim = rpos[u];
        }
        rpos[v] = len + 1;
        for (int k = lim - 1; k >= i + w && lim >= 0; k--)
            if (s[k] == t->cell[v]) {
                rpos[v] = k;
                break;
            }
    }
    for (int v = 0; v < n; v++) {
        x->mid[v] = x->pos[v] < 0 && rpos[v] > len;
        count += x->mid[v];
    }
    return count;
}

int c5_sched_local_search(const c5_dep_tree *t, int *sched, int *len, int window, long max_states, c5_err *err)
{
    if (c5_tree_check(t, err) != 0)
        return -1;
    if (!c5_tree_bound_cells(t))
        return c5_fail(err, "cell tree local search: a cell id above %d (C5_BOUND_MAX_CELLS %d)",
                       C5_BOUND_MAX_CELLS - 1, C5_BOUND_MAX_CELLS);
    if (window < 2)
        return c5_fail(err, "cell tree local search: window %d (at least 2)", window);
    int f = c5_sched_feasible(t, sched, *len);
    if (f < 0)
        return c5_fail(err, "cell tree local search: out of memory (%d nodes)", t->n);
    if (f == 0)
        return c5_fail(err, "cell tree local search: the starting schedule is not feasible");
    int n = t->n, start = *len, rc = -1;
    size_t sz = (size_t)(n > 0 ? n : 1);
    local_ctx x = {t, malloc(sz * sizeof(int)), malloc(sz * sizeof(int)), malloc(sz * sizeof(int)),
                   malloc(sz * sizeof(int)), malloc((sz + 1) * sizeof(int)), malloc(sz * sizeof(int))};
    int *mpar = malloc(sz * sizeof *mpar), *mcel = malloc(sz * sizeof *mcel), *idmap = malloc(sz * sizeof *idmap);
    int *trial = malloc((size_t)(start > 0 ? start : 1) * sizeof *trial);
    if (!x.pos || !x.mid || !x.mcell || !x.kids || !x.kstart || !x.kfill || !mpar || !mcel || !idmap || !trial) {
        c5_fail(err, "cell tree local search: out of memory (%d nodes)", n);
        goto done;
    }
    /* children lists */
    memset(x.kstart, 0, (sz + 1) * sizeof(int));
    for (int v = 0; v < n; v++)
        if (t->parent[v] >= 0)
            x.kstart[t->parent[v] + 1]++;
    for (int v = 0; v < n; v++)
        x.kstart[v + 1] += x.kstart[v];
    memcpy(x.kfill, x.kstart, sz * sizeof(int));
    for (int v = 0; v < n; v++)
        if (t->parent[v] >= 0)
            x.kids[x.kfill[t->parent[v]]++] = v;
    int improved = 1;
    while (improved) {
        improved = 0;
        for (int i = 0; i + 2 <= *len; i++) {
            int w = window < *len - i ? window : *len - i;
            int m = middle(&x, sched, *len, i, w);
            if (m == 0) { /* the window serves nothing: drop it */
                memmove(sched + i, sched + i + w, (size_t)(*len - i - w) * sizeof *sched);
                *len -= w;
                improved = 1;
                i--;
                continue;
            }
            /* M as a tree (ids in node order keep parent < child) */
            int k = 0;
            for (int v = 0; v < n; v++)
                if (x.mid[v]) {
                    idmap[v] = k;
                    mpar[k] = t->parent[v] >= 0 && x.mid[t->parent[v]] ? idmap[t->parent[v]] : -1;
                    mcel[k] = t->cell[v];
                    k++;
                }
            c5_dep_tree mt = {k, mpar, mcel};
            c5_group *g = c5_group_new(&mt, ~0ull, 1, NULL);
            if (!g) {
                c5_fail(err, "cell tree local search: out of memory (%d nodes)", n);
                goto done;
            }
            int nt = c5_group_size(g);
            int *tp = malloc((size_t)nt * sizeof *tp), *tc = malloc((size_t)nt * sizeof *tc);
            if (!tp || !tc) {
                free(tp);
                free(tc);
                c5_group_free(g);
                c5_fail(err, "cell tree local search: out of memory (%d nodes)", n);
                goto done;
            }
            c5_group_tree(g, tp, tc);
            c5_group_free(g);
            c5_dep_tree tt = {nt, tp, tc};
            c5_exact_opts o = {max_states, 0x7fffffff, 1, C5_EXACT_GROUPS_DEFAULT, 0, NULL, 0};
            int best = 0, *ws = NULL;
            int got = c5_sched_optimum_ex(&tt, &o, &best, &ws, NULL, err);
            free(tp);
            free(tc);
            if (got < 0)
                goto done;
            if (got == 1 && best < w) {
                memcpy(trial, sched, (size_t)i * sizeof *trial);
                memcpy(trial + i, ws, (size_t)best * sizeof *trial);
                memcpy(trial + i + best, sched + i + w, (size_t)(*len - i - w) * sizeof *trial);
                int nl = *len - w + best;
                if (c5_sched_feasible(t, trial, nl) != 1) {
                    free(ws);
                    c5_fail(err, "cell tree local search: a spliced window is not feasible (a bug)");
                    goto done;
                }
                memcpy(sched, trial, (size_t)nl * sizeof *sched);
                *len = nl;
                improved = 1;
            }
            free(ws);
        }
    }
    rc = start - *len;
done:
    free(x.pos);
    free(x.mid);
    free(x.mcell);
    free(x.kids);
    free(x.kstart);
    free(x.kfill);
    free(mpar);
    free(mcel);
    free(idmap);
    free(trial);
    return rc;
}
