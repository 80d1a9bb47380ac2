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
 * c5_sched_feasible. Deterministic: windows in a fixed order, no clock.
 *
 * The local walk (c5_sched_local_walk) solves windows drawn at random (a seeded generator)
 * and also takes an answer as long as the window. The search breaks ties by cell id, so the
 * window's cells are renamed by a drawn permutation before it and back after: another of the
 * equally short window schedules comes out, and the schedule moves without growing. A
 * window's answer is a schedule of its forest M whatever the names, so the proof above
 * holds for every step, and the length never grows. */
#include "tree_analysis.h"

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

/* The scratch of a local search over tree t. */
typedef struct {
    local_ctx x;
    int *mpar, *mcel, *idmap, *trial;
} local_work;

static void work_free(local_work *k)
{
    free(k->x.pos);
    free(k->x.mid);
    free(k->x.mcell);
    free(k->x.kids);
    free(k->x.kstart);
    free(k->x.kfill);
    free(k->mpar);
    free(k->mcel);
    free(k->idmap);
    free(k->trial);
}

/* Checks the tree, the window and the start; allocates the scratch for schedules of up to
 * len loads. 0, or -1 with a message. */
static int work_init(local_work *k, const c5_dep_tree *t, const int *sched, int len, int window, const char *who,
                     c5_err *err)
{
    memset(k, 0, sizeof *k);
    if (c5_tree_check(t, err) != 0)
        return -1;
    if (!c5_tree_bound_cells(t))
        return c5_fail(err, "cell tree %s: a cell id above %d (C5_BOUND_MAX_CELLS %d)", who, C5_BOUND_MAX_CELLS - 1,
                       C5_BOUND_MAX_CELLS);
    if (window < 2)
        return c5_fail(err, "cell tree %s: window %d (at least 2)", who, window);
    int f = c5_sched_feasible(t, sched, len);
    if (f < 0)
        return c5_fail(err, "cell tree %s: out of memory (%d nodes)", who, t->n);
    if (f == 0)
        return c5_fail(err, "cell tree %s: the starting schedule is not feasible", who);
    int n = t->n;
    size_t sz = (size_t)(n > 0 ? n : 1);
    local_ctx x = {t, malloc(sz * sizeof(int)), malloc(sz * sizeof(int)), malloc(sz * sizeof(int)),
                   malloc(sz * sizeof(int)), malloc((sz + 1) * sizeof(int)), malloc(sz * sizeof(int))};
    k->x = x;
    k->mpar = malloc(sz * sizeof *k->mpar);
    k->mcel = malloc(sz * sizeof *k->mcel);
    k->idmap = malloc(sz * sizeof *k->idmap);
    k->trial = malloc((size_t)(len > 0 ? len : 1) * sizeof *k->trial);
    if (!x.pos || !x.mid || !x.mcell || !x.kids || !x.kstart || !x.kfill || !k->mpar || !k->mcel || !k->idmap ||
        !k->trial) {
        work_free(k);
        return c5_fail(err, "cell tree %s: out of memory (%d nodes)", who, n);
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
    return 0;
}

/* Solves the window [i, i + w) of sched exactly and splices the answer in when it is shorter
 * (or, with `ties`, no longer). rename (NULL: none) renames the cells of the window's forest
 * before the search and back after: the search breaks ties by cell id, so a renaming picks
 * another of the equally short window schedules. 1: replaced, 0: kept (no shorter answer,
 * or over the state budget), -1 with a message. */
static int solve_window(local_work *k, int *sched, int *len, int i, int w, long max_states, int ties,
                        const int *rename, c5_err *err)
{
    const c5_dep_tree *t = k->x.t;
    int n = t->n;
    int m = middle(&k->x, sched, *len, i, w);
    if (m == 0) { /* the window serves nothing: drop it */
        memmove(sched + i, sched + i + w, (size_t)(*len - i - w) * sizeof *sched);
        *len -= w;
        return 1;
    }
    /* M as a tree (ids in node order keep parent < child) */
    int q = 0;
    for (int v = 0; v < n; v++)
        if (k->x.mid[v]) {
            k->idmap[v] = q;
            k->mpar[q] = t->parent[v] >= 0 && k->x.mid[t->parent[v]] ? k->idmap[t->parent[v]] : -1;
            k->mcel[q] = rename ? rename[t->cell[v]] : t->cell[v];
            q++;
        }
    c5_dep_tree mt = {q, k->mpar, k->mcel};
    c5_group *g = c5_group_new(&mt, ~0ull, 1, NULL);
    if (!g)
        return c5_fail(err, "cell tree local search: out of memory (%d nodes)", n);
    int nt = c5_group_size(g);
    int *tp = malloc((size_t)nt * sizeof *tp), *tc = malloc((size_t)nt * sizeof *tc);
    if (!tp || !tc) {
        free(tp);
        free(tc);
        c5_group_free(g);
        return c5_fail(err, "cell tree local search: out of memory (%d nodes)", n);
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
        return -1;
    int done = 0;
    if (got == 1 && (best < w || (ties && best == w))) {
        int back[C5_BOUND_MAX_CELLS];
        if (rename)
            for (int c = 0; c < C5_BOUND_MAX_CELLS; c++)
                back[rename[c]] = c;
        for (int r = 0; r < best; r++)
            k->trial[i + r] = rename ? back[ws[r]] : ws[r];
        memcpy(k->trial, sched, (size_t)i * sizeof *k->trial);
        memcpy(k->trial + i + best, sched + i + w, (size_t)(*len - i - w) * sizeof *k->trial);
        int nl = *len - w + best;
        if (c5_sched_feasible(t, k->trial, nl) != 1) {
            free(ws);
            return c5_fail(err, "cell tree local search: a spliced window is not feasible (a bug)");
        }
        memcpy(sched, k->trial, (size_t)nl * sizeof *sched);
        *len = nl;
        done = 1;
    }
    free(ws);
    return done;
}

int c5_sched_local_search(const c5_dep_tree *t, int *sched, int *len, int window, long max_states, c5_err *err)
{
    local_work k;
    if (work_init(&k, t, sched, *len, window, "local search", err) != 0)
        return -1;
    int start = *len, improved = 1;
    while (improved) {
        improved = 0;
        for (int i = 0; i + 2 <= *len; i++) {
            int w = window < *len - i ? window : *len - i, before = *len;
            int got = solve_window(&k, sched, len, i, w, max_states, 0, NULL, err);
            if (got < 0) {
                work_free(&k);
                return -1;
            }
            if (got) {
                improved = 1;
                if (*len == before - w)
                    i--; /* a dropped window: the next one starts where it did */
            }
        }
    }
    work_free(&k);
    return start - *len;
}

/* xorshift64: the walk's only source of choice, seeded by the caller (no clock). */
static uint64_t walk_next(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

int c5_sched_local_walk(const c5_dep_tree *t, int *sched, int *len, int wmin, int wmax, int steps, long max_states,
                        uint64_t seed, c5_err *err)
{
    if (wmax < wmin)
        return c5_fail(err, "cell tree local walk: windows of %d..%d loads", wmin, wmax);
    if (steps < 0)
        return c5_fail(err, "cell tree local walk: %d steps", steps);
    local_work k;
    if (work_init(&k, t, sched, *len, wmin, "local walk", err) != 0)
        return -1;
    int start = *len;
    uint64_t s = seed ^ 0x9e3779b97f4a7c15ull;
    if (s == 0)
        s = 1;
    for (int step = 0; step < steps && *len >= 2; step++) {
        int w = wmin + (int)(walk_next(&s) % (uint64_t)(wmax - wmin + 1));
        if (w > *len)
            w = *len;
        int i = (int)(walk_next(&s) % (uint64_t)(*len - w + 1));
        int rename[C5_BOUND_MAX_CELLS];
        for (int c = 0; c < C5_BOUND_MAX_CELLS; c++)
            rename[c] = c;
        for (int c = C5_BOUND_MAX_CELLS - 1; c > 0; c--) {
            int j = (int)(walk_next(&s) % (uint64_t)(c + 1)), a = rename[c];
            rename[c] = rename[j];
            rename[j] = a;
        }
        if (solve_window(&k, sched, len, i, w, max_states, 1, rename, err) < 0) {
            work_free(&k);
            return -1;
        }
    }
    work_free(&k);
    return start - *len;
}
