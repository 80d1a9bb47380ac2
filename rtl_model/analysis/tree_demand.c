/* The unbounded Cell Tree instrument (tree_demand.h). */
#include "tree_demand.h"

#include <stdlib.h>
#include <string.h>

#include "ray.h"

int c5_demand_init(c5_tree_demand *d)
{
    memset(d, 0, sizeof *d);
    d->root = malloc(C5_MAX_CELLS * sizeof *d->root);
    d->hcap = 1u << 12;
    d->hkey = calloc(d->hcap, sizeof *d->hkey);
    d->hval = malloc(d->hcap * sizeof *d->hval);
    if (!d->root || !d->hkey || !d->hval) {
        c5_demand_free(d);
        return -1;
    }
    for (int c = 0; c < C5_MAX_CELLS; c++)
        d->root[c] = C5_DEMAND_NONE;
    return 0;
}

void c5_demand_free(c5_tree_demand *d)
{
    free(d->cell);
    free(d->kids);
    free(d->parent);
    free(d->root);
    free(d->hkey);
    free(d->hval);
    memset(d, 0, sizeof *d);
}

static uint32_t slot_of(const c5_tree_demand *d, uint64_t key)
{
    uint64_t h = key * 0x9E3779B97F4A7C15ull; /* Fibonacci hashing: deterministic, no pointers */
    return (uint32_t)(h >> 32) & (d->hcap - 1);
}

static int grow_map(c5_tree_demand *d)
{
    uint32_t old = d->hcap;
    uint64_t *k = d->hkey;
    uint32_t *v = d->hval;
    d->hcap = old * 2;
    d->hkey = calloc(d->hcap, sizeof *d->hkey);
    d->hval = malloc(d->hcap * sizeof *d->hval);
    if (!d->hkey || !d->hval) {
        free(k);
        free(v);
        return -1;
    }
    for (uint32_t i = 0; i < old; i++)
        if (k[i]) {
            uint32_t s = slot_of(d, k[i]);
            while (d->hkey[s])
                s = (s + 1) & (d->hcap - 1);
            d->hkey[s] = k[i];
            d->hval[s] = v[i];
        }
    free(k);
    free(v);
    return 0;
}

static uint32_t new_node(c5_tree_demand *d, int cell, uint32_t parent)
{
    if (d->n == d->cap) {
        uint32_t cap = d->cap ? 2 * d->cap : 1024;
        uint32_t *c = realloc(d->cell, cap * sizeof *c);
        if (c)
            d->cell = c;
        uint32_t *k = c ? realloc(d->kids, cap * sizeof *k) : NULL;
        if (k)
            d->kids = k;
        uint32_t *p = k ? realloc(d->parent, cap * sizeof *p) : NULL;
        if (p)
            d->parent = p;
        if (!c || !k || !p) {
            d->oom = 1;
            return C5_DEMAND_NONE;
        }
        d->cap = cap;
    }
    d->cell[d->n] = (uint32_t)cell;
    d->kids[d->n] = 0;
    d->parent[d->n] = parent;
    return d->n++;
}

uint32_t c5_demand_tag(c5_tree_demand *d, uint32_t node, int cell)
{
    if (d->oom)
        return C5_DEMAND_NONE;
    if (node == C5_DEMAND_NONE) {
        if (d->root[cell] == C5_DEMAND_NONE)
            d->root[cell] = new_node(d, cell, C5_DEMAND_NONE);
        return d->root[cell];
    }
    if (d->cell[node] == (uint32_t)cell)
        return node;
    uint64_t key = ((uint64_t)node << 16 | (uint32_t)cell) + 1;
    uint32_t s = slot_of(d, key);
    while (d->hkey[s]) {
        if (d->hkey[s] == key)
            return d->hval[s];
        s = (s + 1) & (d->hcap - 1);
    }
    uint32_t child = new_node(d, cell, node);
    if (child == C5_DEMAND_NONE)
        return child;
    d->kids[node]++;
    d->hkey[s] = key;
    d->hval[s] = child;
    if (2 * (uint64_t)(d->n) > d->hcap && grow_map(d) != 0)
        d->oom = 1;
    return child;
}

uint64_t c5_demand_slots(const c5_tree_demand *d, int per_slot)
{
    uint64_t slots = 0;
    for (uint32_t i = 0; i < d->n; i++) {
        uint64_t c = d->kids[i];
        slots += 1; /* the node's own slot holds up to per_slot children */
        while (c > (uint64_t)per_slot) {
            c -= (uint64_t)per_slot - 1; /* per_slot - 1 stay behind the link */
            slots++;
        }
    }
    return slots;
}

uint64_t c5_demand_sum_maxgen(const c5_tree_demand *d)
{
    if (d->oom)
        return 0;
    /* Ids grow down every path (a child is made after its parent), so one pass in id order
     * finds each node's generation from its nearest ancestor of the same cell. */
    uint32_t *gen = malloc(sizeof *gen * (d->n ? d->n : 1)), *most = calloc(C5_MAX_CELLS, sizeof *most);
    uint64_t sum = 0;
    if (gen && most) {
        for (uint32_t v = 0; v < d->n; v++) {
            uint32_t u = d->parent[v];
            while (u != C5_DEMAND_NONE && d->cell[u] != d->cell[v])
                u = d->parent[u];
            gen[v] = u == C5_DEMAND_NONE ? 1 : gen[u] + 1;
            if (gen[v] > most[d->cell[v]])
                most[d->cell[v]] = gen[v];
        }
        for (int c = 0; c < C5_MAX_CELLS; c++)
            sum += most[c];
    }
    free(gen);
    free(most);
    return sum;
}
