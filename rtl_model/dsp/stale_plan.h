/* What the DSP knows, between frames, about following a schedule next frame
 * (docs/cell-tree.md, "The certificate"): Max Work and the schedule both replayed on the
 * frame's Cell Tree with the rays each node received (the DSP counts the packets it tags,
 * one 24-bit word per node slot beside the 96 KB RAM). On the frame's own tree the replay
 * is exact: it gives the loads each order would make on that frame. The ledger (ledger.h)
 * takes the path's bank, the allowance and the evidence of the last camera step from it.
 * Counted in the DSP's operations (dsp_cost.h). */
#ifndef C5_STALE_PLAN_H
#define C5_STALE_PLAN_H

#include <stdint.h>

#include "cell_tree.h"
#include "cell_tree_sdram.h"
#include "err.h"

/* DSP operations of the replay: per node (its count read, added to its cell's waiting
 * rays, its children listed), per load and cell (Max Work's choice, the scan of the cells'
 * waiting counts), per schedule entry (the entry read, the prediction written). */
#define C5_OPS_PLAN_NODE 8
#define C5_OPS_PLAN_CELL 2
#define C5_OPS_PLAN_ENTRY 4
/* Per packet the DSP tags, the node's ray count read, incremented, written (while the frame
 * renders, beside the tag decision). */
#define C5_OPS_NODE_COUNT 3

typedef struct {
    int valid;          /* 0: no prediction (no tree, an overflowed tree) */
    int maxwork_loads;  /* loads of Max Work replayed on the tree */
    int sched_loads;    /* loads following the schedule on the tree (entries that find rays), then
                         * Max Work for any rays left (none on the tree the schedule came from) */
    int len;            /* schedule entries */
    int lag_loads;      /* loads of the schedule this frame followed (made from the frame before),
                         * replayed on this frame's tree: what following a one-frame-old schedule
                         * cost here; -1: there was none */
    uint64_t frame_key; /* the camera registers of the tree's frame (c5_board_stats.frame_key): a
                         * frame with the same key renders the same rays, so the same tree */
    int64_t bank;       /* the path's balance after the tree's frame: Max Work's loads less the
                         * board's fetches, summed over the frames so far (c5_stale_plan_settle) */
    uint32_t *pred;     /* [len] rays the entry's cell holds when the replay reaches it (0: it is
                         * passed empty) */
    uint64_t rays;      /* packets the tree's nodes received */
    uint64_t ops;       /* the replay's DSP operations */
} c5_stale_plan;

/* Replays Max Work, `sched` (len entries of cell ids) and `lag_sched` (the schedule followed
 * in the tree's frame, or NULL) on tree t with node_rays[slot] the packets tagged with each
 * node slot (C5_TREE_SLOTS entries). 0, or -1 with a message. */
int c5_stale_plan_make(const c5_ctree *t, const uint32_t *node_rays, const int *sched, int len, const int *lag_sched,
                       int lag_len, c5_stale_plan *p, c5_err *err);
/* The same on the tree in the DSP's SDRAM, with the packets its rays[] counted. */
int c5_stale_plan_make_sdram(const c5_sdram_tree *t, const int *sched, int len, const int *lag_sched, int lag_len,
                             c5_stale_plan *p, c5_err *err);
void c5_stale_plan_free(c5_stale_plan *p);

/* The ledger after the tree's frame: p->bank = the previous frame's bank (prev, NULL on the
 * path's first frame) + Max Work's loads replayed on this frame's tree - `fetches`, the loads
 * the board made in the frame. The replay is exact on the frame's own tree, so the bank is
 * the exact saving of the path so far; frame_key: the frame's (c5_board_stats.frame_key). A
 * frame without a valid replay (its tree overflowed
 * the RAM: the next frame schedules groups, without a certificate) adds nothing. */
void c5_stale_plan_settle(c5_stale_plan *p, const c5_stale_plan *prev, uint64_t fetches, uint64_t frame_key);

#endif
