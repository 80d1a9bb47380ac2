/* Cell split, emptiness flags, RDRAM fetch (cells.h). */
#include <stdlib.h>
#include <string.h>

#include "cells.h"

/* No sample whose trilinear corners lie in [lo, hi] (voxels, inclusive, clamped) can have
 * alpha > 0: every table entry the interpolated value can touch, floor(min) .. max + 1,
 * has alpha 0. */
static int range_empty(const c5_supervol *sv, const int lo[3], const int hi[3], const int nz_prefix[257])
{
    unsigned vmin = 255, vmax = 0;
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++) {
                unsigned v = c5_supervol_at(sv, x, y, z);
                vmin = v < vmin ? v : vmin;
                vmax = v > vmax ? v : vmax;
            }
    unsigned top = vmax + 1 > 255 ? 255 : vmax + 1;
    return nz_prefix[top + 1] - nz_prefix[vmin] == 0;
}

void c5_cell_box(const c5_cells *c, int cell, int lo[3], int hi[3])
{
    int idx[3] = {cell % c->n[0], (cell / c->n[0]) % c->n[1], cell / (c->n[0] * c->n[1])};
    for (int a = 0; a < 3; a++) {
        lo[a] = c->lo[a][idx[a]];
        hi[a] = c->lo[a][idx[a] + 1];
    }
}

size_t c5_cell_bytes(const c5_cells *c, int cell)
{
    int lo[3], hi[3];
    c5_cell_box(c, cell, lo, hi);
    return (size_t)(hi[0] - lo[0] + 2 * C5_GHOST) * (size_t)(hi[1] - lo[1] + 2 * C5_GHOST) *
           (size_t)(hi[2] - lo[2] + 2 * C5_GHOST);
}

/* The split and the tables, flags left for the caller. */
static int cells_alloc(c5_cells *c, const size_t dims[3], const int n[3], c5_err *err)
{
    memset(c, 0, sizeof *c);
    c->count = 1;
    for (int a = 0; a < 3; a++) {
        c->dims[a] = (int)dims[a];
        c->n[a] = n[a] > 1 ? n[a] : 1;
        c->count *= c->n[a];
        c->lo[a] = malloc(sizeof(int) * (size_t)(c->n[a] + 1));
        c->of[a] = malloc(sizeof(uint16_t) * (size_t)c->dims[a]);
        c->bdims[a] = (c->dims[a] + C5_BLOCK - 1) / C5_BLOCK;
        if (!c->lo[a] || !c->of[a])
            goto oom;
        for (int i = 0; i <= c->n[a]; i++)
            c->lo[a][i] = (int)((long)i * c->dims[a] / c->n[a]);
        for (int i = 0; i < c->n[a]; i++)
            for (int x = c->lo[a][i]; x < c->lo[a][i + 1]; x++)
                c->of[a][x] = (uint16_t)i;
    }
    c->empty = calloc((size_t)c->count, 1);
    c->block_empty = calloc(c5_cells_blocks(c), 1);
    if (!c->empty || !c->block_empty)
        goto oom;
    return 0;
oom:
    c5_cells_free(c);
    return c5_fail(err, "out of memory for the cell tables");
}

int c5_cells_init(c5_cells *c, const c5_supervol *sv, const int n[3], const uint8_t alpha_nz[256], c5_err *err)
{
    if (cells_alloc(c, sv->dims, n, err) != 0)
        return -1;
    int nz_prefix[257] = {0};
    for (int i = 0; i < 256; i++)
        nz_prefix[i + 1] = nz_prefix[i] + (alpha_nz[i] != 0);
    for (int cell = 0; cell < c->count; cell++) {
        int lo[3], hi[3];
        c5_cell_box(c, cell, lo, hi);
        for (int a = 0; a < 3; a++)
            lo[a]--; /* hi is already the first voxel past the cell: the upper corner */
        c->empty[cell] = (uint8_t)range_empty(sv, lo, hi, nz_prefix);
    }
    for (int bz = 0; bz < c->bdims[2]; bz++)
        for (int by = 0; by < c->bdims[1]; by++)
            for (int bx = 0; bx < c->bdims[0]; bx++) {
                int b[3] = {bx, by, bz}, lo[3], hi[3];
                for (int a = 0; a < 3; a++) {
                    lo[a] = b[a] * C5_BLOCK - 1;
                    hi[a] = (b[a] + 1) * C5_BLOCK;
                }
                c->block_empty[((size_t)bz * c->bdims[1] + by) * c->bdims[0] + bx] =
                    (uint8_t)range_empty(sv, lo, hi, nz_prefix);
            }
    return 0;
}

int c5_cells_init_flags(c5_cells *c, const size_t dims[3], const int n[3], const uint8_t *cell_empty,
                        const uint8_t *block_empty, c5_err *err)
{
    if (cells_alloc(c, dims, n, err) != 0)
        return -1;
    memcpy(c->empty, cell_empty, (size_t)c->count);
    memcpy(c->block_empty, block_empty, c5_cells_blocks(c));
    return 0;
}

size_t c5_cells_blocks(const c5_cells *c)
{
    return (size_t)c->bdims[0] * (size_t)c->bdims[1] * (size_t)c->bdims[2];
}

void c5_cells_free(c5_cells *c)
{
    for (int a = 0; a < 3; a++) {
        free(c->lo[a]);
        free(c->of[a]);
    }
    free(c->empty);
    free(c->block_empty);
    memset(c, 0, sizeof *c);
}

int c5_rdram_place(c5_rdram *m, const c5_cells *c, int cell, c5_err *err)
{
    c5_cell_box(c, cell, m->lo, m->hi);
    size_t need = 1;
    for (int a = 0; a < 3; a++) {
        m->org[a] = m->lo[a] - C5_GHOST;
        m->ext[a] = m->hi[a] - m->lo[a] + 2 * C5_GHOST;
        need *= (size_t)m->ext[a];
    }
    if (need > m->cap) {
        uint8_t *p = realloc(m->v, need);
        if (!p)
            return c5_fail(err, "out of memory for the RDRAM model (%zu bytes)", need);
        m->v = p;
        m->cap = need;
    }
    m->cell = cell;
    return 0;
}

int c5_rdram_load(c5_rdram *m, const c5_cells *c, const c5_supervol *sv, int cell, c5_err *err)
{
    if (c5_rdram_place(m, c, cell, err) != 0)
        return -1;
    /* Row by row: the part of a row inside the grid is one copy of the volume's row (the
     * clamp changes no index there), the ghost voxels beyond the grid's faces are clamped. */
    long nx = (long)sv->dims[0], x0 = -m->org[0], x1 = nx - m->org[0];
    x0 = x0 < 0 ? 0 : x0 > m->ext[0] ? m->ext[0] : x0;
    x1 = x1 < x0 ? x0 : x1 > m->ext[0] ? m->ext[0] : x1;
    size_t o = 0;
    for (int z = 0; z < m->ext[2]; z++)
        for (int y = 0; y < m->ext[1]; y++) {
            for (long x = 0; x < x0; x++)
                m->v[o + (size_t)x] = (uint8_t)c5_supervol_at(sv, m->org[0] + x, m->org[1] + y, m->org[2] + z);
            if (x1 > x0) {
                long ny = (long)sv->dims[1], nz = (long)sv->dims[2], j = m->org[1] + y, k = m->org[2] + z;
                j = j < 0 ? 0 : j >= ny ? ny - 1 : j;
                k = k < 0 ? 0 : k >= nz ? nz - 1 : k;
                const uint8_t *row = sv->v + ((size_t)k * (size_t)ny + (size_t)j) * (size_t)nx;
                memcpy(m->v + o + x0, row + m->org[0] + x0, (size_t)(x1 - x0));
            }
            for (long x = x1; x < m->ext[0]; x++)
                m->v[o + (size_t)x] = (uint8_t)c5_supervol_at(sv, m->org[0] + x, m->org[1] + y, m->org[2] + z);
            o += (size_t)m->ext[0];
        }
    return 0;
}

void c5_rdram_free(c5_rdram *m)
{
    free(m->v);
    memset(m, 0, sizeof *m);
    m->cell = -1;
}
