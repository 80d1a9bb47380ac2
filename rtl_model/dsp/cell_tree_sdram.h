/* The Cell Tree in the DSP's SDRAM, for splits whose tree outgrows the 96 KB on-chip RAM
 * (docs/cell-tree.md, "Where the tree lives"). The same rule as cell_tree.c (c5_ctree_tag),
 * in a region of SDRAM instead of the on-chip RAM:
 *
 *  - A node is a 16-byte slot: four children of 22 bits (4 M slots, 64 MB), its cell (12
 *    bits), its index among its cell's nodes (13 bits), generation (6), ready, chained,
 *    extension; a node with more than four children chains extension slots as the on-chip
 *    tree does. The model holds the nodes in arrays and counts their slots and accesses; it
 *    does not hold their bytes.
 *  - The packet keeps its 13-bit cell_tree_node: it carries the node's index among the nodes
 *    of its cell (cell_id). A packet's node always belongs to the cell it is queued for
 *    (the tag rule returns a node of the destination cell), so (cell_id, index) names the
 *    node; the DSP finds its slot in a per-cell directory (one 32-bit word a node).
 *  - The DSP counts the packets tagged with each node in a 32-bit word beside it (for the
 *    replay of stale_plan.h), as the on-chip tree's 24-bit word.
 *  - The tree freezes, as the on-chip tree does, when the region is full (16 bytes a slot and
 *    8 bytes a node) or a cell holds 8,191 nodes (the packet's field).
 *
 * The node store is tree_demand.h's (the same rule on the same ids), so the SDRAM tree that
 * did not freeze is the measured unbounded tree node for node. */
#ifndef C5_CELL_TREE_SDRAM_H
#define C5_CELL_TREE_SDRAM_H

#include <stdint.h>

#include "tree_demand.h"

#define C5_SDRAM_NODE_BYTES 16
#define C5_SDRAM_DIR_BYTES 4   /* a node's directory word */
#define C5_SDRAM_COUNT_BYTES 4 /* its count of the packets tagged with it (stale_plan.h) */
#define C5_SDRAM_CHILDREN 4
#define C5_SDRAM_TREE_BYTES (16u << 20) /* the default region: 16 MiB of the DSP's SDRAM (699,050 nodes) */

/* DSP operations of an SDRAM node access: six 24-bit words over the external port at four
 * wait states each, against C5_OPS_NODE_READ's 10 on chip. A directory word's read is counted
 * as a node access (reads), which overstates it. */
#define C5_OPS_SDRAM_NODE 30

typedef struct {
    c5_tree_demand t;        /* the nodes: cell, parent, children counts, ids in creation order */
    uint32_t *index;         /* [index_cap] node's index among its cell's nodes */
    uint32_t *rays;          /* [index_cap] packets tagged with each node (the caller counts) */
    uint32_t index_cap;
    uint32_t *dir[4096];     /* per cell: its nodes' ids by index (grown on demand) */
    uint32_t dir_n[4096], dir_cap[4096];
    uint64_t bytes;          /* region size */
    uint64_t slots;          /* slots in use (nodes and extension slots) */
    uint32_t max_index;      /* most nodes one cell holds */
    int overflow;            /* a node did not fit: the tree is frozen */
    uint64_t tags, reads, writes, dir_reads;
} c5_sdram_tree;

/* An empty tree in a region of `bytes` (0: C5_SDRAM_TREE_BYTES). 0, or -1 out of memory. */
int c5_sdram_tree_init(c5_sdram_tree *s, uint64_t bytes);
void c5_sdram_tree_free(c5_sdram_tree *s);

/* The DSP's rule for a packet on its way to the queue of `cell` that carries index `index`
 * of a node of cell `from` (C5_NODE_NONE: none, such as an eye ray's): returns the index the
 * packet carries next (C5_NODE_NONE once the tree is frozen). *id: the node's slot id
 * (C5_DEMAND_NONE when none), for the DSP's per-node counts. */
uint32_t c5_sdram_tree_tag(c5_sdram_tree *s, int from, uint32_t index, int cell, uint32_t *id);

/* The node id of (cell, index); C5_DEMAND_NONE for C5_NODE_NONE. */
uint32_t c5_sdram_tree_id(const c5_sdram_tree *s, int cell, uint32_t index);

/* The tree in the scheduler's array form (tree_sched.h), as c5_ctree_export: node ids are in
 * creation order, so parents come first; parent -1 for a root. Uncounted (the caller counts the
 * DSP's read). */
void c5_sdram_tree_export(const c5_sdram_tree *s, int *parent, int *cell);

/* Bytes of the region in use. */
uint64_t c5_sdram_tree_bytes_used(const c5_sdram_tree *s);
/* The most nodes the region can hold: node ids stay below it. */
static inline uint32_t c5_sdram_tree_max_nodes(const c5_sdram_tree *s)
{
    uint64_t n = s->bytes / (C5_SDRAM_NODE_BYTES + C5_SDRAM_DIR_BYTES + C5_SDRAM_COUNT_BYTES);
    return n < 0xFFFFFFFEu ? (uint32_t)n : 0xFFFFFFFEu;
}

#endif
