/* The gradient and shading blocks (sample_pipe.h: c5_grad_blend, and c5_shade_w at the
 * shipped widths) for up to eight samples at once, on the host's AVX2 and FMA units: the same
 * integers as c5_grad_blend and c5_shade, lane by lane.
 *
 * Why it is exact in doubles: every value the blocks blend, normalise or multiply is an
 * integer below 2^53 (a gradient blend's partial sums within 255 2^45, a normal's gradient
 * below 2^17 a component, a half vector's below 2^16, a point light's direction below 2^25,
 * checked), so sums and products are exact; each rounding is done on an exact value (a
 * half-to-even shift is a multiplication by a power of 2 and a round to even; a quotient is
 * rounded from the correctly rounded double and checked on its exact remainder, which FMA
 * forms; floor(sqrt) likewise), and the light terms' products, up to 2^64, are split into
 * two exact halves. docs/board-model.md, "Host speed". */
#ifndef C5_SHADE_WIDE_H
#define C5_SHADE_WIDE_H

#include <stdint.h>

#include "regs.h"

#define C5_SHADE_LANES 8
#define C5_SHADE_ROWS 12

/* Shaded samples of one ray (one direction): inputs and, after c5_shade_wide, outputs. */
typedef struct {
    int n;              /* lanes in use, 1..C5_SHADE_LANES */
    /* The gradient block's inputs (c5_grad_wide): per axis and corner the lanes' central
     * differences (c5_corners.d), and per axis their fractions (c5_corners.frac) */
    int32_t diff[3][8][C5_SHADE_LANES];
    int32_t frac[3][C5_SHADE_LANES];
    /* Or, in the lanes whose bit is set in rows, the voxels those differences are taken
     * from (c5_gather_rows_at): the twelve rows of four (x = i - 1 .. i + 2) at C5_ROW_DY,
     * C5_ROW_DZ from the sample's corner 0, a byte each, x = i - 1 lowest */
    uint32_t row[C5_SHADE_ROWS][C5_SHADE_LANES];
    unsigned rows;
    int64_t grad[C5_SHADE_LANES][3]; /* c5_sample.grad: c5_grad_wide's, or given */
    /* The voxel position (read for point lights only: their direction is from its geom
     * position, as c5_geom_from_voxel makes it) */
    int32_t vpos[3][C5_SHADE_LANES];
    int32_t rgb[3][C5_SHADE_LANES];  /* the table colour, UQ1.15 */
    int64_t out[C5_SHADE_LANES][3];  /* shaded_rgb UQ4.12 */
    uint64_t sat[C5_SHADE_LANES];    /* each lane's saturations (c5_shade's count) */
} c5_shade_lanes;

/* grad of lanes 0..n-1 from diff and frac as c5_grad_blend gives it (gs: r->gs), on the
 * wide units where the host has them. */
void c5_grad_wide(const c5_frame_regs *r, c5_shade_lanes *b);
/* out and sat of lanes 0..n-1 as c5_shade(r, lane, d) gives them; the lanes on the wide units
 * where the host has them and every lane is in range (a point light's direction below 2^25,
 * a voxel position below 2^28), else one by one. */
void c5_shade_wide(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b);
/* c5_grad_wide, then c5_shade_wide, with the gradients kept in the lanes between them (grad
 * is written only where the shading goes lane by lane). */
void c5_grad_shade_wide(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b);
/* Whether c5_shade_wide runs on the wide units on this host (0 in builds without them). */
int c5_shade_wide_usable(void);
/* The wide path alone (tests): 0, or -1 where it does not run (no AVX2 and FMA on the host,
 * or a lane out of its range), out and sat untouched. */
int c5_shade_wide_only(const c5_frame_regs *r, const int64_t d[3], c5_shade_lanes *b);
/* Its normalisation alone (tests): c5_geom_normalize of eight vectors with components below
 * 2^25; 0, or -1 where it does not run. */
int c5_shade_wide_normalize(const int64_t v[C5_SHADE_LANES][3], int64_t out[C5_SHADE_LANES][3]);

#endif
