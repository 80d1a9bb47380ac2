/* The DSP's operation count: what building the Cell Tree and scheduling it would cost the
 * board's DSP (a DSP56311-class core, 255 MIPS: one instruction a cycle at 255 MHz). The
 * model counts primitives (a node examined, removed, restored; a bitset word scanned; a
 * cell's flags updated; a candidate compared; a node read or written in the RAM) and
 * weighs each by an estimate of its instructions: loads, an add or compare, a branch, with
 * the DSP's parallel moves not relied on. The weights are estimates, not a compiled count;
 * what they hold is the order of magnitude and that the same work always counts the same
 * (no clock). docs/cell-tree.md, "The DSP's budget". */
#ifndef C5_DSP_COST_H
#define C5_DSP_COST_H

#include <stdint.h>

#define C5_DSP_MIPS 255.0

/* Scheduling (tree_sched.c), per primitive. */
#define C5_OPS_EXAMINE 4   /* a live node looked at in a peel: load id, load child count, test, branch */
#define C5_OPS_REMOVE 14   /* a leaf removed: list swap (4), counters by generation (4), journal (2), parent (4) */
#define C5_OPS_PARENT 8    /* a parent turned leaf: its counters (4) and flags (mark below, counted apart) */
#define C5_OPS_RESTORE 14  /* undo of one removal, as its removal */
#define C5_OPS_MARK 9      /* a cell's ready/full/leaf bits: three read-modify-writes */
#define C5_OPS_WORD 6      /* 64 cells of a bitset scanned: three 24-bit words, load and test each */
#define C5_OPS_CANDIDATE 6 /* a candidate cell compared (leaf count or score), best kept */
#define C5_OPS_PEEL 12     /* a peel's overhead: call, maxGen update, the schedule entry */
#define C5_OPS_INIT_NODE 24 /* preparing the scheduler per node: ids, generations (walk), lists, counts */
#define C5_OPS_INIT_CELL 12 /* per cell present: renumbering, offsets, flags */

/* The window rule (tree_window.c), per primitive. */
#define C5_OPS_WIN_NODE 4    /* a node or schedule entry relabelled, counted or placed by a counting sort */
#define C5_OPS_EMBED 10      /* a node's earliest and latest load: its parent's / children's bound, two searches set up */
#define C5_OPS_SEARCH 4      /* one step of a binary search in a cell's loads */
#define C5_OPS_WIN_EXTRACT 8 /* a node of a window looked at: its latest load, stamp, parent's trie node, signature */
#define C5_OPS_TRIE_STEP 3   /* a trie sibling compared with the cell sought */
#define C5_OPS_COPY 2        /* a schedule entry moved */

/* The largest-subtree rule (tree_subtree.c). */
#define C5_OPS_SUBTREE_NODE 24 /* a node: its size added to its parent's, cubed (two 48-bit products on
                                  the 24-bit core), put on its cell's ready list, the score's add */
#define C5_OPS_HEAP_STEP 8     /* a step of the cells' heap: two 48-bit scores compared, an entry and
                                  its position moved */

/* Moving the tree between the DSP RAM and the scheduler (dsp_sched.c) and building it
 * during the frame (cell_tree.c): a 12-byte node is four 24-bit words, unpacked or packed
 * by shifts and masks. */
#define C5_OPS_NODE_READ 10
#define C5_OPS_NODE_WRITE 10
#define C5_OPS_TAG 6 /* a packet's tag decision beyond its node accesses: compare cells, branch */

/* The between-frame budget of the scheduling (export, the rule, write-back): 10 ms at
 * 255 MIPS. The next frame cannot start before its schedule, so the budget is board time
 * lost every frame: 10 ms is under two cell fetches and 3 % of the board's frame on the
 * 1/27 splits of docs/cell-tree.md's cases, and it holds the paper's rule on the
 * largest tree (8,191 nodes) with room. docs/cell-tree.md, "The DSP's budget". */
#define C5_DSP_SCHED_BUDGET_OPS 2550000ull

/* The rule's share of the budget on a tree of n nodes: what export and write-back leave
 * (at least 1; 0 would mean no budget). */
static inline uint64_t c5_dsp_rule_budget(int n)
{
    uint64_t io = (uint64_t)(n > 0 ? n : 0) * (C5_OPS_NODE_READ + C5_OPS_NODE_WRITE);
    return io < C5_DSP_SCHED_BUDGET_OPS ? C5_DSP_SCHED_BUDGET_OPS - io : 1;
}

/* The SDRAM tree's between-frame budget (cell_tree_sdram.h): a share of the board time of the
 * frame whose tree it schedules, less reading the tree out and writing it back (io_ops), and
 * never below the on-chip rule's. A split of 512 or 4,096 cells makes trees of 10^4 to 10^5
 * nodes whose frames take seconds of board time; the window rule needs tens to hundreds of
 * millions of operations to shorten them (docs/cell-tree.md, "Where the tree lives"). The
 * share is board time the next frame waits: the fetches it saves must pay for it, and the
 * board's reported frame time includes it. */
#define C5_DSP_SDRAM_FRAME_SHARE 0.10
static inline uint64_t c5_dsp_sdram_budget(double board_s, uint64_t io_ops)
{
    double ops = C5_DSP_SDRAM_FRAME_SHARE * board_s * C5_DSP_MIPS * 1e6;
    uint64_t share = ops > 1e15 ? (uint64_t)1e15 : (uint64_t)ops;
    uint64_t rule = share > io_ops ? share - io_ops : 0;
    return rule > C5_DSP_SCHED_BUDGET_OPS ? rule : C5_DSP_SCHED_BUDGET_OPS;
}

static inline double c5_dsp_us(uint64_t ops) { return (double)ops / C5_DSP_MIPS; }

#endif
