/* A lower bound at any split (tree_analysis.h, c5_sched_lower_bound_blocks).
 *
 * Proof. Cut the grid of cells into disjoint blocks. A schedule S serves the tree when every
 * root-to-leaf path of cells embeds in S as a subsequence. Keep in S only the loads of block
 * B's cells (S|B) and in every path only B's cells: an embedding of the path in S restricts to
 * an embedding of its B-part in S|B, so S|B serves the tree of the B-parts of the paths, T|B
 * (a trie over B's cells, in which a node may have its parent's cell: a path that leaves a
 * cell of B and comes back to it needs it loaded twice). Hence |S| = sum over B of |S|B| >=
 * sum over B of OPT(T|B) >= sum over B of any proven bound on T|B. A block of at most 64
 * cells is a tree the offline bounds take (C5_BOUND_MAX_CELLS); the bound used on each is the
 * better of c5_sched_lower_bound_pairs (the sum of maxGen improved by matched pairs of cells)
 * and c5_sched_lower_bound_split on the block's slabs, so the whole is at least the sum of
 * maxGen. */
#include <stdlib.h>
#include <string.h>

#include "tree_analysis.h"

/* Blocks of b x b x b cells (b = 4: 64 cells), fewer along an axis with fewer cells. */
#define BLOCK_SIDE 4
/* The exact search's states on each slab of a block (c5_sched_lower_bound_split: the bound it
 * proved when it gives up). */
#define SLAB_STATES 20000

/* The best proven bound on a block's tree: matched pairs of cells, or the block's slabs of
 * cells along the best axis (the slabs of a 27-cell split give the best bounds seen there). */
static int block_bound(const c5_dep_tree *t, const int side[3])
{
    int best = c5_sched_lower_bound_pairs(t);
    for (int a = 0; a < 3 && best >= 0; a++) {
        if (side[a] < 2)
            continue;
        uint64_t g[BLOCK_SIDE] = {0};
        for (int l = 0; l < side[0] * side[1] * side[2]; l++) {
            int co[3] = {l % side[0], l / side[0] % side[1], l / (side[0] * side[1])};
            g[co[a]] |= 1ull << l;
        }
        int x = c5_sched_lower_bound_split(t, g, side[a], SLAB_STATES, NULL);
        if (x < 0)
            return -1;
        best = x > best ? x : best;
    }
    return best;
}

typedef struct {
    int n, cap;
    int *parent, *cell;
} block_tree;

static int push(block_tree *b, int parent, int cell)
{
    if (b->n == b->cap) {
        int cap = b->cap ? 2 * b->cap : 64;
        int *p = realloc(b->parent, sizeof *p * (size_t)cap);
        if (p)
            b->parent = p;
        int *c = p ? realloc(b->cell, sizeof *c * (size_t)cap) : NULL;
        if (!c)
            return -1;
        b->cell = c;
        b->cap = cap;
    }
    b->parent[b->n] = parent;
    b->cell[b->n] = cell;
    return b->n++;
}

/* The trie's child of (block tree node parent, local cell): an open-addressing map keyed by
 * (block, parent + 1, cell); 0 is empty. */
typedef struct {
    uint64_t *key;
    int *val;
    uint64_t cap;
} trie_map;

static uint64_t slot(const trie_map *m, uint64_t key)
{
    return (key * 0x9E3779B97F4A7C15ull >> 20) & (m->cap - 1);
}

int c5_sched_lower_bound_blocks(const c5_dep_tree *t, const int split[3])
{
    int side[3], nb[3];
    for (int a = 0; a < 3; a++) {
        if (split[a] < 1)
            return -1;
        side[a] = split[a] < BLOCK_SIDE ? split[a] : BLOCK_SIDE;
        nb[a] = (split[a] + side[a] - 1) / side[a];
    }
    int ncells = split[0] * split[1] * split[2], nblocks = nb[0] * nb[1] * nb[2], n = t->n, rc = -1;
    int *blk = malloc(sizeof *blk * (size_t)(ncells > 0 ? ncells : 1));
    int *loc = malloc(sizeof *loc * (size_t)(ncells > 0 ? ncells : 1));
    int *rnode = malloc(sizeof *rnode * (size_t)(n > 0 ? n : 1)); /* node's trie node in its block */
    block_tree *bt = calloc((size_t)nblocks, sizeof *bt);
    trie_map m = {0};
    for (m.cap = 64; m.cap < 2 * (uint64_t)(n > 0 ? n : 1); m.cap *= 2)
        ;
    m.key = calloc(m.cap, sizeof *m.key);
    m.val = malloc(sizeof *m.val * m.cap);
    if (!blk || !loc || !rnode || !bt || !m.key || !m.val)
        goto done;
    for (int c = 0; c < ncells; c++) {
        int x = c % split[0], y = c / split[0] % split[1], z = c / (split[0] * split[1]);
        blk[c] = x / side[0] + nb[0] * (y / side[1] + nb[1] * (z / side[2]));
        loc[c] = x % side[0] + side[0] * (y % side[1] + side[1] * (z % side[2]));
    }
    for (int v = 0; v < n; v++) {
        int c = t->cell[v];
        if (c < 0 || c >= ncells || t->parent[v] >= v)
            goto done; /* not a tree of this split (parents come first) */
        int b = blk[c], u = t->parent[v];
        while (u >= 0 && blk[t->cell[u]] != b)
            u = t->parent[u];
        int rp = u < 0 ? -1 : rnode[u];
        uint64_t key = ((uint64_t)b << 40 | (uint64_t)(rp + 1) << 8 | (uint64_t)loc[c]) + 1, s = slot(&m, key);
        while (m.key[s] && m.key[s] != key)
            s = (s + 1) & (m.cap - 1);
        if (!m.key[s]) {
            int id = push(&bt[b], rp, loc[c]);
            if (id < 0)
                goto done;
            m.key[s] = key;
            m.val[s] = id;
        }
        rnode[v] = m.val[s];
    }
    int sum = 0;
    for (int b = 0; b < nblocks; b++) {
        if (!bt[b].n)
            continue;
        c5_dep_tree bt_dep = {bt[b].n, bt[b].parent, bt[b].cell};
        int lb = block_bound(&bt_dep, side);
        if (lb < 0)
            goto done;
        sum += lb;
    }
    rc = sum;
done:
    if (bt)
        for (int b = 0; b < nblocks; b++)
            free(bt[b].parent), free(bt[b].cell);
    free(bt);
    free(blk);
    free(loc);
    free(rnode);
    free(m.key);
    free(m.val);
    return rc;
}
