/* An out-of-core grid's cells on disk as the board's RDRAM holds them: each cell with its
 * ghost layers, x fastest (c5_cell_bytes), one after another (each from a page boundary) in a
 * file of cube5's cache (common/cache_dir.h), made once per grid and split from the grid's
 * sources (a generated volume is generated once, not at every fetch). A fetch then reads its
 * cell in place: one contiguous span of the mapped file, asked of the disk when the cell is
 * fetched and dropped from the process when the next one is, so host memory holds one cell
 * whatever the grid (docs/out-of-core.md, "Cells on disk"). */
#ifndef C5_CELL_STORE_H
#define C5_CELL_STORE_H

#include <stddef.h>
#include <stdint.h>

#include "cells.h"
#include "err.h"
#include "supervol.h"

typedef struct c5_cell_store c5_cell_store;

/* The store of sv's grid split as c: opened if the cache holds it, else made (one pass over
 * the grid). 0 with *out set; 0 with *out NULL when there is none to have (a resident grid, a
 * source without identity, the cache off, not writable, or without the room: C5_CACHE_MAX,
 * cache_dir.h; the caller copies each cell from the sources); -1 with err when a read of the
 * grid failed. */
int c5_cell_store_open(const c5_supervol *sv, const c5_cells *c, c5_cell_store **out, c5_err *err);
/* The cell's bytes (c5_cell_bytes of them), its pages asked of the disk now. */
const uint8_t *c5_cell_store_cell(c5_cell_store *s, int cell);
/* The cell will be fetched soon (the schedule's next): its pages asked of the disk now. */
void c5_cell_store_prefetch(c5_cell_store *s, int cell);
/* The cell is no longer read: its pages leave the process. */
void c5_cell_store_release(c5_cell_store *s, int cell);
void c5_cell_store_close(c5_cell_store *s);
/* 1 when open found the store in the cache, 0 when it made it. */
int c5_cell_store_was_cached(const c5_cell_store *s);

#endif
