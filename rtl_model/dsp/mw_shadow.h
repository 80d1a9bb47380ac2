/* Max Work's shadow: the DSP runs Max Work on the frame's Cell Tree as it grows, while the
 * board follows another order of loads (docs/cell-tree.md, "The certificate").
 *
 * Every ray tagged with a node reaches its cell's queue in the load that works off the node's
 * parent (the eye rays: in the set-up), so once a node's cell has been loaded after that, the
 * node's rays are done and its children, with their ray counts, are known. The shadow replays
 * Max Work's choices (most waiting rays, ties to the lowest cell id: the board's rule) on
 * exactly those nodes, and takes a step only when every node that step works off is already
 * done on the board. So after k loads of the board and j steps of the shadow:
 *
 *  - each step the shadow took is one of the frame's Max Work loads, in Max Work's order;
 *  - when the board loads the cell of the shadow's next step, that step becomes possible:
 *    a load spent that way lets the shadow take at least one more step;
 *  - when every queue is empty, the shadow can finish, and its steps are Max Work's fetches
 *    of the frame (the replay of stale_plan.h on the frame's tree, exactly).
 *
 * Hence, whatever the board loaded first, loading the shadow's cells from now on ends the
 * frame within k - j + MW fetches, MW being Max Work's: k - j is the most that following
 * another order has cost so far against Max Work, and the board can cap it. */
#ifndef C5_MW_SHADOW_H
#define C5_MW_SHADOW_H

#include <stdint.h>

#include "cell_tree.h"

/* DSP operations: per packet tagged (the node's state read beside its count), per node worked
 * off on the board (its waiting entry cleared), per node of a shadow step (its children made
 * waiting), per cell per step (Max Work's choice: the scan of the cells' waiting counts). */
#define C5_OPS_SHADOW_TAG 2
#define C5_OPS_SHADOW_DONE 4
#define C5_OPS_SHADOW_NODE 8
#define C5_OPS_SHADOW_CELL 2

typedef struct {
    int ncells;
    uint32_t none;       /* node ids from here on mean none: C5_NODE_NONE on chip, the SDRAM
                          * tree's node capacity there; the arrays hold none + 1 entries */
    uint32_t *rays;      /* [none + 1] packets tagged with each node */
    int32_t *cell;       /* [slots] the node's cell */
    int32_t *first, *sibling; /* [slots] children lists */
    uint8_t *state;      /* [slots] SH_* bits (mw_shadow.c) */
    int32_t *link;       /* [slots] next node in its cell's list of nodes waiting on the board */
    int32_t *vlink;      /* [slots] next node in its cell's list of nodes waiting in the shadow */
    int32_t *head, *vhead; /* [ncells] those lists */
    uint64_t *vrays;     /* [ncells] rays of the nodes waiting in the shadow */
    uint32_t *vpending;  /* [ncells] of those, nodes not yet done on the board */
    uint64_t steps;      /* j: Max Work's loads the shadow has taken */
    int broken;          /* a packet the shadow cannot place (no node: the RAM overflowed; a node
                          * already done): no bound for the rest of the frame */
    uint64_t ops;        /* DSP operations (the C5_OPS_SHADOW_* weights) */
} c5_mw_shadow;

/* Node ids below `none` (0: C5_NODE_NONE, the on-chip tree's). 0, or -1 when out of memory. */
int c5_mw_shadow_init(c5_mw_shadow *s, int ncells, uint32_t none);
void c5_mw_shadow_free(c5_mw_shadow *s);

/* A packet the DSP queues for `cell` from another cell (or the set-up), tagged `node`; `from`:
 * the node it carried before (C5_NODE_NONE: none, the node is the cell's root). */
void c5_mw_shadow_tag(c5_mw_shadow *s, uint32_t from, uint32_t node, int cell);

/* The board loads `cell`: every node waiting in its queue is worked off. */
void c5_mw_shadow_load(c5_mw_shadow *s, int cell);

/* Takes every step the board's loads allow. Returns the cell of the next step, which needs a
 * load of that cell first (its queue holds rays), or -1 when the shadow has finished. */
int c5_mw_shadow_advance(c5_mw_shadow *s);

#endif
