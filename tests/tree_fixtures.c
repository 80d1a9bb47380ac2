/* Fixtures shared by the tree scheduling tests (tree_fixtures.h). */
#include <string.h>

#include "rng.h"
#include "tree_fixtures.h"

/* Random forest honouring the guarantees: each node picks a parent among the earlier nodes
 * (or none), then a cell that neither the parent nor the parent's other children have. A
 * node that finds no free cell after a few tries is dropped; returns the node count. */
int c5t_random_tree(uint64_t *rng, int n, int ncells, int maxdepth, int *parent, int *cell)
{
    uint64_t used[9000]; /* used[p + 1]: cells of p's children (used[0]: roots) */
    int depth[9000], m = 0;
    memset(used, 0, ((size_t)n + 1) * sizeof *used);
    double proot = 0.1 + 0.3 * c5_uniform(rng);
    for (int i = 0; i < n; i++) {
        for (int tries = 0; tries < 20; tries++) {
            int p = (m == 0 || c5_uniform(rng) < proot) ? -1 : (int)(c5_splitmix64(rng) % (uint64_t)m);
            if (p >= 0 && depth[p] >= maxdepth)
                continue;
            uint64_t avail = (ncells == 64 ? ~0ull : (1ull << ncells) - 1) & ~used[p + 1];
            if (p >= 0)
                avail &= ~(1ull << cell[p]);
            if (!avail)
                continue;
            int k = (int)(c5_splitmix64(rng) % (uint64_t)__builtin_popcountll(avail)), c = 0;
            while (!(avail >> c & 1) || k-- > 0)
                c++;
            parent[m] = p;
            cell[m] = c;
            depth[m] = p < 0 ? 1 : depth[p] + 1;
            used[p + 1] |= 1ull << c;
            m++;
            break;
        }
    }
    return m;
}

/* The same with cell ids anywhere in 0..C5_SCHED_MAX_CELLS-1: each node draws its cell from
 * `pool` (npool distinct ids) and redraws while its parent or an earlier sibling has it. */
int c5t_random_tree_wide(uint64_t *rng, int n, const int *pool, int npool, int maxdepth, int *parent, int *cell)
{
    static int depth[9000], firstkid[9001], nextsib[9000];
    int m = 0;
    for (int i = 0; i <= n; i++)
        firstkid[i] = -1;
    double proot = 0.1 + 0.3 * c5_uniform(rng);
    for (int i = 0; i < n; i++) {
        for (int tries = 0; tries < 20; tries++) {
            int p = (m == 0 || c5_uniform(rng) < proot) ? -1 : (int)(c5_splitmix64(rng) % (uint64_t)m);
            if (p >= 0 && depth[p] >= maxdepth)
                continue;
            int c = pool[c5_splitmix64(rng) % (uint64_t)npool], taken = p >= 0 && cell[p] == c;
            for (int k = firstkid[p + 1]; k >= 0 && !taken; k = nextsib[k])
                taken = cell[k] == c;
            if (taken)
                continue;
            parent[m] = p;
            cell[m] = c;
            depth[m] = p < 0 ? 1 : depth[p] + 1;
            nextsib[m] = firstkid[p + 1];
            firstkid[p + 1] = m;
            m++;
            break;
        }
    }
    return m;
}

/* Forward brute force over load sequences of growing length. It needs none of the tree
 * guarantees: a load of c serves every unserved node of c whose parent was served before
 * it, so it also solves projections (a node under a node of its own cell, siblings of one
 * cell). */
static int bf_try(const c5_dep_tree *t, const unsigned char *done, int left, uint64_t used)
{
    int all = 1;
    for (int i = 0; i < t->n && all; i++)
        all = done[i];
    if (all)
        return 1;
    if (left == 0)
        return 0;
    for (int c = 0; c < 64; c++) {
        if (!(used >> c & 1))
            continue;
        unsigned char next[64];
        int any = 0;
        memcpy(next, done, (size_t)t->n);
        for (int i = 0; i < t->n; i++)
            if (!done[i] && t->cell[i] == c && (t->parent[i] < 0 || done[t->parent[i]]))
                next[i] = any = 1;
        if (any && bf_try(t, next, left - 1, used))
            return 1;
    }
    return 0;
}

int c5t_brute_opt(const c5_dep_tree *t)
{
    uint64_t used = 0;
    for (int i = 0; i < t->n; i++)
        used |= 1ull << t->cell[i];
    unsigned char done[64] = {0};
    for (int len = 0;; len++)
        if (bf_try(t, done, len, used))
            return len;
}
