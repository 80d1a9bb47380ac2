/* Lower bounds on the optimum schedule from projections of the Cell Tree onto small groups of
 * cells, and the per-state heuristic the exact solver builds from them (tree_exact.c).
 *
 * Projection. For a set S of cells, the projection T|S keeps the nodes whose cell is in S,
 * each hung under its nearest ancestor in S. Its root-to-node sequences are exactly the
 * sequences P|S (P a root-to-node path of T, restricted to the cells of S).
 *
 * Claim 1: a feasible schedule s of T, restricted to S, is feasible for T|S; so
 *   loads of cells of S in s >= OPT(T|S).
 * Proof: every path P is a subsequence of s; deleting the letters outside S from both sides
 * keeps the embedding, so P|S is a subsequence of s|S, whose length is the number of loads
 * of cells in S.
 *
 * Claim 2: for pairwise disjoint S_1..S_k, OPT(T) >= OPT(T|S_1) + ... + OPT(T|S_k).
 * Proof: apply Claim 1 to an optimal s for each S_j; the loads counted are disjoint.
 *
 * With the singletons, OPT(T|{c}) = maxGen(c), which gives the sum of maxGen back; a group G
 * improves it by gain(G) = OPT(T|G) - sum_{c in G} maxGen(c) >= 0 (Claim 2 on the
 * singletons of G). The bound is sum of maxGen + the largest total gain of pairwise disjoint
 * groups (a set packing; for pairs, a maximum-weight matching). Any packing is a valid
 * bound; the best one is exact for few cells and a search with a node budget otherwise.
 *
 * The projection is not a Cell Tree in the sense of c5_tree_check: a node can have a child
 * of its own cell (a -> x -> a projects to a -> a), and siblings can share a cell. Two
 * consequences: siblings of one cell are merged (the projection becomes a trie of
 * sequences; the set of sequences, hence the optimum, is unchanged), and a schedule over the
 * two cells a, b is NOT free of repeats: the sequences {a a} need "a a", where an
 * alternating schedule needs "a b a". (The shortcut "OPT_ab = best alternating schedule"
 * overestimates, so it is not used.)
 *
 * The optimum of a projection is computed exactly by the peel recursion (the same one as the
 * whole problem): for a non-empty downset D of the trie,
 *   OPT(D) = 1 + min over cells c with a leaf in D of OPT(D minus the leaves of c).
 * Proof: the last load c of an optimal forward schedule serves only leaves of c (nothing
 * follows), so the rest serves D minus some leaves of c, hence OPT(D) >= 1 + OPT(D minus a
 * subset of c's leaves) >= 1 + OPT(D minus all of c's leaves), as OPT cannot grow when
 * sequences are dropped; and appending c to a schedule of D minus c's leaves serves D.
 * Within the recursion, a cell whose live nodes are all leaves is the only branch tried
 * (proof at first_ready in tree_sched.c; it holds for any set of sequences). The recursion
 * memoizes every downset it meets (exact values), up to a budget of stored downsets; a
 * projection over budget falls back to its sum of maxGen, which is always valid. */
#include "bitset_index.h"
#include "tree_analysis.h"

#include <stdlib.h>
#include <string.h>

/* ---- one group: its trie and the memoized recursion ----------------------------------- */

struct c5_group {
    uint64_t cells;
    int k, gcell[C5_BOUND_MAX_CELLS]; /* the group's cells, ascending; local index 0..k-1 */
    int nt, words;               /* trie nodes; 64-bit words of a trie bitset */
    int *tpar;                   /* [nt] trie parent, -1 for a root; tpar[v] < v */
    uint8_t *tloc;               /* [nt] local cell index */
    int *tgen;                   /* [nt] generation within the trie (for the fallback) */
    /* memo: downsets met so far and their exact optimum */
    uint64_t *keys, *khash;
    int *val;
    long nmemo, cap, budget;
    c5_bsidx idx;
    /* scratch */
    int *livekids;    /* [nt] */
    uint64_t *stack;  /* [(nt + 2) * k * words]: the children of each recursion level */
    uint64_t *probe;  /* [words] */
};


void c5_group_free(c5_group *g)
{
    if (!g)
        return;
    free(g->tpar);
    free(g->tloc);
    free(g->tgen);
    free(g->keys);
    free(g->khash);
    free(g->val);
    c5_bsidx_free(&g->idx);
    free(g->livekids);
    free(g->stack);
    free(g->probe);
    free(g);
}


static size_t memo_slot(const c5_group *g, const uint64_t *b, uint64_t h)
{
    return c5_bsidx_find(&g->idx, g->keys, g->khash, g->words, b, h);
}

/* 0 stored, -1 out of memory. Never refused: opt_rec checks the budget before it recurses,
 * and a downset whose children all got their exact values is stored even past the budget
 * (by at most the recursion depth), so that a value once exact stays exact. The heuristic
 * of tree_exact.c depends on that: a state's h must not change between two looks. */
static int memo_put(c5_group *g, const uint64_t *b, uint64_t h, int v)
{
    if (g->nmemo == g->cap) {
        long cap = g->cap ? 2 * g->cap : 256;
        if (cap > g->budget && g->nmemo < g->budget)
            cap = g->budget;
        uint64_t *keys = realloc(g->keys, (size_t)cap * g->words * sizeof *keys);
        if (keys)
            g->keys = keys;
        uint64_t *kh = realloc(g->khash, (size_t)cap * sizeof *kh);
        if (kh)
            g->khash = kh;
        int *val = realloc(g->val, (size_t)cap * sizeof *val);
        if (val)
            g->val = val;
        if (!keys || !kh || !val)
            return -1;
        g->cap = cap;
    }
    size_t slot = memo_slot(g, b, h);
    long s = g->nmemo++;
    memcpy(g->keys + (size_t)s * g->words, b, (size_t)g->words * 8);
    g->khash[s] = h;
    g->val[s] = v;
    g->idx.table[slot] = (int)s;
    if (c5_bsidx_after_store(&g->idx, g->khash, g->nmemo) != 0)
        return -1;
    return 0;
}

int c5_tree_bound_cells(const c5_dep_tree *t)
{
    for (int i = 0; i < t->n; i++)
        if (t->cell[i] < 0 || t->cell[i] >= C5_BOUND_MAX_CELLS)
            return 0;
    return 1;
}

/* Builds the trie of T|cells. map (if not NULL, t->n entries) receives for every node the
 * trie node of its nearest ancestor-or-self in the group (-1: none). */
c5_group *c5_group_new(const c5_dep_tree *t, uint64_t cells, long budget, int *map)
{
    if (!c5_tree_bound_cells(t))
        return NULL;
    c5_group *g = calloc(1, sizeof *g);
    if (!g)
        return NULL;
    g->cells = cells;
    g->budget = budget > 0 ? budget : 1;
    int loc[C5_BOUND_MAX_CELLS];
    for (int c = 0; c < C5_BOUND_MAX_CELLS; c++) {
        loc[c] = -1;
        if (cells >> c & 1) {
            loc[c] = g->k;
            g->gcell[g->k++] = c;
        }
    }
    int inside = 0;
    for (int i = 0; i < t->n; i++)
        inside += loc[t->cell[i]] >= 0;
    size_t cap = (size_t)(inside > 0 ? inside : 1);
    int k = g->k > 0 ? g->k : 1;
    int *child = malloc((cap + 1) * (size_t)k * sizeof *child); /* [(v + 1) * k + l] */
    int *m = map ? map : malloc((size_t)(t->n > 0 ? t->n : 1) * sizeof *m);
    g->tpar = malloc(cap * sizeof *g->tpar);
    g->tloc = malloc(cap);
    g->tgen = malloc(cap * sizeof *g->tgen);
    if (!child || !m || !g->tpar || !g->tloc || !g->tgen)
        goto fail;
    memset(child, 0xff, (cap + 1) * (size_t)k * sizeof *child);
    for (int i = 0; i < t->n; i++) {
        int up = t->parent[i] < 0 ? -1 : m[t->parent[i]], l = loc[t->cell[i]];
        if (l < 0) {
            m[i] = up;
            continue;
        }
        int *slot = &child[(size_t)(up + 1) * k + l];
        if (*slot < 0) {
            int v = g->nt++, gen = 1;
            for (int a = up; a >= 0; a = g->tpar[a])
                if (g->tloc[a] == l) {
                    gen = g->tgen[a] + 1;
                    break;
                }
            g->tpar[v] = up;
            g->tloc[v] = (uint8_t)l;
            g->tgen[v] = gen;
            *slot = v;
        }
        m[i] = *slot;
    }
    free(child);
    child = NULL;
    if (m != map)
        free(m);
    m = NULL;
    g->words = g->nt > 0 ? (g->nt + 63) / 64 : 1;
    g->livekids = malloc(cap * sizeof *g->livekids);
    g->probe = malloc((size_t)g->words * sizeof *g->probe);
    if (!g->livekids || !g->probe || c5_bsidx_grow(&g->idx, g->khash, 0, 256) != 0)
        goto fail;
    return g;
fail:
    free(child);
    if (m != map)
        free(m);
    c5_group_free(g);
    return NULL;
}

int c5_group_size(const c5_group *g) { return g->nt; }
int c5_group_words(const c5_group *g) { return g->words; }
long c5_group_memo(const c5_group *g) { return g->nmemo; }

void c5_group_tree(const c5_group *g, int *parent, int *cell)
{
    for (int v = 0; v < g->nt; v++) {
        parent[v] = g->tpar[v];
        cell[v] = g->gcell[g->tloc[v]];
    }
}

/* Sum over the group's cells of the largest trie generation among the live nodes: a valid
 * lower bound on OPT(D) (each cell c needs maxGen(c) loads). */
static int fallback(const c5_group *g, const uint64_t *d)
{
    int mg[C5_BOUND_MAX_CELLS] = {0}, s = 0;
    for (int w = 0; w < g->words; w++)
        for (uint64_t b = d[w]; b; b &= b - 1) {
            int v = w * 64 + __builtin_ctzll(b);
            if (g->tgen[v] > mg[g->tloc[v]])
                mg[g->tloc[v]] = g->tgen[v];
        }
    for (int l = 0; l < g->k; l++)
        s += mg[l];
    return s;
}

/* Exact OPT of downset d (level = recursion depth, for the scratch rows); -1 over budget,
 * -2 out of memory. */
static int opt_rec(c5_group *g, const uint64_t *d, int level)
{
    int words = g->words, empty = 1;
    for (int w = 0; w < words && empty; w++)
        empty = d[w] == 0;
    if (empty)
        return 0;
    uint64_t h = c5_bits_hash(d, words);
    int s = g->idx.table[memo_slot(g, d, h)];
    if (s >= 0)
        return g->val[s];
    if (g->nmemo >= g->budget)
        return -1;
    /* live children counts, then the leaves of each cell */
    for (int w = 0; w < words; w++)
        for (uint64_t b = d[w]; b; b &= b - 1)
            g->livekids[w * 64 + __builtin_ctzll(b)] = 0;
    for (int w = 0; w < words; w++)
        for (uint64_t b = d[w]; b; b &= b - 1) {
            int v = w * 64 + __builtin_ctzll(b);
            if (g->tpar[v] >= 0)
                g->livekids[g->tpar[v]]++;
        }
    if (!g->stack) { /* the recursion's rows: allocated on first use */
        g->stack = malloc(((size_t)g->nt + 2) * (size_t)g->k * (size_t)words * sizeof *g->stack);
        if (!g->stack)
            return -2;
    }
    int nlive[C5_BOUND_MAX_CELLS] = {0}, nleaf[C5_BOUND_MAX_CELLS] = {0};
    uint64_t *rows = g->stack + (size_t)level * g->k * words;
    for (int l = 0; l < g->k; l++)
        memcpy(rows + (size_t)l * words, d, (size_t)words * 8);
    for (int w = 0; w < words; w++)
        for (uint64_t b = d[w]; b; b &= b - 1) {
            int v = w * 64 + __builtin_ctzll(b), l = g->tloc[v];
            nlive[l]++;
            if (g->livekids[v] == 0) {
                nleaf[l]++;
                rows[(size_t)l * words + w] &= ~(1ull << (v & 63));
            }
        }
    int only = -1;
    for (int l = 0; l < g->k && only < 0; l++)
        if (nlive[l] > 0 && nleaf[l] == nlive[l])
            only = l;
    int best = -1;
    for (int l = 0; l < g->k; l++) {
        if (nleaf[l] == 0 || (only >= 0 && l != only))
            continue;
        int v = opt_rec(g, rows + (size_t)l * words, level + 1);
        if (v < 0)
            return v;
        if (best < 0 || 1 + v < best)
            best = 1 + v;
    }
    if (memo_put(g, d, h, best) != 0)
        return -2;
    return best;
}

/* OPT of the projection restricted to downset d of the trie (words entries); exact when
 * *exact is set, otherwise (budget) the sum of maxGen of d. -1 out of memory. */
int c5_group_opt(c5_group *g, const uint64_t *d, int *exact)
{
    int v = opt_rec(g, d, 0);
    if (v == -2)
        return -1;
    if (exact)
        *exact = v >= 0;
    return v >= 0 ? v : fallback(g, d);
}

/* OPT of the whole projection (every trie node). */
static int group_root_opt(c5_group *g, int *exact)
{
    memset(g->probe, 0, (size_t)g->words * 8);
    for (int v = 0; v < g->nt; v++)
        g->probe[v >> 6] |= 1ull << (v & 63);
    return c5_group_opt(g, g->probe, exact);
}

/* ---- packing groups --------------------------------------------------------------------- */

typedef struct {
    uint64_t mask; /* local cell indices 0..m-1 */
    int gain;
} cand;

typedef struct {
    const cand *c;
    int nc, m;
    const int *first, *count; /* candidates by lowest member, sorted by lowest member */
    const int *ratio;         /* per cell: largest 12 * gain / size over its candidates */
    int best, cur;
    uint64_t best_pick[C5_BOUND_MAX_CELLS], pick[C5_BOUND_MAX_CELLS];
    int npick, best_npick;
    long nodes, max_nodes;
} packer;

/* Branch and bound over cells in order: each undecided cell stays single or starts one of
 * its candidates (every member undecided). Bound: 12 * current + the ratios left. */
static void pack_rec(packer *p, int u, uint64_t used, int rest12)
{
    if (++p->nodes > p->max_nodes)
        return;
    while (u < p->m && (used >> u & 1))
        u++;
    if (u >= p->m) {
        if (p->cur > p->best) {
            p->best = p->cur;
            p->best_npick = p->npick;
            memcpy(p->best_pick, p->pick, sizeof p->pick);
        }
        return;
    }
    if (12 * p->cur + rest12 <= 12 * p->best)
        return;
    for (int k = p->first[u]; k < p->first[u] + p->count[u]; k++) {
        const cand *c = &p->c[k];
        if (c->mask & used)
            continue;
        int r = 0;
        for (uint64_t b = c->mask; b; b &= b - 1)
            r += p->ratio[__builtin_ctzll(b)];
        p->cur += c->gain;
        p->pick[p->npick++] = c->mask;
        pack_rec(p, u + 1, used | c->mask, rest12 - r);
        p->npick--;
        p->cur -= c->gain;
    }
    pack_rec(p, u + 1, used | 1ull << u, rest12 - p->ratio[u]);
}

/* Best packing of candidates (by lowest member) on m cells: exact by dynamic programming
 * over subsets up to 16 cells, by branch and bound (node budget, greedy start) beyond.
 * Fills pick (masks), returns the total gain; -1 out of memory. */
static int pack(cand *c, int nc, int m, uint64_t *pick, int *npick)
{
    *npick = 0;
    if (nc == 0)
        return 0;
    /* sort by lowest member, then larger gain first */
    for (int i = 1; i < nc; i++) {
        cand x = c[i];
        int j = i - 1, lx = __builtin_ctzll(x.mask);
        while (j >= 0) {
            int lj = __builtin_ctzll(c[j].mask);
            if (lj < lx || (lj == lx && c[j].gain >= x.gain))
                break;
            c[j + 1] = c[j];
            j--;
        }
        c[j + 1] = x;
    }
    int first[C5_BOUND_MAX_CELLS] = {0}, count[C5_BOUND_MAX_CELLS] = {0};
    for (int i = nc - 1; i >= 0; i--) {
        int l = __builtin_ctzll(c[i].mask);
        first[l] = i;
        count[l]++;
    }
    if (m <= 16) {
        size_t full = (size_t)1 << m;
        int *f = malloc(full * sizeof *f), *how = malloc(full * sizeof *how);
        if (!f || !how) {
            free(f);
            free(how);
            return -1;
        }
        f[0] = 0;
        for (size_t mask = 1; mask < full; mask++) {
            int low = __builtin_ctzll(mask);
            f[mask] = f[mask & (mask - 1)];
            how[mask] = -1;
            for (int k = first[low]; k < first[low] + count[low]; k++)
                if ((c[k].mask & ~(uint64_t)mask) == 0 && c[k].gain + f[mask & ~c[k].mask] > f[mask]) {
                    f[mask] = c[k].gain + f[mask & ~c[k].mask];
                    how[mask] = k;
                }
        }
        int best = f[full - 1];
        for (size_t mask = full - 1; mask;) {
            if (how[mask] < 0) {
                mask &= mask - 1;
            } else {
                pick[(*npick)++] = c[how[mask]].mask;
                mask &= ~c[how[mask]].mask;
            }
        }
        free(f);
        free(how);
        return best;
    }
    int ratio[C5_BOUND_MAX_CELLS] = {0}, rest12 = 0;
    for (int i = 0; i < nc; i++) {
        int r = 12 * c[i].gain / __builtin_popcountll(c[i].mask) + 1; /* rounded up */
        for (uint64_t b = c[i].mask; b; b &= b - 1)
            if (r > ratio[__builtin_ctzll(b)])
                ratio[__builtin_ctzll(b)] = r;
    }
    for (int u = 0; u < m; u++)
        rest12 += ratio[u];
    packer p;
    memset(&p, 0, sizeof p);
    p.c = c;
    p.nc = nc;
    p.m = m;
    p.first = first;
    p.count = count;
    p.ratio = ratio;
    p.max_nodes = 2000000;
    /* greedy start: largest gain per cell first */
    uint64_t used = 0;
    for (;;) {
        int bi = -1;
        for (int i = 0; i < nc; i++)
            if (!(c[i].mask & used) &&
                (bi < 0 || c[i].gain * __builtin_popcountll(c[bi].mask) > c[bi].gain * __builtin_popcountll(c[i].mask)))
                bi = i;
        if (bi < 0)
            break;
        used |= c[bi].mask;
        p.best += c[bi].gain;
        p.best_pick[p.best_npick++] = c[bi].mask;
    }
    pack_rec(&p, 0, 0, rest12);
    memcpy(pick, p.best_pick, (size_t)p.best_npick * sizeof *pick);
    *npick = p.best_npick;
    return p.best;
}

/* ---- the bound ---------------------------------------------------------------------------- */

/* Bound with groups of up to max_group cells, each projection solved within `budget` memo
 * entries (over budget: the group is not used). groups_out (if not NULL, 64 entries)
 * receives the chosen groups as cell masks, singletons included, *ngroups_out their count.
 * Returns the bound (>= sum of maxGen), -1 when out of memory. (The longest root-to-leaf
 * path, another valid bound, never beats the sum of maxGen: a path holds each cell c at
 * most maxGen(c) times.) */
int c5_sched_bound_partition(const c5_dep_tree *t, int max_group, long budget, uint64_t *groups_out,
                             int *ngroups_out)
{
    if (!c5_tree_bound_cells(t))
        return -1;
    if (max_group > C5_GROUP_MAX)
        max_group = C5_GROUP_MAX;
    int n = t->n;
    int *gen = malloc((size_t)(n > 0 ? n : 1) * sizeof *gen);
    if (!gen || c5_tree_generations(t, gen) < 0) {
        free(gen);
        return -1;
    }
    int maxgen[C5_BOUND_MAX_CELLS] = {0}, sum = 0;
    uint64_t present = 0;
    for (int i = 0; i < n; i++) {
        int c = t->cell[i];
        present |= 1ull << c;
        if (gen[i] > maxgen[c])
            maxgen[c] = gen[i];
    }
    free(gen);
    int cellof[C5_BOUND_MAX_CELLS], m = 0;
    for (int c = 0; c < C5_BOUND_MAX_CELLS; c++)
        if (present >> c & 1) {
            cellof[m++] = c;
            sum += maxgen[c];
        }
    /* every group of 2..max_group present cells, by combinations of local indices */
    size_t ncap = 64, nc = 0;
    cand *cs = malloc(ncap * sizeof *cs);
    int rc = 0, idx[C5_GROUP_MAX];
    if (!cs)
        return -1;
    for (int size = 2; size <= max_group && size <= m && rc == 0; size++) {
        for (int j = 0; j < size; j++)
            idx[j] = j;
        for (;;) {
            uint64_t local = 0, cells = 0;
            int base = 0;
            for (int j = 0; j < size; j++) {
                local |= 1ull << idx[j];
                cells |= 1ull << cellof[idx[j]];
                base += maxgen[cellof[idx[j]]];
            }
            c5_group *g = c5_group_new(t, cells, budget, NULL);
            int exact = 0, v = g ? group_root_opt(g, &exact) : -1;
            c5_group_free(g);
            if (v < 0) {
                rc = -1;
                break;
            }
            if (exact && v > base) {
                if (nc == ncap) {
                    cand *bigger = realloc(cs, 2 * ncap * sizeof *cs);
                    if (!bigger) {
                        rc = -1;
                        break;
                    }
                    cs = bigger;
                    ncap *= 2;
                }
                cs[nc].mask = local;
                cs[nc].gain = v - base;
                nc++;
            }
            int j = size - 1;
            while (j >= 0 && idx[j] == m - size + j)
                j--;
            if (j < 0)
                break;
            idx[j]++;
            for (int q = j + 1; q < size; q++)
                idx[q] = idx[q - 1] + 1;
        }
    }
    uint64_t pick[C5_BOUND_MAX_CELLS];
    int npick = 0, gain = rc == 0 ? pack(cs, (int)nc, m, pick, &npick) : -1;
    free(cs);
    if (gain < 0)
        return -1;
    if (groups_out) {
        uint64_t covered = 0;
        int k = 0;
        for (int q = 0; q < npick; q++) {
            uint64_t cells = 0;
            for (uint64_t b = pick[q]; b; b &= b - 1)
                cells |= 1ull << cellof[__builtin_ctzll(b)];
            groups_out[k++] = cells;
            covered |= pick[q];
        }
        for (int u = 0; u < m; u++)
            if (!(covered >> u & 1))
                groups_out[k++] = 1ull << cellof[u];
        *ngroups_out = k;
    }
    return sum + gain;
}

int c5_sched_lower_bound_groups(const c5_dep_tree *t, int max_group, long budget)
{
    return c5_sched_bound_partition(t, max_group, budget, NULL, NULL);
}

int c5_sched_lower_bound_pairs(const c5_dep_tree *t) { return c5_sched_bound_partition(t, 2, 100000, NULL, NULL); }

/* ---- big groups ------------------------------------------------------------------------------ */

int c5_sched_lower_bound_split(const c5_dep_tree *t, const uint64_t *groups, int ngroups, long max_states,
                               int *all_exact)
{
    uint64_t seen = 0;
    int sum = 0, exact = 1;
    if (!c5_tree_bound_cells(t))
        return -1;
    for (int k = 0; k < ngroups; k++) {
        if (groups[k] & seen)
            return -1; /* not disjoint: the loads would be counted twice */
        seen |= groups[k];
        /* a group none of whose cells is in the tree projects onto nothing */
        c5_exact_opts o = {max_states, 0x7fffffff, 1, C5_EXACT_GROUPS_DEFAULT, 0, NULL, 0};
        c5_exact_stats st;
        c5_err err;
        int len = 0, rc = c5_sched_projection_optimum(t, groups[k], &o, &len, &st, &err);
        if (rc < 0)
            return -1;
        sum += rc == 1 ? len : st.lower;
        exact &= rc == 1;
    }
    /* the cells of no group count their maxGen */
    int *gen = malloc((size_t)(t->n > 0 ? t->n : 1) * sizeof *gen);
    if (!gen || c5_tree_generations(t, gen) < 0) {
        free(gen);
        return -1;
    }
    int maxgen[C5_BOUND_MAX_CELLS] = {0};
    for (int i = 0; i < t->n; i++)
        if (!(seen >> t->cell[i] & 1) && gen[i] > maxgen[t->cell[i]])
            maxgen[t->cell[i]] = gen[i];
    free(gen);
    for (int c = 0; c < C5_BOUND_MAX_CELLS; c++)
        sum += maxgen[c];
    if (all_exact)
        *all_exact = exact;
    return sum;
}
