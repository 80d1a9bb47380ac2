/* Taps: optional observers of the model's blocks while it renders, for golden vectors
 * (vectors/gen/, docs/vectors.md). Each callback sees one transaction of one block, its
 * inputs and outputs as the hardware signals would carry them. A NULL c5_taps, or a NULL
 * callback, costs one predictable branch; taps never change what the model computes. */
#ifndef C5_TAPS_H
#define C5_TAPS_H

#include <stdint.h>

#include "ray_queue.h"

typedef struct c5_taps {
    void *ctx;
    /* A packet as it is written to the eDRAM or SDRAM queue (32 bytes, little-endian). */
    void (*packet)(void *ctx, const uint8_t *packet);
    /* One clock cycle of the active cell's eDRAM sorter. */
    void (*queue)(void *ctx, const c5_rq_in *in, const c5_rq_out *out);
    /* The DSP's Cell Tree rule on one packet: (node, cell) in, the packet's new node out. */
    void (*tree_tag)(void *ctx, uint32_t node, int cell, uint32_t result);
    /* The frame buffer after the frame: w x h pixels of three uint64 sums. */
    void (*frame)(void *ctx, const uint64_t *fb, int w, int h);
} c5_taps;

#endif
