/* Cell split, emptiness flags, RDRAM fetch (cells.h). */
#include <stdlib.h>
#include <string.h>

#include "block_range.h"
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

/* The flags, exactly as if every box were read, from the blocks' ranges (block_range.h). A
 * block's box with its apron is what its apron range covers; so is a cell's whose faces lie
 * on block boundaries, the union of its blocks'. For any other cell's box, the blocks it
 * overlaps give a range that holds the box's (if that is empty, so is the box's) and the
 * blocks wholly inside it a range the box's holds (if that is not empty, neither is the
 * box's). Only a box between the two is read, and of it only the blocks it cuts whose range
 * could still widen what is known. */
typedef struct {
    const c5_cells *c;
    const c5_supervol *sv;
    const c5_block_range *br;
    int nz_prefix[257];
    uint8_t *buf;
    c5_err *err;
} flag_ctx;

_Static_assert(C5_BLOCK == C5_RANGE_BLOCK, "the leaping blocks are the blocks whose ranges are kept");

/* range_empty of [mn, mx], where mn > mx is no voxel at all. */
static int span_empty(const flag_ctx *f, unsigned mn, unsigned mx)
{
    return mn > mx || range_empty(mn, mx, f->nz_prefix);
}

static size_t block_id(const c5_cells *c, int bx, int by, int bz)
{
    return ((size_t)bz * c->bdims[1] + (size_t)by) * c->bdims[0] + (size_t)bx;
}

/* Whether voxels [lo, hi] (inclusive, inside the grid) are empty: 1, 0, or -1 (a read
 * failed, err set). */
static int box_empty(flag_ctx *f, const int lo[3], const int hi[3])
{
    const c5_cells *c = f->c;
    int b0[3], b1[3];
    for (int a = 0; a < 3; a++) {
        b0[a] = lo[a] / C5_BLOCK;
        b1[a] = hi[a] / C5_BLOCK;
    }
    unsigned smn = 255, smx = 0, imn = 255, imx = 0;
    for (int bz = b0[2]; bz <= b1[2]; bz++)
        for (int by = b0[1]; by <= b1[1]; by++)
            for (int bx = b0[0]; bx <= b1[0]; bx++) {
                size_t id = block_id(c, bx, by, bz);
                unsigned mn = f->br->mn[id], mx = f->br->mx[id];
                smn = mn < smn ? mn : smn;
                smx = mx > smx ? mx : smx;
                int b[3] = {bx, by, bz}, inside = 1;
                for (int a = 0; a < 3; a++) {
                    int e = (b[a] + 1) * C5_BLOCK - 1 < c->dims[a] - 1 ? (b[a] + 1) * C5_BLOCK - 1 : c->dims[a] - 1;
                    inside &= b[a] * C5_BLOCK >= lo[a] && e <= hi[a];
                }
                if (inside) {
                    imn = mn < imn ? mn : imn;
                    imx = mx > imx ? mx : imx;
                }
            }
    if (span_empty(f, smn, smx))
        return 1;
    if (!span_empty(f, imn, imx))
        return 0;
    for (int bz = b0[2]; bz <= b1[2]; bz++)
        for (int by = b0[1]; by <= b1[1]; by++)
            for (int bx = b0[0]; bx <= b1[0]; bx++) {
                size_t id = block_id(c, bx, by, bz);
                if (imn <= imx && f->br->mn[id] >= imn && f->br->mx[id] <= imx)
                    continue; /* inside what is known (the blocks wholly inside among them) */
                int b[3] = {bx, by, bz};
                long rlo[3], rhi[3];
                for (int a = 0; a < 3; a++) {
                    rlo[a] = b[a] * C5_BLOCK > lo[a] ? b[a] * C5_BLOCK : lo[a];
                    rhi[a] = (b[a] + 1) * C5_BLOCK - 1 < hi[a] ? (b[a] + 1) * C5_BLOCK : hi[a] + 1;
                }
                if (c5_supervol_read_box(f->sv, rlo, rhi, f->buf, f->err) != 0)
                    return -1;
                minmax(f->buf, (size_t)(rhi[0] - rlo[0]) * (size_t)(rhi[1] - rlo[1]) * (size_t)(rhi[2] - rlo[2]), &imn,
                       &imx);
                if (!span_empty(f, imn, imx))
                    return 0;
            }
    return span_empty(f, imn, imx);
}

/* [lo - 1, hi] of an axis clamped to the grid: the voxels a box with a one-voxel apron reads
 * (clamp to edge repeats the grid's own voxels). */
static void apron_box(const c5_cells *c, const int lo[3], const int hi[3], int blo[3], int bhi[3])
{
    for (int a = 0; a < 3; a++) {
        blo[a] = lo[a] - 1 > 0 ? lo[a] - 1 : 0;
        bhi[a] = hi[a] < c->dims[a] - 1 ? hi[a] : c->dims[a] - 1;
    }
}

/* A cell whose faces lie on block boundaries (or the grid's far face): its box with the
 * apron is the union of its blocks' apron boxes, so its range is theirs. 1, 0, or -1 (not
 * aligned: box_empty reads what it must). */
static int aligned_cell_empty(const flag_ctx *f, const int lo[3], const int hi[3])
{
    const c5_cells *c = f->c;
    for (int a = 0; a < 3; a++)
        if (lo[a] % C5_BLOCK || (hi[a] % C5_BLOCK && hi[a] != c->dims[a]))
            return -1;
    unsigned mn = 255, mx = 0;
    for (int bz = lo[2] / C5_BLOCK; bz < (hi[2] + C5_BLOCK - 1) / C5_BLOCK; bz++)
        for (int by = lo[1] / C5_BLOCK; by < (hi[1] + C5_BLOCK - 1) / C5_BLOCK; by++)
            for (int bx = lo[0] / C5_BLOCK; bx < (hi[0] + C5_BLOCK - 1) / C5_BLOCK; bx++) {
                size_t id = block_id(c, bx, by, bz);
                mn = f->br->amn[id] < mn ? f->br->amn[id] : mn;
                mx = f->br->amx[id] > mx ? f->br->amx[id] : mx;
            }
    return span_empty(f, mn, mx);
}

int c5_cells_init(c5_cells *c, const c5_supervol *sv, const int n[3], const uint8_t alpha_nz[256], c5_err *err)
{
    if (cells_alloc(c, sv->dims, n, err) != 0)
        return -1;
    flag_ctx f = {.c = c, .sv = sv, .err = err};
    for (int i = 0; i < 256; i++)
        f.nz_prefix[i + 1] = f.nz_prefix[i] + (alpha_nz[i] != 0);
    c5_block_range *owned = NULL;
    if (!(f.br = c5_block_range_of(sv, &owned, err)))
        goto fail;
    if (!(f.buf = malloc(C5_BLOCK * C5_BLOCK * C5_BLOCK))) {
        c5_fail(err, "out of memory for the cell flags");
        goto fail;
    }
    for (int cell = 0; cell < c->count; cell++) {
        int lo[3], hi[3], blo[3], bhi[3];
        c5_cell_box(c, cell, lo, hi); /* hi: the first voxel past the cell, the upper corner */
        int e = aligned_cell_empty(&f, lo, hi);
        if (e < 0) {
            apron_box(c, lo, hi, blo, bhi);
            if ((e = box_empty(&f, blo, bhi)) < 0)
                goto fail;
        }
        c->empty[cell] = (uint8_t)e;
    }
    /* a block's apron box is exactly what its apron range covers */
    for (size_t id = 0; id < c5_cells_blocks(c); id++)
        c->block_empty[id] = (uint8_t)span_empty(&f, f.br->amn[id], f.br->amx[id]);
    free(f.buf);
    c5_block_range_free(owned);
    return 0;
fail:
    free(f.buf);
    c5_block_range_free(owned);
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

/* An out-of-core view's span, no longer read: its pages dropped. */
static void release_view(c5_rdram *m)
{
    if (!m->view_of)
        return;
    long lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = m->org[a];
        hi[a] = (long)m->org[a] + m->ext[a];
    }
    c5_supervol_done_reading(m->view_of, lo, hi);
    m->view_of = NULL;
}

/* The cell's box and the RDRAM's (the cell with its ghost layers). */
static void set_box(c5_rdram *m, const c5_cells *c, int cell)
{
    release_view(m);
    c5_cell_box(c, cell, m->lo, m->hi);
    for (int a = 0; a < 3; a++) {
        m->org[a] = m->lo[a] - C5_GHOST;
        m->ext[a] = m->hi[a] - m->lo[a] + 2 * C5_GHOST;
    }
    m->cell = cell;
}

int c5_rdram_place(c5_rdram *m, const c5_cells *c, int cell, c5_err *err)
{
    set_box(m, c, cell);
    size_t need = (size_t)m->ext[0] * (size_t)m->ext[1] * (size_t)m->ext[2];
    if (need > m->cap) {
        uint8_t *p = realloc(m->v, need);
        if (!p)
            return c5_fail(err, "out of memory for the RDRAM model (%zu bytes)", need);
        m->v = p;
        m->cap = need;
    }
    m->view = NULL;
    return 0;
}

int c5_rdram_load(c5_rdram *m, const c5_cells *c, const c5_supervol *sv, int cell, c5_err *err)
{
    if (c5_rdram_place(m, c, cell, err) != 0)
        return -1;
    long lo[3] = {m->org[0], m->org[1], m->org[2]};
    long hi[3] = {lo[0] + m->ext[0], lo[1] + m->ext[1], lo[2] + m->ext[2]};
    int rc = c5_supervol_read_box(sv, lo, hi, m->v, err);
    c5_supervol_done_reading(sv, lo, hi); /* out of core, a mapped file's pages; else nothing */
    return rc;
}

int c5_rdram_view(c5_rdram *m, const c5_cells *c, const c5_supervol *sv, int cell, c5_err *err)
{
    const uint8_t *data = c5_supervol_data(sv);
    if (!data)
        return c5_rdram_load(m, c, sv, cell, err);
    set_box(m, c, cell);
    long lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = m->org[a];
        hi[a] = (long)m->org[a] + m->ext[a];
    }
    m->view = data;
    m->view_sy = (ptrdiff_t)sv->dims[0];
    m->view_sz = (ptrdiff_t)(sv->dims[0] * sv->dims[1]);
    m->view_o0 = m->org[0] + m->org[1] * m->view_sy + m->org[2] * m->view_sz;
    if (!sv->v) {
        c5_supervol_will_read(sv, lo, hi);
        m->view_of = sv;
    }
    return 0;
}

void c5_rdram_at(c5_rdram *m, const c5_cells *c, int cell, const uint8_t *bytes)
{
    set_box(m, c, cell);
    m->view = bytes;
    m->view_sy = m->ext[0];
    m->view_sz = (ptrdiff_t)m->ext[0] * m->ext[1];
    m->view_o0 = 0;
}

void c5_rdram_free(c5_rdram *m)
{
    release_view(m);
    free(m->v);
    memset(m, 0, sizeof *m);
    m->cell = -1;
}
