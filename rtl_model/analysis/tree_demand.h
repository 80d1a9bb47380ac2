/* What the Cell Tree would need with unbounded DSP RAM: a measuring instrument beside the
 * DSP's tree (not the DSP's work, and not in any RAM image). It follows the DSP's rule
 * (c5_ctree_tag) on its own node ids, which rays carry beside their packets (c5_bray.shadow),
 * so it keeps counting after the 96 KB tree has overflowed and frozen. From each node's
 * child count it also gives the slots a node layout with k children a slot would take
 * (extension slots as cell_tree.c chains them), to size the RAM a scene class needs and to
 * compare node layouts by measurement (docs/results/cell-tree-studies.md, "How much RAM a
 * split needs"). */
#ifndef C5_TREE_DEMAND_H
#define C5_TREE_DEMAND_H

#include <stdint.h>

#define C5_DEMAND_NONE UINT32_MAX

typedef struct {
    uint32_t n, cap;      /* nodes */
    uint32_t *cell;       /* [cap] node's cell */
    uint32_t *kids;       /* [cap] its number of children */
    uint32_t *parent;     /* [cap] its parent, C5_DEMAND_NONE: a root */
    uint32_t *root;       /* [C5_MAX_CELLS] each cell's root, C5_DEMAND_NONE: none */
    uint64_t *hkey;       /* open-addressing map (parent << 16 | cell) + 1 -> child; 0: empty */
    uint32_t *hval;
    uint32_t hcap;        /* a power of two */
    int oom;              /* out of host memory: counts stop (the render goes on) */
} c5_tree_demand;

int c5_demand_init(c5_tree_demand *d);
void c5_demand_free(c5_tree_demand *d);
/* The DSP's rule on the instrument's ids: the node a packet for `cell` carries next. */
uint32_t c5_demand_tag(c5_tree_demand *d, uint32_t node, int cell);
/* Slots the tree takes with `per_slot` children a slot (>= 2): every node one slot, and a
 * node with more than per_slot children chains extension slots of per_slot - 1 children
 * and a link, the last holding up to per_slot. */
uint64_t c5_demand_slots(const c5_tree_demand *d, int per_slot);
/* The sum over cells of maxGen (the most nodes of the cell on one root-to-leaf path): every
 * order of loads that serves the frame loads cell c at least maxGen(c) times, so this bounds
 * any schedule of the frame, Max Work's and the board's among them, at any split and whether
 * or not the DSP's tree fitted its RAM (docs/cell-tree.md, "Bounds"). 0 when the host ran out
 * of memory. */
uint64_t c5_demand_sum_maxgen(const c5_tree_demand *d);

#endif
