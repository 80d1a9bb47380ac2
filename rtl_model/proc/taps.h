/* Taps: optional observers of the model's blocks while it renders, for golden vectors
 * (vectors/gen/, docs/vectors.md). Each callback sees one transaction of one block, its
 * inputs and outputs as the hardware signals would carry them. A NULL c5_taps, or a NULL
 * callback, costs one predictable branch; taps never change what the model computes. */
#ifndef C5_TAPS_H
#define C5_TAPS_H

#include <stdint.h>

#include "ray_queue.h"

/* The per-sample datapath's transactions (rtl_model/proc/sample_pipe.h, processor.c): each
 * block's inputs and outputs in the raw integers of its declared formats. */

/* A sample's gather from the RDRAM cell: the inputs of the interpolation and gradient
 * blends (c5_interp_blend, c5_grad_blend). Corner k = kx + 2 ky + 4 kz (x fastest). */
typedef struct c5_corners {
    int64_t frac[3]; /* voxel_frac UQ0.15 per axis: the weight of the upper corners */
    int32_t v[8];    /* the corner voxels (uint8), indices clamped to the grid */
    int32_t d[3][8]; /* with the gradient only: per axis a and corner k the central
                        difference v(c + e_a) - v(c - e_a), SQ8.0 (indices clamped) */
} c5_corners;

/* One sample through c5_shade. */
typedef struct c5_shade_io {
    int64_t grad[3]; /* in: gradient SQ8.8 */
    int64_t rgba[4]; /* in: tf_rgba UQ1.15 (alpha unused) */
    int64_t gpos[3]; /* in: the sample in geom coordinates, SQ13.15 */
    int64_t dir[3];  /* in: the ray direction, SQ1.14 */
    int64_t rgb[3];  /* out: shaded_rgb UQ4.12 */
    int sat;         /* out: channels clamped (0..3) */
} c5_shade_io;

/* One sample through c5_composite. */
typedef struct c5_composite_io {
    int64_t w, opa, rgb[3]; /* in: the ray's contribution, opacity (UQ1.15), colour (UQ2.12) */
    int64_t alpha;          /* in: tf_rgba alpha UQ1.15 */
    int64_t c[3];           /* in: shaded_rgb UQ4.12 (ignored for shadow rays) */
    int64_t a_max;          /* in: max_opacity UQ1.15 */
    int shadow;             /* in: a shadow ray (attenuates only) */
    int64_t rgb_out[3], opa_out; /* out */
    int done, sat;          /* out: early termination, channels clamped (0..3) */
} c5_composite_io;

/* One step of the traversal loop (c5_trav_step, processor.h). */
enum {
    C5_TRAV_SAMPLE, /* sample at pos, then pos' = pos + S, lifetime' = lifetime - 1 (4095 stays) */
    C5_TRAV_LEAP,   /* pos is in an empty 8^3 block: leap `leaped` samples to the block's (or
                       cell's) exit without sampling, cut by the lifetime */
    C5_TRAV_LEAVE,  /* lifetime 0, or pos outside the grid or the cell: the ray is routed on
                       (pos and lifetime unchanged) */
};
typedef struct c5_trav_in {
    int64_t pos[3];      /* grid voxel coordinates, 15 fraction bits; may have stepped outside the grid */
    int64_t S[3];        /* step_vec SQ3.15 */
    uint32_t lifetime;   /* samples left, C5_LIFE_NONE (4095): unbounded */
    int lo[3], hi[3];    /* the cell's voxel box [lo, hi) */
    int dims[3];         /* the grid's voxels */
    int block_empty;     /* the flag of the 8^3 block holding pos (0 outside the grid) */
} c5_trav_in;
typedef struct c5_trav_out {
    int action;          /* C5_TRAV_* */
    int64_t leaped;      /* samples leaped (C5_TRAV_LEAP) */
    int64_t pos[3];
    uint32_t lifetime;
} c5_trav_out;

typedef struct c5_taps {
    void *ctx;
    /* A packet as it is written to the eDRAM or SDRAM queue (32 bytes, little-endian). */
    void (*packet)(void *ctx, const uint8_t *packet);
    /* A packet crossing the ray bus between the processor and the DSP (32 bytes): to_dsp 1,
     * a ray the processor hands to the DSP (for another cell's SDRAM queue, a spill of the
     * active cell's, or an eye ray of the set-up), as it leaves the processor: before the DSP
     * tags it with its Cell Tree node; to_dsp 0, a packet of the active cell's SDRAM queue
     * streaming into the sorter (called after the queue tap of the cycle that accepted it). */
    void (*bus)(void *ctx, const uint8_t *packet, int to_dsp);
    /* One clock cycle of the active cell's eDRAM sorter. */
    void (*queue)(void *ctx, const c5_rq_in *in, const c5_rq_out *out);
    /* The DSP's Cell Tree rule on one packet: (node, cell) in, the packet's new node out. */
    void (*tree_tag)(void *ctx, uint32_t node, int cell, uint32_t result);
    /* The frame buffer after the frame: w x h pixels of three uint64 sums. */
    void (*frame)(void *ctx, const uint64_t *fb, int w, int h);
    /* The per-sample datapath of c5_proc_run, every sample the processor takes: the
     * interpolation (the gather's fracs and corners in, sample_value UQ8.8 out), the
     * gradient (with gradients on: the gather in, gs UQ1.15 and gradient SQ8.8), the
     * classification (sample_value in, tf_rgba out), and for samples with alpha > 0 the
     * shading (with lights and gradients) and the compositing. */
    void (*interp)(void *ctx, const c5_corners *k, int64_t value);
    void (*gradient)(void *ctx, const c5_corners *k, const int64_t gs[3], const int64_t grad[3]);
    void (*classify)(void *ctx, int64_t value, const int64_t rgba[4]);
    void (*shade)(void *ctx, const c5_shade_io *io);
    void (*composite)(void *ctx, const c5_composite_io *io);
    /* Every step of the traversal loop: sample, leap, or leave the cell. */
    void (*traverse)(void *ctx, const c5_trav_in *in, const c5_trav_out *out);
} c5_taps;

#endif
