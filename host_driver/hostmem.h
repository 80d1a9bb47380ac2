/* The host memory a loaded scene occupies (docs/host-protocol.md, "Host memory and the scene
 * descriptor"): the buffers the board reads and writes by DMA, each at a fixed bus address
 * the driver chooses. The driver has no IOMMU or physical memory: a "bus address" is only a
 * name the board uses in its dma_read/dma_write packets, which the driver resolves here.
 *
 * Bus addresses (all above 4 GB, so a board that drops addr_hi faults at once instead of
 * reading the wrong buffer):
 *   0x1_0000_0000  the scene descriptor
 *   0x2_0000_0000  the frame buffer (width * height * 12 bytes, written by the board)
 *   0x3_0000_0000  cell 0; every further cell at the next 4 KiB aligned offset after the
 *                  previous cell's padded length, in cell id order
 *
 * A scene without a volume (dims 0): no cell buffers, the split is forced to 1x1x1 as
 * c5_board_render does for c5_supervol_empty, and the descriptor says dims 0, cells 1,1,1,
 * cell_flags_bytes 0 and block_flags_bytes 0: the board computes the one cell's flags
 * itself (the model's host == NULL path), so there are no flags to send. */
#ifndef C5_HOSTMEM_H
#define C5_HOSTMEM_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "scene.h"

#define C5_HM_DESC_ADDR 0x100000000ull
#define C5_HM_FB_ADDR 0x200000000ull
#define C5_HM_CELL_ADDR 0x300000000ull
#define C5_HM_CELL_ALIGN 4096ull

#define C5_SD_MAGIC 0x44533543u /* 'C' '5' 'S' 'D' in memory order */
#define C5_SD_VERSION 1u

typedef struct {
    uint64_t addr;
    uint8_t *data;
    size_t len; /* a multiple of 4 */
} c5_hm_buf;

typedef struct {
    c5_scene *scene;  /* as parsed, with the width/height override applied */
    int width, height;
    int cells[3];     /* the split (1x1x1 for a scene without a volume) */
    int ncells;
    int has_volume;
    c5_hm_buf desc, fb;
    c5_hm_buf *cell;  /* [ncells] when has_volume, else NULL */
} c5_hostmem;

/* Parses the scene, builds its super volume and cells, and lays out every buffer. cells
 * NULL: 1x1x1. A scene the model refuses fails with the model's message. */
int c5_hostmem_load(c5_hostmem *m, const char *json, const char *base_dir, const char *what, const int cells[3],
                    int width, int height, c5_err *err);
void c5_hostmem_free(c5_hostmem *m);

/* The buffer holding [addr, addr + len) wholly, or NULL. */
const c5_hm_buf *c5_hostmem_find(const c5_hostmem *m, uint64_t addr, size_t len);

#endif
