/* Cell split, emptiness flags, RDRAM fetch (cells.h). */
#include <stdlib.h>
#include <string.h>

#include "cells.h"

/* No sample whose trilinear corners lie in a voxel range of values vmin..vmax can have
 * alpha > 0: every table entry the interpolated value can touch, floor(min) .. max + 1,
 * has alpha 0. */
static int range_empty(unsigned vmin, unsigned vmax, const int nz_prefix[257])
{
    unsigned top = vmax + 1 > 255 ? 255 : vmax + 1;
    return nz_prefix[top + 1] - nz_prefix[vmin] == 0;
}

static void minmax(const uint8_t *p, size_t n, unsigned *mn, unsigned *mx)
{
    unsigned a = *mn, b = *mx;
    for (size_t i = 0; i < n; i++) {
        a = p[i] < a ? p[i] : a;
        b = p[i] > b ? p[i] : b;
    }
    *mn = a;
    *mx = b;
}

/* Bytes of one read of the flag passes: they stream the grid in pieces of this size (or one
 * row of blocks, (dims_x + 2) x 10 x 10), never the grid or a cell whole. */
#define FLAG_READ_BYTES ((size_t)1 << 22)

/* Values of voxels [lo, hi] (inclusive, clamped) read in rows of planes of at most
 * FLAG_READ_BYTES bytes through buf. */
static int box_range(const c5_supervol *sv, const int lo[3], const int hi[3], uint8_t *buf, unsigned *mn,
                     unsigned *mx, c5_err *err)
{
    size_t w = (size_t)(hi[0] - lo[0] + 1), band = FLAG_READ_BYTES / w > 0 ? FLAG_READ_BYTES / w : 1;
    *mn = 255;
    *mx = 0;
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y += (int)band) {
            int y1 = y + (int)band - 1 < hi[1] ? y + (int)band - 1 : hi[1];
            long blo[3] = {lo[0], y, z}, bhi[3] = {(long)hi[0] + 1, (long)y1 + 1, (long)z + 1};
            if (c5_supervol_read_box(sv, blo, bhi, buf, err) != 0)
                return -1;
            minmax(buf, w * (size_t)(y1 - y + 1), mn, mx);
        }
    return 0;
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
    /* one row of blocks with its apron: x in [-1, 8 bdims_x], 10 rows, 10 planes */
    size_t row_w = (size_t)c->bdims[0] * C5_BLOCK + 2, row_bytes = row_w * (C5_BLOCK + 2) * (C5_BLOCK + 2);
    size_t cap = row_bytes > FLAG_READ_BYTES + (size_t)c->dims[0] + 2 ? row_bytes : FLAG_READ_BYTES + (size_t)c->dims[0] + 2;
    uint8_t *buf = malloc(cap);
    if (!buf) {
        c5_cells_free(c);
        return c5_fail(err, "out of memory for the cell flags' read buffer (%zu bytes)", cap);
    }
    for (int cell = 0; cell < c->count; cell++) {
        int lo[3], hi[3];
        unsigned mn, mx;
        c5_cell_box(c, cell, lo, hi);
        for (int a = 0; a < 3; a++)
            lo[a]--; /* hi is already the first voxel past the cell: the upper corner */
        if (box_range(sv, lo, hi, buf, &mn, &mx, err) != 0)
            goto fail;
        c->empty[cell] = (uint8_t)range_empty(mn, mx, nz_prefix);
    }
    for (int bz = 0; bz < c->bdims[2]; bz++)
        for (int by = 0; by < c->bdims[1]; by++) {
            long lo[3] = {-1, (long)by * C5_BLOCK - 1, (long)bz * C5_BLOCK - 1};
            long hi[3] = {lo[0] + (long)row_w, lo[1] + C5_BLOCK + 2, lo[2] + C5_BLOCK + 2};
            if (c5_supervol_read_box(sv, lo, hi, buf, err) != 0)
                goto fail;
            for (int bx = 0; bx < c->bdims[0]; bx++) {
                unsigned mn = 255, mx = 0;
                for (int z = 0; z < C5_BLOCK + 2; z++)
                    for (int y = 0; y < C5_BLOCK + 2; y++)
                        minmax(buf + ((size_t)z * (C5_BLOCK + 2) + (size_t)y) * row_w + (size_t)bx * C5_BLOCK,
                               C5_BLOCK + 2, &mn, &mx);
                c->block_empty[((size_t)bz * c->bdims[1] + by) * c->bdims[0] + bx] =
                    (uint8_t)range_empty(mn, mx, nz_prefix);
            }
        }
    free(buf);
    return 0;
fail:
    free(buf);
    c5_cells_free(c);
    return -1;
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
    long lo[3] = {m->org[0], m->org[1], m->org[2]};
    long hi[3] = {lo[0] + m->ext[0], lo[1] + m->ext[1], lo[2] + m->ext[2]};
    return c5_supervol_read_box(sv, lo, hi, m->v, err);
}

void c5_rdram_free(c5_rdram *m)
{
    free(m->v);
    memset(m, 0, sizeof *m);
    m->cell = -1;
}
