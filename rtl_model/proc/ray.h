/* The ray's registers inside the processor: the fields of the 32-byte ray packet
 * (docs/bit-layouts.md), held as raw integers in arrays for the datapath. The one difference:
 * the processor holds the position in grid coordinates (the active cell's corner added, as
 * the set-up and hit units need it), the packet relative to the corner of the cell it is
 * queued for. Converting to and from the packet is lossless (the corner is a whole number of
 * voxels), which is why a ray's arithmetic cannot depend on where the cell boundaries fall:
 * between two samples the packet is the ray's whole state. */
#ifndef C5_RAY_H
#define C5_RAY_H

#include <stdint.h>

#define C5_POS_F 15       /* pos: voxel coordinates of the next sample, 15 fraction bits */
#define C5_DIR_F 14       /* dir: SQ1.14, unit direction */
#define C5_ONE15 (1 << 15)/* 1.0 in UQ1.15 (contribution, opacity, table entries) */
#define C5_RGB_F 12       /* red/green/blue: UQ2.12 */
#define C5_RGB_MAX ((1 << 14) - 1)
/* A frame accumulator's word (UQ20.12; below 2^53) as the image's float: exactly v 2^-12,
 * rounded once to float (the same as ldexp, without its call at every channel). */
static inline float c5_rgb_float(uint64_t v) { return (float)((double)v * (1.0 / (1 << C5_RGB_F))); }
#define C5_LIFE_NONE 4095u /* lifetime: unbounded */
#define C5_LIFE_MAX 4094u
#define C5_SURF_NONE 31u   /* interaction: no surface at the ray's end */
#define C5_NODE_NONE 8191u /* cell_tree_node: none */
#define C5_MAX_GEN 15
#define C5_MAX_CELLS 4096 /* cell_id: 12 bits */
#define C5_CELL_MAX_EDGE 256 /* pos in the packet: UQ8.15 from the cell's corner */
/* The grid side the model's geometry addresses: geom coordinates (SQ13.15, min spacings from
 * the grid origin) reach 8192; 8000 leaves room for rays stepping out of the grid. The packet
 * bounds the cell (C5_CELL_MAX_EDGE), not the grid. */
#define C5_MODEL_MAX_GRID 8000
/* The image side the packet's destination (9+9 bits) addresses. */
#define C5_MODEL_MAX_IMAGE 512

typedef struct {
    int64_t pos[3];    /* grid coordinates, 15 fraction bits; the processor lets it step outside the grid */
    int64_t dir[3];    /* SQ1.14 */
    uint32_t u, v;     /* destination pixel */
    uint32_t lifetime; /* samples left before the ray's end, C5_LIFE_NONE: unbounded */
    int64_t w;         /* contribution, UQ1.15 */
    int64_t opa;       /* accumulated opacity A = 1 - T, UQ1.15 */
    uint32_t gen, node, cell, type, surf;
    int64_t rgb[3];    /* UQ2.12: composited colour, or a shadow ray's radiance */
    uint32_t shadow;   /* the unbounded tree instrument's node (tree_demand.h): beside the
                        * packet, not in it; the board carries it next to every stored packet */
} c5_bray;

#define C5_PACKET_BYTES 32
struct c5_cells;
/* Packs into / unpacks from the 32-byte packet (generated layout), the position relative to
 * the corner of cell r->cell of the split `c`. Packing asserts that every field is in its
 * format's range: a ray is only queued for the cell its position is in, with its opacity
 * below max_opacity. */
void c5_bray_pack(const c5_bray *r, const struct c5_cells *c, uint8_t out[C5_PACKET_BYTES]);
void c5_bray_unpack(const uint8_t in[C5_PACKET_BYTES], const struct c5_cells *c, c5_bray *r);

#endif
