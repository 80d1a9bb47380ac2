/* The Cell Tree algorithm (paper Section 3.3), its lower bound (Section 3.4), the tree
 * checks and the feasibility test. The exact solver is in tree_exact.c.
 *
 * The interim tree is kept so that a peel costs the cell's live nodes and everything else is
 * O(1) per cell: per node the number of live children (0 = leaf), per cell and generation
 * the number of live nodes and of live leaves. maxGen(c) is then the highest generation with
 * live nodes, and c is ready when that generation's live count equals its leaf count.
 * Removals are journalled so that the lookahead and rollout rules can simulate a peel
 * sequence and undo it in time proportional to what it removed, instead of copying the tree
 * per candidate. */
#include "tree_sched.h"

#include "dsp_cost.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* ---- checks and generations ------------------------------------------------------------ */

static const char *first_bad_rule(const c5_dep_tree *t, int i)
{
    int c = t->cell[i], p = t->parent[i];
    if (c < 0 || c >= C5_SCHED_MAX_CELLS)
        return "cell";
    if (p < -1 || p >= i)
        return "parent";
    if (p >= 0 && t->cell[p] == c)
        return "same";
    return NULL;
}

int c5_tree_check(const c5_dep_tree *t, c5_err *err)
{
    if (!t)
        return c5_fail(err, "cell tree: no tree");
    if (t->n < 0)
        return c5_fail(err, "cell tree: negative node count %d", t->n);
    if (t->n == 0)
        return 0;
    if (!t->parent || !t->cell)
        return c5_fail(err, "cell tree: %d nodes but no parent or cell array", t->n);
    /* bad: the first node that breaks a rule of its own (cell range, parent, parent's cell). */
    int n = t->n, bad = n, maxc = 0;
    for (int i = 0; i < n && bad == n; i++) {
        if (first_bad_rule(t, i))
            bad = i;
        else if (t->cell[i] > maxc)
            maxc = t->cell[i];
    }
    /* Siblings among the nodes before it: the children of each parent (roots: group 0) in
     * index order by a counting sort, each cell stamped with the group that last used it.
     * O(n + cells); dup: the first node whose cell an earlier sibling has. */
    int *first = calloc((size_t)bad + 2, sizeof *first), *order = malloc(((size_t)bad + 1) * sizeof *order);
    int *stamp = calloc((size_t)maxc + 1, sizeof *stamp);
    if (!first || !order || !stamp) {
        free(first);
        free(order);
        free(stamp);
        return c5_fail(err, "cell tree: out of memory for %d nodes", n);
    }
    for (int i = 0; i < bad; i++)
        first[t->parent[i] + 2]++;
    for (int g = 0; g <= bad; g++)
        first[g + 1] += first[g];
    for (int i = 0; i < bad; i++)
        order[first[t->parent[i] + 1]++] = i; /* first[g] ends as the end of group g */
    int dup = bad;
    for (int g = 0, k = 0; g <= bad; g++)
        for (; k < first[g]; k++) {
            int i = order[k], c = t->cell[i];
            if (stamp[c] == g + 1 && i < dup)
                dup = i;
            stamp[c] = g + 1;
        }
    free(first);
    free(order);
    free(stamp);
    if (dup < bad)
        return c5_fail(err, "cell tree: node %d: a sibling (parent %d) already has cell %d", dup, t->parent[dup],
                       t->cell[dup]);
    if (bad == n)
        return 0;
    int c = t->cell[bad], p = t->parent[bad];
    const char *why = first_bad_rule(t, bad);
    if (why[0] == 'c')
        return c5_fail(err, "cell tree: node %d: cell %d outside 0..%d", bad, c, C5_SCHED_MAX_CELLS - 1);
    if (why[0] == 'p')
        return c5_fail(err, "cell tree: node %d: parent %d is not -1 or a lower index", bad, p);
    return c5_fail(err, "cell tree: node %d: same cell %d as its parent %d", bad, c, p);
}

/* The generations of a tree whose cells are 0..ncell-1. */
static int generations(int n, const int *parent, const int *cell, int ncell, int *gen)
{
    if (n == 0)
        return 0;
    /* Depth-first over children lists, keeping per cell the number of same-cell nodes on
     * the current root path: O(n), where walking up each node's ancestors is O(n * depth). */
    int *first = malloc(((size_t)n + 1) * sizeof *first);
    int *kids = malloc((size_t)n * sizeof *kids);
    int *stack = malloc((size_t)n * sizeof *stack);
    int *cursor = malloc((size_t)n * sizeof *cursor);
    int *onpath = calloc((size_t)ncell, sizeof *onpath);
    int best = -1;
    if (first && kids && stack && cursor && onpath) {
        memset(first, 0, ((size_t)n + 1) * sizeof *first);
        for (int i = 0; i < n; i++)
            if (parent[i] >= 0)
                first[parent[i] + 1]++;
        for (int i = 0; i < n; i++)
            first[i + 1] += first[i];
        memcpy(cursor, first, (size_t)n * sizeof *cursor);
        for (int i = 0; i < n; i++)
            if (parent[i] >= 0)
                kids[cursor[parent[i]]++] = i;
        best = 0;
        for (int r = 0; r < n; r++) {
            if (parent[r] >= 0)
                continue;
            int sp = 0;
            stack[sp++] = r;
            cursor[r] = first[r];
            gen[r] = ++onpath[cell[r]];
            while (sp > 0) {
                int v = stack[sp - 1];
                if (cursor[v] < first[v + 1]) {
                    int k = kids[cursor[v]++];
                    gen[k] = ++onpath[cell[k]];
                    if (gen[k] > best)
                        best = gen[k];
                    cursor[k] = first[k];
                    stack[sp++] = k;
                } else {
                    onpath[cell[v]]--;
                    sp--;
                }
            }
            if (gen[r] > best)
                best = gen[r];
        }
    }
    free(first);
    free(kids);
    free(stack);
    free(cursor);
    free(onpath);
    return best;
}

int c5_tree_generations(const c5_dep_tree *t, int *gen)
{
    int maxc = 0;
    for (int i = 0; i < t->n; i++)
        if (t->cell[i] > maxc)
            maxc = t->cell[i];
    return generations(t->n, t->parent, t->cell, maxc + 1, gen);
}

/* ---- feasibility ---------------------------------------------------------------------- */

int c5_sched_feasible(const c5_dep_tree *t, const int *sched, int len)
{
    if (t->n == 0)
        return 1;
    /* pos[i]: where node i embeds, the first load of its cell after its parent's (greedy
     * earliest embedding is optimal for subsequence tests). Parents come first (parent < i). */
    int *pos = malloc((size_t)t->n * sizeof *pos);
    if (!pos)
        return -1;
    int ok = 1;
    for (int i = 0; i < t->n && ok; i++) {
        int k = t->parent[i] < 0 ? 0 : pos[t->parent[i]] + 1;
        while (k < len && sched[k] != t->cell[i])
            k++;
        pos[i] = k;
        ok = k < len;
    }
    free(pos);
    return ok;
}

/* ---- the interim tree ------------------------------------------------------------------ */

/* Cells are renumbered 0..m-1 in ascending id order (m: the cells present), so every
 * per-cell array has m entries whatever the ids, and "lowest id" stays "lowest index". Three
 * bitsets over the local cells answer the questions asked at every peel in O(m / 64): which
 * cells are ready, which are full (every live node a leaf), which have a leaf. They are
 * brought up to date (mark) for every cell whose counts a peel or an undo touches. */
typedef struct {
    int n, m, words;
    const int *parent;
    int *lcell;                        /* [n] local cell of each node */
    int *gid;                          /* [m] cell id of each local cell, ascending */
    int *gen;                          /* [n] */
    int *livekids;                     /* [n] live children; 0 = leaf */
    int *list;                         /* per cell node lists: cell c at [cstart[c], cstart[c+1]) */
    int *cstart;                       /* [m + 1] */
    int *nlive;                        /* [m] live nodes of c = list[cstart[c] .. + nlive[c]) */
    int *nleaf;                        /* [m] live leaves of c */
    int *gbase;                        /* [m + 1] cnt[gbase[c] + g], g in 0..maxGen(c) at the start */
    int *maxgen;                       /* [m] */
    int *cnt, *leafcnt;                /* live nodes / live leaves per cell and generation */
    uint64_t *bready, *bfull, *bleaf;  /* [words] bitsets over the local cells */
    int sum_maxgen, live_total, max_gen;
    uint64_t examined;
    uint64_t ops;   /* the DSP's operations (dsp_cost.h) */
    int *log, nlog; /* removed nodes in removal order (for undo) */
    int full_first; /* completion order: cells with only leaves left first (rollout rule) */
    uint64_t cap;   /* give up past this many nodes examined (0: never) */
} peeler;

static void peeler_free(peeler *p)
{
    free(p->lcell);
    free(p->gid);
    free(p->gen);
    free(p->livekids);
    free(p->list);
    free(p->cstart);
    free(p->cnt);
    free(p->leafcnt);
    free(p->bready);
    free(p->log);
    memset(p, 0, sizeof *p);
}

static int ready(const peeler *p, int c)
{
    int g = p->maxgen[c], k = p->gbase[c] + g;
    return g > 0 && p->leafcnt[k] == p->cnt[k];
}

static void setbit(uint64_t *b, int c, int on)
{
    uint64_t bit = 1ull << (c & 63);
    b[c >> 6] = (b[c >> 6] & ~bit) | (on ? bit : 0);
}

/* The bitsets' bits of cell c from its counts. */
static void mark(peeler *p, int c)
{
    p->ops += C5_OPS_MARK;
    setbit(p->bready, c, ready(p, c));
    setbit(p->bfull, c, p->nlive[c] > 0 && p->nleaf[c] == p->nlive[c]);
    setbit(p->bleaf, c, p->nleaf[c] > 0);
}

/* The lowest cell in bitset b, -1: none. */
static int lowest(peeler *p, const uint64_t *b)
{
    for (int w = 0; w < p->words; w++) {
        p->ops += C5_OPS_WORD;
        if (b[w])
            return w * 64 + __builtin_ctzll(b[w]);
    }
    return -1;
}

static int peeler_init(peeler *p, const c5_dep_tree *t)
{
    memset(p, 0, sizeof *p);
    int n = p->n = t->n, maxc = 0;
    p->parent = t->parent;
    for (int i = 0; i < n; i++)
        if (t->cell[i] > maxc)
            maxc = t->cell[i];
    size_t sz = (size_t)(n > 0 ? n : 1);
    int *loc = malloc(((size_t)maxc + 1) * sizeof *loc);
    p->lcell = malloc(sz * sizeof *p->lcell);
    p->gen = malloc(sz * sizeof *p->gen);
    p->livekids = calloc(sz, sizeof *p->livekids);
    p->list = malloc(sz * sizeof *p->list);
    p->log = malloc(sz * sizeof *p->log);
    if (!loc || !p->lcell || !p->gen || !p->livekids || !p->list || !p->log)
        goto fail;
    for (int c = 0; c <= maxc; c++)
        loc[c] = -1;
    for (int i = 0; i < n; i++)
        loc[t->cell[i]] = 0;
    int m = 0;
    for (int c = 0; c <= maxc; c++)
        if (loc[c] == 0)
            loc[c] = m++;
    p->m = m;
    p->words = m > 0 ? (m + 63) / 64 : 1;
    /* per cell: gid, nlive, nleaf, maxgen [m]; cstart, gbase [m + 1] */
    p->cstart = calloc(6 * (size_t)m + 2, sizeof *p->cstart);
    p->bready = calloc(3 * (size_t)p->words, sizeof *p->bready);
    if (!p->cstart || !p->bready)
        goto fail;
    p->gbase = p->cstart + m + 1;
    p->gid = NULL;
    p->nlive = p->gbase + m + 1;
    p->nleaf = p->nlive + m;
    p->maxgen = p->nleaf + m;
    p->bfull = p->bready + p->words;
    p->bleaf = p->bfull + p->words;
    p->gid = malloc((size_t)(m > 0 ? m : 1) * sizeof *p->gid);
    if (!p->gid)
        goto fail;
    for (int c = 0; c <= maxc; c++)
        if (loc[c] >= 0)
            p->gid[loc[c]] = c;
    for (int i = 0; i < n; i++)
        p->lcell[i] = loc[t->cell[i]];
    free(loc);
    loc = NULL;
    if ((p->max_gen = generations(n, t->parent, p->lcell, m, p->gen)) < 0)
        goto fail;
    for (int i = 0; i < n; i++) {
        int c = p->lcell[i];
        p->nlive[c]++;
        if (p->gen[i] > p->maxgen[c])
            p->maxgen[c] = p->gen[i];
        if (t->parent[i] >= 0)
            p->livekids[t->parent[i]]++;
    }
    for (int c = 0; c < m; c++) {
        p->cstart[c + 1] = p->cstart[c] + p->nlive[c];
        p->gbase[c + 1] = p->gbase[c] + p->maxgen[c] + 1;
        p->sum_maxgen += p->maxgen[c];
    }
    for (int i = 0; i < n; i++) /* the list in node order per cell: nleaf[] serves as the fill count */
        p->list[p->cstart[p->lcell[i]] + p->nleaf[p->lcell[i]]++] = i;
    memset(p->nleaf, 0, (size_t)m * sizeof *p->nleaf);
    p->cnt = calloc((size_t)p->gbase[m] + 1, sizeof *p->cnt);
    p->leafcnt = calloc((size_t)p->gbase[m] + 1, sizeof *p->leafcnt);
    if (!p->cnt || !p->leafcnt)
        goto fail;
    for (int i = 0; i < n; i++) {
        int c = p->lcell[i], k = p->gbase[c] + p->gen[i];
        p->cnt[k]++;
        if (p->livekids[i] == 0) {
            p->leafcnt[k]++;
            p->nleaf[c]++;
        }
    }
    for (int c = 0; c < m; c++)
        mark(p, c);
    p->live_total = n;
    p->ops += (uint64_t)n * C5_OPS_INIT_NODE + (uint64_t)m * C5_OPS_INIT_CELL;
    return 0;
fail:
    free(loc);
    peeler_free(p);
    return -1;
}

/* The cell for the next completion peel, -1 when none is ready. The paper (and rules 1, 2)
 * take the lowest ready id. That order matters: the paper's claim that a completion peel is
 * always part of some optimal schedule is false (tests/test_tree_sched.c, paths 0-1-2 and
 * 1-0-1: peeling the ready cell 1 first costs a load). A narrower claim holds: when every
 * live node of c is a leaf ("full"), peeling c first is optimal. Proof: the rest of the
 * tree then has no node of c, so from any optimal forward schedule of the whole tree,
 * deleting one load of c leaves a schedule of the rest: OPT(rest) <= OPT(tree) - 1. The
 * rollout rule therefore takes full cells first (full_first). A full cell is ready. */
static int first_ready(peeler *p)
{
    int c = p->full_first ? lowest(p, p->bfull) : -1;
    return c >= 0 ? c : lowest(p, p->bready);
}

/* Peels cell c: walks its live nodes, removes the leaves. A removed leaf can only turn its
 * parent (another cell) into a leaf, so the walk never meets a node that changes under it.
 * Removed nodes move to just past the live part of the list (swap with the last live one),
 * which lets undo re-admit them in reverse order. */
static int peel(peeler *p, int c)
{
    int base = p->cstart[c], k = base, end = base + p->nlive[c], removed = 0;
    p->examined += (uint64_t)p->nlive[c];
    p->ops += C5_OPS_PEEL + (uint64_t)p->nlive[c] * C5_OPS_EXAMINE;
    while (k < end) {
        int i = p->list[k];
        if (p->livekids[i] != 0) {
            k++;
            continue;
        }
        p->list[k] = p->list[end - 1];
        p->list[--end] = i;
        int gk = p->gbase[c] + p->gen[i];
        p->cnt[gk]--;
        p->leafcnt[gk]--;
        p->nleaf[c]--;
        p->live_total--;
        p->log[p->nlog++] = i;
        removed++;
        p->ops += C5_OPS_REMOVE;
        int q = p->parent[i];
        if (q >= 0 && --p->livekids[q] == 0) {
            int cq = p->lcell[q];
            p->ops += C5_OPS_PARENT;
            p->leafcnt[p->gbase[cq] + p->gen[q]]++;
            p->nleaf[cq]++;
            mark(p, cq);
        }
    }
    p->nlive[c] = end - base;
    while (p->maxgen[c] > 0 && p->cnt[p->gbase[c] + p->maxgen[c]] == 0) {
        p->maxgen[c]--;
        p->sum_maxgen--;
    }
    mark(p, c);
    return removed;
}

/* Re-admits every node removed since the journal held `mark` entries. */
static void undo(peeler *p, int upto)
{
    while (p->nlog > upto) {
        int i = p->log[--p->nlog], c = p->lcell[i];
        p->ops += C5_OPS_RESTORE;
        p->nlive[c]++; /* i sits at list[cstart[c] + old nlive[c]] (see peel) */
        int gk = p->gbase[c] + p->gen[i];
        p->cnt[gk]++;
        p->leafcnt[gk]++;
        p->nleaf[c]++;
        p->live_total++;
        int q = p->parent[i];
        if (q >= 0 && p->livekids[q]++ == 0) {
            int cq = p->lcell[q];
            p->leafcnt[p->gbase[cq] + p->gen[q]]--;
            p->nleaf[cq]--;
            mark(p, cq);
        }
        if (p->gen[i] > p->maxgen[c]) {
            p->sum_maxgen += p->gen[i] - p->maxgen[c];
            p->maxgen[c] = p->gen[i];
        }
        mark(p, c);
    }
}

/* Completion peels until none is ready; returns how many. */
static int complete(peeler *p)
{
    int k = 0;
    for (int c; (c = first_ready(p)) >= 0; k++)
        peel(p, c);
    return k;
}

/* ---- split rules ----------------------------------------------------------------------- */

static int split_most_leaves(peeler *p)
{
    int best = -1;
    p->ops += (uint64_t)p->words * C5_OPS_WORD;
    for (int w = 0; w < p->words; w++)
        for (uint64_t x = p->bleaf[w]; x; x &= x - 1) {
            int c = w * 64 + __builtin_ctzll(x);
            p->ops += C5_OPS_CANDIDATE;
            if (best < 0 || p->nleaf[c] > p->nleaf[best])
                best = c;
        }
    return best;
}

/* Peels c, scores the outcome with `score`, undoes the peel; lowest score wins, ties: most
 * leaves, then lowest id. (The candidates are the bits of a copy of each bitset word: every
 * undo restores the bitsets.) */
static int best_by_simulation(peeler *p, int (*score)(peeler *))
{
    int best = -1, best_score = 0;
    for (int w = 0; w < p->words; w++)
        for (uint64_t x = p->bleaf[w]; x; x &= x - 1) {
            int c = w * 64 + __builtin_ctzll(x);
            if (p->cap && p->examined > p->cap)
                return -1;
            p->ops += C5_OPS_CANDIDATE;
            int upto = p->nlog;
            peel(p, c);
            int sc = 1 + score(p);
            undo(p, upto);
            if (best < 0 || sc < best_score || (sc == best_score && p->nleaf[c] > p->nleaf[best])) {
                best = c;
                best_score = sc;
            }
        }
    return best;
}

/* Lookahead: the completion peels the split unlocks, plus a lower bound on what is left
 * (sum of maxGen, +1 when the rest is non-empty: the completions stopped, so the next peel
 * is a split, which lowers no maxGen). As each of those completions lowers the sum by one,
 * this is 1 + the sum before the split + (stuck again): it only tells apart the splits after
 * which completions finish the tree; every other choice falls to the tie-break, which is the
 * paper's rule. */
static int score_lookahead(peeler *p) { return complete(p) + p->sum_maxgen + (p->live_total > 0); }

/* Rollout: the length of the rest under the cheap policy (completions, else most leaves). */
static int score_rollout(peeler *p)
{
    int k = 0;
    for (; p->live_total > 0; k++) {
        int c = first_ready(p);
        peel(p, c >= 0 ? c : split_most_leaves(p));
    }
    return k;
}

/* ---- the algorithm --------------------------------------------------------------------- */

void c5_schedule_free(c5_schedule *s)
{
    if (s) {
        free(s->cells);
        memset(s, 0, sizeof *s);
    }
}

/* One peel of the rollout rule: a cell with only leaves left is peeled at once (optimal, see
 * first_ready); otherwise every cell with a leaf, ready or not, is tried by rollout. Since the
 * rollouts follow the same policy from the next state on, the result is never longer than
 * that policy's own schedule. */
static int pick_rollout(peeler *p)
{
    int c = lowest(p, p->bfull);
    return c >= 0 ? c : best_by_simulation(p, score_rollout);
}

int c5_sched_celltree(const c5_dep_tree *t, c5_split_rule rule, c5_schedule *out, c5_err *err)
{
    return c5_sched_celltree_capped(t, rule, 0, out, err);
}

int c5_sched_celltree_capped(const c5_dep_tree *t, c5_split_rule rule, uint64_t max_examined, c5_schedule *out,
                             c5_err *err)
{
    memset(out, 0, sizeof *out);
    if (rule == C5_SPLIT_BOUNDED) /* its own cap: counted operations */
        return c5_sched_bounded(t, c5_dsp_rule_budget(t->n), out, err) < 0 ? -1 : 0;
    if (rule == C5_SPLIT_WINDOW)
        return c5_sched_window(t, c5_dsp_rule_budget(t->n), out, err) < 0 ? -1 : 0;
    if (rule == C5_SPLIT_SUBTREE)
        return c5_tree_check(t, err) != 0 || c5_sched_subtree(t, out, err) != 0 ? -1 : 0;
    if (rule != C5_SPLIT_MOST_LEAVES && rule != C5_SPLIT_LOOKAHEAD && rule != C5_SPLIT_ROLLOUT)
        return c5_fail(err, "cell tree schedule: unknown split rule %d", (int)rule);
    if (c5_tree_check(t, err) != 0)
        return -1;
    peeler p;
    /* Every peel removes at least one node: n entries are enough. */
    int *rev = malloc((size_t)(t->n > 0 ? t->n : 1) * sizeof *rev);
    if (!rev || peeler_init(&p, t) != 0) {
        free(rev);
        return c5_fail(err, "cell tree schedule: out of memory for %d nodes", t->n);
    }
    p.full_first = rule == C5_SPLIT_ROLLOUT;
    p.cap = max_examined;
    int len = 0;
    while (p.live_total > 0) {
        int c;
        if (rule == C5_SPLIT_ROLLOUT)
            c = pick_rollout(&p);
        else if ((c = first_ready(&p)) < 0)
            c = rule == C5_SPLIT_MOST_LEAVES ? split_most_leaves(&p) : best_by_simulation(&p, score_lookahead);
        if (c < 0) { /* over the cap */
            free(rev);
            peeler_free(&p);
            out->cells = malloc(sizeof *out->cells);
            if (!out->cells)
                return c5_fail(err, "cell tree schedule: out of memory");
            return 1;
        }
        if (ready(&p, c))
            out->peels_completion++;
        else
            out->peels_split++;
        peel(&p, c);
        rev[len++] = p.gid[c];
    }
    for (int a = 0, b = len - 1; a < b; a++, b--) {
        int x = rev[a];
        rev[a] = rev[b];
        rev[b] = x;
    }
    out->len = len;
    out->cells = rev;
    out->nodes_examined = p.examined;
    out->dsp_ops = p.ops + (uint64_t)len; /* + writing the schedule out */
    out->max_gen = p.max_gen;
    peeler_free(&p);
    return 0;
}

/* ---- the bounded rollout (C5_SPLIT_BOUNDED) ---------------------------------------------- */

/* The cheap policy's pick: a full cell, else the lowest ready, else most leaves. */
static int policy_pick(peeler *p)
{
    int c = first_ready(p);
    return c >= 0 ? c : split_most_leaves(p);
}

/* The most a peel of c can cost (every live node removed and turning its parent into a
 * leaf, a mark each), with the schedule entry after it and, as slack, the most the work
 * between two checks costs: a pick (bitset scans, a pass over the cells) and a candidate's
 * bookkeeping. */
static uint64_t peel_worst(const peeler *p, int c)
{
    uint64_t nl = (uint64_t)p->nlive[c];
    return C5_OPS_PEEL + C5_OPS_MARK + nl * (C5_OPS_EXAMINE + C5_OPS_REMOVE + C5_OPS_PARENT + C5_OPS_MARK) +
           4 * (uint64_t)p->words * C5_OPS_WORD + ((uint64_t)p->m + 2) * C5_OPS_CANDIDATE + 2;
}

/* Undoing k removals (each may mark its cell and its parent's). */
static uint64_t undo_worst(uint64_t k) { return k * (C5_OPS_RESTORE + 2 * C5_OPS_MARK); }

typedef struct {
    peeler *p;
    uint64_t budget; /* 0: none */
    uint64_t reserve; /* kept for writing the schedule out */
} bounded_ctx;

/* 1 when a peel of c fits the budget with the undo of `removed` more nodes. */
static int affords(const bounded_ctx *b, int c, uint64_t removed)
{
    const peeler *p = b->p;
    if (!b->budget)
        return 1;
    uint64_t need = peel_worst(p, c) + undo_worst(removed + (uint64_t)p->nlive[c]) + b->reserve;
    return p->ops + need <= b->budget;
}

/* Runs the cheap policy from the current state into seq (2 * cell + ready per peel),
 * returning its length; stops when `stop` peels so far plus the sum of maxGen reach `stop`
 * (it cannot beat a schedule of that length: -2) or at the budget (-1). Leaves the peels
 * in the journal; the caller undoes them. `first` >= 0: that cell first. */
static int simulate(bounded_ctx *b, int first, int stop, int *seq, int upto)
{
    peeler *p = b->p;
    int k = 0;
    while (p->live_total > 0) {
        if (stop > 0 && k + p->sum_maxgen >= stop)
            return -2;
        int c = k == 0 && first >= 0 ? first : policy_pick(p);
        if (!affords(b, c, (uint64_t)(p->nlog - upto)))
            return -1;
        seq[k++] = 2 * c + ready(p, c);
        peel(p, c);
        p->ops += 1;
    }
    return k;
}

/* c5_sched_bounded with two knobs for c5_sched_window (tree_window.c): `stop` > 0 asks
 * only for a schedule shorter than stop (the rollouts are pruned against it as against the
 * incumbent, and the search ends once the committed peels plus the sum of maxGen reach it);
 * `with_paper` 0 skips the paper's rule (the caller has its own fallback): then a search that
 * finds nothing shorter than stop, or no incumbent within the budget, returns len 0 with
 * fell_back 1. */
int c5_sched_bounded_core(const c5_dep_tree *t, uint64_t budget_ops, int stop, int with_paper, c5_schedule *out,
                          c5_err *err)
{
    memset(out, 0, sizeof *out);
    if (c5_tree_check(t, err) != 0)
        return -1;
    size_t sz = (size_t)(t->n > 0 ? t->n : 1);
    peeler p;
    /* the paper's reverse schedule, the result, the incumbent continuation and a candidate's */
    int *paper = malloc(sz * sizeof *paper), *rev = malloc(sz * sizeof *rev);
    int *inc = malloc(sz * sizeof *inc), *cand = malloc(sz * sizeof *cand);
    if (!paper || !rev || !inc || !cand || peeler_init(&p, t) != 0) {
        free(paper);
        free(rev);
        free(inc);
        free(cand);
        return c5_fail(err, "cell tree schedule: out of memory for %d nodes", t->n);
    }
    bounded_ctx b = {&p, budget_ops, 2 * (uint64_t)t->n};
    /* The fallback: the paper's rule, whatever the budget; without it, "nothing shorter than
     * stop" (plen = stop, or no limit when stop is 0). */
    int plen = 0, pcomp = 0;
    while (with_paper && p.live_total > 0) {
        int c = first_ready(&p);
        if (c < 0)
            c = split_most_leaves(&p);
        else
            pcomp++;
        peel(&p, c);
        paper[plen++] = c;
    }
    undo(&p, 0);
    if (!with_paper)
        plen = stop > 0 ? stop : INT_MAX;
    /* The incumbent: the cheap policy's schedule from the start (none needed when no
     * schedule can be shorter than stop). */
    p.full_first = 1;
    int len = 0, comp = 0, head = 0, ilen = stop > 0 && p.sum_maxgen >= stop ? -3 : simulate(&b, -1, 0, inc, 0);
    undo(&p, 0);
    if (ilen < 0) { /* over the budget before the first incumbent, or nothing to find */
        out->gave_up = ilen != -3;
        goto result;
    }
    /* inc[head .. ilen) finishes the tree from the current state in ilen - head peels. */
    while (p.live_total > 0) {
        int ci = inc[head] >> 1;
        /* The rollouts are pruned against the incumbent only: a shorter incumbent, even one
         * not shorter than stop, changes where the search goes next. */
        int lim = ilen - head;
        if (stop > 0 && len + p.sum_maxgen >= stop)
            break; /* nothing from here is shorter than stop */
        if (lowest(&p, p.bfull) < 0) {
            for (int w = 0; w < p.words; w++)
                for (uint64_t x = p.bleaf[w]; x; x &= x - 1) {
                    int c = w * 64 + __builtin_ctzll(x);
                    if (c == ci)
                        continue;
                    p.ops += C5_OPS_CANDIDATE;
                    int upto = p.nlog, k = simulate(&b, c, lim, cand, upto);
                    if (k == -1) {
                        out->gave_up = 1;
                        goto result;
                    }
                    undo(&p, upto);
                    if (k >= 0 && k < ilen - head) { /* shorter: the new incumbent */
                        int *tmp = inc;
                        inc = cand;
                        cand = tmp;
                        ilen = k;
                        head = 0;
                        ci = c;
                        lim = k;
                    }
                }
        }
        if (!affords(&b, ci, 0)) {
            out->gave_up = 1;
            goto result;
        }
        comp += ready(&p, ci);
        peel(&p, ci);
        p.ops += 1;
        rev[len++] = ci;
        head++;
    }
result:
    /* The result: the committed peels and the incumbent's rest, or the paper's when shorter
     * or when there is no incumbent. */
    if (ilen < 0 || plen <= len + (ilen - head) || (p.live_total > 0 && !out->gave_up)) {
        /* (a search that broke off at stop has peels left and no complete schedule) */
        len = with_paper ? plen : 0;
        memcpy(rev, paper, (size_t)len * sizeof *rev);
        out->peels_completion = with_paper ? pcomp : 0;
        out->fell_back = 1;
    } else {
        for (int k = head; k < ilen; k++) {
            comp += inc[k] & 1;
            rev[len++] = inc[k] >> 1;
        }
        out->peels_completion = comp;
    }
    out->peels_split = len - out->peels_completion;
    int *fwd = paper; /* reuse: the forward schedule in cell ids */
    for (int k = 0; k < len; k++)
        fwd[k] = p.gid[rev[len - 1 - k]];
    out->len = len;
    out->cells = fwd;
    out->nodes_examined = p.examined;
    out->dsp_ops = p.ops + 2 * (uint64_t)len;
    out->max_gen = p.max_gen;
    peeler_free(&p);
    free(rev);
    free(inc);
    free(cand);
    return 0;
}

int c5_sched_bounded(const c5_dep_tree *t, uint64_t budget_ops, c5_schedule *out, c5_err *err)
{
    return c5_sched_bounded_core(t, budget_ops, 0, 1, out, err);
}

int c5_sched_sum_maxgen(const c5_dep_tree *t)
{
    peeler p;
    if (peeler_init(&p, t) != 0)
        return -1;
    int s = p.sum_maxgen;
    peeler_free(&p);
    return s;
}

int c5_sched_lower_bound(const c5_dep_tree *t)
{
    peeler p;
    if (peeler_init(&p, t) != 0)
        return -1;
    /* Every completion peel lowers the sum by exactly one (the peeled maxGen nodes have
     * generation-(g-1) ancestors of the same cell, which stay), so the sum is the bound so
     * far; one split is forced when completions get stuck before the end. */
    int s = p.sum_maxgen;
    complete(&p);
    s += p.live_total > 0;
    peeler_free(&p);
    return s;
}
