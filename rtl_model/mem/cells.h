/* The super volume split into cells, the RDRAM that holds one of them, and the emptiness
 * flags that let rays leap over empty cells and empty 8^3 blocks.
 *
 * Split: along axis a with n_a cells, cell i owns voxels [floor(i X/n), floor((i+1) X/n)).
 * A fetched cell carries two ghost voxel layers on every face (clamped copies at the grid's
 * edge): one for the trilinear neighbour, one more for its central difference. */
#ifndef C5_CELLS_H
#define C5_CELLS_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "supervol.h"

#define C5_GHOST 2
#define C5_BLOCK 8 /* space-leaping block edge, voxels, aligned to the grid */

typedef struct c5_cells {
    int n[3], count;
    int dims[3];
    int *lo[3];            /* [n+1] boundaries per axis */
    uint16_t *of[3];       /* [dims] voxel index -> cell index per axis */
    uint8_t *empty;        /* [count] no sample in the cell can have alpha > 0 */
    int bdims[3];
    uint8_t *block_empty;  /* [bdims] the same for every 8^3 block of the grid */
} c5_cells;

/* The RDRAM holding one cell and its ghost layers, x fastest. */
typedef struct {
    int cell;              /* -1: nothing loaded */
    int lo[3], hi[3];      /* the cell's voxel box [lo, hi) */
    int org[3];            /* voxel coordinate of buffer index 0 = lo - 2 */
    int ext[3];            /* buffer extent = hi - lo + 4 */
    uint8_t *v;
    size_t cap;
    /* A view instead of v (c5_rdram_view): the grid itself, where the voxels already lie in
     * the host's memory, read with these strides; NULL: v, x fastest over ext. */
    const uint8_t *view;
    ptrdiff_t view_sy, view_sz, view_o0;
    const c5_supervol *view_of; /* an out-of-core grid viewed: its span is released when the
                                 * RDRAM is placed again or freed */
} c5_rdram;

/* What the processor reads: buffer index (x, y, z) (from org) is data[o0 + x + y sy + z sz].
 * The processor clamps every index to the grid before it reads, so a view is never read
 * outside the grid, though its ghost layers may lie beyond the grid's faces. */
static inline const uint8_t *c5_rdram_data(const c5_rdram *m, ptrdiff_t *o0, ptrdiff_t *sy, ptrdiff_t *sz)
{
    if (m->view) {
        *sy = m->view_sy;
        *sz = m->view_sz;
        *o0 = m->view_o0;
        return m->view;
    }
    *sy = m->ext[0];
    *sz = (ptrdiff_t)m->ext[0] * m->ext[1];
    *o0 = 0;
    return m->v;
}

/* alpha_nz: 1 for table entries with alpha > 0 (after the step correction). */
int c5_cells_init(c5_cells *c, const c5_supervol *sv, const int n[3], const uint8_t alpha_nz[256], c5_err *err);
/* The same split with the flags given (the emulated board: the host computed them with
 * c5_cells_init from the volume the board never sees whole); cell_empty has count bytes,
 * block_empty c5_cells_blocks. */
int c5_cells_init_flags(c5_cells *c, const size_t dims[3], const int n[3], const uint8_t *cell_empty,
                        const uint8_t *block_empty, c5_err *err);
void c5_cells_free(c5_cells *c);
/* 8^3 blocks of the grid: bdims[0] * bdims[1] * bdims[2]. */
size_t c5_cells_blocks(const c5_cells *c);

static inline int c5_cell_id(const c5_cells *c, int i, int j, int k) { return (k * c->n[1] + j) * c->n[0] + i; }
/* Cell of the voxel (x, y, z), which must be inside the grid. */
static inline int c5_cell_at(const c5_cells *c, int x, int y, int z)
{
    return c5_cell_id(c, c->of[0][x], c->of[1][y], c->of[2][z]);
}
void c5_cell_box(const c5_cells *c, int cell, int lo[3], int hi[3]);
/* Bytes a fetch of the cell moves: the cell and its ghost layers, one byte a voxel. */
size_t c5_cell_bytes(const c5_cells *c, int cell);

/* Makes the RDRAM hold the cell's box (org, ext; c5_cell_bytes of room), contents undefined. */
int c5_rdram_place(c5_rdram *m, const c5_cells *c, int cell, c5_err *err);
/* Places the cell and copies it with its ghost layers from the super volume. */
int c5_rdram_load(c5_rdram *m, const c5_cells *c, const c5_supervol *sv, int cell, c5_err *err);
/* The same voxels for the processor without the copy: a resident grid, or an out-of-core
 * grid that is one mapped file (c5_supervol_data), is read where it lies (m->view; out of
 * core the cell's pages are asked for now and dropped when the next cell is placed); any
 * other grid is copied (c5_rdram_load). With a view m->v holds nothing: only the processor's
 * reads (c5_rdram_data) see the cell. */
int c5_rdram_view(c5_rdram *m, const c5_cells *c, const c5_supervol *sv, int cell, c5_err *err);
/* The cell's bytes as the RDRAM holds them (c5_cell_bytes, x fastest over ext), read where
 * they are (an out-of-core grid's cell store, cell_store.h). */
void c5_rdram_at(c5_rdram *m, const c5_cells *c, int cell, const uint8_t *bytes);
void c5_rdram_free(c5_rdram *m);

#endif
