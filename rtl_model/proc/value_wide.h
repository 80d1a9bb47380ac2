/* The interpolation and classification blocks (c5_interp_blend_w, then c5_classify_channels:
 * the opacity, and the colour where a sample has one) for up to eight consecutive samples of one ray at once, on
 * the host's AVX2 and FMA units: the same integers, lane by lane.
 *
 * Why it is exact in doubles: the trilinear weights are products of 15-bit fractions, below
 * 2^45, and the blend sums eight of them times voxels below 2^8: every partial sum stays
 * within 255 2^45 < 2^53, so it is the same integer in any order; the half-to-even shift by 37
 * is a multiplication by 2^-37 and a round to even. The table's channels are linear in 32-bit
 * integer lanes (entries below 2^16, times 256). docs/board-model.md, "Host speed". */
#ifndef C5_VALUE_WIDE_H
#define C5_VALUE_WIDE_H

#include <stdint.h>

#include "cells.h"
#include "regs.h"

#define C5_VALUE_LANES 8

typedef struct {
    int32_t value[C5_VALUE_LANES];   /* sample_value UQ8.8 */
    int32_t alpha[C5_VALUE_LANES];   /* tf alpha UQ1.15 */
    int32_t frac[3][C5_VALUE_LANES]; /* c5_corners.frac */
    unsigned lit;                    /* bit j: sample j < n has alpha > 0 */
    int32_t rgb[3][C5_VALUE_LANES];  /* tf colour UQ1.15, where lit has a bit */
    int64_t tag[C5_VALUE_LANES];     /* the voxel cache's tag (c5_cache_tag_of) */
} c5_value_lanes;

/* value, alpha, frac, lit, rgb and tag of the n (1..8) samples at pos + j S, j < n, at the shipped
 * widths, as c5_gather_values, c5_interp_blend_w and c5_classify_channels give them (m: the RDRAM
 * holding their corners): 0, or -1 with nothing written where the host lacks the wide units
 * or a sample lies within a voxel or two of the grid's faces (no corner may need a clamp,
 * and x reads one voxel more either side). */
int c5_value_wide(const c5_frame_regs *r, const c5_rdram *m, const int64_t pos[3], const int64_t S[3], int n,
                  c5_value_lanes *o);

#endif
