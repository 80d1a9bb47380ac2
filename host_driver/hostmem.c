/* Host memory of a loaded scene (hostmem.h): the scene descriptor, the cell buffers and the
 * frame buffer, computed exactly as the board model computes them for itself, so that the
 * emulated board renders bit-identically to c5_board_render. */
#include <stdlib.h>
#include <string.h>

#include "c5_layouts.h"
#include "cells.h"
#include "hostmem.h"
#include "model_limits.h"
#include "regs.h"
#include "supervol.h"


static size_t pad4(size_t n) { return (n + 3) & ~(size_t)3; }

static void split_double(double v, uint32_t *lo, uint32_t *hi)
{
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits); /* the binary64 itself: the board computes with the host's doubles */
    *lo = (uint32_t)bits;
    *hi = (uint32_t)(bits >> 32);
}

/* Header, JSON, cell flags, block flags, each part from a multiple of 4 (host-protocol.md). */
static int build_descriptor(c5_hostmem *m, const char *json, const c5_supervol *sv, const c5_cells *c, c5_err *err)
{
    size_t json_bytes = strlen(json);
    size_t ncf = m->has_volume ? (size_t)c->count : 0, nbf = m->has_volume ? c5_cells_blocks(c) : 0;
    if (json_bytes > UINT32_MAX / 2 || nbf > UINT32_MAX / 2)
        return c5_fail(err, "scene too large for a scene descriptor");
    size_t off_cf = C5_SCENE_DESCRIPTOR_BYTES + pad4(json_bytes), off_bf = off_cf + pad4(ncf);
    size_t total = off_bf + pad4(nbf);
    uint8_t *d = calloc(total, 1);
    if (!d)
        return c5_fail(err, "out of memory for the scene descriptor (%zu bytes)", total);
    c5_scene_descriptor_t h = {.magic = C5_SD_MAGIC,
                               .version = C5_SD_VERSION,
                               .header_bytes = C5_SCENE_DESCRIPTOR_BYTES,
                               .json_bytes = (uint32_t)json_bytes,
                               .dims_x = (uint32_t)sv->dims[0],
                               .dims_y = (uint32_t)sv->dims[1],
                               .dims_z = (uint32_t)sv->dims[2],
                               .cells_x = (uint32_t)m->cells[0],
                               .cells_y = (uint32_t)m->cells[1],
                               .cells_z = (uint32_t)m->cells[2],
                               .cell_flags_bytes = (uint32_t)ncf,
                               .block_flags_bytes = (uint32_t)nbf};
    split_double(sv->spacing.x, &h.spacing_x_lo, &h.spacing_x_hi);
    split_double(sv->spacing.y, &h.spacing_y_lo, &h.spacing_y_hi);
    split_double(sv->spacing.z, &h.spacing_z_lo, &h.spacing_z_hi);
    split_double(sv->origin.x, &h.origin_x_lo, &h.origin_x_hi);
    split_double(sv->origin.y, &h.origin_y_lo, &h.origin_y_hi);
    split_double(sv->origin.z, &h.origin_z_lo, &h.origin_z_hi);
    c5_scene_descriptor_pack(&h, d);
    memcpy(d + C5_SCENE_DESCRIPTOR_BYTES, json, json_bytes);
    if (ncf)
        memcpy(d + off_cf, c->empty, ncf);
    if (nbf)
        memcpy(d + off_bf, c->block_empty, nbf);
    m->desc = (c5_hm_buf){C5_HM_DESC_ADDR, d, total};
    return 0;
}

/* One buffer per cell as c5_rdram holds it, zero-padded to a multiple of 4. */
static int build_cells(c5_hostmem *m, const c5_supervol *sv, const c5_cells *c, c5_err *err)
{
    m->cell = calloc((size_t)c->count, sizeof *m->cell);
    if (!m->cell)
        return c5_fail(err, "out of memory for %d cell buffers", c->count);
    c5_rdram ram = {.cell = -1};
    uint64_t addr = C5_HM_CELL_ADDR;
    int rc = 0;
    for (int i = 0; i < c->count && rc == 0; i++) {
        size_t bytes = c5_cell_bytes(c, i), len = pad4(bytes);
        if ((rc = c5_rdram_load(&ram, c, sv, i, err)) != 0)
            break;
        uint8_t *p = calloc(len, 1);
        if (!p) {
            rc = c5_fail(err, "out of memory for cell %d (%zu bytes)", i, len);
            break;
        }
        memcpy(p, ram.v, bytes);
        m->cell[i] = (c5_hm_buf){addr, p, len};
        addr += (len + C5_HM_CELL_ALIGN - 1) & ~(C5_HM_CELL_ALIGN - 1);
    }
    c5_rdram_free(&ram);
    return rc;
}

int c5_hostmem_load(c5_hostmem *m, const char *json, const char *base_dir, const char *what, const int cells[3],
                    int width, int height, c5_err *err)
{
    memset(m, 0, sizeof *m);
    c5_supervol sv = {0};
    c5_cells c = {0};
    int have_cells = 0, rc = -1;
    c5_frame_regs *r = malloc(sizeof *r);
    m->scene = calloc(1, sizeof *m->scene);
    if (!r || !m->scene) {
        c5_fail(err, "out of memory for the scene");
        goto out;
    }
    if (c5_scene_parse(json, base_dir, what ? what : "scene", m->scene, err) != 0)
        goto out;
    if (width > 0)
        m->scene->render.width = width;
    if (height > 0)
        m->scene->render.height = height;
    /* The model's field-width limits before any volume is read or generated. */
    if (c5_model_check_scene(m->scene, cells, m->scene->source, err) != 0 || c5_supervol_build(m->scene, &sv, err) != 0)
        goto out;
    m->width = m->scene->render.width;
    m->height = m->scene->render.height;
    m->has_volume = !c5_supervol_empty(&sv);
    /* The model's option defaults (c5_board_render): < 1 means the automatic split, no volume
     * forces 1x1x1. */
    for (int a = 0; a < 3; a++)
        m->cells[a] = !m->has_volume ? 1 : !cells || cells[a] < 1 ? 0 : cells[a];
    c5_model_auto_split(sv.dims, m->cells);
    c5_board_opts o = {.cells = {m->cells[0], m->cells[1], m->cells[2]}};
    if (c5_regs_build(m->scene, &sv, &o, r, err) != 0)
        goto out;
    m->ncells = m->cells[0] * m->cells[1] * m->cells[2];
    if (m->has_volume) {
        for (int a = 0; a < 3; a++)
            if (sv.dims[a] > 0xFFFF) { /* the descriptor's 16-bit dims; the model refuses far less */
                c5_fail(err, "grid of %zu voxels along %c: beyond the scene descriptor", sv.dims[a], "xyz"[a]);
                goto out;
            }
        uint8_t alpha_nz[256];
        for (int i = 0; i < 256; i++)
            alpha_nz[i] = r->tf[i][3] > 0; /* as c5_board_render: the step-corrected table */
        if (c5_cells_init(&c, &sv, m->cells, alpha_nz, err) != 0)
            goto out;
        have_cells = 1;
        if (build_cells(m, &sv, &c, err) != 0)
            goto out;
    }
    if (build_descriptor(m, json, &sv, &c, err) != 0)
        goto out;
    size_t fb_len = (size_t)m->width * (size_t)m->height * 12;
    m->fb = (c5_hm_buf){C5_HM_FB_ADDR, calloc(fb_len, 1), fb_len};
    if (!m->fb.data) {
        c5_fail(err, "out of memory for the frame buffer (%zu bytes)", fb_len);
        goto out;
    }
    rc = 0;
out:
    if (have_cells)
        c5_cells_free(&c);
    c5_supervol_free(&sv);
    free(r);
    if (rc != 0)
        c5_hostmem_free(m);
    return rc;
}

void c5_hostmem_free(c5_hostmem *m)
{
    if (m->cell)
        for (int i = 0; i < m->ncells; i++)
            free(m->cell[i].data);
    free(m->cell);
    free(m->desc.data);
    free(m->fb.data);
    free(m->scene);
    memset(m, 0, sizeof *m);
}

static int inside(const c5_hm_buf *b, uint64_t addr, size_t len)
{
    return b->data && addr >= b->addr && addr - b->addr <= b->len && len <= b->len - (addr - b->addr);
}

const c5_hm_buf *c5_hostmem_find(const c5_hostmem *m, uint64_t addr, size_t len)
{
    if (inside(&m->desc, addr, len))
        return &m->desc;
    if (inside(&m->fb, addr, len))
        return &m->fb;
    if (!m->cell || m->ncells == 0)
        return NULL;
    /* cells lie in increasing address order: the last one starting at or below addr */
    int lo = 0, hi = m->ncells - 1;
    while (lo < hi) {
        int mid = lo + (hi - lo + 1) / 2;
        if (m->cell[mid].addr <= addr)
            lo = mid;
        else
            hi = mid - 1;
    }
    return inside(&m->cell[lo], addr, len) ? &m->cell[lo] : NULL;
}
