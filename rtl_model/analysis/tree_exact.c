/* The exact optimum schedule of a Cell Tree: A* over interim trees, in peel (reverse)
 * direction.
 *
 * State: the set of nodes not yet peeled. It is ancestor-closed, so it is a tree again; it
 * is stored as an n-bit set in one arena and found again through a hash table keyed by the
 * bits. Action: peel cell c (it must have a leaf), cost 1. Goal: the empty set.
 *
 * Heuristic h = max(h1, h2).
 * h1 = sum over cells of maxGen + 1 when the state is non-empty and no cell is ready.
 * Admissible without any claim from the paper: a peel lowers maxGen(c) by at most one and
 * only for the peeled cell, and only when c is ready; so with no ready cell the next peel
 * lowers nothing and one more peel than the sum is needed. It is even consistent
 * (h1(S) <= 1 + h1(S') for every peel: with the +1 in S no peel lowers the sum; without it
 * the sum drops by at most one).
 * h2 = the projection heuristic (hpart below): exact optima of the state's projections onto
 * a fixed partition of the cells, also consistent. A maximum of consistent heuristics is
 * consistent, so a state's g is final when it is expanded; a state still waiting in the
 * open list may be reached again more cheaply, which pushes a new entry and leaves the old
 * one to be skipped. (Should h2 lose consistency, through a group over its memo budget,
 * a closed state reached more cheaply is opened again the same way: the search stays
 * exact with any admissible h.)
 *
 * The search also runs on projections (c5_sched_projection_optimum, for tree_bound.c),
 * where a node may have a child of its own cell; successor_h covers that case.
 *
 * Two reductions keep the search exact:
 *  - a cell whose live nodes are all leaves is the only action expanded (peeling it first is
 *    optimal, proof at first_ready in tree_sched.c). The paper's wider claim, that any ready
 *    cell may be peeled first, is false and is NOT used;
 *  - the rollout rule's schedule (length U) is an upper bound: successors with f >= U are
 *    never stored, and when the open list runs dry nothing shorter than U exists.
 * Both are checked by tests/test_tree_sched.c against a forward brute force.
 *
 * The open list prefers smaller f, then larger g (deeper states finish tight instances
 * fast), then the newest entry; every key is an integer, so the search is deterministic. */
#include "bitset_index.h"
#include "tree_analysis.h"

#include <stdlib.h>
#include <string.h>

/* ---- the projection heuristic ------------------------------------------------------------
 *
 * The cells are split into disjoint groups (the packing c5_sched_bound_partition picks for
 * the whole tree); h = sum over groups G of OPT(R|G), the exact optimum of the state R
 * projected onto G (tree_bound.c), which is at most OPT(R) (Claim 2 there). A group over its
 * memo budget counts its sum of maxGen instead, which is still a lower bound.
 * Consistent: a peel of c removes leaves of c only, so the projections onto the groups
 * without c do not change, and R'|G (G the group of c) is R|G minus some of its leaves of
 * cell c (a removed node's trie node goes when its last live preimage goes, and it is then a
 * leaf of R|G: its preimages were leaves of R). A schedule of R'|G followed by one load of c
 * serves R|G, so OPT(R|G) <= 1 + OPT(R'|G). (The fallback may break consistency; the search
 * re-opens a state reached more cheaply, so it stays exact with any admissible h.)
 *
 * The state's projections are rebuilt from its node bitset at each expansion (O(n)); a
 * successor changes only its peeled cell's group: its live-preimage counts are lowered for
 * the peeled leaves, the group's optimum looked up (memoized), and the counts restored. */
typedef struct {
    int ng, n;
    const int *cell;
    c5_group *g[C5_BOUND_MAX_CELLS];
    int gof[C5_BOUND_MAX_CELLS];      /* group of each cell, -1: absent */
    int toff[C5_BOUND_MAX_CELLS + 1]; /* offsets of the groups' trie nodes in cnt */
    int woff[C5_BOUND_MAX_CELLS + 1]; /* offsets of the groups' bitsets in bits */
    int *tnode;                       /* [n] global trie node (toff[g] + local) of each node */
    int *cnt;                         /* live preimages per trie node */
    uint64_t *bits, *scratch;         /* per group downsets; one group's copy */
    int val[C5_BOUND_MAX_CELLS], total;
} hpart;

static void hpart_free(hpart *h)
{
    for (int k = 0; k < h->ng; k++)
        c5_group_free(h->g[k]);
    free(h->tnode);
    free(h->cnt);
    free(h->bits);
    free(h->scratch);
    memset(h, 0, sizeof *h);
}

/* 0, or -1 when out of memory. */
static int hpart_init(hpart *h, const c5_dep_tree *t, const uint64_t *groups, int ng, long budget)
{
    memset(h, 0, sizeof *h);
    h->n = t->n;
    h->cell = t->cell;
    for (int c = 0; c < C5_BOUND_MAX_CELLS; c++)
        h->gof[c] = -1;
    size_t sz = (size_t)(t->n > 0 ? t->n : 1);
    int *map = malloc(sz * sizeof *map);
    h->tnode = malloc(sz * sizeof *h->tnode);
    if (!map || !h->tnode) {
        free(map);
        return -1;
    }
    int maxw = 1;
    for (int k = 0; k < ng; k++) {
        h->g[k] = c5_group_new(t, groups[k], budget, map);
        if (!h->g[k]) {
            free(map);
            hpart_free(h);
            return -1;
        }
        h->ng = k + 1;
        for (int c = 0; c < C5_BOUND_MAX_CELLS; c++)
            if (groups[k] >> c & 1)
                h->gof[c] = k;
        for (int i = 0; i < t->n; i++)
            if (h->gof[t->cell[i]] == k)
                h->tnode[i] = h->toff[k] + map[i];
        h->toff[k + 1] = h->toff[k] + c5_group_size(h->g[k]);
        h->woff[k + 1] = h->woff[k] + c5_group_words(h->g[k]);
        if (c5_group_words(h->g[k]) > maxw)
            maxw = c5_group_words(h->g[k]);
    }
    free(map);
    h->cnt = malloc((size_t)(h->toff[ng] > 0 ? h->toff[ng] : 1) * sizeof *h->cnt);
    h->bits = malloc((size_t)(h->woff[ng] > 0 ? h->woff[ng] : 1) * sizeof *h->bits);
    h->scratch = malloc((size_t)maxw * sizeof *h->scratch);
    if (!h->cnt || !h->bits || !h->scratch) {
        hpart_free(h);
        return -1;
    }
    return 0;
}

/* Loads the state b; returns its h (-1: out of memory). */
static int hpart_load(hpart *h, const uint64_t *b)
{
    memset(h->cnt, 0, (size_t)h->toff[h->ng] * sizeof *h->cnt);
    memset(h->bits, 0, (size_t)h->woff[h->ng] * sizeof *h->bits);
    for (int w = 0; w * 64 < h->n; w++)
        for (uint64_t x = b[w]; x; x &= x - 1) {
            int i = w * 64 + __builtin_ctzll(x), v = h->tnode[i];
            if (h->cnt[v]++ == 0) {
                int k = h->gof[h->cell[i]], local = v - h->toff[k];
                h->bits[h->woff[k] + (local >> 6)] |= 1ull << (local & 63);
            }
        }
    h->total = 0;
    for (int k = 0; k < h->ng; k++) {
        if ((h->val[k] = c5_group_opt(h->g[k], h->bits + h->woff[k], NULL)) < 0)
            return -1;
        h->total += h->val[k];
    }
    return h->total;
}

/* h of the loaded state without these leaves (all of cell c); -1: out of memory. */
static int hpart_without(hpart *h, int c, const int *leaves, int count)
{
    int k = h->gof[c];
    int words = h->woff[k + 1] - h->woff[k];
    memcpy(h->scratch, h->bits + h->woff[k], (size_t)words * sizeof *h->scratch);
    for (int q = 0; q < count; q++) {
        int v = h->tnode[leaves[q]];
        if (--h->cnt[v] == 0) {
            int local = v - h->toff[k];
            h->scratch[local >> 6] &= ~(1ull << (local & 63));
        }
    }
    for (int q = 0; q < count; q++)
        h->cnt[h->tnode[leaves[q]]]++;
    int v = c5_group_opt(h->g[k], h->scratch, NULL);
    return v < 0 ? -1 : h->total - h->val[k] + v;
}

typedef struct {
    int f, g, state;
    unsigned seq;
} open_entry;

typedef struct {
    int n, words;
    const int *parent, *cell;
    int *gen;
    /* the arena: states 0..nstates-1 */
    uint64_t *bits;  /* [cap * words] */
    int *g, *back;   /* best g found, predecessor state */
    uint8_t *action; /* the cell peeled to get here from back */
    uint64_t *hash;
    long nstates, cap, max_states;
    c5_bsidx idx; /* finds a state's bits again */
    open_entry *heap;
    size_t nheap, heapcap;
    unsigned seq;
    /* scratch for one expansion */
    uint64_t *cur, *next;
    int *livekids, *leaves; /* leaves: grouped by cell, [lstart[c], lstart[c] + nleaf[c]) */
    hpart *hp;              /* the projection heuristics (nhp partitions; h is their maximum) */
    int nhp;                /* 0: sum of maxGen only */
    long expanded;
    int root_h, lower; /* h at the root; on giving up, the least f still open */
} astar;


static int heap_before(const open_entry *a, const open_entry *b)
{
    if (a->f != b->f)
        return a->f < b->f;
    if (a->g != b->g)
        return a->g > b->g;
    return a->seq > b->seq;
}

static int heap_push(astar *a, int f, int g, int state)
{
    if (a->nheap == a->heapcap) {
        size_t cap = a->heapcap ? 2 * a->heapcap : 1024;
        open_entry *h = realloc(a->heap, cap * sizeof *h);
        if (!h)
            return -1;
        a->heap = h;
        a->heapcap = cap;
    }
    size_t k = a->nheap++;
    open_entry e = {f, g, state, a->seq++};
    while (k > 0 && heap_before(&e, &a->heap[(k - 1) / 2])) {
        a->heap[k] = a->heap[(k - 1) / 2];
        k = (k - 1) / 2;
    }
    a->heap[k] = e;
    return 0;
}

static open_entry heap_pop(astar *a)
{
    open_entry top = a->heap[0], last = a->heap[--a->nheap];
    size_t k = 0, n = a->nheap;
    for (;;) {
        size_t c = 2 * k + 1;
        if (c >= n)
            break;
        if (c + 1 < n && heap_before(&a->heap[c + 1], &a->heap[c]))
            c++;
        if (!heap_before(&a->heap[c], &last))
            break;
        a->heap[k] = a->heap[c];
        k = c;
    }
    if (n > 0)
        a->heap[k] = last;
    return top;
}

static int table_grow(astar *a)
{
    return c5_bsidx_grow(&a->idx, a->hash, a->nstates, 4096);
}

/* Slot of the state with these bits, or of the empty slot where it would go. */
static size_t table_find(const astar *a, const uint64_t *b, uint64_t h)
{
    return c5_bsidx_find(&a->idx, a->bits, a->hash, a->words, b, h);
}

/* Appends a state; 1 = stored, 0 = over budget, -1 = out of memory. */
static int arena_add(astar *a, const uint64_t *b, uint64_t h, int g, int back, int action, size_t slot)
{
    if (a->nstates >= a->max_states)
        return 0;
    if (a->nstates == a->cap) {
        long cap = a->cap ? 2 * a->cap : 1024;
        if (cap > a->max_states)
            cap = a->max_states;
        uint64_t *bits = realloc(a->bits, (size_t)cap * a->words * sizeof *bits);
        if (bits)
            a->bits = bits;
        int *gg = realloc(a->g, (size_t)cap * sizeof *gg);
        if (gg)
            a->g = gg;
        int *bk = realloc(a->back, (size_t)cap * sizeof *bk);
        if (bk)
            a->back = bk;
        uint8_t *ac = realloc(a->action, (size_t)cap);
        if (ac)
            a->action = ac;
        uint64_t *hh = realloc(a->hash, (size_t)cap * sizeof *hh);
        if (hh)
            a->hash = hh;
        if (!bits || !gg || !bk || !ac || !hh)
            return -1;
        a->cap = cap;
    }
    long s = a->nstates++;
    memcpy(a->bits + (size_t)s * a->words, b, (size_t)a->words * 8);
    a->g[s] = g;
    a->back[s] = back;
    a->action[s] = (uint8_t)action;
    a->hash[s] = h;
    a->idx.table[slot] = (int)s;
    if (c5_bsidx_after_store(&a->idx, a->hash, a->nstates) != 0)
        return -1;
    return 1;
}

/* Per-cell summary of one state, enough to score every successor without rebuilding it. */
typedef struct {
    int maxgen[C5_BOUND_MAX_CELLS];
    int block_top[C5_BOUND_MAX_CELLS];  /* non-leaf nodes at generation maxGen */
    int block_next[C5_BOUND_MAX_CELLS]; /* non-leaf nodes at generation maxGen - 1 */
    int nleaf[C5_BOUND_MAX_CELLS], lstart[C5_BOUND_MAX_CELLS + 1];
    int nlive[C5_BOUND_MAX_CELLS];
    int sum, live;
} summary;

/* A cell whose live nodes are all leaves, or -1. Some optimal schedule peels it first
 * (proof at first_ready in tree_sched.c; tested against brute force), so the searches
 * expand only that one. */
static int full_leaf_cell(const summary *s)
{
    for (int c = 0; c < C5_BOUND_MAX_CELLS; c++)
        if (s->nlive[c] > 0 && s->nleaf[c] == s->nlive[c])
            return c;
    return -1;
}

static void summarize(astar *a, const uint64_t *b, summary *s)
{
    memset(s, 0, sizeof *s);
    memset(a->livekids, 0, (size_t)a->n * sizeof *a->livekids);
    for (int i = 0; i < a->n; i++)
        if (b[i >> 6] >> (i & 63) & 1) {
            s->live++;
            s->nlive[a->cell[i]]++;
            if (a->parent[i] >= 0)
                a->livekids[a->parent[i]]++;
            if (a->gen[i] > s->maxgen[a->cell[i]])
                s->maxgen[a->cell[i]] = a->gen[i];
        }
    for (int i = 0; i < a->n; i++)
        if (b[i >> 6] >> (i & 63) & 1) {
            int c = a->cell[i], d = s->maxgen[c] - a->gen[i];
            if (a->livekids[i] == 0)
                s->nleaf[c]++;
            else if (d == 0)
                s->block_top[c]++;
            else if (d == 1)
                s->block_next[c]++;
        }
    for (int c = 0; c < C5_BOUND_MAX_CELLS; c++) {
        s->lstart[c + 1] = s->lstart[c] + s->nleaf[c];
        s->sum += s->maxgen[c];
    }
    int fill[C5_BOUND_MAX_CELLS];
    memcpy(fill, s->lstart, sizeof fill);
    for (int i = 0; i < a->n; i++)
        if ((b[i >> 6] >> (i & 63) & 1) && a->livekids[i] == 0)
            a->leaves[fill[a->cell[i]]++] = i;
}

static int is_ready(const summary *s, int c) { return s->maxgen[c] > 0 && s->block_top[c] == 0; }

static int state_h(const summary *s)
{
    int any = 0;
    for (int c = 0; c < C5_BOUND_MAX_CELLS && !any; c++)
        any = is_ready(s, c);
    return s->sum + (s->live > 0 && !any);
}

/* h of the state reached by peeling c (whose leaves are listed in s), from s alone. Peeling
 * c lowers maxGen(c) iff c is ready (its maxGen nodes are all leaves and go), and by one
 * only: each removed maxGen node G has a same-cell ancestor of generation G - 1, which is
 * no leaf. Another cell d is ready afterwards iff it was, or the peel turns its last
 * blocking (non-leaf) maxGen node into a leaf (its maxGen does not change). c itself:
 *  - not ready before: not ready after (a blocking maxGen node of c has no child of cell c,
 *    which would be of a higher generation, so it keeps its children);
 *  - ready before, maxGen G >= 2: ready after iff every non-leaf node of c of generation
 *    G - 1 loses all its children. In a Cell Tree a child never has its parent's cell, so
 *    such a node keeps the other-cell node between it and the removed one: never. In a
 *    projection (tree_bound.c: a -> x -> a becomes a -> a) it can happen.
 * livekids is restored before returning. The search checks this against state_h at every
 * expansion. */
static int successor_h(astar *a, const summary *s, int c)
{
    int sum = s->sum - is_ready(s, c), live = s->live - s->nleaf[c];
    if (live == 0)
        return sum;
    int any = 0;
    for (int d = 0; d < C5_BOUND_MAX_CELLS && !any; d++)
        any = d != c && is_ready(s, d);
    int block[C5_BOUND_MAX_CELLS];
    const int *lv = a->leaves + s->lstart[c];
    if (!any) {
        memcpy(block, s->block_top, sizeof block);
        int gc = s->maxgen[c], next = is_ready(s, c) && gc >= 2 ? s->block_next[c] : -1;
        for (int k = 0; k < s->nleaf[c]; k++) {
            int q = a->parent[lv[k]];
            if (q < 0 || --a->livekids[q] != 0)
                continue;
            int cq = a->cell[q];
            if (cq != c && a->gen[q] == s->maxgen[cq] && --block[cq] == 0)
                any = 1;
            if (cq == c && next > 0 && a->gen[q] == gc - 1)
                next--;
        }
        if (next == 0)
            any = 1;
        for (int k = 0; k < s->nleaf[c]; k++) {
            int q = a->parent[lv[k]];
            if (q >= 0)
                a->livekids[q]++;
        }
    }
    return sum + !any;
}

/* h of the state summarized in s (and, for the projection heuristic, in a->cur), which
 * loads the state into a->hp; -1 out of memory. */
static int full_h(astar *a, const summary *s)
{
    int h = state_h(s);
    for (int p = 0; p < a->nhp; p++) {
        int hg = hpart_load(&a->hp[p], a->cur);
        if (hg < 0)
            return -1;
        if (hg > h)
            h = hg;
    }
    return h;
}

static void astar_free(astar *a)
{
    free(a->gen);
    free(a->bits);
    free(a->g);
    free(a->back);
    free(a->action);
    free(a->hash);
    c5_bsidx_free(&a->idx);
    free(a->heap);
    free(a->cur);
    free(a->next);
    free(a->livekids);
    free(a->leaves);
}

/* 1 found, 2 nothing shorter than ub exists, 0 over budget, -1 out of memory, -2 the
 * incremental heuristic disagrees with the state's own (a bug). */
static int search(astar *a, int ub, int *len_out, int **sched_out)
{
    summary s;
    memset(a->cur, 0, (size_t)a->words * 8);
    for (int i = 0; i < a->n; i++)
        a->cur[i >> 6] |= 1ull << (i & 63);
    uint64_t h0 = c5_bits_hash(a->cur, a->words);
    int rc = arena_add(a, a->cur, h0, 0, -1, 0, table_find(a, a->cur, h0));
    if (rc <= 0)
        return rc;
    summarize(a, a->cur, &s);
    int h_root = full_h(a, &s);
    if (h_root < 0)
        return -1;
    a->root_h = h_root;
    if (h_root >= ub)
        return 2;
    if (heap_push(a, h_root, 0, 0) != 0)
        return -1;
    while (a->nheap > 0) {
        open_entry e = heap_pop(a);
        if (e.g != a->g[e.state])
            continue; /* superseded by a cheaper path to the same state */
        memcpy(a->cur, a->bits + (size_t)e.state * a->words, (size_t)a->words * 8);
        summarize(a, a->cur, &s);
        int h_here = full_h(a, &s);
        if (h_here < 0)
            return -1;
        if (h_here != e.f - e.g)
            return -2; /* the successor's h is checked against the full count at every expansion */
        a->expanded++;
        if (s.live == 0) {
            *len_out = e.g;
            if (sched_out) {
                int *out = malloc((size_t)(e.g > 0 ? e.g : 1) * sizeof *out);
                if (!out)
                    return -1;
                /* Walking back from the goal meets the last peel first: that is the
                 * forward (load) order. */
                int k = 0;
                for (int st = e.state; a->back[st] >= 0; st = a->back[st])
                    out[k++] = a->action[st];
                *sched_out = out;
            }
            return 1;
        }
        int only = full_leaf_cell(&s);
        for (int c = 0; c < C5_BOUND_MAX_CELLS; c++) {
            if (s.nleaf[c] == 0 || (only >= 0 && c != only))
                continue;
            memcpy(a->next, a->cur, (size_t)a->words * 8);
            const int *lv = a->leaves + s.lstart[c];
            for (int k = 0; k < s.nleaf[c]; k++)
                a->next[lv[k] >> 6] &= ~(1ull << (lv[k] & 63));
            int hs = successor_h(a, &s, c);
            for (int p = 0; p < a->nhp; p++) {
                int hg = hpart_without(&a->hp[p], c, lv, s.nleaf[c]);
                if (hg < 0)
                    return -1;
                if (hg > hs)
                    hs = hg;
            }
            int g = e.g + 1, f = g + hs;
            if (f >= ub)
                continue; /* cannot beat the heuristic schedule: never stored */
            uint64_t h = c5_bits_hash(a->next, a->words);
            size_t slot = table_find(a, a->next, h);
            int st = a->idx.table[slot];
            if (st < 0) {
                rc = arena_add(a, a->next, h, g, e.state, c, slot);
                if (rc == 0) {
                    /* Giving up. Some state on an optimal path, reached by an optimal g,
                     * is waiting (or is e): its f <= OPT, so the least f is a bound. */
                    a->lower = e.f;
                    for (size_t k = 0; k < a->nheap; k++)
                        if (a->heap[k].f < a->lower)
                            a->lower = a->heap[k].f;
                    return 0;
                }
                if (rc < 0)
                    return rc;
                st = (int)(a->nstates - 1);
            } else if (g < a->g[st]) {
                a->g[st] = g; /* waiting in the open list, reached more cheaply */
                a->back[st] = e.state;
                a->action[st] = (uint8_t)c;
            } else {
                continue;
            }
            if (heap_push(a, f, g, st) != 0)
                return -1;
        }
    }
    return 2;
}

/* The largest group size up to max whose packing costs at most about 1e8 node visits: every
 * group of k of the m cells present is projected in O(n). */
static int group_size(const c5_dep_tree *t, int max)
{
    uint64_t present = 0;
    for (int i = 0; i < t->n; i++)
        present |= 1ull << t->cell[i];
    int m = __builtin_popcountll(present), k = 1;
    double groups = (double)m; /* C(m, k) */
    while (k < max && k < m) {
        double next = groups * (m - k) / (k + 1);
        if (next * (t->n + 64) > 1e8)
            break;
        groups = next;
        k++;
    }
    return k;
}

/* The search on t, which passed c5_tree_check, or is a projection (a trie: parent[i] < i,
 * sibling cells distinct, a child may have its parent's cell), where `projection` is set:
 * then the rollout rule (whose peel walk assumes no such child) is not run. */
/* ---- beam search: a schedule, not a proof --------------------------------------------------
 *
 * Level by level in peel direction, keeping the `width` successors with the least h (ties:
 * fewer live nodes, then generation order); a state met on an earlier level is dropped.
 * Every kept state is stored in the arena (for the schedule's back pointers). */
typedef struct {
    int h, live, back, action;
    uint64_t hash;
    size_t off; /* bits in the candidate buffer */
} beam_cand;

static int beam_cmp(const void *x, const void *y)
{
    const beam_cand *a = x, *b = y;
    if (a->h != b->h)
        return a->h < b->h ? -1 : 1;
    if (a->live != b->live)
        return a->live < b->live ? -1 : 1;
    return a->off < b->off ? -1 : a->off > b->off;
}

static int beam(astar *a, int width, int *len_out, int **sched_out)
{
    summary s;
    int rc = -1;
    size_t ccap = (size_t)width * 8;
    beam_cand *cand = malloc(ccap * sizeof *cand);
    uint64_t *cbits = malloc(ccap * (size_t)a->words * 8);
    int *level = malloc((size_t)width * sizeof *level);
    if (!cand || !cbits || !level)
        goto out;
    memset(a->cur, 0, (size_t)a->words * 8);
    for (int i = 0; i < a->n; i++)
        a->cur[i >> 6] |= 1ull << (i & 63);
    uint64_t h0 = c5_bits_hash(a->cur, a->words);
    if ((rc = arena_add(a, a->cur, h0, 0, -1, 0, table_find(a, a->cur, h0))) <= 0)
        goto out;
    level[0] = 0;
    int nlevel = 1;
    for (int depth = 0;; depth++) {
        size_t nc = 0;
        for (int q = 0; q < nlevel; q++) {
            int st = level[q];
            memcpy(a->cur, a->bits + (size_t)st * a->words, (size_t)a->words * 8);
            summarize(a, a->cur, &s);
            if (full_h(a, &s) < 0) {
                rc = -1;
                goto out;
            }
            a->expanded++;
            if (s.live == 0) {
                *len_out = depth;
                if (sched_out) {
                    int *outs = malloc((size_t)(depth > 0 ? depth : 1) * sizeof *outs);
                    if (!outs) {
                        rc = -1;
                        goto out;
                    }
                    int k = 0;
                    for (int x = st; a->back[x] >= 0; x = a->back[x])
                        outs[k++] = a->action[x];
                    *sched_out = outs;
                }
                rc = 1;
                goto out;
            }
            int only = full_leaf_cell(&s);
            for (int c = 0; c < C5_BOUND_MAX_CELLS; c++) {
                if (s.nleaf[c] == 0 || (only >= 0 && c != only))
                    continue;
                if (nc == ccap) {
                    beam_cand *nc2 = realloc(cand, 2 * ccap * sizeof *cand);
                    if (nc2)
                        cand = nc2;
                    uint64_t *nb = realloc(cbits, 2 * ccap * (size_t)a->words * 8);
                    if (nb)
                        cbits = nb;
                    if (!nc2 || !nb) {
                        rc = -1;
                        goto out;
                    }
                    ccap *= 2;
                }
                uint64_t *nb = cbits + nc * a->words;
                memcpy(nb, a->cur, (size_t)a->words * 8);
                const int *lv = a->leaves + s.lstart[c];
                for (int k = 0; k < s.nleaf[c]; k++)
                    nb[lv[k] >> 6] &= ~(1ull << (lv[k] & 63));
                uint64_t hh = c5_bits_hash(nb, a->words);
                if (a->idx.table[table_find(a, nb, hh)] >= 0)
                    continue; /* met on an earlier level */
                int hs = successor_h(a, &s, c);
                for (int p = 0; p < a->nhp; p++) {
                    int hg = hpart_without(&a->hp[p], c, lv, s.nleaf[c]);
                    if (hg < 0) {
                        rc = -1;
                        goto out;
                    }
                    if (hg > hs)
                        hs = hg;
                }
                cand[nc] = (beam_cand){hs, s.live - s.nleaf[c], st, c, hh, nc};
                nc++;
            }
        }
        qsort(cand, nc, sizeof *cand, beam_cmp);
        nlevel = 0;
        for (size_t k = 0; k < nc && nlevel < width; k++) {
            const uint64_t *nb = cbits + cand[k].off * a->words;
            size_t slot = table_find(a, nb, cand[k].hash);
            if (a->idx.table[slot] >= 0)
                continue; /* the same state twice on this level */
            if ((rc = arena_add(a, nb, cand[k].hash, depth + 1, cand[k].back, cand[k].action, slot)) <= 0)
                goto out;
            level[nlevel++] = (int)(a->nstates - 1);
        }
        if (nlevel == 0) {
            rc = 0;
            goto out;
        }
    }
out:
    free(cand);
    free(cbits);
    free(level);
    return rc;
}

/* The caller's heuristic partitions (c5_exact_opts.groups): disjoint within each, at most
 * C5_EXACT_MAX_PARTS of them. 0, or -1 with a message. */
static int check_parts(const c5_exact_opts *o, c5_err *err)
{
    uint64_t used = 0;
    int parts = 0, open = 0;
    for (int q = 0; q < o->ngroups; q++) {
        if (o->groups[q] == 0) {
            parts += open;
            open = 0;
            used = 0;
            continue;
        }
        if (o->groups[q] & used)
            return c5_fail(err, "cell tree optimum: heuristic groups overlap within a partition (group %d)", q);
        used |= o->groups[q];
        open = 1;
    }
    if (parts + open > C5_EXACT_MAX_PARTS)
        return c5_fail(err, "cell tree optimum: %d heuristic partitions, at most %d", parts + open,
                       C5_EXACT_MAX_PARTS);
    return 0;
}

static int solve(const c5_dep_tree *t, const c5_exact_opts *o, int projection, int beam_width, int *len_out,
                 int **sched_out, c5_exact_stats *stats, c5_err *err)
{
    if (sched_out)
        *sched_out = NULL;
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (!c5_tree_bound_cells(t))
        return c5_fail(err, "cell tree optimum: a cell id above %d: the exact and beam searches take up to %d cells "
                            "(C5_BOUND_MAX_CELLS)", C5_BOUND_MAX_CELLS - 1, C5_BOUND_MAX_CELLS);
    if (check_parts(o, err) != 0)
        return -1;
    long max_states = o->max_states;
    if (t->n > o->max_nodes || max_states < 1)
        return 0;
    if (max_states > 0x7fffffffL)
        max_states = 0x7fffffffL; /* states are numbered by int */
    /* The rollout rule's schedule is an upper bound: states that cannot beat it are not
     * stored, and when none can, it is the optimum. Without it (or should it ever be
     * infeasible) the bound is n + 1: every peel removes a node, so n peels always do. */
    c5_schedule heur;
    memset(&heur, 0, sizeof heur);
    int ub = t->n + 1;
    if (o->use_rollout_ub && !projection) {
        if (c5_sched_celltree(t, C5_SPLIT_ROLLOUT, &heur, err) != 0)
            return -1;
        if (c5_sched_feasible(t, heur.cells, heur.len) == 1)
            ub = heur.len;
    }
    astar a;
    hpart hp[C5_EXACT_MAX_PARTS];
    memset(&a, 0, sizeof a);
    memset(hp, 0, sizeof hp);
    a.hp = hp;
    int rc = -1;
    long budget = o->group_budget > 0 ? o->group_budget : max_states;
    if (o->ngroups > 0) {
        /* the caller's partitions, separated by 0 (checked disjoint: Claim 2 needs it) */
        int first = 0;
        for (int q = 0; q <= o->ngroups; q++) {
            if (q < o->ngroups && o->groups[q] != 0)
                continue;
            if (q > first) {
                if (hpart_init(&hp[a.nhp], t, o->groups + first, q - first, budget) != 0)
                    goto done;
                a.nhp++;
            }
            first = q + 1;
        }
    } else {
        int k = group_size(t, o->group_max);
        if (k >= 2) {
            uint64_t groups[C5_BOUND_MAX_CELLS];
            int ng = 0;
            int lb = c5_sched_bound_partition(t, k, budget < 20000 ? budget : 20000, groups, &ng);
            if (lb < 0 || hpart_init(&hp[0], t, groups, ng, budget) != 0)
                goto done;
            a.nhp = 1;
        }
    }
    a.n = t->n;
    a.words = t->n > 0 ? (t->n + 63) / 64 : 1;
    a.parent = t->parent;
    a.cell = t->cell;
    a.max_states = max_states;
    size_t sz = (size_t)(t->n > 0 ? t->n : 1);
    a.gen = malloc(sz * sizeof *a.gen);
    a.livekids = malloc(sz * sizeof *a.livekids);
    a.leaves = malloc(sz * sizeof *a.leaves);
    a.cur = malloc((size_t)a.words * 8);
    a.next = malloc((size_t)a.words * 8);
    if (a.gen && a.livekids && a.leaves && a.cur && a.next && c5_tree_generations(t, a.gen) >= 0 &&
        table_grow(&a) == 0)
        rc = beam_width > 0 ? beam(&a, beam_width, len_out, sched_out) : search(&a, ub, len_out, sched_out);
done:
    if (stats) {
        stats->states = a.nstates;
        stats->expanded = a.expanded;
        stats->root_h = a.root_h;
        stats->lower = rc == 0 ? a.lower : rc == 2 ? ub : rc == 1 ? *len_out : 0;
        for (int p = 0; p < a.nhp; p++)
            for (int k = 0; k < hp[p].ng; k++)
                stats->memo += c5_group_memo(hp[p].g[k]);
    }
    astar_free(&a);
    for (int p = 0; p < a.nhp; p++)
        hpart_free(&hp[p]);
    if (beam_width > 0 && ub <= t->n && (rc == 0 || (rc == 1 && ub < *len_out))) {
        /* the beam died out (every successor met before) or the rollout rule did better */
        if (sched_out) {
            free(*sched_out);
            *sched_out = NULL;
        }
        rc = 2;
    }
    if (rc == 2 && ub > t->n) {
        c5_schedule_free(&heur); /* cannot happen: n peels always empty the tree */
        return c5_fail(err, "cell tree optimum: search ended without a schedule");
    }
    if (rc == 2) { /* nothing beats the rollout schedule */
        *len_out = heur.len;
        if (sched_out) {
            *sched_out = heur.cells;
            heur.cells = NULL;
        }
        rc = 1;
    }
    c5_schedule_free(&heur);
    if (rc == -2)
        return c5_fail(err, "cell tree optimum: incremental heuristic disagrees with the state's");
    if (rc < 0)
        return c5_fail(err, "cell tree optimum: out of memory (%d nodes)", t->n);
    return rc;
}

int c5_sched_optimum_ex(const c5_dep_tree *t, const c5_exact_opts *o, int *len_out, int **sched_out,
                        c5_exact_stats *stats, c5_err *err)
{
    if (sched_out)
        *sched_out = NULL;
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (c5_tree_check(t, err) != 0)
        return -1;
    return solve(t, o, 0, 0, len_out, sched_out, stats, err);
}

int c5_sched_beam(const c5_dep_tree *t, int width, int *len_out, int **sched_out, c5_err *err)
{
    if (sched_out)
        *sched_out = NULL;
    if (c5_tree_check(t, err) != 0)
        return -1;
    if (width < 1)
        return c5_fail(err, "cell tree beam search: width %d", width);
    /* the arena holds only the kept states; each group's memo at most a million */
    c5_exact_opts o = {0x7fffffffL, 0x7fffffff, 1, C5_EXACT_GROUPS_DEFAULT, 1000000, NULL, 0};
    return c5_sched_beam_ex(t, &o, width, len_out, sched_out, err);
}

int c5_sched_beam_ex(const c5_dep_tree *t, const c5_exact_opts *o, int width, int *len_out, int **sched_out,
                     c5_err *err)
{
    if (sched_out)
        *sched_out = NULL;
    if (c5_tree_check(t, err) != 0)
        return -1;
    if (width < 1)
        return c5_fail(err, "cell tree beam search: width %d", width);
    c5_exact_opts b = *o;
    b.max_states = 0x7fffffffL;
    b.max_nodes = 0x7fffffff;
    b.use_rollout_ub = 1;
    int rc = solve(t, &b, 0, width, len_out, sched_out, NULL, err);
    return rc == 1 ? 0 : rc < 0 ? -1 : c5_fail(err, "cell tree beam search: no schedule");
}

int c5_sched_projection_optimum(const c5_dep_tree *t, uint64_t cells, const c5_exact_opts *o, int *len_out,
                                c5_exact_stats *stats, c5_err *err)
{
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (!c5_tree_bound_cells(t))
        return c5_fail(err, "cell tree projection: a cell id above %d (C5_BOUND_MAX_CELLS %d)", C5_BOUND_MAX_CELLS - 1,
                       C5_BOUND_MAX_CELLS);
    c5_group *g = c5_group_new(t, cells, 1, NULL);
    int nt = g ? c5_group_size(g) : 0;
    int *par = malloc((size_t)(nt > 0 ? nt : 1) * sizeof *par), *cel = malloc((size_t)(nt > 0 ? nt : 1) * sizeof *cel);
    int rc = -1;
    if (g && par && cel) {
        c5_group_tree(g, par, cel);
        c5_dep_tree p = {nt, par, cel};
        rc = solve(&p, o, 1, 0, len_out, NULL, stats, err);
    } else {
        rc = c5_fail(err, "cell tree projection: out of memory (%d nodes)", t->n);
    }
    c5_group_free(g);
    free(par);
    free(cel);
    return rc;
}

int c5_sched_optimum(const c5_dep_tree *t, long max_states, int max_nodes, int *len_out, int **sched_out,
                     c5_err *err)
{
    c5_exact_opts o = {max_states, max_nodes, 1, C5_EXACT_GROUPS_DEFAULT, 0, NULL, 0};
    return c5_sched_optimum_ex(t, &o, len_out, sched_out, NULL, err);
}

int c5_sched_optimum_plain(const c5_dep_tree *t, long max_states, int max_nodes, int *len_out, int **sched_out,
                           c5_err *err)
{
    c5_exact_opts o = {max_states, max_nodes, 0, 0, 0, NULL, 0};
    return c5_sched_optimum_ex(t, &o, len_out, sched_out, NULL, err);
}
