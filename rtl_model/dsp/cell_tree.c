/* The Cell Tree in 96 KB of DSP RAM (cell_tree.h). */
#include <assert.h>
#include <string.h>

#include "cell_tree.h"

static void get(const c5_ctree *t, uint32_t id, c5_cell_tree_node_t *n)
{
    assert(id < t->used);
    c5_cell_tree_node_unpack(t->ram + (size_t)id * C5_CELL_TREE_NODE_BYTES, n);
}

static void put(c5_ctree *t, uint32_t id, const c5_cell_tree_node_t *n)
{
    c5_cell_tree_node_pack(n, t->ram + (size_t)id * C5_CELL_TREE_NODE_BYTES);
    t->writes++;
}

void c5_ctree_read(c5_ctree *t, uint32_t id, c5_cell_tree_node_t *n)
{
    get(t, id, n);
    t->reads++;
}

static void kids_get(const c5_cell_tree_node_t *n, uint32_t k[C5_TREE_CHILDREN])
{
    k[0] = n->child0, k[1] = n->child1, k[2] = n->child2;
    k[3] = n->child3, k[4] = n->child4;
}

static void kids_set(c5_cell_tree_node_t *n, const uint32_t k[C5_TREE_CHILDREN])
{
    n->child0 = k[0], n->child1 = k[1], n->child2 = k[2];
    n->child3 = k[3], n->child4 = k[4];
}

static c5_cell_tree_node_t fresh(int cell)
{
    c5_cell_tree_node_t n = {.cell_id = (uint32_t)cell};
    uint32_t none[C5_TREE_CHILDREN] = {C5_NODE_NONE, C5_NODE_NONE, C5_NODE_NONE, C5_NODE_NONE, C5_NODE_NONE};
    kids_set(&n, none);
    return n;
}

void c5_ctree_init(c5_ctree *t, uint32_t capacity)
{
    memset(t, 0, sizeof *t);
    t->capacity = capacity == 0 || capacity > C5_TREE_MAX_SLOTS ? C5_TREE_MAX_SLOTS : capacity;
    for (int c = 0; c < C5_MAX_CELLS; c++)
        t->root[c] = C5_NODE_NONE;
}

/* Takes `k` free slots, or freezes the tree. */
static int alloc(c5_ctree *t, uint32_t k, uint32_t *first)
{
    if (t->used + k > t->capacity) {
        t->overflow = 1;
        return 0;
    }
    *first = t->used;
    t->used += k;
    return 1;
}

static uint32_t new_node(c5_ctree *t, uint32_t id, int cell)
{
    c5_cell_tree_node_t n = fresh(cell);
    put(t, id, &n);
    t->nodes++;
    return id;
}

/* The child of `owner` for `cell`, made when missing. Children fill a list's slots in
 * order; a full list (five children) moves its last child into an extension slot and
 * chains to it, so the list goes on as long as the RAM does. */
static uint32_t child(c5_ctree *t, uint32_t owner, int cell)
{
    uint32_t slot = owner;
    c5_cell_tree_node_t n;
    uint32_t k[C5_TREE_CHILDREN];
    for (;;) {
        c5_ctree_read(t, slot, &n);
        kids_get(&n, k);
        int last = n.chained ? C5_TREE_CHILDREN - 1 : C5_TREE_CHILDREN;
        for (int i = 0; i < last && k[i] != C5_NODE_NONE; i++) {
            c5_cell_tree_node_t c;
            c5_ctree_read(t, k[i], &c);
            if ((int)c.cell_id == cell)
                return k[i];
        }
        if (!n.chained)
            break;
        slot = k[C5_TREE_CHILDREN - 1];
    }
    int free_at = 0;
    while (free_at < C5_TREE_CHILDREN && k[free_at] != C5_NODE_NONE)
        free_at++;
    uint32_t id;
    if (free_at < C5_TREE_CHILDREN) {
        if (!alloc(t, 1, &id))
            return C5_NODE_NONE;
        k[free_at] = new_node(t, id, cell);
    } else {
        if (!alloc(t, 2, &id))
            return C5_NODE_NONE;
        c5_cell_tree_node_t ext = fresh((int)n.cell_id);
        ext.extension = 1;
        ext.child0 = k[C5_TREE_CHILDREN - 1];
        ext.child1 = new_node(t, id + 1, cell);
        put(t, id, &ext);
        t->extensions++;
        k[C5_TREE_CHILDREN - 1] = id;
        n.chained = 1;
    }
    kids_set(&n, k);
    put(t, slot, &n);
    return free_at < C5_TREE_CHILDREN ? k[free_at] : id + 1;
}

uint32_t c5_ctree_tag(c5_ctree *t, uint32_t node, int cell)
{
    assert(cell >= 0 && cell < C5_MAX_CELLS);
    t->tags++;
    if (t->overflow)
        return C5_NODE_NONE;
    if (node == C5_NODE_NONE) {
        uint32_t id;
        if (t->root[cell] == C5_NODE_NONE && alloc(t, 1, &id))
            t->root[cell] = (uint16_t)new_node(t, id, cell);
        return t->root[cell];
    }
    c5_cell_tree_node_t n;
    c5_ctree_read(t, node, &n);
    if ((int)n.cell_id == cell)
        return node;
    return child(t, node, cell);
}

void c5_ctree_export(const c5_ctree *t, int *parent, int *cell, uint32_t *id)
{
    int index[C5_TREE_SLOTS];
    int n = 0;
    for (uint32_t s = 0; s < t->used; s++) {
        c5_cell_tree_node_t nd;
        get(t, s, &nd);
        index[s] = -1;
        if (nd.extension)
            continue;
        index[s] = n;
        parent[n] = -1;
        cell[n] = (int)nd.cell_id;
        id[n++] = s;
    }
    assert((uint32_t)n == t->nodes);
    /* A child's slot is always after its owner's: walking the owners in order sets each
     * child's parent once. */
    for (int i = 0; i < n; i++) {
        uint32_t slot = id[i];
        for (;;) {
            c5_cell_tree_node_t nd;
            uint32_t k[C5_TREE_CHILDREN];
            get(t, slot, &nd);
            kids_get(&nd, k);
            int last = nd.chained ? C5_TREE_CHILDREN - 1 : C5_TREE_CHILDREN;
            for (int j = 0; j < last && k[j] != C5_NODE_NONE; j++)
                parent[index[k[j]]] = i;
            if (!nd.chained)
                break;
            slot = k[C5_TREE_CHILDREN - 1];
        }
    }
}

int c5_ctree_annotate(c5_ctree *t, const uint32_t *id, const int *generation, int n, c5_err *err)
{
    for (int i = 0; i < n; i++)
        if (generation[i] < 1 || generation[i] >= 1 << C5_CELL_TREE_NODE_GENERATION_WIDTH)
            return c5_fail(err, "Cell Tree node %u: generation %d does not fit the node's %d-bit field", id[i],
                           generation[i], C5_CELL_TREE_NODE_GENERATION_WIDTH);
    for (int i = 0; i < n; i++) {
        c5_cell_tree_node_t nd;
        get(t, id[i], &nd);
        nd.generation = (uint32_t)generation[i];
        nd.ready = 1;
        put(t, id[i], &nd);
    }
    return 0;
}
