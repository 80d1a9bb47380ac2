/* The Cell Tree (Frank & Kaufman, Section 3.2) as the DSP keeps it: 12-byte nodes in the
 * layout of Figure 8 (spec/layouts.toml, docs/bit-layouts.md) in a modelled 96 KB RAM. Every
 * access goes through the RAM bytes and the generated pack/unpack, so the RAM image is the
 * one the DSP software would hold, and reads and writes are counted.
 *
 * Construction: every ray packet the DSP queues carries the node of its ray's dependencies;
 * c5_ctree_tag applies the paper's rule to it (docs/cell-tree.md). Beside the RAM the DSP
 * keeps a root per cell (4,096 x 13 bits, 6.5 KB beside the 96 KB); the per-cell node lists of the paper are built by the
 * scheduler between frames (c5_ctree_export) and are not stored. */
#ifndef C5_CELL_TREE_H
#define C5_CELL_TREE_H

#include <stdint.h>

#include "c5_layouts.h"
#include "err.h"
#include "ray.h"

#define C5_TREE_RAM_BYTES (96 * 1024)
#define C5_TREE_SLOTS (C5_TREE_RAM_BYTES / C5_CELL_TREE_NODE_BYTES) /* 8192 */
#define C5_TREE_MAX_SLOTS (C5_TREE_SLOTS - 1) /* ids 0..8190: 8191 is "none" */
#define C5_TREE_CHILDREN 5

_Static_assert(C5_TREE_MAX_SLOTS == C5_NODE_NONE, "node ids and the packet's none agree");
_Static_assert(C5_CELL_TREE_NODE_CHILD0_WIDTH == C5_RAY_PACKET_CELL_TREE_NODE_WIDTH,
               "a child id and the packet's cell_tree_node have one width");

typedef struct {
    uint8_t ram[C5_TREE_RAM_BYTES];
    uint32_t capacity;         /* slots the tree may use, <= C5_TREE_MAX_SLOTS (tests shrink it) */
    uint32_t used;             /* slots allocated: nodes and extension slots, ids 0..used-1 */
    uint32_t nodes;            /* tree nodes (slots without the extension flag) */
    uint32_t extensions;       /* extension slots */
    uint16_t root[C5_MAX_CELLS]; /* each cell's root, C5_NODE_NONE: none */
    int overflow;              /* a node did not fit: the tree misses dependencies */
    uint64_t tags;             /* packets the DSP looked at */
    uint64_t reads, writes;    /* 12-byte node accesses */
} c5_ctree;

/* An empty tree; capacity 0 means C5_TREE_MAX_SLOTS. */
void c5_ctree_init(c5_ctree *t, uint32_t capacity);

/* The DSP's rule for a ray packet on its way to the queue of `cell`, tagged with `node`
 * (C5_NODE_NONE: a ray with no dependency yet, such as an eye ray): returns the packet's
 * new node. None yet: the cell's root (made on first use). A node of the same cell: kept
 * (the ray stays in its cell). Another cell's node: its child for `cell` (made on first
 * use). Once the RAM has overflowed the tree is frozen and every answer is C5_NODE_NONE;
 * the frame renders the same, only the next frame's schedule is lost. */
uint32_t c5_ctree_tag(c5_ctree *t, uint32_t node, int cell);

/* Reads slot `id` (< used) from the RAM; counted. */
void c5_ctree_read(c5_ctree *t, uint32_t id, c5_cell_tree_node_t *n);

/* The tree in the scheduler's array form (tree_sched.h): nodes in id order (so parents come
 * first), extension slots left out. parent[i] = index or -1, cell[i], id[i] = the node's
 * slot id; each array holds t->nodes entries. Uncounted: the scheduler's own copy. */
void c5_ctree_export(const c5_ctree *t, int *parent, int *cell, uint32_t *id);

/* Writes the scheduler's results into the RAM: generation[i] of node id[i], ready = 1
 * (every node is peeled when a schedule is complete). Counted as one write per node.
 * -1 with a message when a generation does not fit the node's field (nothing written). */
int c5_ctree_annotate(c5_ctree *t, const uint32_t *id, const int *generation, int n, c5_err *err);

#endif
