/* The DSP's Cell Tree tagging rule of the C model (c5_ctree_tag, rtl_model/dsp/cell_tree.c) as a
 * live reference for GHDL (tb/c5ref_pkg.vhd): a tree in its 96 KB RAM image, tagged
 * packet by packet; the RAM's slots (three 32-bit words, word i = bytes 4i..4i+3) and the
 * root table read back at the end. */
#include <stdint.h>
#include <string.h>

#include "c5ref.h"
#include "cell_tree.h"

int32_t c5ref_ct_reset(int32_t capacity);
int32_t c5ref_ct_tag(int32_t node, int32_t cell);
int32_t c5ref_ct_state(int32_t k);
int32_t c5ref_ct_slot_word(int32_t slot, int32_t i);
int32_t c5ref_ct_root(int32_t cell);

static c5_ctree tree;
static long tags, fault = -1; /* this tag's answer is off by one (c5ref.h) */

/* An empty tree of `capacity` slots (0: the whole RAM). */
int32_t c5ref_ct_reset(int32_t capacity)
{
    c5_ctree_init(&tree, (uint32_t)capacity);
    tags = 0;
    fault = c5ref_fault_step();
    return 0;
}

/* The packet's new node for a packet tagged `node` on its way to `cell`. */
int32_t c5ref_ct_tag(int32_t node, int32_t cell)
{
    uint32_t out = c5_ctree_tag(&tree, (uint32_t)node, cell);
    return (int32_t)(out ^ (uint32_t)(tags++ == fault));
}

/* k: 0 the slots used, 1 the overflow flag (the DUT's `frozen`). */
int32_t c5ref_ct_state(int32_t k) { return k == 0 ? (int32_t)tree.used : tree.overflow != 0; }

/* Word i (0..2) of RAM slot `slot` as stored (the generated node layout, little-endian). */
int32_t c5ref_ct_slot_word(int32_t slot, int32_t i)
{
    if (slot < 0 || slot >= C5_TREE_SLOTS || i < 0 || i > 2)
        return 0;
    uint32_t w;
    memcpy(&w, tree.ram + (size_t)slot * C5_CELL_TREE_NODE_BYTES + 4 * (size_t)i, 4);
    return (int32_t)w;
}

int32_t c5ref_ct_root(int32_t cell) { return cell >= 0 && cell < C5_MAX_CELLS ? tree.root[cell] : 0; }
