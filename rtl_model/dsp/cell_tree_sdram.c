/* The Cell Tree in the DSP's SDRAM (cell_tree_sdram.h). */
#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "cell_tree_sdram.h"
#include "ray.h"

_Static_assert(C5_MAX_CELLS == 4096, "one directory per cell id");

int c5_sdram_tree_init(c5_sdram_tree *s, uint64_t bytes)
{
    memset(s, 0, sizeof *s);
    s->bytes = bytes ? bytes : C5_SDRAM_TREE_BYTES;
    return c5_demand_init(&s->t);
}

void c5_sdram_tree_free(c5_sdram_tree *s)
{
    c5_demand_free(&s->t);
    free(s->index);
    free(s->rays);
    for (int c = 0; c < C5_MAX_CELLS; c++)
        free(s->dir[c]);
    memset(s, 0, sizeof *s);
}

uint64_t c5_sdram_tree_bytes_used(const c5_sdram_tree *s)
{
    return s->slots * C5_SDRAM_NODE_BYTES + (uint64_t)s->t.n * (C5_SDRAM_DIR_BYTES + C5_SDRAM_COUNT_BYTES);
}

void c5_sdram_tree_export(const c5_sdram_tree *s, int *parent, int *cell)
{
    for (uint32_t v = 0; v < s->t.n; v++) {
        parent[v] = s->t.parent[v] == C5_DEMAND_NONE ? -1 : (int)s->t.parent[v];
        cell[v] = (int)s->t.cell[v];
    }
}

/* Extension slots of a node with c children, C5_SDRAM_CHILDREN a slot (tree_demand.h). */
static uint64_t ext_slots(uint64_t c)
{
    uint64_t k = 0;
    while (c > C5_SDRAM_CHILDREN) {
        c -= C5_SDRAM_CHILDREN - 1;
        k++;
    }
    return k;
}

/* Files node v (just made) in its cell's directory; 0, or -1 (out of host memory). */
static int file_node(c5_sdram_tree *s, uint32_t v)
{
    uint32_t c = s->t.cell[v];
    if (s->index_cap < s->t.cap) { /* index[] follows the store's capacity */
        uint32_t *ix = realloc(s->index, sizeof *ix * s->t.cap);
        if (ix)
            s->index = ix;
        uint32_t *r = ix ? realloc(s->rays, sizeof *r * s->t.cap) : NULL;
        if (!r)
            return -1;
        s->rays = r;
        memset(r + s->index_cap, 0, sizeof *r * (s->t.cap - s->index_cap));
        s->index_cap = s->t.cap;
    }
    if (s->dir_n[c] == s->dir_cap[c]) {
        uint32_t cap = s->dir_cap[c] ? 2 * s->dir_cap[c] : 16;
        uint32_t *d = realloc(s->dir[c], sizeof *d * cap);
        if (!d)
            return -1;
        s->dir[c] = d;
        s->dir_cap[c] = cap;
    }
    s->index[v] = s->dir_n[c];
    s->dir[c][s->dir_n[c]++] = v;
    if (s->dir_n[c] > s->max_index)
        s->max_index = s->dir_n[c];
    return 0;
}

uint32_t c5_sdram_tree_id(const c5_sdram_tree *s, int cell, uint32_t index)
{
    if (index == C5_NODE_NONE)
        return C5_DEMAND_NONE;
    assert(cell >= 0 && cell < C5_MAX_CELLS && index < s->dir_n[cell]);
    return s->dir[cell][index];
}

uint32_t c5_sdram_tree_tag(c5_sdram_tree *s, int from, uint32_t index, int cell, uint32_t *id)
{
    assert(cell >= 0 && cell < C5_MAX_CELLS);
    s->tags++;
    *id = C5_DEMAND_NONE;
    if (s->overflow || s->t.oom)
        return C5_NODE_NONE;
    uint32_t owner = C5_DEMAND_NONE;
    if (index != C5_NODE_NONE) {
        owner = c5_sdram_tree_id(s, from, index);
        s->dir_reads++;
        s->reads++;
        if (s->t.cell[owner] == (uint32_t)cell) {
            *id = owner;
            return index;
        }
        s->reads += s->t.kids[owner]; /* its children compared with `cell` */
    }
    uint32_t n0 = s->t.n;
    uint64_t ext0 = owner == C5_DEMAND_NONE ? 0 : ext_slots(s->t.kids[owner]);
    uint32_t v = c5_demand_tag(&s->t, owner, cell);
    if (v == C5_DEMAND_NONE)
        return C5_NODE_NONE; /* out of host memory (s->t.oom): the caller reports it */
    if (s->t.n != n0) { /* a new node */
        uint64_t ext = owner == C5_DEMAND_NONE ? 0 : ext_slots(s->t.kids[owner]) - ext0;
        s->slots += 1 + ext;
        s->writes += 1 + ext + (owner != C5_DEMAND_NONE);
        if (file_node(s, v) != 0) {
            s->t.oom = 1;
            return C5_NODE_NONE;
        }
        if (c5_sdram_tree_bytes_used(s) > s->bytes || s->index[v] >= C5_NODE_NONE) {
            s->overflow = 1; /* frozen: this packet and every later one carry none */
            return C5_NODE_NONE;
        }
    }
    *id = v;
    return s->index[v];
}
