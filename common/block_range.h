/* The value range (least and greatest voxel) of every 8^3 block of a super volume's grid, and
 * of every block with a one-voxel apron: what the board model's emptiness flags are derived
 * from (rtl_model/mem/cells.c) for any split and transfer function without reading the grid
 * again. 4 bytes a block: 8 MiB for a 1024^3 grid.
 *
 * A grid that is one file's voxels (c5_supervol.file_id), or out of core, keeps its ranges
 * with it once made, and in a file of cube5's cache (cache_dir.h) named by its identity, so a
 * later run reads the 8 MiB instead of the grid (docs/out-of-core.md, "Block ranges"). */
#ifndef C5_BLOCK_RANGE_H
#define C5_BLOCK_RANGE_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "supervol.h"

#define C5_RANGE_BLOCK 8

typedef enum { C5_RANGE_COMPUTED, C5_RANGE_FROM_CACHE, C5_RANGE_CACHED_NOW } c5_range_origin;

typedef struct c5_block_range {
    size_t bdims[3];       /* blocks a side: ceil(dims / 8) */
    uint8_t *mn, *mx;      /* [bdims product], x fastest: the block's own voxels (a block at the
                            * grid's far faces holds only those inside the grid) */
    uint8_t *amn, *amx;    /* the same with a one-voxel apron: voxels [8b - 1, 8b + 8] per axis,
                            * clamped to the grid (what a sample in the block can read) */
    c5_range_origin origin;
} c5_block_range;

/* The ranges of sv's grid (resident or out of core). A grid from one file, or out of core
 * with an identity (c5_supervol.grid_id: a generated volume too): kept in sv (made once,
 * thread-safe; sv frees them) and in the cache; *owned = NULL. Any other grid (a resident one
 * whose voxels the caller may change after the build): made now into *owned, which the
 * caller frees with c5_block_range_free. NULL with err: a read of the grid failed, or out of
 * memory. */
const c5_block_range *c5_block_range_of(const c5_supervol *sv, c5_block_range **owned, c5_err *err);
void c5_block_range_free(c5_block_range *r);
/* The block of voxel index i along an axis. */
static inline size_t c5_range_block_of(size_t i) { return i / C5_RANGE_BLOCK; }

#endif
